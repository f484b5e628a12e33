/* fuzz_lapped_files: lapped.h's paste and constraint file readers. The first
 * byte picks the reader (bit 0) and a few options; the rest is the file.
 * Besides crashes it checks properties, aborting when one fails:
 *   - a failure carries its code and a message, and hands nothing out;
 *   - a paste set that is read is well formed (ntris 0, patch sizes in
 *     range, patch indices below npatches, triangle indices >= 0, finite
 *     coordinates) and round-trips exactly: written with
 *     lapped_write_pastes (9 significant digits, enough for a
 *     float) and read back it gives the same counts and bit-identical
 *     values, and writing that again gives the same bytes;
 *   - a small paste set is then drawn (lapped_render) and, when bit 7 is
 *     set, baked (lapped_bake_atlas) over a fixed octahedron with patches of the sizes
 *     it names: both either succeed with finite output or fail cleanly;
 *   - constraints that are read are finite, with faces in range, and the
 *     CONSTRAINTS field over the octahedron either fails cleanly or is
 *     finite with t != 0; a success says nothing, or warns that positional
 *     lines are deprecated;
 *   - with the counting allocator (bit 1), every block is freed through the
 *     allocator that made it and none is left over.
 * (Two bugs it found are fixed and have regression tests: constraint
 * values finite as doubles but not as floats, "0 1e39 0 0", were accepted;
 * lapped_render overran a scratch buffer for patches 1 texel wide.) */
#define LAPPED_STATIC /* static: only what the target calls is compiled */
#define LAPPED_IMPLEMENTATION
#include "../lapped.h"
#define FZ_NAME "fuzz_lapped_files"
#include "fuzz.h"

#define fz_lapped_failure(r, err) fz_check_failure((int)(r), (int)(err)->code, (err)->message, sizeof (err)->message)

/* ---- a fixed mesh: the octahedron, 8 triangles --------------------------------- */

static float fz_oct_pos[18] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
static int fz_oct_start[9] = {0, 3, 6, 9, 12, 15, 18, 21, 24};
static int fz_oct_verts[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};

static lapped_mesh fz_octahedron(void)
{
    lapped_mesh m;
    memset(&m, 0, sizeof m);
    m.nverts = 6;
    m.positions = fz_oct_pos;
    m.nfaces = 8;
    m.face_start = fz_oct_start;
    m.face_verts = fz_oct_verts;
    return m;
}


/* ---- pastes ----------------------------------------------------------------------- */

static void fz_check_texture(const lapped_texture *t)
{
    int p, i;
    FZ_CHECK(t->ntris == 0);
    FZ_CHECK(t->npatches >= 1 && t->patch_size);
    for (p = 0; p < t->npatches; p++)
        FZ_CHECK(t->patch_size[2 * p] >= 1 && t->patch_size[2 * p + 1] >= 1 &&
                 t->patch_size[2 * p] <= 65536 && t->patch_size[2 * p + 1] <= 65536);
    FZ_CHECK(t->npastes >= 0 && (t->npastes == 0 || t->pastes));
    for (p = 0; p < t->npastes; p++) {
        const lapped_paste *q = &t->pastes[p];
        FZ_CHECK(q->patch >= 0 && q->patch < t->npatches);
        FZ_CHECK(q->nfaces >= 0 && (q->nfaces == 0 || (q->faces && q->uvs)));
        for (i = 0; i < q->nfaces; i++) FZ_CHECK(q->faces[i] >= 0);
        for (i = 0; i < 6 * q->nfaces; i++) FZ_CHECK(fz_finite(q->uvs[i]));
    }
}

static void fz_same_texture(const lapped_texture *a, const lapped_texture *b)
{
    int p;
    FZ_CHECK(a->ntris == b->ntris && a->npatches == b->npatches && a->npastes == b->npastes);
    FZ_CHECK(!memcmp(a->patch_size, b->patch_size, (size_t)a->npatches * 2 * sizeof(int)));
    for (p = 0; p < a->npastes; p++) {
        const lapped_paste *x = &a->pastes[p], *y = &b->pastes[p];
        FZ_CHECK(x->patch == y->patch && x->nfaces == y->nfaces);
        if (x->nfaces == 0) continue;
        FZ_CHECK(!memcmp(x->faces, y->faces, (size_t)x->nfaces * sizeof(int)));
        FZ_CHECK(!memcmp(x->uvs, y->uvs, (size_t)x->nfaces * 6 * sizeof(float))); /* bits, -0 too */
    }
}

