/* grow.c: pasting (§3.3-3.6): grow a surface patch around an uncovered
 * point, parametrise it over the texture patch, record the paste, update
 * the coverage, until every triangle is covered. */
#include "patch.c" /* and, through it, field.c and core.c */
#include "../common/atlas_charts.h"

/* ---- coverage (§3.6) ------------------------------------------------------ */

/* The paper rasterises each paste's faces into a face-ID buffer and needs
 * several passes when a patch overlaps itself in texture space. We keep, for
 * every triangle, the accumulated opacity at a fixed lattice of points
 * (barycentric (i, j, k)/R, i + j + k = R, corners and edges included):
 * evaluating a paste at a triangle's own points is immune to self-overlap,
 * needs no passes, and gives the "one uncovered point" to seed from. R
 * grows with the triangle's size against the texture scale, so the lattice
 * stays about one texel apart however large a triangle is.
 *
 * Points between lattice points must be covered too, and the alpha
 * fall-off can dip between them. So the lattice reads a conservative alpha:
 * the patch's alpha eroded (minimum over a square of radius r texels) by
 * at least the distance from any point of the triangle to its nearest
 * lattice point, measured in texels of that paste. Since compositing is
 * monotone in every paste's alpha, opacity reached at the lattice with
 * eroded alphas is reached everywhere in the triangle with the real ones. */
#define LAPPED__RMIN 4   /* lattice resolution of triangles small against the patch */
#define LAPPED__RMAX 256 /* ... and of huge ones (they need a finer lattice) */
#define LAPPED__NLEV 8   /* erosion radii 0, 1, 2, 4, ..., 64 texels */

typedef struct lapped__eroded {
    int w, h;
    int top;                  /* the last level still opaque at the patch centre */
    float *lev[LAPPED__NLEV]; /* w*h alpha, eroded by radius 0, 1, 2, 4, ... */
} lapped__eroded;

/* A mesh with its field: the frame (S, T) of each triangle, nf*3 each. */
typedef struct {
    const pw_trimesh *m;
    const float *fs, *ft;
} lapped__surface;

static void lapped__eroded_free(const pw_alloc *a, lapped__eroded *er)
{
    int l;
    for (l = 0; l < LAPPED__NLEV; l++) pw_free(a, er->lev[l]);
    memset(er, 0, sizeof *er);
}

/* One axis of an image seen as parallel lines: n samples per line `step`
 * apart, `lines` lines `pitch` apart (rows: 1 and w; columns: w and 1). */
typedef struct {
    int n, step, lines, pitch;
} lapped__lines;

/* out = minimum of src over [x-r, x+r] along the lines of L;
 * outside the image counts as 0. */
static void lapped__min_1d(const float *src, float *out, const lapped__lines *L, int r)
{
    int n = L->n, step = L->step, lines = L->lines, pitch = L->pitch;
    int l, i, k;
    for (l = 0; l < lines; l++)
        for (i = 0; i < n; i++) {
            float m = i - r < 0 || i + r >= n ? 0.0f : 1.0f;
            for (k = pw_maxi(0, i - r); k <= pw_mini(n - 1, i + r) && m > 0.0f; k++) {
                float v = src[(size_t)l * pitch + (size_t)k * step];
                if (v < m) m = v;
            }
            out[(size_t)l * pitch + (size_t)i * step] = m;
        }
}

static int lapped__eroded_init(const pw_alloc *a, const pw_image *rgba, lapped__eroded *er, pw_err *e)
{
    size_t n = (size_t)rgba->w * rgba->h, i;
    float *tmp = (float *)pw_alloc_array(a, n, sizeof(float), "erosion", e);
    lapped__lines rows, cols;
    int l;
    memset(er, 0, sizeof *er);
    er->w = rgba->w;
    er->h = rgba->h;
    for (l = 0; l < LAPPED__NLEV; l++)
        if (!(er->lev[l] = (float *)pw_alloc_array(a, n, sizeof(float), "erosion", e))) break;
    if (!tmp || l < LAPPED__NLEV) {
        pw_free(a, tmp);
        lapped__eroded_free(a, er);
        return PW_ERR_NOMEM;
    }
    for (i = 0; i < n; i++) er->lev[0][i] = rgba->px[4 * i + 3];
    rows.n = er->w;
    rows.step = 1;
    rows.lines = er->h;
    rows.pitch = er->w;
    cols.n = er->h;
    cols.step = er->w;
    cols.lines = er->w;
    cols.pitch = 1;
    for (l = 1; l < LAPPED__NLEV; l++) { /* separable: rows, then columns */
        int r = 1 << (l - 1);
        lapped__min_1d(er->lev[0], tmp, &rows, r);
        lapped__min_1d(tmp, er->lev[l], &cols, r);
    }
    pw_free(a, tmp);
    return PW_OK;
}

/* The erosion level for a paste of triangle uv[6]: at least one texel (the
 * lookups are bilinear) and enough to cover the distance to the nearest
 * lattice point, but never beyond `top`, so that a paste always covers its seed
 * point and the pasting always progresses (triangles larger than about a
 * third of the patch lose the guarantee between lattice points). */
static int lapped__eroded_level(const lapped__eroded *er, const float uv[6], int R)
{
    float longest = 0.0f, need;
    int k, l;
    for (k = 0; k < 3; k++) {
        float du = (uv[2 * k] - uv[(2 * k + 2) % 6]) * (float)er->w;
        float dv = (uv[2 * k + 1] - uv[(2 * k + 3) % 6]) * (float)er->h;
        float len = sqrtf(du * du + dv * dv);
        if (len > longest) longest = len;
    }
    need = 0.58f * longest / (float)R; /* any point is within spacing/sqrt(3) of the lattice */
    for (l = 1; l < er->top && (float)(1 << (l - 1)) < need; l++) {
    }
    return l < er->top ? l : er->top;
}

/* Bilinear lookup of erosion level l at (u, v) (texel centres at half
 * integers, clamped at the border, 0 outside the image, like
 * lapped__lookup), written out for the hot coverage loop. */
static float lapped__eroded_at(const lapped__eroded *er, int l, float u, float v)
{
    const float *px = er->lev[l];
    float fx = u * (float)er->w - 0.5f, fy = (1.0f - v) * (float)er->h - 0.5f, tx, ty, top, bot;
    int x0, y0, x1, y1;
    if (!(u >= 0.0f && v >= 0.0f && u <= 1.0f && v <= 1.0f)) return 0.0f;
    x0 = fx < 0.0f ? -1 : (int)fx; /* fx >= -0.5, so truncation is floor */
    y0 = fy < 0.0f ? -1 : (int)fy;
    tx = fx - (float)x0;
    ty = fy - (float)y0;
    x1 = x0 + 1 < er->w ? x0 + 1 : er->w - 1;
    y1 = y0 + 1 < er->h ? y0 + 1 : er->h - 1;
    x0 = x0 < 0 ? 0 : x0;
    y0 = y0 < 0 ? 0 : y0;
    top = px[y0 * er->w + x0] + (px[y0 * er->w + x1] - px[y0 * er->w + x0]) * tx;
    bot = px[y1 * er->w + x0] + (px[y1 * er->w + x1] - px[y1 * er->w + x0]) * tx;
    return top + (bot - top) * ty;
}

typedef struct lapped__cover {
    size_t *off;         /* nf+1: triangle f's points are alpha[off[f] .. off[f+1]-1] */
    unsigned short *res; /* nf: its lattice resolution R */
    float *alpha;        /* accumulated opacity per lattice point */
    int *open;           /* triangles not yet covered, in any order */
    int *where;          /* nf: position in open, -1 once covered */
    int nopen;
    float need; /* opacity a point must reach */
} lapped__cover;

static void lapped__cover_free(const pw_alloc *a, lapped__cover *c)
{
    pw_free(a, c->off);
    pw_free(a, c->res);
    pw_free(a, c->alpha);
    pw_free(a, c->open);
    pw_free(a, c->where);
    memset(c, 0, sizeof *c);
}

/* Lattice resolutions: points about 3 texels apart for a triangle of
 * this size at this scale in the largest patch (side `texels`). */
static int lapped__cover_sizes(lapped__cover *c, const pw_trimesh *m, const float *t, int texels, pw_err *e)
{
    int f, k;
    c->off[0] = 0;
    for (f = 0; f < m->nf; f++) {
        float longest = 0.0f, r;
        for (k = 0; k < 3; k++) {
            float len = pw_v3_len(pw_v3_sub(pw_trimesh_corner(m, f, k), pw_trimesh_corner(m, f, (k + 1) % 3)));
            if (len > longest) longest = len;
        }
        r = longest / pw_v3_len(pw_v3_load(t + 3 * f)) * (float)texels / 3.0f;
        c->res[f] = (unsigned short)(r < LAPPED__RMIN ? LAPPED__RMIN : (r > LAPPED__RMAX ? LAPPED__RMAX : (int)r + 1));
        c->off[f + 1] = c->off[f] + (size_t)(c->res[f] + 1) * (c->res[f] + 2) / 2;
    }
    if (c->off[m->nf] > (size_t)PW_MAX_MESH_ELEMENTS)
        return pw_fail(e, PW_ERR_LIMIT,
                       "the triangles are so large against the texture scale that "
                       "tracking their coverage needs %lu points (limit %d)",
                       (unsigned long)c->off[m->nf], PW_MAX_MESH_ELEMENTS);
    return PW_OK;
}

static int lapped__cover_init(const pw_alloc *a, const lapped__surface *s, int texels, float need, lapped__cover *c,
                              pw_err *e)
{
    const pw_trimesh *m = s->m;
    const float *t = s->ft;
    int f, r;
    memset(c, 0, sizeof *c);
    c->off = (size_t *)pw_alloc_array(a, (size_t)m->nf + 1, sizeof(size_t), "coverage", e);
    c->res = (unsigned short *)pw_alloc_array(a, (size_t)m->nf, sizeof(unsigned short), "coverage", e);
    c->open = (int *)pw_alloc_array(a, (size_t)m->nf, sizeof(int), "open triangles", e);
    c->where = (int *)pw_alloc_array(a, (size_t)m->nf, sizeof(int), "open triangles", e);
    if (!c->off || !c->res || !c->open || !c->where) r = PW_ERR_NOMEM;
    else if ((r = lapped__cover_sizes(c, m, t, texels, e)) == PW_OK &&
             !(c->alpha = (float *)pw_calloc_array(a, c->off[m->nf], sizeof(float), "coverage", e)))
        r = PW_ERR_NOMEM;
    if (r != PW_OK) {
        lapped__cover_free(a, c);
        return r;
    }
    for (f = 0; f < m->nf; f++) c->open[f] = c->where[f] = f;
    c->nopen = m->nf;
    c->need = need;
    return PW_OK;
}

/* Sets er->top: the last level still opaque enough at the patch centre.
 * A patch whose alpha never reaches the coverage opacity cannot cover. */
