/* Tests of src/common/image.h: PNM/PAM/GIMP pattern reading and writing,
 * the format front end (png.h), and the image helpers. */
#include "../src/common/png.h"
#include "../src/common/rng.h"
#include "pwtest.h"

/* ---- helpers ---- */

/* A test image of random samples in [0,1]. */
static void make_image(pw_image *img, int w, int h, int c, uint64_t seed)
{
    pw_rng r = pw_rng_seed(seed, 7);
    size_t i;
    pw_image_alloc(NULL, img, w, h, c, NULL);
    for (i = 0; i < (size_t)w * h * c; i++) img->px[i] = pw_rng_float(&r);
}

/* Same samples after quantisation to maxval? */
static int same_quantized(const pw_image *a, const pw_image *b, unsigned maxval)
{
    size_t i;
    if (a->w != b->w || a->h != b->h || a->c != b->c) return 0;
    for (i = 0; i < (size_t)a->w * a->h * a->c; i++)
        if (pw_image_quantize(a->px[i], maxval) != pw_image_quantize(b->px[i], maxval)) return 0;
    return 1;
}

/* Reads `size` bytes of data as an image named "t.img". */
static int read_mem(const void *data, size_t size, pw_image *img, pw_err *e)
{
    pw_err_clear(e);
    return pw_image_read_memory(NULL, (const unsigned char *)data, size, "t.img", img, e);
}

/* Expects the read to fail with `code` and a message containing `what`. */
static void expect_fail(const char *data, size_t size, int code, const char *what, int line)
{
    pw_image img;
    pw_err e;
    int rc = read_mem(data, size, &img, &e);
    if (rc != code || !strstr(e.msg, what) || !strstr(e.msg, "t.img"))
        pwt_fail_(__FILE__, line, "input %.20s...: got code %d '%s', expected %d '%s'", data, rc,
                  e.msg, code, what);
    if (rc == PW_OK) pw_image_free(NULL, &img);
    CHECK(img.px == NULL);
}
#define EXPECT_FAIL(s, code, what) expect_fail(s, sizeof(s) - 1, code, what, __LINE__)

static int fail_write(void *ctx, const void *data, size_t size)
{
    (void)ctx;
    (void)data;
    (void)size;
    return -1;
}

/* ---- round trips ---- */

static void t_pnm_roundtrip_all(void)
{
    int c, bits, ascii, w = 13, h = 7;
    for (c = 1; c <= 4; c++)
        for (bits = 8; bits <= 16; bits += 8)
            for (ascii = 0; ascii <= 1; ascii++) {
                pw_image a, b;
                pw_buf buf;
                pw_err e;
                int rc;
                if (ascii && (c == 2 || c == 4)) continue;
                make_image(&a, w, h, c, (uint64_t)(c * 100 + bits + ascii));
                memset(&buf, 0, sizeof buf);
                pw_err_clear(&e);
                rc = pw_image_write_pnm(&a, bits, ascii, pw_buf_write, &buf, &e);
                CHECKF(rc == PW_OK, "write c=%d bits=%d ascii=%d: %s", c, bits, ascii, e.msg);
                rc = read_mem(buf.data, buf.size, &b, &e);
                CHECKF(rc == PW_OK, "read c=%d bits=%d ascii=%d: %s", c, bits, ascii, e.msg);
                if (rc == PW_OK) {
                    CHECKF(same_quantized(&a, &b, bits == 16 ? 65535u : 255u),
                           "samples differ c=%d bits=%d ascii=%d", c, bits, ascii);
                    CHECK_EQ_INT(b.bits, bits);
                    CHECK_EQ_INT(b.c, c);
                }
                if (c == 1) CHECK(buf.data[0] == 'P' && buf.data[1] == (ascii ? '2' : '5'));
                if (c == 3) CHECK(buf.data[0] == 'P' && buf.data[1] == (ascii ? '3' : '6'));
                if (c == 2 || c == 4) CHECK(buf.data[0] == 'P' && buf.data[1] == '7');
                free(buf.data);
                pw_image_free(NULL, &a);
                pw_image_free(NULL, &b);
            }
}

static void t_pam_roundtrip_all(void)
{
    int c, bits;
    for (c = 1; c <= 4; c++)
        for (bits = 8; bits <= 16; bits += 8) {
            pw_image a, b;
            pw_buf buf;
            pw_err e;
            make_image(&a, 5, 9, c, (uint64_t)(c + bits));
            a.bits = bits;
            memset(&buf, 0, sizeof buf);
            pw_err_clear(&e);
            /* bits = 0: the image's own depth */
            REQUIRE(pw_image_write_pam(&a, 0, pw_buf_write, &buf, &e) == PW_OK);
            REQUIRE(read_mem(buf.data, buf.size, &b, &e) == PW_OK);
            CHECK(same_quantized(&a, &b, bits == 16 ? 65535u : 255u));
            CHECK_EQ_INT(b.bits, bits);
            free(buf.data);
            pw_image_free(NULL, &a);
            pw_image_free(NULL, &b);
        }
}

