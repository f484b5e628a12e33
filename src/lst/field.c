/* field.c: §5.2.2, the fields that orient and scale the pastes. The depth
 * field comes from thin-plate radial basis functions in 3D (Turk & O'Brien
 * 1999) through the painted constraints, or, with none, from the distance
 * to the surface; vectors and scales from Laplacian smoothing over the
 * tetrahedral mesh with barycentric point constraints (Eqs. 1-2); the
 * tensor of a tetrahedron is the average of its four vertices'. */
#include "exemplar.c"

/* ---- the mesh every stage works on -------------------------------------------------- */

typedef struct lst__geo {
    pw_tetmesh m; /* borrowed */
    int *nb;      /* 4 nt: face adjacency (pw_tetmesh_neighbors) */
    int *bface;   /* boundary faces 4t+k */
    int nbface;
    pw_tetrings rings;
    pw_tetgrid grid; /* point location (built on demand) */
    double diag;     /* bounding-box diagonal */
} lst__geo;

static void lst__geo_free(const pw_alloc *a, lst__geo *g)
{
    pw_free(a, g->nb);
    pw_free(a, g->bface);
    pw_tetrings_free(a, &g->rings);
    pw_tetgrid_free(a, &g->grid);
    memset(g, 0, sizeof *g);
}

static int lst__geo_init(const pw_alloc *a, const pw_tetmesh *m, lst__geo *g, pw_err *e)
{
    int r;
    memset(g, 0, sizeof *g);
    g->m = *m;
    g->diag = lst__diagonal(m->pos, m->nv);
    if (!(g->nb = (int *)pw_alloc_array(a, (size_t)m->nt * 4, sizeof(int), "face adjacency", e))) return PW_ERR_NOMEM;
    if ((r = pw_tetmesh_neighbors(a, m, g->nb, e)) == PW_OK &&
        (r = pw_tetmesh_boundary(a, m, g->nb, &g->bface, &g->nbface, e)) == PW_OK &&
        (r = pw_tetmesh_rings(a, m, &g->rings, e)) == PW_OK)
        r = pw_tetgrid_build(a, m, &g->grid, e);
    if (r != PW_OK) lst__geo_free(a, g);
    return r;
}

static void lst__vert(const pw_tetmesh *m, int v, double *p)
{
    p[0] = m->pos[3 * v];
    p[1] = m->pos[3 * v + 1];
    p[2] = m->pos[3 * v + 2];
}

/* The corners (global vertices) of boundary face f = 4t+k, outward. */
static void lst__face_verts(const pw_tetmesh *m, int f, int out[3])
{
    int c[3], i;
    pw_tet_face(f & 3, c);
    for (i = 0; i < 3; i++) out[i] = m->tet[4 * (f >> 2) + c[i]];
}

/* The tetrahedron for a point constraint (Eq. 2): the one containing p,
 * else the one whose barycentre is nearest (the paper's rule), with the
 * barycentric coordinates of p in it. */
static int lst__locate(const lst__geo *g, const double p[3], double l[4])
{
    int t = pw_tetgrid_locate(&g->grid, &g->m, p, l), best = 0, k, i;
    double bd = 1e300;
    if (t >= 0) return t;
    for (t = 0; t < g->m.nt; t++) {
        double c[3] = {0, 0, 0}, d = 0.0;
        for (k = 0; k < 4; k++)
            for (i = 0; i < 3; i++) c[i] += 0.25 * g->m.pos[3 * g->m.tet[4 * t + k] + i];
        for (i = 0; i < 3; i++) d += (c[i] - p[i]) * (c[i] - p[i]);
        if (d < bd) {
            bd = d;
            best = t;
        }
    }
    pw_tet_barycentric(&g->m, best, p, l);
    return best;
}

/* ---- thin-plate RBF in 3D (phi(r) = r^3 plus a linear polynomial) ------------------- */

/* A growable list of constrained points with values: what an RBF is fitted
 * through (the depth constraints, §4.3; a stroke's constraints). */
typedef struct lst__pts {
    int n;
    size_t cap;
    double *p;   /* n*3 */
    double *val; /* n, in a parallel array grown with p */
    size_t vcap;
} lst__pts;

typedef struct lst__rbf {
    int n;
    double *c;      /* n*3 centres, in normalised coordinates */
    double *w;      /* n weights, then 4 polynomial coefficients */
    double o[3], s; /* normalisation: x' = (x - o) / s */
} lst__rbf;

static void lst__rbf_free(const pw_alloc *a, lst__rbf *r)
{
    pw_free(a, r->c);
    pw_free(a, r->w);
    memset(r, 0, sizeof *r);
}

/* Solves the dense n x n system m x = b in place by Gaussian elimination
 * with partial pivoting (b receives x); 0 when singular. */
static int lst__dense_solve(double *m, double *b, int n)
{
    int i, j, k;
    for (k = 0; k < n; k++) {
        int p = k;
        for (i = k + 1; i < n; i++)
            if (fabs(m[(size_t)i * n + k]) > fabs(m[(size_t)p * n + k])) p = i;
        if (!(fabs(m[(size_t)p * n + k]) > 1e-300)) return 0;
        if (p != k) {
            double t;
            for (j = 0; j < n; j++) {
                t = m[(size_t)k * n + j];
                m[(size_t)k * n + j] = m[(size_t)p * n + j];
                m[(size_t)p * n + j] = t;
            }
            t = b[k];
            b[k] = b[p];
            b[p] = t;
        }
        for (i = k + 1; i < n; i++) {
            double f = m[(size_t)i * n + k] / m[(size_t)k * n + k];
            if (f == 0.0) continue;
            for (j = k; j < n; j++) m[(size_t)i * n + j] -= f * m[(size_t)k * n + j];
            b[i] -= f * b[k];
        }
    }
    for (k = n - 1; k >= 0; k--) {
        double s = b[k];
        for (j = k + 1; j < n; j++) s -= m[(size_t)k * n + j] * b[j];
        b[k] = s / m[(size_t)k * n + k];
    }
    return 1;
}

static double lst__dist3(const double *a, const double *b)
{
    double d0 = a[0] - b[0], d1 = a[1] - b[1], d2 = a[2] - b[2];
    return sqrt(d0 * d0 + d1 * d1 + d2 * d2);
}

/* Up to k of the n points (n*3), spread out: farthest-point sampling from
 * point 0 (on squared distances: the same order, no square roots); writes
 * their indices to pick and returns how many. */
static int lst__farthest(const double *p, int n, int k, double *dmin, int *pick)
{
    int i, c, cnt = 0;
    for (i = 0; i < n; i++) dmin[i] = 1e300;
    for (c = 0; c < k && c < n; c++) {
        int best = 0;
        const double *q;
        if (c > 0)
            for (i = 1; i < n; i++)
                if (dmin[i] > dmin[best]) best = i;
        if (c > 0 && !(dmin[best] > 0.0)) break; /* only repeats left */
        pick[cnt++] = best;
        q = p + 3 * best;
        for (i = 0; i < n; i++) {
            const double *x = p + 3 * i;
            double d = (x[0] - q[0]) * (x[0] - q[0]) + (x[1] - q[1]) * (x[1] - q[1]) + (x[2] - q[2]) * (x[2] - q[2]);
            if (d < dmin[i]) dmin[i] = d;
        }
    }
    return cnt;
}

