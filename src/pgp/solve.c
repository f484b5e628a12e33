/* solve.c: §2.3 the periodic global parameterization, the recovery of
 * per-corner coordinates (Eq. 4), the §3 detection of singular 1-rings, the
 * recomputation of an effect area that every edit runs, and the map of a
 * mesh before any constraint (edit.c holds the public editing calls). */
#include "field.c"

#define PGP__TWO_PI 6.28318530717958647692

/* ---- angles without libm -------------------------------------------------------------- */

/* atan(x) for |x| <= 1: two half-angle steps (atan x = 2 atan(x / (1 +
 * sqrt(1 + x^2)))) bring |x| below tan(pi/16) ~ 0.2, then the Taylor series
 * to x^21 (truncation below 1e-17). Only + - * / sqrt: the same bits on
 * every IEEE platform, which libm's atan2 does not promise. */
static double pgp__atan(double x)
{
    double y = x / (1.0 + sqrt(1.0 + x * x)), y2, p = 1.0 / 21.0;
    int k;
    y = y / (1.0 + sqrt(1.0 + y * y));
    y2 = y * y;
    for (k = 19; k >= 1; k -= 2) p = 1.0 / k - y2 * p;
    return 4.0 * y * p;
}

/* Arg(x + iy) / 2 pi, in (-1/2, 1/2]; 0 for 0. */
static double pgp__turns(double x, double y)
{
    const double pi = 3.14159265358979323846;
    double a;
    if (x == 0.0 && y == 0.0) return 0.0;
    if (fabs(y) <= fabs(x)) {
        a = pgp__atan(y / x);
        if (x < 0.0) a += y >= 0.0 ? pi : -pi;
    } else a = (y > 0.0 ? 0.5 * pi : -0.5 * pi) - pgp__atan(x / y);
    return a / PGP__TWO_PI;
}

/* ---- §2.3 per-edge rotations ------------------------------------------------------------ */

/* alpha / 2 pi of half-edge h (from tri[h] to the next corner) for s (k = 0)
 * or t (k = 1): e_ij . (g_T + g_T') / 2, the gradient averaged over the two
 * triangles of the edge (the one triangle on a boundary). This is the
 * coordinate difference s_j - s_i the field asks for along the edge. */
static double pgp__alpha(const pgp__state *P, int h, int k)
{
    int f = h / 3, c = h % 3, t = P->m.hm.twin[h];
    pw_v3 ed = pw_v3_sub(pw_trimesh_corner(&P->m, f, (c + 1) % 3), pw_trimesh_corner(&P->m, f, c));
    pw_v3 g = pgp__grad(P, f, k);
    if (t >= 0) g = pw_v3_scale(pw_v3_add(g, pgp__grad(P, t / 3, k)), 0.5f);
    return (double)pw_v3_dot(ed, g);
}

/* ---- §2.3 the least-squares system ----------------------------------------------------- */

/* The weight of edge h in F_PGP. The paper prints A_T + A_T' (kept as
 * PGP_WEIGHTS_AREA): a term |z_j - R z_i|^2 ~ |e . (grad s - g)|^2 is then
 * an integral of the distortion times A_T / |e|^2 ~ A_T per unit area, so
 * large triangles cost more and the solve pushes the distortion into the
 * small ones (on CGAL's meshes, where triangle sizes vary by 100x, that is
 * where the singular share comes from). Cotangent weights make F_PGP the
 * discrete integral of |grad s - g|^2 (the connection Laplacian of [KCPS15]
 * "Stripe patterns" and of geogram's PGP), the same cost per unit area
 * everywhere. Cotangents of obtuse angles can make a weight negative and
 * the system indefinite: the weight is floored at 0.05, as the §2.2
 * Laplacian's (pgp__lap_weight), which keeps IC(0) and CG well defined.
 * CGAL's meshes are far from Delaunay: the floor holds 2% of the edges of
 * elephant, 7% of knot, 12% of mushroom and 19% of cow (16% of cow's have
 * a negative sum); floors from 0.001 to 0.1 give the same counts within
 * 1 vortex and 0.5% singular. Cotangents of an intrinsic Delaunay
 * triangulation would avoid the floor; they are not implemented. */
static double pgp__pgp_weight(const pgp__state *P, int h)
{
    int tw = P->m.hm.twin[h];
    if (P->o.weights == PGP_WEIGHTS_AREA) return (double)P->m.area[h / 3] + (tw >= 0 ? (double)P->m.area[tw / 3] : 0.0);
    return pgp__lap_weight(&P->m, h);
}

/* The complex Hermitian system of coordinate k over the free vertices,
 * being assembled. */
typedef struct pgp__zsys {
    const double *z; /* nv*2: the current z, read at the fixed vertices */
    const int *id;   /* nv: vertex -> unknown (-1: fixed) */
    int k;           /* the coordinate: 0 for s, 1 for t */
    pw_triplets *t;  /* the matrix being assembled (n x 2n) */
    double *b;       /* 2n: the right-hand side */
} pgp__zsys;

/* Adds the term w |z_j - R(alpha) z_i|^2 |z_j - R(alpha) z_i|^2 of edge h (i -> j) to
 * the system of the free vertices (id >= 0). R(alpha) is the rotation by
 * +alpha, [cos -sin; sin cos], i.e. the product with e^{i alpha}: with
 * z = e^{2 pi i s}, s_j = s_i + alpha/2pi is z_j = e^{i alpha} z_i. (The
 * matrix printed in the paper has the signs of the sines the other way
 * round, which would make s decrease along g; tests/test_pgp.c checks a
 * flat grid, where the exact answer is linear.) In the complex Hermitian
 * system: w on both diagonals, -w e^{i alpha} at (j, i) and its conjugate
 * at (i, j); a fixed end moves to the right-hand side. */
