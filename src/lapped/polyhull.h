/* polyhull: the polygonal hull of a texture patch (Praun, Finkelstein and
 * Hoppe 2000, §3.3 and Fig. 4): a simple polygon with few vertices that
 * contains every pixel of the patch with non-zero alpha. Surface-patch growth
 * asks it whether a mesh edge, mapped into texture space, still reaches into
 * the patch ("we test to see if the edge intersects the interior of a
 * polygonal hull of the texture patch").
 *
 * Construction (pw_polyhull_build):
 *  1. The set of pixels with alpha > 0 (NaN counts as 0) is made one
 *     4-connected set without holes. Separate components are joined by
 *     one-pixel-wide bridges along the shortest-path tree of a 0-1
 *     breadth-first search from the first component (stepping onto a set
 *     pixel costs 0, onto another pixel 1), so bridges are short and shared;
 *     then every background pixel that is not 4-connected to the outside of
 *     the image is filled. Such a set has no pinch corner (two set pixels
 *     meeting only at a corner), so the boundary of the union of its pixel
 *     squares is one simple rectilinear polygon.
 *  2. That boundary is traced with the interior on its left, keeping only
 *     the corners: the paper's "polygon with vertices at all the boundary
 *     pixels" with its collinear runs already collapsed (they cost no area).
 *  3. 2D progressive hull (Sander et al. 2000, as §3.3 adapts it): the edge
 *     (v1,v2) between neighbours v0 and v3 collapses to a point p that lies
 *     on or outside the supporting lines of (v0,v1), (v1,v2) and (v2,v3), so
 *     the polygon only grows. The area added is linear in p, so the best p
 *     is a vertex of that feasible region: v1, v2, or the intersection of
 *     lines (v0,v1) and (v2,v3) (the three cases of Fig. 4; the last only
 *     inside the image, where the patch ends). Collapses are taken in order
 *     of area added, from a binary heap whose stale entries are skipped by
 *     version stamps. Equal areas, common on the pixel staircase, go to the
 *     collapse that shortens the perimeter most: it cuts a step diagonally
 *     instead of growing a bigger rectilinear corner, which makes a 32-gon
 *     add about 2% of the area instead of about 9%. A collapse whose new
 *     edges would touch or cross the rest of the polygon is skipped
 *     (checked against the nearby edges, kept in a uniform grid while the
 *     polygon is large). It stops at max_vertices (zero-area collapses go
 *     on below it) or when no collapse is possible; skipped collapses are
 *     retried in up to PW__HULL_PASSES passes.
 *
 * Coordinates are texture coordinates: u = x / w to the right, v = 1 - y / h
 * upwards (row 0 of the image is v = 1), so the polygon is counter-clockwise.
 * The queries count points within PW_POLYHULL_EPS of the hull as inside,
 * which absorbs the rounding of the vertices to float.
 *
 * Cost: O(w h) for the pixel stage, O(n log n) collapses for a boundary of n
 * corners (each checked against the few edges near it); a 512 x 512 splotch
 * takes a few milliseconds. Queries are O(vertices). */
#ifndef PW__POLYHULL_V1
#define PW__POLYHULL_V1

#include "../common/base.h"

typedef struct pw_polyhull {
    int n;     /* vertices */
    float *uv; /* n*2, counter-clockwise, texture coordinates */
} pw_polyhull;

#define PW_POLYHULL_EPS 1e-6 /* query tolerance, texture coordinates */
#define PW__HULL_PASSES 16   /* retries of collapses that were blocked */
#define PW__HULL_GRID_MIN 64 /* below this many vertices, check every edge */

/* ---- pixel stage: one 4-connected set without holes ----------------------- */

/* The image padded with two rings of cells: cell (x+2, y+2) is pixel
 * (x, y). The inner ring is background outside the image; the outer ring is
 * a wall that floods never enter, so neighbours need no bounds checks. */
enum {
    PW__HM_IN = 1,   /* in the set */
    PW__HM_MARK = 2, /* scratch: reached */
    PW__HM_DONE = 4, /* scratch: settled by the search */
    PW__HM_WALL = 8, /* outer ring */
    PW__HM_OUT = 16  /* not a pixel of the image (both rings) */
};

typedef struct pw__hgrid {
    int w, h, W, H;
    unsigned char *m;
    int *q; /* W*H stack */
} pw__hgrid;

/* Flood fill from the cells on the stack q[0..top-1] (already marked with
 * `flag`): every 4-neighbour whose set bit equals `in`, that is no wall and
 * lacks `flag` gets it. Returns how many cells were marked. */
PW__DEF long pw__hull_flood(pw__hgrid *g, int top, int in, int flag)
{
    long count = 0;
    int off[4], k;
    off[0] = -1;
    off[1] = 1;
    off[2] = -g->W;
    off[3] = g->W;
    while (top > 0) {
        int c = g->q[--top];
        for (k = 0; k < 4; k++) {
            int d = c + off[k];
            if ((g->m[d] & (PW__HM_WALL | flag)) || (g->m[d] & PW__HM_IN) != in) continue;
            g->m[d] = (unsigned char)(g->m[d] | flag);
            g->q[top++] = d;
            count++;
        }
    }
    return count;
}

