/* pgp.h on real meshes (CGAL's corpus, `make data`; skipped when absent)
 * and the §3 rendering fix checked pixel by pixel.
 *
 * On every closed mesh, with the default field (up) and scale:
 *   - Eq. (4): every vertex's coordinates differ between its triangles by
 *     integers only, and an edge between two regular triangles carries the
 *     same (s, t) difference on both sides;
 *   - the parameterization follows the field: the medians over all
 *     triangles of | |grad s| S - 1 | (and the same for t) stay at or below
 *     0.15 and of the angle between grad s and d_s at or below 8 degrees
 *     (measured: 0.055-0.122 and 2.0-5.5 degrees);
 *   - the singular triangles (§3: a corner whose 1-ring holds a triangle
 *     with |grad s - g_s|^2 > 0.5 |g_s|^2 or a mismatched edge) and the
 *     vortices stay within issue 17's bounds at S = diag/10: what
 *     cotangent edge weights gave in geogram's comparison (elephant 33%,
 *     cow 34%, knot 37%, mushroom 24%) with at most 5% more vortices than
 *     the paper's area weights made (47, 47, 64, 34). Measured: 30.5%,
 *     32.9%, 34.1%, 21.5% with 40, 46, 61, 32 vortices (before issue 17,
 *     the paper's weights and a first proximal step at 1e-3: 44.9%, 54.2%,
 *     42.1%, 23.7% with 47, 47, 64, 34). The paper
 *     quotes 5-10% on its meshes; each vortex costs a disc of 0.16 S^2
 *     where |grad s - g| > 0.7 |g| (any periodic parameterization winds
 *     there; test_pgp.c's sphere_regime checks the figure), the vortices
 *     per tile grow as S over the radius of the features (limbs, ears,
 *     tails are about a tile across here), and the ring the rule adds
 *     around each disc is large when a tile spans few triangles. Where
 *     tiles are small against the features and large against the
 *     triangles (the fine sphere) the share is the paper's. `eight` (634
 *     triangles, 71.5%) is only guarded against regressions (85%). */
#define PGP_STATIC /* static: only what the tests call is compiled */
#define PGP_IMPLEMENTATION
#include "pgp.h"
#include "pwtest.h"

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n ? v[n / 2] : 0.0;
}

/* Integer jumps at every corner pair and agreement on regular edges. */
static void check_jumps(const pgp__state *P, const char *name)
{
    int h, k, bad = 0, mism = 0;
    for (h = 0; h < 3 * P->pp.m.nf; h++) {
        int t = P->pp.m.hm.twin[h], f = h / 3, c = h % 3;
        if (t < 0) continue;
        for (k = 0; k < 2; k++) {
            double jump = P->pp.stm[9 * f + 3 * c + k] - P->pp.stm[9 * (t / 3) + 3 * ((t % 3 + 1) % 3) + k];
            if (fabs(jump - floor(jump + 0.5)) > 1e-4) bad++;
        }
        if (!P->fsing[f] && !P->fsing[t / 3]) mism += pgp__mismatch(P, h);
    }
    CHECKF(bad == 0, "%s: %d corner pairs differ by a non-integer", name, bad);
    CHECKF(mism == 0, "%s: %d edges between regular triangles disagree", name, mism);
}

/* Medians of | |grad| S - 1 | and of the angle (degrees) to the field. */
static void field_errors(const pgp__state *P, double *len_med, double *ang_med)
{
    int nf = P->pp.m.nf, f, k, n = 0;
    double *len = (double *)malloc(sizeof(double) * 2 * (size_t)nf), *ang = (double *)malloc(sizeof(double) * 2 * (size_t)nf);
    for (f = 0; len && ang && f < nf; f++)
        for (k = 0; k < 2; k++) {
            const float *o = P->pp.stm + 9 * f;
            pw_v3 g = pw_periodic_grad(&P->pp, f, k), gs = pw_periodic_gradient(&P->pp, f, o[k], o[3 + k], o[6 + k]);
            double L = pw_v3_len(gs), c = L > 0.0 ? pw_v3_dot(gs, g) / (L * pw_v3_len(g)) : -1.0;
            len[n] = fabs(L * pw_periodic_face_scale(&P->pp, f) - 1.0);
            ang[n++] = acos(c > 1.0 ? 1.0 : (c < -1.0 ? -1.0 : c)) * (180.0 / 3.14159265358979);
        }
    *len_med = median(len, n);
    *ang_med = median(ang, n);
    free(len);
    free(ang);
}

