/* tetmesh: the tetrahedral mesh that lapped solid textures work on, and its
 * quality figures.
 *
 * A pw_tetmesh is nv vertices (pos, nv*3 floats) and nt tetrahedra (tet,
 * nt*4 vertex indices). Tetrahedra are positively oriented: with corners
 * a, b, c, d, (b - a) x (c - a) . (d - a) > 0, so the faces opposite each
 * corner, listed by pw_tet_face, have outward normals by the right-hand
 * rule. Readers and the built-in tetrahedralizer produce this orientation
 * (flipping tetrahedra given the other way round) and refuse degenerate
 * (zero-volume) tetrahedra.
 *
 *   pw_tetmesh_free, pw_tet_volume6, pw_tet_face, pw_tet_dihedral_range
 *   pw_tetmesh_check      indices, finite positions, orientation (flips), volume
 *   pw_tetmesh_neighbors  face adjacency; faces shared by three tetrahedra or
 *                         with the same orientation in both (overlap) refused
 *   pw_tetmesh_boundary   the boundary faces, outward, in (tet, corner) order
 *   pw_tetmesh_rings      vertex one-rings (the edge graph) and vertex stars
 *   pw_tet_gradients      gradients of the barycentric coordinates, volume
 *   pw_tet_barycentric    barycentric coordinates of a point
 *   pw_tetgrid_*          point location with a uniform grid of buckets */
#ifndef PW__TETMESH_V1
#define PW__TETMESH_V1

#include "base.h"
#include "vec.h"

typedef struct pw_tetmesh {
    int nv;     /* vertices */
    float *pos; /* nv*3 */
    int nt;     /* tetrahedra */
    int *tet;   /* nt*4, positively oriented */
} pw_tetmesh;

PW__DEF void pw_tetmesh_free(const pw_alloc *a, pw_tetmesh *m)
{
    if (!m) return;
    pw_free(a, m->pos);
    pw_free(a, m->tet);
    memset(m, 0, sizeof *m);
}

/* Six times the signed volume of tetrahedron t (positive when oriented as
 * documented above), in double precision. */
PW__DEF double pw_tet_volume6(const pw_tetmesh *m, int t)
{
    const float *p0 = m->pos + 3 * m->tet[4 * t], *p1 = m->pos + 3 * m->tet[4 * t + 1];
    const float *p2 = m->pos + 3 * m->tet[4 * t + 2], *p3 = m->pos + 3 * m->tet[4 * t + 3];
    double ax = (double)p1[0] - p0[0], ay = (double)p1[1] - p0[1], az = (double)p1[2] - p0[2];
    double bx = (double)p2[0] - p0[0], by = (double)p2[1] - p0[1], bz = (double)p2[2] - p0[2];
    double cx = (double)p3[0] - p0[0], cy = (double)p3[1] - p0[1], cz = (double)p3[2] - p0[2];
    return ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
}

/* The three corners (as indices 0..3 into the tetrahedron) of the face
 * opposite corner k, ordered so that its normal points out of the
 * tetrahedron. */
PW__DEF void pw_tet_face(int k, int out[3])
{
    static const int face[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    out[0] = face[k][0];
    out[1] = face[k][1];
    out[2] = face[k][2];
}

/* The cosines of the smallest (*clo) and largest (*chi) dihedral angle of
 * the tetrahedron with corners p[0..3] (a flat one: 1 and -1): from
 * + - * / and sqrt, so that decisions taken on them are the same on every
 * platform. */
PW__DEF void pw_tet_cosines(const double (*p)[3], double *clo, double *chi)
{
    static const int edge[6][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2}, {1, 2, 0, 3}, {1, 3, 0, 2}, {2, 3, 0, 1}};
    int k, i;
    *clo = -1.0;
    *chi = 1.0;
    for (k = 0; k < 6; k++) { /* the angle along edge (a,b) between the faces (a,b,c) and (a,b,d) */
        const double *a = p[edge[k][0]], *b = p[edge[k][1]], *c = p[edge[k][2]], *d = p[edge[k][3]];
        double u[3], v[3], w[3], n1[3], n2[3], l1, l2, cs;
        for (i = 0; i < 3; i++) {
            u[i] = b[i] - a[i];
            v[i] = c[i] - a[i];
            w[i] = d[i] - a[i];
        }
        pw_cross3(u, v, n1);
        pw_cross3(u, w, n2);
        l1 = sqrt(pw_dot3(n1, n1));
        l2 = sqrt(pw_dot3(n2, n2));
        if (l1 <= 0.0 || l2 <= 0.0) {
            *clo = 1.0;
            *chi = -1.0;
            return;
        }
        cs = pw_dot3(n1, n2) / (l1 * l2);
        cs = cs > 1.0 ? 1.0 : cs < -1.0 ? -1.0 : cs;
        *clo = cs > *clo ? cs : *clo;
        *chi = cs < *chi ? cs : *chi;
    }
}

