/* cmd_pgp.c: `patchwork pgp`, the whole of pgp.h from the shell. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "cli.h"

static const char *pgp_usage = "usage: patchwork pgp --mesh FILE (--tile FILE | --texture IMG) [options]\n"
                               "\n"
                               "Material-space texturing (Ray, Levy, Wang, Turk, Vallet 2009): a tile that is\n"
                               "periodic in s and t and varies along a material axis m, mapped onto a mesh by a\n"
                               "periodic global parameterization that follows orientation, scale and material\n"
                               "constraints; singular triangles are fixed when rendering.\n"
                               "\n"
                               "inputs:\n"
                               "  --mesh FILE          OBJ, OFF or PLY (polygons are fan-triangulated), or\n"
                               "                       procedural:NAME (sphere, torus, bumpy, grid)\n"
                               "  --tile FILE          a material-space tile: NRRD (sizes C W H M, or W H M),\n"
                               "                       any image (one layer), or procedural:NAME (bricks:\n"
                               "                       4 layers weathering along m; stripes: 1 layer)\n"
                               "  --texture IMG        a periodic 2D texture (PNG, PPM, PGM, PAM) as a\n"
                               "                       one-layer tile\n"
                               "mapping:\n"
                               "  --field up[:X,Y,Z]   the tile's t axis along this direction projected on the\n"
                               "                       surface (default +Y)\n"
                               "  --field curvature    the tile's t axis along the direction of least curvature\n"
                               "  --field smooth[:W]   up, or whichever of three perpendicular axes gives the\n"
                               "                       fewest vortices, rotated and the tile side varied\n"
                               "                       (within 1/2 and 2x, mean kept) where that cancels the\n"
                               "                       curl the parameterization cannot follow:\n"
                               "                       fewer vortices, less alignment (W, default 1: how far\n"
                               "                       from the field, in (0, 1e6])\n"
                               "  --scale S            tile side in mesh units (default: 1/10 of the\n"
                               "                       bounding-box diagonal)\n"
                               "  --constraints FILE   lines 'orient F dx dy dz', 'scale V S', 'material V m'\n"
                               "                       and 'radius R' (effect radius of the lines after it)\n"
                               "  --seed S             seed of the procedural tiles (default 0)\n"
                               "outputs (at least one):\n"
                               "  --out-image IMG      a rendering (.png .ppm .pgm .pam)\n"
                               "  --size WxH           rendering size (default 800x600; 16..8192 each)\n" CLI_VIEW_USAGE
                               "  --show WHAT          tile (default), material (m in gray), special (the\n"
                               "                       triangles drawn specially in red; 'singular' is the same)\n"
                               "                       or ghosts (red where a colour mixes lookups whose (s,t)\n"
                               "                       differ by more than a tenth of a period)\n"
                               "  --fix HOW            how vortices are drawn: clean (default: one lookup; in\n"
                               "                       the vortex triangles the pattern ends or forks at a\n"
                               "                       point, after Knoppel et al. 2015), paper (section 3:\n"
                               "                       three blended lookups around singular vertices) or all\n"
                               "                       (three lookups on every triangle)\n"
                               "  --zoom Z             a close-up: the field of view divided by Z (1 to 1e4)\n"
                               "  --center X,Y,Z       the point the close-up looks at (default: the mesh's\n"
                               "                       centre); vortex:K the K-th vortex triangle (from 0)\n"
                               "  --no-fix             one lookup of the raw coordinates everywhere (a seam at\n"
                               "                       every vortex)\n"
                               "  --out-obj FILE       the triangulated mesh with 'vt s t m' per corner, faces\n"
                               "                       in groups 'regular' and 'singular'\n"
                               "  --out-tile FILE.nrrd the tile, as NRRD (uint8)\n"
                               "  --out-glb FILE.glb   binary glTF 2.0: the mesh with an atlas of the rendering\n"
                               "                       (--fix, --show) baked inside, and the camera of --out-image\n"
                               "  --atlas-size PX      its side (default 1024; 16..8192)\n"
                               "  --out-glb-st FILE.glb binary glTF 2.0 with the raw (s,t) per corner and the\n"
                               "                       tile's layer at --glb-material M (0..1, default 0), wrapped:\n"
                               "                       for a viewer with its own material-space shader (the\n"
                               "                       singular triangles show seams)\n";

typedef struct pgp_cmd {
    int center_vortex; /* --center vortex:K: K + 1, 0 when not given */
    const char *mesh, *tile, *texture, *constraints, *out_image, *out_obj, *out_tile, *out_glb, *out_glb_st;
    float glb_material;
    pgp_options opt;
} pgp_cmd;

