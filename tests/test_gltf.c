/* Tests of the binary glTF writer (src/common/gltf.h) through tiled.h:
 * the GLB container (header, chunk types, lengths, 4-byte alignment), the
 * camera present exactly when a view is given, determinism, and clear
 * errors (no writer, a texture without coordinates, non-finite positions,
 * a failing writer, every allocation failing in turn). Through lst.h: a
 * cut model's baked atlas read back from the file bit for bit, the same
 * bytes twice, bad input, and a cut whose pieces touch along edges (a
 * non-manifold boundary). The file's content is checked by other people's
 * programs in tests/sh/gltf.sh (Khronos' validator, three.js). */
#define TILED_STATIC
#define TILED_IMPLEMENTATION
#include "../tiled.h"
#define LST_STATIC
#define LST_IMPLEMENTATION
#include "../lst.h"
#include "pwtest.h"

typedef struct mem {
    unsigned char *data;
    size_t size, cap;
    int fail_after; /* bytes accepted before the writer fails; -1 never */
} mem;

static int mem_write(void *ctx, const void *p, size_t n)
{
    mem *m = (mem *)ctx;
    if (m->fail_after >= 0 && m->size + n > (size_t)m->fail_after) return -1;
    if (m->size + n > m->cap) {
        m->cap = 2 * (m->size + n);
        m->data = (unsigned char *)realloc(m->data, m->cap);
    }
    memcpy(m->data + m->size, p, n);
    m->size += n;
    return 0;
}

static int has(const mem *m, const char *s)
{
    size_t n = strlen(s), i;
    for (i = 0; i + n <= m->size; i++)
        if (!memcmp(m->data + i, s, n)) return 1;
    return 0;
}

static uint32_t le32(const unsigned char *p) { return p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24; }

/* A tiled torus with its texture. */
static int torus(tiled_mesh *quads, tiled_tileset *ts)
{
    tiled_options o = tiled_default_options();
    tiled_image ex;
    tiled_mesh m;
    tiled_error e;
    int ok;
    if (tiled_builtin_exemplar("pebbles", 64, &o, &ex, &e) || tiled_builtin_mesh("torus", &o, &m, &e)) return 0;
    ok = !tiled_synthesize(&ex, &o, ts, &e) && !tiled_map(&m, &ts->layout, &o, quads, &e);
    tiled_image_free(&ex);
    tiled_mesh_free(&m);
    return ok;
}

static void t_container(void)
{
    tiled_mesh q;
    tiled_tileset ts;
    tiled_render_options view;
    tiled_error e;
    mem a = {NULL, 0, 0, -1}, b = {NULL, 0, 0, -1}, c = {NULL, 0, 0, -1};
    uint32_t jl, bl;
    REQUIRE(torus(&q, &ts));
    memset(&view, 0, sizeof view);
    REQUIRE(tiled_write_gltf(&q, &ts.atlas, &view, mem_write, &a, &e) == TILED_OK);
    REQUIRE(tiled_write_gltf(&q, &ts.atlas, &view, mem_write, &b, &e) == TILED_OK);
    REQUIRE(tiled_write_gltf(&q, NULL, NULL, mem_write, &c, &e) == TILED_OK);
    CHECK(a.size == b.size && !memcmp(a.data, b.data, a.size));
    REQUIRE(a.size > 28);
    CHECK(!memcmp(a.data, "glTF", 4) && le32(a.data + 4) == 2 && le32(a.data + 8) == a.size);
    jl = le32(a.data + 12);
    CHECK(!memcmp(a.data + 16, "JSON", 4) && jl % 4 == 0 && a.data[20] == '{');
    REQUIRE(20 + jl + 8 <= a.size);
    bl = le32(a.data + 20 + jl);
    CHECK(!memcmp(a.data + 24 + jl, "BIN", 4) && a.data[27 + jl] == 0 && bl % 4 == 0 && 28 + jl + bl == a.size);
    CHECK(has(&a, "\"cameras\":[{\"type\":\"perspective\"") && has(&a, "\"mimeType\":\"image/png\"") &&
          has(&a, "\"generator\":\"patchwork tiled.h"));
    CHECK(c.size < a.size && !has(&c, "cameras") && !has(&c, "image/png"));
    free(a.data), free(b.data), free(c.data);
    tiled_mesh_free(&q);
    tiled_tileset_free(&ts);
}

