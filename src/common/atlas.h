/* atlas: texture atlases of triangle meshes — charts, packing, baking.
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
 * Charts (pw_atlas_charts_build). A chart is seeded at the lowest-index
 * unassigned triangle, placed isometrically, and grown from a queue of
 * neighbouring faces ordered by the distance of their centroid from the
 * seed's (a face the chart already borders on two sides first). A face
 * joins when
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
 * so every triangle ends in exactly one chart.
 *
 * Packing (pw_atlas_pack): each chart turned so that its minimal-area
 * enclosing rectangle (rotating calipers on its convex hull) is
 * axis-aligned; one scale for all (texels per mesh unit: the texel density
 * is uniform); bottom-left fill of the charts' covered cells, dilated by
 * the gutter, on a bitmap of the atlas, largest chart first, in the
 * quarter turn that ends lowest; a binary search for the largest scale at
 * which everything fits. Charts are at least `gutter` pixels apart.
 *
 * Baking (pw_atlas_bake): every texel whose centre a chart triangle covers
 * (pw_raster_tri) gets the caller's texture there; texels that a bilinear
 * lookup inside a chart can reach but no triangle covers get the texture at
 * the nearest point of the nearest triangle; `gutter` rounds of dilation
 * fill the gutter with the nearest chart texel.
 *
 * Export: pw_atlas_mesh makes the pw_mesh (per-corner coordinates,
 * deduplicated) that the OBJ and glTF writers take. */
#ifndef PW__ATLAS_V1
#define PW__ATLAS_V1

#include "base.h"
#include "vec.h"
#include "image.h"
#include "mesh.h"
#include "trimesh.h"
#include "sparse.h"
#include "raster.h"
#include "heap.h"

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

/* Solves the least-squares system with CGLS warm-started from the current
 * layout (§3.4: "since we begin with a reasonable approximation of the
 * solution, we use a conjugate-gradient iterative solver"), for at most
 * max_iter iterations: stopping there keeps the last iterate, and the
 * check that follows decides. */
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
    r = pw_lsq_solve(G->a, A, b, x, &o, NULL, &se);
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

/* §4: the charts. Each is seeded at the lowest-index unassigned triangle
 * and grown until nothing more can join; every triangle ends in exactly
 * one chart (a seed always forms a chart by itself). */
PW__DEF int pw_atlas_charts_build(const pw_alloc *a, const pw_trimesh *m, double cone_deg, const pw_progress *prog,
                                  pw_atlas_charts *C, pw_err *e)
{
    pw__atlas_grower G;
    int f, r, nfaces = 0;
    memset(C, 0, sizeof *C);
    C->chart = (int *)pw_alloc_array(a, (size_t)m->nf, sizeof(int), "charts", e);
    C->faces = (int *)pw_alloc_array(a, (size_t)m->nf, sizeof(int), "charts", e);
    C->uv = (double *)pw_alloc_array(a, (size_t)m->nf * 6, sizeof(double), "charts", e);
    r = pw_grow(a, (void **)&C->start, &C->scap, 1, sizeof(int), "charts", e);
    if (!C->chart || !C->faces || !C->uv || r || pw__atlas_grower_init(&G, a, m, cone_deg, C->chart, e)) {
        pw_atlas_charts_free(a, C);
        return PW_ERR_NOMEM;
    }
    C->start[0] = 0;
    for (f = 0, r = PW_OK; f < m->nf && r == PW_OK; f++) {
        if (C->chart[f] >= 0) continue;
        G.cur = C->n;
        if ((r = pw__atlas_grow_chart(&G, f)) || (r = pw__atlas_chart_finish(&G, C, &nfaces))) break;
        r = pw_report(prog, 0.5f * (float)nfaces / (float)m->nf, "atlas charts", e);
    }
    pw__atlas_grower_free(&G);
    if (r != PW_OK) pw_atlas_charts_free(a, C);
    return r;
}

/* ---- packing --------------------------------------------------------------- */

/* The paper let the user arrange the charts ("heuristic algorithms ...
 * produce significantly worse results than a trained human"); here they
 * are packed automatically. Each chart is turned so that its minimal-area
 * enclosing rectangle is axis-aligned, and all charts share one scale
 * (texels per mesh unit, so the texel density is uniform over the mesh).
 * The charts, largest first, are placed bottom-left-fill on a bitmap of
 * the atlas: each as the cells it covers, dilated by the gutter, stored as
 * runs per row, at the lowest position where those cells are free, in
 * whichever of four quarter turns ends lowest. Unlike a skyline, the
 * bitmap lets small charts fill the room left beside, under and inside
 * large irregular ones. A binary search finds the largest scale at which
 * all charts fit with `gutter` pixels between charts (floor(gutter/2)
 * to the left of and below each chart, the rest to the right and above,
 * so also to the image border). Beyond 1024 pixels the grid's cells are
 * several pixels wide and both parts are rounded up to whole cells. */
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

