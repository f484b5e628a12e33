/* Tests of src/common/stuffing.h, the built-in tetrahedralizer: validity
 * (positive volumes, conformity, closed boundary), the dihedral-angle
 * bounds, the fit of the boundary to the input surface, the refusals of
 * bad surfaces, determinism, cancellation, allocation failures, and real
 * CGAL meshes (skipped when `make data` has not run). */
#include "../src/common/stuffing.h"
#include "../src/common/shapes.h"
#include "../src/common/rng.h"
#include "pwtest.h"

/* The bounds of stuffing.h (see the top of that file). Uniform lattice:
 * the worst case of its stencils over all configurations, which
 * t_adversary searches. Graded lattice (the default): the bounds that
 * t_graded_random holds the stencils, warping and smoothing to. */
#define MIN_DIHEDRAL 10.2
#define MAX_DIHEDRAL 161.7
#define GRADED_MIN 8.0
#define GRADED_MAX 168.0

typedef struct surf {
    pw_mesh m; /* triangles only */
} surf;

static int surf_from_mesh(pw_mesh *in, surf *s)
{
    pw_err e;
    int ok;
    pw_err_clear(&e);
    ok = pw_mesh_triangulate(NULL, in, &s->m, NULL, &e) == PW_OK;
    pw_mesh_free(NULL, in);
    return ok;
}

/* pw_stuff_tetrahedralize and pw_stuff_fit_measure on the triangles of s. */
static int fill(const pw_alloc *a, const surf *s, const pw_stuff_options *o, const pw_progress *p, pw_tetmesh *out,
                pw_err *e)
{
    pw_stuff_tris in = pw_stuff_tris_of(s->m.pos, s->m.nv, s->m.fv, s->m.nf);
    return pw_stuff_tetrahedralize(a, &in, o, p, out, e);
}

static int fit_of(const surf *s, const pw_tetmesh *t, int samples, pw_stuff_fit *fit, pw_err *e)
{
    pw_stuff_tris in = pw_stuff_tris_of(s->m.pos, s->m.nv, s->m.fv, s->m.nf);
    return pw_stuff_fit_measure(NULL, &in, t, samples, fit, e);
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
    pw_mesh m;
    pw_err e;
    pw_err_clear(&e);
    return pw_mesh_load(NULL, path, &m, &e) == PW_OK && surf_from_mesh(&m, s);
}

static int stuff_with(const surf *s, const pw_stuff_options *o, pw_tetmesh *out, pw_err *e)
{
    pw_err_clear(e);
    return fill(NULL, s, o, NULL, out, e);
}

static int stuff(const surf *s, int target, pw_tetmesh *out, pw_err *e)
{
    pw_stuff_options o = pw_stuff_default_options();
    o.target_tets = target;
    return stuff_with(s, &o, out, e);
}

static int stuff_uniform(const surf *s, int target, pw_tetmesh *out, pw_err *e)
{
    pw_stuff_options o = pw_stuff_default_options();
    o.target_tets = target, o.uniform = 1;
    return stuff_with(s, &o, out, e);
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
 * the angles within [minb, maxb]; returns the enclosed volume. */
static double check_within(const pw_tetmesh *t, double *lo, double *hi, double minb, double maxb)
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
    CHECKF(*lo >= minb && *hi <= maxb, "dihedral angles %.3f..%.3f outside %.1f..%.1f", *lo, *hi, minb, maxb);
    return vol;
}

/* The same within the uniform lattice's proven bounds. */
static double check_mesh(const pw_tetmesh *t, double *lo, double *hi)
{
    return check_within(t, lo, hi, MIN_DIHEDRAL, MAX_DIHEDRAL);
}

