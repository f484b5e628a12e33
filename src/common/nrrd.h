/* nrrd: volumes and the NRRD file format, with gzip streams.
 *
 * A pw_volume holds x*y*z voxels of c channels (1 to 4, as pw_image: gray,
 * gray+alpha, RGB, RGBA) as floats, normally in [0,1]. Samples are
 * interleaved by channel, x varies fastest, then y, then z:
 * px[((z*y_size + y)*x_size + x)*c + k]. Each z slice reads like a pw_image
 * (x = column, y = row with row 0 at the top, i.e. first in the file).
 * Two uses in patchwork:
 *   material-space tiles (pgp.h): sizes C W H M, W x H texels per layer and
 *     M layers along the material axis (a plain 2D texture is M = 1);
 *   solid exemplars (lst.h): sizes C X Y Z, or X Y Z for gray.
 *
 * NRRD ("nearly raw raster data", Teem; teem.sourceforge.net/nrrd) is a
 * text header followed by the samples. Reader (pw_nrrd_read_memory):
 *   magic NRRD0001 to NRRD0005; lines end with LF or CR LF; the header ends
 *   at the first empty line and the data follows it in the same file;
 *   `# comments` and `key:=value` lines are skipped; field names and the
 *   values of type, encoding, endian and kinds are case-insensitive;
 *   type: uchar/unsigned char/uint8(_t) (scaled by 1/255), ushort/unsigned
 *     short (int)/uint16(_t) (1/65535), float (as is; NaN and infinities are
 *     refused); other NRRD types are PW_ERR_UNSUPPORTED;
 *   dimension 4: sizes C X Y Z with C in 1..4;
 *   dimension 3: sizes X Y Z, gray -- unless `kinds` names the first axis a
 *     colour or vector axis (RGB-color, RGBA-color, 3-color, vector, ...,
 *     as Teem's unu writes 2D colour images): then sizes C X Y and Z = 1;
 *   dimension 2: sizes X Y, a gray 2D image (Z = 1);
 *   encoding raw or gzip (gz); endian little or big, required for 16-bit
 *     and float samples; line skip and byte skip only 0;
 *   `data file` (detached data) is refused, as are the text, hex and bzip2
 *     encodings (PW_ERR_UNSUPPORTED);
 *   every other field (space, spacings, content, ...) is accepted and
 *   ignored; a field given twice, a missing required field, a bad number,
 *   truncated data or a non-finite float is PW_ERR_PARSE, and the message
 *   starts with "name:line:". Sizes are checked against PW_MAX_VOLUME_VOXELS
 *   (and the data's length, for raw data) before anything is allocated.
 * Writer (pw_nrrd_write): NRRD0004, type uint8 (samples quantised with
 *   pw_image_quantize), dimension 3 (X Y Z) for one channel, 4 (C X Y Z)
 *   otherwise, with kinds, encoding raw or gzip.
 *
 * gzip (RFC 1952): pw_gzip_decompress reads one or more concatenated
 * members (header with any of FEXTRA, FNAME, FCOMMENT, FHCRC, each checked
 * against its CRC-32 and ISIZE); pw_gzip_compress writes one member with
 * MTIME 0 and OS "unknown", so that its output depends only on the input.
 *
 *   pw_volume_alloc, pw_volume_free, pw_volume_from_image, pw_volume_slice
 *   pw_nrrd_read_memory, pw_nrrd_write, pw_nrrd_load, pw_nrrd_save
 *   pw_gzip_compress, pw_gzip_decompress */
#ifndef PW__NRRD_V1
#define PW__NRRD_V1

#include "deflate.h"
#include "image.h"

#ifndef PW_MAX_VOLUME_VOXELS
#define PW_MAX_VOLUME_VOXELS (1 << 28) /* x*y*z of a volume (channels not counted) */
#endif

typedef struct pw_volume {
    int c, x, y, z; /* channels (1-4) and size */
    float *px;      /* c*x*y*z samples, px[((z*y + j)*x + i)*c + k] */
} pw_volume;

/* Refuses zero and over-limit sizes, before anything is multiplied. */
PW__DEF int pw__volume_check_size(const char *name, uint64_t x, uint64_t y, uint64_t z, pw_err *e)
{
    if (x == 0 || y == 0 || z == 0)
        return pw_fail(e, PW_ERR_INVALID, "%s: volume has zero size (%llux%llux%llu)", name, (unsigned long long)x,
                       (unsigned long long)y, (unsigned long long)z);
    if (x > PW_MAX_VOLUME_VOXELS || y > PW_MAX_VOLUME_VOXELS || z > PW_MAX_VOLUME_VOXELS ||
        x * y > (uint64_t)PW_MAX_VOLUME_VOXELS || x * y * z > (uint64_t)PW_MAX_VOLUME_VOXELS)
        return pw_fail(e, PW_ERR_LIMIT, "%s: volume %llux%llux%llu exceeds the limit of %d voxels", name,
                       (unsigned long long)x, (unsigned long long)y, (unsigned long long)z, PW_MAX_VOLUME_VOXELS);
    return PW_OK;
}

