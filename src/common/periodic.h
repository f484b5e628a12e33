/* periodic: the periodic global parameterization of a triangle mesh along
 * a direction field, shared by pgp.h (Ray, Lévy, Wang, Turk and Vallet
 * 2009, "Material Space Texturing", whose section numbers the comments
 * use) and tiled.h's mode for any mesh.
 *
 * Pieces: the default field (§2.2: the tile's t axis along a global up
 * direction or the direction of least curvature, smoothed); the PGP of
 * §2.3 (one unit complex number per vertex for s and for t, by proximal
 * steps of a complex Hermitian least squares); the per-corner (s, t) of
 * Eq. (4); the winding of s and t around a triangle (a vortex where it is
 * not 0); and the clean coordinates of a vortex triangle (beyond the
 * paper: the differences its neighbours use along its edges, the zero
 * where the pattern forks).
 *
 * A pw_periodic owns its arrays; the method fills scale and sfac (and
 * reads or edits dir) between the steps. stm has 9 floats per triangle,
 * (s, t, m) per corner: the shared code writes s and t, the method m.
 *
 * Determinism: only + - * / and sqrt in the angles (pw_periodic_turns). */
#ifndef PW__PERIODIC_V1
#define PW__PERIODIC_V1

#include "base.h"
#include "vec.h"
#include "mesh.h"
#include "sparse.h"
#include "zsparse.h"
#include "zamg.h"
#include "trimesh.h"
#include "dirfield.h"

#define PW_PERIODIC_TWO_PI 6.28318530717958647692

typedef struct pw_periodic {
    pw_alloc a;
    pw_trimesh m;
    float *conn;          /* dirfield connection, 3nf*2 */
    double *dual;         /* dual edge lengths per half-edge (Dijkstra) */
    double *base;         /* nf*2: default field direction per triangle (frame) */
    double *dir;          /* nf*2: d_s per triangle, unit, in the triangle frame */
    float *scale;         /* nv: S_i */
    float *sfac;          /* nv: a factor of S_i (1 but where the method
                             makes the field integrable) */
    double *zs, *zt;      /* nv*2: the unit complex unknowns of s and t (§2.3) */
    double *turn;         /* nv*2: Arg(z) / 2 pi of s and t per vertex, as the
                             last pw_periodic_solve left z (what
                             pw_periodic_recover reads) */
    float *stm;           /* nf*9: per corner s, t, m (Eq. 4) */
    float *grad;          /* nf*6: g for s and t of every triangle as the
                             last pw_periodic_solve saw the field (what
                             pw_periodic_recover reads) */
    int *forder, *vorder; /* triangles and vertices in breadth-first order: the
                             order of the unknowns of every solve */
    float scale0;         /* default tile side */
    int area_weights;     /* 1: the paper's A_T + A_T' edge weights */
    pw_zrun run;          /* how the complex solves run (zsparse.h; zero: on
                             the calling thread), set by the method */
} pw_periodic;

/* ---- sparse symmetric positive definite solves ----------------------------- */

/* Solves the real symmetric positive definite system collected in t (n x
 * n triplets) for x (warm start: x's current values) to a relative
 * residual tol, by IC(0)-preconditioned CG. (The complex systems are
 * assembled into their structure directly, pw_zcsr_pattern.) */
PW__DEF int pw_periodic_pd_solve(const pw_periodic *P, const pw_triplets *t, const double *b, double *x, double tol,
                                 pw_err *e)
{
    const pw_alloc *a = &P->a;
    pw_csr A;
    pw_ic0 L;
    pw_cg_options o = pw_cg_default_options();
    int r;
    o.tol = tol;
    o.max_iter = 4000;
    memset(&L, 0, sizeof L);
    if ((r = pw_csr_from_triplets(a, t, &A, e)) != PW_OK) return r;
    if ((r = pw_ic0_factor(a, &A, &L, e)) == PW_OK) r = pw_pcg_solve(a, &A, &L, b, x, &o, NULL, e);
    pw_ic0_free(a, &L);
    pw_csr_free(a, &A);
    return r;
}

/* ---- set-up ---------------------------------------------------------------- */

/* The order of the unknowns: triangles breadth first over the dual graph
 * (each component from its first triangle), vertices as those triangles
 * first reach them. Neighbours then sit close in memory and in the
 * incomplete-Cholesky elimination: on a subdivided mesh, whose new vertices
 * the file lists far from their neighbours, the solves take 40% less time.
 * done (nv + nf, all zero) marks what has been placed. */
PW__DEF void pw_periodic_bfs_order(pw_periodic *P, unsigned char *done)
{
    int nf = P->m.nf, nv = P->m.nv, head = 0, tail = 0, nvo = 0, s, k;
    unsigned char *fdone = done + nv, *vdone = done;
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
}

PW__DEF void pw_periodic_free(pw_periodic *P)
{
    pw_alloc a = P->a;
    pw_trimesh_free(&a, &P->m);
    pw_free(&a, P->conn);
    pw_free(&a, P->dual);
    pw_free(&a, P->base);
    pw_free(&a, P->scale);
    pw_free(&a, P->zs);
    pw_free(&a, P->forder);
    memset(P, 0, sizeof *P);
    P->a = a;
}

/* Builds the triangle mesh of v (its positions borrowed), allocates every
 * array and computes the order of the unknowns, the dual edge lengths and
 * the connection. P->a must be set; on failure what was allocated is left
 * for pw_periodic_free. */