static int lapped__eroded_top(lapped__eroded *er, const float centre[2], float need, int k, pw_err *e)
{
    int l;
    if (lapped__eroded_at(er, 0, centre[0], centre[1]) < need)
        return pw_fail(e, PW_ERR_INVALID, "patch %d never reaches opacity %g, so it can never cover a point", k, need);
    for (l = 1; l < LAPPED__NLEV && lapped__eroded_at(er, l, centre[0], centre[1]) >= need; l++) {
    }
    er->top = l - 1;
    return PW_OK;
}

/* Composites one paste's (eroded) alpha over triangle f's lattice (uv: its
 * corners' texture coordinates); returns 1 if every point is now opaque
 * enough. Points go i = 0..R, j = 0..R-i, barycentrics (i, j, R-i-j)/R. */
static int lapped__cover_paint(lapped__cover *c, int f, const float uv[6], const lapped__eroded *er)
{
    float *acc = c->alpha + c->off[f], inv = 1.0f / (float)c->res[f];
    int R = c->res[f], i, j, full = 1, l = lapped__eroded_level(er, uv, R);
    for (i = 0; i <= R; i++)
        for (j = 0; i + j <= R; j++, acc++) {
            float b0 = (float)i * inv, b1 = (float)j * inv, b2 = 1.0f - b0 - b1;
            float a =
                lapped__eroded_at(er, l, b0 * uv[0] + b1 * uv[2] + b2 * uv[4], b0 * uv[1] + b1 * uv[3] + b2 * uv[5]);
            *acc = a + *acc * (1.0f - a);
            full &= *acc >= c->need;
        }
    return full;
}

/* Retires triangle f from the open list once it is covered. */
static void lapped__cover_retire(lapped__cover *c, int f)
{
    if (c->where[f] >= 0) { /* swap-remove from the open list */
        int last = c->open[--c->nopen];
        c->open[c->where[f]] = last;
        c->where[last] = c->where[f];
        c->where[f] = -1;
    }
}

/* One paste painted into the coverage, its triangles in shares on threads
 * (a paste holds each triangle once, and each triangle's lattice is its
 * own): full[i] says whether triangle i of the paste is now covered. The
 * open list changes after, in the paste's order, so the coverage is the
 * same for any number of threads. */
#define LAPPED__PAINT_SHARES 256

typedef struct lapped__painting {
    lapped__cover *c;
    const lapped_paste *q;
    const lapped__eroded *er;
    unsigned char *full;
    int shares, start[LAPPED__PAINT_SHARES + 1]; /* share k: the paste's triangles start[k] to start[k+1] */
} lapped__painting;

static void lapped__paint_share(void *ctx, int share)
{
    const lapped__painting *w = (const lapped__painting *)ctx;
    const lapped_paste *q = w->q;
    int i;
    for (i = w->start[share]; i < w->start[share + 1]; i++)
        w->full[i] = (unsigned char)lapped__cover_paint(w->c, q->faces[i], q->uvs + 6 * i, w->er);
}

/* Lattice points below which a paste is painted on the calling thread
 * alone (handing work to threads costs about as much as painting this
 * many). */
#define LAPPED__PAINT_SERIAL 4096

/* The paste's triangles in shares of about equal lattice points (a
 * triangle's lattice grows with its texture area: equal counts of
 * triangles can differ several times in work), four per thread. */
static void lapped__paint(const pw_parallel *par, lapped__cover *c, const lapped_paste *q, const lapped__eroded *er,
                          unsigned char *full)
{
    lapped__painting w;
    size_t points = 0, done = 0;
    int i, k = 1, width = pw_parallel_width(par);
    for (i = 0; i < q->nfaces && width > 1; i++) points += c->off[q->faces[i] + 1] - c->off[q->faces[i]];
    w.c = c;
    w.q = q;
    w.er = er;
    w.full = full;
    w.shares = points < LAPPED__PAINT_SERIAL ? 1 : (q->nfaces < 4 * width ? q->nfaces : 4 * width);
    if (w.shares > LAPPED__PAINT_SHARES) w.shares = LAPPED__PAINT_SHARES;
    w.start[0] = 0;
    for (i = 0; i < q->nfaces && k < w.shares; i++) {
        done += c->off[q->faces[i] + 1] - c->off[q->faces[i]];
        while (k < w.shares && done * (size_t)w.shares >= points * (size_t)k) w.start[k++] = i + 1;
    }
    while (k <= w.shares) w.start[k++] = q->nfaces;
    if (w.shares <= 1) lapped__paint_share(&w, 0);
    else pw_parallel_for(par, w.shares, lapped__paint_share, &w);
}

/* The least covered lattice point of triangle f, as barycentrics. */
static void lapped__cover_hole(const lapped__cover *c, int f, float b[3])
{
    const float *acc = c->alpha + c->off[f];
    int R = c->res[f], i, j, bi = 0, bj = 0;
    float least = 2.0f;
    for (i = 0; i <= R; i++)
        for (j = 0; i + j <= R; j++, acc++)
            if (*acc < least) {
                least = *acc;
                bi = i;
                bj = j;
            }
    b[0] = (float)bi / (float)R;
    b[1] = (float)bj / (float)R;
    b[2] = 1.0f - b[0] - b[1];
}

/* ---- a surface patch being grown (§3.3) ------------------------------------ */

/* Per-triangle and per-vertex scratch reused by every paste; an entry
 * belongs to the current patch when its stamp equals `stamp`. */
typedef struct lapped__patchbuf {
    int stamp;
    int *fin, *fout;       /* nf: stamp when in the patch / rejected for it */
    int *fq;               /* nf: stamp while waiting in the candidate queue */
    int *vin;              /* nv: stamp when the vertex has texture coordinates */
    int *vloc;             /* nv: index into verts */
    float *vuv;            /* nv*2 texture coordinates */
    float *fs, *ft;        /* nf*3 the frame each patch triangle aligns with */
    int *faces, nfaces;    /* patch triangles in the order they were added */
    int *verts, nverts;    /* patch vertices in the order they were mapped */
    pw_heap queue;         /* candidate triangles by distance (room for nf) */
    int hard;              /* growth stopped somewhere at the distortion limit */
    unsigned char *sliver; /* nf: 1 for a degenerate triangle (pw_trimesh_sliver) */
    float *keep;           /* nv*2: the coordinates of verts before the last optimisation */
    pw__atlas_hash fold;   /* the patch triangles' texture images (lapped__folds) */
} lapped__patchbuf;

static void lapped__patchbuf_free(const pw_alloc *a, lapped__patchbuf *p)
{
    pw_free(a, p->fin);
    pw_free(a, p->fout);
    pw_free(a, p->fq);
    pw_free(a, p->vin);
    pw_free(a, p->vloc);
    pw_free(a, p->vuv);
    pw_free(a, p->fs);
    pw_free(a, p->ft);
    pw_free(a, p->faces);
    pw_free(a, p->verts);
    pw_free(a, p->queue.key);
    pw_free(a, p->queue.item);
    pw_free(a, p->sliver);
    pw_free(a, p->keep);
    pw__atlas_hash_free(a, &p->fold);
    memset(p, 0, sizeof *p);
}

/* Every array sized for the whole mesh: a patch may cover all of it, and a
 * triangle waits in the candidate queue at most once at a time. The fold
 * hash's cells are twice the mean triangle's side in texture units (ft
 * holds the field, |T| the scale). */
static int lapped__patchbuf_init(const pw_alloc *a, const pw_trimesh *m, const float *ft, lapped__patchbuf *p,
                                 pw_err *e)
{
    int nf = m->nf, nv = m->nv, f;
    double mean = 0.0;
    memset(p, 0, sizeof *p);
    for (f = 0; f < nf; f++) mean += m->area[f] / pw_v3_dot(pw_v3_load(ft + 3 * f), pw_v3_load(ft + 3 * f)) / nf;
    if (!(mean > 1e-12)) mean = 1e-12;
    if (pw__atlas_hash_init(a, &p->fold, nf, 2.0 * sqrt(2.0 * mean), e) != PW_OK) return PW_ERR_NOMEM;
    p->sliver = (unsigned char *)pw_alloc_array(a, (size_t)nf, 1, "degenerate triangles", e);
    p->keep = (float *)pw_alloc_array(a, (size_t)nv * 2, sizeof(float), "patch coordinates", e);
    p->fin = (int *)pw_calloc_array(a, (size_t)nf, sizeof(int), "patch triangles", e);
    p->fout = (int *)pw_calloc_array(a, (size_t)nf, sizeof(int), "patch triangles", e);
    p->fq = (int *)pw_calloc_array(a, (size_t)nf, sizeof(int), "patch triangles", e);
    p->vin = (int *)pw_calloc_array(a, (size_t)nv, sizeof(int), "patch vertices", e);
    p->vloc = (int *)pw_alloc_array(a, (size_t)nv, sizeof(int), "patch vertices", e);
    p->vuv = (float *)pw_alloc_array(a, (size_t)nv * 2, sizeof(float), "patch coordinates", e);
    p->fs = (float *)pw_alloc_array(a, (size_t)nf * 3, sizeof(float), "patch frames", e);
    p->ft = (float *)pw_alloc_array(a, (size_t)nf * 3, sizeof(float), "patch frames", e);
    p->faces = (int *)pw_alloc_array(a, (size_t)nf, sizeof(int), "patch triangles", e);
    p->verts = (int *)pw_alloc_array(a, (size_t)nv, sizeof(int), "patch vertices", e);
    p->queue.key = (double *)pw_alloc_array(a, (size_t)nf, sizeof(double), "growth queue", e);
    p->queue.item = (int *)pw_alloc_array(a, (size_t)nf, sizeof(int), "growth queue", e);
    if (p->fin && p->fout && p->fq && p->vin && p->vloc && p->vuv && p->fs && p->ft && p->faces && p->verts &&
        p->queue.key && p->queue.item && p->sliver && p->keep) {
        for (f = 0; f < nf; f++) p->sliver[f] = (unsigned char)pw_trimesh_sliver(m, f);
        return PW_OK;
    }
    lapped__patchbuf_free(a, p);
    return PW_ERR_NOMEM;
}

static void lapped__map_vertex(lapped__patchbuf *p, int v, float u, float w)
{
    if (p->vin[v] != p->stamp) {
        p->vin[v] = p->stamp;
        p->vloc[v] = p->nverts;
        p->verts[p->nverts++] = v;
    }
    p->vuv[2 * v] = u;
    p->vuv[2 * v + 1] = w;
}

/* ---- geometry of the parametrisation (§3.3, §3.4) ----------------------------- */

/* Coefficients of an in-plane vector X of triangle f on its corners:
 * X = w0 A + w1 B + w2 C with w0 + w1 + w2 = 0 (§3.4, footnote 1). */
static void lapped__coeffs(const pw_trimesh *m, int f, pw_v3 x, float w[3])
{
    pw_v3 a = pw_trimesh_corner(m, f, 0);
    pw_v3 e1 = pw_v3_sub(pw_trimesh_corner(m, f, 1), a), e2 = pw_v3_sub(pw_trimesh_corner(m, f, 2), a);
    double g11 = pw_v3_dot(e1, e1), g12 = pw_v3_dot(e1, e2), g22 = pw_v3_dot(e2, e2);
    double r1 = pw_v3_dot(x, e1), r2 = pw_v3_dot(x, e2), det = g11 * g22 - g12 * g12;
    w[1] = (float)((r1 * g22 - r2 * g12) / det);
    w[2] = (float)((r2 * g11 - r1 * g12) / det);
    w[0] = -w[1] - w[2];
}

