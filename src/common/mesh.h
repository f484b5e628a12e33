/* mesh: polygon meshes as flat arrays, and their file formats.
 *
 * A pw_mesh is a list of vertex positions and a list of polygons of any
 * degree, stored as offsets into one array of corners (CSR layout): the
 * corners of face f are fv[fstart[f]] .. fv[fstart[f+1]-1], counter-clockwise
 * seen from outside. Texture coordinates, when present, have their own index
 * per corner (fuv), as in OBJ, so that seams can split a vertex's uv.
 *
 * Readers (all from memory; `name` is only used in messages, usually the
 * file name, and may be NULL):
 *   STL  binary and ASCII (several solids allowed); corners with bit-identical
 *        positions welded into one vertex; facet normals ignored.
 *   OBJ  v/vt/f (a, a/b, a//c, a/b/c, negative indices), any polygon degree,
 *        '\' line continuation; vn, o, g, s, usemtl, mtllib, l, p and the
 *        free-form statements are skipped; an unknown keyword is an error.
 *        uv and fuv are kept when every face has texture indices.
 *   OFF  [ST][C][N]OFF, ASCII (one vertex or face per line, extra values such
 *        as colours ignored, '#' comments anywhere, the keyword optional) and
 *        Geomview's BINARY form. 4OFF and nOFF are refused (unsupported).
 *   PLY  ascii, binary_little_endian and binary_big_endian 1.0, every scalar
 *        type; vertex x, y, z (+ u/v, s/t or texture_u/texture_v as uv);
 *        face list vertex_indices or vertex_index; anything else is skipped.
 * Every reader refuses, with a message naming the file, the line (text) or
 * byte offset (binary) and the element: truncated data (PW_ERR_PARSE), counts
 * the data cannot hold (checked before allocating), sizes over
 * PW_MAX_MESH_ELEMENTS / PW_MAX_FACE_DEGREE (PW_ERR_LIMIT), vertex indices
 * out of range and NaN/Inf coordinates (PW_ERR_INVALID), faces with fewer
 * than 3 corners and meshes without faces (PW_ERR_DEGENERATE). Element
 * indices in messages are 0-based; OBJ indices are quoted as written.
 *
 * Numbers are parsed and printed by hand: locale-independent, no NUL
 * terminator needed, the same bytes on every platform; floats are written
 * with 9 significant digits, so a write -> read round trip is exact.
 *
 * API: pw_mesh_alloc/free/copy/validate/bounds/triangulate;
 * pw_mesh_read_obj/off/ply/stl/memory (+ pw_mesh_load); pw_mesh_write_obj,
 * pw_mesh_write_mtl (+ pw_mesh_save_obj, pw_mesh_save_mtl). The file forms
 * are left out by PW_NO_STDIO. */
#ifndef PW__MESH_V1
#define PW__MESH_V1

#include "base.h"
#include "vec.h"
#include "text.h"
#include "rng.h"

typedef struct pw_mesh {
    int nv;
    float *pos; /* nv*3: vertex i is pos[3*i], pos[3*i+1], pos[3*i+2] */
    int nf;
    int *fstart; /* nf+1 offsets into fv; fstart[0] = 0 */
    int *fv;     /* fstart[nf] vertex indices, counter-clockwise per face */
    int nuv;
    float *uv; /* nuv*2 texture coordinates, or NULL */
    int *fuv;  /* fstart[nf]: uv index of each corner, or NULL */
} pw_mesh;

/* Frees the arrays and zeroes *m (NULL is fine). */
PW__DEF void pw_mesh_free(const pw_alloc *a, pw_mesh *m)
{
    if (!m) return;
    pw_free(a, m->pos);
    pw_free(a, m->fstart);
    pw_free(a, m->fv);
    pw_free(a, m->uv);
    pw_free(a, m->fuv);
    memset(m, 0, sizeof *m);
}

/* Shared by pw_mesh_alloc and pw_mesh_copy: nuv < 0 means no uv arrays. */
PW__DEF int pw__mesh_alloc(const pw_alloc *a, pw_mesh *m, int nv, int nf, int nc, int nuv, pw_err *e)
{
    memset(m, 0, sizeof *m);
    if (nv < 0 || nf < 0 || nc < 0)
        return pw_fail(e, PW_ERR_INVALID, "mesh: negative size (%d vertices, %d faces, %d corners)", nv, nf, nc);
    if (nv > PW_MAX_MESH_ELEMENTS || nf > PW_MAX_MESH_ELEMENTS || nc > PW_MAX_MESH_ELEMENTS ||
        nuv > PW_MAX_MESH_ELEMENTS)
        return pw_fail(e, PW_ERR_LIMIT, "mesh: %d vertices, %d faces, %d corners exceed the limit of %d elements", nv,
                       nf, nc, PW_MAX_MESH_ELEMENTS);
    m->pos = (float *)pw_calloc_array(a, (size_t)nv * 3, sizeof(float), "mesh positions", e);
    m->fstart = (int *)pw_calloc_array(a, (size_t)nf + 1, sizeof(int), "mesh faces", e);
    m->fv = (int *)pw_calloc_array(a, (size_t)nc, sizeof(int), "mesh corners", e);
    if (nuv >= 0) {
        m->uv = (float *)pw_calloc_array(a, (size_t)nuv * 2, sizeof(float), "mesh uvs", e);
        m->fuv = (int *)pw_calloc_array(a, (size_t)nc, sizeof(int), "mesh corner uvs", e);
    }
    if (!m->pos || !m->fstart || !m->fv || (nuv >= 0 && (!m->uv || !m->fuv))) {
        pw_mesh_free(a, m);
        return PW_ERR_NOMEM;
    }
    m->nv = nv;
    m->nf = nf;
    m->nuv = nuv > 0 ? nuv : 0;
    return PW_OK;
}

/* Allocates a zeroed mesh of nv vertices, nf faces and ncorners corners; the
 * caller fills pos, all nf+1 entries of fstart, and fv. With with_uv != 0 it
 * also allocates one texture coordinate per corner (nuv = ncorners, uv
 * zeroed, fuv[i] = i); lower nuv afterwards when sharing uvs. */
PW__DEF int pw_mesh_alloc(const pw_alloc *a, pw_mesh *m, int nv, int nf, int ncorners, int with_uv, pw_err *e)
{
    int r = pw__mesh_alloc(a, m, nv, nf, ncorners, with_uv ? ncorners : -1, e), i;
    if (r == PW_OK && with_uv)
        for (i = 0; i < ncorners; i++) m->fuv[i] = i;
    return r;
}

/* Structural check: sizes, offsets, every index in range, every face with
 * at least 3 corners, finite coordinates. Meshes from the readers pass. */
PW__DEF int pw_mesh_validate(const pw_mesh *m, pw_err *e)
{
    int f, i;
    if (m->nv < 0 || m->nf < 0 || m->nuv < 0 || !m->fstart || (m->nv && !m->pos) || (m->nuv && !m->uv))
        return pw_fail(e, PW_ERR_INVALID, "mesh: negative count or missing array");
    if (m->fstart[0] != 0) return pw_fail(e, PW_ERR_INVALID, "mesh: fstart[0] is %d, must be 0", m->fstart[0]);
    for (f = 0; f < m->nf; f++) {
        int b = m->fstart[f], d; /* b >= 0 by induction */
        if ((int64_t)m->fstart[f + 1] < (int64_t)b + 3)
            return pw_fail(e, PW_ERR_DEGENERATE, "mesh: face %d has %ld corners (at least 3 needed)", f,
                           (long)m->fstart[f + 1] - b);
        d = m->fstart[f + 1] - b;
        for (i = b; i < b + d; i++) {
            if (!m->fv || m->fv[i] < 0 || m->fv[i] >= m->nv)
                return pw_fail(e, PW_ERR_INVALID,
                               "mesh: face %d, corner %d: vertex index %d out of range (%d vertices)", f, i - b,
                               m->fv ? m->fv[i] : -1, m->nv);
            if (m->fuv && (m->fuv[i] < 0 || m->fuv[i] >= m->nuv))
                return pw_fail(e, PW_ERR_INVALID, "mesh: face %d, corner %d: uv index %d out of range (%d uvs)", f,
                               i - b, m->fuv[i], m->nuv);
        }
    }
    for (i = 0; i < m->nv * 3; i++)
        if (!pw_is_finite(m->pos[i]))
            return pw_fail(e, PW_ERR_INVALID, "mesh: vertex %d has a non-finite coordinate", i / 3);
    for (i = 0; m->fuv && i < m->nuv * 2; i++)
        if (!pw_is_finite(m->uv[i]))
            return pw_fail(e, PW_ERR_INVALID, "mesh: texture coordinate %d is not finite", i / 2);
    return PW_OK;
}

/* Axis-aligned bounding box; all zero for a mesh without vertices. */
PW__DEF void pw_mesh_bounds(const pw_mesh *m, float lo[3], float hi[3])
{
    int i, k;
    for (k = 0; k < 3; k++) lo[k] = hi[k] = m->nv > 0 ? m->pos[k] : 0.0f;
    for (i = 1; i < m->nv; i++)
        for (k = 0; k < 3; k++) {
            float x = m->pos[3 * i + k];
            if (x < lo[k]) lo[k] = x;
            if (x > hi[k]) hi[k] = x;
        }
}

