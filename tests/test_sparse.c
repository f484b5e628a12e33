/* Tests of src/common/sparse.h: triplets, CSR products, CG and CGLS checked
 * against dense direct solves written here. */
#include "../src/common/sparse.h"
#include "../src/common/rng.h"
#include "pwtest.h"

/* ---- dense helpers ------------------------------------------------------ */

/* Dense n x m copy of A, row-major (caller frees). */
static double *dense_of(const pw_csr *A)
{
    double *d = (double *)calloc((size_t)A->n * A->m + 1, sizeof(double));
    int i, k;
    for (i = 0; i < A->n; i++)
        for (k = A->rowptr[i]; k < A->rowptr[i + 1]; k++) d[i * A->m + A->col[k]] += A->val[k];
    return d;
}

/* Solves the n x n system M x = b by Gaussian elimination with partial
 * pivoting (M and b are overwritten). Returns 0 if M is singular. */
static int dense_solve(double *M, double *b, double *x, int n)
{
    int i, j, k;
    for (k = 0; k < n; k++) {
        int p = k;
        for (i = k + 1; i < n; i++)
            if (fabs(M[i * n + k]) > fabs(M[p * n + k])) p = i;
        if (fabs(M[p * n + k]) < 1e-300) return 0;
        if (p != k) {
            for (j = 0; j < n; j++) {
                double t = M[k * n + j];
                M[k * n + j] = M[p * n + j];
                M[p * n + j] = t;
            }
            {
                double t = b[k];
                b[k] = b[p];
                b[p] = t;
            }
        }
        for (i = k + 1; i < n; i++) {
            double f = M[i * n + k] / M[k * n + k];
            for (j = k; j < n; j++) M[i * n + j] -= f * M[k * n + j];
            b[i] -= f * b[k];
        }
    }
    for (i = n - 1; i >= 0; i--) {
        double s = b[i];
        for (j = i + 1; j < n; j++) s -= M[i * n + j] * x[j];
        x[i] = s / M[i * n + i];
    }
    return 1;
}

/* Dense Cholesky solve of SPD M (overwritten with L). Returns 0 if M is not
 * positive definite. */
static int dense_cholesky_solve(double *M, const double *b, double *x, int n)
{
    int i, j, k;
    for (j = 0; j < n; j++) {
        double d = M[j * n + j];
        for (k = 0; k < j; k++) d -= M[j * n + k] * M[j * n + k];
        if (d <= 0) return 0;
        M[j * n + j] = sqrt(d);
        for (i = j + 1; i < n; i++) {
            double s = M[i * n + j];
            for (k = 0; k < j; k++) s -= M[i * n + k] * M[j * n + k];
            M[i * n + j] = s / M[j * n + j];
        }
    }
    for (i = 0; i < n; i++) { /* L y = b */
        double s = b[i];
        for (k = 0; k < i; k++) s -= M[i * n + k] * x[k];
        x[i] = s / M[i * n + i];
    }
    for (i = n - 1; i >= 0; i--) { /* Lᵀ x = y */
        double s = x[i];
        for (k = i + 1; k < n; k++) s -= M[k * n + i] * x[k];
        x[i] = s / M[i * n + i];
    }
    return 1;
}

static double vec_norm(const double *v, int n)
{
    double s = 0;
    int i;
    for (i = 0; i < n; i++) s += v[i] * v[i];
    return sqrt(s);
}

static double max_abs_diff(const double *a, const double *b, int n)
{
    double m = 0;
    int i;
    for (i = 0; i < n; i++)
        if (fabs(a[i] - b[i]) > m) m = fabs(a[i] - b[i]);
    return m;
}

/* |b - A x| / |b| computed independently of the solver. */
static double true_rel_residual(const pw_csr *A, const double *b, const double *x)
{
    double *r = (double *)malloc(sizeof(double) * (size_t)(A->n + 1)), s = 0, bn;
    int i, k;
    for (i = 0; i < A->n; i++) {
        double ax = 0;
        for (k = A->rowptr[i]; k < A->rowptr[i + 1]; k++) ax += A->val[k] * x[A->col[k]];
        r[i] = b[i] - ax;
        s += r[i] * r[i];
    }
    bn = vec_norm(b, A->n);
    free(r);
    return sqrt(s) / (bn > 0 ? bn : 1);
}

static double rnd(pw_rng *r, double lo, double hi) { return lo + (hi - lo) * pw_rng_double(r); }

/* ---- matrix builders ---------------------------------------------------- */

/* A random sparse symmetric, strictly diagonally dominant (hence SPD)
 * matrix with about `per_row` off-diagonal entries per row. */
static int random_spd(pw_csr *A, int n, int per_row, uint64_t seed)
{
    pw_triplets t;
    pw_rng r = pw_rng_seed(seed, 1);
    double *rowsum = (double *)calloc((size_t)n, sizeof(double));
    int i, k, rc = 0;
    pw_err e;
    pw_err_clear(&e);
    pw_triplets_init(&t, NULL, n, n, &e);
    for (i = 0; i < n; i++) {
        for (k = 0; k < per_row / 2; k++) {
            int j = (int)pw_rng_below(&r, (uint32_t)n);
            double v = rnd(&r, -1, 1);
            if (j == i) continue;
            rc |= pw_triplets_add(&t, i, j, v, &e);
            rc |= pw_triplets_add(&t, j, i, v, &e);
            rowsum[i] += fabs(v);
            rowsum[j] += fabs(v);
        }
    }
    for (i = 0; i < n; i++) rc |= pw_triplets_add(&t, i, i, rowsum[i] + rnd(&r, 0.01, 1), &e);
    rc |= pw_csr_from_triplets(NULL, &t, A, &e);
    pw_triplets_free(&t);
    free(rowsum);
    return rc;
}

/* 2D Laplacian on a k x k grid. Dirichlet: boundary unknowns get identity
 * rows and their known values g move to the right-hand side, keeping the
 * matrix symmetric. Otherwise (Neumann) the matrix is the singular graph
 * Laplacian, plus `penalty` on the diagonal of vertex 0 if non-zero. b is
 * filled from f (interior source) and g (boundary values). */
static int laplacian(pw_csr *A, double *b, int k, int dirichlet, double penalty, uint64_t seed)
{
    pw_triplets t;
    pw_rng r = pw_rng_seed(seed, 2);
    int x, y, rc = 0, n = k * k;
    double *g = (double *)malloc(sizeof(double) * (size_t)n);
    pw_err e;
    pw_err_clear(&e);
    for (x = 0; x < n; x++) g[x] = rnd(&r, -1, 1);
    pw_triplets_init(&t, NULL, n, n, &e);
    for (y = 0; y < k; y++)
        for (x = 0; x < k; x++) {
            int i = y * k + x, d, bnd = x == 0 || y == 0 || x == k - 1 || y == k - 1;
            static const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
            b[i] = rnd(&r, -1, 1) / (double)n;
            if (dirichlet && bnd) {
                rc |= pw_triplets_add(&t, i, i, 1.0, &e);
                b[i] = g[i];
                continue;
            }
            for (d = 0; d < 4; d++) {
                int xx = x + dx[d], yy = y + dy[d], j = yy * k + xx;
                if (xx < 0 || yy < 0 || xx >= k || yy >= k) continue;
                rc |= pw_triplets_add(&t, i, i, 1.0, &e);
                if (dirichlet && (xx == 0 || yy == 0 || xx == k - 1 || yy == k - 1))
                    b[i] += g[j]; /* known neighbour: to the right-hand side */
                else
                    rc |= pw_triplets_add(&t, i, j, -1.0, &e);
            }
        }
    if (!dirichlet && penalty > 0) rc |= pw_triplets_add(&t, 0, 0, penalty, &e);
    rc |= pw_csr_from_triplets(NULL, &t, A, &e);
    pw_triplets_free(&t);
    free(g);
    return rc;
}

/* A random sparse rows x cols matrix, each row with `per_row` entries. */
static int random_rect(pw_csr *A, int rows, int cols, int per_row, uint64_t seed)
{
    pw_triplets t;
    pw_rng r = pw_rng_seed(seed, 3);
    int i, k, rc = 0;
    pw_err e;
    pw_err_clear(&e);
    pw_triplets_init(&t, NULL, rows, cols, &e);
    for (i = 0; i < rows; i++)
        for (k = 0; k < per_row; k++)
            rc |= pw_triplets_add(&t, i, (int)pw_rng_below(&r, (uint32_t)cols), rnd(&r, -2, 2),
                                  &e);
    rc |= pw_csr_from_triplets(NULL, &t, A, &e);
    pw_triplets_free(&t);
    return rc;
}