static void real_mesh(const char *file, double max_singular, int max_vortices)
{
    const char *path = pwt_data(file);
    pgp_options o = pgp_default_options();
    pgp_mesh m;
    pgp_map map, *P = &map;
    pgp_error err;
    double lm, am, sing, area;
    int f;
    if (!path) return;
    REQUIRE(pgp_load_mesh(path, &o, &m, &err) == PGP_OK);
    CHECKF(pgp_create(&m, &o, P, &err) == PGP_OK, "%s: %s", file, err.message);
    if (P->state) {
        check_jumps(P->state, file);
        field_errors(P->state, &lm, &am);
        sing = (double)pgp_map_singular(P, NULL) / P->state->pp.m.nf;
        for (f = 0, area = 0.0; f < P->state->pp.m.nf; f++) area += P->state->pp.m.area[f];
        pwt_info("%s: %d triangles, %.0f tiles, %d vortices, singular %.1f%% (paper: 5-10%%), median | |grad| S - 1 | "
                 "%.3f, median angle %.2f deg", file, P->state->pp.m.nf, area / ((double)P->state->pp.scale0 * P->state->pp.scale0),
                 pgp_map_vortices(P, NULL), 100.0 * sing, lm, am);
        CHECKF(lm <= 0.15, "%s: median scale error %.3f", file, lm);
        CHECKF(am <= 8.0, "%s: median angle error %.2f deg", file, am);
        CHECKF(sing <= max_singular, "%s: %.1f%% singular triangles (at most %.0f%%)", file, 100.0 * sing,
               100.0 * max_singular);
        CHECKF(pgp_map_vortices(P, NULL) <= max_vortices, "%s: %d vortices (at most %d)", file,
               pgp_map_vortices(P, NULL), max_vortices);
        pgp_map_free(P);
    }
    pgp_mesh_free(&m);
}

static void t_elephant(void) { real_mesh("meshes/elephant.off", 0.33, 49); }
static void t_cow(void) { real_mesh("meshes/cow.off", 0.34, 49); }
static void t_knot(void) { real_mesh("meshes/knot.off", 0.37, 67); }
static void t_eight(void) { real_mesh("meshes/eight.off", 0.85, 1000); }
static void t_mushroom(void) { real_mesh("meshes/mushroom.off", 0.24, 35); }

/* §2.3's printed weights A_T + A_T' (PGP_WEIGHTS_AREA) against the default
 * cotangent weights on CGAL's cow, where the triangle areas vary most: the
 * singular share falls by more than a third (measured 50.4% -> 32.9%,
 * both with the same proximal steps). */
static void t_weights(void)
{
    const char *path = pwt_data("meshes/cow.off");
    pgp_options o = pgp_default_options();
    pgp_mesh m;
    pgp_map a_map, c_map, *A = &a_map, *C = &c_map;
    pgp_error err;
    double sa, sc;
    if (!path) return;
    REQUIRE(pgp_load_mesh(path, &o, &m, &err) == PGP_OK);
    CHECKF(pgp_create(&m, &o, C, &err) == PGP_OK, "%s", err.message);
    o.weights = PGP_WEIGHTS_AREA;
    CHECKF(pgp_create(&m, &o, A, &err) == PGP_OK, "%s", err.message);
    if (A->state && C->state) {
        sa = (double)pgp_map_singular(A, NULL) / A->ntris, sc = (double)pgp_map_singular(C, NULL) / C->ntris;
        pwt_info("cow: singular %.1f%% with area weights (%d vortices), %.1f%% with cotangent weights (%d)",
                 100.0 * sa, pgp_map_vortices(A, NULL), 100.0 * sc, pgp_map_vortices(C, NULL));
        CHECKF(sc < 0.67 * sa, "cotangent weights: %.1f%% singular, area weights %.1f%%", 100.0 * sc, 100.0 * sa);
    }
    pgp_map_free(A);
    o.weights = (pgp_weights)7;
    CHECK(pgp_create(&m, &o, A, &err) == PGP_ERR_INVALID && !A->state && strstr(err.message, "weights"));
    pgp_map_free(C);
    pgp_mesh_free(&m);
}

/* A smooth periodic tile: a small coordinate error changes a colour a
 * little, a lookup at a wrong tile position changes it a lot. */