/* Deep copy (dst is overwritten, not freed). */
PW__DEF int pw_mesh_copy(const pw_alloc *a, const pw_mesh *src, pw_mesh *dst, pw_err *e)
{
    int nc = src->nf > 0 ? src->fstart[src->nf] : 0;
    int with_uv = src->uv && src->fuv;
    int r = pw__mesh_alloc(a, dst, src->nv, src->nf, nc, with_uv ? src->nuv : -1, e);
    if (r) return r;
    if (src->nv) memcpy(dst->pos, src->pos, (size_t)src->nv * 3 * sizeof(float));
    if (src->fstart) memcpy(dst->fstart, src->fstart, ((size_t)src->nf + 1) * sizeof(int));
    if (nc) memcpy(dst->fv, src->fv, (size_t)nc * sizeof(int));
    if (with_uv) {
        if (src->nuv) memcpy(dst->uv, src->uv, (size_t)src->nuv * 2 * sizeof(float));
        if (nc) memcpy(dst->fuv, src->fuv, (size_t)nc * sizeof(int));
    }
    return PW_OK;
}

/* Fan triangulation: face f with corners c0..c(d-1) becomes the triangles
 * (c0, ck, ck+1), k = 1..d-2, in order, so triangles of one face are
 * contiguous. Vertices and uvs are shared with the source numbering. When
 * tri_face is not NULL it receives a new array (free with pw_free(a, ...))
 * mapping each triangle to its source face. Fans suit convex polygons, which
 * is what renderers and the triangle-based methods are given. */
PW__DEF int pw_mesh_triangulate(const pw_alloc *a, const pw_mesh *m, pw_mesh *out, int **tri_face, pw_err *e)
{
    int64_t nt = 0;
    int f, k, t = 0, r, with_uv = m->uv && m->fuv;
    int *map = NULL;
    memset(out, 0, sizeof *out);
    if (tri_face) *tri_face = NULL;
    if ((r = pw_mesh_validate(m, e))) return r;
    for (f = 0; f < m->nf; f++) nt += m->fstart[f + 1] - m->fstart[f] - 2;
    if (nt * 3 > PW_MAX_MESH_ELEMENTS)
        return pw_fail(e, PW_ERR_LIMIT, "triangulation: %ld triangles exceed the limit", (long)nt);
    if ((r = pw__mesh_alloc(a, out, m->nv, (int)nt, (int)nt * 3, with_uv ? m->nuv : -1, e))) return r;
    if (tri_face && !(map = (int *)pw_alloc_array(a, (size_t)nt + 1, sizeof(int), "triangle map", e))) {
        pw_mesh_free(a, out);
        return PW_ERR_NOMEM;
    }
    if (m->nv) memcpy(out->pos, m->pos, (size_t)m->nv * 3 * sizeof(float));
    if (with_uv && m->nuv) memcpy(out->uv, m->uv, (size_t)m->nuv * 2 * sizeof(float));
    for (f = 0; f < m->nf; f++) {
        int b = m->fstart[f], d = m->fstart[f + 1] - b;
        for (k = 1; k + 1 < d; k++, t++) {
            int c[3], j;
            c[0] = b;
            c[1] = b + k;
            c[2] = b + k + 1;
            for (j = 0; j < 3; j++) {
                out->fv[3 * t + j] = m->fv[c[j]];
                if (with_uv) out->fuv[3 * t + j] = m->fuv[c[j]];
            }
            out->fstart[t + 1] = 3 * t + 3;
            if (map) map[t] = f;
        }
    }
    if (tri_face) *tri_face = map;
    return PW_OK;
}

/* Reads a vertex's 3 coordinates and refuses NaN/Inf (also values too large
 * for a float). */
PW__DEF int pw__sc_xyz(pw__sc *s, float xyz[3], long long index)
{
    double v;
    int k, r;
    for (k = 0; k < 3; k++) {
        if ((r = pw__sc_num(s, &v, "vertex", index))) return r;
        xyz[k] = pw__num_to_float(v);
        if (!pw_is_finite(xyz[k]))
            return pw__sc_fail(s, PW_ERR_INVALID, "vertex %lld has a non-finite coordinate", index);
    }
    return PW_OK;
}

/* ---- mesh builder: growable arrays shared by the readers ----------------- */

typedef struct pw__mb {
    const pw_alloc *a;
    pw_err *e;
    pw_mesh m;
    int nc;    /* corners so far */
    int uv_ok; /* every face so far has a uv index on every corner */
    size_t cpos, cfs, cfv, cuv, cfuv;
} pw__mb;

PW__DEF int pw__mb_init(pw__mb *b, const pw_alloc *a, pw_err *e)
{
    memset(b, 0, sizeof *b);
    b->a = a;
    b->e = e;
    b->uv_ok = 1;
    if (pw_grow(a, (void **)&b->m.fstart, &b->cfs, 1, sizeof(int), "mesh faces", e)) return PW_ERR_NOMEM;
    b->m.fstart[0] = 0;
    return PW_OK;
}

PW__DEF void pw__mb_free(pw__mb *b) { pw_mesh_free(b->a, &b->m); }

/* Reserves room for counts announced by a header (already checked). */
PW__DEF int pw__mb_reserve(pw__mb *b, int nv, int nf, int nc)
{
    if (pw_grow(b->a, (void **)&b->m.pos, &b->cpos, (size_t)nv * 3, sizeof(float), "vertex positions", b->e) ||
        pw_grow(b->a, (void **)&b->m.fstart, &b->cfs, (size_t)nf + 1, sizeof(int), "mesh faces", b->e) ||
        pw_grow(b->a, (void **)&b->m.fv, &b->cfv, (size_t)nc, sizeof(int), "face corners", b->e))
        return PW_ERR_NOMEM;
    return PW_OK;
}

PW__DEF int pw__mb_vertex(pw__mb *b, const float xyz[3])
{
    if (pw_grow(b->a, (void **)&b->m.pos, &b->cpos, (size_t)b->m.nv * 3 + 3, sizeof(float), "vertex positions", b->e))
        return PW_ERR_NOMEM;
    memcpy(b->m.pos + (size_t)b->m.nv * 3, xyz, 3 * sizeof(float));
    b->m.nv++;
    return PW_OK;
}

PW__DEF int pw__mb_uv(pw__mb *b, float u, float v)
{
    if (pw_grow(b->a, (void **)&b->m.uv, &b->cuv, (size_t)b->m.nuv * 2 + 2, sizeof(float), "texture coordinates", b->e))
        return PW_ERR_NOMEM;
    b->m.uv[2 * b->m.nuv] = u;
    b->m.uv[2 * b->m.nuv + 1] = v;
    b->m.nuv++;
    return PW_OK;
}

/* Makes room for n more corners. */
PW__DEF int pw__mb_room(pw__mb *b, int n)
{
    if (pw_grow(b->a, (void **)&b->m.fv, &b->cfv, (size_t)b->nc + n, sizeof(int), "face corners", b->e) ||
        (b->uv_ok && pw_grow(b->a, (void **)&b->m.fuv, &b->cfuv, (size_t)b->nc + n, sizeof(int), "corner uvs", b->e)))
        return PW_ERR_NOMEM;
    return PW_OK;
}

/* Appends a corner of the face being built: vertex v, uv index t (-1: none). */
PW__DEF int pw__mb_corner(pw__mb *b, int v, int t)
{
    if (pw_grow(b->a, (void **)&b->m.fv, &b->cfv, (size_t)b->nc + 1, sizeof(int), "face corners", b->e))
        return PW_ERR_NOMEM;
    b->m.fv[b->nc] = v;
    if (b->uv_ok) {
        if (pw_grow(b->a, (void **)&b->m.fuv, &b->cfuv, (size_t)b->nc + 1, sizeof(int), "corner uvs", b->e))
            return PW_ERR_NOMEM;
        b->m.fuv[b->nc] = t;
    }
    b->nc++;
    return PW_OK;
}

PW__DEF int pw__mb_end_face(pw__mb *b)
{
    if (pw_grow(b->a, (void **)&b->m.fstart, &b->cfs, (size_t)b->m.nf + 2, sizeof(int), "mesh faces", b->e))
        return PW_ERR_NOMEM;
    b->m.fstart[++b->m.nf] = b->nc;
    return PW_OK;
}

/* Gives an over-allocated array back (keeping it if realloc fails). */
PW__DEF void pw__mb_shrink(const pw_alloc *a, void **p, size_t bytes)
{
    void *q;
    if (!*p) return;
    q = pw_realloc(a, *p, bytes);
    if (q) *p = q;
}

/* Hands the mesh over: refuses an empty one, drops partial uvs. */
PW__DEF int pw__mb_finish(pw__mb *b, pw_mesh *out, const char *name)
{
    pw_mesh *m = &b->m;
    if (m->nf == 0)
        return pw_fail(b->e, PW_ERR_DEGENERATE, "%s: the mesh has no faces (%d vertices)", name ? name : "<memory>",
                       m->nv);
    if (!b->uv_ok || !m->nuv || !m->fuv) {
        pw_free(b->a, m->uv);
        pw_free(b->a, m->fuv);
        m->uv = NULL;
        m->fuv = NULL;
        m->nuv = 0;
    }
    pw__mb_shrink(b->a, (void **)&m->pos, (size_t)m->nv * 3 * sizeof(float));
    pw__mb_shrink(b->a, (void **)&m->fstart, ((size_t)m->nf + 1) * sizeof(int));
    pw__mb_shrink(b->a, (void **)&m->fv, (size_t)b->nc * sizeof(int));
    pw__mb_shrink(b->a, (void **)&m->fuv, (size_t)b->nc * sizeof(int));
    pw__mb_shrink(b->a, (void **)&m->uv, (size_t)m->nuv * 2 * sizeof(float));
    *out = *m;
    memset(m, 0, sizeof *m);
    return PW_OK;
}

/* ---- OBJ ----------------------------------------------------------------- */

/* Statements that do not change a polygon mesh: skipped. (vn: normals are
 * recomputed where needed; free-form geometry is not supported.) */
