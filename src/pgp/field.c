/* field.c: §2.1 effect areas and §2.2 interpolation of the constraints:
 * scale and material by Laplacian smoothing, orientation by smoothing unit
 * directions, each with the constraints and everything outside the effect
 * area locked. */
#include "core.c"

/* ---- sparse symmetric positive definite solves ----------------------------- */

/* Solves the system collected in t for x (warm start: x's current values)
 * to a relative residual tol: real symmetric positive definite (n x n
 * triplets) by IC(0)-preconditioned CG, or complex Hermitian (zsparse.h:
 * n x 2n triplets, b and x complex) by its complex counterpart. */
static int pgp__pd_solve(const pw_alloc *a, const pw_triplets *t, const double *b, double *x, double tol, pw_err *e)
{
    const int complex = t->m == 2 * t->n;
    pw_csr A;
    pw_ic0 L;
    pw_zcsr ZA;
    pw_zic0 ZL;
    pw_cg_options o = pw_cg_default_options();
    int r;
    o.tol = tol;
    o.max_iter = 4000;
    if (complex) {
        memset(&ZL, 0, sizeof ZL);
        if ((r = pw_zcsr_from_triplets(a, t, &ZA, e)) != PW_OK) return r;
        if ((r = pw_zic0_factor(a, &ZA, &ZL, e)) == PW_OK) r = pw_zpcg_solve(a, &ZA, &ZL, b, x, &o, NULL, e);
        pw_zic0_free(a, &ZL);
        pw_zcsr_free(a, &ZA);
        return r;
    }
    memset(&L, 0, sizeof L);
    if ((r = pw_csr_from_triplets(a, t, &A, e)) != PW_OK) return r;
    if ((r = pw_ic0_factor(a, &A, &L, e)) == PW_OK) r = pw_pcg_solve(a, &A, &L, b, x, &o, NULL, e);
    pw_ic0_free(a, &L);
    pw_csr_free(a, &A);
    return r;
}

/* ---- §2.1 effect area ------------------------------------------------------------ */

/* Where an edit acts: its seed triangles and the geodesic radius of its
 * effect area around them (<= 0: the whole mesh). */
typedef struct pgp__seeds {
    const int *tri;
    int n;
    float radius;
} pgp__seeds;

/* The triangles within sd->radius (geodesic, over the dual graph) of the
 * seed triangles, in order of distance ("a classical greedy algorithm that
 * visits the triangles in order of increasing distance to the nearest
 * constraint"); radius <= 0 takes every triangle. in[f] = 1 for them;
 * order (nf) lists them, *n their number. */
static int pgp__area(const pgp__state *P, const pgp__seeds *sd, unsigned char *in, int *order, int *n, pw_err *e)
{
    const pw_trimesh *m = &P->m;
    const int *seeds = sd->tri, nseeds = sd->n;
    const float radius = sd->radius;
    double *dist = (double *)pw_alloc_array(&P->a, (size_t)m->nf * 4 + 1, sizeof(double), "effect area", e);
    int *hf = (int *)pw_alloc_array(&P->a, (size_t)m->nf * 3 + 1 + (size_t)nseeds, sizeof(int), "effect area", e);
    pw_heap hp;
    int f, k, g, i;
    *n = 0;
    memset(in, 0, (size_t)m->nf);
    if (!dist || !hf) {
        pw_free(&P->a, dist);
        pw_free(&P->a, hf);
        return PW_ERR_NOMEM;
    }
    memset(&hp, 0, sizeof hp);
    hp.key = dist + m->nf;
    hp.item = hf;
    for (f = 0; f < m->nf; f++) dist[f] = DBL_MAX;
    for (i = 0; i < nseeds; i++)
        if (dist[seeds[i]] > 0.0) {
            dist[seeds[i]] = 0.0;
            pw_heap_insert(&hp, 0.0, seeds[i]);
        }
    while (hp.n > 0) {
        double d = hp.key[0];
        f = pw_heap_pop(&hp);
        if (d > dist[f] || in[f]) continue; /* stale entry */
        if (radius > 0.0f && d > radius) break;
        in[f] = 1;
        order[(*n)++] = f;
        for (k = 0; k < 3; k++) {
            double nd = d + P->dual[3 * f + k];
            if ((g = pw_trimesh_across(m, f, k)) >= 0 && !in[g] && nd < dist[g]) {
                dist[g] = nd;
                pw_heap_insert(&hp, nd, g);
            }
        }
    }
    for (f = 0; radius <= 0.0f && f < m->nf; f++) /* components the seeds do not reach */
        if (!in[f]) {
            in[f] = 1;
            order[(*n)++] = f;
        }
    pw_free(&P->a, dist);
    pw_free(&P->a, hf);
    return PW_OK;
}

