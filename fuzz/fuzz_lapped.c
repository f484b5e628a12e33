/* fuzz_lapped: the whole lapped.h pipeline on fuzzed input. A 12-byte
 * header picks the options, the tangent field, the texture and what is
 * done with the result; in CONSTRAINTS mode 6 bytes per constraint follow;
 * the rest is a mesh (OBJ, OFF or PLY, at most FZ_MAX_TRIS triangles).
 *
 *   h[0]  bits 0-2 field mode (5: isotropic, 6: up, 7: an invalid mode),
 *         bit 3 lscm, bit 4 keep_hidden, bit 5 counting allocator,
 *         bit 6 a second patch (built-in dots in a circle), bit 7 bake
 *   h[1]  scale: 0 the default, 255 the raw float in h[4..7], else
 *         h[1]/64 of the mesh's bounding-box diagonal
 *   h[2]  bits 0-2 alpha mode (5-7: AUTO), bits 3-4 render filter,
 *         bit 5 supersample 2, bits 6-7 falloff (default, 1, 6, 0.5 px)
 *   h[3]  bits 0-1 texture (scales, stripes, dots, from the seed's bits),
 *         bits 2-3 its channels - 1, bits 4-6 its size 8..22,
 *         bit 7 a mask image (used by alpha mode MASK)
 *   h[4..7] seed (and the raw scale)
 *   h[8]  bits 0-1 coverage, 2-3 max_distortion, 4-5 early, 6-7 up
 *   h[9]  bits 0-1 atlas size (16..40), 2-3 gutter, 4-5 cone angle,
 *         bit 6 values image, bit 7 FACES: a given s field
 *   h[10] bits 0-1 constraints - 1, bits 2-4 curvature smoothing,
 *         bits 5-7 the progress call that cancels (0: none)
 *   h[11] bit 0 FACES: one bad frame, bits 1-5 max_pastes - 1, bit 6 make
 *         the lapped texture twice (the same inputs give the same result)
 *
 * Work is bounded: at most FZ_MAX_TRIS triangles, max_pastes <= 32, and
 * the progress callback cancels after FZ_MAX_CALLS reports (pasting
 * reports every 16 pastes, the atlas once per chart). Any result is fine;
 * crashes, leaks, sanitizer reports and the following are not:
 *   - a failure carries its code and a message and hands nothing out;
 *   - a lapped texture that is made is consistent: ntris, patch sizes,
 *     patch and triangle indices in range, finite coordinates, every
 *     triangle in some paste, at most max_pastes pastes; its paste file
 *     reads back; made again from the same inputs it is bit-identical;
 *   - the area guarantee (docs/lapped.md): every paste's texture area is
 *     within [1/d^2, d^2] (d = max_distortion) of the surface it covers
 *     over S^2 (up to LAPPED__AREA_SLACK per triangle and 0.1% of
 *     rounding), degenerate triangles included;
 *   - renders and atlases have the requested sizes and finite pixels, atlas
 *     coordinates lie in [0, 1];
 *   - with the counting allocator, every block goes back to the allocator
 *     that made it and none is left over. */
#define LAPPED_STATIC /* static: only what the target calls is compiled */
#define LAPPED_IMPLEMENTATION
#include "../lapped.h"
#define FZ_NAME "fuzz_lapped"
#include "fuzz.h"

#define FZ_MAX_TRIS 300
#define FZ_MAX_VERTS 1000
#define FZ_MAX_CALLS 128
#define FZ_HEADER 12

/* -DFZ_VERBOSE prints what each stage returned (to check seeds). */
#ifdef FZ_VERBOSE
#define FZ_LOG(what, r, err) fprintf(stderr, "  %s: %s%s%s\n", what, lapped_result_string(r), r ? ": " : "", r ? (err)->message : "")
#else
#define FZ_LOG(what, r, err) ((void)0)
#endif

/* lapped's result type through the shared check. */
#define fz_lapped_failure(r, err) fz_check_failure((int)(r), (int)(err)->code, (err)->message, sizeof (err)->message)

/* ---- the inputs ------------------------------------------------------------------------- */

typedef struct fz_input {
    const uint8_t *h;        /* FZ_HEADER bytes */
    const uint8_t *con;      /* 6 bytes per constraint, or NULL */
    int ncon;
    const uint8_t *mesh;
    size_t mesh_size;
    uint64_t seed;
} fz_input;