static void smooth_tile(pgp_tile *t)
{
    int i, j;
    memset(t, 0, sizeof *t);
    t->width = t->height = 64, t->layers = 1, t->channels = 3;
    t->pixels = (float *)malloc(sizeof(float) * 3 * 64 * 64);
    for (j = 0; j < 64; j++)
        for (i = 0; i < 64; i++) {
            double s = (i + 0.5) / 64.0, tt = 1.0 - (j + 0.5) / 64.0, tp = 6.283185307179586;
            float *p = t->pixels + 3 * (j * 64 + i);
            p[0] = (float)(0.5 + 0.5 * sin(tp * s));
            p[1] = (float)(0.5 + 0.5 * cos(tp * tt));
            p[2] = (float)(0.5 + 0.5 * sin(tp * (s + tt)));
        }
}

/* Fraction of pixels whose colour differs by more than 0.25 in a channel. */
static double differing(const pgp_image *a, const pgp_image *b)
{
    size_t i, n = (size_t)a->width * a->height, bad = 0;
    int c;
    for (i = 0; i < n; i++)
        for (c = 0; c < 3; c++)
            if (fabs(a->pixels[3 * i + c] - b->pixels[3 * i + c]) > 0.25f) {
                bad++;
                break;
            }
    return (double)bad / (double)n;
}

/* §3 on a closed mesh: with the fix, no pixel is a lookup from a wrong tile
 * position, judged against the reference that takes three lookups on every
 * triangle; without it, the singular triangles show such pixels (so the
 * comparison can see them). */
static void render_fix(pgp_mesh *m, const char *name)
{
    pgp_options o = pgp_default_options();
    pgp_render_options ro;
    pgp_map map, *P = &map;
    pgp_tile tile;
    pgp_image fixed, ref, raw;
    pgp_error err;
    double d_fixed, d_raw;
    smooth_tile(&tile);
    memset(&ro, 0, sizeof ro);
    ro.width = 400, ro.height = 300, ro.supersample = 1;
    REQUIRE(pgp_create(m, &o, P, &err) == PGP_OK);
    ro.fix = PGP_FIX_PAPER;
    CHECK(pgp_render(P, &tile, &ro, &fixed, &err) == PGP_OK);
    ro.fix = PGP_FIX_ALL;
    CHECK(pgp_render(P, &tile, &ro, &ref, &err) == PGP_OK);
    ro.fix = PGP_FIX_OFF;
    CHECK(pgp_render(P, &tile, &ro, &raw, &err) == PGP_OK);
    d_fixed = differing(&fixed, &ref);
    d_raw = differing(&raw, &ref);
    pwt_info("%s: pixels off the three-lookup reference by > 0.25: %.4f%% with the fix, %.3f%% without", name,
             100.0 * d_fixed, 100.0 * d_raw);
    CHECKF(d_fixed <= 1e-4, "%s: %.4f%% of the pixels are wrong with the fix", name, 100.0 * d_fixed);
    CHECKF(d_raw > 10.0 * d_fixed && d_raw > 0.0, "%s: the unfixed rendering shows no wrong lookups (%.4f%%)", name,
           100.0 * d_raw);
    pgp_image_free(&fixed);
    pgp_image_free(&ref);
    pgp_image_free(&raw);
    pgp_tile_free(&tile);
    pgp_map_free(P);
}

static void t_render_fix_torus(void)
{
    pgp_options o = pgp_default_options();
    pgp_mesh m;
    pgp_error err;
    REQUIRE(pgp_builtin_mesh("torus", &o, &m, &err) == PGP_OK);
    render_fix(&m, "built-in torus");
    pgp_mesh_free(&m);
}

static void t_render_fix_real(void)
{
    const char *path = pwt_data("meshes/elephant.off");
    pgp_options o = pgp_default_options();
    pgp_mesh m;
    pgp_error err;
    if (!path) return;
    REQUIRE(pgp_load_mesh(path, &o, &m, &err) == PGP_OK);
    render_fix(&m, "CGAL elephant");
    pgp_mesh_free(&m);
}

/* Issue 17: options.integrable (the CLI's --field smooth) trades alignment
 * for integrability. The issue asks for at most as many vortices as
 * geogram's own smooth cross field makes at S = diag/10 (elephant 38, cow
 * 42, knot 50, mushroom 15); measured 28, 26, 40, 15 (the up field tried
 * along three axes: mushroom 18 along +Y, whose poles sit on the rim of
 * its cap, 15 along +Z). The search does not depend on which axis is up
 * (mushroom with up = +Z: the same count), and it is deterministic. */
