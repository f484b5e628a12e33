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
 *   UP           up projected onto each face; where up is (within 8
 *                degrees) normal to a face, the neighbours' direction by
 *                propagation that stops at creases sharper than 30 degrees
 *                and is then relaxed to its harmonic extension
 *                (pw_df_up_creased: no bullseye on box tops and caps); a
 *                component wholly normal to up (a flat sheet) takes a
 *                fixed axis.
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
 * The direction-field machinery (frames, connection, propagation,
 * curvature, Dijkstra) is shared with pgp.h in src/common/dirfield.h.
 * Determinism: only + - * / and sqrt; the Gaussians use pw_df_exp_neg
 * (range reduction by ln 2 and a Taylor polynomial, then an exact ldexp)
 * instead of libm's exp. Private helpers carry the prefix lapped__fld_. */
#include "../common/dirfield.h"
#include "core.c"

/* A tenth of the bounding-box diagonal: the documented default patch size. */
static float lapped__default_scale(const pw_trimesh *m) { return 0.1f * m->diag; }

/* opt->scale: 0 means the default; negative or NaN is refused. */
static int lapped__fld_scale(const pw_trimesh *m, const lapped_options *f, float *out, pw_err *e)
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

/* ---- filling the gaps by propagation ------------------------------------- */

/* Writes T = scale * direction (unit z in the triangle frame) and
 * S = T x N (§3.2). scales may be NULL (then `scale` everywhere). */
static void lapped__fld_output(const pw_trimesh *m, const double *z, float scale, const double *scales, float *s,
                               float *t)
{
    int f;
    for (f = 0; f < m->nf; f++) {
        pw_v3 u, v, T;
        float sc = scales ? (float)scales[f] : scale;
        pw_df_frame(m, f, &u, &v);
        T = pw_v3_norm(pw_v3_add(pw_v3_scale(u, (float)z[2 * f]), pw_v3_scale(v, (float)z[2 * f + 1])));
        T = pw_v3_scale(T, sc);
        pw_v3_store(t + 3 * f, T);
        pw_v3_store(s + 3 * f, pw_v3_cross(T, pw_df_normal(m, f)));
    }
}

/* ---- LAPPED_FIELD_UP and ISOTROPIC --------------------------------------- */

/* ---- LAPPED_FIELD_FACES ---------------------------------------------------- */

/* One caller vector of triangle f, projected onto its plane and rescaled to
 * its own length (a vector meant to be tangent keeps its magnitude, the
 * scale). Refuses NaN/Inf, zero, and vectors normal to the face. */
