/* cmd_lst.c: `patchwork lst`, the whole of lst.h from the shell. */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "cli.h"

static const char *lst_usage = "usage: patchwork lst (--mesh FILE | --tets FILE.node | --tets FILE.mesh)\n"
                               "                     (--exemplar FILE.nrrd | --exemplar procedural:NAME) [options]\n"
                               "\n"
                               "Lapped solid textures (Takayama, Okabe, Ijiri, Igarashi 2008): the inside of a\n"
                               "closed surface filled with overlapping solid exemplars aligned to a tensor\n"
                               "field, shown as the surface, cross-sections and a volume rendering.\n"
                               "\n"
                               "inputs:\n"
                               "  --mesh FILE          a closed surface (OBJ, OFF, PLY), tetrahedralized here\n"
                               "                       (holes up to 5% of the diagonal around are closed),\n"
                               "                       or procedural:NAME (sphere, torus, bumpy, kiwi, tree,\n"
                               "                       dumbbell, star)\n"
                               "  --tets FILE          a tetrahedral mesh: TetGen FILE.node (with FILE.ele) or\n"
                               "                       MEDIT FILE.mesh\n"
                               "  --tet-count N        tetrahedra to aim for inside with --mesh (default 20000;\n"
                               "                       the lattice is finer near the surface where it bends,\n"
                               "                       is thin or nearly touches itself, so there are more)\n"
                               "  --cell H             or the lattice spacing inside, mesh units\n"
                               "  --tet-fit F          the bend of the surface one lattice tetrahedron may hold,\n"
                               "                       as a fraction of the diagonal (default 0.0025: the\n"
                               "                       boundary lands within about 0.4%); larger: fewer\n"
                               "  --tet-uniform        a uniform lattice of --tet-count tetrahedra instead\n"
                               "                       (proven dihedral bounds; parts thinner than a cell lost)\n"
                               "  --strict             refuse a closed surface whose triangles cross (by default\n"
                               "                       it is filled where its winding number is at least 1/2,\n"
                               "                       with a warning; --allow-self-intersections is accepted\n"
                               "                       and does nothing)\n"
                               "  --exemplar FILE      a solid exemplar: NRRD (sizes C X Y Z or X Y Z; RGBA:\n"
                               "                       the alpha is the mask of homogeneous types) or\n"
                               "                       procedural:NAME (layers, fibers, spots, rings, kiwi)\n"
                               "  --exemplar-size N    side of a procedural exemplar (default 64)\n"
                               "  --values FILE.nrrd   an extra channel (displacement...) of the exemplar's size\n"
                               "field and pasting:\n"
                               "  --type T             0 (isotropic, default), 1a (fibres), 1b (layers along the\n"
                               "                       depth), 2a (three axes), 2b (three axes, depth-varying)\n"
                               "  --scale S            exemplar side in mesh units (0, 1a, 2a; default 1/5 of\n"
                               "                       the bounding-box diagonal)\n"
                               "  --constraints FILE   a constraint file (repeatable), one constraint a line:\n"
                               "                       depths 'face F D', 'fill F D [CREASE]', 'point X Y Z D',\n"
                               "                       'depth-stroke D X Y Z X Y Z ...'; directions and scales\n"
                               "                       'dir X Y Z DX DY DZ', 'dir-stroke X Y Z X Y Z ...',\n"
                               "                       'scale X Y Z S'; or procedural:NAME (kiwi, tree, torus).\n"
                               "                       Default depth: the normalised distance from the surface;\n"
                               "                       default direction: the principal axis of the shape\n"
                               "  --depth FILE         the same as --constraints (procedural:NAME: only the depth\n"
                               "                       constraints of the built-in set)\n"
                               "  --directions FILE    the same as --constraints (procedural:NAME: only the\n"
                               "                       directions and scales of the built-in set)\n"
                               "  --axis X,Y,Z         the default direction instead of the principal axis\n"
                               "  --samples N          coverage lattice order (default 8: 165 points per tet)\n"
                               "  --seed S             random seed (default 0)\n"
                               "  --paste \"X Y Z UX UY UZ VX VY VZ S [MASK]\"  a manual paste on top (repeatable)\n";

/* The rest of the usage, in string literals of their own (C99 compilers
 * need only take 4095 characters in one). */
static const char *lst_usage_views =
    "views:\n"
    "  --cut \"NX NY NZ D\"   cut away the side NX x + NY y + NZ z > D (repeatable)\n"
    "  --cut-stroke \"X Y Z X Y Z ...\"  cut along a stroke seen along the view\n" CLI_VIEW_USAGE
    "  --up X,Y,Z           the same as --view-up\n"
    "  --size WxH           image size (default 800x600; 16..8192 each)\n"
    "  --show WHAT          color (default), values, pastes, depth (u,v,w as RGB)\n"
    "  --displace A         displacement mapping of the surface by the extra channel\n"
    "  --slices N           volume rendering slices (default 200)\n"
    "  --opacity A          volume rendering opacity (default 0.3)\n";

