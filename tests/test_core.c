/* Tests of the smallest shared modules: base (errors, allocation helpers,
 * extensions), rng (reference vectors, so every platform draws the same
 * numbers) and vec (deterministic trigonometry). */
#include "../src/common/rng.h"
#include "../src/common/vec.h"
#include "pwtest.h"

/* PCG32 reference output for seed 42, stream 54 (pcg32-demo, O'Neill). */
static void t_pcg32_reference(void)
{
    static const uint32_t want[6] = {0xa15c02b7u, 0x7b47f409u, 0xba1d3330u,
                                     0x83d2f293u, 0xbfa4784bu, 0xcbed606eu};
    pw_rng r = pw_rng_seed(42u, 54u);
    int k;
    for (k = 0; k < 6; k++) CHECKF(pw_rng_u32(&r) == want[k], "output %d", k);
}

static void t_rng_ranges(void)
{
    pw_rng r = pw_rng_seed(7u, 1u);
    int k, counts[5] = {0, 0, 0, 0, 0}, perm[10], seen = 0;
    for (k = 0; k < 50000; k++) {
        float f = pw_rng_float(&r);
        double d = pw_rng_double(&r);
        uint32_t b = pw_rng_below(&r, 5u);
        CHECK(f >= 0.0f && f < 1.0f);
        CHECK(d >= 0.0 && d < 1.0);
        REQUIRE(b < 5u);
        counts[b]++;
    }
    for (k = 0; k < 5; k++) CHECKF(counts[k] > 9500 && counts[k] < 10500, "bucket %d: %d", k, counts[k]);
    for (k = 0; k < 10; k++) perm[k] = k;
    pw_rng_shuffle(&r, perm, 10);
    for (k = 0; k < 10; k++) seen |= 1 << perm[k];
    CHECK_EQ_INT(seen, 1023);
}

/* Counter-based hashes are fixed functions of (seed, index): pinned here so
 * that a change that would alter every output is noticed. */
static void t_hash_pinned(void)
{
    CHECK(pw_hash64(0u, 0u) == pw_hash64(0u, 0u));
    CHECK(pw_hash64(0u, 0u) != pw_hash64(0u, 1u));
    CHECK(pw_hash64(1u, 0u) != pw_hash64(0u, 0u));
    /* SplitMix64's first output for state 0 (seed 0, index 0 adds one step) */
    CHECK(pw_hash64(0u, 0u) == 0xE220A8397B1DCDAFull);
}

static void t_trig(void)
{
    double x, worst = 0.0;
    for (x = -50.0; x < 50.0; x += 0.0137) {
        double d1 = fabs(pw_sin(x) - sin(x)), d2 = fabs(pw_cos(x) - cos(x));
        if (d1 > worst) worst = d1;
        if (d2 > worst) worst = d2;
    }
    pwt_info("max |pw_sin - sin|, |pw_cos - cos| on [-50, 50]: %.2e", worst);
    CHECK(worst < 1e-14);
    CHECK(pw_sin(0.0) == 0.0);
}

static void t_errors(void)
{
    pw_err e;
    pw_err_clear(&e);
    CHECK_EQ_INT(pw_fail(&e, PW_ERR_PARSE, "%s:%d: bad", "f.obj", 3), PW_ERR_PARSE);
    CHECK(!strcmp(e.msg, "f.obj:3: bad"));
    CHECK_EQ_INT(pw_fail(&e, PW_ERR_NOMEM, "later"), PW_ERR_PARSE); /* the first error wins */
    CHECK(!strcmp(e.msg, "f.obj:3: bad"));
    CHECK_EQ_INT(pw_fail(NULL, PW_ERR_IO, "x"), PW_ERR_IO);
    CHECK(!strcmp(pw_result_string(PW_OK), "ok"));
    CHECK(!strcmp(pw_result_string(999), "unknown error"));
}

static void t_alloc_helpers(void)
{
    pwt_alloc_state st = {0, 0, -1};
    pw_alloc a = {pwt_malloc, pwt_realloc, pwt_free, NULL};
    pw_err e;
    void *p;
    size_t cap = 0;
    int *q = NULL;
    a.user = &st;
    pw_err_clear(&e);
    CHECK(pw_alloc_array(&a, (size_t)-1 / 2, 4, "huge", &e) == NULL);
    CHECK_EQ_INT(e.code, PW_ERR_NOMEM);
    CHECK(strstr(e.msg, "huge") != NULL);
    CHECK_EQ_INT(st.calls, 0); /* refused before asking the allocator */
    pw_err_clear(&e);
    p = pw_calloc_array(&a, 10, 4, "ten", &e);
    REQUIRE(p != NULL);
    CHECK(((int *)p)[9] == 0);
    pw_free(&a, p);
    CHECK_EQ_INT(pw_grow(&a, (void **)&q, &cap, 100, sizeof(int), "grow", &e), PW_OK);
    CHECK(cap >= 100);
    pw_free(&a, q);
    CHECK_EQ_INT(st.live, 0);
    st.fail_after = st.calls;
    q = NULL;
    cap = 0;
    CHECK_EQ_INT(pw_grow(&a, (void **)&q, &cap, 100, sizeof(int), "grow", &e), PW_ERR_NOMEM);
    CHECK(q == NULL && cap == 0);
}

static void t_extensions(void)
{
    CHECK(pw_has_ext("a/b.PNG", ".png"));
    CHECK(pw_has_ext("x.ppm", ".ppm"));
    CHECK(!pw_has_ext("png", ".png"));
    CHECK(!pw_has_ext("x.png.tmp", ".png"));
}

static void t_finite(void)
{
    volatile double zero = 0.0;
    CHECK(pw_is_finite(1.0));
    CHECK(!pw_is_finite(1.0 / zero));
    CHECK(!pw_is_finite(zero / zero));
}

static const pwt_case cases[] = {
    {"core/pcg32_reference", t_pcg32_reference},
    {"core/rng_ranges", t_rng_ranges},
    {"core/hash_pinned", t_hash_pinned},
    {"core/trig", t_trig},
    {"core/errors", t_errors},
    {"core/alloc_helpers", t_alloc_helpers},
    {"core/extensions", t_extensions},
    {"core/finite", t_finite},
};
PWT_MAIN(cases)
