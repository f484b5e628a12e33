/* Tests of tiled.h through its public API (and, where a test needs to
 * look inside, the shared core compiled into this file). */
#define TILED_STATIC /* static: only what the tests call is compiled */
#define TILED_IMPLEMENTATION
#include "../tiled.h"
#include "pwtest.h"

/* ---- helpers ----------------------------------------------------------- */

static tiled_options opts(int case_number, int n)
{
    tiled_options o = tiled_default_options();
    o.layout.case_number = case_number;
    if (case_number == 1) o.layout.grid = n;
    else o.layout.pairs = n;
    return o;
}

/* Where a corner's texture coordinates land: tile (col,row) and the tile
 * corner 0..3 (0 lower-left, counter-clockwise). */
typedef struct corner_at {
    int col, row, corner;
} corner_at;

static corner_at decode(const tiled_tileset *ts, const float *uv)
{
    static const int corner_of[2][2] = {{0, 3}, {1, 2}}; /* [du][dv] */
    corner_at c;
    int T = ts->layout.tile_size, g = ts->layout.guard < 0 ? 0 : ts->layout.guard, C = T + 2 * g;
    double W = (double)ts->tiles_per_side * C, x = uv[0] * W, y = uv[1] * W;
    int du, dv;
    c.col = (int)((x + 0.5) / C);
    c.row = (int)((y + 0.5) / C);
    if (c.col >= ts->tiles_per_side) c.col = ts->tiles_per_side - 1;
    if (c.row >= ts->tiles_per_side) c.row = ts->tiles_per_side - 1;
    du = x - c.col * C - g > 0.5 * T;
    dv = y - c.row * C - g > 0.5 * T;
    c.corner = corner_of[du][dv];
    return c;
}

/* A layout-only tile set (no atlas) for mapping tests. */
static tiled_tileset layout_only(int case_number, int n, int guard)
{
    tiled_tileset ts;
    memset(&ts, 0, sizeof ts);
    ts.layout.case_number = case_number;
    ts.layout.pairs = case_number == 2 ? n : 1;
    ts.layout.grid = case_number == 1 ? n : 4;
    ts.layout.tile_size = 64;
    ts.layout.guard = guard;
    ts.tiles_per_side = case_number == 1 ? n : 4 * n * n;
    return ts;
}

/* Per half-edge of a mapped quad mesh: the tile side it lies on, whether
 * it walks the side in the tile's counter-clockwise direction, and the
 * side's boundary type read from the tile's name (position in the atlas).
 * Returns 0 if a face's corners are not the four corners of one tile. */
static int sides_of(const tiled_tileset *ts, const tiled_mesh *m, int *side, int *forward, int *type)
{
    int f, k, n = ts->layout.case_number == 1 ? 1 : 2 * ts->layout.pairs;
    for (f = 0; f < m->nfaces; f++) {
        int h0 = m->face_start[f];
        corner_at c[4];
        if (m->face_start[f + 1] - h0 != 4) return 0;
        for (k = 0; k < 4; k++) c[k] = decode(ts, m->uvs + 2 * (h0 + k));
        for (k = 0; k < 4; k++) {
            corner_at a = c[k], b = c[(k + 1) & 3];
            int fwd = (b.corner - a.corner + 4) % 4 == 1, bwd = (a.corner - b.corner + 4) % 4 == 1;
            int s = fwd ? a.corner : b.corner, e[4];
            if (a.col != c[0].col || a.row != c[0].row || (!fwd && !bwd)) return 0;
            e[0] = a.col / n;
            e[1] = a.col % n;
            e[2] = a.row / n;
            e[3] = a.row % n;
            side[h0 + k] = s;
            forward[h0 + k] = fwd;
            type[h0 + k] = ts->layout.case_number == 1 ? 0 : e[s];
        }
    }
    return 1;
}

/* Twin of each corner's half-edge (-1 on the boundary), from a sorted
 * list of undirected edges: independent of the library's half-edge code. */
typedef struct he_key {
    int lo, hi, h;
} he_key;

static int he_cmp(const void *x, const void *y)
{
    const he_key *p = (const he_key *)x, *q = (const he_key *)y;
    if (p->lo != q->lo) return p->lo < q->lo ? -1 : 1;
    if (p->hi != q->hi) return p->hi < q->hi ? -1 : 1;
    return p->h - q->h;
}

static int next_corner(const tiled_mesh *m, int f, int k)
{
    return k + 1 < m->face_start[f + 1] ? k + 1 : m->face_start[f];
}

static int *twins_of(const tiled_mesh *m)
{
    int nc = m->face_start[m->nfaces], f, k, *tw = (int *)malloc(sizeof(int) * nc);
    he_key *keys = (he_key *)malloc(sizeof(he_key) * nc);
    for (f = 0; f < m->nfaces; f++)
        for (k = m->face_start[f]; k < m->face_start[f + 1]; k++) {
            int a = m->face_verts[k], b = m->face_verts[next_corner(m, f, k)];
            keys[k].lo = a < b ? a : b;
            keys[k].hi = a < b ? b : a;
            keys[k].h = k;
            tw[k] = -1;
        }
    qsort(keys, nc, sizeof *keys, he_cmp);
    for (k = 0; k + 1 < nc; k++)
        if (keys[k].lo == keys[k + 1].lo && keys[k].hi == keys[k + 1].hi) {
            tw[keys[k].h] = keys[k + 1].h;
            tw[keys[k + 1].h] = keys[k].h;
        }
    free(keys);
    return tw;
}

static int *faces_of_corners(const tiled_mesh *m)
{
    int f, k, *fc = (int *)malloc(sizeof(int) * m->face_start[m->nfaces]);
    for (f = 0; f < m->nfaces; f++)
        for (k = m->face_start[f]; k < m->face_start[f + 1]; k++) fc[k] = f;
    return fc;
}

/* The Fig. 29 invariants on a mapped mesh: every face's corners are one
 * tile's corners; across every interior edge the two sides have partner
 * types (2k, 2k+1; case 1: the same type) and are walked in opposite
 * directions. Returns the number of interior edges checked (or -1). */
static int check_edges(const tiled_tileset *ts, const tiled_mesh *m)
{
    int nc = m->face_start[m->nfaces], k, bad = 0, edges = 0;
    int *side = (int *)malloc(sizeof(int) * nc), *fwd = (int *)malloc(sizeof(int) * nc);
    int *type = (int *)malloc(sizeof(int) * nc), *tw = twins_of(m);
    int ok = sides_of(ts, m, side, fwd, type);
    CHECKF(ok, "a face's corners are not the corners of one tile");
    for (k = 0; ok && k < nc; k++) {
        int t = tw[k];
        if (t < 0 || t < k) continue;
        edges++;
        if (ts->layout.case_number == 2 ? (type[k] ^ 1) != type[t] : type[k] != type[t]) bad++;
        if (ts->layout.case_number == 2 && (!fwd[k] || !fwd[t])) bad++;
        if (m->corner_types && m->corner_types[k] != type[k]) bad++;
    }
    CHECKF(bad == 0, "%d of %d interior edges break the tile invariants", bad, edges);
    free(side);
    free(fwd);
    free(type);
    free(tw);
    return ok && !bad ? edges : -1;
}

/* Texel next to half-edge h at distance x along it from its start vertex
 * (inside the tile, first row). */
