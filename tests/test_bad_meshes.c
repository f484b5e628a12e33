/* Every surface method on the meshes that go wrong in practice: each
 * either gives a correct result or a clear error that names the problem
 * (an element index or what is wrong), never a crash (the sanitizer build
 * runs this too).
 *
 * Expectations, per mesh (the same for tiled, lapped, pgp and lst unless
 * noted; lst tetrahedralizes the surface, so every open one is refused as
 * "not closed", and fills the twenty closed components):
 *   non-manifold edge or vertex, inconsistent orientation
 *                         -> PW_ERR_TOPOLOGY, naming the element;
 *   a face using a vertex twice -> PW_ERR_DEGENERATE, naming the face;
 *   a zero-area triangle  -> tiled works (its quads need no area);
 *                            lapped works (neighbours' pastes cover it,
 *                            test_lapped_degenerate); pgp refuses it,
 *                            naming the triangle;
 *   NaN or infinite coordinates, an empty file -> refused at load;
 *   duplicate vertices (a seam), isolated vertices, an open boundary,
 *   twenty components, a single triangle -> a result (lst: open ones
 *   refused), checked below. */
/* static: only what the tests call is compiled */
#define TILED_STATIC
#define LAPPED_STATIC
#define PGP_STATIC
#define LST_STATIC
#define PATCHWORK_IMPLEMENTATION
#include "tiled.h"
#include "lapped.h"
#include "pgp.h"
#include "lst.h"
#include "pwtest.h"

/* lst_create with the exemplar and its extra channel (may be NULL) as arguments. */
static lst_result create_model(const lst_tetmesh *m, const lst_mesh *s, const lst_volume *ex, const lst_volume *val,
                               const lst_options *o, lst_model *out, lst_error *err)
{
    lst_source src;
    src.exemplar = ex, src.values = val;
    return lst_create(m, s, &src, o, out, err);
}

/* A tetrahedron of side ~1 at (x, 0, 0), as OBJ text (1-based indices
 * offset by base). */
static int tet_obj(char *out, size_t cap, float x, int base)
{
    return snprintf(out, cap,
                    "v %g 0 0\nv %g 1 0\nv %g 0 1\nv %g 0 0\n"
                    "f %d %d %d\nf %d %d %d\nf %d %d %d\nf %d %d %d\n",
                    x, x, x, x + 1.0f, base + 1, base + 3, base + 2, base + 1, base + 2, base + 4, base + 1,
                    base + 4, base + 3, base + 2, base + 3, base + 4);
}

typedef struct bad_case {
    const char *name, *obj;
    int load_fails;      /* refused by the mesh reader */
    int tiled, lapped, pgp, lst; /* expected result code of each method (0: a result); lst
                                    tetrahedralizes, so it needs a closed surface */
    const char *words;   /* '|'-separated: one of them must be in the message */
} bad_case;

/* Two squares sharing one vertex only (a bow tie of fans). */
#define BOWTIE "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -1 0 0\nv -1 -1 0\nv 0 -1 0\nf 1 2 3\nf 1 3 4\nf 1 5 6\nf 1 6 7\n"
#define GRID3                                                                                                   \
    "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0.3\nv 2 1 0\nv 0 2 0\nv 1 2 0\nv 2 2 0\n"                        \
    "f 1 2 5\nf 1 5 4\nf 2 3 6\nf 2 6 5\nf 4 5 8\nf 4 8 7\nf 5 6 9\nf 5 9 8\n"

