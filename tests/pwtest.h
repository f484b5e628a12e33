/* pwtest: the tiny test framework behind `make test`.
 *
 * A test file lists its cases and ends with PWT_MAIN:
 *
 *     static void t_roundtrip(void) { CHECK(1 + 1 == 2); }
 *     static const pwt_case cases[] = {{"roundtrip", t_roundtrip}};
 *     PWT_MAIN(cases)
 *
 * Each case prints one line, `PASS name`, `FAIL name: where: what` or
 * `SKIP name: why`; tests/run.sh counts them. INFO lines carry measurements.
 * `./test_x NAME` runs only the cases whose name contains NAME. */
#ifndef PWTEST_H
#define PWTEST_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <stdarg.h>
#if defined(__unix__) || defined(__unix) || defined(__APPLE__)
#include <unistd.h>
#define PWT_PID_ ((long)getpid())
#else
#define PWT_PID_ 0L
#endif

#if defined(__GNUC__) || defined(__clang__)
#define PWT_UNUSED __attribute__((unused))
#else
#define PWT_UNUSED
#endif

typedef struct pwt_case {
    const char *name;
    void (*fn)(void);
} pwt_case;

static int pwt_failed_, pwt_skipped_;
static const char *pwt_name_;

static void pwt_fail_(const char *file, int line, const char *fmt, ...)
{
    va_list ap;
    if (!pwt_failed_) printf("FAIL %s: ", pwt_name_);
    else printf("     %s: ", pwt_name_);
    printf("%s:%d: ", file, line);
    va_start(ap, fmt);
    vprintf(fmt, ap);
    va_end(ap);
    printf("\n");
    fflush(stdout);
    pwt_failed_++;
}

/* Skips the current case (a test that needs absent optional data). */
PWT_UNUSED static void pwt_skip(const char *fmt, ...)
{
    va_list ap;
    printf("SKIP %s: ", pwt_name_);
    va_start(ap, fmt);
    vprintf(fmt, ap);
    va_end(ap);
    printf("\n");
    pwt_skipped_ = 1;
}

/* A measurement worth keeping in the log. */
PWT_UNUSED static void pwt_info(const char *fmt, ...)
{
    va_list ap;
    printf("INFO %s: ", pwt_name_);
    va_start(ap, fmt);
    vprintf(fmt, ap);
    va_end(ap);
    printf("\n");
}

