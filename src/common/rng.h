/* rng: seeded random numbers with the same output on every platform.
 * Sequential streams use PCG32 (O'Neill 2014); per-element randomness that
 * must not depend on visiting order uses a counter-based hash (SplitMix64
 * finaliser) of (seed, index). Floats come from integer bits only, so no
 * platform-dependent libm call is involved. */
#ifndef PW__RNG_V1
#define PW__RNG_V1

#include "base.h"

typedef struct pw_rng {
    uint64_t state, inc;
} pw_rng;

PW__DEF uint32_t pw_rng_u32(pw_rng *r)
{
    uint64_t old = r->state;
    uint32_t xorshifted, rot;
    r->state = old * 6364136223846793005ULL + r->inc;
    xorshifted = (uint32_t)(((old >> 18) ^ old) >> 27);
    rot = (uint32_t)(old >> 59);
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
}

/* Seeds a stream; different `stream` values give independent sequences. */
PW__DEF pw_rng pw_rng_seed(uint64_t seed, uint64_t stream)
{
    pw_rng r;
    r.state = 0;
    r.inc = (stream << 1) | 1u;
    pw_rng_u32(&r);
    r.state += seed;
    pw_rng_u32(&r);
    return r;
}

/* Uniform integer in [0, n) without modulo bias (n >= 1). */
PW__DEF uint32_t pw_rng_below(pw_rng *r, uint32_t n)
{
    uint32_t threshold = (0u - n) % n, x;
    do x = pw_rng_u32(r);
    while (x < threshold);
    return x % n;
}

/* Uniform float in [0, 1), 24 random bits. */
PW__DEF float pw_rng_float(pw_rng *r) { return (float)(pw_rng_u32(r) >> 8) * (1.0f / 16777216.0f); }

/* Uniform double in [0, 1), 53 random bits. */
PW__DEF double pw_rng_double(pw_rng *r)
{
    uint64_t hi = pw_rng_u32(r) >> 5, lo = pw_rng_u32(r) >> 6;
    return (double)(hi * 67108864u + lo) * (1.0 / 9007199254740992.0);
}

/* Counter-based: a well-mixed 64-bit value of (seed, index). */
PW__DEF uint64_t pw_hash64(uint64_t seed, uint64_t index)
{
    uint64_t z = seed + 0x9E3779B97F4A7C15ULL * (index + 1);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

/* Fisher-Yates shuffle of n ints. */
PW__DEF void pw_rng_shuffle(pw_rng *r, int *a, int n)
{
    int i;
    for (i = n - 1; i > 0; i--) {
        int j = (int)pw_rng_below(r, (uint32_t)i + 1u), t = a[i];
        a[i] = a[j];
        a[j] = t;
    }
}

#endif /* PW__RNG_V1 */
