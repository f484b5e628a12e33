/* Rendering band by band on threads (issues 20, 21), through each header's
 * public API: every method's picture is the same, bit for bit, on 1, 2 and
 * 3 threads and through a caller's parallel-for that runs the bands in
 * reverse; and what rendering allocates per pixel of the picture, measured
 * with a counting allocator as the growth between two picture sizes, stays
 * within 48 bytes at the default 2 x 2 samples (the bands under way hold a
 * quarter of the frame's samples of 24 bytes, 24 bytes per pixel; the RGB
 * picture 12). Tile synthesis on threads (tiled's tiles, pgp's morph
 * sides): the same tile set, bit for bit, on 1, 2 and 3 threads and through
 * the reversed parallel-for. lapped's and lst's coverage on threads: the
 * same pastes, bit for bit, likewise (their parallel-fors run on a crew,
 * threads kept for the whole create call). The crew itself: thousands of
 * parallel-fors on the same threads, every task run once, none on one
 * thread or under a caller's parallel-for, a parallel-for inside a task.
 * pgp_create's solves on threads (s and t side by side, the field's
 * multigrid sweeps and products): the same map, bit for bit, likewise,
 * and every allocation failing in turn on 2 threads ends in an
 * out-of-memory error with nothing left allocated. */
#define PW_THREADS
#define PATCHWORK_IMPLEMENTATION
#include "../tiled.h"
#include "../lapped.h"
#include "../pgp.h"
#include "../lst.h"
#include <pthread.h>
#include "pwtest.h"

/* ---- a counting, thread-safe allocator: live bytes and their peak ---- */

typedef struct counter {
    pthread_mutex_t lock;
    size_t bytes, peak;
    long calls, fail_at; /* allocations so far; the one that fails (0: none) */
} counter;

static counter C = {PTHREAD_MUTEX_INITIALIZER, 0, 0, 0, 0};

static void *c_malloc(void *user, size_t n)
{
    counter *c = (counter *)user;
    size_t *p;
    int fail;
    pthread_mutex_lock(&c->lock);
    fail = ++c->calls == c->fail_at;
    pthread_mutex_unlock(&c->lock);
    if (fail || !(p = (size_t *)malloc(n + sizeof(size_t)))) return NULL;
    *p = n;
    pthread_mutex_lock(&c->lock);
    c->bytes += n;
    if (c->bytes > c->peak) c->peak = c->bytes;
    pthread_mutex_unlock(&c->lock);
    return p + 1;
}

static void c_free(void *user, void *ptr)
{
    counter *c = (counter *)user;
    if (!ptr) return;
    pthread_mutex_lock(&c->lock);
    c->bytes -= ((size_t *)ptr)[-1];
    pthread_mutex_unlock(&c->lock);
    free((size_t *)ptr - 1);
}

static void *c_realloc(void *user, void *ptr, size_t n)
{
    void *q = c_malloc(user, n);
    if (q && ptr) {
        size_t old = ((size_t *)ptr)[-1];
        memcpy(q, ptr, old < n ? old : n);
        c_free(user, ptr);
    }
    return q;
}

#define SET_ALLOC(al) ((al).malloc_fn = c_malloc, (al).realloc_fn = c_realloc, (al).free_fn = c_free, (al).user = &C)

/* The peak of live bytes from now on, over what is live now. */
static size_t peak_start(void)
{
    size_t now;
    pthread_mutex_lock(&C.lock);
    C.peak = now = C.bytes;
    pthread_mutex_unlock(&C.lock);
    return now;
}

static size_t peak_since(size_t base) { return C.peak - base; }

/* ---- the parallel-for of an embedder: the bands in reverse ---- */

static int reverse_calls, reverse_pairs; /* its calls; those of two tasks */

static void reverse_for(void *pool, int n, void (*task)(void *ctx, int i), void *ctx)
{
    int i;
    (void)pool;
    reverse_calls++;
    reverse_pairs += n == 2;
    for (i = n - 1; i >= 0; i--) task(ctx, i);
}

/* ---- one method: its render under each way of running, compared ---- */

/* A render of the scene at w x h on `threads` threads (0: the reverse
 * parallel-for) into a fresh image; 0 on success. */
typedef int (*render_fn)(void *scene, int w, int h, int threads, float **px, size_t *bytes);

