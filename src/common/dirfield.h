/* dirfield: direction fields on a triangle mesh, one direction per
 * triangle, shared by the surface methods (lapped §3.2, pgp §2.2).
 *
 * A direction is a complex number in the triangle's own frame (u = first
 * edge, v = N x u), so that moving a direction to a neighbour is one complex
 * product: the connection conn[h] of half-edge h unfolds the neighbour
 * about the shared edge into this triangle's plane (a rotation about the
 * edge: the identity for a flat pair, the discrete Levi-Civita transport
 * otherwise). Line fields (directions up to sign: principal curvature
 * directions) use the square (angle doubling) of the same numbers.
 *
 * Pieces: frames and the connection; projection of a global direction;
 * breadth-first filling of unknown directions from known ones; the field
 * of least absolute curvature (Rusinkiewicz 2004), smoothed and oriented;
 * Dijkstra distances over the dual graph (centroid - edge midpoint -
 * centroid) with a deterministic heap.
 *
 * Determinism: only + - * / and sqrt; pw_df_exp_neg replaces libm's exp. */
#ifndef PW__DIRFIELD_V1
#define PW__DIRFIELD_V1

#include "base.h"
#include "vec.h"
#include "trimesh.h"
#include "heap.h"

/* e^-x for x >= 0 from + - * / and an exact power of two: x = n ln2 - r
 * with |r| <= ln2/2, e^r by its Taylor series to r^14 (truncation below
 * 5e-18), then scaled by 2^-n with ldexp (exact). Relative error below 3e-16
 * against libm over [0, 700], and the same bits on every IEEE platform,
 * unlike libm's exp. Returns 0 beyond e^-700 and for NaN. */
PW__DEF double pw_df_exp_neg(double x)
{
    static const double inv[15] = {0.0,     1.0,     1.0 / 2,  1.0 / 3,  1.0 / 4,  1.0 / 5,  1.0 / 6, 1.0 / 7,
                                   1.0 / 8, 1.0 / 9, 1.0 / 10, 1.0 / 11, 1.0 / 12, 1.0 / 13, 1.0 / 14};
    /* ln 2 split as in fdlibm: n * hi is exact for n < 2^20 */
    const double hi = 6.93147180369123816490e-01, lo = 1.90821492927058770002e-10;
    double r, p = 1.0;
    int n, i;
    if (!(x < 700.0)) return 0.0;
    if (x < 0.0) x = 0.0;
    n = (int)(x * 1.44269504088896338700 + 0.5);
    r = ((double)n * hi - x) + (double)n * lo;
    for (i = 14; i >= 1; i--) p = 1.0 + p * r * inv[i]; /* Horner: 1 + r(1 + r/2(1 + ...)) */
    return ldexp(p, -n);
}

/* ---- frames, transport and small numerics -------------------------------- */

PW__DEF pw_v3 pw_df_normal(const pw_trimesh *m, int f) { return pw_v3_load(m->normal + 3 * f); }

PW__DEF pw_v3 pw_df_centroid(const pw_trimesh *m, int f)
{
    pw_v3 c = pw_v3_add(pw_v3_add(pw_trimesh_corner(m, f, 0), pw_trimesh_corner(m, f, 1)), pw_trimesh_corner(m, f, 2));
    return pw_v3_scale(c, 1.0f / 3.0f);
}

/* Surface distance between the triangles on either side of half-edge h
 * (which must have a twin): centroid to the edge's midpoint to centroid. */
PW__DEF double pw_df_dual_len(const pw_trimesh *m, int h)
{
    int f = h / 3, k = h % 3;
    pw_v3 mid = pw_v3_add(pw_trimesh_corner(m, f, k), pw_trimesh_corner(m, f, (k + 1) % 3));
    mid = pw_v3_scale(mid, 0.5f);
    return (double)pw_v3_len(pw_v3_sub(mid, pw_df_centroid(m, f))) +
           (double)pw_v3_len(pw_v3_sub(pw_df_centroid(m, m->hm.twin[h] / 3), mid));
}

/* The frame of triangle f: u along its first edge, v = N x u. A degenerate
 * triangle whose normal came from its neighbours (pw_trimesh_repair_normals)
 * may have edges off that plane, or none at all: u is then the first edge
 * that keeps a tangent part, projected, else the axis least aligned with N. */