/* The same within the graded lattice's bounds (the default fill). */
static double check_graded(const pw_tetmesh *t, double *lo, double *hi)
{
    return check_within(t, lo, hi, GRADED_MIN, GRADED_MAX);
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

/* The unit geosphere both ways: uniform (count near the target, proven
 * bounds) and graded (within its bounds and 0.5% of the diagonal). */
static void t_sphere(void)
{
    surf s;
    int uniform;
    REQUIRE(sphere(8, &s));
    for (uniform = 1; uniform >= 0; uniform--) {
        pw_tetmesh t;
        pw_err e;
        pw_stuff_fit fit;
        double lo, hi, vol, ref = surf_volume(&s);
        REQUIRE((uniform ? stuff_uniform : stuff)(&s, 20000, &t, &e) == PW_OK);
        vol = uniform ? check_mesh(&t, &lo, &hi) : check_graded(&t, &lo, &hi);
        CHECKF(fabs(vol - ref) < 0.02 * ref, "volume %g, surface encloses %g", vol, ref);
        CHECKF(!uniform || (t.nt > 15000 && t.nt < 25000), "%d tetrahedra for a target of 20000", t.nt);
        REQUIRE(fit_of(&s, &t, 20000, &fit, &e) == PW_OK);
        CHECKF(fit.to_surface_max < 1e-6 * fit.diag, "boundary vertex %g off the surface", fit.to_surface_max);
        CHECKF(fit.from_surface_max < 0.01 * fit.diag, "surface vertex %g from the boundary", fit.from_surface_max);
        CHECKF(uniform || (fit.to_max < 0.005 * fit.diag && fit.from_max < 0.005 * fit.diag), "graded fit %g / %g",
               fit.to_max / fit.diag, fit.from_max / fit.diag);
        pwt_info("sphere, %s: %d tets, %d vertices, dihedral %.2f..%.2f, volume %.4f of %.4f, fit %.3f%% / %.3f%% of "
                 "the diagonal", uniform ? "uniform" : "graded", t.nt, t.nv, lo, hi, vol, ref,
                 100.0 * fit.to_max / fit.diag, 100.0 * fit.from_max / fit.diag);
        pw_tetmesh_free(NULL, &t);
    }
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

/* Refusals, each naming the problem: open (with the hole count and
 * place), flipped triangle, non-finite coordinate, index out of range, a
 * repeated corner that opens the surface, self-intersection when strict;
 * and what is no longer refused: a zero-area triangle (skipped, the same
 * solid) and crossing triangles (filled, counted). */
static void t_refusals(void)
{
    surf s, two;
    pw_tetmesh t;
    pw_err e;
    pw_stuff_options o = pw_stuff_default_options();
    pw_stuff_info info;
    double lo, hi;
    int k;
    float keep[3];
    o.target_tets = 1000;
    REQUIRE(sphere(3, &s));
    s.m.nf--; /* a hole */
    CHECKF(stuff(&s, 1000, &t, &e) == PW_ERR_TOPOLOGY && strstr(e.msg, "not closed") && strstr(e.msg, "in 1 hole (") &&
               strstr(e.msg, "3 edges, perimeter"),
           "open: %s", e.msg);
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
    CHECKF(stuff(&s, 1000, &t, &e) == PW_ERR_TOPOLOGY && strstr(e.msg, "not closed"), "repeated corner: %s", e.msg);
    s.m.fv[5] = k;
    /* corner 0 of triangle 0 onto corner 1: zero area (a float midpoint would not be exactly collinear) */
    for (k = 0; k < 3; k++) {
        keep[k] = s.m.pos[3 * s.m.fv[0] + k];
        s.m.pos[3 * s.m.fv[0] + k] = s.m.pos[3 * s.m.fv[1] + k];
    }
    o.info = &info;
    /* both triangles on the collapsed edge have zero area */
    CHECKF(stuff_with(&s, &o, &t, &e) == PW_OK && info.skipped_triangles == 2, "zero area: %d skipped, %s",
           info.skipped_triangles, e.msg);
    check_graded(&t, &lo, &hi);
    pw_tetmesh_free(NULL, &t);
    for (k = 0; k < 3; k++) s.m.pos[3 * s.m.fv[0] + k] = keep[k];
    REQUIRE(join(&s, &s, 0.5f, 1.0f, &two));
    CHECKF(stuff_with(&two, &o, &t, &e) == PW_OK && info.crossing_pairs > 0 && info.first_pair[0] >= 0, "overlap: %s",
           e.msg);
    pw_tetmesh_free(NULL, &t);
    o.strict = 1;
    CHECKF(stuff_with(&two, &o, &t, &e) == PW_ERR_TOPOLOGY && strstr(e.msg, "intersects itself"), "overlap: %s", e.msg);
    pw_mesh_free(NULL, &two.m);
    pw_mesh_free(NULL, &s.m);
}

/* ---- stencil-level tests on a bare lattice (no surface) ---- */

static pw_rng rng;

/* A lattice of n^3 unit cubes, every vertex outside. */
static void lattice(pw__st *st, int n, pw_err *e)
{
    int v;
    memset(st, 0, sizeof *st);
    pw_err_clear(e);
    st->e = e;
    st->n[0] = st->n[1] = st->n[2] = n;
    st->h = 1.0;
    st->nb = (n + 1) * (n + 1) * (n + 1);
    st->nlv = st->nb + n * n * n;
    st->side = (signed char *)malloc((size_t)st->nlv);
    st->warp = (int *)malloc(sizeof(int) * (size_t)st->nlv);
    st->id = (int *)malloc(sizeof(int) * (size_t)st->nlv);
    for (v = 0; v < st->nlv; v++) st->side[v] = -1, st->warp[v] = st->id[v] = -1;
}

static void add_cut(pw__st *st, int in, int out, double t)
{
    pw__stcut *c;
    pw_grow(NULL, (void **)&st->cut, &st->capcut, st->ncut + 1, sizeof *st->cut, "cuts", st->e);
    c = st->cut + st->ncut++;
    c->in = in, c->out = out, c->id = -1, c->t = t;
}

/* A fraction in [lo, hi], often at an end (where the worst cases are). */
static double extreme(double lo, double hi)
{
    uint32_t k = pw_rng_below(&rng, 4);
    return k == 0 ? lo : k == 1 ? hi : lo + (hi - lo) * pw_rng_double(&rng);
}

static double alpha_of(const int *A, const int *B)
{
    return pw__st_long_axis(A, B) >= 0 ? PW__ST_ALPHA_LONG : PW__ST_ALPHA_SHORT;
}

/* Dihedral range of the tetrahedra st emitted from index t0 on. */
static void range_from(const pw__st *st, size_t t0, double *lo, double *hi)
{
    pw_tetmesh m;
    m.nv = (int)st->nopos, m.pos = st->opos, m.nt = (int)(st->notet - t0), m.tet = st->otet + 4 * t0;
    pw_tet_dihedral_range(&m, lo, hi);
}

/* Random inside/outside patterns with cut points anywhere (near the alpha
 * thresholds and the edge ends half the time) through the real warping and
 * stencils: no chained warps, a valid conforming mesh, angles in bounds. */
static void t_random_fields(void)
{
    int it, v, k, chains = 0;
    double worst = 180.0, worst_hi = 0.0;
    rng = pw_rng_seed(11, 1);
    for (it = 0; it < 300; it++) {
        pw__st st;
        pw_err e;
        pw_tetmesh m;
        double lo, hi;
        int U[3], V[3];
        lattice(&st, 5, &e);
        for (v = 0; v < st.nlv; v++) {
            pw__st_coord(&st, v, U);
            if (U[0] > 1 && U[1] > 1 && U[2] > 1 && U[0] < 9 && U[1] < 9 && U[2] < 9 &&
                pw_rng_below(&rng, 100) < (uint32_t)(25 + it % 50))
                st.side[v] = 1;
        }
        for (v = 0; v < st.nlv; v++) {
            if (st.side[v] < 0) continue;
            pw__st_coord(&st, v, U);
            for (k = 0; k < 14; k++) {
                int w, i;
                for (i = 0; i < 3; i++) V[i] = U[i] + pw__st_nb[k][i];
                w = pw__st_index(&st, V);
                if (w >= 0 && st.side[w] < 0) {
                    double a = alpha_of(U, V), t = extreme(0.0, 1.0);
                    uint32_t c = pw_rng_below(&rng, 3);
                    add_cut(&st, v, w, c == 0 ? t : c == 1 ? a * (1.0 + (t - 0.5) * 1e-6) : 1.0 - a * (1.0 + (t - 0.5) * 1e-6));
                }
            }
        }
        REQUIRE(pw__st_warp(&st) == PW_OK);
        for (v = 0; v < st.nlv; v++)
            if (st.warp[v] >= 0) {
                const pw__stcut *c = st.cut + st.warp[v];
                chains += st.warp[c->in == v ? c->out : c->in] >= 0;
            }
        REQUIRE(pw__st_stencils(&st) == PW_OK);
        m.nv = (int)st.nopos, m.pos = st.opos, m.nt = (int)st.notet, m.tet = st.otet;
        if (m.nt) check_mesh(&m, &lo, &hi);
        if (m.nt && lo < worst) worst = lo;
        if (m.nt && hi > worst_hi) worst_hi = hi;
        pw__st_free(&st);
    }
    CHECKF(chains == 0, "%d vertices moved towards a vertex that moved too", chains);
    pwt_info("300 random sign fields: dihedral angles %.3f..%.3f", worst, worst_hi);
}

/* The worst case of the stencils, as in the paper's computer-assisted
 * proof: one lattice tetrahedron, any corner signs; each corner either in
 * place or moved along any of its 14 lattice edges by up to alpha of that
 * edge (towards a vertex of the other sign, which stays in place, one cut
 * point per edge); cut points between unmoved corners of opposite signs
 * anywhere from alpha to 1 - alpha. */
static void add_tagged_cut(pw__st *st, int in, int out, double t, int tag)
{
    add_cut(st, in, out, t);
    st->cut[st->ncut - 1].id = tag;
}

static int adversary_config(pw__st *st, const int *g, int L[4][3])
{
    int k, i, j, sg[4], mv[4], np = 0;
    for (k = 0; k < 4; k++) sg[k] = pw_rng_below(&rng, 2) ? 1 : -1, np += sg[k] > 0, mv[k] = -1;
    if (!np) return 0;
    for (k = 0; k < 4; k++) st->side[g[k]] = (signed char)sg[k];
    for (k = 0; k < 4; k++) {
        int d = (int)pw_rng_below(&rng, 14), W[3], w, c;
        double a, f;
        if (pw_rng_below(&rng, 2)) continue;
        for (i = 0; i < 3; i++) W[i] = L[k][i] + pw__st_nb[d][i];
        w = pw__st_index(st, W);
        for (c = 0; c < 4 && g[c] != w; c++) continue;
        if (c < 4 && (sg[c] == sg[k] || mv[c] >= 0)) continue; /* the far end has the other sign, stays */
        if (c == 4) st->side[w] = (signed char)-sg[k];
        a = alpha_of(L[k], W);
        f = extreme(a * 1e-3, a * (1.0 - 1e-9));
        mv[k] = w;
        if (sg[k] > 0) add_tagged_cut(st, g[k], w, f, -2 - k);
        else add_tagged_cut(st, w, g[k], 1.0 - f, -2 - k);
    }
    for (k = 0; k < 4; k++)
        for (j = 0; j < 4; j++)
            if (mv[k] == g[j] && mv[j] >= 0) return 0; /* moved towards a corner that moved */
    for (i = 0; i < 4; i++)
        for (j = 0; j < 4; j++)
            if (sg[i] > 0 && sg[j] < 0 && mv[i] < 0 && mv[j] < 0) {
                double a = alpha_of(L[i], L[j]);
                add_tagged_cut(st, g[i], g[j], extreme(a, 1.0 - a), -1);
            }
    return 1;
}

static int cmp_cut(const void *x, const void *y)
{
    const pw__stcut *a = (const pw__stcut *)x, *b = (const pw__stcut *)y;
    if (a->in != b->in) return a->in < b->in ? -1 : 1;
    return (a->out > b->out) - (a->out < b->out);
}

/* Searches the configurations; the search must find the known tight case
 * (a +-00 tetrahedron at 10.205 degrees), or it proves nothing. */
static void t_adversary(void)
{
    static const int base[4][3] = {{5, 5, 5}, {5, 7, 5}, {4, 6, 6}, {6, 6, 6}}; /* long edges along y and x */
    int L[4][3], g[4], k, it;
    double worst = 180.0, worst_hi = 0.0, lo, hi;
    pw__st st;
    pw_err e;
    lattice(&st, 6, &e);
    for (k = 0; k < 4; k++) memcpy(L[k], base[k], sizeof L[k]), g[k] = pw__st_index(&st, L[k]);
    rng = pw_rng_seed(5, 2);
    for (it = 0; it < 1500000; it++) {
        size_t c;
        st.ncut = st.nopos = st.notet = 0;
        for (k = 0; k < st.nlv; k++) st.warp[k] = st.id[k] = -1, st.side[k] = -1;
        if (!adversary_config(&st, g, L)) continue;
        qsort(st.cut, st.ncut, sizeof *st.cut, cmp_cut);
        for (c = 0; c < st.ncut; c++) {
            if (st.cut[c].id <= -2) st.warp[g[-2 - st.cut[c].id]] = (int)c;
            st.cut[c].id = -1;
        }
        REQUIRE(pw__st_tet(&st, g) == PW_OK);
        if (!st.notet) continue;
        range_from(&st, 0, &lo, &hi);
        for (k = 0; k < (int)st.notet; k++) {
            pw_tetmesh m;
            m.nv = (int)st.nopos, m.pos = st.opos, m.nt = 1, m.tet = st.otet + 4 * k;
            if (!(pw_tet_volume6(&m, 0) > 0.0)) break;
        }
        CHECKF(k == (int)st.notet, "configuration %d: a tetrahedron is not positive", it);
        if (lo < worst) worst = lo;
        if (hi > worst_hi) worst_hi = hi;
    }
    CHECKF(worst >= MIN_DIHEDRAL && worst_hi <= MAX_DIHEDRAL, "stencils reach %.4f..%.4f", worst, worst_hi);
    CHECKF(worst < 10.3, "the search missed the tight case (worst found %.4f)", worst);
    pwt_info("1.5M stencil configurations: dihedral angles %.4f..%.4f", worst, worst_hi);
    pw__st_free(&st);
}

/* ---- bisect.h: the graded lattice ---- */

static int random_need(void *user, const pw_bisect *b, pw_bstet *t)
{
    (void)user, (void)b;
    return pw_rng_below(&rng, 100) < (uint32_t)(t->depth < 3 ? 60 : 25);
}

static int cmp_int(const void *x, const void *y)
{
    int a = *(const int *)x, b = *(const int *)y;
    return (a > b) - (a < b);
}

static int cmp_face(const void *x, const void *y)
{
    const int *a = (const int *)x, *b = (const int *)y;
    int k;
    for (k = 0; k < 3; k++)
        if (a[k] != b[k]) return a[k] < b[k] ? -1 : 1;
    return 0;
}

/* Random bisection of a 2 x 2 x 2 block of Kuhn cubes, then the closure:
 * the tetrahedra tile the box (volumes add up exactly), every face inside
 * the box is shared by exactly two, none has a vertex inside an edge, and
 * every one is one of the three shapes (dihedral angles within 45..120). */
static void t_bisect(void)
{
    int it;
    rng = pw_rng_seed(31, 9);
    for (it = 0; it < 20; it++) {
        static const int n[3] = {2, 2, 2};
        pw_bisect b;
        pw_err e;
        size_t i, nf = 0, j;
        long long vol = 0;
        int *faces, k, bad = 0, hanging = 0, outside = 0;
        double lo = 180.0, hi = 0.0;
        memset(&b, 0, sizeof b);
        pw_err_clear(&e);
        b.e = &e;
        REQUIRE(pw_bisect_kuhn(&b, n, 64) == PW_OK);
        REQUIRE(pw_bisect_refine(&b, random_need, NULL, 12) == PW_OK);
        REQUIRE(pw_bisect_conform(&b) == PW_OK);
        faces = (int *)malloc(sizeof(int) * 12 * b.nt);
        for (i = 0; i < b.nt; i++) {
            const int *v = b.t[i].v;
            long long d[3][3], det;
            double p[4][3], a, c;
            for (k = 0; k < 3; k++) {
                int m;
                for (m = 0; m < 3; m++) d[k][m] = b.vc[3 * v[k + 1] + m] - b.vc[3 * v[0] + m];
            }
            det = d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1]) - d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0]) +
                  d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0]);
            vol += det < 0 ? -det : det;
            bad += det == 0;
            hanging += pw__bs_hanging(&b, &b.t[i]);
            for (k = 0; k < 4; k++) {
                int m, f[3], x = 0;
                for (m = 0; m < 3; m++) p[k][m] = b.vc[3 * v[k] + m];
                for (m = 0; m < 4; m++)
                    if (m != k) f[x++] = v[m];
                qsort(f, 3, sizeof(int), cmp_int);
                memcpy(faces + 3 * nf++, f, sizeof f);
            }
            pw_tet_angles((const double(*)[3])p, &a, &c);
            lo = a < lo ? a : lo, hi = c > hi ? c : hi;
        }
        qsort(faces, nf, 3 * sizeof(int), cmp_face);
        for (i = 0; i < nf; i = j) { /* a face alone must lie on the box */
            for (j = i + 1; j < nf && !cmp_face(faces + 3 * i, faces + 3 * j); j++) continue;
            if (j - i > 2) bad++;
            if (j - i == 1) {
                int ax, on = 0;
                for (ax = 0; ax < 3; ax++) {
                    int c0 = b.vc[3 * faces[3 * i] + ax], c1 = b.vc[3 * faces[3 * i + 1] + ax];
                    int c2 = b.vc[3 * faces[3 * i + 2] + ax];
                    on |= c0 == c1 && c1 == c2 && (c0 == 0 || c0 == 128);
                }
                outside += !on;
            }
        }
        CHECKF(vol == 6LL * 128 * 128 * 128 && bad == 0 && hanging == 0 && outside == 0,
               "run %d: volume %lld of %lld, %d bad, %d hanging, %d faces alone inside the box", it, vol,
               6LL * 128 * 128 * 128, bad, hanging, outside);
        CHECKF(lo > 45.0 - 1e-9 && hi < 120.0 + 1e-9, "run %d: dihedral angles %.3f..%.3f", it, lo, hi);
        free(faces);
        pw_bisect_free(&b);
    }
}