static int pgp__pgp_edge(const pgp__state *P, const pgp__zsys *Z, int h, pw_err *e)
{
    const double *z = Z->z;
    const int *id = Z->id;
    pw_triplets *t = Z->t;
    double *b = Z->b;
    int k = Z->k, f = h / 3;
    int vi = P->m.tri[h], vj = P->m.tri[3 * f + (h % 3 + 1) % 3], i = id[vi], j = id[vj], r = PW_OK;
    double w = pgp__pgp_weight(P, h);
    double a = PGP__TWO_PI * pgp__alpha(P, h, k), c = pw_cos(a), sn = pw_sin(a);
    const double *zi = z + 2 * vi, *zj = z + 2 * vj;
    if (i >= 0) r = pw_ztriplets_add(t, i, i, w, 0.0, e);
    if (r == PW_OK && j >= 0) r = pw_ztriplets_add(t, j, j, w, 0.0, e);
    if (r == PW_OK && i >= 0 && j >= 0) {
        r = pw_ztriplets_add(t, j, i, -w * c, -w * sn, e);
        if (r == PW_OK) r = pw_ztriplets_add(t, i, j, -w * c, w * sn, e);
    } else if (j >= 0) { /* b_j += w e^{i a} z_i */
        b[2 * j] += w * (c * zi[0] - sn * zi[1]);
        b[2 * j + 1] += w * (c * zi[1] + sn * zi[0]);
    } else if (i >= 0) { /* b_i += w e^{-i a} z_j */
        b[2 * i] += w * (c * zj[0] + sn * zj[1]);
        b[2 * i + 1] += w * (c * zj[1] - sn * zj[0]);
    }
    return r;
}

/* Proximal steps and their weights: each step minimises
 * F_PGP(z) + mu sum_i d_i |z_i - zhat_i|^2 (d_i the diagonal of F's
 * matrix) around the current unit estimate zhat, then normalises. The
 * plain least squares with one vertex locked decays towards 0 away from it
 * wherever the field is not a gradient (its minimum is z = 0 but near the
 * lock), leaving only noise in Arg(z); the unit-length constraint |z_i| = 1
 * of PGP [RLL*06] is what these steps restore, one linear solve each. The
 * first, weak steps let the estimate relax over long distances (the
 * breadth-first start has seams along its tree); the later ones converge.
 * The first step at mu = 1e-5 is nearly an inverse-iteration step towards
 * the smallest eigenvector of F (the global optimum of [KCPS15]): with the
 * cotangent weights, starting at 1e-3 instead leaves more vortices (CGAL's
 * elephant, cow, knot, mushroom at S = diag/10: 46, 44, 67, 36 against 40,
 * 46, 61, 32). Only the last step needs an accurate solve: the others are
 * normalised and refined after, and a relative residual of 1e-3 there
 * takes 40% fewer CG iterations for the same counts. (A fifth step at 0.1
 * or tighter solves change neither the vortex count nor the singular
 * triangles.) */
#define PGP__STEPS 4
static const double pgp__mu[PGP__STEPS] = {1e-5, 1e-3, 1e-2, 0.1};

/* Where each row's diagonal entry sits in A (every row has one). */
static int pgp__diag_index(const pw_alloc *a, const pw_zcsr *A, int **out, pw_err *e)
{
    int i, k, *d = (int *)pw_alloc_array(a, (size_t)A->n, sizeof(int), "PGP", e);
    *out = d;
    if (!d) return PW_ERR_NOMEM;
    for (i = 0; i < A->n; i++)
        for (d[i] = -1, k = A->rowptr[i]; k < A->rowptr[i + 1]; k++)
            if (A->col[k] == i) d[i] = k;
    for (i = 0; i < A->n; i++)
        if (d[i] < 0) return pw_fail(e, PW_ERR_INVALID, "PGP: row %d has no diagonal", i);
    return PW_OK;
}

/* A first estimate: z carried from the fixed vertices along a breadth-first
 * tree, z_j = e^{i alpha_ij} z_i, i.e. the field integrated along the tree. */
static int pgp__propagate(pgp__state *P, double *z, const int *id, int k, pw_err *e)
{
    const pw_trimesh *m = &P->m;
    int nh = 3 * m->nf, *start = (int *)pw_calloc_array(&P->a, (size_t)m->nv + 1, sizeof(int), "PGP", e);
    int *adj = (int *)pw_alloc_array(&P->a, (size_t)nh * 2, sizeof(int), "PGP", e);
    int *queue = (int *)pw_alloc_array(&P->a, (size_t)m->nv, sizeof(int), "PGP", e);
    unsigned char *done = (unsigned char *)pw_alloc_array(&P->a, (size_t)m->nv, 1, "PGP", e);
    int h, v, head = 0, tail = 0, i, r = start && adj && queue && done ? PW_OK : PW_ERR_NOMEM;
    for (h = 0; r == PW_OK && h < nh; h++) { /* each edge from both ends: +(h+1) forward, -(h+1) backward */
        start[m->tri[h] + 1]++;
        if (m->hm.twin[h] < 0) start[m->tri[3 * (h / 3) + (h % 3 + 1) % 3] + 1]++;
    }
    for (v = 0; r == PW_OK && v < m->nv; v++) start[v + 1] += start[v];
    for (h = 0; r == PW_OK && h < nh; h++) {
        int j = m->tri[3 * (h / 3) + (h % 3 + 1) % 3];
        adj[start[m->tri[h]]++] = h + 1;
        if (m->hm.twin[h] < 0) adj[start[j]++] = -(h + 1);
    }
    for (v = m->nv; r == PW_OK && v > 0; v--) start[v] = start[v - 1];
    if (r == PW_OK) start[0] = 0;
    for (v = 0; r == PW_OK && v < m->nv; v++)
        if ((done[v] = (unsigned char)(id[v] < 0)) != 0) queue[tail++] = v;
    while (r == PW_OK && head < tail) {
        int u = queue[head++];
        for (i = start[u]; i < start[u + 1]; i++) {
            int hh = adj[i] > 0 ? adj[i] - 1 : -adj[i] - 1, fw = adj[i] > 0, w;
            double a, c, sn, *zu = z + 2 * u;
            w = fw ? m->tri[3 * (hh / 3) + (hh % 3 + 1) % 3] : m->tri[hh];
            if (done[w]) continue;
            a = PGP__TWO_PI * pgp__alpha(P, hh, k) * (fw ? 1.0 : -1.0);
            c = pw_cos(a);
            sn = pw_sin(a);
            z[2 * w] = c * zu[0] - sn * zu[1];
            z[2 * w + 1] = sn * zu[0] + c * zu[1];
            done[w] = 1;
            queue[tail++] = w;
        }
        if (head == tail) /* a piece no fixed vertex reaches: start it at z = 1 */
            for (v = 0; v < m->nv; v++)
                if (!done[v]) {
                    done[v] = 1;
                    z[2 * v] = 1.0;
                    z[2 * v + 1] = 0.0;
                    queue[tail++] = v;
                    break;
                }
    }
    pw_free(&P->a, start);
    pw_free(&P->a, adj);
    pw_free(&P->a, queue);
    pw_free(&P->a, done);
    return r;
}

