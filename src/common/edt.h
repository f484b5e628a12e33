/* edt: exact Euclidean distance transforms of binary images, plain or
 * periodic (the image wraps around in both directions, as a tile does).
 *
 * The squared distance from every pixel to the nearest "site" pixel is
 * computed exactly by the separable lower-envelope algorithm of Felzenszwalb
 * and Huttenlocher ("Distance transforms of sampled functions", 2004): a 1D
 * transform along every row, then along every column of the result. Each 1D
 * pass builds the lower envelope of the parabolas (q - v)^2 + f(v) and reads
 * it back; on a periodic line the input is laid out three times in a row and
 * the middle copy is read, which is exact because the nearest copy of any
 * site is at most half a period away. Distances are between pixel centres.
 *
 *   pw_edt_sq      squared distance to the nearest site (PW_EDT_FAR if none)
 *   pw_edt_signed  signed distance to the boundary of a mask: positive
 *                  inside, negative outside, |phi| = distance to the nearest
 *                  pixel of the other kind minus 1/2, so that the zero level
 *                  lies on the pixel edges between the two kinds
 * Only sqrt is used (correctly rounded in IEEE arithmetic), so the results
 * are the same on every platform. */
#ifndef PW__EDT_V1
#define PW__EDT_V1

#include "base.h"

#define PW_EDT_FAR FLT_MAX /* squared distance where no site exists */

/* 1D transform of f[0..n) (PW_EDT_FAR: no site) into d[0..n), using the
 * scratch v (n ints) and z (n+1 doubles). Sites are the finite entries. */
PW__DEF void pw__edt_1d(const float *f, int n, float *d, int *v, double *z)
{
    int q, k = -1;
    for (q = 0; q < n; q++) {
        double s = 0.0;
        if (f[q] >= PW_EDT_FAR) continue;
        while (k >= 0) {
            int p = v[k];
            s = (((double)f[q] + (double)q * q) - ((double)f[p] + (double)p * p)) / (2.0 * (q - p));
            if (s > z[k]) break;
            k--;
        }
        k++;
        v[k] = q;
        z[k] = k ? s : -DBL_MAX;
        z[k + 1] = DBL_MAX;
    }
    if (k < 0) {
        for (q = 0; q < n; q++) d[q] = PW_EDT_FAR;
        return;
    }
    for (q = 0, k = 0; q < n; q++) {
        double dq;
        while (z[k + 1] < (double)q) k++;
        dq = (double)(q - v[k]) * (q - v[k]) + f[v[k]];
        d[q] = (float)dq;
    }
}

/* A binary image: w x h pixels px (row-major, nonzero: set); wrap: periodic
 * in x and y (a tile). */
typedef struct pw_edt_image {
    const unsigned char *px;
    int w, h, wrap;
} pw_edt_image;

/* The scratch of the 1D transforms of one distance transform, for lines of
 * up to m pixels (3m when they wrap), and whether they wrap. */
typedef struct pw__edt_ws {
    float *f, *d; /* a line's values and its transform */
    int *v;       /* the parabolas' sites */
    double *z;    /* their boundaries (one more) */
    int wrap;     /* periodic lines, tripled */
} pw__edt_ws;

/* One pass along lines of length n (count lines, element i of line l at
 * data[l*ls + i*es]), in place. */
PW__DEF void pw__edt_pass(float *data, int n, int count, size_t ls, size_t es, const pw__edt_ws *ws)
{
    float *f = ws->f, *d = ws->d;
    int *v = ws->v, wrap = ws->wrap;
    double *z = ws->z;
    int l, i, reps = wrap ? 3 : 1;
    for (l = 0; l < count; l++) {
        float *line = data + (size_t)l * ls;
        for (i = 0; i < n * reps; i++) f[i] = line[(size_t)(i % n) * es];
        pw__edt_1d(f, n * reps, d, v, z);
        for (i = 0; i < n; i++) line[(size_t)i * es] = d[i + (wrap ? n : 0)];
    }
}

