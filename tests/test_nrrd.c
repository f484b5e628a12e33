/* Tests of src/common/nrrd.h: volumes, the NRRD reader and writer, and
 * gzip streams. The gzip inputs below were made once by Python's gzip and
 * zlib modules (independent of our deflate code) and pasted here:
 *
 *   payload = bytes(((i % 24) * 10 + i // 48) & 255 for i in range(192))
 *   gz_plain = gzip.compress(payload, compresslevel=9, mtime=0)
 *   gz_fname = gzip.GzipFile(filename="tile.raw", mode="wb", fileobj=buf,
 *                            mtime=0, compresslevel=6)          (FNAME set)
 *   gz_flags = a member written by hand around zlib's raw deflate
 *              (wbits -15) with FEXTRA ("AB\0\0"), FNAME ("x.raw"),
 *              FCOMMENT ("made by python") and FHCRC set, OS 3
 *   gz_two   = gzip.compress(payload[:100], mtime=0)
 *              + gzip.compress(payload[100:], mtime=0)      (two members) */
#include "../src/common/nrrd.h"
#include "../src/common/rng.h"
#include "pwtest.h"

/* pw_gzip_decompress and pw_gzip_compress into a plain array. */
static int gunzip(const unsigned char *d, size_t n, size_t max, unsigned char **out, size_t *outn, pw_err *e)
{
    pw_buf b;
    int r = pw_gzip_decompress(NULL, d, n, max, &b, e);
    *out = b.data, *outn = b.size;
    return r;
}

static int gzip_mem(const unsigned char *d, size_t n, int level, unsigned char **out, size_t *outn, pw_err *e)
{
    pw_buf b;
    int r = pw_gzip_compress(NULL, d, n, level, &b, e);
    *out = b.data, *outn = b.size;
    return r;
}

static const unsigned char gz_plain[130] = {
    0x1f, 0x8b, 0x08, 0x00, 0x00, 0x00, 0x00, 0x00, 0x02, 0x03, 0x63, 0xe0, 0x12, 0x91, 0xd3,
    0x30, 0xb2, 0x71, 0x0b, 0x88, 0x4a, 0xc9, 0xab, 0x68, 0xea, 0x99, 0xb6, 0x60, 0xd5, 0x96,
    0x7d, 0x27, 0x2e, 0xdd, 0x79, 0xc6, 0x80, 0x43, 0x9c, 0x91, 0x5b, 0x54, 0x5e, 0xd3, 0xd8,
    0xd6, 0x3d, 0x30, 0x3a, 0x35, 0xbf, 0xb2, 0xb9, 0x77, 0xfa, 0xc2, 0xd5, 0x5b, 0xf7, 0x9f,
    0xbc, 0x7c, 0xf7, 0x39, 0x2e, 0x71, 0x26, 0x1e, 0x31, 0x05, 0x2d, 0x13, 0x3b, 0x8f, 0xa0,
    0x98, 0xb4, 0x82, 0xaa, 0x96, 0xbe, 0x19, 0x8b, 0xd6, 0x6c, 0x3b, 0x70, 0xea, 0xca, 0xbd,
    0x17, 0xb8, 0xc4, 0x99, 0x79, 0xc5, 0x15, 0xb5, 0x4d, 0xed, 0x3d, 0x83, 0x63, 0xd3, 0x0b,
    0xab, 0x5b, 0xfb, 0x67, 0x2e, 0x5e, 0xbb, 0xfd, 0xe0, 0xe9, 0xab, 0xf7, 0x5f, 0xe2, 0x12,
    0x07, 0x00, 0x26, 0x42, 0x19, 0xde, 0xc0, 0x00, 0x00, 0x00,
};

static const unsigned char gz_fname[139] = {
    0x1f, 0x8b, 0x08, 0x08, 0x00, 0x00, 0x00, 0x00, 0x00, 0xff, 0x74, 0x69, 0x6c, 0x65, 0x2e, 0x72,
    0x61, 0x77, 0x00, 0x63, 0xe0, 0x12, 0x91, 0xd3, 0x30, 0xb2, 0x71, 0x0b, 0x88, 0x4a, 0xc9, 0xab,
    0x68, 0xea, 0x99, 0xb6, 0x60, 0xd5, 0x96, 0x7d, 0x27, 0x2e, 0xdd, 0x79, 0xc6, 0x80, 0x43, 0x9c,
    0x91, 0x5b, 0x54, 0x5e, 0xd3, 0xd8, 0xd6, 0x3d, 0x30, 0x3a, 0x35, 0xbf, 0xb2, 0xb9, 0x77, 0xfa,
    0xc2, 0xd5, 0x5b, 0xf7, 0x9f, 0xbc, 0x7c, 0xf7, 0x39, 0x2e, 0x71, 0x26, 0x1e, 0x31, 0x05, 0x2d,
    0x13, 0x3b, 0x8f, 0xa0, 0x98, 0xb4, 0x82, 0xaa, 0x96, 0xbe, 0x19, 0x8b, 0xd6, 0x6c, 0x3b, 0x70,
    0xea, 0xca, 0xbd, 0x17, 0xb8, 0xc4, 0x99, 0x79, 0xc5, 0x15, 0xb5, 0x4d, 0xed, 0x3d, 0x83, 0x63,
    0xd3, 0x0b, 0xab, 0x5b, 0xfb, 0x67, 0x2e, 0x5e, 0xbb, 0xfd, 0xe0, 0xe9, 0xab, 0xf7, 0x5f, 0xe2,
    0x12, 0x07, 0x00, 0x26, 0x42, 0x19, 0xde, 0xc0, 0x00, 0x00, 0x00,
};

