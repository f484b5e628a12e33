/* Tests of src/pgp/tile3.h: sampling material-space tiles (s, t
 * periodic, m clamped and blended between layers, mip levels). */
#include "../src/common/rng.h"
#include "../src/pgp/tile3.h"
#include "pwtest.h"

/* Texel (x, y) of layer l, channel k: multiples of 1/255, so that 16-bit
 * storage keeps them to within float rounding. */
static float texel(int x, int y, int l, int k)
{
    return (float)((x * 31 + y * 17 + l * 50 + k * 7) % 256) / 255.0f;
}

/* A W x H x M volume of c channels filled with texel(); alpha (channel 3
 * of 4, or 1 of 2) is 1 unless `alpha` is set. */
static void make_tile_volume(pw_volume *v, int c, int W, int H, int M, int alpha)
{
    int x, y, l, k;
    pw_volume_alloc(NULL, v, c, W, H, M, NULL);
    for (l = 0; l < M; l++)
        for (y = 0; y < H; y++)
            for (x = 0; x < W; x++)
                for (k = 0; k < c; k++) {
                    float val = texel(x, y, l, k);
                    if (!alpha && (c == 2 || c == 4) && k == c - 1) val = 1.0f;
                    v->px[(((size_t)l * H + y) * W + x) * c + k] = val;
                }
}

/* A tile of RGBA texel() values, opaque. */
static int make_tile(pw_tile3 *t, int W, int H, int M)
{
    pw_volume v;
    pw_err e;
    int rc;
    make_tile_volume(&v, 4, W, H, M, 0);
    pw_err_clear(&e);
    rc = pw_tile3_create(NULL, t, &v, 0, &e);
    pw_volume_free(NULL, &v);
    return rc;
}

/* Centre of texel (i, j) (row j from the top): t = 0 is the bottom row. */
static float centre_s(int i, int W) { return ((float)i + 0.5f) / (float)W; }
static float centre_t(int j, int H) { return 1.0f - ((float)j + 0.5f) / (float)H; }

static float max_diff(const float *a, const float *b)
{
    float d = 0.0f;
    int k;
    for (k = 0; k < 4; k++) {
        float x = a[k] > b[k] ? a[k] - b[k] : b[k] - a[k];
        if (!(x <= d)) d = x;
    }
    return d;
}

/* At lod 0, texel centres read the texel itself, in every layer. */
static void t_texel_centres(void)
{
    const int W = 8, H = 4, M = 3;
    pw_tile3 t;
    int i, j, l, k;
    REQUIRE(make_tile(&t, W, H, M) == PW_OK);
    CHECK(t.w == W && t.h == H && t.m == M && t.nlevels == 4);
    for (l = 0; l < M; l++)
        for (j = 0; j < H; j++)
            for (i = 0; i < W; i++) {
                float out[4];
                pw_tile3_sample(&t, centre_s(i, W), centre_t(j, H), (float)l / (float)(M - 1), 0.0f,
                                out);
                for (k = 0; k < 3; k++)
                    CHECKF(out[k] - texel(i, j, l, k) < 1e-6f && texel(i, j, l, k) - out[k] < 1e-6f,
                           "layer %d texel (%d,%d) channel %d: %g vs %g", l, i, j, k, out[k],
                           texel(i, j, l, k));
                CHECK(out[3] == 1.0f);
            }
    pw_tile3_free(NULL, &t);
    CHECK(t.layer == NULL);
}