static void check_clean(const pgp_map *P, const char *name);

/* The same options again (the same coordinates, bit for bit) and with up
 * along +Z (the same three axes in another order: the same count). */
static void integrable_axes(const pgp_mesh *m, pgp_options *o, const pgp_map *P)
{
    pgp_map Q;
    pgp_error err;
    float up[3];
    memcpy(up, o->up, sizeof up);
    CHECK(pgp_create(m, o, &Q, &err) == PGP_OK && Q.state &&
          memcmp(Q.coords, P->coords, sizeof(float) * 9 * (size_t)P->ntris) == 0);
    pgp_map_free(&Q);
    o->up[0] = o->up[1] = 0.0f;
    o->up[2] = 1.0f;
    CHECKF(pgp_create(m, o, &Q, &err) == PGP_OK, "%s", err.message);
    if (Q.state)
        CHECKF(pgp_map_vortices(&Q, NULL) == pgp_map_vortices(P, NULL), "up +Y: %d vortices, up +Z: %d",
               pgp_map_vortices(P, NULL), pgp_map_vortices(&Q, NULL));
    pgp_map_free(&Q);
    memcpy(o->up, up, sizeof up);
}

static void t_integrable(void)
{
    static const char *const files[4] = {"meshes/elephant.off", "meshes/cow.off", "meshes/knot.off",
                                         "meshes/mushroom.off"};
    static const int most[4] = {38, 42, 50, 15};
    pgp_options o = pgp_default_options();
    pgp_mesh m;
    pgp_map map, *P = &map;
    pgp_error err;
    int i, plain;
    for (i = 0; i < 4; i++) {
        const char *path = pwt_data(files[i]);
        if (!path) return;
        REQUIRE(pgp_load_mesh(path, &o, &m, &err) == PGP_OK);
        o.integrable = 0.0f;
        REQUIRE(pgp_create(&m, &o, P, &err) == PGP_OK);
        plain = pgp_map_vortices(P, NULL);
        pgp_map_free(P);
        o.integrable = 1.0f;
        CHECKF(pgp_create(&m, &o, P, &err) == PGP_OK, "%s: %s", files[i], err.message);
        if (P->state) {
            pgp_stats st;
            pgp_map_stats(P, &st);
            pwt_info("%s: %d vortices (%d following the field), singular %.1f%%, stretched %.1f%%, sheared %.1f%%",
                     files[i], st.vortices, plain, 100.0 * st.singular / st.triangles, 100.0 * st.stretched,
                     100.0 * st.sheared);
            CHECKF(st.vortices <= most[i], "%s: %d vortices (at most %d)", files[i], st.vortices, most[i]);
            check_clean(P, files[i]);
        }
        if (P->state && i == 3) integrable_axes(&m, &o, P);
        pgp_map_free(P);
        pgp_mesh_free(&m);
    }
}

/* ---- issue 17: the clean fix of the vortices --------------------------------------------- */

/* (s, t) drawn at barycentric (b1, b2) of triangle f with the clean fix. */
static void drawn_st(const pgp__state *P, const unsigned char *fixed, const float *data, int f, double b1, double b2,
                     double *st)
{
    double b[3];
    int k;
    b[0] = 1.0 - b1 - b2, b[1] = b1, b[2] = b2;
    for (k = 0; k < 2; k++)
        st[k] = fixed[f] ? pw_periodic_clean_eval(data + PGP__FIXDATA * (size_t)f + 12 * k, b)
                         : b[0] * P->pp.stm[9 * f + k] + b[1] * P->pp.stm[9 * f + 3 + k] + b[2] * P->pp.stm[9 * f + 6 + k];
}

/* Point c of 9 along half-edge h, in its triangle's barycentric coordinates. */
static void along(int h, int c, double *b1, double *b2)
{
    double b[3] = {0.0, 0.0, 0.0}, x = (c + 0.5) / 9.0;
    b[h % 3] = 1.0 - x, b[(h % 3 + 1) % 3] = x;
    *b1 = b[1], *b2 = b[2];
}

/* The clean fix (PGP_FIX_CLEAN) on a map: the triangles drawn specially are
 * the vortices and at most 10%; every edge carries the same (s, t) on both
 * sides, modulo integers, at 9 points (no seam anywhere); and around the
 * zero of every vortex triangle the drawn coordinate winds by the
 * triangle's winding (the pattern ends or forks there). */