/* phi(X) for an in-plane vector X of a patch triangle. */
static void lapped__phi(const pw_trimesh *m, const lapped__patchbuf *p, int f, pw_v3 x, float out[2])
{
    float w[3];
    int k;
    lapped__coeffs(m, f, x, w);
    out[0] = out[1] = 0.0f;
    for (k = 0; k < 3; k++) {
        int v = m->tri[3 * f + k];
        out[0] += w[k] * p->vuv[2 * v];
        out[1] += w[k] * p->vuv[2 * v + 1];
    }
}

/* How far the parametrisation of triangle f is from the ideal phi(S) = s^,
 * phi(T) = t^: the larger of the stretch and shrink factors of the 2x2 map
 * with columns phi(S), phi(T), or infinity when it flips orientation. */
static float lapped__distortion(const pw_trimesh *m, const lapped__patchbuf *p, int f)
{
    float ps[2], pt[2], a, b, c, d, det, fro, disc, s1, s2;
    if (p->sliver[f]) return 1.0f; /* no shape to distort: its corners follow its neighbours */
    lapped__phi(m, p, f, pw_v3_load(p->fs + 3 * f), ps);
    lapped__phi(m, p, f, pw_v3_load(p->ft + 3 * f), pt);
    a = ps[0];
    b = pt[0];
    c = ps[1];
    d = pt[1];
    det = a * d - b * c;
    if (!(det > 0.0f)) return FLT_MAX;
    fro = a * a + b * b + c * c + d * d; /* s1^2 + s2^2 */
    disc = sqrtf(pw_clampf(fro * fro - 4.0f * det * det, 0.0f, FLT_MAX));
    s1 = sqrtf(0.5f * (fro + disc));
    s2 = det / s1;
    return s1 > 1.0f / s2 ? s1 : 1.0f / s2;
}

/* The texture displacement the frame (S, T) of triangle f asks for the 3D
 * vector d: d = a S + b T solved in the least-squares sense (S and T need
 * not be orthogonal; the part of d off their plane is ignored), out = (a, b)
 * since phi(S) = (1, 0) and phi(T) = (0, 1) (§3.4). */
static void lapped__frame_coords(const lapped__patchbuf *p, int f, pw_v3 d, float out[2])
{
    pw_v3 s = pw_v3_load(p->fs + 3 * f), t = pw_v3_load(p->ft + 3 * f);
    double ss = pw_v3_dot(s, s), st = pw_v3_dot(s, t), tt = pw_v3_dot(t, t);
    double ds = pw_v3_dot(d, s), dt = pw_v3_dot(d, t), det = ss * tt - st * st;
    out[0] = (float)((ds * tt - dt * st) / det);
    out[1] = (float)((dt * ss - ds * st) / det);
}

/* Texture coordinates of point x of the seed triangle f: the chosen point
 * maps to the patch centre and the face frame (S, T) to the texture axes. */
static void lapped__seed_uv(const lapped__patchbuf *p, int f, pw_v3 x, pw_v3 centre3, const float c[2], float out[2])
{
    lapped__frame_coords(p, f, pw_v3_sub(x, centre3), out);
    out[0] += c[0];
    out[1] += c[1];
}

/* The texture layout of degenerate triangle f: out[2k], out[2k+1] is
 * corner k's offset from corner 0. Its own plane means nothing, so it is
 * laid flat isometrically: its longest edge along that edge's tangent
 * direction (projected onto the frame's plane), the third corner at its
 * true distance from that edge, on the side its orientation gives, all in
 * the frame's texture units. Its texture area is then A / S^2 (§3.4's
 * ideal), however its corners sit. */
static void lapped__sliver_layout(const pw_trimesh *m, const lapped__patchbuf *p, int f, float out[6])
{
    pw_v3 q[3], e, n = pw_v3_load(m->normal + 3 * f), side;
    float best = -1.0f, ae[2], as[2], x, y, own;
    int k, i = 0;
    for (k = 0; k < 3; k++) q[k] = pw_trimesh_corner(m, f, k);
    for (k = 0; k < 3; k++) {
        float l = pw_v3_len(pw_v3_sub(q[(k + 1) % 3], q[k]));
        if (l > best) {
            best = l;
            i = k;
        }
    }
    e = pw_v3_sub(q[(i + 1) % 3], q[i]);
    e = pw_v3_sub(e, pw_v3_scale(n, pw_v3_dot(e, n)));
    e = pw_v3_len(e) > 1e-6f * best && best > 0.0f ? pw_v3_norm(e) : pw_v3_norm(pw_v3_load(p->fs + 3 * f));
    side = pw_v3_cross(n, e);
    lapped__frame_coords(p, f, e, ae);
    lapped__frame_coords(p, f, side, as);
    own = pw_v3_dot(pw_v3_cross(pw_v3_sub(q[1], q[0]), pw_v3_sub(q[2], q[0])), n);
    for (k = 0; k < 3; k++) {
        pw_v3 d = pw_v3_sub(q[k], q[i]), dir = pw_v3_sub(q[(i + 1) % 3], q[i]);
        float dl = pw_v3_len(dir);
        x = dl > 0.0f ? pw_v3_dot(d, dir) / dl : 0.0f;
        y = pw_v3_len(pw_v3_sub(d, pw_v3_scale(dir, dl > 0.0f ? x / dl : 0.0f)));
        y = own < 0.0f ? -y : y; /* the third corner lies left of the longest edge when counter-clockwise */
        out[2 * k] = x * ae[0] + y * as[0];
        out[2 * k + 1] = x * ae[1] + y * as[1];
    }
    for (k = 2; k >= 0; k--) {
        out[2 * k] -= out[0];
        out[2 * k + 1] -= out[1];
    }
}

/* Maillot et al.'s prediction (§3.3): the texture position of corner k of
 * triangle f from its other two, mapped, corners, by a triangle similar to
 * the 3D one with the same orientation. */
static void lapped__predict(const pw_trimesh *m, const lapped__patchbuf *p, int f, int k, float out[2])
{
    int ia = m->tri[3 * f + (k + 1) % 3], ib = m->tri[3 * f + (k + 2) % 3];
    pw_v3 a = pw_trimesh_vert(m, ia), b = pw_trimesh_vert(m, ib), c = pw_trimesh_corner(m, f, k);
    pw_v3 e = pw_v3_sub(b, a), d = pw_v3_sub(c, a);
    float ee = pw_v3_dot(e, e), x = pw_v3_dot(d, e) / ee;
    float y = pw_v3_len(pw_v3_sub(d, pw_v3_scale(e, x))) / sqrtf(ee);
    float du = p->vuv[2 * ib] - p->vuv[2 * ia], dv = p->vuv[2 * ib + 1] - p->vuv[2 * ia + 1];
    if (p->sliver[f]) { /* no usable shape (a needle's short edge amplifies noise): its flat layout */
        float l[6];
        int ka = (k + 1) % 3, kb = (k + 2) % 3;
        lapped__sliver_layout(m, p, f, l);
        out[0] = 0.5f * (p->vuv[2 * ia] + l[2 * k] - l[2 * ka] + p->vuv[2 * ib] + l[2 * k] - l[2 * kb]);
        out[1] = 0.5f * (p->vuv[2 * ia + 1] + l[2 * k + 1] - l[2 * ka + 1] + p->vuv[2 * ib + 1] + l[2 * k + 1] -
                         l[2 * kb + 1]);
        return;
    }
    /* (a, b, c) is counter-clockwise, so c lies to the left of a -> b */
    out[0] = p->vuv[2 * ia] + x * du - y * dv;
    out[1] = p->vuv[2 * ia + 1] + x * dv + y * du;
}

/* Adds the prediction of the triangle of outgoing half-edge h (from v) if
 * its other two corners are mapped. */
static void lapped__predict_from(const pw_trimesh *m, const lapped__patchbuf *p, int h, float sum[2], int *n)
{
    int f = h / 3, k = h % 3;
    float q[2];
    if (p->vin[m->tri[3 * f + (k + 1) % 3]] != p->stamp || p->vin[m->tri[3 * f + (k + 2) % 3]] != p->stamp ||
        p->sliver[f])
        return;
    lapped__predict(m, p, f, k, q);
    sum[0] += q[0];
    sum[1] += q[1];
    (*n)++;
}

/* Maps the new vertex v at the centroid of the predictions of every
 * non-degenerate triangle around it that has its other two corners mapped
 * (§3.3); with none, the frame's prediction in the triangle of h0, a
 * half-edge leaving v whose other two corners are mapped. */
static void lapped__map_new_vertex(const pw_trimesh *m, lapped__patchbuf *p, int v, int h0)
{
    float sum[2] = {0.0f, 0.0f};
    int n = 0, h = h0, guard = 0;
    do { /* counter-clockwise around v until back at h0 or at a boundary */
        lapped__predict_from(m, p, h, sum, &n);
        h = pw_he_ccw(&m->hm, h);
    } while (h >= 0 && h != h0 && ++guard < 4096);
    if (h < 0) /* an open fan: the clockwise side too */
        for (h = pw_he_cw(&m->hm, h0); h >= 0 && ++guard < 8192; h = pw_he_cw(&m->hm, h))
            lapped__predict_from(m, p, h, sum, &n);
    if (n == 0) {
        lapped__predict(m, p, h0 / 3, h0 % 3, sum);
        n = 1;
    }
    lapped__map_vertex(p, v, sum[0] / (float)n, sum[1] / (float)n);
}

/* ---- growing one surface patch (§3.3) ---------------------------------------- */

/* Everything the pasting loop works with. */
typedef struct lapped__paster {
    const pw_alloc *a;
    lapped_options o;
    pw_trimesh m;
    float *fs, *ft;          /* the field (nf*3) */
    float *difficulty;       /* nf, for the early seeds */
    const pw_image *patches; /* npatches views of the caller's RGBA patches */
    int npatches;
    pw_polyhull *hulls;     /* per patch */
    lapped__eroded *eroded; /* per patch, for the coverage */
    float *centre;          /* per patch: texture point where pastes are centred */
    lapped__cover cover;
    lapped__patchbuf pb;
    pw_rng rng;
    lapped_paste *pastes;
    size_t npastes, cap;
    int hard_edges;
    pw_parallel par;     /* the coverage's threads (lapped__paint) */
    unsigned char *full; /* nf: per triangle of a paste, covered now (lapped__paint) */
} lapped__paster;

static pw_v3 lapped__centroid(const pw_trimesh *m, int f)
{
    return pw_v3_scale(
        pw_v3_add(pw_v3_add(pw_trimesh_corner(m, f, 0), pw_trimesh_corner(m, f, 1)), pw_trimesh_corner(m, f, 2)),
        1.0f / 3.0f);
}

/* Queues the triangles across the edges of f that are neither in the patch
 * nor rejected, keyed by distance from the paste's centre point. */