/* The same as angles in degrees (acos from libm). */
PW__DEF void pw_tet_angles(const double (*p)[3], double *lo, double *hi)
{
    double clo, chi;
    pw_tet_cosines(p, &clo, &chi);
    *lo = acos(clo) * (180.0 / 3.14159265358979323846);
    *hi = acos(chi) * (180.0 / 3.14159265358979323846);
}

/* The smallest and largest dihedral angle, in degrees, over all
 * tetrahedra (the quality figures the lst paper and TetGen report). An
 * empty mesh gives 0 and 0. Uses acos from libm: this is a report, not a
 * result that has to be bit-identical across platforms. */
PW__DEF void pw_tet_dihedral_range(const pw_tetmesh *m, double *min_deg, double *max_deg)
{
    double lo = 180.0, hi = 0.0, p[4][3], a, b;
    int t, k, i;
    for (t = 0; t < m->nt; t++) {
        for (k = 0; k < 4; k++)
            for (i = 0; i < 3; i++) p[k][i] = m->pos[3 * m->tet[4 * t + k] + i];
        pw_tet_angles((const double(*)[3])p, &a, &b);
        lo = a < lo ? a : lo;
        hi = b > hi ? b : hi;
    }
    if (m->nt == 0) lo = hi = 0.0;
    *min_deg = lo;
    *max_deg = hi;
}

PW__DEF double pw__tet_longest_edge(const pw_tetmesh *m, int t)
{
    double best = 0.0;
    int i, j, k;
    for (i = 0; i < 4; i++)
        for (j = i + 1; j < 4; j++) {
            const float *p = m->pos + 3 * m->tet[4 * t + i], *q = m->pos + 3 * m->tet[4 * t + j];
            double d = 0.0;
            for (k = 0; k < 3; k++) d += ((double)p[k] - q[k]) * ((double)p[k] - q[k]);
            if (d > best) best = d;
        }
    return sqrt(best);
}

/* Checks a tetrahedral mesh read from a file or given by a caller: at least
 * one tetrahedron, finite positions, corner indices in range and distinct,
 * no zero-volume tetrahedron (|6V| below 1e-12 L^3, L the longest edge).
 * Negatively oriented tetrahedra are flipped (corners 2 and 3 swapped), so
 * that every tetrahedron is positively oriented as documented above.
 * `name` starts the messages. */
PW__DEF int pw_tetmesh_check(pw_tetmesh *m, const char *name, pw_err *e)
{
    int v, t, k, j;
    if (m->nt < 1 || !m->tet) return pw_fail(e, PW_ERR_DEGENERATE, "%s: no tetrahedra", name);
    if (m->nv < 4 || !m->pos) return pw_fail(e, PW_ERR_DEGENERATE, "%s: fewer than 4 vertices", name);
    for (v = 0; v < m->nv; v++)
        for (k = 0; k < 3; k++)
            if (!pw_is_finite(m->pos[3 * v + k]))
                return pw_fail(e, PW_ERR_INVALID, "%s: vertex %d has a non-finite coordinate", name, v);
    for (t = 0; t < m->nt; t++) {
        int *c = m->tet + 4 * t;
        double vol, len;
        for (k = 0; k < 4; k++) {
            if (c[k] < 0 || c[k] >= m->nv)
                return pw_fail(e, PW_ERR_INVALID, "%s: tetrahedron %d uses vertex %d of %d", name, t, c[k], m->nv);
            for (j = 0; j < k; j++)
                if (c[j] == c[k])
                    return pw_fail(e, PW_ERR_DEGENERATE, "%s: tetrahedron %d uses vertex %d twice", name, t, c[k]);
        }
        vol = pw_tet_volume6(m, t);
        len = pw__tet_longest_edge(m, t);
        if (!(fabs(vol) > 1e-12 * len * len * len))
            return pw_fail(e, PW_ERR_DEGENERATE, "%s: tetrahedron %d (vertices %d %d %d %d) has zero volume", name, t,
                           c[0], c[1], c[2], c[3]);
        if (vol < 0.0) {
            int tmp = c[2];
            c[2] = c[3];
            c[3] = tmp;
        }
    }
    return PW_OK;
}

