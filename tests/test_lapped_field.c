/* Tests of lapped.h's tangent fields (§3.2) through lapped_compute_field,
 * and of the §3.3 difficulty (lapped__difficulty, compiled into this file
 * with the implementation). Meshes are built here: icosphere, cylinder,
 * flat grid, torus, subdivided cube, two disjoint spheres; the CGAL
 * elephant is used when `make data` has extracted it. */
#define LAPPED_STATIC /* static: only what the tests call is compiled */
#define LAPPED_IMPLEMENTATION
#include "lapped.h"
#include "pwtest.h"
#include <math.h>
#include <time.h>

#define PI 3.14159265358979323846

/* ---- procedural meshes -------------------------------------------------- */

typedef struct tmesh {
    int nv, nt, capv, capt;
    float *pos;
    int *tri;
} tmesh;

static int tm_vert(tmesh *m, double x, double y, double z)
{
    if (m->nv == m->capv) {
        m->capv = m->capv ? 2 * m->capv : 256;
        m->pos = (float *)realloc(m->pos, (size_t)m->capv * 3 * sizeof(float));
    }
    m->pos[3 * m->nv] = (float)x;
    m->pos[3 * m->nv + 1] = (float)y;
    m->pos[3 * m->nv + 2] = (float)z;
    return m->nv++;
}

/* A triangle, turned so that its normal agrees with the outward hint. */
static void tm_tri(tmesh *m, int a, int b, int c, double hx, double hy, double hz)
{
    const float *p = m->pos + 3 * a, *q = m->pos + 3 * b, *r = m->pos + 3 * c;
    double u[3], v[3], n[3];
    int k;
    for (k = 0; k < 3; k++) u[k] = q[k] - p[k], v[k] = r[k] - p[k];
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
    if (n[0] * hx + n[1] * hy + n[2] * hz < 0) k = b, b = c, c = k;
    if (m->nt == m->capt) {
        m->capt = m->capt ? 2 * m->capt : 256;
        m->tri = (int *)realloc(m->tri, (size_t)m->capt * 3 * sizeof(int));
    }
    m->tri[3 * m->nt] = a;
    m->tri[3 * m->nt + 1] = b;
    m->tri[3 * m->nt + 2] = c;
    m->nt++;
}

static void tm_free(tmesh *m)
{
    free(m->pos);
    free(m->tri);
    memset(m, 0, sizeof *m);
}

/* The public view of a triangle mesh (face_start built here). */
static lapped_mesh tm_view(const tmesh *m, int *fs)
{
    lapped_mesh v;
    int i;
    memset(&v, 0, sizeof v);
    for (i = 0; i <= m->nt; i++) fs[i] = 3 * i;
    v.nverts = m->nv;
    v.positions = m->pos;
    v.nfaces = m->nt;
    v.face_start = fs;
    v.face_verts = m->tri;
    return v;
}

/* Icosphere: an icosahedron subdivided `level` times, radius r, centre c. */
static int ico_mid(tmesh *m, int *key, int *val, int cap, int a, int b, double r, const double *c)
{
    int lo = a < b ? a : b, hi = a < b ? b : a,
        h = (int)(((unsigned)lo * 7919u + (unsigned)hi) % (unsigned)cap);
    double x, y, z, l;
    while (key[2 * h] >= 0) {
        if (key[2 * h] == lo && key[2 * h + 1] == hi) return val[h];
        h = (h + 1) % cap;
    }
    x = 0.5 * (m->pos[3 * a] + m->pos[3 * b]) - c[0];
    y = 0.5 * (m->pos[3 * a + 1] + m->pos[3 * b + 1]) - c[1];
    z = 0.5 * (m->pos[3 * a + 2] + m->pos[3 * b + 2]) - c[2];
    l = sqrt(x * x + y * y + z * z);
    key[2 * h] = lo, key[2 * h + 1] = hi;
    return val[h] = tm_vert(m, c[0] + r * x / l, c[1] + r * y / l, c[2] + r * z / l);
}

