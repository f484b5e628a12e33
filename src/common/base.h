/* base: allocation hooks, result codes, error messages, limits, helpers.
 * Every other shared module builds on this one. */
#ifndef PW__BASE_V1
#define PW__BASE_V1

#include <stddef.h>
#include <stdint.h>
#include <stdarg.h>
#include <string.h>
#include <limits.h>
#include <math.h>
#include <float.h>
#include <stdio.h> /* vsnprintf for error messages; FILE I/O is guarded by PW_NO_STDIO */

#if defined(PW_MALLOC) && defined(PW_FREE) && defined(PW_REALLOC)
/* user-supplied allocator macros */
#elif !defined(PW_MALLOC) && !defined(PW_FREE) && !defined(PW_REALLOC)
#include <stdlib.h>
#define PW_MALLOC(sz) malloc(sz)
#define PW_REALLOC(p, newsz) realloc((p), (newsz))
#define PW_FREE(p) free(p)
#else
#error "patchwork: define all of PW_MALLOC, PW_REALLOC and PW_FREE, or none of them"
#endif

#ifndef PW_ASSERT
#include <assert.h>
#define PW_ASSERT(x) assert(x)
#endif

#if defined(__GNUC__) || defined(__clang__)
#define PW__UNUSED __attribute__((unused))
#else
#define PW__UNUSED
#endif

/* Every shared function is static: each header that includes the shared code
 * gets its own private copy, and the sentinels above stop a second copy. */
#define PW__DEF static PW__UNUSED

/* Limits: sizes read from files are checked against these before anything is
 * multiplied or allocated. Override before including a header. */
#ifndef PW_MAX_IMAGE_DIM
#define PW_MAX_IMAGE_DIM 65536 /* width or height, pixels */
#endif
#ifndef PW_MAX_IMAGE_PIXELS
#define PW_MAX_IMAGE_PIXELS (1 << 28) /* width*height (per slice) */
#endif
#ifndef PW_MAX_MESH_ELEMENTS
#define PW_MAX_MESH_ELEMENTS (1 << 27) /* vertices, faces or face corners */
#endif
#ifndef PW_MAX_FACE_DEGREE
#define PW_MAX_FACE_DEGREE 1024 /* corners of one polygon */
#endif

/* Result codes, shared by the four headers: each header's enum repeats these
 * values under its own prefix (TILED_OK == PW_OK, ...). */
enum {
    PW_OK = 0,
    PW_ERR_NOMEM = 1,       /* an allocation failed */
    PW_ERR_IO = 2,          /* a file could not be opened, read or written */
    PW_ERR_PARSE = 3,       /* malformed or truncated input data */
    PW_ERR_UNSUPPORTED = 4, /* valid input using a feature not implemented */
    PW_ERR_LIMIT = 5,       /* a size exceeds a documented limit */
    PW_ERR_INVALID = 6,     /* invalid argument or value (NaN, out of range) */
    PW_ERR_TOPOLOGY = 7,    /* non-manifold or inconsistently oriented mesh */
    PW_ERR_DEGENERATE = 8,  /* degenerate geometry (zero area, no faces) */
    PW_ERR_CANCELLED = 9,   /* the progress callback asked to stop */
    PW_ERR_NOCONVERGE = 10, /* an iterative solver did not converge */
    PW_ERR__COUNT = 11
};

PW__DEF const char *pw_result_string(int code)
{
    static const char *const names[PW_ERR__COUNT] = {"ok",
                                                     "out of memory",
                                                     "input/output error",
                                                     "parse error",
                                                     "unsupported feature",
                                                     "size limit exceeded",
                                                     "invalid argument",
                                                     "bad mesh topology",
                                                     "degenerate geometry",
                                                     "cancelled",
                                                     "solver did not converge"};
    if (code < 0 || code >= PW_ERR__COUNT) return "unknown error";
    return names[code];
}

/* An error: the code and a message that names what was wrong. */
typedef struct pw_err {
    int code;
    char msg[256];
} pw_err;

/* Records an error (if e is not NULL) and returns its code, so that callers
 * can write `return pw_fail(e, PW_ERR_PARSE, "%s:%d: ...", ...)`. The first
 * error recorded wins: later, more generic failures up the stack keep it. */
