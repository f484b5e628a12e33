/* render.c: a software rendering of a mapped mesh (the thesis rendered
 * its results of ch. V in Maya), and the size tiles are drawn at. */
#include "core.c"

/* Vertical field of view of tiled_render's camera, degrees. */
#define TILED__FOVY 35.0f

#ifndef PW_NO_RENDER
/* What tiled_render draws: a mapped mesh and its fan triangulation, with
 * per-corner texture coordinates (uvs: 6 floats a triangle). */
typedef struct tiled__tris {
    const tiled_mesh *m;
    int *tris; /* 3*ntris vertex indices of m */
    float *uvs;
    int ntris;
} tiled__tris;

/* Fan-triangulates the mapped mesh tl->m into tl's triangles. */
static int tiled__triangles(const pw_alloc *a, tiled__tris *tl, pw_err *e)
{
    const tiled_mesh *m = tl->m;
    int f, k, t = 0, n = m->face_start[m->nfaces] - 2 * m->nfaces;
    int **tris = &tl->tris, *ntris = &tl->ntris;
    float **uvs = &tl->uvs;
    *tris = (int *)pw_alloc_array(a, (size_t)n * 3, sizeof(int), "triangles", e);
    *uvs = (float *)pw_alloc_array(a, (size_t)n * 6, sizeof(float), "triangle coordinates", e);
    if (!*tris || !*uvs) {
        pw_free(a, *tris);
        pw_free(a, *uvs);
        *tris = NULL;
        *uvs = NULL;
        return PW_ERR_NOMEM;
    }
    for (f = 0; f < m->nfaces; f++)
        for (k = m->face_start[f] + 1; k + 1 < m->face_start[f + 1]; k++, t++) {
            int c[3], j;
            c[0] = m->face_start[f];
            c[1] = k;
            c[2] = k + 1;
            for (j = 0; j < 3; j++) {
                (*tris)[3 * t + j] = m->face_verts[c[j]];
                (*uvs)[6 * t + 2 * j] = m->uvs[2 * c[j]];
                (*uvs)[6 * t + 2 * j + 1] = m->uvs[2 * c[j] + 1];
            }
        }
    *ntris = n;
    return PW_OK;
}

/* Draws the triangles lit, textured from the atlas with mip levels capped
 * where they would mix tiles, band by band (pw_render_frame), and resolves
 * the supersamples. */
static int tiled__draw(const pw_alloc *a, const tiled__tris *tl, const tiled_tileset *ts,
                       const tiled_render_options *ro, pw_image *out, pw_err *e)
{
    const tiled_mesh *m = tl->m;
    pw_image atlas = tiled__pw_image(&ts->atlas);
    pw_texture tex;
    pw_draw d;
    pw_camera cam;
    pw_frame f;
    pw_frame_draw1 one;
    pw_parallel par;
    float *normals;
    int r;
    if ((r = pw_texture_create(a, &tex, &atlas, ts->max_mip_level + 1, e)) != PW_OK) return r;
    cam = pw_camera_frame(m->positions, m->nverts, ro->view_dir, ro->up, TILED__FOVY,
                          (float)ro->width / (float)ro->height);
    memset(&d, 0, sizeof d);
    d.positions = m->positions;
    d.nv = m->nverts;
    d.tris = tl->tris;
    d.ntris = tl->ntris;
    d.uvs = tl->uvs;
    d.tex = &tex;
    d.filter = (int)ro->filter;
    d.wrap = PW_WRAP_CLAMP;
    d.lighting = PW_LIGHT_CAMERA;
    d.ambient = 0.3f;
    if (!(normals = pw_draw_normals(a, &d, e))) {
        pw_texture_free(a, &tex);
        return PW_ERR_NOMEM;
    }
    d.normals = normals; /* once, not per band, as the projection */
    one.d = &d;
    one.cam = &cam;
    par = tiled__parallel(ro);
    pw_frame_init(&f, ro->width, ro->height, ro->supersample, ro->background, &par);
    f.draw = pw_frame_draw1_fn;
    f.user = &one;
    if ((r = pw_draw_project(a, &f, &cam, &d, e)) == PW_OK) r = pw_render_frame(a, &f, out, e);
    pw_free(a, normals);
    pw_free(a, (void *)d.projected);
    pw_texture_free(a, &tex);
    return r;
}

#endif /* PW_NO_RENDER */

/* Render settings with the defaults filled in. */
static tiled_render_options tiled__render_options(const tiled_render_options *ro)
{
    tiled_render_options o;
    if (ro) o = *ro;
    else memset(&o, 0, sizeof o);
    pw_view_defaults(&o.width, &o.height, &o.supersample, o.view_dir, o.up, o.background);
    return o;
}

