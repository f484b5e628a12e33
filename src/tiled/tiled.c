/* tiled.c: the implementation of tiled.h (Kaur 2003, "Texture Mapping Using
 * Tiled Textures"). Chapter numbers refer to the thesis. */
#include "../common/base.h"
#include "../common/vec.h"
#include "../common/rng.h"
#include "../common/image.h"
#include "../common/deflate.h"
#include "../common/png.h"
#include "../common/mesh.h"
#include "../common/halfedge.h"
#include "../common/subdiv.h"
#include "../common/raster.h"
#include "../common/render.h"
#include "../common/graphcut.h"
#include "../common/quilt.h"
#include "../common/glue.h"
#include "../common/gltf.h"
#include "tiled.h"

/* ---- glue between the public types and the shared core ------------------ */

/* The public result codes repeat the shared ones. */
typedef char tiled__codes_match[(int)TILED_ERR_NOCONVERGE == PW_ERR_NOCONVERGE ? 1 : -1];

PW_PUBLIC_GLUE(tiled);

/* A pw_mesh view of a public mesh (no copy, no texture coordinates). */
static pw_mesh tiled__pw_mesh(const tiled_mesh *t)
{
    pw_mesh m;
    memset(&m, 0, sizeof m);
    m.nv = t->nverts;
    m.pos = t->positions;
    m.nf = t->nfaces;
    m.fstart = t->face_start;
    m.fv = t->face_verts;
    return m;
}

/* Moves a pw_mesh's geometry into a public mesh (texture coordinates of a
 * loaded file are dropped: tiled.h computes its own). */
static void tiled__take_mesh(pw_mesh *m, const pw_alloc *a, tiled_mesh *t)
{
    memset(t, 0, sizeof *t);
    t->nverts = m->nv;
    t->positions = m->pos;
    t->nfaces = m->nf;
    t->face_start = m->fstart;
    t->face_verts = m->fv;
    t->allocator = tiled__allocator(a);
    pw_free(a, m->uv);
    pw_free(a, m->fuv);
    memset(m, 0, sizeof *m);
}

TILEDDEF tiled_options tiled_default_options(void)
{
    tiled_options o;
    memset(&o, 0, sizeof o);
    o.layout.case_number = 2;
    o.layout.pairs = 1;
    o.layout.grid = 4;
    return o;
}

TILEDDEF const char *tiled_result_string(tiled_result r) { return pw_result_string((int)r); }

static tiled_options tiled__options(const tiled_options *opt)
{
    return opt ? *opt : tiled_default_options();
}

static pw_progress tiled__progress(const tiled_options *o)
{
    pw_progress p;
    p.fn = o->progress;
    p.user = o->progress_user;
    return p;
}

/* ---- layout of the tiled texture (see the top of tiled.h) ------------------ */

/* The power of two nearest x (ties go down). */
static int tiled__pow2_near(int x)
{
    int p = 1;
    while (p * 2 <= x) p *= 2;
    return x - p <= 2 * p - x ? p : 2 * p;
}

/* Pixel geometry of an atlas. */
typedef struct tiled__geom {
    int n;     /* types per side: 2n (case 2) or 1 (case 1) */
    int N;     /* tiles per row and column */
    int T, g;  /* tile size and guard */
    int C, W;  /* cell size and atlas size */
} tiled__geom;

static tiled__geom tiled__geometry(const tiled_layout *l)
{
    tiled__geom gm;
    gm.n = l->case_number == 1 ? 1 : 2 * l->pairs;
    gm.N = l->case_number == 1 ? l->grid : gm.n * gm.n;
    gm.T = l->tile_size;
    gm.g = l->guard < 0 ? 0 : l->guard;
    gm.C = gm.T + 2 * gm.g;
    gm.W = gm.N * gm.C;
    return gm;
}

/* Fills in the defaults of a layout and checks it. tile_hint is the
 * exemplar's smaller side (0 if none). */
static int tiled__resolve(const tiled_layout *in, int tile_hint, tiled_layout *out, pw_err *e)
{
    tiled_layout l = *in;
    tiled__geom gm;
    if (!l.case_number) l.case_number = 2;
    if (!l.pairs) l.pairs = 1;
    if (!l.grid) l.grid = 4;
    if (l.case_number != 1 && l.case_number != 2)
        return pw_fail(e, PW_ERR_INVALID, "case must be 1 or 2 (got %d)", l.case_number);
    if (l.pairs < 1 || l.pairs > 8)
        return pw_fail(e, PW_ERR_INVALID, "pairs must be 1..8 (got %d)", l.pairs);
    if (l.grid < 1 || l.grid > 256)
        return pw_fail(e, PW_ERR_INVALID, "grid must be 1..256 (got %d)", l.grid);
    if (!l.tile_size) l.tile_size = tile_hint > 0 ? pw_clampi(tiled__pow2_near(tile_hint), 16, 256) : 64;
    if (l.tile_size < 4 || l.tile_size > 4096)
        return pw_fail(e, PW_ERR_INVALID, "tile size must be 4..4096 pixels (got %d)", l.tile_size);
    if (!l.guard) l.guard = pw_mini(pw_maxi(tiled__pow2_near(l.tile_size / 8), 2), l.tile_size);
    if (l.guard != TILED_NO_GUARD && (l.guard < 1 || l.guard > l.tile_size))
        return pw_fail(e, PW_ERR_INVALID, "guard must be 1..%d pixels or TILED_NO_GUARD (got %d)",
                       l.tile_size, l.guard);
    gm = tiled__geometry(&l);
    if ((int64_t)gm.N * gm.C > PW_MAX_IMAGE_DIM ||
        (int64_t)gm.N * gm.C * gm.N * gm.C > PW_MAX_IMAGE_PIXELS)
        return pw_fail(e, PW_ERR_LIMIT,
                       "a tiled texture of %dx%d tiles of %d px would be %lld px wide, over the "
                       "image size limit", gm.N, gm.N, gm.C, (long long)gm.N * gm.C);
    *out = l;
    return PW_OK;
}

/* Highest mip level that never mixes two tiles: the cell size must be a
 * multiple of 2^level and the guard must cover a level-`level` texel. */
static int tiled__max_mip(const tiled__geom *gm)
{
    int l = 0;
    while ((2 << l) <= gm->g && gm->C % (2 << l) == 0) l++;
    return l;
}

/* Texture coordinate tables: u of column col at corner offset du (0 or 1)
 * is ucoord[col*2 + du]; rows likewise (v = 0 at the bottom). */
static void tiled__coord_table(const tiled__geom *gm, float *coord)
{
    int k;
    for (k = 0; k < gm->N; k++) {
        coord[2 * k] = (float)((double)(k * gm->C + gm->g) / gm->W);
        coord[2 * k + 1] = (float)((double)(k * gm->C + gm->g + gm->T) / gm->W);
    }
}

/* Boundary types of case-2 tile (col,row): e0 bottom, e1 right, e2 top,
 * e3 left (Fig. 23: column e0*2n+e1, row e2*2n+e3). */
static void tiled__tile_types(const tiled__geom *gm, int case1, int tile, int types[4])
{
    int col = tile % gm->N, row = tile / gm->N;
    if (case1) {
        types[0] = types[1] = types[2] = types[3] = 0;
        return;
    }
    types[0] = col / gm->n;
    types[1] = col % gm->n;
    types[2] = row / gm->n;
    types[3] = row % gm->n;
}

/* The type that must face type t across an edge. */
static int tiled__partner(int case1, int t) { return case1 ? t : t ^ 1; }

/* ---- mapping (ch. III.2, Fig. 29) --------------------------------------- */

/* Checks a caller-made mesh before anything trusts it. */
static int tiled__check_mesh(const tiled_mesh *m, pw_err *e)
{
    int f, k;
    if (!m || !m->positions || !m->face_start || !m->face_verts)
        return pw_fail(e, PW_ERR_INVALID, "mesh has NULL arrays");
    if (m->nverts < 3 || m->nverts > PW_MAX_MESH_ELEMENTS || m->nfaces > PW_MAX_MESH_ELEMENTS)
        return pw_fail(e, PW_ERR_INVALID, "mesh has %d vertices and %d faces", m->nverts,
                       m->nfaces);
    if (m->nfaces < 1) return pw_fail(e, PW_ERR_DEGENERATE, "mesh has no faces");
    if (m->face_start[0] != 0)
        return pw_fail(e, PW_ERR_INVALID, "face_start[0] must be 0 (got %d)", m->face_start[0]);
    for (f = 0; f < m->nfaces; f++) {
        int d = m->face_start[f + 1] - m->face_start[f];
        if (d < 3 || d > PW_MAX_FACE_DEGREE || m->face_start[f + 1] > PW_MAX_MESH_ELEMENTS)
            return pw_fail(e, PW_ERR_DEGENERATE, "face %d has %d corners", f, d);
    }
    for (k = 0; k < m->face_start[m->nfaces]; k++)
        if (m->face_verts[k] < 0 || m->face_verts[k] >= m->nverts)
            return pw_fail(e, PW_ERR_INVALID, "face corner %d refers to vertex %d of %d", k,
                           m->face_verts[k], m->nverts);
    for (k = 0; k < 3 * m->nverts; k++)
        if (!pw_is_finite(m->positions[k]))
            return pw_fail(e, PW_ERR_INVALID, "vertex %d has a non-finite coordinate", k / 3);
    return PW_OK;
}

static int tiled__all_quads(const pw_mesh *m)
{
    int f;
    for (f = 0; f < m->nf; f++)
        if (m->fstart[f + 1] - m->fstart[f] != 4) return 0;
    return 1;
}

/* Catmull-Clark until all faces are quads (ch. VI: "any mesh can easily be
 * converted to a quadrilateral mesh"), then `extra` more levels; `planned`
 * counts every level still to come (smoothing included) for the size
 * check made before any work. On success *q owns its arrays and *hm is its
 * half-edge structure. */
static int tiled__quadrangulate(const pw_alloc *a, const tiled_mesh *in, int planned, int extra,
                                const pw_progress *pr, pw_mesh *q, pw_hmesh *hm, pw_err *e)
{
    pw_mesh view = tiled__pw_mesh(in), next;
    int levels = (tiled__all_quads(&view) ? 0 : 1) + extra, l, r;
    double faces = in->face_start[in->nfaces];
    for (l = 0; l < levels - extra + planned; l++) faces *= 4; /* every level planned, smoothing too */
    if (faces > PW_MAX_MESH_ELEMENTS)
        return pw_fail(e, PW_ERR_LIMIT, "subdividing %d faces %d times would make %.0f faces "
                       "(limit %d)", in->nfaces, levels - extra + planned, faces, PW_MAX_MESH_ELEMENTS);
    if ((r = pw_mesh_copy(a, &view, q, e)) != PW_OK) return r;
    for (l = 0;; l++) {
        if ((r = pw_hmesh_build(a, q->nv, q->nf, q->fstart, q->fv, hm, e)) != PW_OK) break;
        if (l == levels) return PW_OK;
        if ((r = pw_report(pr, (float)l / (float)(levels + 1), "subdivision", e)) != PW_OK) break;
        r = pw_catmull_clark(a, hm, q->pos, &next, e);
        pw_hmesh_free(a, hm);
        if (r != PW_OK) break;
        pw_mesh_free(a, q);
        *q = next;
    }
    pw_hmesh_free(a, hm);
    pw_mesh_free(a, q);
    return r;
}

/* AssignBoundaries (Fig. 29), generalised to n pairs (ch. VI): each edge
 * draws a pair k and an orientation; its half-edges get 2k and 2k+1. One
 * 32-bit draw per edge: bit 0 orients, the rest picks k by a multiply-shift
 * (bias below 1e-8). Case 1 has the single self-matching type 0. */
