/* libFuzzer target for the image readers: pw_image_read_memory (PNM P1-P7,
 * PAM, PNG, GIMP pattern) and the zlib/deflate code under them.
 *
 * Each input is used four ways:
 *   1. as a file, as given;
 *   2. if it starts with the PNG signature, with every chunk CRC recomputed,
 *      so that mutations reach the chunk contents instead of the CRC check;
 *   3. as a zlib stream for pw_zlib_decompress;
 *   4. as the recipe of a synthetic PNG: the first bytes pick the header,
 *      the rest become the filtered rows, compressed by our own deflate,
 *      so that the unfiltering, interlacing and palette code is reached
 *      despite the zlib checksums.
 * Images that decode are written back as PNG and PNM and read again; any
 * difference aborts, as does a compress/decompress round trip that fails.
 *
 * Build: clang -g -O1 -fsanitize=fuzzer,address,undefined -I. fuzz/fuzz_image.c -lm */
#define PW_MAX_IMAGE_PIXELS (1 << 22) /* keeps memory within the fuzzer's limits */
#include "../src/common/png.h"
#include <stdlib.h>

/* Writes img as PNG (png != 0) or PNM at its own depth; it must read back
 * to the same samples. */
static void roundtrip(const pw_image *img, int png)
{
    pw_buf b;
    pw_image back;
    pw_err e;
    size_t i, n = (size_t)img->w * img->h * img->c;
    unsigned maxval = img->bits == 16 ? 65535u : 255u;
    int rc;
    memset(&b, 0, sizeof b);
    pw_err_clear(&e);
    rc = png ? pw_png_write(NULL, img, 0, pw_buf_write, &b, &e)
             : pw_image_write_pnm(img, 0, 0, pw_buf_write, &b, &e);
    if (rc) abort();
    if (pw_image_read_memory(NULL, b.data, b.size, "roundtrip", &back, &e)) abort();
    if (back.w != img->w || back.h != img->h || back.c != img->c ||
        back.bits != (maxval > 255 ? 16 : 8))
        abort();
    for (i = 0; i < n; i++)
        if (pw_image_quantize(back.px[i], maxval) != pw_image_quantize(img->px[i], maxval)) abort();
    pw_image_free(NULL, &back);
    free(b.data);
}

static void read_and_check(const unsigned char *data, size_t size)
{
    pw_image img;
    pw_err e;
    pw_err_clear(&e);
    if (pw_image_read_memory(NULL, data, size, "fuzz", &img, &e) == PW_OK) {
        if (!img.px || img.w <= 0 || img.h <= 0 || img.c < 1 || img.c > 4) abort();
        if ((size_t)img.w * img.h <= 2048) {
            roundtrip(&img, 1);
            roundtrip(&img, 0);
        }
        pw_image_free(NULL, &img);
    } else if (img.px || !e.msg[0]) {
        abort(); /* a failure leaves no image and always explains itself */
    }
}

/* Recomputes the CRC of every complete chunk of a PNG-looking buffer. */
static void fix_crcs(unsigned char *d, size_t n)
{
    size_t pos = 8;
    while (n - pos >= 12) {
        uint32_t len = pw__be32(d + pos);
        if (len > n - pos - 12) break;
        pw__put_be32(d + pos + 8 + len, pw_crc32(0, d + pos + 4, (size_t)len + 4));
        pos += 12 + (size_t)len;
    }
}

/* zlib round trip of the input at a level it chooses. */
static void zlib_roundtrip(const unsigned char *data, size_t size)
{
    unsigned char *z, *back;
    size_t zn, bn;
    pw_err e;
    pw_err_clear(&e);
    if (pw_zlib_compress(NULL, data, size, size ? data[0] % 10 : 6, &z, &zn, &e)) abort();
    if (pw_zlib_decompress(NULL, z, zn, size, &back, &bn, &e)) abort();
    if (bn != size || (size && memcmp(back, data, size))) abort();
    free(z);
    free(back);
}

static void add_chunk(pw_buf *b, const char *type, const unsigned char *d, size_t n)
{
    unsigned char l[4];
    pw__put_be32(l, (uint32_t)n);
    pw_buf_write(b, l, 4);
    pw_buf_write(b, type, 4);
    if (n) pw_buf_write(b, d, n);
    pw__put_be32(l, pw_crc32(pw_crc32(0, type, 4), d, n));
    pw_buf_write(b, l, 4);
}

/* Makes the filter byte of every row (of every pass) a valid one, unless
 * the recipe asks to keep invalid ones. */