/* Fits the RBF through the values of up to maxc of the points pts. The
 * caller sets the normalisation (r->o, r->s); the rest is filled here. */
static int lst__rbf_fit(const pw_alloc *a, const lst__pts *pts, int maxc, lst__rbf *r, pw_err *e)
{
    const double *p = pts->p, *val = pts->val;
    int n = pts->n;
    double o[3], s = r->s;
    double *dmin = (double *)pw_alloc_array(a, (size_t)n, sizeof(double), "RBF", e), *m = NULL;
    int *pick = (int *)pw_alloc_array(a, (size_t)(maxc < n ? maxc : n), sizeof(int), "RBF", e), i, j, k, N;
    memcpy(o, r->o, sizeof o);
    memset(r, 0, sizeof *r);
    memcpy(r->o, o, sizeof r->o);
    r->s = s;
    if (!dmin || !pick) goto nomem;
    r->n = lst__farthest(p, n, maxc, dmin, pick);
    N = r->n + 4;
    r->c = (double *)pw_alloc_array(a, (size_t)r->n * 3, sizeof(double), "RBF centres", e);
    r->w = (double *)pw_calloc_array(a, (size_t)N, sizeof(double), "RBF weights", e);
    m = (double *)pw_calloc_array(a, (size_t)N * N, sizeof(double), "RBF system", e);
    if (!r->c || !r->w || !m) goto nomem;
    for (i = 0; i < r->n; i++)
        for (k = 0; k < 3; k++) r->c[3 * i + k] = (p[3 * pick[i] + k] - o[k]) / s;
    for (i = 0; i < r->n; i++) {
        for (j = 0; j < r->n; j++) {
            double d = lst__dist3(r->c + 3 * i, r->c + 3 * j);
            m[(size_t)i * N + j] = d * d * d + (i == j ? 1e-7 : 0.0); /* a tiny smoothing ridge */
        }
        m[(size_t)i * N + r->n] = m[(size_t)r->n * N + i] = 1.0;
        for (k = 0; k < 3; k++) m[(size_t)i * N + r->n + 1 + k] = m[(size_t)(r->n + 1 + k) * N + i] = r->c[3 * i + k];
        r->w[i] = val[pick[i]];
    }
    if (!lst__dense_solve(m, r->w, N)) {
        pw_free(a, dmin);
        pw_free(a, pick);
        pw_free(a, m);
        lst__rbf_free(a, r);
        return pw_fail(e, PW_ERR_DEGENERATE,
                       "depth constraints: the RBF system is singular (are all "
                       "constraint points on one plane?)");
    }
    pw_free(a, dmin);
    pw_free(a, pick);
    pw_free(a, m);
    return PW_OK;
nomem:
    pw_free(a, dmin);
    pw_free(a, pick);
    pw_free(a, m);
    lst__rbf_free(a, r);
    return PW_ERR_NOMEM;
}

/* The RBF and its gradient (in mesh units) at x. */
static double lst__rbf_eval(const lst__rbf *r, const double *x, double *grad)
{
    double y[3], f, g[3];
    int i, k;
    for (k = 0; k < 3; k++) y[k] = (x[k] - r->o[k]) / r->s;
    f = r->w[r->n] + r->w[r->n + 1] * y[0] + r->w[r->n + 2] * y[1] + r->w[r->n + 3] * y[2];
    for (k = 0; k < 3; k++) g[k] = r->w[r->n + 1 + k];
    for (i = 0; i < r->n; i++) {
        double d[3], len;
        for (k = 0; k < 3; k++) d[k] = y[k] - r->c[3 * i + k];
        len = sqrt(pw_dot3(d, d));
        f += r->w[i] * len * len * len;
        for (k = 0; k < 3; k++) g[k] += 3.0 * r->w[i] * len * d[k];
    }
    if (grad)
        for (k = 0; k < 3; k++) grad[k] = g[k] / r->s;
    return f;
}

/* ---- depth constraints (§4.3) as points ------------------------------------------------- */

static void lst__pts_free(const pw_alloc *a, lst__pts *s)
{
    pw_free(a, s->p);
    pw_free(a, s->val);
    memset(s, 0, sizeof *s);
}

static int lst__pts_add(const pw_alloc *a, lst__pts *s, const double *p, double v, pw_err *e)
{
    if (pw_grow(a, (void **)&s->p, &s->cap, (size_t)s->n * 3 + 3, sizeof(double), "constraint points", e) ||
        pw_grow(a, (void **)&s->val, &s->vcap, (size_t)s->n + 1, sizeof(double), "constraint points", e))
        return PW_ERR_NOMEM;
    memcpy(s->p + 3 * s->n, p, 3 * sizeof(double));
    s->val[s->n++] = v;
    return PW_OK;
}

/* The surface that face constraints name: the caller's (fan-triangulated),
 * or the tetrahedral mesh's boundary (sharing the mesh's positions). */
static int lst__paint_surface(const pw_alloc *a, const lst__geo *g, const lst_mesh *surface, pw_trimesh *tm, pw_err *e)
{
    pw_mesh tmp;
    int f, r;
    if (surface) {
        tmp = lst__pw_mesh(surface);
        return pw_trimesh_init(a, &tmp, tm, e);
    }
    if ((r = pw_mesh_alloc(a, &tmp, 0, g->nbface, 3 * g->nbface, 0, e)) != PW_OK) return r;
    pw_free(a, tmp.pos); /* no positions of its own: the tetrahedral mesh's */
    tmp.nv = g->m.nv;
    tmp.pos = g->m.pos;
    for (f = 0; f < g->nbface; f++) {
        tmp.fstart[f] = 3 * f;
        lst__face_verts(&g->m, g->bface[f], tmp.fv + 3 * f);
    }
    tmp.fstart[g->nbface] = 3 * g->nbface;
    r = pw_trimesh_init(a, &tmp, tm, e);
    tmp.pos = NULL; /* borrowed from the tetrahedral mesh (as the trimesh's) */
    pw_mesh_free(a, &tmp);
    return r;
}

/* §4.3 multi-face fill (constraint c): the triangles reachable from
 * c->face across edges whose dihedral angle is at most c->crease degrees
 * (0: 30) get c->value. */
static int lst__flood(const pw_alloc *a, const pw_trimesh *tm, const lst_constraint *c, double *paint, pw_err *e)
{
    int start = c->face;
    double crease = c->crease > 0.0f ? c->crease : 30.0, v = c->value;
    int *queue = (int *)pw_alloc_array(a, (size_t)tm->nf, sizeof(int), "flood fill", e), head = 0, tail = 0, k;
    unsigned char *seen = (unsigned char *)pw_calloc_array(a, (size_t)tm->nf, 1, "flood fill", e);
    double cmin = pw_cos(crease * (3.14159265358979323846 / 180.0));
    if (!queue || !seen) {
        pw_free(a, queue);
        pw_free(a, seen);
        return PW_ERR_NOMEM;
    }
    queue[tail++] = start;
    seen[start] = 1;
    while (head < tail) {
        int f = queue[head++];
        paint[f] = v;
        for (k = 0; k < 3; k++) {
            int h = pw_trimesh_across(tm, f, k);
            const float *n1 = tm->normal + 3 * f, *n2 = h >= 0 ? tm->normal + 3 * h : n1;
            if (h < 0 || seen[h] || (double)n1[0] * n2[0] + (double)n1[1] * n2[1] + (double)n1[2] * n2[2] < cmin)
                continue;
            seen[h] = 1;
            queue[tail++] = h;
        }
    }
    pw_free(a, queue);
    pw_free(a, seen);
    return PW_OK;
}

