/* Tests of src/common/zsparse.h: complex Hermitian CSR, complex IC(0) and
 * PCG, checked against the same systems written as real 2n x 2n matrices
 * (2x2 blocks [re -im; im re]) and solved by sparse.h's real PCG; and of
 * src/common/zamg.h, the multigrid preconditioner, against IC(0). */
#include "../src/common/zamg.h"
#include "../src/common/rng.h"
#include "pwtest.h"

/* The transports' angles: uniform in [0, 2 pi) times this (1: a random,
 * strongly curved connection; small: a smooth one, as on a mesh). */
static double spread = 1.0;

/* A connection Laplacian on a w x h grid with random unit transports plus
 * a diagonal shift: sum over edges of |z_i - c z_j|^2 + shift |z|^2, the
 * shape of pgp.h's systems. Written both ways. */
static int build(int w, int h, double shift, unsigned seed, pw_triplets *zt, pw_triplets *rt)
{
    int n = w * h, x, y, i, d;
    pw_rng rng = pw_rng_seed(seed, 7);
    pw_err e;
    if (pw_triplets_init(zt, NULL, n, 2 * n, &e) || pw_triplets_init(rt, NULL, 2 * n, 2 * n, &e)) return 1;
    for (i = 0; i < n; i++) {
        pw_ztriplets_add(zt, i, i, shift, 0.0, &e);
        pw_triplets_add(rt, 2 * i, 2 * i, shift, &e);
        pw_triplets_add(rt, 2 * i + 1, 2 * i + 1, shift, &e);
    }
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++)
            for (d = 0; d < 2; d++) {
                int j = d ? (y + 1 < h ? (y + 1) * w + x : -1) : (x + 1 < w ? y * w + x + 1 : -1);
                double a = 6.283185307179586 * spread * pw_rng_float(&rng), c = cos(a), s = sin(a), wt = 0.5 + pw_rng_float(&rng);
                if (j < 0) continue;
                i = y * w + x;
                /* w |z_i - c z_j|^2: diag w at i and j, -w c at (i, j), -w conj(c) at (j, i) */
                pw_ztriplets_add(zt, i, i, wt, 0.0, &e);
                pw_ztriplets_add(zt, j, j, wt, 0.0, &e);
                pw_ztriplets_add(zt, i, j, -wt * c, -wt * s, &e);
                pw_ztriplets_add(zt, j, i, -wt * c, wt * s, &e);
                pw_triplets_add(rt, 2 * i, 2 * i, wt, &e);
                pw_triplets_add(rt, 2 * i + 1, 2 * i + 1, wt, &e);
                pw_triplets_add(rt, 2 * j, 2 * j, wt, &e);
                pw_triplets_add(rt, 2 * j + 1, 2 * j + 1, wt, &e);
                /* block of -w c at (i, j): [[-wc_r, wc_i], [-wc_i, -wc_r]]; its transpose at (j, i) */
                pw_triplets_add(rt, 2 * i, 2 * j, -wt * c, &e);
                pw_triplets_add(rt, 2 * i, 2 * j + 1, wt * s, &e);
                pw_triplets_add(rt, 2 * i + 1, 2 * j, -wt * s, &e);
                pw_triplets_add(rt, 2 * i + 1, 2 * j + 1, -wt * c, &e);
                pw_triplets_add(rt, 2 * j, 2 * i, -wt * c, &e);
                pw_triplets_add(rt, 2 * j + 1, 2 * i, wt * s, &e);
                pw_triplets_add(rt, 2 * j, 2 * i + 1, -wt * s, &e);
                pw_triplets_add(rt, 2 * j + 1, 2 * i + 1, -wt * c, &e);
            }
    return 0;
}