/* The graded fill over random shapes (bumpy spheres, thin tori, stars,
 * an L of cubes with sharp edges), each squashed, turned and moved at
 * random, filled at a random count and fit: every mesh positive,
 * conforming, closed, within the graded bounds. The search over lattice
 * placements and transitions that GRADED_MIN and GRADED_MAX rest on. */
static void t_graded_random(void)
{
    static const unsigned char ell[8] = {1, 1, 1, 0, 1, 0, 0, 0}; /* 2 x 2 x 2 voxels, four solid */
    double worst = 180.0, worst_hi = 0.0;
    int it, runs = 0;
    rng = pw_rng_seed(23, 4);
    for (it = 0; it < 48; it++) {
        pw_mesh m;
        pw_err e;
        surf s;
        pw_tetmesh t;
        pw_stuff_options o = pw_stuff_default_options();
        double q[4], l = 0.0, R[3][3], sc[3], off[3], lo, hi;
        int k, v, r;
        pw_err_clear(&e);
        switch (it % 4) {
        case 0: r = pw_shape_bumpy(NULL, 5, &m, &e); break;
        case 1: r = pw_shape_thin_torus(NULL, 96, 12, 0.02 + 0.1 * pw_rng_double(&rng), &m, &e); break;
        case 2: r = pw_shape_star(NULL, 8, 1.5 + 2.0 * pw_rng_double(&rng), &m, &e); break;
        default: r = pw_shape_polycube(NULL, 2, 2, 2, ell, &m, &e); break;
        }
        REQUIRE(r == PW_OK && surf_from_mesh(&m, &s));
        for (k = 0; k < 4; k++) q[k] = 2.0 * pw_rng_double(&rng) - 1.0, l += q[k] * q[k];
        for (k = 0; k < 4; k++) q[k] /= sqrt(l);
        R[0][0] = 1 - 2 * (q[2] * q[2] + q[3] * q[3]), R[0][1] = 2 * (q[1] * q[2] - q[0] * q[3]);
        R[0][2] = 2 * (q[1] * q[3] + q[0] * q[2]), R[1][0] = 2 * (q[1] * q[2] + q[0] * q[3]);
        R[1][1] = 1 - 2 * (q[1] * q[1] + q[3] * q[3]), R[1][2] = 2 * (q[2] * q[3] - q[0] * q[1]);
        R[2][0] = 2 * (q[1] * q[3] - q[0] * q[2]), R[2][1] = 2 * (q[2] * q[3] + q[0] * q[1]);
        R[2][2] = 1 - 2 * (q[1] * q[1] + q[2] * q[2]);
        for (k = 0; k < 3; k++) sc[k] = 0.5 + 1.5 * pw_rng_double(&rng), off[k] = 10.0 * pw_rng_double(&rng) - 5.0;
        for (v = 0; v < s.m.nv; v++) {
            float *p = s.m.pos + 3 * v;
            double x[3] = {p[0] * sc[0], p[1] * sc[1], p[2] * sc[2]};
            for (k = 0; k < 3; k++) p[k] = (float)(R[k][0] * x[0] + R[k][1] * x[1] + R[k][2] * x[2] + off[k]);
        }
        o.target_tets = 500 + (int)pw_rng_below(&rng, 4000);
        o.fit = 0.003 + 0.02 * pw_rng_double(&rng);
        CHECKF(stuff_with(&s, &o, &t, &e) == PW_OK, "shape %d: %s", it, e.msg);
        if (t.nt) {
            check_graded(&t, &lo, &hi);
            worst = lo < worst ? lo : worst;
            worst_hi = hi > worst_hi ? hi : worst_hi;
            runs++;
        }
        pw_tetmesh_free(NULL, &t);
        pw_mesh_free(NULL, &s.m);
    }
    pwt_info("%d random graded fills: dihedral angles %.2f..%.2f", runs, worst, worst_hi);
}

