/* cells.c: beyond the thesis (issue 23): tiles of a chosen size on any
 * mesh. The periodic global parameterization of pgp.h (shared,
 * src/common/periodic.h) lays an integer grid (s, t) over the surface
 * along a field; every triangle is cut along the grid lines so that each
 * piece lies in one cell; the cells are identified across triangles by
 * union-find over (triangle, cell) pairs, following the integer jumps of
 * (s, t) between neighbours; every cell side then gets a boundary type,
 * partner types (2k, 2k+1) on the two sides of every shared side, and
 * every cell the tile its four sides name (ch. III.1.2's layout).
 *
 * Union-find rather than extracting the quad layout (QEx, Ebke et al.
 * 2013): it needs no tracing of isolines through singularities, and where
 * the grid is not a grid (a vortex, a T-junction) it still yields cells,
 * with their neighbours counted. The types are solved as a 2-colouring:
 * each shared side asks its two cell sides to be partners; sides of one
 * cell met by several neighbours (a T-junction) are all made partners of
 * it, and only an odd cycle of such constraints leaves a side unmatched.
 *
 * Around a vortex the union-find joins the cells the extra row of tiles
 * ends in (one cell of 2 to 4 cells' area); tiled__vortex_cuts cuts that
 * cell along the isoline of the other coordinate through the vortex, each
 * part a rectangle of the (s, t) plane showing its tile's part there at
 * full size (the cut line lies inside the tiles, not on a cell side).
 *
 * Vortex triangles (s or t winds around them, pw_periodic_winding) take
 * pgp's clean treatment: the differences their neighbours use along their
 * edges and a fan of TILED__FAN thin triangles per edge around the point
 * where the pattern ends, each carrying the clean coordinate (linear along
 * every ray from that point) at its corners. One lookup per pixel, so no
 * ghost; the fan's rays carry a jump of about winding / (3 TILED__FAN) of
 * a period at the centre (more where the residual turns fast), falling to
 * 0 at the triangle's edges (docs/tiled.md has the figures). */
#include "layout.c"

#define TILED__FAN 8         /* thin triangles per edge of a vortex triangle */
#define TILED__MAX_SPAN 4096 /* cells a triangle may span before it is left uncut */
#define TILED__CUT_MIN 0.25  /* a vortex's cell is cut no closer to its sides (cells): fewer cut lines */

/* A triangle to cut: a mesh triangle or one of a vortex triangle's fan. */
typedef struct tiled__src {
    float pos[9];
    double st[6];
} tiled__src;

/* A corner of a piece: (s, t), the point, and which sides of its cell it
 * lies on (bit k: side k, 0 bottom, 1 right, 2 top, 3 left). */
typedef struct tiled__pv {
    double s, t;
    float p[3];
    int on;
} tiled__pv;

/* A piece: a convex polygon of one source triangle inside cell (ci, cj).
 * Where vortices' cells are cut into bands (tiled__vortex_cuts), ck is the
 * coordinate cut (0: s, 1: t; -1: none), [lo, hi] the piece's band along
 * it and sub its number (from 1). */
typedef struct tiled__piece {
    int src, ci, cj, v0, nv, ck, sub;
    double lo, hi;
} tiled__piece;

/* A cut line through a vortex: the union-find root of its cell, the
 * coordinate cut and the line's offset in the cell. */
typedef struct tiled__line {
    int root, c;
    double m;
} tiled__line;

/* One shared cell side: the right (side 1) or top (side 2) of cell a is
 * the left or bottom of cell b. */
typedef struct tiled__adj {
    int a, b, side;
} tiled__adj;

typedef struct tiled__grid {
    pw_alloc a;
    pw_periodic pp;
    tiled__src *src;
    int nsrc, *fan; /* fan[f]: first source triangle of vortex triangle f, or -1 */
    float *clean;   /* 24 floats per triangle: pw_periodic_clean_coord of s and t */
    tiled__pv *pv;
    size_t npv, pvcap;
    tiled__piece *pc;
    size_t npc, pccap;
    int *first; /* nsrc + 1: first piece of each source triangle */
    int *uf;    /* per piece: union-find parent */
    int *cls;   /* per piece: cell */
    int ncls;
    tiled__adj *adj; /* shared sides, sorted; a side met twice is listed twice */
    size_t nadj, adjcap;
    int *types; /* 4 per cell: the types of its sides (0 bottom, 1 right, 2 top, 3 left) */
    int *tile;  /* per cell: its tile; then per cell: 1 if special; then its quarter turns */
    tiled_grid_stats st;
} tiled__grid;

static void tiled__grid_free(tiled__grid *C)
{
    pw_periodic_free(&C->pp);
    pw_free(&C->a, C->src);
    pw_free(&C->a, C->fan);
    pw_free(&C->a, C->clean);
    pw_free(&C->a, C->pv);
    pw_free(&C->a, C->pc);
    pw_free(&C->a, C->first);
    pw_free(&C->a, C->uf);
    pw_free(&C->a, C->cls);
    pw_free(&C->a, C->adj);
    pw_free(&C->a, C->types);
    pw_free(&C->a, C->tile);
}

/* ---- the parameterization ------------------------------------------------- */

/* The field, the PGP over the whole mesh and the per-corner (s, t), as
 * pgp_create does with no constraint (pgp's default smoothing, +y up). */
static int tiled__parameterize(tiled__grid *C, const tiled_mesh *in, const tiled_options *o, pw_err *e)
{
    static const float up[3] = {0.0f, 1.0f, 0.0f};
    pw_periodic *P = &C->pp;
    pw_mesh v = tiled__pw_mesh(in);
    unsigned char *vfree;
    int i, r;
    P->a = C->a;
    if ((r = pw_periodic_init(P, &v, e)) != PW_OK) return r;
    P->scale0 = o->scale;
    if ((r = pw_periodic_check_scale(P, o->scale, e)) != PW_OK) return r;
    for (i = 0; i < P->m.nv; i++) {
        P->scale[i] = o->scale;
        P->sfac[i] = 1.0f;
        P->zs[2 * i] = P->zt[2 * i] = 1.0;
        P->zs[2 * i + 1] = P->zt[2 * i + 1] = 0.0;
    }
    if ((r = pw_periodic_base_field(P, up, o->field == TILED_FIELD_CURVATURE, 20, e)) != PW_OK) return r;
    if (!(vfree = (unsigned char *)pw_alloc_array(&C->a, (size_t)P->m.nv, 1, "tiles", e))) return PW_ERR_NOMEM;
    memset(vfree, 1, (size_t)P->m.nv);
    r = pw_periodic_solve(P, vfree, 1, e);
    pw_free(&C->a, vfree);
    for (i = 0; r == PW_OK && i < P->m.nf; i++) pw_periodic_recover(P, i);
    return r;
}