static int bad(const char *what, const char *value)
{
    cli_error("pgp", "%s: '%s' is not valid (try patchwork pgp --help)", what, value);
    return 0;
}

/* --field up[:X,Y,Z] | curvature | smooth[:W] */
static int parse_field(cli_args *a, pgp_cmd *c)
{
    const char *v;
    if (!cli_value(a, &v)) return 0;
    if (!strcmp(v, "smooth")) {
        c->opt.field = PGP_FIELD_UP;
        c->opt.integrable = 1.0f;
    } else if (!strncmp(v, "smooth:", 7)) {
        char *end;
        c->opt.field = PGP_FIELD_UP;
        c->opt.integrable = strtof(v + 7, &end);
        if (end == v + 7 || *end || !(c->opt.integrable > 0.0f && c->opt.integrable <= 1e6f)) return bad("--field", v);
    } else if (!strcmp(v, "curvature")) c->opt.field = PGP_FIELD_CURVATURE;
    else if (!strcmp(v, "up")) c->opt.field = PGP_FIELD_UP;
    else if (!strncmp(v, "up:", 3)) {
        c->opt.field = PGP_FIELD_UP;
        if (!cli_parse_vec3(v + 3, c->opt.up)) return bad("--field", v);
        if (!(c->opt.up[0] != 0.0f || c->opt.up[1] != 0.0f || c->opt.up[2] != 0.0f))
            return bad("--field (zero up vector)", v);
    } else return bad("--field", v);
    return 1;
}

static int parse_show(cli_args *a, pgp_cmd *c)
{
    const char *v;
    if (!cli_value(a, &v)) return 0;
    if (!strcmp(v, "tile")) c->opt.render.show = PGP_SHOW_TILE;
    else if (!strcmp(v, "material")) c->opt.render.show = PGP_SHOW_MATERIAL;
    else if (!strcmp(v, "singular") || !strcmp(v, "special")) c->opt.render.show = PGP_SHOW_SPECIAL;
    else if (!strcmp(v, "ghosts")) c->opt.render.show = PGP_SHOW_GHOSTS;
    else return bad("--show (tile, material, special or ghosts)", v);
    return 1;
}

/* --center X,Y,Z | vortex:K */
static int parse_center(cli_args *a, pgp_cmd *c)
{
    const char *v;
    char *end;
    if (!cli_value(a, &v)) return 0;
    if (!strncmp(v, "vortex:", 7)) {
        long n = strtol(v + 7, &end, 10);
        if (end == v + 7 || *end || n < 0 || n > 100000000L) return bad("--center", v);
        c->center_vortex = (int)n + 1;
        return 1;
    }
    return cli_parse_vec3(v, c->opt.render.center) ? 1 : bad("--center", v);
}

/* --fix clean | paper | all */
static int parse_fix(cli_args *a, pgp_cmd *c)
{
    const char *v;
    if (!cli_value(a, &v)) return 0;
    if (!strcmp(v, "clean")) c->opt.render.fix = PGP_FIX_CLEAN;
    else if (!strcmp(v, "paper")) c->opt.render.fix = PGP_FIX_PAPER;
    else if (!strcmp(v, "all")) c->opt.render.fix = PGP_FIX_ALL;
    else return bad("--fix (clean, paper or all)", v);
    return 1;
}

static int parse_one(cli_args *a, pgp_cmd *c)
{
    int v =
        cli_view_flag(a, c->opt.render.view_dir, c->opt.render.up, &c->opt.render.supersample, &c->opt.render.threads);
    if (cli_is(a, "--help") || cli_is(a, "-h")) return -1;
    if (v >= 0) return v;
    if (cli_is(a, "--mesh")) return cli_value(a, &c->mesh);
    if (cli_is(a, "--tile")) return cli_value(a, &c->tile);
    if (cli_is(a, "--texture")) return cli_value(a, &c->texture);
    if (cli_is(a, "--field")) return parse_field(a, c);
    if (cli_is(a, "--scale")) return cli_float(a, 1e-30f, 1e30f, &c->opt.scale);
    if (cli_is(a, "--constraints")) return cli_value(a, &c->constraints);
    if (cli_is(a, "--seed")) return cli_u64(a, &c->opt.synth.seed);
    if (cli_is(a, "--no-fix")) return (c->opt.render.fix = PGP_FIX_OFF);
    if (cli_is(a, "--fix")) return parse_fix(a, c);
    if (cli_is(a, "--zoom")) return cli_float(a, 1.0f, 1e4f, &c->opt.render.zoom);
    if (cli_is(a, "--center")) return parse_center(a, c);
    if (cli_is(a, "--out-obj")) return cli_value(a, &c->out_obj);
    if (cli_is(a, "--out-glb")) return cli_value(a, &c->out_glb);
    if (cli_is(a, "--out-glb-st")) return cli_value(a, &c->out_glb_st);
    if (cli_is(a, "--glb-material")) return cli_float(a, 0.0f, 1.0f, &c->glb_material);
    if (cli_is(a, "--atlas-size")) return cli_int(a, 16, 8192, &c->opt.atlas.size);
    if (cli_is(a, "--out-image")) return cli_value(a, &c->out_image);
    if (cli_is(a, "--size")) return cli_size(a, &c->opt.render.width, &c->opt.render.height);
    if (cli_is(a, "--out-tile")) return cli_value(a, &c->out_tile);
    if (cli_is(a, "--show")) return parse_show(a, c);
    cli_error("pgp", "unknown option '%s' (try patchwork pgp --help)", a->argv[a->i]);
    return 0;
}

