/* cmd_lapped.c: `patchwork lapped`, the whole of lapped.h from the shell. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "cli.h"

static const char *lapped_usage =
    "usage: patchwork lapped --mesh FILE --texture IMG [--texture IMG ...] [options]\n"
    "\n"
    "Lapped textures (Praun, Finkelstein, Hoppe 2000): texture patches pasted over\n"
    "a mesh along a tangent field until it is covered.\n"
    "\n"
    "inputs:\n"
    "  --mesh FILE          OBJ, OFF or PLY (polygons are fan-triangulated), or\n"
    "                       procedural:NAME (sphere, torus, bumpy, disc)\n"
    "  --texture IMG        a texture patch (PNG, PPM, PGM, PAM, GIMP .pat) or\n"
    "                       procedural:NAME (scales, stripes, dots); repeat for\n"
    "                       several patches, one picked at random per paste\n"
    "  --mask IMG           alpha of the (first) patch from a mask image\n"
    "  --splotch | --circle generated alpha (default: the image's alpha, else splotch)\n"
    "  --falloff PX         alpha fall-off at the patch border (default 3)\n"
    "  --channel IMG        another per-texel channel (bump, displacement...) of the\n"
    "                       same size as the texture; one per --texture, in order\n"
    "field (texture orientation and scale):\n"
    "  --field up[:X,Y,Z]   up direction projected on the surface (default +Y)\n"
    "  --field isotropic    scale only, orientation propagated while growing\n"
    "  --field curvature    along the direction of least curvature\n"
    "  --field constraints:FILE  lines 'orient face dx dy dz [scale [radius [weight]]]'\n"
    "  --scale S            patch side length in mesh units (default: 1/10 of the\n"
    "                       bounding-box diagonal)\n"
    "  --lscm               isotropic: least-squares conformal parametrisation\n"
    "  --seed S             random seed (default 0)\n"
    "outputs (at least one):\n"
    "  --out-pastes FILE    the ordered pastes (text format, see docs/lapped.md)\n"
    "  --out-patch FILE.pam the first patch with its final alpha (RGBA PAM)\n"
    "  --out-image IMG      a rendering by runtime pasting (.png .ppm .pgm .pam)\n"
    "  --size WxH           rendering size (default 800x600; 16..8192 each)\n" CLI_VIEW_USAGE
    "  --out-obj FILE       triangulated mesh with texture-atlas coordinates, and\n"
    "                       FILE's .mtl naming the atlas (needs --out-atlas)\n"
    "  --out-atlas IMG      the lapped texture baked into the atlas (needs --out-obj)\n"
    "  --out-glb FILE.glb   binary glTF 2.0: the mesh with the baked atlas inside\n"
    "  --atlas-size PX      atlas side (default 1024)\n"
    "  --max-pastes N       refuse textures needing more pastes (default 200000;\n"
    "                       a scale that would need more is refused before any work)\n"
    "  --out-channel-image IMG  the --channel images pasted the same way, rendered\n"
    "  --out-channel-atlas IMG  ... baked into an atlas of the same layout as\n"
    "                       --out-atlas (needs --out-obj)\n";

#define MAX_TEXTURES 16

typedef struct lapped_cmd {
    const char *mesh, *textures[MAX_TEXTURES], *channels[MAX_TEXTURES], *mask, *constraints;
    const char *out_pastes, *out_patch, *out_image, *out_obj, *out_atlas, *out_glb;
    const char *out_channel_image, *out_channel_atlas;
    int ntextures, nchannels;
    lapped_options opt;
} lapped_cmd;

static int bad(const char *what, const char *value)
{
    cli_error("lapped", "%s: '%s' is not valid (try patchwork lapped --help)", what, value);
    return 0;
}

/* --field up[:X,Y,Z] | isotropic | curvature | constraints:FILE */
static int parse_field(cli_args *a, lapped_cmd *c)
{
    const char *v;
    lapped_options *f = &c->opt;
    if (!cli_value(a, &v)) return 0;
    if (!strcmp(v, "isotropic")) f->field = LAPPED_FIELD_ISOTROPIC;
    else if (!strcmp(v, "curvature")) f->field = LAPPED_FIELD_CURVATURE;
    else if (!strncmp(v, "constraints:", 12) && v[12]) {
        f->field = LAPPED_FIELD_CONSTRAINTS;
        c->constraints = v + 12;
    } else if (!strcmp(v, "up")) f->field = LAPPED_FIELD_UP;
    else if (!strncmp(v, "up:", 3)) {
        char *end;
        int k;
        const char *p = v + 3;
        f->field = LAPPED_FIELD_UP;
        for (k = 0; k < 3; k++, p = end + 1) {
            f->up[k] = strtof(p, &end);
            if (end == p || (k < 2 && *end != ',') || (k == 2 && *end)) return bad("--field", v);
        }
        if (f->up[0] == 0.0f && f->up[1] == 0.0f && f->up[2] == 0.0f) return bad("--field (zero up vector)", v);
    } else return bad("--field", v);
    return 1;
}

