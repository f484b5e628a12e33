/* png: PNG writer and reader, and the image front end.
 *
 * Writer: 8- or 16-bit gray, gray+alpha, RGB or RGBA by channel count; each
 * row gets the filter whose output has the smallest sum of absolute values
 * (the heuristic the PNG specification suggests); one zlib stream split in
 * 64 KiB IDAT chunks. Temporary buffers come from the caller's allocator
 * (NULL: PW_MALLOC).
 *
 * Reader: every colour type (0 gray, 2 RGB, 3 palette, 4 gray+alpha, 6
 * RGBA) and bit depth (1, 2, 4, 8, 16), tRNS (palette alpha or a colour
 * key, which adds an alpha channel), all five filters, Adam7 interlacing,
 * CRC checks, any number of IDAT chunks. Output channels: gray 1 (2 with
 * tRNS), RGB 3 (4 with tRNS), palette 3 or 4, gray+alpha 2, RGBA 4; bits is
 * 16 for 16-bit files, else 8. Sizes are checked before allocation and the
 * decompressed size is capped at what the IHDR implies. Ancillary chunks
 * (gAMA, sRGB, text...) are ignored: samples are returned as stored.
 *
 * Front end (here rather than in image.h because it dispatches PNG, which
 * needs deflate.h; module order: base vec rng image deflate png):
 *   pw_image_read_memory   any supported format, detected from the content
 *   pw_image_load          the same from a file
 *   pw_image_save          format chosen by the file extension */
#ifndef PW__PNG_V1
#define PW__PNG_V1

#include "base.h"
#include "image.h"
#include "deflate.h"

static const unsigned char pw__png_sig[8] = {137, 80, 78, 71, 13, 10, 26, 10};

/* PW_NO_PNG leaves out the codec (and, where nothing else needs it,
 * deflate.h): the two entry points below refuse instead, and the front end
 * still tells a PNG file by its signature so that loading one fails clearly. */
#ifndef PW_NO_PNG

PW__DEF void pw__put_be32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v >> 24);
    p[1] = (unsigned char)(v >> 16);
    p[2] = (unsigned char)(v >> 8);
    p[3] = (unsigned char)v;
}

/* ======================================================================
 * Writer
 * ====================================================================== */

/* One chunk: length, type, data, CRC of type and data. */
PW__DEF void pw__png_chunk(pw__sink *s, const char *type, const unsigned char *data, size_t n)
{
    unsigned char b[4];
    uint32_t crc = pw_crc32(0, type, 4);
    crc = pw_crc32(crc, data, n);
    pw__put_be32(b, (uint32_t)n);
    pw__sink_put(s, b, 4);
    pw__sink_put(s, type, 4);
    pw__sink_put(s, data, n);
    pw__put_be32(b, crc);
    pw__sink_put(s, b, 4);
}

PW__DEF int pw__absi(int x) { return x < 0 ? -x : x; }

/* The Paeth predictor (PNG specification §9.4). */
PW__DEF int pw__paeth(int a, int b, int c)
{
    int p = a + b - c, pa = pw__absi(p - a), pb = pw__absi(p - b), pc = pw__absi(p - c);
    if (pa <= pb && pa <= pc) return a;
    return pb <= pc ? b : c;
}

/* Filters one row (n bytes, bpp bytes per pixel) with filter type f. */
PW__DEF void pw__png_filter(unsigned char *dst, const unsigned char *cur, const unsigned char *prev, size_t n,
                            size_t bpp, int f)
{
    size_t i;
    for (i = 0; i < n; i++) {
        int x = cur[i], a = i >= bpp ? cur[i - bpp] : 0, b = prev[i];
        int c = i >= bpp ? prev[i - bpp] : 0;
        int pred = f == 0 ? 0 : f == 1 ? a : f == 2 ? b : f == 3 ? (a + b) >> 1 : pw__paeth(a, b, c);
        dst[i] = (unsigned char)(x - pred);
    }
}

/* Quantised rows, each prefixed by the filter byte that minimises the sum
 * of absolute differences (bytes read as signed). */