static void icosphere(tmesh *m, int level, double r, double cx, double cy, double cz)
{
    static const int F[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    double t = (1.0 + sqrt(5.0)) / 2.0, c[3], V[12][3];
    int i, lv, base = m->nv, *tris, nt = 20;
    c[0] = cx, c[1] = cy, c[2] = cz;
    for (i = 0; i < 12; i++) { /* (+-1, +-t, 0) and cyclic permutations */
        double a = (i & 1) ? 1 : -1, b = (i & 2) ? -t : t, p[3];
        int k = i / 4;
        p[k] = a, p[(k + 1) % 3] = b, p[(k + 2) % 3] = 0;
        V[i][0] = p[0], V[i][1] = p[1], V[i][2] = p[2];
    }
    for (i = 0; i < 12; i++) {
        double l = sqrt(V[i][0] * V[i][0] + V[i][1] * V[i][1] + V[i][2] * V[i][2]);
        tm_vert(m, cx + r * V[i][0] / l, cy + r * V[i][1] / l, cz + r * V[i][2] / l);
    }
    tris = (int *)malloc(sizeof(int) * 3 * 20);
    for (i = 0; i < 20; i++)
        tris[3 * i] = base + F[i][0], tris[3 * i + 1] = base + F[i][1], tris[3 * i + 2] = base + F[i][2];
    for (lv = 0; lv < level; lv++) {
        int cap = 6 * nt + 7, *key = (int *)malloc(sizeof(int) * 2 * cap),
            *val = (int *)malloc(sizeof(int) * cap);
        int *nx = (int *)malloc(sizeof(int) * 12 * nt);
        for (i = 0; i < 2 * cap; i++) key[i] = -1;
        for (i = 0; i < nt; i++) {
            int a = tris[3 * i], b = tris[3 * i + 1], d = tris[3 * i + 2];
            int ab = ico_mid(m, key, val, cap, a, b, r, c), bd = ico_mid(m, key, val, cap, b, d, r, c);
            int da = ico_mid(m, key, val, cap, d, a, r, c), *o = nx + 12 * i;
            o[0] = a, o[1] = ab, o[2] = da, o[3] = ab, o[4] = b, o[5] = bd;
            o[6] = da, o[7] = bd, o[8] = d, o[9] = ab, o[10] = bd, o[11] = da;
        }
        free(tris);
        free(key);
        free(val);
        tris = nx;
        nt *= 4;
    }
    for (i = 0; i < nt; i++) {
        const float *p = m->pos + 3 * tris[3 * i];
        tm_tri(m, tris[3 * i], tris[3 * i + 1], tris[3 * i + 2], p[0] - cx, p[1] - cy, p[2] - cz);
    }
    free(tris);
}

/* Open tube around the y axis: radius 1, y in [-2, 2]. */
static void cylinder(tmesh *m, int nu, int nv)
{
    int i, j;
    for (j = 0; j <= nv; j++)
        for (i = 0; i < nu; i++) tm_vert(m, cos(2 * PI * i / nu), -2.0 + 4.0 * j / nv, sin(2 * PI * i / nu));
    for (j = 0; j < nv; j++)
        for (i = 0; i < nu; i++) {
            int a = j * nu + i, b = j * nu + (i + 1) % nu, c = a + nu, d = b + nu;
            double hx = cos(2 * PI * (i + 0.5) / nu), hz = sin(2 * PI * (i + 0.5) / nu);
            tm_tri(m, a, b, d, hx, 0, hz);
            tm_tri(m, a, d, c, hx, 0, hz);
        }
}

/* Flat n x n grid of [-1, 1]^2 in the xz plane, normal +y. */
static void grid(tmesh *m, int n)
{
    int i, j;
    for (j = 0; j <= n; j++)
        for (i = 0; i <= n; i++) tm_vert(m, -1.0 + 2.0 * i / n, 0.0, -1.0 + 2.0 * j / n);
    for (j = 0; j < n; j++)
        for (i = 0; i < n; i++) {
            int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            tm_tri(m, a, b, d, 0, 1, 0);
            tm_tri(m, a, d, c, 0, 1, 0);
        }
}

/* Torus around the y axis: ring radius R, tube radius r. */
static void torus(tmesh *m, double R, double r, int nu, int nv)
{
    int i, j;
    for (j = 0; j < nv; j++)
        for (i = 0; i < nu; i++) {
            double ph = 2 * PI * i / nu, th = 2 * PI * j / nv;
            tm_vert(m, (R + r * cos(th)) * cos(ph), r * sin(th), (R + r * cos(th)) * sin(ph));
        }
    for (j = 0; j < nv; j++)
        for (i = 0; i < nu; i++) {
            int a = j * nu + i, b = j * nu + (i + 1) % nu, c = ((j + 1) % nv) * nu + i,
                d = ((j + 1) % nv) * nu + (i + 1) % nu;
            double ph = 2 * PI * (i + 0.5) / nu, th = 2 * PI * (j + 0.5) / nv;
            double hx = cos(th) * cos(ph), hy = sin(th), hz = cos(th) * sin(ph);
            tm_tri(m, a, b, d, hx, hy, hz);
            tm_tri(m, a, d, c, hx, hy, hz);
        }
}

/* The cube [-1, 1]^3 with an n x n grid on each face (shared edges). */
static void cube(tmesh *m, int n)
{
    int *id = (int *)malloc(sizeof(int) * (n + 1) * (n + 1) * (n + 1)), ax, side, u, v, k;
    for (k = 0; k < (n + 1) * (n + 1) * (n + 1); k++) id[k] = -1;
    for (ax = 0; ax < 3; ax++)
        for (side = 0; side < 2; side++)
            for (v = 0; v < n; v++)
                for (u = 0; u < n; u++) {
                    int q[4], c;
                    double h[3] = {0, 0, 0};
                    h[ax] = side ? 1 : -1;
                    for (c = 0; c < 4; c++) {
                        int L[3], li;
                        L[ax] = side * n;
                        L[(ax + 1) % 3] = u + (c == 1 || c == 2);
                        L[(ax + 2) % 3] = v + (c >= 2);
                        li = (L[0] * (n + 1) + L[1]) * (n + 1) + L[2];
                        if (id[li] < 0)
                            id[li] = tm_vert(m, -1.0 + 2.0 * L[0] / n, -1.0 + 2.0 * L[1] / n,
                                             -1.0 + 2.0 * L[2] / n);
                        q[c] = id[li];
                    }
                    tm_tri(m, q[0], q[1], q[2], h[0], h[1], h[2]);
                    tm_tri(m, q[0], q[2], q[3], h[0], h[1], h[2]);
                }
    free(id);
}

/* ---- geometry seen from the test ---------------------------------------- */

static void tnormal(const lapped_mesh *m, int f, double n[3])
{
    const float *p = m->positions + 3 * m->face_verts[3 * f],
                *q = m->positions + 3 * m->face_verts[3 * f + 1],
                *r = m->positions + 3 * m->face_verts[3 * f + 2];
    double u[3], v[3], l;
    int k;
    for (k = 0; k < 3; k++) u[k] = q[k] - p[k], v[k] = r[k] - p[k];
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
    l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (k = 0; k < 3; k++) n[k] /= l;
}

static void tcentroid(const lapped_mesh *m, int f, double c[3])
{
    int k, i;
    for (k = 0; k < 3; k++) {
        c[k] = 0;
        for (i = 0; i < 3; i++) c[k] += m->positions[3 * m->face_verts[3 * f + i] + k] / 3.0;
    }
}

static double dot3(const double *a, const float *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static double fdot(const float *a, const float *b)
{
    return (double)a[0] * b[0] + (double)a[1] * b[1] + (double)a[2] * b[2];
}
static double flen(const float *a) { return sqrt(fdot(a, a)); }

/* Angle in degrees between two 3D vectors. */
static double fangle(const float *a, const float *b)
{
    double c = fdot(a, b) / (flen(a) * flen(b));
    return acos(c > 1 ? 1 : (c < -1 ? -1 : c)) * 180.0 / PI;
}

/* Neighbouring triangle pairs (each interior edge once), by sorting edges. */
typedef struct tedge {
    int lo, hi, f;
} tedge;

static int tedge_cmp(const void *x, const void *y)
{
    const tedge *a = (const tedge *)x, *b = (const tedge *)y;
    if (a->lo != b->lo) return a->lo < b->lo ? -1 : 1;
    if (a->hi != b->hi) return a->hi < b->hi ? -1 : 1;
    return a->f < b->f ? -1 : (a->f > b->f);
}

/* Neighbouring triangles: pairs[4i] and pairs[4i+1] share the edge
 * pairs[4i+2] - pairs[4i+3]. */
static int tpairs(const lapped_mesh *m, int **pairs)
{
    int nt = m->nfaces, i, k, n = 0;
    tedge *e = (tedge *)malloc(sizeof(tedge) * 3 * nt);
    *pairs = (int *)malloc(sizeof(int) * 6 * nt);
    for (i = 0; i < nt; i++)
        for (k = 0; k < 3; k++) {
            int a = m->face_verts[3 * i + k], b = m->face_verts[3 * i + (k + 1) % 3];
            e[3 * i + k].lo = a < b ? a : b, e[3 * i + k].hi = a < b ? b : a, e[3 * i + k].f = i;
        }
    qsort(e, (size_t)3 * nt, sizeof(tedge), tedge_cmp);
    for (i = 0; i + 1 < 3 * nt; i++)
        if (e[i].lo == e[i + 1].lo && e[i].hi == e[i + 1].hi) {
            int *q = *pairs + 4 * n++;
            q[0] = e[i].f, q[1] = e[i + 1].f, q[2] = e[i].lo, q[3] = e[i].hi;
        }
    free(e);
    return n;
}

/* Angle (degrees) between T of the two triangles of pair q, the second
 * unfolded about the shared edge into the first one's plane: the turn of
 * the field itself, without the bend of the surface. */
static double unfolded_turn(const lapped_mesh *m, const int *q, const float *t)
{
    const float *pa = m->positions + 3 * q[2], *pb = m->positions + 3 * q[3], *tg = t + 3 * q[1];
    double e[3], nf[3], ng[3], bf[3], bg[3], l, a, b, c;
    float w[3];
    int k;
    for (k = 0; k < 3; k++) e[k] = pb[k] - pa[k];
    l = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    for (k = 0; k < 3; k++) e[k] /= l;
    tnormal(m, q[0], nf);
    tnormal(m, q[1], ng);
    for (k = 0; k < 3; k++) {
        bf[k] = nf[(k + 1) % 3] * e[(k + 2) % 3] - nf[(k + 2) % 3] * e[(k + 1) % 3];
        bg[k] = ng[(k + 1) % 3] * e[(k + 2) % 3] - ng[(k + 2) % 3] * e[(k + 1) % 3];
    }
    a = dot3(e, tg), b = dot3(bg, tg), c = dot3(ng, tg);
    for (k = 0; k < 3; k++) w[k] = (float)(a * e[k] + b * bf[k] + c * nf[k]);
    return fangle(t + 3 * q[0], w);
}

static int dcmp(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return a < b ? -1 : (a > b);
}

/* Quantile q of n values (sorted in place). */
static double quantile(double *v, int n, double q)
{
    qsort(v, (size_t)n, sizeof(double), dcmp);
    return n ? v[(int)(q * (n - 1) + 0.5)] : 0.0;
}

/* Median turn (degrees) of T between neighbouring triangles (unfolded). */
static double median_turn(const lapped_mesh *m, const float *t)
{
    int *pairs, n = tpairs(m, &pairs), i;
    double *a = (double *)malloc(sizeof(double) * (n + 1)), med;
    for (i = 0; i < n; i++) a[i] = unfolded_turn(m, pairs + 4 * i, t);
    med = quantile(a, n, 0.5);
    free(a);
    free(pairs);
    return med;
}

/* The §3.2 frame properties: T in the plane, |T| = scale (if scale > 0),
 * S perpendicular to T, |S| = |T|, S = T x N. Returns the failures. */
static int check_frames(const lapped_mesh *m, const float *s, const float *t, double scale, const char *what)
{
    int f, bad = 0;
    for (f = 0; f < m->nfaces; f++) {
        double n[3], lt = flen(t + 3 * f), ls = flen(s + 3 * f), x[3];
        const float *T = t + 3 * f, *S = s + 3 * f;
        tnormal(m, f, n);
        x[0] = T[1] * n[2] - T[2] * n[1] - S[0];
        x[1] = T[2] * n[0] - T[0] * n[2] - S[1];
        x[2] = T[0] * n[1] - T[1] * n[0] - S[2];
        if (!(fabs(dot3(n, T)) <= 1e-4 * lt) || (scale > 0 && !(fabs(lt - scale) <= 1e-4 * scale)) ||
            !(fabs(fdot(S, T)) <= 1e-4 * lt * lt) || !(fabs(ls - lt) <= 1e-4 * lt) ||
            !(sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]) <= 1e-4 * lt)) {
            if (bad++ < 3)
                CHECKF(0, "%s: triangle %d: T.N %g |T| %g (scale %g) S.T %g |S| %g", what, f, dot3(n, T), lt,
                       scale, fdot(S, T), ls);
        }
    }
    return bad;
}

