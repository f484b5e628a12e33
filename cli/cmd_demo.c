/* cmd_demo.c: `patchwork demo [--quick] [DIR]`, every method on built-in data. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "cli.h"

/* --quick: every scene through the same calls with smaller images,
 * exemplars, tiles and tetrahedral meshes (for runs under valgrind). */
static int demo_quick;

/* Quick mode: a size divided by `by`, at least `floor_`. */
static int demo_size(int full, int by, int floor_)
{
    int q = full / by;
    return demo_quick ? (q > floor_ ? q : floor_) : full;
}

/* Quick mode: a small picture with one sample per pixel. */
#define DEMO_QUICK_VIEW(ro)                                                        \
    do {                                                                           \
        if (demo_quick) (ro).width = 200, (ro).height = 150, (ro).supersample = 1; \
    } while (0)

typedef struct demo_scene {
    const char *name, *mesh, *exemplar;
    int subdivide, smooth, case_number, pairs_or_grid, exemplar_size;
    float view[3];
} demo_scene;

static const demo_scene tiled_scenes[] = {
    {"tiled_double_torus", "double-torus", "pebbles", 0, 2, 2, 1, 128, {-0.35f, -0.55f, -0.75f}},
    {"tiled_torus", "torus", "spots", 0, 1, 2, 2, 64, {-0.3f, -0.5f, -0.8f}},
    {"tiled_cube_case1", "cube", "lichen", 1, 2, 1, 4, 128, {-0.6f, -0.5f, -0.62f}},
    {"tiled_icosahedron", "icosahedron", "pebbles", 0, 2, 2, 1, 128, {-0.5f, -0.4f, -0.75f}},
    {"tiled_grid", "grid", "spots", 0, 1, 2, 1, 128, {-0.2f, -0.7f, -0.65f}},
};

/* Writes img as DIR/NAME.ppm and DIR/NAME.png, reporting each file. */
static tiled_result demo_write(const char *dir, const char *name, const tiled_image *img, tiled_error *err)
{
    static const char *const ext[2] = {"ppm", "png"};
    char path[1024];
    cli_outputs outs;
    int k;
    for (k = 0; k < 2; k++) {
        memset(&outs, 0, sizeof outs);
        snprintf(path, sizeof path, "%s/%s.%s", dir, name, ext[k]);
        if (cli_write_image(&outs, path, img, err) != TILED_OK) {
            cli_abort(&outs);
            return err->code;
        }
        if (cli_commit(&outs, err) != TILED_OK) return err->code;
        printf("wrote %s (%dx%d)\n", path, img->width, img->height);
    }
    return TILED_OK;
}

/* Any header's image (lapped_image, pgp_image, lst_image: the same fields)
 * written by demo_write. */
static tiled_result demo_write_pixels(const char *dir, const char *name, int width, int height, int channels,
                                      float *pixels, tiled_error *err)
{
    tiled_image view;
    memset(&view, 0, sizeof view);
    view.width = width;
    view.height = height;
    view.channels = channels;
    view.pixels = pixels;
    return demo_write(dir, name, &view, err);
}
#define DEMO_WRITE(dir, name, img, err) \
    demo_write_pixels(dir, name, (img)->width, (img)->height, (img)->channels, (img)->pixels, err)

/* Any header's error (lapped_error, pgp_error, lst_error) as the demo's;
 * the result codes are the same numbers in every header. */
static tiled_result demo_error(int code, const char *message, tiled_error *err)
{
    err->code = (tiled_result)code;
    snprintf(err->message, sizeof err->message, "%s", message);
    return err->code;
}
#define DEMO_ERROR(e, err) demo_error((int)(e)->code, (e)->message, err)

