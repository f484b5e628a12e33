/* shapes: the built-in surface meshes of the demos and tests, shared by
 * the surface methods (lapped, pgp). Everything is made from + - * / and
 * sqrt (and pw_sin/pw_cos, built from those), so the meshes are the same on
 * every platform. Faces are counter-clockwise seen from outside (from +z
 * for the flat ones); sizes are about one unit.
 *
 *   pw_shape_geosphere  icosahedron faces split n x n, pushed onto the unit
 *                       sphere: 10 n^2 + 2 vertices, 20 n^2 triangles
 *   pw_shape_bumpy      a geosphere with 14 smooth bumps and dents at fixed
 *                       pseudo-random places, a little taller than wide
 *   pw_shape_torus      radii 1 and 0.4 around the z axis, nu x nv quads
 *                       (or each split in two triangles)
 *   pw_shape_thin_torus the same with any tube radius (triangles)
 *   pw_shape_dumbbell   two unit balls joined by a neck of a given radius,
 *                       a surface of revolution about z
 *   pw_shape_star       a geosphere with its 12 icosahedron corners pulled
 *                       out into long thin spikes
 *   pw_shape_disc       a gently domed disc of radius 1 facing +z (boundary)
 *   pw_shape_grid       n x n quads (or triangle pairs) on [-1,1]^2 facing
 *                       +z, optionally waved (boundary) */
#ifndef PW__SHAPES_V1
#define PW__SHAPES_V1

#include "base.h"
#include "vec.h"
#include "rng.h"
#include "mesh.h"

/* A mesh of nv vertices and nf faces of `degree` corners each, fstart
 * filled. */
PW__DEF int pw_shape_alloc(const pw_alloc *a, int nv, int nf, int degree, pw_mesh *m, pw_err *e)
{
    int f, r = pw_mesh_alloc(a, m, nv, nf, nf * degree, 0, e);
    if (r != PW_OK) return r;
    for (f = 0; f <= nf; f++) m->fstart[f] = degree * f;
    return PW_OK;
}

/* The icosahedron: corners (0, +-1, +-phi) and cyclic permutations, faces
 * counter-clockwise seen from outside (the table's 2 stands for phi). */
static const signed char pw__ico_v[12][3] = {{-1, 2, 0},  {1, 2, 0},  {-1, -2, 0}, {1, -2, 0}, {0, -1, 2},  {0, 1, 2},
                                             {0, -1, -2}, {0, 1, -2}, {2, 0, -1},  {2, 0, 1},  {-2, 0, -1}, {-2, 0, 1}};
