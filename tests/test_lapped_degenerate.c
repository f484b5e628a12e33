/* lapped.h on degenerate triangles (issue 18, defect 1): zero-area,
 * near-collinear, needle, coincident-corner triangles and duplicated
 * vertices never collapse a paste. The guarantee (docs/lapped.md): every
 * paste's texture area is within [0.25, 4] times the surface it covers
 * over S^2, and at least 99% of the pasted surface lies on triangles whose
 * own ratio is in that range; every texture coordinate is finite, every
 * triangle (degenerate ones too) is covered; the atlas keeps the same
 * bounds against its global scale. On a mesh built with every kind of
 * degeneracy, and on CGAL meshes that have them (skipped without
 * `make data`). */
#define LAPPED_STATIC /* static: only what the tests call is compiled */
#define LAPPED_IMPLEMENTATION
#include "lapped.h"
#include "pwtest.h"

/* ---- a mesh with every kind of degenerate triangle ------------------------ */

#define GRID 16 /* coordinates i / 16 are exact in binary */

static int gv(int i, int j) { return j * (GRID + 1) + i; }

static float bump(float x, float y) { return 0.25f * sinf(3.14159265f * x) * sinf(3.14159265f * y); }

/* Moves vertex v to (1 - t) p + t q plus d times a unit vector in the
 * plane normal to q - p (towards +z), recomputing nothing else. */
static void place(float *pos, int v, int p, int q, float t, float d)
{
    int k;
    float e[3], len = 0.0f;
    for (k = 0; k < 3; k++) {
        e[k] = pos[3 * q + k] - pos[3 * p + k];
        len += e[k] * e[k];
        pos[3 * v + k] = (1.0f - t) * pos[3 * p + k] + t * pos[3 * q + k];
    }
    pos[3 * v + 2] += d * sqrtf(len);
}

/* A bump (GRID x GRID cells, two triangles each: (a, b, c), (a, c, d) with
 * a = (i, j), b = (i+1, j), c = (i+1, j+1), d = (i, j+1)) with, each in its
 * own place: b exactly on the diagonal a-c (zero area, collinear: a, b, c
 * at one height, exact binary coordinates), b on it but 4e-6 L off
 * (area ~2e-6 L^2, like the scan's), b 1e-4 L from a (a needle with a
 * 0.006 degree angle), b exactly on a (coincident corners: two zero-area
 * triangles), and a seam of duplicated vertices along column 11 (the
 * cells right of it use copies: a boundary through the bump). */
static void degenerate_mesh(lapped_mesh *m)
{
    int nv = (GRID + 1) * (GRID + 1), i, j, f = 0, *dup;
    memset(m, 0, sizeof *m);
    m->nverts = nv + GRID + 1;
    m->positions = (float *)malloc(sizeof(float) * 3 * (size_t)m->nverts);
    m->nfaces = 2 * GRID * GRID;
    m->face_start = (int *)malloc(sizeof(int) * (size_t)(m->nfaces + 1));
    m->face_verts = (int *)malloc(sizeof(int) * 3 * (size_t)m->nfaces);
    dup = (int *)malloc(sizeof(int) * (size_t)nv);
    for (j = 0; j <= GRID; j++)
        for (i = 0; i <= GRID; i++) {
            float *p = m->positions + 3 * gv(i, j), x = (float)i / GRID, y = (float)j / GRID;
            p[0] = x, p[1] = y, p[2] = bump(x, y);
            dup[gv(i, j)] = gv(i, j);
        }
    for (j = 0; j <= GRID; j++) { /* the seam's copies */
        memcpy(m->positions + 3 * (nv + j), m->positions + 3 * gv(11, j), sizeof(float) * 3);
        dup[gv(11, j)] = nv + j;
    }
    m->positions[3 * gv(4, 5) + 2] = m->positions[3 * gv(3, 4) + 2];
    place(m->positions, gv(4, 4), gv(3, 4), gv(4, 5), 0.5f, 0.0f);
    place(m->positions, gv(9, 12), gv(8, 12), gv(9, 13), 0.5f, 4e-6f);
    place(m->positions, gv(6, 14), gv(5, 14), gv(6, 14), 1e-4f, 0.0f);
    memcpy(m->positions + 3 * gv(13, 7), m->positions + 3 * gv(12, 7), sizeof(float) * 3);
    for (j = 0; j < GRID; j++)
        for (i = 0; i < GRID; i++) {
            int a = gv(i, j), b = gv(i + 1, j), c = gv(i + 1, j + 1), d = gv(i, j + 1), *fv = m->face_verts + 3 * f;
            if (i >= 11) a = dup[a], d = dup[d];
            if (i + 1 >= 11) b = dup[b], c = dup[c];
            fv[0] = a, fv[1] = b, fv[2] = c, fv[3] = a, fv[4] = c, fv[5] = d;
            m->face_start[f] = 3 * f;
            m->face_start[f + 1] = 3 * f + 3;
            m->face_start[f + 2] = 3 * f + 6;
            f += 2;
        }
    free(dup);
}