static const float *texel_at(const tiled_tileset *ts, const tiled_mesh *m, const int *side,
                             const int *fwd, const int *fc, int h, int x)
{
    tiled__geom gm = tiled__geometry(&ts->layout);
    pw_image atlas = tiled__pw_image(&ts->atlas);
    int T = gm.T, a = fwd[h] ? x : T - 1 - x, i, j;
    tiled__from_side(side[h], T, a, 0, &i, &j);
    return tiled__atlas_px(&atlas, &gm, m->face_tiles[fc[h]], i, j);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* What neighbouring texels inside tiles differ by: the mean colour jump
 * between every pair of adjacent rows and of adjacent columns of every
 * tile (lines as long as an edge), and the 90th percentile of those line
 * means. An edge's seam is a line pair too, so it looks like the interior
 * when it stays within that spread. */
static double interior_jump(const tiled_tileset *ts, double *p90)
{
    tiled__geom gm = tiled__geometry(&ts->layout);
    pw_image atlas = tiled__pw_image(&ts->atlas);
    int t, i, j, n = 0, T = gm.T;
    double *lines = (double *)malloc(sizeof(double) * 2 * gm.N * gm.N * T), sum = 0.0;
    for (t = 0; t < gm.N * gm.N; t++)
        for (j = 0; j + 1 < T; j++) {
            double row = 0.0, col = 0.0;
            for (i = 0; i < T; i++) {
                row += tiled__dist(tiled__atlas_px(&atlas, &gm, t, i, j), tiled__atlas_px(&atlas, &gm, t, i, j + 1), atlas.c);
                col += tiled__dist(tiled__atlas_px(&atlas, &gm, t, j, i), tiled__atlas_px(&atlas, &gm, t, j + 1, i), atlas.c);
            }
            lines[n++] = row / T;
            lines[n++] = col / T;
            sum += (row + col) / T;
        }
    qsort(lines, (size_t)n, sizeof *lines, cmp_double);
    *p90 = lines[(int)(0.9 * (n - 1))];
    free(lines);
    return sum / n;
}

/* Mean colour jump across the mesh's interior edges, texel against texel;
 * also the worst edge's mean. */
static double seam_jump(const tiled_tileset *ts, const tiled_mesh *m, double *worst)
{
    int nc = m->face_start[m->nfaces], k, x, T = ts->layout.tile_size, c = ts->atlas.channels;
    int *side = (int *)malloc(sizeof(int) * nc), *fwd = (int *)malloc(sizeof(int) * nc);
    int *type = (int *)malloc(sizeof(int) * nc), *tw = twins_of(m), *fc = faces_of_corners(m);
    double sum = 0.0;
    long n = 0;
    *worst = 0.0;
    if (sides_of(ts, m, side, fwd, type))
        for (k = 0; k < nc; k++) {
            double edge = 0.0;
            if (tw[k] < k) continue;
            for (x = 0; x < T; x++)
                edge += tiled__dist(texel_at(ts, m, side, fwd, fc, k, x),
                                    texel_at(ts, m, side, fwd, fc, tw[k], T - 1 - x), c);
            sum += edge;
            n += T;
            if (edge / T > *worst) *worst = edge / T;
        }
    free(side);
    free(fwd);
    free(type);
    free(tw);
    free(fc);
    return n ? sum / (double)n : -1.0;
}

/* ---- tests ----------------------------------------------------------------- */

/* Fig. 29 with the erratum fixed, on the thesis layout (no guard): corner i
 * of tile e0e1e2e3 is at ((2n e0 + e1 + j)/(4n^2), (2n e2 + e3 + i/2)/(4n^2)),
 * j = ((i+1) mod 4)/2. The printed floor(j/2) would put every corner at u
 * offset 0. */
static void t_fig29_formula(void)
{
    int n, f, k;
    for (n = 1; n <= 3; n++) {
        tiled_tileset ts = layout_only(2, n, TILED_NO_GUARD);
        tiled_options o = opts(2, n);
        tiled_mesh mesh, q;
        tiled_error err;
        int bad = 0;
        REQUIRE(tiled_builtin_mesh("torus", &o, &mesh, &err) == TILED_OK);
        REQUIRE(tiled_map(&mesh, &ts.layout, &o, &q, &err) == TILED_OK);
        for (f = 0; f < q.nfaces; f++) {
            int e[4], tile = q.face_tiles[f], N = 4 * n * n, fixed = 0;
            e[0] = (tile % N) / (2 * n);
            e[1] = (tile % N) % (2 * n);
            e[2] = (tile / N) / (2 * n);
            e[3] = (tile / N) % (2 * n);
            for (k = 0; k < 4; k++) {
                const float *uv = q.uvs + 2 * (q.face_start[f] + k);
                int i;
                for (i = 0; i < 4; i++) {
                    int j = ((i + 1) % 4) / 2;
                    double u = (2.0 * n * e[0] + e[1] + j) / (4.0 * n * n);
                    double v = (2.0 * n * e[2] + e[3] + i / 2) / (4.0 * n * n);
                    if (fabs(uv[0] - u) < 1e-6 && fabs(uv[1] - v) < 1e-6) fixed++;
                }
            }
            bad += fixed != 4;
        }
        CHECKF(bad == 0, "n=%d: %d faces' corners do not follow the corrected formula", n, bad);
        tiled_mesh_free(&mesh);
        tiled_mesh_free(&q);
    }
}

/* Thousands of quads, genus 1 and 2, n = 1..3: partner types across every
 * edge, walked in opposite directions. */
static void t_edge_invariants(void)
{
    static const char *meshes[3] = {"torus", "double-torus", "grid"};
    int n, k, total = 0;
    for (k = 0; k < 3; k++)
        for (n = 1; n <= 3; n++) {
            tiled_tileset ts = layout_only(2, n, 0);
            tiled_options o = opts(2, n);
            tiled_mesh mesh, q;
            tiled_error err;
            o.subdivide = k == 1 ? 3 : 2;
            o.seed = (unsigned long long)(n * 10 + k);
            ts.layout.guard = 8;
            REQUIRE(tiled_builtin_mesh(meshes[k], &o, &mesh, &err) == TILED_OK);
            REQUIRE(tiled_map(&mesh, &ts.layout, &o, &q, &err) == TILED_OK);
            total += check_edges(&ts, &q);
            tiled_mesh_free(&mesh);
            tiled_mesh_free(&q);
        }
    pwt_info("%d interior edges checked", total);
}

static void t_case1_invariants(void)
{
    tiled_tileset ts = layout_only(1, 3, 0);
    tiled_options o = opts(1, 3);
    tiled_mesh mesh, q;
    tiled_error err;
    int f, used[9] = {0}, flips = 0, nc, k, *side, *fwd, *type;
    ts.layout.guard = 8;
    o.subdivide = 2;
    REQUIRE(tiled_builtin_mesh("double-torus", &o, &mesh, &err) == TILED_OK);
    REQUIRE(tiled_map(&mesh, &ts.layout, &o, &q, &err) == TILED_OK);
    CHECK(check_edges(&ts, &q) > 1000);
    nc = q.face_start[q.nfaces];
    side = (int *)malloc(sizeof(int) * nc);
    fwd = (int *)malloc(sizeof(int) * nc);
    type = (int *)malloc(sizeof(int) * nc);
    REQUIRE(sides_of(&ts, &q, side, fwd, type));
    for (f = 0; f < q.nfaces; f++) {
        used[q.face_tiles[f]] = 1;
        flips += !fwd[q.face_start[f]];
    }
    for (k = 0; k < 9; k++) CHECKF(used[k], "tile %d never used", k);
    CHECKF(flips > q.nfaces / 4 && flips < 3 * q.nfaces / 4, "%d of %d faces mirrored", flips, q.nfaces);
    o.no_mirror = 1;
    tiled_mesh_free(&q);
    REQUIRE(tiled_map(&mesh, &ts.layout, &o, &q, &err) == TILED_OK);
    REQUIRE(sides_of(&ts, &q, side, fwd, type));
    for (f = flips = 0; f < q.nfaces; f++) flips += !fwd[q.face_start[f]];
    CHECK_EQ_INT(flips, 0);
    free(side);
    free(fwd);
    free(type);
    tiled_mesh_free(&mesh);
    tiled_mesh_free(&q);
}

/* Random starting edge: each face's tile walk starts at any of its four
 * corners; fixed_start pins it to the first. */
static void t_random_start(void)
{
    tiled_tileset ts = layout_only(2, 1, 8);
    tiled_options o = opts(2, 1);
    tiled_mesh mesh, q;
    tiled_error err;
    int f, count[4] = {0, 0, 0, 0};
    REQUIRE(tiled_builtin_mesh("torus", &o, &mesh, &err) == TILED_OK);
    REQUIRE(tiled_map(&mesh, &ts.layout, &o, &q, &err) == TILED_OK);
    for (f = 0; f < q.nfaces; f++) {
        int k;
        for (k = 0; k < 4; k++)
            if (decode(&ts, q.uvs + 2 * (q.face_start[f] + k)).corner == 0) count[k]++;
    }
    for (f = 0; f < 4; f++) CHECKF(count[f] > q.nfaces / 8, "start corner %d used %d times", f, count[f]);
    tiled_mesh_free(&q);
    o.fixed_start = 1;
    REQUIRE(tiled_map(&mesh, &ts.layout, &o, &q, &err) == TILED_OK);
    for (f = 0; f < q.nfaces; f++) CHECK(decode(&ts, q.uvs + 2 * q.face_start[f]).corner == 0);
    tiled_mesh_free(&q);
    tiled_mesh_free(&mesh);
}

/* Synthesises a tile set from a built-in exemplar. */
static int synth(const char *exemplar, tiled_options *o, tiled_tileset *ts)
{
    tiled_image ex;
    tiled_error err;
    int ok = tiled_builtin_exemplar(exemplar, 64, o, &ex, &err) == TILED_OK &&
             tiled_synthesize(&ex, o, ts, &err) == TILED_OK;
    CHECKF(ok, "synthesis failed: %s", err.message);
    tiled_image_free(&ex);
    return ok;
}

/* Seams on a mapped mesh are no larger than neighbouring texels inside
 * tiles: the pattern continues across every edge. */
static void seam_case(int case_number, int n, const char *exemplar, const char *mesh_name)
{
    tiled_options o = opts(case_number, n);
    tiled_tileset ts;
    tiled_mesh mesh, q;
    tiled_error err;
    double inside, worst, seam, p90;
    o.subdivide = 1;
    if (!synth(exemplar, &o, &ts)) return;
    REQUIRE(tiled_builtin_mesh(mesh_name, &o, &mesh, &err) == TILED_OK);
    REQUIRE(tiled_map(&mesh, &ts.layout, &o, &q, &err) == TILED_OK);
    inside = interior_jump(&ts, &p90);
    seam = seam_jump(&ts, &q, &worst);
    pwt_info("case %d n=%d %s on %s: seam %.4f, worst edge %.4f; interior mean %.4f, 90th pct %.4f",
             case_number, n, exemplar, mesh_name, seam, worst, inside, p90);
    CHECKF(seam >= 0.0 && worst <= p90, "worst edge %.4f > interior 90th percentile %.4f", worst, p90);
    tiled_tileset_free(&ts);
    tiled_mesh_free(&mesh);
    tiled_mesh_free(&q);
}

static void t_seams_case2(void) { seam_case(2, 1, "pebbles", "double-torus"); }
static void t_seams_case2_pairs2(void) { seam_case(2, 2, "spots", "torus"); }
static void t_seams_case1(void) { seam_case(1, 3, "lichen", "cube"); }

/* Every tile of the set shows up on a large mesh. */
static void t_all_tiles_used(void)
{
    int n;
    for (n = 1; n <= 2; n++) {
        tiled_tileset ts = layout_only(2, n, 8);
        tiled_options o = opts(2, n);
        tiled_mesh mesh, q;
        tiled_error err;
        int N = ts.tiles_per_side, *used = (int *)calloc((size_t)N * N, sizeof(int)), f, missing = 0;
        o.subdivide = n == 1 ? 1 : 3;
        REQUIRE(tiled_builtin_mesh("torus", &o, &mesh, &err) == TILED_OK);
        REQUIRE(tiled_map(&mesh, &ts.layout, &o, &q, &err) == TILED_OK);
        for (f = 0; f < q.nfaces; f++) used[q.face_tiles[f]]++;
        for (f = 0; f < N * N; f++) missing += !used[f];
        CHECKF(missing == 0, "n=%d: %d of %d tiles unused on %d quads", n, missing, N * N, q.nfaces);
        free(used);
        tiled_mesh_free(&mesh);
        tiled_mesh_free(&q);
    }
}

static int buf_sink(void *ctx, const void *data, size_t size)
{
    return pw_buf_write(ctx, data, size);
}

/* OBJ and PNG of one run, in memory. */
static void run_to_memory(unsigned long long seed, pw_buf *obj, pw_buf *png)
{
    tiled_options o = opts(2, 1);
    tiled_tileset ts;
    tiled_mesh mesh, q;
    tiled_image pic;
    tiled_error err;
    o.render.width = 160;
    o.render.height = 120;
    o.seed = seed;
    memset(obj, 0, sizeof *obj);
    memset(png, 0, sizeof *png);
    if (!synth("pebbles", &o, &ts)) return;
    REQUIRE(tiled_builtin_mesh("double-torus", &o, &mesh, &err) == TILED_OK);
    REQUIRE(tiled_map(&mesh, &ts.layout, &o, &q, &err) == TILED_OK);
    REQUIRE(tiled_write_obj(&q, "x.mtl", buf_sink, obj, &err) == TILED_OK);
    REQUIRE(tiled_render(&q, &ts, &o.render, &pic, &err) == TILED_OK);
    REQUIRE(tiled_write_image(&pic, "png", buf_sink, png, &err) == TILED_OK);
    REQUIRE(tiled_write_image(&ts.atlas, "png", buf_sink, png, &err) == TILED_OK);
    tiled_image_free(&pic);
    tiled_tileset_free(&ts);
    tiled_mesh_free(&mesh);
    tiled_mesh_free(&q);
}

static void t_determinism(void)
{
    pw_buf a1, a2, b1, b2, c1, c2;
    run_to_memory(7, &a1, &a2);
    run_to_memory(7, &b1, &b2);
    run_to_memory(8, &c1, &c2);
    CHECK(a1.size > 0 && a2.size > 0);
    CHECK(a1.size == b1.size && !memcmp(a1.data, b1.data, a1.size));
    CHECK(a2.size == b2.size && !memcmp(a2.data, b2.data, a2.size));
    CHECK(a1.size != c1.size || memcmp(a1.data, c1.data, a1.size));
    CHECK(a2.size != c2.size || memcmp(a2.data, c2.data, a2.size));
    free(a1.data), free(a2.data), free(b1.data), free(b2.data), free(c1.data), free(c2.data);
}

/* The thesis layout (no guard bands) of a synthesised set. */
static tiled_image plain_layout(const tiled_tileset *ts)
{
    tiled__geom gm = tiled__geometry(&ts->layout), plain;
    pw_image atlas = tiled__pw_image(&ts->atlas);
    tiled_image out;
    int t, j;
    memset(&out, 0, sizeof out);
    plain = gm;
    plain.g = 0;
    plain.C = gm.T;
    out.width = out.height = gm.N * gm.T;
    out.channels = atlas.c;
    out.pixels = (float *)malloc(sizeof(float) * out.width * out.height * out.channels);
    for (t = 0; t < gm.N * gm.N; t++)
        for (j = 0; j < gm.T; j++) {
            pw_image o = tiled__pw_image(&out);
            memcpy(tiled__atlas_px(&o, &plain, t, 0, j), tiled__atlas_px(&atlas, &gm, t, 0, j),
                   sizeof(float) * gm.T * atlas.c);
        }
    return out;
}

/* A synthesised set passes validation; the same set with one tile turned
 * by 90 degrees fails on exactly that tile's sides. */
static void t_validate(void)
{
    tiled_options o = opts(2, 1);
    tiled_tileset ts;
    tiled_validation v;
    tiled_error err;
    tiled_image img;
    int T, i, j, k, c, bad_tile = 5, only_that = 1;
    float *copy;
    if (!synth("pebbles", &o, &ts)) return;
    img = plain_layout(&ts);
    REQUIRE(tiled_validate_tiles(&img, &o, &v, &err) == TILED_OK);
    pwt_info("valid set: %d sides, worst seam %.4f, threshold %.4f", v.sides_checked, v.worst, v.threshold);
    CHECK_EQ_INT(v.sides_checked, 64);
    CHECK_EQ_INT(v.nbad, 0);
    T = ts.layout.tile_size;
    c = img.channels;
    copy = (float *)malloc(sizeof(float) * T * T * c);
    for (j = 0; j < T; j++) /* tile 5 sits at column 1, row 1 (from the bottom) */
        memcpy(copy + (size_t)j * T * c, img.pixels + ((size_t)(img.height - 1 - T - j) * img.width + T) * c,
               sizeof(float) * T * c);
    for (j = 0; j < T; j++)
        for (i = 0; i < T; i++)
            for (k = 0; k < c; k++) /* rotate by 90 degrees */
                img.pixels[((size_t)(img.height - 1 - T - j) * img.width + T + i) * c + k] =
                    copy[((size_t)i * T + (T - 1 - j)) * c + k];
    REQUIRE(tiled_validate_tiles(&img, &o, &v, &err) == TILED_OK);
    pwt_info("rotated tile: %d bad sides, worst %.4f", v.nbad, v.worst);
    CHECK(v.nbad >= 2);
    for (k = 0; k < v.nbad && k < TILED_MAX_MISMATCHES; k++) only_that &= v.bad[k].tile == bad_tile;
    CHECKF(only_that, "a side of another tile was reported first");
    free(copy);
    free(img.pixels);
    tiled_tileset_free(&ts);
}

/* Guard bands hold what continues across each side, and a hand-made set
 * re-wrapped by tiled_tileset_from_image gets the same atlas back. */
static void t_guards(void)
{
    tiled_options o = opts(2, 1);
    tiled_tileset ts, again;
    tiled_image img;
    tiled_error err;
    size_t n, k, diff = 0;
    if (!synth("spots", &o, &ts)) return;
    img = plain_layout(&ts);
    REQUIRE(tiled_tileset_from_image(&img, &o, &again, &err) == TILED_OK);
    CHECK_EQ_INT(again.atlas.width, ts.atlas.width);
    CHECK_EQ_INT(again.layout.tile_size, ts.layout.tile_size);
    n = (size_t)ts.atlas.width * ts.atlas.height * ts.atlas.channels;
    for (k = 0; k < n; k++) diff += ts.atlas.pixels[k] != again.atlas.pixels[k];
    CHECK_EQ_INT(diff, 0);
    CHECKF(ts.max_mip_level >= 2, "max mip level %d", ts.max_mip_level);
    free(img.pixels);
    tiled_tileset_free(&again);
    tiled_tileset_free(&ts);
}

/* Triangles and mixed polygons become quads by Catmull-Clark first. */
static void t_catmull_clark_first(void)
{
    tiled_tileset ts = layout_only(2, 1, 8);
    tiled_options o = opts(2, 1);
    tiled_mesh mesh, q;
    tiled_error err;
    REQUIRE(tiled_builtin_mesh("icosahedron", &o, &mesh, &err) == TILED_OK);
    REQUIRE(tiled_map(&mesh, &ts.layout, &o, &q, &err) == TILED_OK);
    CHECK_EQ_INT(q.nfaces, 60);
    CHECK(check_edges(&ts, &q) == 120);
    tiled_mesh_free(&q);
    o.subdivide = 2;
    REQUIRE(tiled_map(&mesh, &ts.layout, &o, &q, &err) == TILED_OK);
    CHECK_EQ_INT(q.nfaces, 960);
    tiled_mesh_free(&q);
    tiled_mesh_free(&mesh);
}

/* ---- bad input ------------------------------------------------------------- */

static tiled_result map_text(const char *text, tiled_error *err)
{
    tiled_tileset ts = layout_only(2, 1, 8);
    tiled_mesh mesh, q;
    tiled_result r = tiled_read_mesh(text, strlen(text), "bad.obj", NULL, &mesh, err);
    if (r != TILED_OK) return r;
    r = tiled_map(&mesh, &ts.layout, NULL, &q, err);
    tiled_mesh_free(&mesh);
    tiled_mesh_free(&q);
    return r;
}

static void t_bad_meshes(void)
{
    tiled_error err;
    /* three quads sharing the edge 0-1 */
    CHECK_EQ_INT(map_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 1 -1 0\nv 0 -1 0\nv 1 0 1\nv 0 0 1\n"
                          "f 1 2 3 4\nf 2 1 6 5\nf 1 2 7 8\n", &err), TILED_ERR_TOPOLOGY);
    CHECKF(strstr(err.message, "non-manifold") != NULL, "message: %s", err.message);
    /* second quad flipped */
    CHECK_EQ_INT(map_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
                          "f 1 2 3 4\nf 2 3 6 5\n", &err), TILED_ERR_TOPOLOGY);
    CHECKF(strstr(err.message, "orientation") != NULL, "message: %s", err.message);
    CHECK_EQ_INT(map_text("v 0 0 nan\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n", &err), TILED_ERR_INVALID);
    CHECK_EQ_INT(map_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 7\n", &err), TILED_ERR_INVALID);
    CHECKF(strstr(err.message, "bad.obj:4") != NULL, "message: %s", err.message);
}

