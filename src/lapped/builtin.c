/* builtin.c: built-in meshes and textures for demos and tests. Everything is
 * made from + - * / and sqrt (and pw_sin/pw_cos, built from those), so the
 * data is the same on every platform. Meshes are triangle meshes,
 * counter-clockwise seen from outside, about unit size. Textures are RGB
 * and follow opt->seed: "scales" and "stripes" are anisotropic (they have an
 * obvious up direction, for LAPPED_FIELD_UP and friends, §3.2), "dots" is
 * isotropic (for LAPPED_FIELD_ISOTROPIC). */
#include "core.c"

/* ---- meshes ----------------------------------------------------------------- */

/* A triangle mesh of nv vertices and nf triangles, face_start filled. */
static int lapped__new_trimesh(const pw_alloc *a, int nv, int nf, lapped_mesh *m, pw_err *e)
{
    int f;
    memset(m, 0, sizeof *m);
    m->positions = (float *)pw_calloc_array(a, (size_t)nv * 3, sizeof(float), "mesh positions", e);
    m->face_start = (int *)pw_alloc_array(a, (size_t)nf + 1, sizeof(int), "mesh faces", e);
    m->face_verts = (int *)pw_calloc_array(a, (size_t)nf * 3, sizeof(int), "mesh faces", e);
    m->allocator = lapped__allocator(a);
    if (!m->positions || !m->face_start || !m->face_verts) {
        lapped_mesh_free(m);
        return PW_ERR_NOMEM;
    }
    m->nverts = nv;
    m->nfaces = nf;
    for (f = 0; f <= nf; f++) m->face_start[f] = 3 * f;
    return PW_OK;
}

/* The icosahedron: corners (0, +-1, +-phi) and cyclic permutations, faces
 * counter-clockwise seen from outside (the table's 2 stands for phi). */
static const signed char lapped__ico_v[12][3] = {{-1, 2, 0}, {1, 2, 0}, {-1, -2, 0}, {1, -2, 0},
                                                 {0, -1, 2}, {0, 1, 2}, {0, -1, -2}, {0, 1, -2},
                                                 {2, 0, -1}, {2, 0, 1}, {-2, 0, -1}, {-2, 0, 1}};
