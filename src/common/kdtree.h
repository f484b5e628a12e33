/* kdtree: nearest-neighbour search among n points of dimension d, with an
 * additive cost per point.
 *
 * The tree is built once over the points (median splits along the widest
 * side of each cell, buckets of at most PW_KD_BUCKET points, stored
 * dimension by dimension so that the distances to a whole bucket are
 * computed in one loop the compiler vectorises) and answers
 *     argmin_i  |q - p_i|^2 + pen_i
 * where pen_i >= 0 is a per-point penalty the caller may change at any time
 * (pw_kdtree_set_penalty, O(leaf + depth)): texture synthesis uses it to
 * charge for input pixels that are already used. Every node keeps the
 * smallest penalty below it, so the search prunes a cell when the distance
 * to the cell plus that penalty cannot beat the best cost found, with the
 * incremental cell distance of Arya and Mount (the distance to a cell is
 * updated one coordinate at a time while descending). With eps > 0 the
 * search is approximate in the usual sense: cells are pruned when
 * (1 + eps)^2 times their distance (plus their penalty) reaches the best
 * cost, so the answer costs at most (1 + eps)^2 times the optimum distance
 * plus penalty. A search may start from a known candidate and cost (the
 * current match): only strictly better points replace it, so ties keep it.
 * Building and searching are deterministic (no randomness, no libm).
 *
 *   pw_kdtree_build, pw_kdtree_free, pw_kdtree_nearest, pw_kdtree_cost,
 *   pw_kdtree_set_penalty */
#ifndef PW__KDTREE_V1
#define PW__KDTREE_V1

#include "base.h"

#define PW_KD_BUCKET 8 /* points per leaf, at most */

typedef struct pw__kdnode {
    int lo, hi;      /* points lo..hi-1 (tree order) */
    int dim;         /* split dimension; -1 for a leaf */
    float split;     /* left: coordinate < split (or equal, by position) */
    int left, right; /* children; for a leaf, left is its bucket */
    int parent;
    float minpen; /* smallest penalty of the points below */
} pw__kdnode;

typedef struct pw_kdtree {
    int n, d, nnodes, nbuckets;
    float *pts;    /* n*d, in tree order */
    float *bucket; /* per bucket (d+1)*PW_KD_BUCKET floats: coordinate k of slot j
                          at [k*B + j], penalty at [d*B + j]; empty slots cost FLT_MAX */
    int *idx;      /* n: caller's index of tree point i */
    int *pos;      /* n: tree position of caller's point i */
    int *leaf_of;  /* n: leaf node of tree point i */
    pw__kdnode *node;
} pw_kdtree;

PW__DEF void pw_kdtree_free(const pw_alloc *a, pw_kdtree *t)
{
    if (!t) return;
    pw_free(a, t->pts);
    pw_free(a, t->bucket);
    pw_free(a, t->idx);
    pw_free(a, t->pos);
    pw_free(a, t->leaf_of);
    pw_free(a, t->node);
    memset(t, 0, sizeof *t);
}

/* Swaps tree points i and j (coordinates and caller indices). */
PW__DEF void pw__kd_swap(pw_kdtree *t, int i, int j)
{
    int k, ti = t->idx[i];
    float *a = t->pts + (size_t)i * t->d, *b = t->pts + (size_t)j * t->d;
    for (k = 0; k < t->d; k++) {
        float x = a[k];
        a[k] = b[k];
        b[k] = x;
    }
    t->idx[i] = t->idx[j];
    t->idx[j] = ti;
}

/* Quickselect: points lo..hi-1 reordered so that the one at position k has
 * the k-th coordinate `dim`, with no larger one before it and no smaller
 * one after it. Three-way partitions (median of three pivots,
 * deterministic) keep runs of equal coordinates, common in textures with
 * flat areas, linear. */
