/* stuffing: the built-in tetrahedralizer of lst.h, so that no external mesher
 * is needed. pw_stuff_tetrahedralize fills the inside of a closed,
 * consistently oriented triangle surface with tetrahedra by isosurface
 * stuffing (Labelle & Shewchuk, "Isosurface stuffing: fast tetrahedral
 * meshes with good dihedral angles", SIGGRAPH 2007), on a graded lattice
 * by default or on the paper's uniform one:
 *
 *  1. Input checks: finite coordinates, indices in range, closed and
 *     consistently oriented (every edge has exactly two triangles,
 *     traversing it in opposite directions: halfedge.h); zero-area
 *     triangles are skipped (the solid does not depend on them); triangle
 *     pairs intersecting except at shared vertices and edges are counted
 *     (exact orientation predicates on the float input, candidate pairs
 *     from a bounding-volume hierarchy) and refused only when strict. Each
 *     refusal names the elements; an open surface, its holes.
 *  2. The lattice.
 *     Uniform: a body-centred cubic lattice of spacing `cell` covers the
 *     surface: black vertices at the cube corners, red ones at the cube
 *     centres. Every pair of cubes sharing a face gives four congruent
 *     tetrahedra with two long edges (length cell) and four short ones
 *     (sqrt(3)/2 cell), dihedral angles 60 and 90 degrees.
 *     Graded (default): cubes of side `cell` cut into six Kuhn tetrahedra,
 *     refined by newest-vertex bisection (bisect.h: three shapes, dihedral
 *     angles 45..120 degrees) wherever the surface within reach of a
 *     tetrahedron bends by more than `fit` times the diagonal (the width of
 *     the slab that holds the triangles clipped to its box, across their
 *     mean normal, times PW__ST_BEND) or faces two ways (a thin part, a
 *     narrow gap between parts), down to edges of PW__ST_MIN_CELL times the
 *     diagonal; then
 *     made conforming. Cells are small where the shape is thin, curved or
 *     nearly touches itself, large inside.
 *  3. Inside or outside for every lattice vertex from the generalised
 *     winding number (Jacobson, Kavan & Sorkine-Hornung 2013): lattice edges
 *     that provably do not meet the surface join the vertices into
 *     components, and one winding number decides the side of a component.
 *  4. Cut points where lattice edges cross the surface (segment-triangle
 *     intersection, so they lie on the input surface), then warping
 *     (§3 of the paper): a lattice vertex nearer to a cut point on one of its
 *     edges than alpha times the edge length (uniform: alpha_long = 0.24999
 *     on long edges, alpha_short = 0.41189 on short ones, the paper's
 *     parameters; graded: 0.3, the length capped at 1.5 times the shortest
 *     edge at the vertex, and no move that would fold a lattice
 *     tetrahedron) moves onto the nearest such cut point and is then on
 *     the surface. A vertex only moves towards an edge end that stays in
 *     place.
 *  5. Stencils: each lattice tetrahedron with an inside corner is kept or
 *     cut into one to three tetrahedra according to the signs of its
 *     corners, the quadrilateral faces being split by a rule that depends on
 *     the face alone (pw__st_diagonal), so that neighbours agree.
 *  6. Graded only: bits of the solid cut off from the rest where a part
 *     thins below the smallest cell are dropped (each surface component
 *     keeps its largest piece), and the vertices of tetrahedra with a
 *     dihedral angle outside 15..165 degrees move (surface vertices along
 *     the surface) while that improves their worst angle.
 *
 * Guarantees: the tetrahedra are positively oriented (tetmesh.h) and form a
 * conforming mesh (neighbours share whole faces) whose boundary is closed;
 * all vertices of the boundary lie on the input surface (to float
 * precision). Uniform lattice: every dihedral angle lies between 10.2 and
 * 161.7 degrees. The paper proves 10.7-164.8 degrees for its own stencils,
 * whose quadrilateral rule this implementation does not reproduce; the
 * bounds here are those of the stencils and warping above, found as the
 * worst case of an adversarial search over all stencil configurations
 * (corner signs, warps along any of the 14 lattice directions up to alpha,
 * cut points anywhere alpha allows; tests/test_stuffing.c repeats it):
 * 10.205 degrees is reached by a +-00 tetrahedron whose long edge is cut a
 * quarter from its inside end while both zero corners moved alpha_short
 * towards the outside corner. Its boundary follows the surface to within
 * about one cell: features thinner than a cell are lost, sharp edges are
 * rounded, and two parts of the solid may touch along lattice edges.
 * Graded lattice: no proven bound; tests/test_stuffing.c holds it to 8..168
 * degrees over random shapes, placements and fits and over the CGAL
 * corpus (measured 15.0..162.0 there), and its boundary to within 0.5% of
 * the diagonal of the CGAL surfaces (measured 0.24-0.38%), their pieces
 * kept; the tips of spikes thinner than the smallest cell are lost. Several
 * components, nested shells and crossing triangles are fine: the inside is
 * where the winding number is at least 1/2. A surface whose triangles all
 * face inward (negative enclosed volume) is used as if reversed.
 *
 *   pw_stuff_default_options, pw_stuff_tetrahedralize, pw_stuff_boundary,
 *   pw_stuff_fit_measure */
#ifndef PW__STUFFING_V1
#define PW__STUFFING_V1

#include <stdlib.h> /* qsort */
#include "base.h"
#include "halfedge.h"
#include "tetmesh.h"
#include "bisect.h"

/* What a fill found in its input, for the caller to report. */
typedef struct pw_stuff_info {
    long crossing_pairs;   /* pairs of triangles that cross (filled where the winding number is >= 1/2) */
    int first_pair[2];     /* the first crossing pair found, -1 -1 if none */
    int skipped_triangles; /* zero-area triangles (collinear or repeated corners) the solid does not depend on */
    int closed_holes;      /* holes of an open surface closed by fans of triangles (all small, see max_hole) */
    int fragments;         /* graded: bits of parts thinner than the smallest cell, cut off and dropped */
} pw_stuff_info;

/* A triangle surface as the caller holds it (borrowed): nv vertices (pos,
 * nv*3 floats) and nt triangles (tri, nt*3 vertex indices). */
typedef struct pw_stuff_tris {
    const float *pos;
    int nv;
    const int *tri;
    int nt;
} pw_stuff_tris;

PW__DEF pw_stuff_tris pw_stuff_tris_of(const float *pos, int nv, const int *tri, int nt)
{
    pw_stuff_tris m;
    m.pos = pos;
    m.nv = nv;
    m.tri = tri;
    m.nt = nt;
    return m;
}

typedef struct pw_stuff_options {
    double cell;         /* lattice spacing (cube side = long-edge length) in mesh units; 0: chosen from target_tets */
    int target_tets;     /* approximate tetrahedron count when cell is 0; 0: 20000 */
    int strict;          /* 1: a closed surface whose triangles cross is refused with the first crossing pair;
                        0 (default): filled where its generalised winding number is at least 1/2
                        (overlapping parts unite, inner sheets vanish) and counted in info */
    double max_hole;     /* an open surface whose holes all have perimeters at most this fraction of the
                        bounding-box diagonal is closed (fans from a vertex of each hole, filled by
                        winding number) and counted in info; larger holes are refused. 0: 0.05;
                        negative: every open surface is refused */
    int uniform;         /* 1: the uniform body-centred cubic lattice of cell (proven dihedral bounds,
                        parts thinner than a cell lost); 0 (default): graded near the surface */
    double fit;          /* graded: the surface deviation allowed inside one lattice tetrahedron, as a
                        fraction of the bounding-box diagonal; 0: 0.0025 */
    pw_stuff_info *info; /* optional: filled with what the fill found (also on failure) */
} pw_stuff_options;

PW__DEF pw_stuff_options pw_stuff_default_options(void)
{
    pw_stuff_options o;
    o.cell = 0.0;
    o.target_tets = 20000;
    o.strict = 0;
    o.max_hole = 0.05;
    o.uniform = 0;
    o.fit = 0.0025;
    o.info = NULL;
    return o;
}

/* Largest lattice one call may use: uniform, black + red vertices (about
 * 13 bytes each); graded, tetrahedra (about 60 bytes each with their
 * vertices and edges). */
#ifndef PW_MAX_STUFF_LATTICE
#define PW_MAX_STUFF_LATTICE (1 << 24)
#endif

/* §3: the paper's warping thresholds (those of its 10.7-164.8 degree bounds). */
#define PW__ST_ALPHA_LONG 0.24999
#define PW__ST_ALPHA_SHORT 0.41189
/* The graded lattice (see "the graded lattice" below): one alpha for every
 * edge, times the shortest edge at the vertex, at most REACH times it; the
 * sizing constants. */
#define PW__ST_ALPHA_GRADED 0.3
#define PW__ST_REACH 1.5
#define PW__ST_BEND 0.4          /* fit bound per width of the slab holding the surface near a tetrahedron */
#define PW__ST_MIN_CELL 0.000625 /* no bisection of tetrahedra shorter than this (or fit / 4), over the diagonal */
#define PW__ST_TIP_CELL 0.5      /* near a sharp tip, down to this fraction of it */
#define PW__ST_TIP_ANGLE 1.5707963267948966 /* a sharp tip: the angles of its triangles there sum to less */
/* Quadrilateral faces with a long cut edge take the diagonal from that
 * edge's cut point when it lies within this fraction of the edge from its
 * inside end (see pw__st_diagonal). */
#define PW__ST_LONG_SPLIT 0.6

/* ---- exact orientation predicates on float input ----
 * The fast double evaluation is trusted beyond Shewchuk's error bound;
 * otherwise the determinant is summed exactly as an expansion of doubles:
 * coordinates are floats (24-bit significands), so the product of two is
 * exact in a double and the product of three is exact as a two-double sum.
 * Needs IEEE double arithmetic without extended precision or -ffast-math. */

PW__DEF void pw__st_two_sum(double a, double b, double *s, double *err)
{
    double x = a + b, bv = x - a, av = x - bv;
    *s = x;
    *err = (a - av) + (b - bv);
}

PW__DEF void pw__st_split(double a, double *hi, double *lo)
{
    double c = 134217729.0 * a, big = c - a; /* 2^27 + 1 */
    *hi = c - big;
    *lo = a - *hi;
}

PW__DEF void pw__st_two_prod(double a, double b, double *p, double *err)
{
    double x = a * b, ah, al, bh, bl;
    pw__st_split(a, &ah, &al);
    pw__st_split(b, &bh, &bl);
    *p = x;
    *err = al * bl - (((x - ah * bh) - al * bh) - ah * bl);
}

/* Adds b to the expansion e[0..n) (nonoverlapping, increasing magnitude),
 * dropping zeros; returns the new length (Shewchuk's grow-expansion). */
PW__DEF int pw__st_grow(double *e, int n, double b)
{
    double q = b, h;
    int i, m = 0;
    for (i = 0; i < n; i++) {
        pw__st_two_sum(q, e[i], &q, &h);
        if (h != 0.0) e[m++] = h;
    }
    if (q != 0.0) e[m++] = q;
    return m;
}

PW__DEF int pw__st_add_prod3(double *e, int n, double x, double y, double z, int sign)
{
    double hi, lo;
    pw__st_two_prod(x * y, z, &hi, &lo);
    n = pw__st_grow(e, n, sign > 0 ? lo : -lo);
    return pw__st_grow(e, n, sign > 0 ? hi : -hi);
}

/* s * det[p; q; r] added to the expansion. */
PW__DEF int pw__st_add_det3(double *e, int n, const double *p, const double *q, const double *r, int s)
{
    n = pw__st_add_prod3(e, n, p[0], q[1], r[2], s);
    n = pw__st_add_prod3(e, n, p[0], q[2], r[1], -s);
    n = pw__st_add_prod3(e, n, p[1], q[0], r[2], -s);
    n = pw__st_add_prod3(e, n, p[1], q[2], r[0], s);
    n = pw__st_add_prod3(e, n, p[2], q[0], r[1], s);
    return pw__st_add_prod3(e, n, p[2], q[1], r[0], -s);
}

/* det[b-a; c-a; d-a] as the 4x4 determinant of the raw coordinates. */
PW__DEF int pw__st_orient3d_exact(const double *a, const double *b, const double *c, const double *d)
{
    double e[48];
    int n = 0;
    n = pw__st_add_det3(e, n, b, c, d, 1);
    n = pw__st_add_det3(e, n, a, c, d, -1);
    n = pw__st_add_det3(e, n, a, b, d, 1);
    n = pw__st_add_det3(e, n, a, b, c, -1);
    return n == 0 ? 0 : e[n - 1] > 0.0 ? 1 : -1;
}

/* Sign of (b-a) x (c-a) . (d-a): positive when d is on the side that the
 * normal of (a, b, c) points to (a positive tetrahedron a, b, c, d). */
PW__DEF int pw__st_orient3d(const double *a, const double *b, const double *c, const double *d)
{
    double bx = b[0] - a[0], by = b[1] - a[1], bz = b[2] - a[2];
    double cx = c[0] - a[0], cy = c[1] - a[1], cz = c[2] - a[2];
    double dx = d[0] - a[0], dy = d[1] - a[1], dz = d[2] - a[2];
    double det = bx * (cy * dz - cz * dy) + by * (cz * dx - cx * dz) + bz * (cx * dy - cy * dx);
    double perm = fabs(bx) * (fabs(cy * dz) + fabs(cz * dy)) + fabs(by) * (fabs(cz * dx) + fabs(cx * dz)) +
                  fabs(bz) * (fabs(cx * dy) + fabs(cy * dx));
    double bound = 7.7715611723761027e-16 * perm; /* (7 + 56 eps) eps */
    if (det > bound) return 1;
    if (-det > bound) return -1;
    return pw__st_orient3d_exact(a, b, c, d);
}

/* Sign of (b-a) x (c-a) in the plane of coordinates i and j. */
PW__DEF int pw__st_orient2d(const double *a, const double *b, const double *c, int i, int j)
{
    double l = (b[i] - a[i]) * (c[j] - a[j]), r = (b[j] - a[j]) * (c[i] - a[i]), det = l - r;
    double bound = 3.3306690738754716e-16 * (fabs(l) + fabs(r)), e[6];
    int n = 0;
    if (det > bound) return 1;
    if (-det > bound) return -1;
    n = pw__st_grow(e, n, b[i] * c[j]);
    n = pw__st_grow(e, n, -b[j] * c[i]);
    n = pw__st_grow(e, n, -a[i] * c[j]);
    n = pw__st_grow(e, n, a[j] * c[i]);
    n = pw__st_grow(e, n, a[i] * b[j]);
    n = pw__st_grow(e, n, -a[j] * b[i]);
    return n == 0 ? 0 : e[n - 1] > 0.0 ? 1 : -1;
}

/* An axis along which triangle abc does not project to a segment, -1 if
 * it has zero area. */
PW__DEF int pw__st_proj_axis(const double *a, const double *b, const double *c)
{
    double n[3], u[3], v[3];
    int k, best = 0, tries;
    for (k = 0; k < 3; k++) {
        u[k] = b[k] - a[k];
        v[k] = c[k] - a[k];
    }
    pw_cross3(u, v, n);
    for (k = 0; k < 3; k++) n[k] = fabs(n[k]);
    if (n[1] > n[best]) best = 1;
    if (n[2] > n[best]) best = 2;
    for (tries = 0; tries < 3; tries++, best = (best + 1) % 3)
        if (pw__st_orient2d(a, b, c, (best + 1) % 3, (best + 2) % 3) != 0) return best;
    return -1;
}

/* x on the closed segment pq, given that the three are collinear. */
PW__DEF int pw__st_on_seg(const double *p, const double *q, const double *x, int i, int j)
{
    return x[i] >= (p[i] < q[i] ? p[i] : q[i]) && x[i] <= (p[i] > q[i] ? p[i] : q[i]) &&
           x[j] >= (p[j] < q[j] ? p[j] : q[j]) && x[j] <= (p[j] > q[j] ? p[j] : q[j]);
}

/* Closed segments pq and ab meet (all four in one plane, axes i, j). */
PW__DEF int pw__st_seg_seg_2d(const double *p, const double *q, const double *a, const double *b, int i, int j)
{
    int d1 = pw__st_orient2d(p, q, a, i, j), d2 = pw__st_orient2d(p, q, b, i, j);
    int d3 = pw__st_orient2d(a, b, p, i, j), d4 = pw__st_orient2d(a, b, q, i, j);
    if (d1 * d2 < 0 && d3 * d4 < 0) return 1;
    return (d1 == 0 && pw__st_on_seg(p, q, a, i, j)) || (d2 == 0 && pw__st_on_seg(p, q, b, i, j)) ||
           (d3 == 0 && pw__st_on_seg(a, b, p, i, j)) || (d4 == 0 && pw__st_on_seg(a, b, q, i, j));
}

/* Point x in the closed triangle abc (coplanar, axes i, j). */
PW__DEF int pw__st_in_tri_2d(const double *x, const double *a, const double *b, const double *c, int i, int j)
{
    int o = pw__st_orient2d(a, b, c, i, j);
    return o * pw__st_orient2d(a, b, x, i, j) >= 0 && o * pw__st_orient2d(b, c, x, i, j) >= 0 &&
           o * pw__st_orient2d(c, a, x, i, j) >= 0;
}

/* Closed segment pq meets closed triangle abc (non-degenerate), exactly. */
PW__DEF int pw__st_seg_tri(const double *p, const double *q, const double *a, const double *b, const double *c)
{
    int o1 = pw__st_orient3d(a, b, c, p), o2 = pw__st_orient3d(a, b, c, q), s1, s2, s3, ax, i, j;
    if (o1 == 0 && o2 == 0) { /* coplanar: work in the projection */
        ax = pw__st_proj_axis(a, b, c);
        i = (ax + 1) % 3;
        j = (ax + 2) % 3;
        return pw__st_in_tri_2d(p, a, b, c, i, j) || pw__st_in_tri_2d(q, a, b, c, i, j) ||
               pw__st_seg_seg_2d(p, q, a, b, i, j) || pw__st_seg_seg_2d(p, q, b, c, i, j) ||
               pw__st_seg_seg_2d(p, q, c, a, i, j);
    }
    if (o1 == o2) return 0;
    s1 = pw__st_orient3d(p, q, a, b);
    s2 = pw__st_orient3d(p, q, b, c);
    s3 = pw__st_orient3d(p, q, c, a);
    return !((s1 > 0 || s2 > 0 || s3 > 0) && (s1 < 0 || s2 < 0 || s3 < 0));
}

/* All three of d, e, f strictly on one side of the plane of abc. */
PW__DEF int pw__st_one_side(const double *a, const double *b, const double *c, const double *d, const double *e,
                            const double *f)
{
    int s = pw__st_orient3d(a, b, c, d);
    return s != 0 && pw__st_orient3d(a, b, c, e) == s && pw__st_orient3d(a, b, c, f) == s;
}

/* ---- the surface and its bounding-volume hierarchy ---- */

typedef struct pw__stsurf {
    int nv, nt;
    double *p;  /* nv*3, the float input as doubles */
    double *tc; /* nt*9: each triangle's corners, in order (one read instead of three) */
    const int *tri;
    int nnode;
    float *box;               /* nnode*6: lo xyz, hi xyz (exact bounds of the float input) */
    int *node;                /* nnode*3: first slot, slot count, left child (-1: leaf; right = left + 1) */
    int *slot;                /* nt: a node's triangles are slot[first .. first+count) */
    double lo[3], hi[3], mag; /* bounding box; mag: its size plus its distance from 0 */
    double volume, area;      /* enclosed volume (positive), surface area */
    int *capfirst;            /* nnode+1: node nd's boundary half-edges are cap[2*capfirst[nd] ..]; NULL: none */
    int *cap;                 /* boundary half-edges of the nodes' triangle sets, 2 vertices each */
    int flip;                 /* 1: the triangles face inward, winding numbers are negated */
} pw__stsurf;

PW__DEF void pw__st_surf_free(const pw_alloc *a, pw__stsurf *s)
{
    pw_free(a, s->p);
    pw_free(a, s->tc);
    pw_free(a, s->box);
    pw_free(a, s->node);
    pw_free(a, s->slot);
    pw_free(a, s->capfirst);
    pw_free(a, s->cap);
    memset(s, 0, sizeof *s);
}

PW__DEF const double *pw__st_corner(const pw__stsurf *s, int t, int k) { return s->tc + 9 * (size_t)t + 3 * k; }

/* Slot order for the median split: by centroid coordinate, ties by index. */
PW__DEF int pw__st_before(const double *cen, int axis, int t, int u)
{
    double x = cen[3 * t + axis], y = cen[3 * u + axis];
    return x < y || (x == y && t < u);
}

PW__DEF void pw__st_swap(int *v, int i, int j)
{
    int t = v[i];
    v[i] = v[j];
    v[j] = t;
}

/* Partially orders v[0..n) so that v[k] is in its sorted place
 * (quickselect, median-of-three pivot). */
PW__DEF void pw__st_select(int *v, int n, int k, const double *cen, int axis)
{
    int lo = 0, hi = n - 1;
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2, i = lo, j = hi, pivot;
        if (pw__st_before(cen, axis, v[mid], v[lo])) pw__st_swap(v, mid, lo);
        if (pw__st_before(cen, axis, v[hi], v[lo])) pw__st_swap(v, hi, lo);
        if (pw__st_before(cen, axis, v[hi], v[mid])) pw__st_swap(v, hi, mid);
        pivot = v[mid];
        while (i <= j) {
            while (pw__st_before(cen, axis, v[i], pivot)) i++;
            while (pw__st_before(cen, axis, pivot, v[j])) j--;
            if (i <= j) pw__st_swap(v, i++, j--);
        }
        if (k <= j) hi = j;
        else if (k >= i) lo = i;
        else return;
    }
}