static const char *lst_usage_outputs =
    "outputs (at least one):\n"
    "  --out-lst FILE       the model (text format, see docs/lst.md)\n"
    "  --out-masks PREFIX   each exemplar's alpha as PREFIX<i>.nrrd\n"
    "  --out-exemplar FILE.nrrd  the exemplar's colour (alone, with no --mesh: only that,\n"
    "                       e.g. a built-in exemplar to start from)\n"
    "  --out-image IMG      the surface (after any cut)\n"
    "  --out-section IMG    the last --cut seen face on\n"
    "  --out-volume IMG     a volume rendering (slices composited with alpha)\n"
    "  --out-tets FILE      the tetrahedral mesh filled: FILE.node (+ .ele) or .mesh\n"
    "  --out-surface FILE.obj  the boundary of the tetrahedral mesh filled, as OBJ\n"
    "  --out-glb FILE.glb   binary glTF 2.0: the surface after any cut (and the cut\n"
    "                       faces) with the model's colour baked into a texture\n"
    "                       atlas inside, and the camera of --out-image\n"
    "  --out-obj FILE.obj   the same mesh with its atlas coordinates, and FILE's .mtl\n"
    "                       naming the atlas (needs --out-atlas)\n"
    "  --out-atlas IMG      the baked atlas (needs --out-obj)\n"
    "  --atlas-size PX      atlas side (default 1024)\n";

#define LST_MAX_CUTS 8
#define LST_MAX_PASTES 16
#define LST_MAX_CONSTRAINT_FILES 16

typedef struct lst_cmd {
    const char *mesh, *tets, *exemplar, *values;
    const char *cons[LST_MAX_CONSTRAINT_FILES]; /* --constraints, --depth, --directions, in order */
    char cons_flag[LST_MAX_CONSTRAINT_FILES];   /* 'c', 'd' or 'f': which flag gave it */
    const char *out_lst, *out_masks, *out_exemplar, *out_image, *out_section, *out_volume, *out_tets, *out_surface;
    const char *out_glb, *out_obj, *out_atlas;
    const char *pastes[LST_MAX_PASTES], *stroke;
    float cuts[LST_MAX_CUTS][4];
    int ncuts, npastes, ncons, exemplar_size;
    lst_options opt; /* with the tetrahedralizer's, the render's and the volume rendering's settings */
} lst_cmd;

static int bad(const char *what, const char *value)
{
    cli_error("lst", "%s: '%s' is not valid (try patchwork lst --help)", what, value);
    return 0;
}

/* n floats separated by blanks or commas; 0 when the text is not that. */
static int parse_floats(const char *v, float *out, int min, int max)
{
    char *end;
    const char *p = v;
    int n = 0;
    for (;;) {
        while (*p == ' ' || *p == ',' || *p == '\t') p++;
        if (!*p) break;
        if (n == max) return 0;
        out[n] = strtof(p, &end);
        if (end == p || !(out[n] - out[n] == 0.0f)) return 0;
        n++;
        p = end;
    }
    return n >= min ? n : 0;
}

static int parse_vec(cli_args *a, float *out)
{
    const char *flag = a->argv[a->i], *v;
    if (!cli_value(a, &v)) return 0;
    if (parse_floats(v, out, 3, 3) != 3) return bad(flag, v);
    return 1;
}

static int parse_type(cli_args *a, lst_cmd *c)
{
    static const char *const names[5] = {"0", "1a", "1b", "2a", "2b"};
    const char *v;
    int k;
    if (!cli_value(a, &v)) return 0;
    for (k = 0; k < 5; k++)
        if (!strcmp(v, names[k])) {
            (c->opt.type = (lst_type)k);
            return 1;
        }
    return bad("--type (0, 1a, 1b, 2a, 2b)", v);
}

static int parse_show(cli_args *a, lst_cmd *c)
{
    static const char *const names[4] = {"color", "values", "pastes", "depth"};
    const char *v;
    int k;
    if (!cli_value(a, &v)) return 0;
    for (k = 0; k < 4; k++)
        if (!strcmp(v, names[k])) {
            (c->opt.render.show = (lst_show)k);
            return 1;
        }
    return bad("--show (color, values, pastes, depth)", v);
}

static int parse_cut(cli_args *a, lst_cmd *c)
{
    const char *v;
    if (!cli_value(a, &v)) return 0;
    if (c->ncuts == LST_MAX_CUTS) return bad("--cut (too many)", v);
    if (parse_floats(v, c->cuts[c->ncuts], 4, 4) != 4) return bad("--cut (\"NX NY NZ D\")", v);
    c->ncuts++;
    return 1;
}

static int parse_paste(cli_args *a, lst_cmd *c)
{
    const char *v;
    float f[11];
    if (!cli_value(a, &v)) return 0;
    if (c->npastes == LST_MAX_PASTES) return bad("--paste (too many)", v);
    if (!parse_floats(v, f, 10, 11)) return bad("--paste (\"X Y Z UX UY UZ VX VY VZ S [MASK]\")", v);
    c->pastes[c->npastes++] = v;
    return 1;
}

