/* builtin.c: built-in meshes and exemplars for demos and tests: the
 * kinds of surfaces of ch. V (a cube, a torus, a genus-2 "double donut",
 * triangle meshes made quads by ch. VI's subdivision, an open grid) and
 * homogeneous, isotropic exemplars for ch. III.1.3. */
#include "core.c"

/* Allocates a mesh of nv vertices and nf faces of `deg` corners. */
static int tiled__new_mesh(const pw_alloc *a, int nv, int nf, int deg, tiled_mesh *m, pw_err *e)
{
    int f;
    memset(m, 0, sizeof *m);
    m->allocator = tiled__allocator(a);
    m->positions = (float *)pw_alloc_array(a, (size_t)nv * 3, sizeof(float), "positions", e);
    m->face_start = (int *)pw_alloc_array(a, (size_t)nf + 1, sizeof(int), "faces", e);
    m->face_verts = (int *)pw_alloc_array(a, (size_t)nf * deg, sizeof(int), "face corners", e);
    if (!m->positions || !m->face_start || !m->face_verts) {
        tiled_mesh_free(m);
        return PW_ERR_NOMEM;
    }
    m->nverts = nv;
    m->nfaces = nf;
    for (f = 0; f <= nf; f++) m->face_start[f] = f * deg;
    return PW_OK;
}

/* The surface of a union of unit voxels: one outward quad per voxel face
 * that touches empty space. A first pass counts (m == NULL), a second
 * writes; vertices are numbered in order of first use. */
typedef struct tiled__voxels {
    int X, Y, Z;
    const unsigned char *vox;
    int *map; /* lattice point -> vertex, -1 if unused */
    tiled_mesh *m;
    int nv, nf;
} tiled__voxels;

static int tiled__solid(const tiled__voxels *v, const int p[3])
{
    return p[0] >= 0 && p[1] >= 0 && p[2] >= 0 && p[0] < v->X && p[1] < v->Y && p[2] < v->Z &&
           v->vox[(p[2] * v->Y + p[1]) * v->X + p[0]];
}

/* Emits the face of voxel p facing direction d (axis d/2, sign by d&1),
 * counter-clockwise seen from outside. */
static void tiled__voxel_face(tiled__voxels *v, const int p[3], int d)
{
    static const int du[4] = {0, 1, 1, 0}, dv[4] = {0, 0, 1, 1};
    int ax = d >> 1, neg = d & 1, u = (ax + 1) % 3, w = (ax + 2) % 3, k, c[3], li;
    for (k = 0; k < 4; k++) {
        int kk = neg ? (4 - k) & 3 : k; /* reversed walk on the negative side */
        memcpy(c, p, sizeof c);
        c[ax] += !neg;
        c[u] += du[kk];
        c[w] += dv[kk];
        li = (c[2] * (v->Y + 1) + c[1]) * (v->X + 1) + c[0];
        if (v->map[li] < 0) {
            if (v->m) {
                v->m->positions[3 * v->nv] = (float)c[0];
                v->m->positions[3 * v->nv + 1] = (float)c[1];
                v->m->positions[3 * v->nv + 2] = (float)c[2];
            }
            v->map[li] = v->nv++;
        }
        if (v->m) v->m->face_verts[4 * v->nf + k] = v->map[li];
    }
    v->nf++;
}

static void tiled__voxel_pass(tiled__voxels *v)
{
    int p[3], q[3], d, k, nl = (v->X + 1) * (v->Y + 1) * (v->Z + 1);
    for (k = 0; k < nl; k++) v->map[k] = -1;
    v->nv = v->nf = 0;
    for (p[2] = 0; p[2] < v->Z; p[2]++)
        for (p[1] = 0; p[1] < v->Y; p[1]++)
            for (p[0] = 0; p[0] < v->X; p[0]++) {
                if (!tiled__solid(v, p)) continue;
                for (d = 0; d < 6; d++) {
                    memcpy(q, p, sizeof q);
                    q[d >> 1] += d & 1 ? -1 : 1;
                    if (!tiled__solid(v, q)) tiled__voxel_face(v, p, d);
                }
            }
}