/* Node nd over slots [first, first+count): its box, then a median split
 * along the longest axis of the centroids (depth <= log2(nt) + 1). */
PW__DEF void pw__st_bvh_node(pw__stsurf *s, const double *cen, int nd, int first, int count)
{
    float *b = s->box + 6 * nd;
    double clo[3], chi[3];
    int i, k, axis = 0, left;
    for (k = 0; k < 3; k++) {
        b[k] = FLT_MAX;
        b[k + 3] = -FLT_MAX;
        clo[k] = DBL_MAX;
        chi[k] = -DBL_MAX;
    }
    for (i = first; i < first + count; i++) {
        int t = s->slot[i], c;
        for (c = 0; c < 3; c++)
            for (k = 0; k < 3; k++) {
                float x = (float)pw__st_corner(s, t, c)[k];
                if (x < b[k]) b[k] = x;
                if (x > b[k + 3]) b[k + 3] = x;
            }
        for (k = 0; k < 3; k++) {
            if (cen[3 * t + k] < clo[k]) clo[k] = cen[3 * t + k];
            if (cen[3 * t + k] > chi[k]) chi[k] = cen[3 * t + k];
        }
    }
    s->node[3 * nd] = first;
    s->node[3 * nd + 1] = count;
    s->node[3 * nd + 2] = -1;
    if (count <= 4) return;
    for (k = 1; k < 3; k++)
        if (chi[k] - clo[k] > chi[axis] - clo[axis]) axis = k;
    pw__st_select(s->slot + first, count, count / 2, cen, axis);
    left = s->nnode;
    s->nnode += 2;
    s->node[3 * nd + 2] = left;
    pw__st_bvh_node(s, cen, left, first, count / 2);
    pw__st_bvh_node(s, cen, left + 1, first + count / 2, count - count / 2);
}

/* Copies the positions, builds the hierarchy and the bounding box. The
 * triangle array is borrowed. Indices must be in range. */
PW__DEF int pw__st_surf_init(const pw_alloc *a, const pw_stuff_tris *m, pw__stsurf *s, pw_err *e)
{
    const float *pos = m->pos;
    const int *tri = m->tri;
    int nv = m->nv, nt = m->nt;
    double *cen;
    int i, k;
    memset(s, 0, sizeof *s);
    s->nv = nv;
    s->nt = nt;
    s->tri = tri;
    s->p = (double *)pw_alloc_array(a, (size_t)nv * 3, sizeof(double), "surface positions", e);
    s->tc = (double *)pw_alloc_array(a, (size_t)nt * 9, sizeof(double), "surface positions", e);
    s->box = (float *)pw_alloc_array(a, (size_t)(2 * nt) * 6, sizeof(float), "surface hierarchy", e);
    s->node = (int *)pw_alloc_array(a, (size_t)(2 * nt) * 3, sizeof(int), "surface hierarchy", e);
    s->slot = (int *)pw_alloc_array(a, (size_t)nt, sizeof(int), "surface hierarchy", e);
    cen = (double *)pw_alloc_array(a, (size_t)nt * 3, sizeof(double), "triangle centroids", e);
    if (!s->p || !s->tc || !s->box || !s->node || !s->slot || !cen) {
        pw_free(a, cen);
        pw__st_surf_free(a, s);
        return PW_ERR_NOMEM;
    }
    for (i = 0; i < 3 * nv; i++) s->p[i] = pos[i];
    for (i = 0; i < 3 * nt; i++) memcpy(s->tc + 3 * (size_t)i, s->p + 3 * (size_t)tri[i], 3 * sizeof(double));
    for (i = 0; i < nt; i++) {
        s->slot[i] = i;
        for (k = 0; k < 3; k++)
            cen[3 * i + k] = (pw__st_corner(s, i, 0)[k] + pw__st_corner(s, i, 1)[k] + pw__st_corner(s, i, 2)[k]) / 3.0;
    }
    s->nnode = 1;
    pw__st_bvh_node(s, cen, 0, 0, nt);
    pw_free(a, cen);
    for (k = 0; k < 3; k++) {
        s->lo[k] = s->box[k];
        s->hi[k] = s->box[k + 3];
    }
    s->mag = 0.0;
    for (k = 0; k < 3; k++) s->mag += (s->hi[k] - s->lo[k]) + fabs(s->lo[k]) + fabs(s->hi[k]);
    return PW_OK;
}

/* ---- input checks ---- */

PW__DEF int pw__st_shared(const int *x, const int *y, int *sx, int *sy)
{
    int i, j, n = 0;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            if (x[i] == y[j]) {
                sx[n] = i;
                sy[n] = j;
                n++;
            }
    return n;
}

/* Triangles sharing edge (p, q), with third corners c and d, overlap
 * beyond it: coplanar, with c and d on the same side of the edge. */
PW__DEF int pw__st_folded(const double *p, const double *q, const double *c, const double *d)
{
    int ax, i, j;
    if (pw__st_orient3d(p, q, c, d) != 0) return 0;
    ax = pw__st_proj_axis(p, q, c);
    i = (ax + 1) % 3;
    j = (ax + 2) % 3;
    return pw__st_orient2d(p, q, c, i, j) * pw__st_orient2d(p, q, d, i, j) > 0;
}

/* The line pq (in the projection on axes i, j) has x strictly on one side
 * and all n points of y strictly on the other. */
PW__DEF int pw__st_splits(const double *p, const double *q, const double *x, const double *const *y, int n, int i,
                          int j)
{
    int s = pw__st_orient2d(p, q, x, i, j), k;
    for (k = 0; k < n && s != 0; k++)
        if (pw__st_orient2d(p, q, y[k], i, j) != -s) return 0;
    return s != 0;
}

/* A cheap exact proof that triangles A and B (sharing n corners, sx/sy
 * their positions) meet only in what they share: a line in the projection
 * along A's dominant normal axis that has them strictly on either side
 * (through the shared corners, if any); the plane through that line along
 * the axis then separates them in space. Coplanar neighbours in flat
 * regions would otherwise all need exact arithmetic. */
PW__DEF int pw__st_apart_2d(const double *const *A, const double *const *B, int n, const int *sx, const int *sy)
{
    int ax = pw__st_proj_axis(A[0], A[1], A[2]), i = (ax + 1) % 3, j = (ax + 2) % 3, k;
    const double *y[3];
    if (n == 2) return pw__st_splits(A[sx[0]], A[sx[1]], A[3 - sx[0] - sx[1]], B + (3 - sy[0] - sy[1]), 1, i, j);
    if (n == 1) {
        const double *a = A[sx[0]], *a1 = A[(sx[0] + 1) % 3], *a2 = A[(sx[0] + 2) % 3];
        const double *b1 = B[(sy[0] + 1) % 3], *b2 = B[(sy[0] + 2) % 3];
        y[0] = b1;
        y[1] = b2;
        if (pw__st_splits(a, a1, a2, y, 2, i, j) || pw__st_splits(a, a2, a1, y, 2, i, j)) return 1;
        y[0] = a1;
        y[1] = a2;
        return pw__st_splits(a, b1, b2, y, 2, i, j) || pw__st_splits(a, b2, b1, y, 2, i, j);
    }
    for (k = 0; k < 3; k++)
        if (pw__st_splits(A[k], A[(k + 1) % 3], A[(k + 2) % 3], B, 3, i, j) ||
            pw__st_splits(B[k], B[(k + 1) % 3], B[(k + 2) % 3], A, 3, i, j))
            return 1;
    return 0;
}

/* Triangles t and u meet somewhere else than in their shared vertices and
 * edge. With one shared vertex v, the two meet beyond v exactly when the
 * edge opposite v in one of them meets the other triangle: along the line
 * through v and any common point, whichever triangle ends first ends on
 * its opposite edge, inside the other. */
PW__DEF int pw__st_tri_tri(const pw__stsurf *s, int t, int u)
{
    const int *x = s->tri + 3 * t, *y = s->tri + 3 * u;
    const double *A[3], *B[3];
    int sx[3], sy[3], n = pw__st_shared(x, y, sx, sy), k;
    for (k = 0; k < 3; k++) {
        A[k] = pw__st_corner(s, t, k);
        B[k] = pw__st_corner(s, u, k);
    }
    if (n == 3) return 1; /* the same triangle twice */
    if (pw__st_apart_2d(A, B, n, sx, sy)) return 0;
    if (n == 2) return pw__st_folded(A[sx[0]], A[sx[1]], A[3 - sx[0] - sx[1]], B[3 - sy[0] - sy[1]]);
    if (n == 1)
        return pw__st_seg_tri(A[(sx[0] + 1) % 3], A[(sx[0] + 2) % 3], B[0], B[1], B[2]) ||
               pw__st_seg_tri(B[(sy[0] + 1) % 3], B[(sy[0] + 2) % 3], A[0], A[1], A[2]);
    if (pw__st_one_side(A[0], A[1], A[2], B[0], B[1], B[2]) || pw__st_one_side(B[0], B[1], B[2], A[0], A[1], A[2]))
        return 0;
    for (k = 0; k < 3; k++)
        if (pw__st_seg_tri(A[k], A[(k + 1) % 3], B[0], B[1], B[2]) ||
            pw__st_seg_tri(B[k], B[(k + 1) % 3], A[0], A[1], A[2]))
            return 1;
    return 0;
}

PW__DEF int pw__st_boxes_meet(const float *a, const float *b)
{
    return a[0] <= b[3] && b[0] <= a[3] && a[1] <= b[4] && b[1] <= a[4] && a[2] <= b[5] && b[2] <= a[5];
}

/* Counts the crossing triangle pairs among the leaves under nodes x and y
 * in hit; the first found goes to hit->first_pair. */
PW__DEF void pw__st_pairs(const pw__stsurf *s, int x, int y, pw_stuff_info *hit)
{
    const int *nx = s->node + 3 * x, *ny = s->node + 3 * y;
    int i, j;
    if (!pw__st_boxes_meet(s->box + 6 * x, s->box + 6 * y)) return;
    if (nx[2] >= 0 && (x == y || ny[2] < 0 || nx[1] >= ny[1])) {
        if (x == y) pw__st_pairs(s, nx[2], nx[2] + 1, hit);
        pw__st_pairs(s, nx[2], y == x ? nx[2] : y, hit);
        pw__st_pairs(s, nx[2] + 1, y == x ? nx[2] + 1 : y, hit);
        return;
    }
    if (ny[2] >= 0) {
        pw__st_pairs(s, x, ny[2], hit);
        pw__st_pairs(s, x, ny[2] + 1, hit);
        return;
    }
    for (i = nx[0]; i < nx[0] + nx[1]; i++)
        for (j = (x == y ? i + 1 : ny[0]); j < ny[0] + ny[1]; j++) {
            int t = s->slot[i], u = s->slot[j];
            if (!pw__st_tri_tri(s, t, u)) continue;
            if (hit->crossing_pairs++ == 0) {
                hit->first_pair[0] = t < u ? t : u;
                hit->first_pair[1] = t < u ? u : t;
            }
        }
}

PW__DEF int pw__st_check_values(const float *pos, int nv, const int *tri, int nt, pw_err *e)
{
    int i;
    if (!pos || !tri) return pw_fail(e, PW_ERR_INVALID, "tetrahedralize: NULL positions or triangles");
    if (nt < 1 || nv < 3) return pw_fail(e, PW_ERR_DEGENERATE, "tetrahedralize: the surface has no triangles");
    if (nv > PW_MAX_MESH_ELEMENTS || nt > PW_MAX_MESH_ELEMENTS)
        return pw_fail(e, PW_ERR_LIMIT, "tetrahedralize: %d vertices and %d triangles exceed PW_MAX_MESH_ELEMENTS (%d)",
                       nv, nt, PW_MAX_MESH_ELEMENTS);
    for (i = 0; i < 3 * nv; i++)
        if (!pw_is_finite(pos[i])) return pw_fail(e, PW_ERR_INVALID, "vertex %d has a non-finite coordinate", i / 3);
    for (i = 0; i < 3 * nt; i++)
        if (tri[i] < 0 || tri[i] >= nv)
            return pw_fail(e, PW_ERR_INVALID, "triangle %d: vertex index %d out of range (%d vertices)", i / 3, tri[i],
                           nv);
    return PW_OK;
}

/* Bounding-box diagonal of the vertices used by triangles tri[0..nt). */
PW__DEF double pw__st_diag(const float *pos, const int *tri, int nt)
{
    double lo[3] = {DBL_MAX, DBL_MAX, DBL_MAX}, hi[3] = {-DBL_MAX, -DBL_MAX, -DBL_MAX}, d = 0.0;
    int i, k;
    for (i = 0; i < 3 * nt; i++)
        for (k = 0; k < 3; k++) {
            double x = pos[3 * tri[i] + k];
            lo[k] = x < lo[k] ? x : lo[k];
            hi[k] = x > hi[k] ? x : hi[k];
        }
    for (k = 0; nt > 0 && k < 3; k++) d += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    return sqrt(d);
}

/* What the closedness check found: the half-edge twins of a closed
 * surface, or the triangles closing the holes of an open one. */
typedef struct pw__st_closure {
    int *twin; /* closed: hm.nh twins (half-edge 3t+k runs from corner k to k+1 of t), allocated; else NULL */
    int *fan;  /* small holes: 3 * nfan indices closing them as fans, allocated; else NULL */
    int nfan;
    int nholes; /* boundary loops of an open surface */
} pw__st_closure;

/* One boundary loop: its edge count, perimeter and the centre of its vertices. */
typedef struct pw__st_hole {
    int len;
    double perim, c[3];
} pw__st_hole;

/* Walks the boundary loop from boundary half-edge h into *hl and marks its
 * half-edges seen. With cl, its closing triangles (origin of h, then each
 * later edge reversed) are appended at cl->fan + 3 * cl->nfan. */
PW__DEF void pw__st_loop(const pw_hmesh *hm, const float *pos, int h, unsigned char *seen, pw__st_hole *hl,
                         pw__st_closure *cl)
{
    int g, k, a0 = pw_he_origin(hm, h);
    double d2, *c = hl->c;
    hl->len = 0;
    hl->perim = c[0] = c[1] = c[2] = 0.0;
    for (g = h; g >= 0 && !seen[g]; g = pw_he_boundary_next(hm, g), hl->len++) {
        int o = pw_he_origin(hm, g), t = pw_he_dest(hm, g);
        seen[g] = 1;
        for (d2 = 0.0, k = 0; k < 3; k++) {
            c[k] += pos[3 * o + k];
            d2 += (double)(pos[3 * t + k] - pos[3 * o + k]) * (pos[3 * t + k] - pos[3 * o + k]);
        }
        hl->perim += sqrt(d2);
        if (cl && g != h && t != a0) {
            int *f = cl->fan + 3 * cl->nfan++;
            f[0] = a0;
            f[1] = t;
            f[2] = o;
        }
    }
    for (k = 0; k < 3; k++) c[k] /= hl->len > 0 ? hl->len : 1;
}

/* The holes of an open surface: when every hole's perimeter is at most
 * max_hole, the triangles that close them as fans (cl->fan, 3 * cl->nfan
 * ints, allocated here); else the refusal: how many holes, the largest
 * one's edge count, perimeter, centre and a vertex on it, and what is
 * needed. */
PW__DEF int pw__st_holes(const pw_alloc *a, const pw_hmesh *hm, const float *pos, double max_hole, pw__st_closure *cl,
                         pw_err *e)
{
    unsigned char *seen = (unsigned char *)pw_calloc_array(a, (size_t)hm->nh + 1, 1, "boundary loops", e);
    double best[3] = {0, 0, 0}, most = -1.0;
    pw__st_hole hl;
    int h, k, blen = 0, vert = -1, r = PW_OK;
    cl->fan = NULL;
    cl->nfan = 0;
    if (!seen) return PW_ERR_NOMEM;
    for (h = 0; h < hm->nh; h++) {
        if (hm->twin[h] >= 0 || seen[h]) continue;
        pw__st_loop(hm, pos, h, seen, &hl, NULL);
        if (hl.perim > most)
            for (most = hl.perim, blen = hl.len, vert = pw_he_origin(hm, h), k = 0; k < 3; k++) best[k] = hl.c[k];
    }
    if (most > max_hole)
        r = pw_fail(e, PW_ERR_TOPOLOGY,
                    "surface is not closed: %d boundary edges in %d hole%s (the largest: %d edges, perimeter %.4g, "
                    "around (%.4g, %.4g, %.4g), through vertex %d); a solid needs a closed surface: close the holes "
                    "(those of perimeter up to %.4g are closed here)",
                    hm->nboundary, hm->nloops, hm->nloops == 1 ? "" : "s", blen, most, best[0], best[1], best[2], vert,
                    max_hole);
    else if (!(cl->fan = (int *)pw_alloc_array(a, 3 * (size_t)hm->nboundary + 3, sizeof(int), "hole fans", e)))
        r = PW_ERR_NOMEM;
    else
        for (memset(seen, 0, (size_t)hm->nh), h = 0; h < hm->nh; h++)
            if (hm->twin[h] < 0 && !seen[h]) pw__st_loop(hm, pos, h, seen, &hl, cl);
    pw_free(a, seen);
    return r;
}

/* Closed and consistently oriented: every half-edge has a twin. The twins
 * go to cl->twin, for the winding-number caps. An open surface whose holes
 * are small (perimeter at most max_hole) gives the triangles that close
 * them in cl->fan instead, and their count in cl->nholes. */
PW__DEF int pw__st_check_closed(const pw_alloc *a, const pw_stuff_tris *m, double max_hole, pw__st_closure *cl,
                                pw_err *e)
{
    pw_hmesh hm;
    int *fs = (int *)pw_alloc_array(a, (size_t)m->nt + 1, sizeof(int), "triangle offsets", e), i, r;
    memset(cl, 0, sizeof *cl);
    if (!fs) return PW_ERR_NOMEM;
    for (i = 0; i <= m->nt; i++) fs[i] = 3 * i;
    r = pw_hmesh_build(a, m->nv, m->nt, fs, m->tri, &hm, e);
    pw_free(a, fs);
    if (r != PW_OK) return r;
    if (hm.nboundary > 0) cl->nholes = hm.nloops;
    if (hm.nboundary > 0) r = pw__st_holes(a, &hm, m->pos, max_hole, cl, e);
    else if (!(cl->twin = (int *)pw_alloc_array(a, (size_t)hm.nh, sizeof(int), "half-edge twins", e))) r = PW_ERR_NOMEM;
    else memcpy(cl->twin, hm.twin, sizeof(int) * (size_t)hm.nh);
    pw_hmesh_free(a, &hm);
    return r;
}

/* Enclosed volume (signed: negative when the triangles face inward) and
 * area, with coordinates taken from the box centre for precision. */
PW__DEF void pw__st_measure(pw__stsurf *s, double *vol)
{
    double c[3];
    int t, k;
    for (k = 0; k < 3; k++) c[k] = 0.5 * (s->lo[k] + s->hi[k]);
    *vol = s->area = 0.0;
    for (t = 0; t < s->nt; t++) {
        double u[3], v[3], w[3], n[3];
        for (k = 0; k < 3; k++) {
            u[k] = pw__st_corner(s, t, 0)[k] - c[k];
            v[k] = pw__st_corner(s, t, 1)[k] - c[k];
            w[k] = pw__st_corner(s, t, 2)[k] - c[k];
        }
        pw_cross3(v, w, n);
        *vol += pw_dot3(u, n) / 6.0;
        for (k = 0; k < 3; k++) {
            v[k] -= u[k];
            w[k] -= u[k];
        }
        pw_cross3(v, w, n);
        s->area += 0.5 * sqrt(pw_dot3(n, n));
    }
}

/* Self-intersections (counted in info; refused when `strict`, naming the
 * first pair by the caller's triangle indices, map), then the enclosed
 * volume (its sign tells the orientation). */
PW__DEF int pw__st_check_geometry(pw__stsurf *s, const int *map, int strict, pw_stuff_info *info, pw_err *e)
{
    double vol, size = 0.0;
    int k;
    pw__st_pairs(s, 0, 0, info);
    if (info->crossing_pairs > 0) {
        info->first_pair[0] = map[info->first_pair[0]];
        info->first_pair[1] = map[info->first_pair[1]];
        if (strict)
            return pw_fail(e, PW_ERR_TOPOLOGY,
                           "surface intersects itself: %ld triangle pairs cross (the first: %d and %d)",
                           info->crossing_pairs, info->first_pair[0], info->first_pair[1]);
    }
    pw__st_measure(s, &vol);
    for (k = 0; k < 3; k++) size += (s->hi[k] - s->lo[k]) * (s->hi[k] - s->lo[k]);
    if (!(fabs(vol) > 1e-12 * size * sqrt(size)))
        return pw_fail(e, PW_ERR_DEGENERATE, "surface encloses no volume (%g)", vol);
    s->flip = vol < 0.0;
    s->volume = fabs(vol);
    return PW_OK;
}

/* ---- queries: segment crossings, closest points, winding numbers ---- */

enum { PW__ST_HIT = 1, PW__ST_GRAZE = 2 };

/* A float box around [lo, hi] grown by margin, rounded outward. */
PW__DEF void pw__st_fbox(const double *lo, const double *hi, double margin, float *b)
{
    int k;
    for (k = 0; k < 3; k++) {
        b[k] = (float)(lo[k] - margin - 1e-7 * fabs(lo[k]));
        b[k + 3] = (float)(hi[k] + margin + 1e-7 * fabs(hi[k]));
    }
}

/* The corner of triangle t with the smallest vertex index: computations
 * started there give a reversed triangle exactly the negated normal, so
 * that an inward surface fills exactly like the outward one. */
