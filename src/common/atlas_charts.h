/* atlas_charts: the charts of a texture atlas (lapped textures §4).
 *
 * A chart is seeded at the lowest-index unassigned triangle, placed
 * isometrically, and grown from a queue of neighbouring faces ordered by
 * the distance of their centroid from the seed's (a face the chart already
 * borders on two sides first). A face joins when
 *   - its normal is within cone_angle of the seed's (otherwise it is
 *     refused for this chart for good);
 *   - the chart stays a disc: across one shared edge its third vertex
 *     must be new, across two it fills a notch, across three it would
 *     close a sphere (otherwise it waits until another neighbour joins);
 *   - its flattened image (the new vertex placed by Maillot's prediction,
 *     the centroid of similar-triangle extensions of the chart's edges
 *     around it) is counter-clockwise with an area not vanishing next to
 *     its 3D area, and overlaps no flattened chart triangle by more than
 *     1e-7 of the mean edge (separating axes against the triangles that a
 *     spatial hash of the chart's flattened triangles, cells of the mean
 *     edge length, returns). Otherwise it is deferred and tried again after
 *     the layout next changes.
 * Each time the chart has grown by half, the vertices added since the
 * previous time are relaxed by least-squares conformal maps (LSCM, the
 * lapped authors' hindsight for isotropic parametrisation) with the rest
 * fixed. When nothing more can join, the whole chart is flattened by LSCM
 * with two pinned vertices (far apart in 3D), solved with pw_lsq_solve
 * warm-started from the current layout, and scaled so that its 2D area
 * equals its 3D area. After every relaxation and after the final
 * flattening the layout is checked in growth order (hash rebuilt from
 * scratch): at the first face that is flipped, degenerate, or overlaps an
 * earlier face, the chart is cut; that face and all faces grown after it
 * return to the pool for later charts (growth stops). The prefix before it
 * is a disc whose layout was just checked, so a cut never leaves an invalid
 * chart; after a cut in the final flattening, the chart is flattened once
 * more and checked (and cut) again. A seed alone is always a valid chart,
 * so every triangle ends in exactly one chart. */
#ifndef PW__ATLAS_CHARTS_V1
#define PW__ATLAS_CHARTS_V1

#include "atlas.h"
#include "vec.h"
#include "sparse.h"
#include "heap.h"

/* ---- spatial hash of a chart's flattened triangles ---------------------- */

/* Square cells of side `cell` hashed into buckets; each bucket lists the
 * triangles whose bounding box meets one of its cells. Triangles covering
 * more than PW__ATLAS_BIG_CELLS cells go to a list that every query scans,
 * and a query covering more cells than the chart has triangles scans the
 * chart instead, so a few huge triangles cost neither memory nor time. */
#define PW__ATLAS_BIG_CELLS 64

typedef struct pw__atlas_hash {
    double cell;
    unsigned mask;    /* buckets - 1 */
    int *head;        /* per bucket: first entry, -1 */
    int *next, *item; /* per entry */
    int n;
    size_t ncap, icap;
    int *used, nused; /* buckets to clear */
    size_t ucap;
    int *all, nall; /* every triangle inserted */
    size_t acap;
    int *big, nbig; /* triangles too large for the cells */
    size_t bcap;
    int *stamp, nstamp; /* per mesh triangle: the last query that met it */
    int query;
} pw__atlas_hash;

/* Item coordinates for queries: writes triangle f's three xy pairs. */
typedef void (*pw__atlas_coords_fn)(const void *ctx, int f, double *t);

PW__DEF void pw__atlas_hash_free(const pw_alloc *a, pw__atlas_hash *H)
{
    pw_free(a, H->head);
    pw_free(a, H->next);
    pw_free(a, H->item);
    pw_free(a, H->used);
    pw_free(a, H->all);
    pw_free(a, H->big);
    pw_free(a, H->stamp);
    memset(H, 0, sizeof *H);
}

PW__DEF int pw__atlas_hash_init(const pw_alloc *a, pw__atlas_hash *H, int nf, double cell, pw_err *e)
{
    unsigned nb = 1024, k;
    memset(H, 0, sizeof *H);
    while (nb < 2u * (unsigned)nf && nb < (1u << 24)) nb <<= 1;
    H->cell = cell;
    H->mask = nb - 1;
    H->nstamp = nf;
    H->head = (int *)pw_alloc_array(a, nb, sizeof(int), "chart hash", e);
    H->stamp = (int *)pw_calloc_array(a, (size_t)nf, sizeof(int), "chart hash", e);
    if (!H->head || !H->stamp) {
        pw__atlas_hash_free(a, H);
        return PW_ERR_NOMEM;
    }
    for (k = 0; k < nb; k++) H->head[k] = -1;
    return PW_OK;
}

PW__DEF void pw__atlas_hash_clear(pw__atlas_hash *H)
{
    int k;
    for (k = 0; k < H->nused; k++) H->head[H->used[k]] = -1;
    H->n = H->nused = H->nall = H->nbig = 0;
}

/* Cell range c = {x0, y0, x1, y1} of the bounding box of t (finite). */
PW__DEF void pw__atlas_hash_cells(const pw__atlas_hash *H, const double *t, int *c)
{
    double lo[2], hi[2];
    int d, k;
    for (d = 0; d < 2; d++) {
        lo[d] = hi[d] = t[d];
        for (k = 1; k < 3; k++) {
            if (t[2 * k + d] < lo[d]) lo[d] = t[2 * k + d];
            if (t[2 * k + d] > hi[d]) hi[d] = t[2 * k + d];
        }
        lo[d] = floor(lo[d] / H->cell);
        hi[d] = floor(hi[d] / H->cell);
        c[d] = (int)(lo[d] < -1e9 ? -1e9 : (lo[d] > 1e9 ? 1e9 : lo[d]));
        c[d + 2] = (int)(hi[d] < -1e9 ? -1e9 : (hi[d] > 1e9 ? 1e9 : hi[d]));
    }
}