static float fz_diag(const lapped_mesh *m)
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
    return d > 0.0f ? sqrtf(d) : 1.0f;
}

/* The texture (kind 3: channels, height and pixels from the seed, values a
 * little outside [0, 1] and alpha sometimes all zero) and the optional
 * mask. */
static int fz_texture(const fz_input *in, const lapped_options *o, lapped_image *tex, lapped_image *mask)
{
    static const char *const names[3] = {"scales", "stripes", "dots"};
    int kind = in->h[3] & 3, c = 1 + (in->h[3] >> 2 & 3), size = 8 + 2 * (in->h[3] >> 4 & 7);
    uint64_t s = in->seed;
    size_t i, n;
    lapped_error err;
    memset(tex, 0, sizeof *tex);
    memset(mask, 0, sizeof *mask);
    if (kind < 3) {
        lapped_result r = lapped_builtin_exemplar(names[kind], size, o, tex, &err);
        FZ_CHECK(r == LAPPED_OK && tex->width == size && tex->height == size && tex->pixels);
    } else {
        int empty_alpha = (in->seed & 15) == 0;
        tex->width = size;
        tex->height = 8 + 2 * (int)(in->seed >> 12 & 7);
        tex->channels = c;
        n = (size_t)tex->width * tex->height;
        if (!(tex->pixels = (float *)malloc(n * c * sizeof(float)))) return 0;
        for (i = 0; i < n * c; i++) {
            float v = 1.2f * fz_unit(&s) - 0.1f;
            if ((c == 2 || c == 4) && i % c == (size_t)c - 1) v = empty_alpha ? 0.0f : (v > 0.3f ? 1.0f : v);
            tex->pixels[i] = v;
        }
    }
    if (in->h[3] & 128) {
        n = (size_t)tex->width * tex->height;
        mask->width = tex->width;
        mask->height = tex->height;
        mask->channels = 1 + (int)(in->seed >> 8 & 1);
        if (!(mask->pixels = (float *)malloc(n * mask->channels * sizeof(float)))) return 0;
        for (i = 0; i < n * mask->channels; i++) mask->pixels[i] = fz_unit(&s) < 0.8f ? 1.0f : 0.0f;
    }
    return 1;
}

static void fz_image_free(lapped_image *img, int ours)
{
    if (ours) free(img->pixels);
    else lapped_image_free(img);
    memset(img, 0, sizeof *img);
}

/* The options from h[0], h[1], h[2], h[8], h[10], h[11]. */
static void fz_options(const fz_input *in, float diag, lapped_options *o)
{
    static const float coverage[4] = {0.0f, 0.5f, 0.9f, 1.0f}, distortion[4] = {0.0f, 1.1f, 4.0f, 100.0f};
    static const float early[4] = {0.0f, 0.01f, 0.5f, 1.0f}, falloff[4] = {0.0f, 1.0f, 6.0f, 0.5f};
    static const float up[4][3] = {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}, {0.3f, 0.9f, -0.2f}};
    const uint8_t *h = in->h;
    int mode = h[0] & 7;
    *o = lapped_default_options();
    o->field = (lapped_field_mode)(mode == 5 ? LAPPED_FIELD_ISOTROPIC : mode == 6 ? LAPPED_FIELD_UP : mode == 7 ? 17 : mode);
    o->lscm = h[0] >> 3 & 1;
    o->keep_hidden = h[0] >> 4 & 1;
    if (h[1] == 255) memcpy(&o->scale, h + 4, 4);
    else o->scale = h[1] ? diag * (float)h[1] / 64.0f : 0.0f;
    o->alpha = (lapped_alpha)((h[2] & 7) <= 4 ? h[2] & 7 : LAPPED_ALPHA_AUTO);
    o->falloff = falloff[h[2] >> 6];
    o->coverage = coverage[h[8] & 3];
    o->max_distortion = distortion[h[8] >> 2 & 3];
    o->early = early[h[8] >> 4 & 3];
    memcpy(o->up, up[h[8] >> 6], sizeof o->up);
    o->smoothing = h[10] >> 2 & 7; /* 0: the default, 20 */
    o->max_pastes = 1 + (h[11] >> 1 & 31);
    o->seed = in->seed;
}

/* CONSTRAINTS: face (one past the end now and then), direction, scale and
 * radius from 6 bytes each. */
