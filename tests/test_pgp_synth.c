/* Tests of pgp.h's material-space tile synthesis (§1): the shared modules
 * it brings (exact periodic distance transform, kd-tree with penalties,
 * PCA) against brute force, the §1.1 mask morph (ends exact, monotone,
 * speed-adaptive), the §1.2 synthesis and the whole tile (every layer
 * tiles, the ends are the keys, colour histograms kept), single-tile mode,
 * real GIMP exemplars, key sizes, determinism, bad input, cancelling and an
 * allocation-failure sweep. The implementation is compiled in where a test
 * looks inside (the syntheses from each end of a morph before blending).
 *
 * Colour metric used throughout (hist_dist): per channel, the earth mover's
 * distance between the two distributions of sample values, W1 = sum over
 * 256 bins of |CDF_a - CDF_b| / 256 (the mean shift of the values, in units
 * of the [0,1] range), averaged over the channels. */
#define PGP_STATIC /* static: only what the tests call is compiled */
#define PGP_IMPLEMENTATION
#include "pgp.h"
#include "pwtest.h"

/* ---- helpers --------------------------------------------------------------- */

static pgp_image make_image(int w, int h, int c)
{
    pgp_image im;
    memset(&im, 0, sizeof im);
    im.width = w, im.height = h, im.channels = c;
    im.pixels = (float *)calloc((size_t)w * h * c, sizeof(float));
    return im;
}

/* Periodic value noise in [0,1) from a hash of the lattice cell. */
static float noise(int x, int y, unsigned seed)
{
    return (float)(pw_hash64(seed, (uint64_t)(y * 7919 + x)) >> 40) / 16777216.0f;
}

/* Spots: dark discs of radius r on a torus of side n, 3 per row and
 * column with jitter, on a light background; colour (orange / dark brown)
 * with a little noise. Mask: the discs. */
static void spots(int n, float r, unsigned seed, pgp_image *img, pgp_image *mask)
{
    int x, y, i, j, k = 3;
    *img = make_image(n, n, 3);
    *mask = make_image(n, n, 1);
    for (y = 0; y < n; y++)
        for (x = 0; x < n; x++) {
            float in = 0.0f, *p = img->pixels + 3 * ((size_t)y * n + x), t = 0.15f * noise(x, y, seed);
            for (j = 0; j < k; j++)
                for (i = 0; i < k; i++) {
                    float cx = (i + 0.5f + 0.4f * (noise(i, j, seed + 1) - 0.5f)) * n / k;
                    float cy = (j + 0.5f + 0.4f * (noise(i, j, seed + 2) - 0.5f)) * n / k;
                    float dx = fabsf(x + 0.5f - cx), dy = fabsf(y + 0.5f - cy);
                    dx = dx > n / 2 ? n - dx : dx, dy = dy > n / 2 ? n - dy : dy;
                    if (dx * dx + dy * dy < r * r) in = 1.0f;
                }
            mask->pixels[(size_t)y * n + x] = in;
            p[0] = in ? 0.15f + t : 0.85f + t;
            p[1] = in ? 0.1f + t : 0.55f + t;
            p[2] = in ? 0.05f + t : 0.25f + t;
        }
}

/* Stripes along x, `period` texels, half of them dark; blue-grey. */
static void stripes(int n, int period, unsigned seed, pgp_image *img, pgp_image *mask)
{
    int x, y;
    *img = make_image(n, n, 3);
    *mask = make_image(n, n, 1);
    for (y = 0; y < n; y++)
        for (x = 0; x < n; x++) {
            float in = (float)((y % period) < period / 2), t = 0.15f * noise(x, y, seed), *p = img->pixels + 3 * ((size_t)y * n + x);
            mask->pixels[(size_t)y * n + x] = in;
            p[0] = in ? 0.1f + t : 0.7f + t;
            p[1] = in ? 0.15f + t : 0.75f + t;
            p[2] = in ? 0.3f + t : 0.85f + t;
        }
}

/* Layer k of a tile as an image view (no copy). */
static pgp_image layer(const pgp_tile *t, int k)
{
    pgp_image im;
    memset(&im, 0, sizeof im);
    im.width = t->width, im.height = t->height, im.channels = t->channels;
    im.pixels = t->pixels + (size_t)k * t->width * t->height * t->channels;
    return im;
}

/* The colour metric of the top of this file. */
static double hist_dist(const pgp_image *a, const pgp_image *b)
{
    double s = 0.0;
    int c, k, ch = a->channels < b->channels ? a->channels : b->channels;
    for (c = 0; c < ch; c++) {
        double ha[256] = {0}, hb[256] = {0}, ca = 0.0, cb = 0.0;
        size_t i, na = (size_t)a->width * a->height, nb = (size_t)b->width * b->height;
        for (i = 0; i < na; i++) ha[pw_clampi((int)(a->pixels[i * a->channels + c] * 256.0f), 0, 255)] += 1.0 / na;
        for (i = 0; i < nb; i++) hb[pw_clampi((int)(b->pixels[i * b->channels + c] * 256.0f), 0, 255)] += 1.0 / nb;
        for (k = 0; k < 256; k++) {
            ca += ha[k], cb += hb[k];
            s += fabs(ca - cb) / 256.0;
        }
    }
    return s / ch;
}

/* Mean absolute difference between columns (dx = 1) or rows i and j. */
static double line_diff(const pgp_image *im, int dx, int i, int j)
{
    int n = dx ? im->height : im->width, k, c;
    double s = 0.0;
    for (k = 0; k < n; k++)
        for (c = 0; c < im->channels; c++) {
            size_t p = dx ? (size_t)k * im->width + i : (size_t)i * im->width + k;
            size_t q = dx ? (size_t)k * im->width + j : (size_t)j * im->width + k;
            s += fabs(im->pixels[p * im->channels + c] - im->pixels[q * im->channels + c]);
        }
    return s / ((double)n * im->channels);
}

/* The seam test, per direction (dx = 1: columns): the wrap-around
 * difference (last column vs first) over the largest difference between
 * neighbouring interior columns. */
static double seam_dir(const pgp_image *im, int dx)
{
    int n = dx ? im->width : im->height, i;
    double mx = 0.0;
    for (i = 0; i + 1 < n; i++) {
        double d = line_diff(im, dx, i, i + 1);
        mx = d > mx ? d : mx;
    }
    return line_diff(im, dx, n - 1, 0) / (mx > 1e-9 ? mx : 1e-9);
}

/* The larger ratio of the two directions. */
static double seam_ratio(const pgp_image *im)
{
    double r0 = seam_dir(im, 0), r1 = seam_dir(im, 1);
    return r0 > r1 ? r0 : r1;
}

/* The colour metric restricted to the texels of one mask class (features
 * when cls = 1): output texels where `mask` (0/1 bytes) is cls against
 * input texels where `imask` is cls. */
