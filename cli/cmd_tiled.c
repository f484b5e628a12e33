/* cmd_tiled.c: `patchwork tiled`, the whole of tiled.h from the shell. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "cli.h"

static const char *tiled_usage =
    "usage: patchwork tiled --mesh FILE [--exemplar IMG | --tiles IMG] [options]\n"
    "\n"
    "Seamless, singularity-free tiled textures on quad meshes (Kaur 2003), or\n"
    "edge-matched tiles of any size on any mesh (--scale).\n"
    "\n"
    "inputs:\n"
    "  --mesh FILE          OBJ, OFF or PLY mesh, or procedural:NAME (cube, torus,\n"
    "                       double-torus, icosahedron, grid); non-quad meshes are\n"
    "                       made all quads by Catmull-Clark subdivision\n"
    "  --exemplar IMG       texture to build the tile set from (PNG, PPM, PGM, PAM,\n"
    "                       GIMP .pat) or procedural:NAME (pebbles, spots, lichen);\n"
    "                       default procedural:pebbles\n"
    "  --tiles IMG          a ready-made tiled texture in the thesis layout (no\n"
    "                       guard bands); its sides are validated first\n"
    "options:\n"
    "  --case 1|2           2: boundary pairs (default), 1: self-matching boundary\n"
    "  --pairs N            case 2: N boundary pairs, (2N)^4 tiles (default 1;\n"
    "                       2 varies what the tiles show at mesh vertices)\n"
    "  --grid N             case 1: N x N tiles (default 4)\n"
    "  --scale S            any mesh: tiles of side S (mesh units) on the grid of\n"
    "                       a periodic global parameterization, instead of one\n"
    "                       tile per quad\n"
    "  --field up|curvature with --scale: tiles upright (+y, default) or along\n"
    "                       the direction of least curvature\n"
    "  --subdivide K        K more Catmull-Clark levels before mapping: more,\n"
    "                       smaller tiles (default 0)\n"
    "  --smooth K           K Catmull-Clark levels after mapping, carrying the\n"
    "                       texture along: a smooth surface (default 0)\n"
    "  --tile-size PX       tile size (default: from the exemplar)\n"
    "  --guard PX|none      guard band around tiles (default tile/8)\n"
    "  --no-mirror          case 1: rotate tiles but never mirror them\n"
    "  --seed S             random seed (default 0)\n"
    "  --validate           with --tiles: only report mismatching sides\n"
    "outputs (at least one):\n"
    "  --out-obj FILE       quad mesh with texture coordinates, plus FILE's .mtl\n"
    "  --out-tiles IMG      the tiled texture the OBJ uses (default with --out-obj:\n"
    "                       the OBJ's name with .png)\n"
    "  --out-image IMG      a rendering (.png .ppm .pgm .pam)\n"
    "  --out-glb FILE.glb   binary glTF 2.0: mapped mesh with the tiled texture\n"
    "  --size WxH           rendering size (default 800x600; 16..8192 each)\n" CLI_VIEW_USAGE;

typedef struct tiled_cmd {
    const char *mesh, *exemplar, *tiles, *out_obj, *out_tiles, *out_image, *out_glb;
    int validate_only;
    tiled_options opt;
} tiled_cmd;

static int parse_guard(cli_args *a, tiled_cmd *c)
{
    const char *v;
    if (!cli_value(a, &v)) return 0;
    if (!strcmp(v, "none")) {
        c->opt.layout.guard = TILED_NO_GUARD;
        return 1;
    }
    c->opt.layout.guard = atoi(v);
    if (c->opt.layout.guard < 1 || c->opt.layout.guard > 4096 || strspn(v, "0123456789") != strlen(v)) {
        cli_error(a->cmd, "--guard: '%s' is not a pixel count or 'none'", v);
        return 0;
    }
    return 1;
}

static int parse_field(cli_args *a, tiled_cmd *c)
{
    const char *v;
    if (!cli_value(a, &v)) return 0;
    if (!strcmp(v, "up") || !strcmp(v, "curvature")) {
        c->opt.field = strcmp(v, "up") ? TILED_FIELD_CURVATURE : TILED_FIELD_UP;
        return 1;
    }
    cli_error(a->cmd, "--field: '%s' is not up or curvature", v);
    return 0;
}

/* One option; returns 0 on a parse error, -1 for --help. */
static int parse_one(cli_args *a, tiled_cmd *c)
{
    int v =
        cli_view_flag(a, c->opt.render.view_dir, c->opt.render.up, &c->opt.render.supersample, &c->opt.render.threads);
    tiled_layout *l = &c->opt.layout;
    if (cli_is(a, "--help") || cli_is(a, "-h")) return -1;
    if (v >= 0) return v;
    if (cli_is(a, "--mesh")) return cli_value(a, &c->mesh);
    if (cli_is(a, "--exemplar")) return cli_value(a, &c->exemplar);
    if (cli_is(a, "--tiles")) return cli_value(a, &c->tiles);
    if (cli_is(a, "--out-obj")) return cli_value(a, &c->out_obj);
    if (cli_is(a, "--out-tiles")) return cli_value(a, &c->out_tiles);
    if (cli_is(a, "--out-image")) return cli_value(a, &c->out_image);
    if (cli_is(a, "--out-glb")) return cli_value(a, &c->out_glb);
    if (cli_is(a, "--case")) return cli_int(a, 1, 2, &l->case_number);
    if (cli_is(a, "--pairs")) return cli_int(a, 1, 8, &l->pairs);
    if (cli_is(a, "--grid")) return cli_int(a, 1, 256, &l->grid);
    if (cli_is(a, "--scale")) return cli_float(a, 1e-30f, 1e30f, &c->opt.scale);
    if (cli_is(a, "--field")) return parse_field(a, c);
    if (cli_is(a, "--subdivide")) return cli_int(a, 0, 8, &c->opt.subdivide);
    if (cli_is(a, "--smooth")) return cli_int(a, 0, 8, &c->opt.smooth);
    if (cli_is(a, "--tile-size")) return cli_int(a, 4, 4096, &l->tile_size);
    if (cli_is(a, "--guard")) return parse_guard(a, c);
    if (cli_is(a, "--seed")) return cli_u64(a, &c->opt.seed);
    if (cli_is(a, "--size")) return cli_size(a, &c->opt.render.width, &c->opt.render.height);
    if (cli_is(a, "--no-mirror")) return (c->opt.no_mirror = 1);
    if (cli_is(a, "--validate")) return (c->validate_only = 1);
    cli_error(a->cmd, "unknown option '%s' (try patchwork tiled --help)", a->argv[a->i]);
    return 0;
}

