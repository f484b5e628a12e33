/* morph.c: the inputs of §1 (keys brought to the tile size, made tileable,
 * their feature masks and signed distance fields) and §1.1, the feature
 * morphing by advection with interior dilation, sweeping and speed-adaptive
 * subsampling. Section numbers refer to Ray, Lévy, Wang, Turk and Vallet
 * 2009 ("Material Space Texturing"). Everything is periodic: the tile wraps
 * in s and t. */
#include "core.c"
#include "../common/rng.h"
#include "../common/graphcut.h"
#include "../common/quilt.h"
#include "../common/edt.h"

/* Zero fields take their defaults. */
static pgp_synth_options pgp__synth_options(const pgp_synth_options *opt)
{
    pgp_synth_options d = pgp__synth_defaults(), o;
    if (!opt) return d;
    o = *opt;
    if (!o.size) o.size = d.size;
    if (!o.layers) o.layers = d.layers;
    if (!o.coarse_passes) o.coarse_passes = d.coarse_passes;
    if (!o.fine_passes) o.fine_passes = d.fine_passes;
    if (!o.color_window) o.color_window = d.color_window;
    if (!o.mask_window) o.mask_window = d.mask_window;
    if (!o.color_dims) o.color_dims = d.color_dims;
    if (!o.mask_dims) o.mask_dims = d.mask_dims;
    if (o.mask_weight == 0.0f) o.mask_weight = d.mask_weight;
    if (o.usage_weight == 0.0f) o.usage_weight = d.usage_weight;
    if (o.usage_weight < 0.0f) o.usage_weight = 0.0f;
    if (o.search_eps == 0.0f) o.search_eps = d.search_eps;
    if (o.search_eps < 0.0f) o.search_eps = 0.0f;
    if (!o.search_buckets) o.search_buckets = d.search_buckets;
    if (o.search_buckets < 0) o.search_buckets = -1;
    return o;
}

static pw_progress pgp__synth_progress(const pgp_synth_options *o)
{
    pw_progress p;
    p.fn = o->progress;
    p.user = o->progress_user;
    return p;
}

/* ---- keys: resampling, tileability, masks ------------------------------------ */

/* One periodic line of `from` samples (c channels, `stride` floats apart) to
 * `to` samples: linear interpolation up, box filter (exact coverage) down. */
static void pgp__resample_line(const float *in, int from, size_t stride, int c, float *out, int to)
{
    int j, k, i;
    double r = (double)from / to;
    for (j = 0; j < to; j++) {
        float *o = out + (size_t)j * stride;
        if (to >= from) { /* centre of output j in input index units */
            double x = (j + 0.5) * r - 0.5, f;
            int x0 = (int)floor(x);
            f = x - x0;
            for (k = 0; k < c; k++)
                o[k] = (float)((1.0 - f) * in[(size_t)((x0 + from) % from) * stride + k] +
                               f * in[(size_t)((x0 + 1) % from) * stride + k]);
        } else { /* input interval [j r, (j + 1) r) */
            double lo = j * r, hi = (j + 1) * r;
            for (k = 0; k < c; k++) o[k] = 0.0f;
            for (i = (int)lo; i < from && i < hi; i++) {
                double w = (i + 1 < hi ? i + 1 : hi) - (i > lo ? i : lo);
                for (k = 0; k < c; k++) o[k] += (float)(w / r * in[(size_t)i * stride + k]);
            }
        }
    }
}

/* The samples of src (w x h x c) to n x n, rows then columns. */
static int pgp__resample(const pw_alloc *a, const pw_image *src, int n, float *out, pw_err *e)
{
    const float *px = src->px;
    int w = src->w, h = src->h, c = src->c;
    float *tmp = (float *)pw_alloc_array(a, (size_t)n * h * c, sizeof(float), "resampled key", e);
    int y, x;
    if (!tmp) return PW_ERR_NOMEM;
    for (y = 0; y < h; y++) pgp__resample_line(px + (size_t)y * w * c, w, (size_t)c, c, tmp + (size_t)y * n * c, n);
    for (x = 0; x < n; x++) pgp__resample_line(tmp + (size_t)x * c, h, (size_t)n * c, c, out + (size_t)x * c, n);
    pw_free(a, tmp);
    return PW_OK;
}