/* s and t have period 1: s and s + n read the same colour. */
static void t_periodic(void)
{
    const int W = 8, H = 4, M = 3;
    pw_tile3 t;
    pw_rng r = pw_rng_seed(42, 1);
    float a[4], b[4];
    int n;
    REQUIRE(make_tile(&t, W, H, M) == PW_OK);
    /* dyadic coordinates: the wrap is exact, so are the results */
    pw_tile3_sample(&t, 0.3125f, 0.5625f, 0.25f, 0.0f, a);
    pw_tile3_sample(&t, 1.3125f, -0.4375f, 0.25f, 0.0f, b);
    CHECK(memcmp(a, b, sizeof a) == 0);
    pw_tile3_sample(&t, -2.6875f, 3.5625f, 0.25f, 1.5f, b);
    pw_tile3_sample(&t, 0.3125f, 0.5625f, 0.25f, 1.5f, a);
    CHECK(memcmp(a, b, sizeof a) == 0);
    /* the seam itself: s = 0 and s = 1, t = 0 and t = 1 */
    pw_tile3_sample(&t, 0.0f, 0.7f, 0.6f, 0.0f, a);
    pw_tile3_sample(&t, 1.0f, 0.7f, 0.6f, 0.0f, b);
    CHECK(memcmp(a, b, sizeof a) == 0);
    pw_tile3_sample(&t, 0.4f, 0.0f, 0.6f, 0.0f, a);
    pw_tile3_sample(&t, 0.4f, 1.0f, 0.6f, 0.0f, b);
    CHECK(memcmp(a, b, sizeof a) == 0);
    for (n = 0; n < 500; n++) {
        float s = pw_rng_float(&r), tt = pw_rng_float(&r), m = pw_rng_float(&r);
        float lod = 3.0f * pw_rng_float(&r);
        int ds = (int)(pw_rng_float(&r) * 7.0f) - 3, dt = (int)(pw_rng_float(&r) * 7.0f) - 3;
        pw_tile3_sample(&t, s, tt, m, lod, a);
        pw_tile3_sample(&t, s + (float)ds, tt + (float)dt, m, lod, b);
        /* the shifted coordinate is rounded differently: a tiny offset */
        CHECKF(max_diff(a, b) < 1e-4f, "(%g,%g) + (%d,%d): differ by %g", s, tt, ds, dt,
               max_diff(a, b));
    }
    pw_tile3_free(NULL, &t);
}

/* Across the seam the neighbours are the texels of the opposite edge. */
static void t_wrap_edges(void)
{
    const int W = 8, H = 4;
    pw_tile3 t;
    float out[4];
    int k;
    REQUIRE(make_tile(&t, W, H, 1) == PW_OK);
    /* s = 0 on the centre line of row 1: half texel 0, half texel W-1 */
    pw_tile3_sample(&t, 0.0f, centre_t(1, H), 0.0f, 0.0f, out);
    for (k = 0; k < 3; k++)
        CHECK_NEAR(out[k], 0.5f * (texel(0, 1, 0, k) + texel(W - 1, 1, 0, k)), 1e-5);
    /* t = 0 (the bottom edge) between the bottom row H-1 and the top row 0 */
    pw_tile3_sample(&t, centre_s(2, W), 0.0f, 0.0f, 0.0f, out);
    for (k = 0; k < 3; k++)
        CHECK_NEAR(out[k], 0.5f * (texel(2, H - 1, 0, k) + texel(2, 0, 0, k)), 1e-5);
    /* t = 0.1 is 0.1 texel below the bottom row's centre: mostly the bottom
     * row, a little of the top one; t = 0.9 the other way round */
    pw_tile3_sample(&t, centre_s(3, W), 0.1f, 0.0f, 0.0f, out);
    CHECK_NEAR(out[0], 0.9f * texel(3, H - 1, 0, 0) + 0.1f * texel(3, 0, 0, 0), 1e-5);
    pw_tile3_sample(&t, centre_s(3, W), 0.9f, 0.0f, 0.0f, out);
    CHECK_NEAR(out[0], 0.1f * texel(3, H - 1, 0, 0) + 0.9f * texel(3, 0, 0, 0), 1e-5);
    pw_tile3_free(NULL, &t);
}

/* Bilinear within a level: a point between texel centres mixes them. */
static void t_bilinear(void)
{
    const int W = 8, H = 4;
    pw_tile3 t;
    float out[4];
    int k;
    REQUIRE(make_tile(&t, W, H, 1) == PW_OK);
    pw_tile3_sample(&t, 3.0f / 8.0f, centre_t(1, H), 0.0f, 0.0f, out); /* between 2 and 3 */
    for (k = 0; k < 3; k++)
        CHECK_NEAR(out[k], 0.5f * (texel(2, 1, 0, k) + texel(3, 1, 0, k)), 1e-5);
    pw_tile3_sample(&t, 2.75f / 8.0f, 0.5f, 0.0f, 0.0f, out); /* 1/4 of the way, rows 1 and 2 */
    for (k = 0; k < 3; k++) {
        float top = 0.75f * texel(2, 1, 0, k) + 0.25f * texel(3, 1, 0, k);
        float bot = 0.75f * texel(2, 2, 0, k) + 0.25f * texel(3, 2, 0, k);
        CHECK_NEAR(out[k], 0.5f * (top + bot), 1e-5);
    }
    pw_tile3_free(NULL, &t);
}

