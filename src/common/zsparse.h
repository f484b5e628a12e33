/* zsparse: complex Hermitian sparse systems, solved by conjugate gradients
 * preconditioned with a complex incomplete Cholesky factor.
 *
 * The direction-field smoothing and the periodic global parameterization
 * of pgp.h minimise sums of w |z_i - c z_j|^2 over unit complex numbers:
 * Hermitian positive (semi)definite systems. Written as real systems of
 * twice the size they store every complex coefficient as a 2x2 block (four
 * values, four column indices); here each is one (re, im) pair under one
 * index, which halves the memory CG streams per iteration, and IC(0) of the
 * complex matrix keeps the pairs together.
 *
 * Complex numbers are (re, im) pairs of doubles: vectors of n complex
 * entries are 2n doubles. Entries are collected in an ordinary pw_triplets
 * of n rows and 2n columns (pw_ztriplets_add writes the real part at
 * column 2j and the imaginary part at 2j + 1, both always, so that the
 * structure depends on positions only), then packed:
 *
 *     pw_triplets t;  pw_zcsr A;  pw_zic0 L;
 *     pw_triplets_init(&t, NULL, n, 2 * n, &e);
 *     pw_ztriplets_add(&t, i, j, re, im, &e);  ...   (duplicates summed)
 *     pw_zcsr_from_triplets(NULL, &t, &A, &e);
 *     pw_zic0_factor(NULL, &A, &L, &e);
 *     pw_zpcg_solve(NULL, &A, &L, b, x, NULL, &stats, &e);   (b, x: 2n)
 *
 * The caller adds both (i, j) and its conjugate (j, i): nothing checks that
 * the matrix is Hermitian, CG just fails to converge if it is not.
 * Determinism as in sparse.h: fixed summation order, no threads. */
#ifndef PW__ZSPARSE_V1
#define PW__ZSPARSE_V1

#include "sparse.h"

/* Adds re + i im at (i, j) of the complex matrix collected in t. */
PW__DEF int pw_ztriplets_add(pw_triplets *t, int i, int j, double re, double im, pw_err *e)
{
    int r = pw_triplets_add(t, i, 2 * j, re, e);
    return r == PW_OK ? pw_triplets_add(t, i, 2 * j + 1, im, e) : r;
}

/* ---- rows in blocks, on threads ---------------------------------------------- */

/* How the solvers' row loops may run on threads: pfor(par, n, task, ctx)
 * runs task(ctx, i) for every i in [0, n), in any order (pw_parallel_for
 * and its pw_parallel, which the headers define later; pfor NULL: in order
 * on the calling thread). Rows go to tasks in blocks that depend on the
 * number of rows only, and every sum over rows is a sum per block and then
 * the blocks in order, so results are the same bits on any number of
 * threads and in any task order. */
struct pw_parallel;
typedef struct pw_zrun {
    void (*pfor)(const struct pw_parallel *par, int n, void (*task)(void *, int), void *ctx);
    const struct pw_parallel *par;
    int width; /* how many tasks of pfor may run at once (pw_parallel_width) */
} pw_zrun;

/* At most this many blocks of at least PW__ZBLOCK_ROWS rows; loops over
 * fewer than PW__ZPAR_ROWS rows stay on the calling thread (a parallel for
 * costs more than they do). */
#define PW__ZBLOCKS 16
#define PW__ZBLOCK_ROWS 4096
#define PW__ZPAR_ROWS 16384

/* The number of blocks of n rows. */
PW__DEF int pw__zblocks(int n)
{
    int nb = (n + PW__ZBLOCK_ROWS - 1) / PW__ZBLOCK_ROWS;
    return nb < 1 ? 1 : (nb > PW__ZBLOCKS ? PW__ZBLOCKS : nb);
}

/* The first row of block b of nb over n rows. */
PW__DEF int pw__zblock_start(int n, int nb, int b) { return (int)((long long)n * b / nb); }

/* Runs task(ctx, b) for the nb blocks of n rows, on run's threads when
 * there are enough rows. */
PW__DEF void pw__zfor(const pw_zrun *run, int n, int nb, void (*task)(void *, int), void *ctx)
{
    int b;
    if (run && run->pfor && n >= PW__ZPAR_ROWS && nb > 1) run->pfor(run->par, nb, task, ctx);
    else
        for (b = 0; b < nb; b++) task(ctx, b);
}

/* n x n complex CSR: row i holds col[k], (val[2k], val[2k+1]) for
 * rowptr[i] <= k < rowptr[i+1], columns increasing. run (NULL: one
 * thread) says how its products run. */
