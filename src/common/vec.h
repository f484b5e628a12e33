/* vec: small vector math on float[3] arrays and a 3-float struct. */
#ifndef PW__VEC_V1
#define PW__VEC_V1

#include "base.h"

typedef struct pw_v3 {
    float x, y, z;
} pw_v3;

PW__DEF pw_v3 pw_v3_make(float x, float y, float z)
{
    pw_v3 r;
    r.x = x;
    r.y = y;
    r.z = z;
    return r;
}
PW__DEF pw_v3 pw_v3_load(const float *p) { return pw_v3_make(p[0], p[1], p[2]); }
PW__DEF void pw_v3_store(float *p, pw_v3 a)
{
    p[0] = a.x;
    p[1] = a.y;
    p[2] = a.z;
}
PW__DEF pw_v3 pw_v3_add(pw_v3 a, pw_v3 b) { return pw_v3_make(a.x + b.x, a.y + b.y, a.z + b.z); }
PW__DEF pw_v3 pw_v3_sub(pw_v3 a, pw_v3 b) { return pw_v3_make(a.x - b.x, a.y - b.y, a.z - b.z); }
PW__DEF pw_v3 pw_v3_scale(pw_v3 a, float s) { return pw_v3_make(a.x * s, a.y * s, a.z * s); }
PW__DEF float pw_v3_dot(pw_v3 a, pw_v3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
PW__DEF pw_v3 pw_v3_cross(pw_v3 a, pw_v3 b)
{
    return pw_v3_make(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
PW__DEF float pw_v3_len(pw_v3 a) { return sqrtf(pw_v3_dot(a, a)); }
/* Unit vector; the zero vector stays zero. */
PW__DEF pw_v3 pw_v3_norm(pw_v3 a)
{
    float l = pw_v3_len(a);
    return l > 0.0f ? pw_v3_scale(a, 1.0f / l) : a;
}
PW__DEF pw_v3 pw_v3_min(pw_v3 a, pw_v3 b)
{
    return pw_v3_make(a.x < b.x ? a.x : b.x, a.y < b.y ? a.y : b.y, a.z < b.z ? a.z : b.z);
}
PW__DEF pw_v3 pw_v3_max(pw_v3 a, pw_v3 b)
{
    return pw_v3_make(a.x > b.x ? a.x : b.x, a.y > b.y ? a.y : b.y, a.z > b.z ? a.z : b.z);
}

/* Double-precision 3-vectors as arrays. */
PW__DEF double pw_dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
/* out = a + (b - a) t, for colours and points (out may alias a or b). */
PW__DEF void pw_mix3(double *out, const double *a, const double *b, double t)
{
    int k;
    for (k = 0; k < 3; k++) out[k] = a[k] + (b[k] - a[k]) * t;
}
PW__DEF void pw_mix3f(float *out, const float *a, const float *b, float t)
{
    int k;
    for (k = 0; k < 3; k++) out[k] = a[k] + (b[k] - a[k]) * t;
}

PW__DEF void pw_cross3(const double *a, const double *b, double *out)
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

PW__DEF double pw_dist3(const double *a, const double *b)
{
    double x = a[0] - b[0], y = a[1] - b[1], z = a[2] - b[2];
    return sqrt(x * x + y * y + z * z);
}

/* Normalises v in place; returns its former length (a zero v stays zero). */
PW__DEF double pw_norm3(double *v)
{
    double l = sqrt(pw_dot3(v, v));
    if (l > 0.0) {
        v[0] /= l;
        v[1] /= l;
        v[2] /= l;
    }
    return l;
}

/* sin and cos from + - * / only, so that procedural geometry is
 * bit-identical on every platform (libm results may differ in the last
 * bit). Taylor series to r^19 after reduction to [-pi/2, pi/2]: error below
 * 1e-14 for |x| < 100, growing with |x| (the reduction uses a double pi). */
PW__DEF double pw_sin(double x)
{
    const double pi = 3.14159265358979323846;
    double k = x / pi, r, r2, s;
    long n = (long)(k >= 0 ? k + 0.5 : k - 0.5);
    r = x - (double)n * pi; /* r in [-pi/2, pi/2] */
    r2 = r * r;
    s = r * (1.0 +
             r2 * (-1.0 / 6 +
                   r2 * (1.0 / 120 +
                         r2 * (-1.0 / 5040 +
                               r2 * (1.0 / 362880 + r2 * (-1.0 / 39916800 +
                                                          r2 * (1.0 / 6227020800.0 +
                                                                r2 * (-1.0 / 1307674368000.0 +
                                                                      r2 * (1.0 / 355687428096000.0 +
                                                                            r2 * (-1.0 / 121645100408832000.0))))))))));
    return (n & 1) ? -s : s;
}
PW__DEF double pw_cos(double x) { return pw_sin(x + 1.57079632679489661923); }

#endif /* PW__VEC_V1 */
