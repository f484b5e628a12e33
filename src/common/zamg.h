/* zamg: a smoothed-aggregation multigrid preconditioner for the complex
 * Hermitian systems of zsparse.h, for meshes too large for IC(0).
 *
 * IC(0)-preconditioned CG needs about sqrt(n) iterations on a surface
 * Laplacian of n unknowns, so its time grows as n^1.5; a multigrid
 * V-cycle keeps the iteration count about constant. The systems pgp.h
 * solves are connection Laplacians: terms w |z_j - R z_i|^2 with unit
 * complex R, so the smooth (low-energy) vectors are not constant but turn
 * by R from unknown to unknown. The coarse spaces follow that:
 *
 *   - Aggregation (Vanek, Mandel, Brezina 1996): unknowns joined by a
 *     strong entry (|a_ij| at least 0.25 of the row's largest) are grouped
 *     around roots taken in index order, leftovers join their strongest
 *     aggregated neighbour.
 *   - Tentative prolongation, one entry per row: the phase that carries the
 *     aggregate's value from the root to the unknown along the edge that
 *     joined it (-a_ij / |a_ij|, which is R for a term as above), so the
 *     coarse vector 1 stands for a section parallel along those edges.
 *   - One damped Jacobi step smooths it (P = (I - omega D^-1 A) P_t,
 *     omega = 2/3), and the coarse matrix is P^H A P (Galerkin).
 *   - A V(1,1) cycle: forward Gauss-Seidel before the coarse correction,
 *     backward after, so the cycle is a symmetric positive definite
 *     preconditioner for CG; the coarsest level (at most 512 unknowns) is
 *     solved by a dense Cholesky factor.
 *   - The Gauss-Seidel sweeps are hybrid, so that they run on threads:
 *     each block of rows (zsparse.h's blocks, set by the number of rows
 *     alone) sweeps its own rows in order and reads the rows of other
 *     blocks as they were before the sweep; their terms are added to the
 *     row's diagonal as sum |a_ij| (the l1 smoother of Baker, Falgout,
 *     Kolev and Yang 2011), which keeps the sweep convergent however the
 *     blocks cut the graph. Within a block it is the plain sweep, so with
 *     at most 16 blocks of at least 4096 rows it smooths about as well.
 *
 *     pw_zamg M;
 *     pw_zamg_setup(NULL, &A, &M, &e);
 *     pw_zamg_solve(NULL, &A, &M, b, x, NULL, &stats, &e);
 *     pw_zamg_free(NULL, &M);
 *
 * Deterministic: the sweeps, residuals, restrictions and prolongations
 * of the cycle and the smoothed prolongation and Galerkin products of the
 * set-up run by blocks of rows on the matrix's run (zsparse.h), each
 * block writing its own rows, so the result is the same on any number of
 * threads; the aggregation and the coarsest factor run on one. */
#ifndef PW__ZAMG_V1
#define PW__ZAMG_V1

#include "zsparse.h"

#define PW__ZAMG_LEVELS 16
#define PW__ZAMG_COARSEST 512

/* One level: its matrix, the prolongation from the next (coarser) level's
 * unknowns (n x nc, complex CSR) and its adjoint (nc x n), the sums of
 * |a_ij| over each row's columns in other blocks (l1, n), and the cycle's
 * vectors (2n doubles). The cycle streams the matrices from memory, so it
 * reads them in single precision (av, pv, hv: A's, P's and P^H's values;
 * the set-up's products are in double, whose values it then frees, but
 * level 0's, the caller's): the cycle is a preconditioner, and CG's
 * products and residuals stay in double. */
typedef struct pw__zamg_level {
    pw_zcsr A;
    int nc;
    int *prow, *pcol;
    double *pval;
    pw_zcsr PH;
    double *l1;
    double *x, *b, *r;
    float *av, *pv, *hv;
    double *dinv;     /* 1 / (a_ii + l1_i) as the cycle reads a_ii, 0 where a_ii <= 0 */
    double *d0, *dd;  /* the diagonal at the set-up, and its change since (pw__zamg_refresh) */
    double *rho;      /* sum_J |p_iJ| of every row of P */
    int *dpos;        /* where each diagonal entry sits in A */
    int *xrow, *xpos; /* each row's entries in other blocks: positions in A */
} pw__zamg_level;

typedef struct pw_zamg {
    int levels;                          /* levels below the finest (0: A is the coarsest) */
    pw__zamg_level lev[PW__ZAMG_LEVELS]; /* lev[0].A: a copy of the caller's matrix's pattern holder (not owned) */
    int nc;                              /* unknowns of the coarsest level */
    double *chol;                        /* its dense Cholesky factor, nc x nc complex, lower */
    double *cx;                          /* scratch for the coarsest solve, 2 nc */
} pw_zamg;

/* ---- complex helpers ------------------------------------------------------ */

/* |v| of the complex number (v[0], v[1]) (no hypot: the values are far from
 * overflow, and hypot's care costs). */
PW__DEF double pw__zamg_abs(const double *v) { return sqrt(v[0] * v[0] + v[1] * v[1]); }

/* The diagonal entry of row i (real); 0 if absent. */
PW__DEF double pw__zamg_diag(const pw_zcsr *A, int i)
{
    int k;
    for (k = A->rowptr[i]; k < A->rowptr[i + 1]; k++)
        if (A->col[k] == i) return A->val[2 * k];
    return 0.0;
}

/* The strength threshold of row i: 0.25 of its largest off-diagonal |a_ij|
 * (0 for a row without any). On pgp's systems (bunny00 at 75K, 300K,
 * 1.2M) 0.25 takes 10-20% fewer V-cycles than 0.08, with levels of about
 * the same size and cost; 0.5 fewer still, but its coarser levels cost
 * more than that saves. */
PW__DEF double pw__zamg_strong(const pw_zcsr *A, int i)
{
    double m = 0.0;
    int k;
    for (k = A->rowptr[i]; k < A->rowptr[i + 1]; k++)
        if (A->col[k] != i) m = pw__zamg_abs(A->val + 2 * k) > m ? pw__zamg_abs(A->val + 2 * k) : m;
    return 0.25 * m;
}

/* ---- aggregation ---------------------------------------------------------- */

/* The tentative prolongation of A: agg[i], the aggregate of unknown i, and
 * (ph[2i], ph[2i+1]), its unit phase; returns the number of aggregates.
 * d[i]: theta times the largest off-diagonal |a_ij| of row i, the strength
 * threshold (relative to the row, not to the diagonal: a diagonal shift
 * must not cut the links). */
