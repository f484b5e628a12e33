/* pca: principal component analysis of vectors streamed one at a time.
 *
 * pw_pca_add accumulates the sums of x and x x^T (in double); pw_pca_solve
 * forms the covariance, diagonalises it with the cyclic Jacobi method
 * (rotations from sqrt only, so the result is the same on every platform)
 * and returns the mean, the k leading unit eigenvectors (largest variance
 * first, each with its sign fixed so that its largest component is
 * positive) and their variances. pw_pca_project maps a vector to its k
 * coordinates (pw_pca_pack and pw_pca_project_packed: the same, faster, for
 * k <= 8). Texture synthesis uses it to shorten neighbourhood vectors
 * before nearest-neighbour search (Lefebvre and Hoppe 2006).
 *
 *   pw_pca_init, pw_pca_add, pw_pca_solve, pw_pca_free, pw_pca_project,
 *   pw_pca_pack, pw_pca_project_packed */
#ifndef PW__PCA_V1
#define PW__PCA_V1

#include "base.h"

typedef struct pw_pca {
    int d;
    double n;
    double *sum;   /* d */
    double *cross; /* d*d, upper triangle used */
} pw_pca;

PW__DEF void pw_pca_free(const pw_alloc *a, pw_pca *p)
{
    if (!p) return;
    pw_free(a, p->sum);
    pw_free(a, p->cross);
    memset(p, 0, sizeof *p);
}

PW__DEF int pw_pca_init(const pw_alloc *a, pw_pca *p, int d, pw_err *e)
{
    memset(p, 0, sizeof *p);
    p->sum = (double *)pw_calloc_array(a, (size_t)d, sizeof(double), "PCA sums", e);
    p->cross = (double *)pw_calloc_array(a, (size_t)d * d, sizeof(double), "PCA covariance", e);
    if (!p->sum || !p->cross) {
        pw_pca_free(a, p);
        return PW_ERR_NOMEM;
    }
    p->d = d;
    return PW_OK;
}

PW__DEF void pw_pca_add(pw_pca *p, const float *x)
{
    int i, j, d = p->d;
    for (i = 0; i < d; i++) {
        double xi = x[i], *row = p->cross + (size_t)i * d;
        p->sum[i] += xi;
        for (j = i; j < d; j++) row[j] += xi * x[j];
    }
    p->n += 1.0;
}

/* One Jacobi rotation zeroing c[p][q] of the symmetric d x d matrix c,
 * accumulated into the eigenvector columns of v. */
PW__DEF void pw__pca_rotate(double *c, double *v, int d, int p, int q)
{
    double apq = c[(size_t)p * d + q], th, t, cs, sn;
    int k;
    th = (c[(size_t)q * d + q] - c[(size_t)p * d + p]) / (2.0 * apq);
    t = (th >= 0.0 ? 1.0 : -1.0) / (fabs(th) + sqrt(th * th + 1.0));
    cs = 1.0 / sqrt(t * t + 1.0);
    sn = t * cs;
    for (k = 0; k < d; k++) { /* columns p, q */
        double ckp = c[(size_t)k * d + p], ckq = c[(size_t)k * d + q];
        c[(size_t)k * d + p] = cs * ckp - sn * ckq;
        c[(size_t)k * d + q] = sn * ckp + cs * ckq;
    }
    for (k = 0; k < d; k++) { /* rows p, q */
        double cpk = c[(size_t)p * d + k], cqk = c[(size_t)q * d + k];
        c[(size_t)p * d + k] = cs * cpk - sn * cqk;
        c[(size_t)q * d + k] = sn * cpk + cs * cqk;
    }
    for (k = 0; k < d; k++) {
        double vkp = v[(size_t)k * d + p], vkq = v[(size_t)k * d + q];
        v[(size_t)k * d + p] = cs * vkp - sn * vkq;
        v[(size_t)k * d + q] = sn * vkp + cs * vkq;
    }
}

/* Cyclic Jacobi sweeps until the off-diagonal part is negligible. */
PW__DEF void pw__pca_jacobi(double *c, double *v, int d)
{
    int sweep, p, q;
    for (p = 0; p < d * d; p++) v[p] = 0.0;
    for (p = 0; p < d; p++) v[(size_t)p * d + p] = 1.0;
    for (sweep = 0; sweep < 60; sweep++) {
        double off = 0.0, diag = 0.0;
        for (p = 0; p < d; p++) {
            diag += c[(size_t)p * d + p] * c[(size_t)p * d + p];
            for (q = p + 1; q < d; q++) off += c[(size_t)p * d + q] * c[(size_t)p * d + q];
        }
        if (off <= 1e-24 * diag || off == 0.0) return;
        for (p = 0; p < d; p++)
            for (q = p + 1; q < d; q++)
                if (c[(size_t)p * d + q] != 0.0) pw__pca_rotate(c, v, d, p, q);
    }
}