PW__DEF void pw_df_frame(const pw_trimesh *m, int f, pw_v3 *u, pw_v3 *v)
{
    pw_v3 n = pw_df_normal(m, f), e = pw_v3_sub(pw_trimesh_corner(m, f, 1), pw_trimesh_corner(m, f, 0)), t;
    int k;
    float el = pw_v3_len(e);
    if (!(el > 0.0f) || fabsf(pw_v3_dot(e, n)) > 1e-3f * el) {
        for (k = 0, e = pw_v3_make(0, 0, 0); k < 3 && !(pw_v3_len(e) > 1e-3f * el); k++) {
            t = pw_v3_sub(pw_trimesh_corner(m, f, (k + 1) % 3), pw_trimesh_corner(m, f, k));
            el = pw_v3_len(t);
            e = pw_v3_sub(t, pw_v3_scale(n, pw_v3_dot(t, n)));
        }
        if (!(pw_v3_len(e) > 1e-3f * el) || !(el > 0.0f)) { /* no edge has a tangent part */
            k = fabsf(n.x) <= fabsf(n.y) && fabsf(n.x) <= fabsf(n.z) ? 0 : (fabsf(n.y) <= fabsf(n.z) ? 1 : 2);
            t = pw_v3_make(k == 0, k == 1, k == 2);
            e = pw_v3_sub(t, pw_v3_scale(n, pw_v3_dot(t, n)));
        }
    }
    *u = pw_v3_norm(e);
    *v = pw_v3_cross(n, *u);
}

/* Tangent vector x of the triangle across half-edge h, unfolded about the
 * shared edge into the plane of h's own triangle: the rotation about the
 * edge that takes one normal to the other. */
PW__DEF pw_v3 pw_df_hinge(const pw_trimesh *m, int h, pw_v3 x)
{
    int f = h / 3, g = m->hm.twin[h] / 3, k = h % 3;
    pw_v3 ed = pw_v3_norm(pw_v3_sub(pw_trimesh_corner(m, f, (k + 1) % 3), pw_trimesh_corner(m, f, k)));
    pw_v3 nf = pw_df_normal(m, f), ng = pw_df_normal(m, g);
    pw_v3 r = pw_v3_scale(ed, pw_v3_dot(x, ed));
    r = pw_v3_add(r, pw_v3_scale(pw_v3_cross(nf, ed), pw_v3_dot(x, pw_v3_cross(ng, ed))));
    return pw_v3_add(r, pw_v3_scale(nf, pw_v3_dot(x, ng)));
}

/* Scales z to unit length; returns 0 (and leaves z) if it is zero. */
PW__DEF int pw_df_unit(double *z)
{
    double l = sqrt(z[0] * z[0] + z[1] * z[1]);
    if (!(l > 0.0) || !pw_is_finite(l)) return 0;
    z[0] /= l;
    z[1] /= l;
    return 1;
}

/* The shared edge of half-edge h as a complex number in the frame of
 * triangle f (either side of the edge). */
PW__DEF void pw_df_edge_in(const pw_trimesh *m, int h, int f, double *w)
{
    int k = h % 3, g = h / 3;
    pw_v3 u, v, ed = pw_v3_sub(pw_trimesh_corner(m, g, (k + 1) % 3), pw_trimesh_corner(m, g, k));
    pw_df_frame(m, f, &u, &v);
    w[0] = pw_v3_dot(ed, u);
    w[1] = pw_v3_dot(ed, v);
}

/* conn[2h], conn[2h+1]: the rotation taking directions of the triangle
 * across h into h's own triangle frame, so that a direction (x, y) over
 * there is (x, y) * conn[h] here (complex product). It is the unfolding
 * about the shared edge (pw_df_hinge): the edge keeps its angle to
 * every vector, so with the edge at angle a_f here and a_g there,
 * conn = e^{i (a_f - a_g)}. Boundary half-edges get 1. */
PW__DEF int pw_df_connection(const pw_alloc *a, const pw_trimesh *m, float **out, pw_err *e)
{
    float *c = (float *)pw_alloc_array(a, (size_t)m->nf * 6, sizeof(float), "field connection", e);
    int h;
    *out = c;
    if (!c) return PW_ERR_NOMEM;
    for (h = 0; h < 3 * m->nf; h++) {
        double wf[2], wg[2], z[2] = {1.0, 0.0};
        if (m->hm.twin[h] >= 0) {
            pw_df_edge_in(m, h, h / 3, wf);
            pw_df_edge_in(m, h, m->hm.twin[h] / 3, wg);
            z[0] = wf[0] * wg[0] + wf[1] * wg[1]; /* wf * conj(wg) */
            z[1] = wf[1] * wg[0] - wf[0] * wg[1];
            if (!pw_df_unit(z)) {
                z[0] = 1.0;
                z[1] = 0.0;
            }
        }
        c[2 * h] = (float)z[0];
        c[2 * h + 1] = (float)z[1];
    }
    return PW_OK;
}

/* z (a direction of the neighbour across h) transported into h's triangle;
 * power 2 for line fields (doubled angles). */
PW__DEF void pw_df_move(const float *conn, int h, int power, const double *z, double *out)
{
    double cx = conn[2 * h], cy = conn[2 * h + 1], t;
    if (power == 2) {
        t = cx * cx - cy * cy;
        cy = 2.0 * cx * cy;
        cx = t;
    }
    out[0] = z[0] * cx - z[1] * cy;
    out[1] = z[0] * cy + z[1] * cx;
}

