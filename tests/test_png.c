/* Tests of src/common/deflate.h and src/common/png.h: checksums, deflate
 * round trips and hand-made/corrupt streams, PNG writing and reading of
 * every colour type, depth, filter and interlacing, malformed files, and
 * cross-checks with python3's zlib and netpbm when they are installed. */
#include "../src/common/png.h"
#include "../src/common/rng.h"
#include "pwtest.h"
#include <time.h>

/* ---- helpers ---- */

static int have(const char *tool)
{
    char cmd[256];
    snprintf(cmd, sizeof cmd, "command -v %s >/dev/null 2>&1", tool);
    return system(cmd) == 0;
}

static int write_bytes(const char *path, const void *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    int ok = f && fwrite(data, 1, n, f) == n;
    if (f && fclose(f) != 0) ok = 0;
    return ok;
}

static unsigned char *read_bytes(const char *path, size_t *n)
{
    unsigned char *d = NULL;
    pw_err e;
    pw_err_clear(&e);
    if (pw_read_file(NULL, path, &d, n, &e)) return NULL;
    return d;
}

static void make_image(pw_image *img, int w, int h, int c, uint64_t seed)
{
    pw_rng r = pw_rng_seed(seed, 3);
    size_t i;
    pw_image_alloc(NULL, img, w, h, c, NULL);
    for (i = 0; i < (size_t)w * h * c; i++) img->px[i] = pw_rng_float(&r);
}

/* A smooth image with some texture: what photos and exemplars look like. */
static void make_smooth(pw_image *img, int w, int h, int c)
{
    int x, y, k;
    pw_rng r = pw_rng_seed(11, 1);
    pw_image_alloc(NULL, img, w, h, c, NULL);
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++)
            for (k = 0; k < c; k++) {
                float v = (float)(x * (k + 1) + y * (3 - k % 3)) / (float)(3 * (w + h));
                v += 0.02f * (pw_rng_float(&r) - 0.5f) + 0.05f * (float)((x / 16 + y / 16) % 2);
                img->px[((size_t)y * w + x) * c + k] = v;
            }
}

static int same_quantized(const pw_image *a, const pw_image *b, unsigned maxval)
{
    size_t i;
    if (a->w != b->w || a->h != b->h || a->c != b->c) return 0;
    for (i = 0; i < (size_t)a->w * a->h * a->c; i++)
        if (pw_image_quantize(a->px[i], maxval) != pw_image_quantize(b->px[i], maxval)) return 0;
    return 1;
}

static double now(void) { return (double)clock() / CLOCKS_PER_SEC; }

/* Writes img as PNG (bits: 8, 16 or 0) into the fresh buffer b. */
static int png_to_buf(const pw_alloc *a, const pw_image *img, int bits, pw_buf *b, pw_err *e)
{
    memset(b, 0, sizeof *b);
    pw_err_clear(e);
    return pw_png_write(a, img, bits, pw_buf_write, b, e);
}

/* ---- checksums ---- */

static void t_checksums(void)
{
    CHECK(pw_crc32(0, "123456789", 9) == 0xcbf43926u);
    CHECK(pw_crc32(pw_crc32(0, "1234", 4), "56789", 5) == 0xcbf43926u);
    CHECK(pw_crc32(0, "", 0) == 0);
    CHECK(pw_adler32(1, "Wikipedia", 9) == 0x11e60398u);
    CHECK(pw_adler32(pw_adler32(1, "Wiki", 4), "pedia", 5) == 0x11e60398u);
    CHECK(pw_crc32(0, "IEND", 4) == 0xae426082u);
}

/* ---- deflate round trips ---- */

/* Compresses and decompresses at `level`, checking the result. */
static size_t roundtrip(const unsigned char *d, size_t n, int level, const char *what)
{
    unsigned char *z = NULL, *back = NULL;
    size_t zn = 0, bn = 0;
    pw_err e;
    pw_err_clear(&e);
    if (pw_zlib_compress(NULL, d, n, level, &z, &zn, &e)) {
        CHECKF(0, "%s level %d: compress: %s", what, level, e.msg);
        return 0;
    }
    if (pw_zlib_decompress(NULL, z, zn, n, &back, &bn, &e)) {
        CHECKF(0, "%s level %d: decompress: %s", what, level, e.msg);
    } else {
        CHECKF(bn == n && (n == 0 || memcmp(back, d, n) == 0), "%s level %d: data differ", what,
               level);
    }
    free(z);
    free(back);
    return zn;
}

static void t_deflate_roundtrip(void)
{
    static const size_t sizes[] = {0, 1, 2, 3, 4, 100, 258, 259, 65535, 65536, 65537, 200000};
    static const int levels[] = {0, 1, 4, 6, 9};
    size_t si, i, big = 200000;
    unsigned char *d = (unsigned char *)malloc(big);
    pw_rng r = pw_rng_seed(1, 1);
    int li, kind;
    REQUIRE(d);
    for (kind = 0; kind < 4; kind++) {
        for (i = 0; i < big; i++)
            d[i] = kind == 0   ? (unsigned char)pw_rng_u32(&r) /* random */
                   : kind == 1 ? 0                             /* constant */
                   : kind == 2
                       ? (unsigned char)"abcdefgh"[i % 7]                        /* periodic */
                       : (unsigned char)(pw_rng_below(&r, 4) + (i / 1000) % 50); /* skewed */
        for (si = 0; si < sizeof sizes / sizeof sizes[0]; si++)
            for (li = 0; li < 5; li++) {
                char what[64];
                size_t zn;
                snprintf(what, sizeof what, "kind %d, %lu bytes", kind, (unsigned long)sizes[si]);
                zn = roundtrip(d, sizes[si], levels[li], what);
                if (kind == 0 && sizes[si] > 1000) /* random: stored blocks, little overhead */
                    CHECKF(zn < sizes[si] + sizes[si] / 1000 + 16, "%s: %lu bytes", what,
                           (unsigned long)zn);
                if (kind == 1 && levels[li] > 0 && sizes[si] >= 65536)
                    CHECKF(zn < sizes[si] / 200, "%s: %lu bytes", what, (unsigned long)zn);
            }
    }
    free(d);
}

/* Empty input gives a valid stream that decodes to nothing. */
static void t_deflate_empty(void)
{
    unsigned char *z, *back;
    size_t zn, bn;
    pw_err e;
    pw_err_clear(&e);
    REQUIRE(pw_zlib_compress(NULL, NULL, 0, 6, &z, &zn, &e) == PW_OK);
    CHECK(zn == 8 && z[0] == 0x78 && z[1] == 0x9c);
    REQUIRE(pw_zlib_decompress(NULL, z, zn, 0, &back, &bn, &e) == PW_OK);
    CHECK(bn == 0 && back != NULL);
    free(z);
    free(back);
}

static void t_deflate_large(void)
{
    size_t n = 16u << 20, i, zn;
    unsigned char *d = (unsigned char *)malloc(n);
    pw_rng r = pw_rng_seed(5, 5);
    double t0;
    REQUIRE(d);
    /* text-like: words from a small vocabulary */
    for (i = 0; i < n;) {
        static const char *const words[] = {"texture ", "patch ", "mesh ", "lapped ",
                                            "tile ",    "seam ",  "\n"};
        const char *w = words[pw_rng_below(&r, 7)];
        size_t k = strlen(w);
        if (i + k > n) k = n - i;
        memcpy(d + i, w, k);
        i += k;
    }
    t0 = now();
    zn = roundtrip(d, n, 6, "16 MiB text");
    pwt_info("16 MiB of words: %lu bytes (%.1f%%), round trip %.2f s", (unsigned long)zn,
             100.0 * zn / n, now() - t0);
    CHECK(zn < n / 3);
    free(d);
}

/* ---- hand-made and corrupt streams ---- */

