/* synth.c: ch. III.1.3, tiled texture image synthesis: an edge-matched
 * tile set made from an exemplar, or wrapped around a tiled texture the
 * user made (tiled_tileset_from_image). */
#include "layout.c"

TILEDDEF tiled_result tiled_tileset_from_image(const tiled_image *tiles, const tiled_options *opt, tiled_tileset *out,
                                               tiled_error *err)
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
    pw_image src; /* periodic source */
    int T, wc;    /* tile size; rows next to a side constrained to it */
    int band;     /* rows from a side where its diamond may appear */
    int case1;
    int dx[9], dy[9];     /* diamond origins (pair k) in the source; [8]: scratch */
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

/* Candidate centre windows per tile: drawn for every tile, in tile order,
 * before any tile is composed, so that tiles can be composed in any order. */
#define TILED__CENTRE_CANDIDATES 16

/* Picks the centre window that best agrees with the side diamonds where
 * both may appear (the best of the tile's candidate origins org[2k],
 * org[2k+1]), and fills label 4. */
static void tiled__centre_source(const tiled__synth *s, const int *org, tiled__scratch *sc)
{
    int T = s->T, c = s->src.c, cand, i, j, k, bx = 0, by = 0;
    double best = -1.0;
    for (cand = 0; cand < TILED__CENTRE_CANDIDATES; cand++) {
        int ox = org[2 * cand], oy = org[2 * cand + 1];
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

static void tiled__scratch_free(const pw_alloc *a, tiled__scratch *sc)
{
    pw_free(a, sc->src);
    pw_free(a, sc->allowed);
    pw_free(a, sc->label);
    pw_free(a, sc->motif);
    memset(sc, 0, sizeof *sc);
}

static int tiled__scratch_alloc(const pw_alloc *a, int T, int c, tiled__scratch *sc, pw_err *e)
{
    size_t tt = (size_t)T * T;
    sc->src = (float *)pw_alloc_array(a, tt * 5 * c, sizeof(float), "tile sources", e);
    sc->allowed = (uint32_t *)pw_alloc_array(a, tt, sizeof(uint32_t), "tile constraints", e);
    sc->label = (int *)pw_alloc_array(a, tt, sizeof(int), "tile labels", e);
    sc->motif = (float *)pw_alloc_array(a, tt * 5, sizeof(float), "tile motif maps", e);
    if (sc->src && sc->allowed && sc->label && sc->motif) return PW_OK;
    tiled__scratch_free(a, sc);
    return PW_ERR_NOMEM;
}

/* The tiles of one synthesis, composed in `shares` shares (share j: tiles
 * j, j + shares, ...), each share with its own scratch, result and seam
 * statistics, so that the shares can run on several threads. Only share 0
 * reports progress. */
typedef struct tiled__tile_work {
    const pw_alloc *a;
    const tiled__synth *s;
    pw_image *atlas;
    const tiled__geom *gm;
    const int *origins; /* per tile, its candidate centre origins */
    const pw_progress *pr;
    int shares;
    tiled__scratch *sc;   /* [shares] */
    pw_seam_stats *stats; /* [shares] */
    int *codes;           /* [shares] */
    pw_err *errs;         /* [shares] */
} tiled__tile_work;

/* Composes tile t into the atlas of w with the scratch of share j. */
static int tiled__compose(const tiled__tile_work *w, int j, int t)
{
    const tiled__synth *s = w->s;
    pw_image *atlas = w->atlas;
    const tiled__geom *gm = w->gm;
    tiled__scratch *sc = &w->sc[j];
    int types[4], T = s->T, c = s->src.c, y, r;
    pw_quilt q;
    tiled__tile_types(gm, s->case1, t, types);
    tiled__side_sources(s, types, sc->src, sc->motif);
    tiled__constraints(s, sc);
    tiled__centre_source(s, w->origins + (size_t)t * 2 * TILED__CENTRE_CANDIDATES, sc);
    q.w = q.h = T;
    q.c = c;
    q.nlabels = 5;
    q.src = sc->src;
    q.label = sc->label;
    q.allowed = sc->allowed;
    q.wrap_x = q.wrap_y = 0;
    q.motif = sc->motif;
    q.motif_weight = s->motif_weight;
    if ((r = pw_quilt_optimize(w->a, &q, 2, &w->errs[j])) != PW_OK) return r;
    if (s->stats) pw_quilt_seam_stats(&q, s->tau, &w->stats[j]);
    for (y = 0; y < T; y++) { /* compose row by row into the atlas */
        int i;
        for (i = 0; i < T; i++)
            memcpy(tiled__atlas_px(atlas, gm, t, i, y), sc->src + ((size_t)(sc->label[y * T + i] * T + y) * T + i) * c,
                   sizeof(float) * c);
    }
    return PW_OK;
}

/* Share j of the tiles (a pw_parallel task). */
static void tiled__compose_share(void *ctx, int j)
{
    const tiled__tile_work *w = (const tiled__tile_work *)ctx;
    int n = w->gm->N * w->gm->N, t, r = PW_OK;
    pw_err_clear(&w->errs[j]);
    for (t = j; t < n && r == PW_OK; t += w->shares) {
        if (j == 0) r = pw_report(w->pr, 0.1f + 0.9f * (float)t / (float)n, "tile synthesis", &w->errs[j]);
        if (r == PW_OK) r = tiled__compose(w, j, t);
    }
    w->codes[j] = r;
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
            s->dx[8] = ox;
            s->dy[8] = oy;
        }
    }
    s->dx[k] = s->dx[8];
    s->dy[k] = s->dy[8];
}