PW__DEF int pw__zamg_aggregate(const pw_zcsr *A, const double *d, int *agg, double *ph)
{
    int n = A->n, i, k, nc = 0;
    for (i = 0; i < n; i++) agg[i] = -1;
    for (i = 0; i < n; i++) { /* roots whose strong neighbours are all free */
        int free_all = 1;
        if (agg[i] >= 0) continue;
        for (k = A->rowptr[i]; k < A->rowptr[i + 1] && free_all; k++) {
            int j = A->col[k];
            double m = pw__zamg_abs(A->val + 2 * k);
            if (j != i && m >= d[i] && agg[j] >= 0) free_all = 0;
        }
        if (!free_all) continue;
        agg[i] = nc;
        ph[2 * i] = 1.0;
        ph[2 * i + 1] = 0.0;
        for (k = A->rowptr[i]; k < A->rowptr[i + 1]; k++) {
            int j = A->col[k];
            double m = pw__zamg_abs(A->val + 2 * k);
            if (j == i || m < d[i] || m == 0.0) continue;
            agg[j] = nc; /* z_j = R z_i with a_ji = -w R = conj(a_ij) */
            ph[2 * j] = -A->val[2 * k] / m;
            ph[2 * j + 1] = A->val[2 * k + 1] / m;
        }
        nc++;
    }
    for (i = 0; i < n; i++) { /* leftovers join their strongest aggregated neighbour */
        int best = -1;
        double bm = 0.0;
        if (agg[i] >= 0) continue;
        for (k = A->rowptr[i]; k < A->rowptr[i + 1]; k++) {
            int j = A->col[k];
            double m = pw__zamg_abs(A->val + 2 * k);
            if (j != i && agg[j] >= 0 && m > bm) {
                bm = m;
                best = k;
            }
        }
        if (best < 0) { /* isolated: an aggregate of its own */
            agg[i] = nc++;
            ph[2 * i] = 1.0;
            ph[2 * i + 1] = 0.0;
        } else { /* z_i = (-a_ij / |a_ij|) z_j */
            int j = A->col[best];
            double re = -A->val[2 * best] / bm, im = -A->val[2 * best + 1] / bm;
            agg[i] = agg[j];
            ph[2 * i] = re * ph[2 * j] - im * ph[2 * j + 1];
            ph[2 * i + 1] = re * ph[2 * j + 1] + im * ph[2 * j];
        }
    }
    return nc;
}

/* ---- sparse products -------------------------------------------------------- */

/* Scratch of a row-by-row product: per column of the result, its slot in
 * the row being built (-1: none) and its sum; the row's columns. */
typedef struct pw__zamg_acc {
    int *mark, *list;
    double *sum;
    int cnt;
} pw__zamg_acc;

PW__DEF void pw__zamg_acc_free(const pw_alloc *a, pw__zamg_acc *w)
{
    pw_free(a, w->mark);
    pw_free(a, w->list);
    pw_free(a, w->sum);
}

PW__DEF int pw__zamg_acc_init(const pw_alloc *a, int ncols, pw__zamg_acc *w, pw_err *e)
{
    int i;
    w->cnt = 0;
    w->mark = (int *)pw_alloc_array(a, (size_t)ncols, sizeof(int), "multigrid scratch", e);
    w->list = (int *)pw_alloc_array(a, (size_t)ncols, sizeof(int), "multigrid scratch", e);
    w->sum = (double *)pw_alloc_array(a, 2 * (size_t)ncols, sizeof(double), "multigrid scratch", e);
    if (!w->mark || !w->list || !w->sum) {
        pw__zamg_acc_free(a, w);
        return PW_ERR_NOMEM;
    }
    for (i = 0; i < ncols; i++) w->mark[i] = -1;
    return PW_OK;
}

/* Adds (re, im) to column c of the row being built. */
PW__DEF void pw__zamg_acc_add(pw__zamg_acc *w, int c, double re, double im)
{
    if (w->mark[c] < 0) {
        w->mark[c] = w->cnt;
        w->list[w->cnt++] = c;
        w->sum[2 * c] = w->sum[2 * c + 1] = 0.0;
    }
    w->sum[2 * c] += re;
    w->sum[2 * c + 1] += im;
}

/* Ends the row: its entries, columns increasing, into (col, val) from
 * position *nnz on. */
PW__DEF void pw__zamg_acc_flush(pw__zamg_acc *w, int *col, double *val, int *nnz)
{
    int m;
    pw__zsort(w->list, w->cnt);
    for (m = 0; m < w->cnt; m++) {
        int c = w->list[m];
        col[*nnz] = c;
        val[2 * *nnz] = w->sum[2 * c];
        val[2 * *nnz + 1] = w->sum[2 * c + 1];
        ++*nnz;
        w->mark[c] = -1;
    }
    w->cnt = 0;
}

/* A sparse matrix built row by row: row(ctx, i, w) adds the entries of
 * row i to w (columns below ncols), which are at most bound(ctx, i).
 * pw__zamg_rows builds it in one pass on run, by blocks of rows each with
 * its own scratch, each block writing its rows from where the bounds of
 * the rows before it end; the blocks then close up, in order. Each row
 * is the same as built alone. */
typedef struct pw__zamg_rowjob {
    void (*row)(const void *ctx, int i, pw__zamg_acc *w);
    int (*bound)(const void *ctx, int i);
    const void *ctx;
    const pw_zrun *run;
    int n;
} pw__zamg_rowjob;

typedef struct pw__zamg_pass {
    const pw__zamg_rowjob *job;
    pw_zcsr *C;
    pw__zamg_acc *w;
    size_t start[PW__ZBLOCKS + 1]; /* where each block's rows go */
    int nb;
} pw__zamg_pass;

/* Block b's rows, from p->start[b] on; row i's count into C->rowptr[i + 1]. */
PW__DEF void pw__zamg_pass_block(void *ctx, int b)
{
    const pw__zamg_pass *p = (const pw__zamg_pass *)ctx;
    pw_zcsr *C = p->C;
    int i, nnz = (int)p->start[b], hi = pw__zblock_start(C->n, p->nb, b + 1);
    for (i = pw__zblock_start(C->n, p->nb, b); i < hi; i++) {
        int at = nnz;
        p->job->row(p->job->ctx, i, &p->w[b]);
        pw__zamg_acc_flush(&p->w[b], C->col, C->val, &nnz);
        C->rowptr[i + 1] = nnz - at;
    }
}