static int inflate_str(const char *s, size_t n, size_t max_out, unsigned char **out, size_t *outn,
                       pw_err *e)
{
    pw_err_clear(e);
    return pw_inflate(NULL, (const unsigned char *)s, n, max_out, out, outn, NULL, e);
}

static void t_inflate_handmade(void)
{
    /* stored, then fixed (python zlib, Z_FIXED), then a dynamic block */
    static const char stored[] = "\x00\x05\x00\xfa\xff"
                                 "hello"
                                 "\x01\x01\x00\xfe\xff"
                                 "!";
    static const char fixed[] = "\x4b\x4c\x4a\x4e\x44\x42\x00";
    static const char dyn[] =
        "\x5d\x92\x31\x0e\x43\x31\x08\x43\xaf\xc2\x11\x02\x24\x24\x51\x4e\x53\xa9\x1d\x3a\xb6\x55"
        "\xef\x5f\xfc\x27\xdc\x31\x08\xd9\xcf\x26\x4d\x3e\xaf\xef\xed\xfd\xb8\xcb\xf3\x23\xed\x88"
        "\xd6\xb7\x1e\xb1\xfa\xee\x47\xbc\xbe\xf7\x91\x4e\xfb\x71\x64\xd4\x81\x8d\x23\x51\x07\x9e"
        "\x1b\x93\x24\x53\x63\xd5\x41\xa4\xc9\xae\x83\x95\x14\xda\xc8\xa6\x01\x94\x49\x0d\x5b\x04"
        "\xab\x3d\x95\xd4\x99\x2f\xdd\x94\x91\x77\x12\x29\x43\x83\x5a\x83\x73\x60\x8b\xc0\x6d\x41"
        "\x8b\xd0\xdd\xe0\xb8\x39\x2f\x3a\x24\xfa\x0e\x7a\x23\xfa\xde\xb1\xc5\x55\xaf\xd4\x32\xa2"
        "\x1f\x96\x8e\x46\xf4\x63\x26\x97\x11\x7d\x80\xde\x88\x3e\xae\x2d\xa2\x9f\x97\x16\xd1\xcf"
        "\xcb\x91\xab\x07\x97\x13\xfd\x06\xbd\x13\xfd\x46\x46\xe7\xee\x1b\xaa\x70\x2e\xbf\xa1\x31"
        "\xe7\xf6\x15\xc5\xfa\xe0\x53\x22\x81\x07\xcf\x70\x26\xa7\x08\xea\xb8\xa6\xaf\xbf\x9b\xc3"
        "\x97\x42\xe8\xc0\xdf\xf8\x01";
    static const char zlib_a[] = "\x78\x9c\x4b\x04\x00\x00\x62\x00\x62";
    char text[1024];
    unsigned char *out;
    size_t outn, used, tn = 0;
    pw_err e;
    int i;
    REQUIRE(inflate_str(stored, sizeof stored - 1, 100, &out, &outn, &e) == PW_OK);
    CHECK(outn == 6 && memcmp(out, "hello!", 6) == 0);
    free(out);
    REQUIRE(inflate_str(fixed, sizeof fixed - 1, 100, &out, &outn, &e) == PW_OK);
    CHECK(outn == 15 && memcmp(out, "abcabcabcabcabc", 15) == 0);
    free(out);
    for (i = 0; i < 40; i++) tn += (size_t)sprintf(text + tn, "%d squared is %d; ", i, i * i);
    pw_err_clear(&e);
    REQUIRE(pw_inflate(NULL, (const unsigned char *)dyn, sizeof dyn - 1, 10000, &out, &outn, &used,
                       &e) == PW_OK);
    CHECK(outn == tn && memcmp(out, text, tn) == 0 && used == sizeof dyn - 1);
    free(out);
    pw_err_clear(&e);
    REQUIRE(pw_zlib_decompress(NULL, (const unsigned char *)zlib_a, 9, 10, &out, &outn, &e) ==
            PW_OK);
    CHECK(outn == 1 && out[0] == 'a');
    free(out);
}

/* Bits LSB first, for building streams by hand. */
typedef struct bits {
    unsigned char b[64];
    int n;
} bits;
static void put(bits *s, unsigned v, int n)
{
    int i;
    for (i = 0; i < n; i++, s->n++)
        if ((v >> i) & 1) s->b[s->n / 8] |= (unsigned char)(1 << (s->n % 8));
}
/* Huffman codes go most significant bit first. */
static void put_code(bits *s, unsigned code, int n)
{
    while (n--) put(s, (code >> n) & 1, 1);
}

static void expect_inflate_fail(const bits *s, int code, const char *what, int line)
{
    unsigned char *out = NULL;
    size_t outn;
    pw_err e;
    int rc = inflate_str((const char *)s->b, (size_t)(s->n + 7) / 8, 1000, &out, &outn, &e);
    if (rc != code || !strstr(e.msg, what))
        pwt_fail_(__FILE__, line, "got %d '%s', expected %d '%s'", rc, e.msg, code, what);
    CHECK(out == NULL);
}
#define EXPECT_INFLATE_FAIL(s, code, what) expect_inflate_fail(s, code, what, __LINE__)

/* Starts a fresh stream with a final block of `type` (0 stored, 1 fixed,
 * 2 dynamic, 3 invalid). */
static void final_block(bits *s, unsigned type)
{
    memset(s, 0, sizeof *s);
    put(s, 1u | type << 1, 3);
}

/* A stored block header with the given LEN and NLEN fields. */
static void stored_header(bits *s, unsigned len, unsigned nlen)
{
    final_block(s, 0);
    put(s, 0, 5); /* to the byte boundary */
    put(s, len, 16);
    put(s, nlen, 16);
}

/* A fixed block: literal 'a', then a match of length 3 (code 257) with
 * distance code dcode. */
static void fixed_a_match(bits *s, unsigned dcode)
{
    final_block(s, 1);
    put_code(s, 0x30 + 'a', 8);
    put_code(s, 1, 7);
    put_code(s, dcode, 5);
}

/* A dynamic block header: HLIT, HDIST and HCLEN as stored (less 257, 1, 4). */
static void dyn_header(bits *s, unsigned hlit, unsigned hdist, unsigned hclen)
{
    final_block(s, 2);
    put(s, hlit, 5);
    put(s, hdist, 5);
    put(s, hclen, 4);
}

/* A dynamic block with 257 literal/length and 1 distance code whose
 * code-length codes 16, 17, 18 and 0 all have length 2 (complete); in
 * canonical order 0 -> 00, 16 -> 01, 17 -> 10, 18 -> 11. */
static void dyn_header_clen2(bits *s)
{
    int i;
    dyn_header(s, 0, 0, 0);
    for (i = 0; i < 4; i++) put(s, 2, 3);
}

/* A dynamic block: literal/length lengths 'a' 1, end-of-block 2, length
 * code 257 2; one distance code (0) of length 1. Data: 'a', then a match of
 * 3 with distance code bit `dbit`, then end-of-block. */
static void dyn_single_dist(bits *s, int dbit)
{
    /* code-length code: 18 -> 0, 1 -> 10, 2 -> 11 (canonical) */
    static const int clen_in_order[18] = {0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 0, 2};
    int i;
    dyn_header(s, 1, 0, 14); /* HLIT 258, HDIST 1, HCLEN 18 */
    for (i = 0; i < 18; i++) put(s, (unsigned)clen_in_order[i], 3);
    put_code(s, 0, 1);
    put(s, 97 - 11, 7); /* 97 zeros */
    put_code(s, 2, 2);  /* 'a': 1 */
    put_code(s, 0, 1);
    put(s, 138 - 11, 7);
    put_code(s, 0, 1);
    put(s, 20 - 11, 7); /* 158 zeros in all */
    put_code(s, 3, 2);  /* 256: 2 */
    put_code(s, 3, 2);  /* 257: 2 */
    put_code(s, 2, 2);  /* distance 0: 1 */
    put_code(s, 0, 1);  /* 'a' */
    put_code(s, 3, 2);  /* length 3 */
    put_code(s, (unsigned)dbit, 1);
    put_code(s, 2, 2); /* end of block */
}