PW__DEF double pw__atlas_ncells(const int *c) { return ((double)c[2] - c[0] + 1) * ((double)c[3] - c[1] + 1); }

PW__DEF unsigned pw__atlas_bucket(const pw__atlas_hash *H, int x, int y)
{
    return ((unsigned)x * 73856093u ^ (unsigned)y * 19349663u) & H->mask;
}

PW__DEF int pw__atlas_hash_insert(const pw_alloc *a, pw__atlas_hash *H, int f, const double *t, pw_err *e)
{
    int c[4], x, y;
    pw__atlas_hash_cells(H, t, c);
    if (pw_grow(a, (void **)&H->all, &H->acap, (size_t)H->nall + 1, sizeof(int), "chart hash", e)) return PW_ERR_NOMEM;
    H->all[H->nall++] = f;
    if (pw__atlas_ncells(c) > PW__ATLAS_BIG_CELLS) {
        if (pw_grow(a, (void **)&H->big, &H->bcap, (size_t)H->nbig + 1, sizeof(int), "chart hash", e))
            return PW_ERR_NOMEM;
        H->big[H->nbig++] = f;
        return PW_OK;
    }
    for (y = c[1]; y <= c[3]; y++)
        for (x = c[0]; x <= c[2]; x++) {
            unsigned b = pw__atlas_bucket(H, x, y);
            if (pw_grow(a, (void **)&H->next, &H->ncap, (size_t)H->n + 1, sizeof(int), "chart hash", e) ||
                pw_grow(a, (void **)&H->item, &H->icap, (size_t)H->n + 1, sizeof(int), "chart hash", e) ||
                pw_grow(a, (void **)&H->used, &H->ucap, (size_t)H->nused + 1, sizeof(int), "chart hash", e))
                return PW_ERR_NOMEM;
            if (H->head[b] < 0) H->used[H->nused++] = (int)b;
            H->item[H->n] = f;
            H->next[H->n] = H->head[b];
            H->head[b] = H->n++;
        }
    return PW_OK;
}

/* Does inserted triangle f (not met yet by this query) overlap t? */
PW__DEF int pw__atlas_hash_test(pw__atlas_hash *H, int f, const double *t, double tol, pw__atlas_coords_fn coords,
                                const void *ctx)
{
    double u[6];
    if (H->stamp[f] == H->query) return 0;
    H->stamp[f] = H->query;
    coords(ctx, f, u);
    return pw__atlas_tris_overlap(t, u, tol);
}

/* Does t overlap any inserted triangle? */
PW__DEF int pw__atlas_hash_hits(pw__atlas_hash *H, const double *t, double tol, pw__atlas_coords_fn coords,
                                const void *ctx)
{
    int c[4], x, y, k;
    if (++H->query == INT_MAX) {
        memset(H->stamp, 0, (size_t)H->nstamp * sizeof(int));
        H->query = 1;
    }
    pw__atlas_hash_cells(H, t, c);
    if (pw__atlas_ncells(c) > (double)H->nall) {
        for (k = 0; k < H->nall; k++)
            if (pw__atlas_hash_test(H, H->all[k], t, tol, coords, ctx)) return 1;
        return 0;
    }
    for (k = 0; k < H->nbig; k++)
        if (pw__atlas_hash_test(H, H->big[k], t, tol, coords, ctx)) return 1;
    for (y = c[1]; y <= c[3]; y++)
        for (x = c[0]; x <= c[2]; x++)
            for (k = H->head[pw__atlas_bucket(H, x, y)]; k >= 0; k = H->next[k])
                if (pw__atlas_hash_test(H, H->item[k], t, tol, coords, ctx)) return 1;
    return 0;
}

/* ---- charts: growth ------------------------------------------------------ */

/* The charts: a partition of the triangles, each chart flattened. */
typedef struct pw_atlas_charts {
    int n;      /* charts */
    int *chart; /* nf: chart of each triangle */
    int *start; /* n+1: chart c holds faces[start[c] .. start[c+1]-1] */
    int *faces; /* nf: each chart's triangles in growth order */
    double *uv; /* nf*6: flattened corners; each chart's 2D area equals its 3D area */
    size_t scap;
} pw_atlas_charts;

PW__DEF void pw_atlas_charts_free(const pw_alloc *a, pw_atlas_charts *c)
{
    pw_free(a, c->chart);
    pw_free(a, c->start);
    pw_free(a, c->faces);
    pw_free(a, c->uv);
    memset(c, 0, sizeof *c);
}

/* The state of chart growth. The chart being grown keeps its faces in
 * growth order with the number of its vertices after each, so that every
 * prefix of the order is a valid smaller chart (a disc whose vertices are a
 * prefix of verts[]): that is what a chart is cut back to. */
typedef struct pw__atlas_grower {
    const pw_trimesh *m;
    const pw_alloc *a;
    pw_err *e;
    double cos_cone; /* §4: normals within the cone around the seed's */
    double tol;      /* overlap tolerance, mesh units */
    int *chart;      /* per triangle: chart, -1 while unassigned */
    int *cone;       /* per triangle: the last chart whose cone refused it */
    int *mark;       /* per triangle: the deferral round it was deferred in */
    int *local;      /* per vertex: index in the chart being grown, -1 */
    int cur, seed, round, last_opt, relaxed_nv;
    double centre[3]; /* centroid of the seed */
    int *faces, *nv_after, nfc;
    size_t fcap, acap;
    int *verts, nlv;
    size_t vcap;
    double *uv; /* nlv*2 flattened vertices */
    size_t uvcap;
    int *deferred, nd;
    size_t dcap;
    pw_heap heap;
    pw__atlas_hash hash;
} pw__atlas_grower;

