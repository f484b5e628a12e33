/* Tests of lapped.h's pasting (§3.3-3.6), its results and its files,
 * through the public API (and the implementation compiled in here where a
 * test needs to look inside). */
#define LAPPED_STATIC /* static: only what the tests call is compiled */
#define LAPPED_IMPLEMENTATION
#include "lapped.h"
#include "pwtest.h"

/* ---- helpers ------------------------------------------------------------- */

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
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

/* The opacity every pasted texture reaches at a dense lattice of points of
 * every triangle (barycentric (i,j,k)/12), compositing the pastes' patch
 * alpha in order; returns the smallest and the share of points below need. */
static float dense_coverage(const lapped_texture *t, const lapped_image *patches, float need, double *below)
{
    const int R = 12;
    lapped__index ix;
    lapped__look L;
    pw_alloc a;
    pw_err e;
    pw_image *views = (pw_image *)calloc((size_t)t->npatches, sizeof(pw_image));
    float worst = 1.0f;
    long n = 0, low = 0;
    int f, i, j, k;
    memset(&a, 0, sizeof a);
    pw_err_clear(&e);
    for (k = 0; k < t->npatches; k++) views[k] = lapped__pw_image(&patches[k]);
    if (lapped__index_build(&a, t, &ix, &e) != PW_OK) return -1.0f;
    L.ix = &ix;
    L.t = t;
    L.patches = views;
    L.values = views;
    for (f = 0; f < t->ntris; f++)
        for (i = 0; i <= R; i++)
            for (j = 0; i + j <= R; j++) {
                float b[3], rgba[4], alpha;
                b[0] = (float)i / R;
                b[1] = (float)j / R;
                b[2] = (float)(R - i - j) / R;
                lapped__eval(&L, f, b, rgba, &alpha);
                if (alpha < worst) worst = alpha;
                low += alpha < need;
                n++;
            }
    lapped__index_free(&a, &ix);
    free(views);
    *below = (double)low / n;
    return worst;
}

/* The source of n patches, without values. */
static lapped_source patches_of(const lapped_image *patches, int n)
{
    lapped_source src;
    src.patches = patches;
    src.npatches = n;
    src.values = NULL;
    return src;
}

/* Runs lapped_create on a built-in mesh and texture. */
static int create(const char *mesh_name, const char *texture, lapped_options *o, lapped_mesh *mesh,
                  lapped_image *patch, lapped_texture *t)
{
    lapped_error err;
    lapped_source src = patches_of(patch, 1);
    if (lapped_builtin_mesh(mesh_name, o, mesh, &err) != LAPPED_OK) {
        CHECKF(0, "mesh: %s", err.message);
        return 0;
    }
    if (!make_patch(texture, 64, o, patch)) return 0;
    if (lapped_create(mesh, &src, o, t, &err) != LAPPED_OK) {
        CHECKF(0, "create: %s", err.message);
        return 0;
    }
    return 1;
}

/* ---- coverage (§3.6) ------------------------------------------------------ */

static void coverage_case(const char *mesh_name, const char *texture, int mode)
{
    lapped_options o = lapped_default_options();
    lapped_mesh mesh;
    lapped_image patch;
    lapped_texture t;
    double below;
    float worst;
    o.field = mode;
    o.scale = 0.5f;
    o.keep_hidden = getenv("KEEP") != NULL;
    if (!create(mesh_name, texture, &o, &mesh, &patch, &t)) return;
    worst = dense_coverage(&t, &patch, 0.99f, &below);
    pwt_info("%s/%s field %d: %d triangles, %d pastes, layers %.2f (%.2f before hiding), %d hard edges; "
             "least opacity %.4f, %.4f%% of points under 0.99", mesh_name, texture, mode, t.ntris,
             t.npastes, t.layers, t.layers_before, t.hard_edges, worst, 100.0 * below);
    CHECKF(worst >= 0.99f, "a point only reaches opacity %.4f", worst);
    lapped_texture_free(&t);
    lapped_image_free(&patch);
    lapped_mesh_free(&mesh);
}

