/* builtin.c: built-in meshes and material-space tiles for demos and tests.
 *
 * Meshes come from the shared shapes module ("sphere", "torus", "bumpy" as
 * in lapped.h, and "grid", a flat square with a boundary). Tiles are RGB,
 * follow opt->synth.seed, and are periodic in s and t by construction: every
 * feature is laid out on a lattice that divides the tile (3 bricks by 8
 * rows, 8 stripes) and every noise is value noise on a lattice whose period
 * divides the tile, so the texel after the last column is the texel of
 * column 0 (§2: "periodic in the (s,t) dimensions"). Everything is made
 * from + - * /, floor and sqrt, so the data is the same on every platform.
 *
 *   "bricks"   4 layers along m (§4, Figure 14): running-bond bricks at
 *              m = 0 that weather as m grows: the mortar widens and turns
 *              earthy and mossy, the bricks erode (rounder, smaller,
 *              shifted, pinched) into pebble-like stones and their colour
 *              drifts from fired red to weathered grey-brown.
 *   "stripes"  1 layer: horizontal bands (constant along s, so the pattern
 *              shows the direction of d_s), each its own colour, with pin
 *              stripes and a faint weave. */
#include "render.c"
#include "../common/shapes.h"
#include "../common/noise.h"

/* ---- meshes ----------------------------------------------------------------- */

PGPDEF pgp_result pgp_builtin_mesh(const char *name, const pgp_options *opt, pgp_mesh *out, pgp_error *err)
{
    pgp_options o = pgp__options(opt);
    pw_alloc a = pgp__alloc(&o.allocator);
    pw_mesh m;
    pw_err pe;
    int r = -1;
    pw_err_clear(&pe);
    memset(&m, 0, sizeof m);
    if (out) memset(out, 0, sizeof *out);
    if (!out || !name) pw_fail(&pe, PW_ERR_INVALID, "pgp_builtin_mesh: NULL argument");
    else if (!strcmp(name, "sphere")) r = pw_shape_geosphere(&a, 12, &m, &pe);
    else if (!strcmp(name, "torus")) r = pw_shape_torus(&a, 128, 64, 0, &m, &pe); /* fine: small singular 1-rings */
    else if (!strcmp(name, "bumpy")) r = pw_shape_bumpy(&a, 16, &m, &pe);
    else if (!strcmp(name, "grid")) r = pw_shape_grid(&a, 32, 0.0, 0, &m, &pe);
    else pw_fail(&pe, PW_ERR_INVALID, "unknown built-in mesh '%s' (sphere, torus, bumpy, grid)", name);
    if (r == PW_OK) pgp__take_mesh(&m, &a, out);
    return pgp__done(&pe, err);
}

/* ---- periodic noise ----------------------------------------------------------- */

/* Uniform in [0, 1): the k-th random number of element `id`. */
static double pgp__rand(unsigned long long seed, int id, int k)
{
    return (double)(pw_hash64(seed ^ 0x5bd1e9955bd1e995ULL, (uint64_t)id * 16u + (uint64_t)k) >> 11) *
           (1.0 / 9007199254740992.0);
}

/* ---- "bricks" ------------------------------------------------------------------ */

/* 3 bricks a row, 8 rows a tile, odd rows shifted by half a brick: both
 * divide the tile, so the bond is periodic. Lengths are in row heights. */
enum { PGP__BX = 3, PGP__BY = 8 };

/* What a point of the wall is: its cell's brick, where it lies from the
 * cell's centre (x, y, in row heights), the signed distance to that
 * stone's edge (< 0 inside) and the surface height there. */
typedef struct pgp__wall {
    int id;
    double x, y;
    double d, h, cover, hy;
} pgp__wall;

/* Signed distance to a box of half sizes (bx, by) with corners rounded by
 * rc, at (x, y) from its centre. */
static double pgp__round_box(double x, double y, double bx, double by, double rc)
{
    double qx = (x < 0 ? -x : x) - (bx - rc), qy = (y < 0 ? -y : y) - (by - rc);
    double ox = qx > 0 ? qx : 0, oy = qy > 0 ? qy : 0, in = qx > qy ? qx : qy;
    return sqrt(ox * ox + oy * oy) + (in < 0 ? in : 0) - rc;
}