/* 0-1 breadth-first search over the image's pixels from cell s: par[] gets
 * the shortest-path tree where entering a set cell costs 0 and any other
 * cell 1 (a deque: cost-0 steps go to the front). Every cell is pushed at
 * most twice, so a ring of 2N+2 entries never overflows. */
PW__DEF void pw__hull_bfs(pw__hgrid *g, int s, int *dist, int *par, int *dq)
{
    int N = g->W * g->H, cap = 2 * N + 2, head = 0, tail = 0, i, off[4], k;
    off[0] = -1;
    off[1] = 1;
    off[2] = -g->W;
    off[3] = g->W;
    for (i = 0; i < N; i++) dist[i] = INT_MAX;
    dist[s] = 0;
    dq[tail++] = s;
    while (head != tail) {
        int c = dq[head];
        head = head + 1 == cap ? 0 : head + 1;
        if (g->m[c] & PW__HM_DONE) continue;
        g->m[c] = (unsigned char)(g->m[c] | PW__HM_DONE);
        for (k = 0; k < 4; k++) {
            int d = c + off[k], nd;
            if (g->m[d] & PW__HM_OUT) continue; /* bridges stay in the image */
            nd = dist[c] + ((g->m[d] & PW__HM_IN) ? 0 : 1);
            if (nd >= dist[d]) continue;
            dist[d] = nd;
            par[d] = c;
            if (nd == dist[c]) {
                head = head == 0 ? cap - 1 : head - 1;
                dq[head] = d;
            } else {
                dq[tail] = d;
                tail = tail + 1 == cap ? 0 : tail + 1;
            }
        }
    }
    for (i = 0; i < N; i++) g->m[i] = (unsigned char)(g->m[i] & ~PW__HM_DONE);
}

/* §3.3 needs one polygon: joins every component to the one of cell s. Each
 * component not yet reached follows the search tree back to a reached cell;
 * the cells on the way join the set, and everything 4-connected to them is
 * marked reached (so a component is bridged once). */
PW__DEF int pw__hull_connect(pw__hgrid *g, int s, long total, const pw_alloc *a, pw_err *e)
{
    int N = g->W * g->H, c, *dist, *par, *dq;
    g->m[s] = (unsigned char)(g->m[s] | PW__HM_MARK);
    g->q[0] = s;
    if (1 + pw__hull_flood(g, 1, 1, PW__HM_MARK) == total) return PW_OK; /* one component */
    dist = (int *)pw_alloc_array(a, (size_t)N, sizeof(int), "hull search", e);
    par = dist ? (int *)pw_alloc_array(a, (size_t)N, sizeof(int), "hull search", e) : NULL;
    dq = par ? (int *)pw_alloc_array(a, (size_t)N * 2 + 2, sizeof(int), "hull search", e) : NULL;
    if (!dq) {
        pw_free(a, dist);
        pw_free(a, par);
        return PW_ERR_NOMEM;
    }
    pw__hull_bfs(g, s, dist, par, dq);
    for (c = 0; c < N; c++) {
        int top = 0, d = c;
        if (!(g->m[c] & PW__HM_IN) || (g->m[c] & PW__HM_MARK)) continue;
        while (!(g->m[d] & PW__HM_MARK)) { /* the bridge: up the tree to a reached cell */
            g->m[d] = (unsigned char)(g->m[d] | PW__HM_IN | PW__HM_MARK);
            g->q[top++] = d;
            d = par[d];
        }
        pw__hull_flood(g, top, 1, PW__HM_MARK);
    }
    pw_free(a, dist);
    pw_free(a, par);
    pw_free(a, dq);
    return PW_OK;
}

/* Fills holes: pixels not 4-connected to the ring around the image through
 * background join the set. Clears the scratch marks. */
PW__DEF void pw__hull_fill(pw__hgrid *g)
{
    int N = g->W * g->H, i, s = g->W + 1; /* a corner of the inner ring */
    for (i = 0; i < N; i++) g->m[i] = (unsigned char)(g->m[i] & ~PW__HM_MARK);
    g->m[s] = (unsigned char)(g->m[s] | PW__HM_MARK);
    g->q[0] = s;
    pw__hull_flood(g, 1, 0, PW__HM_MARK);
    for (i = 0; i < N; i++) {
        if (!(g->m[i] & PW__HM_OUT) && !(g->m[i] & PW__HM_MARK)) g->m[i] = PW__HM_IN;
        g->m[i] = (unsigned char)(g->m[i] & ~PW__HM_MARK);
    }
}

/* ---- tracing the rectilinear boundary ------------------------------------- */

/* A polygon being simplified: vertices in a doubly linked ring, in lattice
 * units (X = x, Y = h - y: pixel corners are integer points). */
typedef struct pw__hentry {
    double cost, dper; /* area added, then perimeter change (ties) */
    int v, stamp;
} pw__hentry;

typedef struct pw__gnode {
    int v, stamp, next;
} pw__gnode;

