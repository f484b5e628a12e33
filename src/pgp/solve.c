/* solve.c: §2.3 the periodic global parameterization, the recovery of
 * per-corner coordinates (Eq. 4), the §3 detection of singular 1-rings, the
 * recomputation of an effect area that every edit runs, and the map of a
 * mesh before any constraint (edit.c holds the public editing calls). */
#include "field.c"

/* ---- Eq. (4): per-corner coordinates -------------------------------------------------- */

/* s, t (the shared recovery, src/common/periodic.h) and m of triangle f's
 * corners. */
static void pgp__recover(pgp__state *P, int f)
{
    const int *tri = P->pp.m.tri + 3 * f;
    float *o = P->pp.stm + 9 * f;
    int c;
    pw_periodic_recover(&P->pp, f);
    for (c = 0; c < 3; c++) o[3 * c + 2] = P->mat[tri[c]];
}

/* The triangles of an area whose coordinates Eq. (4) recovers, by blocks
 * on the solves' threads (each triangle writes its own corners). */
typedef struct pgp__recovery {
    pgp__state *P;
    const int *order;
    int n, nb;
} pgp__recovery;

static void pgp__recover_block(void *ctx, int b)
{
    const pgp__recovery *w = (const pgp__recovery *)ctx;
    int i, hi = pw__zblock_start(w->n, w->nb, b + 1);
    for (i = pw__zblock_start(w->n, w->nb, b); i < hi; i++) pgp__recover(w->P, w->order[i]);
}

/* ---- §3 singular 1-rings --------------------------------------------------------------- */

/* "Highly distorted": ||grad s - g_s||^2 > threshold, or the same for t.
 * The paper's 0.5 is read relative to |g|^2 = 1/S^2 (the paper's tiles have
 * unit size), so that the test does not depend on the units of the mesh. */
static int pgp__distorted(const pgp__state *P, int f)
{
    const float *o = P->pp.stm + 9 * f;
    int k;
    for (k = 0; k < 2; k++) {
        pw_v3 g = pw_periodic_grad(&P->pp, f, k),
              d = pw_v3_sub(pw_periodic_gradient(&P->pp, f, o[k], o[3 + k], o[6 + k]), g);
        if ((double)pw_v3_dot(d, d) > (double)P->o.singular_distortion * pw_v3_dot(g, g)) return 1;
    }
    return 0;
}

/* Whether the two triangles of half-edge h disagree on the coordinate
 * difference along it (s_i^T - s_j^T != s_i^T' - s_j^T', or for t). */
static int pgp__mismatch(const pgp__state *P, int h)
{
    int t = P->pp.m.hm.twin[h], f = h / 3, g, c = h % 3, d, k;
    if (t < 0) return 0;
    g = t / 3;
    d = t % 3; /* h runs from corner c to c+1 of f, t from corner d to d+1 of g */
    for (k = 0; k < 2; k++) {
        double df = P->pp.stm[9 * f + 3 * ((c + 1) % 3) + k] - P->pp.stm[9 * f + 3 * c + k];
        double dg = P->pp.stm[9 * g + 3 * d + k] - P->pp.stm[9 * g + 3 * ((d + 1) % 3) + k];
        if (fabs(df - dg) > 0.5) return 1;
    }
    return 0;
}

/* The triangles around which s or t winds (flags: 1 for s, 2 for t). */
static int pgp__vortices(const pgp__state *P, unsigned char *flags)
{
    int f, n = 0;
    for (f = 0; f < P->pp.m.nf; f++) {
        unsigned char v =
            (unsigned char)((pw_periodic_winding(&P->pp, f, 0) != 0) + 2 * (pw_periodic_winding(&P->pp, f, 1) != 0));
        if (flags) flags[f] = v;
        n += v != 0;
    }
    return n;
}