PW__DEF int pw__png_filtered(const pw_alloc *a, const pw_image *img, unsigned maxval, unsigned char **out, size_t *outn,
                             pw_err *e)
{
    size_t bps = maxval > 255 ? 2 : 1, bpp = bps * (size_t)img->c;
    size_t n = bpp * (size_t)img->w, x, y, k;
    unsigned char *buf, *rows, *cand;
    buf = (unsigned char *)pw_alloc_array(a, (n + 1) * (size_t)img->h, 1, "PNG rows", e);
    rows = (unsigned char *)pw_calloc_array(a, 7, n, "PNG rows", e);
    if (!buf || !rows) {
        pw_free(a, buf);
        pw_free(a, rows);
        return PW_ERR_NOMEM;
    }
    cand = rows + 2 * n; /* rows: previous, current, 5 candidates */
    for (y = 0; y < (size_t)img->h; y++) {
        unsigned char *cur = rows + (y & 1 ? 0 : n), *prev = rows + (y & 1 ? n : 0);
        unsigned long best = (unsigned long)-1;
        int f, bf = 0;
        for (x = 0; x < (size_t)img->w * img->c; x++) {
            unsigned v = pw_image_quantize(img->px[y * img->w * img->c + x], maxval);
            if (bps == 2) cur[2 * x] = (unsigned char)(v >> 8);
            cur[bps * x + bps - 1] = (unsigned char)v;
        }
        for (f = 0; f < 5; f++) {
            unsigned long sum = 0;
            pw__png_filter(cand + f * n, cur, prev, n, bpp, f);
            for (k = 0; k < n; k++) sum += (unsigned long)pw__absi((signed char)cand[f * n + k]);
            if (sum < best) {
                best = sum;
                bf = f;
            }
        }
        buf[y * (n + 1)] = (unsigned char)bf;
        memcpy(buf + y * (n + 1) + 1, cand + bf * n, n);
    }
    pw_free(a, rows);
    *out = buf;
    *outn = (n + 1) * (size_t)img->h;
    return PW_OK;
}

/* Writes img as PNG. bits: 8, 16, or 0 for img->bits. Temporary buffers
 * come from a (NULL: PW_MALLOC). */
PW__DEF int pw_png_write(const pw_alloc *a, const pw_image *img, int bits, pw_write_fn w, void *ctx, pw_err *e)
{
    static const unsigned char ctypes[4] = {0, 4, 2, 6};
    unsigned char ihdr[13], *raw = NULL, *z = NULL;
    size_t rawn, zn, off;
    unsigned maxval;
    pw__sink s;
    int rc = pw__write_bits(img, bits, &maxval, e);
    if (rc) return rc;
    if ((rc = pw__png_filtered(a, img, maxval, &raw, &rawn, e))) return rc;
    rc = pw_zlib_compress(a, raw, rawn, 6, &z, &zn, e);
    pw_free(a, raw);
    if (rc) return rc;
    pw__put_be32(ihdr, (uint32_t)img->w);
    pw__put_be32(ihdr + 4, (uint32_t)img->h);
    ihdr[8] = (unsigned char)(maxval > 255 ? 16 : 8);
    ihdr[9] = ctypes[img->c - 1];
    ihdr[10] = ihdr[11] = ihdr[12] = 0; /* deflate, adaptive filtering, no interlace */
    pw__sink_init(&s, w, ctx);
    pw__sink_put(&s, pw__png_sig, 8);
    pw__png_chunk(&s, "IHDR", ihdr, 13);
    for (off = 0; off < zn; off += 65536) pw__png_chunk(&s, "IDAT", z + off, zn - off < 65536 ? zn - off : 65536);
    pw__png_chunk(&s, "IEND", ihdr, 0);
    pw_free(a, z);
    return pw__sink_end(&s, e);
}

/* ======================================================================
 * Reader
 * ====================================================================== */

typedef struct pw__png {
    const char *name;
    pw_err *e;
    uint32_t w, h;
    int depth, ctype, interlace;
    int spp;        /* samples per pixel in the file */
    int outc;       /* channels of the decoded image */
    int npal, trns; /* palette entries; tRNS seen */
    unsigned char pal[256][4];
    unsigned key[3]; /* tRNS colour key of gray and RGB images */
    int seen_ihdr, seen_idat, seen_iend;
    uint64_t idat_size;
} pw__png;