static void t_errors(void)
{
    tiled_mesh q;
    tiled_tileset ts;
    tiled_error e;
    mem m = {NULL, 0, 0, -1};
    float *uvs, keep;
    REQUIRE(torus(&q, &ts));
    CHECK(tiled_write_gltf(&q, &ts.atlas, NULL, NULL, NULL, &e) == TILED_ERR_INVALID);
    uvs = q.uvs;
    q.uvs = NULL;
    CHECK(tiled_write_gltf(&q, &ts.atlas, NULL, mem_write, &m, &e) == TILED_ERR_INVALID &&
          strstr(e.message, "texture coordinates"));
    q.uvs = uvs;
    keep = q.positions[7];
    q.positions[7] = 0.0f / 0.0f;
    CHECK(tiled_write_gltf(&q, &ts.atlas, NULL, mem_write, &m, &e) != TILED_OK && strstr(e.message, "vertex 2"));
    q.positions[7] = keep;
    CHECK(m.size == 0);
    m.fail_after = 1000;
    CHECK(tiled_write_gltf(&q, &ts.atlas, NULL, mem_write, &m, &e) == TILED_ERR_IO);
    free(m.data);
    tiled_mesh_free(&q);
    tiled_tileset_free(&ts);
}

/* Every allocation of a write failing in turn: NOMEM, nothing leaked. */
static void t_alloc_failures(void)
{
    tiled_mesh q;
    tiled_tileset ts;
    tiled_render_options view;
    tiled_allocator keep;
    tiled_error e;
    int points = 0, bad = 0;
    REQUIRE(torus(&q, &ts));
    memset(&view, 0, sizeof view);
    keep = q.allocator;
    q.allocator.malloc_fn = pwt_alloc_malloc, q.allocator.realloc_fn = pwt_alloc_realloc, q.allocator.free_fn = pwt_alloc_free;
    for (pwt_alloc_fail_at = 0;; pwt_alloc_fail_at++) {
        mem m = {NULL, 0, 0, -1};
        tiled_result r;
        pwt_alloc_calls = pwt_alloc_live = 0;
        r = tiled_write_gltf(&q, &ts.atlas, &view, mem_write, &m, &e);
        free(m.data);
        if (pwt_alloc_live != 0 || (r != TILED_OK && r != TILED_ERR_NOMEM)) bad++;
        if (r == TILED_OK) break;
        points++;
    }
    pwt_alloc_fail_at = -1;
    pwt_info("%d allocation points, each failing in turn: NOMEM, no leak", points);
    CHECK(points > 5 && bad == 0);
    q.allocator = keep;
    tiled_mesh_free(&q);
    tiled_tileset_free(&ts);
}

/* ---- lst.h ---- */

/* A type-0 sphere of spots, about n tetrahedra. */
static int lst_sphere(int n, lst_model *model)
{
    lst_options o = lst_default_options();
    lst_mesh s;
    lst_tetmesh m;
    lst_volume ex;
    lst_source src;
    lst_error e;
    int ok;
    o.tet.target_tets = n, o.tet.uniform = 1; /* a small uniform fill: stuffing tests cover the graded one */
    if (lst_builtin_mesh("sphere", &o, &s, &e) || lst_tetrahedralize(&s, &o, &m, NULL, &e)) return 0;
    if (lst_builtin_exemplar("spots", 16, &o, &ex, NULL, &e)) return 0;
    src.exemplar = &ex, src.values = NULL;
    ok = lst_create(&m, &s, &src, &o, model, &e) == LST_OK;
    lst_volume_free(&ex), lst_tetmesh_free(&m), lst_mesh_free(&s);
    return ok;
}

/* The buffer views of a patchwork GLB of one part (offset, length; views
 * 0 indices, 1 positions, 2 normals, 3 texture coordinates, 4 the image)
 * and the binary chunk; 0 if malformed. */
static int glb_views(const mem *m, size_t off[5], size_t len[5], const unsigned char **bin)
{
    uint32_t jl;
    char *json, *p;
    int k, ok = 1;
    if (m->size < 28 || memcmp(m->data, "glTF", 4) || (jl = le32(m->data + 12)) + 28 > m->size) return 0;
    json = (char *)malloc(jl + 1);
    memcpy(json, m->data + 20, jl);
    json[jl] = 0;
    p = strstr(json, "\"bufferViews\":[");
    for (k = 0; k < 5 && ok; k++) {
        unsigned long o = 0, l = 0;
        ok = p && (p = strstr(p, "\"byteOffset\":")) && sscanf(p + 13, "%lu", &o) == 1 &&
             (p = strstr(p, "\"byteLength\":")) && sscanf(p + 13, "%lu", &l) == 1 && 28 + jl + o + l <= m->size;
        off[k] = o, len[k] = l;
    }
    free(json);
    *bin = m->data + 28 + jl;
    return ok;
}

