/* Tests of lapped.h's texture patches (§3.1), their polygonal hulls (§3.3),
 * the transparent mipmap border (§4) and the built-in meshes and textures.
 * A few patches are written to /tmp/pw_lapped_patch_*.ppm for a visual
 * check (composited over a grey checkerboard). */
#define LAPPED_STATIC /* static: only what the tests call is compiled */
#define LAPPED_IMPLEMENTATION
#include "lapped.h"
#include "pwtest.h"
#include <time.h>

/* ------------------------------------------------------------ helpers */

static lapped_image make_image(int w, int h, int c, float fill)
{
    lapped_image im;
    int i;
    memset(&im, 0, sizeof im);
    im.width = w;
    im.height = h;
    im.channels = c;
    im.pixels = (float *)malloc(sizeof(float) * (size_t)w * h * c);
    for (i = 0; im.pixels && i < w * h * c; i++) im.pixels[i] = fill;
    return im;
}

static float alpha_at(const lapped_image *p, int x, int y) { return p->pixels[((size_t)y * p->width + x) * 4 + 3]; }

/* The patch over a checkerboard, as a binary PPM. */
static void write_patch(const char *name, const lapped_image *p)
{
    char path[256];
    FILE *f;
    int x, y, k;
    snprintf(path, sizeof path, "/tmp/pw_lapped_patch_%s.ppm", name);
    f = fopen(path, "wb");
    if (!f) return;
    fprintf(f, "P6\n%d %d\n255\n", p->width, p->height);
    for (y = 0; y < p->height; y++)
        for (x = 0; x < p->width; x++) {
            const float *q = p->pixels + ((size_t)y * p->width + x) * p->channels;
            float bg = ((x / 8 + y / 8) & 1) ? 0.55f : 0.75f, a = p->channels == 4 ? q[3] : 1.0f;
            for (k = 0; k < 3; k++) {
                float c = p->channels >= 3 ? q[k] : q[0];
                fputc((int)(pw_clampf(c * a + bg * (1 - a), 0, 1) * 255 + 0.5f), f);
            }
        }
    fclose(f);
}

/* Pixels with alpha > 0 form one 4-connected set; returns its size (or -1
 * when it is not connected). */
static long connected_size(const lapped_image *p)
{
    int w = p->width, h = p->height, n = w * h, i, top = 0, seen = 0, total = 0;
    int *stack = (int *)malloc(sizeof(int) * (size_t)n);
    char *mark = (char *)calloc((size_t)n, 1);
    for (i = 0; i < n; i++) total += alpha_at(p, i % w, i / w) > 0;
    for (i = 0; i < n && top == 0 && seen == 0; i++)
        if (alpha_at(p, i % w, i / w) > 0) mark[i] = 1, stack[top++] = i, seen = 1;
    while (top > 0) {
        int c = stack[--top], k;
        for (k = 0; k < 4; k++) {
            int x = c % w + (k == 0 ? -1 : k == 1 ? 1 : 0), y = c / w + (k == 2 ? -1 : k == 3 ? 1 : 0);
            if (x < 0 || y < 0 || x >= w || y >= h || mark[y * w + x] || !(alpha_at(p, x, y) > 0)) continue;
            mark[y * w + x] = 1;
            stack[top++] = y * w + x;
            seen++;
        }
    }
    free(stack);
    free(mark);
    return seen == total ? total : -1;
}

/* Every corner of every pixel with alpha > 0 is inside the patch's hull. */
static long hull_misses(const lapped_image *p, int *nverts)
{
    pw_image v = lapped__pw_image(p);
    pw_polyhull h;
    long miss = 0;
    int x, y, k;
    if (lapped__patch_hull(NULL, &v, &h, NULL) != PW_OK) return -1;
    for (y = 0; y < p->height; y++)
        for (x = 0; x < p->width; x++)
            for (k = 0; alpha_at(p, x, y) > 0 && k < 4; k++)
                miss += !pw_polyhull_contains(&h, (float)(x + (k & 1)) / (float)p->width,
                                              1.0f - (float)(y + (k >> 1)) / (float)p->height);
    *nverts = h.n;
    pw_polyhull_free(NULL, &h);
    return miss;
}