/* How many of the options' constraints are of kinds lo..hi. */
static int lst__count_kind(const lst_options *o, lst_constraint_kind lo, lst_constraint_kind hi)
{
    int i, n = 0;
    for (i = 0; i < o->nconstraints; i++) n += o->constraints[i].kind >= lo && o->constraints[i].kind <= hi;
    return n;
}

/* Paint per surface triangle (-1: none) from the face and fill
 * constraints, in order (a later one repaints). */
static int lst__paint(const pw_alloc *a, const pw_trimesh *tm, const lst_options *o, double *paint, pw_err *e)
{
    int i, f;
    for (f = 0; f < tm->nf; f++) paint[f] = -1.0;
    for (i = 0; i < o->nconstraints; i++) {
        const lst_constraint *c = &o->constraints[i];
        if (c->kind != LST_CONSTRAINT_DEPTH_FACE && c->kind != LST_CONSTRAINT_DEPTH_FILL) continue;
        if (c->face < 0 || c->face >= tm->nf)
            return pw_fail(e, PW_ERR_INVALID, "depth constraint %d: face %d is not a triangle of the surface (0..%d)",
                           i, c->face, tm->nf - 1);
        if (c->kind == LST_CONSTRAINT_DEPTH_FACE) paint[c->face] = c->value;
        else if (lst__flood(a, tm, c, paint, e)) return PW_ERR_NOMEM;
    }
    return PW_OK;
}

/* Per surface vertex, the value of its painted triangles when they agree
 * (else -1: a vertex between two colours is no constraint). */
static void lst__vertex_paint(const pw_trimesh *tm, const double *paint, double *vp)
{
    int f, k;
    for (k = 0; k < tm->nv; k++) vp[k] = -2.0; /* untouched */
    for (f = 0; f < tm->nf; f++) {
        if (paint[f] < 0.0) continue;
        for (k = 0; k < 3; k++) {
            double *x = &vp[tm->tri[3 * f + k]];
            *x = *x == -2.0 || *x == paint[f] ? paint[f] : -1.0;
        }
    }
    for (k = 0; k < tm->nv; k++)
        if (vp[k] == -2.0) vp[k] = -1.0;
}

static int lst__check_depth(const lst_options *o, pw_err *e)
{
    int i, k;
    for (i = 0; i < o->nconstraints; i++) {
        const lst_constraint *c = &o->constraints[i];
        if (c->kind > LST_CONSTRAINT_DEPTH_POINT) continue;
        if (!(c->value >= 0.0f && c->value <= 1.0f))
            return pw_fail(e, PW_ERR_INVALID, "depth constraint %d: depth %g is outside [0, 1]", i, c->value);
        if (!pw_is_finite(c->crease) || c->crease < 0.0f || c->crease > 180.0f)
            return pw_fail(e, PW_ERR_INVALID, "depth constraint %d: crease angle %g is outside [0, 180]", i, c->crease);
        for (k = 0; k < 3; k++)
            if (!pw_is_finite(c->point[k]))
                return pw_fail(e, PW_ERR_INVALID, "depth constraint %d: point is not finite", i);
    }
    return PW_OK;
}

/* The surface with the depth the face and fill constraints paint on it. */
typedef struct lst__painted {
    pw_trimesh tm;
    double *face; /* per triangle: painted depth, -1: none (lst__paint) */
    double *vert; /* per vertex: from its triangles, -1: none (lst__vertex_paint) */
} lst__painted;

/* The constraint points: painted vertices, painted triangles' centroids,
 * then the point constraints. */
static int lst__depth_points(const pw_alloc *a, const lst__painted *ps, const lst_options *o, lst__pts *pts, pw_err *e)
{
    const pw_trimesh *tm = &ps->tm;
    const double *paint = ps->face, *vp = ps->vert;
    double p[3];
    int f, v, i, k;
    for (v = 0; v < tm->nv; v++)
        if (vp[v] >= 0.0) {
            for (k = 0; k < 3; k++) p[k] = tm->pos[3 * v + k];
            if (lst__pts_add(a, pts, p, vp[v], e)) return PW_ERR_NOMEM;
        }
    for (f = 0; f < tm->nf; f++)
        if (paint[f] >= 0.0) {
            for (k = 0; k < 3; k++)
                p[k] = (tm->pos[3 * tm->tri[3 * f] + k] + tm->pos[3 * tm->tri[3 * f + 1] + k] +
                        tm->pos[3 * tm->tri[3 * f + 2] + k]) /
                       3.0;
            if (lst__pts_add(a, pts, p, paint[f], e)) return PW_ERR_NOMEM;
        }
    for (i = 0; i < o->nconstraints; i++)
        if (o->constraints[i].kind == LST_CONSTRAINT_DEPTH_POINT) {
            for (k = 0; k < 3; k++) p[k] = o->constraints[i].point[k];
            if (lst__pts_add(a, pts, p, o->constraints[i].value, e)) return PW_ERR_NOMEM;
        }
    return PW_OK;
}

/* Thins the painted points (all but the last `keep`, the point constraints)
 * to every s-th, s chosen so that about 8 per RBF centre remain for the
 * farthest-point sampling: painted surfaces are dense and their points
 * near each other carry the same value. */
static void lst__pts_thin(lst__pts *pts, int keep, int maxc)
{
    int painted = pts->n - keep, stride = painted / (8 * maxc), i, n = 0;
    if (stride < 2) return;
    for (i = 0; i < pts->n; i++)
        if (i >= painted || i % stride == 0) {
            memmove(pts->p + 3 * n, pts->p + 3 * i, 3 * sizeof(double));
            pts->val[n++] = pts->val[i];
        }
    pts->n = n;
}

/* ---- nearest painted surface vertex ----------------------------------------------------- */

/* A uniform grid over points, for nearest-neighbour queries within reach. */
typedef struct lst__hash {
    int n[3];
    double lo[3], cell;
    int *start, *item;
} lst__hash;

static void lst__hash_free(const pw_alloc *a, lst__hash *h)
{
    pw_free(a, h->start);
    pw_free(a, h->item);
    memset(h, 0, sizeof *h);
}

static size_t lst__hash_cell(const lst__hash *h, const double *p, int off[3])
{
    int c[3], k;
    for (k = 0; k < 3; k++) c[k] = pw_clampi((int)((p[k] - h->lo[k]) / h->cell) + (off ? off[k] : 0), 0, h->n[k] - 1);
    return ((size_t)c[2] * h->n[1] + c[1]) * h->n[0] + c[0];
}

