/* Tests of lst.h's files and failure paths: the model file round trip,
 * the constraint files, tetrahedral meshes through the lst API (TetGen
 * .node/.ele round trip, TetGen's own output filled when tetgen is
 * installed), real meshes (CGAL's elephant, cow, mushroom, pig, knot;
 * skipped when absent), bad input of every kind with clear errors, and
 * allocation failure at every allocation of a fill, a cut, the renderers
 * and the readers (NOMEM, nothing leaked). */
#define _POSIX_C_SOURCE 200809L
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

static int small_tets(int n, lst_tetmesh *m)
{
    lst_options o = lst_default_options();
    lst_mesh s;
    lst_error err;
    int ok;
    o.tet.target_tets = n, o.tet.uniform = 1; /* a small uniform fill: stuffing tests cover the graded one */
    if (lst_builtin_mesh("sphere", &o, &s, &err)) return 0;
    ok = lst_tetrahedralize(&s, &o, m, NULL, &err) == LST_OK && !err.message[0]; /* a clean surface: no warning */
    lst_mesh_free(&s);
    return ok;
}

static int small_model(int type, int n, lst_tetmesh *m, lst_volume *ex, lst_model *model)
{
    lst_options o = lst_default_options();
    lst_error err;
    o.type = type;
    if (!small_tets(n, m) || lst_builtin_exemplar(type == LST_TYPE_2B ? "rings" : "spots", 16, &o, ex, NULL, &err)) return 0;
    return create_model(m, NULL, ex, NULL, &o, model, &err) == LST_OK;
}

/* Model file: write -> read gives the same mesh and pastes (texture
 * coordinates exact), and with the texture and masks given back the same
 * colours everywhere. */
static void t_model_roundtrip(void)
{
    lst_tetmesh m;
    lst_volume ex;
    lst_masks masks;
    lst_model a, b;
    lst_error err;
    pw_buf buf, buf2;
    float pts[3 * 50], c1[4 * 50], c2[4 * 50];
    pw_rng r = pw_rng_seed(1, 1);
    int k;
    memset(&buf, 0, sizeof buf), memset(&buf2, 0, sizeof buf2);
    REQUIRE(small_model(LST_TYPE_2B, 1500, &m, &ex, &a));
    REQUIRE(lst_write_model(&a, pw_buf_write, &buf, &err) == LST_OK);
    REQUIRE(lst_read_model(buf.data, buf.size, "m.lst", NULL, &b, &err) == LST_OK);
    CHECK_EQ_INT(b.mesh.ntets, a.mesh.ntets);
    CHECK_EQ_INT(b.npastes, a.npastes);
    CHECK_EQ_INT(b.masks.count, 3);
    CHECK(!memcmp(a.mesh.positions, b.mesh.positions, sizeof(float) * 3 * (size_t)a.mesh.nverts));
    REQUIRE(lst_write_model(&b, pw_buf_write, &buf2, &err) == LST_OK);
    CHECK(buf.size == buf2.size && !memcmp(buf.data, buf2.data, buf.size));
    {
        lst_options o = lst_default_options();
        o.type = LST_TYPE_2B;
        REQUIRE(lst_make_masks(&ex, &o, &masks, &err) == LST_OK);
    }
    lst_masks_free(&b.masks);
    b.masks = masks;
    lst_volume_free(&b.texture);
    b.texture = a.texture;
    for (k = 0; k < 150; k++) pts[k] = (float)(1.6 * pw_rng_double(&r) - 0.8);
    CHECK(lst_eval(&b, pts, 50, c2, NULL, &err) == LST_OK);
    REQUIRE(lst_eval(&a, pts, 50, c1, NULL, &err) == LST_OK);
    CHECK(!memcmp(c1, c2, sizeof c1));
    memset(&b.texture, 0, sizeof b.texture);
    pwt_info("model file: %lu bytes for %d tetrahedra and %d pastes", (unsigned long)buf.size, a.mesh.ntets, a.npastes);
    free(buf.data), free(buf2.data);
    lst_model_free(&a), lst_model_free(&b);
    lst_volume_free(&ex);
    lst_tetmesh_free(&m);
}

/* A cut model is written as cut: only the visible tetrahedra. */
static void t_model_cut_file(void)
{
    lst_tetmesh m;
    lst_volume ex;
    lst_model a, b;
    lst_error err;
    pw_buf buf;
    float plane[4] = {0, 0, 1, 0};
    int t, vis = 0;
    memset(&buf, 0, sizeof buf);
    REQUIRE(small_model(LST_TYPE_0, 1200, &m, &ex, &a));
    REQUIRE(lst_cut_plane(&a, plane, &err) == LST_OK);
    for (t = 0; t < a.mesh.ntets; t++) vis += !a.removed[t];
    REQUIRE(lst_write_model(&a, pw_buf_write, &buf, &err) == LST_OK);
    REQUIRE(lst_read_model(buf.data, buf.size, "cut.lst", NULL, &b, &err) == LST_OK);
    CHECK_EQ_INT(b.mesh.ntets, vis);
    free(buf.data);
    lst_model_free(&a), lst_model_free(&b), lst_volume_free(&ex), lst_tetmesh_free(&m);
}