static void t_bad_arguments(void)
{
    tiled_options o = opts(2, 1);
    tiled_tileset ts;
    tiled_image ex;
    tiled_mesh mesh, q;
    tiled_error err;
    tiled_layout l = layout_only(2, 1, 8).layout;
    float nan_px[8 * 8 * 3];
    int k;
    REQUIRE(tiled_builtin_mesh("cube", &o, &mesh, &err) == TILED_OK);
    l.pairs = 9;
    CHECK_EQ_INT(tiled_map(&mesh, &l, &o, &q, &err), TILED_ERR_INVALID);
    CHECKF(strstr(err.message, "pairs") != NULL, "message: %s", err.message);
    l.pairs = 1;
    o.subdivide = 9;
    CHECK_EQ_INT(tiled_map(&mesh, &l, &o, &q, &err), TILED_ERR_INVALID);
    o.subdivide = 8;
    l.pairs = 1;
    mesh.positions[4] = (float)(1e30 * 1e30);
    CHECK_EQ_INT(tiled_map(&mesh, &l, &o, &q, &err), TILED_ERR_INVALID);
    tiled_mesh_free(&mesh);
    for (k = 0; k < 8 * 8 * 3; k++) nan_px[k] = k == 100 ? (float)(0.0 * (1e300 * 1e300)) : 0.5f;
    memset(&ex, 0, sizeof ex);
    ex.width = ex.height = 8;
    ex.channels = 3;
    ex.pixels = nan_px;
    CHECK_EQ_INT(tiled_synthesize(&ex, &o, &ts, &err), TILED_ERR_INVALID);
    CHECKF(strstr(err.message, "pixel 33") != NULL, "message: %s", err.message);
    o = opts(2, 8);
    o.layout.tile_size = 256;
    nan_px[100] = 0.5f;
    CHECK_EQ_INT(tiled_synthesize(&ex, &o, &ts, &err), TILED_ERR_LIMIT);
}

/* A run that cancels from its progress callback stops with CANCELLED. */
static int cancel_at_half(void *user, float done, const char *stage)
{
    (void)stage;
    ++*(int *)user;
    return done > 0.5f;
}