/* Every 8-bit and 16-bit sample value survives write + read exactly. */
static void t_every_value_exact(void)
{
    pw_image a, b;
    pw_buf buf;
    pw_err e;
    int i;
    pw_image_alloc(NULL, &a, 256, 256, 1, NULL);
    for (i = 0; i < 65536; i++) a.px[i] = (float)i / 65535.0f;
    memset(&buf, 0, sizeof buf);
    pw_err_clear(&e);
    REQUIRE(pw_image_write_pnm(&a, 16, 0, pw_buf_write, &buf, &e) == PW_OK);
    REQUIRE(read_mem(buf.data, buf.size, &b, &e) == PW_OK);
    for (i = 0; i < 65536; i++) {
        unsigned v = (unsigned)buf.data[buf.size - 131072 + 2 * i] << 8 |
                     buf.data[buf.size - 131072 + 2 * i + 1];
        if (v != (unsigned)i || pw_image_quantize(b.px[i], 65535) != (unsigned)i) {
            CHECKF(0, "16-bit value %d written as %u", i, v);
            break;
        }
    }
    for (i = 0; i < 256; i++)
        if (pw_image_quantize((float)i / 255.0f, 255) != (unsigned)i)
            CHECKF(0, "8-bit value %d", i);
    free(buf.data);
    pw_image_free(NULL, &a);
    pw_image_free(NULL, &b);
}

static void t_written_headers(void)
{
    pw_image a;
    pw_buf buf;
    pw_err e;
    static const char pam[] =
        "P7\nWIDTH 3\nHEIGHT 1\nDEPTH 4\nMAXVAL 65535\nTUPLTYPE RGB_ALPHA\nENDHDR\n";
    make_image(&a, 3, 2, 3, 1);
    memset(&buf, 0, sizeof buf);
    pw_err_clear(&e);
    REQUIRE(pw_image_write_pnm(&a, 0, 0, pw_buf_write, &buf, &e) == PW_OK);
    CHECK(buf.size == 11 + 18 && memcmp(buf.data, "P6\n3 2\n255\n", 11) == 0);
    buf.size = 0;
    a.c = 1; /* the first 6 samples as a gray image */
    REQUIRE(pw_image_write_pnm(&a, 16, 1, pw_buf_write, &buf, &e) == PW_OK);
    CHECK(memcmp(buf.data, "P2\n3 2\n65535\n", 13) == 0);
    a.c = 4;
    a.h = 1;
    buf.size = 0;
    REQUIRE(pw_image_write_pam(&a, 16, pw_buf_write, &buf, &e) == PW_OK);
    CHECK(memcmp(buf.data, pam, sizeof pam - 1) == 0);
    CHECK(buf.size == sizeof pam - 1 + 3 * 4 * 2);
    a.c = 3;
    a.h = 2;
    free(buf.data);
    pw_image_free(NULL, &a);
}

/* ASCII lines stay under 70 characters. */
static void t_ascii_line_length(void)
{
    pw_image a;
    pw_buf buf;
    pw_err e;
    size_t i, col = 0, maxcol = 0;
    make_image(&a, 100, 3, 3, 5);
    memset(&buf, 0, sizeof buf);
    pw_err_clear(&e);
    REQUIRE(pw_image_write_pnm(&a, 16, 1, pw_buf_write, &buf, &e) == PW_OK);
    for (i = 0; i < buf.size; i++) {
        col = buf.data[i] == '\n' ? 0 : col + 1;
        if (col > maxcol) maxcol = col;
    }
    CHECKF(maxcol <= 70, "line of %lu characters", (unsigned long)maxcol);
    free(buf.data);
    pw_image_free(NULL, &a);
}

/* ---- header syntax ---- */