/* Checks CG's answer against a dense Cholesky solve. */
static void check_cg_vs_dense(const pw_csr *A, const double *b, const char *what)
{
    int n = A->n;
    double *M = dense_of(A), *xd = (double *)calloc((size_t)n, sizeof(double));
    double *x = (double *)calloc((size_t)n, sizeof(double)), err, scale;
    pw_cg_stats st;
    pw_cg_options o = pw_cg_default_options();
    pw_err e;
    pw_err_clear(&e);
    o.tol = 1e-12;
    CHECKF(dense_cholesky_solve(M, b, xd, n), "%s: dense Cholesky failed", what);
    CHECKF(pw_cg_solve(NULL, A, b, x, &o, &st, &e) == PW_OK, "%s: %s", what, e.msg);
    CHECK(st.converged);
    CHECKF(true_rel_residual(A, b, x) <= 1e-12, "%s: residual %g", what,
           true_rel_residual(A, b, x));
    err = max_abs_diff(x, xd, n);
    scale = vec_norm(xd, n) / sqrt((double)n) + 1e-300;
    CHECKF(err / scale < 1e-8, "%s: max error %g (scale %g)", what, err, scale);
    free(M);
    free(xd);
    free(x);
}

/* ---- triplets and CSR --------------------------------------------------- */

static void t_triplets_duplicates(void)
{
    pw_triplets t;
    pw_csr A;
    pw_err e;
    pw_err_clear(&e);
    REQUIRE(pw_triplets_init(&t, NULL, 3, 4, &e) == PW_OK);
    /* out of order, with duplicates and a cancelling pair */
    pw_triplets_add(&t, 2, 3, 1.0, &e);
    pw_triplets_add(&t, 0, 2, 2.0, &e);
    pw_triplets_add(&t, 0, 0, 5.0, &e);
    pw_triplets_add(&t, 0, 2, 0.5, &e);
    pw_triplets_add(&t, 2, 0, 7.0, &e);
    pw_triplets_add(&t, 2, 3, 2.0, &e);
    pw_triplets_add(&t, 1, 1, 3.0, &e);
    pw_triplets_add(&t, 1, 1, -3.0, &e);
    pw_triplets_add(&t, 0, 2, 0.25, &e);
    REQUIRE(e.code == PW_OK);
    CHECK_EQ_INT(t.count, 9);
    REQUIRE(pw_csr_from_triplets(NULL, &t, &A, &e) == PW_OK);
    CHECK_EQ_INT(A.n, 3);
    CHECK_EQ_INT(A.m, 4);
    CHECK_EQ_INT(A.rowptr[0], 0);
    CHECK_EQ_INT(A.rowptr[1], 2);
    CHECK_EQ_INT(A.rowptr[2], 3);
    CHECK_EQ_INT(A.rowptr[3], 5);
    CHECK_EQ_INT(A.col[0], 0);
    CHECK(A.val[0] == 5.0);
    CHECK_EQ_INT(A.col[1], 2);
    CHECK(A.val[1] == 2.75);
    CHECK_EQ_INT(A.col[2], 1);
    CHECK(A.val[2] == 0.0); /* cancelled entries keep their place */
    CHECK_EQ_INT(A.col[3], 0);
    CHECK(A.val[3] == 7.0);
    CHECK_EQ_INT(A.col[4], 3);
    CHECK(A.val[4] == 3.0);
    pw_csr_free(NULL, &A);
    /* clearing keeps the memory and starts over */
    pw_triplets_clear(&t);
    CHECK_EQ_INT(t.count, 0);
    CHECK(pw_triplets_add(&t, 1, 1, 1.0, &e) == PW_OK);
    REQUIRE(pw_csr_from_triplets(NULL, &t, &A, &e) == PW_OK);
    CHECK_EQ_INT(A.rowptr[3], 1);
    pw_csr_free(NULL, &A);
    pw_triplets_free(&t);
}

static void t_triplets_invalid(void)
{
    pw_triplets t;
    pw_err e;
    pw_err_clear(&e);
    CHECK(pw_triplets_init(&t, NULL, -1, 3, &e) == PW_ERR_INVALID);
    pw_err_clear(&e);
    REQUIRE(pw_triplets_init(&t, NULL, 2, 3, &e) == PW_OK);
    CHECK(pw_triplets_add(&t, 2, 0, 1.0, &e) == PW_ERR_INVALID);
    CHECKF(strstr(e.msg, "(2, 0)") != NULL, "message: %s", e.msg);
    pw_err_clear(&e);
    CHECK(pw_triplets_add(&t, 0, 3, 1.0, &e) == PW_ERR_INVALID);
    pw_err_clear(&e);
    CHECK(pw_triplets_add(&t, -1, 0, 1.0, &e) == PW_ERR_INVALID);
    pw_err_clear(&e);
    CHECK(pw_triplets_add(&t, 0, 0, sqrt(-1.0), &e) == PW_ERR_INVALID);
    pw_err_clear(&e);
    CHECK(pw_triplets_add(&t, 0, 0, HUGE_VAL, &e) == PW_ERR_INVALID);
    CHECK_EQ_INT(t.count, 0);
    pw_triplets_free(&t);
}

/* Many random entries: the CSR equals the dense sum of the triplets. */
static void t_triplets_random(void)
{
    pw_triplets t;
    pw_csr A;
    pw_rng r = pw_rng_seed(7, 7);
    int n = 37, m = 23, k, i;
    double dense[37 * 23], *d;
    pw_err e;
    pw_err_clear(&e);
    memset(dense, 0, sizeof dense);
    pw_triplets_init(&t, NULL, n, m, &e);
    for (k = 0; k < 3000; k++) {
        int a = (int)pw_rng_below(&r, (uint32_t)n), b = (int)pw_rng_below(&r, (uint32_t)m);
        double v = (double)(int)pw_rng_below(&r, 9) - 4; /* integers: exact sums */
        pw_triplets_add(&t, a, b, v, &e);
        dense[a * m + b] += v;
    }
    REQUIRE(e.code == PW_OK);
    REQUIRE(pw_csr_from_triplets(NULL, &t, &A, &e) == PW_OK);
    d = dense_of(&A);
    CHECK(max_abs_diff(d, dense, n * m) == 0);
    for (i = 0; i < n; i++)
        for (k = A.rowptr[i] + 1; k < A.rowptr[i + 1]; k++) CHECK(A.col[k - 1] < A.col[k]);
    free(d);
    pw_csr_free(NULL, &A);
    pw_triplets_free(&t);
}

static void t_csr_products(void)
{
    pw_csr A, At;
    pw_rng r = pw_rng_seed(3, 3);
    int rows = 41, cols = 29, i, j;
    double x[41], y[41], xt[41], yt[29], ref[41], *d, diag[29];
    pw_err e;
    pw_err_clear(&e);
    REQUIRE(random_rect(&A, rows, cols, 4, 11) == PW_OK);
    d = dense_of(&A);
    for (i = 0; i < cols; i++) x[i] = rnd(&r, -1, 1);
    for (i = 0; i < rows; i++) xt[i] = rnd(&r, -1, 1);
    pw_csr_mul(&A, x, y);
    for (i = 0; i < rows; i++) {
        ref[i] = 0;
        for (j = 0; j < cols; j++) ref[i] += d[i * cols + j] * x[j];
    }
    CHECK(max_abs_diff(y, ref, rows) < 1e-12);
    pw_csr_mul_t(&A, xt, yt);
    for (j = 0; j < cols; j++) {
        ref[j] = 0;
        for (i = 0; i < rows; i++) ref[j] += d[i * cols + j] * xt[i];
    }
    CHECK(max_abs_diff(yt, ref, cols) < 1e-12);
    pw_csr_diag(&A, diag);
    for (i = 0; i < cols; i++) CHECK(diag[i] == d[i * cols + i]);
    REQUIRE(pw_csr_transpose(NULL, &A, &At, &e) == PW_OK);
    CHECK_EQ_INT(At.n, cols);
    CHECK_EQ_INT(At.m, rows);
    {
        double *dt = dense_of(&At);
        int bad = 0;
        for (i = 0; i < rows; i++)
            for (j = 0; j < cols; j++) bad += dt[j * rows + i] != d[i * cols + j];
        CHECK_EQ_INT(bad, 0);
        for (i = 0; i < At.n; i++)
            for (j = At.rowptr[i] + 1; j < At.rowptr[i + 1]; j++) CHECK(At.col[j - 1] < At.col[j]);
        free(dt);
    }
    CHECK(pw_csr_check(&A, &e) == PW_OK);
    free(d);
    pw_csr_free(NULL, &A);
    pw_csr_free(NULL, &At);
}