/* ---- adjacency ------------------------------------------------------------- */

/* The corners of face (t, k) as global vertices, sorted, and the parity of
 * the outward order relative to the sorted one (0 even, 1 odd). */
PW__DEF int pw__tet_face_key(const pw_tetmesh *m, int t, int k, int key[3])
{
    int f[3], i, j, odd = 0;
    pw_tet_face(k, f);
    for (i = 0; i < 3; i++) key[i] = m->tet[4 * t + f[i]];
    for (i = 1; i < 3; i++)
        for (j = i; j > 0 && key[j - 1] > key[j]; j--) {
            int tmp = key[j];
            key[j] = key[j - 1];
            key[j - 1] = tmp;
            odd ^= 1;
        }
    return odd;
}

PW__DEF size_t pw__tet_face_hash(const int key[3], size_t mask)
{
    uint64_t h = (uint64_t)(uint32_t)key[0] * 0x9E3779B97F4A7C15ULL;
    h ^= (uint64_t)(uint32_t)key[1] * 0xC2B2AE3D27D4EB4FULL;
    h ^= (uint64_t)(uint32_t)key[2] * 0x165667B19E3779F9ULL;
    h ^= h >> 29;
    return (size_t)h & mask;
}

/* Pairs face id f = 4t+k with the face already in slot `at` of the table. */
PW__DEF int pw__tet_pair(const pw_tetmesh *m, int *nb, int f, int g, int parity_f, pw_err *e)
{
    int key[3], parity_g = pw__tet_face_key(m, g >> 2, g & 3, key);
    if (nb[g] >= 0)
        return pw_fail(e, PW_ERR_TOPOLOGY, "face (%d %d %d) is shared by three or more tetrahedra (%d, %d and %d)",
                       key[0], key[1], key[2], nb[g] >> 2, g >> 2, f >> 2);
    if (parity_f == parity_g)
        return pw_fail(e, PW_ERR_TOPOLOGY,
                       "tetrahedra %d and %d overlap: they lie on the same side of their shared face (%d %d %d)",
                       g >> 2, f >> 2, key[0], key[1], key[2]);
    nb[f] = g;
    nb[g] = f;
    return PW_OK;
}

/* Face adjacency: nb[4t+k] (caller-allocated, 4 nt ints) is 4u+j when the
 * face of t opposite corner k is the face of u opposite corner j, and -1
 * on the boundary. A face shared by more than two tetrahedra, or shared by
 * two that lie on the same side of it (overlapping, i.e. not a valid
 * decomposition of a solid), is PW_ERR_TOPOLOGY. */
PW__DEF int pw_tetmesh_neighbors(const pw_alloc *a, const pw_tetmesh *m, int *nb, pw_err *e)
{
    size_t cap = 16, mask, h;
    int *slot, f, r = PW_OK;
    while (cap < (size_t)m->nt * 8) cap *= 2;
    mask = cap - 1;
    if (!(slot = (int *)pw_alloc_array(a, cap, sizeof(int), "face table", e))) return PW_ERR_NOMEM;
    memset(slot, 0xFF, cap * sizeof(int));
    for (f = 0; f < 4 * m->nt; f++) nb[f] = -1;
    for (f = 0; f < 4 * m->nt && r == PW_OK; f++) {
        int key[3], other[3], parity = pw__tet_face_key(m, f >> 2, f & 3, key);
        for (h = pw__tet_face_hash(key, mask); slot[h] >= 0; h = (h + 1) & mask) {
            pw__tet_face_key(m, slot[h] >> 2, slot[h] & 3, other);
            if (other[0] == key[0] && other[1] == key[1] && other[2] == key[2]) break;
        }
        if (slot[h] < 0) slot[h] = f;
        else r = pw__tet_pair(m, nb, f, slot[h], parity, e);
        if (r == PW_OK && slot[h] != f) slot[h] = f; /* a third copy then meets this pair */
    }
    pw_free(a, slot);
    return r;
}

