/* synth.c: §1.2 constrained tile synthesis, and the whole of §1: keys ->
 * masks -> morphed masks -> one synthesis per layer from each end of every
 * morph -> blended material-space tile.
 *
 * A synthesis works on indirection maps (§1.2): every output texel holds
 * the index of an input texel at the same pyramid level. The neighbourhood
 * vector of a texel is the colour window (5x5, PCA to 5 coefficients) and
 * the mask window (3x3, PCA to 3, scaled by two) around it: for the input,
 * its own colours and its key's mask; for the output, the colours of the
 * input texels its window points to and the target mask F_m. Each pass
 * visits the texels in random order and points each to the input texel of
 * least |vector difference|^2 + usage penalty, found by a kd-tree
 * (kdtree.h) whose per-point penalty charges each current use of an input
 * texel -- approximately by default, as the paper's ANN (within a factor
 * 1 + search_eps of the nearest distance, at most search_buckets buckets
 * scanned), exactly on request; a texel keeps its match unless another is
 * strictly better. Everything wraps around. */
#include "morph.c"
#include "../common/kdtree.h"
#include "../common/pca.h"

#define PGP__MAX_LEVELS 12
#define PGP__PCA_SAMPLES 16384 /* neighbourhoods sampled (on a regular stride) for each PCA */

enum { PGP__INIT_IDENTITY = 0, PGP__INIT_PREVIOUS = 1, PGP__INIT_RANDOM = 2 };

/* ---- pyramids ------------------------------------------------------------------- */

/* §1.2 "repeatedly downscales the inputs by a factor of 2": periodic
 * binomial [1 4 6 4 1]/16 filter, every second texel. n x n x c to
 * (n/2) x (n/2) x c; tmp holds (n/2)*n*c floats. */
static void pgp__reduce(const float *src, int n, int c, float *dst, float *tmp)
{
    static const float w[5] = {0.0625f, 0.25f, 0.375f, 0.25f, 0.0625f};
    int h = n / 2, x, y, k, t;
    for (y = 0; y < n; y++)
        for (x = 0; x < h; x++)
            for (k = 0; k < c; k++) {
                float s = 0.0f;
                for (t = 0; t < 5; t++) s += w[t] * src[((size_t)y * n + (2 * x + t - 2 + n) % n) * c + k];
                tmp[((size_t)y * h + x) * c + k] = s;
            }
    for (y = 0; y < h; y++)
        for (x = 0; x < h; x++)
            for (k = 0; k < c; k++) {
                float s = 0.0f;
                for (t = 0; t < 5; t++) s += w[t] * tmp[((size_t)((2 * y + t - 2 + n) % n) * h + x) * c + k];
                dst[((size_t)y * h + x) * c + k] = s;
            }
}

/* Levels for side n: the requested count, or (0) halvings while the side
 * stays even and at least 32 texels. 0 when the request is impossible. */
static int pgp__level_count(int n, int want)
{
    int l = 1, s = n;
    if (want > 0) {
        for (; l < want; l++, s /= 2)
            if (s % 2) return 0;
        return want <= PGP__MAX_LEVELS ? want : 0;
    }
    while (s % 2 == 0 && s / 2 >= 32 && l < PGP__MAX_LEVELS) {
        s /= 2;
        l++;
    }
    return l;
}

/* A 0/1 mask as a pyramid: lev[nlev-1] the mask, each coarser one reduced. */
static void pgp__mask_pyramid(const unsigned char *mask, int n, int nlev, float **lev, float *tmp)
{
    size_t i, nn = (size_t)n * n;
    int r;
    for (i = 0; i < nn; i++) lev[nlev - 1][i] = mask[i] ? 1.0f : 0.0f;
    for (r = nlev - 1; r > 0; r--, n /= 2) pgp__reduce(lev[r], n, 1, lev[r - 1], tmp);
}

/* ---- exemplars: an input texture ready to synthesise from -------------------------- */

typedef struct pgp__exlevel {
    int n;
    float *color;   /* n*n*c */
    float *mask;    /* n*n: the key's mask at this level */
    float *pca;     /* colour mean (dc), packed basis (dc*PW_PCA_PACK), mask mean (dm),
                       packed basis (dm*PW_PCA_PACK) */
    float lambda;   /* usage penalty of one use */
    int *count;     /* n*n: current uses of each input texel */
    pw_kdtree tree; /* n*n neighbourhood vectors */
} pgp__exlevel;

typedef struct pgp__ex {
    int c, nlev, cw, mw, dc, dm, cd, md, D;
    float weight;                      /* mask_weight */
    pgp__exlevel lev[PGP__MAX_LEVELS]; /* 0: coarsest */
} pgp__ex;

static void pgp__ex_free(const pw_alloc *a, pgp__ex *ex)
{
    int r;
    for (r = 0; r < PGP__MAX_LEVELS; r++) {
        pgp__exlevel *L = &ex->lev[r];
        pw_free(a, L->color);
        pw_free(a, L->mask);
        pw_free(a, L->pca);
        pw_free(a, L->count);
        pw_kdtree_free(a, &L->tree);
    }
    memset(ex, 0, sizeof *ex);
}

