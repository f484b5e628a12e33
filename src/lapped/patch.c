/* patch.c: §3.1 texture patches. A patch is the texture as RGBA whose
 * alpha says which part of it is pasted: the image's own alpha, a mask, or
 * one of the paper's "predefined shapes, such as a circle or an irregular
 * splotch", then "an alpha mask that falls off near the patch boundary
 * (e.g. over a distance of 3 pixels)". Also the polygonal hull (§3.3) that
 * patch growth tests edges against. */
#include "field.c" /* precedes patch.c in lapped.h; grow.c, which includes this, uses both */

/* ---- §3.1 predefined shapes ------------------------------------------------ */

/* The disc inscribed in the image: pixel centres within min(w,h)/2 of the
 * image centre. */
static void lapped__shape_circle(int w, int h, float *a0)
{
    double r = 0.5 * (w < h ? w : h);
    int x, y;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            double dx = x + 0.5 - 0.5 * w, dy = y + 0.5 - 0.5 * h;
            a0[(size_t)y * w + x] = dx * dx + dy * dy <= r * r ? 1.0f : 0.0f;
        }
}

/* The splotch is star-shaped: r(theta) = 1 + sum_k amp_k cos(k theta + phase_k)
 * for a few low frequencies k, so it is one smooth, hole-free blob. */
#define LAPPED__SPLOTCH_K 6 /* harmonics 2..6 */

typedef struct lapped__splotch {
    double amp[LAPPED__SPLOTCH_K + 1], cph[LAPPED__SPLOTCH_K + 1], sph[LAPPED__SPLOTCH_K + 1];
    double lo[2], hi[2]; /* bounding box of the blob */
} lapped__splotch;

/* r for the direction (c, s) = (cos theta, sin theta): cos(k theta) and
 * sin(k theta) by repeated rotation, no trigonometric call. */
static double lapped__splotch_r(const lapped__splotch *sp, double c, double s)
{
    double ck = c, sk = s, r = 1.0, t;
    int k;
    for (k = 2; k <= LAPPED__SPLOTCH_K; k++) {
        t = ck * c - sk * s;
        sk = sk * c + ck * s;
        ck = t;
        r += sp->amp[k] * (ck * sp->cph[k] - sk * sp->sph[k]);
    }
    return r;
}

/* Random amplitudes (decaying with frequency, summing to at most 0.5 so
 * that r stays in [0.5, 1.5]) and phases, and the blob's bounding box from
 * 1024 directions. */
static void lapped__splotch_init(lapped__splotch *sp, unsigned long long seed)
{
    pw_rng r = pw_rng_seed(seed, 0x5e1075u);
    double sum = 0.0;
    int k, j;
    for (k = 2; k <= LAPPED__SPLOTCH_K; k++) {
        double ph = 6.283185307179586 * pw_rng_double(&r);
        sp->amp[k] = (0.06 + 0.16 * pw_rng_double(&r)) * 2.0 / k;
        sp->cph[k] = pw_cos(ph);
        sp->sph[k] = pw_sin(ph);
        sum += sp->amp[k];
    }
    for (k = 2; sum > 0.5 && k <= LAPPED__SPLOTCH_K; k++) sp->amp[k] *= 0.5 / sum;
    sp->lo[0] = sp->lo[1] = 1e30;
    sp->hi[0] = sp->hi[1] = -1e30;
    for (j = 0; j < 1024; j++) {
        double th = 6.283185307179586 * j / 1024.0, c = pw_cos(th), s = pw_sin(th);
        double rr = lapped__splotch_r(sp, c, s), p[2];
        p[0] = rr * c;
        p[1] = rr * s;
        for (k = 0; k < 2; k++) {
            sp->lo[k] = p[k] < sp->lo[k] ? p[k] : sp->lo[k];
            sp->hi[k] = p[k] > sp->hi[k] ? p[k] : sp->hi[k];
        }
    }
}

/* An irregular splotch seeded by `seed`, its bounding box stretched over the
 * image inside a margin of 3% of the smaller side (at least a pixel). */