PW__DEF int pw_periodic_init(pw_periodic *P, const pw_mesh *v, pw_err *e)
{
    unsigned char *done;
    size_t nf, nv;
    int r;
    if ((r = pw_trimesh_init(&P->a, v, &P->m, e)) != PW_OK) return r;
    nf = (size_t)P->m.nf;
    nv = (size_t)P->m.nv;
    P->dual = (double *)pw_alloc_array(&P->a, 3 * nf, sizeof(double), "mapping", e);
    P->base = (double *)pw_alloc_array(&P->a, 4 * nf, sizeof(double), "mapping", e);
    P->scale = (float *)pw_alloc_array(&P->a, 2 * nv + 15 * nf, sizeof(float), "mapping", e);
    P->zs = (double *)pw_alloc_array(&P->a, 6 * nv, sizeof(double), "mapping", e);
    P->forder = (int *)pw_alloc_array(&P->a, nf + nv, sizeof(int), "mapping", e);
    done = (unsigned char *)pw_calloc_array(&P->a, nv + nf, 1, "mapping", e);
    if (!P->dual || !P->base || !P->scale || !P->zs || !P->forder || !done) {
        pw_free(&P->a, done);
        return PW_ERR_NOMEM;
    }
    P->vorder = P->forder + nf;
    pw_periodic_bfs_order(P, done);
    pw_free(&P->a, done);
    P->dir = P->base + 2 * nf;
    P->sfac = P->scale + nv;
    P->stm = P->sfac + nv;
    P->grad = P->stm + 9 * nf;
    P->zt = P->zs + 2 * nv;
    P->turn = P->zt + 2 * nv;
    pw_df_dual(&P->m, P->dual);
    return pw_df_connection(&P->a, &P->m, &P->conn, e);
}

/* ---- the field and the gradients it asks for ---------------------------------------- */

/* The frame of triangle f as 3D vectors (u along its first edge, v = N x u). */
PW__DEF void pw_periodic_frame(const pw_periodic *P, int f, pw_v3 *u, pw_v3 *v) { pw_df_frame(&P->m, f, u, v); }

/* d_s (k = 0) or d_t = N x d_s (k = 1) of triangle f in 3D. */
PW__DEF pw_v3 pw_periodic_dir3(const pw_periodic *P, int f, int k)
{
    pw_v3 u, v, d;
    double x = P->dir[2 * f], y = P->dir[2 * f + 1];
    pw_periodic_frame(P, f, &u, &v);
    if (k == 1) { /* rot90 in the frame */
        double t = x;
        x = -y;
        y = t;
    }
    d = pw_v3_add(pw_v3_scale(u, (float)x), pw_v3_scale(v, (float)y));
    return d;
}

/* S^T = (S_i + S_j + S_k) / 3 (§2.3), each S_i times its factor. */
PW__DEF double pw_periodic_face_scale(const pw_periodic *P, int f)
{
    const int *t = P->m.tri + 3 * f;
    return ((double)P->scale[t[0]] * P->sfac[t[0]] + (double)P->scale[t[1]] * P->sfac[t[1]] +
            (double)P->scale[t[2]] * P->sfac[t[2]]) /
           3.0;
}

/* g = d / S^T for s (k = 0) or t (k = 1). */
PW__DEF pw_v3 pw_periodic_grad(const pw_periodic *P, int f, int k)
{
    return pw_v3_scale(pw_periodic_dir3(P, f, k), (float)(1.0 / pw_periodic_face_scale(P, f)));
}

/* Cotangent of the angle at corner k of triangle f. */
PW__DEF double pw_periodic_cot(const pw_trimesh *m, int f, int k)
{
    pw_v3 p = pw_trimesh_corner(m, f, k);
    pw_v3 a = pw_v3_sub(pw_trimesh_corner(m, f, (k + 1) % 3), p),
          b = pw_v3_sub(pw_trimesh_corner(m, f, (k + 2) % 3), p);
    double c = pw_v3_dot(a, b), s = pw_v3_len(pw_v3_cross(a, b));
    return s > 0.0 ? c / s : 0.0;
}

/* The Laplacian weight of the edge of half-edge h (the cotangents of the
 * angles facing it, halved), floored so that obtuse triangles keep every
 * weight positive and the smoothing a maximum principle. */
PW__DEF double pw_periodic_lap_weight(const pw_trimesh *m, int h)
{
    double w = 0.5 * pw_periodic_cot(m, h / 3, (h % 3 + 2) % 3);
    if (m->hm.twin[h] >= 0) {
        int t = m->hm.twin[h];
        w += 0.5 * pw_periodic_cot(m, t / 3, (t % 3 + 2) % 3);
    }
    return w > 0.05 ? w : 0.05;
}

/* Weight of the pull of every unknown towards its default: small enough to
 * change nothing visible where constraints or the area's border fix the
 * values, and it makes a component with nothing fixed take the default
 * (where the Laplacian alone would be singular). */
#define PW_PERIODIC_PULL 1e-7

/* Weight of the edge of half-edge h in the orientation smoothing: its
 * length over the dual edge's (the cotangent weight of the dual mesh). */
PW__DEF double pw_periodic_dir_weight(const pw_periodic *P, int h)
{
    int f = h / 3, k = h % 3;
    double len = pw_v3_len(pw_v3_sub(pw_trimesh_corner(&P->m, f, (k + 1) % 3), pw_trimesh_corner(&P->m, f, k)));
    return P->dual[h] > 0.0 ? len / P->dual[h] : 1.0;
}

/* The interior edge k (twin > k) between free triangles (id[f] >= 0): a
 * pair of the orientation system (pw_zpairs). */