static int tiled__polycube(const pw_alloc *a, int X, int Y, int Z, const unsigned char *vox,
                           tiled_mesh *m, pw_err *e)
{
    tiled__voxels v;
    int r;
    v.X = X;
    v.Y = Y;
    v.Z = Z;
    v.vox = vox;
    v.m = NULL;
    v.map = (int *)pw_alloc_array(a, (size_t)(X + 1) * (Y + 1) * (Z + 1), sizeof(int), "lattice", e);
    if (!v.map) return PW_ERR_NOMEM;
    tiled__voxel_pass(&v);
    if ((r = tiled__new_mesh(a, v.nv, v.nf, 4, m, e)) == PW_OK) {
        v.m = m;
        tiled__voxel_pass(&v);
    }
    pw_free(a, v.map);
    return r;
}

/* Torus: R = 1, r = 0.4, nu x nv quads (u around the axis, v around the tube). */
static int tiled__torus(const pw_alloc *a, int nu, int nv, tiled_mesh *m, pw_err *e)
{
    const double pi2 = 6.28318530717958647692;
    int i, j, r = tiled__new_mesh(a, nu * nv, nu * nv, 4, m, e);
    if (r != PW_OK) return r;
    for (i = 0; i < nu; i++)
        for (j = 0; j < nv; j++) {
            double u = pi2 * i / nu, v = pi2 * j / nv, rr = 1.0 + 0.4 * pw_cos(v);
            float *p = m->positions + 3 * (i * nv + j);
            int *f = m->face_verts + 4 * (i * nv + j);
            p[0] = (float)(rr * pw_cos(u));
            p[1] = (float)(rr * pw_sin(u));
            p[2] = (float)(0.4 * pw_sin(v));
            f[0] = i * nv + j;
            f[1] = ((i + 1) % nu) * nv + j;
            f[2] = ((i + 1) % nu) * nv + (j + 1) % nv;
            f[3] = i * nv + (j + 1) % nv;
        }
    return PW_OK;
}

