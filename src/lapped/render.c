/* render.c: runtime pasting (§4): the mesh drawn once per paste, in paste
 * order, each paste's triangles textured with its patch and composited over
 * what is there. */
#include "grow.c"

#ifndef PW_NO_RENDER
/* Checks that a lapped texture belongs to this mesh and these patches. */
static int lapped__check_texture(const pw_trimesh *m, const lapped_texture *t, const lapped_source *src, pw_err *e)
{
    const lapped_image *patches = src ? src->patches : NULL, *values = src ? src->values : NULL;
    int k, p, i;
    if (!t || !patches) return pw_fail(e, PW_ERR_INVALID, "missing lapped texture or patches");
    if (src->npatches != t->npatches)
        return pw_fail(e, PW_ERR_INVALID, "the lapped texture was made with %d patches, the source has %d", t->npatches,
                       src->npatches);
    if (t->ntris && t->ntris != m->nf) /* 0: read from a file, triangle indices checked below */
        return pw_fail(e, PW_ERR_INVALID, "the lapped texture was made for %d triangles, the mesh has %d", t->ntris,
                       m->nf);
    for (k = 0; k < t->npatches; k++) {
        const lapped_image *v = values ? &values[k] : &patches[k];
        if (patches[k].width != t->patch_size[2 * k] || patches[k].height != t->patch_size[2 * k + 1] ||
            patches[k].channels != 4 || !patches[k].pixels)
            return pw_fail(e, PW_ERR_INVALID,
                           "patch %d is not the %dx%d RGBA image the pastes were made "
                           "with",
                           k, t->patch_size[2 * k], t->patch_size[2 * k + 1]);
        if (v->width != patches[k].width || v->height != patches[k].height || !v->pixels)
            return pw_fail(e, PW_ERR_INVALID, "value image %d does not match patch %d's size", k, k);
    }
    for (p = 0; p < t->npastes; p++) {
        if (t->pastes[p].patch < 0 || t->pastes[p].patch >= t->npatches)
            return pw_fail(e, PW_ERR_INVALID, "paste %d uses patch %d of %d", p, t->pastes[p].patch, t->npatches);
        for (i = 0; i < t->pastes[p].nfaces; i++)
            if (t->pastes[p].faces[i] < 0 || t->pastes[p].faces[i] >= m->nf)
                return pw_fail(e, PW_ERR_INVALID, "paste %d refers to triangle %d of %d", p, t->pastes[p].faces[i],
                               m->nf);
    }
    return PW_OK;
}

/* A patch texture for compositing: colour from `value` (any channels),
 * alpha from the patch, and explicitly built mip levels whose border stays
 * transparent (§4: "the texture patch must have a border of transparent
 * pixels at all mipmap levels finer than 2x2"), sampled with clamping. */
static int lapped__patch_texture(const pw_alloc *a, const lapped_image *patch, const lapped_image *value,
                                 pw_texture *tex, pw_err *e)
{
    pw_image rgba, src = lapped__pw_image(value), alpha = lapped__pw_image(patch);
    size_t i, n = (size_t)patch->width * patch->height;
    int r;
    if ((r = pw_image_convert(a, &src, 4, &rgba, e)) != PW_OK) return r;
    for (i = 0; i < n; i++) rgba.px[4 * i + 3] = alpha.px[4 * i + 3];
    r = pw_texture_create(a, tex, &rgba, 0, e);
    if (r == PW_OK) pw_texture_clear_border(tex, 2);
    pw_image_free(a, &rgba);
    return r;
}

/* The paste's triangles as a draw: indices and per-corner coordinates. */
static void lapped__paste_draw(const pw_trimesh *m, const lapped_paste *p, int *tris, pw_draw *d)
{
    int i, k;
    for (i = 0; i < p->nfaces; i++)
        for (k = 0; k < 3; k++) tris[3 * i + k] = m->tri[3 * p->faces[i] + k];
    d->tris = tris;
    d->ntris = p->nfaces;
    d->uvs = p->uvs;
}

/* What every band of a lapped rendering draws (read only: bands may run
 * on several threads). */