static const char *const pw__obj_skip[] = {
    "vn",     "vp",     "o",      "g",          "s",         "usemtl", "mtllib", "l",        "p",
    "cstype", "deg",    "bmat",   "step",       "curv",      "curv2",  "surf",   "parm",     "trim",
    "hole",   "scrv",   "sp",     "end",        "con",       "mg",     "bevel",  "c_interp", "d_interp",
    "lod",    "maplib", "usemap", "shadow_obj", "trace_obj", "ctech",  "stech",  "call",     "csh"};

/* Resolves an OBJ index (1-based, or negative = relative to the end). */
PW__DEF int pw__obj_index(pw__sc *s, long long i, int n, const char *what, int face, int *out)
{
    long long r = i > 0 ? i - 1 : n + i;
    if (i == 0 || r < 0 || r >= n)
        return pw__sc_fail(s, PW_ERR_INVALID, "face %d: %s index %lld out of range (%d defined so far%s)", face, what,
                           i, n, i == 0 ? "; OBJ indices start at 1" : "");
    *out = (int)r;
    return PW_OK;
}

/* One face corner "v", "v/t", "v//n" or "v/t/n"; *t = -1 without t. */
PW__DEF int pw__obj_corner(pw__sc *s, const pw__mb *b, int *v, int *t)
{
    const char *start = s->p, *q;
    long long iv, it = 0, in;
    int has_t = 0, r;
    char tok[32];
    q = pw__num_parse_int(s->p, s->end, &iv);
    if (q && q < s->end && *q == '/') {
        if (q + 1 < s->end && q[1] != '/') {
            q = pw__num_parse_int(q + 1, s->end, &it);
            has_t = 1;
        } else q = q + 1;
        if (q && q < s->end && *q == '/') { /* normal index: ignored, may be empty */
            const char *qn = pw__num_parse_int(q + 1, s->end, &in);
            q = qn ? qn : q + 1;
        }
    }
    if (!q || !pw__sc_delim(s, q))
        return pw__sc_fail(s, PW_ERR_PARSE, "face %d: malformed corner '%s'", b->m.nf, pw__sc_tok(s, start, tok));
    s->p = q;
    *t = -1;
    if ((r = pw__obj_index(s, iv, b->m.nv, "vertex", b->m.nf, v))) return r;
    if (has_t && (r = pw__obj_index(s, it, b->m.nuv, "texture coordinate", b->m.nf, t))) return r;
    return PW_OK;
}

PW__DEF int pw__obj_face(pw__sc *s, pw__mb *b)
{
    int deg = 0, with_t = 0, v, t, r;
    if (b->m.nf >= PW_MAX_MESH_ELEMENTS)
        return pw__sc_fail(s, PW_ERR_LIMIT, "more than %d faces", PW_MAX_MESH_ELEMENTS);
    while (!pw__sc_eol(s)) {
        if ((r = pw__obj_corner(s, b, &v, &t))) return r;
        if (deg >= PW_MAX_FACE_DEGREE || b->nc >= PW_MAX_MESH_ELEMENTS)
            return pw__sc_fail(s, PW_ERR_LIMIT, "face %d: more than %d corners", b->m.nf,
                               deg >= PW_MAX_FACE_DEGREE ? PW_MAX_FACE_DEGREE : PW_MAX_MESH_ELEMENTS);
        if ((r = pw__mb_corner(b, v, t))) return r;
        with_t += t >= 0;
        deg++;
    }
    if (deg < 3)
        return pw__sc_fail(s, PW_ERR_DEGENERATE, "face %d has %d corner%s (at least 3 needed)", b->m.nf, deg,
                           deg == 1 ? "" : "s");
    if (with_t != deg) b->uv_ok = 0;
    return pw__mb_end_face(b);
}

PW__DEF int pw__obj_vertex(pw__sc *s, pw__mb *b)
{
    float xyz[3];
    int r;
    if (b->m.nv >= PW_MAX_MESH_ELEMENTS)
        return pw__sc_fail(s, PW_ERR_LIMIT, "more than %d vertices", PW_MAX_MESH_ELEMENTS);
    if ((r = pw__sc_xyz(s, xyz, b->m.nv))) return r; /* w or colours may follow: ignored */
    return pw__mb_vertex(b, xyz);
}

PW__DEF int pw__obj_texcoord(pw__sc *s, pw__mb *b)
{
    double u, v = 0.0;
    int r;
    if (b->m.nuv >= PW_MAX_MESH_ELEMENTS)
        return pw__sc_fail(s, PW_ERR_LIMIT, "more than %d texture coordinates", PW_MAX_MESH_ELEMENTS);
    if ((r = pw__sc_num(s, &u, "texture coordinate", b->m.nuv))) return r;
    if (!pw__sc_eol(s) && (r = pw__sc_num(s, &v, "texture coordinate", b->m.nuv))) return r;
    if (!pw_is_finite(pw__num_to_float(u)) || !pw_is_finite(pw__num_to_float(v)))
        return pw__sc_fail(s, PW_ERR_INVALID, "texture coordinate %d is not finite", b->m.nuv);
    return pw__mb_uv(b, pw__num_to_float(u), pw__num_to_float(v));
}

/* One statement; leaves the cursor at the start of the next line. */
PW__DEF int pw__obj_line(pw__sc *s, pw__mb *b)
{
    size_t n, k;
    char tok[32];
    const char *w = pw__sc_word(s, &n);
    int r = PW_OK;
    if (n == 0) {
        if (s->p < s->end && *s->p != '\n' && *s->p != '#')
            return pw__sc_fail(s, PW_ERR_PARSE, "unexpected '%c'", *s->p); /* stray backslash */
    } else if (pw__sc_is(w, n, "v")) r = pw__obj_vertex(s, b);
    else if (pw__sc_is(w, n, "vt")) r = pw__obj_texcoord(s, b);
    else if (pw__sc_is(w, n, "f") || pw__sc_is(w, n, "fo")) r = pw__obj_face(s, b);
    else {
        for (k = 0; k < sizeof pw__obj_skip / sizeof pw__obj_skip[0]; k++)
            if (pw__sc_is(w, n, pw__obj_skip[k])) break;
        if (k == sizeof pw__obj_skip / sizeof pw__obj_skip[0])
            return pw__sc_fail(s, PW_ERR_PARSE, "unknown OBJ keyword '%s'", pw__sc_tok(s, w, tok));
    }
    if (r == PW_OK) pw__sc_next_line(s);
    return r;
}

/* Reads a Wavefront OBJ file from memory. */
PW__DEF int pw_mesh_read_obj(const pw_alloc *a, const void *data, size_t size, const char *name, pw_mesh *out,
                             pw_err *e)
{
    pw__sc s;
    pw__mb b;
    int r;
    memset(out, 0, sizeof *out);
    pw__sc_init(&s, data, size, name, 1, e);
    if ((r = pw__mb_init(&b, a, e))) return r;
    while (r == PW_OK && s.p < s.end) r = pw__obj_line(&s, &b);
    if (r == PW_OK) r = pw__mb_finish(&b, out, s.name);
    pw__mb_free(&b);
    return r;
}

/* ---- OFF ----------------------------------------------------------------- */

enum { PW__OFF_ST = 1, PW__OFF_C = 2, PW__OFF_N = 4, PW__OFF_4 = 8, PW__OFF_ND = 16 };

/* Recognises the keyword [ST][C][N][4][n]OFF. */
PW__DEF int pw__off_keyword(const char *w, size_t n, int *flags)
{
    size_t i = 0;
    int f = 0;
    if (n >= 2 && w[0] == 'S' && w[1] == 'T') {
        f |= PW__OFF_ST;
        i = 2;
    }
    if (i < n && w[i] == 'C') {
        f |= PW__OFF_C;
        i++;
    }
    if (i < n && w[i] == 'N') {
        f |= PW__OFF_N;
        i++;
    }
    if (i < n && w[i] == '4') {
        f |= PW__OFF_4;
        i++;
    }
    if (i < n && w[i] == 'n') {
        f |= PW__OFF_ND;
        i++;
    }
    if (n - i != 3 || memcmp(w + i, "OFF", 3) != 0) return 0;
    *flags = f;
    return 1;
}

/* The optional keyword and BINARY; leaves the cursor on the counts. */
PW__DEF int pw__off_header(pw__sc *s, int *flags, int *binary)
{
    size_t n;
    const char *w;
    char tok[32];
    *flags = 0;
    *binary = 0;
    pw__sc_skip_empty(s);
    w = pw__sc_word(s, &n);
    if (!pw__off_keyword(w, n, flags)) {
        if (n && (*w == '+' || (*w >= '0' && *w <= '9'))) {
            s->p = w; /* no keyword: it is optional, the counts come first */
            return PW_OK;
        }
        return pw__sc_fail(s, PW_ERR_PARSE, "expected the OFF keyword, found '%s'",
                           n ? pw__sc_tok(s, w, tok) : "end of file");
    }
    if (*flags & (PW__OFF_4 | PW__OFF_ND))
        return pw__sc_fail(s, PW_ERR_UNSUPPORTED, "'%s': %s vertices are not supported", pw__sc_tok(s, w, tok),
                           (*flags & PW__OFF_ND) ? "n-dimensional (nOFF)" : "homogeneous 4D (4OFF)");
    w = pw__sc_word(s, &n);
    if (pw__sc_is(w, n, "BINARY")) {
        *binary = 1;
        pw__sc_next_line(s); /* binary data starts after the newline */
    } else s->p = w;         /* the counts may share the keyword's line */
    return PW_OK;
}

/* A count from the header: an integer within the limit. */
PW__DEF int pw__off_count(pw__sc *s, const char *what, int *out)
{
    long long v;
    int r;
    pw__sc_skip_empty(s);
    if ((r = pw__sc_int(s, &v, what, -1))) return r;
    if (v < 0) return pw__sc_fail(s, PW_ERR_PARSE, "negative %s (%lld)", what, v);
    if (v > PW_MAX_MESH_ELEMENTS)
        return pw__sc_fail(s, PW_ERR_LIMIT, "%s is %lld, over the limit of %d", what, v, PW_MAX_MESH_ELEMENTS);
    *out = (int)v;
    return PW_OK;
}