static double class_dist(const pgp_image *out, const unsigned char *mask, const pgp_image *in,
                         const unsigned char *imask, int cls)
{
    pgp_image a = make_image(1, 1, in->channels), b = make_image(1, 1, in->channels);
    size_t i, na = 0, nb = 0, n = (size_t)out->width * out->height, m = (size_t)in->width * in->height;
    double d;
    free(a.pixels), free(b.pixels);
    a.pixels = (float *)malloc(sizeof(float) * n * in->channels);
    b.pixels = (float *)malloc(sizeof(float) * m * in->channels);
    for (i = 0; i < n; i++)
        if ((mask[i] != 0) == cls) memcpy(a.pixels + na++ * in->channels, out->pixels + i * in->channels, sizeof(float) * in->channels);
    for (i = 0; i < m; i++)
        if ((imask[i] != 0) == cls) memcpy(b.pixels + nb++ * in->channels, in->pixels + i * in->channels, sizeof(float) * in->channels);
    a.height = (int)na, b.height = (int)nb;
    d = na && nb ? hist_dist(&a, &b) : 0.0;
    pgp_image_free(&a), pgp_image_free(&b);
    return d;
}

static long mask_diff(const pgp_tile *m, int a, int b)
{
    size_t i, nn = (size_t)m->width * m->height;
    long d = 0;
    for (i = 0; i < nn; i++) d += (m->pixels[a * nn + i] > 0.5f) != (m->pixels[b * nn + i] > 0.5f);
    return d;
}

/* ---- shared modules --------------------------------------------------------- */

/* edt.h: squared distances equal brute force (minimum over all sites, with
 * the torus metric when wrapping) on random masks of several densities. */
static void t_edt_brute_force(void)
{
    int w = 37, h = 23, wrap, trial, x, y, bad = 0;
    unsigned char site[37 * 23];
    float d[37 * 23];
    pw_edt_image im;
    for (trial = 0; trial < 6; trial++)
        for (wrap = 0; wrap < 2; wrap++) {
            for (x = 0; x < w * h; x++) site[x] = noise(x, trial, 9) < 0.02f * (trial + 1) * (trial + 1) * 0.3f;
            site[(trial * 131) % (w * h)] = 1;
            im.px = site, im.w = w, im.h = h, im.wrap = wrap;
            CHECK(pw_edt_sq(NULL, &im, d, NULL) == PW_OK);
            for (y = 0; y < h; y++)
                for (x = 0; x < w; x++) {
                    float best = FLT_MAX;
                    int s;
                    for (s = 0; s < w * h; s++)
                        if (site[s]) {
                            int dx = abs(s % w - x), dy = abs(s / w - y);
                            if (wrap) dx = dx < w - dx ? dx : w - dx, dy = dy < h - dy ? dy : h - dy;
                            if ((float)(dx * dx + dy * dy) < best) best = (float)(dx * dx + dy * dy);
                        }
                    bad += d[y * w + x] != best;
                }
        }
    CHECKF(bad == 0, "%d distances differ from brute force", bad);
}

/* edt.h's first pass over binary lines (two sweeps) gives the parabolas'
 * values bit for bit: lines of 1 to 40 pixels, strided, with no site, one,
 * several and all. */
static void t_edt_sites_pass(void)
{
    float a[2 * 40], b[2 * 40], f[80], d[80];
    double z[81];
    int v[80], n, trial, i, bad = 0;
    pw__edt_ws ws;
    ws.f = f, ws.d = d, ws.v = v, ws.z = z, ws.wrap = 0;
    for (n = 1; n <= 40; n++)
        for (trial = 0; trial < 8; trial++) {
            for (i = 0; i < 2 * n; i++) {
                float p = trial == 0 ? 0.0f : trial == 7 ? 1.0f : 0.04f * trial * trial;
                a[i] = b[i] = noise(i, n, trial) < p ? 0.0f : PW_EDT_FAR;
            }
            pw__edt_pass(a, n, 1, 0, 2, &ws); /* every other element */
            pw__edt_sites(b, n, 1, 0, 2);
            for (i = 0; i < 2 * n; i++) bad += memcmp(&a[i], &b[i], sizeof(float)) != 0;
        }
    CHECKF(bad == 0, "%d values of the two-sweep pass differ from the parabolas'", bad);
}

/* pw_edt_signed: positive exactly inside, |phi| = distance to the other
 * kind - 1/2; a disc's signed distance is its radius minus the distance to
 * the centre within a texel. */
static void t_edt_signed_disc(void)
{
    int n = 64, x, y, bad = 0;
    unsigned char m[64 * 64];
    float phi[64 * 64], worst = 0.0f;
    pw_edt_image im;
    for (y = 0; y < n; y++)
        for (x = 0; x < n; x++) m[y * n + x] = (x - 31.5f) * (x - 31.5f) + (y - 31.5f) * (y - 31.5f) < 15.0f * 15.0f;
    im.px = m, im.w = im.h = n, im.wrap = 1;
    CHECK(pw_edt_signed(NULL, &im, phi, NULL) == PW_OK);
    for (y = 0; y < n; y++)
        for (x = 0; x < n; x++) {
            float r = sqrtf((x - 31.5f) * (x - 31.5f) + (y - 31.5f) * (y - 31.5f)), err = fabsf(phi[y * n + x] - (15.0f - r));
            bad += (phi[y * n + x] > 0.0f) != (m[y * n + x] != 0);
            worst = err > worst ? err : worst;
        }
    CHECK_EQ_INT(bad, 0);
    CHECKF(worst < 1.0f, "signed distance of a disc off by %g texels", worst);
}

/* kdtree.h: the nearest point under |q-p|^2 + pen equals brute force, with
 * penalties changed between queries; eps bounds the approximation; a
 * search limited to a few buckets ends no worse than where it started;
 * ties keep the starting candidate. */
static void t_kdtree_penalties(void)
{
    pw_kdtree t;
    pw_kdquery qy;
    pw_rng r = pw_rng_seed(5, 1);
    int n = 3000, d = 6, i, k, qn, bad = 0, worse = 0, dup;
    float *p = (float *)malloc(sizeof(float) * n * d), *pen = (float *)calloc((size_t)n, sizeof(float)), q[6], off[6];
    for (i = 0; i < n * d; i++) p[i] = (float)(i / d % 7 == 0 ? 0.25 : pw_rng_float(&r)); /* duplicate points too */
    REQUIRE(pw_kdtree_build(NULL, &t, p, n, d, NULL) == PW_OK);
    for (qn = 0; qn < 400; qn++) {
        float best = FLT_MAX, got, c;
        int bi = -1, u;
        for (k = 0; k < 20; k++) {
            int j = (int)pw_rng_below(&r, (uint32_t)n);
            pen[j] = 0.05f * pw_rng_float(&r);
            pw_kdtree_set_penalty(&t, j, pen[j]);
        }
        for (k = 0; k < d; k++) q[k] = pw_rng_float(&r);
        for (i = 0; i < n; i++) {
            for (k = 0, c = pen[i]; k < d; k++) c += (q[k] - p[i * d + k]) * (q[k] - p[i * d + k]);
            if (c < best) best = c, bi = i;
        }
        qy.q = q, qy.eps = 0.0f, qy.buckets = -1, qy.start = -1, qy.start_cost = 0.0f, qy.off = off;
        u = pw_kdtree_nearest(&t, &qy, &got);
        bad += got != best || (u != bi && pw_kdtree_cost(&t, q, u) != best);
        qy.eps = 1.0f;
        pw_kdtree_nearest(&t, &qy, &got);
        worse += got > 4.0f * best + 1e-6f;
        c = pw_kdtree_cost(&t, q, qn); /* a bounded search never ends worse than its start */
        qy.eps = 0.0f, qy.buckets = 2, qy.start = qn, qy.start_cost = c;
        pw_kdtree_nearest(&t, &qy, &got);
        worse += got > c || got < best;
    }
    CHECKF(bad == 0, "%d of 400 exact queries differ from brute force", bad);
    CHECKF(worse == 0, "%d of 800 approximate queries cost more than allowed", worse);
    for (i = 0; i < n; i++) pw_kdtree_set_penalty(&t, i, 0.0f);
    for (k = 0; k < d; k++) q[k] = 0.25f; /* exactly the duplicated point */
    dup = 7 * 11;
    qy.q = q, qy.eps = 0.0f, qy.buckets = -1, qy.start = dup, qy.start_cost = 0.0f, qy.off = off;
    CHECK(pw_kdtree_nearest(&t, &qy, NULL) == dup);
    pw_kdtree_free(NULL, &t);
    free(p);
    free(pen);
}