static void t_comments(void)
{
    static const char p3[] = "P3\n# comment\n2 # width\n#another\n1\n# before maxval\n255 # after\n"
                             "0 255 51 # trailing\n# own line\n 102 153 204\n";
    static const char p5[] = "P5 # magic comment\n2 1 255# right after maxval\nAB";
    static const char pam[] = "P7\n# comment\nWIDTH 1\n  # indented comment\nHEIGHT 1\nDEPTH 1\n"
                              "MAXVAL 255\n\nENDHDR\nZ";
    pw_image img;
    pw_err e;
    REQUIRE(read_mem(p3, sizeof p3 - 1, &img, &e) == PW_OK);
    CHECK(img.w == 2 && img.h == 1 && img.c == 3 && img.bits == 8);
    CHECK_NEAR(img.px[1], 1.0, 0);
    CHECK_NEAR(img.px[2], 0.2, 1e-6);
    CHECK_NEAR(img.px[5], 0.8, 1e-6);
    pw_image_free(NULL, &img);
    REQUIRE(read_mem(p5, sizeof p5 - 1, &img, &e) == PW_OK);
    CHECK(img.w == 2 && img.c == 1 && pw_image_quantize(img.px[1], 255) == 'B');
    pw_image_free(NULL, &img);
    REQUIRE(read_mem(pam, sizeof pam - 1, &img, &e) == PW_OK);
    CHECK(img.c == 1 && pw_image_quantize(img.px[0], 255) == 'Z');
    pw_image_free(NULL, &img);
}

static void t_crlf(void)
{
    static const char p2[] = "P2\r\n# dos\r\n2 2\r\n255\r\n1 2\r\n3 4\r\n";
    static const char p6[] = "P6\r\n1 1\r\n255\r\n\n\n\n"; /* raster is 3 newline bytes */
    static const char p6b[] = "P6\r\n1 1\r\n255\r\nabc";
    static const char pam[] = "P7\r\nWIDTH 1\r\nHEIGHT 1\r\nDEPTH 2\r\nMAXVAL 255\r\n"
                              "TUPLTYPE GRAYSCALE_ALPHA\r\nENDHDR\r\nxy";
    pw_image img;
    pw_err e;
    REQUIRE(read_mem(p2, sizeof p2 - 1, &img, &e) == PW_OK);
    CHECK(pw_image_quantize(img.px[3], 255) == 4);
    pw_image_free(NULL, &img);
    REQUIRE(read_mem(p6, sizeof p6 - 1, &img, &e) == PW_OK);
    CHECK(pw_image_quantize(img.px[0], 255) == 10 && pw_image_quantize(img.px[2], 255) == 10);
    pw_image_free(NULL, &img);
    /* CR as the single separator, the LF is skipped because exactly the
     * raster follows it */
    {
        static const char p6c[] = "P6\n1 1\n255\r\nabc";
        REQUIRE(read_mem(p6c, sizeof p6c - 1, &img, &e) == PW_OK);
        CHECK(pw_image_quantize(img.px[0], 255) == 'a');
        pw_image_free(NULL, &img);
    }
    REQUIRE(read_mem(p6b, sizeof p6b - 1, &img, &e) == PW_OK);
    CHECK(pw_image_quantize(img.px[2], 255) == 'c');
    pw_image_free(NULL, &img);
    REQUIRE(read_mem(pam, sizeof pam - 1, &img, &e) == PW_OK);
    CHECK(img.c == 2 && pw_image_quantize(img.px[1], 255) == 'y');
    pw_image_free(NULL, &img);
}

static void t_maxval_scaling(void)
{
    static const char p2[] = "P2 3 1 1000 0 500 1000";
    static const char p5[] = "P5 2 1 15\n\x0f\x05";
    static const char p5w[] = "P5 1 1 300\n\x01\x2c"; /* 16-bit: 300 */
    pw_image img;
    pw_err e;
    REQUIRE(read_mem(p2, sizeof p2 - 1, &img, &e) == PW_OK);
    CHECK(img.bits == 16);
    CHECK_NEAR(img.px[1], 0.5, 1e-7);
    CHECK_NEAR(img.px[2], 1.0, 0);
    pw_image_free(NULL, &img);
    REQUIRE(read_mem(p5, sizeof p5 - 1, &img, &e) == PW_OK);
    CHECK(img.bits == 8);
    CHECK_NEAR(img.px[0], 1.0, 0);
    CHECK_NEAR(img.px[1], 1.0 / 3.0, 1e-7);
    pw_image_free(NULL, &img);
    REQUIRE(read_mem(p5w, sizeof p5w - 1, &img, &e) == PW_OK);
    CHECK(img.bits == 16);
    CHECK_NEAR(img.px[0], 1.0, 0);
    pw_image_free(NULL, &img);
}

