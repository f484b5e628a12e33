/* field.c: §3.2 the tangent field, one frame (S, T) per triangle, and the
 * §3.3 "difficulty" that tells growth where to seed the early pastes.
 *
 * Every mode ends with a unit direction per triangle written as a complex
 * number in the triangle's own frame (u = first edge, v = N x u), so that
 * moving a direction to a neighbour is one complex product: the connection
 * conn[h] of half-edge h unfolds the neighbour about the shared edge into
 * this triangle's plane (a rotation about the edge: the identity for a flat
 * pair, the discrete Levi-Civita transport otherwise). Line fields
 * (directions up to sign: principal curvature directions) use the square
 * (angle doubling) of the same numbers.
 *
 * Output: T in the face plane with |T| the local scale ("the magnitude of T
 * is the desired local uniform scaling"), S = T x N, the "right" direction,
 * with |S| = |T|.
 *
 * Modes (details beside each function):
 *   UP           up projected onto each face; where up is normal to a face,
 *                the neighbours' direction by propagation; a component
 *                wholly normal to up (a flat sheet) takes a fixed axis.
 *   ISOTROPIC    the same field (only the scale matters; growth propagates
 *                its own orientation).
 *   CONSTRAINTS  Gaussian RBFs of Dijkstra distance over the dual graph
 *                (centroid - edge midpoint - centroid), blended in 3D and
 *                projected, weights normalised against the nearest one so
 *                that nothing underflows; constrained faces keep their
 *                constraint; components no constraint reaches take the
 *                constraint nearest in triangle index.
 *   FACES        the caller's T (and S, or T x N), checked and projected.
 *   CURVATURE    least absolute principal curvature direction from
 *                per-face tensors (Rusinkiewicz 2004), a smoothed line field,
 *                flat and umbilic parts filled from their neighbours (or the
 *                up field), signs chosen by a spanning-tree walk.
 *
 * Determinism: only + - * / and sqrt; the Gaussians use lapped__fld_exp_neg
 * below (range reduction by ln 2 and a Taylor polynomial, then an exact
 * ldexp) instead of libm's exp. Private helpers carry the prefix
 * lapped__fld_. */
#include "core.c"

/* A tenth of the bounding-box diagonal: the documented default patch size. */
static float lapped__default_scale(const pw_trimesh *m) { return 0.1f * m->diag; }

/* field->scale: 0 means the default; negative or NaN is refused. */
static int lapped__fld_scale(const pw_trimesh *m, const lapped_field *f, float *out, pw_err *e)
{
    if (f->scale == 0.0f) {
        *out = lapped__default_scale(m);
        return PW_OK;
    }
    if (!(f->scale > 0.0f) || !pw_is_finite(f->scale))
        return pw_fail(e, PW_ERR_INVALID, "field scale %g is not a positive finite number", (double)f->scale);
    *out = f->scale;
    return PW_OK;
}

/* ---- frames, transport and small numerics -------------------------------- */

static pw_v3 lapped__fld_normal(const pw_trimesh *m, int f) { return pw_v3_load(m->normal + 3 * f); }

static pw_v3 lapped__fld_centroid(const pw_trimesh *m, int f)
{
    pw_v3 c = pw_v3_add(pw_v3_add(pw_trimesh_corner(m, f, 0), pw_trimesh_corner(m, f, 1)), pw_trimesh_corner(m, f, 2));
    return pw_v3_scale(c, 1.0f / 3.0f);
}

/* Surface distance between the triangles on either side of half-edge h
 * (which must have a twin): centroid to the edge's midpoint to centroid. */
static double lapped__fld_dual_len(const pw_trimesh *m, int h)
{
    int f = h / 3, k = h % 3;
    pw_v3 mid = pw_v3_add(pw_trimesh_corner(m, f, k), pw_trimesh_corner(m, f, (k + 1) % 3));
    mid = pw_v3_scale(mid, 0.5f);
    return (double)pw_v3_len(pw_v3_sub(mid, lapped__fld_centroid(m, f))) +
           (double)pw_v3_len(pw_v3_sub(lapped__fld_centroid(m, m->hm.twin[h] / 3), mid));
}

/* The frame of triangle f: u along its first edge, v = N x u. */
static void lapped__fld_frame(const pw_trimesh *m, int f, pw_v3 *u, pw_v3 *v)
{
    *u = pw_v3_norm(pw_v3_sub(pw_trimesh_corner(m, f, 1), pw_trimesh_corner(m, f, 0)));
    *v = pw_v3_cross(lapped__fld_normal(m, f), *u);
}

/* Tangent vector x of the triangle across half-edge h, unfolded about the
 * shared edge into the plane of h's own triangle: the rotation about the
 * edge that takes one normal to the other. */
static pw_v3 lapped__fld_hinge(const pw_trimesh *m, int h, pw_v3 x)
{
    int f = h / 3, g = m->hm.twin[h] / 3, k = h % 3;
    pw_v3 ed = pw_v3_norm(pw_v3_sub(pw_trimesh_corner(m, f, (k + 1) % 3), pw_trimesh_corner(m, f, k)));
    pw_v3 nf = lapped__fld_normal(m, f), ng = lapped__fld_normal(m, g);
    pw_v3 r = pw_v3_scale(ed, pw_v3_dot(x, ed));
    r = pw_v3_add(r, pw_v3_scale(pw_v3_cross(nf, ed), pw_v3_dot(x, pw_v3_cross(ng, ed))));
    return pw_v3_add(r, pw_v3_scale(nf, pw_v3_dot(x, ng)));
}

/* Scales z to unit length; returns 0 (and leaves z) if it is zero. */
static int lapped__fld_unit(double *z)
{
    double l = sqrt(z[0] * z[0] + z[1] * z[1]);
    if (!(l > 0.0) || !pw_is_finite(l)) return 0;
    z[0] /= l;
    z[1] /= l;
    return 1;
}

/* The shared edge of half-edge h as a complex number in the frame of
 * triangle f (either side of the edge). */
