/* Tests of the compute-only build (PW_NO_RENDER and PW_NO_PNG, issue 19):
 * all four headers in one translation unit, each method run end to end on
 * its built-in data with what stays available (OBJ, PPM, pastes, model
 * files), and every call whose feature is compiled out failing with
 * X_ERR_UNSUPPORTED and a message naming the macro: rendering, PNG load
 * and save (from memory and from files, leaving no file behind), glTF with
 * a PNG texture. */
#define PW_NO_RENDER
#define PW_NO_PNG
#define PATCHWORK_IMPLEMENTATION
#include "../tiled.h"
#include "../lapped.h"
#include "../pgp.h"
#include "../lst.h"
#include "pwtest.h"

/* A 1x1 gray PNG (a valid file: signature, IHDR, IDAT, IEND). */
static const unsigned char png_1x1[] = {
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52,
    0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x08, 0x00, 0x00, 0x00, 0x00, 0x3a, 0x7e, 0x9b,
    0x55, 0x00, 0x00, 0x00, 0x0a, 0x49, 0x44, 0x41, 0x54, 0x78, 0x9c, 0x63, 0x60, 0x00, 0x00, 0x00,
    0x02, 0x00, 0x01, 0x48, 0xaf, 0xa4, 0x71, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae,
    0x42, 0x60, 0x82};

/* A writer that counts bytes (what stays available still writes). */
static int count_bytes(void *ctx, const void *data, size_t size)
{
    (void)data;
    *(size_t *)ctx += size;
    return 0;
}

static int file_exists(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (f) fclose(f);
    return f != NULL;
}

/* A PNG file on disk, for the loaders. */
static const char *png_file(void)
{
    const char *path = pwt_tmp("norender", 0, ".png");
    FILE *f = fopen(path, "wb");
    if (f) {
        fwrite(png_1x1, 1, sizeof png_1x1, f);
        fclose(f);
    }
    return path;
}

/* The error of a compiled-out call: UNSUPPORTED (4 in every header) and
 * the macro named. */
