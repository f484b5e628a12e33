/* Allocation failure, method by method: a small but complete run through
 * the public API (create, edit, render, write) is repeated with the N-th
 * allocation failing, for every N up to the number of allocations the run
 * makes. Every run must end in an out-of-memory error (or, past the last
 * allocation, succeed), hand out nothing, leak nothing and not crash.
 * (tiled.h's sweep is in test_tiled.c, the atlas's in test_lapped_atlas.c,
 * the shared modules' in their own tests.) */
/* static: only what the tests call is compiled */
#define LAPPED_STATIC
#define PGP_STATIC
#define PATCHWORK_IMPLEMENTATION
#include "lapped.h"
#include "pgp.h"
#include "pwtest.h"

/* An octahedron split 1-to-4 once (32 triangles): small enough that a
 * sweep over every allocation of a whole run stays quick. */
static const char octa_obj[] =
    "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n"
    "v .5 .5 0\nv -.5 .5 0\nv -.5 -.5 0\nv .5 -.5 0\nv .5 0 .5\nv -.5 0 .5\nv 0 .5 .5\nv 0 -.5 .5\n"
    "v .5 0 -.5\nv -.5 0 -.5\nv 0 .5 -.5\nv 0 -.5 -.5\n"
    "f 1 7 11\nf 7 3 13\nf 11 13 5\nf 7 13 11\n"
    "f 3 8 13\nf 8 2 12\nf 13 12 5\nf 8 12 13\n"
    "f 2 9 12\nf 9 4 14\nf 12 14 5\nf 9 14 12\n"
    "f 4 10 14\nf 10 1 11\nf 14 11 5\nf 10 11 14\n"
    "f 3 7 17\nf 7 1 15\nf 17 15 6\nf 7 15 17\n"
    "f 2 8 16\nf 8 3 17\nf 16 17 6\nf 8 17 16\n"
    "f 4 9 18\nf 9 2 16\nf 18 16 6\nf 9 16 18\n"
    "f 1 10 15\nf 10 4 18\nf 15 18 6\nf 10 18 15\n";

/* Runs `run` with allocations failing after 0, 1, 2, ... calls until one
 * run needs no failure; returns the number of failure points. */
static long sweep(const char *what, int (*run)(void *alloc_user, void *data), void *data, int nomem)
{
    long n, points = 0;
    for (n = 0;; n++) {
        pwt_alloc_state st = {0, 0, -1};
        int r;
        st.fail_after = n;
        r = run(&st, data);
        CHECKF(st.live == 0, "%s: failure point %ld leaks %ld blocks", what, n, st.live);
        if (r == 0 && st.calls <= n) break; /* no allocation failed: done */
        CHECKF(r == nomem, "%s: failure point %ld gave %d, not out of memory", what, n, r);
        if (r != nomem || st.live) break;
        points++;
        if (n > 200000) {
            CHECKF(0, "%s: more than 200000 allocations", what);
            break;
        }
    }
    return points;
}

static int count_bytes(void *ctx, const void *data, size_t size)
{
    (void)data;
    *(size_t *)ctx += size;
    return 0;
}

/* ---- lapped.h ------------------------------------------------------------------- */

typedef struct lapped_job {
    lapped_mesh mesh;
    lapped_image texture;
} lapped_job;

static int lapped_run(void *user, void *data)
{
    lapped_job *j = (lapped_job *)data;
    lapped_options o = lapped_default_options();
    lapped_image patch, pic;
    lapped_source src;
    lapped_texture t;
    lapped_error err;
    size_t bytes = 0;
    int r;
    o.allocator.malloc_fn = pwt_malloc;
    o.allocator.realloc_fn = pwt_realloc;
    o.allocator.free_fn = pwt_free;
    o.allocator.user = user;
    o.scale = 2.0f;
    o.render.width = 32, o.render.height = 24, o.render.supersample = 1;
    src.patches = &patch, src.npatches = 1, src.values = NULL;
    if ((r = lapped_make_patch(&j->texture, NULL, &o, &patch, &err)) != LAPPED_OK) return r;
    if ((r = lapped_create(&j->mesh, &src, &o, &t, &err)) == LAPPED_OK) {
        r = lapped_render(&j->mesh, &t, &src, &o.render, &pic, &err);
        if (r == LAPPED_OK) {
            lapped_image_free(&pic);
            r = lapped_write_pastes(&t, count_bytes, &bytes, &err);
        }
        lapped_texture_free(&t);
    }
    lapped_image_free(&patch);
    return r;
}