static void lapped__fld_edge_in(const pw_trimesh *m, int h, int f, double *w)
{
    int k = h % 3, g = h / 3;
    pw_v3 u, v, ed = pw_v3_sub(pw_trimesh_corner(m, g, (k + 1) % 3), pw_trimesh_corner(m, g, k));
    lapped__fld_frame(m, f, &u, &v);
    w[0] = pw_v3_dot(ed, u);
    w[1] = pw_v3_dot(ed, v);
}

/* conn[2h], conn[2h+1]: the rotation taking directions of the triangle
 * across h into h's own triangle frame, so that a direction (x, y) over
 * there is (x, y) * conn[h] here (complex product). It is the unfolding
 * about the shared edge (lapped__fld_hinge): the edge keeps its angle to
 * every vector, so with the edge at angle a_f here and a_g there,
 * conn = e^{i (a_f - a_g)}. Boundary half-edges get 1. */
static int lapped__fld_connection(const pw_alloc *a, const pw_trimesh *m, float **out, pw_err *e)
{
    float *c = (float *)pw_alloc_array(a, (size_t)m->nf * 6, sizeof(float), "field connection", e);
    int h;
    *out = c;
    if (!c) return PW_ERR_NOMEM;
    for (h = 0; h < 3 * m->nf; h++) {
        double wf[2], wg[2], z[2] = {1.0, 0.0};
        if (m->hm.twin[h] >= 0) {
            lapped__fld_edge_in(m, h, h / 3, wf);
            lapped__fld_edge_in(m, h, m->hm.twin[h] / 3, wg);
            z[0] = wf[0] * wg[0] + wf[1] * wg[1]; /* wf * conj(wg) */
            z[1] = wf[1] * wg[0] - wf[0] * wg[1];
            if (!lapped__fld_unit(z)) z[0] = 1.0, z[1] = 0.0;
        }
        c[2 * h] = (float)z[0];
        c[2 * h + 1] = (float)z[1];
    }
    return PW_OK;
}

/* z (a direction of the neighbour across h) transported into h's triangle;
 * power 2 for line fields (doubled angles). */
static void lapped__fld_move(const float *conn, int h, int power, const double *z, double *out)
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
static void lapped__fld_square(double *z)
{
    double x = z[0] * z[0] - z[1] * z[1];
    z[1] = 2.0 * z[0] * z[1];
    z[0] = x;
}

/* Halves the angle of a unit doubled-angle number with sqrt only (no atan2),
 * giving the direction in (-90, 90] degrees. */
static void lapped__fld_halve(double *z)
{
    double c = z[0] < -1.0 ? -1.0 : (z[0] > 1.0 ? 1.0 : z[0]);
    double x = sqrt(0.5 * (1.0 + c)), y = sqrt(0.5 * (1.0 - c));
    z[0] = x;
    z[1] = z[1] < 0.0 ? -y : y;
}

/* The 3D direction d projected onto triangle f, as a unit direction in its
 * frame. Returns 0 when d is (within 1e-4 radians) normal to the face:
 * "project the global up direction onto the surface" has no answer there. */
static int lapped__fld_project(const pw_trimesh *m, int f, pw_v3 d, double *z)
{
    pw_v3 u, v;
    double l2 = (double)pw_v3_dot(d, d);
    lapped__fld_frame(m, f, &u, &v);
    z[0] = pw_v3_dot(d, u);
    z[1] = pw_v3_dot(d, v);
    if (!(z[0] * z[0] + z[1] * z[1] > 1e-8 * l2)) return 0;
    return lapped__fld_unit(z);
}

/* A fixed direction for triangle f when nothing else defines one: the
 * coordinate axis least aligned with its normal (lowest axis on ties),
 * projected; never degenerate (at least sqrt(2/3) of it is tangent). */
static void lapped__fld_axis(const pw_trimesh *m, int f, double *z)
{
    const float *n = m->normal + 3 * f;
    int k = 0, i;
    float ax[3] = {0.0f, 0.0f, 0.0f};
    for (i = 1; i < 3; i++)
        if (fabsf(n[i]) < fabsf(n[k])) k = i;
    ax[k] = 1.0f;
    if (!lapped__fld_project(m, f, pw_v3_load(ax), z)) z[0] = 1.0, z[1] = 0.0;
}

/* e^-x for x >= 0 from + - * / and an exact power of two: x = n ln2 - r
 * with |r| <= ln2/2, e^r by its Taylor series to r^14 (truncation below
 * 5e-18), then scaled by 2^-n with ldexp (exact). Relative error below 3e-16
 * against libm over [0, 700], and the same bits on every IEEE platform,
 * unlike libm's exp. Returns 0 beyond e^-700 and for NaN. */
static double lapped__fld_exp_neg(double x)
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

/* ---- filling the gaps by propagation ------------------------------------- */

/* Seeds a component in which no triangle has a direction yet (level -1 from
 * `start` on): every triangle where `up` projects gets that projection, as
 * in the up field; if none does (a flat piece normal to up), the lowest
 * triangle gets the fixed axis. Seeds go to the queue with level 0. */
static void lapped__fld_seed(const pw_trimesh *m, pw_v3 up, int power, double *z, int *level, int *queue,
                             int *tail, int *stack, int start)
{
    int top = 1, n = 0, i, k, f, g, seeded = 0;
    stack[0] = start;
    level[start] = -2;
    while (n < top) { /* flood the component, in a deterministic order */
        f = stack[n++];
        for (k = 0; k < 3; k++)
            if ((g = pw_trimesh_across(m, f, k)) >= 0 && level[g] == -1) level[g] = -2, stack[top++] = g;
    }
    for (i = 0; i < top; i++) {
        f = stack[i];
        level[f] = -1;
        if (lapped__fld_project(m, f, up, z + 2 * f)) {
            if (power == 2) lapped__fld_square(z + 2 * f);
            level[f] = 0;
            queue[(*tail)++] = f;
            seeded = 1;
        }
    }
    if (!seeded) {
        lapped__fld_axis(m, start, z + 2 * start);
        if (power == 2) lapped__fld_square(z + 2 * start);
        level[start] = 0;
        queue[(*tail)++] = start;
    }
}