static int parse_one(cli_args *a, lapped_cmd *c)
{
    int v =
        cli_view_flag(a, c->opt.render.view_dir, c->opt.render.up, &c->opt.render.supersample, &c->opt.render.threads);
    if (cli_is(a, "--help") || cli_is(a, "-h")) return -1;
    if (v >= 0) return v;
    if (cli_is(a, "--mesh")) return cli_value(a, &c->mesh);
    if (cli_is(a, "--texture")) {
        if (c->ntextures == MAX_TEXTURES) return bad("--texture", "(more than 16)");
        return cli_value(a, &c->textures[c->ntextures++]);
    }
    if (cli_is(a, "--channel")) {
        if (c->nchannels == MAX_TEXTURES) return bad("--channel", "(more than 16)");
        return cli_value(a, &c->channels[c->nchannels++]);
    }
    if (cli_is(a, "--mask")) {
        (c->opt.alpha = LAPPED_ALPHA_MASK);
        return cli_value(a, &c->mask);
    }
    if (cli_is(a, "--splotch")) {
        (c->opt.alpha = LAPPED_ALPHA_SPLOTCH);
        return 1;
    }
    if (cli_is(a, "--circle")) {
        (c->opt.alpha = LAPPED_ALPHA_CIRCLE);
        return 1;
    }
    if (cli_is(a, "--falloff")) return cli_float(a, 0.0f, 1000.0f, &c->opt.falloff);
    if (cli_is(a, "--field")) return parse_field(a, c);
    if (cli_is(a, "--scale")) return cli_float(a, 1e-30f, 1e30f, &c->opt.scale);
    if (cli_is(a, "--lscm")) return (c->opt.lscm = 1);
    if (cli_is(a, "--seed")) return cli_u64(a, &c->opt.seed);
    if (cli_is(a, "--out-pastes")) return cli_value(a, &c->out_pastes);
    if (cli_is(a, "--out-patch")) return cli_value(a, &c->out_patch);
    if (cli_is(a, "--out-image")) return cli_value(a, &c->out_image);
    if (cli_is(a, "--size")) return cli_size(a, &c->opt.render.width, &c->opt.render.height);
    if (cli_is(a, "--out-obj")) return cli_value(a, &c->out_obj);
    if (cli_is(a, "--out-atlas")) return cli_value(a, &c->out_atlas);
    if (cli_is(a, "--out-glb")) return cli_value(a, &c->out_glb);
    if (cli_is(a, "--out-channel-image")) return cli_value(a, &c->out_channel_image);
    if (cli_is(a, "--out-channel-atlas")) return cli_value(a, &c->out_channel_atlas);
    if (cli_is(a, "--atlas-size")) return cli_int(a, 64, 16384, &c->opt.atlas.size);
    if (cli_is(a, "--max-pastes")) return cli_int(a, 1, 100000000, &c->opt.max_pastes);
    cli_error("lapped", "unknown option '%s' (try patchwork lapped --help)", a->argv[a->i]);
    return 0;
}

