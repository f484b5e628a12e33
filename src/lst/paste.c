/* paste.c: §5.2.3-5.2.7, filling the model. Each paste picks a random
 * uncovered seed tetrahedron, maps it to the exemplar's centre along its
 * tensor (§5.2.4), grows a clump of tetrahedra with a similar tensor that
 * the mask reaches, solves the clump's texture coordinates in the least-
 * squares sense so that every tetrahedron's tensor axes map to the texture
 * axes (§5.2.5), regrows where the warped mask is not covered, and
 * accumulates the mask's alpha at fixed sample points of every tetrahedron
 * until all of them are covered (§5.2.6). Depth-varying types use the depth
 * as the v coordinate and choose the mask by depth (§5.2.7). */
#include "field.c"

/* One paste being built. */
typedef struct lst__spec {
    int seed;         /* seed tetrahedron */
    double centre[4]; /* barycentric coordinates of the texture centre in it */
    double w0[3];     /* texture coordinates there: (0.5, 0.5, 0.5) or (0.5, d_seed, 0.5) */
    double axes[9];   /* the seed's frame for this paste: u, v, w axes (mesh units) */
    double rnd[3];    /* the random direction that completes partial frames (0, 1-a, 1-b) */
    double rot[9];    /* type 0: the random rotation (columns) */
    int mask;         /* mask index */
    int manual;       /* §4.6: one rigid frame for the whole clump */
    int depth_coord;  /* v is the depth (§5.2.7), not solved */
    double inv[9];    /* the affine map (lst__spec_setup): the frame's inverse (tensor axes to texture axes) */
    double ctr[3];    /* and the texture centre in mesh coordinates */
} lst__spec;

/* The state of a fill. */
typedef struct lst__fill {
    const pw_alloc *a;
    lst_options o;
    const lst__geo *g;
    const float *frame; /* nt*9 */
    const float *depth; /* nv, for depth-varying types */
    lst__mask mask[3];
    int nmasks;
    int nsamp;                             /* sample points per tetrahedron */
    float *lattice;                        /* nsamp*4 barycentric coordinates, grouped by octant */
    int group[9];                          /* samples group[c] .. group[c+1]-1 lie in octant c (lst__octants) */
    unsigned char *cov;                    /* nt*nsamp accumulated opacity, 0..255 (§5.2.6) */
    int *uncov, *upos, nuncov;             /* the uncovered list and each tetrahedron's place in it (-1: covered) */
    int *opaque;                           /* nt: the latest paste whose opaque core holds the whole tetrahedron */
    unsigned char *seeded;                 /* nt: 1 once the tetrahedron has been a seed */
    unsigned char *full;                   /* 2 nt: per clump tetrahedron, covered now (by shares: lst__coverage) */
    pw_parallel par;                       /* the coverage's threads */
    int threshold;                         /* opacity, 0..255, that counts as covered */
    int *tstamp, *tstate;                  /* nt: paste id of the last visit; 1 in the clump, 2 refused */
    int *vstamp, *vlocal;                  /* nv: paste id; local index of the vertex in the clump */
    int *ctet, nct, *cvert, ncv, *ccorner; /* the clump: tetrahedra, vertices, corners (local) */
    size_t ctcap, cvcap, cccap, wcap;
    double *w; /* ncv*3 texture coordinates */
    lst_paste *pastes;
    int npastes;
    size_t pcap;
    pw_rng rng;
} lst__fill;

/* ---- sample points (§5.2.6) ------------------------------------------------------------ */

/* The midpoint subdivision of a tetrahedron into eight: points 0-3 are its
 * corners, 4-9 the midpoints of edges 01 02 03 12 13 23; four corner
 * tetrahedra, and the middle octahedron cut along 4-9 into four. */
static const int lst__octants[8][4] = {{0, 4, 5, 6}, {4, 1, 7, 8}, {5, 7, 2, 9}, {6, 8, 9, 3},
                                       {4, 9, 5, 6}, {4, 9, 6, 8}, {4, 9, 8, 7}, {4, 9, 7, 5}};
static const int lst__midpoints[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};

/* The octant (lst__octants) holding barycentric point l. */
static int lst__octant_of(const float *l)
{
    double P[10][4], m[16], b[4];
    int c, k, j;
    for (k = 0; k < 4; k++)
        for (j = 0; j < 4; j++) P[k][j] = k == j;
    for (k = 0; k < 6; k++)
        for (j = 0; j < 4; j++) P[4 + k][j] = 0.5 * (P[lst__midpoints[k][0]][j] + P[lst__midpoints[k][1]][j]);
    for (c = 0; c < 8; c++) { /* l = sum_j mu_j P_j: solve for mu, inside when all mu >= 0 */
        for (k = 0; k < 4; k++) {
            for (j = 0; j < 4; j++) m[4 * k + j] = P[lst__octants[c][j]][k];
            b[k] = l[k];
        }
        if (lst__dense_solve(m, b, 4) && b[0] > -1e-9 && b[1] > -1e-9 && b[2] > -1e-9 && b[3] > -1e-9) return c;
    }
    return 7;
}

/* The barycentric lattice of order n: (i, j, k, l) / n with i + j + k + l = n
 * (n = 8 gives the paper's 165 points, corners, edges and faces included),
 * grouped by octant (group: the start of each). */
static int lst__lattice(const pw_alloc *a, int n, float **out, int *group, pw_err *e)
{
    int cnt = (n + 1) * (n + 2) * (n + 3) / 6, i, j, k, c, at = 0, q;
    float *tmp;
    int *oct;
    *out = (float *)pw_alloc_array(a, (size_t)cnt * 4, sizeof(float), "sample points", e);
    tmp = (float *)pw_alloc_array(a, (size_t)cnt * 4, sizeof(float), "sample points", e);
    oct = (int *)pw_alloc_array(a, (size_t)cnt, sizeof(int), "sample points", e);
    if (!*out || !tmp || !oct) {
        pw_free(a, *out);
        pw_free(a, tmp);
        pw_free(a, oct);
        *out = NULL;
        return -1;
    }
    for (i = 0; i <= n; i++)
        for (j = 0; j <= n - i; j++)
            for (k = 0; k <= n - i - j; k++) {
                float *l = tmp + 4 * at;
                l[0] = (float)i / n;
                l[1] = (float)j / n;
                l[2] = (float)k / n;
                l[3] = (float)(n - i - j - k) / n;
                oct[at++] = lst__octant_of(l);
            }
    for (c = 0, at = 0; c < 8; c++) {
        group[c] = at;
        for (q = 0; q < cnt; q++)
            if (oct[q] == c) memcpy(*out + 4 * at++, tmp + 4 * q, 4 * sizeof(float));
    }
    group[8] = at;
    pw_free(a, tmp);
    pw_free(a, oct);
    return cnt;
}

/* ---- frames ---------------------------------------------------------------------------- */

/* Unit vector from v minus its component along unit n (any perpendicular
 * if that vanishes). */
