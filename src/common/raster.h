/* raster: exact scan conversion of 2D triangles.
 *
 * Coordinates are in pixels: pixel (x, y) is the square [x, x+1) x [y, y+1)
 * and is covered when its centre (x + 0.5, y + 0.5) lies inside the
 * triangle. Only pixels of the viewport [0, w) x [0, h) are reported.
 *
 * Exactness. Vertices are snapped to a fixed-point grid of 1/2^bits pixel
 * (bits = 16 for viewports up to 2048 pixels a side, fewer for larger ones,
 * never fewer than 8), and the edge functions are evaluated in 64-bit
 * integers. Coverage is therefore exact for the snapped triangle, and the
 * top-left fill rule (a centre exactly on an edge belongs to the triangle
 * whose interior lies right of, or below, that edge) makes triangles that
 * share an edge (the same two vertices) cover each pixel along it exactly
 * once: no gaps, no double coverage, whatever the windings. Triangles whose
 * snapped area is zero (repeated or collinear vertices) cover nothing.
 * Non-finite coordinates cover nothing.
 *
 * Far vertices. Coordinates must stay within +-range (pw_raster_grid: 2^13
 * pixels for viewports up to 2048 a side, at least twice the viewport) for
 * 64-bit edge functions not to overflow.
 * Triangles reaching beyond are first clipped against that square in double
 * precision (each intersection computed from the edge's endpoints in a fixed
 * order, so both triangles of a shared edge get the same point) and split
 * into a fan; clipped pieces stay watertight with their neighbours.
 *
 * Interfaces, from convenient to fast:
 *   pw_raster_tri        calls fn(user, x, y, b0, b1, b2) for every covered
 *                        pixel, with the barycentrics of its centre;
 *   pw_raster_tri_spans  calls fn(user, y, xa, xb) for each covered run
 *                        [xa, xb) of a row (no per-pixel call: for coverage
 *                        masks and counts);
 *   pw_raster_setup / pw_raster_next / pw_raster_polygon: the snapped edge
 *                        functions and an exact row walker, for inner loops
 *                        that want no callback (the renderer uses these);
 *                        pw_raster_span gives the run of any one row.
 * Rows are produced top to bottom, pixels left to right. Viewports may be
 * up to 2^20 - 32 pixels a side (larger ones cover nothing). */
#ifndef PW__RASTER_V1
#define PW__RASTER_V1

#include "base.h"

#define PW_RASTER_MAX_PIECES 6 /* triangles from one clipped polygon of <= 4 vertices */

/* The raster target: viewport size and the fixed-point precision it allows. */
typedef struct pw_raster_grid {
    int w, h;       /* pixels [0, w) x [0, h) */
    int row0, row1; /* rows rasterized: [row0, row1), default [0, h) (a band of the frame;
                       snapping depends on w and h only, so a band covers exactly the
                       pixels the whole frame would in its rows) */
    int bits;       /* sub-pixel bits: vertices snap to multiples of 2^-bits */
    double range;   /* |coordinate| <= range is rasterized directly, beyond is clipped */
} pw_raster_grid;

/* One snapped triangle. Edge k is opposite vertex k; its value at a pixel
 * centre is (twice the area of the sub-triangle) * 2^(2 bits), positive
 * inside, and the barycentric of vertex k is (e_k - bias_k) / area2. */
typedef struct pw_raster_edges {
    int64_t e[3];       /* edge values at the centre of pixel (x0, y0), bias included */
    int64_t ex[3];      /* change per pixel step to the right */
    int64_t ey[3];      /* change per row down */
    int64_t bias[3];    /* 0 on top-left edges, -1 elsewhere: covered iff all e >= 0 */
    int64_t area2;      /* twice the snapped area in grid units, > 0 */
    int orient;         /* +1 or -1: sign of the area as given (y down) */
    int x0, y0, x1, y1; /* candidate pixels [x0, x1) x [y0, y1), inside the viewport */
    /* row walker (pw_raster_next), an exact integer DDA over the edges that
     * bound runs: nl left ones first, then right ones (horizontal edges only
     * trim [y0, y1)). Per edge: the run bound wd (pixels from x0) on the
     * current row, the remainder wg in [0, wa) of the edge value there, and
     * their change per row (ws, wc). */
    int64_t wd[3], wg[3], ws[3], wc[3], wa[3];
    int nl, nw;
} pw_raster_edges;