PW__DEF int pw__st_first_corner(const pw__stsurf *s, int t)
{
    const int *f = s->tri + 3 * t;
    return f[1] < f[0] ? (f[2] < f[1] ? 2 : 1) : (f[2] < f[0] ? 2 : 0);
}

/* Segment pq against triangle t, conservatively: 0 only when it certainly
 * misses by more than tol; PW__ST_HIT with *tp the crossing as a fraction
 * of pq; PW__ST_GRAZE when it runs (nearly) within the plane. */
PW__DEF int pw__st_seg_cross(const pw__stsurf *s, int t, const double *p, const double *q, double tol, double *tp)
{
    const double *c[3];
    double u[3], v[3], n[3], x[3], len, dp, dq, seg, tt;
    int k, i, j = pw__st_first_corner(s, t);
    for (k = 0; k < 3; k++) c[k] = pw__st_corner(s, t, (j + k) % 3);
    for (k = 0; k < 3; k++) {
        u[k] = c[1][k] - c[0][k];
        v[k] = c[2][k] - c[0][k];
        x[k] = q[k] - p[k];
    }
    pw_cross3(u, v, n);
    len = sqrt(pw_dot3(n, n));
    seg = sqrt(pw_dot3(x, x));
    for (k = 0; k < 3; k++) {
        n[k] /= len;
        u[k] = p[k] - c[0][k];
        v[k] = q[k] - c[0][k];
    }
    dp = pw_dot3(u, n);
    dq = pw_dot3(v, n);
    if ((dp > tol && dq > tol) || (dp < -tol && dq < -tol)) return 0;
    if (fabs(dp - dq) <= 1e-5 * seg) return PW__ST_GRAZE;
    tt = dp / (dp - dq);
    tt = tt < 0.0 ? 0.0 : tt > 1.0 ? 1.0 : tt;
    for (k = 0; k < 3; k++) x[k] = p[k] + tt * (q[k] - p[k]);
    for (i = 0; i < 3; i++) { /* x beyond edge i by more than tol: a miss */
        const double *a = c[i], *b = c[(i + 1) % 3];
        double e[3], w[3], m[3];
        for (k = 0; k < 3; k++) {
            e[k] = b[k] - a[k];
            w[k] = x[k] - a[k];
        }
        pw_cross3(e, w, m);
        if (pw_dot3(m, n) < -tol * sqrt(pw_dot3(e, e))) return 0;
    }
    *tp = tt;
    return PW__ST_HIT;
}

/* The leaves of the hierarchy whose boxes meet box b, depth first: start
 * with *top = -1 (stack: room for 96); returns the next such leaf node, -1
 * when there is none left. */
PW__DEF int pw__st_next_leaf(const pw__stsurf *s, const float *b, int *stack, int *top)
{
    if (*top < 0) {
        stack[0] = 0;
        *top = 1;
    }
    while (*top > 0) {
        int id = stack[--*top];
        const int *nd = s->node + 3 * id;
        if (!pw__st_boxes_meet(s->box + 6 * id, b)) continue;
        if (nd[2] < 0) return id;
        stack[(*top)++] = nd[2];
        stack[(*top)++] = nd[2] + 1;
    }
    return -1;
}

/* Where a segment hits the surface: the first `cap` hit parameters go to
 * t, n counts them all. */
typedef struct pw__st_hits {
    double *t;
    int cap, n;
} pw__st_hits;

/* All crossings of segment pq with the surface: PW__ST_HIT and/or
 * PW__ST_GRAZE bits (0: pq certainly misses the surface); *tfirst is the
 * hit nearest to p; when all is not NULL, the hits are listed there. */
PW__DEF int pw__st_crossings(const pw__stsurf *s, const double *p, const double *q, double *tfirst, pw__st_hits *all)
{
    double lo[3], hi[3], tol = 1e-9 * s->mag, t;
    float sb[6];
    int stack[96], top = -1, res = 0, k, i, id;
    for (k = 0; k < 3; k++) {
        lo[k] = p[k] < q[k] ? p[k] : q[k];
        hi[k] = p[k] < q[k] ? q[k] : p[k];
    }
    pw__st_fbox(lo, hi, tol, sb);
    *tfirst = 2.0;
    while ((id = pw__st_next_leaf(s, sb, stack, &top)) >= 0) {
        const int *nd = s->node + 3 * id;
        for (i = nd[0]; i < nd[0] + nd[1]; i++) {
            int r = pw__st_seg_cross(s, s->slot[i], p, q, tol, &t);
            res |= r;
            if (r == PW__ST_HIT && t < *tfirst) *tfirst = t;
            if (r == PW__ST_HIT && all && all->n++ < all->cap) all->t[all->n - 1] = t;
        }
    }
    return res;
}

PW__DEF int pw__st_segment(const pw__stsurf *s, const double *p, const double *q, double *tfirst)
{
    return pw__st_crossings(s, p, q, tfirst, NULL);
}

/* Squared distance from p to triangle abc; the nearest point to x
 * (Ericson, Real-Time Collision Detection, 5.1.5). */
PW__DEF double pw__st_closest_tri(const double *p, const double *a, const double *b, const double *c, double *x)
{
    double ab[3], ac[3], ap[3], bp[3], cp[3], d1, d2, d3, d4, d5, d6, va, vb, vc, v = 0.0, w = 0.0, r = 0.0;
    int k;
    for (k = 0; k < 3; k++) {
        ab[k] = b[k] - a[k];
        ac[k] = c[k] - a[k];
        ap[k] = p[k] - a[k];
        bp[k] = p[k] - b[k];
        cp[k] = p[k] - c[k];
    }
    d1 = pw_dot3(ab, ap);
    d2 = pw_dot3(ac, ap);
    d3 = pw_dot3(ab, bp);
    d4 = pw_dot3(ac, bp);
    d5 = pw_dot3(ab, cp);
    d6 = pw_dot3(ac, cp);
    vc = d1 * d4 - d3 * d2;
    vb = d5 * d2 - d1 * d6;
    va = d3 * d6 - d5 * d4;
    if (d1 <= 0.0 && d2 <= 0.0) v = w = 0.0;
    else if (d3 >= 0.0 && d4 <= d3) {
        v = 1.0;
        w = 0.0;
    } else if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        v = d1 / (d1 - d3);
        w = 0.0;
    } else if (d6 >= 0.0 && d5 <= d6) {
        v = 0.0;
        w = 1.0;
    } else if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        v = 0.0;
        w = d2 / (d2 - d6);
    } else if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
        w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        v = 1.0 - w;
    } else if (va + vb + vc > 0.0) {
        v = vb / (va + vb + vc);
        w = vc / (va + vb + vc);
    } else v = w = 0.0; /* a flat triangle: its edges belong to its neighbours too */
    for (k = 0; k < 3; k++) {
        x[k] = a[k] + v * ab[k] + w * ac[k];
        r += (p[k] - x[k]) * (p[k] - x[k]);
    }
    return r;
}

PW__DEF double pw__st_box_dist2(const float *b, const double *p)
{
    double r = 0.0, d;
    int k;
    for (k = 0; k < 3; k++) {
        d = b[k] - p[k] > 0.0 ? b[k] - p[k] : p[k] - b[k + 3] > 0.0 ? p[k] - b[k + 3] : 0.0;
        r += d * d;
    }
    return r;
}

/* Squared distance from p to the surface, the nearest point to x, the
 * triangle it lies on to *tri (may be NULL). */
PW__DEF double pw__st_closest(const pw__stsurf *s, const double *p, double *x, int *tri)
{
    double best = DBL_MAX, y[3];
    int stack[96], top = 0, i, k;
    stack[top++] = 0;
    while (top > 0) {
        int nd = stack[--top];
        const int *n = s->node + 3 * nd;
        if (pw__st_box_dist2(s->box + 6 * nd, p) >= best) continue;
        if (n[2] >= 0) { /* the nearer child is searched first */
            int near_first = pw__st_box_dist2(s->box + 6 * n[2], p) <= pw__st_box_dist2(s->box + 6 * (n[2] + 1), p);
            stack[top++] = near_first ? n[2] + 1 : n[2];
            stack[top++] = near_first ? n[2] : n[2] + 1;
            continue;
        }
        for (i = n[0]; i < n[0] + n[1]; i++) {
            int t = s->slot[i];
            double d = pw__st_closest_tri(p, pw__st_corner(s, t, 0), pw__st_corner(s, t, 1), pw__st_corner(s, t, 2), y);
            if (d < best) {
                for (best = d, k = 0; k < 3; k++) x[k] = y[k];
                if (tri) *tri = t;
            }
        }
    }
    return best;
}

/* atan2 from + - * / and sqrt only, so that inside/outside decisions are
 * the same on every platform: two argument halvings bring |z| below
 * tan(pi/16), where the series to z^21 is exact to 1e-17. */
PW__DEF double pw__st_atan2(double y, double x)
{
    const double pi = 3.14159265358979323846;
    double ax = fabs(x), ay = fabs(y), r, z, z2, s = 0.0, a;
    int m;
    if (ax == 0.0 && ay == 0.0) return 0.0;
    r = ay > ax ? ax / ay : ay / ax;
    z = r / (1.0 + sqrt(1.0 + r * r));
    z = z / (1.0 + sqrt(1.0 + z * z));
    z2 = z * z;
    for (m = 10; m >= 0; m--) s = (m % 2 ? -1.0 : 1.0) / (2 * m + 1) + z2 * s;
    a = 4.0 * z * s;
    if (ay > ax) a = 0.5 * pi - a;
    if (x < 0.0) a = pi - a;
    return y < 0.0 ? -a : a;
}

/* Signed solid angle of triangle abc seen from p (Van Oosterom &
 * Strackee): positive when p is on the side the triangle's back faces. */
PW__DEF double pw__st_solid_angle(const double *p, const double *a, const double *b, const double *c)
{
    double A[3], B[3], C[3], la, lb, lc, n[3], num, den;
    int k;
    for (k = 0; k < 3; k++) {
        A[k] = a[k] - p[k];
        B[k] = b[k] - p[k];
        C[k] = c[k] - p[k];
    }
    la = sqrt(pw_dot3(A, A));
    lb = sqrt(pw_dot3(B, B));
    lc = sqrt(pw_dot3(C, C));
    pw_cross3(B, C, n);
    num = pw_dot3(A, n);
    den = la * lb * lc + pw_dot3(A, B) * lc + pw_dot3(B, C) * la + pw_dot3(C, A) * lb;
    return 2.0 * pw__st_atan2(num, den);
}

/* The boundary half-edges of every inner node's triangle set (those whose
 * twin lies outside the node), for the hierarchical winding number. In
 * slot order, so that a node's set is a slot range. */
PW__DEF int pw__st_caps(const pw_alloc *a, pw__stsurf *s, const int *twin, pw_err *e)
{
    int *where = (int *)pw_alloc_array(a, (size_t)s->nt, sizeof(int), "slot index", e), nd, pass, i, k, n = 0;
    s->capfirst = (int *)pw_calloc_array(a, (size_t)s->nnode + 1, sizeof(int), "winding caps", e);
    if (!where || !s->capfirst) {
        pw_free(a, where);
        return PW_ERR_NOMEM;
    }
    for (i = 0; i < s->nt; i++) where[s->slot[i]] = i;
    for (pass = 0; pass < 2; pass++) {
        for (nd = 1, n = 0; nd < s->nnode; nd++) { /* the root is closed: no cap */
            const int *nn = s->node + 3 * nd;
            s->capfirst[nd] = n;
            if (nn[2] < 0) continue;
            for (i = nn[0]; i < nn[0] + nn[1]; i++)
                for (k = 0; k < 3; k++) {
                    int t = s->slot[i], tw = twin[3 * t + k], u = tw < 0 ? -1 : where[tw / 3];
                    if (u >= nn[0] && u < nn[0] + nn[1]) continue;
                    if (pass) {
                        s->cap[2 * n] = s->tri[3 * t + k];
                        s->cap[2 * n + 1] = s->tri[3 * t + (k + 1) % 3];
                    }
                    n++;
                }
        }
        s->capfirst[s->nnode] = n;
        if (!pass && !(s->cap = (int *)pw_alloc_array(a, 2 * (size_t)n + 2, sizeof(int), "winding caps", e))) break;
    }
    pw_free(a, where);
    return s->cap ? PW_OK : PW_ERR_NOMEM;
}

/* Sum of solid angles at p of node nd's triangles, or of the fan closing
 * its boundary when that is shorter and p is outside the node's box (the
 * patch and the fan then make a closed surface not around p, §3.3 of
 * Jacobson et al.). */
PW__DEF double pw__st_node_angle(const pw__stsurf *s, int nd, const double *p, int outside)
{
    const int *nn = s->node + 3 * nd;
    const float *b = s->box + 6 * nd;
    double w = 0.0, o[3];
    int i, k, c0 = s->capfirst ? s->capfirst[nd] : 0, nc = s->capfirst ? s->capfirst[nd + 1] - c0 : 0;
    if (outside && s->capfirst && nn[2] >= 0 && nc < nn[1]) {
        for (k = 0; k < 3; k++) o[k] = 0.5 * ((double)b[k] + b[k + 3]);
        for (i = c0; i < c0 + nc; i++)
            w += pw__st_solid_angle(p, o, s->p + 3 * s->cap[2 * i], s->p + 3 * s->cap[2 * i + 1]);
        return w;
    }
    for (i = nn[0]; i < nn[0] + nn[1]; i++) {
        int t = s->slot[i];
        w += pw__st_solid_angle(p, pw__st_corner(s, t, 0), pw__st_corner(s, t, 1), pw__st_corner(s, t, 2));
    }
    return w;
}

PW__DEF int pw__st_in_box(const float *b, const double *p)
{
    return p[0] >= b[0] && p[0] <= b[3] && p[1] >= b[1] && p[1] <= b[4] && p[2] >= b[2] && p[2] <= b[5];
}

/* Generalised winding number of the surface at p (1 inside, 0 outside,
 * fractional only very near the surface), exact up to rounding: the nodes
 * whose box holds p are opened, the others contribute their caps. */
PW__DEF double pw__st_winding(const pw__stsurf *s, const double *p)
{
    double w = 0.0;
    int stack[96], top = 0;
    if (!pw__st_in_box(s->box, p)) return 0.0; /* outside a closed surface's box */
    stack[top++] = 0;
    while (top > 0) {
        int nd = stack[--top];
        const int *nn = s->node + 3 * nd;
        if (!pw__st_in_box(s->box + 6 * nd, p)) w += pw__st_node_angle(s, nd, p, 1);
        else if (nn[2] < 0) w += pw__st_node_angle(s, nd, p, 0);
        else {
            stack[top++] = nn[2];
            stack[top++] = nn[2] + 1;
        }
    }
    w /= 4.0 * 3.14159265358979323846;
    return s->flip ? -w : w;
}

/* ---- the body-centred cubic lattice ----
 * Lattice vertices are named by half-unit coordinates L: black ones (cube
 * corners) have all three even, red ones (cube centres) all three odd;
 * the position is org + L * cell / 2. Long edges join vertices of one
 * colour (L differs by 2 along one axis), short ones a corner to the
 * centre of its cube (L differs by 1 along every axis). */

typedef struct pw__stcut {
    int in, out; /* the lattice edge: inside end, outside end */
    int id;      /* output vertex, -1 until a tetrahedron uses it */
    double t;    /* where the surface crosses, as a fraction from `in` */
} pw__stcut;

typedef struct pw__st {
    const pw_alloc *a;
    const pw_progress *prog;
    pw_err *e;
    pw__stsurf s;
    int n[3], nb, nlv; /* cubes per axis; black vertices; all lattice vertices */
    int unite;         /* the surface crosses itself: cut where the winding number drops below 1/2 */
    int *tri, *map;    /* the triangles used (zero-area ones dropped), the caller's index of each */
    double org[3], h;
    int graded;           /* 1: the graded lattice (vp, bs) instead of the body-centred cubic one */
    double *vp;           /* graded: nlv*3 vertex positions */
    double unit;          /* graded: mesh units per lattice unit */
    double tol, lmin;     /* graded: surface deviation allowed in a tetrahedron; no refinement below this edge */
    double ltip;          /* graded: nor below this one near a sharp tip of the surface */
    unsigned char *tip;   /* graded: per triangle, bit k: its corner k is a sharp tip */
    double *tipr;         /* graded: per surface vertex, how far from it the finer cells reach (0: not a tip) */
    pw_bisect bs;         /* graded: the tetrahedra and integer vertex coordinates */
    unsigned char *tbusy; /* graded: per tetrahedron, the surface may meet it */
    int *eoff, *eadj;     /* graded: lattice edges from each vertex, eadj[eoff[v] .. eoff[v+1]), free ones flagged */
    size_t capeadj;
    int *vtoff, *vtadj; /* graded: lattice tetrahedra at each vertex, vtadj[vtoff[v] .. vtoff[v+1]) */
    int *scratch;       /* graded: triangles meeting a box */
    int *pool;          /* graded: triangle lists of bisected tetrahedra (pw_bstet.data: count, then the ids) */
    size_t npool, cappool;
    struct pw__stmemo *memo; /* graded: the last sizing decisions, by box (PW__ST_MEMO of them) */
    double *tnorm;           /* graded: per triangle, unit normal and area */
    float *tbox;             /* graded: per triangle, its box (lo xyz, hi xyz) */
    size_t capscratch;
    signed char *side;   /* per lattice vertex: +1 inside, -1 outside, 0 not known yet */
    unsigned char *busy; /* per cube: the surface may meet it */
    int *warp;           /* per lattice vertex: the cut point it moved onto, -1 */
    int *id;             /* per lattice vertex: output vertex, -1 */
    pw__stcut *cut;      /* sorted by inside end */
    size_t ncut, capcut;
    float *opos; /* output positions (nopos vertices) */
    size_t nopos, capopos;
    unsigned char *osurf; /* per output vertex: on the surface */
    int dropped;          /* fragments dropped */
    size_t caposurf;
    int *otet; /* output tetrahedra (notet) */
    size_t notet, capotet;
} pw__st;

/* The 14 lattice neighbours: 6 along long edges, 8 along short ones. */
static const signed char pw__st_nb[14][3] = {{2, 0, 0},  {-2, 0, 0},  {0, 2, 0},   {0, -2, 0},  {0, 0, 2},
                                             {0, 0, -2}, {1, 1, 1},   {1, 1, -1},  {1, -1, 1},  {1, -1, -1},
                                             {-1, 1, 1}, {-1, 1, -1}, {-1, -1, 1}, {-1, -1, -1}};

PW__DEF void pw__st_coord(const pw__st *st, int v, int *L)
{
    int nx = st->n[0] + 1, ny = st->n[1] + 1, odd = 0;
    if (v >= st->nb) {
        v -= st->nb;
        nx = st->n[0];
        ny = st->n[1];
        odd = 1;
    }
    L[0] = 2 * (v % nx) + odd;
    L[1] = 2 * ((v / nx) % ny) + odd;
    L[2] = 2 * (v / nx / ny) + odd;
}

/* The lattice vertex at L, -1 if there is none. */
PW__DEF int pw__st_index(const pw__st *st, const int *L)
{
    int k, odd = L[0] & 1;
    for (k = 0; k < 3; k++)
        if (L[k] < odd || L[k] > 2 * st->n[k] - odd || (L[k] & 1) != odd) return -1;
    if (!odd) return L[0] / 2 + (st->n[0] + 1) * (L[1] / 2 + (st->n[1] + 1) * (L[2] / 2));
    return st->nb + L[0] / 2 + st->n[0] * (L[1] / 2 + st->n[1] * (L[2] / 2));
}

PW__DEF void pw__st_lpos(const pw__st *st, const int *L, double *p)
{
    int k;
    for (k = 0; k < 3; k++) p[k] = st->org[k] + 0.5 * st->h * L[k];
}

PW__DEF void pw__st_vpos(const pw__st *st, int v, double *p)
{
    int L[3];
    if (st->graded) {
        memcpy(p, st->vp + 3 * (size_t)v, 3 * sizeof(double));
        return;
    }
    pw__st_coord(st, v, L);
    pw__st_lpos(st, L, p);
}

/* The axis along which A and B form a long edge, -1 for a short edge. */
PW__DEF int pw__st_long_axis(const int *A, const int *B)
{
    int k;
    for (k = 0; k < 3; k++)
        if (A[k] - B[k] == 2 || B[k] - A[k] == 2) return k;
    return -1;
}

/* The cell for about `target` tetrahedra: the inside holds volume * 12 /
 * cell^3 lattice tetrahedra, and the cut ones near the surface add about
 * 1.3 area / cell^2 (measured on CGAL meshes: 1.1 to 2 for most, so counts
 * land within a few per cent). Newton on x = 1/cell from above (the cubic
 * is increasing and convex), from + - * / only, so that the lattice is the
 * same on every platform. */
PW__DEF double pw__st_cell_for(double volume, double area, double target)
{
    double x = 1.0, f;
    int i;
    for (i = 0; i < 200 && 12.0 * volume * x * x * x < target; i++) x *= 2.0;
    for (i = 0; i < 200 && 12.0 * volume * x * x * x > 8.0 * target; i++) x *= 0.5;
    for (i = 0; i < 60; i++) {
        f = 12.0 * volume * x * x * x + 1.3 * area * x * x - target;
        x -= f / (36.0 * volume * x * x + 2.6 * area * x);
    }
    return 1.0 / x;
}

/* The cell: the caller's, or the one for about target_tets tetrahedra in
 * `volume` (the enclosed volume scaled to the lattice's tetrahedra per
 * cube). */