#define T PW_ERR_TOPOLOGY
#define D PW_ERR_DEGENERATE
static const bad_case cases[] = {
    {"nonmanifold_edge", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n", 0, T, T, T, T,
     "non-manifold|edge"},
    {"nonmanifold_vertex", BOWTIE, 0, T, T, T, T, "non-manifold vertex|not closed"},
    {"inconsistent_orientation", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 4 3\n", 0, T, T, T, T,
     "orientation"},
    {"repeated_vertex", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 2\nf 1 2 3\n", 0, D, D, D, T,
     "twice|not closed"}, /* lst skips the zero-area face: what is left is open */
    {"zero_area", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 1 1 0\nf 1 2 4\nf 2 3 4\nf 1 3 2\n", 0, 0, 0, D, T,
     "zero area|degenerate|not closed"}, /* open, which lst refuses first (closed ones: test_lst_io) */
    {"nan", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", 1, 0, 0, 0, 0, "finite|number"},
    {"inf", "v 0 0 0\nv 1 0 0\nv 0 inf 0\nf 1 2 3\n", 1, 0, 0, 0, 0, "finite|number"},
    {"empty", "", 1, 0, 0, 0, 0, "no faces"},
    {"duplicate_vertices", /* the grid's middle column doubled: a seam, two boundaries */
     "v 0 0 0\nv 1 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 1 1 0\nv 2 1 0\n"
     "f 1 2 6\nf 1 6 5\nf 3 4 8\nf 3 8 7\n",
     0, 0, 0, 0, T, "not closed"},
    {"isolated_vertices", "v 5 5 5\n" GRID3 "v -3 2 1\n", 0, 0, 0, 0, T, "not closed"},
    {"open_boundary", GRID3, 0, 0, 0, 0, T, "not closed"},
    {"single_triangle", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", 0, 0, 0, 0, T, "not closed"},
};
#undef T
#undef D

static int has_word(const char *msg, const char *words)
{
    char buf[256];
    const char *p = words;
    if (!*words) return 1;
    while (*p) {
        size_t n = strcspn(p, "|");
        memcpy(buf, p, n);
        buf[n] = 0;
        if (strstr(msg, buf)) return 1;
        p += n + (p[n] == '|');
    }
    return 0;
}

static void run_tiled(const char *obj, size_t len, const bad_case *c)
{
    tiled_options o = tiled_default_options();
    tiled_layout l;
    tiled_mesh m, q;
    tiled_error err;
    tiled_result r = tiled_read_mesh(obj, len, c->name, &o, &m, &err);
    if (c->load_fails) {
        CHECKF(r != TILED_OK && has_word(err.message, c->words), "%s: tiled load: %s", c->name, err.message);
        if (r == TILED_OK) tiled_mesh_free(&m);
        return;
    }
    REQUIRE(r == TILED_OK);
    memset(&l, 0, sizeof l);
    l.tile_size = 16;
    r = tiled_map(&m, &l, &o, &q, &err);
    CHECKF((int)r == c->tiled, "%s: tiled gave %d (%s), expected %d", c->name, r, r ? err.message : "ok", c->tiled);
    if (r != TILED_OK) CHECKF(has_word(err.message, c->words), "%s: tiled message: %s", c->name, err.message);
    else {
        int k;
        CHECK(q.nfaces > 0 && q.uvs);
        for (k = 0; k < 2 * q.face_start[q.nfaces]; k++) CHECK(q.uvs[k] >= 0.0f && q.uvs[k] <= 1.0f);
        tiled_mesh_free(&q);
    }
    tiled_mesh_free(&m);
}

static void run_lapped(const char *obj, size_t len, const bad_case *c)
{
    lapped_options o = lapped_default_options();
    lapped_mesh m;
    lapped_image tex, patch;
    lapped_source src;
    lapped_texture t;
    lapped_error err;
    lapped_result r = lapped_read_mesh(obj, len, c->name, &o, &m, &err);
    if (c->load_fails) {
        CHECKF(r != LAPPED_OK && has_word(err.message, c->words), "%s: lapped load: %s", c->name, err.message);
        if (r == LAPPED_OK) lapped_mesh_free(&m);
        return;
    }
    REQUIRE(r == LAPPED_OK);
    REQUIRE(lapped_builtin_exemplar("dots", 32, &o, &tex, &err) == LAPPED_OK);
    REQUIRE(lapped_make_patch(&tex, NULL, &o, &patch, &err) == LAPPED_OK);
    o.field = LAPPED_FIELD_ISOTROPIC;
    o.scale = 0.8f;
    src.patches = &patch, src.npatches = 1, src.values = NULL;
    r = lapped_create(&m, &src, &o, &t, &err);
    CHECKF((int)r == c->lapped, "%s: lapped gave %d (%s), expected %d", c->name, r, r ? err.message : "ok", c->lapped);
    if (r != LAPPED_OK) CHECKF(has_word(err.message, c->words), "%s: lapped message: %s", c->name, err.message);
    else {
        CHECK(t.npastes > 0 && t.ntris > 0);
        lapped_texture_free(&t);
    }
    lapped_image_free(&tex);
    lapped_image_free(&patch);
    lapped_mesh_free(&m);
}

static void run_pgp(const char *obj, size_t len, const bad_case *c)
{
    pgp_options o = pgp_default_options();
    pgp_mesh m;
    pgp_map P;
    pgp_error err;
    pgp_result r = pgp_read_mesh(obj, len, c->name, &o, &m, &err);
    if (c->load_fails) {
        CHECKF(r != PGP_OK && has_word(err.message, c->words), "%s: pgp load: %s", c->name, err.message);
        if (r == PGP_OK) pgp_mesh_free(&m);
        return;
    }
    REQUIRE(r == PGP_OK);
    r = pgp_create(&m, &o, &P, &err);
    CHECKF((int)r == c->pgp, "%s: pgp gave %d (%s), expected %d", c->name, r, r ? err.message : "ok", c->pgp);
    if (r != PGP_OK) CHECKF(has_word(err.message, c->words) && !P.state, "%s: pgp message: %s", c->name, err.message);
    else {
        int k;
        for (k = 0; k < 9 * P.ntris; k++) CHECK(P.coords[k] == P.coords[k] && P.coords[k] - P.coords[k] == 0.0f);
        pgp_map_free(&P);
    }
    pgp_mesh_free(&m);
}

/* lst: the surface tetrahedralized, then filled (type 0, a small exemplar). */
static void run_lst(const char *obj, size_t len, const bad_case *c)
{
    lst_options o = lst_default_options();
    lst_mesh m;
    lst_tetmesh tets;
    lst_volume ex;
    lst_model model;
    lst_error err;
    lst_result r = lst_read_mesh(obj, len, c->name, &o, &m, &err);
    if (c->load_fails) {
        CHECKF(r != LST_OK && has_word(err.message, c->words), "%s: lst load: %s", c->name, err.message);
        if (r == LST_OK) lst_mesh_free(&m);
        return;
    }
    REQUIRE(r == LST_OK);
    o.tet.target_tets = 2000, o.tet.uniform = 1; /* a small uniform fill: stuffing tests cover the graded one */
    r = lst_tetrahedralize(&m, &o, &tets, NULL, &err);
    CHECKF((int)r == c->lst, "%s: lst gave %d (%s), expected %d", c->name, r, r ? err.message : "ok", c->lst);
    if (r != LST_OK) CHECKF(has_word(err.message, c->words), "%s: lst message: %s", c->name, err.message);
    else {
        REQUIRE(lst_builtin_exemplar("spots", 16, &o, &ex, NULL, &err) == LST_OK);
        r = create_model(&tets, &m, &ex, NULL, &o, &model, &err);
        CHECKF(r == LST_OK && model.npastes > 0, "%s: lst fill: %s", c->name, r ? err.message : "no pastes");
        if (r == LST_OK) lst_model_free(&model);
        lst_volume_free(&ex);
        lst_tetmesh_free(&tets);
    }
    lst_mesh_free(&m);
}

static void t_cases(void)
{
    size_t k;
    for (k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        const bad_case *c = &cases[k];
        size_t len = strlen(c->obj);
        run_tiled(c->obj, len, c);
        run_lapped(c->obj, len, c);
        run_pgp(c->obj, len, c);
        run_lst(c->obj, len, c);
    }
}

/* Twenty separate tetrahedra: every method handles each component. */
static void t_many_components(void)
{
    static char obj[20 * 200];
    bad_case c;
    int k, n = 0;
    for (k = 0; k < 20; k++) n += tet_obj(obj + n, sizeof obj - (size_t)n, 3.0f * k, 4 * k);
    memset(&c, 0, sizeof c);
    c.name = "twenty_components";
    c.words = "";
    run_tiled(obj, (size_t)n, &c);
    run_lapped(obj, (size_t)n, &c);
    run_pgp(obj, (size_t)n, &c);
    run_lst(obj, (size_t)n, &c);
}

static const pwt_case tests[] = {
    {"bad_meshes/cases", t_cases},
    {"bad_meshes/many_components", t_many_components},
};
PWT_MAIN(tests)