/* Doubles the angle of a unit direction (vector -> line field). */
PW__DEF void pw_df_square(double *z)
{
    double x = z[0] * z[0] - z[1] * z[1];
    z[1] = 2.0 * z[0] * z[1];
    z[0] = x;
}

/* Halves the angle of a unit doubled-angle number with sqrt only (no atan2),
 * giving the direction in (-90, 90] degrees. */
PW__DEF void pw_df_halve(double *z)
{
    double c = z[0] < -1.0 ? -1.0 : (z[0] > 1.0 ? 1.0 : z[0]);
    double x = sqrt(0.5 * (1.0 + c)), y = sqrt(0.5 * (1.0 - c));
    z[0] = x;
    z[1] = z[1] < 0.0 ? -y : y;
}

/* The 3D direction d projected onto triangle f, as a unit direction in its
 * frame. Returns 0 when d is (within 1e-4 radians) normal to the face:
 * "project the global up direction onto the surface" has no answer there.
 * pw_df_project_tilt: the same with the bound on the squared sine of the
 * angle between d and the face plane given. */
PW__DEF int pw_df_project_tilt(const pw_trimesh *m, int f, pw_v3 d, double sin2, double *z)
{
    pw_v3 u, v;
    double l2 = (double)pw_v3_dot(d, d);
    pw_df_frame(m, f, &u, &v);
    z[0] = pw_v3_dot(d, u);
    z[1] = pw_v3_dot(d, v);
    if (!(z[0] * z[0] + z[1] * z[1] > sin2 * l2)) return 0;
    return pw_df_unit(z);
}

PW__DEF int pw_df_project(const pw_trimesh *m, int f, pw_v3 d, double *z)
{
    return pw_df_project_tilt(m, f, d, 1e-8, z);
}

/* A fixed direction for triangle f when nothing else defines one: the
 * coordinate axis least aligned with its normal (lowest axis on ties),
 * projected; never degenerate (at least sqrt(2/3) of it is tangent). */
PW__DEF void pw_df_axis(const pw_trimesh *m, int f, double *z)
{
    const float *n = m->normal + 3 * f;
    int k = 0, i;
    float ax[3] = {0.0f, 0.0f, 0.0f};
    for (i = 1; i < 3; i++)
        if (fabsf(n[i]) < fabsf(n[k])) k = i;
    ax[k] = 1.0f;
    if (!pw_df_project(m, f, pw_v3_load(ax), z)) {
        z[0] = 1.0;
        z[1] = 0.0;
    }
}

/* Where propagation stops (pw_df_up_creased): half-edges marked in `edge`
 * (nf*3) are not crossed, and `sin2` is the squared sine of the tilt below
 * which up does not define a direction. NULL: every edge is crossed, and
 * the tilt bound is 1e-4 radians. */
typedef struct pw_df_cut {
    const unsigned char *edge;
    double sin2;
} pw_df_cut;

/* A direction field being built on a mesh: z (nf*2) holds each triangle's
 * direction in its frame (pw_df_frame), conn (pw_df_connection) carries
 * directions across edges, and known (nf) marks the triangles whose
 * direction is given rather than propagated. The fill and relax steps below
 * all work on the same three arrays, so they travel together. */
typedef struct pw_df_field {
    const pw_trimesh *m;
    const float *conn;
    double *z;
    unsigned char *known;
} pw_df_field;

/* One breadth-first propagation (pw_df_fill_cut): the field, how directions
 * are seeded and carried (power 2: doubled angles; up; the cut or NULL),
 * and the work arrays: level (nf; -1 not reached yet), the queue (nf) with
 * its tail, and a stack (nf) for flooding a component. */
typedef struct pw_df_prop {
    const pw_df_field *F;
    int power;
    pw_v3 up;
    const pw_df_cut *cut;
    int *level, *queue, *stack;
    int tail;
} pw_df_prop;

/* The triangle across edge k of f, or -1 on a boundary or a cut. */
PW__DEF int pw_df_across(const pw_trimesh *m, const pw_df_cut *cut, int f, int k)
{
    return cut && cut->edge[3 * f + k] ? -1 : pw_trimesh_across(m, f, k);
}

/* Seeds a component in which no triangle has a direction yet (level -1 from
 * `start` on): every triangle where `up` projects gets that projection, as
 * in the up field; if none does (a flat piece normal to up), the lowest
 * triangle gets the fixed axis. Seeds go to the queue with level 0. */