/* lapped_compute_field into the caller's arrays s and t (ntris*3 each):
 * the lapped_field's arrays copied there, then freed with its allocator. */
static lapped_result field_into(const lapped_mesh *m, const lapped_options *o, float *s, float *t,
                                lapped_error *err)
{
    lapped_field f;
    lapped_result r = lapped_compute_field(m, o, &f, err);
    if (r == LAPPED_OK) {
        memcpy(s, f.s, sizeof(float) * 3 * (size_t)f.ntris);
        memcpy(t, f.t, sizeof(float) * 3 * (size_t)f.ntris);
    } else
        CHECK(f.ntris == 0 && !f.s && !f.t); /* a failed call leaves its output zeroed */
    lapped_field_free(&f);
    return r;
}

/* Runs one field; returns the result code, s and t malloc'ed (ntris*3). */
static lapped_result run(const lapped_mesh *m, const lapped_options *o, float **s, float **t,
                         lapped_error *err)
{
    *s = (float *)malloc(sizeof(float) * 3 * m->nfaces);
    *t = (float *)malloc(sizeof(float) * 3 * m->nfaces);
    return field_into(m, o, *s, *t, err);
}

static lapped_options field_opts(int mode, float scale)
{
    lapped_options o = lapped_default_options();
    o.field = mode;
    o.scale = scale;
    return o;
}

static lapped_constraint con(int face, float dx, float dy, float dz, float scale, float radius)
{
    lapped_constraint c;
    memset(&c, 0, sizeof c);
    c.face = face;
    c.direction[0] = dx, c.direction[1] = dy, c.direction[2] = dz;
    c.scale = scale;
    c.radius = radius;
    return c;
}

static void expect_error(const lapped_mesh *m, const lapped_options *o, float *s, float *t,
                         lapped_result code, const char *needles, const char *what);

/* ---- test meshes ----------------------------------------------------------- */

enum { M_SPHERE, M_CYLINDER, M_GRID, M_TORUS, M_CUBE, M_COUNT };
static const char *const mesh_names[M_COUNT] = {"icosphere", "cylinder", "grid", "torus", "cube"};

static void build(int which, tmesh *m)
{
    memset(m, 0, sizeof *m);
    if (which == M_SPHERE) icosphere(m, 3, 1.0, 0, 0, 0);
    if (which == M_CYLINDER) cylinder(m, 64, 32);
    if (which == M_GRID) grid(m, 24);
    if (which == M_TORUS) torus(m, 1.0, 0.3, 96, 32);
    if (which == M_CUBE) cube(m, 8);
}

/* ---- cases ------------------------------------------------------------------ */

/* Every mode on every mesh: T in the face plane, |T| = scale, S = T x N. */
static void t_frames_every_mode(void)
{
    static const int modes[4] = {LAPPED_FIELD_UP, LAPPED_FIELD_ISOTROPIC, LAPPED_FIELD_CONSTRAINTS,
                                 LAPPED_FIELD_CURVATURE};
    static const char *const mode_names[4] = {"UP", "ISOTROPIC", "CONSTRAINTS", "CURVATURE"};
    int w, i;
    for (w = 0; w < M_COUNT; w++) {
        tmesh tm;
        int *fs;
        lapped_mesh m;
        build(w, &tm);
        fs = (int *)malloc(sizeof(int) * (tm.nt + 1));
        m = tm_view(&tm, fs);
        for (i = 0; i < 4; i++) {
            lapped_options o = field_opts(modes[i], 0.25f);
            lapped_constraint c[2];
            lapped_error err;
            float *s, *t;
            char what[64];
            c[0] = con(0, 1, 0.3f, 0.2f, 0, 0);
            c[1] = con(tm.nt - 1, -0.2f, 0.1f, 1, 0, 0);
            o.constraints = c;
            o.nconstraints = 2;
            snprintf(what, sizeof what, "%s %s", mesh_names[w], mode_names[i]);
            CHECKF(run(&m, &o, &s, &t, &err) == LAPPED_OK, "%s: %s", what, err.message);
            /* CONSTRAINTS blends the scales: both are the field's here */
            CHECK(check_frames(&m, s, t, 0.25, what) == 0);
            if (i == 0 && w == M_SPHERE) pwt_info("icosphere: %d triangles", tm.nt);
            free(s);
            free(t);
        }
        free(fs);
        tm_free(&tm);
    }
}

/* FACES passes the caller's frame through (projected), S = T x N when
 * face_s is NULL; scale 0 in the options takes the default elsewhere. */
static void t_faces_pass_through(void)
{
    tmesh tm;
    int *fs, f, k, bad = 0;
    lapped_mesh m;
    lapped_options o = field_opts(LAPPED_FIELD_FACES, 0);
    lapped_error err;
    float *ft, *fsv, *s, *t;
    build(M_TORUS, &tm);
    fs = (int *)malloc(sizeof(int) * (tm.nt + 1));
    m = tm_view(&tm, fs);
    ft = (float *)malloc(sizeof(float) * 3 * tm.nt);
    fsv = (float *)malloc(sizeof(float) * 3 * tm.nt);
    for (f = 0; f < tm.nt; f++) { /* tangent vectors of varying length and a sheared S */
        double n[3], a[3] = {0.3, 1.0, -0.4}, d, len = 0.05 + 0.001 * (f % 100);
        float *T = ft + 3 * f, *S = fsv + 3 * f;
        tnormal(&m, f, n);
        d = a[0] * n[0] + a[1] * n[1] + a[2] * n[2];
        for (k = 0; k < 3; k++) a[k] -= d * n[k];
        d = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        for (k = 0; k < 3; k++) T[k] = (float)(len * a[k] / d);
        S[0] = (float)(T[1] * n[2] - T[2] * n[1] + 0.3 * T[0]);
        S[1] = (float)(T[2] * n[0] - T[0] * n[2] + 0.3 * T[1]);
        S[2] = (float)(T[0] * n[1] - T[1] * n[0] + 0.3 * T[2]);
    }
    o.face_t = ft;
    o.face_s = fsv;
    REQUIRE(run(&m, &o, &s, &t, &err) == LAPPED_OK);
    for (f = 0; f < 3 * tm.nt; f++)
        if (!(fabs(t[f] - ft[f]) <= 1e-5 && fabs(s[f] - fsv[f]) <= 1e-5)) bad++;
    CHECKF(bad == 0, "%d coordinates differ", bad);
    o.face_s = NULL;
    REQUIRE(field_into(&m, &o, s, t, &err) == LAPPED_OK);
    CHECK(check_frames(&m, s, t, 0, "FACES S = T x N") == 0);
    for (bad = 0, f = 0; f < 3 * tm.nt; f++) bad += !(fabs(t[f] - ft[f]) <= 1e-5);
    CHECK(bad == 0);
    free(s), free(t), free(ft), free(fsv), free(fs);
    tm_free(&tm);
}

/* Polygons are fan-triangulated: one frame per triangle, constraint faces
 * are triangle indices. A 6 x 6 grid of quads bent into a half cylinder. */