static const unsigned char gz_flags[159] = {
    0x1f, 0x8b, 0x08, 0x1e, 0x00, 0x00, 0x00, 0x00, 0x00, 0x03, 0x04, 0x00, 0x41, 0x42, 0x00, 0x00,
    0x78, 0x2e, 0x72, 0x61, 0x77, 0x00, 0x6d, 0x61, 0x64, 0x65, 0x20, 0x62, 0x79, 0x20, 0x70, 0x79,
    0x74, 0x68, 0x6f, 0x6e, 0x00, 0xc6, 0xc4, 0x63, 0xe0, 0x12, 0x91, 0xd3, 0x30, 0xb2, 0x71, 0x0b,
    0x88, 0x4a, 0xc9, 0xab, 0x68, 0xea, 0x99, 0xb6, 0x60, 0xd5, 0x96, 0x7d, 0x27, 0x2e, 0xdd, 0x79,
    0xc6, 0x80, 0x43, 0x9c, 0x91, 0x5b, 0x54, 0x5e, 0xd3, 0xd8, 0xd6, 0x3d, 0x30, 0x3a, 0x35, 0xbf,
    0xb2, 0xb9, 0x77, 0xfa, 0xc2, 0xd5, 0x5b, 0xf7, 0x9f, 0xbc, 0x7c, 0xf7, 0x39, 0x2e, 0x71, 0x26,
    0x1e, 0x31, 0x05, 0x2d, 0x13, 0x3b, 0x8f, 0xa0, 0x98, 0xb4, 0x82, 0xaa, 0x96, 0xbe, 0x19, 0x8b,
    0xd6, 0x6c, 0x3b, 0x70, 0xea, 0xca, 0xbd, 0x17, 0xb8, 0xc4, 0x99, 0x79, 0xc5, 0x15, 0xb5, 0x4d,
    0xed, 0x3d, 0x83, 0x63, 0xd3, 0x0b, 0xab, 0x5b, 0xfb, 0x67, 0x2e, 0x5e, 0xbb, 0xfd, 0xe0, 0xe9,
    0xab, 0xf7, 0x5f, 0xe2, 0x12, 0x07, 0x00, 0x26, 0x42, 0x19, 0xde, 0xc0, 0x00, 0x00, 0x00,
};

static const unsigned char gz_two[154] = {
    0x1f, 0x8b, 0x08, 0x00, 0x00, 0x00, 0x00, 0x00, 0x02, 0x03, 0x63, 0xe0, 0x12, 0x91, 0xd3, 0x30,
    0xb2, 0x71, 0x0b, 0x88, 0x4a, 0xc9, 0xab, 0x68, 0xea, 0x99, 0xb6, 0x60, 0xd5, 0x96, 0x7d, 0x27,
    0x2e, 0xdd, 0x79, 0xc6, 0x80, 0x43, 0x9c, 0x91, 0x5b, 0x54, 0x5e, 0xd3, 0xd8, 0xd6, 0x3d, 0x30,
    0x3a, 0x35, 0xbf, 0xb2, 0xb9, 0x77, 0xfa, 0xc2, 0xd5, 0x5b, 0xf7, 0x9f, 0xbc, 0x7c, 0xf7, 0x39,
    0x2e, 0x71, 0x26, 0x1e, 0x31, 0x05, 0x00, 0xcf, 0xbc, 0x84, 0x38, 0x64, 0x00, 0x00, 0x00, 0x1f,
    0x8b, 0x08, 0x00, 0x00, 0x00, 0x00, 0x00, 0x02, 0x03, 0xd3, 0x32, 0xb1, 0xf3, 0x08, 0x8a, 0x49,
    0x2b, 0xa8, 0x6a, 0xe9, 0x9b, 0xb1, 0x68, 0xcd, 0xb6, 0x03, 0xa7, 0xae, 0xdc, 0x7b, 0xc1, 0xc4,
    0x23, 0xa6, 0xa0, 0x85, 0x45, 0x9c, 0x99, 0x57, 0x5c, 0x51, 0xdb, 0xd4, 0xde, 0x33, 0x38, 0x36,
    0xbd, 0xb0, 0xba, 0xb5, 0x7f, 0xe6, 0xe2, 0xb5, 0xdb, 0x0f, 0x9e, 0xbe, 0x7a, 0xff, 0x25, 0x2e,
    0x71, 0x00, 0x58, 0x6b, 0x2d, 0x58, 0x5c, 0x00, 0x00, 0x00,
};

/* The 192 samples the gzip arrays hold. */
static unsigned char payload_byte(int i) { return (unsigned char)(((i % 24) * 10 + i / 48) & 255); }

/* ---- helpers ---- */

/* header text followed by n data bytes, in a static buffer */
static size_t make_file(unsigned char *out, size_t cap, const char *head, const void *data,
                        size_t n)
{
    size_t h = strlen(head);
    if (h + n > cap) return 0;
    memcpy(out, head, h);
    if (n) memcpy(out + h, data, n);
    return h + n;
}

static int read_mem(const void *data, size_t size, pw_volume *v, pw_err *e)
{
    pw_err_clear(e);
    return pw_nrrd_read_memory(NULL, (const unsigned char *)data, size, "t.nrrd", v, e);
}

/* Expects the read to fail with `code` and a message containing `what`
 * (and naming the input). */
static void expect_fail(const void *data, size_t size, int code, const char *what, int line)
{
    pw_volume v;
    pw_err e;
    int rc = read_mem(data, size, &v, &e);
    if (rc != code || !strstr(e.msg, what) || strncmp(e.msg, "t.nrrd", 6) != 0)
        pwt_fail_(__FILE__, line, "input '%.40s...': got code %d '%s', expected %d '%s'",
                  (const char *)data, rc, e.msg, code, what);
    if (rc == PW_OK) pw_volume_free(NULL, &v);
    if (v.px) pwt_fail_(__FILE__, line, "a failed read left samples behind");
}
#define EXPECT_FAIL(s, code, what) expect_fail(s, sizeof(s) - 1, code, what, __LINE__)

static void make_volume(pw_volume *v, int c, int x, int y, int z, int seed)
{
    size_t i, n;
    pw_volume_alloc(NULL, v, c, x, y, z, NULL);
    n = (size_t)c * x * y * z;
    for (i = 0; i < n; i++) v->px[i] = (float)((i * 37 + (size_t)seed * 11) & 255) / 255.0f;
}

static int fail_write(void *ctx, const void *data, size_t size)
{
    (void)ctx;
    (void)data;
    (void)size;
    return -1;
}

/* ---- writer and round trips ---- */

/* uint8 volumes of 1-4 channels: written raw and gzip, read back bit for
 * bit (samples k/255 survive quantisation exactly). */
static void t_roundtrip_u8(void)
{
    int c, gz;
    for (c = 1; c <= 4; c++)
        for (gz = 0; gz <= 1; gz++) {
            pw_volume a, b;
            pw_buf buf;
            pw_err e;
            char want[64];
            size_t n;
            make_volume(&a, c, 5, 3, 4, c + 10 * gz);
            n = (size_t)c * 5 * 3 * 4;
            memset(&buf, 0, sizeof buf);
            pw_err_clear(&e);
            REQUIRE(pw_nrrd_write(NULL, &a, gz, pw_buf_write, &buf, &e) == PW_OK);
            REQUIRE(buf.size > 9 && memcmp(buf.data, "NRRD0004\n", 9) == 0);
            if (c == 1)
                snprintf(want, sizeof want, "dimension: 3\nsizes: 5 3 4\n");
            else
                snprintf(want, sizeof want, "dimension: 4\nsizes: %d 5 3 4\n", c);
            CHECKF(strstr((const char *)buf.data, want) != NULL, "c=%d: no '%s'", c, want);
            CHECK(strstr((const char *)buf.data, "type: uint8\n") != NULL);
            CHECK(strstr((const char *)buf.data,
                         gz ? "encoding: gzip\n\n\x1f\x8b" : "encoding: raw\n\n") != NULL);
            if (!gz)
                CHECK_EQ_INT(buf.size,
                             strstr((const char *)buf.data, "\n\n") + 2 - (char *)buf.data + n);
            REQUIRE(read_mem(buf.data, buf.size, &b, &e) == PW_OK);
            CHECK(b.c == c && b.x == 5 && b.y == 3 && b.z == 4);
            CHECKF(memcmp(a.px, b.px, n * sizeof(float)) == 0, "c=%d gzip=%d: samples differ", c,
                   gz);
            pw_volume_free(NULL, &a);
            pw_volume_free(NULL, &b);
            free(buf.data);
        }
}

