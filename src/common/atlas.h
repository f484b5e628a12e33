/* atlas: texture atlases of triangle meshes — what the stages share.
 *
 * Lapped textures' §4 ("Rendering with a texture atlas", Praun et al. 2000)
 * builds its atlas "with a method similar to Maillot et al.": regions grown
 * face by face from a centre face (each a disc), whose normals stay "within
 * a certain angle from the one of the center face", with no overlap in
 * texture space, checked "using a spatial hash table"; the regions are
 * flattened and arranged in the unit square, and the texture is baked into
 * them. lapped.h bakes its pastes this way; pgp.h and lst.h bake their
 * renderings for glTF export with the same code.
 *
 * One file per stage, in the order they run (each file describes its
 * stage):
 *   atlas_charts.h  the charts: grown face by face, flattened by LSCM
 *                   (pw_atlas_charts_build);
 *   atlas_pack.h    the charts packed into the unit square at one scale
 *                   (pw_atlas_pack; pw_atlas_layout runs both);
 *   atlas_bake.h    the texture baked into the packed charts, then the
 *                   gutter (pw_atlas_bake).
 * This file holds what they share: the options every header exposes, the
 * overlap test of 2D triangles, the job they all take, and the export of
 * the result (pw_atlas_mesh makes the
 * pw_mesh, per-corner coordinates deduplicated, that the OBJ and glTF
 * writers take). */
#ifndef PW__ATLAS_V1
#define PW__ATLAS_V1

#include "base.h"
#include "mesh.h"
#include "trimesh.h"

/* ---- options ---------------------------------------------------------------- */

/* The atlas settings every header exposes (X_atlas_options: size, cone
 * angle, gutter), their defaults and ranges. */
#define PW_ATLAS_SIZE 1024
#define PW_ATLAS_CONE 60.0f
#define PW_ATLAS_GUTTER 2
#define PW_ATLAS_MIN 16
#define PW_ATLAS_MAX 8192
#define PW_ATLAS_GUTTER_MAX 64

/* Zero fields replaced by their defaults, then checked: size in
 * PW_ATLAS_MIN..PW_ATLAS_MAX, cone angle in (0, 180] degrees, gutter in
 * 1..PW_ATLAS_GUTTER_MAX and at most an eighth of the size. */
PW__DEF int pw_atlas_options(int *size, float *cone_angle, int *gutter, pw_err *e)
{
    if (!*size) *size = PW_ATLAS_SIZE;
    if (*cone_angle == 0.0f) *cone_angle = PW_ATLAS_CONE;
    if (!*gutter) *gutter = PW_ATLAS_GUTTER;
    if (*size < PW_ATLAS_MIN || *size > PW_ATLAS_MAX)
        return pw_fail(e, *size > PW_ATLAS_MAX ? PW_ERR_LIMIT : PW_ERR_INVALID, "atlas size %d is outside %d..%d",
                       *size, PW_ATLAS_MIN, PW_ATLAS_MAX);
    if (!(*cone_angle > 0.0f && *cone_angle <= 180.0f))
        return pw_fail(e, PW_ERR_INVALID, "atlas cone angle %g is outside (0, 180] degrees", (double)*cone_angle);
    if (*gutter < 0 || *gutter > PW_ATLAS_GUTTER_MAX || 8 * *gutter > *size)
        return pw_fail(e, PW_ERR_INVALID, "atlas gutter %d is outside 1..%d (and at most an eighth of the size)",
                       *gutter, PW_ATLAS_GUTTER_MAX);
    return PW_OK;
}

/* ---- 2D triangles --------------------------------------------------------- */

/* Twice the signed area of the 2D triangle t (three xy pairs), positive
 * when counter-clockwise. */
PW__DEF double pw__atlas_area2(const double *t)
{
    return (t[2] - t[0]) * (t[5] - t[1]) - (t[3] - t[1]) * (t[4] - t[0]);
}

PW__DEF int pw__atlas_finite6(const double *t)
{
    int k;
    for (k = 0; k < 6; k++)
        if (!pw_is_finite(t[k])) return 0;
    return 1;
}

/* The interval of triangle t's projections onto the axis (nx, ny). */
PW__DEF void pw__atlas_project(const double *t, double nx, double ny, double *lo, double *hi)
{
    int k;
    *lo = *hi = t[0] * nx + t[1] * ny;
    for (k = 1; k < 3; k++) {
        double d = t[2 * k] * nx + t[2 * k + 1] * ny;
        if (d < *lo) *lo = d;
        if (d > *hi) *hi = d;
    }
}

/* Do the interiors of the 2D triangles a and b overlap by more than tol?
 * Two convex polygons with disjoint interiors are separated by a line
 * through an edge of one of them, so the six edge normals decide it;
 * triangles that share an edge or a vertex touch without overlapping. */