static int parse(int argc, char **argv, lapped_cmd *c)
{
    cli_args a;
    int r;
    memset(c, 0, sizeof *c);
    c->opt = lapped_default_options();
    a.argc = argc;
    a.argv = argv;
    a.cmd = "lapped";
    for (a.i = 1; a.i < argc; a.i++)
        if ((r = parse_one(&a, c)) <= 0) return r;
    if (!c->mesh || !c->ntextures) {
        cli_error("lapped", "--mesh and --texture are required");
        return 0;
    }
    if (!!c->out_obj != !!c->out_atlas) {
        cli_error("lapped", "--out-obj and --out-atlas go together");
        return 0;
    }
    if (c->nchannels && c->nchannels != c->ntextures) {
        cli_error("lapped", "%d --channel for %d --texture: give one per texture", c->nchannels, c->ntextures);
        return 0;
    }
    if (!c->nchannels != !(c->out_channel_image || c->out_channel_atlas)) {
        cli_error("lapped", "--channel and --out-channel-image/--out-channel-atlas go together");
        return 0;
    }
    if (c->out_channel_atlas && !c->out_obj) {
        cli_error("lapped", "--out-channel-atlas needs --out-obj and --out-atlas");
        return 0;
    }
    {
        const cli_out outs[8] = {{"--out-pastes", c->out_pastes, CLI_OUT_ANY},
                                 {"--out-patch", c->out_patch, CLI_OUT_PAM},
                                 {"--out-image", c->out_image, CLI_OUT_IMAGE},
                                 {"--out-obj", c->out_obj, CLI_OUT_OBJ},
                                 {"--out-atlas", c->out_atlas, CLI_OUT_IMAGE},
                                 {"--out-glb", c->out_glb, CLI_OUT_GLB},
                                 {"--out-channel-image", c->out_channel_image, CLI_OUT_IMAGE},
                                 {"--out-channel-atlas", c->out_channel_atlas, CLI_OUT_IMAGE}};
        if (!cli_check_outputs("lapped", outs, 8)) return 0;
    }
    if (!c->out_pastes && !c->out_patch && !c->out_image && !c->out_obj && !c->out_channel_image && !c->out_glb) {
        cli_error("lapped", "nothing to write: give --out-pastes, --out-patch, --out-image, "
                            "--out-obj, --out-glb or --out-channel-image");
        return 0;
    }
    return 1;
}

static lapped_result load_mesh(const char *src, const lapped_options *o, lapped_mesh *m, lapped_error *err)
{
    const char *name;
    if (cli_is_procedural(src, &name)) return lapped_builtin_mesh(name, o, m, err);
    return lapped_load_mesh(src, o, m, err);
}

static lapped_result load_image(const char *src, const lapped_options *o, lapped_image *img, lapped_error *err)
{
    const char *name;
    if (cli_is_procedural(src, &name)) return lapped_builtin_exemplar(name, 128, o, img, err);
    return lapped_load_image(src, o, img, err);
}

/* Writes a lapped image through the shared image writer. */
static lapped_result write_image(cli_outputs *outs, const char *path, const lapped_image *img, lapped_error *err)
{
    tiled_image view = cli_image_view(img->width, img->height, img->channels, img->pixels, img->bits);
    return err->code = (lapped_result)cli_write_view(outs, path, &view, err->message);
}

/* The RGBA patches from the textures (the mask applies to the first). */
static lapped_result make_patches(lapped_cmd *c, lapped_image *patches, lapped_error *err)
{
    lapped_image tex, mask;
    lapped_result r = LAPPED_OK;
    int k;
    memset(&mask, 0, sizeof mask);
    if (c->mask && (r = load_image(c->mask, &c->opt, &mask, err)) != LAPPED_OK) return r;
    for (k = 0; k < c->ntextures && r == LAPPED_OK; k++) {
        lapped_options o = c->opt;
        if (k > 0 && o.alpha == LAPPED_ALPHA_MASK) o.alpha = LAPPED_ALPHA_AUTO;
        o.seed = c->opt.seed + (unsigned long long)k; /* different splotches */
        if ((r = load_image(c->textures[k], &o, &tex, err)) == LAPPED_OK) {
            r = lapped_make_patch(&tex, k == 0 && c->mask ? &mask : NULL, &o, &patches[k], err);
            lapped_image_free(&tex);
        }
    }
    lapped_image_free(&mask);
    return r;
}