typedef struct pw_zcsr {
    int n;
    int *rowptr, *col;
    double *val; /* 2 per entry */
    const pw_zrun *run;
} pw_zcsr;

PW__DEF void pw_zcsr_free(const pw_alloc *a, pw_zcsr *A)
{
    if (!A) return;
    pw_free(a, A->rowptr);
    pw_free(a, A->col);
    pw_free(a, A->val);
    memset(A, 0, sizeof *A);
}

/* Packs t (n x 2n, filled by pw_ztriplets_add) into A. */
PW__DEF int pw_zcsr_from_triplets(const pw_alloc *a, const pw_triplets *t, pw_zcsr *A, pw_err *e)
{
    pw_csr R;
    int i, k, r;
    memset(A, 0, sizeof *A);
    if (t->m != 2 * t->n) return pw_fail(e, PW_ERR_INVALID, "complex triplets of %dx%d: need n x 2n", t->n, t->m);
    if ((r = pw_csr_from_triplets(a, t, &R, e)) != PW_OK) return r;
    for (k = 0; k < R.rowptr[t->n]; k += 2)
        if (R.col[k] % 2 != 0 || k + 1 >= R.rowptr[t->n] || R.col[k + 1] != R.col[k] + 1) {
            pw_csr_free(a, &R);
            return pw_fail(e, PW_ERR_INVALID,
                           "complex triplets: entry %d lacks its real or imaginary "
                           "part (add entries with pw_ztriplets_add)",
                           k);
        }
    A->n = t->n;
    A->rowptr = (int *)pw_alloc_array(a, (size_t)t->n + 1, sizeof(int), "complex CSR", e);
    A->col = (int *)pw_alloc_array(a, (size_t)R.rowptr[t->n] / 2 + 1, sizeof(int), "complex CSR", e);
    if (!A->rowptr || !A->col) {
        pw_csr_free(a, &R);
        pw_zcsr_free(a, A);
        return PW_ERR_NOMEM;
    }
    /* every complex entry is the adjacent pair (2j, 2j+1) of R's row */
    for (i = 0; i <= t->n; i++) A->rowptr[i] = R.rowptr[i] / 2;
    for (k = 0; k < R.rowptr[t->n]; k += 2) A->col[k / 2] = R.col[k] / 2;
    A->val = R.val; /* the pairs are already interleaved in order */
    R.val = NULL;
    pw_csr_free(a, &R);
    return PW_OK;
}

/* Sorts the first n ints of v (short rows: insertion sort). */
PW__DEF void pw__zsort(int *v, int n)
{
    int i, j;
    for (i = 1; i < n; i++) {
        int x = v[i];
        for (j = i; j > 0 && v[j - 1] > x; j--) v[j] = v[j - 1];
        v[j] = x;
    }
}

/* The position of (i, j) in A, -1 if absent (rows are short: a scan). */
PW__DEF int pw__zcsr_find(const pw_zcsr *A, int i, int j)
{
    int k;
    for (k = A->rowptr[i]; k < A->rowptr[i + 1]; k++)
        if (A->col[k] == j) return k;
    return -1;
}

/* The structure of a Hermitian matrix of n rows holding every diagonal
 * entry and, for each of the np pairs (ij[2p] != ij[2p+1], both in [0,
 * n)), the entries (ij[2p], ij[2p+1]) and (ij[2p+1], ij[2p]), with zero
 * values: dpos[i] is where (i, i) sits, pos[2p] and pos[2p+1] where the
 * pair's two entries sit (a repeated pair shares them). The caller then
 * adds each term at its position, in the order it visits them: no
 * triplets and no sort of the entries (assembly from a mesh's adjacency,
 * where the pairs are its edges). */
