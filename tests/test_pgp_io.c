/* Tests of pgp.h's files and built-in data: tiles in NRRD and as images,
 * the built-in tiles (periodic, layered, deterministic) and meshes, the
 * textured OBJ and the constraints file. The implementation is compiled in
 * here so that the tile generator can be checked directly. */
#define PGP_STATIC /* static: only what the tests call is compiled */
#define PGP_IMPLEMENTATION
#include "pgp.h"
#include "pwtest.h"

/* ---- helpers ------------------------------------------------------------- */

typedef struct membuf {
    unsigned char *data;
    size_t size, cap;
    int fail_after; /* > 0: the writer fails once this many bytes are written */
} membuf;

static int mem_write(void *ctx, const void *data, size_t size)
{
    membuf *b = (membuf *)ctx;
    if (b->fail_after > 0 && b->size + size > (size_t)b->fail_after) return -1;
    if (b->size + size + 1 > b->cap) {
        size_t cap = (b->size + size + 1) * 2;
        unsigned char *p = (unsigned char *)realloc(b->data, cap);
        if (!p) return -1;
        b->data = p;
        b->cap = cap;
    }
    memcpy(b->data + b->size, data, size);
    b->size += size;
    b->data[b->size] = 0; /* so that tests can read it as text */
    return 0;
}

static void mem_free(membuf *b)
{
    free(b->data);
    memset(b, 0, sizeof *b);
}

/* A tile whose samples are k/255 for a pattern of bytes k. */
static int make_tile(pgp_tile *t, int w, int h, int layers, int channels)
{
    size_t n = (size_t)w * h * layers * channels, i;
    memset(t, 0, sizeof *t);
    t->width = w, t->height = h, t->layers = layers, t->channels = channels;
    t->pixels = (float *)malloc(sizeof(float) * n);
    if (!t->pixels) return 0;
    for (i = 0; i < n; i++) t->pixels[i] = (float)((i * 37 + 11) % 256) / 255.0f;
    return 1;
}

static int same_bytes(const membuf *a, const membuf *b)
{
    return a->size == b->size && !memcmp(a->data, b->data, a->size);
}

/* Mean absolute difference between columns x0 and x1 (or rows, by_rows)
 * over all layers and channels of a tile. */
static double line_diff(const pgp_tile *t, int by_rows, int i0, int i1)
{
    double sum = 0.0;
    int z, j, k, n = by_rows ? t->width : t->height;
    for (z = 0; z < t->layers; z++)
        for (j = 0; j < n; j++)
            for (k = 0; k < t->channels; k++) {
                size_t a = by_rows ? ((size_t)(z * t->height + i0) * t->width + j) : ((size_t)(z * t->height + j) * t->width + i0);
                size_t b = by_rows ? ((size_t)(z * t->height + i1) * t->width + j) : ((size_t)(z * t->height + j) * t->width + i1);
                double d = t->pixels[a * t->channels + k] - t->pixels[b * t->channels + k];
                sum += d < 0 ? -d : d;
            }
    return sum / ((double)t->layers * n * t->channels);
}

/* ---- tiles: NRRD ------------------------------------------------------------ */

static void t_tile_nrrd_roundtrip(void)
{
    int c;
    for (c = 1; c <= 4; c++) {
        pgp_tile a, b;
        pgp_error err;
        membuf m1, m2;
        size_t i, n;
        char sizes[64];
        memset(&m1, 0, sizeof m1);
        memset(&m2, 0, sizeof m2);
        REQUIRE(make_tile(&a, 5, 4, 3, c));
        CHECKF(pgp_write_tile(&a, mem_write, &m1, &err) == PGP_OK, "write: %s", err.message);
        snprintf(sizes, sizeof sizes, c > 1 ? "sizes: %d 5 4 3\n" : "sizes: 5 4 3\n", c);
        CHECKF(m1.data && strstr((const char *)m1.data, sizes), "%d channels: no '%s' in the header", c, sizes);
        CHECK(m1.data && strstr((const char *)m1.data, c > 1 ? "dimension: 4\n" : "dimension: 3\n"));
        CHECK(m1.data && strstr((const char *)m1.data, "encoding: raw\n"));
        CHECKF(pgp_read_tile(m1.data, m1.size, "rt.nrrd", NULL, &b, &err) == PGP_OK, "read: %s", err.message);
        CHECK_EQ_INT(b.width, 5);
        CHECK_EQ_INT(b.height, 4);
        CHECK_EQ_INT(b.layers, 3);
        CHECK_EQ_INT(b.channels, c);
        n = (size_t)5 * 4 * 3 * c;
        for (i = 0; b.pixels && i < n; i++)
            if (b.pixels[i] != a.pixels[i]) {
                CHECKF(0, "%d channels: sample %lu is %.9g, was %.9g", c, (unsigned long)i, b.pixels[i], a.pixels[i]);
                break;
            }
        /* and written again, the same bytes */
        CHECK(pgp_write_tile(&b, mem_write, &m2, &err) == PGP_OK && same_bytes(&m1, &m2));
        pgp_tile_free(&b);
        free(a.pixels);
        mem_free(&m1);
        mem_free(&m2);
    }
}