/* One plane of an n x n level: its `c`-channel samples (the colours or
 * the mask), read through an indirection map when there is one. */
typedef struct pgp__plane {
    const float *f;
    int c, n;
    const int *ind; /* sample q read at ind[q]; NULL: at q */
} pgp__plane;

/* The win x win window of plane P's samples around texel p = y*n + x. */
static void pgp__gather(const pgp__plane *P, int p, int win, float *out)
{
    const float *f = P->f;
    const int *ind = P->ind;
    int c = P->c, n = P->n, x = p % n, y = p / n, h = win / 2, dx, dy, j;
    for (dy = -h; dy <= h; dy++) {
        int row = ((y + dy + n) % n) * n;
        for (dx = -h; dx <= h; dx++) {
            int q = row + (x + dx + n) % n;
            const float *s = f + (size_t)(ind ? ind[q] : q) * c;
            for (j = 0; j < c; j++) *out++ = s[j];
        }
    }
}

/* What a neighbourhood vector reads at a level: the colours through an
 * indirection map (NULL: the level's own, for the input) and a mask (the
 * key's for the input, the target for an output). */
typedef struct pgp__source {
    const int *ind;
    const float *mask;
} pgp__source;

/* The neighbourhood vector (D floats) of texel p = y*n + x of level L as
 * read from src. buf: dc + dm + 2 PW_PCA_PACK floats. */
static void pgp__vector(const pgp__ex *ex, const pgp__exlevel *L, const pgp__source *src, int p, float *buf, float *v)
{
    const float *cm = L->pca, *cb = cm + ex->dc, *mm = cb + (size_t)ex->dc * PW_PCA_PACK, *mb = mm + ex->dm;
    float *y8 = buf + ex->dc + ex->dm;
    pgp__plane pc, pm;
    int j;
    pc.f = L->color;
    pc.c = ex->c;
    pc.n = L->n;
    pc.ind = src->ind;
    pm.f = src->mask;
    pm.c = 1;
    pm.n = L->n;
    pm.ind = NULL;
    pgp__gather(&pc, p, ex->cw, buf);
    pw_pca_project_packed(buf, cm, cb, ex->dc, y8);
    pgp__gather(&pm, p, ex->mw, buf + ex->dc);
    pw_pca_project_packed(buf + ex->dc, mm, mb, ex->dm, y8 + PW_PCA_PACK);
    for (j = 0; j < ex->cd; j++) v[j] = y8[j];
    for (j = 0; j < ex->md; j++) v[ex->cd + j] = ex->weight * y8[PW_PCA_PACK + j];
}

/* The PCA bases of level L (colour and mask, separately) from its input
 * neighbourhoods, and the usage penalty from their variance. */
static int pgp__ex_pca(const pw_alloc *a, pgp__ex *ex, pgp__exlevel *L, float usage, pw_err *e)
{
    size_t nn = (size_t)L->n * L->n, step = nn > PGP__PCA_SAMPLES ? nn / PGP__PCA_SAMPLES : 1, u;
    size_t np = (size_t)(ex->dc + ex->dm) * (1 + PW_PCA_PACK);
    float *buf = (float *)pw_alloc_array(a, (size_t)(ex->dc + ex->dm) * (PW_PCA_PACK + 1) + ex->D, sizeof(float),
                                         "PCA window", e);
    float *basis = buf ? buf + ex->dc + ex->dm : NULL,
          *var = basis ? basis + (size_t)(ex->dc + ex->dm) * PW_PCA_PACK : NULL;
    float *mm;
    pw_pca pc, pm;
    pw_pca_out oc, om;
    pgp__plane lc, lm;
    int r, j;
    lc.f = L->color;
    lc.c = ex->c;
    lc.n = L->n;
    lc.ind = NULL;
    lm.f = L->mask;
    lm.c = 1;
    lm.n = L->n;
    lm.ind = NULL;
    memset(&pc, 0, sizeof pc);
    memset(&pm, 0, sizeof pm);
    L->pca = (float *)pw_alloc_array(a, np, sizeof(float), "PCA bases", e);
    r = buf && L->pca ? PW_OK : PW_ERR_NOMEM;
    if (r == PW_OK && (r = pw_pca_init(a, &pc, ex->dc, e)) == PW_OK) r = pw_pca_init(a, &pm, ex->dm, e);
    for (u = 0; r == PW_OK && u < nn; u += step) {
        pgp__gather(&lc, (int)u, ex->cw, buf);
        pw_pca_add(&pc, buf);
        pgp__gather(&lm, (int)u, ex->mw, buf);
        pw_pca_add(&pm, buf);
    }
    mm = L->pca ? L->pca + (size_t)ex->dc * (1 + PW_PCA_PACK) : NULL;
    oc.k = ex->cd;
    oc.mean = L->pca;
    oc.basis = basis;
    oc.var = var;
    om.k = ex->md;
    om.mean = mm;
    om.basis = basis;
    om.var = var + ex->cd;
    if (r == PW_OK && (r = pw_pca_solve(a, &pc, &oc, e)) == PW_OK) pw_pca_pack(basis, ex->dc, ex->cd, L->pca + ex->dc);
    if (r == PW_OK && (r = pw_pca_solve(a, &pm, &om, e)) == PW_OK) pw_pca_pack(basis, ex->dm, ex->md, mm + ex->dm);
    for (j = 0, L->lambda = 0.0f; r == PW_OK && j < ex->D; j++)
        L->lambda += var[j] * (j < ex->cd ? 1.0f : ex->weight * ex->weight);
    L->lambda *= usage;
    pw_pca_free(a, &pc);
    pw_pca_free(a, &pm);
    pw_free(a, buf);
    return r;
}