/* pca.h: points spread along known orthogonal axes with variances 9, 4 and
 * 1 give those axes (up to sign) and variances. */
static void t_pca_axes(void)
{
    pw_pca pc;
    pw_pca_out out;
    pw_rng r = pw_rng_seed(3, 3);
    float axes[3][4] = {{0.5f, 0.5f, 0.5f, 0.5f}, {0.5f, -0.5f, 0.5f, -0.5f}, {0.5f, 0.5f, -0.5f, -0.5f}};
    float mean[4], basis[12], var[3], x[4], sd[3] = {3.0f, 2.0f, 1.0f}, proj[3];
    int i, k, j;
    double sum[3] = {0, 0, 0};
    REQUIRE(pw_pca_init(NULL, &pc, 4, NULL) == PW_OK);
    for (i = 0; i < 20000; i++) {
        for (k = 0; k < 4; k++) x[k] = 1.0f;
        for (j = 0; j < 3; j++) {
            float g = 0.0f;
            for (k = 0; k < 12; k++) g += pw_rng_float(&r);
            for (k = 0; k < 4; k++) x[k] += sd[j] * (g - 6.0f) * axes[j][k];
        }
        pw_pca_add(&pc, x);
    }
    out.k = 3, out.mean = mean, out.basis = basis, out.var = var;
    REQUIRE(pw_pca_solve(NULL, &pc, &out, NULL) == PW_OK);
    for (j = 0; j < 3; j++) {
        float dot = 0.0f;
        for (k = 0; k < 4; k++) dot += basis[j * 4 + k] * axes[j][k];
        CHECKF(fabsf(fabsf(dot) - 1.0f) < 0.01f, "component %d is off its axis (|dot| = %g)", j, fabsf(dot));
        CHECKF(fabsf(var[j] - sd[j] * sd[j]) < 0.05f * sd[j] * sd[j], "variance %d: %g, expected %g", j, var[j], sd[j] * sd[j]);
        sum[j] = mean[j];
    }
    CHECK_NEAR(sum[0], 1.0, 0.1);
    pw_pca_project(x, mean, basis, 4, 3, proj);
    {
        float packed[4 * PW_PCA_PACK], y8[PW_PCA_PACK];
        pw_pca_pack(basis, 4, 3, packed);
        pw_pca_project_packed(x, mean, packed, 4, y8);
        for (j = 0; j < 3; j++) CHECK_NEAR(y8[j], proj[j], 1e-4);
        CHECK(y8[3] == 0.0f);
    }
    pw_pca_free(NULL, &pc);
}

/* ---- §1.1 feature morphing ------------------------------------------------- */

/* Coefficient of variation of the flips between consecutive layers. */
static double flips_cv(const pgp_tile *m)
{
    double s = 0.0, s2 = 0.0;
    int j;
    for (j = 0; j + 1 < m->layers; j++) {
        double f = (double)mask_diff(m, j, j + 1);
        s += f, s2 += f * f;
    }
    s /= m->layers - 1;
    return sqrt(s2 / (m->layers - 1) - s * s) / s;
}

/* The morph of mask a into mask b over `layers` layers: F_0 and F_M are
 * the masks exactly and the masks move monotonically (the distance to F_0
 * grows, the distance to F_M shrinks). Returns the flips' coefficient of
 * variation, speed-adaptive in cv[0] and uniform in cv[1]. */
static void check_morph(const pgp_image *am, const pgp_image *bm, int layers, const char *what, double cv[2])
{
    pgp_tile m[2];
    pgp_error err;
    pgp_synth_options o = pgp_default_options().synth;
    int k, u, n = am->width, ends = 1;
    for (u = 0; u < 2; u++) {
        o.uniform = u;
        REQUIRE(pgp_morph_masks(am, bm, layers, &o, &m[u], &err) == PGP_OK);
        CHECK(m[u].width == n && m[u].layers == layers && m[u].channels == 1);
        cv[u] = flips_cv(&m[u]);
    }
    for (k = 0; k < n * n; k++) {
        if ((m[0].pixels[k] > 0.5f) != (am->pixels[k] > 0.5f)) ends = 0;
        if ((m[0].pixels[(size_t)(layers - 1) * n * n + k] > 0.5f) != (bm->pixels[k] > 0.5f)) ends = 0;
    }
    CHECKF(ends, "%s: the first and last masks are not the keys' masks", what);
    for (k = 1; k < layers; k++) {
        CHECKF(mask_diff(&m[0], k, 0) >= mask_diff(&m[0], k - 1, 0), "%s: layer %d is nearer to F_0 than %d", what, k, k - 1);
        CHECKF(mask_diff(&m[0], k, layers - 1) <= mask_diff(&m[0], k - 1, layers - 1), "%s: layer %d is farther from F_M than %d",
               what, k, k - 1);
    }
    pgp_tile_free(&m[0]);
    pgp_tile_free(&m[1]);
}

/* §1.1 on discs that move, shrink, split and merge into other discs: with
 * speed-adaptive subsampling the flips per layer are near constant (their
 * coefficient of variation under 0.25) and more even than with uniform
 * subsampling. Discs into stripes: ends and monotony; there the first
 * sweep (the stripes' centre rows all lie at the largest distance) flips a
 * quarter of the stripes at one step, which no subsampling can split, so
 * its evenness is reported, not bounded. */