PW__DEF int pw__zamg_rows(const pw_alloc *a, const pw__zamg_rowjob *job, int ncols, pw_zcsr *C, pw_err *e)
{
    pw__zamg_acc w[PW__ZBLOCKS];
    pw__zamg_pass p;
    int i, b, r = PW_OK;
    size_t at = 0;
    memset(C, 0, sizeof *C);
    p.job = job;
    p.C = C;
    p.w = w;
    p.nb = pw__zblocks(job->n);
    for (b = 0, p.start[0] = 0; b < p.nb; b++) { /* (a failed init has freed its own) */
        int hi = pw__zblock_start(job->n, p.nb, b + 1);
        if (r != PW_OK || (r = pw__zamg_acc_init(a, ncols, &w[b], e)) != PW_OK) memset(&w[b], 0, sizeof w[b]);
        for (p.start[b + 1] = p.start[b], i = pw__zblock_start(job->n, p.nb, b); i < hi; i++) {
            int m = job->bound(job->ctx, i);
            p.start[b + 1] += (size_t)(m < ncols ? m : ncols);
        }
    }
    if (r == PW_OK && p.start[p.nb] > (size_t)INT_MAX) r = pw_fail(e, PW_ERR_LIMIT, "multigrid: a product too large");
    C->n = job->n;
    C->rowptr = (int *)pw_alloc_array(a, (size_t)job->n + 1, sizeof(int), "multigrid matrix", e);
    C->col = (int *)pw_alloc_array(a, p.start[p.nb] + 1, sizeof(int), "multigrid matrix", e);
    C->val = (double *)pw_alloc_array(a, 2 * p.start[p.nb] + 2, sizeof(double), "multigrid matrix", e);
    if (r == PW_OK && C->rowptr && C->col && C->val) {
        pw__zfor(job->run, job->n, p.nb, pw__zamg_pass_block, &p);
        for (b = 0; b < p.nb; b++) { /* close up, and the row pointers */
            int lo = pw__zblock_start(job->n, p.nb, b), hi = pw__zblock_start(job->n, p.nb, b + 1);
            size_t cnt = 0;
            for (i = lo; i < hi; i++) cnt += (size_t)C->rowptr[i + 1];
            memmove(C->col + at, C->col + p.start[b], cnt * sizeof(int));
            memmove(C->val + 2 * at, C->val + 2 * p.start[b], 2 * cnt * sizeof(double));
            at += cnt;
        }
        C->rowptr[0] = 0;
        for (i = 0; i < job->n; i++) C->rowptr[i + 1] += C->rowptr[i];
    }
    for (b = 0; b < p.nb; b++) pw__zamg_acc_free(a, &w[b]);
    if (r != PW_OK || !C->rowptr || !C->col || !C->val) {
        pw_zcsr_free(a, C);
        return r != PW_OK ? r : PW_ERR_NOMEM;
    }
    {
        void *q = pw_realloc(a, C->col, (at + 1) * sizeof(int)); /* the bounds' slack back (kept if this fails) */
        if (q) C->col = (int *)q;
        q = pw_realloc(a, C->val, (2 * at + 2) * sizeof(double));
        if (q) C->val = (double *)q;
    }
    return PW_OK;
}

/* The operands of a product X Y. */
typedef struct pw__zamg_prod {
    const pw_zcsr *X, *Y;
} pw__zamg_prod;

/* Row i of X Y. */
PW__DEF void pw__zamg_prod_row(const void *ctx, int i, pw__zamg_acc *w)
{
    const pw__zamg_prod *p = (const pw__zamg_prod *)ctx;
    const pw_zcsr *X = p->X, *Y = p->Y;
    int k, q;
    for (k = X->rowptr[i]; k < X->rowptr[i + 1]; k++) {
        const double *x = X->val + 2 * k;
        int j = X->col[k];
        for (q = Y->rowptr[j]; q < Y->rowptr[j + 1]; q++) {
            const double *y = Y->val + 2 * q;
            pw__zamg_acc_add(w, Y->col[q], x[0] * y[0] - x[1] * y[1], x[0] * y[1] + x[1] * y[0]);
        }
    }
}

/* The entries of row i of X Y at most: those of the rows of Y it sums. */
PW__DEF int pw__zamg_prod_bound(const void *ctx, int i)
{
    const pw__zamg_prod *p = (const pw__zamg_prod *)ctx;
    int k, m = 0;
    for (k = p->X->rowptr[i]; k < p->X->rowptr[i + 1]; k++)
        m += p->Y->rowptr[p->X->col[k] + 1] - p->Y->rowptr[p->X->col[k]];
    return m;
}

/* C = X Y for complex CSR X and Y of ncols columns; C gets C->n = X->n
 * rows (on X's run). */
PW__DEF int pw__zamg_mul(const pw_alloc *a, const pw_zcsr *X, const pw_zcsr *Y, int ncols, pw_zcsr *C, pw_err *e)
{
    pw__zamg_prod p;
    pw__zamg_rowjob job;
    p.X = X;
    p.Y = Y;
    job.row = pw__zamg_prod_row;
    job.bound = pw__zamg_prod_bound;
    job.ctx = &p;
    job.run = X->run;
    job.n = X->n;
    return pw__zamg_rows(a, &job, ncols, C, e);
}

/* The conjugate transpose of an n x ncols complex CSR. */
PW__DEF int pw__zamg_adjoint(const pw_alloc *a, const pw_zcsr *P, int ncols, pw_zcsr *T, pw_err *e)
{
    int i, k, nnz = P->rowptr[P->n], *fill;
    memset(T, 0, sizeof *T);
    T->n = ncols;
    T->rowptr = (int *)pw_calloc_array(a, (size_t)ncols + 1, sizeof(int), "multigrid matrix", e);
    T->col = (int *)pw_alloc_array(a, (size_t)nnz + 1, sizeof(int), "multigrid matrix", e);
    T->val = (double *)pw_alloc_array(a, 2 * (size_t)nnz + 2, sizeof(double), "multigrid matrix", e);
    fill = (int *)pw_alloc_array(a, (size_t)ncols + 1, sizeof(int), "multigrid scratch", e);
    if (!T->rowptr || !T->col || !T->val || !fill) {
        pw_zcsr_free(a, T);
        pw_free(a, fill);
        return PW_ERR_NOMEM;
    }
    for (k = 0; k < nnz; k++) T->rowptr[P->col[k] + 1]++;
    for (i = 0; i < ncols; i++) T->rowptr[i + 1] += T->rowptr[i];
    memcpy(fill, T->rowptr, sizeof(int) * ((size_t)ncols + 1));
    for (i = 0; i < P->n; i++) /* rows in order: every row of T gets its columns increasing */
        for (k = P->rowptr[i]; k < P->rowptr[i + 1]; k++) {
            int q = fill[P->col[k]]++;
            T->col[q] = i;
            T->val[2 * q] = P->val[2 * k];
            T->val[2 * q + 1] = -P->val[2 * k + 1];
        }
    pw_free(a, fill);
    return PW_OK;
}

