/* exemplar.c: solid exemplars (§5): sampling, the procedural exemplars of
 * the demos and tests, the §5.2.1 splotch mask and its §5.2.7 outer,
 * middle and inner copies, and the distance fields that let pasting skip
 * the sample points of tetrahedra wholly outside a mask or inside its
 * opaque core. */
#include "core.c"
#include "../common/noise.h"

/* ---- sampling ------------------------------------------------------------------ */

/* Trilinear interpolation of vol's c channels at voxel coordinates (x, y, z)
 * (voxel centres at integers), clamped to the edge voxels. */
static void lst__trilinear(const pw_volume *vol, float x, float y, float z, float *out)
{
    const int X = vol->x, Y = vol->y, Z = vol->z, c = vol->c;
    float fx, fy, fz;
    size_t dx, dy, dz;
    const float *p;
    int x0, y0, z0, k;
    x = x < 0.0f ? 0.0f : (x > X - 1 ? (float)(X - 1) : x);
    y = y < 0.0f ? 0.0f : (y > Y - 1 ? (float)(Y - 1) : y);
    z = z < 0.0f ? 0.0f : (z > Z - 1 ? (float)(Z - 1) : z);
    x0 = (int)x;
    y0 = (int)y;
    z0 = (int)z;
    fx = x - x0;
    fy = y - y0;
    fz = z - z0;
    dx = x0 + 1 < X ? (size_t)c : 0;
    dy = y0 + 1 < Y ? (size_t)X * c : 0;
    dz = z0 + 1 < Z ? (size_t)X * Y * c : 0;
    p = vol->px + (((size_t)z0 * Y + y0) * X + x0) * c;
    for (k = 0; k < c; k++, p++) {
        float a = p[0] + fx * (p[dx] - p[0]), b = p[dy] + fx * (p[dy + dx] - p[dy]);
        float d = p[dz] + fx * (p[dz + dx] - p[dz]), f = p[dz + dy] + fx * (p[dz + dy + dx] - p[dz + dy]);
        a += fy * (b - a);
        d += fy * (f - d);
        out[k] = a + fz * (d - a);
    }
}

/* Trilinear interpolation at texture coordinates (u, v, w) (v = 0 at the
 * bottom row), clamped to the edge voxels; out gets vol->c values. */
static void lst__sample(const pw_volume *vol, double u, double v, double w, float *out)
{
    lst__trilinear(vol, (float)(u * vol->x - 0.5), (float)((1.0 - v) * vol->y - 0.5), (float)(w * vol->z - 0.5), out);
}

/* A mask's alpha at voxel coordinates (x, y, z) (voxel centres at
 * integers; the unit cube spans -0.5 .. size-0.5): trilinear inside, 0
 * outside (the paste ends at the exemplar's faces). Masks have one channel. */
static float lst__mask_alpha_vox(const pw_volume *mask, float x, float y, float z)
{
    float a;
    if (!(x >= -0.5f && x <= mask->x - 0.5f && y >= -0.5f && y <= mask->y - 0.5f && z >= -0.5f && z <= mask->z - 0.5f))
        return 0.0f;
    lst__trilinear(mask, x, y, z, &a);
    return a;
}

/* Texture coordinates to a mask's voxel coordinates. */
static void lst__to_voxel(const pw_volume *mask, double u, double v, double w, float *out)
{
    out[0] = (float)(u * mask->x - 0.5);
    out[1] = (float)((1.0 - v) * mask->y - 0.5);
    out[2] = (float)(w * mask->z - 0.5);
}

/* A mask's alpha at texture coordinates (u, v, w). */
static float lst__mask_alpha(const pw_volume *mask, double u, double v, double w)
{
    float x[3];
    if (!(u >= 0.0 && u <= 1.0 && v >= 0.0 && v <= 1.0 && w >= 0.0 && w <= 1.0)) return 0.0f;
    lst__to_voxel(mask, u, v, w, x);
    return lst__mask_alpha_vox(mask, x[0], x[1], x[2]);
}

/* ---- the procedural exemplars (u, v, w in the unit cube; v = 0 the skin) ----------- */