/* Triangle f's direction from its neighbours one level closer to the known
 * ones: the unit average of their directions transported into f (§3.2
 * propagation: "projecting onto its face plane the average direction of
 * neighboring faces"); the first neighbour's if the average cancels. */
static void lapped__fld_average(const pw_trimesh *m, const float *conn, int power, const int *level,
                                double *z, int f)
{
    double sum[2] = {0.0, 0.0}, first[2] = {0.0, 0.0}, w[2];
    int k, g, n = 0;
    for (k = 0; k < 3; k++) {
        g = pw_trimesh_across(m, f, k);
        if (g < 0 || level[g] < 0 || level[g] >= level[f]) continue;
        lapped__fld_move(conn, 3 * f + k, power, z + 2 * g, w);
        if (n++ == 0) first[0] = w[0], first[1] = w[1];
        sum[0] += w[0];
        sum[1] += w[1];
    }
    if (!(sum[0] * sum[0] + sum[1] * sum[1] > 1e-12)) sum[0] = first[0], sum[1] = first[1];
    if (!lapped__fld_unit(sum)) sum[0] = 1.0, sum[1] = 0.0;
    z[2 * f] = sum[0];
    z[2 * f + 1] = sum[1];
}

/* Gives every triangle with known[f] == 0 a unit direction (z, nf*2, in
 * the triangle frames; power 2: doubled angles) by breadth-first propagation
 * from the known ones, layer by layer, so that the result does not depend
 * on which known triangle is met first. Components without a known triangle
 * are seeded by lapped__fld_seed. Known directions must be unit. */
static int lapped__fld_fill(const pw_alloc *a, const pw_trimesh *m, const float *conn, int power, pw_v3 up,
                            const unsigned char *known, double *z, pw_err *e)
{
    int *level = (int *)pw_alloc_array(a, (size_t)m->nf * 3, sizeof(int), "field propagation", e);
    int *queue, *stack, head = 0, tail = 0, next = 0, f, k, g;
    if (!level) return PW_ERR_NOMEM;
    queue = level + m->nf;
    stack = queue + m->nf;
    for (f = 0; f < m->nf; f++) {
        level[f] = known[f] ? 0 : -1;
        if (known[f]) queue[tail++] = f;
    }
    for (;;) {
        if (head == tail) {
            while (next < m->nf && level[next] >= 0) next++;
            if (next == m->nf) break;
            lapped__fld_seed(m, up, power, z, level, queue, &tail, stack, next);
        }
        f = queue[head++];
        if (level[f] > 0) lapped__fld_average(m, conn, power, level, z, f);
        for (k = 0; k < 3; k++)
            if ((g = pw_trimesh_across(m, f, k)) >= 0 && level[g] == -1) {
                level[g] = level[f] + 1;
                queue[tail++] = g;
            }
    }
    pw_free(a, level);
    return PW_OK;
}

/* Writes T = scale * direction (unit z in the triangle frame) and
 * S = T x N (§3.2). scales may be NULL (then `scale` everywhere). */
static void lapped__fld_output(const pw_trimesh *m, const double *z, float scale, const double *scales,
                               float *s, float *t)
{
    int f;
    for (f = 0; f < m->nf; f++) {
        pw_v3 u, v, T;
        float sc = scales ? (float)scales[f] : scale;
        lapped__fld_frame(m, f, &u, &v);
        T = pw_v3_norm(pw_v3_add(pw_v3_scale(u, (float)z[2 * f]), pw_v3_scale(v, (float)z[2 * f + 1])));
        T = pw_v3_scale(T, sc);
        pw_v3_store(t + 3 * f, T);
        pw_v3_store(s + 3 * f, pw_v3_cross(T, lapped__fld_normal(m, f)));
    }
}

/* ---- LAPPED_FIELD_UP and ISOTROPIC --------------------------------------- */

/* §3.2: "project the global up direction onto the surface, and then
 * normalize". Where up is normal to a triangle (the top of a box, a pole)
 * the projection is undefined: such triangles take the average of their
 * neighbours' directions, unfolded into their plane, by propagation; a
 * component that is entirely normal to up (a flat sheet) uses a fixed axis
 * (lapped__fld_axis). ISOTROPIC uses the same field: growth replaces the
 * orientation by its own propagation, and a smooth start keeps the
 * discontinuity part of lapped__difficulty quiet. */
static int lapped__fld_up(const pw_alloc *a, const pw_trimesh *m, const float *conn, pw_v3 up, double *z,
                          unsigned char *known, pw_err *e)
{
    int f;
    for (f = 0; f < m->nf; f++) known[f] = (unsigned char)lapped__fld_project(m, f, up, z + 2 * f);
    return lapped__fld_fill(a, m, conn, 1, up, known, z, e);
}

/* ---- LAPPED_FIELD_FACES ---------------------------------------------------- */

/* One caller vector of triangle f, projected onto its plane and rescaled to
 * its own length (a vector meant to be tangent keeps its magnitude, the
 * scale). Refuses NaN/Inf, zero, and vectors normal to the face. */
static int lapped__fld_tangent(const pw_trimesh *m, int f, const float *p, const char *what, pw_v3 *out,
                               pw_err *e)
{
    pw_v3 x = pw_v3_load(p), n = lapped__fld_normal(m, f), q;
    float len, ql;
    if (!pw_is_finite(x.x) || !pw_is_finite(x.y) || !pw_is_finite(x.z))
        return pw_fail(e, PW_ERR_INVALID, "field %s of triangle %d is not finite", what, f);
    len = pw_v3_len(x);
    q = pw_v3_sub(x, pw_v3_scale(n, pw_v3_dot(x, n)));
    ql = pw_v3_len(q);
    if (!(len > 0.0f) || !pw_is_finite(len))
        return pw_fail(e, PW_ERR_INVALID, "field %s of triangle %d is zero", what, f);
    if (!(ql > 1e-4f * len))
        return pw_fail(e, PW_ERR_INVALID, "field %s of triangle %d is normal to the triangle", what, f);
    *out = pw_v3_scale(q, len / ql);
    return PW_OK;
}