/* --constraints (flag 'c'), --depth ('d'), --directions ('f'). */
static int parse_constraints(cli_args *a, lst_cmd *c, char flag)
{
    const char *v;
    if (!cli_value(a, &v)) return 0;
    if (c->ncons == LST_MAX_CONSTRAINT_FILES) return bad("--constraints (too many)", v);
    c->cons_flag[c->ncons] = flag;
    c->cons[c->ncons++] = v;
    return 1;
}

static int parse_options(cli_args *a, lst_cmd *c)
{
    lst_render_options *ro = &c->opt.render;
    int r;
    if (cli_is(a, "--type")) return parse_type(a, c);
    if (cli_is(a, "--scale")) return cli_float(a, 1e-30f, 1e30f, &c->opt.scale);
    if (cli_is(a, "--constraints")) return parse_constraints(a, c, 'c');
    if (cli_is(a, "--depth")) return parse_constraints(a, c, 'd');
    if (cli_is(a, "--directions")) return parse_constraints(a, c, 'f');
    if (cli_is(a, "--axis")) return parse_vec(a, c->opt.axis);
    if (cli_is(a, "--samples")) return cli_int(a, 1, 32, &c->opt.samples);
    if (cli_is(a, "--seed")) return cli_u64(a, &c->opt.seed);
    if (cli_is(a, "--paste")) return parse_paste(a, c);
    if (cli_is(a, "--tet-count")) return cli_int(a, 10, 20000000, &c->opt.tet.target_tets);
    if (cli_is(a, "--tet-uniform")) return (c->opt.tet.uniform = 1);
    if (cli_is(a, "--allow-self-intersections")) return 1; /* the default now, kept for old scripts */
    if (cli_is(a, "--strict")) return (c->opt.tet.strict = 1);
    if (cli_is(a, "--exemplar-size")) return cli_int(a, 4, 512, &c->exemplar_size);
    if (cli_is(a, "--cut")) return parse_cut(a, c);
    if (cli_is(a, "--cut-stroke")) return cli_value(a, &c->stroke);
    if (cli_is(a, "--up")) return cli_vec3(a, ro->up); /* the older name of --view-up */
    if ((r = cli_view_flag(a, ro->view_dir, ro->up, &ro->supersample, &ro->threads)) >= 0) return r;
    if (cli_is(a, "--size")) return cli_size(a, &ro->width, &ro->height);
    if (cli_is(a, "--show")) return parse_show(a, c);
    if (cli_is(a, "--displace")) return cli_float(a, -1e30f, 1e30f, &ro->displace);
    if (cli_is(a, "--slices")) return cli_int(a, 1, 10000, &c->opt.volume.slices);
    if (cli_is(a, "--opacity")) return cli_float(a, 1e-6f, 1000.0f, &c->opt.volume.opacity);
    return -2;
}

static int parse_one(cli_args *a, lst_cmd *c)
{
    float cell;
    int r;
    if (cli_is(a, "--help") || cli_is(a, "-h")) return -1;
    if (cli_is(a, "--mesh")) return cli_value(a, &c->mesh);
    if (cli_is(a, "--tets")) return cli_value(a, &c->tets);
    if (cli_is(a, "--exemplar")) return cli_value(a, &c->exemplar);
    if (cli_is(a, "--values")) return cli_value(a, &c->values);
    if (cli_is(a, "--cell")) return cli_float(a, 1e-30f, 1e30f, &cell) && (c->opt.tet.cell = cell, 1);
    if (cli_is(a, "--tet-fit")) return cli_float(a, 1e-5f, 0.1f, &cell) && (c->opt.tet.fit = cell, 1);
    if (cli_is(a, "--out-lst")) return cli_value(a, &c->out_lst);
    if (cli_is(a, "--out-masks")) return cli_value(a, &c->out_masks);
    if (cli_is(a, "--out-exemplar")) return cli_value(a, &c->out_exemplar);
    if (cli_is(a, "--out-image")) return cli_value(a, &c->out_image);
    if (cli_is(a, "--out-section")) return cli_value(a, &c->out_section);
    if (cli_is(a, "--out-volume")) return cli_value(a, &c->out_volume);
    if (cli_is(a, "--out-tets")) return cli_value(a, &c->out_tets);
    if (cli_is(a, "--out-surface")) return cli_value(a, &c->out_surface);
    if (cli_is(a, "--out-glb")) return cli_value(a, &c->out_glb);
    if (cli_is(a, "--out-obj")) return cli_value(a, &c->out_obj);
    if (cli_is(a, "--out-atlas")) return cli_value(a, &c->out_atlas);
    if (cli_is(a, "--atlas-size")) return cli_int(a, 16, 8192, &c->opt.atlas.size);
    if ((r = parse_options(a, c)) != -2) return r;
    cli_error("lst", "unknown option '%s' (try patchwork lst --help)", a->argv[a->i]);
    return 0;
}