/* Triangle f flattened: corner k at the chart position of its vertex. */
PW__DEF void pw__atlas_grower_coords(const void *ctx, int f, double *t)
{
    const pw__atlas_grower *G = (const pw__atlas_grower *)ctx;
    int k;
    for (k = 0; k < 3; k++) {
        int lv = G->local[G->m->tri[3 * f + k]];
        t[2 * k] = G->uv[2 * lv];
        t[2 * k + 1] = G->uv[2 * lv + 1];
    }
}

/* The same with vertex v (not yet in the chart, or -1) placed at V. */
PW__DEF void pw__atlas_grower_coords_with(const pw__atlas_grower *G, int f, int v, const double *V, double *t)
{
    int k;
    for (k = 0; k < 3; k++) {
        int w = G->m->tri[3 * f + k];
        const double *p = w == v ? V : G->uv + 2 * G->local[w];
        t[2 * k] = p[0];
        t[2 * k + 1] = p[1];
    }
}

PW__DEF void pw__atlas_centroid(const pw_trimesh *m, int f, double *c)
{
    int k, d;
    for (d = 0; d < 3; d++) {
        c[d] = 0.0;
        for (k = 0; k < 3; k++) c[d] += m->pos[3 * m->tri[3 * f + k] + d];
        c[d] /= 3.0;
    }
}

/* A triangle with collinear or coincident corners p, laid on the line of
 * its longest edge (corner 0 at the origin; all at 0 when they coincide). */
PW__DEF void pw__atlas_line(double p[3][3], double *x, double *y)
{
    double d[3], best = 0.0, len;
    int k, j;
    for (k = 0; k < 3; k++) {
        double l2 = 0.0, e[3];
        for (j = 0; j < 3; j++) {
            e[j] = p[(k + 1) % 3][j] - p[k][j];
            l2 += e[j] * e[j];
        }
        if (l2 > best)
            for (best = l2, j = 0; j < 3; j++) d[j] = e[j];
    }
    len = sqrt(best);
    for (k = 0; k < 3; k++) {
        x[k] = 0.0;
        y[k] = 0.0;
        for (j = 0; len > 0.0 && j < 3; j++) x[k] += (p[k][j] - p[0][j]) * d[j] / len;
    }
}

/* Triangle f in its own plane: corner 0 at the origin, corner 1 on +x,
 * corner 2 at y > 0 (counter-clockwise seen from the normal's side). */
PW__DEF void pw__atlas_frame(const pw_trimesh *m, int f, double *x, double *y)
{
    double p[3][3], e1[3], e2[3], n[3], ey[3], len, nl;
    int k, d;
    for (k = 0; k < 3; k++)
        for (d = 0; d < 3; d++) p[k][d] = m->pos[3 * m->tri[3 * f + k] + d];
    for (d = 0; d < 3; d++) {
        e1[d] = p[1][d] - p[0][d];
        e2[d] = p[2][d] - p[0][d];
    }
    len = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    nl = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(nl > 0.0) || !(len > 0.0)) { /* collinear or coincident corners: on a line */
        pw__atlas_line(p, x, y);
        return;
    }
    ey[0] = (n[1] * e1[2] - n[2] * e1[1]) / (nl * len); /* n x e1, unit */
    ey[1] = (n[2] * e1[0] - n[0] * e1[2]) / (nl * len);
    ey[2] = (n[0] * e1[1] - n[1] * e1[0]) / (nl * len);
    x[0] = y[0] = y[1] = 0.0;
    x[1] = len;
    x[2] = (e2[0] * e1[0] + e2[1] * e1[1] + e2[2] * e1[2]) / len;
    y[2] = e2[0] * ey[0] + e2[1] * ey[1] + e2[2] * ey[2];
}

PW__DEF int pw__atlas_add_vertex(pw__atlas_grower *G, int v, double u, double w)
{
    if (pw_grow(G->a, (void **)&G->verts, &G->vcap, (size_t)G->nlv + 1, sizeof(int), "chart", G->e) ||
        pw_grow(G->a, (void **)&G->uv, &G->uvcap, 2 * ((size_t)G->nlv + 1), sizeof(double), "chart", G->e))
        return PW_ERR_NOMEM;
    G->local[v] = G->nlv;
    G->verts[G->nlv] = v;
    G->uv[2 * G->nlv] = u;
    G->uv[2 * G->nlv + 1] = w;
    G->nlv++;
    return PW_OK;
}

/* The queue key of face g: squared distance of its centroid from the
 * seed's (§3.3: "faces are added in order of increasing distance"), except
 * that a face the chart already borders on two sides comes first: filling
 * notches at once keeps chart boundaries short. */
PW__DEF double pw__atlas_key(const pw__atlas_grower *G, int g)
{
    double c[3], key = 0.0;
    int k, shared = 0;
    for (k = 0; k < 3; k++) {
        int h = pw_trimesh_across(G->m, g, k);
        shared += h >= 0 && G->chart[h] == G->cur;
    }
    if (shared >= 2) return -1.0;
    pw__atlas_centroid(G->m, g, c);
    for (k = 0; k < 3; k++) key += (c[k] - G->centre[k]) * (c[k] - G->centre[k]);
    return key;
}