static const unsigned char lapped__ico_f[20][3] = {
    {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
    {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
    {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};

static pw_v3 lapped__ico_corner(int k)
{
    const float phi = 1.61803398874989485f;
    float c[3];
    int i;
    for (i = 0; i < 3; i++) {
        int t = lapped__ico_v[k][i];
        c[i] = t == 2 ? phi : t == -2 ? -phi : (float)t;
    }
    return pw_v3_load(c);
}

/* Index (0..29) of the icosahedron edge between corners p < q. */
static int lapped__ico_edge(int p, int q)
{
    int f, k, n = 0;
    for (f = 0; f < 20; f++)
        for (k = 0; k < 3; k++) {
            int a = lapped__ico_f[f][k], b = lapped__ico_f[f][(k + 1) % 3];
            if (a > b) continue; /* count each edge once, from the face where it runs upwards */
            if (a == p && b == q) return n;
            n++;
        }
    return -1;
}

/* Vertex id of lattice point (i, j) of a frequency-n face with corners
 * c[0..2]: the point c0 + i (c1 - c0)/n + j (c2 - c0)/n. Corners come first,
 * then n-1 points per edge (from its lower corner), then face interiors, so
 * points shared by faces get one id. */
static int lapped__geo_id(const int *c, int f, int n, int i, int j)
{
    int p = -1, q = -1, t = 0, jj = j;
    if (i == 0 && j == 0) return c[0];
    if (i == n) return c[1];
    if (j == n) return c[2];
    if (j == 0) p = c[0], q = c[1], t = i;
    else if (i == 0) p = c[0], q = c[2], t = j;
    else if (i + j == n) p = c[1], q = c[2], t = j;
    if (p >= 0) {
        if (p > q) {
            int s = p;
            p = q;
            q = s;
            t = n - t;
        }
        return 12 + lapped__ico_edge(p, q) * (n - 1) + t - 1;
    }
    return 12 + 30 * (n - 1) + f * (n - 1) * (n - 2) / 2 + (jj - 1) * (n - 1) - (jj - 1) * jj / 2 + i - 1;
}

/* Geodesic sphere: every icosahedron face split into n^2 triangles, the
 * points pushed onto the unit sphere (10 n^2 + 2 vertices, 20 n^2 faces). */
static int lapped__geosphere(const pw_alloc *a, int n, lapped_mesh *m, pw_err *e)
{
    int f, i, j, nt = 0, r = lapped__new_trimesh(a, 10 * n * n + 2, 20 * n * n, m, e);
    if (r != PW_OK) return r;
    for (f = 0; f < 20; f++) {
        int c[3];
        pw_v3 A, B, C;
        c[0] = lapped__ico_f[f][0], c[1] = lapped__ico_f[f][1], c[2] = lapped__ico_f[f][2];
        A = lapped__ico_corner(c[0]), B = lapped__ico_corner(c[1]), C = lapped__ico_corner(c[2]);
        for (j = 0; j <= n; j++)
            for (i = 0; i + j <= n; i++) {
                pw_v3 p = pw_v3_add(A, pw_v3_add(pw_v3_scale(pw_v3_sub(B, A), (float)i / n),
                                                 pw_v3_scale(pw_v3_sub(C, A), (float)j / n)));
                int *t = m->face_verts + 3 * nt;
                pw_v3_store(m->positions + 3 * lapped__geo_id(c, f, n, i, j), pw_v3_norm(p));
                if (i + j == n) continue;
                t[0] = lapped__geo_id(c, f, n, i, j); /* the upright triangle */
                t[1] = lapped__geo_id(c, f, n, i + 1, j);
                t[2] = lapped__geo_id(c, f, n, i, j + 1);
                nt++;
                if (i + j + 1 == n) continue;
                t[3] = t[1]; /* and the inverted one beside it */
                t[4] = lapped__geo_id(c, f, n, i + 1, j + 1);
                t[5] = t[2];
                nt++;
            }
    }
    return PW_OK;
}

/* A smooth bump of height 1 at distance 0, reaching 0 at distance 1 with
 * zero slope and curvature: (1 - t^2)^3. */
static double lapped__bump(double t) { return t >= 1.0 ? 0.0 : (1.0 - t * t) * (1.0 - t * t) * (1.0 - t * t); }

/* "bumpy": a geodesic sphere whose radius is raised or lowered by 14 smooth
 * bumps at fixed pseudo-random places (the same for every seed). The
 * surface stays star-shaped, so it is embedded and keeps its orientation. */
static int lapped__bumpy(const pw_alloc *a, lapped_mesh *m, pw_err *e)
{
    double c[14][3], h[14], rad[14];
    pw_rng rng = pw_rng_seed(2000, 7);
    int k, v, r = lapped__geosphere(a, 16, m, e);
    if (r != PW_OK) return r;
    for (k = 0; k < 14; k++) {
        double x = 2 * pw_rng_double(&rng) - 1, y = 2 * pw_rng_double(&rng) - 1, z = 2 * pw_rng_double(&rng) - 1;
        double l = sqrt(x * x + y * y + z * z) + 1e-9;
        c[k][0] = x / l, c[k][1] = y / l, c[k][2] = z / l;
        h[k] = k % 3 == 2 ? -0.1 : 0.08 + 0.14 * pw_rng_double(&rng);
        rad[k] = 0.45 + 0.4 * pw_rng_double(&rng);
    }
    for (v = 0; v < m->nverts; v++) {
        float *p = m->positions + 3 * v;
        double s = 1.0;
        for (k = 0; k < 14; k++) {
            double dx = p[0] - c[k][0], dy = p[1] - c[k][1], dz = p[2] - c[k][2];
            s += h[k] * lapped__bump(sqrt(dx * dx + dy * dy + dz * dz) / rad[k]);
        }
        p[0] = (float)(p[0] * s);
        p[1] = (float)(p[1] * s * 1.1); /* a little taller than wide */
        p[2] = (float)(p[2] * s);
    }
    return PW_OK;
}

/* Torus around the z axis: radii 1 and 0.4, nu x nv quads split in two. */
static int lapped__torus(const pw_alloc *a, int nu, int nv, lapped_mesh *m, pw_err *e)
{
    const double pi2 = 6.28318530717958647692;
    int i, j, r = lapped__new_trimesh(a, nu * nv, 2 * nu * nv, m, e);
    if (r != PW_OK) return r;
    for (i = 0; i < nu; i++)
        for (j = 0; j < nv; j++) {
            double u = pi2 * i / nu, v = pi2 * j / nv, rr = 1.0 + 0.4 * pw_cos(v);
            float *p = m->positions + 3 * (i * nv + j);
            int *t = m->face_verts + 6 * (i * nv + j);
            int a0 = i * nv + j, a1 = ((i + 1) % nu) * nv + j;
            int a2 = ((i + 1) % nu) * nv + (j + 1) % nv, a3 = i * nv + (j + 1) % nv;
            p[0] = (float)(rr * pw_cos(u));
            p[1] = (float)(rr * pw_sin(u));
            p[2] = (float)(0.4 * pw_sin(v));
            t[0] = a0, t[1] = a1, t[2] = a2; /* d/du x d/dv points outwards */
            t[3] = a0, t[4] = a2, t[5] = a3;
        }
    return PW_OK;
}

/* "disc": a gently domed disc of radius 1 facing +z, with a boundary: a
 * centre and K rings of 6k vertices, neighbouring rings zipped together
 * (6 K^2 triangles). */
static int lapped__disc(const pw_alloc *a, int K, lapped_mesh *m, pw_err *e)
{
    const double pi2 = 6.28318530717958647692;
    int k, i, nt = 0, r = lapped__new_trimesh(a, 1 + 3 * K * (K + 1), 6 * K * K, m, e);
    if (r != PW_OK) return r;
    m->positions[2] = 0.2f;
    for (k = 1; k <= K; k++)
        for (i = 0; i < 6 * k; i++) {
            double rho = (double)k / K, th = pi2 * i / (6 * k);
            float *p = m->positions + 3 * (1 + 3 * k * (k - 1) + i);
            p[0] = (float)(rho * pw_cos(th));
            p[1] = (float)(rho * pw_sin(th));
            p[2] = (float)(0.2 * (1.0 - rho * rho));
        }
    for (k = 1; k <= K; k++) { /* ring k-1 (n0 vertices; the centre for k = 1) against ring k */
        int n0 = k == 1 ? 1 : 6 * (k - 1), n1 = 6 * k, b0 = k == 1 ? 0 : 1 + 3 * (k - 1) * (k - 2);
        int b1 = 1 + 3 * k * (k - 1), i = k == 1 ? 1 : 0, j = 0;
        while (i < n0 || j < n1) { /* step along the ring whose next vertex comes first in angle */
            int *t = m->face_verts + 3 * nt++, inner = j == n1 || (i < n0 && (long)(i + 1) * n1 < (long)(j + 1) * n0);
            t[0] = b0 + i % n0;
            t[1] = b1 + j % n1;
            t[2] = inner ? b0 + (i + 1) % n0 : b1 + (j + 1) % n1; /* counter-clockwise seen from +z */
            if (inner) i++;
            else j++;
        }
    }
    return PW_OK;
}

LAPPEDDEF lapped_result lapped_builtin_mesh(const char *name, const lapped_options *opt, lapped_mesh *out,
                                            lapped_error *err)
{
    lapped_options o = lapped__options(opt);
    pw_alloc a = lapped__alloc(&o.allocator);
    pw_err pe;
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (!out || !name) pw_fail(&pe, PW_ERR_INVALID, "lapped_builtin_mesh: NULL argument");
    else if (!strcmp(name, "sphere")) lapped__geosphere(&a, 12, out, &pe);
    else if (!strcmp(name, "torus")) lapped__torus(&a, 48, 32, out, &pe);
    else if (!strcmp(name, "bumpy")) lapped__bumpy(&a, out, &pe);
    else if (!strcmp(name, "disc")) lapped__disc(&a, 18, out, &pe);
    else
        pw_fail(&pe, PW_ERR_INVALID, "unknown built-in mesh '%s' (sphere, torus, bumpy, disc)", name);
    return lapped__done(&pe, err);
}

/* ---- textures ----------------------------------------------------------------- */

static float lapped__smooth(float e0, float e1, float x)
{
    float t = pw_clampf((x - e0) / (e1 - e0), 0.0f, 1.0f);
    return t * t * (3.0f - 2.0f * t);
}

static void lapped__mix(float *out, const float *a, const float *b, float t)
{
    int k;
    for (k = 0; k < 3; k++) out[k] = a[k] + (b[k] - a[k]) * t;
}

/* A uniform value in [0, 1) for integer lattice point (x, y). */
static float lapped__hash01(unsigned long long seed, int x, int y)
{
    uint64_t key = ((uint64_t)(uint32_t)y << 32) | (uint32_t)x;
    return (float)(pw_hash64(seed, key) >> 40) * (1.0f / 16777216.0f);
}

/* Value noise with a quintic fade, lattice spacing 1, values in [0, 1]. */
static float lapped__noise(unsigned long long seed, float x, float y)
{
    float fx = x < 0 ? x - 1.0f : x, fy = y < 0 ? y - 1.0f : y, tx, ty, v00, v10, v01, v11;
    int ix = (int)fx, iy = (int)fy;
    tx = x - (float)ix;
    ty = y - (float)iy;
    tx = tx * tx * tx * (tx * (tx * 6.0f - 15.0f) + 10.0f);
    ty = ty * ty * ty * (ty * (ty * 6.0f - 15.0f) + 10.0f);
    v00 = lapped__hash01(seed, ix, iy);
    v10 = lapped__hash01(seed, ix + 1, iy);
    v01 = lapped__hash01(seed, ix, iy + 1);
    v11 = lapped__hash01(seed, ix + 1, iy + 1);
    v00 += (v10 - v00) * tx;
    v01 += (v11 - v01) * tx;
    return v00 + (v01 - v00) * ty;
}

/* Three octaves of value noise, in [0, 1]. */
static float lapped__fbm(unsigned long long seed, float x, float y)
{
    return 0.57f * lapped__noise(seed, x, y) + 0.29f * lapped__noise(seed + 1, 2.0f * x, 2.0f * y) +
           0.14f * lapped__noise(seed + 2, 4.0f * x, 4.0f * y);
}

/* "scales": overlapping scales in rows like roof tiles: the rows above lie
 * over the rows below, so each scale shows its lower half, with a dark
 * rounded free edge at the bottom and a shadow under the scale above. 8
 * scales across; (x, y) in scale widths, y down. */
static void lapped__scales(unsigned long long seed, float x, float y, float px, float *rgb)
{
    static const float lo[3] = {0.12f, 0.36f, 0.34f}, hi[3] = {0.62f, 0.7f, 0.34f}, edge[3] = {0.05f, 0.09f, 0.08f};
    const float sy = 0.5f, R = 0.62f;
    int j, j0 = (int)((y - R) / sy + 100.0f) - 100, hit = 0, ci = 0, cj = 0;
    float dx = 0.0f, dy = 0.0f, shade = 1.0f, rho, up = 1.0f, h, base[3];
    for (j = j0; j <= j0 + 4 && !hit; j++) { /* the topmost row containing (x, y) wins */
        float off = (j & 1) ? 0.5f : 0.0f, cy = (float)j * sy;
        int i0 = (int)(x - off + 100.5f) - 100, i;
        for (i = i0 - 1; i <= i0 + 1 && !hit; i++) {
            float ex = x - ((float)i + off), ey = y - cy;
            if (ex * ex + ey * ey < R * R) hit = 1, ci = i, cj = j, dx = ex, dy = ey;
        }
    }
    for (j = -1; j <= 1; j += 2) { /* distance to the edges of the two scales of the row above */
        float cx = (float)ci + ((cj & 1) ? 0.5f : 0.0f) + 0.5f * (float)j, cy = (float)(cj - 1) * sy;
        float d = sqrtf((x - cx) * (x - cx) + (y - cy) * (y - cy)) - R;
        up = d < up ? d : up;
    }
    rho = sqrtf(dx * dx + dy * dy) / R;
    h = lapped__hash01(seed, ci, cj);
    lapped__mix(base, lo, hi, 0.25f + 0.5f * h + 0.35f * (dy / R));
    shade = (0.55f + 0.45f * lapped__smooth(0.0f, 0.22f, up)) * (0.85f + 0.3f * lapped__hash01(seed + 5, ci, cj));
    shade *= 0.9f + 0.2f * lapped__fbm(seed + 9, 24.0f * x, 6.0f * y); /* fine striations */
    shade += 0.25f * lapped__smooth(0.45f, 0.0f, rho) * lapped__smooth(0.0f, 0.3f, up); /* sheen */
    base[0] *= shade, base[1] *= shade, base[2] *= shade;
    lapped__mix(rgb, base, edge, lapped__smooth(1.0f - 0.09f - px, 1.0f - 0.02f, rho));
}

/* "stripes": zebra-like, roughly horizontal dark stripes warped by noise,
 * 7 down the image, their width varying so that some thin out and end or
 * merge. The signed distance into the nearest stripe (in stripe periods; > 0
 * inside); (x, y) in image widths. */
static float lapped__stripe_inside(unsigned long long seed, float x, float y)
{
    const float tau = 6.28318530717958647692f;
    float warp = 0.9f * (lapped__fbm(seed, 2.5f * x, 2.5f * y) - 0.5f) +
                 0.25f * (float)pw_sin(tau * (1.3f * x + 0.2f)) * (float)pw_cos(tau * 0.7f * y);
    float phase = 7.0f * y + 2.2f * warp, f = phase - (float)((int)(phase + 100.0f) - 100), d = f - 0.5f;
    float half = 0.25f + 0.75f * (lapped__fbm(seed + 3, 3.0f * x, 3.0f * y) - 0.5f);
    return half - (d < 0.0f ? -d : d); /* |d|: 0 on a stripe's centre line, 0.5 halfway to the next */
}

/* Coverage from the signed distance and its gradient over one pixel (finite
 * differences), so that every edge is about a pixel wide, also where a
 * stripe tapers off. */
static void lapped__stripes(unsigned long long seed, float x, float y, float px, float *rgb)
{
    static const float dark[3] = {0.07f, 0.06f, 0.06f}, light[3] = {0.93f, 0.89f, 0.8f};
    float v = lapped__stripe_inside(seed, x, y), gx = lapped__stripe_inside(seed, x + px, y) - v;
    float gy = lapped__stripe_inside(seed, x, y + px) - v, g = sqrtf(gx * gx + gy * gy);
    float t = g > 1e-6f ? pw_clampf(v / g + 0.5f, 0.0f, 1.0f) : (v > 0.0f ? 1.0f : 0.0f);
    lapped__mix(rgb, light, dark, t);
    g = 0.92f + 0.16f * lapped__fbm(seed + 7, 40.0f * x, 12.0f * y); /* hair grain */
    rgb[0] *= g, rgb[1] *= g, rgb[2] *= g;
}

/* "dots": polka dots of varied sizes and colours, one per cell of a
 * jittered 6x6 grid, and small dots of a finer 13x13 grid between them, on
 * a warm off-white ground. Isotropic. (x, y) in image widths. */
static void lapped__dot_layer(unsigned long long seed, int cells, float rmin, float rmax, float x, float y,
                              float px, float *rgb)
{
    static const float pal[6][3] = {{0.86f, 0.24f, 0.28f}, {0.19f, 0.44f, 0.76f}, {0.96f, 0.72f, 0.16f},
                                    {0.25f, 0.63f, 0.4f},  {0.55f, 0.33f, 0.72f}, {0.95f, 0.5f, 0.22f}};
    float gx = x * (float)cells, gy = y * (float)cells;
    int ix = (int)gx, iy = (int)gy, c;
    float rad = (rmin + (rmax - rmin) * lapped__hash01(seed, ix, iy)) / (float)cells, room = 0.5f / (float)cells - rad;
    float cx = ((float)ix + 0.5f) / (float)cells + room * (2.0f * lapped__hash01(seed + 1, ix, iy) - 1.0f);
    float cy = ((float)iy + 0.5f) / (float)cells + room * (2.0f * lapped__hash01(seed + 2, ix, iy) - 1.0f);
    float d = sqrtf((x - cx) * (x - cx) + (y - cy) * (y - cy)), cover = pw_clampf((rad - d) / px + 0.5f, 0.0f, 1.0f);
    float col[3], light = 1.0f + 0.25f * lapped__smooth(rad, 0.0f, sqrtf((x - cx + 0.3f * rad) * (x - cx + 0.3f * rad) +
                                                                   (y - cy + 0.3f * rad) * (y - cy + 0.3f * rad)));
    c = (int)(6.0f * lapped__hash01(seed + 3, ix, iy)) % 6;
    col[0] = pw_clampf(pal[c][0] * light, 0.0f, 1.0f);
    col[1] = pw_clampf(pal[c][1] * light, 0.0f, 1.0f);
    col[2] = pw_clampf(pal[c][2] * light, 0.0f, 1.0f);
    lapped__mix(rgb, rgb, col, cover);
}

static void lapped__dots(unsigned long long seed, float x, float y, float px, float *rgb)
{
    float g = 0.94f + 0.06f * lapped__fbm(seed + 11, 20.0f * x, 20.0f * y);
    rgb[0] = 0.97f * g, rgb[1] = 0.94f * g, rgb[2] = 0.86f * g;
    lapped__dot_layer(seed + 20, 13, 0.12f, 0.22f, x, y, px, rgb);
    lapped__dot_layer(seed + 40, 6, 0.2f, 0.42f, x, y, px, rgb);
}

LAPPEDDEF lapped_result lapped_builtin_texture(const char *name, int size, const lapped_options *opt,
                                               lapped_image *out, lapped_error *err)
{
    lapped_options o = lapped__options(opt);
    pw_alloc a = lapped__alloc(&o.allocator);
    pw_image img;
    pw_err pe;
    int x, y, kind = -1;
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (name) kind = !strcmp(name, "scales") ? 0 : !strcmp(name, "stripes") ? 1 : !strcmp(name, "dots") ? 2 : -1;
    if (!out || kind < 0)
        pw_fail(&pe, PW_ERR_INVALID, "unknown built-in texture '%s' (scales, stripes, dots)", name ? name : "(null)");
    else if (size < 8 || size > 4096)
        pw_fail(&pe, PW_ERR_INVALID, "built-in texture size must be 8..4096 (got %d)", size);
    else if (pw_image_alloc(&a, &img, size, size, 3, &pe) == PW_OK) {
        float px = 1.0f / (float)size;
        for (y = 0; y < size; y++)
            for (x = 0; x < size; x++) {
                float u = ((float)x + 0.5f) * px, v = ((float)y + 0.5f) * px, *p = img.px + ((size_t)y * size + x) * 3;
                if (kind == 0) lapped__scales(o.seed, 8.0f * u, 8.0f * v, 8.0f * px, p);
                else if (kind == 1) lapped__stripes(o.seed, u, v, px, p);
                else lapped__dots(o.seed, u, v, px, p);
                p[0] = pw_clampf(p[0], 0.0f, 1.0f);
                p[1] = pw_clampf(p[1], 0.0f, 1.0f);
                p[2] = pw_clampf(p[2], 0.0f, 1.0f);
            }
        lapped__take_image(&img, &a, out);
    }
    return lapped__done(&pe, err);
}
