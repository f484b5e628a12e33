/* field.c: §2.1 effect areas and §2.2 interpolation of the constraints:
 * scale and material by Laplacian smoothing, orientation by smoothing unit
 * directions, each with the constraints and everything outside the effect
 * area locked. */
#include "core.c"

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
    const pw_trimesh *m = &P->pp.m;
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
            double nd = d + P->pp.dual[3 * f + k];
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
    memset(vfree, 0, (size_t)P->pp.m.nv);
    for (f = 0; f < P->pp.m.nf; f++)
        for (k = 0; in[f] && k < 3; k++) vfree[P->pp.m.tri[3 * f + k]] = 1;
    for (f = 0; f < P->pp.m.nf; f++)
        for (k = 0; !in[f] && k < 3; k++) vfree[P->pp.m.tri[3 * f + k]] = 0;
}

/* ---- §2.2 scale and material: Laplacian smoothing ---------------------------------- */

/* Harmonic interpolation of a vertex value (S or m): the free vertices
 * (vfree, minus the `locked` ones) solve the Laplace equation with the
 * others as boundary values. Free vertices of a component without any
 * fixed vertex take `fallback`. */
static int pgp__harmonic(pgp__state *P, const unsigned char *vfree, const unsigned char *locked, float fallback,
                         float *val, pw_err *e)
{
    const pw_trimesh *m = &P->pp.m;
    int *id = (int *)pw_alloc_array(&P->a, (size_t)m->nv, sizeof(int), "interpolation", e);
    double *b = NULL, *x = NULL;
    pw_triplets t;
    int n = 0, v, h, r = id ? PW_OK : PW_ERR_NOMEM;
    memset(&t, 0, sizeof t);
    for (h = 0; r == PW_OK && h < m->nv; h++) { /* breadth-first order */
        v = P->pp.vorder[h];
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
        w = pw_periodic_lap_weight(m, h);
        if (id[i] >= 0) r = pw_triplets_add(&t, id[i], id[i], w, e);
        if (r == PW_OK && id[j] >= 0) r = pw_triplets_add(&t, id[j], id[j], w, e);
        if (r == PW_OK && id[i] >= 0 && id[j] >= 0) {
            r = pw_triplets_add(&t, id[i], id[j], -w, e);
            if (r == PW_OK) r = pw_triplets_add(&t, id[j], id[i], -w, e);
        } else if (r == PW_OK && id[i] >= 0) b[id[i]] += w * val[j];
        else if (r == PW_OK && id[j] >= 0) b[id[j]] += w * val[i];
    }
    for (v = 0; r == PW_OK && n > 0 && v < m->nv; v++) /* a faint pull towards the fallback */
        if (id[v] >= 0 && (r = pw_triplets_add(&t, id[v], id[v], PW_PERIODIC_PULL, e)) == PW_OK)
            b[id[v]] += PW_PERIODIC_PULL * fallback;
    if (r == PW_OK && n > 0) r = pw_periodic_pd_solve(&P->pp, &t, b, x, 1e-8, e);
    for (v = 0; r == PW_OK && n > 0 && v < m->nv; v++)
        if (id[v] >= 0) val[v] = (float)x[id[v]];
    pw_triplets_free(&t);
    pw_free(&P->a, id);
    pw_free(&P->a, b);
    pw_free(&P->a, x);
    return r;
}

/* ---- §2.2 orientation: smoothing of unit directions ------------------------------------- */

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
        memcpy(P->pp.dir, P->pp.base, sizeof(double) * 2 * (size_t)P->pp.m.nf);
        return PW_OK;
    }
    memcpy(mark, in, (size_t)P->pp.m.nf);
    for (i = 0; i < P->ncon; i++) {
        const pgp_constraint *c = &P->con[i].c;
        if (!P->con[i].alive || c->kind != PGP_CONSTRAINT_ORIENT) continue;
        pw_df_project(&P->pp.m, c->element, pw_v3_load(c->value), P->pp.dir + 2 * c->element); /* checked when added */
        mark[c->element] = 0;
    }
    for (f = 0; whole && f < P->pp.m.nf; f++) /* nothing outside: start from the default */
        if (mark[f]) {
            P->pp.dir[2 * f] = P->pp.base[2 * f];
            P->pp.dir[2 * f + 1] = P->pp.base[2 * f + 1];
        }
    return pw_periodic_dir_smooth(&P->pp, mark, NULL, e);
}

/* Scale (kind PGP_CONSTRAINT_SCALE) or material over the area's free vertices:
 * constraint vertices fixed to their value, harmonic in between; then the
 * §2.2 clamps (m in [0, 1], S >= min_scale * scale). */
static int pgp__interp_vertex(pgp__state *P, pgp_constraint_kind kind, const unsigned char *vfree, int whole,
                              unsigned char *locked, pw_err *e)
{
    float *val = kind == PGP_CONSTRAINT_SCALE ? P->pp.scale : P->mat;
    float fallback = kind == PGP_CONSTRAINT_SCALE ? P->pp.scale0 : P->o.material;
    float lo = kind == PGP_CONSTRAINT_SCALE ? P->o.min_scale * P->pp.scale0 : 0.0f,
          hi = kind == PGP_CONSTRAINT_SCALE ? FLT_MAX : 1.0f;
    int v, i, r;
    memset(locked, 0, (size_t)P->pp.m.nv);
    for (i = 0; i < P->ncon; i++)
        if (P->con[i].alive && P->con[i].c.kind == kind) {
            val[P->con[i].c.element] = P->con[i].c.value[0];
            locked[P->con[i].c.element] = 1;
        }
    for (v = 0; whole && v < P->pp.m.nv; v++)
        if (!locked[v]) val[v] = fallback;
    if ((r = pgp__harmonic(P, vfree, locked, fallback, val, e)) != PW_OK) return r;
    for (v = 0; v < P->pp.m.nv; v++) val[v] = val[v] < lo ? lo : (val[v] > hi ? hi : val[v]);
    return PW_OK;
}