static void t_mul_matches_real(void)
{
    pw_triplets zt, rt;
    pw_zcsr Z;
    pw_csr R;
    pw_err e;
    double x[2 * 48], y1[2 * 48], y2[2 * 48], d1, d2 = 0.0;
    int i;
    REQUIRE(!build(8, 6, 0.1, 3, &zt, &rt));
    REQUIRE(pw_zcsr_from_triplets(NULL, &zt, &Z, &e) == PW_OK);
    REQUIRE(pw_csr_from_triplets(NULL, &rt, &R, &e) == PW_OK);
    for (i = 0; i < 96; i++) x[i] = sin(0.37 * i + 1.0);
    d1 = pw_zcsr_mul(&Z, x, y1);
    pw_csr_mul(&R, x, y2);
    for (i = 0; i < 96; i++) {
        CHECKF(fabs(y1[i] - y2[i]) < 1e-12, "entry %d: %g vs %g", i, y1[i], y2[i]);
        d2 += x[i] * y2[i];
    }
    CHECK_NEAR(d1, d2, 1e-10);
    CHECK(d1 > 0.0); /* positive definite */
    pw_zcsr_free(NULL, &Z);
    pw_csr_free(NULL, &R);
    pw_triplets_free(&zt);
    pw_triplets_free(&rt);
}

/* pw_zcsr_pattern: the structure of diagonal + pairs, repeated pairs
 * merged; terms added at the positions it gives make the same matrix, bit
 * for bit, as the triplets added in the same order. */
static void t_pattern_matches_triplets(void)
{
    static const int ij[] = {0, 3, 2, 1, 4, 0, 3, 0, 1, 4, 2, 3, 1, 2};
    const int n = 5, np = 7;
    pw_triplets t;
    pw_zcsr Z, A;
    pw_err e;
    int dpos[5], pos[14], i, p, k;
    REQUIRE(pw_triplets_init(&t, NULL, n, 2 * n, &e) == PW_OK);
    REQUIRE(pw_zcsr_pattern(NULL, n, np, ij, &A, dpos, pos, &e) == PW_OK);
    CHECK_EQ_INT(A.rowptr[n], n + 2 * 5); /* (0, 3) and (2, 1) twice */
    CHECK_EQ_INT(pos[0], pos[7]); /* (0, 3) and its repeat (3, 0) share */
    CHECK_EQ_INT(pos[1], pos[6]);
    for (i = 0; i < n; i++) {
        double d = 0.1 * (i + 1);
        pw_ztriplets_add(&t, i, i, d, 0.0, &e);
        A.val[2 * dpos[i]] += d;
    }
    for (p = 0; p < np; p++) {
        double w = 1.0 + 0.3 * p, c = cos(0.7 * p), s = sin(0.7 * p);
        int a = ij[2 * p], b = ij[2 * p + 1];
        pw_ztriplets_add(&t, a, a, w, 0.0, &e);
        pw_ztriplets_add(&t, b, b, w, 0.0, &e);
        pw_ztriplets_add(&t, a, b, -w * c, -w * s, &e);
        pw_ztriplets_add(&t, b, a, -w * c, w * s, &e);
        A.val[2 * dpos[a]] += w;
        A.val[2 * dpos[b]] += w;
        A.val[2 * pos[2 * p]] += -w * c;
        A.val[2 * pos[2 * p] + 1] += -w * s;
        A.val[2 * pos[2 * p + 1]] += -w * c;
        A.val[2 * pos[2 * p + 1] + 1] += w * s;
    }
    REQUIRE(pw_zcsr_from_triplets(NULL, &t, &Z, &e) == PW_OK);
    for (i = 0; i <= n; i++) CHECK_EQ_INT(A.rowptr[i], Z.rowptr[i]);
    for (k = 0; k < Z.rowptr[n]; k++) {
        CHECK_EQ_INT(A.col[k], Z.col[k]);
        CHECKF(A.val[2 * k] == Z.val[2 * k] && A.val[2 * k + 1] == Z.val[2 * k + 1], "entry %d: (%g, %g) vs (%g, %g)",
               k, A.val[2 * k], A.val[2 * k + 1], Z.val[2 * k], Z.val[2 * k + 1]);
    }
    pw_zcsr_free(NULL, &A);
    pw_zcsr_free(NULL, &Z);
    pw_triplets_free(&t);
}