static void lapped__shape_splotch(int w, int h, unsigned long long seed, float *a0)
{
    lapped__splotch sp;
    double m = 1.0 + 0.03 * (w < h ? w : h), sx, sy;
    int x, y;
    lapped__splotch_init(&sp, seed);
    if (2.0 * m >= (w < h ? w : h)) m = 0.0;
    sx = (sp.hi[0] - sp.lo[0]) / (w - 2.0 * m);
    sy = (sp.hi[1] - sp.lo[1]) / (h - 2.0 * m);
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            double bx = sp.lo[0] + (x + 0.5 - m) * sx, by = sp.lo[1] + (y + 0.5 - m) * sy;
            double rho = sqrt(bx * bx + by * by);
            int in = rho <= 0.0 || rho <= lapped__splotch_r(&sp, bx / rho, by / rho);
            a0[(size_t)y * w + x] = in ? 1.0f : 0.0f;
        }
}

/* ---- §3.1 fall-off: exact Euclidean distance transform ---------------------- */

/* One line of the squared distance transform (Felzenszwalb and Huttenlocher
 * 2012): d[q] = min_p (q - p)^2 + f[p], by the lower envelope of parabolas.
 * All values are integers below 2^53, so the result is exact. */
static void lapped__edt_line(const double *f, int n, double *d, int *v, double *z)
{
    int k = 0, q;
    v[0] = 0;
    z[0] = -1e300;
    z[1] = 1e300;
    for (q = 1; q < n; q++) {
        double s;
        for (;;) { /* pop the parabolas the new one hides (never the first: z[0] = -inf) */
            int p = v[k];
            s = ((f[q] + (double)q * q) - (f[p] + (double)p * p)) / (2.0 * (q - p));
            if (s > z[k]) break;
            k--;
        }
        k++;
        v[k] = q;
        z[k] = s;
        z[k + 1] = 1e300;
    }
    for (k = 0, q = 0; q < n; q++) {
        while (z[k + 1] < q) k++;
        d[q] = (double)(q - v[k]) * (q - v[k]) + f[v[k]];
    }
}

/* Scratch of the distance transform of a w x h image, with W = w + 2,
 * H = h + 2: g, W*H doubles (the padded image); sd, 4 (W + H + 2) doubles
 * and si, W + H ints (one line's values, distances, envelope). */
typedef struct {
    double *g, *sd;
    int *si;
} lapped__edt_scratch;

/* dist[i] = Euclidean distance from pixel i's centre to the nearest centre
 * of a transparent pixel (a0 <= 0), where the pixels just outside the image
 * count as transparent. Works on the image padded by one ring of those:
 * columns, then rows. */
static void lapped__edt(const float *a0, int w, int h, float *dist, const lapped__edt_scratch *ws)
{
    double *g = ws->g, *sd = ws->sd;
    int *si = ws->si;
    int W = w + 2, H = h + 2, n = W > H ? W : H, x, y;
    double inf = 2.0 * ((double)W * W + (double)H * H), *f = sd, *d = sd + n, *z = sd + 2 * n;
    for (y = 0; y < H; y++)
        for (x = 0; x < W; x++) {
            int out = x == 0 || y == 0 || x == W - 1 || y == H - 1;
            g[(size_t)y * W + x] = out || !(a0[(size_t)(y - 1) * w + x - 1] > 0.0f) ? 0.0 : inf;
        }
    for (x = 1; x < W - 1; x++) {
        for (y = 0; y < H; y++) f[y] = g[(size_t)y * W + x];
        lapped__edt_line(f, H, d, si, z);
        for (y = 0; y < H; y++) g[(size_t)y * W + x] = d[y];
    }
    for (y = 1; y < H - 1; y++) {
        lapped__edt_line(g + (size_t)y * W, W, d, si, z);
        for (x = 1; x < W - 1; x++) dist[(size_t)(y - 1) * w + x - 1] = (float)sqrt(d[x]);
    }
}

/* §3.1: alpha = a0 times a ramp that is 0 at distance 1 from the nearest
 * transparent pixel (so the outermost opaque ring and the image border
 * become transparent: §4 wants a transparent border) and 1 at falloff + 1.
 * Returns how many pixels keep a non-zero alpha. */