/* 1-b: a thin skin at v = 0, then strata whose borders wave with u and w. */
static void lst__layers(unsigned long long seed, double u, double v, double w, double *c, double *val)
{
    static const double pal[6][3] = {{0.91, 0.82, 0.62}, {0.72, 0.36, 0.20}, {0.96, 0.93, 0.84},
                                     {0.45, 0.30, 0.22}, {0.80, 0.62, 0.30}, {0.58, 0.60, 0.55}};
    static const double skin[3] = {0.20, 0.32, 0.14};
    double band = v * 6.0 + 0.3 * (pw_fbm3(seed, 2.0 * u, 0.0, 2.0 * w) - 0.5),
           g = pw_fbm3(seed + 7, 24.0 * u, 24.0 * v, 24.0 * w);
    int b = (int)floor(band);
    b = ((b % 6) + 6) % 6;
    pw_mix3(c, pal[b], pal[b], 0.0);
    c[0] *= 0.85 + 0.3 * g;
    c[1] *= 0.85 + 0.3 * g;
    c[2] *= 0.85 + 0.3 * g;
    if (v < 0.035) pw_mix3(c, skin, skin, 0.0);
    *val = v < 0.035 ? 0.5 + 0.4 * (pw_fbm3(seed + 9, 12.0 * u, 0.0, 12.0 * w) - 0.5) : 0.5;
}

/* 1-a: fibres along u (muscle): bundles, cells of a jittered grid in the
 * (v, w) plane (constant along u, as fibres are), each with its own shade
 * and fine streaks, bounded by pale sheaths. */
static void lst__fibers(unsigned long long seed, double u, double v, double w, double *c, double *val)
{
    static const double dark[3] = {0.50, 0.09, 0.11}, light[3] = {0.86, 0.36, 0.34}, sheath[3] = {0.95, 0.88, 0.82};
    const double cells = 7.0;
    double d1 = 9.0, d2 = 9.0, shade = 0.5, streak;
    long cv = (long)floor(v * cells), cw = (long)floor(w * cells), i, k;
    for (i = cv - 1; i <= cv + 1; i++)
        for (k = cw - 1; k <= cw + 1; k++) {
            double pv = (i + 0.15 + 0.7 * pw_lattice01(seed, 0, i, k)) / cells - v;
            double pw_ = (k + 0.15 + 0.7 * pw_lattice01(seed + 1, 0, i, k)) / cells - w;
            double d = sqrt(pv * pv + pw_ * pw_);
            if (d < d1) {
                d2 = d1;
                d1 = d;
                shade = pw_lattice01(seed + 2, 0, i, k);
            } else if (d < d2) d2 = d;
        }
    streak = pw_fbm3(seed + 3, 3.6 * u, 30.0 * v, 30.0 * w);
    pw_mix3(c, dark, light, 0.25 + 0.45 * shade + 0.5 * (streak - 0.5));
    if (d2 - d1 < 0.012) pw_mix3(c, c, sheath, 0.85);
    *val = 0.35 + 0.3 * streak;
}

/* 0: an isotropic aggregate (concrete): stones in a grainy matrix. */
static void lst__spots(unsigned long long seed, double u, double v, double w, double *c, double *val)
{
    static const double matrix[3] = {0.72, 0.70, 0.66},
                        stone[4][3] = {{0.45, 0.40, 0.36}, {0.62, 0.50, 0.38}, {0.30, 0.30, 0.32}, {0.80, 0.74, 0.62}};
    const double cells = 6.0;
    double g = pw_fbm3(seed, 20.0 * u, 20.0 * v, 20.0 * w), best = 1e9;
    long cx = (long)floor(u * cells), cy = (long)floor(v * cells), cz = (long)floor(w * cells), i, j, k, id = 0;
    for (i = cx - 1; i <= cx + 1; i++)
        for (j = cy - 1; j <= cy + 1; j++)
            for (k = cz - 1; k <= cz + 1; k++) { /* a jittered stone per cell, radius 0.3-0.45 cells */
                double px = (i + 0.2 + 0.6 * pw_lattice01(seed, i, j, k)) / cells - u;
                double py = (j + 0.2 + 0.6 * pw_lattice01(seed + 1, i, j, k)) / cells - v;
                double pz = (k + 0.2 + 0.6 * pw_lattice01(seed + 2, i, j, k)) / cells - w;
                double r = (0.3 + 0.15 * pw_lattice01(seed + 3, i, j, k)) / cells,
                       d = sqrt(px * px + py * py + pz * pz) / r;
                if (d < best) {
                    best = d;
                    id = (i * 7 + j * 13 + k * 29) & 3;
                }
            }
    pw_mix3(c, matrix, matrix, 0.0);
    if (best < 1.0) pw_mix3(c, matrix, stone[id], pw_smoothstep(1.0, 0.85, best));
    c[0] *= 0.9 + 0.2 * g;
    c[1] *= 0.9 + 0.2 * g;
    c[2] *= 0.9 + 0.2 * g;
    *val = best < 1.0 ? 0.5 + 0.4 * (1.0 - best) : 0.45 + 0.1 * g;
}