static int ends_with(const char *s, const char *ext)
{
    size_t n = strlen(s), m = strlen(ext);
    return n > m && !strcmp(s + n - m, ext);
}

/* Only --out-exemplar asked for: the exemplar is written, nothing filled. */
static int exemplar_only(const lst_cmd *c)
{
    return c->out_exemplar && !c->mesh && !c->tets && !c->out_lst && !c->out_masks && !c->out_image &&
           !c->out_section && !c->out_volume && !c->out_tets && !c->out_surface && !c->out_glb && !c->out_obj;
}

/* What the options must agree on. */
static int parse_check(const lst_cmd *c)
{
    const char *name;
    if (exemplar_only(c) && c->exemplar)
        return ends_with(c->out_exemplar, ".nrrd") ? 1 : bad("--out-exemplar (FILE.nrrd)", c->out_exemplar);
    if (!!c->mesh == !!c->tets || !c->exemplar) {
        cli_error("lst", "one of --mesh or --tets, and --exemplar, are required");
        return 0;
    }
    if (c->tets && !ends_with(c->tets, ".node") && !ends_with(c->tets, ".ele") && !ends_with(c->tets, ".mesh"))
        return bad("--tets (FILE.node or FILE.mesh)", c->tets);
    if (c->tets && cli_is_procedural(c->tets, &name)) return bad("--tets (use --mesh procedural:NAME)", c->tets);
    if (c->out_tets && !ends_with(c->out_tets, ".node") && !ends_with(c->out_tets, ".mesh"))
        return bad("--out-tets (FILE.node or FILE.mesh)", c->out_tets);
    if (c->out_exemplar && !ends_with(c->out_exemplar, ".nrrd"))
        return bad("--out-exemplar (FILE.nrrd)", c->out_exemplar);
    if (c->out_surface && !ends_with(c->out_surface, ".obj")) return bad("--out-surface (FILE.obj)", c->out_surface);
    {
        const cli_out outs[11] = {{"--out-lst", c->out_lst, CLI_OUT_ANY},
                                  {"--out-masks", c->out_masks, CLI_OUT_PREFIX},
                                  {"--out-exemplar", c->out_exemplar, CLI_OUT_NRRD},
                                  {"--out-image", c->out_image, CLI_OUT_IMAGE},
                                  {"--out-section", c->out_section, CLI_OUT_IMAGE},
                                  {"--out-volume", c->out_volume, CLI_OUT_IMAGE},
                                  {"--out-tets", c->out_tets, CLI_OUT_ANY},
                                  {"--out-surface", c->out_surface, CLI_OUT_ANY},
                                  {"--out-glb", c->out_glb, CLI_OUT_GLB},
                                  {"--out-obj", c->out_obj, CLI_OUT_OBJ},
                                  {"--out-atlas", c->out_atlas, CLI_OUT_IMAGE}};
        if (!cli_check_outputs("lst", outs, 11)) return 0;
    }
    if (!!c->out_obj != !!c->out_atlas) {
        cli_error("lst", "--out-obj and --out-atlas go together");
        return 0;
    }
    if (c->out_section && !c->ncuts) {
        cli_error("lst", "--out-section needs a --cut");
        return 0;
    }
    if (!c->out_lst && !c->out_masks && !c->out_exemplar && !c->out_image && !c->out_section && !c->out_volume &&
        !c->out_tets && !c->out_surface && !c->out_glb && !c->out_obj) {
        cli_error("lst", "nothing to write: give --out-lst, --out-masks, --out-image, --out-section, --out-volume, "
                         "--out-tets, --out-surface, --out-glb, --out-obj or --out-exemplar");
        return 0;
    }
    return 1;
}

static int parse(int argc, char **argv, lst_cmd *c)
{
    cli_args a;
    int r;
    memset(c, 0, sizeof *c);
    c->opt = lst_default_options();
    c->exemplar_size = 64;
    a.argc = argc;
    a.argv = argv;
    a.cmd = "lst";
    for (a.i = 1; a.i < argc; a.i++)
        if ((r = parse_one(&a, c)) <= 0) return r;
    return parse_check(c);
}

/* Everything a run holds. */
typedef struct lst_run {
    lst_mesh surface;
    lst_tetmesh tets;
    lst_volume ex, val;
    lst_constraint *cons; /* of every --constraints, --depth and --directions */
    int ncons;
    lst_model model;
} lst_run;

static void run_free(lst_run *r)
{
    lst_model_free(&r->model);
    free(r->cons);
    lst_volume_free(&r->ex);
    lst_volume_free(&r->val);
    lst_tetmesh_free(&r->tets);
    lst_mesh_free(&r->surface);
}

static double seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* The fill's report: the warnings about the input (stderr), then the count,
 * the two-sided fit of the boundary, the pieces and the dihedral range. */
