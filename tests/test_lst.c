/* Tests of lst.h (Takayama et al. 2008), the fill: every texture type
 * covers every sample point of every tetrahedron (§5.2.6); the texture
 * coordinates map each tetrahedron's tensor axes to the texture axes
 * (§5.2.5) within a stated error on smooth fields; depth-varying types put
 * the exemplar's outer skin on the surface (§5.2.7); the fields of §5.2.2
 * (RBF exactness, Laplacian constants, principal axis, depth-aware
 * weights); masks (§5.2.1, Fig. 14); manual pasting (§4.6); determinism. */
#define LST_STATIC /* static: only what the tests call is compiled */
#define LST_IMPLEMENTATION
#include "../lst.h"
#include "pwtest.h"

/* lst_create with the exemplar and its extra channel (may be NULL) as arguments. */
static lst_result create_model(const lst_tetmesh *m, const lst_mesh *s, const lst_volume *ex, const lst_volume *val,
                               const lst_options *o, lst_model *out, lst_error *err)
{
    lst_source src;
    src.exemplar = ex, src.values = val;
    return lst_create(m, s, &src, o, out, err);
}

/* A sphere of about n tetrahedra from the built-in tetrahedralizer. */
static int sphere_tets(int n, lst_tetmesh *m)
{
    lst_options o = lst_default_options();
    lst_mesh s;
    lst_error err;
    int ok;
    o.tet.target_tets = n, o.tet.uniform = 1; /* a small uniform fill: stuffing tests cover the graded one */
    if (lst_builtin_mesh("sphere", &o, &s, &err)) return 0;
    ok = lst_tetrahedralize(&s, &o, m, NULL, &err) == LST_OK;
    lst_mesh_free(&s);
    return ok;
}

static const char *exemplar_for(int type)
{
    static const char *const names[5] = {"spots", "fibers", "layers", "fibers", "rings"};
    return names[type];
}

/* A filled sphere of about n tetrahedra. */
static int filled(int type, int n, unsigned long long seed, lst_tetmesh *m, lst_model *model)
{
    lst_options o = lst_default_options();
    lst_volume ex, val;
    lst_error err;
    int ok;
    o.type = type;
    o.seed = seed;
    if (!sphere_tets(n, m)) return 0;
    if (lst_builtin_exemplar(exemplar_for(type), 32, &o, &ex, &val, &err)) return 0;
    ok = create_model(m, NULL, &ex, &val, &o, model, &err) == LST_OK;
    if (!ok) printf("     create: %s\n", err.message);
    lst_volume_free(&ex);
    lst_volume_free(&val);
    return ok;
}

/* The smallest composite opacity over the lattice points of order `order`
 * (8: the paper's 165) of every tetrahedron. */
static double min_coverage(const lst_model *model, int order, int *worst)
{
    pw_alloc a;
    lst__view v;
    pw_err e;
    float *lat = NULL, rgba[4];
    double mn = 2.0;
    int t, q, n;
    memset(&a, 0, sizeof a);
    pw_err_clear(&e);
    if (lst__view_init(&a, model, LST_SHOW_COLOR, &v, &e)) return -1.0;
    { int grp[9]; n = lst__lattice(&a, order, &lat, grp, &e); }
    for (t = 0; t < model->mesh.ntets; t++)
        for (q = 0; q < n; q++) {
            double l[4] = {lat[4 * q], lat[4 * q + 1], lat[4 * q + 2], lat[4 * q + 3]};
            lst__eval(&v, t, l, rgba, NULL);
            if (rgba[3] < mn) mn = rgba[3], *worst = t;
        }
    pw_free(&a, lat);
    lst__view_free(&v);
    return mn;
}

static void t_coverage_all_types(void)
{
    int type;
    for (type = LST_TYPE_0; type <= LST_TYPE_2B; type++) {
        lst_tetmesh m;
        lst_model model;
        int worst = -1;
        double c;
        REQUIRE(filled(type, 2500, 1, &m, &model));
        c = min_coverage(&model, 8, &worst);
        pwt_info("type %d: %d tets, %d pastes, %.2f per tet (%.2f before pruning), min opacity %.4f", type,
                 model.mesh.ntets, model.npastes, model.layers, model.layers_before, c);
        CHECKF(c >= 0.985, "type %d: tetrahedron %d reaches only %.4f", type, worst, c);
        lst_model_free(&model);
        lst_tetmesh_free(&m);
    }
}

