/* lapped_example.c: the whole of lapped.h in one page.
 *
 *   cc -O2 -I.. lapped_example.c -lm && ./a.out [mesh.obj [texture.ppm]]
 *
 * Covers a mesh (a built-in bumpy sphere unless a file is given) with
 * pastes of one texture patch (a built-in "scales" texture unless a file is
 * given) whose "up" follows +Y, then writes the ordered pastes, a
 * rendering by runtime pasting (§4) as a PNG, and the texture baked into
 * an atlas (§4) with the mesh as OBJ + MTL and as binary glTF. */
#include <stdio.h>
#define LAPPED_IMPLEMENTATION
#include "../lapped.h"

int main(int argc, char **argv)
{
    lapped_options opt = lapped_default_options();
    lapped_mesh mesh = {0};
    lapped_image texture = {0}, patch = {0}, picture = {0};
    lapped_source src = {0}; /* the patches pasted: here one */
    lapped_texture lt = {0};
    lapped_atlas atlas = {0}; /* opt.atlas: 1024x1024, automatic packing */
    lapped_error err;
    int ok;

    opt.field = LAPPED_FIELD_UP;      /* texture "up" along +Y, projected on the surface */
    opt.scale = 0.0f;                 /* 0: patch side = 1/10 of the bounding-box diagonal */
    opt.alpha = LAPPED_ALPHA_SPLOTCH; /* an irregular blob cut out of the texture (§3.1) */
    opt.seed = 42;                    /* same seed, same pastes, byte for byte */
    opt.render.width = 640;
    opt.render.height = 480;
    src.patches = &patch;
    src.npatches = 1;

    /* Each call returns LAPPED_OK (0) or an error code with err.message
     * naming what went wrong; && stops at the first failure. */
    ok = (argc > 1 ? lapped_load_mesh(argv[1], &opt, &mesh, &err) : lapped_builtin_mesh("bumpy", &opt, &mesh, &err)) ==
             LAPPED_OK &&
         (argc > 2 ? lapped_load_image(argv[2], &opt, &texture, &err)
                   : lapped_builtin_exemplar("scales", 128, &opt, &texture, &err)) == LAPPED_OK &&
         /* the texture with its alpha: the patch that gets pasted */
         lapped_make_patch(&texture, NULL, &opt, &patch, &err) == LAPPED_OK &&
         /* §3: grow, parametrise and paste surface patches until covered */
         lapped_create(&mesh, &src, &opt, &lt, &err) == LAPPED_OK &&
         lapped_save_pastes("lapped_example.pastes", &lt, &err) == LAPPED_OK &&
         /* §4: draw the pastes in order, composited with the patch's alpha */
         lapped_render(&mesh, &lt, &src, &opt.render, &picture, &err) == LAPPED_OK &&
         lapped_save_image("lapped_example.png", &picture, &err) == LAPPED_OK &&
         /* §4: the same pastes baked into one texture, charts packed automatically */
         lapped_bake_atlas(&mesh, &lt, &src, &opt, &atlas, &err) == LAPPED_OK &&
         lapped_save_image("lapped_example_atlas.png", &atlas.image, &err) == LAPPED_OK &&
         lapped_save_obj("lapped_example.obj", &mesh, &atlas, "lapped_example_atlas.png", &err) == LAPPED_OK &&
         lapped_save_gltf("lapped_example.glb", &mesh, &atlas, &opt.render, &err) == LAPPED_OK;
    if (ok)
        printf("%d triangles covered by %d pastes, %.2f layers per triangle (%.2f before removing hidden faces); "
               "wrote lapped_example.pastes, lapped_example.png, lapped_example_atlas.png, lapped_example.obj, "
               "lapped_example.mtl, lapped_example.glb\n",
               lt.ntris, lt.npastes, lt.layers, lt.layers_before);
    else fprintf(stderr, "lapped_example: %s (%s)\n", err.message, lapped_result_string(err.code));

    /* all start zeroed and a failed call leaves its output zeroed: freeing is always safe */
    lapped_atlas_free(&atlas);
    lapped_image_free(&picture);
    lapped_texture_free(&lt);
    lapped_image_free(&patch);
    lapped_image_free(&texture);
    lapped_mesh_free(&mesh);
    return ok ? 0 : 1;
}
