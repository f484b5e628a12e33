/* sparse: sparse matrices and a Jacobi-preconditioned conjugate gradient.
 *
 * Used for the least-squares parametrisations of lapped textures and lapped
 * solid textures (warm-started from the previous patch), for Laplacian
 * smoothing in PGP and for field interpolation. Everything is double
 * precision, single-threaded and sums in a fixed order, so the same inputs
 * give bit-identical results on every run.
 *
 * Build a matrix from (row, col, value) triplets added in any order, convert
 * it to compressed sparse rows once, then multiply or solve:
 *
 *     pw_triplets t;  pw_csr A;  pw_cg_stats st;  pw_err e;
 *     pw_err_clear(&e);
 *     pw_triplets_init(&t, NULL, n, n, &e);
 *     pw_triplets_add(&t, i, j, v, &e);  ...      (duplicates are summed)
 *     pw_csr_from_triplets(NULL, &t, &A, &e);
 *     pw_triplets_free(&t);
 *     pw_cg_solve(NULL, &A, b, x, NULL, &st, &e);  (x: guess in, solution out)
 *     pw_csr_free(NULL, &A);
 *
 * Solvers:
 *   pw_ldlt_factor / pw_ldlt_solve   a direct sparse LDLᵀ with a minimum-
 *                 degree ordering, for small SPD systems and several
 *                 right-hand sides (see its section below).
 *   pw_spd_factor / pw_spd_solve, pw_lsq_solve_small   LDLᵀ where it is
 *                 measured to win (a few hundred to 20,000 unknowns, low
 *                 fill), IC(0)-PCG or CGLS elsewhere ("choosing the
 *                 solver" below).
 *   pw_cg_solve   A x = b for symmetric positive (semi)definite A.
 *   pw_lsq_solve  min |A x - b| for any rectangular A, by CGLS: conjugate
 *                 gradients on the normal equations AᵀA x = Aᵀb without
 *                 forming AᵀA, which keeps the residual b - Ax in row space
 *                 and so loses less accuracy than CG on pw_csr_ata's output
 *                 (the condition number is not squared a second time).
 * Both stop when the relative residual falls to `tol`, recompute the true
 * residual before accepting (and restart from it if rounding has made the
 * recurrence drift), and on hitting the iteration cap return
 * PW_ERR_NOCONVERGE with the residual in the message while x holds the last
 * iterate: CG's best approximation in the energy norm (the A-norm of the
 * error never grows from one iterate to the next), so callers that can live
 * with the reported residual may use it. */
#ifndef PW__SPARSE_V1
#define PW__SPARSE_V1

#include "base.h"

/* Instrumentation for benchmarks and experiments: a program that defines
 * PW_SOLVE_HOOK(kind, A, b, x, opts) before including a header sees every
 * system a solver is given, before it is solved: kind is "cg", "pcg" or
 * "lsq" with A a const pw_csr *, or "zpcg" with A a const pw_zcsr *
 * (zsparse.h); b the right-hand side, x the warm start, opts the
 * pw_cg_options (tolerance) or NULL. Undefined, it costs nothing. */
#ifndef PW_SOLVE_HOOK
#define PW_SOLVE_HOOK(kind, A, b, x, opts) ((void)0)
#endif

/* ---- triplets ---------------------------------------------------------- */

/* A growable list of (row, col, value) entries of an n x m matrix. */
typedef struct pw_triplets {
    int n, m;       /* rows, columns */
    int count;      /* entries added */
    int *row, *col; /* count each */
    double *val;    /* count */
    size_t cap;     /* allocated entries in each array */
    pw_alloc alloc; /* copied at init; all-NULL means PW_MALLOC */
} pw_triplets;

/* Starts an empty n x m list. */
PW__DEF int pw_triplets_init(pw_triplets *t, const pw_alloc *a, int n, int m, pw_err *e)
{
    memset(t, 0, sizeof *t);
    if (a) t->alloc = *a;
    if (n < 0 || m < 0) return pw_fail(e, PW_ERR_INVALID, "sparse matrix size %dx%d is negative", n, m);
    t->n = n;
    t->m = m;
    return PW_OK;
}

/* Forgets the entries and keeps the memory, for building another matrix of
 * the same size. */
PW__DEF void pw_triplets_clear(pw_triplets *t) { t->count = 0; }

PW__DEF void pw_triplets_free(pw_triplets *t)
{
    pw_alloc a = t->alloc;
    pw_free(&a, t->row);
    pw_free(&a, t->col);
    pw_free(&a, t->val);
    memset(t, 0, sizeof *t);
    t->alloc = a;
}

/* Grows the three arrays together so that one capacity describes them all. */
PW__DEF int pw__triplets_grow(pw_triplets *t, pw_err *e)
{
    size_t ncap = t->cap ? t->cap * 2 : 64;
    void *p;
    if (ncap > (size_t)INT_MAX) ncap = (size_t)INT_MAX;
    if (ncap > (size_t)-1 / sizeof(double)) return pw_fail(e, PW_ERR_NOMEM, "sparse triplets: size overflow");
    /* Each successful realloc is kept even if a later one fails: the list
     * stays valid with the old capacity. */
    if (!(p = pw_realloc(&t->alloc, t->row, ncap * sizeof(int)))) goto nomem;
    t->row = (int *)p;
    if (!(p = pw_realloc(&t->alloc, t->col, ncap * sizeof(int)))) goto nomem;
    t->col = (int *)p;
    if (!(p = pw_realloc(&t->alloc, t->val, ncap * sizeof(double)))) goto nomem;
    t->val = (double *)p;
    t->cap = ncap;
    return PW_OK;
nomem:
    return pw_fail(e, PW_ERR_NOMEM, "out of memory growing sparse triplets to %lu entries", (unsigned long)ncap);
}

/* Adds v at (i, j). Entries at the same position are summed by
 * pw_csr_from_triplets. Fails on an index out of range or a non-finite v. */
PW__DEF int pw_triplets_add(pw_triplets *t, int i, int j, double v, pw_err *e)
{
    if (i < 0 || i >= t->n || j < 0 || j >= t->m)
        return pw_fail(e, PW_ERR_INVALID, "sparse entry (%d, %d) outside the %dx%d matrix", i, j, t->n, t->m);
    if (!pw_is_finite(v)) return pw_fail(e, PW_ERR_INVALID, "sparse entry (%d, %d) is not finite", i, j);
    if (t->count == INT_MAX) return pw_fail(e, PW_ERR_LIMIT, "sparse matrix has more than %d entries", INT_MAX);
    if ((size_t)t->count >= t->cap && pw__triplets_grow(t, e)) return PW_ERR_NOMEM;
    t->row[t->count] = i;
    t->col[t->count] = j;
    t->val[t->count] = v;
    t->count++;
    return PW_OK;
}

/* ---- compressed sparse rows -------------------------------------------- */

/* Row i holds col[k], val[k] for rowptr[i] <= k < rowptr[i+1]. Matrices made
 * here have strictly increasing columns within each row. */
typedef struct pw_csr {
    int n, m;    /* rows, columns */
    int *rowptr; /* n+1 */
    int *col;    /* rowptr[n] */
    double *val; /* rowptr[n] */
} pw_csr;

PW__DEF void pw_csr_free(const pw_alloc *a, pw_csr *A)
{
    if (!A) return;
    pw_free(a, A->rowptr);
    pw_free(a, A->col);
    pw_free(a, A->val);
    memset(A, 0, sizeof *A);
}

/* Allocates an n x m matrix with room for nnz entries; rowptr is zeroed. */
PW__DEF int pw__csr_alloc(const pw_alloc *a, pw_csr *A, int n, int m, int nnz, pw_err *e)
{
    memset(A, 0, sizeof *A);
    A->rowptr = (int *)pw_calloc_array(a, (size_t)n + 1, sizeof(int), "CSR rows", e);
    A->col = (int *)pw_alloc_array(a, (size_t)nnz, sizeof(int), "CSR columns", e);
    A->val = (double *)pw_alloc_array(a, (size_t)nnz, sizeof(double), "CSR values", e);
    if (!A->rowptr || !A->col || !A->val) {
        pw_csr_free(a, A);
        return PW_ERR_NOMEM;
    }
    A->n = n;
    A->m = m;
    return PW_OK;
}

/* Stable counting sort of the entries idx[0..cnt) by key[idx[k]] in [0, nkeys):
 * writes the order to out and the start of each key to start[0..nkeys]. */
PW__DEF void pw__counting_sort(const int *key, const int *idx, int cnt, int nkeys, int *start, int *out)
{
    int k;
    memset(start, 0, ((size_t)nkeys + 1) * sizeof(int));
    for (k = 0; k < cnt; k++) start[key[idx ? idx[k] : k] + 1]++;
    for (k = 0; k < nkeys; k++) start[k + 1] += start[k];
    for (k = 0; k < cnt; k++) {
        int id = idx ? idx[k] : k;
        out[start[key[id]]++] = id;
    }
    /* the scatter advanced each start to the next key's start: shift back */
    for (k = nkeys; k > 0; k--) start[k] = start[k - 1];
    start[0] = 0;
}

/* Sums the duplicates of each row of `order` (sorted by row, then column,
 * ties in insertion order, so the sums are taken in insertion order). */
PW__DEF void pw__csr_compress(const pw_triplets *t, const int *order, const int *start, pw_csr *A)
{
    int r, k, nz = 0;
    for (r = 0; r < t->n; r++) {
        A->rowptr[r] = nz;
        for (k = start[r]; k < start[r + 1]; k++) {
            int id = order[k];
            if (nz > A->rowptr[r] && A->col[nz - 1] == t->col[id]) {
                A->val[nz - 1] += t->val[id];
            } else {
                A->col[nz] = t->col[id];
                A->val[nz] = t->val[id];
                nz++;
            }
        }
    }
    A->rowptr[t->n] = nz;
}

/* Builds the CSR matrix of t: duplicates summed (in insertion order),
 * columns sorted within each row. Two stable counting sorts (by column,
 * then by row) give that order in O(entries + n + m). Entries whose sum is
 * zero are kept, so the structure depends only on the positions. */