PW__DEF void pw_df_seed(pw_df_prop *P, int start)
{
    const pw_trimesh *m = P->F->m;
    const pw_df_cut *cut = P->cut;
    double *z = P->F->z;
    int *level = P->level, *queue = P->queue, *stack = P->stack, power = P->power;
    pw_v3 up = P->up;
    int top = 1, n = 0, i, k, f, g, seeded = 0;
    stack[0] = start;
    level[start] = -2;
    while (n < top) { /* flood the component, in a deterministic order */
        f = stack[n++];
        for (k = 0; k < 3; k++)
            if ((g = pw_df_across(m, cut, f, k)) >= 0 && level[g] == -1) {
                level[g] = -2;
                stack[top++] = g;
            }
    }
    for (i = 0; i < top; i++) {
        f = stack[i];
        level[f] = -1;
        if (pw_df_project_tilt(m, f, up, cut ? cut->sin2 : 1e-8, z + 2 * f)) {
            if (power == 2) pw_df_square(z + 2 * f);
            level[f] = 0;
            queue[P->tail++] = f;
            seeded = 1;
        }
    }
    if (!seeded) {
        pw_df_axis(m, start, z + 2 * start);
        if (power == 2) pw_df_square(z + 2 * start);
        level[start] = 0;
        queue[P->tail++] = start;
    }
}

/* Triangle f's direction from its neighbours one level closer to the known
 * ones: the unit average of their directions transported into f (§3.2
 * propagation: "projecting onto its face plane the average direction of
 * neighboring faces"); the first neighbour's if the average cancels. */
PW__DEF void pw_df_average(const pw_df_prop *P, int f)
{
    const pw_trimesh *m = P->F->m;
    const float *conn = P->F->conn;
    const pw_df_cut *cut = P->cut;
    const int *level = P->level;
    double *z = P->F->z;
    int power = P->power;
    double sum[2] = {0.0, 0.0}, first[2] = {0.0, 0.0}, w[2];
    int k, g, n = 0;
    for (k = 0; k < 3; k++) {
        g = pw_df_across(m, cut, f, k);
        if (g < 0 || level[g] < 0 || level[g] >= level[f]) continue;
        pw_df_move(conn, 3 * f + k, power, z + 2 * g, w);
        if (n++ == 0) {
            first[0] = w[0];
            first[1] = w[1];
        }
        sum[0] += w[0];
        sum[1] += w[1];
    }
    if (!(sum[0] * sum[0] + sum[1] * sum[1] > 1e-12)) {
        sum[0] = first[0];
        sum[1] = first[1];
    }
    if (!pw_df_unit(sum)) {
        sum[0] = 1.0;
        sum[1] = 0.0;
    }
    z[2 * f] = sum[0];
    z[2 * f + 1] = sum[1];
}

/* Gives every triangle with known[f] == 0 a unit direction (z, nf*2, in
 * the triangle frames; power 2: doubled angles) by breadth-first propagation
 * from the known ones, layer by layer, so that the result does not depend
 * on which known triangle is met first. Components without a known triangle
 * are seeded by pw_df_seed. Known directions must be unit. With a cut
 * (pw_df_cut), propagation does not cross its edges. */
PW__DEF int pw_df_fill_cut(const pw_alloc *a, const pw_df_field *F, int power, pw_v3 up, const pw_df_cut *cut,
                           pw_err *e)
{
    const pw_trimesh *m = F->m;
    const unsigned char *known = F->known;
    int *level = (int *)pw_alloc_array(a, (size_t)m->nf * 3, sizeof(int), "field propagation", e);
    int head = 0, next = 0, f, k, g;
    pw_df_prop P;
    if (!level) return PW_ERR_NOMEM;
    P.F = F;
    P.power = power;
    P.up = up;
    P.cut = cut;
    P.level = level;
    P.queue = level + m->nf;
    P.stack = P.queue + m->nf;
    P.tail = 0;
    for (f = 0; f < m->nf; f++) {
        level[f] = known[f] ? 0 : -1;
        if (known[f]) P.queue[P.tail++] = f;
    }
    for (;;) {
        if (head == P.tail) {
            while (next < m->nf && level[next] >= 0) next++;
            if (next == m->nf) break;
            pw_df_seed(&P, next);
        }
        f = P.queue[head++];
        if (level[f] > 0) pw_df_average(&P, f);
        for (k = 0; k < 3; k++)
            if ((g = pw_df_across(m, cut, f, k)) >= 0 && level[g] == -1) {
                level[g] = level[f] + 1;
                P.queue[P.tail++] = g;
            }
    }
    pw_free(a, level);
    return PW_OK;
}

PW__DEF int pw_df_fill(const pw_alloc *a, const pw_df_field *F, int power, pw_v3 up, pw_err *e)
{
    return pw_df_fill_cut(a, F, power, up, NULL, e);
}