/* Builds every tile of a resolved layout from the periodic source, the
 * tiles shared among the threads of o's parallel settings: every random
 * choice is drawn first, in tile order, and every tile is composed from
 * its own choices alone, so the tile set does not depend on the threads. */
static int tiled__synth_tiles(const pw_alloc *a, tiled__synth *s, const tiled_options *o, pw_image *atlas,
                              const tiled__geom *gm, pw_err *e)
{
    pw_progress pr = tiled__progress(o);
    pw_parallel par = pw_parallel_make(o->threads, o->parallel, o->parallel_pool);
    pw_rng rng = pw_rng_seed(o->seed, 3);
    tiled__tile_work w;
    int n = gm->N * gm->N, k, j, r = PW_OK;
    int *origins = (int *)pw_alloc_array(a, (size_t)n * 2 * TILED__CENTRE_CANDIDATES, sizeof(int), "tile choices", e);
    memset(&w, 0, sizeof w);
    w.shares = pw_mini(pw_parallel_width(&par), n);
    w.sc = (tiled__scratch *)pw_calloc_array(a, (size_t)w.shares, sizeof(tiled__scratch), "tile scratch", e);
    w.stats = (pw_seam_stats *)pw_calloc_array(a, (size_t)w.shares, sizeof(pw_seam_stats), "seam statistics", e);
    w.codes = (int *)pw_calloc_array(a, (size_t)w.shares, sizeof(int), "tile results", e);
    w.errs = (pw_err *)pw_calloc_array(a, (size_t)w.shares, sizeof(pw_err), "tile messages", e);
    if (!origins || !w.sc || !w.stats || !w.codes || !w.errs) r = PW_ERR_NOMEM;
    for (j = 0; j < w.shares && r == PW_OK; j++) r = tiled__scratch_alloc(a, s->T, s->src.c, &w.sc[j], e);
    if (r == PW_OK) {
        for (k = 0; k < 8; k++) tiled__place_diamond(s, &rng, k, gm->n);
        for (k = 0; k < n * 2 * TILED__CENTRE_CANDIDATES; k++)
            origins[k] = (int)pw_rng_below(&rng, (uint32_t)(k % 2 ? s->src.h : s->src.w));
        w.a = a;
        w.s = s;
        w.atlas = atlas;
        w.gm = gm;
        w.origins = origins;
        w.pr = &pr;
        pw_parallel_for(&par, w.shares, tiled__compose_share, &w);
        for (j = 0; j < w.shares && r == PW_OK; j++)
            if ((r = w.codes[j]) != PW_OK) *e = w.errs[j];
        for (j = 0; j < w.shares && s->stats; j++) {
            s->stats->pairs += w.stats[j].pairs;
            s->stats->cut += w.stats[j].cut;
        }
    }
    for (j = 0; w.sc && j < w.shares; j++) tiled__scratch_free(a, &w.sc[j]);
    pw_free(a, w.sc);
    pw_free(a, w.stats);
    pw_free(a, w.codes);
    pw_free(a, w.errs);
    pw_free(a, origins);
    return r;
}

/* Seam cost per source pixel inside a motif (pw_quilt.motif_weight), in
 * the units of colour distance (0..sqrt(3) per pixel and source pair): a
 * seam through a pebble pays more than one through mortar of any shade. */
#define TILED__MOTIF_WEIGHT 3.0f

/* tiled_synthesize, also adding the seam statistics of every tile (see
 * pw_quilt_seam_stats) to *stats when it is not NULL. */
static int tiled__synthesize(const tiled_image *exemplar, const tiled_options *o, tiled_tileset *out,
                             pw_seam_stats *stats, pw_err *pe)
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
        r = s.motif ? pw_quilt_motif_map(&a, &s.src, s.motif, &s.tau, pe) : PW_ERR_NOMEM;
        if (r == PW_OK && (r = tiled__synth_tiles(&a, &s, o, &atlas, &gm, pe)) == PW_OK)
            tiled__fill_guards(&atlas, &gm, s.case1);
        else tiled_tileset_free(out);
    }
    pw_image_free(&a, &s.src);
    pw_free(&a, s.motif);
    return r;
}

TILEDDEF tiled_result tiled_synthesize(const tiled_image *exemplar, const tiled_options *opt, tiled_tileset *out,
                                       tiled_error *err)
{
    tiled_options o = tiled__options(opt);
    pw_err pe;
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (!out) pw_fail(&pe, PW_ERR_INVALID, "tiled_synthesize: NULL output");
    else tiled__synthesize(exemplar, &o, out, NULL, &pe);
    return tiled__done(&pe, err);
}
