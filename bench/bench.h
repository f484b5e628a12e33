/* bench.h: timing helpers for the benchmarks behind `make bench`.
 * Each measurement runs a body once to warm up, then `runs` times, and
 * reports the median with the spread (min..max). */
#ifndef PW_BENCH_H
#define PW_BENCH_H

#if !defined(_POSIX_C_SOURCE) || _POSIX_C_SOURCE < 200809L
#undef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L
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

/* ---- peers: interleaved timing and the summary table ----------------------
 * A measurement against a peer runs the contenders interleaved, one run of
 * each per round (the order rotating from round to round), so that a noisy
 * neighbour on a shared machine slows both alike; ratios are then taken
 * pair by pair within each round. */

#define BENCH_MAXF 4

typedef struct bench_multi {
    int n, runs, warm;
    double t[BENCH_MAXF][64], c[BENCH_MAXF][64]; /* per round: wall, CPU seconds */
} bench_multi;

/* Runs fn[0..n-1] `runs` rounds (after one warm-up round if `warm`). */
static inline void bench_interleave(bench_multi *m, void (*const *fn)(void *), void *const *arg, int n,
                                    int runs, int warm)
{
    int r, j;
    if (runs > 64) runs = 64;
    if (n > BENCH_MAXF) n = BENCH_MAXF;
    m->n = n;
    m->runs = runs;
    m->warm = warm;
    for (j = 0; warm && j < n; j++) fn[j](arg[j]);
    for (r = 0; r < runs; r++)
        for (j = 0; j < n; j++) {
            int k = (j + r) % n;
            double t0 = bench_now(), c0 = bench_cpu_now();
            fn[k](arg[k]);
            m->c[k][r] = bench_cpu_now() - c0;
            m->t[k][r] = bench_now() - t0;
        }
}

/* Wall-clock statistics of contender k; *cpu (may be NULL) its CPU median. */
static inline bench_stat bench_multi_stat(const bench_multi *m, int k, double *cpu)
{
    double t[64], c[64];
    memcpy(t, m->t[k], sizeof(double) * (size_t)m->runs);
    memcpy(c, m->c[k], sizeof(double) * (size_t)m->runs);
    if (cpu) *cpu = bench_stats(c, m->runs).median;
    return bench_stats(t, m->runs);
}

/* Per-round ratios of contender a's time over b's (CPU time if cpu, else
 * wall-clock): their median and spread. */
static inline bench_stat bench_multi_ratio(const bench_multi *m, int a, int b, int cpu)
{
    double q[64];
    int r;
    for (r = 0; r < m->runs; r++) q[r] = cpu ? m->c[a][r] / m->c[b][r] : m->t[a][r] / m->t[b][r];
    return bench_stats(q, m->runs);
}

/* A duration with a unit that keeps 3 significant digits. */
static inline const char *bench_fmt_time(double s, char *buf, size_t size)
{
    if (s < 1e-3) snprintf(buf, size, "%.3g us", s * 1e6);
    else if (s < 1.0) snprintf(buf, size, "%.3g ms", s * 1e3);
    else snprintf(buf, size, "%.3g s", s);
    return buf;
}

/* The summary table that bench/run.sh prints at the end of `make bench`
 * (and writes to bench/results.md with `make bench-report`) is made of the
 * lines below, which any bench program may print among its own output
 * (run.sh hides them there), tab-separated, "-" for an empty field:
 *   ROW     task  patchwork  peer-figure  peer-name  ratio  paper-figure  runs/spread  [note]
 *   GROWTH  method  exponent  over-what  [note]
 *   PEER    name  version-or-"skipped: why"
 * ratio is patchwork's time over the peer's (< 1: patchwork faster), the
 * median of the per-round ratios (see bench_row_pair). */
static inline void bench_row(const char *task, const char *pw, const char *peer, const char *peer_name,
                             const char *ratio, const char *paper, const char *runs, const char *note)
{
    const char *f[8];
    int i;
    f[0] = task, f[1] = pw, f[2] = peer, f[3] = peer_name, f[4] = ratio, f[5] = paper, f[6] = runs, f[7] = note;
    printf("ROW");
    for (i = 0; i < 8; i++) printf("\t%s", f[i] && *f[i] ? f[i] : "-");
    printf("\n");
    fflush(stdout);
}

/* A row for a patchwork time against a peer's (contender k against
 * contender 0 of m): figures are wall-clock medians with the CPU-time
 * medians in brackets; the ratio is the median of the per-round ratios of
 * CPU time (on a shared machine the wall clock also counts the time other
 * processes held the core; the per-round wall ratio follows in the spread
 * field). `note` is printed only when patchwork is not clearly the faster
 * (ratio above 0.95). */