static void t_model_bad(void)
{
    static const char *const cases[][2] = {
        {"", "expected 'lst'"},
        {"lst 2\n", "outside"},
        {"lst 1\nnodes 4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\ntets 1\n0 1 2 4\n", "node 4 does not exist"},
        {"lst 1\nnodes 4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\ntets 1\n0 2 1 3\n", "negatively oriented"},
        {"lst 1\nnodes 4\n0 0 0\n1 0 0\n0 1 0\n0 0 nan\n", "non-finite"},
        {"lst 1\nnodes 999999\n0 0 0\n", "too short"},
        {"lst 1\nnodes 4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\ntets 1\n0 1 2 3\nexemplars 1\nexemplar 0 8 8 8\npastes 1\npaste 1 1\n", "uses exemplar 1"},
        {"lst 1\nnodes 4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\ntets 1\n0 1 2 3\nexemplars 1\nexemplar 0 8 8 8\npastes 1\npaste 0 1\n"
         "1 0 0 0 1 0 0 0 1 0 0 0 1\n", "tetrahedron 1 does not exist"},
        {"lst 1\nnodes 4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\ntets 1\n0 1 2 3\nexemplars 1\nexemplar 0 8 8 8\npastes 1\npaste 0 1\n"
         "0 0 0 0 1 0 0 0 1 0 0 0\n", "missing"},
        {"lst 1\nnodes 4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\ntets 1\n0 1 2 3\nexemplars 1\nexemplar 0 8 8 8\npastes 0\nextra\n", "unexpected text"},
        {"lst 1\nnodes 4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\ntets 1\n0 1 2 3\nexemplars 0\n", "exemplars"},
    };
    size_t k;
    for (k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        lst_model m;
        lst_error err;
        lst_result r = lst_read_model(cases[k][0], strlen(cases[k][0]), "bad.lst", NULL, &m, &err);
        CHECKF(r != LST_OK && strstr(err.message, cases[k][1]) && !m.mesh.tets && !m.pastes, "case %d: '%s' (expected '%s')",
               (int)k, err.message, cases[k][1]);
    }
}

/* The constraint file: every line form, comments, strokes sampled; every
 * error names the line; the old ambiguous 'stroke' names the two new
 * keywords. */
static void t_constraint_files(void)
{
    static const char file[] = "\357\273\277# depth\nface 3 0\nfill 0 0.5 45\npoint 0 0 0 1 # the centre\n\n"
                               "depth-stroke 1 0 0 -1 0 0 1\ndir 0 0 0 0 0 1\nscale 0.5 0 0 0.25\n"
                               "dir-stroke 0 0 -1 0 0 0 0 0 1\n";
    static const char *const bad[][2] = {
        {"face 3\n", "c:1: expected 'face F D'"}, {"fill 1 2\n", "outside [0, 1]"}, {"point 0 0 0 x\n", "malformed"},
        {"hello 1\n", "c:1: unknown constraint 'hello'"}, {"face -1 0\n", "not a triangle"}, {"\n# none\n", "no constraints"},
        {"face 0 0\ndepth-stroke 0.5 1 2\n", "c:2: expected"}, {"dir 0 0 0 0 0 0\n", "a zero direction"},
        {"scale 0 0 0 -1\n", "not positive"}, {"dir-stroke 0 0 0\n", "expected"}, {"dir 1 2 3\n", "c:1: expected"},
        {"dir 0 0 0 1 0 inf\n", "not finite"}, {"face 0 0\nstroke 0 0 0 1 1 1\n", "c:2: 'stroke' is ambiguous"}};
    lst_constraints c;
    lst_error err;
    int k;
    REQUIRE(lst_read_constraints(file, sizeof file - 1, "c", NULL, &c, &err) == LST_OK);
    CHECK_EQ_INT(c.count, 3 + 9 + 2 + 16);
    CHECK(c.items[0].kind == LST_CONSTRAINT_DEPTH_FACE && c.items[0].face == 3 && c.items[0].value == 0.0f);
    CHECK(c.items[1].kind == LST_CONSTRAINT_DEPTH_FILL && c.items[1].crease == 45.0f && c.items[1].value == 0.5f);
    CHECK(c.items[2].kind == LST_CONSTRAINT_DEPTH_POINT && c.items[2].value == 1.0f);
    CHECK(c.items[3].point[2] == -1.0f && c.items[11].point[2] == 1.0f && c.items[11].kind == LST_CONSTRAINT_DEPTH_POINT);
    CHECK(c.items[12].kind == LST_CONSTRAINT_DIRECTION && c.items[12].direction[2] == 1.0f);
    CHECK(c.items[13].kind == LST_CONSTRAINT_SCALE && c.items[13].value == 0.25f);
    CHECK(c.items[14].kind == LST_CONSTRAINT_DIRECTION && c.items[14].direction[2] == 1.0f);
    CHECK(c.items[29].kind == LST_CONSTRAINT_DIRECTION);
    lst_constraints_free(&c);
    CHECK(c.count == 0 && c.items == NULL);
    lst_constraints_free(&c);
    for (k = 0; k < (int)(sizeof bad / sizeof bad[0]); k++)
        CHECKF(lst_read_constraints(bad[k][0], strlen(bad[k][0]), "c", NULL, &c, &err) != LST_OK &&
                   strstr(err.message, bad[k][1]) && !c.items && !c.count,
               "case %d: '%s'", k, err.message);
    CHECK(lst_read_constraints(bad[12][0], strlen(bad[12][0]), "c", NULL, &c, &err) == LST_ERR_PARSE &&
          strstr(err.message, "depth-stroke") && strstr(err.message, "dir-stroke"));
}