static void t_morph_masks(void)
{
    pgp_image a, am, b, bm, c, cm;
    double cv[2];
    spots(96, 11.0f, 1, &a, &am);
    spots(96, 7.0f, 5, &b, &bm);
    stripes(96, 16, 2, &c, &cm);
    check_morph(&am, &bm, 8, "discs", cv);
    pwt_info("discs to discs, flips per layer, coefficient of variation: speed-adaptive %.3f, uniform %.3f", cv[0], cv[1]);
    CHECKF(cv[0] < 0.25, "speed-adaptive flips vary by %.3f of their mean", cv[0]);
    CHECKF(cv[0] < cv[1], "speed-adaptive (%.3f) is not more even than uniform (%.3f)", cv[0], cv[1]);
    check_morph(&am, &cm, 8, "discs to stripes", cv);
    pwt_info("discs to stripes: speed-adaptive %.3f, uniform %.3f", cv[0], cv[1]);
    CHECK(cv[0] < cv[1]);
    pgp_image_free(&a), pgp_image_free(&am), pgp_image_free(&b), pgp_image_free(&bm);
    pgp_image_free(&c), pgp_image_free(&cm);
}

/* ---- §1 the tile ---------------------------------------------------------------- */

/* The seam ratios of all layers and both directions: the largest in
 * worst[0], the mean in worst[1]. */
static void layers_seams(const pgp_tile *t, double worst[2])
{
    int k, dx;
    worst[0] = worst[1] = 0.0;
    for (k = 0; k < t->layers; k++) {
        pgp_image l = layer(t, k);
        for (dx = 0; dx < 2; dx++) {
            double r = seam_dir(&l, dx);
            worst[0] = r > worst[0] ? r : worst[0];
            worst[1] += r / (2.0 * t->layers);
        }
    }
}

/* Every layer tiles: the wrap-around difference is no larger than the
 * largest difference between neighbouring interior columns and rows, on
 * average over the layers and directions, and within twice that in every
 * one. A periodic layer's wrap-around line is just another line, which a
 * feature may cross where its edge is sharpest (a band swept at the start
 * of §1.1, the quadrant edges GIMP's marble has at its border as well as
 * inside), hence the margin for single layers; tiles cut from a larger
 * texture exceed both bounds by far (t_seam_detector). */
static void check_layers_tile(const pgp_tile *t, const char *what)
{
    double w[2];
    layers_seams(t, w);
    pwt_info("%s: wrap-around over largest interior difference: mean %.2f, largest %.2f", what, w[1], w[0]);
    CHECKF(w[1] <= 1.0 && w[0] <= 2.0, "%s: wrap-around differences %.2f times the largest interior one on average, "
           "%.2f at most", what, w[1], w[0]);
}

/* The seam test can fail: layers cut from a larger smooth texture (sums of
 * sines of periods that do not divide the tile, with noise) exceed both
 * bounds. */
static void t_seam_detector(void)
{
    pgp_tile t;
    double w[2];
    int k, x, y, c;
    memset(&t, 0, sizeof t);
    t.width = t.height = 64, t.layers = 6, t.channels = 3;
    t.pixels = (float *)malloc(sizeof(float) * 64 * 64 * 3 * 6);
    for (k = 0; k < 6; k++)
        for (y = 0; y < 64; y++)
            for (x = 0; x < 64; x++)
                for (c = 0; c < 3; c++)
                    t.pixels[(((size_t)k * 64 + y) * 64 + x) * 3 + c] =
                        0.5f + 0.2f * (float)pw_sin(x / (7.3 + k + c)) * (float)pw_cos(y / (5.1 + k)) + 0.05f * noise(x, y, (unsigned)k);
    layers_seams(&t, w);
    CHECKF(w[1] > 1.5 && w[0] > 2.0, "cut-out layers: %.2f on average, %.2f at most", w[1], w[0]);
    free(t.pixels);
}

/* Two synthetic keys (spots, stripes) at 64 texels, 6 layers: the tile's
 * shape, every layer tiles, layer 0 is key 0 and the last is key 1. */
static void t_tile_two_keys(void)
{
    pgp_image a, am, b, bm;
    pgp_key keys[2];
    pgp_tile t, m;
    pgp_error err;
    pgp_synth_options o = pgp_default_options().synth;
    int k;
    double d0[6], d1[6];
    spots(64, 8.0f, 3, &a, &am);
    stripes(64, 12, 4, &b, &bm);
    keys[0].image = &a, keys[0].mask = &am, keys[1].image = &b, keys[1].mask = &bm;
    o.size = 64;
    o.layers = 6;
    REQUIRE(pgp_synthesize_tile(keys, 2, &o, &t, &m, &err) == PGP_OK);
    CHECK(t.width == 64 && t.height == 64 && t.layers == 6 && t.channels == 3);
    CHECK(m.width == 64 && m.layers == 6 && m.channels == 1);
    check_layers_tile(&t, "spots to stripes");
    for (k = 0; k < 6; k++) {
        pgp_image l = layer(&t, k);
        d0[k] = hist_dist(&l, &a);
        d1[k] = hist_dist(&l, &b);
    }
    pwt_info("histogram distance to key 0 / key 1 per layer: %.3f/%.3f %.3f/%.3f %.3f/%.3f %.3f/%.3f %.3f/%.3f %.3f/%.3f",
             d0[0], d1[0], d0[1], d1[1], d0[2], d1[2], d0[3], d1[3], d0[4], d1[4], d0[5], d1[5]);
    CHECKF(d0[0] < 0.01 && d1[5] < 0.01, "the end layers are not the keys (%.3f, %.3f)", d0[0], d1[5]);
    CHECKF(d0[0] < d1[0] / 5 && d1[5] < d0[5] / 5, "end layers: %.3f vs %.3f, %.3f vs %.3f", d0[0], d1[0], d1[5], d0[5]);
    pgp_tile_free(&t);
    pgp_tile_free(&m);
    pgp_image_free(&a), pgp_image_free(&am), pgp_image_free(&b), pgp_image_free(&bm);
}

/* The syntheses from both ends of a morph of M layers (before blending):
 * the largest class distance (features and background apart, see
 * class_dist) to the input over all layers in worst[0], their mean in
 * worst[1], the least share of texels whose darkness follows the target
 * mask in *agree; every synthesis must tile. */
static void synth_sides(const pgp_synth_options *o, const pgp__key *keys, const unsigned char *masks, int M,
                        const pgp_image *in[2], double worst[2], double *agree)
{
    float *out = (float *)malloc(sizeof(float) * 64 * 64 * 3);
    double done = 0.0;
    pgp__ex ex;
    pgp__synth S;
    pgp__tile_job T; /* o->size is 64 */
    pw_err e;
    int k, m, side, cls, count = 0;
    pw_err_clear(&e);
    worst[0] = worst[1] = 0.0, *agree = 1.0;
    T.a = NULL;
    T.o = o;
    T.keys = keys;
    T.nkeys = 2;
    T.c = 3;
    T.nlev = pgp__level_count(64, 0);
    for (side = 0; side < 2; side++) {
        REQUIRE(pgp__ex_build(&T, &keys[side], &ex, &e) == PW_OK);
        REQUIRE(pgp__synth_init(NULL, &S, &ex, o, &e) == PW_OK);
        S.done = &done, S.total = 1e12;
        for (k = 0; k <= M; k++) {
            const unsigned char *f;
            pgp_image l;
            int i, hit = 0;
            m = side ? M - k : k;
            f = masks + (size_t)m * 64 * 64;
            REQUIRE(pgp__synth_layer(&S, f, k ? PGP__INIT_PREVIOUS : PGP__INIT_IDENTITY, (uint64_t)m, &e) == PW_OK);
            pgp__emit(&S, 1.0f, 0, out);
            l = make_image(64, 64, 3);
            memcpy(l.pixels, out, sizeof(float) * 64 * 64 * 3);
            for (cls = 0; cls < 2; cls++) {
                double d = class_dist(&l, f, in[side], keys[side].mask, cls);
                worst[0] = d > worst[0] ? d : worst[0];
                worst[1] += d, count++;
            }
            for (i = 0; i < 64 * 64; i++) hit += (l.pixels[3 * i] < 0.45f) == (f[i] != 0);
            *agree = hit / 4096.0 < *agree ? hit / 4096.0 : *agree;
            CHECKF(seam_ratio(&l) <= 2.0, "side %d layer %d: seam %.2f", side, m, seam_ratio(&l));
            pgp_image_free(&l);
        }
        pgp__synth_free(NULL, &S);
        pgp__ex_free(NULL, &ex);
    }
    worst[1] /= count;
    free(out);
}

