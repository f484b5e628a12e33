/* trimesh: the triangle mesh that the surface methods (lapped, pgp) work on:
 * the fan triangulation of a polygon mesh (polygon corners 0, k, k+1, in
 * order, so triangle indices are stable and documented), its half-edges
 * (h = 3f+k runs from tri[3f+k] to tri[3f+(k+1)%3]; twin -1 on a
 * boundary), unit normals, areas and the bounding-box diagonal. */
#ifndef PW__TRIMESH_V1
#define PW__TRIMESH_V1

#include "base.h"
#include "vec.h"
#include "mesh.h"
#include "halfedge.h"

typedef struct pw_trimesh {
    int nv, nf;       /* vertices, triangles */
    const float *pos; /* nv*3, borrowed */
    int *tri;         /* nf*3 */
    pw_hmesh hm;
    float *normal; /* nf*3 */
    float *area;   /* nf */
    double total_area;
    float diag; /* bounding-box diagonal */
} pw_trimesh;

PW__DEF void pw_trimesh_free(const pw_alloc *a, pw_trimesh *m)
{
    pw_free(a, m->tri);
    pw_hmesh_free(a, &m->hm);
    pw_free(a, m->normal);
    pw_free(a, m->area);
    memset(m, 0, sizeof *m);
}

PW__DEF pw_v3 pw_trimesh_vert(const pw_trimesh *m, int v) { return pw_v3_load(m->pos + 3 * v); }

/* Corner k of triangle f. */
PW__DEF pw_v3 pw_trimesh_corner(const pw_trimesh *m, int f, int k) { return pw_trimesh_vert(m, m->tri[3 * f + k]); }

/* The triangle across edge k of triangle f (-1 on a boundary). */
PW__DEF int pw_trimesh_across(const pw_trimesh *m, int f, int k)
{
    int t = m->hm.twin[3 * f + k];
    return t < 0 ? -1 : t / 3;
}

/* Degenerate triangles (needles, caps, collinear or coincident corners):
 * area below 1e-5 of the squared longest edge, or an angle whose sine is
 * below sin 0.1 deg = 1.745e-3. Their own plane, normal and linear maps
 * are numerically meaningless (a scan's near-collinear triple has a plane
 * set by its noise), so methods that parametrise treat them apart. */
#define PW_TRIMESH_SLIVER_AREA 1e-5
#define PW_TRIMESH_SLIVER_SINE 1.745e-3

PW__DEF int pw_trimesh_sliver(const pw_trimesh *m, int f)
{
    double l2[3], cr2, longest = 0.0;
    pw_v3 p[3], e1, e2, n;
    int k;
    for (k = 0; k < 3; k++) p[k] = pw_trimesh_corner(m, f, k);
    for (k = 0; k < 3; k++) {
        pw_v3 d = pw_v3_sub(p[(k + 1) % 3], p[k]);
        l2[k] = (double)d.x * d.x + (double)d.y * d.y + (double)d.z * d.z;
        if (l2[k] > longest) longest = l2[k];
    }
    e1 = pw_v3_sub(p[1], p[0]);
    e2 = pw_v3_sub(p[2], p[0]);
    n = pw_v3_cross(e1, e2);
    cr2 = (double)n.x * n.x + (double)n.y * n.y + (double)n.z * n.z; /* (2 area)^2 */
    if (!(cr2 >= 4.0 * PW_TRIMESH_SLIVER_AREA * PW_TRIMESH_SLIVER_AREA * longest * longest)) return 1;
    for (k = 0; k < 3; k++) /* sin^2 of the angle at corner k+1 (between edges k and k+1) */
        if (cr2 < PW_TRIMESH_SLIVER_SINE * PW_TRIMESH_SLIVER_SINE * l2[k] * l2[(k + 1) % 3]) return 1;
    return 0;
}