static void fix_filters(const pw__png *p, unsigned char *raw)
{
    static const unsigned char plain[4] = {0, 0, 1, 1};
    int k;
    for (k = 0; k < (p->interlace ? 7 : 1); k++) {
        const unsigned char *a7 = p->interlace ? pw__adam7[k] : plain;
        uint32_t pw = pw__pass_len(p->w, a7[0], a7[2]), ph = pw__pass_len(p->h, a7[1], a7[3]), j;
        if (!pw || !ph) continue;
        for (j = 0; j < ph; j++) {
            raw[0] %= 5;
            raw += 1 + (size_t)pw__png_rowbytes(p, pw);
        }
    }
}

/* A PNG built from the input: header from the first bytes, then PLTE/tRNS
 * and the rows from the rest (repeated to the size the header implies). */
static void synth_png(const unsigned char *d, size_t n)
{
    static const int ctypes[5] = {0, 2, 3, 4, 6};
    static const int depths[5][5] = {
        {1, 2, 4, 8, 16}, {8, 16, 8, 16, 8}, {1, 2, 4, 8, 8}, {8, 16, 8, 16, 8}, {8, 16, 8, 16, 8}};
    pw__png p;
    pw_buf b;
    unsigned char ihdr[13], pal[768], *raw, *z;
    const unsigned char *body = d + 8;
    size_t rawn, zn, i, bn, npal, ntrns;
    pw_err e;
    if (n < 8) return;
    bn = n - 8;
    memset(&p, 0, sizeof p);
    p.w = 1 + d[0] % 64;
    p.h = 1 + d[1] % 64;
    p.ctype = ctypes[d[2] % 5];
    p.depth = depths[d[2] % 5][d[3] % 5];
    p.interlace = d[4] & 1;
    p.spp = p.ctype == 0 || p.ctype == 3 ? 1 : p.ctype == 4 ? 2 : p.ctype == 2 ? 3 : 4;
    rawn = (size_t)pw__png_rawsize(&p) + (d[4] & 0x80 ? d[7] % 3 : 0); /* sometimes too long */
    raw = (unsigned char *)malloc(rawn);
    for (i = 0; i < rawn; i++) raw[i] = bn ? body[i % bn] : 0;
    for (i = 0; i < sizeof pal; i++) pal[i] = bn ? body[(i * 7) % bn] : (unsigned char)i;
    npal = 1 + (size_t)d[5] % 256;
    ntrns = (size_t)(d[6] >> 1) % (p.ctype == 3 ? npal + 2 : 8);
    if (!(d[4] & 0x40)) fix_filters(&p, raw);
    pw_err_clear(&e);
    if (pw_zlib_compress(NULL, raw, rawn, (d[4] >> 1) % 10, &z, &zn, &e)) abort();
    pw__put_be32(ihdr, p.w);
    pw__put_be32(ihdr + 4, p.h);
    ihdr[8] = (unsigned char)p.depth;
    ihdr[9] = (unsigned char)p.ctype;
    ihdr[10] = ihdr[11] = 0;
    ihdr[12] = (unsigned char)p.interlace;
    memset(&b, 0, sizeof b);
    pw_buf_write(&b, pw__png_sig, 8);
    add_chunk(&b, "IHDR", ihdr, 13);
    if (p.ctype == 3 || (d[5] & 1)) add_chunk(&b, "PLTE", pal, 3 * npal);
    if (d[6] & 1) add_chunk(&b, "tRNS", pal + 1, ntrns);
    for (i = 0; i < zn; i += 1 + d[7])
        add_chunk(&b, "IDAT", z + i, zn - i < 1u + d[7] ? zn - i : 1u + d[7]);
    add_chunk(&b, "IEND", NULL, 0);
    read_and_check(b.data, b.size);
    free(b.data);
    free(z);
    free(raw);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    unsigned char *out;
    size_t outn;
    pw_err e;
    read_and_check(data, size);
    if (size >= 8 && memcmp(data, pw__png_sig, 8) == 0) {
        unsigned char *copy = (unsigned char *)malloc(size);
        memcpy(copy, data, size);
        fix_crcs(copy, size);
        read_and_check(copy, size);
        free(copy);
    }
    pw_err_clear(&e);
    if (pw_zlib_decompress(NULL, data, size, 1 << 20, &out, &outn, &e) == PW_OK) free(out);
    if (size <= 4096) zlib_roundtrip(data, size);
    synth_png(data, size);
    return 0;
}