static void check_method(const char *name, render_fn render, void *scene)
{
    float *ref = NULL, *px = NULL;
    size_t bytes, n = (size_t)160 * 120 * 3, small, large;
    int threads, calls = reverse_calls;
    double slope;
    REQUIRE(render(scene, 160, 120, 1, &ref, &bytes) == 0);
    for (threads = 2; threads <= 4; threads++) {
        REQUIRE(render(scene, 160, 120, threads == 4 ? 0 : threads, &px, &bytes) == 0);
        CHECKF(memcmp(px, ref, n * sizeof(float)) == 0, "%s: the picture %s differs from one thread's", name,
               threads == 4 ? "through a reversed parallel-for" : threads == 2 ? "on 2 threads" : "on 3 threads");
        free(px);
    }
    CHECKF(reverse_calls > calls, "%s: the caller's parallel-for was not used", name);
    free(ref);
    for (threads = 1; threads <= 2; threads++) {
        REQUIRE(render(scene, 400, 300, threads, &px, &small) == 0);
        free(px);
        REQUIRE(render(scene, 800, 600, threads, &px, &large) == 0);
        free(px);
        slope = ((double)large - (double)small) / (800.0 * 600.0 - 400.0 * 300.0);
        pwt_info("%s, %d thread%s: %.1f bytes per pixel at 2x2 samples (peak %.1f MB at 800x600)", name, threads,
                 threads > 1 ? "s" : "", slope, large / 1048576.0);
        CHECKF(slope <= 48.0, "%s: %.1f bytes per pixel", name, slope);
    }
}

/* The peak bytes of one render and a copy of its pixels (malloc). */
#define KEEP_PIXELS(img, w, h, px)                                                          \
    do {                                                                                    \
        *(px) = (float *)malloc(sizeof(float) * 3 * (size_t)(w) * (size_t)(h));             \
        if (*(px)) memcpy(*(px), (img).pixels, sizeof(float) * 3 * (size_t)(w) * (size_t)(h)); \
    } while (0)

/* ---- tiled ---- */

typedef struct tiled_scene {
    tiled_mesh quads;
    tiled_tileset tiles;
} tiled_scene;

static int tiled_draw(void *scene, int w, int h, int threads, float **px, size_t *bytes)
{
    tiled_scene *S = (tiled_scene *)scene;
    tiled_render_options ro = tiled_default_options().render;
    tiled_image out;
    size_t base = peak_start();
    ro.width = w, ro.height = h, ro.threads = threads, ro.parallel = threads ? NULL : reverse_for;
    if (tiled_render(&S->quads, &S->tiles, &ro, &out, NULL) != TILED_OK) return 1;
    *bytes = peak_since(base);
    KEEP_PIXELS(out, w, h, px);
    tiled_image_free(&out);
    return *px == NULL;
}

static void t_tiled(void)
{
    tiled_options opt = tiled_default_options();
    tiled_mesh mesh;
    tiled_image ex;
    tiled_scene S;
    SET_ALLOC(opt.allocator);
    REQUIRE(tiled_builtin_mesh("torus", &opt, &mesh, NULL) == TILED_OK);
    REQUIRE(tiled_builtin_exemplar("pebbles", 64, &opt, &ex, NULL) == TILED_OK);
    REQUIRE(tiled_synthesize(&ex, &opt, &S.tiles, NULL) == TILED_OK);
    REQUIRE(tiled_map(&mesh, &S.tiles.layout, &opt, &S.quads, NULL) == TILED_OK);
    check_method("tiled", tiled_draw, &S);
    tiled_mesh_free(&mesh);
    tiled_mesh_free(&S.quads);
    tiled_image_free(&ex);
    tiled_tileset_free(&S.tiles);
}

/* Tile synthesis: the tile set of 1 thread, of 2 and 3, and of a reversed
 * parallel-for, bit for bit. */
static void t_tiled_synthesis(void)
{
    tiled_options opt = tiled_default_options();
    tiled_image ex;
    tiled_tileset ref, ts;
    size_t n;
    int threads, calls = reverse_calls;
    opt.layout.tile_size = 32;
    REQUIRE(tiled_builtin_exemplar("pebbles", 64, &opt, &ex, NULL) == TILED_OK);
    opt.threads = 1;
    REQUIRE(tiled_synthesize(&ex, &opt, &ref, NULL) == TILED_OK);
    n = (size_t)ref.atlas.width * ref.atlas.height * ref.atlas.channels;
    for (threads = 2; threads <= 4; threads++) {
        opt.threads = threads == 4 ? 0 : threads;
        opt.parallel = threads == 4 ? reverse_for : NULL;
        REQUIRE(tiled_synthesize(&ex, &opt, &ts, NULL) == TILED_OK);
        CHECKF(ts.atlas.width == ref.atlas.width && memcmp(ts.atlas.pixels, ref.atlas.pixels, n * sizeof(float)) == 0,
               "tiled synthesis: the tile set %s differs from one thread's",
               threads == 4 ? "through a reversed parallel-for" : threads == 2 ? "on 2 threads" : "on 3 threads");
        tiled_tileset_free(&ts);
    }
    CHECKF(reverse_calls > calls, "tiled synthesis: the caller's parallel-for was not used");
    tiled_tileset_free(&ref);
    tiled_image_free(&ex);
}

