/* Tests of src/common/zsparse.h: complex Hermitian CSR, complex IC(0) and
 * PCG, checked against the same systems written as real 2n x 2n matrices
 * (2x2 blocks [re -im; im re]) and solved by sparse.h's real PCG. */
#include "../src/common/zsparse.h"
#include "../src/common/rng.h"
#include "pwtest.h"

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
                double a = 6.283185307179586 * pw_rng_float(&rng), c = cos(a), s = sin(a), wt = 0.5 + pw_rng_float(&rng);
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

static const pwt_case cases[] = {
    {"zsparse/mul_matches_real", t_mul_matches_real},
    {"zsparse/solve_matches_real", t_solve_matches_real},
    {"zsparse/errors", t_errors},
    {"zsparse/alloc_failures", t_alloc_failures},
};
PWT_MAIN(cases)
