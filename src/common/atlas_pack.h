/* atlas_pack: the charts of an atlas packed into the unit square.
 *
 * The paper let the user arrange the charts ("heuristic algorithms ...
 * produce significantly worse results than a trained human"); here they
 * are packed automatically. Each chart is turned so that its minimal-area
 * enclosing rectangle (rotating calipers on its convex hull) is
 * axis-aligned, and all charts share one scale (texels per mesh unit, so
 * the texel density is uniform over the mesh). The charts, largest first,
 * are placed bottom-left-fill on a bitmap of the atlas: each as the cells
 * it covers, dilated by the gutter, stored as runs per row, at the lowest
 * position where those cells are free, in whichever of four quarter turns
 * ends lowest. Unlike a skyline, the bitmap lets small charts fill the
 * room left beside, under and inside large irregular ones. A binary search
 * finds the largest scale at which all charts fit with `gutter` pixels
 * between charts (floor(gutter/2) to the left of and below each chart, the
 * rest to the right and above, so also to the image border). Beyond 1024
 * pixels the grid's cells are several pixels wide and both parts are
 * rounded up to whole cells.
 *
 * Nothing here depends on how the charts were made: any partition of a
 * triangle mesh into flattened charts (pw_atlas_charts) packs the same way.
 * pw_atlas_layout, at the end, runs the two stages that make an atlas's
 * coordinates: charts, then packing. */
#ifndef PW__ATLAS_PACK_V1
#define PW__ATLAS_PACK_V1

#include "atlas_charts.h"

/* ---- packing --------------------------------------------------------------- */

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
    if ((r = pw_atlas_charts_build(job, &C, e)) == PW_OK) {
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

#endif /* PW__ATLAS_PACK_V1 */