PW__DEF int pw_csr_from_triplets(const pw_alloc *a, const pw_triplets *t, pw_csr *out, pw_err *e)
{
    int nkeys = pw_maxi(t->n, t->m), *start, *bycol, *order;
    memset(out, 0, sizeof *out);
    start = (int *)pw_alloc_array(a, (size_t)nkeys + 1, sizeof(int), "CSR build", e);
    bycol = (int *)pw_alloc_array(a, (size_t)t->count, sizeof(int), "CSR build", e);
    order = (int *)pw_alloc_array(a, (size_t)t->count, sizeof(int), "CSR build", e);
    if (!start || !bycol || !order || pw__csr_alloc(a, out, t->n, t->m, t->count, e)) {
        pw_free(a, start);
        pw_free(a, bycol);
        pw_free(a, order);
        return PW_ERR_NOMEM;
    }
    pw__counting_sort(t->col, NULL, t->count, t->m, start, bycol);
    pw__counting_sort(t->row, bycol, t->count, t->n, start, order);
    pw__csr_compress(t, order, start, out);
    pw_free(a, start);
    pw_free(a, bycol);
    pw_free(a, order);
    return PW_OK;
}

/* Checks the structure (row pointers, column range) and that every value is
 * finite, so that solvers can fail cleanly on matrices built elsewhere. */
PW__DEF int pw_csr_check(const pw_csr *A, pw_err *e)
{
    int i, k;
    if (!A || A->n < 0 || A->m < 0 || !A->rowptr || A->rowptr[0] != 0)
        return pw_fail(e, PW_ERR_INVALID, "malformed sparse matrix");
    for (i = 0; i < A->n; i++) {
        if (A->rowptr[i + 1] < A->rowptr[i])
            return pw_fail(e, PW_ERR_INVALID, "sparse matrix row %d has a negative length", i);
        for (k = A->rowptr[i]; k < A->rowptr[i + 1]; k++) {
            if (A->col[k] < 0 || A->col[k] >= A->m)
                return pw_fail(e, PW_ERR_INVALID,
                               "sparse matrix entry %d of row %d: column %d "
                               "outside 0..%d",
                               k - A->rowptr[i], i, A->col[k], A->m - 1);
            if (!pw_is_finite(A->val[k]))
                return pw_fail(e, PW_ERR_INVALID, "sparse matrix entry (%d, %d) is not finite", i, A->col[k]);
        }
    }
    return PW_OK;
}

/* y = A x   (x: m, y: n; y must not overlap x) */
PW__DEF void pw_csr_mul(const pw_csr *A, const double *x, double *y)
{
    int i, k;
    for (i = 0; i < A->n; i++) {
        double s = 0;
        for (k = A->rowptr[i]; k < A->rowptr[i + 1]; k++) s += A->val[k] * x[A->col[k]];
        y[i] = s;
    }
}

/* y = Aᵀ x   (x: n, y: m; y must not overlap x). Scatters row by row, so
 * each y[j] is summed in increasing row order. */
PW__DEF void pw_csr_mul_t(const pw_csr *A, const double *x, double *y)
{
    int i, k;
    for (k = 0; k < A->m; k++) y[k] = 0;
    for (i = 0; i < A->n; i++) {
        double xi = x[i];
        for (k = A->rowptr[i]; k < A->rowptr[i + 1]; k++) y[A->col[k]] += A->val[k] * xi;
    }
}

/* d[i] = A(i, i) for i < min(n, m); 0 where the diagonal entry is absent. */
PW__DEF void pw_csr_diag(const pw_csr *A, double *d)
{
    int i, k, nd = pw_mini(A->n, A->m);
    for (i = 0; i < nd; i++) {
        d[i] = 0;
        for (k = A->rowptr[i]; k < A->rowptr[i + 1]; k++)
            if (A->col[k] == i) d[i] += A->val[k];
    }
}

/* out = Aᵀ (m x n). Scanning A's rows in order makes every row of the
 * result come out with sorted columns. */
PW__DEF int pw_csr_transpose(const pw_alloc *a, const pw_csr *A, pw_csr *out, pw_err *e)
{
    int i, k, nnz = A->rowptr[A->n], *next;
    if (pw__csr_alloc(a, out, A->m, A->n, nnz, e)) return PW_ERR_NOMEM;
    next = (int *)pw_alloc_array(a, (size_t)A->m + 1, sizeof(int), "CSR transpose", e);
    if (!next) {
        pw_csr_free(a, out);
        return PW_ERR_NOMEM;
    }
    for (k = 0; k < nnz; k++) out->rowptr[A->col[k] + 1]++;
    for (k = 0; k < A->m; k++) out->rowptr[k + 1] += out->rowptr[k];
    memcpy(next, out->rowptr, ((size_t)A->m + 1) * sizeof(int));
    for (i = 0; i < A->n; i++) {
        for (k = A->rowptr[i]; k < A->rowptr[i + 1]; k++) {
            int p = next[A->col[k]]++;
            out->col[p] = i;
            out->val[p] = A->val[k];
        }
    }
    pw_free(a, next);
    return PW_OK;
}

/* Counts the entries of AᵀA row by row (At = Aᵀ) into C->rowptr; fails
 * when the total does not fit in an int. */
PW__DEF int pw__ata_count(const pw_csr *A, const pw_csr *At, int *mark, int *rowptr, pw_err *e)
{
    int i, k, q;
    int64_t nnz = 0;
    for (i = 0; i < At->n; i++) mark[i] = -1;
    rowptr[0] = 0;
    for (i = 0; i < At->n; i++) {
        for (k = At->rowptr[i]; k < At->rowptr[i + 1]; k++) {
            int r = At->col[k];
            for (q = A->rowptr[r]; q < A->rowptr[r + 1]; q++) {
                if (mark[A->col[q]] != i) {
                    mark[A->col[q]] = i;
                    nnz++;
                }
            }
        }
        if (nnz > INT_MAX) return pw_fail(e, PW_ERR_LIMIT, "A^T A has more than %d entries", INT_MAX);
        rowptr[i + 1] = (int)nnz;
    }
    return PW_OK;
}

/* Fills C = AᵀA (structure counted by pw__ata_count) with columns in order
 * of first touch. C(i,j) = sum over rows r of A(r,i) A(r,j), always in
 * increasing r, so C(i,j) and C(j,i) are bitwise equal. */
PW__DEF void pw__ata_fill(const pw_csr *A, const pw_csr *At, int *pos, pw_csr *C)
{
    int i, k, q;
    for (i = 0; i < At->n; i++) pos[i] = -1;
    for (i = 0; i < At->n; i++) {
        int nz = C->rowptr[i];
        for (k = At->rowptr[i]; k < At->rowptr[i + 1]; k++) {
            int r = At->col[k];
            double ari = At->val[k];
            for (q = A->rowptr[r]; q < A->rowptr[r + 1]; q++) {
                int j = A->col[q];
                /* pos[j] is a slot of row i only if it is not below row i's start */
                if (pos[j] < C->rowptr[i]) {
                    pos[j] = nz;
                    C->col[nz] = j;
                    C->val[nz++] = 0;
                }
                C->val[pos[j]] += ari * A->val[q];
            }
        }
    }
}

/* out = AᵀA (m x m), the normal-equations matrix of min |Ax - b|.
 * The product comes out with unsorted rows; since it is exactly symmetric
 * (see pw__ata_fill), its transpose is the same matrix with sorted rows. */
PW__DEF int pw_csr_ata(const pw_alloc *a, const pw_csr *A, pw_csr *out, pw_err *e)
{
    pw_csr At, C;
    int *work, r = PW_ERR_NOMEM;
    memset(out, 0, sizeof *out);
    memset(&C, 0, sizeof C);
    if (pw_csr_transpose(a, A, &At, e)) return PW_ERR_NOMEM;
    work = (int *)pw_alloc_array(a, (size_t)A->m + 1, sizeof(int), "A^T A", e);
    C.rowptr = (int *)pw_alloc_array(a, (size_t)A->m + 1, sizeof(int), "A^T A", e);
    if (!work || !C.rowptr) goto fail;
    if ((r = pw__ata_count(A, &At, work, C.rowptr, e)) != PW_OK) goto fail;
    r = PW_ERR_NOMEM;
    C.n = C.m = A->m;
    C.col = (int *)pw_alloc_array(a, (size_t)C.rowptr[C.n], sizeof(int), "A^T A", e);
    C.val = (double *)pw_alloc_array(a, (size_t)C.rowptr[C.n], sizeof(double), "A^T A", e);
    if (!C.col || !C.val) goto fail;
    pw__ata_fill(A, &At, work, &C);
    if (pw_csr_transpose(a, &C, out, e)) goto fail;
    pw_csr_free(a, &At);
    pw_csr_free(a, &C);
    pw_free(a, work);
    return PW_OK;
fail:
    pw_csr_free(a, &At);
    pw_csr_free(a, &C);
    pw_free(a, work);
    return r;
}

/* ---- conjugate gradients ----------------------------------------------- */

typedef struct pw_cg_options {
    int max_iter;         /* iteration cap; 0 = max(1000, 10 * unknowns) */
    double tol;           /* stop at relative residual <= tol; 0 = 1e-8 (see each solver) */
    pw_progress progress; /* optional; called every 64 iterations, may cancel */
} pw_cg_options;

typedef struct pw_cg_stats {
    int iterations;  /* iterations run (0 when the guess already satisfies tol) */
    double residual; /* relative residual of the returned x, recomputed from x */
    int converged;   /* 1 if residual <= tol */
} pw_cg_stats;

PW__DEF pw_cg_options pw_cg_default_options(void)
{
    pw_cg_options o;
    memset(&o, 0, sizeof o);
    o.max_iter = 0; /* chosen from the size at solve time */
    o.tol = 1e-8;
    return o;
}

PW__DEF double pw__dot(const double *x, const double *y, int n)
{
    double s = 0;
    int i;
    for (i = 0; i < n; i++) s += x[i] * y[i];
    return s;
}

/* r = b - A x */
PW__DEF void pw__residual(const pw_csr *A, const double *b, const double *x, double *r)
{
    int i;
    pw_csr_mul(A, x, r);
    for (i = 0; i < A->n; i++) r[i] = b[i] - r[i];
}

PW__DEF int pw__check_vec(const double *v, int n, const char *what, pw_err *e)
{
    int i;
    for (i = 0; i < n; i++)
        if (!pw_is_finite(v[i])) return pw_fail(e, PW_ERR_INVALID, "%s[%d] is not finite", what, i);
    return PW_OK;
}

/* Jacobi preconditioner: dinv[j] = 1 / d[j]. A zero or negative entry (an
 * empty row of a semidefinite matrix, or a matrix that is not positive
 * definite) falls back to 1, i.e. no scaling for that unknown. */
PW__DEF void pw__jacobi(double *d, int n)
{
    int i;
    for (i = 0; i < n; i++) d[i] = d[i] > 0 ? 1.0 / d[i] : 1.0;
}