PW__DEF int pw__st_cell(pw__st *st, const pw_stuff_options *o, double volume, double *h)
{
    int target = o && o->target_tets ? o->target_tets : 20000;
    if (o && o->cell != 0.0) {
        if (!(o->cell > 0.0) || !pw_is_finite(o->cell))
            return pw_fail(st->e, PW_ERR_INVALID, "tetrahedralize: cell %g must be positive", o->cell);
        *h = o->cell;
        return PW_OK;
    }
    if (target < 0) return pw_fail(st->e, PW_ERR_INVALID, "tetrahedralize: target_tets %d is negative", target);
    *h = pw__st_cell_for(volume, st->s.area, target);
    return PW_OK;
}

/* Lattice spacing and extent: the surface's box centred in the lattice
 * with at least one cube to spare on every side, so that every lattice
 * vertex of the outer layer is outside. */
PW__DEF int pw__st_lattice(pw__st *st, const pw_stuff_options *o)
{
    double h, count;
    int k, r;
    if ((r = pw__st_cell(st, o, st->s.volume, &h))) return r;
    for (k = 0, count = 1.0; k < 3; k++) {
        double c = (st->s.hi[k] - st->s.lo[k]) / h;
        if (!(c < 1e6)) count = 1e30;
        else {
            st->n[k] = (int)ceil(c) + 2;
            count *= st->n[k] + 1;
        }
    }
    if (count < 1e30) count += (double)st->n[0] * st->n[1] * st->n[2];
    if (count > PW_MAX_STUFF_LATTICE)
        return pw_fail(st->e, PW_ERR_LIMIT,
                       "tetrahedralize: a lattice of spacing %g needs %.3g vertices, more than PW_MAX_STUFF_LATTICE "
                       "(%d); use a larger cell or fewer tetrahedra",
                       h, count, PW_MAX_STUFF_LATTICE);
    st->h = h;
    for (k = 0; k < 3; k++) st->org[k] = 0.5 * (st->s.lo[k] + st->s.hi[k]) - 0.5 * h * st->n[k];
    st->nb = (st->n[0] + 1) * (st->n[1] + 1) * (st->n[2] + 1);
    st->nlv = st->nb + st->n[0] * st->n[1] * st->n[2];
    st->side = (signed char *)pw_calloc_array(st->a, (size_t)st->nlv, 1, "lattice sides", st->e);
    st->busy = (unsigned char *)pw_calloc_array(st->a, (size_t)(st->nlv - st->nb), 1, "lattice cubes", st->e);
    st->warp = (int *)pw_alloc_array(st->a, (size_t)st->nlv, sizeof(int), "lattice warps", st->e);
    st->id = (int *)pw_alloc_array(st->a, (size_t)st->nlv, sizeof(int), "lattice vertex ids", st->e);
    if (!st->side || !st->busy || !st->warp || !st->id) return PW_ERR_NOMEM;
    for (k = 0; k < st->nlv; k++) st->warp[k] = st->id[k] = -1;
    return PW_OK;
}

/* Triangle abc meets the cube of centre c and half-width hw (separating
 * axis test, Akenine-Moller 2001); hw is padded by the caller, so rounding
 * can only report a meeting that is not there. */
PW__DEF int pw__st_tri_box(const double *ctr, const double *hw, const double *a, const double *b, const double *c)
{
    double v[3][3], e[3][3], n[3], ax[3], p[3], r;
    int i, j, k;
    for (k = 0; k < 3; k++) {
        v[0][k] = a[k] - ctr[k];
        v[1][k] = b[k] - ctr[k];
        v[2][k] = c[k] - ctr[k];
        if ((v[0][k] > hw[k] && v[1][k] > hw[k] && v[2][k] > hw[k]) ||
            (v[0][k] < -hw[k] && v[1][k] < -hw[k] && v[2][k] < -hw[k]))
            return 0;
    }
    for (i = 0; i < 3; i++)
        for (k = 0; k < 3; k++) e[i][k] = v[(i + 1) % 3][k] - v[i][k];
    pw_cross3(e[0], e[1], n);
    if (fabs(pw_dot3(n, v[0])) > hw[0] * fabs(n[0]) + hw[1] * fabs(n[1]) + hw[2] * fabs(n[2])) return 0;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) { /* axis: unit vector i cross edge j */
            ax[i] = 0.0;
            ax[(i + 1) % 3] = -e[j][(i + 2) % 3];
            ax[(i + 2) % 3] = e[j][(i + 1) % 3];
            for (k = 0; k < 3; k++) p[k] = pw_dot3(ax, v[k]);
            r = hw[0] * fabs(ax[0]) + hw[1] * fabs(ax[1]) + hw[2] * fabs(ax[2]);
            if ((p[0] > r && p[1] > r && p[2] > r) || (p[0] < -r && p[1] < -r && p[2] < -r)) return 0;
        }
    return 1;
}

/* Marks the cubes that the surface may meet. */
PW__DEF void pw__st_mark(pw__st *st)
{
    const pw__stsurf *s = &st->s;
    int t, k, c0[3], c1[3], c[3];
    for (t = 0; t < s->nt; t++) {
        const double *p[3];
        for (k = 0; k < 3; k++) p[k] = pw__st_corner(s, t, k);
        for (k = 0; k < 3; k++) {
            double lo = p[0][k] < p[1][k] ? p[0][k] : p[1][k], hi = p[0][k] > p[1][k] ? p[0][k] : p[1][k];
            lo = lo < p[2][k] ? lo : p[2][k];
            hi = hi > p[2][k] ? hi : p[2][k];
            c0[k] = pw_clampi((int)floor((lo - st->org[k]) / st->h - 1e-6), 0, st->n[k] - 1);
            c1[k] = pw_clampi((int)floor((hi - st->org[k]) / st->h + 1e-6), 0, st->n[k] - 1);
        }
        for (c[2] = c0[2]; c[2] <= c1[2]; c[2]++)
            for (c[1] = c0[1]; c[1] <= c1[1]; c[1]++)
                for (c[0] = c0[0]; c[0] <= c1[0]; c[0]++) {
                    int L[3] = {2 * c[0] + 1, 2 * c[1] + 1, 2 * c[2] + 1}, i = pw__st_index(st, L) - st->nb;
                    double ctr[3], hw[3];
                    if (st->busy[i]) continue;
                    pw__st_lpos(st, L, ctr);
                    hw[0] = hw[1] = hw[2] = 0.5 * st->h * (1.0 + 1e-6);
                    st->busy[i] = (unsigned char)pw__st_tri_box(ctr, hw, p[0], p[1], p[2]);
                }
    }
}

PW__DEF int pw__st_busy(const pw__st *st, int i, int j, int k)
{
    if (i < 0 || j < 0 || k < 0 || i >= st->n[0] || j >= st->n[1] || k >= st->n[2]) return 0;
    return st->busy[i + st->n[0] * (j + st->n[1] * k)];
}

/* Edge AB lies in a cube that the surface does not meet. A short edge is
 * in the cube of its red end, a red long edge in the two cubes of its
 * ends, a black long edge on the boundary of four cubes. */
PW__DEF int pw__st_edge_free(const pw__st *st, const int *A, const int *B)
{
    int ax = pw__st_long_axis(A, B), c[3], du, dv, u, v;
    if (ax < 0) {
        const int *R = (A[0] & 1) ? A : B;
        return !pw__st_busy(st, R[0] / 2, R[1] / 2, R[2] / 2);
    }
    if (A[0] & 1)
        return !pw__st_busy(st, A[0] / 2, A[1] / 2, A[2] / 2) && !pw__st_busy(st, B[0] / 2, B[1] / 2, B[2] / 2);
    u = (ax + 1) % 3;
    v = (ax + 2) % 3;
    c[ax] = (A[ax] < B[ax] ? A[ax] : B[ax]) / 2;
    for (du = -1; du <= 0; du++)
        for (dv = -1; dv <= 0; dv++) {
            c[u] = A[u] / 2 + du;
            c[v] = A[v] / 2 + dv;
            if (!pw__st_busy(st, c[0], c[1], c[2])) return 1;
        }
    return 0;
}

PW__DEF int pw__st_inside(const pw__st *st, const double *p) { return pw__st_winding(&st->s, p) >= 0.5; }

/* The degree of lattice vertex u (uniform: all 14 directions, some off
 * the lattice), and its k-th neighbour (-1: none), with *free set when the
 * edge to it certainly misses the surface by the lattice's cells alone. */
PW__DEF int pw__st_degree(const pw__st *st, int u) { return st->graded ? st->eoff[u + 1] - st->eoff[u] : 14; }

PW__DEF int pw__st_neighbour(const pw__st *st, int u, int k, int *free_)
{
    int U[3], V[3];
    if (st->graded) {
        int e = st->eadj[st->eoff[u] + k];
        *free_ = e & 1;
        return e >> 1;
    }
    pw__st_coord(st, u, U);
    V[0] = U[0] + pw__st_nb[k][0];
    V[1] = U[1] + pw__st_nb[k][1];
    V[2] = U[2] + pw__st_nb[k][2];
    if ((k = pw__st_index(st, V)) >= 0) *free_ = pw__st_edge_free(st, U, V);
    return k;
}

/* Inside or outside for every lattice vertex: breadth-first over edges
 * that certainly do not meet the surface, one winding number per
 * component (§ "inside decided robustly": no ray parity, no normals). */
PW__DEF int pw__st_sides(pw__st *st)
{
    int *queue = (int *)pw_alloc_array(st->a, (size_t)st->nlv, sizeof(int), "lattice queue", st->e);
    int s0, head, tail, k, r = PW_OK;
    double p[3], q[3], t;
    if (!queue) return PW_ERR_NOMEM;
    if (!st->graded) pw__st_mark(st);
    for (s0 = 0; s0 < st->nlv && r == PW_OK; s0++) {
        signed char sg;
        if ((s0 & 4095) == 0 &&
            (r = pw_report(st->prog, 0.1f + 0.4f * (float)s0 / (float)st->nlv, "lattice sides", st->e)))
            break;
        if (st->side[s0]) continue;
        pw__st_vpos(st, s0, p);
        sg = (signed char)(pw__st_inside(st, p) ? 1 : -1);
        st->side[s0] = sg;
        queue[0] = s0;
        head = 0;
        tail = 1;
        while (head < tail) {
            int u = queue[head++], n = pw__st_degree(st, u);
            for (k = 0; k < n; k++) {
                int fr, v = pw__st_neighbour(st, u, k, &fr);
                if (v < 0 || st->side[v]) continue;
                if (!fr) {
                    pw__st_vpos(st, u, p);
                    pw__st_vpos(st, v, q);
                    if (pw__st_segment(&st->s, p, q, &t)) continue;
                }
                st->side[v] = sg;
                queue[tail++] = v;
            }
        }
    }
    pw_free(st->a, queue);
    return r;
}

/* ---- cut points and warping ---- */

/* Where the lattice edge from pin (inside) to pout (outside) crosses the
 * surface: the first crossing from the inside end, or bisection on the
 * winding number when the crossing grazes a triangle. */
PW__DEF int pw__st_cmp_double(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

PW__DEF void pw__st_lerp(const double *p, const double *q, double t, double *x)
{
    int k;
    for (k = 0; k < 3; k++) x[k] = p[k] + t * (q[k] - p[k]);
}

/* With self-intersections, the crossing after which the winding number is
 * below 1/2 (the first crossings may enter an overlap or leave it); -1 if
 * rounding hides it. */
PW__DEF double pw__st_cut_union(const pw__st *st, const double *pin, const double *pout)
{
    double hits[64], t, x[3];
    pw__st_hits all;
    int n, i, j;
    all.t = hits;
    all.cap = 64;
    all.n = 0;
    pw__st_crossings(&st->s, pin, pout, &t, &all);
    n = all.n;
    if (n > 64) return -1.0;
    qsort(hits, (size_t)n, sizeof(double), pw__st_cmp_double);
    if (n > 0 && hits[n - 1] - hits[0] < 1e-9) return hits[0]; /* one crossing: the side changes there */
    for (i = 0; i < n; i = j) {                                /* probe halfway to the next distinct crossing */
        for (j = i + 1; j < n && hits[j] - hits[i] < 1e-9; j++) continue;
        pw__st_lerp(pin, pout, 0.5 * (hits[i] + (j < n ? hits[j] : 1.0)), x);
        if (!pw__st_inside(st, x)) return hits[i];
    }
    return -1.0;
}

PW__DEF double pw__st_cut_param(const pw__st *st, const double *pin, const double *pout)
{
    double t, lo = 0.0, hi = 1.0, x[3];
    int i;
    if (st->unite && (t = pw__st_cut_union(st, pin, pout)) >= 0.0) return t;
    if (!st->unite && (pw__st_segment(&st->s, pin, pout, &t) & PW__ST_HIT)) return t;
    for (i = 0; i < 48; i++) {
        double mid = 0.5 * (lo + hi);
        pw__st_lerp(pin, pout, mid, x);
        if (pw__st_inside(st, x)) lo = mid;
        else hi = mid;
    }
    return 0.5 * (lo + hi);
}

/* A cut point on every lattice edge from an inside to an outside vertex,
 * sorted by the inside end. */
PW__DEF int pw__st_cuts(pw__st *st)
{
    int u, k, r = PW_OK;
    double p[3], q[3];
    for (u = 0; u < st->nlv && r == PW_OK; u++) {
        int n = pw__st_degree(st, u);
        if ((u & 4095) == 0 && (r = pw_report(st->prog, 0.5f + 0.2f * (float)u / (float)st->nlv, "cut points", st->e)))
            break;
        if (st->side[u] <= 0) continue;
        for (k = 0; k < n; k++) {
            pw__stcut *c;
            int fr, v = pw__st_neighbour(st, u, k, &fr);
            if (v < 0 || st->side[v] >= 0) continue;
            if ((r = pw_grow(st->a, (void **)&st->cut, &st->capcut, st->ncut + 1, sizeof *st->cut, "cut points",
                             st->e)))
                break;
            pw__st_vpos(st, u, p);
            pw__st_vpos(st, v, q);
            c = st->cut + st->ncut++;
            c->in = u;
            c->out = v;
            c->id = -1;
            c->t = pw__st_cut_param(st, p, q);
        }
    }
    return r;
}

/* The cut point on the edge from `in` (inside) to `out` (outside). */
PW__DEF int pw__st_find_cut(const pw__st *st, int in, int out)
{
    size_t lo = 0, hi = st->ncut;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (st->cut[mid].in < in) lo = mid + 1;
        else hi = mid;
    }
    while (lo < st->ncut && st->cut[lo].in == in && st->cut[lo].out != out) lo++;
    PW_ASSERT(lo < st->ncut && st->cut[lo].in == in);
    return (int)lo;
}

PW__DEF void pw__st_cut_pos(const pw__st *st, int c, double *x)
{
    double p[3], q[3];
    int k;
    pw__st_vpos(st, st->cut[c].in, p);
    pw__st_vpos(st, st->cut[c].out, q);
    for (k = 0; k < 3; k++) x[k] = p[k] + st->cut[c].t * (q[k] - p[k]);
}

/* Where lattice vertex r (>= 0, at its cut point once warped) or cut
 * point -1 - r is. */
PW__DEF void pw__st_ref_pos(const pw__st *st, int r, double *x)
{
    if (r >= 0 && st->warp[r] >= 0) r = -1 - st->warp[r];
    if (r < 0) pw__st_cut_pos(st, -1 - r, x);
    else pw__st_vpos(st, r, x);
}

typedef struct pw__stviol {
    int v, c; /* the violated lattice vertex, the cut point */
    double d; /* their distance */
} pw__stviol;

PW__DEF int pw__st_viol_cmp(const void *x, const void *y)
{
    const pw__stviol *a = (const pw__stviol *)x, *b = (const pw__stviol *)y;
    if (a->v != b->v) return a->v < b->v ? -1 : 1;
    if (a->d != b->d) return a->d < b->d ? -1 : 1;
    return (a->c > b->c) - (a->c < b->c);
}

/* The warping state: violations sorted by vertex then distance (vertex v
 * owns vl[first[v] .. first[v+1])), the violations whose cut point lies on
 * an edge towards each vertex (byt[tfirst[v] .. tfirst[v+1]), indices into
 * vl), and the number of live violations of each vertex. */
typedef struct pw__stwarp {
    pw__stviol *vl;
    int n, *first, *byt, *tfirst, *pend, *queue, qn;
    unsigned char *dead; /* graded lattice: per violation, given up (the move would fold a tetrahedron) */
} pw__stwarp;

PW__DEF int pw__st_other(const pw__st *st, const pw__stviol *x)
{
    return st->cut[x->c].in == x->v ? st->cut[x->c].out : st->cut[x->c].in;
}

/* Graded lattice: the length against which alpha measures a cut point
 * on an edge of length len at v: len, but at most PW__ST_REACH times the
 * shortest edge at v, so that a vertex where tetrahedra change size moves
 * by a bounded fraction of its smallest tetrahedra. */
PW__DEF double pw__st_reach(const pw__st *st, int v, double len)
{
    double p[3], q[3], best = DBL_MAX, d;
    int i;
    pw__st_vpos(st, v, p);
    for (i = st->eoff[v]; i < st->eoff[v + 1]; i++) {
        pw__st_vpos(st, st->eadj[i] >> 1, q);
        d = pw_dist3(p, q);
        best = d < best ? d : best;
    }
    best *= PW__ST_REACH;
    return best < len ? best : len;
}

/* A cut point violates the lattice vertex at the end of its edge that is
 * nearer than alpha * edge length (alpha < 1/2: at most one end; graded:
 * alpha times pw__st_reach). */
PW__DEF int pw__st_violations(pw__st *st, pw__stwarp *w)
{
    size_t i;
    w->vl = (pw__stviol *)pw_alloc_array(st->a, st->ncut + 1, sizeof *w->vl, "warp candidates", st->e);
    if (!w->vl) return PW_ERR_NOMEM;
    for (i = 0, w->n = 0; i < st->ncut; i++) {
        const pw__stcut *c = st->cut + i;
        int A[3], B[3], lg;
        double len, al, p[3], q[3];
        if (st->graded) {
            pw__st_vpos(st, c->in, p);
            pw__st_vpos(st, c->out, q);
            len = pw_dist3(p, q);
            al = PW__ST_ALPHA_GRADED;
        } else {
            pw__st_coord(st, c->in, A);
            pw__st_coord(st, c->out, B);
            lg = pw__st_long_axis(A, B) >= 0;
            len = lg ? st->h : 0.86602540378443865 * st->h;
            al = lg ? PW__ST_ALPHA_LONG : PW__ST_ALPHA_SHORT;
        }
        if (c->t * len < al * (st->graded ? pw__st_reach(st, c->in, len) : len)) {
            w->vl[w->n].v = c->in;
            w->vl[w->n].c = (int)i;
            w->vl[w->n++].d = c->t * len;
        } else if ((1.0 - c->t) * len < al * (st->graded ? pw__st_reach(st, c->out, len) : len)) {
            w->vl[w->n].v = c->out;
            w->vl[w->n].c = (int)i;
            w->vl[w->n++].d = (1.0 - c->t) * len;
        }
    }
    qsort(w->vl, (size_t)w->n, sizeof *w->vl, pw__st_viol_cmp);
    return PW_OK;
}

/* The per-vertex index arrays of the warping state (counting sorts). */
PW__DEF int pw__st_warp_index(pw__st *st, pw__stwarp *w)
{
    size_t nl = (size_t)st->nlv + 1;
    int i;
    w->first = (int *)pw_calloc_array(st->a, nl, sizeof(int), "warp index", st->e);
    w->tfirst = (int *)pw_calloc_array(st->a, nl + 1, sizeof(int), "warp index", st->e);
    w->pend = (int *)pw_calloc_array(st->a, nl, sizeof(int), "warp index", st->e);
    w->byt = (int *)pw_alloc_array(st->a, (size_t)w->n + 1, sizeof(int), "warp index", st->e);
    w->queue = (int *)pw_alloc_array(st->a, 2 * (size_t)w->n + 1, sizeof(int), "warp queue", st->e);
    if (st->graded && !(w->dead = (unsigned char *)pw_calloc_array(st->a, (size_t)w->n + 1, 1, "warp index", st->e)))
        return PW_ERR_NOMEM;
    if (!w->first || !w->tfirst || !w->pend || !w->byt || !w->queue) return PW_ERR_NOMEM;
    for (i = 0; i < w->n; i++) {
        w->first[w->vl[i].v + 1]++;
        w->pend[w->vl[i].v]++;
        w->tfirst[pw__st_other(st, w->vl + i) + 2]++;
    }
    for (i = 0; i < st->nlv; i++) {
        w->first[i + 1] += w->first[i];
        w->tfirst[i + 2] += w->tfirst[i + 1];
    }
    for (i = 0; i < w->n; i++) w->byt[w->tfirst[pw__st_other(st, w->vl + i) + 1]++] = i;
    return PW_OK;
}

/* Moves v onto cut point c: the violations on other edges at v die, and
 * vertices left without live violations are stable, so that the vertices
 * violated towards them may warp (queued). */
PW__DEF void pw__st_move(pw__st *st, pw__stwarp *w, int v, int c)
{
    int i, j;
    st->warp[v] = c;
    w->pend[v] = 0;
    for (i = w->tfirst[v]; i < w->tfirst[v + 1]; i++) {
        int x = w->vl[w->byt[i]].v;
        if (st->warp[x] >= 0 || (w->dead && w->dead[w->byt[i]]) || --w->pend[x] > 0) continue;
        for (j = w->tfirst[x]; j < w->tfirst[x + 1]; j++) w->queue[w->qn++] = w->vl[w->byt[j]].v;
    }
}