/* Mean absolute difference between columns x0 and x1 (dx = 1) or rows
 * (dx = 0) of an image. */
static double pgp__line_diff(const pw_image *img, int dx, int i0, int i1)
{
    const float *px = img->px;
    int w = img->w, h = img->h, c = img->c;
    int j, k, len = dx ? h : w;
    double s = 0.0;
    for (j = 0; j < len; j++)
        for (k = 0; k < c; k++) {
            size_t p = dx ? ((size_t)j * w + i0) : ((size_t)i0 * w + j),
                   q = dx ? ((size_t)j * w + i1) : ((size_t)i1 * w + j);
            s += fabs((double)px[p * c + k] - px[q * c + k]);
        }
    return s / ((double)len * c);
}

/* PGP_TILEABLE_AUTO's test: is the wrap-around seam within twice the mean
 * difference of neighbouring lines inside, in both directions? */
static int pgp__tiles(const pw_image *img)
{
    int dx, i;
    for (dx = 0; dx < 2; dx++) {
        int len = dx ? img->w : img->h;
        double inner = 0.0;
        if (len < 3) continue;
        for (i = 0; i + 1 < len; i++) inner += pgp__line_diff(img, dx, i, i + 1);
        inner /= len - 1;
        if (pgp__line_diff(img, dx, len - 1, 0) > 2.0 * inner + 1e-6) return 0;
    }
    return 1;
}

/* Luminance (Rec. 601), colour composited over white where there is alpha. */
static void pgp__luminance(const float *px, size_t n, int c, float *lum)
{
    size_t i;
    for (i = 0; i < n; i++) {
        const float *p = px + i * c;
        float y = c >= 3 ? 0.299f * p[0] + 0.587f * p[1] + 0.114f * p[2] : p[0];
        float al = c == 2 ? p[1] : (c == 4 ? p[3] : 1.0f);
        lum[i] = y * al + (1.0f - al);
    }
}

/* In-place periodic 3x3 binomial blur of a w x h field (tmp: w*h). */
static void pgp__blur3(float *f, int w, int h, float *tmp)
{
    int x, y, pass;
    for (pass = 0; pass < 2; pass++) {
        float *src = pass ? tmp : f, *dst = pass ? f : tmp;
        for (y = 0; y < h; y++)
            for (x = 0; x < w; x++) {
                size_t i = (size_t)y * w + x;
                size_t l = pass ? (size_t)((y + h - 1) % h) * w + x : (size_t)y * w + (x + w - 1) % w;
                size_t r = pass ? (size_t)((y + 1) % h) * w + x : (size_t)y * w + (x + 1) % w;
                dst[i] = 0.25f * src[l] + 0.5f * src[i] + 0.25f * src[r];
            }
    }
}

/* One periodic box filter of radius r along x (dx = 1) or y of a w x h
 * field, by a running sum; out must differ from f. */
static void pgp__box_pass(const float *f, int w, int h, int r, int dx, float *out)
{
    int len = dx ? w : h, lines = dx ? h : w, l, i;
    size_t step = dx ? 1 : (size_t)w;
    for (l = 0; l < lines; l++) {
        const float *in = f + (dx ? (size_t)l * w : (size_t)l);
        float *o = out + (dx ? (size_t)l * w : (size_t)l);
        double sum = 0.0;
        for (i = -r; i <= r; i++) sum += in[(size_t)(((i % len) + len) % len) * step];
        for (i = 0; i < len; i++) {
            o[(size_t)i * step] = (float)(sum / (2 * r + 1));
            sum += in[(size_t)((i + r + 1) % len) * step] - in[(size_t)(((i - r) % len + len) % len) * step];
        }
    }
}

/* f minus its local mean: three periodic box filters of radius r in each
 * direction (close to a Gaussian of standard deviation sqrt(r (r + 1))).
 * tmp: 2*w*h floats. */
static void pgp__high_pass(float *f, int w, int h, int r, float *tmp)
{
    float *a = tmp, *b = tmp + (size_t)w * h;
    size_t i, nn = (size_t)w * h;
    int k;
    memcpy(a, f, nn * sizeof(float));
    for (k = 0; k < 3; k++) {
        pgp__box_pass(a, w, h, r, 1, b);
        pgp__box_pass(b, w, h, r, 0, a);
    }
    for (i = 0; i < nn; i++) f[i] -= a[i];
}