/* The stone of brick o->id at weathering w in [0, 1], at (o->x, o->y)
 * from its cell's centre: the mortar gap widens with w, the brick shrinks
 * and moves a little, its corners round off until it is a pebble, some
 * pebbles get a waist, and the edge is eaten by noise. */
static void pgp__stone(unsigned long long seed, double w, double s, double t, pgp__wall *o)
{
    const double L = (double)PGP__BY / PGP__BX, x = o->x, y = o->y;
    double mw = 0.045 + 0.12 * w, r1 = pgp__rand(seed, o->id, 1), r2 = pgp__rand(seed, o->id, 2);
    double bx = 0.5 * L - mw - 0.4 * w * r1, by = 0.5 - mw - 0.12 * w * r2;
    double cx = 0.3 * w * r1 * (pgp__rand(seed, o->id, 3) - 0.5), cy = 0.07 * w * (pgp__rand(seed, o->id, 4) - 0.5);
    double pinch = pgp__rand(seed, o->id, 5) < 0.4 ? 0.3 * pw_smoothstep(0.4, 1.0, w) : 0.0;
    double ang = 0.14 * w * (pgp__rand(seed, o->id, 6) - 0.5), ca = pw_cos(ang), sa = pw_sin(ang);
    double px = ca * (x - cx) + sa * (y - cy), py = ca * (y - cy) - sa * (x - cx), u = px / (0.6 * bx), waist, rc;
    waist = u > -1.0 && u < 1.0 ? (1.0 - u * u) * (1.0 - u * u) : 0.0;
    by *= 1.0 - pinch * waist;
    rc = (0.03 + 0.97 * w) * by;
    o->hy = by;
    o->d = pgp__round_box(px, py, bx, by, rc);
    o->d += (0.012 + 0.07 * w) * (2.0 * pw_fbm2(seed + 10, s * 16, t * 16, 16) - 1.0);
}

/* The wall at (s, t): cell, stone, anti-aliased coverage (px: a texel in
 * row heights) and height (bevelled bricks, domed pebbles, sunken mortar). */
static void pgp__wall_at(unsigned long long seed, double w, double s, double t, double px, pgp__wall *o)
{
    const double L = (double)PGP__BY / PGP__BX;
    double x = s * PGP__BY, y = t * PGP__BY, fy = floor(y), off, fx, in, bevel, a, prof, top, mortar;
    int row = (int)fy, col;
    off = (row & 1) ? 0.5 * L : 0.0;
    fx = floor((x - off) / L);
    col = (int)fx;
    row = ((row % PGP__BY) + PGP__BY) % PGP__BY;
    col = ((col % PGP__BX) + PGP__BX) % PGP__BX;
    o->id = row * PGP__BX + col;
    o->x = x - off - (fx + 0.5) * L;
    o->y = y - fy - 0.5;
    pgp__stone(seed, w, s, t, o);
    o->cover = pw_smoothstep(-0.5, 0.5, -o->d / px);
    in = -o->d;
    bevel = 0.035 + 0.9 * w * o->hy;
    a = in <= 0.0 ? 0.0 : in >= bevel ? 1.0 : in / bevel;
    prof = (1.0 - w) * a * a * (3.0 - 2.0 * a) + w * sqrt(a * (2.0 - a)); /* bevel .. dome */
    /* each height only where it shows (the noise is most of the cost) */
    top = o->cover > 0.0 ? (0.05 + 0.16 * w) * prof + 0.012 * pw_fbm2(seed + 20, s * 64, t * 64, 64) : 0.0;
    mortar = o->cover < 1.0 ? -0.04 - 0.05 * w + 0.03 * pw_fbm2(seed + 21, s * 48, t * 48, 48) : 0.0;
    o->h = o->cover >= 1.0 ? top : mortar + (top - mortar) * o->cover;
}

/* Lambert shading of the height field (light from the upper left, t up),
 * 1 on flat ground. */
static double pgp__wall_light(unsigned long long seed, double w, double s, double t, double px, double h)
{
    static const double l[3] = {-0.42, 0.55, 0.72};
    pgp__wall ex, ey;
    double e = px / PGP__BY, gx, gy, n;
    pgp__wall_at(seed, w, s + e, t, px, &ex);
    pgp__wall_at(seed, w, s, t + e, px, &ey);
    gx = (ex.h - h) / px;
    gy = (ey.h - h) / px;
    n = sqrt(gx * gx + gy * gy + 1.0);
    return pw_clampf((float)((-gx * l[0] - gy * l[1] + l[2]) / (n * l[2])), 0.3f, 1.45f);
}

