/* bench_sparse: the sparse systems that lapped.h, pgp.h and lst.h really build,
 * dumped from real runs on real meshes by bench/sysdump (Matrix Market,
 * build/bench-data/systems), solved by patchwork's solvers exactly as the
 * headers call them and by Eigen's (libeigen3-dev, when bench/probe.sh
 * found it at build time), to the same relative residual, interleaved
 * round by round:
 *   patchwork  pcg:  pw_spd_factor + pw_spd_solve (lapped's patch
 *                    parametrisation, §3.4: LDLT or IC(0)-PCG by
 *                    sparse.h's rule), or pw_ic0_factor + pw_pcg_solve
 *                    where the header calls them (lst's clumps); zpcg,
 *                    zamg: pgp's orientation field and PGP by
 *                    pw_zpd_solve's rule: pw_zamg_setup + pw_zamg_solve
 *                    (multigrid) on large systems, pw_zic0_factor +
 *                    pw_zpcg_solve otherwise; lsq: pw_lsq_solve_small (lapped's
 *                    atlas charts and lst's fields: LDLT of the normal
 *                    equations or CGLS by the same rule; lst factors once
 *                    for three right-hand sides, timed here with one)
 *   Eigen      ConjugateGradient (its default diagonal preconditioner),
 *              ConjugateGradient + IncompleteCholesky, SimplicialLDLT
 *              (least squares: LeastSquaresConjugateGradient, and
 *              SimplicialLDLT of the normal equations).
 * Every timing includes what the solve needs from the matrix alone
 * (factorisations, preconditioners, orderings) and starts from the dumped
 * warm start; building the matrices is not timed for anyone. The residual
 * each one reaches is recomputed here from its x. Complex Hermitian systems
 * are std::complex<double> matrices on Eigen's side.
 * The systems of the mushroom ladder (4.6K..295K triangles) give the
 * growth exponents of each solver against the unknowns.
 * Usage: bench_sparse [DIR] (default build/bench-data/systems). */
#include "bench.h"
#include "../src/common/zamg.h"
#include "mm.h"
#ifdef BENCH_EIGEN
#include "peer_eigen.h"
#endif

#define MAX_SYS 64
#define NCONT 4 /* contenders: patchwork, then Eigen's three */

typedef struct sys {
    char name[160], kind[8], method[16], stage[40], mesh[40];
    int n, nnz, max_iter, lsq;
    int direct; /* the header solves it by LDLT (lapped's systems that pass sparse.h's rule) */
    double tol;
    mm_csr A;
    double *b, *x0;
    void *peer;
} sys;

typedef struct job {
    const sys *s;
    int method; /* -1 patchwork, else PEER_EIGEN_* */
    int reps;   /* solves per timed call: small systems are timed in batches */
    int iters, fail;
    double *x;
} job;

static const char *const names[NCONT] = {"patchwork", "Eigen CG (diagonal)", "Eigen CG + IncompleteCholesky",
                                         "Eigen SimplicialLDLT"};
static const char *const lsq_names[NCONT] = {"patchwork", "Eigen LeastSquaresCG", "-",
                                             "Eigen SimplicialLDLT (normal eq.)"};

/* ---- patchwork's solvers, as the headers call them --------------------------- */