static void t_polygons(void)
{
    int nq = 6, i, j, fs[37], fv[144], nt = 2 * 36;
    float pos[49 * 3], s[72 * 3], t[72 * 3], y[3] = {0, 1, 0};
    lapped_mesh m;
    lapped_options o = field_opts(LAPPED_FIELD_CURVATURE, 0.2f);
    lapped_constraint c[1];
    lapped_error err;
    for (j = 0; j <= nq; j++)
        for (i = 0; i <= nq; i++) {
            double a = PI * i / nq;
            float *p = pos + 3 * (j * (nq + 1) + i);
            p[0] = (float)cos(a), p[1] = (float)(j * 0.5), p[2] = (float)sin(a);
        }
    for (j = 0; j < nq; j++)
        for (i = 0; i < nq; i++) {
            int *q = fv + 4 * (j * nq + i), a = j * (nq + 1) + i;
            q[0] = a, q[1] = a + nq + 1, q[2] = a + nq + 2, q[3] = a + 1; /* outward */
            fs[j * nq + i] = 4 * (j * nq + i);
        }
    fs[36] = 144;
    memset(&m, 0, sizeof m);
    m.nverts = 49, m.positions = pos, m.nfaces = 36, m.face_start = fs, m.face_verts = fv;
    REQUIRE(field_into(&m, &o, s, t, &err) == LAPPED_OK);
    for (i = 0; i < nt; i++) {
        double a = fangle(t + 3 * i, y);
        CHECKF(a < 1.0, "triangle %d: %g deg from the axis", i, a);
    }
    { /* the lapped_field itself: one frame per triangle, not per polygon; freed to zeros */
        lapped_field f;
        REQUIRE(lapped_compute_field(&m, &o, &f, &err) == LAPPED_OK);
        CHECK(f.ntris == nt && f.s && f.t && !memcmp(f.t, t, sizeof t) && !memcmp(f.s, s, sizeof s));
        lapped_field_free(&f);
        CHECK(f.ntris == 0 && !f.s && !f.t);
        lapped_field_free(&f); /* safe on a freed field, and on NULL */
        lapped_field_free(NULL);
    }
    o.field = LAPPED_FIELD_CONSTRAINTS;
    c[0] = con(nt - 1, 0, 1, 0, 0, 0);
    o.constraints = c;
    o.nconstraints = 1;
    CHECKF(field_into(&m, &o, s, t, &err) == LAPPED_OK, "%s", err.message);
    c[0].face = nt;
    expect_error(&m, &o, s, t, LAPPED_ERR_INVALID, "triangle 72|has 72", "constraint on polygon index");
}

/* UP on a sphere: T follows up projected onto each face, away from the
 * poles (where the projection vanishes and the field is singular). */
static void t_up_sphere(void)
{
    tmesh tm;
    int *fs, f, k, bad = 0, n = 0;
    lapped_mesh m;
    lapped_options o = field_opts(LAPPED_FIELD_UP, 0.2f);
    lapped_error err;
    float *s, *t;
    double worst = 0;
    build(M_SPHERE, &tm);
    fs = (int *)malloc(sizeof(int) * (tm.nt + 1));
    m = tm_view(&tm, fs);
    o.up[0] = 0.0f, o.up[1] = 0.0f, o.up[2] = 2.0f; /* +z, not unit */
    REQUIRE(run(&m, &o, &s, &t, &err) == LAPPED_OK);
    for (f = 0; f < tm.nt; f++) {
        double nn[3], up[3] = {0, 0, 1}, d, a;
        float p[3];
        tnormal(&m, f, nn);
        d = nn[2];
        if (fabs(d) > 0.98) continue; /* within ~11 degrees of a pole */
        for (k = 0; k < 3; k++) p[k] = (float)(up[k] - d * nn[k]);
        a = fangle(t + 3 * f, p);
        if (a > worst) worst = a;
        bad += !(fdot(t + 3 * f, p) > 0);
        n++;
    }
    CHECKF(bad == 0 && worst < 0.01, "%d of %d faces do not point up, worst %g deg", bad, n, worst);
    pwt_info("UP on the icosphere: %d faces off the poles, largest angle to projected up %.2g deg", n, worst);
    free(s), free(t), free(fs);
    tm_free(&tm);
}

/* Where up is normal to the surface: a flat sheet normal to up takes the
 * fixed axis (x here); the top and bottom of a cube are filled from their
 * sides (T finite, in the plane, |T| = scale). */
static void t_up_normal_to_surface(void)
{
    tmesh tm;
    int *fs, f, bad = 0;
    lapped_mesh m;
    lapped_options o = field_opts(LAPPED_FIELD_UP, 0.1f);
    lapped_error err;
    float *s, *t, x[3] = {1, 0, 0};
    build(M_GRID, &tm);
    fs = (int *)malloc(sizeof(int) * (tm.nt + 1));
    m = tm_view(&tm, fs);
    REQUIRE(run(&m, &o, &s, &t, &err) == LAPPED_OK);
    CHECK(check_frames(&m, s, t, 0.1, "grid normal to up") == 0);
    for (f = 0; f < tm.nt; f++) bad += !(fangle(t + 3 * f, x) < 1e-3);
    CHECKF(bad == 0, "%d faces not along x", bad);
    free(s), free(t), free(fs);
    tm_free(&tm);
    build(M_CUBE, &tm);
    fs = (int *)malloc(sizeof(int) * (tm.nt + 1));
    m = tm_view(&tm, fs);
    REQUIRE(run(&m, &o, &s, &t, &err) == LAPPED_OK);
    CHECK(check_frames(&m, s, t, 0.1, "cube with up normal to top") == 0);
    free(s), free(t), free(fs);
    tm_free(&tm);
}

/* ---- no bullseye where up is normal to the surface (issue 18) ------------- */

/* Largest angle (degrees) between T of any two triangles whose normal is
 * within 1 degree of +y and whose centroid is above y0: the spread of the
 * field over a flat up-facing region. *n gets how many there are. */
static double up_spread(const lapped_mesh *m, const float *t, double y0, int *n)
{
    int f, g, *sel = (int *)malloc(sizeof(int) * m->nfaces);
    double worst = 0.0;
    *n = 0;
    for (f = 0; f < m->nfaces; f++) {
        double nn[3], c[3];
        tnormal(m, f, nn);
        tcentroid(m, f, c);
        if (nn[1] > cos(PI / 180.0) && c[1] > y0) sel[(*n)++] = f;
    }
    for (f = 0; f < *n; f++)
        for (g = f + 1; g < *n; g++) {
            double a = fangle(t + 3 * sel[f], t + 3 * sel[g]);
            if (a > worst) worst = a;
        }
    free(sel);
    return worst;
}

/* Kinks of the field off the creases: neighbouring triangles (dihedral
 * under 30 degrees) whose T turn by more than 30 degrees unfolded, among
 * those with both centroids above y0; *far gets the largest horizontal
 * distance of such an edge from the y axis (a point singularity on the
 * axis keeps its kinks within a ring of it). */
static int up_kinks(const lapped_mesh *m, const float *t, double y0, double *far)
{
    int *pairs, n = tpairs(m, &pairs), i, kinks = 0;
    *far = 0.0;
    for (i = 0; i < n; i++) {
        double na[3], nb[3], ca[3], cb[3], r;
        const int *q = pairs + 4 * i;
        tnormal(m, q[0], na);
        tnormal(m, q[1], nb);
        tcentroid(m, q[0], ca);
        tcentroid(m, q[1], cb);
        if (na[0] * nb[0] + na[1] * nb[1] + na[2] * nb[2] < cos(PI / 6.0) || ca[1] <= y0 || cb[1] <= y0) continue;
        if (unfolded_turn(m, q, t) <= 30.0) continue;
        kinks++;
        r = sqrt(0.25 * (ca[0] + cb[0]) * (ca[0] + cb[0]) + 0.25 * (ca[2] + cb[2]) * (ca[2] + cb[2]));
        if (r > *far) *far = r;
    }
    free(pairs);
    return kinks;
}

/* Runs UP (+y) on tm and reports the spread over its up-facing flats above
 * y0 and the kinks above y1. */
static void up_case(tmesh *tm, const char *what, double y0, double y1, double *spread, int *kinks, double *far)
{
    int *fs = (int *)malloc(sizeof(int) * (tm->nt + 1)), n;
    lapped_mesh m = tm_view(tm, fs);
    lapped_options o = field_opts(LAPPED_FIELD_UP, 0.2f);
    lapped_error err;
    float *s, *t;
    REQUIRE(run(&m, &o, &s, &t, &err) == LAPPED_OK);
    CHECK(check_frames(&m, s, t, 0.2, what) == 0);
    *spread = up_spread(&m, t, y0, &n);
    *kinks = up_kinks(&m, t, y1, far);
    pwt_info("%s: %d up-facing flat triangles, spread %.2f deg; %d kinks above y = %g, within %.3f of the axis",
             what, n, *spread, *kinks, y1, *far);
    free(s), free(t), free(fs);
}

/* A box: the cube scaled by (sx, sy, sz). */
static void box(tmesh *m, int n, double sx, double sy, double sz)
{
    int v;
    memset(m, 0, sizeof *m);
    cube(m, n);
    for (v = 0; v < m->nv; v++) m->pos[3 * v] *= (float)sx, m->pos[3 * v + 1] *= (float)sy, m->pos[3 * v + 2] *= (float)sz;
}