PW__DEF int pw_zcsr_pattern(const pw_alloc *a, int n, int np, const int *ij, pw_zcsr *A, int *dpos, int *pos, pw_err *e)
{
    int i, k, p, lo = 0, out = 0;
    memset(A, 0, sizeof *A);
    A->n = n;
    A->rowptr = (int *)pw_calloc_array(a, (size_t)n + 1, sizeof(int), "complex CSR", e);
    A->col = (int *)pw_alloc_array(a, (size_t)n + 2 * (size_t)np, sizeof(int), "complex CSR", e);
    if (!A->rowptr || !A->col) {
        pw_zcsr_free(a, A);
        return PW_ERR_NOMEM;
    }
    for (p = 0; p < 2 * np; p++) A->rowptr[ij[p] + 1]++;
    for (i = 0; i < n; i++) A->rowptr[i + 1] += A->rowptr[i] + 1; /* + the diagonal */
    for (i = 0; i < n; i++) {                                     /* dpos: each row's fill cursor */
        dpos[i] = A->rowptr[i];
        A->col[dpos[i]++] = i;
    }
    for (p = 0; p < np; p++) {
        A->col[dpos[ij[2 * p]]++] = ij[2 * p + 1];
        A->col[dpos[ij[2 * p + 1]]++] = ij[2 * p];
    }
    for (i = 0; i < n; i++) { /* columns increasing, repeats merged */
        int hi = A->rowptr[i + 1];
        pw__zsort(A->col + lo, hi - lo);
        A->rowptr[i] = out;
        for (k = lo; k < hi; k++)
            if (k == lo || A->col[k] != A->col[k - 1]) A->col[out++] = A->col[k];
        lo = hi;
    }
    A->rowptr[n] = out;
    A->val = (double *)pw_calloc_array(a, 2 * (size_t)out + 2, sizeof(double), "complex CSR", e);
    if (!A->val) {
        pw_zcsr_free(a, A);
        return PW_ERR_NOMEM;
    }
    for (i = 0; i < n; i++) dpos[i] = pw__zcsr_find(A, i, i);
    for (p = 0; p < np; p++) {
        pos[2 * p] = pw__zcsr_find(A, ij[2 * p], ij[2 * p + 1]);
        pos[2 * p + 1] = pw__zcsr_find(A, ij[2 * p + 1], ij[2 * p]);
    }
    return PW_OK;
}

/* A Hermitian system sum w |z_i - c z_j|^2 (+ diagonal terms) assembled
 * into its structure (pw_zcsr_pattern): the matrix, where its diagonal
 * and pair entries sit, the right-hand side (2n) and the pairs used so
 * far. The pairs are given by pair(ctx, k, ij) for k in [0, count): 1
 * and the two unknowns in ij when k makes one (both ends unknowns). */
typedef struct pw_zpairs {
    int count;
    int (*pair)(const void *ctx, int k, int *ij);
    const void *ctx;
} pw_zpairs;

typedef struct pw_zasm {
    pw_zcsr A;
    int *dpos, *pos;
    double *b;
    int next, npairs; /* the pair pw_zasm_term adds next; how many pos holds */
} pw_zasm;

PW__DEF void pw_zasm_free(const pw_alloc *a, pw_zasm *S)
{
    pw_zcsr_free(a, &S->A);
    pw_free(a, S->dpos);
    pw_free(a, S->pos);
    pw_free(a, S->b);
    memset(S, 0, sizeof *S);
}

/* The structure of the system of n unknowns and the pairs of pr, values
 * and right-hand side zero; on failure what was allocated is left for
 * pw_zasm_free. */
PW__DEF int pw_zasm_init(const pw_alloc *a, pw_zasm *S, int n, const pw_zpairs *pr, pw_err *e)
{
    int k, np = 0, ij[2], *all, r;
    memset(S, 0, sizeof *S);
    for (k = 0; k < pr->count; k++) np += pr->pair(pr->ctx, k, ij);
    S->dpos = (int *)pw_alloc_array(a, (size_t)n + 1, sizeof(int), "complex system", e);
    S->pos = (int *)pw_alloc_array(a, 2 * (size_t)np + 1, sizeof(int), "complex system", e);
    S->b = (double *)pw_calloc_array(a, 2 * (size_t)n + 1, sizeof(double), "complex system", e);
    all = (int *)pw_alloc_array(a, 2 * (size_t)np + 2, sizeof(int), "complex system", e); /* + a refused pair's */
    if (!S->dpos || !S->pos || !S->b || !all) {
        pw_free(a, all);
        return PW_ERR_NOMEM;
    }
    for (k = 0, np = 0; k < pr->count; k++)
        if (pr->pair(pr->ctx, k, all + 2 * np)) np++;
    S->npairs = np;
    r = pw_zcsr_pattern(a, n, np, all, &S->A, S->dpos, S->pos, e);
    pw_free(a, all);
    return r;
}

/* dst: src's structure (n, pattern, dpos and pos), values and right-hand
 * side zero, run NULL; on failure what was allocated is left for
 * pw_zasm_free. */