/* Vertices whose every triangle is in the area: the unknowns of an edit.
 * The others keep their values (§2.1: "all variables m, S, s, t associated
 * to the boundary are fixed to their initial value"). */
static void pgp__free_vertices(const pgp__state *P, const unsigned char *in, unsigned char *vfree)
{
    int f, k;
    memset(vfree, 0, (size_t)P->m.nv);
    for (f = 0; f < P->m.nf; f++)
        for (k = 0; in[f] && k < 3; k++) vfree[P->m.tri[3 * f + k]] = 1;
    for (f = 0; f < P->m.nf; f++)
        for (k = 0; !in[f] && k < 3; k++) vfree[P->m.tri[3 * f + k]] = 0;
}

/* ---- §2.2 scale and material: Laplacian smoothing ---------------------------------- */

/* Cotangent of the angle at corner k of triangle f. */
static double pgp__cot(const pw_trimesh *m, int f, int k)
{
    pw_v3 p = pw_trimesh_corner(m, f, k);
    pw_v3 a = pw_v3_sub(pw_trimesh_corner(m, f, (k + 1) % 3), p),
          b = pw_v3_sub(pw_trimesh_corner(m, f, (k + 2) % 3), p);
    double c = pw_v3_dot(a, b), s = pw_v3_len(pw_v3_cross(a, b));
    return s > 0.0 ? c / s : 0.0;
}

/* The Laplacian weight of the edge of half-edge h (the cotangents of the
 * angles facing it, halved), floored so that obtuse triangles keep every
 * weight positive and the smoothing a maximum principle. */
static double pgp__lap_weight(const pw_trimesh *m, int h)
{
    double w = 0.5 * pgp__cot(m, h / 3, (h % 3 + 2) % 3);
    if (m->hm.twin[h] >= 0) {
        int t = m->hm.twin[h];
        w += 0.5 * pgp__cot(m, t / 3, (t % 3 + 2) % 3);
    }
    return w > 0.05 ? w : 0.05;
}

/* Weight of the pull of every unknown towards its default: small enough to
 * change nothing visible where constraints or the area's border fix the
 * values, and it makes a component with nothing fixed take the default
 * (where the Laplacian alone would be singular). */
#define PGP__PULL 1e-7

/* Harmonic interpolation of a vertex value (S or m): the free vertices
 * (vfree, minus the `locked` ones) solve the Laplace equation with the
 * others as boundary values. Free vertices of a component without any
 * fixed vertex take `fallback`. */