/* Otsu's threshold of n values: the one that maximises the between-class
 * variance of a 256-bin histogram; +inf when all values are equal. */
static float pgp__otsu(const float *v, size_t n)
{
    double hist[256], lo = v[0], hi = v[0], sum = 0.0, w0 = 0.0, s0 = 0.0, best = -1.0;
    size_t i;
    int b, tb = 0;
    for (i = 1; i < n; i++) {
        lo = v[i] < lo ? v[i] : lo;
        hi = v[i] > hi ? v[i] : hi;
    }
    if (!(hi > lo)) return FLT_MAX;
    memset(hist, 0, sizeof hist);
    for (i = 0; i < n; i++) {
        int k = (int)((v[i] - lo) / (hi - lo) * 256.0);
        hist[k > 255 ? 255 : k] += 1.0;
    }
    for (b = 0; b < 256; b++) sum += b * hist[b];
    for (b = 0; b < 255; b++) {
        double w1, m0, m1, between;
        w0 += hist[b];
        s0 += b * hist[b];
        w1 = (double)n - w0;
        if (w0 == 0.0 || w1 == 0.0) continue;
        m0 = s0 / w0;
        m1 = (sum - s0) / w1;
        between = w0 * w1 * (m0 - m1) * (m0 - m1);
        if (between > best) {
            best = between;
            tb = b;
        }
    }
    return (float)(lo + (hi - lo) * (tb + 1) / 256.0);
}

/* §1: "constructed automatically": mask[i] = 1 on the features of a w x h
 * image (PGP_MASK_*). */
static int pgp__auto_mask(const pw_alloc *a, const pw_image *img, int mode, unsigned char *mask, pw_err *e)
{
    const float *px = img->px;
    int w = img->w, h = img->h, c = img->c;
    size_t i, nn = (size_t)w * h;
    float *lum = (float *)pw_alloc_array(a, nn * 3, sizeof(float), "automatic mask", e), *g, thr;
    int x, y;
    if (!lum) return PW_ERR_NOMEM;
    g = lum + nn * 2;
    pgp__luminance(px, nn, c, lum);
    pgp__blur3(lum, w, h, lum + nn);
    if (mode != PGP_MASK_GRADIENT) pgp__high_pass(lum, w, h, pw_maxi(1, pw_mini(w, h) / 10), lum + nn);
    if (mode == PGP_MASK_GRADIENT) {
        for (y = 0; y < h; y++)
            for (x = 0; x < w; x++) {
                float gx = lum[(size_t)y * w + (x + 1) % w] - lum[(size_t)y * w + (x + w - 1) % w];
                float gy = lum[(size_t)((y + 1) % h) * w + x] - lum[(size_t)((y + h - 1) % h) * w + x];
                g[(size_t)y * w + x] = sqrtf(gx * gx + gy * gy);
            }
        memcpy(lum, g, nn * sizeof(float));
    }
    thr = pgp__otsu(lum, nn);
    for (i = 0; i < nn; i++)
        mask[i] = (unsigned char)(thr < FLT_MAX && (mode == PGP_MASK_DARK ? lum[i] < thr : lum[i] >= thr));
    pw_free(a, lum);
    return PW_OK;
}

/* Refuses a mask without features or without background (needed by
 * §1.1: the signed distance of such a mask is infinite). */
static int pgp__check_mask(const unsigned char *mask, size_t nn, const char *what, pw_err *e)
{
    size_t i, on = 0;
    for (i = 0; i < nn; i++) on += mask[i] != 0;
    if (on == 0) return pw_fail(e, PW_ERR_INVALID, "%s: no feature texel (empty mask)", what);
    if (on == nn) return pw_fail(e, PW_ERR_INVALID, "%s: every texel is a feature (a mask of all ones)", what);
    return PW_OK;
}

/* A key as the synthesis needs it: colour (n*n*c, c the tile's channels)
 * and mask (n*n, 0/1), both tileable and resampled to n x n. */
