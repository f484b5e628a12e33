/* Tests of src/common/stuffing.h, the built-in tetrahedralizer: validity
 * (positive volumes, conformity, closed boundary), the dihedral-angle
 * bounds, the fit of the boundary to the input surface, the refusals of
 * bad surfaces, determinism, cancellation, allocation failures, and real
 * CGAL meshes (skipped when `make data` has not run). */
#include "../src/common/stuffing.h"
#include "../src/common/shapes.h"
#include "../src/common/rng.h"
#include "pwtest.h"

/* The bounds that Labelle & Shewchuk prove for alpha_long = 0.24999 and
 * alpha_short = 0.41189 (the abstract's 10.7 and 164.8 degrees). */
#define MIN_DIHEDRAL 10.7
#define MAX_DIHEDRAL 164.8

typedef struct surf {
    pw_mesh m; /* triangles only */
} surf;

static int surf_from_mesh(pw_mesh *in, surf *s)
{
    pw_err e;
    pw_err_clear(&e);
    if (pw_mesh_triangulate(NULL, in, &s->m, NULL, &e) != PW_OK) return 0;
    pw_mesh_free(NULL, in);
    return 1;
}

static int sphere(int n, surf *s)
{
    pw_mesh m;
    pw_err e;
    pw_err_clear(&e);
    return pw_shape_geosphere(NULL, n, &m, &e) == PW_OK && surf_from_mesh(&m, s);
}

static int load(const char *path, surf *s)
{
    unsigned char *d;
    size_t n;
    pw_mesh m;
    pw_err e;
    int ok;
    pw_err_clear(&e);
    if (pw_read_file(NULL, path, &d, &n, &e) != PW_OK) return 0;
    ok = pw_mesh_read_memory(NULL, d, n, path, &m, &e) == PW_OK && surf_from_mesh(&m, s);
    free(d);
    return ok;
}

static int stuff(const surf *s, int target, pw_tetmesh *out, pw_err *e)
{
    pw_stuff_options o = pw_stuff_default_options();
    o.target_tets = target;
    pw_err_clear(e);
    return pw_stuff_tetrahedralize(NULL, s->m.pos, s->m.nv, s->m.fv, s->m.nf, &o, NULL, out, e);
}

static int cmp_edge(const void *x, const void *y)
{
    const long long *a = (const long long *)x, *b = (const long long *)y;
    return (*a > *b) - (*a < *b);
}

/* Closed: every directed boundary edge a->b is matched by one b->a (an edge
 * may carry four triangles where two parts of the solid touch). */
static int boundary_closed(const int *tri, int nb)
{
    long long *fw = (long long *)malloc(sizeof(long long) * 3 * (size_t)nb);
    long long *bw = (long long *)malloc(sizeof(long long) * 3 * (size_t)nb);
    int i, ok;
    for (i = 0; i < 3 * nb; i++) {
        long long a = tri[i], b = tri[i - i % 3 + (i % 3 + 1) % 3];
        fw[i] = (a << 32) | b;
        bw[i] = (b << 32) | a;
    }
    qsort(fw, (size_t)(3 * nb), sizeof *fw, cmp_edge);
    qsort(bw, (size_t)(3 * nb), sizeof *bw, cmp_edge);
    ok = !memcmp(fw, bw, sizeof(long long) * 3 * (size_t)nb);
    free(fw);
    free(bw);
    return ok;
}

/* Every tetrahedron positive, the mesh conforming with a closed boundary,
 * the angles within the bounds; returns the enclosed volume. */
static double check_mesh(const pw_tetmesh *t, double *lo, double *hi)
{
    int *btri = NULL, nb = 0, k, bad = 0;
    double vol = 0.0;
    pw_err e;
    pw_err_clear(&e);
    for (k = 0; k < t->nt; k++) {
        double v = pw_tet_volume6(t, k);
        if (!(v > 0.0)) bad++;
        vol += v / 6.0;
    }
    CHECKF(bad == 0, "%d of %d tetrahedra not positive", bad, t->nt);
    for (k = 0; k < 4 * t->nt; k++) bad += t->tet[k] < 0 || t->tet[k] >= t->nv;
    CHECKF(bad == 0, "vertex indices out of range");
    CHECKF(pw_stuff_boundary(NULL, t, &btri, &nb, &e) == PW_OK, "not conforming: %s", e.msg);
    CHECKF(nb > 0 && boundary_closed(btri, nb), "boundary of %d triangles not closed", nb);
    free(btri);
    pw_tet_dihedral_range(t, lo, hi);
    CHECKF(*lo >= MIN_DIHEDRAL && *hi <= MAX_DIHEDRAL, "dihedral angles %.3f..%.3f outside %.1f..%.1f", *lo, *hi,
           MIN_DIHEDRAL, MAX_DIHEDRAL);
    return vol;
}

