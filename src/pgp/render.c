/* render.c: §3 rendering. Regular triangles take one lookup at their
 * interpolated (s, t, m); a triangle with a singular corner takes three,
 * one from each corner's point of view, blended by the barycentric
 * coordinates: "This makes the texture lookup use the optimal coordinates
 * at each vertex, and linearly interpolates the result between them." */
#include "solve.c"

/* Everything the shader needs. views: per triangle that uses the fix,
 * 3 points of view x 3 corners x (s, t); NULL entries use the regular
 * coordinates. */
typedef struct pgp__shading {
    const pgp_map *P;
    const pw_tile3 *tile;
    const float *views; /* nf*18 */
    const unsigned char *fixed; /* nf: 1 where the three lookups are used */
    int show;
} pgp__shading;

/* Corner b of triangle f seen from corner a (§3): s'_{a,a} = s_a^T and
 * s'_{a,b} = s'_{a,a} + alpha_ab, for s and t, written to out[0..1]. */
static void pgp__view(const pgp_map *P, int f, int a, int b, float *out)
{
    int k;
    for (k = 0; k < 2; k++) {
        double al = 0.0;
        if (b == (a + 1) % 3) al = pgp__alpha(P, 3 * f + a, k);
        else if (b != a) al = -pgp__alpha(P, 3 * f + b, k); /* edge b -> a */
        out[k] = (float)(P->stm[9 * f + 3 * a + k] + al);
    }
}

/* The three points of view of triangle f: a singular corner sees its
 * neighbours through the field; a regular corner agrees with the
 * triangle's own coordinates. */
static void pgp__views(const pgp_map *P, int f, int all, float *out)
{
    int a, b;
    for (a = 0; a < 3; a++)
        for (b = 0; b < 3; b++) {
            float *o = out + 6 * a + 2 * b;
            if (all || P->vsing[P->m.tri[3 * f + a]]) pgp__view(P, f, a, b, o);
            else o[0] = P->stm[9 * f + 3 * b], o[1] = P->stm[9 * f + 3 * b + 1];
        }
}

/* One lookup at barycentric b of corner coordinates c (3 x (s, t) with
 * stride `st`), material m; the mip level from the pixel footprint. */
static void pgp__lookup(const pgp__shading *S, const float *c, int st, const float *b, const float *db, float m,
                        float *rgba)
{
    float s = b[0] * c[0] + b[1] * c[st] + b[2] * c[2 * st], t = b[0] * c[1] + b[1] * c[st + 1] + b[2] * c[2 * st + 1];
    float W = (float)S->tile->w, H = (float)S->tile->h;
    float sx = ((c[st] - c[0]) * db[0] + (c[2 * st] - c[0]) * db[2]) * W;
    float sy = ((c[st] - c[0]) * db[1] + (c[2 * st] - c[0]) * db[3]) * W;
    float tx = ((c[st + 1] - c[1]) * db[0] + (c[2 * st + 1] - c[1]) * db[2]) * H;
    float ty = ((c[st + 1] - c[1]) * db[1] + (c[2 * st + 1] - c[1]) * db[3]) * H;
    float rx = sx * sx + tx * tx, ry = sy * sy + ty * ty;
    pw_tile3_sample(S->tile, s, t, m, 0.5f * pw__log2f(rx > ry ? rx : ry), rgba);
}

static void pgp__shade(void *user, int f, float b1, float b2, const float db[4], float rgba[4])
{
    const pgp__shading *S = (const pgp__shading *)user;
    const float *stm = S->P->stm + 9 * f;
    float b[3], m, col[4];
    int a, k;
    b[0] = 1.0f - b1 - b2, b[1] = b1, b[2] = b2;
    m = b[0] * stm[2] + b[1] * stm[5] + b[2] * stm[8];
    if (S->show == 1) {
        rgba[0] = rgba[1] = rgba[2] = m;
        rgba[3] = 1.0f;
        return;
    }
    if (!S->fixed[f]) pgp__lookup(S, stm, 3, b, db, m, rgba);
    else {
        memset(rgba, 0, 4 * sizeof(float));
        for (a = 0; a < 3; a++) {
            pgp__lookup(S, S->views + 18 * (size_t)f + 6 * a, 2, b, db, m, col);
            for (k = 0; k < 4; k++) rgba[k] += b[a] * col[k];
        }
    }
    if (rgba[3] > 0.0f) /* premultiplied -> straight */
        for (k = 0; k < 3; k++) rgba[k] /= rgba[3];
    if (S->show == 2 && S->P->fsing[f]) rgba[0] = 0.5f + 0.5f * rgba[0], rgba[1] *= 0.5f, rgba[2] *= 0.5f;
}