static void lst__perp_to(const double *n, const double *v, double *out)
{
    double d = pw_dot3(n, v);
    int k;
    for (k = 0; k < 3; k++) out[k] = v[k] - d * n[k];
    if (!(pw_norm3(out) > 1e-9)) lst__any_perp(n, out);
}

/* A random unit vector (rejection sampling in the ball: no libm). */
static void lst__random_unit(pw_rng *r, double *v, int dim)
{
    double n2;
    int k;
    do {
        n2 = 0.0;
        for (k = 0; k < dim; k++) {
            v[k] = 2.0 * pw_rng_double(r) - 1.0;
            n2 += v[k] * v[k];
        }
    } while (n2 > 1.0 || n2 < 1e-6);
    n2 = sqrt(n2);
    for (k = 0; k < dim; k++) v[k] /= n2;
}

/* A uniformly random rotation (columns), from a random unit quaternion. */
static void lst__random_rotation(pw_rng *r, double *m)
{
    double q[4], w, x, y, z;
    lst__random_unit(r, q, 4);
    w = q[0];
    x = q[1];
    y = q[2];
    z = q[3];
    m[0] = 1 - 2 * (y * y + z * z);
    m[1] = 2 * (x * y + w * z);
    m[2] = 2 * (x * z - w * y);
    m[3] = 2 * (x * y - w * z);
    m[4] = 1 - 2 * (x * x + z * z);
    m[5] = 2 * (y * z + w * x);
    m[6] = 2 * (x * z + w * y);
    m[7] = 2 * (y * z - w * x);
    m[8] = 1 - 2 * (x * x + y * y);
}

/* The frame of tetrahedron t for paste s (axes u, v, w as columns, mesh
 * units): §5.2.2 "the other direction is chosen randomly when pasting each
 * patch" for 1-a and 1-b (the paste's random direction made perpendicular
 * to the tetrahedron's field axis), a random rotation for type 0, the
 * field itself for 2-a and 2-b, the user's frame for manual pastes. */
static void lst__frame_of(const lst__fill *F, const lst__spec *s, int t, double *ax)
{
    const float *f = F->frame + 9 * (size_t)t;
    double u[3], v[3], w[3], len;
    int k, type = F->o.type;
    if (s->manual) {
        memcpy(ax, s->axes, 9 * sizeof(double));
        return;
    }
    for (k = 0; k < 3; k++) {
        u[k] = f[k];
        v[k] = f[3 + k];
    }
    len = pw_norm3(u);
    pw_norm3(v);
    if (type == LST_TYPE_0) {
        memcpy(u, s->rot, 3 * sizeof u[0]);
        memcpy(v, s->rot + 3, 3 * sizeof v[0]);
    } else if (type == LST_TYPE_1A) lst__perp_to(u, s->rnd, v);
    else if (type == LST_TYPE_1B) lst__perp_to(v, s->rnd, u);
    pw_cross3(u, v, w);
    for (k = 0; k < 3; k++) {
        ax[k] = len * u[k];
        ax[3 + k] = len * v[k];
        ax[6 + k] = len * w[k];
    }
}

/* §5.2.4 "its tensor is not markedly different from that of the seed":
 * the axes that come from a field within max_angle of the seed's, the
 * scale within a factor max_stretch. */
static int lst__similar(const lst__fill *F, const lst__spec *s, const double *ax)
{
    double c = pw_cos(F->o.max_angle * (3.14159265358979323846 / 180.0)), su, st, k;
    int type = F->o.type, a;
    if (s->manual) return 1;
    su = sqrt(pw_dot3(s->axes, s->axes));
    st = sqrt(pw_dot3(ax, ax));
    k = st / su;
    if (k > F->o.max_stretch || k * F->o.max_stretch < 1.0) return 0;
    for (a = 0; a < 2; a++) {
        int field = a == 0 ? lst__has_direction(type) : lst__has_depth(type);
        if (field && pw_dot3(ax + 3 * a, s->axes + 3 * a) < c * st * su) return 0;
    }
    return 1;
}

/* The affine map of §5.2.4 for paste s: texture coordinates of point p,
 * from the seed frame's inverse (tensor axes to texture axes) and the
 * centre (depth-varying pastes replace v, see lst__predict). */