/* 2-b: a tree: bark at v = 0 (furrows along u), cambium, growth rings
 * along v that wobble with w, grain along u, darker heartwood, the pith at
 * v = 1. The extra channel is the bark's relief. */
static void lst__rings(unsigned long long seed, double u, double v, double w, double *c, double *val)
{
    static const double bark[3] = {0.30, 0.21, 0.15}, barkhi[3] = {0.55, 0.47, 0.40}, cambium[3] = {0.80, 0.78, 0.45};
    static const double early[3] = {0.89, 0.72, 0.50}, late[3] = {0.62, 0.38, 0.19}, heart[3] = {0.70, 0.45, 0.26};
    double furrow = pw_noise3(seed + 4, u * 2.0, 0.0, w * 9.0 + 0.6 * pw_noise3(seed + 5, u * 3.0, 0.0, w * 3.0));
    double ridge = 1.0 - fabs(2.0 * furrow - 1.0), phase, ring, grain;
    *val = 0.5 + 0.45 * (ridge - 0.5) * 2.0 * (1.0 - pw_smoothstep(0.05, 0.09, v));
    if (v < 0.075 - 0.025 * ridge) {
        pw_mix3(c, bark, barkhi, ridge * (0.6 + 0.4 * pw_fbm3(seed + 6, 16.0 * u, 16.0 * v, 16.0 * w)));
        return;
    }
    if (v < 0.09) {
        pw_mix3(c, cambium, early, (v - 0.05) / 0.04);
        return;
    }
    phase = v * 11.0 + 0.35 * (pw_fbm3(seed, 1.2 * u, 4.0 * v, 4.0 * w) - 0.5);
    ring = pw_smoothstep(0.55, 0.85, phase - floor(phase)) * (1.0 - pw_smoothstep(0.9, 1.0, phase - floor(phase)));
    grain = pw_fbm3(seed + 8, 3.2 * u, 40.0 * v, 40.0 * w);
    pw_mix3(c, early, late, ring);
    if (v > 0.55) pw_mix3(c, c, heart, pw_smoothstep(0.55, 0.7, v) * 0.6);
    c[0] *= 0.88 + 0.24 * grain;
    c[1] *= 0.88 + 0.24 * grain;
    c[2] *= 0.88 + 0.24 * grain;
    if (v > 0.975) pw_mix3(c, c, late, 0.8);
}

/* 2-b: a kiwi fruit: a fuzzy skin, green flesh that pales inward with
 * radial rays, a ring of black seeds elongated along v (the radius), a
 * pale core near v = 1. The extra channel is the skin's fuzz. */
static void lst__kiwi(unsigned long long seed, double u, double v, double w, double *c, double *val)
{
    static const double skin[3] = {0.42, 0.30, 0.15}, flesh[3] = {0.35, 0.62, 0.10}, pale[3] = {0.66, 0.82, 0.30};
    static const double core[3] = {0.94, 0.93, 0.74}, seedc[3] = {0.06, 0.05, 0.04}, ray[3] = {0.86, 0.92, 0.62};
    const double cells = 17.0;
    double g = pw_fbm3(seed, 18.0 * u, 18.0 * v, 18.0 * w),
           edge = 0.90 + 0.03 * (pw_noise3(seed + 2, u * 6, 0, w * 6) - 0.5);
    double best = 9.0, raydist = 9.0;
    long cu = (long)floor(u * cells), cw = (long)floor(w * cells), i, k;
    *val = v < 0.04 ? 0.5 + 0.45 * (pw_fbm3(seed + 3, 30.0 * u, 0.0, 30.0 * w) - 0.5) : 0.5;
    if (v < 0.028 + 0.01 * g) {
        pw_mix3(c, skin, skin, 0.0);
        c[0] *= 0.8 + 0.4 * g;
        c[1] *= 0.8 + 0.4 * g;
        c[2] *= 0.8 + 0.4 * g;
        return;
    }
    if (v > edge) {
        pw_mix3(c, core, pale, 0.3 * g);
        return;
    }
    for (i = cu - 1; i <= cu + 1; i++)
        for (k = cw - 1; k <= cw + 1; k++) { /* a seed (and a ray) per jittered cell of the (u, w) plane */
            double su = (i + 0.2 + 0.6 * pw_lattice01(seed, i, 0, k)) / cells - u;
            double sw = (k + 0.2 + 0.6 * pw_lattice01(seed + 1, i, 0, k)) / cells - w;
            double sv = 0.80 + 0.05 * (pw_lattice01(seed + 4, i, 0, k) - 0.5) - v;
            double d = sqrt((su / 0.026) * (su / 0.026) + (sv / 0.055) * (sv / 0.055) + (sw / 0.02) * (sw / 0.02));
            double r = sqrt(su * su + sw * sw);
            if (d < best) best = d;
            if (r < raydist) raydist = r;
        }
    pw_mix3(c, flesh, pale, pw_smoothstep(0.1, 0.85, v) * 0.75 + 0.25 * g);
    if (v > 0.4 && raydist < 0.008) pw_mix3(c, c, ray, 0.75 * pw_smoothstep(0.4, 0.7, v));
    if (v > 0.7) pw_mix3(c, c, core, 0.35 * pw_smoothstep(0.7, edge, v));
    if (best < 1.0) pw_mix3(c, c, seedc, pw_smoothstep(1.0, 0.7, best));
}