/* AᵀA equals the dense product, is sorted and exactly symmetric. */
static void t_csr_ata(void)
{
    static const int shapes[3][3] = {{60, 25, 3}, {25, 25, 5}, {10, 40, 6}};
    int s;
    for (s = 0; s < 3; s++) {
        pw_csr A, C;
        int rows = shapes[s][0], cols = shapes[s][1], i, j, k, bad = 0, unsorted = 0;
        double *d, *c, maxerr = 0;
        pw_err e;
        pw_err_clear(&e);
        REQUIRE(random_rect(&A, rows, cols, shapes[s][2], 20 + s) == PW_OK);
        REQUIRE(pw_csr_ata(NULL, &A, &C, &e) == PW_OK);
        CHECK_EQ_INT(C.n, cols);
        CHECK_EQ_INT(C.m, cols);
        d = dense_of(&A);
        c = dense_of(&C);
        for (i = 0; i < cols; i++)
            for (j = 0; j < cols; j++) {
                double ref = 0;
                for (k = 0; k < rows; k++) ref += d[k * cols + i] * d[k * cols + j];
                if (fabs(ref - c[i * cols + j]) > maxerr) maxerr = fabs(ref - c[i * cols + j]);
                bad += c[i * cols + j] != c[j * cols + i];
            }
        for (i = 0; i < C.n; i++)
            for (k = C.rowptr[i] + 1; k < C.rowptr[i + 1]; k++) unsorted += C.col[k - 1] >= C.col[k];
        CHECKF(maxerr < 1e-12, "shape %d: max error %g", s, maxerr);
        CHECK_EQ_INT(bad, 0);
        CHECK_EQ_INT(unsorted, 0);
        free(d);
        free(c);
        pw_csr_free(NULL, &A);
        pw_csr_free(NULL, &C);
    }
}

static void t_csr_check_malformed(void)
{
    int rowptr[3] = {0, 2, 1}, col[2] = {0, 5};
    double val[2] = {1, 2};
    pw_csr A;
    pw_err e;
    A.n = 2;
    A.m = 2;
    A.rowptr = rowptr;
    A.col = col;
    A.val = val;
    pw_err_clear(&e);
    CHECK(pw_csr_check(&A, &e) == PW_ERR_INVALID); /* column 5 out of range */
    rowptr[1] = 1;
    rowptr[2] = 2;
    col[1] = 1;
    val[1] = sqrt(-1.0);
    pw_err_clear(&e);
    CHECK(pw_csr_check(&A, &e) == PW_ERR_INVALID); /* NaN */
    CHECKF(strstr(e.msg, "not finite") != NULL, "message: %s", e.msg);
    rowptr[1] = 2;
    rowptr[2] = 1;
    val[1] = 1;
    pw_err_clear(&e);
    CHECK(pw_csr_check(&A, &e) == PW_ERR_INVALID); /* decreasing row pointer */
}

/* ---- conjugate gradients ------------------------------------------------ */

static void t_cg_random_spd(void)
{
    static const int sizes[] = {1, 2, 5, 17, 60, 150};
    int s;
    for (s = 0; s < (int)(sizeof sizes / sizeof *sizes); s++) {
        pw_csr A;
        int n = sizes[s], i;
        double *b = (double *)malloc(sizeof(double) * (size_t)n);
        pw_rng r = pw_rng_seed(100 + (uint64_t)s, 5);
        char what[32];
        REQUIRE(random_spd(&A, n, 6, 50 + (uint64_t)s) == PW_OK);
        for (i = 0; i < n; i++) b[i] = rnd(&r, -1, 1);
        snprintf(what, sizeof what, "n=%d", n);
        check_cg_vs_dense(&A, b, what);
        free(b);
        pw_csr_free(NULL, &A);
    }
}

/* SPD but not diagonally dominant: BᵀB + small shift, built with pw_csr_ata. */
static void t_cg_normal_matrix(void)
{
    pw_csr B, A;
    pw_triplets t;
    int n = 40, i, k;
    double b[40];
    pw_rng r = pw_rng_seed(9, 9);
    pw_err e;
    pw_err_clear(&e);
    REQUIRE(random_rect(&B, 80, n, 3, 31) == PW_OK);
    REQUIRE(pw_csr_ata(NULL, &B, &A, &e) == PW_OK);
    /* add 0.1 I through triplets to make it safely definite */
    pw_triplets_init(&t, NULL, n, n, &e);
    for (i = 0; i < n; i++) {
        for (k = A.rowptr[i]; k < A.rowptr[i + 1]; k++) pw_triplets_add(&t, i, A.col[k], A.val[k], &e);
        pw_triplets_add(&t, i, i, 0.1, &e);
    }
    pw_csr_free(NULL, &A);
    REQUIRE(pw_csr_from_triplets(NULL, &t, &A, &e) == PW_OK);
    for (i = 0; i < n; i++) b[i] = rnd(&r, -1, 1);
    check_cg_vs_dense(&A, b, "BtB+0.1I");
    pw_triplets_free(&t);
    pw_csr_free(NULL, &A);
    pw_csr_free(NULL, &B);
}

static void t_cg_laplacian_dirichlet(void)
{
    static const int ks[] = {3, 8, 14};
    int s;
    for (s = 0; s < 3; s++) {
        pw_csr A;
        int k = ks[s];
        double *b = (double *)malloc(sizeof(double) * (size_t)(k * k));
        char what[32];
        REQUIRE(laplacian(&A, b, k, 1, 0, 40 + (uint64_t)s) == PW_OK);
        snprintf(what, sizeof what, "k=%d", k);
        check_cg_vs_dense(&A, b, what);
        free(b);
        pw_csr_free(NULL, &A);
    }
}

/* Starting from the exact solution takes 0 or 1 iterations. */
static void t_cg_warm_start(void)
{
    pw_csr A;
    int n = 100, i;
    double b[100], x[100], *M = NULL;
    pw_cg_stats st;
    pw_err e;
    pw_rng r = pw_rng_seed(4, 4);
    pw_err_clear(&e);
    REQUIRE(laplacian(&A, b, 10, 1, 0, 77) == PW_OK);
    (void)r;
    M = dense_of(&A);
    REQUIRE(dense_cholesky_solve(M, b, x, n));
    REQUIRE(pw_cg_solve(NULL, &A, b, x, NULL, &st, &e) == PW_OK);
    CHECKF(st.iterations <= 1, "iterations %d", st.iterations);
    CHECK(st.converged);
    CHECK(st.residual <= 1e-8);
    /* a slightly perturbed start converges in fewer iterations than a cold one */
    {
        pw_cg_stats cold;
        double x0[100];
        for (i = 0; i < n; i++) {
            x[i] += 1e-6 * rnd(&r, -1, 1);
            x0[i] = 0;
        }
        REQUIRE(pw_cg_solve(NULL, &A, b, x, NULL, &st, &e) == PW_OK);
        REQUIRE(pw_cg_solve(NULL, &A, b, x0, NULL, &cold, &e) == PW_OK);
        CHECKF(st.iterations < cold.iterations, "warm %d, cold %d", st.iterations, cold.iterations);
        pwt_info("warm start (1e-6 perturbation): %d iterations, cold: %d", st.iterations,
                 cold.iterations);
    }
    free(M);
    pw_csr_free(NULL, &A);
}