/* Icosahedron: 20 triangles (Catmull-Clark turns them into quads). */
static int tiled__icosahedron(const pw_alloc *a, tiled_mesh *m, pw_err *e)
{
    static const signed char vs[12][3] = {{-1, 2, 0}, {1, 2, 0}, {-1, -2, 0}, {1, -2, 0},
                                          {0, -1, 2}, {0, 1, 2}, {0, -1, -2}, {0, 1, -2},
                                          {2, 0, -1}, {2, 0, 1}, {-2, 0, -1}, {-2, 0, 1}};
    static const unsigned char fs[20][3] = {
        {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
        {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    const float phi = 1.61803398874989485f;
    int k, r = tiled__new_mesh(a, 12, 20, 3, m, e);
    if (r != PW_OK) return r;
    for (k = 0; k < 36; k++) { /* the table's 2 stands for the golden ratio */
        int c = vs[k / 3][k % 3];
        m->positions[k] = c == 2 ? phi : (c == -2 ? -phi : (float)c);
    }
    for (k = 0; k < 60; k++) m->face_verts[k] = fs[k / 3][k % 3];
    return PW_OK;
}

/* An open, gently waved n x n quad grid on [-1,1]^2: a mesh with a boundary. */
static int tiled__grid(const pw_alloc *a, int n, tiled_mesh *m, pw_err *e)
{
    const double pi = 3.14159265358979323846;
    int i, j, r = tiled__new_mesh(a, (n + 1) * (n + 1), n * n, 4, m, e);
    if (r != PW_OK) return r;
    for (j = 0; j <= n; j++)
        for (i = 0; i <= n; i++) {
            double x = -1.0 + 2.0 * i / n, y = -1.0 + 2.0 * j / n;
            float *p = m->positions + 3 * (j * (n + 1) + i);
            p[0] = (float)x;
            p[1] = (float)y;
            p[2] = (float)(0.2 * pw_sin(pi * x) * pw_sin(pi * y));
        }
    for (j = 0; j < n; j++)
        for (i = 0; i < n; i++) {
            int *f = m->face_verts + 4 * (j * n + i), v = j * (n + 1) + i;
            f[0] = v;
            f[1] = v + 1;
            f[2] = v + n + 2;
            f[3] = v + n + 1;
        }
    return PW_OK;
}

/* Moves a mesh's bounding-box centre to the origin and scales it to fit
 * [-1,1]^3 (voxel meshes come in lattice units). */
static void tiled__normalise(tiled_mesh *m)
{
    float lo[3], hi[3], s;
    int k, v;
    for (k = 0; k < 3; k++) lo[k] = hi[k] = m->positions[k];
    for (v = 0; v < m->nverts; v++)
        for (k = 0; k < 3; k++) {
            float x = m->positions[3 * v + k];
            lo[k] = x < lo[k] ? x : lo[k];
            hi[k] = x > hi[k] ? x : hi[k];
        }
    s = 0.0f;
    for (k = 0; k < 3; k++) s = hi[k] - lo[k] > s ? hi[k] - lo[k] : s;
    for (v = 0; v < m->nverts; v++)
        for (k = 0; k < 3; k++)
            m->positions[3 * v + k] = (m->positions[3 * v + k] - 0.5f * (lo[k] + hi[k])) * 2.0f / s;
}

TILEDDEF tiled_result tiled_builtin_mesh(const char *name, const tiled_options *opt,
                                         tiled_mesh *out, tiled_error *err)
{
    /* genus 2: a 5x3x2 slab of voxels with two holes through it */
    static const unsigned char slab[30] = {1, 1, 1, 1, 1, 1, 0, 1, 0, 1, 1, 1, 1, 1, 1,
                                           1, 1, 1, 1, 1, 1, 0, 1, 0, 1, 1, 1, 1, 1, 1};
    static const unsigned char one = 1;
    tiled_options o = tiled__options(opt);
    pw_alloc a = tiled__alloc(&o.allocator);
    pw_err pe;
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (!out || !name) pw_fail(&pe, PW_ERR_INVALID, "tiled_builtin_mesh: NULL argument");
    else if (!strcmp(name, "cube")) tiled__polycube(&a, 1, 1, 1, &one, out, &pe);
    else if (!strcmp(name, "double-torus")) tiled__polycube(&a, 5, 3, 2, slab, out, &pe);
    else if (!strcmp(name, "torus")) tiled__torus(&a, 24, 12, out, &pe);
    else if (!strcmp(name, "icosahedron")) tiled__icosahedron(&a, out, &pe);
    else if (!strcmp(name, "grid")) tiled__grid(&a, 12, out, &pe);
    else
        pw_fail(&pe, PW_ERR_INVALID, "unknown built-in mesh '%s' (cube, torus, double-torus, "
                "icosahedron, grid)", name);
    if (pe.code == PW_OK) tiled__normalise(out);
    return tiled__done(&pe, err);
}

/* Procedural exemplars: periodic on the unit torus, built from + - * / and
 * sqrt only, so they are identical on every platform. */
typedef struct tiled__cells {
    int m;           /* m x m jittered cells */
    float px[256], py[256]; /* one feature point per cell, in [0,1) */
    float col[256][3];
} tiled__cells;

static void tiled__cells_init(tiled__cells *c, int m, pw_rng *r)
{
    int k;
    c->m = m;
    for (k = 0; k < m * m; k++) {
        c->px[k] = ((float)(k % m) + 0.15f + 0.7f * pw_rng_float(r)) / (float)m;
        c->py[k] = ((float)(k / m) + 0.15f + 0.7f * pw_rng_float(r)) / (float)m;
        c->col[k][0] = pw_rng_float(r);
        c->col[k][1] = pw_rng_float(r);
        c->col[k][2] = pw_rng_float(r);
    }
}

/* Distances to the nearest and second nearest feature points (periodic),
 * and the nearest point's index. */
static void tiled__cells_eval(const tiled__cells *c, float x, float y, float *f1, float *f2, int *id)
{
    int cx = (int)(x * (float)c->m), cy = (int)(y * (float)c->m), dx, dy;
    *f1 = *f2 = 4.0f;
    *id = 0;
    for (dy = -2; dy <= 2; dy++)
        for (dx = -2; dx <= 2; dx++) {
            int gx = cx + dx, gy = cy + dy, k;
            float ox = 0.0f, oy = 0.0f, ddx, ddy, d;
            if (gx < 0) { gx += c->m; ox = -1.0f; }
            if (gx >= c->m) { gx -= c->m; ox = 1.0f; }
            if (gy < 0) { gy += c->m; oy = -1.0f; }
            if (gy >= c->m) { gy -= c->m; oy = 1.0f; }
            k = gy * c->m + gx;
            ddx = c->px[k] + ox - x;
            ddy = c->py[k] + oy - y;
            d = sqrtf(ddx * ddx + ddy * ddy);
            if (d < *f1) { *f2 = *f1; *f1 = d; *id = k; }
            else if (d < *f2) *f2 = d;
        }
}

/* Periodic value noise with a smooth (quintic) fade, `lattice` cells per
 * side, values in [0,1]. */
static float tiled__noise(uint64_t seed, int lattice, float x, float y)
{
    float fx = x * (float)lattice, fy = y * (float)lattice, tx, ty, v[4];
    int ix = (int)fx, iy = (int)fy, k;
    tx = fx - (float)ix;
    ty = fy - (float)iy;
    for (k = 0; k < 4; k++) {
        int gx = (ix + (k & 1)) % lattice, gy = (iy + (k >> 1)) % lattice;
        v[k] = (float)(pw_hash64(seed, (uint64_t)(gy * lattice + gx)) >> 40) / 16777216.0f;
    }
    tx = tx * tx * tx * (tx * (tx * 6.0f - 15.0f) + 10.0f);
    ty = ty * ty * ty * (ty * (ty * 6.0f - 15.0f) + 10.0f);
    return (v[0] + (v[1] - v[0]) * tx) + ((v[2] + (v[3] - v[2]) * tx) - (v[0] + (v[1] - v[0]) * tx)) * ty;
}

static float tiled__fbm(uint64_t seed, float x, float y)
{
    return 0.5f * tiled__noise(seed, 4, x, y) + 0.25f * tiled__noise(seed + 1, 8, x, y) +
           0.15f * tiled__noise(seed + 2, 16, x, y) + 0.1f * tiled__noise(seed + 3, 32, x, y);
}

static void tiled__mix(float *out, const float *a, const float *b, float t)
{
    int k;
    t = pw_clampf(t, 0.0f, 1.0f);
    for (k = 0; k < 3; k++) out[k] = a[k] + (b[k] - a[k]) * t;
}

/* Pebbles: rounded stones of varied greys and browns in dark mortar. */
static void tiled__pebbles(const tiled__cells *c, uint64_t seed, float x, float y, float *rgb)
{
    static const float mortar[3] = {0.16f, 0.13f, 0.11f};
    float f1, f2, stone[3], edge, grain;
    int id, k;
    tiled__cells_eval(c, x, y, &f1, &f2, &id);
    grain = tiled__fbm(seed, x, y);
    for (k = 0; k < 3; k++) /* warm greys: shared brightness, a little hue */
        stone[k] = 0.35f + 0.35f * c->col[id][0] + 0.12f * (c->col[id][k] - 0.5f) + 0.25f * (grain - 0.5f);
    edge = (f2 - f1) * (float)c->m * 3.0f; /* 0 on the cell border */
    tiled__mix(rgb, mortar, stone, edge * edge);
}

/* Spots: broken dark rosettes with brown centres on a tawny, mottled
 * ground (leopard-like). */
static void tiled__spots(const tiled__cells *c, uint64_t seed, float x, float y, float *rgb)
{
    static const float ground[3] = {0.86f, 0.67f, 0.37f}, ring[3] = {0.1f, 0.07f, 0.05f},
                       centre[3] = {0.6f, 0.4f, 0.19f};
    float f1, f2, r, base[3], n = tiled__fbm(seed, x, y), broken, k;
    int id;
    tiled__cells_eval(c, x, y, &f1, &f2, &id);
    r = (0.25f + 0.12f * c->col[id][0]) / (float)c->m; /* rosette radius */
    k = 40.0f * (float)c->m;                             /* edge sharpness */
    broken = tiled__noise(seed + 11, 16, x, y) > 0.3f ? 1.0f : 0.0f;
    tiled__mix(base, ground, centre, (0.5f * r - f1) * k);
    tiled__mix(rgb, base, ring, broken * pw_clampf((f1 - 0.5f * r) * k, 0.0f, 1.0f) *
                                    pw_clampf((r - f1) * k, 0.0f, 1.0f));
    rgb[0] *= 0.85f + 0.3f * n;
    rgb[1] *= 0.85f + 0.3f * n;
    rgb[2] *= 0.85f + 0.3f * n;
}

/* Lichen: yellow-green crusts on grey stone, from thresholded fBm. */
static void tiled__lichen(uint64_t seed, float x, float y, float *rgb)
{
    static const float stone[3] = {0.5f, 0.5f, 0.48f}, moss[3] = {0.55f, 0.62f, 0.2f},
                       dark[3] = {0.2f, 0.22f, 0.12f};
    float n = tiled__fbm(seed, x, y), d = tiled__fbm(seed + 7, x, y), base[3];
    tiled__mix(base, stone, moss, (n - 0.5f) * 12.0f);
    tiled__mix(rgb, base, dark, (d - 0.62f) * 8.0f);
}

TILEDDEF tiled_result tiled_builtin_exemplar(const char *name, int size, const tiled_options *opt,
                                             tiled_image *out, tiled_error *err)
{
    tiled_options o = tiled__options(opt);
    pw_alloc a = tiled__alloc(&o.allocator);
    pw_rng r = pw_rng_seed(o.seed, 4);
    tiled__cells cells;
    pw_image img;
    pw_err pe;
    int x, y, kind = -1;
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (name) kind = !strcmp(name, "pebbles") ? 0 : !strcmp(name, "spots") ? 1 : !strcmp(name, "lichen") ? 2 : -1;
    if (!out || kind < 0)
        pw_fail(&pe, PW_ERR_INVALID, "unknown built-in exemplar '%s' (pebbles, spots, lichen)",
                name ? name : "(null)");
    else if (size < 8 || size > 4096)
        pw_fail(&pe, PW_ERR_INVALID, "exemplar size must be 8..4096 (got %d)", size);
    else if (pw_image_alloc(&a, &img, size, size, 3, &pe) == PW_OK) {
        tiled__cells_init(&cells, kind == 0 ? 4 : 3, &r);
        for (y = 0; y < size; y++)
            for (x = 0; x < size; x++) {
                float u = ((float)x + 0.5f) / (float)size, v = ((float)y + 0.5f) / (float)size;
                float *p = img.px + ((size_t)y * size + x) * 3;
                if (kind == 0) tiled__pebbles(&cells, o.seed, u, v, p);
                else if (kind == 1) tiled__spots(&cells, o.seed, u, v, p);
                else tiled__lichen(o.seed, u, v, p);
                p[0] = pw_clampf(p[0], 0.0f, 1.0f);
                p[1] = pw_clampf(p[1], 0.0f, 1.0f);
                p[2] = pw_clampf(p[2], 0.0f, 1.0f);
            }
        tiled__take_image(&img, &a, out);
    }
    return tiled__done(&pe, err);
}