static int lapped__fld_tangent(const pw_trimesh *m, int f, const float *p, const char *what, pw_v3 *out, pw_err *e)
{
    pw_v3 x = pw_v3_load(p), n = pw_df_normal(m, f), q;
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
static int lapped__fld_faces(const pw_trimesh *m, const lapped_options *fl, float *s, float *t, pw_err *e)
{
    int f, r;
    if (!fl->face_t) return pw_fail(e, PW_ERR_INVALID, "FACES field: face_t is NULL");
    for (f = 0; f < m->nf; f++) {
        pw_v3 T, S, n = pw_df_normal(m, f);
        if ((r = lapped__fld_tangent(m, f, fl->face_t + 3 * f, "T", &T, e)) != PW_OK) return r;
        if (!fl->face_s) S = pw_v3_cross(T, n);
        else if ((r = lapped__fld_tangent(m, f, fl->face_s + 3 * f, "S", &S, e)) != PW_OK) return r;
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
        return pw_fail(e, PW_ERR_INVALID, "constraint %d: %s %g is negative or not finite", i, what, (double)x);
    *out = x > 0.0f ? (double)x : def;
    return PW_OK;
}

/* Checks constraint i and resolves its defaults (lapped.h: scale 0 is the
 * field's scale, radius 0 is twice the constraint's scale, weight 0 is 1). */
static int lapped__fld_check(const pw_trimesh *m, const lapped_constraint *in, int i, float scale, lapped__fld_con *c,
                             pw_err *e)
{
    pw_v3 d = pw_v3_load(in->direction), n;
    double z[2];
    int r;
    if (in->face < 0 || in->face >= m->nf)
        return pw_fail(e, PW_ERR_INVALID, "constraint %d: triangle %d is out of range (the mesh has %d)", i, in->face,
                       m->nf);
    if (!pw_is_finite(d.x) || !pw_is_finite(d.y) || !pw_is_finite(d.z) || !pw_is_finite(pw_v3_dot(d, d)))
        return pw_fail(e, PW_ERR_INVALID, "constraint %d: direction is not finite", i);
    if (!(pw_v3_dot(d, d) > 0.0f)) return pw_fail(e, PW_ERR_INVALID, "constraint %d: direction is zero", i);
    if (!pw_df_project(m, in->face, d, z))
        return pw_fail(e, PW_ERR_INVALID, "constraint %d: direction is normal to triangle %d", i, in->face);
    c->face = in->face;
    n = pw_df_normal(m, in->face);
    c->dir = pw_v3_norm(pw_v3_sub(d, pw_v3_scale(n, pw_v3_dot(d, n))));
    if ((r = lapped__fld_value(i, "scale", in->scale, scale, &c->scale, e)) != PW_OK) return r;
    if ((r = lapped__fld_value(i, "radius", in->radius, 2.0 * c->scale, &c->radius, e)) != PW_OK) return r;
    return lapped__fld_value(i, "weight", in->weight, 1.0, &c->weight, e);
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
            g = pw_df_exp_neg(acc->q[f] - q);
            acc->w[f] *= g;
            acc->sc[f] *= g;
            for (k = 0; k < 3; k++) acc->dir[3 * f + k] *= g;
            acc->q[f] = q;
        }
        wt = c->weight * pw_df_exp_neg(q - acc->q[f]);
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
static void lapped__fld_orphans(const pw_trimesh *m, const lapped__fld_con *c, int nc, lapped__fld_acc *acc, int *stack)
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
static int lapped__fld_checks(const pw_trimesh *m, const lapped_options *fl, float scale, lapped__fld_con *c, pw_err *e)
{
    int i, r;
    for (i = 0; i < fl->nconstraints; i++)
        if ((r = lapped__fld_check(m, fl->constraints + i, i, scale, c + i, e)) != PW_OK) return r;
    return PW_OK;
}

/* The blended 3D directions projected onto each face (§3.2: vectors "at
 * the remaining faces"), and the blended scales. A blend that cancels or is
 * normal to its face is filled from the neighbours. */
static int lapped__fld_blend(const pw_alloc *a, const pw_df_field *F, pw_v3 up, const lapped__fld_acc *acc,
                             double *scales, pw_err *e)
{
    const pw_trimesh *m = F->m;
    int f;
    for (f = 0; f < m->nf; f++) {
        double w = acc->w[f];
        pw_v3 d = pw_v3_make((float)(acc->dir[3 * f] / w), (float)(acc->dir[3 * f + 1] / w),
                             (float)(acc->dir[3 * f + 2] / w));
        F->known[f] = (unsigned char)(pw_v3_dot(d, d) > 1e-8f && pw_df_project(m, f, d, F->z + 2 * f));
        scales[f] = acc->sc[f] / w;
    }
    return pw_df_fill(a, F, 1, up, e);
}

/* §3.2: "the user specifies vectors at a few faces. We interpolate vectors
 * at the remaining faces using Gaussian radial basis functions, where radius
 * is defined as distance over the mesh, as computed using Dijkstra's
 * algorithm. The user has control over the spatial extent and weight of each
 * basis function." Weight of constraint i at triangle f:
 * weight_i exp(-d_i(f)^2 / (2 radius_i^2)); directions are blended in 3D
 * and projected onto f, scales blended linearly. One Dijkstra run per
 * constraint: O(nconstraints * nf log nf) time, O(nf) memory. */
static int lapped__fld_constraints(const pw_alloc *a, const pw_df_field *F, const lapped_options *fl, float scale,
                                   double *scales, pw_err *e)
{
    const pw_trimesh *m = F->m;
    size_t n = (size_t)m->nf;
    int nc = fl->nconstraints, i, f, r = PW_OK;
    lapped__fld_con *c;
    double *len, *dist;
    lapped__fld_acc acc;
    pw_heap hp;
    if (nc < 1 || !fl->constraints)
        return pw_fail(e, PW_ERR_INVALID, "CONSTRAINTS field needs constraints (nconstraints %d%s)", nc,
                       fl->constraints ? "" : ", constraints NULL");
    c = (lapped__fld_con *)pw_alloc_array(a, (size_t)nc, sizeof *c, "constraints", e);
    len = (double *)pw_alloc_array(a, 13 * n + 1, sizeof(double), "geodesic distances", e);
    memset(&hp, 0, sizeof hp);
    hp.item = (int *)pw_alloc_array(a, 3 * n + 1, sizeof(int), "Dijkstra heap", e);
    if (!c || !len || !hp.item) r = PW_ERR_NOMEM;
    if (r == PW_OK) r = lapped__fld_checks(m, fl, scale, c, e);
    if (r == PW_OK) {
        dist = len + 3 * n;
        hp.key = dist + n;
        acc.q = hp.key + 3 * n + 1;
        acc.w = acc.q + n;
        acc.sc = acc.w + n;
        acc.dir = acc.sc + n;
        for (f = 0; f < m->nf; f++) acc.q[f] = DBL_MAX;
        memset(acc.w, 0, 5 * n * sizeof(double));
        pw_df_dual(m, len);
        for (i = 0; i < nc; i++) {
            pw_df_dijkstra(m, len, c[i].face, dist, &hp);
            lapped__fld_accumulate(m->nf, dist, c + i, &acc);
        }
        lapped__fld_pin(c, nc, &acc);
        lapped__fld_orphans(m, c, nc, &acc, hp.item);
        r = lapped__fld_blend(a, F, pw_v3_load(fl->up), &acc, scales, e);
    }
    pw_free(a, c);
    pw_free(a, len);
    pw_free(a, hp.item);
    return r;
}

/* ---- LAPPED_FIELD_CURVATURE ------------------------------------------------ */

/* The paper's future work: "automatic direction field construction using
 * surface curvatures". Per-triangle curvature tensors from vertex normals
 * (Rusinkiewicz, "Estimating curvatures and their derivatives on triangle
 * meshes", 3DPVT 2004, §3), the direction of least absolute curvature as a
 * line field (up to sign), smoothed, gaps filled from the neighbours, then
 * one sign chosen by a breadth-first walk. */

/* ---- the field, the difficulty, and the public entry ----------------------- */

/* §3.2: fills s and t (nf*3 each) for every lapped_field_mode. */
static int lapped__field(const pw_alloc *a, const pw_trimesh *m, const lapped_options *fl, float *s, float *t,
                         pw_err *e)
{
    size_t n = (size_t)m->nf;
    pw_v3 up = pw_v3_load(fl->up);
    double *z, *scales = NULL;
    unsigned char *known;
    float scale = 0.0f, *conn = NULL;
    pw_df_field F;
    int r;
    if ((r = lapped__fld_scale(m, fl, &scale, e)) != PW_OK) return r;
    if (fl->field == LAPPED_FIELD_FACES) return lapped__fld_faces(m, fl, s, t, e);
    if ((int)fl->field < LAPPED_FIELD_UP || (int)fl->field > LAPPED_FIELD_CURVATURE)
        return pw_fail(e, PW_ERR_INVALID, "unknown field mode %d", (int)fl->field);
    if (!pw_is_finite(up.x) || !pw_is_finite(up.y) || !pw_is_finite(up.z) || !(pw_v3_dot(up, up) > 0.0f) ||
        !pw_is_finite(pw_v3_dot(up, up)))
        return pw_fail(e, PW_ERR_INVALID, "field up vector (%g, %g, %g) is zero or not finite", (double)up.x,
                       (double)up.y, (double)up.z);
    z = (double *)pw_alloc_array(a, 3 * n, sizeof(double), "field directions", e);
    known = (unsigned char *)pw_alloc_array(a, n, 1, "field flags", e);
    if (!z || !known || pw_df_connection(a, m, &conn, e) != PW_OK) r = PW_ERR_NOMEM;
    F.m = m;
    F.conn = conn;
    F.z = z;
    F.known = known;
    if (r == PW_OK && fl->field == LAPPED_FIELD_CONSTRAINTS)
        r = lapped__fld_constraints(a, &F, fl, scale, scales = z + 2 * n, e);
    else if (r == PW_OK && fl->field == LAPPED_FIELD_CURVATURE)
        r = pw_df_curvature(a, &F, pw_v3_load(fl->up), fl->smoothing, e);
    else if (r == PW_OK) r = pw_df_up_creased(a, &F, up, e);
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
    pw_v3 dn = pw_v3_sub(pw_df_normal(m, h / 3), pw_df_normal(m, m->hm.twin[h] / 3));
    double d = pw_df_dual_len(m, h), x = d > 0.0 ? pw_v3_len(dn) * size / d : 0.0;
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
                pw_v3 G = pw_df_hinge(m, h, pw_v3_load(t + 3 * g));
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
LAPPEDDEF lapped_result lapped_compute_field(const lapped_mesh *mesh, const lapped_options *opt, lapped_field *out,
                                             lapped_error *err)
{
    lapped_options o = lapped__options(opt);
    pw_alloc a = lapped__alloc(&o.allocator);
    pw_trimesh m;
    pw_err e;
    pw_err_clear(&e);
    if (out) memset(out, 0, sizeof *out);
    if (!out) pw_fail(&e, PW_ERR_INVALID, "lapped_compute_field: NULL output");
    else if (lapped__mesh_init(&a, mesh, &m, &e) == PW_OK) {
        out->allocator = lapped__allocator(&a);
        out->s = (float *)pw_alloc_array(&a, (size_t)m.nf * 3, sizeof(float), "field", &e);
        out->t = (float *)pw_alloc_array(&a, (size_t)m.nf * 3, sizeof(float), "field", &e);
        if (out->s && out->t && lapped__field(&a, &m, &o, out->s, out->t, &e) == PW_OK) out->ntris = m.nf;
        else lapped_field_free(out);
        pw_trimesh_free(&a, &m);
    }
    return lapped__done(&e, err);
}

LAPPEDDEF void lapped_field_free(lapped_field *f)
{
    pw_alloc a;
    if (!f) return;
    a = lapped__alloc(&f->allocator);
    pw_free(&a, f->s);
    pw_free(&a, f->t);
    memset(f, 0, sizeof *f);
}