/* §3.2: "project the global up direction onto the surface, and then
 * normalize". Where up is normal to a triangle (the top of a box, a pole)
 * the projection is undefined: such triangles take the average of their
 * neighbours' directions, unfolded into their plane, by propagation; a
 * component that is entirely normal to up (a flat sheet) uses a fixed axis
 * (pw_df_axis). ISOTROPIC uses the same field: growth replaces the
 * orientation by its own propagation, and a smooth start keeps the
 * discontinuity part of lapped__difficulty quiet. */
PW__DEF int pw_df_up(const pw_alloc *a, const pw_df_field *F, pw_v3 up, pw_err *e)
{
    int f;
    for (f = 0; f < F->m->nf; f++) F->known[f] = (unsigned char)pw_df_project(F->m, f, up, F->z + 2 * f);
    return pw_df_fill(a, F, 1, up, e);
}

/* The up field without bullseyes. Where up is (nearly) normal to the
 * surface - a box top, a floor, a pole - the projection has no direction,
 * and a field on a closed surface needs singularities of total index 2
 * somewhere there. Breadth-first propagation from the sides (pw_df_up)
 * puts it in the middle of a flat top and draws its layers as rings with
 * creases along the medial axis. Here:
 *   - triangles tilted less than PW_DF_UP_TILT degrees take no direction
 *     from up (noise on a scanned floor would otherwise decide it);
 *   - propagation does not cross edges sharper than PW_DF_UP_CREASE
 *     degrees, so a flat up-facing region bounded by creases is a
 *     component of its own, seeded once and transported across unchanged
 *     (uniform on a plane: the singularity sits on the crease);
 *   - the directions propagated into an up-facing region that no crease
 *     bounds (a smooth cap: a pole, the top of a head) are relaxed by
 *     Gauss-Seidel sweeps of the connection Laplacian (each the mean of
 *     its neighbours transported, not normalised), the discrete harmonic
 *     extension of its border, whose one zero is a clean point
 *     singularity instead of the propagation's layers. */
#define PW_DF_UP_TILT 8.0
#define PW_DF_UP_CREASE 30.0
#define PW_DF_UP_SWEEPS 200

/* cut[h] for every half-edge whose dihedral angle exceeds PW_DF_UP_CREASE. */
PW__DEF void pw_df_creases(const pw_trimesh *m, unsigned char *cut)
{
    double c = cos(PW_DF_UP_CREASE * 3.14159265358979323846 / 180.0);
    int h;
    for (h = 0; h < 3 * m->nf; h++) {
        int t = m->hm.twin[h];
        cut[h] = (unsigned char)(t >= 0 && pw_v3_dot(pw_df_normal(m, h / 3), pw_df_normal(m, t / 3)) < c);
    }
}

/* One Gauss-Seidel sweep over the triangles not known: each becomes the
 * mean of its uncut neighbours' directions transported into it. */
PW__DEF void pw_df_relax(const pw_df_field *F, const pw_df_cut *cut)
{
    const pw_trimesh *m = F->m;
    const float *conn = F->conn;
    const unsigned char *known = F->known;
    double *z = F->z;
    int f, k, g;
    for (f = 0; f < m->nf; f++) {
        double sum[2] = {0.0, 0.0}, w[2];
        int n = 0;
        if (known[f]) continue;
        for (k = 0; k < 3; k++) {
            if ((g = pw_df_across(m, cut, f, k)) < 0) continue;
            pw_df_move(conn, 3 * f + k, 1, z + 2 * g, w);
            sum[0] += w[0];
            sum[1] += w[1];
            n++;
        }
        if (n > 0 && sum[0] * sum[0] + sum[1] * sum[1] > 0.0) {
            z[2 * f] = sum[0] / n;
            z[2 * f + 1] = sum[1] / n;
        }
    }
}

PW__DEF int pw_df_up_creased(const pw_alloc *a, const pw_df_field *F, pw_v3 up, pw_err *e)
{
    const pw_trimesh *m = F->m;
    double *z = F->z;
    unsigned char *edge = (unsigned char *)pw_alloc_array(a, (size_t)m->nf * 3, 1, "field creases", e);
    double st = sin(PW_DF_UP_TILT * 3.14159265358979323846 / 180.0);
    pw_df_cut cut;
    int f, i, r;
    if (!edge) return PW_ERR_NOMEM;
    pw_df_creases(m, edge);
    cut.edge = edge;
    cut.sin2 = st * st;
    for (f = 0; f < m->nf; f++) F->known[f] = (unsigned char)pw_df_project_tilt(m, f, up, cut.sin2, z + 2 * f);
    r = pw_df_fill_cut(a, F, 1, up, &cut, e);
    for (i = 0; r == PW_OK && i < PW_DF_UP_SWEEPS; i++) pw_df_relax(F, &cut);
    for (f = 0; r == PW_OK && f < m->nf; f++)
        if (!pw_df_unit(z + 2 * f)) pw_df_axis(m, f, z + 2 * f);
    pw_free(a, edge);
    return r;
}