/* Allocates a zeroed volume of c channels (1-4) and x*y*z voxels. Free with
 * pw_volume_free(a, vol). */
PW__DEF int pw_volume_alloc(const pw_alloc *a, pw_volume *vol, int c, int x, int y, int z, pw_err *e)
{
    int rc;
    memset(vol, 0, sizeof *vol);
    if (c < 1 || c > 4 || x <= 0 || y <= 0 || z <= 0)
        return pw_fail(e, PW_ERR_INVALID, "invalid volume size %dx%dx%d with %d channels", x, y, z, c);
    if ((rc = pw__volume_check_size("volume", (uint64_t)x, (uint64_t)y, (uint64_t)z, e))) return rc;
    vol->px = (float *)pw_calloc_array(a, (size_t)x * y * z * c, sizeof(float), "volume", e);
    if (!vol->px) return PW_ERR_NOMEM;
    vol->c = c;
    vol->x = x;
    vol->y = y;
    vol->z = z;
    return PW_OK;
}

PW__DEF void pw_volume_free(const pw_alloc *a, pw_volume *vol)
{
    if (!vol) return;
    pw_free(a, vol->px);
    memset(vol, 0, sizeof *vol);
}

/* Checks that vol is a usable volume (for writers and converters). */
PW__DEF int pw__volume_check(const pw_volume *v, pw_err *e)
{
    if (!v || !v->px || v->c < 1 || v->c > 4 || v->x <= 0 || v->y <= 0 || v->z <= 0)
        return pw_fail(e, PW_ERR_INVALID, "invalid volume (%dx%dx%d, %d channels)", v ? v->x : 0, v ? v->y : 0,
                       v ? v->z : 0, v ? v->c : 0);
    return pw__volume_check_size("volume", (uint64_t)v->x, (uint64_t)v->y, (uint64_t)v->z, e);
}

/* A copy of a 2D image as a volume of one slice (x = w, y = h, z = 1, same
 * channels): a plain periodic texture is the one-layer material-space tile. */
PW__DEF int pw_volume_from_image(const pw_alloc *a, const pw_image *img, pw_volume *vol, pw_err *e)
{
    int rc = pw__image_check(img, e);
    memset(vol, 0, sizeof *vol);
    if (rc) return rc;
    if ((rc = pw_volume_alloc(a, vol, img->c, img->w, img->h, 1, e))) return rc;
    memcpy(vol->px, img->px, (size_t)img->w * img->h * img->c * sizeof(float));
    return PW_OK;
}

/* Slice z of a volume as a new image (w = x, h = y, same channels, bits 8).
 * Free with pw_image_free. */
PW__DEF int pw_volume_slice(const pw_alloc *a, const pw_volume *vol, int z, pw_image *img, pw_err *e)
{
    int rc = pw__volume_check(vol, e);
    size_t n;
    memset(img, 0, sizeof *img);
    if (rc) return rc;
    if (z < 0 || z >= vol->z)
        return pw_fail(e, PW_ERR_INVALID, "slice %d is outside the volume (0 to %d)", z, vol->z - 1);
    if ((rc = pw_image_alloc(a, img, vol->x, vol->y, vol->c, e))) return rc;
    n = (size_t)vol->x * vol->y * vol->c;
    memcpy(img->px, vol->px + (size_t)z * n, n * sizeof(float));
    return PW_OK;
}

/* ======================================================================
 * gzip (RFC 1952)
 * ====================================================================== */

PW__DEF uint32_t pw__le32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

PW__DEF void pw__put_le32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)v;
    p[1] = (unsigned char)(v >> 8);
    p[2] = (unsigned char)(v >> 16);
    p[3] = (unsigned char)(v >> 24);
}

/* One gzip member of data[0..n): *hlen receives the length of its header
 * (§2.3.1: fixed part, then FEXTRA, FNAME, FCOMMENT, FHCRC in this order). */