static lapped_result write_pastes(cli_outputs *outs, const char *path, const lapped_texture *t, lapped_error *err)
{
    FILE *f = cli_open(outs, path, err->message, sizeof err->message);
    lapped_result r;
    if (!f) return err->code = LAPPED_ERR_IO;
    r = lapped_write_pastes(t, cli_fwrite, f, err);
    if (!cli_close(f, r == LAPPED_OK, path, err->message, sizeof err->message)) r = LAPPED_ERR_IO;
    return err->code = r;
}

/* OBJ + MTL naming the atlas image. */
static lapped_result write_obj(lapped_cmd *c, cli_outputs *outs, const lapped_mesh *mesh, const lapped_atlas *atlas,
                               lapped_error *err)
{
    char mtl[1024];
    lapped_result r;
    FILE *f;
    cli_with_ext(c->out_obj, ".mtl", mtl, sizeof mtl);
    if ((f = cli_open(outs, c->out_obj, err->message, sizeof err->message)) == NULL) return err->code = LAPPED_ERR_IO;
    r = lapped_write_obj(mesh, atlas, cli_texture_ref(c->out_obj, mtl), cli_fwrite, f, err);
    if (!cli_close(f, r == LAPPED_OK, c->out_obj, err->message, sizeof err->message)) r = LAPPED_ERR_IO;
    if (r == LAPPED_OK && (f = cli_open(outs, mtl, err->message, sizeof err->message)) == NULL) r = LAPPED_ERR_IO;
    else if (r == LAPPED_OK) {
        r = lapped_write_mtl(cli_texture_ref(c->out_obj, c->out_atlas), cli_fwrite, f, err);
        if (!cli_close(f, r == LAPPED_OK, mtl, err->message, sizeof err->message)) r = LAPPED_ERR_IO;
    }
    return err->code = r;
}

static lapped_result write_glb(cli_outputs *outs, const char *path, const lapped_mesh *mesh, const lapped_atlas *atlas,
                               const lapped_render_options *view, lapped_error *err)
{
    FILE *f = cli_open(outs, path, err->message, sizeof err->message);
    lapped_result r;
    if (!f) return err->code = LAPPED_ERR_IO;
    r = lapped_write_gltf(mesh, atlas, view, cli_fwrite, f, err);
    if (!cli_close(f, r == LAPPED_OK, path, err->message, sizeof err->message)) r = LAPPED_ERR_IO;
    return err->code = r;
}

/* What a run's renderings and atlases are made from: the command, its
 * outputs, the mesh and the lapped texture made for it. */
typedef struct lapped_made {
    lapped_cmd *c;
    cli_outputs *outs;
    const lapped_mesh *mesh;
    const lapped_texture *t;
} lapped_made;

/* The lapped texture (src->values NULL) or the extra channel baked into an
 * atlas image at `path` (if not NULL); with `obj`, also the OBJ + MTL, and
 * with `glb` the binary glTF. The layout depends only on the mesh and the
 * pastes, so both atlases share it. */
static lapped_result write_atlas(const lapped_made *M, const lapped_source *src, const char *path, int obj,
                                 const char *glb, lapped_error *err)
{
    lapped_cmd *c = M->c;
    cli_outputs *outs = M->outs;
    const lapped_mesh *mesh = M->mesh;
    lapped_atlas atlas;
    lapped_result r = lapped_bake_atlas(mesh, M->t, src, &c->opt, &atlas, err);
    if (r != LAPPED_OK) return r;
    if (obj) r = write_obj(c, outs, mesh, &atlas, err);
    if (r == LAPPED_OK && glb) r = write_glb(outs, glb, mesh, &atlas, &c->opt.render, err);
    if (r == LAPPED_OK && path) r = write_image(outs, path, &atlas.image, err);
    if (r == LAPPED_OK && (obj || glb))
        printf("lapped: atlas of %d charts, %.0f%% of %dx%d filled\n", atlas.ncharts, 100.0 * atlas.fill,
               atlas.image.width, atlas.image.height);
    lapped_atlas_free(&atlas);
    return err->code = r;
}