/* (s, t) of triangle f's boundary at corner a + lam (edge a -> a+1): the
 * Eq. (4) coordinates, or a vortex triangle's clean ones (U + lam D). */
static void tiled__edge_st(const tiled__grid *C, int f, int a, double lam, double *st)
{
    int k;
    for (k = 0; k < 2; k++) {
        if (C->fan[f] >= 0) {
            const float *o = C->clean + 24 * (size_t)f + 12 * k;
            st[k] = o[a] + lam * o[3 + a];
        } else {
            const float *c = C->pp.stm + 9 * (size_t)f;
            st[k] = c[3 * a + k] + lam * ((double)c[3 * ((a + 1) % 3) + k] - c[3 * a + k]);
        }
    }
}

/* The source triangles: every regular triangle as it is, every vortex
 * triangle as its fan (centre c: where s ends, else where t ends). The
 * centre corner of thin triangle i takes the clean coordinate's limit
 * along the ray to the middle of its outer edge. */
static void tiled__fan(tiled__grid *C, int f)
{
    const float *o = C->clean + 24 * (size_t)f, *q = o[9] >= 0.0f ? o + 9 : o + 21;
    const int *tri = C->pp.m.tri + 3 * f;
    double c[3], b[3], lam0, lam1, lm;
    int i, a, k, j;
    for (k = 0; k < 3; k++) c[k] = q[0] >= 0.0f ? q[k] : 1.0 / 3.0;
    for (i = 0; i < 3 * TILED__FAN; i++) {
        tiled__src *s = C->src + C->fan[f] + i;
        a = i / TILED__FAN;
        lam0 = (double)(i % TILED__FAN) / TILED__FAN;
        lam1 = (double)(i % TILED__FAN + 1) / TILED__FAN;
        lm = 0.5 * (lam0 + lam1);
        for (k = 0; k < 3; k++) {
            double p0 = C->pp.m.pos[3 * tri[a] + k], p1 = C->pp.m.pos[3 * tri[(a + 1) % 3] + k], pc = 0.0;
            for (j = 0; j < 3; j++) pc += c[j] * C->pp.m.pos[3 * tri[j] + k];
            s->pos[k] = (float)pc;
            s->pos[3 + k] = (float)(p0 + lam0 * (p1 - p0));
            s->pos[6 + k] = (float)(p0 + lam1 * (p1 - p0));
        }
        tiled__edge_st(C, f, a, lam0, s->st + 2);
        tiled__edge_st(C, f, a, lam1, s->st + 4);
        for (k = 0; k < 3; k++) b[k] = c[k] * (1.0 - 1e-4);
        b[a] += 1e-4 * (1.0 - lm);
        b[(a + 1) % 3] += 1e-4 * lm;
        for (k = 0; k < 2; k++) /* a coordinate that does not wind: its value at the centre, exactly */
            s->st[k] = pw_periodic_clean_eval(o + 12 * k, o[12 * k + 9] < 0.0f ? c : b);
    }
}

static int tiled__sources(tiled__grid *C, pw_err *e)
{
    const pw_periodic *P = &C->pp;
    int f, k, nv = 0;
    C->fan = (int *)pw_alloc_array(&C->a, (size_t)P->m.nf, sizeof(int), "tiles", e);
    C->clean = (float *)pw_calloc_array(&C->a, (size_t)P->m.nf * 24, sizeof(float), "tiles", e);
    if (!C->fan || !C->clean) return PW_ERR_NOMEM;
    for (f = 0; f < P->m.nf; f++) {
        C->fan[f] = pw_periodic_vortex(P, f) ? P->m.nf + 3 * TILED__FAN * nv++ : -1;
        for (k = 0; C->fan[f] >= 0 && k < 2; k++) pw_periodic_clean_coord(P, f, k, C->clean + 24 * (size_t)f + 12 * k);
    }
    C->st.triangles = P->m.nf;
    C->st.vortex_triangles = nv;
    C->nsrc = P->m.nf + 3 * TILED__FAN * nv;
    C->src = (tiled__src *)pw_calloc_array(&C->a, (size_t)C->nsrc, sizeof(tiled__src), "tiles", e);
    if (!C->src) return PW_ERR_NOMEM;
    for (f = 0; f < P->m.nf; f++) {
        tiled__src *s = C->src + f;
        if (C->fan[f] >= 0) {
            tiled__fan(C, f);
            continue;
        }
        for (k = 0; k < 9; k++) s->pos[k] = P->m.pos[3 * P->m.tri[3 * f + k / 3] + k % 3];
        for (k = 0; k < 3; k++) tiled__edge_st(C, f, k, 0.0, s->st + 2 * k);
    }
    return PW_OK;
}

/* ---- cutting along the grid ------------------------------------------------ */

/* Keeps the part of polygon in (n corners) on the inner side of line
 * coordinate k (0: s, 1: t) = x (keep >= x if lower, else <= x); writes
 * out, returns its corner count. Corners made on the line get it exactly. */
static int tiled__clip(const tiled__pv *in, int n, int k, double x, int lower, tiled__pv *out)
{
    int i, j, m = 0;
    for (i = 0; i < n; i++) {
        const tiled__pv *p = in + i, *q = in + (i + 1) % n;
        double vp = k ? p->t : p->s, vq = k ? q->t : q->s;
        int ip = lower ? vp >= x : vp <= x, iq = lower ? vq >= x : vq <= x;
        if (ip) out[m++] = *p;
        if (ip != iq) {
            double u = (x - vp) / (vq - vp);
            tiled__pv *r = out + m++;
            r->s = k ? p->s + u * (q->s - p->s) : x;
            r->t = k ? x : p->t + u * (q->t - p->t);
            for (j = 0; j < 3; j++) r->p[j] = (float)(p->p[j] + u * (q->p[j] - p->p[j]));
        }
    }
    return m;
}