/* The cap is respected and reported; x still improves on the guess. */
static void t_cg_iteration_cap(void)
{
    pw_csr A;
    int k = 30, n = 900, cap;
    double *b = (double *)malloc(sizeof(double) * 900), *x = (double *)calloc(900, sizeof(double));
    pw_cg_options o = pw_cg_default_options();
    pw_cg_stats st;
    pw_err e;
    REQUIRE(laplacian(&A, b, k, 1, 0, 5) == PW_OK);
    for (cap = 1; cap <= 16; cap *= 4) {
        memset(x, 0, sizeof(double) * (size_t)n);
        o.max_iter = cap;
        pw_err_clear(&e);
        CHECK(pw_cg_solve(NULL, &A, b, x, &o, &st, &e) == PW_ERR_NOCONVERGE);
        CHECK_EQ_INT(st.iterations, cap);
        CHECK(!st.converged);
        CHECK(st.residual > 1e-8 && st.residual < 1.0);
        CHECKF(fabs(st.residual - true_rel_residual(&A, b, x)) < 1e-12, "reported %g, true %g",
               st.residual, true_rel_residual(&A, b, x));
        CHECKF(strstr(e.msg, "residual") != NULL && strstr(e.msg, "cap") != NULL, "message: %s",
               e.msg);
    }
    /* continuing from the capped iterate (a warm start) finishes the job */
    o.max_iter = 0;
    pw_err_clear(&e);
    CHECK(pw_cg_solve(NULL, &A, b, x, &o, &st, &e) == PW_OK);
    CHECK(st.converged);
    free(b);
    free(x);
    pw_csr_free(NULL, &A);
}

/* Each tolerance is met by the true residual of the returned x. */
static void t_cg_tolerance(void)
{
    static const double tols[] = {1e-2, 1e-5, 1e-8, 1e-11, 1e-13};
    pw_csr A;
    int k = 24, n = 576, s, prev = -1;
    double *b = (double *)malloc(sizeof(double) * 576), *x = (double *)malloc(sizeof(double) * 576);
    pw_cg_options o = pw_cg_default_options();
    pw_cg_stats st;
    pw_err e;
    REQUIRE(laplacian(&A, b, k, 1, 0, 6) == PW_OK);
    for (s = 0; s < 5; s++) {
        double tr;
        memset(x, 0, sizeof(double) * (size_t)n);
        o.tol = tols[s];
        pw_err_clear(&e);
        CHECKF(pw_cg_solve(NULL, &A, b, x, &o, &st, &e) == PW_OK, "tol %g: %s", tols[s], e.msg);
        tr = true_rel_residual(&A, b, x);
        CHECKF(tr <= tols[s], "tol %g: true residual %g", tols[s], tr);
        CHECKF(st.iterations >= prev, "tol %g: %d iterations", tols[s], st.iterations);
        prev = st.iterations;
        pwt_info("tol %g: %d iterations, residual %.3g", tols[s], st.iterations, tr);
    }
    free(b);
    free(x);
    pw_csr_free(NULL, &A);
}

static void t_cg_zero_rhs(void)
{
    pw_csr A;
    double b[16] = {0}, x[16];
    int i;
    pw_cg_stats st;
    pw_err e;
    pw_err_clear(&e);
    REQUIRE(random_spd(&A, 16, 4, 3) == PW_OK);
    for (i = 0; i < 16; i++) x[i] = i + 1;
    CHECK(pw_cg_solve(NULL, &A, b, x, NULL, &st, &e) == PW_OK);
    CHECK_EQ_INT(st.iterations, 0);
    CHECK(st.converged);
    for (i = 0; i < 16; i++) CHECK(x[i] == 0);
    pw_csr_free(NULL, &A);
}

static void t_cg_invalid(void)
{
    pw_csr A, R;
    double b[10], x[10];
    int i;
    pw_cg_stats st;
    pw_err e;
    pw_err_clear(&e);
    REQUIRE(random_spd(&A, 10, 4, 8) == PW_OK);
    for (i = 0; i < 10; i++) b[i] = x[i] = 1;
    b[3] = sqrt(-1.0);
    CHECK(pw_cg_solve(NULL, &A, b, x, NULL, &st, &e) == PW_ERR_INVALID);
    CHECKF(strstr(e.msg, "b[3]") != NULL, "message: %s", e.msg);
    b[3] = 1;
    x[7] = HUGE_VAL;
    pw_err_clear(&e);
    CHECK(pw_cg_solve(NULL, &A, b, x, NULL, &st, &e) == PW_ERR_INVALID);
    CHECKF(strstr(e.msg, "x[7]") != NULL, "message: %s", e.msg);
    x[7] = 1;
    A.val[2] = sqrt(-1.0);
    pw_err_clear(&e);
    CHECK(pw_cg_solve(NULL, &A, b, x, NULL, &st, &e) == PW_ERR_INVALID);
    pw_csr_free(NULL, &A);
    REQUIRE(random_rect(&R, 10, 9, 2, 1) == PW_OK);
    pw_err_clear(&e);
    CHECK(pw_cg_solve(NULL, &R, b, x, NULL, &st, &e) == PW_ERR_INVALID); /* not square */
    pw_csr_free(NULL, &R);
}

/* Zero and negative diagonals: the preconditioner falls back to 1. */
static void t_cg_bad_diagonal(void)
{
    pw_triplets t;
    pw_csr A;
    double b[3] = {1, 0, 2}, x[3] = {0, 0, 0};
    pw_cg_stats st;
    pw_err e;
    int i;
    pw_err_clear(&e);
    /* semidefinite: unknown 1 has an empty row and b[1] = 0 */
    pw_triplets_init(&t, NULL, 3, 3, &e);
    pw_triplets_add(&t, 0, 0, 2, &e);
    pw_triplets_add(&t, 2, 2, 4, &e);
    pw_triplets_add(&t, 0, 2, 1, &e);
    pw_triplets_add(&t, 2, 0, 1, &e);
    REQUIRE(pw_csr_from_triplets(NULL, &t, &A, &e) == PW_OK);
    CHECK(pw_cg_solve(NULL, &A, b, x, NULL, &st, &e) == PW_OK);
    CHECK_NEAR(x[0], 2.0 / 7.0, 1e-12);
    CHECK(x[1] == 0);
    CHECK_NEAR(x[2], 3.0 / 7.0, 1e-12);
    pw_csr_free(NULL, &A);
    /* negative definite: breaks down at once, cleanly */
    pw_triplets_clear(&t);
    for (i = 0; i < 3; i++) pw_triplets_add(&t, i, i, -1, &e);
    REQUIRE(pw_csr_from_triplets(NULL, &t, &A, &e) == PW_OK);
    memset(x, 0, sizeof x);
    CHECK(pw_cg_solve(NULL, &A, b, x, NULL, &st, &e) == PW_ERR_NOCONVERGE);
    CHECKF(strstr(e.msg, "broke down") != NULL, "message: %s", e.msg);
    for (i = 0; i < 3; i++) CHECK(pw_is_finite(x[i]));
    pw_csr_free(NULL, &A);
    pw_triplets_free(&t);
}

/* Semidefinite consistent systems: a Neumann Laplacian with a zero-mean
 * right-hand side, and the same fixed by a penalty on one vertex. */
static void t_cg_semidefinite(void)
{
    pw_csr A;
    int k = 12, n = 144, i;
    double b[144], x[144], mean = 0;
    pw_cg_stats st;
    pw_err e;
    pw_err_clear(&e);
    REQUIRE(laplacian(&A, b, k, 0, 0, 9) == PW_OK);
    for (i = 0; i < n; i++) mean += b[i] / n;
    for (i = 0; i < n; i++) {
        b[i] -= mean;
        x[i] = 0;
    }
    CHECKF(pw_cg_solve(NULL, &A, b, x, NULL, &st, &e) == PW_OK, "%s", e.msg);
    CHECKF(true_rel_residual(&A, b, x) <= 1e-8, "residual %g", true_rel_residual(&A, b, x));
    /* Solutions differ by a constant. (L + 11ᵀ) y = b has the zero-mean one;
     * preconditioned CG need not return it (its iterates live in the range
     * of D⁻¹L), so compare after removing the mean. */
    {
        double *M = dense_of(&A), y[144], scale;
        for (i = 0; i < n * n; i++) M[i] += 1.0;
        REQUIRE(dense_cholesky_solve(M, b, y, n));
        mean = 0;
        for (i = 0; i < n; i++) mean += x[i] / n;
        for (i = 0; i < n; i++) x[i] -= mean;
        scale = vec_norm(y, n) / sqrt((double)n);
        CHECKF(max_abs_diff(x, y, n) / scale < 1e-6, "error %g", max_abs_diff(x, y, n) / scale);
        free(M);
    }
    pw_csr_free(NULL, &A);
    REQUIRE(laplacian(&A, b, k, 0, 10.0, 9) == PW_OK);
    check_cg_vs_dense(&A, b, "penalty");
    pw_csr_free(NULL, &A);
}