static void tiled__assign_boundaries(const pw_hmesh *hm, const tiled_layout *l, uint64_t seed,
                                     int *types)
{
    pw_rng r = pw_rng_seed(seed, 1);
    const int nh = hm->nh, *twin = hm->twin;
    int h, pairs = l->case_number == 1 ? 0 : l->pairs;
    if (!pairs) {
        memset(types, 0, sizeof(int) * (size_t)nh);
        return;
    }
    for (h = 0; h < nh; h++) { /* edges in order of their lower half-edge */
        int t = twin[h], o, k;
        uint32_t x;
        if (t >= 0 && t < h) continue;
        x = pw_rng_u32(&r);
        o = (int)(x & 1u);
        k = (int)(((uint64_t)(x >> 1) * (uint32_t)pairs) >> 31);
        types[h] = 2 * k + o;
        if (t >= 0) types[t] = 2 * k + 1 - o;
    }
}

/* AssignTextureCoordinates (Fig. 29, with the u-offset erratum fixed and
 * guard bands): a random starting edge per quad ("further randomness") makes
 * the walk e0e1e2e3 start at corner `rot`; corner (rot+k) mod 4 takes the
 * tile's corner k. Case 1 draws a tile, a rotation and a mirror instead. */
static void tiled__assign_uvs(const pw_mesh *q, const int *types, const tiled__geom *gm,
                              int case1, const tiled_options *o, const float *coord, float *uv,
                              int *face_tiles)
{
    pw_rng r = pw_rng_seed(o->seed, 2);
    const int nf = q->nf, n = gm->n, N = gm->N, nn = N * N;
    const uint32_t rot_mask = o->fixed_start ? 0u : 3u, flip_mask = case1 && !o->no_mirror;
    int f, c;
    for (f = 0; f < nf; f++) {
        const int *t = types + 4 * f; /* all quads: face f's corners are 4f..4f+3 */
        float cu[4], cv[4], *out = uv + 8 * f;
        uint32_t x = pw_rng_u32(&r);
        int rot = (int)(x & rot_mask), flip = (int)(x >> 2 & flip_mask), col, row;
        if (case1) { /* a random tile; mirrored tiles take tile corner k ^ 1 */
            int tile = (int)(((uint64_t)(x >> 3) * (uint32_t)nn) >> 29);
            col = tile % N;
            row = tile / N;
        } else {
            col = t[rot] * n + t[(rot + 1) & 3];
            row = t[(rot + 2) & 3] * n + t[(rot + 3) & 3];
        }
        cu[0] = cu[3] = coord[2 * col]; /* tile corners 0..3: (0,0) (1,0) (1,1) (0,1) */
        cu[1] = cu[2] = coord[2 * col + 1];
        cv[0] = cv[1] = coord[2 * row];
        cv[2] = cv[3] = coord[2 * row + 1];
        for (c = 0; c < 4; c++) { /* quad corner c is tile corner c - rot */
            int k = ((c - rot) & 3) ^ flip;
            out[2 * c] = cu[k];
            out[2 * c + 1] = cv[k];
        }
        face_tiles[f] = row * N + col;
    }
}

TILEDDEF void tiled_mesh_free(tiled_mesh *m)
{
    pw_alloc a;
    if (!m) return;
    a = tiled__alloc(&m->allocator);
    pw_free(&a, m->positions);
    pw_free(&a, m->face_start);
    pw_free(&a, m->face_verts);
    pw_free(&a, m->uvs);
    pw_free(&a, m->corner_types);
    pw_free(&a, m->face_tiles);
    memset(m, 0, sizeof *m);
}

/* A quad mesh being mapped: geometry, its half-edges, and per corner the
 * texture coordinates and boundary types, per face the tile. */
typedef struct tiled__mapped {
    pw_mesh q;
    pw_hmesh hm;
    float *uv;
    int *types, *tiles;
} tiled__mapped;

static void tiled__mapped_free(const pw_alloc *a, tiled__mapped *m)
{
    pw_mesh_free(a, &m->q);
    pw_hmesh_free(a, &m->hm);
    pw_free(a, m->uv);
    pw_free(a, m->types);
    pw_free(a, m->tiles);
    memset(m, 0, sizeof *m);
}

/* Allocates the per-corner and per-face arrays for nc corners, nf faces. */
static int tiled__mapped_arrays(const pw_alloc *a, int nc, int nf, float **uv, int **types,
                                int **tiles, pw_err *e)
{
    *uv = (float *)pw_alloc_array(a, (size_t)nc * 2, sizeof(float), "texture coordinates", e);
    *types = (int *)pw_alloc_array(a, (size_t)nc, sizeof(int), "boundary types", e);
    *tiles = (int *)pw_alloc_array(a, (size_t)nf, sizeof(int), "face tiles", e);
    if (*uv && *types && *tiles) return PW_OK;
    pw_free(a, *uv);
    pw_free(a, *types);
    pw_free(a, *tiles);
    *uv = NULL;
    *types = *tiles = NULL;
    return PW_ERR_NOMEM;
}

/* Runs both procedures of Fig. 29 on the quad mesh. */
static int tiled__assign(const pw_alloc *a, tiled__mapped *m, const tiled_layout *l,
                         const tiled_options *o, pw_err *e)
{
    tiled__geom gm = tiled__geometry(l);
    float *coord = (float *)pw_alloc_array(a, (size_t)gm.N * 2, sizeof(float), "coordinates", e);
    if (!coord ||
        tiled__mapped_arrays(a, m->q.fstart[m->q.nf], m->q.nf, &m->uv, &m->types, &m->tiles, e)) {
        pw_free(a, coord);
        return PW_ERR_NOMEM;
    }
    tiled__coord_table(&gm, coord);
    tiled__assign_boundaries(&m->hm, l, o->seed, m->types);
    tiled__assign_uvs(&m->q, m->types, &gm, l->case_number == 1, o, coord, m->uv, m->tiles);
    pw_free(a, coord);
    return PW_OK;
}

/* Carries the mapping through one Catmull-Clark step (the thesis smooths
 * its meshes after mapping, Figs. 30, 31, 36, 38). Output quad h is
 * (corner h, edge point of h, face point, edge point of prev(h)); each
 * quad's tile is an axis-aligned square in texture space, so the
 * sub-quads' coordinates are exact bilinear values: corner, edge midpoints
 * and centre. Sub-edges on an old edge keep its boundary type; new
 * interior edges get -1. */
static void tiled__smooth_uvs(const tiled__mapped *m, float *uv, int *types, int *tiles)
{
    int h, k;
    for (h = 0; h < m->hm.nh; h++) {
        int f = m->hm.hface[h], nx = pw_he_next(&m->hm, h), pv = pw_he_prev(&m->hm, h);
        float c[2] = {0.0f, 0.0f}, inv = 1.0f / (float)(m->q.fstart[f + 1] - m->q.fstart[f]);
        for (k = m->q.fstart[f]; k < m->q.fstart[f + 1]; k++) {
            c[0] += m->uv[2 * k] * inv;
            c[1] += m->uv[2 * k + 1] * inv;
        }
        for (k = 0; k < 2; k++) {
            uv[8 * h + k] = m->uv[2 * h + k];
            uv[8 * h + 2 + k] = 0.5f * (m->uv[2 * h + k] + m->uv[2 * nx + k]);
            uv[8 * h + 4 + k] = c[k];
            uv[8 * h + 6 + k] = 0.5f * (m->uv[2 * pv + k] + m->uv[2 * h + k]);
        }
        types[4 * h] = m->types[h];
        types[4 * h + 1] = types[4 * h + 2] = -1;
        types[4 * h + 3] = m->types[pv];
        tiles[h] = m->tiles[f];
    }
}

static int tiled__smooth(const pw_alloc *a, tiled__mapped *m, pw_err *e)
{
    tiled__mapped next;
    int r;
    memset(&next, 0, sizeof next);
    if ((r = pw_catmull_clark(a, &m->hm, m->q.pos, &next.q, e)) != PW_OK ||
        (r = tiled__mapped_arrays(a, 4 * m->hm.nh, m->hm.nh, &next.uv, &next.types, &next.tiles, e)) != PW_OK ||
        (r = pw_hmesh_build(a, next.q.nv, next.q.nf, next.q.fstart, next.q.fv, &next.hm, e)) != PW_OK) {
        tiled__mapped_free(a, &next);
        return r;
    }
    tiled__smooth_uvs(m, next.uv, next.types, next.tiles);
    tiled__mapped_free(a, m);
    *m = next;
    return PW_OK;
}

TILEDDEF tiled_result tiled_map(const tiled_mesh *in, const tiled_layout *layout,
                                const tiled_options *opt, tiled_mesh *out, tiled_error *err)
{
    tiled_options o = tiled__options(opt);
    pw_alloc a = tiled__alloc(&o.allocator);
    pw_progress pr = tiled__progress(&o);
    tiled_layout l;
    tiled__mapped m;
    pw_err pe;
    int k;
    pw_err_clear(&pe);
    memset(&m, 0, sizeof m);
    if (out) memset(out, 0, sizeof *out);
    if (!out || !layout) pw_fail(&pe, PW_ERR_INVALID, "tiled_map: NULL argument");
    else if (o.subdivide < 0 || o.subdivide > 8 || o.smooth < 0 || o.smooth > 8)
        pw_fail(&pe, PW_ERR_INVALID, "subdivide and smooth must be 0..8 (got %d and %d)",
                o.subdivide, o.smooth);
    else if (tiled__resolve(layout, 0, &l, &pe) == PW_OK && tiled__check_mesh(in, &pe) == PW_OK &&
             tiled__quadrangulate(&a, in, o.subdivide + o.smooth, o.subdivide, &pr, &m.q, &m.hm,
                                  &pe) == PW_OK &&
             pw_report(&pr, 0.8f, "texture coordinates", &pe) == PW_OK &&
             tiled__assign(&a, &m, &l, &o, &pe) == PW_OK) {
        for (k = 0; k < o.smooth && pe.code == PW_OK; k++)
            if (pw_report(&pr, 0.85f + 0.1f * (float)k / (float)o.smooth, "smoothing", &pe) == PW_OK)
                tiled__smooth(&a, &m, &pe);
        if (pe.code == PW_OK) {
            tiled__take_mesh(&m.q, &a, out);
            out->uvs = m.uv;
            out->corner_types = m.types;
            out->face_tiles = m.tiles;
            m.uv = NULL;
            m.types = m.tiles = NULL;
        }
    }
    tiled__mapped_free(&a, &m);
    return tiled__done(&pe, err);
}

/* ---- tiles: side frames and guard bands --------------------------------- */

/* Tile pixels are addressed (i, j): column i from the left, row j from the
 * BOTTOM, both 0..T-1. Side s has its own frame (a, b): a runs along the
 * side in the counter-clockwise walk of the tile, b counts rows inward
 * (b < 0 is outside the tile). Across an edge, the neighbour's frame is
 * (a', b') = (T-1-a, -1-b): the two tiles walk the edge in opposite
 * directions (DESIGN.md errata). */
static void tiled__to_side(int side, int T, int i, int j, int *a, int *b)
{
    switch (side) {
    case 0: *a = i; *b = j; break;
    case 1: *a = j; *b = T - 1 - i; break;
    case 2: *a = T - 1 - i; *b = T - 1 - j; break;
    default: *a = T - 1 - j; *b = i; break;
    }
}

