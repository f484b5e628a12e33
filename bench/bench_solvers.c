/* bench_solvers: the numerical core shared by the methods.
 *   - Jacobi-preconditioned CG on a 2D Dirichlet Laplacian (cold start and
 *     warm start from a nearby solution, as lapped textures re-solve);
 *   - CGLS on the edge least-squares form of the same problem;
 *   - Boykov-Kolmogorov max-flow on 4-connected grids with seam-like costs
 *     and constrained borders, as in graph-cut texture quilting.
 * Sizes 256x256 and 512x512 (unknowns or pixels). Runs in about 20 s;
 * the slowest solves are timed once. */
#include "bench/bench.h"
#include "src/common/sparse.h"
#include "src/common/graphcut.h"
#include "src/common/rng.h"

/* ---- CG on a Laplacian --------------------------------------------------- */

typedef struct cg_job {
    pw_csr A;
    double *b, *x, *x0;
    int iterations;
    double residual;
    int lsq;
} cg_job;

/* -Δu = f on a k x k grid, u = 0 outside (5-point stencil, SPD). */
static int build_laplacian(cg_job *j, int k)
{
    pw_triplets t;
    pw_rng r = pw_rng_seed(1, 1);
    int x, y, n = k * k, rc;
    pw_err e;
    pw_err_clear(&e);
    pw_triplets_init(&t, NULL, n, n, &e);
    j->b = (double *)malloc(sizeof(double) * (size_t)n);
    j->x = (double *)malloc(sizeof(double) * (size_t)n);
    j->x0 = (double *)calloc((size_t)n, sizeof(double));
    for (y = 0; y < k; y++)
        for (x = 0; x < k; x++) {
            int i = y * k + x;
            pw_triplets_add(&t, i, i, 4, &e);
            if (x > 0) pw_triplets_add(&t, i, i - 1, -1, &e);
            if (x + 1 < k) pw_triplets_add(&t, i, i + 1, -1, &e);
            if (y > 0) pw_triplets_add(&t, i, i - k, -1, &e);
            if (y + 1 < k) pw_triplets_add(&t, i, i + k, -1, &e);
            j->b[i] = pw_rng_double(&r) - 0.5;
        }
    rc = pw_csr_from_triplets(NULL, &t, &j->A, &e);
    pw_triplets_free(&t);
    return rc;
}

/* Edge least squares on the same grid: u_i - u_j = d per grid edge and a
 * weak penalty row per vertex (u_i = 0, weight 0.01) keeping it definite. */
static int build_edge_lsq(cg_job *j, int k)
{
    pw_triplets t;
    pw_rng r = pw_rng_seed(2, 2);
    int x, y, n = k * k, rows = 0, rc;
    pw_err e;
    pw_err_clear(&e);
    pw_triplets_init(&t, NULL, 2 * k * (k - 1) + n, n, &e);
    j->b = (double *)malloc(sizeof(double) * (size_t)t.n);
    j->x = (double *)malloc(sizeof(double) * (size_t)n);
    j->x0 = (double *)calloc((size_t)n, sizeof(double));
    for (y = 0; y < k; y++)
        for (x = 0; x < k; x++) {
            int i = y * k + x;
            if (x + 1 < k) {
                pw_triplets_add(&t, rows, i, 1, &e);
                pw_triplets_add(&t, rows, i + 1, -1, &e);
                j->b[rows++] = pw_rng_double(&r) - 0.5;
            }
            if (y + 1 < k) {
                pw_triplets_add(&t, rows, i, 1, &e);
                pw_triplets_add(&t, rows, i + k, -1, &e);
                j->b[rows++] = pw_rng_double(&r) - 0.5;
            }
            pw_triplets_add(&t, rows, i, 0.01, &e);
            j->b[rows++] = 0;
        }
    rc = pw_csr_from_triplets(NULL, &t, &j->A, &e);
    pw_triplets_free(&t);
    return rc;
}

static void run_cg(void *arg)
{
    cg_job *j = (cg_job *)arg;
    pw_cg_stats st;
    pw_cg_options o = pw_cg_default_options();
    pw_err e;
    pw_err_clear(&e);
    o.tol = 1e-8;
    memcpy(j->x, j->x0, sizeof(double) * (size_t)j->A.m);
    if (j->lsq)
        pw_lsq_solve(NULL, &j->A, j->b, j->x, &o, &st, &e);
    else
        pw_cg_solve(NULL, &j->A, j->b, j->x, &o, &st, &e);
    j->iterations = st.iterations;
    j->residual = st.residual;
}

static void free_job(cg_job *j)
{
    pw_csr_free(NULL, &j->A);
    free(j->b);
    free(j->x);
    free(j->x0);
}

/* bench_time with runs = 1 skips the warm-up: for the solves that take
 * seconds, where one run is steady enough. */
static bench_stat time_runs(void (*fn)(void *), void *arg, int runs)
{
    double t;
    if (runs > 1) return bench_time(fn, arg, runs);
    t = bench_now();
    fn(arg);
    t = bench_now() - t;
    return bench_stats(&t, 1);
}