static void fz_constraints(const fz_input *in, int ntris, float diag, lapped_constraint *c)
{
    int i, k;
    for (i = 0; i < in->ncon; i++) {
        const uint8_t *b = in->con + 6 * i;
        memset(&c[i], 0, sizeof c[i]);
        c[i].face = b[0] % (ntris + 1);
        for (k = 0; k < 3; k++) c[i].direction[k] = (float)(int8_t)b[1 + k];
        c[i].scale = b[4] ? diag * (float)b[4] / 64.0f : 0.0f;
        c[i].radius = b[5] ? diag * (float)b[5] / 32.0f : 0.0f;
        c[i].weight = (float)(b[5] & 3);
    }
}

/* FACES: frames about (+X, +Y) times the scale; one normal to its triangle when
 * asked (the library must refuse it). */
static int fz_faces(const fz_input *in, const lapped_mesh *m, int ntris, float scale, float **ft, float **fs)
{
    uint64_t s = in->seed ^ 0xfacefaceull;
    int f, k;
    *ft = (float *)malloc((size_t)ntris * 3 * sizeof(float));
    *fs = (float *)malloc((size_t)ntris * 3 * sizeof(float));
    if (!*ft || !*fs) return 0;
    for (f = 0; f < 3 * ntris; f++) { /* t about +Y, s about +X, both perturbed */
        (*ft)[f] = ((f % 3 == 1 ? 1.0f : 0.0f) + 0.6f * fz_unit(&s) - 0.3f) * scale;
        (*fs)[f] = ((f % 3 == 0 ? 1.0f : 0.0f) + 0.6f * fz_unit(&s) - 0.3f) * scale;
    }
    if ((in->h[11] & 1) && ntris > 0) { /* triangle 0: t along its normal */
        const float *p = m->positions;
        const int *v = m->face_verts + m->face_start[0];
        float a[3], b[3];
        for (k = 0; k < 3; k++) {
            a[k] = p[3 * v[1] + k] - p[3 * v[0] + k];
            b[k] = p[3 * v[2] + k] - p[3 * v[0] + k];
        }
        (*ft)[0] = a[1] * b[2] - a[2] * b[1];
        (*ft)[1] = a[2] * b[0] - a[0] * b[2];
        (*ft)[2] = a[0] * b[1] - a[1] * b[0];
    }
    return 1;
}

/* ---- checks on the results ------------------------------------------------------------ */

static void fz_check_texture(const lapped_texture *t, int ntris, const lapped_image *patches, int npatches,
                             const lapped_options *o)
{
    unsigned char *seen = (unsigned char *)calloc((size_t)ntris, 1);
    int p, i;
    FZ_CHECK(seen);
    FZ_CHECK(t->ntris == ntris && t->npatches == npatches && t->patch_size);
    for (p = 0; p < npatches; p++)
        FZ_CHECK(t->patch_size[2 * p] == patches[p].width && t->patch_size[2 * p + 1] == patches[p].height);
    FZ_CHECK(t->npastes >= 1 && t->npastes <= o->max_pastes && t->pastes);
    FZ_CHECK(t->hard_edges >= 0 && t->layers >= 1.0 && t->layers_before >= t->layers);
    for (p = 0; p < t->npastes; p++) {
        const lapped_paste *q = &t->pastes[p];
        FZ_CHECK(q->patch >= 0 && q->patch < npatches);
        FZ_CHECK(q->nfaces >= 1 && q->faces && q->uvs);
        for (i = 0; i < q->nfaces; i++) {
            FZ_CHECK(q->faces[i] >= 0 && q->faces[i] < ntris);
            seen[q->faces[i]] = 1;
        }
        for (i = 0; i < 6 * q->nfaces; i++) FZ_CHECK(fz_finite(q->uvs[i]));
    }
    for (i = 0; i < ntris; i++) FZ_CHECK(seen[i]);
    free(seen);
}

/* The area guarantee, per paste, against the field lapped_compute_field
 * gives for the same options. */