/* pgp's tile synthesis: the two ends of a morph side by side. Keys: tiled's
 * built-in pebbles and spots, viewed as pgp images. */
static void t_pgp_synthesis(void)
{
    tiled_image ex[2];
    pgp_image img[2];
    pgp_key keys[2];
    pgp_synth_options o = pgp_default_options().synth;
    pgp_tile ref, t;
    size_t n;
    int k, threads, calls = reverse_calls;
    REQUIRE(tiled_builtin_exemplar("pebbles", 32, NULL, &ex[0], NULL) == TILED_OK);
    REQUIRE(tiled_builtin_exemplar("spots", 32, NULL, &ex[1], NULL) == TILED_OK);
    for (k = 0; k < 2; k++) {
        memset(&img[k], 0, sizeof img[k]);
        img[k].width = ex[k].width, img[k].height = ex[k].height, img[k].channels = ex[k].channels;
        img[k].pixels = ex[k].pixels;
        keys[k].image = &img[k], keys[k].mask = NULL;
    }
    o.size = 32, o.layers = 5, o.threads = 1;
    REQUIRE(pgp_synthesize_tile(keys, 2, &o, &ref, NULL, NULL) == PGP_OK);
    n = (size_t)ref.width * ref.height * ref.channels * ref.layers;
    for (threads = 2; threads <= 3; threads++) {
        o.threads = threads == 3 ? 0 : threads;
        o.parallel = threads == 3 ? reverse_for : NULL;
        REQUIRE(pgp_synthesize_tile(keys, 2, &o, &t, NULL, NULL) == PGP_OK);
        CHECKF(memcmp(t.pixels, ref.pixels, n * sizeof(float)) == 0, "pgp synthesis: the tile %s differs from one thread's",
               threads == 3 ? "through a reversed parallel-for" : "on 2 threads");
        pgp_tile_free(&t);
    }
    CHECKF(reverse_calls > calls, "pgp synthesis: the caller's parallel-for was not used");
    pgp_tile_free(&ref);
    for (k = 0; k < 2; k++) tiled_image_free(&ex[k]);
}

/* ---- lapped ---- */

typedef struct lapped_scene {
    lapped_mesh mesh;
    lapped_image patch;
    lapped_texture lt;
} lapped_scene;

static int lapped_draw(void *scene, int w, int h, int threads, float **px, size_t *bytes)
{
    lapped_scene *S = (lapped_scene *)scene;
    lapped_render_options ro = lapped_default_options().render;
    lapped_source src;
    lapped_image out;
    size_t base = peak_start();
    memset(&src, 0, sizeof src);
    src.patches = &S->patch;
    src.npatches = 1;
    ro.width = w, ro.height = h, ro.threads = threads, ro.parallel = threads ? NULL : reverse_for;
    if (lapped_render(&S->mesh, &S->lt, &src, &ro, &out, NULL) != LAPPED_OK) return 1;
    *bytes = peak_since(base);
    KEEP_PIXELS(out, w, h, px);
    lapped_image_free(&out);
    return *px == NULL;
}

static void t_lapped(void)
{
    lapped_options opt = lapped_default_options();
    lapped_image ex;
    lapped_source src;
    lapped_scene S;
    SET_ALLOC(opt.allocator);
    REQUIRE(lapped_builtin_mesh("bumpy", &opt, &S.mesh, NULL) == LAPPED_OK);
    REQUIRE(lapped_builtin_exemplar("scales", 64, &opt, &ex, NULL) == LAPPED_OK);
    REQUIRE(lapped_make_patch(&ex, NULL, &opt, &S.patch, NULL) == LAPPED_OK);
    memset(&src, 0, sizeof src);
    src.patches = &S.patch;
    src.npatches = 1;
    opt.scale = 0.6f;
    REQUIRE(lapped_create(&S.mesh, &src, &opt, &S.lt, NULL) == LAPPED_OK);
    check_method("lapped", lapped_draw, &S);
    lapped_texture_free(&S.lt);
    lapped_image_free(&S.patch);
    lapped_image_free(&ex);
    lapped_mesh_free(&S.mesh);
}