/* Length of each dual edge: centroid to edge midpoint to centroid, a path
 * on the surface even across a crease (the straight centroid-to-centroid
 * segment would cut through it). 0 on the boundary. */
PW__DEF void pw_df_dual(const pw_trimesh *m, double *len)
{
    int h;
    for (h = 0; h < 3 * m->nf; h++) len[h] = m->hm.twin[h] < 0 ? 0.0 : pw_df_dual_len(m, h);
}

/* §3.2 "radius is defined as distance over the mesh, as computed using
 * Dijkstra's algorithm": distances over the dual graph (triangle centroids
 * joined through edge midpoints) from triangle src; DBL_MAX where
 * unreachable. The heap holds at most 3*nf+1 entries (a triangle is pushed
 * only when one of its <= 3 neighbours improves it). */
PW__DEF void pw_df_dijkstra(const pw_trimesh *m, const double *len, int src, double *dist, pw_heap *hp)
{
    int f, k, g;
    for (f = 0; f < m->nf; f++) dist[f] = DBL_MAX;
    dist[src] = 0.0;
    hp->n = 0;
    pw_heap_insert(hp, 0.0, src);
    while (hp->n > 0) {
        double d = hp->key[0];
        f = pw_heap_pop(hp);
        if (d > dist[f]) continue; /* stale entry */
        for (k = 0; k < 3; k++) {
            double nd = d + len[3 * f + k];
            if ((g = pw_trimesh_across(m, f, k)) >= 0 && nd < dist[g]) {
                dist[g] = nd;
                pw_heap_insert(hp, nd, g);
            }
        }
    }
}

/* Vertex normals with Max's weights (J. Graphics Tools 4(2), 1999): each
 * triangle's corner cross product over the squared lengths of its two
 * edges; exact on a sphere, no trigonometry. */
PW__DEF int pw_df_vertex_normals(const pw_alloc *a, const pw_trimesh *m, double **out, pw_err *e)
{
    double *vn = (double *)pw_calloc_array(a, (size_t)m->nv * 3, sizeof(double), "vertex normals", e);
    int f, i, v;
    *out = vn;
    if (!vn) return PW_ERR_NOMEM;
    for (f = 0; f < m->nf; f++)
        for (i = 0; i < 3; i++) {
            pw_v3 p = pw_trimesh_corner(m, f, i);
            pw_v3 e1 = pw_v3_sub(pw_trimesh_corner(m, f, (i + 1) % 3), p);
            pw_v3 e2 = pw_v3_sub(pw_trimesh_corner(m, f, (i + 2) % 3), p);
            pw_v3 c = pw_v3_cross(e1, e2);
            double w = 1.0 / ((double)pw_v3_dot(e1, e1) * (double)pw_v3_dot(e2, e2));
            v = m->tri[3 * f + i];
            vn[3 * v] += w * c.x;
            vn[3 * v + 1] += w * c.y;
            vn[3 * v + 2] += w * c.z;
        }
    for (v = 0; v < m->nv; v++) {
        double *p = vn + 3 * v, l = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        for (i = 0; l > 0.0 && i < 3; i++) vn[3 * v + i] /= l;
    }
    return PW_OK;
}

/* Second fundamental form [[a, b], [b, c]] of triangle f in its frame:
 * least squares over its three edges e of II e = (dn . u, dn . v), dn the
 * difference of the vertex normals along e (Rusinkiewicz 2004, eq. 5),
 * solved by Cramer's rule on the 3x3 normal equations. */
PW__DEF void pw_df_tensor(const pw_trimesh *m, const double *vn, int f, double abc[3])
{
    double suu = 0, suv = 0, svv = 0, r0 = 0, r1 = 0, r2 = 0, det;
    pw_v3 u, v;
    int i;
    pw_df_frame(m, f, &u, &v);
    for (i = 0; i < 3; i++) {
        int p = m->tri[3 * f + (i + 1) % 3], q = m->tri[3 * f + (i + 2) % 3], k;
        pw_v3 ed = pw_v3_sub(pw_trimesh_vert(m, q), pw_trimesh_vert(m, p));
        double dn[3], eu = pw_v3_dot(ed, u), ev = pw_v3_dot(ed, v), du = 0, dv = 0;
        for (k = 0; k < 3; k++) dn[k] = vn[3 * q + k] - vn[3 * p + k];
        du = dn[0] * u.x + dn[1] * u.y + dn[2] * u.z;
        dv = dn[0] * v.x + dn[1] * v.y + dn[2] * v.z;
        suu += eu * eu;
        suv += eu * ev;
        svv += ev * ev;
        r0 += eu * du;
        r1 += ev * du + eu * dv;
        r2 += ev * dv;
    }
    /* M = [[suu, suv, 0], [suv, suu + svv, suv], [0, suv, svv]] */
    det = suu * ((suu + svv) * svv - suv * suv) - suv * suv * svv;
    if (!(det != 0.0)) {
        abc[0] = abc[1] = abc[2] = 0.0;
        return;
    }
    abc[0] = (r0 * ((suu + svv) * svv - suv * suv) - suv * (r1 * svv - suv * r2)) / det;
    abc[1] = (suu * (r1 * svv - suv * r2) - r0 * suv * svv) / det;
    abc[2] = (suu * ((suu + svv) * r2 - suv * r1) - suv * (suv * r2) + r0 * suv * suv) / det;
}

