/* quilt: graph-cut compositing of several source images ("graph-cut
 * textures", Kwatra et al. 2003), the seam machinery behind tile synthesis.
 *
 * Every pixel of a w x h grid takes its colour from one of `nlabels` source
 * images that all cover the grid. The labelling minimises the total seam
 * cost: for neighbouring pixels p, q with labels A != B, the cost is
 * |A(p) - B(p)| + |A(q) - B(q)| (Euclidean colour distance), which is small
 * where the two sources agree on both sides of the seam. That cost is a
 * metric, so alpha-expansion (Boykov, Veksler, Zabih 2001) applies: each
 * move lets every pixel either keep its label or switch to label alpha, and
 * is solved exactly by one minimum cut. Hard constraints are per-pixel masks
 * of the labels a pixel may take. The grid may wrap around in x and/or y,
 * for textures that must tile.
 *
 * Optionally the cost also follows the sources' structure: with a motif
 * map (1 inside a motif, 0 on its outline or between motifs, from
 * pw_quilt_motif_map) a seam between p and q also pays motif_weight for
 * each of the four source pixels A(p), B(p), A(q), B(q) that lies inside a
 * motif. Seams then run where both sources show outlines or mortar and
 * keep pebbles, bricks and leaves whole (issue 18; the colour term alone
 * happily cuts a pebble in two against a pebble of a similar colour). The
 * extra term is a sum of per-label terms, so the cost stays a metric. */
#ifndef PW__QUILT_V1
#define PW__QUILT_V1

#include "base.h"
#include "graphcut.h"
#include "image.h"

typedef struct pw_quilt {
    int w, h, c;             /* grid size and colour channels */
    int nlabels;             /* number of sources, at most 32 */
    const float *src;        /* nlabels*w*h*c: source l's colour at pixel i is src + (l*w*h + i)*c */
    int *label;              /* w*h, in/out: the labelling (initial labels must be allowed) */
    const uint32_t *allowed; /* w*h bit masks (bit l: label l allowed) or NULL: all */
    int wrap_x, wrap_y;      /* non-zero: the grid is periodic in that direction */
    const float *motif;      /* NULL or nlabels*w*h: source l's motif value at pixel i is motif[l*w*h + i] */
    float motif_weight;      /* seam cost per source pixel inside a motif */
} pw_quilt;

/* |A(i) - B(i)|: distance between the colours of two labels at pixel i. */
PW__DEF float pw__quilt_diff(const pw_quilt *q, int la, int lb, int i)
{
    const float *a = q->src + ((size_t)la * q->w * q->h + i) * q->c;
    const float *b = q->src + ((size_t)lb * q->w * q->h + i) * q->c;
    float s = 0.0f;
    int k;
    if (la == lb) return 0.0f;
    for (k = 0; k < q->c; k++) s += (a[k] - b[k]) * (a[k] - b[k]);
    return sqrtf(s);
}

/* How far inside motifs sources la and lb are at pixel i (0..2). */
PW__DEF float pw__quilt_motif(const pw_quilt *q, int la, int lb, int i)
{
    size_t n = (size_t)q->w * q->h;
    return q->motif ? q->motif[la * n + i] + q->motif[lb * n + i] : 0.0f;
}

/* Seam cost between neighbours i, j labelled la, lb. */
PW__DEF float pw_quilt_pair_cost(const pw_quilt *q, int i, int j, int la, int lb)
{
    if (la == lb) return 0.0f;
    return pw__quilt_diff(q, la, lb, i) + pw__quilt_diff(q, la, lb, j) +
           (q->motif ? q->motif_weight * (pw__quilt_motif(q, la, lb, i) + pw__quilt_motif(q, la, lb, j)) : 0.0f);
}

/* The right and upper neighbours of pixel i (-1 where the grid ends). */
PW__DEF void pw__quilt_neighbours(const pw_quilt *q, int i, int nb[2])
{
    int x = i % q->w, y = i / q->w;
    nb[0] = x + 1 < q->w ? i + 1 : (q->wrap_x && q->w > 2 ? i + 1 - q->w : -1);
    nb[1] = y + 1 < q->h ? i + q->w : (q->wrap_y && q->h > 2 ? x : -1);
}

/* Seam statistics of a labelling, the measure of cut motifs: `pairs`
 * counts neighbour pairs (p, q) whose labels A, B differ (seam pairs),
 * `cut` those where, at p or at q, the seam passes inside a motif of A or
 * of B (motif value above 1/2; without a motif map: anywhere) and the two
 * sources differ by more than tau, |A(x) - B(x)| > tau. There the seam
 * chops a pebble, brick or leaf off, or gives its outline a kink. Where
 * both sources show outlines or mortar, or agree, it cannot be seen. */