typedef void (*lst__exemplar_fn)(unsigned long long seed, double u, double v, double w, double *c, double *val);

static lst__exemplar_fn lst__exemplar_by_name(const char *name)
{
    if (!strcmp(name, "layers")) return lst__layers;
    if (!strcmp(name, "fibers")) return lst__fibers;
    if (!strcmp(name, "spots")) return lst__spots;
    if (!strcmp(name, "rings")) return lst__rings;
    if (!strcmp(name, "kiwi")) return lst__kiwi;
    return NULL;
}

static int lst__fill_exemplar(lst__exemplar_fn fn, unsigned long long seed, pw_volume *col, pw_volume *val)
{
    int x, y, z, n = col->x, k;
    for (z = 0; z < n; z++)
        for (y = 0; y < n; y++)
            for (x = 0; x < n; x++) {
                double c[3], v, u = (x + 0.5) / n, vv = 1.0 - (y + 0.5) / n, w = (z + 0.5) / n;
                size_t at = ((size_t)z * n + y) * n + x;
                fn(seed, u, vv, w, c, &v);
                for (k = 0; k < 3; k++) col->px[3 * at + k] = pw_clampf((float)c[k], 0.0f, 1.0f);
                if (val) val->px[at] = pw_clampf((float)v, 0.0f, 1.0f);
            }
    return PW_OK;
}

LSTDEF lst_result lst_builtin_exemplar(const char *name, int size, const lst_options *opt, lst_volume *color,
                                       lst_volume *values, lst_error *err)
{
    lst_options o = lst__options(opt);
    pw_alloc a = lst__alloc(&o.allocator);
    pw_volume col, val;
    lst__exemplar_fn fn = name ? lst__exemplar_by_name(name) : NULL;
    pw_err e;
    pw_err_clear(&e);
    memset(&col, 0, sizeof col);
    memset(&val, 0, sizeof val);
    if (color) memset(color, 0, sizeof *color);
    if (values) memset(values, 0, sizeof *values);
    if (size == 0) size = 64;
    if (!color) pw_fail(&e, PW_ERR_INVALID, "lst_builtin_exemplar: NULL output");
    else if (!fn)
        pw_fail(&e, PW_ERR_INVALID, "unknown built-in exemplar '%s' (layers, fibers, spots, rings, kiwi)",
                name ? name : "(null)");
    else if (size < 4 || size > 512) pw_fail(&e, PW_ERR_INVALID, "exemplar size %d is outside 4..512", size);
    else if (pw_volume_alloc(&a, &col, 3, size, size, size, &e) == PW_OK &&
             (!values || pw_volume_alloc(&a, &val, 1, size, size, size, &e) == PW_OK)) {
        lst__fill_exemplar(fn, o.seed, &col, values ? &val : NULL);
        lst__take_volume(&col, &a, color);
        if (values) lst__take_volume(&val, &a, values);
    }
    pw_volume_free(&a, &col);
    pw_volume_free(&a, &val);
    return lst__done(&e, err);
}

/* ---- masks (§5.2.1, §5.2.7) ------------------------------------------------------------- */

/* The splotch's radius toward unit direction d: a sphere of mean radius r
 * with eight smooth lobes and dents (±12%) at directions drawn from the
 * seed, so that the pastes' borders do not line up. */
static double lst__splotch_radius(const double *lobes, double r, const double *d)
{
    double s = 1.0;
    int k;
    for (k = 0; k < 8; k++) {
        double c = pw_dot3(lobes + 4 * k, d), t = c > 0.5 ? (c - 0.5) / 0.5 : 0.0;
        s += lobes[4 * k + 3] * t * t * (3.0 - 2.0 * t);
    }
    return r * s;
}