/* Buckets of side `cell` over the vertices of tm that keep[] selects (>= 0). */
static int lst__hash_build(const pw_alloc *a, const pw_trimesh *tm, const double *keep, double cell, lst__hash *h,
                           pw_err *e)
{
    const float *pos = tm->pos;
    int n = tm->nv;
    size_t cells, c;
    int i, k;
    double hi[3];
    memset(h, 0, sizeof *h);
    for (k = 0; k < 3; k++) {
        h->lo[k] = 1e300;
        hi[k] = -1e300;
    }
    for (i = 0; i < n; i++)
        if (keep[i] >= 0.0)
            for (k = 0; k < 3; k++) {
                h->lo[k] = pos[3 * i + k] < h->lo[k] ? pos[3 * i + k] : h->lo[k];
                hi[k] = pos[3 * i + k] > hi[k] ? pos[3 * i + k] : hi[k];
            }
    h->cell = cell;
    for (k = 0; k < 3; k++) h->n[k] = hi[k] >= h->lo[k] ? pw_clampi((int)((hi[k] - h->lo[k]) / cell) + 1, 1, 256) : 1;
    for (k = 0; k < 3; k++)
        if ((hi[k] - h->lo[k]) / h->n[k] > h->cell) h->cell = (hi[k] - h->lo[k]) / h->n[k];
    cells = (size_t)h->n[0] * h->n[1] * h->n[2];
    h->start = (int *)pw_calloc_array(a, cells + 1, sizeof(int), "point buckets", e);
    h->item = (int *)pw_alloc_array(a, (size_t)n, sizeof(int), "point buckets", e);
    if (!h->start || !h->item) {
        lst__hash_free(a, h);
        return PW_ERR_NOMEM;
    }
    for (i = 0; i < n; i++) {
        double p[3] = {pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]};
        if (keep[i] >= 0.0) h->start[lst__hash_cell(h, p, NULL) + 1]++;
    }
    for (c = 0; c < cells; c++) h->start[c + 1] += h->start[c];
    for (i = 0; i < n; i++) {
        double p[3] = {pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]};
        if (keep[i] >= 0.0) h->item[h->start[lst__hash_cell(h, p, NULL)]++] = i;
    }
    for (c = cells; c > 0; c--) h->start[c] = h->start[c - 1];
    h->start[0] = 0;
    return PW_OK;
}

/* The nearest kept point within `reach` of p, or -1. */
static int lst__hash_nearest(const lst__hash *h, const float *pos, const double *p, double reach)
{
    int off[3], best = -1, i;
    double bd = reach * reach;
    for (off[2] = -1; off[2] <= 1; off[2]++)
        for (off[1] = -1; off[1] <= 1; off[1]++)
            for (off[0] = -1; off[0] <= 1; off[0]++) {
                size_t c = lst__hash_cell(h, p, off);
                for (i = h->start[c]; i < h->start[c + 1]; i++) {
                    const float *q = pos + 3 * h->item[i];
                    double d =
                        (q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) + (q[2] - p[2]) * (q[2] - p[2]);
                    if (d < bd || (d == bd && best >= 0 && h->item[i] < best)) {
                        bd = d;
                        best = h->item[i];
                    }
                }
            }
    return best;
}

/* §5.2.7: the outer skin must land on the surface exactly, which the
 * smooth RBF only approximates: boundary vertices of the tetrahedral mesh
 * take the value of the nearest painted surface vertex (within the
 * longest surface edge). */
static int lst__depth_snap(const pw_alloc *a, const lst__geo *g, const pw_trimesh *tm, const double *vp, double *depth,
                           pw_err *e)
{
    lst__hash h;
    double reach = 0.0;
    int f, k;
    unsigned char *done;
    for (f = 0; f < tm->nf; f++)
        for (k = 0; k < 3; k++) {
            const float *p = tm->pos + 3 * tm->tri[3 * f + k], *q = tm->pos + 3 * tm->tri[3 * f + (k + 1) % 3];
            double d = sqrt(((double)p[0] - q[0]) * (p[0] - q[0]) + ((double)p[1] - q[1]) * (p[1] - q[1]) +
                            ((double)p[2] - q[2]) * (p[2] - q[2]));
            if (d > reach) reach = d;
        }
    if (!(done = (unsigned char *)pw_calloc_array(a, (size_t)g->m.nv, 1, "depth snap", e))) return PW_ERR_NOMEM;
    if (lst__hash_build(a, tm, vp, reach, &h, e)) {
        pw_free(a, done);
        return PW_ERR_NOMEM;
    }
    for (f = 0; f < g->nbface; f++) {
        int c[3];
        lst__face_verts(&g->m, g->bface[f], c);
        for (k = 0; k < 3; k++) {
            double p[3];
            int near;
            if (done[c[k]]) continue;
            done[c[k]] = 1;
            lst__vert(&g->m, c[k], p);
            if ((near = lst__hash_nearest(&h, tm->pos, p, reach)) >= 0) depth[c[k]] = vp[near];
        }
    }
    lst__hash_free(a, &h);
    pw_free(a, done);
    return PW_OK;
}

/* ---- the depth field ----------------------------------------------------------------------- */

/* What one computation of the fields (§5.2.2) works from: the mesh with its
 * adjacency, the surface the depth constraints are painted on, the
 * options, and where allocation, progress and errors go. */
typedef struct lst__field_job {
    const pw_alloc *a;
    const lst__geo *g;
    const lst_mesh *surface;
    const lst_options *o;
    const pw_progress *p;
    pw_err *e;
} lst__field_job;

/* §5.2.2 thin-plate RBF interpolation of the depth constraints, with its
 * analytic gradient at every vertex; then the boundary snapped to the
 * painted values. */
static int lst__depth_rbf(const lst__field_job *j, double *depth, double *grad)
{
    const pw_alloc *a = j->a;
    const lst__geo *g = j->g;
    const lst_options *o = j->o;
    pw_err *e = j->e;
    lst__painted ps;
    lst__pts pts;
    lst__rbf rbf;
    double lo[3], hi[3], p[3];
    int v, k, r;
    memset(&pts, 0, sizeof pts);
    memset(&rbf, 0, sizeof rbf);
    if ((r = lst__paint_surface(a, g, j->surface, &ps.tm, e)) != PW_OK) return r;
    ps.face = (double *)pw_alloc_array(a, (size_t)ps.tm.nf, sizeof(double), "depth paint", e);
    ps.vert = (double *)pw_alloc_array(a, (size_t)ps.tm.nv, sizeof(double), "depth paint", e);
    r = !ps.face || !ps.vert ? PW_ERR_NOMEM : lst__paint(a, &ps.tm, o, ps.face, e);
    if (r == PW_OK) {
        lst__vertex_paint(&ps.tm, ps.face, ps.vert);
        r = lst__depth_points(a, &ps, o, &pts, e);
    }
    if (r == PW_OK && pts.n < 1) r = pw_fail(e, PW_ERR_INVALID, "depth constraints: none applies");
    if (r == PW_OK)
        lst__pts_thin(&pts, lst__count_kind(o, LST_CONSTRAINT_DEPTH_POINT, LST_CONSTRAINT_DEPTH_POINT), o->rbf_centers);
    if (r == PW_OK) {
        for (k = 0; k < 3; k++) lo[k] = hi[k] = g->m.pos[k];
        for (v = 0; v < g->m.nv; v++)
            for (k = 0; k < 3; k++) {
                lo[k] = g->m.pos[3 * v + k] < lo[k] ? g->m.pos[3 * v + k] : lo[k];
                hi[k] = g->m.pos[3 * v + k] > hi[k] ? g->m.pos[3 * v + k] : hi[k];
            }
        for (k = 0; k < 3; k++) rbf.o[k] = 0.5 * (lo[k] + hi[k]);
        rbf.s = g->diag > 0.0 ? g->diag : 1.0;
        r = lst__rbf_fit(a, &pts, o->rbf_centers, &rbf, e);
    }
    for (v = 0; r == PW_OK && v < g->m.nv; v++) {
        lst__vert(&g->m, v, p);
        depth[v] = lst__rbf_eval(&rbf, p, grad + 3 * v);
        depth[v] = depth[v] < 0.0 ? 0.0 : (depth[v] > 1.0 ? 1.0 : depth[v]);
    }
    if (r == PW_OK) r = lst__depth_snap(a, g, &ps.tm, ps.vert, depth, e);
    lst__rbf_free(a, &rbf);
    lst__pts_free(a, &pts);
    pw_free(a, ps.face);
    pw_free(a, ps.vert);
    pw_trimesh_free(a, &ps.tm);
    return r;
}