typedef struct pw__phull {
    const pw_alloc *a;
    pw_err *e;
    int n0, n; /* vertices traced, alive */
    size_t cap;
    double *x, *y;        /* positions */
    int *prev, *next;     /* ring; prev = -1 once removed */
    int *cstamp, *estamp; /* versions of each vertex's collapse and of its outgoing edge */
    int *seen, qstamp;    /* edges already tested by the current query */
    double *px, *py;      /* the collapse's new position */
    pw__hentry *heap;
    size_t nheap, capheap;
    int gx, gy, use_grid; /* uniform grid of edges (by bounding box) */
    double cs;            /* cell side, lattice units */
    int *head;            /* gx*gy list heads */
    pw__gnode *node;
    size_t nnode, capnode;
    double clr;  /* clearance between non-adjacent edges, lattice units */
    double w, h; /* the image: the hull stays inside [0,w] x [0,h] */
} pw__phull;

/* Is the cell whose lower-left lattice corner is (X, Y) in the set? */
PW__DEF int pw__hull_in(const pw__hgrid *g, int X, int Y)
{
    return g->m[(size_t)(g->h - Y + 1) * g->W + X + 2] & PW__HM_IN;
}

PW__DEF int pw__hull_push_vertex(pw__phull *P, int X, int Y)
{
    if (P->n0 == (int)P->cap) {
        size_t c = P->cap;
        if (pw_grow(P->a, (void **)&P->x, &c, P->cap + 1, sizeof(double), "hull", P->e)) return PW_ERR_NOMEM;
        c = P->cap;
        if (pw_grow(P->a, (void **)&P->y, &c, P->cap + 1, sizeof(double), "hull", P->e)) return PW_ERR_NOMEM;
        P->cap = c;
    }
    P->x[P->n0] = X;
    P->y[P->n0] = Y;
    P->n0++;
    return PW_OK;
}

/* Walks the boundary with the set on the left, starting along the top edge
 * of the first set pixel in row order, and records every corner. At each
 * lattice point the cells ahead-left and ahead-right decide: ahead-left
 * outside turns left, both inside turns right, else straight on. */
PW__DEF int pw__hull_trace(const pw__hgrid *g, pw__phull *P)
{
    int x0 = 0, y0 = 0, cx, cy, dx = -1, dy = 0, sx, sy, i;
    for (i = 0; i < g->w * g->h; i++)
        if (pw__hull_in(g, i % g->w, g->h - 1 - i / g->w)) break;
    x0 = i % g->w;
    y0 = i / g->w;
    sx = cx = x0 + 1;
    sy = cy = g->h - y0;
    do {
        int lx = -dy, ly = dx, al, ar;
        cx += dx;
        cy += dy;
        al = pw__hull_in(g, (2 * cx + dx + lx - 1) / 2, (2 * cy + dy + ly - 1) / 2);
        ar = pw__hull_in(g, (2 * cx + dx - lx - 1) / 2, (2 * cy + dy - ly - 1) / 2);
        if (!al || ar) {
            if (pw__hull_push_vertex(P, cx, cy)) return PW_ERR_NOMEM;
            dx = !al ? lx : -lx; /* left, or right = -left */
            dy = !al ? ly : -ly;
        }
    } while (cx != sx || cy != sy || dx != -1 || dy != 0);
    return PW_OK;
}

/* ---- geometry ------------------------------------------------------------- */

/* Twice the signed area of (a, b, c): > 0 when c is left of a->b. */
PW__DEF double pw__hull_orient(double ax, double ay, double bx, double by, double cx, double cy)
{
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
}

/* Squared distance from point p to segment ab. */
PW__DEF double pw__hull_pseg2(double px, double py, double ax, double ay, double bx, double by)
{
    double ux = bx - ax, uy = by - ay, wx = px - ax, wy = py - ay, l2 = ux * ux + uy * uy, t;
    t = l2 > 0.0 ? (wx * ux + wy * uy) / l2 : 0.0;
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    wx -= t * ux;
    wy -= t * uy;
    return wx * wx + wy * wy;
}

/* Squared distance between segments ab and cd (0 when they cross). */
PW__DEF double pw__hull_sseg2(const double *a, const double *b, const double *c, const double *d)
{
    double o1 = pw__hull_orient(a[0], a[1], b[0], b[1], c[0], c[1]);
    double o2 = pw__hull_orient(a[0], a[1], b[0], b[1], d[0], d[1]);
    double o3 = pw__hull_orient(c[0], c[1], d[0], d[1], a[0], a[1]);
    double o4 = pw__hull_orient(c[0], c[1], d[0], d[1], b[0], b[1]);
    double r, t;
    if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) return 0.0;
    r = pw__hull_pseg2(a[0], a[1], c[0], c[1], d[0], d[1]);
    t = pw__hull_pseg2(b[0], b[1], c[0], c[1], d[0], d[1]);
    r = t < r ? t : r;
    t = pw__hull_pseg2(c[0], c[1], a[0], a[1], b[0], b[1]);
    r = t < r ? t : r;
    t = pw__hull_pseg2(d[0], d[1], a[0], a[1], b[0], b[1]);
    return t < r ? t : r;
}

/* Heap order: least area added first (§3.3); exact ties, which the pixel
 * staircase makes common, go to the collapse that shortens the perimeter
 * most (it cuts a diagonal step rather than growing a rectilinear corner:
 * the simplified hull then adds about a fifth of the area), then to the
 * lower vertex index. */