static void lapped__push_neighbours(lapped__paster *P, int f, pw_v3 centre3)
{
    lapped__patchbuf *p = &P->pb;
    int k;
    for (k = 0; k < 3; k++) {
        int g = pw_trimesh_across(&P->m, f, k);
        if (g < 0 || p->fin[g] == p->stamp || p->fout[g] == p->stamp || p->fq[g] == p->stamp) continue;
        p->fq[g] = p->stamp;
        pw_heap_insert(&p->queue, pw_v3_len(pw_v3_sub(lapped__centroid(&P->m, g), centre3)), g);
    }
}

/* The frame triangle g aligns with. For isotropic textures (§3.2) the
 * orientation is propagated: the average of the patch neighbours' T,
 * projected onto g's plane, at the field's scale. */
static void lapped__frame(lapped__paster *P, int g)
{
    lapped__patchbuf *p = &P->pb;
    pw_v3 n = pw_v3_load(P->m.normal + 3 * g), t = pw_v3_make(0, 0, 0), s;
    float scale = pw_v3_len(pw_v3_load(P->ft + 3 * g));
    int k;
    if (P->o.field != LAPPED_FIELD_ISOTROPIC || p->nfaces == 0) {
        memcpy(p->fs + 3 * g, P->fs + 3 * g, sizeof(float) * 3);
        memcpy(p->ft + 3 * g, P->ft + 3 * g, sizeof(float) * 3);
        return;
    }
    for (k = 0; k < 3; k++) {
        int h = pw_trimesh_across(&P->m, g, k);
        if (h >= 0 && p->fin[h] == p->stamp) t = pw_v3_add(t, pw_v3_norm(pw_v3_load(p->ft + 3 * h)));
    }
    t = pw_v3_sub(t, pw_v3_scale(n, pw_v3_dot(t, n)));
    if (!(pw_v3_len(t) > 1e-6f)) t = pw_v3_load(P->ft + 3 * g); /* opposite neighbours cancel */
    t = pw_v3_scale(pw_v3_norm(t), scale);
    s = pw_v3_cross(t, n); /* S = T x N (§3.2) */
    pw_v3_store(p->ft + 3 * g, t);
    pw_v3_store(p->fs + 3 * g, s);
}

/* The texture coordinates of patch triangle f's corners (the fold hash's
 * coordinates; ctx is the paster). */
static void lapped__tex_tri(const void *ctx, int f, double *t)
{
    const lapped__paster *P = (const lapped__paster *)ctx;
    int k;
    for (k = 0; k < 6; k++) t[k] = P->pb.vuv[2 * P->m.tri[3 * f + k / 2] + k % 2];
}

/* Adds triangle f to the patch, its image to the fold hash. */
static int lapped__join(lapped__paster *P, int f, pw_v3 centre3, pw_err *e)
{
    lapped__patchbuf *p = &P->pb;
    double t[6];
    p->fin[f] = p->stamp;
    p->faces[p->nfaces++] = f;
    lapped__push_neighbours(P, f, centre3);
    lapped__tex_tri(P, f, t);
    return pw__atlas_hash_insert(P->a, &p->fold, f, t, e);
}

/* After the optimisation moved the vertices: the fold hash from scratch. */
static int lapped__rehash(lapped__paster *P, pw_err *e)
{
    lapped__patchbuf *p = &P->pb;
    double t[6];
    int i, r = PW_OK;
    pw__atlas_hash_clear(&p->fold);
    for (i = 0; i < p->nfaces && r == PW_OK; i++) {
        lapped__tex_tri(P, p->faces[i], t);
        r = pw__atlas_hash_insert(P->a, &p->fold, p->faces[i], t, e);
    }
    return r;
}

/* Would candidate g, mapped, fold over the patch: does its texture image
 * overlap a patch triangle's by more than a thousandth of its longest
 * side? The paper lets a patch wrap over itself in texture space (§3.3),
 * which it found rare on meshes of about 5,000 faces. Growth makes it
 * common on fine meshes: the coordinates of a new vertex are predicted
 * from its neighbours' (Maillot et al.), the predictions of two fronts
 * that meet disagree by an amount set by the surface's curvature and the
 * distance grown, not by the triangles' size, so the finer the mesh the
 * more of the triangles between them exceed the distortion limit; refused,
 * they leave slits, and the fronts on either side go on growing as
 * separate sheets over the same texture. On CGAL's bunny00 scan (75K
 * triangles) the grown pastes covered their texture 1.00 times (median),
 * on its 1-to-4 subdivision 1.73 times (up to 9.5), and held 5.4 and 11.1
 * times the mesh's triangles (docs/performance.md). A second sheet pastes
 * the same texture again over more surface; refusing it keeps a paste to
 * one layer of its texture patch, whatever the mesh's resolution. */
static int lapped__folds(lapped__paster *P, int g)
{
    double t[6], longest = 0.0;
    int k;
    lapped__tex_tri(P, g, t);
    for (k = 0; k < 3; k++) {
        double du = t[2 * ((k + 1) % 3)] - t[2 * k], dv = t[2 * ((k + 1) % 3) + 1] - t[2 * k + 1];
        if (du * du + dv * dv > longest) longest = du * du + dv * dv;
    }
    return pw__atlas_hash_hits(&P->pb.fold, t, 1e-3 * sqrt(longest), lapped__tex_tri, P);
}

/* Starts a patch on triangle f at barycentric point b, mapped to the
 * centre of patch image `patch` (§3.3). */
static int lapped__start(lapped__paster *P, int f, const float b[3], int patch, pw_v3 *centre3, pw_err *e)
{
    lapped__patchbuf *p = &P->pb;
    int k;
    p->stamp++;
    p->nfaces = p->nverts = p->queue.n = p->hard = 0;
    *centre3 = pw_v3_add(
        pw_v3_add(pw_v3_scale(pw_trimesh_corner(&P->m, f, 0), b[0]), pw_v3_scale(pw_trimesh_corner(&P->m, f, 1), b[1])),
        pw_v3_scale(pw_trimesh_corner(&P->m, f, 2), b[2]));
    lapped__frame(P, f);
    if (p->sliver[f]) { /* its flat layout, with the chosen point at the patch centre */
        float l[6], c[2];
        lapped__sliver_layout(&P->m, p, f, l);
        for (k = 0; k < 2; k++) c[k] = P->centre[2 * patch + k] - b[1] * l[2 + k] - b[2] * l[4 + k];
        for (k = 0; k < 3; k++) lapped__map_vertex(p, P->m.tri[3 * f + k], c[0] + l[2 * k], c[1] + l[2 * k + 1]);
    } else
        for (k = 0; k < 3; k++) {
            float uv[2];
            lapped__seed_uv(p, f, pw_trimesh_corner(&P->m, f, k), *centre3, P->centre + 2 * patch, uv);
            lapped__map_vertex(p, P->m.tri[3 * f + k], uv[0], uv[1]);
        }
    pw__atlas_hash_clear(&p->fold);
    return lapped__join(P, f, *centre3, e);
}

/* Shared edges of candidate g with the patch: how many, the last one, and
 * whether any of them still reaches into the texture patch's hull. */
static int lapped__shared(const lapped__paster *P, int g, const pw_polyhull *hull, int *edge, int *inside)
{
    const lapped__patchbuf *p = &P->pb;
    int k, n = 0;
    *inside = 0;
    for (k = 0; k < 3; k++) {
        int h = pw_trimesh_across(&P->m, g, k), va = P->m.tri[3 * g + k], vb = P->m.tri[3 * g + (k + 1) % 3];
        if (h < 0 || p->fin[h] != p->stamp) continue;
        n++;
        *edge = k;
        if (!*inside)
            *inside =
                pw_polyhull_segment_hits(hull, p->vuv[2 * va], p->vuv[2 * va + 1], p->vuv[2 * vb], p->vuv[2 * vb + 1]);
    }
    return n;
}

/* Tries to add candidate g (§3.3): only across an edge that still reaches
 * into the texture patch, only if the patch stays a disc, and only if the
 * new triangle is neither too distorted nor folded over the patch (else
 * the paste keeps a hard edge). */
static int lapped__try_add(lapped__paster *P, int g, const pw_polyhull *hull, pw_v3 centre3, pw_err *e)
{
    lapped__patchbuf *p = &P->pb;
    int edge = 0, inside, shared = lapped__shared(P, g, hull, &edge, &inside);
    int c = P->m.tri[3 * g + (edge + 2) % 3], fresh = 0;
    if (shared == 0 || !inside) return PW_OK; /* may be reached again through another edge */
    if (shared == 3 || (shared == 1 && p->vin[c] == p->stamp)) {
        p->fout[g] = p->stamp; /* would close the surface or pinch a hole: not a disc */
        return PW_OK;
    }
    lapped__frame(P, g);
    if (shared == 1) {
        lapped__map_new_vertex(&P->m, p, c, 3 * g + (edge + 2) % 3);
        fresh = 1;
    }
    if (lapped__distortion(&P->m, p, g) > P->o.max_distortion || lapped__folds(P, g)) {
        if (fresh) { /* forget the vertex mapped for it */
            p->vin[c] = 0;
            p->nverts--;
        }
        p->fout[g] = p->stamp;
        p->hard = 1;
        return PW_OK;
    }
    return lapped__join(P, g, centre3, e);
}

/* Grows until no candidate is left; *added gets how many triangles were
 * added. */
static int lapped__grow(lapped__paster *P, const pw_polyhull *hull, pw_v3 centre3, int *added, pw_err *e)
{
    lapped__patchbuf *p = &P->pb;
    int before = p->nfaces, r = PW_OK;
    while (p->queue.n > 0 && r == PW_OK) {
        int g = pw_heap_pop(&p->queue);
        p->fq[g] = 0;
        if (p->fin[g] != p->stamp && p->fout[g] != p->stamp) r = lapped__try_add(P, g, hull, centre3, e);
    }
    *added = p->nfaces - before;
    return r;
}

/* After the optimisation moved the vertices, the boundary may expose more
 * of the texture patch (§3.3: "we further grow the patch"): queue the
 * boundary's outside neighbours again. */
static void lapped__requeue_boundary(lapped__paster *P, pw_v3 centre3)
{
    int i;
    for (i = 0; i < P->pb.nfaces; i++) lapped__push_neighbours(P, P->pb.faces[i], centre3);
}

/* ---- optimising the parametrisation (§3.4) --------------------------------------- */

/* Rows of the least-squares system: for every patch triangle, phi(S) and
 * phi(T) as linear functions of the corner coordinates (coefficient rows
 * w_S, w_T). Field alignment (§3.4) asks phi(S) = s^ = (1,0) and
 * phi(T) = t^ = (0,1): u and v separate into two systems with the same
 * matrix. Texture coordinate j of vertex verts[i] is unknown i.
 *
 * A degenerate triangle has no usable w (they grow as 1/height: a scan's
 * near-collinear triple weighted its two rows 10^5 times above the rest,
 * and the ridge that follows the mean diagonal then shrank whole pastes to
 * 1e-7 of their area). Its rows are written on its edges instead: each
 * edge's texture vector is the one of its flat layout
 * (lapped__sliver_layout), scaled by |T| / (longest edge) like an ordinary
 * triangle's rows. */
