/* builtin.c: built-in meshes (made by the shared shapes module) and textures
 * for demos and tests. Everything is made from + - * / and sqrt (and
 * pw_sin/pw_cos, built from those), so the data is the same on every
 * platform. Meshes are triangle meshes, counter-clockwise seen from
 * outside, about unit size. Textures are RGB and follow opt->seed:
 * "scales" and "stripes" are anisotropic (they have an obvious up
 * direction, for LAPPED_FIELD_UP and friends, §3.2), "dots" is isotropic
 * (for LAPPED_FIELD_ISOTROPIC). */
#include "core.c"
#include "../common/shapes.h"
#include "../common/noise.h"

/* ---- meshes ----------------------------------------------------------------- */

LAPPEDDEF lapped_result lapped_builtin_mesh(const char *name, const lapped_options *opt, lapped_mesh *out,
                                            lapped_error *err)
{
    lapped_options o = lapped__options(opt);
    pw_alloc a = lapped__alloc(&o.allocator);
    pw_mesh m;
    pw_err pe;
    int r = -1;
    pw_err_clear(&pe);
    memset(&m, 0, sizeof m);
    if (out) memset(out, 0, sizeof *out);
    if (!out || !name) pw_fail(&pe, PW_ERR_INVALID, "lapped_builtin_mesh: NULL argument");
    else if (!strcmp(name, "sphere")) r = pw_shape_geosphere(&a, 12, &m, &pe);
    else if (!strcmp(name, "torus")) r = pw_shape_torus(&a, 48, 32, 0, &m, &pe);
    else if (!strcmp(name, "bumpy")) r = pw_shape_bumpy(&a, 16, &m, &pe);
    else if (!strcmp(name, "disc")) r = pw_shape_disc(&a, 18, &m, &pe);
    else pw_fail(&pe, PW_ERR_INVALID, "unknown built-in mesh '%s' (sphere, torus, bumpy, disc)", name);
    if (r == PW_OK) lapped__take_mesh(&m, &a, out);
    return lapped__done(&pe, err);
}

/* ---- textures ----------------------------------------------------------------- */

/* "scales": overlapping scales in rows like roof tiles: the rows above lie
 * over the rows below, so each scale shows its lower half, with a dark
 * rounded free edge at the bottom and a shadow under the scale above. 8
 * scales across; (x, y) in scale widths, y down. */
static void lapped__scales(unsigned long long seed, float x, float y, float px, float *rgb)
{
    static const float lo[3] = {0.12f, 0.36f, 0.34f}, hi[3] = {0.62f, 0.7f, 0.34f}, edge[3] = {0.05f, 0.09f, 0.08f};
    const float sy = 0.5f, R = 0.62f;
    int j, j0 = (int)((y - R) / sy + 100.0f) - 100, hit = 0, ci = 0, cj = 0;
    float dx = 0.0f, dy = 0.0f, shade = 1.0f, rho, up = 1.0f, h, base[3];
    for (j = j0; j <= j0 + 4 && !hit; j++) { /* the topmost row containing (x, y) wins */
        float off = (j & 1) ? 0.5f : 0.0f, cy = (float)j * sy;
        int i0 = (int)(x - off + 100.5f) - 100, i;
        for (i = i0 - 1; i <= i0 + 1 && !hit; i++) {
            float ex = x - ((float)i + off), ey = y - cy;
            if (ex * ex + ey * ey < R * R) {
                hit = 1;
                ci = i;
                cj = j;
                dx = ex;
                dy = ey;
            }
        }
    }
    for (j = -1; j <= 1; j += 2) { /* distance to the edges of the two scales of the row above */
        float cx = (float)ci + ((cj & 1) ? 0.5f : 0.0f) + 0.5f * (float)j, cy = (float)(cj - 1) * sy;
        float d = sqrtf((x - cx) * (x - cx) + (y - cy) * (y - cy)) - R;
        up = d < up ? d : up;
    }
    rho = sqrtf(dx * dx + dy * dy) / R;
    h = (float)pw_lattice01(seed, ci, cj, 0);
    pw_mix3f(base, lo, hi, 0.25f + 0.5f * h + 0.35f * (dy / R));
    shade = (0.55f + 0.45f * (float)pw_smoothstep(0.0f, 0.22f, up)) *
            (0.85f + 0.3f * (float)pw_lattice01(seed + 5, ci, cj, 0));
    shade *= 0.9f + 0.2f * (float)pw_fbm2(seed + 9, 24.0f * x, 6.0f * y, 0); /* fine striations */
    shade += 0.25f * (float)pw_smoothstep(0.45f, 0.0f, rho) * (float)pw_smoothstep(0.0f, 0.3f, up); /* sheen */
    base[0] *= shade;
    base[1] *= shade;
    base[2] *= shade;
    pw_mix3f(rgb, base, edge, (float)pw_smoothstep(1.0f - 0.09f - px, 1.0f - 0.02f, rho));
}