PW__DEF int pw__hull_less(const pw__hentry *a, const pw__hentry *b)
{
    if (a->cost != b->cost) return a->cost < b->cost;
    if (a->dper != b->dper) return a->dper < b->dper;
    return a->v < b->v;
}

/* ---- §3.3, Fig. 4: the collapse of one edge ------------------------------- */

/* Is p on or outside (right of) the supporting line of a->b? The slack,
 * 1e-9 pixel, only absorbs the rounding of intersection points. */
PW__DEF int pw__hull_outside(const pw__phull *P, int a, int b, double px, double py)
{
    double lx = P->x[b] - P->x[a], ly = P->y[b] - P->y[a];
    return pw__hull_orient(P->x[a], P->y[a], P->x[b], P->y[b], px, py) <= 1e-9 * sqrt(lx * lx + ly * ly);
}

/* Squared distance from p to vertex v. */
PW__DEF double pw__hull_d2(const pw__phull *P, int v, double px, double py)
{
    return (px - P->x[v]) * (px - P->x[v]) + (py - P->y[v]) * (py - P->y[v]);
}

/* Area added by replacing v0-v1-v2-v3 with v0-p-v3: the signed area of the
 * closed polygon (v0, p, v3, v2, v1), relative to v0 for precision. */
PW__DEF double pw__hull_added(const pw__phull *P, const int *v, double px, double py)
{
    double xs[5], ys[5], s = 0.0;
    int k;
    xs[0] = 0.0;
    ys[0] = 0.0;
    xs[1] = px - P->x[v[0]];
    ys[1] = py - P->y[v[0]];
    for (k = 2; k < 5; k++) {
        xs[k] = P->x[v[5 - k]] - P->x[v[0]];
        ys[k] = P->y[v[5 - k]] - P->y[v[0]];
    }
    for (k = 0; k < 5; k++) s += xs[k] * ys[(k + 1) % 5] - xs[(k + 1) % 5] * ys[k];
    return 0.5 * s;
}

/* Perimeter change of replacing v0-v1-v2-v3 with v0-p-v3. */
PW__DEF double pw__hull_dper(const pw__phull *P, const int *v, double px, double py)
{
    double d = sqrt(pw__hull_d2(P, v[0], px, py)) + sqrt(pw__hull_d2(P, v[3], px, py));
    int k;
    for (k = 0; k < 3; k++) d -= sqrt(pw__hull_d2(P, v[k], P->x[v[k + 1]], P->y[v[k + 1]]));
    return d;
}

/* The three candidates of Fig. 4 for collapsing the edge leaving v1: v1
 * (feasible when outside line v2v3), v2 (outside line v0v1), and the
 * intersection of lines v0v1 and v2v3 (outside line v1v2). The cheapest
 * feasible one goes to c->cost, c->dper, *px, *py; returns 0 when none is. */
PW__DEF int pw__hull_candidate(const pw__phull *P, int v1, pw__hentry *best, double *px, double *py)
{
    int v[4], ok[3], k, found = 0;
    double cx[3], cy[3], d1x, d1y, d2x, d2y, den;
    v[1] = v1;
    v[0] = P->prev[v1];
    v[2] = P->next[v1];
    v[3] = P->next[v[2]];
    if (P->n < 4) return 0;
    cx[0] = P->x[v[1]];
    cy[0] = P->y[v[1]];
    ok[0] = pw__hull_outside(P, v[2], v[3], cx[0], cy[0]);
    cx[1] = P->x[v[2]];
    cy[1] = P->y[v[2]];
    ok[1] = pw__hull_outside(P, v[0], v[1], cx[1], cy[1]);
    d1x = P->x[v[1]] - P->x[v[0]];
    d1y = P->y[v[1]] - P->y[v[0]];
    d2x = P->x[v[3]] - P->x[v[2]];
    d2y = P->y[v[3]] - P->y[v[2]];
    den = d1x * d2y - d1y * d2x;
    ok[2] = 0;
    if (den != 0.0) {
        double t = ((P->x[v[2]] - P->x[v[0]]) * d2y - (P->y[v[2]] - P->y[v[0]]) * d2x) / den;
        cx[2] = P->x[v[0]] + t * d1x;
        cy[2] = P->y[v[0]] + t * d1y;
        /* beyond v1 on ray v0->v1 and before v2 on ray v3->v2 */
        ok[2] = t > 1.0 && pw_is_finite(cx[2]) && pw_is_finite(cy[2]) &&
                (cx[2] - P->x[v[2]]) * d2x + (cy[2] - P->y[v[2]]) * d2y < 0.0 &&
                pw__hull_outside(P, v[1], v[2], cx[2], cy[2]);
    }
    ok[2] = ok[2] && cx[2] >= 0.0 && cx[2] <= P->w && cy[2] >= 0.0 && cy[2] <= P->h; /* the patch ends there */
    for (k = 0; k < 3; k++) {
        pw__hentry c;
        if (!ok[k] || pw__hull_d2(P, v[0], cx[k], cy[k]) < P->clr * P->clr ||
            pw__hull_d2(P, v[3], cx[k], cy[k]) < P->clr * P->clr)
            continue; /* would make a (nearly) zero-length edge */
        c.cost = pw__hull_added(P, v, cx[k], cy[k]);
        if (c.cost < 0.0) c.cost = 0.0; /* rounding of a collinear case */
        c.dper = pw__hull_dper(P, v, cx[k], cy[k]);
        c.v = v1;
        if (!found || pw__hull_less(&c, best)) {
            *best = c;
            *px = cx[k];
            *py = cy[k];
            found = 1;
        }
    }
    return found;
}