static int pgp__harmonic(pgp__state *P, const unsigned char *vfree, const unsigned char *locked, float fallback,
                         float *val, pw_err *e)
{
    const pw_trimesh *m = &P->m;
    int *id = (int *)pw_alloc_array(&P->a, (size_t)m->nv, sizeof(int), "interpolation", e);
    double *b = NULL, *x = NULL;
    pw_triplets t;
    int n = 0, v, h, r = id ? PW_OK : PW_ERR_NOMEM;
    memset(&t, 0, sizeof t);
    for (h = 0; r == PW_OK && h < m->nv; h++) { /* breadth-first order */
        v = P->vorder[h];
        id[v] = vfree[v] && !locked[v] ? n++ : -1;
    }
    if (r == PW_OK && n > 0) {
        b = (double *)pw_calloc_array(&P->a, (size_t)n, sizeof(double), "interpolation", e);
        x = (double *)pw_alloc_array(&P->a, (size_t)n, sizeof(double), "interpolation", e);
        if (!b || !x || pw_triplets_init(&t, &P->a, n, n, e) != PW_OK) r = PW_ERR_NOMEM;
    }
    for (v = 0; r == PW_OK && n > 0 && v < m->nv; v++)
        if (id[v] >= 0) x[id[v]] = val[v];
    for (h = 0; r == PW_OK && n > 0 && h < 3 * m->nf; h++) {
        int i = m->tri[h], j = m->tri[3 * (h / 3) + (h % 3 + 1) % 3];
        double w;
        if (m->hm.twin[h] >= 0 && m->hm.twin[h] < h) continue; /* each edge once */
        w = pgp__lap_weight(m, h);
        if (id[i] >= 0) r = pw_triplets_add(&t, id[i], id[i], w, e);
        if (r == PW_OK && id[j] >= 0) r = pw_triplets_add(&t, id[j], id[j], w, e);
        if (r == PW_OK && id[i] >= 0 && id[j] >= 0) {
            r = pw_triplets_add(&t, id[i], id[j], -w, e);
            if (r == PW_OK) r = pw_triplets_add(&t, id[j], id[i], -w, e);
        } else if (r == PW_OK && id[i] >= 0) b[id[i]] += w * val[j];
        else if (r == PW_OK && id[j] >= 0) b[id[j]] += w * val[i];
    }
    for (v = 0; r == PW_OK && n > 0 && v < m->nv; v++) /* a faint pull towards the fallback */
        if (id[v] >= 0 && (r = pw_triplets_add(&t, id[v], id[v], PGP__PULL, e)) == PW_OK)
            b[id[v]] += PGP__PULL * fallback;
    if (r == PW_OK && n > 0) r = pgp__pd_solve(&P->a, &t, b, x, 1e-8, e);
    for (v = 0; r == PW_OK && n > 0 && v < m->nv; v++)
        if (id[v] >= 0) val[v] = (float)x[id[v]];
    pw_triplets_free(&t);
    pw_free(&P->a, id);
    pw_free(&P->a, b);
    pw_free(&P->a, x);
    return r;
}

/* ---- §2.2 orientation: smoothing of unit directions ------------------------------------- */

/* Weight of the edge of half-edge h in the orientation smoothing: its
 * length over the dual edge's (the cotangent weight of the dual mesh). */
static double pgp__dir_weight(const pgp__state *P, int h)
{
    int f = h / 3, k = h % 3;
    double len = pw_v3_len(pw_v3_sub(pw_trimesh_corner(&P->m, f, (k + 1) % 3), pw_trimesh_corner(&P->m, f, k)));
    return P->dual[h] > 0.0 ? len / P->dual[h] : 1.0;
}

/* Adds one interior edge (half-edge h of triangle f, twin in g) to the
 * orientation system: w |z_f - c z_g|^2 with c the transport from g into f
 * (pw_df_connection): w on both diagonals, -w c at (f, g) and its
 * conjugate at (g, f); a fixed neighbour moves to b. */
static int pgp__dir_edge(const pgp__state *P, const int *id, int h, pw_triplets *t, double *b, pw_err *e)
{
    int f = h / 3, g = P->m.hm.twin[h] / 3, i = id[f], j = id[g], r = PW_OK;
    double w = pgp__dir_weight(P, h), cx = P->conn[2 * h], cy = P->conn[2 * h + 1];
    const double *zf = P->dir + 2 * f, *zg = P->dir + 2 * g;
    if (i >= 0) r = pw_ztriplets_add(t, i, i, w, 0.0, e);
    if (r == PW_OK && j >= 0) r = pw_ztriplets_add(t, j, j, w, 0.0, e);
    if (r == PW_OK && i >= 0 && j >= 0) {
        r = pw_ztriplets_add(t, i, j, -w * cx, -w * cy, e);
        if (r == PW_OK) r = pw_ztriplets_add(t, j, i, -w * cx, w * cy, e);
    } else if (i >= 0) { /* b_f += w c z_g */
        b[2 * i] += w * (cx * zg[0] - cy * zg[1]);
        b[2 * i + 1] += w * (cx * zg[1] + cy * zg[0]);
    } else if (j >= 0) { /* b_g += w conj(c) z_f */
        b[2 * j] += w * (cx * zf[0] + cy * zf[1]);
        b[2 * j + 1] += w * (cx * zf[1] - cy * zf[0]);
    }
    return r;
}

/* Directions are normalised after the solve: a loose tolerance suffices. */
#define PGP__DIR_TOL 3e-3