/* ---- one coarser level ------------------------------------------------------ */

/* The smoothed prolongation's inputs: level L's matrix, the tentative
 * prolongation (agg, ph: pw__zamg_aggregate) and the diagonal d. */
typedef struct pw__zamg_smooth {
    const pw_zcsr *A;
    const int *agg;
    const double *ph, *d;
} pw__zamg_smooth;

/* Row i of P = (I - omega D^-1 A) P_t. */
PW__DEF void pw__zamg_prolong_row(const void *ctx, int i, pw__zamg_acc *w)
{
    const pw__zamg_smooth *m = (const pw__zamg_smooth *)ctx;
    const pw_zcsr *A = m->A;
    const double omega = 2.0 / 3.0, s = m->d[i] > 0.0 ? omega / m->d[i] : 0.0;
    int k;
    pw__zamg_acc_add(w, m->agg[i], m->ph[2 * i], m->ph[2 * i + 1]);
    for (k = A->rowptr[i]; k < A->rowptr[i + 1]; k++) {
        const double *v = A->val + 2 * k, *p = m->ph + 2 * A->col[k];
        pw__zamg_acc_add(w, m->agg[A->col[k]], -s * (v[0] * p[0] - v[1] * p[1]), -s * (v[0] * p[1] + v[1] * p[0]));
    }
}

/* The entries of row i of P at most: one per entry of A's row i, and
 * its own aggregate. */
PW__DEF int pw__zamg_prolong_bound(const void *ctx, int i)
{
    const pw_zcsr *A = ((const pw__zamg_smooth *)ctx)->A;
    return A->rowptr[i + 1] - A->rowptr[i] + 1;
}

/* The smoothed prolongation P = (I - omega D^-1 A) P_t of level L (n x nc),
 * P_t given by agg and ph (pw__zamg_aggregate), into P. */
PW__DEF int pw__zamg_prolong(const pw_alloc *a, const pw__zamg_level *L, const int *agg, const double *ph,
                             const double *d, pw_zcsr *P, pw_err *e)
{
    pw__zamg_smooth m;
    pw__zamg_rowjob job;
    m.A = &L->A;
    m.agg = agg;
    m.ph = ph;
    m.d = d;
    job.row = pw__zamg_prolong_row;
    job.bound = pw__zamg_prolong_bound;
    job.ctx = &m;
    job.run = L->A.run;
    job.n = L->A.n;
    return pw__zamg_rows(a, &job, L->nc, P, e);
}

/* Level L's prolongation (from aggregates of L->A) and the next level's
 * matrix P^H A P into *C. */
PW__DEF int pw__zamg_coarsen(const pw_alloc *a, pw__zamg_level *L, pw_zcsr *C, pw_err *e)
{
    const pw_zcsr *A = &L->A;
    int n = A->n, i, r;
    int *agg = (int *)pw_alloc_array(a, (size_t)n, sizeof(int), "multigrid aggregates", e);
    double *ph = (double *)pw_alloc_array(a, 2 * (size_t)n, sizeof(double), "multigrid aggregates", e);
    double *d = (double *)pw_alloc_array(a, (size_t)n, sizeof(double), "multigrid aggregates", e);
    pw_zcsr P, PH, AP;
    memset(&P, 0, sizeof P);
    memset(&PH, 0, sizeof PH);
    memset(&AP, 0, sizeof AP);
    r = agg && ph && d ? PW_OK : PW_ERR_NOMEM;
    if (r == PW_OK) {
        for (i = 0; i < n; i++) d[i] = pw__zamg_strong(A, i);
        L->nc = pw__zamg_aggregate(A, d, agg, ph);
        for (i = 0; i < n; i++) d[i] = pw__zamg_diag(A, i);
        r = pw__zamg_prolong(a, L, agg, ph, d, &P, e);
    }
    if (r == PW_OK && (r = pw__zamg_adjoint(a, &P, L->nc, &PH, e)) == PW_OK) PH.run = A->run;
    if (r == PW_OK) r = pw__zamg_mul(a, A, &P, L->nc, &AP, e);
    if (r == PW_OK) r = pw__zamg_mul(a, &PH, &AP, L->nc, C, e);
    if (r == PW_OK) {
        L->prow = P.rowptr;
        L->pcol = P.col;
        L->pval = P.val;
        L->PH = PH;
    } else {
        pw_zcsr_free(a, &P);
        pw_zcsr_free(a, &PH);
    }
    pw_zcsr_free(a, &AP);
    pw_free(a, agg);
    pw_free(a, ph);
    pw_free(a, d);
    return r;
}

/* ---- the coarsest level: dense Cholesky --------------------------------------- */

/* Factors the n x n Hermitian A (sparse) plus the diagonal dd into the
 * dense lower L (row-major, complex) with L L^H = (A + dd) + shift
 * diag(A + dd); 0 when a pivot is not positive. */
PW__DEF int pw__zamg_chol_try(const pw_zcsr *A, const double *dd, double shift, double *L)
{
    int n = A->n, i, j, k;
    memset(L, 0, sizeof(double) * 2 * (size_t)n * n);
    for (i = 0; i < n; i++)
        for (k = A->rowptr[i]; k < A->rowptr[i + 1]; k++)
            if (A->col[k] <= i) {
                double *l = L + 2 * ((size_t)i * n + A->col[k]);
                l[0] = A->col[k] == i ? (A->val[2 * k] + dd[i]) * (1.0 + shift) : A->val[2 * k];
                l[1] = A->val[2 * k + 1];
            }
    for (j = 0; j < n; j++) {
        double *ljj = L + 2 * ((size_t)j * n + j), dj;
        for (k = 0; k < j; k++) {
            const double *v = L + 2 * ((size_t)j * n + k);
            ljj[0] -= v[0] * v[0] + v[1] * v[1];
        }
        if (!(ljj[0] > 0.0) || !pw_is_finite(ljj[0])) return 0;
        dj = ljj[0] = sqrt(ljj[0]);
        ljj[1] = 0.0;
        for (i = j + 1; i < n; i++) { /* L_ij = (A_ij - sum_k L_ik conj(L_jk)) / L_jj */
            double *lij = L + 2 * ((size_t)i * n + j);
            for (k = 0; k < j; k++) {
                const double *u = L + 2 * ((size_t)i * n + k), *v = L + 2 * ((size_t)j * n + k);
                lij[0] -= u[0] * v[0] + u[1] * v[1];
                lij[1] -= u[1] * v[0] - u[0] * v[1];
            }
            lij[0] /= dj;
            lij[1] /= dj;
        }
    }
    return 1;
}

