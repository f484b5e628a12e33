/* io.c: the paste file format and the file conveniences of lapped.h.
 *
 * A paste file records a lapped texture for runtime pasting (§3.5, §4):
 *
 *     lapped-pastes 1
 *     patches P
 *     patch <index> <width> <height>                  (P lines)
 *     pastes K
 *     paste <patch-index> <face-count>                (K blocks, in compositing order)
 *     <face> <u0> <v0> <u1> <v1> <u2> <v2>            (face-count lines)
 *
 * Faces are 0-based triangles of the fan triangulation; corners in the
 * triangle's vertex order; (u,v) in patch texture space, (0,0) the
 * bottom-left of the patch image. Numbers are written so that they read
 * back exactly, whatever the locale. */
#include "atlas.c"

/* ---- writing ----------------------------------------------------------------- */

static void lapped__wb_line(pw__wb *b, const char *word, const long long *v, int n)
{
    int k;
    pw__wb_str(b, word);
    for (k = 0; k < n; k++) pw__wb_int(b, v[k], ' ');
    pw__wb_str(b, "\n");
}

LAPPEDDEF lapped_result lapped_write_pastes(const lapped_texture *t, lapped_write_fn fn, void *ctx, lapped_error *err)
{
    pw__wb b;
    pw_err pe;
    long long v[3];
    int p, i, k;
    pw_err_clear(&pe);
    if (!t || !fn) {
        pw_fail(&pe, PW_ERR_INVALID, "lapped_write_pastes: NULL argument");
        return lapped__done(&pe, err);
    }
    memset(&b, 0, sizeof b);
    b.w = fn;
    b.ctx = ctx;
    pw__wb_str(&b, "lapped-pastes 1\n");
    v[0] = t->npatches;
    lapped__wb_line(&b, "patches", v, 1);
    for (k = 0; k < t->npatches; k++) {
        v[0] = k;
        v[1] = t->patch_size[2 * k];
        v[2] = t->patch_size[2 * k + 1];
        lapped__wb_line(&b, "patch", v, 3);
    }
    v[0] = t->npastes;
    lapped__wb_line(&b, "pastes", v, 1);
    for (p = 0; p < t->npastes; p++) {
        const lapped_paste *q = &t->pastes[p];
        v[0] = q->patch;
        v[1] = q->nfaces;
        lapped__wb_line(&b, "paste", v, 2);
        for (i = 0; i < q->nfaces; i++) {
            pw__wb_int(&b, q->faces[i], 0);
            for (k = 0; k < 6; k++) pw__wb_float(&b, q->uvs[6 * i + k]);
            pw__wb_str(&b, "\n");
        }
    }
    pw__wb_done(&b, &pe);
    return lapped__done(&pe, err);
}

/* ---- reading ----------------------------------------------------------------- */

static int lapped__read_header(pw__sc *s, const pw_alloc *a, lapped_texture *t, pw_err *e)
{
    long long v[3];
    int k, r;
    if ((r = pw__sc_read_ints(s, "lapped-pastes", v, 1, 1, 1)) != PW_OK ||
        (r = pw__sc_read_ints(s, "patches", v, 1, 1, 4096)) != PW_OK)
        return r;
    t->npatches = (int)v[0];
    if (!(t->patch_size = (int *)pw_alloc_array(a, (size_t)t->npatches * 2, sizeof(int), "patch sizes", e)))
        return PW_ERR_NOMEM;
    for (k = 0; k < t->npatches; k++) {
        if ((r = pw__sc_read_ints(s, "patch", v, 3, 0, PW_MAX_IMAGE_DIM)) != PW_OK) return r;
        if (v[0] != k) return pw__sc_fail(s, PW_ERR_PARSE, "patch %lld listed where patch %d belongs", v[0], k);
        if (v[1] < 1 || v[2] < 1) return pw__sc_fail(s, PW_ERR_PARSE, "patch %d has an empty size", k);
        t->patch_size[2 * k] = (int)v[1];
        t->patch_size[2 * k + 1] = (int)v[2];
    }
    return PW_OK;
}

