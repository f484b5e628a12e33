#!/bin/sh
# probe.sh PEER COMPILER: exit status 0 when the peer library PEER can be
# built against with COMPILER (the Makefile asks at build time, so that the
# benchmarks build without the peers and say so when run). With PEER
# "eigen-flags" it prints the compiler flags Eigen needs.
#   eigen   Eigen's sparse solvers (Debian: libeigen3-dev), with a C++ compiler
#   osmesa  Mesa's off-screen renderer (Debian: libosmesa6-dev), with a C compiler
# BENCH_NO_PEERS="eigen osmesa" (or "all") reports them absent, to try the
# skip paths on a machine that has them.
peer=$1
cc=${2:-cc}
case " $BENCH_NO_PEERS " in *" all "*|*" ${peer%-flags} "*) exit 1 ;; esac
tmp=${TMPDIR:-/tmp}/pw-probe-$$
trap 'rm -f "$tmp" "$tmp".c "$tmp".cpp' EXIT
eigen_flags() {
    pkg-config --cflags eigen3 2>/dev/null || echo "-I/usr/include/eigen3"
}
case $peer in
eigen-flags)
    eigen_flags ;;
eigen)
    printf '#include <Eigen/Sparse>\n#include <Eigen/IterativeLinearSolvers>\nint main() { Eigen::SparseMatrix<double> A(2, 2); return (int)A.nonZeros(); }\n' > "$tmp".cpp
    $cc $(eigen_flags) -o "$tmp" "$tmp".cpp >/dev/null 2>&1 ;;
osmesa)
    printf '#include <GL/osmesa.h>\nint main(void) { return OSMesaGetCurrentContext() != 0; }\n' > "$tmp".c
    $cc -o "$tmp" "$tmp".c -lOSMesa >/dev/null 2>&1 ;;
*)
    echo "probe.sh: unknown peer $peer" >&2; exit 2 ;;
esac