static void t_cancel(void)
{
    tiled_options o = opts(2, 1);
    tiled_tileset ts;
    tiled_image ex;
    tiled_error err;
    int calls = 0;
    o.progress = cancel_at_half;
    o.progress_user = &calls;
    REQUIRE(tiled_builtin_exemplar("pebbles", 32, &o, &ex, &err) == TILED_OK);
    CHECK_EQ_INT(tiled_synthesize(&ex, &o, &ts, &err), TILED_ERR_CANCELLED);
    CHECK(calls > 2);
    CHECK(ts.atlas.pixels == NULL);
    tiled_image_free(&ex);
}

/* Every allocation of a small synthesis + mapping + render + encode fails
 * in turn: each call reports out-of-memory, nothing leaks, nothing crashes. */
static int sink_null(void *ctx, const void *data, size_t size)
{
    (void)ctx, (void)data, (void)size;
    return 0;
}

static int pipeline_with(tiled_options *o, tiled_error *err)
{
    tiled_image ex, pic;
    tiled_tileset ts;
    tiled_mesh mesh, q;
    int r;
    o->render.width = o->render.height = 32;
    memset(&ts, 0, sizeof ts);
    memset(&q, 0, sizeof q);
    memset(&pic, 0, sizeof pic);
    memset(&mesh, 0, sizeof mesh);
    if ((r = tiled_builtin_exemplar("spots", 16, o, &ex, err)) != TILED_OK) return r;
    if ((r = tiled_synthesize(&ex, o, &ts, err)) == TILED_OK &&
        (r = tiled_builtin_mesh("icosahedron", o, &mesh, err)) == TILED_OK &&
        (r = tiled_map(&mesh, &ts.layout, o, &q, err)) == TILED_OK &&
        (r = tiled_render(&q, &ts, &o->render, &pic, err)) == TILED_OK &&
        (r = tiled_write_image(&pic, "png", sink_null, NULL, err)) == TILED_OK)
        r = tiled_write_obj(&q, "x.mtl", sink_null, NULL, err);
    tiled_image_free(&pic);
    tiled_mesh_free(&q);
    tiled_mesh_free(&mesh);
    tiled_tileset_free(&ts);
    tiled_image_free(&ex);
    return r;
}

/* Every allocation failure of the whole pipeline, one tile per quad
 * (scale 0) or tiles of side `scale`: NOMEM and nothing leaked. */
static void alloc_loop(float scale)
{
    int budget, done = 0;
    for (budget = 0; budget < 100000 && !done; budget++) {
        pwt_alloc_state st = {0, 0, 0};
        tiled_options o = opts(2, 1);
        tiled_error err;
        int r;
        st.fail_after = budget;
        o.allocator.malloc_fn = pwt_malloc;
        o.allocator.realloc_fn = pwt_realloc;
        o.allocator.free_fn = pwt_free;
        o.allocator.user = &st;
        o.smooth = scale > 0.0f ? 0 : 1;
        o.subdivide = scale > 0.0f;
        o.scale = scale;
        r = pipeline_with(&o, &err);
        if (r == TILED_OK) done = 1;
        else CHECKF(r == TILED_ERR_NOMEM, "budget %d: %s", budget, err.message);
        CHECKF(st.live == 0, "budget %d: %ld blocks leaked", budget, st.live);
        if (pwt_failed_) return;
    }
    CHECK(done);
    pwt_info("%d allocation failure points exercised", budget - 1);
}

static void t_alloc_failures(void) { alloc_loop(0.0f); }
static void t_grid_alloc_failures(void) { alloc_loop(1.5f); }

/* ---- real data (make data) --------------------------------------------------- */

/* CGAL meshes: quad meshes of genus 0..2 and triangle meshes. */
static void real_mesh(const char *file, int subdivide)
{
    const char *path = pwt_data(file);
    tiled_tileset ts = layout_only(2, 1, 8);
    tiled_options o = opts(2, 1);
    tiled_mesh mesh, q;
    tiled_error err;
    int edges;
    if (!path) return;
    o.subdivide = subdivide;
    REQUIRE(tiled_load_mesh(path, &o, &mesh, &err) == TILED_OK);
    if (tiled_map(&mesh, &ts.layout, &o, &q, &err) != TILED_OK) {
        CHECKF(0, "%s: %s", path, err.message);
        tiled_mesh_free(&mesh);
        return;
    }
    edges = check_edges(&ts, &q);
    pwt_info("%s: %d faces -> %d quads, %d interior edges matched", file, mesh.nfaces, q.nfaces, edges);
    tiled_mesh_free(&mesh);
    tiled_mesh_free(&q);
}

static void t_real_cube_quad(void) { real_mesh("meshes/cube_quad.off", 1); }
static void t_real_torus_quad(void) { real_mesh("meshes/torus_quad.off", 0); }
static void t_real_cross_quad(void) { real_mesh("meshes/cross_quad.off", 0); }
static void t_real_double_torus(void) { real_mesh("meshes/double-torus-example.off", 0); }
static void t_real_elephant(void) { real_mesh("meshes/elephant.off", 0); }
static void t_real_knot(void) { real_mesh("meshes/knot.off", 0); }

/* GIMP patterns: synthesis keeps every mapped edge seamless. */
static void real_exemplar(const char *name)
{
    char rel[256];
    const char *path;
    tiled_options o = opts(2, 1);
    tiled_tileset ts;
    tiled_image ex;
    tiled_mesh mesh, q;
    tiled_error err;
    double inside, seam, worst, p90;
    snprintf(rel, sizeof rel, "textures/%s.ppm", name);
    if (!(path = pwt_data(rel))) return;
    REQUIRE(tiled_load_image(path, &o, &ex, &err) == TILED_OK);
    REQUIRE(tiled_synthesize(&ex, &o, &ts, &err) == TILED_OK);
    o.subdivide = 1;
    REQUIRE(tiled_builtin_mesh("double-torus", &o, &mesh, &err) == TILED_OK);
    REQUIRE(tiled_map(&mesh, &ts.layout, &o, &q, &err) == TILED_OK);
    inside = interior_jump(&ts, &p90);
    seam = seam_jump(&ts, &q, &worst);
    pwt_info("%s (%dx%d): tiles of %d px; seam %.4f, worst edge %.4f; interior mean %.4f, 90th pct %.4f",
             name, ex.width, ex.height, ts.layout.tile_size, seam, worst, inside, p90);
    CHECKF(worst <= p90, "worst edge %.4f > interior 90th percentile %.4f", worst, p90);
    tiled_image_free(&ex);
    tiled_tileset_free(&ts);
    tiled_mesh_free(&mesh);
    tiled_mesh_free(&q);
}

static void t_real_brick(void) { real_exemplar("brick"); }
static void t_real_leopard(void) { real_exemplar("leopard"); }
static void t_real_burlap(void) { real_exemplar("burlap"); }
static void t_real_java(void) { real_exemplar("java"); }
static void t_real_pine(void) { real_exemplar("pine"); }
static void t_real_marble3(void) { real_exemplar("marble3"); }

/* ---- motifs kept whole at seams (issue 18) ---------------------------------- */

/* The share of seam pixel pairs inside the tiles of a case-2 tile set
 * that cut a motif (pw_quilt_seam_stats: the seam passes a pixel or more
 * inside a motif of either source, by quilt.h's motif map, and the two
 * sources differ there by more than the exemplar's strong-edge gradient). */
static double cut_share(const tiled_image *ex, const char *what)
{
    tiled_options o = opts(2, 1);
    tiled_tileset ts;
    pw_seam_stats st = {0, 0};
    pw_err pe;
    double share;
    long ntiles;
    pw_err_clear(&pe);
    if (tiled__synthesize(ex, &o, &ts, &st, &pe) != PW_OK) {
        CHECKF(0, "%s: %s", what, pe.msg);
        return 1.0;
    }
    share = st.pairs ? (double)st.cut / (double)st.pairs : 0.0;
    ntiles = (long)ts.tiles_per_side * ts.tiles_per_side;
    pwt_info("%s (%dx%d, tiles of %d px): %ld of %ld seam pairs cut a motif (%.1f%%), %ld per tile",
             what, ex->width, ex->height, ts.layout.tile_size, st.cut, st.pairs, 100.0 * share,
             st.cut / ntiles);
    tiled_tileset_free(&ts);
    return share;
}

/* The demo's exemplar (procedural pebbles, 128 px as in `make demo`):
 * before issue 18, 13.1% of its seam pairs cut a pebble. */
static void t_motif_cuts_pebbles(void)
{
    tiled_options o = opts(2, 1);
    tiled_image ex;
    tiled_error err;
    double share;
    REQUIRE(tiled_builtin_exemplar("pebbles", 128, &o, &ex, &err) == TILED_OK);
    share = cut_share(&ex, "procedural pebbles");
    CHECKF(share <= 0.10, "%.1f%% of seam pairs cut a motif (at most 10%%)", 100.0 * share);
    tiled_image_free(&ex);
}

/* GIMP's structured patterns (pebbles.ppm shows coffee beans), with the
 * share of seam pairs that cut a motif before issue 18 and the most
 * allowed now. Bricks are tiled at 64 px, where a 45 x 28 px brick leaves
 * a seam little room to go round it. */
static void t_motif_cuts_gimp(void)
{
    static const struct {
        const char *name;
        double before, limit;
    } ex_[] = {{"pebbles", 0.298, 0.10}, {"stone33", 0.361, 0.10}, {"leaves3", 0.086, 0.04},
               {"brick", 0.220, 0.15}};
    tiled_options o = opts(2, 1);
    int k;
    for (k = 0; k < 4; k++) {
        char rel[64];
        const char *path;
        tiled_image ex;
        tiled_error err;
        double share;
        snprintf(rel, sizeof rel, "textures/%s.ppm", ex_[k].name);
        if (!(path = pwt_data(rel))) return;
        REQUIRE(tiled_load_image(path, &o, &ex, &err) == TILED_OK);
        share = cut_share(&ex, ex_[k].name);
        CHECKF(share <= ex_[k].limit, "%s: %.1f%% of seam pairs cut a motif (at most %.0f%%; %.1f%% before "
               "issue 18)", ex_[k].name, 100.0 * share, 100.0 * ex_[k].limit, 100.0 * ex_[k].before);
        tiled_image_free(&ex);
    }
}

/* Mean colour difference of two r x r squares: one at (ax, ay) stepping
 * (adx, ady) into the image, the other likewise, transposed if tr. */