/* One "<face> u0 v0 u1 v1 u2 v2" line. */
static int lapped__read_face(pw__sc *s, lapped_paste *q, int i)
{
    long long f;
    double x;
    int k, r;
    pw__sc_skip_empty(s);
    if ((r = pw__sc_int(s, &f, "paste triangle", i)) != PW_OK) return r;
    if (f < 0 || f >= PW_MAX_MESH_ELEMENTS) return pw__sc_fail(s, PW_ERR_PARSE, "triangle index %lld", f);
    q->faces[i] = (int)f;
    for (k = 0; k < 6; k++) {
        if ((r = pw__sc_num(s, &x, "texture coordinate", i)) != PW_OK) return r;
        q->uvs[6 * i + k] = pw__num_to_float(x);
        if (!pw_is_finite(q->uvs[6 * i + k]))
            return pw__sc_fail(s, PW_ERR_INVALID, "a texture coordinate is not finite");
    }
    if (!pw__sc_eol(s)) return pw__sc_fail(s, PW_ERR_PARSE, "unexpected text after a triangle");
    pw__sc_next_line(s);
    return PW_OK;
}

static int lapped__read_pastes(pw__sc *s, const pw_alloc *a, lapped_texture *t, pw_err *e)
{
    long long v[2];
    int p, i, r;
    /* a face line has at least 14 bytes: checked before allocating */
    if ((r = pw__sc_read_ints(s, "pastes", v, 1, 0, PW_MAX_MESH_ELEMENTS)) != PW_OK) return r;
    if (v[0] > (long long)(s->end - s->p) / 8 + 1)
        return pw__sc_fail(s, PW_ERR_PARSE, "%lld pastes announced, the file is too short for them", v[0]);
    if (!(t->pastes = (lapped_paste *)pw_calloc_array(a, (size_t)v[0], sizeof(lapped_paste), "pastes", e)))
        return PW_ERR_NOMEM;
    t->npastes = (int)v[0];
    for (p = 0; p < t->npastes; p++) {
        lapped_paste *q = &t->pastes[p];
        if ((r = pw__sc_read_ints(s, "paste", v, 2, 0, PW_MAX_MESH_ELEMENTS)) != PW_OK) return r;
        if (v[0] >= t->npatches)
            return pw__sc_fail(s, PW_ERR_PARSE, "paste %d uses patch %lld of %d", p, v[0], t->npatches);
        if (v[1] > (long long)(s->end - s->p) / 14 + 1)
            return pw__sc_fail(s, PW_ERR_PARSE, "paste %d announces %lld triangles, the file is too short", p, v[1]);
        q->patch = (int)v[0];
        q->faces = (int *)pw_alloc_array(a, (size_t)v[1], sizeof(int), "paste triangles", e);
        q->uvs = (float *)pw_alloc_array(a, (size_t)v[1] * 6, sizeof(float), "paste coordinates", e);
        if (!q->faces || !q->uvs) return PW_ERR_NOMEM;
        q->nfaces = (int)v[1];
        for (i = 0; i < q->nfaces; i++)
            if ((r = lapped__read_face(s, q, i)) != PW_OK) return r;
    }
    pw__sc_skip_empty(s);
    if (s->p < s->end) return pw__sc_fail(s, PW_ERR_PARSE, "unexpected text after the last paste");
    return PW_OK;
}

/* A texture read from a file does not know its mesh's triangle count:
 * ntris is 0 ("unknown"), and every triangle index is checked when the
 * texture is used with a mesh. */