/* The kd-tree of level L's input vectors and its usage counts. */
static int pgp__ex_tree(const pw_alloc *a, pgp__ex *ex, pgp__exlevel *L, pw_err *e)
{
    size_t nn = (size_t)L->n * L->n, u;
    float *pts = (float *)pw_alloc_array(a, nn * ex->D, sizeof(float), "neighbourhood vectors", e);
    float *buf = (float *)pw_alloc_array(a, (size_t)ex->dc + ex->dm + 2 * PW_PCA_PACK, sizeof(float), "window", e);
    int r = pts && buf ? PW_OK : PW_ERR_NOMEM;
    pgp__source src;
    src.ind = NULL;
    src.mask = L->mask;
    for (u = 0; r == PW_OK && u < nn; u++) pgp__vector(ex, L, &src, (int)u, buf, pts + u * ex->D);
    if (r == PW_OK) r = pw_kdtree_build(a, &L->tree, pts, (int)nn, ex->D, e);
    if (r == PW_OK && !(L->count = (int *)pw_calloc_array(a, nn, sizeof(int), "usage counts", e))) r = PW_ERR_NOMEM;
    pw_free(a, pts);
    pw_free(a, buf);
    return r;
}

/* One tile synthesis (§1): the allocator, the checked options, the
 * prepared keys and the tile's channels and pyramid levels, shared by the
 * steps of pgp__synth_run. */
typedef struct pgp__tile_job {
    const pw_alloc *a;
    const pgp_synth_options *o;
    const pgp__key *keys; /* nkeys, prepared (pgp__prepare_key) */
    int nkeys, c, nlev;
} pgp__tile_job;

/* Exemplar of a prepared key of job T: pyramids of colour and mask, then
 * PCA and kd-tree per level. */
static int pgp__ex_build(const pgp__tile_job *T, const pgp__key *key, pgp__ex *ex, pw_err *e)
{
    const pw_alloc *a = T->a;
    const pgp_synth_options *o = T->o;
    int n = o->size, c = T->c, nlev = T->nlev;
    float *tmp = (float *)pw_alloc_array(a, (size_t)n * n * c / 2 + 1, sizeof(float), "pyramid", e);
    int r = tmp ? PW_OK : PW_ERR_NOMEM, l;
    size_t i;
    memset(ex, 0, sizeof *ex);
    ex->c = c;
    ex->nlev = nlev;
    ex->cw = o->color_window;
    ex->mw = o->mask_window;
    ex->weight = o->mask_weight;
    ex->dc = ex->cw * ex->cw * c;
    ex->dm = ex->mw * ex->mw;
    ex->cd = pw_mini(o->color_dims, ex->dc);
    ex->md = pw_mini(o->mask_dims, ex->dm);
    ex->D = ex->cd + ex->md;
    for (l = nlev - 1; r == PW_OK && l >= 0; l--, n /= 2) {
        pgp__exlevel *L = &ex->lev[l];
        L->n = n;
        L->color = (float *)pw_alloc_array(a, (size_t)n * n * c, sizeof(float), "pyramid colours", e);
        L->mask = (float *)pw_alloc_array(a, (size_t)n * n, sizeof(float), "pyramid masks", e);
        if (!L->color || !L->mask) r = PW_ERR_NOMEM;
        else if (l == nlev - 1) {
            memcpy(L->color, key->color, sizeof(float) * (size_t)n * n * c);
            for (i = 0; i < (size_t)n * n; i++) L->mask[i] = key->mask[i] ? 1.0f : 0.0f;
        } else {
            pgp__reduce(ex->lev[l + 1].color, 2 * n, c, L->color, tmp);
            pgp__reduce(ex->lev[l + 1].mask, 2 * n, 1, L->mask, tmp);
        }
    }
    for (l = 0; r == PW_OK && l < nlev; l++)
        if ((r = pgp__ex_pca(a, ex, &ex->lev[l], o->usage_weight, e)) == PW_OK) r = pgp__ex_tree(a, ex, &ex->lev[l], e);
    pw_free(a, tmp);
    return r;
}

/* ---- one layer ---------------------------------------------------------------------- */

/* The working set of the syntheses from one exemplar: an indirection map
 * and a target mask per level (the coarsest map carries over to the next
 * layer), scratch, and the progress shared by the whole tile. */