static void t_pbm(void)
{
    static const char p1[] = "P1\n# bitmap\n3 2\n0 1 0\n110";
    static const char p4[] = "P4 9 2\n\x80\x80\x7f\x00";
    pw_image img;
    pw_err e;
    REQUIRE(read_mem(p1, sizeof p1 - 1, &img, &e) == PW_OK);
    CHECK(img.c == 1 && img.w == 3 && img.h == 2);
    CHECK(img.px[0] == 1.0f && img.px[1] == 0.0f && img.px[3] == 0.0f && img.px[5] == 1.0f);
    pw_image_free(NULL, &img);
    REQUIRE(read_mem(p4, sizeof p4 - 1, &img, &e) == PW_OK);
    CHECK(img.px[0] == 0.0f && img.px[1] == 1.0f && img.px[8] == 0.0f);
    CHECK(img.px[9] == 1.0f && img.px[10] == 0.0f && img.px[17] == 1.0f);
    pw_image_free(NULL, &img);
}

/* ---- malformed input ---- */

static void t_malformed_pnm(void)
{
    EXPECT_FAIL("", PW_ERR_PARSE, "empty");
    EXPECT_FAIL("P8\n1 1\n255\n", PW_ERR_UNSUPPORTED, "unknown image format");
    EXPECT_FAIL("JFIF....", PW_ERR_UNSUPPORTED, "unknown image format");
    EXPECT_FAIL("P6x 1 1 255\nabc", PW_ERR_PARSE, "bad magic");
    EXPECT_FAIL("P6\n2 2\n255\n01234567890", PW_ERR_PARSE,
                "truncated: 12 bytes needed, 11 present");
    EXPECT_FAIL("P6\n2 2\n255", PW_ERR_PARSE, "no pixel data");
    EXPECT_FAIL("P6\n2 2\n", PW_ERR_PARSE, ":3: file truncated: it ends before the maxval");
    EXPECT_FAIL("P6\n2", PW_ERR_PARSE, "ends before the height");
    EXPECT_FAIL("P5\n0 2\n255\n", PW_ERR_PARSE, "zero size");
    EXPECT_FAIL("P5\n2 0\n255\n", PW_ERR_PARSE, "zero size");
    EXPECT_FAIL("P5\n2 2\n0\nabcd", PW_ERR_PARSE, "maxval 0 is out of range");
    EXPECT_FAIL("P5\n2 2\n65536\nabcdefgh", PW_ERR_PARSE, "maxval 65536 is out of range");
    EXPECT_FAIL("P5\n70000 2\n255\n", PW_ERR_LIMIT, "exceeds the limits");
    EXPECT_FAIL("P5\n99999999999 2\n255\n", PW_ERR_LIMIT, "width is too large");
    EXPECT_FAIL("P5\n2x 2\n255\n", PW_ERR_PARSE, "expected the end of the number, found 'x'");
    EXPECT_FAIL("P5\n-2 2\n255\n", PW_ERR_PARSE, "expected the width, found '-'");
    EXPECT_FAIL("P5\n1 1\n100\n\xc8", PW_ERR_PARSE, "sample 0 is 200, above maxval 100");
    EXPECT_FAIL("P2\n2 1\n255\n\n1 256\n", PW_ERR_PARSE,
                "t.img:5: sample 1 is 256, above maxval 255");
    EXPECT_FAIL("P2\n2 1\n255\n1 x\n", PW_ERR_PARSE, ":4: expected the sample, found 'x'");
    EXPECT_FAIL("P3\n2 1\n255\n1 2 3 4 5\n", PW_ERR_PARSE, "truncated: it ends before the sample");
    EXPECT_FAIL("P3\n100 100\n255\n1 2 3\n", PW_ERR_PARSE, "too short for 30000 samples");
    EXPECT_FAIL("P1\n2 1\n0 2\n", PW_ERR_PARSE, "expected the bit 0 or 1, found '2'");
    EXPECT_FAIL("P1\n2 1\n0", PW_ERR_PARSE, "truncated");
    EXPECT_FAIL("P4\n9 2\n\x80\x80\x7f", PW_ERR_PARSE, "truncated");
}