static double surf_volume(const surf *s)
{
    double v = 0.0;
    int f;
    for (f = 0; f < s->m.nf; f++) {
        const float *a = s->m.pos + 3 * s->m.fv[3 * f], *b = s->m.pos + 3 * s->m.fv[3 * f + 1];
        const float *c = s->m.pos + 3 * s->m.fv[3 * f + 2];
        v += (double)a[0] * ((double)b[1] * c[2] - (double)b[2] * c[1]) -
             (double)a[1] * ((double)b[0] * c[2] - (double)b[2] * c[0]) +
             (double)a[2] * ((double)b[0] * c[1] - (double)b[1] * c[0]);
    }
    return v / 6.0;
}

static void t_sphere(void)
{
    surf s;
    pw_tetmesh t;
    pw_err e;
    pw_stuff_fit fit;
    double lo, hi, vol, ref;
    REQUIRE(sphere(8, &s));
    REQUIRE(stuff(&s, 20000, &t, &e) == PW_OK);
    vol = check_mesh(&t, &lo, &hi);
    ref = surf_volume(&s);
    CHECKF(fabs(vol - ref) < 0.02 * ref, "volume %g, surface encloses %g", vol, ref);
    CHECKF(t.nt > 15000 && t.nt < 25000, "%d tetrahedra for a target of 20000", t.nt);
    REQUIRE(pw_stuff_fit_measure(NULL, s.m.pos, s.m.nv, s.m.fv, s.m.nf, &t, &fit, &e) == PW_OK);
    CHECKF(fit.to_surface_max < 1e-6 * fit.diag, "boundary vertex %g off the surface", fit.to_surface_max);
    CHECKF(fit.from_surface_max < 0.01 * fit.diag, "surface vertex %g from the boundary", fit.from_surface_max);
    pwt_info("sphere: %d tets, %d vertices, dihedral %.2f..%.2f, volume %.4f of %.4f, fit %.2g / %.2g of the diagonal",
             t.nt, t.nv, lo, hi, vol, ref, fit.to_surface_max / fit.diag, fit.from_surface_max / fit.diag);
    pw_tetmesh_free(NULL, &t);
    pw_mesh_free(NULL, &s.m);
}

/* The same input twice gives the same bytes. */
static void t_deterministic(void)
{
    surf s;
    pw_tetmesh a, b;
    pw_err e;
    REQUIRE(sphere(5, &s));
    REQUIRE(stuff(&s, 5000, &a, &e) == PW_OK);
    REQUIRE(stuff(&s, 5000, &b, &e) == PW_OK);
    CHECK(a.nv == b.nv && a.nt == b.nt);
    CHECK(a.nv == b.nv && !memcmp(a.pos, b.pos, sizeof(float) * 3 * (size_t)a.nv));
    CHECK(a.nt == b.nt && !memcmp(a.tet, b.tet, sizeof(int) * 4 * (size_t)a.nt));
    pw_tetmesh_free(NULL, &a);
    pw_tetmesh_free(NULL, &b);
    pw_mesh_free(NULL, &s.m);
}

/* Surface a, followed by surface b moved by (dx, 0, 0) and scaled by
 * scale (negative: reversed orientation). */
static int join(const surf *a, const surf *b, float dx, float scale, surf *out)
{
    pw_err e;
    int v, k;
    pw_err_clear(&e);
    if (pw_mesh_alloc(NULL, &out->m, a->m.nv + b->m.nv, a->m.nf + b->m.nf, 3 * (a->m.nf + b->m.nf), 0, &e)) return 0;
    memcpy(out->m.pos, a->m.pos, sizeof(float) * 3 * (size_t)a->m.nv);
    for (v = 0; v < b->m.nv; v++)
        for (k = 0; k < 3; k++)
            out->m.pos[3 * (a->m.nv + v) + k] = b->m.pos[3 * v + k] * (scale < 0 ? -scale : scale) + (k == 0 ? dx : 0.0f);
    memcpy(out->m.fv, a->m.fv, sizeof(int) * 3 * (size_t)a->m.nf);
    for (v = 0; v < 3 * b->m.nf; v++)
        out->m.fv[3 * a->m.nf + v] = a->m.nv + b->m.fv[scale < 0 ? v - v % 3 + (3 - v % 3) % 3 : v];
    for (v = 0; v <= out->m.nf; v++) out->m.fstart[v] = 3 * v;
    return 1;
}

/* Refusals, each naming the problem: open, flipped triangle, non-finite
 * coordinate, index out of range, repeated corner, zero area,
 * self-intersection. */