typedef struct pgp__synth {
    const pgp_synth_options *o;
    pgp__ex *ex;
    int *ind[PGP__MAX_LEVELS];
    float *target[PGP__MAX_LEVELS];
    float *buf, *q, *off, *tmp;
    int *perm;
    pw_progress prog;
    double *done, total;
    double share; /* work counted per texel update: 2 when the other side runs unreported beside it */
} pgp__synth;

static void pgp__synth_free(const pw_alloc *a, pgp__synth *S)
{
    int r;
    for (r = 0; r < PGP__MAX_LEVELS; r++) {
        pw_free(a, S->ind[r]);
        pw_free(a, S->target[r]);
    }
    pw_free(a, S->buf);
    pw_free(a, S->perm);
    memset(S, 0, sizeof *S);
}

static int pgp__synth_init(const pw_alloc *a, pgp__synth *S, pgp__ex *ex, const pgp_synth_options *o, pw_err *e)
{
    int r, ok = 1, n = ex->lev[ex->nlev - 1].n;
    memset(S, 0, sizeof *S);
    S->o = o;
    S->ex = ex;
    S->share = 1.0;
    for (r = 0; r < ex->nlev; r++) {
        size_t nn = (size_t)ex->lev[r].n * ex->lev[r].n;
        S->ind[r] = (int *)pw_alloc_array(a, nn, sizeof(int), "indirection map", e);
        S->target[r] = (float *)pw_alloc_array(a, nn, sizeof(float), "target mask", e);
        ok = ok && S->ind[r] && S->target[r];
    }
    S->buf = (float *)pw_alloc_array(a, (size_t)ex->dc + ex->dm + 2 * PW_PCA_PACK + 2 * ex->D + (size_t)n * n / 2 + 1,
                                     sizeof(float), "synthesis scratch", e);
    S->perm = (int *)pw_alloc_array(a, (size_t)n * n, sizeof(int), "pixel order", e);
    if (!ok || !S->buf || !S->perm) {
        pgp__synth_free(a, S);
        return PW_ERR_NOMEM;
    }
    S->q = S->buf + ex->dc + ex->dm + 2 * PW_PCA_PACK;
    S->off = S->q + ex->D;
    S->tmp = S->off + ex->D;
    return PW_OK;
}

/* Usage counts of map ind and the tree's penalties from them. */
static void pgp__count_uses(pgp__exlevel *L, const int *ind)
{
    size_t nn = (size_t)L->n * L->n, i;
    for (i = 0; i < nn; i++) L->count[i] = 0;
    for (i = 0; i < nn; i++) L->count[ind[i]]++;
    for (i = 0; i < nn; i++) pw_kdtree_set_penalty(&L->tree, (int)i, L->lambda * (float)L->count[i]);
}

/* Texel p points to the best input texel; its current one is kept unless
 * another is strictly better (its own use is not charged to it). */
static void pgp__update_texel(pgp__synth *S, pgp__exlevel *L, int *ind, const float *target, int p)
{
    int u0 = ind[p], u;
    pw_kdquery qy;
    pgp__source src;
    src.ind = ind;
    src.mask = target;
    pgp__vector(S->ex, L, &src, p, S->buf, S->q);
    qy.q = S->q;
    qy.eps = S->o->search_eps;
    qy.buckets = S->o->search_buckets;
    qy.off = S->off;
    qy.start = u0;
    qy.start_cost = pw_kdtree_cost(&L->tree, S->q, u0) - L->lambda;
    u = pw_kdtree_nearest(&L->tree, &qy, NULL);
    if (u == u0) return;
    L->count[u0]--;
    pw_kdtree_set_penalty(&L->tree, u0, L->lambda * (float)L->count[u0]);
    L->count[u]++;
    pw_kdtree_set_penalty(&L->tree, u, L->lambda * (float)L->count[u]);
    ind[p] = u;
}

/* §1.2 optimisation of level r: `passes` passes over the texels in random
 * order. */
static int pgp__optimize(pgp__synth *S, int r, pw_rng *rng, pw_err *e)
{
    pgp__exlevel *L = &S->ex->lev[r];
    int nn = L->n * L->n, i, pass, passes = r == 0 ? S->o->coarse_passes : S->o->fine_passes;
    pgp__count_uses(L, S->ind[r]);
    for (i = 0; i < nn; i++) S->perm[i] = i;
    for (pass = 0; pass < passes; pass++) {
        pw_rng_shuffle(rng, S->perm, nn);
        for (i = 0; i < nn; i++) pgp__update_texel(S, L, S->ind[r], S->target[r], S->perm[i]);
        *S->done += S->share * nn;
        if (pw_report(&S->prog, (float)(0.05 + 0.95 * *S->done / S->total), "tile synthesis", e))
            return PW_ERR_CANCELLED;
    }
    return PW_OK;
}

/* §1.2 initialisation of level r > 0: "the result of the coarser level is
 * upsampled", I(2i+bi, 2j+bj) = I(i, j) + (bi, bj) at the finer pixel size. */