typedef void (*pw_raster_fn)(void *user, int x, int y, float b0, float b1, float b2);
typedef void (*pw_raster_span_fn)(void *user, int y, int xa, int xb);

/* Floor of a / 2^bits (a right shift of a negative value is not portable). */
PW__DEF int64_t pw__raster_floorshift(int64_t a, int bits)
{
    return a >= 0 ? a >> bits : -((-a + ((int64_t)1 << bits) - 1) >> bits);
}

/* floor(num / den) for den > 0 and |num| < 2^62: a floating-point estimate
 * (an integer division is far slower), off by a few units at most for
 * quotients up to 2^54, corrected exactly. */
PW__DEF int64_t pw__raster_fdiv(int64_t num, int64_t den)
{
    int64_t q = (int64_t)((double)num / (double)den);
    while (q * den > num) q--;
    while ((q + 1) * den <= num) q++;
    return q;
}

/* Chooses the precision for a w x h viewport; returns 0 if it is empty or
 * too large (over 2^20 - 32 pixels a side). bits + log2(range) = 29 keeps
 * every edge value below 2^62; the range is at least twice the viewport, so
 * bits >= 8. */
PW__DEF int pw_raster_grid_init(pw_raster_grid *g, int w, int h)
{
    int k = 8, m = w > h ? w : h;
    memset(g, 0, sizeof *g);
    if (w <= 0 || h <= 0 || m > (1 << 20) - 32) return 0;
    while ((1 << k) < 2 * m + 64) k++;
    g->w = w;
    g->h = h;
    g->row1 = h;
    g->bits = 29 - k < 16 ? 29 - k : 16;
    g->range = (double)(1 << (29 - g->bits)); /* >= 2^k */
    return 1;
}

/* Nearest grid point of coordinate x (|x| <= range), rounding half up:
 * floor(x 2^bits + 0.5) without a libm call. */
PW__DEF int64_t pw__raster_snap(const pw_raster_grid *g, double x)
{
    double v = x * (double)((int64_t)1 << g->bits) + 0.5;
    int64_t i = (int64_t)v; /* truncates toward zero */
    return (double)i > v ? i - 1 : i;
}

PW__DEF int64_t pw__raster_min3(const int64_t *v)
{
    int64_t m = v[0] < v[1] ? v[0] : v[1];
    return m < v[2] ? m : v[2];
}

PW__DEF int64_t pw__raster_max3(const int64_t *v)
{
    int64_t m = v[0] > v[1] ? v[0] : v[1];
    return m > v[2] ? m : v[2];
}

/* Pixel index range [lo, hi] whose centres lie in [a, b] (grid units). */
PW__DEF void pw__raster_centres(int64_t a, int64_t b, int bits, int n, int *lo, int *hi)
{
    int64_t half = (int64_t)1 << (bits - 1);
    int64_t l = -pw__raster_floorshift(half - a, bits); /* ceil((a - half) / one) */
    int64_t r = pw__raster_floorshift(b - half, bits);
    *lo = (int)(l < 0 ? 0 : (l > n ? n : l));
    *hi = (int)(r < -1 ? -1 : (r > n - 1 ? n - 1 : r));
}

/* Trims [y0, y1) to the rows where horizontal edges (a = 0) are not
 * negative and moves the edge values to the new y0. Returns 0 if no row is
 * left. */
PW__DEF int pw__raster_trim_rows(pw_raster_edges *s)
{
    int64_t y0 = s->y0, y1 = s->y1;
    int k;
    for (k = 0; k < 3; k++) {
        int64_t e = s->e[k], ey = s->ey[k];
        if (s->ex[k] != 0) continue;
        if (ey > 0 && e < 0) { /* first row with e + ey dy >= 0 */
            int64_t r = s->y0 - pw__raster_fdiv(e, ey);
            if (r > y0) y0 = r;
        } else if (ey < 0) { /* last row with e + ey dy >= 0 */
            int64_t r = s->y0 + pw__raster_fdiv(e, -ey) + 1;
            if (r < y1) y1 = r;
        }
    }
    if (y0 >= y1) return 0;
    for (k = 0; k < 3; k++) s->e[k] += s->ey[k] * (y0 - s->y0);
    s->y0 = (int)y0;
    s->y1 = (int)y1;
    return 1;
}

