/* atlas_bake: a texture baked into the packed charts of an atlas.
 *
 * Every texel whose centre a chart triangle covers (pw_raster_tri) gets
 * the caller's texture there; texels that a bilinear lookup inside a chart
 * can reach but no triangle covers get the texture at the nearest point of
 * the nearest triangle; `gutter` rounds of dilation fill the gutter with
 * the nearest chart texel. */
#ifndef PW__ATLAS_BAKE_V1
#define PW__ATLAS_BAKE_V1

#include "atlas.h"
#include "image.h"
#include "raster.h"

/* ---- baking ------------------------------------------------------------------- */

/* The texture at a point of triangle f, barycentrics b (in the triangle's
 * corner order): `oc` channels into out. */
typedef void (*pw_atlas_texel_fn)(void *user, int f, const float b[3], float *out);

/* What an atlas shows: fn(user, ...) gives `oc` channels per point. */
typedef struct pw_atlas_source {
    pw_atlas_texel_fn fn;
    void *user;
    int oc;
} pw_atlas_source;

typedef struct pw__atlas_baker {
    pw_atlas_texel_fn fn;
    void *user;
    const float *uvs;
    pw_image *img; /* size x size, oc channels */
    int *id;       /* per texel: covering triangle; -2 - f when extrapolated from f; -1 */
    int size, oc, f;
} pw__atlas_baker;

PW__DEF void pw__atlas_bake_eval(pw__atlas_baker *B, int f, const float *b, int x, int y)
{
    B->fn(B->user, f, b, B->img->px + ((size_t)y * B->size + x) * B->oc);
}

PW__DEF void pw__atlas_bake_texel(void *user, int x, int y, float b0, float b1, float b2)
{
    pw__atlas_baker *B = (pw__atlas_baker *)user;
    float b[3];
    b[0] = b0;
    b[1] = b1;
    b[2] = b2;
    B->id[(size_t)y * B->size + x] = B->f;
    pw__atlas_bake_eval(B, B->f, b, x, y);
}

/* Triangle f in pixels: x right, y down from the top row (v = 0 is the
 * bottom row of the image). */
PW__DEF void pw__atlas_bake_px(const pw__atlas_baker *B, int f, float *p)
{
    int k;
    for (k = 0; k < 3; k++) {
        p[2 * k] = B->uvs[6 * f + 2 * k] * (float)B->size;
        p[2 * k + 1] = (1.0f - B->uvs[6 * f + 2 * k + 1]) * (float)B->size;
    }
}

/* Squared distance from (x, y) to triangle p (pixels) and the barycentrics
 * of the closest point. */
PW__DEF double pw__atlas_closest(const float *p, double x, double y, float *b)
{
    double t[6], d2, best = DBL_MAX;
    int k;
    for (k = 0; k < 6; k++) t[k] = p[k];
    d2 = pw__atlas_area2(t);
    if (d2 != 0.0) {
        double q[6];
        for (k = 0; k < 3; k++) {
            memcpy(q, t, sizeof q);
            q[2 * k] = x;
            q[2 * k + 1] = y;
            b[k] = (float)(pw__atlas_area2(q) / d2);
        }
        if (b[0] >= 0.0f && b[1] >= 0.0f && b[2] >= 0.0f) return 0.0;
    }
    for (k = 0; k < 3; k++) {
        const double *P = t + 2 * k, *Q = t + 2 * ((k + 1) % 3);
        double ex = Q[0] - P[0], ey = Q[1] - P[1], l2 = ex * ex + ey * ey, s = 0.0, dx, dy;
        if (l2 > 0.0) s = ((x - P[0]) * ex + (y - P[1]) * ey) / l2;
        s = s < 0.0 ? 0.0 : (s > 1.0 ? 1.0 : s);
        dx = P[0] + s * ex - x;
        dy = P[1] + s * ey - y;
        if (dx * dx + dy * dy < best) {
            best = dx * dx + dy * dy;
            b[k] = (float)(1.0 - s);
            b[(k + 1) % 3] = (float)s;
            b[(k + 2) % 3] = 0.0f;
        }
    }
    return best;
}

/* Does the open 2x2 square centred on (x, y) meet triangle p? A bilinear
 * lookup somewhere in the triangle then reads the texel centred there. */
PW__DEF int pw__atlas_near_tri(const float *p, double x, double y)
{
    double t[6], lo, hi;
    int k;
    for (k = 0; k < 6; k++) t[k] = p[k];
    pw__atlas_project(t, 1.0, 0.0, &lo, &hi);
    if (hi <= x - 1.0 || lo >= x + 1.0) return 0;
    pw__atlas_project(t, 0.0, 1.0, &lo, &hi);
    if (hi <= y - 1.0 || lo >= y + 1.0) return 0;
    for (k = 0; k < 3; k++) {
        const double *P = t + 2 * k, *Q = t + 2 * ((k + 1) % 3);
        double nx = Q[1] - P[1], ny = P[0] - Q[0], c = nx * x + ny * y, r = fabs(nx) + fabs(ny);
        pw__atlas_project(t, nx, ny, &lo, &hi);
        if (hi <= c - r || lo >= c + r) return 0;
    }
    return 1;
}

/* Claims, for extrapolation from triangle f, the uncovered texels a
 * bilinear lookup inside f can reach, unless a nearer triangle claimed
 * them. With them a lookup anywhere in a chart reads only that chart's
 * texture, so the atlas has no seams of its own inside the charts' area. */
