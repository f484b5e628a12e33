/* image: float images and their file formats.
 *
 * A pw_image holds w*h pixels of c channels (1 gray, 2 gray+alpha, 3 RGB,
 * 4 RGBA) as floats in [0,1], row 0 at the top (file order). Texture
 * lookups use the OBJ/OpenGL convention: v = 0 is the bottom row. `bits`
 * remembers the sample depth of the source (8 or 16) so that a round trip
 * writes what was read.
 *
 * This module reads and writes the netpbm formats (PBM P1/P4 read only,
 * PGM P2/P5, PPM P3/P6, PAM P7; maxval up to 65535, 16-bit samples big
 * endian, values scaled by maxval) and reads GIMP patterns (.pat). Writers
 * quantise with pw_image_quantize: clamp to [0,1], round to nearest, NaN
 * becomes 0. Every reader takes a `name` (usually the file name) that
 * starts each error message, with the line number for text headers.
 *
 *   pw_image_alloc, pw_image_free, pw_image_copy   (a = NULL: PW_MALLOC)
 *   pw_image_convert          1-4 channels: gray <-> RGB, add/drop alpha
 *   pw_image_sample_bilinear  clamped lookup in pixel coordinates
 *   pw_image_quantize, pw_image_to_u8
 *   pw_image_read_pnm_memory  P1-P7     pw_image_read_pat_memory  .pat
 *   pw_image_write_pnm        PGM/PPM (binary or ASCII), PAM with alpha
 *   pw_image_write_pam        PAM for any channel count
 *
 * The front end that detects the format of a buffer or file and also
 * handles PNG -- pw_image_read_memory, pw_image_load, pw_image_save -- is in
 * png.h, because PNG needs deflate.h, which comes after this module in the
 * module order (base vec rng image deflate png). */
#ifndef PW__IMAGE_V1
#define PW__IMAGE_V1

#include "base.h"

typedef struct pw_image {
    int w, h, c;
    int bits;
    float *px; /* w*h*c, px[(y*w + x)*c + k] */
} pw_image;

/* Allocates a zeroed w x h x c image (bits = 8). Checks the limits. */
PW__DEF int pw_image_alloc(const pw_alloc *a, pw_image *img, int w, int h, int c, pw_err *e)
{
    memset(img, 0, sizeof *img);
    if (w <= 0 || h <= 0 || c < 1 || c > 4)
        return pw_fail(e, PW_ERR_INVALID, "invalid image size %dx%d with %d channels", w, h, c);
    if (w > PW_MAX_IMAGE_DIM || h > PW_MAX_IMAGE_DIM || (int64_t)w * h > PW_MAX_IMAGE_PIXELS)
        return pw_fail(e, PW_ERR_LIMIT, "image %dx%d exceeds the limit of %d pixels", w, h, PW_MAX_IMAGE_PIXELS);
    img->px = (float *)pw_calloc_array(a, (size_t)w * h * c, sizeof(float), "image", e);
    if (!img->px) return PW_ERR_NOMEM;
    img->w = w;
    img->h = h;
    img->c = c;
    img->bits = 8;
    return PW_OK;
}

PW__DEF void pw_image_free(const pw_alloc *a, pw_image *img)
{
    if (!img) return;
    pw_free(a, img->px);
    memset(img, 0, sizeof *img);
}

/* ======================================================================
 * Helpers
 * ====================================================================== */

/* v in [0,1] to an integer in [0, maxval]: clamped, rounded to nearest,
 * NaN -> 0. Every writer quantises with this, so reading a file and writing
 * it back at the same depth reproduces its samples exactly. */
PW__DEF unsigned pw_image_quantize(float v, unsigned maxval)
{
    if (!(v > 0.0f)) return 0; /* also NaN */
    if (v >= 1.0f) return maxval;
    return (unsigned)(v * (float)maxval + 0.5f);
}

/* Checks that img is a usable image (for writers and converters). */
PW__DEF int pw__image_check(const pw_image *img, pw_err *e)
{
    if (!img || !img->px || img->w <= 0 || img->h <= 0 || img->c < 1 || img->c > 4)
        return pw_fail(e, PW_ERR_INVALID, "invalid image (%dx%d, %d channels)", img ? img->w : 0, img ? img->h : 0,
                       img ? img->c : 0);
    if (img->w > PW_MAX_IMAGE_DIM || img->h > PW_MAX_IMAGE_DIM || (int64_t)img->w * img->h > PW_MAX_IMAGE_PIXELS)
        return pw_fail(e, PW_ERR_LIMIT, "image %dx%d exceeds the size limits", img->w, img->h);
    return PW_OK;
}