PW__DEF int pw_fail(pw_err *e, int code, const char *fmt, ...)
{
    va_list ap;
    if (!e || e->code != PW_OK) return e ? e->code : code;
    e->code = code;
    va_start(ap, fmt);
    vsnprintf(e->msg, sizeof e->msg, fmt, ap);
    va_end(ap);
    return code;
}

PW__DEF void pw_err_clear(pw_err *e)
{
    if (e) {
        e->code = PW_OK;
        e->msg[0] = 0;
    }
}

/* Run-time allocator: NULL function pointers fall back to PW_MALLOC etc. */
typedef struct pw_alloc {
    void *(*malloc_fn)(void *user, size_t size);
    void *(*realloc_fn)(void *user, void *ptr, size_t size);
    void (*free_fn)(void *user, void *ptr);
    void *user;
} pw_alloc;

PW__DEF void *pw_malloc(const pw_alloc *a, size_t n)
{
    if (n == 0) n = 1;
    if (a && a->malloc_fn) return a->malloc_fn(a->user, n);
    return PW_MALLOC(n);
}

PW__DEF void *pw_realloc(const pw_alloc *a, void *p, size_t n)
{
    if (n == 0) n = 1;
    if (a && a->realloc_fn) return a->realloc_fn(a->user, p, n);
    return PW_REALLOC(p, n);
}

PW__DEF void pw_free(const pw_alloc *a, void *p)
{
    if (!p) return;
    if (a && a->free_fn) a->free_fn(a->user, p);
    else PW_FREE(p);
}

/* count*size bytes, overflow-checked; records PW_ERR_NOMEM (naming `what`)
 * on failure. */
PW__DEF void *pw_alloc_array(const pw_alloc *a, size_t count, size_t size, const char *what, pw_err *e)
{
    void *p;
    if (size && count > (size_t)-1 / size) {
        pw_fail(e, PW_ERR_NOMEM, "%s: %lu elements of %lu bytes overflow size_t", what, (unsigned long)count,
                (unsigned long)size);
        return NULL;
    }
    p = pw_malloc(a, count * size);
    if (!p) pw_fail(e, PW_ERR_NOMEM, "out of memory allocating %s (%lu bytes)", what, (unsigned long)(count * size));
    return p;
}

/* Same, zero-filled. */
PW__DEF void *pw_calloc_array(const pw_alloc *a, size_t count, size_t size, const char *what, pw_err *e)
{
    void *p = pw_alloc_array(a, count, size, what, e);
    if (p) memset(p, 0, count * size);
    return p;
}

/* Grows *p (holding *cap elements of `size` bytes) to at least `need`
 * elements, doubling. Returns 0 on success. */
PW__DEF int pw_grow(const pw_alloc *a, void **p, size_t *cap, size_t need, size_t size, const char *what, pw_err *e)
{
    size_t ncap;
    void *np;
    if (need <= *cap) return PW_OK;
    ncap = *cap ? *cap : 16;
    while (ncap < need) {
        if (ncap > ((size_t)-1 / 2) / size) return pw_fail(e, PW_ERR_NOMEM, "%s: size overflow", what);
        ncap *= 2;
    }
    np = pw_realloc(a, *p, ncap * size);
    if (!np)
        return pw_fail(e, PW_ERR_NOMEM, "out of memory growing %s to %lu bytes", what, (unsigned long)(ncap * size));
    *p = np;
    *cap = ncap;
    return PW_OK;
}

/* Progress reporting: fn returns non-zero to cancel. May be NULL. */
typedef struct pw_progress {
    int (*fn)(void *user, float done, const char *stage);
    void *user;
} pw_progress;

/* Reports progress; returns PW_ERR_CANCELLED (recorded in e) if asked. */
PW__DEF int pw_report(const pw_progress *p, float done, const char *stage, pw_err *e)
{
    if (p && p->fn && p->fn(p->user, done, stage))
        return pw_fail(e, PW_ERR_CANCELLED, "cancelled by the progress callback during %s", stage);
    return PW_OK;
}

/* Output sink for writers: returns 0 on success. */
typedef int (*pw_write_fn)(void *ctx, const void *data, size_t size);

PW__DEF int pw_is_finite(double x) { return x == x && x - x == 0.0; }