typedef struct pw_seam_stats {
    long pairs, cut;
} pw_seam_stats;

/* 1 if pixel i of source l lies inside a motif with its 4 neighbours: a
 * pixel or more away from the motif's outline. */
PW__DEF int pw__quilt_deep(const pw_quilt *q, int l, int i)
{
    const float *m = q->motif + (size_t)l * q->w * q->h;
    int x = i % q->w, y = i / q->w;
    return m[i] > 0.5f && (x == 0 || m[i - 1] > 0.5f) && (x == q->w - 1 || m[i + 1] > 0.5f) &&
           (y == 0 || m[i - q->w] > 0.5f) && (y == q->h - 1 || m[i + q->w] > 0.5f);
}

PW__DEF int pw__quilt_cuts_at(const pw_quilt *q, int la, int lb, int i, float tau)
{
    int inside = !q->motif || pw__quilt_deep(q, la, i) || pw__quilt_deep(q, lb, i);
    return inside && pw__quilt_diff(q, la, lb, i) > tau;
}

PW__DEF void pw_quilt_seam_stats(const pw_quilt *q, float tau, pw_seam_stats *st)
{
    int i, k, n = q->w * q->h, nb[2];
    for (i = 0; i < n; i++) {
        pw__quilt_neighbours(q, i, nb);
        for (k = 0; k < 2; k++) {
            int j = nb[k], la = q->label[i], lb = j >= 0 ? q->label[j] : la;
            if (la == lb) continue;
            st->pairs++;
            if (pw__quilt_cuts_at(q, la, lb, i, tau) || pw__quilt_cuts_at(q, la, lb, j, tau)) st->cut++;
        }
    }
}

/* Box blur of a periodic image, 3 taps, `passes` times along x and y. */
PW__DEF void pw__quilt_blur(float *px, float *tmp, int w, int h, int c, int passes)
{
    int p, x, y, k, d;
    for (p = 0; p < 2 * passes; p++) {
        for (y = 0; y < h; y++)
            for (x = 0; x < w; x++)
                for (k = 0; k < c; k++) {
                    float v = 0.0f;
                    for (d = -1; d <= 1; d++)
                        v += p & 1 ? px[((size_t)((y + d + h) % h) * w + x) * c + k]
                                   : px[((size_t)y * w + (x + d + w) % w) * c + k];
                    tmp[((size_t)y * w + x) * c + k] = v / 3.0f;
                }
        memcpy(px, tmp, sizeof(float) * (size_t)w * h * c);
    }
}

/* Gradient magnitude (central differences, colour distance) of a periodic image. */
PW__DEF void pw__quilt_gradient(const float *px, int w, int h, int c, float *g)
{
    int x, y, k;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            double gx = 0.0, gy = 0.0;
            for (k = 0; k < c; k++) {
                float a = px[((size_t)y * w + (x + 1) % w) * c + k] - px[((size_t)y * w + (x + w - 1) % w) * c + k];
                float b = px[((size_t)((y + 1) % h) * w + x) * c + k] - px[((size_t)((y + h - 1) % h) * w + x) * c + k];
                gx += a * a;
                gy += b * b;
            }
            g[(size_t)y * w + x] = 0.5f * (float)sqrt(gx + gy);
        }
}

PW__DEF int pw__quilt_cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return x < y ? -1 : x > y;
}

/* The components of a w x h motif map m on the torus: comp (w*h) holds the
 * stamp of the component each pixel was flooded with (-1: none yet), ux
 * and uy its unwrapped position, stack the pixels to visit. */
typedef struct pw__quilt_flood {
    const float *m;
    int w, h;
    int *comp, *ux, *uy, *stack;
} pw__quilt_flood;

/* Floods the component of motif pixels (value 1) through `seed` on the
 * torus, stamping it with seed's index. Returns 1 if the component wraps
 * around the torus (reaches a pixel again at another unwrapped position):
 * a network such as mortar or the dark gaps between leaves, the ground, not
 * a motif. *size gets its pixel count. */
PW__DEF int pw__quilt_wraps(const pw__quilt_flood *F, int seed, size_t *size)
{
    static const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
    const float *m = F->m;
    int w = F->w, h = F->h, stamp = seed, *comp = F->comp, *ux = F->ux, *uy = F->uy, *stack = F->stack;
    int top = 0, wraps = 0, k;
    *size = 0;
    comp[seed] = stamp;
    ux[seed] = seed % w;
    uy[seed] = seed / w;
    stack[top++] = seed;
    while (top > 0) {
        int i = stack[--top];
        (*size)++;
        for (k = 0; k < 4; k++) {
            int u = ux[i] + dx[k], v = uy[i] + dy[k];
            int j = ((v % h + h) % h) * w + (u % w + w) % w;
            if (m[j] <= 0.5f) continue;
            if (comp[j] == stamp) {
                if (ux[j] != u || uy[j] != v) wraps = 1;
                continue;
            }
            comp[j] = stamp;
            ux[j] = u;
            uy[j] = v;
            stack[top++] = j;
        }
    }
    return wraps;
}