static void tiled__from_side(int side, int T, int a, int b, int *i, int *j)
{
    switch (side) {
    case 0: *i = a; *j = b; break;
    case 1: *j = a; *i = T - 1 - b; break;
    case 2: *i = T - 1 - a; *j = T - 1 - b; break;
    default: *j = T - 1 - a; *i = b; break;
    }
}

/* Pixel (i, j) of tile (col, row) in an atlas; i, j may reach into the
 * guard band (-g .. T+g-1). Cells count rows from the bottom of the image. */
static float *tiled__atlas_px(const pw_image *atlas, const tiled__geom *gm, int tile, int i,
                              int j)
{
    int col = tile % gm->N, row = tile / gm->N;
    int x = col * gm->C + gm->g + i, y = row * gm->C + gm->g + j;
    return atlas->px + ((size_t)(atlas->h - 1 - y) * atlas->w + x) * atlas->c;
}

/* For each boundary type, the first tile side that carries it: the pattern
 * that continues across a side of the partner type. */
static void tiled__representatives(const tiled__geom *gm, int case1, int *rep_tile, int *rep_side)
{
    int t, s, types[4];
    for (t = 0; t < gm->n; t++) rep_tile[t] = -1;
    for (t = 0; t < gm->N * gm->N; t++) {
        tiled__tile_types(gm, case1, t, types);
        for (s = 0; s < 4; s++)
            if (rep_tile[types[s]] < 0) {
                rep_tile[types[s]] = t;
                rep_side[types[s]] = s;
            }
    }
}

/* The side a guard pixel (i, j) belongs to: the one it lies least far
 * outside of (corners of the band split along the diagonal). */
static int tiled__guard_side(int T, int i, int j, int *depth)
{
    int d[4], s, best = -1;
    d[0] = -j;
    d[1] = i - (T - 1);
    d[2] = j - (T - 1);
    d[3] = -i;
    for (s = 0; s < 4; s++)
        if (d[s] > 0 && (best < 0 || d[s] < d[best])) best = s;
    *depth = best >= 0 ? d[best] : 0;
    return best;
}

/* Fills every tile's guard band with what continues across each side: the
 * rows just inside a tile of the partner type, turned by 180 degrees. For
 * synthesised tiles this is exactly what any neighbour shows; for a
 * hand-made set it is its first tile of the partner type. */
static void tiled__fill_guards(pw_image *atlas, const tiled__geom *gm, int case1)
{
    int rep_tile[16], rep_side[16], t, i, j, types[4];
    int T = gm->T, g = gm->g;
    if (g == 0) return;
    tiled__representatives(gm, case1, rep_tile, rep_side);
    for (t = 0; t < gm->N * gm->N; t++) {
        tiled__tile_types(gm, case1, t, types);
        for (j = -g; j < T + g; j++)
            for (i = -g; i < T + g; i++) {
                int depth, s = tiled__guard_side(T, i, j, &depth), a, b, pt, pi, pj;
                if (s < 0) continue;
                if ((i < 0 || i >= T) && (j < 0 || j >= T)) {
                    /* beyond a corner the pattern depends on the vertex's
                     * valence: reflect the tile's own corner instead */
                    memcpy(tiled__atlas_px(atlas, gm, t, i, j),
                           tiled__atlas_px(atlas, gm, t, i < 0 ? -1 - i : 2 * T - 1 - i,
                                           j < 0 ? -1 - j : 2 * T - 1 - j),
                           sizeof(float) * atlas->c);
                    continue;
                }
                tiled__to_side(s, T, pw_clampi(i, 0, T - 1), pw_clampi(j, 0, T - 1), &a, &b);
                pt = tiled__partner(case1, types[s]);
                tiled__from_side(rep_side[pt], T, T - 1 - a, depth - 1, &pi, &pj);
                memcpy(tiled__atlas_px(atlas, gm, t, i, j),
                       tiled__atlas_px(atlas, gm, rep_tile[pt], pi, pj), sizeof(float) * atlas->c);
            }
    }
}

TILEDDEF void tiled_image_free(tiled_image *img)
{
    pw_alloc a;
    if (!img) return;
    a = tiled__alloc(&img->allocator);
    pw_free(&a, img->pixels);
    memset(img, 0, sizeof *img);
}

TILEDDEF void tiled_tileset_free(tiled_tileset *ts)
{
    if (!ts) return;
    tiled_image_free(&ts->atlas);
    memset(ts, 0, sizeof *ts);
}

/* Allocates a tile set's atlas for a resolved layout. */
static int tiled__new_tileset(const pw_alloc *a, const tiled_layout *l, int channels,
                              tiled_tileset *ts, pw_err *e)
{
    tiled__geom gm = tiled__geometry(l);
    pw_image img;
    int r = pw_image_alloc(a, &img, gm.W, gm.W, channels, e);
    if (r != PW_OK) return r;
    ts->layout = *l;
    ts->tiles_per_side = gm.N;
    ts->max_mip_level = tiled__max_mip(&gm);
    tiled__take_image(&img, a, &ts->atlas);
    return PW_OK;
}

/* The resolved layout of a hand-made tiled texture (thesis layout: square,
 * no guard bands); its tile size comes from the image, the guard band to
 * add from `want`. */
static int tiled__layout_of_image(const tiled_layout *want, const tiled_image *img,
                                  tiled_layout *out, pw_err *e)
{
    tiled_layout l = *want;
    tiled__geom gm;
    int r;
    l.tile_size = 4;
    l.guard = TILED_NO_GUARD;
    if ((r = tiled__check_image(img, "tiled texture", e)) != PW_OK ||
        (r = tiled__resolve(&l, 0, &l, e)) != PW_OK)
        return r;
    gm = tiled__geometry(&l);
    if (img->width != img->height || img->width % gm.N || img->width / gm.N < 4)
        return pw_fail(e, PW_ERR_INVALID, "a tiled texture for this layout must be square with a "
                       "side divisible by %d, tiles of 4 px or more (got %dx%d)", gm.N,
                       img->width, img->height);
    l.tile_size = img->width / gm.N;
    l.guard = want->guard;
    return tiled__resolve(&l, 0, out, e);
}

/* Pixel (i, j) (j from the bottom) of tile t of a thesis-layout image. */
static const float *tiled__plain_px(const pw_image *img, const tiled__geom *gm, int t, int i, int j)
{
    int x = (t % gm->N) * gm->T + i, y = (t / gm->N) * gm->T + j;
    return img->px + ((size_t)(img->h - 1 - y) * img->w + x) * img->c;
}

TILEDDEF tiled_result tiled_tileset_from_image(const tiled_image *tiles, const tiled_options *opt,
                                               tiled_tileset *out, tiled_error *err)
{
    tiled_options o = tiled__options(opt);
    pw_alloc a = tiled__alloc(&o.allocator);
    tiled_layout l;
    pw_err pe;
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (!out) pw_fail(&pe, PW_ERR_INVALID, "tiled_tileset_from_image: NULL output");
    else if (tiled__layout_of_image(&o.layout, tiles, &l, &pe) == PW_OK &&
             tiled__new_tileset(&a, &l, tiles->channels, out, &pe) == PW_OK) {
        pw_image src = tiled__pw_image(tiles), dst = tiled__pw_image(&out->atlas);
        tiled__geom gm = tiled__geometry(&l);
        int t, j;
        for (t = 0; t < gm.N * gm.N; t++)
            for (j = 0; j < gm.T; j++)
                memcpy(tiled__atlas_px(&dst, &gm, t, 0, j), tiled__plain_px(&src, &gm, t, 0, j),
                       sizeof(float) * gm.T * src.c);
        tiled__fill_guards(&dst, &gm, l.case_number == 1);
    }
    return tiled__done(&pe, err);
}

/* ---- tile-set synthesis (ch. III.1.3) ------------------------------------ */

/* The thesis made its tiled textures with "a variant of image quilting"
 * (Green 2003, unpublished). We follow the Wang-tile construction of Cohen
 * et al. 2003, adapted to complementary, orientation-reversed edge types:
 *
 *  - The exemplar is first made periodic (graph cut with shifted copies of
 *    itself), so that windows can be taken anywhere.
 *  - Boundary pair k owns a "diamond": a window D_k of the periodic source
 *    straddling an edge. A side of type 2k shows the half of D_k on one side
 *    of the edge, a side of type 2k+1 the other half turned by 180 degrees;
 *    on a mesh the two halves meet again, so every edge continues the
 *    source texture (Fig. 24).
 *  - Each tile composites its four side diamonds and a random centre window
 *    with minimum-cost graph-cut seams (alpha-expansion, see quilt.h). The
 *    rows next to each side are constrained to that side's diamond, the
 *    centre square to the centre window, everything else is free, so seams
 *    fall where the sources agree and tiles with equal sides still differ.
 *  - Seams keep motifs whole (issue 18): the seam cost also charges every
 *    source pixel inside a motif (quilt.h's motif map: what strong
 *    outlines enclose, not the mortar around it), so seams run along
 *    mortar and outlines instead of through pebbles; the diamonds reach
 *    3/8 of the way in, which leaves a seam room to go round a motif; and
 *    each diamond is placed so that its ends, which meet at every tile
 *    corner along a fixed diagonal, show ground, not a motif.
 *  - Case 1 has one self-matching side: its diamond must look the same from
 *    both sides of the edge and, because tiles are mirrored, from both
 *    ends: it is made symmetric by reflection (C0, not C1, across edges). */
typedef struct tiled__synth {
    pw_image src;   /* periodic source */
    int T, wc;      /* tile size; rows next to a side constrained to it */
    int band;       /* rows from a side where its diamond may appear */
    int case1;
    int dx[9], dy[9]; /* diamond origins (pair k) in the source; [8]: scratch */
    float *motif;         /* the periodic source's motif map (pw_quilt_motif_map) */
    float motif_weight;   /* seam cost per source pixel inside a motif */
    pw_seam_stats *stats; /* NULL, or where to add every tile's seam statistics */
    float tau;            /* their colour threshold: the source's strong-edge gradient */
} tiled__synth;

/* Index of source pixel (x, y), wrapped: the source is periodic. */
static size_t tiled__src_index(const tiled__synth *s, int x, int y)
{
    x %= s->src.w;
    y %= s->src.h;
    if (x < 0) x += s->src.w;
    if (y < 0) y += s->src.h;
    return (size_t)y * s->src.w + x;
}

static const float *tiled__src_px(const tiled__synth *s, int x, int y)
{
    return s->src.px + tiled__src_index(s, x, y) * s->src.c;
}

/* Source pixel shown by a side of boundary type `type` at side-frame point (a, b). */
static size_t tiled__side_index(const tiled__synth *s, int type, int a, int b)
{
    int T = s->T, k = type >> 1;
    if (s->case1) { /* symmetric under a -> T-1-a and b -> -1-b */
        a = a < T - 1 - a ? a : T - 1 - a;
        b = b >= 0 ? b : -1 - b;
        k = 0;
    } else if (type & 1) { /* the partner's half, turned by 180 degrees */
        a = T - 1 - a;
        b = -1 - b;
    }
    return tiled__src_index(s, s->dx[k] + a, s->dy[k] - b); /* b up = source rows up */
}


/* Scratch of one tile composition: 5 label images, masks, labels. */
typedef struct tiled__scratch {
    float *src;        /* 5*T*T*c */
    float *motif;      /* 5*T*T: the sources' motif maps */
    uint32_t *allowed; /* T*T */
    int *label;        /* T*T */
} tiled__scratch;

/* Fills the four side labels' images and motif maps of a tile with
 * boundary types[4]. */
