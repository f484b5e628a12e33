/* io.c: files. Meshes and exemplars in; the mapped mesh with its texture
 * coordinates out as OBJ + MTL or glTF, for other programs to render (the
 * thesis took its meshes from and to Maya, ch. IV.2 and V), and images. */
#include "render.c"

PW_PUBLIC_IO(tiled, TILEDDEF);

/* Distinct texture coordinates in order of first use (an open-addressing
 * table on their bit patterns), so the OBJ lists each vt once. */
static int tiled__index_uvs(const pw_alloc *a, const tiled_mesh *m, pw_mesh *pm, pw_err *e)
{
    int nc = m->face_start[m->nfaces], k, cap = 16, *slot;
    while (cap < 2 * nc) cap *= 2;
    slot = (int *)pw_alloc_array(a, (size_t)cap, sizeof(int), "uv table", e);
    pm->uv = (float *)pw_alloc_array(a, (size_t)nc * 2, sizeof(float), "uvs", e);
    pm->fuv = (int *)pw_alloc_array(a, (size_t)nc, sizeof(int), "uv indices", e);
    if (!slot || !pm->uv || !pm->fuv) {
        pw_free(a, slot);
        return PW_ERR_NOMEM;
    }
    memset(slot, 0xFF, sizeof(int) * (size_t)cap);
    pm->nuv = 0;
    for (k = 0; k < nc; k++) {
        uint32_t bu, bv, i;
        memcpy(&bu, m->uvs + 2 * k, 4);
        memcpy(&bv, m->uvs + 2 * k + 1, 4);
        i = (uint32_t)pw_hash64(bu, bv) & (uint32_t)(cap - 1);
        while (slot[i] >= 0 && memcmp(pm->uv + 2 * slot[i], m->uvs + 2 * k, 8)) i = (i + 1) & (uint32_t)(cap - 1);
        if (slot[i] < 0) {
            slot[i] = pm->nuv++;
            memcpy(pm->uv + 2 * slot[i], m->uvs + 2 * k, 8);
        }
        pm->fuv[k] = slot[i];
    }
    pw_free(a, slot);
    return PW_OK;
}

TILEDDEF tiled_result tiled_write_obj(const tiled_mesh *m, const char *mtl_name, tiled_write_fn fn, void *ctx,
                                      tiled_error *err)
{
    pw_alloc a = tiled__alloc(m ? &m->allocator : NULL);
    pw_mesh pm;
    pw_err pe;
    pw_err_clear(&pe);
    if (!fn) pw_fail(&pe, PW_ERR_INVALID, "tiled_write_obj: NULL writer");
    else if (tiled__check_mesh(m, &pe) == PW_OK) {
        pm = tiled__pw_mesh(m);
        if (!m->uvs || tiled__index_uvs(&a, m, &pm, &pe) == PW_OK)
            pw_mesh_write_obj(&pm, mtl_name, mtl_name ? "tiled" : NULL, fn, ctx, &pe);
        if (m->uvs) {
            pw_free(&a, pm.uv);
            pw_free(&a, pm.fuv);
        }
    }
    return tiled__done(&pe, err);
}

TILEDDEF tiled_result tiled_write_gltf(const tiled_mesh *m, const tiled_image *texture,
                                       const tiled_render_options *view, tiled_write_fn fn, void *ctx, tiled_error *err)
{
    pw_alloc a = tiled__alloc(m ? &m->allocator : NULL);
    pw_gltf_part part;
    pw_gltf_scene scene;
    pw_camera cam;
    pw_image img;
    pw_err pe;
    pw_err_clear(&pe);
    memset(&part, 0, sizeof part);
    memset(&scene, 0, sizeof scene);
    if (!fn) pw_fail(&pe, PW_ERR_INVALID, "tiled_write_gltf: NULL writer");
    else if (texture && !m->uvs) pw_fail(&pe, PW_ERR_INVALID, "glTF: a texture for a mesh without texture coordinates");
    else if (tiled__check_mesh(m, &pe) == PW_OK && (!texture || tiled__check_image(texture, "texture", &pe) == PW_OK)) {
        part.name = "tiled";
        part.nv = m->nverts;
        part.pos = m->positions;
        part.nf = m->nfaces;
        part.fstart = m->face_start;
        part.fv = m->face_verts;
        part.corner_uv = m->uvs;
        if (texture) {
            img = tiled__pw_image(texture);
            part.texture = &img;
        }
        scene.parts = &part;
        scene.nparts = 1;
        scene.generator = "patchwork tiled.h " TILED_VERSION_STRING;
        if (view) {
            cam = pw_gltf_view_camera(m->positions, m->nverts, view->width, view->height, view->view_dir, view->up,
                                      &scene.aspect);
            scene.camera = &cam;
        }
        pw_gltf_write(&a, &scene, fn, ctx, &pe);
    }
    return tiled__done(&pe, err);
}