static int border_clear(const lapped_image *p)
{
    int x, y;
    for (y = 0; y < p->height; y++)
        for (x = 0; x < p->width; x++)
            if ((x == 0 || y == 0 || x == p->width - 1 || y == p->height - 1) && alpha_at(p, x, y) != 0) return 0;
    return 1;
}

/* ------------------------------------------------------------ §3.1 patches */

static void t_circle(void)
{
    lapped_options o = lapped_default_options();
    lapped_image tex, patch;
    lapped_error err;
    int x, y, bad_out = 0, bad_in = 0, bad_rgb = 0;
    tex = make_image(96, 64, 3, 0.25f);
    for (x = 0; x < 96 * 64 * 3; x++) tex.pixels[x] = (float)(x % 7) / 7.0f;
    o.alpha = LAPPED_ALPHA_CIRCLE;
    REQUIRE(lapped_make_patch(&tex, NULL, &o, &patch, &err) == LAPPED_OK);
    CHECK(patch.width == 96 && patch.height == 64 && patch.channels == 4);
    for (y = 0; y < 64; y++)
        for (x = 0; x < 96; x++) { /* R = 32: transparent outside, opaque 1 + 3 px inside */
            double d = sqrt((x + 0.5 - 48) * (x + 0.5 - 48) + (y + 0.5 - 32) * (y + 0.5 - 32));
            float a = alpha_at(&patch, x, y);
            if (d > 32 - 0.5 && a != 0) bad_out++;
            if (d < 32 - 5.5 && a != 1) bad_in++;
            if (memcmp(patch.pixels + 4 * (y * 96 + x), tex.pixels + 3 * (y * 96 + x), 3 * sizeof(float))) bad_rgb++;
        }
    CHECK_EQ_INT(bad_out, 0);
    CHECK_EQ_INT(bad_in, 0);
    CHECK_EQ_INT(bad_rgb, 0);
    CHECK(connected_size(&patch) > 0);
    CHECK(alpha_at(&patch, 48, 32) == 1.0f && alpha_at(&patch, 48, 0) == 0.0f);
    write_patch("circle", &patch);
    lapped_image_free(&patch);
    free(tex.pixels);
}

static void t_splotch(void)
{
    lapped_options o = lapped_default_options();
    lapped_image tex, p1, p2;
    int s, sizes[4] = {32, 128, 200, 333};
    for (s = 0; s < 8; s++) {
        int w = sizes[s % 4], h = sizes[(s + 1) % 4], x, y, lox = w, hix = -1, loy = h, hiy = -1;
        long n;
        tex = make_image(w, h, 3, 0.5f);
        o.alpha = s % 2 ? LAPPED_ALPHA_SPLOTCH : LAPPED_ALPHA_AUTO; /* AUTO on RGB: a splotch */
        o.seed = (unsigned long long)s * 7919u;
        REQUIRE(lapped_make_patch(&tex, NULL, &o, &p1, NULL) == LAPPED_OK);
        REQUIRE(lapped_make_patch(&tex, NULL, &o, &p2, NULL) == LAPPED_OK);
        CHECK(!memcmp(p1.pixels, p2.pixels, sizeof(float) * 4 * w * h)); /* deterministic */
        n = connected_size(&p1);
        CHECKF(n > 0, "splotch %d is not one connected blob", s);
        CHECKF(n > 0.3 * w * h, "splotch %d covers only %ld of %d pixels", s, n, w * h);
        CHECK(border_clear(&p1));
        for (y = 0; y < h; y++)
            for (x = 0; x < w; x++)
                if (alpha_at(&p1, x, y) > 0) {
                    lox = x < lox ? x : lox, hix = x > hix ? x : hix;
                    loy = y < loy ? y : loy, hiy = y > hiy ? y : hiy;
                }
        CHECKF(hix - lox + 1 >= 0.9 * w - 4 && hiy - loy + 1 >= 0.9 * h - 4, "splotch %d spans %dx%d of %dx%d", s, hix - lox,
               hiy - loy, w, h);
        if (s == 2) {
            write_patch("splotch", &p1);
            o.seed++;
            lapped_image_free(&p2);
            REQUIRE(lapped_make_patch(&tex, NULL, &o, &p2, NULL) == LAPPED_OK);
            CHECK(memcmp(p1.pixels, p2.pixels, sizeof(float) * 4 * w * h) != 0); /* the seed matters */
        }
        lapped_image_free(&p1);
        lapped_image_free(&p2);
        free(tex.pixels);
    }
}