PW__DEF void pw__atlas_bake_ring(pw__atlas_baker *B, int f)
{
    float p[6], q[6], b[3];
    int x, y, x0, x1, y0, y1, k;
    pw__atlas_bake_px(B, f, p);
    x0 = x1 = (int)floor(p[0]);
    y0 = y1 = (int)floor(p[1]);
    for (k = 1; k < 3; k++) {
        x0 = pw_mini(x0, (int)floor(p[2 * k]));
        x1 = pw_maxi(x1, (int)floor(p[2 * k]));
        y0 = pw_mini(y0, (int)floor(p[2 * k + 1]));
        y1 = pw_maxi(y1, (int)floor(p[2 * k + 1]));
    }
    for (y = pw_maxi(y0 - 1, 0); y <= pw_mini(y1 + 1, B->size - 1); y++)
        for (x = pw_maxi(x0 - 1, 0); x <= pw_mini(x1 + 1, B->size - 1); x++) {
            int *id = B->id + (size_t)y * B->size + x;
            if (*id >= 0 || !pw__atlas_near_tri(p, x + 0.5, y + 0.5)) continue;
            if (*id <= -2) {
                pw__atlas_bake_px(B, -2 - *id, q);
                if (pw__atlas_closest(q, x + 0.5, y + 0.5, b) <= pw__atlas_closest(p, x + 0.5, y + 0.5, b)) continue;
            }
            *id = -2 - f;
        }
}

/* The extrapolated texels: the lapped texture at the closest point of
 * their triangle. */
PW__DEF void pw__atlas_bake_ring_values(pw__atlas_baker *B)
{
    int x, y;
    for (y = 0; y < B->size; y++)
        for (x = 0; x < B->size; x++) {
            int id = B->id[(size_t)y * B->size + x];
            float p[6], b[3];
            if (id > -2) continue;
            pw__atlas_bake_px(B, -2 - id, p);
            pw__atlas_closest(p, x + 0.5, y + 0.5, b);
            pw__atlas_bake_eval(B, -2 - id, b, x, y);
        }
}

/* The gutter: `gutter` rounds of dilation. Each round gives every empty
 * texel next to one filled in an earlier round that texel's value (side
 * neighbours first, then diagonal ones), so each gutter texel copies its
 * nearest chart texel (chessboard distance) and bilinear or mipmapped
 * lookups near a chart's border do not pick up the background. The rest
 * of the image stays 0. */
PW__DEF int pw__atlas_dilate(const pw_alloc *a, pw__atlas_baker *B, int gutter, pw_err *e)
{
    static const int dx[8] = {-1, 1, 0, 0, -1, 1, -1, 1}, dy[8] = {0, 0, -1, 1, -1, -1, 1, 1};
    int n = B->size, x, y, k, pass;
    unsigned char *lev = (unsigned char *)pw_alloc_array(a, (size_t)n * n, 1, "atlas gutter", e);
    if (!lev) return PW_ERR_NOMEM;
    for (k = 0; k < n * n; k++) lev[k] = B->id[k] != -1;
    for (pass = 1; pass <= gutter; pass++)
        for (y = 0; y < n; y++)
            for (x = 0; x < n; x++) {
                size_t at = (size_t)y * n + x;
                if (lev[at]) continue;
                for (k = 0; k < 8; k++) {
                    int X = x + dx[k], Y = y + dy[k];
                    size_t from = (size_t)Y * n + X;
                    if (X < 0 || Y < 0 || X >= n || Y >= n || !lev[from] || lev[from] > pass) continue;
                    memcpy(B->img->px + at * B->oc, B->img->px + from * B->oc, sizeof(float) * B->oc);
                    lev[at] = (unsigned char)(pass + 1);
                    break;
                }
            }
    pw_free(a, lev);
    return PW_OK;
}

/* Baking: src's texture into an image of job->size x job->size pixels
 * with src->oc channels (allocated here), through the per-corner atlas
 * coordinates uvs (m->nf * 6, v = 0 at the bottom row): every texel whose
 * centre a triangle covers, then the texels a bilinear lookup inside a
 * triangle can reach (the texture at the triangle's nearest point), then
 * job->gutter rounds of dilation. */
PW__DEF int pw_atlas_bake(const pw_atlas_job *job, const float *uvs, const pw_atlas_source *src, pw_image *out,
                          pw_err *e)
{
    const pw_alloc *a = job->a;
    const pw_trimesh *m = job->m;
    const pw_progress *prog = job->prog;
    int size = job->size, oc = src->oc;
    pw__atlas_baker B;
    int f, k, r;
    memset(&B, 0, sizeof B);
    B.fn = src->fn;
    B.user = src->user;
    B.uvs = uvs;
    B.img = out;
    B.size = size;
    B.oc = oc;
    if ((r = pw_image_alloc(a, out, size, size, oc, e))) return r;
    B.id = (int *)pw_alloc_array(a, (size_t)size * size, sizeof(int), "atlas triangle ids", e);
    if (!B.id) return PW_ERR_NOMEM;
    for (k = 0; k < size * size; k++) B.id[k] = -1;
    for (f = 0, r = PW_OK; f < m->nf && r == PW_OK; f++) {
        float p[6];
        pw__atlas_bake_px(&B, f, p);
        B.f = f;
        pw_raster_tri(p, size, size, pw__atlas_bake_texel, &B);
        if ((f & 4095) == 4095) r = pw_report(prog, 0.7f + 0.25f * (float)f / (float)m->nf, "atlas baking", e);
    }
    for (f = 0; f < m->nf && r == PW_OK; f++) pw__atlas_bake_ring(&B, f);
    if (r == PW_OK) {
        pw__atlas_bake_ring_values(&B);
        r = pw__atlas_dilate(a, &B, job->gutter, e);
    }
    pw_free(a, B.id);
    return r;
}

#endif /* PW__ATLAS_BAKE_V1 */
