/* fuzz_pgp: pgp.h's mapping on fuzzed input. An 8-byte header picks the
 * options, then h[5] bytes of constraints file (the CLI's text format,
 * applied line by line), then a mesh (OBJ, OFF or PLY, at most FZ_MAX_TRIS
 * triangles after triangulation).
 *
 *   h[0]  bit 0 field (0 up, 1 curvature), bit 1 counting allocator,
 *         bit 2 render (tile, or material / singular view by bits 3-4),
 *         bits 5-7 the progress call that cancels (0: none)
 *   h[1]  scale: 0 the default, else h[1] / 64 of the bounding-box diagonal
 *   h[2]  default material h[2] / 255; h[3] smoothing sweeps (curvature)
 *   h[4]  bits 0-2 the up direction (axes, one diagonal), bit 3 make the
 *         map twice (the same inputs give the same coordinates), bit 4
 *         write the OBJ, bits 5-6 singular_distortion (default, 0.1, 2, 10)
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
    o->field = h[0] & 1;
    o->scale = h[1] ? (float)h[1] / 64.0f * fz_diag(m) : 0.0f;
    o->material = (float)h[2] / 255.0f;
    o->smoothing = h[3] & 31;
    memcpy(o->up, up[h[4] & 7], sizeof o->up);
    o->singular_distortion = dist[h[4] >> 5 & 3];
    o->weights = h[3] >> 5 & 1;                    /* cotangent or the paper's area weights */
    o->integrable = (h[3] >> 6 & 1) ? 1.0f : 0.0f; /* --field smooth */
}

/* A made map is consistent. */
static void fz_check_map(const pgp_map *P)
{
    int nf = pgp_triangle_count(P), nv = pgp_vertex_count(P), i, k;
    float *stm = (float *)malloc(sizeof(float) * 9 * (size_t)nf + 1);
    float *ds = (float *)malloc(sizeof(float) * 3 * (size_t)nf + 1);
    float *sc = (float *)malloc(sizeof(float) * (size_t)nv + 1), *mat = (float *)malloc(sizeof(float) * (size_t)nv + 1);
    FZ_CHECK(stm && ds && sc && mat);
    pgp_get_coords(P, stm);
    pgp_get_field(P, ds, sc, mat);
    for (i = 0; i < 9 * nf; i++) FZ_CHECK(fz_finite(stm[i]));
    for (i = 0; i < nf; i++) {
        float l = ds[3 * i] * ds[3 * i] + ds[3 * i + 1] * ds[3 * i + 1] + ds[3 * i + 2] * ds[3 * i + 2];
        FZ_CHECK(l > 0.99f && l < 1.01f);
        for (k = 0; k < 3; k++) FZ_CHECK(stm[9 * i + 3 * k + 2] >= 0.0f && stm[9 * i + 3 * k + 2] <= 1.0f);
    }
    for (i = 0; i < nv; i++) FZ_CHECK(fz_finite(sc[i]) && sc[i] > 0.0f && mat[i] >= 0.0f && mat[i] <= 1.0f);
    k = pgp_get_singular(P, NULL);
    FZ_CHECK(k >= 0 && k <= nf);
    { /* issue 17: the report is finite, the clean fix treats exactly the vortices */
        pgp_stats st;
        pgp_get_stats(P, &st);
        FZ_CHECK(st.triangles == nf && st.singular == k && st.stretched >= 0.0f && st.stretched <= 1.0f &&
                 st.sheared >= 0.0f && st.sheared <= 1.0f && fz_finite(st.mean_edge) && st.scale > 0.0f);
        FZ_CHECK(pgp_get_special(P, PGP_FIX_CLEAN, NULL) == pgp_get_vortices(P, NULL));
        FZ_CHECK(pgp_get_special(P, PGP_FIX_PAPER, NULL) == k && pgp_get_special(P, PGP_FIX_OFF, NULL) == 0);
    }
    {
        unsigned char *vort = (unsigned char *)malloc((size_t)nf + 1);
        int nvort = 0;
        FZ_CHECK(vort != NULL);
        k = pgp_get_vortices(P, vort);
        for (i = 0; i < nf; i++) {
            FZ_CHECK(vort[i] <= 3);
            nvort += vort[i] != 0;
        }
        FZ_CHECK(k == nvort);
        free(vort);
    }
    free(stm);
    free(ds);
    free(sc);
    free(mat);
}