static void lst__splotch_lobes(unsigned long long seed, double *lobes)
{
    pw_rng rng = pw_rng_seed(seed, 0x5107C4);
    int k;
    for (k = 0; k < 8; k++) {
        double *l = lobes + 4 * k, n2;
        do {
            l[0] = 2.0 * pw_rng_double(&rng) - 1.0;
            l[1] = 2.0 * pw_rng_double(&rng) - 1.0;
            l[2] = 2.0 * pw_rng_double(&rng) - 1.0;
            n2 = pw_dot3(l, l);
        } while (n2 > 1.0 || n2 < 1e-4);
        pw_norm3(l);
        l[3] = 0.24 * pw_rng_double(&rng) - 0.12;
    }
}

/* Fills mask with the splotch centred at texture coordinates centre: alpha
 * 1 inside, a smooth fall-off of width `falloff` (fraction of the side) at
 * the border, 0 outside. */
static void lst__splotch(pw_volume *mask, const double *lobes, double radius, double falloff, const double *centre)
{
    double top = 1.0, cap = 0.5 - 0.5 / mask->x, rmax; /* cap: the radius stays inside the cube's sides */
    int x, y, z, k;
    float *px = mask->px;
    for (k = 0; k < 8; k++) top += lobes[4 * k + 3] > 0.0 ? lobes[4 * k + 3] : 0.0;
    rmax = (radius * top < cap ? radius * top : cap) * (1.0 + 1e-9); /* no radius reaches it */
    for (z = 0; z < mask->z; z++)
        for (y = 0; y < mask->y; y++)
            for (x = 0; x < mask->x; x++, px++) {
                double d[3], len, r;
                d[0] = (x + 0.5) / mask->x - centre[0];
                d[1] = 1.0 - (y + 0.5) / mask->y - centre[1];
                d[2] = (z + 0.5) / mask->z - centre[2];
                len = pw_norm3(d);
                if (len > rmax) { /* beyond every lobe: the fall-off gives 0 */
                    *px = 0.0f;
                    continue;
                }
                r = len > 0.0 ? lst__splotch_radius(lobes, radius, d) : radius;
                if (r > cap) r = cap;
                *px = (float)pw_smoothstep(r, r - falloff, len);
            }
}

/* The number of masks a type uses: three layers for depth-varying types. */
static int lst__mask_count(int type) { return lst__depth_varying(type) ? 3 : 1; }

/* §5.2.7: which mask a paste seeded at depth d uses (0 outer, 1 middle,
 * 2 inner); the centres along v below keep each third inside its core. */
static int lst__mask_for_depth(double d) { return d < 1.0 / 3.0 ? 0 : (d < 2.0 / 3.0 ? 1 : 2); }
static const double lst__layer_centre[3] = {0.15, 0.5, 0.85};

static int lst__use_exemplar_alpha(const lst_options *o, const lst_volume *ex)
{
    if (lst__depth_varying(o->type)) return 0;
    if (o->mask == LST_MASK_EXEMPLAR) return 1;
    return o->mask == LST_MASK_AUTO && (ex->channels == 2 || ex->channels == 4);
}

/* The masks of an exemplar (§5.2.1): its alpha, or the splotch (three
 * copies along v for depth-varying types, §5.2.7, Fig. 14). */
static int lst__masks(const pw_alloc *a, const lst_volume *ex, const lst_options *o, pw_volume *masks, int *count,
                      pw_err *e)
{
    double lobes[32], centre[3] = {0.5, 0.5, 0.5};
    int k, n = lst__mask_count(o->type);
    size_t i, nvox = (size_t)ex->width * ex->height * ex->depth;
    if (o->mask == LST_MASK_EXEMPLAR && (lst__depth_varying(o->type) || (ex->channels != 2 && ex->channels != 4)))
        return pw_fail(e, PW_ERR_INVALID,
                       "the exemplar's alpha as mask needs an exemplar with alpha and a "
                       "homogeneous type (0, 1-a, 2-a)");
    lst__splotch_lobes(o->seed, lobes);
    *count = 0;
    for (k = 0; k < n; k++) {
        if (pw_volume_alloc(a, &masks[k], 1, ex->width, ex->height, ex->depth, e)) return PW_ERR_NOMEM;
        *count = k + 1;
        if (lst__use_exemplar_alpha(o, ex)) {
            for (i = 0; i < nvox; i++)
                masks[k].px[i] = pw_clampf(ex->voxels[i * ex->channels + ex->channels - 1], 0, 1);
            continue;
        }
        if (n == 3) centre[1] = lst__layer_centre[k];
        lst__splotch(&masks[k], lobes, o->mask_radius, o->falloff, centre);
    }
    return PW_OK;
}