/* The colour of stone `id`: fired brick at w = 0 (a few over-burnt), a
 * weathered stone at w = 1, soot and blotches in between. */
static void pgp__stone_colour(unsigned long long seed, double w, double s, double t, int id, double *c)
{
    static const double brick[5][3] = {
        {0.66, 0.27, 0.17}, {0.58, 0.22, 0.15}, {0.72, 0.36, 0.22}, {0.52, 0.21, 0.15}, {0.63, 0.31, 0.22}};
    static const double stone[6][3] = {{0.60, 0.55, 0.48}, {0.47, 0.44, 0.41}, {0.66, 0.58, 0.47},
                                       {0.53, 0.43, 0.35}, {0.41, 0.39, 0.38}, {0.57, 0.48, 0.39}};
    static const double burnt[3] = {0.34, 0.17, 0.13};
    double b[3], st[3], v = 0.88 + 0.24 * pgp__rand(seed, id, 8), grain, blotch;
    int k;
    pw_mix3(b, brick[(int)(5.0 * pgp__rand(seed, id, 10))], burnt, pgp__rand(seed, id, 7) < 0.1 ? 0.8 : 0.0);
    memcpy(st, stone[(int)(6.0 * pgp__rand(seed, id, 9))], sizeof st);
    pw_mix3(c, b, st, w);
    grain = 0.9 + 0.2 * pw_fbm2(seed + 30, s * 96, t * 96, 96) * (1.0 + w);
    blotch = 1.0 - (0.1 + 0.5 * w * (1.0 - w)) * pw_smoothstep(0.45, 0.8, pw_fbm2(seed + 31, s * 12, t * 12, 12));
    for (k = 0; k < 3; k++) c[k] *= v * grain * blotch;
}

/* The mortar: light lime at w = 0, earthy with moss patches at w = 1. */
static void pgp__mortar_colour(unsigned long long seed, double w, double s, double t, double *c)
{
    static const double fresh[3] = {0.80, 0.78, 0.73}, old[3] = {0.43, 0.39, 0.31}, moss[3] = {0.31, 0.41, 0.17};
    double g = 0.85 + 0.3 * pw_fbm2(seed + 40, s * 128, t * 128, 128);
    int k;
    pw_mix3(c, fresh, old, w);
    if (w > 0.0) pw_mix3(c, c, moss, w * pw_smoothstep(0.5, 0.68, pw_fbm2(seed + 41, s * 8, t * 8, 8)));
    for (k = 0; k < 3; k++) c[k] *= g;
}

static void pgp__bricks(unsigned long long seed, double w, double s, double t, double px, double *rgb)
{
    pgp__wall o;
    double stone[3], mortar[3], light, ao;
    int k;
    pgp__wall_at(seed, w, s, t, px, &o);
    light = pgp__wall_light(seed, w, s, t, px, o.h);
    memset(stone, 0, sizeof stone);
    memset(mortar, 0, sizeof mortar);
    if (o.cover > 0.0) pgp__stone_colour(seed, w, s, t, o.id, stone);
    if (o.cover < 1.0) pgp__mortar_colour(seed, w, s, t, mortar);
    ao = 0.55 + 0.45 * pw_smoothstep(0.0, 0.05 + 0.1 * w, o.d); /* the mortar is dark beside the stones */
    for (k = 0; k < 3; k++) rgb[k] = (mortar[k] * ao + (stone[k] - mortar[k] * ao) * o.cover) * light;
}

/* ---- "stripes" ----------------------------------------------------------------- */

/* 8 bands down the tile; band k holds a coloured stripe of its own width on
 * a cream ground, with a thin darker pin stripe in the gap above it. */