static void check_clean(const pgp_map *map, const char *name)
{
    const pgp__state *P = map->state;
    int nf = P->pp.m.nf, h, c, k, f, seams = 0, raw = 0, unwound = 0, n;
    unsigned char *fixed = (unsigned char *)malloc((size_t)nf), *none = (unsigned char *)calloc((size_t)nf, 1);
    float *data = (float *)malloc(sizeof(float) * PGP__FIXDATA * (size_t)nf);
    double worst = 0.0, st0[2], st1[2], r0[2], r1[2], b1, b2;
    REQUIRE(fixed && data && none);
    pgp__fix_data(P, PGP_FIX_CLEAN, fixed, data);
    n = pgp_map_special(map, PGP_FIX_CLEAN, NULL);
    for (h = 0; h < 3 * nf; h++) {
        int t = P->pp.m.hm.twin[h];
        if (t < h) continue;
        for (c = 0; c < 9; c++) {
            along(h, c, &b1, &b2);
            drawn_st(P, fixed, data, h / 3, b1, b2, st0);
            drawn_st(P, none, data, h / 3, b1, b2, r0);
            along(t, 8 - c, &b1, &b2);
            drawn_st(P, fixed, data, t / 3, b1, b2, st1);
            drawn_st(P, none, data, t / 3, b1, b2, r1);
            for (k = 0; k < 2; k++) {
                double d = fabs(pgp__wrap(st0[k] - st1[k]));
                worst = d > worst ? d : worst;
                seams += d > 1e-3;
                raw += fabs(pgp__wrap(r0[k] - r1[k])) > 1e-3; /* Eq. (4) alone: the seams the fix removes */
            }
        }
    }
    for (f = 0; f < nf; f++) /* 64 steps on a circle of radius 0.02 around the zero */
        for (k = 0; fixed[f] && k < 2; k++) {
            const float *Q = data + PGP__FIXDATA * (size_t)f + 12 * k + 9;
            double sum = 0.0, prev = 0.0, cur;
            int i;
            if (Q[0] < 0.0f) continue;
            for (i = 0; i <= 64; i++, prev = cur) {
                double a = 6.283185307179586 * i / 64.0;
                drawn_st(P, fixed, data, f, Q[1] + 0.02 * cos(a), Q[2] + 0.02 * sin(a), st0);
                cur = st0[k];
                if (i) sum += pgp__wrap(cur - prev);
            }
            unwound += fabs(fabs(sum) - fabs((double)pw_periodic_winding(&P->pp, f, k))) > 1e-6 || fabs(sum) < 0.5;
        }
    pwt_info("%s: %d triangles drawn specially (%.2f%%), %d vortices; largest (s, t) difference across an edge %.2g "
             "(Eq. 4 alone: %d edge points off)", name, n, 100.0 * n / nf, pgp_map_vortices(map, NULL), worst, raw);
    CHECKF(n == pgp_map_vortices(map, NULL), "%s: %d triangles drawn specially, %d vortices", name, n,
           pgp_map_vortices(map, NULL));
    CHECKF(n <= 0.10 * nf, "%s: %.1f%% drawn specially", name, 100.0 * n / nf);
    CHECKF(seams == 0, "%s: %d edge points where the two sides differ (up to %.3g)", name, seams, worst);
    CHECKF(n == 0 || raw > 0, "%s: Eq. (4) alone shows no seam at %d vortices", name, n);
    CHECKF(unwound == 0, "%s: %d vortex triangles whose drawn coordinate does not wind", name, unwound);
    free(fixed);
    free(none);
    free(data);
}

static void clean_mesh(pgp_mesh *m, const char *name)
{
    pgp_options o = pgp_default_options();
    pgp_map map, *P = &map;
    pgp_error err;
    CHECKF(pgp_create(m, &o, P, &err) == PGP_OK, "%s: %s", name, err.message);
    if (P->state) check_clean(P, name);
    pgp_map_free(P);
}

static void t_clean_builtin(void)
{
    static const char *const names[3] = {"torus", "sphere", "bumpy"};
    pgp_options o = pgp_default_options();
    pgp_mesh m;
    pgp_error err;
    int i;
    for (i = 0; i < 3; i++) {
        REQUIRE(pgp_builtin_mesh(names[i], &o, &m, &err) == PGP_OK);
        clean_mesh(&m, names[i]);
        pgp_mesh_free(&m);
    }
}