PGPDEF int pgp_map_vortices(const pgp_map *map, unsigned char *flags)
{
    const pgp__state *P = pgp__state_of(map);
    return P ? pgp__vortices(P, flags) : 0;
}

/* The distorted triangles of a block, on the solves' threads. */
typedef struct pgp__distortion_job {
    const pgp__state *P;
    unsigned char *dist;
    int nb;
} pgp__distortion_job;

static void pgp__distorted_block(void *ctx, int b)
{
    const pgp__distortion_job *w = (const pgp__distortion_job *)ctx;
    int f, nf = w->P->pp.m.nf, hi = pw__zblock_start(nf, w->nb, b + 1);
    for (f = pw__zblock_start(nf, w->nb, b); f < hi; f++) w->dist[f] = (unsigned char)pgp__distorted(w->P, f);
}

/* §3: a vertex's 1-ring is singular if it holds a distorted triangle or a
 * spoke edge whose two triangles disagree; a triangle is singular (drawn
 * with three lookups) if one of its corners is. */
static int pgp__singularities(pgp__state *P, pw_err *e)
{
    unsigned char *dist = (unsigned char *)pw_alloc_array(&P->a, (size_t)P->pp.m.nf, 1, "singularities", e);
    pgp__distortion_job job;
    int f, c, h;
    if (!dist) return PW_ERR_NOMEM;
    memset(P->vsing, 0, (size_t)P->pp.m.nv);
    job.P = P;
    job.dist = dist;
    job.nb = pw__zblocks(P->pp.m.nf);
    pw__zfor(&P->pp.run, P->pp.m.nf, job.nb, pgp__distorted_block, &job);
    for (h = 0; h < 3 * P->pp.m.nf; h++) {
        int f3 = h / 3, c3 = h % 3;
        if (dist[f3]) P->vsing[P->pp.m.tri[h]] = 1;
        if (pgp__mismatch(P, h)) P->vsing[P->pp.m.tri[h]] = P->vsing[P->pp.m.tri[3 * f3 + (c3 + 1) % 3]] = 1;
    }
    P->nsing = 0;
    for (f = 0; f < P->pp.m.nf; f++) {
        P->fsing[f] = 0;
        for (c = 0; c < 3; c++) P->fsing[f] |= P->vsing[P->pp.m.tri[3 * f + c]];
        P->nsing += P->fsing[f];
    }
    pw_free(&P->a, dist);
    return PW_OK;
}

/* ---- edits: §2's three steps over an effect area ------------------------------------------ */

/* Recomputes the fields of `kind` and the coordinates over the area around
 * the seed triangles (radius <= 0: the whole mesh). */
static int pgp__edit(pgp__state *P, pgp_constraint_kind kind, const pgp__seeds *sd, pgp_area *area, pw_err *e)
{
    const float radius = sd->radius;
    size_t nf = (size_t)P->pp.m.nf, nv = (size_t)P->pp.m.nv;
    unsigned char *in = (unsigned char *)pw_alloc_array(&P->a, 2 * nf + 2 * nv, 1, "effect area", e);
    int *order = (int *)pw_alloc_array(&P->a, nf, sizeof(int), "effect area", e);
    pw_progress pr = pgp__progress(&P->o);
    int n = 0, whole = !(radius > 0.0f), r = in && order ? PW_OK : PW_ERR_NOMEM;
    pgp__recovery rec;
    unsigned char *mark = in + nf, *vfree = in + 2 * nf, *locked = vfree + nv;
    if (r == PW_OK) r = pgp__area(P, sd, in, order, &n, e);
    if (r == PW_OK) pgp__free_vertices(P, in, vfree);
    if (r == PW_OK) r = pw_report(&pr, 0.2f, "interpolation", e);
    if (r == PW_OK && kind == PGP_CONSTRAINT_ORIENT) r = pgp__interp_dir(P, in, whole, mark, e);
    if (r == PW_OK && kind != PGP_CONSTRAINT_ORIENT) r = pgp__interp_vertex(P, kind, vfree, whole, locked, e);
    if (r == PW_OK) r = pw_report(&pr, 0.4f, "periodic global parameterization", e);
    if (r == PW_OK && kind != PGP_CONSTRAINT_MATERIAL) r = pw_periodic_solve(&P->pp, vfree, whole, e);
    rec.P = P;
    rec.order = order;
    rec.n = n;
    rec.nb = pw__zblocks(n);
    if (r == PW_OK) pw__zfor(&P->pp.run, n, rec.nb, pgp__recover_block, &rec);
    if (r == PW_OK) r = pw_report(&pr, 0.9f, "singularities", e);
    if (r == PW_OK) r = pgp__singularities(P, e);
    if (r == PW_OK && area) {
        area->faces = (int *)pw_alloc_array(&P->a, (size_t)n, sizeof(int), "effect area", e);
        if (!area->faces) r = PW_ERR_NOMEM;
        else {
            memcpy(area->faces, order, sizeof(int) * (size_t)n);
            area->nfaces = n;
        }
        area->allocator = pgp__allocator(&P->a);
    }
    pw_free(&P->a, in);
    pw_free(&P->a, order);
    return r;
}