/* The exact bytes of a small file, and the quantisation of odd values. */
static void t_write_exact_bytes(void)
{
    static const char want[] = "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 6 1 1\n"
                               "kinds: domain domain domain\nencoding: raw\n\n"
                               "\x00\xff\x80\x00\xff\x00";
    static const char want4[] = "NRRD0004\ntype: uint8\ndimension: 4\nsizes: 3 1 1 2\n"
                                "kinds: RGB-color domain domain domain\nencoding: raw\n\n"
                                "\x01\x02\x03\x04\x05\x06";
    pw_volume v;
    pw_buf buf;
    pw_err e;
    float zero = 0.0f;
    int i;
    REQUIRE(pw_volume_alloc(NULL, &v, 1, 6, 1, 1, NULL) == PW_OK);
    v.px[0] = 0.0f;
    v.px[1] = 1.0f;
    v.px[2] = 0.5f;  /* 127.5 rounds up */
    v.px[3] = -3.0f; /* clamped */
    v.px[4] = 7.0f;
    v.px[5] = zero / zero; /* NaN: 0 */
    memset(&buf, 0, sizeof buf);
    pw_err_clear(&e);
    REQUIRE(pw_nrrd_write(NULL, &v, 0, pw_buf_write, &buf, &e) == PW_OK);
    CHECK_EQ_INT(buf.size, sizeof want - 1);
    CHECK(buf.size == sizeof want - 1 && memcmp(buf.data, want, buf.size) == 0);
    pw_volume_free(NULL, &v);
    free(buf.data);
    REQUIRE(pw_volume_alloc(NULL, &v, 3, 1, 1, 2, NULL) == PW_OK);
    for (i = 0; i < 6; i++) v.px[i] = (float)(i + 1) / 255.0f;
    memset(&buf, 0, sizeof buf);
    REQUIRE(pw_nrrd_write(NULL, &v, 0, pw_buf_write, &buf, &e) == PW_OK);
    CHECK(buf.size == sizeof want4 - 1 && memcmp(buf.data, want4, buf.size) == 0);
    pw_volume_free(NULL, &v);
    free(buf.data);
}

/* NaN written as 0, as pw_image_quantize does. */
static void t_write_nan(void)
{
    pw_volume v, b;
    pw_buf buf;
    pw_err e;
    float zero = 0.0f;
    REQUIRE(pw_volume_alloc(NULL, &v, 1, 2, 1, 1, NULL) == PW_OK);
    v.px[0] = zero / zero;
    v.px[1] = 1.0f;
    memset(&buf, 0, sizeof buf);
    pw_err_clear(&e);
    REQUIRE(pw_nrrd_write(NULL, &v, 1, pw_buf_write, &buf, &e) == PW_OK);
    REQUIRE(read_mem(buf.data, buf.size, &b, &e) == PW_OK);
    CHECK(b.px[0] == 0.0f && b.px[1] == 1.0f);
    pw_volume_free(NULL, &v);
    pw_volume_free(NULL, &b);
    free(buf.data);
}

static void t_write_errors(void)
{
    pw_volume v;
    pw_err e;
    pw_buf buf;
    memset(&v, 0, sizeof v);
    memset(&buf, 0, sizeof buf);
    pw_err_clear(&e);
    CHECK(pw_nrrd_write(NULL, &v, 0, pw_buf_write, &buf, &e) == PW_ERR_INVALID);
    CHECK(strstr(e.msg, "invalid volume") != NULL);
    make_volume(&v, 3, 40, 40, 3, 1);
    pw_err_clear(&e);
    CHECK(pw_nrrd_write(NULL, &v, 0, fail_write, NULL, &e) == PW_ERR_IO);
    pw_err_clear(&e);
    CHECK(pw_nrrd_write(NULL, &v, 1, fail_write, NULL, &e) == PW_ERR_IO);
    v.c = 5;
    pw_err_clear(&e);
    CHECK(pw_nrrd_write(NULL, &v, 0, pw_buf_write, &buf, &e) == PW_ERR_INVALID);
    v.c = 3;
    pw_volume_free(NULL, &v);
    CHECK(buf.size == 0);
    free(buf.data);
}

/* ---- reading handcrafted files ---- */

static void t_read_u16_endian(void)
{
    static const unsigned char be[6] = {0x12, 0x34, 0xff, 0xff, 0x00, 0x01};
    static const unsigned char le[6] = {0x34, 0x12, 0xff, 0xff, 0x01, 0x00};
    static const char *const types[3] = {"ushort", "unsigned short int", "uint16_t"};
    unsigned char f[256];
    char head[160];
    pw_volume v;
    pw_err e;
    int big, t;
    for (big = 0; big <= 1; big++)
        for (t = 0; t < 3; t++) {
            size_t n;
            snprintf(
                head, sizeof head,
                "NRRD0004\ntype: %s\ndimension: 3\nsizes: 3 1 1\nendian: %s\nencoding: raw\n\n",
                types[t], big ? "big" : "little");
            n = make_file(f, sizeof f, head, big ? be : le, 6);
            REQUIRE(read_mem(f, n, &v, &e) == PW_OK);
            CHECK(v.c == 1 && v.x == 3 && v.y == 1 && v.z == 1);
            CHECK(v.px[0] == (float)0x1234 / 65535.0f);
            CHECK(v.px[1] == 1.0f);
            CHECK(v.px[2] == 1.0f / 65535.0f);
            pw_volume_free(NULL, &v);
        }
}