static void run_pw1(job *j)
{
    const sys *s = j->s;
    pw_cg_options o = pw_cg_default_options();
    pw_cg_stats st;
    pw_err e;
    int r;
    pw_err_clear(&e);
    memset(&st, 0, sizeof st);
    o.tol = s->tol;
    o.max_iter = s->max_iter;
    memcpy(j->x, s->x0, sizeof(double) * (s->A.cplx ? 2 : 1) * (size_t)s->A.m);
    if (s->A.cplx) {
        pw_zcsr Z;
        pw_zic0 L;
        pw_zamg M;
        memset(&Z, 0, sizeof Z); /* no parallel-for: one thread */
        Z.n = s->A.n, Z.rowptr = s->A.rowptr, Z.col = s->A.col, Z.val = s->A.val;
        if (pw_zamg_pays(&Z) && (r = pw_zamg_setup(NULL, &Z, &M, &e)) == PW_OK) {
            r = pw_zamg_solve(NULL, &Z, &M, s->b, j->x, &o, &st, &e);
            pw_zamg_free(NULL, &M);
        } else if ((r = pw_zic0_factor(NULL, &Z, &L, &e)) == PW_OK) {
            r = pw_zpcg_solve(NULL, &Z, &L, s->b, j->x, &o, &st, &e);
            pw_zic0_free(NULL, &L);
        }
    } else {
        pw_csr R;
        pw_ic0 L;
        pw_spd S;
        R.n = s->A.n, R.m = s->A.m, R.rowptr = s->A.rowptr, R.col = s->A.col, R.val = s->A.val;
        if (s->lsq && s->direct) r = pw_lsq_solve_small(NULL, &R, s->b, j->x, &o, &e);
        else if (s->lsq) r = pw_lsq_solve(NULL, &R, s->b, j->x, &o, &st, &e);
        else if (!strcmp(s->kind, "cg")) r = pw_cg_solve(NULL, &R, s->b, j->x, &o, &st, &e);
        else if (s->direct && (r = pw_spd_factor(NULL, &R, &S, &e)) == PW_OK) {
            r = pw_spd_solve(NULL, &S, s->b, j->x, &o, &e);
            pw_spd_free(NULL, &S);
        } else if (!s->direct && (r = pw_ic0_factor(NULL, &R, &L, &e)) == PW_OK) {
            r = pw_pcg_solve(NULL, &R, &L, s->b, j->x, &o, &st, &e);
            pw_ic0_free(NULL, &L);
        }
    }
    j->iters = st.iterations;
    j->fail |= r != PW_OK && r != PW_ERR_NOCONVERGE; /* the headers accept the cap's iterate too */
}

static void run_pw(void *arg)
{
    job *j = (job *)arg;
    int r;
    for (r = 0; r < j->reps; r++) run_pw1(j);
}

#ifdef BENCH_EIGEN
static void run_eigen(void *arg)
{
    job *j = (job *)arg;
    const sys *s = j->s;
    int r;
    for (r = 0; r < j->reps; r++) {
        j->iters = peer_eigen_solve(s->peer, j->method, s->b, s->x0, s->tol, s->max_iter, j->x);
        j->fail |= j->iters < 0;
    }
}
#endif

/* ---- residuals --------------------------------------------------------------- */

/* y = A x (transposed: y = A^H x), real or complex. */
static void mul(const mm_csr *A, const double *x, double *y, int transposed)
{
    int i, k, w = A->cplx ? 2 : 1;
    memset(y, 0, sizeof(double) * w * (size_t)(transposed ? A->m : A->n));
    for (i = 0; i < A->n; i++)
        for (k = A->rowptr[i]; k < A->rowptr[i + 1]; k++) {
            const double *a = A->val + w * k;
            const double *xi = x + w * (transposed ? i : A->col[k]);
            double *yi = y + w * (transposed ? A->col[k] : i);
            if (!A->cplx) yi[0] += a[0] * xi[0];
            else if (!transposed) yi[0] += a[0] * xi[0] - a[1] * xi[1], yi[1] += a[0] * xi[1] + a[1] * xi[0];
            else yi[0] += a[0] * xi[0] + a[1] * xi[1], yi[1] += a[0] * xi[1] - a[1] * xi[0];
        }
}

static double norm(const double *v, size_t n)
{
    double s = 0;
    size_t i;
    for (i = 0; i < n; i++) s += v[i] * v[i];
    return sqrt(s);
}

/* |b - A x| / |b|, or for least squares |A^H (b - A x)| / |A^H b|. */
static double relres(const sys *s, const double *x)
{
    int w = s->A.cplx ? 2 : 1;
    size_t nr = (size_t)w * s->A.n, nc = (size_t)w * s->A.m, i;
    double *r = (double *)malloc(sizeof(double) * (nr + 1)), *g = (double *)malloc(sizeof(double) * (nc + 1)), q;
    mul(&s->A, x, r, 0);
    for (i = 0; i < nr; i++) r[i] = s->b[i] - r[i];
    if (s->lsq) {
        mul(&s->A, r, g, 1);
        q = norm(g, nc);
        mul(&s->A, s->b, g, 1);
        q /= norm(g, nc);
    } else
        q = norm(r, nr) / norm(s->b, nr);
    free(r);
    free(g);
    return q;
}

