/* builtin.c: the tetrahedralizer entry point, checks of caller meshes, and
 * the built-in surfaces and constraints of the demos and tests: closed
 * surfaces of implicit shapes by marching tetrahedra on a grid (a kiwi
 * fruit and a tree trunk with branches, for the look of the paper's
 * Fig. 1), with the depth and direction constraints a user would paint
 * and draw on them (§4.3-4.5). */
#include "cut.c"

/* ---- tetrahedral meshes -------------------------------------------------------------------- */

/* What the fill found, and the two-sided fit of its boundary (30000
 * samples a side) relative to the surface's diagonal. */
static int lst__tet_report(const pw_alloc *a, const pw_stuff_tris *tri, const pw_tetmesh *tm, const pw_stuff_info *info,
                           lst_tet_report *rep, pw_err *e)
{
    pw_stuff_fit fit;
    int r = pw_stuff_fit_measure(a, tri, tm, 30000, &fit, e);
    memset(rep, 0, sizeof *rep);
    rep->crossing_pairs = info->crossing_pairs;
    rep->skipped_triangles = info->skipped_triangles;
    rep->closed_holes = info->closed_holes;
    rep->fragments = info->fragments;
    if (r != PW_OK) return r;
    rep->pieces = fit.pieces;
    rep->surface_pieces = fit.surface_pieces;
    rep->fit_max = (fit.to_max > fit.from_max ? fit.to_max : fit.from_max) / fit.diag;
    rep->fit_p99 = (fit.to_p99 > fit.from_p99 ? fit.to_p99 : fit.from_p99) / fit.diag;
    return PW_OK;
}

/* Rule C1: what the fill repaired, as a warning with code OK (empty when
 * nothing was). */
static void lst__tet_warning(const pw_stuff_info *info, pw_err *e)
{
    size_t n = 0;
    if (info->crossing_pairs > 0)
        n += (size_t)snprintf(e->msg, sizeof e->msg,
                              "the surface crosses itself (%ld triangle pairs); filled where its "
                              "winding number is at least 1/2",
                              info->crossing_pairs);
    if (info->skipped_triangles > 0 && n < sizeof e->msg)
        n += (size_t)snprintf(e->msg + n, sizeof e->msg - n, "%s%d zero-area triangles skipped", n ? "; " : "",
                              info->skipped_triangles);
    if (info->closed_holes > 0 && n < sizeof e->msg)
        snprintf(e->msg + n, sizeof e->msg - n, "%sthe surface was open: %d small holes closed", n ? "; " : "",
                 info->closed_holes);
}

LSTDEF lst_result lst_tetrahedralize(const lst_mesh *surface, const lst_options *opt, lst_tetmesh *out,
                                     lst_tet_report *report, lst_error *err)
{
    lst_options o = lst__options(opt);
    pw_alloc a = lst__alloc(&o.allocator);
    pw_progress p = lst__progress(&o);
    pw_stuff_options so = pw_stuff_default_options();
    pw_stuff_info info;
    pw_mesh m, tri;
    pw_tetmesh tm;
    pw_err e;
    pw_err_clear(&e);
    if (out) memset(out, 0, sizeof *out);
    memset(&tri, 0, sizeof tri);
    memset(&tm, 0, sizeof tm);
    so.cell = o.tet.cell;
    so.strict = o.tet.strict;
    so.max_hole = o.tet.max_hole;
    so.info = &info;
    so.uniform = o.tet.uniform;
    so.fit = o.tet.fit;
    if (o.tet.target_tets > 0) so.target_tets = o.tet.target_tets;
    if (!surface || !out) pw_fail(&e, PW_ERR_INVALID, "lst_tetrahedralize: NULL argument");
    else if (!(so.cell >= 0.0) || !pw_is_finite(so.cell) || !pw_is_finite(so.max_hole) || o.tet.target_tets < 0)
        pw_fail(&e, PW_ERR_INVALID, "tetrahedralize: cell %g, target %d or max_hole %g is invalid", so.cell,
                o.tet.target_tets, so.max_hole);
    else {
        m = lst__pw_mesh(surface);
        if (pw_mesh_validate(&m, &e) == PW_OK && pw_mesh_triangulate(&a, &m, &tri, NULL, &e) == PW_OK) {
            pw_stuff_tris in = pw_stuff_tris_of(tri.pos, tri.nv, tri.fv, tri.nf);
            if (pw_stuff_tetrahedralize(&a, &in, &so, &p, &tm, &e) == PW_OK &&
                (!report || lst__tet_report(&a, &in, &tm, &info, report, &e) == PW_OK)) {
                lst__take_tets(&tm, &a, out);
                lst__tet_warning(&info, &e);
            } else if (tm.tet) pw_tetmesh_free(&a, &tm);
        }
    }
    pw_mesh_free(&a, &tri);
    return lst__done(&e, err);
}