/* Twice the signed area of a polygon in (s, t). */
static double tiled__st_area(const tiled__pv *v, int n)
{
    double A = 0.0;
    int i;
    for (i = 0; i < n; i++) A += v[i].s * v[(i + 1) % n].t - v[(i + 1) % n].s * v[i].t;
    return A;
}

/* Appends polygon a (n corners) as piece q. Bit k of a corner's `on`: on
 * side k of the cell; bit 4: on the band's lower line, bit 5: its upper. */
static int tiled__append(tiled__grid *C, const tiled__piece *q, tiled__pv *a, int n, pw_err *e)
{
    int k, r;
    double i = q->ci, j = q->cj;
    if ((r = pw_grow(&C->a, (void **)&C->pv, &C->pvcap, C->npv + (size_t)n, sizeof *C->pv, "pieces", e)) != PW_OK ||
        (r = pw_grow(&C->a, (void **)&C->pc, &C->pccap, C->npc + 1, sizeof *C->pc, "pieces", e)) != PW_OK)
        return r;
    for (k = 0; k < n; k++) {
        a[k].on = (a[k].t == j) | (a[k].s == i + 1.0) << 1 | (a[k].t == j + 1.0) << 2 | (a[k].s == i) << 3 |
                  (q->ck >= 0 && q->sub > 1 && (q->ck ? a[k].t : a[k].s) == q->lo) << 4 |
                  (q->ck >= 0 && (q->ck ? a[k].t : a[k].s) == q->hi && q->hi < (q->ck ? j : i) + 1.0) << 5;
        C->pv[C->npv + (size_t)k] = a[k];
    }
    C->pc[C->npc] = *q;
    C->pc[C->npc].v0 = (int)C->npv;
    C->pc[C->npc].nv = n;
    C->npv += (size_t)n;
    C->npc++;
    return PW_OK;
}

/* Appends the piece of source triangle src inside cell (i, j), if any. */
static int tiled__add_piece(tiled__grid *C, int src, int i, int j, int whole, pw_err *e)
{
    tiled__pv a[16], b[16];
    tiled__piece q;
    int n = 3, k;
    for (k = 0; k < 3; k++) {
        a[k].s = C->src[src].st[2 * k];
        a[k].t = C->src[src].st[2 * k + 1];
        memcpy(a[k].p, C->src[src].pos + 3 * k, sizeof a[k].p);
    }
    if (!whole) {
        n = tiled__clip(a, n, 0, (double)i, 1, b);
        n = tiled__clip(b, n, 0, (double)i + 1.0, 0, a);
        n = tiled__clip(a, n, 1, (double)j, 1, b);
        n = tiled__clip(b, n, 1, (double)j + 1.0, 0, a);
        if (n < 3 || fabs(tiled__st_area(a, n)) < 1e-12) return PW_OK;
    }
    memset(&q, 0, sizeof q);
    q.src = src;
    q.ci = i;
    q.cj = j;
    q.ck = -1;
    return tiled__append(C, &q, a, n, e);
}

/* Cuts every source triangle into its cells. A triangle spanning more than
 * TILED__MAX_SPAN cells (a degenerate parameterization) stays whole, in
 * the cell of its first corner. */
static int tiled__cut(tiled__grid *C, pw_err *e)
{
    int s, k, r = PW_OK;
    C->first = (int *)pw_alloc_array(&C->a, (size_t)C->nsrc + 1, sizeof(int), "pieces", e);
    if (!C->first) return PW_ERR_NOMEM;
    for (s = 0; s < C->nsrc && r == PW_OK; s++) {
        const double *st = C->src[s].st;
        double lo[2], hi[2];
        int i, j;
        C->first[s] = (int)C->npc;
        if (s < C->pp.m.nf && C->fan[s] >= 0) continue;
        for (k = 0; k < 2; k++) {
            lo[k] = floor(st[k] < st[2 + k] ? (st[k] < st[4 + k] ? st[k] : st[4 + k])
                                            : (st[2 + k] < st[4 + k] ? st[2 + k] : st[4 + k]));
            hi[k] = floor(st[k] > st[2 + k] ? (st[k] > st[4 + k] ? st[k] : st[4 + k])
                                            : (st[2 + k] > st[4 + k] ? st[2 + k] : st[4 + k]));
        }
        if ((hi[0] - lo[0] + 1.0) * (hi[1] - lo[1] + 1.0) > TILED__MAX_SPAN) {
            r = tiled__add_piece(C, s, (int)floor(st[0]), (int)floor(st[1]), 1, e);
            continue;
        }
        for (j = (int)lo[1]; j <= (int)hi[1] && r == PW_OK; j++)
            for (i = (int)lo[0]; i <= (int)hi[0] && r == PW_OK; i++) r = tiled__add_piece(C, s, i, j, 0, e);
    }
    C->first[C->nsrc] = (int)C->npc;
    C->st.pieces = (int)C->npc;
    return r;
}

/* ---- cells: union-find over (triangle, cell) -------------------------------- */

static int tiled__find(int *uf, int x)
{
    while (uf[x] != x) {
        uf[x] = uf[uf[x]];
        x = uf[x];
    }
    return x;
}

static void tiled__union(int *uf, int x, int y)
{
    x = tiled__find(uf, x);
    y = tiled__find(uf, y);
    if (x != y) uf[x > y ? x : y] = x < y ? x : y; /* the lower piece is the root */
}

/* The piece of source triangle src in cell (i, j) holding point st (the
 * band it lies in; st NULL: the first), or -1. */
static int tiled__node(const tiled__grid *C, int src, int i, int j, const double *st)
{
    int p;
    for (p = C->first[src]; p < C->first[src + 1]; p++) {
        const tiled__piece *q = C->pc + p;
        if (q->ci == i && q->cj == j && (q->ck < 0 || !st || (st[q->ck] >= q->lo && st[q->ck] <= q->hi))) return p;
    }
    return -1;
}

/* A stretch of boundary shared by source triangles sa and sb: its (s, t)
 * at both ends seen from each (a0/b0 the same point, a1/b1 the other).
 * Between consecutive grid crossings (seen from sa), the two cells under
 * the stretch are the same cell: the integer jump of (s, t) between the
 * sides says which. A jump that is not near an integer (a mismatch next to
 * a vortex) joins nothing. */