/* Several shells: disjoint spheres add up, an inward inner sphere is a
 * cavity, an outward inner sphere adds nothing (winding number 2 is still
 * inside), overlapping spheres unite when self-intersections are allowed. */
static void t_shells(void)
{
    surf a, b, two;
    pw_tetmesh t;
    pw_err e;
    pw_stuff_options o = pw_stuff_default_options();
    double lo, hi, vol, va, vb;
    REQUIRE(sphere(6, &a) && sphere(4, &b));
    va = surf_volume(&a), vb = surf_volume(&b) * 0.125; /* b is scaled by 0.5 below */
    o.target_tets = 20000;
    REQUIRE(join(&a, &b, 3.0f, 0.5f, &two));
    REQUIRE(stuff_with(&two, &o, &t, &e) == PW_OK);
    vol = check_graded(&t, &lo, &hi);
    CHECKF(fabs(vol - (va + vb)) < 0.03 * (va + vb), "disjoint: %g, expected %g", vol, va + vb);
    pw_tetmesh_free(NULL, &t), pw_mesh_free(NULL, &two.m);
    REQUIRE(join(&a, &b, 0.0f, -0.5f, &two));
    REQUIRE(stuff_with(&two, &o, &t, &e) == PW_OK);
    vol = check_graded(&t, &lo, &hi);
    CHECKF(fabs(vol - (va - vb)) < 0.03 * (va - vb), "cavity: %g, expected %g", vol, va - vb);
    pw_tetmesh_free(NULL, &t), pw_mesh_free(NULL, &two.m);
    REQUIRE(join(&a, &b, 0.0f, 0.5f, &two));
    REQUIRE(stuff_with(&two, &o, &t, &e) == PW_OK);
    vol = check_graded(&t, &lo, &hi);
    CHECKF(fabs(vol - va) < 0.03 * va, "nested: %g, expected %g", vol, va);
    pw_tetmesh_free(NULL, &t), pw_mesh_free(NULL, &two.m);
    REQUIRE(join(&a, &a, 0.5f, 1.0f, &two));
    o.strict = 1;
    CHECK(stuff_with(&two, &o, &t, &e) == PW_ERR_TOPOLOGY);
    o.strict = 0;
    REQUIRE(stuff_with(&two, &o, &t, &e) == PW_OK);
    vol = check_graded(&t, &lo, &hi);
    { /* union of two unit balls 0.5 apart: two balls minus the lens pi (4r + d)(2r - d)^2 / 12 */
        double ball = 4.0 / 3.0 * 3.14159265358979 * va / (4.0 / 3.0 * 3.14159265358979);
        double lens = 3.14159265358979 * 4.5 * 2.25 / 12.0 * (va / (4.0 / 3.0 * 3.14159265358979));
        CHECKF(fabs(vol - (2.0 * ball - lens)) < 0.03 * vol, "union: %g, expected %g", vol, 2.0 * ball - lens);
    }
    pwt_info("union of overlapping spheres: %d tets, volume %.4f, dihedral %.2f..%.2f", t.nt, vol, lo, hi);
    pw_tetmesh_free(NULL, &t), pw_mesh_free(NULL, &two.m);
    pw_mesh_free(NULL, &a.m), pw_mesh_free(NULL, &b.m);
}

