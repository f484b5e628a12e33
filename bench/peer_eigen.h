/* peer_eigen.h: the C interface of bench/peer_eigen.cpp (Eigen's sparse
 * solvers), linked into bench_sparse when bench/probe.sh finds Eigen. */
#ifndef PW_BENCH_PEER_EIGEN_H
#define PW_BENCH_PEER_EIGEN_H

#ifdef __cplusplus
extern "C" {
#endif

enum {
    PEER_EIGEN_CG = 0,   /* ConjugateGradient, diagonal preconditioner (Eigen's default);
                            least squares: LeastSquaresConjugateGradient */
    PEER_EIGEN_ICCG = 1, /* ConjugateGradient with IncompleteCholesky (not for least squares) */
    PEER_EIGEN_LDLT = 2  /* SimplicialLDLT (least squares: of the normal equations) */
};

const char *peer_eigen_version(void);

/* The n x m CSR matrix (values: 1 double per entry, or (re, im) pairs when
 * is_complex) copied into Eigen's own format; lsq: solve it in the
 * least-squares sense. NULL when out of memory. */
void *peer_eigen_prepare(int n, int m, int is_complex, int lsq, const int *rowptr, const int *col,
                         const double *val);

/* x = the solution by `method` (b, x0, x as for patchwork: complex entries
 * are (re, im) pairs); iterative methods start from x0 and stop at relative
 * residual tol or max_iter iterations. Returns the iterations (0 for LDLT),
 * or -1 on failure. */
int peer_eigen_solve(void *p, int method, const double *b, const double *x0, double tol, int max_iter,
                     double *x);

/* Nonzeros of SimplicialLDLT's factor L (strictly lower part), for the
 * notes; -1 for least squares or on failure. */
long peer_eigen_ldlt_fill(void *p);

void peer_eigen_free(void *p);

#ifdef __cplusplus
}
#endif

#endif