static void t_malformed_pam(void)
{
    EXPECT_FAIL("P7\nWIDTH 2\nHEIGHT 2\nDEPTH 3\nMAXVAL 255\nTUPLTYPE RGB_ALPHA\nENDHDR\n",
                PW_ERR_PARSE, "TUPLTYPE RGB_ALPHA needs DEPTH 4, not 3");
    EXPECT_FAIL("P7\nWIDTH 2\nHEIGHT 2\nDEPTH 3\nMAXVAL 255\n", PW_ERR_PARSE, "no ENDHDR");
    EXPECT_FAIL("P7\nWIDTH 2\nHEIGHT 2\nDEPTH 3\nMAXVAL 255", PW_ERR_PARSE,
                ":5: file truncated: PAM header has no ENDHDR");
    EXPECT_FAIL("P7\nHEIGHT 2\nDEPTH 3\nMAXVAL 255\nENDHDR\n", PW_ERR_PARSE, "lacks WIDTH");
    EXPECT_FAIL("P7\nWIDTH 1\nHEIGHT 2\nDEPTH 3\nENDHDR\n", PW_ERR_PARSE, "lacks MAXVAL");
    EXPECT_FAIL("P7\nWIDTH 1\nFOO 2\nENDHDR\n", PW_ERR_PARSE,
                "t.img:3: unknown PAM header field 'FOO'");
    EXPECT_FAIL("P7\nWIDTH x1\nENDHDR\n", PW_ERR_PARSE, ":2: bad WIDTH value");
    EXPECT_FAIL("P7\nWIDTH 1\nHEIGHT 1\nDEPTH 4\nMAXVAL 255\nTUPLTYPE CMYK\nENDHDR\nabcd",
                PW_ERR_UNSUPPORTED, "TUPLTYPE 'CMYK' is not supported");
    EXPECT_FAIL("P7\nWIDTH 1\nHEIGHT 1\nDEPTH 5\nMAXVAL 255\nENDHDR\nabcde", PW_ERR_UNSUPPORTED,
                "depth 5");
    EXPECT_FAIL("P7\nWIDTH 1\nHEIGHT 1\nDEPTH 1\nMAXVAL 70000\nENDHDR\na", PW_ERR_PARSE,
                "maxval 70000");
    EXPECT_FAIL("P7\nWIDTH 2\nHEIGHT 2\nDEPTH 1\nMAXVAL 300\nENDHDR\nabcdefg", PW_ERR_PARSE,
                "truncated: 8 bytes needed, 7 present");
    EXPECT_FAIL("P7 WIDTH 1\n", PW_ERR_PARSE, "bad magic");
}

/* A header claiming 2^31 x 2^31 pixels is refused before any allocation. */
static void t_huge_header_no_alloc(void)
{
    static const char *const heads[] = {
        "P6\n2147483648 2147483648\n255\n",
        "P7\nWIDTH 2147483648\nHEIGHT 2147483648\nDEPTH 4\nMAXVAL 255\nENDHDR\n",
        "P5\n65536 65536\n255\n", "P3\n60000 60000\n255\n1 2 3", "P5\n60000 60000\n255\nabc"};
    static const unsigned char gpat[28] = {0, 0, 0, 26, 0, 0, 0,   1,   0x80, 0,   0,   0, 0x80, 0,
                                           0, 0, 0, 0,  0, 4, 'G', 'P', 'A',  'T', 'x', 0, 1,    2};
    pwt_alloc_state counts = {0, 0, -1};
    pw_alloc counting = {pwt_malloc, pwt_realloc, pwt_free, &counts};
    pw_image img;
    pw_err e;
    size_t i;
    for (i = 0; i < sizeof heads / sizeof heads[0]; i++) {
        int rc;
        counts.calls = 0;
        pw_err_clear(&e);
        rc = pw_image_read_memory(&counting, (const unsigned char *)heads[i], strlen(heads[i]),
                                  "big", &img, &e);
        CHECKF(rc == PW_ERR_LIMIT || rc == PW_ERR_PARSE, "header %lu: rc %d", (unsigned long)i, rc);
        CHECKF(counts.calls == 0, "header %lu allocated", (unsigned long)i);
    }
    counts.calls = 0;
    pw_err_clear(&e);
    CHECK(pw_image_read_memory(&counting, gpat, sizeof gpat, "big", &img, &e) == PW_ERR_LIMIT);
    CHECK(counts.calls == 0 && strstr(e.msg, "exceeds"));
}

/* ---- GIMP patterns ---- */

/* A .pat file in memory: header, name, w*h*bpp pixel bytes (value = index). */
static size_t make_pat(unsigned char *buf, unsigned w, unsigned h, unsigned bpp, const char *name)
{
    size_t hs = 24 + strlen(name) + 1, i;
    pw__put_be32(buf, (uint32_t)hs);
    pw__put_be32(buf + 4, 1);
    pw__put_be32(buf + 8, w);
    pw__put_be32(buf + 12, h);
    pw__put_be32(buf + 16, bpp);
    memcpy(buf + 20, "GPAT", 4);
    memcpy(buf + 24, name, strlen(name) + 1);
    for (i = 0; i < (size_t)w * h * bpp; i++) buf[hs + i] = (unsigned char)(i * 7);
    return hs + (size_t)w * h * bpp;
}