/* Graded lattice: moving v onto cut point c keeps every lattice
 * tetrahedron at v the way round it was (neighbours of very different
 * sizes could otherwise fold). */
PW__DEF int pw__st_warp_safe(const pw__st *st, int v, int c)
{
    int i, k, j;
    for (i = st->vtoff[v]; i < st->vtoff[v + 1]; i++) {
        const pw_bstet *t = st->bs.t + st->vtadj[i];
        double p[4][3], u[3], w[3], z[3], n[3], d0, d1;
        for (k = 0; k < 4; k++) {
            if (t->v[k] == v) pw__st_cut_pos(st, c, p[k]);
            else pw__st_ref_pos(st, t->v[k], p[k]);
        }
        for (j = 0; j < 3; j++) {
            u[j] = p[1][j] - p[0][j];
            w[j] = p[2][j] - p[0][j];
            z[j] = p[3][j] - p[0][j];
        }
        pw_cross3(u, w, n);
        d1 = pw_dot3(n, z);
        for (k = 0; k < 4; k++) pw__st_vpos(st, t->v[k], p[k]);
        for (j = 0; j < 3; j++) {
            u[j] = p[1][j] - p[0][j];
            w[j] = p[2][j] - p[0][j];
            z[j] = p[3][j] - p[0][j];
        }
        pw_cross3(u, w, n);
        d0 = pw_dot3(n, z);
        if (!(d1 * (d0 > 0.0 ? 1.0 : -1.0) > 0.0)) return 0;
    }
    return 1;
}

/* Warps v onto its nearest live violating cut point whose other end is
 * stable (any live one when `any`); returns 1 if it moved. On the graded
 * lattice a move that would fold a tetrahedron is given up, and a vertex
 * whose every violation was given up is stable. */
PW__DEF int pw__st_try_warp(pw__st *st, pw__stwarp *w, int v, int any)
{
    int i, j;
    if (st->warp[v] >= 0 || w->pend[v] == 0) return 0;
    for (i = w->first[v]; i < w->first[v + 1]; i++) {
        int o = pw__st_other(st, w->vl + i);
        if (w->dead && w->dead[i]) continue;
        if (st->warp[o] < 0 && (any || w->pend[o] == 0)) {
            if (st->graded && !pw__st_warp_safe(st, v, w->vl[i].c)) {
                w->dead[i] = 1;
                if (--w->pend[v] == 0)
                    for (j = w->tfirst[v]; j < w->tfirst[v + 1]; j++) w->queue[w->qn++] = w->vl[w->byt[j]].v;
                if (w->pend[v] == 0) return 0;
                continue;
            }
            pw__st_move(st, w, v, w->vl[i].c);
            return 1;
        }
    }
    return 0;
}

/* §3 warping: each violated vertex moves onto its nearest violating cut
 * point and is then on the surface, so the cut points on its other edges
 * vanish. A vertex only moves towards an end that stays in place (one that
 * moves towards another that moves too can make slivers outside the
 * bounds): first the vertices violated towards stable ends, each move
 * making further ends stable. What remains pending is a core of vertices
 * all violated towards one another; violations join inside to outside
 * vertices, so moving exactly the core's outside vertices (towards inside
 * ones, which then have no live violation left) keeps every end in place. */
PW__DEF int pw__st_warp(pw__st *st)
{
    pw__stwarp w;
    int r, i, scan = 0;
    memset(&w, 0, sizeof w);
    r = pw__st_violations(st, &w);
    if (r == PW_OK) r = pw__st_warp_index(st, &w);
    for (i = w.n - 1; r == PW_OK && i >= 0; i--) w.queue[w.qn++] = w.vl[i].v; /* popped in index order */
    while (r == PW_OK && (w.qn > 0 || scan < w.n)) {
        if (w.qn > 0) pw__st_try_warp(st, &w, w.queue[--w.qn], 0);
        else if (st->side[w.vl[scan++].v] < 0) pw__st_try_warp(st, &w, w.vl[scan - 1].v, 1);
    }
    pw_free(st->a, w.vl);
    pw_free(st->a, w.first);
    pw_free(st->a, w.tfirst);
    pw_free(st->a, w.pend);
    pw_free(st->a, w.byt);
    pw_free(st->a, w.queue);
    pw_free(st->a, w.dead);
    return r;
}

/* ---- stencils ---- */

/* Lattice vertex v after warping: +1 inside, -1 outside, 0 on the surface. */
PW__DEF int pw__st_class(const pw__st *st, int v) { return st->warp[v] >= 0 ? 0 : st->side[v]; }

/* Output tetrahedra are built from references: a lattice vertex v >= 0,
 * or cut point c as -1 - c. */
PW__DEF int pw__st_cutref(const pw__st *st, int in, int out) { return -1 - pw__st_find_cut(st, in, out); }

/* The output vertex of reference r, created on first use (-1: no memory). */
PW__DEF int pw__st_ref_id(pw__st *st, int r)
{
    int *slot = r < 0 ? &st->cut[-1 - r].id : &st->id[r], k;
    double x[3];
    if (*slot >= 0) return *slot;
    if (pw_grow(st->a, (void **)&st->opos, &st->capopos, 3 * (st->nopos + 1), sizeof(float), "tetrahedron vertices",
                st->e) ||
        pw_grow(st->a, (void **)&st->osurf, &st->caposurf, st->nopos + 1, 1, "tetrahedron vertices", st->e))
        return -1;
    st->osurf[st->nopos] = (unsigned char)(r < 0 || st->warp[r] >= 0);
    pw__st_ref_pos(st, r, x);
    for (k = 0; k < 3; k++) st->opos[3 * st->nopos + k] = (float)x[k];
    *slot = (int)st->nopos++;
    return *slot;
}

/* Appends a tetrahedron, positively oriented. */
PW__DEF int pw__st_emit(pw__st *st, int r0, int r1, int r2, int r3)
{
    int r[4], id[4], k;
    double p[4][3], u[3], v[3], w[3], n[3];
    r[0] = r0;
    r[1] = r1;
    r[2] = r2;
    r[3] = r3;
    for (k = 0; k < 4; k++) pw__st_ref_pos(st, r[k], p[k]);
    for (k = 0; k < 3; k++) {
        u[k] = p[1][k] - p[0][k];
        v[k] = p[2][k] - p[0][k];
        w[k] = p[3][k] - p[0][k];
    }
    pw_cross3(u, v, n);
    if (pw_dot3(n, w) < 0.0) {
        r[0] = r1;
        r[1] = r0;
    }
    for (k = 0; k < 4; k++)
        if ((id[k] = pw__st_ref_id(st, r[k])) < 0) return PW_ERR_NOMEM;
    if (st->notet >= PW_MAX_MESH_ELEMENTS)
        return pw_fail(st->e, PW_ERR_LIMIT, "tetrahedralize: more than PW_MAX_MESH_ELEMENTS (%d) tetrahedra",
                       PW_MAX_MESH_ELEMENTS);
    if (pw_grow(st->a, (void **)&st->otet, &st->capotet, 4 * (st->notet + 1), sizeof(int), "tetrahedra", st->e))
        return PW_ERR_NOMEM;
    memcpy(st->otet + 4 * st->notet++, id, sizeof id);
    return PW_OK;
}

/* §3, quadrilateral faces: the surface cuts lattice face (p, q, m), p and
 * q inside, m outside, into the quadrilateral p, q, cut(q,m), cut(p,m).
 * Its diagonal depends on the face alone, so that both tetrahedra sharing
 * the face split it alike. When m's edge to p (or q) is long, the diagonal
 * takes the cut point on that long edge (to the other inside corner) if the
 * cut lies within PW__ST_LONG_SPLIT of the edge from p, else p itself (to
 * the other cut point); the two faces at one long edge then decide alike,
 * so a prism's diagonals cannot cycle. The adversarial search (see the top
 * of the file) found the worst angles flat for splits from 0.55 to 0.7,
 * and worse for a fixed choice either way (9.3 degrees). When pq is the
 * long edge, a parity rule on the lattice coordinates picks the end (it
 * flips between the two faces at a long edge). Returns 1 for the diagonal
 * p - cut(q, m), 2 for q - cut(p, m). */
PW__DEF int pw__st_diagonal(const pw__st *st, int p, int q, int m)
{
    int P[3], Q[3], M[3], k, s = 0;
    if (st->graded) { /* from the inside corner whose cut point is nearer (in edge fractions) */
        double tp = st->cut[pw__st_find_cut(st, p, m)].t, tq = st->cut[pw__st_find_cut(st, q, m)].t;
        return tp < tq || (tp == tq && p < q) ? 1 : 2;
    }
    pw__st_coord(st, p, P);
    pw__st_coord(st, q, Q);
    pw__st_coord(st, m, M);
    if (pw__st_long_axis(P, M) >= 0) return st->cut[pw__st_find_cut(st, p, m)].t < PW__ST_LONG_SPLIT ? 2 : 1;
    if (pw__st_long_axis(Q, M) >= 0) return st->cut[pw__st_find_cut(st, q, m)].t < PW__ST_LONG_SPLIT ? 1 : 2;
    for (k = 0; k < 3; k++) s += P[k] != Q[k] ? P[k] > Q[k] : M[k] < Q[k];
    return (s & 1) ? 2 : 1;
}

/* A triangular prism, columns (b[i], t[i]); dir[i] is the diagonal of the
 * quadrilateral between columns i and i+1: +1 for b[i]-t[i+1], -1 for
 * b[i+1]-t[i], 0 to be chosen. The three diagonals must not cycle; then
 * one column's bottom carries two of them, and the prism is its top
 * triangle with that bottom plus a pyramid. */
PW__DEF int pw__st_prism(pw__st *st, const int *b, const int *t, int *dir)
{
    int i, s = -1, x, y, r;
    for (i = 0; i < 3; i++)
        if (dir[i] == 0) dir[i] = dir[(i + 1) % 3] == dir[(i + 2) % 3] ? -dir[(i + 1) % 3] : 1;
    for (i = 0; i < 3; i++)
        if (dir[i] > 0 && dir[(i + 2) % 3] < 0) s = i;
    PW_ASSERT(s >= 0);
    x = (s + 1) % 3;
    y = (s + 2) % 3;
    if ((r = pw__st_emit(st, b[s], t[s], t[x], t[y]))) return r;
    if (dir[x] > 0) {
        if ((r = pw__st_emit(st, b[s], b[x], b[y], t[y]))) return r;
        return pw__st_emit(st, b[s], b[x], t[y], t[x]);
    }
    if ((r = pw__st_emit(st, b[s], b[x], b[y], t[x]))) return r;
    return pw__st_emit(st, b[s], b[y], t[y], t[x]);
}

/* Corners p, q inside, m outside, z on the surface: a pyramid on the
 * quadrilateral of face (p, q, m) with apex z. */
PW__DEF int pw__st_pyramid(pw__st *st, int p, int q, int m, int z)
{
    int cp = pw__st_cutref(st, p, m), cq = pw__st_cutref(st, q, m), r;
    if (pw__st_diagonal(st, p, q, m) == 1) {
        if ((r = pw__st_emit(st, z, p, q, cq))) return r;
        return pw__st_emit(st, z, p, cq, cp);
    }
    if ((r = pw__st_emit(st, z, p, q, cp))) return r;
    return pw__st_emit(st, z, q, cq, cp);
}

/* §3 stencils for lattice tetrahedron g by the signs of its corners. */
PW__DEF int pw__st_tet(pw__st *st, const int *g)
{
    int P[4], M[4], Z[4], np = 0, nm = 0, nz = 0, k, r[4], b[3], t[3], dir[3];
    for (k = 0; k < 4; k++) {
        int c = pw__st_class(st, g[k]);
        if (c > 0) P[np++] = g[k];
        else if (c < 0) M[nm++] = g[k];
        else Z[nz++] = g[k];
    }
    if (np == 0) return PW_OK; /* also with four corners on the surface: a sliver outside the bounds */
    if (nm == 0) return pw__st_emit(st, g[0], g[1], g[2], g[3]);
    if (np == 1) { /* one tetrahedron: the inside corner and the cut points towards the outside ones */
        for (k = 0; k < 4; k++) r[k] = pw__st_class(st, g[k]) < 0 ? pw__st_cutref(st, P[0], g[k]) : g[k];
        return pw__st_emit(st, r[0], r[1], r[2], r[3]);
    }
    if (np == 2 && nm == 1) return pw__st_pyramid(st, P[0], P[1], M[0], Z[0]);
    if (np == 2) { /* ++--: prism between the faces of P[0] and P[1]; the cut quadrilateral is free */
        b[0] = P[0];
        b[1] = pw__st_cutref(st, P[0], M[0]);
        b[2] = pw__st_cutref(st, P[0], M[1]);
        t[0] = P[1];
        t[1] = pw__st_cutref(st, P[1], M[0]);
        t[2] = pw__st_cutref(st, P[1], M[1]);
        dir[0] = pw__st_diagonal(st, P[0], P[1], M[0]) == 1 ? 1 : -1;
        dir[1] = 0;
        dir[2] = pw__st_diagonal(st, P[0], P[1], M[1]) == 1 ? -1 : 1;
        return pw__st_prism(st, b, t, dir);
    }
    for (k = 0; k < 3; k++) { /* +++-: the tetrahedron minus its outside corner */
        b[k] = P[k];
        t[k] = pw__st_cutref(st, P[k], M[0]);
        dir[k] = pw__st_diagonal(st, P[k], P[(k + 1) % 3], M[0]) == 1 ? 1 : -1;
    }
    return pw__st_prism(st, b, t, dir);
}

/* Every lattice tetrahedron: for each cube and each of its faces towards
 * +x, +y, +z, the long edge between the two cube centres with each of the
 * four edges of the face. */
PW__DEF int pw__st_stencils(pw__st *st)
{
    int c[3], ax, e, k, r = PW_OK, g[4], L[3], B[3], C[3];
    for (c[2] = 0; c[2] < st->n[2] && r == PW_OK; c[2]++) {
        r = pw_report(st->prog, 0.7f + 0.3f * (float)c[2] / (float)st->n[2], "stencils", st->e);
        for (c[1] = 0; c[1] < st->n[1] && r == PW_OK; c[1]++)
            for (c[0] = 0; c[0] < st->n[0] && r == PW_OK; c[0]++)
                for (ax = 0; ax < 3 && r == PW_OK; ax++) {
                    int u = (ax + 1) % 3, v = (ax + 2) % 3;
                    if (c[ax] + 1 >= st->n[ax]) continue;
                    for (k = 0; k < 3; k++) L[k] = 2 * c[k] + 1;
                    g[0] = pw__st_index(st, L);
                    L[ax] += 2;
                    g[1] = pw__st_index(st, L);
                    for (e = 0; e < 4 && r == PW_OK; e++) {
                        int along = e < 2 ? u : v, across = e < 2 ? v : u;
                        B[ax] = C[ax] = 2 * c[ax] + 2;
                        B[across] = C[across] = 2 * c[across] + 2 * (e & 1);
                        B[along] = 2 * c[along];
                        C[along] = B[along] + 2;
                        g[2] = pw__st_index(st, B);
                        g[3] = pw__st_index(st, C);
                        for (k = 0; k < 4 && pw__st_class(st, g[k]) < 0; k++) continue;
                        if (k < 4) r = pw__st_tet(st, g);
                    }
                }
    }
    return r;
}

/* ---- the graded lattice ----
 * Newest-vertex bisection of a Kuhn lattice (bisect.h): coarse cubes of
 * the cell chosen from target_tets, every tetrahedron the surface meets
 * bisected while the surface within its reach bends by more than st->tol
 * (pw__st_need), down to edges of st->lmin. Then the same stages as the
 * uniform lattice over an explicit edge list: sides, cut points, warping
 * with one alpha for every edge, stencils with quadrilateral diagonals
 * from the inside corner whose cut point is nearer. */

/* A box query: the box lo..hi, its centre and padded half-widths for the
 * separating axis test, and its float box for the triangle boxes. */
typedef struct pw__stbox {
    double lo[3], hi[3], ctr[3], hw[3];
    float fb[6];
} pw__stbox;

PW__DEF void pw__st_query(const pw__st *st, const double *lo, const double *hi, pw__stbox *q)
{
    int k;
    for (k = 0; k < 3; k++) {
        q->lo[k] = lo[k];
        q->hi[k] = hi[k];
        q->ctr[k] = 0.5 * (lo[k] + hi[k]);
        q->hw[k] = 0.5 * (hi[k] - lo[k]) * (1.0 + 1e-6) + 1e-9 * st->s.mag;
    }
    pw__st_fbox(lo, hi, 1e-9 * st->s.mag, q->fb);
}

/* Triangle t's box lies inside the box lo..hi. */
PW__DEF int pw__st_tri_inside(const pw__st *st, int t, const double *lo, const double *hi)
{
    const float *b = st->tbox + 6 * (size_t)t;
    return b[0] >= lo[0] && b[1] >= lo[1] && b[2] >= lo[2] && b[3] <= hi[0] && b[4] <= hi[1] && b[5] <= hi[2];
}

/* A corner of triangle t lies in the box lo..hi. */
PW__DEF int pw__st_corner_inside(const pw__st *st, int t, const double *lo, const double *hi)
{
    int c;
    for (c = 0; c < 3; c++) {
        const double *p = pw__st_corner(&st->s, t, c);
        if (p[0] >= lo[0] && p[1] >= lo[1] && p[2] >= lo[2] && p[0] <= hi[0] && p[1] <= hi[1] && p[2] <= hi[2])
            return 1;
    }
    return 0;
}

/* The triangles list[0..count) that meet the query box: with PW__ST_ANY,
 * 1 at the first; with PW__ST_NEAR, appended to st->scratch (*n of them so
 * far), 0 (-1 without memory). */
enum { PW__ST_ANY, PW__ST_NEAR };
PW__DEF int pw__st_filter(pw__st *st, const pw__stbox *q, const int *list, int count, int mode, int *n)
{
    const pw__stsurf *s = &st->s;
    int i;
    for (i = 0; i < count; i++) {
        int t = list[i];
        if (!pw__st_boxes_meet(st->tbox + 6 * (size_t)t, q->fb) ||
            (!pw__st_tri_inside(st, t, q->lo, q->hi) && !pw__st_corner_inside(st, t, q->lo, q->hi) &&
             !pw__st_tri_box(q->ctr, q->hw, pw__st_corner(s, t, 0), pw__st_corner(s, t, 1), pw__st_corner(s, t, 2))))
            continue;
        if (mode == PW__ST_ANY) return 1;
        if (pw_grow(st->a, (void **)&st->scratch, &st->capscratch, (size_t)*n + 1, sizeof(int), "triangles in a box",
                    st->e))
            return -1;
        st->scratch[(*n)++] = t;
    }
    return 0;
}

/* The triangles that meet the box lo..hi, among those of list `from` (an
 * offset in st->pool: the list of a tetrahedron around this box) or, when
 * it is negative, among all (through the hierarchy): with PW__ST_ANY, 1 if
 * there is one (0 if none); with PW__ST_NEAR, all of them in st->scratch,
 * and their count (-1 without memory). */
enum {
    PW__ST_FAR = 1,
    PW__ST_CLEAR,
    PW__ST_BUSY
}; /* pw_bstet.mark (pw__st_need): no triangle within reach; some
                                                       within reach, none in the tetrahedron's box; some in it */
PW__DEF int pw__st_box_tris(pw__st *st, int from, const double *lo, const double *hi, int mode)
{
    const pw__stsurf *s = &st->s;
    pw__stbox q;
    int stack[96], top = -1, n = 0, r = 0, id;
    pw__st_query(st, lo, hi, &q);
    if (from >= 0) r = pw__st_filter(st, &q, st->pool + from + 1, st->pool[from], mode, &n);
    else
        while (r == 0 && (id = pw__st_next_leaf(s, q.fb, stack, &top)) >= 0)
            r = pw__st_filter(st, &q, s->slot + s->node[3 * id], s->node[3 * id + 1], mode, &n);
    return r ? r : n;
}

/* Box and longest edge of lattice tetrahedron t. */
PW__DEF double pw__st_gbox(const pw__st *st, const pw_bisect *b, const int *v, double *lo, double *hi)
{
    double p[4][3], len = 0.0;
    int i, j, k;
    for (i = 0; i < 4; i++)
        for (k = 0; k < 3; k++) p[i][k] = st->org[k] + st->unit * b->vc[3 * v[i] + k];
    for (k = 0; k < 3; k++) {
        lo[k] = hi[k] = p[0][k];
        for (i = 1; i < 4; i++) {
            lo[k] = p[i][k] < lo[k] ? p[i][k] : lo[k];
            hi[k] = p[i][k] > hi[k] ? p[i][k] : hi[k];
        }
    }
    for (i = 0; i < 4; i++)
        for (j = i + 1; j < 4; j++) {
            double d = pw_dist3(p[i], p[j]);
            len = d > len ? d : len;
        }
    return len;
}

/* pw_bisect_need: the surface in t's box bends by more than st->tol. */
/* Triangle t clipped to the box lo..hi (Sutherland-Hodgman): its corners
 * to out (room for 9), their count. */