static void report_fill(const lst_tetmesh *t, const lst_tet_report *rep, int uniform, double lo, double hi, double s)
{
    if (rep->crossing_pairs > 0)
        fprintf(stderr,
                "lst: warning: the surface crosses itself (%ld triangle pairs); filled where its winding "
                "number is at least 1/2 (--strict refuses)\n",
                rep->crossing_pairs);
    if (rep->skipped_triangles > 0)
        fprintf(stderr, "lst: warning: %d zero-area triangles skipped\n", rep->skipped_triangles);
    if (rep->surface_pieces >= 0 && rep->pieces != rep->surface_pieces && rep->crossing_pairs == 0)
        fprintf(stderr,
                "lst: warning: the tetrahedra make %d pieces where the surface encloses %d: parts thinner "
                "than the lattice cell are lost or cut off (%s)\n",
                rep->pieces, rep->surface_pieces,
                uniform ? "a larger --tet-count keeps more; the default graded lattice keeps thin parts"
                        : "a smaller --tet-fit keeps more");
    if (rep->fragments > 0)
        fprintf(stderr, "lst: note: %d bits of parts thinner than the smallest cell were cut off and dropped\n",
                rep->fragments);
    if (rep->closed_holes > 0)
        fprintf(stderr, "lst: warning: the surface was open: %d small holes closed\n", rep->closed_holes);
    printf("lst: %d tetrahedra, %d vertices, boundary within %.2f%% of the surface (99%%: %.2f%%), %d piece%s, "
           "dihedral angles %.1f..%.1f degrees (tetrahedralized and measured, %.2f s)\n",
           t->ntets, t->nverts, 100.0 * rep->fit_max, 100.0 * rep->fit_p99, rep->pieces, rep->pieces == 1 ? "" : "s",
           lo, hi, s);
}

/* The tetrahedral mesh: read, or the surface tetrahedralized; and the
 * surface the depth constraints paint (the mesh's boundary with --tets). */
static lst_result load_tets(const lst_cmd *c, lst_run *r, lst_error *err)
{
    const char *name;
    lst_result res;
    double lo = 0, hi = 0, t0 = seconds();
    lst_tet_report rep;
    if (c->tets) res = lst_load_tetmesh(c->tets, &c->opt, &r->tets, err);
    else if (cli_is_procedural(c->mesh, &name)) res = lst_builtin_mesh(name, &c->opt, &r->surface, err);
    else res = lst_load_mesh(c->mesh, &c->opt, &r->surface, err);
    if (res == LST_OK && c->mesh) res = lst_tetrahedralize(&r->surface, &c->opt, &r->tets, &rep, err);
    if (res == LST_OK && c->tets) res = lst_tetmesh_surface(&r->tets, &c->opt, &r->surface, err);
    if (res == LST_OK) res = lst_tetmesh_check(&r->tets, &lo, &hi, err);
    if (res == LST_OK && c->mesh) report_fill(&r->tets, &rep, c->opt.tet.uniform, lo, hi, seconds() - t0);
    else if (res == LST_OK)
        printf("lst: %d tetrahedra, %d vertices, dihedral angles %.1f..%.1f degrees (read, %.2f s)\n", r->tets.ntets,
               r->tets.nverts, lo, hi, seconds() - t0);
    return res;
}

/* The exemplar (and its values): a volume, so a 2D image is refused by name
 * with the way to a solid one. */
static lst_result load_exemplar(const lst_cmd *c, lst_run *r, lst_error *err)
{
    const char *name;
    lst_image img;
    lst_error ie;
    lst_result res;
    if (cli_is_procedural(c->exemplar, &name))
        res = lst_builtin_exemplar(name, c->exemplar_size, &c->opt, &r->ex, c->values ? NULL : &r->val, err);
    else if ((res = lst_load_volume(c->exemplar, &c->opt, &r->ex, err)) == LST_ERR_PARSE &&
             lst_load_image(c->exemplar, &c->opt, &img, &ie) == LST_OK) {
        snprintf(err->message, sizeof err->message,
                 "%s is a 2D image (%dx%d); lst pastes solid exemplars: a NRRD volume or procedural:NAME "
                 "(--exemplar procedural:layers --out-exemplar layers.nrrd writes one to start from)",
                 c->exemplar, img.width, img.height);
        lst_image_free(&img);
    }
    if (res == LST_OK && c->values) res = lst_load_volume(c->values, &c->opt, &r->val, err);
    return res;
}

/* Whether constraint kind k of a built-in set is taken by flag f (--depth:
 * the depths, --directions: directions and scales, --constraints: all). */
static int keeps(char f, lst_constraint_kind k) { return f == 'c' || (f == 'd') == (k <= LST_CONSTRAINT_DEPTH_POINT); }

/* --constraints, --depth and --directions in order: files (all three read
 * the same syntax), or the constraints of a built-in shape. */