static tiled_result demo_tiled_scene(const char *dir, const demo_scene *s, tiled_error *err)
{
    tiled_options o = tiled_default_options();
    tiled_mesh mesh, quads;
    tiled_image ex, pic;
    tiled_tileset ts;
    tiled_result r;
    char name[256];
    memset(&ts, 0, sizeof ts);
    memset(&quads, 0, sizeof quads);
    memset(&pic, 0, sizeof pic);
    memcpy(o.render.view_dir, s->view, sizeof o.render.view_dir);
    DEMO_QUICK_VIEW(o.render);
    o.subdivide = s->subdivide;
    o.smooth = s->smooth;
    o.layout.case_number = s->case_number;
    if (s->case_number == 1) o.layout.grid = s->pairs_or_grid;
    else o.layout.pairs = s->pairs_or_grid;
    if ((r = tiled_builtin_mesh(s->mesh, &o, &mesh, err)) != TILED_OK) return r;
    if ((r = tiled_builtin_exemplar(s->exemplar, demo_size(s->exemplar_size, 2, 32), &o, &ex, err)) == TILED_OK &&
        (r = tiled_synthesize(&ex, &o, &ts, err)) == TILED_OK &&
        (r = tiled_map(&mesh, &ts.layout, &o, &quads, err)) == TILED_OK &&
        (r = tiled_render(&quads, &ts, &o.render, &pic, err)) == TILED_OK) {
        snprintf(name, sizeof name, "%s_tiles", s->name);
        if ((r = demo_write(dir, s->name, &pic, err)) == TILED_OK) r = demo_write(dir, name, &ts.atlas, err);
    }
    tiled_image_free(&pic);
    tiled_mesh_free(&quads);
    tiled_tileset_free(&ts);
    tiled_image_free(&ex);
    tiled_mesh_free(&mesh);
    return r;
}

typedef struct lapped_scene {
    const char *name, *mesh, *texture;
    int field, atlas;
    float scale, view[3];
} lapped_scene;

static const lapped_scene lapped_scenes[] = {
    {"lapped_bumpy_scales", "bumpy", "scales", LAPPED_FIELD_UP, 1, 0.45f, {-0.3f, -0.35f, -0.9f}},
    {"lapped_torus_stripes", "torus", "stripes", LAPPED_FIELD_CURVATURE, 0, 0.5f, {-0.2f, -0.6f, -0.75f}},
    {"lapped_sphere_dots", "sphere", "dots", LAPPED_FIELD_ISOTROPIC, 0, 0.5f, {-0.4f, -0.3f, -0.85f}},
};

/* A lapped scene: the patch, the runtime-pasting render and, for some, the
 * texture atlas. */
static tiled_result demo_lapped_scene(const char *dir, const lapped_scene *s, tiled_error *err)
{
    lapped_options o = lapped_default_options();
    lapped_source src;
    lapped_mesh mesh;
    lapped_image tex, patch, pic;
    lapped_texture t;
    lapped_atlas atlas;
    lapped_error le;
    tiled_result r = TILED_OK;
    char name[256];
    memset(&t, 0, sizeof t);
    memset(&pic, 0, sizeof pic);
    memset(&patch, 0, sizeof patch);
    memset(&atlas, 0, sizeof atlas);
    memcpy(o.render.view_dir, s->view, sizeof o.render.view_dir);
    DEMO_QUICK_VIEW(o.render);
    o.field = s->field;
    o.scale = s->scale;
    src.patches = &patch;
    src.npatches = 1;
    src.values = NULL;
    if (lapped_builtin_mesh(s->mesh, &o, &mesh, &le) != LAPPED_OK) return DEMO_ERROR(&le, err);
    if (lapped_builtin_exemplar(s->texture, demo_size(128, 2, 64), &o, &tex, &le) != LAPPED_OK ||
        lapped_make_patch(&tex, NULL, &o, &patch, &le) != LAPPED_OK ||
        lapped_create(&mesh, &src, &o, &t, &le) != LAPPED_OK ||
        lapped_render(&mesh, &t, &src, &o.render, &pic, &le) != LAPPED_OK ||
        (s->atlas && lapped_bake_atlas(&mesh, &t, &src, &o, &atlas, &le) != LAPPED_OK)) {
        r = DEMO_ERROR(&le, err);
    }
    if (r == TILED_OK) r = DEMO_WRITE(dir, s->name, &pic, err);
    snprintf(name, sizeof name, "%s_patch", s->name);
    if (r == TILED_OK) r = DEMO_WRITE(dir, name, &patch, err);
    snprintf(name, sizeof name, "%s_atlas", s->name);
    if (r == TILED_OK && s->atlas) r = DEMO_WRITE(dir, name, &atlas.image, err);
    lapped_atlas_free(&atlas);
    lapped_image_free(&pic);
    lapped_texture_free(&t);
    lapped_image_free(&patch);
    lapped_image_free(&tex);
    lapped_mesh_free(&mesh);
    return r;
}