typedef struct pgp__key {
    float *color;
    unsigned char *mask;
} pgp__key;

/* Colour and (given) mask of key k stacked: w*h*(c+1) samples, the mask's
 * luminance last. */
static int pgp__stack_key(const pw_alloc *a, const pgp_key *key, int c, float **out, pw_err *e)
{
    pw_image img = pgp__pw_image(key->image), conv, mk;
    size_t i, nn = (size_t)img.w * img.h;
    int cs = c + (key->mask ? 1 : 0), k, r;
    memset(&mk, 0, sizeof mk);
    if ((r = pw_image_convert(a, &img, c, &conv, e)) != PW_OK) return r;
    if (key->mask) {
        pw_image m = pgp__pw_image(key->mask);
        r = pw_image_convert(a, &m, 1, &mk, e);
    }
    *out = r == PW_OK ? (float *)pw_alloc_array(a, nn * cs, sizeof(float), "key", e) : NULL;
    if (r == PW_OK && !*out) r = PW_ERR_NOMEM;
    for (i = 0; r == PW_OK && i < nn; i++) {
        for (k = 0; k < c; k++) (*out)[i * cs + k] = conv.px[i * c + k];
        if (key->mask) (*out)[i * cs + c] = mk.px[i];
    }
    pw_image_free(a, &conv);
    pw_image_free(a, &mk);
    return r;
}

/* §1 inputs for key k: validated, made tileable when needed (the mask cut
 * with the colours), resampled to n x n, its mask thresholded or computed. */
static int pgp__prepare_key(const pw_alloc *a, const pgp_key *key, int c, const pgp_synth_options *o, pgp__key *out,
                            pw_err *e)
{
    pw_image img = pgp__pw_image(key->image);
    int n = o->size, cs = c + (key->mask ? 1 : 0), r;
    size_t i, nn = (size_t)n * n;
    float *st = NULL, *cut = NULL, *rs = NULL;
    pw_image sv, tile; /* views: the stacked key (cs channels), and its n x n colour */
    r = pgp__stack_key(a, key, c, &st, e);
    sv = img;
    sv.c = cs;
    sv.px = st;
    if (r == PW_OK && (o->tileable == PGP_TILEABLE_MAKE || (o->tileable == PGP_TILEABLE_AUTO && !pgp__tiles(&sv)))) {
        cut = (float *)pw_alloc_array(a, (size_t)img.w * img.h * cs, sizeof(float), "tileable key", e);
        r = cut ? pw_quilt_make_tileable_px(a, &sv, cut, e) : PW_ERR_NOMEM;
    }
    if (r == PW_OK && !(rs = (float *)pw_alloc_array(a, nn * cs, sizeof(float), "key", e))) r = PW_ERR_NOMEM;
    if (cut) sv.px = cut;
    if (r == PW_OK) r = pgp__resample(a, &sv, n, rs, e);
    out->color = r == PW_OK ? (float *)pw_alloc_array(a, nn * c, sizeof(float), "key colour", e) : NULL;
    out->mask = r == PW_OK ? (unsigned char *)pw_alloc_array(a, nn, 1, "key mask", e) : NULL;
    if (r == PW_OK && (!out->color || !out->mask)) r = PW_ERR_NOMEM;
    for (i = 0; r == PW_OK && i < nn; i++) {
        memcpy(out->color + i * c, rs + i * cs, sizeof(float) * c);
        if (key->mask) out->mask[i] = (unsigned char)(rs[i * cs + c] > 0.5f);
    }
    tile = img;
    tile.w = tile.h = n;
    tile.c = c;
    tile.px = out->color;
    if (r == PW_OK && !key->mask) r = pgp__auto_mask(a, &tile, o->auto_mask, out->mask, e);
    pw_free(a, st);
    pw_free(a, cut);
    pw_free(a, rs);
    return r;
}

static void pgp__key_free(const pw_alloc *a, pgp__key *k)
{
    pw_free(a, k->color);
    pw_free(a, k->mask);
    memset(k, 0, sizeof *k);
}

/* ---- §1.1 feature morphing --------------------------------------------------- */

/* The advection state of one morph on an n x n torus: phi_n advected from
 * phi_0 towards psi = phi_N (the target's signed distance), and the sign
 * of every phi_n kept as bits for the subsampling. */