PW__DEF int pw__st_clip(const pw__st *st, int t, const double *lo, const double *hi, double (*out)[3])
{
    double buf[2][9][3];
    int n = 3, k, side, i, j, cur = 0;
    for (i = 0; i < 3; i++) memcpy(buf[0][i], pw__st_corner(&st->s, t, i), sizeof buf[0][i]);
    for (k = 0; k < 3 && n > 0; k++)
        for (side = 0; side < 2 && n > 0; side++) {
            double(*a)[3] = buf[cur], (*b)[3] = buf[1 - cur], c = side ? hi[k] : lo[k], sg = side ? -1.0 : 1.0;
            int m = 0;
            for (i = 0; i < n && sg * (a[i][k] - c) >= 0.0; i++) continue;
            if (i == n) continue; /* all on the inner side: unchanged */
            for (i = 0; i < n; i++) {
                const double *p = a[i], *q = a[(i + 1) % n];
                double dp = sg * (p[k] - c), dq = sg * (q[k] - c);
                if (dp >= 0.0) memcpy(b[m++], p, sizeof b[0]);
                if ((dp >= 0.0) != (dq >= 0.0) && m < 9) { /* from the smaller end: the same point either way round */
                    int sw = memcmp(p, q, sizeof(double) * 3) > 0;
                    const double *u = sw ? q : p, *w = sw ? p : q;
                    double du = sw ? dq : dp, dw = sw ? dp : dq;
                    for (j = 0; j < 3; j++) b[m][j] = u[j] + du / (du - dw) * (w[j] - u[j]);
                    m++;
                }
            }
            n = m;
            cur = 1 - cur;
        }
    memcpy(out, buf[cur], (size_t)n * sizeof buf[0][0]);
    return n;
}

/* The triangles st->scratch[0..n) within reach of a tetrahedron (box
 * lo..hi) lie in a slab, across their mean normal, wider than st->tol /
 * PW__ST_BEND (the parts of the triangles inside the box), or face two
 * ways. The slab of the whole triangles holds that of their parts: when it
 * is thin enough, nothing is clipped. */
PW__DEF int pw__st_bends(const pw__st *st, int n, const double *lo, const double *hi)
{
    double N[3] = {0.0, 0.0, 0.0}, A = 0.0, nn, wlo = DBL_MAX, whi = -DBL_MAX, poly[9][3];
    int i, j, k, m, first;
    for (i = 0; i < n; i++) {
        const double *c = st->tnorm + 4 * (size_t)st->scratch[i];
        for (k = 0; k < 3; k++) N[k] += c[3] * c[k];
        A += c[3];
    }
    nn = sqrt(pw_dot3(N, N));
    if (nn < 0.5 * A) return 1; /* sheets facing opposite ways */
    for (k = 0; k < 3; k++) N[k] /= nn;
    for (i = 0; i < n; i++)
        for (j = 0; j < 3; j++) {
            double d = pw_dot3(pw__st_corner(&st->s, st->scratch[i], j), N);
            wlo = d < wlo ? d : wlo;
            whi = d > whi ? d : whi;
        }
    if (!(PW__ST_BEND * (whi - wlo) > st->tol)) return 0;
    for (i = 0, first = 0, wlo = 2.0; i < n; i++) { /* the triangle most tilted from N first: a bend shows soonest */
        double c = pw_dot3(st->tnorm + 4 * (size_t)st->scratch[i], N);
        first = c < wlo ? i : first;
        wlo = c < wlo ? c : wlo;
    }
    wlo = DBL_MAX;
    whi = -DBL_MAX;
    for (i = -1; i < n; i++) {
        int t = st->scratch[i < 0 ? first : i], inside;
        if (i == first) continue;
        inside = pw__st_tri_inside(st, t, lo, hi);
        if (inside)
            for (m = 0; m < 3; m++) memcpy(poly[m], pw__st_corner(&st->s, t, m), sizeof poly[m]);
        m = inside ? 3 : pw__st_clip(st, t, lo, hi, poly);
        for (j = 0; j < m; j++) {
            double d = pw_dot3(poly[j], N);
            wlo = d < wlo ? d : wlo;
            whi = d > whi ? d : whi;
        }
        if (PW__ST_BEND * (whi - wlo) > st->tol) return 1;
    }
    return 0;
}

/* A sharp tip of the surface (a corner of one of st->scratch[0..n)) lies
 * in the box lo..hi. */
PW__DEF int pw__st_tip_near(const pw__st *st, int n, const double *lo, const double *hi)
{
    int i, k;
    for (i = 0; i < n; i++)
        for (k = 0; k < 3; k++)
            if (st->tip[st->scratch[i]] >> k & 1) {
                const double *p = pw__st_corner(&st->s, st->scratch[i], k);
                double r = st->tipr[st->s.tri[3 * st->scratch[i] + k]];
                if (p[0] >= lo[0] - r && p[1] >= lo[1] - r && p[2] >= lo[2] - r && p[0] <= hi[0] + r &&
                    p[1] <= hi[1] + r && p[2] <= hi[2] + r)
                    return 1;
            }
    return 0;
}

/* Appends st->scratch[0..n) to st->pool as a list: its offset, -1
 * without memory. */
PW__DEF int pw__st_keep_list(pw__st *st, int n)
{
    size_t o = st->npool;
    if (o + (size_t)n + 1 > (size_t)INT_MAX) {
        pw_fail(st->e, PW_ERR_LIMIT, "tetrahedralize: more than %d triangle references in the sizing", INT_MAX);
        return -1;
    }
    if (pw_grow(st->a, (void **)&st->pool, &st->cappool, o + (size_t)n + 1, sizeof(int), "sizing lists", st->e))
        return -1;
    st->pool[o] = n;
    memcpy(st->pool + o + 1, st->scratch, (size_t)n * sizeof(int));
    st->npool = o + (size_t)n + 1;
    return (int)o;
}

/* pw_bisect_need: the surface within reach of t (its box grown by alpha
 * times its longest edge: how far warping moves a corner along an edge no
 * longer than t's; the longer edges that the warping's cap allows, up to
 * PW__ST_REACH times, are left out, which halves the tetrahedra near the
 * surface for a fit 0.01-0.05% of the diagonal looser on the CGAL corpus)
 * bends (pw__st_bends). The candidates are the
 * triangles within reach of the tetrahedron t was cut from (t->data, kept
 * for both halves of a bisected one); t->mark says whether any triangle is
 * within reach, and if so whether any meets t's own box. */
PW__DEF int pw__st_decide(pw__st *st, const pw_bisect *b, pw_bstet *t)
{
    double lo[3], hi[3], glo[3], ghi[3], len = pw__st_gbox(st, b, t->v, lo, hi);
    pw__stbox q;
    int n, k, none = 0;
    for (k = 0; k < 3; k++) { /* the reach of warping: corners move onto the surface about that far */
        glo[k] = lo[k] - PW__ST_ALPHA_GRADED * len;
        ghi[k] = hi[k] + PW__ST_ALPHA_GRADED * len;
    }
    if ((n = pw__st_box_tris(st, t->data, glo, ghi, PW__ST_NEAR)) < 0) return PW_ERR_NOMEM;
    t->mark = PW__ST_FAR;
    if (n == 0) return 0;
    if ((len > st->lmin || (len > st->ltip && pw__st_tip_near(st, n, glo, ghi))) && pw__st_bends(st, n, glo, ghi)) {
        t->mark = 0; /* unknown in both halves */
        if ((t->data < 0 || n < st->pool[t->data]) && (t->data = pw__st_keep_list(st, n)) < 0)
            return st->e ? st->e->code : PW_ERR_NOMEM;
        return 1;
    }
    pw__st_query(st, lo, hi, &q);
    t->mark = pw__st_filter(st, &q, st->scratch, n, PW__ST_ANY, &none) ? PW__ST_BUSY : PW__ST_CLEAR;
    return 0;
}

/* The sizing decisions depend on a tetrahedron's box and longest edge
 * only, and many tetrahedra share both (the six Kuhn tetrahedra of a cube,
 * and many of their halves): the last decision of each of PW__ST_MEMO
 * slots is kept, by its exact key (the box's integer corners and the
 * squared longest edge), with its mark and triangle list. */
#define PW__ST_MEMO 8192
typedef struct pw__stmemo {
    uint64_t lo, hi, len2; /* len2 0: empty */
    int data, mark, split;
} pw__stmemo;

/* pw_bisect_need: pw__st_decide, remembered. */
PW__DEF int pw__st_need(void *user, const pw_bisect *b, pw_bstet *t)
{
    pw__st *st = (pw__st *)user;
    int lo[3], hi[3], i, j, k, r;
    uint64_t len2 = 0, klo, khi, h;
    pw__stmemo *m;
    for (k = 0; k < 3; k++) {
        lo[k] = hi[k] = b->vc[3 * t->v[0] + k];
        for (i = 1; i < 4; i++) {
            int c = b->vc[3 * t->v[i] + k];
            lo[k] = c < lo[k] ? c : lo[k];
            hi[k] = c > hi[k] ? c : hi[k];
        }
    }
    for (i = 0; i < 4; i++)
        for (j = i + 1; j < 4; j++) {
            uint64_t d = 0;
            for (k = 0; k < 3; k++) {
                int64_t x = (int64_t)b->vc[3 * t->v[i] + k] - b->vc[3 * t->v[j] + k];
                d += (uint64_t)(x * x);
            }
            len2 = d > len2 ? d : len2;
        }
    klo = pw__bs_key(lo);
    khi = pw__bs_key(hi);
    h = pw__bs_slot(klo ^ (khi * 0x9e3779b97f4a7c15ull) ^ (len2 * 0xc2b2ae3d27d4eb4full), PW__ST_MEMO - 1);
    m = st->memo + h;
    if (m->len2 == len2 && m->lo == klo && m->hi == khi) {
        t->mark = m->mark;
        if (m->split) t->data = m->data;
        return m->split;
    }
    if ((r = pw__st_decide(st, b, t)) < 0) return r;
    m->lo = klo;
    m->hi = khi;
    m->len2 = len2;
    m->data = t->data;
    m->mark = t->mark;
    m->split = r;
    return r;
}

/* The tetrahedra at each vertex, which tetrahedra the surface may meet,
 * and the edges of each vertex (eadj holds 2 * other end + 1 when the edge
 * lies in a tetrahedron the surface does not meet). */
PW__DEF int pw__st_gedges(pw__st *st)
{
    size_t i;
    int r = PW_OK, v, k, n = 0, *mark = NULL;
    st->tbusy = (unsigned char *)pw_alloc_array(st->a, st->bs.nt + 1, 1, "lattice cells", st->e);
    st->vtoff = (int *)pw_calloc_array(st->a, (size_t)st->nlv + 2, sizeof(int), "lattice stars", st->e);
    st->vtadj = (int *)pw_alloc_array(st->a, 4 * st->bs.nt + 1, sizeof(int), "lattice stars", st->e);
    st->eoff = (int *)pw_alloc_array(st->a, (size_t)st->nlv + 1, sizeof(int), "lattice edges", st->e);
    mark = (int *)pw_alloc_array(st->a, (size_t)st->nlv + 1, sizeof(int), "lattice edges", st->e);
    if (!st->tbusy || !st->vtoff || !st->vtadj || !st->eoff || !mark) r = PW_ERR_NOMEM;
    for (i = 0; r == PW_OK && i < st->bs.nt; i++) {
        double lo[3], hi[3];
        pw__st_gbox(st, &st->bs, st->bs.t[i].v, lo, hi);
        if (st->bs.t[i].kept) st->tbusy[i] = st->bs.t[i].mark == PW__ST_BUSY; /* sized */
        else /* cut by the closure: empty if its parent's box was */
            st->tbusy[i] = st->bs.t[i].mark != PW__ST_FAR && st->bs.t[i].mark != PW__ST_CLEAR &&
                           pw__st_box_tris(st, st->bs.t[i].data, lo, hi, PW__ST_ANY) > 0;
        for (k = 0; k < 4; k++) st->vtoff[st->bs.t[i].v[k] + 2]++;
    }
    if (r == PW_OK) {
        for (v = 0; v < st->nlv; v++) st->vtoff[v + 2] += st->vtoff[v + 1];
        for (i = 0; i < st->bs.nt; i++)
            for (k = 0; k < 4; k++) st->vtadj[st->vtoff[st->bs.t[i].v[k] + 1]++] = (int)i;
        for (v = 0; v < st->nlv; v++) mark[v] = -1;
    }
    for (v = 0; r == PW_OK && v < st->nlv; v++) { /* mark[u] = slot of edge v-u while v is visited */
        int j;
        st->eoff[v] = n;
        for (j = st->vtoff[v]; j < st->vtoff[v + 1]; j++) {
            const int *g = st->bs.t[st->vtadj[j]].v;
            int fr = !st->tbusy[st->vtadj[j]];
            for (k = 0; k < 4; k++) {
                int u = g[k];
                if (u == v) continue;
                if (mark[u] >= 0) {
                    st->eadj[mark[u]] |= fr;
                    continue;
                }
                if (pw_grow(st->a, (void **)&st->eadj, &st->capeadj, (size_t)n + 1, sizeof(int), "lattice edges",
                            st->e)) {
                    r = PW_ERR_NOMEM;
                    break;
                }
                mark[u] = n;
                st->eadj[n++] = 2 * u + fr;
            }
        }
        for (j = st->eoff[v]; j < n; j++) mark[st->eadj[j] >> 1] = -1;
    }
    if (r == PW_OK) st->eoff[st->nlv] = n;
    pw_free(st->a, mark);
    return r;
}

/* The corners of the surface where the angles of its triangles sum to
 * less than PW__ST_TIP_ANGLE (the apex of a thin spike), as st->tip. */
PW__DEF int pw__st_tips(pw__st *st)
{
    double *sum = (double *)pw_calloc_array(st->a, (size_t)st->s.nv + 1, sizeof(double), "vertex angles", st->e);
    int t, k, j;
    st->tip = (unsigned char *)pw_calloc_array(st->a, (size_t)st->s.nt + 1, 1, "sharp tips", st->e);
    st->tipr = sum;
    if (!sum || !st->tip) return PW_ERR_NOMEM;
    for (t = 0; t < st->s.nt; t++)
        for (k = 0; k < 3; k++) {
            const double *a = pw__st_corner(&st->s, t, k), *b = pw__st_corner(&st->s, t, (k + 1) % 3);
            const double *c = pw__st_corner(&st->s, t, (k + 2) % 3);
            double u[3], v[3], n[3];
            for (j = 0; j < 3; j++) {
                u[j] = b[j] - a[j];
                v[j] = c[j] - a[j];
            }
            pw_cross3(u, v, n);
            sum[st->s.tri[3 * t + k]] += pw__st_atan2(sqrt(pw_dot3(n, n)), pw_dot3(u, v));
        }
    for (t = 0; t < st->s.nt; t++)
        for (k = 0; k < 3; k++)
            if (sum[st->s.tri[3 * t + k]] < PW__ST_TIP_ANGLE) st->tip[t] |= (unsigned char)(1 << k);
    for (j = 0; j < st->s.nv; j++) /* a cone of half-angle a: angles summing to 2 pi sin a at its apex, and
                                      thinner than lmin up to about lmin / sin a from it (at most 64 lmin) */
        sum[j] = sum[j] < PW__ST_TIP_ANGLE ? st->lmin * (sum[j] > 0.1 ? 6.283185307179586 / sum[j] : 64.0) : 0.0;
    return PW_OK;
}

/* Unit normal, area and box of every triangle, and the sharp tips, for the
 * sizing of the graded lattice. */
PW__DEF int pw__st_tri_frames(pw__st *st)
{
    int t, k;
    st->tnorm = (double *)pw_alloc_array(st->a, 4 * (size_t)st->s.nt, sizeof(double), "triangle normals", st->e);
    st->tbox = (float *)pw_alloc_array(st->a, 6 * (size_t)st->s.nt, sizeof(float), "triangle boxes", st->e);
    if (!st->tnorm || !st->tbox || pw__st_tips(st)) return PW_ERR_NOMEM;
    for (t = 0; t < st->s.nt; t++) {
        int j = pw__st_first_corner(&st->s, t);
        const double *a = pw__st_corner(&st->s, t, j), *b = pw__st_corner(&st->s, t, (j + 1) % 3);
        const double *c = pw__st_corner(&st->s, t, (j + 2) % 3);
        double u[3], v[3], *n = st->tnorm + 4 * (size_t)t, lo[3], hi[3];
        for (k = 0; k < 3; k++) {
            u[k] = b[k] - a[k];
            v[k] = c[k] - a[k];
            lo[k] = a[k] < b[k] ? a[k] : b[k];
            hi[k] = a[k] > b[k] ? a[k] : b[k];
            lo[k] = c[k] < lo[k] ? c[k] : lo[k];
            hi[k] = c[k] > hi[k] ? c[k] : hi[k];
        }
        pw_cross3(u, v, n);
        n[3] = pw_norm3(n);
        pw__st_fbox(lo, hi, 0.0, st->tbox + 6 * (size_t)t);
    }
    return PW_OK;
}

/* The graded lattice: coarse Kuhn cubes, refined near the surface, made
 * conforming; vertex positions and per-vertex arrays. */
PW__DEF int pw__st_glattice(pw__st *st, const pw_stuff_options *o, double fit)
{
    enum { SIDE_LOG = 10 };
    double h, count = 1.0, diag = 0.0;
    int k, n[3], r;
    if ((r = pw__st_cell(st, o, 0.5 * st->s.volume, &h))) return r; /* six Kuhn tetrahedra per cube, BCC's twelve */
    for (k = 0; k < 3; k++) {
        double c = (st->s.hi[k] - st->s.lo[k]) / h;
        diag += (st->s.hi[k] - st->s.lo[k]) * (st->s.hi[k] - st->s.lo[k]);
        if (!(c < 1e6)) count = 1e30;
        else {
            n[k] = (int)ceil(c) + 2;
            count *= n[k];
        }
    }
    if (count * 6.0 > PW_MAX_STUFF_LATTICE || n[0] >= (1 << (21 - SIDE_LOG)) || n[1] >= (1 << (21 - SIDE_LOG)) ||
        n[2] >= (1 << (21 - SIDE_LOG)))
        return pw_fail(st->e, PW_ERR_LIMIT,
                       "tetrahedralize: a lattice of spacing %g needs %.3g cubes, more than PW_MAX_STUFF_LATTICE "
                       "(%d) / 6; use a larger cell or fewer tetrahedra",
                       h, count, PW_MAX_STUFF_LATTICE);
    st->graded = 1;
    st->h = h;
    st->unit = h / (1 << SIDE_LOG);
    st->tol = fit * sqrt(diag);
    st->lmin = (fit > 4.0 * PW__ST_MIN_CELL ? 0.25 * fit : PW__ST_MIN_CELL) * sqrt(diag);
    st->ltip = PW__ST_TIP_CELL * st->lmin;
    for (k = 0; k < 3; k++) st->org[k] = 0.5 * (st->s.lo[k] + st->s.hi[k]) - 0.5 * h * n[k];
    st->bs.a = st->a;
    st->bs.e = st->e;
    st->bs.max_tets = PW_MAX_STUFF_LATTICE;
    if ((r = pw__st_tri_frames(st))) return r;
    st->memo = (pw__stmemo *)pw_calloc_array(st->a, PW__ST_MEMO, sizeof *st->memo, "sizing memo", st->e);
    if (!st->memo) return PW_ERR_NOMEM;
    r = pw_bisect_kuhn(&st->bs, n, 1 << SIDE_LOG);
    if (r == PW_OK) r = pw_report(st->prog, 0.1f, "graded lattice", st->e);
    if (r == PW_OK) r = pw_bisect_refine(&st->bs, pw__st_need, st, 3 * (SIDE_LOG - 1));
    if (r == PW_OK)
        r = pw_bisect_conform(&st->bs); /* the closure's tetrahedra are not sized again (it would
                                                        add 1-25% of tetrahedra for no better fit) */
    if (r) return r;
    st->nlv = st->bs.nv;
    st->vp = (double *)pw_alloc_array(st->a, 3 * (size_t)st->nlv, sizeof(double), "lattice vertices", st->e);
    st->side = (signed char *)pw_calloc_array(st->a, (size_t)st->nlv, 1, "lattice sides", st->e);
    st->warp = (int *)pw_alloc_array(st->a, (size_t)st->nlv, sizeof(int), "lattice warps", st->e);
    st->id = (int *)pw_alloc_array(st->a, (size_t)st->nlv, sizeof(int), "lattice vertex ids", st->e);
    if (!st->vp || !st->side || !st->warp || !st->id) return PW_ERR_NOMEM;
    for (k = 0; k < st->nlv; k++) {
        int j;
        st->warp[k] = st->id[k] = -1;
        for (j = 0; j < 3; j++) st->vp[3 * k + j] = st->org[j] + st->unit * st->bs.vc[3 * k + j];
    }
    return pw__st_gedges(st);
}

/* Every graded lattice tetrahedron with a corner not outside. */
PW__DEF int pw__st_gstencils(pw__st *st)
{
    size_t i;
    int k, r = PW_OK;
    for (i = 0; i < st->bs.nt && r == PW_OK; i++) {
        const int *g = st->bs.t[i].v;
        if ((i & 65535) == 0 && (r = pw_report(st->prog, 0.8f + 0.2f * (float)i / (float)st->bs.nt, "stencils", st->e)))
            break;
        for (k = 0; k < 4 && pw__st_class(st, g[k]) < 0; k++) continue;
        if (k < 4) r = pw__st_tet(st, g);
    }
    return r;
}

/* ---- pieces ---- */

/* Root of x in union-find array up, with path halving. */
PW__DEF int pw__st_root(int *up, int x)
{
    while (up[x] != x) x = up[x] = up[up[x]];
    return x;
}

/* Piece labels: up[t] (nt ints) is the smallest tetrahedron of t's piece
 * (tetrahedra joined by shared faces, nb from pw_tetmesh_neighbors);
 * returns the number of pieces. */