static void t_lapped(void)
{
    lapped_options o = lapped_default_options();
    lapped_error err;
    lapped_job j;
    long points;
    REQUIRE(lapped_read_mesh(octa_obj, sizeof octa_obj - 1, "octa.obj", &o, &j.mesh, &err) == LAPPED_OK);
    REQUIRE(lapped_builtin_exemplar("scales", 24, &o, &j.texture, &err) == LAPPED_OK);
    points = sweep("lapped", lapped_run, &j, LAPPED_ERR_NOMEM);
    pwt_info("lapped_make_patch + lapped_create + lapped_render + paste file: %ld allocation failure points", points);
    CHECK(points > 50);
    lapped_mesh_free(&j.mesh);
    lapped_image_free(&j.texture);
}

/* ---- pgp.h ---------------------------------------------------------------------- */

typedef struct pgp_job {
    pgp_mesh mesh;
    pgp_tile tile;
} pgp_job;

static int pgp_run(void *user, void *data)
{
    pgp_job *j = (pgp_job *)data;
    pgp_options o = pgp_default_options();
    pgp_render_options ro;
    pgp_map P;
    pgp_constraint c[3];
    pgp_constraints cons;
    pgp_area area;
    pgp_image pic;
    pgp_error err;
    size_t bytes = 0;
    int r, id = -1;
    o.allocator.malloc_fn = pwt_malloc;
    o.allocator.realloc_fn = pwt_realloc;
    o.allocator.free_fn = pwt_free;
    o.allocator.user = user;
    memset(&ro, 0, sizeof ro);
    ro.width = 32, ro.height = 24, ro.supersample = 1;
    memset(c, 0, sizeof c);
    c[0].kind = PGP_CONSTRAINT_MATERIAL, c[0].element = 3, c[0].value[0] = 1.0f;
    c[1].kind = PGP_CONSTRAINT_ORIENT, c[1].element = 10, c[1].value[0] = 1.0f, c[1].radius = 0.8f;
    c[2].kind = PGP_CONSTRAINT_SCALE, c[2].element = 7, c[2].value[0] = 0.3f, c[2].radius = 0.4f;
    o.constraints = c;
    o.nconstraints = 1;
    if ((r = pgp_create(&j->mesh, &o, &P, &err)) != PGP_OK) return P.state ? -1 : r;
    r = pgp_add_constraint(&P, &c[1], &id, &area, &err);
    if (r == PGP_OK) pgp_area_free(&area), r = pgp_add_constraint(&P, &c[2], NULL, NULL, &err);
    if (r == PGP_OK) r = pgp_remove_constraint(&P, id, NULL, &err);
    if (r == PGP_OK && (r = pgp_read_constraints("radius 0.3\nmaterial 5 0.5\n", 26, "c.txt", &o, &cons, &err)) == PGP_OK) {
        r = pgp_add_constraint(&P, &cons.items[0], NULL, NULL, &err);
        pgp_constraints_free(&cons);
    }
    if (r == PGP_OK && (r = pgp_render(&P, &j->tile, &ro, &pic, &err)) == PGP_OK) pgp_image_free(&pic);
    if (r == PGP_OK) r = pgp_write_obj(&j->mesh, &P, count_bytes, &bytes, &err);
    pgp_map_free(&P);
    return r;
}

static void t_pgp(void)
{
    pgp_options o = pgp_default_options();
    pgp_error err;
    pgp_job j;
    long points;
    REQUIRE(pgp_read_mesh(octa_obj, sizeof octa_obj - 1, "octa.obj", &o, &j.mesh, &err) == PGP_OK);
    REQUIRE(pgp_builtin_tile("bricks", 16, &o, &j.tile, &err) == PGP_OK);
    points = sweep("pgp", pgp_run, &j, PGP_ERR_NOMEM);
    pwt_info("pgp_create with a constraint + 2 more, a removal, a constraints file, pgp_render, OBJ: %ld allocation failure "
             "points", points);
    CHECK(points > 50);
    pgp_mesh_free(&j.mesh);
    pgp_tile_free(&j.tile);
}

static const pwt_case cases[] = {
    {"alloc_failures/lapped", t_lapped},
    {"alloc_failures/pgp", t_pgp},
};
PWT_MAIN(cases)