/* Below this ratio of |k1| - |k2| to |k1| + |k2| a triangle is treated as
 * umbilic (sphere-like): its least-curvature direction is noise, and it takes
 * its neighbours' direction instead. */
#define PW_DF_UMBILIC 0.1

/* The direction of least absolute curvature of [[a, b], [b, c]] as a
 * doubled-angle number whose length is the confidence |k1| - |k2|
 * (0 where flat, umbilic or a balanced saddle). With mean curvature H and
 * half-difference R = |k1 - k2| / 2, the eigenvector of the larger eigenvalue
 * has doubled angle along (a - c, 2b); the least |k| is the smaller
 * eigenvalue when H >= 0 and the larger one when H < 0. */
PW__DEF void pw_df_least(const double abc[3], double flat, double *z)
{
    double hm = 0.5 * (abc[0] + abc[2]), dd = 0.5 * (abc[0] - abc[2]), b = abc[1];
    double rr = sqrt(dd * dd + b * b), ah = fabs(hm), conf = 2.0 * (ah < rr ? ah : rr);
    double big = 2.0 * (ah > rr ? ah : rr), sg = hm >= 0.0 ? -1.0 : 1.0;
    z[0] = z[1] = 0.0;
    if (!(rr > 0.0) || !(conf > flat) || !(conf > PW_DF_UMBILIC * big)) return;
    z[0] = sg * dd / rr * conf;
    z[1] = sg * b / rr * conf;
}

/* `iters` Jacobi sweeps: each triangle's doubled-angle number becomes the
 * mean of its own and its neighbours' (transported): confident directions
 * dominate weak ones, and the flat or umbilic ones (exactly 0) pick up their
 * neighbours' direction one ring per sweep. */
PW__DEF int pw_df_smooth(const pw_alloc *a, const pw_trimesh *m, const float *conn, int iters, double *z, pw_err *e)
{
    double *tmp = (double *)pw_alloc_array(a, (size_t)m->nf * 2, sizeof(double), "field smoothing", e), w[2];
    int it, f, k, g, n;
    if (!tmp) return PW_ERR_NOMEM;
    for (it = 0; it < iters; it++) {
        for (f = 0; f < m->nf; f++) {
            double sx = z[2 * f], sy = z[2 * f + 1];
            for (n = 1, k = 0; k < 3; k++)
                if ((g = pw_trimesh_across(m, f, k)) >= 0) {
                    pw_df_move(conn, 3 * f + k, 2, z + 2 * g, w);
                    sx += w[0];
                    sy += w[1];
                    n++;
                }
            tmp[2 * f] = sx / n;
            tmp[2 * f + 1] = sy / n;
        }
        memcpy(z, tmp, (size_t)m->nf * 2 * sizeof(double));
    }
    pw_free(a, tmp);
    return PW_OK;
}

/* Relaxes the neighbours of triangle f (just oriented) in the orientation
 * walk: a neighbour's key is 1 - |cos| of the angle between its line and
 * f's direction carried over, the smallest key (best agreement) kept. */
/* The orientation walk's state: seen (nf) marks oriented triangles, best
 * (nf) the smallest key offered to each, via (nf) the half-edge it came
 * through, hp the heap of offers (room for 3 nf + 1 entries). */
typedef struct pw_df_walker {
    unsigned char *seen;
    double *best;
    int *via;
    pw_heap *hp;
} pw_df_walker;

PW__DEF void pw_df_offer(const pw_trimesh *m, const float *conn, const double *z, int f, const pw_df_walker *W)
{
    const unsigned char *seen = W->seen;
    double *best = W->best;
    int *via = W->via;
    int k, g, th;
    double w[2], key;
    for (k = 0; k < 3; k++) {
        if ((th = m->hm.twin[3 * f + k]) < 0 || seen[g = th / 3]) continue;
        pw_df_move(conn, th, 1, z + 2 * f, w); /* f's direction seen from g */
        key = 1.0 - fabs(w[0] * z[2 * g] + w[1] * z[2 * g + 1]);
        if (key < best[g]) {
            best[g] = key;
            via[g] = th;
            pw_heap_insert(W->hp, key, g);
        }
    }
}