static void bench_cg(int k, int cold_runs, int warm_runs)
{
    cg_job j;
    char name[96];
    bench_stat s;
    int i;
    memset(&j, 0, sizeof j);
    if (build_laplacian(&j, k)) return;
    s = time_runs(run_cg, &j, cold_runs);
    snprintf(name, sizeof name, "cg laplacian %dx%d cold (%d it)", k, k, j.iterations);
    bench_report(name, s, (double)j.iterations * j.A.rowptr[j.A.n], "nnz-it");
    /* warm start: the solution with a 1% perturbation, as when a
     * parametrisation is re-solved after a small change */
    for (i = 0; i < j.A.n; i++) j.x0[i] = j.x[i] * (1.0 + 0.01 * sin(i * 0.1));
    s = time_runs(run_cg, &j, warm_runs);
    snprintf(name, sizeof name, "cg laplacian %dx%d warm (%d it)", k, k, j.iterations);
    bench_report(name, s, (double)j.iterations * j.A.rowptr[j.A.n], "nnz-it");
    free_job(&j);
}

static void bench_lsq(int k, int runs)
{
    cg_job j;
    char name[96];
    bench_stat s;
    memset(&j, 0, sizeof j);
    j.lsq = 1;
    if (build_edge_lsq(&j, k)) return;
    s = time_runs(run_cg, &j, runs);
    snprintf(name, sizeof name, "cgls edges %dx%d (%d it)", k, k, j.iterations);
    bench_report(name, s, (double)j.iterations * j.A.rowptr[j.A.n], "nnz-it");
    free_job(&j);
}

/* ---- max-flow on seam grids --------------------------------------------- */

typedef struct flow_job {
    int w, h;
    float *hc, *vc; /* seam costs of the right and lower links of each pixel */
    pw_graph g;
    double flow;
} flow_job;

/* Costs like Kwatra's |A(s)-B(s)| + |A(t)-B(t)| for two smooth random
 * images: low-frequency differences with noise, so that seams have to
 * wander. */
static void seam_costs(flow_job *f)
{
    pw_rng r = pw_rng_seed(3, 3);
    int x, y, n = f->w * f->h;
    float *d = (float *)malloc(sizeof(float) * (size_t)n);
    f->hc = (float *)malloc(sizeof(float) * (size_t)n);
    f->vc = (float *)malloc(sizeof(float) * (size_t)n);
    for (y = 0; y < f->h; y++)
        for (x = 0; x < f->w; x++)
            d[y * f->w + x] = (float)(fabs(sin(x * 0.05) * cos(y * 0.07)) +
                                      0.3 * pw_rng_double(&r));
    for (y = 0; y < f->h; y++)
        for (x = 0; x < f->w; x++) {
            int i = y * f->w + x;
            f->hc[i] = x + 1 < f->w ? d[i] + d[i + 1] : 0;
            f->vc[i] = y + 1 < f->h ? d[i] + d[i + f->w] : 0;
        }
    free(d);
}

/* Builds the graph (part of the timing: it is part of every seam solve)
 * and runs the max-flow. Left column forced to the old patch (source),
 * right column to the new one (sink). */
static void run_flow(void *arg)
{
    flow_job *f = (flow_job *)arg;
    int x, y, w = f->w;
    pw_err e;
    pw_err_clear(&e);
    pw_graph_reset(&f->g, w * f->h, &e);
    for (y = 0; y < f->h; y++)
        for (x = 0; x < w; x++) {
            int i = y * w + x;
            if (x + 1 < w) pw_graph_add_edge(&f->g, i, i + 1, f->hc[i], f->hc[i], &e);
            if (y + 1 < f->h) pw_graph_add_edge(&f->g, i, i + w, f->vc[i], f->vc[i], &e);
        }
    for (y = 0; y < f->h; y++) {
        pw_graph_add_tweights(&f->g, y * w, HUGE_VAL, 0);
        pw_graph_add_tweights(&f->g, y * w + w - 1, 0, HUGE_VAL);
    }
    pw_graph_maxflow(&f->g, &f->flow, &e);
}

static void bench_flow(int w, int h, int runs)
{
    flow_job f;
    char name[96];
    bench_stat s;
    pw_err e;
    pw_err_clear(&e);
    memset(&f, 0, sizeof f);
    f.w = w;
    f.h = h;
    seam_costs(&f);
    if (pw_graph_init(&f.g, NULL, w * h, 2 * w * h, &e)) return;
    s = bench_time(run_flow, &f, runs);
    snprintf(name, sizeof name, "maxflow seam grid %dx%d", w, h);
    bench_report(name, s, (double)w * h, "node");
    pw_graph_free(&f.g);
    free(f.hc);
    free(f.vc);
}

int main(void)
{
    bench_cg(256, 3, 3);
    bench_cg(512, 1, 1);
    bench_lsq(128, 3);
    bench_lsq(256, 1);
    bench_flow(256, 256, 7);
    bench_flow(512, 512, 3);
    return 0;
}