/* The masks of an exemplar into out (empty on failure). */
static int lst__make_masks(const pw_alloc *a, const lst_volume *ex, const lst_options *o, lst_masks *out, pw_err *e)
{
    pw_volume m[3];
    int n = 0, k, r;
    memset(m, 0, sizeof m);
    r = lst__masks(a, ex, o, m, &n, e);
    if (r == PW_OK && !(out->volumes = (lst_volume *)pw_calloc_array(a, (size_t)n, sizeof(lst_volume), "masks", e)))
        r = PW_ERR_NOMEM;
    for (k = 0; k < n; k++) {
        if (r == PW_OK) lst__take_volume(&m[k], a, &out->volumes[k]);
        pw_volume_free(a, &m[k]);
    }
    if (r == PW_OK) {
        out->count = n;
        out->allocator = lst__allocator(a);
    }
    return r;
}

LSTDEF lst_result lst_make_masks(const lst_volume *exemplar, const lst_options *opt, lst_masks *out, lst_error *err)
{
    lst_options o = lst__options(opt);
    pw_alloc a = lst__alloc(&o.allocator);
    pw_err e;
    pw_err_clear(&e);
    if (out) memset(out, 0, sizeof *out);
    if (!out) pw_fail(&e, PW_ERR_INVALID, "lst_make_masks: NULL output");
    else if (lst__check_options(&o, &e) == PW_OK && lst__check_volume(exemplar, "exemplar", &e) == PW_OK)
        lst__make_masks(&a, exemplar, &o, out, &e);
    return lst__done(&e, err);
}

/* ---- distance fields of a mask ------------------------------------------------------------ */

/* dist[i] = distance, in texture units (of the largest side), from voxel
 * i to the nearest voxel with alpha > 0 (want_positive) or with alpha < 1:
 * the shared exact transform (edt.h) along x, y and z in turn. */
static int lst__edt(const pw_alloc *a, const pw_volume *mask, int want_positive, float *dist, pw_err *e)
{
    int X = mask->x, Y = mask->y, Z = mask->z, big = pw_maxi(X, pw_maxi(Y, Z)), z;
    size_t total = (size_t)X * Y * Z, k;
    pw__edt_ws ws;
    float *f = (float *)pw_alloc_array(a, (size_t)big * 2, sizeof(float), "distance transform", e);
    int *v = (int *)pw_alloc_array(a, (size_t)big, sizeof(int), "distance transform", e);
    double *zz = (double *)pw_alloc_array(a, (size_t)big + 1, sizeof(double), "distance transform", e);
    if (!f || !v || !zz) {
        pw_free(a, f);
        pw_free(a, v);
        pw_free(a, zz);
        return PW_ERR_NOMEM;
    }
    for (k = 0; k < total; k++) { /* 0 on the sites, "far" elsewhere */
        int hit = want_positive ? mask->px[k] > 0.0f : mask->px[k] < 1.0f;
        dist[k] = hit ? 0.0f : PW_EDT_FAR;
    }
    ws.f = f;
    ws.d = f + big;
    ws.v = v;
    ws.z = zz;
    ws.wrap = 0;
    pw__edt_sites(dist, X, Y * Z, (size_t)X, 1);
    for (z = 0; z < Z; z++) pw__edt_pass(dist + (size_t)z * X * Y, Y, X, 1, (size_t)X, &ws);
    pw__edt_pass(dist, Z, X * Y, 1, (size_t)X * Y, &ws);
    for (k = 0; k < total; k++) dist[k] = dist[k] >= PW_EDT_FAR ? 1e6f : (float)(sqrt((double)dist[k]) / big);
    pw_free(a, f);
    pw_free(a, v);
    pw_free(a, zz);
    return PW_OK;
}

/* What pasting knows about one mask: the volume, and per voxel the
 * distance to the nearest voxel with alpha > 0 (out) and to the nearest
 * with alpha < 1 or the cube's outside (in). out only ever clears regions
 * (what it clears has no alpha, and what it does not is sampled), so a
 * lower bound does: out8 * ostep, a byte a voxel, which keeps the lookups
 * in cache (the exact floats were a tenth of the fill in cache misses). in
 * decides the opaque core, which the result shows, so it stays exact. */
typedef struct lst__mask {
    pw_volume vol;
    unsigned char *out8; /* per voxel: out8 * ostep <= out */
    double ostep;
    float *in;
    unsigned char *cell; /* a bit per voxel: 1 if trilinear alpha is > 0 somewhere in the cell it starts */
    unsigned *sum;       /* (x+1)(y+1)(z+1): the cells' bits summed over [0, x) x [0, y) x [0, z) (4 bytes a voxel) */
    float hi[3];         /* the volume's sides less half a voxel: where lookups stop */
    double margin;       /* how far trilinear interpolation and the nearest-voxel lookup reach */
} lst__mask;

