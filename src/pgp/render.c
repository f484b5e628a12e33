/* render.c: §3 rendering, and a cleaner treatment of the vortices.
 *
 * PGP_FIX_CLEAN (the default, beyond the paper): every triangle takes one
 * lookup. A triangle around which s (or t) winds (a vortex, pgp_map_vortices)
 * cannot take a linear (s, t): its edges are given the differences its
 * neighbours use (the integer nearest the field's alpha, Eq. 4), and its
 * interior the "stripe patterns" interpolation of Knöppel, Crane, Pinkall
 * and Schröder 2015, generalised to s and t: the zero of the linearly
 * interpolated residual e^{2 pi i (s - L)} (L the field's linear function)
 * is where the pattern ends or forks, and the residual is carried along
 * rays from that zero. The coordinates then match the neighbours' along
 * every edge exactly, modulo integers, and wind around the zero, so the
 * extra stripe (or row of bricks) ends there without ghosting or a seam.
 * Every other triangle is regular: its Eq. (4) coordinates agree with its
 * neighbours' (an edge mismatch needs a winding on one side).
 *
 * PGP_FIX_PAPER (§3): a triangle with a singular corner takes three lookups,
 * one from each corner's point of view, blended by the barycentric
 * coordinates: "This makes the texture lookup use the optimal coordinates
 * at each vertex, and linearly interpolates the result between them."
 * Where those points of view disagree the blend shows ghosts. */
#include "solve.c"

#define PGP__FIXDATA 24 /* floats of fix data per triangle */

/* Everything the shader needs. fix: per triangle that takes the special
 * treatment, PGP__FIXDATA floats: PAPER (and ALL) 3 points of view x 3
 * corners x (s, t); CLEAN pgp__clean_data's layout. */
typedef struct pgp__shading {
    const pgp__state *P;
    const pw_tile3 *tile;
    const float *fix;
    const unsigned char *fixed; /* nf: 1 where the special treatment is used */
    int mode, show;
} pgp__shading;

/* Corner b of triangle f seen from corner a (§3): s'_{a,a} = s_a^T and
 * s'_{a,b} = s'_{a,a} + alpha_ab, for s and t, written to out[0..1]. */
static void pgp__view(const pgp__state *P, int f, int a, int b, float *out)
{
    int k;
    for (k = 0; k < 2; k++) {
        double al = 0.0;
        if (b == (a + 1) % 3) al = pw_periodic_alpha(&P->pp, 3 * f + a, k);
        else if (b != a) al = -pw_periodic_alpha(&P->pp, 3 * f + b, k); /* edge b -> a */
        out[k] = (float)(P->pp.stm[9 * f + 3 * a + k] + al);
    }
}

/* The three points of view of triangle f: a singular corner sees its
 * neighbours through the field; a regular corner agrees with the
 * triangle's own coordinates. */
static void pgp__views(const pgp__state *P, int f, int all, float *out)
{
    int a, b;
    for (a = 0; a < 3; a++)
        for (b = 0; b < 3; b++) {
            float *o = out + 6 * a + 2 * b;
            if (all || P->vsing[P->pp.m.tri[3 * f + a]]) pgp__view(P, f, a, b, o);
            else {
                o[0] = P->pp.stm[9 * f + 3 * b];
                o[1] = P->pp.stm[9 * f + 3 * b + 1];
            }
        }
}

/* ---- the clean fix of a vortex triangle (beyond §3) ------------------------------------ */

/* Difference a - b brought into [-1/2, 1/2): coordinates wind by integers. */
static double pgp__wrap(double d) { return d - floor(d + 0.5); }

/* (s, t) at barycentric (b1, b2) of a vortex triangle, and their screen
 * derivatives (ds/dx, ds/dy, dt/dx, dt/dy) by differences over a quarter
 * pixel (the function is not linear), for the mip level. */
static void pgp__clean_st(const float *o, float b1, float b2, const float db[4], double *st, double *d)
{
    double b[3], bx[3], by[3];
    const double h = 0.25;
    int k;
    b[0] = 1.0 - b1 - b2;
    b[1] = b1;
    b[2] = b2;
    bx[1] = b1 + h * db[0];
    bx[2] = b2 + h * db[2];
    bx[0] = 1.0 - bx[1] - bx[2];
    by[1] = b1 + h * db[1];
    by[2] = b2 + h * db[3];
    by[0] = 1.0 - by[1] - by[2];
    for (k = 0; k < 2; k++) {
        st[k] = pw_periodic_clean_eval(o + 12 * k, b);
        d[2 * k] = pgp__wrap(pw_periodic_clean_eval(o + 12 * k, bx) - st[k]) / h;
        d[2 * k + 1] = pgp__wrap(pw_periodic_clean_eval(o + 12 * k, by) - st[k]) / h;
    }
}