static void t_read_float_endian(void)
{
    /* 0.25, -1.5, 3.0 and 1e-3 as IEEE 754 single precision, big endian */
    static const unsigned char be[16] = {0x3e, 0x80, 0, 0, 0xbf, 0xc0, 0,    0,
                                         0x40, 0x40, 0, 0, 0x3a, 0x83, 0x12, 0x6f};
    unsigned char le[16], f[256];
    pw_volume v;
    pw_err e;
    int i, big;
    for (i = 0; i < 16; i++) le[i] = be[(i & ~3) + 3 - (i & 3)];
    for (big = 0; big <= 1; big++) {
        size_t n = make_file(f, sizeof f,
                             big ? "NRRD0004\ntype: float\ndimension: 4\nsizes: 2 2 1 1\nendian: "
                                   "big\nencoding: raw\n\n"
                                 : "NRRD0004\ntype: float\ndimension: 4\nsizes: 2 2 1 1\nendian: "
                                   "little\nencoding: raw\n\n",
                             big ? be : le, 16);
        REQUIRE(read_mem(f, n, &v, &e) == PW_OK);
        CHECK(v.c == 2 && v.x == 2 && v.y == 1 && v.z == 1);
        CHECK(v.px[0] == 0.25f && v.px[1] == -1.5f && v.px[2] == 3.0f);
        CHECK(v.px[3] == 0.001f);
        pw_volume_free(NULL, &v);
    }
}

/* Comments, key:=value lines, ignored and unknown fields, CR LF line ends,
 * case, the oldest magic and extra bytes after the data. */
static void t_read_header_variants(void)
{
    static const char *const heads[] = {
        "NRRD0001\n# a comment\ncontent: two: colons\nTYPE: UChar\ndimension: 3\n"
        "space: right-anterior-superior\nspace directions: (1,0,0) (0,1,0) (0,0,1)\n"
        "space origin: (0,0,0)\nsizes:   2 3 1  \nkinds: domain domain domain\n"
        "spacings: 1 1 1\nfoo bar: unknown field\nmy key:=my: value\nEncoding: raw\n"
        "byte skip: 0\nline skip: 0\n# the end\n\n",
        "NRRD0005\r\ntype: unsigned char\r\ndimension: 3\r\nsizes: 2 3 1\r\nencoding: raw\r\n\r\n",
        "NRRD0003\ntype: uint8_t\ndimension: 3\nsizes: 2 3 1\nendian: big\nencoding: raw\n\n",
        "NRRD0002\ntype: uint8\ndimension: 3\nsizes: 2 3 1\nencoding: raw\ncenterings: cell cell "
        "cell\n"
        "datafilez: not data file\n\n"};
    static const unsigned char data[8] = {0, 51, 102, 153, 204, 255, 7, 7};
    unsigned char f[1024];
    size_t i;
    for (i = 0; i < sizeof heads / sizeof heads[0]; i++) {
        pw_volume v;
        pw_err e;
        int k;
        size_t n = make_file(f, sizeof f, heads[i], data, 6 + (i & 1) * 2);
        int rc = read_mem(f, n, &v, &e);
        CHECKF(rc == PW_OK, "header %lu: %s", (unsigned long)i, e.msg);
        if (rc) continue;
        CHECK(v.c == 1 && v.x == 2 && v.y == 3 && v.z == 1);
        for (k = 0; k < 6; k++) CHECK(v.px[k] == (float)data[k] / 255.0f);
        pw_volume_free(NULL, &v);
    }
}

/* dimension 3 with a colour first axis is a 2D colour image; without, a
 * gray volume; dimension 2 is a gray image. */
static void t_read_kinds_and_dims(void)
{
    static const unsigned char d[12] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
    unsigned char f[512];
    pw_volume v;
    pw_err e;
    size_t n = make_file(f, sizeof f,
                         "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 3 2 2\nkinds: RGB-color "
                         "domain domain\nencoding: raw\n\n",
                         d, 12);
    REQUIRE(read_mem(f, n, &v, &e) == PW_OK);
    CHECK(v.c == 3 && v.x == 2 && v.y == 2 && v.z == 1);
    CHECK(v.px[11] == 12.0f / 255.0f);
    pw_volume_free(NULL, &v);
    n = make_file(f, sizeof f,
                  "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 3 2 2\nkinds: space space "
                  "space\nencoding: raw\n\n",
                  d, 12);
    REQUIRE(read_mem(f, n, &v, &e) == PW_OK);
    CHECK(v.c == 1 && v.x == 3 && v.y == 2 && v.z == 2);
    pw_volume_free(NULL, &v);
    n = make_file(f, sizeof f, "NRRD0004\ntype: uchar\ndimension: 2\nsizes: 4 3\nencoding: raw\n\n",
                  d, 12);
    REQUIRE(read_mem(f, n, &v, &e) == PW_OK);
    CHECK(v.c == 1 && v.x == 4 && v.y == 3 && v.z == 1);
    CHECK(v.px[4] == 5.0f / 255.0f);
    pw_volume_free(NULL, &v);
}

/* ---- gzip ---- */

static void check_payload(const pw_volume *v, const char *what)
{
    int i;
    REQUIRE(v->c == 3 && v->x == 8 && v->y == 4 && v->z == 2);
    for (i = 0; i < 192; i++)
        if (v->px[i] != (float)payload_byte(i) / 255.0f) {
            CHECKF(0, "%s: sample %d is %g, expected %d/255", what, i, v->px[i], payload_byte(i));
            return;
        }
}

/* The Python-made members, through the NRRD reader and directly. */
static void t_gzip_python(void)
{
    static const struct {
        const unsigned char *d;
        size_t n;
        const char *name;
    } gz[4] = {{gz_plain, sizeof gz_plain, "plain"},
               {gz_fname, sizeof gz_fname, "fname"},
               {gz_flags, sizeof gz_flags, "flags"},
               {gz_two, sizeof gz_two, "two members"}};
    static const char head[] =
        "NRRD0005\ntype: uint8\ndimension: 4\nsizes: 3 8 4 2\nencoding: gzip\n\n";
    unsigned char f[1024], *out;
    size_t i, outn;
    int k;
    for (i = 0; i < 4; i++) {
        pw_volume v;
        pw_err e;
        size_t n = make_file(f, sizeof f, head, gz[i].d, gz[i].n);
        pw_err_clear(&e);
        CHECKF(gunzip(gz[i].d, gz[i].n, 1000, &out, &outn, &e) == PW_OK, "%s: %s",
               gz[i].name, e.msg);
        CHECK_EQ_INT(outn, 192);
        for (k = 0; k < 192 && k < (int)outn; k++) CHECK(out[k] == payload_byte(k));
        free(out);
        CHECKF(read_mem(f, n, &v, &e) == PW_OK, "%s: %s", gz[i].name, e.msg);
        if (v.px) check_payload(&v, gz[i].name);
        pw_volume_free(NULL, &v);
    }
    /* "gz" names the same encoding */
    {
        pw_volume v;
        pw_err e;
        size_t n = make_file(
            f, sizeof f, "NRRD0004\ntype: uint8\ndimension: 4\nsizes: 3 8 4 2\nencoding: gz\n\n",
            gz_plain, sizeof gz_plain);
        REQUIRE(read_mem(f, n, &v, &e) == PW_OK);
        check_payload(&v, "gz");
        pw_volume_free(NULL, &v);
    }
}