static void lst__mask_free(const pw_alloc *a, lst__mask *m)
{
    pw_free(a, m->out8);
    pw_free(a, m->in);
    pw_free(a, m->cell);
    pw_free(a, m->sum);
    m->in = NULL;
    m->sum = NULL;
    m->out8 = m->cell = NULL;
}

/* Bit [x,y,z] of cell (voxel index i: byte i / 8, bit i % 8) is 1 when
 * one of the 8 voxels that trilinear interpolation blends between (x, y,
 * z) and (x+1, y+1, z+1) (clamped) has alpha > 0: then, and only then,
 * alpha can be > 0 in that cell. cell starts zeroed. */
static void lst__mask_cells(const pw_volume *v, unsigned char *cell)
{
    int x, y, z, i, j, k;
    size_t at = 0;
    for (z = 0; z < v->z; z++)
        for (y = 0; y < v->y; y++)
            for (x = 0; x < v->x; x++, at++) {
                unsigned char any = 0;
                for (k = 0; k < 2; k++)
                    for (j = 0; j < 2; j++)
                        for (i = 0; i < 2; i++) {
                            int X = pw_mini(x + i, v->x - 1), Y = pw_mini(y + j, v->y - 1),
                                Z = pw_mini(z + k, v->z - 1);
                            any |= v->px[((size_t)Z * v->y + Y) * v->x + X] > 0.0f;
                        }
                cell[at >> 3] = (unsigned char)(cell[at >> 3] | any << (at & 7));
            }
}

/* Whether alpha is > 0 at voxel coordinates (x, y, z) of mask m (exactly
 * as lst__mask_alpha_vox would say), from one byte of its cells. Inside
 * [-0.5, side - 0.5] truncation is the clamp to the voxels (a coordinate
 * in [-0.5, 0) gives 0, one above side - 1 gives side - 1). Inline: it is
 * called for every sample point of growth and coverage, and the call cost
 * 3% of the kiwi's fill (callgrind). */
static inline int lst__cell_any(const lst__mask *m, float x, float y, float z)
{
    size_t i;
    if (!(x >= -0.5f && x <= m->hi[0] && y >= -0.5f && y <= m->hi[1] && z >= -0.5f && z <= m->hi[2])) return 0;
    i = ((size_t)(int)z * m->vol.y + (int)y) * m->vol.x + (int)x;
    return m->cell[i >> 3] >> (i & 7) & 1;
}

/* m->sum from m->cell: a summed-volume table (unsigned arithmetic: the
 * differences of lst__cells_in_box are exact modulo 2^32, and no count
 * reaches it). */
static void lst__mask_sums(lst__mask *m)
{
    const int X = m->vol.x, Y = m->vol.y, Z = m->vol.z;
    const size_t sy = (size_t)X + 1, sz = sy * ((size_t)Y + 1);
    size_t i = 0;
    int x, y, z;
    memset(m->sum, 0, sizeof(unsigned) * sz);
    for (z = 0; z < Z; z++) {
        unsigned *s = m->sum + (size_t)(z + 1) * sz;
        memset(s, 0, sizeof(unsigned) * sy);
        for (y = 0; y < Y; y++) {
            s[(size_t)(y + 1) * sy] = 0;
            for (x = 0; x < X; x++, i++) {
                unsigned bit = m->cell[i >> 3] >> (i & 7) & 1u;
                const size_t at = (size_t)(y + 1) * sy + (size_t)x + 1;
                const unsigned *below = s - sz; /* the plane z */
                s[at] = bit + s[at - 1] + s[at - sy] - s[at - 1 - sy] + below[at] - below[at - 1] - below[at - sy] +
                        below[at - 1 - sy];
            }
        }
    }
}

/* 0 when no point of the box lo..hi (voxel coordinates) is inside the
 * mask as lst__cell_any tells it: no cell of the box has its bit (the
 * coordinates outside [-0.5, side - 0.5] are never inside, the others
 * truncate to their cell). 1 when one has, or the box is not finite. */