PW__DEF int pw__st_piece_labels(const pw_tetmesh *m, const int *nb, int *up)
{
    int t, f, n = 0;
    for (t = 0; t < m->nt; t++) up[t] = t;
    for (f = 0; f < 4 * m->nt; f++) {
        int x, y;
        if (nb[f] < 0) continue;
        x = pw__st_root(up, f >> 2);
        y = pw__st_root(up, nb[f] >> 2);
        if (x != y) up[x > y ? x : y] = x < y ? x : y;
    }
    for (t = 0; t < m->nt; t++) n += (up[t] = pw__st_root(up, t)) == t;
    return n;
}

/* Pieces of a tetrahedral mesh: tetrahedra joined by shared faces (nb from
 * pw_tetmesh_neighbors), by union-find with path halving. */
PW__DEF int pw_tetmesh_pieces(const pw_alloc *a, const pw_tetmesh *m, const int *nb, pw_err *e)
{
    int *up = (int *)pw_alloc_array(a, (size_t)m->nt + 1, sizeof(int), "piece labels", e), n;
    if (!up) return -1;
    n = pw__st_piece_labels(m, nb, up);
    pw_free(a, up);
    return n;
}

/* The surface's connected components (triangles sharing a vertex): comp[t]
 * in 0 .. *nc-1, numbered in order of their first triangle. */
PW__DEF int pw__st_components(const pw_alloc *a, const pw_stuff_tris *m, int *comp, int *nc, pw_err *e)
{
    const int *tri = m->tri;
    int nv = m->nv, nt = m->nt;
    int *up = (int *)pw_alloc_array(a, (size_t)nv + 1, sizeof(int), "surface components", e), v, t, k;
    if (!up) return PW_ERR_NOMEM;
    for (v = 0; v < nv; v++) up[v] = -1;
    for (t = 0; t < nt; t++)
        for (k = 0; k < 3; k++) up[tri[3 * t + k]] = tri[3 * t + k];
    for (t = 0; t < nt; t++)
        for (k = 1; k < 3; k++) {
            int x = pw__st_root(up, tri[3 * t]), y = pw__st_root(up, tri[3 * t + k]);
            if (x != y) up[x > y ? x : y] = x < y ? x : y;
        }
    for (v = 0; v < nv; v++) up[v] = up[v] < 0 ? -1 : pw__st_root(up, v);
    for (*nc = 0, t = 0; t < nt; t++) { /* roots relabelled -2 - component */
        int r = up[tri[3 * t]];
        if (r >= 0 && up[r] >= 0) up[r] = -2 - (*nc)++;
        comp[t] = r >= 0 ? -2 - up[r] : -2 - up[tri[3 * t]];
    }
    pw_free(a, up);
    return PW_OK;
}

/* ---- fragments (graded lattice) ----
 * Where a part thins below the smallest cell (the tip of a spike), the
 * stencils can leave bits of it cut off from the rest. Each piece is given
 * the surface component of the triangle nearest to one of its boundary
 * vertices; every component keeps its largest piece (by volume) and the
 * other pieces are dropped, so that the pieces are those the surface
 * encloses. */
PW__DEF int pw__st_drop_fragments(pw__st *st)
{
    pw_tetmesh m;
    size_t nt = st->notet, i, kept = 0;
    int *nb = (int *)pw_alloc_array(st->a, 4 * nt + 1, sizeof(int), "tetrahedron neighbours", st->e);
    int *up = (int *)pw_alloc_array(st->a, nt + 1, sizeof(int), "piece labels", st->e);
    int *comp = (int *)pw_alloc_array(st->a, (size_t)st->s.nt + 1, sizeof(int), "surface components", st->e);
    int *pc = (int *)pw_alloc_array(st->a, nt + 1, sizeof(int), "piece components", st->e);
    double *vol = (double *)pw_calloc_array(st->a, nt + 1, sizeof(double), "piece volumes", st->e);
    int *best = NULL, *to = NULL, r = PW_OK, npieces = 0, nc = 0, k, v;
    m.nv = (int)st->nopos;
    m.pos = st->opos;
    m.nt = (int)nt;
    m.tet = st->otet;
    if (!nb || !up || !comp || !pc || !vol) r = PW_ERR_NOMEM;
    if (r == PW_OK) r = pw_tetmesh_neighbors(st->a, &m, nb, st->e);
    if (r == PW_OK && (npieces = pw__st_piece_labels(&m, nb, up)) > 1) {
        pw_stuff_tris surf = pw_stuff_tris_of(NULL, st->s.nv, st->s.tri, st->s.nt); /* positions not needed */
        r = pw__st_components(st->a, &surf, comp, &nc, st->e);
        best = (int *)pw_alloc_array(st->a, (size_t)nc + 1, sizeof(int), "component pieces", st->e);
        to = (int *)pw_alloc_array(st->a, (size_t)m.nv + 1, sizeof(int), "vertex renumbering", st->e);
        if (r == PW_OK && (!best || !to)) r = PW_ERR_NOMEM;
    }
    if (r == PW_OK && npieces > 1) {
        for (i = 0; i < nt; i++) pc[i] = -1;
        for (k = 0; k < nc; k++) best[k] = -1;
        for (i = 0; i < nt; i++) {
            const int *c = st->otet + 4 * i;
            vol[up[i]] += pw_tet_volume6(&m, (int)i);
            for (k = 0; k < 4 && pc[up[i]] < 0; k++)
                if (st->osurf[c[k]]) {
                    double p[3], x[3];
                    int t = 0, j;
                    for (j = 0; j < 3; j++) p[j] = st->opos[3 * (size_t)c[k] + j];
                    pw__st_closest(&st->s, p, x, &t);
                    pc[up[i]] = comp[t];
                }
        }
        for (i = 0; i < nt; i++)
            if (up[i] == (int)i && pc[i] >= 0 && (best[pc[i]] < 0 || vol[i] > vol[best[pc[i]]])) best[pc[i]] = (int)i;
        for (v = 0; v < m.nv; v++) to[v] = -1;
        for (i = 0; i < nt; i++) {
            if (pc[up[i]] >= 0 && best[pc[up[i]]] != up[i]) {
                st->dropped += up[i] == (int)i;
                continue;
            }
            memmove(st->otet + 4 * kept++, st->otet + 4 * i, 4 * sizeof(int));
            for (k = 0; k < 4; k++) to[st->otet[4 * (kept - 1) + k]] = 0;
        }
        for (v = 0, k = 0; v < m.nv; v++) /* the vertices left, in order */
            if (to[v] == 0) {
                to[v] = k;
                memmove(st->opos + 3 * (size_t)k, st->opos + 3 * (size_t)v, 3 * sizeof(float));
                st->osurf[k++] = st->osurf[v];
            }
        for (i = 0; i < 4 * kept; i++) st->otet[i] = to[st->otet[i]];
        st->notet = kept;
        st->nopos = (size_t)k;
    }
    pw_free(st->a, nb);
    pw_free(st->a, up);
    pw_free(st->a, comp);
    pw_free(st->a, pc);
    pw_free(st->a, vol);
    pw_free(st->a, best);
    pw_free(st->a, to);
    return r;
}

/* ---- smoothing the worst tetrahedra (graded lattice) ----
 * The stencils of the graded lattice have no proven bound, so the
 * vertices of tetrahedra whose dihedral angles leave [GOAL, 180 - GOAL]
 * move, one at a time in index order, to whichever of a few points along
 * the way to the centre of their neighbours (surface vertices: of their
 * surface neighbours, then onto the nearest point of the surface, so that
 * the boundary stays on it) makes the worst angle of their tetrahedra
 * better, never creating an inverted one. */
#define PW__ST_GOAL 0.96592582628906829 /* cos 15 degrees */

/* The largest |cos| of a dihedral angle over the tetrahedra of v with v
 * at x (2: one of them is not positive); the worst tetrahedron to
 * *worst_tet, which on entry names one to look at first (-1: none). Stops
 * early at `limit` or above (the value returned is then at least limit):
 * looking first at the tetrahedron that was the worst, most candidates
 * that do no better stop there. */
PW__DEF double pw__st_star_worst(const pw__st *st, const pw_tetrings *g, int v, const float *x, double limit,
                                 int *worst_tet)
{
    double worst = 0.0, p[4][3], clo, chi, u[3], w[3], z[3], n[3];
    int i, k, j, first = *worst_tet;
    for (i = g->sstart[v] - 1; i < g->sstart[v + 1]; i++) {
        int t = i < g->sstart[v] ? first : g->star[i];
        const int *c;
        if (t < 0 || (i >= g->sstart[v] && t == first)) continue;
        c = st->otet + 4 * (size_t)t;
        for (k = 0; k < 4; k++)
            for (j = 0; j < 3; j++) p[k][j] = c[k] == v ? x[j] : st->opos[3 * (size_t)c[k] + j];
        for (j = 0; j < 3; j++) {
            u[j] = p[1][j] - p[0][j];
            w[j] = p[2][j] - p[0][j];
            z[j] = p[3][j] - p[0][j];
        }
        pw_cross3(u, w, n);
        if (!(pw_dot3(n, z) > 0.0)) return 2.0;
        pw_tet_cosines((const double(*)[3])p, &clo, &chi);
        clo = clo > -chi ? clo : -chi;
        if (clo > worst) *worst_tet = t;
        worst = clo > worst ? clo : worst;
        if (worst >= limit) break;
    }
    return worst;
}

/* The unit normal of the face of tetrahedron t opposite v, towards v, and
 * the face's mean edge length. */
PW__DEF double pw__st_away(const pw__st *st, int t, int v, double *n)
{
    const int *c = st->otet + 4 * (size_t)t;
    double f[3][3], u[3], w[3], len = 0.0, pv[3];
    int k, j, m = 0;
    for (k = 0; k < 4; k++)
        for (j = 0; j < 3; j++) {
            if (c[k] == v) pv[j] = st->opos[3 * (size_t)v + j];
            else f[m][j] = st->opos[3 * (size_t)c[k] + j];
            m += c[k] != v && j == 2;
        }
    for (j = 0; j < 3; j++) {
        u[j] = f[1][j] - f[0][j];
        w[j] = f[2][j] - f[0][j];
        pv[j] -= f[0][j];
    }
    pw_cross3(u, w, n);
    pw_norm3(n);
    if (pw_dot3(n, pv) < 0.0)
        for (j = 0; j < 3; j++) n[j] = -n[j];
    for (k = 0; k < 3; k++) len += pw_dist3(f[k], f[(k + 1) % 3]) / 3.0;
    return len;
}

/* Tries moving v; returns 1 if it moved. The candidates: steps towards the
 * centre of its neighbours (surface vertices: of their surface
 * neighbours), steps away from the face opposite v in its worst
 * tetrahedron, and steps along the six axis directions (0.05 and 0.15 of
 * the mean edge at v); a surface vertex's candidates are then put on the
 * surface. */
PW__DEF int pw__st_smooth_vertex(pw__st *st, const pw_tetrings *g, int v)
{
    static const double steps[6] = {1.0, 0.5, 0.25, 0.1, 0.2, 0.35};
    float *pv = st->opos + 3 * (size_t)v, x[3], best[3];
    double c[3] = {0.0, 0.0, 0.0}, y[3], q[3], nrm[3], len, mean = 0.0, bq, now;
    int i, k, n = 0, s, wt = -1, ct;
    now = bq = pw__st_star_worst(st, g, v, pv, 2.0, &wt);
    if (now <= PW__ST_GOAL || wt < 0) return 0;
    for (i = g->start[v]; i < g->start[v + 1]; i++) {
        int u = g->adj[i];
        for (k = 0; k < 3; k++) y[k] = st->opos[3 * (size_t)u + k] - pv[k];
        mean += sqrt(pw_dot3(y, y)) / (g->start[v + 1] - g->start[v]);
        if (st->osurf[v] && !st->osurf[u]) continue;
        for (k = 0; k < 3; k++) c[k] += st->opos[3 * (size_t)u + k];
        n++;
    }
    len = pw__st_away(st, wt, v, nrm);
    for (s = n ? 0 : 3; s < 18; s++) {
        double w;
        for (k = 0; k < 3; k++) {
            if (s < 3) y[k] = pv[k] + steps[s] * (c[k] / n - pv[k]);
            else if (s < 6) y[k] = pv[k] + steps[s] * len * nrm[k];
            else y[k] = pv[k] + (k == (s - 6) % 3 ? (s < 12 ? 0.05 : 0.15) * mean * ((s & 1) ? -1.0 : 1.0) : 0.0);
        }
        if (st->osurf[v]) {
            pw__st_closest(&st->s, y, q, NULL);
            memcpy(y, q, sizeof q);
        }
        for (k = 0; k < 3; k++) x[k] = (float)y[k];
        ct = wt;
        if ((w = pw__st_star_worst(st, g, v, x, bq, &ct)) < bq) { /* (no better: stops at bq) */
            bq = w;
            memcpy(best, x, sizeof x);
        }
    }
    if (bq >= now) return 0;
    memcpy(pv, best, sizeof best);
    return 1;
}

PW__DEF int pw__st_smooth(pw__st *st)
{
    pw_tetmesh m;
    pw_tetrings g;
    unsigned char *bad;
    int r, pass, v, i, k, j, moved = 1;
    m.nv = (int)st->nopos;
    m.pos = st->opos;
    m.nt = (int)st->notet;
    m.tet = st->otet;
    bad = (unsigned char *)pw_calloc_array(st->a, (size_t)m.nv + 1, 1, "vertex marks", st->e);
    if (!bad) return PW_ERR_NOMEM;
    if ((r = pw_tetmesh_rings(st->a, &m, &g, st->e))) {
        pw_free(st->a, bad);
        return r;
    }
    for (i = 0; i < m.nt; i++) { /* the corners of the tetrahedra outside the goal */
        double p[4][3], clo, chi;
        const int *c = m.tet + 4 * (size_t)i;
        if (!st->osurf[c[0]] && !st->osurf[c[1]] && !st->osurf[c[2]] && !st->osurf[c[3]])
            continue; /* a whole lattice tetrahedron: 45..120 degrees */
        for (k = 0; k < 4; k++)
            for (j = 0; j < 3; j++) p[k][j] = st->opos[3 * (size_t)m.tet[4 * i + k] + j];
        pw_tet_cosines((const double(*)[3])p, &clo, &chi);
        if (clo > PW__ST_GOAL || -chi > PW__ST_GOAL)
            for (k = 0; k < 4; k++) bad[m.tet[4 * i + k]] = 1;
    }
    for (pass = 0; pass < 8 && moved; pass++)
        for (v = 0, moved = 0; v < m.nv; v++)
            if (bad[v] && pw__st_smooth_vertex(st, &g, v)) { /* its neighbours may do better now */
                moved++;
                for (i = g.start[v]; i < g.start[v + 1]; i++) bad[g.adj[i]] = 1;
            } else bad[v] = 0;
    pw_tetrings_free(st->a, &g);
    pw_free(st->a, bad);
    return PW_OK;
}

PW__DEF void pw__st_free(pw__st *st)
{
    pw__st_surf_free(st->a, &st->s);
    pw_free(st->a, st->tri);
    pw_free(st->a, st->map);
    pw_free(st->a, st->side);
    pw_free(st->a, st->busy);
    pw_free(st->a, st->warp);
    pw_free(st->a, st->id);
    pw_free(st->a, st->cut);
    pw_free(st->a, st->opos);
    pw_free(st->a, st->otet);
    pw_free(st->a, st->vp);
    pw_free(st->a, st->osurf);
    pw_free(st->a, st->tbusy);
    pw_free(st->a, st->eoff);
    pw_free(st->a, st->eadj);
    pw_free(st->a, st->vtoff);
    pw_free(st->a, st->vtadj);
    pw_free(st->a, st->scratch);
    pw_free(st->a, st->pool);
    pw_free(st->a, st->memo);
    pw_free(st->a, st->tnorm);
    pw_free(st->a, st->tip);
    pw_free(st->a, st->tipr);
    pw_free(st->a, st->tbox);
    pw_bisect_free(&st->bs);
    memset(st, 0, sizeof *st);
}

/* Triangles with a repeated corner index, dropped before the closedness
 * check: their two real edges are one edge traversed both ways, so the
 * neighbours across them become twins. st->tri (3 * *n ints) and st->map
 * (the caller's index of each) are allocated here, with room for 3 nt more
 * triangles (the fans closing holes: fewer than the boundary edges). */
PW__DEF int pw__st_drop_repeats(pw__st *st, const int *tri, int nt, int *n)
{
    int t, k;
    st->tri =
        (int *)pw_alloc_array(st->a, (size_t)nt * 12 + 3, sizeof(int), "triangles", st->e); /* room for hole fans */
    st->map = (int *)pw_alloc_array(st->a, (size_t)nt * 4 + 1, sizeof(int), "triangle map", st->e);
    if (!st->tri || !st->map) return PW_ERR_NOMEM;
    for (*n = 0, t = 0; t < nt; t++) {
        const int *c = tri + 3 * t;
        if (c[0] == c[1] || c[1] == c[2] || c[2] == c[0]) continue;
        for (k = 0; k < 3; k++) st->tri[3 * *n + k] = c[k];
        st->map[(*n)++] = t;
    }
    return PW_OK;
}

/* Drops the zero-area triangles (exactly collinear corners) from
 * st->tri[0..*n) in place, with their st->map entries, and renumbers twin
 * (half-edge 3t+k) to the kept triangles, -1 across a dropped one: for the
 * winding number a dropped triangle is a cap of zero solid angle, so the
 * caps stay exact. Dropped triangles of the caller's (map >= 0) are added
 * to *count. */
PW__DEF int pw__st_drop_flat(pw__st *st, const float *pos, int *twin, int *n, int *count)
{
    int *tri = st->tri, *map = st->map, t, k, m = 0;
    int *to = (int *)pw_alloc_array(st->a, (size_t)*n + 1, sizeof(int), "triangle renumbering", st->e);
    double p[3][3];
    if (!to) return PW_ERR_NOMEM;
    for (t = 0; t < *n; t++) {
        for (k = 0; k < 9; k++) p[k / 3][k % 3] = pos[3 * tri[3 * t + k / 3] + k % 3];
        to[t] = pw__st_proj_axis(p[0], p[1], p[2]) < 0 ? -1 : m++;
        *count += to[t] < 0 && map[t] >= 0;
    }
    for (t = 0; t < *n; t++) {
        if (to[t] < 0) continue;
        for (k = 0; k < 3; k++) {
            int tw = twin[3 * t + k];
            tri[3 * to[t] + k] = tri[3 * t + k];
            twin[3 * to[t] + k] = to[tw / 3] < 0 ? -1 : 3 * to[tw / 3] + tw % 3;
        }
        map[to[t]] = map[t];
    }
    *n = m;
    pw_free(st->a, to);
    return PW_OK;
}

/* Appends the hole-closing triangles fan[0 .. 3 nfan) to st->tri (which
 * has room for them), with caller index -1. */
PW__DEF void pw__st_add_fans(pw__st *st, const int *fan, int nfan, int *n)
{
    int i;
    memcpy(st->tri + 3 * *n, fan, 3 * (size_t)nfan * sizeof(int));
    for (i = 0; i < nfan; i++) st->map[*n + i] = -1;
    *n += nfan;
}

/* The surface the fill uses: the caller's triangles without the zero-area
 * ones (counted in info), closed and consistently oriented, with its
 * hierarchy and winding-number caps. st->tri and st->map own the arrays. */
PW__DEF int pw__st_surface(pw__st *st, const pw_stuff_tris *m, double max_hole, pw_stuff_info *info)
{
    pw__st_closure cl;
    pw_stuff_tris used; /* the triangles kept so far, in st->tri */
    int n = 0, r;
    memset(&cl, 0, sizeof cl);
    r = pw__st_drop_repeats(st, m->tri, m->nt, &n);
    info->skipped_triangles = m->nt - n;
    used = pw_stuff_tris_of(m->pos, m->nv, st->tri, n);
    if (r == PW_OK) {
        r = pw__st_check_closed(st->a, &used, max_hole * pw__st_diag(m->pos, st->tri, n), &cl, st->e);
        info->closed_holes = cl.nholes;
    }
    if (r == PW_OK && cl.fan) {
        pw__st_add_fans(st, cl.fan, cl.nfan, &n);
        pw_free(st->a, cl.fan);
        used.nt = n;
        r = pw__st_check_closed(st->a, &used, -1.0, &cl, st->e);
    }
    if (r == PW_OK) r = pw__st_drop_flat(st, m->pos, cl.twin, &n, &info->skipped_triangles);
    if (r == PW_OK && n == 0)
        r = pw_fail(st->e, PW_ERR_DEGENERATE, "surface encloses no volume (every triangle is flat)");
    if (r == PW_OK) {
        pw_stuff_tris used = pw_stuff_tris_of(m->pos, m->nv, st->tri, n);
        r = pw__st_surf_init(st->a, &used, &st->s, st->e);
    }
    if (r == PW_OK) r = pw__st_caps(st->a, &st->s, cl.twin, st->e);
    pw_free(st->a, cl.twin);
    return r;
}

/* The largest hole perimeter closed, as a fraction of the diagonal. */
PW__DEF double pw__st_max_hole(const pw_stuff_options *o) { return !o || o->max_hole == 0.0 ? 0.05 : o->max_hole; }