static void fz_check_areas(const lapped_mesh *mesh, const lapped_texture *t, const lapped_options *o)
{
    lapped_field f;
    lapped__surface sf;
    double d = o->max_distortion > 0.0f ? o->max_distortion : 2.0, lo = 0.999 / (d * d), hi = 1.001 * d * d;
    lapped_error err;
    pw_trimesh m;
    pw_alloc a;
    pw_err e;
    int p;
    memset(&a, 0, sizeof a);
    pw_err_clear(&e);
    FZ_CHECK(lapped_compute_field(mesh, o, &f, &err) == LAPPED_OK && f.ntris == t->ntris);
    FZ_CHECK(lapped__mesh_init(&a, mesh, &m, &e) == PW_OK);
    sf.m = &m;
    sf.fs = f.s;
    sf.ft = f.t;
    for (p = 0; p < t->npastes; p++) {
        lapped__areas ar;
        lapped__paste_areas(&sf, &t->pastes[p], lo, hi, &ar);
        FZ_CHECK(lapped__area_ok(ar.tex, ar.surf, lo, hi, t->pastes[p].nfaces));
    }
    pw_trimesh_free(&a, &m);
    lapped_field_free(&f);
}

/* Determinism: lapped_create again, the same result bit for bit. */
static void fz_check_again(const lapped_mesh *mesh, const lapped_source *src, const lapped_options *o,
                           const lapped_texture *t)
{
    lapped_options o2 = *o;
    fz_progress prog;
    lapped_texture u;
    lapped_error err;
    int p;
    memset(&prog, 0, sizeof prog);
    prog.max_calls = FZ_MAX_CALLS;
    o2.progress_user = &prog;
    FZ_CHECK(lapped_create(mesh, src, &o2, &u, &err) == LAPPED_OK);
    FZ_CHECK(u.ntris == t->ntris && u.npatches == t->npatches && u.npastes == t->npastes);
    FZ_CHECK(u.layers == t->layers && u.layers_before == t->layers_before && u.hard_edges == t->hard_edges);
    for (p = 0; p < t->npastes; p++) {
        const lapped_paste *x = &t->pastes[p], *y = &u.pastes[p];
        FZ_CHECK(x->patch == y->patch && x->nfaces == y->nfaces);
        FZ_CHECK(!memcmp(x->faces, y->faces, (size_t)x->nfaces * sizeof(int)));
        FZ_CHECK(!memcmp(x->uvs, y->uvs, (size_t)x->nfaces * 6 * sizeof(float)));
    }
    lapped_texture_free(&u);
}

/* The paste file of a made texture reads back with the same counts. */
static void fz_check_file(const lapped_texture *t, const lapped_options *o)
{
    fz_buf b;
    lapped_texture r;
    lapped_error err;
    int p;
    memset(&b, 0, sizeof b);
    FZ_CHECK(lapped_write_pastes(t, fz_append, &b, &err) == LAPPED_OK);
    FZ_CHECK(lapped_read_pastes(b.data, b.size, "made", o, &r, &err) == LAPPED_OK);
    FZ_CHECK(r.npatches == t->npatches && r.npastes == t->npastes);
    for (p = 0; p < t->npastes; p++) {
        FZ_CHECK(r.pastes[p].nfaces == t->pastes[p].nfaces);
        FZ_CHECK(!memcmp(r.pastes[p].uvs, t->pastes[p].uvs, (size_t)t->pastes[p].nfaces * 6 * sizeof(float)));
    }
    lapped_texture_free(&r);
    free(b.data);
}

static void fz_render(const fz_input *in, const lapped_mesh *mesh, const lapped_texture *t,
                      const lapped_source *src)
{
    lapped_render_options ro;
    lapped_image pic;
    lapped_error err;
    lapped_result r;
    size_t i;
    memset(&ro, 0, sizeof ro);
    ro.width = 32;
    ro.height = 24;
    ro.supersample = 1 + (in->h[2] >> 5 & 1);
    ro.filter = (lapped_filter)((in->h[2] >> 3 & 3) % 3);
    r = lapped_render(mesh, t, src, &ro, &pic, &err);
    FZ_LOG("render", r, &err);
    if (r != LAPPED_OK) {
        fz_lapped_failure(r, &err);
        FZ_CHECK(pic.pixels == NULL);
        return;
    }
    FZ_CHECK(pic.width == 32 && pic.height == 24 && pic.pixels);
    for (i = 0; i < (size_t)32 * 24 * pic.channels; i++) FZ_CHECK(fz_finite(pic.pixels[i]));
    lapped_image_free(&pic);
}