static void t_refusals(void)
{
    surf s, two;
    pw_tetmesh t;
    pw_err e;
    int k;
    float keep[3];
    REQUIRE(sphere(3, &s));
    s.m.nf--; /* a hole */
    CHECKF(stuff(&s, 1000, &t, &e) == PW_ERR_TOPOLOGY && strstr(e.msg, "not closed"), "open: %s", e.msg);
    CHECK(t.nt == 0 && t.tet == NULL && t.pos == NULL);
    s.m.nf++;
    k = s.m.fv[0], s.m.fv[0] = s.m.fv[1], s.m.fv[1] = k; /* one triangle flipped */
    CHECKF(stuff(&s, 1000, &t, &e) == PW_ERR_TOPOLOGY && strstr(e.msg, "orientation"), "flipped: %s", e.msg);
    k = s.m.fv[0], s.m.fv[0] = s.m.fv[1], s.m.fv[1] = k;
    keep[0] = s.m.pos[4], s.m.pos[4] = (float)NAN;
    CHECKF(stuff(&s, 1000, &t, &e) == PW_ERR_INVALID && strstr(e.msg, "vertex 1"), "NaN: %s", e.msg);
    s.m.pos[4] = keep[0];
    k = s.m.fv[5], s.m.fv[5] = 100000;
    CHECKF(stuff(&s, 1000, &t, &e) == PW_ERR_INVALID && strstr(e.msg, "triangle 1"), "range: %s", e.msg);
    s.m.fv[5] = s.m.fv[4];
    CHECKF(stuff(&s, 1000, &t, &e) == PW_ERR_DEGENERATE, "repeated corner: %s", e.msg);
    s.m.fv[5] = k;
    /* corner 0 of triangle 0 onto corner 1: zero area (a float midpoint would not be exactly collinear) */
    for (k = 0; k < 3; k++) {
        keep[k] = s.m.pos[3 * s.m.fv[0] + k];
        s.m.pos[3 * s.m.fv[0] + k] = s.m.pos[3 * s.m.fv[1] + k];
    }
    CHECKF(stuff(&s, 1000, &t, &e) != PW_OK && strstr(e.msg, "zero area"), "zero area: %s", e.msg);
    for (k = 0; k < 3; k++) s.m.pos[3 * s.m.fv[0] + k] = keep[k];
    REQUIRE(join(&s, &s, 0.5f, 1.0f, &two));
    CHECKF(stuff(&two, 1000, &t, &e) == PW_ERR_TOPOLOGY && strstr(e.msg, "intersects itself"), "overlap: %s", e.msg);
    pw_mesh_free(NULL, &two.m);
    pw_mesh_free(NULL, &s.m);
}

/* Real closed CGAL meshes at 5K and 100K tetrahedra. */
static void t_cgal(void)
{
    static const char *names[] = {"elephant", "knot", "eight", "bunny00", "femur", "cactus", "dino"};
    static const int sizes[] = {5000, 100000};
    int i, j, done = 0;
    for (i = 0; i < (int)(sizeof names / sizeof names[0]); i++) {
        char rel[64];
        const char *path;
        surf s;
        snprintf(rel, sizeof rel, "meshes/%s.off", names[i]);
        if (!(path = pwt_data_opt(rel))) continue;
        REQUIRE(load(path, &s));
        for (j = 0; j < 2; j++) {
            pw_tetmesh t;
            pw_err e;
            pw_stuff_fit fit;
            double lo, hi, vol, ref = surf_volume(&s);
            CHECKF(stuff(&s, sizes[j], &t, &e) == PW_OK, "%s: %s", names[i], e.msg);
            vol = check_mesh(&t, &lo, &hi);
            CHECKF(pw_stuff_fit_measure(NULL, s.m.pos, s.m.nv, s.m.fv, s.m.nf, &t, &fit, &e) == PW_OK, "%s", e.msg);
            CHECKF(fit.to_surface_max < 1e-6 * fit.diag, "%s: boundary vertex %g off the surface", names[i],
                   fit.to_surface_max);
            pwt_info("%s: %d tets, dihedral %.2f..%.2f, volume %.4g of %.4g, fit %.2g / %.2g of the diagonal", names[i],
                     t.nt, lo, hi, vol, ref, fit.to_surface_max / fit.diag, fit.from_surface_max / fit.diag);
            pw_tetmesh_free(NULL, &t);
        }
        pw_mesh_free(NULL, &s.m);
        done++;
    }
    if (!done) pwt_skip("no CGAL meshes in %s/meshes (run `make data`)", pwt_data_dir());
}

static const pwt_case cases[] = {
    {"stuffing/cgal", t_cgal},
    {"stuffing/sphere", t_sphere},
    {"stuffing/deterministic", t_deterministic},
    {"stuffing/refusals", t_refusals},
};
PWT_MAIN(cases)
