/* lst_example.c: the whole of lst.h in one page.
 *
 *   cc -O2 -I.. lst_example.c -lm && ./a.out [surface.off [exemplar.nrrd]]
 *
 * Fills a closed surface (a built-in kiwi fruit unless a file is given)
 * with a depth-varying solid texture (a built-in kiwi exemplar unless an
 * NRRD file is given) along a tensor field (texture type 2-b: depth from
 * the skin to the core, the fruit's axis as the second direction), then
 * writes the model file, the surface, a cross-section and a volume
 * rendering. */
#include <stdio.h>
#include <string.h>
#define LST_IMPLEMENTATION
#include "../lst.h"

int main(int argc, char **argv)
{
    lst_options opt = lst_default_options(); /* every setting, the render's included */
    lst_render_options *view = &opt.render;
    lst_mesh surface = {0};
    lst_tetmesh mesh = {0};
    lst_volume exemplar = {0}, bumps = {0};
    lst_source source; /* the texture: the exemplar and its bumps */
    lst_model model = {0};
    lst_image picture = {0}, section = {0}, volume = {0};
    lst_constraints guides = {0};
    const float cut[4] = {0.0f, 0.0f, 1.0f, 0.1f}; /* keep z <= 0.1 */
    lst_error err;
    int ok;

    view->width = 360;
    view->height = 300;
    opt.type = LST_TYPE_2B;     /* three distinct axes, depth-varying (kiwi, carrot, tree) */
    opt.seed = 42;              /* same seed, same model, byte for byte */
    opt.tet.target_tets = 3000; /* inside (default 20000); finer near the surface */

    /* Each call returns LST_OK (0) or an error code with err.message naming
     * what went wrong; && stops at the first failure. */
    ok = (argc > 1 ? lst_load_mesh(argv[1], &opt, &surface, &err) : lst_builtin_mesh("kiwi", &opt, &surface, &err)) ==
             LST_OK &&
         (argc > 2 ? lst_load_volume(argv[2], &opt, &exemplar, &err)
                   : lst_builtin_exemplar("kiwi", 64, &opt, &exemplar, &bumps, &err)) == LST_OK &&
         lst_tetrahedralize(&surface, &opt, &mesh, NULL, &err) == LST_OK;
    /* §4.3-4.5: the skin painted depth 0, the core stroked depth 1, the axis
     * drawn as the second direction (the built-in kiwi's; without them the
     * depth is the distance to the surface, the direction its main axis) */
    if (ok && argc <= 1) ok = lst_builtin_constraints("kiwi", &surface, &opt, &guides, &err) == LST_OK;
    opt.constraints = guides.items;
    opt.nconstraints = guides.count;
    source.exemplar = &exemplar;
    source.values = bumps.voxels ? &bumps : NULL;
    ok = ok &&
         /* §5.2: fields, then pastes until every tetrahedron is covered */
         lst_create(&mesh, &surface, &source, &opt, &model, &err) == LST_OK &&
         lst_save_model("lst_example.lst", &model, &err) == LST_OK &&
         /* §5.1: the surface, each triangle composited with its pastes */
         lst_render(&model, view, &picture, &err) == LST_OK &&
         lst_save_image("lst_example.png", &picture, &err) == LST_OK &&
         /* §5.1.1: cut, then look at the cross-section face on */
         lst_cut_plane(&model, cut, &err) == LST_OK;
    view->view_dir[0] = 0.0f;
    view->view_dir[1] = 0.0f;
    view->view_dir[2] = -1.0f;
    ok = ok && lst_render(&model, view, &section, &err) == LST_OK &&
         lst_save_image("lst_example_section.png", &section, &err) == LST_OK;
    /* §5.1.2: the whole fruit again, as a translucent volume of slices */
    lst_uncut(&model);
    view->view_dir[0] = -0.55f;
    view->view_dir[1] = -0.45f;
    view->view_dir[2] = -0.7f;
    ok = ok && lst_render_volume(&model, view, &opt.volume, &volume, &err) == LST_OK &&
         lst_save_image("lst_example_volume.png", &volume, &err) == LST_OK;
    if (ok)
        printf("%d tetrahedra filled by %d pastes (%.1f per tetrahedron); wrote lst_example.lst, lst_example.png, "
               "lst_example_section.png, lst_example_volume.png\n",
               mesh.ntets, model.npastes, model.layers);
    else fprintf(stderr, "lst_example: %s (%s)\n", err.message, lst_result_string(err.code));
    lst_constraints_free(&guides);
    lst_image_free(&picture);
    lst_image_free(&section);
    lst_image_free(&volume);
    lst_model_free(&model);
    lst_volume_free(&exemplar);
    lst_volume_free(&bumps);
    lst_tetmesh_free(&mesh);
    lst_mesh_free(&surface);
    return ok ? 0 : 1;
}