/* lapped_create's coverage on threads: the same pastes, bit for bit, on
 * 1, 2 and 3 threads and through the reversed parallel-for (the pruning
 * runs there in shares of the triangles, the pastes' painting in shares of
 * their triangles). */
static int lapped_same(const lapped_texture *a, const lapped_texture *b)
{
    int p;
    if (a->npastes != b->npastes || a->layers != b->layers || a->layers_before != b->layers_before ||
        a->hard_edges != b->hard_edges)
        return 0;
    for (p = 0; p < a->npastes; p++) {
        const lapped_paste *x = &a->pastes[p], *y = &b->pastes[p];
        if (x->patch != y->patch || x->nfaces != y->nfaces ||
            memcmp(x->faces, y->faces, sizeof(int) * (size_t)x->nfaces) != 0 ||
            memcmp(x->uvs, y->uvs, sizeof(float) * 6 * (size_t)x->nfaces) != 0)
            return 0;
    }
    return 1;
}

static void t_lapped_coverage(void)
{
    lapped_options opt = lapped_default_options();
    lapped_mesh mesh;
    lapped_image ex, patch;
    lapped_source src;
    lapped_texture ref, t;
    int threads, calls = reverse_calls;
    REQUIRE(lapped_builtin_mesh("bumpy", &opt, &mesh, NULL) == LAPPED_OK);
    REQUIRE(lapped_builtin_exemplar("scales", 192, &opt, &ex, NULL) == LAPPED_OK);
    REQUIRE(lapped_make_patch(&ex, NULL, &opt, &patch, NULL) == LAPPED_OK);
    memset(&src, 0, sizeof src);
    src.patches = &patch;
    src.npatches = 1;
    opt.scale = 0.6f, opt.threads = 1;
    REQUIRE(lapped_create(&mesh, &src, &opt, &ref, NULL) == LAPPED_OK);
    for (threads = 2; threads <= 4; threads++) {
        opt.threads = threads == 4 ? 0 : threads;
        opt.parallel = threads == 4 ? reverse_for : NULL;
        REQUIRE(lapped_create(&mesh, &src, &opt, &t, NULL) == LAPPED_OK);
        CHECKF(lapped_same(&ref, &t), "lapped coverage: the pastes %s differ from one thread's",
               threads == 4 ? "through a reversed parallel-for" : threads == 2 ? "on 2 threads" : "on 3 threads");
        lapped_texture_free(&t);
    }
    CHECKF(reverse_calls > calls + 1, "lapped coverage: the caller's parallel-for was used %d times",
           reverse_calls - calls);
    pwt_info("lapped coverage: %d pastes, %d calls of the parallel-for", ref.npastes, reverse_calls - calls);
    opt.threads = -1, opt.parallel = NULL;
    CHECK(lapped_create(&mesh, &src, &opt, &t, NULL) == LAPPED_ERR_INVALID);
    lapped_texture_free(&ref);
    lapped_image_free(&patch);
    lapped_image_free(&ex);
    lapped_mesh_free(&mesh);
}

/* ---- pgp ---- */

typedef struct pgp_scene {
    pgp_map map;
    pgp_tile tile;
} pgp_scene;

static int pgp_draw(void *scene, int w, int h, int threads, float **px, size_t *bytes)
{
    pgp_scene *S = (pgp_scene *)scene;
    pgp_render_options ro = pgp_default_options().render;
    pgp_image out;
    size_t base = peak_start();
    ro.width = w, ro.height = h, ro.threads = threads, ro.parallel = threads ? NULL : reverse_for;
    if (pgp_render(&S->map, &S->tile, &ro, &out, NULL) != PGP_OK) return 1;
    *bytes = peak_since(base);
    KEEP_PIXELS(out, w, h, px);
    pgp_image_free(&out);
    return *px == NULL;
}

static void t_pgp(void)
{
    pgp_options opt = pgp_default_options();
    pgp_mesh mesh;
    pgp_scene S;
    SET_ALLOC(opt.allocator);
    REQUIRE(pgp_builtin_mesh("torus", &opt, &mesh, NULL) == PGP_OK);
    REQUIRE(pgp_builtin_tile("bricks", 64, &opt, &S.tile, NULL) == PGP_OK);
    REQUIRE(pgp_create(&mesh, &opt, &S.map, NULL) == PGP_OK);
    check_method("pgp", pgp_draw, &S);
    pgp_map_free(&S.map);
    pgp_tile_free(&S.tile);
    pgp_mesh_free(&mesh);
}

