/* core.c: lapped.h's glue to the shared core, its defaults, and the mesh
 * every stage works on. Section numbers refer to Praun, Finkelstein and
 * Hoppe 2000. */
#include "../common/base.h"
#include "../common/vec.h"
#include "../common/rng.h"
#include "../common/image.h"
#include "../common/deflate.h"
#include "../common/png.h"
#include "../common/mesh.h"
#include "../common/halfedge.h"
#include "../common/sparse.h"
#include "../common/raster.h"
#include "../common/render.h"
#include "../common/polyhull.h"
#include "../common/glue.h"
#include "lapped.h"

/* ---- glue between the public types and the shared core ------------------ */

typedef char lapped__codes_match[(int)LAPPED_ERR_NOCONVERGE == PW_ERR_NOCONVERGE ? 1 : -1];

PW_PUBLIC_GLUE(lapped);

static void lapped__take_mesh(pw_mesh *m, const pw_alloc *a, lapped_mesh *t)
{
    memset(t, 0, sizeof *t);
    t->nverts = m->nv;
    t->positions = m->pos;
    t->nfaces = m->nf;
    t->face_start = m->fstart;
    t->face_verts = m->fv;
    t->allocator = lapped__allocator(a);
    pw_free(a, m->uv);
    pw_free(a, m->fuv);
    memset(m, 0, sizeof *m);
}

LAPPEDDEF lapped_options lapped_default_options(void)
{
    lapped_options o;
    memset(&o, 0, sizeof o);
    o.field.up[1] = 1.0f;
    o.field.smoothing = 20;
    o.falloff = 3.0f;
    o.coverage = 0.99f;
    o.max_distortion = 2.0f;
    o.early = 0.25f;
    o.max_pastes = 200000;
    return o;
}

LAPPEDDEF const char *lapped_result_string(lapped_result r) { return pw_result_string((int)r); }

/* Options with every zero field replaced by its default. */
static lapped_options lapped__options(const lapped_options *opt)
{
    lapped_options d = lapped_default_options(), o = opt ? *opt : d;
    if (!o.field.up[0] && !o.field.up[1] && !o.field.up[2]) o.field.up[1] = 1.0f;
    if (!o.field.smoothing) o.field.smoothing = d.field.smoothing;
    if (!(o.falloff > 0.0f)) o.falloff = d.falloff;
    if (!(o.coverage > 0.0f)) o.coverage = d.coverage;
    if (!(o.max_distortion > 0.0f)) o.max_distortion = d.max_distortion;
    if (!(o.early > 0.0f)) o.early = d.early;
    if (!o.max_pastes) o.max_pastes = d.max_pastes;
    return o;
}

static pw_progress lapped__progress(const lapped_options *o)
{
    pw_progress p;
    p.fn = o->progress;
    p.user = o->progress_user;
    return p;
}

LAPPEDDEF void lapped_image_free(lapped_image *img)
{
    pw_alloc a;
    if (!img) return;
    a = lapped__alloc(&img->allocator);
    pw_free(&a, img->pixels);
    memset(img, 0, sizeof *img);
}

LAPPEDDEF void lapped_mesh_free(lapped_mesh *m)
{
    pw_alloc a;
    if (!m) return;
    a = lapped__alloc(&m->allocator);
    pw_free(&a, m->positions);
    pw_free(&a, m->face_start);
    pw_free(&a, m->face_verts);
    memset(m, 0, sizeof *m);
}

/* ---- the triangle mesh every stage works on ------------------------------ */

/* Triangles of the fan triangulation, their half-edges (h = 3f+k runs from
 * tri[3f+k] to tri[3f+(k+1)%3]), unit normals and areas. */
typedef struct lapped__mesh {
    int nv, nf;          /* vertices, triangles */
    const float *pos;    /* nv*3, borrowed */
    int *tri;            /* nf*3 */
    pw_hmesh hm;         /* twin[h] = -1 on a boundary */
    float *normal;       /* nf*3 */
    float *area;         /* nf */
    double total_area;
    float diag;          /* bounding-box diagonal */
} lapped__mesh;

static void lapped__mesh_free(const pw_alloc *a, lapped__mesh *m)
{
    pw_free(a, m->tri);
    pw_hmesh_free(a, &m->hm);
    pw_free(a, m->normal);
    pw_free(a, m->area);
    memset(m, 0, sizeof *m);
}

static pw_v3 lapped__vert(const lapped__mesh *m, int v) { return pw_v3_load(m->pos + 3 * v); }