/* §3.2: "The user could alternatively specify this tangential basis
 * directly": the caller's T per triangle (its length is the scale) and S,
 * or S = T x N when face_s is NULL. S parallel to T is refused (no frame). */
static int lapped__fld_faces(const pw_trimesh *m, const lapped_field *fl, float *s, float *t, pw_err *e)
{
    int f, r;
    if (!fl->face_t) return pw_fail(e, PW_ERR_INVALID, "FACES field: face_t is NULL");
    for (f = 0; f < m->nf; f++) {
        pw_v3 T, S, n = lapped__fld_normal(m, f);
        if ((r = lapped__fld_tangent(m, f, fl->face_t + 3 * f, "T", &T, e)) != PW_OK) return r;
        if (!fl->face_s)
            S = pw_v3_cross(T, n);
        else if ((r = lapped__fld_tangent(m, f, fl->face_s + 3 * f, "S", &S, e)) != PW_OK)
            return r;
        if (!(fabsf(pw_v3_dot(pw_v3_cross(S, T), n)) > 1e-4f * pw_v3_len(S) * pw_v3_len(T)))
            return pw_fail(e, PW_ERR_INVALID, "field S and T of triangle %d are parallel", f);
        pw_v3_store(t + 3 * f, T);
        pw_v3_store(s + 3 * f, S);
    }
    return PW_OK;
}

/* ---- LAPPED_FIELD_CONSTRAINTS ---------------------------------------------- */

/* A constraint with its defaults resolved: unit direction tangent to its
 * own triangle, scale, Gaussian standard deviation and weight. */
typedef struct lapped__fld_con {
    int face;
    pw_v3 dir;
    double scale, radius, weight;
} lapped__fld_con;

/* A constraint value that must be finite and >= 0; 0 means `def`. */
static int lapped__fld_value(int i, const char *what, float x, double def, double *out, pw_err *e)
{
    if (!(x >= 0.0f) || !pw_is_finite(x))
        return pw_fail(e, PW_ERR_INVALID, "constraint %d: %s %g is negative or not finite", i, what,
                       (double)x);
    *out = x > 0.0f ? (double)x : def;
    return PW_OK;
}

/* Checks constraint i and resolves its defaults (lapped.h: scale 0 is the
 * field's scale, radius 0 is twice the constraint's scale, weight 0 is 1). */
static int lapped__fld_check(const pw_trimesh *m, const lapped_constraint *in, int i, float scale,
                             lapped__fld_con *c, pw_err *e)
{
    pw_v3 d = pw_v3_load(in->direction), n;
    double z[2];
    int r;
    if (in->face < 0 || in->face >= m->nf)
        return pw_fail(e, PW_ERR_INVALID, "constraint %d: triangle %d is out of range (the mesh has %d)", i,
                       in->face, m->nf);
    if (!pw_is_finite(d.x) || !pw_is_finite(d.y) || !pw_is_finite(d.z) || !pw_is_finite(pw_v3_dot(d, d)))
        return pw_fail(e, PW_ERR_INVALID, "constraint %d: direction is not finite", i);
    if (!(pw_v3_dot(d, d) > 0.0f)) return pw_fail(e, PW_ERR_INVALID, "constraint %d: direction is zero", i);
    if (!lapped__fld_project(m, in->face, d, z))
        return pw_fail(e, PW_ERR_INVALID, "constraint %d: direction is normal to triangle %d", i, in->face);
    c->face = in->face;
    n = lapped__fld_normal(m, in->face);
    c->dir = pw_v3_norm(pw_v3_sub(d, pw_v3_scale(n, pw_v3_dot(d, n))));
    if ((r = lapped__fld_value(i, "scale", in->scale, scale, &c->scale, e)) != PW_OK) return r;
    if ((r = lapped__fld_value(i, "radius", in->radius, 2.0 * c->scale, &c->radius, e)) != PW_OK) return r;
    return lapped__fld_value(i, "weight", in->weight, 1.0, &c->weight, e);
}

/* Length of each dual edge: centroid to edge midpoint to centroid, a path
 * on the surface even across a crease (the straight centroid-to-centroid
 * segment would cut through it). 0 on the boundary. */
static void lapped__fld_dual(const pw_trimesh *m, double *len)
{
    int h;
    for (h = 0; h < 3 * m->nf; h++) len[h] = m->hm.twin[h] < 0 ? 0.0 : lapped__fld_dual_len(m, h);
}

/* A binary min-heap of (distance, triangle), ties broken by the lower
 * triangle index so that the order never depends on anything else. */
typedef struct lapped__fld_heap {
    double *d;
    int *f, n;
} lapped__fld_heap;

static int lapped__fld_less(const lapped__fld_heap *hp, int i, int j)
{
    return hp->d[i] < hp->d[j] || (hp->d[i] == hp->d[j] && hp->f[i] < hp->f[j]);
}

static void lapped__fld_swap(lapped__fld_heap *hp, int i, int j)
{
    double d = hp->d[i];
    int f = hp->f[i];
    hp->d[i] = hp->d[j], hp->f[i] = hp->f[j];
    hp->d[j] = d, hp->f[j] = f;
}

static void lapped__fld_push(lapped__fld_heap *hp, double d, int f)
{
    int i = hp->n++;
    hp->d[i] = d;
    hp->f[i] = f;
    while (i > 0 && lapped__fld_less(hp, i, (i - 1) / 2)) {
        lapped__fld_swap(hp, i, (i - 1) / 2);
        i = (i - 1) / 2;
    }
}

static void lapped__fld_pop(lapped__fld_heap *hp)
{
    int i = 0;
    lapped__fld_swap(hp, 0, --hp->n);
    for (;;) {
        int l = 2 * i + 1, r = l + 1, b = i;
        if (l < hp->n && lapped__fld_less(hp, l, b)) b = l;
        if (r < hp->n && lapped__fld_less(hp, r, b)) b = r;
        if (b == i) break;
        lapped__fld_swap(hp, i, b);
        i = b;
    }
}