/* pgp_create's solves on threads: a bumpy height field of 150 x 150
 * vertices (22,500 PGP unknowns: s and t side by side, each by multigrid
 * on one thread; 44,402 orientation unknowns: multigrid, rows enough for
 * the parallel sweeps), then an orientation constraint over half of it
 * (s and t side by side again); the coordinates and the singular
 * triangles compared bit for bit. */
static int pgp_grid(pgp_mesh *m, int GRID)
{
    int i, j, f = 0;
    memset(m, 0, sizeof *m);
    m->nverts = GRID * GRID;
    m->nfaces = 2 * (GRID - 1) * (GRID - 1);
    m->positions = (float *)malloc(sizeof(float) * 3 * (size_t)m->nverts);
    m->face_start = (int *)malloc(sizeof(int) * ((size_t)m->nfaces + 1));
    m->face_verts = (int *)malloc(sizeof(int) * 3 * (size_t)m->nfaces);
    if (!m->positions || !m->face_start || !m->face_verts) return 1;
    for (j = 0; j < GRID; j++)
        for (i = 0; i < GRID; i++) {
            float *p = m->positions + 3 * (j * GRID + i), x = (float)i / (GRID - 1), y = (float)j / (GRID - 1);
            p[0] = x;
            p[1] = y;
            p[2] = 0.05f * sinf(9.0f * x) * cosf(7.0f * y) + 0.1f * x * y;
        }
    for (j = 0; j + 1 < GRID; j++)
        for (i = 0; i + 1 < GRID; i++) {
            int v = j * GRID + i, *q = m->face_verts + 3 * f;
            q[0] = v, q[1] = v + 1, q[2] = v + GRID + 1;
            q[3] = v, q[4] = v + GRID + 1, q[5] = v + GRID;
            m->face_start[f] = 3 * f;
            m->face_start[f + 1] = 3 * (f + 1);
            m->face_start[f + 2] = 3 * (f + 2);
            f += 2;
        }
    return 0;
}

/* The map of the grid with o, then with an orientation constraint over
 * half of it: its coordinates and singular flags into out (ntris * 10
 * floats), 0 on success. */
static int pgp_grid_map(const pgp_mesh *m, const pgp_options *o, float *out)
{
    pgp_map map;
    pgp_constraint c;
    unsigned char *sing = (unsigned char *)malloc((size_t)m->nfaces);
    int f, id, r;
    memset(&c, 0, sizeof c);
    c.kind = PGP_CONSTRAINT_ORIENT;
    c.element = m->nfaces / 2;
    c.value[0] = 1.0f, c.value[1] = 1.0f;
    c.radius = 0.5f;
    r = !sing || pgp_create(m, o, &map, NULL) != PGP_OK;
    if (!r) {
        r = pgp_add_constraint(&map, &c, &id, NULL, NULL) != PGP_OK;
        memcpy(out, map.coords, sizeof(float) * 9 * (size_t)m->nfaces);
        pgp_map_singular(&map, sing);
        for (f = 0; f < m->nfaces; f++) out[9 * (size_t)m->nfaces + f] = sing[f];
        pgp_map_free(&map);
    }
    free(sing);
    return r;
}

static void t_pgp_create(void)
{
    pgp_options opt = pgp_default_options();
    pgp_mesh mesh;
    size_t n;
    float *ref, *got;
    int threads, calls = reverse_calls, pairs = reverse_pairs;
    REQUIRE(pgp_grid(&mesh, 150) == 0);
    n = 10 * (size_t)mesh.nfaces;
    ref = (float *)malloc(sizeof(float) * n);
    got = (float *)malloc(sizeof(float) * n);
    REQUIRE(ref && got);
    opt.scale = 0.05f, opt.threads = 1;
    REQUIRE(pgp_grid_map(&mesh, &opt, ref) == 0);
    for (threads = 2; threads <= 4; threads++) {
        opt.threads = threads == 4 ? 0 : threads;
        opt.parallel = threads == 4 ? reverse_for : NULL;
        REQUIRE(pgp_grid_map(&mesh, &opt, got) == 0);
        CHECKF(memcmp(ref, got, sizeof(float) * n) == 0, "pgp_create: the map %s differs from one thread's",
               threads == 4 ? "through a reversed parallel-for" : threads == 2 ? "on 2 threads" : "on 3 threads");
    }
    CHECKF(reverse_calls > calls + 20, "pgp_create: the caller's parallel-for was used %d times",
           reverse_calls - calls);
    CHECKF(reverse_pairs >= pairs + 2, "pgp_create: s and t solved side by side %d times, not at create and edit",
           reverse_pairs - pairs);
    pwt_info("pgp_create: %d triangles, %d calls of the parallel-for", mesh.nfaces, reverse_calls - calls);
    opt.threads = -1, opt.parallel = NULL;
    CHECK(pgp_grid_map(&mesh, &opt, got) != 0);
    free(ref);
    free(got);
    free(mesh.positions);
    free(mesh.face_start);
    free(mesh.face_verts);
}