/* Corner k of triangle f. */
static pw_v3 lapped__corner(const lapped__mesh *m, int f, int k) { return lapped__vert(m, m->tri[3 * f + k]); }

/* The triangle across edge k of triangle f (-1 on a boundary). */
static int lapped__across(const lapped__mesh *m, int f, int k)
{
    int t = m->hm.twin[3 * f + k];
    return t < 0 ? -1 : t / 3;
}

/* Checks the caller's polygon mesh (the half-edge build checks topology). */
static int lapped__check_mesh(const lapped_mesh *m, pw_err *e)
{
    pw_mesh v;
    if (!m || !m->positions || !m->face_start || !m->face_verts)
        return pw_fail(e, PW_ERR_INVALID, "mesh has NULL arrays");
    memset(&v, 0, sizeof v);
    v.nv = m->nverts;
    v.pos = m->positions;
    v.nf = m->nfaces;
    v.fstart = m->face_start;
    v.fv = m->face_verts;
    if (m->nfaces < 1) return pw_fail(e, PW_ERR_DEGENERATE, "mesh has no faces");
    return pw_mesh_validate(&v, e);
}

/* Normals, areas and the bounding box; zero-area triangles are refused:
 * neither the field nor the parametrisation is defined on them. */
static int lapped__mesh_geometry(lapped__mesh *m, pw_err *e)
{
    pw_v3 lo, hi;
    int f, v;
    m->total_area = 0.0;
    for (f = 0; f < m->nf; f++) {
        pw_v3 a = lapped__corner(m, f, 0), b = lapped__corner(m, f, 1), c = lapped__corner(m, f, 2);
        pw_v3 n = pw_v3_cross(pw_v3_sub(b, a), pw_v3_sub(c, a));
        float len = pw_v3_len(n), ref = pw_v3_dot(pw_v3_sub(b, a), pw_v3_sub(b, a)) +
                                        pw_v3_dot(pw_v3_sub(c, a), pw_v3_sub(c, a));
        if (!(len > 1e-12f * ref) || !(len > 0.0f))
            return pw_fail(e, PW_ERR_DEGENERATE, "triangle %d (vertices %d, %d, %d) has zero area", f,
                           m->tri[3 * f], m->tri[3 * f + 1], m->tri[3 * f + 2]);
        pw_v3_store(m->normal + 3 * f, pw_v3_scale(n, 1.0f / len));
        m->area[f] = 0.5f * len;
        m->total_area += m->area[f];
    }
    lo = hi = lapped__vert(m, m->tri[0]);
    for (v = 0; v < 3 * m->nf; v++) {
        lo = pw_v3_min(lo, lapped__vert(m, m->tri[v]));
        hi = pw_v3_max(hi, lapped__vert(m, m->tri[v]));
    }
    m->diag = pw_v3_len(pw_v3_sub(hi, lo));
    return PW_OK;
}

/* Fan-triangulates the caller's mesh and builds adjacency and geometry. */
static int lapped__mesh_init(const pw_alloc *a, const lapped_mesh *in, lapped__mesh *m, pw_err *e)
{
    int f, k, t = 0, r, *fs;
    memset(m, 0, sizeof *m);
    if ((r = lapped__check_mesh(in, e)) != PW_OK) return r;
    m->nv = in->nverts;
    m->pos = in->positions;
    m->nf = in->face_start[in->nfaces] - 2 * in->nfaces;
    m->tri = (int *)pw_alloc_array(a, (size_t)m->nf * 3, sizeof(int), "triangles", e);
    m->normal = (float *)pw_alloc_array(a, (size_t)m->nf * 3, sizeof(float), "normals", e);
    m->area = (float *)pw_alloc_array(a, (size_t)m->nf, sizeof(float), "areas", e);
    fs = (int *)pw_alloc_array(a, (size_t)m->nf + 1, sizeof(int), "triangle offsets", e);
    if (!m->tri || !m->normal || !m->area || !fs) r = PW_ERR_NOMEM;
    for (f = 0; r == PW_OK && f < in->nfaces; f++)
        for (k = in->face_start[f] + 1; k + 1 < in->face_start[f + 1]; k++, t++) {
            m->tri[3 * t] = in->face_verts[in->face_start[f]];
            m->tri[3 * t + 1] = in->face_verts[k];
            m->tri[3 * t + 2] = in->face_verts[k + 1];
        }
    for (f = 0; r == PW_OK && f <= m->nf; f++) fs[f] = 3 * f;
    if (r == PW_OK) r = pw_hmesh_build(a, m->nv, m->nf, fs, m->tri, &m->hm, e);
    if (r == PW_OK) r = lapped__mesh_geometry(m, e);
    pw_free(a, fs);
    if (r != PW_OK) lapped__mesh_free(a, m);
    return r;
}