/* Expects pw_gzip_decompress to fail on d with `code` and `what`. */
static void gz_fail(const unsigned char *d, size_t n, int code, const char *what, int line)
{
    unsigned char *out = (unsigned char *)1;
    size_t outn = 1;
    pw_err e;
    int rc;
    pw_err_clear(&e);
    rc = gunzip(d, n, 1000, &out, &outn, &e);
    if (rc != code || !strstr(e.msg, what))
        pwt_fail_(__FILE__, line, "got %d '%s', expected %d '%s'", rc, e.msg, code, what);
    if (rc == PW_OK)
        free(out);
    else if (out || outn)
        pwt_fail_(__FILE__, line, "failure left output behind");
}

static void t_gzip_errors(void)
{
    unsigned char d[512];
    size_t n = sizeof gz_plain, nf = sizeof gz_flags;
    memcpy(d, gz_plain, n);
    d[n - 8] ^= 1;
    gz_fail(d, n, PW_ERR_PARSE, "CRC-32 mismatch", __LINE__);
    memcpy(d, gz_plain, n);
    d[n - 4] ^= 1;
    gz_fail(d, n, PW_ERR_PARSE, "its trailer says", __LINE__);
    gz_fail(gz_plain, n - 3, PW_ERR_PARSE, "truncated", __LINE__);
    gz_fail(gz_plain, n - 60, PW_ERR_PARSE, "truncated", __LINE__);
    gz_fail(gz_plain, 12, PW_ERR_PARSE, "truncated", __LINE__);
    gz_fail(gz_plain, 0, PW_ERR_PARSE, "truncated", __LINE__);
    memcpy(d, gz_plain, n);
    memcpy(d + n, "xyz", 3);
    gz_fail(d, n + 3, PW_ERR_PARSE, "3 bytes of garbage after member 1", __LINE__);
    memcpy(d, gz_plain, n);
    d[0] = 0x1e;
    gz_fail(d, n, PW_ERR_PARSE, "bad magic", __LINE__);
    memcpy(d, gz_plain, n);
    d[2] = 7;
    gz_fail(d, n, PW_ERR_UNSUPPORTED, "compression method 7", __LINE__);
    memcpy(d, gz_plain, n);
    d[3] = 0x20;
    gz_fail(d, n, PW_ERR_PARSE, "reserved flag", __LINE__);
    memcpy(d, gz_flags, nf);
    d[12] ^= 1; /* inside the extra field: the header CRC no longer matches */
    gz_fail(d, nf, PW_ERR_PARSE, "header CRC mismatch", __LINE__);
    memcpy(d, gz_flags, nf);
    d[10] = 0xff; /* extra field longer than the input */
    gz_fail(d, nf, PW_ERR_PARSE, "truncated (extra field)", __LINE__);
    memcpy(d, gz_fname, 20); /* FNAME set, no terminating NUL in reach */
    memset(d + 10, 'a', 10);
    gz_fail(d, 20, PW_ERR_PARSE, "truncated (file name)", __LINE__);
    memcpy(d, gz_plain, n); /* a corrupt deflate block type */
    d[10] |= 6;
    gz_fail(d, n, PW_ERR_PARSE, "deflate data", __LINE__);
    {
        unsigned char *out;
        size_t outn;
        pw_err e;
        pw_err_clear(&e);
        CHECK(gunzip(gz_plain, n, 191, &out, &outn, &e) == PW_ERR_LIMIT);
        CHECK(out == NULL);
        pw_err_clear(&e);
        CHECK(gunzip(gz_two, sizeof gz_two, 150, &out, &outn, &e) ==
              PW_ERR_LIMIT);
        CHECK(out == NULL);
    }
}

/* Our own gzip members: header bytes and a round trip through our reader
 * (the Python-made members above check the reader independently). */
static void t_gzip_own(void)
{
    unsigned char data[5000], *z, *back;
    size_t zn, bn, i;
    pw_err e;
    int level;
    for (i = 0; i < sizeof data; i++) data[i] = (unsigned char)((i * i) >> 5);
    for (level = -1; level <= 9; level += 5) {
        pw_err_clear(&e);
        REQUIRE(gzip_mem(data, sizeof data, level, &z, &zn, &e) == PW_OK);
        CHECK(zn > 18 && z[0] == 0x1f && z[1] == 0x8b && z[2] == 8 && z[3] == 0 && z[9] == 255);
        CHECK(z[zn - 4] == (sizeof data & 255) && z[zn - 3] == (sizeof data >> 8));
        REQUIRE(gunzip(z, zn, sizeof data, &back, &bn, &e) == PW_OK);
        CHECK(bn == sizeof data && memcmp(back, data, bn) == 0);
        free(z);
        free(back);
    }
    REQUIRE(gzip_mem(data, 0, 6, &z, &zn, &e) == PW_OK);
    REQUIRE(gunzip(z, zn, 0, &back, &bn, &e) == PW_OK);
    CHECK(bn == 0);
    free(z);
    free(back);
}

/* gzip data that does not match the header's sizes. */
static void t_gzip_size_mismatch(void)
{
    unsigned char f[1024];
    size_t n = make_file(f, sizeof f,
                         "NRRD0004\ntype: uint8\ndimension: 4\nsizes: 3 8 4 1\nencoding: gzip\n\n",
                         gz_plain, sizeof gz_plain);
    expect_fail(f, n, PW_ERR_PARSE, "t.nrrd:6: the gzip data holds more than the 96 bytes",
                __LINE__);
    n = make_file(f, sizeof f,
                  "NRRD0004\ntype: uint8\ndimension: 4\nsizes: 3 8 4 3\nencoding: gzip\n\n",
                  gz_plain, sizeof gz_plain);
    expect_fail(f, n, PW_ERR_PARSE, "t.nrrd:6: data truncated: 288 bytes needed, 192 present",
                __LINE__);
    n = make_file(f, sizeof f,
                  "NRRD0004\ntype: uint8\ndimension: 4\nsizes: 3 8 4 2\nencoding: gzip\n\n",
                  gz_plain, sizeof gz_plain - 1);
    expect_fail(f, n, PW_ERR_PARSE, "t.nrrd:6: gzip data truncated", __LINE__);
    n = make_file(f, sizeof f,
                  "NRRD0004\ntype: uint8\ndimension: 4\nsizes: 3 8 4 2\nencoding: gzip\n\n",
                  gz_plain + 1, sizeof gz_plain - 1);
    expect_fail(f, n, PW_ERR_PARSE, "t.nrrd:6: not gzip data", __LINE__);
}