/* Every corner of the atlas in the file: the same position and (u, 1 - v)
 * bit for bit; the image a PNG. */
static void t_lst_roundtrip(void)
{
    lst_model model;
    lst_options o = lst_default_options();
    lst_atlas at;
    lst_error e;
    mem a = {NULL, 0, 0, -1};
    size_t off[5], len[5];
    const unsigned char *bin;
    const float cut[4] = {0.3f, 0.2f, 1.0f, 0.1f};
    int c, bad = 0, nv;
    REQUIRE(lst_sphere(1500, &model));
    REQUIRE(lst_cut_plane(&model, cut, &e) == LST_OK);
    o.atlas.size = 256;
    REQUIRE(lst_bake_atlas(&model, &o, &at, &e) == LST_OK);
    CHECK(at.image.width == 256 && at.image.channels == 3 && at.ncharts >= 2 && at.fill > 0.2f);
    REQUIRE(lst_write_gltf(&at, &o.render, mem_write, &a, &e) == LST_OK);
    REQUIRE(glb_views(&a, off, len, &bin));
    CHECK(len[0] == 12 * (size_t)at.ntris && len[1] % 12 == 0 && len[3] == len[1] / 12 * 8);
    nv = (int)(len[1] / 12);
    CHECK(nv >= at.nverts);
    for (c = 0; c < 3 * at.ntris && len[0] == 12 * (size_t)at.ntris; c++) {
        uint32_t i = le32(bin + off[0] + 4 * (size_t)c);
        float uv[2], v1 = 1.0f - at.uvs[2 * c + 1];
        if ((int)i >= nv || memcmp(bin + off[1] + 12 * (size_t)i, at.positions + 3 * at.tris[c], 12)) {
            bad++;
            continue;
        }
        memcpy(uv, bin + off[3] + 8 * (size_t)i, 8);
        if (memcmp(uv, at.uvs + 2 * c, 4) || memcmp(uv + 1, &v1, 4)) bad++;
    }
    pwt_info("%d triangles, %d atlas vertices, %d in the file, %d charts, fill %.2f", at.ntris, at.nverts, nv, at.ncharts,
             (double)at.fill);
    CHECK(bad == 0);
    CHECK(len[4] > 8 && !memcmp(bin + off[4], "\x89PNG", 4) && has(&a, "\"mimeType\":\"image/png\"") &&
          has(&a, "\"cameras\":[{") && has(&a, "\"generator\":\"patchwork lst.h"));
    free(a.data);
    lst_atlas_free(&at);
    lst_model_free(&model);
}

/* The same model gives the same file twice (bake and write). */
static void t_lst_deterministic(void)
{
    lst_model model;
    lst_options o = lst_default_options();
    lst_atlas x, y;
    lst_error e;
    mem a = {NULL, 0, 0, -1}, b = {NULL, 0, 0, -1};
    const float cut[4] = {1, 0, 0, 0};
    REQUIRE(lst_sphere(800, &model));
    REQUIRE(lst_cut_plane(&model, cut, &e) == LST_OK);
    o.atlas.size = 128;
    REQUIRE(lst_bake_atlas(&model, &o, &x, &e) == LST_OK && lst_bake_atlas(&model, &o, &y, &e) == LST_OK);
    REQUIRE(lst_write_gltf(&x, &o.render, mem_write, &a, &e) == LST_OK && lst_write_gltf(&y, &o.render, mem_write, &b, &e) == LST_OK);
    CHECK(a.size == b.size && !memcmp(a.data, b.data, a.size));
    /* the files: the same bytes; the OBJ's MTL names the texture */
    {
        char glb[256], obj[256], mtl[256], line[256];
        FILE *f;
        size_t n = 0;
        int named = 0;
        strcpy(glb, pwt_tmp("lst", 0, ".glb")), strcpy(obj, pwt_tmp("lst", 1, ".obj")), strcpy(mtl, pwt_tmp("lst", 1, ".mtl"));
        REQUIRE(lst_save_gltf(glb, &x, &o.render, &e) == LST_OK && lst_save_atlas_obj(obj, &x, "atlas.png", &e) == LST_OK);
        if ((f = fopen(glb, "rb")) != NULL) {
            unsigned char *buf = (unsigned char *)malloc(a.size + 1);
            n = fread(buf, 1, a.size + 1, f);
            fclose(f);
            CHECK(n == a.size && !memcmp(buf, a.data, n));
            free(buf);
        }
        if ((f = fopen(mtl, "r")) != NULL) {
            while (fgets(line, sizeof line, f)) named |= !strcmp(line, "map_Kd atlas.png\n");
            fclose(f);
        }
        CHECK(n == a.size && named);
        remove(glb), remove(obj), remove(mtl);
    }
    free(a.data), free(b.data);
    lst_atlas_free(&x), lst_atlas_free(&y);
    lst_model_free(&model);
}