/* ---- creation -------------------------------------------------------------------------- */

static void pgp__state_free(pgp__state *P)
{
    pw_alloc a;
    if (!P) return;
    a = P->a;
    pw_periodic_free(&P->pp);
    pw_free(&a, P->pos);
    pw_free(&a, P->mat);
    pw_free(&a, P->vsing);
    pw_free(&a, P->con);
    pw_free(&a, P);
}

PGPDEF void pgp_map_free(pgp_map *map)
{
    if (!map) return;
    pgp__state_free(map->state);
    memset(map, 0, sizeof *map);
}

static int pgp__check_options(const pgp_options *o, pw_err *e)
{
    if (o->field != PGP_FIELD_UP && o->field != PGP_FIELD_CURVATURE)
        return pw_fail(e, PW_ERR_INVALID, "unknown field mode %d", o->field);
    if (!pw_is_finite(o->up[0]) || !pw_is_finite(o->up[1]) || !pw_is_finite(o->up[2]))
        return pw_fail(e, PW_ERR_INVALID, "up vector is not finite");
    if (!(o->scale >= 0.0f) || !pw_is_finite(o->scale))
        return pw_fail(e, PW_ERR_INVALID, "scale %g is not a positive finite number", (double)o->scale);
    if (!(o->material >= 0.0f && o->material <= 1.0f))
        return pw_fail(e, PW_ERR_INVALID, "default material %g is not in [0, 1]", (double)o->material);
    if (!(o->min_scale > 0.0f && o->min_scale <= 1.0f))
        return pw_fail(e, PW_ERR_INVALID, "min_scale %g is not in (0, 1]", (double)o->min_scale);
    if (!(o->singular_distortion > 0.0f) || !pw_is_finite(o->singular_distortion))
        return pw_fail(e, PW_ERR_INVALID, "singular_distortion %g is not positive", (double)o->singular_distortion);
    if (o->smoothing < 0) return pw_fail(e, PW_ERR_INVALID, "smoothing %d is negative", o->smoothing);
    if (o->threads < 0) return pw_fail(e, PW_ERR_INVALID, "threads %d is negative", o->threads);
    if (!(o->integrable >= 0.0f && o->integrable <= 1e6f))
        return pw_fail(e, PW_ERR_INVALID, "integrable %g is not in [0, 1e6]", (double)o->integrable);
    if (o->weights != PGP_WEIGHTS_COTAN && o->weights != PGP_WEIGHTS_AREA)
        return pw_fail(e, PW_ERR_INVALID, "unknown weights %d", o->weights);
    return PW_OK;
}