/* ---- malformed input ---- */

#define HDR3 "type: uint8\ndimension: 3\nsizes: 2 1 1\n"

static void t_malformed(void)
{
    EXPECT_FAIL("", PW_ERR_PARSE, "not a NRRD file");
    EXPECT_FAIL("P5\n1 1\n255\nx", PW_ERR_PARSE, "not a NRRD file");
    EXPECT_FAIL("NRRD0009\n" HDR3 "encoding: raw\n\nab", PW_ERR_UNSUPPORTED, "format version 9");
    EXPECT_FAIL("NRRD0004 extra\n" HDR3 "encoding: raw\n\nab", PW_ERR_PARSE, "t.nrrd:1: the magic");
    EXPECT_FAIL("NRRD0004", PW_ERR_PARSE, "t.nrrd:1: the magic");
    /* types */
    EXPECT_FAIL("NRRD0004\ntype: double\ndimension: 3\nsizes: 1 1 1\nendian: little\nencoding: "
                "raw\n\n12345678",
                PW_ERR_UNSUPPORTED,
                "t.nrrd:2: type is not supported (uchar, ushort or float): 'double'");
    EXPECT_FAIL("NRRD0004\ntype: signed short\ndimension: 3\nsizes: 1 1 1\nencoding: raw\n\nab",
                PW_ERR_UNSUPPORTED, "'signed short'");
    EXPECT_FAIL("NRRD0004\ntype: int\ndimension: 3\nsizes: 1 1 1\nencoding: raw\n\nabcd",
                PW_ERR_UNSUPPORTED, "'int'");
    EXPECT_FAIL("NRRD0004\ntype: block\ndimension: 3\nsizes: 1 1 1\nencoding: raw\n\nabcd",
                PW_ERR_UNSUPPORTED, "'block'");
    EXPECT_FAIL("NRRD0004\ntype: uint9\ndimension: 3\nsizes: 1 1 1\nencoding: raw\n\nab",
                PW_ERR_PARSE, "t.nrrd:2: unknown type 'uint9'");
    EXPECT_FAIL("NRRD0004\ntype:\ndimension: 3\nsizes: 1 1 1\nencoding: raw\n\nab", PW_ERR_PARSE,
                "t.nrrd:2: expected 'field: value'");
    /* dimension */
    EXPECT_FAIL("NRRD0004\ntype: uint8\ndimension: 5\nsizes: 1 1 1 1 1\nencoding: raw\n\nab",
                PW_ERR_UNSUPPORTED, "t.nrrd:3: dimension 5 is not supported");
    EXPECT_FAIL("NRRD0004\ntype: uint8\ndimension: 1\nsizes: 1\nencoding: raw\n\nab",
                PW_ERR_UNSUPPORTED, "dimension 1 is not supported");
    EXPECT_FAIL("NRRD0004\ntype: uint8\ndimension: three\nsizes: 1 1 1\nencoding: raw\n\nab",
                PW_ERR_PARSE, "t.nrrd:3: bad dimension 'three'");
    EXPECT_FAIL("NRRD0004\ntype: uint8\ndimension: 0\nsizes: 1 1 1\nencoding: raw\n\nab",
                PW_ERR_PARSE, "t.nrrd:3: bad dimension (1 to 16)");
    /* sizes */
    EXPECT_FAIL("NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 1\nencoding: raw\n\nab",
                PW_ERR_PARSE, "t.nrrd:4: sizes has 2 values, dimension says 3");
    EXPECT_FAIL("NRRD0004\ntype: uint8\ndimension: 4\nsizes: 1 2 1 1 1\nencoding: raw\n\nab",
                PW_ERR_PARSE, "t.nrrd:4: sizes has 5 values, dimension says 4");
    EXPECT_FAIL("NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 x 1\nencoding: raw\n\nab",
                PW_ERR_PARSE, "t.nrrd:4: bad size (a positive integer is needed): 'x'");
    EXPECT_FAIL("NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 0 1\nencoding: raw\n\nab",
                PW_ERR_PARSE, "t.nrrd:4: bad size (a positive integer is needed): '0'");
    EXPECT_FAIL("NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 -1 1\nencoding: raw\n\nab",
                PW_ERR_PARSE, "bad size");
    EXPECT_FAIL("NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 1.5 1\nencoding: raw\n\nab",
                PW_ERR_PARSE, "bad size");
    EXPECT_FAIL("NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 99999999999999999999 1\nencoding: "
                "raw\n\nab",
                PW_ERR_LIMIT, "t.nrrd:4: size is too large");
    EXPECT_FAIL(
        "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 "
        "17\nencoding: raw\n\nab",
        PW_ERR_PARSE, "t.nrrd:4: more than 16 sizes");
    EXPECT_FAIL("NRRD0004\ntype: uint8\ndimension: 4\nsizes: 5 1 1 1\nencoding: raw\n\nabcde",
                PW_ERR_UNSUPPORTED, "t.nrrd:4: 5 channels (the first size) are not supported");
    EXPECT_FAIL("NRRD0004\ntype: uint8\ndimension: 3\nsizes: 3000 3000 3000\nencoding: raw\n\nab",
                PW_ERR_LIMIT, "exceeds the limit");
    /* encoding and endian */
    EXPECT_FAIL("NRRD0004\n" HDR3 "encoding: bzip2\n\nab", PW_ERR_UNSUPPORTED,
                "t.nrrd:5: encoding is not supported (raw or gzip): 'bzip2'");
    EXPECT_FAIL("NRRD0004\n" HDR3 "encoding: ascii\n\n1 2", PW_ERR_UNSUPPORTED, "'ascii'");
    EXPECT_FAIL("NRRD0004\n" HDR3 "encoding: zip\n\nab", PW_ERR_PARSE,
                "t.nrrd:5: unknown encoding 'zip'");
    EXPECT_FAIL("NRRD0004\ntype: ushort\ndimension: 3\nsizes: 2 1 1\nencoding: raw\n\nabcd",
                PW_ERR_PARSE, "t.nrrd:6: the header lacks the 'endian' field (needed for 16-bit");
    EXPECT_FAIL("NRRD0004\ntype: float\ndimension: 3\nsizes: 1 1 1\nencoding: raw\n\nabcd",
                PW_ERR_PARSE, "lacks the 'endian' field (needed for float");
    EXPECT_FAIL("NRRD0004\n" HDR3 "endian: middle\nencoding: raw\n\nab", PW_ERR_PARSE,
                "t.nrrd:5: bad endian (little or big): 'middle'");
    /* detached data, skips */
    EXPECT_FAIL("NRRD0004\n" HDR3 "encoding: raw\ndata file: vol.raw\n\n", PW_ERR_UNSUPPORTED,
                "t.nrrd:6: detached data is not supported");
    EXPECT_FAIL("NRRD0004\n" HDR3 "encoding: raw\ndatafile: vol.raw\n", PW_ERR_UNSUPPORTED,
                "data file 'vol.raw'");
    EXPECT_FAIL("NRRD0004\n" HDR3 "encoding: raw\nline skip: 2\n\nab", PW_ERR_UNSUPPORTED,
                "t.nrrd:6: line skip 2 is not supported");
    EXPECT_FAIL("NRRD0004\n" HDR3 "encoding: raw\nbyte skip: -1\n\nab", PW_ERR_UNSUPPORTED,
                "t.nrrd:6: byte skip -1 is not supported");
    EXPECT_FAIL("NRRD0004\n" HDR3 "encoding: raw\nbyteskip: 1k\n\nab", PW_ERR_PARSE,
                "t.nrrd:6: bad byte skip '1k'");
    /* duplicates, missing fields, header structure */
    EXPECT_FAIL("NRRD0004\n" HDR3 "encoding: raw\ntype: uint8\n\nab", PW_ERR_PARSE,
                "t.nrrd:6: duplicate field 'type' (first given on line 2)");
    EXPECT_FAIL("NRRD0004\n" HDR3 "encoding: raw\nspacings: 1 1 1\nspacings: 1 1 1\n\nab",
                PW_ERR_PARSE, "t.nrrd:7: duplicate field 'spacings' (first given on line 6)");
    EXPECT_FAIL("NRRD0004\n" HDR3 "encoding: raw\nline skip: 0\nlineskip: 0\n\nab", PW_ERR_PARSE,
                "duplicate field 'lineskip'");
    EXPECT_FAIL("NRRD0004\ndimension: 3\nsizes: 2 1 1\nencoding: raw\n\nab", PW_ERR_PARSE,
                "t.nrrd:5: the header lacks the required 'type' field");
    EXPECT_FAIL("NRRD0004\ntype: uint8\nsizes: 2 1 1\nencoding: raw\n\nab", PW_ERR_PARSE,
                "lacks the required 'dimension' field");
    EXPECT_FAIL("NRRD0004\ntype: uint8\ndimension: 3\nencoding: raw\n\nab", PW_ERR_PARSE,
                "lacks the required 'sizes' field");
    EXPECT_FAIL("NRRD0004\n" HDR3 "\nab", PW_ERR_PARSE,
                "t.nrrd:5: the header lacks the required 'encoding' field");
    EXPECT_FAIL("NRRD0004\n" HDR3 "encoding: raw\n", PW_ERR_PARSE,
                "t.nrrd:6: the header does not end with an empty line");
    EXPECT_FAIL("NRRD0004\n" HDR3 "encoding: raw", PW_ERR_PARSE,
                "t.nrrd:5: the header does not end with an empty line");
    EXPECT_FAIL("NRRD0004\n" HDR3 "encoding raw\n\nab", PW_ERR_PARSE,
                "t.nrrd:5: expected 'field: value' or 'key:=value', found 'encoding raw'");
    EXPECT_FAIL("NRRD0004\n" HDR3 ": raw\n\nab", PW_ERR_PARSE, "t.nrrd:5: expected 'field: value'");
    EXPECT_FAIL("NRRD0004\n" HDR3 "encoding: raw\x00\n\nab", PW_ERR_PARSE, "t.nrrd:5: NUL byte");
    /* data */
    EXPECT_FAIL("NRRD0004\n" HDR3 "encoding: raw\n\na", PW_ERR_PARSE,
                "t.nrrd:6: data truncated: 2 bytes needed, 1 present");
    EXPECT_FAIL("NRRD0004\n" HDR3 "encoding: raw\n\n", PW_ERR_PARSE,
                "t.nrrd:6: data truncated: 2 bytes needed, 0 present");
    EXPECT_FAIL("NRRD0004\ntype: ushort\ndimension: 3\nsizes: 2 1 1\nendian: big\nencoding: "
                "raw\n\nabc",
                PW_ERR_PARSE, "4 bytes needed, 3 present");
    EXPECT_FAIL("NRRD0004\ntype: float\ndimension: 3\nsizes: 2 1 1\nendian: big\nencoding: "
                "raw\n\n\x3f\x80\x00\x00\x7f\xc0\x00\x00",
                PW_ERR_PARSE, "t.nrrd:7: float sample 1 is NaN");
    EXPECT_FAIL("NRRD0004\ntype: float\ndimension: 3\nsizes: 2 1 1\nendian: little\nencoding: "
                "raw\n\n\x00\x00\x80\xff\x00\x00\x80\x3f",
                PW_ERR_PARSE, "float sample 0 is infinite");
}