PW__DEF int pw__gzip_header(const unsigned char *d, size_t n, size_t *hlen, pw_err *e)
{
    size_t pos = 10;
    unsigned flg;
    if (n < 18) return pw_fail(e, PW_ERR_PARSE, "gzip data truncated (%lu bytes)", (unsigned long)n);
    if (d[0] != 0x1f || d[1] != 0x8b)
        return pw_fail(e, PW_ERR_PARSE, "not gzip data (bad magic 0x%02x 0x%02x)", d[0], d[1]);
    if (d[2] != 8) return pw_fail(e, PW_ERR_UNSUPPORTED, "gzip compression method %d (only 8, deflate)", d[2]);
    flg = d[3];
    if (flg & 0xe0) return pw_fail(e, PW_ERR_PARSE, "gzip header: reserved flag bits are set");
    if (flg & 4) { /* FEXTRA: a little-endian length, then that many bytes */
        size_t xlen = (size_t)d[10] | (size_t)d[11] << 8;
        if (xlen > n - 12) return pw_fail(e, PW_ERR_PARSE, "gzip header truncated (extra field)");
        pos = 12 + xlen;
    }
    if (flg & 8) { /* FNAME and FCOMMENT: zero-terminated */
        const unsigned char *z = (const unsigned char *)memchr(d + pos, 0, n - pos);
        if (!z) return pw_fail(e, PW_ERR_PARSE, "gzip header truncated (file name)");
        pos = (size_t)(z - d) + 1;
    }
    if (flg & 16) {
        const unsigned char *z = (const unsigned char *)memchr(d + pos, 0, n - pos);
        if (!z) return pw_fail(e, PW_ERR_PARSE, "gzip header truncated (comment)");
        pos = (size_t)(z - d) + 1;
    }
    if (flg & 2) { /* FHCRC: low 16 bits of the CRC-32 of the header so far */
        if (n - pos < 2) return pw_fail(e, PW_ERR_PARSE, "gzip header truncated (header CRC)");
        if ((pw_crc32(0, d, pos) & 0xffffu) != ((unsigned)d[pos] | (unsigned)d[pos + 1] << 8))
            return pw_fail(e, PW_ERR_PARSE, "gzip header: header CRC mismatch");
        pos += 2;
    }
    *hlen = pos;
    return PW_OK;
}

/* Appends m bytes to the growing output of pw_gzip_decompress. */
PW__DEF int pw__gzip_append(pw_buf *out, const unsigned char *m, size_t mn, pw_err *e)
{
    if (pw_grow(out->alloc, (void **)&out->data, &out->cap, out->size + mn, 1, "gzip data", e))
        return e && e->code ? e->code : PW_ERR_NOMEM;
    if (mn) memcpy(out->data + out->size, m, mn);
    out->size += mn;
    return PW_OK;
}

/* Decodes a gzip stream of one or more members into a new buffer of at most
 * max_out bytes (PW_ERR_LIMIT beyond): out->data (out->size bytes; out is
 * set up here, with allocator a). Every member's CRC-32 and length are
 * checked; bytes after the last member are an error. Free out->data with
 * pw_free(a, ...). */
PW__DEF int pw_gzip_decompress(const pw_alloc *a, const unsigned char *data, size_t n, size_t max_out, pw_buf *out,
                               pw_err *e)
{
    size_t pos = 0;
    int r = PW_OK, member = 0;
    memset(out, 0, sizeof *out);
    out->alloc = a;
    do {
        size_t hlen = 0, used = 0, mn = 0;
        unsigned char *m = NULL;
        const unsigned char *t;
        if (member > 0 && (n - pos < 2 || data[pos] != 0x1f || data[pos + 1] != 0x8b)) {
            r = pw_fail(e, PW_ERR_PARSE, "gzip data: %lu bytes of garbage after member %d", (unsigned long)(n - pos),
                        member);
            break;
        }
        if ((r = pw__gzip_header(data + pos, n - pos, &hlen, e))) break;
        pos += hlen;
        r = pw_inflate(a, data + pos, n - pos, max_out - out->size, &m, &mn, &used, e);
        if (r) break;
        pos += used;
        t = data + pos;
        if (n - pos < 8)
            r = pw_fail(e, PW_ERR_PARSE, "gzip data truncated (member %d has no CRC and size)", member + 1);
        else if (pw_crc32(0, m, mn) != pw__le32(t))
            r = pw_fail(e, PW_ERR_PARSE, "gzip data: CRC-32 mismatch in member %d", member + 1);
        else if (pw__le32(t + 4) != (uint32_t)mn)
            r = pw_fail(e, PW_ERR_PARSE, "gzip data: member %d holds %lu bytes, its trailer says %lu", member + 1,
                        (unsigned long)mn, (unsigned long)pw__le32(t + 4));
        else if (member == 0 && pos + 8 == n) { /* the usual single member: no copy */ out->data = m;
            out->size = out->cap = mn;
            return PW_OK;
        } else {
            r = pw__gzip_append(out, m, mn, e);
        }
        pw_free(a, m);
        pos += 8;
        member++;
    } while (!r && pos < n);
    if (r) {
        pw_free(a, out->data);
        out->data = NULL;
        out->size = out->cap = 0;
    }
    return r;
}

/* One gzip member holding data[0..n) at deflate `level` (0-9, -1 = 6), in
 * out->data (out->size bytes; out is set up here, with allocator a). */
