/* fuzz.h: what the libFuzzer targets share: a check that aborts with the
 * target's name, a counting allocator that catches leaks and frees through
 * the wrong allocator, a pseudo-random stream from the input's bytes, write
 * callbacks and a progress callback that cancels.
 *
 * Define FZ_NAME (the target's name, a string) before including it. */
#ifndef FZ_FUZZ_H
#define FZ_FUZZ_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef FZ_NAME
#error "define FZ_NAME before including fuzz.h"
#endif

#define FZ_CHECK(c)                                                                 \
    do {                                                                            \
        if (!(c)) {                                                                 \
            fprintf(stderr, FZ_NAME ": check failed at line %d: %s\n", __LINE__, #c); \
            abort();                                                                \
        }                                                                           \
    } while (0)

/* Every patchwork header's result codes: 0 is success, 1..10 the errors. */
#define FZ_MAX_RESULT 10

/* A failure carries its code and a terminated, non-empty message. */
static void fz_check_failure(int r, int code, const char *message, size_t cap)
{
    FZ_CHECK(r > 0 && r <= FZ_MAX_RESULT);
    FZ_CHECK(code == r);
    FZ_CHECK(message[0] != 0);
    FZ_CHECK(memchr(message, 0, cap) != NULL);
}

static int fz_finite(float x) { return x == x && x - x == 0.0f; }

/* ---- a counting allocator: a tagged header before every block ---------------- */

typedef struct fz_heap {
    long live;
} fz_heap;

#define FZ_TAG 0x70617463u /* "patc" */
#define FZ_HDR 16

static void *fz_malloc(void *user, size_t n)
{
    unsigned char *p = (unsigned char *)malloc(n + FZ_HDR);
    uint32_t tag = FZ_TAG;
    if (!p) return NULL;
    memcpy(p, &tag, 4);
    ((fz_heap *)user)->live++;
    return p + FZ_HDR;
}

static unsigned char *fz_header(void *ptr)
{
    unsigned char *p = (unsigned char *)ptr - FZ_HDR;
    uint32_t tag;
    memcpy(&tag, p, 4);
    FZ_CHECK(tag == FZ_TAG); /* not one of ours: freed through the wrong allocator */
    return p;
}

static void *fz_realloc(void *user, void *ptr, size_t n)
{
    unsigned char *p;
    if (!ptr) return fz_malloc(user, n);
    p = (unsigned char *)realloc(fz_header(ptr), n + FZ_HDR);
    return p ? p + FZ_HDR : NULL;
}

static void fz_free(void *user, void *ptr)
{
    unsigned char *p;
    if (!ptr) return;
    p = fz_header(ptr);
    memset(p, 0, 4);
    free(p);
    ((fz_heap *)user)->live--;
}

/* ---- a pseudo-random stream (splitmix64) ----------------------------------------- */

static uint64_t fz_next(uint64_t *s)
{
    uint64_t z = (*s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static float fz_unit(uint64_t *s) { return (float)(fz_next(s) >> 40) / 16777216.0f; }

/* ---- write callbacks ------------------------------------------------------------- */

typedef struct fz_buf {
    unsigned char *data;
    size_t size, cap;
} fz_buf;

/* Appends to an fz_buf (ctx). */
static int fz_append(void *ctx, const void *data, size_t size)
{
    fz_buf *b = (fz_buf *)ctx;
    if (b->size + size > b->cap) {
        size_t cap = b->cap ? b->cap : 256;
        unsigned char *p;
        while (cap < b->size + size) cap *= 2;
        if (!(p = (unsigned char *)realloc(b->data, cap))) return 1;
        b->data = p;
        b->cap = cap;
    }
    memcpy(b->data + b->size, data, size);
    b->size += size;
    return 0;
}

/* Counts the bytes (ctx: a size_t). */
static int fz_count(void *ctx, const void *data, size_t size)
{
    (void)data;
    *(size_t *)ctx += size;
    return 0;
}

/* ---- progress: cancels at call cancel_at (0: never) and after max_calls ------------ */

typedef struct fz_progress {
    int calls, cancel_at, max_calls;
} fz_progress;

static int fz_progress_fn(void *user, float done, const char *stage)
{
    fz_progress *p = (fz_progress *)user;
    FZ_CHECK(stage && stage[0]);
    FZ_CHECK(done >= 0.0f && done <= 1.0f);
    p->calls++;
    return p->calls == p->cancel_at || p->calls > p->max_calls;
}

#endif /* FZ_FUZZ_H */