static double square_diff(const tiled_image *a, const int *pa, const tiled_image *b, const int *pb, int r, int tr)
{
    double sum = 0.0;
    int u, v, k;
    for (v = 0; v < r; v++)
        for (u = 0; u < r; u++) {
            const int bu = tr ? v : u, bv = tr ? u : v;
            const float *x = a->pixels + ((size_t)(pa[1] + pa[3] * v) * a->width + pa[0] + pa[2] * u) * a->channels;
            const float *y = b->pixels + ((size_t)(pb[1] + pb[3] * bv) * b->width + pb[0] + pb[2] * bu) * b->channels;
            for (k = 0; k < 3; k++) sum += fabs(x[k] - y[k]);
        }
    return sum / (3.0 * r * r);
}

/* How alike the corners of a tile set are: the mean colour difference of
 * the T/4 squares at the corners of two tiles (seen from each corner into
 * its tile, transposed or not, whichever matches better), over the mean
 * difference of two random squares of the exemplar. At a mesh vertex the
 * corners of all its tiles meet; 1 means they differ as much as any two
 * places of the exemplar, 0 that every vertex shows the same star. */
static double corner_repetition(const tiled_tileset *ts, const tiled_image *ex)
{
    const int T = ts->layout.tile_size, g = ts->layout.guard, N = ts->tiles_per_side, r = T / 4, nc = 4 * N * N;
    pw_rng rng = pw_rng_seed(5, 1);
    double corners = 0.0, windows = 0.0;
    int i, n = 4000;
    for (i = 0; i < n; i++) {
        int q[2][4], j;
        for (j = 0; j < 2; j++) {
            const int c = (int)pw_rng_below(&rng, (uint32_t)nc), t = c / 4, k = c % 4;
            q[j][0] = (t % N) * (T + 2 * g) + g + (k == 1 || k == 2 ? T - 1 : 0);
            q[j][1] = (t / N) * (T + 2 * g) + g + (k >= 2 ? T - 1 : 0);
            q[j][2] = k == 1 || k == 2 ? -1 : 1;
            q[j][3] = k >= 2 ? -1 : 1;
        }
        corners += fmin(square_diff(&ts->atlas, q[0], &ts->atlas, q[1], r, 0),
                        square_diff(&ts->atlas, q[0], &ts->atlas, q[1], r, 1));
        for (j = 0; j < 2; j++) {
            q[j][0] = (int)pw_rng_below(&rng, (uint32_t)(ex->width - r));
            q[j][1] = (int)pw_rng_below(&rng, (uint32_t)(ex->height - r));
            q[j][2] = q[j][3] = 1;
        }
        windows += fmin(square_diff(ex, q[0], ex, q[1], r, 0), square_diff(ex, q[0], ex, q[1], r, 1));
    }
    return corners / windows;
}

/* Issue 18's star at mesh vertices: with one boundary pair every corner
 * of every tile shows the ends of the same diamond, so the corners are
 * far more alike than places of the exemplar; two pairs give each vertex
 * ends of two diamonds to combine (see docs/tiled.md). */
static void t_corner_repetition(void)
{
    tiled_image ex;
    tiled_error err;
    double rep[2];
    int pairs;
    tiled_options o = opts(2, 1);
    REQUIRE(tiled_builtin_exemplar("pebbles", 128, &o, &ex, &err) == TILED_OK);
    for (pairs = 1; pairs <= 2; pairs++) {
        tiled_tileset ts;
        o = opts(2, pairs);
        o.layout.tile_size = 64;
        REQUIRE(tiled_synthesize(&ex, &o, &ts, &err) == TILED_OK);
        rep[pairs - 1] = corner_repetition(&ts, &ex);
        pwt_info("procedural pebbles, %d pair(s), tiles of 64 px: corners differ %.2f as much as places of the "
                 "exemplar", pairs, rep[pairs - 1]);
        tiled_tileset_free(&ts);
    }
    CHECKF(rep[0] > 0.2, "one pair: corners %.2f (at least 0.2)", rep[0]);
    CHECKF(rep[1] > rep[0] + 0.15, "two pairs: corners %.2f, not clearly more varied than one pair's %.2f", rep[1],
           rep[0]);
    tiled_image_free(&ex);
}

/* The drawn tile size: tiles of the cube span its faces, so a tile is as
 * wide on screen as a face; twice the picture height draws it twice as
 * wide; a subdivision level about halves it; bad arguments are errors. */
static void t_drawn_tile_size(void)
{
    tiled_tileset ts = layout_only(2, 1, 8);
    tiled_options o = opts(2, 1);
    tiled_render_options ro;
    tiled_mesh mesh, q, q2;
    tiled_error err;
    float px, px2, px_fine;
    ts.atlas.width = ts.atlas.height = 4 * (64 + 2 * 8); /* only its size is read */
    memset(&ro, 0, sizeof ro);
    ro.width = 400, ro.height = 300;
    REQUIRE(tiled_builtin_mesh("cube", &o, &mesh, &err) == TILED_OK);
    REQUIRE(tiled_map(&mesh, &ts.layout, &o, &q, &err) == TILED_OK);
    REQUIRE(tiled_drawn_tile_size(&q, &ts, &ro, &px, &err) == TILED_OK);
    ro.width = 800, ro.height = 600;
    REQUIRE(tiled_drawn_tile_size(&q, &ts, &ro, &px2, &err) == TILED_OK);
    o.subdivide = 1;
    REQUIRE(tiled_map(&mesh, &ts.layout, &o, &q2, &err) == TILED_OK);
    REQUIRE(tiled_drawn_tile_size(&q2, &ts, &ro, &px_fine, &err) == TILED_OK);
    pwt_info("cube: tiles drawn %.1f px at 400x300, %.1f px at 800x600, %.1f px one level finer",
             px, px2, px_fine);
    CHECKF(px > 60.0f && px < 300.0f, "a cube face drawn %.1f px wide in a 400x300 picture", px);
    CHECK_NEAR(px2 / px, 2.0, 1e-3);
    CHECK_NEAR(px_fine / px2, 0.5, 0.05); /* Catmull-Clark rounds the cube: framed a bit closer */
    CHECK(tiled_drawn_tile_size(&mesh, &ts, &ro, &px, &err) == TILED_ERR_INVALID); /* no uvs */
    CHECK(tiled_drawn_tile_size(&q, NULL, &ro, &px, &err) == TILED_ERR_INVALID);
    CHECK(tiled_drawn_tile_size(&q, &ts, &ro, NULL, &err) == TILED_ERR_INVALID);
    tiled_mesh_free(&mesh);
    tiled_mesh_free(&q);
    tiled_mesh_free(&q2);
}

/* opt.render holds the render defaults (rule O2): a zeroed struct, NULL and
 * tiled_default_options().render draw the same picture; every filter of
 * the enum draws, a value outside it is an error naming it. */
static void t_render_options(void)
{
    tiled_options o = opts(2, 1);
    tiled_render_options zero;
    tiled_tileset ts;
    tiled_mesh mesh, q;
    tiled_image a, b, c;
    tiled_error err;
    int f;
    CHECK(o.render.width == 800 && o.render.height == 600 && o.render.supersample == 2);
    CHECK(o.render.filter == TILED_FILTER_TRILINEAR && o.render.up[1] == 1.0f && o.render.background[0] == 1.0f);
    memset(&zero, 0, sizeof zero);
    o.render.width = zero.width = 80;
    o.render.height = zero.height = 60;
    if (!synth("spots", &o, &ts)) return;
    REQUIRE(tiled_builtin_mesh("cube", &o, &mesh, &err) == TILED_OK);
    REQUIRE(tiled_map(&mesh, &ts.layout, &o, &q, &err) == TILED_OK);
    REQUIRE(tiled_render(&q, &ts, &o.render, &a, &err) == TILED_OK);
    REQUIRE(tiled_render(&q, &ts, &zero, &b, &err) == TILED_OK);
    CHECK(a.width == b.width && a.height == b.height &&
          !memcmp(a.pixels, b.pixels, sizeof(float) * 3 * (size_t)a.width * (size_t)a.height));
    tiled_image_free(&b);
    for (f = TILED_FILTER_TRILINEAR; f <= TILED_FILTER_NEAREST; f++) {
        o.render.filter = (tiled_filter)f;
        CHECKF(tiled_render(&q, &ts, &o.render, &c, &err) == TILED_OK, "filter %d: %s", f, err.message);
        tiled_image_free(&c);
    }
    o.render.filter = (tiled_filter)3;
    CHECK(tiled_render(&q, &ts, &o.render, &c, &err) == TILED_ERR_INVALID && strstr(err.message, "filter 3"));
    REQUIRE(tiled_render(&q, &ts, NULL, &b, &err) == TILED_OK);
    CHECK(b.width == 800 && b.height == 600);
    tiled_image_free(&a);
    tiled_image_free(&b);
    tiled_tileset_free(&ts);
    tiled_mesh_free(&mesh);
    tiled_mesh_free(&q);
}

/* ---- tiles of a chosen size on any mesh (issue 23) ------------------------------ */

/* The grid of a mesh at tile side `scale`: the library's own steps up to
 * the tiles, so that the cells' shared sides can be measured. */
static int grid_of(const tiled_mesh *mesh, const tiled_layout *l, const tiled_options *o, tiled__grid *C)
{
    pw_err e;
    int r;
    pw_err_clear(&e);
    memset(C, 0, sizeof *C);
    C->a = tiled__alloc(NULL);
    r = tiled__grid_build(C, mesh, l, o, &e);
    CHECKF(r == PW_OK, "grid: %s", e.msg);
    return r == PW_OK;
}

/* Every shared cell side: its two cells' tiles name partner types there
 * (2k against 2k+1, read back from the tiles' places in the atlas), and
 * the colour jump across it, texel against texel along the side, as
 * seam_jump does across mesh edges. Returns the mean jump; worst: the
 * worst side's; *bad: sides whose tiles do not name partner types. */
