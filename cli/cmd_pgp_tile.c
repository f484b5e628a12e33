/* cmd_pgp_tile.c: `patchwork pgp-tile`, material-space tile synthesis
 * (pgp.h, section 1) from the shell. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "cli.h"

static const char *tile_usage =
    "usage: patchwork pgp-tile --key IMG[:MASK] --key IMG[:MASK] [--key ...] [--layers M]\n"
    "                          [--size PX] [--seed S] --out FILE.nrrd [--out-slices PREFIX]\n"
    "\n"
    "Material-space tile synthesis (Ray, Levy, Wang, Turk, Vallet 2009, section 1): a 3D\n"
    "texture whose every layer tiles in s and t and whose pattern morphs along m from\n"
    "key to key, the features moving, splitting and merging (level-set advection of\n"
    "the feature masks), each layer synthesised from both neighbouring keys under its\n"
    "morphed mask and blended. The tile is what `patchwork pgp --tile` maps on a mesh.\n"
    "\n"
    "keys (in order along m, the first at m = 0 and the last at m = 1):\n"
    "  --key IMG[:MASK]     a key texture (PNG, PPM, PGM, PAM, GIMP .pat) and optionally\n"
    "                       its feature mask, an image of the same size whose light texels\n"
    "                       (luminance above 1/2) are the features; two or more keys\n"
    "  --single             single-tile mode (Fig. 14): one key, every layer synthesised\n"
    "                       under its mask, to hide the periodicity of one texture\n"
    "  --mask-mode MODE     masks not given are computed: dark (default; texels darker\n"
    "                       than their surroundings), bright, or gradient (edges)\n"
    "  --tileable MODE      auto (default: keys with a visible wrap-around seam are made\n"
    "                       tileable by graph-cut quilting), keep, or make\n"
    "options:\n"
    "  --layers M           layers of the tile (default 8, at least one per key)\n"
    "  --size PX            tile side in texels, 16..4096 (default 128); every key is\n"
    "                       resampled to PX x PX, never cropped\n"
    "  --seed S             seed of the pixel order (default 0)\n"
    "  --uniform            layers at equal advection steps instead of speed-adaptive\n"
    "  --exact              exact nearest neighbours (default: approximate, within a\n"
    "                       factor 2 and 64 kd-tree buckets, as the paper's ANN; slower)\n"
    "outputs:\n"
    "  --out FILE.nrrd      the tile: NRRD, uint8, sizes C W H M (W H M when gray)\n"
    "  --out-slices PREFIX  every layer as PREFIX_00.png, PREFIX_01.png, ... (PREFIX\n"
    "                       ending in .ppm or .png chooses the format)\n"
    "  --out-masks PREFIX   every layer's feature mask, the same way\n";

typedef struct tile_cmd {
    const char *key[256];
    int nkeys;
    const char *out, *slices, *masks;
    pgp_synth_options opt;
} tile_cmd;

static int bad(const char *what, const char *value)
{
    cli_error("pgp-tile", "%s: '%s' is not valid (try patchwork pgp-tile --help)", what, value);
    return 0;
}

/* --mask-mode and --tileable */
static int parse_mode(cli_args *a, const char *const *names, int n, int *out)
{
    const char *flag = a->argv[a->i], *v;
    int k;
    if (!cli_value(a, &v)) return 0;
    for (k = 0; k < n; k++)
        if (!strcmp(v, names[k])) {
            (*out = k);
            return 1;
        }
    return bad(flag, v);
}

static int parse_one(cli_args *a, tile_cmd *c)
{
    static const char *const masks[3] = {"dark", "bright", "gradient"}, *const tileable[3] = {"auto", "keep", "make"};
    int k;
    if (cli_is(a, "--help") || cli_is(a, "-h")) return -1;
    if (cli_is(a, "--key")) {
        if (c->nkeys == 256) return bad("--key (at most 256 keys)", a->argv[a->i]);
        return cli_value(a, &c->key[c->nkeys++]);
    }
    if (cli_is(a, "--single")) return (c->opt.single = 1);
    if (cli_is(a, "--mask-mode")) return parse_mode(a, masks, 3, &k) ? (c->opt.auto_mask = (pgp_mask)k, 1) : 0;
    if (cli_is(a, "--tileable")) return parse_mode(a, tileable, 3, &k) ? (c->opt.tileable = (pgp_tileable)k, 1) : 0;
    if (cli_is(a, "--layers")) return cli_int(a, 1, 1024, &c->opt.layers);
    if (cli_is(a, "--size")) return cli_int(a, 16, 4096, &c->opt.size);
    if (cli_is(a, "--seed")) return cli_u64(a, &c->opt.seed);
    if (cli_is(a, "--uniform")) return (c->opt.uniform = 1);
    if (cli_is(a, "--exact")) {
        (c->opt.search_eps = -1.0f);
        (c->opt.search_buckets = -1);
        return 1;
    }
    if (cli_is(a, "--out")) return cli_value(a, &c->out);
    if (cli_is(a, "--out-slices")) return cli_value(a, &c->slices);
    if (cli_is(a, "--out-masks")) return cli_value(a, &c->masks);
    cli_error("pgp-tile", "unknown option '%s' (try patchwork pgp-tile --help)", a->argv[a->i]);
    return 0;
}