static void tiled__join(tiled__grid *C, int sa, const double *a0, const double *a1, int sb, const double *b0,
                        const double *b1)
{
    double cut[2 * (TILED__MAX_SPAN + 2)], tmp;
    int n = 0, k, i, j, x, lo, hi;
    cut[n++] = 0.0;
    for (k = 0; k < 2; k++) {
        if (a0[k] == a1[k]) continue;
        lo = (int)ceil(a0[k] < a1[k] ? a0[k] : a1[k]);
        hi = (int)floor(a0[k] < a1[k] ? a1[k] : a0[k]);
        for (x = lo; x <= hi && n < 2 * TILED__MAX_SPAN; x++) cut[n++] = ((double)x - a0[k]) / (a1[k] - a0[k]);
    }
    for (i = C->first[sa]; i < C->first[sa + 1] && n < 2 * TILED__MAX_SPAN + 2; i++) { /* cut lines */
        const tiled__piece *q = C->pc + i;
        double u;
        if (q->ck < 0 || q->sub == 1 || a0[q->ck] == a1[q->ck]) continue;
        u = (q->lo - a0[q->ck]) / (a1[q->ck] - a0[q->ck]);
        if (u > 0.0 && u < 1.0) cut[n++] = u;
    }
    cut[n++] = 1.0;
    for (i = 1; i < n; i++) /* insertion sort: few crossings */
        for (j = i; j > 0 && cut[j - 1] > cut[j]; j--) {
            tmp = cut[j];
            cut[j] = cut[j - 1];
            cut[j - 1] = tmp;
        }
    for (i = 0; i + 1 < n; i++) {
        double u = 0.5 * (cut[i] + cut[i + 1]), sa_[2], sb_[2], d[2];
        int pa, pb, ok = 1;
        if (cut[i + 1] - cut[i] < 1e-9) continue;
        for (k = 0; k < 2; k++) {
            sa_[k] = a0[k] + u * (a1[k] - a0[k]);
            sb_[k] = b0[k] + u * (b1[k] - b0[k]);
            d[k] = sb_[k] - sa_[k];
            ok &= fabs(d[k] - floor(d[k] + 0.5)) < 0.25;
            d[k] = floor(d[k] + 0.5);
        }
        if (!ok) continue;
        pa = tiled__node(C, sa, (int)floor(sa_[0]), (int)floor(sa_[1]), sa_);
        pb = tiled__node(C, sb, (int)floor(sa_[0]) + (int)d[0], (int)floor(sa_[1]) + (int)d[1], sb_);
        if (pa >= 0 && pb >= 0 && C->pc[pa].sub == C->pc[pb].sub) /* never across a cut line */
            tiled__union(C->uf, pa, pb);
    }
}

/* The source triangle of triangle f holding its boundary at corner a + lam. */
static int tiled__src_at(const tiled__grid *C, int f, int a, double lam)
{
    int j = (int)floor(lam * TILED__FAN);
    if (C->fan[f] < 0) return f;
    return C->fan[f] + a * TILED__FAN + (j < 0 ? 0 : (j >= TILED__FAN ? TILED__FAN - 1 : j));
}

/* Joins across every mesh edge (in TILED__FAN parts where a side is a
 * vortex fan) and across the rays of every fan. */
static void tiled__join_all(tiled__grid *C)
{
    const pw_periodic *P = &C->pp;
    int h, p, i, f;
    for (h = 0; h < 3 * P->m.nf; h++) {
        int t = P->m.hm.twin[h], f0 = h / 3, a = h % 3, g, b, parts;
        if (t < h) continue;
        g = t / 3;
        b = t % 3;
        parts = C->fan[f0] >= 0 || C->fan[g] >= 0 ? TILED__FAN : 1;
        for (p = 0; p < parts; p++) {
            double l0 = (double)p / parts, l1 = (double)(p + 1) / parts, a0[2], a1[2], b0[2], b1[2];
            double lm = 0.5 * (l0 + l1);
            tiled__edge_st(C, f0, a, l0, a0);
            tiled__edge_st(C, f0, a, l1, a1);
            tiled__edge_st(C, g, b, 1.0 - l0, b0);
            tiled__edge_st(C, g, b, 1.0 - l1, b1);
            tiled__join(C, tiled__src_at(C, f0, a, lm), a0, a1, tiled__src_at(C, g, b, 1.0 - lm), b0, b1);
        }
    }
    for (f = 0; f < P->m.nf; f++)
        for (i = 0; C->fan[f] >= 0 && i < 3 * TILED__FAN; i++) { /* thin i's ray x_{i+1} -> c is thin i+1's */
            const tiled__src *A = C->src + C->fan[f] + i, *B = C->src + C->fan[f] + (i + 1) % (3 * TILED__FAN);
            tiled__join(C, C->fan[f] + i, A->st + 4, A->st, C->fan[f] + (i + 1) % (3 * TILED__FAN), B->st + 2, B->st);
        }
}

/* ---- vortices: their cell cut in two ------------------------------------------ */

static int tiled__cut_cmp(const void *x, const void *y)
{
    const tiled__line *p = (const tiled__line *)x, *q = (const tiled__line *)y;
    if (p->root != q->root) return p->root < q->root ? -1 : 1;
    return p->m < q->m ? -1 : p->m > q->m;
}

/* Around a vortex of s (where the extra column of tiles ends), the
 * union-find joins the cells on both sides of the isoline s = k that ends
 * at the zero, through the face of the isolines around it: one cell of 2
 * to 4 cells' area. The isoline of t through the zero (t does not wind
 * there, so it is a plain line, straight in the vortex triangle; the
 * ending isoline arrives along it) cuts that face in two: on one side the
 * cells (k-1, j) and (k, j), on the other one cell, each an axis-aligned
 * rectangle of the (s, t) plane. A face holding several vortices is cut
 * into bands, along the coordinate its first vortex asks for; lines closer
 * than TILED__CUT_MIN of a cell to another or to a grid line are left (a
 * sliver of another tile along a side). Lists the cuts by root (cuts, *n); returns how many vortices
 * were cut. */