/* .node/.ele and .mesh through the lst API: exact round trips. */
static void t_tet_files(void)
{
    lst_tetmesh m, b;
    pw_buf n, e;
    lst_error err;
    memset(&n, 0, sizeof n), memset(&e, 0, sizeof e);
    REQUIRE(small_tets(800, &m));
    REQUIRE(lst_write_tetgen(&m, pw_buf_write, &n, pw_buf_write, &e, &err) == LST_OK);
    REQUIRE(lst_read_tetgen(n.data, n.size, e.data, e.size, "s", NULL, &b, &err) == LST_OK);
    CHECK(b.ntets == m.ntets && !memcmp(b.tets, m.tets, sizeof(int) * 4 * (size_t)m.ntets));
    CHECK(!memcmp(b.positions, m.positions, sizeof(float) * 3 * (size_t)m.nverts));
    lst_tetmesh_free(&b);
    free(n.data);
    memset(&n, 0, sizeof n);
    REQUIRE(lst_write_medit(&m, pw_buf_write, &n, &err) == LST_OK);
    REQUIRE(lst_read_medit(n.data, n.size, "s.mesh", NULL, &b, &err) == LST_OK);
    CHECK(b.ntets == m.ntets && !memcmp(b.tets, m.tets, sizeof(int) * 4 * (size_t)m.ntets));
    lst_tetmesh_free(&b);
    free(n.data), free(e.data);
    lst_tetmesh_free(&m);
}

/* A tetrahedral mesh's boundary written as OBJ reads back the same
 * (vertices and faces), from memory and through a file; an image written
 * as PNG and as PPM reads back the same; a file of no image format is
 * refused with its name. */
static void t_obj_image_files(void)
{
    lst_tetmesh m;
    lst_mesh s, b;
    lst_image img, back;
    pw_buf buf;
    lst_error err;
    const char *obj = pwt_tmp("lst_obj", 0, ".obj"), *ppm = pwt_tmp("lst_img", 0, ".ppm");
    int k;
    memset(&buf, 0, sizeof buf);
    REQUIRE(small_tets(400, &m));
    REQUIRE(lst_tetmesh_surface(&m, NULL, &s, &err) == LST_OK);
    REQUIRE(lst_write_obj(&s, pw_buf_write, &buf, &err) == LST_OK);
    REQUIRE(lst_read_mesh(buf.data, buf.size, "b.obj", NULL, &b, &err) == LST_OK);
    CHECK(b.nverts == s.nverts && b.nfaces == s.nfaces);
    CHECK(!memcmp(b.positions, s.positions, sizeof(float) * 3 * (size_t)s.nverts));
    CHECK(!memcmp(b.face_start, s.face_start, sizeof(int) * ((size_t)s.nfaces + 1)));
    CHECK(!memcmp(b.face_verts, s.face_verts, sizeof(int) * (size_t)s.face_start[s.nfaces]));
    lst_mesh_free(&b);
    REQUIRE(lst_save_obj(obj, &s, &err) == LST_OK);
    REQUIRE(lst_load_mesh(obj, NULL, &b, &err) == LST_OK);
    CHECK(b.nfaces == s.nfaces && !memcmp(b.face_verts, s.face_verts, sizeof(int) * (size_t)s.face_start[s.nfaces]));
    CHECK(lst_write_obj(NULL, pw_buf_write, &buf, &err) == LST_ERR_INVALID && strstr(err.message, "lst_write_obj"));
    lst_mesh_free(&b);
    memset(&img, 0, sizeof img);
    img.width = 4, img.height = 3, img.channels = 3;
    img.pixels = (float *)malloc(sizeof(float) * 36);
    for (k = 0; k < 36; k++) img.pixels[k] = (float)(7 * k) / 255.0f;
    free(buf.data);
    memset(&buf, 0, sizeof buf);
    REQUIRE(lst_write_image(&img, "png", pw_buf_write, &buf, &err) == LST_OK);
    REQUIRE(lst_read_image(buf.data, buf.size, "i.png", NULL, &back, &err) == LST_OK);
    CHECK(back.width == 4 && back.height == 3 && back.channels == 3);
    for (k = 0; k < 36; k++) CHECK_NEAR(back.pixels[k], img.pixels[k], 1e-6);
    lst_image_free(&back);
    REQUIRE(lst_save_image(ppm, &img, &err) == LST_OK);
    REQUIRE(lst_load_image(ppm, NULL, &back, &err) == LST_OK);
    CHECK(back.width == 4 && back.height == 3 && back.channels == 3);
    for (k = 0; k < 36; k++) CHECK_NEAR(back.pixels[k], img.pixels[k], 1e-6);
    lst_image_free(&back);
    CHECK(lst_read_image("hello", 5, "x.img", NULL, &back, &err) == LST_ERR_UNSUPPORTED && strstr(err.message, "x.img") &&
          !back.pixels);
    free(img.pixels), free(buf.data);
    remove(obj), remove(ppm);
    lst_mesh_free(&s), lst_tetmesh_free(&m);
}

