/* atlas.c: §4 "Rendering with a texture atlas".
 *
 * The paper builds its atlas "with a method similar to Maillot et al.":
 * regions grown with the §3.3 machinery under a normal-cone and a
 * no-overlap constraint, flattened, arranged in the unit square, and "the
 * texture paste operations are composited into the atlas charts". The
 * charts, the (automatic) arrangement and the baking loop are shared with
 * pgp.h and lst.h: src/common/atlas.h describes them. What is lapped's own
 * is what a texel holds: the lapped texture at that point of the surface
 * (all pastes of the triangle composited in order), composited over
 * mid-grey where the pastes leave it partly transparent, c a + 0.5 (1 - a),
 * in every channel (an atlas has no alpha of its own).
 *
 * Extra channels: the same charts and the same pastes carry any per-texel
 * channel (`values`), composited with the patches' alpha.
 *
 * Export: lapped_write_obj (the triangulated mesh with per-corner
 * coordinates), lapped_write_mtl. */
#include "core.c"
#include "../common/atlas_pack.h"
#include "../common/atlas_bake.h"

/* ---- public functions ---------------------------------------------------------- */

/* Atlas options with zero fields replaced by their defaults, checked
 * (pw_atlas_options). */
static int lapped__atlas_options(const lapped_atlas_options *ao, lapped_atlas_options *o, pw_err *e)
{
    *o = *ao;
    return pw_atlas_options(&o->size, &o->cone_angle, &o->gutter, e);
}

/* Checks that the pastes refer to existing triangles and patches. */
static int lapped__atlas_check_pastes(const lapped_texture *t, int ntris, pw_err *e)
{
    int p, k;
    if (t->ntris != ntris)
        return pw_fail(e, PW_ERR_INVALID, "lapped texture was made for %d triangles; the mesh has %d", t->ntris, ntris);
    if (t->npatches < 1 || !t->patch_size) return pw_fail(e, PW_ERR_INVALID, "lapped texture has no patches");
    if (t->npastes < 0 || (t->npastes > 0 && !t->pastes))
        return pw_fail(e, PW_ERR_INVALID, "lapped texture has %d pastes and no paste array", t->npastes);
    for (p = 0; p < t->npastes; p++) {
        const lapped_paste *q = t->pastes + p;
        if (q->patch < 0 || q->patch >= t->npatches)
            return pw_fail(e, PW_ERR_INVALID, "paste %d: patch %d is outside 0..%d", p, q->patch, t->npatches - 1);
        if (q->nfaces < 0 || (q->nfaces > 0 && (!q->faces || !q->uvs)))
            return pw_fail(e, PW_ERR_INVALID, "paste %d: %d faces without arrays", p, q->nfaces);
        for (k = 0; k < q->nfaces; k++)
            if (q->faces[k] < 0 || q->faces[k] >= ntris)
                return pw_fail(e, PW_ERR_INVALID, "paste %d: face %d is triangle %d, outside 0..%d", p, k, q->faces[k],
                               ntris - 1);
        for (k = 0; k < 6 * q->nfaces; k++)
            if (!pw_is_finite(q->uvs[k]))
                return pw_fail(e, PW_ERR_INVALID, "paste %d: texture coordinate %d is not finite", p, k);
    }
    return PW_OK;
}

/* Checks the patches (RGBA, of the sizes the lapped texture records) and
 * the values (one per patch, of its size, one channel count). */
static int lapped__atlas_check_images(const lapped_texture *t, const lapped_image *patches, const lapped_image *values,
                                      pw_err *e)
{
    int i, r;
    char what[64];
    if (!patches) return pw_fail(e, PW_ERR_INVALID, "no patches");
    for (i = 0; i < t->npatches; i++) {
        const lapped_image *p = patches + i, *v = values ? values + i : NULL;
        snprintf(what, sizeof what, "patch %d", i);
        if ((r = lapped__check_image(p, what, e))) return r;
        if (p->channels != 4)
            return pw_fail(e, PW_ERR_INVALID, "patch %d has %d channels; patches are RGBA", i, p->channels);
        if (p->width != t->patch_size[2 * i] || p->height != t->patch_size[2 * i + 1])
            return pw_fail(e, PW_ERR_INVALID, "patch %d is %dx%d; the lapped texture was made with %dx%d", i, p->width,
                           p->height, t->patch_size[2 * i], t->patch_size[2 * i + 1]);
        if (!v) continue;
        snprintf(what, sizeof what, "value image %d", i);
        if ((r = lapped__check_image(v, what, e))) return r;
        if (v->width != p->width || v->height != p->height || v->channels != values[0].channels)
            return pw_fail(e, PW_ERR_INVALID,
                           "value image %d is %dx%dx%d; patch %d is %dx%d and value image 0 "
                           "has %d channels",
                           i, v->width, v->height, v->channels, i, p->width, p->height, values[0].channels);
    }
    return PW_OK;
}