static void t_gpat_memory(void)
{
    unsigned char buf[512];
    unsigned bpp;
    pw_image img;
    pw_err e;
    for (bpp = 1; bpp <= 4; bpp++) {
        size_t n = make_pat(buf, 5, 3, bpp, "test pattern"), i;
        REQUIRE(read_mem(buf, n, &img, &e) == PW_OK);
        CHECK(img.w == 5 && img.h == 3 && img.c == (int)bpp && img.bits == 8);
        for (i = 0; i < 15 * bpp; i++)
            if (pw_image_quantize(img.px[i], 255) != (unsigned)((i * 7) & 255)) {
                CHECKF(0, "bpp %u sample %lu", bpp, (unsigned long)i);
                break;
            }
        pw_image_free(NULL, &img);
    }
}

static void t_gpat_malformed(void)
{
    unsigned char buf[512];
    size_t n = make_pat(buf, 4, 4, 3, "p");
    pw_image img;
    pw_err e;
    struct {
        int off;
        unsigned val;
        size_t size;
        int code;
        const char *what;
    } cases[] = {
        {-1, 0, 23, PW_ERR_UNSUPPORTED, "unknown image format"}, /* no magic visible */
        {20, 0x47504154u ^ 1u, 0, PW_ERR_UNSUPPORTED, "unknown image format"},
        {4, 2, 0, PW_ERR_UNSUPPORTED, "version 2"},
        {0, 24, 0, PW_ERR_PARSE, "bad GIMP pattern header size 24"},
        {0, 100000, 0, PW_ERR_PARSE, "bad GIMP pattern header size 100000"},
        {8, 0, 0, PW_ERR_PARSE, "zero size"},
        {16, 5, 0, PW_ERR_PARSE, "5 bytes per pixel"},
        {16, 0, 0, PW_ERR_PARSE, "0 bytes per pixel"},
        {12, 5, 0, PW_ERR_PARSE, "truncated: 60 bytes needed, 48 present"},
        {-1, 0, 26 + 47, PW_ERR_PARSE, "truncated"},
    };
    size_t i;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        unsigned char t[512];
        int rc;
        memcpy(t, buf, n);
        if (cases[i].off >= 0) pw__put_be32(t + cases[i].off, cases[i].val);
        rc = read_mem(t, cases[i].size ? cases[i].size : n, &img, &e);
        CHECKF(rc == cases[i].code && strstr(e.msg, cases[i].what) && strstr(e.msg, "t.img"),
               "case %lu: %d '%s'", (unsigned long)i, rc, e.msg);
        if (!rc) pw_image_free(NULL, &img);
    }
    pw_err_clear(&e);
    CHECK(pw_image_read_pat_memory(NULL, buf, 20, "t.img", &img, &e) == PW_ERR_PARSE &&
          strstr(e.msg, "t.img: GIMP pattern header truncated"));
    pw_err_clear(&e);
    buf[21] = 'X';
    CHECK(pw_image_read_pat_memory(NULL, buf, n, "t.img", &img, &e) == PW_ERR_PARSE &&
          strstr(e.msg, "t.img: not a GIMP pattern (bad magic)"));
    buf[21] = 'P';
    /* name without its NUL */
    buf[25] = 'x';
    CHECK(read_mem(buf, n, &img, &e) == PW_ERR_PARSE && strstr(e.msg, "not NUL-terminated"));
}

static void t_gimp_pattern_files(void)
{
    static const char *const files[] = {"/usr/share/gimp/2.0/patterns/Stone/brick.pat",
                                        "/usr/share/gimp/2.0/patterns/3dweave.pat",
                                        "/usr/share/gimp/2.0/patterns/blackwhitefloor.pat"};
    size_t i;
    int found = 0;
    for (i = 0; i < sizeof files / sizeof files[0]; i++) {
        pw_image img;
        pw_err e;
        FILE *f = fopen(files[i], "rb");
        if (!f) continue;
        fclose(f);
        found++;
        pw_err_clear(&e);
        CHECKF(pw_image_load(NULL, files[i], &img, &e) == PW_OK, "%s", e.msg);
        CHECK(img.w > 0 && img.h > 0 && (img.c == 1 || img.c == 3));
        if (img.px) pwt_info("%s: %dx%d, %d channels", files[i], img.w, img.h, img.c);
        pw_image_free(NULL, &img);
    }
    if (!found) pwt_skip("no GIMP patterns under /usr/share/gimp/2.0/patterns");
}

/* ---- helpers ---- */