static void tiled__side_sources(const tiled__synth *s, const int types[4], float *src, float *motif)
{
    int T = s->T, c = s->src.c, l, i, j, a, b;
    for (l = 0; l < 4; l++)
        for (j = 0; j < T; j++)
            for (i = 0; i < T; i++) {
                size_t k, p = (size_t)(l * T + j) * T + i;
                tiled__to_side(l, T, i, j, &a, &b);
                k = tiled__side_index(s, types[l], a, b);
                memcpy(src + p * c, s->src.px + k * c, sizeof(float) * c);
                motif[p] = s->motif[k];
            }
}

/* Distances of pixel (i, j) to the four sides. */
static void tiled__side_dists(int T, int i, int j, int d[4])
{
    d[0] = j;
    d[1] = T - 1 - i;
    d[2] = T - 1 - j;
    d[3] = i;
}

/* Hard constraints and the initial labelling. Rows closer than wc to a side
 * belong to that side (so the edge continues into the neighbour); a side
 * may also be used up to `band` rows in, and the centre window (label 4)
 * anywhere but those first rows. Keeping the diamonds to a band stops
 * tiles that share side types from looking alike. */
static void tiled__constraints(const tiled__synth *s, tiled__scratch *sc)
{
    int T = s->T, i, j, k, d[4];
    for (j = 0; j < T; j++)
        for (i = 0; i < T; i++) {
            int p = j * T + i, best = 0;
            uint32_t near = 0;
            tiled__side_dists(T, i, j, d);
            for (k = 0; k < 4; k++) {
                if (d[k] < d[best]) best = k;
                if (d[k] < s->band) near |= 1u << k;
            }
            sc->label[p] = d[best] < s->band ? best : 4;
            sc->allowed[p] = d[best] < s->wc ? 1u << best : near | 1u << 4;
        }
}

/* Picks the centre window that best agrees with the side diamonds where
 * both may appear (best of a few random origins), and fills label 4. */
static void tiled__centre_source(const tiled__synth *s, pw_rng *rng, tiled__scratch *sc)
{
    int T = s->T, c = s->src.c, cand, i, j, k, bx = 0, by = 0;
    double best = -1.0;
    for (cand = 0; cand < 16; cand++) {
        int ox = (int)pw_rng_below(rng, (uint32_t)s->src.w), oy = (int)pw_rng_below(rng, (uint32_t)s->src.h);
        double cost = 0.0;
        for (j = 0; j < T; j++)
            for (i = 0; i < T; i++) {
                int p = j * T + i;
                const float *a, *b;
                if (sc->label[p] == 4 || sc->allowed[p] == (1u << sc->label[p])) continue;
                a = tiled__src_px(s, ox + i, oy - j);
                b = sc->src + ((size_t)sc->label[p] * T * T + p) * c;
                for (k = 0; k < c; k++) cost += (a[k] - b[k]) * (a[k] - b[k]);
            }
        if (best < 0.0 || cost < best) {
            best = cost;
            bx = ox;
            by = oy;
        }
    }
    for (j = 0; j < T; j++)
        for (i = 0; i < T; i++) {
            size_t p = (size_t)(4 * T + j) * T + i, k = tiled__src_index(s, bx + i, by - j);
            memcpy(sc->src + p * c, s->src.px + k * c, sizeof(float) * c);
            sc->motif[p] = s->motif[k];
        }
}

/* Composes tile t into the atlas. */
static int tiled__compose(const pw_alloc *a, const tiled__synth *s, pw_rng *rng, tiled__scratch *sc,
                          pw_image *atlas, const tiled__geom *gm, int t, pw_err *e)
{
    int types[4], T = s->T, c = s->src.c, j, r;
    pw_quilt q;
    tiled__tile_types(gm, s->case1, t, types);
    tiled__side_sources(s, types, sc->src, sc->motif);
    tiled__constraints(s, sc);
    tiled__centre_source(s, rng, sc);
    q.w = q.h = T;
    q.c = c;
    q.nlabels = 5;
    q.src = sc->src;
    q.label = sc->label;
    q.allowed = sc->allowed;
    q.wrap_x = q.wrap_y = 0;
    q.motif = sc->motif;
    q.motif_weight = s->motif_weight;
    if ((r = pw_quilt_optimize(a, &q, 2, e)) != PW_OK) return r;
    if (s->stats) pw_quilt_seam_stats(&q, s->tau, s->stats);
    for (j = 0; j < T; j++) { /* compose row by row into the atlas */
        int i;
        for (i = 0; i < T; i++)
            memcpy(tiled__atlas_px(atlas, gm, t, i, j),
                   sc->src + ((size_t)(sc->label[j * T + i] * T + j) * T + i) * c,
                   sizeof(float) * c);
    }
    return PW_OK;
}

/* Cost of the corner between the bottom side (type t0) and the right side
 * (type t1) of a tile: there the two sides' diamonds meet along the
 * diagonal of the wc x wc square, a seam that no graph cut can move. In
 * each row v < wc it sums, over the horizontal pixel pairs (T-2-u, v),
 * (T-1-u, v) with u = v-1 and u = v (those next to the diagonal), the
 * colour jumps between the two diamonds and, for every source pixel inside
 * a motif, the motif weight (as pw_quilt_pair_cost does). */
static double tiled__corner_cost(const tiled__synth *s, int t0, int t1)
{
    int T = s->T, u, v, w, k, c = s->src.c, a0, b0, a1, b1;
    double cost = 0.0;
    for (v = 0; v < s->wc; v++)
        for (u = v > 0 ? v - 1 : 0; u <= v && u + 1 < s->wc; u++)
            for (w = 0; w < 2; w++) {
                size_t p0, p1;
                tiled__to_side(0, T, T - 1 - u - w, v, &a0, &b0);
                tiled__to_side(1, T, T - 1 - u - w, v, &a1, &b1);
                p0 = tiled__side_index(s, t0, a0, b0);
                p1 = tiled__side_index(s, t1, a1, b1);
                for (k = 0; k < c; k++) cost += fabs(s->src.px[p0 * c + k] - s->src.px[p1 * c + k]);
                cost += s->motif_weight * (s->motif[p0] + s->motif[p1]);
            }
    return cost;
}

/* Sum of the corner costs of every pair of types that involves pair k,
 * with the pairs already placed (0..k). Case 1 has one type, k = 0. */
static double tiled__corners_of(const tiled__synth *s, int k, int ntypes)
{
    int t0, t1;
    double cost = 0.0;
    for (t0 = 0; t0 < ntypes; t0++)
        for (t1 = 0; t1 < ntypes; t1++)
            if ((t0 >> 1) <= k && (t1 >> 1) <= k && ((t0 >> 1) == k || (t1 >> 1) == k))
                cost += tiled__corner_cost(s, t0, t1);
    return cost;
}

/* Places diamond k: the best of 32 random origins. A candidate pays how
 * much the source changes across the edge line (the two sides of every
 * edge of pair k show the rows just above and below it, so it should not
 * run along a cut seam of the periodic source) and the cost of the tile
 * corners its ends make with the diamonds placed before it: where a
 * diamond's ends show mortar, the corners of tiles cut no pebble. */
static void tiled__place_diamond(tiled__synth *s, pw_rng *rng, int k, int ntypes)
{
    double best = -1.0;
    int cand, a, c;
    for (cand = 0; cand < 32; cand++) {
        int ox = (int)pw_rng_below(rng, (uint32_t)s->src.w), oy = (int)pw_rng_below(rng, (uint32_t)s->src.h);
        double cost = 0.0;
        for (a = 0; a < s->T; a++) {
            const float *p = tiled__src_px(s, ox + a, oy), *q = tiled__src_px(s, ox + a, oy + 1);
            for (c = 0; c < s->src.c; c++) cost += fabs(p[c] - q[c]);
        }
        s->dx[k] = ox;
        s->dy[k] = oy;
        cost += tiled__corners_of(s, k, ntypes);
        if (best < 0.0 || cost < best) {
            best = cost;
            s->dx[8] = ox, s->dy[8] = oy;
        }
    }
    s->dx[k] = s->dx[8];
    s->dy[k] = s->dy[8];
}

/* Builds every tile of a resolved layout from the periodic source. */
static int tiled__synth_tiles(const pw_alloc *a, tiled__synth *s, const tiled_options *o,
                              pw_image *atlas, const tiled__geom *gm, pw_err *e)
{
    pw_progress pr = tiled__progress(o);
    pw_rng rng = pw_rng_seed(o->seed, 3);
    tiled__scratch sc;
    size_t tt = (size_t)s->T * s->T;
    int k, t, r = PW_OK;
    for (k = 0; k < 8; k++) tiled__place_diamond(s, &rng, k, gm->n);
    sc.src = (float *)pw_alloc_array(a, tt * 5 * s->src.c, sizeof(float), "tile sources", e);
    sc.allowed = (uint32_t *)pw_alloc_array(a, tt, sizeof(uint32_t), "tile constraints", e);
    sc.label = (int *)pw_alloc_array(a, tt, sizeof(int), "tile labels", e);
    sc.motif = (float *)pw_alloc_array(a, tt * 5, sizeof(float), "tile motif maps", e);
    if (!sc.src || !sc.allowed || !sc.label || !sc.motif) r = PW_ERR_NOMEM;
    for (t = 0; t < gm->N * gm->N && r == PW_OK; t++) {
        r = pw_report(&pr, 0.1f + 0.9f * (float)t / (float)(gm->N * gm->N), "tile synthesis", e);
        if (r == PW_OK) r = tiled__compose(a, s, &rng, &sc, atlas, gm, t, e);
    }
    pw_free(a, sc.src);
    pw_free(a, sc.allowed);
    pw_free(a, sc.label);
    pw_free(a, sc.motif);
    return r;
}

/* Seam cost per source pixel inside a motif (pw_quilt.motif_weight), in
 * the units of colour distance (0..sqrt(3) per pixel and source pair): a
 * seam through a pebble pays more than one through mortar of any shade. */
#define TILED__MOTIF_WEIGHT 3.0f

/* tiled_synthesize, also adding the seam statistics of every tile (see
 * pw_quilt_seam_stats) to *stats when it is not NULL. */
static int tiled__synthesize(const tiled_image *exemplar, const tiled_options *o,
                             tiled_tileset *out, pw_seam_stats *stats, pw_err *pe)
{
    pw_alloc a = tiled__alloc(&o->allocator);
    pw_progress pr = tiled__progress(o);
    tiled_layout l;
    tiled__synth s;
    pw_image ex;
    int r;
    memset(&s, 0, sizeof s);
    if ((r = tiled__check_image(exemplar, "exemplar", pe)) != PW_OK) return r;
    ex = tiled__pw_image(exemplar);
    if (ex.w < 8 || ex.h < 8)
        return pw_fail(pe, PW_ERR_INVALID, "exemplar must be at least 8x8 pixels (got %dx%d)", ex.w, ex.h);
    if ((r = tiled__resolve(&o->layout, pw_mini(ex.w, ex.h), &l, pe)) == PW_OK &&
        (r = pw_report(&pr, 0.0f, "periodic source", pe)) == PW_OK &&
        (r = pw_quilt_make_tileable(&a, &ex, &s.src, pe)) == PW_OK &&
        (r = tiled__new_tileset(&a, &l, ex.c, out, pe)) == PW_OK) {
        tiled__geom gm = tiled__geometry(&l);
        pw_image atlas = tiled__pw_image(&out->atlas);
        s.T = l.tile_size;
        s.wc = pw_mini(pw_maxi(2, gm.g / 2), pw_maxi(1, s.T / 4));
        s.band = pw_maxi(s.wc + 1, s.T * 3 / (l.case_number == 1 ? 10 : 8));
        s.case1 = l.case_number == 1;
        s.stats = stats;
        s.motif_weight = TILED__MOTIF_WEIGHT;
        s.motif = (float *)pw_alloc_array(&a, (size_t)s.src.w * s.src.h, sizeof(float), "motif map", pe);
        r = s.motif ? pw_quilt_motif_map(&a, s.src.px, s.src.w, s.src.h, s.src.c, s.motif, &s.tau, pe)
                    : PW_ERR_NOMEM;
        if (r == PW_OK && (r = tiled__synth_tiles(&a, &s, o, &atlas, &gm, pe)) == PW_OK)
            tiled__fill_guards(&atlas, &gm, s.case1);
        else
            tiled_tileset_free(out);
    }
    pw_image_free(&a, &s.src);
    pw_free(&a, s.motif);
    return r;
}