/* The pw_image views of the patches and of the values (the patches when
 * values is NULL): 2 * npatches entries. */
static pw_image *lapped__atlas_image_views(const pw_alloc *a, const lapped_texture *t, const lapped_image *patches,
                                           const lapped_image *values, pw_err *e)
{
    pw_image *v = (pw_image *)pw_alloc_array(a, 2 * (size_t)t->npatches, sizeof(pw_image), "patch views", e);
    int i;
    for (i = 0; v && i < t->npatches; i++) {
        v[i] = lapped__pw_image(patches + i);
        v[t->npatches + i] = lapped__pw_image(values ? values + i : patches + i);
    }
    return v;
}

/* What a texel of the atlas holds: the lapped texture (or the values
 * channel) at that point, composited over mid-grey. */
typedef struct lapped__atlas_texel {
    lapped__look look;
    int oc;
} lapped__atlas_texel;

static void lapped__atlas_eval(void *user, int f, const float b[3], float *px)
{
    const lapped__atlas_texel *T = (const lapped__atlas_texel *)user;
    float out[4], alpha;
    int k;
    lapped__eval(&T->look, f, b, out, &alpha);
    for (k = 0; k < T->oc; k++) px[k] = out[k] * alpha + 0.5f * (1.0f - alpha);
}

/* Charts, packing and baking of the atlas `job`, once everything has been
 * checked; T says what its texels hold (its index is built here). */
static int lapped__atlas_run(const pw_atlas_job *job, lapped__atlas_texel *T, lapped_atlas *out, pw_image *img,
                             pw_err *e)
{
    pw_atlas_source src;
    lapped__index ix;
    int r;
    memset(&ix, 0, sizeof ix);
    src.fn = lapped__atlas_eval;
    src.user = T;
    src.oc = T->oc;
    r = pw_atlas_layout(job, &out->uvs, &out->ncharts, &out->fill, e);
    if (r == PW_OK) r = lapped__index_build(job->a, T->look.t, &ix, e);
    T->look.ix = &ix;
    if (r == PW_OK) r = pw_atlas_bake(job, out->uvs, &src, img, e);
    lapped__index_free(job->a, &ix);
    T->look.ix = NULL; /* freed */
    if (r == PW_OK) r = pw_report(job->prog, 1.0f, "atlas", e);
    return r;
}