static void t_mask(void)
{
    lapped_options o = lapped_default_options();
    lapped_image tex = make_image(60, 40, 3, 0.8f), mask = make_image(60, 40, 2, 0.0f), p;
    int x, y, bad = 0;
    for (y = 5; y < 35; y++)
        for (x = 10; x < 50; x++) mask.pixels[2 * (y * 60 + x)] = x < 30 ? 1.0f : 0.5f; /* channel 2 ignored */
    REQUIRE(lapped_make_patch(&tex, &mask, &o, &p, NULL) == LAPPED_OK); /* AUTO with a mask: the mask */
    for (y = 0; y < 40; y++)
        for (x = 0; x < 60; x++) {
            float a = alpha_at(&p, x, y);
            int in = y >= 5 && y < 35 && x >= 10 && x < 50;
            if (!in && a != 0) bad++;
            if (in && a > (x < 30 ? 1.0f : 0.5f)) bad++;
        }
    CHECK_EQ_INT(bad, 0);
    CHECK(alpha_at(&p, 20, 20) == 1.0f && alpha_at(&p, 40, 20) == 0.5f);
    lapped_image_free(&p);
    o.alpha = LAPPED_ALPHA_MASK;
    REQUIRE(lapped_make_patch(&tex, &mask, &o, &p, NULL) == LAPPED_OK);
    CHECK(alpha_at(&p, 20, 20) == 1.0f && alpha_at(&p, 10, 20) == 0.0f);
    lapped_image_free(&p);
    free(tex.pixels);
    free(mask.pixels);
}

/* §3.1 fall-off: 0 at the boundary, 1 at `falloff` pixels inside it. */
static void t_falloff(void)
{
    lapped_options o = lapped_default_options();
    lapped_image tex = make_image(64, 64, 4, 1.0f), p; /* opaque RGBA: only the image border */
    float widths[3] = {3.0f, 6.0f, 0.5f};
    int k, x;
    for (k = 0; k < 3; k++) {
        o.falloff = widths[k];
        REQUIRE(lapped_make_patch(&tex, NULL, &o, &p, NULL) == LAPPED_OK);
        CHECK(border_clear(&p));
        for (x = 0; x < 32; x++) { /* along the middle row from the left border */
            float want = pw_clampf((float)x / widths[k], 0, 1);
            CHECK_NEAR(alpha_at(&p, x, 32), want, 1e-6);
        }
        CHECK(alpha_at(&p, (int)widths[k], 32) == 1.0f || widths[k] != (int)widths[k]);
        if (k == 0) write_patch("falloff3", &p);
        lapped_image_free(&p);
    }
    /* near a corner the nearest outside pixel is straight across, 6 px away */
    o.falloff = 10.0f;
    REQUIRE(lapped_make_patch(&tex, NULL, &o, &p, NULL) == LAPPED_OK);
    CHECK_NEAR(alpha_at(&p, 5, 5), (6.0f - 1.0f) / 10.0f, 1e-6); /* nearest: (-1,5), distance 6 */
    CHECK_NEAR(alpha_at(&p, 5, 30), 0.5f, 1e-6);
    lapped_image_free(&p);
    { /* around a single transparent pixel: radial ramp, distance sqrt(dx^2+dy^2) */
        int y;
        tex.pixels[4 * (32 * 64 + 32) + 3] = 0.0f;
        REQUIRE(lapped_make_patch(&tex, NULL, &o, &p, NULL) == LAPPED_OK);
        for (y = 28; y <= 36; y++)
            for (x = 28; x <= 36; x++) {
                double d = sqrt((double)(x - 32) * (x - 32) + (double)(y - 32) * (y - 32));
                CHECK_NEAR(alpha_at(&p, x, y), pw_clampf((float)(d - 1) / 10.0f, 0, 1), 1e-6);
            }
        lapped_image_free(&p);
    }
    free(tex.pixels);
}