/* x = (L L^H)^-1 b, dense, complex; x may be b. */
PW__DEF void pw__zamg_chol_solve(const double *L, int n, const double *b, double *x)
{
    int i, k;
    for (i = 0; i < n; i++) {
        double sr = b[2 * i], si = b[2 * i + 1];
        for (k = 0; k < i; k++) {
            const double *v = L + 2 * ((size_t)i * n + k), *y = x + 2 * k;
            sr -= v[0] * y[0] - v[1] * y[1];
            si -= v[0] * y[1] + v[1] * y[0];
        }
        x[2 * i] = sr / L[2 * ((size_t)i * n + i)];
        x[2 * i + 1] = si / L[2 * ((size_t)i * n + i)];
    }
    for (i = n - 1; i >= 0; i--) { /* L^H x = y: (L^H)_ik = conj(L_ki) */
        double sr = x[2 * i], si = x[2 * i + 1];
        for (k = i + 1; k < n; k++) {
            const double *v = L + 2 * ((size_t)k * n + i), *y = x + 2 * k;
            sr -= v[0] * y[0] + v[1] * y[1];
            si -= v[0] * y[1] - v[1] * y[0];
        }
        x[2 * i] = sr / L[2 * ((size_t)i * n + i)];
        x[2 * i + 1] = si / L[2 * ((size_t)i * n + i)];
    }
}

/* The entries of every row of level L in columns outside its block
 * (xrow, xpos: their positions in A), and the l1 terms of the smoother,
 * the sums of their |a_ij|. */
PW__DEF int pw__zamg_l1(const pw_alloc *a, pw__zamg_level *L, pw_err *e)
{
    const pw_zcsr *A = &L->A;
    int n = A->n, nb = pw__zblocks(n), b, i, k, m = 0;
    L->l1 = (double *)pw_alloc_array(a, (size_t)n, sizeof(double), "multigrid smoother", e);
    L->xrow = (int *)pw_alloc_array(a, (size_t)n + 1, sizeof(int), "multigrid smoother", e);
    for (b = 0; b < nb; b++) {
        int lo = pw__zblock_start(n, nb, b), hi = pw__zblock_start(n, nb, b + 1);
        for (k = A->rowptr[lo]; k < A->rowptr[hi]; k++) m += A->col[k] < lo || A->col[k] >= hi;
    }
    L->xpos = (int *)pw_alloc_array(a, (size_t)m + 1, sizeof(int), "multigrid smoother", e);
    if (!L->l1 || !L->xrow || !L->xpos) return PW_ERR_NOMEM;
    for (b = 0, m = 0; b < nb; b++) {
        int lo = pw__zblock_start(n, nb, b), hi = pw__zblock_start(n, nb, b + 1);
        for (i = lo; i < hi; i++) {
            double s = 0.0;
            L->xrow[i] = m;
            for (k = A->rowptr[i]; k < A->rowptr[i + 1]; k++)
                if (A->col[k] < lo || A->col[k] >= hi) {
                    s += pw__zamg_abs(A->val + 2 * k);
                    L->xpos[m++] = k;
                }
            L->l1[i] = s;
        }
    }
    L->xrow[n] = m;
    return PW_OK;
}

/* ---- the hierarchy and the cycle ---------------------------------------------- */

PW__DEF void pw_zamg_free(const pw_alloc *a, pw_zamg *M)
{
    int l;
    for (l = 0; l <= M->levels && l < PW__ZAMG_LEVELS; l++) {
        pw__zamg_level *L = &M->lev[l];
        if (l > 0) pw_zcsr_free(a, &L->A); /* level 0's matrix is the caller's */
        pw_free(a, L->prow);
        pw_free(a, L->pcol);
        pw_free(a, L->pval);
        pw_zcsr_free(a, &L->PH);
        pw_free(a, L->av);
        pw_free(a, L->pv);
        pw_free(a, L->hv);
        pw_free(a, L->xrow);
        pw_free(a, L->xpos);
        pw_free(a, L->dinv);
        pw_free(a, L->d0);
        pw_free(a, L->dd);
        pw_free(a, L->dpos);
        pw_free(a, L->rho);
        pw_free(a, L->l1);
        pw_free(a, L->x);
        pw_free(a, L->b);
        pw_free(a, L->r);
    }
    pw_free(a, M->chol);
    pw_free(a, M->cx);
    memset(M, 0, sizeof *M);
}

/* The single-precision copy of the 2 cnt values *v (for the cycle):
 * *out, and *v freed unless keep. */
PW__DEF int pw__zamg_single(const pw_alloc *a, double **v, size_t cnt, int keep, float **out, pw_err *e)
{
    size_t k;
    *out = (float *)pw_alloc_array(a, 2 * cnt + 2, sizeof(float), "multigrid matrix", e);
    if (!*out) return PW_ERR_NOMEM;
    for (k = 0; k < 2 * cnt; k++) (*out)[k] = (float)(*v)[k];
    if (!keep) {
        pw_free(a, *v);
        *v = NULL;
    }
    return PW_OK;
}

/* The sweeps' inverse diagonal of level L from its single-precision
 * values. */
PW__DEF void pw__zamg_dinv(const pw__zamg_level *L)
{
    int i, k;
    for (i = 0; i < L->A.n; i++) {
        double d = 0.0;
        for (k = L->A.rowptr[i]; k < L->A.rowptr[i + 1]; k++)
            if (L->A.col[k] == i) d = L->av[2 * k];
        L->dinv[i] = d > 0.0 ? 1.0 / (d + L->l1[i]) : 0.0;
    }
}

/* The coarsest level's dense factor, from its matrix plus its diagonal's
 * change (a growing shift where a pivot is not positive); 0 if none
 * worked. */
PW__DEF int pw__zamg_factor(const pw_zamg *M)
{
    const pw__zamg_level *L = &M->lev[M->levels];
    double shift = 0.0;
    int k;
    for (k = 0; k<40; k++, shift = shift> 0.0 ? 2.0 * shift : 1e-10)
        if (pw__zamg_chol_try(&L->A, L->dd, shift, M->chol)) return 1;
    return 0;
}

/* Level 0's single-precision values from A (the caller's matrix, whose
 * values may have changed since the set-up: pgp's steps change its
 * diagonal), and a change D of its diagonal carried to the coarse levels:
 * the Galerkin matrix of A + D is P^H A P + P^H D P, which each level
 * takes lumped on its diagonal, sum_J |(P^H D P)_IJ| bounded by sum_i
 * |p_iI| d_i sum_J |p_iJ| (the coarse levels stay positive definite; on
 * smooth vectors, whose phases the connection aligns, the bound is close
 * to the quadratic form: on zsparse/amg_diagonal_change the hierarchy so
 * updated takes the V-cycles of one set up anew, where the diagonal
 * alone, without the rest of P^H D P, takes up to 40% more); the
 * coarsest is factored again. 0 if that factor failed. */