/* Layer k at m = k/(M-1), linear in between, m clamped to [0, 1]. */
static void t_layers(void)
{
    const int W = 8, H = 4, M = 3;
    pw_tile3 t;
    float out[4], l0[4], l1[4], l2[4];
    float s = centre_s(5, W), tt = centre_t(2, H);
    int k;
    REQUIRE(make_tile(&t, W, H, M) == PW_OK);
    pw_tile3_sample(&t, s, tt, 0.0f, 0.0f, l0);
    pw_tile3_sample(&t, s, tt, 0.5f, 0.0f, l1);
    pw_tile3_sample(&t, s, tt, 1.0f, 0.0f, l2);
    for (k = 0; k < 3; k++) {
        CHECK_NEAR(l0[k], texel(5, 2, 0, k), 1e-6);
        CHECK_NEAR(l1[k], texel(5, 2, 1, k), 1e-6);
        CHECK_NEAR(l2[k], texel(5, 2, 2, k), 1e-6);
    }
    pw_tile3_sample(&t, s, tt, 0.25f, 0.0f, out); /* halfway between layers 0 and 1 */
    for (k = 0; k < 4; k++) CHECK_NEAR(out[k], 0.5f * (l0[k] + l1[k]), 1e-6);
    pw_tile3_sample(&t, s, tt, 0.8f, 0.0f, out); /* p = 1.6: 0.4 of layer 1, 0.6 of layer 2 */
    for (k = 0; k < 4; k++) CHECK_NEAR(out[k], 0.4f * l1[k] + 0.6f * l2[k], 1e-6);
    pw_tile3_sample(&t, s, tt, -0.5f, 0.0f, out);
    CHECK(memcmp(out, l0, sizeof out) == 0);
    pw_tile3_sample(&t, s, tt, 7.0f, 0.0f, out);
    CHECK(memcmp(out, l2, sizeof out) == 0);
    {
        float zero = 0.0f;
        pw_tile3_sample(&t, s, tt, zero / zero, 0.0f, out);
        CHECK(memcmp(out, l0, sizeof out) == 0);
    }
    pw_tile3_free(NULL, &t);
}

/* One layer: m is ignored. */
static void t_single_layer(void)
{
    pw_tile3 t;
    float a[4], b[4];
    REQUIRE(make_tile(&t, 6, 6, 1) == PW_OK);
    pw_tile3_sample(&t, 0.3f, 0.4f, 0.0f, 0.7f, a);
    pw_tile3_sample(&t, 0.3f, 0.4f, 0.9f, 0.7f, b);
    CHECK(memcmp(a, b, sizeof a) == 0);
    pw_tile3_sample(&t, 0.3f, 0.4f, -4.0f, 0.7f, b);
    CHECK(memcmp(a, b, sizeof a) == 0);
    pw_tile3_free(NULL, &t);
}

/* Level 1 is the 2x2 box average of level 0, level 2 the 4x4 one; lod
 * between levels blends them; lod beyond the chain is clamped. */
