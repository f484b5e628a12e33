/* gltf: binary glTF 2.0 (.glb) output: one self-contained file with the
 * meshes, their texture images (PNG) and materials, which engines, Blender
 * (File > Import > glTF 2.0), three.js, Babylon.js and web viewers load.
 *
 * A file holds one or more parts, each a polygon mesh (faces of any degree,
 * fan-triangulated) with optional per-corner texture coordinates and one
 * base-colour texture. Per glTF, a vertex carries one position, normal and
 * texture coordinate, so a mesh vertex whose corners have different
 * coordinates (a texture seam) is written once per distinct coordinate.
 * What is written (glTF 2.0 core only, no extension):
 *   - POSITION (with the min/max the format requires), NORMAL (area-weighted
 *     vertex normals of the input mesh, unit length; smooth across texture
 *     seams), TEXCOORD_0 when the part has coordinates, indices as
 *     UNSIGNED_INT, triangles;
 *   - a material per part: metallic 0, roughness 1, the texture as
 *     baseColorTexture (or white); single-sided;
 *   - a sampler per part: LINEAR magnification, LINEAR_MIPMAP_LINEAR
 *     minification, wrap REPEAT or CLAMP_TO_EDGE as the part asks;
 *   - a node and a mesh per part, named; the generator string;
 *   - optionally the camera patchwork's renderer used (a perspective camera
 *     on its own node), so that a viewer can open the file as patchwork
 *     drew it.
 * No tangents: they are needed only by normal textures, which patchwork
 * does not write. glTF's unit is the metre: mesh units are written as they
 * are (one unit, one metre). Texture coordinates follow OBJ/OpenGL's
 * convention on input ((0,0) at the bottom-left of the image) and are
 * written in glTF's ((0,0) at the top-left): v becomes 1 - v.
 *
 * The output is byte-for-byte deterministic: the same parts give the same
 * file. API: pw_gltf_write (a pw_gltf_scene to a pw_write_fn). */
#ifndef PW__GLTF_V1
#define PW__GLTF_V1

#include "base.h"
#include "image.h"
#include "png.h"
#include "text.h"
#include "render.h"
#include "glue.h"

typedef struct pw_gltf_part {
    const char *name; /* mesh and node name (NULL: "mesh") */
    int nv;
    const float *pos; /* nv*3 */
    int nf;
    const int *fstart;       /* nf+1 offsets into fv */
    const int *fv;           /* fstart[nf] vertex indices, counter-clockwise */
    const float *corner_uv;  /* fstart[nf]*2 per-corner texture coordinates, or NULL */
    const pw_image *texture; /* base colour, or NULL (white); needs corner_uv */
    int repeat;              /* sampler wrap: 1 REPEAT, 0 CLAMP_TO_EDGE */
} pw_gltf_part;

typedef struct pw_gltf_scene {
    const pw_gltf_part *parts;
    int nparts;
    const pw_camera *camera; /* NULL: no camera */
    float aspect;            /* the camera's width / height */
    const char *generator;   /* asset.generator (NULL: "patchwork") */
} pw_gltf_scene;

/* The vertices of one part as glTF needs them: one per distinct (mesh
 * vertex, texture coordinate) pair, in order of first use. */
typedef struct pw__gltf_verts {
    int n;
    int *src;    /* n: the mesh vertex */
    int *corner; /* n: a corner that uses it (its coordinate) */
    int *index;  /* fstart[nf]: the glTF vertex of each corner */
} pw__gltf_verts;

static void pw__gltf_verts_free(const pw_alloc *a, pw__gltf_verts *V)
{
    pw_free(a, V->src);
    pw_free(a, V->corner);
    pw_free(a, V->index);
    memset(V, 0, sizeof *V);
}

/* Splits the mesh vertices at texture seams: each mesh vertex keeps a chain
 * of its glTF vertices (head, next), searched for the corner's coordinate. */