static int parse(int argc, char **argv, tiled_cmd *c)
{
    cli_args a;
    int r;
    memset(c, 0, sizeof *c);
    c->opt = tiled_default_options();
    a.argc = argc;
    a.argv = argv;
    a.cmd = "tiled";
    for (a.i = 1; a.i < argc; a.i++)
        if ((r = parse_one(&a, c)) <= 0) return r;
    if (c->exemplar && c->tiles) {
        cli_error("tiled", "give --exemplar or --tiles, not both");
        return 0;
    }
    if (c->validate_only ? !c->tiles : !c->mesh) {
        cli_error("tiled", c->validate_only ? "--validate needs --tiles" : "--mesh is required");
        return 0;
    }
    {
        const cli_out outs[4] = {{"--out-obj", c->out_obj, CLI_OUT_OBJ},
                                 {"--out-tiles", c->out_tiles, CLI_OUT_IMAGE},
                                 {"--out-image", c->out_image, CLI_OUT_IMAGE},
                                 {"--out-glb", c->out_glb, CLI_OUT_GLB}};
        if (!cli_check_outputs("tiled", outs, 4)) return 0;
    }
    if (!c->validate_only && !c->out_obj && !c->out_tiles && !c->out_image && !c->out_glb) {
        cli_error("tiled", "nothing to write: give --out-obj, --out-tiles, --out-image or --out-glb");
        return 0;
    }
    return 1;
}

static tiled_result load_mesh(const char *src, const tiled_options *o, tiled_mesh *m, tiled_error *err)
{
    const char *name;
    if (cli_is_procedural(src, &name)) return tiled_builtin_mesh(name, o, m, err);
    return tiled_load_mesh(src, o, m, err);
}

static tiled_result load_image(const char *src, const tiled_options *o, tiled_image *img, tiled_error *err)
{
    const char *name;
    if (cli_is_procedural(src, &name)) return tiled_builtin_exemplar(name, 64, o, img, err);
    return tiled_load_image(src, o, img, err);
}