/* The top of a cube and of a table-like slab: flat, bounded by 90-degree
 * creases. The field jumps across the creases and stays uniform on top
 * (issue 18: at most 15 degrees; propagation from the sides drew rings, a
 * spread of 180 degrees). */
static void t_up_box_tops(void)
{
    tmesh tm;
    double spread, far;
    int kinks;
    box(&tm, 12, 1.0, 1.0, 1.0);
    up_case(&tm, "cube top", 0.99, 0.99, &spread, &kinks, &far);
    CHECKF(spread <= 15.0 && kinks == 0, "cube top: spread %.1f deg, %d kinks", spread, kinks);
    tm_free(&tm);
    box(&tm, 16, 2.0, 0.08, 1.0);
    up_case(&tm, "table top", 0.079, 0.079, &spread, &kinks, &far);
    CHECKF(spread <= 15.0 && kinks == 0, "table top: spread %.1f deg, %d kinks", spread, kinks);
    tm_free(&tm);
}

/* A sphere's pole and the top of a sphere squashed to a fifth of its
 * height (smooth caps, the second one wide and nearly flat): one clean
 * point singularity on the axis, every kink within two rings of it. */
static void t_up_sphere_pole(void)
{
    tmesh tm;
    double spread, far;
    int kinks, v;
    memset(&tm, 0, sizeof tm);
    icosphere(&tm, 4, 1.0, 0, 0, 0); /* edges ~0.08 */
    up_case(&tm, "sphere pole", 2.0, 0.9, &spread, &kinks, &far);
    CHECKF(kinks <= 12 && far <= 0.2, "sphere pole: %d kinks, as far as %.3f from the axis", kinks, far);
    for (v = 0; v < tm.nv; v++) tm.pos[3 * v + 1] *= 0.2f; /* a flattened top, like a head's */
    up_case(&tm, "squashed sphere top", 2.0, 0.19, &spread, &kinks, &far);
    CHECKF(kinks <= 12 && far <= 0.2, "squashed sphere top: %d kinks, as far as %.3f from the axis", kinks, far);
    tm_free(&tm);
}

/* A terrain: a 48 x 48 height field with a flat square mesa (y = 0.3,
 * sides on grid lines, 45-degree cliffs: creases) and a smooth hill. The
 * mesa top stays uniform; the hill's top keeps one point singularity. */
static void t_up_terrain(void)
{
    tmesh tm;
    double spread, far;
    int kinks, v;
    memset(&tm, 0, sizeof tm);
    grid(&tm, 48);
    for (v = 0; v < tm.nv; v++) {
        float *p = tm.pos + 3 * v;
        double dx = fabs(p[0] + 0.5), dz = fabs(p[2] + 0.5), rm = dx > dz ? dx : dz;
        double rh = (p[0] - 0.5) * (p[0] - 0.5) + (p[2] - 0.5) * (p[2] - 0.5);
        double mesa = rm < 0.25 ? 0.3 : (rm < 0.55 ? 0.3 - (rm - 0.25) : 0.0);
        p[1] = (float)(mesa + 0.6 * exp(-rh / 0.04));
    }
    up_case(&tm, "terrain mesa", 0.29, 5.0, &spread, &kinks, &far);
    CHECKF(spread <= 15.0, "terrain mesa: spread %.1f deg", spread);
    for (v = 0; v < tm.nv; v++) tm.pos[3 * v] -= 0.5f, tm.pos[3 * v + 2] -= 0.5f; /* the hill on the axis */
    up_case(&tm, "terrain hill", 5.0, 0.35, &spread, &kinks, &far);
    CHECKF(kinks <= 12 && far <= 0.12, "terrain hill: %d kinks, as far as %.3f from its top", kinks, far);
    tm_free(&tm);
}

/* Index of the grid triangle whose centroid is nearest to (x, z). */
static int grid_face(const lapped_mesh *m, double x, double z)
{
    int f, best = 0;
    double bd = 1e30, c[3];
    for (f = 0; f < m->nfaces; f++) {
        tcentroid(m, f, c);
        if ((c[0] - x) * (c[0] - x) + (c[2] - z) * (c[2] - z) < bd)
            bd = (c[0] - x) * (c[0] - x) + (c[2] - z) * (c[2] - z), best = f;
    }
    return best;
}

/* One constraint: reproduced at its face; two: blended halfway, smooth,
 * each scale respected near its own constraint; deterministic. */
static void t_constraints_grid(void)
{
    tmesh tm;
    int *fs, fa, fb, fm;
    lapped_mesh m;
    lapped_options o = field_opts(LAPPED_FIELD_CONSTRAINTS, 0.1f);
    lapped_constraint c[2];
    lapped_error err;
    float *s, *t, *s2, *t2, x[3] = {1, 0, 0}, z[3] = {0, 0, 1};
    double a, turn;
    build(M_GRID, &tm);
    fs = (int *)malloc(sizeof(int) * (tm.nt + 1));
    m = tm_view(&tm, fs);
    fa = grid_face(&m, -0.8, 0.0), fb = grid_face(&m, 0.8, 0.0), fm = grid_face(&m, 0.0, 0.0);
    c[0] = con(fa, 3, 0.5f, 0, 0.05f, 0.6f); /* x (the y part is normal to the grid) */
    c[1] = con(fb, 0, 0, 1, 0.2f, 0.6f);     /* z */
    o.constraints = c;
    o.nconstraints = 1;
    REQUIRE(run(&m, &o, &s, &t, &err) == LAPPED_OK);
    CHECKF(fangle(t + 3 * fa, x) < 1e-3, "single constraint: %g deg off at its face", fangle(t + 3 * fa, x));
    CHECK(check_frames(&m, s, t, 0.05, "single constraint scale") == 0);
    o.nconstraints = 2;
    REQUIRE(field_into(&m, &o, s, t, &err) == LAPPED_OK);
    CHECK(check_frames(&m, s, t, 0, "two constraints") == 0);
    a = fangle(t + 3 * fm, x);
    CHECKF(fabs(a - 45.0) < 4.0 && fangle(t + 3 * fm, z) < 50.0, "halfway: %g deg from x", a);
    CHECKF(fangle(t + 3 * fa, x) < 0.5 && fangle(t + 3 * fb, z) < 0.5, "constraints not reproduced: %g %g",
           fangle(t + 3 * fa, x), fangle(t + 3 * fb, z));
    CHECKF(fabs(flen(t + 3 * fa) - 0.05) < 0.001 && fabs(flen(t + 3 * fb) - 0.2) < 0.004,
           "scales at the constraints %g %g", flen(t + 3 * fa), flen(t + 3 * fb));
    CHECKF(flen(t + 3 * fm) > 0.06 && flen(t + 3 * fm) < 0.19, "scale halfway %g", flen(t + 3 * fm));
    turn = median_turn(&m, t);
    CHECKF(turn < 3.0, "median turn %g deg", turn);
    pwt_info(
        "grid %d tris: halfway %.2f deg from x (45 expected), |T| %.4f at 0.05, %.4f at 0.2, %.4f halfway; "
        "median turn between neighbours %.3f deg",
        tm.nt, a, flen(t + 3 * fa), flen(t + 3 * fb), flen(t + 3 * fm), turn);
    REQUIRE(run(&m, &o, &s2, &t2, &err) == LAPPED_OK);
    CHECK(memcmp(s, s2, sizeof(float) * 3 * tm.nt) == 0 && memcmp(t, t2, sizeof(float) * 3 * tm.nt) == 0);
    free(s), free(t), free(s2), free(t2), free(fs);
    tm_free(&tm);
}

/* On curved surfaces: smoothness, and numerical safety far (in Gaussian
 * units) from every constraint: tiny radii still give a finite field that
 * follows the nearest constraint. */