/* The boundary faces (nb[f] < 0) as face ids 4t+k in increasing order;
 * *faces is allocated here. Their corners, outward, are pw_tet_face(k). */
PW__DEF int pw_tetmesh_boundary(const pw_alloc *a, const pw_tetmesh *m, const int *nb, int **faces, int *count,
                                pw_err *e)
{
    int f, n = 0;
    for (f = 0; f < 4 * m->nt; f++) n += nb[f] < 0;
    *count = 0;
    if (!(*faces = (int *)pw_alloc_array(a, (size_t)n, sizeof(int), "boundary faces", e))) return PW_ERR_NOMEM;
    for (f = 0; f < 4 * m->nt; f++)
        if (nb[f] < 0) (*faces)[(*count)++] = f;
    return PW_OK;
}

/* Vertex one-rings and stars, as compressed rows: the neighbours of vertex
 * v (sharing an edge) are adj[start[v] .. start[v+1]-1], sorted; the
 * tetrahedra around v are star[sstart[v] .. sstart[v+1]-1], increasing.
 * Either pair of outputs may be NULL. Everything is allocated here. */
typedef struct pw_tetrings {
    int *start, *adj;   /* nv+1, start[nv] */
    int *sstart, *star; /* nv+1, 4 nt */
} pw_tetrings;

PW__DEF void pw_tetrings_free(const pw_alloc *a, pw_tetrings *g)
{
    pw_free(a, g->start);
    pw_free(a, g->adj);
    pw_free(a, g->sstart);
    pw_free(a, g->star);
    memset(g, 0, sizeof *g);
}

/* Removes the repeats of row [lo, hi) of adj (mark: one int per vertex,
 * never equal to v before; each kept entry is marked v), then sorts the
 * rest in place; returns the row's new end. Marking first leaves the
 * insertion sort a vertex's dozen or so neighbours instead of the three
 * entries per tetrahedron of its star. */
PW__DEF int pw__ring_unique(int *adj, int lo, int hi, int *mark, int v)
{
    int i, j, n = lo;
    for (i = lo; i < hi; i++)
        if (mark[adj[i]] != v) mark[adj[n++] = adj[i]] = v;
    for (i = lo + 1; i < n; i++)
        for (j = i; j > lo && adj[j - 1] > adj[j]; j--) {
            int tmp = adj[j];
            adj[j] = adj[j - 1];
            adj[j - 1] = tmp;
        }
    return n;
}

PW__DEF int pw_tetmesh_rings(const pw_alloc *a, const pw_tetmesh *m, pw_tetrings *g, pw_err *e)
{
    int t, i, j, v, n = 0, *fill;
    memset(g, 0, sizeof *g);
    g->start = (int *)pw_calloc_array(a, (size_t)m->nv + 1, sizeof(int), "vertex rings", e);
    g->sstart = (int *)pw_calloc_array(a, (size_t)m->nv + 1, sizeof(int), "vertex stars", e);
    g->adj = (int *)pw_alloc_array(a, (size_t)m->nt * 12, sizeof(int), "vertex rings", e);
    g->star = (int *)pw_alloc_array(a, (size_t)m->nt * 4, sizeof(int), "vertex stars", e);
    fill = (int *)pw_alloc_array(a, (size_t)m->nv + 1, sizeof(int), "vertex rings", e);
    if (!g->start || !g->sstart || !g->adj || !g->star || !fill) {
        pw_free(a, fill);
        pw_tetrings_free(a, g);
        return PW_ERR_NOMEM;
    }
    for (i = 0; i < 4 * m->nt; i++) g->sstart[m->tet[i] + 1]++;
    for (v = 0; v < m->nv; v++) g->sstart[v + 1] += g->sstart[v];
    memcpy(fill, g->sstart, ((size_t)m->nv + 1) * sizeof(int));
    for (i = 0; i < 4 * m->nt; i++) g->star[fill[m->tet[i]]++] = i / 4;
    for (v = 0; v < m->nv; v++) g->start[v + 1] = g->start[v] + 3 * (g->sstart[v + 1] - g->sstart[v]);
    memcpy(fill, g->start, ((size_t)m->nv + 1) * sizeof(int));
    for (t = 0; t < m->nt; t++)
        for (i = 0; i < 4; i++)
            for (j = 0; j < 4; j++)
                if (i != j) g->adj[fill[m->tet[4 * t + i]]++] = m->tet[4 * t + j];
    for (v = 0; v <= m->nv; v++) fill[v] = -1; /* now the marks of pw__ring_unique */
    for (v = 0; v < m->nv; v++) {              /* compact: each row sorted without repeats */
        int lo = g->start[v], hi = g->start[v + 1], end = pw__ring_unique(g->adj, lo, hi, fill, v);
        g->start[v] = n;
        for (i = lo; i < end; i++) g->adj[n++] = g->adj[i];
    }
    g->start[m->nv] = n;
    pw_free(a, fill);
    return PW_OK;
}