/* Queues the unassigned neighbours of f. */
PW__DEF int pw__atlas_push_neighbours(pw__atlas_grower *G, int f)
{
    int k;
    for (k = 0; k < 3; k++) {
        int g = pw_trimesh_across(G->m, f, k);
        if (g < 0 || G->chart[g] >= 0 || G->cone[g] == G->cur) continue;
        if (pw_heap_push(G->a, &G->heap, pw__atlas_key(G, g), g, G->e)) return PW_ERR_NOMEM;
    }
    return PW_OK;
}

/* Appends f (with its new vertex v at V, or v = -1) to the chart. */
PW__DEF int pw__atlas_grow_add(pw__atlas_grower *G, int f, int v, const double *V)
{
    double t[6];
    if (v >= 0 && pw__atlas_add_vertex(G, v, V[0], V[1])) return PW_ERR_NOMEM;
    if (pw_grow(G->a, (void **)&G->faces, &G->fcap, (size_t)G->nfc + 1, sizeof(int), "chart", G->e) ||
        pw_grow(G->a, (void **)&G->nv_after, &G->acap, (size_t)G->nfc + 1, sizeof(int), "chart", G->e))
        return PW_ERR_NOMEM;
    G->faces[G->nfc] = f;
    G->nv_after[G->nfc++] = G->nlv;
    G->chart[f] = G->cur;
    pw__atlas_grower_coords(G, f, t);
    if (pw__atlas_hash_insert(G->a, &G->hash, f, t, G->e)) return PW_ERR_NOMEM;
    return pw__atlas_push_neighbours(G, f);
}

/* Places the seed triangle isometrically (its own plane) as the whole
 * chart. */
PW__DEF int pw__atlas_seed_layout(pw__atlas_grower *G)
{
    double x[3], y[3], t[6];
    int k;
    pw__atlas_frame(G->m, G->seed, x, y);
    for (k = 0; k < 3; k++) {
        int v = G->m->tri[3 * G->seed + k];
        if (G->local[v] < 0 && pw__atlas_add_vertex(G, v, x[k], y[k])) return PW_ERR_NOMEM;
        G->uv[2 * G->local[v]] = x[k];
        G->uv[2 * G->local[v] + 1] = y[k];
    }
    pw__atlas_hash_clear(&G->hash);
    pw__atlas_grower_coords(G, G->seed, t);
    G->last_opt = 1;
    return pw__atlas_hash_insert(G->a, &G->hash, G->seed, t, G->e);
}

/* Starts chart `cur` at seed f. */
PW__DEF int pw__atlas_grow_start(pw__atlas_grower *G, int f)
{
    G->seed = f;
    G->nfc = G->nlv = G->nd = 0;
    G->heap.n = 0;
    G->round++;
    pw__atlas_centroid(G->m, f, G->centre);
    if (pw_grow(G->a, (void **)&G->faces, &G->fcap, 1, sizeof(int), "chart", G->e) ||
        pw_grow(G->a, (void **)&G->nv_after, &G->acap, 1, sizeof(int), "chart", G->e) || pw__atlas_seed_layout(G))
        return PW_ERR_NOMEM;
    G->faces[0] = f;
    G->nv_after[0] = 3;
    G->nfc = 1;
    G->relaxed_nv = 3;
    G->chart[f] = G->cur;
    return pw__atlas_push_neighbours(G, f);
}

/* Maillot's initial placement of new vertex v (§3.3, [10]): every face
 * around v whose opposite edge is already in the chart predicts v by
 * extending that edge with a triangle similar to the face in 3D; v goes
 * to the centroid of the predictions. */
PW__DEF void pw__atlas_maillot(const pw__atlas_grower *G, int v, double *V)
{
    const pw_trimesh *m = G->m;
    int h0 = m->hm.vout[v], h = h0, n = 0;
    V[0] = V[1] = 0.0;
    do {
        int g = h / 3, k = h % 3, o = 3 * g + (k + 1) % 3, tw = m->hm.twin[o];
        if (tw >= 0 && G->chart[tw / 3] == G->cur) {
            const float *pv = m->pos + 3 * v, *pp = m->pos + 3 * m->tri[o];
            const float *pq = m->pos + 3 * m->tri[3 * g + (k + 2) % 3];
            const double *P = G->uv + 2 * G->local[m->tri[o]];
            const double *Q = G->uv + 2 * G->local[m->tri[3 * g + (k + 2) % 3]];
            double e3[3], r[3], L2 = 0.0, t = 0.0, h2 = 0.0, hgt, ex = Q[0] - P[0], ey = Q[1] - P[1];
            int d;
            for (d = 0; d < 3; d++) {
                e3[d] = (double)pq[d] - pp[d];
                r[d] = (double)pv[d] - pp[d];
                L2 += e3[d] * e3[d];
                t += r[d] * e3[d];
            }
            t /= L2;
            for (d = 0; d < 3; d++) h2 += (r[d] - t * e3[d]) * (r[d] - t * e3[d]);
            hgt = sqrt(h2 / L2);
            /* (v, p, q) is counter-clockwise: v lies left of p -> q */
            V[0] += P[0] + t * ex - hgt * ey;
            V[1] += P[1] + t * ey + hgt * ex;
            n++;
        }
        h = pw_he_ccw(&m->hm, h);
    } while (h >= 0 && h != h0);
    V[0] /= n;
    V[1] /= n;
}

/* Remembers f, refused for its flattened shape, to be tried again once
 * the next optimisation has moved the chart's vertices. */
PW__DEF int pw__atlas_defer(pw__atlas_grower *G, int f)
{
    if (G->mark[f] == G->round) return PW_OK;
    if (pw_grow(G->a, (void **)&G->deferred, &G->dcap, (size_t)G->nd + 1, sizeof(int), "chart", G->e))
        return PW_ERR_NOMEM;
    G->mark[f] = G->round;
    G->deferred[G->nd++] = f;
    return PW_OK;
}