typedef struct lapped__picture {
    const pw_alloc *a;
    const pw_trimesh *m;
    const lapped_texture *t;
    const pw_texture *tex;
    const float *normals;    /* smooth vertex normals of the whole mesh */
    const double *rows;      /* per paste: the sample rows its corners reach (pw__draw_rows) */
    const double *projected; /* the mesh's vertices, projected once for all the bands */
    pw_camera cam;
    int filter;
} lapped__picture;

/* One band: the base pass, the bare mesh, mid-grey, writing depth; then
 * every paste over it with depth test "less or equal" and no depth write,
 * all with the vertices projected once for the frame. */
static int lapped__draw_band(void *user, pw_fb *fb, pw_err *e)
{
    const lapped__picture *F = (const lapped__picture *)user;
    const pw_trimesh *m = F->m;
    int *tris = (int *)pw_alloc_array(F->a, (size_t)m->nf * 3, sizeof(int), "paste triangles", e);
    pw_draw d;
    int p, r;
    if (!tris) return PW_ERR_NOMEM;
    memset(&d, 0, sizeof d);
    d.positions = m->pos;
    d.nv = m->nv;
    d.tris = m->tri;
    d.ntris = m->nf;
    d.normals = F->normals;
    d.projected = F->projected;
    d.color[0] = d.color[1] = d.color[2] = 0.5f;
    d.color[3] = 1.0f;
    d.lighting = PW_LIGHT_CAMERA;
    d.ambient = 0.3f;
    r = pw_render_draw(fb, &F->cam, &d, e);
    d.color[0] = d.color[1] = d.color[2] = d.color[3] = 1.0f;
    d.filter = F->filter;
    d.wrap = PW_WRAP_CLAMP;
    d.blend = PW_BLEND_OVER;
    d.depth_test = PW_DEPTH_LEQUAL;
    d.no_depth_write = 1;
    for (p = 0; p < F->t->npastes && r == PW_OK; p++) {
        /* pastes wholly above or below the band draw nothing in it */
        if (F->t->pastes[p].nfaces == 0 || F->rows[2 * p + 1] < fb->y0 || F->rows[2 * p] > fb->y0 + fb->bh) continue;
        lapped__paste_draw(m, &F->t->pastes[p], tris, &d);
        d.tex = &F->tex[F->t->pastes[p].patch];
        r = pw_render_draw(fb, &F->cam, &d, e);
    }
    pw_free(F->a, tris);
    return r;
}

/* The sample rows each paste reaches in the frame (rows[2p], rows[2p + 1]),
 * from its triangles' corners as the draws project them (pw__draw_rows),
 * so that the bands skip the pastes they do not meet. */
static int lapped__paste_rows(const lapped__picture *F, const lapped_render_options *ro, double *rows, pw_err *e)
{
    const pw_trimesh *m = F->m;
    int *tris = (int *)pw_alloc_array(F->a, (size_t)m->nf * 3, sizeof(int), "paste triangles", e), p;
    pw__view v;
    pw_draw d;
    if (!tris) return PW_ERR_NOMEM;
    memset(&d, 0, sizeof d);
    d.positions = m->pos;
    d.nv = m->nv;
    for (p = 0; p < F->t->npastes; p++) {
        rows[2 * p] = -DBL_MAX;
        rows[2 * p + 1] = DBL_MAX;
    }
    if (pw__view_init(&v, &F->cam, ro->width * ro->supersample, ro->height * ro->supersample, NULL) == PW_OK)
        for (p = 0; p < F->t->npastes; p++) {
            lapped__paste_draw(m, &F->t->pastes[p], tris, &d);
            pw__draw_rows(&v, &d, F->projected, rows + 2 * p, rows + 2 * p + 1);
        }
    pw_free(F->a, tris);
    return PW_OK;
}

/* The frame, band by band (pw_render_frame): the normals once, from the
 * whole mesh (every paste is lit as the surface), and the rows each paste
 * reaches, then the bands. F comes with its allocator, mesh, texture and
 * patch textures; this sets the rest. */