static void fz_bake(const fz_input *in, const lapped_mesh *mesh, const lapped_texture *t,
                    const lapped_source *src, const lapped_options *o)
{
    static const int sizes[4] = {16, 24, 32, 40};
    static const float cones[4] = {0.0f, 10.0f, 90.0f, 180.0f};
    lapped_options bo = *o;
    lapped_atlas_options ao;
    lapped_atlas atlas;
    lapped_error err;
    lapped_result r;
    size_t i, n, bytes = 0;
    memset(&ao, 0, sizeof ao);
    ao.size = sizes[in->h[9] & 3];
    ao.gutter = in->h[9] >> 2 & 3;
    ao.cone_angle = cones[in->h[9] >> 4 & 3];
    bo.atlas = ao;
    r = lapped_bake_atlas(mesh, t, src, &bo, &atlas, &err);
    FZ_LOG("atlas", r, &err);
    if (r != LAPPED_OK) {
        fz_lapped_failure(r, &err);
        FZ_CHECK(atlas.uvs == NULL && atlas.image.pixels == NULL);
        return;
    }
    FZ_CHECK(atlas.ntris == t->ntris && atlas.uvs && atlas.ncharts >= 1);
    FZ_CHECK(atlas.image.width == ao.size && atlas.image.height == ao.size && atlas.image.pixels);
    for (i = 0; i < (size_t)atlas.ntris * 6; i++)
        FZ_CHECK(fz_finite(atlas.uvs[i]) && atlas.uvs[i] >= 0.0f && atlas.uvs[i] <= 1.0f);
    n = (size_t)ao.size * ao.size * atlas.image.channels;
    for (i = 0; i < n; i++) FZ_CHECK(fz_finite(atlas.image.pixels[i]));
    FZ_CHECK(lapped_write_obj(mesh, &atlas, "x.mtl", fz_count, &bytes, &err) == LAPPED_OK);
    FZ_CHECK(bytes > 0);
    lapped_atlas_free(&atlas);
}

/* ---- the pipeline ---------------------------------------------------------------------- */

