/* fuzz_pgp: pgp.h's mapping on fuzzed input. An 8-byte header picks the
 * options, then h[5] bytes of constraints file (the CLI's text format,
 * read by pgp_read_constraints), then a mesh (OBJ, OFF or PLY, at most FZ_MAX_TRIS
 * triangles after triangulation).
 *
 *   h[0]  bit 0 field (0 up, 1 curvature), bit 1 counting allocator,
 *         bit 2 render (tile, or material / singular view by bits 3-4),
 *         bits 5-7 the progress call that cancels (0: none)
 *   h[1]  scale: 0 the default, else h[1] / 64 of the bounding-box diagonal
 *   h[2]  default material h[2] / 255; h[3] smoothing sweeps (curvature)
 *   h[4]  bits 0-2 the up direction (axes, one diagonal), bit 3 make the
 *         map twice (the same inputs give the same coordinates), bit 4
 *         write the OBJ, bits 5-6 singular_distortion (default, 0.1, 2, 10),
 *         bit 7 the file's constraints given to pgp_create (opt.constraints)
 *         rather than added one by one after it
 *   h[5]  length of the constraints text that follows
 *   h[6], h[7]  an extra orientation constraint's triangle and radius
 *
 * Any result is fine; crashes, leaks, sanitizer reports and these are not:
 *   - a failure carries its code and a message and hands nothing out;
 *   - a map that is made has finite coordinates, materials in [0, 1],
 *     positive finite scales, unit directions, at most ntris singular
 *     triangles, vortex flags that match their count, and made again from the same inputs it is bit-identical;
 *   - a rendering has the requested size and finite pixels;
 *   - with the counting allocator, every block goes back to the allocator
 *     that made it and none is left over. */
#define PGP_STATIC /* static: only what the target calls is compiled */
#define PGP_IMPLEMENTATION
#include "../pgp.h"
#define FZ_NAME "fuzz_pgp"
#include "fuzz.h"

#define FZ_MAX_TRIS 300
#define FZ_HEADER 8

#define fz_pgp_failure(r, err) fz_check_failure((int)(r), (int)(err)->code, (err)->message, sizeof (err)->message)

static int fz_triangles(const pgp_mesh *m)
{
    int f, n = 0;
    for (f = 0; f < m->nfaces; f++) n += m->face_start[f + 1] - m->face_start[f] - 2;
    return n;
}

static float fz_diag(const pgp_mesh *m)
{
    float lo[3], hi[3], d = 0.0f;
    int v, k;
    for (k = 0; k < 3; k++) lo[k] = hi[k] = m->positions[k];
    for (v = 1; v < m->nverts; v++)
        for (k = 0; k < 3; k++) {
            float x = m->positions[3 * v + k];
            lo[k] = x < lo[k] ? x : lo[k];
            hi[k] = x > hi[k] ? x : hi[k];
        }
    for (k = 0; k < 3; k++) d += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    return d > 0.0f && d < 1e30f ? sqrtf(d) : 1.0f;
}

static void fz_options(const uint8_t *h, const pgp_mesh *m, pgp_options *o)
{
    static const float up[8][3] = {{0, 1, 0}, {1, 0, 0}, {0, 0, 1}, {0, -1, 0},
                                   {1, 1, 1}, {-1, 0, 0}, {0, 0, -1}, {0.3f, -1, 0.2f}};
    static const float dist[4] = {0.0f, 0.1f, 2.0f, 10.0f};
    *o = pgp_default_options();
    o->field = (h[0] & 1) ? PGP_FIELD_CURVATURE : PGP_FIELD_UP;
    o->scale = h[1] ? (float)h[1] / 64.0f * fz_diag(m) : 0.0f;
    o->material = (float)h[2] / 255.0f;
    o->smoothing = h[3] & 31;
    memcpy(o->up, up[h[4] & 7], sizeof o->up);
    o->singular_distortion = dist[h[4] >> 5 & 3];
    o->weights = (h[3] >> 5 & 1) ? PGP_WEIGHTS_AREA : PGP_WEIGHTS_COTAN; /* or the paper's area weights */
    o->integrable = (h[3] >> 6 & 1) ? 1.0f : 0.0f; /* --field smooth */
}