/* Hand-written files: x is s, y the rows from the top, z the layers. */
static void t_tile_nrrd_layout(void)
{
    static const char head4[] = "NRRD0004\ntype: uchar\ndimension: 4\nsizes: 3 2 2 2\nencoding: raw\n\n";
    static const char head3[] = "NRRD0005\n# gray\ntype: uint8\ndimension: 3\nsizes: 4 3 2\nencoding: raw\n\n";
    unsigned char buf[256];
    pgp_tile t;
    pgp_error err;
    int i, ok;
    memcpy(buf, head4, sizeof head4 - 1);
    for (i = 0; i < 24; i++) buf[sizeof head4 - 1 + i] = (unsigned char)(10 * i);
    ok = pgp_read_tile(buf, sizeof head4 - 1 + 24, "d4.nrrd", NULL, &t, &err) == PGP_OK;
    REQUIRE(ok);
    CHECK(t.width == 2 && t.height == 2 && t.layers == 2 && t.channels == 3);
    for (i = 0; i < 24; i++) CHECK_NEAR(t.pixels[i], 10 * i / 255.0, 1e-6);
    /* texel (x=1, row 0, layer 1), green: ((1*2 + 0)*2 + 1)*3 + 1 */
    CHECK_NEAR(t.pixels[16], 160 / 255.0, 1e-6);
    pgp_tile_free(&t);
    memcpy(buf, head3, sizeof head3 - 1);
    for (i = 0; i < 24; i++) buf[sizeof head3 - 1 + i] = (unsigned char)i;
    REQUIRE(pgp_read_tile(buf, sizeof head3 - 1 + 24, "d3.nrrd", NULL, &t, &err) == PGP_OK);
    CHECK(t.width == 4 && t.height == 3 && t.layers == 2 && t.channels == 1);
    CHECK_NEAR(t.pixels[13], 13 / 255.0, 1e-6); /* x 1, row 0, layer 1 */
    pgp_tile_free(&t);
}

static void t_tile_nrrd_errors(void)
{
    static const char trunc[] = "NRRD0004\ntype: uint8\ndimension: 4\nsizes: 3 2 2 2\nencoding: raw\n\n\001\002";
    static const char bad[] = "NRRD0004\ntype: uint8\ndimension: 4\nsizes: 3 2 x 2\nencoding: raw\n\n";
    pgp_tile t, nan;
    pgp_error err;
    membuf m;
    memset(&m, 0, sizeof m);
    CHECK(pgp_read_tile(trunc, sizeof trunc - 1, "short.nrrd", NULL, &t, &err) == PGP_ERR_PARSE);
    CHECKF(strstr(err.message, "short.nrrd") != NULL, "message: %s", err.message);
    CHECK(t.pixels == NULL && t.layers == 0);
    CHECK(pgp_read_tile(bad, sizeof bad - 1, "bad.nrrd", NULL, &t, &err) == PGP_ERR_PARSE);
    CHECKF(strstr(err.message, "bad.nrrd:4") != NULL, "message: %s", err.message);
    CHECK(pgp_read_tile("hello", 5, "junk.bin", NULL, &t, &err) != PGP_OK);
    CHECK(pgp_read_tile(NULL, 4, "x", NULL, &t, &err) == PGP_ERR_INVALID);
    CHECK(pgp_read_tile("", 0, "empty", NULL, &t, &err) != PGP_OK);
    /* writing: bad shapes and samples are refused, writer failures reported */
    REQUIRE(make_tile(&nan, 3, 3, 2, 3));
    nan.channels = 5;
    CHECK(pgp_write_tile(&nan, mem_write, &m, &err) == PGP_ERR_INVALID && m.size == 0);
    nan.channels = 3;
    nan.layers = 0;
    CHECK(pgp_write_tile(&nan, mem_write, &m, &err) == PGP_ERR_INVALID && m.size == 0);
    nan.layers = 2;
    nan.pixels[7] = (float)NAN;
    CHECK(pgp_write_tile(&nan, mem_write, &m, &err) == PGP_ERR_INVALID && m.size == 0);
    CHECKF(strstr(err.message, "texel 2") != NULL, "message: %s", err.message);
    nan.pixels[7] = 0.5f;
    m.fail_after = 40;
    CHECK(pgp_write_tile(&nan, mem_write, &m, &err) == PGP_ERR_IO);
    CHECK(pgp_write_tile(NULL, mem_write, &m, &err) == PGP_ERR_INVALID);
    CHECK(pgp_write_tile(&nan, NULL, &m, &err) == PGP_ERR_INVALID);
    free(nan.pixels);
    mem_free(&m);
}

/* ---- tiles: 2D images ----------------------------------------------------------- */