static void pgp__upsample(const int *coarse, int nc, int *fine)
{
    int n = 2 * nc, x, y;
    for (y = 0; y < n; y++)
        for (x = 0; x < n; x++) {
            int u = coarse[(y / 2) * nc + x / 2], ux = 2 * (u % nc) + x % 2, uy = 2 * (u / nc) + y % 2;
            fine[y * n + x] = (uy % n) * n + ux % n;
        }
}

/* One layer: the target mask pyramid of `mask`, then coarse to fine the
 * paper's initialisation (m = 0: identity, which is already optimal, so it
 * is not optimised; m > 0 at the coarsest level: the previous layer's map,
 * left in ind[0]; single-tile layers: random) and the optimisation. */
static int pgp__synth_layer(pgp__synth *S, const unsigned char *mask, int init, uint64_t stream, pw_err *e)
{
    pgp__ex *ex = S->ex;
    pw_rng rng = pw_rng_seed(S->o->seed, stream);
    int r, rc = PW_OK, nn0 = ex->lev[0].n * ex->lev[0].n, i;
    pgp__mask_pyramid(mask, ex->lev[ex->nlev - 1].n, ex->nlev, S->target, S->tmp);
    if (init == PGP__INIT_IDENTITY) {
        for (r = 0; r < ex->nlev; r++)
            for (i = 0; i < ex->lev[r].n * ex->lev[r].n; i++) S->ind[r][i] = i;
        return PW_OK;
    }
    if (init == PGP__INIT_RANDOM)
        for (i = 0; i < nn0; i++) S->ind[0][i] = (int)pw_rng_below(&rng, (uint32_t)nn0);
    for (r = 0; r < ex->nlev && rc == PW_OK; r++) {
        if (r > 0) pgp__upsample(S->ind[r - 1], ex->lev[r - 1].n, S->ind[r]);
        rc = pgp__optimize(S, r, &rng, e);
    }
    return rc;
}

/* out (+)= w * the colours the finest map points to. */
static void pgp__emit(const pgp__synth *S, float w, int add, float *out)
{
    const pgp__exlevel *L = &S->ex->lev[S->ex->nlev - 1];
    size_t nn = (size_t)L->n * L->n, i;
    int k, c = S->ex->c;
    for (i = 0; i < nn; i++) {
        const float *s = L->color + (size_t)S->ind[S->ex->nlev - 1][i] * c;
        for (k = 0; k < c; k++) out[i * c + k] = (add ? out[i * c + k] : 0.0f) + w * s[k];
    }
}

/* ---- §1: the tile ------------------------------------------------------------------ */

/* The tile's channels: RGB if any key has colour, plus alpha if any has it. */
static int pgp__tile_channels(const pgp_key *keys, int nkeys)
{
    int k, rgb = 0, alpha = 0;
    for (k = 0; k < nkeys; k++) {
        int c = keys[k].image->channels;
        rgb |= c >= 3;
        alpha |= c == 2 || c == 4;
    }
    return (rgb ? 3 : 1) + alpha;
}

/* The layer of key k: evenly spaced (rounded), the first at 0 and the last
 * at layers - 1. */
static int pgp__key_layer(int k, int nkeys, int layers)
{
    if (nkeys < 2) return 0;
    return (int)(((long)k * (layers - 1) * 2 + (nkeys - 1)) / (2L * (nkeys - 1)));
}

static int pgp__check_synth_options(const pgp_synth_options *o, int nkeys, int *nlev, pw_err *e)
{
    int win = pw_maxi(o->color_window, o->mask_window);
    if (o->single && nkeys != 1)
        return pw_fail(e, PW_ERR_INVALID, "single-tile mode takes exactly one key (%d given)", nkeys);
    if (!o->single && (nkeys < 2 || nkeys > 256))
        return pw_fail(e, PW_ERR_INVALID, "a morph takes 2 to 256 keys (%d given; single-tile mode takes one)", nkeys);
    if (o->size < 16 || o->size > 4096) return pw_fail(e, PW_ERR_INVALID, "tile size %d (16 to 4096 texels)", o->size);
    if (o->layers < (o->single ? 1 : nkeys) || o->layers > 1024)
        return pw_fail(e, PW_ERR_INVALID, "%d layers for %d keys (at least one layer per key, at most 1024)", o->layers,
                       nkeys);
    if (o->tileable < PGP_TILEABLE_AUTO || o->tileable > PGP_TILEABLE_MAKE || o->auto_mask < PGP_MASK_DARK ||
        o->auto_mask > PGP_MASK_GRADIENT)
        return pw_fail(e, PW_ERR_INVALID, "unknown tileable (%d) or auto_mask (%d) mode", o->tileable, o->auto_mask);
    if (o->steps < 0 || o->steps > 100000 || o->coarse_passes < 1 || o->coarse_passes > 1000 || o->fine_passes < 1 ||
        o->fine_passes > 1000)
        return pw_fail(e, PW_ERR_INVALID, "steps %d (0 to 100000) or passes %d, %d (1 to 1000)", o->steps,
                       o->coarse_passes, o->fine_passes);
    if (o->color_window < 1 || o->color_window % 2 == 0 || o->mask_window < 1 || o->mask_window % 2 == 0 || win > 15 ||
        o->color_dims < 1 || o->mask_dims < 1 || o->color_dims > PW_PCA_PACK || o->mask_dims > PW_PCA_PACK)
        return pw_fail(e, PW_ERR_INVALID, "windows %d, %d (odd, 1 to 15) or dimensions %d, %d (1 to 8)",
                       o->color_window, o->mask_window, o->color_dims, o->mask_dims);
    if (!(o->mask_weight > 0.0f && o->mask_weight < 1e6f) || !(o->usage_weight >= 0.0f && o->usage_weight < 1e6f) ||
        !(o->search_eps >= 0.0f && o->search_eps < 1e6f))
        return pw_fail(e, PW_ERR_INVALID, "mask_weight %g (> 0), usage_weight %g or search_eps %g is not valid",
                       o->mask_weight, o->usage_weight, o->search_eps);
    *nlev = o->levels < 0 ? 0 : pgp__level_count(o->size, o->levels);
    if (!*nlev || (o->size >> (*nlev - 1)) < win)
        return pw_fail(e, PW_ERR_INVALID,
                       "%d pyramid levels do not fit a %d-texel tile (each halving needs an even "
                       "side, and the coarsest one at least the %d-texel window)",
                       o->levels, o->size, win);
    return PW_OK;
}