PW__DEF int pw_mini(int a, int b) { return a < b ? a : b; }
PW__DEF int pw_maxi(int a, int b) { return a > b ? a : b; }
PW__DEF int pw_clampi(int x, int lo, int hi) { return x < lo ? lo : (x > hi ? hi : x); }
PW__DEF float pw_clampf(float x, float lo, float hi) { return x < lo ? lo : (x > hi ? hi : x); }

/* Case-insensitive suffix test, for choosing formats by file extension. */
PW__DEF int pw_has_ext(const char *path, const char *ext)
{
    size_t lp = strlen(path), le = strlen(ext), i;
    if (le > lp) return 0;
    for (i = 0; i < le; i++) {
        char a = path[lp - le + i], b = ext[i];
        if (a >= 'A' && a <= 'Z') a = (char)(a - 'A' + 'a');
        if (b >= 'A' && b <= 'Z') b = (char)(b - 'A' + 'a');
        if (a != b) return 0;
    }
    return 1;
}

#ifndef PW_NO_STDIO
/* Reads a whole file into memory (with a terminating NUL not counted in
 * *size). */
PW__DEF int pw_read_file(const pw_alloc *a, const char *path, unsigned char **data, size_t *size, pw_err *e)
{
    FILE *f = fopen(path, "rb");
    unsigned char *buf = NULL;
    size_t cap = 0, n = 0, got;
    *data = NULL;
    *size = 0;
    if (!f) return pw_fail(e, PW_ERR_IO, "%s: cannot open file for reading", path);
    for (;;) {
        if (pw_grow(a, (void **)&buf, &cap, n + 65536 + 1, 1, path, e)) {
            fclose(f);
            pw_free(a, buf);
            return e ? e->code : PW_ERR_NOMEM;
        }
        got = fread(buf + n, 1, cap - n - 1, f);
        n += got;
        if (got == 0) break;
    }
    if (ferror(f)) {
        fclose(f);
        pw_free(a, buf);
        return pw_fail(e, PW_ERR_IO, "%s: read error", path);
    }
    fclose(f);
    buf[n] = 0;
    *data = buf;
    *size = n;
    return PW_OK;
}

PW__DEF int pw__file_write(void *ctx, const void *data, size_t size)
{
    return fwrite(data, 1, size, (FILE *)ctx) == size ? 0 : -1;
}

/* Opens `path` for writing and runs body(arg, sink, FILE*, e), which writes
 * through the sink. A failing sink or fclose is reported naming the file. */
PW__DEF int pw_write_file(const char *path, int (*body)(void *arg, pw_write_fn w, void *ctx, pw_err *e), void *arg,
                          pw_err *e)
{
    pw_err local;
    FILE *f = fopen(path, "wb");
    int r;
    if (!f) return pw_fail(e, PW_ERR_IO, "%s: cannot open file for writing", path);
    pw_err_clear(&local);
    r = body(arg, pw__file_write, f, &local);
    if (fclose(f) != 0 && r == PW_OK) r = local.code = PW_ERR_IO;
#ifdef PW_NO_PNG
    /* a body that needed the compiled-out PNG encoder refused before writing
     * a byte: leave no empty file behind */
    if (r == PW_ERR_UNSUPPORTED) remove(path);
#endif
    if (r == PW_ERR_IO) return pw_fail(e, PW_ERR_IO, "%s: write error (disk full?)", path);
    if (r != PW_OK) return pw_fail(e, r, "%s", local.msg);
    return PW_OK;
}
#endif

/* Output buffer: a growable byte array usable as a pw_write_fn sink. */
typedef struct pw_buf {
    unsigned char *data;
    size_t size, cap;
    const pw_alloc *alloc;
    int failed;
} pw_buf;

PW__DEF int pw_buf_write(void *ctx, const void *data, size_t size)
{
    pw_buf *b = (pw_buf *)ctx;
    if (b->failed) return -1;
    if (pw_grow(b->alloc, (void **)&b->data, &b->cap, b->size + size, 1, "buffer", NULL)) {
        b->failed = 1;
        return -1;
    }
    memcpy(b->data + b->size, data, size);
    b->size += size;
    return 0;
}

#endif /* PW__BASE_V1 */