static void t_tile_from_image(void)
{
    float px[2 * 3 * 3];
    pgp_image img;
    pgp_tile t;
    pgp_error err;
    membuf m;
    int i;
    memset(&img, 0, sizeof img);
    memset(&m, 0, sizeof m);
    for (i = 0; i < 18; i++) px[i] = (float)(i * 13 % 256) / 255.0f;
    img.width = 3, img.height = 2, img.channels = 3, img.pixels = px;
    REQUIRE(pgp_tile_from_image(&img, NULL, &t, &err) == PGP_OK);
    CHECK(t.width == 3 && t.height == 2 && t.layers == 1 && t.channels == 3);
    CHECK(t.pixels != px && !memcmp(t.pixels, px, sizeof px));
    pgp_tile_free(&t);
    /* through a PNG in memory: one layer with the image's texels */
    REQUIRE(pgp_write_image(&img, "png", mem_write, &m, &err) == PGP_OK);
    REQUIRE(pgp_read_tile(m.data, m.size, "x.png", NULL, &t, &err) == PGP_OK);
    CHECK(t.width == 3 && t.height == 2 && t.layers == 1 && t.channels == 3);
    for (i = 0; t.pixels && i < 18; i++) CHECK_NEAR(t.pixels[i], px[i], 1e-6);
    pgp_tile_free(&t);
    mem_free(&m);
    /* a gray PGM */
    REQUIRE(pgp_read_tile("P5\n2 1\n255\n\000\377", 13, "g.pgm", NULL, &t, &err) == PGP_OK);
    CHECK(t.width == 2 && t.height == 1 && t.layers == 1 && t.channels == 1);
    CHECK(t.pixels && t.pixels[0] == 0.0f && t.pixels[1] == 1.0f);
    pgp_tile_free(&t);
    /* refused images */
    px[4] = (float)NAN;
    CHECK(pgp_tile_from_image(&img, NULL, &t, &err) == PGP_ERR_INVALID && t.pixels == NULL);
    img.channels = 0;
    CHECK(pgp_tile_from_image(&img, NULL, &t, &err) == PGP_ERR_INVALID);
    CHECK(pgp_tile_from_image(NULL, NULL, &t, &err) == PGP_ERR_INVALID);
}

/* ---- built-in tiles ---------------------------------------------------------------- */

/* The generator itself: (s, t), (s + 1, t), (s, t + 1) and (s - 1, t - 1)
 * give the same colour up to rounding, in every layer. */
static void t_builtin_tiles_periodic_generator(void)
{
    pw_rng rng = pw_rng_seed(5, 1);
    double worst = 0.0;
    int kind, layer, i, k, j;
    for (kind = 0; kind < 2; kind++)
        for (layer = 0; layer < (kind == PGP__TILE_BRICKS ? 4 : 1); layer++)
            for (i = 0; i < 400; i++) {
                double s = pw_rng_double(&rng), t = pw_rng_double(&rng);
                static const double shift[3][2] = {{1, 0}, {0, 1}, {-1, -1}};
                float a[3], b[3];
                pgp__builtin B;
                B.kind = kind;
                B.seed = 3;
                B.layers = kind == PGP__TILE_BRICKS ? 4 : 1;
                B.px = 1.0 / 128;
                pgp__tile_texel(&B, layer, s, t, a);
                for (j = 0; j < 3; j++) {
                    pgp__tile_texel(&B, layer, s + shift[j][0], t + shift[j][1], b);
                    for (k = 0; k < 3; k++) {
                        double d = a[k] > b[k] ? a[k] - b[k] : b[k] - a[k];
                        worst = d > worst ? d : worst;
                    }
                }
            }
    CHECKF(worst < 2e-3, "a texel and its copy one period away differ by %g", worst);
    pwt_info("largest difference one period away: %g", worst);
}

/* The tiles: the texel after the last column (row) is column (row) 0, and
 * the step from the last column to the first is no larger than the largest
 * step between neighbours inside (no seam). */
static void t_builtin_tiles_periodic(void)
{
    static const char *const names[2] = {"bricks", "stripes"};
    int kind;
    for (kind = 0; kind < 2; kind++) {
        pgp_tile t;
        pgp_error err;
        double inside_c = 0.0, inside_r = 0.0, wrap_c, wrap_r, worst = 0.0;
        int x, y, z, k, n = 64;
        REQUIRE(pgp_builtin_tile(names[kind], n, NULL, &t, &err) == PGP_OK);
        for (z = 0; z < t.layers; z++)
            for (y = 0; y < n; y++) { /* column n is column 0, row n is row 0 */
                float c[3], r[3];
                pgp__builtin B;
                B.kind = kind;
                B.seed = 0;
                B.layers = t.layers;
                B.px = 1.0 / n;
                pgp__tile_texel(&B, z, (n + 0.5) / n, 1.0 - (y + 0.5) / n, c);
                pgp__tile_texel(&B, z, (y + 0.5) / n, 1.0 - (n + 0.5) / n, r);
                for (k = 0; k < 3; k++) {
                    double dc = c[k] - t.pixels[(((size_t)z * n + y) * n) * 3 + k];
                    double dr = r[k] - t.pixels[(((size_t)z * n) * n + y) * 3 + k];
                    dc = dc < 0 ? -dc : dc;
                    dr = dr < 0 ? -dr : dr;
                    worst = dc > worst ? dc : worst;
                    worst = dr > worst ? dr : worst;
                }
            }
        CHECKF(worst < 2e-3, "%s: the texel after the last column or row differs from the first by %g", names[kind], worst);
        for (x = 0; x + 1 < n; x++) {
            double dc = line_diff(&t, 0, x, x + 1), dr = line_diff(&t, 1, x, x + 1);
            inside_c = dc > inside_c ? dc : inside_c;
            inside_r = dr > inside_r ? dr : inside_r;
        }
        wrap_c = line_diff(&t, 0, n - 1, 0);
        wrap_r = line_diff(&t, 1, n - 1, 0);
        CHECKF(wrap_c <= inside_c + 1e-3, "%s: seam across s: %g, at most %g inside", names[kind], wrap_c, inside_c);
        CHECKF(wrap_r <= inside_r + 1e-3, "%s: seam across t: %g, at most %g inside", names[kind], wrap_r, inside_r);
        pgp_tile_free(&t);
    }
}