PW__DEF int pw_periodic_dir_pair(const void *ctx, int k, int *ij)
{
    const pw_periodic *P = (const pw_periodic *)((const void *const *)ctx)[0];
    const int *id = (const int *)((const void *const *)ctx)[1], t = P->m.hm.twin[k];
    if (t < k) return 0;
    ij[0] = id[k / 3];
    ij[1] = id[t / 3];
    return ij[0] >= 0 && ij[1] >= 0;
}

/* Adds one interior edge (half-edge h of triangle f, twin in g) to the
 * orientation system: w |z_f - c z_g|^2 with c the transport from g into f
 * (pw_df_connection); a fixed neighbour moves to b. */
PW__DEF void pw_periodic_dir_edge(const pw_periodic *P, pw_zasm *S, const int *id, int h)
{
    int f = h / 3, g = P->m.hm.twin[h] / 3;
    double c[2];
    c[0] = P->conn[2 * h];
    c[1] = P->conn[2 * h + 1];
    pw_zasm_term(S, id[f], id[g], pw_periodic_dir_weight(P, h), c, P->dir + 2 * (id[f] < 0 ? f : g));
}

/* Directions are normalised after the solve: a loose tolerance suffices. */
#define PW_PERIODIC_DIR_TOL 3e-3

/* Smooths the directions of the free triangles (free[f]) with the others
 * fixed, each pulled towards the default field with weight pull[f] (NULL:
 * a faint pull that only decides components with nothing fixed), then
 * normalises: "orientations rather than vectors" (the scale is
 * interpolated separately). Singularities emerge where the fixed directions
 * force them. A free component with nothing fixed takes the default field. */
PW__DEF int pw_periodic_dir_smooth(pw_periodic *P, const unsigned char *free, const double *pull, pw_err *e)
{
    const pw_trimesh *m = &P->m;
    int *id = (int *)pw_alloc_array(&P->a, (size_t)m->nf, sizeof(int), "orientation", e);
    double *x = NULL;
    const void *ctx[2];
    pw_zpairs pr;
    pw_zasm S;
    pw_cg_options o = pw_cg_default_options();
    int n = 0, f, h, r = id ? PW_OK : PW_ERR_NOMEM;
    memset(&S, 0, sizeof S);
    for (h = 0; r == PW_OK && h < m->nf; h++) { /* breadth-first order */
        f = P->forder[h];
        id[f] = free[f] ? n++ : -1;
    }
    ctx[0] = P;
    ctx[1] = id;
    pr.count = 3 * m->nf;
    pr.pair = pw_periodic_dir_pair;
    pr.ctx = ctx;
    if (r == PW_OK && n > 0) {
        x = (double *)pw_alloc_array(&P->a, (size_t)n * 2, sizeof(double), "orientation", e);
        r = x ? pw_zasm_init(&P->a, &S, n, &pr, e) : PW_ERR_NOMEM;
    }
    for (f = 0; r == PW_OK && n > 0 && f < m->nf; f++)
        if (id[f] >= 0) {
            double w = pull ? pull[f] + PW_PERIODIC_PULL : PW_PERIODIC_PULL;
            x[2 * id[f]] = P->dir[2 * f];
            x[2 * id[f] + 1] = P->dir[2 * f + 1];
            S.b[2 * id[f]] += w * P->base[2 * f];
            S.b[2 * id[f] + 1] += w * P->base[2 * f + 1];
            S.A.val[2 * S.dpos[id[f]]] = w;
        }
    for (h = 0; r == PW_OK && n > 0 && h < 3 * m->nf; h++)
        if (m->hm.twin[h] > h && (id[h / 3] >= 0 || id[m->hm.twin[h] / 3] >= 0)) pw_periodic_dir_edge(P, &S, id, h);
    o.tol = PW_PERIODIC_DIR_TOL;
    o.max_iter = 4000;
    if (r == PW_OK && n > 0) {
        S.A.run = &P->run;
        r = pw_zpd_solve(&P->a, &S.A, S.b, x, &o, e);
    }
    for (f = 0; r == PW_OK && n > 0 && f < m->nf; f++)
        if (id[f] >= 0) {
            double *z = P->dir + 2 * f;
            z[0] = x[2 * id[f]];
            z[1] = x[2 * id[f] + 1];
            if (!pw_df_unit(z)) {
                z[0] = P->base[2 * f];
                z[1] = P->base[2 * f + 1];
            }
        }
    pw_zasm_free(&P->a, &S);
    pw_free(&P->a, id);
    pw_free(&P->a, x);
    return r;
}

/* The default field (§2.2, where no constraint reaches): the tile's t axis
 * along the global up direction projected onto each triangle, or along the
 * direction of least curvature (curvature != 0, smoothed `smoothing`
 * times); then smoothed ("a vector field smoothing algorithm" [LRL06]):
 * each triangle is pulled towards that direction with a weight A_f c_f /
 * S^2 against the smoothness terms between neighbours, so that the field
 * varies over about one tile size and the poles of the projection (c_f =
 * 1 - (up . n)^2 small: up nearly normal to the face) are filled smoothly.
 * A field that turns within a tile cannot be followed by a periodic
 * parameterization without distortion. Writes base and dir. */