typedef struct pgp__morph {
    int n, N;
    size_t nn, words;
    float *phi0, *psi, *gx, *gy, *phi, *next;
    float dt, sup;
    uint64_t *bits; /* (N+1)*words */
} pgp__morph;

static void pgp__morph_free(const pw_alloc *a, pgp__morph *m)
{
    pw_free(a, m->phi0);
    pw_free(a, m->bits);
    memset(m, 0, sizeof *m);
}

static void pgp__store_sign(pgp__morph *m, int step)
{
    uint64_t *b = m->bits + (size_t)step * m->words;
    size_t i;
    memset(b, 0, m->words * sizeof(uint64_t));
    for (i = 0; i < m->nn; i++)
        if (m->phi[i] > 0.0f) b[i >> 6] |= (uint64_t)1 << (i & 63);
}

/* Texels whose sign differs between steps i and j. */
static long pgp__flips(const pgp__morph *m, int i, int j)
{
    const uint64_t *a = m->bits + (size_t)i * m->words, *b = m->bits + (size_t)j * m->words;
    size_t w;
    long s = 0;
    for (w = 0; w < m->words; w++) {
        uint64_t x = a[w] ^ b[w];
        x = x - ((x >> 1) & 0x5555555555555555ULL);
        x = (x & 0x3333333333333333ULL) + ((x >> 2) & 0x3333333333333333ULL);
        x = (x + (x >> 4)) & 0x0F0F0F0F0F0F0F0FULL;
        s += (long)((x * 0x0101010101010101ULL) >> 56);
    }
    return s;
}

/* One §1.1 morph as the synthesis asks for it: from mask f0 to mask f1
 * (n x n, 0/1) in M layers, written to masks ((M+1)*n*n: F_0 = f0 ... F_M
 * = f1), reporting progress over [p0, p1] of prog. */
typedef struct pgp__morph_job {
    const unsigned char *f0, *f1;
    int n, M;
    unsigned char *masks;
    const pw_progress *prog;
    float p0, p1;
} pgp__morph_job;

/* Signed distances (periodic, exact), the gradient of psi by central
 * differences, dt = -min psi / N (§1.1 "material space oversampling") and
 * sup |psi|. */
static int pgp__morph_init(const pw_alloc *a, pgp__morph *m, const pgp__morph_job *J, int steps, pw_err *e)
{
    const unsigned char *f0 = J->f0, *f1 = J->f1;
    int n = J->n, M = J->M;
    pw_edt_image im0, im1;
    size_t i;
    int x, y, r;
    float lo = 0.0f;
    memset(m, 0, sizeof *m);
    m->n = n;
    m->nn = (size_t)n * n;
    m->words = (m->nn + 63) / 64;
    if (!(m->phi0 = (float *)pw_alloc_array(a, m->nn * 6, sizeof(float), "morph fields", e))) return PW_ERR_NOMEM;
    m->psi = m->phi0 + m->nn;
    m->gx = m->psi + m->nn;
    m->gy = m->gx + m->nn;
    m->phi = m->gy + m->nn;
    m->next = m->phi + m->nn;
    im0.px = f0;
    im1.px = f1;
    im0.w = im0.h = im1.w = im1.h = n;
    im0.wrap = im1.wrap = 1; /* tiles */
    if ((r = pw_edt_signed(a, &im0, m->phi0, e)) != PW_OK || (r = pw_edt_signed(a, &im1, m->psi, e)) != PW_OK) return r;
    for (i = 0; i < m->nn; i++) {
        lo = m->psi[i] < lo ? m->psi[i] : lo;
        m->sup = fabsf(m->psi[i]) > m->sup ? fabsf(m->psi[i]) : m->sup;
    }
    m->N = steps > 0 ? steps : pw_maxi(16 * M, (int)ceilf(-2.0f * lo));
    m->N = pw_maxi(m->N, M);
    m->dt = -lo / (float)m->N;
    for (y = 0; y < n; y++)
        for (x = 0; x < n; x++) {
            i = (size_t)y * n + x;
            m->gx[i] = 0.5f * (m->psi[(size_t)y * n + (x + 1) % n] - m->psi[(size_t)y * n + (x + n - 1) % n]);
            m->gy[i] = 0.5f * (m->psi[(size_t)((y + 1) % n) * n + x] - m->psi[(size_t)((y + n - 1) % n) * n + x]);
        }
    memcpy(m->phi, m->phi0, m->nn * sizeof(float));
    m->bits = (uint64_t *)pw_alloc_array(a, (size_t)(m->N + 1) * m->words, sizeof(uint64_t), "morph masks", e);
    if (!m->bits) return PW_ERR_NOMEM;
    pgp__store_sign(m, 0);
    return PW_OK;
}