typedef struct pgp_scene {
    const char *name, *mesh, *tile;
    pgp_field_mode field;
    float scale, view[3];
    float fresh[3], weathered[3]; /* material 0 / 1 on the side of the mesh this way; 0: none */
} pgp_scene;

static const pgp_scene pgp_scenes[] = {
    {"pgp_bumpy_bricks",
     "bumpy",
     "bricks",
     PGP_FIELD_UP,
     0.5f,
     {-0.3f, -0.35f, -0.9f},
     {-0.48f, 0.57f, 0.67f},
     {0.92f, -0.26f, 0.28f}},
    {"pgp_torus_stripes",
     "torus",
     "stripes",
     PGP_FIELD_CURVATURE,
     0.6f,
     {-0.2f, -0.6f, -0.75f},
     {0.0f, 0.0f, 0.0f},
     {0.0f, 0.0f, 0.0f}},
};

/* The layers of a tile side by side, m growing to the right. */
static tiled_result demo_pgp_tile(const char *dir, const char *name, const pgp_tile *t, tiled_error *err)
{
    tiled_image strip;
    tiled_result r;
    int y, k, row = t->width * t->channels;
    memset(&strip, 0, sizeof strip);
    strip.width = t->width * t->layers;
    strip.height = t->height;
    strip.channels = t->channels;
    if (!(strip.pixels = (float *)malloc(sizeof(float) * (size_t)row * t->layers * t->height))) {
        err->code = TILED_ERR_NOMEM;
        snprintf(err->message, sizeof err->message, "out of memory");
        return err->code;
    }
    for (k = 0; k < t->layers; k++)
        for (y = 0; y < t->height; y++)
            memcpy(strip.pixels + ((size_t)y * t->layers + k) * row, t->pixels + ((size_t)k * t->height + y) * row,
                   sizeof(float) * (size_t)row);
    r = demo_write(dir, name, &strip, err);
    free(strip.pixels);
    return r;
}

/* Material constraints (§2.2): m = 0 at the vertices whose direction from
 * the origin is within about 37 degrees of s->fresh, m = 1 near
 * s->weathered. Each recomputes a small area; the last one the whole mesh,
 * so that m runs smoothly from one side to the other. */
