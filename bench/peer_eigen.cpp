// peer_eigen.cpp: Eigen (libeigen3-dev) solving the systems bench_sparse
// reads, for the comparison with patchwork's own solvers. Compiled only in
// bench/, only when bench/probe.sh finds Eigen; bench_sparse.c (C) calls
// it through the C functions declared in peer_eigen.h.
//
// Complex Hermitian systems are solved as std::complex<double> matrices
// (Eigen's CG and LDLT take the adjoint where a real solver takes the
// transpose), not as the equivalent real 2n x 2n system.
#include <Eigen/Sparse>
#include <Eigen/IterativeLinearSolvers>
#include <complex>
#include <cstdio>
#include <new>
#include "peer_eigen.h"

namespace {

typedef std::complex<double> cplx;

template <class S> struct system {
    typedef Eigen::SparseMatrix<S> mat;
    typedef Eigen::Matrix<S, Eigen::Dynamic, 1> vec;
    mat A;  // n x m, column-major (what Eigen's solvers work on)
    vec b, x;
};

// The CSR arrays as an Eigen matrix (copied: the timing starts after).
template <class S> system<S> *make(int n, int m, const int *rowptr, const int *col, const double *val)
{
    typedef Eigen::SparseMatrix<S, Eigen::RowMajor> rowmat;
    system<S> *s = new system<S>;
    Eigen::Map<const rowmat> R(n, m, rowptr[n], rowptr, col, reinterpret_cast<const S *>(val));
    s->A = R;
    s->A.makeCompressed();
    return s;
}

template <class S, class Solver> int iterate(system<S> *s, Solver &solver, const double *b, const double *x0,
                                             double tol, int max_iter, double *x)
{
    typedef typename system<S>::vec vec;
    Eigen::Map<const vec> B(reinterpret_cast<const S *>(b), s->A.rows());
    Eigen::Map<const vec> X0(reinterpret_cast<const S *>(x0), s->A.cols());
    Eigen::Map<vec> X(reinterpret_cast<S *>(x), s->A.cols());
    solver.setTolerance(tol);
    if (max_iter > 0) solver.setMaxIterations(max_iter);
    solver.compute(s->A);
    X = solver.solveWithGuess(B, X0);
    return (int)solver.iterations();
}

template <class S> int solve(system<S> *s, int method, int lsq, const double *b, const double *x0, double tol,
                             int max_iter, double *x)
{
    typedef typename system<S>::mat mat;
    typedef typename system<S>::vec vec;
    if (lsq && method == PEER_EIGEN_CG) {
        Eigen::LeastSquaresConjugateGradient<mat> solver; // column-norm (Jacobi) preconditioner
        return iterate(s, solver, b, x0, tol, max_iter, x);
    }
    if (lsq && method == PEER_EIGEN_LDLT) { // normal equations, formed inside the timing
        Eigen::Map<const vec> B(reinterpret_cast<const S *>(b), s->A.rows());
        Eigen::Map<vec> X(reinterpret_cast<S *>(x), s->A.cols());
        mat N = s->A.adjoint() * s->A;
        Eigen::SimplicialLDLT<mat> solver(N);
        X = solver.solve(s->A.adjoint() * B);
        return 0;
    }
    if (lsq) return -1;
    if (method == PEER_EIGEN_CG) {
        Eigen::ConjugateGradient<mat, Eigen::Lower | Eigen::Upper> solver; // diagonal preconditioner
        return iterate(s, solver, b, x0, tol, max_iter, x);
    }
    if (method == PEER_EIGEN_ICCG) {
        Eigen::ConjugateGradient<mat, Eigen::Lower | Eigen::Upper, Eigen::IncompleteCholesky<S> > solver;
        return iterate(s, solver, b, x0, tol, max_iter, x);
    }
    Eigen::Map<const vec> B(reinterpret_cast<const S *>(b), s->A.rows());
    Eigen::Map<vec> X(reinterpret_cast<S *>(x), s->A.cols());
    Eigen::SimplicialLDLT<mat> solver(s->A); // AMD ordering, lower triangle
    X = solver.solve(B);
    return solver.info() == Eigen::Success ? 0 : -1;
}

template <class S> long ldlt_fill(system<S> *s)
{
    Eigen::SimplicialLDLT<typename system<S>::mat> solver(s->A);
    return solver.info() == Eigen::Success ? (long)solver.matrixL().nestedExpression().nonZeros() : -1;
}

struct peer {
    int cplx_, lsq;
    system<double> *r;
    system<cplx> *c;
};

} // namespace

extern "C" {

const char *peer_eigen_version(void)
{
    static char v[32];
    std::snprintf(v, sizeof v, "%d.%d.%d", EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION);
    return v;
}

void *peer_eigen_prepare(int n, int m, int is_complex, int lsq, const int *rowptr, const int *col,
                         const double *val)
{
    peer *p = new (std::nothrow) peer();
    if (!p) return 0;
    p->cplx_ = is_complex;
    p->lsq = lsq;
    try {
        if (is_complex) p->c = make<cplx>(n, m, rowptr, col, val);
        else p->r = make<double>(n, m, rowptr, col, val);
    } catch (...) {
        delete p;
        return 0;
    }
    return p;
}

int peer_eigen_solve(void *handle, int method, const double *b, const double *x0, double tol, int max_iter,
                     double *x)
{
    peer *p = static_cast<peer *>(handle);
    try {
        return p->cplx_ ? solve(p->c, method, p->lsq, b, x0, tol, max_iter, x)
                        : solve(p->r, method, p->lsq, b, x0, tol, max_iter, x);
    } catch (...) {
        return -1;
    }
}

long peer_eigen_ldlt_fill(void *handle)
{
    peer *p = static_cast<peer *>(handle);
    if (p->lsq) return -1;
    try {
        return p->cplx_ ? ldlt_fill(p->c) : ldlt_fill(p->r);
    } catch (...) {
        return -1;
    }
}

void peer_eigen_free(void *handle)
{
    peer *p = static_cast<peer *>(handle);
    if (!p) return;
    delete p->r;
    delete p->c;
    delete p;
}

} // extern "C"