static void lst__affine(const lst__spec *s, const double *p, double *out)
{
    const double *inv = s->inv, *c = s->ctr;
    double d[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
    int k;
    for (k = 0; k < 3; k++) out[k] = s->w0[k] + inv[3 * k] * d[0] + inv[3 * k + 1] * d[1] + inv[3 * k + 2] * d[2];
}

/* §5.2.7: the v coordinate of depth d for a paste of mask m, the depth
 * kept between the exemplar's outermost voxel centres. The lookups clamp
 * to those centres anyway, so the colours are the same; but at exactly
 * v = 0 or 1 (the surface, or an RBF depth constraint of 1) a sample
 * point interpolated from its corners lands just outside the exemplar or
 * just inside it depending on rounding, and the fill's coverage test and
 * the renderer could disagree: a hole in a solid the fill called covered
 * (found by fuzz_lst; tests/test_lst.c depth_at_exemplar_faces). */
static double lst__depth_v(const lst__mask *m, double d)
{
    double lo = 0.5 / m->vol.y;
    return d < lo ? lo : (d > 1.0 - lo ? 1.0 - lo : d);
}

/* ---- the mask over a mapped tetrahedron -------------------------------------------------- */

enum { LST__OUT = 0, LST__PART = 1, LST__CORE = 2 };

/* The centroid g of a mapped tetrahedron and the radius of the ball around
 * it that holds the tetrahedron. */
static double lst__ball(double c[4][3], double *g)
{
    double rad = 0.0;
    int k;
    for (k = 0; k < 3; k++) g[k] = 0.25 * (c[0][k] + c[1][k] + c[2][k] + c[3][k]);
    for (k = 0; k < 4; k++) {
        double d = lst__dist3(c[k], g);
        if (d > rad) rad = d;
    }
    return rad;
}

/* How the mask meets a tetrahedron whose corners map to c[0..3] (each 3
 * texture coordinates): wholly outside its support, wholly inside its
 * opaque core (the distance fields at the centroid against the bounding
 * ball, plus a margin for interpolation, decide: lst__overlap_fields,
 * LST__PART when they do not), or partly, as the sample points tell
 * (§5.2.4 "partially inside the alpha mask", at the points where coverage
 * is measured). */
static int lst__overlap_fields(const lst__mask *m, double c[4][3])
{
    double g[3], lim = lst__ball(c, g) + m->margin;
    if (lst__mask_clear(m, pw_clampf((float)g[0], 0, 1), pw_clampf((float)g[1], 0, 1), pw_clampf((float)g[2], 0, 1),
                        lim))
        return LST__OUT;
    if (g[0] >= 0 && g[0] <= 1 && g[1] >= 0 && g[1] <= 1 && g[2] >= 0 && g[2] <= 1 &&
        m->in[lst__mask_voxel(m, g[0], g[1], g[2])] > lim)
        return LST__CORE;
    return LST__PART;
}

/* The box of voxel coordinates around the points vc[idx[0..3]], widened
 * by LST__BOX_SLACK voxels: it holds every sample point interpolated
 * between them (the float rounding of the interpolation included). */
#define LST__BOX_SLACK 0.01f
static inline void lst__box(float vc[10][3], const int *idx, float *lo, float *hi)
{
    int k, j;
    for (j = 0; j < 3; j++) lo[j] = hi[j] = vc[idx[0]][j];
    for (k = 1; k < 4; k++)
        for (j = 0; j < 3; j++) {
            float x = vc[idx[k]][j];
            lo[j] = x < lo[j] ? x : lo[j];
            hi[j] = x > hi[j] ? x : hi[j];
        }
    for (j = 0; j < 3; j++) {
        lo[j] -= LST__BOX_SLACK * (1.0f + fabsf(lo[j]));
        hi[j] += LST__BOX_SLACK * (1.0f + fabsf(hi[j]));
    }
}

/* lst__overlap_fields, then, when it says LST__PART, the sample points,
 * octant by octant (lst__octants). The samples are taken only where the
 * cells can answer yes: the summed cells (lst__cells_in_box) of the box
 * around the tetrahedron, then around each octant, must hold one with
 * alpha. Exactly what sampling every point says, found sooner: on the
 * kiwi's fill 3.29 -> 3.06 G instructions (callgrind), where the distance
 * field around each octant's centroid cleared less and cost more. */
static int lst__overlap(const lst__fill *F, const lst__mask *m, double c[4][3])
{
    static const int corners[4] = {0, 1, 2, 3};
    float vc[10][3], lo[3], hi[3];
    int k, j, s, q, ov = lst__overlap_fields(m, c);
    if (ov != LST__PART) return ov;
    for (k = 0; k < 4; k++) lst__to_voxel(&m->vol, c[k][0], c[k][1], c[k][2], vc[k]);
    lst__box(vc, corners, lo, hi);
    if (!lst__cells_in_box(m, lo, hi)) return LST__OUT;
    for (k = 0; k < 6; k++)
        for (j = 0; j < 3; j++) vc[4 + k][j] = 0.5f * (vc[lst__midpoints[k][0]][j] + vc[lst__midpoints[k][1]][j]);
    for (q = 0; q < 8; q++) {
        lst__box(vc, lst__octants[q], lo, hi);
        if (!lst__cells_in_box(m, lo, hi)) continue;
        for (s = F->group[q]; s < F->group[q + 1]; s++) {
            const float *l = F->lattice + 4 * s;
            if (lst__cell_any(m, l[0] * vc[0][0] + l[1] * vc[1][0] + l[2] * vc[2][0] + l[3] * vc[3][0],
                              l[0] * vc[0][1] + l[1] * vc[1][1] + l[2] * vc[2][1] + l[3] * vc[3][1],
                              l[0] * vc[0][2] + l[1] * vc[1][2] + l[2] * vc[2][2] + l[3] * vc[3][2]))
                return LST__PART;
        }
    }
    return LST__OUT;
}

/* ---- the clump ----------------------------------------------------------------------------- */

/* The local index of vertex v in the clump being built, adding it with the
 * predicted texture coordinates `pred` if new. */
static int lst__clump_vertex(lst__fill *F, int id, int v, const double *pred, pw_err *e)
{
    if (F->vstamp[v] == id) return F->vlocal[v];
    if (pw_grow(F->a, (void **)&F->cvert, &F->cvcap, (size_t)F->ncv + 1, sizeof(int), "clump", e) ||
        pw_grow(F->a, (void **)&F->w, &F->wcap, (size_t)F->ncv * 3 + 3, sizeof(double), "clump", e))
        return -1;
    F->vstamp[v] = id;
    F->vlocal[v] = F->ncv;
    F->cvert[F->ncv] = v;
    memcpy(F->w + 3 * F->ncv, pred, 3 * sizeof(double));
    return F->ncv++;
}

static int lst__clump_add(lst__fill *F, int id, int t, double c[4][3], pw_err *e)
{
    int k, li;
    if (pw_grow(F->a, (void **)&F->ctet, &F->ctcap, (size_t)F->nct + 1, sizeof(int), "clump", e) ||
        pw_grow(F->a, (void **)&F->ccorner, &F->cccap, (size_t)F->nct * 4 + 4, sizeof(int), "clump", e))
        return PW_ERR_NOMEM;
    for (k = 0; k < 4; k++) {
        if ((li = lst__clump_vertex(F, id, F->g->m.tet[4 * t + k], c[k], e)) < 0) return PW_ERR_NOMEM;
        F->ccorner[4 * F->nct + k] = li;
    }
    F->ctet[F->nct++] = t;
    F->tstate[t] = 1;
    return PW_OK;
}

/* The texture coordinates of t's corners: the clump's where the corner is
 * in it, else the affine map moved by the mean offset of the clump's
 * corners from it (so that regrowth continues the warped map). */
static void lst__predict(const lst__fill *F, const lst__spec *s, int id, int t, double c[4][3])
{
    double off[3] = {0, 0, 0}, p[3], aff[4][3];
    int k, i, n = 0;
    for (k = 0; k < 4; k++) {
        int v = F->g->m.tet[4 * t + k];
        lst__vert(&F->g->m, v, p);
        lst__affine(s, p, aff[k]);
        if (F->vstamp[v] == id) {
            for (i = 0; i < 3; i++) off[i] += F->w[3 * F->vlocal[v] + i] - aff[k][i];
            n++;
        }
    }
    for (k = 0; k < 4; k++) {
        int v = F->g->m.tet[4 * t + k];
        for (i = 0; i < 3; i++)
            c[k][i] = F->vstamp[v] == id ? F->w[3 * F->vlocal[v] + i] : aff[k][i] + (n ? off[i] / n : 0.0);
        if (s->depth_coord) c[k][1] = lst__depth_v(&F->mask[s->mask], F->depth[v]);
    }
}

/* Tries the face neighbours of clump tetrahedra: each not yet in the
 * clump, not refused for its tensor and not already found outside in this
 * round joins when it is partly inside the mask under the (predicted) map.
 * Breadth first over the clump as it grows; returns the number added or -1
 * on failure. tstate: 1 in the clump, 2 refused, 16 + round tested outside. */
static int lst__grow(lst__fill *F, const lst__spec *s, int id, int round, pw_err *e)
{
    int i, k, added = 0;
    for (i = 0; i < F->nct; i++) {
        int t = F->ctet[i];
        for (k = 0; k < 4; k++) {
            int nb = F->g->nb[4 * t + k], u;
            double c[4][3], ax[9];
            if (nb < 0) continue;
            u = nb >> 2;
            if (F->tstamp[u] == id && (F->tstate[u] == 1 || F->tstate[u] == 2 || F->tstate[u] == 16 + round)) continue;
            if (F->tstamp[u] != id) {
                F->tstamp[u] = id;
                lst__frame_of(F, s, u, ax);
                if (!lst__similar(F, s, ax)) {
                    F->tstate[u] = 2;
                    continue;
                }
            }
            F->tstate[u] = 16 + round;
            lst__predict(F, s, id, u, c);
            if (lst__overlap(F, &F->mask[s->mask], c) == LST__OUT) continue;
            if (lst__clump_add(F, id, u, c, e)) return -1;
            added++;
        }
    }
    return added;
}

/* ---- §5.2.5 texture optimisation ------------------------------------------------------------- */

/* The normal equations of the clump's least-squares problem. Tetrahedron i
 * contributes, for each axis a, the row c_a (c_ak = grad lambda_k . A_i,a)
 * with right-hand side e_a: a 4x4 block sum_a c_a c_a^T of the matrix and
 * c_j (for coordinate j) of the right-hand side; the positional constraint
 * adds W^2 c c^T and W^2 c w0. coef: 12 per tetrahedron, kept for the
 * right-hand sides. Returns the weight W. */
static double lst__normal_matrix(lst__fill *F, const lst__spec *s, double *coef, pw_triplets *T, pw_err *e)
{
    double gsum = 0.0, W;
    int i, a, k, l, r = PW_OK;
    for (i = 0; i < F->nct; i++) {
        double g[4][3], ax[9];
        pw_tet_gradients(&F->g->m, F->ctet[i], g);
        lst__frame_of(F, s, F->ctet[i], ax);
        for (a = 0; a < 3; a++) {
            double n2 = 0.0;
            for (k = 0; k < 4; k++) {
                double v = pw_dot3(g[k], ax + 3 * a);
                coef[12 * i + 4 * a + k] = v;
                n2 += v * v;
            }
            gsum += sqrt(n2);
        }
        for (k = 0; k < 4 && r == PW_OK; k++)
            for (l = 0; l < 4 && r == PW_OK; l++) {
                double v = 0.0;
                for (a = 0; a < 3; a++) v += coef[12 * i + 4 * a + k] * coef[12 * i + 4 * a + l];
                r = pw_triplets_add(T, F->ccorner[4 * i + k], F->ccorner[4 * i + l], v, e);
            }
    }
    W = 10.0 * gsum / (3.0 * F->nct);
    for (k = 0; k < 4 && r == PW_OK; k++)
        for (l = 0; l < 4 && r == PW_OK; l++)
            r = pw_triplets_add(T, F->ccorner[k], F->ccorner[l], W * W * s->centre[k] * s->centre[l], e);
    return r == PW_OK ? W : -1.0;
}

/* The clump's texture coordinates minimising, over its tetrahedra i and
 * axes a, |sum_k (grad lambda_k . A_i,a) w_k - e_a|^2 (the transformed
 * tensor axes against the texture axes, Fig. 12), with the positional
 * constraint sum_k c_k w_k = w0 on the seed as a heavily weighted row: the
 * sparse normal equations, solved by conjugate gradients with an
 * incomplete Cholesky factor shared by the coordinates, warm-started from
 * the current ones. The depth coordinate of depth-varying pastes is not
 * solved (§5.2.7). */
static int lst__optimise(lst__fill *F, const lst__spec *s, const pw_progress *p, pw_err *e)
{
    pw_triplets T;
    pw_csr A;
    pw_ic0 L;
    double *coef, *b = NULL, *x = NULL, W = 0.0;
    int i, k, j, r;
    memset(&A, 0, sizeof A);
    memset(&L, 0, sizeof L);
    if (!(coef = (double *)pw_alloc_array(F->a, (size_t)F->nct * 12, sizeof(double), "texture optimisation", e)))
        return PW_ERR_NOMEM;
    if ((r = pw_triplets_init(&T, F->a, F->ncv, F->ncv, e)) == PW_OK) {
        W = lst__normal_matrix(F, s, coef, &T, e);
        r = W < 0.0 ? PW_ERR_NOMEM : pw_csr_from_triplets(F->a, &T, &A, e);
    }
    pw_triplets_free(&T);
    b = (double *)pw_alloc_array(F->a, (size_t)F->ncv, sizeof(double), "texture optimisation", e);
    x = (double *)pw_alloc_array(F->a, (size_t)F->ncv, sizeof(double), "texture optimisation", e);
    if (r == PW_OK && (!b || !x)) r = PW_ERR_NOMEM;
    if (r == PW_OK) r = pw_ic0_factor(F->a, &A, &L, e);
    for (j = 0; j < 3 && r == PW_OK; j++) {
        pw_cg_options co = pw_cg_default_options();
        pw_err local;
        if (j == 1 && s->depth_coord) continue;
        memset(b, 0, sizeof(double) * (size_t)F->ncv);
        for (i = 0; i < F->nct; i++)
            for (k = 0; k < 4; k++) b[F->ccorner[4 * i + k]] += coef[12 * i + 4 * j + k];
        for (k = 0; k < 4; k++) b[F->ccorner[k]] += W * W * s->centre[k] * s->w0[j];
        for (k = 0; k < F->ncv; k++) x[k] = F->w[3 * k + j];
        co.tol = 1e-6;
        co.max_iter = 300;
        if (p) co.progress = *p;
        pw_err_clear(&local);
        r = pw_pcg_solve(F->a, &A, &L, b, x, &co, NULL, &local);
        if (r == PW_ERR_NOCONVERGE) r = PW_OK; /* x is the best iterate: still a fine map */
        else if (r != PW_OK) pw_fail(e, r, "%s", local.msg);
        for (k = 0; r == PW_OK && k < F->ncv; k++) F->w[3 * k + j] = x[k];
    }
    pw_ic0_free(F->a, &L);
    pw_csr_free(F->a, &A);
    pw_free(F->a, coef);
    pw_free(F->a, b);
    pw_free(F->a, x);
    return r;
}

/* ---- §5.2.6 coverage --------------------------------------------------------------------------- */

static void lst__uncover_remove(lst__fill *F, int t)
{
    int pos = F->upos[t], last = F->uncov[--F->nuncov];
    F->uncov[pos] = last;
    F->upos[last] = pos;
    F->upos[t] = -1;
}

/* The mask's alpha of paste `id` accumulated ("over") at the sample points
 * of the clump's uncovered tetrahedra; a tetrahedron whose points all
 * reach the threshold leaves the uncovered list. A tetrahedron inside the
 * paste's opaque core is marked, so that earlier pastes there can be
 * dropped as hidden. Points already opaque are not sampled again.
 *
 * On threads the clump goes in shares, dealt round-robin (tetrahedron i
 * to share i mod shares): the costly tetrahedra, those the paste's edge
 * crosses, sampled point by point, lie together in the clump's order, so
 * contiguous ranges kept one thread waiting (the kiwi's coverage stage on
 * 2 threads, six runs each: median 1.67 times faster with ranges, 1.78
 * dealt). A clump holds each tetrahedron once, and each one's samples and
 * mark are its own. Whether clump tetrahedron i is now covered goes to
 * full[], each share's answers together (share s's j-th at s * per + j,
 * per = ceil(nct / shares)): dealt one by one into full[i], neighbouring
 * bytes came from different threads, and each write fetched the cache
 * line from the other core. The uncovered list changes after, in the
 * clump's order, so the fill is the same for any number of threads. */
typedef struct lst__covering {
    lst__fill *F;
    const lst__mask *m;
    int id, shares, per;
} lst__covering;

static void lst__coverage_share(void *ctx, int share)
{
    const lst__covering *w = (const lst__covering *)ctx;
    lst__fill *F = w->F;
    const lst__mask *m = w->m;
    unsigned char *full = F->full + (size_t)share * w->per;
    int i, j, k, q;
    for (i = share, j = 0; i < F->nct; i += w->shares, j++) {
        int t = F->ctet[i], all = 1, ov;
        unsigned char *cv = F->cov + (size_t)t * F->nsamp;
        double c[4][3];
        float vc[4][3];
        for (k = 0; k < 4; k++) memcpy(c[k], F->w + 3 * F->ccorner[4 * i + k], sizeof c[k]);
        ov = F->upos[t] < 0 ? lst__overlap_fields(m, c) : lst__overlap(F, m, c); /* covered: only the core counts */
        if (ov == LST__CORE) F->opaque[t] = w->id;
        if (F->upos[t] < 0 || ov == LST__OUT) {
            full[j] = 0;
            continue;
        }
        for (k = 0; k < 4; k++) lst__to_voxel(&m->vol, c[k][0], c[k][1], c[k][2], vc[k]);
        for (q = 0; q < F->nsamp; q++) {
            const float *l = F->lattice + 4 * q;
            float al = 1.0f, x, y, z;
            if (cv[q] == 255) continue;
            if (ov != LST__CORE) { /* a cell of zero voxels gives exactly 0: one byte instead of eight floats */
                x = l[0] * vc[0][0] + l[1] * vc[1][0] + l[2] * vc[2][0] + l[3] * vc[3][0];
                y = l[0] * vc[0][1] + l[1] * vc[1][1] + l[2] * vc[2][1] + l[3] * vc[3][1];
                z = l[0] * vc[0][2] + l[1] * vc[1][2] + l[2] * vc[2][2] + l[3] * vc[3][2];
                al = lst__cell_any(m, x, y, z) ? lst__mask_alpha_vox(&m->vol, x, y, z) : 0.0f;
            }
            cv[q] = (unsigned char)(cv[q] + (int)(al * (255 - cv[q]) + 0.5f));
            all &= cv[q] >= F->threshold;
        }
        full[j] = (unsigned char)all;
    }
}

/* Samples below which a clump is covered on the calling thread alone
 * (handing work to the crew, spinning between clumps, costs about as much
 * as this many; at 16384, 583 of the kiwi's 779 clumps stayed on one). */
#define LST__COVER_SERIAL 4096

static void lst__coverage(lst__fill *F, const lst__spec *s, int id)
{
    lst__covering w;
    int i, width = pw_parallel_width(&F->par);
    w.F = F;
    w.m = &F->mask[s->mask];
    w.id = id;
    w.shares =
        width < 2 || (long long)F->nct * F->nsamp < LST__COVER_SERIAL ? 1 : (F->nct < 4 * width ? F->nct : 4 * width);
    w.per = (F->nct + w.shares - 1) / w.shares;
    if (w.shares <= 1) lst__coverage_share(&w, 0);
    else pw_parallel_for(&F->par, w.shares, lst__coverage_share, &w);
    for (i = 0; i < F->nct; i++)
        if (F->full[(size_t)(i % w.shares) * w.per + i / w.shares]) lst__uncover_remove(F, F->ctet[i]);
}

/* Keeps the clump as paste `id`: tetrahedra, corners, vertices and their
 * texture coordinates, allocated to size. */
static int lst__store(lst__fill *F, const lst__spec *s, pw_err *e)
{
    lst_paste *p;
    int k;
    if (pw_grow(F->a, (void **)&F->pastes, &F->pcap, (size_t)F->npastes + 1, sizeof(lst_paste), "pastes", e))
        return PW_ERR_NOMEM;
    p = &F->pastes[F->npastes];
    memset(p, 0, sizeof *p);
    p->exemplar = s->mask;
    p->tets = (int *)pw_alloc_array(F->a, (size_t)F->nct, sizeof(int), "paste", e);
    p->corners = (int *)pw_alloc_array(F->a, (size_t)F->nct * 4, sizeof(int), "paste", e);
    p->verts = (int *)pw_alloc_array(F->a, (size_t)F->ncv, sizeof(int), "paste", e);
    p->uvw = (float *)pw_alloc_array(F->a, (size_t)F->ncv * 3, sizeof(float), "paste", e);
    F->npastes++; /* counted now so that a failure frees what was allocated */
    if (!p->tets || !p->corners || !p->verts || !p->uvw) return PW_ERR_NOMEM;
    p->ntets = F->nct;
    p->nverts = F->ncv;
    memcpy(p->tets, F->ctet, (size_t)F->nct * sizeof(int));
    memcpy(p->corners, F->ccorner, (size_t)F->nct * 4 * sizeof(int));
    memcpy(p->verts, F->cvert, (size_t)F->ncv * sizeof(int));
    for (k = 0; k < 3 * F->ncv; k++) p->uvw[k] = (float)F->w[k];
    return PW_OK;
}

/* ---- one paste ---------------------------------------------------------------------------------- */

/* Seed frame, map and mask of paste s (s->seed, centre, manual frame set). */
static int lst__spec_setup(lst__fill *F, lst__spec *s)
{
    double *inv = s->inv, *ctr = s->ctr;
    double m[9], d = 0.0;
    int k, j;
    if (!s->manual) {
        lst__random_rotation(&F->rng, s->rot);
        lst__random_unit(&F->rng, s->rnd, 3);
        lst__frame_of(F, s, s->seed, s->axes);
    }
    for (k = 0; k < 3; k++)
        for (j = 0; j < 3; j++) m[3 * k + j] = s->axes[3 * j + k]; /* columns u, v, w */
    if (lst__inv3(m, inv) == 0.0) return 0;
    for (k = 0; k < 3; k++) {
        ctr[k] = 0.0;
        for (j = 0; j < 4; j++) ctr[k] += s->centre[j] * F->g->m.pos[3 * F->g->m.tet[4 * s->seed + j] + k];
    }
    s->w0[0] = s->w0[1] = s->w0[2] = 0.5;
    s->depth_coord = !s->manual && F->depth != NULL;
    if (s->depth_coord) {
        for (j = 0; j < 4; j++) d += s->centre[j] * F->depth[F->g->m.tet[4 * s->seed + j]];
        s->mask = lst__mask_for_depth(d);
        s->w0[1] = lst__depth_v(&F->mask[s->mask], d);
    }
    return 1;
}

/* §5.2.4-5.2.6 for one paste. The clump regrows while the optimised map
 * uncovers more of the mask (up to four times); a last regrowth that adds
 * less than a twentieth of the clump keeps the predicted coordinates of
 * what it added (they only reach the mask's fall-off) rather than solving
 * again. */
static int lst__paste_one(lst__fill *F, lst__spec *s, int coverage, const pw_progress *p, pw_err *e)
{
    double c[4][3];
    int id = F->npastes, round, added, r;
    F->nct = F->ncv = 0;
    if (!lst__spec_setup(F, s)) return pw_fail(e, PW_ERR_DEGENERATE, "tetrahedron %d has a degenerate tensor", s->seed);
    lst__predict(F, s, id, s->seed, c);
    F->tstamp[s->seed] = id;
    if ((r = lst__clump_add(F, id, s->seed, c, e)) != PW_OK) return r;
    if (lst__grow(F, s, id, 0, e) < 0) return PW_ERR_NOMEM;
    for (round = 1; round <= 5; round++) {
        if ((r = lst__optimise(F, s, p, e)) != PW_OK) return r;
        if (round == 5 || (added = lst__grow(F, s, id, round, e)) == 0) break;
        if (added < 0) return PW_ERR_NOMEM;
        if (added * 20 < F->nct) break;
    }
    if (coverage) lst__coverage(F, s, id);
    return lst__store(F, s, e);
}

/* ---- the fill ---------------------------------------------------------------------------------- */

static void lst__fill_free(lst__fill *F)
{
    const pw_alloc *a = F->a;
    int k;
    pw_parallel_stop(&F->par);
    for (k = 0; k < F->nmasks; k++) lst__mask_free(a, &F->mask[k]);
    pw_free(a, F->lattice);
    pw_free(a, F->cov);
    pw_free(a, F->uncov);
    pw_free(a, F->upos);
    pw_free(a, F->opaque);
    pw_free(a, F->seeded);
    pw_free(a, F->full);
    pw_free(a, F->tstamp);
    pw_free(a, F->tstate);
    pw_free(a, F->vstamp);
    pw_free(a, F->vlocal);
    pw_free(a, F->ctet);
    pw_free(a, F->cvert);
    pw_free(a, F->ccorner);
    pw_free(a, F->w);
    for (k = 0; k < F->npastes; k++) lst__paste_free(a, &F->pastes[k]);
    pw_free(a, F->pastes);
    memset(F, 0, sizeof *F);
}

/* The scratch of a fill with masks (nmasks of them; coverage: the sample
 * points and the uncovered list too). The caller zeroes *F and sets what
 * the fill works on: F->a, F->o and the mesh F->g. */
static int lst__fill_init(lst__fill *F, const pw_volume *masks, int nmasks, int coverage, pw_err *e)
{
    const pw_alloc *a = F->a;
    const lst_options *o = &F->o;
    int nt = F->g->m.nt, nv = F->g->m.nv, k;
    F->rng = pw_rng_seed(o->seed, 0x157);
    F->threshold = (int)(o->coverage * 255.0f + 0.999f);
    F->tstamp = (int *)pw_alloc_array(a, (size_t)nt, sizeof(int), "fill", e);
    F->tstate = (int *)pw_calloc_array(a, (size_t)nt, sizeof(int), "fill", e);
    F->vstamp = (int *)pw_alloc_array(a, (size_t)nv, sizeof(int), "fill", e);
    F->vlocal = (int *)pw_alloc_array(a, (size_t)nv, sizeof(int), "fill", e);
    F->opaque = (int *)pw_alloc_array(a, (size_t)nt, sizeof(int), "fill", e);
    if (!F->tstamp || !F->tstate || !F->vstamp || !F->vlocal || !F->opaque) return PW_ERR_NOMEM;
    for (k = 0; k < nt; k++) F->tstamp[k] = F->opaque[k] = -1;
    for (k = 0; k < nv; k++) F->vstamp[k] = -1;
    for (k = 0; k < nmasks; k++) {
        if (lst__mask_init(a, &masks[k], &F->mask[k], e)) return e->code;
        F->nmasks = k + 1;
    }
    if ((F->nsamp = lst__lattice(a, o->samples, &F->lattice, F->group, e)) < 0) return PW_ERR_NOMEM;
    if (!coverage) return PW_OK;
    F->cov = (unsigned char *)pw_calloc_array(a, (size_t)nt * F->nsamp, 1, "coverage samples", e);
    F->uncov = (int *)pw_alloc_array(a, (size_t)nt, sizeof(int), "uncovered list", e);
    F->upos = (int *)pw_alloc_array(a, (size_t)nt, sizeof(int), "uncovered list", e);
    F->seeded = (unsigned char *)pw_calloc_array(a, (size_t)nt, 1, "uncovered list", e);
    F->full = (unsigned char *)pw_alloc_array(a, (size_t)nt * 2, 1, "uncovered list", e); /* shares' rounding */
    if (!F->cov || !F->uncov || !F->upos || !F->seeded || !F->full) return PW_ERR_NOMEM;
    F->par = pw_parallel_make(o->threads, o->parallel, o->parallel_pool);
    pw_parallel_start(&F->par); /* one crew for every clump's coverage */
    for (k = 0; k < nt; k++) F->uncov[k] = F->upos[k] = k;
    F->nuncov = nt;
    return PW_OK;
}

/* Where paste of seed t centres the texture: the barycentre (§5.2.4), or,
 * when t was a seed before and is still not covered (a tetrahedron large
 * against the mask, or one the tensor field isolates), its least-covered
 * sample point, so that every paste covers something new and the fill
 * ends. */
static void lst__seed_centre(lst__fill *F, int t, double *c)
{
    const unsigned char *cv = F->cov + (size_t)t * F->nsamp;
    int q, best = 0, k;
    if (!F->seeded[t]) {
        F->seeded[t] = 1;
        c[0] = c[1] = c[2] = c[3] = 0.25;
        return;
    }
    for (q = 1; q < F->nsamp; q++)
        if (cv[q] < cv[best]) best = q;
    for (k = 0; k < 4; k++) c[k] = F->lattice[4 * best + k];
}

/* §5.2.3: pastes at random uncovered seeds until none is left (a progress
 * report before the first paste and every eighth after it). */
static int lst__fill_run(lst__fill *F, const pw_progress *p, pw_err *e)
{
    int r, nt = F->g->m.nt;
    while (F->nuncov > 0) {
        lst__spec s;
        if ((F->npastes & 7) == 0 && pw_report(p, 0.35f + 0.6f * (float)(nt - F->nuncov) / (float)nt, "pasting", e))
            return PW_ERR_CANCELLED;
        if (F->npastes >= F->o.max_pastes)
            return pw_fail(e, PW_ERR_LIMIT,
                           "filling needs more than %d pastes (%d of %d tetrahedra still uncovered): "
                           "a larger scale or a coarser mesh would do",
                           F->o.max_pastes, F->nuncov, nt);
        memset(&s, 0, sizeof s);
        s.seed = F->uncov[pw_rng_below(&F->rng, (uint32_t)F->nuncov)];
        lst__seed_centre(F, s.seed, s.centre);
        if ((r = lst__paste_one(F, &s, 1, p, e)) != PW_OK) return r;
    }
    return PW_OK;
}

/* Drops the entries of paste p's tetrahedra that a later paste's opaque
 * core hides entirely, and the vertices no longer used. */
static void lst__prune_paste(lst_paste *p, int id, const int *opaque, int *map)
{
    int i, k, n = 0, nv = 0;
    for (k = 0; k < p->nverts; k++) map[k] = -1;
    for (i = 0; i < p->ntets; i++) {
        if (opaque[p->tets[i]] > id) continue;
        p->tets[n] = p->tets[i];
        for (k = 0; k < 4; k++) map[p->corners[4 * n + k] = p->corners[4 * i + k]] = 0;
        n++;
    }
    for (k = 0; k < p->nverts; k++) /* new indices in increasing order: moves go down */
        if (map[k] >= 0) {
            map[k] = nv++;
            p->verts[map[k]] = p->verts[k];
            memmove(p->uvw + 3 * map[k], p->uvw + 3 * k, 3 * sizeof(float));
        }
    for (i = 0; i < 4 * n; i++) p->corners[i] = map[p->corners[i]];
    p->ntets = n;
    p->nverts = nv;
}

/* Pruning of every paste (unless keep_hidden), empty pastes dropped; the
 * mean entries per tetrahedron before and after. */
static int lst__prune(lst__fill *F, double *before, double *after, pw_err *e)
{
    size_t tot0 = 0, tot1 = 0, big = 1;
    int p, n = 0, *map;
    for (p = 0; p < F->npastes; p++) {
        tot0 += (size_t)F->pastes[p].ntets;
        if ((size_t)F->pastes[p].nverts > big) big = (size_t)F->pastes[p].nverts;
    }
    if (!(map = (int *)pw_alloc_array(F->a, big, sizeof(int), "pruning", e))) return PW_ERR_NOMEM;
    for (p = 0; p < F->npastes; p++) {
        if (!F->o.keep_hidden) lst__prune_paste(&F->pastes[p], p, F->opaque, map);
        if (F->pastes[p].ntets == 0) {
            lst__paste_free(F->a, &F->pastes[p]);
            continue;
        }
        tot1 += (size_t)F->pastes[p].ntets;
        F->pastes[n++] = F->pastes[p];
    }
    F->npastes = n;
    pw_free(F->a, map);
    *before = (double)tot0 / F->g->m.nt;
    *after = (double)tot1 / F->g->m.nt;
    return PW_OK;
}

/* ---- lst_create ---------------------------------------------------------------------------------- */

/* Fields given by the caller: sizes, finite non-degenerate frames, depth
 * in [0, 1] where the type needs one. */
static int lst__check_fields(const lst_field *f, const pw_tetmesh *m, int type, pw_err *e)
{
    int t, k;
    if (f->nverts != m->nv || f->ntets != m->nt || !f->frame)
        return pw_fail(e, PW_ERR_INVALID, "fields: made for %d vertices and %d tetrahedra, the mesh has %d and %d",
                       f->nverts, f->ntets, m->nv, m->nt);
    if (lst__depth_varying(type) && !f->depth)
        return pw_fail(e, PW_ERR_INVALID, "fields: a depth-varying type needs a depth");
    for (t = 0; t < m->nt; t++) {
        double mm[9], inv[9];
        for (k = 0; k < 9; k++) mm[k] = f->frame[9 * t + k];
        if (!(lst__inv3(mm, inv) > 0.0))
            return pw_fail(e, PW_ERR_INVALID,
                           "fields: the frame of tetrahedron %d is degenerate, left-handed or not finite", t);
    }
    for (k = 0; f->depth && k < m->nv; k++)
        if (!(f->depth[k] >= 0.0f && f->depth[k] <= 1.0f))
            return pw_fail(e, PW_ERR_INVALID, "fields: depth %g at vertex %d is outside [0, 1]", f->depth[k], k);
    return PW_OK;
}

/* A copy of volume src (its first `channels` channels). */
static int lst__copy_volume(const pw_alloc *a, const lst_volume *src, int channels, lst_volume *dst, pw_err *e)
{
    pw_volume v;
    size_t i, n = (size_t)src->width * src->height * src->depth;
    int k;
    if (pw_volume_alloc(a, &v, channels, src->width, src->height, src->depth, e)) return e->code;
    for (i = 0; i < n; i++)
        for (k = 0; k < channels; k++) v.px[i * channels + k] = src->voxels[i * src->channels + k];
    lst__take_volume(&v, a, dst);
    return PW_OK;
}

/* The model's own mesh, texture (alpha, now a mask, dropped), values and masks. */
static int lst__model_start(const pw_alloc *a, const lst_tetmesh *mesh, const lst_source *src, const lst_options *o,
                            lst_model *out, pw_err *e)
{
    const lst_volume *ex = src->exemplar, *values = src->values;
    int r;
    size_t nv = (size_t)mesh->nverts * 3, nt = (size_t)mesh->ntets * 4;
    out->allocator = lst__allocator(a);
    out->type = o->type;
    out->mesh.positions = (float *)pw_alloc_array(a, nv, sizeof(float), "model mesh", e);
    out->mesh.tets = (int *)pw_alloc_array(a, nt, sizeof(int), "model mesh", e);
    out->removed = (unsigned char *)pw_calloc_array(a, (size_t)mesh->ntets, 1, "model mesh", e);
    out->mesh.allocator = out->allocator;
    if (!out->mesh.positions || !out->mesh.tets || !out->removed) return PW_ERR_NOMEM;
    memcpy(out->mesh.positions, mesh->positions, nv * sizeof(float));
    memcpy(out->mesh.tets, mesh->tets, nt * sizeof(int));
    out->mesh.nverts = mesh->nverts;
    out->mesh.ntets = mesh->ntets;
    if ((r = lst__copy_volume(a, ex, ex->channels == 2 || ex->channels == 4 ? ex->channels - 1 : ex->channels,
                              &out->texture, e)) != PW_OK ||
        (values && (r = lst__copy_volume(a, values, values->channels, &out->values, e)) != PW_OK))
        return r;
    return lst__make_masks(a, ex, o, &out->masks, e);
}

static int lst__check_inputs(const lst_tetmesh *mesh, const lst_volume *ex, const lst_volume *values, pw_err *e)
{
    if (lst__check_tets(mesh, e) || lst__check_volume(ex, "exemplar", e)) return e->code;
    if (values && (lst__check_volume(values, "values", e) || values->width != ex->width ||
                   values->height != ex->height || values->depth != ex->depth))
        return e->code ? e->code
                       : pw_fail(e, PW_ERR_INVALID, "values: %dx%dx%d, the exemplar is %dx%dx%d", values->width,
                                 values->height, values->depth, ex->width, ex->height, ex->depth);
    return PW_OK;
}

/* The fill proper on the model's copy of the mesh. */
static int lst__create(const pw_alloc *a, const lst_mesh *surface, const lst_options *o, lst_model *out, pw_err *e)
{
    pw_tetmesh m = lst__pw_tets(&out->mesh);
    pw_progress p = lst__progress(o);
    pw_volume masks[3];
    lst__geo g;
    lst__fill F;
    float *depth = NULL, *frame = NULL;
    int k, r;
    if ((r = lst__geo_init(a, &m, &g, e)) != PW_OK) return r;
    if (o->field) r = lst__check_fields(o->field, &m, o->type, e);
    else {
        lst__field_job job;
        job.a = a;
        job.g = &g;
        job.surface = surface;
        job.o = o;
        job.p = &p;
        job.e = e;
        r = lst__fields(&job, &depth, &frame);
    }
    for (k = 0; k < out->masks.count; k++) masks[k] = lst__pw_volume(&out->masks.volumes[k]);
    memset(&F, 0, sizeof F);
    F.a = a;
    F.o = *o;
    F.g = &g;
    if (r == PW_OK) r = lst__fill_init(&F, masks, out->masks.count, 1, e);
    F.frame = o->field ? o->field->frame : frame;
    F.depth = lst__depth_varying(o->type) ? (o->field ? o->field->depth : depth) : NULL;
    if (r == PW_OK) r = lst__fill_run(&F, &p, e);
    if (r == PW_OK) r = lst__prune(&F, &out->layers_before, &out->layers, e);
    if (r == PW_OK) {
        out->pastes = F.pastes;
        out->npastes = F.npastes;
        F.pastes = NULL;
        F.npastes = 0;
        r = pw_report(&p, 1.0f, "done", e);
    }
    lst__fill_free(&F);
    pw_free(a, depth);
    pw_free(a, frame);
    lst__geo_free(a, &g);
    return r;
}

LSTDEF lst_result lst_create(const lst_tetmesh *mesh, const lst_mesh *surface, const lst_source *src,
                             const lst_options *opt, lst_model *out, lst_error *err)
{
    lst_options o = lst__options(opt);
    pw_alloc a = lst__alloc(&o.allocator);
    const lst_volume *exemplar = src ? src->exemplar : NULL, *values = src ? src->values : NULL;
    pw_err e;
    pw_err_clear(&e);
    if (out) memset(out, 0, sizeof *out);
    if (!out) pw_fail(&e, PW_ERR_INVALID, "lst_create: NULL output");
    else if (lst__check_options(&o, &e) == PW_OK && lst__check_inputs(mesh, exemplar, values, &e) == PW_OK &&
             lst__model_start(&a, mesh, src, &o, out, &e) == PW_OK)
        lst__create(&a, surface, &o, out, &e);
    if (out && e.code != PW_OK) lst_model_free(out);
    return lst__done(&e, err);
}

/* ---- §4.6 manual pasting --------------------------------------------------------------------------- */

static int lst__manual_spec(const lst__geo *g, const lst_paste_spec *spec, lst__spec *s, pw_err *e)
{
    double p[3], u[3], v[3], w[3];
    float scale = spec->scale;
    int k;
    memset(s, 0, sizeof *s);
    for (k = 0; k < 3; k++) {
        p[k] = spec->point[k];
        u[k] = spec->u_axis[k];
        v[k] = spec->v_axis[k];
    }
    if (!pw_is_finite(p[0] + p[1] + p[2]) || !(scale > 0.0f && pw_is_finite(scale)))
        return pw_fail(e, PW_ERR_INVALID, "manual paste: the point or the scale is not valid");
    if (!(pw_norm3(u) > 0.0) || !pw_is_finite(u[0] + u[1] + u[2]) || !pw_is_finite(v[0] + v[1] + v[2]))
        return pw_fail(e, PW_ERR_INVALID, "manual paste: the u axis is zero or not finite");
    lst__perp_to(u, v, v);
    pw_cross3(u, v, w);
    for (k = 0; k < 3; k++) {
        s->axes[k] = scale * u[k];
        s->axes[3 + k] = scale * v[k];
        s->axes[6 + k] = scale * w[k];
    }
    s->manual = 1;
    s->seed = pw_tetgrid_locate(&g->grid, &g->m, p, s->centre);
    if (s->seed < 0)
        return pw_fail(e, PW_ERR_INVALID, "manual paste: the point (%g, %g, %g) is outside the model", p[0], p[1],
                       p[2]);
    return PW_OK;
}

LSTDEF lst_result lst_paste_at(lst_model *model, const lst_paste_spec *spec, const lst_options *opt, lst_error *err)
{
    lst_options o = lst__options(opt);
    pw_alloc a;
    pw_tetmesh m;
    pw_volume mv;
    lst__geo g;
    lst__fill F;
    lst__spec s;
    lst_paste *grown;
    pw_err e;
    int mask;
    pw_err_clear(&e);
    if (!model || !model->mesh.tets || !spec) {
        pw_fail(&e, PW_ERR_INVALID, "lst_paste_at: NULL argument or empty model");
        return lst__done(&e, err);
    }
    mask = spec->mask;
    if (mask < 0 || mask >= model->masks.count || !model->masks.volumes[mask].voxels) {
        pw_fail(&e, PW_ERR_INVALID, "lst_paste_at: mask %d does not exist (the model has %d)", mask,
                model->masks.count);
        return lst__done(&e, err);
    }
    a = lst__alloc(&model->allocator);
    m = lst__pw_tets(&model->mesh);
    mv = lst__pw_volume(&model->masks.volumes[mask]);
    memset(&F, 0, sizeof F);
    F.a = &a;
    if (lst__geo_init(&a, &m, &g, &e) != PW_OK) return lst__done(&e, err);
    F.o = o;
    F.g = &g;
    if (lst__manual_spec(&g, spec, &s, &e) == PW_OK && lst__fill_init(&F, &mv, 1, 0, &e) == PW_OK) {
        s.mask = 0; /* the one mask of this fill */
        if (lst__paste_one(&F, &s, 0, NULL, &e) == PW_OK &&
            (grown = (lst_paste *)pw_realloc(&a, model->pastes, sizeof(lst_paste) * ((size_t)model->npastes + 1))) !=
                NULL) {
            model->pastes = grown;
            model->pastes[model->npastes] = F.pastes[0];
            model->pastes[model->npastes++].exemplar = mask;
            F.npastes = 0;
        } else if (e.code == PW_OK) pw_fail(&e, PW_ERR_NOMEM, "out of memory adding a paste");
    }
    lst__fill_free(&F);
    lst__geo_free(&a, &g);
    return lst__done(&e, err);
}