/* Sizes beyond the limit or beyond the data are refused before anything is
 * allocated. */
static void t_limits_no_alloc(void)
{
    static const char *const heads[] = {
        "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 100000 100000 100000\nencoding: raw\n\nab",
        "NRRD0004\ntype: float\ndimension: 4\nsizes: 4 65536 65536 65536\nendian: big\nencoding: "
        "raw\n\nab",
        "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4294967296 4294967296 1\nencoding: raw\n\nab",
        "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 1000 1000 100\nencoding: raw\n\nab",
        "NRRD0004\ntype: float\ndimension: 4\nsizes: 4 1000 1000 100\nendian: big\nencoding: "
        "raw\n\nab"};
    pwt_alloc_state counts = {0, 0, -1};
    pw_alloc counting = {pwt_malloc, pwt_realloc, pwt_free, &counts};
    size_t i;
    for (i = 0; i < sizeof heads / sizeof heads[0]; i++) {
        pw_volume v;
        pw_err e;
        int rc;
        counts.calls = 0;
        pw_err_clear(&e);
        rc = pw_nrrd_read_memory(&counting, (const unsigned char *)heads[i], strlen(heads[i]),
                                 "big", &v, &e);
        CHECKF(rc == (i < 3 ? PW_ERR_LIMIT : PW_ERR_PARSE), "header %lu: rc %d (%s)",
               (unsigned long)i, rc, e.msg);
        CHECKF(counts.calls == 0, "header %lu allocated", (unsigned long)i);
        CHECK(v.px == NULL);
    }
}