static void t_coverage_sphere_up(void) { coverage_case("sphere", "scales", LAPPED_FIELD_UP); }
static void t_coverage_torus_isotropic(void) { coverage_case("torus", "dots", LAPPED_FIELD_ISOTROPIC); }
static void t_coverage_bumpy_curvature(void) { coverage_case("bumpy", "stripes", LAPPED_FIELD_CURVATURE); }
static void t_coverage_disc_boundary(void) { coverage_case("disc", "dots", LAPPED_FIELD_UP); }

/* ---- alignment (§3.4) ------------------------------------------------------ */

/* |phi(S) - s^| and |phi(T) - t^| per pasted triangle (all pastes kept
 * whole), with the field the pasting used. */
static void alignment_errors(const lapped_mesh *mesh, const lapped_texture *t, const lapped_options *o,
                             double *median, double *p90)
{
    pw_trimesh m;
    pw_alloc a;
    pw_err e;
    lapped_field field;
    float *s, *tt;
    double *errs;
    long n = 0, total = 0;
    int p, i, k;
    lapped_error le;
    memset(&a, 0, sizeof a);
    pw_err_clear(&e);
    REQUIRE(lapped_compute_field(mesh, o, &field, &le) == LAPPED_OK);
    s = field.s, tt = field.t;
    REQUIRE(lapped__mesh_init(&a, mesh, &m, &e) == PW_OK);
    for (p = 0; p < t->npastes; p++) total += t->pastes[p].nfaces;
    errs = (double *)malloc(sizeof(double) * (size_t)total);
    for (p = 0; p < t->npastes; p++)
        for (i = 0; i < t->pastes[p].nfaces; i++) {
            int f = t->pastes[p].faces[i];
            const float *uv = t->pastes[p].uvs + 6 * i;
            float ws[3], wt[3], ps[2] = {0, 0}, pt[2] = {0, 0};
            lapped__coeffs(&m, f, pw_v3_load(s + 3 * f), ws);
            lapped__coeffs(&m, f, pw_v3_load(tt + 3 * f), wt);
            for (k = 0; k < 3; k++) {
                ps[0] += ws[k] * uv[2 * k], ps[1] += ws[k] * uv[2 * k + 1];
                pt[0] += wt[k] * uv[2 * k], pt[1] += wt[k] * uv[2 * k + 1];
            }
            errs[n++] = 0.5 * (sqrt((ps[0] - 1) * (ps[0] - 1) + ps[1] * ps[1]) +
                               sqrt(pt[0] * pt[0] + (pt[1] - 1) * (pt[1] - 1)));
        }
    qsort(errs, (size_t)n, sizeof *errs, cmp_double);
    *median = errs[n / 2];
    *p90 = errs[(long)(0.9 * (n - 1))];
    free(errs);
    lapped_field_free(&field);
    pw_trimesh_free(&a, &m);
}

/* With a smooth up field on a smooth mesh, phi(S) and phi(T) match the
 * texture axes: the median relative error stays under 5%. */
static void t_alignment(void)
{
    lapped_options o = lapped_default_options();
    lapped_mesh mesh;
    lapped_image patch;
    lapped_texture t;
    double med = 1.0, p90 = 1.0;
    o.field = LAPPED_FIELD_UP;
    o.up[0] = 0.3f;
    o.up[1] = 1.0f;
    o.up[2] = 0.2f;
    o.scale = 0.4f;
    o.keep_hidden = 1;
    if (!create("bumpy", "scales", &o, &mesh, &patch, &t)) return;
    alignment_errors(&mesh, &t, &o, &med, &p90);
    pwt_info("|phi(S) - s^|, |phi(T) - t^| over %d pastes: median %.4f, 90th percentile %.4f", t.npastes, med, p90);
    CHECKF(med < 0.05, "median alignment error %.4f", med);
    lapped_texture_free(&t);
    lapped_image_free(&patch);
    lapped_mesh_free(&mesh);
}

/* ---- disc topology of every surface patch (§3.3) ---------------------------- */

/* A set of triangles is a disc when V - E + F = 1 and the triangles around
 * each of its vertices form one fan: walking around a vertex, at most one
 * triangle of the set has its next neighbour (across the edge leaving the
 * vertex) outside the set. vmark and ends are nv zeroed scratch arrays. */