static void t_convert(void)
{
    pw_image g, rgb, rgba, back, ga;
    pw_err e;
    pw_err_clear(&e);
    make_image(&g, 4, 3, 1, 9);
    g.bits = 16;
    REQUIRE(pw_image_convert(NULL, &g, 3, &rgb, &e) == PW_OK);
    CHECK(rgb.c == 3 && rgb.bits == 16 && rgb.px[3] == g.px[1] && rgb.px[4] == g.px[1] &&
          rgb.px[5] == g.px[1]);
    REQUIRE(pw_image_convert(NULL, &rgb, 4, &rgba, &e) == PW_OK);
    CHECK(rgba.px[3] == 1.0f && rgba.px[4] == g.px[1]);
    REQUIRE(pw_image_convert(NULL, &rgba, 1, &back, &e) == PW_OK);
    CHECK_NEAR(back.px[7], g.px[7], 1e-6);
    REQUIRE(pw_image_convert(NULL, &g, 2, &ga, &e) == PW_OK);
    CHECK(ga.px[2] == g.px[1] && ga.px[3] == 1.0f);
    /* luma weights, and in-place conversion */
    rgb.px[0] = 1.0f;
    rgb.px[1] = 0.0f;
    rgb.px[2] = 0.0f;
    REQUIRE(pw_image_convert(NULL, &rgb, 1, &rgb, &e) == PW_OK);
    CHECK(rgb.c == 1);
    CHECK_NEAR(rgb.px[0], 0.299, 1e-6);
    CHECK(pw_image_convert(NULL, &g, 5, &back, &e) == PW_ERR_INVALID);
    pw_image_free(NULL, &g);
    pw_image_free(NULL, &rgb);
    pw_image_free(NULL, &rgba);
    pw_image_free(NULL, &back);
    pw_image_free(NULL, &ga);
}

static void t_copy_and_u8(void)
{
    pw_image a, b;
    pw_err e;
    unsigned char *u8;
    make_image(&a, 3, 3, 2, 4);
    a.bits = 16;
    a.px[0] = -1.0f;
    a.px[1] = 2.0f;
    a.px[2] = 0.5f;
    a.px[3] = NAN;
    pw_err_clear(&e);
    REQUIRE(pw_image_copy(NULL, &a, &b, &e) == PW_OK);
    CHECK(b.bits == 16 && b.c == 2 && memcmp(a.px, b.px, 18 * sizeof(float)) == 0);
    REQUIRE(pw_image_to_u8(NULL, &a, &u8, &e) == PW_OK);
    CHECK(u8[0] == 0 && u8[1] == 255 && u8[2] == 128 && u8[3] == 0);
    CHECK(u8[17] == pw_image_quantize(a.px[17], 255));
    free(u8);
    pw_image_free(NULL, &a);
    pw_image_free(NULL, &b);
}

static void t_sample_bilinear(void)
{
    pw_image a;
    float v[2];
    pw_image_alloc(NULL, &a, 2, 2, 2, NULL);
    a.px[0] = 0.0f; /* (0,0) */
    a.px[2] = 1.0f; /* (1,0) */
    a.px[4] = 2.0f; /* (0,1) */
    a.px[6] = 3.0f; /* (1,1) */
    a.px[1] = a.px[3] = a.px[5] = a.px[7] = 0.25f;
    pw_image_sample_bilinear(&a, 0.5f, 0.5f, v);
    CHECK_NEAR(v[0], 0.0, 0);
    CHECK_NEAR(v[1], 0.25, 0);
    pw_image_sample_bilinear(&a, 1.5f, 0.5f, v);
    CHECK_NEAR(v[0], 1.0, 0);
    pw_image_sample_bilinear(&a, 0.5f, 1.5f, v);
    CHECK_NEAR(v[0], 2.0, 0);
    pw_image_sample_bilinear(&a, 1.0f, 1.0f, v);
    CHECK_NEAR(v[0], 1.5, 1e-6);
    pw_image_sample_bilinear(&a, 1.0f, 0.5f, v);
    CHECK_NEAR(v[0], 0.5, 1e-6);
    pw_image_sample_bilinear(&a, -5.0f, -5.0f, v);
    CHECK_NEAR(v[0], 0.0, 0);
    pw_image_sample_bilinear(&a, 1e30f, 7.0f, v);
    CHECK_NEAR(v[0], 3.0, 0);
    pw_image_sample_bilinear(&a, 0.0f, 1.5f, v); /* left edge clamps */
    CHECK_NEAR(v[0], 2.0, 0);
    pw_image_sample_bilinear(&a, NAN, 0.5f, v);
    CHECK(v[0] == v[0]);
    pw_image_free(NULL, &a);
}

/* ---- writer errors and files ---- */