/* PREFIX_kk.EXT for layer k: EXT from PREFIX's own extension (png, ppm), else png. */
static void slice_path(const char *prefix, int k, char *out, size_t size)
{
    const char *fmt = cli_image_format(prefix);
    char base[1024];
    if (fmt && (!strcmp(fmt, "png") || !strcmp(fmt, "ppm"))) {
        cli_with_ext(prefix, "", base, sizeof base);
        snprintf(out, size, "%s_%02d.%s", base, k, fmt);
    } else snprintf(out, size, "%s_%02d.png", prefix, k);
}

static int parse(int argc, char **argv, tile_cmd *c)
{
    cli_args a;
    int r;
    memset(c, 0, sizeof *c);
    c->opt = pgp_default_options().synth;
    a.argc = argc;
    a.argv = argv;
    a.cmd = "pgp-tile";
    for (a.i = 1; a.i < argc; a.i++)
        if ((r = parse_one(&a, c)) <= 0) return r;
    if (c->nkeys < (c->opt.single ? 1 : 2) || (c->opt.single && c->nkeys > 1)) {
        cli_error("pgp-tile",
                  c->opt.single ? "--single takes exactly one --key (%d given)"
                                : "a morph needs two or more --key (%d given; --single takes one)",
                  c->nkeys);
        return 0;
    }
    if (!c->out) {
        cli_error("pgp-tile", "--out FILE.nrrd is required");
        return 0;
    }
    {
        const cli_out outs[3] = {{"--out", c->out, CLI_OUT_NRRD},
                                 {"--out-slices", c->slices, CLI_OUT_PREFIX},
                                 {"--out-masks", c->masks, CLI_OUT_PREFIX}};
        if (!cli_check_outputs("pgp-tile", outs, 3)) return 0;
    }
    if (c->slices && c->masks) {
        char a0[1100], b0[1100];
        slice_path(c->slices, 0, a0, sizeof a0);
        slice_path(c->masks, 0, b0, sizeof b0);
        if (!strcmp(a0, b0)) {
            cli_error("pgp-tile", "--out-slices and --out-masks name the same files (%s ...)", a0);
            return 0;
        }
    }
    return 1;
}

/* IMG[:MASK]: the mask after the last ':' when what precedes it is a
 * readable file (so that a path with a colon still works as an image). */
static pgp_result load_key(const char *spec, pgp_image *img, pgp_image *mask, int *has_mask, pgp_error *err)
{
    char path[1024];
    const char *colon = strrchr(spec, ':');
    FILE *f;
    pgp_result r;
    *has_mask = 0;
    if (colon && (size_t)(colon - spec) < sizeof path) {
        memcpy(path, spec, (size_t)(colon - spec));
        path[colon - spec] = 0;
        if ((f = fopen(path, "rb")) != NULL) {
            fclose(f);
            if ((r = pgp_load_image(path, NULL, img, err)) != PGP_OK) return r;
            if ((r = pgp_load_image(colon + 1, NULL, mask, err)) != PGP_OK) pgp_image_free(img);
            *has_mask = r == PGP_OK;
            return r;
        }
    }
    return pgp_load_image(spec, NULL, img, err);
}

/* Staged outputs, 16 per cli_outputs. */
typedef struct tile_outs {
    cli_outputs *o;
    int n;
} tile_outs;

static cli_outputs *next_outs(tile_outs *t)
{
    if (t->o[t->n].n == 16) t->n++;
    return &t->o[t->n];
}

