/* io.c: files and memory for pgp.h: material-space tiles (NRRD, or any 2D
 * image as one layer), meshes, images, the textured OBJ and constraints
 * files.
 *
 * Tiles and NRRD volumes share their layout (pw_volume, nrrd.h): x is s
 * (the width), y the rows from the top (t = 0 at the bottom row), z the
 * layers along m. A tile is written as NRRD0004, uint8, raw, with sizes
 * C W H M (dimension 4), or W H M (dimension 3) for one channel.
 *
 * The OBJ holds the map's triangles (the fan triangulation of the mesh):
 *     v x y z                          one per vertex
 *     vt s t m                         one per triangle corner, in triangle
 *                                      order (Eq. 4, before the §3 fix)
 *     g regular / f a/ta b/tb c/tc     triangles without a singular corner
 *     g singular / f ...               the others (§3)
 * with vertex and vt indices 1-based; numbers read back exactly whatever
 * the locale.
 *
 * A constraints file holds one constraint (§2) per line, in the order they
 * are applied; '#' starts a comment, blank lines are ignored, a UTF-8
 * byte-order mark is skipped:
 *     radius R                effect radius of the lines that follow, mesh
 *                             units (0 or less, the default: whole mesh)
 *     orient F dx dy dz       the tile's s axis along (dx, dy, dz) at triangle F
 *     scale V S               tile side S (mesh units, > 0) at vertex V
 *     material V m            material m in [0, 1] at vertex V
 * Triangles and vertices are 0-based. An error names the file and line. */
#include "builtin.c"

/* ---- tiles ------------------------------------------------------------------ */

/* A tile as a volume (no copy), checked: sizes, channels, finite samples. */
static int pgp__tile_view(const pgp_tile *t, pw_volume *v, pw_err *e)
{
    size_t k, n;
    int r;
    memset(v, 0, sizeof *v);
    if (!t || !t->pixels) return pw_fail(e, PW_ERR_INVALID, "tile: empty (no texels)");
    if (t->width < 1 || t->height < 1 || t->layers < 1 || t->channels < 1 || t->channels > 4)
        return pw_fail(e, PW_ERR_INVALID, "tile: %dx%d texels, %d layers, %d channels (1 to 4) is not a tile", t->width,
                       t->height, t->layers, t->channels);
    if ((r = pw__volume_check_size("tile", (uint64_t)t->width, (uint64_t)t->height, (uint64_t)t->layers, e)) != PW_OK)
        return r;
    v->c = t->channels;
    v->x = t->width;
    v->y = t->height;
    v->z = t->layers;
    v->px = t->pixels;
    n = (size_t)v->c * v->x * v->y * v->z;
    for (k = 0; k < n; k++)
        if (!pw_is_finite(v->px[k]))
            return pw_fail(e, PW_ERR_INVALID, "tile: texel %lu is not a finite number", (unsigned long)(k / v->c));
    return PW_OK;
}

/* Moves a volume's samples into a tile. */
static void pgp__take_volume(pw_volume *v, const pw_alloc *a, pgp_tile *t)
{
    t->width = v->x;
    t->height = v->y;
    t->layers = v->z;
    t->channels = v->c;
    t->pixels = v->px;
    t->allocator = pgp__allocator(a);
    memset(v, 0, sizeof *v);
}

PGPDEF pgp_result pgp_tile_from_image(const pgp_image *img, const pgp_options *opt, pgp_tile *out, pgp_error *err)
{
    pgp_options o = pgp__options(opt);
    pw_alloc a = pgp__alloc(&o.allocator);
    pw_volume vol;
    pw_image view;
    pw_err pe;
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (!out) pw_fail(&pe, PW_ERR_INVALID, "pgp_tile_from_image: NULL output");
    else if (pgp__check_image(img, "image", &pe) == PW_OK) {
        view = pgp__pw_image(img);
        if (pw_volume_from_image(&a, &view, &vol, &pe) == PW_OK) pgp__take_volume(&vol, &a, out);
    }
    return pgp__done(&pe, err);
}