PW__DEF int pw_gzip_compress(const pw_alloc *a, const unsigned char *data, size_t n, int level, pw_buf *out, pw_err *e)
{
    /* MTIME 0 and OS 255 (unknown): the bytes depend on the data alone */
    static const unsigned char head[10] = {0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 255};
    unsigned char *z, *g;
    size_t zn;
    int r;
    memset(out, 0, sizeof *out);
    out->alloc = a;
    if ((r = pw_deflate(a, data, n, level, &z, &zn, e))) return r;
    g = zn <= (size_t)-1 - 18 ? (unsigned char *)pw_realloc(a, z, zn + 18) : NULL;
    if (!g) {
        pw_free(a, z);
        return pw_fail(e, PW_ERR_NOMEM, "out of memory writing gzip data");
    }
    memmove(g + 10, g, zn);
    memcpy(g, head, 10);
    pw__put_le32(g + 10 + zn, pw_crc32(0, data, n));
    pw__put_le32(g + 14 + zn, (uint32_t)n);
    out->data = g;
    out->size = out->cap = zn + 18;
    return PW_OK;
}

/* ======================================================================
 * NRRD reader
 * ====================================================================== */

#define PW__NRRD_MAX_DIM 16 /* Teem's NRRD_DIM_MAX */

/* Indexes, in the list of pw__nrrd_field, of the fields that are read; the
 * others are known only to refuse their duplicates. */
enum {
    PW__NF_TYPE,
    PW__NF_DIMENSION,
    PW__NF_SIZES,
    PW__NF_ENCODING,
    PW__NF_ENDIAN,
    PW__NF_DATA_FILE,
    PW__NF_LINE_SKIP,
    PW__NF_BYTE_SKIP,
    PW__NF_KINDS,
    PW__NF_COUNT = 32 /* room for every field of pw__nrrd_field */
};

typedef struct pw__nrrd {
    const unsigned char *p;
    size_t n, pos;
    const char *name;
    pw_err *e;
    int line;  /* current line, 1-based (the magic is line 1) */
    int bytes; /* per sample: 1, 2 (unsigned integers) or 4 (float) */
    int dim, nsizes;
    uint64_t size[PW__NRRD_MAX_DIM];
    int gzip;               /* encoding: 0 raw, 1 gzip */
    int endian;             /* 0 not given, 1 little, 2 big */
    int first_kind;         /* kinds: 1 when the first axis holds channels */
    int seen[PW__NF_COUNT]; /* line where each known field was given, 0 = not yet */
    int c, x, y, z;         /* the volume, once the header is read */
} pw__nrrd;

/* Case-insensitive: do the n bytes at s spell kw? */
PW__DEF int pw__nrrd_ieq(const char *s, size_t n, const char *kw)
{
    size_t i;
    for (i = 0; i < n; i++) {
        int a = (unsigned char)s[i], b = (unsigned char)kw[i];
        if (!b) return 0;
        if (a >= 'A' && a <= 'Z') a += 'a' - 'A';
        if (b >= 'A' && b <= 'Z') b += 'a' - 'A';
        if (a != b) return 0;
    }
    return kw[n] == 0;
}

/* Is s[0..n) one of the '|'-separated words of list (case-insensitive)?
 * The list ends at its NUL or at a ';'. */
PW__DEF int pw__nrrd_in_list(const char *s, size_t n, const char *list)
{
    char w[32];
    while (*list && *list != ';') {
        size_t k = 0;
        while (list[k] && list[k] != '|' && list[k] != ';' && k < sizeof w - 1) {
            w[k] = list[k];
            k++;
        }
        w[k] = 0;
        if (pw__nrrd_ieq(s, n, w)) return 1;
        list += k;
        if (*list == '|') list++;
    }
    return 0;
}

/* Index of a known field name (aliases share the index), or -1. Fields are
 * separated by ';', aliases by '|'; the first nine are the PW__NF_ ones. */
PW__DEF int pw__nrrd_field(const char *s, size_t n)
{
    static const char names[] =
        "type;dimension;sizes;encoding;endian;data file|datafile;line skip|lineskip;"
        "byte skip|byteskip;kinds;content;block size|blocksize;min;max;old min|oldmin;"
        "old max|oldmax;number;sample units|sampleunits;spacings;thicknesses;axis mins|axismins;"
        "axis maxs|axismaxs;centers|centerings;labels;units;space;space dimension;space units;"
        "space origin;space directions;measurement frame";
    const char *p = names;
    int i;
    for (i = 0; *p; i++) {
        if (pw__nrrd_in_list(s, n, p)) return i;
        while (*p && *p != ';') p++;
        if (*p) p++;
    }
    return -1;
}

/* A decimal integer filling all of s[0..n), optionally negative. Returns
 * 0, -1 when s is not such a number, -2 beyond 10^15 (too large for any
 * size; no overflow). */
PW__DEF int pw__nrrd_int(const char *s, size_t n, int64_t *v)
{
    int64_t x = 0;
    int neg = n > 0 && s[0] == '-';
    size_t i = (size_t)neg;
    if (i >= n) return -1;
    for (; i < n; i++) {
        if (s[i] < '0' || s[i] > '9') return -1;
        x = x * 10 + (s[i] - '0');
        if (x > 1000000000000000LL) return -2;
    }
    *v = neg ? -x : x;
    return 0;
}