/* The runtime-pasting rendering of the patches (src->values NULL) or of
 * the extra channel. */
static lapped_result write_render(const lapped_made *M, const lapped_source *src, const char *path, lapped_error *err)
{
    lapped_image pic;
    lapped_result r = lapped_render(M->mesh, M->t, src, &M->c->opt.render, &pic, err);
    if (r != LAPPED_OK) return r;
    r = write_image(M->outs, path, &pic, err);
    lapped_image_free(&pic);
    return r;
}

static lapped_result run(lapped_cmd *c, cli_outputs *outs, lapped_error *err)
{
    lapped_image patches[MAX_TEXTURES], channels[MAX_TEXTURES];
    lapped_source src, channel_src;
    lapped_made made;
    lapped_constraints cons;
    lapped_texture t;
    lapped_mesh mesh;
    lapped_result r;
    int k;
    memset(patches, 0, sizeof patches);
    memset(channels, 0, sizeof channels);
    memset(&t, 0, sizeof t);
    memset(&mesh, 0, sizeof mesh);
    memset(&cons, 0, sizeof cons);
    src.patches = channel_src.patches = patches;
    src.npatches = channel_src.npatches = c->ntextures;
    src.values = NULL;
    channel_src.values = channels;
    r = make_patches(c, patches, err);
    for (k = 0; k < c->nchannels && r == LAPPED_OK; k++) r = load_image(c->channels[k], &c->opt, &channels[k], err);
    if (r == LAPPED_OK && c->constraints &&
        (r = lapped_load_constraints(c->constraints, &c->opt, &cons, err)) == LAPPED_OK) {
        if (err->message[0]) fprintf(stderr, "patchwork lapped: warning: %s\n", err->message);
        c->opt.constraints = cons.items;
        c->opt.nconstraints = cons.count;
    }
    if (r == LAPPED_OK) r = load_mesh(c->mesh, &c->opt, &mesh, err);
    c->opt.threads = c->opt.render.threads; /* --threads: the coverage's too */
    if (r == LAPPED_OK && (r = lapped_create(&mesh, &src, &c->opt, &t, err)) == LAPPED_OK)
        printf("lapped: %d triangles covered by %d pastes, %.2f layers per triangle (%.2f before "
               "removing hidden ones), %d with hard edges\n",
               t.ntris, t.npastes, t.layers, t.layers_before, t.hard_edges);
    if (r == LAPPED_OK && c->out_patch) r = write_image(outs, c->out_patch, &patches[0], err);
    if (r == LAPPED_OK && c->out_pastes) r = write_pastes(outs, c->out_pastes, &t, err);
    made.c = c;
    made.outs = outs;
    made.mesh = &mesh;
    made.t = &t;
    if (r == LAPPED_OK && c->out_image) r = write_render(&made, &src, c->out_image, err);
    if (r == LAPPED_OK && c->out_channel_image) r = write_render(&made, &channel_src, c->out_channel_image, err);
    if (r == LAPPED_OK && (c->out_obj || c->out_glb))
        r = write_atlas(&made, &src, c->out_atlas, c->out_obj != NULL, c->out_glb, err);
    if (r == LAPPED_OK && c->out_channel_atlas)
        r = write_atlas(&made, &channel_src, c->out_channel_atlas, 0, NULL, err);
    lapped_texture_free(&t);
    lapped_mesh_free(&mesh);
    lapped_constraints_free(&cons);
    for (k = 0; k < MAX_TEXTURES; k++) {
        lapped_image_free(&patches[k]);
        lapped_image_free(&channels[k]);
    }
    return r;
}

int cmd_lapped(int argc, char **argv)
{
    lapped_cmd c;
    cli_outputs outs;
    lapped_error err;
    int p = parse(argc, argv, &c);
    if (p < 0) {
        fputs(lapped_usage, stdout);
        return 0;
    }
    if (!p) return 1;
    memset(&outs, 0, sizeof outs);
    return cli_finish("lapped", &outs, run(&c, &outs, &err) != LAPPED_OK, err.message);
}