static double layer_diff(const pgp_tile *t, int a, int b)
{
    size_t n = (size_t)t->width * t->height * t->channels, i;
    double sum = 0.0;
    for (i = 0; i < n; i++) {
        double d = t->pixels[a * n + i] - t->pixels[b * n + i];
        sum += d < 0 ? -d : d;
    }
    return sum / n;
}

static void t_builtin_tiles(void)
{
    pgp_options o = pgp_default_options();
    pgp_tile a, b, c;
    pgp_error err;
    size_t i, n;
    double along_s = 0.0, along_t = 0.0;
    int x, y, k, inrange = 1;
    REQUIRE(pgp_builtin_tile("bricks", 64, &o, &a, &err) == PGP_OK);
    CHECK(a.width == 64 && a.height == 64 && a.layers == 4 && a.channels == 3);
    n = (size_t)64 * 64 * 4 * 3;
    for (i = 0; i < n; i++) inrange &= a.pixels[i] >= 0.0f && a.pixels[i] <= 1.0f;
    CHECK(inrange);
    /* the layers weather progressively: each further from the first */
    CHECKF(layer_diff(&a, 0, 1) > 0.03 && layer_diff(&a, 0, 2) > layer_diff(&a, 0, 1) &&
               layer_diff(&a, 0, 3) > layer_diff(&a, 0, 2),
           "layer differences %g %g %g", layer_diff(&a, 0, 1), layer_diff(&a, 0, 2), layer_diff(&a, 0, 3));
    /* deterministic, and the seed matters */
    REQUIRE(pgp_builtin_tile("bricks", 64, &o, &b, &err) == PGP_OK);
    CHECK(!memcmp(a.pixels, b.pixels, sizeof(float) * n));
    o.synth.seed = 9;
    REQUIRE(pgp_builtin_tile("bricks", 64, &o, &c, &err) == PGP_OK);
    CHECK(memcmp(a.pixels, c.pixels, sizeof(float) * n) != 0);
    pgp_tile_free(&a);
    pgp_tile_free(&b);
    pgp_tile_free(&c);
    /* stripes: one layer, bands across t (they vary along t, hardly along s) */
    REQUIRE(pgp_builtin_tile("stripes", 64, NULL, &a, &err) == PGP_OK);
    CHECK(a.width == 64 && a.height == 64 && a.layers == 1 && a.channels == 3);
    for (y = 0; y + 1 < 64; y++)
        for (x = 0; x + 1 < 64; x++)
            for (k = 0; k < 3; k++) {
                float p = a.pixels[(y * 64 + x) * 3 + k], ds = a.pixels[(y * 64 + x + 1) * 3 + k] - p;
                float dt = a.pixels[((y + 1) * 64 + x) * 3 + k] - p;
                along_s += ds < 0 ? -ds : ds;
                along_t += dt < 0 ? -dt : dt;
            }
    CHECKF(along_t > 4.0 * along_s, "stripes vary %g along t and %g along s", along_t, along_s);
    pgp_tile_free(&a);
    CHECK(pgp_builtin_tile("plaid", 64, NULL, &a, &err) == PGP_ERR_INVALID);
    CHECKF(strstr(err.message, "plaid") != NULL, "message: %s", err.message);
    CHECK(pgp_builtin_tile("bricks", 4, NULL, &a, &err) == PGP_ERR_INVALID);
    CHECK(pgp_builtin_tile(NULL, 64, NULL, &a, &err) == PGP_ERR_INVALID);
    CHECK(pgp_builtin_tile("bricks", 64, NULL, NULL, &err) == PGP_ERR_INVALID);
}

/* ---- built-in meshes ------------------------------------------------------------------ */