static int is_disc(const pw_trimesh *m, const int *faces, int n, int *in_set, int *vmark, int *ends)
{
    int i, k, v = 0, e2 = 0, bad = 0;
    for (i = 0; i < n; i++) in_set[faces[i]] = 1;
    for (i = 0; i < n; i++)
        for (k = 0; k < 3; k++) {
            int g = pw_trimesh_across(m, faces[i], k), vert = m->tri[3 * faces[i] + k];
            int inside = g >= 0 && in_set[g];
            e2 += inside ? 1 : 2; /* edges inside the set are seen from both sides */
            if (!vmark[vert]++) v++;
            if (!inside && ++ends[vert] > 1) bad++;
        }
    for (i = 0; i < n; i++) {
        in_set[faces[i]] = 0;
        for (k = 0; k < 3; k++) vmark[m->tri[3 * faces[i] + k]] = ends[m->tri[3 * faces[i] + k]] = 0;
    }
    return !bad && v - e2 / 2 + n == 1;
}

static void t_disc_topology(void)
{
    lapped_options o = lapped_default_options();
    lapped_mesh mesh;
    lapped_image patch;
    lapped_texture t;
    pw_trimesh m;
    pw_alloc a;
    pw_err e;
    int p, bad = 0, *in_set, *vmark, *ends;
    o.field = LAPPED_FIELD_ISOTROPIC;
    o.scale = 0.6f;
    o.keep_hidden = 1;
    if (!create("torus", "dots", &o, &mesh, &patch, &t)) return;
    memset(&a, 0, sizeof a);
    pw_err_clear(&e);
    REQUIRE(lapped__mesh_init(&a, &mesh, &m, &e) == PW_OK);
    in_set = (int *)calloc((size_t)m.nf, sizeof(int));
    vmark = (int *)calloc((size_t)m.nv, sizeof(int));
    ends = (int *)calloc((size_t)m.nv, sizeof(int));
    for (p = 0; p < t.npastes; p++) bad += !is_disc(&m, t.pastes[p].faces, t.pastes[p].nfaces, in_set, vmark, ends);
    CHECKF(bad == 0, "%d of %d surface patches are not discs", bad, t.npastes);
    pwt_info("%d surface patches checked", t.npastes);
    free(in_set);
    free(vmark);
    free(ends);
    pw_trimesh_free(&a, &m);
    lapped_texture_free(&t);
    lapped_image_free(&patch);
    lapped_mesh_free(&mesh);
}

/* ---- determinism and the paste file --------------------------------------------- */

static int buf_sink(void *ctx, const void *data, size_t size) { return pw_buf_write(ctx, data, size); }

static void pastes_text(unsigned long long seed, pw_buf *out)
{
    lapped_options o = lapped_default_options();
    lapped_mesh mesh;
    lapped_image patch;
    lapped_texture t;
    lapped_error err;
    memset(out, 0, sizeof *out);
    o.seed = seed;
    o.scale = 0.5f;
    if (!create("sphere", "scales", &o, &mesh, &patch, &t)) return;
    CHECK(lapped_write_pastes(&t, buf_sink, out, &err) == LAPPED_OK);
    lapped_texture_free(&t);
    lapped_image_free(&patch);
    lapped_mesh_free(&mesh);
}

static void t_determinism(void)
{
    pw_buf a, b, c;
    pastes_text(3, &a);
    pastes_text(3, &b);
    pastes_text(4, &c);
    CHECK(a.size > 0 && a.size == b.size && !memcmp(a.data, b.data, a.size));
    CHECK(a.size != c.size || memcmp(a.data, c.data, a.size));
    free(a.data), free(b.data), free(c.data);
}

/* Written, read back and written again: the same bytes; and the read
 * texture renders the same picture. */