static void t_constraints_curved(void)
{
    tmesh tm;
    int *fs, f, w, bad;
    lapped_mesh m;
    lapped_options o = field_opts(LAPPED_FIELD_CONSTRAINTS, 0.2f);
    lapped_constraint c[3];
    lapped_error err;
    float *s, *t;
    for (w = 0; w < 2; w++) {
        build(w ? M_TORUS : M_SPHERE, &tm);
        fs = (int *)malloc(sizeof(int) * (tm.nt + 1));
        m = tm_view(&tm, fs);
        c[0] = con(0, 0, 1, 0, 0, 0.5f);
        c[1] = con(tm.nt / 3, 1, 0, 0, 0, 0.5f);
        c[2] = con(2 * tm.nt / 3, 0, 0, 1, 0, 0.5f);
        o.constraints = c;
        o.nconstraints = 3;
        REQUIRE(run(&m, &o, &s, &t, &err) == LAPPED_OK);
        pwt_info("%s (%d tris), 3 constraints, radius 0.5: median turn between neighbours %.3f deg",
                 mesh_names[w ? M_TORUS : M_SPHERE], tm.nt, median_turn(&m, t));
        CHECK(median_turn(&m, t) < 5.0);
        c[0].radius = c[1].radius = c[2].radius = 1e-4f; /* exp(-d^2/2r^2) underflows everywhere else */
        REQUIRE(field_into(&m, &o, s, t, &err) == LAPPED_OK);
        CHECK(check_frames(&m, s, t, 0.2, "tiny radii") == 0);
        for (bad = 0, f = 0; f < 3 * tm.nt; f++) bad += !pw_is_finite(t[f]) || !pw_is_finite(s[f]);
        CHECK(bad == 0);
        pwt_info("%s, radii 1e-4: median turn %.3f deg (piecewise: nearest constraint)",
                 mesh_names[w ? M_TORUS : M_SPHERE], median_turn(&m, t));
        free(s), free(t), free(fs);
        tm_free(&tm);
    }
}

/* A component that no constraint reaches takes the constraint nearest in
 * triangle index (documented); the constrained one is unaffected. */
static void t_constraints_components(void)
{
    tmesh tm;
    int *fs, f, n1;
    lapped_mesh m;
    lapped_options o = field_opts(LAPPED_FIELD_CONSTRAINTS, 0.2f);
    lapped_constraint c[1];
    lapped_error err;
    float *s, *t, y[3] = {0, 1, 0};
    int bad = 0;
    memset(&tm, 0, sizeof tm);
    icosphere(&tm, 2, 1.0, 0, 0, 0);
    n1 = tm.nt;
    icosphere(&tm, 2, 1.0, 5, 0, 0);
    fs = (int *)malloc(sizeof(int) * (tm.nt + 1));
    m = tm_view(&tm, fs);
    c[0] = con(3, 0, 1, 0, 0, 0);
    c[0].direction[0] = 0.01f;
    o.constraints = c;
    o.nconstraints = 1;
    REQUIRE(run(&m, &o, &s, &t, &err) == LAPPED_OK);
    CHECK(check_frames(&m, s, t, 0.2, "two spheres, one constraint") == 0);
    { /* the constraint as stated: its direction projected onto its face */
        double n[3], d;
        int k;
        tnormal(&m, 3, n);
        d = 0.01 * n[0] + n[1];
        y[0] = (float)(0.01 - d * n[0]), y[1] = (float)(1.0 - d * n[1]), y[2] = (float)(-d * n[2]);
        d = flen(y);
        for (k = 0; k < 3; k++) y[k] = (float)(y[k] / d);
    }
    for (f = n1; f < tm.nt; f++) { /* second sphere: that direction projected, as an up field */
        double n[3];
        tnormal(&m, f, n);
        if (fabs(dot3(n, y)) < 0.95) bad += !(fdot(t + 3 * f, y) > 0);
    }
    CHECKF(bad == 0, "%d faces of the unconstrained sphere do not follow the fallback", bad);
    free(s), free(t), free(fs);
    tm_free(&tm);
}

/* CURVATURE on a cylinder: least curvature is along the axis (y). */
static void t_curvature_cylinder(void)
{
    tmesh tm;
    int *fs, f, up = 0;
    lapped_mesh m;
    lapped_options o = field_opts(LAPPED_FIELD_CURVATURE, 0.3f);
    lapped_error err;
    float *s, *t, y[3] = {0, 1, 0};
    double *a, med, p95;
    build(M_CYLINDER, &tm);
    fs = (int *)malloc(sizeof(int) * (tm.nt + 1));
    m = tm_view(&tm, fs);
    REQUIRE(run(&m, &o, &s, &t, &err) == LAPPED_OK);
    CHECK(check_frames(&m, s, t, 0.3, "cylinder CURVATURE") == 0);
    a = (double *)malloc(sizeof(double) * tm.nt);
    for (f = 0; f < tm.nt; f++) {
        a[f] = fangle(t + 3 * f, y);
        if (a[f] > 90) a[f] = 180 - a[f];
        up += fdot(t + 3 * f, y) > 0;
    }
    med = quantile(a, tm.nt, 0.5);
    p95 = quantile(a, tm.nt, 0.95);
    CHECKF(med < 2.0 && p95 < 5.0, "median %g, 95%% %g deg from the axis", med, p95);
    CHECKF(up == tm.nt, "signs: %d of %d along +y", up, tm.nt);
    pwt_info("cylinder %d tris: angle to the axis median %.3g deg, 95%% %.3g deg, max %.3g; %d/%d point +y",
             tm.nt, med, p95, a[tm.nt - 1], up, tm.nt);
    free(a), free(s), free(t), free(fs);
    tm_free(&tm);
}

/* CURVATURE on a torus (R = 1, r = 0.3): least |curvature| is around the
 * ring everywhere (|k_ring| <= 1/(R - r) < 1/r); signs consistent. */
static void t_curvature_torus(void)
{
    tmesh tm;
    int *fs, f, *pairs, np, flips = 0;
    lapped_mesh m;
    lapped_options o = field_opts(LAPPED_FIELD_CURVATURE, 0.3f);
    lapped_error err;
    float *s, *t;
    double *a, med, p95;
    build(M_TORUS, &tm);
    fs = (int *)malloc(sizeof(int) * (tm.nt + 1));
    m = tm_view(&tm, fs);
    REQUIRE(run(&m, &o, &s, &t, &err) == LAPPED_OK);
    CHECK(check_frames(&m, s, t, 0.3, "torus CURVATURE") == 0);
    a = (double *)malloc(sizeof(double) * tm.nt);
    for (f = 0; f < tm.nt; f++) {
        double c[3], ph;
        float ring[3];
        tcentroid(&m, f, c);
        ph = atan2(c[2], c[0]);
        ring[0] = (float)-sin(ph), ring[1] = 0, ring[2] = (float)cos(ph);
        a[f] = fangle(t + 3 * f, ring);
        if (a[f] > 90) a[f] = 180 - a[f];
    }
    med = quantile(a, tm.nt, 0.5);
    p95 = quantile(a, tm.nt, 0.95);
    np = tpairs(&m, &pairs);
    for (f = 0; f < np; f++) flips += unfolded_turn(&m, pairs + 4 * f, t) > 90.0;
    CHECKF(med < 2.0 && p95 < 5.0, "median %g, 95%% %g deg from the ring direction", med, p95);
    CHECKF(flips == 0, "%d sign flips between neighbours", flips);
    pwt_info(
        "torus %d tris: angle to the ring direction median %.3g deg, 95%% %.3g deg; %d of %d neighbour pairs "
        "with opposite signs",
        tm.nt, med, p95, flips, np);
    free(a), free(s), free(t), free(fs), free(pairs);
    tm_free(&tm);
}

/* CURVATURE where there is none (flat grid) or it has no direction
 * (sphere): the up field. */
static void t_curvature_fallbacks(void)
{
    tmesh tm;
    int *fs, f, bad = 0;
    lapped_mesh m;
    lapped_options o = field_opts(LAPPED_FIELD_CURVATURE, 0.3f);
    lapped_error err;
    float *s, *t, *s2, *t2;
    build(M_SPHERE, &tm);
    fs = (int *)malloc(sizeof(int) * (tm.nt + 1));
    m = tm_view(&tm, fs);
    REQUIRE(run(&m, &o, &s, &t, &err) == LAPPED_OK);
    o.field = LAPPED_FIELD_UP;
    REQUIRE(run(&m, &o, &s2, &t2, &err) == LAPPED_OK);
    for (f = 0; f < tm.nt; f++) bad += !(fangle(t + 3 * f, t2 + 3 * f) < 1.0);
    pwt_info("icosphere: %d of %d faces differ from the up field by over 1 deg", bad, tm.nt);
    CHECK(bad < tm.nt / 20);
    free(s), free(t), free(s2), free(t2), free(fs);
    tm_free(&tm);
}

/* Difficulty: high along the cube's creases, zero on the flat middle of
 * its faces; in [0, 1] everywhere; also high where the field turns. */