LAPPEDDEF lapped_result lapped_read_pastes(const void *data, size_t size, const char *name, const lapped_options *opt,
                                           lapped_texture *out, lapped_error *err)
{
    lapped_options o = lapped__options(opt);
    pw_alloc a = lapped__alloc(&o.allocator);
    pw__sc s;
    pw_err pe;
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (!out || (!data && size)) {
        pw_fail(&pe, PW_ERR_INVALID, "lapped_read_pastes: NULL argument");
        return lapped__done(&pe, err);
    }
    out->allocator = lapped__allocator(&a);
    pw__sc_init(&s, data, size, name ? name : "pastes", 0, &pe);
    if (lapped__read_header(&s, &a, out, &pe) == PW_OK) lapped__read_pastes(&s, &a, out, &pe);
    if (pe.code != PW_OK) lapped_texture_free(out);
    return lapped__done(&pe, err);
}

/* ---- constraint files (docs/lapped.md) ------------------------------------------ */

/* "F DX DY DZ [SCALE [RADIUS [WEIGHT]]]": the numbers of a constraint line,
 * after its keyword. */
static int lapped__read_constraint(pw__sc *s, lapped_constraint *c, int index)
{
    double v[7];
    long long face;
    int k, n, r;
    memset(c, 0, sizeof *c);
    if ((r = pw__sc_int(s, &face, "constraint", index)) != PW_OK) return r;
    if (face < 0 || face > PW_MAX_MESH_ELEMENTS)
        return pw__sc_fail(s, PW_ERR_INVALID, "constraint %d: face %lld", index, face);
    for (n = 0; n < 6 && !pw__sc_eol(s); n++)
        if ((r = pw__sc_num(s, &v[n], "constraint", index)) != PW_OK) return r;
    if (n < 3 || !pw__sc_eol(s))
        return pw__sc_fail(s, PW_ERR_PARSE, "constraint %d: expected 'orient face dx dy dz [scale [radius [weight]]]'",
                           index);
    for (k = 0; k < n; k++) /* finite as floats: 1e39 is finite as a double only */
        if (!pw_is_finite(pw__num_to_float(v[k])))
            return pw__sc_fail(s, PW_ERR_INVALID, "constraint %d has a non-finite value (or one beyond float range)",
                               index);
    c->face = (int)face;
    for (k = 0; k < 3; k++) c->direction[k] = (float)v[k];
    c->scale = n > 3 ? (float)v[3] : 0.0f;
    c->radius = n > 4 ? (float)v[4] : 0.0f;
    c->weight = n > 5 ? (float)v[5] : 0.0f;
    pw__sc_next_line(s);
    return PW_OK;
}

/* One line: "orient ...", or an old positional line (no keyword: it starts
 * with the face number), whose line number *old_line keeps for the warning
 * (the first one). */
static int lapped__constraint_line(pw__sc *s, lapped_constraint *c, int index, int *old_line)
{
    char tok[32];
    const char *w;
    size_t n;
    pw__sc_blank(s);
    if (*s->p && strchr("0123456789+-.", *s->p)) {
        if (!*old_line) *old_line = s->line;
        return lapped__read_constraint(s, c, index);
    }
    w = pw__sc_word(s, &n);
    if (!pw__sc_is(w, n, "orient"))
        return pw__sc_fail(s, PW_ERR_PARSE,
                           "unknown keyword '%s' (a constraint line is 'orient face dx dy dz "
                           "[scale [radius [weight]]]')",
                           pw__sc_tok(s, w, tok));
    return lapped__read_constraint(s, c, index);
}