TILEDDEF tiled_result tiled_synthesize(const tiled_image *exemplar, const tiled_options *opt,
                                       tiled_tileset *out, tiled_error *err)
{
    tiled_options o = tiled__options(opt);
    pw_err pe;
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (!out) pw_fail(&pe, PW_ERR_INVALID, "tiled_synthesize: NULL output");
    else tiled__synthesize(exemplar, &o, out, NULL, &pe);
    return tiled__done(&pe, err);
}

/* ---- validation of hand-made tile sets ------------------------------------ */

static float tiled__dist(const float *p, const float *q, int c)
{
    float s = 0.0f;
    int k;
    for (k = 0; k < c; k++) s += (p[k] - q[k]) * (p[k] - q[k]);
    return sqrtf(s);
}

/* Mean colour jump between horizontally and vertically neighbouring
 * pixels inside tiles: what a seam should not exceed. */
static float tiled__interior_jump(const pw_image *img, const tiled__geom *gm)
{
    double sum = 0.0;
    long count = 0;
    int t, i, j;
    for (t = 0; t < gm->N * gm->N; t++)
        for (j = 0; j + 1 < gm->T; j++)
            for (i = 0; i + 1 < gm->T; i++) {
                const float *p = tiled__plain_px(img, gm, t, i, j);
                sum += tiled__dist(p, tiled__plain_px(img, gm, t, i + 1, j), img->c);
                sum += tiled__dist(p, tiled__plain_px(img, gm, t, i, j + 1), img->c);
                count += 2;
            }
    return count ? (float)(sum / (double)count) : 0.0f;
}

/* Mean jump across side s of tile t when it meets side ps of tile pt
 * (reversed walk; `mirrored` compares the partner walked the same way, as
 * happens when case-1 tiles are mirrored). */
static float tiled__seam(const pw_image *img, const tiled__geom *gm, int t, int s, int pt, int ps,
                         int mirrored)
{
    double sum = 0.0;
    int a, T = gm->T;
    for (a = 0; a < T; a++) {
        int i, j, pi, pj;
        tiled__from_side(s, T, a, 0, &i, &j);
        tiled__from_side(ps, T, mirrored ? a : T - 1 - a, 0, &pi, &pj);
        sum += tiled__dist(tiled__plain_px(img, gm, t, i, j), tiled__plain_px(img, gm, pt, pi, pj),
                           img->c);
    }
    return (float)(sum / T);
}

/* Mean seam of side (t, s) against up to 64 sides of the partner type. */
static float tiled__side_seam(const pw_image *img, const tiled__geom *gm, int case1, int mirror,
                              int t, int s, int type)
{
    int u, us, types[4], n = 0;
    double sum = 0.0;
    for (u = 0; u < gm->N * gm->N && n < 64; u++) {
        tiled__tile_types(gm, case1, u, types);
        for (us = 0; us < 4 && n < 64; us++) {
            if (types[us] != tiled__partner(case1, type)) continue;
            sum += tiled__seam(img, gm, t, s, u, us, 0);
            n++;
            if (mirror) {
                sum += tiled__seam(img, gm, t, s, u, us, 1);
                n++;
            }
        }
    }
    return n ? (float)(sum / n) : 0.0f;
}

/* Records a failing side, keeping the list sorted worst first. */
static void tiled__note_bad(tiled_validation *rep, int t, int s, int type, float seam)
{
    int k, n = rep->nbad < TILED_MAX_MISMATCHES ? rep->nbad : TILED_MAX_MISMATCHES;
    rep->nbad++;
    if (n == TILED_MAX_MISMATCHES && seam <= rep->bad[n - 1].seam) return;
    if (n == TILED_MAX_MISMATCHES) n--;
    for (k = n; k > 0 && rep->bad[k - 1].seam < seam; k--) rep->bad[k] = rep->bad[k - 1];
    rep->bad[k].tile = t;
    rep->bad[k].side = s;
    rep->bad[k].type = type;
    rep->bad[k].seam = seam;
}

/* A side passes when its seam is at most twice the typical jump between
 * neighbouring pixels inside tiles (plus one 8-bit step): matching sides
 * continue the pattern, so their seams look like interior neighbours. */
TILEDDEF tiled_result tiled_validate_tiles(const tiled_image *tiles, const tiled_options *opt,
                                           tiled_validation *report, tiled_error *err)
{
    tiled_options o = tiled__options(opt);
    tiled_layout l;
    pw_err pe;
    pw_err_clear(&pe);
    if (report) memset(report, 0, sizeof *report);
    if (!report) pw_fail(&pe, PW_ERR_INVALID, "tiled_validate_tiles: NULL report");
    else if (tiled__layout_of_image(&o.layout, tiles, &l, &pe) == PW_OK) {
        pw_image img = tiled__pw_image(tiles);
        tiled__geom gm = tiled__geometry(&l);
        int case1 = l.case_number == 1, t, s, types[4];
        gm.g = 0;
        gm.C = gm.T;
        report->interior = tiled__interior_jump(&img, &gm);
        report->threshold = 2.0f * report->interior + 1.0f / 255.0f;
        for (t = 0; t < gm.N * gm.N; t++) {
            tiled__tile_types(&gm, case1, t, types);
            for (s = 0; s < 4; s++) {
                float seam = tiled__side_seam(&img, &gm, case1, case1 && !o.no_mirror, t, s, types[s]);
                report->sides_checked++;
                if (seam > report->worst) report->worst = seam;
                if (seam > report->threshold) tiled__note_bad(report, t, s, types[s], seam);
            }
        }
    }
    return tiled__done(&pe, err);
}

/* ---- built-in meshes and exemplars (for demos and tests) ------------------ */

/* Allocates a mesh of nv vertices and nf faces of `deg` corners. */
static int tiled__new_mesh(const pw_alloc *a, int nv, int nf, int deg, tiled_mesh *m, pw_err *e)
{
    int f;
    memset(m, 0, sizeof *m);
    m->allocator = tiled__allocator(a);
    m->positions = (float *)pw_alloc_array(a, (size_t)nv * 3, sizeof(float), "positions", e);
    m->face_start = (int *)pw_alloc_array(a, (size_t)nf + 1, sizeof(int), "faces", e);
    m->face_verts = (int *)pw_alloc_array(a, (size_t)nf * deg, sizeof(int), "face corners", e);
    if (!m->positions || !m->face_start || !m->face_verts) {
        tiled_mesh_free(m);
        return PW_ERR_NOMEM;
    }
    m->nverts = nv;
    m->nfaces = nf;
    for (f = 0; f <= nf; f++) m->face_start[f] = f * deg;
    return PW_OK;
}

/* The surface of a union of unit voxels: one outward quad per voxel face
 * that touches empty space. A first pass counts (m == NULL), a second
 * writes; vertices are numbered in order of first use. */
typedef struct tiled__voxels {
    int X, Y, Z;
    const unsigned char *vox;
    int *map; /* lattice point -> vertex, -1 if unused */
    tiled_mesh *m;
    int nv, nf;
} tiled__voxels;

static int tiled__solid(const tiled__voxels *v, const int p[3])
{
    return p[0] >= 0 && p[1] >= 0 && p[2] >= 0 && p[0] < v->X && p[1] < v->Y && p[2] < v->Z &&
           v->vox[(p[2] * v->Y + p[1]) * v->X + p[0]];
}

/* Emits the face of voxel p facing direction d (axis d/2, sign by d&1),
 * counter-clockwise seen from outside. */
static void tiled__voxel_face(tiled__voxels *v, const int p[3], int d)
{
    static const int du[4] = {0, 1, 1, 0}, dv[4] = {0, 0, 1, 1};
    int ax = d >> 1, neg = d & 1, u = (ax + 1) % 3, w = (ax + 2) % 3, k, c[3], li;
    for (k = 0; k < 4; k++) {
        int kk = neg ? (4 - k) & 3 : k; /* reversed walk on the negative side */
        memcpy(c, p, sizeof c);
        c[ax] += !neg;
        c[u] += du[kk];
        c[w] += dv[kk];
        li = (c[2] * (v->Y + 1) + c[1]) * (v->X + 1) + c[0];
        if (v->map[li] < 0) {
            if (v->m) {
                v->m->positions[3 * v->nv] = (float)c[0];
                v->m->positions[3 * v->nv + 1] = (float)c[1];
                v->m->positions[3 * v->nv + 2] = (float)c[2];
            }
            v->map[li] = v->nv++;
        }
        if (v->m) v->m->face_verts[4 * v->nf + k] = v->map[li];
    }
    v->nf++;
}

static void tiled__voxel_pass(tiled__voxels *v)
{
    int p[3], q[3], d, k, nl = (v->X + 1) * (v->Y + 1) * (v->Z + 1);
    for (k = 0; k < nl; k++) v->map[k] = -1;
    v->nv = v->nf = 0;
    for (p[2] = 0; p[2] < v->Z; p[2]++)
        for (p[1] = 0; p[1] < v->Y; p[1]++)
            for (p[0] = 0; p[0] < v->X; p[0]++) {
                if (!tiled__solid(v, p)) continue;
                for (d = 0; d < 6; d++) {
                    memcpy(q, p, sizeof q);
                    q[d >> 1] += d & 1 ? -1 : 1;
                    if (!tiled__solid(v, q)) tiled__voxel_face(v, p, d);
                }
            }
}

static int tiled__polycube(const pw_alloc *a, int X, int Y, int Z, const unsigned char *vox,
                           tiled_mesh *m, pw_err *e)
{
    tiled__voxels v;
    int r;
    v.X = X;
    v.Y = Y;
    v.Z = Z;
    v.vox = vox;
    v.m = NULL;
    v.map = (int *)pw_alloc_array(a, (size_t)(X + 1) * (Y + 1) * (Z + 1), sizeof(int), "lattice", e);
    if (!v.map) return PW_ERR_NOMEM;
    tiled__voxel_pass(&v);
    if ((r = tiled__new_mesh(a, v.nv, v.nf, 4, m, e)) == PW_OK) {
        v.m = m;
        tiled__voxel_pass(&v);
    }
    pw_free(a, v.map);
    return r;
}

/* Torus: R = 1, r = 0.4, nu x nv quads (u around the axis, v around the tube). */
static int tiled__torus(const pw_alloc *a, int nu, int nv, tiled_mesh *m, pw_err *e)
{
    const double pi2 = 6.28318530717958647692;
    int i, j, r = tiled__new_mesh(a, nu * nv, nu * nv, 4, m, e);
    if (r != PW_OK) return r;
    for (i = 0; i < nu; i++)
        for (j = 0; j < nv; j++) {
            double u = pi2 * i / nu, v = pi2 * j / nv, rr = 1.0 + 0.4 * pw_cos(v);
            float *p = m->positions + 3 * (i * nv + j);
            int *f = m->face_verts + 4 * (i * nv + j);
            p[0] = (float)(rr * pw_cos(u));
            p[1] = (float)(rr * pw_sin(u));
            p[2] = (float)(0.4 * pw_sin(v));
            f[0] = i * nv + j;
            f[1] = ((i + 1) % nu) * nv + j;
            f[2] = ((i + 1) % nu) * nv + (j + 1) % nv;
            f[3] = i * nv + (j + 1) % nv;
        }
    return PW_OK;
}