/* §1.2 from each end of a morph, before blending: every synthesis follows
 * its target mask (dark where the mask says so), tiles, and keeps its
 * input's colour histogram within each mask class -- a mask with another
 * share of features cannot keep the histogram of the whole, but the
 * features' colours and the background's stay those of the input: class
 * distance at most 0.04 everywhere. The usage penalty is what keeps them:
 * without it the mean class distance is larger. */
static void t_synthesis_histograms(void)
{
    pgp_image a, am, b, bm, ka, kb;
    pgp_synth_options o = pgp__synth_options(NULL);
    pgp__key keys[2];
    pgp_key pk[2];
    const pgp_image *in[2];
    unsigned char *masks;
    double with[2], without[2], agree, agree0;
    pgp__morph_job J;
    pw_err e;
    int k, M = 5;
    pw_err_clear(&e);
    o.size = 64;
    spots(64, 8.0f, 5, &a, &am);
    stripes(64, 16, 6, &b, &bm);
    pk[0].image = &a, pk[0].mask = &am, pk[1].image = &b, pk[1].mask = &bm;
    masks = (unsigned char *)malloc((size_t)(M + 1) * 64 * 64);
    for (k = 0; k < 2; k++) REQUIRE(pgp__prepare_key(NULL, &pk[k], 3, &o, &keys[k], &e) == PW_OK);
    J.f0 = keys[0].mask, J.f1 = keys[1].mask, J.n = 64, J.M = M, J.masks = masks;
    J.prog = NULL, J.p0 = 0.0f, J.p1 = 1.0f;
    REQUIRE(pgp__morph_masks(NULL, &J, &o, &e) == PW_OK);
    ka = make_image(64, 64, 3), kb = make_image(64, 64, 3);
    memcpy(ka.pixels, keys[0].color, sizeof(float) * 64 * 64 * 3);
    memcpy(kb.pixels, keys[1].color, sizeof(float) * 64 * 64 * 3);
    in[0] = &ka, in[1] = &kb;
    synth_sides(&o, keys, masks, M, in, with, &agree);
    o.usage_weight = 0.0f;
    synth_sides(&o, keys, masks, M, in, without, &agree0);
    pwt_info("class histogram distance of the syntheses to their inputs: largest %.4f, mean %.4f (without the usage "
             "penalty %.4f, %.4f); least mask agreement %.3f", with[0], with[1], without[0], without[1], agree);
    CHECKF(with[0] <= 0.04, "a synthesis is %.4f away from its input's class histogram (bound 0.04)", with[0]);
    CHECKF(with[1] < without[1], "the usage penalty does not bring the histograms closer (%.4f vs %.4f)", with[1], without[1]);
    CHECKF(agree >= 0.9, "a synthesis follows its target mask on only %.3f of the texels", agree);
    for (k = 0; k < 2; k++) pgp__key_free(NULL, &keys[k]);
    free(masks);
    pgp_image_free(&a), pgp_image_free(&am), pgp_image_free(&b), pgp_image_free(&bm);
    pgp_image_free(&ka), pgp_image_free(&kb);
}

/* Single-tile mode (Fig. 14): every layer follows the key's one mask, keeps
 * the key's histogram and tiles, and the layers differ from each other. */
static void t_single_tile(void)
{
    pgp_image a, am;
    pgp_key key;
    pgp_tile t, m;
    pgp_error err;
    pgp_synth_options o = pgp_default_options().synth;
    int k, i;
    spots(64, 8.0f, 7, &a, &am);
    key.image = &a, key.mask = &am;
    o.size = 64, o.layers = 4, o.single = 1;
    REQUIRE(pgp_synthesize_tile(&key, 1, &o, &t, &m, &err) == PGP_OK);
    check_layers_tile(&t, "single tile");
    for (k = 1; k < 4; k++) {
        pgp_image l = layer(&t, k), p = layer(&t, k - 1);
        double diff = 0.0;
        int agree = 0;
        for (i = 0; i < 64 * 64 * 3; i++) diff += fabs(l.pixels[i] - p.pixels[i]);
        for (i = 0; i < 64 * 64; i++) agree += (l.pixels[3 * i] < 0.45f) == (am.pixels[i] > 0.5f);
        CHECKF(hist_dist(&l, &a) <= 0.03, "layer %d: histogram distance %.4f to the key", k, hist_dist(&l, &a));
        CHECKF(agree >= 0.9 * 4096, "layer %d follows the shared mask on %d of 4096 texels", k, agree);
        CHECKF(diff / (64 * 64 * 3) > 0.02, "layer %d is the same as layer %d", k, k - 1);
        CHECK(mask_diff(&m, k, 0) == 0);
    }
    pgp_tile_free(&t);
    pgp_tile_free(&m);
    pgp_image_free(&a), pgp_image_free(&am);
}

/* The same keys and seed give the same bytes; another seed another tile. */
static void t_determinism(void)
{
    pgp_image a, am, b, bm;
    pgp_key keys[2];
    pgp_tile t[3];
    pgp_error err;
    pgp_synth_options o = pgp_default_options().synth;
    int k;
    spots(48, 7.0f, 8, &a, &am);
    stripes(48, 10, 9, &b, &bm);
    keys[0].image = &a, keys[0].mask = NULL, keys[1].image = &b, keys[1].mask = NULL;
    o.size = 48, o.layers = 4;
    for (k = 0; k < 3; k++) {
        o.seed = k == 2 ? 7 : 0;
        REQUIRE(pgp_synthesize_tile(keys, 2, &o, &t[k], NULL, &err) == PGP_OK);
    }
    CHECK(!memcmp(t[0].pixels, t[1].pixels, sizeof(float) * 48 * 48 * 3 * 4));
    CHECK(memcmp(t[0].pixels, t[2].pixels, sizeof(float) * 48 * 48 * 3 * 4) != 0);
    for (k = 0; k < 3; k++) pgp_tile_free(&t[k]);
    pgp_image_free(&a), pgp_image_free(&am), pgp_image_free(&b), pgp_image_free(&bm);
}