static void t_mip(void)
{
    const int W = 8, H = 4, M = 2;
    pw_tile3 t;
    float out[4], a[4], b[4], mean[4] = {0, 0, 0, 0};
    int i, j, k, l, x, y;
    REQUIRE(make_tile(&t, W, H, M) == PW_OK);
    CHECK(t.nlevels == 4 && t.layer[0].lw[1] == 4 && t.layer[0].lh[1] == 2);
    for (l = 0; l < M; l++)
        for (j = 0; j < H / 2; j++)
            for (i = 0; i < W / 2; i++) {
                pw_tile3_sample(&t, centre_s(i, W / 2), centre_t(j, H / 2), (float)l, 1.0f, out);
                for (k = 0; k < 3; k++) {
                    float box =
                        0.25f * (texel(2 * i, 2 * j, l, k) + texel(2 * i + 1, 2 * j, l, k) +
                                 texel(2 * i, 2 * j + 1, l, k) + texel(2 * i + 1, 2 * j + 1, l, k));
                    CHECKF(out[k] - box < 2e-5f && box - out[k] < 2e-5f,
                           "layer %d level-1 texel (%d,%d) channel %d: %g vs box %g", l, i, j, k,
                           out[k], box);
                }
            }
    /* level 2 (2x1): 4x4 boxes */
    for (i = 0; i < 2; i++) {
        pw_tile3_sample(&t, centre_s(i, 2), 0.5f, 0.0f, 2.0f, out);
        for (k = 0; k < 3; k++) {
            float box = 0.0f;
            for (y = 0; y < 4; y++)
                for (x = 0; x < 4; x++) box += texel(4 * i + x, y, 0, k) / 16.0f;
            CHECK_NEAR(out[k], box, 3e-5);
        }
    }
    /* lod 0.5: halfway between lod 0 and lod 1 */
    pw_tile3_sample(&t, 0.37f, 0.61f, 0.3f, 0.0f, a);
    pw_tile3_sample(&t, 0.37f, 0.61f, 0.3f, 1.0f, b);
    pw_tile3_sample(&t, 0.37f, 0.61f, 0.3f, 0.5f, out);
    for (k = 0; k < 4; k++) CHECK_NEAR(out[k], 0.5f * (a[k] + b[k]), 1e-6);
    /* negative lod is level 0; lod beyond the chain is the 1x1 mean */
    pw_tile3_sample(&t, 0.37f, 0.61f, 0.3f, -5.0f, out);
    CHECK(memcmp(out, a, sizeof a) == 0);
    for (y = 0; y < H; y++)
        for (x = 0; x < W; x++)
            for (k = 0; k < 3; k++) mean[k] += texel(x, y, 0, k) / (float)(W * H);
    pw_tile3_sample(&t, 0.9f, 0.1f, 0.0f, 100.0f, out);
    for (k = 0; k < 3; k++) CHECK_NEAR(out[k], mean[k], 3e-5);
    pw_tile3_free(NULL, &t);
}

/* Sizes that are not powers of two: the area-weighted box filter keeps the
 * mean of the layer down to 1x1. */
static void t_odd_sizes(void)
{
    const int W = 5, H = 3, M = 2;
    pw_tile3 t;
    float out[4];
    int l, x, y, k;
    REQUIRE(make_tile(&t, W, H, M) == PW_OK);
    CHECK(t.nlevels == 3 && t.layer[1].lw[1] == 2 && t.layer[1].lh[1] == 1);
    for (l = 0; l < M; l++) {
        float mean[3] = {0, 0, 0};
        for (y = 0; y < H; y++)
            for (x = 0; x < W; x++)
                for (k = 0; k < 3; k++) mean[k] += texel(x, y, l, k) / (float)(W * H);
        pw_tile3_sample(&t, 0.2f, 0.7f, (float)l, 10.0f, out);
        for (k = 0; k < 3; k++) CHECK_NEAR(out[k], mean[k], 3e-5);
        pw_tile3_sample(&t, centre_s(4, W), centre_t(2, H), (float)l, 0.0f, out);
        for (k = 0; k < 3; k++) CHECK_NEAR(out[k], texel(4, 2, l, k), 1e-6);
    }
    pw_tile3_free(NULL, &t);
}

/* 1-4 channels: gray is replicated, missing alpha is 1, alpha is
 * premultiplied. max_levels caps the chain. */
static void t_channels(void)
{
    int c;
    for (c = 1; c <= 4; c++) {
        pw_volume v;
        pw_tile3 t;
        pw_err e;
        float out[4], g, al;
        make_tile_volume(&v, c, 4, 4, 2, 1);
        pw_err_clear(&e);
        REQUIRE(pw_tile3_create(NULL, &t, &v, 1, &e) == PW_OK);
        CHECK(t.nlevels == 1);
        pw_tile3_sample(&t, centre_s(1, 4), centre_t(2, 4), 1.0f, 3.0f, out); /* lod: no levels */
        g = texel(1, 2, 1, 0);
        al = c == 2 ? texel(1, 2, 1, 1) : c == 4 ? texel(1, 2, 1, 3) : 1.0f;
        CHECK_NEAR(out[3], al, 1e-5);
        CHECK_NEAR(out[0], g * al, 1e-5);
        CHECK_NEAR(out[1], (c >= 3 ? texel(1, 2, 1, 1) : g) * al, 1e-5);
        CHECK_NEAR(out[2], (c >= 3 ? texel(1, 2, 1, 2) : g) * al, 1e-5);
        pw_tile3_free(NULL, &t);
        pw_volume_free(NULL, &v);
    }
}

