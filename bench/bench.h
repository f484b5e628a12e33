/* bench.h: timing helpers for the benchmarks behind `make bench`.
 * Each measurement runs a body once to warm up, then `runs` times, and
 * reports the median with the spread (min..max). */
#ifndef PW_BENCH_H
#define PW_BENCH_H

#if !defined(_POSIX_C_SOURCE) || _POSIX_C_SOURCE < 199309L
#undef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 199309L
#endif
#include <time.h>
#include <stdio.h>
#include <stdlib.h>
#include <math.h>

#if defined(__GNUC__) || defined(__clang__)
#define BENCH_UNUSED __attribute__((unused))
#else
#define BENCH_UNUSED
#endif

static double bench_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int bench_cmp_(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

typedef struct bench_stat {
    double median, min, max; /* seconds */
    int runs;
} bench_stat;

static bench_stat bench_stats(double *t, int n)
{
    bench_stat s;
    qsort(t, (size_t)n, sizeof *t, bench_cmp_);
    s.runs = n;
    s.min = t[0];
    s.max = t[n - 1];
    s.median = n % 2 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2]);
    return s;
}

/* Times fn(arg) `runs` times after one warm-up call. */
static bench_stat bench_time(void (*fn)(void *), void *arg, int runs)
{
    double t[64];
    int i;
    if (runs > 64) runs = 64;
    fn(arg);
    for (i = 0; i < runs; i++) {
        double t0 = bench_now();
        fn(arg);
        t[i] = bench_now() - t0;
    }
    return bench_stats(t, runs);
}

/* Prints "name: median (spread, runs) [rate]": `items` per run gives a
 * throughput in `unit`/s when non-zero. */
static void bench_report(const char *name, bench_stat s, double items, const char *unit)
{
    printf("%-44s median %9.3f ms  (%.3f..%.3f ms, %d runs)", name, s.median * 1e3,
           s.min * 1e3, s.max * 1e3, s.runs);
    if (items > 0) printf("  %.2f M%s/s", items / s.median * 1e-6, unit);
    printf("\n");
    fflush(stdout);
}

/* Least-squares slope of log y against log x: the growth exponent of a
 * size ladder (1 = linear). */
BENCH_UNUSED static double bench_loglog_slope(const double *x, const double *y, int n)
{
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int i;
    for (i = 0; i < n; i++) {
        double lx = log(x[i]), ly = log(y[i]);
        sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
    }
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

#endif