/* Starts the row walker at row y0. An edge with a = ex > 0 bounds the run
 * on the left: first d with e + a d >= 0, d = ceil(-e / a); one with a < 0 on
 * the right: last d with e + a d >= 0, d = floor(e / -a). Row to row, d
 * moves by a constant quotient and the remainder carries, as in Bresenham's
 * algorithm. Quotients stay below 2^54 (|e| < 2^62, |a| >= 2^8). */
PW__DEF void pw__raster_walk_init(pw_raster_edges *s)
{
    int k, side, m = 0;
    for (side = 1; side >= -1; side -= 2) {
        for (k = 0; k < 3; k++) {
            int64_t a = s->ex[k], e = s->e[k], ey = s->ey[k];
            if (a * side <= 0) continue;
            if (side > 0) { /* left: d = ceil(-e / a), remainder e + a d */
                s->wd[m] = -pw__raster_fdiv(e, a);
                s->ws[m] = -pw__raster_fdiv(ey, a);
                s->wg[m] = e + a * s->wd[m];
                s->wc[m] = ey + a * s->ws[m];
                s->wa[m] = a;
            } else { /* right: d = floor(e / b), remainder e - b d, b = -a */
                s->wd[m] = pw__raster_fdiv(e, -a);
                s->ws[m] = pw__raster_fdiv(ey, -a);
                s->wg[m] = e + a * s->wd[m];
                s->wc[m] = ey + a * s->ws[m];
                s->wa[m] = -a;
            }
            m++;
        }
        if (side > 0) s->nl = m;
    }
    s->nw = m;
}

/* The covered run [*xa, *xb) of the walker's current row, then steps to the
 * next row: call once per row from y0 to y1 - 1. Returns xb > xa. A few
 * integer operations per edge and no division. */
PW__DEF int pw_raster_next(pw_raster_edges *s, int *xa, int *xb)
{
    int64_t lo = 0, hi = s->x1 - s->x0;
    int k;
    for (k = 0; k < s->nl; k++) {
        if (s->wd[k] > lo) lo = s->wd[k];
        s->wd[k] += s->ws[k];
        s->wg[k] += s->wc[k];
        if (s->wg[k] >= s->wa[k]) {
            s->wg[k] -= s->wa[k];
            s->wd[k]--;
        }
    }
    for (; k < s->nw; k++) {
        if (s->wd[k] + 1 < hi) hi = s->wd[k] + 1;
        s->wd[k] += s->ws[k];
        s->wg[k] += s->wc[k];
        if (s->wg[k] >= s->wa[k]) {
            s->wg[k] -= s->wa[k];
            s->wd[k]++;
        }
    }
    if (lo >= hi) return 0;
    *xa = s->x0 + (int)lo;
    *xb = s->x0 + (int)hi;
    return 1;
}

/* pw_raster_setup without the row walker (nw = -1): for triangles a few
 * pixels wide, whose runs pw__raster_row finds by testing the candidate
 * pixels of the row, cheaper than the walker's divisions. */
