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
#include <string.h>
#include <math.h>

static inline double bench_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static inline int bench_cmp_(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

typedef struct bench_stat {
    double median, min, max; /* seconds */
    int runs;
} bench_stat;

static inline bench_stat bench_stats(double *t, int n)
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
static inline bench_stat bench_time(void (*fn)(void *), void *arg, int runs)
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
static inline void bench_report(const char *name, bench_stat s, double items, const char *unit)
{
    printf("%-44s median %9.3f ms  (%.3f..%.3f ms, %d runs)", name, s.median * 1e3,
           s.min * 1e3, s.max * 1e3, s.runs);
    if (items > 0) printf("  %.2f M%s/s", items / s.median * 1e-6, unit);
    printf("\n");
    fflush(stdout);
}

/* Process CPU time: the machine may be shared, and CPU time is what one
 * core spent whatever else runs (wall time stays the headline figure). */
static inline double bench_cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* bench_time with the warm-up call optional (a big rung would spend a
 * whole run, seconds, warming caches that one run fills anyway), and the
 * CPU time's median too (cpu_median may be NULL). */
static inline bench_stat bench_time_cpu(void (*fn)(void *), void *arg, int runs, int warm, double *cpu_median)
{
    double t[64], c[64];
    int i;
    if (runs > 64) runs = 64;
    if (warm) fn(arg);
    for (i = 0; i < runs; i++) {
        double t0 = bench_now(), c0 = bench_cpu_now();
        fn(arg);
        c[i] = bench_cpu_now() - c0;
        t[i] = bench_now() - t0;
    }
    if (cpu_median) *cpu_median = bench_stats(c, runs).median;
    return bench_stats(t, runs);
}

/* Least-squares slope of log y against log x: the growth exponent. */
static inline double bench_loglog_slope(const double *x, const double *y, int n)
{
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int i;
    for (i = 0; i < n; i++) {
        double lx = log(x[i]), ly = log(y[i]);
        sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
    }
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

/* ---- size ladders: 1-to-4 midpoint subdivision of a triangle mesh ---------- */

/* A polygon mesh as the headers pass it (every header's *_mesh has these
 * fields); the ladders copy the pointers in and out. */
typedef struct bench_mesh {
    int nverts;
    float *positions; /* nverts*3 */
    int nfaces;
    int *face_start;  /* nfaces+1 */
    int *face_verts;
} bench_mesh;

/* Edge-midpoint table: open addressing on the (smaller, larger) vertex pair. */
typedef struct bench_edge_map {
    long long *key;
    int *mid;
    size_t mask;
} bench_edge_map;

static inline int bench_edge_mid(bench_edge_map *em, bench_mesh *out, int a, int b)
{
    long long k = a < b ? (long long)a << 32 | (unsigned)b : (long long)b << 32 | (unsigned)a;
    size_t h = (size_t)((unsigned long long)k * 0x9E3779B97F4A7C15ull >> 20) & em->mask;
    int c, i;
    while (em->key[h] != -1 && em->key[h] != k) h = (h + 1) & em->mask;
    if (em->key[h] == k) return em->mid[h];
    em->key[h] = k;
    em->mid[h] = c = out->nverts++;
    for (i = 0; i < 3; i++)
        out->positions[3 * c + i] = 0.5f * (out->positions[3 * a + i] + out->positions[3 * b + i]);
    return c;
}

/* Every triangle of `in` (all faces must be triangles) split in four at its
 * edge midpoints: the surface stays the same flat triangles, which is all
 * the timing needs. Orientation is kept. Arrays are malloc'ed (free them
 * with bench_mesh_free). Returns 0 on success. */
static inline int bench_subdivide(const bench_mesh *in, bench_mesh *out)
{
    size_t cap = 1;
    int ne = 3 * in->nfaces, f; /* at most this many edges */
    bench_edge_map em;
    while (cap < (size_t)ne * 2) cap <<= 1;
    memset(out, 0, sizeof *out);
    em.key = (long long *)malloc(cap * sizeof *em.key);
    em.mid = (int *)malloc(cap * sizeof *em.mid);
    em.mask = cap - 1;
    out->positions = (float *)malloc(sizeof(float) * 3 * ((size_t)in->nverts + ne));
    out->face_start = (int *)malloc(sizeof(int) * (4 * (size_t)in->nfaces + 1));
    out->face_verts = (int *)malloc(sizeof(int) * 12 * (size_t)in->nfaces);
    if (!em.key || !em.mid || !out->positions || !out->face_start || !out->face_verts) return 1;
    memset(em.key, 0xff, cap * sizeof *em.key);
    memcpy(out->positions, in->positions, sizeof(float) * 3 * in->nverts);
    out->nverts = in->nverts;
    for (f = 0; f < in->nfaces; f++) {
        const int *v = in->face_verts + in->face_start[f];
        int m[3], t, k, q[4][3];
        if (in->face_start[f + 1] - in->face_start[f] != 3) return 1;
        for (k = 0; k < 3; k++) m[k] = bench_edge_mid(&em, out, v[k], v[(k + 1) % 3]);
        q[0][0] = v[0], q[0][1] = m[0], q[0][2] = m[2];
        q[1][0] = m[0], q[1][1] = v[1], q[1][2] = m[1];
        q[2][0] = m[2], q[2][1] = m[1], q[2][2] = v[2];
        q[3][0] = m[0], q[3][1] = m[1], q[3][2] = m[2];
        for (t = 0; t < 4; t++)
            for (k = 0; k < 3; k++) out->face_verts[12 * f + 3 * t + k] = q[t][k];
    }
    out->nfaces = 4 * in->nfaces;
    for (f = 0; f <= out->nfaces; f++) out->face_start[f] = 3 * f;
    free(em.key);
    free(em.mid);
    return 0;
}

static inline void bench_mesh_free(bench_mesh *m)
{
    free(m->positions);
    free(m->face_start);
    free(m->face_verts);
    memset(m, 0, sizeof *m);
}

/* Copies the five mesh fields from src to dst (pointers shared), between a
 * bench_mesh and any header's mesh type, in either direction. */
#define BENCH_MESH_COPY(dst, src)                                                  \
    ((dst).nverts = (src).nverts, (dst).positions = (src).positions,              \
     (dst).nfaces = (src).nfaces, (dst).face_start = (src).face_start,            \
     (dst).face_verts = (src).face_verts)

/* A size ladder: rung[0] = *base (subdivided first until it has at least
 * min_faces triangles), each further rung the previous one subdivided.
 * Takes ownership of *base's arrays (they must come from malloc, as the
 * headers' default allocator gives them). Returns 0 on success. */
static inline int bench_ladder(const bench_mesh *base, bench_mesh *rung, int nrungs, int min_faces)
{
    int i;
    rung[0] = *base;
    while (rung[0].nfaces < min_faces) {
        bench_mesh out;
        if (bench_subdivide(&rung[0], &out)) return 1;
        bench_mesh_free(&rung[0]);
        rung[0] = out;
    }
    for (i = 1; i < nrungs; i++)
        if (bench_subdivide(&rung[i - 1], &rung[i])) return 1;
    return 0;
}

/* Bounding-box diagonal of nverts points. */
static inline float bench_bbox_diagonal(const float *positions, int nverts)
{
    float lo[3], hi[3], d = 0.0f;
    int v, k;
    for (k = 0; k < 3; k++) lo[k] = hi[k] = positions[k];
    for (v = 0; v < nverts; v++)
        for (k = 0; k < 3; k++) {
            float x = positions[3 * v + k];
            lo[k] = x < lo[k] ? x : lo[k];
            hi[k] = x > hi[k] ? x : hi[k];
        }
    for (k = 0; k < 3; k++) d += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    return sqrtf(d);
}

#endif