/* A plain 2D texture is the one-layer tile: image -> volume -> tile reads
 * the image with v = 0 at its bottom row. */
static void t_from_image(void)
{
    pw_image img;
    pw_volume v;
    pw_tile3 t;
    pw_err e;
    float out[4];
    int x, y;
    REQUIRE(pw_image_alloc(NULL, &img, 4, 2, 3, NULL) == PW_OK);
    for (x = 0; x < 24; x++) img.px[x] = (float)x / 23.0f;
    pw_err_clear(&e);
    REQUIRE(pw_volume_from_image(NULL, &img, &v, &e) == PW_OK);
    REQUIRE(pw_tile3_create(NULL, &t, &v, 0, &e) == PW_OK);
    for (y = 0; y < 2; y++)
        for (x = 0; x < 4; x++) {
            pw_tile3_sample(&t, centre_s(x, 4), centre_t(y, 2), 0.5f, 0.0f, out);
            CHECK_NEAR(out[0], img.px[(y * 4 + x) * 3], 2e-5);
            CHECK_NEAR(out[2], img.px[(y * 4 + x) * 3 + 2], 2e-5);
        }
    pw_tile3_free(NULL, &t);
    pw_volume_free(NULL, &v);
    pw_image_free(NULL, &img);
}

/* Coordinates that are NaN or huge read something finite (no crash). */
static void t_bad_coordinates(void)
{
    pw_tile3 t;
    float out[4], zero = 0.0f, nan = zero / zero;
    int k;
    REQUIRE(make_tile(&t, 8, 4, 3) == PW_OK);
    pw_tile3_sample(&t, nan, nan, nan, nan, out);
    for (k = 0; k < 4; k++) CHECK(out[k] >= 0.0f && out[k] <= 1.0f);
    pw_tile3_sample(&t, 1e30f, -1e30f, 1e30f, 1e30f, out);
    for (k = 0; k < 4; k++) CHECK(out[k] >= 0.0f && out[k] <= 1.0f);
    pw_tile3_sample(&t, 1.0f / zero, -1.0f / zero, -1.0f / zero, -1.0f / zero, out);
    for (k = 0; k < 4; k++) CHECK(out[k] >= 0.0f && out[k] <= 1.0f);
    pw_tile3_free(NULL, &t);
}

static void t_errors_and_alloc(void)
{
    pw_volume v;
    pw_tile3 t;
    pw_err e;
    long k;
    int ok = 0;
    memset(&v, 0, sizeof v);
    pw_err_clear(&e);
    CHECK(pw_tile3_create(NULL, &t, &v, 0, &e) == PW_ERR_INVALID && t.layer == NULL);
    REQUIRE(pw_volume_alloc(NULL, &v, 1, PW_MAX_IMAGE_DIM + 1, 1, 2, NULL) == PW_OK);
    pw_err_clear(&e);
    CHECK(pw_tile3_create(NULL, &t, &v, 0, &e) == PW_ERR_LIMIT && t.layer == NULL);
    CHECK(strstr(e.msg, "material-space tile") != NULL);
    pw_volume_free(NULL, &v);
    make_tile_volume(&v, 3, 6, 5, 4, 0);
    for (k = 0; k < 30; k++) {
        pwt_alloc_state st = {0, 0, -1};
        pw_alloc al = {pwt_malloc, pwt_realloc, pwt_free, &st};
        int rc;
        st.fail_after = k;
        pw_err_clear(&e);
        rc = pw_tile3_create(&al, &t, &v, 0, &e);
        CHECKF(rc == PW_OK || rc == PW_ERR_NOMEM, "k=%ld: rc %d", k, rc);
        if (rc == PW_OK)
            ok++;
        else
            CHECK(t.layer == NULL);
        pw_tile3_free(&al, &t);
        CHECKF(st.live == 0, "k=%ld: %ld blocks leaked", k, st.live);
    }
    CHECK(ok > 0);
    pw_volume_free(NULL, &v);
}