/* A flattened triangle is valid when finite and counter-clockwise with an
 * area not vanishing next to its area in 3D (a sliver cannot hold texels). */
PW__DEF int pw__atlas_flat_ok(const pw__atlas_grower *G, int f, const double *t)
{
    return pw__atlas_finite6(t) && pw__atlas_area2(t) > 1e-6 * 2.0 * G->m->area[f];
}

/* growth step: f joins the chart if its normal is within the cone of
 * the seed's, the chart stays a disc (§3.3) and f's flattened image neither
 * flips nor overlaps the chart (spatial hash). Faces refused for their
 * flattened shape are deferred. A degenerate triangle (pw_trimesh_sliver)
 * neither joins nor grows a chart: alone, it keeps its exact (line) shape,
 * and no conformal map divides by its area. */
PW__DEF int pw__atlas_grow_try(pw__atlas_grower *G, int f)
{
    const pw_trimesh *m = G->m;
    const float *n = m->normal + 3 * f, *ns = m->normal + 3 * G->seed;
    int k, shared = 0, sk = 0, v = -1;
    double t[6], V[2] = {0.0, 0.0};
    if (G->chart[f] >= 0 || G->cone[f] == G->cur) return PW_OK;
    if (pw_trimesh_sliver(m, f) || pw_trimesh_sliver(m, G->seed)) { /* no shape to flatten: a chart alone */
        G->cone[f] = G->cur;
        return PW_OK;
    }
    if ((double)n[0] * ns[0] + (double)n[1] * ns[1] + (double)n[2] * ns[2] < G->cos_cone) {
        G->cone[f] = G->cur;
        return PW_OK;
    }
    for (k = 0; k < 3; k++) {
        int g = pw_trimesh_across(m, f, k);
        if (g >= 0 && G->chart[g] == G->cur) {
            shared++;
            sk = k;
        }
    }
    /* Disc: across one edge the third vertex must be new (else the chart
     * would pinch or close a loop); across two edges f fills a notch;
     * across three it would close the chart into a sphere. */
    if (shared == 0 || shared == 3) return PW_OK;
    if (shared == 1) {
        v = m->tri[3 * f + (sk + 2) % 3];
        if (G->local[v] >= 0) return PW_OK;
        pw__atlas_maillot(G, v, V);
    }
    pw__atlas_grower_coords_with(G, f, v, V, t);
    if (!pw__atlas_flat_ok(G, f, t) || pw__atlas_hash_hits(&G->hash, t, G->tol, pw__atlas_grower_coords, G))
        return pw__atlas_defer(G, f);
    return pw__atlas_grow_add(G, f, v, V);
}

/* ---- charts: flattening -------------------------------------------------- */

/* Squared 3D distance between chart vertices i and j. */
PW__DEF double pw__atlas_dist3(const pw__atlas_grower *G, int i, int j)
{
    const float *p = G->m->pos + 3 * G->verts[i], *q = G->m->pos + 3 * G->verts[j];
    double d = 0.0;
    int k;
    for (k = 0; k < 3; k++) d += ((double)p[k] - q[k]) * ((double)p[k] - q[k]);
    return d;
}

/* The two pinned vertices of the conformal map: far apart on the surface
 * (the farthest vertex in 3D from the seed's first corner, then the
 * farthest from that one), which conditions the system well; pins close
 * together, such as the two tips of a chart wrapped almost around a tube,
 * would let a small error of their prescribed distance scale the whole
 * chart. */
PW__DEF void pw__atlas_pins(const pw__atlas_grower *G, int *p0, int *p1)
{
    int i, a = 0, b = 0;
    double best = -1.0;
    for (i = 0; i < G->nlv; i++)
        if (pw__atlas_dist3(G, 0, i) > best) {
            best = pw__atlas_dist3(G, 0, i);
            a = i;
        }
    for (i = 0, best = -1.0; i < G->nlv; i++)
        if (pw__atlas_dist3(G, a, i) > best) {
            best = pw__atlas_dist3(G, a, i);
            b = i;
        }
    *p0 = a;
    *p1 = b != a ? b : (a + 1) % G->nlv;
}

/* Scales the layout about vertex 0 so that its 2D area equals its 3D area:
 * the pins keep their current positions, whose distance need not be
 * their distance on the surface, while growth (hash cells, tolerances)
 * assumes mesh units. */
PW__DEF void pw__atlas_rescale(pw__atlas_grower *G)
{
    double a2 = 0.0, a3 = 0.0, s, t[6], o[2];
    int i;
    for (i = 0; i < G->nfc; i++) {
        pw__atlas_grower_coords(G, G->faces[i], t);
        a2 += 0.5 * pw__atlas_area2(t);
        a3 += G->m->area[G->faces[i]];
    }
    if (!(a2 > 0.0) || !pw_is_finite(a2)) return; /* flipped: the check will cut */
    s = sqrt(a3 / a2);
    o[0] = G->uv[0];
    o[1] = G->uv[1];
    for (i = 0; i < G->nlv; i++) {
        G->uv[2 * i] = o[0] + (G->uv[2 * i] - o[0]) * s;
        G->uv[2 * i + 1] = o[1] + (G->uv[2 * i + 1] - o[1]) * s;
    }
}

/* The two rows (from row r) of face f in the least-squares conformal map
 * (Lévy et al. 2002; the authors' hindsight for isotropic textures): in
 * f's own plane, with W_j = (x_{j+2} - x_{j+1}) + i (y_{j+2} - y_{j+1}),
 * the map U = u + i v is conformal on f when sum_j W_j U_j = 0; each row
 * is weighted by 1/sqrt(area), so the residual is the conformal energy.
 * Pinned vertices (col < 0) move to the right-hand side. */