/* Solves for the unit complex numbers z (nv*2) of coordinate k at the free
 * vertices (id >= 0, n of them), the others fixed. */
static int pgp__pgp_solve(pgp__state *P, double *z, const int *id, int n, int k, pw_err *e)
{
    double *b = (double *)pw_calloc_array(&P->a, (size_t)n * 5, sizeof(double), "PGP", e);
    double *x = b + 2 * n, *dg = b + 4 * n, *rhs = NULL;
    int *dpos = NULL;
    pw_triplets t;
    pw_zcsr A;
    pw_zic0 L;
    pw_cg_options o = pw_cg_default_options();
    pgp__zsys Z;
    int v, h, q, step, r = b ? PW_OK : PW_ERR_NOMEM;
    Z.z = z;
    Z.id = id;
    Z.k = k;
    Z.t = &t;
    Z.b = b;
    memset(&t, 0, sizeof t);
    memset(&A, 0, sizeof A);
    memset(&L, 0, sizeof L);
    if (r == PW_OK) r = pw_triplets_init(&t, &P->a, n, 2 * n, e);
    for (h = 0; r == PW_OK && h < 3 * P->m.nf; h++)
        if (P->m.hm.twin[h] < h) r = pgp__pgp_edge(P, &Z, h, e); /* each edge once */
    for (q = 0; r == PW_OK && q < t.count; q++)                  /* the (real) diagonal of F's matrix */
        if (t.col[q] == 2 * t.row[q]) dg[t.row[q]] += t.val[q];
    if (r == PW_OK) r = pgp__propagate(P, z, id, k, e);
    if (r == PW_OK && (r = pw_zcsr_from_triplets(&P->a, &t, &A, e)) == PW_OK) r = pgp__diag_index(&P->a, &A, &dpos, e);
    if (r == PW_OK && !(rhs = (double *)pw_alloc_array(&P->a, (size_t)n * 2, sizeof(double), "PGP", e)))
        r = PW_ERR_NOMEM;
    o.max_iter = 4000;
    for (step = 0; r == PW_OK && step < PGP__STEPS; step++) {
        double mu = pgp__mu[step];
        for (q = 0; q < n; q++) A.val[2 * dpos[q]] = dg[q] * (1.0 + mu);
        pw_zic0_free(&P->a, &L);
        if ((r = pw_zic0_factor(&P->a, &A, &L, e)) != PW_OK) break;
        for (v = 0; v < P->m.nv; v++)
            if ((q = id[v]) >= 0) {
                x[2 * q] = z[2 * v];
                x[2 * q + 1] = z[2 * v + 1];
                rhs[2 * q] = b[2 * q] + mu * dg[q] * z[2 * v];
                rhs[2 * q + 1] = b[2 * q + 1] + mu * dg[q] * z[2 * v + 1];
            }
        o.tol = step < PGP__STEPS - 1 ? 1e-3 : 1e-4; /* each step is normalised: no need for more */
        r = pw_zpcg_solve(&P->a, &A, &L, rhs, x, &o, NULL, e);
        for (v = 0; r == PW_OK && v < P->m.nv; v++)
            if ((q = id[v]) >= 0) {
                double zz[2];
                zz[0] = x[2 * q];
                zz[1] = x[2 * q + 1];
                if (pw_df_unit(zz)) {
                    z[2 * v] = zz[0];
                    z[2 * v + 1] = zz[1];
                }
            }
    }
    pw_free(&P->a, dpos);
    pw_zic0_free(&P->a, &L);
    pw_zcsr_free(&P->a, &A);
    pw_triplets_free(&t);
    pw_free(&P->a, b);
    pw_free(&P->a, rhs);
    return r;
}

/* §2.3 over the free vertices: "in the special case of initialization, we
 * lock a single vertex s_0 = 0 <=> z_0 = [1,0], else s is locked outside
 * the effect area" (whole: the first vertex of every component locked). */
static int pgp__pgp(pgp__state *P, const unsigned char *vfree, int whole, pw_err *e)
{
    int *id = (int *)pw_alloc_array(&P->a, (size_t)P->m.nv, sizeof(int), "PGP", e);
    int *comp = (int *)pw_calloc_array(&P->a, (size_t)P->m.nf * 2, sizeof(int), "PGP", e);
    unsigned char *lock = (unsigned char *)pw_calloc_array(&P->a, (size_t)P->m.nv, 1, "PGP", e);
    int n = 0, v, f, c, nc = 0, r = id && comp && lock ? PW_OK : PW_ERR_NOMEM;
    if (r == PW_OK && whole) r = pw_hmesh_components(&P->a, &P->m.hm, comp, &nc, e);
    for (f = 0; r == PW_OK && whole && f < P->m.nf; f++) /* the first triangle of each component */
        if (!comp[P->m.nf + comp[f]]) {
            int lo = P->m.tri[3 * f];
            comp[P->m.nf + comp[f]] = 1;
            for (c = 1; c < 3; c++) lo = P->m.tri[3 * f + c] < lo ? P->m.tri[3 * f + c] : lo;
            lock[lo] = 1;
        }
    for (c = 0; r == PW_OK && c < P->m.nv; c++) {
        v = P->vorder[c];
        id[v] = vfree[v] && !lock[v] ? n++ : -1;
        if (lock[v]) {
            P->zs[2 * v] = P->zt[2 * v] = 1.0;
            P->zs[2 * v + 1] = P->zt[2 * v + 1] = 0.0;
        }
    }
    if (r == PW_OK && n > 0) r = pgp__pgp_solve(P, P->zs, id, n, 0, e);
    if (r == PW_OK && n > 0) r = pgp__pgp_solve(P, P->zt, id, n, 1, e);
    pw_free(&P->a, id);
    pw_free(&P->a, comp);
    pw_free(&P->a, lock);
    return r;
}