/* Tiles one texel wide or high (a 1 x H layer once overran a scratch
 * buffer of pw_texture_create): texel centres, wrap and the mean at the
 * top of the chain. */
static void t_thin(void)
{
    static const int sizes[5][2] = {{1, 5}, {1, 2}, {1, 1}, {5, 1}, {1, 16}};
    int n;
    for (n = 0; n < 5; n++) {
        const int W = sizes[n][0], H = sizes[n][1];
        pw_tile3 t;
        float out[4], mean = 0.0f;
        int i, j;
        REQUIRE(make_tile(&t, W, H, 2) == PW_OK);
        CHECK(t.w == W && t.h == H && t.m == 2);
        CHECK_EQ_INT(t.nlevels, 1 + (W > H ? (W > 4 ? 2 : W > 1)
                                           : (H >= 16  ? 4
                                              : H >= 4 ? 2
                                                       : H > 1)));
        for (j = 0; j < H; j++)
            for (i = 0; i < W; i++) {
                pw_tile3_sample(&t, centre_s(i, W) + 2.0f, centre_t(j, H), 1.0f, 0.0f, out);
                CHECKF(out[1] - texel(i, j, 1, 1) < 1e-6f && texel(i, j, 1, 1) - out[1] < 1e-6f,
                       "%dx%d texel (%d,%d): %g vs %g", W, H, i, j, out[1], texel(i, j, 1, 1));
                mean += texel(i, j, 1, 1) / (float)(W * H);
            }
        pw_tile3_sample(&t, 0.3f, 0.8f, 1.0f, 50.0f, out);
        CHECK_NEAR(out[1], mean, 3e-5);
        pw_tile3_free(NULL, &t);
    }
}

/* A tile of full white, opaque, sampled anywhere at any level, stays in
 * [0, 1]: the filter weights' rounding (their sum can pass 1 by an ulp)
 * must not push a value past 1 (fuzz_nrrd found 1.00000012). */
static void t_in_range(void)
{
    pw_volume v;
    pw_tile3 t;
    pw_err e;
    size_t i;
    int k, bad = 0;
    pw_rng r = pw_rng_seed(5, 1);
    pw_volume_alloc(NULL, &v, 4, 12, 10, 3, NULL);
    for (i = 0; i < (size_t)4 * 12 * 10 * 3; i++) v.px[i] = 1.0f;
    REQUIRE(pw_tile3_create(NULL, &t, &v, 0, &e) == PW_OK);
    for (i = 0; i < 20000; i++) {
        float out[4];
        pw_tile3_sample(&t, 10.0f * pw_rng_float(&r) - 5.0f, 10.0f * pw_rng_float(&r) - 5.0f, pw_rng_float(&r),
                        4.0f * pw_rng_float(&r) - 1.0f, out);
        for (k = 0; k < 4; k++) bad += !(out[k] >= 0.0f && out[k] <= 1.0f);
    }
    CHECKF(bad == 0, "%d values outside [0, 1]", bad);
    pw_tile3_free(NULL, &t);
    pw_volume_free(NULL, &v);
}

static const pwt_case cases[] = {
    {"tile3_texel_centres", t_texel_centres},
    {"tile3_in_range", t_in_range},
    {"tile3_periodic", t_periodic},
    {"tile3_wrap_edges", t_wrap_edges},
    {"tile3_bilinear", t_bilinear},
    {"tile3_layers", t_layers},
    {"tile3_single_layer", t_single_layer},
    {"tile3_mip", t_mip},
    {"tile3_odd_sizes", t_odd_sizes},
    {"tile3_thin", t_thin},
    {"tile3_channels", t_channels},
    {"tile3_from_image", t_from_image},
    {"tile3_bad_coordinates", t_bad_coordinates},
    {"tile3_errors_and_alloc", t_errors_and_alloc},
};
PWT_MAIN(cases)