/* IHDR (§11.2.2): size, and a bit depth allowed for the colour type. */
PW__DEF int pw__png_ihdr(pw__png *p, const unsigned char *d, uint32_t len)
{
    static const int spp[7] = {1, 0, 3, 1, 2, 0, 4};
    int ok, rc;
    if (len != 13)
        return pw_fail(p->e, PW_ERR_PARSE, "%s: IHDR chunk has length %lu, not 13", p->name, (unsigned long)len);
    p->w = pw__be32(d);
    p->h = pw__be32(d + 4);
    p->depth = d[8];
    p->ctype = d[9];
    p->interlace = d[12];
    if (p->ctype > 6 || spp[p->ctype] == 0)
        return pw_fail(p->e, PW_ERR_PARSE, "%s: invalid PNG colour type %d", p->name, p->ctype);
    ok = p->depth == 8 || (p->depth == 16 && p->ctype != 3) ||
         ((p->depth == 1 || p->depth == 2 || p->depth == 4) && (p->ctype == 0 || p->ctype == 3));
    if (!ok)
        return pw_fail(p->e, PW_ERR_PARSE, "%s: bit depth %d is invalid for PNG colour type %d", p->name, p->depth,
                       p->ctype);
    if (d[10] != 0 || d[11] != 0 || p->interlace > 1)
        return pw_fail(p->e, PW_ERR_PARSE, "%s: unknown PNG compression, filter or interlace method (%d, %d, %d)",
                       p->name, d[10], d[11], d[12]);
    if ((rc = pw__image_check_size(p->name, p->w, p->h, p->e))) return rc;
    p->spp = spp[p->ctype];
    p->seen_ihdr = 1;
    return PW_OK;
}

/* PLTE and tRNS (§11.2.3, §11.3.2.1). */
PW__DEF int pw__png_palette(pw__png *p, const char *type, const unsigned char *d, uint32_t len)
{
    uint32_t i;
    if (p->seen_idat) return pw_fail(p->e, PW_ERR_PARSE, "%s: %s chunk after the image data", p->name, type);
    if (type[0] == 'P') {
        if (len % 3 || len == 0 || len > 768)
            return pw_fail(p->e, PW_ERR_PARSE, "%s: PLTE chunk has invalid length %lu", p->name, (unsigned long)len);
        if (p->ctype == 0 || p->ctype == 4) return PW_OK; /* not allowed, harmless */
        p->npal = (int)(len / 3);
        for (i = 0; i < len / 3; i++) {
            memcpy(p->pal[i], d + 3 * i, 3);
            p->pal[i][3] = 255;
        }
        return PW_OK;
    }
    if (p->ctype == 3) {
        if (len > (uint32_t)p->npal)
            return pw_fail(p->e, PW_ERR_PARSE, "%s: tRNS chunk has %lu entries for a palette of %d", p->name,
                           (unsigned long)len, p->npal);
        for (i = 0; i < len; i++) p->pal[i][3] = d[i];
    } else if (p->ctype == 0 || p->ctype == 2) {
        if (len != (p->ctype ? 6u : 2u))
            return pw_fail(p->e, PW_ERR_PARSE, "%s: tRNS chunk has invalid length %lu", p->name, (unsigned long)len);
        for (i = 0; i < len / 2; i++) p->key[i] = (unsigned)d[2 * i] << 8 | d[2 * i + 1];
    } else {
        return PW_OK; /* not allowed with an alpha channel; ignored */
    }
    p->trns = 1;
    return PW_OK;
}

