/* pgp_example.c: pgp.h's mapping in one page.
 *
 *   cc -O2 -I.. pgp_example.c -lm && ./a.out [mesh.obj [tile.nrrd|image.png]]
 *
 * Maps a material-space tile (built-in bricks that weather into pebbles
 * along m, unless a file is given) onto a mesh (a built-in bumpy sphere
 * unless a file is given) with a periodic global parameterization (§2.3):
 * then turns the bricks near one triangle with an orientation constraint
 * of limited radius (§2: only that area is recomputed), weathers one side
 * with a material constraint, edits the orientation again, and renders
 * before and after (§3) as PNG. */
#include <stdio.h>
#define PGP_IMPLEMENTATION
#include "../pgp.h"

static pgp_result render(const pgp_map *map, const pgp_tile *tile, const pgp_options *opt, const char *path,
                         pgp_error *err)
{
    pgp_image picture = {0};
    pgp_result r = pgp_render(map, tile, &opt->render, &picture, err);
    if (r == PGP_OK) r = pgp_save_image(path, &picture, err);
    pgp_image_free(&picture);
    return r;
}

/* The face (a triangle of the fan triangulation) whose first corner lies
 * furthest towards the default camera, so that the edits show. */
static int facing_face(const pgp_mesh *m)
{
    int f, t = 0, best = 0;
    float top = -1e30f;
    for (f = 0; f < m->nfaces; f++) {
        const float *p = m->positions + 3 * m->face_verts[m->face_start[f]];
        float d = 0.55f * p[0] + 0.45f * p[1] + 0.7f * p[2];
        if (d > top) {
            top = d;
            best = t;
        }
        t += m->face_start[f + 1] - m->face_start[f] - 2;
    }
    return best;
}

int main(int argc, char **argv)
{
    pgp_options opt = pgp_default_options();
    pgp_mesh mesh = {0};
    pgp_tile tile = {0};
    pgp_map map = {0};
    pgp_area area = {0};
    pgp_constraint c = {PGP_CONSTRAINT_ORIENT, 0, {1, 0, 0}, 0.6f}; /* kind, element, value, radius */
    pgp_error err;
    const float slanted[3] = {1, 1, 0};
    int turn = -1, face, ok;

    opt.field = PGP_FIELD_UP; /* the tile's t axis follows +Y, projected on the surface */
    opt.scale = 0.0f;         /* 0: a tile side of 1/10 of the bounding-box diagonal */
    opt.render.width = 640;   /* every other render setting keeps its default */
    opt.render.height = 480;

    ok = (argc > 1 ? pgp_load_mesh(argv[1], &opt, &mesh, &err) : pgp_builtin_mesh("bumpy", &opt, &mesh, &err)) ==
             PGP_OK &&
         (argc > 2 ? pgp_load_tile(argv[2], &opt, &tile, &err) : pgp_builtin_tile("bricks", 64, &opt, &tile, &err)) ==
             PGP_OK &&
         /* the field, scale and material everywhere, then the parameterization */
         pgp_create(&mesh, &opt, &map, &err) == PGP_OK &&
         render(&map, &tile, &opt, "pgp_example_before.png", &err) == PGP_OK;
    /* bricks laid along X around the face in front, within a radius of 0.6 */
    face = ok ? facing_face(&mesh) : 0;
    c.element = face;
    ok = ok && pgp_add_constraint(&map, &c, &turn, &area, &err) == PGP_OK;
    if (ok) printf("the orientation constraint recomputed %d of %d triangles\n", area.nfaces, map.ntris);
    pgp_area_free(&area);
    /* weathered bricks (m = 1: pebbles) around that face's first corner */
    c.kind = PGP_CONSTRAINT_MATERIAL;
    c.element = mesh.face_verts[mesh.face_start[face]];
    c.value[0] = 1.0f;
    c.radius = 0.8f;
    ok = ok && pgp_add_constraint(&map, &c, NULL, NULL, &err) == PGP_OK &&
         /* the same orientation constraint turned again: only its area changes */
         pgp_edit_constraint(&map, turn, slanted, NULL, &err) == PGP_OK &&
         render(&map, &tile, &opt, "pgp_example_after.png", &err) == PGP_OK;
    if (ok)
        printf("%d triangles, %d singular, %d around vortices; wrote pgp_example_before.png, pgp_example_after.png\n",
               map.ntris, pgp_map_singular(&map, NULL), pgp_map_vortices(&map, NULL));
    else fprintf(stderr, "pgp_example: %s (%s)\n", err.message, pgp_result_string(err.code));

    pgp_map_free(&map); /* a zeroed map is fine, as for every free */
    pgp_tile_free(&tile);
    pgp_mesh_free(&mesh);
    return ok ? 0 : 1;
}