PW__DEF int pw_periodic_base_field(pw_periodic *P, const float *up3, int curvature, int smoothing, pw_err *e)
{
    size_t nf = (size_t)P->m.nf;
    unsigned char *known = (unsigned char *)pw_alloc_array(&P->a, nf, 1, "field", e);
    double *pull = (double *)pw_alloc_array(&P->a, nf, sizeof(double), "field", e);
    pw_v3 up = pw_v3_norm(pw_v3_load(up3));
    int r = known && pull ? PW_OK : PW_ERR_NOMEM, f;
    pw_df_field F;
    F.m = &P->m;
    F.conn = P->conn;
    F.z = P->base;
    F.known = known;
    if (r == PW_OK && curvature) r = pw_df_curvature(&P->a, &F, up, smoothing, e);
    else if (r == PW_OK) r = pw_df_up(&P->a, &F, up, e);
    for (f = 0; r == PW_OK && f < P->m.nf; f++) { /* that is d_t; d_s = rot(-90)(d_t) */
        double x = P->base[2 * f], c = pw_v3_dot(up, pw_v3_load(P->m.normal + 3 * f));
        P->base[2 * f] = P->base[2 * f + 1];
        P->base[2 * f + 1] = -x;
        P->dir[2 * f] = P->base[2 * f];
        P->dir[2 * f + 1] = P->base[2 * f + 1];
        pull[f] = (curvature ? 1.0 : 1.0 - c * c) * P->m.area[f] / ((double)P->scale0 * P->scale0);
        known[f] = 1;
    }
    if (r == PW_OK) r = pw_periodic_dir_smooth(P, known, pull, e);
    if (r == PW_OK) memcpy(P->base, P->dir, sizeof(double) * 2 * nf);
    pw_free(&P->a, known);
    pw_free(&P->a, pull);
    return r;
}

/* ---- angles without libm -------------------------------------------------------------- */

/* atan(x) for |x| <= 1: two half-angle steps (atan x = 2 atan(x / (1 +
 * sqrt(1 + x^2)))) bring |x| below tan(pi/16) ~ 0.2, then the Taylor series
 * to x^21 (truncation below 1e-17). Only + - * / sqrt: the same bits on
 * every IEEE platform, which libm's atan2 does not promise. */
PW__DEF double pw_periodic_atan(double x)
{
    double y = x / (1.0 + sqrt(1.0 + x * x)), y2, p = 1.0 / 21.0;
    int k;
    y = y / (1.0 + sqrt(1.0 + y * y));
    y2 = y * y;
    for (k = 19; k >= 1; k -= 2) p = 1.0 / k - y2 * p;
    return 4.0 * y * p;
}

/* Arg(x + iy) / 2 pi, in (-1/2, 1/2]; 0 for 0. */
PW__DEF double pw_periodic_turns(double x, double y)
{
    const double pi = 3.14159265358979323846;
    double a;
    if (x == 0.0 && y == 0.0) return 0.0;
    if (fabs(y) <= fabs(x)) {
        a = pw_periodic_atan(y / x);
        if (x < 0.0) a += y >= 0.0 ? pi : -pi;
    } else a = (y > 0.0 ? 0.5 * pi : -0.5 * pi) - pw_periodic_atan(x / y);
    return a / PW_PERIODIC_TWO_PI;
}

/* ---- §2.3 per-edge rotations ------------------------------------------------------------ */

/* alpha / 2 pi of half-edge h (from tri[h] to the next corner) given the
 * gradients g of its triangle and gt of its twin's (unused on a boundary):
 * e_ij . (g_T + g_T') / 2, the gradient averaged over the two triangles of
 * the edge (the one triangle on a boundary). This is the coordinate
 * difference s_j - s_i the field asks for along the edge. */
PW__DEF double pw__periodic_alpha_of(const pw_periodic *P, int h, pw_v3 g, pw_v3 gt)
{
    int f = h / 3, c = h % 3;
    pw_v3 ed = pw_v3_sub(pw_trimesh_corner(&P->m, f, (c + 1) % 3), pw_trimesh_corner(&P->m, f, c));
    if (P->m.hm.twin[h] >= 0) g = pw_v3_scale(pw_v3_add(g, gt), 0.5f);
    return (double)pw_v3_dot(ed, g);
}

/* alpha / 2 pi of half-edge h for s (k = 0) or t (k = 1), from the field
 * as it is. */
PW__DEF double pw_periodic_alpha(const pw_periodic *P, int h, int k)
{
    int t = P->m.hm.twin[h];
    pw_v3 g = pw_periodic_grad(P, h / 3, k);
    return pw__periodic_alpha_of(P, h, g, t >= 0 ? pw_periodic_grad(P, t / 3, k) : g);
}

/* The same from the gradients of the last solve (P->grad): the same value
 * while the field has not changed since. */
PW__DEF double pw_periodic_alpha_solved(const pw_periodic *P, int h, int k)
{
    int t = P->m.hm.twin[h];
    pw_v3 g = pw_v3_load(P->grad + 6 * (h / 3) + 3 * k);
    return pw__periodic_alpha_of(P, h, g, t >= 0 ? pw_v3_load(P->grad + 6 * (t / 3) + 3 * k) : g);
}

/* P->grad over a block of triangles (on the solve's threads). */
PW__DEF void pw__periodic_grad_block(void *ctx, int b)
{
    pw_periodic *P = (pw_periodic *)ctx;
    int f, k, nb = pw__zblocks(P->m.nf), hi = pw__zblock_start(P->m.nf, nb, b + 1);
    for (f = pw__zblock_start(P->m.nf, nb, b); f < hi; f++)
        for (k = 0; k < 2; k++) pw_v3_store(P->grad + 6 * f + 3 * k, pw_periodic_grad(P, f, k));
}

/* ---- §2.3 the least-squares system ----------------------------------------------------- */