/* §3.2 "radius is defined as distance over the mesh, as computed using
 * Dijkstra's algorithm": distances over the dual graph (triangle centroids
 * joined through edge midpoints) from triangle src; DBL_MAX where
 * unreachable. The heap holds at most 3*nf+1 entries (a triangle is pushed
 * only when one of its <= 3 neighbours improves it). */
static void lapped__fld_dijkstra(const pw_trimesh *m, const double *len, int src, double *dist,
                                 lapped__fld_heap *hp)
{
    int f, k, g;
    for (f = 0; f < m->nf; f++) dist[f] = DBL_MAX;
    dist[src] = 0.0;
    hp->n = 0;
    lapped__fld_push(hp, 0.0, src);
    while (hp->n > 0) {
        double d = hp->d[0];
        f = hp->f[0];
        lapped__fld_pop(hp);
        if (d > dist[f]) continue; /* stale entry */
        for (k = 0; k < 3; k++) {
            double nd = d + len[3 * f + k];
            if ((g = pw_trimesh_across(m, f, k)) >= 0 && nd < dist[g]) {
                dist[g] = nd;
                lapped__fld_push(hp, nd, g);
            }
        }
    }
}

/* Running Gaussian-weighted sums per triangle, kept relative to the
 * smallest exponent met so far (q = d^2 / (2 radius^2)): every weight is
 * w_i exp(-(q_i - qmin)), so the nearest constraint (in Gaussian units)
 * always weighs about its own weight and nothing underflows to 0/0 far from
 * every constraint; the ratio of the sums is the plain RBF blend. */
typedef struct lapped__fld_acc {
    double *q, *w, *dir, *sc; /* nf, nf, nf*3, nf */
} lapped__fld_acc;

static void lapped__fld_accumulate(int nf, const double *dist, const lapped__fld_con *c, lapped__fld_acc *acc)
{
    int f, k;
    for (f = 0; f < nf; f++) {
        double q, g, wt;
        if (dist[f] == DBL_MAX) continue;
        q = dist[f] * dist[f] / (2.0 * c->radius * c->radius);
        if (q < acc->q[f]) { /* new smallest exponent: rescale what is there */
            g = lapped__fld_exp_neg(acc->q[f] - q);
            acc->w[f] *= g;
            acc->sc[f] *= g;
            for (k = 0; k < 3; k++) acc->dir[3 * f + k] *= g;
            acc->q[f] = q;
        }
        wt = c->weight * lapped__fld_exp_neg(q - acc->q[f]);
        acc->w[f] += wt;
        acc->sc[f] += wt * c->scale;
        acc->dir[3 * f] += wt * c->dir.x;
        acc->dir[3 * f + 1] += wt * c->dir.y;
        acc->dir[3 * f + 2] += wt * c->dir.z;
    }
}

static int lapped__fld_gap(int a, int b) { return a > b ? a - b : b - a; }

/* Connected components that no constraint reaches (no geodesic distance):
 * each takes, whole, the direction and scale of the constraint whose
 * triangle index is nearest to the component's lowest triangle (the lower
 * constraint on ties), projected onto each face like an up vector. */
static void lapped__fld_orphans(const pw_trimesh *m, const lapped__fld_con *c, int nc, lapped__fld_acc *acc,
                                int *stack)
{
    int f, i, j, top, k, g;
    for (f = 0; f < m->nf; f++) {
        if (acc->q[f] != DBL_MAX) continue;
        for (j = 0, i = 1; i < nc; i++)
            if (lapped__fld_gap(c[i].face, f) < lapped__fld_gap(c[j].face, f)) j = i;
        stack[0] = f;
        top = 1;
        acc->q[f] = 0.0;
        while (top > 0) {
            int h = stack[--top];
            acc->w[h] = 1.0;
            acc->sc[h] = c[j].scale;
            acc->dir[3 * h] = c[j].dir.x;
            acc->dir[3 * h + 1] = c[j].dir.y;
            acc->dir[3 * h + 2] = c[j].dir.z;
            for (k = 0; k < 3; k++)
                if ((g = pw_trimesh_across(m, h, k)) >= 0 && acc->q[g] == DBL_MAX) {
                    acc->q[g] = 0.0;
                    stack[top++] = g;
                }
        }
    }
}

/* §3.2 interpolates "at the remaining faces": a constrained triangle keeps
 * its own constraint exactly (the weighted mean of its constraints if
 * several share it), instead of the blend with the others' tails. */
static void lapped__fld_pin(const lapped__fld_con *c, int nc, lapped__fld_acc *acc)
{
    int i, f;
    for (i = 0; i < nc; i++) {
        f = c[i].face;
        if (acc->q[f] != -1.0) { /* first constraint on f: start afresh (q = -1 marks it) */
            acc->q[f] = -1.0;
            acc->w[f] = acc->sc[f] = 0.0;
            acc->dir[3 * f] = acc->dir[3 * f + 1] = acc->dir[3 * f + 2] = 0.0;
        }
        acc->w[f] += c[i].weight;
        acc->sc[f] += c[i].weight * c[i].scale;
        acc->dir[3 * f] += c[i].weight * c[i].dir.x;
        acc->dir[3 * f + 1] += c[i].weight * c[i].dir.y;
        acc->dir[3 * f + 2] += c[i].weight * c[i].dir.z;
    }
}

/* Checks and resolves every constraint into c[]. */
static int lapped__fld_checks(const pw_trimesh *m, const lapped_field *fl, float scale, lapped__fld_con *c,
                              pw_err *e)
{
    int i, r;
    for (i = 0; i < fl->nconstraints; i++)
        if ((r = lapped__fld_check(m, fl->constraints + i, i, scale, c + i, e)) != PW_OK) return r;
    return PW_OK;
}

/* The blended 3D directions projected onto each face (§3.2: vectors "at
 * the remaining faces"), and the blended scales. A blend that cancels or is
 * normal to its face is filled from the neighbours. */