/* Small holes are closed (fans from a vertex of each, the solid by winding
 * number): a finely split sphere missing one triangle (perimeter 3.9% of
 * the diagonal, under the default 5%) fills like the whole sphere; with
 * max_hole negative it is refused. */
static void t_small_hole(void)
{
    surf s;
    pw_tetmesh t;
    pw_err e;
    pw_stuff_options o = pw_stuff_default_options();
    pw_stuff_info info;
    double lo, hi, vol, ref;
    REQUIRE(sphere(24, &s));
    ref = surf_volume(&s);
    s.m.nf--;
    o.target_tets = 5000, o.info = &info;
    REQUIRE(stuff_with(&s, &o, &t, &e) == PW_OK);
    CHECK_EQ_INT(info.closed_holes, 1);
    vol = check_graded(&t, &lo, &hi);
    CHECKF(fabs(vol - ref) < 0.05 * ref, "volume %g, the closed sphere %g", vol, ref);
    pw_tetmesh_free(NULL, &t);
    o.max_hole = -1.0;
    CHECKF(stuff_with(&s, &o, &t, &e) == PW_ERR_TOPOLOGY && strstr(e.msg, "not closed"), "%s", e.msg);
    o.max_hole = NAN;
    CHECKF(stuff_with(&s, &o, &t, &e) == PW_ERR_INVALID && strstr(e.msg, "max_hole"), "%s", e.msg);
    pw_mesh_free(NULL, &s.m);
}

/* All triangles reversed: the same mesh (a documented repair). */
static void t_inward(void)
{
    surf s;
    pw_tetmesh a, b;
    pw_err e;
    int f, k;
    REQUIRE(sphere(5, &s));
    REQUIRE(stuff(&s, 3000, &a, &e) == PW_OK);
    for (f = 0; f < s.m.nf; f++) k = s.m.fv[3 * f], s.m.fv[3 * f] = s.m.fv[3 * f + 1], s.m.fv[3 * f + 1] = k;
    REQUIRE(stuff(&s, 3000, &b, &e) == PW_OK);
    CHECK(a.nv == b.nv && a.nt == b.nt && !memcmp(a.pos, b.pos, sizeof(float) * 3 * (size_t)a.nv) &&
          !memcmp(a.tet, b.tet, sizeof(int) * 4 * (size_t)a.nt));
    pw_tetmesh_free(NULL, &a), pw_tetmesh_free(NULL, &b);
    pw_mesh_free(NULL, &s.m);
}

/* The options: an explicit cell, the count following target_tets, bad
 * values, a lattice too large, a cell too coarse for the shape. */
