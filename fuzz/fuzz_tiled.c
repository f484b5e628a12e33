/* fuzz_tiled: the tiled.h pipeline on fuzzed inputs. The first byte picks
 * the layout; the rest is a mesh (mapped, smoothed once) or, if it reads as
 * an image, an exemplar (synthesised into small tiles) and a hand-made
 * tiled texture (validated and wrapped). Any result is fine; crashes,
 * leaks and sanitizer reports are not. */
#define TILED_STATIC /* static: only what the target calls is compiled */
#define TILED_IMPLEMENTATION
#include "../tiled.h"
#include <stdint.h>

static void run_mesh(const uint8_t *data, size_t size, tiled_options *o)
{
    tiled_mesh mesh, q;
    tiled_layout l = o->layout;
    tiled_error err;
    if (tiled_read_mesh(data, size, "fuzz", o, &mesh, &err)) return;
    if (mesh.face_start[mesh.nfaces] <= 4096) {
        l.tile_size = 16;
        o->smooth = 1;
        if (tiled_map(&mesh, &l, o, &q, &err) == TILED_OK) tiled_mesh_free(&q);
    }
    tiled_mesh_free(&mesh);
}

static void run_image(const uint8_t *data, size_t size, tiled_options *o)
{
    tiled_image img;
    tiled_tileset ts;
    tiled_validation v;
    tiled_error err;
    if (tiled_read_image(data, size, "fuzz", o, &img, &err)) return;
    if (img.width <= 64 && img.height <= 64) {
        o->layout.tile_size = 8;
        if (tiled_synthesize(&img, o, &ts, &err) == TILED_OK) tiled_tileset_free(&ts);
        o->layout.tile_size = 0;
        if (tiled_validate_tiles(&img, o, &v, &err) == TILED_OK &&
            tiled_tileset_from_image(&img, o, &ts, &err) == TILED_OK)
            tiled_tileset_free(&ts);
    }
    tiled_image_free(&img);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    tiled_options o = tiled_default_options();
    if (size < 1) return 0;
    o.layout.case_number = data[0] & 1 ? 1 : 2;
    o.layout.pairs = 1 + (data[0] >> 1 & 1);
    o.layout.grid = 1 + (data[0] >> 2 & 3);
    o.seed = data[0] >> 4;
    run_mesh(data + 1, size - 1, &o);
    run_image(data + 1, size - 1, &o);
    return 0;
}