/* Clears the motif value of every component that is ground, not a motif:
 * one that wraps around the torus or covers a quarter of the image or
 * more (mortar, the dark gaps between leaves: a network around motifs,
 * which outlines that nearly touch may split), or one under 1/200 of the
 * image (grain, a pocket of mortar). */
PW__DEF int pw__quilt_clear_ground(const pw_alloc *a, float *m, int w, int h, pw_err *e)
{
    size_t n = (size_t)w * h, i, size;
    int *buf = (int *)pw_alloc_array(a, n * 4, sizeof(int), "motif components", e);
    int *comp = buf;
    pw__quilt_flood F;
    if (!buf) return PW_ERR_NOMEM;
    F.m = m;
    F.w = w;
    F.h = h;
    F.comp = comp;
    F.ux = buf + n;
    F.uy = buf + 2 * n;
    F.stack = buf + 3 * n;
    for (i = 0; i < n; i++) comp[i] = -1;
    for (i = 0; i < n; i++)
        if (m[i] > 0.5f && comp[i] < 0 && (pw__quilt_wraps(&F, (int)i, &size) || size * 4 >= n || size * 200 < n)) {
            size_t j;
            for (j = 0; j < n; j++)
                if (comp[j] == (int)i) m[j] = 0.0f;
        }
    pw_free(a, buf);
    return PW_OK;
}

/* The motif map of a periodic image (w, h >= 3): 1 inside motifs, 0 on
 * their outlines (within a pixel of a strong edge) and on the ground.
 * Strong edges are the top 30% of gradient magnitudes after a blur that
 * removes grain (two 3-tap box passes), so outlines of pebbles, bricks and
 * leaves count and the speckle inside them does not. What the outlines
 * enclose is a motif; what stays connected around the whole (periodic)
 * image is the ground between motifs (mortar, gaps). *edge gets the
 * threshold (a colour change per pixel). motif holds src's w*h pixels. */
PW__DEF int pw_quilt_motif_map(const pw_alloc *a, const pw_image *src, float *motif, float *edge, pw_err *e)
{
    const float *px = src->px;
    int w = src->w, h = src->h, c = src->c;
    size_t n = (size_t)w * h;
    float *blur = (float *)pw_alloc_array(a, n * 2 * c, sizeof(float), "motif map", e);
    float *g = (float *)pw_alloc_array(a, n * 2, sizeof(float), "motif gradients", e);
    int x, y, dx, dy;
    float te;
    if (!blur || !g) {
        pw_free(a, blur);
        pw_free(a, g);
        return PW_ERR_NOMEM;
    }
    memcpy(blur, px, sizeof(float) * n * c);
    pw__quilt_blur(blur, blur + n * c, w, h, c, 2);
    pw__quilt_gradient(blur, w, h, c, g);
    memcpy(g + n, g, sizeof(float) * n);
    qsort(g + n, n, sizeof(float), pw__quilt_cmp_float);
    te = g[n + (size_t)(0.7 * (double)(n - 1))];
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            float m = 1.0f;
            for (dy = -1; dy <= 1; dy++)
                for (dx = -1; dx <= 1; dx++)
                    if (g[(size_t)((y + dy + h) % h) * w + (x + dx + w) % w] > te) m = 0.0f;
            motif[(size_t)y * w + x] = m;
        }
    if (edge) *edge = te;
    pw_free(a, blur);
    pw_free(a, g);
    return pw__quilt_clear_ground(a, motif, w, h, e);
}

/* One alpha-expansion move being built: the quilt, the label alpha, the
 * graph g, node[i] (w*h) the graph variable of pixel i or -1 for a pixel
 * that cannot switch, and u0, u1 (per variable) the unary costs of keeping
 * and of switching. The arrays are caller scratch. */
typedef struct pw__quilt_move {
    const pw_quilt *q;
    int alpha;
    pw_graph *g;
    int *node;
    double *u0, *u1;
} pw__quilt_move;

/* Adds the expansion-move energy of one neighbour pair to the graph.
 * Variable x = 1 means "switch to alpha"; node[i] < 0 marks a constant. */