PW__DEF int pw__raster_setup_edges(pw_raster_edges *s, const pw_raster_grid *g, const double xy[6])
{
    int64_t X[3], Y[3], one = (int64_t)1 << g->bits, half = one >> 1, px, py;
    int k, xlo, xhi, ylo, yhi;
    for (k = 0; k < 6; k++) /* outside the range (or NaN): pw_raster_polygon's job */
        if (!(xy[k] >= -g->range && xy[k] <= g->range)) return 0;
    for (k = 0; k < 3; k++) {
        X[k] = pw__raster_snap(g, xy[2 * k]);
        Y[k] = pw__raster_snap(g, xy[2 * k + 1]);
    }
    s->area2 = (X[1] - X[0]) * (Y[2] - Y[0]) - (Y[1] - Y[0]) * (X[2] - X[0]);
    if (s->area2 == 0) return 0;
    s->orient = s->area2 > 0 ? 1 : -1;
    pw__raster_centres(pw__raster_min3(X), pw__raster_max3(X), g->bits, g->w, &xlo, &xhi);
    pw__raster_centres(pw__raster_min3(Y), pw__raster_max3(Y), g->bits, g->h, &ylo, &yhi);
    if (ylo < g->row0) ylo = g->row0;
    if (yhi > g->row1 - 1) yhi = g->row1 - 1;
    if (xlo > xhi || ylo > yhi) return 0;
    s->x0 = xlo;
    s->x1 = xhi + 1;
    s->y0 = ylo;
    s->y1 = yhi + 1;
    if (s->area2 < 0) s->area2 = -s->area2;
    px = (int64_t)xlo * one + half;
    py = (int64_t)ylo * one + half;
    for (k = 0; k < 3; k++) {
        int a = (k + 1) % 3, b = (k + 2) % 3;
        /* e_k(P) = A (Px - Xa) + B (Py - Ya), oriented positive inside */
        int64_t A = (Y[a] - Y[b]) * s->orient, B = (X[b] - X[a]) * s->orient;
        /* top-left: the interior lies right of (A > 0) or below (A == 0,
         * B > 0) the edge; only those edges own the centres exactly on them */
        s->bias[k] = (A > 0 || (A == 0 && B > 0)) ? 0 : -1;
        s->e[k] = A * (px - X[a]) + B * (py - Y[a]) + s->bias[k];
        s->ex[k] = A * one;
        s->ey[k] = B * one;
    }
    s->nl = 0;
    s->nw = -1;
    return pw__raster_trim_rows(s);
}

/* Sets up the edge functions of a triangle whose coordinates all lie within
 * +-g->range (pw_raster_polygon handles the others; a triangle outside is
 * refused here). Returns 1 if some pixel of the viewport may be covered, 0
 * if none can be (zero area, off screen, out of range). */
PW__DEF int pw_raster_setup(pw_raster_edges *s, const pw_raster_grid *g, const double xy[6])
{
    if (!pw__raster_setup_edges(s, g, xy)) return 0;
    pw__raster_walk_init(s);
    return 1;
}

/* The covered run [*xa, *xb) of row y, for rows taken in order from y0 (as
 * pw_raster_next): from the walker, or without one (nw < 0) by testing the
 * edges at the row's candidate pixels (a convex run: the first covered
 * pixel, then up to the first one not covered). Returns xb > xa. */
PW__DEF int pw__raster_row(pw_raster_edges *s, int y, int *xa, int *xb)
{
    int64_t e0, e1, e2;
    int d = 0, lo, n = s->x1 - s->x0;
    if (s->nw >= 0) return pw_raster_next(s, xa, xb);
    e0 = s->e[0] + s->ey[0] * (y - s->y0);
    e1 = s->e[1] + s->ey[1] * (y - s->y0);
    e2 = s->e[2] + s->ey[2] * (y - s->y0);
    for (; d < n && (e0 | e1 | e2) < 0; d++) {
        e0 += s->ex[0];
        e1 += s->ex[1];
        e2 += s->ex[2];
    }
    for (lo = d; d < n && (e0 | e1 | e2) >= 0; d++) {
        e0 += s->ex[0];
        e1 += s->ex[1];
        e2 += s->ex[2];
    }
    if (lo >= d) return 0;
    *xa = s->x0 + lo;
    *xb = s->x0 + d;
    return 1;
}

/* The covered run [*xa, *xb) of any row y (y0 <= y < y1), without the
 * walker; returns xb > xa. Each edge bounds the run at -e/a pixels from x0:
 * estimated in floating point, then corrected with exact integer tests, so
 * the result is exact. */
PW__DEF int pw_raster_span(const pw_raster_edges *s, int y, int *xa, int *xb)
{
    int64_t lo = 0, hi = s->x1 - s->x0, n = hi;
    int k;
    for (k = 0; k < 3; k++) {
        int64_t e = s->e[k] + s->ey[k] * (y - s->y0), a = s->ex[k], d;
        double t = a ? -(double)e / (double)a : 0.0; /* the bound, within 1e-6 */
        if (a > 0) {                                 /* first d with e + a d >= 0 */
            if (e >= 0) continue;
            if (t > (double)n + 1.0) return 0;
            d = (int64_t)t + 1; /* floor(t) + 1: the answer, or one off either way */
            d += e + a * d < 0;
            d -= e + a * (d - 1) >= 0;
            if (d > lo) lo = d;
        } else if (a < 0) { /* last d with e + a d >= 0, plus one */
            if (e < 0) return 0;
            if (t >= (double)n) continue;
            d = (int64_t)t + 1;
            d += e + a * d >= 0;
            d -= e + a * (d - 1) < 0;
            if (d < hi) hi = d;
        } else if (e < 0) {
            return 0;
        }
    }
    if (lo >= hi) return 0;
    *xa = s->x0 + (int)lo;
    *xb = s->x0 + (int)hi;
    return 1;
}