PW__DEF int pw__atlas_tris_overlap(const double *a, const double *b, double tol)
{
    const double *t[2];
    int s, k;
    t[0] = a;
    t[1] = b;
    for (s = 0; s < 2; s++)
        for (k = 0; k < 3; k++) {
            const double *p = t[s] + 2 * k, *q = t[s] + 2 * ((k + 1) % 3);
            double nx = q[1] - p[1], ny = p[0] - q[0], len = sqrt(nx * nx + ny * ny);
            double alo, ahi, blo, bhi;
            if (!(len > 0.0)) continue;
            pw__atlas_project(a, nx, ny, &alo, &ahi);
            pw__atlas_project(b, nx, ny, &blo, &bhi);
            if (ahi <= blo + tol * len || bhi <= alo + tol * len) return 0;
        }
    return 1;
}

/* ---- the job ----------------------------------------------------------------- */

/* One atlas of a mesh: the allocator, the mesh m, the charts' cone (in
 * degrees), the image's size (size x size pixels) and gutter (pixels
 * between charts), and the progress; what pw_atlas_layout, pw_atlas_pack
 * and pw_atlas_bake share. */
typedef struct pw_atlas_job {
    const pw_alloc *a;
    const pw_trimesh *m;
    float cone;
    int size, gutter;
    const pw_progress *prog;
} pw_atlas_job;

/* ---- export ------------------------------------------------------------------- */

/* Deduplicated texture coordinates: index of each corner's (u, v) in the
 * list of distinct pairs, in order of first appearance (open addressing
 * on the pairs' bits). */
PW__DEF int pw__atlas_dedup_uvs(const pw_alloc *a, const float *uvs, int nc, pw_mesh *pm, pw_err *e)
{
    float *uv = pm->uv;
    int *fuv = pm->fuv;
    size_t cap = 16, mask, k;
    int *slot, c, n = 0;
    while (cap < 2 * (size_t)nc) cap <<= 1;
    mask = cap - 1;
    slot = (int *)pw_alloc_array(a, cap, sizeof(int), "OBJ texture coordinates", e);
    if (!slot) return PW_ERR_NOMEM;
    for (k = 0; k < cap; k++) slot[k] = -1;
    for (c = 0; c < nc; c++) {
        uint32_t bu, bv;
        memcpy(&bu, uvs + 2 * c, 4);
        memcpy(&bv, uvs + 2 * c + 1, 4);
        for (k = ((size_t)bu * 2654435761u ^ (size_t)bv * 40503u) & mask;; k = (k + 1) & mask) {
            int s = slot[k];
            if (s < 0) {
                slot[k] = n;
                uv[2 * n] = uvs[2 * c];
                uv[2 * n + 1] = uvs[2 * c + 1];
                fuv[c] = n++;
                break;
            }
            if (!memcmp(uv + 2 * s, uvs + 2 * c, 2 * sizeof(float))) {
                fuv[c] = s;
                break;
            }
        }
    }
    pw_free(a, slot);
    pm->nuv = n;
    return PW_OK;
}

/* The triangulated mesh with per-corner atlas coordinates uvs (m->nf * 6) as
 * a pw_mesh for the OBJ and glTF writers (positions borrowed); free fstart,
 * uv and fuv. */
PW__DEF int pw_atlas_mesh(const pw_alloc *a, const pw_trimesh *m, const float *uvs, pw_mesh *pm, pw_err *e)
{
    int f, k;
    memset(pm, 0, sizeof *pm);
    for (k = 0; k < 6 * m->nf; k++)
        if (!pw_is_finite(uvs[k]))
            return pw_fail(e, PW_ERR_INVALID, "atlas: coordinate %d of triangle %d is not finite", k % 6, k / 6);
    pm->nv = m->nv;
    pm->pos = (float *)m->pos;
    pm->nf = m->nf;
    pm->fv = m->tri;
    pm->fstart = (int *)pw_alloc_array(a, (size_t)m->nf + 1, sizeof(int), "OBJ faces", e);
    pm->uv = (float *)pw_alloc_array(a, (size_t)m->nf * 6, sizeof(float), "OBJ texture coordinates", e);
    pm->fuv = (int *)pw_alloc_array(a, (size_t)m->nf * 3, sizeof(int), "OBJ texture coordinates", e);
    if (!pm->fstart || !pm->uv || !pm->fuv) return PW_ERR_NOMEM;
    for (f = 0; f <= m->nf; f++) pm->fstart[f] = 3 * f;
    return pw__atlas_dedup_uvs(a, uvs, 3 * m->nf, pm, e);
}

#endif /* PW__ATLAS_V1 */