PW__DEF int pw__nrrd_bad(pw__nrrd *r, int code, const char *what, const char *s, size_t n)
{
    return pw_fail(r->e, code, "%s:%d: %s '%.*s'", r->name, r->line, what, (int)(n < 40 ? n : 40), s);
}

PW__DEF int pw__nrrd_type(pw__nrrd *r, const char *s, size_t n)
{
    if (pw__nrrd_in_list(s, n, "uchar|unsigned char|uint8|uint8_t")) r->bytes = 1;
    else if (pw__nrrd_in_list(s, n, "ushort|unsigned short|unsigned short int|uint16|uint16_t")) r->bytes = 2;
    else if (pw__nrrd_ieq(s, n, "float")) r->bytes = 4;
    else if (pw__nrrd_in_list(s, n,
                              "signed char|int8|int8_t|short|short int|signed short|signed short "
                              "int|int16|int16_t|int|signed int|int32|int32_t|uint|unsigned "
                              "int|uint32|uint32_t|longlong|long long|long long int|signed long "
                              "long|signed long long int|int64|int64_t|ulonglong|unsigned long "
                              "long|unsigned long long int|uint64|uint64_t|double|block"))
        return pw__nrrd_bad(r, PW_ERR_UNSUPPORTED, "type is not supported (uchar, ushort or float):", s, n);
    else return pw__nrrd_bad(r, PW_ERR_PARSE, "unknown type", s, n);
    return PW_OK;
}

PW__DEF int pw__nrrd_encoding(pw__nrrd *r, const char *s, size_t n)
{
    if (pw__nrrd_ieq(s, n, "raw")) r->gzip = 0;
    else if (pw__nrrd_in_list(s, n, "gzip|gz")) r->gzip = 1;
    else if (pw__nrrd_in_list(s, n, "txt|text|ascii|hex|bz2|bzip2"))
        return pw__nrrd_bad(r, PW_ERR_UNSUPPORTED, "encoding is not supported (raw or gzip):", s, n);
    else return pw__nrrd_bad(r, PW_ERR_PARSE, "unknown encoding", s, n);
    return PW_OK;
}

/* sizes: up to PW__NRRD_MAX_DIM positive integers. */
PW__DEF int pw__nrrd_sizes(pw__nrrd *r, const char *s, size_t n)
{
    size_t i = 0;
    while (i < n) {
        size_t k = i;
        int64_t v = 0;
        int rc;
        while (k < n && s[k] != ' ' && s[k] != '\t') k++;
        if (r->nsizes == PW__NRRD_MAX_DIM)
            return pw_fail(r->e, PW_ERR_PARSE, "%s:%d: more than %d sizes", r->name, r->line, PW__NRRD_MAX_DIM);
        rc = pw__nrrd_int(s + i, k - i, &v);
        if (rc == -2) return pw__nrrd_bad(r, PW_ERR_LIMIT, "size is too large:", s + i, k - i);
        if (rc || v <= 0)
            return pw__nrrd_bad(r, PW_ERR_PARSE, "bad size (a positive integer is needed):", s + i, k - i);
        r->size[r->nsizes++] = (uint64_t)v;
        i = k;
        while (i < n && (s[i] == ' ' || s[i] == '\t')) i++;
    }
    return PW_OK;
}

/* dimension, line skip, byte skip: integers. */
PW__DEF int pw__nrrd_number_field(pw__nrrd *r, int id, const char *s, size_t n)
{
    int64_t v = 0;
    if (pw__nrrd_int(s, n, &v))
        return pw__nrrd_bad(r, PW_ERR_PARSE,
                            id == PW__NF_DIMENSION   ? "bad dimension"
                            : id == PW__NF_LINE_SKIP ? "bad line skip"
                                                     : "bad byte skip",
                            s, n);
    if (id == PW__NF_DIMENSION) {
        if (v < 1 || v > PW__NRRD_MAX_DIM) return pw__nrrd_bad(r, PW_ERR_PARSE, "bad dimension (1 to 16):", s, n);
        if (v < 2 || v > 4)
            return pw_fail(r->e, PW_ERR_UNSUPPORTED,
                           "%s:%d: dimension %d is not supported (2: X Y, 3: X Y Z, 4: C X Y Z)", r->name, r->line,
                           (int)v);
        r->dim = (int)v;
    } else if (v != 0) {
        return pw_fail(r->e, PW_ERR_UNSUPPORTED, "%s:%d: %s %lld is not supported (the data must follow the header)",
                       r->name, r->line, id == PW__NF_LINE_SKIP ? "line skip" : "byte skip", (long long)v);
    }
    return PW_OK;
}