static void t_builtin_meshes(void)
{
    static const char *const names[4] = {"sphere", "torus", "bumpy", "grid"};
    static const int nv[4] = {1442, 8192, 2562, 1089}, nf[4] = {2880, 16384, 5120, 2048};
    pgp_mesh m;
    pgp_error err;
    int k, i, flat = 1;
    for (k = 0; k < 4; k++) {
        REQUIRE(pgp_builtin_mesh(names[k], NULL, &m, &err) == PGP_OK);
        CHECKF(m.nverts == nv[k] && m.nfaces == nf[k], "%s: %d vertices, %d faces", names[k], m.nverts, m.nfaces);
        CHECK(m.face_start[m.nfaces] == 3 * m.nfaces);
        if (k == 3)
            for (i = 0; i < m.nverts; i++) flat &= m.positions[3 * i + 2] == 0.0f;
        pgp_mesh_free(&m);
    }
    CHECK(flat);
    CHECK(pgp_builtin_mesh("teapot", NULL, &m, &err) == PGP_ERR_INVALID);
    CHECKF(strstr(err.message, "teapot") != NULL, "message: %s", err.message);
    CHECK(pgp_builtin_mesh(NULL, NULL, &m, &err) == PGP_ERR_INVALID);
}

/* ---- meshes and images from memory ----------------------------------------------------- */

static void t_mesh_image_memory(void)
{
    static const char obj[] = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
    float px[4] = {0.0f, 0.25f, 0.5f, 1.0f};
    pgp_image img;
    pgp_mesh m;
    pgp_error err;
    membuf b;
    memset(&b, 0, sizeof b);
    REQUIRE(pgp_read_mesh(obj, sizeof obj - 1, "quad.obj", NULL, &m, &err) == PGP_OK);
    CHECK(m.nverts == 4 && m.nfaces == 1 && m.face_start[1] == 4);
    pgp_mesh_free(&m);
    CHECK(pgp_read_mesh("v 0 0 0\nf 1 2 x\n", 16, "bad.obj", NULL, &m, &err) != PGP_OK);
    CHECKF(strstr(err.message, "bad.obj:2") != NULL, "message: %s", err.message);
    memset(&img, 0, sizeof img);
    img.width = 2, img.height = 2, img.channels = 1, img.pixels = px;
    REQUIRE(pgp_write_image(&img, "pgm", mem_write, &b, &err) == PGP_OK);
    CHECK(b.size == 11 + 4 && !memcmp(b.data, "P5\n2 2\n255\n", 11));
    REQUIRE(pgp_read_image(b.data, b.size, "x.pgm", NULL, &img, &err) == PGP_OK);
    CHECK(img.width == 2 && img.height == 2 && img.channels == 1 && img.pixels[3] == 1.0f && img.pixels[0] == 0.0f);
    pgp_image_free(&img);
    CHECK(pgp_read_image("P5\n2 2\n255\n", 11, "short.pgm", NULL, &img, &err) == PGP_ERR_PARSE && !img.pixels);
    CHECKF(strstr(err.message, "short.pgm") != NULL, "message: %s", err.message);
    CHECK(pgp_read_image(NULL, 3, "x", NULL, &img, &err) == PGP_ERR_INVALID);
    img.width = 2, img.height = 2, img.channels = 1, img.pixels = px;
    CHECK(pgp_write_image(&img, "gif", mem_write, &b, &err) == PGP_ERR_UNSUPPORTED);
    mem_free(&b);
}

/* ---- the textured OBJ -------------------------------------------------------------------- */

/* Parses the OBJ of a map: counts, groups in order, faces in triangle
 * order within each group with vt 3f+1..3f+3, and the vt values equal to
 * pgp_map.coords. */
static void check_obj(const char *text, const pgp_map *map, const pgp_mesh *mesh)
{
    int nf = map->ntris, nv = map->nverts, nsing = pgp_map_singular(map, NULL);
    const float *stm = map->coords;
    unsigned char *sing = (unsigned char *)malloc((size_t)nf);
    int v = 0, vt = 0, f = 0, group = -1, last = -1, bad = 0, fsing = 0, badvt = 0, badv = 0, k;
    const char *p = text;
    pgp_map_singular(map, sing);
    while (*p) {
        const char *e = strchr(p, '\n');
        if (!e) e = p + strlen(p);
        if (!strncmp(p, "v ", 2)) {
            float x, y, z;
            if (sscanf(p, "v %f %f %f", &x, &y, &z) != 3 || x != mesh->positions[3 * v] || y != mesh->positions[3 * v + 1] ||
                z != mesh->positions[3 * v + 2])
                badv++;
            v++;
        } else if (!strncmp(p, "vt ", 3)) {
            float s, t, m;
            if (vt >= 3 * nf || sscanf(p, "vt %f %f %f", &s, &t, &m) != 3 || s != stm[3 * vt] || t != stm[3 * vt + 1] ||
                m != stm[3 * vt + 2])
                badvt++;
            vt++;
        } else if (!strncmp(p, "g regular", 9)) {
            bad += group != -1 || f != 0;
            group = 0, last = -1;
        } else if (!strncmp(p, "g singular", 10)) {
            bad += group != 0;
            group = 1, last = -1;
        } else if (!strncmp(p, "f ", 2)) {
            int a[3], t[3], tri;
            if (sscanf(p, "f %d/%d %d/%d %d/%d", &a[0], &t[0], &a[1], &t[1], &a[2], &t[2]) != 6 || group < 0) {
                bad++;
            } else {
                tri = (t[0] - 1) / 3;
                for (k = 0; k < 3; k++) bad += t[k] != 3 * tri + k + 1 || a[k] < 1 || a[k] > nv;
                bad += tri <= last || tri >= nf || sing[tri] != group;
                bad += tri < nf && a[0] - 1 != mesh->face_verts[3 * tri];
                last = tri;
                fsing += group;
            }
            f++;
        } else if (*p != '#') {
            bad++;
        }
        p = *e ? e + 1 : e;
    }
    CHECK_EQ_INT(v, nv);
    CHECK_EQ_INT(vt, 3 * nf);
    CHECK_EQ_INT(f, nf);
    CHECK_EQ_INT(fsing, nsing);
    CHECK_EQ_INT(group, 1);
    CHECK_EQ_INT(bad, 0);
    CHECK_EQ_INT(badv, 0);
    CHECK_EQ_INT(badvt, 0);
    free(sing);
}