/* Prints the validation report of a hand-made tiled texture. */
static void print_validation(const char *path, const tiled_validation *v, FILE *f)
{
    static const char *const side[4] = {"bottom", "right", "top", "left"};
    int k, n = v->nbad < TILED_MAX_MISMATCHES ? v->nbad : TILED_MAX_MISMATCHES;
    fprintf(f, "%s: %d of %d tile sides do not match (seam > %.4f; interior jump %.4f, worst %.4f)\n", path, v->nbad,
            v->sides_checked, v->threshold, v->interior, v->worst);
    for (k = 0; k < n; k++)
        fprintf(f, "  tile %d %s side (type %d): seam %.4f\n", v->bad[k].tile, side[v->bad[k].side], v->bad[k].type,
                v->bad[k].seam);
}

/* Builds the tile set from --tiles or --exemplar. */
static tiled_result make_tiles(tiled_cmd *c, tiled_tileset *ts, tiled_error *err)
{
    tiled_image img;
    tiled_result r = load_image(c->tiles      ? c->tiles
                                : c->exemplar ? c->exemplar
                                              : "procedural:pebbles",
                                &c->opt, &img, err);
    if (r != TILED_OK) return r;
    if (c->tiles) {
        tiled_validation v;
        r = tiled_validate_tiles(&img, &c->opt, &v, err);
        if (r == TILED_OK && (v.nbad || c->validate_only))
            print_validation(c->tiles, &v, c->validate_only ? stdout : stderr);
        if (r == TILED_OK && c->validate_only && v.nbad) r = TILED_ERR_INVALID;
        if (r == TILED_OK && !c->validate_only) r = tiled_tileset_from_image(&img, &c->opt, ts, err);
        if (r == TILED_ERR_INVALID && c->validate_only)
            snprintf(err->message, sizeof err->message, "%s: tile sides do not match", c->tiles);
    } else r = tiled_synthesize(&img, &c->opt, ts, err);
    tiled_image_free(&img);
    return r;
}

/* Writes an OBJ and its MTL (naming the texture) to staged paths; a glTF. */
static tiled_result write_obj(cli_outputs *o, const char *obj, const char *texture, const tiled_mesh *m,
                              tiled_error *err);
static tiled_result write_glb(cli_outputs *o, const char *path, const tiled_mesh *m, const tiled_image *texture,
                              const tiled_render_options *view, tiled_error *err);

/* Tiles drawn under this many pixels wide show no texture. */
#define MIN_TILE_PX 16.0f

/* Warns when the rendering (at --size, or 800x600) would draw tiles too
 * small to see: one tile per quad needs big quads (issue 18). */
static tiled_result warn_small_tiles(const tiled_mesh *quads, const tiled_tileset *ts, const tiled_render_options *ro,
                                     tiled_error *err)
{
    float px;
    tiled_result r = tiled_drawn_tile_size(quads, ts, ro, &px, err);
    if (r == TILED_OK && px < MIN_TILE_PX)
        fprintf(stderr,
                "patchwork tiled: warning: tiles are drawn about %.1f px wide on %d quads "
                "(under %.0f px the texture cannot be seen): tiled.h puts one tile on every quad, "
                "so give it a coarser quad mesh (fewer, larger quads; --subdivide only makes tiles "
                "smaller), or --scale S for tiles of side S on any mesh, or texture dense meshes "
                "such as scans with `patchwork pgp` or `patchwork lapped`, whose texture scale does "
                "not follow the faces\n",
                (double)px, quads->nfaces, (double)MIN_TILE_PX);
    return r;
}