static void pgp__stripes(unsigned long long seed, double s, double t, double px, double *rgb)
{
    static const double pal[6][3] = {{0.16, 0.27, 0.50}, {0.70, 0.20, 0.18}, {0.16, 0.45, 0.35},
                                     {0.85, 0.62, 0.18}, {0.40, 0.24, 0.46}, {0.12, 0.12, 0.15}};
    static const double cream[3] = {0.93, 0.90, 0.82};
    const int N = 8;
    double y = t * N, fy = floor(y), v = y - fy, half, cov, pin, col[3], weave;
    int band = (((int)fy % N) + N) % N, k;
    half = 0.22 + 0.16 * pgp__rand(seed, band, 0);
    memcpy(col, pal[(int)(6.0 * pgp__rand(seed, band, 1))], sizeof col);
    cov = pw_smoothstep(-0.5, 0.5, (half - (v < 0.5 ? 0.5 - v : v - 0.5)) / (px * N)); /* px: a texel in t */
    pin = pw_smoothstep(-0.5, 0.5, (0.018 - (v < 0.93 ? 0.93 - v : v - 0.93)) / (px * N));
    for (k = 0; k < 3; k++) rgb[k] = cream[k] + (col[k] - cream[k]) * cov;
    for (k = 0; k < 3; k++) rgb[k] += (0.55 * col[k] - rgb[k]) * pin * (1.0 - cov);
    weave = 0.93 + 0.1 * pw_fbm2(seed + 50, s * 8, t * 8, 8) + 0.05 * pw_noise2(seed + 51, s * 256, t * 256, 256);
    for (k = 0; k < 3; k++) rgb[k] *= weave;
}

/* ---- tiles ---------------------------------------------------------------------- */

enum { PGP__TILE_BRICKS = 0, PGP__TILE_STRIPES = 1 };

/* A built-in tile being drawn: its kind, seed, layer count and the side
 * of a texel in tile units. */
typedef struct pgp__builtin {
    int kind;
    unsigned long long seed;
    int layers;
    double px;
} pgp__builtin;

/* The colour of built-in tile B at (s, t) of layer `layer`. Periodic:
 * (s + 1, t) and (s, t + 1) give the same colour up to rounding. */
static void pgp__tile_texel(const pgp__builtin *B, int layer, double s, double t, float *rgb)
{
    const int kind = B->kind, layers = B->layers;
    const unsigned long long seed = B->seed;
    const double px = B->px;
    double c[3];
    int k;
    if (kind == PGP__TILE_BRICKS)
        pgp__bricks(seed, layers > 1 ? (double)layer / (layers - 1) : 0.0, s, t, px * PGP__BY, c);
    else pgp__stripes(seed, s, t, px, c);
    for (k = 0; k < 3; k++) rgb[k] = pw_clampf((float)c[k], 0.0f, 1.0f);
}

PGPDEF pgp_result pgp_builtin_tile(const char *name, int size, const pgp_options *opt, pgp_tile *out, pgp_error *err)
{
    pgp_options o = pgp__options(opt);
    pw_alloc a = pgp__alloc(&o.allocator);
    pw_volume vol;
    pgp__builtin B;
    pw_err pe;
    int kind = -1, layers, x, y, z;
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (name) kind = !strcmp(name, "bricks") ? PGP__TILE_BRICKS : !strcmp(name, "stripes") ? PGP__TILE_STRIPES : -1;
    layers = kind == PGP__TILE_BRICKS ? 4 : 1;
    if (!out || kind < 0)
        pw_fail(&pe, PW_ERR_INVALID, "unknown built-in tile '%s' (bricks, stripes)", name ? name : "(null)");
    else if (size < 8 || size > 4096) pw_fail(&pe, PW_ERR_INVALID, "built-in tile size must be 8..4096 (got %d)", size);
    else if (pw_volume_alloc(&a, &vol, 3, size, size, layers, &pe) == PW_OK) {
        double px = 1.0 / size;
        B.kind = kind;
        B.seed = o.synth.seed;
        B.layers = layers;
        B.px = px;
        for (z = 0; z < layers; z++)
            for (y = 0; y < size; y++)
                for (x = 0; x < size; x++) /* texel centres; row 0 at the top, t = 0 at the bottom */
                    pgp__tile_texel(&B, z, (x + 0.5) * px, 1.0 - (y + 0.5) * px,
                                    vol.px + (((size_t)z * size + y) * size + x) * 3);
        out->width = out->height = size;
        out->layers = layers;
        out->channels = 3;
        out->pixels = vol.px;
        out->allocator = pgp__allocator(&a);
    }
    return pgp__done(&pe, err);
}