static int tiled__vortex_cuts(tiled__grid *C, tiled__line **cuts, size_t *n, pw_err *e)
{
    const pw_periodic *P = &C->pp;
    size_t cap = 0, i, k = 0;
    int f, a, r;
    for (f = 0; f < P->m.nf; f++) {
        const float *o = C->clean + 24 * (size_t)f;
        int c, p = -1;
        double b[3];
        if (C->fan[f] < 0 || (pw_periodic_winding(P, f, 0) != 0) == (pw_periodic_winding(P, f, 1) != 0)) continue;
        c = pw_periodic_winding(P, f, 0) != 0; /* the coordinate that does not wind */
        for (a = 0; a < 3; a++) b[a] = o[12 * (1 - c) + 9 + a];
        for (a = 0; p < 0 && a < 3 * TILED__FAN; a++) { /* the cell at the zero */
            const double *ap = C->src[C->fan[f] + a].st;
            p = tiled__node(C, C->fan[f] + a, (int)floor(ap[0]), (int)floor(ap[1]), NULL);
        }
        if (p < 0) continue;
        if ((r = pw_grow(&C->a, (void **)cuts, &cap, k + 1, sizeof **cuts, "cells", e)) != PW_OK) return -1;
        (*cuts)[k].root = tiled__find(C->uf, p);
        (*cuts)[k].c = c;
        (*cuts)[k].m = pw_periodic_clean_eval(o + 12 * c, b) - (c ? C->pc[p].cj : C->pc[p].ci);
        k++;
    }
    if (k) qsort(*cuts, k, sizeof **cuts, tiled__cut_cmp);
    for (i = 0, *n = 0; i < k; i++) { /* keep: the face's coordinate, no slivers */
        tiled__line *q = *cuts + i, *prev = *n && (*cuts)[*n - 1].root == q->root ? *cuts + *n - 1 : NULL;
        if (q->m < TILED__CUT_MIN || q->m > 1.0 - TILED__CUT_MIN) continue;
        if (prev && (prev->c != q->c || q->m - prev->m < TILED__CUT_MIN)) continue;
        (*cuts)[(*n)++] = *q;
    }
    return (int)*n;
}

/* Cuts every piece whose cell (union-find root) has cut lines into its
 * bands, in place of the pieces. cut[root]: the root's first cut in cuts
 * (sorted by root), or -1. */
static int tiled__split(tiled__grid *C, const tiled__line *cuts, size_t ncut, const int *cut, pw_err *e)
{
    tiled__pv *pv = C->pv, a[16], b[16], d[16];
    tiled__piece *pc = C->pc;
    int s, p, end = C->first[0], r = PW_OK;
    C->pv = NULL;
    C->pc = NULL;
    C->npv = C->npc = C->pvcap = C->pccap = 0;
    for (s = 0; s < C->nsrc && r == PW_OK; s++) {
        int p0 = end;
        end = C->first[s + 1];
        C->first[s] = (int)C->npc;
        for (p = p0; p < end && r == PW_OK; p++) {
            tiled__piece q = pc[p];
            int root = tiled__find(C->uf, p), n = q.nv, m, h, c0;
            memcpy(a, pv + q.v0, (size_t)n * sizeof *a);
            if (cut[root] < 0) {
                r = tiled__append(C, &q, a, n, e);
                continue;
            }
            q.ck = cuts[cut[root]].c;
            c0 = q.ck ? q.cj : q.ci;
            for (h = cut[root]; r == PW_OK; h++) { /* band h - cut[root] + 1 */
                int last = h == (int)ncut || cuts[h].root != root;
                q.sub = h - cut[root] + 1;
                q.lo = q.sub == 1 ? c0 : c0 + cuts[h - 1].m;
                q.hi = last ? c0 + 1.0 : c0 + cuts[h].m;
                m = q.sub == 1 ? n : tiled__clip(a, n, q.ck, q.lo, 1, b);
                memcpy(d, q.sub == 1 ? a : b, (size_t)m * sizeof *d);
                if (!last) m = tiled__clip(d, m, q.ck, q.hi, 0, b);
                else memcpy(b, d, (size_t)m * sizeof *b);
                if (m >= 3 && fabs(tiled__st_area(b, m)) >= 1e-12) r = tiled__append(C, &q, b, m, e);
                if (last) break;
            }
        }
    }
    C->first[C->nsrc] = (int)C->npc;
    C->st.pieces = (int)C->npc;
    pw_free(&C->a, pv);
    pw_free(&C->a, pc);
    return r;
}

/* The union-find over the pieces, joined across every edge and ray. */
static int tiled__cell_uf(tiled__grid *C, pw_err *e)
{
    int p;
    pw_free(&C->a, C->uf);
    if (!(C->uf = (int *)pw_alloc_array(&C->a, C->npc + 1, sizeof(int), "cells", e))) return PW_ERR_NOMEM;
    for (p = 0; p < (int)C->npc; p++) C->uf[p] = p;
    tiled__join_all(C);
    return PW_OK;
}

/* The cells, with every vortex's cell cut where it can be. */
static int tiled__cut_cells(tiled__grid *C, pw_err *e)
{
    tiled__line *cuts = NULL;
    size_t ncut = 0, i;
    int *cut, r;
    if ((r = tiled__cell_uf(C, e)) != PW_OK) return r;
    if (!(cut = (int *)pw_alloc_array(&C->a, C->npc + 1, sizeof(int), "cells", e))) return PW_ERR_NOMEM;
    for (i = 0; i < C->npc; i++) cut[i] = -1;
    if ((C->st.cut_vortices = tiled__vortex_cuts(C, &cuts, &ncut, e)) < 0) r = PW_ERR_NOMEM;
    for (i = ncut; i-- > 0;) cut[cuts[i].root] = (int)i;
    if (r == PW_OK && ncut && (r = tiled__split(C, cuts, ncut, cut, e)) == PW_OK) r = tiled__cell_uf(C, e);
    pw_free(&C->a, cut);
    pw_free(&C->a, cuts);
    return r;
}

/* Numbers the cells in order of their first piece and lists the shared
 * sides: a piece with a side on its cell's right (top) line meets the
 * piece of the same source triangle in the next cell. A cut line is no
 * side: the bands either side of it show the insides of their tiles. */