LAPPEDDEF lapped_result lapped_bake_atlas(const lapped_mesh *mesh, const lapped_texture *t, const lapped_source *src,
                                          const lapped_options *opt, lapped_atlas *out, lapped_error *err)
{
    const lapped_image *patches = src ? src->patches : NULL, *values = src ? src->values : NULL;
    lapped_options o = lapped__options(opt);
    lapped_atlas_options ato;
    pw_alloc a = lapped__alloc(&o.allocator);
    pw_progress prog = lapped__progress(&o);
    pw_trimesh m;
    pw_image img, *views = NULL;
    pw_err pe;
    int r;
    pw_err_clear(&pe);
    memset(&m, 0, sizeof m);
    memset(&img, 0, sizeof img);
    if (!out) {
        pw_fail(&pe, PW_ERR_INVALID, "atlas: no output");
        return lapped__done(&pe, err);
    }
    memset(out, 0, sizeof *out);
    if (!t) pw_fail(&pe, PW_ERR_INVALID, "atlas: no lapped texture");
    else if (src && src->npatches != t->npatches)
        pw_fail(&pe, PW_ERR_INVALID, "atlas: the lapped texture was made with %d patches, the source has %d",
                t->npatches, src->npatches);
    if (!pe.code && !lapped__atlas_options(&o.atlas, &ato, &pe) && !lapped__mesh_init(&a, mesh, &m, &pe) &&
        !lapped__atlas_check_pastes(t, m.nf, &pe) && !lapped__atlas_check_images(t, patches, values, &pe) &&
        (views = lapped__atlas_image_views(&a, t, patches, values, &pe)) != NULL) {
        pw_atlas_job job;
        lapped__atlas_texel T;
        job.a = &a;
        job.m = &m;
        job.cone = ato.cone_angle;
        job.size = ato.size;
        job.gutter = ato.gutter;
        job.prog = &prog;
        T.look.t = t;
        T.look.patches = views;
        T.look.values = views + t->npatches;
        T.oc = values ? values[0].channels : 3; /* the patches' colour without their alpha */
        out->ntris = m.nf;
        r = lapped__atlas_run(&job, &T, out, &img, &pe);
        if (r != PW_OK) pw_fail(&pe, r, "atlas: %s", pw_result_string(r)); /* keeps a recorded message */
        else lapped__take_image(&img, &a, &out->image);
    }
    pw_free(&a, views);
    pw_trimesh_free(&a, &m);
    if (pe.code) {
        pw_image_free(&a, &img);
        pw_free(&a, out->uvs);
        memset(out, 0, sizeof *out);
    }
    return lapped__done(&pe, err);
}

LAPPEDDEF void lapped_atlas_free(lapped_atlas *atlas)
{
    pw_alloc a;
    if (!atlas) return;
    a = lapped__alloc(&atlas->image.allocator);
    pw_free(&a, atlas->uvs);
    lapped_image_free(&atlas->image);
    memset(atlas, 0, sizeof *atlas);
}

/* What every export of an atlas checks first (`what` names the format):
 * an atlas and a writer, the mesh triangulated into m with the atlas's
 * allocator (*a), as many triangles as the atlas has. */
static int lapped__atlas_export_open(const lapped_mesh *mesh, const lapped_atlas *atlas, lapped_write_fn fn,
                                     const char *what, pw_alloc *a, pw_trimesh *m, pw_err *e)
{
    memset(m, 0, sizeof *m);
    *a = lapped__alloc(atlas ? &atlas->image.allocator : NULL);
    if (!atlas || !atlas->uvs || !fn) return pw_fail(e, PW_ERR_INVALID, "%s: no atlas or no writer", what);
    if (lapped__mesh_init(a, mesh, m, e)) return e->code;
    if (atlas->ntris != m->nf)
        return pw_fail(e, PW_ERR_INVALID, "%s: the atlas has %d triangles; the mesh has %d", what, atlas->ntris, m->nf);
    return PW_OK;
}

LAPPEDDEF lapped_result lapped_write_obj(const lapped_mesh *mesh, const lapped_atlas *atlas, const char *mtl_name,
                                         lapped_write_fn fn, void *ctx, lapped_error *err)
{
    pw_alloc a;
    pw_trimesh m;
    pw_mesh pm;
    pw_err pe;
    pw_err_clear(&pe);
    memset(&pm, 0, sizeof pm);
    if (!lapped__atlas_export_open(mesh, atlas, fn, "OBJ", &a, &m, &pe) && !pw_atlas_mesh(&a, &m, atlas->uvs, &pm, &pe))
        pw_mesh_write_obj(&pm, mtl_name, mtl_name ? "lapped" : NULL, fn, ctx, &pe);
    pw_free(&a, pm.fstart);
    pw_free(&a, pm.uv);
    pw_free(&a, pm.fuv);
    pw_trimesh_free(&a, &m);
    return lapped__done(&pe, err);
}

LAPPEDDEF lapped_result lapped_write_mtl(const char *texture_name, lapped_write_fn fn, void *ctx, lapped_error *err)
{
    pw_err pe;
    pw_err_clear(&pe);
    if (!fn) pw_fail(&pe, PW_ERR_INVALID, "MTL: no writer");
    else pw_mesh_write_mtl("lapped", texture_name, fn, ctx, &pe);
    return lapped__done(&pe, err);
}