/* The point of triangle (a, b, c) closest to p (Ericson, Real-Time
 * Collision Detection, 5.1.5). */
static void lst__closest_tri(const double *p, const double *a, const double *b, const double *c, double *q)
{
    double ab[3], ac[3], ap[3], bp[3], cp[3], d1, d2, d3, d4, d5, d6, va, vb, vc, den, v, w;
    int k;
    for (k = 0; k < 3; k++) {
        ab[k] = b[k] - a[k];
        ac[k] = c[k] - a[k];
        ap[k] = p[k] - a[k];
    }
    d1 = pw_dot3(ab, ap);
    d2 = pw_dot3(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) goto corner_a;
    for (k = 0; k < 3; k++) bp[k] = p[k] - b[k];
    d3 = pw_dot3(ab, bp);
    d4 = pw_dot3(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) {
        memcpy(q, b, 3 * sizeof(double));
        return;
    }
    vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        v = d1 / (d1 - d3);
        for (k = 0; k < 3; k++) q[k] = a[k] + v * ab[k];
        return;
    }
    for (k = 0; k < 3; k++) cp[k] = p[k] - c[k];
    d5 = pw_dot3(ab, cp);
    d6 = pw_dot3(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) {
        memcpy(q, c, 3 * sizeof(double));
        return;
    }
    vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        w = d2 / (d2 - d6);
        for (k = 0; k < 3; k++) q[k] = a[k] + w * ac[k];
        return;
    }
    va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
        w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        for (k = 0; k < 3; k++) q[k] = b[k] + w * (c[k] - b[k]);
        return;
    }
    den = va + vb + vc;
    if (!(den > 0.0)) goto corner_a;
    v = vb / den;
    w = vc / den;
    for (k = 0; k < 3; k++) q[k] = a[k] + ab[k] * v + ac[k] * w;
    return;
corner_a:
    memcpy(q, a, 3 * sizeof(double));
}

/* Distance from p to boundary face f, and the closest point. */
static double lst__face_dist(const lst__geo *g, int f, const double *p, double *q)
{
    int c[3];
    double A[3], B[3], C[3];
    lst__face_verts(&g->m, g->bface[f], c);
    lst__vert(&g->m, c[0], A);
    lst__vert(&g->m, c[1], B);
    lst__vert(&g->m, c[2], C);
    lst__closest_tri(p, A, B, C, q);
    return lst__dist3(p, q);
}

/* Every vertex's distance to the boundary by closest-point propagation:
 * each vertex inherits the nearest boundary face of the neighbour that
 * reaches it first (Dijkstra order), measured exactly. near: nv faces. */
static int lst__boundary_distance(const pw_alloc *a, const lst__geo *g, double *dist, int *near, pw_err *e)
{
    pw_heap h;
    int f, k, v, j;
    double q[3], p[3], d;
    size_t cap = (size_t)g->m.nv + (size_t)g->rings.start[g->m.nv] + 1;
    memset(&h, 0, sizeof h);
    h.key = (double *)pw_alloc_array(a, cap, sizeof(double), "distance heap", e);
    h.item = (int *)pw_alloc_array(a, cap, sizeof(int), "distance heap", e);
    if (!h.key || !h.item) {
        pw_free(a, h.key);
        pw_free(a, h.item);
        return PW_ERR_NOMEM;
    }
    for (v = 0; v < g->m.nv; v++) {
        dist[v] = 1e300;
        near[v] = -1;
    }
    for (f = 0; f < g->nbface; f++) {
        int c[3];
        lst__face_verts(&g->m, g->bface[f], c);
        for (k = 0; k < 3; k++)
            if (near[c[k]] < 0) {
                dist[c[k]] = 0.0;
                near[c[k]] = f;
                pw_heap_insert(&h, 0.0, c[k]);
            }
    }
    while (h.n > 0) {
        d = h.key[0];
        v = pw_heap_pop(&h);
        if (d > dist[v]) continue; /* a stale entry */
        for (j = g->rings.start[v]; j < g->rings.start[v + 1]; j++) {
            int u = g->rings.adj[j];
            lst__vert(&g->m, u, p);
            d = lst__face_dist(g, near[v], p, q);
            if (d < dist[u] && (size_t)h.n < cap) {
                dist[u] = d;
                near[u] = near[v];
                pw_heap_insert(&h, d, u);
            }
        }
    }
    pw_free(a, h.key);
    pw_free(a, h.item);
    return PW_OK;
}

/* §5.2.2 without constraints: depth = distance to the surface divided by
 * the largest distance (at vertices or tetrahedron centres), so 0 on the
 * surface and 1 at the deepest point; its gradient points away from the
 * closest surface point (the inward normal on the surface). */