/* The walk of pw_df_orient over the field z (nf*2, no known flags). */
PW__DEF void pw_df_walk(const pw_df_field *F, pw_v3 up, const pw_df_walker *W)
{
    const pw_trimesh *m = F->m;
    const float *conn = F->conn;
    double *z = F->z, *best = W->best;
    unsigned char *seen = W->seen;
    int *via = W->via;
    pw_heap *hp = W->hp;
    double w[2];
    int s, f;
    for (f = 0; f < m->nf; f++) best[f] = 2.0;
    for (s = 0; s < m->nf; s++) {
        if (seen[s]) continue;
        if (pw_df_project(m, s, up, w) && w[0] * z[2 * s] + w[1] * z[2 * s + 1] < 0.0) {
            z[2 * s] = -z[2 * s];
            z[2 * s + 1] = -z[2 * s + 1];
        }
        seen[s] = 1;
        pw_df_offer(m, conn, z, s, W);
        while (hp->n > 0) {
            f = pw_heap_pop(hp);
            if (seen[f]) continue; /* stale entry */
            pw_df_move(conn, via[f], 1, z + 2 * (m->hm.twin[via[f]] / 3), w);
            if (w[0] * z[2 * f] + w[1] * z[2 * f + 1] < 0.0) {
                z[2 * f] = -z[2 * f];
                z[2 * f + 1] = -z[2 * f + 1];
            }
            seen[f] = 1;
            pw_df_offer(m, conn, z, f, W);
        }
    }
}

/* Turns a line field into a vector field. Each component starts at its
 * lowest triangle (T made to point along `up` when not normal to it) and
 * grows like Prim's spanning tree, always orienting next the triangle that
 * agrees best with an oriented neighbour, flipped to agree with it. Around
 * a half-integer singularity the signs must disagree somewhere: this puts
 * the seams where neighbouring lines are closest to perpendicular, near the
 * singularities, rather than wherever a breadth-first walk closes. */
PW__DEF int pw_df_orient(const pw_alloc *a, const pw_trimesh *m, const float *conn, pw_v3 up, double *z, pw_err *e)
{
    size_t n = (size_t)m->nf;
    double *dbl = (double *)pw_alloc_array(a, 4 * n + 1, sizeof(double), "field orientation", e);
    int *ints = (int *)pw_alloc_array(a, 4 * n + 1, sizeof(int), "field orientation", e);
    unsigned char *seen = (unsigned char *)pw_calloc_array(a, n, 1, "field orientation", e);
    int r = dbl && ints && seen ? PW_OK : PW_ERR_NOMEM;
    pw_heap hp;
    pw_df_field F;
    pw_df_walker W;
    if (r == PW_OK) { /* dbl: best keys, then the heap's; ints: via, then the heap's */
        memset(&hp, 0, sizeof hp);
        hp.key = dbl + n;
        hp.item = ints + n;
        F.m = m;
        F.conn = conn;
        F.z = z;
        F.known = NULL;
        W.seen = seen;
        W.best = dbl;
        W.via = ints;
        W.hp = &hp;
        pw_df_walk(&F, up, &W);
    }
    pw_free(a, dbl);
    pw_free(a, ints);
    pw_free(a, seen);
    return r;
}

/* The least-curvature field: raw per-triangle directions (flat below
 * 1e-3 / diagonal, i.e. radii of curvature over a thousand mesh sizes),
 * smoothing, unit length, gaps filled (components with no direction at all,
 * like a sphere or a plane, get the up field), halved to vectors, oriented. */
PW__DEF int pw_df_curvature(const pw_alloc *a, const pw_df_field *F, pw_v3 up, int smoothing, pw_err *e)
{
    const pw_trimesh *m = F->m;
    const float *conn = F->conn;
    double *z = F->z, *vn, abc[3];
    int f, r;
    if (smoothing < 0) return pw_fail(e, PW_ERR_INVALID, "curvature field: smoothing %d is negative", smoothing);
    if ((r = pw_df_vertex_normals(a, m, &vn, e)) != PW_OK) return r;
    for (f = 0; f < m->nf; f++) {
        pw_df_tensor(m, vn, f, abc);
        pw_df_least(abc, 1e-3 / m->diag, z + 2 * f);
    }
    pw_free(a, vn);
    if ((r = pw_df_smooth(a, m, conn, smoothing, z, e)) != PW_OK) return r;
    for (f = 0; f < m->nf; f++) F->known[f] = (unsigned char)pw_df_unit(z + 2 * f);
    if ((r = pw_df_fill(a, F, 2, up, e)) != PW_OK) return r;
    for (f = 0; f < m->nf; f++) pw_df_halve(z + 2 * f);
    return pw_df_orient(a, m, conn, up, z, e);
}

#endif /* PW__DIRFIELD_V1 */