/* Write, read back, compare; write again, compare the bytes. */
static void fz_roundtrip(const lapped_texture *t, const lapped_options *o)
{
    fz_buf b1, b2;
    lapped_texture r;
    lapped_error err;
    memset(&b1, 0, sizeof b1);
    memset(&b2, 0, sizeof b2);
    FZ_CHECK(lapped_write_pastes(t, fz_append, &b1, &err) == LAPPED_OK);
    if (lapped_read_pastes(b1.data, b1.size, "roundtrip", o, &r, &err) != LAPPED_OK) {
        fprintf(stderr, "fuzz_lapped_files: re-reading a written paste file failed: %s\n", err.message);
        abort();
    }
    fz_check_texture(&r);
    fz_same_texture(t, &r);
    FZ_CHECK(lapped_write_pastes(&r, fz_append, &b2, &err) == LAPPED_OK);
    FZ_CHECK(b1.size == b2.size && !memcmp(b1.data, b2.data, b1.size));
    lapped_texture_free(&r);
    free(b1.data);
    free(b2.data);
}

/* An RGBA patch of w x h: a colour ramp, opaque inside a transparent border. */
static int fz_make_patch(int w, int h, int k, lapped_image *img)
{
    int x, y;
    memset(img, 0, sizeof *img);
    img->width = w;
    img->height = h;
    img->channels = 4;
    if (!(img->pixels = (float *)malloc((size_t)w * h * 4 * sizeof(float)))) return 0;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            float *p = img->pixels + ((size_t)y * w + x) * 4;
            p[0] = (float)x / (float)w;
            p[1] = (float)y / (float)h;
            p[2] = (float)(k % 3) * 0.5f;
            p[3] = x > 0 && y > 0 && x < w - 1 && y < h - 1 ? 1.0f : 0.0f;
        }
    return 1;
}

/* Bakes an atlas (the slow part, so only when bit 7 is set). Baking needs
 * the triangle count, which a paste file does not record. */
static void fz_bake(lapped_texture *t, const lapped_mesh *mesh, const lapped_source *src, unsigned flags,
                    const lapped_options *o)
{
    lapped_options bo = *o;
    lapped_atlas atlas;
    lapped_error err;
    lapped_result r;
    size_t i, discarded = 0;
    t->ntris = mesh->nfaces;
    bo.atlas.size = 32;
    bo.atlas.gutter = 1 + (int)(flags >> 5 & 1);
    r = lapped_bake_atlas(mesh, t, src, &bo, &atlas, &err);
    if (r == LAPPED_OK) {
        FZ_CHECK(atlas.ntris == mesh->nfaces && atlas.uvs && atlas.image.pixels);
        FZ_CHECK(atlas.image.width == 32 && atlas.image.height == 32);
        for (i = 0; i < (size_t)atlas.ntris * 6; i++)
            FZ_CHECK(fz_finite(atlas.uvs[i]) && atlas.uvs[i] >= 0.0f && atlas.uvs[i] <= 1.0f);
        for (i = 0; i < (size_t)32 * 32 * atlas.image.channels; i++) FZ_CHECK(fz_finite(atlas.image.pixels[i]));
        FZ_CHECK(lapped_write_obj(mesh, &atlas, "x.mtl", fz_count, &discarded, &err) == LAPPED_OK);
        lapped_atlas_free(&atlas);
    } else {
        fz_lapped_failure(r, &err);
        FZ_CHECK(atlas.uvs == NULL && atlas.image.pixels == NULL);
    }
    t->ntris = 0;
}

/* Draws (and with bit 7 bakes) a small paste set over the octahedron. */
static void fz_use_texture(lapped_texture *t, unsigned flags, const lapped_options *o)
{
    lapped_image patches[8], values[8], pic;
    lapped_source src;
    lapped_render_options ro;
    lapped_mesh mesh = fz_octahedron();
    lapped_error err;
    lapped_result r;
    long total = 0;
    int k, n = t->npatches, ok = 1, use_values = flags >> 4 & 1;
    size_t i;
    if (n > 8) return;
    for (k = 0; k < n; k++) {
        if (t->patch_size[2 * k] > 32 || t->patch_size[2 * k + 1] > 32) return;
    }
    for (k = 0; k < t->npastes; k++) total += t->pastes[k].nfaces;
    if (total > 4096) return;
    memset(patches, 0, sizeof patches);
    memset(values, 0, sizeof values);
    for (k = 0; k < n && ok; k++) {
        ok = fz_make_patch(t->patch_size[2 * k], t->patch_size[2 * k + 1], k, &patches[k]);
        if (ok && use_values) { /* a one-channel value image per patch */
            values[k] = patches[k];
            values[k].channels = 1;
            values[k].pixels = (float *)malloc((size_t)values[k].width * values[k].height * sizeof(float));
            ok = values[k].pixels != NULL;
            for (i = 0; ok && i < (size_t)values[k].width * values[k].height; i++)
                values[k].pixels[i] = (float)(i % 7) / 6.0f;
        }
    }
    if (ok) {
        memset(&ro, 0, sizeof ro);
        ro.width = 16 + (int)(flags >> 5 & 1) * 16;
        ro.height = 12;
        ro.supersample = 1 + (int)(flags >> 6 & 1);
        ro.filter = (lapped_filter)((int)(flags >> 2 & 3) % 3);
        src.patches = patches, src.npatches = n, src.values = use_values ? values : NULL;
        r = lapped_render(&mesh, t, &src, &ro, &pic, &err);
        if (r == LAPPED_OK) {
            FZ_CHECK(pic.width == ro.width && pic.height == ro.height && pic.pixels);
            for (i = 0; i < (size_t)pic.width * pic.height * pic.channels; i++) FZ_CHECK(fz_finite(pic.pixels[i]));
            lapped_image_free(&pic);
        } else {
            fz_lapped_failure(r, &err);
            FZ_CHECK(pic.pixels == NULL);
        }
        if (flags & 128) fz_bake(t, &mesh, &src, flags, o);
    }
    for (k = 0; k < n; k++) {
        free(patches[k].pixels);
        free(values[k].pixels);
    }
}