/* ---- Eq. (4): per-corner coordinates -------------------------------------------------- */

/* s, t, m of triangle f's corners: corner 0 reads Arg(z)/2pi, corners 1 and
 * 2 add the integer p that brings their difference to corner 0 closest to
 * what the field asks for along the edge (alpha), so that every vertex
 * differs between its triangles by integers only. */
static void pgp__recover(pgp__state *P, int f)
{
    const int *tri = P->m.tri + 3 * f;
    float *o = P->stm + 9 * f;
    int c, k;
    for (k = 0; k < 2; k++) {
        const double *z = k ? P->zt : P->zs;
        double s0 = pgp__turns(z[2 * tri[0]], z[2 * tri[0] + 1]);
        o[k] = (float)s0;
        for (c = 1; c < 3; c++) {
            /* alpha from corner 0 to corner c: edge 0->1 is half-edge 3f, edge 0->2 is 3f+2 reversed */
            double want = s0 + (c == 1 ? pgp__alpha(P, 3 * f, k) : -pgp__alpha(P, 3 * f + 2, k));
            double sc = pgp__turns(z[2 * tri[c]], z[2 * tri[c] + 1]);
            o[3 * c + k] = (float)(sc + floor(want - sc + 0.5));
        }
    }
    for (c = 0; c < 3; c++) o[3 * c + 2] = P->mat[tri[c]];
}

/* ---- §3 singular 1-rings --------------------------------------------------------------- */

/* The 3D gradient of the linear function with corner values w0, w1, w2 on
 * triangle f. */
static pw_v3 pgp__gradient(const pgp__state *P, int f, double w0, double w1, double w2)
{
    pw_v3 p = pw_trimesh_corner(&P->m, f, 0);
    pw_v3 e1 = pw_v3_sub(pw_trimesh_corner(&P->m, f, 1), p), e2 = pw_v3_sub(pw_trimesh_corner(&P->m, f, 2), p);
    double a11 = pw_v3_dot(e1, e1), a12 = pw_v3_dot(e1, e2), a22 = pw_v3_dot(e2, e2), det = a11 * a22 - a12 * a12;
    double d1 = w1 - w0, d2 = w2 - w0, x, y;
    if (!(det > 0.0)) return pw_v3_make(0.0f, 0.0f, 0.0f);
    x = (d1 * a22 - d2 * a12) / det;
    y = (d2 * a11 - d1 * a12) / det;
    return pw_v3_add(pw_v3_scale(e1, (float)x), pw_v3_scale(e2, (float)y));
}

/* "Highly distorted": ||grad s - g_s||^2 > threshold, or the same for t.
 * The paper's 0.5 is read relative to |g|^2 = 1/S^2 (the paper's tiles have
 * unit size), so that the test does not depend on the units of the mesh. */
static int pgp__distorted(const pgp__state *P, int f)
{
    const float *o = P->stm + 9 * f;
    int k;
    for (k = 0; k < 2; k++) {
        pw_v3 g = pgp__grad(P, f, k), d = pw_v3_sub(pgp__gradient(P, f, o[k], o[3 + k], o[6 + k]), g);
        if ((double)pw_v3_dot(d, d) > (double)P->o.singular_distortion * pw_v3_dot(g, g)) return 1;
    }
    return 0;
}

/* Whether the two triangles of half-edge h disagree on the coordinate
 * difference along it (s_i^T - s_j^T != s_i^T' - s_j^T', or for t). */
static int pgp__mismatch(const pgp__state *P, int h)
{
    int t = P->m.hm.twin[h], f = h / 3, g, c = h % 3, d, k;
    if (t < 0) return 0;
    g = t / 3;
    d = t % 3; /* h runs from corner c to c+1 of f, t from corner d to d+1 of g */
    for (k = 0; k < 2; k++) {
        double df = P->stm[9 * f + 3 * ((c + 1) % 3) + k] - P->stm[9 * f + 3 * c + k];
        double dg = P->stm[9 * g + 3 * d + k] - P->stm[9 * g + 3 * ((d + 1) % 3) + k];
        if (fabs(df - dg) > 0.5) return 1;
    }
    return 0;
}

/* The winding of coordinate k around triangle f, an integer (0 but at a
 * vortex of the periodic parameterization): Eq. (4) brought corners 1 and 2
 * next to corner 0 along the field, so the edge from 1 to 2 carries it all.
 * The sum over the edges of alpha plus the wrapped rest is
 * -round(s_2 - s_1 - alpha_12). */
static int pgp__winding(const pgp__state *P, int f, int k)
{
    const float *o = P->stm + 9 * f;
    return -(int)floor((double)o[6 + k] - o[3 + k] - pgp__alpha(P, 3 * f + 1, k) + 0.5);
}

PGPDEF int pgp_map_vortices(const pgp_map *map, unsigned char *flags)
{
    const pgp__state *P = pgp__state_of(map);
    int f, n = 0;
    for (f = 0; P && f < P->m.nf; f++) {
        unsigned char v = (unsigned char)((pgp__winding(P, f, 0) != 0) + 2 * (pgp__winding(P, f, 1) != 0));
        if (flags) flags[f] = v;
        n += v != 0;
    }
    return n;
}

/* §3: a vertex's 1-ring is singular if it holds a distorted triangle or a
 * spoke edge whose two triangles disagree; a triangle is singular (drawn
 * with three lookups) if one of its corners is. */