/* Handles one chunk; IDAT data is appended to idat (when not NULL). */
PW__DEF int pw__png_chunk_read(pw__png *p, const unsigned char *c, uint32_t len)
{
    char type[5];
    memcpy(type, c + 4, 4);
    type[4] = 0;
    if (!p->seen_ihdr && strcmp(type, "IHDR") != 0)
        return pw_fail(p->e, PW_ERR_PARSE, "%s: first PNG chunk is not IHDR", p->name);
    if (strcmp(type, "IHDR") == 0) {
        if (p->seen_ihdr) return pw_fail(p->e, PW_ERR_PARSE, "%s: more than one IHDR chunk", p->name);
        return pw__png_ihdr(p, c + 8, len);
    }
    if (strcmp(type, "PLTE") == 0 || strcmp(type, "tRNS") == 0) return pw__png_palette(p, type, c + 8, len);
    if (strcmp(type, "IDAT") == 0) {
        p->idat_size += len;
        p->seen_idat = 1;
        return PW_OK;
    }
    if (strcmp(type, "IEND") == 0) {
        p->seen_iend = 1;
        return PW_OK;
    }
    if (!(type[0] & 0x20)) /* an uppercase first letter marks a critical chunk */
        return pw_fail(p->e, PW_ERR_UNSUPPORTED, "%s: unknown critical PNG chunk '%s'", p->name, type);
    return PW_OK;
}

/* Walks the chunks up to IEND, checking lengths, types and CRCs, and
 * totals the image data. */
PW__DEF int pw__png_walk(pw__png *p, const unsigned char *data, size_t size)
{
    size_t pos = 8;
    int rc, i;
    while (!p->seen_iend) {
        const unsigned char *c = data + pos;
        uint32_t len;
        if (size - pos < 12) return pw_fail(p->e, PW_ERR_PARSE, "%s: PNG file truncated (no IEND chunk)", p->name);
        len = pw__be32(c);
        for (i = 4; i < 8; i++)
            if (!((c[i] >= 'A' && c[i] <= 'Z') || (c[i] >= 'a' && c[i] <= 'z')))
                return pw_fail(p->e, PW_ERR_PARSE, "%s: bad PNG chunk type at offset %lu", p->name, (unsigned long)pos);
        if (len > 0x7fffffffu || len > size - pos - 12)
            return pw_fail(p->e, PW_ERR_PARSE, "%s: PNG chunk '%.4s' truncated (length %lu)", p->name,
                           (const char *)c + 4, (unsigned long)len);
        if (pw_crc32(0, c + 4, len + 4) != pw__be32(c + 8 + len))
            return pw_fail(p->e, PW_ERR_PARSE, "%s: CRC mismatch in PNG chunk '%.4s'", p->name, (const char *)c + 4);
        if ((rc = pw__png_chunk_read(p, c, len))) return rc;
        pos += 12 + (size_t)len;
    }
    if (!p->seen_idat) return pw_fail(p->e, PW_ERR_PARSE, "%s: PNG file has no IDAT chunk", p->name);
    if (p->ctype == 3 && !p->npal) return pw_fail(p->e, PW_ERR_PARSE, "%s: palette PNG has no PLTE chunk", p->name);
    return PW_OK;
}

/* Concatenates the IDAT data of a file that pw__png_walk accepted. */
PW__DEF void pw__png_gather(const unsigned char *data, unsigned char *idat)
{
    size_t pos = 8, n = 0;
    for (;;) {
        uint32_t len = pw__be32(data + pos);
        if (memcmp(data + pos + 4, "IEND", 4) == 0) return;
        if (memcmp(data + pos + 4, "IDAT", 4) == 0) {
            memcpy(idat + n, data + pos + 8, len);
            n += len;
        }
        pos += 12 + (size_t)len;
    }
}

/* Adam7 passes (§8.2): x start, y start, x step, y step. A plain image is
 * the single pass {0, 0, 1, 1}. */
static const unsigned char pw__adam7[7][4] = {{0, 0, 8, 8}, {4, 0, 8, 8}, {0, 4, 4, 8}, {2, 0, 4, 4},
                                              {0, 2, 2, 4}, {1, 0, 2, 2}, {0, 1, 1, 2}};

/* Pixels of a pass along one axis (0 when the pass is empty). */
PW__DEF uint32_t pw__pass_len(uint32_t size, int start, int step)
{
    return size > (uint32_t)start ? (size - (uint32_t)start + (uint32_t)step - 1) / (uint32_t)step : 0;
}