static int parse(int argc, char **argv, pgp_cmd *c)
{
    cli_args a;
    const char *name;
    int r;
    memset(c, 0, sizeof *c);
    c->opt = pgp_default_options();
    a.argc = argc;
    a.argv = argv;
    a.cmd = "pgp";
    for (a.i = 1; a.i < argc; a.i++)
        if ((r = parse_one(&a, c)) <= 0) return r;
    if (!c->mesh || !!c->tile == !!c->texture) {
        cli_error("pgp", "--mesh and one of --tile or --texture are required");
        return 0;
    }
    if (c->texture && cli_is_procedural(c->texture, &name)) {
        cli_error("pgp", "--texture takes an image file; use --tile procedural:%s", name);
        return 0;
    }
    {
        const cli_out outs[5] = {{"--out-image", c->out_image, CLI_OUT_IMAGE},
                                 {"--out-obj", c->out_obj, CLI_OUT_OBJ},
                                 {"--out-tile", c->out_tile, CLI_OUT_NRRD},
                                 {"--out-glb", c->out_glb, CLI_OUT_GLB},
                                 {"--out-glb-st", c->out_glb_st, CLI_OUT_GLB}};
        if (!cli_check_outputs("pgp", outs, 5)) return 0;
    }
    if (!c->out_image && !c->out_obj && !c->out_tile && !c->out_glb && !c->out_glb_st) {
        cli_error("pgp", "nothing to write: give --out-image, --out-obj, --out-tile, --out-glb or --out-glb-st");
        return 0;
    }
    return 1;
}

static pgp_result load_tile(const pgp_cmd *c, pgp_tile *t, pgp_error *err)
{
    const char *name;
    pgp_image img;
    pgp_result r;
    if (c->tile && cli_is_procedural(c->tile, &name)) return pgp_builtin_tile(name, 256, &c->opt, t, err);
    if (c->tile) return pgp_load_tile(c->tile, &c->opt, t, err);
    if ((r = pgp_load_image(c->texture, &c->opt, &img, err)) != PGP_OK) return r;
    r = pgp_tile_from_image(&img, &c->opt, t, err);
    pgp_image_free(&img);
    return r;
}

static pgp_result load_mesh(const char *src, const pgp_options *o, pgp_mesh *m, pgp_error *err)
{
    const char *name;
    if (cli_is_procedural(src, &name)) return pgp_builtin_mesh(name, o, m, err);
    return pgp_load_mesh(src, o, m, err);
}

/* Writes a pgp image through the shared image writer. */
static pgp_result write_image(cli_outputs *outs, const char *path, const pgp_image *img, pgp_error *err)
{
    tiled_image view = cli_image_view(img->width, img->height, img->channels, img->pixels, img->bits);
    return err->code = (pgp_result)cli_write_view(outs, path, &view, err->message);
}

/* The mapping as glTF with the atlas, to a staged file. */
static pgp_result write_glb(cli_outputs *outs, const char *path, const pgp_map *map, const pgp_atlas *atlas,
                            const pgp_render_options *view, pgp_error *err)
{
    FILE *f = cli_open(outs, path, err->message, sizeof err->message);
    pgp_result r;
    if (!f) return err->code = PGP_ERR_IO;
    r = pgp_write_gltf(map, atlas, view, cli_fwrite, f, err);
    if (r == PGP_ERR_IO) snprintf(err->message, sizeof err->message, "%.200s: write error (disk full?)", path);
    if (!cli_close(f, r == PGP_OK, path, err->message, sizeof err->message)) r = PGP_ERR_IO;
    return err->code = r;
}