static void free_mesh(lapped_mesh *m)
{
    free(m->positions);
    free(m->face_start);
    free(m->face_verts);
}

/* Degenerate triangles of the fan triangulation (pw_trimesh_sliver), and
 * how many of them have exactly zero area. */
static int count_degenerate(const lapped_mesh *mesh, int *zero)
{
    pw_trimesh m;
    pw_alloc a;
    pw_err e;
    int f, n = 0;
    memset(&a, 0, sizeof a);
    pw_err_clear(&e);
    *zero = 0;
    if (lapped__mesh_init(&a, mesh, &m, &e) != PW_OK) return -1;
    for (f = 0; f < m.nf; f++) {
        n += pw_trimesh_sliver(&m, f);
        *zero += m.area[f] == 0.0f;
    }
    pw_trimesh_free(&a, &m);
    return n;
}

/* ---- the guarantee ------------------------------------------------------- */

typedef struct areas {
    int bad_pastes, nonfinite, uncovered;
    double lo, hi;  /* least and largest paste ratio */
    double share;   /* pasted surface on triangles within range */
} areas;

static areas measure(const lapped_mesh *mesh, const lapped_texture *t, const lapped_options *o)
{
    areas r;
    pw_trimesh m;
    pw_alloc a;
    pw_err e;
    lapped_error le;
    lapped_field field;
    lapped__surface sf;
    char *seen = (char *)calloc((size_t)t->ntris, 1);
    double in = 0.0, all = 0.0;
    int p, i;
    memset(&r, 0, sizeof r);
    memset(&a, 0, sizeof a);
    pw_err_clear(&e);
    r.lo = 1e30;
    if (lapped_compute_field(mesh, o, &field, &le) != LAPPED_OK || lapped__mesh_init(&a, mesh, &m, &e) != PW_OK) {
        CHECKF(0, "field: %s %s", le.message, e.msg);
        r.bad_pastes = -1;
        lapped_field_free(&field);
        free(seen);
        return r;
    }
    sf.m = &m;
    sf.fs = field.s;
    sf.ft = field.t;
    for (p = 0; p < t->npastes; p++) {
        const lapped_paste *q = &t->pastes[p];
        lapped__areas ar;
        double tex, surf;
        lapped__paste_areas(&sf, q, 0.25, 4.0, &ar);
        tex = ar.tex;
        surf = ar.surf;
        r.bad_pastes += !lapped__area_ok(tex, surf, 0.25, 4.0, q->nfaces);
        if (surf > 0.0 && tex / surf < r.lo) r.lo = tex / surf;
        if (surf > 0.0 && tex / surf > r.hi) r.hi = tex / surf;
        in += ar.inside;
        all += surf;
        for (i = 0; i < 6 * q->nfaces; i++) r.nonfinite += !pw_is_finite(q->uvs[i]);
        for (i = 0; i < q->nfaces; i++) seen[q->faces[i]] = 1;
    }
    for (i = 0; i < t->ntris; i++) r.uncovered += !seen[i];
    r.share = all > 0.0 ? in / all : 0.0;
    pw_trimesh_free(&a, &m);
    lapped_field_free(&field);
    free(seen);
    return r;
}