static void t_options(void)
{
    surf s;
    pw_tetmesh t;
    pw_err e;
    pw_stuff_options o = pw_stuff_default_options();
    int small, big;
    REQUIRE(sphere(4, &s));
    o.cell = 0.1, o.uniform = 1;
    REQUIRE(stuff_with(&s, &o, &t, &e) == PW_OK);
    /* about 12 tetrahedra per cube: volume 4.1 / 0.001 * 12 = 50K */
    CHECKF(t.nt > 40000 && t.nt < 60000, "%d tetrahedra for cell 0.1", t.nt);
    pw_tetmesh_free(NULL, &t);
    CHECK(stuff_uniform(&s, 2000, &t, &e) == PW_OK);
    small = t.nt;
    pw_tetmesh_free(NULL, &t);
    CHECK(stuff_uniform(&s, 8000, &t, &e) == PW_OK);
    big = t.nt;
    pw_tetmesh_free(NULL, &t);
    CHECKF(small > 1500 && small < 2600 && big > 6500 && big < 9500, "targets 2000/8000 gave %d/%d", small, big);
    o.uniform = 0, o.cell = 0.0, o.fit = 0.01; /* graded: a looser fit, fewer tetrahedra */
    CHECK(stuff_with(&s, &o, &t, &e) == PW_OK);
    small = t.nt;
    pw_tetmesh_free(NULL, &t);
    o.fit = 0.0;
    CHECK(stuff_with(&s, &o, &t, &e) == PW_OK);
    big = t.nt;
    pw_tetmesh_free(NULL, &t);
    CHECKF(small < big, "fit 0.01 gave %d tetrahedra, the default fit %d", small, big);
    o.fit = -0.1;
    CHECKF(stuff_with(&s, &o, &t, &e) == PW_ERR_INVALID && strstr(e.msg, "fit"), "%s", e.msg);
    o.fit = (double)NAN;
    CHECKF(stuff_with(&s, &o, &t, &e) == PW_ERR_INVALID && strstr(e.msg, "fit"), "%s", e.msg);
    o.fit = 0.0, o.uniform = 1;
    o.cell = -1.0;
    CHECK(stuff_with(&s, &o, &t, &e) == PW_ERR_INVALID && strstr(e.msg, "cell"));
    o.cell = (double)NAN;
    CHECK(stuff_with(&s, &o, &t, &e) == PW_ERR_INVALID);
    o.cell = 1e-5;
    CHECKF(stuff_with(&s, &o, &t, &e) == PW_ERR_LIMIT && strstr(e.msg, "PW_MAX_STUFF_LATTICE"), "%s", e.msg);
    o.uniform = 0;
    CHECKF(stuff_with(&s, &o, &t, &e) == PW_ERR_LIMIT && strstr(e.msg, "PW_MAX_STUFF_LATTICE"), "graded: %s", e.msg);
    o.uniform = 1, o.cell = 10.0;
    CHECKF(stuff_with(&s, &o, &t, &e) == PW_ERR_DEGENERATE && strstr(e.msg, "smaller cell"), "%s", e.msg);
    o.cell = 0.0, o.target_tets = -5;
    CHECK(stuff_with(&s, &o, &t, &e) == PW_ERR_INVALID);
    CHECK(fill(NULL, &s, NULL, NULL, &t, &e) == PW_OK && t.nt > 15000);
    pw_tetmesh_free(NULL, &t);
    CHECK(fill(NULL, &s, NULL, NULL, NULL, &e) == PW_ERR_INVALID);
    pw_mesh_free(NULL, &s.m);
}

static int cancel_after(void *user, float done, const char *stage)
{
    (void)done, (void)stage;
    return --*(int *)user < 0;
}

/* The progress callback sees the stages in order and can stop each. */
static void t_cancel(void)
{
    surf s;
    pw_tetmesh t;
    pw_err e;
    pw_progress p;
    int n, calls = 0, total;
    REQUIRE(sphere(4, &s));
    p.fn = cancel_after, p.user = &calls;
    calls = 1 << 30;
    pw_err_clear(&e);
    REQUIRE(fill(NULL, &s, NULL, &p, &t, &e) == PW_OK);
    pw_tetmesh_free(NULL, &t);
    total = (1 << 30) - calls;
    CHECKF(total >= 4, "%d progress calls", total);
    for (n = 0; n < total; n++) {
        calls = n;
        pw_err_clear(&e);
        CHECKF(fill(NULL, &s, NULL, &p, &t, &e) == PW_ERR_CANCELLED &&
                   t.nt == 0 && t.tet == NULL && strstr(e.msg, "cancelled"),
               "call %d: %s", n, e.msg);
    }
    pw_mesh_free(NULL, &s.m);
}

/* Every allocation made to fail once: NOMEM, nothing leaked. */
static void t_alloc_failures(void)
{
    surf s;
    pw_tetmesh t;
    pw_err e;
    pwt_alloc_state st = {0, 0, -1};
    pw_alloc al;
    pw_stuff_options o = pw_stuff_default_options();
    long k, total, bad = 0, leaks = 0;
    REQUIRE(sphere(3, &s));
    al.malloc_fn = pwt_malloc, al.realloc_fn = pwt_realloc, al.free_fn = pwt_free, al.user = &st;
    o.target_tets = 400;
    pw_err_clear(&e);
    REQUIRE(fill(&al, &s, &o, NULL, &t, &e) == PW_OK);
    pw_tetmesh_free(&al, &t);
    total = st.calls;
    CHECK_EQ_INT(st.live, 0);
    for (k = 0; k < total; k++) {
        int r;
        st.calls = 0, st.live = 0, st.fail_after = k;
        pw_err_clear(&e);
        r = fill(&al, &s, &o, NULL, &t, &e);
        if (r == PW_OK) pw_tetmesh_free(&al, &t);
        else if (r != PW_ERR_NOMEM || t.tet || t.pos) bad++;
        if (st.live) leaks++;
    }
    pwt_info("%ld allocations per run, each made to fail once", total);
    CHECKF(bad == 0, "%ld failures reported as something else than NOMEM", bad);
    CHECKF(leaks == 0, "%ld failures leaked memory", leaks);
    pw_mesh_free(NULL, &s.m);
}

/* Corner k of the cube [c - h, c + h]^3 (bit 0: x, 1: y, 2: z). */
static void cube_corner(int k, double c, double h, float *out)
{
    int i;
    for (i = 0; i < 3; i++) out[i] = (float)(c + ((k >> i) & 1 ? h : -h));
}

/* The 12 outward triangles of a cube (corners as cube_corner) and its 6
 * Kuhn tetrahedra around the diagonal 0-7, oriented positively. */
static const int cube_tri[36] = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                                 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
static const int cube_kuhn[24] = {0, 1, 3, 7, 0, 3, 2, 7, 0, 2, 6, 7, 0, 6, 4, 7, 0, 4, 5, 7, 0, 5, 1, 7};

/* pw_stuff_fit_measure on a known answer: the boundary of the cube of
 * half-width 0.45 against the surface of the cube of half-width 0.5 is
 * 0.05 from it everywhere (its corners included), while the outer cube's
 * corners are 0.05 sqrt 3 from the inner one and its faces 0.05 but near their edges and corners; a
 * second, disjoint inner cube makes two pieces. */