PW__DEF int pw__zamg_refresh(const pw_zamg *M, const pw_zcsr *A)
{
    const pw__zamg_level *L0 = &M->lev[0];
    size_t k, cnt = 2 * (size_t)A->rowptr[A->n];
    int i, l, q, changed = 0;
    if (!L0->av) return 1; /* A is the coarsest level: no cycle reads it */
    for (k = 0; k < cnt; k++) L0->av[k] = (float)A->val[k];
    pw__zamg_dinv(L0);
    for (i = 0; i < A->n; i++) {
        double d = A->val[2 * L0->dpos[i]] - L0->d0[i];
        changed |= d != L0->dd[i];
        L0->dd[i] = d;
    }
    if (!changed) return 1;
    for (l = 0; l < M->levels; l++) {
        const pw__zamg_level *L = &M->lev[l], *C = &M->lev[l + 1];
        for (i = 0; i < C->A.n; i++) {
            double d = 0.0;
            for (q = L->PH.rowptr[i]; q < L->PH.rowptr[i + 1]; q++) {
                const float *h = L->hv + 2 * q;
                int j = L->PH.col[q];
                d += sqrt((double)h[0] * h[0] + (double)h[1] * h[1]) * L->rho[j] * L->dd[j];
            }
            C->dd[i] = d;
            if (l + 1 < M->levels) C->av[2 * C->dpos[i]] = (float)(C->d0[i] + d);
        }
        if (l + 1 < M->levels) pw__zamg_dinv(C);
    }
    return pw__zamg_factor(M);
}

/* Level L's diagonal at the set-up (d0, dpos; dd zero). */
PW__DEF int pw__zamg_diagonal(const pw_alloc *a, pw__zamg_level *L, pw_err *e)
{
    int i, k, n = L->A.n;
    L->d0 = (double *)pw_alloc_array(a, (size_t)n + 1, sizeof(double), "multigrid diagonal", e);
    L->dd = (double *)pw_calloc_array(a, (size_t)n + 1, sizeof(double), "multigrid diagonal", e);
    L->dpos = (int *)pw_alloc_array(a, (size_t)n + 1, sizeof(int), "multigrid diagonal", e);
    if (!L->d0 || !L->dd || !L->dpos) return PW_ERR_NOMEM;
    for (i = 0; i < n; i++)
        for (L->dpos[i] = -1, L->d0[i] = 0.0, k = L->A.rowptr[i]; k < L->A.rowptr[i + 1]; k++)
            if (L->A.col[k] == i) {
                L->dpos[i] = k;
                L->d0[i] = L->A.val[2 * k];
            }
    for (i = 0; i < n; i++)
        if (L->dpos[i] < 0) return pw_fail(e, PW_ERR_INVALID, "multigrid: row %d has no diagonal entry", i);
    return PW_OK;
}

/* The cycle's single-precision values: level 0's a copy of the caller's
 * (refreshed by every solve), the others' in place of the doubles, which
 * only the set-up needed (but the coarsest's, factored again when the
 * diagonal changes). */
PW__DEF int pw__zamg_singles(const pw_alloc *a, pw_zamg *M, pw_err *e)
{
    int l, i, k, r = PW_OK;
    for (l = 0; l <= M->levels && r == PW_OK; l++) {
        pw__zamg_level *L = &M->lev[l];
        r = pw__zamg_diagonal(a, L, e);
        if (l == M->levels || r != PW_OK) break;
        r = pw__zamg_single(a, &L->pval, (size_t)L->prow[L->A.n], 0, &L->pv, e);
        if (r == PW_OK) r = pw__zamg_single(a, &L->PH.val, (size_t)L->PH.rowptr[L->PH.n], 0, &L->hv, e);
        if (r == PW_OK && !(L->rho = (double *)pw_alloc_array(a, (size_t)L->A.n, sizeof(double), "multigrid", e)))
            r = PW_ERR_NOMEM;
        for (i = 0; r == PW_OK && i < L->A.n; i++)
            for (L->rho[i] = 0.0, k = L->prow[i]; k < L->prow[i + 1]; k++)
                L->rho[i] += sqrt((double)L->pv[2 * k] * L->pv[2 * k] + (double)L->pv[2 * k + 1] * L->pv[2 * k + 1]);
        if (r == PW_OK) r = pw__zamg_single(a, &L->A.val, (size_t)L->A.rowptr[L->A.n], l == 0, &L->av, e);
        if (r == PW_OK &&
            !(L->dinv = (double *)pw_alloc_array(a, (size_t)L->A.n, sizeof(double), "multigrid smoother", e)))
            r = PW_ERR_NOMEM;
        if (r == PW_OK) pw__zamg_dinv(L);
    }
    return r;
}

/* Builds the hierarchy of a Hermitian positive (semi)definite A whose
 * diagonal entries are all present; A must outlive M (level 0 uses it). */
PW__DEF int pw_zamg_setup(const pw_alloc *a, const pw_zcsr *A, pw_zamg *M, pw_err *e)
{
    int l = 0, r = PW_OK;
    memset(M, 0, sizeof *M);
    M->lev[0].A = *A;
    while (r == PW_OK && M->lev[l].A.n > PW__ZAMG_COARSEST && l + 1 < PW__ZAMG_LEVELS) {
        pw__zamg_level *L = &M->lev[l];
        size_t n2 = 2 * (size_t)L->A.n;
        L->x = (double *)pw_alloc_array(a, n2, sizeof(double), "multigrid vectors", e);
        L->b = (double *)pw_alloc_array(a, n2, sizeof(double), "multigrid vectors", e);
        L->r = (double *)pw_alloc_array(a, n2, sizeof(double), "multigrid vectors", e);
        if (!L->x || !L->b || !L->r) r = PW_ERR_NOMEM;
        if (r == PW_OK) r = pw__zamg_l1(a, L, e);
        if (r == PW_OK) r = pw__zamg_coarsen(a, L, &M->lev[l + 1].A, e);
        if (r != PW_OK) break;
        M->lev[l + 1].A.run = A->run;
        M->levels = ++l;
        if (M->lev[l].A.n * 10 > L->A.n * 9) break; /* aggregation stalls: solve here */
    }
    M->nc = M->lev[l].A.n;
    if (r == PW_OK && M->nc > 4 * PW__ZAMG_COARSEST)
        r = pw_fail(e, PW_ERR_INVALID, "multigrid: coarsening stopped at %d unknowns", M->nc);
    if (r == PW_OK) {
        M->chol = (double *)pw_alloc_array(a, 2 * (size_t)M->nc * M->nc, sizeof(double), "multigrid coarse factor", e);
        M->cx = (double *)pw_alloc_array(a, 2 * (size_t)M->nc, sizeof(double), "multigrid vectors", e);
        M->lev[l].x = (double *)pw_alloc_array(a, 2 * (size_t)M->nc, sizeof(double), "multigrid vectors", e);
        M->lev[l].b = (double *)pw_alloc_array(a, 2 * (size_t)M->nc, sizeof(double), "multigrid vectors", e);
        if (!M->chol || !M->cx || !M->lev[l].x || !M->lev[l].b) r = PW_ERR_NOMEM;
    }
    if (r == PW_OK) r = pw__zamg_singles(a, M, e);
    if (r == PW_OK && !pw__zamg_factor(M))
        r = pw_fail(e, PW_ERR_INVALID, "multigrid: the coarsest matrix is not positive definite");
    if (r != PW_OK) pw_zamg_free(a, M);
    return r;
}