/* ---- the dumped systems ------------------------------------------------------ */

/* Whether sparse.h's rule solves s directly (pw_spd_factor for SPD
 * systems, pw_lsq_solve_small on the normal equations for least squares). */
static int takes_direct(const sys *s)
{
    pw_csr R, N;
    pw_ldlt F;
    pw_err e;
    int r, direct;
    R.n = s->A.n, R.m = s->A.m, R.rowptr = s->A.rowptr, R.col = s->A.col, R.val = s->A.val;
    memset(&N, 0, sizeof N);
    if (s->lsq && pw_csr_ata(NULL, &R, &N, &e)) return 0;
    direct = pw__try_direct(NULL, s->lsq ? &N : &R, s->lsq ? PW__DIRECT_MIN_LSQ : PW__DIRECT_MIN_SPD, &F, &r, &e);
    pw_ldlt_free(NULL, &F);
    pw_csr_free(NULL, &N);
    return direct;
}

static int load(const char *dir, const char *line, sys *s)
{
    char path[512];
    memset(s, 0, sizeof *s);
    if (sscanf(line, "%159s %7s %15s %39s %39s %d %d %lf %d", s->name, s->kind, s->method, s->stage, s->mesh, &s->n,
               &s->nnz, &s->tol, &s->max_iter) != 9)
        return 1;
    s->lsq = !strcmp(s->kind, "lsq");

    snprintf(path, sizeof path, "%s/%s.mtx", dir, s->name);
    if (mm_read_csr(path, &s->A)) return printf("bench_sparse: cannot read %s\n", path), 1;
    snprintf(path, sizeof path, "%s/%s.b.mtx", dir, s->name);
    s->b = mm_read_vec(path, s->A.n, s->A.cplx);
    snprintf(path, sizeof path, "%s/%s.x0.mtx", dir, s->name);
    s->x0 = mm_read_vec(path, s->A.m, s->A.cplx);
    if (!s->b || !s->x0) return printf("bench_sparse: cannot read the vectors of %s\n", s->name), 1;
    /* lapped's SPD systems and every least-squares one go through the rule;
     * lst's clumps are factored by IC(0) */
    s->direct = !s->A.cplx && (s->lsq || !strcmp(s->method, "lapped")) && takes_direct(s);
    return 0;
}

static void unload(sys *s)
{
#ifdef BENCH_EIGEN
    peer_eigen_free(s->peer);
#endif
    mm_csr_free(&s->A);
    free(s->b);
    free(s->x0);
}

/* The figures of one system: median wall time per contender, kept for the
 * growth exponents. */
typedef struct result {
    double t[NCONT];
    int ran[NCONT];
} result;

/* Rounds by size: a few milliseconds get 15 (after a warm-up round),
 * seconds get 3 (without). */
static int rounds(const sys *s) { return s->nnz < 50000 ? 15 : s->nnz < 150000 ? 7 : 3; }

/* The factorisation alone, which every patchwork solve here starts with
 * (LDLT where sparse.h's rule takes it, else IC(0)): median CPU time of
 * `runs`. */
static double factor_time(const sys *s, int runs)
{
    double t[64];
    int r;
    for (r = 0; r < runs && r < 64; r++) {
        pw_err e;
        double t0 = bench_cpu_now();
        if (s->A.cplx) {
            pw_zcsr Z;
            pw_zic0 L;
            memset(&Z, 0, sizeof Z);
            Z.n = s->A.n, Z.rowptr = s->A.rowptr, Z.col = s->A.col, Z.val = s->A.val;
            if (pw_zic0_factor(NULL, &Z, &L, &e) == PW_OK) pw_zic0_free(NULL, &L);
        } else {
            pw_csr R;
            pw_ic0 L;
            pw_spd S;
            R.n = s->A.n, R.m = s->A.m, R.rowptr = s->A.rowptr, R.col = s->A.col, R.val = s->A.val;
            if (s->direct && pw_spd_factor(NULL, &R, &S, &e) == PW_OK) pw_spd_free(NULL, &S);
            else if (!s->direct && pw_ic0_factor(NULL, &R, &L, &e) == PW_OK) pw_ic0_free(NULL, &L);
        }
        t[r] = bench_cpu_now() - t0;
    }
    return bench_stats(t, r).median;
}