/* Normals, areas and the bounding box. Zero-area triangles are refused
 * (neither a tangent field nor a parametrisation is defined on them)
 * unless keep_degenerate, which gives them area 0 and a zero normal that
 * pw_trimesh_repair_normals fills. */
PW__DEF int pw__trimesh_geometry(pw_trimesh *m, int keep_degenerate, pw_err *e)
{
    pw_v3 lo, hi;
    int f, v;
    m->total_area = 0.0;
    for (f = 0; f < m->nf; f++) {
        pw_v3 a = pw_trimesh_corner(m, f, 0), b = pw_trimesh_corner(m, f, 1), c = pw_trimesh_corner(m, f, 2);
        pw_v3 n = pw_v3_cross(pw_v3_sub(b, a), pw_v3_sub(c, a));
        float len = pw_v3_len(n),
              ref = pw_v3_dot(pw_v3_sub(b, a), pw_v3_sub(b, a)) + pw_v3_dot(pw_v3_sub(c, a), pw_v3_sub(c, a));
        int zero = !(len > 1e-12f * ref) || !(len > 0.0f);
        if (zero && !(keep_degenerate && pw_is_finite(len) && pw_is_finite(ref)))
            return pw_fail(e, PW_ERR_DEGENERATE, "triangle %d (vertices %d, %d, %d) has zero area", f, m->tri[3 * f],
                           m->tri[3 * f + 1], m->tri[3 * f + 2]);
        pw_v3_store(m->normal + 3 * f, zero ? pw_v3_make(0, 0, 0) : pw_v3_scale(n, 1.0f / len));
        m->area[f] = zero ? 0.0f : 0.5f * len;
        m->total_area += m->area[f];
    }
    if (!(m->total_area > 0.0)) return pw_fail(e, PW_ERR_DEGENERATE, "every triangle of the mesh has zero area");
    lo = hi = pw_trimesh_vert(m, m->tri[0]);
    for (v = 0; v < 3 * m->nf; v++) {
        lo = pw_v3_min(lo, pw_trimesh_vert(m, m->tri[v]));
        hi = pw_v3_max(hi, pw_trimesh_vert(m, m->tri[v]));
    }
    m->diag = pw_v3_len(pw_v3_sub(hi, lo));
    return PW_OK;
}

/* One pass of pw_trimesh_repair_normals: each degenerate triangle not yet
 * done (done[f] == 0) whose neighbours include done ones takes their mean
 * normal; returns how many were done in this pass. */
PW__DEF int pw__trimesh_repair_pass(pw_trimesh *m, unsigned char *done, int pass)
{
    int f, k, n = 0;
    for (f = 0; f < m->nf; f++) {
        pw_v3 sum = pw_v3_make(0, 0, 0);
        if (done[f]) continue;
        for (k = 0; k < 3; k++) {
            int g = pw_trimesh_across(m, f, k);
            if (g >= 0 && done[g] && done[g] < pass) sum = pw_v3_add(sum, pw_v3_load(m->normal + 3 * g));
        }
        if (!(pw_v3_len(sum) > 1e-6f)) continue;
        pw_v3_store(m->normal + 3 * f, pw_v3_norm(sum));
        done[f] = (unsigned char)pass;
        n++;
    }
    return n;
}

/* Degenerate triangles (pw_trimesh_sliver) take the mean normal of their
 * nearest non-degenerate neighbours, pass by pass outwards; a component
 * made only of them keeps its own normals, and a zero normal left after
 * that is an error naming the triangle. */