/* The Jacobian of paste p's map on its i-th tetrahedron: J[r][c] = d w_r / d x_c. */
static void paste_jacobian(const lst_model *model, const lst_paste *p, int i, double J[3][3])
{
    pw_tetmesh tm = lst__pw_tets(&model->mesh);
    double g[4][3];
    int r, c, k;
    pw_tet_gradients(&tm, p->tets[i], g);
    for (r = 0; r < 3; r++)
        for (c = 0; c < 3; c++) {
            J[r][c] = 0.0;
            for (k = 0; k < 4; k++) J[r][c] += p->uvw[3 * p->corners[4 * i + k] + r] * g[k][c];
        }
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* A slab 2.4 x 2.4 x 0.8 (rounded by the tetrahedralizer), about n
 * tetrahedra, with its top painted depth 0 and its bottom depth 1: flat
 * layers, a field that does not turn. */
static double slab_shape(const double *p)
{
    double d[3] = {fabs(p[0]) - 1.2, fabs(p[1]) - 1.2, fabs(p[2]) - 0.4};
    double m = d[0] > d[1] ? d[0] : d[1];
    return m > d[2] ? m : d[2];
}

static int slab(int n, lst_mesh *s, lst_tetmesh *m, lst_constraint **dc, int *nd)
{
    static const lst__shape_grid slab = {slab_shape, {-1.5, -1.5, -0.7}, 3.0 / 40, 40};
    lst_options o = lst_default_options();
    lst_error err;
    pw_alloc a;
    pw_mesh pm;
    pw_err e;
    int f, k;
    memset(&a, 0, sizeof a);
    pw_err_clear(&e);
    o.tet.target_tets = n, o.tet.uniform = 1; /* a small uniform fill: stuffing tests cover the graded one */
    if (lst__implicit(&a, &slab, &pm, &e)) return 0;
    lst__take_mesh(&pm, &a, s);
    if (lst_tetrahedralize(s, &o, m, NULL, &err)) return 0;
    *dc = (lst_constraint *)calloc((size_t)s->nfaces, sizeof **dc);
    for (f = 0, *nd = 0; f < s->nfaces; f++) {
        const float *A = s->positions + 3 * s->face_verts[3 * f], *B = s->positions + 3 * s->face_verts[3 * f + 1];
        const float *C = s->positions + 3 * s->face_verts[3 * f + 2];
        double u[3], w[3], nz;
        for (k = 0; k < 3; k++) u[k] = B[k] - A[k], w[k] = C[k] - A[k];
        nz = (u[0] * w[1] - u[1] * w[0]) / sqrt(pow(u[1] * w[2] - u[2] * w[1], 2) + pow(u[2] * w[0] - u[0] * w[2], 2) + pow(u[0] * w[1] - u[1] * w[0], 2));
        if (fabs(nz) < 0.95) continue;
        (*dc)[*nd].kind = LST_CONSTRAINT_DEPTH_FACE, (*dc)[*nd].face = f, (*dc)[(*nd)++].value = nz > 0 ? 0.0f : 1.0f;
    }
    return 1;
}

/* §5.2.5 "minimize the difference between the tensor axes of the
 * tetrahedron transformed into the texture space and the standard texture
 * coordinate axes": the images J A of the tensor axes A of every entry
 * (paste, tetrahedron) against the identity, relative error |J A - I| / |I|
 * (Frobenius), for the axes that come from fields (all three for 2-a and
 * 2-b; u for 1-a, v for 1-b). Returns the median; *p90 the 90th
 * percentile. */
static double alignment(const lst_tetmesh *m, const lst_mesh *s, const lst_options *o, double *p90)
{
    lst_model model;
    lst_field f;
    lst_error err;
    lst_volume ex, val;
    double *errs, med;
    size_t n = 0, cap = 0;
    int p, i, a, r, a0 = o->type == LST_TYPE_1B, a1 = o->type == LST_TYPE_1A ? 1 : (o->type == LST_TYPE_1B ? 2 : 3);
    lst_builtin_exemplar(exemplar_for(o->type), 32, o, &ex, &val, &err);
    if (create_model(m, s, &ex, &val, o, &model, &err) || lst_compute_field(m, s, o, &f, &err)) return 9.0;
    lst_volume_free(&ex), lst_volume_free(&val);
    for (p = 0; p < model.npastes; p++) cap += (size_t)model.pastes[p].ntets;
    errs = (double *)malloc(sizeof(double) * cap);
    for (p = 0; p < model.npastes; p++)
        for (i = 0; i < model.pastes[p].ntets; i++) {
            double J[3][3], e2 = 0.0;
            const float *fr = f.frame + 9 * model.pastes[p].tets[i];
            paste_jacobian(&model, &model.pastes[p], i, J);
            for (a = a0; a < a1; a++)
                for (r = 0; r < 3; r++) {
                    double img = J[r][0] * fr[3 * a] + J[r][1] * fr[3 * a + 1] + J[r][2] * fr[3 * a + 2];
                    e2 += (img - (r == a)) * (img - (r == a));
                }
            errs[n++] = sqrt(e2 / (a1 - a0));
        }
    qsort(errs, n, sizeof *errs, cmp_double);
    med = errs[n / 2];
    *p90 = errs[n * 9 / 10];
    free(errs);
    lst_field_free(&f);
    lst_model_free(&model);
    return med;
}

/* Bounds, from the geometry of each case. The slab's depth is linear (the
 * RBF reproduces linear functions) and the direction constant: the map is
 * affine, the error must vanish (bound 1e-3). On the sphere with the
 * distance depth the tensor turns radially: at scale 0.3 (pastes of radius
 * 0.12, turning up to about 0.3 radian across one away from the centre) the
 * least-squares map can only bend so far: bound 0.15 on the median; for
 * 2-b the pastes are as large as the radius (scale = 1/|grad depth|) and
 * the field turns across each by up to a radian: bound 0.25 (the paper's
 * §7 singularity at the centre). */
static void t_alignment(void)
{
    lst_options o = lst_default_options();
    lst_mesh s;
    lst_tetmesh m;
    lst_constraint *dc;
    double med, p90;
    int nd, type;
    REQUIRE(slab(3000, &s, &m, &dc, &nd));
    o.constraints = dc, o.nconstraints = nd, o.axis[0] = 1.0f, o.axis[1] = 0.3f;
    for (type = LST_TYPE_1A; type <= LST_TYPE_2B; type++) {
        o.type = type;
        med = alignment(&m, &s, &o, &p90);
        pwt_info("slab, type %d: median relative error of the mapped field axes %.2g (90th percentile %.2g), bound 1e-3",
                 type, med, p90);
        CHECK(med < 1e-3);
    }
    free(dc);
    lst_tetmesh_free(&m);
    lst_mesh_free(&s);
    REQUIRE(sphere_tets(3000, &m));
    o = lst_default_options();
    o.type = LST_TYPE_2A, o.scale = 0.3f, o.axis[1] = 1.0f;
    med = alignment(&m, NULL, &o, &p90);
    pwt_info("sphere, 2-a at scale 0.3: median %.4f (90th percentile %.4f), bound 0.15", med, p90);
    CHECK(med < 0.15);
    o.type = LST_TYPE_2B;
    med = alignment(&m, NULL, &o, &p90);
    pwt_info("sphere, 2-b (pastes as large as the radius, the field turns across them): median %.4f (90th percentile "
             "%.4f), bound 0.25", med, p90);
    CHECK(med < 0.25);
    lst_tetmesh_free(&m);
}

/* §5.2.7 / §6 "our depth adjustment technique arranges solid textures
 * successfully so that such outer skin regions align precisely with the
 * surfaces": every paste's v coordinate at every boundary vertex is within
 * the skin (half a voxel: the depth coordinate stays on the exemplar's
 * outermost voxel centres), and the surface shows the skin
 * colour of the layers exemplar. */
static void t_skin_on_surface(void)
{
    lst_tetmesh m;
    lst_model model;
    pw_alloc a;
    lst__geo g;
    lst__view v;
    pw_err e;
    unsigned char *onb;
    pw_tetmesh tm;
    float skin[3], rgba[4];
    double vmax = 0.0, cerr = 0.0;
    int p, i, f, k;
    memset(&a, 0, sizeof a);
    pw_err_clear(&e);
    REQUIRE(filled(LST_TYPE_1B, 2500, 3, &m, &model));
    tm = lst__pw_tets(&model.mesh);
    REQUIRE(lst__geo_init(&a, &tm, &g, &e) == PW_OK);
    onb = (unsigned char *)calloc((size_t)tm.nv, 1);
    for (f = 0; f < g.nbface; f++) {
        int c[3];
        lst__face_verts(&tm, g.bface[f], c);
        for (k = 0; k < 3; k++) onb[c[k]] = 1;
    }
    for (p = 0; p < model.npastes; p++)
        for (i = 0; i < model.pastes[p].nverts; i++)
            if (onb[model.pastes[p].verts[i]] && model.pastes[p].uvw[3 * i + 1] > vmax) vmax = model.pastes[p].uvw[3 * i + 1];
    {
        pw_volume tex = lst__pw_volume(&model.texture);
        lst__sample(&tex, 0.5, 0.0, 0.5, skin);
    }
    REQUIRE(lst__view_init(&a, &model, LST_SHOW_COLOR, &v, &e) == PW_OK);
    for (f = 0; f < g.nbface; f++) { /* face centroids */
        double l[4] = {1.0 / 3, 1.0 / 3, 1.0 / 3, 1.0 / 3};
        l[g.bface[f] & 3] = 0.0;
        lst__eval(&v, g.bface[f] >> 2, l, rgba, NULL);
        for (k = 0; k < 3; k++)
            if (fabs(rgba[k] - skin[k]) > cerr) cerr = fabs(rgba[k] - skin[k]);
    }
    pwt_info("largest v at a boundary vertex %.2g; largest colour difference to the skin on the surface %.3f", vmax, cerr);
    CHECK(vmax <= 1.0 / 64);
    CHECK(cerr < 0.05);
    free(onb);
    lst__view_free(&v);
    lst__geo_free(&a, &g);
    lst_model_free(&model);
    lst_tetmesh_free(&m);
}

/* The same with an RBF depth (painted skin, an axis at depth 1): the
 * boundary snaps to the painted 0 exactly. */
static void t_skin_rbf(void)
{
    lst_options o = lst_default_options();
    lst_mesh s;
    lst_tetmesh m;
    lst_field f;
    lst_error err;
    lst_constraints c;
    int k, bad = 0, t;
    double dmax = 0.0;
    o.tet.target_tets = 2500, o.tet.uniform = 1; /* a small uniform fill: stuffing tests cover the graded one */
    o.type = LST_TYPE_2B;
    REQUIRE(lst_builtin_mesh("kiwi", &o, &s, &err) == LST_OK);
    REQUIRE(lst_tetrahedralize(&s, &o, &m, NULL, &err) == LST_OK);
    REQUIRE(lst_builtin_constraints("kiwi", &s, &o, &c, &err) == LST_OK);
    o.constraints = c.items, o.nconstraints = c.count;
    REQUIRE(lst_compute_field(&m, &s, &o, &f, &err) == LST_OK);
    {
        pw_alloc a;
        lst__geo g;
        pw_tetmesh tm = lst__pw_tets(&m);
        pw_err e;
        memset(&a, 0, sizeof a);
        pw_err_clear(&e);
        REQUIRE(lst__geo_init(&a, &tm, &g, &e) == PW_OK);
        for (k = 0; k < g.nbface; k++) {
            int c[3], j;
            lst__face_verts(&tm, g.bface[k], c);
            for (j = 0; j < 3; j++) bad += f.depth[c[j]] != 0.0f;
        }
        lst__geo_free(&a, &g);
    }
    for (t = 0; t < m.nverts; t++) dmax = f.depth[t] > dmax ? f.depth[t] : dmax;
    pwt_info("kiwi: %d boundary vertex depths not 0; deepest vertex %.3f", bad, dmax);
    CHECK_EQ_INT(bad, 0);
    CHECK(dmax > 0.9);
    lst_field_free(&f);
    lst_constraints_free(&c);
    lst_tetmesh_free(&m);
    lst_mesh_free(&s);
}

/* The thin-plate RBF reproduces linear functions exactly (its polynomial
 * part), at points away from the centres too. */
static void t_rbf_linear(void)
{
    pw_alloc a;
    lst__rbf rbf;
    lst__pts pts;
    pw_err e;
    double p[60 * 3], val[60], o[3] = {0, 0, 0}, worst = 0.0;
    pw_rng r = pw_rng_seed(4, 2);
    int i, k;
    memset(&a, 0, sizeof a);
    pw_err_clear(&e);
    for (i = 0; i < 60; i++) {
        for (k = 0; k < 3; k++) p[3 * i + k] = 2.0 * pw_rng_double(&r) - 1.0;
        val[i] = 0.3 + 0.2 * p[3 * i] - 0.5 * p[3 * i + 1] + 0.1 * p[3 * i + 2];
    }
    pts.n = 60, pts.p = p, pts.val = val;
    memcpy(rbf.o, o, sizeof rbf.o), rbf.s = 2.0;
    REQUIRE(lst__rbf_fit(&a, &pts, 40, &rbf, &e) == PW_OK);
    for (i = 0; i < 200; i++) {
        double x[3], g[3], f;
        for (k = 0; k < 3; k++) x[k] = 1.6 * pw_rng_double(&r) - 0.8;
        f = lst__rbf_eval(&rbf, x, g);
        f -= 0.3 + 0.2 * x[0] - 0.5 * x[1] + 0.1 * x[2];
        if (fabs(f) > worst) worst = fabs(f);
        if (fabs(g[0] - 0.2) > worst) worst = fabs(g[0] - 0.2);
    }
    CHECKF(worst < 1e-4, "RBF error on a linear function %g", worst);
    lst__rbf_free(&a, &rbf);
}

/* Laplacian smoothing of one constant constraint is that constant
 * everywhere; two scale constraints give a field between them, monotone
 * along the line joining them. */
static void t_laplacian(void)
{
    lst_options o = lst_default_options();
    lst_tetmesh m;
    lst_field f;
    lst_error err;
    lst_constraint fc[2];
    int t, bad = 0;
    double lo = 1e9, hi = 0;
    memset(fc, 0, sizeof fc);
    REQUIRE(sphere_tets(2000, &m));
    fc[0].kind = LST_CONSTRAINT_SCALE, fc[0].point[0] = -0.7f, fc[0].value = 0.2f;
    fc[1].kind = LST_CONSTRAINT_SCALE, fc[1].point[0] = 0.7f, fc[1].value = 0.6f;
    o.constraints = fc, o.nconstraints = 1;
    REQUIRE(lst_compute_field(&m, NULL, &o, &f, &err) == LST_OK);
    for (t = 0; t < m.ntets; t++) {
        const float *u = f.frame + 9 * t;
        double s = sqrt((double)u[0] * u[0] + (double)u[1] * u[1] + (double)u[2] * u[2]);
        bad += fabs(s - 0.2) > 2e-3;
    }
    CHECK_EQ_INT(bad, 0);
    lst_field_free(&f);
    o.nconstraints = 2;
    REQUIRE(lst_compute_field(&m, NULL, &o, &f, &err) == LST_OK);
    for (t = 0; t < m.ntets; t++) {
        const float *u = f.frame + 9 * t;
        double s = sqrt((double)u[0] * u[0] + (double)u[1] * u[1] + (double)u[2] * u[2]);
        lo = s < lo ? s : lo, hi = s > hi ? s : hi;
    }
    pwt_info("two scale constraints 0.2 and 0.6: the field spans %.3f..%.3f", lo, hi);
    CHECK(lo > 0.15 && lo < 0.3 && hi > 0.5 && hi < 0.65);
    lst_field_free(&f);
    lst_tetmesh_free(&m);
}

/* The principal axis of an elongated shape (the kiwi, long along z) is
 * the default direction; given axis and constraints are followed. */
static void t_principal_axis(void)
{
    lst_options o = lst_default_options();
    lst_mesh s;
    lst_tetmesh m;
    lst_field f;
    lst_error err;
    lst_constraint fc;
    double worst = 1.0;
    int t;
    o.tet.target_tets = 2000, o.tet.uniform = 1; /* a small uniform fill: stuffing tests cover the graded one */
    o.type = LST_TYPE_1A;
    REQUIRE(lst_builtin_mesh("kiwi", &o, &s, &err) == LST_OK);
    REQUIRE(lst_tetrahedralize(&s, &o, &m, NULL, &err) == LST_OK);
    REQUIRE(lst_compute_field(&m, NULL, &o, &f, &err) == LST_OK);
    for (t = 0; t < m.ntets; t++) {
        const float *u = f.frame + 9 * t;
        double c = fabs(u[2]) / sqrt((double)u[0] * u[0] + (double)u[1] * u[1] + (double)u[2] * u[2]);
        worst = c < worst ? c : worst;
    }
    CHECKF(worst > 0.9999, "the u axis leaves the kiwi's long axis (cos %g)", worst);
    lst_field_free(&f);
    memset(&fc, 0, sizeof fc);
    fc.kind = LST_CONSTRAINT_DIRECTION, fc.direction[0] = 1.0f;
    o.constraints = &fc, o.nconstraints = 1;
    REQUIRE(lst_compute_field(&m, NULL, &o, &f, &err) == LST_OK);
    worst = 1.0;
    for (t = 0; t < m.ntets; t++) {
        const float *u = f.frame + 9 * t;
        double c = u[0] / sqrt((double)u[0] * u[0] + (double)u[1] * u[1] + (double)u[2] * u[2]);
        worst = c < worst ? c : worst;
    }
    CHECKF(worst > 0.999, "one direction constraint along x: cos %g", worst);
    lst_field_free(&f);
    lst_tetmesh_free(&m);
    lst_mesh_free(&s);
}

/* §5.2.2 2-a: the direction is orthogonalised against the depth gradient,
 * the frame is orthonormal and right-handed (no mirrored exemplar). */
static void t_frames_orthonormal(void)
{
    lst_options o = lst_default_options();
    lst_tetmesh m;
    lst_field f;
    lst_error err;
    double worst = 0.0;
    int t, type, k;
    REQUIRE(sphere_tets(2000, &m));
    for (type = LST_TYPE_0; type <= LST_TYPE_2B; type++) {
        o.type = type;
        REQUIRE(lst_compute_field(&m, NULL, &o, &f, &err) == LST_OK);
        for (t = 0; t < m.ntets; t++) {
            const float *a = f.frame + 9 * t;
            double s2 = a[0] * (double)a[0] + a[1] * (double)a[1] + a[2] * (double)a[2], d[3], det;
            for (k = 0; k < 3; k++) d[k] = (a[3 * k] * (double)a[3 * ((k + 1) % 3)] + a[3 * k + 1] * (double)a[3 * ((k + 1) % 3) + 1] +
                                            a[3 * k + 2] * (double)a[3 * ((k + 1) % 3) + 2]) / s2;
            det = (a[0] * ((double)a[4] * a[8] - (double)a[5] * a[7]) - a[1] * ((double)a[3] * a[8] - (double)a[5] * a[6]) +
                   a[2] * ((double)a[3] * a[7] - (double)a[4] * a[6])) / (s2 * sqrt(s2));
            for (k = 0; k < 3; k++) worst = fabs(d[k]) > worst ? fabs(d[k]) : worst;
            worst = fabs(det - 1.0) > worst ? fabs(det - 1.0) : worst;
        }
        lst_field_free(&f);
    }
    CHECKF(worst < 1e-4, "frames not orthonormal and right-handed (%g)", worst);
    lst_tetmesh_free(&m);
}

/* §4.3 multi-face fill: from a top face of the slab it paints the top and
 * stops at the rounded edge's crease; a single face paints one triangle. */
static void t_flood_fill(void)
{
    lst_mesh s;
    lst_tetmesh m;
    lst_constraint *dc, fill;
    lst_options o = lst_default_options();
    pw_alloc a;
    pw_trimesh tm;
    pw_mesh pm;
    pw_err e;
    double *paint;
    int nd, f, top = -1, painted = 0, tops = 0;
    memset(&a, 0, sizeof a);
    pw_err_clear(&e);
    REQUIRE(slab(1500, &s, &m, &dc, &nd));
    pm = lst__pw_mesh(&s);
    REQUIRE(pw_trimesh_init(&a, &pm, &tm, &e) == PW_OK);
    for (f = 0; f < tm.nf; f++)
        if (tm.normal[3 * f + 2] > 0.99f) {
            tops++;
            if (top < 0) top = f;
        }
    memset(&fill, 0, sizeof fill);
    fill.kind = LST_CONSTRAINT_DEPTH_FILL, fill.face = top, fill.crease = 30.0f;
    o.constraints = &fill, o.nconstraints = 1;
    paint = (double *)malloc(sizeof(double) * (size_t)tm.nf);
    REQUIRE(lst__paint(&a, &tm, &o, paint, &e) == PW_OK);
    for (f = 0; f < tm.nf; f++) painted += paint[f] == 0.0;
    pwt_info("fill from a top face: %d triangles painted, %d face up, %d in all", painted, tops, tm.nf);
    CHECK(painted >= tops && painted < tops + tm.nf / 10);
    fill.kind = LST_CONSTRAINT_DEPTH_FACE;
    REQUIRE(lst__paint(&a, &tm, &o, paint, &e) == PW_OK);
    for (f = 0, painted = 0; f < tm.nf; f++) painted += paint[f] == 0.0;
    CHECK_EQ_INT(painted, 1);
    free(paint);
    free(dc);
    pw_trimesh_free(&a, &tm);
    lst_tetmesh_free(&m);
    lst_mesh_free(&s);
}

/* §5.2.2 the 2-a/2-b weights: w_ij = exp(-(d_i - d_j)^2) / sum_k
 * exp(-(d_i - d_k)^2) over the one-ring, rows of the Laplacian summing to
 * zero; uniform 1/|N_i| without a depth. */
static void t_layer_weights(void)
{
    lst_tetmesh m;
    pw_alloc a;
    lst__geo g;
    lst__lsq sa, sb; /* no constraints */
    lst__field_job job;
    pw_csr A, B;
    pw_err e;
    pw_tetmesh tm;
    double *depth, worst = 0.0;
    int v, k;
    memset(&a, 0, sizeof a);
    memset(&sa, 0, sizeof sa);
    memset(&sb, 0, sizeof sb);
    memset(&job, 0, sizeof job);
    sa.W = sb.W = 10.0;
    job.a = &a, job.g = &g, job.e = &e;
    pw_err_clear(&e);
    REQUIRE(sphere_tets(800, &m));
    tm = lst__pw_tets(&m);
    REQUIRE(lst__geo_init(&a, &tm, &g, &e) == PW_OK);
    depth = (double *)malloc(sizeof(double) * (size_t)tm.nv);
    for (v = 0; v < tm.nv; v++) depth[v] = 0.5 + 0.5 * tm.pos[3 * v]; /* varies along x */
    REQUIRE(lst__smooth_matrix(&job, depth, 3.0, &sa) == PW_OK);
    REQUIRE(lst__smooth_matrix(&job, NULL, 1.0, &sb) == PW_OK);
    A = sa.A, B = sb.A;
    for (v = 0; v < tm.nv; v++) {
        double sum = 0.0, sumw = 0.0, row = 0.0;
        for (k = g.rings.start[v]; k < g.rings.start[v + 1]; k++) {
            double dd = 3.0 * (depth[v] - depth[g.rings.adj[k]]);
            sumw += exp(-dd * dd);
        }
        for (k = A.rowptr[v]; k < A.rowptr[v + 1]; k++) {
            int j = A.col[k];
            row += A.val[k];
            if (j != v) {
                double dd = 3.0 * (depth[v] - depth[j]), want = -exp(-dd * dd) / sumw;
                sum = fabs(A.val[k] - want);
                worst = sum > worst ? sum : worst;
            }
        }
        worst = fabs(row) > worst ? fabs(row) : worst;
        for (k = B.rowptr[v]; k < B.rowptr[v + 1]; k++)
            if (B.col[k] != v) {
                double want = -1.0 / (g.rings.start[v + 1] - g.rings.start[v]);
                worst = fabs(B.val[k] - want) > worst ? fabs(B.val[k] - want) : worst;
            }
    }
    CHECKF(worst < 1e-12, "weights off by %g", worst);
    pw_csr_free(&a, &A), pw_csr_free(&a, &B);
    free(depth);
    lst__geo_free(&a, &g);
    lst_tetmesh_free(&m);
}

/* exp without libm matches libm closely (the weights of §5.2.2). */
static void t_exp(void)
{
    double x, worst = 0.0;
    for (x = 0.0; x > -30.0; x -= 0.01) {
        double r = fabs(lst__exp_neg(x) - exp(x)) / exp(x);
        if (r > worst) worst = r;
    }
    CHECKF(worst < 1e-12, "relative error %g", worst);
}

/* §5.2.1 splotch: opaque in the middle, fading over the fall-off, zero at
 * the cube's faces; §5.2.7 Fig. 14: the three layers along v, the outer
 * one opaque at v = 0 (the skin), the inner at v = 1. */
static void t_masks(void)
{
    lst_options o = lst_default_options();
    lst_volume ex;
    lst_masks masks;
    lst_error err;
    pw_volume m0, m2;
    REQUIRE(lst_builtin_exemplar("spots", 32, &o, &ex, NULL, &err) == LST_OK);
    REQUIRE(lst_make_masks(&ex, &o, &masks, &err) == LST_OK);
    CHECK_EQ_INT(masks.count, 1);
    m0 = lst__pw_volume(&masks.volumes[0]);
    CHECK(lst__mask_alpha(&m0, 0.5, 0.5, 0.5) == 1.0f);
    CHECK(lst__mask_alpha(&m0, 0.5, 0.5, 0.99) == 0.0f);
    CHECK(lst__mask_alpha(&m0, 0.01, 0.5, 0.5) == 0.0f);
    lst_masks_free(&masks);
    CHECK(masks.count == 0 && masks.volumes == NULL);
    lst_masks_free(&masks);
    o.type = LST_TYPE_2B;
    REQUIRE(lst_make_masks(&ex, &o, &masks, &err) == LST_OK);
    CHECK_EQ_INT(masks.count, 3);
    m0 = lst__pw_volume(&masks.volumes[0]);
    m2 = lst__pw_volume(&masks.volumes[2]);
    CHECK(lst__mask_alpha(&m0, 0.5, 0.0, 0.5) == 1.0f && lst__mask_alpha(&m0, 0.5, 0.2, 0.5) == 1.0f);
    CHECK(lst__mask_alpha(&m0, 0.5, 0.9, 0.5) == 0.0f);
    CHECK(lst__mask_alpha(&m2, 0.5, 1.0, 0.5) == 1.0f && lst__mask_alpha(&m2, 0.5, 0.1, 0.5) == 0.0f);
    {
        pw_volume m1 = lst__pw_volume(&masks.volumes[1]);
        float mid = lst__mask_alpha(&m1, 0.5, 0.5, 0.5), edge = lst__mask_alpha(&m1, 0.5, 0.5, 0.5 + 0.34);
        CHECK(mid == 1.0f && edge > 0.0f && edge < 1.0f);
    }
    lst_masks_free(&masks);
    lst_volume_free(&ex);
}

/* Whether a point of [lo, hi] along one axis of n cells reaches cell c as
 * lst__cell_any looks it up: cell 0 from -0.5, the last to n - 0.5, each
 * other [c, c + 1). */
static int box_reaches(float lo, float hi, int c, int n)
{
    float a = c == 0 ? -0.5f : (float)c, b = c == n - 1 ? (float)n - 0.5f : (float)c + 1.0f;
    return lo <= b && hi >= a && (c == n - 1 || lo < b);
}

/* The summed cells of a mask (lst__cells_in_box, growth's and coverage's
 * shortcut past sampling): against every cell with alpha tested one by
 * one, on random boxes of a random sparse mask of odd sides, many of them
 * reaching past the volume; a box that is not finite must be sampled. */
static void t_mask_box(void)
{
    pw_alloc a;
    pw_volume vol;
    lst__mask m;
    pw_err e;
    pw_rng r = pw_rng_seed(11, 3);
    int i, k, x, y, z, wrong = 0, empty = 0, full = 0;
    memset(&a, 0, sizeof a);
    vol.c = 1, vol.x = 7, vol.y = 5, vol.z = 6;
    vol.px = (float *)calloc((size_t)vol.x * vol.y * vol.z, sizeof(float));
    REQUIRE(vol.px != NULL);
    for (i = 0; i < vol.x * vol.y * vol.z; i++) vol.px[i] = pw_rng_double(&r) < 0.03 ? 0.5f : 0.0f;
    memset(&m, 0, sizeof m);
    pw_err_clear(&e);
    REQUIRE(lst__mask_init(&a, &vol, &m, &e) == PW_OK);
    for (i = 0; i < 20000; i++) {
        float lo[3], hi[3];
        int want = 0, got;
        for (k = 0; k < 3; k++) {
            int n = k == 0 ? vol.x : k == 1 ? vol.y : vol.z;
            float u = (float)(pw_rng_double(&r) * (n + 3) - 2.0), w = (float)(pw_rng_double(&r) * 3.0);
            lo[k] = u;
            hi[k] = u + (i % 4 == 0 ? 0.0f : w);
        }
        for (z = 0; z < vol.z; z++)
            for (y = 0; y < vol.y; y++)
                for (x = 0; x < vol.x; x++) {
                    size_t c = ((size_t)z * vol.y + y) * vol.x + x;
                    want |= (m.cell[c >> 3] >> (c & 7) & 1) && box_reaches(lo[0], hi[0], x, vol.x) &&
                            box_reaches(lo[1], hi[1], y, vol.y) && box_reaches(lo[2], hi[2], z, vol.z);
                }
        got = lst__cells_in_box(&m, lo, hi);
        wrong += got != want;
        empty += !want;
        full += want;
    }
    CHECKF(wrong == 0, "%d of 20000 boxes answered wrong", wrong);
    CHECKF(empty > 2000 && full > 2000, "boxes: %d empty, %d not", empty, full);
    {
        float lo[3] = {0.0f, 0.0f, 0.0f}, hi[3] = {1.0f, 1.0f, 1.0f};
        lo[1] = NAN;
        CHECK(lst__cells_in_box(&m, lo, hi) == 1);
    }
    lst__mask_free(&a, &m);
    free(vol.px);
}

/* Same inputs and seed: the same model file byte for byte; another seed:
 * another model. */
static void t_determinism(void)
{
    lst_tetmesh m1, m2;
    lst_model a, b, c;
    pw_buf x, y, z;
    lst_error err;
    memset(&x, 0, sizeof x), memset(&y, 0, sizeof y), memset(&z, 0, sizeof z);
    REQUIRE(filled(LST_TYPE_2B, 1500, 7, &m1, &a));
    REQUIRE(filled(LST_TYPE_2B, 1500, 7, &m2, &b));
    lst_tetmesh_free(&m2);
    REQUIRE(filled(LST_TYPE_2B, 1500, 8, &m2, &c));
    REQUIRE(lst_write_model(&a, pw_buf_write, &x, &err) == LST_OK);
    REQUIRE(lst_write_model(&b, pw_buf_write, &y, &err) == LST_OK);
    REQUIRE(lst_write_model(&c, pw_buf_write, &z, &err) == LST_OK);
    CHECK(x.size == y.size && !memcmp(x.data, y.data, x.size));
    CHECK(x.size != z.size || memcmp(x.data, z.data, x.size));
    free(x.data), free(y.data), free(z.data);
    lst_model_free(&a), lst_model_free(&b), lst_model_free(&c);
    lst_tetmesh_free(&m1), lst_tetmesh_free(&m2);
}

/* §4.6: a manual paste on top shows the exemplar's centre at its point;
 * outside the model it is refused. */
static void t_manual_paste(void)
{
    lst_tetmesh m;
    lst_model model;
    lst_error err;
    lst_paste_spec spec;
    float rgba[4], want[3];
    pw_volume tex;
    int n, k;
    memset(&spec, 0, sizeof spec);
    spec.point[0] = 0.1f, spec.point[1] = 0.2f, spec.point[2] = -0.1f;
    spec.u_axis[0] = 1.0f, spec.v_axis[1] = 1.0f, spec.scale = 0.5f;
    REQUIRE(filled(LST_TYPE_0, 2000, 2, &m, &model));
    n = model.npastes;
    REQUIRE(lst_paste_at(&model, &spec, NULL, &err) == LST_OK);
    CHECK_EQ_INT(model.npastes, n + 1);
    CHECK(model.pastes[n].ntets > 10);
    REQUIRE(lst_eval(&model, spec.point, 1, rgba, NULL, &err) == LST_OK);
    tex = lst__pw_volume(&model.texture);
    lst__sample(&tex, 0.5, 0.5, 0.5, want);
    for (k = 0; k < 3; k++) CHECK_NEAR(rgba[k], want[k], 1e-3);
    spec.point[0] = 3.0f, spec.point[1] = spec.point[2] = 0.0f;
    CHECK(lst_paste_at(&model, &spec, NULL, &err) == LST_ERR_INVALID && strstr(err.message, "outside"));
    spec.point[0] = 0.1f, spec.point[1] = 0.2f, spec.point[2] = -0.1f, spec.mask = 3;
    CHECK(lst_paste_at(&model, &spec, NULL, &err) == LST_ERR_INVALID && strstr(err.message, "mask 3"));
    lst_model_free(&model);
    lst_tetmesh_free(&m);
}

static int cancel_after(void *user, float done, const char *stage)
{
    (void)done, (void)stage;
    return --*(int *)user < 0;
}

static void t_cancel(void)
{
    lst_options o = lst_default_options();
    lst_tetmesh m;
    lst_volume ex;
    lst_model model;
    lst_error err;
    int calls = 3;
    REQUIRE(sphere_tets(1500, &m));
    REQUIRE(lst_builtin_exemplar("spots", 16, &o, &ex, NULL, &err) == LST_OK);
    o.progress = cancel_after, o.progress_user = &calls;
    CHECK(create_model(&m, NULL, &ex, NULL, &o, &model, &err) == LST_ERR_CANCELLED);
    CHECK(model.mesh.tets == NULL && model.pastes == NULL);
    lst_volume_free(&ex);
    lst_tetmesh_free(&m);
}

/* Depth-varying pastes take the depth as v (§5.2.7). Where the depth is
 * exactly 0 or 1 (the surface; an RBF constraint of depth 1), v sat on the
 * exemplar's face, and a sample point interpolated from corners there
 * fell just outside it or just inside depending on rounding: the fill's
 * coverage test counted it covered, the renderer saw nothing (fuzz_lst
 * found it: 4 of 480 sample points of a 2-b fill with alpha 0). The depth
 * coordinate now stays between the outermost voxel centres. The fuzzer's
 * input first (its constraint file, with a byte-order mark, as it is in
 * fuzz/corpus/fuzz_lst/depth_at_face), then both depth-varying types over
 * seeds and lattice orders with the same constraints. */
static void t_depth_at_exemplar_faces(void)
{
    static const char file[] = "\357\273\277face 3 0\nfill 0 0 40\npoint 0 0 0 1\ndepth-stroke 1 0 0 -0.5 0 0 0.5\n";
    lst_options o = lst_default_options();
    lst_constraints dc;
    lst_tetmesh m;
    lst_volume ex;
    lst_error err;
    double worst = 2.0;
    int type, seed, order, bad = 0, fills = 0;
    REQUIRE(sphere_tets(60, &m));
    REQUIRE(lst_builtin_exemplar("rings", 8, &o, &ex, NULL, &err) == LST_OK);
    REQUIRE(lst_read_constraints(file, sizeof file - 1, "depth_at_face", NULL, &dc, &err) == LST_OK);
    for (type = LST_TYPE_1B; type <= LST_TYPE_2B; type += LST_TYPE_2B - LST_TYPE_1B)
        for (seed = 0; seed < 4; seed++)
            for (order = 1; order <= 3; order++) {
                lst_model model;
                int t;
                double c;
                o.type = type, o.seed = type == LST_TYPE_2B && seed == 0 ? 187 : (unsigned long long)seed;
                o.samples = order, o.scale = 2.0f, o.constraints = dc.items, o.nconstraints = dc.count, o.max_pastes = 3000;
                if (create_model(&m, NULL, &ex, NULL, &o, &model, &err) != LST_OK) {
                    CHECKF(0, "type %d seed %d order %d: %s", type, seed, order, err.message);
                    continue;
                }
                c = min_coverage(&model, order, &t);
                if (c < worst) worst = c;
                bad += c < 0.98;
                fills++;
                lst_model_free(&model);
            }
    pwt_info("%d fills of types 1-b and 2-b with depth 1 at a point: least opacity at a sample point %.4f", fills, worst);
    CHECK(fills == 24 && bad == 0);
    lst_constraints_free(&dc);
    lst_volume_free(&ex);
    lst_tetmesh_free(&m);
}

static const pwt_case cases[] = {
    {"coverage_all_types", t_coverage_all_types},
    {"alignment", t_alignment},
    {"skin_on_surface", t_skin_on_surface},
    {"skin_rbf", t_skin_rbf},
    {"depth_at_exemplar_faces", t_depth_at_exemplar_faces},
    {"rbf_linear", t_rbf_linear},
    {"laplacian", t_laplacian},
    {"principal_axis", t_principal_axis},
    {"frames_orthonormal", t_frames_orthonormal},
    {"flood_fill", t_flood_fill},
    {"layer_weights", t_layer_weights},
    {"exp", t_exp},
    {"masks", t_masks},
    {"mask_box", t_mask_box},
    {"determinism", t_determinism},
    {"manual_paste", t_manual_paste},
    {"cancel", t_cancel},
};
PWT_MAIN(cases)