static const char *describe(const sys *s, char *buf, size_t size)
{
    snprintf(buf, size, "%s %s, %s: %s n=%d, nnz=%d, tol %g", s->method, s->stage, s->mesh,
             s->lsq ? "least squares" : s->A.cplx ? "complex Hermitian" : "real SPD", s->A.m, s->nnz, s->tol);
    return buf;
}

#ifdef BENCH_EIGEN
/* What the two did, for the note of a row where patchwork is the slower:
 * iterations and their cost, or the direct factor's fill. */
static void slower_note(const sys *s, const bench_multi *m, int k, const job *pw, const job *peer, double ftime,
                        long fill, char *buf, size_t size)
{
    char a[32], b[32], c[32];
    double cp, cq;
    int pi = pw->iters > 0 ? pw->iters : 1, qi = peer->iters > 0 ? peer->iters : 1;
    bench_multi_stat(m, 0, &cp);
    bench_multi_stat(m, k, &cq);
    bench_fmt_time((cp - ftime) / pi, a, sizeof a);
    bench_fmt_time(ftime, c, sizeof c);
    if (s->direct)
        snprintf(buf, size, "both factor %s directly (up-looking LDLT after an approximate minimum degree ordering "
                 "with AMD's supervariables and element absorption; see docs/performance.md)",
                 s->lsq ? "the normal equations" : "A");
    else if (peer->method == PEER_EIGEN_LDLT && !s->lsq)
        snprintf(buf, size, "one sparse LDLT (AMD ordering; L has %.1fx the nonzeros of A's lower triangle) costs "
                 "less than %d IC(0)-PCG iterations of %s each; %s", fill / (0.5 * (s->nnz - s->A.n)), pw->iters, a,
                 !strcmp(s->method, "lapped") ? "sparse.h's rule keeps PCG here (see docs/performance.md)"
                 : !strcmp(s->method, "lst")  ? "lst's clumps stay with IC(0)-PCG (LDLT made the fill slower)"
                                              : "zsparse.h has no direct solver for the complex systems");
    else if (peer->method == PEER_EIGEN_LDLT)
        snprintf(buf, size, "forming and factoring the %d-unknown normal equations once costs less than %d CGLS "
                 "iterations of %s each at tol %g; sparse.h's rule keeps CGLS here (see docs/performance.md)",
                 s->A.m, pw->iters, a, s->tol);
    else if (s->lsq)
        snprintf(buf, size, "the same algorithm (CGLS, column-norm Jacobi): %d iterations of %s against Eigen's %d of "
                 "%s", pw->iters, a, peer->iters, bench_fmt_time(cq / qi, b, sizeof b));
    else
        snprintf(buf, size, "IC(0) cuts the iterations (%d against Eigen's %d) but each costs %s against %s (two "
                 "triangular solves) and the factorisation %s: at this size they balance", pw->iters, peer->iters, a,
                 bench_fmt_time(cq / qi, b, sizeof b), c);
}

static void eigen_rows(const sys *s, const bench_multi *m, const int *map, const job *jobs, double ftime, long fill)
{
    char desc[256], task[300], peer[96], note[300];
    int k;
    snprintf(task, sizeof task, "solve %s", describe(s, desc, sizeof desc));
    for (k = 1; k < m->n; k++) {
        snprintf(peer, sizeof peer, "Eigen %s %s", peer_eigen_version(), (s->lsq ? lsq_names : names)[map[k]] + 6);
        slower_note(s, m, k, &jobs[0], &jobs[map[k]], ftime, fill, note, sizeof note);
        bench_row_pair(task, m, k, peer, NULL, note);
    }
}
#endif

