/* libFuzzer target for the NRRD reader (src/common/nrrd.h), the gzip code
 * under it and the material-space tile sampler (src/pgp/tile3.h) over what it reads.
 *
 * Each input is used four ways:
 *   1. as a NRRD file, as given;
 *   2. as the recipe of a synthetic NRRD: the first bytes pick the type,
 *      dimension, sizes, endian, kinds and encoding of a well-formed header,
 *      the rest becomes the samples (gzip-compressed by our own encoder when
 *      the recipe says so), so that the sample conversion, the NaN checks
 *      and the gzip member parsing are reached despite the CRC-32;
 *   3. as a gzip stream for pw_gzip_decompress;
 *   4. as data for a gzip compress/decompress round trip.
 * Volumes that read are checked (shape, finite samples), written back as
 * uint8 NRRD (raw and gzip) and read again: any difference aborts. Small
 * ones become a pw_tile3 that is sampled at a few points: the samples must
 * be finite and in [0, 1].
 *
 * Build: clang -g -O1 -fsanitize=fuzzer,address,undefined -I. fuzz/fuzz_nrrd.c -lm */
#define PW_MAX_VOLUME_VOXELS (1 << 20) /* keeps memory within the fuzzer's limits */
#include "../src/pgp/tile3.h"
#include <stdlib.h>

/* uint8 round trip: the samples quantised to bytes must come back. */
static void roundtrip(const pw_volume *v, int gzip)
{
    pw_buf b;
    pw_volume back;
    pw_err e;
    size_t i, n = (size_t)v->c * v->x * v->y * v->z;
    memset(&b, 0, sizeof b);
    pw_err_clear(&e);
    if (pw_nrrd_write(NULL, v, gzip, pw_buf_write, &b, &e)) abort();
    if (pw_nrrd_read_memory(NULL, b.data, b.size, "roundtrip", &back, &e)) abort();
    if (back.c != v->c || back.x != v->x || back.y != v->y || back.z != v->z) abort();
    for (i = 0; i < n; i++)
        if (pw_image_quantize(back.px[i], 255) != pw_image_quantize(v->px[i], 255)) abort();
    pw_volume_free(NULL, &back);
    free(b.data);
}

static void sample_tile(const pw_volume *v, const unsigned char *d, size_t n)
{
    pw_tile3 t;
    pw_err e;
    size_t i;
    int k;
    pw_err_clear(&e);
    if (pw_tile3_create(NULL, &t, v, 0, &e)) abort();
    for (i = 0; i + 4 <= n && i < 64; i += 4) {
        float out[4];
        pw_tile3_sample(&t, (float)d[i] / 37.0f - 3.0f, (float)d[i + 1] / 29.0f - 4.0f,
                        (float)d[i + 2] / 200.0f - 0.1f, (float)d[i + 3] / 25.0f - 1.0f, out);
        for (k = 0; k < 4; k++)
            if (!(out[k] >= 0.0f && out[k] <= 1.0f)) abort();
    }
    pw_tile3_free(NULL, &t);
}

static void read_and_check(const unsigned char *data, size_t size)
{
    pw_volume v;
    pw_err e;
    pw_err_clear(&e);
    if (pw_nrrd_read_memory(NULL, data, size, "fuzz", &v, &e) == PW_OK) {
        size_t i, n;
        if (!v.px || v.c < 1 || v.c > 4 || v.x < 1 || v.y < 1 || v.z < 1) abort();
        n = (size_t)v.c * v.x * v.y * v.z;
        for (i = 0; i < n; i++)
            if (!pw_is_finite(v.px[i])) abort();
        if (n <= 4096) {
            roundtrip(&v, 0);
            roundtrip(&v, 1);
            sample_tile(&v, data, size);
        }
        pw_volume_free(NULL, &v);
    } else if (v.px || !e.msg[0] || e.code == PW_OK) {
        abort(); /* a failure leaves no volume and always explains itself */
    }
}