static int lst__depth_distance(const pw_alloc *a, const lst__geo *g, double *depth, double *grad, pw_err *e)
{
    int *near = (int *)pw_alloc_array(a, (size_t)g->m.nv, sizeof(int), "distance", e), v, t, k, f;
    double M = 0.0, q[3], p[3];
    if (!near || lst__boundary_distance(a, g, depth, near, e)) {
        pw_free(a, near);
        return PW_ERR_NOMEM;
    }
    for (v = 0; v < g->m.nv; v++) M = depth[v] > M && depth[v] < 1e300 ? depth[v] : M;
    for (t = 0; t < g->m.nt; t++) {
        double c[3] = {0, 0, 0}, d = 1e300;
        for (k = 0; k < 4; k++)
            for (f = 0; f < 3; f++) c[f] += 0.25 * g->m.pos[3 * g->m.tet[4 * t + k] + f];
        for (k = 0; k < 4; k++)
            if (near[g->m.tet[4 * t + k]] >= 0) {
                double dd = lst__face_dist(g, near[g->m.tet[4 * t + k]], c, q);
                d = dd < d ? dd : d;
            }
        if (d < 1e300 && d > M) M = d;
    }
    if (!(M > 0.0)) M = g->diag > 0.0 ? g->diag : 1.0;
    for (v = 0; v < g->m.nv; v++) grad[3 * v] = grad[3 * v + 1] = grad[3 * v + 2] = 0.0;
    for (f = 0; f < g->nbface; f++) { /* inward normals of the boundary, area-weighted */
        int c[3];
        double A[3], B[3], C[3], u[3], w[3], n[3];
        lst__face_verts(&g->m, g->bface[f], c);
        lst__vert(&g->m, c[0], A);
        lst__vert(&g->m, c[1], B);
        lst__vert(&g->m, c[2], C);
        for (k = 0; k < 3; k++) {
            u[k] = B[k] - A[k];
            w[k] = C[k] - A[k];
        }
        pw_cross3(u, w, n);
        for (k = 0; k < 3; k++) {
            grad[3 * c[0] + k] -= n[k];
            grad[3 * c[1] + k] -= n[k];
            grad[3 * c[2] + k] -= n[k];
        }
    }
    for (v = 0; v < g->m.nv; v++) {
        double *gr = grad + 3 * v;
        if (depth[v] > 0.0 && depth[v] < 1e300) {
            lst__vert(&g->m, v, p);
            lst__face_dist(g, near[v], p, q);
            for (k = 0; k < 3; k++) gr[k] = p[k] - q[k];
        }
        pw_norm3(gr);
        for (k = 0; k < 3; k++) gr[k] /= M;
        depth[v] = depth[v] < 1e300 ? depth[v] / M : 1.0; /* an unconnected vertex: deepest */
        if (depth[v] > 1.0) depth[v] = 1.0;
    }
    pw_free(a, near);
    return PW_OK;
}

static int lst__depth_field(const lst__field_job *j, double *depth, double *grad)
{
    int r = lst__check_depth(j->o, j->e);
    if (r != PW_OK) return r;
    return lst__count_kind(j->o, LST_CONSTRAINT_DEPTH_FACE, LST_CONSTRAINT_DEPTH_POINT) > 0
               ? lst__depth_rbf(j, depth, grad)
               : lst__depth_distance(j->a, j->g, depth, grad, j->e);
}

/* ---- Laplacian smoothing (Eqs. 1-2) ---------------------------------------------------- */

/* Point constraints located in the mesh: tetrahedron and barycentric
 * coordinates of each. */
typedef struct lst__cons {
    int n;
    int *tet;
    double *bary; /* n*4 */
    double *val;  /* n*dim values */
} lst__cons;

static void lst__cons_free(const pw_alloc *a, lst__cons *c)
{
    pw_free(a, c->tet);
    pw_free(a, c->bary);
    pw_free(a, c->val);
    memset(c, 0, sizeof *c);
}

/* One smoothing system (Eqs. 1-2): the located constraints, their weight
 * W, the least-squares matrix built from them, and the matrix prepared for
 * the solves of every component (a factor of its normal equations where
 * sparse.h's rule finds that pays: one factor, then a cheap solve each). */
typedef struct lst__lsq {
    lst__cons c;
    double W;
    pw_csr A;
    pw_lsq L;
} lst__lsq;

static void lst__lsq_free(const pw_alloc *a, lst__lsq *s)
{
    pw_lsq_free(a, &s->L);
    pw_csr_free(a, &s->A);
    lst__cons_free(a, &s->c);
}

/* The constraints of `kind`, DIRECTION or SCALE (directions made unit,
 * dim 3; scales, dim 1), located. */
static int lst__field_cons(const pw_alloc *a, const lst__geo *g, const lst_options *o, lst_constraint_kind kind,
                           lst__cons *c, pw_err *e)
{
    int i, n = lst__count_kind(o, kind, kind), dim = kind == LST_CONSTRAINT_DIRECTION ? 3 : 1, k;
    memset(c, 0, sizeof *c);
    c->tet = (int *)pw_alloc_array(a, (size_t)n, sizeof(int), "field constraints", e);
    c->bary = (double *)pw_alloc_array(a, (size_t)n * 4, sizeof(double), "field constraints", e);
    c->val = (double *)pw_alloc_array(a, (size_t)n * dim, sizeof(double), "field constraints", e);
    if (!c->tet || !c->bary || !c->val) {
        lst__cons_free(a, c);
        return PW_ERR_NOMEM;
    }
    for (i = 0; i < o->nconstraints; i++) {
        const lst_constraint *f = &o->constraints[i];
        double p[3], d[3];
        if (f->kind != kind) continue;
        for (k = 0; k < 3; k++) {
            p[k] = f->point[k];
            d[k] = f->direction[k];
        }
        if (kind == LST_CONSTRAINT_DIRECTION && !(pw_norm3(d) > 0.0 && pw_is_finite(d[0] + d[1] + d[2])))
            return pw_fail(e, PW_ERR_INVALID, "field constraint %d: the direction is zero or not finite", i);
        if (kind == LST_CONSTRAINT_SCALE && !(f->value > 0.0f && pw_is_finite(f->value)))
            return pw_fail(e, PW_ERR_INVALID, "field constraint %d: scale %g is not positive", i, f->value);
        c->tet[c->n] = lst__locate(g, p, c->bary + 4 * c->n);
        for (k = 0; k < dim; k++) c->val[dim * c->n + k] = kind == LST_CONSTRAINT_DIRECTION ? d[k] : f->value;
        c->n++;
    }
    return PW_OK;
}

/* The least-squares system s->A: a Laplacian row per vertex (Eq. 1: x_i
 * minus the weighted mean of its one-ring; weights uniform, or exp(-(kw(d_i
 * - d_j))^2) normalised when depth is given, §5.2.2), then W times each
 * constraint row (Eq. 2). */
static int lst__smooth_matrix(const lst__field_job *j, const double *depth, double kw, lst__lsq *s)
{
    const pw_alloc *a = j->a;
    const lst__geo *g = j->g;
    const lst__cons *c = &s->c;
    double W = s->W;
    pw_err *e = j->e;
    pw_triplets t;
    int v, jj, i, k, r;
    if ((r = pw_triplets_init(&t, a, g->m.nv + c->n, g->m.nv, e)) != PW_OK) return r;
    for (v = 0; v < g->m.nv && r == PW_OK; v++) {
        double sum = 0.0;
        int lo = g->rings.start[v], hi = g->rings.start[v + 1];
        if (lo == hi) continue; /* an unused vertex keeps its guess */
        for (jj = lo; jj < hi; jj++) {
            double dd = depth ? kw * (depth[v] - depth[g->rings.adj[jj]]) : 0.0;
            sum += depth ? lst__exp_neg(-dd * dd) : 1.0;
        }
        r = pw_triplets_add(&t, v, v, 1.0, e);
        for (jj = lo; jj < hi && r == PW_OK; jj++) {
            double dd = depth ? kw * (depth[v] - depth[g->rings.adj[jj]]) : 0.0;
            r = pw_triplets_add(&t, v, g->rings.adj[jj], -(depth ? lst__exp_neg(-dd * dd) : 1.0) / sum, e);
        }
    }
    for (i = 0; i < c->n && r == PW_OK; i++)
        for (k = 0; k < 4 && r == PW_OK; k++)
            r = pw_triplets_add(&t, g->m.nv + i, g->m.tet[4 * c->tet[i] + k], W * c->bary[4 * i + k], e);
    if (r == PW_OK) r = pw_csr_from_triplets(a, &t, &s->A, e);
    pw_triplets_free(&t);
    if (r == PW_OK) r = pw_lsq_prepare(a, &s->A, &s->L, e);
    return r;
}