static void t_cg_determinism(void)
{
    pw_csr A;
    int n = 400, i;
    double b[400], x1[400], x2[400];
    pw_cg_stats s1, s2;
    pw_err e;
    pw_err_clear(&e);
    REQUIRE(random_spd(&A, n, 8, 99) == PW_OK);
    for (i = 0; i < n; i++) {
        b[i] = sin(i * 0.37);
        x1[i] = x2[i] = cos(i * 0.11);
    }
    REQUIRE(pw_cg_solve(NULL, &A, b, x1, NULL, &s1, &e) == PW_OK);
    REQUIRE(pw_cg_solve(NULL, &A, b, x2, NULL, &s2, &e) == PW_OK);
    CHECK(memcmp(x1, x2, sizeof x1) == 0);
    CHECK_EQ_INT(s1.iterations, s2.iterations);
    CHECK(s1.residual == s2.residual);
    pw_csr_free(NULL, &A);
}

static int cancel_after_first(void *user, float done, const char *stage)
{
    int *calls = (int *)user;
    (void)done;
    (void)stage;
    return ++*calls >= 2;
}

static void t_cg_progress_cancel(void)
{
    pw_csr A;
    int calls = 0;
    double *b = (double *)malloc(sizeof(double) * 1600), *x = (double *)calloc(1600, sizeof(double));
    pw_cg_options o = pw_cg_default_options();
    pw_cg_stats st;
    pw_err e;
    pw_err_clear(&e);
    REQUIRE(laplacian(&A, b, 40, 1, 0, 12) == PW_OK);
    o.progress.fn = cancel_after_first;
    o.progress.user = &calls;
    CHECK(pw_cg_solve(NULL, &A, b, x, &o, &st, &e) == PW_ERR_CANCELLED);
    CHECK_EQ_INT(calls, 2);
    CHECK_EQ_INT(st.iterations, 64);
    free(b);
    free(x);
    pw_csr_free(NULL, &A);
}

/* ---- allocation failures ------------------------------------------------ */

/* Builds, multiplies and solves with every allocation failing in turn:
 * each failure is reported as PW_ERR_NOMEM and nothing leaks. */
static void t_alloc_failures(void)
{
    int budget, finished = 0;
    for (budget = 0; budget < 120 && !finished; budget++) {
        pwt_alloc_state f = {0, 0, budget};
        pw_alloc al = {pwt_malloc, pwt_realloc, pwt_free, &f};
        pw_triplets t;
        pw_csr A, C;
        double b[30], x[30];
        pw_cg_stats st;
        pw_err e;
        int i, rc;
        pw_err_clear(&e);
        memset(&A, 0, sizeof A);
        memset(&C, 0, sizeof C);
        rc = pw_triplets_init(&t, &al, 30, 30, &e);
        for (i = 0; i < 100 && !rc; i++) rc = pw_triplets_add(&t, i % 30, (i * 7) % 30, 1.0 + i, &e);
        for (i = 0; i < 30 && !rc; i++) rc = pw_triplets_add(&t, i, i, 500.0, &e);
        if (!rc) rc = pw_csr_from_triplets(&al, &t, &A, &e);
        if (!rc) rc = pw_csr_ata(&al, &A, &C, &e);
        for (i = 0; i < 30; i++) {
            b[i] = 1;
            x[i] = 0;
        }
        if (!rc) rc = pw_lsq_solve(&al, &A, b, x, NULL, &st, &e);
        if (!rc) rc = pw_cg_solve(&al, &C, b, x, NULL, &st, &e);
        if (!rc) {
            pw_ldlt F;
            if (!(rc = pw_ldlt_factor(&al, &C, &F, &e))) pw_ldlt_solve(&F, b, x), pw_ldlt_free(&al, &F);
            else CHECKF(!F.perm && !F.Lx, "budget %d: a failed factor kept its arrays", budget);
        }
        CHECKF(rc == PW_OK || rc == PW_ERR_NOMEM, "budget %d: %d %s", budget, rc, e.msg);
        if (rc) CHECKF(e.code == PW_ERR_NOMEM && e.msg[0], "budget %d: no message", budget);
        finished = rc == PW_OK;
        pw_triplets_free(&t);
        pw_csr_free(&al, &A);
        pw_csr_free(&al, &C);
        CHECKF(f.live == 0, "budget %d: %ld blocks leaked", budget, f.live);
    }
    CHECK(finished);
}

/* ---- least squares ------------------------------------------------------ */

/* Dense normal-equation solution of min |A x - b|. */
static void dense_lsq(const pw_csr *A, const double *b, double *x)
{
    int n = A->n, m = A->m, i, j, k;
    double *d = dense_of(A), *M = (double *)calloc((size_t)m * m, sizeof(double));
    double *rhs = (double *)calloc((size_t)m, sizeof(double));
    for (i = 0; i < m; i++) {
        for (j = 0; j < m; j++)
            for (k = 0; k < n; k++) M[i * m + j] += d[k * m + i] * d[k * m + j];
        for (k = 0; k < n; k++) rhs[i] += d[k * m + i] * b[k];
    }
    dense_solve(M, rhs, x, m);
    free(d);
    free(M);
    free(rhs);
}

static void t_lsq_overdetermined(void)
{
    static const int shapes[3][2] = {{50, 10}, {200, 60}, {31, 30}};
    int s;
    for (s = 0; s < 3; s++) {
        pw_csr A;
        int n = shapes[s][0], m = shapes[s][1], i, j;
        double *b = (double *)malloc(sizeof(double) * (size_t)n);
        double *x = (double *)calloc((size_t)m, sizeof(double));
        double *xd = (double *)calloc((size_t)m, sizeof(double)), err, scale;
        pw_rng r = pw_rng_seed(60 + (uint64_t)s, 6);
        pw_cg_options o = pw_cg_default_options();
        pw_cg_stats st;
        pw_err e;
        pw_err_clear(&e);
        REQUIRE(random_rect(&A, n, m, 4, 70 + (uint64_t)s) == PW_OK);
        {   /* make sure every column is used: add a diagonal block */
            pw_triplets t;
            pw_triplets_init(&t, NULL, n, m, &e);
            for (i = 0; i < n; i++)
                for (j = A.rowptr[i]; j < A.rowptr[i + 1]; j++)
                    pw_triplets_add(&t, i, A.col[j], A.val[j], &e);
            for (j = 0; j < m; j++) pw_triplets_add(&t, j, j, 1.0, &e);
            pw_csr_free(NULL, &A);
            REQUIRE(pw_csr_from_triplets(NULL, &t, &A, &e) == PW_OK);
            pw_triplets_free(&t);
        }
        for (i = 0; i < n; i++) b[i] = rnd(&r, -1, 1); /* inconsistent in general */
        dense_lsq(&A, b, xd);
        o.tol = 1e-12;
        CHECKF(pw_lsq_solve(NULL, &A, b, x, &o, &st, &e) == PW_OK, "%dx%d: %s", n, m, e.msg);
        CHECK(st.converged && st.residual <= 1e-12);
        err = max_abs_diff(x, xd, m);
        scale = vec_norm(xd, m) / sqrt((double)m);
        CHECKF(err / scale < 1e-8, "%dx%d: error %g scale %g", n, m, err, scale);
        pwt_info("%dx%d: %d iterations", n, m, st.iterations);
        free(b);
        free(x);
        free(xd);
        pw_csr_free(NULL, &A);
    }
}

/* The least-squares form of a Laplacian solve: one row per grid edge
 * (x_i - x_j = d_ij) and one penalty row fixing vertex 0, as a
 * parametrisation would. Compared with CG on the dense normal equations,
 * and warm-started from the answer. */