PW__DEF int pw__off_vertices(pw__sc *s, pw__mb *b, int nv)
{
    float xyz[3];
    int i, r;
    for (i = 0; i < nv; i++) {
        pw__sc_skip_empty(s);
        if (s->p >= s->end)
            return pw__sc_fail(s, PW_ERR_PARSE, "unexpected end of file after %d of %d vertices", i, nv);
        if ((r = pw__sc_xyz(s, xyz, i)) || (r = pw__mb_vertex(b, xyz))) return r;
        pw__sc_next_line(s); /* normals, colours, texture coordinates: ignored */
    }
    return PW_OK;
}

PW__DEF int pw__off_faces(pw__sc *s, pw__mb *b, int nf)
{
    long long d, v;
    int f, k, r;
    for (f = 0; f < nf; f++) {
        pw__sc_skip_empty(s);
        if (s->p >= s->end) return pw__sc_fail(s, PW_ERR_PARSE, "unexpected end of file after %d of %d faces", f, nf);
        if ((r = pw__sc_int(s, &d, "face", f))) return r;
        if (d < 3) return pw__sc_fail(s, PW_ERR_DEGENERATE, "face %d has %lld corners (at least 3 needed)", f, d);
        if (d > PW_MAX_FACE_DEGREE || b->nc + d > PW_MAX_MESH_ELEMENTS)
            return pw__sc_fail(s, PW_ERR_LIMIT, "face %d has %lld corners (limit %d)", f, d, PW_MAX_FACE_DEGREE);
        for (k = 0; k < d; k++) {
            if ((r = pw__sc_int(s, &v, "face", f))) return r;
            if (v < 0 || v >= b->m.nv)
                return pw__sc_fail(s, PW_ERR_INVALID, "face %d: vertex index %lld out of range (%d vertices)", f, v,
                                   b->m.nv);
            if ((r = pw__mb_corner(b, (int)v, -1))) return r;
        }
        if ((r = pw__mb_end_face(b))) return r;
        pw__sc_next_line(s); /* a colour may follow */
    }
    return PW_OK;
}

PW__DEF int pw__off_text(pw__sc *s, pw__mb *b)
{
    int nv, nf, r;
    long long ne;
    size_t left;
    if ((r = pw__off_count(s, "header: number of vertices", &nv)) ||
        (r = pw__off_count(s, "header: number of faces", &nf)))
        return r;
    if (!pw__sc_eol(s) && (r = pw__sc_int(s, &ne, "header: number of edges", -1))) return r;
    pw__sc_next_line(s);
    /* each vertex line is at least "0 0 0\n", each face "3 0 1 2\n" */
    left = (size_t)(s->end - s->p);
    if ((double)nv * 6 + (double)nf * 8 > (double)left + 1)
        return pw__sc_fail(
            s, PW_ERR_PARSE,
            "header claims %d vertices and %d faces, more than the %lu bytes left can hold (truncated file?)", nv, nf,
            (unsigned long)left);
    b->uv_ok = 0;
    if ((r = pw__mb_reserve(b, nv, nf, 3 * nf))) return r;
    if ((r = pw__off_vertices(s, b, nv))) return r;
    return pw__off_faces(s, b, nf);
}