static int check_areas(const char *what, const areas *r, int npastes)
{
    pwt_info("%s: %d pastes, paste ratio [%.3g, %.3g], %d out of [0.25, 4], %.4f%% of the pasted surface "
             "in range, %d non-finite coordinates, %d triangles in no paste", what, npastes, r->lo, r->hi,
             r->bad_pastes, 100.0 * r->share, r->nonfinite, r->uncovered);
    CHECKF(r->bad_pastes == 0, "%s: %d pastes outside [0.25, 4] (ratios %.3g .. %.3g)", what, r->bad_pastes,
           r->lo, r->hi);
    CHECKF(r->share >= 0.99, "%s: only %.4f of the pasted surface is within range", what, r->share);
    CHECKF(r->nonfinite == 0, "%s: %d non-finite texture coordinates", what, r->nonfinite);
    CHECKF(r->uncovered == 0, "%s: %d triangles in no paste", what, r->uncovered);
    return r->bad_pastes == 0 && r->share >= 0.99 && r->nonfinite == 0 && r->uncovered == 0;
}

static int make_patch(const char *texture, int size, lapped_options *o, lapped_image *patch)
{
    lapped_image tex;
    lapped_error err;
    int ok = lapped_builtin_exemplar(texture, size, o, &tex, &err) == LAPPED_OK &&
             lapped_make_patch(&tex, NULL, o, patch, &err) == LAPPED_OK;
    CHECKF(ok, "patch: %s", err.message);
    lapped_image_free(&tex);
    return ok;
}

/* ---- the atlas ------------------------------------------------------------ */

/* The atlas holds one scale for every chart: each triangle's atlas area
 * over its surface area, against the whole atlas's, must be in [0.25, 4]
 * for 99% of the surface, and every coordinate finite. */
static void check_atlas(const char *what, const lapped_mesh *mesh, const lapped_texture *t, const lapped_image *patch)
{
    lapped_options o = lapped_default_options();
    lapped_source src;
    lapped_atlas at;
    lapped_error err;
    pw_trimesh m;
    pw_alloc a;
    pw_err e;
    double tex = 0.0, surf = 0.0, in = 0.0, scale;
    int f, k, nonfinite = 0;
    memset(&a, 0, sizeof a);
    pw_err_clear(&e);
    o.atlas.size = 512;
    src.patches = patch, src.npatches = 1, src.values = NULL;
    if (lapped_bake_atlas(mesh, t, &src, &o, &at, &err) != LAPPED_OK) {
        CHECKF(0, "%s atlas: %s", what, err.message);
        return;
    }
    REQUIRE(lapped__mesh_init(&a, mesh, &m, &e) == PW_OK);
    for (k = 0; k < 6 * at.ntris; k++) nonfinite += !pw_is_finite(at.uvs[k]);
    for (f = 0; f < at.ntris; f++) {
        const float *uv = at.uvs + 6 * f;
        tex += 0.5 * fabs(((double)uv[2] - uv[0]) * ((double)uv[5] - uv[1]) -
                          ((double)uv[4] - uv[0]) * ((double)uv[3] - uv[1]));
        surf += m.area[f];
    }
    scale = tex / surf;
    for (f = 0; f < at.ntris; f++) {
        const float *uv = at.uvs + 6 * f;
        double ta = 0.5 * fabs(((double)uv[2] - uv[0]) * ((double)uv[5] - uv[1]) -
                               ((double)uv[4] - uv[0]) * ((double)uv[3] - uv[1]));
        if (lapped__area_ok(ta / scale, m.area[f], 0.25, 4.0, 1)) in += m.area[f];
    }
    pwt_info("%s atlas: %d charts, %.4f%% of the surface within [0.25, 4] of the atlas scale, %d non-finite",
             what, at.ncharts, 100.0 * in / surf, nonfinite);
    CHECKF(nonfinite == 0, "%s atlas: %d non-finite coordinates", what, nonfinite);
    CHECKF(in >= 0.99 * surf, "%s atlas: only %.4f of the surface within range", what, in / surf);
    pw_trimesh_free(&a, &m);
    lapped_atlas_free(&at);
}