/* --out-glb (baked) or --out-glb-st (raw coordinates). */
static pgp_result write_gltf_out(const pgp_cmd *c, cli_outputs *outs, const pgp_map *map, const pgp_tile *tile, int raw,
                                 pgp_error *err)
{
    pgp_atlas atlas;
    pgp_result r =
        raw ? pgp_tile_atlas(map, tile, c->glb_material, &atlas, err) : pgp_bake_atlas(map, tile, &c->opt, &atlas, err);
    if (r == PGP_OK) r = write_glb(outs, raw ? c->out_glb_st : c->out_glb, map, &atlas, &c->opt.render, err);
    pgp_atlas_free(&atlas);
    return r;
}

/* The OBJ (tile NULL) or the tile, to a staged file. */
static pgp_result write_file(cli_outputs *outs, const char *path, const pgp_mesh *mesh, const pgp_map *map,
                             const pgp_tile *tile, pgp_error *err)
{
    FILE *f = cli_open(outs, path, err->message, sizeof err->message);
    pgp_result r;
    if (!f) return err->code = PGP_ERR_IO;
    r = tile ? pgp_write_tile(tile, cli_fwrite, f, err) : pgp_write_obj(mesh, map, cli_fwrite, f, err);
    if (r == PGP_ERR_IO) snprintf(err->message, sizeof err->message, "%.200s: write error (disk full?)", path);
    if (!cli_close(f, r == PGP_OK, path, err->message, sizeof err->message)) r = PGP_ERR_IO;
    return err->code = r;
}

/* Issue 17: what happened, on stdout, with a warning when periods are
 * short for the triangles (pgp_create refused anything worse). The
 * warning is part of the report, on stdout: the built-in shapes are coarse
 * enough to draw it at their default tile side. */
static void report(const pgp_cmd *c, const pgp_map *map, const pgp_tile *tile)
{
    static const char *const fix[4] = {"clean", "none", "all", "paper"};
    pgp_stats st;
    int sp = pgp_map_special(map, c->opt.render.fix, NULL), n;
    pgp_map_stats(map, &st);
    n = st.triangles;
    printf("pgp: %d triangles, %d singular (%.1f%%) around %d vorti%s, tile %dx%d with %d layer%s\n", n, st.singular,
           n ? 100.0 * st.singular / n : 0.0, st.vortices, st.vortices == 1 ? "ex" : "ces", tile->width, tile->height,
           tile->layers, tile->layers == 1 ? "" : "s");
    printf("pgp: drawn specially (fix %s): %d triangles (%.1f%%); surface stretched by more than 30%%: %.1f%%, "
           "sheared by more than 20 degrees: %.1f%%\n",
           fix[c->opt.render.fix], sp, n ? 100.0 * sp / n : 0.0, 100.0 * st.stretched, 100.0 * st.sheared);
    if (st.scale < 8.0f * st.mean_edge)
        printf("pgp: warning: tile side %g is under 8 mean edge lengths (%g): each period spans too few triangles "
               "to follow the field\n",
               (double)st.scale, 8.0 * st.mean_edge);
}

/* --zoom without --center looks at the middle of the bounding box;
 * --center vortex:K at the K-th vortex triangle's centroid. */
static pgp_result set_center(pgp_cmd *c, const pgp_mesh *mesh, const pgp_map *map, pgp_error *err)
{
    int n = map->ntris, f, k, seen = 0;
    const int *tri = map->tris;
    unsigned char *v = (unsigned char *)malloc((size_t)n + 1);
    pgp_result r = v ? PGP_OK : PGP_ERR_NOMEM;
    float lo[3], hi[3];
    for (k = 0; r == PGP_OK && !c->center_vortex && k < 3; k++) {
        lo[k] = hi[k] = mesh->positions[k];
        for (f = 1; f < mesh->nverts; f++) {
            float p = mesh->positions[3 * f + k];
            lo[k] = p < lo[k] ? p : lo[k];
            hi[k] = p > hi[k] ? p : hi[k];
        }
        c->opt.render.center[k] = 0.5f * (lo[k] + hi[k]);
    }
    if (r == PGP_OK && c->center_vortex) {
        pgp_map_vortices(map, v);
        for (f = 0; f < n && !(v[f] && seen++ == c->center_vortex - 1); f++) {
        }
        if (f == n) {
            snprintf(err->message, sizeof err->message, "--center vortex:%d: the map has %d vortices",
                     c->center_vortex - 1, seen);
            r = PGP_ERR_INVALID;
        }
        for (k = 0; r == PGP_OK && k < 3; k++)
            c->opt.render.center[k] = (mesh->positions[3 * tri[3 * f] + k] + mesh->positions[3 * tri[3 * f + 1] + k] +
                                       mesh->positions[3 * tri[3 * f + 2] + k]) /
                                      3.0f;
    }
    free(v);
    return err->code = r;
}