static int pw__gltf_split(const pw_alloc *a, const pw_gltf_part *p, pw__gltf_verts *V, pw_err *e)
{
    int nc = p->fstart[p->nf], c, *head, *next;
    memset(V, 0, sizeof *V);
    head = (int *)pw_alloc_array(a, (size_t)p->nv, sizeof(int), "glTF vertices", e);
    next = (int *)pw_alloc_array(a, (size_t)nc, sizeof(int), "glTF vertices", e);
    V->src = (int *)pw_alloc_array(a, (size_t)nc, sizeof(int), "glTF vertices", e);
    V->corner = (int *)pw_alloc_array(a, (size_t)nc, sizeof(int), "glTF vertices", e);
    V->index = (int *)pw_alloc_array(a, (size_t)nc, sizeof(int), "glTF vertices", e);
    if (!head || !next || !V->src || !V->corner || !V->index) {
        pw_free(a, head);
        pw_free(a, next);
        pw__gltf_verts_free(a, V);
        return PW_ERR_NOMEM;
    }
    memset(head, 0xFF, sizeof(int) * (size_t)p->nv);
    for (c = 0; c < nc; c++) {
        int v = p->fv[c], k = head[v];
        while (k >= 0 && p->corner_uv && memcmp(p->corner_uv + 2 * V->corner[k], p->corner_uv + 2 * c, 8)) k = next[k];
        if (k < 0) {
            k = V->n++;
            V->src[k] = v;
            V->corner[k] = c;
            next[k] = head[v];
            head[v] = k;
        }
        V->index[c] = k;
    }
    pw_free(a, head);
    pw_free(a, next);
    return PW_OK;
}

/* Area-weighted unit normals of the mesh vertices (fan triangles); a vertex
 * of zero-area faces only gets +z, so that every normal is unit length. */
static int pw__gltf_normals(const pw_alloc *a, const pw_gltf_part *p, float **out, pw_err *e)
{
    double *acc = (double *)pw_calloc_array(a, (size_t)p->nv * 3, sizeof(double), "glTF normals", e);
    float *n = (float *)pw_alloc_array(a, (size_t)p->nv * 3, sizeof(float), "glTF normals", e);
    int f, i, k;
    if (!acc || !n) {
        pw_free(a, acc);
        pw_free(a, n);
        return PW_ERR_NOMEM;
    }
    for (f = 0; f < p->nf; f++)
        for (i = p->fstart[f] + 1; i + 1 < p->fstart[f + 1]; i++) {
            const int t[3] = {p->fv[p->fstart[f]], p->fv[i], p->fv[i + 1]};
            double u[3], w[3], c[3];
            for (k = 0; k < 3; k++) {
                u[k] = (double)p->pos[3 * t[1] + k] - p->pos[3 * t[0] + k];
                w[k] = (double)p->pos[3 * t[2] + k] - p->pos[3 * t[0] + k];
            }
            pw_cross3(u, w, c);
            for (k = 0; k < 9; k++) acc[3 * t[k / 3] + k % 3] += c[k % 3];
        }
    for (i = 0; i < p->nv; i++) {
        double *v = acc + 3 * i, l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        for (k = 0; k < 3; k++) n[3 * i + k] = l > 0.0 && pw_is_finite(l) ? (float)(v[k] / l) : (float)(k == 2);
    }
    pw_free(a, acc);
    *out = n;
    return PW_OK;
}

/* ---- the binary chunk: buffer views, 4-byte aligned --------------------- */

typedef struct pw__gltf_view {
    size_t offset, length;
    int target; /* 34962 vertex attributes, 34963 indices, 0 images */
} pw__gltf_view;

typedef struct pw__gltf_out {
    const pw_alloc *a;
    pw_buf bin;
    pw__gltf_view *views;
    size_t nviews, vcap;
    pw__wb js; /* the JSON, into json */
    pw_buf json;
} pw__gltf_out;