/* Bytes of one filtered row of `w` pixels, without the filter byte. */
PW__DEF uint64_t pw__png_rowbytes(const pw__png *p, uint32_t w)
{
    return ((uint64_t)w * (uint64_t)(p->spp * p->depth) + 7) / 8;
}

/* Size of the decompressed image data the IHDR implies. */
PW__DEF uint64_t pw__png_rawsize(const pw__png *p)
{
    uint64_t total = 0;
    int k;
    if (!p->interlace) return (uint64_t)p->h * (1 + pw__png_rowbytes(p, p->w));
    for (k = 0; k < 7; k++) {
        uint32_t pw = pw__pass_len(p->w, pw__adam7[k][0], pw__adam7[k][2]);
        uint32_t ph = pw__pass_len(p->h, pw__adam7[k][1], pw__adam7[k][3]);
        if (pw && ph) total += (uint64_t)ph * (1 + pw__png_rowbytes(p, pw));
    }
    return total;
}

/* Undoes the filter of one row in place (§9.2); prev is NULL for the first
 * row of a pass. */
PW__DEF int pw__png_unfilter(pw__png *p, unsigned char *row, const unsigned char *prev, size_t n, size_t bpp, int f)
{
    size_t i;
    if (f > 4) return pw_fail(p->e, PW_ERR_PARSE, "%s: invalid PNG filter type %d", p->name, f);
    if (f == 0) return PW_OK;
    for (i = 0; i < n; i++) {
        int a = i >= bpp ? row[i - bpp] : 0, b = prev ? prev[i] : 0;
        int c = prev && i >= bpp ? prev[i - bpp] : 0;
        int pred = f == 1 ? a : f == 2 ? b : f == 3 ? (a + b) >> 1 : pw__paeth(a, b, c);
        row[i] = (unsigned char)(row[i] + pred);
    }
    return PW_OK;
}

/* Sample i of an unfiltered row (depths below 8 pack from the high bit). */
PW__DEF unsigned pw__png_sample(const unsigned char *row, size_t i, int depth)
{
    size_t bit;
    if (depth == 8) return row[i];
    if (depth == 16) return (unsigned)row[2 * i] << 8 | row[2 * i + 1];
    bit = i * (size_t)depth;
    return (unsigned)(row[bit / 8] >> (8 - depth - (int)(bit % 8))) & ((1u << depth) - 1);
}

/* Converts `count` pixels of a row to floats at dst, dst + step, ... */
PW__DEF int pw__png_pixels(pw__png *p, const unsigned char *row, uint32_t count, float *dst, size_t step)
{
    float maxv = (float)((1u << p->depth) - 1);
    unsigned s[4];
    uint32_t x;
    int k;
    for (x = 0; x < count; x++, dst += step) {
        for (k = 0; k < p->spp; k++) s[k] = pw__png_sample(row, (size_t)x * p->spp + k, p->depth);
        if (p->ctype == 3) {
            if (s[0] >= (unsigned)p->npal)
                return pw_fail(p->e, PW_ERR_PARSE, "%s: palette index %u out of range (%d entries)", p->name, s[0],
                               p->npal);
            for (k = 0; k < p->outc; k++) dst[k] = (float)p->pal[s[0]][k] / 255.0f;
            continue;
        }
        for (k = 0; k < p->spp; k++) dst[k] = (float)s[k] / maxv;
        if (p->trns) /* colour key: alpha 0 where the pixel equals it */
            dst[p->spp] =
                (s[0] == p->key[0] && (p->spp == 1 || (s[1] == p->key[1] && s[2] == p->key[2]))) ? 0.0f : 1.0f;
    }
    return PW_OK;
}