static void t_inflate_corrupt(void)
{
    bits s;
    int i;
    final_block(&s, 3);
    EXPECT_INFLATE_FAIL(&s, PW_ERR_PARSE, "invalid block type 3");
    stored_header(&s, 5, 5);
    EXPECT_INFLATE_FAIL(&s, PW_ERR_PARSE, "stored block length check failed");
    stored_header(&s, 5, 0xfffa);
    put(&s, 'a', 8);
    EXPECT_INFLATE_FAIL(&s, PW_ERR_PARSE, "truncated");
    /* fixed block: a match before any output */
    final_block(&s, 1);
    put_code(&s, 1, 7); /* length code 257: 3 */
    put_code(&s, 0, 5); /* distance code 0: 1 */
    EXPECT_INFLATE_FAIL(&s, PW_ERR_PARSE, "distance 1 too far back");
    /* fixed block: literal 'a' then distance 2 */
    fixed_a_match(&s, 1);
    EXPECT_INFLATE_FAIL(&s, PW_ERR_PARSE, "distance 2 too far back");
    /* fixed block: length code 286 is invalid */
    final_block(&s, 1);
    put_code(&s, 0xc6, 8);
    EXPECT_INFLATE_FAIL(&s, PW_ERR_PARSE, "invalid length code 286");
    /* fixed block: distance code 30 is invalid */
    fixed_a_match(&s, 30);
    EXPECT_INFLATE_FAIL(&s, PW_ERR_PARSE, "invalid distance code 30");
    /* fixed block without end-of-block */
    final_block(&s, 1);
    put_code(&s, 0x30 + 'a', 8);
    EXPECT_INFLATE_FAIL(&s, PW_ERR_PARSE, "truncated");
    /* dynamic: all 19 code-length codes of length 1: over-subscribed */
    dyn_header(&s, 0, 0, 15);
    for (i = 0; i < 19; i++) put(&s, 1, 3);
    EXPECT_INFLATE_FAIL(&s, PW_ERR_PARSE, "bad code-length code");
    /* dynamic: HLIT 287 */
    dyn_header(&s, 30, 0, 0);
    EXPECT_INFLATE_FAIL(&s, PW_ERR_PARSE, "too many length or distance codes");
    /* dynamic: the first symbol is a repeat (16) with nothing to repeat */
    dyn_header_clen2(&s);
    put_code(&s, 1, 2);
    put(&s, 0, 2);
    EXPECT_INFLATE_FAIL(&s, PW_ERR_PARSE, "repeat with no previous length");
    /* dynamic: 258 zero lengths via 18 (code 11) x2: no end-of-block code */
    dyn_header_clen2(&s);
    put_code(&s, 3, 2);
    put(&s, 127, 7); /* 138 zeros */
    put_code(&s, 3, 2);
    put(&s, 109, 7); /* 120 zeros: 258 = 257 + 1 */
    EXPECT_INFLATE_FAIL(&s, PW_ERR_PARSE, "no end-of-block code");
    /* dynamic: repeat past the end */
    dyn_header_clen2(&s);
    put_code(&s, 3, 2);
    put(&s, 127, 7);
    put_code(&s, 3, 2);
    put(&s, 127, 7);
    EXPECT_INFLATE_FAIL(&s, PW_ERR_PARSE, "repeat past the end");
    /* dynamic with a single distance code: using it works, using the
     * other 1-bit pattern is an invalid code */
    dyn_single_dist(&s, 0);
    {
        unsigned char *out;
        size_t outn;
        pw_err e;
        CHECK(inflate_str((const char *)s.b, (size_t)(s.n + 7) / 8, 100, &out, &outn, &e) == PW_OK);
        CHECK(outn == 4 && memcmp(out, "aaaa", 4) == 0);
        free(out);
    }
    dyn_single_dist(&s, 1);
    EXPECT_INFLATE_FAIL(&s, PW_ERR_PARSE, "invalid Huffman code");
}

/* Every prefix of valid streams fails cleanly; so do single-bit flips
 * (which may also decode to something else, but never crash). */
static void t_inflate_truncated_and_flipped(void)
{
    unsigned char d[3000], *z, *out;
    size_t zn, outn, k;
    pw_rng r = pw_rng_seed(2, 2);
    pw_err e;
    int level;
    for (k = 0; k < sizeof d; k++)
        d[k] = (unsigned char)("lapped textures "[k % 16] + (k % 97 == 0));
    for (level = 0; level <= 9; level += 3) {
        pw_err_clear(&e);
        REQUIRE(pw_zlib_compress(NULL, d, sizeof d, level, &z, &zn, &e) == PW_OK);
        for (k = 0; k < zn; k++) {
            pw_err_clear(&e);
            if (pw_zlib_decompress(NULL, z, k, sizeof d, &out, &outn, &e) != PW_ERR_PARSE) {
                CHECKF(0, "level %d: prefix of %lu bytes accepted or wrong code: %s", level,
                       (unsigned long)k, e.msg);
                break;
            }
        }
        for (k = 0; k < 2000; k++) {
            size_t bit = pw_rng_below(&r, (uint32_t)(zn * 8));
            int rc;
            z[bit / 8] ^= (unsigned char)(1 << (bit % 8));
            pw_err_clear(&e);
            rc = pw_zlib_decompress(NULL, z, zn, sizeof d, &out, &outn, &e);
            if (rc == PW_OK) {
                CHECK(outn == sizeof d && memcmp(out, d, outn) == 0); /* only if harmless */
                free(out);
            } else {
                CHECK(out == NULL && e.msg[0]);
            }
            z[bit / 8] ^= (unsigned char)(1 << (bit % 8));
        }
        free(z);
    }
}

static void t_zlib_errors(void)
{
    unsigned char zeros[100000], *z, *out;
    size_t zn, outn;
    pwt_alloc_state counts = {0, 0, -1};
    pw_alloc counting = {pwt_malloc, pwt_realloc, pwt_free, &counts};
    pw_err e;
    memset(zeros, 0, sizeof zeros);
    pw_err_clear(&e);
    REQUIRE(pw_zlib_compress(NULL, zeros, sizeof zeros, 6, &z, &zn, &e) == PW_OK);
    /* output cap: a zip bomb is cut off */
    CHECK(pw_zlib_decompress(NULL, z, zn, 99999, &out, &outn, &e) == PW_ERR_LIMIT &&
          strstr(e.msg, "99999"));
    CHECK(out == NULL);
    pw_err_clear(&e);
    CHECK(pw_zlib_decompress(&counting, z, zn, sizeof zeros, &out, &outn, &e) == PW_OK);
    pwt_free(&counts, out);
    z[zn - 1] ^= 1;
    pw_err_clear(&e);
    CHECK(pw_zlib_decompress(NULL, z, zn, sizeof zeros, &out, &outn, &e) == PW_ERR_PARSE &&
          strstr(e.msg, "Adler-32"));
    pw_err_clear(&e);
    CHECK(pw_zlib_decompress(NULL, z, zn - 2, sizeof zeros, &out, &outn, &e) == PW_ERR_PARSE &&
          strstr(e.msg, "no Adler-32"));
    z[0] = 0x79;
    pw_err_clear(&e);
    CHECK(pw_zlib_decompress(NULL, z, zn, sizeof zeros, &out, &outn, &e) == PW_ERR_PARSE &&
          strstr(e.msg, "zlib header"));
    z[0] = 0x88;
    pw_err_clear(&e);
    CHECK(pw_zlib_decompress(NULL, z, zn, sizeof zeros, &out, &outn, &e) == PW_ERR_PARSE &&
          strstr(e.msg, "window"));
    z[0] = 0x78;
    z[1] = 0xbb; /* preset dictionary, check bits valid */
    pw_err_clear(&e);
    CHECK(pw_zlib_decompress(NULL, z, zn, sizeof zeros, &out, &outn, &e) == PW_ERR_UNSUPPORTED &&
          strstr(e.msg, "dictionary"));
    pw_err_clear(&e);
    CHECK(pw_zlib_decompress(NULL, z, 1, sizeof zeros, &out, &outn, &e) == PW_ERR_PARSE &&
          strstr(e.msg, "truncated"));
    free(z);
}