static int lapped__align_nrows(const lapped__patchbuf *p)
{
    int i, n = 0;
    for (i = 0; i < p->nfaces; i++) n += p->sliver[p->faces[i]] ? 3 : 2;
    return n;
}

/* One paste's least-squares system (§3.4), allocated once for all pastes:
 * its rows tr, right-hand sides b (u then v for alignment), unknowns x
 * (u then v) and the scratch rhs for the normal equations' Aᵀb. */
typedef struct {
    pw_triplets *tr;
    double *b, *x, *rhs;
} lapped__lsq;

/* |T| / (longest edge) of triangle f: the size of its rows. */
static double lapped__row_weight(const lapped__paster *P, int f)
{
    double longest = 0.0, t = pw_v3_len(pw_v3_load(P->pb.ft + 3 * f));
    int k;
    for (k = 0; k < 3; k++) {
        double l = pw_v3_len(pw_v3_sub(pw_trimesh_corner(&P->m, f, k), pw_trimesh_corner(&P->m, f, (k + 1) % 3)));
        if (l > longest) longest = l;
    }
    return longest > 0.0 && t > 0.0 ? t / longest : 1.0;
}

/* The three edge rows of degenerate triangle f from row `row` on. */
static int lapped__sliver_rows(lapped__paster *P, int f, int row, const lapped__lsq *ls, pw_err *e)
{
    pw_triplets *tr = ls->tr;
    double *bu = ls->b, *bv = ls->b + tr->n;
    double w = lapped__row_weight(P, f);
    float l[6];
    int k, r = PW_OK;
    lapped__sliver_layout(&P->m, &P->pb, f, l);
    for (k = 0; k < 3 && r == PW_OK; k++) {
        int i = P->m.tri[3 * f + k], j = P->m.tri[3 * f + (k + 1) % 3], kj = (k + 1) % 3;
        r = pw_triplets_add(tr, row + k, P->pb.vloc[j], w, e);
        if (r == PW_OK) r = pw_triplets_add(tr, row + k, P->pb.vloc[i], -w, e);
        bu[row + k] = w * (l[2 * kj] - l[2 * k]);
        bv[row + k] = w * (l[2 * kj + 1] - l[2 * k + 1]);
    }
    return r;
}

/* Rows of the alignment system (§3.4) into ls: u right-hand sides in
 * ls->b, v ones after them. */
static int lapped__align_rows(lapped__paster *P, const lapped__lsq *ls, pw_err *e)
{
    lapped__patchbuf *p = &P->pb;
    pw_triplets *tr = ls->tr;
    double *bu = ls->b, *bv = ls->b + tr->n;
    int i, k, row = 0, r = PW_OK;
    for (i = 0; i < p->nfaces && r == PW_OK; i++) {
        int f = p->faces[i];
        float ws[3], wt[3];
        if (p->sliver[f]) {
            r = lapped__sliver_rows(P, f, row, ls, e);
            row += 3;
            continue;
        }
        lapped__coeffs(&P->m, f, pw_v3_load(p->fs + 3 * f), ws);
        lapped__coeffs(&P->m, f, pw_v3_load(p->ft + 3 * f), wt);
        for (k = 0; k < 3 && r == PW_OK; k++) {
            int col = p->vloc[P->m.tri[3 * f + k]];
            r = pw_triplets_add(tr, row, col, ws[k], e);
            if (r == PW_OK) r = pw_triplets_add(tr, row + 1, col, wt[k], e);
        }
        bu[row] = 1.0;
        bu[row + 1] = 0.0;
        bv[row] = 0.0;
        bv[row + 1] = 1.0;
        row += 2;
    }
    return r;
}

/* Conformal rows of degenerate triangle f (rows 2i, 2i+1): with z1, z2 its
 * edges from corner 0 in its flat layout (complex), z2 (U1 - U0) =
 * z1 (U2 - U0), Lévy et al.'s form, which needs no inverse; scaled by
 * (|T| / longest edge)^2. */
static int lapped__sliver_lscm(lapped__paster *P, int f, int i, pw_triplets *tr, pw_err *e)
{
    const int *t = P->m.tri + 3 * f;
    double w = lapped__row_weight(P, f), cu[3], cv[3], iu[3], iv[3];
    float l[6], *z1 = l + 2, *z2 = l + 4;
    int k, n = P->pb.nverts, r = PW_OK;
    w *= w;
    lapped__sliver_layout(&P->m, &P->pb, f, l);
    /* real part: a2 du1 - b2 dv1 - a1 du2 + b1 dv2; imaginary: b2 du1 + a2 dv1 - b1 du2 - a1 dv2 */
    cu[1] = z2[0];
    cv[1] = -z2[1];
    cu[2] = -z1[0];
    cv[2] = z1[1];
    iu[1] = z2[1];
    iv[1] = z2[0];
    iu[2] = -z1[1];
    iv[2] = -z1[0];
    cu[0] = -cu[1] - cu[2];
    cv[0] = -cv[1] - cv[2];
    iu[0] = -iu[1] - iu[2];
    iv[0] = -iv[1] - iv[2];
    for (k = 0; k < 3 && r == PW_OK; k++) {
        int col = P->pb.vloc[t[k]];
        r = pw_triplets_add(tr, 2 * i, col, w * cu[k], e);
        if (r == PW_OK) r = pw_triplets_add(tr, 2 * i, n + col, w * cv[k], e);
        if (r == PW_OK) r = pw_triplets_add(tr, 2 * i + 1, col, w * iu[k], e);
        if (r == PW_OK) r = pw_triplets_add(tr, 2 * i + 1, n + col, w * iv[k], e);
    }
    return r;
}

/* The pins of the least-squares conformal map: phi(S), phi(T) of triangle
 * f (the seed, or the first non-degenerate patch triangle when the seed is
 * degenerate) equal to the texture axes; when every patch triangle is
 * degenerate, the seed's two edges from corner 0 equal its flat layout's. */
static int lapped__lscm_pins(lapped__paster *P, int seed, int rows, pw_triplets *tr, double *b, pw_err *e)
{
    lapped__patchbuf *p = &P->pb;
    int i, k, f = seed, n = p->nverts, r = PW_OK;
    for (i = 0; p->sliver[f] && i < p->nfaces; i++) f = p->faces[i];
    for (i = 0; i < 2 && r == PW_OK; i++) { /* phi(S_f) = (1,0), phi(T_f) = (0,1) */
        float w[3] = {0.0f, 0.0f, 0.0f}, q[2], l[6];
        if (p->sliver[f]) { /* U_{i+1} - U_0 as in its flat layout */
            w[0] = -1.0f;
            w[i + 1] = 1.0f;
            lapped__sliver_layout(&P->m, p, f, l);
            q[0] = l[2 * i + 2];
            q[1] = l[2 * i + 3];
        } else {
            lapped__coeffs(&P->m, f, pw_v3_load((i ? p->ft : p->fs) + 3 * f), w);
            q[0] = i ? 0.0f : 1.0f;
            q[1] = i ? 1.0f : 0.0f;
        }
        for (k = 0; k < 3 && r == PW_OK; k++) {
            int col = p->vloc[P->m.tri[3 * f + k]];
            r = pw_triplets_add(tr, rows + 2 * i, col, w[k], e);
            if (r == PW_OK) r = pw_triplets_add(tr, rows + 2 * i + 1, n + col, w[k], e);
        }
        b[rows + 2 * i] = q[0];
        b[rows + 2 * i + 1] = q[1];
    }
    return r;
}

/* The hindsights' least-squares conformal variant for isotropic textures:
 * phi(S) = rot90(phi(T)), i.e. u.wS - v.wT = 0 and v.wS + u.wT = 0 (u in
 * columns 0..n-1, v in n..2n-1), with the seed triangle's phi(S), phi(T)
 * pinned to the texture axes to fix the similarity. */
static int lapped__lscm_rows(lapped__paster *P, int seed, pw_triplets *tr, double *b, pw_err *e)
{
    lapped__patchbuf *p = &P->pb;
    int i, k, n = p->nverts, rows = 2 * p->nfaces, r = PW_OK;
    for (i = 0; i < p->nfaces && r == PW_OK; i++) {
        int f = p->faces[i];
        float ws[3], wt[3];
        b[2 * i] = b[2 * i + 1] = 0.0;
        if (p->sliver[f]) {
            r = lapped__sliver_lscm(P, f, i, tr, e);
            continue;
        }
        lapped__coeffs(&P->m, f, pw_v3_load(p->fs + 3 * f), ws);
        lapped__coeffs(&P->m, f, pw_v3_load(p->ft + 3 * f), wt);
        for (k = 0; k < 3 && r == PW_OK; k++) {
            int col = p->vloc[P->m.tri[3 * f + k]];
            r = pw_triplets_add(tr, 2 * i, col, ws[k], e);
            if (r == PW_OK) r = pw_triplets_add(tr, 2 * i, n + col, -wt[k], e);
            if (r == PW_OK) r = pw_triplets_add(tr, 2 * i + 1, n + col, ws[k], e);
            if (r == PW_OK) r = pw_triplets_add(tr, 2 * i + 1, col, wt[k], e);
        }
    }
    return r == PW_OK ? lapped__lscm_pins(P, seed, rows, tr, b, e) : r;
}

/* Fill (times the nonzeros of AᵀA) up to which a paste's system that
 * pw_spd_factor's rule leaves to IC(0)-PCG for its fill still gets an LDLᵀ
 * factor: the pastes of a fine mesh (thousands of vertices each, since
 * their count is set by the scale) ran PCG to its iteration cap, 97% of
 * lapped_create's time at 1.2M triangles. */
#define LAPPED__DIRECT_FILL 24

static int lapped__direct(const pw_alloc *a, const pw_csr *N, pw_spd *S, pw_err *e)
{
    pw_ldlt F;
    pw_err local;
    int r;
    if (S->direct || N->n < PW__DIRECT_MIN_SPD) return PW_OK;
    pw_err_clear(&local);
    r = pw__ldlt_factor_capped(a, N, (long)LAPPED__DIRECT_FILL * N->rowptr[N->n], &F, &local);
    if (r == PW_ERR_NOMEM) return pw_fail(e, r, "%s", local.msg);
    if (r != PW_OK) return PW_OK; /* past the cap, or a pivot not positive: PCG stays */
    pw_ic0_free(a, &S->M);
    S->F = F;
    S->direct = 1;
    return PW_OK;
}

/* Solves the least-squares systems A x_j = b_j (nrhs right-hand sides of
 * tr->n rows, unknowns of tr->m columns, warm-started from x; all in ls) through their
 * normal equations AᵀA x = Aᵀb: one sparse LDLᵀ for all right-hand sides
 * where pw_spd_factor's rule takes it (patches of 800 to 20,000 vertices:
 * 0.5-0.9 of the iterative solve's time) or lapped__direct does, else
 * conjugate gradients
 * preconditioned with incomplete Cholesky from the warm start (the paper's
 * CG, §3.4; IC(0) cuts the iterations threefold over Jacobi; on smaller
 * patches it stops after a few iterations). A ridge of 1e-8 of the mean
 * diagonal makes AᵀA
 * definite (the functional ignores translations); it moves nothing but the
 * translation, which lapped__optimize fixes afterwards. Hitting the
 * iteration cap (only patches of tens of thousands of triangles come near
 * it) is not an error here: the warm start is already a usable
 * parametrisation and every iterate improves it. */