LAPPEDDEF lapped_result lapped_read_constraints(const void *data, size_t size, const char *name,
                                                const lapped_options *opt, lapped_constraints *out, lapped_error *err)
{
    lapped_options o = lapped__options(opt);
    pw_alloc a = lapped__alloc(&o.allocator);
    lapped_constraint *c = NULL;
    size_t cap = 0;
    int n = 0, old_line = 0;
    pw__sc s;
    pw_err pe;
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (!out || (!data && size)) {
        pw_fail(&pe, PW_ERR_INVALID, "lapped_read_constraints: NULL argument");
        return lapped__done(&pe, err);
    }
    pw__sc_init(&s, data, size, name ? name : "constraints", 0, &pe);
    for (pw__sc_skip_empty(&s); s.p < s.end && pe.code == PW_OK; pw__sc_skip_empty(&s))
        if (pw_grow(&a, (void **)&c, &cap, (size_t)n + 1, sizeof *c, "constraints", &pe) == PW_OK &&
            lapped__constraint_line(&s, &c[n], n, &old_line) == PW_OK)
            n++;
    if (pe.code == PW_OK && n == 0) pw_fail(&pe, PW_ERR_PARSE, "%s: no constraints", s.name);
    if (pe.code != PW_OK) {
        pw_free(&a, c);
        return lapped__done(&pe, err);
    }
    out->count = n;
    out->items = c;
    out->allocator = lapped__allocator(&a);
    if (old_line) /* rule C1: a warning, the call succeeds */
        pw_fail(&pe, PW_OK, "%s: line %d: positional constraint lines are deprecated; write 'orient F dx dy dz ...'",
                s.name, old_line);
    return lapped__done(&pe, err);
}

LAPPEDDEF void lapped_constraints_free(lapped_constraints *c)
{
    pw_alloc a;
    if (!c) return;
    a = lapped__alloc(&c->allocator);
    pw_free(&a, c->items);
    memset(c, 0, sizeof *c);
}

/* ---- meshes and images --------------------------------------------------------- */

PW_PUBLIC_IO(lapped, LAPPEDDEF);

/* The atlas's mesh as one glTF part: the fan triangles with their
 * per-corner atlas coordinates, the atlas image as the texture. */
LAPPEDDEF lapped_result lapped_write_gltf(const lapped_mesh *mesh, const lapped_atlas *atlas,
                                          const lapped_render_options *view, lapped_write_fn fn, void *ctx,
                                          lapped_error *err)
{
    pw_alloc a;
    pw_trimesh m;
    pw_gltf_part part;
    pw_gltf_scene scene;
    pw_camera cam;
    pw_image img;
    int *fstart = NULL, f;
    pw_err pe;
    pw_err_clear(&pe);
    memset(&part, 0, sizeof part);
    memset(&scene, 0, sizeof scene);
    if (!lapped__atlas_export_open(mesh, atlas, fn, "glTF", &a, &m, &pe) &&
        !lapped__check_image(&atlas->image, "atlas image", &pe)) {
        if ((fstart = (int *)pw_alloc_array(&a, (size_t)m.nf + 1, sizeof(int), "glTF faces", &pe)) != NULL) {
            for (f = 0; f <= m.nf; f++) fstart[f] = 3 * f;
            img = lapped__pw_image(&atlas->image);
            part.name = "lapped";
            part.nv = m.nv;
            part.pos = m.pos;
            part.nf = m.nf;
            part.fstart = fstart;
            part.fv = m.tri;
            part.corner_uv = atlas->uvs;
            part.texture = &img;
            scene.parts = &part;
            scene.nparts = 1;
            scene.generator = "patchwork lapped.h " LAPPED_VERSION_STRING;
            if (view) {
                cam = pw_gltf_view_camera(m.pos, m.nv, view->width, view->height, view->view_dir, view->up,
                                          &scene.aspect);
                scene.camera = &cam;
            }
            pw_gltf_write(&a, &scene, fn, ctx, &pe);
        }
    }
    pw_free(&a, fstart);
    pw_trimesh_free(&a, &m);
    return lapped__done(&pe, err);
}

#ifndef PW_NO_STDIO
/* the public file loaders: each file read whole, then read from memory */
PW_PUBLIC_LOAD(lapped, LAPPEDDEF, mesh, lapped_mesh);
PW_PUBLIC_LOAD(lapped, LAPPEDDEF, image, lapped_image);
PW_PUBLIC_LOAD(lapped, LAPPEDDEF, constraints, lapped_constraints);
PW_PUBLIC_LOAD(lapped, LAPPEDDEF, pastes, lapped_texture);