/* Starts a buffer view at the next 4-byte boundary of the binary chunk. */
static int pw__gltf_view_begin(pw__gltf_out *o, int target, pw_err *e)
{
    static const unsigned char zero[4] = {0, 0, 0, 0};
    if (o->bin.size % 4 && pw_buf_write(&o->bin, zero, 4 - o->bin.size % 4))
        return pw_fail(e, PW_ERR_NOMEM, "out of memory writing glTF");
    if (pw_grow(o->a, (void **)&o->views, &o->vcap, o->nviews + 1, sizeof *o->views, "glTF views", e))
        return PW_ERR_NOMEM;
    o->views[o->nviews].offset = o->bin.size;
    o->views[o->nviews].length = 0;
    o->views[o->nviews].target = target;
    return PW_OK;
}

static int pw__gltf_view_end(pw__gltf_out *o, pw_err *e)
{
    if (o->bin.failed) return pw_fail(e, PW_ERR_NOMEM, "out of memory writing glTF");
    o->views[o->nviews].length = o->bin.size - o->views[o->nviews].offset;
    o->nviews++;
    return PW_OK;
}

/* Little-endian 32-bit words into the binary chunk. */
static void pw__gltf_put32(pw__gltf_out *o, uint32_t v)
{
    unsigned char b[4];
    b[0] = (unsigned char)v;
    b[1] = (unsigned char)(v >> 8);
    b[2] = (unsigned char)(v >> 16);
    b[3] = (unsigned char)(v >> 24);
    pw_buf_write(&o->bin, b, 4);
}

static void pw__gltf_putf(pw__gltf_out *o, float f)
{
    uint32_t v;
    memcpy(&v, &f, 4);
    pw__gltf_put32(o, v);
}

/* ---- JSON ------------------------------------------------------------------ */

static void pw__js(pw__gltf_out *o, const char *s) { pw__wb_str(&o->js, s); }
static void pw__js_int(pw__gltf_out *o, long long v) { pw__wb_int(&o->js, v, 0); }

static void pw__js_float(pw__gltf_out *o, float x)
{
    char t[24];
    pw__wb_put(&o->js, t, (size_t)pw__num_format(t, x));
}

/* A JSON string: quotes, backslashes and control characters escaped. */
static void pw__js_string(pw__gltf_out *o, const char *s)
{
    static const char hex[] = "0123456789abcdef";
    pw__js(o, "\"");
    for (; *s; s++) {
        unsigned char c = (unsigned char)*s;
        char u[6] = {'\\', 'u', '0', '0', 0, 0};
        if (c == '"' || c == '\\') {
            pw__wb_put(&o->js, "\\", 1);
            pw__wb_put(&o->js, s, 1);
        } else if (c < 0x20) {
            u[4] = hex[c >> 4];
            u[5] = hex[c & 15];
            pw__wb_put(&o->js, u, 6);
        } else pw__wb_put(&o->js, s, 1);
    }
    pw__js(o, "\"");
}

/* ---- one part's data -------------------------------------------------------- */

/* Per part, the buffer views are, in order: indices, positions, normals,
 * [texture coordinates], [image]; the accessors: indices, positions,
 * normals, [texture coordinates]. */
typedef struct pw__gltf_info {
    int nverts, ntris;
    float lo[3], hi[3];
    int has_uv, has_image;
    int view0, acc0;
} pw__gltf_info;