/* Every allocation failing in turn: NOMEM or success, and nothing leaks. */
static void t_alloc_failures(void)
{
    unsigned char f[1024];
    size_t n = make_file(f, sizeof f,
                         "NRRD0004\ntype: uint8\ndimension: 4\nsizes: 3 8 4 2\nencoding: gzip\n\n",
                         gz_two, sizeof gz_two);
    long k;
    int ok = 0;
    for (k = 0; k < 40; k++) {
        pwt_alloc_state st = {0, 0, -1};
        pw_alloc al = {pwt_malloc, pwt_realloc, pwt_free, &st};
        pw_volume v, w;
        pw_buf buf;
        pw_err e;
        int rc;
        st.fail_after = k;
        pw_err_clear(&e);
        rc = pw_nrrd_read_memory(&al, f, n, "t.nrrd", &v, &e);
        CHECKF(rc == PW_OK || rc == PW_ERR_NOMEM, "k=%ld: rc %d %s", k, rc, e.msg);
        if (rc == PW_OK) {
            check_payload(&v, "alloc");
            memset(&buf, 0, sizeof buf);
            pw_err_clear(&e);
            rc = pw_nrrd_write(&al, &v, 1, pw_buf_write, &buf, &e);
            CHECKF(rc == PW_OK || rc == PW_ERR_NOMEM, "write k=%ld: rc %d %s", k, rc, e.msg);
            if (rc == PW_OK) {
                pw_err_clear(&e);
                rc = pw_nrrd_read_memory(&al, buf.data, buf.size, "t.nrrd", &w, &e);
                CHECK(rc == PW_OK || rc == PW_ERR_NOMEM);
                if (rc == PW_OK) {
                    ok++;
                    CHECK(memcmp(v.px, w.px, 192 * sizeof(float)) == 0);
                }
                pw_volume_free(&al, &w);
            }
            free(buf.data);
            pw_volume_free(&al, &v);
        } else {
            CHECK(v.px == NULL);
        }
        CHECKF(st.live == 0, "k=%ld: %ld blocks leaked", k, st.live);
    }
    CHECK(ok > 0);
}

/* ---- volumes ---- */

static void t_volume_image(void)
{
    pw_image img, back;
    pw_volume v;
    pw_err e;
    int i;
    REQUIRE(pw_image_alloc(NULL, &img, 4, 3, 2, NULL) == PW_OK);
    for (i = 0; i < 24; i++) img.px[i] = (float)i / 23.0f;
    pw_err_clear(&e);
    REQUIRE(pw_volume_from_image(NULL, &img, &v, &e) == PW_OK);
    CHECK(v.c == 2 && v.x == 4 && v.y == 3 && v.z == 1);
    CHECK(memcmp(v.px, img.px, 24 * sizeof(float)) == 0);
    REQUIRE(pw_volume_slice(NULL, &v, 0, &back, &e) == PW_OK);
    CHECK(back.w == 4 && back.h == 3 && back.c == 2);
    CHECK(memcmp(back.px, img.px, 24 * sizeof(float)) == 0);
    pw_image_free(NULL, &back);
    CHECK(pw_volume_slice(NULL, &v, 1, &back, &e) == PW_ERR_INVALID && back.px == NULL);
    CHECK(strstr(e.msg, "slice 1") != NULL);
    pw_volume_free(NULL, &v);
    pw_image_free(NULL, &img);
    /* slices of a deeper volume: slice k holds samples k*n .. (k+1)*n - 1 */
    make_volume(&v, 3, 2, 2, 3, 5);
    for (i = 0; i < 3; i++) {
        REQUIRE(pw_volume_slice(NULL, &v, i, &back, NULL) == PW_OK);
        CHECK(memcmp(back.px, v.px + 12 * i, 12 * sizeof(float)) == 0);
        pw_image_free(NULL, &back);
    }
    pw_volume_free(NULL, &v);
    pw_err_clear(&e);
    CHECK(pw_volume_alloc(NULL, &v, 0, 1, 1, 1, &e) == PW_ERR_INVALID && v.px == NULL);
    pw_err_clear(&e);
    CHECK(pw_volume_alloc(NULL, &v, 1, 65536, 65536, 65536, &e) == PW_ERR_LIMIT && v.px == NULL);
    memset(&img, 0, sizeof img);
    pw_err_clear(&e);
    CHECK(pw_volume_from_image(NULL, &img, &v, &e) == PW_ERR_INVALID && v.px == NULL);
}

static void t_file_io(void)
{
    const char *path = pwt_tmp("nrrd", 0, ".nrrd");
    pw_volume a, b;
    pw_err e;
    make_volume(&a, 4, 6, 5, 3, 9);
    pw_err_clear(&e);
    REQUIRE(pw_nrrd_save(NULL, &a, 1, path, &e) == PW_OK);
    REQUIRE(pw_nrrd_load(NULL, path, &b, &e) == PW_OK);
    CHECK(b.c == 4 && b.x == 6 && b.y == 5 && b.z == 3);
    CHECK(memcmp(a.px, b.px, (size_t)4 * 6 * 5 * 3 * sizeof(float)) == 0);
    pw_volume_free(NULL, &b);
    remove(path);
    pw_err_clear(&e);
    CHECK(pw_nrrd_load(NULL, path, &b, &e) == PW_ERR_IO && b.px == NULL);
    CHECK(strstr(e.msg, path) != NULL);
    pw_err_clear(&e);
    CHECK(pw_nrrd_save(NULL, &a, 0, "/nonexistent-dir/x.nrrd", &e) == PW_ERR_IO);
    pw_volume_free(NULL, &a);
}

static const pwt_case cases[] = {
    {"nrrd_roundtrip_u8", t_roundtrip_u8},
    {"nrrd_write_exact_bytes", t_write_exact_bytes},
    {"nrrd_write_nan", t_write_nan},
    {"nrrd_write_errors", t_write_errors},
    {"nrrd_read_u16_endian", t_read_u16_endian},
    {"nrrd_read_float_endian", t_read_float_endian},
    {"nrrd_read_header_variants", t_read_header_variants},
    {"nrrd_read_kinds_and_dims", t_read_kinds_and_dims},
    {"nrrd_gzip_python", t_gzip_python},
    {"nrrd_gzip_errors", t_gzip_errors},
    {"nrrd_gzip_own", t_gzip_own},
    {"nrrd_gzip_size_mismatch", t_gzip_size_mismatch},
    {"nrrd_malformed", t_malformed},
    {"nrrd_limits_no_alloc", t_limits_no_alloc},
    {"nrrd_alloc_failures", t_alloc_failures},
    {"nrrd_volume_image", t_volume_image},
    {"nrrd_file_io", t_file_io},
};
PWT_MAIN(cases)