/* Intersection of segment pq with the line coord[axis] == c, computed from
 * the lexicographically smaller endpoint so that both triangles sharing the
 * edge get exactly the same point. */
PW__DEF void pw__raster_cut(const double *p, const double *q, int axis, double c, double *out)
{
    const double *a = p, *b = q;
    double t;
    if (q[0] < p[0] || (q[0] == p[0] && q[1] < p[1])) {
        a = q;
        b = p;
    }
    t = (c - a[axis]) / (b[axis] - a[axis]);
    out[axis] = c;
    out[1 - axis] = a[1 - axis] + t * (b[1 - axis] - a[1 - axis]);
}

/* Clips the polygon in[n] (xy pairs) to the half-plane side*coord[axis] <=
 * range; returns the new vertex count. */
PW__DEF int pw__raster_clip1(const double *in, int n, int axis, double side, double range, double *out)
{
    int i, m = 0;
    for (i = 0; i < n; i++) {
        const double *p = in + 2 * i, *q = in + 2 * ((i + 1) % n);
        int pin = side * p[axis] <= range, qin = side * q[axis] <= range;
        if (pin) {
            out[2 * m] = p[0];
            out[2 * m + 1] = p[1];
            m++;
        }
        if (pin != qin) {
            pw__raster_cut(p, q, axis, side * range, out + 2 * m);
            m++;
        }
    }
    return m;
}

/* Splits a convex polygon of n <= 4 vertices (xy pairs, either winding) into
 * snapped triangles, clipping it to +-range first when needed. Writes up to
 * PW_RASTER_MAX_PIECES setups and returns their count. Fan pieces whose
 * snapped orientation disagrees with the polygon's are slivers made by
 * snapping near-collinear clip points (far outside the viewport): dropped. */
PW__DEF int pw_raster_polygon(const pw_raster_grid *g, const double *xy, int n, pw_raster_edges *out)
{
    double a[16], b[16], tri[6], area = 0.0;
    int i, np = 0, inside = 1;
    if (n < 3 || n > 4) return 0;
    for (i = 0; i < 2 * n; i++) {
        if (!pw_is_finite(xy[i])) return 0;
        if (xy[i] > g->range || xy[i] < -g->range) inside = 0;
    }
    memcpy(a, xy, sizeof(double) * 2 * n);
    if (!inside) {
        n = pw__raster_clip1(a, n, 0, 1.0, g->range, b);
        n = pw__raster_clip1(b, n, 0, -1.0, g->range, a);
        n = pw__raster_clip1(a, n, 1, 1.0, g->range, b);
        n = pw__raster_clip1(b, n, 1, -1.0, g->range, a);
    }
    for (i = 0; i < n; i++) {
        const double *p = a + 2 * i, *q = a + 2 * ((i + 1) % n);
        area += p[0] * q[1] - p[1] * q[0];
    }
    for (i = 1; i + 1 < n; i++) {
        tri[0] = a[0];
        tri[1] = a[1];
        memcpy(tri + 2, a + 2 * i, sizeof(double) * 4);
        if (pw_raster_setup(out + np, g, tri) && (n == 3 || (out[np].orient > 0) == (area > 0))) np++;
    }
    return np;
}

/* Double-precision barycentric planes of the triangle as given: b_k(x, y) =
 * p[3k] x + p[3k+1] y + p[3k+2]. Used for clipped triangles, whose snapped
 * pieces no longer carry the original edge functions. */
PW__DEF int pw__raster_bary_planes(const double *v, double *p)
{
    double d = (v[2] - v[0]) * (v[5] - v[1]) - (v[3] - v[1]) * (v[4] - v[0]);
    int k;
    if (d == 0.0 || !pw_is_finite(d)) return 0;
    for (k = 0; k < 3; k++) {
        const double *a = v + 2 * ((k + 1) % 3), *b = v + 2 * ((k + 2) % 3);
        p[3 * k] = (a[1] - b[1]) / d;
        p[3 * k + 1] = (b[0] - a[0]) / d;
        p[3 * k + 2] = (a[0] * b[1] - a[1] * b[0]) / d;
    }
    return 1;
}