/* python3's zlib decodes our streams and we decode its streams. */
static void t_python_zlib(void)
{
    const char *ours = pwt_tmp("png", 0, ".z"), *raw = pwt_tmp("png", 1, ".bin"), *theirs = pwt_tmp("png", 2, ".z");
    char cmd[1024];
    size_t n = 300000, i, zn, tn, on;
    unsigned char *d = (unsigned char *)malloc(n), *z, *t, *out;
    pw_image img;
    pw_err e;
    int level;
    if (!have("python3") || system("python3 -c 'import zlib' >/dev/null 2>&1") != 0) {
        pwt_skip("python3 with zlib not available");
        free(d);
        return;
    }
    REQUIRE(d);
    make_smooth(&img, 250, 400, 3);
    for (i = 0; i < n; i++) d[i] = (unsigned char)pw_image_quantize(img.px[i], 255);
    pw_image_free(NULL, &img);
    REQUIRE(write_bytes(raw, d, n));
    for (level = 0; level <= 9; level++) {
        pw_err_clear(&e);
        REQUIRE(pw_zlib_compress(NULL, d, n, level, &z, &zn, &e) == PW_OK);
        REQUIRE(write_bytes(ours, z, zn));
        snprintf(
            cmd, sizeof cmd,
            "python3 -c \"import zlib,sys; a=open('%s','rb').read(); b=open('%s','rb').read(); "
            "sys.exit(0 if zlib.decompress(a)==b else 1)\"",
            ours, raw);
        CHECKF(system(cmd) == 0, "python cannot decode our level %d stream", level);
        snprintf(cmd, sizeof cmd,
                 "python3 -c \"import zlib; "
                 "open('%s','wb').write(zlib.compress(open('%s','rb').read(), %d))\"",
                 theirs, raw, level);
        REQUIRE(system(cmd) == 0);
        t = read_bytes(theirs, &tn);
        REQUIRE(t);
        pw_err_clear(&e);
        CHECKF(pw_zlib_decompress(NULL, t, tn, n, &out, &on, &e) == PW_OK && on == n &&
                   memcmp(out, d, n) == 0,
               "cannot decode python level %d: %s", level, e.msg);
        if (level == 1 || level == 6 || level == 9)
            pwt_info("level %d, smooth 250x400 RGB (%lu bytes): ours %lu, python zlib %lu", level,
                     (unsigned long)n, (unsigned long)zn, (unsigned long)tn);
        free(out);
        free(t);
        free(z);
    }
    remove(ours);
    remove(raw);
    remove(theirs);
    free(d);
}

/* ---- PNG round trips ---- */

static void t_png_roundtrip(void)
{
    static const int sizes[][2] = {{1, 1}, {1, 7}, {7, 1}, {13, 11}, {64, 3}};
    int c, bits, si;
    for (c = 1; c <= 4; c++)
        for (bits = 8; bits <= 16; bits += 8)
            for (si = 0; si < 5; si++) {
                pw_image a, b;
                pw_buf buf;
                pw_err e;
                make_image(&a, sizes[si][0], sizes[si][1], c, (uint64_t)(c * 7 + bits + si));
                REQUIRE(png_to_buf(NULL, &a, bits, &buf, &e) == PW_OK);
                pw_err_clear(&e);
                CHECKF(pw_image_read_memory(NULL, buf.data, buf.size, "rt.png", &b, &e) == PW_OK,
                       "%s", e.msg);
                if (b.px) {
                    CHECKF(same_quantized(&a, &b, bits == 16 ? 65535u : 255u),
                           "c=%d bits=%d size %d", c, bits, si);
                    CHECK(b.bits == bits);
                }
                CHECK(buf.data[24] == bits && buf.data[25] == "\0\4\2\6"[c - 1]);
                free(buf.data);
                pw_image_free(NULL, &a);
                pw_image_free(NULL, &b);
            }
}

/* The writer's output is deterministic, its buffers come from the caller's
 * allocator (a failure there is reported and leaks nothing), and its chunk
 * CRCs are right. */
static void t_png_write_structure(void)
{
    pw_image a;
    pw_buf b1, b2;
    pw_err e;
    pwt_alloc_state counts = {0, 0, -1};
    pw_alloc al = {pwt_malloc, pwt_realloc, pwt_free, &counts};
    size_t pos = 8;
    int nchunks = 0;
    long budget;
    make_smooth(&a, 300, 200, 3);
    REQUIRE(png_to_buf(NULL, &a, 8, &b1, &e) == PW_OK);
    REQUIRE(png_to_buf(&al, &a, 8, &b2, &e) == PW_OK);
    CHECK(b1.size == b2.size && memcmp(b1.data, b2.data, b1.size) == 0);
    CHECKF(counts.calls > 0 && counts.live == 0, "%ld calls, %ld live", counts.calls, counts.live);
    for (budget = 0; budget < counts.calls; budget++) {
        pwt_alloc_state f = {0, 0, budget};
        pw_alloc fa = {pwt_malloc, pwt_realloc, pwt_free, &f};
        pw_buf b3;
        CHECKF(png_to_buf(&fa, &a, 8, &b3, &e) == PW_ERR_NOMEM, "budget %ld", budget);
        CHECKF(f.live == 0, "budget %ld: %ld blocks leaked", budget, f.live);
        free(b3.data);
    }
    CHECK(memcmp(b1.data, "\x89PNG\r\n\x1a\n", 8) == 0);
    while (pos + 12 <= b1.size) {
        uint32_t len = pw__be32(b1.data + pos);
        CHECK(pw_crc32(0, b1.data + pos + 4, len + 4) == pw__be32(b1.data + pos + 8 + len));
        nchunks++;
        pos += 12 + len;
    }
    CHECK(pos == b1.size && nchunks >= 3);
    CHECK(memcmp(b1.data + b1.size - 8, "IEND", 4) == 0);
    pw_err_clear(&e);
    CHECK(pw_png_write(NULL, &a, 4, pw_buf_write, &b1, &e) == PW_ERR_INVALID);
    free(b1.data);
    free(b2.data);
    pw_image_free(NULL, &a);
}

/* ---- a test-side PNG encoder for every colour type, depth and filter ---- */

typedef struct spec {
    int w, h, ctype, depth, interlace;
    int npal, ntrns;
    unsigned char pal[256 * 3], trns[256];
    int has_key;
    unsigned key[3];
    unsigned *s; /* samples, spp per pixel, row-major */
} spec;

static int spp_of(int ctype)
{
    return ctype == 0 || ctype == 3 ? 1 : ctype == 4 ? 2 : ctype == 2 ? 3 : 4;
}

static void add_chunk(pw_buf *b, const char *type, const unsigned char *d, size_t n)
{
    unsigned char l[4];
    uint32_t crc = pw_crc32(pw_crc32(0, type, 4), d, n);
    pw__put_be32(l, (uint32_t)n);
    pw_buf_write(b, l, 4);
    pw_buf_write(b, type, 4);
    if (n) pw_buf_write(b, d, n);
    pw__put_be32(l, crc);
    pw_buf_write(b, l, 4);
}

static void add_ihdr(pw_buf *b, uint32_t w, uint32_t h, int depth, int ctype, int interlace)
{
    unsigned char d[13];
    pw__put_be32(d, w);
    pw__put_be32(d + 4, h);
    d[8] = (unsigned char)depth;
    d[9] = (unsigned char)ctype;
    d[10] = d[11] = 0;
    d[12] = (unsigned char)interlace;
    pw_buf_write(b, "\x89PNG\r\n\x1a\n", 8);
    add_chunk(b, "IHDR", d, 13);
}