static lst_result load_constraints(const lst_cmd *c, lst_run *r, lst_error *err)
{
    lst_result res = LST_OK;
    int k, j;
    for (k = 0; k < c->ncons && res == LST_OK; k++) {
        const char *name;
        int builtin = cli_is_procedural(c->cons[k], &name);
        lst_constraints got;
        lst_constraint *grown;
        if (builtin) res = lst_builtin_constraints(name, &r->surface, &c->opt, &got, err);
        else res = lst_load_constraints(c->cons[k], &c->opt, &got, err);
        if (res != LST_OK) break;
        if (!(grown = (lst_constraint *)realloc(r->cons, sizeof *grown * (size_t)(r->ncons + got.count)))) {
            snprintf(err->message, sizeof err->message, "out of memory");
            res = err->code = LST_ERR_NOMEM;
        } else {
            r->cons = grown;
            for (j = 0; j < got.count; j++)
                if (!builtin || keeps(c->cons_flag[k], got.items[j].kind)) r->cons[r->ncons++] = got.items[j];
        }
        lst_constraints_free(&got);
    }
    return res;
}

/* --paste "X Y Z UX UY UZ VX VY VZ S [MASK]" (checked when parsed). */
static lst_result manual_pastes(const lst_cmd *c, lst_run *r, lst_error *err)
{
    int k, n;
    for (k = 0; k < c->npastes; k++) {
        float f[11];
        lst_paste_spec spec;
        lst_result res;
        n = parse_floats(c->pastes[k], f, 10, 11);
        memcpy(spec.point, f, sizeof spec.point);
        memcpy(spec.u_axis, f + 3, sizeof spec.u_axis);
        memcpy(spec.v_axis, f + 6, sizeof spec.v_axis);
        spec.scale = f[9];
        spec.mask = n == 11 ? (int)f[10] : 0;
        res = lst_paste_at(&r->model, &spec, &c->opt, err);
        if (res != LST_OK) return res;
    }
    return LST_OK;
}

static lst_result fill(lst_cmd *c, lst_run *r, lst_error *err)
{
    static const char *const types[5] = {"0", "1-a", "1-b", "2-a", "2-b"};
    lst_source src;
    lst_result res;
    double t0;
    c->opt.constraints = r->cons;
    c->opt.nconstraints = r->ncons;
    t0 = seconds();
    src.exemplar = &r->ex;
    src.values = r->val.voxels ? &r->val : NULL;
    c->opt.threads = c->opt.render.threads; /* --threads: the coverage's too */
    res = lst_create(&r->tets, &r->surface, &src, &c->opt, &r->model, err);
    if (res != LST_OK) return res;
    printf("lst: type %s, %d pastes, %.2f per tetrahedron (%.2f before hidden ones were dropped), %d masks, "
           "filled in %.2f s\n",
           types[c->opt.type], r->model.npastes, r->model.layers, r->model.layers_before, r->model.masks.count,
           seconds() - t0);
    return manual_pastes(c, r, err);
}

/* ---- outputs ---- */

typedef lst_result (*writer_fn)(const void *obj, lst_write_fn fn, void *ctx, lst_error *err);

static lst_result w_model(const void *o, lst_write_fn fn, void *ctx, lst_error *err)
{
    return lst_write_model((const lst_model *)o, fn, ctx, err);
}
static lst_result w_volume(const void *o, lst_write_fn fn, void *ctx, lst_error *err)
{
    return lst_write_volume((const lst_volume *)o, fn, ctx, err);
}
static lst_result w_medit(const void *o, lst_write_fn fn, void *ctx, lst_error *err)
{
    return lst_write_medit((const lst_tetmesh *)o, fn, ctx, err);
}
static lst_result w_obj(const void *o, lst_write_fn fn, void *ctx, lst_error *err)
{
    return lst_write_obj((const lst_mesh *)o, fn, ctx, err);
}

/* obj written by w to the staged file of path. */
static lst_result write_out(cli_outputs *outs, const char *path, writer_fn w, const void *obj, lst_error *err)
{
    FILE *f = cli_open(outs, path, err->message, sizeof err->message);
    lst_result r;
    if (!f) return err->code = LST_ERR_IO;
    r = w(obj, cli_fwrite, f, err);
    if (r == LST_ERR_IO) snprintf(err->message, sizeof err->message, "%.200s: write error (disk full?)", path);
    if (!cli_close(f, r == LST_OK, path, err->message, sizeof err->message)) r = LST_ERR_IO;
    return err->code = r;
}

