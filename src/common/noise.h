/* noise: value noise and its fractal sum, for the built-in procedural
 * exemplars of every method (tiled's pebbles and lichen, lapped's scales and
 * stripes, pgp's stone walls, lst's wood, fibres and kiwi). Value noise
 * (Perlin 1985 "An image synthesizer", its lattice form): a random value at
 * each integer lattice point, blended with a quintic fade (Perlin 2002) so
 * the noise is C2 between cells. The lattice values come from the
 * counter-based hash of rng.h, so the noise is the same on every platform
 * and independent of evaluation order. */
#ifndef PW__NOISE_V1
#define PW__NOISE_V1

#include "rng.h"
#include <math.h>

/* A uniform value in [0, 1) for integer lattice point (x, y, z); the
 * coordinates are taken modulo 2^21, far beyond any exemplar's lattice. */
PW__DEF double pw_lattice01(uint64_t seed, long x, long y, long z)
{
    uint64_t key = (uint64_t)(x & 0x1FFFFF) | (uint64_t)(y & 0x1FFFFF) << 21 | (uint64_t)(z & 0x1FFFFF) << 42;
    return (double)(pw_hash64(seed, key) >> 11) * (1.0 / 9007199254740992.0);
}

/* The quintic fade 6t^5 - 15t^4 + 10t^3 on [0, 1]. */
PW__DEF double pw_fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

/* Hermite smoothstep: 0 below e0, 1 above e1, C1 between. */
PW__DEF double pw_smoothstep(double e0, double e1, double x)
{
    double t = (x - e0) / (e1 - e0);
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    return t * t * (3.0 - 2.0 * t);
}

/* Lattice cell and position within it for coordinate x, the lattice
 * wrapped to `period` cells when period > 0 (so the noise repeats every
 * `period` units); *i0, *i1 are the cell's two lattice coordinates. */
PW__DEF double pw__noise_cell(double x, long period, long *i0, long *i1)
{
    double f = floor(x);
    long i = (long)f;
    if (period > 0) {
        i %= period;
        i += i < 0 ? period : 0;
        *i1 = i + 1 < period ? i + 1 : 0;
    } else {
        *i1 = i + 1;
    }
    *i0 = i;
    return pw_fade(x - f);
}

/* 2D value noise in [0, 1] with lattice spacing 1, repeating every
 * `period` units in x and y when period > 0. */
PW__DEF double pw_noise2(uint64_t seed, double x, double y, long period)
{
    long x0, x1, y0, y1;
    double tx = pw__noise_cell(x, period, &x0, &x1), ty = pw__noise_cell(y, period, &y0, &y1);
    double a = pw_lattice01(seed, x0, y0, 0), b = pw_lattice01(seed, x1, y0, 0);
    double c = pw_lattice01(seed, x0, y1, 0), d = pw_lattice01(seed, x1, y1, 0);
    a += (b - a) * tx;
    c += (d - c) * tx;
    return a + (c - a) * ty;
}

/* 3D value noise in [0, 1] with lattice spacing 1 (not periodic). */
PW__DEF double pw_noise3(uint64_t seed, double x, double y, double z)
{
    long x0, x1, y0, y1, z0, z1;
    double tx = pw__noise_cell(x, 0, &x0, &x1), ty = pw__noise_cell(y, 0, &y0, &y1);
    double tz = pw__noise_cell(z, 0, &z0, &z1), c[2];
    int k;
    for (k = 0; k < 2; k++) {
        long zk = k ? z1 : z0;
        double a = pw_lattice01(seed, x0, y0, zk), b = pw_lattice01(seed, x1, y0, zk);
        double d = pw_lattice01(seed, x0, y1, zk), e = pw_lattice01(seed, x1, y1, zk);
        a += (b - a) * tx;
        d += (e - d) * tx;
        c[k] = a + (d - a) * ty;
    }
    return c[0] + (c[1] - c[0]) * tz;
}

/* Fractal sums in [0, 1]: three octaves of the noise above at frequencies
 * 1, 2 and 4 with weights 4/7, 2/7 and 1/7 (each octave half the amplitude
 * of the one below, seeds seed, seed + 1, seed + 2). pw_fbm2's octaves
 * repeat every period, period/2 and period/4 units when period > 0. */
PW__DEF double pw_fbm2(uint64_t seed, double x, double y, long period)
{
    return (4.0 * pw_noise2(seed, x, y, period) + 2.0 * pw_noise2(seed + 1, 2.0 * x, 2.0 * y, 2 * period) +
            pw_noise2(seed + 2, 4.0 * x, 4.0 * y, 4 * period)) /
           7.0;
}

PW__DEF double pw_fbm3(uint64_t seed, double x, double y, double z)
{
    return (4.0 * pw_noise3(seed, x, y, z) + 2.0 * pw_noise3(seed + 1, 2.0 * x, 2.0 * y, 2.0 * z) +
            pw_noise3(seed + 2, 4.0 * x, 4.0 * y, 4.0 * z)) /
           7.0;
}

#endif