/* ---- pastes per triangle, and evaluating the lapped texture ---------------- */

/* For each triangle, the pastes that contain it, in paste order: entries
 * start[f] .. start[f+1]-1 of paste[] (paste index) and slot[] (position of
 * the triangle in that paste). */
typedef struct lapped__index {
    int *start, *paste, *slot;
} lapped__index;

static void lapped__index_free(const pw_alloc *a, lapped__index *ix)
{
    pw_free(a, ix->start);
    pw_free(a, ix->paste);
    pw_free(a, ix->slot);
    memset(ix, 0, sizeof *ix);
}

static int lapped__index_build(const pw_alloc *a, const lapped_texture *t, lapped__index *ix, pw_err *e)
{
    size_t total = 0;
    int p, k, f;
    memset(ix, 0, sizeof *ix);
    for (p = 0; p < t->npastes; p++) total += (size_t)t->pastes[p].nfaces;
    ix->start = (int *)pw_calloc_array(a, (size_t)t->ntris + 1, sizeof(int), "paste index", e);
    ix->paste = (int *)pw_alloc_array(a, total, sizeof(int), "paste index", e);
    ix->slot = (int *)pw_alloc_array(a, total, sizeof(int), "paste index", e);
    if (!ix->start || !ix->paste || !ix->slot) {
        lapped__index_free(a, ix);
        return PW_ERR_NOMEM;
    }
    for (p = 0; p < t->npastes; p++)
        for (k = 0; k < t->pastes[p].nfaces; k++) ix->start[t->pastes[p].faces[k] + 1]++;
    for (f = 0; f < t->ntris; f++) ix->start[f + 1] += ix->start[f];
    for (p = 0; p < t->npastes; p++) /* counting sort: paste order is kept within each triangle */
        for (k = 0; k < t->pastes[p].nfaces; k++) {
            int face = t->pastes[p].faces[k], at = ix->start[face]++;
            ix->paste[at] = p;
            ix->slot[at] = k;
        }
    for (f = t->ntris; f > 0; f--) ix->start[f] = ix->start[f - 1];
    ix->start[0] = 0;
    return PW_OK;
}

/* Bilinear lookup at texture coordinates (u, v) ((0,0) bottom-left), with
 * everything outside the image transparent (alpha 0): the patch ends
 * there. out gets img->c channels. */
static void lapped__lookup(const pw_image *img, float u, float v, float *out)
{
    float x = u * (float)img->w, y = (1.0f - v) * (float)img->h;
    int k;
    if (!(x >= 0.0f && y >= 0.0f && x <= (float)img->w && y <= (float)img->h)) {
        for (k = 0; k < img->c; k++) out[k] = 0.0f;
        return;
    }
    pw_image_sample_bilinear(img, x, y, out);
}

/* The lapped texture at barycentric point b of triangle f: every paste that
 * contains f composited "over" in order. Colours come from values[patch]
 * (channel count vc), opacity from the patches' alpha (channel 4). The
 * result is straight colour in out[0..vc-1] and total opacity in *alpha. */
static void lapped__eval(const lapped__index *ix, const lapped_texture *t, const pw_image *patches,
                         const pw_image *values, int f, const float b[3], float *out, float *alpha)
{
    float acc[4] = {0, 0, 0, 0}, a = 0.0f, px[4], vx[4];
    int i, k, vc = values[0].c;
    for (i = ix->start[f]; i < ix->start[f + 1]; i++) {
        const lapped_paste *p = &t->pastes[ix->paste[i]];
        const float *uv = p->uvs + 6 * ix->slot[i];
        float u = b[0] * uv[0] + b[1] * uv[2] + b[2] * uv[4];
        float v = b[0] * uv[1] + b[1] * uv[3] + b[2] * uv[5];
        lapped__lookup(&patches[p->patch], u, v, px);
        lapped__lookup(&values[p->patch], u, v, vx);
        for (k = 0; k < vc; k++) acc[k] = vx[k] * px[3] + acc[k] * (1.0f - px[3]);
        a = px[3] + a * (1.0f - px[3]);
    }
    for (k = 0; k < vc; k++) out[k] = a > 0.0f ? acc[k] / a : 0.0f;
    *alpha = a;
}