/* One fill of mesh with patch, its paste areas checked (and its atlas's). */
static void create_and_check(const char *what, const lapped_mesh *mesh, const lapped_image *patch, const lapped_options *o,
                             int atlas)
{
    lapped_texture t;
    lapped_source src;
    lapped_error err;
    areas r;
    src.patches = patch, src.npatches = 1, src.values = NULL;
    if (lapped_create(mesh, &src, o, &t, &err) != LAPPED_OK) {
        CHECKF(0, "%s: %s", what, err.message);
        return;
    }
    r = measure(mesh, &t, o);
    check_areas(what, &r, t.npastes);
    if (atlas) check_atlas(what, mesh, &t, patch);
    lapped_texture_free(&t);
}

/* ---- cases ------------------------------------------------------------------ */

static void degenerate_case(const char *what, int mode, int lscm, int keep_hidden, int atlas)
{
    lapped_options o = lapped_default_options();
    lapped_mesh mesh;
    lapped_image patch;
    int zero, n;
    degenerate_mesh(&mesh);
    n = count_degenerate(&mesh, &zero);
    CHECKF(n >= 6 && zero >= 3, "the test mesh has %d degenerate triangles (%d zero-area)", n, zero);
    o.field = mode;
    o.scale = 0.3f;
    o.lscm = lscm;
    o.keep_hidden = keep_hidden;
    if (!make_patch("scales", 64, &o, &patch)) return;
    create_and_check(what, &mesh, &patch, &o, atlas);
    lapped_image_free(&patch);
    free_mesh(&mesh);
}

static void t_degenerate_up(void) { degenerate_case("degenerate bump, up", LAPPED_FIELD_UP, 0, 0, 1); }
static void t_degenerate_isotropic(void) { degenerate_case("degenerate bump, isotropic", LAPPED_FIELD_ISOTROPIC, 0, 1, 0); }
static void t_degenerate_lscm(void) { degenerate_case("degenerate bump, lscm", LAPPED_FIELD_ISOTROPIC, 1, 0, 0); }
static void t_degenerate_curvature(void) { degenerate_case("degenerate bump, curvature", LAPPED_FIELD_CURVATURE, 0, 0, 0); }

/* CGAL meshes with such triangles: triceratops (two near-collinear ones in
 * a foot, 1.8e-6 and 2.6e-6 L^2, which collapsed 2-3 pastes to ~1e-7 of
 * their area before) and mpi (two exactly zero-area ones, refused before). */
static void real_case(const char *file, int mode, unsigned long long seed, float scale, int atlas)
{
    const char *mpath = pwt_data(file), *tpath;
    lapped_options o = lapped_default_options();
    lapped_mesh mesh;
    lapped_image tex, patch;
    lapped_error err;
    char what[128];
    if (!mpath || !(tpath = pwt_data("textures/leopard.ppm"))) return;
    o.field = mode;
    o.seed = seed;
    o.scale = scale;
    REQUIRE(lapped_load_mesh(mpath, &o, &mesh, &err) == LAPPED_OK);
    REQUIRE(lapped_load_image(tpath, &o, &tex, &err) == LAPPED_OK);
    REQUIRE(lapped_make_patch(&tex, NULL, &o, &patch, &err) == LAPPED_OK);
    snprintf(what, sizeof what, "%s field %d seed %llu scale %g", file, mode, seed, (double)scale);
    create_and_check(what, &mesh, &patch, &o, atlas);
    lapped_image_free(&patch);
    lapped_image_free(&tex);
    lapped_mesh_free(&mesh);
}