static void t_image_alpha(void)
{
    lapped_options o = lapped_default_options();
    lapped_image ga = make_image(40, 30, 2, 0.3f), p;
    int x, y;
    for (y = 0; y < 30; y++)
        for (x = 0; x < 40; x++) ga.pixels[2 * (y * 40 + x) + 1] = (x > 20) ? 0.75f : 0.0f;
    REQUIRE(lapped_make_patch(&ga, NULL, &o, &p, NULL) == LAPPED_OK);
    CHECK(p.channels == 4);
    CHECK(alpha_at(&p, 10, 15) == 0.0f && alpha_at(&p, 21, 15) == 0.0f);
    CHECK_NEAR(alpha_at(&p, 30, 15), 0.75f, 1e-6);
    CHECK_NEAR(alpha_at(&p, 22, 15), 0.75f / 3.0f, 1e-6);
    CHECK(p.pixels[4 * (15 * 40 + 30)] == 0.3f && p.pixels[4 * (15 * 40 + 30) + 2] == 0.3f); /* grey to RGB */
    lapped_image_free(&p);
    free(ga.pixels);
}

static int fails(const lapped_image *tex, const lapped_image *mask, const lapped_options *o, int code,
                 const char *needle)
{
    lapped_image p;
    lapped_error err;
    lapped_result r = lapped_make_patch(tex, mask, o, &p, &err);
    if (r == LAPPED_OK) lapped_image_free(&p);
    if ((int)r != code || err.code != r || !strstr(err.message, needle)) {
        printf("     got %d '%s', wanted %d '%s'\n", (int)r, r ? err.message : "", code, needle);
        return 0;
    }
    return p.pixels == NULL;
}

static void t_errors(void)
{
    lapped_options o = lapped_default_options();
    lapped_image tex = make_image(30, 20, 3, 0.5f), rgba = make_image(30, 20, 4, 0.0f);
    lapped_image mask = make_image(30, 21, 1, 1.0f), zero = make_image(30, 20, 1, 0.0f), tiny = make_image(2, 2, 3, 1);
    o.alpha = LAPPED_ALPHA_MASK;
    CHECK(fails(&tex, &mask, &o, LAPPED_ERR_INVALID, "mask is 30x21 but the texture is 30x20"));
    CHECK(fails(&tex, &zero, &o, LAPPED_ERR_INVALID, "mask is all zero"));
    CHECK(fails(&tex, NULL, &o, LAPPED_ERR_INVALID, "needs a mask"));
    o.alpha = LAPPED_ALPHA_CIRCLE;
    CHECK(fails(&tex, &zero, &o, LAPPED_ERR_INVALID, "a mask was given"));
    o.alpha = LAPPED_ALPHA_AUTO;
    CHECK(fails(&rgba, NULL, &o, LAPPED_ERR_INVALID, "alpha channel is fully transparent"));
    o.alpha = LAPPED_ALPHA_IMAGE;
    CHECK(fails(&tex, NULL, &o, LAPPED_ERR_INVALID, "has 3 channels and no alpha"));
    o.alpha = 17;
    CHECK(fails(&tex, NULL, &o, LAPPED_ERR_INVALID, "unknown alpha mode 17"));
    o.alpha = LAPPED_ALPHA_AUTO;
    o.falloff = (float)sqrt(-1.0);
    CHECK(fails(&tex, NULL, &o, LAPPED_ERR_INVALID, "falloff must be a finite number"));
    o.falloff = -1.0f;
    CHECK(fails(&tex, NULL, &o, LAPPED_ERR_INVALID, "falloff must be a finite number"));
    o.falloff = 1e30f * 1e30f;
    CHECK(fails(&tex, NULL, &o, LAPPED_ERR_INVALID, "falloff must be a finite number"));
    o.falloff = 0.0f; /* zero means the default */
    CHECK(fails(&tiny, NULL, &o, LAPPED_ERR_INVALID, "fully transparent after the 3-pixel fall-off"));
    tex.pixels[3 * 31 + 1] = (float)sqrt(-1.0);
    CHECK(fails(&tex, NULL, &o, LAPPED_ERR_INVALID, "texture: pixel 31 is not a finite number"));
    tex.pixels[3 * 31 + 1] = 0.5f;
    mask.height = 20;
    mask.pixels[7] = 1e30f * 1e30f;
    o.alpha = LAPPED_ALPHA_MASK;
    CHECK(fails(&tex, &mask, &o, LAPPED_ERR_INVALID, "mask: pixel 7 is not a finite number"));
    CHECK(fails(NULL, NULL, &o, LAPPED_ERR_INVALID, "texture: empty image"));
    CHECK(lapped_make_patch(&tex, NULL, NULL, NULL, NULL) == LAPPED_ERR_INVALID);
    free(tex.pixels);
    free(rgba.pixels);
    free(mask.pixels);
    free(zero.pixels);
    free(tiny.pixels);
}