/* TetGen's own tetrahedralization of the built-in sphere loads and fills. */
static void t_tetgen_fill(void)
{
    lst_options o = lst_default_options();
    lst_mesh s;
    lst_tetmesh m;
    lst_volume ex;
    lst_model model;
    lst_error err;
    FILE *f;
    char cmd[512];
    const char *off = pwt_tmp("lst_tg", 0, ".off"), *node = pwt_tmp("lst_tg", 0, ".1.node");
    int v, t;
    double lo, hi;
    if (system("command -v tetgen >/dev/null 2>&1") != 0) {
        pwt_skip("tetgen is not installed");
        return;
    }
    REQUIRE(lst_builtin_mesh("sphere", &o, &s, &err) == LST_OK);
    REQUIRE((f = fopen(off, "w")) != NULL);
    fprintf(f, "OFF\n%d %d 0\n", s.nverts, s.nfaces);
    for (v = 0; v < s.nverts; v++) fprintf(f, "%.9g %.9g %.9g\n", s.positions[3 * v], s.positions[3 * v + 1], s.positions[3 * v + 2]);
    for (t = 0; t < s.nfaces; t++) fprintf(f, "3 %d %d %d\n", s.face_verts[3 * t], s.face_verts[3 * t + 1], s.face_verts[3 * t + 2]);
    REQUIRE(fclose(f) == 0);
    snprintf(cmd, sizeof cmd, "cd /tmp && tetgen -pq1.4Q %s >/dev/null 2>&1", off);
    REQUIRE(system(cmd) == 0);
    REQUIRE(lst_load_tetmesh(node, NULL, &m, &err) == LST_OK);
    REQUIRE(lst_tetmesh_check(&m, &lo, &hi, &err) == LST_OK);
    REQUIRE(lst_builtin_exemplar("spots", 16, &o, &ex, NULL, &err) == LST_OK);
    CHECKF(create_model(&m, NULL, &ex, NULL, &o, &model, &err) == LST_OK, "%s", err.message);
    pwt_info("tetgen: %d tetrahedra, dihedral %.1f..%.1f, %d pastes", m.ntets, lo, hi, model.npastes);
    snprintf(cmd, sizeof cmd, "rm -f /tmp/pw_test_lst_tg_%ld_0.*", (long)getpid());
    CHECK(system(cmd) == 0);
    lst_model_free(&model), lst_volume_free(&ex), lst_tetmesh_free(&m), lst_mesh_free(&s);
}

/* CGAL's meshes: the closed ones fill; the open ones (mushroom, pig) are
 * refused with the reason, the self-intersecting cow refused when strict
 * and filled by default (its crossing pairs reported). */