/* ---- the heap of collapses ------------------------------------------------- */

PW__DEF int pw__hull_heap_push(pw__phull *P, const pw__hentry *t)
{
    size_t i;
    if (pw_grow(P->a, (void **)&P->heap, &P->capheap, P->nheap + 1, sizeof(pw__hentry), "hull heap", P->e))
        return PW_ERR_NOMEM;
    i = P->nheap++;
    P->heap[i] = *t;
    while (i > 0 && pw__hull_less(&P->heap[i], &P->heap[(i - 1) / 2])) {
        pw__hentry t = P->heap[i];
        P->heap[i] = P->heap[(i - 1) / 2];
        P->heap[(i - 1) / 2] = t;
        i = (i - 1) / 2;
    }
    return PW_OK;
}

PW__DEF pw__hentry pw__hull_heap_pop(pw__phull *P)
{
    pw__hentry top = P->heap[0];
    size_t i = 0;
    P->heap[0] = P->heap[--P->nheap];
    for (;;) {
        size_t l = 2 * i + 1, r = l + 1, m = i;
        pw__hentry t;
        if (l < P->nheap && pw__hull_less(&P->heap[l], &P->heap[m])) m = l;
        if (r < P->nheap && pw__hull_less(&P->heap[r], &P->heap[m])) m = r;
        if (m == i) break;
        t = P->heap[i];
        P->heap[i] = P->heap[m];
        P->heap[m] = t;
        i = m;
    }
    return top;
}

/* Re-evaluates the collapse of the edge leaving v (a new version: older
 * heap entries for v become stale). */
PW__DEF int pw__hull_update(pw__phull *P, int v)
{
    pw__hentry t;
    P->cstamp[v]++;
    if (!pw__hull_candidate(P, v, &t, &P->px[v], &P->py[v])) return PW_OK;
    t.stamp = P->cstamp[v];
    return pw__hull_heap_push(P, &t);
}

/* ---- the grid of edges: which edges can a collapse's new edges touch? ----- */

PW__DEF int pw__hull_cell(double x, double cs, int n)
{
    double t = x / cs;
    if (!(t > 0.0)) return 0;
    return t >= (double)n ? n - 1 : (int)t;
}

/* Cell range of the box around points (xs[k], ys[k]), k < np, grown by the
 * clearance. */
PW__DEF void pw__hull_box(const pw__phull *P, const double *xs, const double *ys, int np, int *r)
{
    double lx = xs[0], hx = xs[0], ly = ys[0], hy = ys[0];
    int k;
    for (k = 1; k < np; k++) {
        lx = xs[k] < lx ? xs[k] : lx;
        hx = xs[k] > hx ? xs[k] : hx;
        ly = ys[k] < ly ? ys[k] : ly;
        hy = ys[k] > hy ? ys[k] : hy;
    }
    r[0] = pw__hull_cell(lx - P->clr, P->cs, P->gx);
    r[1] = pw__hull_cell(hx + P->clr, P->cs, P->gx);
    r[2] = pw__hull_cell(ly - P->clr, P->cs, P->gy);
    r[3] = pw__hull_cell(hy + P->clr, P->cs, P->gy);
}

/* Files the edge leaving vertex v (its current version) in every cell its
 * bounding box overlaps. */
PW__DEF int pw__hull_register(pw__phull *P, int v)
{
    double xs[2], ys[2];
    int r[4], i, j, b = P->next[v];
    xs[0] = P->x[v];
    xs[1] = P->x[b];
    ys[0] = P->y[v];
    ys[1] = P->y[b];
    pw__hull_box(P, xs, ys, 2, r);
    for (j = r[2]; j <= r[3]; j++)
        for (i = r[0]; i <= r[1]; i++) {
            pw__gnode *nd;
            if (pw_grow(P->a, (void **)&P->node, &P->capnode, P->nnode + 1, sizeof(pw__gnode), "hull grid", P->e))
                return PW_ERR_NOMEM;
            nd = &P->node[P->nnode];
            nd->v = v;
            nd->stamp = P->estamp[v];
            nd->next = P->head[j * P->gx + i];
            P->head[j * P->gx + i] = (int)P->nnode++;
        }
    return PW_OK;
}

/* ---- the collapse itself ---------------------------------------------------- */

/* Do adjacent edges a-b and b-c fold onto each other? */
PW__DEF int pw__hull_fold(const pw__phull *P, const double *a, const double *b, const double *c)
{
    double c2 = P->clr * P->clr;
    return pw__hull_pseg2(a[0], a[1], b[0], b[1], c[0], c[1]) < c2 ||
           pw__hull_pseg2(c[0], c[1], a[0], a[1], b[0], b[1]) < c2;
}