/* Every allocation failing in turn: a clean error, nothing leaked. */
static void t_allocator(void)
{
    pwt_alloc_state st = {0, 0, -1};
    lapped_options o = lapped_default_options();
    lapped_image tex = make_image(50, 40, 3, 0.5f), p;
    lapped_mesh m;
    long total, k;
    int which;
    o.allocator.malloc_fn = pwt_malloc;
    o.allocator.realloc_fn = pwt_realloc;
    o.allocator.free_fn = pwt_free;
    o.allocator.user = &st;
    for (which = 0; which < 3; which++) {
        st.calls = 0;
        st.fail_after = -1;
        if (which == 1) {
            REQUIRE(lapped_builtin_mesh("bumpy", &o, &m, NULL) == LAPPED_OK);
            lapped_mesh_free(&m);
        } else {
            REQUIRE((which == 0 ? lapped_make_patch(&tex, NULL, &o, &p, NULL)
                                : lapped_builtin_exemplar("scales", 16, &o, &p, NULL)) == LAPPED_OK);
            lapped_image_free(&p);
        }
        CHECK(st.live == 0);
        total = st.calls;
        for (k = 0; k < total; k++) {
            lapped_result r;
            st.calls = 0;
            st.fail_after = k;
            r = which == 0 ? lapped_make_patch(&tex, NULL, &o, &p, NULL)
                : which == 1 ? lapped_builtin_mesh("bumpy", &o, &m, NULL)
                             : lapped_builtin_exemplar("scales", 16, &o, &p, NULL);
            CHECKF(r == LAPPED_ERR_NOMEM, "call %d, failure at %ld: %d", which, k, (int)r);
            CHECKF(st.live == 0, "call %d: leak after a failure at %ld", which, k);
        }
    }
    free(tex.pixels);
}

/* §3.3: the hull of every built-in patch contains all its non-zero alpha. */
static void t_hulls(void)
{
    static const char *names[3] = {"scales", "stripes", "dots"};
    lapped_options o = lapped_default_options();
    int k, mode, worst = 0;
    for (k = 0; k < 3; k++)
        for (mode = LAPPED_ALPHA_CIRCLE; mode <= LAPPED_ALPHA_SPLOTCH; mode++) {
            lapped_image tex, p;
            int nv = 0;
            long miss;
            o.alpha = mode;
            o.seed = (unsigned long long)(k * 10 + mode);
            REQUIRE(lapped_builtin_exemplar(names[k], 96 + 80 * k, &o, &tex, NULL) == LAPPED_OK);
            REQUIRE(lapped_make_patch(&tex, NULL, &o, &p, NULL) == LAPPED_OK);
            miss = hull_misses(&p, &nv);
            CHECKF(miss == 0, "%s, mode %d: %ld pixel corners outside the hull", names[k], mode, miss);
            CHECK(nv >= 3 && nv <= 32);
            worst = nv > worst ? nv : worst;
            if (mode == LAPPED_ALPHA_SPLOTCH) {
                char name[32];
                snprintf(name, sizeof name, "%s_splotch", names[k]);
                write_patch(name, &p);
            }
            lapped_image_free(&tex);
            lapped_image_free(&p);
        }
    { /* and the hull refuses what is not RGBA */
        pw_image g;
        pw_polyhull h;
        pw_err e;
        float px[4] = {1, 1, 1, 1};
        g.w = 2, g.h = 2, g.c = 1, g.bits = 8, g.px = px;
        pw_err_clear(&e);
        CHECK(lapped__patch_hull(NULL, &g, &h, &e) == PW_ERR_INVALID && strstr(e.msg, "RGBA"));
    }
    pwt_info("hulls of 9 built-in patches: at most %d vertices", worst);
}