/* ---- lookups -------------------------------------------------------------------------- */

/* One lookup at (s, t, m), the mip level from the screen derivatives d
 * (ds/dx, ds/dy, dt/dx, dt/dy) in periods. */
static void pgp__sample(const pgp__shading *S, double s, double t, float m, const double *d, float *rgba)
{
    double W = (double)S->tile->w, H = (double)S->tile->h;
    double rx = d[0] * d[0] * W * W + d[2] * d[2] * H * H, ry = d[1] * d[1] * W * W + d[3] * d[3] * H * H;
    pw_tile3_sample(S->tile, (float)s, (float)t, m, 0.5f * pw__log2f((float)(rx > ry ? rx : ry)), rgba);
}

/* (s, t) at barycentric b of corner coordinates c (3 x (s, t) with stride
 * `st`) and their screen derivatives. */
static void pgp__linear_st(const float *c, int st, const float *b, const float *db, double *out, double *d)
{
    int k;
    for (k = 0; k < 2; k++) {
        double d1 = (double)c[st + k] - c[k], d2 = (double)c[2 * st + k] - c[k];
        out[k] = b[0] * c[k] + b[1] * c[st + k] + b[2] * c[2 * st + k];
        d[2 * k] = d1 * db[0] + d2 * db[2];
        d[2 * k + 1] = d1 * db[1] + d2 * db[3];
    }
}

/* Whether the §3 blend at b mixes points of view whose (s, t) differ by
 * more than a tenth of a period (a ghost). */
