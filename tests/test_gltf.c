/* Tests of the binary glTF writer (src/common/gltf.h) through tiled.h:
 * the GLB container (header, chunk types, lengths, 4-byte alignment), the
 * camera present exactly when a view is given, determinism, and clear
 * errors (no writer, a texture without coordinates, non-finite positions,
 * a failing writer, every allocation failing in turn). The file's
 * content is checked by other people's programs in tests/sh/gltf.sh
 * (Khronos' validator, three.js). */
#define TILED_STATIC
#define TILED_IMPLEMENTATION
#include "../tiled.h"
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
static int live, fail_at, count;
static void *cnt_malloc(void *u, size_t n)
{
    void *p;
    (void)u;
    if (count++ == fail_at) return NULL;
    if ((p = malloc(n)) != NULL) live++;
    return p;
}
static void *cnt_realloc(void *u, void *p, size_t n)
{
    void *q;
    (void)u;
    if (count++ == fail_at) return NULL;
    q = realloc(p, n);
    if (q && !p) live++;
    return q;
}
static void cnt_free(void *u, void *p)
{
    (void)u;
    if (p) live--;
    free(p);
}

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
    q.allocator.malloc_fn = cnt_malloc, q.allocator.realloc_fn = cnt_realloc, q.allocator.free_fn = cnt_free;
    for (fail_at = 0;; fail_at++) {
        mem m = {NULL, 0, 0, -1};
        tiled_result r;
        count = live = 0;
        r = tiled_write_gltf(&q, &ts.atlas, &view, mem_write, &m, &e);
        free(m.data);
        if (live != 0 || (r != TILED_OK && r != TILED_ERR_NOMEM)) bad++;
        if (r == TILED_OK) break;
        points++;
    }
    pwt_info("%d allocation points, each failing in turn: NOMEM, no leak", points);
    CHECK(points > 5 && bad == 0);
    q.allocator = keep;
    tiled_mesh_free(&q);
    tiled_tileset_free(&ts);
}

static const pwt_case cases[] = {
    {"container", t_container},
    {"errors", t_errors},
    {"alloc_failures", t_alloc_failures},
};
PWT_MAIN(cases)