/* State shared by CG and CGLS: settings, counters, the outcome. */
typedef struct pw__krylov {
    int n; /* unknowns */
    int max_iter;
    double tol;
    double bnorm; /* norm the residual is measured against */
    double rnorm; /* current (recurrence) residual norm */
    int it;
    int status; /* PW_OK, or why the loop stopped */
    const pw_progress *progress;
} pw__krylov;

PW__DEF void pw__krylov_init(pw__krylov *k, int n, const pw_cg_options *o)
{
    memset(k, 0, sizeof *k);
    k->n = n;
    k->tol = o && o->tol > 0 ? o->tol : 1e-8;
    k->max_iter = o ? o->max_iter : 0;
    if (k->max_iter <= 0) k->max_iter = n > INT_MAX / 10 ? INT_MAX : pw_maxi(1000, 10 * n);
    k->progress = o ? &o->progress : NULL;
}

/* Reports progress as the fraction of the way, in orders of magnitude, from
 * relative residual 1 down to the tolerance. Returns non-zero to stop. */
PW__DEF int pw__krylov_report(pw__krylov *k, pw_err *e)
{
    double done;
    if (!k->progress || !k->progress->fn || k->it % 64 != 0) return PW_OK;
    done = k->rnorm > 0 && k->tol < 1 ? log(k->rnorm / k->bnorm) / log(k->tol) : 1.0;
    done = done < 0 ? 0 : (done > 1 ? 1 : done);
    k->status = pw_report(k->progress, (float)done, "conjugate gradients", e);
    return k->status;
}

/* Fills the stats and turns a stop without convergence into an error that
 * carries the residual. `what` names the solver. */
PW__DEF int pw__krylov_finish(const pw__krylov *k, double true_rnorm, const char *what, pw_cg_stats *s, pw_err *e)
{
    double rel = true_rnorm / k->bnorm;
    if (s) {
        s->iterations = k->it;
        s->residual = rel;
        s->converged = rel <= k->tol;
    }
    if (rel <= k->tol) return PW_OK;
    if (k->status == PW_ERR_CANCELLED) return k->status;
    if (k->status)
        return pw_fail(e, PW_ERR_NOCONVERGE,
                       "%s broke down after %d iterations (the matrix is "
                       "not positive definite or the system is inconsistent): relative "
                       "residual %.3g, tolerance %.3g",
                       what, k->it, rel, k->tol);
    return pw_fail(e, PW_ERR_NOCONVERGE,
                   "%s stopped at the cap of %d iterations: relative "
                   "residual %.3g, tolerance %.3g",
                   what, k->it, rel, k->tol);
}

/* The loops below are fused so that each iteration streams the matrix once
 * and the vectors as few times as possible: CG on large grids is limited
 * by memory bandwidth, not arithmetic. The preconditioned residual
 * z = D⁻¹r is never stored. Every sum still runs in index order. */

/* q = A p; returns p·q (A square) or, if `norm`, q·q. */
PW__DEF double pw__mul_dot(const pw_csr *A, const double *p, double *q, int norm)
{
    double d = 0;
    int i, k;
    for (i = 0; i < A->n; i++) {
        double s = 0;
        for (k = A->rowptr[i]; k < A->rowptr[i + 1]; k++) s += A->val[k] * p[A->col[k]];
        q[i] = s;
        d += (norm ? s : p[i]) * s;
    }
    return d;
}

/* Returns r·D⁻¹r, and |r|² in *rr. */
PW__DEF double pw__precond_dots(const double *r, const double *dinv, int n, double *rr)
{
    double rz = 0, r2 = 0;
    int i;
    for (i = 0; i < n; i++) {
        rz += r[i] * dinv[i] * r[i];
        r2 += r[i] * r[i];
    }
    *rr = r2;
    return rz;
}

/* p = D⁻¹r + beta p (beta = 0 restarts along the preconditioned residual). */
PW__DEF void pw__new_direction(double *p, const double *r, const double *dinv, double beta, int n)
{
    int i;
    if (beta == 0)
        for (i = 0; i < n; i++) p[i] = dinv[i] * r[i];
    else
        for (i = 0; i < n; i++) p[i] = dinv[i] * r[i] + beta * p[i];
}

/* Work vectors of CG, one allocation: residual, direction, A times the
 * direction, inverse diagonal. */
typedef struct pw__cg_ws {
    double *r, *p, *q, *dinv;
} pw__cg_ws;

/* One CG step along p (q = A p, pq = p·q): x += alpha p, r -= alpha q,
 * then the next direction. Returns |r|²; *rz carries r·D⁻¹r along. */
PW__DEF double pw__cg_step(double *x, pw__cg_ws *w, int n, double pq, double *rz)
{
    double alpha = *rz / pq, rz1 = 0, rr = 0;
    int i;
    for (i = 0; i < n; i++) {
        double ri = w->r[i] - alpha * w->q[i];
        x[i] += alpha * w->p[i];
        w->r[i] = ri;
        rz1 += ri * w->dinv[i] * ri;
        rr += ri * ri;
    }
    pw__new_direction(w->p, w->r, w->dinv, rz1 / *rz, n);
    *rz = rz1;
    return rr;
}

/* Preconditioned CG iterations from x; r holds b - A x on entry. Restarts
 * from the true residual when the recurrence claims convergence that the
 * true residual does not confirm (rounding drift). */
PW__DEF void pw__cg_loop(const pw_csr *A, const double *b, double *x, pw__cg_ws *w, pw__krylov *k, pw_err *e)
{
    int n = k->n, restart = 1, fresh = 1;
    double rz = 0, rr;
    rz = pw__precond_dots(w->r, w->dinv, n, &rr);
    k->rnorm = sqrt(rr);
    for (;;) {
        double pq;
        if (k->rnorm <= k->tol * k->bnorm) {
            if (fresh) break;
            pw__residual(A, b, x, w->r);
            rz = pw__precond_dots(w->r, w->dinv, n, &rr);
            k->rnorm = sqrt(rr);
            fresh = restart = 1;
            if (k->rnorm <= k->tol * k->bnorm) break;
        }
        if (k->it >= k->max_iter || pw__krylov_report(k, e)) break;
        if (restart) pw__new_direction(w->p, w->r, w->dinv, 0, n);
        restart = 0;
        pq = pw__mul_dot(A, w->p, w->q, 0);
        if (!(pq > 0) || !pw_is_finite(rz / pq)) {
            k->status = PW_ERR_NOCONVERGE; /* p·Ap <= 0: not positive definite */
            break;
        }
        k->rnorm = sqrt(pw__cg_step(x, w, n, pq, &rz));
        k->it++;
        fresh = 0;
    }
}

/* Solves A x = b for a symmetric positive definite, or semidefinite with b
 * in its range, matrix A (n x n) by conjugate gradients with a Jacobi
 * preconditioner. x holds the initial guess (warm start) and receives the
 * solution. Stops when |b - A x| <= tol |b| (opts may be NULL; see
 * pw_cg_options). b = 0 gives x = 0 at once. Returns PW_ERR_INVALID for a
 * non-square or non-finite input, PW_ERR_NOCONVERGE (residual in the
 * message) at the iteration cap or on breakdown, PW_ERR_CANCELLED if the
 * progress callback stopped it: in those three cases x holds the last
 * iterate, never worse in the energy norm than the guess, and *s its
 * residual. */
PW__DEF int pw_cg_solve(const pw_alloc *a, const pw_csr *A, const double *b, double *x, const pw_cg_options *o,
                        pw_cg_stats *s, pw_err *e)
{
    pw__krylov k;
    pw__cg_ws w;
    int n, r;
    if (s) memset(s, 0, sizeof *s);
    if (pw_csr_check(A, e)) return PW_ERR_INVALID;
    n = A->n;
    if (A->m != n) return pw_fail(e, PW_ERR_INVALID, "CG needs a square matrix, not %dx%d", n, A->m);
    if (pw__check_vec(b, n, "CG right-hand side b", e) || pw__check_vec(x, n, "CG guess x", e)) return PW_ERR_INVALID;
    PW_SOLVE_HOOK("cg", A, b, x, o);
    pw__krylov_init(&k, n, o);
    k.bnorm = sqrt(pw__dot(b, b, n));
    if (k.bnorm == 0) {
        memset(x, 0, (size_t)n * sizeof *x);
        if (s) s->converged = 1;
        return PW_OK;
    }
    w.r = (double *)pw_alloc_array(a, (size_t)n * 4, sizeof(double), "CG vectors", e);
    if (!w.r) return PW_ERR_NOMEM;
    w.p = w.r + n;
    w.q = w.p + n;
    w.dinv = w.q + n;
    pw_csr_diag(A, w.dinv);
    pw__jacobi(w.dinv, n);
    pw__residual(A, b, x, w.r);
    pw__cg_loop(A, b, x, &w, &k, e);
    pw__residual(A, b, x, w.r); /* report what x achieves, not the recurrence */
    r = pw__krylov_finish(&k, sqrt(pw__dot(w.r, w.r, n)), "CG", s, e);
    pw_free(a, w.r);
    return r;
}

/* ---- incomplete Cholesky preconditioning -------------------------------- */

/* IC(0): a lower-triangular L with the sparsity of A's lower triangle and
 * L Lᵀ ~ A. For the Laplacian-like systems of mesh parametrisation it cuts
 * CG's iterations several-fold over Jacobi. Rows hold their diagonal last. */
typedef struct pw_ic0 {
    int n;
    int *rowptr, *col;
    double *val;
} pw_ic0;

PW__DEF void pw_ic0_free(const pw_alloc *a, pw_ic0 *L)
{
    pw_free(a, L->rowptr);
    pw_free(a, L->col);
    pw_free(a, L->val);
    memset(L, 0, sizeof *L);
}

/* Sparse dot product of rows i and j of L over columns below `below`. */
PW__DEF double pw__ic0_dot(const pw_ic0 *L, int i, int j, int below)
{
    int a = L->rowptr[i], b = L->rowptr[j], ea = L->rowptr[i + 1], eb = L->rowptr[j + 1];
    double s = 0.0;
    while (a < ea && b < eb && L->col[a] < below && L->col[b] < below) {
        if (L->col[a] == L->col[b]) s += L->val[a++] * L->val[b++];
        else if (L->col[a] < L->col[b]) a++;
        else b++;
    }
    return s;
}

/* Factors A + shift diag(A) into L; returns 0 when a pivot is not
 * positive (the caller retries with a larger shift). */