/* The image format a file name's extension names (case-insensitive):
 * "png", "ppm" (.ppm and .pnm), "pgm", "pam"; NULL for any other. */
PW__DEF const char *pw_image_format_of(const char *path)
{
    if (pw_has_ext(path, ".png")) return "png";
    if (pw_has_ext(path, ".ppm") || pw_has_ext(path, ".pnm")) return "ppm";
    if (pw_has_ext(path, ".pgm")) return "pgm";
    if (pw_has_ext(path, ".pam")) return "pam";
    return NULL;
}

/* A deep copy of src (same size, channels and bits). */
PW__DEF int pw_image_copy(const pw_alloc *a, const pw_image *src, pw_image *out, pw_err *e)
{
    int r = pw__image_check(src, e);
    if (r) return r;
    if (src == out) return PW_OK;
    r = pw_image_alloc(a, out, src->w, src->h, src->c, e);
    if (r) return r;
    memcpy(out->px, src->px, (size_t)src->w * src->h * src->c * sizeof(float));
    out->bits = src->bits;
    return PW_OK;
}

/* Converts src to `channels` (1-4): gray <-> RGB, adding alpha (= 1) or
 * dropping it (without compositing). RGB to gray uses the Rec. 601 luma
 * weights, as netpbm's ppmtopgm does. out may be src itself: its pixels are
 * then replaced (and freed with a). */
PW__DEF int pw_image_convert(const pw_alloc *a, const pw_image *src, int channels, pw_image *out, pw_err *e)
{
    pw_image t;
    size_t i, n;
    int r = pw__image_check(src, e), sc;
    if (r) return r;
    if (channels < 1 || channels > 4)
        return pw_fail(e, PW_ERR_INVALID, "cannot convert an image to %d channels", channels);
    r = pw_image_alloc(a, &t, src->w, src->h, channels, e);
    if (r) return r;
    t.bits = src->bits;
    sc = src->c;
    n = (size_t)src->w * src->h;
    for (i = 0; i < n; i++) {
        const float *s = src->px + i * sc;
        float *d = t.px + i * channels, rgba[4];
        rgba[0] = s[0];
        rgba[1] = sc >= 3 ? s[1] : s[0];
        rgba[2] = sc >= 3 ? s[2] : s[0];
        rgba[3] = sc == 2 ? s[1] : sc == 4 ? s[3] : 1.0f;
        if (channels <= 2) {
            d[0] = sc >= 3 ? 0.299f * rgba[0] + 0.587f * rgba[1] + 0.114f * rgba[2] : rgba[0];
            if (channels == 2) d[1] = rgba[3];
        } else {
            memcpy(d, rgba, (size_t)channels * sizeof(float));
        }
    }
    if (out == src) pw_free(a, out->px);
    *out = t;
    return PW_OK;
}

/* Bilinear lookup in pixel coordinates: x = 0.5 is the centre of column 0,
 * y = 0.5 the centre of row 0 (the top row); outside, the edge pixels
 * extend. Writes img->c floats to out. NaN coordinates read pixel (0,0). */
PW__DEF void pw_image_sample_bilinear(const pw_image *img, float x, float y, float *out)
{
    float fx = x - 0.5f, fy = y - 0.5f, tx, ty;
    int x0, y0, x1, y1, k, c = img->c;
    const float *p00, *p10, *p01, *p11;
    /* clamp first: keeps floor() within int range and makes NaN harmless */
    fx = fx > -1.0f ? (fx < (float)img->w ? fx : (float)img->w) : -1.0f;
    fy = fy > -1.0f ? (fy < (float)img->h ? fy : (float)img->h) : -1.0f;
    x0 = (int)floorf(fx);
    y0 = (int)floorf(fy);
    tx = fx - (float)x0;
    ty = fy - (float)y0;
    x1 = pw_clampi(x0 + 1, 0, img->w - 1);
    y1 = pw_clampi(y0 + 1, 0, img->h - 1);
    x0 = pw_clampi(x0, 0, img->w - 1);
    y0 = pw_clampi(y0, 0, img->h - 1);
    p00 = img->px + ((size_t)y0 * img->w + x0) * c;
    p10 = img->px + ((size_t)y0 * img->w + x1) * c;
    p01 = img->px + ((size_t)y1 * img->w + x0) * c;
    p11 = img->px + ((size_t)y1 * img->w + x1) * c;
    for (k = 0; k < c; k++) {
        float top = p00[k] + (p10[k] - p00[k]) * tx;
        float bot = p01[k] + (p11[k] - p01[k]) * tx;
        out[k] = top + (bot - top) * ty;
    }
}