static int lapped__fld_blend(const pw_alloc *a, const pw_trimesh *m, const float *conn, pw_v3 up,
                             const lapped__fld_acc *acc, double *z, double *scales, unsigned char *known,
                             pw_err *e)
{
    int f;
    for (f = 0; f < m->nf; f++) {
        double w = acc->w[f];
        pw_v3 d = pw_v3_make((float)(acc->dir[3 * f] / w), (float)(acc->dir[3 * f + 1] / w),
                             (float)(acc->dir[3 * f + 2] / w));
        known[f] = (unsigned char)(pw_v3_dot(d, d) > 1e-8f && lapped__fld_project(m, f, d, z + 2 * f));
        scales[f] = acc->sc[f] / w;
    }
    return lapped__fld_fill(a, m, conn, 1, up, known, z, e);
}

/* §3.2: "the user specifies vectors at a few faces. We interpolate vectors
 * at the remaining faces using Gaussian radial basis functions, where radius
 * is defined as distance over the mesh, as computed using Dijkstra's
 * algorithm. The user has control over the spatial extent and weight of each
 * basis function." Weight of constraint i at triangle f:
 * weight_i exp(-d_i(f)^2 / (2 radius_i^2)); directions are blended in 3D
 * and projected onto f, scales blended linearly. One Dijkstra run per
 * constraint: O(nconstraints * nf log nf) time, O(nf) memory. */
static int lapped__fld_constraints(const pw_alloc *a, const pw_trimesh *m, const lapped_field *fl,
                                   float scale, const float *conn, double *z, double *scales,
                                   unsigned char *known, pw_err *e)
{
    size_t n = (size_t)m->nf;
    int nc = fl->nconstraints, i, f, r = PW_OK;
    lapped__fld_con *c;
    double *len, *dist;
    lapped__fld_acc acc;
    lapped__fld_heap hp;
    if (nc < 1 || !fl->constraints)
        return pw_fail(e, PW_ERR_INVALID, "CONSTRAINTS field needs constraints (nconstraints %d%s)", nc,
                       fl->constraints ? "" : ", constraints NULL");
    c = (lapped__fld_con *)pw_alloc_array(a, (size_t)nc, sizeof *c, "constraints", e);
    len = (double *)pw_alloc_array(a, 13 * n + 1, sizeof(double), "geodesic distances", e);
    hp.f = (int *)pw_alloc_array(a, 3 * n + 1, sizeof(int), "Dijkstra heap", e);
    if (!c || !len || !hp.f) r = PW_ERR_NOMEM;
    if (r == PW_OK) r = lapped__fld_checks(m, fl, scale, c, e);
    if (r == PW_OK) {
        dist = len + 3 * n;
        hp.d = dist + n;
        acc.q = hp.d + 3 * n + 1;
        acc.w = acc.q + n;
        acc.sc = acc.w + n;
        acc.dir = acc.sc + n;
        for (f = 0; f < m->nf; f++) acc.q[f] = DBL_MAX;
        memset(acc.w, 0, 5 * n * sizeof(double));
        lapped__fld_dual(m, len);
        for (i = 0; i < nc; i++) {
            lapped__fld_dijkstra(m, len, c[i].face, dist, &hp);
            lapped__fld_accumulate(m->nf, dist, c + i, &acc);
        }
        lapped__fld_pin(c, nc, &acc);
        lapped__fld_orphans(m, c, nc, &acc, hp.f);
        r = lapped__fld_blend(a, m, conn, pw_v3_load(fl->up), &acc, z, scales, known, e);
    }
    pw_free(a, c);
    pw_free(a, len);
    pw_free(a, hp.f);
    return r;
}

/* ---- LAPPED_FIELD_CURVATURE ------------------------------------------------ */

/* The paper's future work: "automatic direction field construction using
 * surface curvatures". Per-triangle curvature tensors from vertex normals
 * (Rusinkiewicz, "Estimating curvatures and their derivatives on triangle
 * meshes", 3DPVT 2004, §3), the direction of least absolute curvature as a
 * line field (up to sign), smoothed, gaps filled from the neighbours, then
 * one sign chosen by a breadth-first walk. */

/* Vertex normals with Max's weights (J. Graphics Tools 4(2), 1999): each
 * triangle's corner cross product over the squared lengths of its two
 * edges; exact on a sphere, no trigonometry. */
