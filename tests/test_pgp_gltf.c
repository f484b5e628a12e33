/* pgp.h for other programs (issue 22): the baked atlas holds what §3's
 * rendering draws (compared with the shading itself at random surface
 * points), the raw atlas the Eq. (4) coordinates and a layer of the tile;
 * pgp_write_gltf's container, sampler and camera; determinism; errors;
 * every allocation of a bake failing in turn. What a viewer makes of the
 * files is checked in tests/sh/gltf.sh (Khronos' validator, three.js). */
#define PGP_STATIC
#define PGP_IMPLEMENTATION
#include "../pgp.h"
#include "pwtest.h"

typedef struct mem {
    unsigned char *data;
    size_t size, cap;
} mem;

static int mem_write(void *ctx, const void *p, size_t n)
{
    mem *m = (mem *)ctx;
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

/* The built-in torus mapped with the bricks tile (4 layers), and a
 * material constraint so that m varies. */
typedef struct scene {
    pgp_mesh mesh;
    pgp_tile tile;
    pgp_map map;
} scene;

static int make_scene(scene *s, const pgp_options *o)
{
    pgp_constraint c;
    memset(s, 0, sizeof *s);
    memset(&c, 0, sizeof c);
    c.kind = PGP_CONSTRAINT_MATERIAL, c.element = 10, c.value[0] = 1.0f, c.radius = 1.0f;
    return !pgp_builtin_mesh("torus", o, &s->mesh, NULL) && !pgp_builtin_tile("bricks", 64, o, &s->tile, NULL) &&
           !pgp_create(&s->mesh, o, &s->map, NULL) && !pgp_add_constraint(&s->map, &c, NULL, NULL, NULL);
}

static void free_scene(scene *s)
{
    pgp_map_free(&s->map);
    pgp_tile_free(&s->tile);
    pgp_mesh_free(&s->mesh);
}

/* Bilinear lookup of the atlas image at (u, v) (v = 0 at the bottom). */
static void lookup(const pgp_image *img, float u, float v, float *out)
{
    float x = u * img->width - 0.5f, y = (1.0f - v) * img->height - 0.5f;
    int x0 = (int)floorf(x), y0 = (int)floorf(y), k, i, j;
    float fx = x - x0, fy = y - y0;
    for (k = 0; k < 3; k++) out[k] = 0.0f;
    for (j = 0; j < 2; j++)
        for (i = 0; i < 2; i++) {
            int X = x0 + i < 0 ? 0 : (x0 + i >= img->width ? img->width - 1 : x0 + i);
            int Y = y0 + j < 0 ? 0 : (y0 + j >= img->height ? img->height - 1 : y0 + j);
            float w = (i ? fx : 1.0f - fx) * (j ? fy : 1.0f - fy);
            for (k = 0; k < 3; k++) out[k] += w * img->pixels[((size_t)Y * img->width + X) * 3 + k];
        }
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* The baked atlas against the shading at random points of random
 * triangles (the texture's own colour, derivatives zero: the finest mip
 * level, which a 1024 atlas of a 64-texel tile reaches). */
static void t_bake(void)
{
    pgp_options o = pgp_default_options();
    pgp_atlas a, again;
    pgp__shading S;
    scene s;
    pgp_error e;
    double d[2000];
    int i, k, n = 0, outside = 0;
    pw_rng rng;
    REQUIRE(make_scene(&s, &o));
    o.atlas.size = 1024;
    REQUIRE(pgp_bake_atlas(&s.map, &s.tile, &o, &a, &e) == PGP_OK);
    CHECK(a.ntris == s.map.ntris && a.ncharts >= 1 && a.fill > 0.3f && a.fill <= 1.0f && !a.repeat);
    CHECK(a.image.width == 1024 && a.image.height == 1024 && a.image.channels == 3);
    for (i = 0; i < 6 * a.ntris; i++) outside += !(a.uvs[i] >= 0.0f && a.uvs[i] <= 1.0f);
    CHECK(outside == 0);
    REQUIRE(pgp_bake_atlas(&s.map, &s.tile, &o, &again, &e) == PGP_OK);
    CHECK(!memcmp(a.uvs, again.uvs, sizeof(float) * 6 * a.ntris) &&
          !memcmp(a.image.pixels, again.image.pixels, sizeof(float) * 3 * 1024 * 1024));
    pgp_atlas_free(&again);
    REQUIRE(pgp__shading_init(s.map.state, &s.tile, PGP_FIX_CLEAN, PGP_SHOW_TILE, &S, NULL) == PW_OK);
    rng = pw_rng_seed(7, 0);
    for (i = 0; i < 2000; i++) {
        int f = (int)(pw_rng_u32(&rng) % (uint32_t)a.ntris);
        float b1 = pw_rng_float(&rng), b2 = pw_rng_float(&rng), db[4] = {0, 0, 0, 0}, rgba[4], got[3], u, v;
        double diff = 0.0;
        if (b1 + b2 > 1.0f) b1 = 1.0f - b1, b2 = 1.0f - b2;
        u = (1.0f - b1 - b2) * a.uvs[6 * f] + b1 * a.uvs[6 * f + 2] + b2 * a.uvs[6 * f + 4];
        v = (1.0f - b1 - b2) * a.uvs[6 * f + 1] + b1 * a.uvs[6 * f + 3] + b2 * a.uvs[6 * f + 5];
        pgp__shade(&S, f, b1, b2, db, rgba);
        lookup(&a.image, u, v, got);
        for (k = 0; k < 3; k++) diff += fabs(got[k] - rgba[k] * rgba[3]) / 3.0;
        d[n++] = diff;
    }
    qsort(d, (size_t)n, sizeof d[0], cmp_double);
    pwt_info("|atlas - shading| at %d random surface points: median %.4f, p90 %.4f, p99 %.4f (colours 0..1)", n,
             d[n / 2], d[n * 9 / 10], d[n * 99 / 100]);
    CHECK(d[n / 2] < 0.02 && d[n * 9 / 10] < 0.08);
    pgp__shading_free(s.map.state, &S);
    pgp_atlas_free(&a);
    free_scene(&s);
}

/* The raw atlas: the coordinates of Eq. (4), the layers blended at m. */
static void t_tile_atlas(void)
{
    pgp_options o = pgp_default_options();
    pgp_atlas a;
    scene s;
    size_t n;
    int i, bad = 0;
    REQUIRE(make_scene(&s, &o));
    REQUIRE(pgp_tile_atlas(&s.map, &s.tile, 0.5f, &a, NULL) == PGP_OK);
    CHECK(a.repeat == 1 && a.ntris == s.map.ntris && a.image.width == 64 && a.image.channels == s.tile.channels);
    for (i = 0; i < 3 * a.ntris; i++)
        bad += a.uvs[2 * i] != s.map.coords[3 * i] || a.uvs[2 * i + 1] != s.map.coords[3 * i + 1];
    CHECK(bad == 0);
    n = (size_t)64 * 64 * s.tile.channels; /* m = 0.5 of 4 layers: 1/2 of layer 1, 1/2 of layer 2 */
    for (i = 0, bad = 0; i < (int)n; i++)
        bad += fabsf(a.image.pixels[i] - (0.5f * s.tile.pixels[n + i] + 0.5f * s.tile.pixels[2 * n + i])) > 1e-6f;
    CHECK(bad == 0);
    pgp_atlas_free(&a);
    CHECK(pgp_tile_atlas(&s.map, &s.tile, 0.0f / 0.0f, &a, NULL) == PGP_ERR_INVALID && a.uvs == NULL);
    free_scene(&s);
}

/* The file: GLB header, the sampler's wrap (33071 CLAMP_TO_EDGE for the
 * baked atlas, 10497 REPEAT for the raw one), a camera exactly when a view
 * is given, the same bytes twice. */
static void t_gltf(void)
{
    pgp_options o = pgp_default_options();
    pgp_atlas baked, raw;
    scene s;
    mem m1 = {NULL, 0, 0}, m2 = {NULL, 0, 0}, m3 = {NULL, 0, 0};
    pgp_error e;
    REQUIRE(make_scene(&s, &o));
    o.atlas.size = 256;
    REQUIRE(pgp_bake_atlas(&s.map, &s.tile, &o, &baked, &e) == PGP_OK);
    REQUIRE(pgp_tile_atlas(&s.map, &s.tile, 0.0f, &raw, &e) == PGP_OK);
    CHECK(pgp_write_gltf(&s.map, &baked, &o.render, mem_write, &m1, &e) == PGP_OK);
    CHECK(pgp_write_gltf(&s.map, &baked, &o.render, mem_write, &m2, &e) == PGP_OK);
    CHECK(m1.size == m2.size && !memcmp(m1.data, m2.data, m1.size));
    CHECK(m1.size > 20 && !memcmp(m1.data, "glTF", 4) && has(&m1, "\"cameras\"") && has(&m1, "33071") &&
          !has(&m1, "10497") && has(&m1, "patchwork pgp.h"));
    CHECK(pgp_write_gltf(&s.map, &raw, NULL, mem_write, &m3, &e) == PGP_OK);
    CHECK(has(&m3, "10497") && !has(&m3, "\"cameras\""));
    raw.ntris--;
    CHECK(pgp_write_gltf(&s.map, &raw, NULL, mem_write, &m3, &e) == PGP_ERR_INVALID && strstr(e.message, "triangles"));
    raw.ntris++;
    CHECK(pgp_write_gltf(NULL, &raw, NULL, mem_write, &m3, &e) == PGP_ERR_INVALID);
    CHECK(pgp_write_gltf(&s.map, NULL, NULL, mem_write, &m3, &e) == PGP_ERR_INVALID);
    pgp_atlas_free(&baked);
    o.atlas.size = 9000;
    CHECK(pgp_bake_atlas(&s.map, &s.tile, &o, &baked, &e) == PGP_ERR_LIMIT && strstr(e.message, "atlas size") &&
          baked.uvs == NULL);
    free(m1.data), free(m2.data), free(m3.data);
    pgp_atlas_free(&raw);
    free_scene(&s);
}

/* Every allocation of a bake failing in turn: NOMEM, nothing leaked. */
static void t_alloc_failures(void)
{
    pgp_options o = pgp_default_options();
    pgp_mesh mesh;
    pgp_tile tile;
    pgp_map map;
    int points = 0, bad = 0, before;
    o.allocator.malloc_fn = pwt_alloc_malloc, o.allocator.realloc_fn = pwt_alloc_realloc, o.allocator.free_fn = pwt_alloc_free;
    pwt_alloc_fail_at = -1;
    REQUIRE(!pgp_builtin_mesh("sphere", &o, &mesh, NULL) && !pgp_builtin_tile("stripes", 32, &o, &tile, NULL) &&
            !pgp_create(&mesh, &o, &map, NULL));
    o.atlas.size = 64;
    before = pwt_alloc_live;
    for (pwt_alloc_fail_at = 0;; pwt_alloc_fail_at++) {
        pgp_atlas a;
        pgp_result r;
        pwt_alloc_calls = 0;
        r = pgp_bake_atlas(&map, &tile, &o, &a, NULL);
        if (r == PGP_OK) {
            pgp_atlas_free(&a);
            break;
        }
        if (pwt_alloc_live != before || r != PGP_ERR_NOMEM || a.uvs) bad++;
        points++;
    }
    pwt_alloc_fail_at = -1;
    pwt_info("%d allocation points, each failing in turn: NOMEM, no leak", points);
    CHECK(points > 5 && bad == 0 && pwt_alloc_live == before);
    pgp_map_free(&map);
    pgp_tile_free(&tile);
    pgp_mesh_free(&mesh);
    CHECK(pwt_alloc_live == 0);
}

static const pwt_case cases[] = {
    {"pgp_gltf/bake", t_bake},
    {"pgp_gltf/tile_atlas", t_tile_atlas},
    {"pgp_gltf/file", t_gltf},
    {"pgp_gltf/alloc_failures", t_alloc_failures},
};
PWT_MAIN(cases)
