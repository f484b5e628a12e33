/* export.c: the mapping for other programs. A viewer that knows nothing of
 * material space (a glTF viewer, an engine) draws one 2D texture through
 * per-corner coordinates; pgp_bake_atlas gives it the picture §3's
 * rendering draws, baked into an atlas (the charts, packing and baking
 * loop of lapped textures' §4, src/common/atlas.h), and pgp_tile_atlas the
 * raw coordinates of Eq. (4) with one layer of the tile, for a program that
 * shades material space itself. pgp_write_gltf writes either. */
#include "io.c"
#include "../common/atlas_pack.h"
#include "../common/atlas_bake.h"
#include "../common/gltf.h"

/* ---- baking ------------------------------------------------------------------------------ */

/* What a texel holds: the colour pgp__shade gives the triangle at that
 * point, the mip level from the texel's footprint (the barycentrics'
 * derivatives per texel, from the triangle's corners in the atlas). */
typedef struct pgp__bake {
    const pgp__shading *S;
    const float *uvs;
    int size;
} pgp__bake;

static void pgp__bake_texel(void *user, int f, const float b[3], float *out)
{
    const pgp__bake *B = (const pgp__bake *)user;
    const float *uv = B->uvs + 6 * (size_t)f;
    double x1 = (uv[2] - uv[0]) * (double)B->size, y1 = (uv[1] - uv[3]) * (double)B->size;
    double x2 = (uv[4] - uv[0]) * (double)B->size, y2 = (uv[1] - uv[5]) * (double)B->size;
    double det = x1 * y2 - x2 * y1;
    float db[4] = {0.0f, 0.0f, 0.0f, 0.0f}, rgba[4];
    int k;
    if (det != 0.0) { /* (x, y) = b1 (x1, y1) + b2 (x2, y2): invert the 2x2 matrix */
        db[0] = (float)(y2 / det);
        db[1] = (float)(-x2 / det);
        db[2] = (float)(-y1 / det);
        db[3] = (float)(x1 / det);
    }
    pgp__shade((void *)B->S, f, b[1], b[2], db, rgba);
    for (k = 0; k < 3; k++) out[k] = rgba[k] * rgba[3]; /* over black, as pgp_render composites */
}

PGPDEF pgp_result pgp_bake_atlas(const pgp_map *map, const pgp_tile *tile, const pgp_options *opt, pgp_atlas *out,
                                 pgp_error *err)
{
    const pgp__state *P = pgp__state_of(map);
    pgp_options o = pgp__options(opt);
    pgp_render_options ro;
    pw_progress prog = pgp__progress(&o);
    pgp__shading S;
    pgp__bake B;
    pw_atlas_job job;
    pw_atlas_source src;
    pw_image img;
    pw_err pe;
    pw_err_clear(&pe);
    memset(&S, 0, sizeof S);
    memset(&img, 0, sizeof img);
    if (out) memset(out, 0, sizeof *out);
    if (!out || !P) {
        pw_fail(&pe, PW_ERR_INVALID, "pgp_bake_atlas: NULL map or output");
        return pgp__done(&pe, err);
    }
    if (pw_atlas_options(&o.atlas.size, &o.atlas.cone_angle, &o.atlas.gutter, &pe) == PW_OK &&
        pgp__render_options(&o.render, &ro, &pe) == PW_OK &&
        pgp__shading_init(P, tile, ro.fix, ro.show, &S, &pe) == PW_OK) {
        job.a = &P->a;
        job.m = &P->pp.m;
        job.cone = o.atlas.cone_angle;
        job.size = o.atlas.size;
        job.gutter = o.atlas.gutter;
        job.prog = &prog;
        if (pw_atlas_layout(&job, &out->uvs, &out->ncharts, &out->fill, &pe) == PW_OK) {
            B.S = &S;
            B.uvs = out->uvs;
            B.size = o.atlas.size;
            out->ntris = P->pp.m.nf;
            src.fn = pgp__bake_texel;
            src.user = &B;
            src.oc = 3;
            if (pw_atlas_bake(&job, out->uvs, &src, &img, &pe) == PW_OK) pgp__take_image(&img, &P->a, &out->image);
        }
    }
    pgp__shading_free(P, &S);
    if (pe.code) {
        pw_image_free(&P->a, &img);
        pw_free(&P->a, out->uvs);
        memset(out, 0, sizeof *out);
    }
    return pgp__done(&pe, err);
}

/* ---- the raw coordinates ----------------------------------------------------------------- */

/* Layer image of tile t at material m: the two nearest layers blended. */
static int pgp__tile_layer(const pw_alloc *a, const pgp_tile *t, float m, pw_image *out, pw_err *e)
{
    size_t n = (size_t)t->width * t->height * t->channels, i;
    float z = pw_clampf(m, 0.0f, 1.0f) * (float)(t->layers - 1), w;
    int k0 = (int)z, k1 = k0 + 1 < t->layers ? k0 + 1 : k0, r;
    w = z - (float)k0;
    if ((r = pw_image_alloc(a, out, t->width, t->height, t->channels, e)) != PW_OK) return r;
    for (i = 0; i < n; i++) out->px[i] = (1.0f - w) * t->pixels[(size_t)k0 * n + i] + w * t->pixels[(size_t)k1 * n + i];
    return PW_OK;
}