LSTDEF lst_result lst_tetmesh_check(lst_tetmesh *mesh, double *min_dihedral, double *max_dihedral, lst_error *err)
{
    pw_alloc a;
    pw_tetmesh m;
    pw_err e;
    int *nb;
    pw_err_clear(&e);
    if (!mesh || !mesh->positions || !mesh->tets || mesh->nverts < 0 || mesh->ntets < 0) {
        pw_fail(&e, PW_ERR_INVALID, "lst_tetmesh_check: empty mesh");
        return lst__done(&e, err);
    }
    a = lst__alloc(&mesh->allocator);
    m = lst__pw_tets(mesh);
    if (pw_tetmesh_check(&m, "tetrahedral mesh", &e) == PW_OK &&
        (nb = (int *)pw_alloc_array(&a, (size_t)m.nt * 4, sizeof(int), "face adjacency", &e)) != NULL) {
        if (pw_tetmesh_neighbors(&a, &m, nb, &e) == PW_OK && (min_dihedral || max_dihedral)) {
            double lo, hi;
            pw_tet_dihedral_range(&m, &lo, &hi);
            if (min_dihedral) *min_dihedral = lo;
            if (max_dihedral) *max_dihedral = hi;
        }
        pw_free(&a, nb);
    }
    return lst__done(&e, err);
}

LSTDEF lst_result lst_tetmesh_surface(const lst_tetmesh *mesh, const lst_options *opt, lst_mesh *out, lst_error *err)
{
    lst_options o = lst__options(opt);
    pw_alloc a = lst__alloc(&o.allocator);
    pw_tetmesh m;
    pw_mesh s;
    lst__geo g;
    pw_err e;
    int f;
    pw_err_clear(&e);
    if (out) memset(out, 0, sizeof *out);
    memset(&s, 0, sizeof s);
    if (!out) pw_fail(&e, PW_ERR_INVALID, "lst_tetmesh_surface: NULL output");
    else if (lst__check_tets(mesh, &e) == PW_OK) {
        m = lst__pw_tets(mesh);
        if (lst__geo_init(&a, &m, &g, &e) == PW_OK) {
            if (pw_mesh_alloc(&a, &s, m.nv, g.nbface, 3 * g.nbface, 0, &e) == PW_OK) {
                memcpy(s.pos, m.pos, (size_t)m.nv * 3 * sizeof(float));
                for (f = 0; f < g.nbface; f++) {
                    s.fstart[f] = 3 * f;
                    lst__face_verts(&m, g.bface[f], s.fv + 3 * f);
                }
                s.fstart[g.nbface] = 3 * g.nbface;
                lst__take_mesh(&s, &a, out);
            }
            lst__geo_free(&a, &g);
        }
    }
    return lst__done(&e, err);
}

/* ---- closed surfaces of implicit shapes ------------------------------------------------------- */

typedef double (*lst__shape_fn)(const double *p);

/* The root of f on segment p q (f(p) < 0 < f(q) or the other way), by
 * regula falsi with the Illinois modification: a few steps put the vertex
 * on the surface far better than linear interpolation. It stays 5% of the
 * edge away from both ends, as the snapped grid values promise, so that
 * no triangle degenerates. */
static void lst__root(lst__shape_fn f, const double *p, const double *q, double fp, double fq, double *out)
{
    double a = 0.0, b = 1.0, fa = fp, fb = fq, x[3], t = 0.5;
    int it, k, side = 0;
    for (it = 0; it < 12; it++) {
        double fx;
        t = (a * fb - b * fa) / (fb - fa);
        for (k = 0; k < 3; k++) x[k] = p[k] + t * (q[k] - p[k]);
        fx = f(x);
        if ((fx < 0.0) == (fa < 0.0)) {
            a = t;
            fa = fx;
            if (side == -1) fb *= 0.5;
            side = -1;
        } else {
            b = t;
            fb = fx;
            if (side == 1) fa *= 0.5;
            side = 1;
        }
    }
    t = t < 0.05 ? 0.05 : (t > 0.95 ? 0.95 : t);
    for (k = 0; k < 3; k++) out[k] = p[k] + t * (q[k] - p[k]);
}