static int tiled__grid_sides(tiled__grid *C, pw_err *e)
{
    int p, k, r = PW_OK;
    C->cls = (int *)pw_alloc_array(&C->a, C->npc + 1, sizeof(int), "cells", e);
    if (!C->cls) return PW_ERR_NOMEM;
    for (p = 0; p < (int)C->npc; p++)
        C->cls[p] = tiled__find(C->uf, p) == p ? C->ncls++ : C->cls[tiled__find(C->uf, p)];
    for (p = 0; p < (int)C->npc && r == PW_OK; p++) {
        const tiled__piece *q = C->pc + p;
        for (k = 0; k < q->nv && r == PW_OK; k++) {
            const tiled__pv *v = C->pv + q->v0 + k, *w = C->pv + q->v0 + (k + 1) % q->nv;
            double mid[2];
            int on = v->on & w->on, side, nb;
            mid[0] = 0.5 * (v->s + w->s);
            mid[1] = 0.5 * (v->t + w->t);
            if (on & 48 || !(side = on & 2 ? 1 : (on & 4 ? 2 : 0))) continue;
            if ((nb = tiled__node(C, q->src, q->ci + (side == 1), q->cj + (side == 2), mid)) < 0) continue;
            if ((r = pw_grow(&C->a, (void **)&C->adj, &C->adjcap, C->nadj + 1, sizeof *C->adj, "cells", e)) != PW_OK)
                break;
            C->adj[C->nadj].a = C->cls[p];
            C->adj[C->nadj].b = C->cls[nb];
            C->adj[C->nadj].side = side;
            C->nadj++;
        }
    }
    return r;
}

static int tiled__adj_cmp(const void *x, const void *y)
{
    const tiled__adj *p = (const tiled__adj *)x, *q = (const tiled__adj *)y;
    if (p->a != q->a) return p->a < q->a ? -1 : 1;
    if (p->side != q->side) return p->side < q->side ? -1 : 1;
    return p->b < q->b ? -1 : p->b > q->b;
}

/* ---- boundary types: partner sides as a 2-colouring ------------------------- */

/* Root of cell side x and its parity (0: same type as the root, 1: the
 * partner type). */
static int tiled__pfind(int *uf, unsigned char *par, int x, int *parity)
{
    int r = x, q = 0, nx, px;
    while (uf[r] != r) {
        q ^= par[r];
        r = uf[r];
    }
    *parity = q;
    while (uf[x] != x) { /* compress: point every side on the path at the root */
        nx = uf[x];
        px = par[x];
        uf[x] = r;
        par[x] = (unsigned char)q;
        q ^= px;
        x = nx;
    }
    return r;
}

/* Types of the 4 sides of every cell (side k of cell c at 4c + k): every
 * shared side asks partners; each group of sides tied together draws a
 * pair k and an orientation, as AssignBoundaries does per edge. Case 1 has
 * the one self-matching type 0. */
static int tiled__side_types(tiled__grid *C, const tiled_layout *l, uint64_t seed, int *types, pw_err *e)
{
    int n4 = 4 * C->ncls, i, pa, pb, ra, rb,
        *uf = (int *)pw_alloc_array(&C->a, (size_t)n4 + 1, sizeof(int), "types", e);
    unsigned char *par = (unsigned char *)pw_calloc_array(&C->a, (size_t)n4 + 1, 1, "types", e);
    pw_rng r = pw_rng_seed(seed, 1);
    if (!uf || !par) {
        pw_free(&C->a, uf);
        pw_free(&C->a, par);
        return PW_ERR_NOMEM;
    }
    for (i = 0; i < n4; i++) uf[i] = i;
    for (i = 0; l->case_number == 2 && i < (int)C->nadj; i++) {
        ra = tiled__pfind(uf, par, 4 * C->adj[i].a + C->adj[i].side, &pa);
        rb = tiled__pfind(uf, par, 4 * C->adj[i].b + (C->adj[i].side + 2) % 4, &pb);
        if (ra == rb) continue; /* an odd cycle shows as a mismatch below */
        uf[ra > rb ? ra : rb] = ra < rb ? ra : rb;
        par[ra > rb ? ra : rb] = (unsigned char)(pa ^ pb ^ 1);
    }
    for (i = 0; i < n4; i++) types[i] = -1;
    for (i = 0; i < n4; i++) {
        int root = tiled__pfind(uf, par, i, &pa);
        if (l->case_number == 1) types[i] = 0;
        else if (root == i) {
            uint32_t x = pw_rng_u32(&r);
            types[i] = 2 * (int)(((uint64_t)(x >> 1) * (uint32_t)l->pairs) >> 31) + (int)(x & 1u);
        } else types[i] = types[root] ^ pa; /* the root comes first */
    }
    pw_free(&C->a, uf);
    pw_free(&C->a, par);
    return PW_OK;
}

static int tiled__u64_cmp(const void *x, const void *y)
{
    uint64_t p = *(const uint64_t *)x, q = *(const uint64_t *)y;
    return p < q ? -1 : p > q;
}

/* The figures of tiled_grid_stats over the shared sides (adj sorted,
 * duplicates once): mismatched types, the same tile on both sides, and
 * (tile, side, tile) triples met before. special (ncls) is set where a
 * cell covers more than 1.5 cells of the (s, t) plane or is its own
 * neighbour: a vortex's face left whole. */
static int tiled__side_stats(tiled__grid *C, int case1, const int *types, const int *tile, int *special, pw_err *e)
{
    double *area = (double *)pw_calloc_array(&C->a, (size_t)C->ncls + 1, sizeof(double), "cells", e);
    uint64_t *key = (uint64_t *)pw_alloc_array(&C->a, C->nadj + 1, sizeof(uint64_t), "cells", e);
    int i, n = 0;
    if (!area || !key) {
        pw_free(&C->a, area);
        pw_free(&C->a, key);
        return PW_ERR_NOMEM;
    }
    for (i = 0; i < (int)C->npc; i++) area[C->cls[i]] += 0.5 * fabs(tiled__st_area(C->pv + C->pc[i].v0, C->pc[i].nv));
    for (i = 0; i < C->ncls; i++) special[i] = area[i] > 1.5;
    for (i = 0; i < (int)C->nadj; i++) {
        const tiled__adj *q = C->adj + i;
        int ta = types[4 * q->a + q->side], tb = types[4 * q->b + (q->side + 2) % 4];
        if (i && q[-1].a == q->a && q[-1].side == q->side && q[-1].b == q->b) continue;
        if (q->a == q->b) special[q->a] = 1;
        C->st.grid_edges++;
        C->st.mismatched_edges += tiled__partner(case1, ta) != tb;
        C->st.same_tile_edges += tile[q->a] == tile[q->b];
        key[n++] =
            ((uint64_t)(unsigned)tile[q->a] << 33) | ((uint64_t)(unsigned)tile[q->b] << 1) | (uint64_t)(q->side == 2);
    }
    qsort(key, (size_t)n, sizeof *key, tiled__u64_cmp);
    for (i = 1; i < n; i++) C->st.repeated_edges += key[i] == key[i - 1];
    C->st.cells = C->ncls;
    for (i = 0; i < C->ncls; i++) C->st.special_cells += special[i];
    pw_free(&C->a, area);
    pw_free(&C->a, key);
    return PW_OK;
}