PW__DEF int pw__atlas_lscm_rows(const pw__atlas_grower *G, int f, int r, const int *col, pw_triplets *T, double *b)
{
    pw_err *e = G->e;
    int j;
    double x[3], y[3], w = 1.0 / sqrt((double)G->m->area[f]);
    pw__atlas_frame(G->m, f, x, y);
    b[r] = b[r + 1] = 0.0;
    for (j = 0; j < 3; j++) {
        int lv = G->local[G->m->tri[3 * f + j]], c = col[lv];
        double wr = (x[(j + 2) % 3] - x[(j + 1) % 3]) * w, wi = (y[(j + 2) % 3] - y[(j + 1) % 3]) * w;
        if (c < 0) {
            double u = G->uv[2 * lv], v = G->uv[2 * lv + 1];
            b[r] -= wr * u - wi * v;
            b[r + 1] -= wi * u + wr * v;
            continue;
        }
        if (pw_triplets_add(T, r, 2 * c, wr, e) || pw_triplets_add(T, r, 2 * c + 1, -wi, e) ||
            pw_triplets_add(T, r + 1, 2 * c, wi, e) || pw_triplets_add(T, r + 1, 2 * c + 1, wr, e))
            return e->code;
    }
    return PW_OK;
}

/* Solves the least-squares system: charts of up to a few thousand
 * vertices directly (pw_lsq_solve_small: LDLᵀ of the normal equations,
 * about 0.8 of CGLS's time on a 1,060-unknown chart, exact to rounding),
 * larger ones with CGLS warm-started from the current layout (§3.4: "since
 * we begin with a reasonable approximation of the solution, we use a
 * conjugate-gradient iterative solver"), for at most max_iter iterations:
 * stopping there keeps the last iterate, and the check that follows
 * decides. */
PW__DEF int pw__atlas_lscm_solve(pw__atlas_grower *G, const pw_csr *A, const double *b, const int *col, int max_iter)
{
    double *x = (double *)pw_alloc_array(G->a, (size_t)A->m, sizeof(double), "conformal map", G->e);
    pw_cg_options o = pw_cg_default_options();
    pw_err se;
    int i, r;
    if (!x) return PW_ERR_NOMEM;
    for (i = 0; i < G->nlv; i++)
        if (col[i] >= 0) {
            x[2 * col[i]] = G->uv[2 * i];
            x[2 * col[i] + 1] = G->uv[2 * i + 1];
        }
    o.tol = 1e-5;
    o.max_iter = max_iter;
    pw_err_clear(&se);
    r = pw_lsq_solve_small(G->a, A, b, x, &o, &se);
    if (r == PW_OK || r == PW_ERR_NOCONVERGE) {
        for (i = 0; i < G->nlv; i++)
            if (col[i] >= 0) {
                G->uv[2 * i] = x[2 * col[i]];
                G->uv[2 * i + 1] = x[2 * col[i] + 1];
            }
        r = PW_OK;
    } else {
        pw_fail(G->e, r, "chart %d: %s", G->cur, se.msg);
    }
    pw_free(G->a, x);
    return r;
}

/* Which vertices move: with from >= 2, those added since vertex `from`
 * (the rest stay where they are); otherwise all but two pins. Returns the
 * number of free vertices; col[v] is v's unknown or -1. */
PW__DEF int pw__atlas_free_vertices(const pw__atlas_grower *G, int from, int *col)
{
    int i, p0 = -1, p1 = -1, n = 0;
    if (from < 2) pw__atlas_pins(G, &p0, &p1);
    for (i = 0; i < G->nlv; i++) col[i] = i < from || i == p0 || i == p1 ? -1 : n++;
    return n;
}

/* "flatten each region": the least-squares conformal map of the chart
 * (from < 2: two pins, then scaled to the chart's 3D area) or of the
 * vertices added since vertex `from` with the others fixed. Only faces
 * with a free vertex contribute. */
PW__DEF int pw__atlas_lscm(pw__atlas_grower *G, int from, int max_iter)
{
    int i, nfree, rows = 0, r = PW_ERR_NOMEM, *col;
    pw_triplets T;
    pw_csr A;
    double *b;
    memset(&A, 0, sizeof A);
    memset(&T, 0, sizeof T);
    col = (int *)pw_alloc_array(G->a, (size_t)G->nlv, sizeof(int), "conformal map", G->e);
    b = (double *)pw_alloc_array(G->a, 2 * (size_t)G->nfc, sizeof(double), "conformal map", G->e);
    if (col && b && (nfree = pw__atlas_free_vertices(G, from, col)) == 0) r = PW_OK;
    else if (col && b && !pw_triplets_init(&T, G->a, 2 * G->nfc, 2 * nfree, G->e)) {
        for (i = 0, r = PW_OK; i < G->nfc && r == PW_OK; i++) {
            const int *t = G->m->tri + 3 * G->faces[i];
            if (col[G->local[t[0]]] < 0 && col[G->local[t[1]]] < 0 && col[G->local[t[2]]] < 0) continue;
            r = pw__atlas_lscm_rows(G, G->faces[i], rows, col, &T, b);
            rows += 2;
        }
        T.n = rows;
        if (r == PW_OK) r = pw_csr_from_triplets(G->a, &T, &A, G->e);
        if (r == PW_OK) r = pw__atlas_lscm_solve(G, &A, b, col, max_iter);
        if (r == PW_OK && from < 2) pw__atlas_rescale(G);
    }
    pw_triplets_free(&T);
    pw_csr_free(G->a, &A);
    pw_free(G->a, col);
    pw_free(G->a, b);
    return r;
}