/* An implicit shape and the grid it is sampled on: f over the box lo ..
 * lo + n h, n cells per axis. */
typedef struct lst__shape_grid {
    lst__shape_fn f;
    double lo[3], h;
    int n;
} lst__shape_grid;

typedef struct lst__grid {
    lst__shape_fn f;
    double lo[3], h;
    int n;       /* cells per axis */
    double *val; /* (n+1)^3 values */
    lst__edges E;
    pw__mb b; /* the mesh being built */
} lst__grid;

static int lst__grid_id(const lst__grid *G, int x, int y, int z) { return (z * (G->n + 1) + y) * (G->n + 1) + x; }

static void lst__grid_pos(const lst__grid *G, int id, double *p)
{
    int s = G->n + 1;
    p[0] = G->lo[0] + G->h * (id % s);
    p[1] = G->lo[1] + G->h * ((id / s) % s);
    p[2] = G->lo[2] + G->h * (id / (s * s));
}

/* The surface vertex on grid edge (a, b), made once. */
static int lst__grid_vertex_on(lst__grid *G, int a, int b)
{
    int *id = lst__edge_find(&G->E, a, b, 1), idx = G->b.m.nv;
    double p[3], q[3], x[3];
    float xf[3];
    if (*id >= 0) return *id;
    lst__grid_pos(G, a < b ? a : b, p);
    lst__grid_pos(G, a < b ? b : a, q);
    lst__root(G->f, p, q, G->val[a < b ? a : b], G->val[a < b ? b : a], x);
    xf[0] = (float)x[0];
    xf[1] = (float)x[1];
    xf[2] = (float)x[2];
    if (pw__mb_vertex(&G->b, xf)) return -1;
    return *id = idx;
}

/* A triangle on grid edges e[k] (each from its inside end to its outside
 * end) facing the outside: every edge crosses the triangle's plane from
 * the inside to the outside, so the normal must agree with the edges. */
static int lst__grid_tri(lst__grid *G, int e[3][2])
{
    int v[3], k;
    double n[3], u[3], w[3], p[3], q[3], side = 0.0;
    const float *P;
    for (k = 0; k < 3; k++)
        if ((v[k] = lst__grid_vertex_on(G, e[k][0], e[k][1])) < 0) return PW_ERR_NOMEM;
    P = G->b.m.pos; /* after the vertices were added: they may move it */
    for (k = 0; k < 3; k++) {
        u[k] = P[3 * v[1] + k] - P[3 * v[0] + k];
        w[k] = P[3 * v[2] + k] - P[3 * v[0] + k];
    }
    pw_cross3(u, w, n);
    for (k = 0; k < 3; k++) {
        int j;
        lst__grid_pos(G, e[k][0], p);
        lst__grid_pos(G, e[k][1], q);
        for (j = 0; j < 3; j++) q[j] -= p[j];
        side += pw_dot3(n, q);
    }
    if (side < 0.0) {
        k = v[1];
        v[1] = v[2];
        v[2] = k;
    }
    if (pw__mb_room(&G->b, 3)) return PW_ERR_NOMEM;
    for (k = 0; k < 3; k++)
        if (pw__mb_corner(&G->b, v[k], -1)) return PW_ERR_NOMEM;
    return pw__mb_end_face(&G->b);
}

/* Marching tetrahedra on one of the six tetrahedra of a grid cube. */
static int lst__grid_tet(lst__grid *G, const int *c)
{
    int neg[4], pos[4], nn = 0, np = 0, k, e[4][2], r;
    for (k = 0; k < 4; k++) {
        if (G->val[c[k]] < 0.0) neg[nn++] = c[k];
        else pos[np++] = c[k];
    }
    if (!nn || !np) return PW_OK;
    if (nn == 2) {
        e[0][0] = neg[0];
        e[0][1] = pos[0];
        e[1][0] = neg[0];
        e[1][1] = pos[1];
        e[2][0] = neg[1];
        e[2][1] = pos[1];
        e[3][0] = neg[1];
        e[3][1] = pos[0];
        if ((r = lst__grid_tri(G, e)) != PW_OK) return r;
        e[1][0] = e[2][0];
        e[1][1] = e[2][1];
        e[2][0] = e[3][0];
        e[2][1] = e[3][1];
        return lst__grid_tri(G, e);
    }
    for (k = 0; k < 3; k++) {
        e[k][0] = nn == 1 ? neg[0] : neg[k];
        e[k][1] = nn == 1 ? pos[k] : pos[0];
    }
    return lst__grid_tri(G, e);
}

