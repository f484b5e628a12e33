/* Tests of src/common/quilt.h: alpha-expansion graph-cut compositing and
 * making images tile. */
#include "../src/common/quilt.h"
#include "../src/common/png.h"
#include "../src/common/rng.h"
#include "../src/common/vec.h"
#include "pwtest.h"

/* Total seam cost of the current labelling. */
static double quilt_energy(const pw_quilt *q)
{
    double s = 0.0;
    int i, k, n = q->w * q->h, nb[2];
    for (i = 0; i < n; i++) {
        pw__quilt_neighbours(q, i, nb);
        for (k = 0; k < 2; k++)
            if (nb[k] >= 0) s += pw_quilt_pair_cost(q, i, nb[k], q->label[i], q->label[nb[k]]);
    }
    return s;
}

/* Mean colour jump between neighbouring pixels, and across the wrap. */
static void jumps(const pw_image *im, double *inside, double *wrap)
{
    double si = 0.0, sw = 0.0;
    long ni = 0, nw = 0;
    int x, y, k;
    for (y = 0; y < im->h; y++)
        for (x = 0; x < im->w; x++) {
            const float *p = im->px + ((size_t)y * im->w + x) * im->c;
            const float *r = im->px + ((size_t)y * im->w + (x + 1) % im->w) * im->c;
            const float *d = im->px + ((size_t)((y + 1) % im->h) * im->w + x) * im->c;
            double a = 0.0, b = 0.0;
            for (k = 0; k < im->c; k++) {
                a += fabs(p[k] - r[k]);
                b += fabs(p[k] - d[k]);
            }
            if (x + 1 < im->w) si += a, ni++;
            else sw += a, nw++;
            if (y + 1 < im->h) si += b, ni++;
            else sw += b, nw++;
        }
    *inside = si / ni;
    *wrap = sw / nw;
}

/* A smooth, clearly non-periodic image: a gradient plus smooth bumps. */
static void make_gradient(pw_image *im, int w, int h)
{
    int x, y;
    REQUIRE(pw_image_alloc(NULL, im, w, h, 3, NULL) == PW_OK);
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            float *p = im->px + ((size_t)y * w + x) * 3;
            p[0] = (float)x / w;
            p[1] = (float)y / h;
            p[2] = 0.5f + 0.4f * (float)pw_sin(0.3 * x) * (float)pw_cos(0.21 * y);
        }
}

static void t_make_tileable(void)
{
    pw_image in, out;
    double i0, w0, i1, w1;
    pw_err e;
    pw_err_clear(&e);
    make_gradient(&in, 64, 48);
    REQUIRE(pw_quilt_make_tileable(NULL, &in, &out, &e) == PW_OK);
    jumps(&in, &i0, &w0);
    jumps(&out, &i1, &w1);
    pwt_info("input: inside %.4f, across the wrap %.4f; tileable: inside %.4f, across the wrap %.4f",
             i0, w0, i1, w1);
    CHECK(w0 > 10 * i0);     /* the input does not tile */
    CHECK(w1 < 3 * i1);      /* the output does */
    CHECK_EQ_INT(out.w, 64);
    CHECK_EQ_INT(out.h, 48);
    pw_image_free(NULL, &in);
    pw_image_free(NULL, &out);
}

/* Real textures: GIMP patterns are already periodic, a crop is not. */
static void t_make_tileable_real(void)
{
    const char *path = pwt_data("textures/burlap.ppm");
    pw_image full, crop, out;
    double i0, w0, i1, w1;
    pw_err e;
    int y;
    if (!path) return;
    pw_err_clear(&e);
    REQUIRE(pw_image_load(NULL, path, &full, &e) == PW_OK);
    REQUIRE(pw_image_alloc(NULL, &crop, 61, 53, full.c, &e) == PW_OK);
    for (y = 0; y < 53; y++)
        memcpy(crop.px + (size_t)y * 61 * full.c, full.px + ((size_t)(y + 7) * full.w + 5) * full.c,
               sizeof(float) * 61 * full.c);
    REQUIRE(pw_quilt_make_tileable(NULL, &crop, &out, &e) == PW_OK);
    jumps(&crop, &i0, &w0);
    jumps(&out, &i1, &w1);
    pwt_info("burlap crop: wrap/inside %.2f before, %.2f after", w0 / i0, w1 / i1);
    CHECK(w1 / i1 < w0 / i0);
    CHECK(w1 < 1.5 * i1);
    pw_image_free(NULL, &full);
    pw_image_free(NULL, &crop);
    pw_image_free(NULL, &out);
}