/* "stripes": zebra-like, roughly horizontal dark stripes warped by noise,
 * 7 down the image, their width varying so that some thin out and end or
 * merge. The signed distance into the nearest stripe (in stripe periods; > 0
 * inside); (x, y) in image widths. */
static float lapped__stripe_inside(unsigned long long seed, float x, float y)
{
    const float tau = 6.28318530717958647692f;
    float warp = 0.9f * ((float)pw_fbm2(seed, 2.5f * x, 2.5f * y, 0) - 0.5f) +
                 0.25f * (float)pw_sin(tau * (1.3f * x + 0.2f)) * (float)pw_cos(tau * 0.7f * y);
    float phase = 7.0f * y + 2.2f * warp, f = phase - (float)((int)(phase + 100.0f) - 100), d = f - 0.5f;
    float half = 0.25f + 0.75f * ((float)pw_fbm2(seed + 3, 3.0f * x, 3.0f * y, 0) - 0.5f);
    return half - (d < 0.0f ? -d : d); /* |d|: 0 on a stripe's centre line, 0.5 halfway to the next */
}

/* Coverage from the signed distance and its gradient over one pixel (finite
 * differences), so that every edge is about a pixel wide, also where a
 * stripe tapers off. */
static void lapped__stripes(unsigned long long seed, float x, float y, float px, float *rgb)
{
    static const float dark[3] = {0.07f, 0.06f, 0.06f}, light[3] = {0.93f, 0.89f, 0.8f};
    float v = lapped__stripe_inside(seed, x, y), gx = lapped__stripe_inside(seed, x + px, y) - v;
    float gy = lapped__stripe_inside(seed, x, y + px) - v, g = sqrtf(gx * gx + gy * gy);
    float t = g > 1e-6f ? pw_clampf(v / g + 0.5f, 0.0f, 1.0f) : (v > 0.0f ? 1.0f : 0.0f);
    pw_mix3f(rgb, light, dark, t);
    g = 0.92f + 0.16f * (float)pw_fbm2(seed + 7, 40.0f * x, 12.0f * y, 0); /* hair grain */
    rgb[0] *= g;
    rgb[1] *= g;
    rgb[2] *= g;
}

/* "dots": polka dots of varied sizes and colours, one per cell of a
 * jittered 6x6 grid, and small dots of a finer 13x13 grid between them, on
 * a warm off-white ground. Isotropic. (x, y) in image widths. */

/* One layer of dots: a cells x cells grid, each dot's radius in
 * [rmin, rmax] cells, placed and coloured by the lattice noise of seed. */
typedef struct {
    unsigned long long seed;
    int cells;
    float rmin, rmax;
} lapped__dot_grid;