static int lapped__solve(lapped__paster *P, const lapped__lsq *ls, int nrhs, pw_err *e)
{
    const pw_triplets *tr = ls->tr;
    const double *b = ls->b;
    double *x = ls->x, *rhs = ls->rhs;
    pw_csr A, N;
    pw_spd S;
    pw_cg_options co = pw_cg_default_options();
    pw_err local;
    double mean = 0.0;
    int r, i, k, j;
    co.tol = 1e-4;
    co.max_iter = 1000; /* IC(0)-CG needs about sqrt(unknowns) iterations: enough up to ~10^5 */
    memset(&N, 0, sizeof N);
    memset(&S, 0, sizeof S);
    if ((r = pw_csr_from_triplets(P->a, tr, &A, e)) != PW_OK) return r;
    if ((r = pw_csr_ata(P->a, &A, &N, e)) == PW_OK) {
        for (i = 0; i < N.n; i++)
            for (k = N.rowptr[i]; k < N.rowptr[i + 1]; k++) mean += N.col[k] == i ? N.val[k] / N.n : 0.0;
        for (i = 0; i < N.n; i++)
            for (k = N.rowptr[i]; k < N.rowptr[i + 1]; k++)
                if (N.col[k] == i) N.val[k] += 1e-8 * mean;
        r = pw_spd_factor(P->a, &N, &S, e);
        if (r == PW_OK) r = lapped__direct(P->a, &N, &S, e);
    }
    for (j = 0; j < nrhs && r == PW_OK; j++) {
        pw_csr_mul_t(&A, b + (size_t)j * A.n, rhs);
        pw_err_clear(&local);
        r = pw_spd_solve(P->a, &S, rhs, x + (size_t)j * A.m, &co, &local);
        if (r == PW_ERR_NOCONVERGE) r = PW_OK;
        else if (r != PW_OK) pw_fail(e, r, "%s", local.msg);
    }
    pw_spd_free(P->a, &S);
    pw_csr_free(P->a, &N);
    pw_csr_free(P->a, &A);
    return r;
}

/* Optimises the patch's coordinates (§3.4), then translates them so the
 * seed point stays at the patch centre ("a positional constraint to fix
 * the location of the patch center": the functional ignores translations,
 * so fixing it afterwards is exact). */
static int lapped__optimize(lapped__paster *P, int seed, const float bary[3], int patch, const lapped__lsq *ls,
                            pw_err *e)
{
    pw_triplets *tr = ls->tr;
    double *x = ls->x, *b = ls->b;
    lapped__patchbuf *p = &P->pb;
    int n = p->nverts, i, j, r, lscm = P->o.lscm && P->o.field == LAPPED_FIELD_ISOTROPIC;
    float du, dv;
    pw_triplets_clear(tr);
    tr->n = lscm ? 2 * p->nfaces + 4 : lapped__align_nrows(p);
    tr->m = lscm ? 2 * n : n;
    for (i = 0; i < n; i++) {
        x[i] = p->vuv[2 * p->verts[i]];
        x[n + i] = p->vuv[2 * p->verts[i] + 1];
    }
    if (lscm) {
        r = lapped__lscm_rows(P, seed, tr, b, e);
        if (r == PW_OK) r = lapped__solve(P, ls, 1, e);
    } else {
        r = lapped__align_rows(P, ls, e);
        if (r == PW_OK) r = lapped__solve(P, ls, 2, e);
    }
    if (r != PW_OK) return r;
    for (i = 0; i < n; i++) lapped__map_vertex(p, p->verts[i], (float)x[i], (float)x[n + i]);
    du = P->centre[2 * patch];
    dv = P->centre[2 * patch + 1];
    for (j = 0; j < 3; j++) {
        int v = P->m.tri[3 * seed + j];
        du -= bary[j] * p->vuv[2 * v];
        dv -= bary[j] * p->vuv[2 * v + 1];
    }
    for (i = 0; i < n; i++) {
        p->vuv[2 * p->verts[i]] += du;
        p->vuv[2 * p->verts[i] + 1] += dv;
    }
    return PW_OK;
}

/* ---- one paste, and the pasting loop ----------------------------------------------- */

/* Records the current patch as a paste and composites it into the
 * coverage (§3.5, §3.6). */
static int lapped__record(lapped__paster *P, int patch, pw_err *e)
{
    lapped__patchbuf *p = &P->pb;
    lapped_paste *q;
    int i, k;
    if (pw_grow(P->a, (void **)&P->pastes, &P->cap, P->npastes + 1, sizeof *P->pastes, "pastes", e))
        return PW_ERR_NOMEM;
    q = &P->pastes[P->npastes];
    q->patch = patch;
    q->nfaces = p->nfaces;
    q->faces = (int *)pw_alloc_array(P->a, (size_t)p->nfaces, sizeof(int), "paste triangles", e);
    q->uvs = (float *)pw_alloc_array(P->a, (size_t)p->nfaces * 6, sizeof(float), "paste coordinates", e);
    if (!q->faces || !q->uvs) {
        pw_free(P->a, q->faces);
        pw_free(P->a, q->uvs);
        return PW_ERR_NOMEM;
    }
    P->npastes++;
    for (i = 0; i < p->nfaces; i++) {
        int f = p->faces[i];
        q->faces[i] = f;
        for (k = 0; k < 3; k++) {
            q->uvs[6 * i + 2 * k] = p->vuv[2 * P->m.tri[3 * f + k]];
            q->uvs[6 * i + 2 * k + 1] = p->vuv[2 * P->m.tri[3 * f + k] + 1];
        }
    }
    lapped__paint(&P->par, &P->cover, q, &P->eroded[patch], P->full);
    for (i = 0; i < p->nfaces; i++)
        if (P->full[i]) lapped__cover_retire(&P->cover, p->faces[i]);
    P->hard_edges += p->hard;
    return PW_OK;
}

/* A random point not yet covered (§3.3): on a random open triangle, at its
 * least covered point. Early in the process, the most difficult of a few
 * open triangles (high curvature, field discontinuities). */
static void lapped__pick(lapped__paster *P, int early, int *f, float b[3])
{
    int k, best = P->cover.open[pw_rng_below(&P->rng, (uint32_t)P->cover.nopen)];
    for (k = 1; early && k < 8; k++) {
        int g = P->cover.open[pw_rng_below(&P->rng, (uint32_t)P->cover.nopen)];
        if (P->difficulty[g] > P->difficulty[best] || (P->difficulty[g] == P->difficulty[best] && g < best)) best = g;
    }
    *f = best;
    lapped__cover_hole(&P->cover, best, b);
}

/* ---- the area guarantee (§3.4) ------------------------------------------------------ */

/* The field asks phi(T) = t^ (§3.4), so a triangle of area A at field
 * scale |T| = S should take A / S^2 of texture (the patch is the unit
 * square). Below LAPPED__AREA_SLACK of the patch (a hundredth of a texel
 * of a 256-texel patch) the comparison means nothing: nothing is drawn
 * there, and a degenerate triangle's surface area is zero. */
#define LAPPED__AREA_SLACK 1e-7

/* Triangle f with corner coordinates uv: its texture area *tex and its
 * surface area over S^2, *surf, where S^2 = |S x T| (the area the frame
 * maps to the unit square; |T|^2 for every field but a caller's FACES). */
static void lapped__tri_areas(const lapped__surface *s, int f, const float uv[6], double *tex, double *surf)
{
    pw_v3 c = pw_v3_cross(pw_v3_load(s->fs + 3 * f), pw_v3_load(s->ft + 3 * f));
    double s2 = (double)c.x * c.x + (double)c.y * c.y + (double)c.z * c.z;
    s2 = sqrt(s2);
    *tex = 0.5 *
           fabs(((double)uv[2] - uv[0]) * ((double)uv[5] - uv[1]) - ((double)uv[4] - uv[0]) * ((double)uv[3] - uv[1]));
    *surf = (double)s->m->area[f] / s2;
}

/* Whether texture area tex, summed over n triangles, is within [lo, hi]
 * times their surf, up to the slack of each triangle: two degenerate
 * triangles of one paste may each hold just under the slack. */
static int lapped__area_ok(double tex, double surf, double lo, double hi, int n)
{
    return tex >= lo * surf - n * LAPPED__AREA_SLACK && tex <= hi * surf + n * LAPPED__AREA_SLACK;
}

/* The areas of one paste (the tests and the fuzzer check the guarantee
 * with them): tex = its texture area, surf = the sum of its A_f / S_f^2,
 * inside = the part of surf whose triangles keep their own ratio within
 * [lo, hi]. */
typedef struct {
    double tex, surf, inside;
} lapped__areas;

static PW__UNUSED void lapped__paste_areas(const lapped__surface *s, const lapped_paste *q, double lo, double hi,
                                           lapped__areas *out)
{
    int i;
    out->tex = out->surf = out->inside = 0.0;
    for (i = 0; i < q->nfaces; i++) {
        double ta, sa;
        lapped__tri_areas(s, q->faces[i], q->uvs + 6 * i, &ta, &sa);
        out->tex += ta;
        out->surf += sa;
        if (lapped__area_ok(ta, sa, lo, hi, 1)) out->inside += sa;
    }
}

/* After the last optimisation: the distortion limit that growth applies
 * to each new triangle (§3.3) applied again to all of them, since the
 * least-squares compromise can stretch a triangle that was fine when it
 * was added. Triangles beyond it leave the paste (later pastes cover
 * them), except the seed, which keeps the pasting progressing. Distortion
 * at most d bounds a triangle's texture area to [1/d^2, d^2] times
 * A / S^2, so with the default d = 2 every pasted triangle, and hence
 * every paste, keeps its area within [0.25, 4] times. A degenerate
 * triangle has no distortion to measure; it leaves when its texture area
 * leaves [1/d^2, d^2] times its surface's. */
static int lapped__trim_out(lapped__paster *P, int f)
{
    lapped__patchbuf *p = &P->pb;
    lapped__surface s;
    float uv[6];
    double ta, sa, d2 = (double)P->o.max_distortion * P->o.max_distortion;
    int k;
    if (!p->sliver[f]) return lapped__distortion(&P->m, p, f) > P->o.max_distortion;
    for (k = 0; k < 3; k++) {
        uv[2 * k] = p->vuv[2 * P->m.tri[3 * f + k]];
        uv[2 * k + 1] = p->vuv[2 * P->m.tri[3 * f + k] + 1];
    }
    s.m = &P->m;
    s.fs = P->fs;
    s.ft = P->ft;
    lapped__tri_areas(&s, f, uv, &ta, &sa);
    return !lapped__area_ok(ta, sa, 1.0 / d2, d2, 1);
}