#define CHECK_LEFT_OUT(call, err, macro)                                                                   \
    do {                                                                                                   \
        int r_ = (int)(call);                                                                              \
        CHECKF(r_ == 4 && strstr((err).message, macro) != NULL, "%s: %d '%s'", #call, r_, (err).message); \
    } while (0)

static void t_tiled(void)
{
    tiled_options opt = tiled_default_options();
    tiled_mesh mesh = {0}, mapped = {0};
    tiled_image exemplar = {0}, picture = {0}, loaded = {0};
    tiled_tileset tiles = {0};
    tiled_error err;
    size_t n = 0;
    const char *ppm = pwt_tmp("norender_tiled", 1, ".ppm"), *png = pwt_tmp("norender_tiled", 2, ".png");
    const char *glb = pwt_tmp("norender_tiled", 3, ".glb");
    opt.layout.pairs = 1;
    opt.seed = 42;
    REQUIRE(tiled_builtin_mesh("double-torus", &opt, &mesh, &err) == TILED_OK);
    REQUIRE(tiled_builtin_exemplar("pebbles", 64, &opt, &exemplar, &err) == TILED_OK);
    REQUIRE(tiled_synthesize(&exemplar, &opt, &tiles, &err) == TILED_OK);
    REQUIRE(tiled_map(&mesh, &tiles.layout, &opt, &mapped, &err) == TILED_OK);
    CHECK(mapped.nfaces > 0 && mapped.uvs != NULL);
    CHECK(tiled_write_obj(&mapped, NULL, count_bytes, &n, &err) == TILED_OK && n > 0);
    CHECK(tiled_save_image(ppm, &tiles.atlas, &err) == TILED_OK);
    CHECK(tiled_load_image(ppm, &opt, &loaded, &err) == TILED_OK && loaded.width == tiles.atlas.width);
    remove(ppm);
    CHECK_LEFT_OUT(tiled_render(&mapped, &tiles, &opt.render, &picture, &err), err, "PW_NO_RENDER");
    CHECK(picture.pixels == NULL);
    CHECK_LEFT_OUT(tiled_write_image(&tiles.atlas, "png", count_bytes, &n, &err), err, "PW_NO_PNG");
    CHECK_LEFT_OUT(tiled_save_image(png, &tiles.atlas, &err), err, "PW_NO_PNG");
    CHECK(!file_exists(png));
    CHECK_LEFT_OUT(tiled_save_gltf(glb, &mapped, &tiles.atlas, NULL, &err), err, "PW_NO_PNG");
    CHECK(!file_exists(glb));
    CHECK(tiled_save_gltf(glb, &mapped, NULL, NULL, &err) == TILED_OK && file_exists(glb)); /* untextured */
    remove(glb);
    tiled_image_free(&loaded);
    CHECK_LEFT_OUT(tiled_read_image(png_1x1, sizeof png_1x1, "x.png", &opt, &loaded, &err), err, "PW_NO_PNG");
    CHECK_LEFT_OUT(tiled_load_image(png_file(), &opt, &loaded, &err), err, "PW_NO_PNG");
    CHECK(loaded.pixels == NULL);
    remove(png_file());
    tiled_mesh_free(&mapped), tiled_mesh_free(&mesh);
    tiled_tileset_free(&tiles);
    tiled_image_free(&exemplar);
}

static void t_lapped(void)
{
    lapped_options opt = lapped_default_options();
    lapped_mesh mesh = {0};
    lapped_image texture = {0}, patch = {0}, picture = {0}, loaded = {0};
    lapped_source src = {0};
    lapped_texture lt = {0};
    lapped_atlas atlas = {0};
    lapped_error err;
    size_t n = 0;
    const char *ppm = pwt_tmp("norender_lapped", 1, ".ppm"), *png = pwt_tmp("norender_lapped", 2, ".png");
    opt.seed = 42;
    opt.atlas.size = 256;
    src.patches = &patch, src.npatches = 1;
    REQUIRE(lapped_builtin_mesh("bumpy", &opt, &mesh, &err) == LAPPED_OK);
    REQUIRE(lapped_builtin_exemplar("scales", 64, &opt, &texture, &err) == LAPPED_OK);
    REQUIRE(lapped_make_patch(&texture, NULL, &opt, &patch, &err) == LAPPED_OK);
    REQUIRE(lapped_create(&mesh, &src, &opt, &lt, &err) == LAPPED_OK);
    CHECK(lt.npastes > 0);
    CHECK(lapped_write_pastes(&lt, count_bytes, &n, &err) == LAPPED_OK && n > 0);
    /* the atlas is baked by rasterizing charts: it stays */
    CHECK(lapped_bake_atlas(&mesh, &lt, &src, &opt, &atlas, &err) == LAPPED_OK && atlas.image.pixels != NULL);
    CHECK(lapped_save_image(ppm, &atlas.image, &err) == LAPPED_OK);
    remove(ppm);
    CHECK_LEFT_OUT(lapped_render(&mesh, &lt, &src, &opt.render, &picture, &err), err, "PW_NO_RENDER");
    CHECK(picture.pixels == NULL);
    CHECK_LEFT_OUT(lapped_save_image(png, &atlas.image, &err), err, "PW_NO_PNG");
    CHECK(!file_exists(png));
    CHECK_LEFT_OUT(lapped_load_image(png_file(), &opt, &loaded, &err), err, "PW_NO_PNG");
    remove(png_file());
    lapped_atlas_free(&atlas);
    lapped_texture_free(&lt);
    lapped_image_free(&patch), lapped_image_free(&texture);
    lapped_mesh_free(&mesh);
}

static void t_pgp(void)
{
    pgp_options opt = pgp_default_options();
    pgp_mesh mesh = {0};
    pgp_tile tile = {0};
    pgp_map map = {0};
    pgp_image picture = {0}, loaded = {0};
    pgp_error err;
    size_t n = 0;
    REQUIRE(pgp_builtin_mesh("bumpy", &opt, &mesh, &err) == PGP_OK);
    REQUIRE(pgp_builtin_tile("bricks", 32, &opt, &tile, &err) == PGP_OK);
    REQUIRE(pgp_create(&mesh, &opt, &map, &err) == PGP_OK);
    CHECK(map.ntris > 0);
    CHECK(pgp_write_obj(&mesh, &map, count_bytes, &n, &err) == PGP_OK && n > 0);
    CHECK_LEFT_OUT(pgp_render(&map, &tile, &opt.render, &picture, &err), err, "PW_NO_RENDER");
    CHECK(picture.pixels == NULL);
    CHECK_LEFT_OUT(pgp_load_image(png_file(), &opt, &loaded, &err), err, "PW_NO_PNG");
    remove(png_file());
    pgp_map_free(&map);
    pgp_tile_free(&tile);
    pgp_mesh_free(&mesh);
}

static void t_lst(void)
{
    lst_options opt = lst_default_options();
    lst_mesh surface = {0};
    lst_tetmesh mesh = {0};
    lst_volume exemplar = {0}, bumps = {0};
    lst_source source;
    lst_model model = {0};
    lst_image picture = {0}, loaded = {0};
    lst_error err;
    size_t n = 0;
    opt.seed = 42;
    opt.tet.target_tets = 1000;
    REQUIRE(lst_builtin_mesh("kiwi", &opt, &surface, &err) == LST_OK);
    REQUIRE(lst_builtin_exemplar("kiwi", 16, &opt, &exemplar, &bumps, &err) == LST_OK);
    REQUIRE(lst_tetrahedralize(&surface, &opt, &mesh, NULL, &err) == LST_OK);
    memset(&source, 0, sizeof source);
    source.exemplar = &exemplar;
    REQUIRE(lst_create(&mesh, &surface, &source, &opt, &model, &err) == LST_OK);
    CHECK(model.npastes > 0);
    CHECK(lst_write_model(&model, count_bytes, &n, &err) == LST_OK && n > 0);
    CHECK_LEFT_OUT(lst_render(&model, &opt.render, &picture, &err), err, "PW_NO_RENDER");
    CHECK_LEFT_OUT(lst_render_volume(&model, &opt.render, &opt.volume, &picture, &err), err, "PW_NO_RENDER");
    CHECK(picture.pixels == NULL);
    CHECK_LEFT_OUT(lst_load_image(png_file(), &opt, &loaded, &err), err, "PW_NO_PNG");
    remove(png_file());
    lst_model_free(&model);
    lst_volume_free(&exemplar), lst_volume_free(&bumps);
    lst_tetmesh_free(&mesh);
    lst_mesh_free(&surface);
}

static const pwt_case cases[] = {{"tiled", t_tiled}, {"lapped", t_lapped}, {"pgp", t_pgp}, {"lst", t_lst}};
PWT_MAIN(cases)