/* Keys of other sizes are resampled to size x size (not cropped): a key of
 * 40 x 20 texels with a vertical sine of 2 periods and a horizontal one of
 * 1 comes out at 64 x 64 with the same numbers of periods, as layer 0. */
static void t_key_sizes(void)
{
    pgp_image a = make_image(40, 20, 1), b = make_image(96, 96, 3);
    pgp_key keys[2];
    pgp_tile t;
    pgp_error err;
    pgp_synth_options o = pgp_default_options().synth;
    int x, y, crossings = 0, crossings_y = 0;
    for (y = 0; y < 20; y++)
        for (x = 0; x < 40; x++)
            a.pixels[y * 40 + x] = 0.5f + 0.2f * (float)pw_sin(6.283185307 * 2 * (x + 0.5) / 40) + 0.2f * (float)pw_sin(6.283185307 * (y + 0.5) / 20);
    for (x = 0; x < 96 * 96 * 3; x++) b.pixels[x] = noise(x, 1, 2);
    keys[0].image = &a, keys[0].mask = NULL, keys[1].image = &b, keys[1].mask = NULL;
    o.size = 64, o.layers = 2;
    REQUIRE(pgp_synthesize_tile(keys, 2, &o, &t, NULL, &err) == PGP_OK);
    CHECK(t.width == 64 && t.height == 64 && t.channels == 3);
    for (x = 0; x < 64; x++) { /* sign changes of (value - 0.5) along row 16 and column 0 */
        float v = t.pixels[3 * (16 * 64 + x)] - 0.5f - 0.2f * (float)pw_sin(6.283185307 * (16 + 0.5) / 64);
        float w = t.pixels[3 * (16 * 64 + (x + 1) % 64)] - 0.5f - 0.2f * (float)pw_sin(6.283185307 * (16 + 0.5) / 64);
        float p = t.pixels[3 * (x * 64)] - 0.5f, q = t.pixels[3 * (((x + 1) % 64) * 64)] - 0.5f;
        crossings += (v < 0.0f) != (w < 0.0f);
        crossings_y += (p < 0.0f) != (q < 0.0f);
    }
    CHECK_EQ_INT(crossings, 4);
    CHECK_EQ_INT(crossings_y, 2);
    pgp_tile_free(&t);
    pgp_image_free(&a), pgp_image_free(&b);
}

/* Bad input gets a clear error and no output: an empty mask, a mask of all
 * ones, a mask of another size, a NaN texel, too few layers, a single-tile
 * request with two keys, a morph of one key, a bad window, a file that is
 * not an image. */
static void t_bad_input(void)
{
    pgp_image a, am, b, bm, empty = make_image(32, 32, 1), full = make_image(32, 32, 1), small = make_image(16, 16, 1);
    pgp_key keys[2];
    pgp_tile t;
    pgp_error err;
    pgp_synth_options o = pgp_default_options().synth;
    pgp_image img;
    int k;
    static const char junk[] = "this is not an image";
    struct { int what; const char *msg; } cases[] = {
        {0, "key 1 mask: no feature texel (empty mask)"}, {1, "key 1 mask: every texel is a feature"},
        {2, "key 1: the mask is 16x16 but the image 32x32"}, {3, "key 0 image: pixel 5 is not a finite number"},
        {4, "3 layers for 4 keys"}, {5, "single-tile mode takes exactly one key"},
        {6, "a morph takes 2 to 256 keys (1 given"}, {7, "windows 4, 3 (odd"}};
    spots(32, 5.0f, 1, &a, &am);
    stripes(32, 8, 1, &b, &bm);
    for (k = 0; k < 32 * 32; k++) full.pixels[k] = 1.0f;
    o.size = 32;
    for (k = 0; k < (int)(sizeof cases / sizeof cases[0]); k++) {
        pgp_synth_options oc = o;
        pgp_key kk[4];
        int nk = 2, w = cases[k].what;
        float keep = a.pixels[15];
        kk[0].image = &a, kk[0].mask = &am, kk[1].image = &b, kk[1].mask = &bm;
        kk[2] = kk[3] = kk[0];
        if (w == 0) kk[1].mask = &empty;
        if (w == 1) kk[1].mask = &full;
        if (w == 2) kk[1].mask = &small;
        if (w == 3) a.pixels[15] = (float)NAN;
        if (w == 4) nk = 4, oc.layers = 3;
        if (w == 5) oc.single = 1;
        if (w == 6) nk = 1;
        if (w == 7) oc.color_window = 4;
        memset(&t, 0xff, sizeof t);
        CHECKF(pgp_synthesize_tile(kk, nk, &oc, &t, NULL, &err) == PGP_ERR_INVALID, "case %d accepted", w);
        CHECKF(strstr(err.message, cases[k].msg) != NULL, "case %d: '%s' lacks '%s'", w, err.message, cases[k].msg);
        CHECK(t.pixels == NULL && t.layers == 0);
        a.pixels[15] = keep;
    }
    /* single-tile mode takes an empty mask: documented, the synthesis is then unconstrained */
    keys[0].image = &a, keys[0].mask = &empty;
    o.single = 1, o.layers = 2;
    CHECK(pgp_synthesize_tile(keys, 1, &o, &t, NULL, &err) == PGP_OK);
    pgp_tile_free(&t);
    {
        char path[64];
        FILE *f;
        snprintf(path, sizeof path, "/tmp/pgp_synth_junk_%ld.ppm", PWT_PID_);
        f = fopen(path, "wb");
        REQUIRE(f != NULL);
        fwrite(junk, 1, sizeof junk - 1, f);
        fclose(f);
        CHECK(pgp_load_image(path, NULL, &img, &err) != PGP_OK && img.pixels == NULL);
        CHECKF(strstr(err.message, "unknown image format") != NULL, "'%s'", err.message);
        remove(path);
    }
    pgp_image_free(&a), pgp_image_free(&am), pgp_image_free(&b), pgp_image_free(&bm);
    pgp_image_free(&empty), pgp_image_free(&full), pgp_image_free(&small);
}

static int cancel_at(void *user, float done, const char *stage)
{
    int *calls = (int *)user;
    (void)done, (void)stage;
    return ++*calls >= 5;
}

/* The progress callback is called and can cancel; nothing leaks. */
static void t_cancel(void)
{
    pgp_image a, am, b, bm;
    pgp_key keys[2];
    pgp_tile t;
    pgp_error err;
    pgp_synth_options o = pgp_default_options().synth;
    pwt_alloc_state st = {0, 0, -1};
    int calls = 0;
    spots(32, 5.0f, 2, &a, &am);
    stripes(32, 8, 2, &b, &bm);
    keys[0].image = &a, keys[0].mask = &am, keys[1].image = &b, keys[1].mask = &bm;
    o.size = 32, o.layers = 4;
    o.progress = cancel_at, o.progress_user = &calls;
    o.allocator.malloc_fn = pwt_malloc, o.allocator.realloc_fn = pwt_realloc, o.allocator.free_fn = pwt_free;
    o.allocator.user = &st;
    CHECK(pgp_synthesize_tile(keys, 2, &o, &t, NULL, &err) == PGP_ERR_CANCELLED);
    CHECK(strstr(err.message, "cancelled") != NULL);
    CHECK_EQ_INT(calls, 5);
    CHECK_EQ_INT(st.live, 0);
    CHECK(t.pixels == NULL);
    pgp_image_free(&a), pgp_image_free(&am), pgp_image_free(&b), pgp_image_free(&bm);
}