/* Copies the mesh, builds the triangle mesh and allocates every array. */
static int pgp__setup(pgp__state *P, const pgp_mesh *in, pw_err *e)
{
    pw_mesh v;
    int r;
    if (!in || !in->positions || in->nverts < 1) return pw_fail(e, PW_ERR_INVALID, "no mesh or no vertices");
    if (in->nverts > PW_MAX_MESH_ELEMENTS) return pw_fail(e, PW_ERR_LIMIT, "%d vertices is over the limit", in->nverts);
    P->pos = (float *)pw_alloc_array(&P->a, (size_t)in->nverts * 3, sizeof(float), "positions", e);
    if (!P->pos) return PW_ERR_NOMEM;
    memcpy(P->pos, in->positions, sizeof(float) * 3 * (size_t)in->nverts);
    v = pgp__pw_mesh(in);
    v.pos = P->pos; /* the map's own copy */
    P->pp.area_weights = P->o.weights == PGP_WEIGHTS_AREA;
    if ((r = pw_periodic_init(&P->pp, &v, e)) != PW_OK) return r;
    P->mat = (float *)pw_alloc_array(&P->a, (size_t)P->pp.m.nv, sizeof(float), "mapping", e);
    P->vsing = (unsigned char *)pw_calloc_array(&P->a, (size_t)(P->pp.m.nv + P->pp.m.nf), 1, "mapping", e);
    if (!P->mat || !P->vsing) return PW_ERR_NOMEM;
    P->fsing = P->vsing + P->pp.m.nv;
    return PW_OK;
}

/* ---- beyond the paper: an integrable field --------------------------------------------- */

/* Adds triangle f's two rows to the normal equations of the curl
 * reduction. The circulation c = alpha_01 + alpha_12 + alpha_20 of s (and
 * of t) around f is what the PGP cannot follow: every whole turn it sums to
 * over a region is a vortex. A factor (1 + u) of the tile side and a
 * rotation theta of the field change alpha_e by -alpha_e u_e (s and t) and
 * +theta_e alpha^t_e (s) or -theta_e alpha^s_e (t), u_e and theta_e the
 * means over the edge's ends; each row asks c + those = 0, weighted by
 * 1 / area so that the sum is the integral of the squared curl. The part
 * of u common to the triangle only scales c (larger tiles, fewer periods,
 * fewer vortices: not what is asked) and is left out of the rows, so only
 * the variation of the tile side cancels curl: the conformal factor that
 * cancels the Gaussian curvature, which a rotation alone cannot (on CGAL's
 * meshes rotation alone removes no vortex). Unknowns: u_i at 2 i, theta_i
 * at 2 i + 1. */
static int pgp__curl_rows(const pgp__state *P, int f, pw_triplets *t, double *b, pw_err *e)
{
    double al[2][3], row[6], c, w = 1.0 / ((double)P->pp.m.area[f] + 1e-300);
    int k, a, i, j, col[6], r = PW_OK;
    for (k = 0; k < 2; k++)
        for (a = 0; a < 3; a++) al[k][a] = pw_periodic_alpha(&P->pp, 3 * f + a, k);
    for (k = 0; k < 2 && r == PW_OK; k++) {
        for (a = 0, c = 0.0; a < 3; a++) c += al[k][a];
        for (a = 0; a < 3; a++) { /* corner a touches edges a and a - 1 */
            int am = (a + 2) % 3;
            col[2 * a] = 2 * P->pp.m.tri[3 * f + a];
            col[2 * a + 1] = col[2 * a] + 1;
            row[2 * a] = -0.5 * (al[k][a] + al[k][am]) + c / 3.0;
            row[2 * a + 1] = (k ? -0.5 : 0.5) * (al[1 - k][a] + al[1 - k][am]);
        }
        for (i = 0; i < 6; i++) {
            b[col[i]] -= w * row[i] * c;
            for (j = 0; j < 6 && r == PW_OK; j++) r = pw_triplets_add(t, col[i], col[j], w * row[i] * row[j], e);
        }
    }
    return r;
}