/* Solves one component: x (nv, holding the guess) minimising the rows of
 * s->A with right-hand side 0 for the Laplacian rows and W val[dim*i +
 * comp] for constraint i. A solver that stops short of its tolerance still
 * gives a usable smooth field; only memory and cancellation are errors. */
static int lst__smooth_solve(const lst__field_job *j, const lst__lsq *s, int dim, int comp, double *x)
{
    const pw_alloc *a = j->a;
    const pw_csr *A = &s->A;
    const lst__cons *c = &s->c;
    const pw_progress *p = j->p;
    double W = s->W;
    int nv = j->g->m.nv;
    pw_err *e = j->e;
    double *b = (double *)pw_calloc_array(a, (size_t)A->n, sizeof(double), "smoothing", e);
    pw_cg_options co = pw_cg_default_options();
    pw_err local;
    int i, r;
    if (!b) return PW_ERR_NOMEM;
    for (i = 0; i < c->n; i++) b[nv + i] = W * c->val[dim * i + comp];
    co.tol = 1e-7;
    co.max_iter = 4000;
    if (p) co.progress = *p;
    pw_err_clear(&local);
    r = pw_lsq_solve_prepared(a, &s->L, b, x, &co, NULL, &local);
    pw_free(a, b);
    if (r == PW_ERR_NOCONVERGE) return PW_OK;
    if (r != PW_OK) return pw_fail(e, r, "%s", local.msg);
    return PW_OK;
}

/* The principal axis of the shape: the main eigenvector of the
 * covariance of the tetrahedra's centroids, weighted by volume. */
static void lst__principal_axis(const pw_tetmesh *m, double *axis)
{
    double c[3] = {0, 0, 0}, cov[9] = {0}, wsum = 0.0;
    int t, k, i, j;
    for (t = 0; t < m->nt; t++) {
        double w = pw_tet_volume6(m, t);
        for (k = 0; k < 4; k++)
            for (i = 0; i < 3; i++) c[i] += 0.25 * w * m->pos[3 * m->tet[4 * t + k] + i];
        wsum += w;
    }
    for (i = 0; i < 3; i++) c[i] /= wsum > 0.0 ? wsum : 1.0;
    for (t = 0; t < m->nt; t++) {
        double w = pw_tet_volume6(m, t), d[3] = {0, 0, 0};
        for (k = 0; k < 4; k++)
            for (i = 0; i < 3; i++) d[i] += 0.25 * m->pos[3 * m->tet[4 * t + k] + i];
        for (i = 0; i < 3; i++) d[i] -= c[i];
        for (i = 0; i < 3; i++)
            for (j = 0; j < 3; j++) cov[3 * i + j] += w * d[i] * d[j];
    }
    lst__principal(cov, axis);
}

/* §5.2.2 the direction field (unit, per vertex): the constraints smoothed
 * per component (depth-aware weights for 2-a/2-b), normalised; without
 * constraints the given or principal axis everywhere. */
static int lst__direction_field(const lst__field_job *j, const double *depth, double *dir)
{
    const pw_alloc *a = j->a;
    const lst__geo *g = j->g;
    const lst_options *o = j->o;
    pw_err *e = j->e;
    lst__lsq s;
    double axis[3], *x = NULL;
    int v, k, r;
    for (k = 0; k < 3; k++) axis[k] = o->axis[k];
    if (!(pw_norm3(axis) > 0.0)) lst__principal_axis(&g->m, axis);
    for (v = 0; v < g->m.nv; v++) memcpy(dir + 3 * v, axis, sizeof axis);
    memset(&s, 0, sizeof s);
    s.W = o->constraint_weight;
    if ((r = lst__field_cons(a, g, o, LST_CONSTRAINT_DIRECTION, &s.c, e)) != PW_OK || s.c.n == 0) {
        lst__cons_free(a, &s.c);
        return r;
    }
    if (!(x = (double *)pw_alloc_array(a, (size_t)g->m.nv, sizeof(double), "direction field", e))) r = PW_ERR_NOMEM;
    if (r == PW_OK)
        r = lst__smooth_matrix(j, o->type == LST_TYPE_2A || o->type == LST_TYPE_2B ? depth : NULL, o->layer_weight, &s);
    for (k = 0; k < 3 && r == PW_OK; k++) {
        for (v = 0; v < g->m.nv; v++) x[v] = axis[k];
        if ((r = lst__smooth_solve(j, &s, 3, k, x)) == PW_OK)
            for (v = 0; v < g->m.nv; v++) dir[3 * v + k] = x[v];
    }
    for (v = 0; r == PW_OK && v < g->m.nv; v++)
        if (!(pw_norm3(dir + 3 * v) > 1e-12)) memcpy(dir + 3 * v, axis, sizeof axis);
    pw_free(a, x);
    lst__lsq_free(a, &s);
    return r;
}

/* The user's scale field (types 0, 1-a, 2-a): constraints smoothed, or
 * the default everywhere; kept above a thousandth of the default. */
static int lst__scale_field(const lst__field_job *j, double s0, double *scale)
{
    const lst__geo *g = j->g;
    lst__lsq s;
    int v, r;
    for (v = 0; v < g->m.nv; v++) scale[v] = s0;
    memset(&s, 0, sizeof s);
    s.W = j->o->constraint_weight;
    if ((r = lst__field_cons(j->a, g, j->o, LST_CONSTRAINT_SCALE, &s.c, j->e)) != PW_OK || s.c.n == 0) {
        lst__cons_free(j->a, &s.c);
        return r;
    }
    if ((r = lst__smooth_matrix(j, NULL, 1.0, &s)) == PW_OK) r = lst__smooth_solve(j, &s, 1, 0, scale);
    for (v = 0; v < g->m.nv; v++)
        if (!(scale[v] > 1e-3 * s0)) scale[v] = 1e-3 * s0;
    lst__lsq_free(j->a, &s);
    return r;
}

/* ---- tensors per tetrahedron ------------------------------------------------------------ */

/* Orthonormal axes from averaged ones: the primary axis `first` (0 = u,
 * 1 = v) kept, the other orthogonalised against it (or any perpendicular
 * when it has no field), the third their cross product, so that (u, v, w)
 * is right-handed. */
static void lst__orthonormal(double *u, double *v, double *w, int first, int second_given)
{
    double *p = first == 0 ? u : v, *q = first == 0 ? v : u, d;
    int k;
    if (!(pw_norm3(p) > 0.0)) {
        p[0] = first == 0;
        p[1] = first == 1;
        p[2] = 0.0;
    }
    d = pw_dot3(p, q);
    for (k = 0; k < 3; k++) q[k] -= d * p[k];
    if (!second_given || !(pw_norm3(q) > 1e-9)) lst__any_perp(p, q);
    pw_cross3(u, v, w);
}