/* Does edge a (leaving vertex a) come within the clearance of the new edges
 * s1 = (v0, p) or s2 = (p, v3)? Edges adjacent to one of them are tested
 * against the other only. */
PW__DEF int pw__hull_hits_edge(const pw__phull *P, const int *v, const double *p, int a)
{
    double A[2], B[2], V0[2], V3[2], c2 = P->clr * P->clr;
    int b = P->next[a];
    if (a == v[0] || a == v[1] || a == v[2]) return 0; /* replaced edges */
    A[0] = P->x[a];
    A[1] = P->y[a];
    B[0] = P->x[b];
    B[1] = P->y[b];
    V0[0] = P->x[v[0]];
    V0[1] = P->y[v[0]];
    V3[0] = P->x[v[3]];
    V3[1] = P->y[v[3]];
    if (b != v[0] && pw__hull_sseg2(V0, p, A, B) < c2) return 1;
    if (a != v[3] && pw__hull_sseg2(p, V3, A, B) < c2) return 1;
    return 0;
}

/* Would collapsing the edge leaving v1 to p make the polygon touch or cross
 * itself? (§3.3: "operations that would give rise to self-intersections are
 * disallowed"; touching is refused too, so the result stays simple.) */
PW__DEF int pw__hull_blocked(pw__phull *P, int v1, const double *p)
{
    int v[4], a, r[4], i, j;
    double P0[2], P3[2], Pm[2], P4[2], xs[3], ys[3];
    v[1] = v1;
    v[0] = P->prev[v1];
    v[2] = P->next[v1];
    v[3] = P->next[v[2]];
    P0[0] = P->x[v[0]];
    P0[1] = P->y[v[0]];
    P3[0] = P->x[v[3]];
    P3[1] = P->y[v[3]];
    Pm[0] = P->x[P->prev[v[0]]];
    Pm[1] = P->y[P->prev[v[0]]];
    P4[0] = P->x[P->next[v[3]]];
    P4[1] = P->y[P->next[v[3]]];
    if (pw__hull_fold(P, P0, p, P3) || pw__hull_fold(P, Pm, P0, p) || pw__hull_fold(P, p, P3, P4)) return 1;
    if (!P->use_grid) {
        a = v[3];
        do {
            if (pw__hull_hits_edge(P, v, p, a)) return 1;
            a = P->next[a];
        } while (a != v[3]);
        return 0;
    }
    xs[0] = P0[0];
    xs[1] = p[0];
    xs[2] = P3[0];
    ys[0] = P0[1];
    ys[1] = p[1];
    ys[2] = P3[1];
    pw__hull_box(P, xs, ys, 3, r);
    P->qstamp++;
    for (j = r[2]; j <= r[3]; j++)
        for (i = r[0]; i <= r[1]; i++) {
            int k;
            for (k = P->head[j * P->gx + i]; k >= 0; k = P->node[k].next) {
                a = P->node[k].v;
                if (P->prev[a] < 0 || P->estamp[a] != P->node[k].stamp || P->seen[a] == P->qstamp) continue;
                P->seen[a] = P->qstamp;
                if (pw__hull_hits_edge(P, v, p, a)) return 1;
            }
        }
    return 0;
}

/* Collapses the edge leaving v1 to its candidate point, and re-evaluates
 * the four collapses whose neighbourhoods changed. */
PW__DEF int pw__hull_collapse(pw__phull *P, int v1)
{
    int v0 = P->prev[v1], v2 = P->next[v1], v3 = P->next[v2], vm = P->prev[v0], r = PW_OK;
    P->x[v1] = P->px[v1];
    P->y[v1] = P->py[v1];
    P->next[v1] = v3;
    P->prev[v3] = v1;
    P->prev[v2] = P->next[v2] = -1;
    P->n--;
    P->estamp[v0]++;
    P->estamp[v1]++;
    if (P->n <= PW__HULL_GRID_MIN) P->use_grid = 0;
    if (P->use_grid && ((r = pw__hull_register(P, v0)) != PW_OK || (r = pw__hull_register(P, v1)) != PW_OK)) return r;
    if ((r = pw__hull_update(P, vm)) != PW_OK || (r = pw__hull_update(P, v0)) != PW_OK ||
        (r = pw__hull_update(P, v1)) != PW_OK || (r = pw__hull_update(P, v3)) != PW_OK)
        return r;
    return PW_OK;
}

/* One pass: every collapse queued, then taken cheapest first while allowed.
 * Sets *progress when something collapsed. */
PW__DEF int pw__hull_pass(pw__phull *P, int maxv, int *progress)
{
    int v, r;
    *progress = 0;
    P->nheap = 0;
    for (v = 0; v < P->n0; v++)
        if (P->prev[v] >= 0 && (r = pw__hull_update(P, v)) != PW_OK) return r;
    while (P->nheap > 0) {
        pw__hentry t = pw__hull_heap_pop(P);
        double p[2];
        if (P->prev[t.v] < 0 || P->cstamp[t.v] != t.stamp) continue; /* stale */
        if (t.cost > 0.0 && P->n <= maxv) break;                     /* only free collapses below the target */
        p[0] = P->px[t.v];
        p[1] = P->py[t.v];
        if (pw__hull_blocked(P, t.v, p)) continue;
        if ((r = pw__hull_collapse(P, t.v)) != PW_OK) return r;
        *progress = 1;
    }
    return PW_OK;
}