/* Where pw_pca_solve puts the k (<= d) leading components: the caller's
 * arrays mean[d], basis[k*d] (row j is component j), var[k] (may be NULL). */
typedef struct pw_pca_out {
    int k;
    float *mean, *basis, *var;
} pw_pca_out;

/* The leading components into out. Needs at least one vector. */
PW__DEF int pw_pca_solve(const pw_alloc *a, const pw_pca *p, const pw_pca_out *out, pw_err *e)
{
    float *mean = out->mean, *basis = out->basis, *var = out->var;
    int d = p->d, k = out->k, i, j, r;
    double *c = (double *)pw_alloc_array(a, (size_t)d * d * 2, sizeof(double), "PCA eigenvectors", e);
    double *v = c + (size_t)d * d;
    if (!c) return PW_ERR_NOMEM;
    if (p->n < 1.0 || k < 1 || k > d) {
        pw_free(a, c);
        return pw_fail(e, PW_ERR_INVALID, "PCA: %d components of %g vectors of dimension %d", k, p->n, d);
    }
    for (i = 0; i < d; i++) mean[i] = (float)(p->sum[i] / p->n);
    for (i = 0; i < d; i++)
        for (j = i; j < d; j++)
            c[(size_t)i * d + j] = c[(size_t)j * d + i] =
                p->cross[(size_t)i * d + j] / p->n - (p->sum[i] / p->n) * (p->sum[j] / p->n);
    pw__pca_jacobi(c, v, d);
    for (r = 0; r < k; r++) { /* selection of the largest remaining eigenvalue */
        int best = -1, big = 0;
        for (j = 0; j < d; j++)
            if (c[(size_t)j * d + j] > -DBL_MAX && (best < 0 || c[(size_t)j * d + j] > c[(size_t)best * d + best]))
                best = j;
        for (i = 1; i < d; i++)
            if (fabs(v[(size_t)i * d + best]) > fabs(v[(size_t)big * d + best])) big = i;
        for (i = 0; i < d; i++)
            basis[(size_t)r * d + i] =
                (float)(v[(size_t)big * d + best] < 0.0 ? -v[(size_t)i * d + best] : v[(size_t)i * d + best]);
        if (var) var[r] = (float)(c[(size_t)best * d + best] > 0.0 ? c[(size_t)best * d + best] : 0.0);
        c[(size_t)best * d + best] = -DBL_MAX;
    }
    pw_free(a, c);
    return PW_OK;
}

/* y[k] = basis (x - mean). */
PW__DEF void pw_pca_project(const float *x, const float *mean, const float *basis, int d, int k, float *y)
{
    int i, j;
    for (j = 0; j < k; j++) {
        const float *b = basis + (size_t)j * d;
        float s = 0.0f;
        for (i = 0; i < d; i++) s += b[i] * (x[i] - mean[i]);
        y[j] = s;
    }
}

/* A basis of k <= PW_PCA_PACK components repacked for pw_pca_project_packed:
 * packed[i*PW_PCA_PACK + j] = basis[j*d + i], zero for j >= k (d*PW_PCA_PACK
 * floats). */
#define PW_PCA_PACK 8
PW__DEF void pw_pca_pack(const float *basis, int d, int k, float *packed)
{
    int i, j;
    for (i = 0; i < d; i++)
        for (j = 0; j < PW_PCA_PACK; j++) packed[(size_t)i * PW_PCA_PACK + j] = j < k ? basis[(size_t)j * d + i] : 0.0f;
}

/* y[PW_PCA_PACK] = packed basis (x - mean): the same coordinates (zeros past
 * k), with every component's sum advancing in one fixed-width loop the
 * compiler keeps in vector registers -- several times faster than one
 * dot product after the other, for the short vectors of texture synthesis. */
PW__DEF void pw_pca_project_packed(const float *x, const float *mean, const float *packed, int d, float *y)
{
    float acc[PW_PCA_PACK];
    int i, j;
    for (j = 0; j < PW_PCA_PACK; j++) acc[j] = 0.0f;
    for (i = 0; i < d; i++) {
        const float xi = x[i] - mean[i], *b = packed + (size_t)i * PW_PCA_PACK;
        for (j = 0; j < PW_PCA_PACK; j++) acc[j] += b[j] * xi;
    }
    for (j = 0; j < PW_PCA_PACK; j++) y[j] = acc[j];
}

#endif /* PW__PCA_V1 */