PW__DEF int pw_zasm_copy(const pw_alloc *a, pw_zasm *dst, const pw_zasm *src, pw_err *e)
{
    size_t n = (size_t)src->A.n, nnz = (size_t)src->A.rowptr[n], np = (size_t)src->npairs;
    memset(dst, 0, sizeof *dst);
    dst->A.n = src->A.n;
    dst->npairs = src->npairs;
    dst->A.rowptr = (int *)pw_alloc_array(a, n + 1, sizeof(int), "complex system", e);
    dst->A.col = (int *)pw_alloc_array(a, nnz + 1, sizeof(int), "complex system", e);
    dst->A.val = (double *)pw_calloc_array(a, 2 * nnz + 2, sizeof(double), "complex system", e);
    dst->dpos = (int *)pw_alloc_array(a, n + 1, sizeof(int), "complex system", e);
    dst->pos = (int *)pw_alloc_array(a, 2 * np + 1, sizeof(int), "complex system", e);
    dst->b = (double *)pw_calloc_array(a, 2 * n + 1, sizeof(double), "complex system", e);
    if (!dst->A.rowptr || !dst->A.col || !dst->A.val || !dst->dpos || !dst->pos || !dst->b) return PW_ERR_NOMEM;
    memcpy(dst->A.rowptr, src->A.rowptr, (n + 1) * sizeof(int));
    memcpy(dst->A.col, src->A.col, nnz * sizeof(int));
    memcpy(dst->dpos, src->dpos, n * sizeof(int));
    memcpy(dst->pos, src->pos, 2 * np * sizeof(int));
    return PW_OK;
}

/* Adds the term w |z_i - c z_j|^2 (i or j -1 where that end is not an
 * unknown, its value zfix moving to b): w on the diagonals of the
 * unknowns, -w c at (i, j) and -w conj(c) at (j, i) when both are (the
 * next pair, in the order pw_zasm_init met them). */
PW__DEF void pw_zasm_term(pw_zasm *S, int i, int j, double w, const double *c, const double *zfix)
{
    double *v = S->A.val, *b = S->b;
    if (i >= 0) v[2 * S->dpos[i]] += w;
    if (j >= 0) v[2 * S->dpos[j]] += w;
    if (i >= 0 && j >= 0) {
        double *ij = v + 2 * S->pos[2 * S->next], *ji = v + 2 * S->pos[2 * S->next + 1];
        ij[0] += -w * c[0];
        ij[1] += -w * c[1];
        ji[0] += -w * c[0];
        ji[1] += w * c[1];
        S->next++;
    } else if (i >= 0) { /* b_i += w c z_j */
        b[2 * i] += w * (c[0] * zfix[0] - c[1] * zfix[1]);
        b[2 * i + 1] += w * (c[0] * zfix[1] + c[1] * zfix[0]);
    } else if (j >= 0) { /* b_j += w conj(c) z_i */
        b[2 * j] += w * (c[0] * zfix[0] + c[1] * zfix[1]);
        b[2 * j + 1] += w * (c[0] * zfix[1] - c[1] * zfix[0]);
    }
}

/* A product y = A x by blocks of rows: each block's share of Re(x^H y). */
typedef struct pw__zmul {
    const pw_zcsr *A;
    const double *x;
    double *y;
    int nb;
    double part[PW__ZBLOCKS];
} pw__zmul;

PW__DEF void pw__zmul_block(void *ctx, int b)
{
    pw__zmul *w = (pw__zmul *)ctx;
    const pw_zcsr *A = w->A;
    const double *x = w->x;
    double d = 0.0;
    int i, k, hi = pw__zblock_start(A->n, w->nb, b + 1);
    for (i = pw__zblock_start(A->n, w->nb, b); i < hi; i++) {
        double sr = 0.0, si = 0.0;
        for (k = A->rowptr[i]; k < A->rowptr[i + 1]; k++) {
            const double *v = A->val + 2 * k, *xx = x + 2 * A->col[k];
            sr += v[0] * xx[0] - v[1] * xx[1];
            si += v[0] * xx[1] + v[1] * xx[0];
        }
        w->y[2 * i] = sr;
        w->y[2 * i + 1] = si;
        d += x[2 * i] * sr + x[2 * i + 1] * si;
    }
    w->part[b] = d;
}

/* y = A x over complex vectors (2n doubles), on A->run's threads; returns
 * Re(x^H y), summed per block of rows and then over the blocks in order. */
PW__DEF double pw_zcsr_mul(const pw_zcsr *A, const double *x, double *y)
{
    pw__zmul w;
    double d = 0.0;
    int b;
    w.A = A;
    w.x = x;
    w.y = y;
    w.nb = pw__zblocks(A->n);
    pw__zfor(A->run, A->n, w.nb, pw__zmul_block, &w);
    for (b = 0; b < w.nb; b++) d += w.part[b];
    return d;
}