static void t_difficulty(void)
{
    tmesh tm;
    int *fs, f, nc = 0, nf = 0, r;
    lapped_mesh m;
    pw_trimesh lm;
    lapped_options o = field_opts(LAPPED_FIELD_UP, 0.4f);
    lapped_error err;
    pw_err e;
    pw_alloc a;
    float *s, *t, *d;
    double crease = 0, flat = 0, flat_max = 0, crease_min = 1;
    build(M_CUBE, &tm);
    fs = (int *)malloc(sizeof(int) * (tm.nt + 1));
    m = tm_view(&tm, fs);
    o.up[0] = 0.3f, o.up[1] = 1.0f, o.up[2] = 0.6f; /* no face normal to up */
    REQUIRE(run(&m, &o, &s, &t, &err) == LAPPED_OK);
    memset(&a, 0, sizeof a);
    pw_err_clear(&e);
    REQUIRE(lapped__mesh_init(&a, &m, &lm, &e) == PW_OK);
    d = (float *)malloc(sizeof(float) * tm.nt);
    r = lapped__difficulty(&a, &lm, t, d, &e);
    CHECK(r == PW_OK);
    for (f = 0; f < tm.nt; f++) {
        double c[3], n[3], u = 0;
        int k;
        tcentroid(&m, f, c);
        tnormal(&m, f, n);
        for (k = 0; k < 3; k++) /* largest in-plane coordinate: 1 at the cube's edges */
            if (fabs(n[k]) < 0.5 && fabs(c[k]) > u) u = fabs(c[k]);
        CHECK(d[f] >= 0.0f && d[f] <= 1.0f);
        if (u > 0.9) { /* touches a crease (cells are 0.25 wide) */
            int touches = 0;
            for (k = 0; k < 3; k++) {
                const float *p = m.positions + 3 * m.face_verts[3 * f + k];
                int j, ones = 0;
                for (j = 0; j < 3; j++) ones += fabs(fabs(p[j]) - 1.0) < 1e-6;
                touches |= ones >= 2;
            }
            if (!touches) continue;
            crease += d[f], nc++;
            if (d[f] < crease_min) crease_min = d[f];
        } else if (u < 0.5) {
            flat += d[f], nf++;
            if (d[f] > flat_max) flat_max = d[f];
        }
    }
    crease /= nc, flat /= nf;
    CHECKF(crease > 0.8 && flat_max < 1e-3 && crease_min > 0.5, "crease %g (min %g), flat %g (max %g)",
           crease, crease_min, flat, flat_max);
    pwt_info("cube: difficulty along creases mean %.3f (min %.3f, %d tris), flat middles mean %.2g (max "
             "%.2g, %d tris)",
             crease, crease_min, nc, flat, flat_max, nf);
    r = lapped__difficulty(&a, &lm, NULL, d, &e); /* curvature only */
    CHECK(r == PW_OK);
    free(d), free(s), free(t);
    pw_trimesh_free(&a, &lm);
    free(fs);
    tm_free(&tm);
}

/* Expects `code` and every word of `needles` (separated by '|') in the
 * message. */
static void expect_error(const lapped_mesh *m, const lapped_options *o, float *s, float *t,
                         lapped_result code, const char *needles, const char *what)
{
    lapped_error err;
    char buf[256], *p, *q;
    lapped_result r;
    memset(&err, 0, sizeof err);
    r = field_into(m, o, s, t, &err);
    CHECKF(r == code, "%s: result %d (%s), expected %d", what, (int)r, err.message, (int)code);
    snprintf(buf, sizeof buf, "%s", needles);
    for (p = buf; p && *p; p = q) {
        q = strchr(p, '|');
        if (q) *q++ = 0;
        CHECKF(strstr(err.message, p) != NULL, "%s: message '%s' lacks '%s'", what, err.message, p);
    }
}

static void t_bad_inputs(void)
{
    tmesh tm;
    int *fs;
    lapped_mesh m;
    lapped_options o;
    lapped_constraint c[2];
    lapped_error err;
    float *s, *t, *ft, nan = (float)(0.0 * HUGE_VAL);
    nan = nan - nan;
    build(M_SPHERE, &tm);
    fs = (int *)malloc(sizeof(int) * (tm.nt + 1));
    m = tm_view(&tm, fs);
    s = (float *)malloc(sizeof(float) * 3 * tm.nt);
    t = (float *)malloc(sizeof(float) * 3 * tm.nt);
    ft = (float *)calloc((size_t)3 * tm.nt, sizeof(float));
    o = field_opts(LAPPED_FIELD_CONSTRAINTS, 0.2f);
    c[0] = con(5, 1, 0, 0, 0, 0);
    c[1] = con(99999, 1, 0, 0, 0, 0);
    o.constraints = c;
    o.nconstraints = 2;
    expect_error(&m, &o, s, t, LAPPED_ERR_INVALID, "constraint 1|triangle 99999", "face out of range");
    c[1] = con(7, nan, 0, 0, 0, 0);
    expect_error(&m, &o, s, t, LAPPED_ERR_INVALID, "constraint 1|direction|not finite", "NaN direction");
    c[1] = con(7, 0, 0, 0, 0, 0);
    expect_error(&m, &o, s, t, LAPPED_ERR_INVALID, "constraint 1|direction is zero", "zero direction");
    c[1] = con(7, 1, 0, 0, 0, -1);
    expect_error(&m, &o, s, t, LAPPED_ERR_INVALID, "constraint 1|radius", "negative radius");
    c[1] = con(7, 1, 0, 0, -0.1f, 0);
    expect_error(&m, &o, s, t, LAPPED_ERR_INVALID, "constraint 1|scale", "negative constraint scale");
    c[1] = con(7, 1, 0, 0, 0, 0);
    c[1].weight = nan;
    expect_error(&m, &o, s, t, LAPPED_ERR_INVALID, "constraint 1|weight", "NaN weight");
    c[1] = con(7, 1, 0, 0, 0, 0); /* radius 0 is the documented default (2 * scale) */
    CHECK(field_into(&m, &o, s, t, &err) == LAPPED_OK);
    {
        double n[3];
        tnormal(&m, 7, n);
        c[1] = con(7, (float)n[0], (float)n[1], (float)n[2], 0, 0);
        expect_error(&m, &o, s, t, LAPPED_ERR_INVALID, "constraint 1|normal to triangle 7",
                     "normal direction");
    }
    o.nconstraints = 0;
    expect_error(&m, &o, s, t, LAPPED_ERR_INVALID, "needs constraints", "no constraints");
    o = field_opts(LAPPED_FIELD_FACES, 0);
    expect_error(&m, &o, s, t, LAPPED_ERR_INVALID, "face_t is NULL", "FACES without arrays");
    o.face_t = ft; /* all zero */
    expect_error(&m, &o, s, t, LAPPED_ERR_INVALID, "triangle 0|zero", "FACES zero vector");
    {
        int f, k;
        double n[3];
        for (f = 0; f < tm.nt; f++) {
            double a[3] = {1, 2, 3}, d;
            tnormal(&m, f, n);
            d = a[0] * n[0] + a[1] * n[1] + a[2] * n[2];
            for (k = 0; k < 3; k++) ft[3 * f + k] = (float)(a[k] - d * n[k]);
        }
        CHECK(field_into(&m, &o, s, t, &err) == LAPPED_OK);
        ft[3 * 11 + 1] = nan;
        expect_error(&m, &o, s, t, LAPPED_ERR_INVALID, "triangle 11|not finite", "FACES NaN");
        ft[3 * 11] = ft[3 * 11 + 1] = ft[3 * 11 + 2] = 0;
        expect_error(&m, &o, s, t, LAPPED_ERR_INVALID, "triangle 11|zero", "FACES zero at 11");
        tnormal(&m, 11, n);
        ft[33] = (float)n[0], ft[34] = (float)n[1], ft[35] = (float)n[2];
        expect_error(&m, &o, s, t, LAPPED_ERR_INVALID, "triangle 11|normal", "FACES normal vector");
    }
    o = field_opts(LAPPED_FIELD_UP, -1.0f);
    expect_error(&m, &o, s, t, LAPPED_ERR_INVALID, "scale", "negative scale");
    o.scale = nan;
    expect_error(&m, &o, s, t, LAPPED_ERR_INVALID, "scale", "NaN scale");
    o = field_opts(42, 0);
    expect_error(&m, &o, s, t, LAPPED_ERR_INVALID, "mode 42", "unknown mode");
    o = field_opts(LAPPED_FIELD_CURVATURE, 0);
    o.smoothing = -3;
    expect_error(&m, &o, s, t, LAPPED_ERR_INVALID, "smoothing -3", "negative smoothing");
    o = field_opts(LAPPED_FIELD_UP, 0);
    o.up[1] = nan;
    expect_error(&m, &o, s, t, LAPPED_ERR_INVALID, "up vector", "NaN up");
    o = field_opts(LAPPED_FIELD_UP, 0);
    CHECK(lapped_compute_field(&m, &o, NULL, &err) == LAPPED_ERR_INVALID && strstr(err.message, "NULL output"));
    free(s), free(t), free(ft), free(fs);
    tm_free(&tm);
}