/* A well-formed NRRD built from the input: 8 recipe bytes, then samples. */
static void synth_nrrd(const unsigned char *d, size_t n)
{
    static const char *const types[3] = {"uchar", "ushort", "float"};
    static const int bytes[3] = {1, 2, 4};
    pw_buf b;
    char head[256];
    const unsigned char *body = d + 8;
    unsigned char *raw;
    size_t bn, need, i;
    int ty, dim, c, x, y, z, gz, k;
    if (n < 8) return;
    bn = n - 8;
    ty = d[0] % 3;
    dim = 2 + d[1] % 3;
    c = 1 + d[2] % 4;
    x = 1 + d[3] % 16;
    y = 1 + d[4] % 16;
    z = 1 + d[5] % 8;
    gz = d[6] & 1;
    if (dim == 2) c = z = 1;
    if (dim == 3 && !(d[6] & 2)) c = 1; /* gray volume; else 2D colour via kinds */
    if (dim == 3 && c > 1) z = 1;
    need = (size_t)c * x * y * z * bytes[ty];
    if (d[7] & 0x80) need -= need > 2 ? d[7] % 3u : 0; /* sometimes short */
    if (dim == 2)
        k = snprintf(head, sizeof head, "NRRD0004\ntype: %s\ndimension: 2\nsizes: %d %d\n",
                     types[ty], x, y);
    else if (dim == 3 && c > 1)
        k = snprintf(head, sizeof head,
                     "NRRD0004\ntype: %s\ndimension: 3\nsizes: %d %d %d\nkinds: RGB-color domain "
                     "domain\n",
                     types[ty], c, x, y);
    else if (dim == 3)
        k = snprintf(head, sizeof head, "NRRD0004\ntype: %s\ndimension: 3\nsizes: %d %d %d\n",
                     types[ty], x, y, z);
    else
        k = snprintf(head, sizeof head, "NRRD0004\ntype: %s\ndimension: 4\nsizes: %d %d %d %d\n",
                     types[ty], c, x, y, z);
    k += snprintf(head + k, sizeof head - (size_t)k, "%sencoding: %s\n\n",
                  ty ? (d[7] & 1 ? "endian: big\n" : "endian: little\n") : "", gz ? "gzip" : "raw");
    raw = (unsigned char *)malloc(need + 1);
    for (i = 0; i < need; i++) raw[i] = bn ? body[i % bn] : (unsigned char)i;
    if (ty == 2 && !(d[7] & 0x40)) /* mostly finite floats: clear the top exponent bit */
        for (i = 0; i + 4 <= need; i += 4) raw[i + ((d[7] & 1) ? 0 : 3)] &= 0xbf;
    memset(&b, 0, sizeof b);
    pw_buf_write(&b, head, (size_t)k);
    if (gz) {
        pw_buf z8;
        pw_err e;
        pw_err_clear(&e);
        if (pw_gzip_compress(NULL, raw, need, d[7] % 10, &z8, &e)) abort();
        pw_buf_write(&b, z8.data, z8.size);
        free(z8.data);
    } else {
        pw_buf_write(&b, raw, need);
    }
    read_and_check(b.data, b.size);
    free(b.data);
    free(raw);
}

/* gzip round trip of the input at a level it chooses. */
static void gzip_roundtrip(const unsigned char *data, size_t size)
{
    pw_buf z, back;
    pw_err e;
    pw_err_clear(&e);
    if (pw_gzip_compress(NULL, data, size, size ? data[0] % 10 : 6, &z, &e)) abort();
    if (pw_gzip_decompress(NULL, z.data, z.size, size, &back, &e)) abort();
    if (back.size != size || (size && memcmp(back.data, data, size))) abort();
    free(z.data);
    free(back.data);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    pw_buf out;
    pw_err e;
    read_and_check(data, size);
    synth_nrrd(data, size);
    pw_err_clear(&e);
    if (pw_gzip_decompress(NULL, data, size, 1 << 20, &out, &e) == PW_OK) free(out.data);
    if (size <= 4096) gzip_roundtrip(data, size);
    return 0;
}