/* pgp_create on 2 threads with the N-th allocation failing, for every N:
 * s and t are solved side by side there (a 72 x 72 grid, 5,184 unknowns),
 * so a failure may come in either task, or in the copy of the system,
 * while the other task runs on. Every run ends in PGP_ERR_NOMEM (or, past
 * the last allocation, succeeds) and leaves no byte allocated. */
static void t_pgp_create_nomem(void)
{
    pgp_options opt = pgp_default_options();
    pgp_mesh mesh;
    pgp_map map;
    long total, n, runs = 0, nomem = 0, leaks = 0, other = 0;
    size_t base;
    REQUIRE(pgp_grid(&mesh, 72) == 0);
    SET_ALLOC(opt.allocator);
    opt.scale = 0.05f, opt.threads = 2;
    base = C.bytes;
    C.calls = 0, C.fail_at = 0;
    REQUIRE(pgp_create(&mesh, &opt, &map, NULL) == PGP_OK);
    pgp_map_free(&map);
    total = C.calls;
    n = reverse_pairs;
    opt.threads = 0, opt.parallel = reverse_for; /* the split is taken at this size */
    REQUIRE(pgp_create(&mesh, &opt, &map, NULL) == PGP_OK);
    pgp_map_free(&map);
    CHECKF(reverse_pairs > n, "pgp_create: s and t not solved side by side on the %d x %d grid", 72, 72);
    opt.threads = 2, opt.parallel = NULL;
    for (n = 1; n <= total + 1; n++, runs++) {
        pgp_result r;
        C.calls = 0, C.fail_at = n;
        r = pgp_create(&mesh, &opt, &map, NULL);
        if (r == PGP_OK) pgp_map_free(&map);
        if (r == PGP_ERR_NOMEM) nomem++;
        else if (n <= total || r != PGP_OK) other++;
        leaks += C.bytes != base;
    }
    C.fail_at = 0;
    CHECKF(other == 0, "pgp_create on 2 threads: %ld of %ld runs did not end in NOMEM (or, the last, succeed)", other,
           runs);
    CHECKF(leaks == 0, "pgp_create on 2 threads: %ld of %ld runs left bytes allocated", leaks, runs);
    pwt_info("pgp_create on 2 threads: %ld allocations, %ld runs with one failing, %ld ended in NOMEM", total, runs,
             nomem);
    free(mesh.positions);
    free(mesh.face_start);
    free(mesh.face_verts);
}

/* ---- lst: the surface and the volume ---- */

typedef struct lst_scene {
    lst_model model;
    int volume;
} lst_scene;

static int lst_draw(void *scene, int w, int h, int threads, float **px, size_t *bytes)
{
    lst_scene *S = (lst_scene *)scene;
    lst_options opt = lst_default_options();
    lst_image out;
    size_t base = peak_start();
    lst_result r;
    opt.render.width = w, opt.render.height = h;
    opt.render.threads = threads, opt.render.parallel = threads ? NULL : reverse_for;
    opt.volume.slices = 24;
    r = S->volume ? lst_render_volume(&S->model, &opt.render, &opt.volume, &out, NULL)
                  : lst_render(&S->model, &opt.render, &out, NULL);
    if (r != LST_OK) return 1;
    *bytes = peak_since(base);
    KEEP_PIXELS(out, w, h, px);
    lst_image_free(&out);
    return *px == NULL;
}

static void t_lst(void)
{
    lst_options opt = lst_default_options();
    lst_mesh surface;
    lst_tetmesh tets;
    lst_volume ex;
    lst_source src;
    lst_scene S;
    const float cut[4] = {0.3f, 0.2f, 1.0f, 0.1f};
    SET_ALLOC(opt.allocator);
    opt.tet.target_tets = 3000, opt.tet.uniform = 1; /* a small uniform fill: stuffing tests cover the graded one */
    REQUIRE(lst_builtin_mesh("sphere", &opt, &surface, NULL) == LST_OK);
    REQUIRE(lst_tetrahedralize(&surface, &opt, &tets, NULL, NULL) == LST_OK);
    REQUIRE(lst_builtin_exemplar("spots", 32, &opt, &ex, NULL, NULL) == LST_OK);
    src.exemplar = &ex, src.values = NULL;
    REQUIRE(lst_create(&tets, &surface, &src, &opt, &S.model, NULL) == LST_OK);
    REQUIRE(lst_cut_plane(&S.model, cut, NULL) == LST_OK); /* the cut faces are drawn too */
    S.volume = 0;
    check_method("lst", lst_draw, &S);
    S.volume = 1;
    check_method("lst volume", lst_draw, &S);
    lst_model_free(&S.model);
    lst_volume_free(&ex);
    lst_tetmesh_free(&tets);
    lst_mesh_free(&surface);
}