static int pw__gltf_part_data(pw__gltf_out *o, const pw_gltf_part *p, const pw__gltf_verts *V, const float *nrm,
                              pw__gltf_info *I, pw_err *e)
{
    int f, i, k, r;
    I->nverts = V->n;
    I->ntris = 0;
    I->view0 = (int)o->nviews;
    if ((r = pw__gltf_view_begin(o, 34963, e))) return r;
    for (f = 0; f < p->nf; f++)
        for (i = p->fstart[f] + 1; i + 1 < p->fstart[f + 1]; i++, I->ntris++) {
            pw__gltf_put32(o, (uint32_t)V->index[p->fstart[f]]);
            pw__gltf_put32(o, (uint32_t)V->index[i]);
            pw__gltf_put32(o, (uint32_t)V->index[i + 1]);
        }
    if ((r = pw__gltf_view_end(o, e)) || (r = pw__gltf_view_begin(o, 34962, e))) return r;
    for (i = 0; i < V->n; i++)
        for (k = 0; k < 3; k++) {
            float x = p->pos[3 * V->src[i] + k];
            if (i == 0 || x < I->lo[k]) I->lo[k] = x;
            if (i == 0 || x > I->hi[k]) I->hi[k] = x;
            pw__gltf_putf(o, x);
        }
    if ((r = pw__gltf_view_end(o, e)) || (r = pw__gltf_view_begin(o, 34962, e))) return r;
    for (i = 0; i < V->n; i++)
        for (k = 0; k < 3; k++) pw__gltf_putf(o, nrm[3 * V->src[i] + k]);
    if ((r = pw__gltf_view_end(o, e))) return r;
    if ((I->has_uv = p->corner_uv != NULL)) {
        if ((r = pw__gltf_view_begin(o, 34962, e))) return r;
        for (i = 0; i < V->n; i++) {
            pw__gltf_putf(o, p->corner_uv[2 * V->corner[i]]);
            pw__gltf_putf(o, 1.0f - p->corner_uv[2 * V->corner[i] + 1]);
        }
        if ((r = pw__gltf_view_end(o, e))) return r;
    }
    if ((I->has_image = p->texture != NULL)) {
        pw_err local; /* the PNG writer sees a failing sink where the buffer ran out of memory */
        pw_err_clear(&local);
        if ((r = pw__gltf_view_begin(o, 0, e))) return r;
        if ((r = pw_png_write(o->a, p->texture, 8, pw_buf_write, &o->bin, &local)))
            return o->bin.failed ? pw_fail(e, PW_ERR_NOMEM, "out of memory writing glTF")
                                 : pw_fail(e, r, "%s", local.msg);
        if ((r = pw__gltf_view_end(o, e))) return r;
    }
    return PW_OK;
}

/* Checks a part: sizes, indices, finite positions and coordinates. */
static int pw__gltf_check(const pw_gltf_part *p, int k, pw_err *e)
{
    int i, nc;
    if (!p->pos || !p->fstart || !p->fv || p->nv < 1 || p->nf < 1 || p->fstart[0] != 0)
        return pw_fail(e, PW_ERR_INVALID, "glTF part %d: empty or malformed mesh", k);
    if (p->texture && !p->corner_uv)
        return pw_fail(e, PW_ERR_INVALID, "glTF part %d: a texture without texture coordinates", k);
    for (i = 0; i < p->nf; i++)
        if (p->fstart[i + 1] - p->fstart[i] < 3 || p->fstart[i + 1] > PW_MAX_MESH_ELEMENTS)
            return pw_fail(e, PW_ERR_INVALID, "glTF part %d: face %d has %d corners", k, i,
                           p->fstart[i + 1] - p->fstart[i]);
    nc = p->fstart[p->nf];
    for (i = 0; i < nc; i++)
        if (p->fv[i] < 0 || p->fv[i] >= p->nv)
            return pw_fail(e, PW_ERR_INVALID, "glTF part %d: corner %d names vertex %d of %d", k, i, p->fv[i], p->nv);
    for (i = 0; i < 3 * p->nv; i++)
        if (!pw_is_finite(p->pos[i]))
            return pw_fail(e, PW_ERR_INVALID, "glTF part %d: vertex %d is not finite", k, i / 3);
    for (i = 0; p->corner_uv && i < 2 * nc; i++)
        if (!pw_is_finite(p->corner_uv[i]))
            return pw_fail(e, PW_ERR_INVALID, "glTF part %d: corner %d's texture coordinate is not finite", k, i / 2);
    return PW_OK;
}

/* ---- the JSON document ----------------------------------------------------- */