/* The weight of edge h in F_PGP. The paper prints A_T + A_T' (kept as
 * area_weights): a term |z_j - R z_i|^2 ~ |e . (grad s - g)|^2 is then
 * an integral of the distortion times A_T / |e|^2 ~ A_T per unit area, so
 * large triangles cost more and the solve pushes the distortion into the
 * small ones (on CGAL's meshes, where triangle sizes vary by 100x, that is
 * where the singular share comes from). Cotangent weights make F_PGP the
 * discrete integral of |grad s - g|^2 (the connection Laplacian of [KCPS15]
 * "Stripe patterns" and of geogram's PGP), the same cost per unit area
 * everywhere. Cotangents of obtuse angles can make a weight negative and
 * the system indefinite: the weight is floored at 0.05, as the §2.2
 * Laplacian's (pw_periodic_lap_weight), which keeps IC(0) and CG well
 * defined. CGAL's meshes are far from Delaunay: the floor holds 2% of the
 * edges of elephant, 7% of knot, 12% of mushroom and 19% of cow (16% of
 * cow's have a negative sum); floors from 0.001 to 0.1 give the same
 * counts within 1 vortex and 0.5% singular. Cotangents of an intrinsic
 * Delaunay triangulation would avoid the floor; they are not implemented. */
PW__DEF double pw_periodic_weight(const pw_periodic *P, int h)
{
    int tw = P->m.hm.twin[h];
    if (P->area_weights) return (double)P->m.area[h / 3] + (tw >= 0 ? (double)P->m.area[tw / 3] : 0.0);
    return pw_periodic_lap_weight(&P->m, h);
}

/* The complex Hermitian system of coordinate k over the free vertices,
 * being assembled: its structure (the edges between free vertices, the
 * same for s and t) and the terms of every edge. */
typedef struct pw_periodic_zsys {
    const double *z; /* nv*2: the current z, read at the fixed vertices */
    const int *id;   /* nv: vertex -> unknown (-1: fixed) */
    int k;           /* the coordinate: 0 for s, 1 for t */
    pw_zasm S;       /* the matrix and right-hand side */
    double *edge;    /* 3nf*3: per half-edge assembled (twin < h) its weight
                         and e^{i alpha}, pw_periodic_edge_terms */
    const pw_periodic *P;
} pw_periodic_zsys;

/* The weight and rotation of every half-edge of a block of triangles
 * that the assembly visits (twin < h), on the solve's threads: the
 * cotangents and the field's gradients cost more than the assembly. */
PW__DEF void pw_periodic_edge_terms(void *ctx, int blk)
{
    const pw_periodic_zsys *Z = (const pw_periodic_zsys *)ctx;
    const pw_periodic *P = Z->P;
    int nf = P->m.nf, nb = pw__zblocks(nf), h, hi = 3 * pw__zblock_start(nf, nb, blk + 1);
    for (h = 3 * pw__zblock_start(nf, nb, blk); h < hi; h++)
        if (P->m.hm.twin[h] < h) {
            double a = PW_PERIODIC_TWO_PI * pw_periodic_alpha_solved(P, h, Z->k), *o = Z->edge + 3 * (size_t)h;
            o[0] = pw_periodic_weight(P, h);
            o[1] = pw_cos(a);
            o[2] = pw_sin(a);
        }
}

/* Edge k (twin < k, each edge once) between free vertices: a pair of
 * the PGP's systems (pw_zpairs), i -> j. */
PW__DEF int pw_periodic_pair(const void *ctx, int k, int *ij)
{
    const pw_periodic_zsys *Z = (const pw_periodic_zsys *)ctx;
    const pw_trimesh *m = &Z->P->m;
    if (m->hm.twin[k] >= k) return 0;
    ij[0] = Z->id[m->tri[k]];
    ij[1] = Z->id[m->tri[3 * (k / 3) + (k % 3 + 1) % 3]];
    return ij[0] >= 0 && ij[1] >= 0;
}

/* Adds the term w |z_j - R(alpha) z_i|^2 of edge h (i -> j) to the system
 * of the free vertices (id >= 0). R(alpha) is the rotation by +alpha,
 * [cos -sin; sin cos], i.e. the product with e^{i alpha}: with z = e^{2
 * pi i s}, s_j = s_i + alpha/2pi is z_j = e^{i alpha} z_i. (The matrix
 * printed in the paper has the signs of the sines the other way round,
 * which would make s decrease along g; tests/test_pgp.c checks a flat
 * grid, where the exact answer is linear.) That is |z_i - e^{-i alpha}
 * z_j|^2: w on both diagonals, -w e^{-i alpha} at (i, j) and its
 * conjugate at (j, i); a fixed end moves to the right-hand side. */