/* Advection: every texel outside the target features (psi < 0) moves to
 * s + grad psi(s) dt and is rasterised with the bilinear overlap
 * max(1-|ds|,0) max(1-|dt|,0) (the product; the paper's '+' is a typo) onto
 * the texels outside the target; what lands inside is absorbed there,
 * where interior dilation takes over (limitation 1). Texels inside stay. */
static void pgp__advect(pgp__morph *m)
{
    int n = m->n, x, y, k;
    memset(m->next, 0, m->nn * sizeof(float));
    for (y = 0; y < n; y++)
        for (x = 0; x < n; x++) {
            size_t i = (size_t)y * n + x;
            float px, py, fx, fy, v = m->phi[i];
            int x0, y0;
            if (m->psi[i] >= 0.0f) {
                m->next[i] += v;
                continue;
            }
            px = (float)x + m->gx[i] * m->dt;
            py = (float)y + m->gy[i] * m->dt;
            x0 = (int)floorf(px);
            y0 = (int)floorf(py);
            fx = px - (float)x0;
            fy = py - (float)y0;
            for (k = 0; k < 4; k++) {
                int xx = ((x0 + (k & 1)) % n + n) % n, yy = ((y0 + (k >> 1)) % n + n) % n;
                size_t j = (size_t)yy * n + xx;
                float w = ((k & 1) ? fx : 1.0f - fx) * ((k >> 1) ? fy : 1.0f - fy);
                if (m->psi[j] < 0.0f) m->next[j] += w * v;
            }
        }
}

/* Interior dilation: a texel inside a target feature takes the value of a
 * neighbour (8-neighbourhood) inside an advected source feature, the
 * largest when several are. */
static void pgp__dilate(pgp__morph *m)
{
    int n = m->n, x, y, dx, dy;
    for (y = 0; y < n; y++)
        for (x = 0; x < n; x++) {
            size_t i = (size_t)y * n + x;
            float best = 0.0f;
            if (m->psi[i] <= 0.0f) continue;
            for (dy = -1; dy <= 1; dy++)
                for (dx = -1; dx <= 1; dx++) {
                    float v = m->phi[(size_t)((y + dy + n) % n) * n + (x + dx + n) % n];
                    best = v > best ? v : best;
                }
            if (best > 0.0f && best > m->next[i]) m->next[i] = best;
        }
}

/* Sweeping before step `step` is kept: phi = psi (= phi_N) on the texels
 * where |psi| > (1 - step/N) sup |psi|, first far inside the target
 * features (limitation 2: a feature no source reaches fills from its core)
 * and far outside them, at the sources of the advection field where phi
 * tends to zero (limitation 3), then ever closer to the target boundaries,
 * everywhere at step N. The paper prints |phi_0(s)| on the left; that does
 * not do what its next sentence says (removing what cannot reach a target,
 * filling what is not reached: both are about the distance to the target)
 * and, when the source's distances are the larger, swaps most of the mask
 * to the target at the first step, so this is read as |phi_N(s)|. */
static void pgp__sweep(pgp__morph *m, int step)
{
    float thr = (1.0f - (float)step / (float)m->N) * m->sup;
    size_t i;
    for (i = 0; i < m->nn; i++)
        if (fabsf(m->psi[i]) > thr || step == m->N) m->next[i] = m->psi[i];
}