typedef struct pw__atlas_packer {
    const pw_trimesh *m;
    const pw_atlas_charts *C;
    int size, gutter;           /* the packing grid: size x size cells of `unit` pixels; gutter in cells */
    int pad_lo;                 /* cells of the gutter on the left of and below a chart (the rest:
                            right and above): floor(gutter/2) pixels, rounded up to cells */
    int unit, pixels;           /* cell side and atlas side, pixels */
    double *rect;               /* per chart 6: unit direction (dx, dy) of the rectangle's side,
                            its min corner (x0, y0) in the turned frame, its extent (w, h) */
    double *area;               /* per chart: 3D area */
    int *order;                 /* charts, largest first */
    int *bstart, *bedge;        /* boundary half-edges of each chart */
    int16_t *run;               /* size*size, rows from the bottom: the free run starting at each
                            cell (> 0), or minus the occupied run (< 0) */
    int *maxrun;                /* size: the longest free run of each row */
    unsigned char *cov;         /* size*size: the cells the chart being placed covers */
    int *cl, *cr, *cst;         /* their runs, row by row (cst: first run of each row) */
    double *lo, *hi;            /* a triangle's extent over each row */
    int *sl, *sr, *srow;        /* the dilated chart's runs [sl, sr) and their rows */
    int *ord;                   /* the order in which runs are tried */
    int *kl, *kr, *krow, nkeep; /* the runs of the best turn so far */
    int *rowmax;                /* per row: its longest run */
    int nspan, wp, hp;          /* runs, and the dilated chart's width and height */
    int *place;                 /* per chart 3: content origin x, y (cells from the bottom-left), turn */
    int *best;                  /* the placement of the largest scale that fitted */
} pw__atlas_packer;

PW__DEF void pw__atlas_packer_free(const pw_alloc *a, pw__atlas_packer *P)
{
    pw_free(a, P->rect);
    pw_free(a, P->area);
    pw_free(a, P->order);
    pw_free(a, P->bstart);
    pw_free(a, P->bedge);
    pw_free(a, P->run);
    pw_free(a, P->maxrun);
    pw_free(a, P->cov);
    pw_free(a, P->cl);
    pw_free(a, P->cr);
    pw_free(a, P->cst);
    pw_free(a, P->sl);
    pw_free(a, P->sr);
    pw_free(a, P->srow);
    pw_free(a, P->ord);
    pw_free(a, P->kl);
    pw_free(a, P->kr);
    pw_free(a, P->krow);
    pw_free(a, P->rowmax);
    pw_free(a, P->lo);
    pw_free(a, P->hi);
    pw_free(a, P->place);
    pw_free(a, P->best);
    memset(P, 0, sizeof *P);
}

/* Lists the boundary half-edges of every chart (fill = 0 only counts). */
PW__DEF int pw__atlas_boundary(pw__atlas_packer *P, int fill)
{
    const pw_atlas_charts *C = P->C;
    int c, i, k, n = 0;
    for (c = 0; c < C->n; c++) {
        if (fill) P->bstart[c] = n;
        for (i = C->start[c]; i < C->start[c + 1]; i++)
            for (k = 0; k < 3; k++) {
                int h = 3 * C->faces[i] + k, tw = P->m->hm.twin[h];
                if (tw >= 0 && C->chart[tw / 3] == c) continue;
                if (fill) P->bedge[n] = h;
                n++;
            }
    }
    if (fill) P->bstart[C->n] = n;
    return n;
}

PW__DEF int pw__atlas_cmp_point(const void *x, const void *y)
{
    const double *p = (const double *)x, *q = (const double *)y;
    if (p[0] != q[0]) return p[0] < q[0] ? -1 : 1;
    if (p[1] != q[1]) return p[1] < q[1] ? -1 : 1;
    return 0;
}