static int pgp__check_keys(const pgp_key *keys, int nkeys, pw_err *e)
{
    char what[64];
    int k;
    if (!keys) return pw_fail(e, PW_ERR_INVALID, "no keys given");
    for (k = 0; k < nkeys; k++) {
        snprintf(what, sizeof what, "key %d image", k);
        if (pgp__check_image(keys[k].image, what, e) != PW_OK) return e->code;
        snprintf(what, sizeof what, "key %d mask", k);
        if (keys[k].mask && pgp__check_image(keys[k].mask, what, e) != PW_OK) return e->code;
        if (keys[k].mask &&
            (keys[k].mask->width != keys[k].image->width || keys[k].mask->height != keys[k].image->height))
            return pw_fail(e, PW_ERR_INVALID, "key %d: the mask is %dx%d but the image %dx%d", k, keys[k].mask->width,
                           keys[k].mask->height, keys[k].image->width, keys[k].image->height);
    }
    return PW_OK;
}

/* Feature masks of every layer (layers*n*n): the keys' masks at their
 * layers and §1.1 between them, or the one key's mask everywhere in
 * single-tile mode. */
static int pgp__layer_masks(const pgp__tile_job *T, const pw_progress *prog, unsigned char *masks, pw_err *e)
{
    const pgp_synth_options *o = T->o;
    const pgp__key *keys = T->keys;
    int nkeys = T->nkeys;
    size_t nn = (size_t)o->size * o->size;
    char what[64];
    int k, l, r = PW_OK;
    if (o->single) {
        for (l = 0; l < o->layers; l++) memcpy(masks + l * nn, keys[0].mask, nn);
        return PW_OK;
    }
    for (k = 0; k < nkeys && r == PW_OK; k++) {
        snprintf(what, sizeof what, "key %d mask", k);
        r = pgp__check_mask(keys[k].mask, nn, what, e);
    }
    for (k = 0; k + 1 < nkeys && r == PW_OK; k++) {
        int b = pgp__key_layer(k, nkeys, o->layers);
        pgp__morph_job J;
        J.f0 = keys[k].mask;
        J.f1 = keys[k + 1].mask;
        J.n = o->size;
        J.M = pgp__key_layer(k + 1, nkeys, o->layers) - b;
        J.masks = masks + b * nn;
        J.prog = prog;
        J.p0 = 0.05f * k / (nkeys - 1);
        J.p1 = 0.05f * (k + 1) / (nkeys - 1);
        r = pgp__morph_masks(T->a, &J, o, e);
    }
    return r;
}

/* The layers of one morph: M + 1 masks (n*n each) from one key's layer to
 * the next key's, and the colours of its first M layers (n*n*c each). */
typedef struct pgp__span {
    const unsigned char *masks;
    int M;
    float *out[2]; /* the layers of each end's synthesis; [1] may be [0] */
} pgp__span;

/* One end of morph span sp: from its own key (from_end 0: m = 0, 1, ...,
 * M-1, weight 1 - m/M, written to out[0]) or from the other (from_end 1:
 * m = M, ..., 1, weight m/M, added to out[1] if it is out[0], else
 * written), §1 step 3. */
static int pgp__synth_side(pgp__synth *S, const pgp__span *sp, int from_end, uint64_t stream, pw_err *e)
{
    const unsigned char *masks = sp->masks;
    int M = sp->M, add = from_end && sp->out[1] == sp->out[0];
    float *out = sp->out[from_end];
    const pgp__exlevel *L = &S->ex->lev[S->ex->nlev - 1];
    size_t nn = (size_t)L->n * L->n, lay = nn * S->ex->c;
    int k, r = PW_OK;
    for (k = 0; k < M && r == PW_OK; k++) {
        int m = from_end ? M - k : k;
        r = pgp__synth_layer(S, masks + m * nn, k == 0 ? PGP__INIT_IDENTITY : PGP__INIT_PREVIOUS, stream + (uint64_t)m,
                             e);
        if (r == PW_OK && m < M)
            pgp__emit(S, from_end ? (float)m / (float)M : 1.0f - (float)m / (float)M, add, out + m * lay);
    }
    return r;
}