static void t_pastes_roundtrip(void)
{
    lapped_options o = lapped_default_options();
    lapped_render_options ro;
    lapped_mesh mesh;
    lapped_image patch, p1, p2;
    lapped_texture t, back;
    lapped_source src = patches_of(&patch, 1);
    lapped_error err;
    pw_buf a, b;
    memset(&a, 0, sizeof a);
    memset(&b, 0, sizeof b);
    memset(&ro, 0, sizeof ro);
    ro.width = 96;
    ro.height = 72;
    o.scale = 0.5f;
    if (!create("torus", "stripes", &o, &mesh, &patch, &t)) return;
    REQUIRE(lapped_write_pastes(&t, buf_sink, &a, &err) == LAPPED_OK);
    REQUIRE(lapped_read_pastes(a.data, a.size, "x.pastes", &o, &back, &err) == LAPPED_OK);
    REQUIRE(lapped_write_pastes(&back, buf_sink, &b, &err) == LAPPED_OK);
    CHECK(a.size == b.size && !memcmp(a.data, b.data, a.size));
    REQUIRE(lapped_render(&mesh, &t, &src, &ro, &p1, &err) == LAPPED_OK);
    REQUIRE(lapped_render(&mesh, &back, &src, &ro, &p2, &err) == LAPPED_OK);
    CHECK(!memcmp(p1.pixels, p2.pixels, sizeof(float) * 96 * 72 * 3));
    lapped_image_free(&p1);
    lapped_image_free(&p2);
    lapped_texture_free(&back);
    lapped_texture_free(&t);
    lapped_image_free(&patch);
    lapped_mesh_free(&mesh);
    free(a.data), free(b.data);
}

static void t_pastes_malformed(void)
{
    static const char *bad[] = {
        "",
        "lapped-pastes 2\n",
        "lapped-pastes 1\npatches 1\npatch 0 64 64\npastes 1\npaste 0 1\n0 0 0 1 0 0\n",
        "lapped-pastes 1\npatches 1\npatch 0 64 64\npastes 1\npaste 3 1\n0 0 0 1 0 0 1\n",
        "lapped-pastes 1\npatches 1\npatch 0 64 64\npastes 1\npaste 0 1\n0 0 0 1 0 nan 1\n",
        "lapped-pastes 1\npatches 1\npatch 0 64 64\npastes 2147483647\n",
        "lapped-pastes 1\npatches 1\npatch 0 64 64\npastes 1\npaste 0 99999999\n0 0 0 1 0 0 1\n",
        "lapped-pastes 1\npatches 1\npatch 0 64 64\npastes 0\nextra\n",
    };
    lapped_texture t;
    lapped_error err;
    size_t k;
    for (k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        lapped_result r = lapped_read_pastes(bad[k], strlen(bad[k]), "bad.pastes", NULL, &t, &err);
        CHECKF(r != LAPPED_OK, "case %d was accepted", (int)k);
        CHECKF(strstr(err.message, "bad.pastes") != NULL, "case %d: %s", (int)k, err.message);
    }
}

/* Constraint files: the documented keyword lines (after a UTF-8
 * byte-order mark), then malformed lines, each refused with the file name
 * and line. "orient 0 1e39 0 0" is finite as a double but not as a float
 * (fuzz_lapped_files found it accepted). */
static void t_constraints_file(void)
{
    static const char good[] = "\xEF\xBB\xBF# orient face dx dy dz [scale [radius [weight]]]\n"
                               "orient 3 0 1 0\n"
                               "\n"
                               "  orient 7 1 0 0 0.5 2 0.25   # a comment\n";
    static const char *bad[] = {
        "", "# only a comment\n", "orient 3 0 1\n", "orient 3 0 1 0 1 1 1 1\n", "orient -1 0 1 0\n",
        "orient x 0 1 0\n", "orient 3 nan 1 0\n", "orient 3 0 inf 0\n", "orient 0 1e39 0 0\n",
        "orient 0 0 1 0 -1e300\n", "orient\n", "x 0 1 0\n",
    };
    static const char kw[] = "orient 1 0 1 0\nscale 2 0.5\n";
    lapped_constraints c;
    lapped_error err;
    size_t k;
    REQUIRE(lapped_read_constraints(good, sizeof good - 1, "good.txt", NULL, &c, &err) == LAPPED_OK);
    CHECKF(err.message[0] == 0, "a warning for keyword lines: %s", err.message);
    CHECK_EQ_INT(c.count, 2);
    CHECK(c.items[0].face == 3 && c.items[0].direction[1] == 1.0f && c.items[0].scale == 0.0f &&
          c.items[0].weight == 0.0f);
    CHECK(c.items[1].face == 7 && c.items[1].scale == 0.5f && c.items[1].radius == 2.0f && c.items[1].weight == 0.25f);
    lapped_constraints_free(&c);
    CHECK(c.count == 0 && c.items == NULL);
    lapped_constraints_free(&c); /* safe on a freed struct, and on NULL */
    lapped_constraints_free(NULL);
    for (k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        lapped_result r = lapped_read_constraints(bad[k], strlen(bad[k]), "bad.txt", NULL, &c, &err);
        CHECKF(r != LAPPED_OK, "case %d (%s) was accepted", (int)k, bad[k]);
        CHECKF(strstr(err.message, k < 2 ? "bad.txt: no constraints" : "bad.txt:1:") != NULL, "case %d: %s", (int)k,
               err.message);
        CHECK(c.count == 0 && c.items == NULL);
    }
    /* an unknown keyword names itself and its line */
    REQUIRE(lapped_read_constraints(kw, strlen(kw), "kw.txt", NULL, &c, &err) == LAPPED_ERR_PARSE);
    CHECKF(strstr(err.message, "kw.txt:2:") && strstr(err.message, "unknown keyword 'scale'"), "%s", err.message);
}