/* Adds the terms that keep the correction small and smooth: integrable^-1
 * A_i / S^4 (u_i^2 + theta_i^2) (how far from the field; the rows above
 * integrate curl^2 ~ |grad theta|^2 / S^2, so u and theta vary over about
 * sqrt(integrable) tiles) and 0.01 / S^2 of the cotangent Dirichlet energy
 * of u and theta. */
static int pgp__curl_reg(const pgp__state *P, pw_triplets *t, pw_err *e)
{
    double S2 = (double)P->pp.scale0 * P->pp.scale0, lam = 1.0 / ((double)P->o.integrable * S2 * S2), w;
    int h, k, i, j, r = PW_OK;
    for (h = 0; h < 3 * P->pp.m.nf && r == PW_OK; h++) {
        i = P->pp.m.tri[h];
        j = P->pp.m.tri[3 * (h / 3) + (h % 3 + 1) % 3];
        for (k = 0; k < 2 && r == PW_OK; k++) /* a third of the triangle's area to each corner */
            r = pw_triplets_add(t, 2 * i + k, 2 * i + k, lam * P->pp.m.area[h / 3] / 3.0, e);
        if (P->pp.m.hm.twin[h] >= 0 && P->pp.m.hm.twin[h] < h) continue;
        w = 0.01 * pw_periodic_lap_weight(&P->pp.m, h) / S2;
        for (k = 0; k < 2 && r == PW_OK; k++) {
            r = pw_triplets_add(t, 2 * i + k, 2 * i + k, w, e);
            if (r == PW_OK) r = pw_triplets_add(t, 2 * j + k, 2 * j + k, w, e);
            if (r == PW_OK) r = pw_triplets_add(t, 2 * i + k, 2 * j + k, -w, e);
            if (r == PW_OK) r = pw_triplets_add(t, 2 * j + k, 2 * i + k, -w, e);
        }
    }
    return r;
}

/* Applies the correction x (u, theta per vertex): the factor of every S_i
 * (u less its area-weighted mean, the factor kept in [1/2, 2]) and the rotation of the default field of every
 * triangle by the mean theta of its corners. */
static void pgp__curl_apply(pgp__state *P, const double *x)
{
    double mean = 0.0, area = 0.0;
    int v, f, h;
    for (h = 0; h < 3 * P->pp.m.nf; h++) /* the mean of u is 0: the tile side the user asked for */
    {
        mean += x[2 * P->pp.m.tri[h]] * P->pp.m.area[h / 3];
        area += P->pp.m.area[h / 3];
    }
    mean = area > 0.0 ? mean / area : 0.0;
    for (v = 0; v < P->pp.m.nv; v++) {
        double s = P->pp.sfac[v] * (1.0 + x[2 * v] - mean);
        P->pp.sfac[v] = (float)(s < 0.5 ? 0.5 : (s > 2.0 ? 2.0 : s));
    }
    for (f = 0; f < P->pp.m.nf; f++) {
        const int *tr = P->pp.m.tri + 3 * f;
        double th = (x[2 * tr[0] + 1] + x[2 * tr[1] + 1] + x[2 * tr[2] + 1]) / 3.0, c, s, *d = P->pp.base + 2 * f;
        th = th > 0.5 ? 0.5 : (th < -0.5 ? -0.5 : th); /* at most ~30 degrees per step */
        c = pw_cos(th);
        s = pw_sin(th);
        th = c * d[0] - s * d[1];
        d[1] = s * d[0] + c * d[1];
        d[0] = th;
        P->pp.dir[2 * f] = d[0];
        P->pp.dir[2 * f + 1] = d[1];
    }
}

/* options.integrable > 0: three Gauss-Newton steps of the curl reduction
 * (beyond the paper: the PGP of §2.3 follows a field whose gradients have
 * curl, and each whole turn of it is a vortex; the trade is documented in
 * docs/pgp.md). */