/* ---- geometry of one tetrahedron ---------------------------------------------- */

/* Gradients of the four barycentric coordinates of tetrahedron t (constant
 * over it): g[k] is the gradient of lambda_k. Returns 6V. */
PW__DEF double pw_tet_gradients(const pw_tetmesh *m, int t, double g[4][3])
{
    const float *p0 = m->pos + 3 * m->tet[4 * t];
    double d[3][3], vol6;
    int i, k;
    for (i = 0; i < 3; i++)
        for (k = 0; k < 3; k++) d[i][k] = (double)m->pos[3 * m->tet[4 * t + 1 + i] + k] - p0[k];
    vol6 = d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1]) - d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0]) +
           d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0]);
    for (i = 0; i < 3; i++) { /* the gradient of lambda_(i+1) is (d_j x d_k) / 6V */
        pw_cross3(d[(i + 1) % 3], d[(i + 2) % 3], g[i + 1]);
        for (k = 0; k < 3; k++) g[i + 1][k] /= vol6;
    }
    for (k = 0; k < 3; k++) g[0][k] = -(g[1][k] + g[2][k] + g[3][k]);
    return vol6;
}

/* Barycentric coordinates of point p in tetrahedron t. */
PW__DEF void pw_tet_barycentric(const pw_tetmesh *m, int t, const double p[3], double l[4])
{
    double g[4][3], d[3];
    const float *p0 = m->pos + 3 * m->tet[4 * t];
    int k, i;
    pw_tet_gradients(m, t, g);
    for (k = 0; k < 3; k++) d[k] = p[k] - p0[k];
    l[0] = 1.0;
    for (i = 1; i < 4; i++) {
        l[i] = g[i][0] * d[0] + g[i][1] * d[1] + g[i][2] * d[2];
        l[0] -= l[i];
    }
}

/* ---- point location --------------------------------------------------------------- */

/* A uniform grid over the bounding box with about one tetrahedron per
 * cell; each cell lists the tetrahedra whose bounding box meets it. */
typedef struct pw_tetgrid {
    int n[3];
    double lo[3], inv[3]; /* cells per unit length */
    int *start, *tets;    /* n0 n1 n2 + 1 offsets; the lists */
} pw_tetgrid;

PW__DEF void pw_tetgrid_free(const pw_alloc *a, pw_tetgrid *g)
{
    pw_free(a, g->start);
    pw_free(a, g->tets);
    memset(g, 0, sizeof *g);
}

/* Cell range of the bounding box of tetrahedron t. */
PW__DEF void pw__tetgrid_range(const pw_tetgrid *g, const pw_tetmesh *m, int t, int lo[3], int hi[3])
{
    int k, i;
    for (k = 0; k < 3; k++) {
        double mn = m->pos[3 * m->tet[4 * t] + k], mx = mn, c;
        for (i = 1; i < 4; i++) {
            c = m->pos[3 * m->tet[4 * t + i] + k];
            if (c < mn) mn = c;
            if (c > mx) mx = c;
        }
        lo[k] = pw_clampi((int)((mn - g->lo[k]) * g->inv[k]), 0, g->n[k] - 1);
        hi[k] = pw_clampi((int)((mx - g->lo[k]) * g->inv[k]), 0, g->n[k] - 1);
    }
}