/* The line of constraints file `path` that holds constraint i (from 0),
 * for messages. The file was read, so every line that is not blank, a
 * comment or a 'radius' line (the only keyword starting with 'r') holds one
 * constraint; bytes of the byte-order mark count as blanks. 0 if unknown. */
static int constraint_line(const char *path, int i)
{
    FILE *f = fopen(path, "rb");
    int ch, line = 1, start = 1, found = 0;
    while (f && !found && (ch = getc(f)) != EOF) {
        if (ch == '\n') {
            line++;
            start = 1;
        } else if (start &&
                   !(ch == ' ' || ch == '\t' || ch == '\r' || ch == '\v' || ch == '\f' || (line == 1 && ch >= 0x80))) {
            start = 0;
            found = ch != '#' && ch != 'r' && i-- == 0;
        }
    }
    if (f) fclose(f);
    return found ? line : 0;
}

/* The file's constraints, one by one, each as the line it came from. */
static pgp_result add_constraints(const pgp_cmd *c, const pgp_constraints *cons, pgp_map *map, pgp_error *err)
{
    char msg[sizeof err->message];
    pgp_result r = PGP_OK;
    int i;
    for (i = 0; i < cons->count && r == PGP_OK; i++)
        if ((r = pgp_add_constraint(map, &cons->items[i], NULL, NULL, err)) != PGP_OK) {
            memcpy(msg, err->message, sizeof msg);
            snprintf(err->message, sizeof err->message, "%.100s:%d: %.140s", c->constraints,
                     constraint_line(c->constraints, i), msg);
        }
    return r;
}

static pgp_result run(pgp_cmd *c, cli_outputs *outs, pgp_error *err)
{
    pgp_mesh mesh;
    pgp_tile tile;
    pgp_image pic;
    pgp_constraints cons;
    pgp_map map;
    pgp_result r;
    memset(&mesh, 0, sizeof mesh);
    memset(&pic, 0, sizeof pic);
    memset(&cons, 0, sizeof cons);
    memset(&map, 0, sizeof map);
    if ((r = load_tile(c, &tile, err)) != PGP_OK) return r;
    c->opt.threads = c->opt.render.threads; /* --threads: the solves' too */
    if ((r = load_mesh(c->mesh, &c->opt, &mesh, err)) == PGP_OK &&
        (!c->constraints || (r = pgp_load_constraints(c->constraints, &c->opt, &cons, err)) == PGP_OK) &&
        (r = pgp_create(&mesh, &c->opt, &map, err)) == PGP_OK && (r = add_constraints(c, &cons, &map, err)) == PGP_OK)
        report(c, &map, &tile);
    if (r == PGP_OK && (c->opt.render.zoom > 1.0f || c->center_vortex)) r = set_center(c, &mesh, &map, err);
    if (r == PGP_OK && c->out_tile) r = write_file(outs, c->out_tile, NULL, NULL, &tile, err);
    if (r == PGP_OK && c->out_obj) r = write_file(outs, c->out_obj, &mesh, &map, NULL, err);
    if (r == PGP_OK && c->out_glb) r = write_gltf_out(c, outs, &map, &tile, 0, err);
    if (r == PGP_OK && c->out_glb_st) r = write_gltf_out(c, outs, &map, &tile, 1, err);
    if (r == PGP_OK && c->out_image && (r = pgp_render(&map, &tile, &c->opt.render, &pic, err)) == PGP_OK)
        r = write_image(outs, c->out_image, &pic, err);
    pgp_image_free(&pic);
    pgp_map_free(&map);
    pgp_constraints_free(&cons);
    pgp_mesh_free(&mesh);
    pgp_tile_free(&tile);
    return r;
}

int cmd_pgp(int argc, char **argv)
{
    pgp_cmd c;
    cli_outputs outs;
    pgp_error err;
    int p = parse(argc, argv, &c);
    if (p < 0) {
        fputs(pgp_usage, stdout);
        return 0;
    }
    if (!p) return 1;
    memset(&outs, 0, sizeof outs);
    return cli_finish("pgp", &outs, run(&c, &outs, &err) != PGP_OK, err.message);
}