/* Reports the pixels of one piece, with barycentrics either from its own
 * exact edge values (planes == NULL) or from the original triangle. */
PW__DEF void pw__raster_emit(pw_raster_edges *s, const double *planes, pw_raster_fn fn, void *user)
{
    double inv = 1.0 / (double)s->area2;
    int y, x, xa, xb, k;
    for (y = s->y0; y < s->y1; y++) {
        int64_t e[3];
        if (!pw_raster_next(s, &xa, &xb)) continue;
        for (k = 0; k < 3; k++) e[k] = s->e[k] - s->bias[k] + s->ey[k] * (y - s->y0) + s->ex[k] * (xa - s->x0);
        for (x = xa; x < xb; x++) {
            if (planes) {
                double cx = x + 0.5, cy = y + 0.5;
                fn(user, x, y, (float)(planes[0] * cx + planes[1] * cy + planes[2]),
                   (float)(planes[3] * cx + planes[4] * cy + planes[5]),
                   (float)(planes[6] * cx + planes[7] * cy + planes[8]));
            } else {
                fn(user, x, y, (float)((double)e[0] * inv), (float)((double)e[1] * inv), (float)((double)e[2] * inv));
            }
            for (k = 0; k < 3; k++) e[k] += s->ex[k];
        }
    }
}

/* Snaps a triangle given in floats into pieces; *clipped tells whether the
 * pieces are a clipped fan (their own barycentrics are then not the
 * triangle's). Returns the number of pieces. */
PW__DEF int pw__raster_pieces(const float xy[6], const pw_raster_grid *g, double *v, pw_raster_edges *pieces,
                              int *clipped)
{
    int k;
    for (k = 0; k < 6; k++) v[k] = xy[k];
    *clipped = 0;
    for (k = 0; k < 6; k++) {
        if (!pw_is_finite(v[k])) return 0;
        if (v[k] > g->range || v[k] < -g->range) *clipped = 1;
    }
    if (!*clipped) return pw_raster_setup(pieces, g, v);
    return pw_raster_polygon(g, v, 3, pieces);
}

/* Calls fn(user, x, y, b0, b1, b2) for every pixel of [0,w) x [0,h) whose
 * centre the triangle xy = (x0, y0, x1, y1, x2, y2) covers (top-left rule, either winding), row by row.
 * b0 + b1 + b2 = 1 and b0 v0 + b1 v1 + b2 v2 is the pixel centre, up to the
 * snapping of the vertices (2^-17 pixel at most on viewports up to 2048). */
PW__DEF void pw_raster_tri(const float xy[6], int w, int h, pw_raster_fn fn, void *user)
{
    pw_raster_grid g;
    pw_raster_edges pieces[PW_RASTER_MAX_PIECES];
    double v[6], planes[9];
    int n, i, clipped;
    if (!pw_raster_grid_init(&g, w, h)) return;
    n = pw__raster_pieces(xy, &g, v, pieces, &clipped);
    if (clipped && !pw__raster_bary_planes(v, planes)) return;
    for (i = 0; i < n; i++) pw__raster_emit(pieces + i, clipped ? planes : NULL, fn, user);
}

/* Same coverage as pw_raster_tri, reported as runs: fn(user, y, xa, xb) for
 * the pixels [xa, xb) of row y. A clipped triangle may report a row in
 * several adjacent runs. */
PW__DEF void pw_raster_tri_spans(const float xy[6], int w, int h, pw_raster_span_fn fn, void *user)
{
    pw_raster_grid g;
    pw_raster_edges pieces[PW_RASTER_MAX_PIECES];
    double v[6];
    int n, i, y, xa, xb, clipped;
    if (!pw_raster_grid_init(&g, w, h)) return;
    n = pw__raster_pieces(xy, &g, v, pieces, &clipped);
    for (i = 0; i < n; i++)
        for (y = pieces[i].y0; y < pieces[i].y1; y++)
            if (pw_raster_next(pieces + i, &xa, &xb)) fn(user, y, xa, xb);
}

#endif /* PW__RASTER_V1 */