static void pw__gltf_json_views(pw__gltf_out *o)
{
    size_t k;
    pw__js(o, "],\"bufferViews\":[");
    for (k = 0; k < o->nviews; k++) {
        pw__js(o, k ? ",{\"buffer\":0,\"byteOffset\":" : "{\"buffer\":0,\"byteOffset\":");
        pw__js_int(o, (long long)o->views[k].offset);
        pw__js(o, ",\"byteLength\":");
        pw__js_int(o, (long long)o->views[k].length);
        if (o->views[k].target) {
            pw__js(o, ",\"target\":");
            pw__js_int(o, o->views[k].target);
        }
        pw__js(o, "}");
    }
    pw__js(o, "],\"buffers\":[{\"byteLength\":");
    pw__js_int(o, (long long)o->bin.size);
    pw__js(o, "}]");
}

static void pw__gltf_accessor(pw__gltf_out *o, int first, int view, int type, int count, const char *kind)
{
    pw__js(o, first ? "{\"bufferView\":" : ",{\"bufferView\":");
    pw__js_int(o, view);
    pw__js(o, ",\"componentType\":");
    pw__js_int(o, type);
    pw__js(o, ",\"count\":");
    pw__js_int(o, count);
    pw__js(o, ",\"type\":\"");
    pw__js(o, kind);
    pw__js(o, "\"");
}

static void pw__gltf_json_accessors(pw__gltf_out *o, const pw__gltf_info *I, int np)
{
    int p, k;
    pw__js(o, "],\"accessors\":[");
    for (p = 0; p < np; p++) {
        int v = I[p].view0;
        pw__gltf_accessor(o, p == 0, v, 5125, 3 * I[p].ntris, "SCALAR");
        pw__js(o, "}");
        pw__gltf_accessor(o, 0, v + 1, 5126, I[p].nverts, "VEC3");
        pw__js(o, ",\"min\":[");
        for (k = 0; k < 3; k++) {
            pw__js(o, k ? "," : "");
            pw__js_float(o, I[p].lo[k]);
        }
        pw__js(o, "],\"max\":[");
        for (k = 0; k < 3; k++) {
            pw__js(o, k ? "," : "");
            pw__js_float(o, I[p].hi[k]);
        }
        pw__js(o, "]}");
        pw__gltf_accessor(o, 0, v + 2, 5126, I[p].nverts, "VEC3");
        pw__js(o, "}");
        if (I[p].has_uv) {
            pw__gltf_accessor(o, 0, v + 3, 5126, I[p].nverts, "VEC2");
            pw__js(o, "}");
        }
    }
}

/* Accessor indices of part p: indices, positions, normals, uv. */
static int pw__gltf_acc0(const pw__gltf_info *I, int p)
{
    int k, n = 0;
    for (k = 0; k < p; k++) n += 3 + I[k].has_uv;
    return n;
}

static void pw__gltf_json_meshes(pw__gltf_out *o, const pw_gltf_part *parts, const pw__gltf_info *I, int np)
{
    int p;
    pw__js(o, "],\"meshes\":[");
    for (p = 0; p < np; p++) {
        int a0 = pw__gltf_acc0(I, p);
        pw__js(o, p ? ",{\"name\":" : "{\"name\":");
        pw__js_string(o, parts[p].name ? parts[p].name : "mesh");
        pw__js(o, ",\"primitives\":[{\"attributes\":{\"POSITION\":");
        pw__js_int(o, a0 + 1);
        pw__js(o, ",\"NORMAL\":");
        pw__js_int(o, a0 + 2);
        if (I[p].has_uv) {
            pw__js(o, ",\"TEXCOORD_0\":");
            pw__js_int(o, a0 + 3);
        }
        pw__js(o, "},\"indices\":");
        pw__js_int(o, a0);
        pw__js(o, ",\"material\":");
        pw__js_int(o, p);
        pw__js(o, ",\"mode\":4}]}");
    }
    pw__js(o, "],\"materials\":[");
    for (p = 0; p < np; p++) {
        pw__js(o, p ? ",{\"name\":" : "{\"name\":");
        pw__js_string(o, parts[p].name ? parts[p].name : "mesh");
        pw__js(o, ",\"pbrMetallicRoughness\":{");
        if (I[p].has_image) {
            int t = 0, k;
            for (k = 0; k < p; k++) t += I[k].has_image;
            pw__js(o, "\"baseColorTexture\":{\"index\":");
            pw__js_int(o, t);
            pw__js(o, "},");
        }
        pw__js(o, "\"metallicFactor\":0,\"roughnessFactor\":1}}");
    }
}