static void add_idat(pw_buf *b, const unsigned char *raw, size_t n, size_t chunk)
{
    unsigned char *z;
    size_t zn, off;
    pw_err e;
    pw_err_clear(&e);
    pw_zlib_compress(NULL, raw, n, 6, &z, &zn, &e);
    for (off = 0; off < zn; off += chunk)
        add_chunk(b, "IDAT", z + off, zn - off < chunk ? zn - off : chunk);
    free(z);
}

/* Packs one row of samples at `depth` bits, most significant first. */
static size_t pack_row(const spec *sp, int y, int x0, int dx, int count, unsigned char *out)
{
    int spp = spp_of(sp->ctype), i, k;
    size_t bit = 0;
    for (i = 0; i < count; i++)
        for (k = 0; k < spp; k++) {
            unsigned v = sp->s[((size_t)y * sp->w + x0 + (size_t)i * dx) * spp + k];
            if (sp->depth == 16) {
                out[bit / 8] = (unsigned char)(v >> 8);
                out[bit / 8 + 1] = (unsigned char)v;
            } else if (sp->depth == 8) {
                out[bit / 8] = (unsigned char)v;
            } else {
                if (bit % 8 == 0) out[bit / 8] = 0;
                out[bit / 8] |= (unsigned char)(v << (8 - sp->depth - bit % 8));
            }
            bit += (size_t)sp->depth;
        }
    return (bit + 7) / 8;
}

/* Forward filter f (test-side implementation of PNG §9.2). */
static void filter_row(unsigned char *dst, const unsigned char *cur, const unsigned char *prev,
                       size_t n, size_t bpp, int f)
{
    size_t i;
    for (i = 0; i < n; i++) {
        int a = i >= bpp ? cur[i - bpp] : 0, b = prev[i], c = i >= bpp ? prev[i - bpp] : 0, pr = 0;
        if (f == 1) pr = a;
        if (f == 2) pr = b;
        if (f == 3) pr = (a + b) / 2;
        if (f == 4) {
            int p = a + b - c, pa = p > a ? p - a : a - p, pb = p > b ? p - b : b - p,
                pc = p > c ? p - c : c - p;
            pr = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
        }
        dst[i] = (unsigned char)(cur[i] - pr);
    }
}

/* Encodes sp as PNG, cycling the filter types over rows. */
static void encode_spec(const spec *sp, pw_buf *b, size_t idat_chunk)
{
    static const int a7[7][4] = {{0, 0, 8, 8}, {4, 0, 8, 8}, {0, 4, 4, 8}, {2, 0, 4, 4},
                                 {0, 2, 2, 4}, {1, 0, 2, 2}, {0, 1, 1, 2}};
    static const int one[4] = {0, 0, 1, 1};
    size_t cap = (size_t)sp->w * sp->h * 8 + (size_t)sp->h * 16 + 64, rn = 0, bpp;
    unsigned char *raw = (unsigned char *)malloc(cap), cur[4096], prev[4096];
    int p, j, np = sp->interlace ? 7 : 1, f = 0;
    bpp = (size_t)(spp_of(sp->ctype) * sp->depth + 7) / 8;
    for (p = 0; p < np; p++) {
        const int *q = sp->interlace ? a7[p] : one;
        int pw = sp->w > q[0] ? (sp->w - q[0] + q[2] - 1) / q[2] : 0;
        int ph = sp->h > q[1] ? (sp->h - q[1] + q[3] - 1) / q[3] : 0;
        if (!pw || !ph) continue;
        memset(prev, 0, sizeof prev);
        for (j = 0; j < ph; j++) {
            size_t n = pack_row(sp, q[1] + j * q[3], q[0], q[2], pw, cur);
            raw[rn++] = (unsigned char)(f % 5);
            filter_row(raw + rn, cur, prev, n, bpp, f++ % 5);
            rn += n;
            memcpy(prev, cur, n);
        }
    }
    add_ihdr(b, (uint32_t)sp->w, (uint32_t)sp->h, sp->depth, sp->ctype, sp->interlace);
    if (sp->npal) add_chunk(b, "PLTE", sp->pal, (size_t)sp->npal * 3);
    if (sp->ntrns) add_chunk(b, "tRNS", sp->trns, (size_t)sp->ntrns);
    if (sp->has_key) {
        unsigned char k[6];
        int i, n = sp->ctype == 0 ? 1 : 3;
        for (i = 0; i < n; i++) {
            k[2 * i] = (unsigned char)(sp->key[i] >> 8);
            k[2 * i + 1] = (unsigned char)sp->key[i];
        }
        add_chunk(b, "tRNS", k, (size_t)n * 2);
    }
    add_chunk(b, "teXt", (const unsigned char *)"Comment\0ancillary", 17);
    add_idat(b, raw, rn, idat_chunk);
    add_chunk(b, "IEND", NULL, 0);
    free(raw);
}

/* What the reader must return for sp: floats per output channel. */
static int expected_channels(const spec *sp)
{
    if (sp->ctype == 3) return sp->ntrns ? 4 : 3;
    return spp_of(sp->ctype) + sp->has_key;
}

static float expected_value(const spec *sp, size_t pixel, int k)
{
    int spp = spp_of(sp->ctype);
    const unsigned *s = sp->s + pixel * spp;
    float maxv = (float)((1u << sp->depth) - 1);
    if (sp->ctype == 3) {
        if (k == 3) return (int)s[0] < sp->ntrns ? sp->trns[s[0]] / 255.0f : 1.0f;
        return sp->pal[s[0] * 3 + k] / 255.0f;
    }
    if (k < spp) return (float)s[k] / maxv;
    return (s[0] == sp->key[0] && (spp == 1 || (s[1] == sp->key[1] && s[2] == sp->key[2]))) ? 0.0f
                                                                                            : 1.0f;
}

/* Fills sp with random samples (and palette / key). */
static void random_spec(spec *sp, int w, int h, int ctype, int depth, int interlace, int trns,
                        pw_rng *r)
{
    size_t i, n;
    int spp = spp_of(ctype), maxv = (1 << depth) - 1;
    memset(sp, 0, sizeof *sp);
    sp->w = w;
    sp->h = h;
    sp->ctype = ctype;
    sp->depth = depth;
    sp->interlace = interlace;
    n = (size_t)w * h * spp;
    sp->s = (unsigned *)malloc(n * sizeof *sp->s);
    if (ctype == 3) {
        sp->npal = 1 + (int)pw_rng_below(r, (uint32_t)maxv + 1);
        for (i = 0; i < (size_t)sp->npal * 3; i++) sp->pal[i] = (unsigned char)pw_rng_u32(r);
        if (trns) {
            sp->ntrns = (int)pw_rng_below(r, (uint32_t)sp->npal + 1);
            if (!sp->ntrns) sp->ntrns = 1;
            for (i = 0; i < (size_t)sp->ntrns; i++) sp->trns[i] = (unsigned char)pw_rng_u32(r);
        }
    }
    for (i = 0; i < n; i++)
        sp->s[i] =
            ctype == 3 ? pw_rng_below(r, (uint32_t)sp->npal) : pw_rng_below(r, (uint32_t)maxv + 1);
    if (trns && (ctype == 0 || ctype == 2)) {
        sp->has_key = 1;
        for (i = 0; i < (size_t)spp; i++)
            sp->key[i] = sp->s[i]; /* the first pixel is transparent */
    }
}

static int check_decoded(const spec *sp, const pw_image *img)
{
    size_t i;
    int k, c = expected_channels(sp);
    if (img->w != sp->w || img->h != sp->h || img->c != c ||
        img->bits != (sp->depth == 16 ? 16 : 8))
        return 0;
    for (i = 0; i < (size_t)sp->w * sp->h; i++)
        for (k = 0; k < c; k++)
            if (img->px[i * c + k] != expected_value(sp, i, k)) return 0;
    return 1;
}