/* The old positional lines (no keyword) are still read, with one warning
 * naming the first of them; the call succeeds (rule C1). */
static void t_constraints_positional(void)
{
    static const char old[] = "# the format before 0.9\n"
                              "orient 1 0 1 0\n"
                              "3 0 1 0\n"
                              "7 1 0 0 0.5 2 0.25\n";
    lapped_constraints c;
    lapped_error err;
    REQUIRE(lapped_read_constraints(old, sizeof old - 1, "old.txt", NULL, &c, &err) == LAPPED_OK);
    CHECK_EQ_INT(err.code, LAPPED_OK);
    CHECKF(!strcmp(err.message, "old.txt: line 3: positional constraint lines are deprecated; write 'orient F dx "
                   "dy dz ...'"), "%s", err.message);
    CHECK_EQ_INT(c.count, 3);
    CHECK(c.items[1].face == 3 && c.items[1].direction[1] == 1.0f);
    CHECK(c.items[2].face == 7 && c.items[2].scale == 0.5f && c.items[2].radius == 2.0f && c.items[2].weight == 0.25f);
    lapped_constraints_free(&c);
}

/* ---- bad input ---------------------------------------------------------------------- */

static lapped_result create_text(const char *obj, const lapped_image *patch, const lapped_options *o,
                                 lapped_error *err)
{
    lapped_mesh mesh;
    lapped_texture t;
    lapped_source src = patches_of(patch, 1);
    lapped_result r = lapped_read_mesh(obj, strlen(obj), "bad.obj", o, &mesh, err);
    if (r != LAPPED_OK) return r;
    r = lapped_create(&mesh, &src, o, &t, err);
    lapped_texture_free(&t);
    lapped_mesh_free(&mesh);
    return r;
}