/* The complex solve reaches the tolerance and agrees with the real one. */
static void t_solve_matches_real(void)
{
    pw_triplets zt, rt;
    pw_zcsr Z;
    pw_zic0 ZL;
    pw_csr R;
    pw_ic0 RL;
    pw_err e;
    pw_cg_options o = pw_cg_default_options();
    pw_cg_stats zs, rs;
    enum { W = 40, H = 30, N = 2 * W * H };
    static double b[N], xz[N], xr[N], chk[N];
    double worst = 0.0, rn = 0.0, bn = 0.0;
    int i;
    REQUIRE(!build(W, H, 1e-3, 11, &zt, &rt));
    REQUIRE(pw_zcsr_from_triplets(NULL, &zt, &Z, &e) == PW_OK);
    REQUIRE(pw_csr_from_triplets(NULL, &rt, &R, &e) == PW_OK);
    REQUIRE(pw_zic0_factor(NULL, &Z, &ZL, &e) == PW_OK);
    REQUIRE(pw_ic0_factor(NULL, &R, &RL, &e) == PW_OK);
    for (i = 0; i < N; i++) b[i] = cos(0.11 * i) + 0.3 * sin(1.7 * i), xz[i] = xr[i] = 0.0;
    o.tol = 1e-10;
    CHECK(pw_zpcg_solve(NULL, &Z, &ZL, b, xz, &o, &zs, &e) == PW_OK);
    CHECK(pw_pcg_solve(NULL, &R, &RL, b, xr, &o, &rs, &e) == PW_OK);
    pw_zcsr_mul(&Z, xz, chk);
    for (i = 0; i < N; i++) {
        worst = fabs(xz[i] - xr[i]) > worst ? fabs(xz[i] - xr[i]) : worst;
        rn += (chk[i] - b[i]) * (chk[i] - b[i]);
        bn += b[i] * b[i];
    }
    CHECKF(sqrt(rn / bn) <= 1e-10, "residual %g", sqrt(rn / bn));
    CHECKF(worst < 1e-6, "complex and real solutions differ by %g", worst);
    /* the same preconditioner, up to pivoting order: similar iteration counts */
    CHECKF(zs.iterations <= rs.iterations + 5, "complex %d vs real %d iterations", zs.iterations, rs.iterations);
    pwt_info("%d complex unknowns: %d iterations (real form: %d)", N / 2, zs.iterations, rs.iterations);
    pw_zic0_free(NULL, &ZL);
    pw_ic0_free(NULL, &RL);
    pw_zcsr_free(NULL, &Z);
    pw_csr_free(NULL, &R);
    pw_triplets_free(&zt);
    pw_triplets_free(&rt);
}

static void t_errors(void)
{
    pw_triplets t;
    pw_zcsr Z;
    pw_err e;
    pw_err_clear(&e); /* pw_fail keeps the first error: an uncleared one could be stack garbage */
    REQUIRE(pw_triplets_init(&t, NULL, 3, 5, &e) == PW_OK);
    CHECK(pw_zcsr_from_triplets(NULL, &t, &Z, &e) == PW_ERR_INVALID);
    pw_triplets_free(&t);
    pw_err_clear(&e);
    REQUIRE(pw_triplets_init(&t, NULL, 2, 4, &e) == PW_OK);
    pw_triplets_add(&t, 0, 1, 1.0, &e); /* an imaginary part without its real part */
    CHECK(pw_zcsr_from_triplets(NULL, &t, &Z, &e) == PW_ERR_INVALID);
    CHECK(strstr(e.msg, "real or imaginary") != NULL);
    pw_triplets_free(&t);
    pw_err_clear(&e);
    /* not positive definite: IC(0) gives up with a clear message */
    REQUIRE(pw_triplets_init(&t, NULL, 1, 2, &e) == PW_OK);
    pw_ztriplets_add(&t, 0, 0, -1.0, 0.0, &e);
    REQUIRE(pw_zcsr_from_triplets(NULL, &t, &Z, &e) == PW_OK);
    {
        pw_zic0 L;
        CHECK(pw_zic0_factor(NULL, &Z, &L, &e) == PW_ERR_INVALID);
    }
    pw_zcsr_free(NULL, &Z);
    pw_triplets_free(&t);
}