static void t_real_meshes(void)
{
    static const char *const names[5] = {"elephant", "cow", "mushroom", "pig", "knot"};
    static const char *const expect[5] = {NULL, "intersects itself", "not closed", "not closed", NULL};
    int k, found = 0;
    for (k = 0; k < 5; k++) {
        char rel[64];
        const char *path;
        lst_options o = lst_default_options();
        lst_tet_report rep;
        lst_mesh s;
        lst_tetmesh m;
        lst_volume ex;
        lst_model model;
        lst_error err;
        lst_result r;
        snprintf(rel, sizeof rel, "meshes/%s.off", names[k]);
        if (!(path = pwt_data_opt(rel))) continue;
        found++;
        o.tet.target_tets = 2500, o.tet.uniform = 1, o.tet.strict = k == 1;
        REQUIRE(lst_load_mesh(path, &o, &s, &err) == LST_OK);
        r = lst_tetrahedralize(&s, &o, &m, NULL, &err);
        if (expect[k]) {
            CHECKF(r != LST_OK && strstr(err.message, expect[k]), "%s: '%s'", names[k], err.message);
            if (k == 1) { /* the cow, by default */
                o.tet.strict = 0;
                r = lst_tetrahedralize(&s, &o, &m, &rep, &err);
                CHECKF(r == LST_OK && rep.crossing_pairs > 0 && rep.pieces >= 1 && rep.fit_max > 0.0,
                       "cow: %ld crossing pairs, %d pieces, fit %g", rep.crossing_pairs, rep.pieces, rep.fit_max);
            }
        }
        if (r == LST_OK) {
            double lo, hi;
            o.type = LST_TYPE_1B;
            REQUIRE(lst_tetmesh_check(&m, &lo, &hi, &err) == LST_OK);
            REQUIRE(lst_builtin_exemplar("layers", 16, &o, &ex, NULL, &err) == LST_OK);
            CHECKF(create_model(&m, &s, &ex, NULL, &o, &model, &err) == LST_OK, "%s: %s", names[k], err.message);
            pwt_info("%s: %d tetrahedra (dihedral %.1f..%.1f), %d pastes", names[k], m.ntets, lo, hi, model.npastes);
            CHECK(lo > 10.0);
            lst_model_free(&model), lst_volume_free(&ex), lst_tetmesh_free(&m);
        }
        if (k == 0) { /* the elephant at the defaults: graded, its legs, tusks and trunk kept */
            lst_options d = lst_default_options();
            CHECKF(lst_tetrahedralize(&s, &d, &m, &rep, &err) == LST_OK && rep.fit_max < 0.005 &&
                       rep.pieces == 1 && rep.surface_pieces == 1,
                   "elephant, defaults: %s, fit %g, %d pieces of %d", err.message, rep.fit_max, rep.pieces,
                   rep.surface_pieces);
            pwt_info("elephant at the defaults: %d tetrahedra, boundary within %.2f%% of the diagonal", m.ntets,
                     100.0 * rep.fit_max);
            lst_tetmesh_free(&m);
        }
        lst_mesh_free(&s);
    }
    if (!found) pwt_skip("no CGAL meshes in %s/meshes (run `make data`)", pwt_data_dir());
}

/* ---- bad input ------------------------------------------------------------------------------------ */

static void expect(lst_result got, lst_result want, const lst_error *err, const char *what, const char *text)
{
    CHECKF(got == want && strstr(err->message, text), "%s: code %d '%s' (expected %d, '%s')", what, (int)got, err->message,
           (int)want, text);
}