/* Registers every tetrahedron in its cells (pass 0 counts, pass 1 fills). */
PW__DEF void pw__tetgrid_fill(pw_tetgrid *g, const pw_tetmesh *m, int pass)
{
    int t, lo[3], hi[3], x, y, z;
    for (t = 0; t < m->nt; t++) {
        pw__tetgrid_range(g, m, t, lo, hi);
        for (z = lo[2]; z <= hi[2]; z++)
            for (y = lo[1]; y <= hi[1]; y++)
                for (x = lo[0]; x <= hi[0]; x++) {
                    size_t c = ((size_t)z * g->n[1] + y) * g->n[0] + x;
                    if (pass == 0) g->start[c + 1]++;
                    else g->tets[g->start[c]++] = t;
                }
    }
}

PW__DEF int pw_tetgrid_build(const pw_alloc *a, const pw_tetmesh *m, pw_tetgrid *g, pw_err *e)
{
    double hi[3], side;
    size_t cells, c, total;
    int k, v;
    memset(g, 0, sizeof *g);
    for (k = 0; k < 3; k++) g->lo[k] = hi[k] = m->pos[k];
    for (v = 1; v < m->nv; v++)
        for (k = 0; k < 3; k++) {
            if (m->pos[3 * v + k] < g->lo[k]) g->lo[k] = m->pos[3 * v + k];
            if (m->pos[3 * v + k] > hi[k]) hi[k] = m->pos[3 * v + k];
        }
    side = (hi[0] - g->lo[0]) + (hi[1] - g->lo[1]) + (hi[2] - g->lo[2]);
    side = side > 0.0 ? side / 3.0 : 1.0;
    for (k = 0; k < 3; k++) { /* about nt cells of roughly cubic shape */
        double len = hi[k] - g->lo[k], cube = 1.0;
        while (cube * cube * cube < (double)m->nt) cube += 1.0;
        g->n[k] = pw_clampi((int)(cube * len / side) + 1, 1, 1024);
        g->inv[k] = len > 0.0 ? g->n[k] / (len * (1.0 + 1e-9)) : 0.0;
    }
    cells = (size_t)g->n[0] * g->n[1] * g->n[2];
    if (!(g->start = (int *)pw_calloc_array(a, cells + 1, sizeof(int), "point-location grid", e))) return PW_ERR_NOMEM;
    pw__tetgrid_fill(g, m, 0);
    for (c = 0; c < cells; c++) g->start[c + 1] += g->start[c];
    total = (size_t)g->start[cells];
    if (!(g->tets = (int *)pw_alloc_array(a, total, sizeof(int), "point-location grid", e))) {
        pw_tetgrid_free(a, g);
        return PW_ERR_NOMEM;
    }
    pw__tetgrid_fill(g, m, 1);
    for (c = cells; c > 0; c--) g->start[c] = g->start[c - 1];
    g->start[0] = 0;
    return PW_OK;
}

/* The tetrahedron containing p (barycentric coordinates in l), or -1 when p
 * is outside the mesh. Points on a shared face go to the first tetrahedron
 * listed; within a tolerance of 1e-6 in the barycentric coordinates the
 * nearest candidate is taken, so that points on the boundary are found. */
PW__DEF int pw_tetgrid_locate(const pw_tetgrid *g, const pw_tetmesh *m, const double p[3], double l[4])
{
    int cell[3], k, i, best = -1;
    double bestmin = -1e-6, b[4];
    size_t c;
    for (k = 0; k < 3; k++) {
        double x = (p[k] - g->lo[k]) * g->inv[k];
        if (!(x >= -1e-9 * g->n[k] && x <= g->n[k] * (1.0 + 1e-9))) return -1;
        cell[k] = pw_clampi((int)x, 0, g->n[k] - 1);
    }
    c = ((size_t)cell[2] * g->n[1] + cell[1]) * g->n[0] + cell[0];
    for (i = g->start[c]; i < g->start[c + 1]; i++) {
        double mn;
        pw_tet_barycentric(m, g->tets[i], p, b);
        mn = b[0];
        for (k = 1; k < 4; k++) mn = b[k] < mn ? b[k] : mn;
        if (mn > bestmin) {
            bestmin = mn;
            best = g->tets[i];
            memcpy(l, b, sizeof b);
            if (mn >= 0.0) break;
        }
    }
    return best;
}

#endif /* PW__TETMESH_V1 */