static void lapped__trim(lapped__paster *P, int seed)
{
    lapped__patchbuf *p = &P->pb;
    int i, n = 0;
    for (i = 0; i < p->nfaces; i++) {
        int f = p->faces[i];
        if (f != seed && lapped__trim_out(P, f)) {
            p->fin[f] = 0;
            p->hard = 1;
            continue;
        }
        p->faces[n++] = f;
    }
    p->nfaces = n;
}

/* Saves (restore = 0) or restores (1) the patch's coordinates. */
static void lapped__keep(lapped__patchbuf *p, int restore)
{
    int i;
    for (i = 0; i < p->nverts; i++) {
        float *uv = p->vuv + 2 * p->verts[i], *k = p->keep + 2 * i;
        if (restore) {
            uv[0] = k[0];
            uv[1] = k[1];
        } else {
            k[0] = uv[0];
            k[1] = uv[1];
        }
    }
}

/* One paste: seed, grow, optimise, grow again where the optimisation
 * uncovered texture, up to three rounds (§3.3, §3.4), trim, record. */
static int lapped__paste(lapped__paster *P, int early, const lapped__lsq *ls, pw_err *e)
{
    int f, patch, round, added = 0, r;
    float bary[3];
    pw_v3 centre3;
    lapped__pick(P, early, &f, bary);
    patch = P->npatches > 1 ? (int)pw_rng_below(&P->rng, (uint32_t)P->npatches) : 0;
    r = lapped__start(P, f, bary, patch, &centre3, e);
    if (r == PW_OK) r = lapped__grow(P, &P->hulls[patch], centre3, &added, e);
    for (round = 0; round < 3 && r == PW_OK; round++) {
        lapped__keep(&P->pb, 0);
        r = lapped__optimize(P, f, bary, patch, ls, e);
        if (r == PW_OK && lapped__trim_out(P, f)) {
            lapped__keep(&P->pb, 1); /* the seed itself got distorted: the last coordinates stay */
            break;
        }
        lapped__requeue_boundary(P, centre3);
        if (r == PW_OK) r = lapped__rehash(P, e);
        if (r == PW_OK) r = lapped__grow(P, &P->hulls[patch], centre3, &added, e);
        if (r != PW_OK || added == 0) break;
    }
    if (r == PW_OK) lapped__trim(P, f);
    return r == PW_OK ? lapped__record(P, patch, e) : r;
}

/* ---- hidden faces (§4) --------------------------------------------------------------- */

/* Drops the pastes that later ones hide completely, keeping the order. */
static void lapped__drop_empty(lapped__paster *P)
{
    size_t p, n = 0;
    for (p = 0; p < P->npastes; p++) {
        if (P->pastes[p].nfaces > 0) {
            P->pastes[n++] = P->pastes[p];
            continue;
        }
        pw_free(P->a, P->pastes[p].faces);
        pw_free(P->a, P->pastes[p].uvs);
    }
    P->npastes = n;
}

/* Removes from each paste the triangles that later pastes hide (§4: "we
 * remove for a given paste operation any faces that are completely
 * occluded by subsequent paste operations"): walking the pastes backwards,
 * a triangle is hidden once the later pastes' opacity, accumulated at its
 * lattice points with the eroded alphas of the coverage (so that it holds
 * between the points too), is 0.999 everywhere. With remove = 0 the
 * triangles stay; the layer counts are the same.
 *
 * On threads, each share of the triangles (a range of them, about equal
 * in lattice points) walks every paste for its own triangles: a
 * triangle's lattice sees the same paints in the same order for any
 * number of threads. hidden[first[p] + i] answers for triangle i of paste p. */
typedef struct lapped__pruning {
    lapped__cover *c;
    const lapped__paster *P;
    const size_t *first;
    unsigned char *hidden;
    int nf, shares;
} lapped__pruning;

/* The first triangle of share k: the lattice points split evenly. */
static int lapped__prune_bound(const lapped__pruning *w, int k)
{
    size_t goal = w->c->off[w->nf] / (size_t)w->shares * (size_t)k;
    int lo = 0, hi = w->nf;
    if (k >= w->shares) return w->nf;
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (w->c->off[mid] < goal) lo = mid + 1;
        else hi = mid;
    }
    return lo;
}

static void lapped__prune_share(void *ctx, int share)
{
    const lapped__pruning *w = (const lapped__pruning *)ctx;
    const lapped__cover *c = w->c;
    int lo = lapped__prune_bound(w, share), hi = lapped__prune_bound(w, share + 1), p, i;
    for (p = (int)w->P->npastes - 1; p >= 0; p--) {
        const lapped_paste *q = &w->P->pastes[p];
        for (i = 0; i < q->nfaces; i++) {
            int f = q->faces[i], hidden = 1;
            const float *acc = c->alpha + c->off[f];
            size_t np = c->off[f + 1] - c->off[f], s;
            if (f < lo || f >= hi) continue;
            for (s = 0; s < np && hidden; s++) hidden = acc[s] >= 0.999f;
            lapped__cover_paint(w->c, f, q->uvs + 6 * i, &w->P->eroded[q->patch]);
            w->hidden[w->first[p] + (size_t)i] = (unsigned char)hidden;
        }
    }
}

static int lapped__prune(lapped__paster *P, int remove, double *before, double *after, pw_err *e)
{
    lapped__cover *c = &P->cover;
    lapped__pruning w;
    size_t *first = (size_t *)pw_alloc_array(P->a, P->npastes + 1, sizeof(size_t), "pruning", e), p;
    unsigned char *hidden = NULL;
    long kept = 0;
    int i, width = pw_parallel_width(&P->par);
    if (first) {
        first[0] = 0;
        for (p = 0; p < P->npastes; p++) first[p + 1] = first[p] + (size_t)P->pastes[p].nfaces;
        hidden = (unsigned char *)pw_alloc_array(P->a, first[P->npastes] + 1, 1, "pruning", e);
    }
    if (!hidden) {
        pw_free(P->a, first);
        return PW_ERR_NOMEM;
    }
    memset(c->alpha, 0, sizeof(float) * c->off[P->m.nf]);
    w.c = c;
    w.P = P;
    w.first = first;
    w.hidden = hidden;
    w.nf = P->m.nf;
    w.shares = width > 1 ? 4 * width : 1;
    pw_parallel_for(&P->par, w.shares, lapped__prune_share, &w);
    for (p = 0; p < P->npastes; p++) {
        lapped_paste *q = &P->pastes[p];
        int n = 0;
        for (i = 0; i < q->nfaces; i++) {
            kept += !hidden[first[p] + (size_t)i];
            if (hidden[first[p] + (size_t)i] && remove) continue;
            q->faces[n] = q->faces[i];
            memmove(q->uvs + 6 * n, q->uvs + 6 * i, sizeof(float) * 6);
            n++;
        }
        q->nfaces = n;
    }
    *before = (double)first[P->npastes] / P->m.nf;
    *after = (double)kept / P->m.nf;
    pw_free(P->a, first);
    pw_free(P->a, hidden);
    lapped__drop_empty(P);
    return PW_OK;
}

/* ---- set-up -------------------------------------------------------------------------- */

/* Where a paste is centred in each patch: its most interior point, the
 * texel farthest (in a 3-4 chamfer distance) from every texel under half
 * opacity, so that the seed point always lands well inside the patch. */
static void lapped__chamfer_at(float *dist, int w, int h, int x, int y, int dir)
{
    static const int dx[4] = {-1, -1, 0, 1}, dy[4] = {0, -1, -1, -1}, cost[4] = {3, 4, 3, 4};
    int k, i = y * w + x;
    for (k = 0; k < 4; k++) { /* the forward mask; the backward one is its mirror */
        int nx = x + dir * dx[k], ny = y + dir * dy[k];
        float d = nx < 0 || ny < 0 || nx >= w || ny >= h ? 0.0f : dist[ny * w + nx]; /* outside: empty */
        if (d + (float)cost[k] < dist[i]) dist[i] = d + (float)cost[k];
    }
}

static void lapped__centre_of(const pw_image *img, float *dist, float out[2])
{
    int w = img->w, h = img->h, x, y, best = 0;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) dist[y * w + x] = img->px[((size_t)y * w + x) * 4 + 3] >= 0.5f ? 1e9f : 0.0f;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) lapped__chamfer_at(dist, w, h, x, y, 1);
    for (y = h - 1; y >= 0; y--)
        for (x = w - 1; x >= 0; x--) lapped__chamfer_at(dist, w, h, x, y, -1);
    for (y = 0; y < w * h; y++)
        if (dist[y] > dist[best]) best = y;
    out[0] = ((float)(best % w) + 0.5f) / (float)w;
    out[1] = 1.0f - ((float)(best / w) + 0.5f) / (float)h;
}

static void lapped__free_pastes(const pw_alloc *a, lapped_paste *pastes, size_t n)
{
    size_t i;
    for (i = 0; pastes && i < n; i++) {
        pw_free(a, pastes[i].faces);
        pw_free(a, pastes[i].uvs);
    }
    pw_free(a, pastes);
}

static void lapped__paster_free(lapped__paster *P)
{
    int k;
    pw_parallel_stop(&P->par);
    for (k = 0; P->hulls && k < P->npatches; k++) pw_polyhull_free(P->a, &P->hulls[k]);
    for (k = 0; P->eroded && k < P->npatches; k++) lapped__eroded_free(P->a, &P->eroded[k]);
    pw_free(P->a, P->hulls);
    pw_free(P->a, P->eroded);
    pw_free(P->a, (void *)P->patches);
    pw_free(P->a, P->centre);
    pw_free(P->a, P->fs);
    pw_free(P->a, P->ft);
    pw_free(P->a, P->difficulty);
    pw_free(P->a, P->full);
    lapped__cover_free(P->a, &P->cover);
    lapped__patchbuf_free(P->a, &P->pb);
    lapped__free_pastes(P->a, P->pastes, P->npastes);
    pw_trimesh_free(P->a, &P->m);
}

/* The caller's patches: RGBA, finite, each reaching full opacity somewhere
 * (a paste centred there is what guarantees progress). Builds their views,
 * hulls (§3.3) and centres. */