static const unsigned char pw__ico_f[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                               {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                               {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                               {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};

PW__DEF pw_v3 pw__ico_corner(int k)
{
    const float phi = 1.61803398874989485f;
    float c[3];
    int i;
    for (i = 0; i < 3; i++) {
        int t = pw__ico_v[k][i];
        c[i] = t == 2 ? phi : t == -2 ? -phi : (float)t;
    }
    return pw_v3_load(c);
}

/* Index (0..29) of the icosahedron edge between corners p < q. */
PW__DEF int pw__ico_edge(int p, int q)
{
    int f, k, n = 0;
    for (f = 0; f < 20; f++)
        for (k = 0; k < 3; k++) {
            int a = pw__ico_f[f][k], b = pw__ico_f[f][(k + 1) % 3];
            if (a > b) continue; /* count each edge once, from the face where it runs upwards */
            if (a == p && b == q) return n;
            n++;
        }
    return -1;
}

/* Vertex id of lattice point (i, j) of a frequency-n face with corners
 * c[0..2]: the point c0 + i (c1 - c0)/n + j (c2 - c0)/n. Corners come first,
 * then n-1 points per edge (from its lower corner), then face interiors, so
 * points shared by faces get one id. */
PW__DEF int pw__geo_id(const int *c, int f, int n, int i, int j)
{
    int p = -1, q = -1, t = 0, jj = j;
    if (i == 0 && j == 0) return c[0];
    if (i == n) return c[1];
    if (j == n) return c[2];
    if (j == 0) {
        p = c[0];
        q = c[1];
        t = i;
    } else if (i == 0) {
        p = c[0];
        q = c[2];
        t = j;
    } else if (i + j == n) {
        p = c[1];
        q = c[2];
        t = j;
    }
    if (p >= 0) {
        if (p > q) {
            int s = p;
            p = q;
            q = s;
            t = n - t;
        }
        return 12 + pw__ico_edge(p, q) * (n - 1) + t - 1;
    }
    return 12 + 30 * (n - 1) + f * (n - 1) * (n - 2) / 2 + (jj - 1) * (n - 1) - (jj - 1) * jj / 2 + i - 1;
}

/* Geodesic sphere: every icosahedron face split into n^2 triangles, the
 * points pushed onto the unit sphere (10 n^2 + 2 vertices, 20 n^2 faces).
 * Vertices 0..11 are the icosahedron's corners. */
PW__DEF int pw_shape_geosphere(const pw_alloc *a, int n, pw_mesh *m, pw_err *e)
{
    int f, i, j, nt = 0, r = pw_shape_alloc(a, 10 * n * n + 2, 20 * n * n, 3, m, e);
    if (r != PW_OK) return r;
    for (f = 0; f < 20; f++) {
        int c[3];
        pw_v3 A, B, C;
        c[0] = pw__ico_f[f][0];
        c[1] = pw__ico_f[f][1];
        c[2] = pw__ico_f[f][2];
        A = pw__ico_corner(c[0]);
        B = pw__ico_corner(c[1]);
        C = pw__ico_corner(c[2]);
        for (j = 0; j <= n; j++)
            for (i = 0; i + j <= n; i++) {
                pw_v3 p = pw_v3_add(A, pw_v3_add(pw_v3_scale(pw_v3_sub(B, A), (float)i / n),
                                                 pw_v3_scale(pw_v3_sub(C, A), (float)j / n)));
                int *t = m->fv + 3 * nt;
                pw_v3_store(m->pos + 3 * pw__geo_id(c, f, n, i, j), pw_v3_norm(p));
                if (i + j == n) continue;
                t[0] = pw__geo_id(c, f, n, i, j); /* the upright triangle */
                t[1] = pw__geo_id(c, f, n, i + 1, j);
                t[2] = pw__geo_id(c, f, n, i, j + 1);
                nt++;
                if (i + j + 1 == n) continue;
                t[3] = t[1]; /* and the inverted one beside it */
                t[4] = pw__geo_id(c, f, n, i + 1, j + 1);
                t[5] = t[2];
                nt++;
            }
    }
    return PW_OK;
}

/* A smooth bump of height 1 at distance 0, reaching 0 at distance 1 with
 * zero slope and curvature: (1 - t^2)^3. */
PW__DEF double pw__shape_bump(double t) { return t >= 1.0 ? 0.0 : (1.0 - t * t) * (1.0 - t * t) * (1.0 - t * t); }

/* "bumpy": a frequency-n geodesic sphere whose radius is raised or lowered
 * by 14 smooth bumps at fixed pseudo-random places (the same for every
 * seed). The surface stays star-shaped, so it is embedded and keeps its
 * orientation. */
PW__DEF int pw_shape_bumpy(const pw_alloc *a, int n, pw_mesh *m, pw_err *e)
{
    double c[14][3], h[14], rad[14];
    pw_rng rng = pw_rng_seed(2000, 7);
    int k, v, r = pw_shape_geosphere(a, n, m, e);
    if (r != PW_OK) return r;
    for (k = 0; k < 14; k++) {
        double x = 2 * pw_rng_double(&rng) - 1, y = 2 * pw_rng_double(&rng) - 1, z = 2 * pw_rng_double(&rng) - 1;
        double l = sqrt(x * x + y * y + z * z) + 1e-9;
        c[k][0] = x / l;
        c[k][1] = y / l;
        c[k][2] = z / l;
        h[k] = k % 3 == 2 ? -0.1 : 0.08 + 0.14 * pw_rng_double(&rng);
        rad[k] = 0.45 + 0.4 * pw_rng_double(&rng);
    }
    for (v = 0; v < m->nv; v++) {
        float *p = m->pos + 3 * v;
        double s = 1.0;
        for (k = 0; k < 14; k++) {
            double dx = p[0] - c[k][0], dy = p[1] - c[k][1], dz = p[2] - c[k][2];
            s += h[k] * pw__shape_bump(sqrt(dx * dx + dy * dy + dz * dz) / rad[k]);
        }
        p[0] = (float)(p[0] * s);
        p[1] = (float)(p[1] * s * 1.1); /* a little taller than wide */
        p[2] = (float)(p[2] * s);
    }
    return PW_OK;
}

/* A torus of radius 1 around the z axis: nu x nv quads (quads != 0) or
 * each split in two triangles, tube radius `tube`. */
typedef struct pw__torus {
    int nu, nv, quads;
    double tube;
} pw__torus;

PW__DEF int pw__shape_torus(const pw_alloc *a, const pw__torus *T, pw_mesh *m, pw_err *e);

/* Torus around the z axis: radii 1 and 0.4, nu x nv quads (quads != 0) or
 * each quad split in two triangles. Vertex i*nv + j sits at angle 2 pi i/nu
 * around the axis and 2 pi j/nv around the tube. */
PW__DEF int pw_shape_torus(const pw_alloc *a, int nu, int nv, int quads, pw_mesh *m, pw_err *e)
{
    pw__torus T;
    T.nu = nu;
    T.nv = nv;
    T.quads = quads;
    T.tube = 0.4;
    return pw__shape_torus(a, &T, m, e);
}

/* The same torus of radius 1 with tube radius `tube` (0 < tube < 1), in
 * triangles: a thin ring for the tetrahedralizer's tests. */
PW__DEF int pw_shape_thin_torus(const pw_alloc *a, int nu, int nv, double tube, pw_mesh *m, pw_err *e)
{
    pw__torus T;
    if (!(tube > 0.0 && tube < 1.0)) return pw_fail(e, PW_ERR_INVALID, "torus: tube radius %g not in (0, 1)", tube);
    T.nu = nu;
    T.nv = nv;
    T.quads = 0;
    T.tube = tube;
    return pw__shape_torus(a, &T, m, e);
}

PW__DEF int pw__shape_torus(const pw_alloc *a, const pw__torus *T, pw_mesh *m, pw_err *e)
{
    const double pi2 = 6.28318530717958647692, tube = T->tube;
    const int nu = T->nu, nv = T->nv, quads = T->quads;
    int d = quads ? 4 : 3, i, j, r = pw_shape_alloc(a, nu * nv, (quads ? 1 : 2) * nu * nv, d, m, e);
    if (r != PW_OK) return r;
    for (i = 0; i < nu; i++)
        for (j = 0; j < nv; j++) {
            double u = pi2 * i / nu, v = pi2 * j / nv, rr = 1.0 + tube * pw_cos(v);
            float *p = m->pos + 3 * (i * nv + j);
            int *t = m->fv + (size_t)(quads ? 4 : 6) * (i * nv + j);
            int a0 = i * nv + j, a1 = ((i + 1) % nu) * nv + j;
            int a2 = ((i + 1) % nu) * nv + (j + 1) % nv, a3 = i * nv + (j + 1) % nv;
            p[0] = (float)(rr * pw_cos(u));
            p[1] = (float)(rr * pw_sin(u));
            p[2] = (float)(tube * pw_sin(v));
            t[0] = a0;
            t[1] = a1;
            t[2] = a2; /* d/du x d/dv points outwards */
            if (quads) t[3] = a3;
            else {
                t[3] = a0;
                t[4] = a2;
                t[5] = a3;
            }
        }
    return PW_OK;
}

/* "disc": a gently domed disc of radius 1 facing +z, with a boundary: a
 * centre and K rings of 6k vertices, neighbouring rings zipped together
 * (6 K^2 triangles). */
PW__DEF int pw_shape_disc(const pw_alloc *a, int K, pw_mesh *m, pw_err *e)
{
    const double pi2 = 6.28318530717958647692;
    int k, i, nt = 0, r = pw_shape_alloc(a, 1 + 3 * K * (K + 1), 6 * K * K, 3, m, e);
    if (r != PW_OK) return r;
    m->pos[2] = 0.2f;
    for (k = 1; k <= K; k++)
        for (i = 0; i < 6 * k; i++) {
            double rho = (double)k / K, th = pi2 * i / (6 * k);
            float *p = m->pos + 3 * (1 + 3 * k * (k - 1) + i);
            p[0] = (float)(rho * pw_cos(th));
            p[1] = (float)(rho * pw_sin(th));
            p[2] = (float)(0.2 * (1.0 - rho * rho));
        }
    for (k = 1; k <= K; k++) { /* ring k-1 (n0 vertices; the centre for k = 1) against ring k */
        int n0 = k == 1 ? 1 : 6 * (k - 1), n1 = 6 * k, b0 = k == 1 ? 0 : 1 + 3 * (k - 1) * (k - 2);
        int b1 = 1 + 3 * k * (k - 1), i = k == 1 ? 1 : 0, j = 0;
        while (i < n0 || j < n1) { /* step along the ring whose next vertex comes first in angle */
            int *t = m->fv + 3 * nt++, inner = j == n1 || (i < n0 && (long)(i + 1) * n1 < (long)(j + 1) * n0);
            t[0] = b0 + i % n0;
            t[1] = b1 + j % n1;
            t[2] = inner ? b0 + (i + 1) % n0 : b1 + (j + 1) % n1; /* counter-clockwise seen from +z */
            if (inner) i++;
            else j++;
        }
    }
    return PW_OK;
}

/* The icosahedron itself: corners (0, +-1, +-phi) and their cyclic
 * permutations, 20 triangles counter-clockwise seen from outside. */
PW__DEF int pw_shape_icosahedron(const pw_alloc *a, pw_mesh *m, pw_err *e)
{
    const float phi = 1.61803398874989485f;
    int k, r = pw_shape_alloc(a, 12, 20, 3, m, e);
    if (r != PW_OK) return r;
    for (k = 0; k < 36; k++) { /* the table's 2 stands for the golden ratio */
        int c = pw__ico_v[k / 3][k % 3];
        m->pos[k] = c == 2 ? phi : (c == -2 ? -phi : (float)c);
    }
    for (k = 0; k < 60; k++) m->fv[k] = pw__ico_f[k / 3][k % 3];
    return PW_OK;
}

/* The surface of a union of unit voxels (an X x Y x Z array vox, x fastest,
 * non-zero = solid): one outward quad per voxel face that touches empty
 * space, in lattice units. A first pass counts (m == NULL), a second
 * writes; vertices are numbered in order of first use. */
typedef struct pw__voxels {
    int X, Y, Z;
    const unsigned char *vox;
    int *map; /* lattice point -> vertex, -1 if unused */
    pw_mesh *m;
    int nv, nf;
} pw__voxels;

PW__DEF int pw__voxel_solid(const pw__voxels *v, const int p[3])
{
    return p[0] >= 0 && p[1] >= 0 && p[2] >= 0 && p[0] < v->X && p[1] < v->Y && p[2] < v->Z &&
           v->vox[(p[2] * v->Y + p[1]) * v->X + p[0]];
}

/* Emits the face of voxel p facing direction d (axis d/2, sign by d&1),
 * counter-clockwise seen from outside. */
PW__DEF void pw__voxel_face(pw__voxels *v, const int p[3], int d)
{
    static const int du[4] = {0, 1, 1, 0}, dv[4] = {0, 0, 1, 1};
    int ax = d >> 1, neg = d & 1, u = (ax + 1) % 3, w = (ax + 2) % 3, k, c[3], li;
    for (k = 0; k < 4; k++) {
        int kk = neg ? (4 - k) & 3 : k; /* reversed walk on the negative side */
        memcpy(c, p, sizeof c);
        c[ax] += !neg;
        c[u] += du[kk];
        c[w] += dv[kk];
        li = (c[2] * (v->Y + 1) + c[1]) * (v->X + 1) + c[0];
        if (v->map[li] < 0) {
            if (v->m) {
                v->m->pos[3 * v->nv] = (float)c[0];
                v->m->pos[3 * v->nv + 1] = (float)c[1];
                v->m->pos[3 * v->nv + 2] = (float)c[2];
            }
            v->map[li] = v->nv++;
        }
        if (v->m) v->m->fv[4 * v->nf + k] = v->map[li];
    }
    v->nf++;
}

PW__DEF void pw__voxel_pass(pw__voxels *v)
{
    int p[3], q[3], d, k, nl = (v->X + 1) * (v->Y + 1) * (v->Z + 1);
    for (k = 0; k < nl; k++) v->map[k] = -1;
    v->nv = v->nf = 0;
    for (p[2] = 0; p[2] < v->Z; p[2]++)
        for (p[1] = 0; p[1] < v->Y; p[1]++)
            for (p[0] = 0; p[0] < v->X; p[0]++) {
                if (!pw__voxel_solid(v, p)) continue;
                for (d = 0; d < 6; d++) {
                    memcpy(q, p, sizeof q);
                    q[d >> 1] += d & 1 ? -1 : 1;
                    if (!pw__voxel_solid(v, q)) pw__voxel_face(v, p, d);
                }
            }
}

PW__DEF int pw_shape_polycube(const pw_alloc *a, int X, int Y, int Z, const unsigned char *vox, pw_mesh *m, pw_err *e)
{
    pw__voxels v;
    int r;
    v.X = X;
    v.Y = Y;
    v.Z = Z;
    v.vox = vox;
    v.m = NULL;
    v.map = (int *)pw_alloc_array(a, (size_t)(X + 1) * (Y + 1) * (Z + 1), sizeof(int), "lattice", e);
    if (!v.map) return PW_ERR_NOMEM;
    pw__voxel_pass(&v);
    if ((r = pw_shape_alloc(a, v.nv, v.nf, 4, m, e)) == PW_OK) {
        v.m = m;
        pw__voxel_pass(&v);
    }
    pw_free(a, v.map);
    return r;
}

/* An n x n grid of quads (quads != 0) or triangle pairs on [-1,1]^2 facing
 * +z, with a boundary; z = wave sin(pi x) sin(pi y) (0: flat). Vertex
 * j*(n+1) + i sits at x = -1 + 2i/n, y = -1 + 2j/n; the triangles of cell
 * (i, j) are 2(j n + i) and 2(j n + i) + 1. */
PW__DEF int pw_shape_grid(const pw_alloc *a, int n, double wave, int quads, pw_mesh *m, pw_err *e)
{
    const double pi = 3.14159265358979323846;
    int i, j, r = pw_shape_alloc(a, (n + 1) * (n + 1), (quads ? 1 : 2) * n * n, quads ? 4 : 3, m, e);
    if (r != PW_OK) return r;
    for (j = 0; j <= n; j++)
        for (i = 0; i <= n; i++) {
            double x = -1.0 + 2.0 * i / n, y = -1.0 + 2.0 * j / n;
            float *p = m->pos + 3 * (j * (n + 1) + i);
            p[0] = (float)x;
            p[1] = (float)y;
            p[2] = wave != 0.0 ? (float)(wave * pw_sin(pi * x) * pw_sin(pi * y)) : 0.0f;
        }
    for (j = 0; j < n; j++)
        for (i = 0; i < n; i++) {
            int *f = m->fv + (size_t)(quads ? 4 : 6) * (j * n + i), v = j * (n + 1) + i;
            f[0] = v;
            f[1] = v + 1;
            f[2] = v + n + 2;
            if (quads) f[3] = v + n + 1;
            else {
                f[3] = v;
                f[4] = v + n + 2;
                f[5] = v + n + 1;
            }
        }
    return PW_OK;
}

/* asin(x) for 0 <= x <= 1 by bisection on pw_sin: the same bits everywhere. */
PW__DEF double pw__shape_asin(double x)
{
    double lo = 0.0, hi = 1.57079632679489661923;
    int k;
    for (k = 0; k < 60; k++) {
        double mid = 0.5 * (lo + hi);
        if (pw_sin(mid) < x) lo = mid;
        else hi = mid;
    }
    return 0.5 * (lo + hi);
}

/* The profile of a surface of revolution about z: points (z[k], r[k]),
 * k = 0..n-1, from the top pole to the bottom one (r > 0 between). */
typedef struct pw__profile {
    const double *z, *r;
    int n;
} pw__profile;

/* A closed surface of revolution about z of profile P, each inner point a
 * ring of `around` vertices; the poles are single vertices. Faces
 * counter-clockwise seen from outside. */
PW__DEF int pw__shape_revolve(const pw_alloc *a, const pw__profile *P, int around, pw_mesh *m, pw_err *e)
{
    const double pi2 = 6.28318530717958647692, *z = P->z, *r = P->r;
    const int n = P->n;
    int rings = n - 2, nv = rings * around + 2, k, j, nt = 0, res;
    int bot = nv - 1; /* vertex 0 is the top pole; ring k (1..rings) starts at 1 + (k-1) * around */
    if ((res = pw_shape_alloc(a, nv, 2 * around * (rings - 1) + 2 * around, 3, m, e)) != PW_OK) return res;
    m->pos[0] = m->pos[1] = 0.0f;
    m->pos[2] = (float)z[0];
    m->pos[3 * bot] = m->pos[3 * bot + 1] = 0.0f;
    m->pos[3 * bot + 2] = (float)z[n - 1];
    for (k = 1; k <= rings; k++)
        for (j = 0; j < around; j++) {
            float *p = m->pos + 3 * (1 + (k - 1) * around + j);
            p[0] = (float)(r[k] * pw_cos(pi2 * j / around));
            p[1] = (float)(r[k] * pw_sin(pi2 * j / around));
            p[2] = (float)z[k];
        }
    for (j = 0; j < around; j++) {
        int j1 = (j + 1) % around, *t;
        t = m->fv + 3 * nt++;
        t[0] = 0;
        t[1] = 1 + j;
        t[2] = 1 + j1;
        for (k = 1; k < rings; k++) {
            int a0 = 1 + (k - 1) * around + j, a1 = 1 + (k - 1) * around + j1, b0 = a0 + around, b1 = a1 + around;
            t = m->fv + 3 * nt++;
            t[0] = a0;
            t[1] = b0;
            t[2] = b1;
            t = m->fv + 3 * nt++;
            t[0] = a0;
            t[1] = b1;
            t[2] = a1;
        }
        t = m->fv + 3 * nt++;
        t[0] = bot;
        t[1] = 1 + (rings - 1) * around + j1;
        t[2] = 1 + (rings - 1) * around + j;
    }
    return PW_OK;
}

/* Dumbbell: unit balls centred at z = +-2 joined by a cylinder of radius
 * `neck` (0 < neck < 1), revolved with `around` vertices per ring; about
 * 4 `around` rings along the profile, spaced about evenly by arc length. */
PW__DEF int pw_shape_dumbbell(const pw_alloc *a, double neck, int around, pw_mesh *m, pw_err *e)
{
    const double pi = 3.14159265358979323846;
    double *z, *r, tn, zn, step = 2.0 * pi / around, len;
    pw__profile prof;
    int nb, nn, n, k, res;
    if (!(neck > 0.0 && neck < 1.0) || around < 3)
        return pw_fail(e, PW_ERR_INVALID, "dumbbell: neck %g not in (0, 1) or %d vertices around", neck, around);
    tn = pi - pw__shape_asin(neck); /* polar angle where a ball meets the neck */
    zn = 2.0 + pw_cos(tn);          /* the neck runs over |z| <= zn */
    nb = (int)(tn / step) + 1;
    len = 2.0 * zn;
    nn = (int)(len / step) + 1;
    n = 2 * nb + nn + 1;
    z = (double *)pw_alloc_array(a, (size_t)n, sizeof(double), "profile", e);
    r = (double *)pw_alloc_array(a, (size_t)n, sizeof(double), "profile", e);
    if (!z || !r) {
        pw_free(a, z);
        pw_free(a, r);
        return PW_ERR_NOMEM;
    }
    for (k = 0; k < nb; k++) {
        z[k] = 2.0 + pw_cos(tn * k / nb);
        r[k] = pw_sin(tn * k / nb);
    }
    for (k = 0; k <= nn; k++) {
        z[nb + k] = zn - len * k / nn;
        r[nb + k] = neck;
    }
    for (k = 0; k < nb; k++) {
        z[n - 1 - k] = -z[k];
        r[n - 1 - k] = r[k];
    }
    prof.z = z;
    prof.r = r;
    prof.n = n;
    res = pw__shape_revolve(a, &prof, around, m, e);
    pw_free(a, z);
    pw_free(a, r);
    return res;
}

/* Star: a geosphere (n as pw_shape_geosphere) whose 12 icosahedron corners
 * move out to radius `reach`: 12 spikes, each as thin at its base as the
 * geosphere's triangles are wide (about 1.1 / n) and pointed. */
PW__DEF int pw_shape_star(const pw_alloc *a, int n, double reach, pw_mesh *m, pw_err *e)
{
    int k, i, res = pw_shape_geosphere(a, n, m, e);
    if (res != PW_OK) return res;
    for (k = 0; k < 12; k++)
        for (i = 0; i < 3; i++) m->pos[3 * k + i] = (float)(m->pos[3 * k + i] * reach);
    return PW_OK;
}

#endif /* PW__SHAPES_V1 */