/* Tetrahedralizes the inside of a closed, oriented triangle surface (in:
 * its triangles counter-clockwise seen from outside; a surface facing
 * inward throughout is used reversed) into *out: positively oriented
 * tetrahedra (tetmesh.h), freed with pw_tetmesh_free(a, out). o may be NULL
 * (defaults); p may be NULL, else it sees the stages "surface checks",
 * "lattice sides", "cut points" and "stencils" and may cancel. Same inputs,
 * same bytes out. On failure *out is empty and e names the problem:
 *   PW_ERR_INVALID     NULL arrays, a non-finite coordinate, an index out of
 *                      range, a negative or non-finite option
 *   PW_ERR_DEGENERATE  no triangles, no enclosed volume, a cell so coarse
 *                      that no lattice vertex is inside
 *   PW_ERR_TOPOLOGY    not closed (the holes counted, the largest placed),
 *                      inconsistent orientation, a non-manifold edge or
 *                      vertex, two triangles crossing (only when strict)
 *   PW_ERR_LIMIT       a lattice above PW_MAX_STUFF_LATTICE vertices (graded:
 *                      tetrahedra; a larger fit or cell needs fewer), more
 *                      than PW_MAX_MESH_ELEMENTS vertices, triangles or
 *                      tetrahedra
 *   PW_ERR_NOMEM, PW_ERR_CANCELLED */
PW__DEF int pw_stuff_tetrahedralize(const pw_alloc *a, const pw_stuff_tris *in, const pw_stuff_options *o,
                                    const pw_progress *p, pw_tetmesh *out, pw_err *e)
{
    pw__st st;
    pw_stuff_info scratch, *info = o && o->info ? o->info : &scratch;
    int r;
    memset(info, 0, sizeof *info);
    info->first_pair[0] = info->first_pair[1] = -1;
    if (!out) return pw_fail(e, PW_ERR_INVALID, "tetrahedralize: no output mesh");
    memset(out, 0, sizeof *out);
    memset(&st, 0, sizeof st);
    st.a = a;
    st.prog = p;
    st.e = e;
    r = in ? pw__st_check_values(in->pos, in->nv, in->tri, in->nt, e)
           : pw_fail(e, PW_ERR_INVALID, "tetrahedralize: NULL positions or triangles");
    if (r == PW_OK && o && !pw_is_finite(o->max_hole))
        r = pw_fail(e, PW_ERR_INVALID, "tetrahedralize: max_hole %g is not finite", o->max_hole);
    if (r == PW_OK && o && !(o->fit >= 0.0 && o->fit <= 0.1))
        r = pw_fail(e, PW_ERR_INVALID, "tetrahedralize: fit %g is not in [0, 0.1] (a fraction of the diagonal)",
                    o->fit);
    if (r == PW_OK) r = pw_report(p, 0.0f, "surface checks", e);
    if (r == PW_OK) r = pw__st_surface(&st, in, pw__st_max_hole(o), info);
    if (r == PW_OK) r = pw__st_check_geometry(&st.s, st.map, o && o->strict, info, e);
    st.unite = info->crossing_pairs > 0;
    if (o && o->uniform) {
        if (r == PW_OK) r = pw__st_lattice(&st, o);
        if (r == PW_OK) r = pw__st_sides(&st);
        if (r == PW_OK) r = pw__st_cuts(&st);
        if (r == PW_OK) r = pw__st_warp(&st);
        if (r == PW_OK) r = pw__st_stencils(&st);
    } else {
        if (r == PW_OK) r = pw__st_glattice(&st, o, o && o->fit > 0.0 ? o->fit : 0.0025);
        if (r == PW_OK) r = pw__st_sides(&st);
        if (r == PW_OK) r = pw__st_cuts(&st);
        if (r == PW_OK) r = pw__st_warp(&st);
        if (r == PW_OK) r = pw__st_gstencils(&st);
        if (r == PW_OK && st.notet) r = pw__st_drop_fragments(&st);
        if (r == PW_OK && st.notet) r = pw__st_smooth(&st);
        info->fragments = st.dropped;
    }
    if (r == PW_OK && st.notet == 0)
        r = pw_fail(e, PW_ERR_DEGENERATE,
                    "tetrahedralize: no lattice vertex of spacing %g is inside the surface; "
                    "use a smaller cell",
                    st.h);
    if (r == PW_OK) r = pw_report(p, 1.0f, "stencils", e);
    if (r == PW_OK) {
        out->nv = (int)st.nopos;
        out->pos = st.opos;
        out->nt = (int)st.notet;
        out->tet = st.otet;
        st.opos = NULL;
        st.otet = NULL;
    }
    pw__st_free(&st);
    return r;
}

/* ---- the boundary of a tetrahedral mesh, and how well it fits ---- */

typedef struct pw__stface {
    int k[3]; /* corners, sorted */
    int odd;  /* the sort was an odd permutation of the outward order */
    int t, f; /* tetrahedron, face (opposite corner) */
} pw__stface;

PW__DEF int pw__st_face_cmp(const void *x, const void *y)
{
    const pw__stface *a = (const pw__stface *)x, *b = (const pw__stface *)y;
    int k;
    for (k = 0; k < 3; k++)
        if (a->k[k] != b->k[k]) return a->k[k] < b->k[k] ? -1 : 1;
    if (a->t != b->t) return a->t < b->t ? -1 : 1;
    return (a->f > b->f) - (a->f < b->f);
}

PW__DEF void pw__st_face_key(const pw_tetmesh *m, int t, int f, pw__stface *x)
{
    int c[3], i, j;
    pw_tet_face(f, c);
    for (i = 0; i < 3; i++) x->k[i] = m->tet[4 * t + c[i]];
    x->odd = 0;
    x->t = t;
    x->f = f;
    for (i = 0; i < 3; i++)
        for (j = 0; j + 1 < 3 - i; j++)
            if (x->k[j] > x->k[j + 1]) {
                int s = x->k[j];
                x->k[j] = x->k[j + 1];
                x->k[j + 1] = s;
                x->odd ^= 1;
            }
}

/* Faces that appear once in sorted order fl[0..n) go to tri (outward);
 * faces in two tetrahedra must be oppositely oriented. */
PW__DEF int pw__st_face_runs(const pw_tetmesh *m, const pw__stface *fl, size_t n, int *tri, int *nb, pw_err *e)
{
    size_t i = 0, j;
    int c[3], k;
    *nb = 0;
    while (i < n) {
        for (j = i + 1; j < n && !memcmp(fl[j].k, fl[i].k, sizeof fl[i].k); j++) continue;
        if (j - i > 2 || (j - i == 2 && fl[i].odd == fl[i + 1].odd))
            return pw_fail(e, PW_ERR_TOPOLOGY, "tetrahedra %d and %d overlap at face v%d-v%d-v%d", fl[i].t, fl[i + 1].t,
                           fl[i].k[0], fl[i].k[1], fl[i].k[2]);
        if (j - i == 1 && tri) {
            pw_tet_face(fl[i].f, c);
            for (k = 0; k < 3; k++) tri[3 * *nb + k] = m->tet[4 * fl[i].t + c[k]];
        }
        if (j - i == 1) ++*nb;
        i = j;
    }
    return PW_OK;
}

/* The boundary triangles of a tetrahedral mesh (faces of one tetrahedron
 * only), outward, in order of their sorted corners: *tri (3 * *ntri, free
 * with pw_free). PW_ERR_TOPOLOGY when the mesh does not conform: a face in
 * more than two tetrahedra, or in two on the same side. */
PW__DEF int pw_stuff_boundary(const pw_alloc *a, const pw_tetmesh *m, int **tri, int *ntri, pw_err *e)
{
    size_t n = (size_t)m->nt * 4, i;
    pw__stface *fl;
    int r, nb;
    *tri = NULL;
    *ntri = 0;
    fl = (pw__stface *)pw_alloc_array(a, n + 1, sizeof *fl, "tetrahedron faces", e);
    if (!fl) return PW_ERR_NOMEM;
    for (i = 0; i < n; i++) pw__st_face_key(m, (int)(i / 4), (int)(i % 4), fl + i);
    qsort(fl, n, sizeof *fl, pw__st_face_cmp);
    r = pw__st_face_runs(m, fl, n, NULL, &nb, e);
    if (r == PW_OK && !(*tri = (int *)pw_alloc_array(a, (size_t)nb * 3 + 1, sizeof(int), "boundary triangles", e)))
        r = PW_ERR_NOMEM;
    if (r == PW_OK) r = pw__st_face_runs(m, fl, n, *tri, ntri, e);
    pw_free(a, fl);
    if (r != PW_OK) {
        pw_free(a, *tri);
        *tri = NULL;
        *ntri = 0;
    }
    return r;
}

/* How well the boundary of a tetrahedral mesh follows a surface. The
 * sampled figures are the two-sided surface distance: area-weighted dense
 * samples on one surface, exact point-triangle distance to the other. */
typedef struct pw_stuff_fit {
    double to_surface_max, to_surface_mean;     /* boundary vertices of the tetrahedra -> surface */
    double from_surface_max, from_surface_mean; /* surface vertices -> boundary of the tetrahedra */
    double to_max, to_p99;     /* samples of the tetrahedra's boundary -> surface: largest, 99th percentile */
    double from_max, from_p99; /* samples of the surface -> boundary of the tetrahedra */
    double diag;               /* the surface's bounding-box diagonal, for relative figures */
    int boundary_triangles;
    int pieces;         /* connected components of the tetrahedra (joined by shared faces) */
    int surface_pieces; /* pieces of the solid the surface encloses (pw_stuff_surface_pieces), -1: not counted */
    int samples;        /* samples taken on each side */
} pw_stuff_fit;

/* Signed volume of component c and the winding number of the other
 * components at a corner of its first triangle (solid angles summed, Van
 * Oosterom & Strackee). */
PW__DEF void pw__st_weigh(const pw_stuff_tris *m, const int *comp, int c, double *vol, double *w)
{
    const float *pos = m->pos;
    const int *tri = m->tri;
    int nt = m->nt;
    double p[3] = {0, 0, 0}, q[3][3];
    int t, k, first = 1;
    *vol = *w = 0.0;
    for (t = 0; t < nt; t++) {
        for (k = 0; k < 9; k++) q[k / 3][k % 3] = pos[3 * tri[3 * t + k / 3] + k % 3];
        if (comp[t] == c && first)
            for (first = 0, k = 0; k < 3; k++) p[k] = q[0][k];
        if (comp[t] == c)
            *vol +=
                (q[0][0] * (q[1][1] * q[2][2] - q[1][2] * q[2][1]) - q[0][1] * (q[1][0] * q[2][2] - q[1][2] * q[2][0]) +
                 q[0][2] * (q[1][0] * q[2][1] - q[1][1] * q[2][0])) /
                6.0;
    }
    for (t = 0; t < nt; t++) {
        if (comp[t] == c) continue;
        for (k = 0; k < 9; k++) q[k / 3][k % 3] = pos[3 * tri[3 * t + k / 3] + k % 3];
        *w += pw__st_solid_angle(p, q[0], q[1], q[2]) / (4.0 * 3.14159265358979323846);
    }
}

/* Pieces of the solid that a closed surface without crossings encloses:
 * its components that face outward (as the whole surface does) and lie
 * outside the others (their winding number 0 there). A cavity faces
 * inward; a shell inside a cavity is at winding number 0 again. Crossing
 * components are counted apart (the solid may have fewer pieces). -1 when
 * the count would cost more than 5e7 solid angles. */
PW__DEF int pw_stuff_surface_pieces(const pw_alloc *a, const pw_stuff_tris *m, int *pieces, pw_err *e)
{
    int nt = m->nt;
    int *comp = (int *)pw_alloc_array(a, (size_t)nt + 1, sizeof(int), "surface components", e), nc = 0, c, r;
    double total = 0.0, *vol, *w;
    *pieces = -1;
    if (!comp) return PW_ERR_NOMEM;
    r = pw__st_components(a, m, comp, &nc, e);
    vol = (double *)pw_alloc_array(a, 2 * (size_t)nc + 2, sizeof(double), "surface components", e);
    if (r == PW_OK && !vol) r = PW_ERR_NOMEM;
    if (r == PW_OK && (double)nc * nt <= 5e7) {
        w = vol + nc;
        for (c = 0; c < nc; c++) {
            pw__st_weigh(m, comp, c, vol + c, w + c);
            total += vol[c];
        }
        for (*pieces = 0, c = 0; c < nc; c++) *pieces += (total < 0.0 ? -vol[c] : vol[c]) > 0.0 && fabs(w[c]) < 0.5;
    }
    pw_free(a, vol);
    pw_free(a, comp);
    return r;
}

/* A distance sample and its area weight. */
typedef struct pw__stsample {
    double d, w;
} pw__stsample;

/* One side of the fit: distances from the triangles `from` to the surface
 * `to`, and what they measured. */
typedef struct pw__st_dist {
    pw_stuff_tris from;
    const pw__stsurf *to;
    double vmax, vmean; /* pw__st_vertex_dist: over the vertices the triangles use */
    double smax, p99;   /* pw__st_sampled_dist: over area samples (p99: area-weighted 99th percentile) */
    int samples;
} pw__st_dist;

PW__DEF int pw__st_sample_cmp(const void *x, const void *y)
{
    double a = ((const pw__stsample *)x)->d, b = ((const pw__stsample *)y)->d;
    return (a > b) - (a < b);
}

/* Sub-triangle side count for triangle t of (pos, tri) so that its pieces
 * have about area a0; *area gets the triangle's area. */
PW__DEF int pw__st_sample_split(const float *pos, const int *tri, int t, double a0, double *area)
{
    double u[3], v[3], n[3], k;
    int i;
    for (i = 0; i < 3; i++) {
        u[i] = (double)pos[3 * tri[3 * t + 1] + i] - pos[3 * tri[3 * t] + i];
        v[i] = (double)pos[3 * tri[3 * t + 2] + i] - pos[3 * tri[3 * t] + i];
    }
    pw_cross3(u, v, n);
    *area = 0.5 * sqrt(pw_dot3(n, n));
    k = ceil(sqrt(*area / a0));
    return k < 1.0 ? 1 : k > 256.0 ? 256 : (int)k;
}

/* The distance from barycentric point (l1, l2) of triangle t of d->from to
 * d->to, recorded with weight w. */
PW__DEF void pw__st_sample_at(const pw__st_dist *d, int t, double l1, double l2, double w, pw__stsample *out)
{
    const float *pos = d->from.pos;
    const int *c = d->from.tri + 3 * t;
    double p[3], x[3];
    int i;
    for (i = 0; i < 3; i++)
        p[i] = (1.0 - l1 - l2) * pos[3 * c[0] + i] + l1 * pos[3 * c[1] + i] + l2 * pos[3 * c[2] + i];
    out->d = sqrt(pw__st_closest(d->to, p, x, NULL));
    out->w = w;
}

/* Samples of triangle t of d->from split into k*k congruent pieces: their
 * centroids (weight: the piece's area) and the corners (weight 0, for the
 * maximum). */
PW__DEF size_t pw__st_sample_tri(const pw__st_dist *d, int t, int k, double area, pw__stsample *out)
{
    double w = area / ((double)k * k);
    size_t n = 0;
    int i, j;
    for (i = 0; i < k; i++)
        for (j = 0; i + j < k; j++) {
            pw__st_sample_at(d, t, (i + 1.0 / 3.0) / k, (j + 1.0 / 3.0) / k, w, out + n++);
            if (i + j + 2 <= k) pw__st_sample_at(d, t, (i + 2.0 / 3.0) / k, (j + 2.0 / 3.0) / k, w, out + n++);
        }
    pw__st_sample_at(d, t, 0.0, 0.0, 0.0, out + n++);
    pw__st_sample_at(d, t, 1.0, 0.0, 0.0, out + n++);
    pw__st_sample_at(d, t, 0.0, 1.0, 0.0, out + n++);
    return n;
}

/* Largest (d->smax) and area-weighted 99th-percentile (d->p99) distance
 * from about `want` area-weighted samples on d->from to d->to; their count
 * in d->samples. */
PW__DEF int pw__st_sampled_dist(const pw_alloc *a, pw__st_dist *d, int want, pw_err *e)
{
    const float *pos = d->from.pos;
    const int *tri = d->from.tri;
    int nt = d->from.nt, t;
    double total = 0.0, area, a0, acc = 0.0;
    size_t n = 0, i;
    pw__stsample *sm;
    for (t = 0; t < nt; t++) {
        pw__st_sample_split(pos, tri, t, 1e300, &area);
        total += area;
    }
    a0 = total > 0.0 ? total / (want > 0 ? want : 1) : 1.0;
    for (t = 0; t < nt; t++) {
        int k = pw__st_sample_split(pos, tri, t, a0, &area);
        n += (size_t)k * k + 3;
    }
    if (!(sm = (pw__stsample *)pw_alloc_array(a, n + 1, sizeof *sm, "fit samples", e))) return PW_ERR_NOMEM;
    for (n = 0, t = 0; t < nt; t++) {
        int k = pw__st_sample_split(pos, tri, t, a0, &area);
        n += pw__st_sample_tri(d, t, k, area, sm + n);
    }
    qsort(sm, n, sizeof *sm, pw__st_sample_cmp);
    d->smax = n ? sm[n - 1].d : 0.0;
    d->p99 = d->smax;
    d->samples = (int)n;
    for (i = 0; i < n; i++)
        if ((acc += sm[i].w) >= 0.99 * total) {
            d->p99 = sm[i].d;
            break;
        }
    pw_free(a, sm);
    return PW_OK;
}

/* Largest (d->vmax) and mean (d->vmean) distance from the vertices used by
 * the triangles d->from to d->to. */
PW__DEF int pw__st_vertex_dist(const pw_alloc *a, pw__st_dist *d, pw_err *e)
{
    const pw_stuff_tris *m = &d->from;
    unsigned char *used = (unsigned char *)pw_calloc_array(a, (size_t)m->nv + 1, 1, "used vertices", e);
    double x[3], p[3], sum = 0.0, dist;
    int v, k, n = 0;
    if (!used) return PW_ERR_NOMEM;
    for (k = 0; k < 3 * m->nt; k++) used[m->tri[k]] = 1;
    d->vmax = 0.0;
    for (v = 0; v < m->nv; v++) {
        if (!used[v]) continue;
        for (k = 0; k < 3; k++) p[k] = m->pos[3 * v + k];
        dist = sqrt(pw__st_closest(d->to, p, x, NULL));
        sum += dist;
        n++;
        if (dist > d->vmax) d->vmax = dist;
    }
    d->vmean = n ? sum / n : 0.0;
    pw_free(a, used);
    return PW_OK;
}

/* The piece count of m. */
PW__DEF int pw__st_pieces_of(const pw_alloc *a, const pw_tetmesh *m, int *pieces, pw_err *e)
{
    int *nb = (int *)pw_alloc_array(a, (size_t)m->nt * 4 + 1, sizeof(int), "face adjacency", e), r;
    if (!nb) return PW_ERR_NOMEM;
    r = pw_tetmesh_neighbors(a, m, nb, e);
    if (r == PW_OK && (*pieces = pw_tetmesh_pieces(a, m, nb, e)) < 0) r = PW_ERR_NOMEM;
    pw_free(a, nb);
    return r;
}

/* Measures how well the boundary of m matches the closed surface in:
 * distances from the boundary vertices of m to the surface and
 * from the surface's vertices to the boundary of m, the two-sided sampled
 * distance (about `samples` samples a side, 0: 100000) and the pieces of m,
 * in mesh units (divide by fit->diag for relative figures). */
PW__DEF int pw_stuff_fit_measure(const pw_alloc *a, const pw_stuff_tris *in, const pw_tetmesh *m, int samples,
                                 pw_stuff_fit *fit, pw_err *e)
{
    pw__stsurf s, b;
    pw__st_dist to, from; /* boundary of m to the surface, surface to the boundary */
    int *btri = NULL, nb = 0, r, k;
    memset(fit, 0, sizeof *fit);
    if (samples <= 0) samples = 100000;
    memset(&s, 0, sizeof s);
    memset(&b, 0, sizeof b);
    memset(&to, 0, sizeof to);
    memset(&from, 0, sizeof from);
    r = pw__st_check_values(in->pos, in->nv, in->tri, in->nt, e);
    if (r == PW_OK) r = pw_stuff_boundary(a, m, &btri, &nb, e);
    if (r == PW_OK && nb == 0) r = pw_fail(e, PW_ERR_DEGENERATE, "fit: the tetrahedral mesh has no boundary");
    to.from = pw_stuff_tris_of(m->pos, m->nv, btri, nb);
    to.to = &s;
    from.from = *in;
    from.to = &b;
    if (r == PW_OK) r = pw__st_surf_init(a, in, &s, e);
    if (r == PW_OK) r = pw__st_surf_init(a, &to.from, &b, e);
    if (r == PW_OK && (r = pw__st_vertex_dist(a, &to, e)) == PW_OK) {
        fit->to_surface_max = to.vmax;
        fit->to_surface_mean = to.vmean;
    }
    if (r == PW_OK && (r = pw__st_vertex_dist(a, &from, e)) == PW_OK) {
        fit->from_surface_max = from.vmax;
        fit->from_surface_mean = from.vmean;
    }
    if (r == PW_OK && (r = pw__st_sampled_dist(a, &to, samples, e)) == PW_OK) {
        fit->to_max = to.smax;
        fit->to_p99 = to.p99;
        fit->samples = to.samples;
    }
    if (r == PW_OK && (r = pw__st_sampled_dist(a, &from, samples, e)) == PW_OK) {
        fit->from_max = from.smax;
        fit->from_p99 = from.p99;
        fit->samples = from.samples;
    }
    if (r == PW_OK) r = pw__st_pieces_of(a, m, &fit->pieces, e);
    if (r == PW_OK) r = pw_stuff_surface_pieces(a, in, &fit->surface_pieces, e);
    for (k = 0; k < 3; k++) fit->diag += (s.hi[k] - s.lo[k]) * (s.hi[k] - s.lo[k]);
    fit->diag = sqrt(fit->diag);
    fit->boundary_triangles = nb;
    pw__st_surf_free(a, &s);
    pw__st_surf_free(a, &b);
    pw_free(a, btri);
    return r;
}

#endif /* PW__STUFFING_V1 */