/* ---- complex IC(0) -------------------------------------------------------- */

/* L lower triangular with A's lower sparsity and a real positive diagonal
 * (stored last in each row, imaginary part 0), L L^H ~ A. */
typedef struct pw_zic0 {
    int n;
    int *rowptr, *col;
    double *val; /* 2 per entry */
} pw_zic0;

PW__DEF void pw_zic0_free(const pw_alloc *a, pw_zic0 *L)
{
    pw_free(a, L->rowptr);
    pw_free(a, L->col);
    pw_free(a, L->val);
    memset(L, 0, sizeof *L);
}

/* sum over k < below of L_ik conj(L_jk), into (re, im). */
PW__DEF void pw__zic0_dot(const pw_zic0 *L, int i, int j, int below, double *re, double *im)
{
    int a = L->rowptr[i], b = L->rowptr[j], ea = L->rowptr[i + 1], eb = L->rowptr[j + 1];
    double sr = 0.0, si = 0.0;
    while (a < ea && b < eb && L->col[a] < below && L->col[b] < below) {
        if (L->col[a] == L->col[b]) {
            const double *u = L->val + 2 * a++, *v = L->val + 2 * b++;
            sr += u[0] * v[0] + u[1] * v[1];
            si += u[1] * v[0] - u[0] * v[1];
        } else if (L->col[a] < L->col[b]) a++;
        else b++;
    }
    *re = sr;
    *im = si;
}

/* Factors A + shift diag(A); 0 when a pivot is not positive. */
PW__DEF int pw__zic0_try(const pw_zcsr *A, double shift, pw_zic0 *L)
{
    int i, k, out = 0;
    for (i = 0; i < A->n; i++) {
        double diag = 0.0, re, im;
        for (k = A->rowptr[i]; k < A->rowptr[i + 1] && A->col[k] <= i; k++) {
            int j = A->col[k];
            if (j == i) diag = A->val[2 * k] * (1.0 + shift);
            else { /* L_ij = (A_ij - sum_k L_ik conj(L_jk)) / L_jj, L_jj real */
                double djj = L->val[2 * (L->rowptr[j + 1] - 1)];
                pw__zic0_dot(L, i, j, j, &re, &im);
                L->col[out] = j;
                L->val[2 * out] = (A->val[2 * k] - re) / djj;
                L->val[2 * out + 1] = (A->val[2 * k + 1] - im) / djj;
                out++;
                L->rowptr[i + 1] = out; /* rows read themselves while being filled */
            }
        }
        L->rowptr[i + 1] = out;
        pw__zic0_dot(L, i, i, i, &re, &im); /* sum |L_ik|^2: im is 0 */
        diag -= re;
        if (!(diag > 0.0) || !pw_is_finite(diag)) return 0;
        L->col[out] = i;
        L->val[2 * out] = sqrt(diag);
        L->val[2 * out + 1] = 0.0;
        L->rowptr[i + 1] = ++out;
    }
    return 1;
}

/* Factors a Hermitian positive (semi)definite A whose every diagonal entry
 * is present (real); breakdowns are cured by a growing diagonal shift, as
 * pw_ic0_factor does. */
PW__DEF int pw_zic0_factor(const pw_alloc *a, const pw_zcsr *A, pw_zic0 *L, pw_err *e)
{
    int i, k, nnz = 0;
    double shift = 0.0;
    memset(L, 0, sizeof *L);
    for (i = 0; i < A->n; i++)
        for (k = A->rowptr[i]; k < A->rowptr[i + 1] && A->col[k] <= i; k++) nnz++;
    L->n = A->n;
    L->rowptr = (int *)pw_calloc_array(a, (size_t)A->n + 1, sizeof(int), "complex IC(0)", e);
    L->col = (int *)pw_alloc_array(a, (size_t)nnz + (size_t)A->n, sizeof(int), "complex IC(0)", e);
    L->val = (double *)pw_alloc_array(a, 2 * ((size_t)nnz + (size_t)A->n), sizeof(double), "complex IC(0)", e);
    if (!L->rowptr || !L->col || !L->val) {
        pw_zic0_free(a, L);
        return PW_ERR_NOMEM;
    }
    for (k = 0; k<40; k++, shift = shift> 0.0 ? 2.0 * shift : 1e-3)
        if (pw__zic0_try(A, shift, L)) return PW_OK;
    pw_zic0_free(a, L);
    return pw_fail(e, PW_ERR_INVALID, "complex IC(0): the matrix is not positive definite");
}