static void t_bad_create(void)
{
    lst_options o = lst_default_options();
    lst_tetmesh m, bad;
    lst_volume ex, tiny, val;
    lst_model model;
    lst_error err;
    lst_constraint dc;
    REQUIRE(small_tets(400, &m));
    REQUIRE(lst_builtin_exemplar("spots", 16, &o, &ex, &val, &err) == LST_OK);
    expect(create_model(NULL, NULL, &ex, NULL, &o, &model, &err), LST_ERR_DEGENERATE, &err, "NULL mesh", "empty");
    bad = m;
    bad.positions = (float *)malloc(sizeof(float) * 3 * (size_t)m.nverts);
    memcpy(bad.positions, m.positions, sizeof(float) * 3 * (size_t)m.nverts);
    bad.positions[7] = NAN;
    expect(create_model(&bad, NULL, &ex, NULL, &o, &model, &err), LST_ERR_INVALID, &err, "NaN vertex", "vertex 2 is not finite");
    free(bad.positions);
    bad = m;
    bad.tets = (int *)malloc(sizeof(int) * 4 * (size_t)m.ntets);
    memcpy(bad.tets, m.tets, sizeof(int) * 4 * (size_t)m.ntets);
    bad.tets[5] = m.nverts;
    expect(create_model(&bad, NULL, &ex, NULL, &o, &model, &err), LST_ERR_INVALID, &err, "index", "tetrahedron 1 uses vertex");
    memcpy(bad.tets, m.tets, sizeof(int) * 4 * (size_t)m.ntets);
    bad.tets[2] = m.tets[3], bad.tets[3] = m.tets[2];
    expect(create_model(&bad, NULL, &ex, NULL, &o, &model, &err), LST_ERR_DEGENERATE, &err, "flipped", "negatively oriented");
    memcpy(bad.tets, m.tets, sizeof(int) * 4 * (size_t)m.ntets);
    memcpy(bad.tets + 4, bad.tets, 4 * sizeof(int)); /* a tetrahedron twice: its faces in three or more */
    expect(create_model(&bad, NULL, &ex, NULL, &o, &model, &err), LST_ERR_TOPOLOGY, &err, "duplicate", "tetrahedra");
    free(bad.tets);
    o.type = 7;
    expect(create_model(&m, NULL, &ex, NULL, &o, &model, &err), LST_ERR_INVALID, &err, "type", "texture type 7");
    o = lst_default_options(), o.mask_radius = 0.7f;
    expect(create_model(&m, NULL, &ex, NULL, &o, &model, &err), LST_ERR_INVALID, &err, "mask radius", "radius");
    o = lst_default_options(), o.mask = LST_MASK_EXEMPLAR;
    expect(create_model(&m, NULL, &ex, NULL, &o, &model, &err), LST_ERR_INVALID, &err, "exemplar alpha", "alpha");
    o = lst_default_options();
    ex.voxels[10] = NAN;
    expect(create_model(&m, NULL, &ex, NULL, &o, &model, &err), LST_ERR_INVALID, &err, "NaN voxel", "voxel 3 is not a finite");
    ex.voxels[10] = 0.5f;
    tiny = val, tiny.depth = 8;
    expect(create_model(&m, NULL, &ex, &tiny, &o, &model, &err), LST_ERR_INVALID, &err, "values size", "values: 16x16x8");
    memset(&dc, 0, sizeof dc);
    dc.kind = LST_CONSTRAINT_DEPTH_FACE, dc.face = 1000000;
    o.type = LST_TYPE_1B, o.constraints = &dc, o.nconstraints = 1;
    expect(create_model(&m, NULL, &ex, NULL, &o, &model, &err), LST_ERR_INVALID, &err, "depth face", "face 1000000");
    dc.kind = LST_CONSTRAINT_DEPTH_POINT, dc.value = 2.0f;
    expect(create_model(&m, NULL, &ex, NULL, &o, &model, &err), LST_ERR_INVALID, &err, "depth value", "outside [0, 1]");
    o = lst_default_options(), o.type = LST_TYPE_1A;
    memset(&dc, 0, sizeof dc);
    dc.kind = LST_CONSTRAINT_DIRECTION;
    o.constraints = &dc, o.nconstraints = 1;
    expect(create_model(&m, NULL, &ex, NULL, &o, &model, &err), LST_ERR_INVALID, &err, "zero direction", "zero");
    dc.kind = (lst_constraint_kind)9;
    expect(create_model(&m, NULL, &ex, NULL, &o, &model, &err), LST_ERR_INVALID, &err, "kind", "unknown kind 9");
    CHECK(!model.mesh.tets && !model.pastes);
    lst_volume_free(&ex), lst_volume_free(&val), lst_tetmesh_free(&m);
}

static void t_bad_surface(void)
{
    lst_options o = lst_default_options();
    lst_mesh s;
    lst_tetmesh m;
    lst_error err;
    pw_mesh disc;
    pw_err e;
    pw_alloc a;
    memset(&a, 0, sizeof a);
    pw_err_clear(&e);
    REQUIRE(pw_shape_disc(&a, 6, &disc, &e) == PW_OK);
    lst__take_mesh(&disc, &a, &s);
    expect(lst_tetrahedralize(&s, &o, &m, NULL, &err), LST_ERR_TOPOLOGY, &err, "open surface", "not closed");
    s.positions[4] = INFINITY;
    CHECK(lst_tetrahedralize(&s, &o, &m, NULL, &err) == LST_ERR_INVALID);
    lst_mesh_free(&s);
    expect(lst_builtin_mesh("cube", &o, &s, &err), LST_ERR_INVALID, &err, "unknown surface", "unknown built-in surface");
    {
        static const char *const bad[][2] = {
            /* a tetrahedron with one face turned over */
            {"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 3 2 4\n", "orientation"},
            /* two tetrahedra sharing a vertex: a non-manifold vertex */
            {"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv -1 0 0\nv 0 -1 0\nv 0 0 -1\n"
             "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\nf 1 5 6\nf 1 7 5\nf 1 6 7\nf 5 7 6\n", "vertex"},
            /* a face using a vertex twice: skipped (zero area), which leaves a big hole */
            {"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 3\n", "not closed"},
        };
        size_t k;
        for (k = 0; k < sizeof bad / sizeof bad[0]; k++) {
            lst_result r;
            REQUIRE(lst_read_mesh(bad[k][0], strlen(bad[k][0]), "bad.obj", &o, &s, &err) == LST_OK);
            r = lst_tetrahedralize(&s, &o, &m, NULL, &err);
            CHECKF(r != LST_OK && strstr(err.message, bad[k][1]) && !m.tets, "bad surface %d: code %d '%s' (expected '%s')",
                   (int)k, (int)r, err.message, bad[k][1]);
            lst_mesh_free(&s);
        }
    }
    { /* a tetrahedron and a second one through it: filled by default, refused when strict */
        static const char crossing[] =
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 0.2 0.2 -0.5\nv 1.2 0.2 -0.5\nv 0.2 1.2 -0.5\nv 0.2 0.2 0.5\n"
            "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\nf 5 7 6\nf 5 6 8\nf 5 8 7\nf 6 7 8\n";
        lst_options to = lst_default_options();
        lst_tet_report rep;
        to.tet.target_tets = 2000, to.tet.uniform = 1; /* a small uniform fill: stuffing tests cover the graded one */
        REQUIRE(lst_read_mesh(crossing, strlen(crossing), "cross.obj", &o, &s, &err) == LST_OK);
        CHECKF(lst_tetrahedralize(&s, &to, &m, &rep, &err) == LST_OK && rep.crossing_pairs > 0 && rep.pieces == 1,
               "crossing: %s, %ld pairs, %d pieces", err.message, rep.crossing_pairs, rep.pieces);
        CHECKF(strstr(err.message, "crosses itself") && strstr(err.message, "triangle pairs"), "no warning: '%s'", err.message);
        lst_tetmesh_free(&m);
        to.tet.strict = 1;
        CHECKF(lst_tetrahedralize(&s, &to, &m, NULL, &err) == LST_ERR_TOPOLOGY && strstr(err.message, "intersect") &&
                   !m.tets,
               "strict: '%s'", err.message);
        lst_mesh_free(&s);
    }
    {
        lst_volume v;
        expect(lst_builtin_exemplar("marble", 16, &o, &v, NULL, &err), LST_ERR_INVALID, &err, "unknown exemplar", "marble");
        expect(lst_builtin_exemplar("spots", 2, &o, &v, NULL, &err), LST_ERR_INVALID, &err, "tiny exemplar", "size 2");
    }
}