PW__DEF int pw__quilt_add_pair(const pw__quilt_move *M, int i, int j, pw_err *e)
{
    const pw_quilt *q = M->q;
    const int *node = M->node;
    double *u0 = M->u0, *u1 = M->u1;
    int alpha = M->alpha;
    int li = q->label[i], lj = q->label[j], vi = node[i], vj = node[j];
    if (vi >= 0 && vj >= 0) {
        /* E00 = V(li,lj), E01 = V(li,a), E10 = V(a,lj), E11 = 0 */
        double a00 = pw_quilt_pair_cost(q, i, j, li, lj);
        double a01 = pw_quilt_pair_cost(q, i, j, li, alpha);
        double a10 = pw_quilt_pair_cost(q, i, j, alpha, lj);
        double w = a01 + a10 - a00; /* >= 0: the cost is a metric */
        u0[vi] += a00;              /* E = a00 + (a10-a00) xi - a10 xj + w [xi=0,xj=1] */
        u1[vi] += a10;
        u0[vj] += a10;
        return pw_graph_add_edge(M->g, vi, vj, w > 0.0 ? (float)w : 0.0f, 0.0f, e);
    }
    if (vi >= 0) {
        u0[vi] += pw_quilt_pair_cost(q, i, j, li, lj);
        u1[vi] += pw_quilt_pair_cost(q, i, j, alpha, lj);
    } else if (vj >= 0) {
        u0[vj] += pw_quilt_pair_cost(q, i, j, li, lj);
        u1[vj] += pw_quilt_pair_cost(q, i, j, li, alpha);
    }
    return PW_OK;
}

/* Normalises the pairwise edges' unary parts: u0 (cost when keeping) and
 * u1 (cost when switching) become t-links, both non-negative. */
PW__DEF void pw__quilt_tlinks(pw_graph *g, const double *u0, const double *u1, int nvar)
{
    int v;
    for (v = 0; v < nvar; v++) {
        double m = u0[v] < u1[v] ? u0[v] : u1[v];
        /* source side = keep: cutting the sink link pays u0, the source link u1 */
        pw_graph_add_tweights(g, v, (float)(u1[v] - m), (float)(u0[v] - m));
    }
}

/* One alpha-expansion move (M: its label and scratch of w*h entries, the
 * graph made here). Returns the number of pixels that switched in
 * *changed. */
PW__DEF int pw__quilt_expand_one(pw__quilt_move *M, int *changed, const pw_alloc *a, pw_err *e)
{
    const pw_quilt *q = M->q;
    int alpha = M->alpha, *node = M->node;
    double *u0 = M->u0, *u1 = M->u1;
    pw_graph g;
    int i, k, n = q->w * q->h, nvar = 0, nb[2], r;
    double flow;
    *changed = 0;
    for (i = 0; i < n; i++)
        node[i] = q->label[i] == alpha || (q->allowed && !(q->allowed[i] >> alpha & 1u)) ? -1 : nvar++;
    if (nvar == 0) return PW_OK;
    for (i = 0; i < nvar; i++) u0[i] = u1[i] = 0.0;
    if ((r = pw_graph_init(&g, a, nvar, 2 * nvar, e)) != PW_OK) return r;
    M->g = &g;
    for (i = 0; i < n && r == PW_OK; i++) {
        pw__quilt_neighbours(q, i, nb);
        for (k = 0; k < 2 && r == PW_OK; k++)
            if (nb[k] >= 0) r = pw__quilt_add_pair(M, i, nb[k], e);
    }
    if (r == PW_OK) {
        pw__quilt_tlinks(&g, u0, u1, nvar);
        r = pw_graph_maxflow(&g, &flow, e);
    }
    for (i = 0; i < n && r == PW_OK; i++)
        if (node[i] >= 0 && !pw_graph_in_source(&g, node[i])) {
            q->label[i] = alpha;
            (*changed)++;
        }
    pw_graph_free(&g);
    M->g = NULL;
    return r;
}

/* Alpha-expansion over every label, `cycles` times (or until no pixel
 * changes). Deterministic: labels are visited in increasing order. */
PW__DEF int pw_quilt_optimize(const pw_alloc *a, pw_quilt *q, int cycles, pw_err *e)
{
    int n = q->w * q->h, c, l, r = PW_OK, changed, total;
    int *node = (int *)pw_alloc_array(a, (size_t)n, sizeof(int), "quilt nodes", e);
    double *u = (double *)pw_alloc_array(a, (size_t)n * 2, sizeof(double), "quilt costs", e);
    pw__quilt_move M;
    if (!node || !u) {
        pw_free(a, node);
        pw_free(a, u);
        return PW_ERR_NOMEM;
    }
    for (c = 0; c < cycles && r == PW_OK; c++) {
        total = 0;
        for (l = 0; l < q->nlabels && r == PW_OK; l++) {
            M.q = q;
            M.alpha = l;
            M.g = NULL;
            M.node = node;
            M.u0 = u;
            M.u1 = u + n;
            r = pw__quilt_expand_one(&M, &changed, a, e);
            total += changed;
        }
        if (total == 0) break;
    }
    pw_free(a, node);
    pw_free(a, u);
    return r;
}