/* Per tetrahedron: the average of its vertices' direction (u axis),
 * depth gradient (v axis) and scale, made an orthonormal frame times the
 * scale (§5.2.2, "the tensor of a tetrahedron is the average of the
 * tensors of its four vertices"). */
static void lst__tet_frames(const pw_tetmesh *m, int type, const double *dir, const double *grad, const double *scale,
                            float *frame)
{
    int t, k, i;
    for (t = 0; t < m->nt; t++) {
        double u[3] = {0, 0, 0}, v[3] = {0, 0, 0}, w[3], s = 0.0;
        for (k = 0; k < 4; k++) {
            int x = m->tet[4 * t + k];
            for (i = 0; i < 3; i++) {
                if (dir) u[i] += dir[3 * x + i];
                if (grad) v[i] += grad[3 * x + i];
            }
            s += 0.25 * scale[x];
        }
        if (type == LST_TYPE_0) {
            u[0] = 1.0;
            v[1] = 1.0;
        }
        lst__orthonormal(u, v, w, type == LST_TYPE_1B || grad ? 1 : 0, type == LST_TYPE_0 || (dir && grad));
        for (i = 0; i < 3; i++) {
            frame[9 * t + i] = (float)(s * u[i]);
            frame[9 * t + 3 + i] = (float)(s * v[i]);
            frame[9 * t + 6 + i] = (float)(s * w[i]);
        }
    }
}

/* The default exemplar side: a fifth of the bounding-box diagonal. */
static double lst__default_scale(const lst__geo *g, const lst_options *o)
{
    return o->scale > 0.0f ? o->scale : 0.2 * (g->diag > 0.0 ? g->diag : 1.0);
}

/* All of §5.2.2: depth (float per vertex, for types that have one; NULL
 * otherwise) and the frame of every tetrahedron, allocated here. */
static int lst__fields(const lst__field_job *j, float **depth_out, float **frame_out)
{
    const pw_alloc *a = j->a;
    const lst__geo *g = j->g;
    const lst_options *o = j->o;
    pw_err *e = j->e;
    int nv = g->m.nv, v, r = PW_OK, hd = lst__has_depth(o->type);
    double *depth = NULL, *grad = NULL, *dir = NULL, *scale, s0 = lst__default_scale(g, o);
    *depth_out = NULL;
    *frame_out = (float *)pw_alloc_array(a, (size_t)g->m.nt * 9, sizeof(float), "tensor field", e);
    scale = (double *)pw_alloc_array(a, (size_t)nv, sizeof(double), "scale field", e);
    if (hd) {
        depth = (double *)pw_alloc_array(a, (size_t)nv, sizeof(double), "depth field", e);
        grad = (double *)pw_alloc_array(a, (size_t)nv * 3, sizeof(double), "depth field", e);
        *depth_out = (float *)pw_alloc_array(a, (size_t)nv, sizeof(float), "depth field", e);
        if (!depth || !grad || !*depth_out) r = PW_ERR_NOMEM;
    }
    if (lst__has_direction(o->type) &&
        !(dir = (double *)pw_alloc_array(a, (size_t)nv * 3, sizeof(double), "direction field", e)))
        r = PW_ERR_NOMEM;
    if (!*frame_out || !scale) r = PW_ERR_NOMEM;
    if (r == PW_OK && hd) r = lst__depth_field(j, depth, grad);
    if (r == PW_OK && pw_report(j->p, 0.3f, "fields", e) != PW_OK) r = PW_ERR_CANCELLED;
    if (r == PW_OK && dir) r = lst__direction_field(j, depth, dir);
    if (r == PW_OK && lst__depth_varying(o->type)) /* §5.2.7: scale = 1 / |grad depth| */
        for (v = 0; v < nv; v++) {
            double gl = sqrt(pw_dot3(grad + 3 * v, grad + 3 * v)), s = gl > 0.0 ? 1.0 / gl : 2.0 * g->diag;
            scale[v] = s < 1e-3 * g->diag ? 1e-3 * g->diag : (s > 2.0 * g->diag ? 2.0 * g->diag : s);
        }
    else if (r == PW_OK) r = lst__scale_field(j, s0, scale);
    if (r == PW_OK) {
        lst__tet_frames(&g->m, o->type, dir, grad, scale, *frame_out);
        for (v = 0; hd && v < nv; v++) (*depth_out)[v] = (float)depth[v];
    }
    pw_free(a, depth);
    pw_free(a, grad);
    pw_free(a, dir);
    pw_free(a, scale);
    if (r != PW_OK) {
        pw_free(a, *depth_out);
        pw_free(a, *frame_out);
        *depth_out = NULL;
        *frame_out = NULL;
    }
    return r;
}

LSTDEF lst_result lst_compute_field(const lst_tetmesh *mesh, const lst_mesh *surface, const lst_options *opt,
                                    lst_field *out, lst_error *err)
{
    lst_options o = lst__options(opt);
    pw_alloc a = lst__alloc(&o.allocator);
    pw_progress p = lst__progress(&o);
    pw_tetmesh m;
    lst__geo g;
    lst__field_job job;
    pw_err e;
    pw_err_clear(&e);
    job.a = &a;
    job.g = &g;
    job.surface = surface;
    job.o = &o;
    job.p = &p;
    job.e = &e;
    if (out) memset(out, 0, sizeof *out);
    if (!out) pw_fail(&e, PW_ERR_INVALID, "lst_compute_field: NULL output");
    else if (lst__check_options(&o, &e) == PW_OK && lst__check_tets(mesh, &e) == PW_OK) {
        m = lst__pw_tets(mesh);
        if (lst__geo_init(&a, &m, &g, &e) == PW_OK) {
            if (lst__fields(&job, &out->depth, &out->frame) == PW_OK) {
                out->nverts = m.nv;
                out->ntets = m.nt;
                out->allocator = lst__allocator(&a);
            }
            lst__geo_free(&a, &g);
        }
    }
    return lst__done(&e, err);
}

/* ---- growable constraint lists (files, built-in constraints) ---------------------------------- */

typedef struct lst__cset {
    lst_constraint *c;
    int n;
    size_t cap;
} lst__cset;

/* A constraint from its parts (p, d: NULL for none). */
static lst_constraint lst__constraint(lst_constraint_kind kind, int face, const double *p, const double *d,
                                      double value, double crease)
{
    lst_constraint x;
    int k;
    memset(&x, 0, sizeof x);
    x.kind = kind;
    x.face = face;
    x.value = (float)value;
    x.crease = (float)crease;
    for (k = 0; k < 3; k++) {
        x.point[k] = p ? (float)p[k] : 0.0f;
        x.direction[k] = d ? (float)d[k] : 0.0f;
    }
    return x;
}

static int lst__add_constraint(const pw_alloc *a, lst__cset *s, lst_constraint x, pw_err *e)
{
    if (pw_grow(a, (void **)&s->c, &s->cap, (size_t)s->n + 1, sizeof *s->c, "constraints", e)) return PW_ERR_NOMEM;
    s->c[s->n++] = x;
    return PW_OK;
}