/* One step of the cycle at one level, by blocks of rows. */
typedef struct pw__zamg_step {
    const pw__zamg_level *L, *C;
    int nb;
} pw__zamg_step;

/* The forward sweep of block b from x = 0 (rows of other blocks read 0,
 * the block's rows above the current one too: not swept yet), and what it
 * leaves of r = b - A x within the block: row i was solved with the
 * block's rows below it and (a_ii + l1_i) on the diagonal, so what is left
 * is l1_i x_i less the terms of the block's rows above it, which each row
 * subtracts from the rows below it as it is solved (a_ji = conj(a_ij):
 * only the lower part is read); pw__zamg_cross then subtracts the other
 * blocks' terms. A row without a positive diagonal (all zero, A being
 * semidefinite) keeps x_i = 0 and r_i = b_i. */
PW__DEF void pw__zamg_pre(void *ctx, int b)
{
    const pw__zamg_step *w = (const pw__zamg_step *)ctx;
    const pw_zcsr *A = &w->L->A;
    const float *av = w->L->av;
    const double *rhs = w->L->b;
    double *x = w->L->x, *r = w->L->r;
    int i, k, lo = pw__zblock_start(A->n, w->nb, b), hi = pw__zblock_start(A->n, w->nb, b + 1);
    for (i = lo; i < hi; i++) {
        double sr = rhs[2 * i], si = rhs[2 * i + 1], xr, xi, di = w->L->dinv[i];
        int k0 = A->rowptr[i], kd;
        for (k = k0; k < A->rowptr[i + 1] && A->col[k] < i; k++) {
            const float *v = av + 2 * k;
            const double *y = x + 2 * A->col[k];
            if (A->col[k] >= lo) {
                sr -= v[0] * y[0] - v[1] * y[1];
                si -= v[0] * y[1] + v[1] * y[0];
            }
        }
        kd = k;
        xr = x[2 * i] = sr * di;
        xi = x[2 * i + 1] = si * di;
        r[2 * i] = di > 0.0 ? w->L->l1[i] * xr : rhs[2 * i];
        r[2 * i + 1] = di > 0.0 ? w->L->l1[i] * xi : rhs[2 * i + 1];
        for (k = k0; k < kd; k++) { /* r_j -= conj(a_ij) x_i for the block's rows j above */
            const float *v = av + 2 * k;
            double *y = r + 2 * A->col[k];
            if (A->col[k] < lo) continue;
            y[0] -= v[0] * xr + v[1] * xi;
            y[1] -= v[0] * xi - v[1] * xr;
        }
    }
}

/* r_i -= the terms of row i from other blocks, over block b, once every
 * block is swept (pw__zamg_pre). */
PW__DEF void pw__zamg_cross(void *ctx, int b)
{
    const pw__zamg_step *w = (const pw__zamg_step *)ctx;
    const pw__zamg_level *L = w->L;
    const double *x = L->x;
    double *r = L->r;
    int i, q, hi = pw__zblock_start(L->A.n, w->nb, b + 1);
    for (i = pw__zblock_start(L->A.n, w->nb, b); i < hi; i++)
        for (q = L->xrow[i]; q < L->xrow[i + 1]; q++) {
            int k = L->xpos[q];
            const float *v = L->av + 2 * k;
            const double *y = x + 2 * L->A.col[k];
            r[2 * i] -= v[0] * y[0] - v[1] * y[1];
            r[2 * i + 1] -= v[0] * y[1] + v[1] * y[0];
        }
}

/* b_c = P^H r over block b of the coarse rows (the adjoint's rows: each
 * sum over the fine rows in order). */
PW__DEF void pw__zamg_restrict(void *ctx, int b)
{
    const pw__zamg_step *w = (const pw__zamg_step *)ctx;
    const pw_zcsr *H = &w->L->PH;
    const double *r = w->L->r;
    double *bc = w->C->b;
    int I, k, hi = pw__zblock_start(H->n, w->nb, b + 1);
    for (I = pw__zblock_start(H->n, w->nb, b); I < hi; I++) {
        double sr = 0.0, si = 0.0;
        for (k = H->rowptr[I]; k < H->rowptr[I + 1]; k++) {
            const float *h = w->L->hv + 2 * k;
            const double *y = r + 2 * H->col[k];
            sr += h[0] * y[0] - h[1] * y[1];
            si += h[0] * y[1] + h[1] * y[0];
        }
        bc[2 * I] = sr;
        bc[2 * I + 1] = si;
    }
}

/* x += P x_c over block b, and r = x: what the backward sweep reads of
 * the rows of other blocks. */
PW__DEF void pw__zamg_prolong_add(void *ctx, int b)
{
    const pw__zamg_step *w = (const pw__zamg_step *)ctx;
    const pw__zamg_level *L = w->L;
    const double *xc = w->C->x;
    int i, k, hi = pw__zblock_start(L->A.n, w->nb, b + 1);
    for (i = pw__zblock_start(L->A.n, w->nb, b); i < hi; i++) {
        double sr = L->x[2 * i], si = L->x[2 * i + 1];
        for (k = L->prow[i]; k < L->prow[i + 1]; k++) {
            const float *p = L->pv + 2 * k;
            const double *y = xc + 2 * L->pcol[k];
            sr += p[0] * y[0] - p[1] * y[1];
            si += p[0] * y[1] + p[1] * y[0];
        }
        L->x[2 * i] = L->r[2 * i] = sr;
        L->x[2 * i + 1] = L->r[2 * i + 1] = si;
    }
}

/* The backward sweep of block b: rows of other blocks read as they were
 * before it (r, pw__zamg_prolong_add). */