static int lapped__setup_patches(lapped__paster *P, const lapped_image *in, int n, pw_err *e)
{
    pw_image *views;
    float *dist = NULL;
    int k, r = PW_OK;
    size_t maxpx = 0;
    if (!in || n < 1 || n > 4096) return pw_fail(e, PW_ERR_INVALID, "need 1..4096 texture patches (got %d)", n);
    views = (pw_image *)pw_calloc_array(P->a, (size_t)n, sizeof(pw_image), "patches", e);
    P->patches = views;
    P->npatches = n;
    P->hulls = (pw_polyhull *)pw_calloc_array(P->a, (size_t)n, sizeof(pw_polyhull), "hulls", e);
    P->eroded = (lapped__eroded *)pw_calloc_array(P->a, (size_t)n, sizeof(lapped__eroded), "erosion", e);
    P->centre = (float *)pw_alloc_array(P->a, (size_t)n * 2, sizeof(float), "patch centres", e);
    if (!views || !P->hulls || !P->eroded || !P->centre) return PW_ERR_NOMEM;
    for (k = 0; k < n && r == PW_OK; k++) {
        char what[32];
        snprintf(what, sizeof what, "patch %d", k);
        if ((r = lapped__check_image(&in[k], what, e)) != PW_OK) break;
        if (in[k].channels != 4)
            return pw_fail(e, PW_ERR_INVALID,
                           "patch %d has %d channels: patches are RGBA (see "
                           "lapped_make_patch)",
                           k, in[k].channels);
        views[k] = lapped__pw_image(&in[k]);
        if ((size_t)in[k].width * in[k].height > maxpx) maxpx = (size_t)in[k].width * in[k].height;
    }
    if (r == PW_OK && !(dist = (float *)pw_alloc_array(P->a, maxpx, sizeof(float), "distances", e))) r = PW_ERR_NOMEM;
    for (k = 0; k < n && r == PW_OK; k++) {
        r = lapped__patch_hull(P->a, &views[k], &P->hulls[k], e);
        if (r == PW_OK) lapped__centre_of(&views[k], dist, P->centre + 2 * k);
        if (r == PW_OK) r = lapped__eroded_init(P->a, &views[k], &P->eroded[k], e);
        if (r == PW_OK) r = lapped__eroded_top(&P->eroded[k], P->centre + 2 * k, P->o.coverage, k, e);
    }
    pw_free(P->a, dist);
    return r;
}

/* The largest side of any patch, in texels. */
static int lapped__max_side(const lapped__paster *P)
{
    int k, m = 1;
    for (k = 0; k < P->npatches; k++) m = pw_maxi(m, pw_maxi(P->patches[k].w, P->patches[k].h));
    return m;
}

/* Roughly how many pastes will be needed: the surface area over the area a
 * paste covers fully (scale^2 times the patch's opaque fraction), twice for
 * the overlap. Used to refuse absurd scales up front and to time the early,
 * difficulty-seeking seeds. */
static double lapped__estimate(const lapped__paster *P)
{
    double need = 0.0, opaque = 0.0;
    int f, k;
    size_t i;
    for (k = 0; k < P->npatches; k++) {
        const pw_image *im = &P->patches[k];
        size_t n = (size_t)im->w * im->h, full = 0;
        for (i = 0; i < n; i++) full += im->px[4 * i + 3] >= P->o.coverage;
        opaque += (double)full / (double)n / P->npatches;
    }
    for (f = 0; f < P->m.nf; f++) {
        double s = pw_v3_len(pw_v3_load(P->ft + 3 * f));
        need += P->m.area[f] / (s * s * (opaque > 1e-6 ? opaque : 1e-6));
    }
    return 2.0 * need;
}

/* |v| in double: a float length overflows for absurd scales. */
static double lapped__len_d(const float *v)
{
    return sqrt((double)v[0] * v[0] + (double)v[1] * v[1] + (double)v[2] * v[2]);
}

/* Every triangle's frame within what a paste can be: S and T no longer
 * than 20 times the mesh's size (one patch would cover the whole mesh) and
 * no shorter than 1e-5 of it (10^10 pastes to cover it). Checked before
 * the paste estimate: one vector that short on a zero-area triangle makes
 * the estimate 0/0, and a frame whose squared length underflows a float
 * has no inverse. */
static int lapped__check_frames(const lapped__paster *P, pw_err *e)
{
    int f, k;
    for (f = 0; f < P->m.nf; f++)
        for (k = 0; k < 2; k++) {
            double len = lapped__len_d((k ? P->fs : P->ft) + 3 * f);
            if (len > 20.0 * P->m.diag)
                return pw_fail(e, PW_ERR_INVALID,
                               "the texture scale %g at triangle %d is more than 20 times the mesh's size "
                               "(%g): one patch would have to cover the whole mesh",
                               len, f, P->m.diag);
            if (!(len >= 1e-5 * P->m.diag))
                return pw_fail(e, PW_ERR_INVALID,
                               "the texture scale %g at triangle %d is under 1e-5 of the mesh's size (%g)", len, f,
                               P->m.diag);
        }
    return PW_OK;
}

static int lapped__setup(lapped__paster *P, const lapped_mesh *mesh, const lapped_image *patches, int npatches,
                         double *estimate, pw_err *e)
{
    lapped__surface surf;
    int nf, r;
    if ((r = lapped__mesh_init(P->a, mesh, &P->m, e)) != PW_OK) return r;
    nf = P->m.nf;
    P->fs = (float *)pw_alloc_array(P->a, (size_t)nf * 3, sizeof(float), "field", e);
    P->ft = (float *)pw_alloc_array(P->a, (size_t)nf * 3, sizeof(float), "field", e);
    P->difficulty = (float *)pw_alloc_array(P->a, (size_t)nf, sizeof(float), "difficulty", e);
    P->full = (unsigned char *)pw_alloc_array(P->a, (size_t)nf, 1, "coverage", e);
    if (!P->fs || !P->ft || !P->difficulty || !P->full) return PW_ERR_NOMEM;
    P->par = pw_parallel_make(P->o.threads, P->o.parallel, P->o.parallel_pool);
    pw_parallel_start(&P->par); /* one crew for every paste's painting and the pruning */
    if ((r = lapped__field(P->a, &P->m, &P->o, P->fs, P->ft, e)) != PW_OK ||
        (r = lapped__difficulty(P->a, &P->m, P->o.field == LAPPED_FIELD_ISOTROPIC ? NULL : P->ft, P->difficulty, e)) !=
            PW_OK ||
        (r = lapped__setup_patches(P, patches, npatches, e)) != PW_OK)
        return r;
    if ((r = lapped__check_frames(P, e)) != PW_OK) return r;
    /* before the coverage lattice, whose size grows as the scale shrinks:
     * the count a fill would reach is 1.4-1.6 times the area estimate
     * (CGAL's elephant, cow, knot and mushroom at four scales), so 1.5
     * times it beyond the limit is refused at once, not after the limit */
    *estimate = lapped__estimate(P);
    if (1.5 * *estimate > P->o.max_pastes)
        return pw_fail(e, PW_ERR_LIMIT,
                       "the texture scale is too small for this mesh: covering it would take about "
                       "%.0f pastes, over the limit of %d (lapped_options.max_pastes; --max-pastes)",
                       1.5 * *estimate, P->o.max_pastes);
    surf.m = &P->m;
    surf.fs = P->fs;
    surf.ft = P->ft;
    if ((r = lapped__cover_init(P->a, &surf, lapped__max_side(P), P->o.coverage, &P->cover, e)) != PW_OK ||
        (r = lapped__patchbuf_init(P->a, &P->m, P->ft, &P->pb, e)) != PW_OK)
        return r;
    P->rng = pw_rng_seed(P->o.seed, 5);
    return PW_OK;
}

/* The pasting loop (§3): until every triangle is covered. */
static int lapped__run(lapped__paster *P, double estimate, pw_err *e)
{
    pw_progress pr = lapped__progress(&P->o);
    pw_triplets tr;
    lapped__lsq ls;
    double *x = (double *)pw_alloc_array(P->a, (size_t)P->m.nv * 4, sizeof(double), "solver unknowns", e);
    double *b = (double *)pw_alloc_array(P->a, (size_t)P->m.nf * 6 + 8, sizeof(double), "solver rows", e);
    int r = x && b ? pw_triplets_init(&tr, P->a, 1, 1, e) : PW_ERR_NOMEM;
    ls.tr = &tr;
    ls.x = x;
    ls.b = b;
    ls.rhs = x ? x + 2 * P->m.nv : NULL;
    if (!x || !b) {
        pw_free(P->a, x);
        pw_free(P->a, b);
        return r;
    }
    while (r == PW_OK && P->cover.nopen > 0) {
        if (P->npastes >= (size_t)P->o.max_pastes)
            r = pw_fail(e, PW_ERR_LIMIT,
                        "stopped after %d pastes with %d triangles still uncovered "
                        "(lapped_options.max_pastes; --max-pastes)",
                        P->o.max_pastes, P->cover.nopen);
        else if (P->npastes % 16 == 0) r = pw_report(&pr, 1.0f - (float)P->cover.nopen / (float)P->m.nf, "pasting", e);
        if (r == PW_OK) r = lapped__paste(P, (double)P->npastes < P->o.early * estimate, &ls, e);
    }
    pw_triplets_free(&tr);
    pw_free(P->a, x);
    pw_free(P->a, b);
    return r;
}

/* Moves the pastes into the caller's lapped_texture. */
static int lapped__output(lapped__paster *P, lapped_texture *out, pw_err *e)
{
    int k;
    memset(out, 0, sizeof *out);
    out->patch_size = (int *)pw_alloc_array(P->a, (size_t)P->npatches * 2, sizeof(int), "patch sizes", e);
    if (!out->patch_size) return PW_ERR_NOMEM;
    for (k = 0; k < P->npatches; k++) {
        out->patch_size[2 * k] = P->patches[k].w;
        out->patch_size[2 * k + 1] = P->patches[k].h;
    }
    out->ntris = P->m.nf;
    out->npatches = P->npatches;
    out->hard_edges = P->hard_edges;
    out->allocator = lapped__allocator(P->a);
    if (lapped__prune(P, !P->o.keep_hidden, &out->layers_before, &out->layers, e) != PW_OK) {
        pw_free(P->a, out->patch_size);
        memset(out, 0, sizeof *out);
        return PW_ERR_NOMEM;
    }
    out->npastes = (int)P->npastes;
    out->pastes = P->pastes;
    P->pastes = NULL;
    P->npastes = 0;
    return PW_OK;
}

LAPPEDDEF lapped_result lapped_create(const lapped_mesh *mesh, const lapped_source *src, const lapped_options *opt,
                                      lapped_texture *out, lapped_error *err)
{
    lapped__paster P;
    pw_alloc a;
    pw_err pe;
    double estimate = 0.0;
    memset(&P, 0, sizeof P);
    pw_err_clear(&pe);
    P.o = lapped__options(opt);
    a = lapped__alloc(&P.o.allocator);
    P.a = &a;
    if (out) memset(out, 0, sizeof *out);
    if (!out) pw_fail(&pe, PW_ERR_INVALID, "lapped_create: NULL output");
    else if (!src) pw_fail(&pe, PW_ERR_INVALID, "lapped_create: no source (texture patches)");
    else if (P.o.threads < 0)
        pw_fail(&pe, PW_ERR_INVALID, "lapped_create: threads %d (0: one per processor)", P.o.threads);
    else if (lapped__setup(&P, mesh, src->patches, src->npatches, &estimate, &pe) == PW_OK &&
             lapped__run(&P, estimate, &pe) == PW_OK)
        lapped__output(&P, out, &pe);
    lapped__paster_free(&P);
    return lapped__done(&pe, err);
}

LAPPEDDEF void lapped_texture_free(lapped_texture *t)
{
    pw_alloc a;
    if (!t) return;
    a = lapped__alloc(&t->allocator);
    lapped__free_pastes(&a, t->pastes, (size_t)t->npastes);
    pw_free(&a, t->patch_size);
    memset(t, 0, sizeof *t);
}
