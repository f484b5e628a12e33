/* map.c: ch. III.2, the texture mapping algorithm of Fig. 29
 * (AssignBoundaries, AssignTextureCoordinates), and ch. VI: Catmull-Clark
 * subdivision before mapping (any polygon mesh made all quads) and after
 * it, carrying the texture along (Figs. 30, 31). */
#include "cells.c"

static int tiled__all_quads(const pw_mesh *m)
{
    int f;
    for (f = 0; f < m->nf; f++)
        if (m->fstart[f + 1] - m->fstart[f] != 4) return 0;
    return 1;
}

/* A quad mesh being mapped: geometry, its half-edges, and per corner the
 * texture coordinates and boundary types, per face the tile. */
typedef struct tiled__mapped {
    pw_mesh q;
    pw_hmesh hm;
    float *uv;
    int *types, *tiles;
} tiled__mapped;

/* Catmull-Clark until all faces are quads (ch. VI: "any mesh can easily be
 * converted to a quadrilateral mesh"), then `extra` more levels; `planned`
 * counts every level still to come (smoothing included) for the size
 * check made before any work; here extra = o->subdivide and planned =
 * o->subdivide + o->smooth. On success m->q owns its arrays and m->hm is
 * its half-edge structure. */
static int tiled__quadrangulate(const pw_alloc *a, const tiled_mesh *in, const tiled_options *o, const pw_progress *pr,
                                tiled__mapped *m, pw_err *e)
{
    const int planned = o->subdivide + o->smooth, extra = o->subdivide;
    pw_mesh *q = &m->q;
    pw_hmesh *hm = &m->hm;
    pw_mesh view = tiled__pw_mesh(in), next;
    int levels = (tiled__all_quads(&view) ? 0 : 1) + extra, l, r;
    double faces = in->face_start[in->nfaces];
    for (l = 0; l < levels - extra + planned; l++) faces *= 4; /* every level planned, smoothing too */
    if (faces > PW_MAX_MESH_ELEMENTS)
        return pw_fail(e, PW_ERR_LIMIT,
                       "subdividing %d faces %d times would make %.0f faces "
                       "(limit %d)",
                       in->nfaces, levels - extra + planned, faces, PW_MAX_MESH_ELEMENTS);
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
static void tiled__assign_boundaries(const pw_hmesh *hm, const tiled_layout *l, uint64_t seed, int *types)
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
 * tile's corner k. Case 1 draws a tile, a rotation and a mirror instead.
 * Reads m's quads and boundary types, writes its uv and tiles. */
static void tiled__assign_uvs(tiled__mapped *m, const tiled__geom *gm, int case1, const tiled_options *o,
                              const float *coord)
{
    pw_rng r = pw_rng_seed(o->seed, 2);
    const int *types = m->types;
    float *uv = m->uv;
    int *face_tiles = m->tiles;
    const int nf = m->q.nf, n = gm->n, N = gm->N, nn = N * N;
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

static void tiled__mapped_free(const pw_alloc *a, tiled__mapped *m)
{
    pw_mesh_free(a, &m->q);
    pw_hmesh_free(a, &m->hm);
    pw_free(a, m->uv);
    pw_free(a, m->types);
    pw_free(a, m->tiles);
    memset(m, 0, sizeof *m);
}

/* Allocates m's per-corner and per-face arrays for nc corners, nf faces. */
static int tiled__mapped_arrays(const pw_alloc *a, tiled__mapped *m, int nc, int nf, pw_err *e)
{
    m->uv = (float *)pw_alloc_array(a, (size_t)nc * 2, sizeof(float), "texture coordinates", e);
    m->types = (int *)pw_alloc_array(a, (size_t)nc, sizeof(int), "boundary types", e);
    m->tiles = (int *)pw_alloc_array(a, (size_t)nf, sizeof(int), "face tiles", e);
    if (m->uv && m->types && m->tiles) return PW_OK;
    pw_free(a, m->uv);
    pw_free(a, m->types);
    pw_free(a, m->tiles);
    m->uv = NULL;
    m->types = m->tiles = NULL;
    return PW_ERR_NOMEM;
}

/* Runs both procedures of Fig. 29 on the quad mesh. */
static int tiled__assign(const pw_alloc *a, tiled__mapped *m, const tiled_layout *l, const tiled_options *o, pw_err *e)
{
    tiled__geom gm = tiled__geometry(l);
    float *coord = (float *)pw_alloc_array(a, (size_t)gm.N * 2, sizeof(float), "coordinates", e);
    if (!coord || tiled__mapped_arrays(a, m, m->q.fstart[m->q.nf], m->q.nf, e)) {
        pw_free(a, coord);
        return PW_ERR_NOMEM;
    }
    tiled__coord_table(&gm, coord);
    tiled__assign_boundaries(&m->hm, l, o->seed, m->types);
    tiled__assign_uvs(m, &gm, l->case_number == 1, o, coord);
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
        (r = tiled__mapped_arrays(a, &next, 4 * m->hm.nh, m->hm.nh, e)) != PW_OK ||
        (r = pw_hmesh_build(a, next.q.nv, next.q.nf, next.q.fstart, next.q.fv, &next.hm, e)) != PW_OK) {
        tiled__mapped_free(a, &next);
        return r;
    }
    tiled__smooth_uvs(m, next.uv, next.types, next.tiles);
    tiled__mapped_free(a, m);
    *m = next;
    return PW_OK;
}

TILEDDEF tiled_result tiled_map(const tiled_mesh *in, const tiled_layout *layout, const tiled_options *opt,
                                tiled_mesh *out, tiled_error *err)
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
    else if (!(o.scale >= 0.0f) || !pw_is_finite(o.scale))
        pw_fail(&pe, PW_ERR_INVALID, "scale %g is not a positive finite number", (double)o.scale);
    else if (o.scale > 0.0f && (o.field != TILED_FIELD_UP && o.field != TILED_FIELD_CURVATURE))
        pw_fail(&pe, PW_ERR_INVALID, "unknown field %d", (int)o.field);
    else if (o.scale > 0.0f && (o.subdivide < 0 || o.subdivide > 8 || o.smooth))
        pw_fail(&pe, PW_ERR_INVALID, "with scale %g: subdivide must be 0..8 (got %d) and smooth 0 (got %d)",
                (double)o.scale, o.subdivide, o.smooth);
    else if (o.scale > 0.0f) { /* any mesh; subdivide: Catmull-Clark first, a finer mesh to cut */
        if (tiled__resolve(layout, 0, &l, &pe) == PW_OK && tiled__check_mesh(in, &pe) == PW_OK &&
            (!o.subdivide || tiled__quadrangulate(&a, in, &o, &pr, &m, &pe) == PW_OK)) {
            tiled_mesh fine = *in;
            if (o.subdivide) {
                fine.nverts = m.q.nv;
                fine.positions = m.q.pos;
                fine.nfaces = m.q.nf;
                fine.face_start = m.q.fstart;
                fine.face_verts = m.q.fv;
            }
            tiled__map_cells(&a, &fine, &l, &o, out, &pe);
        }
    } else if (o.subdivide < 0 || o.subdivide > 8 || o.smooth < 0 || o.smooth > 8)
        pw_fail(&pe, PW_ERR_INVALID, "subdivide and smooth must be 0..8 (got %d and %d)", o.subdivide, o.smooth);
    else if (tiled__resolve(layout, 0, &l, &pe) == PW_OK && tiled__check_mesh(in, &pe) == PW_OK &&
             tiled__quadrangulate(&a, in, &o, &pr, &m, &pe) == PW_OK &&
             pw_report(&pr, 0.8f, "texture coordinates", &pe) == PW_OK && tiled__assign(&a, &m, &l, &o, &pe) == PW_OK) {
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