static int pgp__singularities(pgp__state *P, pw_err *e)
{
    unsigned char *dist = (unsigned char *)pw_alloc_array(&P->a, (size_t)P->m.nf, 1, "singularities", e);
    int f, c, h;
    if (!dist) return PW_ERR_NOMEM;
    memset(P->vsing, 0, (size_t)P->m.nv);
    for (f = 0; f < P->m.nf; f++) dist[f] = (unsigned char)pgp__distorted(P, f);
    for (h = 0; h < 3 * P->m.nf; h++) {
        int f3 = h / 3, c3 = h % 3;
        if (dist[f3]) P->vsing[P->m.tri[h]] = 1;
        if (pgp__mismatch(P, h)) P->vsing[P->m.tri[h]] = P->vsing[P->m.tri[3 * f3 + (c3 + 1) % 3]] = 1;
    }
    P->nsing = 0;
    for (f = 0; f < P->m.nf; f++) {
        P->fsing[f] = 0;
        for (c = 0; c < 3; c++) P->fsing[f] |= P->vsing[P->m.tri[3 * f + c]];
        P->nsing += P->fsing[f];
    }
    pw_free(&P->a, dist);
    return PW_OK;
}

/* ---- edits: §2's three steps over an effect area ------------------------------------------ */

/* Recomputes the fields of `kind` and the coordinates over the area around
 * the seed triangles (radius <= 0: the whole mesh). */
static int pgp__edit(pgp__state *P, pgp_constraint_kind kind, const pgp__seeds *sd, pgp_area *area, pw_err *e)
{
    const float radius = sd->radius;
    size_t nf = (size_t)P->m.nf, nv = (size_t)P->m.nv;
    unsigned char *in = (unsigned char *)pw_alloc_array(&P->a, 2 * nf + 2 * nv, 1, "effect area", e);
    int *order = (int *)pw_alloc_array(&P->a, nf, sizeof(int), "effect area", e);
    pw_progress pr = pgp__progress(&P->o);
    int n = 0, i, whole = !(radius > 0.0f), r = in && order ? PW_OK : PW_ERR_NOMEM;
    unsigned char *mark = in + nf, *vfree = in + 2 * nf, *locked = vfree + nv;
    if (r == PW_OK) r = pgp__area(P, sd, in, order, &n, e);
    if (r == PW_OK) pgp__free_vertices(P, in, vfree);
    if (r == PW_OK) r = pw_report(&pr, 0.2f, "interpolation", e);
    if (r == PW_OK && kind == PGP_CONSTRAINT_ORIENT) r = pgp__interp_dir(P, in, whole, mark, e);
    if (r == PW_OK && kind != PGP_CONSTRAINT_ORIENT) r = pgp__interp_vertex(P, kind, vfree, whole, locked, e);
    if (r == PW_OK) r = pw_report(&pr, 0.4f, "periodic global parameterization", e);
    if (r == PW_OK && kind != PGP_CONSTRAINT_MATERIAL) r = pgp__pgp(P, vfree, whole, e);
    for (i = 0; r == PW_OK && i < n; i++) pgp__recover(P, order[i]);
    if (r == PW_OK) r = pw_report(&pr, 0.9f, "singularities", e);
    if (r == PW_OK) r = pgp__singularities(P, e);
    if (r == PW_OK && area) {
        area->faces = (int *)pw_alloc_array(&P->a, (size_t)n, sizeof(int), "effect area", e);
        if (!area->faces) r = PW_ERR_NOMEM;
        else {
            memcpy(area->faces, order, sizeof(int) * (size_t)n);
            area->nfaces = n;
        }
        area->allocator = pgp__allocator(&P->a);
    }
    pw_free(&P->a, in);
    pw_free(&P->a, order);
    return r;
}

/* ---- creation -------------------------------------------------------------------------- */

static void pgp__state_free(pgp__state *P)
{
    pw_alloc a;
    if (!P) return;
    a = P->a;
    pw_trimesh_free(&a, &P->m);
    pw_free(&a, P->pos);
    pw_free(&a, P->conn);
    pw_free(&a, P->dual);
    pw_free(&a, P->base);
    pw_free(&a, P->scale);
    pw_free(&a, P->sfac);
    pw_free(&a, P->zs);
    pw_free(&a, P->vsing);
    pw_free(&a, P->forder);
    pw_free(&a, P->con);
    pw_free(&a, P);
}

PGPDEF void pgp_map_free(pgp_map *map)
{
    if (!map) return;
    pgp__state_free(map->state);
    memset(map, 0, sizeof *map);
}

static int pgp__check_options(const pgp_options *o, pw_err *e)
{
    if (o->field != PGP_FIELD_UP && o->field != PGP_FIELD_CURVATURE)
        return pw_fail(e, PW_ERR_INVALID, "unknown field mode %d", o->field);
    if (!pw_is_finite(o->up[0]) || !pw_is_finite(o->up[1]) || !pw_is_finite(o->up[2]))
        return pw_fail(e, PW_ERR_INVALID, "up vector is not finite");
    if (!(o->scale >= 0.0f) || !pw_is_finite(o->scale))
        return pw_fail(e, PW_ERR_INVALID, "scale %g is not a positive finite number", (double)o->scale);
    if (!(o->material >= 0.0f && o->material <= 1.0f))
        return pw_fail(e, PW_ERR_INVALID, "default material %g is not in [0, 1]", (double)o->material);
    if (!(o->min_scale > 0.0f && o->min_scale <= 1.0f))
        return pw_fail(e, PW_ERR_INVALID, "min_scale %g is not in (0, 1]", (double)o->min_scale);
    if (!(o->singular_distortion > 0.0f) || !pw_is_finite(o->singular_distortion))
        return pw_fail(e, PW_ERR_INVALID, "singular_distortion %g is not positive", (double)o->singular_distortion);
    if (o->smoothing < 0) return pw_fail(e, PW_ERR_INVALID, "smoothing %d is negative", o->smoothing);
    if (!(o->integrable >= 0.0f && o->integrable <= 1e6f))
        return pw_fail(e, PW_ERR_INVALID, "integrable %g is not in [0, 1e6]", (double)o->integrable);
    if (o->weights != PGP_WEIGHTS_COTAN && o->weights != PGP_WEIGHTS_AREA)
        return pw_fail(e, PW_ERR_INVALID, "unknown weights %d", o->weights);
    return PW_OK;
}