/* NRRD when the data starts with its magic, else a 2D image (one layer). */
PGPDEF pgp_result pgp_read_tile(const void *data, size_t size, const char *name, const pgp_options *opt, pgp_tile *out,
                                pgp_error *err)
{
    pgp_options o = pgp__options(opt);
    pw_alloc a = pgp__alloc(&o.allocator);
    const unsigned char *d = (const unsigned char *)data;
    pw_volume vol;
    pw_image img;
    pw_err pe;
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (!name) name = "tile";
    if (!out || (!data && size)) pw_fail(&pe, PW_ERR_INVALID, "pgp_read_tile: NULL argument");
    else if (size >= 4 && !memcmp(d, "NRRD", 4)) {
        if (pw_nrrd_read_memory(&a, d, size, name, &vol, &pe) == PW_OK) pgp__take_volume(&vol, &a, out);
    } else if (pw_image_read_memory(&a, d, size, name, &img, &pe) == PW_OK) {
        vol.c = img.c;
        vol.x = img.w;
        vol.y = img.h;
        vol.z = 1;
        vol.px = img.px;
        pgp__take_volume(&vol, &a, out);
    }
    return pgp__done(&pe, err);
}

PGPDEF pgp_result pgp_write_tile(const pgp_tile *tile, pgp_write_fn fn, void *ctx, pgp_error *err)
{
    pw_volume v;
    pw_alloc a;
    pw_err pe;
    pw_err_clear(&pe);
    if (!fn) pw_fail(&pe, PW_ERR_INVALID, "pgp_write_tile: NULL writer");
    else if (pgp__tile_view(tile, &v, &pe) == PW_OK) {
        a = pgp__alloc(&tile->allocator);
        pw_nrrd_write(&a, &v, 0, fn, ctx, &pe);
    }
    return pgp__done(&pe, err);
}

/* ---- meshes and images --------------------------------------------------------- */

PW_PUBLIC_IO(pgp, PGPDEF);

/* ---- the textured OBJ ------------------------------------------------------------ */

/* The mesh given with a map must be the one it was made from: the same
 * vertices and the same fan triangulation. */
static int pgp__same_mesh(const pgp_mesh *mesh, const pgp__state *P, pw_err *e)
{
    int f, k, t = 0;
    if (mesh->nverts != P->pp.m.nv || mesh->nfaces < 0 || !mesh->face_start || !mesh->face_verts)
        return pw_fail(e, PW_ERR_INVALID, "the mesh (%d vertices) is not the map's (%d vertices)", mesh->nverts,
                       P->pp.m.nv);
    for (f = 0; f < mesh->nfaces; f++) {
        const int *c = mesh->face_verts + mesh->face_start[f];
        int d = mesh->face_start[f + 1] - mesh->face_start[f];
        for (k = 1; k + 1 < d; k++, t++)
            if (t >= P->pp.m.nf || P->pp.m.tri[3 * t] != c[0] || P->pp.m.tri[3 * t + 1] != c[k] ||
                P->pp.m.tri[3 * t + 2] != c[k + 1])
                return pw_fail(e, PW_ERR_INVALID, "the mesh is not the map's (face %d differs)", f);
    }
    if (t != P->pp.m.nf) return pw_fail(e, PW_ERR_INVALID, "the mesh has %d triangles, the map %d", t, P->pp.m.nf);
    return PW_OK;
}

/* The faces of one group: regular (sing = 0) or singular (sing = 1). */
static void pgp__obj_group(pw__wb *b, const pgp__state *P, int sing)
{
    int f, k;
    pw__wb_str(b, sing ? "g singular\n" : "g regular\n");
    for (f = 0; f < P->pp.m.nf; f++) {
        if (!P->fsing[f] != !sing) continue;
        pw__wb_str(b, "f");
        for (k = 0; k < 3; k++) {
            pw__wb_int(b, (long long)P->pp.m.tri[3 * f + k] + 1, ' ');
            pw__wb_int(b, 3LL * f + k + 1, '/');
        }
        pw__wb_str(b, "\n");
    }
}