PW__DEF void pw__kd_select(pw_kdtree *t, int lo, int hi, int k, int dim)
{
    const int d = t->d;
    while (hi - lo > 1) {
        int mid = lo + (hi - lo) / 2, lt = lo, i = lo, gt = hi;
        float a = t->pts[(size_t)lo * d + dim], b = t->pts[(size_t)mid * d + dim];
        float c = t->pts[(size_t)(hi - 1) * d + dim];
        float piv = (a < b) == (b < c) ? b : ((b < a) == (a < c) ? a : c);
        while (i < gt) { /* [lo,lt) < piv, [lt,i) == piv, [gt,hi) > piv */
            float x = t->pts[(size_t)i * d + dim];
            if (x < piv) pw__kd_swap(t, lt++, i++);
            else if (x > piv) pw__kd_swap(t, i, --gt);
            else i++;
        }
        if (k < lt) hi = lt;
        else if (k >= gt) lo = gt;
        else return;
    }
}

/* The dimension along which points lo..hi-1 spread most. */
PW__DEF int pw__kd_widest(const pw_kdtree *t, int lo, int hi)
{
    int k, i, best = 0;
    float wbest = -1.0f;
    for (k = 0; k < t->d; k++) {
        float mn = t->pts[(size_t)lo * t->d + k], mx = mn;
        for (i = lo + 1; i < hi; i++) {
            float x = t->pts[(size_t)i * t->d + k];
            mn = x < mn ? x : mn;
            mx = x > mx ? x : mx;
        }
        if (mx - mn > wbest) {
            wbest = mx - mn;
            best = k;
        }
    }
    return best;
}

/* Splits node ni (and below) until buckets hold at most PW_KD_BUCKET
 * points; leaves are numbered as buckets in order. */
PW__DEF void pw__kd_split(pw_kdtree *t, int ni)
{
    pw__kdnode *nd = &t->node[ni];
    int lo = nd->lo, hi = nd->hi, mid = lo + (hi - lo) / 2, dim, i, c[2];
    nd->minpen = 0.0f;
    if (hi - lo <= PW_KD_BUCKET) {
        for (i = lo; i < hi; i++) t->leaf_of[i] = ni;
        nd->left = t->nbuckets++;
        return;
    }
    dim = pw__kd_widest(t, lo, hi);
    pw__kd_select(t, lo, hi, mid, dim);
    nd->dim = dim;
    nd->split = t->pts[(size_t)mid * t->d + dim];
    for (i = 0; i < 2; i++) {
        pw__kdnode *ch = &t->node[c[i] = t->nnodes++];
        ch->lo = i ? mid : lo;
        ch->hi = i ? hi : mid;
        ch->dim = -1;
        ch->parent = ni;
        ch->left = ch->right = -1;
    }
    t->node[ni].left = c[0];
    t->node[ni].right = c[1];
    pw__kd_split(t, c[0]);
    pw__kd_split(t, c[1]);
}

/* Fills the buckets from the points in tree order (penalties 0). */
PW__DEF void pw__kd_fill(pw_kdtree *t)
{
    const int B = PW_KD_BUCKET, d = t->d;
    int ni, i, k;
    for (ni = 0; ni < t->nnodes; ni++) {
        const pw__kdnode *nd = &t->node[ni];
        float *b;
        if (nd->dim >= 0) continue;
        b = t->bucket + (size_t)nd->left * (d + 1) * B;
        for (i = 0; i < B; i++) {
            int p = nd->lo + i;
            for (k = 0; k < d; k++) b[k * B + i] = p < nd->hi ? t->pts[(size_t)p * d + k] : 0.0f;
            b[d * B + i] = p < nd->hi ? 0.0f : FLT_MAX;
        }
    }
}