static long lapped__falloff(pw_image *rgba, const float *a0, const float *dist, float falloff)
{
    size_t i, n = (size_t)rgba->w * rgba->h;
    long nonzero = 0;
    for (i = 0; i < n; i++) {
        float t = pw_clampf((dist[i] - 1.0f) / falloff, 0.0f, 1.0f);
        rgba->px[4 * i + 3] = a0[i] * t;
        nonzero += rgba->px[4 * i + 3] > 0.0f;
    }
    return nonzero;
}

/* ---- lapped_make_patch ------------------------------------------------------- */

/* Which alpha: AUTO is the mask when one is given, else the image's alpha
 * channel if it has one, else a splotch. */
static int lapped__alpha_mode(const lapped_image *tex, const lapped_image *mask, int mode, int *out, pw_err *e)
{
    if (mode < LAPPED_ALPHA_AUTO || mode > LAPPED_ALPHA_SPLOTCH)
        return pw_fail(e, PW_ERR_INVALID, "unknown alpha mode %d (LAPPED_ALPHA_AUTO..SPLOTCH)", mode);
    if (mode == LAPPED_ALPHA_AUTO)
        mode = mask                                         ? LAPPED_ALPHA_MASK
               : (tex->channels == 2 || tex->channels == 4) ? LAPPED_ALPHA_IMAGE
                                                            : LAPPED_ALPHA_SPLOTCH;
    if (mask && mode != LAPPED_ALPHA_MASK)
        return pw_fail(e, PW_ERR_INVALID, "a mask was given but the alpha mode is %d, not LAPPED_ALPHA_MASK", mode);
    if (mode == LAPPED_ALPHA_MASK && !mask)
        return pw_fail(e, PW_ERR_INVALID, "alpha mode LAPPED_ALPHA_MASK needs a mask image");
    if (mode == LAPPED_ALPHA_IMAGE && tex->channels != 2 && tex->channels != 4)
        return pw_fail(e, PW_ERR_INVALID,
                       "alpha mode LAPPED_ALPHA_IMAGE, but the texture has %d channels "
                       "and no alpha",
                       tex->channels);
    if (mode == LAPPED_ALPHA_MASK && (mask->width != tex->width || mask->height != tex->height))
        return pw_fail(e, PW_ERR_INVALID, "the mask is %dx%d but the texture is %dx%d", mask->width, mask->height,
                       tex->width, tex->height);
    *out = mode;
    return PW_OK;
}

/* One patch to make: the caller's texture and optional mask, the alpha
 * source (LAPPED_ALPHA_*), the splotch seed and the fall-off width. */
typedef struct {
    const lapped_image *tex, *mask;
    int mode;
    unsigned long long seed;
    float falloff;
} lapped__patch_job;

/* The alpha before the fall-off, in [0, 1]; refuses an all-zero one. */
static int lapped__base_alpha(const lapped__patch_job *job, float *a0, pw_err *e)
{
    const lapped_image *tex = job->tex, *mask = job->mask;
    int mode = job->mode;
    size_t i, n = (size_t)tex->width * tex->height;
    long nonzero = 0;
    if (mode == LAPPED_ALPHA_CIRCLE) lapped__shape_circle(tex->width, tex->height, a0);
    if (mode == LAPPED_ALPHA_SPLOTCH) lapped__shape_splotch(tex->width, tex->height, job->seed, a0);
    for (i = 0; i < n; i++) {
        if (mode == LAPPED_ALPHA_IMAGE) a0[i] = tex->pixels[(i + 1) * tex->channels - 1];
        if (mode == LAPPED_ALPHA_MASK) a0[i] = mask->pixels[i * mask->channels];
        a0[i] = pw_clampf(a0[i], 0.0f, 1.0f);
        nonzero += a0[i] > 0.0f;
    }
    if (nonzero > 0) return PW_OK;
    if (mode == LAPPED_ALPHA_MASK) return pw_fail(e, PW_ERR_INVALID, "the mask is all zero");
    return pw_fail(e, PW_ERR_INVALID, "the texture's alpha channel is fully transparent");
}

/* Checks the arguments; *falloff gets the fall-off width (0 means the
 * default, 3 pixels). */