/* ------------------------------------------------------------ §4 border */

static void t_clear_border(void)
{
    pw_image img;
    pw_texture tex;
    int L, x, y, k, ok = 1;
    REQUIRE(pw_image_alloc(NULL, &img, 37, 20, 4, NULL) == PW_OK);
    for (k = 0; k < 37 * 20 * 4; k++) img.px[k] = 0.8f;
    REQUIRE(pw_texture_create(NULL, &tex, &img, 0, NULL) == PW_OK);
    pw_texture_clear_border(&tex, 2);
    for (L = 0; L < tex.nlevels; L++) {
        int W = tex.lw[L], H = tex.lh[L], cleared = W > 2 && H > 2;
        for (y = 0; y < H; y++)
            for (x = 0; x < W; x++) {
                const uint16_t *t = tex.level[L] + ((size_t)y * W + x) * 4;
                int ring = x == 0 || y == 0 || x == W - 1 || y == H - 1;
                int zero = !t[0] && !t[1] && !t[2] && !t[3];
                if (cleared && ring != zero) ok = 0;
                if (!cleared && zero) ok = 0;
            }
    }
    CHECKF(ok, "levels %dx%d .. %dx%d", tex.lw[0], tex.lh[0], tex.lw[tex.nlevels - 1], tex.lh[tex.nlevels - 1]);
    CHECK(tex.nlevels == 6 && tex.lw[2] == 9 && tex.lh[2] == 5 && tex.lh[3] == 2); /* 37x20 .. 1x1 */
    /* sampling with clamped coordinates outside the patch now gives transparency */
    {
        float out[4];
        pw_texture_sample(&tex, -0.5f, 0.5f, 1.5f, PW_FILTER_TRILINEAR, PW_WRAP_CLAMP, out);
        CHECK(out[3] == 0.0f);
        pw_texture_sample(&tex, 0.5f, 0.5f, 0.0f, PW_FILTER_TRILINEAR, PW_WRAP_CLAMP, out);
        CHECK(out[3] > 0.79f);
    }
    pw_texture_clear_border(&tex, 1000); /* nothing is larger: no change */
    CHECK(tex.level[0][4 * (10 * 37 + 10) + 3] != 0);
    pw_texture_clear_border(NULL, 2);
    pw_texture_free(NULL, &tex);
    pw_image_free(NULL, &img);
}

/* ------------------------------------------------------------ built-in data */

/* Closed (or one boundary loop for the disc), manifold, consistently
 * oriented, outward (positive signed volume / +z normals), the right
 * counts, no degenerate triangle. */