static void t_obj_writer(void)
{
    pgp_options o = pgp_default_options();
    pgp_mesh mesh, grid;
    pgp_map map;
    pgp_error err;
    membuf b;
    memset(&b, 0, sizeof b);
    o.scale = 0.35f;
    REQUIRE(pgp_builtin_mesh("sphere", &o, &mesh, &err) == PGP_OK);
    REQUIRE(pgp_create(&mesh, &o, &map, &err) == PGP_OK);
    CHECKF(pgp_map_singular(&map, NULL) > 0, "the sphere has no singular triangles to group");
    CHECKF(pgp_write_obj(&mesh, &map, mem_write, &b, &err) == PGP_OK, "%s", err.message);
    if (b.data) check_obj((const char *)b.data, &map, &mesh);
    /* the same without the mesh */
    {
        membuf c;
        memset(&c, 0, sizeof c);
        CHECK(pgp_write_obj(NULL, &map, mem_write, &c, &err) == PGP_OK && same_bytes(&b, &c));
        mem_free(&c);
    }
    /* another mesh, a failing writer, NULL arguments */
    REQUIRE(pgp_builtin_mesh("grid", &o, &grid, &err) == PGP_OK);
    CHECK(pgp_write_obj(&grid, &map, mem_write, &b, &err) == PGP_ERR_INVALID);
    mesh.face_verts[4] = mesh.face_verts[5];
    CHECK(pgp_write_obj(&mesh, &map, mem_write, &b, &err) == PGP_ERR_INVALID);
    CHECKF(strstr(err.message, "face 1") != NULL, "message: %s", err.message);
    mem_free(&b);
    b.fail_after = 100;
    CHECK(pgp_write_obj(NULL, &map, mem_write, &b, &err) == PGP_ERR_IO);
    CHECK(pgp_write_obj(NULL, NULL, mem_write, &b, &err) == PGP_ERR_INVALID);
    CHECK(pgp_write_obj(NULL, &map, NULL, &b, &err) == PGP_ERR_INVALID);
    mem_free(&b);
    pgp_map_free(&map);
    CHECK(pgp_write_obj(NULL, &map, mem_write, &b, &err) == PGP_ERR_INVALID); /* a freed map is empty */
    pgp_mesh_free(&mesh);
    pgp_mesh_free(&grid);
}

/* ---- constraints files ---------------------------------------------------------------------- */

/* The grid map with the constraints of a file's text (NULL text: none). */
static pgp_result grid_map(const char *text, pgp_mesh *mesh, pgp_map *map, pgp_error *err)
{
    pgp_options o = pgp_default_options();
    pgp_constraints cons;
    pgp_result r;
    memset(&cons, 0, sizeof cons);
    o.scale = 0.5f;
    memset(map, 0, sizeof *map);
    if ((r = pgp_builtin_mesh("grid", &o, mesh, err)) != PGP_OK) return r;
    if (text && (r = pgp_read_constraints(text, strlen(text), "c.txt", &o, &cons, err)) != PGP_OK) return r;
    o.constraints = cons.items;
    o.nconstraints = cons.count;
    r = pgp_create(mesh, &o, map, err);
    pgp_constraints_free(&cons);
    return r;
}