/* The tile of every cell: the one its four side types name, read from
 * side rot on (Fig. 23: column e0*2n+e1, row e2*2n+e3); case 1 draws one.
 * rot (tile + 2 ncls): the cell's tile turns by rot quarter turns, 0 or 2
 * at random unless fixed_start: the thesis's "further randomness" (a
 * random starting side), by half turns only so that the tile's axes stay
 * along the field. */
static void tiled__cell_tiles(const tiled__grid *C, const tiled__geom *gm, int case1, const tiled_options *o,
                              const int *types, int *tile)
{
    pw_rng r = pw_rng_seed(o->seed, 2), q = pw_rng_seed(o->seed, 3);
    int c, k, *rot = tile + 2 * C->ncls;
    for (c = 0; c < C->ncls; c++) {
        const int *t = types + 4 * c;
        k = rot[c] = o->fixed_start ? 0 : 2 * (int)(pw_rng_u32(&q) >> 31);
        if (case1) tile[c] = (int)(((uint64_t)pw_rng_u32(&r) * (uint32_t)(gm->N * gm->N)) >> 32);
        else tile[c] = (t[(k + 2) & 3] * gm->n + t[(k + 3) & 3]) * gm->N + t[k] * gm->n + t[(k + 1) & 3];
    }
}

/* ---- the mapped mesh ----------------------------------------------------------- */

/* A corner's place on the welding grid: its position in steps of h. */
static void tiled__weld_key(const float *p, const double *lo, double h, int64_t *k)
{
    int j;
    for (j = 0; j < 3; j++) k[j] = (int64_t)floor(((double)p[j] - lo[j]) / h);
}

/* Welds out's corners (one vertex each, as tiled__emit writes them) into
 * shared vertices: corners in the same step of 1e-5 of the bounding box's
 * diagonal (pieces' corners on one grid crossing, computed from different
 * triangles, differ in the last bits) become one vertex at the first one's
 * position, unless that vertex is already a corner of the same face (a
 * sliver stays a triangle); a corner whose texture coordinates are within
 * 1e-6 of another's at its vertex takes them exactly, so that exports
 * share the vertex too. Corners either side of a step stay apart, which
 * only leaves the mesh a little larger. */
static int tiled__weld(tiled__grid *C, tiled_mesh *out, pw_err *e)
{
    int nc = out->nverts, cap = 64, f, i, j, nv = 0, *slot, *next, *head;
    double lo[3], hi[3], h = 0.0;
    int64_t ki[3], kv[3];
    float *pos;
    while (cap < 2 * nc && cap < (1 << 30)) cap *= 2;
    slot = (int *)pw_alloc_array(&C->a, (size_t)cap, sizeof(int), "welding", e);
    next = (int *)pw_alloc_array(&C->a, (size_t)nc + 1, sizeof(int), "welding", e);
    head = (int *)pw_alloc_array(&C->a, (size_t)nc + 1, sizeof(int), "welding", e);
    pos = (float *)pw_alloc_array(&C->a, (size_t)nc * 3 + 1, sizeof(float), "mapped mesh", e);
    if (!slot || !next || !head || !pos) {
        pw_free(&C->a, slot);
        pw_free(&C->a, next);
        pw_free(&C->a, head);
        pw_free(&C->a, pos);
        return PW_ERR_NOMEM;
    }
    memset(slot, 0xFF, sizeof(int) * (size_t)cap);
    for (j = 0; j < 3; j++) lo[j] = hi[j] = nc ? out->positions[j] : 0.0;
    for (i = 0; i < 3 * nc; i++) {
        lo[i % 3] = out->positions[i] < lo[i % 3] ? out->positions[i] : lo[i % 3];
        hi[i % 3] = out->positions[i] > hi[i % 3] ? out->positions[i] : hi[i % 3];
    }
    for (j = 0; j < 3; j++) h += (hi[j] - lo[j]) * (hi[j] - lo[j]);
    h = sqrt(h) > 0.0 ? 1e-5 * sqrt(h) : 1.0;
    for (f = 0; f < out->nfaces; f++)
        for (i = out->face_start[f]; i < out->face_start[f + 1]; i++) {
            const float *p = out->positions + 3 * i;
            uint32_t b = 0, x;
            int v, c, k;
            tiled__weld_key(p, lo, h, ki);
            for (j = 0; j < 3; j++) b = (uint32_t)pw_hash64(b ^ (uint64_t)ki[j], (uint64_t)j);
            for (x = b & (uint32_t)(cap - 1); (v = slot[x]) >= 0; x = (x + 1) & (uint32_t)(cap - 1)) {
                tiled__weld_key(pos + 3 * v, lo, h, kv);
                if (kv[0] == ki[0] && kv[1] == ki[1] && kv[2] == ki[2]) break;
            }
            for (k = out->face_start[f]; v >= 0 && k < i; k++)
                if (out->face_verts[k] == v) v = -2; /* already this face's: a new vertex, unlisted */
            if (v < 0) {
                if (v == -1) slot[x] = nv;
                v = nv++;
                memcpy(pos + 3 * v, p, 3 * sizeof(float));
                head[v] = -1;
            }
            for (c = head[v]; c >= 0; c = next[c])
                if (fabs(out->uvs[2 * c] - out->uvs[2 * i]) < 1e-6 &&
                    fabs(out->uvs[2 * c + 1] - out->uvs[2 * i + 1]) < 1e-6) {
                    memcpy(out->uvs + 2 * i, out->uvs + 2 * c, 2 * sizeof(float));
                    break;
                }
            next[i] = head[v];
            head[v] = i;
            out->face_verts[i] = v;
        }
    pw_free(&C->a, slot);
    pw_free(&C->a, next);
    pw_free(&C->a, head);
    pw_free(&C->a, out->positions);
    out->positions = pos;
    out->nverts = nv;
    return PW_OK;
}