/* lst_create's coverage on threads: the same pastes, bit for bit, on 1,
 * 2 and 3 threads and through the reversed parallel-for. */
static int lst_same(const lst_model *a, const lst_model *b)
{
    int p;
    if (a->npastes != b->npastes || a->layers != b->layers || a->layers_before != b->layers_before) return 0;
    for (p = 0; p < a->npastes; p++) {
        const lst_paste *x = &a->pastes[p], *y = &b->pastes[p];
        if (x->exemplar != y->exemplar || x->ntets != y->ntets || x->nverts != y->nverts ||
            memcmp(x->tets, y->tets, sizeof(int) * (size_t)x->ntets) != 0 ||
            memcmp(x->corners, y->corners, sizeof(int) * 4 * (size_t)x->ntets) != 0 ||
            memcmp(x->verts, y->verts, sizeof(int) * (size_t)x->nverts) != 0 ||
            memcmp(x->uvw, y->uvw, sizeof(float) * 3 * (size_t)x->nverts) != 0)
            return 0;
    }
    return 1;
}

static void t_lst_coverage(void)
{
    lst_options opt = lst_default_options();
    lst_mesh surface;
    lst_tetmesh tets;
    lst_volume ex;
    lst_source src;
    lst_model ref, m;
    int threads, calls = reverse_calls;
    opt.tet.target_tets = 3000, opt.tet.uniform = 1;
    REQUIRE(lst_builtin_mesh("sphere", &opt, &surface, NULL) == LST_OK);
    REQUIRE(lst_tetrahedralize(&surface, &opt, &tets, NULL, NULL) == LST_OK);
    REQUIRE(lst_builtin_exemplar("spots", 32, &opt, &ex, NULL, NULL) == LST_OK);
    src.exemplar = &ex, src.values = NULL;
    opt.threads = 1;
    REQUIRE(lst_create(&tets, &surface, &src, &opt, &ref, NULL) == LST_OK);
    for (threads = 2; threads <= 4; threads++) {
        opt.threads = threads == 4 ? 0 : threads;
        opt.parallel = threads == 4 ? reverse_for : NULL;
        REQUIRE(lst_create(&tets, &surface, &src, &opt, &m, NULL) == LST_OK);
        CHECKF(lst_same(&ref, &m), "lst coverage: the pastes %s differ from one thread's",
               threads == 4 ? "through a reversed parallel-for" : threads == 2 ? "on 2 threads" : "on 3 threads");
        lst_model_free(&m);
    }
    CHECKF(reverse_calls > calls, "lst coverage: the caller's parallel-for was not used");
    pwt_info("lst coverage: %d pastes, %d calls of the parallel-for", ref.npastes, reverse_calls - calls);
    opt.threads = -1, opt.parallel = NULL;
    CHECK(lst_create(&tets, &surface, &src, &opt, &m, NULL) == LST_ERR_INVALID);
    lst_model_free(&ref);
    lst_volume_free(&ex);
    lst_tetmesh_free(&tets);
    lst_mesh_free(&surface);
}

/* ---- the crew: threads kept between parallel-fors ---- */

/* One task set: hits[i] counts the runs of task i; a task of a nested set
 * runs an inner parallel-for on the same crew. Threads that ran a task
 * count themselves out when they end (the key's destructor). */
typedef struct crew_job {
    pthread_mutex_t lock;
    int hits[64], inner[64], nested, n;
    const pw_parallel *par;
} crew_job;

static pthread_key_t crew_key;
static int crew_exits;
static pthread_mutex_t crew_exit_lock = PTHREAD_MUTEX_INITIALIZER;

static void crew_exit(void *v)
{
    (void)v;
    pthread_mutex_lock(&crew_exit_lock);
    crew_exits++;
    pthread_mutex_unlock(&crew_exit_lock);
}