/* FILE.node and FILE.ele, or FILE.mesh. */
static lst_result write_tets(cli_outputs *outs, const char *path, const lst_tetmesh *m, lst_error *err)
{
    char ele[1024];
    FILE *f, *g;
    lst_result r;
    int ok;
    if (ends_with(path, ".mesh")) return write_out(outs, path, w_medit, m, err);
    cli_with_ext(path, ".ele", ele, sizeof ele);
    if (!(f = cli_open(outs, path, err->message, sizeof err->message))) return err->code = LST_ERR_IO;
    if (!(g = cli_open(outs, ele, err->message, sizeof err->message))) {
        fclose(f);
        return err->code = LST_ERR_IO;
    }
    r = lst_write_tetgen(m, cli_fwrite, f, cli_fwrite, g, err);
    if (r == LST_ERR_IO) snprintf(err->message, sizeof err->message, "%.200s: write error (disk full?)", path);
    ok = cli_close(f, r == LST_OK, path, err->message, sizeof err->message);
    ok = cli_close(g, ok, ele, err->message, sizeof err->message);
    return err->code = ok ? r : LST_ERR_IO;
}

/* --out-surface: the boundary of the tetrahedral mesh as OBJ. */
static lst_result write_surface(cli_outputs *outs, const char *path, const lst_tetmesh *m, const lst_options *o,
                                lst_error *err)
{
    lst_mesh s;
    lst_result r = lst_tetmesh_surface(m, o, &s, err);
    if (r == LST_OK) r = write_out(outs, path, w_obj, &s, err);
    lst_mesh_free(&s);
    return r;
}

static lst_result write_image(cli_outputs *outs, const char *path, const lst_image *img, lst_error *err)
{
    tiled_image view = cli_image_view(img->width, img->height, img->channels, img->pixels, img->bits);
    return err->code = (lst_result)cli_write_view(outs, path, &view, err->message);
}

static lst_result write_masks(cli_outputs *outs, const lst_cmd *c, const lst_model *m, lst_error *err)
{
    char path[1024];
    int k;
    lst_result r = LST_OK;
    for (k = 0; k < m->masks.count && r == LST_OK; k++) {
        snprintf(path, sizeof path, "%s%d.nrrd", c->out_masks, k);
        r = write_out(outs, path, w_volume, &m->masks.volumes[k], err);
    }
    return r;
}

/* What --out-glb writes: the atlas, seen as --out-image sees the model. */
typedef struct glb_job {
    const lst_atlas *atlas;
    const lst_render_options *view;
} glb_job;

static lst_result w_gltf(const void *o, lst_write_fn fn, void *ctx, lst_error *err)
{
    const glb_job *j = (const glb_job *)o;
    return lst_write_gltf(j->atlas, j->view, fn, ctx, err);
}

/* --out-glb, --out-obj with its MTL and --out-atlas: the visible boundary
 * with the model's colour baked into an atlas. */
static lst_result write_atlas(const lst_cmd *c, lst_model *model, cli_outputs *outs, lst_error *err)
{
    char mtl[1024];
    glb_job job;
    lst_atlas atlas;
    lst_result r = lst_bake_atlas(model, &c->opt, &atlas, err);
    FILE *f;
    if (r != LST_OK) return r;
    job.atlas = &atlas;
    job.view = &c->opt.render;
    if (c->out_glb) r = write_out(outs, c->out_glb, w_gltf, &job, err);
    if (r == LST_OK && c->out_obj) {
        cli_with_ext(c->out_obj, ".mtl", mtl, sizeof mtl);
        if ((f = cli_open(outs, c->out_obj, err->message, sizeof err->message)) == NULL) r = LST_ERR_IO;
        else {
            r = lst_write_atlas_obj(&atlas, cli_texture_ref(c->out_obj, mtl), cli_fwrite, f, err);
            if (!cli_close(f, r == LST_OK, c->out_obj, err->message, sizeof err->message)) r = LST_ERR_IO;
        }
        if (r == LST_OK && (f = cli_open(outs, mtl, err->message, sizeof err->message)) == NULL) r = LST_ERR_IO;
        else if (r == LST_OK) {
            r = lst_write_mtl(cli_texture_ref(c->out_obj, c->out_atlas), cli_fwrite, f, err);
            if (!cli_close(f, r == LST_OK, mtl, err->message, sizeof err->message)) r = LST_ERR_IO;
        }
        if (r == LST_OK) r = write_image(outs, c->out_atlas, &atlas.image, err);
    }
    if (r == LST_OK)
        printf("lst: atlas of %d charts, %.0f%% of %dx%d filled\n", atlas.ncharts, 100.0 * atlas.fill,
               atlas.image.width, atlas.image.height);
    lst_atlas_free(&atlas);
    return err->code = r;
}