static int pgp__write_obj(const pgp__state *P, pw_write_fn fn, void *ctx, pw_err *e)
{
    pw__wb b;
    int i, k;
    memset(&b, 0, sizeof b);
    b.w = fn;
    b.ctx = ctx;
    pw__wb_str(&b, "# patchwork pgp: vt s t m per triangle corner; groups regular and singular (§3)\n");
    for (i = 0; i < P->pp.m.nv; i++) {
        pw__wb_str(&b, "v");
        for (k = 0; k < 3; k++) pw__wb_float(&b, P->pos[3 * i + k]);
        pw__wb_str(&b, "\n");
    }
    for (i = 0; i < 3 * P->pp.m.nf; i++) {
        pw__wb_str(&b, "vt");
        for (k = 0; k < 3; k++) pw__wb_float(&b, P->pp.stm[3 * i + k]);
        pw__wb_str(&b, "\n");
    }
    pgp__obj_group(&b, P, 0);
    pgp__obj_group(&b, P, 1);
    return pw__wb_done(&b, e);
}

PGPDEF pgp_result pgp_write_obj(const pgp_mesh *mesh, const pgp_map *map, pgp_write_fn fn, void *ctx, pgp_error *err)
{
    const pgp__state *P = pgp__state_of(map);
    pw_err pe;
    pw_err_clear(&pe);
    if (!P || !fn) pw_fail(&pe, PW_ERR_INVALID, "pgp_write_obj: NULL or empty map, or NULL writer");
    else if (!mesh || pgp__same_mesh(mesh, P, &pe) == PW_OK) pgp__write_obj(P, fn, ctx, &pe);
    return pgp__done(&pe, err);
}

/* ---- constraints files -------------------------------------------------------------- */

/* A triangle or vertex index (whether it exists is checked when the
 * constraint is applied: the file knows no mesh). */
static int pgp__con_index(pw__sc *s, const char *what, int *out)
{
    long long v;
    int r;
    if ((r = pw__sc_int(s, &v, what, -1)) != PW_OK) return r;
    if (v < 0 || v > PW_MAX_MESH_ELEMENTS) return pw__sc_fail(s, PW_ERR_INVALID, "%s %lld does not exist", what, v);
    *out = (int)v;
    return PW_OK;
}

/* n finite numbers. */
static int pgp__con_numbers(pw__sc *s, const char *what, float *v, int n)
{
    double x;
    int k, r;
    for (k = 0; k < n; k++) {
        if ((r = pw__sc_num(s, &x, what, -1)) != PW_OK) return r;
        v[k] = pw__num_to_float(x);
        if (!pw_is_finite(v[k])) return pw__sc_fail(s, PW_ERR_INVALID, "%s: a value is not a finite number", what);
    }
    return PW_OK;
}

/* One line: a radius, or a constraint in *c, checked (pgp__check_values),
 * and *got set. */
static int pgp__con_line(pw__sc *s, float *radius, pgp_constraint *c, int *got)
{
    static const char *const names[4] = {"radius", "orient", "scale", "material"};
    char tok[32];
    const char *w;
    size_t n;
    float v[3];
    int kind, r;
    pw_err le;
    w = pw__sc_word(s, &n);
    kind = pw__sc_is(w, n, "radius")     ? 0
           : pw__sc_is(w, n, "orient")   ? 1
           : pw__sc_is(w, n, "scale")    ? 2
           : pw__sc_is(w, n, "material") ? 3
                                         : -1;
    if (kind < 0)
        return pw__sc_fail(s, PW_ERR_PARSE, "unknown keyword '%s' (orient, scale, material, radius)",
                           pw__sc_tok(s, w, tok));
    memset(c, 0, sizeof *c);
    if (kind == 1) r = pgp__con_index(s, "orient: triangle", &c->element);
    else if (kind > 1) r = pgp__con_index(s, kind == 2 ? "scale: vertex" : "material: vertex", &c->element);
    else r = PW_OK;
    if (r != PW_OK || (r = pgp__con_numbers(s, names[kind], v, kind == 1 ? 3 : 1)) != PW_OK) return r;
    if (!pw__sc_eol(s)) return pw__sc_fail(s, PW_ERR_PARSE, "unexpected text after '%s'", names[kind]);
    *got = kind > 0;
    if (kind == 0) *radius = v[0];
    else {
        c->kind = kind == 1 ? PGP_CONSTRAINT_ORIENT : kind == 2 ? PGP_CONSTRAINT_SCALE : PGP_CONSTRAINT_MATERIAL;
        memcpy(c->value, v, sizeof(float) * (kind == 1 ? 3 : 1));
        c->radius = *radius;
        pw_err_clear(&le);
        if (pgp__check_values(c, &le) != PW_OK) return pw__sc_fail(s, le.code, "%s", le.msg);
    }
    pw__sc_next_line(s);
    return PW_OK;
}