/* The order of the unknowns: triangles breadth first over the dual graph
 * (each component from its first triangle), vertices as those triangles
 * first reach them. Neighbours then sit close in memory and in the
 * incomplete-Cholesky elimination: on a subdivided mesh, whose new vertices
 * the file lists far from their neighbours, the solves take 40% less time.
 * vsing (all zero here) marks what has been placed. */
static void pgp__bfs_order(pgp__state *P)
{
    int nf = P->m.nf, nv = P->m.nv, head = 0, tail = 0, nvo = 0, s, k;
    unsigned char *fdone = P->vsing + nv, *vdone = P->vsing;
    for (s = 0; s < nf; s++) {
        if (fdone[s]) continue;
        fdone[s] = 1;
        P->forder[tail++] = s;
        while (head < tail) {
            int f = P->forder[head++];
            for (k = 0; k < 3; k++) {
                int g = pw_trimesh_across(&P->m, f, k), v = P->m.tri[3 * f + k];
                if (!vdone[v]) {
                    vdone[v] = 1;
                    P->vorder[nvo++] = v;
                }
                if (g >= 0 && !fdone[g]) {
                    fdone[g] = 1;
                    P->forder[tail++] = g;
                }
            }
        }
    }
    for (s = 0; s < nv; s++) /* vertices no triangle uses */
        if (!vdone[s]) P->vorder[nvo++] = s;
    memset(P->vsing, 0, (size_t)(nv + nf));
}

/* Copies the mesh, builds the triangle mesh and allocates every array. */
static int pgp__setup(pgp__state *P, const pgp_mesh *in, pw_err *e)
{
    size_t nf, nv;
    pw_mesh v;
    int r;
    if (!in || !in->positions || in->nverts < 1) return pw_fail(e, PW_ERR_INVALID, "no mesh or no vertices");
    if (in->nverts > PW_MAX_MESH_ELEMENTS) return pw_fail(e, PW_ERR_LIMIT, "%d vertices is over the limit", in->nverts);
    P->pos = (float *)pw_alloc_array(&P->a, (size_t)in->nverts * 3, sizeof(float), "positions", e);
    if (!P->pos) return PW_ERR_NOMEM;
    memcpy(P->pos, in->positions, sizeof(float) * 3 * (size_t)in->nverts);
    v = pgp__pw_mesh(in);
    v.pos = P->pos; /* the map's own copy */
    if ((r = pw_trimesh_init(&P->a, &v, &P->m, e)) != PW_OK) return r;
    nf = (size_t)P->m.nf;
    nv = (size_t)P->m.nv;
    P->dual = (double *)pw_alloc_array(&P->a, 3 * nf, sizeof(double), "mapping", e);
    P->base = (double *)pw_alloc_array(&P->a, 4 * nf, sizeof(double), "mapping", e);
    P->scale = (float *)pw_alloc_array(&P->a, 2 * nv + 9 * nf, sizeof(float), "mapping", e);
    P->sfac = (float *)pw_alloc_array(&P->a, nv, sizeof(float), "mapping", e);
    P->zs = (double *)pw_alloc_array(&P->a, 4 * nv, sizeof(double), "mapping", e);
    P->vsing = (unsigned char *)pw_calloc_array(&P->a, nv + nf, 1, "mapping", e);
    P->forder = (int *)pw_alloc_array(&P->a, nf + nv, sizeof(int), "mapping", e);
    if (!P->dual || !P->base || !P->scale || !P->sfac || !P->zs || !P->vsing || !P->forder) return PW_ERR_NOMEM;
    P->vorder = P->forder + nf;
    pgp__bfs_order(P);
    P->dir = P->base + 2 * nf;
    P->mat = P->scale + nv;
    P->stm = P->mat + nv;
    P->zt = P->zs + 2 * nv;
    P->fsing = P->vsing + nv;
    pw_df_dual(&P->m, P->dual);
    return pw_df_connection(&P->a, &P->m, &P->conn, e);
}

/* ---- beyond the paper: an integrable field --------------------------------------------- */

/* Adds triangle f's two rows to the normal equations of the curl
 * reduction. The circulation c = alpha_01 + alpha_12 + alpha_20 of s (and
 * of t) around f is what the PGP cannot follow: every whole turn it sums to
 * over a region is a vortex. A factor (1 + u) of the tile side and a
 * rotation theta of the field change alpha_e by -alpha_e u_e (s and t) and
 * +theta_e alpha^t_e (s) or -theta_e alpha^s_e (t), u_e and theta_e the
 * means over the edge's ends; each row asks c + those = 0, weighted by
 * 1 / area so that the sum is the integral of the squared curl. The part
 * of u common to the triangle only scales c (larger tiles, fewer periods,
 * fewer vortices: not what is asked) and is left out of the rows, so only
 * the variation of the tile side cancels curl: the conformal factor that
 * cancels the Gaussian curvature, which a rotation alone cannot (on CGAL's
 * meshes rotation alone removes no vortex). Unknowns: u_i at 2 i, theta_i
 * at 2 i + 1. */