static int lapped__draw_pastes(lapped__picture *F, const lapped_render_options *ro, pw_image *pic, pw_err *e)
{
    const pw_alloc *a = F->a;
    const pw_trimesh *m = F->m;
    pw_frame f;
    pw_parallel par;
    pw_draw d;
    float *normals = (float *)pw_alloc_array(a, (size_t)m->nv * 3, sizeof(float), "normals", e);
    double *rows =
        normals ? (double *)pw_alloc_array(a, (size_t)F->t->npastes * 2 + 2, sizeof(double), "paste rows", e) : NULL;
    int r;
    F->cam = pw_camera_frame(m->pos, m->nv, ro->view_dir, ro->up, 35.0f, (float)ro->width / (float)ro->height);
    memset(&d, 0, sizeof d);
    d.positions = m->pos;
    d.nv = m->nv;
    d.tris = m->tri;
    d.ntris = m->nf;
    par = lapped__parallel(ro);
    pw_frame_init(&f, ro->width, ro->height, ro->supersample, ro->background, &par);
    r = rows ? pw_draw_project(a, &f, &F->cam, &d, e) : PW_ERR_NOMEM;
    F->projected = d.projected;
    if (r == PW_OK) r = lapped__paste_rows(F, ro, rows, e);
    if (r != PW_OK) {
        pw_free(a, normals);
        pw_free(a, rows);
        pw_free(a, (void *)d.projected);
        return r;
    }
    pw__smooth_normals(&d, normals);
    F->normals = normals;
    F->rows = rows;
    F->filter = (int)ro->filter;
    f.draw = lapped__draw_band;
    f.user = F;
    r = pw_render_frame(a, &f, pic, e);
    pw_free(a, normals);
    pw_free(a, rows);
    pw_free(a, (void *)F->projected);
    return r;
}

LAPPEDDEF lapped_result lapped_render(const lapped_mesh *mesh, const lapped_texture *t, const lapped_source *src,
                                      const lapped_render_options *ro, lapped_image *out, lapped_error *err)
{
    lapped_render_options o;
    pw_alloc a = lapped__alloc(t ? &t->allocator : NULL);
    lapped__picture F;
    pw_trimesh m;
    pw_texture *tex = NULL;
    pw_image pic;
    pw_err pe;
    int k, r;
    if (ro) o = *ro;
    else memset(&o, 0, sizeof o);
    pw_view_defaults(&o.width, &o.height, &o.supersample, o.view_dir, o.up, o.background);
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (!out) pw_fail(&pe, PW_ERR_INVALID, "lapped_render: NULL output");
    else if (o.width < 1 || o.height < 1 || o.supersample < 1 || o.supersample > 8 || (int)o.filter < 0 ||
             (int)o.filter > 2 || o.threads < 0)
        pw_fail(&pe, PW_ERR_INVALID, "render options: size %dx%d, supersample %d, filter %d, threads %d", o.width,
                o.height, o.supersample, (int)o.filter, o.threads);
    else if (lapped__mesh_init_as(&a, mesh, 1, &m, &pe) == PW_OK) { /* triangles only: no adjacency */
        r = lapped__check_texture(&m, t, src, &pe);
        if (r == PW_OK && !(tex = (pw_texture *)pw_calloc_array(&a, (size_t)t->npatches, sizeof *tex, "textures", &pe)))
            r = PW_ERR_NOMEM;
        for (k = 0; r == PW_OK && k < t->npatches; k++)
            r = lapped__patch_texture(&a, &src->patches[k], src->values ? &src->values[k] : &src->patches[k], &tex[k],
                                      &pe);
        F.a = &a;
        F.m = &m;
        F.t = t;
        F.tex = tex;
        if (r == PW_OK && lapped__draw_pastes(&F, &o, &pic, &pe) == PW_OK) lapped__take_image(&pic, &a, out);
        for (k = 0; tex && k < t->npatches; k++) pw_texture_free(&a, &tex[k]);
        pw_free(&a, tex);
        pw_trimesh_free(&a, &m);
    }
    return lapped__done(&pe, err);
}

#else
LAPPEDDEF lapped_result lapped_render(const lapped_mesh *mesh, const lapped_texture *t, const lapped_source *src,
                                      const lapped_render_options *ro, lapped_image *out, lapped_error *err)
{
    (void)mesh;
    (void)t;
    (void)src;
    (void)ro;
    if (out) memset(out, 0, sizeof *out);
    return lapped__left_out("rendering", "PW_NO_RENDER", err);
}
#endif /* PW_NO_RENDER */