PW__DEF int pw__ic0_try(const pw_csr *A, double shift, pw_ic0 *L)
{
    int i, k, out = 0;
    for (i = 0; i < A->n; i++) {
        double diag = 0.0;
        for (k = A->rowptr[i]; k < A->rowptr[i + 1] && A->col[k] <= i; k++) {
            int j = A->col[k];
            if (j == i) diag = A->val[k] * (1.0 + shift);
            else {
                L->col[out] = j;
                L->val[out] = (A->val[k] - pw__ic0_dot(L, i, j, j)) / L->val[L->rowptr[j + 1] - 1];
                out++;
                L->rowptr[i + 1] = out; /* rows read themselves while being filled */
            }
        }
        L->rowptr[i + 1] = out;
        diag -= pw__ic0_dot(L, i, i, i);
        if (!(diag > 0.0) || !pw_is_finite(diag)) return 0;
        L->col[out] = i;
        L->val[out++] = sqrt(diag);
        L->rowptr[i + 1] = out;
    }
    return 1;
}

/* Factors a symmetric positive (semi)definite A with sorted columns and
 * every diagonal entry present. Breakdowns (IC(0) of an SPD matrix can meet
 * a non-positive pivot) are cured by a growing diagonal shift. */
PW__DEF int pw_ic0_factor(const pw_alloc *a, const pw_csr *A, pw_ic0 *L, pw_err *e)
{
    int i, k, nnz = 0;
    double shift = 0.0;
    memset(L, 0, sizeof *L);
    if (A->n != A->m) return pw_fail(e, PW_ERR_INVALID, "IC(0) needs a square matrix, not %dx%d", A->n, A->m);
    for (i = 0; i < A->n; i++)
        for (k = A->rowptr[i]; k < A->rowptr[i + 1] && A->col[k] <= i; k++) nnz++;
    L->n = A->n;
    L->rowptr = (int *)pw_calloc_array(a, (size_t)A->n + 1, sizeof(int), "IC(0) rows", e);
    L->col = (int *)pw_alloc_array(a, (size_t)nnz + (size_t)A->n, sizeof(int), "IC(0) columns", e);
    L->val = (double *)pw_alloc_array(a, (size_t)nnz + (size_t)A->n, sizeof(double), "IC(0) values", e);
    if (!L->rowptr || !L->col || !L->val) {
        pw_ic0_free(a, L);
        return PW_ERR_NOMEM;
    }
    for (k = 0; k<40; k++, shift = shift> 0.0 ? 2.0 * shift : 1e-3)
        if (pw__ic0_try(A, shift, L)) return PW_OK;
    pw_ic0_free(a, L);
    return pw_fail(e, PW_ERR_INVALID, "IC(0): the matrix is not positive definite");
}

/* z = (L Lᵀ)⁻¹ r. */
PW__DEF void pw_ic0_apply(const pw_ic0 *L, const double *r, double *z)
{
    int i, k;
    for (i = 0; i < L->n; i++) { /* L y = r */
        double s = r[i];
        for (k = L->rowptr[i]; k < L->rowptr[i + 1] - 1; k++) s -= L->val[k] * z[L->col[k]];
        z[i] = s / L->val[L->rowptr[i + 1] - 1];
    }
    for (i = L->n - 1; i >= 0; i--) { /* Lᵀ z = y, by columns of Lᵀ = rows of L */
        z[i] /= L->val[L->rowptr[i + 1] - 1];
        for (k = L->rowptr[i]; k < L->rowptr[i + 1] - 1; k++) z[L->col[k]] -= L->val[k] * z[i];
    }
}

/* A preconditioned system A x = b for the CG core: mul computes y = A x
 * and returns x . y, precond z = M^-1 r, both over n doubles; b and x (the
 * warm start, then the solution) hold n doubles; `what` names the solver in
 * errors. The complex Hermitian systems of zsparse.h run through the same
 * core: with complex numbers stored as (re, im) pairs and real step
 * lengths, every vector update is real, and Re(x^H y) is the real dot
 * product of the pairs. */
typedef struct pw__pcg_op {
    int n;
    double (*mul)(const void *ctx, const double *x, double *y);
    void (*precond)(const void *ctx, const double *r, double *z);
    const void *actx, *mctx;
    const double *b;
    double *x;
    const char *what;
} pw__pcg_op;

/* The PCG iterations shared by pw_pcg_solve and pw_zpcg_solve: b and x
 * already checked. */
PW__DEF int pw__pcg_run(const pw_alloc *a, const pw__pcg_op *op, const pw_cg_options *o, pw_cg_stats *s, pw_err *e)
{
    const double *b = op->b;
    double *x = op->x;
    pw__krylov k;
    double *r, *z, *p, *q, rz, rr;
    int n = op->n, i, ret;
    pw__krylov_init(&k, n, o);
    k.bnorm = sqrt(pw__dot(b, b, n));
    if (k.bnorm == 0) {
        memset(x, 0, (size_t)n * sizeof *x);
        if (s) s->converged = 1;
        return PW_OK;
    }
    if (!(r = (double *)pw_alloc_array(a, (size_t)n * 4, sizeof(double), "PCG vectors", e))) return PW_ERR_NOMEM;
    z = r + n;
    p = z + n;
    q = p + n;
    op->mul(op->actx, x, r);
    for (i = 0; i < n; i++) r[i] = b[i] - r[i];
    op->precond(op->mctx, r, z);
    memcpy(p, z, sizeof(double) * (size_t)n);
    rz = pw__dot(r, z, n);
    for (rr = pw__dot(r, r, n); (k.rnorm = sqrt(rr)) > k.tol * k.bnorm && k.it < k.max_iter; k.it++) {
        double pq = op->mul(op->actx, p, q), alpha, rz1;
        if (!(pq > 0) || !pw_is_finite(rz / pq) || pw__krylov_report(&k, e)) {
            if (k.status == PW_OK) k.status = PW_ERR_NOCONVERGE;
            break;
        }
        alpha = rz / pq;
        for (i = 0; i < n; i++) {
            x[i] += alpha * p[i];
            r[i] -= alpha * q[i];
        }
        op->precond(op->mctx, r, z);
        rz1 = pw__dot(r, z, n);
        for (i = 0; i < n; i++) p[i] = z[i] + rz1 / rz * p[i];
        rz = rz1;
        rr = pw__dot(r, r, n);
    }
    op->mul(op->actx, x, r); /* report what x achieves, not the recurrence */
    for (i = 0; i < n; i++) r[i] = b[i] - r[i];
    ret = pw__krylov_finish(&k, sqrt(pw__dot(r, r, n)), op->what, s, e);
    pw_free(a, r);
    return ret;
}

PW__DEF double pw__csr_op_mul(const void *A, const double *x, double *y)
{
    return pw__mul_dot((const pw_csr *)A, x, y, 0);
}

PW__DEF void pw__ic0_op(const void *M, const double *r, double *z) { pw_ic0_apply((const pw_ic0 *)M, r, z); }

/* CG preconditioned by an IC(0) factor M of A; otherwise as pw_cg_solve
 * (same options, stopping rule, warm start and errors). */
PW__DEF int pw_pcg_solve(const pw_alloc *a, const pw_csr *A, const pw_ic0 *M, const double *b, double *x,
                         const pw_cg_options *o, pw_cg_stats *s, pw_err *e)
{
    pw__pcg_op op;
    if (s) memset(s, 0, sizeof *s);
    if (pw_csr_check(A, e) || pw__check_vec(b, A->n, "PCG right-hand side b", e) ||
        pw__check_vec(x, A->n, "PCG guess x", e))
        return PW_ERR_INVALID;
    PW_SOLVE_HOOK("pcg", A, b, x, o);
    op.n = A->n;
    op.mul = pw__csr_op_mul;
    op.precond = pw__ic0_op;
    op.actx = A;
    op.mctx = M;
    op.b = b;
    op.x = x;
    op.what = "PCG";
    return pw__pcg_run(a, &op, o, s, e);
}

/* ---- least squares (CGLS) ---------------------------------------------- */

/* Work vectors of CGLS: r, q in row space (rows); s = Aᵀr, p, dinv in
 * column space (cols). */
typedef struct pw__cgls_ws {
    double *r, *q, *s, *p, *dinv;
} pw__cgls_ws;

/* r = b - A x, s = Aᵀ r; returns |s|. */
PW__DEF double pw__cgls_residual(const pw_csr *A, const double *b, const double *x, pw__cgls_ws *w)
{
    pw__residual(A, b, x, w->r);
    pw_csr_mul_t(A, w->r, w->s);
    return sqrt(pw__dot(w->s, w->s, A->m));
}

/* One CGLS step along p: x += alpha p with the residual updated in row
 * space, then s = Aᵀr and the next direction. Returns |s|², or -1 on
 * breakdown (A p = 0); *gamma carries s·D⁻¹s along. */
PW__DEF double pw__cgls_step(const pw_csr *A, double *x, pw__cgls_ws *w, double *gamma)
{
    int i, m = A->m;
    double qq = pw__mul_dot(A, w->p, w->q, 1), alpha, g1, ss;
    if (!(qq > 0) || !pw_is_finite(*gamma / qq)) return -1;
    alpha = *gamma / qq;
    for (i = 0; i < m; i++) x[i] += alpha * w->p[i];
    for (i = 0; i < A->n; i++) w->r[i] -= alpha * w->q[i];
    pw_csr_mul_t(A, w->r, w->s);
    g1 = pw__precond_dots(w->s, w->dinv, m, &ss);
    pw__new_direction(w->p, w->s, w->dinv, g1 / *gamma, m);
    *gamma = g1;
    return ss;
}

/* CGLS iterations, structured like pw__cg_loop with the normal-equation
 * residual s = Aᵀ(b - A x) in the role of CG's residual. */
PW__DEF void pw__cgls_loop(const pw_csr *A, const double *b, double *x, pw__cgls_ws *w, pw__krylov *k, pw_err *e)
{
    int m = A->m, restart = 1, fresh = 1;
    double gamma = 0, ss;
    k->rnorm = pw__cgls_residual(A, b, x, w);
    for (;;) {
        if (k->rnorm <= k->tol * k->bnorm) {
            if (fresh) break;
            k->rnorm = pw__cgls_residual(A, b, x, w);
            fresh = restart = 1;
            if (k->rnorm <= k->tol * k->bnorm) break;
        }
        if (k->it >= k->max_iter || pw__krylov_report(k, e)) break;
        if (restart) {
            gamma = pw__precond_dots(w->s, w->dinv, m, &ss);
            pw__new_direction(w->p, w->s, w->dinv, 0, m);
            restart = 0;
        }
        ss = pw__cgls_step(A, x, w, &gamma);
        if (ss < 0) {
            k->status = PW_ERR_NOCONVERGE;
            break;
        }
        k->rnorm = sqrt(ss);
        k->it++;
        fresh = 0;
    }
}