PW__DEF void pw_periodic_edge(const pw_periodic *P, pw_periodic_zsys *Z, int h)
{
    int vi = P->m.tri[h], vj = P->m.tri[3 * (h / 3) + (h % 3 + 1) % 3], i = Z->id[vi], j = Z->id[vj];
    const double *term = Z->edge + 3 * (size_t)h;
    double c[2];
    c[0] = term[1];
    c[1] = -term[2];
    pw_zasm_term(&Z->S, i, j, term[0], c, Z->z + 2 * (i < 0 ? vi : vj));
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
#define PW_PERIODIC_STEPS 4
static const double pw_periodic_mu[PW_PERIODIC_STEPS] = {1e-5, 1e-3, 1e-2, 0.1};

/* A first estimate: z carried from the fixed vertices along a breadth-first
 * tree, z_j = e^{i alpha_ij} z_i, i.e. the field integrated along the tree. */
PW__DEF int pw_periodic_propagate(pw_periodic *P, double *z, const int *id, int k, pw_err *e)
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
            a = PW_PERIODIC_TWO_PI * pw_periodic_alpha_solved(P, hh, k) * (fw ? 1.0 : -1.0);
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
 * vertices (Z->id >= 0, n of them), the others fixed; Z->S holds the
 * structure (pw_zasm_init with pw_periodic_pair). */
PW__DEF int pw_periodic_solve_k(pw_periodic *P, pw_periodic_zsys *Z, double *z, int n, int k, pw_err *e)
{
    double *x = (double *)pw_alloc_array(&P->a, (size_t)n * 5, sizeof(double), "PGP", e);
    double *dg = x + 2 * n, *rhs = x + 3 * n, *b = Z->S.b, dsum, off;
    const int *id = Z->id;
    pw_zcsr *A = &Z->S.A;
    pw_zamg M;
    pw_cg_options o = pw_cg_default_options();
    int v, h, q, step, multigrid = 0, pays, r = x ? PW_OK : PW_ERR_NOMEM;
    Z->z = z;
    Z->k = k;
    Z->edge = (double *)pw_alloc_array(&P->a, 9 * (size_t)P->m.nf + 1, sizeof(double), "PGP", e);
    if (!Z->edge) r = PW_ERR_NOMEM;
    else pw__zfor(A->run, P->m.nf, pw__zblocks(P->m.nf), pw_periodic_edge_terms, Z);
    memset(A->val, 0, sizeof(double) * 2 * (size_t)A->rowptr[n]);
    memset(b, 0, sizeof(double) * 2 * (size_t)n);
    Z->S.next = 0;
    for (h = 0; r == PW_OK && h < 3 * P->m.nf; h++)
        if (P->m.hm.twin[h] < h) pw_periodic_edge(P, Z, h); /* each edge once */
    pw_free(&P->a, Z->edge);
    Z->edge = NULL;
    for (q = 0; r == PW_OK && q < n; q++) dg[q] = A->val[2 * Z->S.dpos[q]]; /* the (real) diagonal of F's matrix */
    if (r == PW_OK) r = pw_periodic_propagate(P, z, id, k, e);
    o.max_iter = 4000;
    memset(&M, 0, sizeof M);
    if (r == PW_OK) pw__zamg_sums(A, &dsum, &off); /* the off-diagonal moduli: the same for every step */
    for (step = 0; r == PW_OK && step < PW_PERIODIC_STEPS; step++) {
        double mu = pw_periodic_mu[step];
        for (q = 0, dsum = 0.0; q < n; q++) dsum += A->val[2 * Z->S.dpos[q]] = dg[q] * (1.0 + mu);
        pays = pw_zamg_pays_sums(n, dsum, off);
        if (step == 0 && pays) { /* one hierarchy for the steps that need it */
            pw_err se;
            int sr;
            pw_err_clear(&se);
            sr = pw_zamg_setup(&P->a, A, &M, &se);
            multigrid = sr == PW_OK;
            if (sr != PW_OK && sr != PW_ERR_INVALID) r = pw_fail(e, sr, "%s", se.msg); /* INVALID: IC(0) instead */
        }
        for (v = 0; v < P->m.nv; v++)
            if ((q = id[v]) >= 0) {
                x[2 * q] = z[2 * v];
                x[2 * q + 1] = z[2 * v + 1];
                rhs[2 * q] = b[2 * q] + mu * dg[q] * z[2 * v];
                rhs[2 * q + 1] = b[2 * q + 1] + mu * dg[q] * z[2 * v + 1];
            }
        o.tol = step < PW_PERIODIC_STEPS - 1 ? 1e-3 : 1e-4; /* each step is normalised: no need for more */
        /* the steps' matrices differ in the diagonal only: level 0 sees it, the coarse levels need not */
        if (r == PW_OK)
            r = multigrid && pays ? pw_zamg_solve(&P->a, A, &M, rhs, x, &o, NULL, e)
                                  : pw_zic0_solve(&P->a, A, rhs, x, &o, e);
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
    if (multigrid) pw_zamg_free(&P->a, &M);
    pw_free(&P->a, x);
    return r;
}

/* P->turn over a block of vertices (on the solve's threads). */
PW__DEF void pw__periodic_turn_block(void *ctx, int b)
{
    pw_periodic *P = (pw_periodic *)ctx;
    int v, nb = pw__zblocks(P->m.nv), hi = pw__zblock_start(P->m.nv, nb, b + 1);
    for (v = pw__zblock_start(P->m.nv, nb, b); v < hi; v++) {
        P->turn[2 * v] = pw_periodic_turns(P->zs[2 * v], P->zs[2 * v + 1]);
        P->turn[2 * v + 1] = pw_periodic_turns(P->zt[2 * v], P->zt[2 * v + 1]);
    }
}

/* s and t solved at once, each on one thread, when the solve's run has
 * two (pw_periodic_solve): their systems share the structure only. */
typedef struct pw__periodic_both {
    pw_periodic *P;
    pw_periodic_zsys Z[2];
    int n, r[2];
    pw_err e[2];
} pw__periodic_both;

PW__DEF void pw__periodic_solve_task(void *ctx, int k)
{
    pw__periodic_both *B = (pw__periodic_both *)ctx;
    pw_err_clear(&B->e[k]);
    B->r[k] = pw_periodic_solve_k(B->P, &B->Z[k], k ? B->P->zt : B->P->zs, B->n, k, &B->e[k]);
}

/* Unknowns from which s and t are solved side by side on two threads. */
#define PW__PERIODIC_BOTH 4096

/* §2.3 over the free vertices: "in the special case of initialization, we
 * lock a single vertex s_0 = 0 <=> z_0 = [1,0], else s is locked outside
 * the effect area" (whole: the first vertex of every component locked).
 *
 * s and t are independent systems. On two threads or more they are solved
 * at the same time, one on each thread, their row loops on that thread
 * alone: most of a solve is sequential (the aggregation, the coarsest
 * factor, IC(0)'s triangular solves), so this halves it where the loops
 * on threads took 40% off (bunny00). The price: a second copy of the
 * system and of its multigrid hierarchy while both run. Both ways give the
 * same bits: the row loops' blocks don't depend on the threads. */
PW__DEF int pw_periodic_solve(pw_periodic *P, const unsigned char *vfree, int whole, pw_err *e)
{
    int *id = (int *)pw_alloc_array(&P->a, (size_t)P->m.nv, sizeof(int), "PGP", e);
    int *comp = (int *)pw_calloc_array(&P->a, (size_t)P->m.nf * 2, sizeof(int), "PGP", e);
    unsigned char *lock = (unsigned char *)pw_calloc_array(&P->a, (size_t)P->m.nv, 1, "PGP", e);
    int n = 0, v, f, c, nc = 0, r = id && comp && lock ? PW_OK : PW_ERR_NOMEM;
    pw__periodic_both B;
    pw_periodic_zsys *Z = B.Z;
    pw_zpairs pr;
    memset(&B, 0, sizeof B);
    B.P = P;
    Z[0].id = Z[1].id = id;
    Z[0].P = Z[1].P = P;
    pr.count = 3 * P->m.nf;
    pr.pair = pw_periodic_pair;
    pr.ctx = &Z[0];
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
    pw_free(&P->a, comp);
    pw__zfor(&P->run, P->m.nf, pw__zblocks(P->m.nf), pw__periodic_grad_block, P);
    if (r == PW_OK && n > 0) r = pw_zasm_init(&P->a, &Z[0].S, n, &pr, e);
    if (r == PW_OK && n >= PW__PERIODIC_BOTH && P->run.pfor && P->run.width > 1) {
        B.n = n;
        if ((r = pw_zasm_copy(&P->a, &Z[1].S, &Z[0].S, e)) == PW_OK) {
            P->run.pfor(P->run.par, 2, pw__periodic_solve_task, &B);
            for (c = 0; c < 2 && r == PW_OK; c++)
                if ((r = B.r[c]) != PW_OK) pw_fail(e, r, "%s", B.e[c].msg);
        }
    } else if (r == PW_OK && n > 0) {
        Z[0].S.A.run = &P->run;
        r = pw_periodic_solve_k(P, &Z[0], P->zs, n, 0, e);
        if (r == PW_OK) r = pw_periodic_solve_k(P, &Z[0], P->zt, n, 1, e);
    }
    if (r == PW_OK) pw__zfor(&P->run, P->m.nv, pw__zblocks(P->m.nv), pw__periodic_turn_block, P);
    pw_zasm_free(&P->a, &Z[0].S);
    pw_zasm_free(&P->a, &Z[1].S);
    pw_free(&P->a, id);
    pw_free(&P->a, lock);
    return r;
}

/* ---- Eq. (4): per-corner coordinates -------------------------------------------------- */

/* s and t of triangle f's corners: corner 0 reads Arg(z)/2pi, corners 1
 * and 2 add the integer p that brings their difference to corner 0 closest
 * to what the field asks for along the edge (alpha), so that every vertex
 * differs between its triangles by integers only. z and alpha are the last
 * pw_periodic_solve's (the field must not have changed since). */
PW__DEF void pw_periodic_recover(pw_periodic *P, int f)
{
    const int *tri = P->m.tri + 3 * f;
    float *o = P->stm + 9 * f;
    int c, k;
    for (k = 0; k < 2; k++) {
        double s0 = P->turn[2 * tri[0] + k];
        o[k] = (float)s0;
        for (c = 1; c < 3; c++) {
            /* alpha from corner 0 to corner c: edge 0->1 is half-edge 3f, edge 0->2 is 3f+2 reversed */
            double want =
                s0 + (c == 1 ? pw_periodic_alpha_solved(P, 3 * f, k) : -pw_periodic_alpha_solved(P, 3 * f + 2, k));
            double sc = P->turn[2 * tri[c] + k];
            o[3 * c + k] = (float)(sc + floor(want - sc + 0.5));
        }
    }
}

/* ---- vortices ---------------------------------------------------------------------------- */

/* The 3D gradient of the linear function with corner values w0, w1, w2 on
 * triangle f. */
PW__DEF pw_v3 pw_periodic_gradient(const pw_periodic *P, int f, double w0, double w1, double w2)
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

/* The winding of coordinate k around triangle f, an integer (0 but at a
 * vortex of the periodic parameterization): Eq. (4) brought corners 1 and 2
 * next to corner 0 along the field, so the edge from 1 to 2 carries it all.
 * The sum over the edges of alpha plus the wrapped rest is
 * -round(s_2 - s_1 - alpha_12). */
PW__DEF int pw_periodic_winding(const pw_periodic *P, int f, int k)
{
    const float *o = P->stm + 9 * f;
    return -(int)floor((double)o[6 + k] - o[3 + k] - pw_periodic_alpha(P, 3 * f + 1, k) + 0.5);
}

/* Whether s or t winds around triangle f. */
PW__DEF int pw_periodic_vortex(const pw_periodic *P, int f)
{
    return pw_periodic_winding(P, f, 0) != 0 || pw_periodic_winding(P, f, 1) != 0;
}

/* ---- the clean coordinates of a vortex triangle (beyond §3) ----------------------------- */

/* Layout of a vortex triangle's data, per coordinate k (12 floats):
 * U[3] the boundary values at the corners walking 0 -> 1 -> 2 (U_0 = s_0),
 * D[3] the difference along edge a -> a+1 (the integer shift nearest
 * alpha, as every regular neighbour has it; U_2 + D_2 = U_0 - winding),
 * V[3] the field's linear function L at the corners (corner 0's view, §3),
 * Q[3] the barycentric coordinates of the zero. A coordinate that does not
 * wind here has Q[0] < 0 and is linear in U. The zero is that of the
 * linearly interpolated residual e^{2 pi i (U - V)} ("stripe patterns",
 * Knöppel, Crane, Pinkall and Schröder 2015), kept off the edges. */
PW__DEF void pw_periodic_clean_coord(const pw_periodic *P, int f, int k, float *o)
{
    const float *c = P->stm + 9 * f;
    double U[3], D[3], V[3], r[3], zr[3], zi[3], det, q1, q2;
    int a;
    for (a = 0; a < 3; a++) { /* the edge from corner a to a+1: half-edge 3f + a */
        double d = (double)c[3 * ((a + 1) % 3) + k] - c[3 * a + k], al = pw_periodic_alpha(P, 3 * f + a, k);
        D[a] = d + floor(al - d + 0.5);
    }
    U[0] = c[k];
    U[1] = U[0] + D[0];
    U[2] = U[1] + D[1];
    V[0] = c[k];
    V[1] = c[k] + pw_periodic_alpha(P, 3 * f, k);
    V[2] = c[k] - pw_periodic_alpha(P, 3 * f + 2, k);
    for (a = 0; a < 3; a++) {
        o[a] = (float)U[a];
        o[3 + a] = (float)D[a];
        o[6 + a] = (float)V[a];
    }
    o[9] = -1.0f;
    o[10] = o[11] = 0.0f;
    if (pw_periodic_winding(P, f, k) == 0) return;
    for (a = 0; a < 3; a++) {
        r[a] = PW_PERIODIC_TWO_PI * (U[a] - V[a]);
        zr[a] = pw_cos(r[a]);
        zi[a] = pw_sin(r[a]);
    }
    /* [KCPS15]: the zero of z_0 + q1 (z_1 - z_0) + q2 (z_2 - z_0) */
    det = (zr[1] - zr[0]) * (zi[2] - zi[0]) - (zi[1] - zi[0]) * (zr[2] - zr[0]);
    q1 = det != 0.0 ? (-zr[0] * (zi[2] - zi[0]) + zi[0] * (zr[2] - zr[0])) / det : 1.0 / 3.0;
    q2 = det != 0.0 ? (-zi[0] * (zr[1] - zr[0]) + zr[0] * (zi[1] - zi[0])) / det : 1.0 / 3.0;
    if (!(q1 >= 0.0 && q2 >= 0.0 && q1 + q2 <= 1.0)) q1 = q2 = 1.0 / 3.0; /* |winding| > 1: the centre */
    /* kept off the edges, so that no sector of the fan is a sliver */
    q1 = 0.1 + 0.7 * q1;
    q2 = 0.1 + 0.7 * q2;
    o[9] = (float)(1.0 - q1 - q2);
    o[10] = (float)q1;
    o[11] = (float)q2;
}

/* The clean coordinate (o: pw_periodic_clean_coord's 12 floats of one
 * coordinate) of a vortex triangle at barycentric b: the point x where
 * the ray from the zero Q through b leaves the triangle takes the boundary
 * value (linear along the edge, as the neighbour's), and b takes it plus
 * L(b) - L(x): the field's gradient inside, the residual constant along
 * rays, so the coordinate winds once (n times) around Q. */
PW__DEF double pw_periodic_clean_eval(const float *o, const double *b)
{
    const float *U = o, *D = o + 3, *V = o + 6, *Q = o + 9;
    double mu = 2.0, x[3], u;
    int c, e = 0;
    if (Q[0] < 0.0f) return b[0] * U[0] + b[1] * U[1] + b[2] * U[2];
    for (c = 0; c < 3; c++) /* the edge the ray leaves by: opposite the smallest b_c / Q_c */
        if (b[c] / Q[c] < mu) {
            mu = b[c] / Q[c];
            e = (c + 1) % 3;
        }
    if (mu >= 1.0 - 1e-9) return U[0]; /* at the zero itself */
    for (c = 0; c < 3; c++) x[c] = (b[c] - mu * Q[c]) / (1.0 - mu);
    u = U[e] + x[(e + 1) % 3] * D[e];
    for (c = 0; c < 3; c++) u += (b[c] - x[c]) * V[c];
    return u;
}

/* Mean edge length of the triangle mesh. */
PW__DEF double pw_periodic_mean_edge(const pw_periodic *P)
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
 * period spans less than two triangles and Eq. 4 cannot recover it). */
PW__DEF int pw_periodic_check_scale(const pw_periodic *P, double side, pw_err *e)
{
    double lo = 2.0 * pw_periodic_mean_edge(P), hi = 10.0 * P->m.diag;
    if (side > hi || side < lo)
        return pw_fail(e, PW_ERR_INVALID,
                       "tile side %g is outside [%g, %g] (2 mean edge lengths to 10 bounding-box "
                       "diagonals)",
                       side, lo, hi);
    return PW_OK;
}

#endif /* PW__PERIODIC_V1 */