/* Unfilters every pass of the decompressed data and fills img. */
PW__DEF int pw__png_decode(pw__png *p, unsigned char *raw, pw_image *img)
{
    static const unsigned char plain[4] = {0, 0, 1, 1};
    size_t bpp = (size_t)(p->spp * p->depth + 7) / 8, c = (size_t)img->c;
    int k, npass = p->interlace ? 7 : 1, rc;
    for (k = 0; k < npass; k++) {
        const unsigned char *a7 = p->interlace ? pw__adam7[k] : plain;
        uint32_t pw = pw__pass_len(p->w, a7[0], a7[2]), ph = pw__pass_len(p->h, a7[1], a7[3]), j;
        size_t n = (size_t)pw__png_rowbytes(p, pw);
        unsigned char *prev = NULL;
        if (!pw || !ph) continue;
        for (j = 0; j < ph; j++) {
            unsigned char *row = raw + 1;
            size_t y = a7[1] + (size_t)j * a7[3];
            if ((rc = pw__png_unfilter(p, row, prev, n, bpp, raw[0]))) return rc;
            rc = pw__png_pixels(p, row, pw, img->px + (y * img->w + a7[0]) * c, a7[2] * c);
            if (rc) return rc;
            prev = row;
            raw += n + 1;
        }
    }
    return PW_OK;
}

/* Decompresses the gathered IDAT data, exactly `want` bytes. */
PW__DEF int pw__png_inflate(pw__png *p, const pw_alloc *a, const unsigned char *z, size_t zn, size_t want,
                            unsigned char **raw)
{
    pw_err local;
    size_t got;
    int rc;
    pw_err_clear(&local);
    rc = pw_zlib_decompress(a, z, zn, want, raw, &got, &local);
    if (rc == PW_ERR_LIMIT)
        return pw_fail(p->e, PW_ERR_PARSE, "%s: PNG image data is longer than the %lu bytes its size implies", p->name,
                       (unsigned long)want);
    if (rc) return pw_fail(p->e, rc, "%s: PNG image data: %s", p->name, local.msg);
    if (got != want) {
        pw_free(a, *raw);
        *raw = NULL;
        return pw_fail(p->e, PW_ERR_PARSE, "%s: PNG image data truncated (%lu of %lu bytes)", p->name,
                       (unsigned long)got, (unsigned long)want);
    }
    return PW_OK;
}

/* Reads a PNG from memory; `name` prefixes error messages. */
PW__DEF int pw_png_read_memory(const pw_alloc *a, const unsigned char *data, size_t size, const char *name,
                               pw_image *out, pw_err *e)
{
    pw__png p;
    unsigned char *z = NULL, *raw = NULL;
    uint64_t want;
    int rc;
    memset(out, 0, sizeof *out);
    memset(&p, 0, sizeof p);
    p.name = name ? name : "image";
    p.e = e;
    if (size < 8 || memcmp(data, pw__png_sig, 8) != 0)
        return pw_fail(e, PW_ERR_PARSE, "%s: not a PNG file (bad signature)", p.name);
    if ((rc = pw__png_walk(&p, data, size))) return rc;
    want = pw__png_rawsize(&p);
    /* deflate expands at most 1032:1 (a 258-byte match in 2 bits): refuse
     * sizes the data cannot hold before allocating anything */
    if (want > p.idat_size * 1032 + 64 || want > (size_t)-1)
        return pw_fail(e, PW_ERR_PARSE, "%s: PNG image data (%lu bytes) too short for a %lux%lu image", p.name,
                       (unsigned long)p.idat_size, (unsigned long)p.w, (unsigned long)p.h);
    z = (unsigned char *)pw_alloc_array(a, (size_t)p.idat_size, 1, "PNG image data", e);
    if (!z) return PW_ERR_NOMEM;
    pw__png_gather(data, z);
    rc = pw__png_inflate(&p, a, z, (size_t)p.idat_size, (size_t)want, &raw);
    pw_free(a, z);
    if (rc) return rc;
    p.outc = p.ctype == 3 ? 3 + p.trns : p.spp + p.trns;
    rc = pw_image_alloc(a, out, (int)p.w, (int)p.h, p.outc, e);
    if (!rc) {
        out->bits = p.depth == 16 ? 16 : 8;
        rc = pw__png_decode(&p, raw, out);
        if (rc) pw_image_free(a, out);
    }
    pw_free(a, raw);
    return rc;
}