static const int type_depths[][2] = {{0, 1}, {0, 2},  {0, 4},  {0, 8}, {0, 16},
                                     {2, 8}, {2, 16}, {3, 1},  {3, 2}, {3, 4},
                                     {3, 8}, {4, 8},  {4, 16}, {6, 8}, {6, 16}};

static void t_png_read_all_types(void)
{
    static const int sizes[][2] = {{1, 1}, {3, 2}, {9, 9}, {17, 5}, {33, 20}};
    pw_rng r = pw_rng_seed(9, 9);
    size_t t;
    int si, il, trns, count = 0;
    for (t = 0; t < sizeof type_depths / sizeof type_depths[0]; t++)
        for (si = 0; si < 5; si++)
            for (il = 0; il <= 1; il++)
                for (trns = 0; trns <= 1; trns++) {
                    spec sp;
                    pw_buf b;
                    pw_image img;
                    pw_err e;
                    int ct = type_depths[t][0];
                    if (trns && (ct == 4 || ct == 6)) continue;
                    random_spec(&sp, sizes[si][0], sizes[si][1], ct, type_depths[t][1], il, trns,
                                &r);
                    memset(&b, 0, sizeof b);
                    encode_spec(&sp, &b, si == 3 ? 7 : 65536); /* also many small IDATs */
                    pw_err_clear(&e);
                    CHECKF(pw_image_read_memory(NULL, b.data, b.size, "all.png", &img, &e) == PW_OK,
                           "type %d depth %d: %s", ct, sp.depth, e.msg);
                    CHECKF(img.px && check_decoded(&sp, &img),
                           "type %d depth %d size %dx%d interlace %d trns %d", ct, sp.depth, sp.w,
                           sp.h, il, trns);
                    count++;
                    pw_image_free(NULL, &img);
                    free(b.data);
                    free(sp.s);
                }
    pwt_info("%d generated PNG files decoded", count);
}

/* netpbm decodes the same generated files identically. */
static void t_png_read_vs_netpbm(void)
{
    pw_rng r = pw_rng_seed(4, 4);
    const char *png = pwt_tmp("png", 0, ".png"), *pam = pwt_tmp("png", 1, ".pam");
    char cmd[700];
    size_t t;
    int il, trns, count = 0;
    if (!have("pngtopam")) {
        pwt_skip("netpbm (pngtopam) not installed");
        return;
    }
    for (t = 0; t < sizeof type_depths / sizeof type_depths[0]; t++)
        for (il = 0; il <= 1; il++)
            for (trns = 0; trns <= 1; trns++) {
                spec sp;
                pw_buf b;
                pw_image ours, theirs, conv;
                pw_err e;
                int ct = type_depths[t][0];
                if (trns && (ct == 4 || ct == 6)) continue;
                /* pngtopam (netpbm 11.1) ignores the tRNS colour key of RGB
                 * images, which the PNG specification (§11.3.2.1) makes
                 * transparent; png_read_all_types covers that case */
                if (trns && ct == 2) continue;
                random_spec(&sp, 19, 11, ct, type_depths[t][1], il, trns, &r);
                memset(&b, 0, sizeof b);
                encode_spec(&sp, &b, 100);
                REQUIRE(write_bytes(png, b.data, b.size));
                snprintf(cmd, sizeof cmd, "pngtopam -alphapam %s > %s 2>/dev/null", png, pam);
                CHECKF(system(cmd) == 0, "pngtopam failed on type %d depth %d", ct, sp.depth);
                pw_err_clear(&e);
                REQUIRE(pw_image_read_memory(NULL, b.data, b.size, png, &ours, &e) == PW_OK);
                REQUIRE(pw_image_load(NULL, pam, &theirs, &e) == PW_OK);
                /* pngtopam -alphapam always adds alpha */
                REQUIRE(pw_image_convert(NULL, &ours, theirs.c, &conv, &e) == PW_OK);
                CHECKF(same_quantized(&conv, &theirs, 65535),
                       "type %d depth %d interlace %d trns %d", ct, sp.depth, il, trns);
                count++;
                pw_image_free(NULL, &ours);
                pw_image_free(NULL, &theirs);
                pw_image_free(NULL, &conv);
                free(b.data);
                free(sp.s);
            }
    remove(png);
    remove(pam);
    pwt_info("%d files agree with pngtopam", count);
}

/* pnmtopng, plain and interlaced, turns the PNM file pnm (holding a's
 * samples) into back, which must read back as a at maxval. */
static void check_pnmtopng(const pw_image *a, const char *pnm, const char *back, unsigned maxval,
                           const char *what)
{
    char cmd[900];
    int il;
    for (il = 0; il <= 1; il++) {
        pw_image b;
        pw_err e;
        snprintf(cmd, sizeof cmd, "pnmtopng %s %s > %s 2>/dev/null", il ? "-interlace" : "", pnm,
                 back);
        CHECKF(system(cmd) == 0, "pnmtopng %s interlace %d failed", what, il);
        pw_err_clear(&e);
        CHECKF(pw_image_load(NULL, back, &b, &e) == PW_OK, "%s", e.msg);
        CHECKF(b.px && same_quantized(a, &b, maxval), "pnmtopng %s interlace %d", what, il);
        pw_image_free(NULL, &b);
    }
}

/* netpbm's pngtopnm/pngtopam decode our PNGs to our own PNM samples, and
 * we decode pnmtopng's PNGs (its own choices of depth, palette, interlace). */
static void t_png_netpbm_cross(void)
{
    const char *png = pwt_tmp("png", 0, ".png"), *pnm = pwt_tmp("png", 1, ".pnm"), *back = pwt_tmp("png", 2, ".pnm");
    char cmd[900], what[64];
    int c, bits;
    if (!have("pngtopnm") || !have("pngtopam") || !have("pnmtopng")) {
        pwt_skip("netpbm (pngtopnm, pngtopam, pnmtopng) not installed");
        return;
    }
    for (c = 1; c <= 4; c++)
        for (bits = 8; bits <= 16; bits += 8) {
            pw_image a, b;
            pw_err e;
            make_smooth(&a, 37, 23, c);
            a.bits = bits;
            pw_err_clear(&e);
            REQUIRE(pw_image_save(png, &a, &e) == PW_OK);
            snprintf(cmd, sizeof cmd,
                     c == 1 || c == 3 ? "pngtopnm %s > %s 2>/dev/null"
                                      : "pngtopam -alphapam %s > %s 2>/dev/null",
                     png, pnm);
            CHECKF(system(cmd) == 0, "netpbm cannot decode our c=%d bits=%d PNG", c, bits);
            REQUIRE(pw_image_load(NULL, pnm, &b, &e) == PW_OK);
            CHECKF(same_quantized(&a, &b, bits == 16 ? 65535u : 255u) && b.bits == bits,
                   "netpbm decodes c=%d bits=%d differently", c, bits);
            pw_image_free(NULL, &b);
            snprintf(what, sizeof what, "c=%d bits=%d", c, bits);
            if (c == 1 || c == 3) /* the other direction */
                check_pnmtopng(&a, pnm, back, bits == 16 ? 65535u : 255u, what);
            pw_image_free(NULL, &a);
        }
    {
        /* few gray levels and few colours: pnmtopng picks low depths and palettes */
        static const char *const srcs[] = {
            "P2 5 3 3 0 1 2 3 0 3 2 1 0 1 1 1 1 1 1\n",
            "P3 4 2 255 255 0 0 0 255 0 0 0 255 255 0 0 9 9 9 255 255 255 0 0 0 0 0 255\n"};
        int i;
        for (i = 0; i < 2; i++) {
            pw_image a;
            pw_err e;
            pw_err_clear(&e);
            REQUIRE(write_bytes(pnm, srcs[i], strlen(srcs[i])));
            REQUIRE(pw_image_load(NULL, pnm, &a, &e) == PW_OK);
            snprintf(what, sizeof what, "source %d", i);
            check_pnmtopng(&a, pnm, back, 255, what);
            pw_image_free(NULL, &a);
        }
    }
    remove(png);
    remove(pnm);
    remove(back);
}