PW__DEF int pw_trimesh_repair_normals(const pw_alloc *a, pw_trimesh *m, pw_err *e)
{
    unsigned char *done = (unsigned char *)pw_alloc_array(a, (size_t)m->nf, 1, "degenerate triangles", e);
    int f, pass = 2, r = PW_OK;
    if (!done) return PW_ERR_NOMEM;
    for (f = 0; f < m->nf; f++) done[f] = (unsigned char)!pw_trimesh_sliver(m, f);
    while (pass < 250 && pw__trimesh_repair_pass(m, done, pass) > 0) pass++;
    for (f = 0; f < m->nf && r == PW_OK; f++)
        if (!(pw_v3_len(pw_v3_load(m->normal + 3 * f)) > 0.5f))
            r = pw_fail(e, PW_ERR_DEGENERATE,
                        "triangle %d (vertices %d, %d, %d) has zero area and no "
                        "neighbour with a normal",
                        f, m->tri[3 * f], m->tri[3 * f + 1], m->tri[3 * f + 2]);
    pw_free(a, done);
    return r;
}

/* Fan-triangulates a polygon mesh (positions borrowed: they must outlive
 * the trimesh) and builds adjacency and geometry. Non-manifold or
 * inconsistently oriented meshes and zero-area triangles are errors that
 * name the element; with keep_degenerate, zero-area triangles are kept
 * (area 0) and every degenerate triangle takes its neighbours' normal. */
/* The validated mesh's faces as fans of triangles, and nothing else (no
 * adjacency, normals or areas): what drawing needs. */
PW__DEF int pw_trimesh_init_tris(const pw_alloc *a, const pw_mesh *in, pw_trimesh *m, pw_err *e)
{
    int f, k, t = 0, r;
    memset(m, 0, sizeof *m);
    if (!in->pos || !in->fstart || !in->fv) return pw_fail(e, PW_ERR_INVALID, "mesh has NULL arrays");
    if (in->nf < 1) return pw_fail(e, PW_ERR_DEGENERATE, "mesh has no faces");
    if ((r = pw_mesh_validate(in, e)) != PW_OK) return r;
    m->nv = in->nv;
    m->pos = in->pos;
    m->nf = in->fstart[in->nf] - 2 * in->nf;
    m->tri = (int *)pw_alloc_array(a, (size_t)m->nf * 3, sizeof(int), "triangles", e);
    if (!m->tri) return PW_ERR_NOMEM;
    for (f = 0; f < in->nf; f++)
        for (k = in->fstart[f] + 1; k + 1 < in->fstart[f + 1]; k++, t++) {
            m->tri[3 * t] = in->fv[in->fstart[f]];
            m->tri[3 * t + 1] = in->fv[k];
            m->tri[3 * t + 2] = in->fv[k + 1];
        }
    return PW_OK;
}

PW__DEF int pw_trimesh_init_ex(const pw_alloc *a, const pw_mesh *in, int keep_degenerate, pw_trimesh *m, pw_err *e)
{
    int f, r, *fs;
    if ((r = pw_trimesh_init_tris(a, in, m, e)) != PW_OK) return r;
    m->normal = (float *)pw_alloc_array(a, (size_t)m->nf * 3, sizeof(float), "normals", e);
    m->area = (float *)pw_alloc_array(a, (size_t)m->nf, sizeof(float), "areas", e);
    fs = (int *)pw_alloc_array(a, (size_t)m->nf + 1, sizeof(int), "triangle offsets", e);
    if (!m->normal || !m->area || !fs) r = PW_ERR_NOMEM;
    for (f = 0; r == PW_OK && f <= m->nf; f++) fs[f] = 3 * f;
    if (r == PW_OK) r = pw_hmesh_build(a, m->nv, m->nf, fs, m->tri, &m->hm, e);
    if (r == PW_OK) r = pw__trimesh_geometry(m, keep_degenerate, e);
    if (r == PW_OK && keep_degenerate) r = pw_trimesh_repair_normals(a, m, e);
    pw_free(a, fs);
    if (r != PW_OK) pw_trimesh_free(a, m);
    return r;
}

PW__DEF int pw_trimesh_init(const pw_alloc *a, const pw_mesh *in, pw_trimesh *m, pw_err *e)
{
    return pw_trimesh_init_ex(a, in, 0, m, e);
}

#endif /* PW__TRIMESH_V1 */