/* The first face, in growth order, whose flattened image is flipped,
 * degenerate or overlaps an earlier face's (G->nfc if none). Rebuilds the
 * hash with the faces before it. */
PW__DEF int pw__atlas_first_bad(pw__atlas_grower *G, int *bad)
{
    int i;
    pw__atlas_hash_clear(&G->hash);
    for (i = 0; i < G->nfc; i++) {
        double t[6];
        int f = G->faces[i];
        pw__atlas_grower_coords(G, f, t);
        if (!pw__atlas_flat_ok(G, f, t) || pw__atlas_hash_hits(&G->hash, t, G->tol, pw__atlas_grower_coords, G)) break;
        if (pw__atlas_hash_insert(G->a, &G->hash, f, t, G->e)) return PW_ERR_NOMEM;
    }
    *bad = i;
    return PW_OK;
}

/* Cuts the chart back to its first k faces (k >= 1): the others return to
 * the unassigned pool, for later charts. The prefix keeps its layout,
 * which first_bad found valid. */
PW__DEF int pw__atlas_cut(pw__atlas_grower *G, int k)
{
    int i;
    if (k < 1) k = 1;
    for (i = k; i < G->nfc; i++) G->chart[G->faces[i]] = -1;
    for (i = G->nv_after[k - 1]; i < G->nlv; i++) G->local[G->verts[i]] = -1;
    G->nlv = G->nv_after[k - 1];
    G->nfc = k;
    return k == 1 ? pw__atlas_seed_layout(G) : PW_OK;
}

/* Checks the layout after an optimisation. requires no overlap: a
 * triangle that overlaps an earlier one (in growth order) or flips is left
 * for another chart, together with every triangle grown after it; the
 * prefix before it is a disc whose layout is valid as it stands. *cut
 * tells whether anything was cut. */
PW__DEF int pw__atlas_check(pw__atlas_grower *G, int *cut)
{
    int bad, r;
    if ((r = pw__atlas_first_bad(G, &bad))) return r;
    *cut = bad < G->nfc;
    return *cut ? pw__atlas_cut(G, bad) : PW_OK;
}

/* Relaxes the vertices added since the last relaxation (the rest fixed) so
 * that new vertices are predicted from a good layout: Maillot's
 * prediction alone drifts on curved surfaces. Cheap, as only a ring of
 * the chart moves. */
#define PW__ATLAS_RING_ITER 300
PW__DEF int pw__atlas_relax(pw__atlas_grower *G, int *cut)
{
    int r;
    if ((r = pw__atlas_lscm(G, G->relaxed_nv, PW__ATLAS_RING_ITER)) || (r = pw__atlas_check(G, cut))) return r;
    G->relaxed_nv = G->nlv;
    G->last_opt = G->nfc;
    return PW_OK;
}

/* The final flattening: the conformal map of the whole chart. If it has
 * flipped or overlapping triangles the chart is cut (above), flattened
 * once more, and cut again if need be. */
#define PW__ATLAS_FULL_ITER 2000
PW__DEF int pw__atlas_flatten(pw__atlas_grower *G)
{
    int r, cut = 0;
    if (G->nfc < 2) return PW_OK; /* one triangle keeps its exact shape */
    if ((r = pw__atlas_lscm(G, 0, PW__ATLAS_FULL_ITER)) || (r = pw__atlas_check(G, &cut))) return r;
    if (cut && G->nfc >= 2 && ((r = pw__atlas_lscm(G, 0, PW__ATLAS_FULL_ITER)) || (r = pw__atlas_check(G, &cut))))
        return r;
    return PW_OK;
}

/* Queues the deferred faces again, after the chart's layout changed. */
PW__DEF int pw__atlas_retry_deferred(pw__atlas_grower *G)
{
    int i, nd = G->nd;
    G->nd = 0;
    G->round++;
    for (i = 0; i < nd; i++) {
        int f = G->deferred[i];
        if (G->chart[f] >= 0) continue;
        if (pw_heap_push(G->a, &G->heap, pw__atlas_key(G, f), f, G->e)) return PW_ERR_NOMEM;
    }
    return PW_OK;
}

/* Grows one chart from seed f (§4, growth as §3.3), relaxing the newest
 * part of the layout each time the chart has grown by half (from 32
 * faces); deferred faces are retried after each relaxation, and up to
 * three more times when the queue runs dry. A cut ends the growth; the
 * chart is then flattened as a whole. */
PW__DEF int pw__atlas_grow_chart(pw__atlas_grower *G, int f)
{
    int next = 32, extra = 0, cut = 0, r;
    if ((r = pw__atlas_grow_start(G, f))) return r;
    while (!cut) {
        if (G->heap.n == 0) {
            if (G->nd == 0 || G->nfc == G->last_opt || extra++ >= 3) break;
            if ((r = pw__atlas_relax(G, &cut)) || (!cut && (r = pw__atlas_retry_deferred(G)))) return r;
            continue;
        }
        if ((r = pw__atlas_grow_try(G, pw_heap_pop(&G->heap)))) return r;
        if (G->nfc >= next) {
            next = G->nfc + G->nfc / 2;
            if ((r = pw__atlas_relax(G, &cut)) || (!cut && (r = pw__atlas_retry_deferred(G)))) return r;
        }
    }
    return pw__atlas_flatten(G);
}

/* Records the grown chart: its faces, and its corners scaled so that its
 * 2D area equals its 3D area (the packer then gives every chart the same
 * texel density). Releases the chart's vertices. */