/* ---- allocation failure ----------------------------------------------------------------------------- */

/* Runs fn(arg, allocator) with the k-th allocation failing, for every k;
 * fn returns the result and frees what it made on success. */
typedef lst_result (*alloc_fn)(void *arg, const lst_allocator *al);

static void sweep(const char *what, alloc_fn fn, void *arg)
{
    pwt_alloc_state st = {0, 0, -1};
    lst_allocator al;
    long k, total, bad = 0, leaks = 0;
    al.malloc_fn = pwt_malloc, al.realloc_fn = pwt_realloc, al.free_fn = pwt_free, al.user = &st;
    if (fn(arg, &al) != LST_OK) {
        CHECKF(0, "%s fails without any allocation failure", what);
        return;
    }
    CHECKF(st.live == 0, "%s leaks %ld blocks", what, st.live);
    total = st.calls;
    for (k = 0; k < total; k++) {
        lst_result r;
        st.calls = 0, st.live = 0, st.fail_after = k;
        r = fn(arg, &al);
        if (r != LST_OK && r != LST_ERR_NOMEM) bad++;
        if (st.live) leaks++;
    }
    st.fail_after = -1;
    pwt_info("%s: %ld allocations, each made to fail once", what, total);
    CHECKF(bad == 0, "%s: %ld failures reported as something else than NOMEM", what, bad);
    CHECKF(leaks == 0, "%s: %ld failures leaked memory", what, leaks);
}

typedef struct sweep_in {
    lst_tetmesh m;
    lst_mesh s;
    lst_volume ex;
    int type;
    const lst_constraint *dc;
    int nd;
} sweep_in;

/* Options that keep the sweeps short: few sample points, large pastes. */
static lst_options sweep_options(const lst_allocator *al, int type)
{
    lst_options o = lst_default_options();
    o.allocator = *al, o.type = type, o.samples = 1, o.scale = 2.0f;
    return o;
}

static lst_result sw_create(void *arg, const lst_allocator *al)
{
    sweep_in *in = (sweep_in *)arg;
    lst_options o = sweep_options(al, in->type);
    lst_model model;
    lst_error err;
    lst_result r;
    o.constraints = in->dc, o.nconstraints = in->nd;
    r = create_model(&in->m, in->nd ? &in->s : NULL, &in->ex, NULL, &o, &model, &err);
    if (r == LST_OK) lst_model_free(&model);
    return r;
}