static void t_lst_errors(void)
{
    lst_model model;
    lst_options o = lst_default_options();
    lst_atlas at;
    lst_error e;
    mem m = {NULL, 0, 0, -1};
    int keep;
    CHECK(lst_write_gltf(NULL, NULL, mem_write, &m, &e) == LST_ERR_INVALID && strstr(e.message, "no atlas"));
    CHECK(lst_bake_atlas(NULL, NULL, &at, &e) == LST_ERR_INVALID && strstr(e.message, "no model") && !at.uvs);
    REQUIRE(lst_sphere(800, &model));
    o.atlas.size = 8;
    CHECK(lst_bake_atlas(&model, &o, &at, &e) == LST_ERR_INVALID && strstr(e.message, "atlas size 8"));
    o.atlas.size = 64, o.atlas.gutter = 9;
    CHECK(lst_bake_atlas(&model, &o, &at, &e) == LST_ERR_INVALID && strstr(e.message, "atlas gutter 9"));
    o.atlas.gutter = 0;
    REQUIRE(lst_bake_atlas(&model, &o, &at, &e) == LST_OK);
    CHECK(lst_write_gltf(&at, NULL, NULL, NULL, &e) == LST_ERR_INVALID);
    keep = at.tris[4];
    at.tris[4] = at.nverts;
    CHECK(lst_write_gltf(&at, NULL, mem_write, &m, &e) == LST_ERR_INVALID && strstr(e.message, "corner 1 of atlas triangle 1"));
    at.tris[4] = keep;
    CHECK(m.size == 0);
    m.fail_after = 1000;
    CHECK(lst_write_gltf(&at, NULL, mem_write, &m, &e) == LST_ERR_IO);
    memset(model.removed, 1, (size_t)model.mesh.ntets);
    lst_atlas_free(&at);
    CHECK(lst_bake_atlas(&model, &o, &at, &e) != LST_OK && strstr(e.message, "cut away"));
    free(m.data);
    lst_model_free(&model);
}

/* Undirected edge (a, b) of triangle list tri (n triangles): how many
 * triangles run a -> b and b -> a. */
static void edge_uses(const int *tri, int n, int a, int b, int *ab, int *ba)
{
    int f, k;
    *ab = *ba = 0;
    for (f = 0; f < n; f++)
        for (k = 0; k < 3; k++) {
            int p = tri[3 * f + k], q = tri[3 * f + (k + 1) % 3];
            *ab += p == a && q == b;
            *ba += p == b && q == a;
        }
}

/* A cut along the zero set of x*y keeps two opposite quarters of the
 * sphere, which touch along the z axis: the boundary has edges with four
 * faces. The atlas still bakes, its mesh is a manifold (every edge run
 * at most once each way) and covers the boundary's area. */