static void t_alloc_failures(void)
{
    pw_triplets zt, rt;
    pw_zcsr Z;
    pw_err e;
    int k, fails = 0;
    REQUIRE(!build(5, 4, 0.1, 5, &zt, &rt));
    for (k = 0; k < 64; k++) {
        pwt_alloc_state st = {0, 0, -1};
        pw_alloc al = {pwt_malloc, pwt_realloc, pwt_free, &st};
        pw_zic0 L;
        double b[40], x[40];
        int r, i;
        st.fail_after = k;
        for (i = 0; i < 40; i++) b[i] = 1.0, x[i] = 0.0;
        r = pw_zcsr_from_triplets(&al, &zt, &Z, &e);
        if (r == PW_OK) {
            r = pw_zic0_factor(&al, &Z, &L, &e);
            if (r == PW_OK) r = pw_zpcg_solve(&al, &Z, &L, b, x, NULL, NULL, &e), pw_zic0_free(&al, &L);
            pw_zcsr_free(&al, &Z);
        }
        CHECKF(r == PW_OK || r == PW_ERR_NOMEM, "failure point %d: %d", k, r);
        CHECKF(st.live == 0, "failure point %d leaks %d blocks", k, st.live);
        if (r == PW_OK) break;
        fails++;
    }
    CHECK(fails > 3);
    pw_triplets_free(&zt);
    pw_triplets_free(&rt);
}

/* A smooth connection Laplacian on a w x h grid (transports within 0.02
 * turns of 1, a shift of 1e-5 of the edge weights: the low end of pgp's
 * spectrum, where IC(0) needs ever more iterations), packed; b a fixed
 * right-hand side. */
static int grid_system(int w, int h, pw_zcsr *Z, double **b)
{
    pw_triplets zt, rt;
    pw_err e;
    int i, n = w * h;
    pw_rng rng = pw_rng_seed(11, 3);
    spread = 0.02;
    i = build(w, h, 1e-5, 9, &zt, &rt);
    spread = 1.0;
    if (i) return 1;
    i = pw_zcsr_from_triplets(NULL, &zt, Z, &e);
    pw_triplets_free(&zt);
    pw_triplets_free(&rt);
    if (i || !(*b = (double *)malloc(sizeof(double) * 2 * n))) return 1;
    for (i = 0; i < 2 * n; i++) (*b)[i] = pw_rng_float(&rng) - 0.5;
    return 0;
}

/* Iterations of IC(0)-PCG and of multigrid PCG to 1e-8 on a w x h grid;
 * both must converge, and the multigrid answer must solve the system. */
static void amg_vs_ic0(int w, int h, int *it_ic0, int *it_amg, int *levels)
{
    pw_zcsr Z;
    pw_zic0 L;
    pw_zamg M;
    pw_cg_options o;
    pw_cg_stats s1, s2;
    pw_err e;
    double *b, *x;
    int n = w * h;
    REQUIRE(!grid_system(w, h, &Z, &b));
    x = (double *)calloc(2 * (size_t)n, sizeof(double));
    memset(&o, 0, sizeof o);
    o.tol = 1e-8;
    REQUIRE(pw_zic0_factor(NULL, &Z, &L, &e) == PW_OK);
    REQUIRE(pw_zpcg_solve(NULL, &Z, &L, b, x, &o, &s1, &e) == PW_OK);
    memset(x, 0, sizeof(double) * 2 * n);
    REQUIRE(pw_zamg_setup(NULL, &Z, &M, &e) == PW_OK);
    REQUIRE(pw_zamg_solve(NULL, &Z, &M, b, x, &o, &s2, &e) == PW_OK);
    CHECKF(s1.converged && s2.converged && s2.residual <= 1e-8, "%dx%d: IC(0) %d, multigrid %d (residual %.2g)", w, h,
           s1.converged, s2.converged, s2.residual);
    *it_ic0 = s1.iterations;
    *it_amg = s2.iterations;
    *levels = M.levels;
    pw_zamg_free(NULL, &M);
    pw_zic0_free(NULL, &L);
    pw_zcsr_free(NULL, &Z);
    free(b);
    free(x);
}