/* kinds: only the first axis matters, to tell 2D colour from 3D gray. */
PW__DEF void pw__nrrd_kinds(pw__nrrd *r, const char *s, size_t n)
{
    size_t k = 0;
    while (k < n && s[k] != ' ' && s[k] != '\t') k++;
    r->first_kind =
        pw__nrrd_in_list(s, k,
                         "RGB-color|RGBA-color|HSV-color|XYZ-color|3-color|4-color|vector|2-vector|3-vector|4-"
                         "vector|covariant-vector|normal|3-normal|3-gradient|point|list|quaternion|complex");
}

/* The value of one known field. */
PW__DEF int pw__nrrd_value(pw__nrrd *r, int id, const char *s, size_t n)
{
    switch (id) {
    case PW__NF_TYPE: return pw__nrrd_type(r, s, n);
    case PW__NF_ENCODING: return pw__nrrd_encoding(r, s, n);
    case PW__NF_SIZES: return pw__nrrd_sizes(r, s, n);
    case PW__NF_KINDS: pw__nrrd_kinds(r, s, n); return PW_OK;
    case PW__NF_DIMENSION:
    case PW__NF_LINE_SKIP:
    case PW__NF_BYTE_SKIP: return pw__nrrd_number_field(r, id, s, n);
    case PW__NF_ENDIAN:
        if (pw__nrrd_ieq(s, n, "little")) r->endian = 1;
        else if (pw__nrrd_ieq(s, n, "big")) r->endian = 2;
        else return pw__nrrd_bad(r, PW_ERR_PARSE, "bad endian (little or big):", s, n);
        return PW_OK;
    case PW__NF_DATA_FILE:
        return pw__nrrd_bad(r, PW_ERR_UNSUPPORTED,
                            "detached data is not supported (the data must follow the header): "
                            "data file",
                            s, n);
    default: return PW_OK; /* content, spacings, space, ...: ignored */
    }
}

/* One header line s[0..n) (no line terminator): a comment, "key:=value"
 * (ignored) or "field: value". */
PW__DEF int pw__nrrd_line(pw__nrrd *r, const char *s, size_t n)
{
    size_t k, v;
    int id;
    if (memchr(s, 0, n)) return pw_fail(r->e, PW_ERR_PARSE, "%s:%d: NUL byte in the header", r->name, r->line);
    if (s[0] == '#') return PW_OK;
    for (k = 0; k + 1 < n; k++)
        if (s[k] == ':' && (s[k + 1] == ' ' || s[k + 1] == '=')) break;
    if (k + 1 >= n || k == 0)
        return pw__nrrd_bad(r, PW_ERR_PARSE, "expected 'field: value' or 'key:=value', found", s, n);
    if (s[k + 1] == '=') return PW_OK;
    id = pw__nrrd_field(s, k);
    if (id < 0) return PW_OK; /* unknown fields are ignored */
    if (r->seen[id])
        return pw_fail(r->e, PW_ERR_PARSE, "%s:%d: duplicate field '%.*s' (first given on line %d)", r->name, r->line,
                       (int)k, s, r->seen[id]);
    r->seen[id] = r->line;
    v = k + 2;
    while (v < n && (s[v] == ' ' || s[v] == '\t')) v++;
    while (n > v && (s[n - 1] == ' ' || s[n - 1] == '\t')) n--;
    return pw__nrrd_value(r, id, s + v, n - v);
}

/* The magic line: NRRD0001 to NRRD0005. */
PW__DEF int pw__nrrd_magic(pw__nrrd *r)
{
    const unsigned char *p = r->p;
    if (r->n < 8 || memcmp(p, "NRRD000", 7) != 0 || p[7] < '0' || p[7] > '9')
        return pw_fail(r->e, PW_ERR_PARSE, "%s: not a NRRD file (no NRRD000X magic)", r->name);
    if (p[7] < '1' || p[7] > '5')
        return pw_fail(r->e, PW_ERR_UNSUPPORTED, "%s: NRRD format version %c is not supported (NRRD0001 to NRRD0005)",
                       r->name, p[7]);
    r->pos = 8;
    if (r->pos < r->n && r->p[r->pos] == '\r') r->pos++;
    if (r->pos >= r->n || r->p[r->pos] != '\n')
        return pw_fail(r->e, PW_ERR_PARSE, "%s:1: the magic must be alone on the first line", r->name);
    r->pos++;
    r->line = 2;
    return PW_OK;
}

/* Header lines up to and including the empty line that ends the header. */
PW__DEF int pw__nrrd_header(pw__nrrd *r)
{
    for (;; r->line++) {
        const unsigned char *nl =
            r->pos < r->n ? (const unsigned char *)memchr(r->p + r->pos, '\n', r->n - r->pos) : NULL;
        size_t start = r->pos, end;
        int rc;
        if (!nl)
            return pw_fail(r->e, PW_ERR_PARSE, "%s:%d: the header does not end with an empty line (no data follows)",
                           r->name, r->line);
        end = (size_t)(nl - r->p);
        r->pos = end + 1;
        if (end > start && r->p[end - 1] == '\r') end--;
        if (end == start) return PW_OK;
        if ((rc = pw__nrrd_line(r, (const char *)r->p + start, end - start))) return rc;
    }
}