static void t_bad_input(void)
{
    lapped_options o = lapped_default_options();
    lapped_image patch, clear;
    lapped_source src = patches_of(&patch, 1), clear_src = patches_of(&clear, 1);
    lapped_mesh sphere;
    lapped_texture t;
    lapped_error err;
    size_t k;
    if (!make_patch("dots", 32, &o, &patch)) return;
    /* three triangles on one edge */
    CHECK_EQ_INT(create_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n",
                             &patch, &o, &err), LAPPED_ERR_TOPOLOGY);
    /* only zero-area triangles (one beside others is covered by their pastes: test_lapped_degenerate) */
    CHECK_EQ_INT(create_text("v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nf 1 2 3\nf 3 2 4\n", &patch, &o, &err),
                 LAPPED_ERR_DEGENERATE);
    CHECKF(strstr(err.message, "zero area") != NULL, "%s", err.message);
    REQUIRE(lapped_builtin_mesh("sphere", &o, &sphere, &err) == LAPPED_OK);
    /* a fully transparent patch */
    clear = patch;
    clear.pixels = (float *)calloc((size_t)patch.width * patch.height * 4, sizeof(float));
    CHECK_EQ_INT(lapped_create(&sphere, &clear_src, &o, &t, &err), LAPPED_ERR_INVALID);
    CHECKF(strstr(err.message, "transparent") != NULL, "%s", err.message);
    free(clear.pixels);
    /* absurd scales: refused up front, no hang */
    o.scale = 1e-4f;
    CHECK_EQ_INT(lapped_create(&sphere, &src, &o, &t, &err), LAPPED_ERR_LIMIT);
    CHECKF(strstr(err.message, "pastes") != NULL, "%s", err.message);
    o.scale = 1e4f;
    CHECK_EQ_INT(lapped_create(&sphere, &src, &o, &t, &err), LAPPED_ERR_INVALID);
    o.scale = -1.0f;
    CHECK_EQ_INT(lapped_create(&sphere, &src, &o, &t, &err), LAPPED_ERR_INVALID);
    o.scale = 0.5f;
    {   /* one tiny vector in a FACES field: under the paste estimate, refused by name (a fuzzer's find) */
        lapped_field fld;
        lapped_options fo = o;
        int k3;
        REQUIRE(lapped_compute_field(&sphere, &o, &fld, &err) == LAPPED_OK);
        fo.field = LAPPED_FIELD_FACES;
        fo.face_t = fld.t;
        fo.face_s = fld.s;
        CHECK_EQ_INT(lapped_create(&sphere, &src, &fo, &t, &err), LAPPED_OK);
        lapped_texture_free(&t);
        for (k3 = 0; k3 < 3; k3++) fld.t[3 * 7 + k3] *= 1e-7f, fld.s[3 * 7 + k3] *= 1e-7f;
        CHECK_EQ_INT(lapped_create(&sphere, &src, &fo, &t, &err), LAPPED_ERR_INVALID);
        CHECKF(strstr(err.message, "triangle 7") && strstr(err.message, "1e-5"), "%s", err.message);
        lapped_field_free(&fld);
    }
    /* patches that are not RGBA, and no patches */
    clear = patch;
    clear.channels = 3;
    CHECK_EQ_INT(lapped_create(&sphere, &clear_src, &o, &t, &err), LAPPED_ERR_INVALID);
    src.npatches = 0;
    CHECK_EQ_INT(lapped_create(&sphere, &src, &o, &t, &err), LAPPED_ERR_INVALID);
    CHECK_EQ_INT(lapped_create(&sphere, NULL, &o, &t, &err), LAPPED_ERR_INVALID);
    CHECKF(strstr(err.message, "no source") != NULL, "%s", err.message);
    for (k = 0; k < 1; k++) CHECK(t.pastes == NULL);
    lapped_mesh_free(&sphere);
    lapped_image_free(&patch);
}

/* A run that cancels from its progress callback stops with CANCELLED. */
static int cancel_half(void *user, float done, const char *stage)
{
    (void)stage;
    ++*(int *)user;
    return done > 0.5f;
}

static void t_cancel(void)
{
    lapped_options o = lapped_default_options();
    lapped_mesh mesh;
    lapped_image patch;
    lapped_source src = patches_of(&patch, 1);
    lapped_texture t;
    lapped_error err;
    int calls = 0;
    o.progress = cancel_half;
    o.progress_user = &calls;
    o.scale = 0.3f;
    REQUIRE(lapped_builtin_mesh("sphere", &o, &mesh, &err) == LAPPED_OK);
    if (make_patch("dots", 32, &o, &patch)) {
        CHECK_EQ_INT(lapped_create(&mesh, &src, &o, &t, &err), LAPPED_ERR_CANCELLED);
        CHECK(calls > 1 && t.pastes == NULL);
        lapped_image_free(&patch);
    }
    lapped_mesh_free(&mesh);
}

/* ---- real data ---------------------------------------------------------------------------- */