/* The multigrid iteration count stays about the same from 64x64 to 256x256
 * unknowns (16x more) while IC(0)'s grows with the side, and is below it. */
static void t_amg_scaling(void)
{
    int ic[2], mg[2], lv[2], k, side[2] = {64, 256};
    for (k = 0; k < 2; k++) {
        amg_vs_ic0(side[k], side[k], &ic[k], &mg[k], &lv[k]);
        pwt_info("%dx%d grid: IC(0)-PCG %d iterations, multigrid PCG %d (%d coarser levels)", side[k], side[k], ic[k],
                 mg[k], lv[k]);
    }
    CHECKF(lv[0] >= 1 && lv[1] > lv[0], "levels %d, %d", lv[0], lv[1]);
    CHECKF(mg[1] <= mg[0] + 6, "multigrid iterations grow from %d to %d", mg[0], mg[1]);
    CHECKF(2 * ic[1] >= 3 * ic[0], "IC(0) iterations %d -> %d: the grid is too easy to tell", ic[0], ic[1]);
    CHECKF(2 * mg[1] < ic[1], "multigrid %d against IC(0) %d iterations at 256x256", mg[1], ic[1]);
}

/* Below the coarsest size the preconditioner is the exact inverse (one
 * iteration); the same system twice gives the same bits. */
static void t_amg_small_and_determinism(void)
{
    pw_zcsr Z;
    pw_zamg M;
    pw_cg_options o;
    pw_cg_stats s;
    pw_err e;
    double *b, *x[2];
    int k, n = 96 * 96;
    REQUIRE(!grid_system(16, 16, &Z, &b));
    x[0] = (double *)calloc(2 * 256, sizeof(double));
    memset(&o, 0, sizeof o);
    o.tol = 1e-10;
    REQUIRE(pw_zamg_setup(NULL, &Z, &M, &e) == PW_OK);
    CHECK_EQ_INT(M.levels, 0);
    REQUIRE(pw_zamg_solve(NULL, &Z, &M, b, x[0], &o, &s, &e) == PW_OK);
    CHECKF(s.iterations <= 2 && s.converged, "%d iterations on a directly solved level", s.iterations);
    pw_zamg_free(NULL, &M);
    pw_zcsr_free(NULL, &Z);
    free(b);
    free(x[0]);
    REQUIRE(!grid_system(96, 96, &Z, &b));
    for (k = 0; k < 2; k++) {
        x[k] = (double *)calloc(2 * (size_t)n, sizeof(double));
        REQUIRE(pw_zamg_setup(NULL, &Z, &M, &e) == PW_OK);
        REQUIRE(pw_zamg_solve(NULL, &Z, &M, b, x[k], &o, &s, &e) == PW_OK);
        pw_zamg_free(NULL, &M);
    }
    CHECK(!memcmp(x[0], x[1], sizeof(double) * 2 * n));
    pw_zcsr_free(NULL, &Z);
    free(b);
    free(x[0]);
    free(x[1]);
}

/* Every allocation of the setup failing in turn: PW_ERR_NOMEM, nothing left. */
/* A hierarchy set up for A serves A + mu D (D = A's diagonal, as pgp's
 * proximal steps): the solve carries the diagonal's change to the coarse
 * levels, and takes about the V-cycles of a hierarchy set up for A + mu D
 * itself (the change left at level 0 alone takes many more). */