/* Jacobi preconditioner of the normal equations: the squared column norms
 * of A, i.e. diag(AᵀA), summed in row order. */
PW__DEF void pw__col_norms2(const pw_csr *A, double *d)
{
    int i, k;
    for (k = 0; k < A->m; k++) d[k] = 0;
    for (i = 0; i < A->n; i++)
        for (k = A->rowptr[i]; k < A->rowptr[i + 1]; k++) d[A->col[k]] += A->val[k] * A->val[k];
}

/* Least squares: x minimising |A x - b| for A with n rows and m columns
 * (b: n, x: m), by Jacobi-preconditioned CGLS. x holds the initial guess
 * and receives the solution. The tolerance applies to the normal-equation
 * residual, |Aᵀ(b - A x)| <= tol |Aᵀ b| (the quantity that vanishes at the
 * minimum even when A x = b has no solution); stats->residual reports it.
 * Aᵀb = 0 gives x = 0. Unknowns that no row touches keep their guess. Errors
 * and the meaning of x after a failure are as for pw_cg_solve. */
PW__DEF int pw_lsq_solve(const pw_alloc *a, const pw_csr *A, const double *b, double *x, const pw_cg_options *o,
                         pw_cg_stats *s, pw_err *e)
{
    pw__krylov k;
    pw__cgls_ws w;
    int m, r;
    if (s) memset(s, 0, sizeof *s);
    if (pw_csr_check(A, e)) return PW_ERR_INVALID;
    m = A->m;
    if (pw__check_vec(b, A->n, "least-squares right-hand side b", e) || pw__check_vec(x, m, "least-squares guess x", e))
        return PW_ERR_INVALID;
    PW_SOLVE_HOOK("lsq", A, b, x, o);
    pw__krylov_init(&k, m, o);
    w.r = (double *)pw_alloc_array(a, (size_t)A->n * 2 + (size_t)m * 3, sizeof(double), "least-squares vectors", e);
    if (!w.r) return PW_ERR_NOMEM;
    w.q = w.r + A->n;
    w.s = w.q + A->n;
    w.p = w.s + m;
    w.dinv = w.p + m;
    pw_csr_mul_t(A, b, w.s);
    k.bnorm = sqrt(pw__dot(w.s, w.s, m));
    if (k.bnorm == 0) {
        memset(x, 0, (size_t)m * sizeof *x);
        if (s) s->converged = 1;
        pw_free(a, w.r);
        return PW_OK;
    }
    pw__col_norms2(A, w.dinv);
    pw__jacobi(w.dinv, m);
    pw__cgls_loop(A, b, x, &w, &k, e);
    r = pw__krylov_finish(&k, pw__cgls_residual(A, b, x, &w), "least-squares CG", s, e);
    pw_free(a, w.r);
    return r;
}

/* ---- sparse LDLᵀ ------------------------------------------------------------ */

/* A direct solver for symmetric positive definite systems: P A Pᵀ = L D Lᵀ
 * with a minimum-degree ordering P, then any number of right-hand sides in
 * two triangular sweeps. On the small systems of the methods (a few
 * thousand unknowns: a texture patch, a chart, a clump) one factorisation
 * costs less than the tens to hundreds of preconditioned CG iterations a
 * solve to tolerance needs, and the solution is exact to rounding.
 *
 * Ordering: minimum degree on the elimination graph (George & Liu 1989):
 * eliminate a vertex of least current degree, make its neighbours a
 * clique, repeat; ties go to the lowest index, so the order is
 * deterministic. The graph is kept explicitly (adjacency lists, a
 * degree bucket list), which is fine for the sizes this solver is meant for
 * (fill stays within a small multiple of A).
 * Factorisation: the up-looking LDLᵀ of Davis's LDL (ACM TOMS 2005): the
 * elimination tree and column counts first, then row k of L from a sparse
 * triangular solve along the tree, one row at a time. L is stored by
 * columns, its rows increasing. */
typedef struct pw_ldlt {
    int n;
    int *perm; /* n: new index k is the original unknown perm[k] */
    int *Lp;   /* n+1: column j of L (strictly below the diagonal) is Li/Lx[Lp[j] .. Lp[j+1]-1] */
    int *Li;
    double *Lx;
    double *D;    /* n: the diagonal */
    double *work; /* n: solve scratch */
} pw_ldlt;

PW__DEF void pw_ldlt_free(const pw_alloc *a, pw_ldlt *F)
{
    pw_free(a, F->perm);
    pw_free(a, F->Lp);
    pw_free(a, F->Li);
    pw_free(a, F->Lx);
    pw_free(a, F->D);
    pw_free(a, F->work);
    memset(F, 0, sizeof *F);
}

/* The quotient graph of the minimum-degree ordering (George and Liu; the
 * approximate degrees, supervariables and aggressive absorption of
 * Amestoy, Davis and Duff's AMD, 1996). An eliminated variable becomes an
 * element, whose list L_e holds the live variables its elimination joined
 * into a clique; the clique is never formed. A live variable i keeps its
 * variable neighbours not yet covered by an element (var(i)) and the
 * elements it belongs to (elt(i)). Every element containing the pivot is
 * absorbed into the pivot's new element, and so is every element whose
 * list lies inside the new one's. Variables with the same lists (the same
 * neighbours) are merged into one supervariable of weight nv, eliminated
 * at once; degrees count weights. All lists live in one pool of ints
 * (offsets, never pointers, since the pool moves as it grows): a new
 * element's list and an elt list that outgrows its room are placed at its
 * end. */
typedef struct pw__amd {
    const pw_alloc *a;
    int n, total, done; /* nodes; their weights' sum; weight eliminated so far */
    int *pool;
    size_t used, cap;
    size_t *var, *elt, *L;   /* list offsets in pool */
    int *nvar, *nelt, *celt; /* counts, room of elt lists */
    int *nL, *deg;           /* elements' weighted sizes; approximate external degrees */
    int *head, *next, *prev; /* degree buckets: doubly linked lists */
    int *nv, *chain, *tail;  /* supervariables: weight (0: merged), next member, last member */
    int *hhead, *hnext;      /* hash buckets of the supervariable search */
    unsigned char *status;   /* 0 variable, 1 element, 2 absorbed element, 3 merged variable */
    int *mark, *w, *wmark, stamp;
    int dmin; /* no live variable has a smaller degree */
} pw__amd;

PW__DEF void pw__amd_free(pw__amd *G)
{
    pw_free(G->a, G->pool);
    pw_free(G->a, G->var);
    pw_free(G->a, G->nvar);
    pw_free(G->a, G->head);
    pw_free(G->a, G->status);
}

PW__DEF void pw__amd_unlink(pw__amd *G, int v)
{
    if (G->prev[v] >= 0) G->next[G->prev[v]] = G->next[v];
    else G->head[G->deg[v]] = G->next[v];
    if (G->next[v] >= 0) G->prev[G->next[v]] = G->prev[v];
}

/* Pushes v on the front of its degree's bucket: among equal degrees the
 * vertex touched last goes first (deterministic, and it keeps the
 * elimination local, as multiple-elimination orderings do). */
PW__DEF void pw__amd_link(pw__amd *G, int v)
{
    int d = G->deg[v];
    G->next[v] = G->head[d];
    G->prev[v] = -1;
    if (G->head[d] >= 0) G->prev[G->head[d]] = v;
    G->head[d] = v;
    if (d < G->dmin) G->dmin = d;
}

/* Room for k more ints at the end of the pool; returns their offset. */
PW__DEF int pw__amd_room(pw__amd *G, size_t k, size_t *at, pw_err *e)
{
    if (G->used + k > G->cap) {
        size_t cap = G->used + k > 2 * G->cap ? G->used + k : 2 * G->cap;
        int *grown = (int *)pw_realloc(G->a, G->pool, sizeof(int) * cap);
        if (!grown) return pw_fail(e, PW_ERR_NOMEM, "out of memory ordering a sparse matrix");
        G->pool = grown;
        G->cap = cap;
    }
    *at = G->used;
    G->used += k;
    return PW_OK;
}

/* The graph of A, node i of weight weight[i] (NULL: all 1). */
PW__DEF int pw__amd_init(pw__amd *G, const pw_alloc *a, const pw_csr *A, const int *weight, pw_err *e)
{
    int n = A->n, i, k;
    size_t at = 0;
    memset(G, 0, sizeof *G);
    G->a = a;
    G->n = n;
    for (i = 0; i < n; i++) G->total += weight ? weight[i] : 1;
    G->var = (size_t *)pw_alloc_array(a, (size_t)n * 3, sizeof(size_t), "ordering graph", e);
    G->nvar = (int *)pw_calloc_array(a, (size_t)n * 15, sizeof(int), "ordering graph", e);
    G->head = (int *)pw_alloc_array(a, (size_t)G->total + 1, sizeof(int), "ordering graph", e);
    G->status = (unsigned char *)pw_calloc_array(a, (size_t)n, 1, "ordering graph", e);
    if (!G->var || !G->nvar || !G->head || !G->status ||
        pw__amd_room(G, (size_t)A->rowptr[n] + 4 * (size_t)n, &at, e) != PW_OK)
        return PW_ERR_NOMEM;
    G->elt = G->var + n;
    G->L = G->elt + n;
    G->nelt = G->nvar + n;
    G->celt = G->nelt + n;
    G->nL = G->celt + n;
    G->deg = G->nL + n;
    G->next = G->deg + n;
    G->prev = G->next + n;
    G->mark = G->prev + n;
    G->w = G->mark + n;
    G->wmark = G->w + n;
    G->nv = G->wmark + n;
    G->chain = G->nv + n;
    G->tail = G->chain + n;
    G->hhead = G->tail + n;
    G->hnext = G->hhead + n;
    for (i = 0; i < n; i++) {
        G->nv[i] = weight ? weight[i] : 1;
        G->chain[i] = G->hhead[i] = -1;
        G->tail[i] = i;
    }
    for (i = 0; i < n; i++) {
        G->var[i] = at;
        for (k = A->rowptr[i]; k < A->rowptr[i + 1]; k++)
            if (A->col[k] != i) {
                G->pool[at + G->nvar[i]++] = A->col[k];
                G->deg[i] += G->nv[A->col[k]];
            }
        at += (size_t)G->nvar[i];
        G->elt[i] = at;
        G->celt[i] = 4;
        at += 4;
    }
    G->used = at;
    G->dmin = G->total;
    for (i = 0; i <= G->total; i++) G->head[i] = -1;
    for (i = n - 1; i >= 0; i--) pw__amd_link(G, i); /* vertex 0 first among equals */
    return PW_OK;
}