static void t_fit_measure(void)
{
    float spos[24], tpos[48], spos2[48];
    int ttet[48], cube_tri2[72], i, k;
    pw_tetmesh t;
    pw_stuff_fit fit;
    pw_err e;
    pw_stuff_tris cube = pw_stuff_tris_of(spos, 8, cube_tri, 12), two = pw_stuff_tris_of(tpos, 16, cube_tri2, 24);
    pw_stuff_tris nested = pw_stuff_tris_of(spos2, 16, cube_tri2, 24);
    for (k = 0; k < 8; k++) cube_corner(k, 0.0, 0.5, spos + 3 * k), cube_corner(k, 0.0, 0.45, tpos + 3 * k);
    for (k = 0; k < 8; k++) cube_corner(k, 5.0, 0.45, tpos + 24 + 3 * k);
    for (i = 0; i < 48; i++) ttet[i] = cube_kuhn[i % 24] + (i >= 24 ? 8 : 0);
    for (i = 0; i < 72; i++) cube_tri2[i] = cube_tri[i % 36] + (i >= 36 ? 8 : 0);
    for (k = 0; k < 8; k++) cube_corner(k, 0.0, 0.5, spos2 + 3 * k), cube_corner(k, 0.0, 0.25, spos2 + 24 + 3 * k);
    t.nv = 8, t.nt = 6, t.pos = tpos, t.tet = ttet;
    for (i = 0; i < t.nt; i++) CHECKF(pw_tet_volume6(&t, i) > 0.0, "Kuhn tetrahedron %d not positive", i);
    pw_err_clear(&e);
    REQUIRE(pw_stuff_fit_measure(NULL, &cube, &t, 5000, &fit, &e) == PW_OK);
    CHECK_NEAR(fit.to_max, 0.05, 1e-6);
    CHECK_NEAR(fit.to_p99, 0.05, 1e-6);
    CHECK_NEAR(fit.from_max, 0.05 * sqrt(3.0), 1e-6);
    CHECKF(fit.from_p99 > 0.05 && fit.from_p99 < fit.from_max - 0.01, "from p99 %g", fit.from_p99);
    CHECK_EQ_INT(fit.pieces, 1);
    CHECK_EQ_INT(fit.surface_pieces, 1);
    CHECKF(fit.samples >= 5000, "%d samples", fit.samples);
    CHECK_NEAR(fit.diag, sqrt(3.0), 1e-6);
    t.nv = 16, t.nt = 12;
    REQUIRE(pw_stuff_fit_measure(NULL, &cube, &t, 5000, &fit, &e) == PW_OK);
    CHECK_EQ_INT(fit.pieces, 2);
    CHECKF(fit.to_max > 4.0, "the far cube at %g", fit.to_max);
    t.nv = 8, t.nt = 6;
    REQUIRE(pw_stuff_fit_measure(NULL, &two, &t, 1000, &fit, &e) == PW_OK);
    CHECK_EQ_INT(fit.surface_pieces, 2); /* two disjoint cubes enclose two pieces */
    for (i = 36; i < 72; i += 3) k = cube_tri2[i + 1], cube_tri2[i + 1] = cube_tri2[i + 2], cube_tri2[i + 2] = k;
    REQUIRE(pw_stuff_fit_measure(NULL, &nested, &t, 1000, &fit, &e) == PW_OK);
    CHECK_EQ_INT(fit.surface_pieces, 1); /* a cube with a cube-shaped cavity: one */
}

/* Fills shape m at the default settings; its fit and pieces to *fit. */
static int fill_and_fit(pw_mesh *m, const char *name, int uniform, pw_stuff_fit *fit)
{
    surf s;
    pw_tetmesh t;
    pw_err e;
    double lo, hi;
    int ok = surf_from_mesh(m, &s);
    CHECKF(ok, "%s: not triangulated", name);
    if (!ok) return 0;
    ok = (uniform ? stuff_uniform : stuff)(&s, 20000, &t, &e) == PW_OK;
    CHECKF(ok, "%s: %s", name, e.msg);
    if (ok) {
        if (uniform) check_mesh(&t, &lo, &hi);
        else check_graded(&t, &lo, &hi);
        ok = fit_of(&s, &t, 50000, fit, &e) == PW_OK;
        CHECKF(ok, "%s: %s", name, e.msg);
        CHECKF(!ok || fit->to_surface_max < 1e-6 * fit->diag, "%s: boundary vertex %g off the surface", name,
               fit->to_surface_max);
        pwt_info("%s: %d tets, %d piece(s), fit %.2f%% (99%%: %.2f%%) surface->tets, %.2f%% (%.2f%%) tets->surface, "
                 "dihedral %.1f..%.1f", name, t.nt, fit->pieces, 100.0 * fit->from_max / fit->diag,
                 100.0 * fit->from_p99 / fit->diag, 100.0 * fit->to_max / fit->diag, 100.0 * fit->to_p99 / fit->diag,
                 lo, hi);
        pw_tetmesh_free(NULL, &t);
    }
    pw_mesh_free(NULL, &s.m);
    return ok;
}

/* Thin synthetic shapes (issue 16): a torus whose tube radius is 1% of
 * the diagonal, a dumbbell whose neck is 1% of the diagonal thick, a star
 * of 12 long spikes. The graded fill keeps them: one piece, within 0.5% of
 * the diagonal both ways (99th percentile 0.2%), the star's spike tips
 * too (finer cells near a sharp tip: 0.30%, 0.65% without). The uniform
 * lattice at the same count loses the
 * dumbbell's neck, which the measure must see. */
static void thin_check(const char *name, const pw_stuff_fit *fit, double max)
{
    CHECKF(fit->pieces == 1 && fit->surface_pieces == 1, "%s: %d pieces of %d", name, fit->pieces, fit->surface_pieces);
    CHECKF(fit->from_max < max * fit->diag && fit->to_max < max * fit->diag, "%s: fit %g / %g", name,
           fit->from_max / fit->diag, fit->to_max / fit->diag);
    CHECKF(fit->from_p99 < 0.002 * fit->diag && fit->to_p99 < 0.002 * fit->diag, "%s: 99th percentile %g / %g", name,
           fit->from_p99 / fit->diag, fit->to_p99 / fit->diag);
}