/* One staged file: the tile (img NULL) or an image. */
static pgp_result write_one(tile_outs *t, const char *path, const pgp_tile *tile, const pgp_image *img, pgp_error *err)
{
    const char *fmt = img ? cli_image_format(path) : NULL;
    FILE *f = cli_open(next_outs(t), path, err->message, sizeof err->message);
    pgp_result r;
    if (!f) return err->code = PGP_ERR_IO;
    r = img ? pgp_write_image(img, fmt, cli_fwrite, f, err) : pgp_write_tile(tile, cli_fwrite, f, err);
    if (r == PGP_ERR_IO) snprintf(err->message, sizeof err->message, "%.200s: write error (disk full?)", path);
    if (!cli_close(f, r == PGP_OK, path, err->message, sizeof err->message)) r = PGP_ERR_IO;
    return err->code = r;
}

/* Every layer of a tile as an image. */
static pgp_result write_slices(tile_outs *t, const char *prefix, const pgp_tile *tile, pgp_error *err)
{
    char path[1100];
    pgp_image view;
    pgp_result r = PGP_OK;
    int k;
    memset(&view, 0, sizeof view);
    view.width = tile->width;
    view.height = tile->height;
    view.channels = tile->channels;
    for (k = 0; k < tile->layers && r == PGP_OK; k++) {
        view.pixels = tile->pixels + (size_t)k * tile->width * tile->height * tile->channels;
        slice_path(prefix, k, path, sizeof path);
        r = write_one(t, path, NULL, &view, err);
    }
    return r;
}

static pgp_result synthesize(tile_cmd *c, tile_outs *outs, pgp_error *err)
{
    pgp_image img[256], mask[256];
    pgp_key keys[256];
    pgp_tile tile, masks;
    pgp_result r = PGP_OK;
    int k, has;
    memset(&tile, 0, sizeof tile);
    memset(&masks, 0, sizeof masks);
    memset(img, 0, sizeof img);
    memset(mask, 0, sizeof mask);
    for (k = 0; k < c->nkeys && r == PGP_OK; k++) {
        r = load_key(c->key[k], &img[k], &mask[k], &has, err);
        keys[k].image = &img[k];
        keys[k].mask = has ? &mask[k] : NULL;
    }
    if (r == PGP_OK) r = pgp_synthesize_tile(keys, c->nkeys, &c->opt, &tile, c->masks ? &masks : NULL, err);
    if (r == PGP_OK) {
        printf("pgp-tile: %d layer%s of %dx%d texels, %d channel%s, from %d key%s\n", tile.layers,
               tile.layers == 1 ? "" : "s", tile.width, tile.height, tile.channels, tile.channels == 1 ? "" : "s",
               c->nkeys, c->nkeys == 1 ? "" : "s");
        r = write_one(outs, c->out, &tile, NULL, err);
    }
    if (r == PGP_OK && c->slices) r = write_slices(outs, c->slices, &tile, err);
    if (r == PGP_OK && c->masks) r = write_slices(outs, c->masks, &masks, err);
    for (k = 0; k < c->nkeys; k++) {
        pgp_image_free(&img[k]);
        pgp_image_free(&mask[k]);
    }
    pgp_tile_free(&tile);
    pgp_tile_free(&masks);
    return r;
}

int cmd_pgp_tile(int argc, char **argv)
{
    tile_cmd c;
    tile_outs outs;
    pgp_error err;
    tiled_error terr;
    int p = parse(argc, argv, &c), k, status = 0;
    if (p < 0) {
        fputs(tile_usage, stdout);
        return 0;
    }
    if (!p) return 1;
    outs.n = 0;
    outs.o = (cli_outputs *)calloc((size_t)(1 + 2 * c.opt.layers) / 16 + 2, sizeof(cli_outputs));
    if (!outs.o) {
        cli_error("pgp-tile", "out of memory");
        return 1;
    }
    if (synthesize(&c, &outs, &err) != PGP_OK) {
        for (k = 0; k <= outs.n; k++) cli_abort(&outs.o[k]);
        cli_error("pgp-tile", "%s", err.message);
        status = 1;
    }
    for (k = 0; status == 0 && k <= outs.n; k++)
        if (cli_commit(&outs.o[k], &terr) != TILED_OK) {
            for (k++; k <= outs.n; k++) cli_abort(&outs.o[k]);
            cli_error("pgp-tile", "%s", terr.message);
            status = 1;
        }
    free(outs.o);
    return status;
}