static void fz_pastes(const uint8_t *data, size_t size, unsigned flags, const lapped_options *o)
{
    lapped_texture t;
    lapped_error err;
    lapped_result r = lapped_read_pastes(data, size, "fuzz", o, &t, &err);
    if (r != LAPPED_OK) {
        fz_lapped_failure(r, &err);
        FZ_CHECK(t.pastes == NULL && t.patch_size == NULL && t.npastes == 0 && t.npatches == 0);
        return;
    }
    fz_check_texture(&t);
    fz_roundtrip(&t, o);
    fz_use_texture(&t, flags, o);
    lapped_texture_free(&t);
    FZ_CHECK(t.pastes == NULL && t.npastes == 0);
}

/* ---- constraints ------------------------------------------------------------------ */

static void fz_constraints(const uint8_t *data, size_t size, unsigned flags, const lapped_options *o)
{
    lapped_constraints cs;
    lapped_constraint *c;
    lapped_options fo = *o;
    lapped_mesh mesh = fz_octahedron();
    lapped_field f;
    lapped_error err;
    lapped_result r;
    int n, i, k;
    memset(&cs, 0xff, sizeof cs);
    r = lapped_read_constraints(data, size, "fuzz", o, &cs, &err);
    if (r != LAPPED_OK) {
        fz_lapped_failure(r, &err);
        FZ_CHECK(cs.items == NULL && cs.count == 0);
        return;
    }
    c = cs.items, n = cs.count;
    FZ_CHECK(c != NULL && n >= 1);
    FZ_CHECK(!err.message[0] || strstr(err.message, ": positional constraint lines are deprecated; write 'orient"));
    for (i = 0; i < n; i++) {
        FZ_CHECK(c[i].face >= 0);
        for (k = 0; k < 3; k++) FZ_CHECK(fz_finite(c[i].direction[k]));
        FZ_CHECK(fz_finite(c[i].scale) && fz_finite(c[i].radius) && fz_finite(c[i].weight));
    }
    if (n <= 256) { /* the field over the octahedron: O(n) Dijkstra runs */
        fo.field = LAPPED_FIELD_CONSTRAINTS;
        fo.constraints = c;
        fo.nconstraints = n;
        fo.scale = flags >> 2 & 1 ? 0.5f : 0.0f;
        r = lapped_compute_field(&mesh, &fo, &f, &err);
        if (r == LAPPED_OK) {
            FZ_CHECK(f.ntris == 8);
            for (i = 0; i < 8; i++) { /* |t| may be tiny (a scale of 1e-30), never 0 */
                for (k = 0; k < 3; k++) FZ_CHECK(fz_finite(f.s[3 * i + k]) && fz_finite(f.t[3 * i + k]));
                FZ_CHECK(f.t[3 * i] != 0.0f || f.t[3 * i + 1] != 0.0f || f.t[3 * i + 2] != 0.0f);
            }
            lapped_field_free(&f);
        } else {
            fz_lapped_failure(r, &err);
        }
    }
    lapped_constraints_free(&cs);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    lapped_options o = lapped_default_options();
    fz_heap heap;
    unsigned flags;
    if (size < 1) return 0;
    flags = data[0];
    heap.live = 0;
    if (flags & 2) {
        o.allocator.malloc_fn = fz_malloc;
        o.allocator.realloc_fn = fz_realloc;
        o.allocator.free_fn = fz_free;
        o.allocator.user = &heap;
    }
    if (flags & 1) fz_constraints(data + 1, size - 1, flags, &o);
    else fz_pastes(data + 1, size - 1, flags, &o);
    FZ_CHECK(heap.live == 0);
    return 0;
}