static void bench_system(sys *s, int emit_rows, result *res)
{
    job jobs[NCONT];
    void (*fn[NCONT])(void *);
    void *arg[NCONT];
    int map[NCONT], n = 0, k, runs = rounds(s);
    size_t xn = (size_t)(s->A.cplx ? 2 : 1) * s->A.m + 1;
    bench_multi m;
    char desc[256], task[300];
    int reps, r;
    double t1, ftime = 0.0;
#ifdef BENCH_EIGEN
    long fill = -1;
#endif
    memset(jobs, 0, sizeof jobs);
    memset(res, 0, sizeof *res);
    for (k = 0; k < NCONT; k++) {
        jobs[k].s = s;
        jobs[k].method = k - 1;
        jobs[k].reps = 1;
        jobs[k].x = (double *)calloc(xn, sizeof(double));
    }
    t1 = bench_now(); /* one patchwork solve sets the batch: rounds of >= 20 ms */
    run_pw(&jobs[0]);
    t1 = bench_now() - t1;
    reps = t1 > 0.02 ? 1 : t1 > 2e-5 ? (int)(0.02 / t1) : 1000;
    for (k = 0; k < NCONT; k++) jobs[k].reps = reps;
    fn[n] = run_pw, arg[n] = &jobs[0], map[n++] = 0;
#ifdef BENCH_EIGEN
    s->peer = peer_eigen_prepare(s->A.n, s->A.m, s->A.cplx, s->lsq, s->A.rowptr, s->A.col, s->A.val);
    for (k = 1; s->peer && k < NCONT; k++)
        if (!(s->lsq && k == 2)) fn[n] = run_eigen, arg[n] = &jobs[k], map[n++] = k;
#endif
    bench_interleave(&m, fn, arg, n, runs, s->nnz < 150000);
    for (k = 0; k < n; k++) /* per solve */
        for (r = 0; r < m.runs; r++) m.t[k][r] /= reps, m.c[k][r] /= reps;
    printf("%s\n", describe(s, desc, sizeof desc));
    if (reps > 1) printf("  (each round times %d solves in a row, per contender; figures are per solve)\n", reps);
    for (k = 0; k < n; k++) {
        job *j = &jobs[map[k]];
        double cpu;
        bench_stat st = bench_multi_stat(&m, k, &cpu);
        printf("  %-36s median %9.3f ms (%.3f..%.3f, %d runs) cpu %9.3f ms %5d it  residual %.2e%s\n",
               (s->lsq ? lsq_names : names)[map[k]], st.median * 1e3, st.min * 1e3, st.max * 1e3, st.runs,
               cpu * 1e3, j->iters, relres(s, j->x), j->fail ? "  FAILED" : "");
        res->t[map[k]] = st.median;
        res->ran[map[k]] = !j->fail;
    }
    if (!s->lsq && strcmp(s->kind, "cg")) {
        ftime = factor_time(s, runs);
        printf("  patchwork's %s factorisation alone: median %.3f ms\n", s->direct ? "LDLT" : "IC(0)", ftime * 1e3);
    }
#ifdef BENCH_EIGEN
    if (s->peer && !s->lsq) {
        fill = peer_eigen_ldlt_fill(s->peer);
        printf("  Eigen SimplicialLDLT's factor L: %ld nonzeros below the diagonal, %.1fx those of A's lower "
               "triangle\n", fill, fill / (0.5 * (s->nnz - s->A.n)));
    }
    if (emit_rows && n > 1) eigen_rows(s, &m, map, jobs, ftime, fill);
#endif
    fflush(stdout);
    if (emit_rows && n == 1) {
        char t[32];
        snprintf(task, sizeof task, "solve %s", describe(s, desc, sizeof desc));
        bench_row(task, bench_fmt_time(res->t[0], t, sizeof t), "skipped", "Eigen (libeigen3-dev) not found at build",
                  NULL, NULL, NULL, NULL);
    }
    for (k = 0; k < NCONT; k++) free(jobs[k].x);
}