static void crew_inner(void *ctx, int i)
{
    crew_job *j = (crew_job *)ctx;
    pthread_mutex_lock(&j->lock);
    j->inner[i]++;
    pthread_mutex_unlock(&j->lock);
}

static void crew_task(void *ctx, int i)
{
    crew_job *j = (crew_job *)ctx;
    pthread_setspecific(crew_key, j);
    pthread_mutex_lock(&j->lock);
    j->hits[i]++;
    pthread_mutex_unlock(&j->lock);
    if (j->nested) pw_parallel_for(j->par, 5, crew_inner, j);
}

static int crew_exits_now(void)
{
    int n;
    pthread_mutex_lock(&crew_exit_lock);
    n = crew_exits;
    pthread_mutex_unlock(&crew_exit_lock);
    return n;
}

/* Runs `sets` task sets of sizes 1..17 on par; 1 if each task ran exactly once
 * (and, nested, each task's inner set of 5 once per task). */
static int crew_sets(const pw_parallel *par, int sets, int nested)
{
    crew_job j;
    int s, i, ok = 1;
    memset(&j, 0, sizeof j);
    pthread_mutex_init(&j.lock, NULL);
    j.par = par;
    j.nested = nested;
    for (s = 0; s < sets && ok; s++) {
        int n = 1 + s % 17;
        memset(j.hits, 0, sizeof j.hits);
        memset(j.inner, 0, sizeof j.inner);
        pw_parallel_for(par, n, crew_task, &j);
        for (i = 0; i < 64; i++) ok &= j.hits[i] == (i < n) && j.inner[i] == (nested && i < 5 ? n : 0);
    }
    pthread_mutex_destroy(&j.lock);
    return ok;
}

static void t_crew(void)
{
    pw_parallel par;
    int threads, exits;
    REQUIRE(pthread_key_create(&crew_key, crew_exit) == 0);
    for (threads = 2; threads <= 3; threads++) {
        par = pw_parallel_make(threads, NULL, NULL);
        pw_parallel_start(&par);
        REQUIRE(par.crew != NULL);
        CHECKF(par.crew->nthreads == threads - 1, "crew of %d: %d threads started", threads, par.crew->nthreads);
        exits = crew_exits_now();
        CHECKF(crew_sets(&par, 3000, 0), "crew of %d: a task of 3000 parallel-fors ran other than once", threads);
        CHECKF(crew_exits_now() == exits, "crew of %d: %d threads ended during its parallel-fors", threads,
               crew_exits_now() - exits);
        CHECKF(crew_sets(&par, 200, 1), "crew of %d: a parallel-for inside a task ran other than once", threads);
        pw_parallel_stop(&par);
        CHECK(par.crew == NULL);
        CHECKF(crew_exits_now() - exits <= threads - 1, "crew of %d: %d threads ended at its stop", threads,
               crew_exits_now() - exits);
        pw_parallel_stop(&par); /* a second stop does nothing */
    }
    exits = crew_exits_now(); /* without a crew, each parallel-for starts (and ends) its threads */
    par = pw_parallel_make(2, NULL, NULL);
    CHECK(crew_sets(&par, 200, 0));
    pwt_info("crew: without one, %d threads ended over 200 parallel-fors", crew_exits_now() - exits);
    par = pw_parallel_make(1, NULL, NULL); /* one thread: no crew, tasks in order here */
    pw_parallel_start(&par);
    CHECK(par.crew == NULL);
    CHECK(crew_sets(&par, 100, 1));
    par = pw_parallel_make(3, reverse_for, NULL); /* the caller's parallel-for: no crew, the caller's runs */
    pw_parallel_start(&par);
    CHECK(par.crew == NULL);
    exits = reverse_calls;
    CHECK(crew_sets(&par, 100, 0));
    CHECKF(reverse_calls == exits + 100, "crew: the caller's parallel-for ran %d of 100 sets", reverse_calls - exits);
    pw_parallel_stop(&par);
    pthread_key_delete(crew_key);
}

static const pwt_case cases[] = {
    {"threads_tiled", t_tiled},
    {"threads_tiled_synthesis", t_tiled_synthesis},
    {"threads_pgp_synthesis", t_pgp_synthesis},
    {"threads_lapped", t_lapped},
    {"threads_lapped_coverage", t_lapped_coverage},
    {"threads_pgp", t_pgp},
    {"threads_pgp_create", t_pgp_create},
    {"threads_pgp_create_nomem", t_pgp_create_nomem},
    {"threads_lst", t_lst},
    {"threads_lst_coverage", t_lst_coverage},
    {"threads_crew", t_crew},
};
PWT_MAIN(cases)