#define PGP__CURL_STEPS 3
static int pgp__integrable(pgp__state *P, pw_err *e)
{
    size_t n = 2 * (size_t)P->pp.m.nv;
    double *b = (double *)pw_alloc_array(&P->a, 2 * n, sizeof(double), "integrability", e), *x = b + n;
    pw_triplets t;
    int step, f, r = b ? PW_OK : PW_ERR_NOMEM;
    memset(&t, 0, sizeof t);
    memcpy(P->pp.dir, P->pp.base, sizeof(double) * 2 * (size_t)P->pp.m.nf);
    for (step = 0; step < PGP__CURL_STEPS && r == PW_OK; step++) {
        memset(b, 0, sizeof(double) * 2 * n); /* b and x, a cold start: x is the step */
        r = pw_triplets_init(&t, &P->a, (int)n, (int)n, e);
        for (f = 0; f < P->pp.m.nf && r == PW_OK; f++) r = pgp__curl_rows(P, f, &t, b, e);
        if (r == PW_OK) r = pgp__curl_reg(P, &t, e);
        if (r == PW_OK) r = pw_periodic_pd_solve(&P->pp, &t, b, x, 1e-6, e);
        if (r == PW_OK) pgp__curl_apply(P, x);
        pw_triplets_free(&t);
    }
    pw_free(&P->a, b);
    return r;
}

/* The three axes the up field is tried along with options.integrable: up,
 * the world axis least parallel to it made perpendicular, and their cross
 * product. */
static void pgp__axes(const float *up3, float *ax)
{
    float u[3], w[3] = {0.0f, 0.0f, 0.0f};
    pw_v3 up = pw_v3_norm(pw_v3_load(up3)), a;
    int c, least = 0;
    pw_v3_store(u, up);
    for (c = 1; c < 3; c++)
        if (fabsf(u[c]) < fabsf(u[least])) least = c;
    w[least] = 1.0f;
    a = pw_v3_norm(pw_v3_sub(pw_v3_load(w), pw_v3_scale(up, u[least])));
    pw_v3_store(ax, up);
    pw_v3_store(ax + 3, a);
    pw_v3_store(ax + 6, pw_v3_cross(up, a));
}

/* The default field with options.integrable. An up field has two poles
 * (on a closed surface of genus 0), and around each the curl the
 * correction cannot cancel (the tile side stops shrinking at 1/2) is as
 * many vortices as periods fit around the pole there: on CGAL's mushroom,
 * up = +Y puts the poles on the rim of its round cap, 9 vortices each, Z
 * at the centres of the cap's top and of the square foot, 15 in all (at
 * the cap). So the up field is tried
 * along three perpendicular axes (pgp__axes), each made integrable and
 * parameterized, and the one with the fewest vortices is kept (the first
 * on a tie: up itself). The least-curvature field has no axis to choose. */