#else
PW__DEF int pw_png_write(const pw_alloc *a, const pw_image *img, int bits, pw_write_fn w, void *ctx, pw_err *e)
{
    (void)a;
    (void)img;
    (void)bits;
    (void)w;
    (void)ctx;
    return pw_fail(e, PW_ERR_UNSUPPORTED, "PNG compiled out (PW_NO_PNG)");
}

PW__DEF int pw_png_read_memory(const pw_alloc *a, const unsigned char *data, size_t size, const char *name,
                               pw_image *out, pw_err *e)
{
    (void)a;
    (void)data;
    (void)size;
    memset(out, 0, sizeof *out);
    return pw_fail(e, PW_ERR_UNSUPPORTED, "%s: PNG compiled out (PW_NO_PNG)", name ? name : "image");
}
#endif /* PW_NO_PNG */

/* ======================================================================
 * Front end: any format
 * ====================================================================== */

/* Reads PNG, PNM/PAM (P1-P7) or a GIMP pattern, recognised by content
 * (PNG signature, "P1".."P7", "GPAT" at offset 20). `name` (usually the
 * file name) prefixes every error message; `a` may be NULL. */
PW__DEF int pw_image_read_memory(const pw_alloc *a, const unsigned char *data, size_t size, const char *name,
                                 pw_image *out, pw_err *e)
{
    memset(out, 0, sizeof *out);
    if (!name) name = "image";
    if (size >= 8 && memcmp(data, pw__png_sig, 8) == 0) return pw_png_read_memory(a, data, size, name, out, e);
    if (size >= 2 && data[0] == 'P' && data[1] >= '1' && data[1] <= '7')
        return pw_image_read_pnm_memory(a, data, size, name, out, e);
    if (size >= 24 && memcmp(data + 20, "GPAT", 4) == 0) return pw_image_read_pat_memory(a, data, size, name, out, e);
    return pw_fail(e, size ? PW_ERR_UNSUPPORTED : PW_ERR_PARSE, "%s: %s", name,
                   size ? "unknown image format (not PNG, PNM, PAM or GIMP pattern)" : "empty file");
}

#ifndef PW_NO_STDIO
/* Reads an image file of any supported format. */
PW__DEF int pw_image_load(const pw_alloc *a, const char *path, pw_image *out, pw_err *e)
{
    unsigned char *data;
    size_t size;
    int rc;
    memset(out, 0, sizeof *out);
    if ((rc = pw_read_file(a, path, &data, &size, e))) return rc;
    rc = pw_image_read_memory(a, data, size, path, out, e);
    pw_free(a, data);
    return rc;
}

typedef struct pw__save_job {
    const pw_image *img;
    int kind; /* 0 PNM by channels, 1 PAM, 2 PNG */
} pw__save_job;

PW__DEF int pw__save_body(void *arg, pw_write_fn w, void *ctx, pw_err *e)
{
    const pw__save_job *j = (const pw__save_job *)arg;
    if (j->kind == 2) return pw_png_write(NULL, j->img, 0, w, ctx, e);
    if (j->kind == 1) return pw_image_write_pam(j->img, 0, w, ctx, e);
    return pw_image_write_pnm(j->img, 0, 0, w, ctx, e);
}

/* Writes img at its own depth (img->bits) and channels in the format the
 * extension names (pw_image_format_of): .ppm .pgm .pnm (binary PGM or PPM
 * by the channels, or PAM when the image has alpha), .pam, .png. Keeps
 * every channel (tests and benchmarks store images with it); the public
 * X_save_image converts to what the format holds (pw_image_save_as). */
PW__DEF int pw_image_save(const char *path, const pw_image *img, pw_err *e)
{
    pw__save_job j;
    const char *format = pw_image_format_of(path);
    int rc = pw__image_check(img, e);
    if (rc) return rc;
    if (!format)
        return pw_fail(e, PW_ERR_UNSUPPORTED, "%s: unknown image file extension (use .png, .ppm, .pgm, .pnm or .pam)",
                       path);
    j.img = img;
    j.kind = !strcmp(format, "png") ? 2 : !strcmp(format, "pam") ? 1 : 0;
    return pw_write_file(path, pw__save_body, &j, e);
}
#endif /* PW_NO_STDIO */

#endif /* PW__PNG_V1 */