/* Every allocation failure of a small run (automatic masks, a key that is
 * quilted, two morphs, the mask output) returns PGP_ERR_NOMEM with nothing
 * leaked. */
static void t_alloc_failures(void)
{
    pgp_image a, am, b, bm, c = make_image(24, 24, 3);
    pgp_key keys[3];
    pgp_tile t, m;
    pgp_error err;
    pgp_synth_options o = pgp_default_options().synth;
    pwt_alloc_state st = {0, 0, -1};
    long total, k, bad = 0;
    int x, y;
    spots(24, 4.0f, 3, &a, &am);
    stripes(24, 6, 3, &b, &bm);
    for (y = 0; y < 24; y++)
        for (x = 0; x < 24; x++) /* a ramp: does not tile, so it is quilted */
            c.pixels[3 * (y * 24 + x)] = c.pixels[3 * (y * 24 + x) + 1] = (x + y) / 48.0f + 0.3f * noise(x, y, 4);
    keys[0].image = &a, keys[0].mask = NULL, keys[1].image = &b, keys[1].mask = &bm, keys[2].image = &c, keys[2].mask = NULL;
    o.size = 24, o.layers = 4, o.coarse_passes = 2, o.fine_passes = 1;
    o.allocator.malloc_fn = pwt_malloc, o.allocator.realloc_fn = pwt_realloc, o.allocator.free_fn = pwt_free;
    o.allocator.user = &st;
    REQUIRE(pgp_synthesize_tile(keys, 3, &o, &t, &m, &err) == PGP_OK);
    pgp_tile_free(&t);
    pgp_tile_free(&m);
    total = st.calls;
    for (k = 0; k < total; k++) {
        pgp_result r;
        st.calls = 0, st.live = 0, st.fail_after = k;
        r = pgp_synthesize_tile(keys, 3, &o, &t, &m, &err);
        if (r == PGP_OK) pgp_tile_free(&t), pgp_tile_free(&m);
        if (r != PGP_ERR_NOMEM || st.live != 0) {
            if (!bad++) pwt_fail_(__FILE__, __LINE__, "failing allocation %ld: result %d, %ld blocks leaked", k, (int)r, st.live);
        }
    }
    pwt_info("%ld allocation failure points exercised", total);
    CHECK_EQ_INT(bad, 0);
    pgp_image_free(&a), pgp_image_free(&am), pgp_image_free(&b), pgp_image_free(&bm), pgp_image_free(&c);
}

/* Automatic masks: the dark spots of a spot texture (DARK), its light
 * background (BRIGHT), and its outlines (GRADIENT). */
static void t_auto_masks(void)
{
    pgp_image a, am, m[3];
    pgp_error err;
    int k, i, agree[3] = {0, 0, 0};
    spots(64, 9.0f, 6, &a, &am);
    for (k = 0; k < 3; k++) REQUIRE(pgp_feature_mask(&a, (pgp_mask)k, NULL, &m[k], &err) == PGP_OK);
    for (i = 0; i < 64 * 64; i++) {
        int x = i % 64, y = i / 64, edge = 0, dx, dy;
        for (dy = -1; dy <= 1; dy++)
            for (dx = -1; dx <= 1; dx++) edge |= (am.pixels[((y + dy + 64) % 64) * 64 + (x + dx + 64) % 64] > 0.5f) != (am.pixels[i] > 0.5f);
        agree[0] += (m[0].pixels[i] > 0.5f) == (am.pixels[i] > 0.5f);
        agree[1] += (m[1].pixels[i] > 0.5f) != (am.pixels[i] > 0.5f);
        agree[2] += !edge || m[2].pixels[i] > 0.5f;
    }
    pwt_info("automatic masks agree on %d, %d, %d of 4096 texels", agree[0], agree[1], agree[2]);
    CHECK(agree[0] > 0.95 * 4096 && agree[1] > 0.95 * 4096 && agree[2] > 0.8 * 4096);
    for (k = 0; k < 3; k++) pgp_image_free(&m[k]);
    pgp_image_free(&a), pgp_image_free(&am);
}

/* A key that does not tile (a ramp) is quilted onto a torus in AUTO mode:
 * its seam drops from well over the largest interior difference to within
 * it; KEEP leaves it as it is. */
static void t_make_tileable(void)
{
    pgp_image c = make_image(64, 64, 3), b, bm;
    pgp_key keys[2];
    pgp_tile t;
    pgp_error err;
    pgp_synth_options o = pgp_default_options().synth;
    pgp_image l;
    int x, y, k;
    double before;
    for (y = 0; y < 64; y++)
        for (x = 0; x < 64; x++)
            for (k = 0; k < 3; k++) c.pixels[3 * (y * 64 + x) + k] = 0.1f + 0.6f * (x + y) / 128.0f + 0.3f * noise(x / 3, y / 3, 5 + k);
    stripes(64, 12, 7, &b, &bm);
    before = seam_ratio(&c);
    keys[0].image = &c, keys[0].mask = NULL, keys[1].image = &b, keys[1].mask = &bm;
    o.size = 64, o.layers = 2, o.tileable = PGP_TILEABLE_KEEP;
    REQUIRE(pgp_synthesize_tile(keys, 2, &o, &t, NULL, &err) == PGP_OK);
    l = layer(&t, 0);
    CHECKF(seam_ratio(&l) > 1.5, "KEEP: seam %.2f", seam_ratio(&l));
    pgp_tile_free(&t);
    o.tileable = PGP_TILEABLE_AUTO;
    REQUIRE(pgp_synthesize_tile(keys, 2, &o, &t, NULL, &err) == PGP_OK);
    l = layer(&t, 0);
    pwt_info("ramp key: seam ratio %.2f before, %.2f after quilting", before, seam_ratio(&l));
    CHECKF(before > 1.5 && seam_ratio(&l) <= 1.0, "seam %.2f before, %.2f after", before, seam_ratio(&l));
    pgp_tile_free(&t);
    pgp_image_free(&c), pgp_image_free(&b), pgp_image_free(&bm);
}