static int pgp__integrable_field(pgp__state *P, pw_err *e)
{
    size_t nf = (size_t)P->pp.m.nf, nv = (size_t)P->pp.m.nv;
    double *keep = (double *)pw_alloc_array(&P->a, 2 * nf, sizeof(double), "integrability", e);
    float *kfac = (float *)pw_alloc_array(&P->a, nv, sizeof(float), "integrability", e), ax[9];
    unsigned char *all = (unsigned char *)pw_alloc_array(&P->a, nv, 1, "integrability", e);
    int c, f, v, n, best = -1, ncand = P->o.field == PGP_FIELD_CURVATURE ? 1 : 3,
                    r = keep && kfac && all ? PW_OK : PW_ERR_NOMEM;
    pgp__axes(P->o.up, ax);
    if (all) memset(all, 1, nv);
    for (c = 0; c < ncand && r == PW_OK; c++) {
        for (v = 0; v < P->pp.m.nv; v++) P->pp.sfac[v] = 1.0f;
        r = pw_periodic_base_field(&P->pp, c ? ax + 3 * c : P->o.up, P->o.field == PGP_FIELD_CURVATURE, P->o.smoothing,
                                   e);
        if (r == PW_OK) r = pgp__integrable(P, e);
        if (r == PW_OK && ncand > 1) r = pw_periodic_solve(&P->pp, all, 1, e);
        for (f = 0; r == PW_OK && ncand > 1 && f < P->pp.m.nf; f++) pw_periodic_recover(&P->pp, f);
        n = r == PW_OK && ncand > 1 ? pgp__vortices(P, NULL) : 0;
        if (r == PW_OK && (best < 0 || n < best)) {
            best = n;
            memcpy(keep, P->pp.base, sizeof(double) * 2 * nf);
            memcpy(kfac, P->pp.sfac, sizeof(float) * nv);
        }
    }
    if (r == PW_OK) {
        memcpy(P->pp.base, keep, sizeof(double) * 2 * nf);
        memcpy(P->pp.dir, keep, sizeof(double) * 2 * nf);
        memcpy(P->pp.sfac, kfac, sizeof(float) * nv);
    }
    pw_free(&P->a, keep);
    pw_free(&P->a, kfac);
    pw_free(&P->a, all);
    return r;
}

/* A tile side the mesh can carry: at most 10 bounding-box diagonals (beyond,
 * the whole mesh is one colour) and at least 2 mean edge lengths (below, a
 * period spans less than two triangles and Eq. 4 cannot recover it). Only
 * a side the caller gave is refused: the default (diag / 10) is kept on
 * meshes of a few triangles, where it is all one can do. */
static int pgp__check_scale(const pgp__state *P, pw_err *e)
{
    return P->o.scale > 0.0f ? pw_periodic_check_scale(&P->pp, P->pp.scale0, e) : PW_OK;
}

/* The map of a mesh without constraints (pgp_create, edit.c, adds them):
 * the default field, scale and material and the initial parameterization. */
/* pgp_create's work on its state P: the mesh, the field and the PGP. */
static int pgp__map_solve(pgp__state *P, const pgp_mesh *mesh, pw_err *e)
{
    const pgp_options *o = &P->o;
    pgp__seeds whole; /* no seeds, radius 0: the whole mesh */
    int v;
    whole.tri = NULL;
    whole.n = 0;
    whole.radius = 0.0f;
    if (pgp__setup(P, mesh, e) != PW_OK) return e->code;
    P->pp.scale0 = o->scale > 0.0f ? o->scale : 0.1f * P->pp.m.diag;
    for (v = 0; v < P->pp.m.nv; v++) {
        P->pp.scale[v] = P->pp.scale0;
        P->pp.sfac[v] = 1.0f;
        P->mat[v] = o->material;
    }
    for (v = 0; v < P->pp.m.nv; v++) {
        P->pp.zs[2 * v] = P->pp.zt[2 * v] = 1.0;
        P->pp.zs[2 * v + 1] = P->pp.zt[2 * v + 1] = 0.0;
    }
    if (pgp__check_scale(P, e) != PW_OK ||
        (o->integrable > 0.0f
             ? pgp__integrable_field(P, e)
             : pw_periodic_base_field(&P->pp, o->up, o->field == PGP_FIELD_CURVATURE, o->smoothing, e)) != PW_OK ||
        pgp__edit(P, PGP_CONSTRAINT_ORIENT, &whole, NULL, e) != PW_OK)
        return e->code;
    return PW_OK;
}