#define CHECK(c) ((c) ? (void)0 : pwt_fail_(__FILE__, __LINE__, "%s", #c))
#define CHECKF(c, ...) ((c) ? (void)0 : pwt_fail_(__FILE__, __LINE__, __VA_ARGS__))
#define REQUIRE(c)                                           \
    do {                                                     \
        if (!(c)) {                                          \
            pwt_fail_(__FILE__, __LINE__, "required: %s", #c); \
            return;                                          \
        }                                                    \
    } while (0)
#define CHECK_EQ_INT(a, b)                                                        \
    do {                                                                          \
        long long pwt_a_ = (long long)(a), pwt_b_ = (long long)(b);               \
        if (pwt_a_ != pwt_b_)                                                     \
            pwt_fail_(__FILE__, __LINE__, "%s == %s (%lld vs %lld)", #a, #b, pwt_a_, \
                      pwt_b_);                                                    \
    } while (0)
#define CHECK_NEAR(a, b, tol)                                                         \
    do {                                                                              \
        double pwt_a_ = (double)(a), pwt_b_ = (double)(b);                            \
        if (!(pwt_a_ - pwt_b_ <= (tol) && pwt_b_ - pwt_a_ <= (tol)))                  \
            pwt_fail_(__FILE__, __LINE__, "%s ~= %s (%g vs %g, tol %g)", #a, #b, pwt_a_, \
                      pwt_b_, (double)(tol));                                         \
    } while (0)

/* Directory of optional real data (make data), overridable with PW_DATA. */
PWT_UNUSED static const char *pwt_data_dir(void)
{
    const char *d = getenv("PW_DATA");
    return d && *d ? d : "data";
}

/* Path of a data file in a static buffer (the last four stay valid); NULL
 * if the file is absent. */
PWT_UNUSED static const char *pwt_data_opt(const char *rel)
{
    static char buf[4][1024];
    static int k;
    FILE *f;
    char *p = buf[k++ & 3];
    snprintf(p, 1024, "%s/%s", pwt_data_dir(), rel);
    f = fopen(p, "rb");
    if (!f) return NULL;
    fclose(f);
    return p;
}

/* The same, and the case skipped if the file is absent. */
PWT_UNUSED static const char *pwt_data(const char *rel)
{
    const char *p = pwt_data_opt(rel);
    if (!p) pwt_skip("%s/%s absent (run `make data`)", pwt_data_dir(), rel);
    return p;
}

/* A counting allocator that can be made to fail, for the run-time allocator
 * hooks (user pointer: a pwt_alloc_state). A test builds its own
 *
 *     pwt_alloc_state st = {0, 0, -1};
 *     pw_alloc al = {pwt_malloc, pwt_realloc, pwt_free, &st};
 *
 * calls: malloc/realloc calls so far (failed ones included);
 * live: blocks allocated and not yet freed (0 after a run that leaks nothing);
 * fail_after: < 0 never fails, else calls after the first fail_after return
 * NULL (0: every call fails). */
typedef struct pwt_alloc_state {
    long calls, live, fail_after;
} pwt_alloc_state;

PWT_UNUSED static void *pwt_malloc(void *user, size_t n)
{
    pwt_alloc_state *s = (pwt_alloc_state *)user;
    void *p;
    if (++s->calls > s->fail_after && s->fail_after >= 0) return NULL;
    p = malloc(n);
    if (p) s->live++;
    return p;
}

PWT_UNUSED static void *pwt_realloc(void *user, void *p, size_t n)
{
    pwt_alloc_state *s = (pwt_alloc_state *)user;
    void *q;
    if (++s->calls > s->fail_after && s->fail_after >= 0) return NULL;
    q = realloc(p, n);
    if (q && !p) s->live++;
    return q;
}

PWT_UNUSED static void pwt_free(void *user, void *p)
{
    pwt_alloc_state *s = (pwt_alloc_state *)user;
    if (p) s->live--;
    free(p);
}

/* A per-process temporary file name, /tmp/pw_test_STEM_PID_K.EXT, in a
 * static buffer (the last four stay valid). */
PWT_UNUSED static const char *pwt_tmp(const char *stem, int k, const char *ext)
{
    static char buf[4][256];
    static int n;
    char *p = buf[n++ & 3];
    snprintf(p, 256, "/tmp/pw_test_%s_%ld_%d%s", stem, PWT_PID_, k, ext);
    return p;
}

/* An allocator (for a header's X_allocator: malloc_fn, realloc_fn,
 * free_fn) whose call number pwt_alloc_fail_at (from 0; -1: none) fails,
 * counting the calls (pwt_alloc_calls) and the blocks still live
 * (pwt_alloc_live): a test runs an operation with each call failing in
 * turn and checks it reports running out of memory and leaks nothing. */
static int pwt_alloc_live, pwt_alloc_fail_at = -1, pwt_alloc_calls;

static PWT_UNUSED void *pwt_alloc_malloc(void *u, size_t n)
{
    void *p;
    (void)u;
    if (pwt_alloc_calls++ == pwt_alloc_fail_at) return NULL;
    if ((p = malloc(n)) != NULL) pwt_alloc_live++;
    return p;
}

static PWT_UNUSED void *pwt_alloc_realloc(void *u, void *p, size_t n)
{
    void *q;
    (void)u;
    if (pwt_alloc_calls++ == pwt_alloc_fail_at) return NULL;
    q = realloc(p, n);
    if (q && !p) pwt_alloc_live++;
    return q;
}

static PWT_UNUSED void pwt_alloc_free(void *u, void *p)
{
    (void)u;
    if (p) pwt_alloc_live--;
    free(p);
}

/* Runs the cases whose names contain argv[1] (all without it). With the
 * environment variable PWT_TIME set, each case's CPU time goes to stderr
 * ("TIME name seconds"), to find the slow ones. */
static int pwt_run_(const pwt_case *cases, int n, int argc, char **argv)
{
    int i, nfail = 0, timed = getenv("PWT_TIME") != NULL;
    for (i = 0; i < n; i++) {
        clock_t t0 = clock();
        if (argc > 1 && !strstr(cases[i].name, argv[1])) continue;
        pwt_name_ = cases[i].name;
        pwt_failed_ = 0;
        pwt_skipped_ = 0;
        cases[i].fn();
        if (timed) fprintf(stderr, "TIME %s %.2f\n", cases[i].name, (double)(clock() - t0) / CLOCKS_PER_SEC);
        if (pwt_failed_) nfail++;
        else if (!pwt_skipped_) printf("PASS %s\n", cases[i].name);
        fflush(stdout);
    }
    return nfail ? 1 : 0;
}

#define PWT_MAIN(cases)                                                          \
    int main(int argc, char **argv)                                              \
    {                                                                            \
        return pwt_run_(cases, (int)(sizeof(cases) / sizeof(cases[0])), argc, argv); \
    }

#endif