/* The pixels quantised to bytes (w*h*c, same layout), for display and for
 * code that wants 8-bit data. Free *out with pw_free(a, ...). */
PW__DEF int pw_image_to_u8(const pw_alloc *a, const pw_image *img, unsigned char **out, pw_err *e)
{
    size_t i, n;
    int r = pw__image_check(img, e);
    *out = NULL;
    if (r) return r;
    n = (size_t)img->w * img->h * img->c;
    *out = (unsigned char *)pw_alloc_array(a, n, 1, "8-bit image", e);
    if (!*out) return PW_ERR_NOMEM;
    for (i = 0; i < n; i++) (*out)[i] = (unsigned char)pw_image_quantize(img->px[i], 255);
    return PW_OK;
}

/* Buffered output through a pw_write_fn, so writers need no allocation. */
typedef struct pw__sink {
    pw_write_fn w;
    void *ctx;
    int failed;
    size_t n;
    unsigned char buf[4096];
} pw__sink;

PW__DEF void pw__sink_init(pw__sink *s, pw_write_fn w, void *ctx)
{
    s->w = w;
    s->ctx = ctx;
    s->failed = 0;
    s->n = 0;
}

PW__DEF void pw__sink_flush(pw__sink *s)
{
    if (s->n && !s->failed && s->w(s->ctx, s->buf, s->n)) s->failed = 1;
    s->n = 0;
}

PW__DEF void pw__sink_put(pw__sink *s, const void *data, size_t n)
{
    const unsigned char *p = (const unsigned char *)data;
    while (n > 0) {
        size_t k = sizeof s->buf - s->n;
        if (k > n) k = n;
        memcpy(s->buf + s->n, p, k);
        s->n += k;
        p += k;
        n -= k;
        if (s->n == sizeof s->buf) pw__sink_flush(s);
    }
}

PW__DEF void pw__sink_byte(pw__sink *s, unsigned c)
{
    if (s->n == sizeof s->buf) pw__sink_flush(s);
    s->buf[s->n++] = (unsigned char)c;
}

/* Flushes and returns PW_OK or PW_ERR_IO (recorded in e). */
PW__DEF int pw__sink_end(pw__sink *s, pw_err *e)
{
    pw__sink_flush(s);
    return s->failed ? pw_fail(e, PW_ERR_IO, "write error") : PW_OK;
}

/* Refuses zero and over-limit sizes; called on header values before any
 * multiplication or allocation. */
PW__DEF int pw__image_check_size(const char *name, uint64_t w, uint64_t h, pw_err *e)
{
    if (w == 0 || h == 0)
        return pw_fail(e, PW_ERR_PARSE, "%s: image has zero size (%llux%llu)", name, (unsigned long long)w,
                       (unsigned long long)h);
    if (w > PW_MAX_IMAGE_DIM || h > PW_MAX_IMAGE_DIM || w * h > (uint64_t)PW_MAX_IMAGE_PIXELS)
        return pw_fail(e, PW_ERR_LIMIT, "%s: image size %llux%llu exceeds the limits (%d per side, %d pixels)", name,
                       (unsigned long long)w, (unsigned long long)h, PW_MAX_IMAGE_DIM, PW_MAX_IMAGE_PIXELS);
    return PW_OK;
}

/* ======================================================================
 * Netpbm: PBM, PGM, PPM (P1-P6) and PAM (P7)
 * ====================================================================== */

typedef struct pw__pnm {
    const unsigned char *p;
    size_t n, pos;
    int line; /* current line (1-based), for messages */
    const char *name;
    pw_err *e;
    int fmt; /* the digit of the magic, 1-7 */
    uint64_t w, h, depth, maxval;
} pw__pnm;