static void fz_same(const pgp_map *a, const pgp_map *b)
{
    int nf = pgp_triangle_count(a);
    float *x = (float *)malloc(sizeof(float) * 9 * (size_t)nf + 1), *y = (float *)malloc(sizeof(float) * 9 * (size_t)nf + 1);
    FZ_CHECK(x && y && nf == pgp_triangle_count(b));
    pgp_get_coords(a, x);
    pgp_get_coords(b, y);
    FZ_CHECK(memcmp(x, y, sizeof(float) * 9 * (size_t)nf) == 0);
    FZ_CHECK(pgp_get_singular(a, NULL) == pgp_get_singular(b, NULL));
    FZ_CHECK(pgp_get_vortices(a, NULL) == pgp_get_vortices(b, NULL));
    free(x);
    free(y);
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
    ro.show = h[0] >> 3 & 3;
    ro.fix = h[3] >> 1 & 3;
    if (h[3] & 0x80) ro.zoom = 6.0f; /* a close-up of the origin */
    FZ_CHECK(pgp_builtin_tile(h[3] & 1 ? "stripes" : "bricks", 16, &o, &tile, &err) == PGP_OK);
    r = pgp_render(P, &tile, &ro, &img, &err);
    if (r == PGP_OK) {
        FZ_CHECK(img.width == 24 && img.height == 18 && img.pixels);
        for (i = 0; i < (size_t)24 * 18 * img.channels; i++) FZ_CHECK(fz_finite(img.pixels[i]));
        pgp_image_free(&img);
    } else
        fz_pgp_failure(r, &err);
    pgp_tile_free(&tile);
}

/* Creates the map, applies the constraints, and checks what comes out. */
static void fz_pipeline(const uint8_t *h, const uint8_t *con, size_t ncon, const pgp_mesh *mesh, fz_heap *heap)
{
    pgp_options o;
    pgp_map *P = NULL, *Q = NULL;
    pgp_error err;
    pgp_area area;
    fz_progress prog;
    pgp_result r;
    float dir[3] = {1.0f, 0.5f, 0.25f};
    fz_options(h, mesh, &o);
    if (h[0] & 2) {
        o.allocator.malloc_fn = fz_malloc;
        o.allocator.realloc_fn = fz_realloc;
        o.allocator.free_fn = fz_free;
        o.allocator.user = heap;
    }
    memset(&prog, 0, sizeof prog);
    prog.max_calls = 64;
    prog.cancel_at = h[0] >> 5;
    o.progress = fz_progress_fn;
    o.progress_user = &prog;
    r = pgp_create(mesh, &o, &P, &err);
    if (r != PGP_OK) {
        fz_pgp_failure(r, &err);
        FZ_CHECK(P == NULL);
        return;
    }
    prog.cancel_at = 0; /* the edits run to the end */
    if (ncon && (r = pgp_apply_constraints_from_memory(P, con, ncon, "fuzz.txt", &err)) != PGP_OK) fz_pgp_failure(r, &err);
    r = pgp_add_orientation(P, h[6] % pgp_triangle_count(P), dir, (float)h[7] / 64.0f * fz_diag(mesh), NULL, &area, &err);
    if (r == PGP_OK) {
        int i;
        for (i = 0; i < area.nfaces; i++) FZ_CHECK(area.faces[i] >= 0 && area.faces[i] < pgp_triangle_count(P));
        pgp_area_free(&area);
    } else
        fz_pgp_failure(r, &err);
    fz_check_map(P);
    if (h[4] & 8) { /* the same inputs again */
        FZ_CHECK(pgp_create(mesh, &o, &Q, &err) == PGP_OK);
        if (ncon) pgp_apply_constraints_from_memory(Q, con, ncon, "fuzz.txt", &err);
        pgp_add_orientation(Q, h[6] % pgp_triangle_count(Q), dir, (float)h[7] / 64.0f * fz_diag(mesh), NULL, NULL, &err);
        fz_same(P, Q);
        pgp_destroy(Q);
    }
    if (h[0] & 4) fz_render(h, P);
    if (h[4] & 16) {
        size_t bytes = 0;
        FZ_CHECK(pgp_write_obj_to_func(mesh, P, fz_count, &bytes, &err) == PGP_OK && bytes > 0);
    }
    pgp_destroy(P);
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
    if (pgp_load_mesh_from_memory(data + FZ_HEADER + ncon, size - FZ_HEADER - ncon, "fuzz", &lo, &mesh, &err) !=
        PGP_OK) {
        fz_pgp_failure(err.code, &err);
        return 0;
    }
    if (mesh.nfaces > 0 && fz_triangles(&mesh) <= FZ_MAX_TRIS) fz_pipeline(data, data + FZ_HEADER, ncon, &mesh, &heap);
    pgp_mesh_free(&mesh);
    FZ_CHECK(heap.live == 0);
    return 0;
}