/* The tile as a pw_tile3 (layers of mip-mapped textures). */
static int pgp__tile3(const pw_alloc *a, const pgp_tile *t, pw_tile3 *out, pw_err *e)
{
    pw_volume v;
    if (!t || !t->pixels || t->width < 1 || t->height < 1 || t->layers < 1 || t->channels < 1 || t->channels > 4)
        return pw_fail(e, PW_ERR_INVALID, "tile: empty, or bad size or channel count");
    v.c = t->channels, v.x = t->width, v.y = t->height, v.z = t->layers, v.px = t->pixels;
    return pw_tile3_create(a, out, &v, 0, e);
}

static int pgp__draw(const pgp_map *P, pgp__shading *S, const pgp_render_options *o, pw_image *pic, pw_err *e)
{
    pw_camera cam = pw_camera_frame(P->pos, P->m.nv, o->view_dir, o->up, 35.0f, (float)o->width / (float)o->height);
    float bg[4];
    pw_draw d;
    pw_fb fb;
    int r;
    memcpy(bg, o->background, sizeof o->background);
    bg[3] = 1.0f;
    memset(&d, 0, sizeof d);
    d.positions = P->pos;
    d.nv = P->m.nv;
    d.tris = P->m.tri;
    d.ntris = P->m.nf;
    d.lighting = PW_LIGHT_CAMERA;
    d.ambient = 0.3f;
    d.shader = pgp__shade;
    d.shader_user = S;
    if ((r = pw_fb_create(&P->a, &fb, o->width, o->height, o->supersample, bg, e)) != PW_OK) return r;
    if ((r = pw_render_draw(&fb, &cam, &d, e)) == PW_OK) r = pw_fb_resolve(&fb, pic, 3, e);
    pw_fb_free(&fb);
    return r;
}

PGPDEF pgp_result pgp_render(const pgp_map *map, const pgp_tile *tile, const pgp_render_options *ro, pgp_image *out,
                             pgp_error *err)
{
    pgp_render_options o;
    pgp__shading S;
    pw_tile3 t3;
    pw_image pic;
    pw_err pe;
    float *views = NULL;
    unsigned char *fixed = NULL;
    int f;
    if (ro) o = *ro;
    else memset(&o, 0, sizeof o);
    pw_view_defaults(&o.width, &o.height, &o.supersample, o.view_dir, o.up, o.background);
    pw_err_clear(&pe);
    memset(&t3, 0, sizeof t3);
    if (out) memset(out, 0, sizeof *out);
    if (!out || !map) pw_fail(&pe, PW_ERR_INVALID, "pgp_render: NULL map or output");
    else if (o.width < 1 || o.height < 1 || o.supersample < 1 || o.supersample > 8 || o.fix < 0 || o.fix > 2 ||
             o.show < 0 || o.show > 2)
        pw_fail(&pe, PW_ERR_INVALID, "render options: size %dx%d, supersample %d, fix %d, show %d", o.width,
                o.height, o.supersample, o.fix, o.show);
    else if (pgp__tile3(&map->a, tile, &t3, &pe) == PW_OK &&
             (views = (float *)pw_alloc_array(&map->a, (size_t)map->m.nf * 18, sizeof(float), "views", &pe)) != NULL &&
             (fixed = (unsigned char *)pw_alloc_array(&map->a, (size_t)map->m.nf, 1, "views", &pe)) != NULL) {
        for (f = 0; f < map->m.nf; f++) {
            fixed[f] = (unsigned char)(o.fix == 2 || (o.fix == 0 && map->fsing[f]));
            if (fixed[f]) pgp__views(map, f, o.fix == 2, views + 18 * (size_t)f);
        }
        S.P = map, S.tile = &t3, S.views = views, S.fixed = fixed, S.show = o.show;
        if (pgp__draw(map, &S, &o, &pic, &pe) == PW_OK) pgp__take_image(&pic, &map->a, out);
    }
    pw_free(map ? &map->a : NULL, views);
    pw_free(map ? &map->a : NULL, fixed);
    if (map) pw_tile3_free(&map->a, &t3);
    return pgp__done(&pe, err);
}