static void t_constraints_good(void)
{
    static const char text[] = "\xEF\xBB\xBF# a constraints file\r\n\r\nradius 0.6\r\nmaterial 10 1\r\n"
                               "scale 500 0.3   # a comment\r\norient 700 1 1 0\r\nradius 0\r\n"
                               "  material\t1000 0.25\r\n";
    pgp_constraints cons;
    pgp_mesh mesh;
    pgp_map map;
    pgp_field fd;
    pgp_error err;
    REQUIRE(pgp_read_constraints(text, sizeof text - 1, "good.txt", NULL, &cons, &err) == PGP_OK);
    CHECK_EQ_INT(cons.count, 4);
    CHECK(cons.items[0].kind == PGP_CONSTRAINT_MATERIAL && cons.items[0].element == 10 && cons.items[0].value[0] == 1.0f &&
          cons.items[0].radius == 0.6f);
    CHECK(cons.items[1].kind == PGP_CONSTRAINT_SCALE && cons.items[1].element == 500 && cons.items[1].value[0] == 0.3f);
    CHECK(cons.items[2].kind == PGP_CONSTRAINT_ORIENT && cons.items[2].element == 700 && cons.items[2].value[1] == 1.0f &&
          cons.items[2].value[2] == 0.0f && cons.items[2].radius == 0.6f);
    CHECK(cons.items[3].kind == PGP_CONSTRAINT_MATERIAL && cons.items[3].radius == 0.0f);
    pgp_constraints_free(&cons);
    CHECK(cons.items == NULL && cons.count == 0);
    pgp_constraints_free(&cons); /* zeroed: nothing to do */
    CHECKF(grid_map(text, &mesh, &map, &err) == PGP_OK, "%s", err.message);
    REQUIRE(pgp_map_field(&map, &fd, &err) == PGP_OK);
    CHECK_NEAR(fd.material[10], 1.0, 1e-6);
    CHECK_NEAR(fd.material[1000], 0.25, 1e-6);
    CHECK_NEAR(fd.scale[500], 0.3, 1e-6);
    /* triangle 700 points along (1, 1, 0) */
    CHECK_NEAR(fd.dir[3 * 700] * 0.70710678, 0.5, 1e-3);
    CHECK_NEAR(fd.dir[3 * 700 + 1] * 0.70710678, 0.5, 1e-3);
    pgp_field_free(&fd);
    pgp_map_free(&map);
    pgp_mesh_free(&mesh);
}

/* Each bad file fails with its code, and the message names file:line; the
 * elements that do not exist on the mesh fail when the constraints are
 * applied, naming the constraint. */
static void t_constraints_bad(void)
{
    static const struct {
        const char *text, *where, *what;
        pgp_result code;
    } cases[] = {
        {"material 3 0.5\ncolour 1 2 3\n", "c.txt:2:", "unknown keyword 'colour'", PGP_ERR_PARSE},
        {"scale 3 abc\n", "c.txt:1:", "malformed", PGP_ERR_PARSE},
        {"# c\nscale 3.5 1\n", "c.txt:2:", "malformed integer", PGP_ERR_PARSE},
        {"material 3 nan\n", "c.txt:1:", "not a finite number", PGP_ERR_INVALID},
        {"radius inf\nmaterial 3 1\n", "c.txt:1:", "not a finite number", PGP_ERR_INVALID},
        {"scale 3 1e99\n", "c.txt:1:", "not a finite number", PGP_ERR_INVALID},
        {"\n\norient 99999 1 0 0\n", "constraint 0:", "triangle 99999 does not exist", PGP_ERR_INVALID},
        {"material 1 1\norient 2048 1 0 0\n", "constraint 1:", "triangle 2048", PGP_ERR_INVALID},
        {"scale -1 0.5\n", "c.txt:1:", "vertex -1 does not exist", PGP_ERR_INVALID},
        {"material 1089 0.5\n", "constraint 0:", "vertex 1089", PGP_ERR_INVALID},
        {"orient 5 1 0\n", "c.txt:1:", "missing", PGP_ERR_PARSE},
        {"scale 3 0.5 7\n", "c.txt:1:", "unexpected text after 'scale'", PGP_ERR_PARSE},
        {"material 3 1.5\n", "c.txt:1:", "material", PGP_ERR_INVALID},
        {"scale 3 0\n", "c.txt:1:", "scale", PGP_ERR_INVALID},
        {"orient 5 0 0 0\n", "c.txt:1:", "orientation", PGP_ERR_INVALID},
        {"orient 5 0 0 1\n", "constraint 0:", "normal to the triangle", PGP_ERR_INVALID},
        {"# nothing\n\n", "c.txt", "no constraints", PGP_ERR_PARSE},
        {"radius 2\n", "c.txt", "no constraints", PGP_ERR_PARSE},
        {"", "c.txt", "no constraints", PGP_ERR_PARSE},
    };
    pgp_constraints cons;
    pgp_mesh mesh;
    pgp_map map;
    pgp_error err;
    size_t k;
    for (k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        pgp_result r = grid_map(cases[k].text, &mesh, &map, &err);
        CHECKF(r == cases[k].code, "case %d: code %d, expected %d (%s)", (int)k, (int)r, (int)cases[k].code, err.message);
        CHECKF(!strncmp(err.message, cases[k].where, strlen(cases[k].where)) && strstr(err.message, cases[k].what),
               "case %d: message '%s' lacks '%s' or '%s'", (int)k, err.message, cases[k].where, cases[k].what);
        CHECK(map.state == NULL);
        pgp_mesh_free(&mesh);
    }
    CHECK(pgp_read_constraints(NULL, 9, "x", NULL, &cons, &err) == PGP_ERR_INVALID);
    CHECK(pgp_read_constraints("scale 1 1", 9, "x", NULL, NULL, &err) == PGP_ERR_INVALID);
}