/* The tile written as NRRD (sizes C W H M) reads back as the same tile. */
static void t_nrrd_round_trip(void)
{
    pgp_image a, am, b, bm;
    pgp_key keys[2];
    pgp_tile t, back;
    pgp_error err;
    pgp_synth_options o = pgp_default_options().synth;
    pw_buf buf;
    size_t i;
    int same = 1;
    spots(32, 5.0f, 9, &a, &am);
    stripes(32, 8, 9, &b, &bm);
    keys[0].image = &a, keys[0].mask = &am, keys[1].image = &b, keys[1].mask = &bm;
    o.size = 32, o.layers = 3;
    REQUIRE(pgp_synthesize_tile(keys, 2, &o, &t, NULL, &err) == PGP_OK);
    memset(&buf, 0, sizeof buf);
    REQUIRE(pgp_write_tile(&t, pw_buf_write, &buf, &err) == PGP_OK);
    CHECK(strstr((const char *)buf.data, "sizes: 3 32 32 3") != NULL);
    REQUIRE(pgp_read_tile(buf.data, buf.size, "tile.nrrd", NULL, &back, &err) == PGP_OK);
    CHECK(back.width == 32 && back.height == 32 && back.layers == 3 && back.channels == 3);
    for (i = 0; i < (size_t)32 * 32 * 3 * 3; i++) same &= fabsf(back.pixels[i] - t.pixels[i]) <= 0.5f / 255.0f + 1e-6f;
    CHECK(same);
    free(buf.data);
    pgp_tile_free(&t);
    pgp_tile_free(&back);
    pgp_image_free(&a), pgp_image_free(&am), pgp_image_free(&b), pgp_image_free(&bm);
}

/* ---- real exemplars ------------------------------------------------------------- */

/* An RGBA image composited over white, as RGB (the GIMP stripes are drawn
 * in their alpha channel). */
static void over_white(pgp_image *im)
{
    size_t i, n = (size_t)im->width * im->height;
    float *p;
    if (im->channels != 4) return;
    p = (float *)malloc(sizeof(float) * 3 * n);
    for (i = 0; i < n; i++) {
        int k;
        for (k = 0; k < 3; k++) p[3 * i + k] = im->pixels[4 * i + k] * im->pixels[4 * i + 3] + 1.0f - im->pixels[4 * i + 3];
    }
    free(im->pixels);
    im->pixels = p;
    im->channels = 3;
}

/* Writes the layers side by side as PNG into $PWT_SLICES (when set), to be
 * looked at. */
static void save_strip(const pgp_tile *t, const char *name)
{
    const char *dir = getenv("PWT_SLICES");
    char path[1024];
    pgp_image s;
    pgp_error err;
    int y, k;
    if (!dir || !*dir) return;
    s = make_image(t->width * t->layers, t->height, t->channels);
    for (k = 0; k < t->layers; k++)
        for (y = 0; y < t->height; y++)
            memcpy(s.pixels + ((size_t)y * s.width + (size_t)k * t->width) * t->channels,
                   t->pixels + (((size_t)k * t->height + y) * t->width) * t->channels, sizeof(float) * t->width * t->channels);
    snprintf(path, sizeof path, "%s/%s.png", dir, name);
    if (pgp_save_image(path, &s, &err) != PGP_OK) pwt_info("%s", err.message);
    pgp_image_free(&s);
}

#define REAL_SIZE 64

/* Runs keys (files under data/textures) through the whole pipeline at
 * REAL_SIZE texels and checks every layer tiles, the key layers are the keys and the
 * masks of each morph move monotonically. With PWT_SLICES=DIR the layers
 * are written side by side to DIR/NAME.png. */
static void real_morph(const char *const *files, int nkeys, int layers, const char *name)
{
    pgp_image img[4];
    pgp_key keys[4];
    pgp_tile t, m;
    pgp_error err;
    pgp_synth_options o = pgp_default_options().synth;
    int k, j;
    for (k = 0; k < nkeys; k++) {
        const char *path = pwt_data(files[k]);
        if (!path) {
            while (k-- > 0) pgp_image_free(&img[k]);
            return;
        }
        REQUIRE(pgp_load_image(path, NULL, &img[k], &err) == PGP_OK);
        over_white(&img[k]);
        keys[k].image = &img[k], keys[k].mask = NULL;
    }
    o.size = REAL_SIZE, o.layers = layers;
    REQUIRE(pgp_synthesize_tile(keys, nkeys, &o, &t, &m, &err) == PGP_OK);
    check_layers_tile(&t, name);
    for (k = 0; k + 1 < nkeys; k++) {
        int b = pgp__key_layer(k, nkeys, layers), e = pgp__key_layer(k + 1, nkeys, layers);
        for (j = b + 1; j <= e; j++) {
            CHECKF(mask_diff(&m, j, b) >= mask_diff(&m, j - 1, b), "%s: layer %d nearer to key %d's mask", name, j, k);
            CHECKF(mask_diff(&m, j, e) <= mask_diff(&m, j - 1, e), "%s: layer %d farther from key %d's mask", name, j, k + 1);
        }
    }
    for (k = 0; k < nkeys; k++) { /* the key layers are the keys, resampled to REAL_SIZE */
        pgp_image l = layer(&t, pgp__key_layer(k, nkeys, layers));
        pgp__key pk;
        pw_err e;
        pw_err_clear(&e);
        REQUIRE(pgp__prepare_key(NULL, &keys[k], 3, &o, &pk, &e) == PW_OK);
        CHECKF(!memcmp(l.pixels, pk.color, sizeof(float) * REAL_SIZE * REAL_SIZE * 3), "%s: the layer of key %d is not the key", name, k);
        pgp__key_free(NULL, &pk);
    }
    save_strip(&t, name);
    pgp_tile_free(&t);
    pgp_tile_free(&m);
    for (k = 0; k < nkeys; k++) pgp_image_free(&img[k]);
}

/* Spots to stripes and back (GIMP leopard and Stripes2px). */
static void t_real_spots_stripes(void)
{
    static const char *const f[3] = {"textures/leopard.ppm", "textures/Stripes2px.pam", "textures/leopard.ppm"};
    real_morph(f, 3, 9, "leopard_stripes_leopard");
}

/* Brick to marble to wood (GIMP brick, marble3, wood1). */
static void t_real_brick_marble_wood(void)
{
    static const char *const f[3] = {"textures/brick.ppm", "textures/marble3.ppm", "textures/wood1.ppm"};
    real_morph(f, 3, 9, "brick_marble_wood");
}

static const pwt_case cases[] = {
    {"pgp_synth/edt_brute_force", t_edt_brute_force},
    {"pgp_synth/edt_sites_pass", t_edt_sites_pass},
    {"pgp_synth/edt_signed_disc", t_edt_signed_disc},
    {"pgp_synth/kdtree_penalties", t_kdtree_penalties},
    {"pgp_synth/pca_axes", t_pca_axes},
    {"pgp_synth/morph_masks", t_morph_masks},
    {"pgp_synth/seam_detector", t_seam_detector},
    {"pgp_synth/tile_two_keys", t_tile_two_keys},
    {"pgp_synth/synthesis_histograms", t_synthesis_histograms},
    {"pgp_synth/single_tile", t_single_tile},
    {"pgp_synth/determinism", t_determinism},
    {"pgp_synth/key_sizes", t_key_sizes},
    {"pgp_synth/bad_input", t_bad_input},
    {"pgp_synth/cancel", t_cancel},
    {"pgp_synth/alloc_failures", t_alloc_failures},
    {"pgp_synth/auto_masks", t_auto_masks},
    {"pgp_synth/make_tileable", t_make_tileable},
    {"pgp_synth/nrrd_round_trip", t_nrrd_round_trip},
    {"pgp_synth/real_spots_stripes", t_real_spots_stripes},
    {"pgp_synth/real_brick_marble_wood", t_real_brick_marble_wood},
};
PWT_MAIN(cases)
