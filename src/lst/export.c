/* export.c: the visible boundary with a baked texture atlas, for glTF.
 *
 * §5.1 draws "each surface triangle ... multiple times using the texture
 * coordinates in its assigned list, with alpha blending", and the faces a
 * cut opened the same way. A standard viewer has no such list: what it
 * can show is one texture per triangle. So the boundary lst_render draws
 * (lst__boundary_tris: the surface after the cuts, then the cut faces) is
 * made a triangle mesh of its own, cut into charts, packed into one image
 * (src/common/atlas.h, as lapped.h's §4 atlas), and each texel is baked
 * with the model's colour at that point of the boundary: the composite of
 * the pastes there (lst__eval), as lst_render shows it with show = COLOR
 * and unlit. The viewer lights that albedo itself.
 *
 * The boundary of a tetrahedral mesh is not always a manifold: after a
 * cut, two pieces of the solid can touch along an edge (four boundary
 * faces around it) or at a vertex (two fans of faces). Charts need a
 * manifold (pw_trimesh_init), so the mesh is built with a vertex per fan:
 * an edge joins its two faces only when exactly one face runs along it
 * each way; the corners joined through such edges around a mesh vertex
 * (union-find) share one atlas vertex. Around one atlas vertex the faces
 * then form one fan, and no edge has two faces running the same way, so
 * the result is a manifold with the boundary's geometry. Surface and cut
 * faces never share a vertex: lst_render draws them as two meshes, each
 * with its own smooth normals, and the glTF file's normals (per vertex)
 * match that.
 *
 * Export: lst_write_gltf (the mesh, the atlas image, optionally the camera
 * lst_render frames: pw_camera_frame depends only on the extreme points of
 * the vertices it is given, and the visible tetrahedra's extreme points
 * are boundary vertices, so framing the atlas's vertices gives the same
 * camera), lst_write_atlas_obj. */
#include "io.c"
#include "../common/atlas_pack.h"
#include "../common/atlas_bake.h"

/* ---- the visible boundary as a manifold triangle mesh ------------------------------------- */

/* A half-edge h = 3f + k of a triangle list, a -> b, sorted by (a, b). */
typedef struct lst__half {
    uint64_t key; /* a << 32 | b */
    int h;
} lst__half;

static uint64_t lst__hkey(const int *tri, int h, int reverse)
{
    uint32_t a = (uint32_t)tri[h], b = (uint32_t)tri[3 * (h / 3) + (h % 3 + 1) % 3];
    return reverse ? (uint64_t)b << 32 | a : (uint64_t)a << 32 | b;
}

static int lst__cmp_half(const void *x, const void *y)
{
    const lst__half *p = (const lst__half *)x, *q = (const lst__half *)y;
    return p->key < q->key ? -1 : p->key > q->key ? 1 : (p->h > q->h) - (p->h < q->h);
}

/* The half-edges with this key in the sorted list: the first at *at, their
 * count returned. */
static int lst__half_range(const lst__half *sorted, int nh, uint64_t key, int *at)
{
    int lo = 0, hi = nh, n = 0;
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (sorted[mid].key < key) lo = mid + 1;
        else hi = mid;
    }
    *at = lo;
    while (lo + n < nh && sorted[lo + n].key == key) n++;
    return n;
}

