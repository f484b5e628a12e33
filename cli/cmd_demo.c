/* cmd_demo.c: `patchwork demo [DIR]`, every method on built-in data. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include "cli.h"

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
static tiled_result demo_write(const char *dir, const char *name, const tiled_image *img,
                               tiled_error *err)
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

static tiled_result demo_tiled_scene(const char *dir, const demo_scene *s, tiled_error *err)
{
    tiled_options o = tiled_default_options();
    tiled_render_options ro;
    tiled_mesh mesh, quads;
    tiled_image ex, pic;
    tiled_tileset ts;
    tiled_result r;
    char name[256];
    memset(&ro, 0, sizeof ro);
    memset(&ts, 0, sizeof ts);
    memset(&quads, 0, sizeof quads);
    memset(&pic, 0, sizeof pic);
    memcpy(ro.view_dir, s->view, sizeof ro.view_dir);
    o.subdivide = s->subdivide;
    o.smooth = s->smooth;
    o.layout.case_number = s->case_number;
    if (s->case_number == 1) o.layout.grid = s->pairs_or_grid;
    else o.layout.pairs = s->pairs_or_grid;
    if ((r = tiled_builtin_mesh(s->mesh, &o, &mesh, err)) != TILED_OK) return r;
    if ((r = tiled_builtin_exemplar(s->exemplar, s->exemplar_size, &o, &ex, err)) == TILED_OK &&
        (r = tiled_synthesize(&ex, &o, &ts, err)) == TILED_OK &&
        (r = tiled_map(&mesh, &ts.layout, &o, &quads, err)) == TILED_OK &&
        (r = tiled_render(&quads, &ts, &ro, &pic, err)) == TILED_OK) {
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

static tiled_result demo_write_lapped(const char *dir, const char *name, const lapped_image *img,
                                      tiled_error *err)
{
    tiled_image view;
    memset(&view, 0, sizeof view);
    view.width = img->width;
    view.height = img->height;
    view.channels = img->channels;
    view.pixels = img->pixels;
    return demo_write(dir, name, &view, err);
}

static tiled_result demo_lapped_error(const lapped_error *le, tiled_error *err)
{
    err->code = (tiled_result)le->code;
    memcpy(err->message, le->message, sizeof err->message);
    return err->code;
}

/* A lapped scene: the patch, the runtime-pasting render and, for some, the
 * texture atlas. */
static tiled_result demo_lapped_scene(const char *dir, const lapped_scene *s, tiled_error *err)
{
    lapped_options o = lapped_default_options();
    lapped_render_options ro;
    lapped_mesh mesh;
    lapped_image tex, patch, pic;
    lapped_texture t;
    lapped_atlas atlas;
    lapped_error le;
    tiled_result r = TILED_OK;
    char name[256];
    memset(&ro, 0, sizeof ro);
    memset(&t, 0, sizeof t);
    memset(&pic, 0, sizeof pic);
    memset(&patch, 0, sizeof patch);
    memset(&atlas, 0, sizeof atlas);
    memcpy(ro.view_dir, s->view, sizeof ro.view_dir);
    o.field.mode = s->field;
    o.field.scale = s->scale;
    if (lapped_builtin_mesh(s->mesh, &o, &mesh, &le) != LAPPED_OK) return demo_lapped_error(&le, err);
    if (lapped_builtin_texture(s->texture, 128, &o, &tex, &le) != LAPPED_OK ||
        lapped_make_patch(&tex, NULL, &o, &patch, &le) != LAPPED_OK ||
        lapped_create(&mesh, &patch, 1, &o, &t, &le) != LAPPED_OK ||
        lapped_render(&mesh, &t, &patch, NULL, &ro, &pic, &le) != LAPPED_OK ||
        (s->atlas && lapped_bake_atlas(&mesh, &t, &patch, NULL, NULL, &o, &atlas, &le) != LAPPED_OK)) {
        r = demo_lapped_error(&le, err);
    }
    if (r == TILED_OK) r = demo_write_lapped(dir, s->name, &pic, err);
    snprintf(name, sizeof name, "%s_patch", s->name);
    if (r == TILED_OK) r = demo_write_lapped(dir, name, &patch, err);
    snprintf(name, sizeof name, "%s_atlas", s->name);
    if (r == TILED_OK && s->atlas) r = demo_write_lapped(dir, name, &atlas.image, err);
    lapped_atlas_free(&atlas);
    lapped_image_free(&pic);
    lapped_texture_free(&t);
    lapped_image_free(&patch);
    lapped_image_free(&tex);
    lapped_mesh_free(&mesh);
    return r;
}

int cmd_demo(int argc, char **argv)
{
    const char *dir = argc > 1 ? argv[1] : "out";
    tiled_error err;
    size_t k;
    if (argc > 2 || (argc > 1 && argv[1][0] == '-')) {
        if (argc > 1 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h"))) {
            printf("usage: patchwork demo [DIR]\n\nRenders every method on built-in meshes and "
                   "exemplars into DIR (default out/), as PPM and PNG.\n");
            return 0;
        }
        cli_error("demo", "usage: patchwork demo [DIR]");
        return 1;
    }
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
    return 0;
}