static void pw__gltf_json_textures(pw__gltf_out *o, const pw_gltf_part *parts, const pw__gltf_info *I, int np)
{
    int p, t = 0;
    const char *sep = "";
    for (p = 0; p < np; p++) t += I[p].has_image;
    if (!t) return;
    pw__js(o, "],\"textures\":[");
    for (p = 0, t = 0; p < np; p++)
        if (I[p].has_image) {
            pw__js(o, sep);
            pw__js(o, "{\"sampler\":");
            pw__js_int(o, t);
            pw__js(o, ",\"source\":");
            pw__js_int(o, t);
            pw__js(o, "}");
            sep = ",";
            t++;
        }
    pw__js(o, "],\"samplers\":[");
    for (p = 0, sep = ""; p < np; p++)
        if (I[p].has_image) {
            const char *wrap = parts[p].repeat ? "10497" : "33071";
            pw__js(o, sep);
            pw__js(o, "{\"magFilter\":9729,\"minFilter\":9987,\"wrapS\":");
            pw__js(o, wrap);
            pw__js(o, ",\"wrapT\":");
            pw__js(o, wrap);
            pw__js(o, "}");
            sep = ",";
        }
    pw__js(o, "],\"images\":[");
    for (p = 0, sep = ""; p < np; p++)
        if (I[p].has_image) {
            pw__js(o, sep);
            pw__js(o, "{\"bufferView\":");
            pw__js_int(o, I[p].view0 + 3 + I[p].has_uv);
            pw__js(o, ",\"mimeType\":\"image/png\"}");
            sep = ",";
        }
}

/* The rotation taking the camera's local axes (glTF cameras look along -z
 * with +y up) to the world's: columns right, up, -forward, as a unit
 * quaternion (x, y, z, w). */
static void pw__gltf_camera_rotation(const pw_camera *c, double *q)
{
    double f[3], r[3], u[3], m[3][3], t;
    int k;
    for (k = 0; k < 3; k++) {
        f[k] = (double)c->target[k] - c->eye[k];
        u[k] = c->up[k];
    }
    pw_norm3(f);
    pw_cross3(f, u, r);
    pw_norm3(r);
    pw_cross3(r, f, u);
    for (k = 0; k < 3; k++) {
        m[k][0] = r[k];
        m[k][1] = u[k];
        m[k][2] = -f[k];
    }
    t = m[0][0] + m[1][1] + m[2][2];
    if (t > 0.0) { /* the largest of w, x, y, z divides: no cancellation */
        double s = 2.0 * sqrt(1.0 + t);
        q[3] = 0.25 * s;
        q[0] = (m[2][1] - m[1][2]) / s;
        q[1] = (m[0][2] - m[2][0]) / s;
        q[2] = (m[1][0] - m[0][1]) / s;
    } else if (m[0][0] > m[1][1] && m[0][0] > m[2][2]) {
        double s = 2.0 * sqrt(1.0 + m[0][0] - m[1][1] - m[2][2]);
        q[3] = (m[2][1] - m[1][2]) / s;
        q[0] = 0.25 * s;
        q[1] = (m[0][1] + m[1][0]) / s;
        q[2] = (m[0][2] + m[2][0]) / s;
    } else if (m[1][1] > m[2][2]) {
        double s = 2.0 * sqrt(1.0 + m[1][1] - m[0][0] - m[2][2]);
        q[3] = (m[0][2] - m[2][0]) / s;
        q[0] = (m[0][1] + m[1][0]) / s;
        q[1] = 0.25 * s;
        q[2] = (m[1][2] + m[2][1]) / s;
    } else {
        double s = 2.0 * sqrt(1.0 + m[2][2] - m[0][0] - m[1][1]);
        q[3] = (m[1][0] - m[0][1]) / s;
        q[0] = (m[0][2] + m[2][0]) / s;
        q[1] = (m[1][2] + m[2][1]) / s;
        q[2] = 0.25 * s;
    }
    t = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (k = 0; k < 4; k++) q[k] /= t;
}