PW__DEF uint32_t pw__mesh_be32(const unsigned char *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

PW__DEF float pw__mesh_float_bits(uint32_t u)
{
    float f;
    memcpy(&f, &u, 4);
    return f;
}

/* Geomview's binary OFF: big-endian int32 counts, per vertex 3 float32
 * coordinates (+3 normal, +4 colour, +2 texture floats as the keyword
 * says), per face int32 n, n int32 indices, int32 k and k float32 colour
 * components. */
PW__DEF int pw__off_binary(pw__sc *s, pw__mb *b, int flags)
{
    const unsigned char *p = (const unsigned char *)s->p, *end = (const unsigned char *)s->end;
    const unsigned char *start = (const unsigned char *)s->p;
    int stride = 3 + (flags & PW__OFF_N ? 3 : 0) + (flags & PW__OFF_C ? 4 : 0) + (flags & PW__OFF_ST ? 2 : 0);
    int32_t nv, nf;
    int i, k, r;
    if (end - p < 12) return pw_fail(s->e, PW_ERR_PARSE, "%s: binary OFF: truncated header", s->name);
    nv = (int32_t)pw__mesh_be32(p);
    nf = (int32_t)pw__mesh_be32(p + 4);
    p += 12;
    if (nv < 0 || nf < 0 || nv > PW_MAX_MESH_ELEMENTS || nf > PW_MAX_MESH_ELEMENTS)
        return pw_fail(s->e, nv < 0 || nf < 0 ? PW_ERR_PARSE : PW_ERR_LIMIT,
                       "%s: binary OFF: %d vertices and %d faces (limit %d)", s->name, nv, nf, PW_MAX_MESH_ELEMENTS);
    if ((double)nv * stride * 4 + (double)nf * 20 > (double)(end - p))
        return pw_fail(s->e, PW_ERR_PARSE,
                       "%s: binary OFF: header claims %d vertices and %d faces, more than the %lu bytes left can hold "
                       "(truncated file?)",
                       s->name, nv, nf, (unsigned long)(end - p));
    if ((r = pw__mb_reserve(b, nv, nf, 3 * nf))) return r;
    for (i = 0; i < nv; i++, p += 4 * stride) {
        float xyz[3];
        for (k = 0; k < 3; k++) xyz[k] = pw__mesh_float_bits(pw__mesh_be32(p + 4 * k));
        if (!pw_is_finite(xyz[0]) || !pw_is_finite(xyz[1]) || !pw_is_finite(xyz[2]))
            return pw_fail(s->e, PW_ERR_INVALID, "%s: binary OFF: vertex %d has a non-finite coordinate", s->name, i);
        pw__mb_vertex(b, xyz); /* reserved: cannot fail */
    }
    b->uv_ok = 0;
    for (i = 0; i < nf; i++) {
        uint32_t d, nc, v;
        if (end - p < 8) break;
        d = pw__mesh_be32(p);
        if (d < 3 || d > PW_MAX_FACE_DEGREE || b->nc + (int)d > PW_MAX_MESH_ELEMENTS)
            return pw_fail(s->e, d < 3 ? PW_ERR_DEGENERATE : PW_ERR_LIMIT,
                           "%s: binary OFF: face %d (byte %lu) has %ld corners (3 to %d allowed)", s->name, i,
                           (unsigned long)(p - start), (long)(int32_t)d, PW_MAX_FACE_DEGREE);
        if ((size_t)(end - p) < 4 * (size_t)d + 8) break;
        for (k = 0, p += 4; k < (int)d; k++, p += 4) {
            v = pw__mesh_be32(p);
            if (v >= (uint32_t)nv)
                return pw_fail(s->e, PW_ERR_INVALID,
                               "%s: binary OFF: face %d: vertex index %ld out of range (%d vertices)", s->name, i,
                               (long)(int32_t)v, nv);
            if ((r = pw__mb_corner(b, (int)v, -1))) return r;
        }
        nc = pw__mesh_be32(p);
        if (nc > 4 || (size_t)(end - p) < 4 + 4 * (size_t)nc)
            return pw_fail(s->e, PW_ERR_PARSE, "%s: binary OFF: face %d: bad colour count %ld or truncated", s->name, i,
                           (long)(int32_t)nc);
        p += 4 + 4 * nc;
        if ((r = pw__mb_end_face(b))) return r;
    }
    if (i < nf) return pw_fail(s->e, PW_ERR_PARSE, "%s: binary OFF: file ends after %d of %d faces", s->name, i, nf);
    return PW_OK;
}

/* Reads an OFF file (ASCII or binary) from memory. */
PW__DEF int pw_mesh_read_off(const pw_alloc *a, const void *data, size_t size, const char *name, pw_mesh *out,
                             pw_err *e)
{
    pw__sc s;
    pw__mb b;
    int flags, binary, r;
    memset(out, 0, sizeof *out);
    pw__sc_init(&s, data, size, name, 0, e);
    if ((r = pw__mb_init(&b, a, e))) return r;
    r = pw__off_header(&s, &flags, &binary);
    if (r == PW_OK) r = binary ? pw__off_binary(&s, &b, flags) : pw__off_text(&s, &b);
    if (r == PW_OK) r = pw__mb_finish(&b, out, s.name);
    pw__mb_free(&b);
    return r;
}

/* ---- PLY ----------------------------------------------------------------- */

enum { PW__PLY_ASCII, PW__PLY_LE, PW__PLY_BE };
enum { PW__R_NONE, PW__R_X, PW__R_Y, PW__R_Z, PW__R_U, PW__R_V, PW__R_IDX };
enum { PW__E_OTHER, PW__E_VERTEX, PW__E_FACE };
#define PW__PLY_MAX_ELEMENTS 64
#define PW__PLY_MAX_PROPS 1024

/* Scalar types 1..8: int8 uint8 int16 uint16 int32 uint32 float32 float64. */
static const unsigned char pw__ply_size[9] = {0, 1, 1, 2, 2, 4, 4, 4, 8};

typedef struct pw__plyprop {
    unsigned char type;  /* scalar type, or the item type of a list */
    unsigned char ctype; /* 0: scalar; else the type of the list's count */
    unsigned char role;  /* PW__R_* */
} pw__plyprop;

typedef struct pw__plyel {
    int kind, first, nprop;
    long long count;
} pw__plyel;

typedef struct pw__ply {
    pw__sc s; /* header and ASCII data */
    int format, nel, nprop, has_uv;
    const unsigned char *bp, *bstart; /* binary data cursor */
    pw__plyel el[PW__PLY_MAX_ELEMENTS];
    pw__plyprop prop[PW__PLY_MAX_PROPS];
    pw__mb *b;
    int nv; /* vertex count declared by the header */
} pw__ply;

/* Records an error naming the line (ASCII) or byte offset (binary). */
PW__DEF int pw__ply_fail(pw__ply *p, int code, const char *fmt, ...)
{
    char msg[200];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (p->bp)
        return pw_fail(p->s.e, code, "%s: byte %lu: %s", p->s.name,
                       (unsigned long)(p->bp - (const unsigned char *)p->bstart), msg);
    return pw_fail(p->s.e, code, "%s:%d: %s", p->s.name, p->s.line, msg);
}

PW__DEF int pw__ply_type(const char *w, size_t n)
{
    static const char *const names[16] = {"char", "int8",  "uchar", "uint8",  "short", "int16",   "ushort", "uint16",
                                          "int",  "int32", "uint",  "uint32", "float", "float32", "double", "float64"};
    int k;
    for (k = 0; k < 16; k++)
        if (pw__sc_is(w, n, names[k])) return k / 2 + 1;
    return 0;
}

PW__DEF int pw__ply_role(int kind, const char *w, size_t n)
{
    if (kind == PW__E_VERTEX) {
        if (pw__sc_is(w, n, "x")) return PW__R_X;
        if (pw__sc_is(w, n, "y")) return PW__R_Y;
        if (pw__sc_is(w, n, "z")) return PW__R_Z;
        if (pw__sc_is(w, n, "u") || pw__sc_is(w, n, "s") || pw__sc_is(w, n, "texture_u") ||
            pw__sc_is(w, n, "texture_s"))
            return PW__R_U;
        if (pw__sc_is(w, n, "v") || pw__sc_is(w, n, "t") || pw__sc_is(w, n, "texture_v") ||
            pw__sc_is(w, n, "texture_t"))
            return PW__R_V;
    }
    if (kind == PW__E_FACE && (pw__sc_is(w, n, "vertex_indices") || pw__sc_is(w, n, "vertex_index"))) return PW__R_IDX;
    return PW__R_NONE;
}

PW__DEF int pw__ply_element(pw__ply *p)
{
    size_t n;
    long long count;
    const char *w = pw__sc_word(&p->s, &n);
    pw__plyel *el;
    int kind = pw__sc_is(w, n, "vertex") ? PW__E_VERTEX : pw__sc_is(w, n, "face") ? PW__E_FACE : PW__E_OTHER, r, k;
    if (n == 0) return pw__ply_fail(p, PW_ERR_PARSE, "element without a name");
    if (p->nel >= PW__PLY_MAX_ELEMENTS)
        return pw__ply_fail(p, PW_ERR_LIMIT, "more than %d elements", PW__PLY_MAX_ELEMENTS);
    for (k = 0; k < p->nel && kind != PW__E_OTHER; k++)
        if (p->el[k].kind == kind)
            return pw__ply_fail(p, PW_ERR_PARSE, "second '%s' element", kind == PW__E_VERTEX ? "vertex" : "face");
    if ((r = pw__sc_int(&p->s, &count, "element count", -1))) return r;
    if (count < 0 || count > (kind == PW__E_OTHER ? INT_MAX : PW_MAX_MESH_ELEMENTS))
        return pw__ply_fail(p, count < 0 ? PW_ERR_PARSE : PW_ERR_LIMIT, "element %d has %lld items (limit %d)", p->nel,
                            count, kind == PW__E_OTHER ? INT_MAX : PW_MAX_MESH_ELEMENTS);
    el = &p->el[p->nel++];
    el->kind = kind;
    el->count = count;
    el->first = p->nprop;
    el->nprop = 0;
    if (kind == PW__E_VERTEX) p->nv = (int)count;
    return PW_OK;
}

PW__DEF int pw__ply_property(pw__ply *p)
{
    size_t n;
    char tok[32];
    const char *w = pw__sc_word(&p->s, &n);
    pw__plyprop pr;
    pw__plyel *el = p->nel ? &p->el[p->nel - 1] : NULL;
    int k;
    if (!el) return pw__ply_fail(p, PW_ERR_PARSE, "property before any element");
    if (p->nprop >= PW__PLY_MAX_PROPS)
        return pw__ply_fail(p, PW_ERR_LIMIT, "more than %d properties", PW__PLY_MAX_PROPS);
    pr.ctype = 0;
    if (pw__sc_is(w, n, "list")) {
        w = pw__sc_word(&p->s, &n);
        if (!(pr.ctype = (unsigned char)pw__ply_type(w, n)))
            return pw__ply_fail(p, PW_ERR_PARSE, "unknown list count type '%s'", pw__sc_tok(&p->s, w, tok));
        w = pw__sc_word(&p->s, &n);
    }
    if (!(pr.type = (unsigned char)pw__ply_type(w, n)))
        return pw__ply_fail(p, PW_ERR_PARSE, "unknown property type '%s'", pw__sc_tok(&p->s, w, tok));
    w = pw__sc_word(&p->s, &n);
    if (n == 0) return pw__ply_fail(p, PW_ERR_PARSE, "property without a name");
    pr.role = (unsigned char)pw__ply_role(el->kind, w, n);
    /* a scalar index list or a list coordinate would be meaningless: skip it */
    if ((pr.role == PW__R_IDX) != (pr.ctype != 0)) pr.role = PW__R_NONE;
    for (k = el->first; k < el->first + el->nprop; k++)
        if (p->prop[k].role == pr.role) pr.role = PW__R_NONE; /* the first one wins */
    p->prop[p->nprop++] = pr;
    el->nprop++;
    return PW_OK;
}

PW__DEF int pw__ply_format(pw__ply *p)
{
    size_t n, nv;
    char tok[32];
    const char *w = pw__sc_word(&p->s, &n), *ver;
    if (pw__sc_is(w, n, "ascii")) p->format = PW__PLY_ASCII;
    else if (pw__sc_is(w, n, "binary_little_endian")) p->format = PW__PLY_LE;
    else if (pw__sc_is(w, n, "binary_big_endian")) p->format = PW__PLY_BE;
    else return pw__ply_fail(p, PW_ERR_UNSUPPORTED, "unknown PLY format '%s'", pw__sc_tok(&p->s, w, tok));
    ver = pw__sc_word(&p->s, &nv);
    if (!pw__sc_is(ver, nv, "1.0") && !pw__sc_is(ver, nv, "1"))
        return pw__ply_fail(p, PW_ERR_UNSUPPORTED, "PLY version '%s' (only 1.0 is supported)",
                            pw__sc_tok(&p->s, ver, tok));
    return PW_OK;
}

/* Header: every line up to end_header. */
PW__DEF int pw__ply_header(pw__ply *p)
{
    size_t n;
    char tok[32];
    const char *w = pw__sc_word(&p->s, &n);
    int r = PW_OK, have_format = 0;
    if (!pw__sc_is(w, n, "ply") || !pw__sc_eol(&p->s))
        return pw__ply_fail(p, PW_ERR_PARSE, "not a PLY file (the first line must be 'ply')");
    for (;;) {
        pw__sc_next_line(&p->s);
        if (p->s.p >= p->s.end) return pw__ply_fail(p, PW_ERR_PARSE, "header ends without 'end_header'");
        w = pw__sc_word(&p->s, &n);
        if (pw__sc_is(w, n, "format")) {
            r = pw__ply_format(p);
            have_format = 1;
        } else if (pw__sc_is(w, n, "element")) r = pw__ply_element(p);
        else if (pw__sc_is(w, n, "property")) r = pw__ply_property(p);
        else if (pw__sc_is(w, n, "end_header")) break;
        else if (n && !pw__sc_is(w, n, "comment") && !pw__sc_is(w, n, "obj_info"))
            return pw__ply_fail(p, PW_ERR_PARSE, "unknown header keyword '%s'", pw__sc_tok(&p->s, w, tok));
        if (r) return r;
    }
    if (!have_format) return pw__ply_fail(p, PW_ERR_PARSE, "header has no 'format' line");
    pw__sc_next_line(&p->s); /* data starts after end_header's newline */
    return PW_OK;
}

/* Checks what the header declares: x, y, z and the index list present, and
 * no more items than the bytes left can hold (before allocating). */
PW__DEF int pw__ply_check(pw__ply *p)
{
    double need = 0.0;
    int e, k, roles = 0;
    for (e = 0; e < p->nel; e++) {
        const pw__plyel *el = &p->el[e];
        int min = 0;
        for (k = el->first; k < el->first + el->nprop; k++) {
            const pw__plyprop *pr = &p->prop[k];
            if (el->kind != PW__E_OTHER) roles |= 1 << pr->role;
            min += p->format == PW__PLY_ASCII ? 2 : pw__ply_size[pr->ctype ? pr->ctype : pr->type];
        }
        need += (double)el->count * min;
        if (el->kind == PW__E_FACE && !(roles & (1 << PW__R_IDX)))
            return pw__ply_fail(p, PW_ERR_PARSE, "the face element has no vertex_indices list");
    }
    if ((roles & 0xE) != 0xE) return pw__ply_fail(p, PW_ERR_PARSE, "no vertex element with x, y and z properties");
    p->has_uv = (roles & 0x30) == 0x30;
    if (need > (double)(p->s.end - p->s.p) + 1)
        return pw__ply_fail(
            p, PW_ERR_PARSE,
            "header declares items needing at least %.0f bytes, but only %lu are left (truncated file?)", need,
            (unsigned long)(p->s.end - p->s.p));
    return PW_OK;
}

/* Decodes one binary scalar: bytes gathered most significant first, then
 * sign or bit pattern applied arithmetically (no implementation-defined
 * casts). */
PW__DEF double pw__ply_decode(const unsigned char *q, int type, int big)
{
    int n = pw__ply_size[type], i;
    uint64_t u = 0;
    uint32_t u32;
    float f;
    double d;
    if (big)
        for (i = 0; i < n; i++) u = u << 8 | q[i];
    else
        for (i = n - 1; i >= 0; i--) u = u << 8 | q[i];
    switch (type) {
    case 1: return u >= 0x80u ? (double)u - 256.0 : (double)u;
    case 3: return u >= 0x8000u ? (double)u - 65536.0 : (double)u;
    case 5: return u >= 0x80000000u ? (double)u - 4294967296.0 : (double)u;
    case 7:
        u32 = (uint32_t)u;
        memcpy(&f, &u32, 4);
        return (double)f;
    case 8: memcpy(&d, &u, 8); return d;
    default: return (double)u; /* unsigned types */
    }
}

/* Reads one value of `type` (ASCII token or binary scalar). */
PW__DEF int pw__ply_value(pw__ply *p, int type, double *v, const char *what, long long index)
{
    char tok[32];
    const char *q;
    if (p->format != PW__PLY_ASCII) {
        if ((size_t)(p->s.end - (const char *)p->bp) < pw__ply_size[type])
            return pw__ply_fail(p, PW_ERR_PARSE, "unexpected end of file in %s %lld", what, index);
        *v = pw__ply_decode(p->bp, type, p->format == PW__PLY_BE);
        p->bp += pw__ply_size[type];
        return PW_OK;
    }
    pw__sc_skip_ws(&p->s);
    if (p->s.p >= p->s.end) return pw__ply_fail(p, PW_ERR_PARSE, "unexpected end of file in %s %lld", what, index);
    q = pw__num_parse(p->s.p, p->s.end, v);
    if (!q || !pw__sc_delim(&p->s, q))
        return pw__ply_fail(p, PW_ERR_PARSE, "%s %lld: malformed number '%s'", what, index,
                            pw__sc_tok(&p->s, p->s.p, tok));
    p->s.p = q;
    return PW_OK;
}

/* Reads a list's count; refuses non-integers and counts the data cannot hold. */
PW__DEF int pw__ply_count(pw__ply *p, int ctype, int type, long long *c, const char *what, long long index)
{
    double v;
    size_t left;
    int r;
    if ((r = pw__ply_value(p, ctype, &v, what, index))) return r;
    left = p->format == PW__PLY_ASCII ? (size_t)(p->s.end - p->s.p) : (size_t)(p->s.end - (const char *)p->bp);
    if (!(v >= 0.0 && v < 4e9) || v != (double)(long long)v)
        return pw__ply_fail(p, PW_ERR_PARSE, "%s %lld: bad list length %g", what, index, v);
    if (v * (p->format == PW__PLY_ASCII ? 1 : pw__ply_size[type]) > (double)left)
        return pw__ply_fail(p, PW_ERR_PARSE, "%s %lld: list of %.0f items runs past the end of the file", what, index,
                            v);
    *c = (long long)v;
    return PW_OK;
}

/* Skips one property value (scalar or list). */
PW__DEF int pw__ply_skip(pw__ply *p, const pw__plyprop *pr, const char *what, long long index)
{
    long long c = 1, k;
    double v;
    int r;
    if (pr->ctype && (r = pw__ply_count(p, pr->ctype, pr->type, &c, what, index))) return r;
    if (p->format != PW__PLY_ASCII && pr->ctype) {
        p->bp += (size_t)c * pw__ply_size[pr->type]; /* checked by pw__ply_count */
        return PW_OK;
    }
    for (k = 0; k < c; k++)
        if ((r = pw__ply_value(p, pr->type, &v, what, index))) return r;
    return PW_OK;
}

PW__DEF int pw__ply_vertices(pw__ply *p, const pw__plyel *el)
{
    long long i;
    int k, r;
    pw__mb *b = p->b;
    for (i = 0; i < el->count; i++) {
        float c[6] = {0, 0, 0, 0, 0, 0}; /* x y z u v, by role - 1 */
        for (k = el->first; k < el->first + el->nprop; k++) {
            const pw__plyprop *pr = &p->prop[k];
            double v;
            if (pr->role == PW__R_NONE || pr->ctype) {
                if ((r = pw__ply_skip(p, pr, "vertex", i))) return r;
                continue;
            }
            if ((r = pw__ply_value(p, pr->type, &v, "vertex", i))) return r;
            c[pr->role - 1] = pw__num_to_float(v);
        }
        if (!pw_is_finite(c[0]) || !pw_is_finite(c[1]) || !pw_is_finite(c[2]))
            return pw__ply_fail(p, PW_ERR_INVALID, "vertex %lld has a non-finite coordinate", i);
        if (!pw_is_finite(c[3]) || !pw_is_finite(c[4]))
            return pw__ply_fail(p, PW_ERR_INVALID, "vertex %lld has a non-finite texture coordinate", i);
        pw__mb_vertex(b, c); /* reserved: cannot fail */
        if (p->has_uv) {
            b->m.uv[2 * i] = c[3];
            b->m.uv[2 * i + 1] = c[4];
        }
    }
    return PW_OK;
}

/* The vertex index list of face f. */
PW__DEF int pw__ply_corners(pw__ply *p, const pw__plyprop *pr, long long f)
{
    long long c, k;
    double v;
    int r;
    pw__mb *b = p->b;
    if ((r = pw__ply_count(p, pr->ctype, pr->type, &c, "face", f))) return r;
    if (c < 3) return pw__ply_fail(p, PW_ERR_DEGENERATE, "face %lld has %lld corners (at least 3 needed)", f, c);
    if (c > PW_MAX_FACE_DEGREE || b->nc + c > PW_MAX_MESH_ELEMENTS)
        return pw__ply_fail(p, PW_ERR_LIMIT, "face %lld has %lld corners (limit %d)", f, c, PW_MAX_FACE_DEGREE);
    if ((r = pw__mb_room(b, (int)c))) return r;
    for (k = 0; k < c; k++) {
        if (p->format != PW__PLY_ASCII) { /* pw__ply_count checked that the list is there */
            v = pw__ply_decode(p->bp, pr->type, p->format == PW__PLY_BE);
            p->bp += pw__ply_size[pr->type];
        } else if ((r = pw__ply_value(p, pr->type, &v, "face", f))) return r;
        if (!(v >= 0.0 && v < (double)p->nv && v == (double)(int)v))
            return pw__ply_fail(p, PW_ERR_INVALID, "face %lld: vertex index %g out of range (%d vertices)", f, v,
                                p->nv);
        b->m.fv[b->nc] = (int)v;
        if (b->uv_ok) b->m.fuv[b->nc] = (int)v; /* vertex uvs: one per vertex */
        b->nc++;
    }
    return PW_OK;
}

PW__DEF int pw__ply_faces(pw__ply *p, const pw__plyel *el)
{
    long long f;
    int k, r;
    for (f = 0; f < el->count; f++) {
        for (k = el->first; k < el->first + el->nprop; k++) {
            const pw__plyprop *pr = &p->prop[k];
            r = pr->role == PW__R_IDX ? pw__ply_corners(p, pr, f) : pw__ply_skip(p, pr, "face", f);
            if (r) return r;
        }
        if ((r = pw__mb_end_face(p->b))) return r;
    }
    return PW_OK;
}

/* Another element: skipped value by value, or in one step when every
 * property is a binary scalar. */
PW__DEF int pw__ply_other(pw__ply *p, const pw__plyel *el)
{
    long long i;
    size_t stride = 0;
    int k, r, fixed = p->format != PW__PLY_ASCII;
    for (k = el->first; k < el->first + el->nprop; k++) {
        fixed &= !p->prop[k].ctype;
        stride += pw__ply_size[p->prop[k].type];
    }
    if (fixed || el->nprop == 0) {
        if ((double)stride * (double)el->count > (double)(p->s.end - (const char *)p->bp))
            return pw__ply_fail(p, PW_ERR_PARSE, "unexpected end of file in an element of %lld items", el->count);
        p->bp += stride * (size_t)el->count;
        return PW_OK;
    }
    for (i = 0; i < el->count; i++)
        for (k = el->first; k < el->first + el->nprop; k++)
            if ((r = pw__ply_skip(p, &p->prop[k], "item", i))) return r;
    return PW_OK;
}

PW__DEF int pw__ply_data(pw__ply *p)
{
    int e, r = PW_OK;
    pw__mb *b = p->b;
    if ((r = pw__mb_reserve(b, p->nv, 0, 0))) return r;
    b->uv_ok = p->has_uv; /* then fuv is written as a copy of fv */
    if (p->has_uv) {
        b->m.uv = (float *)pw_alloc_array(b->a, (size_t)p->nv * 2, sizeof(float), "texture coordinates", b->e);
        if (!b->m.uv) return PW_ERR_NOMEM;
        b->m.nuv = p->nv;
    }
    if (p->format != PW__PLY_ASCII) p->bp = p->bstart = (const unsigned char *)p->s.p;
    for (e = 0; e < p->nel && r == PW_OK; e++) {
        const pw__plyel *el = &p->el[e];
        if (el->kind == PW__E_VERTEX) r = pw__ply_vertices(p, el);
        else if (el->kind == PW__E_FACE) r = pw__ply_faces(p, el);
        else if (p->format == PW__PLY_ASCII && el->nprop == 0) continue;
        else r = pw__ply_other(p, el);
    }
    return r;
}

/* Reads a PLY file (ascii, binary_little_endian, binary_big_endian). */
PW__DEF int pw_mesh_read_ply(const pw_alloc *a, const void *data, size_t size, const char *name, pw_mesh *out,
                             pw_err *e)
{
    pw__ply *p;
    pw__mb b;
    int r;
    memset(out, 0, sizeof *out);
    p = (pw__ply *)pw_calloc_array(a, 1, sizeof *p, "PLY reader", e); /* ~4 KB: not on the stack */
    if (!p) return PW_ERR_NOMEM;
    if ((r = pw__mb_init(&b, a, e))) {
        pw_free(a, p);
        return r;
    }
    pw__sc_init(&p->s, data, size, name, 0, e);
    p->b = &b;
    if (!(r = pw__ply_header(p)) && !(r = pw__ply_check(p)) && !(r = pw__ply_data(p)))
        r = pw__mb_finish(&b, out, p->s.name);
    pw__mb_free(&b);
    pw_free(a, p);
    return r;
}

/* ---- STL ------------------------------------------------------------------ */

/* STL lists each triangle with its own three corners; the readers weld
 * corners with bit-identical positions into one vertex (an open-addressing
 * table on the coordinates' bits), so the mesh is connected as the scanner
 * or CAD program meant it. Facet normals are ignored (they are derived
 * from the corner order anyway). */
typedef struct pw__weld {
    int *slot;
    uint32_t mask;
} pw__weld;

PW__DEF int pw__weld_init(pw__weld *w, pw__mb *b, size_t corners)
{
    size_t cap = 64;
    while (cap < 2 * corners && cap < ((size_t)1 << 30)) cap *= 2;
    w->mask = (uint32_t)(cap - 1);
    w->slot = (int *)pw_alloc_array(b->a, cap, sizeof(int), "STL vertex table", b->e);
    if (!w->slot) return PW_ERR_NOMEM;
    memset(w->slot, 0xFF, cap * sizeof(int));
    return PW_OK;
}

/* Grows the table when half full (rehashing every vertex). */
PW__DEF int pw__weld_grow(pw__weld *w, pw__mb *b)
{
    pw__weld n;
    int v;
    if ((uint32_t)b->m.nv < (w->mask + 1) / 2) return PW_OK;
    if (pw__weld_init(&n, b, (size_t)w->mask + 1)) return PW_ERR_NOMEM;
    for (v = 0; v < b->m.nv; v++) {
        uint32_t h[3], i;
        memcpy(h, b->m.pos + 3 * v, 12);
        i = (uint32_t)pw_hash64(h[0] ^ ((uint64_t)h[1] << 32), h[2]) & n.mask;
        while (n.slot[i] >= 0) i = (i + 1) & n.mask;
        n.slot[i] = v;
    }
    pw_free(b->a, w->slot);
    *w = n;
    return PW_OK;
}

/* The vertex at xyz, added if new; -1 when out of memory. */
PW__DEF int pw__weld_vertex(pw__weld *w, pw__mb *b, const float *xyz)
{
    uint32_t h[3], i;
    if (pw__weld_grow(w, b)) return -1;
    memcpy(h, xyz, 12);
    i = (uint32_t)pw_hash64(h[0] ^ ((uint64_t)h[1] << 32), h[2]) & w->mask;
    while (w->slot[i] >= 0) {
        if (!memcmp(b->m.pos + 3 * w->slot[i], xyz, 12)) return w->slot[i];
        i = (i + 1) & w->mask;
    }
    if (pw__mb_vertex(b, xyz)) return -1;
    return w->slot[i] = b->m.nv - 1;
}

/* One triangle from three welded corners (-0.0 read as 0.0, so that the
 * two zeros weld). */
PW__DEF int pw__stl_triangle(pw__weld *w, pw__mb *b, float c[3][3])
{
    int k, j, v;
    if (b->m.nf >= PW_MAX_MESH_ELEMENTS / 3)
        return pw_fail(b->e, PW_ERR_LIMIT, "STL: more than %d triangles", PW_MAX_MESH_ELEMENTS / 3);
    for (k = 0; k < 3; k++) {
        for (j = 0; j < 3; j++) c[k][j] += 0.0f;
        if ((v = pw__weld_vertex(w, b, c[k])) < 0 || pw__mb_corner(b, v, -1)) return PW_ERR_NOMEM;
    }
    return pw__mb_end_face(b);
}

PW__DEF float pw__le_float(const unsigned char *p)
{
    uint32_t u = p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
    float f;
    memcpy(&f, &u, 4);
    return f;
}

/* Binary STL: an 80-byte header, a little-endian uint32 triangle count,
 * then 50 bytes per triangle (normal, three corners as float32, a 16-bit
 * attribute). */
PW__DEF int pw__stl_binary(const unsigned char *d, size_t size, const char *name, pw__mb *b)
{
    uint32_t n = d[80] | (uint32_t)d[81] << 8 | (uint32_t)d[82] << 16 | (uint32_t)d[83] << 24, t;
    pw__weld w;
    int r = PW_OK, k, j;
    if (n == 0) return pw_fail(b->e, PW_ERR_DEGENERATE, "%s: binary STL with no triangle", name);
    if ((size - 84) / 50 < n)
        return pw_fail(
            b->e, PW_ERR_PARSE,
            "%s: binary STL: the header claims %lu triangles, the %lu bytes after it hold %lu (truncated file?)", name,
            (unsigned long)n, (unsigned long)(size - 84), (unsigned long)((size - 84) / 50));
    if (n > (uint32_t)(PW_MAX_MESH_ELEMENTS / 3))
        return pw_fail(b->e, PW_ERR_LIMIT, "%s: binary STL: %lu triangles (limit %d)", name, (unsigned long)n,
                       PW_MAX_MESH_ELEMENTS / 3);
    if (pw__weld_init(&w, b, (size_t)n)) return PW_ERR_NOMEM;
    for (t = 0; t < n && r == PW_OK; t++) {
        const unsigned char *p = d + 84 + 50 * (size_t)t + 12;
        float c[3][3];
        for (k = 0; k < 3; k++)
            for (j = 0; j < 3; j++) {
                c[k][j] = pw__le_float(p + 12 * k + 4 * j);
                if (!pw_is_finite(c[k][j]))
                    r = pw_fail(b->e, PW_ERR_INVALID, "%s: binary STL: triangle %lu has a non-finite coordinate", name,
                                (unsigned long)t);
            }
        if (r == PW_OK) r = pw__stl_triangle(&w, b, c);
    }
    pw_free(b->a, w.slot);
    return r;
}

/* Expects the keyword `kw` as the next word. */
PW__DEF int pw__stl_expect(pw__sc *s, const char *kw)
{
    size_t n;
    const char *w;
    char tok[32];
    pw__sc_skip_ws(s);
    w = pw__sc_word(s, &n);
    if (!pw__sc_is(w, n, kw))
        return pw__sc_fail(s, PW_ERR_PARSE,
                           n ? "expected '%s', found '%s'" : "expected '%s', found the end of the file", kw,
                           pw__sc_tok(s, w, tok));
    return PW_OK;
}

/* ASCII STL: "solid [name]", then facets "facet normal x y z / outer loop /
 * vertex x y z (three) / endloop / endfacet", then "endsolid [name]"; more
 * solids may follow. */
PW__DEF int pw__stl_ascii(pw__sc *s, pw__mb *b)
{
    pw__weld w;
    int r = PW_OK, k;
    if (pw__weld_init(&w, b, 1024)) return PW_ERR_NOMEM;
    while (r == PW_OK) {
        size_t n;
        const char *kw;
        pw__sc_skip_ws(s);
        if (s->p >= s->end) break;
        kw = pw__sc_word(s, &n);
        if (pw__sc_is(kw, n, "solid") || pw__sc_is(kw, n, "endsolid")) {
            pw__sc_next_line(s); /* the name, if any */
        } else if (pw__sc_is(kw, n, "facet")) {
            float c[3][3], nrm[3];
            if ((r = pw__stl_expect(s, "normal")) || (r = pw__sc_xyz(s, nrm, b->m.nf)) ||
                (r = pw__stl_expect(s, "outer")) || (r = pw__stl_expect(s, "loop")))
                break;
            for (k = 0; k < 3 && r == PW_OK; k++)
                if (!(r = pw__stl_expect(s, "vertex"))) r = pw__sc_xyz(s, c[k], b->m.nf);
            if (r || (r = pw__stl_expect(s, "endloop")) || (r = pw__stl_expect(s, "endfacet"))) break;
            r = pw__stl_triangle(&w, b, c);
        } else {
            char tok[32];
            r = pw__sc_fail(s, PW_ERR_PARSE, "ASCII STL: expected 'facet' or 'endsolid', found '%s'",
                            pw__sc_tok(s, kw, tok));
        }
    }
    pw_free(b->a, w.slot);
    return r;
}

/* Whether an STL is ASCII: it begins with "solid" and has no NUL byte in
 * its first kilobyte (binary files may begin with "solid" too, but their
 * header padding and counts hold zeros). */
PW__DEF int pw__stl_is_ascii(const unsigned char *d, size_t size)
{
    size_t i, n = size < 1024 ? size : 1024;
    for (i = 0; i < n; i++)
        if (!d[i]) return 0;
    return 1;
}

/* Reads an STL file, binary or ASCII, from memory. Binary when the size is
 * exactly what its triangle count says, ASCII when it begins with "solid"
 * and holds text (pw__stl_is_ascii), else binary. */
PW__DEF int pw_mesh_read_stl(const pw_alloc *a, const void *data, size_t size, const char *name, pw_mesh *out,
                             pw_err *e)
{
    const unsigned char *d = (const unsigned char *)data;
    pw__sc s;
    pw__mb b;
    int r;
    memset(out, 0, sizeof *out);
    if ((r = pw__mb_init(&b, a, e))) return r;
    pw__sc_init(&s, data, size, name, 0, e);
    pw__sc_skip_ws(&s);
    if (size >= 84 && (size - 84) % 50 == 0 &&
        (size - 84) / 50 == (size_t)(d[80] | (uint32_t)d[81] << 8 | (uint32_t)d[82] << 16 | (uint32_t)d[83] << 24))
        r = pw__stl_binary(d, size, s.name, &b);
    else if (s.end - s.p >= 5 && !memcmp(s.p, "solid", 5) && pw__stl_is_ascii(d, size)) r = pw__stl_ascii(&s, &b);
    else if (size >= 84) r = pw__stl_binary(d, size, s.name, &b);
    else
        r = pw_fail(e, PW_ERR_PARSE, "%s: not an STL file (%lu bytes: neither 'solid' nor an 84-byte binary header)",
                    s.name, (unsigned long)size);
    if (r == PW_OK) r = pw__mb_finish(&b, out, s.name);
    pw__mb_free(&b);
    return r;
}

/* ---- format detection ---------------------------------------------------- */

/* STL by content: "solid" then "facet" (an OBJ cannot begin so), or a
 * binary STL whose size is exactly what its triangle count says. */
PW__DEF int pw__is_stl(pw__sc *s, const void *data, size_t size)
{
    const unsigned char *d = (const unsigned char *)data;
    size_t n;
    const char *w;
    if (size >= 84 && (size - 84) % 50 == 0 &&
        (size - 84) / 50 == (size_t)(d[80] | (uint32_t)d[81] << 8 | (uint32_t)d[82] << 16 | (uint32_t)d[83] << 24))
        return 1;
    w = pw__sc_word(s, &n);
    if (!pw__sc_is(w, n, "solid")) return 0;
    pw__sc_next_line(s);
    pw__sc_skip_ws(s);
    w = pw__sc_word(s, &n);
    return pw__sc_is(w, n, "facet") || pw__sc_is(w, n, "endsolid");
}

/* Reads OBJ, OFF, PLY or STL, recognised by content: the "ply" magic line,
 * an OFF keyword as the first word (after comments), "solid" followed by a
 * "facet" line or a binary STL's exact size, else by the extension of `name`
 * (.off, .ply, .stl), else OBJ. */
PW__DEF int pw_mesh_read_memory(const pw_alloc *a, const void *data, size_t size, const char *name, pw_mesh *out,
                                pw_err *e)
{
    pw__sc s, t;
    size_t n;
    const char *w;
    int flags;
    pw__sc_init(&s, data, size, name, 0, NULL);
    if (s.end - s.p >= 4 && !memcmp(s.p, "ply", 3) && (s.p[3] == '\n' || s.p[3] == '\r'))
        return pw_mesh_read_ply(a, data, size, name, out, e);
    pw__sc_skip_empty(&s);
    t = s;
    w = pw__sc_word(&s, &n);
    if (pw__off_keyword(w, n, &flags) || (name && pw_has_ext(name, ".off")))
        return pw_mesh_read_off(a, data, size, name, out, e);
    if (name && pw_has_ext(name, ".ply")) return pw_mesh_read_ply(a, data, size, name, out, e);
    if (pw__is_stl(&t, data, size) || (name && pw_has_ext(name, ".stl")))
        return pw_mesh_read_stl(a, data, size, name, out, e);
    return pw_mesh_read_obj(a, data, size, name, out, e);
}

#ifndef PW_NO_STDIO
/* Reads a mesh file (format as pw_mesh_read_memory). */
PW__DEF int pw_mesh_load(const pw_alloc *a, const char *path, pw_mesh *out, pw_err *e)
{
    unsigned char *data;
    size_t size;
    int r;
    memset(out, 0, sizeof *out);
    if ((r = pw_read_file(a, path, &data, &size, e))) return r;
    r = pw_mesh_read_memory(a, data, size, path, out, e);
    pw_free(a, data);
    return r;
}
#endif

/* ---- OBJ and MTL writers -------------------------------------------------- */

/* Names written on a line of their own must not break the line. */
PW__DEF int pw__obj_name_ok(const char *s, const char *what, pw_err *e)
{
    if (s && (strchr(s, '\n') || strchr(s, '\r') || !*s))
        return pw_fail(e, PW_ERR_INVALID, "%s name is empty or contains a line break", what);
    return PW_OK;
}

/* Writes m as OBJ: v lines, vt lines when m has uv and fuv, faces "f v/t"
 * (1-based). mtllib and material (usemtl) lines when not NULL. */
PW__DEF int pw_mesh_write_obj(const pw_mesh *m, const char *mtllib, const char *material, pw_write_fn w, void *ctx,
                              pw_err *e)
{
    pw__wb b;
    int i, f, r, uv = m->uv && m->fuv;
    if ((r = pw_mesh_validate(m, e)) || (r = pw__obj_name_ok(mtllib, "mtllib", e)) ||
        (r = pw__obj_name_ok(material, "material", e)))
        return r;
    b.w = w;
    b.ctx = ctx;
    b.n = 0;
    b.failed = 0;
    pw__wb_str(&b, "# patchwork\n");
    if (mtllib) {
        pw__wb_str(&b, "mtllib ");
        pw__wb_str(&b, mtllib);
        pw__wb_str(&b, "\n");
    }
    for (i = 0; i < m->nv; i++) {
        pw__wb_str(&b, "v");
        pw__wb_float(&b, m->pos[3 * i]);
        pw__wb_float(&b, m->pos[3 * i + 1]);
        pw__wb_float(&b, m->pos[3 * i + 2]);
        pw__wb_str(&b, "\n");
    }
    for (i = 0; uv && i < m->nuv; i++) {
        pw__wb_str(&b, "vt");
        pw__wb_float(&b, m->uv[2 * i]);
        pw__wb_float(&b, m->uv[2 * i + 1]);
        pw__wb_str(&b, "\n");
    }
    if (material) {
        pw__wb_str(&b, "usemtl ");
        pw__wb_str(&b, material);
        pw__wb_str(&b, "\n");
    }
    for (f = 0; f < m->nf; f++) {
        pw__wb_str(&b, "f");
        for (i = m->fstart[f]; i < m->fstart[f + 1]; i++) {
            pw__wb_int(&b, (long long)m->fv[i] + 1, ' ');
            if (uv) pw__wb_int(&b, (long long)m->fuv[i] + 1, '/');
        }
        pw__wb_str(&b, "\n");
    }
    return pw__wb_done(&b, e);
}

/* Writes an MTL file with one material: white (Kd 1 1 1), textured by
 * texture_file (map_Kd) when it is not NULL. */
PW__DEF int pw_mesh_write_mtl(const char *material, const char *texture_file, pw_write_fn w, void *ctx, pw_err *e)
{
    pw__wb b;
    int r;
    if (!material) return pw_fail(e, PW_ERR_INVALID, "MTL: no material name");
    if ((r = pw__obj_name_ok(material, "material", e)) || (r = pw__obj_name_ok(texture_file, "texture file", e)))
        return r;
    b.w = w;
    b.ctx = ctx;
    b.n = 0;
    b.failed = 0;
    pw__wb_str(&b, "# patchwork\nnewmtl ");
    pw__wb_str(&b, material);
    pw__wb_str(&b, "\nKa 1 1 1\nKd 1 1 1\nKs 0 0 0\nd 1\nillum 1\n");
    if (texture_file) {
        pw__wb_str(&b, "map_Kd ");
        pw__wb_str(&b, texture_file);
        pw__wb_str(&b, "\n");
    }
    return pw__wb_done(&b, e);
}

#ifndef PW_NO_STDIO
typedef struct pw__obj_args {
    const pw_mesh *m;
    const char *a, *b;
} pw__obj_args;

PW__DEF int pw__obj_body(void *arg, pw_write_fn w, void *ctx, pw_err *e)
{
    const pw__obj_args *o = (const pw__obj_args *)arg;
    return pw_mesh_write_obj(o->m, o->a, o->b, w, ctx, e);
}

PW__DEF int pw__mtl_body(void *arg, pw_write_fn w, void *ctx, pw_err *e)
{
    const pw__obj_args *o = (const pw__obj_args *)arg;
    return pw_mesh_write_mtl(o->a, o->b, w, ctx, e);
}

/* The MTL file beside an OBJ: obj_path with its extension replaced by .mtl
 * into mtl (size bytes); *name is the MTL's file name without folders, as
 * the OBJ's mtllib line names it. Fails on a NULL or too long path. */
PW__DEF int pw_obj_mtl_path(const char *obj_path, char *mtl, size_t size, const char **name, pw_err *e)
{
    const char *dot, *slash;
    size_t n;
    if (!obj_path || strlen(obj_path) + 5 > size) return pw_fail(e, PW_ERR_INVALID, "OBJ: missing or too long path");
    dot = strrchr(obj_path, '.');
    slash = strrchr(obj_path, '/');
    n = dot && (!slash || dot > slash) ? (size_t)(dot - obj_path) : strlen(obj_path);
    memcpy(mtl, obj_path, n);
    strcpy(mtl + n, ".mtl");
    *name = strrchr(mtl, '/') ? strrchr(mtl, '/') + 1 : mtl;
    return PW_OK;
}

/* pw_mesh_write_obj into the file `path`. */
PW__DEF int pw_mesh_save_obj(const char *path, const pw_mesh *m, const char *mtllib, const char *material, pw_err *e)
{
    pw__obj_args o;
    o.m = m;
    o.a = mtllib;
    o.b = material;
    return pw_write_file(path, pw__obj_body, &o, e);
}

/* pw_mesh_write_mtl into the file `path`. */
PW__DEF int pw_mesh_save_mtl(const char *path, const char *material, const char *texture_file, pw_err *e)
{
    pw__obj_args o;
    o.m = NULL;
    o.a = material;
    o.b = texture_file;
    return pw_write_file(path, pw__mtl_body, &o, e);
}
#endif

#endif /* PW__MESH_V1 */