PW__DEF void pw__hull_release(pw__phull *P)
{
    pw_free(P->a, P->x);
    pw_free(P->a, P->y);
    pw_free(P->a, P->prev);
    pw_free(P->a, P->next);
    pw_free(P->a, P->cstamp);
    pw_free(P->a, P->estamp);
    pw_free(P->a, P->seen);
    pw_free(P->a, P->px);
    pw_free(P->a, P->py);
    pw_free(P->a, P->heap);
    pw_free(P->a, P->head);
    pw_free(P->a, P->node);
}

/* Ring links, per-vertex arrays and the edge grid for the traced polygon.
 * Cells are about 8 pixels, at most 128 per side. */
PW__DEF int pw__hull_setup(pw__phull *P, int w, int h)
{
    size_t n = (size_t)P->n0;
    int v, r, side = w > h ? w : h;
    P->n = P->n0;
    P->prev = (int *)pw_alloc_array(P->a, n, sizeof(int), "hull", P->e);
    P->next = (int *)pw_alloc_array(P->a, n, sizeof(int), "hull", P->e);
    P->cstamp = (int *)pw_calloc_array(P->a, n, sizeof(int), "hull", P->e);
    P->estamp = (int *)pw_calloc_array(P->a, n, sizeof(int), "hull", P->e);
    P->seen = (int *)pw_calloc_array(P->a, n, sizeof(int), "hull", P->e);
    P->px = (double *)pw_alloc_array(P->a, n, sizeof(double), "hull", P->e);
    P->py = (double *)pw_alloc_array(P->a, n, sizeof(double), "hull", P->e);
    P->cs = side / 128 > 8 ? (double)side / 128.0 : 8.0;
    P->gx = (int)(w / P->cs) + 1;
    P->gy = (int)(h / P->cs) + 1;
    P->head = (int *)pw_alloc_array(P->a, (size_t)P->gx * P->gy, sizeof(int), "hull grid", P->e);
    if (!P->prev || !P->next || !P->cstamp || !P->estamp || !P->seen || !P->px || !P->py || !P->head)
        return PW_ERR_NOMEM;
    for (v = 0; v < P->n0; v++) {
        P->prev[v] = v == 0 ? P->n0 - 1 : v - 1;
        P->next[v] = v + 1 == P->n0 ? 0 : v + 1;
    }
    for (v = 0; v < P->gx * P->gy; v++) P->head[v] = -1;
    P->use_grid = P->n0 > PW__HULL_GRID_MIN;
    for (v = 0; P->use_grid && v < P->n0; v++)
        if ((r = pw__hull_register(P, v)) != PW_OK) return r;
    return PW_OK;
}

/* The simplified ring as texture coordinates, from its lowest vertex index. */
PW__DEF int pw__hull_output(const pw__phull *P, int w, int h, pw_polyhull *out)
{
    int v = 0, k;
    while (P->prev[v] < 0) v++;
    out->uv = (float *)pw_alloc_array(P->a, (size_t)P->n * 2, sizeof(float), "hull", P->e);
    if (!out->uv) return PW_ERR_NOMEM;
    out->n = P->n;
    for (k = 0; k < P->n; k++, v = P->next[v]) {
        out->uv[2 * k] = (float)(P->x[v] / w);
        out->uv[2 * k + 1] = (float)(P->y[v] / h);
    }
    return PW_OK;
}

/* ---- public --------------------------------------------------------------- */

PW__DEF void pw_polyhull_free(const pw_alloc *a, pw_polyhull *h)
{
    if (!h) return;
    pw_free(a, h->uv);
    h->uv = NULL;
    h->n = 0;
}

/* The rings, and the pixel set (alpha > 0); *total gets its pixel count
 * and *first its first cell in row order. */
PW__DEF int pw__hull_pixels(pw__hgrid *g, const float *alpha, int stride, long *total, int *first)
{
    int x, y;
    *total = 0;
    *first = -1;
    for (y = 0; y < g->H; y++)
        for (x = 0; x < g->W; x++) {
            int ring = x < 2 || y < 2 || x >= g->w + 2 || y >= g->h + 2;
            int wall = x == 0 || y == 0 || x == g->W - 1 || y == g->H - 1;
            g->m[y * g->W + x] = (unsigned char)((ring ? PW__HM_OUT : 0) | (wall ? PW__HM_WALL : 0));
        }
    for (y = 0; y < g->h; y++)
        for (x = 0; x < g->w; x++) {
            int c = (y + 2) * g->W + x + 2;
            if (!(alpha[((size_t)y * g->w + x) * stride] > 0.0f)) continue;
            g->m[c] = PW__HM_IN;
            if (*first < 0) *first = c;
            (*total)++;
        }
    return *total > 0;
}

/* §3.3: the polygonal hull of the pixels of alpha (w x h, `stride` floats
 * apart, e.g. 4 for the alpha of RGBA) that are > 0, simplified to at most
 * max_vertices vertices (0: 32) when possible. Free with pw_polyhull_free. */