PW__DEF void pw__zamg_post(void *ctx, int b)
{
    const pw__zamg_step *w = (const pw__zamg_step *)ctx;
    const pw_zcsr *A = &w->L->A;
    const double *rhs = w->L->b, *old = w->L->r;
    double *x = w->L->x;
    int i, k, lo = pw__zblock_start(A->n, w->nb, b), hi = pw__zblock_start(A->n, w->nb, b + 1);
    for (i = hi - 1; i >= lo; i--) { /* x_i += (b - A x)_i / (a_ii + l1_i) */
        double sr = rhs[2 * i] + w->L->l1[i] * x[2 * i], si = rhs[2 * i + 1] + w->L->l1[i] * x[2 * i + 1],
               di = w->L->dinv[i];
        for (k = A->rowptr[i]; k < A->rowptr[i + 1]; k++) {
            int j = A->col[k];
            const float *v = w->L->av + 2 * k;
            const double *y = (j >= lo && j < hi ? x : old) + 2 * j;
            if (j == i) continue;
            sr -= v[0] * y[0] - v[1] * y[1];
            si -= v[0] * y[1] + v[1] * y[0];
        }
        if (di > 0.0) {
            x[2 * i] = sr * di;
            x[2 * i + 1] = si * di;
        }
    }
}

/* The V-cycle from level l: lev[l].x ~ A_l^-1 lev[l].b, from x = 0. */
PW__DEF void pw__zamg_cycle(const pw_zamg *M, int l)
{
    const pw__zamg_level *L = &M->lev[l];
    pw__zamg_step w, wc;
    int n;
    if (l == M->levels) {
        pw__zamg_chol_solve(M->chol, M->nc, L->b, L->x);
        return;
    }
    n = L->A.n;
    w.L = wc.L = L;
    w.C = wc.C = &M->lev[l + 1];
    w.nb = pw__zblocks(n);
    wc.nb = pw__zblocks(L->nc);
    pw__zfor(L->A.run, n, w.nb, pw__zamg_pre, &w);
    if (w.nb > 1) pw__zfor(L->A.run, n, w.nb, pw__zamg_cross, &w);
    pw__zfor(L->A.run, L->nc, wc.nb, pw__zamg_restrict, &wc);
    pw__zamg_cycle(M, l + 1);
    pw__zfor(L->A.run, n, w.nb, pw__zamg_prolong_add, &w);
    pw__zfor(L->A.run, n, w.nb, pw__zamg_post, &w);
}

/* z = one V-cycle applied to r (2n doubles each), with level 0's values
 * as the last set-up or solve saw them. */
PW__DEF void pw_zamg_apply(const pw_zamg *M, const double *r, double *z)
{
    const pw__zamg_level *L = &M->lev[0];
    memcpy(L->b, r, sizeof(double) * 2 * (size_t)L->A.n);
    pw__zamg_cycle(M, 0);
    memcpy(z, L->x, sizeof(double) * 2 * (size_t)L->A.n);
}

PW__DEF void pw__zamg_op(const void *M, const double *r, double *z) { pw_zamg_apply((const pw_zamg *)M, r, z); }

/* Solves A x = b as pw_zpcg_solve does, preconditioned by a V-cycle of M
 * (pw_zamg_setup of A). */
PW__DEF int pw_zamg_solve(const pw_alloc *a, const pw_zcsr *A, const pw_zamg *M, const double *b, double *x,
                          const pw_cg_options *o, pw_cg_stats *s, pw_err *e)
{
    pw__pcg_op op;
    op.precond = pw__zamg_op;
    op.actx = A;
    op.mctx = M;
    op.b = b;
    op.x = x;
    op.what = "multigrid PCG";
    if (!pw__zamg_refresh(M, A))
        return pw_fail(e, PW_ERR_INVALID, "multigrid: the coarsest matrix is not positive definite");
    return pw__zpcg_checked(a, &op, "zamg", o, s, e);
}

/* Unknowns from which multigrid pays against IC(0) (its setup costs about
 * ten IC(0)-PCG iterations; on pgp's systems the two break even near 20K
 * unknowns: the PGP of CGAL's bunny00, 37.7K unknowns, takes 10 V-cycles
 * where IC(0) takes 80), and the diagonal excess below which it is used: a matrix whose
 * diagonal exceeds the off-diagonal sums by more than 0.5% on average is so
 * well conditioned that IC(0) needs only a few iterations. */
#define PW_ZAMG_MIN_UNKNOWNS 20000
#define PW_ZAMG_MAX_EXCESS 0.005

/* The sums of A's diagonal and of the moduli of its other entries. */
PW__DEF void pw__zamg_sums(const pw_zcsr *A, double *dsum, double *off)
{
    int i, k;
    *dsum = *off = 0.0;
    for (i = 0; i < A->n; i++)
        for (k = A->rowptr[i]; k < A->rowptr[i + 1]; k++)
            if (A->col[k] == i) *dsum += A->val[2 * k];
            else *off += pw__zamg_abs(A->val + 2 * k);
}

/* 1 if multigrid pays on a matrix of n unknowns whose diagonal sums to
 * dsum and the moduli of its other entries to off: large and poorly
 * conditioned (the diagonal excess, (dsum - off) / dsum, small). */
PW__DEF int pw_zamg_pays_sums(int n, double dsum, double off)
{
    return n >= PW_ZAMG_MIN_UNKNOWNS && (dsum > 0.0 ? (dsum - off) / dsum : 0.0) < PW_ZAMG_MAX_EXCESS;
}

/* 1 if multigrid pays on A. */
PW__DEF int pw_zamg_pays(const pw_zcsr *A)
{
    double dsum, off;
    pw__zamg_sums(A, &dsum, &off);
    return pw_zamg_pays_sums(A->n, dsum, off);
}

/* Solves the Hermitian positive definite A x = b (x the warm start) by CG,
 * preconditioned by multigrid where it pays and by IC(0) otherwise (also
 * when the coarsening stalls); options and stopping rule as
 * pw_zpcg_solve. */
PW__DEF int pw_zpd_solve(const pw_alloc *a, const pw_zcsr *A, const double *b, double *x, const pw_cg_options *o,
                         pw_err *e)
{
    int r;
    if (pw_zamg_pays(A)) {
        pw_zamg M;
        pw_err se;
        pw_err_clear(&se);
        r = pw_zamg_setup(a, A, &M, &se);
        if (r == PW_OK) {
            r = pw_zamg_solve(a, A, &M, b, x, o, NULL, e);
            pw_zamg_free(a, &M);
            return r;
        }
        if (r != PW_ERR_INVALID) return pw_fail(e, r, "%s", se.msg);
    }
    return pw_zic0_solve(a, A, b, x, o, e);
}

#endif /* PW__ZAMG_V1 */
