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
#include "polyhull.h"
#include "../common/trimesh.h"
#include "../common/atlas.h"
#include "../common/glue.h"
#include "../common/gltf.h"
#include "lapped.h"

/* ---- glue between the public types and the shared core ------------------ */

typedef char lapped__codes_match[(int)LAPPED_ERR_NOCONVERGE == PW_ERR_NOCONVERGE ? 1 : -1];

PW_PUBLIC_GLUE(lapped);
PW_PUBLIC_IMAGE_FREE(lapped, LAPPEDDEF);
PW_PUBLIC_MESH_FREE(lapped, LAPPEDDEF);

LAPPEDDEF lapped_options lapped_default_options(void)
{
    lapped_options o;
    memset(&o, 0, sizeof o);
    o.up[1] = 1.0f;
    o.smoothing = 20;
    o.falloff = 3.0f;
    o.coverage = 0.99f;
    o.max_distortion = 2.0f;
    o.early = 0.25f;
    o.max_pastes = 200000;
    pw_view_defaults(&o.render.width, &o.render.height, &o.render.supersample, o.render.view_dir, o.render.up,
                     o.render.background);
    o.atlas.size = PW_ATLAS_SIZE;
    o.atlas.cone_angle = PW_ATLAS_CONE;
    o.atlas.gutter = PW_ATLAS_GUTTER;
    return o;
}

LAPPEDDEF const char *lapped_result_string(lapped_result r) { return pw_result_string((int)r); }

/* Options with every zero field replaced by its default. */
static lapped_options lapped__options(const lapped_options *opt)
{
    lapped_options d = lapped_default_options(), o = opt ? *opt : d;
    if (!o.up[0] && !o.up[1] && !o.up[2]) o.up[1] = 1.0f;
    if (!o.smoothing) o.smoothing = d.smoothing;
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

/* ---- the triangle mesh every stage works on ------------------------------ */

/* The fan triangulation of the caller's mesh, with adjacency and geometry.
 * Degenerate triangles (pw_trimesh_sliver: zero-area, needles, caps) are
 * kept: they take their neighbours' normal, and growth and the
 * parametrisation treat them apart (grow.c), since real scans are full of
 * them. draw_only: the triangles alone, all that rendering needs. */
static int lapped__mesh_init_as(const pw_alloc *a, const lapped_mesh *in, int draw_only, pw_trimesh *m, pw_err *e)
{
    pw_mesh v;
    memset(m, 0, sizeof *m);
    if (!in) return pw_fail(e, PW_ERR_INVALID, "no mesh given");
    v = lapped__pw_mesh(in);
    return draw_only ? pw_trimesh_init_tris(a, &v, m, e) : pw_trimesh_init_ex(a, &v, 1, m, e);
}

static int lapped__mesh_init(const pw_alloc *a, const lapped_mesh *in, pw_trimesh *m, pw_err *e)
{
    return lapped__mesh_init_as(a, in, 0, m, e);
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

/* A lapped texture ready to evaluate: its pastes t, their index ix, and
 * per patch the RGBA image (patches) and the colour source (values; the
 * patches themselves unless the caller gave a values channel). */
typedef struct lapped__look {
    const lapped__index *ix;
    const lapped_texture *t;
    const pw_image *patches, *values;
} lapped__look;

/* The lapped texture L at barycentric point b of triangle f: every paste
 * that contains f composited "over" in order. Colours come from
 * values[patch] (channel count vc), opacity from the patches' alpha
 * (channel 4). The result is straight colour in out[0..vc-1] and total
 * opacity in *alpha. */
static void lapped__eval(const lapped__look *L, int f, const float b[3], float *out, float *alpha)
{
    const lapped__index *ix = L->ix;
    const lapped_texture *t = L->t;
    const pw_image *patches = L->patches, *values = L->values;
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