static void t_lsq_penalty_graph(void)
{
    pw_triplets t;
    pw_csr A;
    int k = 10, n = 100, rows = 0, x, y, i;
    double b[400], sol[100], xd[100];
    pw_rng r = pw_rng_seed(1, 1);
    pw_cg_stats st;
    pw_err e;
    pw_err_clear(&e);
    pw_triplets_init(&t, NULL, 2 * k * (k - 1) + 1, n, &e);
    for (y = 0; y < k; y++)
        for (x = 0; x < k; x++) {
            if (x + 1 < k) {
                pw_triplets_add(&t, rows, y * k + x, 1, &e);
                pw_triplets_add(&t, rows, y * k + x + 1, -1, &e);
                b[rows++] = rnd(&r, -1, 1);
            }
            if (y + 1 < k) {
                pw_triplets_add(&t, rows, y * k + x, 1, &e);
                pw_triplets_add(&t, rows, (y + 1) * k + x, -1, &e);
                b[rows++] = rnd(&r, -1, 1);
            }
        }
    pw_triplets_add(&t, rows, 0, 3.0, &e); /* 3 (x_0 - 0.5) = 0 */
    b[rows++] = 1.5;
    REQUIRE(rows == t.n);
    REQUIRE(pw_csr_from_triplets(NULL, &t, &A, &e) == PW_OK);
    dense_lsq(&A, b, xd);
    for (i = 0; i < n; i++) sol[i] = 0;
    CHECKF(pw_lsq_solve(NULL, &A, b, sol, NULL, &st, &e) == PW_OK, "%s", e.msg);
    CHECKF(max_abs_diff(sol, xd, n) < 1e-6, "error %g", max_abs_diff(sol, xd, n));
    pwt_info("edge least squares %dx%d: %d iterations", A.n, A.m, st.iterations);
    memcpy(sol, xd, sizeof sol);
    CHECK(pw_lsq_solve(NULL, &A, b, sol, NULL, &st, &e) == PW_OK);
    CHECKF(st.iterations <= 1, "warm start took %d iterations", st.iterations);
    pw_csr_free(NULL, &A);
    pw_triplets_free(&t);
}

static void t_lsq_edge_cases(void)
{
    pw_csr A;
    double b[20], x[8];
    int i;
    pw_cg_options o = pw_cg_default_options();
    pw_cg_stats st;
    pw_err e;
    pw_err_clear(&e);
    REQUIRE(random_rect(&A, 20, 8, 3, 5) == PW_OK);
    for (i = 0; i < 20; i++) b[i] = 0;
    for (i = 0; i < 8; i++) x[i] = 5;
    CHECK(pw_lsq_solve(NULL, &A, b, x, NULL, &st, &e) == PW_OK); /* Aᵀb = 0 */
    for (i = 0; i < 8; i++) CHECK(x[i] == 0);
    for (i = 0; i < 20; i++) b[i] = sin(i + 1.0);
    o.max_iter = 2;
    CHECK(pw_lsq_solve(NULL, &A, b, x, &o, &st, &e) == PW_ERR_NOCONVERGE);
    CHECK_EQ_INT(st.iterations, 2);
    CHECKF(strstr(e.msg, "residual") != NULL, "message: %s", e.msg);
    b[4] = sqrt(-1.0);
    pw_err_clear(&e);
    CHECK(pw_lsq_solve(NULL, &A, b, x, NULL, &st, &e) == PW_ERR_INVALID);
    pw_csr_free(NULL, &A);
}

/* A consistent underdetermined system: any exact solution is fine. */
static void t_lsq_underdetermined(void)
{
    pw_csr A;
    double b[10], x[30], *r;
    int i;
    pw_cg_stats st;
    pw_err e;
    pw_rng g = pw_rng_seed(2, 2);
    pw_err_clear(&e);
    REQUIRE(random_rect(&A, 10, 30, 6, 8) == PW_OK);
    for (i = 0; i < 30; i++) x[i] = rnd(&g, -1, 1);
    pw_csr_mul(&A, x, b); /* b in the range */
    for (i = 0; i < 30; i++) x[i] = 0;
    CHECKF(pw_lsq_solve(NULL, &A, b, x, NULL, &st, &e) == PW_OK, "%s", e.msg);
    r = b;
    CHECKF(true_rel_residual(&A, r, x) < 1e-6, "residual %g", true_rel_residual(&A, r, x));
    pw_csr_free(NULL, &A);
}

/* IC(0)-preconditioned CG reaches the same solution as Jacobi CG on 2D
 * Laplacians, in several times fewer iterations, and survives a matrix
 * whose plain IC(0) breaks down (a shift is applied). */
static void t_pcg_ic0(void)
{
    int k;
    for (k = 16; k <= 64; k *= 2) {
        pw_csr A;
        pw_ic0 M;
        pw_cg_stats sj, si;
        pw_err e;
        double *b = (double *)malloc(sizeof(double) * k * k), *xj = (double *)calloc((size_t)k * k, sizeof(double));
        double *xi = (double *)calloc((size_t)k * k, sizeof(double)), diff = 0.0;
        pw_cg_options o = pw_cg_default_options();
        int i;
        pw_err_clear(&e);
        REQUIRE(laplacian(&A, b, k, 1, 0, 90 + (uint64_t)k) == PW_OK);
        REQUIRE(pw_cg_solve(NULL, &A, b, xj, &o, &sj, &e) == PW_OK);
        REQUIRE(pw_ic0_factor(NULL, &A, &M, &e) == PW_OK);
        REQUIRE(pw_pcg_solve(NULL, &A, &M, b, xi, &o, &si, &e) == PW_OK);
        for (i = 0; i < k * k; i++) diff = fabs(xi[i] - xj[i]) > diff ? fabs(xi[i] - xj[i]) : diff;
        pwt_info("%dx%d Laplacian: Jacobi %d iterations, IC(0) %d; max difference %.2e", k, k, sj.iterations,
                 si.iterations, diff);
        CHECK(si.converged && diff < 1e-5);
        CHECK(si.iterations * 2 < sj.iterations);
        pw_ic0_free(NULL, &M);
        pw_csr_free(NULL, &A);
        free(b), free(xj), free(xi);
    }
}

/* Sparse LDLT: exact to rounding against the dense solver on random SPD
 * matrices; on grid Laplacians the minimum-degree ordering keeps the fill
 * far below the natural order's band (k x k grid: k^3 for the band) and
 * the solution matches IC(0)-PCG run to a tight tolerance; several
 * right-hand sides from one factor; deterministic. */
static void t_ldlt_random(void)
{
    int n, seed;
    double worst = 0.0;
    for (n = 1; n <= 120; n += 17)
        for (seed = 0; seed < 3; seed++) {
            pw_csr A;
            pw_ldlt F;
            pw_err e;
            pw_rng r = pw_rng_seed((uint64_t)(seed + 7 * n), 5);
            double *M, *b = (double *)malloc(sizeof(double) * n), *b2 = (double *)malloc(sizeof(double) * n);
            double *x = (double *)malloc(sizeof(double) * n), *xd = (double *)malloc(sizeof(double) * n);
            int i;
            pw_err_clear(&e);
            REQUIRE(random_spd(&A, n, 6, 300 + (uint64_t)(seed + 7 * n)) == PW_OK);
            for (i = 0; i < n; i++) b[i] = b2[i] = rnd(&r, -1, 1);
            M = dense_of(&A);
            REQUIRE(dense_solve(M, b2, xd, n));
            REQUIRE(pw_ldlt_factor(NULL, &A, &F, &e) == PW_OK);
            pw_ldlt_solve(&F, b, x);
            for (i = 0; i < n; i++) worst = fabs(x[i] - xd[i]) > worst ? fabs(x[i] - xd[i]) : worst;
            pw_ldlt_free(NULL, &F);
            pw_csr_free(NULL, &A);
            free(M), free(b), free(b2), free(x), free(xd);
        }
    pwt_info("random SPD, n 1..120: largest difference to the dense solve %.2e", worst);
    CHECK(worst < 1e-10);
}

/* Nonzeros of L below the diagonal (to compare with A's). */
static long ldlt_nnz(const pw_ldlt *F) { return F->n ? (long)F->Lp[F->n] : 0; }