/* The camera's node (after the parts') and its "cameras" entry. */
static void pw__gltf_json_camera_node(pw__gltf_out *o, const pw_camera *c)
{
    double q[4];
    int k;
    pw__gltf_camera_rotation(c, q);
    pw__js(o, ",{\"name\":\"patchwork view\",\"camera\":0,\"translation\":[");
    for (k = 0; k < 3; k++) {
        pw__js(o, k ? "," : "");
        pw__js_float(o, c->eye[k]);
    }
    pw__js(o, "],\"rotation\":[");
    for (k = 0; k < 4; k++) {
        pw__js(o, k ? "," : "");
        pw__js_float(o, (float)q[k]);
    }
    pw__js(o, "]}");
}

static void pw__gltf_json_camera(pw__gltf_out *o, const pw_camera *c, float aspect)
{
    pw__js(o, "],\"cameras\":[{\"type\":\"perspective\",\"perspective\":{\"yfov\":");
    pw__js_float(o, (float)(c->fovy_deg * (3.14159265358979323846 / 180.0)));
    pw__js(o, ",\"aspectRatio\":");
    pw__js_float(o, aspect);
    pw__js(o, ",\"znear\":");
    pw__js_float(o, c->znear);
    pw__js(o, ",\"zfar\":");
    pw__js_float(o, c->zfar);
    pw__js(o, "}}");
}

static void pw__gltf_json(pw__gltf_out *o, const pw_gltf_scene *S, const pw__gltf_info *I)
{
    const pw_gltf_part *parts = S->parts;
    int p, np = S->nparts;
    pw__js(o, "{\"asset\":{\"version\":\"2.0\",\"generator\":");
    pw__js_string(o, S->generator ? S->generator : "patchwork");
    pw__js(o, "},\"scene\":0,\"scenes\":[{\"nodes\":[");
    for (p = 0; p < np + (S->camera != NULL); p++) {
        pw__js(o, p ? "," : "");
        pw__js_int(o, p);
    }
    pw__js(o, "]}],\"nodes\":[");
    for (p = 0; p < np; p++) {
        pw__js(o, p ? ",{\"name\":" : "{\"name\":");
        pw__js_string(o, parts[p].name ? parts[p].name : "mesh");
        pw__js(o, ",\"mesh\":");
        pw__js_int(o, p);
        pw__js(o, "}");
    }
    if (S->camera) {
        pw__gltf_json_camera_node(o, S->camera);
        pw__gltf_json_camera(o, S->camera, S->aspect);
    }
    pw__gltf_json_meshes(o, parts, I, np);
    pw__gltf_json_textures(o, parts, I, np);
    pw__gltf_json_accessors(o, I, np);
    pw__gltf_json_views(o);
    pw__js(o, "}");
}

/* ---- the container ------------------------------------------------------------ */

static void pw__gltf_le32(unsigned char *b, uint32_t v)
{
    b[0] = (unsigned char)v;
    b[1] = (unsigned char)(v >> 8);
    b[2] = (unsigned char)(v >> 16);
    b[3] = (unsigned char)(v >> 24);
}

/* GLB: the 12-byte header, the JSON chunk padded with spaces, the binary
 * chunk padded with zeros (both to 4 bytes). */