/* The closed surface f = 0 (f < 0 inside) over box lo..lo+n h, by marching
 * tetrahedra on the six-tetrahedra (Kuhn) split of each grid cube, which
 * neighbouring cubes share, so the surface is closed and manifold. Values
 * within a twentieth of a cell of zero move outward, so that no surface
 * vertex comes near a grid vertex and no triangle degenerates. */
static int lst__implicit(const pw_alloc *a, const lst__shape_grid *s, pw_mesh *out, pw_err *e)
{
    lst__shape_fn f = s->f;
    double h = s->h;
    int n = s->n;
    static const int split[6][4] = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6}, {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
    static const int cor[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                  {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    lst__grid G;
    size_t nvals = (size_t)(n + 1) * (n + 1) * (n + 1), cap = 16, i;
    int x, y, z, k, j, r = PW_OK;
    memset(&G, 0, sizeof G);
    G.f = f;
    G.h = h;
    G.n = n;
    memcpy(G.lo, s->lo, sizeof G.lo);
    while (cap < 8 * nvals / (size_t)n) cap *= 2;
    G.E.mask = cap - 1;
    G.val = (double *)pw_alloc_array(a, nvals, sizeof(double), "implicit surface", e);
    G.E.key = (uint64_t *)pw_calloc_array(a, cap, sizeof(uint64_t), "implicit surface", e);
    G.E.id = (int *)pw_alloc_array(a, cap, sizeof(int), "implicit surface", e);
    if (!G.val || !G.E.key || !G.E.id || pw__mb_init(&G.b, a, e)) r = PW_ERR_NOMEM;
    G.b.uv_ok = 0;
    for (i = 0; r == PW_OK && i < nvals; i++) {
        double p[3];
        lst__grid_pos(&G, (int)i, p);
        G.val[i] = f(p);
        if (fabs(G.val[i]) < 0.05 * h) G.val[i] = 0.05 * h;
    }
    for (z = 0; r == PW_OK && z < n; z++)
        for (y = 0; r == PW_OK && y < n; y++)
            for (x = 0; r == PW_OK && x < n; x++)
                for (k = 0; r == PW_OK && k < 6; k++) {
                    int c[4];
                    for (j = 0; j < 4; j++)
                        c[j] =
                            lst__grid_id(&G, x + cor[split[k][j]][0], y + cor[split[k][j]][1], z + cor[split[k][j]][2]);
                    r = lst__grid_tet(&G, c);
                }
    if (r == PW_OK) r = pw__mb_finish(&G.b, out, "implicit surface");
    else pw__mb_free(&G.b);
    pw_free(a, G.val);
    pw_free(a, G.E.key);
    pw_free(a, G.E.id);
    return r;
}

/* Smooth union (polynomial smooth minimum, radius k). */
static double lst__smin(double a, double b, double k)
{
    double h = k - fabs(a - b);
    return (a < b ? a : b) - (h > 0.0 ? h * h / (4.0 * k) : 0.0);
}

/* A kiwi: an egg-shaped spheroid along z, slightly narrower at the top. */
static double lst__kiwi_shape(const double *p)
{
    double rx = 0.78 * (1.0 - 0.06 * p[2]), ry = 0.72 * (1.0 - 0.06 * p[2]), rz = 1.15;
    double q = sqrt((p[0] / rx) * (p[0] / rx) + (p[1] / ry) * (p[1] / ry) + (p[2] / rz) * (p[2] / rz));
    return (q - 1.0) * 0.75;
}

/* The tree's parts: trunk along z, two branches; axis start, unit
 * direction, length, radius at the start and at the end, and how much the
 * radius flares within 0.6 of the start (the trunk's roots). */
static const double lst__tree_parts[3][10] = {
    {0.0, 0.0, -1.3, 0.0, 0.0, 1.0, 2.6, 0.44, 0.32, 0.5},
    {0.0, 0.05, 0.05, 0.62, 0.22, 0.753, 1.25, 0.21, 0.15, 0.0},
    {0.0, -0.05, 0.45, -0.58, -0.34, 0.74, 0.95, 0.18, 0.13, 0.0},
};

/* Distance-like value of a tapered cylinder with flat ends; t: the axial
 * parameter of p. */
static double lst__part(const double *c, const double *p, double *t)
{
    double d[3], r, radial, axial;
    int k;
    for (k = 0; k < 3; k++) d[k] = p[k] - c[k];
    *t = pw_dot3(d, c + 3);
    for (k = 0; k < 3; k++) d[k] -= *t * c[3 + k];
    r = c[7] + (c[8] - c[7]) * pw_clampf((float)(*t / c[6]), 0.0f, 1.0f);
    if (*t < 0.6) r += c[9] * (0.6 - *t) * (0.6 - *t);
    radial = sqrt(pw_dot3(d, d)) - r;
    axial = *t < 0.0 ? -*t : *t - c[6];
    return radial > axial ? radial : axial;
}

static double lst__tree_shape(const double *p)
{
    double t, d = lst__part(lst__tree_parts[0], p, &t);
    d = lst__smin(d, lst__part(lst__tree_parts[1], p, &t), 0.12);
    return lst__smin(d, lst__part(lst__tree_parts[2], p, &t), 0.12);
}

LSTDEF lst_result lst_builtin_mesh(const char *name, const lst_options *opt, lst_mesh *out, lst_error *err)
{
    static const lst__shape_grid kiwi = {lst__kiwi_shape, {-1.0, -1.0, -1.3}, 2.6 / 48, 48};
    static const lst__shape_grid tree = {lst__tree_shape, {-1.7, -1.7, -1.4}, 3.4 / 64, 64};
    lst_options o = lst__options(opt);
    pw_alloc a = lst__alloc(&o.allocator);
    pw_mesh m;
    pw_err e;
    pw_err_clear(&e);
    memset(&m, 0, sizeof m);
    if (out) memset(out, 0, sizeof *out);
    if (!out || !name) pw_fail(&e, PW_ERR_INVALID, "lst_builtin_mesh: NULL argument");
    else if (!strcmp(name, "sphere")) pw_shape_geosphere(&a, 8, &m, &e);
    else if (!strcmp(name, "torus")) pw_shape_torus(&a, 48, 24, 0, &m, &e);
    else if (!strcmp(name, "bumpy")) pw_shape_bumpy(&a, 12, &m, &e);
    else if (!strcmp(name, "dumbbell")) pw_shape_dumbbell(&a, 0.0332, 48, &m, &e); /* neck 1% of the diagonal */
    else if (!strcmp(name, "star")) pw_shape_star(&a, 12, 3.0, &m, &e);
    else if (!strcmp(name, "kiwi")) lst__implicit(&a, &kiwi, &m, &e);
    else if (!strcmp(name, "tree")) lst__implicit(&a, &tree, &m, &e);
    else
        pw_fail(&e, PW_ERR_INVALID, "unknown built-in surface '%s' (sphere, torus, bumpy, kiwi, tree, dumbbell, star)",
                name);
    if (e.code == PW_OK) lst__take_mesh(&m, &a, out);
    else pw_mesh_free(&a, &m);
    return lst__done(&e, err);
}

/* ---- constraints that go with the built-in surfaces (§4.3-4.5) -------------------------------------- */

/* Depth 1 and the direction along the axis of part c, at n points evenly
 * over the interval span[0] .. span[1] of its parameter. */
static int lst__axis_constraints(const pw_alloc *a, const double *c, const double span[2], int n, lst__cset *s,
                                 pw_err *e)
{
    double p[3], t0 = span[0], t1 = span[1];
    int i, k;
    for (i = 0; i < n; i++) {
        double t = t0 + (t1 - t0) * i / (n - 1);
        for (k = 0; k < 3; k++) p[k] = c[k] + t * c[3 + k];
        if (lst__add_constraint(a, s, lst__constraint(LST_CONSTRAINT_DEPTH_POINT, 0, p, NULL, 1.0, 0.0), e) ||
            lst__add_constraint(a, s, lst__constraint(LST_CONSTRAINT_DIRECTION, 0, p, c + 3, 0.0, 0.0), e))
            return PW_ERR_NOMEM;
    }
    return PW_OK;
}

/* The tree: depth 0 on the bark (the triangles whose normal is across the
 * axis of the part they belong to; the flat ends stay free, so that they
 * show the rings), 1 along the pith of every part, directions along the
 * parts. */
static int lst__tree_constraints(const pw_alloc *a, const lst_mesh *surface, lst__cset *s, pw_err *e)
{
    pw_mesh m = lst__pw_mesh(surface);
    int f, k, j, tri = 0;
    for (f = 0; f < m.nf; f++)
        for (k = m.fstart[f] + 1; k + 1 < m.fstart[f + 1]; k++, tri++) {
            const float *A = m.pos + 3 * m.fv[m.fstart[f]], *B = m.pos + 3 * m.fv[k], *C = m.pos + 3 * m.fv[k + 1];
            double u[3], w[3], n[3], c[3], t, best = 1e300, dn = 0.0;
            for (j = 0; j < 3; j++) {
                u[j] = B[j] - A[j];
                w[j] = C[j] - A[j];
                c[j] = (A[j] + B[j] + C[j]) / 3.0;
            }
            pw_cross3(u, w, n);
            pw_norm3(n);
            for (j = 0; j < 3; j++) {
                double d = fabs(lst__part(lst__tree_parts[j], c, &t));
                if (d < best) {
                    best = d;
                    dn = fabs(pw_dot3(n, lst__tree_parts[j] + 3));
                }
            }
            if (dn < 0.6 &&
                lst__add_constraint(a, s, lst__constraint(LST_CONSTRAINT_DEPTH_FACE, tri, NULL, NULL, 0.0, 0.0), e))
                return PW_ERR_NOMEM;
        }
    for (j = 0; j < 3; j++) {
        double span[2];
        span[0] = j ? 0.3 : 0.0;
        span[1] = lst__tree_parts[j][6];
        if (lst__axis_constraints(a, lst__tree_parts[j], span, 12, s, e)) return PW_ERR_NOMEM;
    }
    return PW_OK;
}

/* The torus: directions around its ring (a stroke along the core circle;
 * no depth constraint: the default depth is the distance to the surface). */
static int lst__torus_constraints(const pw_alloc *a, lst__cset *s, pw_err *e)
{
    int i;
    for (i = 0; i < 24; i++) {
        double t = i * (2.0 * 3.14159265358979323846 / 24), p[3], d[3];
        p[0] = pw_cos(t);
        p[1] = pw_sin(t);
        p[2] = 0.0;
        d[0] = -p[1];
        d[1] = p[0];
        d[2] = 0.0;
        if (lst__add_constraint(a, s, lst__constraint(LST_CONSTRAINT_DIRECTION, 0, p, d, 0.0, 0.0), e))
            return PW_ERR_NOMEM;
    }
    return PW_OK;
}

LSTDEF lst_result lst_builtin_constraints(const char *name, const lst_mesh *surface, const lst_options *opt,
                                          lst_constraints *out, lst_error *err)
{
    static const double kiwi_axis[9] = {0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0, 0, 0};
    static const double kiwi_span[2] = {-0.9, 0.9};
    lst_options o = lst__options(opt);
    pw_alloc a = lst__alloc(&o.allocator);
    lst__cset s;
    pw_err e;
    pw_err_clear(&e);
    memset(&s, 0, sizeof s);
    if (out) memset(out, 0, sizeof *out);
    if (!name || !out || (!surface && name && !strcmp(name, "tree")))
        pw_fail(&e, PW_ERR_INVALID, "lst_builtin_constraints: NULL argument");
    else if (!strcmp(name, "kiwi")) { /* the skin (one fill) at 0, the core along z at 1 */
        if (lst__add_constraint(&a, &s, lst__constraint(LST_CONSTRAINT_DEPTH_FILL, 0, NULL, NULL, 0.0, 60.0), &e) ==
            PW_OK)
            lst__axis_constraints(&a, kiwi_axis, kiwi_span, 13, &s, &e);
    } else if (!strcmp(name, "tree")) lst__tree_constraints(&a, surface, &s, &e);
    else if (!strcmp(name, "torus")) lst__torus_constraints(&a, &s, &e);
    else pw_fail(&e, PW_ERR_INVALID, "no built-in constraints for '%s' (kiwi, tree, torus)", name);
    if (e.code == PW_OK) {
        out->items = s.c;
        out->count = s.n;
        out->allocator = lst__allocator(&a);
    } else pw_free(&a, s.c);
    return lst__done(&e, err);
}