/* Smooths the directions of the free triangles (free[f]) with the others
 * fixed, each pulled towards the default field with weight pull[f] (NULL:
 * a faint pull that only decides components with nothing fixed), then
 * normalises: "orientations rather than vectors" (the scale is
 * interpolated separately). Singularities emerge where the fixed directions
 * force them. A free component with nothing fixed takes the default field. */
static int pgp__dir_smooth(pgp__state *P, const unsigned char *free, const double *pull, pw_err *e)
{
    const pw_trimesh *m = &P->m;
    int *id = (int *)pw_alloc_array(&P->a, (size_t)m->nf, sizeof(int), "orientation", e);
    double *b = NULL, *x = NULL;
    pw_triplets t;
    int n = 0, f, h, r = id ? PW_OK : PW_ERR_NOMEM;
    memset(&t, 0, sizeof t);
    for (h = 0; r == PW_OK && h < m->nf; h++) { /* breadth-first order */
        f = P->forder[h];
        id[f] = free[f] ? n++ : -1;
    }
    if (r == PW_OK && n > 0) {
        b = (double *)pw_calloc_array(&P->a, (size_t)n * 2, sizeof(double), "orientation", e);
        x = (double *)pw_alloc_array(&P->a, (size_t)n * 2, sizeof(double), "orientation", e);
        if (!b || !x) r = PW_ERR_NOMEM;
        else r = pw_triplets_init(&t, &P->a, n, 2 * n, e);
    }
    for (f = 0; r == PW_OK && n > 0 && f < m->nf; f++)
        if (id[f] >= 0) {
            double w = pull ? pull[f] + PGP__PULL : PGP__PULL;
            x[2 * id[f]] = P->dir[2 * f];
            x[2 * id[f] + 1] = P->dir[2 * f + 1];
            b[2 * id[f]] += w * P->base[2 * f];
            b[2 * id[f] + 1] += w * P->base[2 * f + 1];
            r = pw_ztriplets_add(&t, id[f], id[f], w, 0.0, e);
        }
    for (h = 0; r == PW_OK && n > 0 && h < 3 * m->nf; h++)
        if (m->hm.twin[h] > h && (id[h / 3] >= 0 || id[m->hm.twin[h] / 3] >= 0)) r = pgp__dir_edge(P, id, h, &t, b, e);
    if (r == PW_OK && n > 0) r = pgp__pd_solve(&P->a, &t, b, x, PGP__DIR_TOL, e);
    for (f = 0; r == PW_OK && n > 0 && f < m->nf; f++)
        if (id[f] >= 0) {
            double *z = P->dir + 2 * f;
            z[0] = x[2 * id[f]];
            z[1] = x[2 * id[f] + 1];
            if (!pw_df_unit(z)) {
                z[0] = P->base[2 * f];
                z[1] = P->base[2 * f + 1];
            }
        }
    pw_triplets_free(&t);
    pw_free(&P->a, id);
    pw_free(&P->a, b);
    pw_free(&P->a, x);
    return r;
}

/* The default field (§2.2, where no constraint reaches): the tile's t axis
 * along the global up direction projected onto each triangle, or along the
 * direction of least curvature; then smoothed ("a vector field smoothing
 * algorithm" [LRL06]): each triangle is pulled towards that direction with
 * a weight A_f c_f / S^2 against the smoothness terms between neighbours,
 * so that the field varies over about one tile size and the poles of the
 * projection (c_f = 1 - (up . n)^2 small: up nearly normal to the face) are
 * filled smoothly. A field that turns within a tile cannot be followed by a
 * periodic parameterization without distortion. */