static void check_mesh(const char *name, int nv, int nf, int chi, int loops)
{
    lapped_options o = lapped_default_options();
    lapped_mesh m;
    pw_hmesh hm;
    pw_err e;
    double vol = 0, minarea = 1e30, lo[3] = {1e30, 1e30, 1e30}, hi[3] = {-1e30, -1e30, -1e30};
    int f, k, upz = 0;
    pw_err_clear(&e);
    REQUIRE(lapped_builtin_mesh(name, &o, &m, NULL) == LAPPED_OK);
    CHECK_EQ_INT(m.nverts, nv);
    CHECK_EQ_INT(m.nfaces, nf);
    for (f = 0; f <= m.nfaces; f++) CHECK(m.face_start[f] == 3 * f);
    REQUIRE(pw_hmesh_build(NULL, m.nverts, m.nfaces, m.face_start, m.face_verts, &hm, &e) == PW_OK);
    CHECKF(hm.nv - hm.ne + hm.nf == chi, "%s: Euler characteristic %d", name, hm.nv - hm.ne + hm.nf);
    CHECKF(hm.nloops == loops, "%s: %d boundary loops", name, hm.nloops);
    for (k = 0; k < hm.nv; k++) CHECK(hm.vout[k] >= 0); /* no isolated vertex */
    for (f = 0; f < m.nfaces; f++) {
        pw_v3 a = pw_v3_load(m.positions + 3 * m.face_verts[3 * f]);
        pw_v3 b = pw_v3_load(m.positions + 3 * m.face_verts[3 * f + 1]);
        pw_v3 c = pw_v3_load(m.positions + 3 * m.face_verts[3 * f + 2]);
        pw_v3 n = pw_v3_cross(pw_v3_sub(b, a), pw_v3_sub(c, a));
        vol += pw_v3_dot(a, pw_v3_cross(b, c)) / 6.0;
        minarea = 0.5 * pw_v3_len(n) < minarea ? 0.5 * pw_v3_len(n) : minarea;
        upz += n.z > 0;
    }
    for (k = 0; k < 3 * m.nverts; k++) {
        lo[k % 3] = m.positions[k] < lo[k % 3] ? m.positions[k] : lo[k % 3];
        hi[k % 3] = m.positions[k] > hi[k % 3] ? m.positions[k] : hi[k % 3];
    }
    if (loops == 0) CHECKF(vol > 0, "%s: signed volume %g", name, vol);
    else CHECKF(upz == m.nfaces, "%s: %d of %d triangles face +z", name, upz, m.nfaces);
    CHECKF(minarea > 1e-5, "%s: a triangle of area %g", name, minarea);
    for (k = 0; k < 3; k++) CHECK(hi[k] - lo[k] < 3.2 && hi[k] > 0.15 && lo[k] < 0.15);
    pwt_info("%s: %d vertices, %d triangles, volume %.3f, extent %.2f x %.2f x %.2f", name, m.nverts, m.nfaces,
             vol, hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
    pw_hmesh_free(NULL, &hm);
    lapped_mesh_free(&m);
}

static void t_meshes(void)
{
    lapped_mesh m;
    lapped_error err;
    check_mesh("sphere", 1442, 2880, 2, 0);
    check_mesh("torus", 1536, 3072, 0, 0);
    check_mesh("bumpy", 2562, 5120, 2, 0);
    check_mesh("disc", 1027, 1944, 1, 1);
    CHECK(lapped_builtin_mesh("cube", NULL, &m, &err) == LAPPED_ERR_INVALID);
    CHECK(strstr(err.message, "sphere, torus, bumpy, disc") != NULL);
    CHECK(m.positions == NULL);
    CHECK(lapped_builtin_mesh(NULL, NULL, &m, NULL) == LAPPED_ERR_INVALID);
    CHECK(lapped_builtin_mesh("sphere", NULL, NULL, NULL) == LAPPED_ERR_INVALID);
    { /* the same mesh every time, whatever the seed */
        lapped_options o = lapped_default_options();
        lapped_mesh a, b;
        o.seed = 99;
        REQUIRE(lapped_builtin_mesh("bumpy", NULL, &a, NULL) == LAPPED_OK);
        REQUIRE(lapped_builtin_mesh("bumpy", &o, &b, NULL) == LAPPED_OK);
        CHECK(!memcmp(a.positions, b.positions, sizeof(float) * 3 * a.nverts));
        lapped_mesh_free(&a);
        lapped_mesh_free(&b);
    }
}

static void t_textures(void)
{
    static const char *names[3] = {"scales", "stripes", "dots"};
    lapped_options o = lapped_default_options();
    lapped_image a, b;
    lapped_error err;
    int k;
    size_t i;
    for (k = 0; k < 3; k++) {
        double mean = 0, var = 0;
        size_t n = 256 * 256 * 3;
        int inrange = 1;
        o.seed = 5;
        REQUIRE(lapped_builtin_exemplar(names[k], 256, &o, &a, NULL) == LAPPED_OK);
        REQUIRE(lapped_builtin_exemplar(names[k], 256, &o, &b, NULL) == LAPPED_OK);
        CHECK(a.width == 256 && a.height == 256 && a.channels == 3);
        CHECKF(!memcmp(a.pixels, b.pixels, sizeof(float) * n), "%s is not deterministic", names[k]);
        lapped_image_free(&b);
        o.seed = 6;
        REQUIRE(lapped_builtin_exemplar(names[k], 256, &o, &b, NULL) == LAPPED_OK);
        CHECKF(memcmp(a.pixels, b.pixels, sizeof(float) * n) != 0, "%s ignores the seed", names[k]);
        for (i = 0; i < n; i++) {
            inrange &= a.pixels[i] >= 0 && a.pixels[i] <= 1;
            mean += a.pixels[i];
        }
        mean /= (double)n;
        for (i = 0; i < n; i++) var += (a.pixels[i] - mean) * (a.pixels[i] - mean);
        CHECK(inrange);
        CHECKF(var / n > 0.01, "%s has little contrast (variance %g)", names[k], var / n);
        {
            char name[32];
            snprintf(name, sizeof name, "tex_%s", names[k]);
            write_patch(name, &a);
        }
        pwt_info("%s: mean %.3f, standard deviation %.3f", names[k], mean, sqrt(var / n));
        lapped_image_free(&a);
        lapped_image_free(&b);
    }
    CHECK(lapped_builtin_exemplar("bricks", 64, NULL, &a, &err) == LAPPED_ERR_INVALID);
    CHECK(strstr(err.message, "scales, stripes, dots") != NULL);
    CHECK(lapped_builtin_exemplar("dots", 7, NULL, &a, &err) == LAPPED_ERR_INVALID);
    CHECK(strstr(err.message, "8..4096") != NULL);
    CHECK(lapped_builtin_exemplar("dots", 4097, NULL, &a, NULL) == LAPPED_ERR_INVALID);
    CHECK(a.pixels == NULL);
    REQUIRE(lapped_builtin_exemplar("stripes", 8, NULL, &a, NULL) == LAPPED_OK);
    lapped_image_free(&a);
}

/* The paper's setting for a patch: built-in texture, splotch, 3-pixel
 * fall-off, hull; timed at 512 x 512. */
static void t_speed(void)
{
    lapped_options o = lapped_default_options();
    lapped_image tex, p;
    pw_image v;
    pw_polyhull h;
    clock_t t0;
    double tp, th;
    int nv;
    REQUIRE(lapped_builtin_exemplar("scales", 512, &o, &tex, NULL) == LAPPED_OK);
    t0 = clock();
    REQUIRE(lapped_make_patch(&tex, NULL, &o, &p, NULL) == LAPPED_OK);
    tp = (double)(clock() - t0) / CLOCKS_PER_SEC;
    v = lapped__pw_image(&p);
    t0 = clock();
    REQUIRE(lapped__patch_hull(NULL, &v, &h, NULL) == PW_OK);
    th = (double)(clock() - t0) / CLOCKS_PER_SEC;
    CHECK(hull_misses(&p, &nv) == 0);
    CHECK(th < 0.1);
    pwt_info("512x512 splotch patch in %.1f ms, its hull in %.1f ms (%d vertices)", tp * 1e3, th * 1e3, h.n);
    write_patch("scales512", &p);
    pw_polyhull_free(NULL, &h);
    lapped_image_free(&tex);
    lapped_image_free(&p);
}

static const pwt_case cases[] = {
    {"circle", t_circle},   {"splotch", t_splotch}, {"mask", t_mask},         {"falloff", t_falloff},
    {"image_alpha", t_image_alpha}, {"errors", t_errors}, {"allocator", t_allocator}, {"hulls", t_hulls},
    {"clear_border", t_clear_border}, {"meshes", t_meshes}, {"textures", t_textures}, {"speed", t_speed},
};
PWT_MAIN(cases)