static int lapped__patch_args(const lapped_image *tex, const lapped_image *mask, const lapped_options *opt,
                              float *falloff, pw_err *e)
{
    int r;
    if ((r = lapped__check_image(tex, "texture", e)) != PW_OK) return r;
    if (mask && (r = lapped__check_image(mask, "mask", e)) != PW_OK) return r;
    *falloff = opt ? opt->falloff : 0.0f;
    if (!pw_is_finite(*falloff) || *falloff < 0.0f)
        return pw_fail(e, PW_ERR_INVALID, "falloff must be a finite number >= 0 pixels (got %g)", (double)*falloff);
    if (*falloff == 0.0f) *falloff = lapped_default_options().falloff;
    return PW_OK;
}

/* Alpha and fall-off into rgba (whose colour is already the texture's). */
static int lapped__patch_alpha(const pw_alloc *a, const lapped__patch_job *job, pw_image *rgba, pw_err *e)
{
    const lapped_image *tex = job->tex;
    size_t n = (size_t)tex->width * tex->height, nl = (size_t)(tex->width + tex->height + 4);
    float *a0 = (float *)pw_alloc_array(a, n * 2, sizeof(float), "patch alpha", e);
    lapped__edt_scratch ws;
    int r;
    ws.g = a0 ? (double *)pw_alloc_array(a, (size_t)(tex->width + 2) * (tex->height + 2), sizeof(double),
                                         "distance transform", e)
              : NULL;
    ws.sd = ws.g ? (double *)pw_alloc_array(a, 4 * nl, sizeof(double), "distance transform", e) : NULL;
    ws.si = ws.sd ? (int *)pw_alloc_array(a, nl, sizeof(int), "distance transform", e) : NULL;
    r = ws.si ? PW_OK : PW_ERR_NOMEM;
    if (r == PW_OK) r = lapped__base_alpha(job, a0, e);
    if (r == PW_OK) {
        lapped__edt(a0, tex->width, tex->height, a0 + n, &ws);
        if (lapped__falloff(rgba, a0, a0 + n, job->falloff) == 0)
            r = pw_fail(e, PW_ERR_INVALID,
                        "the patch is fully transparent after the %g-pixel fall-off "
                        "(the image or its opaque region is too small)",
                        (double)job->falloff);
    }
    pw_free(a, a0);
    pw_free(a, ws.g);
    pw_free(a, ws.sd);
    pw_free(a, ws.si);
    return r;
}

LAPPEDDEF lapped_result lapped_make_patch(const lapped_image *texture, const lapped_image *mask,
                                          const lapped_options *opt, lapped_image *out, lapped_error *err)
{
    lapped_options o = lapped__options(opt);
    pw_alloc a = lapped__alloc(&o.allocator);
    pw_image src, rgba;
    pw_err pe;
    lapped__patch_job job;
    memset(&job, 0, sizeof job);
    job.tex = texture;
    job.mask = mask;
    job.seed = o.seed;
    pw_err_clear(&pe);
    memset(&rgba, 0, sizeof rgba);
    if (out) memset(out, 0, sizeof *out);
    if (!out) pw_fail(&pe, PW_ERR_INVALID, "lapped_make_patch: NULL output");
    else if (lapped__patch_args(texture, mask, opt, &job.falloff, &pe) == PW_OK &&
             lapped__alpha_mode(texture, mask, o.alpha, &job.mode, &pe) == PW_OK) {
        src = lapped__pw_image(texture);
        if (pw_image_convert(&a, &src, 4, &rgba, &pe) == PW_OK && lapped__patch_alpha(&a, &job, &rgba, &pe) == PW_OK)
            lapped__take_image(&rgba, &a, out);
        pw_image_free(&a, &rgba);
    }
    return lapped__done(&pe, err);
}

/* §3.3: the polygonal hull of an RGBA patch's non-zero alpha (channel 4),
 * for the growth test. */
static PW__UNUSED int lapped__patch_hull(const pw_alloc *a, const pw_image *rgba, pw_polyhull *out, pw_err *e)
{
    if (!rgba || !rgba->px || rgba->c != 4)
        return pw_fail(e, PW_ERR_INVALID, "a texture patch must be RGBA (got %d channels)", rgba ? rgba->c : 0);
    return pw_polyhull_build(a, rgba->px + 3, rgba->w, rgba->h, 4, 0, out, e);
}