static void t_lst_nonmanifold(void)
{
    lst_model model;
    lst_options o = lst_default_options();
    lst_atlas at;
    lst_error e;
    float *phi;
    int *btri, nb = 0, t, k, v, bad = 0, nonmanifold = 0;
    double area_b = 0.0, area_a = 0.0;
    REQUIRE(lst_sphere(1500, &model));
    phi = (float *)malloc(sizeof(float) * (size_t)model.mesh.nverts);
    for (v = 0; v < model.mesh.nverts; v++) phi[v] = model.mesh.positions[3 * v] * model.mesh.positions[3 * v + 1];
    REQUIRE(lst_cut_field(&model, phi, &e) == LST_OK);
    free(phi);
    /* the boundary faces, by brute force: faces of kept tetrahedra with no kept neighbour across */
    btri = (int *)malloc(sizeof(int) * 12 * (size_t)model.mesh.ntets);
    for (t = 0; t < model.mesh.ntets; t++) {
        static const int fc[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
        if (model.removed[t]) continue;
        for (k = 0; k < 4; k++) {
            int c[3], u, shared = 0;
            for (v = 0; v < 3; v++) c[v] = model.mesh.tets[4 * t + fc[k][v]];
            for (u = 0; u < model.mesh.ntets && !shared; u++) {
                int hits = 0, j;
                if (u == t || model.removed[u]) continue;
                for (j = 0; j < 4; j++) hits += model.mesh.tets[4 * u + j] == c[0] || model.mesh.tets[4 * u + j] == c[1] ||
                                                model.mesh.tets[4 * u + j] == c[2];
                shared = hits == 3;
            }
            if (!shared) memcpy(btri + 3 * nb++, c, sizeof c);
        }
    }
    for (t = 0; t < nb; t++)
        for (k = 0; k < 3; k++) {
            int ab, ba, a = btri[3 * t + k], b = btri[3 * t + (k + 1) % 3];
            edge_uses(btri, nb, a, b, &ab, &ba);
            nonmanifold += ab + ba > 2;
        }
    pwt_info("boundary: %d triangles, %d half-edges on edges with more than two faces", nb, nonmanifold);
    CHECK(nonmanifold > 0);
    o.atlas.size = 256;
    REQUIRE(lst_bake_atlas(&model, &o, &at, &e) == LST_OK);
    CHECK(at.ntris == nb);
    for (t = 0; t < at.ntris; t++)
        for (k = 0; k < 3; k++) {
            int ab, ba;
            edge_uses(at.tris, at.ntris, at.tris[3 * t + k], at.tris[3 * t + (k + 1) % 3], &ab, &ba);
            bad += ab != 1 || ba > 1;
        }
    CHECK(bad == 0);
    for (t = 0; t < nb; t++) {
        const float *P[2][3];
        double d[2][2][3], cr[3];
        int s;
        for (k = 0; k < 3; k++) P[0][k] = model.mesh.positions + 3 * btri[3 * t + k], P[1][k] = at.positions + 3 * at.tris[3 * t + k];
        for (s = 0; s < 2; s++) {
            for (k = 0; k < 3; k++) d[s][0][k] = (double)P[s][1][k] - P[s][0][k], d[s][1][k] = (double)P[s][2][k] - P[s][0][k];
            cr[0] = d[s][0][1] * d[s][1][2] - d[s][0][2] * d[s][1][1];
            cr[1] = d[s][0][2] * d[s][1][0] - d[s][0][0] * d[s][1][2];
            cr[2] = d[s][0][0] * d[s][1][1] - d[s][0][1] * d[s][1][0];
            *(s ? &area_a : &area_b) += 0.5 * sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
        }
    }
    pwt_info("atlas: %d vertices, %d charts; area %.6f, boundary's %.6f", at.nverts, at.ncharts, area_a, area_b);
    CHECK(fabs(area_a - area_b) <= 1e-9 * area_b);
    free(btri);
    lst_atlas_free(&at);
    lst_model_free(&model);
}

/* Every allocation of a bake and a write failing in turn: NOMEM, nothing
 * leaked. */
static void t_lst_alloc_failures(void)
{
    lst_model model;
    lst_options o = lst_default_options();
    lst_error e;
    const float cut[4] = {0, 1, 0, 0.2f};
    int points = 0, bad = 0;
    REQUIRE(lst_sphere(400, &model));
    REQUIRE(lst_cut_plane(&model, cut, &e) == LST_OK);
    o.atlas.size = 64;
    o.allocator.malloc_fn = pwt_alloc_malloc, o.allocator.realloc_fn = pwt_alloc_realloc, o.allocator.free_fn = pwt_alloc_free;
    for (pwt_alloc_fail_at = 0;; pwt_alloc_fail_at++) {
        mem m = {NULL, 0, 0, -1};
        lst_atlas at;
        lst_result r;
        pwt_alloc_calls = pwt_alloc_live = 0;
        r = lst_bake_atlas(&model, &o, &at, &e);
        if (r == LST_OK) r = lst_write_gltf(&at, &o.render, mem_write, &m, &e);
        lst_atlas_free(&at);
        free(m.data);
        if (pwt_alloc_live != 0 || (r != LST_OK && (r != LST_ERR_NOMEM || !e.message[0]))) bad++;
        if (r == LST_OK) break;
        points++;
    }
    pwt_alloc_fail_at = -1;
    pwt_info("%d allocation points, each failing in turn: NOMEM, no leak", points);
    CHECK(points > 20 && bad == 0);
    lst_model_free(&model);
}

static const pwt_case cases[] = {
    {"container", t_container},
    {"errors", t_errors},
    {"alloc_failures", t_alloc_failures},
    {"lst_roundtrip", t_lst_roundtrip},
    {"lst_deterministic", t_lst_deterministic},
    {"lst_errors", t_lst_errors},
    {"lst_nonmanifold", t_lst_nonmanifold},
    {"lst_alloc_failures", t_lst_alloc_failures},
};
PWT_MAIN(cases)