TILEDDEF tiled_result tiled_write_mtl(const char *texture_name, tiled_write_fn fn, void *ctx, tiled_error *err)
{
    pw_err pe;
    pw_err_clear(&pe);
    if (!fn || !texture_name) pw_fail(&pe, PW_ERR_INVALID, "tiled_write_mtl: NULL argument");
    else pw_mesh_write_mtl("tiled", texture_name, fn, ctx, &pe);
    return tiled__done(&pe, err);
}

#ifndef PW_NO_STDIO
/* the public file loaders: each file read whole, then read from memory */
PW_PUBLIC_LOAD(tiled, TILEDDEF, mesh, tiled_mesh);
PW_PUBLIC_LOAD(tiled, TILEDDEF, image, tiled_image);

/* Writers behind pw_write_file. */
typedef struct tiled__job {
    const tiled_image *img;
    const char *format;
    const tiled_mesh *mesh;
    const char *name; /* mtl name or texture name */
    const tiled_render_options *view;
} tiled__job;

static int tiled__obj_job(void *arg, pw_write_fn w, void *ctx, pw_err *e)
{
    const tiled__job *j = (const tiled__job *)arg;
    tiled_error te;
    int r = (int)tiled_write_obj(j->mesh, j->name, w, ctx, &te);
    if (r) pw_fail(e, r, "%s", te.message);
    return r;
}

static int tiled__mtl_job(void *arg, pw_write_fn w, void *ctx, pw_err *e)
{
    const tiled__job *j = (const tiled__job *)arg;
    return pw_mesh_write_mtl("tiled", j->name, w, ctx, e);
}

static int tiled__gltf_job(void *arg, pw_write_fn w, void *ctx, pw_err *e)
{
    const tiled__job *j = (const tiled__job *)arg;
    tiled_error te;
    int r = (int)tiled_write_gltf(j->mesh, j->img, j->view, w, ctx, &te);
    if (r) pw_fail(e, r, "%s", te.message);
    return r;
}

PW_PUBLIC_SAVE_IMAGE(tiled, TILEDDEF);

TILEDDEF tiled_result tiled_save_gltf(const char *path, const tiled_mesh *m, const tiled_image *texture,
                                      const tiled_render_options *view, tiled_error *err)
{
    tiled__job j;
    pw_err pe;
    pw_err_clear(&pe);
    memset(&j, 0, sizeof j);
    j.mesh = m;
    j.img = texture;
    j.view = view;
    if (!path) pw_fail(&pe, PW_ERR_INVALID, "tiled_save_gltf: NULL path");
    else pw_write_file(path, tiled__gltf_job, &j, &pe);
    return tiled__done(&pe, err);
}

TILEDDEF tiled_result tiled_save_obj(const char *obj_path, const tiled_mesh *m, const char *texture_path,
                                     tiled_error *err)
{
    char mtl[1024];
    const char *mtl_name = NULL;
    tiled__job j;
    pw_err pe;
    pw_err_clear(&pe);
    memset(&j, 0, sizeof j);
    if (pw_obj_mtl_path(obj_path, mtl, sizeof mtl, &mtl_name, &pe) != PW_OK) return tiled__done(&pe, err);
    j.mesh = m;
    j.name = texture_path ? mtl_name : NULL;
    if (pw_write_file(obj_path, tiled__obj_job, &j, &pe) == PW_OK && texture_path) {
        j.name = texture_path;
        pw_write_file(mtl, tiled__mtl_job, &j, &pe);
    }
    return tiled__done(&pe, err);
}
#endif