/* --cut planes, then --cut-stroke along the view. */
static lst_result cuts(const lst_cmd *c, lst_run *r, lst_error *err)
{
    static const float view0[3] = {-0.55f, -0.45f, -0.7f};
    float pts[3000], *phi;
    const float *v = c->opt.render.view_dir, *view = v[0] || v[1] || v[2] ? v : view0;
    int k, n;
    lst_result res = LST_OK;
    for (k = 0; k < c->ncuts && res == LST_OK; k++) res = lst_cut_plane(&r->model, c->cuts[k], err);
    if (res != LST_OK || !c->stroke) return res;
    if ((n = parse_floats(c->stroke, pts, 6, 3000)) == 0 || n % 3) {
        err->code = LST_ERR_INVALID;
        snprintf(err->message, sizeof err->message, "--cut-stroke: '%.100s' is not X Y Z X Y Z ... (2 to 1000 points)",
                 c->stroke);
        return err->code;
    }
    if (!(phi = (float *)malloc(sizeof(float) * (size_t)r->model.mesh.nverts))) {
        snprintf(err->message, sizeof err->message, "out of memory");
        return err->code = LST_ERR_NOMEM;
    }
    res = lst_stroke_field(&r->model, pts, n / 3, view, phi, err);
    if (res == LST_OK) res = lst_cut_field(&r->model, phi, err);
    free(phi);
    return res;
}

/* The last plane cut seen face on (looking against its normal). */
static lst_result section(const lst_cmd *c, const lst_run *r, lst_image *img, lst_error *err)
{
    lst_render_options ro = c->opt.render;
    const float *n = c->cuts[c->ncuts - 1];
    float up[3] = {0, 1, 0}, len = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    int k;
    if (ro.up[0] || ro.up[1] || ro.up[2]) memcpy(up, ro.up, sizeof up);
    if ((up[0] * n[0] + up[1] * n[1] + up[2] * n[2]) * (up[0] * n[0] + up[1] * n[1] + up[2] * n[2]) >
        0.98f * len * (up[0] * up[0] + up[1] * up[1] + up[2] * up[2])) {
        up[0] = 0;
        up[1] = 0;
        up[2] = 1;
    } /* up along the normal: any other will do */
    if (n[2] * n[2] > 0.98f * len && up[2] == 1) {
        up[1] = 1;
        up[2] = 0;
    }
    for (k = 0; k < 3; k++) {
        ro.view_dir[k] = -n[k];
        ro.up[k] = up[k];
    }
    return lst_render(&r->model, &ro, img, err);
}

static lst_result outputs(const lst_cmd *c, lst_run *r, cli_outputs *outs, lst_error *err)
{
    lst_image img;
    lst_result res = LST_OK;
    double t0;
    memset(&img, 0, sizeof img);
    if (c->out_tets) res = write_tets(outs, c->out_tets, &r->tets, err);
    if (res == LST_OK && c->out_surface) res = write_surface(outs, c->out_surface, &r->tets, &c->opt, err);
    if (res == LST_OK && c->out_masks) res = write_masks(outs, c, &r->model, err);
    if (res == LST_OK && c->out_exemplar) res = write_out(outs, c->out_exemplar, w_volume, &r->ex, err);
    t0 = seconds();
    if (res == LST_OK) res = cuts(c, r, err);
    if (res == LST_OK && (c->ncuts || c->stroke))
        printf("lst: cut in %.3f s, %d tetrahedra now\n", seconds() - t0, r->model.mesh.ntets);
    if (res == LST_OK && c->out_lst) res = write_out(outs, c->out_lst, w_model, &r->model, err);
    if (res == LST_OK && c->out_image && (res = lst_render(&r->model, &c->opt.render, &img, err)) == LST_OK)
        res = write_image(outs, c->out_image, &img, err);
    lst_image_free(&img);
    if (res == LST_OK && c->out_section && (res = section(c, r, &img, err)) == LST_OK)
        res = write_image(outs, c->out_section, &img, err);
    lst_image_free(&img);
    if (res == LST_OK && c->out_volume &&
        (res = lst_render_volume(&r->model, &c->opt.render, &c->opt.volume, &img, err)) == LST_OK)
        res = write_image(outs, c->out_volume, &img, err);
    lst_image_free(&img);
    if (res == LST_OK && (c->out_glb || c->out_obj)) res = write_atlas(c, &r->model, outs, err);
    return res;
}

int cmd_lst(int argc, char **argv)
{
    lst_cmd c;
    lst_run r;
    cli_outputs outs;
    lst_error err;
    lst_result res;
    int p = parse(argc, argv, &c);
    if (p < 0) {
        fputs(lst_usage, stdout);
        fputs(lst_usage_views, stdout);
        fputs(lst_usage_outputs, stdout);
        return 0;
    }
    if (!p) return 1;
    memset(&r, 0, sizeof r);
    memset(&outs, 0, sizeof outs);
    if (exemplar_only(&c)) { /* a built-in exemplar to a file, e.g. to edit it */
        if ((res = load_exemplar(&c, &r, &err)) == LST_OK)
            res = write_out(&outs, c.out_exemplar, w_volume, &r.ex, &err);
    } else if ((res = load_exemplar(&c, &r, &err)) == LST_OK && (res = load_tets(&c, &r, &err)) == LST_OK &&
               (res = load_constraints(&c, &r, &err)) == LST_OK && (res = fill(&c, &r, &err)) == LST_OK)
        res = outputs(&c, &r, &outs, &err);
    run_free(&r);
    return cli_finish("lst", &outs, res != LST_OK, err.message);
}