static int pgp__create_map(const pgp_mesh *mesh, const pgp_options *opt, pgp_map *out, pw_err *e)
{
    pgp_options o = pgp__options(opt);
    pw_alloc a = pgp__alloc(&o.allocator);
    pgp__state *P;
    int r;
    if (pgp__check_options(&o, e) != PW_OK ||
        (P = (pgp__state *)pw_calloc_array(&a, 1, sizeof *P, "mapping", e)) == NULL)
        return e->code;
    P->a = a;
    P->pp.a = a;
    P->o = o;
    P->par = pw_parallel_make(o.threads, o.parallel, o.parallel_pool);
    P->pp.run.pfor = pw_parallel_for;
    P->pp.run.par = &P->par;
    P->pp.run.width = pw_parallel_width(&P->par);
    out->state = P;
    out->allocator = pgp__allocator(&a);
    pw_parallel_start(&P->par); /* one crew for the whole map's solves */
    r = pgp__map_solve(P, mesh, e);
    pw_parallel_stop(&P->par);
    if (r != PW_OK) return r;
    out->nverts = P->pp.m.nv;
    out->ntris = P->pp.m.nf;
    out->tris = P->pp.m.tri;
    out->coords = P->pp.stm;
    return PW_OK;
}

/* ---- what happened (issue 17) ------------------------------------------------------------ */

/* Stretch (1) and shear (2) flags of triangle f: the singular values of
 * J = S (grad s; grad t) in the triangle's frame outside [1/1.3, 1.3], S
 * the side the user asked for (without the integrability factor), the
 * angle between grad s and grad t more than 20 degrees off 90. */
static int pgp__distortion(const pgp__state *P, int f)
{
    const float *o = P->pp.stm + 9 * f, *sc = P->pp.scale;
    const int *tr3 = P->pp.m.tri + 3 * f;
    double S = ((double)sc[tr3[0]] + sc[tr3[1]] + sc[tr3[2]]) / 3.0, a, b, c, d, tr, det, disc, s1, s2, cs;
    pw_v3 u, v, gs = pw_periodic_gradient(&P->pp, f, o[0], o[3], o[6]),
                gt = pw_periodic_gradient(&P->pp, f, o[1], o[4], o[7]);
    pw_periodic_frame(&P->pp, f, &u, &v);
    a = S * pw_v3_dot(gs, u);
    b = S * pw_v3_dot(gs, v);
    c = S * pw_v3_dot(gt, u);
    d = S * pw_v3_dot(gt, v);
    tr = a * a + b * b + c * c + d * d;
    det = a * d - b * c; /* s1^2 + s2^2 and s1 s2 */
    disc = tr * tr - 4.0 * det * det;
    disc = sqrt(disc > 0.0 ? disc : 0.0);
    s1 = sqrt(0.5 * (tr + disc));
    s2 = tr > disc ? sqrt(0.5 * (tr - disc)) : 0.0;
    cs = (a * c + b * d) / (sqrt(a * a + b * b) * sqrt(c * c + d * d) + 1e-300);
    return (s1 > 1.3 || s2 < 1.0 / 1.3) + 2 * (fabs(cs) > 0.3420201433); /* sin 20 deg */
}

PGPDEF void pgp_map_stats(const pgp_map *map, pgp_stats *out)
{
    const pgp__state *P = pgp__state_of(map);
    double total = 0.0, st = 0.0, sh = 0.0;
    int f, d;
    if (!out) return;
    memset(out, 0, sizeof *out);
    if (!P) return;
    for (f = 0; f < P->pp.m.nf; f++) {
        d = pgp__distortion(P, f);
        total += P->pp.m.area[f];
        st += (d & 1) ? P->pp.m.area[f] : 0.0;
        sh += (d & 2) ? P->pp.m.area[f] : 0.0;
    }
    out->triangles = P->pp.m.nf;
    out->vortices = pgp_map_vortices(map, NULL);
    out->singular = P->nsing;
    out->stretched = total > 0.0 ? (float)(st / total) : 0.0f;
    out->sheared = total > 0.0 ? (float)(sh / total) : 0.0f;
    out->mean_edge = (float)pw_periodic_mean_edge(&P->pp);
    out->diagonal = P->pp.m.diag;
    out->scale = P->pp.scale0;
}