/* Runs the N steps, storing every sign. */
static int pgp__morph_run(pgp__morph *m, const pw_progress *prog, float p0, float p1, pw_err *e)
{
    int step;
    for (step = 1; step <= m->N; step++) {
        float *t;
        pgp__advect(m);
        pgp__dilate(m);
        pgp__sweep(m, step);
        t = m->phi;
        m->phi = m->next;
        m->next = t;
        pgp__store_sign(m, step);
        if ((step & 15) == 0 && pw_report(prog, p0 + (p1 - p0) * (float)step / (float)m->N, "feature morphing", e))
            return PW_ERR_CANCELLED;
    }
    return PW_OK;
}

/* Speed-adaptive subsampling: H(0) = 0, H(M) = N, increasing, with the
 * flips between consecutive kept steps as equal as possible: first at equal
 * shares of the cumulative flips, then each H(m) moved to balance its two
 * neighbouring segments, sweep after sweep until nothing moves. */
static void pgp__subsample(const pgp__morph *m, int M, int uniform, int *H)
{
    long total = 0, acc = 0;
    int k, j, sweep, moved = 1;
    for (k = 0; k < m->N; k++) total += pgp__flips(m, k, k + 1);
    H[0] = 0;
    H[M] = m->N;
    for (j = 1, k = 0; j < M; j++) {
        if (uniform) {
            H[j] = (int)((long)j * m->N / M);
            continue;
        }
        while (k < m->N && acc * M < total * j) {
            acc += pgp__flips(m, k, k + 1);
            k++;
        }
        H[j] = pw_clampi(k, H[j - 1] + 1, m->N - (M - j));
    }
    for (sweep = 0; sweep < 8 * M && moved && !uniform; sweep++)
        for (j = 1, moved = 0; j < M; j++) {
            long best = -1;
            int h, bh = H[j];
            for (h = H[j - 1] + 1; h < H[j + 1]; h++) {
                long d = pgp__flips(m, H[j - 1], h) - pgp__flips(m, h, H[j + 1]);
                d = d < 0 ? -d : d;
                if (best < 0 || d < best) {
                    best = d;
                    bh = h;
                }
            }
            moved |= bh != H[j];
            H[j] = bh;
        }
}

/* §1.1: the masks of job J. */
static int pgp__morph_masks(const pw_alloc *a, const pgp__morph_job *J, const pgp_synth_options *o, pw_err *e)
{
    int M = J->M;
    unsigned char *masks = J->masks;
    pgp__morph m;
    int *H = (int *)pw_alloc_array(a, (size_t)M + 1, sizeof(int), "subsampling", e), r, j;
    size_t i;
    if (!H) return PW_ERR_NOMEM;
    r = pgp__morph_init(a, &m, J, o->steps, e);
    if (r == PW_OK) r = pgp__morph_run(&m, J->prog, J->p0, J->p1, e);
    if (r == PW_OK) pgp__subsample(&m, M, o->uniform, H);
    for (j = 0; r == PW_OK && j <= M; j++) {
        const uint64_t *b = m.bits + (size_t)H[j] * m.words;
        for (i = 0; i < m.nn; i++) masks[(size_t)j * m.nn + i] = (unsigned char)(b[i >> 6] >> (i & 63) & 1u);
    }
    pgp__morph_free(a, &m);
    pw_free(a, H);
    return r;
}

/* ---- public: masks ----------------------------------------------------------- */

/* An image's luminance above 1/2 as 0/1 (a mask given by the caller). */
static int pgp__binary_mask(const pw_alloc *a, const pgp_image *img, unsigned char *out, pw_err *e)
{
    pw_image v = pgp__pw_image(img), g;
    size_t i, nn = (size_t)v.w * v.h;
    int r = pw_image_convert(a, &v, 1, &g, e);
    for (i = 0; r == PW_OK && i < nn; i++) out[i] = (unsigned char)(g.px[i] > 0.5f);
    pw_image_free(a, &g);
    return r;
}

/* A tile of `layers` one-channel layers of n x n from 0/1 masks. */
static int pgp__mask_tile(const pw_alloc *a, const unsigned char *masks, int n, int layers, pgp_tile *out, pw_err *e)
{
    size_t i, total = (size_t)n * n * layers;
    memset(out, 0, sizeof *out);
    if (!(out->pixels = (float *)pw_alloc_array(a, total, sizeof(float), "mask tile", e))) return PW_ERR_NOMEM;
    for (i = 0; i < total; i++) out->pixels[i] = masks[i] ? 1.0f : 0.0f;
    out->width = out->height = n;
    out->layers = layers;
    out->channels = 1;
    out->allocator = pgp__allocator(a);
    return PW_OK;
}