static double grid_seam(const tiled_tileset *ts, const tiled__grid *C, double *worst, int *bad)
{
    tiled__geom gm = tiled__geometry(&ts->layout);
    pw_image atlas = tiled__pw_image(&ts->atlas);
    int k, x, T = gm.T, case1 = ts->layout.case_number == 1;
    double sum = 0.0;
    long n = 0;
    *worst = 0.0;
    *bad = 0;
    for (k = 0; k < (int)C->nadj; k++) {
        const tiled__adj *q = C->adj + k;
        /* the tiles' sides there: a cell turned by rot quarter turns shows
           its tile's side (side - rot) mod 4 */
        int sa = (q->side - C->tile[2 * C->ncls + q->a] + 4) % 4, sb = (q->side + 2 - C->tile[2 * C->ncls + q->b] + 4) % 4;
        int ta[4], tb[4], i, j, i2, j2;
        double edge = 0.0;
        if (k && q[-1].a == q->a && q[-1].side == q->side && q[-1].b == q->b) continue;
        tiled__tile_types(&gm, case1, C->tile[q->a], ta);
        tiled__tile_types(&gm, case1, C->tile[q->b], tb);
        *bad += tiled__partner(case1, ta[sa]) != tb[sb];
        for (x = 0; x < T; x++) {
            tiled__from_side(sa, T, x, 0, &i, &j);
            tiled__from_side(sb, T, T - 1 - x, 0, &i2, &j2);
            edge += tiled__dist(tiled__atlas_px(&atlas, &gm, C->tile[q->a], i, j),
                                tiled__atlas_px(&atlas, &gm, C->tile[q->b], i2, j2), atlas.c);
        }
        sum += edge;
        n += T;
        if (edge / T > *worst) *worst = edge / T;
    }
    return n ? sum / (double)n : -1.0;
}

/* Output corners on a cell side carry the type that the piece's tile has
 * on that side; returns how many do not. */
static int grid_corner_types(const tiled_tileset *ts, const tiled_mesh *q)
{
    tiled__geom gm = tiled__geometry(&ts->layout);
    int f, k, bad = 0, t[4], s;
    for (f = 0; f < q->nfaces; f++) {
        tiled__tile_types(&gm, ts->layout.case_number == 1, q->face_tiles[f], t);
        for (k = q->face_start[f]; k < q->face_start[f + 1]; k++) {
            if (q->corner_types[k] < 0) continue;
            for (s = 0; s < 4 && t[s] != q->corner_types[k]; s++) continue;
            bad += s == 4;
        }
    }
    return bad;
}

/* Output corners outside their face's tile in the atlas (by more than a
 * thousandth of a tile): every piece, a band of a cut cell too, shows its
 * own tile only. */
static int grid_uv_outside(const tiled_tileset *ts, const tiled_mesh *q)
{
    tiled__geom gm = tiled__geometry(&ts->layout);
    float coord[2 * 64];
    int f, k, bad = 0;
    if (gm.N > 64) return -1;
    tiled__coord_table(&gm, coord);
    for (f = 0; f < q->nfaces; f++) {
        int col = q->face_tiles[f] % gm.N, row = q->face_tiles[f] / gm.N;
        double eu = 1e-3 * (coord[2 * col + 1] - coord[2 * col]), ev = 1e-3 * (coord[2 * row + 1] - coord[2 * row]);
        for (k = q->face_start[f]; k < q->face_start[f + 1]; k++)
            bad += q->uvs[2 * k] < coord[2 * col] - eu || q->uvs[2 * k] > coord[2 * col + 1] + eu ||
                   q->uvs[2 * k + 1] < coord[2 * row] - ev || q->uvs[2 * k + 1] > coord[2 * row + 1] + ev;
    }
    return bad;
}

/* A corner's place in its cell, as drawn: its texture coordinates in its
 * face's tile (0..1 along each axis), a half-turned cell turned back. */
static void grid_drawn(const tiled__geom *gm, const float *coord, const tiled_mesh *q, int face, int k, int turned,
                       double *x)
{
    int col = q->face_tiles[face] % gm->N, row = q->face_tiles[face] / gm->N;
    x[0] = (q->uvs[2 * k] - coord[2 * col]) / (coord[2 * col + 1] - coord[2 * col]);
    x[1] = (q->uvs[2 * k + 1] - coord[2 * row]) / (coord[2 * row + 1] - coord[2 * row]);
    if (turned) {
        x[0] = 1.0 - x[0];
        x[1] = 1.0 - x[1];
    }
}

/* The share of the surface drawn with a tile scaled by more than 1.5 or
 * less than 1/1.5 along either of its axes (a tile's side against the
 * side asked for, per fan triangle of every output face). */
static double grid_stretched(const tiled_tileset *ts, const tiled_mesh *q, double side)
{
    tiled__geom gm = tiled__geometry(&ts->layout);
    float coord[2 * 64];
    double all = 0.0, bad = 0.0;
    int f, k, j;
    if (gm.N > 64) return -1.0;
    tiled__coord_table(&gm, coord);
    for (f = 0; f < q->nfaces; f++) {
        int c0 = q->face_start[f];
        for (k = c0 + 1; k + 1 < q->face_start[f + 1]; k++) {
            const float *p0 = q->positions + 3 * q->face_verts[c0], *p1 = q->positions + 3 * q->face_verts[k],
                        *p2 = q->positions + 3 * q->face_verts[k + 1];
            double x0[2], x1[2], x2[2], e1[3], e2[3], n[3], a, b, c, d, det, lu = 0.0, lv = 0.0, area;
            grid_drawn(&gm, coord, q, f, c0, 0, x0);
            grid_drawn(&gm, coord, q, f, k, 0, x1);
            grid_drawn(&gm, coord, q, f, k + 1, 0, x2);
            a = x1[0] - x0[0];
            b = x2[0] - x0[0];
            c = x1[1] - x0[1];
            d = x2[1] - x0[1];
            det = a * d - b * c;
            for (j = 0; j < 3; j++) {
                e1[j] = (double)p1[j] - p0[j];
                e2[j] = (double)p2[j] - p0[j];
            }
            n[0] = e1[1] * e2[2] - e1[2] * e2[1];
            n[1] = e1[2] * e2[0] - e1[0] * e2[2];
            n[2] = e1[0] * e2[1] - e1[1] * e2[0];
            area = 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            if (fabs(det) < 1e-12 || area <= 0.0) continue;
            for (j = 0; j < 3; j++) { /* the columns of d(position)/d(tile coordinates) */
                double du = (e1[j] * d - e2[j] * c) / det, dv = (e2[j] * a - e1[j] * b) / det;
                lu += du * du;
                lv += dv * dv;
            }
            lu = sqrt(lu) / side;
            lv = sqrt(lv) / side;
            all += area;
            if (lu > 1.5 || lu < 1.0 / 1.5 || lv > 1.5 || lv < 1.0 / 1.5) bad += area;
        }
    }
    return all > 0.0 ? bad / all : -1.0;
}

/* Where output face p (piece p of C) draws point st of the (s, t) plane:
 * its affine map through three of its corners, in its tile (0..1; turned:
 * a half-turned cell turned back). */
static void grid_at(const tiled__geom *gm, const float *coord, const tiled__grid *C, const tiled_mesh *q, int p,
                    const double *st, int turned, double *x)
{
    const tiled__pv *n0 = C->pv + C->pc[p].v0;
    double best = 0.0, x0[2], x1[2], x2[2], d, u, w;
    int a1 = 1, a2 = 2, m, l, j, rot = turned && C->tile[2 * C->ncls + C->cls[p]];
    for (m = 1; m < C->pc[p].nv; m++)
        for (l = m + 1; l < C->pc[p].nv; l++) {
            d = fabs((n0[m].s - n0[0].s) * (n0[l].t - n0[0].t) - (n0[l].s - n0[0].s) * (n0[m].t - n0[0].t));
            if (d > best) {
                best = d;
                a1 = m;
                a2 = l;
            }
        }
    grid_drawn(gm, coord, q, p, C->pc[p].v0, rot, x0);
    grid_drawn(gm, coord, q, p, C->pc[p].v0 + a1, rot, x1);
    grid_drawn(gm, coord, q, p, C->pc[p].v0 + a2, rot, x2);
    d = (n0[a1].s - n0[0].s) * (n0[a2].t - n0[0].t) - (n0[a2].s - n0[0].s) * (n0[a1].t - n0[0].t);
    u = ((st[0] - n0[0].s) * (n0[a2].t - n0[0].t) - (n0[a2].s - n0[0].s) * (st[1] - n0[0].t)) / d;
    w = ((n0[a1].s - n0[0].s) * (st[1] - n0[0].t) - (st[0] - n0[0].s) * (n0[a1].t - n0[0].t)) / d;
    for (j = 0; j < 2; j++) x[j] = x0[j] + u * (x1[j] - x0[j]) + w * (x2[j] - x0[j]);
}

/* The texel of tile coordinates x (0..1) in face p's tile. */
static const float *grid_texel(const pw_image *atlas, const tiled__geom *gm, const tiled_mesh *q, int p, const double *x)
{
    int i = (int)floor(x[0] * gm->T), j = (int)floor(x[1] * gm->T);
    i = i < 0 ? 0 : (i >= gm->T ? gm->T - 1 : i);
    j = j < 0 ? 0 : (j >= gm->T ? gm->T - 1 : j);
    return tiled__atlas_px(atlas, gm, q->face_tiles[p], i, j);
}

/* Along every shared cell side, as the output draws it: the length (in
 * mesh units) where the two tiles' places along the side disagree (by
 * more than a thousandth of a tile: a tile squashed on one side only, so
 * that the sides' motifs do not meet), over the sides' length (f[0]); the
 * length of the vortex cut lines over it (f[1]) and the mean colour jump
 * across them, texel against texel at 16 points of every piece's side
 * (f[2]). Output face p is piece p. */