static int pgp__curl_rows(const pgp__state *P, int f, pw_triplets *t, double *b, pw_err *e)
{
    double al[2][3], row[6], c, w = 1.0 / ((double)P->m.area[f] + 1e-300);
    int k, a, i, j, col[6], r = PW_OK;
    for (k = 0; k < 2; k++)
        for (a = 0; a < 3; a++) al[k][a] = pgp__alpha(P, 3 * f + a, k);
    for (k = 0; k < 2 && r == PW_OK; k++) {
        for (a = 0, c = 0.0; a < 3; a++) c += al[k][a];
        for (a = 0; a < 3; a++) { /* corner a touches edges a and a - 1 */
            int am = (a + 2) % 3;
            col[2 * a] = 2 * P->m.tri[3 * f + a];
            col[2 * a + 1] = col[2 * a] + 1;
            row[2 * a] = -0.5 * (al[k][a] + al[k][am]) + c / 3.0;
            row[2 * a + 1] = (k ? -0.5 : 0.5) * (al[1 - k][a] + al[1 - k][am]);
        }
        for (i = 0; i < 6; i++) {
            b[col[i]] -= w * row[i] * c;
            for (j = 0; j < 6 && r == PW_OK; j++) r = pw_triplets_add(t, col[i], col[j], w * row[i] * row[j], e);
        }
    }
    return r;
}

/* Adds the terms that keep the correction small and smooth: integrable^-1
 * A_i / S^4 (u_i^2 + theta_i^2) (how far from the field; the rows above
 * integrate curl^2 ~ |grad theta|^2 / S^2, so u and theta vary over about
 * sqrt(integrable) tiles) and 0.01 / S^2 of the cotangent Dirichlet energy
 * of u and theta. */
static int pgp__curl_reg(const pgp__state *P, pw_triplets *t, pw_err *e)
{
    double S2 = (double)P->scale0 * P->scale0, lam = 1.0 / ((double)P->o.integrable * S2 * S2), w;
    int h, k, i, j, r = PW_OK;
    for (h = 0; h < 3 * P->m.nf && r == PW_OK; h++) {
        i = P->m.tri[h];
        j = P->m.tri[3 * (h / 3) + (h % 3 + 1) % 3];
        for (k = 0; k < 2 && r == PW_OK; k++) /* a third of the triangle's area to each corner */
            r = pw_triplets_add(t, 2 * i + k, 2 * i + k, lam * P->m.area[h / 3] / 3.0, e);
        if (P->m.hm.twin[h] >= 0 && P->m.hm.twin[h] < h) continue;
        w = 0.01 * pgp__lap_weight(&P->m, h) / S2;
        for (k = 0; k < 2 && r == PW_OK; k++) {
            r = pw_triplets_add(t, 2 * i + k, 2 * i + k, w, e);
            if (r == PW_OK) r = pw_triplets_add(t, 2 * j + k, 2 * j + k, w, e);
            if (r == PW_OK) r = pw_triplets_add(t, 2 * i + k, 2 * j + k, -w, e);
            if (r == PW_OK) r = pw_triplets_add(t, 2 * j + k, 2 * i + k, -w, e);
        }
    }
    return r;
}

/* Applies the correction x (u, theta per vertex): the factor of every S_i
 * (u less its area-weighted mean, the factor kept in [1/2, 2]) and the rotation of the default field of every
 * triangle by the mean theta of its corners. */
static void pgp__curl_apply(pgp__state *P, const double *x)
{
    double mean = 0.0, area = 0.0;
    int v, f, h;
    for (h = 0; h < 3 * P->m.nf; h++) /* the mean of u is 0: the tile side the user asked for */
    {
        mean += x[2 * P->m.tri[h]] * P->m.area[h / 3];
        area += P->m.area[h / 3];
    }
    mean = area > 0.0 ? mean / area : 0.0;
    for (v = 0; v < P->m.nv; v++) {
        double s = P->sfac[v] * (1.0 + x[2 * v] - mean);
        P->sfac[v] = (float)(s < 0.5 ? 0.5 : (s > 2.0 ? 2.0 : s));
    }
    for (f = 0; f < P->m.nf; f++) {
        const int *tr = P->m.tri + 3 * f;
        double th = (x[2 * tr[0] + 1] + x[2 * tr[1] + 1] + x[2 * tr[2] + 1]) / 3.0, c, s, *d = P->base + 2 * f;
        th = th > 0.5 ? 0.5 : (th < -0.5 ? -0.5 : th); /* at most ~30 degrees per step */
        c = pw_cos(th);
        s = pw_sin(th);
        th = c * d[0] - s * d[1];
        d[1] = s * d[0] + c * d[1];
        d[0] = th;
        P->dir[2 * f] = d[0];
        P->dir[2 * f + 1] = d[1];
    }
}

/* options.integrable > 0: three Gauss-Newton steps of the curl reduction
 * (beyond the paper: the PGP of §2.3 follows a field whose gradients have
 * curl, and each whole turn of it is a vortex; the trade is documented in
 * docs/pgp.md). */
#define PGP__CURL_STEPS 3
static int pgp__integrable(pgp__state *P, pw_err *e)
{
    size_t n = 2 * (size_t)P->m.nv;
    double *b = (double *)pw_alloc_array(&P->a, 2 * n, sizeof(double), "integrability", e), *x = b + n;
    pw_triplets t;
    int step, f, r = b ? PW_OK : PW_ERR_NOMEM;
    memset(&t, 0, sizeof t);
    memcpy(P->dir, P->base, sizeof(double) * 2 * (size_t)P->m.nf);
    for (step = 0; step < PGP__CURL_STEPS && r == PW_OK; step++) {
        memset(b, 0, sizeof(double) * 2 * n); /* b and x, a cold start: x is the step */
        r = pw_triplets_init(&t, &P->a, (int)n, (int)n, e);
        for (f = 0; f < P->m.nf && r == PW_OK; f++) r = pgp__curl_rows(P, f, &t, b, e);
        if (r == PW_OK) r = pgp__curl_reg(P, &t, e);
        if (r == PW_OK) r = pgp__pd_solve(&P->a, &t, b, x, 1e-6, e);
        if (r == PW_OK) pgp__curl_apply(P, x);
        pw_triplets_free(&t);
    }
    pw_free(&P->a, b);
    return r;
}