PGPDEF pgp_result pgp_feature_mask(const pgp_image *image, pgp_mask mode, const pgp_synth_options *opt, pgp_image *out,
                                   pgp_error *err)
{
    pgp_synth_options o = pgp__synth_options(opt);
    pw_alloc a = pgp__alloc(&o.allocator);
    pw_image v, res;
    unsigned char *mask = NULL;
    size_t i;
    pw_err pe;
    pw_err_clear(&pe);
    memset(&res, 0, sizeof res);
    if (out) memset(out, 0, sizeof *out);
    if (!out) pw_fail(&pe, PW_ERR_INVALID, "pgp_feature_mask: NULL output");
    else if (mode < PGP_MASK_DARK || mode > PGP_MASK_GRADIENT)
        pw_fail(&pe, PW_ERR_INVALID, "pgp_feature_mask: unknown mode %d", mode);
    else if (pgp__check_image(image, "image", &pe) == PW_OK) {
        v = pgp__pw_image(image);
        if (pw_image_alloc(&a, &res, v.w, v.h, 1, &pe) == PW_OK &&
            (mask = (unsigned char *)pw_alloc_array(&a, (size_t)v.w * v.h, 1, "mask", &pe)) != NULL &&
            pgp__auto_mask(&a, &v, mode, mask, &pe) == PW_OK) {
            for (i = 0; i < (size_t)v.w * v.h; i++) res.px[i] = mask[i] ? 1.0f : 0.0f;
            pgp__take_image(&res, &a, out);
        }
    }
    pw_free(&a, mask);
    pw_image_free(&a, &res);
    return pgp__done(&pe, err);
}

PGPDEF pgp_result pgp_morph_masks(const pgp_image *mask0, const pgp_image *mask1, int layers,
                                  const pgp_synth_options *opt, pgp_tile *out, pgp_error *err)
{
    pgp_synth_options o = pgp__synth_options(opt);
    pw_alloc a = pgp__alloc(&o.allocator);
    pw_progress prog = pgp__synth_progress(&o);
    unsigned char *f = NULL;
    int n = 0;
    size_t nn = 0;
    pgp__morph_job J;
    pw_err pe;
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (!out) pw_fail(&pe, PW_ERR_INVALID, "pgp_morph_masks: NULL output");
    else if (layers < 2 || layers > 1024)
        pw_fail(&pe, PW_ERR_INVALID, "pgp_morph_masks: %d layers (2 to 1024)", layers);
    else if (pgp__check_image(mask0, "mask 0", &pe) == PW_OK && pgp__check_image(mask1, "mask 1", &pe) == PW_OK &&
             (mask0->width != mask0->height || mask1->width != mask0->width || mask1->height != mask0->height))
        pw_fail(&pe, PW_ERR_INVALID, "pgp_morph_masks: masks of %dx%d and %dx%d (both must be the same square)",
                mask0->width, mask0->height, mask1->width, mask1->height);
    if (pe.code == PW_OK) {
        n = mask0->width;
        nn = (size_t)n * n;
        f = (unsigned char *)pw_alloc_array(&a, nn * (layers + 2), 1, "masks", &pe);
    }
    J.f0 = f;
    J.f1 = f + nn;
    J.n = n;
    J.M = layers - 1;
    J.masks = f + 2 * nn;
    J.prog = &prog;
    J.p0 = 0.0f;
    J.p1 = 1.0f;
    if (f && pgp__binary_mask(&a, mask0, f, &pe) == PW_OK && pgp__binary_mask(&a, mask1, f + nn, &pe) == PW_OK &&
        pgp__check_mask(f, nn, "mask 0", &pe) == PW_OK && pgp__check_mask(f + nn, nn, "mask 1", &pe) == PW_OK &&
        pgp__morph_masks(&a, &J, &o, &pe) == PW_OK)
        pgp__mask_tile(&a, f + 2 * nn, n, layers, out, &pe);
    pw_free(&a, f);
    return pgp__done(&pe, err);
}