/* Icosahedron: 20 triangles (Catmull-Clark turns them into quads). */
static int tiled__icosahedron(const pw_alloc *a, tiled_mesh *m, pw_err *e)
{
    static const signed char vs[12][3] = {{-1, 2, 0}, {1, 2, 0}, {-1, -2, 0}, {1, -2, 0},
                                          {0, -1, 2}, {0, 1, 2}, {0, -1, -2}, {0, 1, -2},
                                          {2, 0, -1}, {2, 0, 1}, {-2, 0, -1}, {-2, 0, 1}};
    static const unsigned char fs[20][3] = {
        {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
        {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    const float phi = 1.61803398874989485f;
    int k, r = tiled__new_mesh(a, 12, 20, 3, m, e);
    if (r != PW_OK) return r;
    for (k = 0; k < 36; k++) { /* the table's 2 stands for the golden ratio */
        int c = vs[k / 3][k % 3];
        m->positions[k] = c == 2 ? phi : (c == -2 ? -phi : (float)c);
    }
    for (k = 0; k < 60; k++) m->face_verts[k] = fs[k / 3][k % 3];
    return PW_OK;
}

/* An open, gently waved n x n quad grid on [-1,1]^2: a mesh with a boundary. */
static int tiled__grid(const pw_alloc *a, int n, tiled_mesh *m, pw_err *e)
{
    const double pi = 3.14159265358979323846;
    int i, j, r = tiled__new_mesh(a, (n + 1) * (n + 1), n * n, 4, m, e);
    if (r != PW_OK) return r;
    for (j = 0; j <= n; j++)
        for (i = 0; i <= n; i++) {
            double x = -1.0 + 2.0 * i / n, y = -1.0 + 2.0 * j / n;
            float *p = m->positions + 3 * (j * (n + 1) + i);
            p[0] = (float)x;
            p[1] = (float)y;
            p[2] = (float)(0.2 * pw_sin(pi * x) * pw_sin(pi * y));
        }
    for (j = 0; j < n; j++)
        for (i = 0; i < n; i++) {
            int *f = m->face_verts + 4 * (j * n + i), v = j * (n + 1) + i;
            f[0] = v;
            f[1] = v + 1;
            f[2] = v + n + 2;
            f[3] = v + n + 1;
        }
    return PW_OK;
}

/* Moves a mesh's bounding-box centre to the origin and scales it to fit
 * [-1,1]^3 (voxel meshes come in lattice units). */
static void tiled__normalise(tiled_mesh *m)
{
    float lo[3], hi[3], s;
    int k, v;
    for (k = 0; k < 3; k++) lo[k] = hi[k] = m->positions[k];
    for (v = 0; v < m->nverts; v++)
        for (k = 0; k < 3; k++) {
            float x = m->positions[3 * v + k];
            lo[k] = x < lo[k] ? x : lo[k];
            hi[k] = x > hi[k] ? x : hi[k];
        }
    s = 0.0f;
    for (k = 0; k < 3; k++) s = hi[k] - lo[k] > s ? hi[k] - lo[k] : s;
    for (v = 0; v < m->nverts; v++)
        for (k = 0; k < 3; k++)
            m->positions[3 * v + k] = (m->positions[3 * v + k] - 0.5f * (lo[k] + hi[k])) * 2.0f / s;
}

TILEDDEF tiled_result tiled_builtin_mesh(const char *name, const tiled_options *opt,
                                         tiled_mesh *out, tiled_error *err)
{
    /* genus 2: a 5x3x2 slab of voxels with two holes through it */
    static const unsigned char slab[30] = {1, 1, 1, 1, 1, 1, 0, 1, 0, 1, 1, 1, 1, 1, 1,
                                           1, 1, 1, 1, 1, 1, 0, 1, 0, 1, 1, 1, 1, 1, 1};
    static const unsigned char one = 1;
    tiled_options o = tiled__options(opt);
    pw_alloc a = tiled__alloc(&o.allocator);
    pw_err pe;
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (!out || !name) pw_fail(&pe, PW_ERR_INVALID, "tiled_builtin_mesh: NULL argument");
    else if (!strcmp(name, "cube")) tiled__polycube(&a, 1, 1, 1, &one, out, &pe);
    else if (!strcmp(name, "double-torus")) tiled__polycube(&a, 5, 3, 2, slab, out, &pe);
    else if (!strcmp(name, "torus")) tiled__torus(&a, 24, 12, out, &pe);
    else if (!strcmp(name, "icosahedron")) tiled__icosahedron(&a, out, &pe);
    else if (!strcmp(name, "grid")) tiled__grid(&a, 12, out, &pe);
    else
        pw_fail(&pe, PW_ERR_INVALID, "unknown built-in mesh '%s' (cube, torus, double-torus, "
                "icosahedron, grid)", name);
    if (pe.code == PW_OK) tiled__normalise(out);
    return tiled__done(&pe, err);
}

/* Procedural exemplars: periodic on the unit torus, built from + - * / and
 * sqrt only, so they are identical on every platform. */
typedef struct tiled__cells {
    int m;           /* m x m jittered cells */
    float px[256], py[256]; /* one feature point per cell, in [0,1) */
    float col[256][3];
} tiled__cells;

static void tiled__cells_init(tiled__cells *c, int m, pw_rng *r)
{
    int k;
    c->m = m;
    for (k = 0; k < m * m; k++) {
        c->px[k] = ((float)(k % m) + 0.15f + 0.7f * pw_rng_float(r)) / (float)m;
        c->py[k] = ((float)(k / m) + 0.15f + 0.7f * pw_rng_float(r)) / (float)m;
        c->col[k][0] = pw_rng_float(r);
        c->col[k][1] = pw_rng_float(r);
        c->col[k][2] = pw_rng_float(r);
    }
}

/* Distances to the nearest and second nearest feature points (periodic),
 * and the nearest point's index. */
static void tiled__cells_eval(const tiled__cells *c, float x, float y, float *f1, float *f2, int *id)
{
    int cx = (int)(x * (float)c->m), cy = (int)(y * (float)c->m), dx, dy;
    *f1 = *f2 = 4.0f;
    *id = 0;
    for (dy = -2; dy <= 2; dy++)
        for (dx = -2; dx <= 2; dx++) {
            int gx = cx + dx, gy = cy + dy, k;
            float ox = 0.0f, oy = 0.0f, ddx, ddy, d;
            if (gx < 0) { gx += c->m; ox = -1.0f; }
            if (gx >= c->m) { gx -= c->m; ox = 1.0f; }
            if (gy < 0) { gy += c->m; oy = -1.0f; }
            if (gy >= c->m) { gy -= c->m; oy = 1.0f; }
            k = gy * c->m + gx;
            ddx = c->px[k] + ox - x;
            ddy = c->py[k] + oy - y;
            d = sqrtf(ddx * ddx + ddy * ddy);
            if (d < *f1) { *f2 = *f1; *f1 = d; *id = k; }
            else if (d < *f2) *f2 = d;
        }
}

/* Periodic value noise with a smooth (quintic) fade, `lattice` cells per
 * side, values in [0,1]. */
static float tiled__noise(uint64_t seed, int lattice, float x, float y)
{
    float fx = x * (float)lattice, fy = y * (float)lattice, tx, ty, v[4];
    int ix = (int)fx, iy = (int)fy, k;
    tx = fx - (float)ix;
    ty = fy - (float)iy;
    for (k = 0; k < 4; k++) {
        int gx = (ix + (k & 1)) % lattice, gy = (iy + (k >> 1)) % lattice;
        v[k] = (float)(pw_hash64(seed, (uint64_t)(gy * lattice + gx)) >> 40) / 16777216.0f;
    }
    tx = tx * tx * tx * (tx * (tx * 6.0f - 15.0f) + 10.0f);
    ty = ty * ty * ty * (ty * (ty * 6.0f - 15.0f) + 10.0f);
    return (v[0] + (v[1] - v[0]) * tx) + ((v[2] + (v[3] - v[2]) * tx) - (v[0] + (v[1] - v[0]) * tx)) * ty;
}

static float tiled__fbm(uint64_t seed, float x, float y)
{
    return 0.5f * tiled__noise(seed, 4, x, y) + 0.25f * tiled__noise(seed + 1, 8, x, y) +
           0.15f * tiled__noise(seed + 2, 16, x, y) + 0.1f * tiled__noise(seed + 3, 32, x, y);
}

static void tiled__mix(float *out, const float *a, const float *b, float t)
{
    int k;
    t = pw_clampf(t, 0.0f, 1.0f);
    for (k = 0; k < 3; k++) out[k] = a[k] + (b[k] - a[k]) * t;
}

/* Pebbles: rounded stones of varied greys and browns in dark mortar. */
static void tiled__pebbles(const tiled__cells *c, uint64_t seed, float x, float y, float *rgb)
{
    static const float mortar[3] = {0.16f, 0.13f, 0.11f};
    float f1, f2, stone[3], edge, grain;
    int id, k;
    tiled__cells_eval(c, x, y, &f1, &f2, &id);
    grain = tiled__fbm(seed, x, y);
    for (k = 0; k < 3; k++) /* warm greys: shared brightness, a little hue */
        stone[k] = 0.35f + 0.35f * c->col[id][0] + 0.12f * (c->col[id][k] - 0.5f) + 0.25f * (grain - 0.5f);
    edge = (f2 - f1) * (float)c->m * 3.0f; /* 0 on the cell border */
    tiled__mix(rgb, mortar, stone, edge * edge);
}

/* Spots: broken dark rosettes with brown centres on a tawny, mottled
 * ground (leopard-like). */
static void tiled__spots(const tiled__cells *c, uint64_t seed, float x, float y, float *rgb)
{
    static const float ground[3] = {0.86f, 0.67f, 0.37f}, ring[3] = {0.1f, 0.07f, 0.05f},
                       centre[3] = {0.6f, 0.4f, 0.19f};
    float f1, f2, r, base[3], n = tiled__fbm(seed, x, y), broken, k;
    int id;
    tiled__cells_eval(c, x, y, &f1, &f2, &id);
    r = (0.25f + 0.12f * c->col[id][0]) / (float)c->m; /* rosette radius */
    k = 40.0f * (float)c->m;                             /* edge sharpness */
    broken = tiled__noise(seed + 11, 16, x, y) > 0.3f ? 1.0f : 0.0f;
    tiled__mix(base, ground, centre, (0.5f * r - f1) * k);
    tiled__mix(rgb, base, ring, broken * pw_clampf((f1 - 0.5f * r) * k, 0.0f, 1.0f) *
                                    pw_clampf((r - f1) * k, 0.0f, 1.0f));
    rgb[0] *= 0.85f + 0.3f * n;
    rgb[1] *= 0.85f + 0.3f * n;
    rgb[2] *= 0.85f + 0.3f * n;
}

/* Lichen: yellow-green crusts on grey stone, from thresholded fBm. */
static void tiled__lichen(uint64_t seed, float x, float y, float *rgb)
{
    static const float stone[3] = {0.5f, 0.5f, 0.48f}, moss[3] = {0.55f, 0.62f, 0.2f},
                       dark[3] = {0.2f, 0.22f, 0.12f};
    float n = tiled__fbm(seed, x, y), d = tiled__fbm(seed + 7, x, y), base[3];
    tiled__mix(base, stone, moss, (n - 0.5f) * 12.0f);
    tiled__mix(rgb, base, dark, (d - 0.62f) * 8.0f);
}

TILEDDEF tiled_result tiled_builtin_exemplar(const char *name, int size, const tiled_options *opt,
                                             tiled_image *out, tiled_error *err)
{
    tiled_options o = tiled__options(opt);
    pw_alloc a = tiled__alloc(&o.allocator);
    pw_rng r = pw_rng_seed(o.seed, 4);
    tiled__cells cells;
    pw_image img;
    pw_err pe;
    int x, y, kind = -1;
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (name) kind = !strcmp(name, "pebbles") ? 0 : !strcmp(name, "spots") ? 1 : !strcmp(name, "lichen") ? 2 : -1;
    if (!out || kind < 0)
        pw_fail(&pe, PW_ERR_INVALID, "unknown built-in exemplar '%s' (pebbles, spots, lichen)",
                name ? name : "(null)");
    else if (size < 8 || size > 4096)
        pw_fail(&pe, PW_ERR_INVALID, "exemplar size must be 8..4096 (got %d)", size);
    else if (pw_image_alloc(&a, &img, size, size, 3, &pe) == PW_OK) {
        tiled__cells_init(&cells, kind == 0 ? 4 : 3, &r);
        for (y = 0; y < size; y++)
            for (x = 0; x < size; x++) {
                float u = ((float)x + 0.5f) / (float)size, v = ((float)y + 0.5f) / (float)size;
                float *p = img.px + ((size_t)y * size + x) * 3;
                if (kind == 0) tiled__pebbles(&cells, o.seed, u, v, p);
                else if (kind == 1) tiled__spots(&cells, o.seed, u, v, p);
                else tiled__lichen(o.seed, u, v, p);
                p[0] = pw_clampf(p[0], 0.0f, 1.0f);
                p[1] = pw_clampf(p[1], 0.0f, 1.0f);
                p[2] = pw_clampf(p[2], 0.0f, 1.0f);
            }
        tiled__take_image(&img, &a, out);
    }
    return tiled__done(&pe, err);
}

/* ---- rendering ------------------------------------------------------------------ */

/* Fan-triangulates a mapped mesh into triangles with per-corner texture
 * coordinates. */
static int tiled__triangles(const pw_alloc *a, const tiled_mesh *m, int **tris, float **uvs,
                            int *ntris, pw_err *e)
{
    int f, k, t = 0, n = m->face_start[m->nfaces] - 2 * m->nfaces;
    *tris = (int *)pw_alloc_array(a, (size_t)n * 3, sizeof(int), "triangles", e);
    *uvs = (float *)pw_alloc_array(a, (size_t)n * 6, sizeof(float), "triangle coordinates", e);
    if (!*tris || !*uvs) {
        pw_free(a, *tris);
        pw_free(a, *uvs);
        return PW_ERR_NOMEM;
    }
    for (f = 0; f < m->nfaces; f++)
        for (k = m->face_start[f] + 1; k + 1 < m->face_start[f + 1]; k++, t++) {
            int c[3], j;
            c[0] = m->face_start[f];
            c[1] = k;
            c[2] = k + 1;
            for (j = 0; j < 3; j++) {
                (*tris)[3 * t + j] = m->face_verts[c[j]];
                (*uvs)[6 * t + 2 * j] = m->uvs[2 * c[j]];
                (*uvs)[6 * t + 2 * j + 1] = m->uvs[2 * c[j] + 1];
            }
        }
    *ntris = n;
    return PW_OK;
}

/* Vertical field of view of tiled_render's camera, degrees. */
#define TILED__FOVY 35.0f

/* Draws the triangles lit, textured from the atlas with mip levels capped
 * where they would mix tiles, and resolves the supersamples. */
static int tiled__draw(const pw_alloc *a, const tiled_mesh *m, const tiled_tileset *ts,
                       const tiled_render_options *ro, const int *tris, const float *uvs, int ntris,
                       pw_image *out, pw_err *e)
{
    pw_image atlas = tiled__pw_image(&ts->atlas);
    pw_texture tex;
    pw_fb fb;
    pw_draw d;
    pw_camera cam;
    float bg[4];
    int r;
    memcpy(bg, ro->background, sizeof ro->background);
    bg[3] = 1.0f;
    if ((r = pw_texture_create(a, &tex, &atlas, ts->max_mip_level + 1, e)) != PW_OK) return r;
    if ((r = pw_fb_create(a, &fb, ro->width, ro->height, ro->supersample, bg, e)) == PW_OK) {
        cam = pw_camera_frame(m->positions, m->nverts, ro->view_dir, ro->up, TILED__FOVY,
                              (float)ro->width / (float)ro->height);
        memset(&d, 0, sizeof d);
        d.positions = m->positions;
        d.nv = m->nverts;
        d.tris = tris;
        d.ntris = ntris;
        d.uvs = uvs;
        d.tex = &tex;
        d.filter = ro->filter;
        d.wrap = PW_WRAP_CLAMP;
        d.lighting = PW_LIGHT_CAMERA;
        d.ambient = 0.3f;
        r = pw_render_draw(&fb, &cam, &d, e);
        if (r == PW_OK) r = pw_fb_resolve(&fb, out, 3, e);
        pw_fb_free(&fb);
    }
    pw_texture_free(a, &tex);
    return r;
}

/* Render settings with the defaults filled in. */
static tiled_render_options tiled__render_options(const tiled_render_options *ro)
{
    tiled_render_options o;
    if (ro) o = *ro;
    else memset(&o, 0, sizeof o);
    pw_view_defaults(&o.width, &o.height, &o.supersample, o.view_dir, o.up, o.background);
    return o;
}

TILEDDEF tiled_result tiled_render(const tiled_mesh *mapped, const tiled_tileset *ts,
                                   const tiled_render_options *ro, tiled_image *out,
                                   tiled_error *err)
{
    tiled_render_options o = tiled__render_options(ro);
    pw_alloc a = tiled__alloc(ts ? &ts->atlas.allocator : NULL);
    pw_image pic;
    pw_err pe;
    int *tris = NULL, ntris = 0;
    float *uvs = NULL;
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (!out || !ts || !mapped || !mapped->uvs)
        pw_fail(&pe, PW_ERR_INVALID, "tiled_render: needs a mapped mesh (with uvs), a tile set "
                "and an output image");
    else if (o.width < 1 || o.height < 1 || o.supersample < 1 || o.supersample > 8 ||
             o.filter < 0 || o.filter > 2)
        pw_fail(&pe, PW_ERR_INVALID, "render options: size %dx%d, supersample %d, filter %d",
                o.width, o.height, o.supersample, o.filter);
    else if (tiled__check_mesh(mapped, &pe) == PW_OK &&
             tiled__check_image(&ts->atlas, "tile set atlas", &pe) == PW_OK &&
             tiled__triangles(&a, mapped, &tris, &uvs, &ntris, &pe) == PW_OK) {
        if (tiled__draw(&a, mapped, ts, &o, tris, uvs, ntris, &pic, &pe) == PW_OK)
            tiled__take_image(&pic, &a, out);
        pw_free(&a, tris);
        pw_free(&a, uvs);
    }
    return tiled__done(&pe, err);
}

/* Areas of face f in world and texture space (fan of triangles). */
static void tiled__face_areas(const tiled_mesh *m, int f, double *world, double *tex)
{
    int c0 = m->face_start[f], k;
    const float *p0 = m->positions + 3 * m->face_verts[c0], *t0 = m->uvs + 2 * c0;
    *world = *tex = 0.0;
    for (k = c0 + 1; k + 1 < m->face_start[f + 1]; k++) {
        const float *p1 = m->positions + 3 * m->face_verts[k], *p2 = m->positions + 3 * m->face_verts[k + 1];
        const float *t1 = m->uvs + 2 * k, *t2 = m->uvs + 2 * (k + 1);
        double a[3], b[3], n[3];
        int j;
        for (j = 0; j < 3; j++) a[j] = p1[j] - p0[j], b[j] = p2[j] - p0[j];
        n[0] = a[1] * b[2] - a[2] * b[1];
        n[1] = a[2] * b[0] - a[0] * b[2];
        n[2] = a[0] * b[1] - a[1] * b[0];
        *world += 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        *tex += 0.5 * fabs((t1[0] - t0[0]) * (t2[1] - t0[1]) - (t2[0] - t0[0]) * (t1[1] - t0[1]));
    }
}

static int tiled__cmp_double(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return a < b ? -1 : a > b;
}

/* Median over faces of the world length of a tile side: a face covers
 * world/tex of world area per unit of texture area, and a tile side is
 * T/W of the texture's width. 0 if no face has texture area. */
static double tiled__tile_length(const pw_alloc *a, const tiled_mesh *m, const tiled_tileset *ts, pw_err *e)
{
    double *len = (double *)pw_alloc_array(a, (size_t)m->nfaces, sizeof(double), "tile lengths", e);
    double side = (double)ts->layout.tile_size / ts->atlas.width, mid;
    int f, n = 0;
    if (!len) return -1.0;
    for (f = 0; f < m->nfaces; f++) {
        double w, t;
        tiled__face_areas(m, f, &w, &t);
        if (t > 0.0 && pw_is_finite(w / t)) len[n++] = sqrt(w / t) * side;
    }
    qsort(len, (size_t)n, sizeof *len, tiled__cmp_double);
    mid = n ? len[n / 2] : 0.0;
    pw_free(a, len);
    return mid;
}

TILEDDEF tiled_result tiled_drawn_tile_size(const tiled_mesh *mapped, const tiled_tileset *ts,
                                            const tiled_render_options *ro, float *pixels,
                                            tiled_error *err)
{
    tiled_render_options o = tiled__render_options(ro);
    pw_alloc a = tiled__alloc(ts ? &ts->atlas.allocator : NULL);
    pw_err pe;
    pw_err_clear(&pe);
    if (pixels) *pixels = 0.0f;
    if (!pixels || !ts || !mapped || !mapped->uvs || ts->atlas.width < 1 || o.width < 1 || o.height < 1)
        pw_fail(&pe, PW_ERR_INVALID, "tiled_drawn_tile_size: needs a mapped mesh (with uvs), its "
                "tile set, an output and a valid render size");
    else if (tiled__check_mesh(mapped, &pe) == PW_OK) {
        double len = tiled__tile_length(&a, mapped, ts, &pe), d[3], dist;
        pw_camera cam = pw_camera_frame(mapped->positions, mapped->nverts, o.view_dir, o.up, TILED__FOVY,
                                        (float)o.width / (float)o.height);
        int k;
        for (k = 0; k < 3; k++) d[k] = cam.eye[k] - cam.target[k];
        dist = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        /* pixels per world unit at the framed mesh's centre */
        if (len >= 0.0 && dist > 0.0)
            *pixels = (float)(len * o.height / (2.0 * dist * pw__tan_deg(0.5 * TILED__FOVY)));
    }
    return tiled__done(&pe, err);
}

/* ---- files --------------------------------------------------------------------- */

TILEDDEF tiled_result tiled_load_mesh_from_memory(const void *data, size_t size, const char *name,
                                                  const tiled_options *opt, tiled_mesh *out,
                                                  tiled_error *err)
{
    tiled_options o = tiled__options(opt);
    pw_alloc a = tiled__alloc(&o.allocator);
    pw_mesh m;
    pw_err pe;
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (!out || (!data && size)) pw_fail(&pe, PW_ERR_INVALID, "tiled_load_mesh_from_memory: NULL argument");
    else if (pw_mesh_read_memory(&a, data, size, name ? name : "mesh", &m, &pe) == PW_OK)
        tiled__take_mesh(&m, &a, out);
    return tiled__done(&pe, err);
}

TILEDDEF tiled_result tiled_load_image_from_memory(const void *data, size_t size, const char *name,
                                                   const tiled_options *opt, tiled_image *out,
                                                   tiled_error *err)
{
    tiled_options o = tiled__options(opt);
    pw_alloc a = tiled__alloc(&o.allocator);
    pw_image img;
    pw_err pe;
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (!out || (!data && size)) pw_fail(&pe, PW_ERR_INVALID, "tiled_load_image_from_memory: NULL argument");
    else if (pw_image_read_memory(&a, (const unsigned char *)data, size, name ? name : "image", &img,
                                  &pe) == PW_OK)
        tiled__take_image(&img, &a, out);
    return tiled__done(&pe, err);
}

TILEDDEF tiled_result tiled_write_image_to_func(const tiled_image *img, const char *format,
                                                tiled_write_fn fn, void *ctx, tiled_error *err)
{
    pw_err pe;
    pw_err_clear(&pe);
    if (!fn) pw_fail(&pe, PW_ERR_INVALID, "tiled_write_image_to_func: NULL writer");
    else if (tiled__check_image(img, "image", &pe) == PW_OK) tiled__encode(img, format, fn, ctx, &pe);
    return tiled__done(&pe, err);
}

/* Distinct texture coordinates in order of first use (an open-addressing
 * table on their bit patterns), so the OBJ lists each vt once. */
static int tiled__index_uvs(const pw_alloc *a, const tiled_mesh *m, pw_mesh *pm, pw_err *e)
{
    int nc = m->face_start[m->nfaces], k, cap = 16, *slot;
    while (cap < 2 * nc) cap *= 2;
    slot = (int *)pw_alloc_array(a, (size_t)cap, sizeof(int), "uv table", e);
    pm->uv = (float *)pw_alloc_array(a, (size_t)nc * 2, sizeof(float), "uvs", e);
    pm->fuv = (int *)pw_alloc_array(a, (size_t)nc, sizeof(int), "uv indices", e);
    if (!slot || !pm->uv || !pm->fuv) {
        pw_free(a, slot);
        return PW_ERR_NOMEM;
    }
    memset(slot, 0xFF, sizeof(int) * (size_t)cap);
    pm->nuv = 0;
    for (k = 0; k < nc; k++) {
        uint32_t bu, bv, i;
        memcpy(&bu, m->uvs + 2 * k, 4);
        memcpy(&bv, m->uvs + 2 * k + 1, 4);
        i = (uint32_t)pw_hash64(bu, bv) & (uint32_t)(cap - 1);
        while (slot[i] >= 0 && memcmp(pm->uv + 2 * slot[i], m->uvs + 2 * k, 8)) i = (i + 1) & (uint32_t)(cap - 1);
        if (slot[i] < 0) {
            slot[i] = pm->nuv++;
            memcpy(pm->uv + 2 * slot[i], m->uvs + 2 * k, 8);
        }
        pm->fuv[k] = slot[i];
    }
    pw_free(a, slot);
    return PW_OK;
}

TILEDDEF tiled_result tiled_write_obj_to_func(const tiled_mesh *m, const char *mtl_name,
                                              tiled_write_fn fn, void *ctx, tiled_error *err)
{
    pw_alloc a = tiled__alloc(m ? &m->allocator : NULL);
    pw_mesh pm;
    pw_err pe;
    pw_err_clear(&pe);
    if (!fn) pw_fail(&pe, PW_ERR_INVALID, "tiled_write_obj_to_func: NULL writer");
    else if (tiled__check_mesh(m, &pe) == PW_OK) {
        pm = tiled__pw_mesh(m);
        if (!m->uvs || tiled__index_uvs(&a, m, &pm, &pe) == PW_OK)
            pw_mesh_write_obj(&pm, mtl_name, mtl_name ? "tiled" : NULL, fn, ctx, &pe);
        if (m->uvs) {
            pw_free(&a, pm.uv);
            pw_free(&a, pm.fuv);
        }
    }
    return tiled__done(&pe, err);
}

TILEDDEF tiled_result tiled_write_gltf_to_func(const tiled_mesh *m, const tiled_image *texture,
                                               const tiled_render_options *view, tiled_write_fn fn, void *ctx,
                                               tiled_error *err)
{
    pw_alloc a = tiled__alloc(m ? &m->allocator : NULL);
    pw_gltf_part part;
    pw_gltf_scene scene;
    pw_camera cam;
    pw_image img;
    pw_err pe;
    pw_err_clear(&pe);
    memset(&part, 0, sizeof part);
    memset(&scene, 0, sizeof scene);
    if (!fn) pw_fail(&pe, PW_ERR_INVALID, "tiled_write_gltf_to_func: NULL writer");
    else if (texture && !m->uvs) pw_fail(&pe, PW_ERR_INVALID, "glTF: a texture for a mesh without texture coordinates");
    else if (tiled__check_mesh(m, &pe) == PW_OK && (!texture || tiled__check_image(texture, "texture", &pe) == PW_OK)) {
        part.name = "tiled";
        part.nv = m->nverts, part.pos = m->positions;
        part.nf = m->nfaces, part.fstart = m->face_start, part.fv = m->face_verts;
        part.corner_uv = m->uvs;
        if (texture) img = tiled__pw_image(texture), part.texture = &img;
        scene.parts = &part, scene.nparts = 1, scene.generator = "patchwork tiled.h " TILED_VERSION_STRING;
        if (view) {
            cam = pw_gltf_view_camera(m->positions, m->nverts, view->width, view->height, view->view_dir, view->up,
                                      &scene.aspect);
            scene.camera = &cam;
        }
        pw_gltf_write(&a, &scene, fn, ctx, &pe);
    }
    return tiled__done(&pe, err);
}

TILEDDEF tiled_result tiled_write_mtl_to_func(const char *texture_name, tiled_write_fn fn,
                                              void *ctx, tiled_error *err)
{
    pw_err pe;
    pw_err_clear(&pe);
    if (!fn || !texture_name) pw_fail(&pe, PW_ERR_INVALID, "tiled_write_mtl_to_func: NULL argument");
    else pw_mesh_write_mtl("tiled", texture_name, fn, ctx, &pe);
    return tiled__done(&pe, err);
}

#ifndef PW_NO_STDIO
TILEDDEF tiled_result tiled_load_mesh(const char *path, const tiled_options *opt, tiled_mesh *out,
                                      tiled_error *err)
{
    tiled_options o = tiled__options(opt);
    pw_alloc a = tiled__alloc(&o.allocator);
    pw_mesh m;
    pw_err pe;
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (!out || !path) pw_fail(&pe, PW_ERR_INVALID, "tiled_load_mesh: NULL argument");
    else if (pw_mesh_load(&a, path, &m, &pe) == PW_OK) tiled__take_mesh(&m, &a, out);
    return tiled__done(&pe, err);
}

TILEDDEF tiled_result tiled_load_image(const char *path, const tiled_options *opt,
                                       tiled_image *out, tiled_error *err)
{
    tiled_options o = tiled__options(opt);
    pw_alloc a = tiled__alloc(&o.allocator);
    pw_image img;
    pw_err pe;
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (!out || !path) pw_fail(&pe, PW_ERR_INVALID, "tiled_load_image: NULL argument");
    else if (pw_image_load(&a, path, &img, &pe) == PW_OK) tiled__take_image(&img, &a, out);
    return tiled__done(&pe, err);
}

/* Writers behind pw_write_file. */
typedef struct tiled__job {
    const tiled_image *img;
    const char *format;
    const tiled_mesh *mesh;
    const char *name; /* mtl name or texture name */
    const tiled_render_options *view;
} tiled__job;

static int tiled__image_job(void *arg, pw_write_fn w, void *ctx, pw_err *e)
{
    const tiled__job *j = (const tiled__job *)arg;
    return tiled__encode(j->img, j->format, w, ctx, e);
}

static int tiled__obj_job(void *arg, pw_write_fn w, void *ctx, pw_err *e)
{
    const tiled__job *j = (const tiled__job *)arg;
    tiled_error te;
    int r = (int)tiled_write_obj_to_func(j->mesh, j->name, w, ctx, &te);
    if (r) pw_fail(e, r, "%s", te.message);
    return r;
}

static int tiled__mtl_job(void *arg, pw_write_fn w, void *ctx, pw_err *e)
{
    const tiled__job *j = (const tiled__job *)arg;
    return pw_mesh_write_mtl("tiled", j->name, w, ctx, e);
}

static int tiled__gltf_job(void *arg, pw_write_fn w, void *ctx, pw_err *e)
{
    const tiled__job *j = (const tiled__job *)arg;
    tiled_error te;
    int r = (int)tiled_write_gltf_to_func(j->mesh, j->img, j->view, w, ctx, &te);
    if (r) pw_fail(e, r, "%s", te.message);
    return r;
}

static const char *tiled__format_of(const char *path)
{
    if (pw_has_ext(path, ".png")) return "png";
    if (pw_has_ext(path, ".ppm") || pw_has_ext(path, ".pnm")) return "ppm";
    if (pw_has_ext(path, ".pgm")) return "pgm";
    if (pw_has_ext(path, ".pam")) return "pam";
    return NULL;
}

TILEDDEF tiled_result tiled_save_image(const char *path, const tiled_image *img, tiled_error *err)
{
    tiled__job j;
    pw_err pe;
    pw_err_clear(&pe);
    memset(&j, 0, sizeof j);
    j.img = img;
    if (!path) pw_fail(&pe, PW_ERR_INVALID, "tiled_save_image: NULL path");
    else if (!(j.format = tiled__format_of(path)))
        pw_fail(&pe, PW_ERR_UNSUPPORTED, "%s: unknown image extension (use .png, .ppm, .pgm, .pam)", path);
    else if (tiled__check_image(img, path, &pe) == PW_OK)
        pw_write_file(path, tiled__image_job, &j, &pe);
    return tiled__done(&pe, err);
}

TILEDDEF tiled_result tiled_save_gltf(const char *path, const tiled_mesh *m, const tiled_image *texture,
                                      const tiled_render_options *view, tiled_error *err)
{
    tiled__job j;
    pw_err pe;
    pw_err_clear(&pe);
    memset(&j, 0, sizeof j);
    j.mesh = m, j.img = texture, j.view = view;
    if (!path) pw_fail(&pe, PW_ERR_INVALID, "tiled_save_gltf: NULL path");
    else pw_write_file(path, tiled__gltf_job, &j, &pe);
    return tiled__done(&pe, err);
}

TILEDDEF tiled_result tiled_save_obj(const char *obj_path, const tiled_mesh *m,
                                     const char *texture_path, tiled_error *err)
{
    char mtl[1024];
    const char *mtl_name = NULL;
    tiled__job j;
    pw_err pe;
    pw_err_clear(&pe);
    memset(&j, 0, sizeof j);
    if (pw_obj_mtl_path(obj_path, mtl, sizeof mtl, &mtl_name, &pe) != PW_OK) return tiled__done(&pe, err);
    j.mesh = m;
    j.name = texture_path ? mtl_name : NULL;
    if (pw_write_file(obj_path, tiled__obj_job, &j, &pe) == PW_OK && texture_path) {
        j.name = texture_path;
        pw_write_file(mtl, tiled__mtl_job, &j, &pe);
    }
    return tiled__done(&pe, err);
}
#endif