typedef struct lapped__job {
    const char *format;
    const lapped_texture *tex;
    const lapped_mesh *mesh;
    const lapped_atlas *atlas;
    const lapped_render_options *view;
} lapped__job;

static int lapped__obj_job(void *arg, pw_write_fn w, void *ctx, pw_err *e)
{
    const lapped__job *j = (const lapped__job *)arg;
    lapped_error le;
    int r = (int)lapped_write_obj(j->mesh, j->atlas, j->format, w, ctx, &le);
    return r ? pw_fail(e, r, "%s", le.message) : PW_OK;
}

static int lapped__mtl_job(void *arg, pw_write_fn w, void *ctx, pw_err *e)
{
    const lapped__job *j = (const lapped__job *)arg;
    return pw_mesh_write_mtl("lapped", j->format, w, ctx, e);
}

/* obj_path and, with texture_path, an MTL beside it (obj_path's name with
 * .mtl) whose map_Kd names the atlas image. */
LAPPEDDEF lapped_result lapped_save_obj(const char *obj_path, const lapped_mesh *mesh, const lapped_atlas *atlas,
                                        const char *texture_path, lapped_error *err)
{
    char mtl[1024];
    const char *mtl_name = NULL;
    lapped__job j;
    pw_err pe;
    pw_err_clear(&pe);
    memset(&j, 0, sizeof j);
    if (pw_obj_mtl_path(obj_path, mtl, sizeof mtl, &mtl_name, &pe) != PW_OK) return lapped__done(&pe, err);
    j.mesh = mesh;
    j.atlas = atlas;
    j.format = texture_path ? mtl_name : NULL; /* the mtllib name */
    if (pw_write_file(obj_path, lapped__obj_job, &j, &pe) == PW_OK && texture_path) {
        j.format = texture_path;
        pw_write_file(mtl, lapped__mtl_job, &j, &pe);
    }
    return lapped__done(&pe, err);
}

static int lapped__gltf_job(void *arg, pw_write_fn w, void *ctx, pw_err *e)
{
    const lapped__job *j = (const lapped__job *)arg;
    lapped_error le;
    int r = (int)lapped_write_gltf(j->mesh, j->atlas, j->view, w, ctx, &le);
    return r ? pw_fail(e, r, "%s", le.message) : PW_OK;
}

LAPPEDDEF lapped_result lapped_save_gltf(const char *path, const lapped_mesh *mesh, const lapped_atlas *atlas,
                                         const lapped_render_options *view, lapped_error *err)
{
    lapped__job j;
    pw_err pe;
    pw_err_clear(&pe);
    memset(&j, 0, sizeof j);
    j.mesh = mesh;
    j.atlas = atlas;
    j.view = view;
    if (!path) pw_fail(&pe, PW_ERR_INVALID, "lapped_save_gltf: NULL path");
    else pw_write_file(path, lapped__gltf_job, &j, &pe);
    return lapped__done(&pe, err);
}

static int lapped__pastes_job(void *arg, pw_write_fn w, void *ctx, pw_err *e)
{
    const lapped__job *j = (const lapped__job *)arg;
    lapped_error le;
    int r = (int)lapped_write_pastes(j->tex, w, ctx, &le);
    return r ? pw_fail(e, r, "%s", le.message) : PW_OK;
}

PW_PUBLIC_SAVE_IMAGE(lapped, LAPPEDDEF);

LAPPEDDEF lapped_result lapped_save_pastes(const char *path, const lapped_texture *t, lapped_error *err)
{
    lapped__job j;
    pw_err pe;
    pw_err_clear(&pe);
    memset(&j, 0, sizeof j);
    j.tex = t;
    if (!path || !t) pw_fail(&pe, PW_ERR_INVALID, "lapped_save_pastes: NULL argument");
    else pw_write_file(path, lapped__pastes_job, &j, &pe);
    return lapped__done(&pe, err);
}

#endif