/* Appends element p to elt(i), moving the list to the pool's end with
 * twice the room when it is full. */
PW__DEF int pw__amd_add_elt(pw__amd *G, int i, int p, pw_err *e)
{
    if (G->nelt[i] == G->celt[i]) {
        size_t at;
        if (pw__amd_room(G, 2 * (size_t)G->celt[i], &at, e) != PW_OK) return PW_ERR_NOMEM;
        memcpy(G->pool + at, G->pool + G->elt[i], sizeof(int) * (size_t)G->nelt[i]);
        G->elt[i] = at;
        G->celt[i] *= 2;
    }
    G->pool[G->elt[i] + G->nelt[i]++] = p;
    return PW_OK;
}

/* 1 if variables i and j have the same elements and variable neighbours
 * (lists without repeats). */
PW__DEF int pw__amd_same(pw__amd *G, int i, int j)
{
    const int *pool = G->pool;
    int q, stamp = ++G->stamp;
    if (G->nelt[i] != G->nelt[j] || G->nvar[i] != G->nvar[j]) return 0;
    for (q = 0; q < G->nelt[i]; q++) G->mark[pool[G->elt[i] + q]] = stamp;
    for (q = 0; q < G->nvar[i]; q++) G->mark[pool[G->var[i] + q]] = stamp;
    for (q = 0; q < G->nelt[j]; q++)
        if (G->mark[pool[G->elt[j] + q]] != stamp) return 0;
    for (q = 0; q < G->nvar[j]; q++)
        if (G->mark[pool[G->var[j] + q]] != stamp) return 0;
    return 1;
}

/* Merges the variables of nb (the new element's list, nn of them) that
 * have the same lists into supervariables: the first of each keeps the
 * weight, its degree less the others' weights, and their members. */
PW__DEF void pw__amd_supervariables(pw__amd *G, const int *nb, int nn)
{
    const int *pool = G->pool;
    int i, q;
    for (i = 0; i < nn; i++) { /* hash: the sum of the lists' entries */
        int v = nb[i];
        unsigned long h = 0;
        for (q = 0; q < G->nelt[v]; q++) h += (unsigned)pool[G->elt[v] + q];
        for (q = 0; q < G->nvar[v]; q++) h += (unsigned)pool[G->var[v] + q];
        G->w[v] = (int)(h % (unsigned long)G->n); /* v is a variable: its w (an element's) is free */
        G->hnext[v] = G->hhead[G->w[v]];
        G->hhead[G->w[v]] = v;
    }
    for (i = 0; i < nn; i++) {
        int v = nb[i], h = G->w[v], j, *link;
        if (G->hhead[h] < 0) continue;
        for (v = G->hhead[h]; v >= 0; v = G->hnext[v]) {
            if (G->status[v] != 0) continue;
            for (link = &G->hnext[v], j = *link; j >= 0; j = *link) {
                if (G->status[j] == 0 && pw__amd_same(G, v, j)) {
                    G->deg[v] -= G->nv[j];
                    G->nv[v] += G->nv[j];
                    G->nv[j] = 0;
                    G->status[j] = 3;
                    G->chain[G->tail[v]] = j;
                    G->tail[v] = G->tail[j];
                    *link = G->hnext[j];
                } else link = &G->hnext[j];
            }
        }
        G->hhead[h] = -1;
    }
}

/* Eliminates supervariable p: its element's list L_p (its variable
 * neighbours and the lists of the elements it belongs to, which it
 * absorbs) into nb, then, for every i in L_p, |L_e \ L_p| (weighted) of
 * i's other elements (w), the absorption of elements wholly inside L_p,
 * i's lists pruned, and its approximate external degree: |var(i)| +
 * |L_p| - nv(i) + the sum of w over its other elements, at most its old
 * degree plus |L_p| - nv(i) and the weight left; then the supervariables
 * among L_p. */
PW__DEF int pw__amd_eliminate(pw__amd *G, int p, int *nb, pw_err *e)
{
    int stamp = ++G->stamp, nn = 0, wp = 0, i, j, q;
    const int *pool;
    size_t at;
    G->status[p] = 1;
    G->mark[p] = stamp;
    G->done += G->nv[p];
    pool = G->pool;
    for (j = 0; j < G->nvar[p]; j++) {
        int v = pool[G->var[p] + j];
        if (G->status[v] == 0 && G->mark[v] != stamp) G->mark[nb[nn++] = v] = stamp;
    }
    for (j = 0; j < G->nelt[p]; j++) {
        int el = pool[G->elt[p] + j];
        if (G->status[el] != 1) continue;
        for (q = 0; q < G->nL[el]; q++) {
            int v = pool[G->L[el] + q];
            if (G->status[v] == 0 && G->mark[v] != stamp) G->mark[nb[nn++] = v] = stamp;
        }
        G->status[el] = 2;
    }
    for (i = 0; i < nn; i++) wp += G->nv[nb[i]];
    G->nvar[p] = G->nelt[p] = 0;
    if (pw__amd_room(G, (size_t)nn, &at, e) != PW_OK) return PW_ERR_NOMEM;
    pool = G->pool;
    for (i = 0; i < nn; i++) /* w(e) = |L_e \ L_p|, weighted */
        for (j = 0; j < G->nelt[nb[i]]; j++) {
            int el = pool[G->elt[nb[i]] + j];
            if (G->status[el] != 1) continue;
            if (G->wmark[el] != stamp) {
                G->wmark[el] = stamp;
                G->w[el] = G->deg[el];
            }
            G->w[el] -= G->nv[nb[i]];
        }
    for (i = 0; i < nn; i++) { /* absorption, pruning and the new degree of each variable of L_p */
        int v = nb[i], m = 0, ext = 0, vw = 0;
        long d;
        int *ev = G->pool + G->elt[v], *vv = G->pool + G->var[v];
        for (j = 0; j < G->nelt[v]; j++) {
            int el = ev[j];
            if (G->status[el] == 1 && G->w[el] == 0) G->status[el] = 2; /* inside L_p: absorbed */
            if (G->status[el] != 1) continue;
            ev[m++] = el;
            ext += G->w[el];
        }
        G->nelt[v] = m;
        for (j = 0, m = 0; j < G->nvar[v]; j++)
            if (G->status[vv[j]] == 0 && G->mark[vv[j]] != stamp) {
                vw += G->nv[vv[j]];
                vv[m++] = vv[j];
            }
        G->nvar[v] = m;
        if (pw__amd_add_elt(G, v, p, e) != PW_OK) return PW_ERR_NOMEM;
        d = (long)vw + wp - G->nv[v] + ext;
        if (d > (long)G->deg[v] + wp - G->nv[v]) d = (long)G->deg[v] + wp - G->nv[v];
        if (d > G->total - G->done - G->nv[v]) d = G->total - G->done - G->nv[v];
        pw__amd_unlink(G, v);
        G->deg[v] = (int)(d > 0 ? d : 0);
    }
    pw__amd_supervariables(G, nb, nn);
    for (i = 0, q = 0; i < nn; i++) /* L_p: the supervariables left */
        if (G->status[nb[i]] == 0) {
            G->pool[at + q++] = nb[i];
            if (G->deg[nb[i]] < 0) G->deg[nb[i]] = 0;
            pw__amd_link(G, nb[i]);
        }
    G->L[p] = at;
    G->nL[p] = q;
    G->deg[p] = wp; /* an element's degree: its list's weight */
    return PW_OK;
}

/* Minimum-degree order of A's graph (node i of weight weight[i], NULL: 1)
 * into perm (approximate degrees on the quotient graph: the cost follows
 * the nonzeros, not the fill). */
PW__DEF int pw__min_degree_graph(const pw_alloc *a, const pw_csr *A, const int *weight, int *perm, pw_err *e)
{
    pw__amd G;
    int k = 0, r = pw__amd_init(&G, a, A, weight, e);
    int *nb = NULL;
    if (r == PW_OK && !(nb = (int *)pw_alloc_array(a, (size_t)A->n, sizeof(int), "ordering graph", e)))
        r = PW_ERR_NOMEM;
    while (r == PW_OK && G.done < G.total) {
        int v, u;
        while (G.head[G.dmin] < 0) G.dmin++;
        v = G.head[G.dmin];
        pw__amd_unlink(&G, v);
        for (u = v; u >= 0; u = G.chain[u]) perm[k++] = u;
        r = pw__amd_eliminate(&G, v, nb, e);
    }
    pw_free(a, nb);
    pw__amd_free(&G);
    return r;
}

/* Order-independent hash of node i's closed neighbourhood in A. */
PW__DEF uint64_t pw__nbhd_hash(const pw_csr *A, int i)
{
    uint64_t h = 0;
    int k, self = 0;
    for (k = A->rowptr[i]; k < A->rowptr[i + 1]; k++) {
        uint64_t x = (uint64_t)A->col[k] * 0x9E3779B97F4A7C15ull;
        h += (x ^ (x >> 29)) * 0xBF58476D1CE4E5B9ull;
        self |= A->col[k] == i;
    }
    if (!self) {
        uint64_t x = (uint64_t)i * 0x9E3779B97F4A7C15ull;
        h += (x ^ (x >> 29)) * 0xBF58476D1CE4E5B9ull;
    }
    return h;
}

/* 1 if nodes i and j of A have the same closed neighbourhood (mark: n
 * entries, none equal to stamp on entry; rows without repeated columns). */
PW__DEF int pw__same_nbhd(const pw_csr *A, int i, int j, int *mark, int stamp)
{
    int k, ni = 1, nj = 1;
    mark[i] = stamp;
    for (k = A->rowptr[i]; k < A->rowptr[i + 1]; k++)
        if (A->col[k] != i) {
            mark[A->col[k]] = stamp;
            ni++;
        }
    if (mark[j] != stamp) return 0; /* j is not next to i */
    for (k = A->rowptr[j]; k < A->rowptr[j + 1]; k++)
        if (A->col[k] != j) {
            if (mark[A->col[k]] != stamp) return 0;
            nj++;
        }
    return ni == nj;
}