static void fz_pipeline(const fz_input *in, const lapped_mesh *mesh, int ntris, fz_heap *heap)
{
    lapped_options o;
    lapped_constraint con[4];
    lapped_image tex, tex2, mask, patches[2], values[2];
    lapped_source src;
    lapped_texture t;
    lapped_error err;
    lapped_result r;
    fz_progress prog;
    float *ft = NULL, *fs = NULL, diag = fz_diag(mesh);
    int npatches = 1 + (in->h[0] >> 6 & 1), k, ours = (in->h[3] & 3) == 3, use_mask;
    fz_options(in, diag, &o);
    if (in->h[0] & 32) {
        o.allocator.malloc_fn = fz_malloc;
        o.allocator.realloc_fn = fz_realloc;
        o.allocator.free_fn = fz_free;
        o.allocator.user = heap;
    }
    memset(patches, 0, sizeof patches);
    memset(values, 0, sizeof values);
    memset(&tex2, 0, sizeof tex2);
    if (!fz_texture(in, &o, &tex, &mask)) goto done;
    use_mask = o.alpha == LAPPED_ALPHA_MASK || (o.alpha == LAPPED_ALPHA_AUTO && mask.pixels);
    if (npatches == 2) { /* the second patch: built-in dots of another size, in a circle */
        int side = 12 + 2 * (int)(in->seed >> 20 & 7);
        FZ_CHECK(lapped_builtin_exemplar("dots", side, &o, &tex2, &err) == LAPPED_OK);
    }
    for (k = 0; k < npatches; k++) {
        lapped_options po = o;
        const lapped_image *src = k == 0 ? &tex : &tex2;
        if (k == 1) po.alpha = LAPPED_ALPHA_CIRCLE;
        r = lapped_make_patch(src, k == 0 && use_mask && mask.pixels ? &mask : NULL, &po, &patches[k], &err);
        FZ_LOG("patch", r, &err);
        if (r != LAPPED_OK) {
            fz_lapped_failure(r, &err);
            FZ_CHECK(patches[k].pixels == NULL);
            goto done;
        }
        FZ_CHECK(patches[k].width == src->width && patches[k].height == src->height && patches[k].channels == 4);
    }
    if (o.field == LAPPED_FIELD_CONSTRAINTS) {
        fz_constraints(in, ntris, diag, con);
        o.constraints = con;
        o.nconstraints = in->ncon;
    } else if (o.field == LAPPED_FIELD_FACES) {
        if (!fz_faces(in, mesh, ntris, o.scale > 0.0f && o.scale < 1e30f ? o.scale : diag / 4,
                      &ft, &fs))
            goto done;
        o.face_t = ft;
        o.face_s = in->h[9] & 128 ? fs : NULL;
    }
    memset(&prog, 0, sizeof prog);
    prog.max_calls = FZ_MAX_CALLS;
    prog.cancel_at = in->h[10] >> 5;
    o.progress = fz_progress_fn;
    o.progress_user = &prog;
    src.patches = patches, src.npatches = npatches, src.values = NULL;
    r = lapped_create(mesh, &src, &o, &t, &err);
    FZ_LOG("create", r, &err);
#ifdef FZ_VERBOSE
    if (r == LAPPED_OK) fprintf(stderr, "  %d pastes, %d progress calls\n", t.npastes, prog.calls);
#endif
    if (r != LAPPED_OK) {
        fz_lapped_failure(r, &err);
        FZ_CHECK(t.pastes == NULL && t.npastes == 0 && t.patch_size == NULL);
        goto done;
    }
    fz_check_texture(&t, ntris, patches, npatches, &o);
    fz_check_areas(mesh, &t, &o);
    fz_check_file(&t, &o);
    if (in->h[11] & 64) fz_check_again(mesh, &src, &o, &t);
    if (in->h[9] & 64) /* a value channel: the patch's first channel */
        for (k = 0; k < npatches; k++) {
            size_t i, n = (size_t)patches[k].width * patches[k].height;
            values[k].width = patches[k].width;
            values[k].height = patches[k].height;
            values[k].channels = 1;
            if (!(values[k].pixels = (float *)malloc(n * sizeof(float)))) goto free_texture;
            for (i = 0; i < n; i++) values[k].pixels[i] = patches[k].pixels[4 * i];
        }
    src.values = in->h[9] & 64 ? values : NULL;
    fz_render(in, mesh, &t, &src);
    if (in->h[0] & 128) {
        prog.calls = 0;
        prog.cancel_at = prog.cancel_at ? prog.cancel_at + 1 : 0;
        fz_bake(in, mesh, &t, &src, &o);
    }
free_texture:
    lapped_texture_free(&t);
    FZ_CHECK(t.pastes == NULL && t.npastes == 0);
done:
    for (k = 0; k < 2; k++) {
        lapped_image_free(&patches[k]);
        free(values[k].pixels);
    }
    fz_image_free(&tex, ours);
    lapped_image_free(&tex2);
    free(mask.pixels);
    free(ft);
    free(fs);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    lapped_options lo = lapped_default_options();
    lapped_mesh mesh;
    lapped_error err;
    fz_input in;
    fz_heap heap;
    int ntris;
    if (size < FZ_HEADER) return 0;
    memset(&in, 0, sizeof in);
    in.h = data;
    in.mesh = data + FZ_HEADER;
    in.mesh_size = size - FZ_HEADER;
    memcpy(&in.seed, data + 4, 4);
    in.seed &= 0xffffffffull;
    if ((data[0] & 7) == LAPPED_FIELD_CONSTRAINTS) {
        in.ncon = 1 + (data[10] & 3);
        if (in.mesh_size < (size_t)6 * in.ncon) return 0;
        in.con = in.mesh;
        in.mesh += 6 * in.ncon;
        in.mesh_size -= (size_t)6 * in.ncon;
    }
    heap.live = 0;
    if (data[0] & 32) { /* the mesh too, so that lapped_mesh_free is checked */
        lo.allocator.malloc_fn = fz_malloc;
        lo.allocator.realloc_fn = fz_realloc;
        lo.allocator.free_fn = fz_free;
        lo.allocator.user = &heap;
    }
    if (lapped_read_mesh(in.mesh, in.mesh_size, "fuzz", &lo, &mesh, &err) != LAPPED_OK) {
        FZ_LOG("mesh", err.code, &err);
        fz_lapped_failure(err.code, &err);
        FZ_CHECK(mesh.positions == NULL && mesh.face_start == NULL && mesh.face_verts == NULL);
        FZ_CHECK(heap.live == 0);
        return 0;
    }
    FZ_CHECK(mesh.nverts >= 1 && mesh.nfaces >= 1);
    ntris = mesh.face_start[mesh.nfaces] - 2 * mesh.nfaces;
    if (ntris >= 1 && ntris <= FZ_MAX_TRIS && mesh.nverts <= FZ_MAX_VERTS) fz_pipeline(&in, &mesh, ntris, &heap);
    lapped_mesh_free(&mesh);
    FZ_CHECK(heap.live == 0);
    return 0;
}