/* Writes the composite: out[i*c..] = colour of pixel i's label. */
PW__DEF void pw_quilt_compose(const pw_quilt *q, float *out)
{
    int i, n = q->w * q->h;
    for (i = 0; i < n; i++)
        memcpy(out + (size_t)i * q->c, q->src + ((size_t)q->label[i] * n + i) * q->c, sizeof(float) * (size_t)q->c);
}

/* Labels of pw_quilt_make_tileable: the image itself and two copies of it
 * shifted by half and by a quarter of its size. Each source is
 * discontinuous only along the lines where its shifted lookup wraps; a
 * source is forbidden on both sides of its own lines, so every seam left in
 * the result is a cut between two sources that were continuous there. */
PW__DEF int pw__tileable_shift(int l, int n) { return l == 0 ? 0 : (l == 1 ? n / 2 : n / 4); }

PW__DEF int pw__tileable_near_wrap(int x, int n, int shift)
{
    int x0 = (n - shift) % n; /* first column whose shifted lookup wrapped */
    return x == x0 || x == (x0 + n - 1) % n;
}

/* Makes an image tile seamlessly (periodic in x and y) by graph-cut
 * compositing of it with shifted copies of itself (see above), on raw
 * samples: in and out hold w*h pixels of c >= 1 channels (any number, so
 * that a feature mask can travel as an extra channel and be cut with the
 * colours). Images under 8 pixels wide or high are copied. */
PW__DEF int pw_quilt_make_tileable_px(const pw_alloc *a, const pw_image *in, float *out, pw_err *e)
{
    const float *px = in->px;
    int w = in->w, h = in->h, c = in->c;
    int x, y, l, r;
    size_t n = (size_t)w * h, i;
    float *src;
    uint32_t *allowed;
    int *label;
    pw_quilt q;
    if (w < 8 || h < 8) {
        memcpy(out, px, sizeof(float) * n * c);
        return PW_OK;
    }
    src = (float *)pw_alloc_array(a, n * 3 * c, sizeof(float), "tileable sources", e);
    allowed = (uint32_t *)pw_alloc_array(a, n, sizeof(uint32_t), "tileable constraints", e);
    label = (int *)pw_alloc_array(a, n, sizeof(int), "tileable labels", e);
    if (!src || !allowed || !label) {
        r = PW_ERR_NOMEM;
        goto done;
    }
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            i = (size_t)y * w + x;
            allowed[i] = 0;
            for (l = 0; l < 3; l++) {
                int sx = pw__tileable_shift(l, w), sy = pw__tileable_shift(l, h);
                size_t j = (size_t)((y + sy) % h) * w + (size_t)((x + sx) % w);
                memcpy(src + (l * n + i) * c, px + j * c, sizeof(float) * c);
                if (!pw__tileable_near_wrap(x, w, sx) && !pw__tileable_near_wrap(y, h, sy)) allowed[i] |= 1u << l;
            }
            label[i] = allowed[i] & 1u ? 0 : (allowed[i] & 2u ? 1 : 2);
        }
    q.w = w;
    q.h = h;
    q.c = c;
    q.nlabels = 3;
    q.src = src;
    q.label = label;
    q.allowed = allowed;
    q.wrap_x = q.wrap_y = 1;
    q.motif = NULL;
    q.motif_weight = 0.0f;
    r = pw_quilt_optimize(a, &q, 3, e);
    if (r == PW_OK) pw_quilt_compose(&q, out);
done:
    pw_free(a, src);
    pw_free(a, allowed);
    pw_free(a, label);
    return r;
}

/* The same for an image: out is a new image of the input's size. */
PW__DEF int pw_quilt_make_tileable(const pw_alloc *a, const pw_image *in, pw_image *out, pw_err *e)
{
    int r;
    if ((r = pw_image_alloc(a, out, in->w, in->h, in->c, e)) != PW_OK) return r;
    out->bits = in->bits;
    r = pw_quilt_make_tileable_px(a, in, out->px, e);
    if (r != PW_OK) pw_image_free(a, out);
    return r;
}

#endif /* PW__QUILT_V1 */