PW__DEF int pw__is_space(int c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

/* Skips whitespace and comments (# to the end of the line). */
PW__DEF void pw__pnm_skip(pw__pnm *r)
{
    while (r->pos < r->n) {
        int c = r->p[r->pos];
        if (c == '#') {
            while (r->pos < r->n && r->p[r->pos] != '\n' && r->p[r->pos] != '\r') r->pos++;
        } else if (pw__is_space(c)) {
            if (c == '\n') r->line++;
            r->pos++;
        } else {
            break;
        }
    }
}

/* Error for an unexpected byte, shown as a character when printable. */
PW__DEF int pw__pnm_unexpected(pw__pnm *r, const char *what)
{
    int c = r->p[r->pos];
    if (c > 32 && c < 127)
        return pw_fail(r->e, PW_ERR_PARSE, "%s:%d: expected the %s, found '%c'", r->name, r->line, what, c);
    return pw_fail(r->e, PW_ERR_PARSE, "%s:%d: expected the %s, found byte 0x%02x", r->name, r->line, what, c);
}

/* Reads an unsigned decimal number: a header field or an ASCII sample. */
PW__DEF int pw__pnm_number(pw__pnm *r, const char *what, uint64_t *v)
{
    uint64_t x = 0;
    pw__pnm_skip(r);
    if (r->pos >= r->n)
        return pw_fail(r->e, PW_ERR_PARSE, "%s:%d: file truncated: it ends before the %s", r->name, r->line, what);
    if (r->p[r->pos] < '0' || r->p[r->pos] > '9') return pw__pnm_unexpected(r, what);
    while (r->pos < r->n && r->p[r->pos] >= '0' && r->p[r->pos] <= '9') {
        x = x * 10 + (uint64_t)(r->p[r->pos++] - '0');
        if (x > 0xffffffffu) return pw_fail(r->e, PW_ERR_LIMIT, "%s:%d: %s is too large", r->name, r->line, what);
    }
    if (r->pos < r->n && !pw__is_space(r->p[r->pos]) && r->p[r->pos] != '#')
        return pw__pnm_unexpected(r, "end of the number");
    *v = x;
    return PW_OK;
}

PW__DEF int pw__pnm_check_maxval(pw__pnm *r)
{
    if (r->maxval == 0 || r->maxval > 65535)
        return pw_fail(r->e, PW_ERR_PARSE, "%s:%d: maxval %llu is out of range (1 to 65535)", r->name, r->line,
                       (unsigned long long)r->maxval);
    return PW_OK;
}

/* Width, height and maxval of P1-P6. */
PW__DEF int pw__pnm_header(pw__pnm *r)
{
    int rc;
    if (r->pos < r->n && !pw__is_space(r->p[r->pos]) && r->p[r->pos] != '#')
        return pw_fail(r->e, PW_ERR_PARSE, "%s: bad magic number (P%d not followed by a space)", r->name, r->fmt);
    if ((rc = pw__pnm_number(r, "width", &r->w))) return rc;
    if ((rc = pw__pnm_number(r, "height", &r->h))) return rc;
    r->maxval = 1;
    if (r->fmt != 1 && r->fmt != 4) {
        if ((rc = pw__pnm_number(r, "maxval", &r->maxval))) return rc;
        if ((rc = pw__pnm_check_maxval(r))) return rc;
    }
    r->depth = (r->fmt == 3 || r->fmt == 6) ? 3 : 1;
    return pw__image_check_size(r->name, r->w, r->h, r->e);
}

PW__DEF int pw__pnm_need(pw__pnm *r, uint64_t need)
{
    if ((uint64_t)(r->n - r->pos) < need)
        return pw_fail(r->e, PW_ERR_PARSE, "%s: pixel data truncated: %llu bytes needed, %llu present", r->name,
                       (unsigned long long)need, (unsigned long long)(r->n - r->pos));
    return PW_OK;
}

/* Moves to the binary raster: after the last header field, an optional
 * comment, then exactly one whitespace byte. Checks that `need` bytes
 * follow. */
PW__DEF int pw__pnm_raster(pw__pnm *r, uint64_t need)
{
    int c;
    if (r->pos < r->n && r->p[r->pos] == '#')
        while (r->pos < r->n && r->p[r->pos] != '\n' && r->p[r->pos] != '\r') r->pos++;
    if (r->pos >= r->n) return pw_fail(r->e, PW_ERR_PARSE, "%s: file truncated: no pixel data", r->name);
    c = r->p[r->pos++];
    /* CRLF from a text-mode writer: skip the LF when exactly the raster
     * follows it (a lone CR separator followed by a sample 10 is kept) */
    if (c == '\r' && r->pos < r->n && r->p[r->pos] == '\n' && r->n - r->pos - 1 == need) r->pos++;
    return pw__pnm_need(r, need);
}

/* Binary samples (1 byte, or 2 big-endian bytes when maxval > 255). */
PW__DEF int pw__pnm_binary(pw__pnm *r, pw_image *img)
{
    size_t i, n = (size_t)img->w * img->h * img->c;
    const unsigned char *p = r->p + r->pos;
    unsigned v, m = (unsigned)r->maxval;
    for (i = 0; i < n; i++) {
        v = m > 255 ? (unsigned)p[2 * i] << 8 | p[2 * i + 1] : p[i];
        if (v > m)
            return pw_fail(r->e, PW_ERR_PARSE, "%s: sample %lu is %u, above maxval %u", r->name, (unsigned long)i, v,
                           m);
        img->px[i] = (float)v / (float)m;
    }
    return PW_OK;
}

/* ASCII samples (P2, P3): decimal numbers separated by whitespace. */
PW__DEF int pw__pnm_ascii(pw__pnm *r, pw_image *img)
{
    size_t i, n = (size_t)img->w * img->h * img->c;
    uint64_t v;
    int rc;
    for (i = 0; i < n; i++) {
        if ((rc = pw__pnm_number(r, "sample", &v))) return rc;
        if (v > r->maxval)
            return pw_fail(r->e, PW_ERR_PARSE, "%s:%d: sample %lu is %llu, above maxval %llu", r->name, r->line,
                           (unsigned long)i, (unsigned long long)v, (unsigned long long)r->maxval);
        img->px[i] = (float)v / (float)r->maxval;
    }
    return PW_OK;
}

/* PBM: 1 is black. P1 digits need no separators; P4 rows are padded to
 * whole bytes, most significant bit first. */
PW__DEF int pw__pbm_pixels(pw__pnm *r, pw_image *img)
{
    size_t x, y, row = ((size_t)img->w + 7) / 8;
    for (y = 0; y < (size_t)img->h; y++)
        for (x = 0; x < (size_t)img->w; x++) {
            int bit;
            if (r->fmt == 4) {
                bit = (r->p[r->pos + y * row + x / 8] >> (7 - x % 8)) & 1;
            } else {
                pw__pnm_skip(r);
                if (r->pos >= r->n)
                    return pw_fail(r->e, PW_ERR_PARSE, "%s:%d: file truncated: it ends before pixel %lu", r->name,
                                   r->line, (unsigned long)(y * img->w + x));
                if (r->p[r->pos] != '0' && r->p[r->pos] != '1') return pw__pnm_unexpected(r, "bit 0 or 1");
                bit = r->p[r->pos++] - '0';
            }
            img->px[y * img->w + x] = bit ? 0.0f : 1.0f;
        }
    return PW_OK;
}

/* True when the n bytes at s spell the keyword kw. */
PW__DEF int pw__token_is(const unsigned char *s, size_t n, const char *kw)
{
    return strlen(kw) == n && memcmp(s, kw, n) == 0;
}

/* Parses the value of a numeric PAM field (the whole value must be digits). */
PW__DEF int pw__pam_number(pw__pnm *r, const unsigned char *s, size_t n, const char *key, uint64_t *v)
{
    size_t i;
    uint64_t x = 0;
    if (n == 0 || n > 10)
        return pw_fail(r->e, n ? PW_ERR_LIMIT : PW_ERR_PARSE, "%s:%d: bad %s value", r->name, r->line, key);
    for (i = 0; i < n; i++) {
        if (s[i] < '0' || s[i] > '9')
            return pw_fail(r->e, PW_ERR_PARSE, "%s:%d: bad %s value (not a number)", r->name, r->line, key);
        x = x * 10 + (uint64_t)(s[i] - '0');
    }
    *v = x;
    return PW_OK;
}

/* One "KEY value" line of a PAM header; sets *done at ENDHDR. */
PW__DEF int pw__pam_line(pw__pnm *r, const unsigned char *s, size_t n, char *tupltype, int *done)
{
    size_t k = 0, v;
    while (n > 0 && pw__is_space(s[0])) {
        s++;
        n--;
    }
    while (n > 0 && pw__is_space(s[n - 1])) n--;
    while (k < n && !pw__is_space(s[k])) k++;
    v = k;
    while (v < n && pw__is_space(s[v])) v++;
    if (n == 0 || s[0] == '#') return PW_OK;
    if (pw__token_is(s, k, "ENDHDR")) {
        *done = 1;
        return PW_OK;
    }
    if (pw__token_is(s, k, "WIDTH")) return pw__pam_number(r, s + v, n - v, "WIDTH", &r->w);
    if (pw__token_is(s, k, "HEIGHT")) return pw__pam_number(r, s + v, n - v, "HEIGHT", &r->h);
    if (pw__token_is(s, k, "DEPTH")) return pw__pam_number(r, s + v, n - v, "DEPTH", &r->depth);
    if (pw__token_is(s, k, "MAXVAL")) return pw__pam_number(r, s + v, n - v, "MAXVAL", &r->maxval);
    if (pw__token_is(s, k, "TUPLTYPE")) {
        size_t m = n - v < 63 ? n - v : 63;
        memcpy(tupltype, s + v, m);
        tupltype[m] = 0;
        return PW_OK;
    }
    return pw_fail(r->e, PW_ERR_PARSE, "%s:%d: unknown PAM header field '%.*s'", r->name, r->line,
                   (int)(k < 32 ? k : 32), (const char *)s);
}

/* Checks TUPLTYPE against DEPTH; an absent TUPLTYPE is read by depth. */
PW__DEF int pw__pam_tupltype(pw__pnm *r, const char *t)
{
    static const char *const names[6] = {"GRAYSCALE", "GRAYSCALE_ALPHA", "RGB",
                                         "RGB_ALPHA", "BLACKANDWHITE",   "BLACKANDWHITE_ALPHA"};
    static const int depths[6] = {1, 2, 3, 4, 1, 2};
    int i;
    if (r->depth == 0 || r->depth > 4)
        return pw_fail(r->e, r->depth ? PW_ERR_UNSUPPORTED : PW_ERR_PARSE,
                       "%s: PAM depth %llu is not supported (1 to 4)", r->name, (unsigned long long)r->depth);
    if (!t[0]) return PW_OK;
    for (i = 0; i < 6; i++)
        if (strcmp(t, names[i]) == 0) {
            if ((uint64_t)depths[i] == r->depth) return PW_OK;
            return pw_fail(r->e, PW_ERR_PARSE, "%s: TUPLTYPE %s needs DEPTH %d, not %llu", r->name, t, depths[i],
                           (unsigned long long)r->depth);
        }
    return pw_fail(r->e, PW_ERR_UNSUPPORTED, "%s: PAM TUPLTYPE '%s' is not supported", r->name, t);
}

/* The PAM header, up to and including the ENDHDR line. */
PW__DEF int pw__pam_header(pw__pnm *r)
{
    char tupltype[64];
    int done = 0, rc;
    tupltype[0] = 0;
    r->w = r->h = r->depth = r->maxval = 0;
    while (r->pos < r->n && r->p[r->pos] != '\n') /* rest of the "P7" line */
        if (!pw__is_space(r->p[r->pos++]))
            return pw_fail(r->e, PW_ERR_PARSE, "%s: bad magic number (P7 not followed by a newline)", r->name);
    while (!done) {
        size_t start, end;
        if (r->pos >= r->n)
            return pw_fail(r->e, PW_ERR_PARSE, "%s:%d: file truncated: PAM header has no ENDHDR", r->name, r->line);
        r->pos++; /* the newline ending the previous line */
        r->line++;
        start = end = r->pos;
        while (end < r->n && r->p[end] != '\n') end++;
        if (end >= r->n)
            return pw_fail(r->e, PW_ERR_PARSE, "%s:%d: file truncated: PAM header has no ENDHDR", r->name, r->line);
        r->pos = end;
        if ((rc = pw__pam_line(r, r->p + start, end - start, tupltype, &done))) return rc;
    }
    r->pos++; /* the raster follows the ENDHDR line */
    if (!r->w || !r->h || !r->depth || !r->maxval)
        return pw_fail(r->e, PW_ERR_PARSE, "%s: PAM header lacks %s", r->name,
                       !r->w       ? "WIDTH"
                       : !r->h     ? "HEIGHT"
                       : !r->depth ? "DEPTH"
                                   : "MAXVAL");
    if ((rc = pw__pnm_check_maxval(r)) || (rc = pw__pam_tupltype(r, tupltype))) return rc;
    return pw__image_check_size(r->name, r->w, r->h, r->e);
}

/* Reads a netpbm image (P1-P7) from memory. `name` (usually the file name)
 * prefixes every error message. Bit depth: 16 when maxval > 255. */
PW__DEF int pw_image_read_pnm_memory(const pw_alloc *a, const unsigned char *data, size_t size, const char *name,
                                     pw_image *out, pw_err *e)
{
    pw__pnm r;
    uint64_t need = 0;
    int rc;
    memset(out, 0, sizeof *out);
    memset(&r, 0, sizeof r);
    r.p = data;
    r.n = size;
    r.pos = 2;
    r.line = 1;
    r.name = name ? name : "image";
    r.e = e;
    if (size < 2 || data[0] != 'P' || data[1] < '1' || data[1] > '7')
        return pw_fail(e, PW_ERR_PARSE, "%s: not a PNM/PAM file (no P1-P7 magic number)", r.name);
    r.fmt = data[1] - '0';
    rc = r.fmt == 7 ? pw__pam_header(&r) : pw__pnm_header(&r);
    if (rc) return rc;
    /* enough bytes before allocating: the raster for binary formats, one
     * character (P1) or two (digit + separator, P2/P3) per sample */
    if (r.fmt >= 4) {
        need = r.fmt == 4 ? (r.w + 7) / 8 * r.h : r.w * r.h * r.depth * (r.maxval > 255 ? 2 : 1);
        rc = r.fmt == 7 ? pw__pnm_need(&r, need) : pw__pnm_raster(&r, need);
        if (rc) return rc;
    } else if ((uint64_t)(r.n - r.pos) < r.w * r.h * r.depth * (r.fmt == 1 ? 1 : 2) - 1) {
        return pw_fail(e, PW_ERR_PARSE, "%s: file truncated: too short for %llu samples", r.name,
                       (unsigned long long)(r.w * r.h * r.depth));
    }
    if ((rc = pw_image_alloc(a, out, (int)r.w, (int)r.h, (int)r.depth, e))) return rc;
    out->bits = r.maxval > 255 ? 16 : 8;
    rc = (r.fmt == 1 || r.fmt == 4)   ? pw__pbm_pixels(&r, out)
         : (r.fmt == 2 || r.fmt == 3) ? pw__pnm_ascii(&r, out)
                                      : pw__pnm_binary(&r, out);
    if (rc) pw_image_free(a, out);
    return rc;
}

/* ======================================================================
 * GIMP pattern (.pat), read only
 * ====================================================================== */

PW__DEF uint32_t pw__be32(const unsigned char *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

/* Header: big-endian uint32 header_size, version (1), width, height, bytes
 * per pixel (1 gray, 2 gray+alpha, 3 RGB, 4 RGBA), magic "GPAT", then the
 * NUL-terminated pattern name up to header_size; 8-bit pixels follow, top
 * row first. */
PW__DEF int pw_image_read_pat_memory(const pw_alloc *a, const unsigned char *data, size_t size, const char *name,
                                     pw_image *out, pw_err *e)
{
    uint32_t hs, ver, w, h, bpp;
    size_t i, n;
    int rc;
    memset(out, 0, sizeof *out);
    if (!name) name = "image";
    if (size < 24) return pw_fail(e, PW_ERR_PARSE, "%s: GIMP pattern header truncated", name);
    if (memcmp(data + 20, "GPAT", 4) != 0) return pw_fail(e, PW_ERR_PARSE, "%s: not a GIMP pattern (bad magic)", name);
    hs = pw__be32(data);
    ver = pw__be32(data + 4);
    w = pw__be32(data + 8);
    h = pw__be32(data + 12);
    bpp = pw__be32(data + 16);
    if (ver != 1)
        return pw_fail(e, PW_ERR_UNSUPPORTED, "%s: GIMP pattern version %lu (only 1 is known)", name,
                       (unsigned long)ver);
    if (hs <= 24 || hs > size)
        return pw_fail(e, PW_ERR_PARSE, "%s: bad GIMP pattern header size %lu (file has %lu bytes)", name,
                       (unsigned long)hs, (unsigned long)size);
    if (!memchr(data + 24, 0, hs - 24))
        return pw_fail(e, PW_ERR_PARSE, "%s: GIMP pattern name is not NUL-terminated", name);
    if (bpp < 1 || bpp > 4)
        return pw_fail(e, PW_ERR_PARSE, "%s: GIMP pattern has %lu bytes per pixel (1 to 4)", name, (unsigned long)bpp);
    if ((rc = pw__image_check_size(name, w, h, e))) return rc;
    if ((uint64_t)w * h * bpp > (uint64_t)(size - hs))
        return pw_fail(e, PW_ERR_PARSE, "%s: pixel data truncated: %llu bytes needed, %lu present", name,
                       (unsigned long long)((uint64_t)w * h * bpp), (unsigned long)(size - hs));
    if ((rc = pw_image_alloc(a, out, (int)w, (int)h, (int)bpp, e))) return rc;
    n = (size_t)w * h * bpp;
    for (i = 0; i < n; i++) out->px[i] = (float)data[hs + i] / 255.0f;
    return PW_OK;
}

/* ======================================================================
 * Netpbm writers
 * ====================================================================== */

/* Resolves the `bits` argument of a writer (0 = the image's own depth). */
PW__DEF int pw__write_bits(const pw_image *img, int bits, unsigned *maxval, pw_err *e)
{
    int rc = pw__image_check(img, e);
    if (rc) return rc;
    if (bits == 0) bits = img->bits == 16 ? 16 : 8;
    if (bits != 8 && bits != 16) return pw_fail(e, PW_ERR_INVALID, "cannot write %d-bit samples (8 or 16)", bits);
    *maxval = bits == 16 ? 65535u : 255u;
    return PW_OK;
}

/* Binary samples: bytes, or big-endian pairs for maxval 65535. */
PW__DEF void pw__put_samples(pw__sink *s, const pw_image *img, unsigned maxval)
{
    size_t i, n = (size_t)img->w * img->h * img->c;
    for (i = 0; i < n; i++) {
        unsigned v = pw_image_quantize(img->px[i], maxval);
        if (maxval > 255) pw__sink_byte(s, v >> 8);
        pw__sink_byte(s, v & 255);
    }
}

/* ASCII samples: one image row per line group, lines under 70 characters
 * as the netpbm specification asks. */
PW__DEF void pw__put_ascii(pw__sink *s, const pw_image *img, unsigned maxval)
{
    size_t x, y, rowlen = (size_t)img->w * img->c;
    char num[16];
    for (y = 0; y < (size_t)img->h; y++) {
        int col = 0;
        for (x = 0; x < rowlen; x++) {
            int k = snprintf(num, sizeof num, "%u", pw_image_quantize(img->px[y * rowlen + x], maxval));
            if (col > 0 && col + 1 + k > 69) {
                pw__sink_byte(s, '\n');
                col = 0;
            } else if (col > 0) {
                pw__sink_byte(s, ' ');
                col++;
            }
            pw__sink_put(s, num, (size_t)k);
            col += k;
        }
        pw__sink_byte(s, '\n');
    }
}

/* PAM (P7) for any channel count, binary. bits: 8, 16, or 0 for img->bits. */
PW__DEF int pw_image_write_pam(const pw_image *img, int bits, pw_write_fn w, void *ctx, pw_err *e)
{
    static const char *const types[4] = {"GRAYSCALE", "GRAYSCALE_ALPHA", "RGB", "RGB_ALPHA"};
    pw__sink s;
    char head[160];
    unsigned maxval;
    int rc = pw__write_bits(img, bits, &maxval, e), k;
    if (rc) return rc;
    k = snprintf(head, sizeof head, "P7\nWIDTH %d\nHEIGHT %d\nDEPTH %d\nMAXVAL %u\nTUPLTYPE %s\nENDHDR\n", img->w,
                 img->h, img->c, maxval, types[img->c - 1]);
    pw__sink_init(&s, w, ctx);
    pw__sink_put(&s, head, (size_t)k);
    pw__put_samples(&s, img, maxval);
    return pw__sink_end(&s, e);
}

/* PGM for 1 channel, PPM for 3 (binary P5/P6, or ASCII P2/P3 when `ascii`
 * is set), PAM for 2 and 4 (binary only: PW_ERR_UNSUPPORTED with ascii). */
PW__DEF int pw_image_write_pnm(const pw_image *img, int bits, int ascii, pw_write_fn w, void *ctx, pw_err *e)
{
    pw__sink s;
    char head[64];
    unsigned maxval;
    int rc = pw__write_bits(img, bits, &maxval, e), k;
    if (rc) return rc;
    if (img->c == 2 || img->c == 4) {
        if (ascii)
            return pw_fail(e, PW_ERR_UNSUPPORTED, "images with alpha are written as PAM, which has no ASCII form");
        return pw_image_write_pam(img, bits, w, ctx, e);
    }
    k = snprintf(head, sizeof head, "P%d\n%d %d\n%u\n", (img->c == 1 ? 2 : 3) + (ascii ? 0 : 3), img->w, img->h,
                 maxval);
    pw__sink_init(&s, w, ctx);
    pw__sink_put(&s, head, (size_t)k);
    if (ascii) pw__put_ascii(&s, img, maxval);
    else pw__put_samples(&s, img, maxval);
    return pw__sink_end(&s, e);
}

#endif /* PW__IMAGE_V1 */