static void t_ldlt_laplacian(void)
{
    int k = 48, n = k * k, i;
    pw_csr A;
    pw_ldlt F, G;
    pw_ic0 M;
    pw_cg_options o = pw_cg_default_options();
    pw_err e;
    double *b = (double *)malloc(sizeof(double) * n), *x = (double *)malloc(sizeof(double) * n);
    double *xi = (double *)calloc((size_t)n, sizeof(double)), *x2 = (double *)malloc(sizeof(double) * n), diff = 0.0;
    long lower = 0;
    pw_err_clear(&e);
    REQUIRE(laplacian(&A, b, k, 0, 1.0, 77) == PW_OK);
    for (i = 0; i < n; i++) {
        int q;
        for (q = A.rowptr[i]; q < A.rowptr[i + 1]; q++) lower += A.col[q] < i;
    }
    REQUIRE(pw_ldlt_factor(NULL, &A, &F, &e) == PW_OK && pw_ldlt_factor(NULL, &A, &G, &e) == PW_OK);
    CHECK(!memcmp(F.perm, G.perm, sizeof(int) * n) && ldlt_nnz(&F) == ldlt_nnz(&G) &&
          !memcmp(F.Lx, G.Lx, sizeof(double) * (size_t)ldlt_nnz(&F)));
    pw_ldlt_solve(&F, b, x);
    o.tol = 1e-12;
    o.max_iter = 10000;
    REQUIRE(pw_ic0_factor(NULL, &A, &M, &e) == PW_OK && pw_pcg_solve(NULL, &A, &M, b, xi, &o, NULL, &e) == PW_OK);
    for (i = 0; i < n; i++) diff = fabs(x[i] - xi[i]) > diff ? fabs(x[i] - xi[i]) : diff;
    for (i = 0; i < n; i++) x2[i] = b[i];
    pw_ldlt_solve(&F, x2, x2); /* in place, the same factor again */
    pwt_info("%dx%d Laplacian (+1 on one diagonal): L has %ld nonzeros below the diagonal, %.1fx A's lower triangle "
             "(natural order: about %d); difference to IC(0)-PCG at 1e-12: %.2e",
             k, k, ldlt_nnz(&F), (double)ldlt_nnz(&F) / (double)lower, k * n, diff);
    CHECK(ldlt_nnz(&F) < (long)k * n / 3);
    /* AMD's supervariables and weighted degrees: 29,660; the quotient
     * graph without them left 31,860 */
    CHECK(ldlt_nnz(&F) < 30500);
    CHECK(diff < 1e-6 && !memcmp(x, x2, sizeof(double) * n));
    pw_ldlt_free(NULL, &F), pw_ldlt_free(NULL, &G);
    pw_ic0_free(NULL, &M);
    pw_csr_free(NULL, &A);
    free(b), free(x), free(xi), free(x2);
}

/* Two unknowns per node, coupled (the Laplacian times [[2, 1], [1, 2]]),
 * as a parameterisation's u and v are: the ordering merges each node's
 * pair (same closed neighbourhood) and keeps it together, the factor has
 * about four times the scalar factor's nonzeros (its 2x2 blocks), and
 * solves as well. */
static void t_ldlt_groups(void)
{
    static const double B[2][2] = {{2.0, 1.0}, {1.0, 2.0}};
    int k = 32, n = k * k, i, q, c, d, split = 0;
    pw_csr A, A2;
    pw_ldlt F, F2;
    pw_triplets t;
    pw_err e;
    double *b = (double *)malloc(sizeof(double) * n), *b2 = (double *)malloc(sizeof(double) * 2 * n);
    double *x2 = (double *)malloc(sizeof(double) * 2 * n), *r2 = (double *)malloc(sizeof(double) * 2 * n), res = 0;
    pw_err_clear(&e);
    REQUIRE(laplacian(&A, b, k, 0, 1.0, 78) == PW_OK);
    REQUIRE(pw_triplets_init(&t, NULL, 2 * n, 2 * n, &e) == PW_OK);
    for (i = 0; i < n; i++)
        for (q = A.rowptr[i]; q < A.rowptr[i + 1]; q++)
            for (c = 0; c < 2; c++)
                for (d = 0; d < 2; d++)
                    REQUIRE(pw_triplets_add(&t, 2 * i + c, 2 * A.col[q] + d, A.val[q] * B[c][d], &e) == PW_OK);
    REQUIRE(pw_csr_from_triplets(NULL, &t, &A2, &e) == PW_OK);
    pw_triplets_free(&t);
    REQUIRE(pw_ldlt_factor(NULL, &A, &F, &e) == PW_OK && pw_ldlt_factor(NULL, &A2, &F2, &e) == PW_OK);
    for (i = 0; i < 2 * n; i += 2) split += F2.perm[i] / 2 != F2.perm[i + 1] / 2;
    for (i = 0; i < 2 * n; i++) b2[i] = b[i / 2] + (i & 1) * 0.5 * b[i / 2];
    pw_ldlt_solve(&F2, b2, x2);
    pw_csr_mul(&A2, x2, r2);
    for (i = 0; i < 2 * n; i++) res = fmax(res, fabs(r2[i] - b2[i]));
    pwt_info("%dx%d Laplacian, two unknowns per node: L has %ld nonzeros below the diagonal, %.2fx the scalar "
             "factor's %ld; %d pairs split; largest residual %.2e",
             k, k, ldlt_nnz(&F2), (double)ldlt_nnz(&F2) / (double)ldlt_nnz(&F), ldlt_nnz(&F), split, res);
    CHECK(split == 0);
    CHECK(ldlt_nnz(&F2) <= 4 * ldlt_nnz(&F) + n + n / 10);
    CHECK(ldlt_nnz(&F) < 11100); /* 10,849 with supervariables, 11,338 without */
    CHECK(res < 1e-10);
    pw_ldlt_free(NULL, &F), pw_ldlt_free(NULL, &F2);
    pw_csr_free(NULL, &A), pw_csr_free(NULL, &A2);
    free(b), free(b2), free(x2), free(r2);
}

/* Not positive definite (a singular Neumann Laplacian; an indefinite
 * matrix): an error naming the pivot, nothing left allocated. */
static void t_ldlt_not_spd(void)
{
    pw_csr A;
    pw_ldlt F;
    pw_err e;
    double b[64];
    pw_err_clear(&e);
    REQUIRE(laplacian(&A, b, 8, 0, 0.0, 3) == PW_OK);
    CHECK(pw_ldlt_factor(NULL, &A, &F, &e) == PW_ERR_DEGENERATE && strstr(e.msg, "not positive definite") && !F.Lx && !F.perm);
    pw_csr_free(NULL, &A);
    pw_err_clear(&e);
    REQUIRE(random_spd(&A, 30, 6, 9) == PW_OK);
    {
        int q; /* a negative diagonal entry: indefinite */
        for (q = A.rowptr[5]; q < A.rowptr[6]; q++)
            if (A.col[q] == 5) A.val[q] = -1.0;
    }
    CHECK(pw_ldlt_factor(NULL, &A, &F, &e) == PW_ERR_DEGENERATE);
    pw_csr_free(NULL, &A);
}

/* pw_spd's rule: a 32x32 Laplacian (1,024 unknowns) is factored directly
 * and solved exactly; a 16x16 one (256, under the threshold) and a random
 * pattern (whose factor would fill in far beyond 4x A) go to IC(0)-PCG;
 * a singular one falls back to IC(0) too. All solve to their tolerance. */