static int lapped__fld_vertex_normals(const pw_alloc *a, const pw_trimesh *m, double **out, pw_err *e)
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
static void lapped__fld_tensor(const pw_trimesh *m, const double *vn, int f, double abc[3])
{
    double suu = 0, suv = 0, svv = 0, r0 = 0, r1 = 0, r2 = 0, det;
    pw_v3 u, v;
    int i;
    lapped__fld_frame(m, f, &u, &v);
    for (i = 0; i < 3; i++) {
        int p = m->tri[3 * f + (i + 1) % 3], q = m->tri[3 * f + (i + 2) % 3], k;
        pw_v3 ed = pw_v3_sub(pw_trimesh_vert(m, q), pw_trimesh_vert(m, p));
        double dn[3], eu = pw_v3_dot(ed, u), ev = pw_v3_dot(ed, v), du = 0, dv = 0;
        for (k = 0; k < 3; k++) dn[k] = vn[3 * q + k] - vn[3 * p + k];
        du = dn[0] * u.x + dn[1] * u.y + dn[2] * u.z;
        dv = dn[0] * v.x + dn[1] * v.y + dn[2] * v.z;
        suu += eu * eu, suv += eu * ev, svv += ev * ev;
        r0 += eu * du, r1 += ev * du + eu * dv, r2 += ev * dv;
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
#define LAPPED__UMBILIC 0.1

/* The direction of least absolute curvature of [[a, b], [b, c]] as a
 * doubled-angle number whose length is the confidence |k1| - |k2|
 * (0 where flat, umbilic or a balanced saddle). With mean curvature H and
 * half-difference R = |k1 - k2| / 2, the eigenvector of the larger eigenvalue
 * has doubled angle along (a - c, 2b); the least |k| is the smaller
 * eigenvalue when H >= 0 and the larger one when H < 0. */
static void lapped__fld_least(const double abc[3], double flat, double *z)
{
    double hm = 0.5 * (abc[0] + abc[2]), dd = 0.5 * (abc[0] - abc[2]), b = abc[1];
    double rr = sqrt(dd * dd + b * b), ah = fabs(hm), conf = 2.0 * (ah < rr ? ah : rr);
    double big = 2.0 * (ah > rr ? ah : rr), sg = hm >= 0.0 ? -1.0 : 1.0;
    z[0] = z[1] = 0.0;
    if (!(rr > 0.0) || !(conf > flat) || !(conf > LAPPED__UMBILIC * big)) return;
    z[0] = sg * dd / rr * conf;
    z[1] = sg * b / rr * conf;
}

/* `iters` Jacobi sweeps: each triangle's doubled-angle number becomes the
 * mean of its own and its neighbours' (transported): confident directions
 * dominate weak ones, and the flat or umbilic ones (exactly 0) pick up their
 * neighbours' direction one ring per sweep. */
static int lapped__fld_smooth(const pw_alloc *a, const pw_trimesh *m, const float *conn, int iters,
                              double *z, pw_err *e)
{
    double *tmp = (double *)pw_alloc_array(a, (size_t)m->nf * 2, sizeof(double), "field smoothing", e), w[2];
    int it, f, k, g, n;
    if (!tmp) return PW_ERR_NOMEM;
    for (it = 0; it < iters; it++) {
        for (f = 0; f < m->nf; f++) {
            double sx = z[2 * f], sy = z[2 * f + 1];
            for (n = 1, k = 0; k < 3; k++)
                if ((g = pw_trimesh_across(m, f, k)) >= 0) {
                    lapped__fld_move(conn, 3 * f + k, 2, z + 2 * g, w);
                    sx += w[0], sy += w[1], n++;
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
static void lapped__fld_offer(const pw_trimesh *m, const float *conn, const double *z, int f,
                              const unsigned char *seen, double *best, int *via, lapped__fld_heap *hp)
{
    int k, g, th;
    double w[2], key;
    for (k = 0; k < 3; k++) {
        if ((th = m->hm.twin[3 * f + k]) < 0 || seen[g = th / 3]) continue;
        lapped__fld_move(conn, th, 1, z + 2 * f, w); /* f's direction seen from g */
        key = 1.0 - fabs(w[0] * z[2 * g] + w[1] * z[2 * g + 1]);
        if (key < best[g]) {
            best[g] = key;
            via[g] = th;
            lapped__fld_push(hp, key, g);
        }
    }
}

/* The walk of lapped__fld_orient (best: nf keys, via: nf half-edges,
 * hp: room for 3 nf + 1 entries). */
static void lapped__fld_walk(const pw_trimesh *m, const float *conn, pw_v3 up, double *z,
                             unsigned char *seen, double *best, int *via, lapped__fld_heap *hp)
{
    double w[2];
    int s, f;
    for (f = 0; f < m->nf; f++) best[f] = 2.0;
    for (s = 0; s < m->nf; s++) {
        if (seen[s]) continue;
        if (lapped__fld_project(m, s, up, w) && w[0] * z[2 * s] + w[1] * z[2 * s + 1] < 0.0)
            z[2 * s] = -z[2 * s], z[2 * s + 1] = -z[2 * s + 1];
        seen[s] = 1;
        lapped__fld_offer(m, conn, z, s, seen, best, via, hp);
        while (hp->n > 0) {
            f = hp->f[0];
            lapped__fld_pop(hp);
            if (seen[f]) continue; /* stale entry */
            lapped__fld_move(conn, via[f], 1, z + 2 * (m->hm.twin[via[f]] / 3), w);
            if (w[0] * z[2 * f] + w[1] * z[2 * f + 1] < 0.0)
                z[2 * f] = -z[2 * f], z[2 * f + 1] = -z[2 * f + 1];
            seen[f] = 1;
            lapped__fld_offer(m, conn, z, f, seen, best, via, hp);
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
static int lapped__fld_orient(const pw_alloc *a, const pw_trimesh *m, const float *conn, pw_v3 up,
                              double *z, pw_err *e)
{
    size_t n = (size_t)m->nf;
    double *dbl = (double *)pw_alloc_array(a, 4 * n + 1, sizeof(double), "field orientation", e);
    int *ints = (int *)pw_alloc_array(a, 4 * n + 1, sizeof(int), "field orientation", e);
    unsigned char *seen = (unsigned char *)pw_calloc_array(a, n, 1, "field orientation", e);
    int r = dbl && ints && seen ? PW_OK : PW_ERR_NOMEM;
    lapped__fld_heap hp;
    if (r == PW_OK) { /* dbl: best keys, then the heap's; ints: via, then the heap's */
        hp.d = dbl + n, hp.f = ints + n, hp.n = 0;
        lapped__fld_walk(m, conn, up, z, seen, dbl, ints, &hp);
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
static int lapped__fld_curvature(const pw_alloc *a, const pw_trimesh *m, const lapped_field *fl,
                                 const float *conn, double *z, unsigned char *known, pw_err *e)
{
    double *vn, abc[3];
    int f, r;
    pw_v3 up = pw_v3_load(fl->up);
    if (fl->smoothing < 0)
        return pw_fail(e, PW_ERR_INVALID, "CURVATURE field: smoothing %d is negative", fl->smoothing);
    if ((r = lapped__fld_vertex_normals(a, m, &vn, e)) != PW_OK) return r;
    for (f = 0; f < m->nf; f++) {
        lapped__fld_tensor(m, vn, f, abc);
        lapped__fld_least(abc, 1e-3 / m->diag, z + 2 * f);
    }
    pw_free(a, vn);
    if ((r = lapped__fld_smooth(a, m, conn, fl->smoothing, z, e)) != PW_OK) return r;
    for (f = 0; f < m->nf; f++) known[f] = (unsigned char)lapped__fld_unit(z + 2 * f);
    if ((r = lapped__fld_fill(a, m, conn, 2, up, known, z, e)) != PW_OK) return r;
    for (f = 0; f < m->nf; f++) lapped__fld_halve(z + 2 * f);
    return lapped__fld_orient(a, m, conn, up, z, e);
}

/* ---- the field, the difficulty, and the public entry ----------------------- */

/* §3.2: fills s and t (nf*3 each) for every mode of lapped_field. */
static int lapped__field(const pw_alloc *a, const pw_trimesh *m, const lapped_field *fl, float *s, float *t,
                         pw_err *e)
{
    size_t n = (size_t)m->nf;
    pw_v3 up = pw_v3_load(fl->up);
    double *z, *scales = NULL;
    unsigned char *known;
    float scale = 0.0f, *conn = NULL;
    int r;
    if ((r = lapped__fld_scale(m, fl, &scale, e)) != PW_OK) return r;
    if (fl->mode == LAPPED_FIELD_FACES) return lapped__fld_faces(m, fl, s, t, e);
    if (fl->mode < LAPPED_FIELD_UP || fl->mode > LAPPED_FIELD_CURVATURE)
        return pw_fail(e, PW_ERR_INVALID, "unknown field mode %d", fl->mode);
    if (!pw_is_finite(up.x) || !pw_is_finite(up.y) || !pw_is_finite(up.z) || !(pw_v3_dot(up, up) > 0.0f) ||
        !pw_is_finite(pw_v3_dot(up, up)))
        return pw_fail(e, PW_ERR_INVALID, "field up vector (%g, %g, %g) is zero or not finite", (double)up.x,
                       (double)up.y, (double)up.z);
    z = (double *)pw_alloc_array(a, 3 * n, sizeof(double), "field directions", e);
    known = (unsigned char *)pw_alloc_array(a, n, 1, "field flags", e);
    if (!z || !known || lapped__fld_connection(a, m, &conn, e) != PW_OK)
        r = PW_ERR_NOMEM;
    else if (fl->mode == LAPPED_FIELD_CONSTRAINTS)
        r = lapped__fld_constraints(a, m, fl, scale, conn, z, scales = z + 2 * n, known, e);
    else if (fl->mode == LAPPED_FIELD_CURVATURE)
        r = lapped__fld_curvature(a, m, fl, conn, z, known, e);
    else
        r = lapped__fld_up(a, m, conn, up, z, known, e);
    if (r == PW_OK) lapped__fld_output(m, z, scale, scales, s, t);
    pw_free(a, z);
    pw_free(a, known);
    pw_free(a, conn);
    return r;
}

/* The curvature part of the difficulty across one edge: the turn of the
 * normal (chord |n_f - n_g| = 2 sin(angle/2)) per unit of surface distance,
 * times the local patch size |T|: how far a patch bends there. Mapped to
 * [0, 1) by x / (1 + x). */
static double lapped__fld_bend(const pw_trimesh *m, int h, double size)
{
    pw_v3 dn = pw_v3_sub(lapped__fld_normal(m, h / 3), lapped__fld_normal(m, m->hm.twin[h] / 3));
    double d = lapped__fld_dual_len(m, h), x = d > 0.0 ? pw_v3_len(dn) * size / d : 0.0;
    return x > 0.0 ? x / (1.0 + x) : 0.0;
}

/* §3.3: "Early in the process we give higher priority both to areas of
 * high curvature and to discontinuities in the direction field - where the
 * parametrization is difficult". Per triangle, in [0, 1]: the largest bend
 * over its edges (lapped__fld_bend) combined with the largest turn of T
 * against a neighbour's T unfolded into its plane, (1 - cos)/2 (0 aligned,
 * 1 opposite), as 1 - (1 - bend)(1 - turn). t may be NULL (an isotropic
 * field, whose orientation does not matter): curvature only, at the default
 * scale. */
static int lapped__difficulty(const pw_alloc *a, const pw_trimesh *m, const float *t, float *out, pw_err *e)
{
    int f, k;
    (void)a;
    (void)e;
    for (f = 0; f < m->nf; f++) {
        pw_v3 T = t ? pw_v3_load(t + 3 * f) : pw_v3_make(0, 0, 0);
        double size = t ? pw_v3_len(T) : lapped__default_scale(m), bend = 0.0, turn = 0.0, x;
        for (k = 0; k < 3; k++) {
            int h = 3 * f + k, g = pw_trimesh_across(m, f, k);
            if (g < 0) continue;
            if ((x = lapped__fld_bend(m, h, size)) > bend) bend = x;
            if (t) {
                pw_v3 G = lapped__fld_hinge(m, h, pw_v3_load(t + 3 * g));
                double l = (double)pw_v3_len(T) * pw_v3_len(G);
                x = l > 0.0 ? 0.5 * (1.0 - pw_v3_dot(T, G) / l) : 1.0;
                if (x > turn) turn = x;
            }
        }
        x = 1.0 - (1.0 - bend) * (1.0 - turn);
        out[f] = x >= 0.0 && x <= 1.0 ? (float)x : (x > 1.0 ? 1.0f : 0.0f);
    }
    return PW_OK;
}

/* Public: lapped.h. */
LAPPEDDEF lapped_result lapped_compute_field(const lapped_mesh *mesh, const lapped_options *opt, float *s,
                                             float *t, lapped_error *err)
{
    lapped_options o = lapped__options(opt);
    pw_alloc a = lapped__alloc(&o.allocator);
    pw_trimesh m;
    pw_err e;
    pw_err_clear(&e);
    if (!s || !t)
        pw_fail(&e, PW_ERR_INVALID, "lapped_compute_field: output array %s is NULL", !s ? "s" : "t");
    else if (lapped__mesh_init(&a, mesh, &m, &e) == PW_OK) {
        lapped__field(&a, &m, &o.field, s, t, &e);
        pw_trimesh_free(&a, &m);
    }
    return lapped__done(&e, err);
}