/* Minimum-degree order of A's graph into perm, on the graph of its groups
 * of indistinguishable nodes when there are some: nodes with the same
 * closed neighbourhood (the unknowns of one vertex, as a parameterisation's
 * u and v are) are eliminated together in any minimum-degree order, so
 * they are merged first, the merged graph is ordered, and each group's
 * nodes follow one another (AMD finds such supervariables as elimination
 * goes; finding those present from the start gets most of the gain on the
 * systems that have them). */
PW__DEF int pw__min_degree(const pw_alloc *a, const pw_csr *A, int *perm, pw_err *e)
{
    const int n = A->n;
    uint64_t *key = (uint64_t *)pw_alloc_array(a, (size_t)n + 1, sizeof *key, "ordering groups", e);
    int *group = (int *)pw_alloc_array(a, (size_t)n * 6 + 1, sizeof(int), "ordering groups", e);
    int *leader = group ? group + n : NULL, *mark = group ? group + 2 * n : NULL, *start = group ? group + 3 * n : NULL;
    int *head = group ? group + 4 * n : NULL, *next = group ? group + 5 * n : NULL;
    int i, j, k, g = 0, r = PW_OK, stamp = 0;
    pw_csr C;
    memset(&C, 0, sizeof C);
    if (!key || !group) r = PW_ERR_NOMEM;
    for (i = 0; r == PW_OK && i < n; i++) head[i] = -1;
    for (i = n - 1; r == PW_OK && i >= 0; i--) { /* buckets by hash, each in index order */
        key[i] = pw__nbhd_hash(A, i);
        next[i] = head[key[i] % (uint64_t)n];
        head[key[i] % (uint64_t)n] = i;
        mark[i] = 0;
        leader[i] = i;
    }
    for (i = 0; r == PW_OK && i < n; i++) /* each node joins the first earlier match */
        for (j = next[i]; leader[i] == i && j >= 0; j = next[j])
            if (leader[j] == j && key[j] == key[i] && pw__same_nbhd(A, i, j, mark, ++stamp)) leader[j] = i;
    for (i = 0; r == PW_OK && i < n; i++) group[i] = leader[i] == i ? g++ : group[leader[i]];
    if (r == PW_OK && g > n - n / 10) { /* few groups: order the graph itself */
        pw_free(a, key);
        pw_free(a, group);
        return pw__min_degree_graph(a, A, NULL, perm, e);
    }
    if (r == PW_OK) { /* the graph of the groups: each group's edges are its leader's */
        C.n = C.m = g;
        C.rowptr = (int *)pw_calloc_array(a, (size_t)g + 1, sizeof(int), "ordering groups", e);
        C.col = (int *)pw_alloc_array(a, (size_t)A->rowptr[n] + 1, sizeof(int), "ordering groups", e);
        if (!C.rowptr || !C.col) r = PW_ERR_NOMEM;
    }
    for (i = 0; r == PW_OK && i < n; i++) mark[i] = -1;
    for (i = 0, k = 0; r == PW_OK && i < n; i++) {
        int q;
        if (leader[i] != i) continue;
        for (q = A->rowptr[i]; q < A->rowptr[i + 1]; q++) {
            const int h = group[A->col[q]];
            if (h != group[i] && mark[h] != group[i]) C.col[k++] = h;
            mark[h] = group[i];
        }
        C.rowptr[group[i] + 1] = k;
    }
    for (i = 0; r == PW_OK && i < g; i++) start[i] = 0; /* the groups' weights: their sizes */
    for (i = 0; r == PW_OK && i < n; i++) start[group[i]]++;
    if (r == PW_OK) r = pw__min_degree_graph(a, &C, start, perm + (n - g), e); /* the groups' order, at the end */
    if (r == PW_OK) { /* each group's nodes in index order, where the group comes */
        for (i = 0; i <= g; i++) start[i] = 0;
        for (i = 0; i < n; i++) start[group[i] + 1]++;
        for (i = 0; i < g; i++) start[i + 1] += start[i];
        for (i = 0; i < n; i++) mark[start[group[i]]++] = i; /* members, grouped */
        for (i = g; i > 0; i--) start[i] = start[i - 1];
        start[0] = 0;
        for (k = 0, j = n - g; j < n; j++) {
            const int h = perm[j];
            for (i = start[h]; i < start[h + 1]; i++) perm[k++] = mark[i];
        }
    }
    pw_free(a, C.rowptr);
    pw_free(a, C.col);
    pw_free(a, key);
    pw_free(a, group);
    return r;
}

/* The elimination tree (parent) and the count of each column of L, for
 * the permuted matrix (inverse permutation iperm); flag is scratch. */
PW__DEF void pw__ldlt_symbolic(const pw_csr *A, const int *perm, const int *iperm, int *parent, int *count, int *flag)
{
    int k, p;
    for (k = 0; k < A->n; k++) {
        int old = perm[k];
        parent[k] = -1;
        flag[k] = k;
        count[k] = 0;
        for (p = A->rowptr[old]; p < A->rowptr[old + 1]; p++) {
            int i = iperm[A->col[p]];
            for (; i < k && flag[i] != k; i = parent[i]) {
                if (parent[i] == -1) parent[i] = k;
                count[i]++;
                flag[i] = k;
            }
        }
    }
}

/* Row k of L and D[k]: y = the permuted column k above the diagonal,
 * solved against the rows before it along the elimination tree (pattern:
 * the reach of its entries, in topological order). Returns 0 on a pivot
 * that is not positive, or not above 1e-14 of the diagonal entry it came
 * from (what a singular matrix leaves after cancellation). */
/* The scratch of pw_ldlt_factor (n entries each): the inverse ordering, the
 * elimination tree, the entries of each column of L so far, visit marks,
 * the reach of a row, and the dense row being solved (zero between rows). */
typedef struct pw__ldlt_work {
    const int *iperm, *parent;
    int *len, *flag, *pattern;
    double *y;
} pw__ldlt_work;

PW__DEF int pw__ldlt_row(pw_ldlt *F, const pw_csr *A, const pw__ldlt_work *W, int k)
{
    const int *iperm = W->iperm, *parent = W->parent;
    int *len = W->len, *flag = W->flag, *pattern = W->pattern;
    double *y = W->y;
    int old = F->perm[k], p, top = F->n;
    double akk;
    flag[k] = k;
    y[k] = 0.0;
    for (p = A->rowptr[old]; p < A->rowptr[old + 1]; p++) {
        int i = iperm[A->col[p]], n = 0;
        if (i > k) continue;
        y[i] += A->val[p];
        for (; flag[i] != k; i = parent[i]) {
            pattern[n++] = i;
            flag[i] = k;
        }
        while (n > 0) pattern[--top] = pattern[--n];
    }
    F->D[k] = akk = y[k];
    y[k] = 0.0;
    for (; top < F->n; top++) {
        int i = pattern[top], q, end = F->Lp[i] + len[i];
        const int *Li = F->Li;
        const double *Lx = F->Lx;
        double yi = y[i], nyi = -yi, l;
        y[i] = 0.0;
        for (q = F->Lp[i]; q < end; q++) y[Li[q]] += Lx[q] * nyi; /* y - Lx yi, exactly, one load fewer */
        l = yi / F->D[i];
        F->D[k] -= l * yi;
        F->Li[end] = k;
        F->Lx[end] = l;
        len[i]++;
    }
    return F->D[k] > 1e-14 * akk && pw_is_finite(F->D[k]); /* relative: a singular matrix leaves rounding noise */
}

/* pw_ldlt_factor, refusing (PW_ERR_LIMIT, after the ordering and the
 * symbolic analysis, before any numeric work) a factor of more than
 * max_fill nonzeros below the diagonal. */
PW__DEF int pw__ldlt_factor_capped(const pw_alloc *a, const pw_csr *A, long max_fill, pw_ldlt *F, pw_err *e)
{
    int n = A->n, k, r = PW_OK, *iperm, *parent, *flag, *len, *pattern;
    double *y;
    pw__ldlt_work W;
    memset(F, 0, sizeof *F);
    if (A->n != A->m) return pw_fail(e, PW_ERR_INVALID, "LDLT needs a square matrix, not %dx%d", A->n, A->m);
    F->n = n;
    F->perm = (int *)pw_alloc_array(a, (size_t)n, sizeof(int), "LDLT ordering", e);
    F->Lp = (int *)pw_alloc_array(a, (size_t)n + 1, sizeof(int), "LDLT factor", e);
    F->D = (double *)pw_alloc_array(a, (size_t)n, sizeof(double), "LDLT factor", e);
    F->work = (double *)pw_alloc_array(a, (size_t)n, sizeof(double), "LDLT factor", e);
    iperm = (int *)pw_alloc_array(a, (size_t)n * 5, sizeof(int), "LDLT scratch", e);
    y = (double *)pw_calloc_array(a, (size_t)n, sizeof(double), "LDLT scratch", e);
    if (!F->perm || !F->Lp || !F->D || !F->work || !iperm || !y) r = PW_ERR_NOMEM;
    if (r == PW_OK) r = pw__min_degree(a, A, F->perm, e);
    if (r == PW_OK) {
        parent = iperm + n;
        flag = parent + n;
        len = flag + n;
        pattern = len + n;
        for (k = 0; k < n; k++) iperm[F->perm[k]] = k;
        pw__ldlt_symbolic(A, F->perm, iperm, parent, len, flag);
        for (F->Lp[0] = 0, k = 0; k < n; k++) F->Lp[k + 1] = F->Lp[k] + len[k];
        if (F->Lp[n] > max_fill)
            r = pw_fail(e, PW_ERR_LIMIT, "LDLT: the factor would hold %d nonzeros, over the %ld allowed", F->Lp[n],
                        max_fill);
    }
    if (r == PW_OK) {
        F->Li = (int *)pw_alloc_array(a, (size_t)F->Lp[n] + 1, sizeof(int), "LDLT factor", e);
        F->Lx = (double *)pw_alloc_array(a, (size_t)F->Lp[n] + 1, sizeof(double), "LDLT factor", e);
        if (!F->Li || !F->Lx) r = PW_ERR_NOMEM;
        for (k = 0; k < n; k++) len[k] = 0;
        W.iperm = iperm;
        W.parent = parent;
        W.len = len;
        W.flag = flag;
        W.pattern = pattern;
        W.y = y;
        for (k = 0; k < n && r == PW_OK; k++)
            if (!pw__ldlt_row(F, A, &W, k))
                r = pw_fail(e, PW_ERR_DEGENERATE,
                            "LDLT: the matrix is not positive definite (pivot %d of %d, unknown %d, is %g)", k, n,
                            F->perm[k], F->D[k]);
    }
    pw_free(a, iperm);
    pw_free(a, y);
    if (r != PW_OK) pw_ldlt_free(a, F);
    return r;
}