static void grid_side_fit(const tiled_tileset *ts, const tiled__grid *C, const tiled_mesh *q, double *f)
{
    tiled__geom gm = tiled__geometry(&ts->layout);
    pw_image atlas = tiled__pw_image(&ts->atlas);
    float coord[2 * 64];
    double all = 0.0, bad = 0.0, cutlen = 0.0, jump = 0.0;
    long njump = 0;
    int p, k, j;
    f[0] = f[1] = f[2] = -1.0;
    if (gm.N > 64 || q->nfaces != (int)C->npc) return;
    tiled__coord_table(&gm, coord);
    for (p = 0; p < (int)C->npc; p++) {
        const tiled__piece *pc = C->pc + p;
        for (k = 0; k < pc->nv; k++) {
            const tiled__pv *v = C->pv + pc->v0 + k, *w = C->pv + pc->v0 + (k + 1) % pc->nv;
            int on = v->on & w->on, side = on & 2 ? 1 : (on & 4 ? 2 : 0), along = side == 1, nb, i;
            double mid[2], len = 0.0, st[2], xa[2], xb[2], worst = 0.0;
            for (j = 0; j < 3; j++) len += ((double)v->p[j] - w->p[j]) * ((double)v->p[j] - w->p[j]);
            len = sqrt(len);
            mid[0] = 0.5 * (v->s + w->s);
            mid[1] = 0.5 * (v->t + w->t);
            if (on & 32) { /* a cut line: the next band's piece of the same triangle */
                cutlen += len;
                for (nb = C->first[pc->src]; nb < C->first[pc->src + 1]; nb++)
                    if (C->pc[nb].ci == pc->ci && C->pc[nb].cj == pc->cj && C->pc[nb].sub == pc->sub + 1) break;
                for (i = 0; nb < C->first[pc->src + 1] && i < 16; i++, njump++) {
                    st[0] = v->s + (i + 0.5) / 16.0 * (w->s - v->s);
                    st[1] = v->t + (i + 0.5) / 16.0 * (w->t - v->t);
                    grid_at(&gm, coord, C, q, p, st, 0, xa);
                    grid_at(&gm, coord, C, q, nb, st, 0, xb);
                    jump += tiled__dist(grid_texel(&atlas, &gm, q, p, xa), grid_texel(&atlas, &gm, q, nb, xb), atlas.c);
                }
                continue;
            }
            if (!side || (nb = tiled__node(C, pc->src, pc->ci + (side == 1), pc->cj + (side == 2), mid)) < 0) continue;
            for (i = 0; i < 2; i++) { /* the side's ends: drawn by p, and by nb's affine map there */
                const tiled__pv *e = i ? w : v;
                grid_drawn(&gm, coord, q, p, pc->v0 + (i ? (k + 1) % pc->nv : k), C->tile[2 * C->ncls + C->cls[p]],
                           xa);
                st[0] = e->s;
                st[1] = e->t;
                grid_at(&gm, coord, C, q, nb, st, 1, xb);
                if (fabs(xa[along] - xb[along]) > worst) worst = fabs(xa[along] - xb[along]);
            }
            all += len;
            if (worst > 1e-3) bad += len;
        }
    }
    if (all > 0.0) {
        f[0] = bad / all;
        f[1] = cutlen / all;
    }
    if (njump) f[2] = jump / (double)njump;
}

/* The share of the surface in special cells (C->tile + C->ncls): drawn,
 * like every cell, one tile lookup per pixel at the parameterization's
 * scale, but a tile shown more than once or next to itself. */
static double grid_special_area(const tiled__grid *C)
{
    double all = 0.0, sp = 0.0;
    int p, k, j;
    for (p = 0; p < (int)C->npc; p++) {
        const tiled__pv *v = C->pv + C->pc[p].v0;
        double a = 0.0;
        for (k = 1; k + 1 < C->pc[p].nv; k++) {
            double e1[3], e2[3], n[3];
            for (j = 0; j < 3; j++) {
                e1[j] = (double)v[k].p[j] - v[0].p[j];
                e2[j] = (double)v[k + 1].p[j] - v[0].p[j];
            }
            n[0] = e1[1] * e2[2] - e1[2] * e2[1];
            n[1] = e1[2] * e2[0] - e1[0] * e2[2];
            n[2] = e1[0] * e2[1] - e1[1] * e2[0];
            a += 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        }
        all += a;
        if (C->tile[C->ncls + C->cls[p]]) sp += a;
    }
    return all > 0.0 ? sp / all : -1.0;
}

/* A writer that only counts bytes. */
static int grid_count_bytes(void *ctx, const void *data, size_t size)
{
    (void)data;
    *(size_t *)ctx += size;
    return 0;
}

/* The OBJ and glTF sizes of q and of q with every corner its own vertex
 * (as the output was before its vertices were welded): sz[0..1] OBJ,
 * sz[2..3] glTF. */
static void grid_export_sizes(const tiled_mesh *q, size_t *sz)
{
    tiled_mesh u = *q;
    tiled_error err;
    int k, nc = q->face_start[q->nfaces];
    memset(sz, 0, 4 * sizeof *sz);
    u.nverts = nc;
    u.positions = (float *)malloc(sizeof(float) * 3 * (size_t)nc);
    u.face_verts = (int *)malloc(sizeof(int) * (size_t)nc);
    REQUIRE(u.positions && u.face_verts);
    for (k = 0; k < nc; k++) {
        memcpy(u.positions + 3 * k, q->positions + 3 * q->face_verts[k], 3 * sizeof(float));
        u.face_verts[k] = k;
    }
    CHECK(tiled_write_obj(q, "m.mtl", grid_count_bytes, sz, &err) == TILED_OK);
    CHECK(tiled_write_obj(&u, "m.mtl", grid_count_bytes, sz + 1, &err) == TILED_OK);
    CHECK(tiled_write_gltf(q, NULL, NULL, grid_count_bytes, sz + 2, &err) == TILED_OK);
    CHECK(tiled_write_gltf(&u, NULL, NULL, grid_count_bytes, sz + 3, &err) == TILED_OK);
    free(u.positions);
    free(u.face_verts);
}

/* The mode for any mesh on a mesh at side `scale` (subdivide: Catmull-Clark
 * first): every shared cell side matches, its seams look like the inside
 * of the tiles, the output's corner types agree, and the figures. */
static void grid_case(const tiled_mesh *mesh, const char *name, float scale, int subdivide, double max_special)
{
    tiled_options o = opts(2, 1);
    tiled_tileset ts;
    tiled_mesh q;
    tiled_grid_stats st;
    tiled_error err;
    tiled__grid C;
    double inside, p90, seam, worst, fit[3], stretched;
    size_t sz[4];
    int bad, r;
    clock_t t0;
    o.scale = scale;
    o.subdivide = subdivide;
    o.stats = &st;
    if (!synth("pebbles", &o, &ts)) return;
    t0 = clock();
    r = tiled_map(mesh, &ts.layout, &o, &q, &err);
    CHECKF(r == TILED_OK, "%s: %s", name, err.message);
    if (r == TILED_OK) {
        double secs = (double)(clock() - t0) / CLOCKS_PER_SEC;
        int corners = grid_corner_types(&ts, &q), outside = grid_uv_outside(&ts, &q);
        inside = interior_jump(&ts, &p90);
        o.subdivide = 0;
        if (!subdivide && grid_of(mesh, &ts.layout, &o, &C)) {
            seam = grid_seam(&ts, &C, &worst, &bad);
            grid_side_fit(&ts, &C, &q, fit);
            stretched = grid_stretched(&ts, &q, scale);
            pwt_info("%s at side %g: seam %.4f, worst side %.4f; interior mean %.4f, 90th pct %.4f; tiles "
                     "stretched (> 1.5x or < 0.67x) on %.2f%% of the area; sides drawn unmatched on %.2f%% of their "
                     "length; cut lines %.2f%% of it, jump across them %.4f; special cells %.2f%% of the area",
                     name, (double)scale, seam, worst, inside, p90, 100.0 * stretched, 100.0 * fit[0],
                     100.0 * fit[1], fit[2], 100.0 * grid_special_area(&C));
            /* before the cut cells' bands showed whole tiles squashed into
               them: 18% to 28% of the area stretched, 11% to 13% of the
               sides' length drawn unmatched */
            CHECKF(stretched >= 0.0 && stretched <= 0.15, "tiles stretched on %.1f%% of the area (at most 15%%)",
                   100.0 * stretched);
            CHECKF(fit[0] == 0.0, "sides drawn unmatched on %.2f%% of their length", 100.0 * fit[0]);
            CHECKF(bad == 0 && bad == st.mismatched_edges, "%d shared sides without partner types (stats %d)", bad,
                   st.mismatched_edges);
            CHECKF(seam >= 0.0 && worst <= p90, "worst side %.4f > interior 90th percentile %.4f", worst, p90);
            tiled__grid_free(&C);
        }
        pwt_info("%s: %d triangles (%d vortex, %.1f%%) -> %d pieces, %d cells, %d special (%.1f%%), %d vortex "
                 "cuts; %d shared sides, %d mismatched, same tile on both sides %.1f%%, repeated (tile, side, tile) "
                 "%.1f%%; %.2f s",
                 name, st.triangles, st.vortex_triangles, 100.0 * st.vortex_triangles / st.triangles, st.pieces,
                 st.cells, st.special_cells, 100.0 * st.special_cells / st.cells, st.cut_vortices, st.grid_edges,
                 st.mismatched_edges, 100.0 * st.same_tile_edges / st.grid_edges,
                 100.0 * st.repeated_edges / st.grid_edges, secs);
        CHECKF(st.mismatched_edges == 0, "%d of %d shared sides mismatched", st.mismatched_edges, st.grid_edges);
        grid_export_sizes(&q, sz);
        pwt_info("%s: %d corners on %d vertices; OBJ %lu bytes (%lu with a vertex per corner), glTF %lu (%lu)", name,
                 q.face_start[q.nfaces], q.nverts, (unsigned long)sz[0], (unsigned long)sz[1], (unsigned long)sz[2],
                 (unsigned long)sz[3]);
        /* the pieces' corners welded: before, one vertex per corner */
        CHECKF(2 * q.nverts < q.face_start[q.nfaces], "%d vertices for %d corners", q.nverts, q.face_start[q.nfaces]);
        CHECKF(sz[0] < sz[1] && sz[2] < sz[3], "exports not smaller welded: OBJ %lu >= %lu or glTF %lu >= %lu",
               (unsigned long)sz[0], (unsigned long)sz[1], (unsigned long)sz[2], (unsigned long)sz[3]);
        CHECKF(corners == 0, "%d corners' types are not their tile's", corners);
        CHECKF(outside == 0, "%d corners outside their tile", outside);
        /* special: more than 1.5 cells' area or its own neighbour (a vortex's
           face left whole); before the faces were cut, 13% (torus) to 34%
           (elephant) */
        CHECKF(st.cells > 0 && st.special_cells <= max_special * st.cells, "%d of %d cells special (at most %.0f%%)",
               st.special_cells, st.cells, 100.0 * max_special);
        CHECKF(st.cut_vortices > 0, "no vortex's face cut (%d vortex triangles)", st.vortex_triangles);
        /* with 16 tiles and independent sides, the same tile meets itself on
           1 side in 16 (a periodic texture: on every side); a cell that spans
           two (special) ties its neighbours' sides together, which makes it
           up to 3 times as often on these meshes (a cell next to itself
           counts; up to 5 times before the faces were cut) */
        CHECKF(st.same_tile_edges <= 0.25 * st.grid_edges, "same tile on %d of %d sides", st.same_tile_edges,
               st.grid_edges);
        tiled_mesh_free(&q);
    }
    tiled_tileset_free(&ts);
}