/* LAPPED_SWEEP=1 runs the 15 configurations of docs/lapped.md (fields up,
 * curvature, isotropic; seeds 0-4; scales 1, 4, 8 against the default
 * 2.02) instead of three. */
static void t_real_triceratops(void)
{
    static const int sweep[15][3] = {{0, 0, 0}, {0, 1, 0}, {0, 2, 0}, {0, 3, 0}, {0, 4, 0},
                                     {4, 0, 0}, {4, 1, 0}, {4, 2, 0}, {1, 0, 0}, {1, 1, 0},
                                     {0, 0, 1}, {0, 0, 4}, {0, 0, 8}, {4, 3, 8}, {1, 4, 1}};
    int i;
    if (getenv("LAPPED_SWEEP")) {
        for (i = 0; i < 15; i++)
            real_case("meshes/triceratops.off", sweep[i][0], (unsigned long long)sweep[i][1], (float)sweep[i][2], 0);
        return;
    }
    real_case("meshes/triceratops.off", LAPPED_FIELD_UP, 0, 0.0f, 1);
    real_case("meshes/triceratops.off", LAPPED_FIELD_CURVATURE, 3, 0.0f, 0);
    real_case("meshes/triceratops.off", LAPPED_FIELD_ISOTROPIC, 1, 0.0f, 0);
}

static void t_real_mpi(void) { real_case("meshes/mpi.off", LAPPED_FIELD_UP, 0, 0.0f, 1); }

/* The area guarantee holds per triangle, up to LAPPED__AREA_SLACK of
 * texture each; a paste's sum gets the slack of each of its triangles.
 * The case fuzz_lapped found (fuzz/corpus/fuzz_lapped/
 * regress_area_slack_two_degenerate): a paste of two zero-area triangles
 * whose corners, shared with their neighbours, are not quite collinear in
 * the texture, 7.9e-8 and 5.2e-8 of it: each within the slack, their sum
 * above one slack. */
static void t_area_slack_per_triangle(void)
{
    static const float uv[2][6] = {{0.520266f, 0.312942f, 0.522746f, 0.312561f, 0.522727f, 0.3125f},
                                   {0.522746f, 0.312561f, 0.524337f, 0.312166f, 0.522727f, 0.3125f}};
    double tex = 0.0;
    int k;
    for (k = 0; k < 2; k++) {
        double ta = 0.5 * fabs(((double)uv[k][2] - uv[k][0]) * ((double)uv[k][5] - uv[k][1]) -
                               ((double)uv[k][4] - uv[k][0]) * ((double)uv[k][3] - uv[k][1]));
        CHECK(ta > 0.0 && lapped__area_ok(ta, 0.0, 0.25, 4.0, 1)); /* each triangle: within the slack */
        tex += ta;
    }
    CHECK(tex > LAPPED__AREA_SLACK);                   /* the sum: over one slack */
    CHECK(lapped__area_ok(tex, 0.0, 0.25, 4.0, 2));    /* within the slack of its two triangles */
    CHECK(!lapped__area_ok(tex, 0.0, 0.25, 4.0, 1));
    CHECK(!lapped__area_ok(3.0 * LAPPED__AREA_SLACK, 0.0, 0.25, 4.0, 2)); /* and no more */
}

static const pwt_case cases[] = {
    {"area_slack_per_triangle", t_area_slack_per_triangle},
    {"lapped_degenerate/up", t_degenerate_up},
    {"lapped_degenerate/isotropic", t_degenerate_isotropic},
    {"lapped_degenerate/lscm", t_degenerate_lscm},
    {"lapped_degenerate/curvature", t_degenerate_curvature},
    {"lapped_degenerate/real_triceratops", t_real_triceratops},
    {"lapped_degenerate/real_mpi", t_real_mpi},
};

PWT_MAIN(cases)