/* Required fields and the shape of the volume, checked against the limits. */
PW__DEF int pw__nrrd_shape(pw__nrrd *r)
{
    static const char *const req[4] = {"type", "dimension", "sizes", "encoding"};
    const uint64_t *s = r->size;
    uint64_t z;
    int i, rest, rc;
    for (i = 0; i < 4; i++)
        if (!r->seen[i])
            return pw_fail(r->e, PW_ERR_PARSE, "%s:%d: the header lacks the required '%s' field", r->name, r->line,
                           req[i]);
    if (r->nsizes != r->dim)
        return pw_fail(r->e, PW_ERR_PARSE, "%s:%d: sizes has %d values, dimension says %d", r->name,
                       r->seen[PW__NF_SIZES], r->nsizes, r->dim);
    if (r->bytes > 1 && !r->endian)
        return pw_fail(r->e, PW_ERR_PARSE, "%s:%d: the header lacks the 'endian' field (needed for %s samples)",
                       r->name, r->line, r->bytes == 2 ? "16-bit" : "float");
    r->c = 1;
    rest = r->dim; /* spatial axes */
    if (r->dim == 4 || (r->dim == 3 && r->first_kind)) {
        if (s[0] > 4)
            return pw_fail(r->e, PW_ERR_UNSUPPORTED, "%s:%d: %llu channels (the first size) are not supported (1 to 4)",
                           r->name, r->seen[PW__NF_SIZES], (unsigned long long)s[0]);
        r->c = (int)s[0];
        s++;
        rest--;
    }
    z = rest == 3 ? s[2] : 1; /* dimension 2 and 2D colour: one slice */
    if ((rc = pw__volume_check_size(r->name, s[0], s[1], z, r->e))) return rc;
    r->x = (int)s[0];
    r->y = (int)s[1];
    r->z = (int)z;
    return PW_OK;
}

/* Samples to floats: bytes /255, 16-bit /65535, floats as they are (but
 * not NaN or infinite). */
PW__DEF int pw__nrrd_convert(pw__nrrd *r, const unsigned char *src, pw_volume *v)
{
    size_t i, n = (size_t)v->c * v->x * v->y * v->z;
    int big = r->endian == 2;
    for (i = 0; i < n; i++) {
        if (r->bytes == 1) {
            v->px[i] = (float)src[i] / 255.0f;
        } else if (r->bytes == 2) {
            const unsigned char *p = src + 2 * i;
            unsigned u = big ? (unsigned)p[0] << 8 | p[1] : (unsigned)p[1] << 8 | p[0];
            v->px[i] = (float)u / 65535.0f;
        } else {
            const unsigned char *p = src + 4 * i;
            uint32_t u = big ? pw__be32(p) : pw__le32(p);
            float f;
            memcpy(&f, &u, sizeof f);
            if (!pw_is_finite(f))
                return pw_fail(r->e, PW_ERR_PARSE, "%s:%d: float sample %lu is %s", r->name, r->line, (unsigned long)i,
                               f != f ? "NaN" : "infinite");
            v->px[i] = f;
        }
    }
    return PW_OK;
}

/* The data after the header: raw or gunzipped, then converted. */
PW__DEF int pw__nrrd_data(const pw_alloc *a, pw__nrrd *r, pw_volume *out)
{
    uint64_t need = (uint64_t)r->c * r->x * r->y * r->z * (uint64_t)r->bytes;
    unsigned char *buf = NULL;
    const unsigned char *src = r->p + r->pos;
    size_t have = r->n - r->pos;
    int rc;
    if (need > (size_t)-1)
        return pw_fail(r->e, PW_ERR_LIMIT, "%s: %llu bytes of data do not fit in memory", r->name,
                       (unsigned long long)need);
    if (r->gzip) {
        pw_err local;
        pw_buf unz;
        pw_err_clear(&local);
        rc = pw_gzip_decompress(a, src, have, (size_t)need, &unz, &local);
        buf = unz.data;
        have = unz.size;
        if (rc == PW_ERR_LIMIT)
            return pw_fail(r->e, PW_ERR_PARSE,
                           "%s:%d: the gzip data holds more than the %llu bytes that sizes and "
                           "type describe",
                           r->name, r->line, (unsigned long long)need);
        if (rc) return pw_fail(r->e, rc, "%s:%d: %s", r->name, r->line, local.msg);
        src = buf;
    }
    if (have < need) {
        pw_free(a, buf);
        return pw_fail(r->e, PW_ERR_PARSE, "%s:%d: data truncated: %llu bytes needed, %llu present%s", r->name, r->line,
                       (unsigned long long)need, (unsigned long long)have, r->gzip ? " after gunzip" : "");
    }
    rc = pw_volume_alloc(a, out, r->c, r->x, r->y, r->z, r->e);
    if (!rc) rc = pw__nrrd_convert(r, src, out);
    if (rc) pw_volume_free(a, out);
    pw_free(a, buf);
    return rc;
}