/* Fill, cut, manual paste and renderings of one small model. */
static lst_result sw_views(void *arg, const lst_allocator *al)
{
    sweep_in *in = (sweep_in *)arg;
    lst_options o = sweep_options(al, LST_TYPE_2B);
    lst_render_options ro;
    lst_volume_options vo;
    lst_model model;
    lst_image img;
    lst_error err;
    lst_result r;
    float plane[4] = {0, 0.3f, 1, 0.1f};
    lst_paste_spec spec;
    pwt_alloc_state *st = (pwt_alloc_state *)al->user;
    long budget = st->fail_after;
    memset(&ro, 0, sizeof ro);
    memset(&vo, 0, sizeof vo);
    memset(&spec, 0, sizeof spec);
    ro.width = 32, ro.height = 24, ro.supersample = 1, vo.slices = 4;
    spec.point[0] = 0.1f, spec.point[1] = -0.1f, spec.point[2] = -0.3f;
    spec.u_axis[0] = 1.0f, spec.v_axis[2] = 1.0f, spec.scale = 0.6f, spec.mask = 1;
    st->fail_after = -1; /* the fill itself is swept by sw_create */
    if ((r = create_model(&in->m, NULL, &in->ex, NULL, &o, &model, &err)) != LST_OK) return r;
    st->fail_after = budget < 0 ? -1 : st->calls + budget;
    if ((r = lst_cut_plane(&model, plane, &err)) == LST_OK && (r = lst_paste_at(&model, &spec, &o, &err)) == LST_OK &&
        (r = lst_render(&model, &ro, &img, &err)) == LST_OK) {
        lst_image_free(&img);
        if ((r = lst_render_volume(&model, &ro, &vo, &img, &err)) == LST_OK) lst_image_free(&img);
    }
    st->fail_after = -1;
    lst_model_free(&model);
    return r;
}

static lst_result sw_read(void *arg, const lst_allocator *al)
{
    const pw_buf *b = (const pw_buf *)arg;
    lst_options o = lst_default_options();
    lst_model m;
    lst_error err;
    lst_result r;
    o.allocator = *al;
    r = lst_read_model(b->data, b->size, "m", &o, &m, &err);
    if (r == LST_OK) lst_model_free(&m);
    return r;
}

static lst_result sw_builtin(void *arg, const lst_allocator *al)
{
    lst_options o = lst_default_options();
    lst_mesh s;
    lst_volume v, w;
    lst_constraints c;
    lst_error err;
    lst_result r;
    (void)arg;
    o.allocator = *al;
    if ((r = lst_builtin_mesh("kiwi", &o, &s, &err)) != LST_OK) return r;
    if ((r = lst_builtin_constraints("tree", &s, &o, &c, &err)) == LST_OK) lst_constraints_free(&c);
    lst_mesh_free(&s);
    if (r == LST_OK && (r = lst_builtin_exemplar("kiwi", 8, &o, &v, &w, &err)) == LST_OK) lst_volume_free(&v), lst_volume_free(&w);
    return r;
}

static void t_nomem(void)
{
    lst_options o = lst_default_options();
    sweep_in in;
    lst_error err;
    lst_model model;
    pw_buf b;
    lst_constraint dc[2];
    memset(&in, 0, sizeof in);
    memset(&b, 0, sizeof b);
    REQUIRE(small_tets(60, &in.m));
    REQUIRE(lst_tetmesh_surface(&in.m, NULL, &in.s, &err) == LST_OK);
    REQUIRE(lst_builtin_exemplar("rings", 8, &o, &in.ex, NULL, &err) == LST_OK);
    in.type = LST_TYPE_0;
    sweep("create, type 0", sw_create, &in);
    memset(dc, 0, sizeof dc);
    dc[0].kind = LST_CONSTRAINT_DEPTH_FILL, dc[0].crease = 90.0f;
    dc[1].kind = LST_CONSTRAINT_DEPTH_POINT, dc[1].value = 1.0f;
    in.type = LST_TYPE_2B, in.dc = dc, in.nd = 2;
    sweep("create, type 2-b with an RBF depth", sw_create, &in);
    in.nd = 0;
    sweep("cut, manual paste, renderings", sw_views, &in);
    o.type = LST_TYPE_2B, o.samples = 1;
    REQUIRE(create_model(&in.m, NULL, &in.ex, NULL, &o, &model, &err) == LST_OK);
    REQUIRE(lst_write_model(&model, pw_buf_write, &b, &err) == LST_OK);
    sweep("model file reader", sw_read, &b);
    sweep("built-in surface, constraints, exemplar", sw_builtin, NULL);
    free(b.data);
    lst_model_free(&model);
    lst_volume_free(&in.ex), lst_mesh_free(&in.s), lst_tetmesh_free(&in.m);
}

static const pwt_case cases[] = {
    {"model_roundtrip", t_model_roundtrip},
    {"model_cut_file", t_model_cut_file},
    {"model_bad", t_model_bad},
    {"constraint_files", t_constraint_files},
    {"tet_files", t_tet_files},
    {"obj_image_files", t_obj_image_files},
    {"tetgen_fill", t_tetgen_fill},
    {"real_meshes", t_real_meshes},
    {"bad_create", t_bad_create},
    {"bad_surface", t_bad_surface},
    {"nomem", t_nomem},
};
PWT_MAIN(cases)