/* A made map is consistent. */
static void fz_check_map(const pgp_map *P)
{
    int nf = P->ntris, nv = P->nverts, i, k;
    const float *stm = P->coords;
    pgp_field fd;
    pgp_error err;
    FZ_CHECK(pgp_map_field(P, &fd, &err) == PGP_OK && fd.ntris == nf && fd.nverts == nv);
    for (i = 0; i < 9 * nf; i++) FZ_CHECK(fz_finite(stm[i]));
    for (i = 0; i < nf; i++) {
        const float *d = fd.dir + 3 * i;
        float l = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        FZ_CHECK(l > 0.99f && l < 1.01f);
        for (k = 0; k < 3; k++) FZ_CHECK(stm[9 * i + 3 * k + 2] >= 0.0f && stm[9 * i + 3 * k + 2] <= 1.0f);
    }
    for (i = 0; i < nv; i++)
        FZ_CHECK(fz_finite(fd.scale[i]) && fd.scale[i] > 0.0f && fd.material[i] >= 0.0f && fd.material[i] <= 1.0f);
    pgp_field_free(&fd);
    k = pgp_map_singular(P, NULL);
    FZ_CHECK(k >= 0 && k <= nf);
    { /* issue 17: the report is finite, the clean fix treats exactly the vortices */
        pgp_stats st;
        pgp_map_stats(P, &st);
        FZ_CHECK(st.triangles == nf && st.singular == k && st.stretched >= 0.0f && st.stretched <= 1.0f &&
                 st.sheared >= 0.0f && st.sheared <= 1.0f && fz_finite(st.mean_edge) && st.scale > 0.0f);
        FZ_CHECK(pgp_map_special(P, PGP_FIX_CLEAN, NULL) == pgp_map_vortices(P, NULL));
        FZ_CHECK(pgp_map_special(P, PGP_FIX_PAPER, NULL) == k && pgp_map_special(P, PGP_FIX_OFF, NULL) == 0);
    }
    {
        unsigned char *vort = (unsigned char *)malloc((size_t)nf + 1);
        int nvort = 0;
        FZ_CHECK(vort != NULL);
        k = pgp_map_vortices(P, vort);
        for (i = 0; i < nf; i++) {
            FZ_CHECK(vort[i] <= 3);
            nvort += vort[i] != 0;
        }
        FZ_CHECK(k == nvort);
        free(vort);
    }
}

static void fz_same(const pgp_map *a, const pgp_map *b)
{
    FZ_CHECK(a->ntris == b->ntris && memcmp(a->coords, b->coords, sizeof(float) * 9 * (size_t)a->ntris) == 0);
    FZ_CHECK(pgp_map_singular(a, NULL) == pgp_map_singular(b, NULL));
    FZ_CHECK(pgp_map_vortices(a, NULL) == pgp_map_vortices(b, NULL));
}

/* An atlas (baked, or the raw coordinates) and its glTF file: made, or a
 * clean failure; baked coordinates in [0, 1], finite pixels. */
static void fz_gltf(const pgp_map *P, const pgp_tile *tile, pgp_options *o, const pgp_render_options *ro)
{
    pgp_atlas a;
    pgp_error err;
    pgp_result r;
    size_t i, bytes = 0;
    int raw = ro->show == PGP_SHOW_MATERIAL;
    o->atlas.size = 32;
    o->render = *ro;
    r = raw ? pgp_tile_atlas(P, tile, 0.5f, &a, &err) : pgp_bake_atlas(P, tile, o, &a, &err);
    if (r != PGP_OK) {
        fz_pgp_failure(r, &err);
        FZ_CHECK(a.uvs == NULL && a.image.pixels == NULL);
        return;
    }
    FZ_CHECK(a.ntris == P->ntris && a.image.pixels);
    for (i = 0; i < (size_t)6 * a.ntris; i++) FZ_CHECK(fz_finite(a.uvs[i]) && (raw || (a.uvs[i] >= 0.0f && a.uvs[i] <= 1.0f)));
    for (i = 0; i < (size_t)a.image.width * a.image.height * a.image.channels; i++) FZ_CHECK(fz_finite(a.image.pixels[i]));
    r = pgp_write_gltf(P, &a, ro, fz_count, &bytes, &err);
    if (r == PGP_OK) FZ_CHECK(bytes > 0);
    else fz_pgp_failure(r, &err);
    pgp_atlas_free(&a);
}

static void fz_render(const uint8_t *h, const pgp_map *P)
{
    pgp_render_options ro;
    pgp_options o = pgp_default_options();
    pgp_tile tile;
    pgp_image img;
    pgp_error err;
    pgp_result r;
    size_t i;
    memset(&ro, 0, sizeof ro);
    ro.width = 24, ro.height = 18, ro.supersample = 1;
    ro.show = (pgp_show)(h[0] >> 3 & 3);
    ro.fix = (pgp_fix)(h[3] >> 1 & 3);
    if (h[3] & 0x80) ro.zoom = 6.0f; /* a close-up of the origin */
    FZ_CHECK(pgp_builtin_tile(h[3] & 1 ? "stripes" : "bricks", 16, &o, &tile, &err) == PGP_OK);
    r = pgp_render(P, &tile, &ro, &img, &err);
    if (r == PGP_OK) {
        FZ_CHECK(img.width == 24 && img.height == 18 && img.pixels);
        for (i = 0; i < (size_t)24 * 18 * img.channels; i++) FZ_CHECK(fz_finite(img.pixels[i]));
        pgp_image_free(&img);
    } else
        fz_pgp_failure(r, &err);
    if (h[3] & 0x40) fz_gltf(P, &tile, &o, &ro);
    pgp_tile_free(&tile);
}