PW__DEF double pw__atlas_cross(const double *o, const double *a, const double *b)
{
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

/* Andrew's monotone chain: the convex hull of pts[n] (sorted in place)
 * into hull (room for n + 1 points), counter-clockwise, without collinear
 * points. Returns its size. */
PW__DEF int pw__atlas_hull(double *pts, int n, double *hull)
{
    int i, k = 0, lower;
    qsort(pts, (size_t)n, 2 * sizeof(double), pw__atlas_cmp_point);
    for (i = 0; i < n; i++) {
        while (k >= 2 && pw__atlas_cross(hull + 2 * (k - 2), hull + 2 * (k - 1), pts + 2 * i) <= 0.0) k--;
        hull[2 * k] = pts[2 * i];
        hull[2 * k + 1] = pts[2 * i + 1];
        k++;
    }
    for (i = n - 2, lower = k + 1; i >= 0; i--) {
        while (k >= lower && pw__atlas_cross(hull + 2 * (k - 2), hull + 2 * (k - 1), pts + 2 * i) <= 0.0) k--;
        hull[2 * k] = pts[2 * i];
        hull[2 * k + 1] = pts[2 * i + 1];
        k++;
    }
    return k > 1 ? k - 1 : k; /* the last point repeats the first */
}

/* Moves index i forward around the hull while the next point lies
 * further along (nx, ny) (at most h steps). */
PW__DEF int pw__atlas_caliper(const double *H, int h, int i, double nx, double ny, int sign)
{
    int guard;
    for (guard = 0; guard < h; guard++) {
        int j = (i + 1) % h;
        double d = (H[2 * j] - H[2 * i]) * nx + (H[2 * j + 1] - H[2 * i + 1]) * ny;
        if (!(d * sign > 0.0)) break;
        i = j;
    }
    return i;
}

/* The minimal-area rectangle enclosing a convex polygon has a side on one
 * of its edges (Freeman and Shapira 1975). Rotating calipers (Toussaint
 * 1983) find it in O(h): for edge i with direction d and inward normal n,
 * the extreme points along +d, +n and -d only move forward as i advances.
 * Writes the unit direction of the best edge. */
PW__DEF void pw__atlas_min_rect_dir(const double *H, int h, double *dir)
{
    int i, j = 0, k = 0, l = 0;
    double best = -1.0;
    dir[0] = 1.0;
    dir[1] = 0.0;
    for (i = 0; h >= 3 && i < h; i++) {
        const double *p = H + 2 * i, *q = H + 2 * ((i + 1) % h);
        double dx = q[0] - p[0], dy = q[1] - p[1], len = sqrt(dx * dx + dy * dy), w, ht;
        if (!(len > 0.0)) continue;
        dx /= len;
        dy /= len;
        j = pw__atlas_caliper(H, h, i == 0 ? 1 % h : j, dx, dy, 1);
        k = pw__atlas_caliper(H, h, i == 0 ? j : k, -dy, dx, 1);
        l = pw__atlas_caliper(H, h, i == 0 ? k : l, dx, dy, -1);
        w = (H[2 * j] - H[2 * l]) * dx + (H[2 * j + 1] - H[2 * l + 1]) * dy;
        ht = (H[2 * k] - p[0]) * -dy + (H[2 * k + 1] - p[1]) * dx;
        if (best < 0.0 || w * ht < best) {
            best = w * ht;
            dir[0] = dx;
            dir[1] = dy;
        }
    }
}

/* Chart c's rectangle: the direction from the calipers, the extent from
 * all of the hull's points (robust to rounding in the calipers). */
PW__DEF void pw__atlas_chart_rect(pw__atlas_packer *P, int c, double *pts, double *hull)
{
    const pw_atlas_charts *C = P->C;
    double *R = P->rect + 6 * c, dir[2], lo[2] = {0, 0}, hi[2] = {0, 0};
    int i, n = 0, h;
    for (i = P->bstart[c]; i < P->bstart[c + 1]; i++, n++) {
        pts[2 * n] = C->uv[2 * P->bedge[i]];
        pts[2 * n + 1] = C->uv[2 * P->bedge[i] + 1];
    }
    h = pw__atlas_hull(pts, n, hull);
    pw__atlas_min_rect_dir(hull, h, dir);
    for (i = 0; i < h; i++) {
        double x = dir[0] * hull[2 * i] + dir[1] * hull[2 * i + 1];
        double y = -dir[1] * hull[2 * i] + dir[0] * hull[2 * i + 1];
        if (i == 0 || x < lo[0]) lo[0] = x;
        if (i == 0 || y < lo[1]) lo[1] = y;
        if (i == 0 || x > hi[0]) hi[0] = x;
        if (i == 0 || y > hi[1]) hi[1] = y;
    }
    R[0] = dir[0];
    R[1] = dir[1];
    R[2] = lo[0];
    R[3] = lo[1];
    R[4] = hi[0] - lo[0];
    R[5] = hi[1] - lo[1];
}

/* A chart point uv in pixels at scale s, after quarter turn o, inside
 * the chart's box [0, W] x [0, H] (W, H swapped on odd turns). */
PW__DEF void pw__atlas_pack_xy(const pw__atlas_packer *P, int c, double s, int o, const double *uv, double *out)
{
    const double *R = P->rect + 6 * c;
    double x = (R[0] * uv[0] + R[1] * uv[1] - R[2]) * s, y = (-R[1] * uv[0] + R[0] * uv[1] - R[3]) * s;
    double W = R[4] * s, H = R[5] * s;
    switch (o) {
    case 0:
        out[0] = x;
        out[1] = y;
        break;
    case 1:
        out[0] = H - y;
        out[1] = x;
        break;
    case 2:
        out[0] = W - x;
        out[1] = H - y;
        break;
    default:
        out[0] = y;
        out[1] = W - x;
        break;
    }
}

/* Widens the x extents [lo, hi] of the rows [j, j+1] that segment AB
 * crosses (rows j0..j1 of a box of nrow rows) with the part of AB in each. */
PW__DEF void pw__atlas_edge_rows(pw__atlas_packer *P, const double *A, const double *B, int nrow)
{
    double y0 = A[1] < B[1] ? A[1] : B[1], y1 = A[1] < B[1] ? B[1] : A[1];
    int j, j0 = pw_clampi((int)floor(y0), 0, nrow - 1), j1 = pw_clampi((int)floor(y1), 0, nrow - 1);
    for (j = j0; j <= j1; j++) {
        double ya = j > y0 ? (double)j : y0, yb = j + 1 < y1 ? (double)(j + 1) : y1, xa, xb;
        if (ya > y1) ya = y1;
        if (yb < y0) yb = y0;
        if (B[1] != A[1]) {
            xa = A[0] + (ya - A[1]) * (B[0] - A[0]) / (B[1] - A[1]);
            xb = A[0] + (yb - A[1]) * (B[0] - A[0]) / (B[1] - A[1]);
        } else {
            xa = A[0];
            xb = B[0];
        }
        P->lo[j] = xa < P->lo[j] ? xa : P->lo[j];
        P->lo[j] = xb < P->lo[j] ? xb : P->lo[j];
        P->hi[j] = xa > P->hi[j] ? xa : P->hi[j];
        P->hi[j] = xb > P->hi[j] ? xb : P->hi[j];
    }
}

/* Marks in P->cov (w x h cells) every cell that triangle t (cells)
 * touches: over each row, the triangle's extent is that of its edges. */
PW__DEF void pw__atlas_cover_tri(pw__atlas_packer *P, const double *t, int w, int h)
{
    int j, k, j0 = h, j1 = -1;
    for (k = 0; k < 3; k++) {
        j0 = pw_mini(j0, pw_clampi((int)floor(t[2 * k + 1]), 0, h - 1));
        j1 = pw_maxi(j1, pw_clampi((int)floor(t[2 * k + 1]), 0, h - 1));
    }
    for (j = j0; j <= j1; j++) {
        P->lo[j] = DBL_MAX;
        P->hi[j] = -DBL_MAX;
    }
    for (k = 0; k < 3; k++) pw__atlas_edge_rows(P, t + 2 * k, t + 2 * ((k + 1) % 3), h);
    for (j = j0; j <= j1; j++) {
        int x0, x1;
        if (P->lo[j] > P->hi[j]) continue;
        x0 = pw_clampi((int)floor(P->lo[j]), 0, w - 1);
        x1 = pw_clampi(pw_maxi((int)ceil(P->hi[j]), x0 + 1), 1, w);
        memset(P->cov + (size_t)j * w + x0, 1, (size_t)(x1 - x0));
    }
}

/* The cells chart c covers at scale s, turn o, in its w x h box. */
PW__DEF void pw__atlas_cover(pw__atlas_packer *P, int c, double s, int o, int w, int h)
{
    const pw_atlas_charts *C = P->C;
    int i, k;
    memset(P->cov, 0, (size_t)w * h);
    for (i = C->start[c]; i < C->start[c + 1]; i++) {
        double t[6];
        for (k = 0; k < 3; k++) pw__atlas_pack_xy(P, c, s, o, C->uv + 6 * C->faces[i] + 2 * k, t + 2 * k);
        pw__atlas_cover_tri(P, t, w, h);
    }
}

/* The runs of covered cells of each row of P->cov (w x h): row j holds
 * (cl, cr)[cst[j] .. cst[j+1]-1], left to right. */
PW__DEF void pw__atlas_cover_runs(pw__atlas_packer *P, int w, int h)
{
    int j, n = 0;
    for (j = 0; j < h; j++) {
        const unsigned char *row = P->cov + (size_t)j * w, *p = row, *end = row + w;
        P->cst[j] = n;
        while (p < end && (p = (const unsigned char *)memchr(p, 1, (size_t)(end - p))) != NULL) {
            const unsigned char *q = (const unsigned char *)memchr(p, 0, (size_t)(end - p));
            if (!q) q = end;
            P->cl[n] = (int)(p - row);
            P->cr[n++] = (int)(q - row);
            p = q;
        }
    }
    P->cst[h] = n;
}

/* The chart's runs dilated by the gutter g, as the runs (sl, sr, srow) of
 * a box of wp x hp cells: cell (x, y) is set when a covered cell lies in
 * [x - g, x] x [y - g, y], so with the chart at (pad_lo, pad_lo) in the
 * box it is padded by pad_lo cells on the left and bottom and the rest on
 * the right and top. Padded row y is the union of content rows y - g .. y,
 * each run widened by g: gathered, sorted by start (insertion sort: few
 * runs) and merged. Also each row's longest run. */
PW__DEF void pw__atlas_dilate_runs(pw__atlas_packer *P, int h)
{
    int g = P->gutter, y, j, k, n = 0;
    for (y = 0; y < P->hp; y++) {
        int first = n, m;
        for (j = pw_maxi(y - g, 0); j <= pw_mini(y, h - 1); j++)
            for (k = P->cst[j]; k < P->cst[j + 1]; k++) {
                int l = P->cl[k], r = P->cr[k] + g, i = n++;
                for (; i > first && P->sl[i - 1] > l; i--) {
                    P->sl[i] = P->sl[i - 1];
                    P->sr[i] = P->sr[i - 1];
                }
                P->sl[i] = l;
                P->sr[i] = r;
            }
        for (k = first + 1, m = first; k < n; k++) { /* merge overlapping or touching runs */
            if (P->sl[k] <= P->sr[m]) P->sr[m] = pw_maxi(P->sr[m], P->sr[k]);
            else {
                m++;
                P->sl[m] = P->sl[k];
                P->sr[m] = P->sr[k];
            }
        }
        n = n > first ? m + 1 : first;
        P->rowmax[y] = 0;
        for (k = first; k < n; k++) {
            P->srow[k] = y;
            P->rowmax[y] = pw_maxi(P->rowmax[y], P->sr[k] - P->sl[k]);
        }
    }
    P->nspan = n;
}

/* The dilated cells of chart c at scale s, turn o, as runs; 0 if the
 * chart cannot fit the grid. */
PW__DEF int pw__atlas_profile(pw__atlas_packer *P, int c, double s, int o)
{
    const double *R = P->rect + 6 * c;
    double bw = (o & 1 ? R[5] : R[4]) * s, bh = (o & 1 ? R[4] : R[5]) * s;
    int w, h;
    if (!(bw + P->gutter + 1 <= P->size && bh + P->gutter + 1 <= P->size)) return 0;
    w = pw_maxi((int)ceil(bw), 1);
    h = pw_maxi((int)ceil(bh), 1);
    P->wp = w + P->gutter;
    P->hp = h + P->gutter;
    if (P->wp > P->size || P->hp > P->size) return 0;
    pw__atlas_cover(P, c, s, o, w, h);
    pw__atlas_cover_runs(P, w, h);
    pw__atlas_dilate_runs(P, h);
    return 1;
}

/* The leftmost x at which every run fits with the chart's bottom on row
 * y, or -1. A run that does not fit tells how far to jump: past the
 * occupied cell that stops it, or past the occupied run it starts in. The
 * runs are tried in P->ord, and one that fails moves to the front: runs
 * that failed at one position tend to fail at the next. */
PW__DEF int pw__atlas_scan(pw__atlas_packer *P, int y)
{
    int x = 0, j, k;
    while (x + P->wp <= P->size) {
        int v = 0, q = 0;
        for (j = 0; j < P->nspan; j++) {
            q = P->ord[j];
            v = P->run[(size_t)(y + P->srow[q]) * P->size + x + P->sl[q]];
            if (v < P->sr[q] - P->sl[q]) break;
        }
        if (j == P->nspan) return x;
        for (k = j; k > 0; k--) P->ord[k] = P->ord[k - 1];
        P->ord[0] = q;
        x = v > 0 ? x + v + 1 : x - v;
    }
    return -1;
}

/* Marks cells [a, b) of grid row y occupied. Each cell's run depends only
 * on the cells to its right, so the runs are recounted from b - 1 leftwards
 * until one comes out unchanged; then the row's longest free run, jumping
 * from run to run. */
PW__DEF void pw__atlas_mark(pw__atlas_packer *P, int y, int a, int b)
{
    int16_t *row = P->run + (size_t)y * P->size;
    int k, n = P->size, best = 0;
    for (k = a; k < b; k++) row[k] = -1;
    for (k = b - 1; k >= 0; k--) {
        int16_t v;
        if (k >= a || row[k] < 0) v = (int16_t)(k + 1 < n && row[k + 1] < 0 ? row[k + 1] - 1 : -1);
        else v = (int16_t)(k + 1 < n && row[k + 1] > 0 ? row[k + 1] + 1 : 1);
        if (k < a && v == row[k]) break;
        row[k] = v;
    }
    for (k = 0; k<n; k += row[k]> 0 ? row[k] : -row[k])
        if (row[k] > best) best = row[k];
    P->maxrun[y] = best;
}

/* Marks the runs of the chosen turn (P->kl, P->kr, P->krow: nkeep runs)
 * occupied with the chart's box at (x, y). */
PW__DEF void pw__atlas_occupy(pw__atlas_packer *P, int x, int y)
{
    int k;
    for (k = 0; k < P->nkeep; k++) pw__atlas_mark(P, y + P->krow[k], x + P->kl[k], x + P->kr[k]);
}

/* Keeps the runs of the turn just profiled, the best so far. */
PW__DEF void pw__atlas_keep(pw__atlas_packer *P)
{
    size_t n = (size_t)P->nspan * sizeof(int);
    memcpy(P->kl, P->sl, n);
    memcpy(P->kr, P->sr, n);
    memcpy(P->krow, P->srow, n);
    P->nkeep = P->nspan;
}

/* The lowest position (its top, then its bottom row, then leftmost) of
 * the chart profiled last, improving on *best_top: 1 if found. Rows
 * whose longest free run is too short for the chart's are passed over
 * without a scan. */
PW__DEF int pw__atlas_fit(pw__atlas_packer *P, int *best_top, int *bx, int *by)
{
    int widest = 0, y, i, k;
    for (k = 1; k < P->nspan; k++)
        if (P->sr[k] - P->sl[k] > P->sr[widest] - P->sl[widest]) widest = k;
    for (k = 0; k < P->nspan; k++) P->ord[k] = k; /* the widest first */
    P->ord[0] = widest;
    P->ord[widest] = 0;
    for (y = 0; y + P->hp <= P->size && y + P->hp < *best_top; y++) {
        int x;
        if (P->maxrun[y + P->srow[widest]] < P->sr[widest] - P->sl[widest]) continue;
        for (i = 0; i < P->hp; i++)
            if (P->maxrun[y + i] < P->rowmax[i]) break;
        if (i < P->hp || (x = pw__atlas_scan(P, y)) < 0) continue;
        *best_top = y + P->hp;
        *bx = x;
        *by = y;
        return 1;
    }
    return 0;
}

/* Places chart c at scale s in the turn that ends lowest; 0 if it fits
 * nowhere. */
PW__DEF int pw__atlas_place(pw__atlas_packer *P, int c, double s)
{
    int o, best_o = -1, best_top = INT_MAX, x = 0, y = 0;
    for (o = 0; o < 4; o++)
        if (pw__atlas_profile(P, c, s, o) && P->nspan > 0 && pw__atlas_fit(P, &best_top, &x, &y)) {
            best_o = o;
            pw__atlas_keep(P);
        }
    if (best_o < 0) return 0;
    pw__atlas_occupy(P, x, y);
    P->place[3 * c] = x + P->pad_lo;
    P->place[3 * c + 1] = y + P->pad_lo;
    P->place[3 * c + 2] = best_o;
    return 1;
}

/* Packs every chart at scale s (cells per mesh unit); 0 if one does not fit. */
PW__DEF int pw__atlas_pack_at(pw__atlas_packer *P, double s)
{
    int i, k, n = P->size;
    for (i = 0; i < n; i++) {
        for (k = 0; k < n; k++) P->run[(size_t)i * n + k] = (int16_t)(n - k);
        P->maxrun[i] = n;
    }
    for (i = 0; i < P->C->n; i++)
        if (!pw__atlas_place(P, P->order[i], s)) return 0;
    return 1;
}

typedef struct pw__atlas_by_area {
    double area;
    int chart;
} pw__atlas_by_area;

PW__DEF int pw__atlas_cmp_area(const void *x, const void *y)
{
    const pw__atlas_by_area *p = (const pw__atlas_by_area *)x, *q = (const pw__atlas_by_area *)y;
    if (p->area != q->area) return p->area > q->area ? -1 : 1;
    return p->chart - q->chart;
}

/* Areas, the packing order (largest first) and each chart's rectangle. */
PW__DEF int pw__atlas_pack_prepare(const pw_alloc *a, pw__atlas_packer *P, pw_err *e)
{
    const pw_atlas_charts *C = P->C;
    int c, i, nb = P->bstart[C->n];
    double *pts = (double *)pw_alloc_array(a, 2 * (size_t)nb, sizeof(double), "packing", e);
    double *hull = (double *)pw_alloc_array(a, 2 * ((size_t)nb + 1), sizeof(double), "packing", e);
    pw__atlas_by_area *by = (pw__atlas_by_area *)pw_alloc_array(a, (size_t)C->n, sizeof *by, "packing", e);
    int r = pts && hull && by ? PW_OK : PW_ERR_NOMEM;
    for (c = 0; r == PW_OK && c < C->n; c++) {
        P->area[c] = 0.0;
        for (i = C->start[c]; i < C->start[c + 1]; i++) P->area[c] += P->m->area[C->faces[i]];
        by[c].area = P->area[c];
        by[c].chart = c;
        pw__atlas_chart_rect(P, c, pts, hull);
    }
    if (r == PW_OK) {
        qsort(by, (size_t)C->n, sizeof *by, pw__atlas_cmp_area);
        for (c = 0; c < C->n; c++) P->order[c] = by[c].chart;
    }
    pw_free(a, pts);
    pw_free(a, hull);
    pw_free(a, by);
    return r;
}

/* The packing grid: cells of one pixel up to 1024 pixels a side, of
 * ceil(size / 1024) pixels beyond (the search costs grow with the grid's
 * area; a chart then loses at most a cell's rounding per side). */
PW__DEF int pw__atlas_packer_init(const pw_atlas_job *job, pw__atlas_packer *P, const pw_atlas_charts *C, pw_err *e)
{
    const pw_alloc *a = job->a;
    int size = job->size, gutter = job->gutter;
    size_t n = (size_t)C->n, rows, cells, spans, runs;
    memset(P, 0, sizeof *P);
    P->m = job->m;
    P->C = C;
    P->pixels = size;
    P->unit = (size + 1023) / 1024;
    P->size = size / P->unit;
    P->pad_lo = (gutter / 2 + P->unit - 1) / P->unit;
    P->gutter = P->pad_lo + ((gutter + 1) / 2 + P->unit - 1) / P->unit;
    rows = (size_t)P->size + 2;
    cells = (size_t)P->size * P->size;
    runs = (size_t)P->size * ((size_t)P->size / 2 + 1);                    /* runs are separated by gaps */
    spans = ((size_t)P->size + P->gutter + 1) * ((size_t)P->size / 2 + 1); /* + a row's gathering */
    P->rect = (double *)pw_alloc_array(a, 6 * n, sizeof(double), "packing", e);
    P->area = (double *)pw_alloc_array(a, n, sizeof(double), "packing", e);
    P->order = (int *)pw_alloc_array(a, n, sizeof(int), "packing", e);
    P->place = (int *)pw_alloc_array(a, 3 * n, sizeof(int), "packing", e);
    P->best = (int *)pw_alloc_array(a, 3 * n, sizeof(int), "packing", e);
    P->bstart = (int *)pw_alloc_array(a, n + 1, sizeof(int), "packing", e);
    P->run = (int16_t *)pw_alloc_array(a, (size_t)P->size * P->size, sizeof(int16_t), "packing bitmap", e);
    P->maxrun = (int *)pw_alloc_array(a, rows, sizeof(int), "packing", e);
    P->rowmax = (int *)pw_alloc_array(a, rows, sizeof(int), "packing", e);
    P->lo = (double *)pw_alloc_array(a, rows, sizeof(double), "packing", e);
    P->hi = (double *)pw_alloc_array(a, rows, sizeof(double), "packing", e);
    P->cov = (unsigned char *)pw_alloc_array(a, cells, 1, "packing bitmap", e);
    P->cl = (int *)pw_alloc_array(a, runs, sizeof(int), "packing runs", e);
    P->cr = (int *)pw_alloc_array(a, runs, sizeof(int), "packing runs", e);
    P->cst = (int *)pw_alloc_array(a, rows, sizeof(int), "packing runs", e);
    P->sl = (int *)pw_alloc_array(a, spans, sizeof(int), "packing runs", e);
    P->sr = (int *)pw_alloc_array(a, spans, sizeof(int), "packing runs", e);
    P->srow = (int *)pw_alloc_array(a, spans, sizeof(int), "packing runs", e);
    P->ord = (int *)pw_alloc_array(a, spans, sizeof(int), "packing runs", e);
    P->kl = (int *)pw_alloc_array(a, spans, sizeof(int), "packing runs", e);
    P->kr = (int *)pw_alloc_array(a, spans, sizeof(int), "packing runs", e);
    P->krow = (int *)pw_alloc_array(a, spans, sizeof(int), "packing runs", e);
    if (P->rect && P->area && P->order && P->place && P->best && P->bstart && P->run && P->maxrun && P->rowmax &&
        P->lo && P->hi && P->cov && P->cl && P->cr && P->cst && P->sl && P->sr && P->srow && P->ord && P->kl && P->kr &&
        P->krow)
        P->bedge = (int *)pw_alloc_array(a, (size_t)pw__atlas_boundary(P, 0), sizeof(int), "packing", e);
    if (!P->bedge) {
        pw__atlas_packer_free(a, P);
        return PW_ERR_NOMEM;
    }
    pw__atlas_boundary(P, 1);
    return PW_OK;
}

/* Packs at scale s and remembers the placement if everything fits. */
PW__DEF int pw__atlas_try(pw__atlas_packer *P, double s)
{
    if (!pw__atlas_pack_at(P, s)) return 0;
    memcpy(P->best, P->place, sizeof(int) * 3 * (size_t)P->C->n);
    return 1;
}

/* The largest scale (cells per mesh unit) at which every chart fits, to
 * 0.5 %: from fill 1/2 (downwards by 0.8 while that fails) by bisection.
 * Leaves its placement in P->best. */
PW__DEF int pw__atlas_pack_search(pw__atlas_packer *P, const pw_progress *prog, double *scale, pw_err *e)
{
    double total = 0.0, maxdim = 0.0, hi, lo, s;
    int c;
    for (c = 0; c < P->C->n; c++) {
        total += P->area[c];
        maxdim = P->rect[6 * c + 4] > maxdim ? P->rect[6 * c + 4] : maxdim;
        maxdim = P->rect[6 * c + 5] > maxdim ? P->rect[6 * c + 5] : maxdim;
    }
    hi = P->size / sqrt(total);
    lo = hi * sqrt(0.5);
    while (!pw__atlas_try(P, lo)) {
        if (lo * maxdim < 0.5) /* every chart within one cell, and still too many */
            return pw_fail(e, PW_ERR_LIMIT,
                           "atlas: %d charts do not fit in %dx%d pixels with a %d-pixel "
                           "gutter (use a larger size, a wider cone or a smaller gutter)",
                           P->C->n, P->pixels, P->pixels, P->gutter * P->unit);
        hi = lo;
        lo *= 0.8;
    }
    while (hi > lo * 1.005) {
        if (pw_report(prog, 0.5f + 0.2f * (float)(lo / hi), "atlas packing", e)) return PW_ERR_CANCELLED;
        s = 0.5 * (lo + hi);
        if (pw__atlas_try(P, s)) lo = s;
        else hi = s;
    }
    *scale = lo;
    return PW_OK;
}

/* Atlas coordinates of every corner ((0,0) bottom-left of the image) and
 * the fill: the charts' area over the image's, from the coordinates. */
PW__DEF void pw__atlas_pack_uvs(const pw__atlas_packer *P, double s, float *uvs, float *fill)
{
    const pw_atlas_charts *C = P->C;
    double sum = 0.0;
    int c, i, k;
    for (c = 0; c < C->n; c++) {
        const int *pl = P->best + 3 * c;
        for (i = C->start[c]; i < C->start[c + 1]; i++) {
            int f = C->faces[i];
            double t[6];
            for (k = 0; k < 3; k++) {
                double q[2];
                pw__atlas_pack_xy(P, c, s, pl[2], C->uv + 6 * f + 2 * k, q);
                uvs[6 * f + 2 * k] = (float)((pl[0] + q[0]) * P->unit / P->pixels);
                uvs[6 * f + 2 * k + 1] = (float)((pl[1] + q[1]) * P->unit / P->pixels);
                t[2 * k] = uvs[6 * f + 2 * k];
                t[2 * k + 1] = uvs[6 * f + 2 * k + 1];
            }
            sum += 0.5 * pw__atlas_area2(t);
        }
    }
    *fill = (float)sum;
}

/* packing: the charts C of job->m into the unit square; uvs gets nf*6
 * coordinates. */
PW__DEF int pw_atlas_pack(const pw_atlas_job *job, const pw_atlas_charts *C, float *uvs, float *fill, pw_err *e)
{
    pw__atlas_packer P;
    double s = 0.0;
    int r;
    if ((r = pw__atlas_packer_init(job, &P, C, e))) return r;
    if ((r = pw__atlas_pack_prepare(job->a, &P, e)) == PW_OK &&
        (r = pw__atlas_pack_search(&P, job->prog, &s, e)) == PW_OK)
        pw__atlas_pack_uvs(&P, s, uvs, fill);
    pw__atlas_packer_free(job->a, &P);
    return r;
}

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

/* ---- layout ------------------------------------------------------------------- */

/* Charts of job->m (job->cone in degrees) packed into a size x size atlas
 * with `gutter` pixels between them: per-corner coordinates uvs (m->nf *
 * 6, allocated here), the chart count and the fraction of the image
 * covered. */
PW__DEF int pw_atlas_layout(const pw_atlas_job *job, float **uvs, int *ncharts, float *fill, pw_err *e)
{
    const pw_alloc *a = job->a;
    const pw_trimesh *m = job->m;
    pw_atlas_charts C;
    int r;
    *uvs = (float *)pw_alloc_array(a, (size_t)m->nf * 6, sizeof(float), "atlas coordinates", e);
    if (!*uvs) return PW_ERR_NOMEM;
    if ((r = pw_atlas_charts_build(a, m, job->cone, job->prog, &C, e)) == PW_OK) {
        *ncharts = C.n;
        r = pw_atlas_pack(job, &C, *uvs, fill, e);
        pw_atlas_charts_free(a, &C);
    }
    if (r != PW_OK) {
        pw_free(a, *uvs);
        *uvs = NULL;
    }
    return r;
}

#endif /* PW__ATLAS_V1 */