static tiled_result run(tiled_cmd *c, cli_outputs *outs, tiled_error *err)
{
    tiled_mesh mesh, quads;
    tiled_tileset ts;
    tiled_image pic;
    tiled_grid_stats gs;
    tiled_result r;
    char tex_path[1024];
    memset(&mesh, 0, sizeof mesh);
    memset(&quads, 0, sizeof quads);
    memset(&pic, 0, sizeof pic);
    if ((r = make_tiles(c, &ts, err)) != TILED_OK || c->validate_only) return r;
    if (c->out_obj && !c->out_tiles) { /* the MTL must name a texture that exists */
        cli_with_ext(c->out_obj, ".png", tex_path, sizeof tex_path);
        c->out_tiles = tex_path;
    }
    c->opt.stats = &gs;
    if ((r = load_mesh(c->mesh, &c->opt, &mesh, err)) == TILED_OK &&
        (r = tiled_map(&mesh, &ts.layout, &c->opt, &quads, err)) != TILED_OK) {
        char msg[1400]; /* name the mesh: the library does not know it */
        snprintf(msg, sizeof msg, "%.1000s: %s", c->mesh, err->message);
        memcpy(err->message, msg, sizeof err->message - 1);
        err->message[sizeof err->message - 1] = 0;
    } else if (r == TILED_OK) {
        if (c->opt.scale > 0.0f)
            printf("tiled: %d triangles -> %d pieces in %d cells (%d special, %d vortex triangles, %d vortex cells "
                   "cut); %d shared cell sides, %d mismatched\n",
                   gs.triangles, gs.pieces, gs.cells, gs.special_cells, gs.vortex_triangles, gs.cut_vortices,
                   gs.grid_edges, gs.mismatched_edges);
        else
            printf("tiled: %d faces -> %d quads; %d x %d tiles of %d px (guard %d)\n", mesh.nfaces, quads.nfaces,
                   ts.tiles_per_side, ts.tiles_per_side, ts.layout.tile_size,
                   ts.layout.guard < 0 ? 0 : ts.layout.guard);
        if (r == TILED_OK && c->opt.scale <= 0.0f) r = warn_small_tiles(&quads, &ts, &c->opt.render, err);
        if (r == TILED_OK && c->out_tiles) r = cli_write_image(outs, c->out_tiles, &ts.atlas, err);
        if (r == TILED_OK && c->out_obj) r = write_obj(outs, c->out_obj, c->out_tiles, &quads, err);
        if (r == TILED_OK && c->out_glb) r = write_glb(outs, c->out_glb, &quads, &ts.atlas, &c->opt.render, err);
        if (r == TILED_OK && c->out_image && (r = tiled_render(&quads, &ts, &c->opt.render, &pic, err)) == TILED_OK)
            r = cli_write_image(outs, c->out_image, &pic, err);
    }
    tiled_image_free(&pic);
    tiled_mesh_free(&quads);
    tiled_mesh_free(&mesh);
    tiled_tileset_free(&ts);
    return r;
}

static tiled_result write_one(cli_outputs *o, const char *path, int is_obj, const char *arg, const tiled_mesh *m,
                              tiled_error *err)
{
    FILE *f = cli_open(o, path, err->message, sizeof err->message);
    tiled_result r;
    if (!f) return err->code = TILED_ERR_IO;
    r = is_obj ? tiled_write_obj(m, arg, cli_fwrite, f, err) : tiled_write_mtl(arg, cli_fwrite, f, err);
    if (r == TILED_ERR_IO) snprintf(err->message, sizeof err->message, "%.200s: write error (disk full?)", path);
    if (!cli_close(f, r == TILED_OK, path, err->message, sizeof err->message)) r = TILED_ERR_IO;
    return err->code = r;
}

static tiled_result write_glb(cli_outputs *o, const char *path, const tiled_mesh *m, const tiled_image *texture,
                              const tiled_render_options *view, tiled_error *err)
{
    FILE *f = cli_open(o, path, err->message, sizeof err->message);
    tiled_result r;
    if (!f) return err->code = TILED_ERR_IO;
    r = tiled_write_gltf(m, texture, view, cli_fwrite, f, err);
    if (!cli_close(f, r == TILED_OK, path, err->message, sizeof err->message)) r = TILED_ERR_IO;
    return err->code = r;
}

static tiled_result write_obj(cli_outputs *o, const char *obj, const char *texture, const tiled_mesh *m,
                              tiled_error *err)
{
    char mtl[1024];
    tiled_result r;
    cli_with_ext(obj, ".mtl", mtl, sizeof mtl);
    r = write_one(o, obj, 1, cli_texture_ref(obj, mtl), m, err);
    if (r == TILED_OK) r = write_one(o, mtl, 0, cli_texture_ref(obj, texture), m, err);
    return r;
}

int cmd_tiled(int argc, char **argv)
{
    tiled_cmd c;
    cli_outputs outs;
    tiled_error err;
    int p = parse(argc, argv, &c);
    if (p < 0) {
        fputs(tiled_usage, stdout);
        return 0;
    }
    if (!p) return 1;
    memset(&outs, 0, sizeof outs);
    return cli_finish("tiled", &outs, run(&c, &outs, &err) != TILED_OK, err.message);
}
