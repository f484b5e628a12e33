/* fuzz_lst: lst.h's readers and its pipeline on whatever they accept.
 *
 * Each input is used three ways:
 *   1. as a model file: a model that reads is written back and read again,
 *      byte for byte the same file;
 *   2. as a constraint file: constraints that read steer a fill of a small built-in mesh (type, seed, mask size and
 *      a cut plane from the input's first bytes), which must succeed or fail
 *      with a known code and a message; a model that fills is covered (its
 *      composite opacity at every sample point of every tetrahedron at least
 *      0.98), is cut by the plane, renders a tiny image, and bakes a
 *      64x64 atlas of what is left, written as glTF to memory;
 *   3. its first bytes as the options of a fill with no constraints.
 * Every failure must carry a code and a message and leave no model. Fills
 * run on fuzz.h's counting allocator (leaks and frees through the wrong
 * allocator abort) and sometimes with a progress callback that cancels.
 *
 * Build: clang -g -O1 -fsanitize=fuzzer,address,undefined -I. fuzz/fuzz_lst.c -lm */
#define FZ_NAME "fuzz_lst"
#include "fuzz.h"
#define LST_STATIC /* static: only what the target calls is compiled */
#define LST_IMPLEMENTATION
#include "../lst.h"

static lst_tetmesh fz_mesh;
static lst_volume fz_ex;

static void fz_check_err(lst_result r, const lst_error *e) { fz_check_failure((int)r, (int)e->code, e->message, sizeof e->message); }

static void fz_setup(void)
{
    lst_options o = lst_default_options();
    lst_mesh s;
    lst_error e;
    if (fz_mesh.tets) return;
    o.tet.target_tets = 60, o.tet.uniform = 1; /* a small mesh: this target is about model files */
    FZ_CHECK(!lst_builtin_mesh("sphere", &o, &s, &e) && !lst_tetrahedralize(&s, &o, &fz_mesh, NULL, &e) &&
             !lst_builtin_exemplar("rings", 8, &o, &fz_ex, NULL, &e));
    lst_mesh_free(&s);
}

static void fz_model_file(const uint8_t *d, size_t n)
{
    lst_model m, b;
    lst_error e;
    pw_buf x, y;
    lst_result r = lst_read_model(d, n, "fuzz.lst", NULL, &m, &e);
    if (r != LST_OK) {
        fz_check_err(r, &e);
        FZ_CHECK(!m.mesh.tets && !m.pastes);
        return;
    }
    memset(&x, 0, sizeof x), memset(&y, 0, sizeof y);
    FZ_CHECK(!lst_write_model(&m, pw_buf_write, &x, &e));
    FZ_CHECK(!lst_read_model(x.data, x.size, "again", NULL, &b, &e));
    FZ_CHECK(!lst_write_model(&b, pw_buf_write, &y, &e));
    FZ_CHECK(x.size == y.size && !memcmp(x.data, y.data, x.size));
    free(x.data), free(y.data);
    lst_model_free(&m), lst_model_free(&b);
}

/* A small atlas of what is left after the cut, written as glTF to memory:
 * it succeeds or fails with a code and a message, leaving nothing. */
static void fz_atlas(const lst_model *m, const lst_options *opt)
{
    lst_options o = *opt;
    lst_atlas at;
    lst_error e;
    lst_result r;
    pw_buf x;
    o.atlas.size = 64;
    o.progress = NULL;
    r = lst_bake_atlas(m, &o, &at, &e);
    if (r != LST_OK) {
        fz_check_err(r, &e);
        FZ_CHECK(!at.positions && !at.tris && !at.uvs && !at.image.pixels);
        return;
    }
    memset(&x, 0, sizeof x);
    r = lst_write_gltf(&at, &o.render, pw_buf_write, &x, &e);
    if (r != LST_OK) fz_check_err(r, &e);
    else FZ_CHECK(x.size > 28 && !memcmp(x.data, "glTF", 4));
    free(x.data);
    lst_atlas_free(&at);
}

/* A fill with options from the first bytes; the model's checks. */
static void fz_fill(const uint8_t *d, size_t n, const lst_constraint *c, int nc)
{
    lst_options o = lst_default_options();
    lst_render_options ro;
    lst_source src;
    lst_model m;
    lst_image img;
    lst_error e;
    lst_result r;
    fz_heap heap = {0};
    fz_progress prog = {0, 0, 1 << 30};
    float plane[4] = {0, 0, 1, 0};
    int t, k;
    o.allocator.malloc_fn = fz_malloc, o.allocator.realloc_fn = fz_realloc, o.allocator.free_fn = fz_free;
    o.allocator.user = &heap;
    if (n > 7 && d[7] < 16) o.progress = fz_progress_fn, o.progress_user = &prog, prog.cancel_at = 1 + d[7];
    o.type = (lst_type)(n > 0 ? d[0] % 5 : 0);
    o.seed = n > 1 ? d[1] : 0;
    o.samples = 1 + (n > 2 ? d[2] % 3 : 0);
    o.scale = 0.8f + (n > 3 ? d[3] % 8 : 0) * 0.2f;
    o.constraints = c, o.nconstraints = nc;
    o.max_pastes = 3000;
    if (n > 6) plane[0] = (d[4] - 128) / 64.0f, plane[1] = (d[5] - 128) / 64.0f, plane[3] = (d[6] - 128) / 256.0f;
    src.exemplar = &fz_ex, src.values = NULL;
    r = lst_create(&fz_mesh, NULL, &src, &o, &m, &e);
    if (r != LST_OK) {
        fz_check_err(r, &e);
        FZ_CHECK(!m.mesh.tets && !m.pastes && heap.live == 0);
        return;
    }
    {
        pw_alloc a;
        lst__view v;
        pw_err pe;
        float *lat = NULL, rgba[4];
        int q, ns, grp[9];
        memset(&a, 0, sizeof a);
        pw_err_clear(&pe);
        FZ_CHECK(!lst__view_init(&a, &m, LST_SHOW_COLOR, &v, &pe) && (ns = lst__lattice(&a, o.samples, &lat, grp, &pe)) >= 0);
        for (t = 0; t < m.mesh.ntets; t++)
            for (q = 0; q < ns; q++) {
                double l[4];
                for (k = 0; k < 4; k++) l[k] = lat[4 * q + k];
                lst__eval(&v, t, l, rgba, NULL);
                FZ_CHECK(rgba[3] >= 0.98f);
            }
        pw_free(&a, lat);
        lst__view_free(&v);
    }
    r = lst_cut_plane(&m, plane, &e);
    if (r != LST_OK) fz_check_err(r, &e);
    memset(&ro, 0, sizeof ro);
    ro.width = 16, ro.height = 12, ro.supersample = 1;
    r = lst_render(&m, &ro, &img, &e);
    if (r == LST_OK) lst_image_free(&img);
    else fz_check_err(r, &e);
    fz_atlas(&m, &o);
    lst_model_free(&m);
    FZ_CHECK(heap.live == 0);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    lst_constraints c;
    lst_error e;
    lst_result r;
    fz_setup();
    fz_model_file(data, size);
    r = lst_read_constraints(data, size, "fuzz.constraints", NULL, &c, &e);
    if (r != LST_OK) {
        fz_check_err(r, &e);
        FZ_CHECK(!c.items && !c.count);
    } else
        fz_fill(data, size, c.items, c.count);
    if (size < 16) fz_fill(data, size, NULL, 0);
    lst_constraints_free(&c);
    return 0;
}