static void t_clean_cgal(void)
{
    static const char *const files[4] = {"meshes/elephant.off", "meshes/cow.off", "meshes/knot.off",
                                         "meshes/mushroom.off"};
    pgp_options o = pgp_default_options();
    pgp_mesh m;
    pgp_error err;
    int i;
    for (i = 0; i < 4; i++) {
        const char *path = pwt_data(files[i]);
        if (!path) return;
        REQUIRE(pgp_load_mesh(path, &o, &m, &err) == PGP_OK);
        clean_mesh(&m, files[i]);
        pgp_mesh_free(&m);
    }
}

/* Share of the covered pixels a PGP_SHOW_GHOSTS rendering marks (red:
 * the final colour mixes lookups whose (s, t) differ by more than a tenth
 * of a period); the background is blue. */
static double ghost_share(const pgp_map *P, const pgp_tile *tile, int fix)
{
    pgp_render_options ro;
    pgp_image img;
    pgp_error err;
    size_t i, n, covered = 0, ghosts = 0;
    memset(&ro, 0, sizeof ro);
    ro.width = 400, ro.height = 300, ro.supersample = 1, ro.fix = fix, ro.show = PGP_SHOW_GHOSTS;
    ro.background[2] = 1.0f;
    if (pgp_render(P, tile, &ro, &img, &err) != PGP_OK) return -1.0;
    for (i = 0, n = (size_t)img.width * img.height; i < n; i++) {
        const float *p = img.pixels + 3 * i;
        if (p[0] == 0.0f && p[1] == 0.0f && p[2] == 1.0f) continue;
        covered++;
        ghosts += p[1] < 0.5f * p[0];
    }
    pgp_image_free(&img);
    return covered ? (double)ghosts / covered : -1.0;
}

/* Ghost pixels of the renderings of bricks and stripes on the built-in
 * torus and CGAL's elephant: at most 0.1% with the clean fix; the §3 blend
 * (PGP_FIX_PAPER) shows them, so the measure can see them. */
static void t_ghosts(void)
{
    static const char *const tiles[2] = {"bricks", "stripes"};
    const char *path = pwt_data("meshes/elephant.off");
    pgp_options o = pgp_default_options();
    pgp_mesh m;
    pgp_map map, *P = &map;
    pgp_tile tile;
    pgp_error err;
    int i, j;
    for (j = 0; j < (path ? 2 : 1); j++) {
        REQUIRE((j ? pgp_load_mesh(path, &o, &m, &err) : pgp_builtin_mesh("torus", &o, &m, &err)) == PGP_OK);
        REQUIRE(pgp_create(&m, &o, P, &err) == PGP_OK);
        for (i = 0; i < 2; i++) {
            double clean, paper;
            REQUIRE(pgp_builtin_tile(tiles[i], 64, &o, &tile, &err) == PGP_OK);
            clean = ghost_share(P, &tile, PGP_FIX_CLEAN), paper = ghost_share(P, &tile, PGP_FIX_PAPER);
            pwt_info("%s, %s: ghost pixels %.3f%% with the clean fix, %.3f%% with section 3's", j ? "elephant" : "torus",
                     tiles[i], 100.0 * clean, 100.0 * paper);
            CHECKF(clean >= 0.0 && clean <= 0.001, "%s: %.3f%% ghost pixels", tiles[i], 100.0 * clean);
            CHECKF(paper > 0.001, "%s: the measure sees no ghost in section 3's blend (%.3f%%)", tiles[i], 100.0 * paper);
            pgp_tile_free(&tile);
        }
        pgp_map_free(P);
        pgp_mesh_free(&m);
    }
}

static const pwt_case cases[] = {
    {"pgp_real/elephant", t_elephant},
    {"pgp_real/cow", t_cow},
    {"pgp_real/knot", t_knot},
    {"pgp_real/eight", t_eight},
    {"pgp_real/mushroom", t_mushroom},
    {"pgp_real/weights", t_weights},
    {"pgp_real/clean_builtin", t_clean_builtin},
    {"pgp_real/clean_cgal", t_clean_cgal},
    {"pgp_real/ghosts", t_ghosts},
    {"pgp_real/integrable", t_integrable},
    {"pgp_real/render_fix_torus", t_render_fix_torus},
    {"pgp_real/render_fix_elephant", t_render_fix_real},
};
PWT_MAIN(cases)