/* z = (L L^H)^-1 r over complex vectors. */
PW__DEF void pw_zic0_apply(const pw_zic0 *L, const double *r, double *z)
{
    int i, k;
    for (i = 0; i < L->n; i++) { /* L y = r */
        double sr = r[2 * i], si = r[2 * i + 1], d;
        for (k = L->rowptr[i]; k < L->rowptr[i + 1] - 1; k++) {
            const double *v = L->val + 2 * k, *y = z + 2 * L->col[k];
            sr -= v[0] * y[0] - v[1] * y[1];
            si -= v[0] * y[1] + v[1] * y[0];
        }
        d = L->val[2 * (L->rowptr[i + 1] - 1)];
        z[2 * i] = sr / d;
        z[2 * i + 1] = si / d;
    }
    for (i = L->n - 1; i >= 0; i--) { /* L^H z = y, by columns of L^H = rows of L */
        double d = L->val[2 * (L->rowptr[i + 1] - 1)], zr, zi;
        zr = z[2 * i] /= d;
        zi = z[2 * i + 1] /= d;
        for (k = L->rowptr[i]; k < L->rowptr[i + 1] - 1; k++) { /* z_j -= conj(L_ij) z_i */
            const double *v = L->val + 2 * k;
            double *y = z + 2 * L->col[k];
            y[0] -= v[0] * zr + v[1] * zi;
            y[1] -= v[0] * zi - v[1] * zr;
        }
    }
}

PW__DEF double pw__zcsr_op_mul(const void *A, const double *x, double *y)
{
    return pw_zcsr_mul((const pw_zcsr *)A, x, y);
}

PW__DEF void pw__zic0_op(const void *M, const double *r, double *z) { pw_zic0_apply((const pw_zic0 *)M, r, z); }

/* The complex PCG of op on the matrix A = op->actx (op's b, x, precond,
 * mctx and what filled in): the inputs checked, the solve shown to
 * PW_SOLVE_HOOK as `kind`, then the iterations. */
PW__DEF int pw__zpcg_checked(const pw_alloc *a, pw__pcg_op *op, const char *kind, const pw_cg_options *o,
                             pw_cg_stats *s, pw_err *e)
{
    const pw_zcsr *A = (const pw_zcsr *)op->actx;
    if (s) memset(s, 0, sizeof *s);
    if (pw__check_vec(op->b, 2 * A->n, "complex PCG right-hand side b", e) ||
        pw__check_vec(op->x, 2 * A->n, "complex PCG guess x", e) ||
        pw__check_vec(A->val, 2 * A->rowptr[A->n], "complex matrix", e))
        return PW_ERR_INVALID;
    (void)kind; /* seen by PW_SOLVE_HOOK only */
    PW_SOLVE_HOOK(kind, A, op->b, op->x, o);
    op->n = 2 * A->n;
    op->mul = pw__zcsr_op_mul;
    return pw__pcg_run(a, op, o, s, e);
}

/* Solves A x = b (complex, 2n doubles each; x the warm start) for a
 * Hermitian positive definite A, by CG preconditioned with M = pw_zic0 of
 * A; options, stopping rule (|b - A x| <= tol |b|) and errors as
 * pw_pcg_solve. */
PW__DEF int pw_zpcg_solve(const pw_alloc *a, const pw_zcsr *A, const pw_zic0 *M, const double *b, double *x,
                          const pw_cg_options *o, pw_cg_stats *s, pw_err *e)
{
    pw__pcg_op op;
    op.precond = pw__zic0_op;
    op.actx = A;
    op.mctx = M;
    op.b = b;
    op.x = x;
    op.what = "complex PCG";
    return pw__zpcg_checked(a, &op, "zpcg", o, s, e);
}

/* pw_zpcg_solve with A's own IC(0) factor, made and freed here. */
PW__DEF int pw_zic0_solve(const pw_alloc *a, const pw_zcsr *A, const double *b, double *x, const pw_cg_options *o,
                          pw_err *e)
{
    pw_zic0 L;
    int r;
    if ((r = pw_zic0_factor(a, A, &L, e)) != PW_OK) return r;
    r = pw_zpcg_solve(a, A, &L, b, x, o, NULL, e);
    pw_zic0_free(a, &L);
    return r;
}

#endif /* PW__ZSPARSE_V1 */