#ifndef PW_NO_RENDER
TILEDDEF tiled_result tiled_render(const tiled_mesh *mapped, const tiled_tileset *ts, const tiled_render_options *ro,
                                   tiled_image *out, tiled_error *err)
{
    tiled_render_options o = tiled__render_options(ro);
    pw_alloc a = tiled__alloc(ts ? &ts->atlas.allocator : NULL);
    pw_image pic;
    pw_err pe;
    tiled__tris tl;
    memset(&tl, 0, sizeof tl);
    tl.m = mapped;
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (!out || !ts || !mapped || !mapped->uvs)
        pw_fail(&pe, PW_ERR_INVALID,
                "tiled_render: needs a mapped mesh (with uvs), a tile set "
                "and an output image");
    else if (o.width < 1 || o.height < 1 || o.supersample < 1 || o.supersample > 8 || (int)o.filter < 0 ||
             (int)o.filter > 2 || o.threads < 0)
        pw_fail(&pe, PW_ERR_INVALID, "render options: size %dx%d, supersample %d, filter %d, threads %d", o.width,
                o.height, o.supersample, (int)o.filter, o.threads);
    else if (tiled__check_mesh(mapped, &pe) == PW_OK &&
             tiled__check_image(&ts->atlas, "tile set atlas", &pe) == PW_OK &&
             tiled__triangles(&a, &tl, &pe) == PW_OK) {
        if (tiled__draw(&a, &tl, ts, &o, &pic, &pe) == PW_OK) tiled__take_image(&pic, &a, out);
        pw_free(&a, tl.tris);
        pw_free(&a, tl.uvs);
    }
    return tiled__done(&pe, err);
}

#else
TILEDDEF tiled_result tiled_render(const tiled_mesh *mapped, const tiled_tileset *ts, const tiled_render_options *ro,
                                   tiled_image *out, tiled_error *err)
{
    (void)mapped;
    (void)ts;
    (void)ro;
    if (out) memset(out, 0, sizeof *out);
    return tiled__left_out("rendering", "PW_NO_RENDER", err);
}
#endif /* PW_NO_RENDER */

/* Areas of face f in world and texture space (fan of triangles). */
static void tiled__face_areas(const tiled_mesh *m, int f, double *world, double *tex)
{
    int c0 = m->face_start[f], k;
    const float *p0 = m->positions + 3 * m->face_verts[c0], *t0 = m->uvs + 2 * c0;
    *world = *tex = 0.0;
    for (k = c0 + 1; k + 1 < m->face_start[f + 1]; k++) {
        const float *p1 = m->positions + 3 * m->face_verts[k], *p2 = m->positions + 3 * m->face_verts[k + 1];
        const float *t1 = m->uvs + 2 * k, *t2 = m->uvs + 2 * (k + 1);
        double a[3], b[3], n[3];
        int j;
        for (j = 0; j < 3; j++) {
            a[j] = p1[j] - p0[j];
            b[j] = p2[j] - p0[j];
        }
        pw_cross3(a, b, n);
        *world += 0.5 * sqrt(pw_dot3(n, n));
        *tex += 0.5 * fabs((t1[0] - t0[0]) * (t2[1] - t0[1]) - (t2[0] - t0[0]) * (t1[1] - t0[1]));
    }
}

static int tiled__cmp_double(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return a < b ? -1 : a > b;
}

/* Median over faces of the world length of a tile side: a face covers
 * world/tex of world area per unit of texture area, and a tile side is
 * T/W of the texture's width. 0 if no face has texture area. */
static double tiled__tile_length(const pw_alloc *a, const tiled_mesh *m, const tiled_tileset *ts, pw_err *e)
{
    double *len = (double *)pw_alloc_array(a, (size_t)m->nfaces, sizeof(double), "tile lengths", e);
    double side = (double)ts->layout.tile_size / ts->atlas.width, mid;
    int f, n = 0;
    if (!len) return -1.0;
    for (f = 0; f < m->nfaces; f++) {
        double w, t;
        tiled__face_areas(m, f, &w, &t);
        if (t > 0.0 && pw_is_finite(w / t)) len[n++] = sqrt(w / t) * side;
    }
    qsort(len, (size_t)n, sizeof *len, tiled__cmp_double);
    mid = n ? len[n / 2] : 0.0;
    pw_free(a, len);
    return mid;
}

TILEDDEF tiled_result tiled_drawn_tile_size(const tiled_mesh *mapped, const tiled_tileset *ts,
                                            const tiled_render_options *ro, float *pixels, tiled_error *err)
{
    tiled_render_options o = tiled__render_options(ro);
    pw_alloc a = tiled__alloc(ts ? &ts->atlas.allocator : NULL);
    pw_err pe;
    pw_err_clear(&pe);
    if (pixels) *pixels = 0.0f;
    if (!pixels || !ts || !mapped || !mapped->uvs || ts->atlas.width < 1 || o.width < 1 || o.height < 1)
        pw_fail(&pe, PW_ERR_INVALID,
                "tiled_drawn_tile_size: needs a mapped mesh (with uvs), its "
                "tile set, an output and a valid render size");
    else if (tiled__check_mesh(mapped, &pe) == PW_OK) {
        double len = tiled__tile_length(&a, mapped, ts, &pe), d[3], dist;
        pw_camera cam = pw_camera_frame(mapped->positions, mapped->nverts, o.view_dir, o.up, TILED__FOVY,
                                        (float)o.width / (float)o.height);
        int k;
        for (k = 0; k < 3; k++) d[k] = cam.eye[k] - cam.target[k];
        dist = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        /* pixels per world unit at the framed mesh's centre */
        if (len >= 0.0 && dist > 0.0) *pixels = (float)(len * o.height / (2.0 * dist * pw__tan_deg(0.5 * TILED__FOVY)));
    }
    return tiled__done(&pe, err);
}