/* The first pass over a binary image, along lines of length n laid out as
 * in pw__edt_pass that hold 0 at the sites and PW_EDT_FAR elsewhere, not
 * wrapping: the squared distance to the nearest site on the line, by a
 * sweep each way. The same values as pw__edt_pass's (squares of integers,
 * exact in float), at a fraction of the cost: no parabolas, no division. */
PW__DEF void pw__edt_sites(float *data, int n, int count, size_t ls, size_t es)
{
    int l, i, at;
    for (l = 0; l < count; l++) {
        float *line = data + (size_t)l * ls;
        for (i = 0, at = -1; i < n; i++) { /* to the nearest site before: 0 marks the sites */
            float *d = line + (size_t)i * es;
            if (*d == 0.0f) at = i;
            else if (at >= 0) *d = (float)((i - at) * (i - at));
        }
        for (i = n - 1, at = -1; i >= 0; i--) { /* or after, when nearer */
            float *d = line + (size_t)i * es, after = (float)((at - i) * (at - i));
            if (*d == 0.0f) at = i;
            else if (at >= 0 && after < *d) *d = after;
        }
    }
}

/* out[y*w + x] = squared distance from (x, y) to the nearest pixel with
 * site[] != 0, periodic in x and y when wrap is set; PW_EDT_FAR everywhere
 * when there is no site. */
PW__DEF int pw_edt_sq(const pw_alloc *a, const pw_edt_image *site, float *out, pw_err *e)
{
    int w = site->w, h = site->h, m = (w > h ? w : h) * (site->wrap ? 3 : 1);
    size_t i, n = (size_t)w * h;
    pw__edt_ws ws;
    float *f = (float *)pw_alloc_array(a, (size_t)m * 2, sizeof(float), "distance transform", e);
    int *v = (int *)pw_alloc_array(a, (size_t)m, sizeof(int), "distance transform", e);
    double *z = (double *)pw_alloc_array(a, (size_t)m + 1, sizeof(double), "distance transform", e);
    if (!f || !v || !z) {
        pw_free(a, f);
        pw_free(a, v);
        pw_free(a, z);
        return PW_ERR_NOMEM;
    }
    ws.f = f;
    ws.d = f + m;
    ws.v = v;
    ws.z = z;
    ws.wrap = site->wrap;
    for (i = 0; i < n; i++) out[i] = site->px[i] ? 0.0f : PW_EDT_FAR;
    if (site->wrap) pw__edt_pass(out, w, h, (size_t)w, 1, &ws);
    else pw__edt_sites(out, w, h, (size_t)w, 1);
    pw__edt_pass(out, h, w, 1, (size_t)w, &ws);
    pw_free(a, f);
    pw_free(a, v);
    pw_free(a, z);
    return PW_OK;
}

/* phi[i] > 0 where mask[i] != 0 (inside), < 0 elsewhere; |phi| is the
 * distance to the nearest pixel of the other kind minus 1/2. A mask with no
 * pixel of one kind gives +-sqrt(PW_EDT_FAR) on the other. */
PW__DEF int pw_edt_signed(const pw_alloc *a, const pw_edt_image *im, float *phi, pw_err *e)
{
    const unsigned char *mask = im->px;
    size_t i, n = (size_t)im->w * im->h;
    unsigned char *inv = (unsigned char *)pw_alloc_array(a, n, 1, "signed distance", e);
    float *din = (float *)pw_alloc_array(a, n, sizeof(float), "signed distance", e);
    pw_edt_image rest = *im; /* the other kind */
    int r = inv && din ? PW_OK : PW_ERR_NOMEM;
    rest.px = inv;
    for (i = 0; r == PW_OK && i < n; i++) inv[i] = (unsigned char)!mask[i];
    if (r == PW_OK) r = pw_edt_sq(a, im, phi, e);    /* outside: to the mask */
    if (r == PW_OK) r = pw_edt_sq(a, &rest, din, e); /* inside: to the rest */
    for (i = 0; r == PW_OK && i < n; i++) phi[i] = mask[i] ? sqrtf(din[i]) - 0.5f : 0.5f - sqrtf(phi[i]);
    pw_free(a, inv);
    pw_free(a, din);
    return r;
}

#endif /* PW__EDT_V1 */