PGPDEF pgp_result pgp_tile_atlas(const pgp_map *map, const pgp_tile *tile, float m, pgp_atlas *out, pgp_error *err)
{
    const pgp__state *P = pgp__state_of(map);
    pw_image img;
    pw_err pe;
    int f, k;
    pw_err_clear(&pe);
    memset(&img, 0, sizeof img);
    if (out) memset(out, 0, sizeof *out);
    if (!out || !P) pw_fail(&pe, PW_ERR_INVALID, "pgp_tile_atlas: NULL map or output");
    else if (!tile || !tile->pixels || tile->width < 1 || tile->height < 1 || tile->layers < 1 || tile->channels < 1 ||
             tile->channels > 4)
        pw_fail(&pe, PW_ERR_INVALID, "pgp_tile_atlas: empty tile, or bad size or channel count");
    else if (!pw_is_finite(m))
        pw_fail(&pe, PW_ERR_INVALID, "pgp_tile_atlas: material %g is not a finite number", (double)m);
    else if ((out->uvs =
                  (float *)pw_alloc_array(&P->a, (size_t)P->pp.m.nf * 6, sizeof(float), "atlas coordinates", &pe)) &&
             pgp__tile_layer(&P->a, tile, m, &img, &pe) == PW_OK) {
        for (f = 0; f < P->pp.m.nf; f++)
            for (k = 0; k < 3; k++) {
                out->uvs[6 * f + 2 * k] = P->pp.stm[9 * f + 3 * k];
                out->uvs[6 * f + 2 * k + 1] = P->pp.stm[9 * f + 3 * k + 1];
            }
        out->ntris = P->pp.m.nf;
        out->fill = 1.0f;
        out->repeat = 1;
        pgp__take_image(&img, &P->a, &out->image);
    }
    if (pe.code && P) {
        pw_free(&P->a, out ? out->uvs : NULL);
        if (out) memset(out, 0, sizeof *out);
    }
    return pgp__done(&pe, err);
}

PGPDEF void pgp_atlas_free(pgp_atlas *atlas)
{
    pw_alloc a;
    if (!atlas) return;
    a = pgp__alloc(&atlas->image.allocator);
    pw_free(&a, atlas->uvs);
    pgp_image_free(&atlas->image);
    memset(atlas, 0, sizeof *atlas);
}

/* ---- glTF -------------------------------------------------------------------------------- */

PGPDEF pgp_result pgp_write_gltf(const pgp_map *map, const pgp_atlas *atlas, const pgp_render_options *view,
                                 pgp_write_fn fn, void *ctx, pgp_error *err)
{
    const pgp__state *P = pgp__state_of(map);
    pgp_render_options ro;
    pw_gltf_part part;
    pw_gltf_scene scene;
    pw_camera cam;
    pw_image img;
    int *fstart = NULL, f;
    pw_err pe;
    pw_err_clear(&pe);
    memset(&part, 0, sizeof part);
    memset(&scene, 0, sizeof scene);
    if (!P || !atlas || !atlas->uvs || !fn) pw_fail(&pe, PW_ERR_INVALID, "glTF: no map, atlas or writer");
    else if (atlas->ntris != P->pp.m.nf)
        pw_fail(&pe, PW_ERR_INVALID, "glTF: the atlas has %d triangles; the map has %d", atlas->ntris, P->pp.m.nf);
    else if (pgp__check_image(&atlas->image, "atlas image", &pe) == PW_OK &&
             (!view || pgp__render_options(view, &ro, &pe) == PW_OK) &&
             (fstart = (int *)pw_alloc_array(&P->a, (size_t)P->pp.m.nf + 1, sizeof(int), "glTF faces", &pe)) != NULL) {
        for (f = 0; f <= P->pp.m.nf; f++) fstart[f] = 3 * f;
        img = pgp__pw_image(&atlas->image);
        part.name = "pgp";
        part.nv = P->pp.m.nv;
        part.pos = P->pos;
        part.nf = P->pp.m.nf;
        part.fstart = fstart;
        part.fv = P->pp.m.tri;
        part.corner_uv = atlas->uvs;
        part.texture = &img;
        part.repeat = atlas->repeat != 0;
        scene.parts = &part;
        scene.nparts = 1;
        scene.generator = "patchwork pgp.h " PGP_VERSION_STRING;
        if (view) {
            cam = pgp__camera(P, &ro);
            scene.camera = &cam;
            scene.aspect = (float)ro.width / (float)ro.height;
        }
        pw_gltf_write(&P->a, &scene, fn, ctx, &pe);
    }
    pw_free(P ? &P->a : NULL, fstart);
    return pgp__done(&pe, err);
}

#ifndef PW_NO_STDIO
typedef struct pgp__gltf_job {
    const pgp_map *map;
    const pgp_atlas *atlas;
    const pgp_render_options *view;
} pgp__gltf_job;

static int pgp__gltf_job_run(void *arg, pw_write_fn w, void *ctx, pw_err *e)
{
    const pgp__gltf_job *j = (const pgp__gltf_job *)arg;
    pgp_error pe;
    int r = (int)pgp_write_gltf(j->map, j->atlas, j->view, w, ctx, &pe);
    if (r) pw_fail(e, r, "%s", pe.message);
    return r;
}

PGPDEF pgp_result pgp_save_gltf(const char *path, const pgp_map *map, const pgp_atlas *atlas,
                                const pgp_render_options *view, pgp_error *err)
{
    pgp__gltf_job j;
    pw_err pe;
    pw_err_clear(&pe);
    j.map = map;
    j.atlas = atlas;
    j.view = view;
    if (!path) pw_fail(&pe, PW_ERR_INVALID, "pgp_save_gltf: NULL path");
    else pw_write_file(path, pgp__gltf_job_run, &j, &pe);
    return pgp__done(&pe, err);
}
#endif