static inline void bench_row_pair(const char *task, const bench_multi *m, int peer, const char *peer_name,
                                  const char *paper, const char *slower_note)
{
    char a[80], b[80], q[32], sp[160], t0[32], t1[32];
    double ca, cb;
    bench_stat sa = bench_multi_stat(m, 0, &ca), sb = bench_multi_stat(m, peer, &cb);
    bench_stat qc = bench_multi_ratio(m, 0, peer, 1), qw = bench_multi_ratio(m, 0, peer, 0);
    snprintf(a, sizeof a, "%s (cpu %s)", bench_fmt_time(sa.median, t0, sizeof t0), bench_fmt_time(ca, t1, sizeof t1));
    snprintf(b, sizeof b, "%s (cpu %s)", bench_fmt_time(sb.median, t0, sizeof t0), bench_fmt_time(cb, t1, sizeof t1));
    snprintf(q, sizeof q, "%.2f", qc.median);
    snprintf(sp, sizeof sp, "%d rounds%s; ratio %.2f..%.2f; wall-time ratio %.2f (%.2f..%.2f)", m->runs,
             m->warm ? "" : " (no warm-up)", qc.min, qc.max, qw.median, qw.min, qw.max);
    bench_row(task, a, b, peer_name, q, paper, sp, qc.median > 0.95 ? slower_note : NULL);
}

/* Thread scaling: fn(one) on one thread against fn(two) on two, interleaved
 * `runs` rounds after a warm-up, wall time (what threads shorten); prints
 * the medians and the speed-up and emits a row whose peer is the one-thread
 * run. `same`: whether the two results were compared equal bit for bit. */
static inline void bench_threads_row(const char *task, void (*fn)(void *), void *one, void *two, int runs,
                                     int (*same)(void *, void *))
{
    void (*fns[2])(void *);
    void *args[2];
    bench_multi m;
    bench_stat a, b, q;
    char fa[32], fb[32], ratio[32], sp[160], t0[32];
    int eq;
    fns[0] = fns[1] = fn;
    args[0] = two, args[1] = one;
    bench_interleave(&m, fns, args, 2, runs, 1);
    b = bench_multi_stat(&m, 0, NULL);
    a = bench_multi_stat(&m, 1, NULL);
    q = bench_multi_ratio(&m, 0, 1, 0);
    eq = same(one, two);
    printf("threads: %s: 1 thread %s, 2 threads %s, speed-up %.2fx (rounds %.2f..%.2f); results %s\n", task,
           bench_fmt_time(a.median, fa, sizeof fa), bench_fmt_time(b.median, fb, sizeof fb), 1.0 / q.median,
           1.0 / q.max, 1.0 / q.min, eq ? "identical" : "DIFFER");
    snprintf(ratio, sizeof ratio, "%.2f", q.median);
    snprintf(sp, sizeof sp, "%d rounds, wall time; speed-up %.2fx (%.2f..%.2f); results %s", runs, 1.0 / q.median,
             1.0 / q.max, 1.0 / q.min, eq ? "identical" : "DIFFER");
    bench_row(task, bench_fmt_time(b.median, fb, sizeof fb), bench_fmt_time(a.median, t0, sizeof t0),
              "the same on 1 thread", ratio, NULL, sp, NULL);
}

static inline void bench_growth(const char *method, double exponent, const char *over, const char *note)
{
    printf("GROWTH\t%s\t%.2f\t%s\t%s\n", method, exponent, over && *over ? over : "-", note && *note ? note : "-");
    fflush(stdout);
}

static inline void bench_peer(const char *name, const char *version)
{
    printf("PEER\t%s\t%s\n", name, version);
    fflush(stdout);
}

/* Where the benchmarks write their inputs and pictures (never committed):
 * $BENCH_DATA, which bench/run.sh sets, or build/bench-data. */
static inline const char *bench_data_dir(void)
{
    const char *d = getenv("BENCH_DATA");
    return d && *d ? d : "build/bench-data";
}

/* 1 if the peer `name` is to be treated as absent: BENCH_NO_PEERS lists
 * names (or "all"), to try the skip paths on a machine that has them. */
static inline int bench__has_word(const char *s, const char *w)
{
    const char *p;
    size_t n = strlen(w);
    for (p = s; (p = strstr(p, w)) != NULL; p += n)
        if ((p == s || p[-1] == ' ' || p[-1] == ',') && (p[n] == '\0' || p[n] == ' ' || p[n] == ',')) return 1;
    return 0;
}

static inline int bench_peer_disabled(const char *name)
{
    const char *s = getenv("BENCH_NO_PEERS");
    return s && (bench__has_word(s, "all") || bench__has_word(s, name));
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

/* A binary little-endian PLY (float xyz; uchar count, int indices per face)
 * of a polygon mesh, through w(ctx, data, size) (0 on success). The bench
 * runs on little-endian hosts, which write their floats and ints as is. */
static inline int bench_write_ply(int (*w)(void *, const void *, size_t), void *ctx, int nv, const float *pos,
                                  int nf, const int *fstart, const int *fv)
{
    char hdr[256];
    int f, bad;
    snprintf(hdr, sizeof hdr,
             "ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
             "property float z\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n",
             nv, nf);
    bad = w(ctx, hdr, strlen(hdr)) || w(ctx, pos, (size_t)nv * 12);
    for (f = 0; f < nf && !bad; f++) {
        unsigned char d = (unsigned char)(fstart[f + 1] - fstart[f]);
        bad = w(ctx, &d, 1) || w(ctx, fv + fstart[f], 4 * (size_t)d);
    }
    return bad;
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