/* Optimised texel updates of the whole tile, for the progress report. */
static double pgp__work(const pgp_synth_options *o, int nkeys, int nlev)
{
    double per = 0.0;
    int r, layers = 0, k;
    for (r = 0; r < nlev; r++) {
        double s = (double)(o->size >> (nlev - 1 - r));
        per += s * s * (r == 0 ? o->coarse_passes : o->fine_passes);
    }
    if (o->single) layers = o->layers - 1;
    for (k = 0; !o->single && k + 1 < nkeys; k++)
        layers += 2 * (pgp__key_layer(k + 1, nkeys, o->layers) - pgp__key_layer(k, nkeys, o->layers) - 1);
    return per * (layers > 0 ? layers : 1);
}

/* The two ends of a morph span as two tasks of a pw_parallel: each with its
 * own synthesis state, exemplar and layers, nothing shared but the span's
 * masks. */
typedef struct pgp__sides {
    pgp__synth *S; /* [2] */
    const pgp__span *sp;
    uint64_t stream;
    int codes[2];
    pw_err errs[2];
} pgp__sides;

static void pgp__side_task(void *ctx, int j)
{
    pgp__sides *D = (pgp__sides *)ctx;
    pw_err_clear(&D->errs[j]);
    D->codes[j] = pgp__synth_side(&D->S[j], D->sp, j, D->stream + (uint64_t)j * 2048, &D->errs[j]);
}

/* How the morph spans run: the parallel settings, the synthesis states
 * S[2], the exemplars ex[2] (the span's start and end) and, when the ends
 * run side by side, the far end's layers (else NULL). */
typedef struct pgp__span_run {
    const pw_parallel *par;
    pgp__synth *S;
    pgp__ex *ex;
    float *apart;
} pgp__span_run;

/* Both ends of span sp: one after the other with S[0] when R->apart is
 * NULL, else side by side, the far end's layers in R->apart and added
 * after (the same sums in the same order: the tile does not depend on the
 * threads). */
static int pgp__synth_span(const pgp__span_run *R, pgp__span *sp, uint64_t stream, pw_err *e)
{
    pgp__synth *S = R->S;
    pgp__ex *ex = R->ex;
    float *apart = R->apart;
    size_t lay = (size_t)S[0].o->size * S[0].o->size * ex[0].c, i;
    pgp__sides D;
    int r;
    if (!apart) {
        sp->out[1] = sp->out[0];
        S[0].ex = &ex[0];
        r = pgp__synth_side(&S[0], sp, 0, stream, e);
        S[0].ex = &ex[1];
        return r == PW_OK ? pgp__synth_side(&S[0], sp, 1, stream + 2048, e) : r;
    }
    sp->out[1] = apart;
    S[0].ex = &ex[0];
    S[1].ex = &ex[1];
    D.S = S;
    D.sp = sp;
    D.stream = stream;
    pw_parallel_for(R->par, 2, pgp__side_task, &D);
    if ((r = D.codes[0]) != PW_OK || (r = D.codes[1]) != PW_OK) {
        *e = D.errs[D.codes[0] != PW_OK ? 0 : 1];
        return r;
    }
    for (i = lay; i < (size_t)sp->M * lay; i++) sp->out[0][i] += apart[i];
    return PW_OK;
}

/* Every layer's colours (layers*n*n*c): the morphs with a rolling pair of
 * exemplars, the two ends of each morph side by side when o's parallel
 * settings allow two tasks at once, or the single-tile layers. */