/* ---- files ------------------------------------------------------------------------------------- */

static void t_files(void)
{
    const char *nrrd = pwt_tmp("pgp_io", 0, ".nrrd"), *obj = pwt_tmp("pgp_io", 1, ".obj");
    const char *cfile = pwt_tmp("pgp_io", 2, ".txt"), *png = pwt_tmp("pgp_io", 3, ".png");
    pgp_tile a, b;
    pgp_mesh mesh, back;
    pgp_image img;
    pgp_constraints cons;
    pgp_map map;
    pgp_error err;
    FILE *f;
    REQUIRE(make_tile(&a, 6, 5, 2, 3));
    CHECKF(pgp_save_tile(nrrd, &a, &err) == PGP_OK, "%s", err.message);
    CHECKF(pgp_load_tile(nrrd, NULL, &b, &err) == PGP_OK, "%s", err.message);
    CHECK(b.width == 6 && b.height == 5 && b.layers == 2 && b.channels == 3 && b.pixels &&
          !memcmp(a.pixels, b.pixels, sizeof(float) * 180));
    pgp_tile_free(&b);
    CHECK(pgp_save_tile(png, &a, &err) == PGP_ERR_UNSUPPORTED);
    CHECK(pgp_load_tile("/nonexistent/x.nrrd", NULL, &b, &err) == PGP_ERR_IO);
    CHECKF(strstr(err.message, "/nonexistent/x.nrrd") != NULL, "message: %s", err.message);
    free(a.pixels);
    REQUIRE(grid_map(NULL, &mesh, &map, &err) == PGP_OK);
    CHECKF(pgp_save_obj(obj, &mesh, &map, &err) == PGP_OK, "%s", err.message);
    CHECKF(pgp_load_mesh(obj, NULL, &back, &err) == PGP_OK, "%s", err.message); /* it reads as a mesh */
    CHECK(back.nverts == mesh.nverts && back.nfaces == mesh.nfaces);
    pgp_mesh_free(&back);
    REQUIRE((f = fopen(cfile, "wb")) != NULL);
    fputs("radius 0\nmaterial 0 1\nmaterial 1088 0.5\n", f);
    fclose(f);
    CHECKF(pgp_load_constraints(cfile, NULL, &cons, &err) == PGP_OK, "%s", err.message);
    CHECK(cons.count == 2 && cons.items[1].kind == PGP_CONSTRAINT_MATERIAL && cons.items[1].element == 1088 &&
          cons.items[1].value[0] == 0.5f);
    pgp_constraints_free(&cons);
    CHECK(pgp_load_constraints("/nonexistent/c.txt", NULL, &cons, &err) == PGP_ERR_IO && !cons.items);
    REQUIRE((f = fopen(cfile, "wb")) != NULL);
    fputs("material 0 1\nmaterial 1088 2\n", f);
    fclose(f);
    CHECK(pgp_load_constraints(cfile, NULL, &cons, &err) == PGP_ERR_INVALID && !cons.items);
    CHECKF(!strncmp(err.message, cfile, strlen(cfile)) && strstr(err.message, ":2:"), "message: %s", err.message);
    REQUIRE(pgp_builtin_tile("stripes", 16, NULL, &a, &err) == PGP_OK);
    memset(&img, 0, sizeof img);
    img.width = 16, img.height = 16, img.channels = 3, img.pixels = a.pixels;
    CHECKF(pgp_save_image(png, &img, &err) == PGP_OK, "%s", err.message);
    CHECKF(pgp_load_tile(png, NULL, &b, &err) == PGP_OK, "%s", err.message);
    CHECK(b.width == 16 && b.layers == 1 && b.channels == 3);
    pgp_tile_free(&b);
    pgp_tile_free(&a);
    pgp_map_free(&map);
    pgp_mesh_free(&mesh);
    remove(nrrd);
    remove(obj);
    remove(cfile);
    remove(png);
}

static const pwt_case cases[] = {
    {"pgp_io/tile_nrrd_roundtrip", t_tile_nrrd_roundtrip},
    {"pgp_io/tile_nrrd_layout", t_tile_nrrd_layout},
    {"pgp_io/tile_nrrd_errors", t_tile_nrrd_errors},
    {"pgp_io/tile_from_image", t_tile_from_image},
    {"pgp_io/builtin_tiles_periodic_generator", t_builtin_tiles_periodic_generator},
    {"pgp_io/builtin_tiles_periodic", t_builtin_tiles_periodic},
    {"pgp_io/builtin_tiles", t_builtin_tiles},
    {"pgp_io/builtin_meshes", t_builtin_meshes},
    {"pgp_io/mesh_image_memory", t_mesh_image_memory},
    {"pgp_io/obj_writer", t_obj_writer},
    {"pgp_io/constraints_good", t_constraints_good},
    {"pgp_io/constraints_bad", t_constraints_bad},
    {"pgp_io/files", t_files},
};
PWT_MAIN(cases)
