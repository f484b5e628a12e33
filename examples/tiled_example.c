/* tiled_example.c: the whole of tiled.h in one page.
 *
 *   cc -O2 -I.. tiled_example.c -lm && ./a.out [mesh.obj]
 *
 * Builds a tile set from a procedural exemplar, maps it onto a mesh (a
 * built-in genus-2 surface unless a file is given), and writes the tiled
 * texture, the textured OBJ (+ MTL) and a rendering, as PPM images. */
#include <stdio.h>
#define TILED_IMPLEMENTATION
#include "../tiled.h"

int main(int argc, char **argv)
{
    tiled_options opt = tiled_default_options();
    tiled_mesh mesh = {0}, mapped = {0};
    tiled_image exemplar = {0}, picture = {0};
    tiled_tileset tiles = {0};
    tiled_error err;
    int ok;

    opt.layout.pairs = 1; /* case 2, one boundary pair: 16 tiles */
    opt.smooth = 2;       /* smooth the quads after mapping, as the thesis does */
    opt.seed = 42;
    opt.render.width = 640;
    opt.render.height = 480;

    ok = (argc > 1 ? tiled_load_mesh(argv[1], &opt, &mesh, &err)
                   : tiled_builtin_mesh("double-torus", &opt, &mesh, &err)) == TILED_OK &&
         tiled_builtin_exemplar("pebbles", 128, &opt, &exemplar, &err) == TILED_OK &&
         tiled_synthesize(&exemplar, &opt, &tiles, &err) == TILED_OK &&
         tiled_map(&mesh, &tiles.layout, &opt, &mapped, &err) == TILED_OK &&
         tiled_save_image("example_tiles.ppm", &tiles.atlas, &err) == TILED_OK &&
         tiled_save_obj("example.obj", &mapped, "example_tiles.ppm", &err) == TILED_OK &&
         tiled_render(&mapped, &tiles, &opt.render, &picture, &err) == TILED_OK &&
         tiled_save_image("example.ppm", &picture, &err) == TILED_OK;
    if (ok)
        printf("%d faces -> %d textured quads; wrote example_tiles.ppm, example.obj, example.mtl, "
               "example.ppm\n",
               mesh.nfaces, mapped.nfaces);
    else fprintf(stderr, "tiled_example: %s\n", err.message);

    tiled_image_free(&picture);
    tiled_mesh_free(&mapped);
    tiled_tileset_free(&tiles);
    tiled_image_free(&exemplar);
    tiled_mesh_free(&mesh);
    return ok ? 0 : 1;
}