/* Writes the pieces as out's faces, each corner's texture coordinates in
 * its cell's tile and the type of the cell side it starts, if any; then
 * welds the corners into shared vertices. */
static int tiled__emit(tiled__grid *C, const tiled__geom *gm, const int *types, const int *tile, tiled_mesh *out,
                       pw_err *e)
{
    float *coord = (float *)pw_alloc_array(&C->a, (size_t)gm->N * 2, sizeof(float), "coordinates", e);
    int p, k, nc = (int)C->npv;
    memset(out, 0, sizeof *out);
    out->nverts = nc;
    out->nfaces = (int)C->npc;
    out->positions = (float *)pw_alloc_array(&C->a, (size_t)nc * 3, sizeof(float), "mapped mesh", e);
    out->face_start = (int *)pw_alloc_array(&C->a, C->npc + 1, sizeof(int), "mapped mesh", e);
    out->face_verts = (int *)pw_alloc_array(&C->a, (size_t)nc, sizeof(int), "mapped mesh", e);
    out->uvs = (float *)pw_alloc_array(&C->a, (size_t)nc * 2, sizeof(float), "mapped mesh", e);
    out->corner_types = (int *)pw_alloc_array(&C->a, (size_t)nc, sizeof(int), "mapped mesh", e);
    out->face_tiles = (int *)pw_alloc_array(&C->a, C->npc + 1, sizeof(int), "mapped mesh", e);
    out->allocator = tiled__allocator(&C->a);
    if (!coord || !out->positions || !out->face_start || !out->face_verts || !out->uvs || !out->corner_types ||
        !out->face_tiles) {
        pw_free(&C->a, coord);
        return PW_ERR_NOMEM;
    }
    tiled__coord_table(gm, coord);
    for (p = 0; p < (int)C->npc; p++) {
        const tiled__piece *q = C->pc + p;
        int c = C->cls[p], col = tile[c] % gm->N, row = tile[c] / gm->N;
        double u0 = coord[2 * col], du = (double)coord[2 * col + 1] - u0;
        double v0 = coord[2 * row], dv = (double)coord[2 * row + 1] - v0;
        out->face_start[p] = q->v0;
        out->face_tiles[p] = tile[c];
        for (k = 0; k < q->nv; k++) {
            const tiled__pv *v = C->pv + q->v0 + k;
            int on = v->on & C->pv[q->v0 + (k + 1) % q->nv].on, side = -1, i = q->v0 + k;
            double x[2];
            x[0] = v->s - q->ci;
            x[1] = v->t - q->cj;
            if (tile[2 * C->ncls + c]) { /* a half turn */
                x[0] = 1.0 - x[0];
                x[1] = 1.0 - x[1];
            }
            memcpy(out->positions + 3 * i, v->p, sizeof v->p);
            out->face_verts[i] = i;
            out->uvs[2 * i] = (float)(u0 + x[0] * du);
            out->uvs[2 * i + 1] = (float)(v0 + x[1] * dv);
            if (on & 48) side = -1; /* a cut line: inside the tiles */
            else if (on) side = on & 1 ? 0 : (on & 2 ? 1 : (on & 4 ? 2 : 3));
            out->corner_types[i] = side < 0 ? -1 : types[4 * c + side];
        }
    }
    out->face_start[C->npc] = nc;
    pw_free(&C->a, coord);
    return tiled__weld(C, out, e);
}

/* Everything but the output: the parameterization, the pieces, the cells,
 * their sides' types and their tiles. */
static int tiled__grid_build(tiled__grid *C, const tiled_mesh *in, const tiled_layout *l, const tiled_options *o,
                             pw_err *e)
{
    pw_progress pr = tiled__progress(o);
    tiled__geom gm = tiled__geometry(l);
    int r;
    if ((r = pw_report(&pr, 0.0f, "periodic global parameterization", e)) != PW_OK ||
        (r = tiled__parameterize(C, in, o, e)) != PW_OK ||
        (r = pw_report(&pr, 0.7f, "cutting along the grid", e)) != PW_OK || (r = tiled__sources(C, e)) != PW_OK ||
        (r = tiled__cut(C, e)) != PW_OK)
        return r;
    if ((r = tiled__cut_cells(C, e)) != PW_OK || (r = tiled__grid_sides(C, e)) != PW_OK) return r;
    qsort(C->adj, C->nadj, sizeof *C->adj, tiled__adj_cmp);
    C->types = (int *)pw_alloc_array(&C->a, (size_t)C->ncls * 4 + 1, sizeof(int), "types", e);
    C->tile = (int *)pw_calloc_array(&C->a, (size_t)C->ncls * 3 + 1, sizeof(int), "tiles", e);
    if (!C->types || !C->tile) return PW_ERR_NOMEM;
    if ((r = tiled__side_types(C, l, o->seed, C->types, e)) != PW_OK) return r;
    tiled__cell_tiles(C, &gm, l->case_number == 1, o, C->types, C->tile);
    return tiled__side_stats(C, l->case_number == 1, C->types, C->tile, C->tile + C->ncls, e);
}

/* tiled_map with opt->scale > 0. */
static int tiled__map_cells(const pw_alloc *a, const tiled_mesh *in, const tiled_layout *l, const tiled_options *o,
                            tiled_mesh *out, pw_err *e)
{
    tiled__geom gm = tiled__geometry(l);
    tiled__grid C;
    int r;
    memset(&C, 0, sizeof C);
    C.a = *a;
    if ((r = tiled__grid_build(&C, in, l, o, e)) == PW_OK &&
        (r = tiled__emit(&C, &gm, C.types, C.tile, out, e)) != PW_OK)
        tiled_mesh_free(out);
    if (r == PW_OK && o->stats) *o->stats = C.st;
    tiled__grid_free(&C);
    return r;
}