/* Every mode twice: byte-identical; and every allocation failure is
 * reported as NOMEM with nothing leaked. */
static void t_deterministic_and_allocation_failures(void)
{
    static const int modes[5] = {LAPPED_FIELD_UP, LAPPED_FIELD_ISOTROPIC, LAPPED_FIELD_CONSTRAINTS,
                                 LAPPED_FIELD_FACES, LAPPED_FIELD_CURVATURE};
    tmesh tm;
    int *fs, i, n;
    lapped_mesh m;
    lapped_constraint c[2];
    lapped_error err;
    float *s, *t, *s2, *t2, *ft;
    build(M_TORUS, &tm);
    fs = (int *)malloc(sizeof(int) * (tm.nt + 1));
    m = tm_view(&tm, fs);
    c[0] = con(10, 1, 1, 0, 0, 0.4f);
    c[1] = con(2000, 0, 1, 1, 0.1f, 0.3f);
    {
        lapped_options o = field_opts(LAPPED_FIELD_UP, 0.1f);
        REQUIRE(run(&m, &o, &s, &ft, &err) == LAPPED_OK); /* a frame for FACES */
        free(s);
    }
    for (i = 0; i < 5; i++) {
        lapped_options o = field_opts(modes[i], 0.15f);
        pwt_alloc_state st;
        o.constraints = c;
        o.nconstraints = 2;
        o.face_t = ft;
        REQUIRE(run(&m, &o, &s, &t, &err) == LAPPED_OK);
        REQUIRE(run(&m, &o, &s2, &t2, &err) == LAPPED_OK);
        CHECKF(memcmp(s, s2, sizeof(float) * 3 * tm.nt) == 0 && memcmp(t, t2, sizeof(float) * 3 * tm.nt) == 0,
               "mode %d differs between runs", modes[i]);
        for (n = 0;; n++) {
            lapped_result r;
            st.calls = 0, st.live = 0, st.fail_after = n;
            o.allocator.malloc_fn = pwt_malloc, o.allocator.realloc_fn = pwt_realloc;
            o.allocator.free_fn = pwt_free, o.allocator.user = &st;
            r = field_into(&m, &o, s2, t2, &err);
            CHECKF(st.live == 0, "mode %d, failing after %d: %ld blocks leaked", modes[i], n, st.live);
            if (r == LAPPED_OK) break;
            CHECKF(r == LAPPED_ERR_NOMEM, "mode %d, failing after %d: %s", modes[i], n, err.message);
            if (n > 100) break;
        }
        CHECK(memcmp(t, t2, sizeof(float) * 3 * tm.nt) == 0);
        pwt_info("mode %d: %d allocation failures, all reported, nothing leaked", modes[i], n);
        free(s), free(t), free(s2), free(t2);
    }
    free(ft), free(fs);
    tm_free(&tm);
}

/* The CGAL elephant (make data): CURVATURE and CONSTRAINTS, timed (best
 * of 5 calls, each building the internal mesh too). */
static double best_ms(const lapped_mesh *m, const lapped_options *o, float *s, float *t)
{
    double best = 1e30;
    int i;
    for (i = 0; i < 5; i++) {
        lapped_error err;
        clock_t t0 = clock();
        field_into(m, o, s, t, &err);
        if (1e3 * (double)(clock() - t0) / CLOCKS_PER_SEC < best)
            best = 1e3 * (double)(clock() - t0) / CLOCKS_PER_SEC;
    }
    return best;
}

static void elephant_case(const char *rel)
{
    const char *path = pwt_data(rel);
    pw_mesh pm;
    pw_err e;
    lapped_mesh m;
    lapped_options o;
    lapped_constraint c[6];
    lapped_error err;
    float *s, *t;
    int i, nt;
    double tu, tk, tc, mu, mk, mc;
    if (!path) return;
    pw_err_clear(&e);
    REQUIRE(pw_mesh_load(NULL, path, &pm, &e) == PW_OK);
    memset(&m, 0, sizeof m);
    m.nverts = pm.nv, m.positions = pm.pos, m.nfaces = pm.nf, m.face_start = pm.fstart, m.face_verts = pm.fv;
    nt = pm.fstart[pm.nf] - 2 * pm.nf;
    s = (float *)malloc(sizeof(float) * 3 * nt);
    t = (float *)malloc(sizeof(float) * 3 * nt);
    for (i = 0; i < 6; i++) c[i] = con(i * (nt / 6), (float)(i & 1), 1.0f, (float)(i % 3), 0, 0);
    o = field_opts(LAPPED_FIELD_UP, 0);
    o.constraints = c;
    o.nconstraints = 6;
    CHECKF(field_into(&m, &o, s, t, &err) == LAPPED_OK, "UP: %s", err.message);
    mu = median_turn(&m, t);
    tu = best_ms(&m, &o, s, t);
    o.field = LAPPED_FIELD_CURVATURE;
    CHECKF(field_into(&m, &o, s, t, &err) == LAPPED_OK, "CURVATURE: %s", err.message);
    CHECK(check_frames(&m, s, t, 0, "elephant CURVATURE") == 0);
    mk = median_turn(&m, t);
    {
        int *pairs, np = tpairs(&m, &pairs), k, flips = 0;
        for (k = 0; k < np; k++) flips += unfolded_turn(&m, pairs + 4 * k, t) > 90.0;
        pwt_info("%s: CURVATURE sign seams (turn over 90 deg) on %d of %d edges", rel, flips, np);
        free(pairs);
    }
    tk = best_ms(&m, &o, s, t);
    o.field = LAPPED_FIELD_CONSTRAINTS;
    CHECKF(field_into(&m, &o, s, t, &err) == LAPPED_OK, "CONSTRAINTS: %s", err.message);
    CHECK(check_frames(&m, s, t, 0, "elephant CONSTRAINTS") == 0);
    mc = median_turn(&m, t);
    tc = best_ms(&m, &o, s, t);
    pwt_info("%s: %d triangles; median turn of T between neighbours: UP %.2f deg, CURVATURE %.2f deg, "
             "CONSTRAINTS (6, default radius) %.2f deg",
             rel, nt, mu, mk, mc);
    pwt_info("%s: ms per call, best of 5 (internal mesh build included): UP %.1f, CURVATURE (20 smoothing "
             "sweeps) %.1f, CONSTRAINTS (6 Dijkstra runs) %.1f",
             rel, tu, tk, tc);
    free(s), free(t);
    pw_mesh_free(NULL, &pm);
}

static void t_elephant(void) { elephant_case("meshes/elephant.off"); }
static void t_refined_elephant(void) { elephant_case("meshes/refined_elephant.off"); }

static const pwt_case cases[] = {
    {"frames_every_mode", t_frames_every_mode},
    {"faces_pass_through", t_faces_pass_through},
    {"polygons", t_polygons},
    {"up_sphere", t_up_sphere},
    {"up_normal_to_surface", t_up_normal_to_surface},
    {"up_box_tops", t_up_box_tops},
    {"up_sphere_pole", t_up_sphere_pole},
    {"up_terrain", t_up_terrain},
    {"constraints_grid", t_constraints_grid},
    {"constraints_curved", t_constraints_curved},
    {"constraints_components", t_constraints_components},
    {"curvature_cylinder", t_curvature_cylinder},
    {"curvature_torus", t_curvature_torus},
    {"curvature_fallbacks", t_curvature_fallbacks},
    {"difficulty", t_difficulty},
    {"bad_inputs", t_bad_inputs},
    {"deterministic_and_allocation_failures", t_deterministic_and_allocation_failures},
    {"elephant", t_elephant},
    {"refined_elephant", t_refined_elephant},
};
PWT_MAIN(cases)