static void lapped__dot_layer(const lapped__dot_grid *grid, float x, float y, float px, float *rgb)
{
    unsigned long long seed = grid->seed;
    int cells = grid->cells;
    float rmin = grid->rmin, rmax = grid->rmax;
    static const float pal[6][3] = {{0.86f, 0.24f, 0.28f}, {0.19f, 0.44f, 0.76f}, {0.96f, 0.72f, 0.16f},
                                    {0.25f, 0.63f, 0.4f},  {0.55f, 0.33f, 0.72f}, {0.95f, 0.5f, 0.22f}};
    float gx = x * (float)cells, gy = y * (float)cells;
    int ix = (int)gx, iy = (int)gy, c;
    float rad = (rmin + (rmax - rmin) * (float)pw_lattice01(seed, ix, iy, 0)) / (float)cells,
          room = 0.5f / (float)cells - rad;
    float cx = ((float)ix + 0.5f) / (float)cells + room * (2.0f * (float)pw_lattice01(seed + 1, ix, iy, 0) - 1.0f);
    float cy = ((float)iy + 0.5f) / (float)cells + room * (2.0f * (float)pw_lattice01(seed + 2, ix, iy, 0) - 1.0f);
    float d = sqrtf((x - cx) * (x - cx) + (y - cy) * (y - cy)), cover = pw_clampf((rad - d) / px + 0.5f, 0.0f, 1.0f);
    float col[3], light = 1.0f + 0.25f * (float)pw_smoothstep(rad, 0.0f,
                                                              sqrtf((x - cx + 0.3f * rad) * (x - cx + 0.3f * rad) +
                                                                    (y - cy + 0.3f * rad) * (y - cy + 0.3f * rad)));
    c = (int)(6.0f * (float)pw_lattice01(seed + 3, ix, iy, 0)) % 6;
    col[0] = pw_clampf(pal[c][0] * light, 0.0f, 1.0f);
    col[1] = pw_clampf(pal[c][1] * light, 0.0f, 1.0f);
    col[2] = pw_clampf(pal[c][2] * light, 0.0f, 1.0f);
    pw_mix3f(rgb, rgb, col, cover);
}

static void lapped__dots(unsigned long long seed, float x, float y, float px, float *rgb)
{
    float g = 0.94f + 0.06f * (float)pw_fbm2(seed + 11, 20.0f * x, 20.0f * y, 0);
    lapped__dot_grid small, big;
    rgb[0] = 0.97f * g;
    rgb[1] = 0.94f * g;
    rgb[2] = 0.86f * g;
    small.seed = seed + 20;
    small.cells = 13;
    small.rmin = 0.12f;
    small.rmax = 0.22f;
    big.seed = seed + 40;
    big.cells = 6;
    big.rmin = 0.2f;
    big.rmax = 0.42f;
    lapped__dot_layer(&small, x, y, px, rgb);
    lapped__dot_layer(&big, x, y, px, rgb);
}

LAPPEDDEF lapped_result lapped_builtin_exemplar(const char *name, int size, const lapped_options *opt,
                                                lapped_image *out, lapped_error *err)
{
    lapped_options o = lapped__options(opt);
    pw_alloc a = lapped__alloc(&o.allocator);
    pw_image img;
    pw_err pe;
    int x, y, kind = -1;
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (name) kind = !strcmp(name, "scales") ? 0 : !strcmp(name, "stripes") ? 1 : !strcmp(name, "dots") ? 2 : -1;
    if (!out || kind < 0)
        pw_fail(&pe, PW_ERR_INVALID, "unknown built-in texture '%s' (scales, stripes, dots)", name ? name : "(null)");
    else if (size < 8 || size > 4096)
        pw_fail(&pe, PW_ERR_INVALID, "built-in texture size must be 8..4096 (got %d)", size);
    else if (pw_image_alloc(&a, &img, size, size, 3, &pe) == PW_OK) {
        float px = 1.0f / (float)size;
        for (y = 0; y < size; y++)
            for (x = 0; x < size; x++) {
                float u = ((float)x + 0.5f) * px, v = ((float)y + 0.5f) * px, *p = img.px + ((size_t)y * size + x) * 3;
                if (kind == 0) lapped__scales(o.seed, 8.0f * u, 8.0f * v, 8.0f * px, p);
                else if (kind == 1) lapped__stripes(o.seed, u, v, px, p);
                else lapped__dots(o.seed, u, v, px, p);
                p[0] = pw_clampf(p[0], 0.0f, 1.0f);
                p[1] = pw_clampf(p[1], 0.0f, 1.0f);
                p[2] = pw_clampf(p[2], 0.0f, 1.0f);
            }
        lapped__take_image(&img, &a, out);
    }
    return lapped__done(&pe, err);
}