/* A CGAL mesh covered with a GIMP pattern: full coverage at dense points. */
static void real_case(const char *file, const char *texture, int mode)
{
    const char *mpath = pwt_data(file), *tpath;
    char rel[128];
    lapped_options o = lapped_default_options();
    lapped_mesh mesh;
    lapped_image tex, patch;
    lapped_source src = patches_of(&patch, 1);
    lapped_texture t;
    lapped_error err;
    double below;
    float worst;
    snprintf(rel, sizeof rel, "textures/%s.ppm", texture);
    if (!mpath || !(tpath = pwt_data(rel))) return;
    o.field = mode;
    REQUIRE(lapped_load_mesh(mpath, &o, &mesh, &err) == LAPPED_OK);
    REQUIRE(lapped_load_image(tpath, &o, &tex, &err) == LAPPED_OK);
    REQUIRE(lapped_make_patch(&tex, NULL, &o, &patch, &err) == LAPPED_OK);
    if (lapped_create(&mesh, &src, &o, &t, &err) != LAPPED_OK) {
        CHECKF(0, "%s: %s", file, err.message);
    } else {
        worst = dense_coverage(&t, &patch, 0.99f, &below);
        pwt_info("%s with %s: %d triangles, %d pastes, %.2f layers (%.2f before), %d hard edges, "
                 "least opacity %.4f", file, texture, t.ntris, t.npastes, t.layers, t.layers_before,
                 t.hard_edges, worst);
        CHECKF(worst >= 0.99f, "a point only reaches opacity %.4f", worst);
        lapped_texture_free(&t);
    }
    lapped_image_free(&patch);
    lapped_image_free(&tex);
    lapped_mesh_free(&mesh);
}

/* The 1-to-4 midpoint subdivision of triangle mesh m (the same surface):
 * the midpoint of edge (a, b) is found by its key a * nverts + b, a < b,
 * in the sorted list of every edge's key. */
static int cmp_key(const void *a, const void *b)
{
    long long x = *(const long long *)a, y = *(const long long *)b;
    return x < y ? -1 : x > y;
}

static int subdivide(const lapped_mesh *m, lapped_mesh *out)
{
    int nf = m->nfaces, nv = m->nverts, f, k, ne = 0, i;
    long long *key = (long long *)malloc(sizeof(long long) * 3 * (size_t)nf);
    memset(out, 0, sizeof *out);
    for (f = 0; f < nf; f++)
        if (m->face_start[f + 1] - m->face_start[f] != 3) return free(key), 0;
    for (i = 0; i < 3 * nf; i++) {
        int a = m->face_verts[i], b = m->face_verts[i % 3 == 2 ? i - 2 : i + 1];
        key[i] = a < b ? (long long)a * nv + b : (long long)b * nv + a;
    }
    qsort(key, 3 * (size_t)nf, sizeof *key, cmp_key);
    for (i = 0; i < 3 * nf; i++)
        if (i == 0 || key[i] != key[i - 1]) key[ne++] = key[i];
    out->nverts = nv + ne;
    out->nfaces = 4 * nf;
    out->positions = (float *)malloc(sizeof(float) * 3 * (size_t)out->nverts);
    out->face_start = (int *)malloc(sizeof(int) * ((size_t)out->nfaces + 1));
    out->face_verts = (int *)malloc(sizeof(int) * 3 * (size_t)out->nfaces);
    memcpy(out->positions, m->positions, sizeof(float) * 3 * (size_t)nv);
    for (i = 0; i < ne; i++)
        for (k = 0; k < 3; k++)
            out->positions[3 * (nv + i) + k] =
                0.5f * (m->positions[3 * (key[i] / nv) + k] + m->positions[3 * (key[i] % nv) + k]);
    for (f = 0; f < nf; f++) {
        const int *t = m->face_verts + 3 * f;
        int mid[3], q[12];
        for (k = 0; k < 3; k++) {
            int a = t[k], b = t[(k + 1) % 3];
            long long want = a < b ? (long long)a * nv + b : (long long)b * nv + a;
            mid[k] = nv + (int)((long long *)bsearch(&want, key, (size_t)ne, sizeof *key, cmp_key) - key);
        }
        q[0] = t[0], q[1] = mid[0], q[2] = mid[2];
        q[3] = t[1], q[4] = mid[1], q[5] = mid[0];
        q[6] = t[2], q[7] = mid[2], q[8] = mid[1];
        q[9] = mid[0], q[10] = mid[1], q[11] = mid[2];
        memcpy(out->face_verts + 12 * f, q, sizeof q);
    }
    for (f = 0; f <= out->nfaces; f++) out->face_start[f] = 3 * f;
    free(key);
    return 1;
}