/* Systems of a ladder: same method, stage and kind on "mushroom-*" meshes. */
static int on_ladder(const sys *s) { return !strncmp(s->mesh, "mushroom-", 9); }

static int same_group(const sys *a, const sys *b)
{
    return on_ladder(a) && on_ladder(b) && !strcmp(a->method, b->method) && !strcmp(a->stage, b->stage) &&
           !strcmp(a->kind, b->kind);
}

/* One growth exponent per solver for each ladder group of >= 3 rungs. */
static void growth(const sys *all, const result *res, int nsys)
{
    int i, j, k, done[MAX_SYS];
    memset(done, 0, sizeof done);
    for (i = 0; i < nsys; i++) {
        double x[MAX_SYS], y[MAX_SYS];
        int idx[MAX_SYS], cnt = 0;
        if (done[i] || !on_ladder(&all[i])) continue;
        for (j = i; j < nsys; j++)
            if (same_group(&all[i], &all[j])) idx[cnt++] = j, done[j] = 1;
        if (cnt < 3) continue;
        for (k = 0; k < NCONT; k++) {
            char method[128], over[160];
            int c = 0;
            for (j = 0; j < cnt; j++)
                if (res[idx[j]].ran[k]) x[c] = all[idx[j]].A.m, y[c++] = res[idx[j]].t[k];
            if (c < cnt) continue;
            snprintf(method, sizeof method, "solve %s %s: %s", all[i].method, all[i].stage,
                     (all[i].lsq ? lsq_names : names)[k]);
            snprintf(over, sizeof over, "unknowns, %d systems %.0f..%.0f (mushroom ladder)", cnt, x[0], x[cnt - 1]);
            bench_growth(method, bench_loglog_slope(x, y, cnt), over, NULL);
        }
    }
}

int main(int argc, char **argv)
{
    const char *dir = argc > 1 ? argv[1] : "build/bench-data/systems";
    static sys all[MAX_SYS];
    static result res[MAX_SYS];
    char path[512], line[512];
    FILE *idx;
    int n = 0, i, bad = 0;
    double t0 = bench_now();
#ifdef BENCH_EIGEN
    if (bench_peer_disabled("eigen")) {
        printf("bench_sparse: Eigen disabled by BENCH_NO_PEERS\n");
        bench_peer("Eigen", "skipped: disabled by BENCH_NO_PEERS");
        return 0;
    }
    bench_peer("Eigen", peer_eigen_version());
#else
    bench_peer("Eigen", "skipped: libeigen3-dev not found when bench_sparse was built");
#endif
    snprintf(path, sizeof path, "%s/index.txt", dir);
    if (!(idx = fopen(path, "r"))) {
        printf("bench_sparse: no systems in %s (bench/sysdump writes them; run.sh runs it first)\n", dir);
        bench_row("solve the systems of lapped.h, pgp.h and lst.h", "skipped", "-", "-", "-", "-", "-",
                  "no dumped systems: `make data` for the CGAL meshes, then bench/sysdump");
        return 0;
    }
    while (n < MAX_SYS && fgets(line, sizeof line, idx))
        if (load(dir, line, &all[n]) == 0) n++;
        else bad = 1;
    fclose(idx);
    if (n == 0)
        bench_row("solve the systems of lapped.h, pgp.h and lst.h", "skipped", "-", "-", "-", "-", "-",
                  "sysdump found no meshes to run the methods on: `make data` for the CGAL meshes");
    printf("%d systems from %s; times are medians of interleaved rounds (after a warm-up round below 400K "
           "nonzeros)\n", n, dir);
    for (i = 0; i < n; i++) {
        int j, largest = 1; /* rows for everything but the smaller rungs of a ladder */
        for (j = 0; j < n; j++)
            if (j != i && same_group(&all[i], &all[j]) && all[j].A.m > all[i].A.m) largest = 0;
        bench_system(&all[i], largest, &res[i]);
    }
    growth(all, res, n);
    for (i = 0; i < n; i++) unload(&all[i]);
    printf("whole bench: %.1f s\n", bench_now() - t0);
    return bad;
}