/* Reads a NRRD volume from memory (see the top of this module for what is
 * read). `name` (usually the file name) starts every error message. */
PW__DEF int pw_nrrd_read_memory(const pw_alloc *a, const unsigned char *data, size_t size, const char *name,
                                pw_volume *out, pw_err *e)
{
    pw__nrrd r;
    int rc;
    memset(out, 0, sizeof *out);
    memset(&r, 0, sizeof r);
    r.p = data;
    r.n = data ? size : 0;
    r.name = name ? name : "volume";
    r.e = e;
    r.line = 1;
    if ((rc = pw__nrrd_magic(&r)) || (rc = pw__nrrd_header(&r)) || (rc = pw__nrrd_shape(&r))) return rc;
    return pw__nrrd_data(a, &r, out);
}

/* ======================================================================
 * NRRD writer
 * ====================================================================== */

/* NRRD0004, uint8 samples (pw_image_quantize), dimension 3 (sizes X Y Z)
 * for one channel and 4 (sizes C X Y Z) otherwise, raw or (gzip != 0)
 * gzip-encoded. a is used only for gzip. */
PW__DEF int pw_nrrd_write(const pw_alloc *a, const pw_volume *vol, int gzip, pw_write_fn w, void *ctx, pw_err *e)
{
    static const char *const kinds[4] = {"", "2-vector ", "RGB-color ", "RGBA-color "};
    pw__sink s;
    char head[256], sz[16];
    size_t i, n;
    int rc = pw__volume_check(vol, e), k;
    if (rc) return rc;
    n = (size_t)vol->c * vol->x * vol->y * vol->z;
    sz[0] = 0;
    if (vol->c > 1) snprintf(sz, sizeof sz, "%d ", vol->c);
    k = snprintf(head, sizeof head,
                 "NRRD0004\ntype: uint8\ndimension: %d\nsizes: %s%d %d %d\n"
                 "kinds: %sdomain domain domain\nencoding: %s\n\n",
                 vol->c > 1 ? 4 : 3, sz, vol->x, vol->y, vol->z, kinds[vol->c - 1], gzip ? "gzip" : "raw");
    pw__sink_init(&s, w, ctx);
    pw__sink_put(&s, head, (size_t)k);
    if (gzip) {
        unsigned char *b;
        pw_buf z;
        b = (unsigned char *)pw_alloc_array(a, n, 1, "NRRD samples", e);
        if (!b) return PW_ERR_NOMEM;
        for (i = 0; i < n; i++) b[i] = (unsigned char)pw_image_quantize(vol->px[i], 255);
        rc = pw_gzip_compress(a, b, n, -1, &z, e);
        pw_free(a, b);
        if (rc) return rc;
        pw__sink_put(&s, z.data, z.size);
        pw_free(a, z.data);
    } else {
        for (i = 0; i < n; i++) pw__sink_byte(&s, pw_image_quantize(vol->px[i], 255));
    }
    return pw__sink_end(&s, e);
}

#ifndef PW_NO_STDIO
/* Reads the NRRD file at path. */
PW__DEF int pw_nrrd_load(const pw_alloc *a, const char *path, pw_volume *out, pw_err *e)
{
    unsigned char *data;
    size_t n;
    int rc;
    memset(out, 0, sizeof *out);
    if ((rc = pw_read_file(a, path, &data, &n, e))) return rc;
    rc = pw_nrrd_read_memory(a, data, n, path, out, e);
    pw_free(a, data);
    return rc;
}

typedef struct pw__nrrd_save_arg {
    const pw_alloc *a;
    const pw_volume *vol;
    int gzip;
} pw__nrrd_save_arg;

PW__DEF int pw__nrrd_save_body(void *arg, pw_write_fn w, void *ctx, pw_err *e)
{
    const pw__nrrd_save_arg *s = (const pw__nrrd_save_arg *)arg;
    return pw_nrrd_write(s->a, s->vol, s->gzip, w, ctx, e);
}

/* Writes vol to the NRRD file at path (see pw_nrrd_write). */
PW__DEF int pw_nrrd_save(const pw_alloc *a, const pw_volume *vol, int gzip, const char *path, pw_err *e)
{
    pw__nrrd_save_arg s;
    int rc = pw__volume_check(vol, e);
    if (rc) return rc;
    s.a = a;
    s.vol = vol;
    s.gzip = gzip;
    return pw_write_file(path, pw__nrrd_save_body, &s, e);
}
#endif

#endif /* PW__NRRD_V1 */