/* ---- malformed PNG ---- */

/* A small valid palette PNG to corrupt. */
static void base_png(pw_buf *b, int idat_extra)
{
    unsigned char raw[16] = {0, 0, 1, 2, 0, 2, 1, 0};
    unsigned char pal[9] = {255, 0, 0, 0, 255, 0, 0, 0, 255};
    memset(b, 0, sizeof *b);
    add_ihdr(b, 3, 2, 8, 3, 0);
    add_chunk(b, "PLTE", pal, 9);
    add_idat(b, raw, (size_t)(8 + idat_extra), 65536);
    add_chunk(b, "IEND", NULL, 0);
}

/* Expects reading b to fail with `code` and a message naming the file and
 * containing `what`; frees b. */
static void expect_png_fail(pw_buf *b, int code, const char *what, int line)
{
    pw_image img;
    pw_err e;
    int rc;
    pw_err_clear(&e);
    rc = pw_image_read_memory(NULL, b->data, b->size, "bad.png", &img, &e);
    if (rc != code || !strstr(e.msg, what) || !strstr(e.msg, "bad.png"))
        pwt_fail_(__FILE__, line, "got %d '%s', expected %d '%s'", rc, e.msg, code, what);
    if (rc == PW_OK) pw_image_free(NULL, &img);
    free(b->data);
}
#define EXPECT_PNG_FAIL(b, code, what) expect_png_fail(b, code, what, __LINE__)

/* A PNG whose raw (filtered) data is given. */
static void raw_png(pw_buf *b, uint32_t w, uint32_t h, int depth, int ctype, int il,
                    const unsigned char *raw, size_t n)
{
    memset(b, 0, sizeof *b);
    add_ihdr(b, w, h, depth, ctype, il);
    add_idat(b, raw, n, 65536);
    add_chunk(b, "IEND", NULL, 0);
}

/* The start of a 3x2 8-bit PNG of colour type ctype: signature and IHDR. */
static void png_head(pw_buf *b, int ctype)
{
    memset(b, 0, sizeof *b);
    add_ihdr(b, 3, 2, 8, ctype, 0);
}

/* Its end: 8 bytes of raw data in an IDAT chunk, then IEND. */
static void png_tail(pw_buf *b, const unsigned char *raw)
{
    add_idat(b, raw, 8, 65536);
    add_chunk(b, "IEND", NULL, 0);
}

static void t_png_malformed(void)
{
    /* invalid IHDR fields: width, bit depth, colour type, interlace method */
    static const struct bad_ihdr {
        uint32_t w;
        int depth, ctype, il;
        const char *what;
    } bad[] = {{3, 3, 0, 0, "bit depth 3 is invalid for PNG colour type 0"},
               {3, 16, 3, 0, "bit depth 16 is invalid for PNG colour type 3"},
               {3, 4, 2, 0, "bit depth 4 is invalid for PNG colour type 2"},
               {3, 8, 5, 0, "invalid PNG colour type 5"},
               {3, 8, 0, 2, "interlace method"},
               {0, 8, 0, 0, "zero size"}};
    pw_buf b;
    pw_image img;
    pw_err e;
    size_t k;
    unsigned char raw[64];
    memset(raw, 0, sizeof raw);
    base_png(&b, 0);
    pw_err_clear(&e);
    REQUIRE(pw_image_read_memory(NULL, b.data, b.size, "ok.png", &img, &e) == PW_OK);
    CHECK(img.c == 3 && img.px[0] == 1.0f && img.px[4] == 1.0f && img.px[8] == 1.0f &&
          img.px[11] == 1.0f);
    pw_image_free(NULL, &img);
    /* every truncation fails with a parse error */
    for (k = 0; k < b.size; k++) {
        pw_err_clear(&e);
        if (pw_png_read_memory(NULL, b.data, k, "bad.png", &img, &e) != PW_ERR_PARSE ||
            !strstr(e.msg, "bad.png")) {
            CHECKF(0, "truncated to %lu: %s", (unsigned long)k, e.msg);
            break;
        }
    }
    pw_err_clear(&e);
    CHECK(pw_png_read_memory(NULL, b.data, b.size - 12, "bad.png", &img, &e) == PW_ERR_PARSE &&
          strstr(e.msg, "no IEND"));
    b.data[0] = 0x88;
    pw_err_clear(&e);
    CHECK(pw_png_read_memory(NULL, b.data, b.size, "bad.png", &img, &e) == PW_ERR_PARSE &&
          strstr(e.msg, "not a PNG"));
    b.data[0] = 0x89;
    b.data[8 + 8 + 3] ^= 1; /* IHDR width */
    EXPECT_PNG_FAIL(&b, PW_ERR_PARSE, "CRC mismatch in PNG chunk 'IHDR'");
    base_png(&b, 0);
    b.data[33 + 8] ^= 1; /* PLTE data */
    EXPECT_PNG_FAIL(&b, PW_ERR_PARSE, "CRC mismatch in PNG chunk 'PLTE'");
    base_png(&b, 0);
    b.data[33 + 4] = '1';
    EXPECT_PNG_FAIL(&b, PW_ERR_PARSE, "bad PNG chunk type");
    base_png(&b, 0);
    b.data[33 + 3] = 200; /* PLTE length beyond the file */
    EXPECT_PNG_FAIL(&b, PW_ERR_PARSE, "chunk 'PLTE' truncated");

    base_png(&b, 1);
    EXPECT_PNG_FAIL(&b, PW_ERR_PARSE, "longer than the 8 bytes");
    base_png(&b, -2);
    EXPECT_PNG_FAIL(&b, PW_ERR_PARSE, "image data truncated (6 of 8 bytes)");

    for (k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        raw_png(&b, bad[k].w, 2, bad[k].depth, bad[k].ctype, bad[k].il, raw, 8);
        EXPECT_PNG_FAIL(&b, PW_ERR_PARSE, bad[k].what);
    }
    raw[4] = 5; /* filter type of row 1 */
    png_head(&b, 0);
    png_tail(&b, raw);
    EXPECT_PNG_FAIL(&b, PW_ERR_PARSE, "invalid PNG filter type 5");
    raw[4] = 0;
    raw[3] = 7; /* palette index 7 of 3 */
    png_head(&b, 3);
    add_chunk(&b, "PLTE", raw + 8, 9);
    png_tail(&b, raw);
    EXPECT_PNG_FAIL(&b, PW_ERR_PARSE, "palette index 7 out of range (3 entries)");
    raw[3] = 0;
    png_head(&b, 3);
    add_chunk(&b, "PLTE", raw + 8, 9);
    add_chunk(&b, "tRNS", raw + 8, 4);
    png_tail(&b, raw);
    EXPECT_PNG_FAIL(&b, PW_ERR_PARSE, "tRNS chunk has 4 entries for a palette of 3");
    png_head(&b, 3);
    png_tail(&b, raw);
    EXPECT_PNG_FAIL(&b, PW_ERR_PARSE, "palette PNG has no PLTE chunk");
    png_head(&b, 0);
    add_chunk(&b, "ABCD", raw, 3);
    png_tail(&b, raw);
    EXPECT_PNG_FAIL(&b, PW_ERR_UNSUPPORTED, "unknown critical PNG chunk 'ABCD'");
    png_head(&b, 0);
    add_chunk(&b, "IEND", NULL, 0);
    EXPECT_PNG_FAIL(&b, PW_ERR_PARSE, "no IDAT chunk");
    memset(&b, 0, sizeof b);
    pw_buf_write(&b, "\x89PNG\r\n\x1a\n", 8);
    add_chunk(&b, "gAMA", raw, 4);
    EXPECT_PNG_FAIL(&b, PW_ERR_PARSE, "first PNG chunk is not IHDR");
    png_head(&b, 0);
    add_chunk(&b, "IDAT", (const unsigned char *)"\x78\x9c\xff\xff\xff\xff", 6);
    add_chunk(&b, "IEND", NULL, 0);
    EXPECT_PNG_FAIL(&b, PW_ERR_PARSE, "bad.png: PNG image data: deflate data");
    png_head(&b, 0);
    add_chunk(&b, "IHDR", raw, 13);
    EXPECT_PNG_FAIL(&b, PW_ERR_PARSE, "more than one IHDR");
    png_head(&b, 3);
    add_chunk(&b, "PLTE", raw + 8, 9);
    add_idat(&b, raw, 8, 65536);
    add_chunk(&b, "PLTE", raw + 8, 9);
    add_chunk(&b, "IEND", NULL, 0);
    EXPECT_PNG_FAIL(&b, PW_ERR_PARSE, "PLTE chunk after the image data");
}