static void t_amg_diagonal_change(void)
{
    static const double mus[3] = {1e-3, 1e-2, 0.1};
    pw_zcsr Z;
    pw_zamg M, F;
    pw_cg_options o;
    pw_cg_stats s1, s2;
    pw_err e;
    double *b, *x, *d;
    int n = 96 * 96, i, k, m;
    REQUIRE(!grid_system(96, 96, &Z, &b));
    x = (double *)calloc(2 * (size_t)n, sizeof(double));
    d = (double *)malloc(sizeof(double) * (size_t)n);
    REQUIRE(x && d);
    for (i = 0; i < n; i++)
        for (k = Z.rowptr[i]; k < Z.rowptr[i + 1]; k++)
            if (Z.col[k] == i) d[i] = Z.val[2 * k];
    memset(&o, 0, sizeof o);
    o.tol = 1e-6;
    REQUIRE(pw_zamg_setup(NULL, &Z, &M, &e) == PW_OK);
    for (m = 0; m < 3; m++) {
        for (i = 0; i < n; i++)
            for (k = Z.rowptr[i]; k < Z.rowptr[i + 1]; k++)
                if (Z.col[k] == i) Z.val[2 * k] = d[i] * (1.0 + mus[m]);
        memset(x, 0, sizeof(double) * 2 * n);
        REQUIRE(pw_zamg_solve(NULL, &Z, &M, b, x, &o, &s1, &e) == PW_OK);
        REQUIRE(pw_zamg_setup(NULL, &Z, &F, &e) == PW_OK);
        memset(x, 0, sizeof(double) * 2 * n);
        REQUIRE(pw_zamg_solve(NULL, &Z, &F, b, x, &o, &s2, &e) == PW_OK);
        pw_zamg_free(NULL, &F);
        pwt_info("diagonal times 1 + %g: %d V-cycles with the first hierarchy, %d with its own", mus[m],
                 s1.iterations, s2.iterations);
        CHECKF(s1.iterations <= s2.iterations + 2, "mu %g: %d V-cycles against %d", mus[m], s1.iterations,
               s2.iterations);
    }
    pw_zamg_free(NULL, &M);
    pw_zcsr_free(NULL, &Z);
    free(b);
    free(x);
    free(d);
}

static void t_amg_alloc_failures(void)
{
    pw_zcsr Z;
    double *b;
    int k, fails = 0;
    REQUIRE(!grid_system(40, 40, &Z, &b));
    for (k = 0; k < 400; k++) {
        pwt_alloc_state st = {0, 0, -1};
        pw_alloc al = {pwt_malloc, pwt_realloc, pwt_free, &st};
        pw_zamg M;
        pw_err e;
        int r;
        st.fail_after = k;
        r = pw_zamg_setup(&al, &Z, &M, &e);
        if (r == PW_OK) pw_zamg_free(&al, &M);
        CHECKF(r == PW_OK || r == PW_ERR_NOMEM, "failure point %d: %d", k, r);
        CHECKF(st.live == 0, "failure point %d leaks %d blocks", k, st.live);
        if (r == PW_OK) break;
        fails++;
    }
    CHECK(fails > 10);
    pw_zcsr_free(NULL, &Z);
    free(b);
}

static const pwt_case cases[] = {
    {"zsparse/mul_matches_real", t_mul_matches_real},
    {"zsparse/pattern_matches_triplets", t_pattern_matches_triplets},
    {"zsparse/solve_matches_real", t_solve_matches_real},
    {"zsparse/errors", t_errors},
    {"zsparse/alloc_failures", t_alloc_failures},
    {"zsparse/amg_scaling", t_amg_scaling},
    {"zsparse/amg_small_and_determinism", t_amg_small_and_determinism},
    {"zsparse/amg_diagonal_change", t_amg_diagonal_change},
    {"zsparse/amg_alloc_failures", t_amg_alloc_failures},
};
PWT_MAIN(cases)