/* Mean edge length of the triangle mesh. */
static double pgp__mean_edge(const pgp__state *P)
{
    double sum = 0.0;
    int h, n = 0;
    for (h = 0; h < 3 * P->m.nf; h++) {
        int f = h / 3, c = h % 3;
        if (P->m.hm.twin[h] > h) continue; /* each edge once */
        sum += pw_v3_len(pw_v3_sub(pw_trimesh_corner(&P->m, f, (c + 1) % 3), pw_trimesh_corner(&P->m, f, c)));
        n++;
    }
    return n ? sum / n : 0.0;
}

/* A tile side the mesh can carry: at most 10 bounding-box diagonals (beyond,
 * the whole mesh is one colour) and at least 2 mean edge lengths (below, a
 * period spans less than two triangles and Eq. 4 cannot recover it). Only
 * a side the caller gave is refused: the default (diag / 10) is kept on
 * meshes of a few triangles, where it is all one can do. */
static int pgp__check_scale(const pgp__state *P, pw_err *e)
{
    double lo = 2.0 * pgp__mean_edge(P), hi = 10.0 * P->m.diag;
    if (P->o.scale > 0.0f && (P->scale0 > hi || P->scale0 < lo))
        return pw_fail(e, PW_ERR_INVALID,
                       "tile side %g is outside [%g, %g] (2 mean edge lengths to 10 bounding-box "
                       "diagonals)",
                       (double)P->scale0, lo, hi);
    return PW_OK;
}

/* The map of a mesh without constraints (pgp_create, edit.c, adds them):
 * the default field, scale and material and the initial parameterization. */
static int pgp__create_map(const pgp_mesh *mesh, const pgp_options *opt, pgp_map *out, pw_err *e)
{
    pgp_options o = pgp__options(opt);
    pw_alloc a = pgp__alloc(&o.allocator);
    pgp__state *P;
    pgp__seeds whole; /* no seeds, radius 0: the whole mesh */
    int v;
    whole.tri = NULL;
    whole.n = 0;
    whole.radius = 0.0f;
    if (pgp__check_options(&o, e) != PW_OK ||
        (P = (pgp__state *)pw_calloc_array(&a, 1, sizeof *P, "mapping", e)) == NULL)
        return e->code;
    P->a = a;
    P->o = o;
    out->state = P;
    out->allocator = pgp__allocator(&a);
    if (pgp__setup(P, mesh, e) != PW_OK) return e->code;
    P->scale0 = o.scale > 0.0f ? o.scale : 0.1f * P->m.diag;
    for (v = 0; v < P->m.nv; v++) {
        P->scale[v] = P->scale0;
        P->sfac[v] = 1.0f;
        P->mat[v] = o.material;
    }
    for (v = 0; v < P->m.nv; v++) {
        P->zs[2 * v] = P->zt[2 * v] = 1.0;
        P->zs[2 * v + 1] = P->zt[2 * v + 1] = 0.0;
    }
    if (pgp__check_scale(P, e) != PW_OK || pgp__base_field(P, e) != PW_OK ||
        (o.integrable > 0.0f && pgp__integrable(P, e) != PW_OK) ||
        pgp__edit(P, PGP_CONSTRAINT_ORIENT, &whole, NULL, e) != PW_OK)
        return e->code;
    out->nverts = P->m.nv;
    out->ntris = P->m.nf;
    out->tris = P->m.tri;
    out->coords = P->stm;
    return PW_OK;
}

/* ---- what happened (issue 17) ------------------------------------------------------------ */

/* Stretch (1) and shear (2) flags of triangle f: the singular values of
 * J = S (grad s; grad t) in the triangle's frame outside [1/1.3, 1.3], S
 * the side the user asked for (without the integrability factor), the
 * angle between grad s and grad t more than 20 degrees off 90. */
static int pgp__distortion(const pgp__state *P, int f)
{
    const float *o = P->stm + 9 * f, *sc = P->scale;
    const int *tr3 = P->m.tri + 3 * f;
    double S = ((double)sc[tr3[0]] + sc[tr3[1]] + sc[tr3[2]]) / 3.0, a, b, c, d, tr, det, disc, s1, s2, cs;
    pw_v3 u, v, gs = pgp__gradient(P, f, o[0], o[3], o[6]), gt = pgp__gradient(P, f, o[1], o[4], o[7]);
    pgp__frame(P, f, &u, &v);
    a = S * pw_v3_dot(gs, u);
    b = S * pw_v3_dot(gs, v);
    c = S * pw_v3_dot(gt, u);
    d = S * pw_v3_dot(gt, v);
    tr = a * a + b * b + c * c + d * d;
    det = a * d - b * c; /* s1^2 + s2^2 and s1 s2 */
    disc = tr * tr - 4.0 * det * det;
    disc = sqrt(disc > 0.0 ? disc : 0.0);
    s1 = sqrt(0.5 * (tr + disc));
    s2 = tr > disc ? sqrt(0.5 * (tr - disc)) : 0.0;
    cs = (a * c + b * d) / (sqrt(a * a + b * b) * sqrt(c * c + d * d) + 1e-300);
    return (s1 > 1.3 || s2 < 1.0 / 1.3) + 2 * (fabs(cs) > 0.3420201433); /* sin 20 deg */
}

PGPDEF void pgp_map_stats(const pgp_map *map, pgp_stats *out)
{
    const pgp__state *P = pgp__state_of(map);
    double total = 0.0, st = 0.0, sh = 0.0;
    int f, d;
    if (!out) return;
    memset(out, 0, sizeof *out);
    if (!P) return;
    for (f = 0; f < P->m.nf; f++) {
        d = pgp__distortion(P, f);
        total += P->m.area[f];
        st += (d & 1) ? P->m.area[f] : 0.0;
        sh += (d & 2) ? P->m.area[f] : 0.0;
    }
    out->triangles = P->m.nf;
    out->vortices = pgp_map_vortices(map, NULL);
    out->singular = P->nsing;
    out->stretched = total > 0.0 ? (float)(st / total) : 0.0f;
    out->sheared = total > 0.0 ? (float)(sh / total) : 0.0f;
    out->mean_edge = (float)pgp__mean_edge(P);
    out->diagonal = P->m.diag;
    out->scale = P->scale0;
}