static pgp_result demo_pgp_weather(const pgp_scene *s, const pgp_mesh *mesh, pgp_map *map, pgp_error *pe)
{
    pgp_result r = PGP_OK;
    pgp_constraint c;
    int v, last = -1;
    memset(&c, 0, sizeof c);
    c.kind = PGP_CONSTRAINT_MATERIAL;
    for (v = 0; v < mesh->nverts && r == PGP_OK; v++) {
        const float *p = mesh->positions + 3 * v;
        float l = sqrtf(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        float d0 = l > 0.0f ? (p[0] * s->fresh[0] + p[1] * s->fresh[1] + p[2] * s->fresh[2]) / l : 0.0f;
        float d1 = l > 0.0f ? (p[0] * s->weathered[0] + p[1] * s->weathered[1] + p[2] * s->weathered[2]) / l : 0.0f;
        c.element = v;
        c.value[0] = d1 > 0.8f ? 1.0f : 0.0f;
        c.radius = 0.1f;
        if (d0 > 0.8f || d1 > 0.8f) r = pgp_add_constraint(map, &c, NULL, NULL, pe);
        if (d0 > 0.8f) last = v;
    }
    c.element = last;
    c.value[0] = 0.0f;
    c.radius = 0.0f;
    if (r == PGP_OK && last >= 0) r = pgp_add_constraint(map, &c, NULL, NULL, pe);
    return r;
}

/* A pgp scene: the rendering, a second view (the material for a weathered
 * scene, else the singular triangles and the rendering without the §3
 * fix), and the tile's layers. */
static tiled_result demo_pgp_scene(const char *dir, const pgp_scene *s, tiled_error *err)
{
    pgp_options o = pgp_default_options();
    pgp_render_options ro;
    pgp_mesh mesh;
    pgp_tile tile;
    pgp_image pic[3];
    pgp_map map;
    pgp_error pe;
    tiled_result r = TILED_OK;
    int weather = s->weathered[0] != 0.0f || s->weathered[1] != 0.0f || s->weathered[2] != 0.0f, k;
    static const char *const suffix[2][3] = {{"", "_singular", "_nofix"}, {"", "_material", NULL}};
    char name[256];
    memset(&ro, 0, sizeof ro);
    memset(pic, 0, sizeof pic);
    memset(&tile, 0, sizeof tile);
    memset(&map, 0, sizeof map);
    memcpy(ro.view_dir, s->view, sizeof ro.view_dir);
    DEMO_QUICK_VIEW(ro);
    o.field = s->field;
    o.scale = s->scale;
    if (pgp_builtin_mesh(s->mesh, &o, &mesh, &pe) != PGP_OK) return DEMO_ERROR(&pe, err);
    if (pgp_builtin_tile(s->tile, demo_size(256, 4, 64), &o, &tile, &pe) != PGP_OK ||
        pgp_create(&mesh, &o, &map, &pe) != PGP_OK || (weather && demo_pgp_weather(s, &mesh, &map, &pe) != PGP_OK))
        r = DEMO_ERROR(&pe, err);
    for (k = 0; k < 3 && r == TILED_OK && suffix[weather][k]; k++) {
        ro.show = k == 1 ? (weather ? PGP_SHOW_MATERIAL : PGP_SHOW_SPECIAL) : PGP_SHOW_TILE;
        ro.fix = k == 2 ? PGP_FIX_OFF : PGP_FIX_CLEAN;
        if (pgp_render(&map, &tile, &ro, &pic[k], &pe) != PGP_OK) r = DEMO_ERROR(&pe, err);
        snprintf(name, sizeof name, "%s%s", s->name, suffix[weather][k]);
        if (r == TILED_OK) r = DEMO_WRITE(dir, name, &pic[k], err);
    }
    snprintf(name, sizeof name, "%s_tile", s->name);
    if (r == TILED_OK) r = demo_pgp_tile(dir, name, &tile, err);
    for (k = 0; k < 3; k++) pgp_image_free(&pic[k]);
    pgp_map_free(&map);
    pgp_tile_free(&tile);
    pgp_mesh_free(&mesh);
    return r;
}

typedef struct lst_scene {
    const char *name, *surface, *exemplar;
    int type, tets;
    float view[3], up[3], cuts[2][4]; /* a section face on per cut (normal zero: none) */
    float displace;
    int volume;
} lst_scene;

static const lst_scene lst_scenes[] = {
    {"lst_kiwi",
     "kiwi",
     "kiwi",
     LST_TYPE_2B,
     6000,
     {-0.5f, -0.6f, -0.6f},
     {0, 0, 1},
     {{0, 0, 1, 0.15f}, {0, 1, 0, 0}},
     0.0f,
     1},
    {"lst_tree",
     "tree",
     "rings",
     LST_TYPE_2B,
     9000,
     {-0.6f, 0.8f, -0.1f},
     {0, 0, 1},
     {{0, 0, 1, -0.4f}, {1, 0, 0, 0}},
     0.03f,
     0},
    {"lst_layers",
     "sphere",
     "layers",
     LST_TYPE_1B,
     5000,
     {-0.55f, -0.45f, -0.7f},
     {0, 1, 0},
     {{0.3f, 0.3f, 1, 0.2f}, {0, 0, 0, 0}},
     0.0f,
     0},
    {"lst_fibers",
     "torus",
     "fibers",
     LST_TYPE_1A,
     6000,
     {-0.3f, -0.5f, -0.8f},
     {0, 1, 0},
     {{1, 0, 0, 0.4f}, {0, 0, 0, 0}},
     0.0f,
     0},
    {"lst_spots",
     "bumpy",
     "spots",
     LST_TYPE_0,
     5000,
     {-0.3f, -0.35f, -0.9f},
     {0, 1, 0},
     {{0, 0, 1, 0}, {0, 0, 0, 0}},
     0.0f,
     0},
};

/* The model of a scene: built-in surface, tetrahedralized, filled with its
 * built-in constraints (kiwi and tree) or the default fields. */
static lst_result demo_lst_model(const lst_scene *s, lst_options *o, lst_model *m, lst_error *le)
{
    lst_mesh surf;
    lst_tetmesh tets;
    lst_volume ex, val;
    lst_source src;
    lst_constraints c;
    lst_result r;
    memset(&c, 0, sizeof c);
    memset(&tets, 0, sizeof tets);
    memset(&ex, 0, sizeof ex);
    memset(&val, 0, sizeof val);
    o->tet.target_tets = demo_size(s->tets, 5, 1000);
    if (demo_quick) o->tet.fit = 0.02; /* the graded lattice, coarser */
    o->type = s->type;
    if ((r = lst_builtin_mesh(s->surface, o, &surf, le)) != LST_OK) return r;
    if ((r = lst_tetrahedralize(&surf, o, &tets, NULL, le)) == LST_OK &&
        (r = lst_builtin_exemplar(s->exemplar, demo_size(64, 2, 32), o, &ex, &val, le)) == LST_OK &&
        (strcmp(s->surface, "kiwi") && strcmp(s->surface, "tree") && strcmp(s->surface, "torus")
             ? LST_OK
             : (r = lst_builtin_constraints(s->surface, &surf, o, &c, le))) == LST_OK) {
        o->constraints = c.items;
        o->nconstraints = c.count;
        src.exemplar = &ex;
        src.values = &val;
        r = lst_create(&tets, &surf, &src, o, m, le);
    }
    lst_constraints_free(&c);
    lst_volume_free(&ex);
    lst_volume_free(&val);
    lst_tetmesh_free(&tets);
    lst_mesh_free(&surf);
    return r;
}

/* One section: the cut, the cut part face on, then everything back. */
static tiled_result demo_lst_section(const char *dir, const lst_scene *s, int k, lst_model *m, lst_render_options ro,
                                     tiled_error *err)
{
    lst_image pic;
    lst_error le;
    tiled_result r;
    char name[256];
    int j;
    memset(&pic, 0, sizeof pic);
    for (j = 0; j < 3; j++) ro.view_dir[j] = -s->cuts[k][j];
    if (fabsf(s->cuts[k][2]) > 0.9f) {
        ro.up[0] = 0;
        ro.up[1] = 1;
        ro.up[2] = 0;
    }
    ro.displace = 0.0f;
    if (lst_cut_plane(m, s->cuts[k], &le) != LST_OK || lst_render(m, &ro, &pic, &le) != LST_OK)
        return DEMO_ERROR(&le, err);
    snprintf(name, sizeof name, "%s_section%d", s->name, k + 1);
    r = DEMO_WRITE(dir, name, &pic, err);
    lst_image_free(&pic);
    lst_uncut(m);
    return r;
}

/* A lst scene: the surface, a section per cut, the cut model in its
 * view, and for some a volume rendering. */
static tiled_result demo_lst_scene(const char *dir, const lst_scene *s, tiled_error *err)
{
    lst_options o = lst_default_options();
    lst_render_options ro;
    lst_volume_options vo;
    lst_model m;
    lst_image pic;
    lst_error le;
    tiled_result r = TILED_OK;
    char name[256];
    int k;
    memset(&ro, 0, sizeof ro);
    memset(&vo, 0, sizeof vo);
    memset(&pic, 0, sizeof pic);
    ro.width = demo_size(600, 4, 150);
    ro.height = demo_size(500, 4, 125);
    memcpy(ro.view_dir, s->view, sizeof ro.view_dir);
    memcpy(ro.up, s->up, sizeof ro.up);
    ro.displace = s->displace;
    if (demo_lst_model(s, &o, &m, &le) != LST_OK) return DEMO_ERROR(&le, err);
    if (lst_render(&m, &ro, &pic, &le) != LST_OK) r = DEMO_ERROR(&le, err);
    if (r == TILED_OK) r = DEMO_WRITE(dir, s->name, &pic, err);
    lst_image_free(&pic);
    for (k = 0; k < 2 && r == TILED_OK; k++)
        if (s->cuts[k][0] || s->cuts[k][1] || s->cuts[k][2]) r = demo_lst_section(dir, s, k, &m, ro, err);
    ro.displace = 0.0f;
    for (k = 0; k < 3; k++) ro.view_dir[k] = s->view[k] - s->cuts[0][k]; /* tilted towards the cut face */
    if (r == TILED_OK && (lst_cut_plane(&m, s->cuts[0], &le) != LST_OK || lst_render(&m, &ro, &pic, &le) != LST_OK))
        r = DEMO_ERROR(&le, err);
    snprintf(name, sizeof name, "%s_cut", s->name);
    if (r == TILED_OK) r = DEMO_WRITE(dir, name, &pic, err);
    lst_image_free(&pic);
    lst_uncut(&m);
    memcpy(ro.view_dir, s->view, sizeof ro.view_dir);
    ro.width = demo_size(400, 4, 100);
    ro.height = demo_size(330, 4, 83);
    vo.slices = demo_size(200, 4, 50);
    if (r == TILED_OK && s->volume && lst_render_volume(&m, &ro, &vo, &pic, &le) != LST_OK) r = DEMO_ERROR(&le, err);
    snprintf(name, sizeof name, "%s_volume", s->name);
    if (r == TILED_OK && s->volume) r = DEMO_WRITE(dir, name, &pic, err);
    lst_image_free(&pic);
    lst_model_free(&m);
    return r;
}

/* Tile synthesis (pgp.h §1): the built-in bricks' first layer morphed into
 * its last (pebbles) by pgp_synthesize_tile, 6 layers of 128 x 128, written
 * side by side; a couple of seconds. */
static tiled_result demo_pgp_synth(const char *dir, tiled_error *err)
{
    pgp_synth_options so = pgp_default_options().synth;
    pgp_tile bricks, tile;
    pgp_image key[2];
    pgp_key keys[2];
    pgp_error pe;
    tiled_result r = TILED_OK;
    int k;
    const int size = demo_size(128, 4, 32);
    if (pgp_builtin_tile("bricks", size, NULL, &bricks, &pe) != PGP_OK) return DEMO_ERROR(&pe, err);
    for (k = 0; k < 2; k++) {
        memset(&key[k], 0, sizeof key[k]);
        key[k].width = key[k].height = size;
        key[k].channels = bricks.channels;
        key[k].pixels = bricks.pixels + (size_t)k * (bricks.layers - 1) * size * size * bricks.channels;
        keys[k].image = &key[k];
        keys[k].mask = NULL;
    }
    so.size = size;
    so.layers = demo_size(6, 2, 3);
    if (pgp_synthesize_tile(keys, 2, &so, &tile, NULL, &pe) != PGP_OK) r = DEMO_ERROR(&pe, err);
    else r = demo_pgp_tile(dir, "pgp_synth_bricks_pebbles", &tile, err);
    pgp_tile_free(&tile);
    pgp_tile_free(&bricks);
    return r;
}

int cmd_demo(int argc, char **argv)
{
    const char *dir;
    tiled_error err;
    size_t k;
    if (argc > 1 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h"))) {
        printf("usage: patchwork demo [--quick] [DIR]\n\nRenders every method on built-in meshes and "
               "exemplars into DIR (default out/), as PPM and PNG.\n"
               "--quick: the same scenes and calls with small images, exemplars, tiles and\n"
               "         tetrahedral meshes (a few seconds; for checkers such as valgrind).\n");
        return 0;
    }
    demo_quick = argc > 1 && !strcmp(argv[1], "--quick");
    argc -= demo_quick;
    argv += demo_quick;
    if (argc > 2 || (argc > 1 && argv[1][0] == '-')) {
        cli_error("demo", "usage: patchwork demo [--quick] [DIR]");
        return 1;
    }
    dir = argc > 1 ? argv[1] : "out";
    if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
        cli_error("demo", "%s: cannot create folder (%s)", dir, strerror(errno));
        return 1;
    }
    for (k = 0; k < sizeof tiled_scenes / sizeof tiled_scenes[0]; k++) {
        if (demo_tiled_scene(dir, &tiled_scenes[k], &err) != TILED_OK) {
            cli_error("demo", "%s: %s", tiled_scenes[k].name, err.message);
            return 1;
        }
    }
    for (k = 0; k < sizeof lapped_scenes / sizeof lapped_scenes[0]; k++)
        if (demo_lapped_scene(dir, &lapped_scenes[k], &err) != TILED_OK) {
            cli_error("demo", "%s: %s", lapped_scenes[k].name, err.message);
            return 1;
        }
    for (k = 0; k < sizeof pgp_scenes / sizeof pgp_scenes[0]; k++)
        if (demo_pgp_scene(dir, &pgp_scenes[k], &err) != TILED_OK) {
            cli_error("demo", "%s: %s", pgp_scenes[k].name, err.message);
            return 1;
        }
    if (demo_pgp_synth(dir, &err) != TILED_OK) {
        cli_error("demo", "pgp_synth_bricks_pebbles: %s", err.message);
        return 1;
    }
    for (k = 0; k < sizeof lst_scenes / sizeof lst_scenes[0]; k++)
        if (demo_lst_scene(dir, &lst_scenes[k], &err) != TILED_OK) {
            cli_error("demo", "%s: %s", lst_scenes[k].name, err.message);
            return 1;
        }
    return 0;
}