static void t_thin_shapes(void)
{
    pw_mesh m;
    pw_err e;
    pw_stuff_fit fit;
    pw_err_clear(&e);
    REQUIRE(pw_shape_thin_torus(NULL, 192, 12, 0.0294, &m, &e) == PW_OK); /* diagonal 2.91: tube 1.0% of it */
    if (fill_and_fit(&m, "torus, tube radius 1% of the diagonal", 0, &fit)) thin_check("torus", &fit, 0.005);
    REQUIRE(pw_shape_dumbbell(NULL, 0.0332, 48, &m, &e) == PW_OK); /* diagonal 6.63: neck 0.066 thick, 1.0% */
    if (fill_and_fit(&m, "dumbbell, neck 1% of the diagonal", 0, &fit)) thin_check("dumbbell", &fit, 0.005);
    REQUIRE(pw_shape_star(NULL, 12, 3.0, &m, &e) == PW_OK);
    if (fill_and_fit(&m, "star of 12 spikes", 0, &fit)) thin_check("star", &fit, 0.005);
    REQUIRE(pw_shape_dumbbell(NULL, 0.0332, 48, &m, &e) == PW_OK);
    if (fill_and_fit(&m, "dumbbell, uniform lattice", 1, &fit))
        CHECKF(fit.pieces == 2 && fit.surface_pieces == 1 && fit.from_max > 0.1 * fit.diag,
               "uniform dumbbell: %d pieces of %d, fit %g: the neck kept?", fit.pieces, fit.surface_pieces,
               fit.from_max / fit.diag);
}

/* Real closed CGAL meshes at the default settings (issue 16): the graded
 * fill within its angle bounds, its boundary within 0.5% of the diagonal
 * of the surface both ways (99th percentile within 0.2%), the pieces the
 * surface encloses. */
static void t_cgal(void)
{
    static const char *names[] = {"elephant", "knot", "eight", "dino", "cactus", "fandisk", "bunny00", "femur"};
    int i, done = 0;
    for (i = 0; i < (int)(sizeof names / sizeof names[0]); i++) {
        char rel[64];
        const char *path;
        surf s;
        pw_tetmesh t;
        pw_err e;
        pw_stuff_fit fit;
        double lo, hi, vol, ref, worst, p99;
        snprintf(rel, sizeof rel, "meshes/%s.off", names[i]);
        if (!(path = pwt_data_opt(rel))) continue;
        REQUIRE(load(path, &s));
        ref = surf_volume(&s);
        CHECKF(stuff(&s, 20000, &t, &e) == PW_OK, "%s: %s", names[i], e.msg);
        vol = check_graded(&t, &lo, &hi);
        CHECKF(fit_of(&s, &t, 50000, &fit, &e) == PW_OK, "%s", e.msg);
        worst = (fit.to_max > fit.from_max ? fit.to_max : fit.from_max) / fit.diag;
        p99 = (fit.to_p99 > fit.from_p99 ? fit.to_p99 : fit.from_p99) / fit.diag;
        CHECKF(fit.to_surface_max < 1e-6 * fit.diag, "%s: boundary vertex %g off the surface", names[i],
               fit.to_surface_max);
        CHECKF(worst < 0.005 && p99 < 0.002, "%s: fit %.3f%% (99%%: %.3f%%)", names[i], 100.0 * worst, 100.0 * p99);
        CHECKF(fit.pieces == fit.surface_pieces, "%s: %d pieces, the surface encloses %d", names[i], fit.pieces,
               fit.surface_pieces);
        pwt_info("%s: %d tets, dihedral %.2f..%.2f, volume %.4g of %.4g, %d piece(s), two-sided fit %.3f%% (99%%: "
                 "%.3f%%) of the diagonal", names[i], t.nt, lo, hi, vol, ref, fit.pieces, 100.0 * worst, 100.0 * p99);
        pw_tetmesh_free(NULL, &t);
        pw_mesh_free(NULL, &s.m);
        done++;
    }
    if (!done) pwt_skip("no CGAL meshes in %s/meshes (run `make data`)", pwt_data_dir());
}

/* CGAL meshes that intersect themselves (confirmed with tetgen -d):
 * filled by default as a union (the crossing pairs counted), refused when
 * strict. */
static void t_cgal_union(void)
{
    static const char *names[] = {"cow", "bull", "camel"};
    int i, done = 0;
    for (i = 0; i < 3; i++) {
        char rel[64];
        const char *path;
        surf s;
        pw_tetmesh t;
        pw_err e;
        pw_stuff_fit fit;
        pw_stuff_options o = pw_stuff_default_options();
        pw_stuff_info info;
        double lo, hi;
        snprintf(rel, sizeof rel, "meshes/%s.off", names[i]);
        if (!(path = pwt_data_opt(rel))) continue;
        REQUIRE(load(path, &s));
        o.strict = 1;
        CHECKF(stuff_with(&s, &o, &t, &e) == PW_ERR_TOPOLOGY && strstr(e.msg, "intersects itself"), "%s: %s",
               names[i], e.msg);
        o.strict = 0, o.info = &info;
        CHECKF(stuff_with(&s, &o, &t, &e) == PW_OK && info.crossing_pairs > 0, "%s: %s", names[i], e.msg);
        check_graded(&t, &lo, &hi);
        CHECK(fit_of(&s, &t, 20000, &fit, &e) == PW_OK);
        CHECKF(fit.to_surface_max < 1e-6 * fit.diag, "%s: boundary vertex %g off the surface", names[i], fit.to_surface_max);
        pwt_info("%s (%ld crossing pairs, united): %d tets, dihedral %.2f..%.2f, fit %.2g / %.2g of the diagonal",
                 names[i], info.crossing_pairs, t.nt, lo, hi, fit.to_max / fit.diag, fit.from_max / fit.diag);
        pw_tetmesh_free(NULL, &t);
        pw_mesh_free(NULL, &s.m);
        done++;
    }
    if (!done) pwt_skip("no CGAL meshes in %s/meshes (run `make data`)", pwt_data_dir());
}

static const pwt_case cases[] = {
    {"stuffing/cgal_union", t_cgal_union},
    {"stuffing/random_fields", t_random_fields},
    {"stuffing/adversary", t_adversary},
    {"stuffing/graded_random", t_graded_random},
    {"stuffing/bisect", t_bisect},
    {"stuffing/cgal", t_cgal},
    {"stuffing/sphere", t_sphere},
    {"stuffing/fit_measure", t_fit_measure},
    {"stuffing/thin_shapes", t_thin_shapes},
    {"stuffing/deterministic", t_deterministic},
    {"stuffing/refusals", t_refusals},
    {"stuffing/small_hole", t_small_hole},
    {"stuffing/shells", t_shells},
    {"stuffing/inward", t_inward},
    {"stuffing/options", t_options},
    {"stuffing/cancel", t_cancel},
    {"stuffing/alloc_failures", t_alloc_failures},
};
PWT_MAIN(cases)