/* Two sources that agree only on columns 10 and 11: the only free seam is
 * between them, the constrained end columns keep their labels, and the
 * energy is zero. */
static void t_seam_follows_agreement(void)
{
    enum { W = 16, H = 8 };
    float src[2 * W * H];
    int label[W * H], x, y;
    uint32_t allowed[W * H];
    pw_quilt q;
    pw_err e;
    pw_err_clear(&e);
    for (y = 0; y < H; y++)
        for (x = 0; x < W; x++) {
            src[y * W + x] = 0.05f * (float)x;
            src[W * H + y * W + x] = 0.05f * (float)x + (x == 10 || x == 11 ? 0.0f : 0.5f);
            label[y * W + x] = 0;
            allowed[y * W + x] = x == 0 ? 1u : (x == W - 1 ? 2u : 3u);
        }
    for (y = 0; y < H; y++) label[y * W + W - 1] = 1;
    q.w = W;
    q.h = H;
    q.c = 1;
    q.nlabels = 2;
    q.src = src;
    q.label = label;
    q.allowed = allowed;
    q.wrap_x = q.wrap_y = 0;
    q.motif = NULL;
    q.motif_weight = 0.0f;
    REQUIRE(pw_quilt_optimize(NULL, &q, 3, &e) == PW_OK);
    for (y = 0; y < H; y++) {
        CHECK(label[y * W] == 0 && label[y * W + W - 1] == 1);
        for (x = 0; x < W; x++) CHECK(label[y * W + x] == (x >= 11));
    }
    CHECK_NEAR(quilt_energy(&q), 0.0, 1e-9);
}

/* With the four quadrants' corners pinned to four labels, alpha-expansion
 * lowers the energy of a random labelling a lot, keeps every constraint,
 * and gives the same labelling twice. */
static void t_energy_decreases(void)
{
    enum { W = 24, H = 24, L = 4 };
    static float src[L * W * H * 3];
    int label[W * H], label2[W * H], i;
    uint32_t allowed[W * H];
    pw_rng r = pw_rng_seed(3u, 0u);
    pw_quilt q;
    double before, after;
    pw_err e;
    pw_err_clear(&e);
    for (i = 0; i < L * W * H * 3; i++) src[i] = pw_rng_float(&r);
    for (i = 0; i < W * H; i++) {
        int x = i % W, y = i / W, quad = (x >= W / 2) + 2 * (y >= H / 2);
        int pinned = (x < 3 || x >= W - 3) && (y < 3 || y >= H - 3);
        allowed[i] = pinned ? 1u << quad : 0xFu;
        label[i] = pinned ? quad : (int)pw_rng_below(&r, L);
    }
    memcpy(label2, label, sizeof label);
    q.w = W;
    q.h = H;
    q.c = 3;
    q.nlabels = L;
    q.src = src;
    q.label = label;
    q.allowed = allowed;
    q.wrap_x = q.wrap_y = 0;
    q.motif = NULL;
    q.motif_weight = 0.0f;
    before = quilt_energy(&q);
    REQUIRE(pw_quilt_optimize(NULL, &q, 4, &e) == PW_OK);
    after = quilt_energy(&q);
    pwt_info("energy %.2f -> %.2f", before, after);
    CHECK(after > 0.0 && after < 0.5 * before);
    for (i = 0; i < W * H; i++) CHECK(allowed[i] >> label[i] & 1u);
    q.label = label2;
    REQUIRE(pw_quilt_optimize(NULL, &q, 4, &e) == PW_OK);
    CHECK(!memcmp(label, label2, sizeof label));
}