static void t_spd_rule(void)
{
    static const int sizes[2] = {32, 16};
    pw_cg_options o = pw_cg_default_options();
    pw_err e;
    pw_csr A;
    pw_spd S;
    int c, i, n;
    double b[1024], x[1024], r[1024], nr, nb;
    o.tol = 1e-10;
    for (c = 0; c < 3; c++) {
        pw_err_clear(&e);
        if (c < 2) REQUIRE(laplacian(&A, b, sizes[c], 0, 1.0, 5) == PW_OK);
        else {
            REQUIRE(random_spd(&A, 1000, 8, 4) == PW_OK);
            for (i = 0; i < A.n; i++) b[i] = sin(0.1 * i);
        }
        n = A.n;
        memset(x, 0, sizeof(double) * n);
        REQUIRE(pw_spd_factor(NULL, &A, &S, &e) == PW_OK);
        CHECKF(S.direct == (c == 0), "case %d: direct %d", c, S.direct);
        CHECK(pw_spd_solve(NULL, &S, b, x, &o, &e) == PW_OK);
        pw_csr_mul(&A, x, r);
        for (i = 0, nr = nb = 0.0; i < n; i++) nr += (r[i] - b[i]) * (r[i] - b[i]), nb += b[i] * b[i];
        pwt_info("case %d: %d unknowns, %s, relative residual %.2e", c, n, S.direct ? "LDLT" : "IC(0)-PCG",
                 sqrt(nr / nb));
        CHECK(sqrt(nr / nb) < (S.direct ? 1e-13 : 1e-9));
        pw_spd_free(NULL, &S);
        pw_csr_free(NULL, &A);
    }
    REQUIRE(laplacian(&A, b, 30, 0, 0.0, 6) == PW_OK); /* singular: LDLT refuses, IC(0) takes it */
    REQUIRE(pw_spd_factor(NULL, &A, &S, &e) == PW_OK);
    CHECK(!S.direct && S.M.val && !S.F.Lx);
    pw_spd_free(NULL, &S);
    pw_csr_free(NULL, &A);
}

/* The rows of a k x k grid's gradient (x_i - x_j per edge) and a weak
 * tie of every unknown to a value: a well-posed least-squares problem with
 * a sparse factor, as the atlas charts are. */
static int grid_lsq(pw_csr *A, double *b, int k)
{
    pw_triplets t;
    pw_err e;
    int x, y, row = 0, rc;
    pw_err_clear(&e);
    rc = pw_triplets_init(&t, NULL, 3 * k * k, k * k, &e);
    for (y = 0; y < k && !rc; y++)
        for (x = 0; x < k && !rc; x++) {
            int i = y * k + x;
            if (x + 1 < k) {
                rc |= pw_triplets_add(&t, row, i, 1.0, &e) | pw_triplets_add(&t, row, i + 1, -1.0, &e);
                b[row++] = 0.01 * y;
            }
            if (y + 1 < k) {
                rc |= pw_triplets_add(&t, row, i, 1.0, &e) | pw_triplets_add(&t, row, i + k, -1.0, &e);
                b[row++] = -0.02 * x;
            }
            rc |= pw_triplets_add(&t, row, i, 0.1, &e);
            b[row++] = sin(0.3 * i);
        }
    t.n = row;
    if (!rc) rc = pw_csr_from_triplets(NULL, &t, A, &e);
    pw_triplets_free(&t);
    return rc;
}

/* pw_lsq_solve_small: the direct solve of the normal equations agrees with
 * CGLS run to 1e-12 (a 24x24 grid: 576 unknowns, direct; 16x16: 256,
 * CGLS); an unknown no row touches makes the normal equations singular,
 * and CGLS takes over, keeping its guess. */
static void t_lsq_small(void)
{
    pw_cg_options o = pw_cg_default_options(), tight = pw_cg_default_options();
    pw_err e;
    pw_csr A;
    static double b[3 * 576], x[577], xi[577];
    int c, i;
    o.tol = 1e-5;
    tight.tol = 1e-12;
    tight.max_iter = 20000;
    for (c = 0; c < 2; c++) {
        int k = c == 0 ? 24 : 16;
        double diff = 0.0;
        pw_err_clear(&e);
        REQUIRE(grid_lsq(&A, b, k) == PW_OK);
        memset(x, 0, sizeof x);
        memset(xi, 0, sizeof xi);
        CHECK(pw_lsq_solve_small(NULL, &A, b, x, &o, &e) == PW_OK);
        REQUIRE(pw_lsq_solve(NULL, &A, b, xi, &tight, NULL, &e) == PW_OK);
        for (i = 0; i < A.m; i++) diff = fabs(x[i] - xi[i]) > diff ? fabs(x[i] - xi[i]) : diff;
        pwt_info("%d unknowns: largest difference to CGLS at 1e-12: %.2e", A.m, diff);
        CHECK(diff < (c == 0 ? 1e-9 : 1e-3));
        pw_csr_free(NULL, &A);
    }
    REQUIRE(grid_lsq(&A, b, 24) == PW_OK);
    A.m = 577; /* one more unknown, in no row */
    for (i = 0; i < 577; i++) x[i] = 7.0;
    CHECK(pw_lsq_solve_small(NULL, &A, b, x, &o, &e) == PW_OK && x[576] == 7.0);
    pw_csr_free(NULL, &A);
}

/* The direct paths of pw_spd and pw_lsq_solve_small with every allocation
 * failing in turn (a 29x29 Laplacian, 841 unknowns, and a 20x20 grid's
 * least squares, 400: both over the thresholds): PW_ERR_NOMEM with a
 * message, never a silent fallback to the iterative solver, nothing
 * leaked; the last run takes the direct path. */
static void t_alloc_direct(void)
{
    static double b[1200], x[841];
    pw_csr A, G;
    pw_err e;
    int budget, c;
    pw_err_clear(&e);
    REQUIRE(laplacian(&A, b, 29, 0, 1.0, 8) == PW_OK && grid_lsq(&G, b, 20) == PW_OK);
    for (c = 0; c < 2; c++) {
        int finished = 0, direct = 0;
        for (budget = 0; budget < 20000 && !finished; budget++) {
            pwt_alloc_state f = {0, 0, budget};
            pw_alloc al = {pwt_malloc, pwt_realloc, pwt_free, &f};
            int rc;
            pw_err_clear(&e);
            memset(x, 0, sizeof x);
            if (c == 0) {
                pw_spd S;
                rc = pw_spd_factor(&al, &A, &S, &e);
                if (!rc) rc = pw_spd_solve(&al, &S, b, x, NULL, &e);
                direct = S.direct;
                pw_spd_free(&al, &S);
            } else
                rc = pw_lsq_solve_small(&al, &G, b, x, NULL, &e);
            CHECKF(rc == PW_OK || (rc == PW_ERR_NOMEM && e.code == PW_ERR_NOMEM && e.msg[0]), "%d, budget %d: %d %s",
                   c, budget, rc, e.msg);
            CHECKF(f.live == 0, "%d, budget %d: %ld blocks leaked", c, budget, f.live);
            finished = rc == PW_OK;
        }
        pwt_info("%s: %d allocation failure points", c ? "pw_lsq_solve_small" : "pw_spd", budget - 1);
        CHECK(finished && (c == 1 || direct));
    }
    pw_csr_free(NULL, &A);
    pw_csr_free(NULL, &G);
}

static const pwt_case cases[] = {
    {"triplets_duplicates", t_triplets_duplicates},
    {"triplets_invalid", t_triplets_invalid},
    {"triplets_random", t_triplets_random},
    {"csr_products", t_csr_products},
    {"csr_ata", t_csr_ata},
    {"csr_check_malformed", t_csr_check_malformed},
    {"cg_random_spd", t_cg_random_spd},
    {"cg_normal_matrix", t_cg_normal_matrix},
    {"cg_laplacian_dirichlet", t_cg_laplacian_dirichlet},
    {"pcg_ic0", t_pcg_ic0},
    {"ldlt_random", t_ldlt_random},
    {"ldlt_laplacian", t_ldlt_laplacian},
    {"ldlt_groups", t_ldlt_groups},
    {"ldlt_not_spd", t_ldlt_not_spd},
    {"spd_rule", t_spd_rule},
    {"lsq_small", t_lsq_small},
    {"alloc_direct", t_alloc_direct},
    {"cg_warm_start", t_cg_warm_start},
    {"cg_iteration_cap", t_cg_iteration_cap},
    {"cg_tolerance", t_cg_tolerance},
    {"cg_zero_rhs", t_cg_zero_rhs},
    {"cg_invalid", t_cg_invalid},
    {"cg_bad_diagonal", t_cg_bad_diagonal},
    {"cg_semidefinite", t_cg_semidefinite},
    {"cg_determinism", t_cg_determinism},
    {"cg_progress_cancel", t_cg_progress_cancel},
    {"alloc_failures", t_alloc_failures},
    {"lsq_overdetermined", t_lsq_overdetermined},
    {"lsq_penalty_graph", t_lsq_penalty_graph},
    {"lsq_edge_cases", t_lsq_edge_cases},
    {"lsq_underdetermined", t_lsq_underdetermined},
};
PWT_MAIN(cases)