PW__DEF int pw_polyhull_build(const pw_alloc *a, const float *alpha, int w, int h, int stride, int max_vertices,
                              pw_polyhull *out, pw_err *e)
{
    pw__hgrid g;
    pw__phull P;
    long total;
    int first, r = PW_OK, pass, progress = 1;
    if (out) {
        out->n = 0;
        out->uv = NULL;
    }
    if (!out || !alpha || w < 1 || h < 1 || stride < 1)
        return pw_fail(e, PW_ERR_INVALID, "polygonal hull: NULL argument or empty image");
    if (w > PW_MAX_IMAGE_DIM || h > PW_MAX_IMAGE_DIM || (int64_t)w * h > PW_MAX_IMAGE_PIXELS)
        return pw_fail(e, PW_ERR_LIMIT, "polygonal hull: %dx%d pixels is over the limit", w, h);
    if (max_vertices < 0 || (max_vertices > 0 && max_vertices < 3))
        return pw_fail(e, PW_ERR_INVALID, "polygonal hull: max_vertices must be 0 or at least 3 (got %d)",
                       max_vertices);
    if (max_vertices == 0) max_vertices = 32;
    memset(&P, 0, sizeof P);
    P.a = a;
    P.e = e;
    P.clr = 1e-3; /* a thousandth of a pixel */
    P.w = w;
    P.h = h;
    g.w = w;
    g.h = h;
    g.W = w + 4;
    g.H = h + 4;
    g.m = (unsigned char *)pw_alloc_array(a, (size_t)g.W * g.H, 1, "hull mask", e);
    g.q = g.m ? (int *)pw_alloc_array(a, (size_t)g.W * g.H, sizeof(int), "hull mask", e) : NULL;
    if (!g.q) r = PW_ERR_NOMEM;
    if (r == PW_OK && !pw__hull_pixels(&g, alpha, stride, &total, &first))
        r = pw_fail(e, PW_ERR_INVALID, "the patch is fully transparent");
    if (r == PW_OK) r = pw__hull_connect(&g, first, total, a, e);
    if (r == PW_OK) pw__hull_fill(&g);
    if (r == PW_OK) r = pw__hull_trace(&g, &P);
    pw_free(a, g.m);
    pw_free(a, g.q);
    if (r == PW_OK) r = pw__hull_setup(&P, w, h);
    for (pass = 0; r == PW_OK && progress && P.n > max_vertices && pass < PW__HULL_PASSES; pass++)
        r = pw__hull_pass(&P, max_vertices, &progress);
    if (r == PW_OK) r = pw__hull_output(&P, w, h, out);
    pw__hull_release(&P);
    return r == PW_OK ? PW_OK : pw_fail(e, r, "polygonal hull: out of memory");
}

/* Is (u, v) inside the hull or within PW_POLYHULL_EPS of it? Even-odd rule
 * plus a distance test for the boundary. */
PW__DEF int pw_polyhull_contains(const pw_polyhull *h, float u, float v)
{
    int i, j, in = 0;
    const double eps2 = PW_POLYHULL_EPS * PW_POLYHULL_EPS;
    if (!h || !h->uv || h->n < 3) return 0;
    for (i = 0, j = h->n - 1; i < h->n; j = i++) { /* crossing parity first: most queries are inside */
        double xi = h->uv[2 * i], yi = h->uv[2 * i + 1], xj = h->uv[2 * j], yj = h->uv[2 * j + 1];
        if ((yi > v) != (yj > v) && u < xj + (v - yj) * (xi - xj) / (yi - yj)) in = !in;
    }
    for (i = 0, j = h->n - 1; !in && i < h->n; j = i++) /* within PW_POLYHULL_EPS of the boundary */
        if (pw__hull_pseg2(u, v, h->uv[2 * j], h->uv[2 * j + 1], h->uv[2 * i], h->uv[2 * i + 1]) <= eps2) in = 1;
    return in;
}

/* Does segment (u0,v0)-(u1,v1) meet the hull (inside or on it, within
 * PW_POLYHULL_EPS)? Either an end is inside, or it comes near an edge. */
PW__DEF int pw_polyhull_segment_hits(const pw_polyhull *h, float u0, float v0, float u1, float v1)
{
    double s0[2], s1[2], a[2], b[2];
    const double eps2 = PW_POLYHULL_EPS * PW_POLYHULL_EPS;
    int i, j;
    if (!h || !h->uv || h->n < 3) return 0;
    if (pw_polyhull_contains(h, u0, v0) || pw_polyhull_contains(h, u1, v1)) return 1;
    s0[0] = u0;
    s0[1] = v0;
    s1[0] = u1;
    s1[1] = v1;
    for (i = 0, j = h->n - 1; i < h->n; j = i++) {
        a[0] = h->uv[2 * j];
        a[1] = h->uv[2 * j + 1];
        b[0] = h->uv[2 * i];
        b[1] = h->uv[2 * i + 1];
        if (pw__hull_sseg2(s0, s1, a, b) <= eps2) return 1;
    }
    return 0;
}

#endif /* PW__POLYHULL_V1 */