PGPDEF pgp_result pgp_read_constraints(const void *data, size_t size, const char *name, const pgp_options *opt,
                                       pgp_constraints *out, pgp_error *err)
{
    pgp_options o = pgp__options(opt);
    pw_alloc a = pgp__alloc(&o.allocator);
    pgp_constraint c;
    float radius = 0.0f;
    size_t cap = 0;
    int got = 0;
    pw__sc s;
    pw_err pe;
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (!out || (!data && size)) {
        pw_fail(&pe, PW_ERR_INVALID, "pgp_read_constraints: NULL argument");
        return pgp__done(&pe, err);
    }
    out->allocator = pgp__allocator(&a);
    pw__sc_init(&s, data, size, name ? name : "constraints", 0, &pe);
    for (pw__sc_skip_empty(&s); s.p < s.end && pe.code == PW_OK; pw__sc_skip_empty(&s))
        if (pgp__con_line(&s, &radius, &c, &got) == PW_OK && got &&
            pw_grow(&a, (void **)&out->items, &cap, (size_t)out->count + 1, sizeof c, "constraints", &pe) == PW_OK)
            out->items[out->count++] = c;
    if (pe.code == PW_OK && out->count == 0) pw_fail(&pe, PW_ERR_PARSE, "%s: no constraints", s.name);
    if (pe.code != PW_OK) pgp_constraints_free(out);
    return pgp__done(&pe, err);
}

/* ---- files ------------------------------------------------------------------------------ */

#ifndef PW_NO_STDIO
/* the public file loaders: each file read whole, then read from memory */
PW_PUBLIC_LOAD(pgp, PGPDEF, mesh, pgp_mesh);
PW_PUBLIC_LOAD(pgp, PGPDEF, image, pgp_image);
PW_PUBLIC_LOAD(pgp, PGPDEF, tile, pgp_tile);
PW_PUBLIC_LOAD(pgp, PGPDEF, constraints, pgp_constraints);

/* What a file writer writes: one of these is set. */
typedef struct pgp__job {
    const pgp_tile *tile;
    const pgp_mesh *mesh;
    const pgp_map *map;
} pgp__job;

static int pgp__job_body(void *arg, pw_write_fn w, void *ctx, pw_err *e)
{
    const pgp__job *j = (const pgp__job *)arg;
    pgp_error le;
    pgp_result r = j->tile ? pgp_write_tile(j->tile, w, ctx, &le) : pgp_write_obj(j->mesh, j->map, w, ctx, &le);
    return r != PGP_OK ? pw_fail(e, (int)r, "%s", le.message) : PW_OK;
}

PGPDEF pgp_result pgp_save_tile(const char *path, const pgp_tile *tile, pgp_error *err)
{
    pgp__job j;
    pw_volume v;
    pw_err pe;
    pw_err_clear(&pe);
    memset(&j, 0, sizeof j);
    j.tile = tile;
    if (!path) pw_fail(&pe, PW_ERR_INVALID, "pgp_save_tile: NULL path");
    else if (!pw_has_ext(path, ".nrrd")) pw_fail(&pe, PW_ERR_UNSUPPORTED, "%s: a tile is saved as .nrrd", path);
    else if (pgp__tile_view(tile, &v, &pe) == PW_OK) pw_write_file(path, pgp__job_body, &j, &pe);
    return pgp__done(&pe, err);
}

PW_PUBLIC_SAVE_IMAGE(pgp, PGPDEF);

PGPDEF pgp_result pgp_save_obj(const char *path, const pgp_mesh *mesh, const pgp_map *map, pgp_error *err)
{
    pgp__job j;
    pw_err pe;
    pw_err_clear(&pe);
    memset(&j, 0, sizeof j);
    j.mesh = mesh;
    j.map = map;
    if (!path || !pgp__state_of(map)) pw_fail(&pe, PW_ERR_INVALID, "pgp_save_obj: NULL argument or empty map");
    else if (!mesh || pgp__same_mesh(mesh, map->state, &pe) == PW_OK) pw_write_file(path, pgp__job_body, &j, &pe);
    return pgp__done(&pe, err);
}
#endif
