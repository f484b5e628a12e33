/* layout.c: ch. III.1, the boundary types and the tiled texture they
 * index: the tile layout of case 1 (ch. III.1.1) and case 2 (ch. III.1.2,
 * generalised to n pairs as ch. VI suggests), the atlas geometry with its
 * guard bands, and the tile set that holds it. */
#include "core.c"

/* The power of two nearest x (ties go down). */
static int tiled__pow2_near(int x)
{
    int p = 1;
    while (p * 2 <= x) p *= 2;
    return x - p <= 2 * p - x ? p : 2 * p;
}

/* Pixel geometry of an atlas. */
typedef struct tiled__geom {
    int n;    /* types per side: 2n (case 2) or 1 (case 1) */
    int N;    /* tiles per row and column */
    int T, g; /* tile size and guard */
    int C, W; /* cell size and atlas size */
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
    if (l.pairs < 1 || l.pairs > 8) return pw_fail(e, PW_ERR_INVALID, "pairs must be 1..8 (got %d)", l.pairs);
    if (l.grid < 1 || l.grid > 256) return pw_fail(e, PW_ERR_INVALID, "grid must be 1..256 (got %d)", l.grid);
    if (!l.tile_size) l.tile_size = tile_hint > 0 ? pw_clampi(tiled__pow2_near(tile_hint), 16, 256) : 64;
    if (l.tile_size < 4 || l.tile_size > 4096)
        return pw_fail(e, PW_ERR_INVALID, "tile size must be 4..4096 pixels (got %d)", l.tile_size);
    if (!l.guard) l.guard = pw_mini(pw_maxi(tiled__pow2_near(l.tile_size / 8), 2), l.tile_size);
    if (l.guard != TILED_NO_GUARD && (l.guard < 1 || l.guard > l.tile_size))
        return pw_fail(e, PW_ERR_INVALID, "guard must be 1..%d pixels or TILED_NO_GUARD (got %d)", l.tile_size,
                       l.guard);
    gm = tiled__geometry(&l);
    if ((int64_t)gm.N * gm.C > PW_MAX_IMAGE_DIM || (int64_t)gm.N * gm.C * gm.N * gm.C > PW_MAX_IMAGE_PIXELS)
        return pw_fail(e, PW_ERR_LIMIT,
                       "a tiled texture of %dx%d tiles of %d px would be %lld px wide, over the "
                       "image size limit",
                       gm.N, gm.N, gm.C, (long long)gm.N * gm.C);
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
    case 0:
        *a = i;
        *b = j;
        break;
    case 1:
        *a = j;
        *b = T - 1 - i;
        break;
    case 2:
        *a = T - 1 - i;
        *b = T - 1 - j;
        break;
    default:
        *a = T - 1 - j;
        *b = i;
        break;
    }
}

static void tiled__from_side(int side, int T, int a, int b, int *i, int *j)
{
    switch (side) {
    case 0:
        *i = a;
        *j = b;
        break;
    case 1:
        *j = a;
        *i = T - 1 - b;
        break;
    case 2:
        *i = T - 1 - a;
        *j = T - 1 - b;
        break;
    default:
        *j = T - 1 - a;
        *i = b;
        break;
    }
}

/* Pixel (i, j) of tile (col, row) in an atlas; i, j may reach into the
 * guard band (-g .. T+g-1). Cells count rows from the bottom of the image. */
static float *tiled__atlas_px(const pw_image *atlas, const tiled__geom *gm, int tile, int i, int j)
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
                    memcpy(
                        tiled__atlas_px(atlas, gm, t, i, j),
                        tiled__atlas_px(atlas, gm, t, i < 0 ? -1 - i : 2 * T - 1 - i, j < 0 ? -1 - j : 2 * T - 1 - j),
                        sizeof(float) * atlas->c);
                    continue;
                }
                tiled__to_side(s, T, pw_clampi(i, 0, T - 1), pw_clampi(j, 0, T - 1), &a, &b);
                pt = tiled__partner(case1, types[s]);
                tiled__from_side(rep_side[pt], T, T - 1 - a, depth - 1, &pi, &pj);
                memcpy(tiled__atlas_px(atlas, gm, t, i, j), tiled__atlas_px(atlas, gm, rep_tile[pt], pi, pj),
                       sizeof(float) * atlas->c);
            }
    }
}

/* Allocates a tile set's atlas for a resolved layout. */
static int tiled__new_tileset(const pw_alloc *a, const tiled_layout *l, int channels, tiled_tileset *ts, pw_err *e)
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
static int tiled__layout_of_image(const tiled_layout *want, const tiled_image *img, tiled_layout *out, pw_err *e)
{
    tiled_layout l = *want;
    tiled__geom gm;
    int r;
    l.tile_size = 4;
    l.guard = TILED_NO_GUARD;
    if ((r = tiled__check_image(img, "tiled texture", e)) != PW_OK || (r = tiled__resolve(&l, 0, &l, e)) != PW_OK)
        return r;
    gm = tiled__geometry(&l);
    if (img->width != img->height || img->width % gm.N || img->width / gm.N < 4)
        return pw_fail(e, PW_ERR_INVALID,
                       "a tiled texture for this layout must be square with a "
                       "side divisible by %d, tiles of 4 px or more (got %dx%d)",
                       gm.N, img->width, img->height);
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