static int pgp__base_field(pgp__state *P, pw_err *e)
{
    size_t nf = (size_t)P->m.nf;
    unsigned char *known = (unsigned char *)pw_alloc_array(&P->a, nf, 1, "field", e);
    double *pull = (double *)pw_alloc_array(&P->a, nf, sizeof(double), "field", e);
    pw_v3 up = pw_v3_norm(pw_v3_load(P->o.up));
    int r = known && pull ? PW_OK : PW_ERR_NOMEM, f;
    pw_df_field F;
    F.m = &P->m;
    F.conn = P->conn;
    F.z = P->base;
    F.known = known;
    if (r == PW_OK && P->o.field == PGP_FIELD_CURVATURE) r = pw_df_curvature(&P->a, &F, up, P->o.smoothing, e);
    else if (r == PW_OK) r = pw_df_up(&P->a, &F, up, e);
    for (f = 0; r == PW_OK && f < P->m.nf; f++) { /* that is d_t; d_s = rot(-90)(d_t) */
        double x = P->base[2 * f], c = pw_v3_dot(up, pw_v3_load(P->m.normal + 3 * f));
        P->base[2 * f] = P->base[2 * f + 1];
        P->base[2 * f + 1] = -x;
        P->dir[2 * f] = P->base[2 * f];
        P->dir[2 * f + 1] = P->base[2 * f + 1];
        pull[f] =
            (P->o.field == PGP_FIELD_CURVATURE ? 1.0 : 1.0 - c * c) * P->m.area[f] / ((double)P->scale0 * P->scale0);
        known[f] = 1;
    }
    if (r == PW_OK) r = pgp__dir_smooth(P, known, pull, e);
    if (r == PW_OK) memcpy(P->base, P->dir, sizeof(double) * 2 * nf);
    pw_free(&P->a, known);
    pw_free(&P->a, pull);
    return r;
}

/* ---- re-interpolation over an effect area ------------------------------------------------ */

/* Whether a live constraint of `kind` exists. */
static int pgp__has(const pgp__state *P, pgp_constraint_kind kind)
{
    int i;
    for (i = 0; i < P->ncon; i++)
        if (P->con[i].alive && P->con[i].c.kind == kind) return 1;
    return 0;
}

/* Orientation over the area: constraint triangles take their direction and
 * stay fixed, the rest of the area is smoothed against them and against
 * the fixed outside. With the whole mesh in the area and no orientation
 * constraint, the default field. */
static int pgp__interp_dir(pgp__state *P, const unsigned char *in, int whole, unsigned char *mark, pw_err *e)
{
    int f, i;
    if (whole && !pgp__has(P, PGP_CONSTRAINT_ORIENT)) {
        memcpy(P->dir, P->base, sizeof(double) * 2 * (size_t)P->m.nf);
        return PW_OK;
    }
    memcpy(mark, in, (size_t)P->m.nf);
    for (i = 0; i < P->ncon; i++) {
        const pgp_constraint *c = &P->con[i].c;
        if (!P->con[i].alive || c->kind != PGP_CONSTRAINT_ORIENT) continue;
        pw_df_project(&P->m, c->element, pw_v3_load(c->value), P->dir + 2 * c->element); /* checked when added */
        mark[c->element] = 0;
    }
    for (f = 0; whole && f < P->m.nf; f++) /* nothing outside: start from the default */
        if (mark[f]) {
            P->dir[2 * f] = P->base[2 * f];
            P->dir[2 * f + 1] = P->base[2 * f + 1];
        }
    return pgp__dir_smooth(P, mark, NULL, e);
}

/* Scale (kind PGP_CONSTRAINT_SCALE) or material over the area's free vertices:
 * constraint vertices fixed to their value, harmonic in between; then the
 * §2.2 clamps (m in [0, 1], S >= min_scale * scale). */
static int pgp__interp_vertex(pgp__state *P, pgp_constraint_kind kind, const unsigned char *vfree, int whole,
                              unsigned char *locked, pw_err *e)
{
    float *val = kind == PGP_CONSTRAINT_SCALE ? P->scale : P->mat;
    float fallback = kind == PGP_CONSTRAINT_SCALE ? P->scale0 : P->o.material;
    float lo = kind == PGP_CONSTRAINT_SCALE ? P->o.min_scale * P->scale0 : 0.0f,
          hi = kind == PGP_CONSTRAINT_SCALE ? FLT_MAX : 1.0f;
    int v, i, r;
    memset(locked, 0, (size_t)P->m.nv);
    for (i = 0; i < P->ncon; i++)
        if (P->con[i].alive && P->con[i].c.kind == kind) {
            val[P->con[i].c.element] = P->con[i].c.value[0];
            locked[P->con[i].c.element] = 1;
        }
    for (v = 0; whole && v < P->m.nv; v++)
        if (!locked[v]) val[v] = fallback;
    if ((r = pgp__harmonic(P, vfree, locked, fallback, val, e)) != PW_OK) return r;
    for (v = 0; v < P->m.nv; v++) val[v] = val[v] < lo ? lo : (val[v] > hi ? hi : val[v]);
    return PW_OK;
}
