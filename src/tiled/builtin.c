/* builtin.c: built-in meshes and exemplars for demos and tests: the
 * kinds of surfaces of ch. V (a cube, a torus, a genus-2 "double donut",
 * triangle meshes made quads by ch. VI's subdivision, an open grid) and
 * homogeneous, isotropic exemplars for ch. III.1.3. */
#include "core.c"
#include "../common/noise.h"

/* Moves a mesh's bounding-box centre to the origin and scales it to fit
 * [-1,1]^3 (voxel meshes come in lattice units). */
static void tiled__normalise(tiled_mesh *m)
{
    float lo[3], hi[3], s;
    int k, v;
    for (k = 0; k < 3; k++) lo[k] = hi[k] = m->positions[k];
    for (v = 0; v < m->nverts; v++)
        for (k = 0; k < 3; k++) {
            float x = m->positions[3 * v + k];
            lo[k] = x < lo[k] ? x : lo[k];
            hi[k] = x > hi[k] ? x : hi[k];
        }
    s = 0.0f;
    for (k = 0; k < 3; k++) s = hi[k] - lo[k] > s ? hi[k] - lo[k] : s;
    for (v = 0; v < m->nverts; v++)
        for (k = 0; k < 3; k++) m->positions[3 * v + k] = (m->positions[3 * v + k] - 0.5f * (lo[k] + hi[k])) * 2.0f / s;
}

TILEDDEF tiled_result tiled_builtin_mesh(const char *name, const tiled_options *opt, tiled_mesh *out, tiled_error *err)
{
    /* genus 2: a 5x3x2 slab of voxels with two holes through it */
    static const unsigned char slab[30] = {1, 1, 1, 1, 1, 1, 0, 1, 0, 1, 1, 1, 1, 1, 1,
                                           1, 1, 1, 1, 1, 1, 0, 1, 0, 1, 1, 1, 1, 1, 1};
    static const unsigned char one = 1;
    tiled_options o = tiled__options(opt);
    pw_alloc a = tiled__alloc(&o.allocator);
    pw_mesh pm;
    pw_err pe;
    pw_err_clear(&pe);
    memset(&pm, 0, sizeof pm);
    if (out) memset(out, 0, sizeof *out);
    if (!out || !name) pw_fail(&pe, PW_ERR_INVALID, "tiled_builtin_mesh: NULL argument");
    else if (!strcmp(name, "cube")) pw_shape_polycube(&a, 1, 1, 1, &one, &pm, &pe);
    else if (!strcmp(name, "double-torus")) pw_shape_polycube(&a, 5, 3, 2, slab, &pm, &pe);
    else if (!strcmp(name, "torus")) pw_shape_torus(&a, 24, 12, 1, &pm, &pe);
    else if (!strcmp(name, "icosahedron")) pw_shape_icosahedron(&a, &pm, &pe);
    else if (!strcmp(name, "grid")) pw_shape_grid(&a, 12, 0.2, 1, &pm, &pe);
    else
        pw_fail(&pe, PW_ERR_INVALID,
                "unknown built-in mesh '%s' (cube, torus, double-torus, "
                "icosahedron, grid)",
                name);
    if (pe.code == PW_OK) tiled__take_mesh(&pm, &a, out);
    if (pe.code == PW_OK) tiled__normalise(out);
    return tiled__done(&pe, err);
}

/* Procedural exemplars: periodic on the unit torus, built from + - * / and
 * sqrt only, so they are identical on every platform. */
typedef struct tiled__cells {
    int m;                  /* m x m jittered cells */
    float px[256], py[256]; /* one feature point per cell, in [0,1) */
    float col[256][3];
} tiled__cells;

static void tiled__cells_init(tiled__cells *c, int m, pw_rng *r)
{
    int k;
    c->m = m;
    for (k = 0; k < m * m; k++) {
        c->px[k] = ((float)(k % m) + 0.15f + 0.7f * pw_rng_float(r)) / (float)m;
        c->py[k] = ((float)(k / m) + 0.15f + 0.7f * pw_rng_float(r)) / (float)m;
        c->col[k][0] = pw_rng_float(r);
        c->col[k][1] = pw_rng_float(r);
        c->col[k][2] = pw_rng_float(r);
    }
}

/* Distances to the nearest and second nearest feature points (periodic),
 * and the nearest point's index. */
static void tiled__cells_eval(const tiled__cells *c, float x, float y, float *f1, float *f2, int *id)
{
    int cx = (int)(x * (float)c->m), cy = (int)(y * (float)c->m), dx, dy;
    *f1 = *f2 = 4.0f;
    *id = 0;
    for (dy = -2; dy <= 2; dy++)
        for (dx = -2; dx <= 2; dx++) {
            int gx = cx + dx, gy = cy + dy, k;
            float ox = 0.0f, oy = 0.0f, ddx, ddy, d;
            if (gx < 0) {
                gx += c->m;
                ox = -1.0f;
            }
            if (gx >= c->m) {
                gx -= c->m;
                ox = 1.0f;
            }
            if (gy < 0) {
                gy += c->m;
                oy = -1.0f;
            }
            if (gy >= c->m) {
                gy -= c->m;
                oy = 1.0f;
            }
            k = gy * c->m + gx;
            ddx = c->px[k] + ox - x;
            ddy = c->py[k] + oy - y;
            d = sqrtf(ddx * ddx + ddy * ddy);
            if (d < *f1) {
                *f2 = *f1;
                *f1 = d;
                *id = k;
            } else if (d < *f2) *f2 = d;
        }
}