/* The file's constraints added one by one, up to the first refused. */
static void fz_add_all(pgp_map *P, const pgp_constraints *cons)
{
    pgp_error err;
    pgp_result r = PGP_OK;
    int i;
    for (i = 0; i < cons->count && r == PGP_OK; i++)
        if ((r = pgp_add_constraint(P, &cons->items[i], NULL, NULL, &err)) != PGP_OK) fz_pgp_failure(r, &err);
}

/* The map with the file's constraints (at creation or after, by h[4] bit
 * 7) and one more orientation; prog (may be NULL) cancels pgp_create only. */
static pgp_result fz_map(const uint8_t *h, const pgp_constraints *cons, const pgp_mesh *mesh, pgp_options o,
                         fz_progress *prog, pgp_map *P, pgp_area *area, pgp_error *err)
{
    pgp_constraint c;
    pgp_result r;
    if (h[4] & 128) o.constraints = cons->items, o.nconstraints = cons->count;
    if ((r = pgp_create(mesh, &o, P, err)) != PGP_OK) return r;
    if (prog) prog->cancel_at = 0; /* the edits run to the end */
    if (!(h[4] & 128)) fz_add_all(P, cons);
    memset(&c, 0, sizeof c);
    c.kind = PGP_CONSTRAINT_ORIENT;
    c.element = h[6] % P->ntris;
    c.value[0] = 1.0f, c.value[1] = 0.5f, c.value[2] = 0.25f;
    c.radius = (float)h[7] / 64.0f * fz_diag(mesh);
    r = pgp_add_constraint(P, &c, NULL, area, err);
    if (r != PGP_OK) fz_pgp_failure(r, err);
    return PGP_OK;
}

/* Creates the map, applies the constraints, and checks what comes out. */
static void fz_pipeline(const uint8_t *h, const uint8_t *con, size_t ncon, const pgp_mesh *mesh, fz_heap *heap)
{
    pgp_options o;
    pgp_constraints cons;
    pgp_map P, Q;
    pgp_error err;
    pgp_area area;
    fz_progress prog;
    pgp_result r;
    int i;
    fz_options(h, mesh, &o);
    if (h[0] & 2) {
        o.allocator.malloc_fn = fz_malloc;
        o.allocator.realloc_fn = fz_realloc;
        o.allocator.free_fn = fz_free;
        o.allocator.user = heap;
    }
    memset(&cons, 0, sizeof cons);
    if (ncon && (r = pgp_read_constraints(con, ncon, "fuzz.txt", &o, &cons, &err)) != PGP_OK) {
        fz_pgp_failure(r, &err);
        FZ_CHECK(cons.items == NULL && cons.count == 0);
    }
    memset(&prog, 0, sizeof prog);
    prog.max_calls = 64 * (1 + cons.count);
    prog.cancel_at = h[0] >> 5;
    o.progress = fz_progress_fn;
    o.progress_user = &prog;
    r = fz_map(h, &cons, mesh, o, &prog, &P, &area, &err);
    if (r != PGP_OK) {
        fz_pgp_failure(r, &err);
        FZ_CHECK(P.state == NULL && P.coords == NULL);
        pgp_constraints_free(&cons);
        return;
    }
    for (i = 0; i < area.nfaces; i++) FZ_CHECK(area.faces[i] >= 0 && area.faces[i] < P.ntris);
    pgp_area_free(&area);
    fz_check_map(&P);
    if (h[4] & 8) { /* the same inputs again */
        o.progress = NULL;
        FZ_CHECK(fz_map(h, &cons, mesh, o, NULL, &Q, NULL, &err) == PGP_OK);
        fz_same(&P, &Q);
        pgp_map_free(&Q);
    }
    if (h[0] & 4) fz_render(h, &P);
    if (h[4] & 16) {
        size_t bytes = 0;
        FZ_CHECK(pgp_write_obj(mesh, &P, fz_count, &bytes, &err) == PGP_OK && bytes > 0);
    }
    pgp_map_free(&P);
    pgp_constraints_free(&cons);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    pgp_options lo = pgp_default_options();
    pgp_mesh mesh;
    pgp_error err;
    fz_heap heap;
    size_t ncon;
    if (size < FZ_HEADER) return 0;
    ncon = data[5];
    if (FZ_HEADER + ncon > size) return 0;
    heap.live = 0;
    if (pgp_read_mesh(data + FZ_HEADER + ncon, size - FZ_HEADER - ncon, "fuzz", &lo, &mesh, &err) !=
        PGP_OK) {
        fz_pgp_failure(err.code, &err);
        return 0;
    }
    if (mesh.nfaces > 0 && fz_triangles(&mesh) <= FZ_MAX_TRIS) fz_pipeline(data, data + FZ_HEADER, ncon, &mesh, &heap);
    pgp_mesh_free(&mesh);
    FZ_CHECK(heap.live == 0);
    return 0;
}