PW__DEF int pw__atlas_chart_finish(pw__atlas_grower *G, pw_atlas_charts *C, int *nfaces)
{
    double a3 = 0.0, a2 = 0.0, s, t[6];
    int i, k;
    if (pw_grow(G->a, (void **)&C->start, &C->scap, (size_t)C->n + 2, sizeof(int), "charts", G->e)) return PW_ERR_NOMEM;
    for (i = 0; i < G->nfc; i++) {
        pw__atlas_grower_coords(G, G->faces[i], t);
        a2 += 0.5 * pw__atlas_area2(t);
        a3 += G->m->area[G->faces[i]];
    }
    s = a2 > 0.0 && a3 > 0.0 ? sqrt(a3 / a2) : 1.0; /* a degenerate triangle alone keeps its size */
    for (i = 0; i < G->nfc; i++) {
        int f = G->faces[i];
        pw__atlas_grower_coords(G, f, t);
        for (k = 0; k < 6; k++) C->uv[6 * f + k] = t[k] * s;
        C->faces[*nfaces + i] = f;
    }
    *nfaces += G->nfc;
    C->start[++C->n] = *nfaces;
    for (i = 0; i < G->nlv; i++) G->local[G->verts[i]] = -1;
    return PW_OK;
}

PW__DEF void pw__atlas_grower_free(pw__atlas_grower *G)
{
    const pw_alloc *a = G->a;
    pw_free(a, G->cone);
    pw_free(a, G->mark);
    pw_free(a, G->local);
    pw_free(a, G->faces);
    pw_free(a, G->nv_after);
    pw_free(a, G->verts);
    pw_free(a, G->uv);
    pw_free(a, G->deferred);
    pw_heap_free(a, &G->heap);
    pw__atlas_hash_free(a, &G->hash);
}

/* Mean edge length: the hash's cell size. */
PW__DEF double pw__atlas_mean_edge(const pw_trimesh *m)
{
    double sum = 0.0;
    int f, k, d;
    for (f = 0; f < m->nf; f++)
        for (k = 0; k < 3; k++) {
            const float *p = m->pos + 3 * m->tri[3 * f + k], *q = m->pos + 3 * m->tri[3 * f + (k + 1) % 3];
            double l2 = 0.0;
            for (d = 0; d < 3; d++) l2 += ((double)q[d] - p[d]) * ((double)q[d] - p[d]);
            sum += sqrt(l2);
        }
    return sum / (3.0 * m->nf);
}

PW__DEF int pw__atlas_grower_init(pw__atlas_grower *G, const pw_alloc *a, const pw_trimesh *m, double cone_deg,
                                  int *chart, pw_err *e)
{
    double cell = pw__atlas_mean_edge(m);
    int i;
    memset(G, 0, sizeof *G);
    G->m = m;
    G->a = a;
    G->e = e;
    G->chart = chart;
    G->cos_cone = cone_deg >= 180.0 ? -2.0 : pw_cos(cone_deg * 3.14159265358979323846 / 180.0);
    G->tol = 1e-7 * cell;
    G->cone = (int *)pw_alloc_array(a, (size_t)m->nf, sizeof(int), "charts", e);
    G->mark = (int *)pw_alloc_array(a, (size_t)m->nf, sizeof(int), "charts", e);
    G->local = (int *)pw_alloc_array(a, (size_t)m->nv, sizeof(int), "charts", e);
    if (!G->cone || !G->mark || !G->local || pw__atlas_hash_init(a, &G->hash, m->nf, cell, e)) {
        pw__atlas_grower_free(G);
        return PW_ERR_NOMEM;
    }
    for (i = 0; i < m->nf; i++) chart[i] = G->cone[i] = G->mark[i] = -1;
    for (i = 0; i < m->nv; i++) G->local[i] = -1;
    return PW_OK;
}

/* §4: the charts of job->m (job->cone in degrees). Each is seeded at the
 * lowest-index unassigned triangle and grown until nothing more can join;
 * every triangle ends in exactly one chart (a seed always forms a chart by
 * itself). */
PW__DEF int pw_atlas_charts_build(const pw_atlas_job *job, pw_atlas_charts *C, pw_err *e)
{
    const pw_alloc *a = job->a;
    const pw_trimesh *m = job->m;
    pw__atlas_grower G;
    int f, r, nfaces = 0;
    memset(C, 0, sizeof *C);
    C->chart = (int *)pw_alloc_array(a, (size_t)m->nf, sizeof(int), "charts", e);
    C->faces = (int *)pw_alloc_array(a, (size_t)m->nf, sizeof(int), "charts", e);
    C->uv = (double *)pw_alloc_array(a, (size_t)m->nf * 6, sizeof(double), "charts", e);
    r = pw_grow(a, (void **)&C->start, &C->scap, 1, sizeof(int), "charts", e);
    if (!C->chart || !C->faces || !C->uv || r || pw__atlas_grower_init(&G, a, m, job->cone, C->chart, e)) {
        pw_atlas_charts_free(a, C);
        return PW_ERR_NOMEM;
    }
    C->start[0] = 0;
    for (f = 0, r = PW_OK; f < m->nf && r == PW_OK; f++) {
        if (C->chart[f] >= 0) continue;
        G.cur = C->n;
        if ((r = pw__atlas_grow_chart(&G, f)) || (r = pw__atlas_chart_finish(&G, C, &nfaces))) break;
        r = pw_report(job->prog, 0.5f * (float)nfaces / (float)m->nf, "atlas charts", e);
    }
    pw__atlas_grower_free(&G);
    if (r != PW_OK) pw_atlas_charts_free(a, C);
    return r;
}

#endif /* PW__ATLAS_CHARTS_V1 */