static int pgp__ghost(const float *views, const float *b)
{
    static const float db[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    double st[3][2], d[4];
    int a, c, k;
    for (a = 0; a < 3; a++) pgp__linear_st(views + 6 * a, 2, b, db, st[a], d);
    for (a = 0; a < 3; a++)
        for (c = a + 1; c < 3; c++)
            for (k = 0; k < 2; k++)
                if (b[a] > 0.0f && b[c] > 0.0f && fabs(pgp__wrap(st[a][k] - st[c][k])) > 0.1) return 1;
    return 0;
}

/* The colour of triangle f at barycentric b: one lookup, or §3's three. */
static void pgp__color(const pgp__shading *S, int f, const float *b, const float *db, float m, float *rgba)
{
    const float *fx = S->fix + PGP__FIXDATA * (size_t)f;
    double st[2], d[4];
    float col[4];
    int a, k;
    if (!S->fixed[f] || S->mode == PGP_FIX_CLEAN) {
        if (S->fixed[f]) pgp__clean_st(fx, b[1], b[2], db, st, d);
        else pgp__linear_st(S->P->pp.stm + 9 * f, 3, b, db, st, d);
        pgp__sample(S, st[0], st[1], m, d, rgba);
        return;
    }
    memset(rgba, 0, 4 * sizeof(float));
    for (a = 0; a < 3; a++) {
        pgp__linear_st(fx + 6 * a, 2, b, db, st, d);
        pgp__sample(S, st[0], st[1], m, d, col);
        for (k = 0; k < 4; k++) rgba[k] += b[a] * col[k];
    }
}

static void pgp__shade(void *user, int f, float b1, float b2, const float db[4], float rgba[4])
{
    const pgp__shading *S = (const pgp__shading *)user;
    const float *stm = S->P->pp.stm + 9 * f;
    float b[3], m;
    int k;
    b[0] = 1.0f - b1 - b2;
    b[1] = b1;
    b[2] = b2;
    m = b[0] * stm[2] + b[1] * stm[5] + b[2] * stm[8];
    rgba[3] = 1.0f;
    if (S->show == PGP_SHOW_MATERIAL) {
        rgba[0] = rgba[1] = rgba[2] = m;
        return;
    }
    if (S->show == PGP_SHOW_GHOSTS) { /* red where the blend mixes disagreeing lookups */
        int g = S->fixed[f] && S->mode != PGP_FIX_CLEAN && pgp__ghost(S->fix + PGP__FIXDATA * (size_t)f, b);
        rgba[0] = 1.0f;
        rgba[1] = rgba[2] = g ? 0.0f : 1.0f;
        return;
    }
    pgp__color(S, f, b, db, m, rgba);
    if (rgba[3] > 0.0f) /* premultiplied -> straight */
        for (k = 0; k < 3; k++) rgba[k] /= rgba[3];
    if (S->show == PGP_SHOW_SPECIAL && S->fixed[f]) {
        rgba[0] = 0.5f + 0.5f * rgba[0];
        rgba[1] *= 0.5f;
        rgba[2] *= 0.5f;
    }
}

/* The tile as a pw_tile3 (layers of mip-mapped textures). */
static int pgp__tile3(const pw_alloc *a, const pgp_tile *t, pw_tile3 *out, pw_err *e)
{
    pw_volume v;
    if (!t || !t->pixels || t->width < 1 || t->height < 1 || t->layers < 1 || t->channels < 1 || t->channels > 4)
        return pw_fail(e, PW_ERR_INVALID, "tile: empty, or bad size or channel count");
    v.c = t->channels;
    v.x = t->width;
    v.y = t->height;
    v.z = t->layers;
    v.px = t->pixels;
    return pw_tile3_create(a, out, &v, 0, e);
}

/* The camera of render options o (defaults filled in): the mesh framed,
 * or with zoom > 1 a close-up from the same direction and distance,
 * looking at center. */
static pw_camera pgp__camera(const pgp__state *P, const pgp_render_options *o)
{
    pw_camera cam = pw_camera_frame(P->pos, P->pp.m.nv, o->view_dir, o->up, 35.0f, (float)o->width / (float)o->height);
    int k;
    if (o->zoom > 1.0f)
        for (cam.fovy_deg /= o->zoom, k = 0; k < 3; k++) {
            cam.eye[k] += o->center[k] - cam.target[k];
            cam.target[k] = o->center[k];
        }
    return cam;
}

#ifndef PW_NO_RENDER
static int pgp__draw(const pgp__state *P, pgp__shading *S, const pgp_render_options *o, pw_image *pic, pw_err *e)
{
    pw_camera cam = pgp__camera(P, o);
    pw_draw d;
    pw_frame f;
    pw_frame_draw1 one;
    pw_parallel par;
    float *normals;
    int r;
    memset(&d, 0, sizeof d);
    d.positions = P->pos;
    d.nv = P->pp.m.nv;
    d.tris = P->pp.m.tri;
    d.ntris = P->pp.m.nf;
    d.lighting = PW_LIGHT_CAMERA;
    d.ambient = 0.3f;
    d.shader = pgp__shade;
    d.shader_user = S;
    if (!(normals = pw_draw_normals(&P->a, &d, e))) return PW_ERR_NOMEM;
    d.normals = normals; /* once, not per band, as the projection */
    one.d = &d;
    one.cam = &cam;
    par = pgp__parallel(o);
    pw_frame_init(&f, o->width, o->height, o->supersample, o->background, &par);
    f.draw = pw_frame_draw1_fn;
    f.user = &one;
    if ((r = pw_draw_project(&P->a, &f, &cam, &d, e)) == PW_OK) r = pw_render_frame(&P->a, &f, pic, e);
    pw_free(&P->a, normals);
    pw_free(&P->a, (void *)d.projected);
    return r;
}

#endif /* PW_NO_RENDER */

/* Whether triangle f takes the special treatment of fix mode `mode`: a
 * vortex (CLEAN), a singular corner (PAPER, §3), every triangle (ALL). */
static int pgp__special(const pgp__state *P, int mode, int f)
{
    if (mode == PGP_FIX_CLEAN) return pw_periodic_winding(&P->pp, f, 0) != 0 || pw_periodic_winding(&P->pp, f, 1) != 0;
    if (mode == PGP_FIX_PAPER) return P->fsing[f];
    return mode == PGP_FIX_ALL;
}

PGPDEF int pgp_map_special(const pgp_map *map, pgp_fix fix, unsigned char *flags)
{
    const pgp__state *P = pgp__state_of(map);
    int f, n = 0, s;
    for (f = 0; P && f < P->pp.m.nf; f++) {
        n += s = pgp__special(P, fix, f);
        if (flags) flags[f] = (unsigned char)s;
    }
    return n;
}

/* The fix data of every triangle that takes the special treatment. */
static void pgp__fix_data(const pgp__state *P, int mode, unsigned char *fixed, float *data)
{
    int f, k;
    for (f = 0; f < P->pp.m.nf; f++) {
        float *o = data + PGP__FIXDATA * (size_t)f;
        if (!(fixed[f] = (unsigned char)pgp__special(P, mode, f))) continue;
        if (mode == PGP_FIX_CLEAN)
            for (k = 0; k < 2; k++) pw_periodic_clean_coord(&P->pp, f, k, o + 12 * k);
        else pgp__views(P, f, mode == PGP_FIX_ALL, o);
    }
}

/* Render options with the defaults filled in, checked. */
static int pgp__render_options(const pgp_render_options *ro, pgp_render_options *o, pw_err *e)
{
    if (ro) *o = *ro;
    else memset(o, 0, sizeof *o);
    pw_view_defaults(&o->width, &o->height, &o->supersample, o->view_dir, o->up, o->background);
    if (o->width < 1 || o->height < 1 || o->supersample < 1 || o->supersample > 8 || o->threads < 0 || o->fix < 0 ||
        o->fix > PGP_FIX_PAPER || o->show < 0 || o->show > PGP_SHOW_GHOSTS || !(o->zoom <= 1e4f) ||
        !pw_is_finite(o->center[0]) || !pw_is_finite(o->center[1]) || !pw_is_finite(o->center[2]))
        return pw_fail(e, PW_ERR_INVALID,
                       "render options: size %dx%d, supersample %d, threads %d, fix %d, show %d, zoom %g", o->width,
                       o->height, o->supersample, o->threads, o->fix, o->show, (double)o->zoom);
    return PW_OK;
}

/* The shading of the tile with fix mode `fix` and what `show` asks for:
 * the tile as a pw_tile3 and the fix data (free with pgp__shading_free). */
static int pgp__shading_init(const pgp__state *P, const pgp_tile *tile, pgp_fix fix, pgp_show show, pgp__shading *S,
                             pw_err *e)
{
    pw_tile3 *t3 = (pw_tile3 *)pw_calloc_array(&P->a, 1, sizeof *t3, "tile", e);
    float *data = NULL;
    unsigned char *fixed = NULL;
    memset(S, 0, sizeof *S);
    if (!t3) return PW_ERR_NOMEM;
    S->tile = t3;
    if (pgp__tile3(&P->a, tile, t3, e) != PW_OK) return e->code;
    data = (float *)pw_alloc_array(&P->a, (size_t)P->pp.m.nf * PGP__FIXDATA, sizeof(float), "fix", e);
    fixed = (unsigned char *)pw_alloc_array(&P->a, (size_t)P->pp.m.nf, 1, "fix", e);
    S->fix = data;
    S->fixed = fixed;
    if (!data || !fixed) return PW_ERR_NOMEM;
    pgp__fix_data(P, fix, fixed, data);
    S->P = P;
    S->mode = fix;
    S->show = show;
    return PW_OK;
}

static void pgp__shading_free(const pgp__state *P, pgp__shading *S)
{
    if (S->tile) pw_tile3_free(&P->a, (pw_tile3 *)S->tile);
    pw_free(&P->a, (void *)S->tile);
    pw_free(&P->a, (void *)S->fix);
    pw_free(&P->a, (void *)S->fixed);
    memset(S, 0, sizeof *S);
}

#ifndef PW_NO_RENDER
PGPDEF pgp_result pgp_render(const pgp_map *map, const pgp_tile *tile, const pgp_render_options *ro, pgp_image *out,
                             pgp_error *err)
{
    const pgp__state *P = pgp__state_of(map);
    pgp_render_options o;
    pgp__shading S;
    pw_image pic;
    pw_err pe;
    pw_err_clear(&pe);
    memset(&S, 0, sizeof S);
    if (out) memset(out, 0, sizeof *out);
    if (!out || !P) pw_fail(&pe, PW_ERR_INVALID, "pgp_render: NULL map or output");
    else if (pgp__render_options(ro, &o, &pe) == PW_OK && pgp__shading_init(P, tile, o.fix, o.show, &S, &pe) == PW_OK &&
             pgp__draw(P, &S, &o, &pic, &pe) == PW_OK)
        pgp__take_image(&pic, &P->a, out);
    if (P) pgp__shading_free(P, &S);
    return pgp__done(&pe, err);
}
#else
PGPDEF pgp_result pgp_render(const pgp_map *map, const pgp_tile *tile, const pgp_render_options *ro, pgp_image *out,
                             pgp_error *err)
{
    (void)map;
    (void)tile;
    (void)ro;
    if (out) memset(out, 0, sizeof *out);
    return pgp__left_out("rendering", "PW_NO_RENDER", err);
}
#endif /* PW_NO_RENDER */