/* Builds the tree over pts (n*d floats, copied); penalties start at 0. */
PW__DEF int pw_kdtree_build(const pw_alloc *a, pw_kdtree *t, const float *pts, int n, int d, pw_err *e)
{
    size_t maxnodes = 4 * ((size_t)n / PW_KD_BUCKET + 1);
    int i;
    memset(t, 0, sizeof *t);
    if (n < 1 || d < 1) return pw_fail(e, PW_ERR_INVALID, "kd-tree: %d points of dimension %d", n, d);
    t->n = n;
    t->d = d;
    t->pts = (float *)pw_alloc_array(a, (size_t)n * d, sizeof(float), "kd-tree points", e);
    t->idx = (int *)pw_alloc_array(a, (size_t)n, sizeof(int), "kd-tree indices", e);
    t->pos = (int *)pw_alloc_array(a, (size_t)n, sizeof(int), "kd-tree positions", e);
    t->leaf_of = (int *)pw_alloc_array(a, (size_t)n, sizeof(int), "kd-tree leaves", e);
    t->node = (pw__kdnode *)pw_alloc_array(a, maxnodes, sizeof(pw__kdnode), "kd-tree nodes", e);
    t->bucket = (float *)pw_alloc_array(a, maxnodes * (d + 1), PW_KD_BUCKET * sizeof(float), "kd-tree buckets", e);
    if (!t->pts || !t->idx || !t->pos || !t->leaf_of || !t->node || !t->bucket) {
        pw_kdtree_free(a, t);
        return PW_ERR_NOMEM;
    }
    memcpy(t->pts, pts, sizeof(float) * (size_t)n * d);
    for (i = 0; i < n; i++) t->idx[i] = i;
    t->nnodes = 1;
    t->node[0].lo = 0;
    t->node[0].hi = n;
    t->node[0].dim = -1;
    t->node[0].parent = t->node[0].left = t->node[0].right = -1;
    pw__kd_split(t, 0);
    for (i = 0; i < n; i++) t->pos[t->idx[i]] = i;
    pw__kd_fill(t);
    return PW_OK;
}

/* The penalty slot of tree point p. */
PW__DEF float *pw__kd_pen(const pw_kdtree *t, int p)
{
    const pw__kdnode *nd = &t->node[t->leaf_of[p]];
    return t->bucket + ((size_t)nd->left * (t->d + 1) + t->d) * PW_KD_BUCKET + (p - nd->lo);
}

/* |q - p|^2 + pen of caller's point i. */
PW__DEF float pw_kdtree_cost(const pw_kdtree *t, const float *q, int i)
{
    int p = t->pos[i], k;
    const float *x = t->pts + (size_t)p * t->d;
    float s = *pw__kd_pen(t, p);
    for (k = 0; k < t->d; k++) s += (q[k] - x[k]) * (q[k] - x[k]);
    return s;
}

/* Sets the penalty of caller's point i and updates the node minima. */
PW__DEF void pw_kdtree_set_penalty(pw_kdtree *t, int i, float pen)
{
    int p = t->pos[i], k;
    pw__kdnode *nd = &t->node[t->leaf_of[p]];
    float m = pen, *slots = pw__kd_pen(t, p) - (p - nd->lo);
    slots[p - nd->lo] = pen;
    for (k = 0; k < nd->hi - nd->lo; k++) m = slots[k] < m ? slots[k] : m;
    nd->minpen = m;
    while (nd->parent >= 0) {
        pw__kdnode *up = &t->node[nd->parent];
        float l = t->node[up->left].minpen, r = t->node[up->right].minpen;
        m = l < r ? l : r;
        if (m == up->minpen) break;
        up->minpen = m;
        nd = up;
    }
}

typedef struct pw__kdsearch {
    const float *q;
    float *off;  /* per-dimension offset of q from the current cell */
    float scale; /* (1 + eps)^2 */
    float best;
    int bi;     /* tree position of the best point, -1 none */
    int budget; /* buckets that may still be visited (negative: no limit) */
} pw__kdsearch;