static int lst__uf_find(int *parent, int x)
{
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

static void lst__uf_join(int *parent, int x, int y)
{
    x = lst__uf_find(parent, x);
    y = lst__uf_find(parent, y);
    if (x < y) parent[y] = x;
    else parent[x] = y;
}

/* Joins the corners of the faces on both sides of every edge that exactly
 * one face runs along each way; parent: 3n corners, a union-find. */
static int lst__join_corners(const pw_alloc *a, const int *tri, int n, int *parent, pw_err *e)
{
    int nh = 3 * n, h, at;
    lst__half *sorted = (lst__half *)pw_alloc_array(a, (size_t)nh, sizeof(lst__half), "boundary edges", e);
    if (!sorted) return PW_ERR_NOMEM;
    for (h = 0; h < nh; h++) {
        sorted[h].key = lst__hkey(tri, h, 0);
        sorted[h].h = h;
        parent[h] = h;
    }
    qsort(sorted, (size_t)nh, sizeof(lst__half), lst__cmp_half); /* a total order: the same on every platform */
    for (h = 0; h < nh; h++) {
        int g, f = h / 3, k = h % 3;
        if (lst__half_range(sorted, nh, lst__hkey(tri, h, 0), &at) != 1 ||
            lst__half_range(sorted, nh, lst__hkey(tri, h, 1), &at) != 1)
            continue;
        g = sorted[at].h; /* b -> a: its corner at b starts it, its corner at a ends it */
        lst__uf_join(parent, 3 * f + k, 3 * (g / 3) + (g % 3 + 1) % 3);
        lst__uf_join(parent, 3 * f + (k + 1) % 3, g);
    }
    pw_free(a, sorted);
    return PW_OK;
}

/* The boundary triangles (surface, then cut faces; vertex ids: mesh vertex,
 * plus nverts on cut faces) into atlas vertices, one per class of joined
 * corners, numbered in order of first use. */
static int lst__atlas_vertices(const pw_alloc *a, const lst_model *m, const int *tri, int n, lst_atlas *out, pw_err *e)
{
    int *parent = (int *)pw_alloc_array(a, (size_t)n * 3, sizeof(int), "boundary corners", e);
    int *id = (int *)pw_alloc_array(a, (size_t)n * 3, sizeof(int), "boundary corners", e), c, r;
    out->tris = (int *)pw_alloc_array(a, (size_t)n * 3, sizeof(int), "atlas triangles", e);
    out->positions = (float *)pw_alloc_array(a, (size_t)n * 9, sizeof(float), "atlas vertices", e);
    r = parent && id && out->tris && out->positions ? lst__join_corners(a, tri, n, parent, e) : PW_ERR_NOMEM;
    for (c = 0; r == PW_OK && c < 3 * n; c++) {
        int root = lst__uf_find(parent, c);
        if (root == c) {
            memcpy(out->positions + 3 * out->nverts, m->mesh.positions + 3 * (tri[c] % m->mesh.nverts),
                   3 * sizeof(float));
            id[c] = out->nverts++;
        }
        out->tris[c] = id[root]; /* the root is the class's first corner */
    }
    out->ntris = r == PW_OK ? n : 0;
    pw_free(a, parent);
    pw_free(a, id);
    return r;
}

/* The visible boundary: surface triangles then cut faces (as lst_render
 * draws them) into *all (mesh vertices, tetrahedra, barycentrics) and the
 * atlas's mesh. */
static int lst__atlas_boundary(const pw_alloc *a, const lst_model *m, lst__tris *all, lst_atlas *out, pw_err *e)
{
    pw_tetmesh tm = lst__pw_tets(&m->mesh);
    lst__tris cut;
    int *nb = (int *)pw_alloc_array(a, (size_t)m->mesh.ntets * 4, sizeof(int), "face adjacency", e), *tri = NULL, k, r;
    memset(&cut, 0, sizeof cut);
    memset(all, 0, sizeof *all);
    r = nb ? pw_tetmesh_neighbors(a, &tm, nb, e) : PW_ERR_NOMEM;
    if (r == PW_OK) r = lst__boundary_tris(a, m, nb, 0, all, e);
    if (r == PW_OK) r = lst__boundary_tris(a, m, nb, 1, &cut, e);
    for (k = 0; r == PW_OK && k < cut.n; k++) {
        if ((r = lst__tris_room(a, all, e)) != PW_OK) break;
        memcpy(all->tri + 3 * all->n, cut.tri + 3 * k, 3 * sizeof(int));
        memcpy(all->bary + 12 * all->n, cut.bary + 12 * k, 12 * sizeof(float));
        all->tet[all->n++] = cut.tet[k];
    }
    if (r == PW_OK && all->n == 0)
        r = pw_fail(e, PW_ERR_DEGENERATE, "atlas: nothing visible: every tetrahedron was cut away");
    if (r == PW_OK && !(tri = (int *)pw_alloc_array(a, (size_t)all->n * 3, sizeof(int), "boundary corners", e)))
        r = PW_ERR_NOMEM;
    for (k = 0; r == PW_OK && k < 3 * all->n; k++)
        tri[k] = all->tri[k] + (k / 3 >= all->n - cut.n ? m->mesh.nverts : 0);
    if (r == PW_OK) r = lst__atlas_vertices(a, m, tri, all->n, out, e);
    pw_free(a, tri);
    pw_free(a, nb);
    lst__tris_free(a, &cut);
    return r;
}

/* ---- baking ------------------------------------------------------------------------------------ */

/* What a texel holds: the model's colour at that point of triangle f. */
typedef struct lst__atlas_texel {
    const lst__view *v;
    const lst__tris *tris;
} lst__atlas_texel;

static void lst__atlas_eval(void *user, int f, const float b[3], float *px)
{
    const lst__atlas_texel *T = (const lst__atlas_texel *)user;
    const float *w = T->tris->bary + 12 * (size_t)f;
    double l[4];
    float rgba[4];
    int k;
    for (k = 0; k < 4; k++) l[k] = b[0] * w[k] + b[1] * w[4 + k] + b[2] * w[8 + k];
    lst__eval(T->v, T->tris->tet[f], l, rgba, NULL);
    memcpy(px, rgba, 3 * sizeof(float));
}

/* Charts, packing and baking of the atlas's mesh (out, from the boundary
 * tris of m), by options opt (its atlas settings checked); the picture
 * goes to out->image. */
static int lst__atlas_run(const pw_alloc *a, const lst_model *m, const lst__tris *tris, const lst_options *opt,
                          lst_atlas *out, pw_err *e)
{
    const lst_atlas_options *o = &opt->atlas;
    pw_progress progress = lst__progress(opt);
    const pw_progress *prog = &progress;
    pw_image pic, *img = &pic;
    pw_mesh pm;
    pw_trimesh tm;
    lst__view v;
    lst__atlas_texel T;
    pw_atlas_job job;
    pw_atlas_source src;
    int *fstart = (int *)pw_alloc_array(a, (size_t)out->ntris + 1, sizeof(int), "atlas faces", e), f, r;
    memset(&pm, 0, sizeof pm);
    memset(&tm, 0, sizeof tm);
    memset(&v, 0, sizeof v);
    memset(&pic, 0, sizeof pic);
    job.a = a;
    job.m = &tm;
    job.cone = o->cone_angle;
    job.size = o->size;
    job.gutter = o->gutter;
    job.prog = prog;
    if (!fstart) return PW_ERR_NOMEM;
    for (f = 0; f <= out->ntris; f++) fstart[f] = 3 * f;
    pm.nv = out->nverts;
    pm.pos = out->positions;
    pm.nf = out->ntris;
    pm.fstart = fstart;
    pm.fv = out->tris;
    r = pw_trimesh_init_ex(a, &pm, 1, &tm, e);
    if (r == PW_OK) r = pw_atlas_layout(&job, &out->uvs, &out->ncharts, &out->fill, e);
    if (r == PW_OK) r = lst__view_init(a, m, LST_SHOW_COLOR, &v, e);
    T.v = &v;
    T.tris = tris;
    src.fn = lst__atlas_eval;
    src.user = &T;
    src.oc = 3;
    if (r == PW_OK) r = pw_atlas_bake(&job, out->uvs, &src, img, e);
    lst__view_free(&v);
    pw_trimesh_free(a, &tm);
    pw_free(a, fstart);
    if (r == PW_OK) r = pw_report(prog, 1.0f, "atlas", e);
    if (r == PW_OK) lst__take_image(&pic, a, &out->image);
    else pw_image_free(a, &pic);
    return r;
}

LSTDEF lst_result lst_bake_atlas(const lst_model *model, const lst_options *opt, lst_atlas *out, lst_error *err)
{
    lst_options o = lst__options(opt);
    pw_alloc a = lst__alloc(&o.allocator);
    lst__tris tris;
    pw_err e;
    pw_err_clear(&e);
    memset(&tris, 0, sizeof tris);
    if (!out) {
        pw_fail(&e, PW_ERR_INVALID, "atlas: no output");
        return lst__done(&e, err);
    }
    memset(out, 0, sizeof *out);
    if (!model) pw_fail(&e, PW_ERR_INVALID, "atlas: no model");
    else if (!pw_atlas_options(&o.atlas.size, &o.atlas.cone_angle, &o.atlas.gutter, &e) &&
             !lst__check_model(model, &e) && !lst__atlas_boundary(&a, model, &tris, out, &e)) {
        int r = lst__atlas_run(&a, model, &tris, &o, out, &e);
        if (r != PW_OK) pw_fail(&e, r, "atlas: %s", pw_result_string(r)); /* keeps a recorded message */
    }
    lst__tris_free(&a, &tris);
    out->allocator = lst__allocator(&a);
    if (e.code) lst_atlas_free(out);
    return lst__done(&e, err);
}

LSTDEF void lst_atlas_free(lst_atlas *atlas)
{
    pw_alloc a;
    if (!atlas) return;
    a = lst__alloc(&atlas->allocator);
    pw_free(&a, atlas->positions);
    pw_free(&a, atlas->tris);
    pw_free(&a, atlas->uvs);
    lst_image_free(&atlas->image);
    memset(atlas, 0, sizeof *atlas);
}

/* ---- export ------------------------------------------------------------------------------------ */

/* What every export of an atlas checks first (`what` names the format). */
static int lst__atlas_check(const lst_atlas *at, lst_write_fn fn, const char *what, pw_err *e)
{
    int k;
    if (!at || !fn) return pw_fail(e, PW_ERR_INVALID, "%s: no atlas or no writer", what);
    if (at->nverts < 1 || at->ntris < 1 || !at->positions || !at->tris || !at->uvs)
        return pw_fail(e, PW_ERR_INVALID, "%s: the atlas is empty (%d vertices, %d triangles)", what, at->nverts,
                       at->ntris);
    for (k = 0; k < 3 * at->ntris; k++)
        if (at->tris[k] < 0 || at->tris[k] >= at->nverts)
            return pw_fail(e, PW_ERR_INVALID, "%s: corner %d of atlas triangle %d names vertex %d of %d", what, k % 3,
                           k / 3, at->tris[k], at->nverts);
    return PW_OK;
}

LSTDEF lst_result lst_write_gltf(const lst_atlas *atlas, const lst_render_options *view, lst_write_fn fn, void *ctx,
                                 lst_error *err)
{
    pw_alloc a = lst__alloc(atlas ? &atlas->allocator : NULL);
    pw_gltf_part part;
    pw_gltf_scene scene;
    pw_camera cam;
    pw_image img;
    int *fstart = NULL, f;
    pw_err e;
    pw_err_clear(&e);
    memset(&part, 0, sizeof part);
    memset(&scene, 0, sizeof scene);
    if (!lst__atlas_check(atlas, fn, "glTF", &e) && !lst__check_image(&atlas->image, "atlas image", &e) &&
        (fstart = (int *)pw_alloc_array(&a, (size_t)atlas->ntris + 1, sizeof(int), "glTF faces", &e)) != NULL) {
        for (f = 0; f <= atlas->ntris; f++) fstart[f] = 3 * f;
        img = lst__pw_image(&atlas->image);
        part.name = "lst";
        part.nv = atlas->nverts;
        part.pos = atlas->positions;
        part.nf = atlas->ntris;
        part.fstart = fstart;
        part.fv = atlas->tris;
        part.corner_uv = atlas->uvs;
        part.texture = &img;
        scene.parts = &part;
        scene.nparts = 1;
        scene.generator = "patchwork lst.h " LST_VERSION_STRING;
        if (view) {
            cam = pw_gltf_view_camera(atlas->positions, atlas->nverts, view->width, view->height, view->view_dir,
                                      view->up, &scene.aspect);
            scene.camera = &cam;
        }
        pw_gltf_write(&a, &scene, fn, ctx, &e);
    }
    pw_free(&a, fstart);
    return lst__done(&e, err);
}

LSTDEF lst_result lst_write_atlas_obj(const lst_atlas *atlas, const char *mtl_name, lst_write_fn fn, void *ctx,
                                      lst_error *err)
{
    pw_alloc a = lst__alloc(atlas ? &atlas->allocator : NULL);
    pw_trimesh tm;
    pw_mesh pm;
    pw_err e;
    pw_err_clear(&e);
    memset(&tm, 0, sizeof tm);
    memset(&pm, 0, sizeof pm);
    if (!lst__atlas_check(atlas, fn, "OBJ", &e)) {
        tm.nv = atlas->nverts;
        tm.pos = atlas->positions;
        tm.nf = atlas->ntris;
        tm.tri = atlas->tris;
        if (!pw_atlas_mesh(&a, &tm, atlas->uvs, &pm, &e))
            pw_mesh_write_obj(&pm, mtl_name, mtl_name ? "lst" : NULL, fn, ctx, &e);
    }
    pw_free(&a, pm.fstart);
    pw_free(&a, pm.uv);
    pw_free(&a, pm.fuv);
    return lst__done(&e, err);
}

LSTDEF lst_result lst_write_mtl(const char *texture_name, lst_write_fn fn, void *ctx, lst_error *err)
{
    pw_err e;
    pw_err_clear(&e);
    if (!fn) pw_fail(&e, PW_ERR_INVALID, "MTL: no writer");
    else pw_mesh_write_mtl("lst", texture_name, fn, ctx, &e);
    return lst__done(&e, err);
}

#ifndef PW_NO_STDIO
typedef struct lst__export_job {
    const lst_atlas *atlas;
    const lst_render_options *view;
    const char *name; /* OBJ: the mtllib name; MTL: the texture */
} lst__export_job;

static int lst__gltf_job(void *arg, pw_write_fn w, void *ctx, pw_err *e)
{
    const lst__export_job *j = (const lst__export_job *)arg;
    lst_error le;
    int r = (int)lst_write_gltf(j->atlas, j->view, w, ctx, &le);
    return r ? pw_fail(e, r, "%s", le.message) : PW_OK;
}

LSTDEF lst_result lst_save_gltf(const char *path, const lst_atlas *atlas, const lst_render_options *view,
                                lst_error *err)
{
    lst__export_job j;
    pw_err e;
    pw_err_clear(&e);
    j.atlas = atlas;
    j.view = view;
    j.name = NULL;
    if (!path) pw_fail(&e, PW_ERR_INVALID, "lst_save_gltf: NULL path");
    else pw_write_file(path, lst__gltf_job, &j, &e);
    return lst__done(&e, err);
}

static int lst__atlas_obj_job(void *arg, pw_write_fn w, void *ctx, pw_err *e)
{
    const lst__export_job *j = (const lst__export_job *)arg;
    lst_error le;
    int r = (int)lst_write_atlas_obj(j->atlas, j->name, w, ctx, &le);
    return r ? pw_fail(e, r, "%s", le.message) : PW_OK;
}

static int lst__mtl_job(void *arg, pw_write_fn w, void *ctx, pw_err *e)
{
    const lst__export_job *j = (const lst__export_job *)arg;
    return pw_mesh_write_mtl("lst", j->name, w, ctx, e);
}

LSTDEF lst_result lst_save_atlas_obj(const char *obj_path, const lst_atlas *atlas, const char *texture_path,
                                     lst_error *err)
{
    char mtl[1024];
    const char *mtl_name = NULL;
    lst__export_job j;
    pw_err e;
    pw_err_clear(&e);
    if (pw_obj_mtl_path(obj_path, mtl, sizeof mtl, &mtl_name, &e) != PW_OK) return lst__done(&e, err);
    j.atlas = atlas;
    j.view = NULL;
    j.name = texture_path ? mtl_name : NULL;
    if (pw_write_file(obj_path, lst__atlas_obj_job, &j, &e) == PW_OK && texture_path) {
        j.name = texture_path;
        pw_write_file(mtl, lst__mtl_job, &j, &e);
    }
    return lst__done(&e, err);
}
#endif