/* pw_mix3f with t clamped to [0, 1]. */
static void tiled__mix(float *out, const float *a, const float *b, float t)
{
    pw_mix3f(out, a, b, pw_clampf(t, 0.0f, 1.0f));
}

/* Pebbles: rounded stones of varied greys and browns in dark mortar. */
static void tiled__pebbles(const tiled__cells *c, uint64_t seed, float x, float y, float *rgb)
{
    static const float mortar[3] = {0.16f, 0.13f, 0.11f};
    float f1, f2, stone[3], edge, grain;
    int id, k;
    tiled__cells_eval(c, x, y, &f1, &f2, &id);
    grain = (float)pw_fbm2(seed, 4.0 * x, 4.0 * y, 4);
    for (k = 0; k < 3; k++) /* warm greys: shared brightness, a little hue */
        stone[k] = 0.35f + 0.35f * c->col[id][0] + 0.12f * (c->col[id][k] - 0.5f) + 0.25f * (grain - 0.5f);
    edge = (f2 - f1) * (float)c->m * 3.0f; /* 0 on the cell border */
    tiled__mix(rgb, mortar, stone, edge * edge);
}

/* Spots: broken dark rosettes with brown centres on a tawny, mottled
 * ground (leopard-like). */
static void tiled__spots(const tiled__cells *c, uint64_t seed, float x, float y, float *rgb)
{
    static const float ground[3] = {0.86f, 0.67f, 0.37f}, ring[3] = {0.1f, 0.07f, 0.05f},
                       centre[3] = {0.6f, 0.4f, 0.19f};
    float f1, f2, r, base[3], n = (float)pw_fbm2(seed, 4.0 * x, 4.0 * y, 4), broken, k;
    int id;
    tiled__cells_eval(c, x, y, &f1, &f2, &id);
    r = (0.25f + 0.12f * c->col[id][0]) / (float)c->m; /* rosette radius */
    k = 40.0f * (float)c->m;                           /* edge sharpness */
    broken = (float)pw_noise2(seed + 11, 16 * x, 16 * y, 16) > 0.3f ? 1.0f : 0.0f;
    tiled__mix(base, ground, centre, (0.5f * r - f1) * k);
    tiled__mix(rgb, base, ring,
               broken * pw_clampf((f1 - 0.5f * r) * k, 0.0f, 1.0f) * pw_clampf((r - f1) * k, 0.0f, 1.0f));
    rgb[0] *= 0.85f + 0.3f * n;
    rgb[1] *= 0.85f + 0.3f * n;
    rgb[2] *= 0.85f + 0.3f * n;
}

/* Lichen: yellow-green crusts on grey stone, from thresholded fBm. */
static void tiled__lichen(uint64_t seed, float x, float y, float *rgb)
{
    static const float stone[3] = {0.5f, 0.5f, 0.48f}, moss[3] = {0.55f, 0.62f, 0.2f}, dark[3] = {0.2f, 0.22f, 0.12f};
    float n = (float)pw_fbm2(seed, 4.0 * x, 4.0 * y, 4), d = (float)pw_fbm2(seed + 7, 4.0 * x, 4.0 * y, 4), base[3];
    tiled__mix(base, stone, moss, (n - 0.5f) * 12.0f);
    tiled__mix(rgb, base, dark, (d - 0.62f) * 8.0f);
}

TILEDDEF tiled_result tiled_builtin_exemplar(const char *name, int size, const tiled_options *opt, tiled_image *out,
                                             tiled_error *err)
{
    tiled_options o = tiled__options(opt);
    pw_alloc a = tiled__alloc(&o.allocator);
    pw_rng r = pw_rng_seed(o.seed, 4);
    tiled__cells cells;
    pw_image img;
    pw_err pe;
    int x, y, kind = -1;
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (name) kind = !strcmp(name, "pebbles") ? 0 : !strcmp(name, "spots") ? 1 : !strcmp(name, "lichen") ? 2 : -1;
    if (!out || kind < 0)
        pw_fail(&pe, PW_ERR_INVALID, "unknown built-in exemplar '%s' (pebbles, spots, lichen)", name ? name : "(null)");
    else if (size < 8 || size > 4096) pw_fail(&pe, PW_ERR_INVALID, "exemplar size must be 8..4096 (got %d)", size);
    else if (pw_image_alloc(&a, &img, size, size, 3, &pe) == PW_OK) {
        tiled__cells_init(&cells, kind == 0 ? 4 : 3, &r);
        for (y = 0; y < size; y++)
            for (x = 0; x < size; x++) {
                float u = ((float)x + 0.5f) / (float)size, v = ((float)y + 0.5f) / (float)size;
                float *p = img.px + ((size_t)y * size + x) * 3;
                if (kind == 0) tiled__pebbles(&cells, o.seed, u, v, p);
                else if (kind == 1) tiled__spots(&cells, o.seed, u, v, p);
                else tiled__lichen(o.seed, u, v, p);
                p[0] = pw_clampf(p[0], 0.0f, 1.0f);
                p[1] = pw_clampf(p[1], 0.0f, 1.0f);
                p[2] = pw_clampf(p[2], 0.0f, 1.0f);
            }
        tiled__take_image(&img, &a, out);
    }
    return tiled__done(&pe, err);
}