static int lst__cells_in_box(const lst__mask *m, const float *lo, const float *hi)
{
    const size_t sy = (size_t)m->vol.x + 1, sz = sy * ((size_t)m->vol.y + 1);
    const unsigned *far, *near; /* the planes z = b and z = a of the table */
    size_t a[3], b[3];
    int k;
    for (k = 0; k < 3; k++) {
        if (!(lo[k] <= hi[k])) return 1; /* NaN */
        if (hi[k] < -0.5f || lo[k] > m->hi[k]) return 0;
        a[k] = lo[k] < 0.0f ? 0 : (size_t)lo[k];
        b[k] = (size_t)(hi[k] < m->hi[k] ? hi[k] : m->hi[k]) + 1;
    }
    far = m->sum + b[2] * sz;
    near = m->sum + a[2] * sz;
    return far[b[1] * sy + b[0]] - far[b[1] * sy + a[0]] - far[a[1] * sy + b[0]] + far[a[1] * sy + a[0]] -
               (near[b[1] * sy + b[0]] - near[b[1] * sy + a[0]] - near[a[1] * sy + b[0]] + near[a[1] * sy + a[0]]) !=
           0u;
}

/* out8 and ostep from the exact distances d: the largest multiple of
 * ostep (1/255 of the largest distance) that is not above each. */
static void lst__quantise_out(const float *d, size_t total, lst__mask *m)
{
    float top = 0.0f;
    size_t k;
    for (k = 0; k < total; k++) top = d[k] > top ? d[k] : top;
    m->ostep = top > 0.0f ? top / 255.0 : 1.0;
    for (k = 0; k < total; k++) {
        int q = (int)(d[k] / m->ostep);
        q = q > 255 ? 255 : q;
        while (q > 0 && q * m->ostep > d[k]) q--;
        m->out8[k] = (unsigned char)q;
    }
}

static int lst__mask_init(const pw_alloc *a, const pw_volume *vol, lst__mask *m, pw_err *e)
{
    size_t total = (size_t)vol->x * vol->y * vol->z;
    int x, y, z, r = PW_OK;
    float *out = (float *)pw_alloc_array(a, total, sizeof(float), "mask distances", e);
    m->vol = *vol;
    m->out8 = (unsigned char *)pw_alloc_array(a, total, 1, "mask distances", e);
    m->in = (float *)pw_alloc_array(a, total, sizeof(float), "mask distances", e);
    m->cell = (unsigned char *)pw_calloc_array(a, total / 8 + 1, 1, "mask cells", e);
    m->sum = (unsigned *)pw_alloc_array(a, ((size_t)vol->x + 1) * (vol->y + 1) * (vol->z + 1), sizeof(unsigned),
                                        "mask cells", e);
    m->margin = 2.6 / pw_mini(vol->x, pw_mini(vol->y, vol->z));
    m->hi[0] = (float)vol->x - 0.5f;
    m->hi[1] = (float)vol->y - 0.5f;
    m->hi[2] = (float)vol->z - 0.5f;
    if (!out || !m->out8 || !m->in || !m->cell || !m->sum) r = PW_ERR_NOMEM;
    if (r == PW_OK && (lst__edt(a, vol, 1, out, e) || lst__edt(a, vol, 0, m->in, e))) r = e->code;
    if (r == PW_OK) lst__quantise_out(out, total, m);
    pw_free(a, out);
    if (r != PW_OK) {
        lst__mask_free(a, m);
        return r;
    }
    for (z = 0; z < vol->z; z++) /* the cube's outside is not core: distance to the faces */
        for (y = 0; y < vol->y; y++)
            for (x = 0; x < vol->x; x++) {
                size_t k = ((size_t)z * vol->y + y) * vol->x + x;
                double f = pw_mini(pw_mini(x, vol->x - 1 - x),
                                   pw_mini(pw_mini(y, vol->y - 1 - y), pw_mini(z, vol->z - 1 - z)));
                f = (f + 0.5) / pw_maxi(vol->x, pw_maxi(vol->y, vol->z));
                if (f < m->in[k]) m->in[k] = (float)f;
            }
    lst__mask_cells(vol, m->cell);
    lst__mask_sums(m);
    return PW_OK;
}

/* The index of the voxel nearest to (u, v, w), the point first clamped
 * into the cube. */
static size_t lst__mask_voxel(const lst__mask *m, double u, double v, double w)
{
    int x = pw_clampi((int)(u * m->vol.x), 0, m->vol.x - 1),
        y = pw_clampi((int)((1.0 - v) * m->vol.y), 0, m->vol.y - 1);
    int z = pw_clampi((int)(w * m->vol.z), 0, m->vol.z - 1);
    return ((size_t)z * m->vol.y + y) * m->vol.x + x;
}

/* Whether the out distance (its lower bound) at (u, v, w) exceeds lim:
 * no alpha within lim of that voxel. */
static int lst__mask_clear(const lst__mask *m, double u, double v, double w, double lim)
{
    return m->out8[lst__mask_voxel(m, u, v, w)] * m->ostep > lim;
}