/* Huge IHDR sizes are refused before any allocation. */
static void t_png_huge_no_alloc(void)
{
    static const uint32_t dims[][2] = {
        {0x80000000u, 0x80000000u}, {65537, 1}, {65536, 65536}, {60000, 4000}};
    unsigned char raw[8] = {0};
    pwt_alloc_state counts = {0, 0, -1};
    pw_alloc counting = {pwt_malloc, pwt_realloc, pwt_free, &counts};
    size_t i;
    for (i = 0; i < 4; i++) {
        pw_buf b;
        pw_image img;
        pw_err e;
        int rc;
        raw_png(&b, dims[i][0], dims[i][1], 16, 6, (int)i & 1, raw, sizeof raw);
        counts.calls = 0;
        pw_err_clear(&e);
        rc = pw_image_read_memory(&counting, b.data, b.size, "huge.png", &img, &e);
        CHECKF(rc == (i < 3 ? PW_ERR_LIMIT : PW_ERR_PARSE), "case %lu: %d %s", (unsigned long)i, rc,
               e.msg);
        CHECKF(counts.calls == 0, "case %lu: %ld allocations", (unsigned long)i, counts.calls);
        CHECK(strstr(e.msg, i < 3 ? "exceeds the limits" : "too short for a 60000x4000 image") !=
              NULL);
        free(b.data);
    }
}

/* ---- compression and speed ---- */

static void t_png_compression_ratio(void)
{
    pw_image g;
    pw_buf b;
    pw_err e;
    size_t raw;
    int x, y;
    pw_image_alloc(NULL, &g, 256, 256, 3, NULL);
    for (y = 0; y < 256; y++)
        for (x = 0; x < 256; x++) {
            float *p = g.px + ((size_t)y * 256 + x) * 3;
            p[0] = (float)x / 255.0f;
            p[1] = (float)y / 255.0f;
            p[2] = (float)(x + y) / 510.0f;
        }
    REQUIRE(png_to_buf(NULL, &g, 8, &b, &e) == PW_OK);
    raw = 256 * 256 * 3;
    pwt_info("256x256 RGB gradient: %lu bytes as PNG, raw %lu (%.2f%%)", (unsigned long)b.size,
             (unsigned long)raw, 100.0 * b.size / raw);
    CHECK(b.size < raw / 2);
    CHECK(b.size < raw / 20);
    free(b.data);
    pw_image_free(NULL, &g);
    make_smooth(&g, 256, 256, 3);
    REQUIRE(png_to_buf(NULL, &g, 8, &b, &e) == PW_OK);
    pwt_info("256x256 RGB smooth+noise: %lu bytes as PNG (%.1f%% of raw)", (unsigned long)b.size,
             100.0 * b.size / raw);
    CHECK(b.size < raw / 2);
    free(b.data);
    pw_image_free(NULL, &g);
}

/* A real texture (GIMP pattern) at 256x256 and upsampled to 512x512. */
static void t_png_texture(void)
{
    const char *path = "/usr/share/gimp/2.0/patterns/3dweave.pat";
    pw_image t, big;
    pw_buf b;
    pw_err e;
    int x, y;
    double t0;
    FILE *f = fopen(path, "rb");
    if (!f) {
        pwt_skip("%s absent", path);
        return;
    }
    fclose(f);
    pw_err_clear(&e);
    REQUIRE(pw_image_load(NULL, path, &t, &e) == PW_OK);
    t0 = now();
    REQUIRE(png_to_buf(NULL, &t, 8, &b, &e) == PW_OK);
    pwt_info("%s %dx%d: PNG %lu bytes, raw %lu (%.1f%%), %.3f s", path, t.w, t.h,
             (unsigned long)b.size, (unsigned long)t.w * t.h * t.c,
             100.0 * b.size / ((double)t.w * t.h * t.c), now() - t0);
    CHECK(b.size < (size_t)t.w * t.h * t.c * 9 / 10);
    free(b.data);
    REQUIRE(pw_image_alloc(NULL, &big, 512, 512, t.c, &e) == PW_OK);
    for (y = 0; y < 512; y++)
        for (x = 0; x < 512; x++)
            pw_image_sample_bilinear(&t, (x + 0.5f) * t.w / 512.0f, (y + 0.5f) * t.h / 512.0f,
                                     big.px + ((size_t)y * 512 + x) * t.c);
    t0 = now();
    REQUIRE(png_to_buf(NULL, &big, 8, &b, &e) == PW_OK);
    pwt_info("512x512 upsampled texture: PNG %lu bytes, raw %lu (%.1f%%), %.3f s",
             (unsigned long)b.size, (unsigned long)512 * 512 * t.c,
             100.0 * b.size / (512.0 * 512 * t.c), now() - t0);
    CHECK(b.size < (size_t)512 * 512 * t.c / 2);
    free(b.data);
    pw_image_free(NULL, &t);
    pw_image_free(NULL, &big);
}

static void t_png_speed(void)
{
    pw_image img, back;
    pw_buf b;
    pw_err e;
    double t0, tw, tr;
    make_smooth(&img, 1024, 1024, 3);
    t0 = now();
    REQUIRE(png_to_buf(NULL, &img, 8, &b, &e) == PW_OK);
    tw = now() - t0;
    t0 = now();
    REQUIRE(pw_png_read_memory(NULL, b.data, b.size, "speed.png", &back, &e) == PW_OK);
    tr = now() - t0;
    pwt_info("1024x1024 RGB: PNG %lu bytes (%.1f%% of raw), write %.3f s, read %.3f s",
             (unsigned long)b.size, 100.0 * b.size / (1024.0 * 1024 * 3), tw, tr);
    CHECK(same_quantized(&img, &back, 255));
    CHECK(tw < 5.0); /* generous: sanitizer builds are slower */
    free(b.data);
    pw_image_free(NULL, &img);
    pw_image_free(NULL, &back);
}

static const pwt_case cases[] = {
    {"checksums", t_checksums},
    {"deflate_roundtrip", t_deflate_roundtrip},
    {"deflate_empty", t_deflate_empty},
    {"deflate_large", t_deflate_large},
    {"inflate_handmade", t_inflate_handmade},
    {"inflate_corrupt", t_inflate_corrupt},
    {"inflate_truncated_and_flipped", t_inflate_truncated_and_flipped},
    {"zlib_errors", t_zlib_errors},
    {"python_zlib", t_python_zlib},
    {"png_roundtrip", t_png_roundtrip},
    {"png_write_structure", t_png_write_structure},
    {"png_read_all_types", t_png_read_all_types},
    {"png_read_vs_netpbm", t_png_read_vs_netpbm},
    {"png_netpbm_cross", t_png_netpbm_cross},
    {"png_malformed", t_png_malformed},
    {"png_huge_no_alloc", t_png_huge_no_alloc},
    {"png_compression_ratio", t_png_compression_ratio},
    {"png_texture", t_png_texture},
    {"png_speed", t_png_speed},
};
PWT_MAIN(cases)