/* Issue 21: a paste's surface is set by the scale and the patch, not by the
 * mesh's resolution. The pastes' triangles before hiding, per mesh
 * triangle, on a CGAL mesh and on its 1-to-4 subdivision (the same surface,
 * so the same area per layer) must stay within 15%. Before growth refused
 * texture-space folds (lapped__folds) the finer meshes' pastes wrapped
 * over their texture: elephant 5.69 -> 6.44 (x1.13), camel 6.96 -> 10.16
 * (x1.46, which failed); with it 5.05 -> 4.45 and 5.43 -> 5.23. */
static void resolution_case(const char *file)
{
    const char *mpath = pwt_data(file);
    lapped_options o = lapped_default_options();
    lapped_mesh mesh[2];
    lapped_image patch;
    lapped_source src = patches_of(&patch, 1);
    lapped_texture t;
    lapped_error err;
    double before[2] = {0.0, 0.0};
    int k;
    if (!mpath) return;
    REQUIRE(lapped_load_mesh(mpath, &o, &mesh[0], &err) == LAPPED_OK);
    REQUIRE(subdivide(&mesh[0], &mesh[1]));
    if (make_patch("scales", 128, &o, &patch)) {
        for (k = 0; k < 2; k++) {
            if (lapped_create(&mesh[k], &src, &o, &t, &err) != LAPPED_OK) {
                CHECKF(0, "%s: %s", file, err.message);
                continue;
            }
            before[k] = t.layers_before;
            pwt_info("%s%s: %d triangles, %d pastes, %.2f layers before hiding, %.2f after", file,
                     k ? " subdivided" : "", t.ntris, t.npastes, t.layers_before, t.layers);
            lapped_texture_free(&t);
        }
        CHECKF(before[1] <= 1.15 * before[0], "%s: the pastes hold %.2f times the mesh, %.2f on the subdivision",
               file, before[0], before[1]);
        lapped_image_free(&patch);
    }
    free(mesh[1].positions);
    free(mesh[1].face_start);
    free(mesh[1].face_verts);
    lapped_mesh_free(&mesh[0]);
}

static void t_resolution(void)
{
    resolution_case("meshes/elephant.off");
    resolution_case("meshes/camel.off");
}

static void t_real_elephant(void) { real_case("meshes/elephant.off", "leopard", LAPPED_FIELD_UP); }
static void t_real_cow(void) { real_case("meshes/cow.off", "burlap", LAPPED_FIELD_ISOTROPIC); }
static void t_real_mushroom(void) { real_case("meshes/mushroom.off", "marble3", LAPPED_FIELD_UP); }
static void t_real_knot(void) { real_case("meshes/knot.off", "java", LAPPED_FIELD_CURVATURE); }
static void t_real_eight(void) { real_case("meshes/eight.off", "pine", LAPPED_FIELD_UP); }
static void t_real_pig(void) { real_case("meshes/pig.off", "leopard", LAPPED_FIELD_ISOTROPIC); }
static void t_real_boundary(void) { real_case("meshes/cube-ouvert.off", "burlap", LAPPED_FIELD_UP); }

static const pwt_case cases[] = {
    {"lapped/coverage_sphere_up", t_coverage_sphere_up},
    {"lapped/coverage_torus_isotropic", t_coverage_torus_isotropic},
    {"lapped/coverage_bumpy_curvature", t_coverage_bumpy_curvature},
    {"lapped/coverage_disc_boundary", t_coverage_disc_boundary},
    {"lapped/alignment", t_alignment},
    {"lapped/disc_topology", t_disc_topology},
    {"lapped/determinism", t_determinism},
    {"lapped/pastes_roundtrip", t_pastes_roundtrip},
    {"lapped/pastes_malformed", t_pastes_malformed},
    {"lapped/constraints_file", t_constraints_file},
    {"lapped/constraints_positional", t_constraints_positional},
    {"lapped/bad_input", t_bad_input},
    {"lapped/cancel", t_cancel},
    {"lapped/real_elephant", t_real_elephant},
    {"lapped/real_cow", t_real_cow},
    {"lapped/real_mushroom", t_real_mushroom},
    {"lapped/real_knot", t_real_knot},
    {"lapped/real_eight", t_real_eight},
    {"lapped/real_pig", t_real_pig},
    {"lapped/real_boundary", t_real_boundary},
    {"lapped/resolution", t_resolution},
};
PWT_MAIN(cases)