static void t_write_errors(void)
{
    pw_image a, bad;
    pw_buf buf;
    pw_err e;
    make_image(&a, 2, 2, 4, 3);
    memset(&buf, 0, sizeof buf);
    memset(&bad, 0, sizeof bad);
    pw_err_clear(&e);
    CHECK(pw_image_write_pnm(&a, 0, 1, pw_buf_write, &buf, &e) == PW_ERR_UNSUPPORTED &&
          strstr(e.msg, "ASCII"));
    pw_err_clear(&e);
    CHECK(pw_image_write_pnm(&a, 12, 0, pw_buf_write, &buf, &e) == PW_ERR_INVALID &&
          strstr(e.msg, "12-bit"));
    pw_err_clear(&e);
    CHECK(pw_image_write_pam(&bad, 8, pw_buf_write, &buf, &e) == PW_ERR_INVALID);
    pw_err_clear(&e);
    CHECK(pw_image_write_pnm(&a, 8, 0, fail_write, NULL, &e) == PW_ERR_IO);
    CHECK(buf.size == 0);
    free(buf.data);
    pw_image_free(NULL, &a);
}

static void t_save_load_files(void)
{
    static const char *const ext[] = {".ppm", ".PGM", ".pnm", ".pam", ".png", ".Png"};
    int i, c;
    for (i = 0; i < 6; i++)
        for (c = 1; c <= 4; c++) {
            const char *path = pwt_tmp("image", c, ext[i]);
            pw_image a, b;
            pw_err e;
            make_image(&a, 6, 5, c, (uint64_t)(i * 10 + c));
            a.bits = (i + c) % 2 ? 16 : 8;
            pw_err_clear(&e);
            CHECKF(pw_image_save(path, &a, &e) == PW_OK, "%s: %s", path, e.msg);
            CHECKF(pw_image_load(NULL, path, &b, &e) == PW_OK, "%s: %s", path, e.msg);
            if (b.px) {
                CHECKF(same_quantized(&a, &b, a.bits == 16 ? 65535u : 255u), "%s differs", path);
                CHECK(b.bits == a.bits);
            }
            remove(path);
            pw_image_free(NULL, &a);
            pw_image_free(NULL, &b);
        }
    {
        pw_image a, b;
        pw_err e;
        make_image(&a, 2, 2, 3, 1);
        pw_err_clear(&e);
        CHECK(pw_image_save("/tmp/out.jpg", &a, &e) == PW_ERR_UNSUPPORTED &&
              strstr(e.msg, "/tmp/out.jpg"));
        pw_err_clear(&e);
        CHECK(pw_image_load(NULL, "/nonexistent/x.ppm", &b, &e) == PW_ERR_IO &&
              strstr(e.msg, "/nonexistent/x.ppm"));
        pw_err_clear(&e);
        CHECK(pw_image_save("/nonexistent/x.ppm", &a, &e) == PW_ERR_IO);
        pw_image_free(NULL, &a);
    }
}

/* netpbm, when installed, reads what we write. */
static void t_netpbm_reads_ours(void)
{
    const char *path = pwt_tmp("image", 0, ".pnm");
    char cmd[600];
    pw_image a;
    pw_err e;
    int c, bits;
    if (system("command -v pamfile >/dev/null 2>&1") != 0) {
        pwt_skip("netpbm (pamfile) not installed");
        return;
    }
    for (c = 1; c <= 4; c++)
        for (bits = 8; bits <= 16; bits += 8) {
            make_image(&a, 7, 4, c, 3);
            a.bits = bits;
            pw_err_clear(&e);
            REQUIRE(pw_image_save(path, &a, &e) == PW_OK);
            snprintf(cmd, sizeof cmd, "pamfile %s 2>/dev/null | grep -q '7 by 4.*maxval %d'", path,
                     bits == 16 ? 65535 : 255);
            CHECKF(system(cmd) == 0, "pamfile rejects c=%d bits=%d", c, bits);
            remove(path);
            pw_image_free(NULL, &a);
        }
}

static const pwt_case cases[] = {
    {"pnm_roundtrip_all", t_pnm_roundtrip_all},
    {"pam_roundtrip_all", t_pam_roundtrip_all},
    {"every_value_exact", t_every_value_exact},
    {"written_headers", t_written_headers},
    {"ascii_line_length", t_ascii_line_length},
    {"comments", t_comments},
    {"crlf", t_crlf},
    {"maxval_scaling", t_maxval_scaling},
    {"pbm", t_pbm},
    {"malformed_pnm", t_malformed_pnm},
    {"malformed_pam", t_malformed_pam},
    {"huge_header_no_alloc", t_huge_header_no_alloc},
    {"gpat_memory", t_gpat_memory},
    {"gpat_malformed", t_gpat_malformed},
    {"gimp_pattern_files", t_gimp_pattern_files},
    {"convert", t_convert},
    {"copy_and_u8", t_copy_and_u8},
    {"sample_bilinear", t_sample_bilinear},
    {"write_errors", t_write_errors},
    {"save_load_files", t_save_load_files},
    {"netpbm_reads_ours", t_netpbm_reads_ours},
};
PWT_MAIN(cases)