static void t_grid_torus(void)
{
    tiled_options o = opts(2, 1);
    tiled_mesh mesh, fine;
    tiled_error err;
    tiled_tileset ts = layout_only(2, 1, 8);
    REQUIRE(tiled_builtin_mesh("torus", &o, &mesh, &err) == TILED_OK);
    o.subdivide = 2; /* 9,216 triangles: the built-in torus is too coarse for tiles of 0.3 */
    REQUIRE(tiled_map(&mesh, &ts.layout, &o, &fine, &err) == TILED_OK);
    grid_case(&fine, "torus (subdivided twice)", 0.3f, 0, 0.15);
    grid_case(&mesh, "torus --subdivide 2", 0.3f, 2, 0.15);
    tiled_mesh_free(&mesh);
    tiled_mesh_free(&fine);
}

static void t_grid_icosahedron(void)
{
    tiled_options o = opts(2, 1);
    tiled_mesh mesh, fine;
    tiled_error err;
    tiled_tileset ts = layout_only(2, 1, 8);
    REQUIRE(tiled_builtin_mesh("icosahedron", &o, &mesh, &err) == TILED_OK);
    o.subdivide = 3;
    REQUIRE(tiled_map(&mesh, &ts.layout, &o, &fine, &err) == TILED_OK);
    grid_case(&fine, "icosahedron (subdivided 3 times)", 0.3f, 0, 0.15);
    grid_case(&mesh, "icosahedron --subdivide 3", 0.3f, 3, 0.15);
    tiled_mesh_free(&mesh);
    tiled_mesh_free(&fine);
}

static void grid_real(const char *file, float diag_fraction, double max_special)
{
    const char *path = pwt_data(file);
    tiled_options o = opts(2, 1);
    tiled_mesh mesh;
    tiled_error err;
    pw_trimesh tm;
    pw_err e;
    pw_mesh v;
    pw_alloc a = tiled__alloc(NULL);
    if (!path) return;
    REQUIRE(tiled_load_mesh(path, &o, &mesh, &err) == TILED_OK);
    v = tiled__pw_mesh(&mesh);
    REQUIRE(pw_trimesh_init(&a, &v, &tm, &e) == PW_OK);
    grid_case(&mesh, file, diag_fraction * tm.diag, 0, max_special);
    pw_trimesh_free(&a, &tm);
    tiled_mesh_free(&mesh);
}

static void t_grid_real_elephant(void) { grid_real("meshes/elephant.off", 0.06f, 0.22); }
static void t_grid_real_armadillo(void) { grid_real("meshes/armadillo.off", 0.026f, 0.12); }
static void t_grid_real_bunny(void) { grid_real("meshes/bunny00.off", 0.05f, 0.13); }

/* Same inputs, same mesh; another seed, other tiles on the same cells;
 * fixed_start: the same cells without half turns. */
static void t_grid_determinism(void)
{
    tiled_options o = opts(2, 1);
    tiled_tileset ts = layout_only(2, 1, 8);
    tiled_mesh mesh, q[4];
    tiled_error err;
    int k, same01, same02, same03;
    REQUIRE(tiled_builtin_mesh("double-torus", &o, &mesh, &err) == TILED_OK);
    o.scale = 1.2f;
    o.subdivide = 2;
    for (k = 0; k < 4; k++) { /* q[3]: no half turns (fixed_start) */
        o.seed = k == 2 ? 5 : 4;
        o.fixed_start = k == 3;
        REQUIRE(tiled_map(&mesh, &ts.layout, &o, &q[k], &err) == TILED_OK);
    }
    same01 = q[0].nfaces == q[1].nfaces && q[0].nverts == q[1].nverts &&
             !memcmp(q[0].positions, q[1].positions, sizeof(float) * 3 * q[0].nverts) &&
             !memcmp(q[0].uvs, q[1].uvs, sizeof(float) * 2 * q[0].nverts) &&
             !memcmp(q[0].face_tiles, q[1].face_tiles, sizeof(int) * q[0].nfaces);
    same02 = q[0].nfaces == q[2].nfaces && !memcmp(q[0].face_tiles, q[2].face_tiles, sizeof(int) * q[0].nfaces);
    same03 = q[0].nfaces == q[3].nfaces && !memcmp(q[0].uvs, q[3].uvs, sizeof(float) * 2 * q[0].nverts);
    CHECK(same01);
    CHECK(!same02);
    CHECK(q[0].nfaces == q[3].nfaces && !same03);
    for (k = 0; k < 4; k++) tiled_mesh_free(&q[k]);
    tiled_mesh_free(&mesh);
}

/* Bad sides and options are refused by name, with the range. */
static void t_grid_bad_input(void)
{
    tiled_options o = opts(2, 1);
    tiled_tileset ts = layout_only(2, 1, 8);
    tiled_mesh mesh, q;
    tiled_error err;
    static const float bad[3] = {-1.0f, 1e9f, 0.001f};
    int k;
    REQUIRE(tiled_builtin_mesh("torus", &o, &mesh, &err) == TILED_OK);
    for (k = 0; k < 3; k++) {
        o.scale = bad[k];
        CHECK_EQ_INT(tiled_map(&mesh, &ts.layout, &o, &q, &err), TILED_ERR_INVALID);
        CHECKF(strstr(err.message, k ? "outside [" : "not a positive") != NULL, "scale %g: %s", (double)bad[k],
               err.message);
        CHECK(q.nfaces == 0 && q.positions == NULL);
    }
    o.scale = (float)(0.0 * (1e300 * 1e300));
    CHECK_EQ_INT(tiled_map(&mesh, &ts.layout, &o, &q, &err), TILED_ERR_INVALID);
    CHECKF(strstr(err.message, "scale") != NULL, "message: %s", err.message);
    o.scale = 0.5f;
    o.smooth = 1;
    CHECK_EQ_INT(tiled_map(&mesh, &ts.layout, &o, &q, &err), TILED_ERR_INVALID);
    CHECKF(strstr(err.message, "smooth") != NULL, "message: %s", err.message);
    o.smooth = 0;
    o.field = (tiled_field)7;
    CHECK_EQ_INT(tiled_map(&mesh, &ts.layout, &o, &q, &err), TILED_ERR_INVALID);
    CHECKF(strstr(err.message, "field") != NULL, "message: %s", err.message);
    tiled_mesh_free(&mesh);
}

/* The curvature field and case 1 run as well: case 1's one self-matching
 * type leaves no side unmatched. */
static void t_grid_curvature_case1(void)
{
    tiled_options o = opts(1, 3);
    tiled_tileset ts = layout_only(1, 3, 8);
    tiled_mesh mesh, q;
    tiled_grid_stats st;
    tiled_error err;
    REQUIRE(tiled_builtin_mesh("torus", &o, &mesh, &err) == TILED_OK);
    o.scale = 0.4f;
    o.subdivide = 2;
    o.field = TILED_FIELD_CURVATURE;
    o.stats = &st;
    REQUIRE(tiled_map(&mesh, &ts.layout, &o, &q, &err) == TILED_OK);
    pwt_info("curvature field, case 1: %d cells, %d special, %d vortex triangles", st.cells, st.special_cells,
             st.vortex_triangles);
    CHECK(st.cells > 0 && st.mismatched_edges == 0 && q.nfaces == st.pieces);
    tiled_mesh_free(&q);
    tiled_mesh_free(&mesh);
}

static const pwt_case cases[] = {
    {"tiled/fig29_formula", t_fig29_formula},
    {"tiled/edge_invariants", t_edge_invariants},
    {"tiled/case1_invariants", t_case1_invariants},
    {"tiled/random_start", t_random_start},
    {"tiled/seams_case2", t_seams_case2},
    {"tiled/seams_case2_pairs2", t_seams_case2_pairs2},
    {"tiled/seams_case1", t_seams_case1},
    {"tiled/all_tiles_used", t_all_tiles_used},
    {"tiled/determinism", t_determinism},
    {"tiled/validate", t_validate},
    {"tiled/guards", t_guards},
    {"tiled/catmull_clark_first", t_catmull_clark_first},
    {"tiled/bad_meshes", t_bad_meshes},
    {"tiled/bad_arguments", t_bad_arguments},
    {"tiled/cancel", t_cancel},
    {"tiled/alloc_failures", t_alloc_failures},
    {"tiled/real_cube_quad", t_real_cube_quad},
    {"tiled/real_torus_quad", t_real_torus_quad},
    {"tiled/real_cross_quad", t_real_cross_quad},
    {"tiled/real_double_torus", t_real_double_torus},
    {"tiled/real_elephant", t_real_elephant},
    {"tiled/real_knot", t_real_knot},
    {"tiled/real_brick", t_real_brick},
    {"tiled/real_leopard", t_real_leopard},
    {"tiled/real_burlap", t_real_burlap},
    {"tiled/real_java", t_real_java},
    {"tiled/real_pine", t_real_pine},
    {"tiled/real_marble3", t_real_marble3},
    {"tiled/drawn_tile_size", t_drawn_tile_size},
    {"tiled/render_options", t_render_options},
    {"tiled/motif_cuts_pebbles", t_motif_cuts_pebbles},
    {"tiled/corner_repetition", t_corner_repetition},
    {"tiled/motif_cuts_gimp", t_motif_cuts_gimp},
    {"tiled/grid_torus", t_grid_torus},
    {"tiled/grid_icosahedron", t_grid_icosahedron},
    {"tiled/grid_real_elephant", t_grid_real_elephant},
    {"tiled/grid_real_armadillo", t_grid_real_armadillo},
    {"tiled/grid_real_bunny", t_grid_real_bunny},
    {"tiled/grid_determinism", t_grid_determinism},
    {"tiled/grid_bad_input", t_grid_bad_input},
    {"tiled/grid_curvature_case1", t_grid_curvature_case1},
    {"tiled/grid_alloc_failures", t_grid_alloc_failures},
};
PWT_MAIN(cases)