static int pgp__synth_layers(const pgp__tile_job *T, const unsigned char *masks, float *px, pw_err *e)
{
    const pw_alloc *a = T->a;
    const pgp_synth_options *o = T->o;
    const pgp__key *keys = T->keys;
    int nkeys = T->nkeys, c = T->c, nlev = T->nlev;
    size_t nn = (size_t)o->size * o->size, lay = nn * c;
    pw_parallel par = pw_parallel_make(o->threads, o->parallel, o->parallel_pool);
    int two = !o->single && nkeys > 1 && pw_parallel_width(&par) > 1;
    float *apart = NULL;
    pgp__ex ex[2];
    pgp__synth S[2];
    pgp__span_run R;
    double done = 0.0, done_apart = 0.0;
    int k, l, r;
    memset(ex, 0, sizeof ex);
    memset(S, 0, sizeof S);
    r = pgp__ex_build(T, &keys[0], &ex[0], e);
    if (r == PW_OK) r = pgp__synth_init(a, &S[0], &ex[0], o, e);
    if (r == PW_OK && two && (r = pgp__synth_init(a, &S[1], &ex[0], o, e)) == PW_OK) {
        apart = (float *)pw_alloc_array(a, lay * o->layers, sizeof(float), "far-end layers", e);
        if (!apart) r = PW_ERR_NOMEM;
    }
    S[0].prog = pgp__synth_progress(o);
    S[0].done = &done;
    S[0].total = S[1].total = pgp__work(o, nkeys, nlev);
    S[0].share = two ? 2.0 : 1.0;
    S[1].done = &done_apart; /* the far end reports nothing: its thread is not the caller's */
    memcpy(px, keys[0].color, sizeof(float) * lay);
    for (l = 1; o->single && r == PW_OK && l < o->layers; l++) {
        if ((r = pgp__synth_layer(&S[0], masks, PGP__INIT_RANDOM, (uint64_t)l, e)) == PW_OK)
            pgp__emit(&S[0], 1.0f, 0, px + l * lay);
    }
    for (k = 0; !o->single && r == PW_OK && k + 1 < nkeys; k++) {
        int b = pgp__key_layer(k, nkeys, o->layers), M = pgp__key_layer(k + 1, nkeys, o->layers) - b;
        pgp__span sp;
        if ((r = pgp__ex_build(T, &keys[k + 1], &ex[1], e)) != PW_OK) break;
        sp.masks = masks + b * nn;
        sp.M = M;
        sp.out[0] = px + b * lay;
        R.par = &par;
        R.S = S;
        R.ex = ex;
        R.apart = apart;
        r = pgp__synth_span(&R, &sp, (uint64_t)k * 4096, e);
        memcpy(px + (b + M) * lay, keys[k + 1].color, sizeof(float) * lay);
        pgp__ex_free(a, &ex[0]);
        ex[0] = ex[1];
        memset(&ex[1], 0, sizeof ex[1]);
    }
    pgp__synth_free(a, &S[0]);
    pgp__synth_free(a, &S[1]);
    pw_free(a, apart);
    pgp__ex_free(a, &ex[0]);
    pgp__ex_free(a, &ex[1]);
    return r;
}

/* The pipeline behind pgp_synthesize_tile, on checked arguments: T holds
 * the allocator, options, key count and levels; its channels and prepared
 * keys are filled here from `keys`. */
static int pgp__synth_run(pgp__tile_job *T, const pgp_key *keys, pgp_tile *out, pgp_tile *masks_out, pw_err *e)
{
    const pw_alloc *a = T->a;
    const pgp_synth_options *o = T->o;
    int nkeys = T->nkeys;
    size_t nn = (size_t)o->size * o->size;
    int c = pgp__tile_channels(keys, nkeys), k, r = PW_OK;
    pw_progress prog = pgp__synth_progress(o);
    pgp__key *pk = (pgp__key *)pw_calloc_array(a, (size_t)nkeys, sizeof(pgp__key), "keys", e);
    unsigned char *masks = (unsigned char *)pw_alloc_array(a, nn * o->layers, 1, "layer masks", e);
    float *px = (float *)pw_alloc_array(a, nn * c * o->layers, sizeof(float), "tile", e);
    if (!pk || !masks || !px) r = PW_ERR_NOMEM;
    for (k = 0; k < nkeys && r == PW_OK; k++) r = pgp__prepare_key(a, &keys[k], c, o, &pk[k], e);
    T->c = c;
    T->keys = pk;
    if (r == PW_OK) r = pgp__layer_masks(T, &prog, masks, e);
    if (r == PW_OK) r = pgp__synth_layers(T, masks, px, e);
    if (r == PW_OK && masks_out) r = pgp__mask_tile(a, masks, o->size, o->layers, masks_out, e);
    if (r == PW_OK && (r = pw_report(&prog, 1.0f, "tile synthesis", e)) == PW_OK) {
        out->width = out->height = o->size;
        out->layers = o->layers;
        out->channels = c;
        out->pixels = px;
        out->allocator = pgp__allocator(a);
        px = NULL;
    }
    if (r != PW_OK && masks_out) pgp_tile_free(masks_out);
    for (k = 0; pk && k < nkeys; k++) pgp__key_free(a, &pk[k]);
    pw_free(a, pk);
    pw_free(a, masks);
    pw_free(a, px);
    return r;
}

PGPDEF pgp_result pgp_synthesize_tile(const pgp_key *keys, int nkeys, const pgp_synth_options *opt, pgp_tile *out,
                                      pgp_tile *masks, pgp_error *err)
{
    pgp_synth_options o = pgp__synth_options(opt);
    pw_alloc a = pgp__alloc(&o.allocator);
    int nlev = 0;
    pgp__tile_job T;
    pw_err pe;
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (masks) memset(masks, 0, sizeof *masks);
    if (!out) pw_fail(&pe, PW_ERR_INVALID, "pgp_synthesize_tile: NULL output");
    else if (pgp__check_synth_options(&o, nkeys, &nlev, &pe) == PW_OK && pgp__check_keys(keys, nkeys, &pe) == PW_OK) {
        T.a = &a;
        T.o = &o;
        T.keys = NULL;
        T.nkeys = nkeys;
        T.c = 0;
        T.nlev = nlev;
        pgp__synth_run(&T, keys, out, masks, &pe);
    }
    return pgp__done(&pe, err);
}