/* Costs of a whole bucket in one loop over its slots. */
PW__DEF void pw__kd_leaf(const pw_kdtree *t, const pw__kdnode *nd, pw__kdsearch *s)
{
    const int B = PW_KD_BUCKET, d = t->d;
    const float *b = t->bucket + (size_t)nd->left * (d + 1) * B;
    float c[PW_KD_BUCKET];
    int j, k;
    for (j = 0; j < B; j++) c[j] = b[d * B + j];
    for (k = 0; k < d; k++) {
        const float qk = s->q[k], *x = b + k * B;
        for (j = 0; j < B; j++) c[j] += (qk - x[j]) * (qk - x[j]);
    }
    for (j = 0; j < B; j++)
        if (c[j] < s->best) {
            s->best = c[j];
            s->bi = nd->lo + j;
        }
}

/* Searches below node ni, whose cell is at squared distance rd from q and
 * not pruned: the near child by recursion, then the far one in the same
 * frame (its offset undone on the way out); children are tested before
 * they are entered. */
PW__DEF void pw__kd_search(const pw_kdtree *t, int ni, float rd, pw__kdsearch *s)
{
    int undo_dim[64], nu = 0;
    float undo_off[64];
    for (;;) {
        const pw__kdnode *nd = &t->node[ni];
        float diff, old, rfar;
        int near, far;
        if (nd->dim < 0) {
            if (s->budget != 0) {
                pw__kd_leaf(t, nd, s);
                s->budget--;
            }
            break;
        }
        diff = s->q[nd->dim] - nd->split;
        near = diff < 0.0f ? nd->left : nd->right;
        far = diff < 0.0f ? nd->right : nd->left;
        if (rd * s->scale + t->node[near].minpen < s->best) pw__kd_search(t, near, rd, s);
        old = s->off[nd->dim];
        rfar = rd - old * old + diff * diff;
        if (rfar * s->scale + t->node[far].minpen >= s->best || s->budget == 0) break;
        if (nu == 64) { /* deeper than any tree of fewer than 2^60 points */
            s->off[nd->dim] = diff;
            pw__kd_search(t, far, rfar, s);
            s->off[nd->dim] = old;
            break;
        }
        undo_dim[nu] = nd->dim;
        undo_off[nu++] = old;
        s->off[nd->dim] = diff;
        rd = rfar;
        ni = far;
    }
    while (nu-- > 0) s->off[undo_dim[nu]] = undo_off[nu];
}

/* A nearest-point query: the point q (d floats), the approximation eps (a
 * cell is skipped unless (1 + eps)^2 times its distance beats the best
 * cost), at most `buckets` buckets scanned (negative: no limit), in the
 * depth-first, nearest-cell-first order of the search, as ANN's bound on
 * the points visited: the cost of a query is then bounded where many points
 * are nearly equidistant (smooth images); the candidate to beat, `start`
 * (caller's index, or -1) of cost start_cost; off: scratch of d floats. */
typedef struct pw_kdquery {
    const float *q;
    float eps;
    int buckets;
    int start;
    float start_cost;
    float *off;
} pw_kdquery;

/* The caller's index of the point minimising |q - p|^2 + pen for query qy;
 * its cost in *cost (may be NULL). */
PW__DEF int pw_kdtree_nearest(const pw_kdtree *t, const pw_kdquery *qy, float *cost)
{
    pw__kdsearch s;
    int k, start = qy->start;
    for (k = 0; k < t->d; k++) qy->off[k] = 0.0f;
    s.q = qy->q;
    s.off = qy->off;
    s.scale = (1.0f + qy->eps) * (1.0f + qy->eps);
    s.best = start >= 0 ? qy->start_cost : FLT_MAX;
    s.bi = start >= 0 ? t->pos[start] : -1;
    s.budget = qy->buckets;
    if (t->node[0].minpen < s.best) pw__kd_search(t, 0, 0.0f, &s);
    if (cost) *cost = s.best;
    return s.bi >= 0 ? t->idx[s.bi] : -1;
}

#endif /* PW__KDTREE_V1 */