static void t_alloc_failures(void)
{
    pw_image in, out;
    int budget, done = 0;
    make_gradient(&in, 32, 32);
    for (budget = 0; budget < 200 && !done; budget++) {
        pwt_alloc_state st = {0, 0, 0};
        pw_alloc a = {pwt_malloc, pwt_realloc, pwt_free, NULL};
        pw_err e;
        int r;
        st.fail_after = budget;
        a.user = &st;
        pw_err_clear(&e);
        r = pw_quilt_make_tileable(&a, &in, &out, &e);
        if (r == PW_OK) {
            done = 1;
            pw_image_free(&a, &out);
        } else
            CHECKF(r == PW_ERR_NOMEM, "budget %d: %s", budget, e.msg);
        CHECKF(st.live == 0, "budget %d: %ld blocks leaked", budget, st.live);
    }
    CHECK(done);
    pwt_info("%d allocation failure points exercised", budget - 1);
    pw_image_free(NULL, &in);
}

/* Discs of radius 10 at (16,16), (48,16), (16,48), (48,48) on a 64 x 64
 * periodic ground; colour `disc` inside, 0.2 outside. */
static void discs(float *px, float disc)
{
    int x, y;
    for (y = 0; y < 64; y++)
        for (x = 0; x < 64; x++) {
            int dx = (x % 32) - 16, dy = (y % 32) - 16;
            px[y * 64 + x] = dx * dx + dy * dy < 100 ? disc : 0.2f;
        }
}

/* The motif map finds the discs' insides (1) and tells their outlines and
 * the ground that wraps around them (0) apart; a seam through the discs,
 * where the two sources' discs differ in colour, cuts motifs, and the
 * optimised seam (colour and motif cost) runs through the ground and cuts
 * none. */
static void t_motif_map(void)
{
    static float src[2 * 64 * 64], motif[2 * 64 * 64];
    int label[64 * 64], i, x, y;
    uint32_t allowed[64 * 64];
    float edge;
    pw_seam_stats st = {0, 0};
    pw_quilt q;
    pw_image view;
    pw_err e;
    pw_err_clear(&e);
    discs(src, 0.8f);
    discs(src + 64 * 64, 0.5f);
    view.w = view.h = 64, view.c = 1, view.bits = 32, view.px = src;
    REQUIRE(pw_quilt_motif_map(NULL, &view, motif, &edge, &e) == PW_OK);
    view.px = src + 64 * 64;
    REQUIRE(pw_quilt_motif_map(NULL, &view, motif + 64 * 64, &edge, &e) == PW_OK);
    CHECK(motif[16 * 64 + 16] == 1.0f && motif[48 * 64 + 48] == 1.0f); /* disc centres */
    CHECK(motif[16 * 64 + 26] == 0.0f && motif[16 * 64 + 6] == 0.0f); /* outlines */
    CHECK(motif[0] == 0.0f && motif[32 * 64 + 32] == 0.0f);            /* ground */
    CHECKF(edge > 0.0f, "edge threshold %g", edge);
    /* left columns from source 0, right from 1; x < 3 and x >= 61 pinned */
    for (y = 0; y < 64; y++)
        for (x = 0; x < 64; x++) {
            i = y * 64 + x;
            allowed[i] = x < 3 ? 1u : (x >= 61 ? 2u : 3u);
            label[i] = x < 16 ? 0 : 1; /* a seam at x = 16, through the discs */
        }
    memset(&q, 0, sizeof q);
    q.w = q.h = 64;
    q.c = 1;
    q.nlabels = 2;
    q.src = src;
    q.label = label;
    q.allowed = allowed;
    q.motif = motif;
    pw_quilt_seam_stats(&q, edge, &st);
    CHECKF(st.pairs == 64 && st.cut > 0, "seam through the discs: %ld pairs, %ld cut", st.pairs, st.cut);
    q.motif_weight = 1.0f;
    REQUIRE(pw_quilt_optimize(NULL, &q, 3, &e) == PW_OK);
    st.pairs = st.cut = 0;
    pw_quilt_seam_stats(&q, edge, &st);
    pwt_info("after optimising with the motif cost: %ld seam pairs, %ld cut a motif", st.pairs, st.cut);
    CHECKF(st.pairs > 0 && st.cut == 0, "%ld of %ld seam pairs cut a disc", st.cut, st.pairs);
}

static const pwt_case cases[] = {
    {"quilt/make_tileable", t_make_tileable},
    {"quilt/make_tileable_real", t_make_tileable_real},
    {"quilt/seam_follows_agreement", t_seam_follows_agreement},
    {"quilt/energy_decreases", t_energy_decreases},
    {"quilt/alloc_failures", t_alloc_failures},
    {"quilt/motif_map", t_motif_map},
};
PWT_MAIN(cases)