static int pw__gltf_emit(const pw__gltf_out *o, pw_write_fn w, void *ctx, pw_err *e)
{
    static const char spaces[4] = {' ', ' ', ' ', ' '}, zeros[4] = {0, 0, 0, 0};
    size_t jl = (o->json.size + 3) & ~(size_t)3, bl = (o->bin.size + 3) & ~(size_t)3, total = 12 + 8 + jl + 8 + bl;
    unsigned char h[20];
    if (total > 0xFFFFFFFFu)
        return pw_fail(e, PW_ERR_LIMIT, "glTF: %lu bytes is over GLB's 4 GiB", (unsigned long)total);
    memcpy(h, "glTF", 4);
    pw__gltf_le32(h + 4, 2);
    pw__gltf_le32(h + 8, (uint32_t)total);
    pw__gltf_le32(h + 12, (uint32_t)jl);
    memcpy(h + 16, "JSON", 4);
    if (w(ctx, h, 20) || w(ctx, o->json.data, o->json.size) || w(ctx, spaces, jl - o->json.size))
        return pw_fail(e, PW_ERR_IO, "write failed");
    pw__gltf_le32(h, (uint32_t)bl);
    memcpy(h + 4, "BIN\0", 4);
    if (w(ctx, h, 8) || w(ctx, o->bin.data, o->bin.size) || w(ctx, zeros, bl - o->bin.size))
        return pw_fail(e, PW_ERR_IO, "write failed");
    return PW_OK;
}

/* The camera pw_render's callers use for a view (fields of a method's
 * render options; zero fields take pw_view_defaults): framing pos at 35
 * degrees. Sets *aspect. */
PW__DEF pw_camera pw_gltf_view_camera(const float *pos, int nv, int width, int height, const float view_dir[3],
                                      const float up[3], float *aspect)
{
    float vd[3], u[3], bg[3] = {1, 1, 1};
    int ss = 1;
    memcpy(vd, view_dir, sizeof vd);
    memcpy(u, up, sizeof u);
    pw_view_defaults(&width, &height, &ss, vd, u, bg);
    *aspect = (float)width / (float)height;
    return pw_camera_frame(pos, nv, vd, u, 35.0f, *aspect);
}

/* Writes the scene as one binary glTF file. */
PW__DEF int pw_gltf_write(const pw_alloc *a, const pw_gltf_scene *S, pw_write_fn w, void *ctx, pw_err *e)
{
    const pw_gltf_part *parts = S ? S->parts : NULL;
    pw__gltf_out o;
    pw__gltf_info *I;
    int p, r = PW_OK, np = S ? S->nparts : 0;
    if (!parts || np < 1 || !w) return pw_fail(e, PW_ERR_INVALID, "glTF: no parts or no writer");
    if (S->camera && !(S->aspect > 0.0f && S->camera->znear > 0.0f && S->camera->zfar > S->camera->znear &&
                       S->camera->fovy_deg > 0.0f && S->camera->fovy_deg < 180.0f))
        return pw_fail(e, PW_ERR_INVALID, "glTF: the camera's field of view, aspect or clipping range is not valid");
    for (p = 0; p < np; p++)
        if ((r = pw__gltf_check(&parts[p], p, e))) return r;
    memset(&o, 0, sizeof o);
    o.a = a;
    o.bin.alloc = a;
    o.json.alloc = a;
    o.js.w = pw_buf_write;
    o.js.ctx = &o.json;
    if (!(I = (pw__gltf_info *)pw_calloc_array(a, (size_t)np, sizeof *I, "glTF parts", e))) return PW_ERR_NOMEM;
    for (p = 0; p < np && r == PW_OK; p++) {
        pw__gltf_verts V;
        float *nrm = NULL;
        if ((r = pw__gltf_split(a, &parts[p], &V, e))) break;
        if ((r = pw__gltf_normals(a, &parts[p], &nrm, e)) == PW_OK)
            r = pw__gltf_part_data(&o, &parts[p], &V, nrm, &I[p], e);
        pw__gltf_verts_free(a, &V);
        pw_free(a, nrm);
    }
    if (r == PW_OK) {
        pw__gltf_json(&o, S, I);
        pw__wb_flush(&o.js);
        r = o.js.failed || o.json.failed ? pw_fail(e, PW_ERR_NOMEM, "out of memory writing glTF")
                                         : pw__gltf_emit(&o, w, ctx, e);
    }
    pw_free(a, I);
    pw_free(a, o.views);
    pw_free(a, o.bin.data);
    pw_free(a, o.json.data);
    return r;
}

#endif /* PW__GLTF_V1 */