/* Factors a symmetric positive definite A (full storage, both triangles,
 * every diagonal entry present) as P A Pᵀ = L D Lᵀ. A matrix that is not
 * positive definite fails with PW_ERR_DEGENERATE naming the pivot. */
PW__DEF int pw_ldlt_factor(const pw_alloc *a, const pw_csr *A, pw_ldlt *F, pw_err *e)
{
    return pw__ldlt_factor_capped(a, A, (long)INT_MAX, F, e);
}

/* x = A⁻¹ b (x may be b). */
PW__DEF void pw_ldlt_solve(const pw_ldlt *F, const double *b, double *x)
{
    double *w = F->work;
    int j, p;
    for (j = 0; j < F->n; j++) w[j] = b[F->perm[j]];
    for (j = 0; j < F->n; j++) /* L w = P b, by columns */
        for (p = F->Lp[j]; p < F->Lp[j + 1]; p++) w[F->Li[p]] -= F->Lx[p] * w[j];
    for (j = 0; j < F->n; j++) w[j] /= F->D[j];
    for (j = F->n - 1; j >= 0; j--) /* Lᵀ */
        for (p = F->Lp[j]; p < F->Lp[j + 1]; p++) w[j] -= F->Lx[p] * w[F->Li[p]];
    for (j = 0; j < F->n; j++) x[F->perm[j]] = w[j];
}

/* ---- choosing the solver ------------------------------------------------------ */

/* Where LDLᵀ wins. The iterative solvers are warm-started from a close
 * guess by every caller (the previous paste, the current chart layout), so
 * on small systems they stop after a few iterations, and the ordering a
 * direct factor needs costs more than that. Measured over every system
 * lapped_create and lapped_bake_atlas solve on the armadillo, bunny and
 * mushroom (docs/performance.md): LDLᵀ of the patch systems (against
 * IC(0)-PCG) takes 1.5-4x PCG's time below 400 unknowns, 0.9-1.5x at
 * 400-800 and 0.5-0.9x at 800-1,600; of the atlas's normal equations
 * (against CGLS, which needs more iterations) 1.1-2x below 200, 0.7-1.2x
 * at 200-400 and 0.1-0.8x from 400 up to the largest chart (about 10,000
 * unknowns: 0.14). lst's smoothing of its fields (30,070 unknowns on the
 * elephant at the default fill, three solves of one matrix): 0.47x CGLS
 * for one solve, and lst_create 10.4 s -> 4.0 s with one factor for the
 * three (at 100K tetrahedra the factor would hold 8x the normal
 * equations' nonzeros: the fill cap keeps CGLS there). lst's clumps
 * (tetrahedra: twice the neighbours of a surface vertex, more fill) stay
 * with IC(0)-PCG: LDLᵀ made the fill 10% slower. (These were measured with
 * the ordering before AMD's approximate degrees, which made it 4-20x
 * faster: the direct factor now wins from fewer unknowns.) The rule: a direct factor for a matrix of PW__DIRECT_MIN_SPD
 * (pw_spd) or PW__DIRECT_MIN_LSQ (pw_lsq_solve_small) to PW__DIRECT_MAX_N
 * unknowns whose factor holds at most PW__DIRECT_FILL times A's nonzeros
 * (both triangles; the ordering and the symbolic analysis tell before any
 * numeric work); otherwise, or when the factorisation meets a pivot that is
 * not positive (a semidefinite matrix rounded the wrong way), the
 * iterative solver. Both are deterministic; the direct solve is exact to
 * rounding, so it meets any tolerance the iterative one would stop at. */
#define PW__DIRECT_MIN_SPD 800
#define PW__DIRECT_MIN_LSQ 400
#define PW__DIRECT_MAX_N 40000
#define PW__DIRECT_FILL 4

/* A symmetric positive definite matrix ready for any number of solves:
 * its LDLᵀ or, failing the rule above, its IC(0) factor for PCG. */
typedef struct pw_spd {
    const pw_csr *A;
    int direct; /* 1: F holds the factor; 0: M does */
    pw_ldlt F;
    pw_ic0 M;
} pw_spd;

PW__DEF void pw_spd_free(const pw_alloc *a, pw_spd *S)
{
    pw_ldlt_free(a, &S->F);
    pw_ic0_free(a, &S->M);
    memset(S, 0, sizeof *S);
}

/* The direct factor of A when the rule allows it (min_n: the fewest
 * unknowns) and it succeeds: 1, else 0 with nothing kept (only running out
 * of memory is an error, in *r). */
PW__DEF int pw__try_direct(const pw_alloc *a, const pw_csr *A, int min_n, pw_ldlt *F, int *r, pw_err *e)
{
    pw_err local;
    int rc;
    *r = PW_OK;
    memset(F, 0, sizeof *F);
    if (A->n > PW__DIRECT_MAX_N || A->n < min_n || A->n != A->m) return 0;
    pw_err_clear(&local);
    rc = pw__ldlt_factor_capped(a, A, (long)PW__DIRECT_FILL * A->rowptr[A->n], F, &local);
    if (rc == PW_ERR_NOMEM) *r = pw_fail(e, rc, "%s", local.msg);
    return rc == PW_OK;
}

/* Prepares A (as for pw_pcg_solve: square, sorted columns, every diagonal
 * entry present) for pw_spd_solve; A must outlive S. */
PW__DEF int pw_spd_factor(const pw_alloc *a, const pw_csr *A, pw_spd *S, pw_err *e)
{
    int r;
    memset(S, 0, sizeof *S);
    S->A = A;
    if (pw_csr_check(A, e)) return PW_ERR_INVALID;
    S->direct = pw__try_direct(a, A, PW__DIRECT_MIN_SPD, &S->F, &r, e);
    if (r != PW_OK || S->direct) return r;
    return pw_ic0_factor(a, A, &S->M, e);
}

/* A x = b: by the LDLᵀ factor, or by PCG from the guess in x with the
 * options o (tolerance, cap, progress; its errors as pw_pcg_solve's). */
PW__DEF int pw_spd_solve(const pw_alloc *a, const pw_spd *S, const double *b, double *x, const pw_cg_options *o,
                         pw_err *e)
{
    if (!S->direct) return pw_pcg_solve(a, S->A, &S->M, b, x, o, NULL, e);
    if (pw__check_vec(b, S->A->n, "right-hand side b", e)) return PW_ERR_INVALID;
    PW_SOLVE_HOOK("pcg", S->A, b, x, o);
    pw_ldlt_solve(&S->F, b, x);
    return PW_OK;
}

/* A least-squares matrix ready for any number of right-hand sides: the
 * LDLᵀ factor of its normal equations AᵀA when they pass the rule above
 * (their condition number is the square of A's: fine for the well-posed
 * smoothing and parametrisation systems that call this, where the direct
 * solution's residual is far below the CGLS tolerance), else nothing, and
 * every solve runs CGLS. */
typedef struct pw_lsq {
    const pw_csr *A;
    int direct; /* 1: F holds the factor of AᵀA */
    pw_ldlt F;
} pw_lsq;

PW__DEF void pw_lsq_free(const pw_alloc *a, pw_lsq *L)
{
    pw_ldlt_free(a, &L->F);
    memset(L, 0, sizeof *L);
}

/* Prepares A (m x n, as for pw_lsq_solve) for pw_lsq_solve_prepared; A
 * must outlive L. */
PW__DEF int pw_lsq_prepare(const pw_alloc *a, const pw_csr *A, pw_lsq *L, pw_err *e)
{
    pw_csr N;
    int r = PW_OK;
    memset(L, 0, sizeof *L);
    L->A = A;
    if (pw_csr_check(A, e)) return PW_ERR_INVALID;
    memset(&N, 0, sizeof N);
    if (A->m >= PW__DIRECT_MIN_LSQ && A->m <= PW__DIRECT_MAX_N && (r = pw_csr_ata(a, A, &N, e)) != PW_OK) return r;
    if (N.n > 0) L->direct = pw__try_direct(a, &N, PW__DIRECT_MIN_LSQ, &L->F, &r, e);
    pw_csr_free(a, &N);
    return r;
}

/* min |A x - b| for the matrix L was prepared from: by the factor (stats:
 * no iterations, the residual of the normal equations), or by CGLS from
 * the guess in x (as pw_lsq_solve, stats and errors included). */
PW__DEF int pw_lsq_solve_prepared(const pw_alloc *a, const pw_lsq *L, const double *b, double *x,
                                  const pw_cg_options *o, pw_cg_stats *stats, pw_err *e)
{
    const pw_csr *A = L->A;
    if (!L->direct) return pw_lsq_solve(a, A, b, x, o, stats, e);
    if (pw__check_vec(b, A->n, "least-squares right-hand side b", e) ||
        pw__check_vec(x, A->m, "least-squares guess x", e))
        return PW_ERR_INVALID;
    PW_SOLVE_HOOK("lsq", A, b, x, o);
    pw_csr_mul_t(A, b, x);
    pw_ldlt_solve(&L->F, x, x);
    if (stats) {
        double *r = (double *)pw_alloc_array(a, (size_t)A->n + 2 * (size_t)A->m, sizeof(double), "residual", e);
        double *g = r ? r + A->n : NULL, *g0 = g ? g + A->m : NULL;
        int i;
        if (!r) return PW_ERR_NOMEM;
        pw_csr_mul(A, x, r);
        for (i = 0; i < A->n; i++) r[i] = b[i] - r[i];
        pw_csr_mul_t(A, r, g);
        pw_csr_mul_t(A, b, g0);
        memset(stats, 0, sizeof *stats);
        stats->converged = 1;
        stats->residual = pw__dot(g0, g0, A->m) > 0.0 ? sqrt(pw__dot(g, g, A->m) / pw__dot(g0, g0, A->m)) : 0.0;
        pw_free(a, r);
    }
    return PW_OK;
}

/* min |A x - b| as pw_lsq_solve, but by LDLᵀ of the normal equations when
 * they pass the rule above (pw_lsq_prepare), for one right-hand side. */
PW__DEF int pw_lsq_solve_small(const pw_alloc *a, const pw_csr *A, const double *b, double *x, const pw_cg_options *o,
                               pw_err *e)
{
    pw_lsq L;
    int r = pw_lsq_prepare(a, A, &L, e);
    if (r == PW_OK) r = pw_lsq_solve_prepared(a, &L, b, x, o, NULL, e);
    pw_lsq_free(a, &L);
    return r;
}

#endif /* PW__SPARSE_V1 */
