/* Tests of lapped.h's texture atlas (§4 "Rendering with a texture atlas"):
 * charts, packing, baking and the OBJ/MTL export, on procedural meshes and
 * (after `make data`) real ones. The lapped textures are built by hand here
 * (a planar paste over everything and a few overlapping pastes with alpha),
 * so these tests do not depend on the pasting itself.
 *
 * Set LAPPED_ATLAS_OUT=/some/dir to also write each baked atlas and a
 * rendering of the textured mesh there (PNG) for a visual check. */
#define LAPPED_STATIC /* static: only what the tests call is compiled */
#define LAPPED_IMPLEMENTATION
#include "lapped.h"
#include "pwtest.h"
#include <math.h>
#include <time.h>

/* ---- helpers: meshes ----------------------------------------------------- */

/* A mesh under construction, polygons of any degree. */
typedef struct builder {
    float *pos;
    int *fs, *fv;
    int nv, nf, nc, capv, capf, capc;
} builder;

static int b_vert(builder *b, double x, double y, double z)
{
    if (b->nv == b->capv) {
        b->capv = b->capv ? 2 * b->capv : 256;
        b->pos = (float *)realloc(b->pos, sizeof(float) * 3 * b->capv);
    }
    b->pos[3 * b->nv] = (float)x;
    b->pos[3 * b->nv + 1] = (float)y;
    b->pos[3 * b->nv + 2] = (float)z;
    return b->nv++;
}

static void b_face(builder *b, int n, const int *v)
{
    int k;
    if (b->nf + 2 >= b->capf) {
        b->capf = b->capf ? 2 * b->capf : 256;
        b->fs = (int *)realloc(b->fs, sizeof(int) * (b->capf + 1));
    }
    if (b->nc + n >= b->capc) {
        b->capc = b->capc ? 2 * b->capc + n : 1024;
        b->fv = (int *)realloc(b->fv, sizeof(int) * b->capc);
    }
    if (b->nf == 0) b->fs[0] = 0;
    for (k = 0; k < n; k++) b->fv[b->nc++] = v[k];
    b->fs[++b->nf] = b->nc;
}

static void b_tri(builder *b, int a, int c, int d)
{
    int v[3];
    v[0] = a, v[1] = c, v[2] = d;
    b_face(b, 3, v);
}

static void b_quad(builder *b, int a, int c, int d, int e)
{
    int v[4];
    v[0] = a, v[1] = c, v[2] = d, v[3] = e;
    b_face(b, 4, v);
}

static lapped_mesh b_done(builder *b)
{
    lapped_mesh m;
    memset(&m, 0, sizeof m);
    m.nverts = b->nv;
    m.positions = b->pos;
    m.nfaces = b->nf;
    m.face_start = b->fs;
    m.face_verts = b->fv;
    return m;
}

/* Midpoint of edge (a, b), made once: an open-addressing table of edges. */
typedef struct edge_map {
    long long *key;
    int *val, cap;
} edge_map;

static int midpoint(builder *bd, edge_map *em, int a, int b)
{
    long long k = a < b ? (long long)a * 1000003 + b : (long long)b * 1000003 + a;
    int h = (int)((unsigned long long)k * 11400714819323198485ULL >> 40) & (em->cap - 1), m;
    double p[3], len;
    while (em->key[h] >= 0 && em->key[h] != k) h = (h + 1) & (em->cap - 1);
    if (em->key[h] == k) return em->val[h];
    for (m = 0; m < 3; m++) p[m] = 0.5 * ((double)bd->pos[3 * a + m] + bd->pos[3 * b + m]);
    len = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    em->key[h] = k;
    return em->val[h] = b_vert(bd, p[0] / len, p[1] / len, p[2] / len);
}

/* Icosphere: an icosahedron subdivided `level` times, on the unit sphere
 * (20 * 4^level triangles). */
static lapped_mesh make_icosphere(int level)
{
    static const int ico[20][3] = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9},
                                   {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2},
                                   {3, 2, 6}, {3, 6, 8}, {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10},
                                   {8, 6, 7}, {9, 8, 1}};
    double t = (1.0 + sqrt(5.0)) / 2.0;
    double q[12][3] = {{-1, 0, 0}, {1, 0, 0}, {-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0},
                       {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}, {0, 0, -1}, {0, 0, 1}};
    int *tri = (int *)malloc(sizeof(int) * 60), nt = 20, i, l;
    builder b;
    memset(&b, 0, sizeof b);
    for (i = 0; i < 12; i++) {
        double s2 = (i & 2) ? -t : t; /* (+-1, +-t, 0), (0, +-1, +-t), (+-t, 0, +-1) */
        if (i < 4) q[i][1] = s2;
        else if (i < 8) q[i][2] = (i & 2) ? -t : t;
        else q[i][0] = (i & 2) ? -t : t;
        {
            double len = sqrt(q[i][0] * q[i][0] + q[i][1] * q[i][1] + q[i][2] * q[i][2]);
            b_vert(&b, q[i][0] / len, q[i][1] / len, q[i][2] / len);
        }
    }
    for (i = 0; i < 60; i++) tri[i] = ico[i / 3][i % 3];
    for (l = 0; l < level; l++) {
        edge_map em;
        int *nt4 = (int *)malloc(sizeof(int) * 12 * nt), f;
        em.cap = 1;
        while (em.cap < 4 * 3 * nt) em.cap <<= 1;
        em.key = (long long *)malloc(sizeof(long long) * em.cap);
        em.val = (int *)malloc(sizeof(int) * em.cap);
        for (i = 0; i < em.cap; i++) em.key[i] = -1;
        for (f = 0; f < nt; f++) {
            int a = tri[3 * f], c = tri[3 * f + 1], d = tri[3 * f + 2];
            int ac = midpoint(&b, &em, a, c), cd = midpoint(&b, &em, c, d), da = midpoint(&b, &em, d, a);
            int *o = nt4 + 12 * f;
            o[0] = a, o[1] = ac, o[2] = da, o[3] = ac, o[4] = c, o[5] = cd;
            o[6] = da, o[7] = cd, o[8] = d, o[9] = ac, o[10] = cd, o[11] = da;
        }
        free(em.key);
        free(em.val);
        free(tri);
        tri = nt4;
        nt *= 4;
    }
    for (i = 0; i < nt; i++) b_tri(&b, tri[3 * i], tri[3 * i + 1], tri[3 * i + 2]);
    free(tri);
    return b_done(&b);
}

/* Torus of quads (nu around the ring, nv around the tube). */
static lapped_mesh make_torus(int nu, int nv, double R, double r)
{
    builder b;
    int i, j;
    memset(&b, 0, sizeof b);
    for (i = 0; i < nu; i++)
        for (j = 0; j < nv; j++) {
            double u = 2 * 3.14159265358979 * i / nu, v = 2 * 3.14159265358979 * j / nv;
            b_vert(&b, (R + r * cos(v)) * cos(u), r * sin(v), (R + r * cos(v)) * sin(u));
        }
    for (i = 0; i < nu; i++)
        for (j = 0; j < nv; j++) {
            int a = i * nv + j, c = ((i + 1) % nu) * nv + j, d = ((i + 1) % nu) * nv + (j + 1) % nv,
                e = i * nv + (j + 1) % nv;
            b_quad(&b, a, e, d, c);
        }
    return b_done(&b);
}

/* A box [-1,1] x [-0.6,0.6] x [-0.4,0.4] of n x n quads per side: sharp
 * edges and corners. */
static lapped_mesh make_box(int n)
{
    builder b;
    int s, i, j, *grid = (int *)malloc(sizeof(int) * (n + 1) * (n + 1));
    double ext[3] = {1.0, 0.6, 0.4};
    memset(&b, 0, sizeof b);
    for (s = 0; s < 6; s++) {
        int ax = s / 2, sg = s % 2 ? -1 : 1, u = (ax + 1) % 3, w = (ax + 2) % 3;
        for (i = 0; i <= n; i++)
            for (j = 0; j <= n; j++) {
                double p[3];
                int k, found = -1;
                p[ax] = sg * ext[ax];
                p[u] = ext[u] * (2.0 * i / n - 1.0);
                p[w] = ext[w] * (2.0 * j / n - 1.0) * sg;
                for (k = 0; k < b.nv && found < 0; k++)
                    if (b.pos[3 * k] == (float)p[0] && b.pos[3 * k + 1] == (float)p[1] && b.pos[3 * k + 2] == (float)p[2])
                        found = k;
                grid[i * (n + 1) + j] = found >= 0 ? found : b_vert(&b, p[0], p[1], p[2]);
            }
        for (i = 0; i < n; i++)
            for (j = 0; j < n; j++)
                b_quad(&b, grid[i * (n + 1) + j], grid[(i + 1) * (n + 1) + j], grid[(i + 1) * (n + 1) + j + 1],
                       grid[i * (n + 1) + j + 1]);
    }
    free(grid);
    return b_done(&b);
}

/* A disc with a boundary, gently domed (z = 0.3 (1 - r^2)): rings x segs. */
static lapped_mesh make_disc(int rings, int segs)
{
    builder b;
    int i, j, c;
    memset(&b, 0, sizeof b);
    c = b_vert(&b, 0, 0, 0.3);
    for (i = 1; i <= rings; i++)
        for (j = 0; j < segs; j++) {
            double r = (double)i / rings, a = 2 * 3.14159265358979 * j / segs;
            b_vert(&b, r * cos(a), r * sin(a), 0.3 * (1 - r * r));
        }
    for (j = 0; j < segs; j++) b_tri(&b, c, 1 + j, 1 + (j + 1) % segs);
    for (i = 1; i < rings; i++)
        for (j = 0; j < segs; j++) {
            int a = 1 + (i - 1) * segs + j, d = 1 + (i - 1) * segs + (j + 1) % segs;
            b_quad(&b, a, a + segs, d + segs, d);
        }
    return b_done(&b);
}

/* A real mesh from data/ (the case is skipped when absent). */
static int load_data_mesh(const char *rel, lapped_mesh *out)
{
    const char *path = pwt_data(rel);
    pw_mesh pm;
    pw_err e;
    if (!path) return 0;
    pw_err_clear(&e);
    if (pw_mesh_load(NULL, path, &pm, &e)) {
        pwt_skip("%s: %s", rel, e.msg);
        return 0;
    }
    memset(out, 0, sizeof *out);
    out->nverts = pm.nv;
    out->positions = pm.pos;
    out->nfaces = pm.nf;
    out->face_start = pm.fstart;
    out->face_verts = pm.fv;
    free(pm.uv);
    free(pm.fuv);
    return 1;
}

/* ---- helpers: a lapped texture made by hand --------------------------------- */

typedef struct handmade {
    lapped_texture t;
    lapped_image patches[2];
    lapped_image values[2]; /* one channel, for the extra-channel test */
} handmade;

static void make_image(lapped_image *im, int w, int h, int c)
{
    memset(im, 0, sizeof *im);
    im->width = w, im->height = h, im->channels = c;
    im->pixels = (float *)calloc((size_t)w * h * c, sizeof(float));
}

/* Patch 0: smooth colours, opaque except a fall-off to transparent at the
 * right (u > 0.8). Patch 1: other colours, a radial alpha reaching 0 at
 * radius 0.45. Colours stay within [0.1, 0.9]. Values: one smooth channel. */
static void make_patches(handmade *H)
{
    int i, j, p;
    make_image(&H->patches[0], 64, 64, 4);
    make_image(&H->patches[1], 48, 48, 4);
    for (p = 0; p < 2; p++) {
        lapped_image *im = &H->patches[p];
        make_image(&H->values[p], im->width, im->height, 1);
        for (i = 0; i < im->height; i++)
            for (j = 0; j < im->width; j++) {
                double u = (j + 0.5) / im->width, v = 1.0 - (i + 0.5) / im->height, a;
                float *px = im->pixels + 4 * (i * im->width + j);
                if (p == 0) {
                    px[0] = (float)(0.5 + 0.4 * sin(6.0 * u));
                    px[1] = (float)(0.5 + 0.4 * cos(5.0 * v));
                    px[2] = (float)(0.5 + 0.4 * sin(4.0 * (u + v)));
                    a = (0.95 - u) / 0.15;
                } else {
                    double r = sqrt((u - 0.5) * (u - 0.5) + (v - 0.5) * (v - 0.5));
                    px[0] = (float)(0.2 + 0.6 * u);
                    px[1] = (float)(0.8 - 0.6 * v);
                    px[2] = (float)(0.5 + 0.3 * sin(9.0 * u * v));
                    a = (0.45 - r) / 0.15;
                }
                px[3] = (float)(a < 0 ? 0 : a > 1 ? 1 : a);
                H->values[p].pixels[i * im->width + j] = (float)(0.3 + 0.2 * u + 0.4 * v * v);
            }
    }
}

static void bbox(const lapped_mesh *m, double *lo, double *hi)
{
    int v, k;
    for (k = 0; k < 3; k++) lo[k] = hi[k] = m->positions[k];
    for (v = 0; v < m->nverts; v++)
        for (k = 0; k < 3; k++) {
            if (m->positions[3 * v + k] < lo[k]) lo[k] = m->positions[3 * v + k];
            if (m->positions[3 * v + k] > hi[k]) hi[k] = m->positions[3 * v + k];
        }
}

/* Paste 0: every triangle, planar projection onto the box's two longest
 * axes into [0.05, 0.95]. Pastes 1..k, around every (nf/k)-th triangle:
 * the triangles with a vertex within R of its centroid c, each vertex p
 * mapped to 0.5 + 0.5 (p - c) / R turned into the tangent plane at c
 * (its projection's direction, its 3D length), so a paste's alpha (zero
 * from radius 0.45) vanishes before the edge of its triangles: the lapped
 * texture is continuous, and bilinear lookups of the atlas can be compared
 * with it anywhere. */
static void paste_uv(const float *v, const double *cc, const double *e1, const double *e2, double R, float *uv)
{
    double d[3], a, b, len3, lenp;
    int c;
    for (c = 0; c < 3; c++) d[c] = v[c] - cc[c];
    a = d[0] * e1[0] + d[1] * e1[1] + d[2] * e1[2];
    b = d[0] * e2[0] + d[1] * e2[1] + d[2] * e2[2];
    len3 = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    lenp = sqrt(a * a + b * b);
    if (lenp > 0) a *= len3 / lenp, b *= len3 / lenp;
    uv[0] = (float)(0.5 + 0.5 * a / R);
    uv[1] = (float)(0.5 + 0.5 * b / R);
}

static void make_texture(const pw_trimesh *m, int k, handmade *H)
{
    double lo[3], hi[3], ext = 0, R, d[3];
    int a0, a1, p, f, c, i, s = 0;
    lapped_mesh view;
    memset(&view, 0, sizeof view);
    view.nverts = m->nv;
    view.positions = (float *)m->pos;
    bbox(&view, lo, hi);
    for (i = 0; i < 3; i++) {
        d[i] = hi[i] - lo[i];
        ext = d[i] > ext ? d[i] : ext;
        if (d[i] < d[s]) s = i; /* the shortest axis is dropped */
    }
    a0 = (s + 1) % 3, a1 = (s + 2) % 3;
    R = 0.15 * ext;
    make_patches(H);
    memset(&H->t, 0, sizeof H->t);
    H->t.ntris = m->nf;
    H->t.npatches = 2;
    H->t.patch_size = (int *)malloc(sizeof(int) * 4);
    H->t.patch_size[0] = 64, H->t.patch_size[1] = 64, H->t.patch_size[2] = 48, H->t.patch_size[3] = 48;
    H->t.npastes = 1 + k;
    H->t.pastes = (lapped_paste *)calloc((size_t)(1 + k), sizeof(lapped_paste));
    for (p = 0; p <= k; p++) {
        lapped_paste *q = H->t.pastes + p;
        int seed = p == 0 ? 0 : (int)((long long)(p - 1) * m->nf / k);
        const float *n0 = m->normal + 3 * seed;
        double cc[3] = {0, 0, 0}, e1[3], e2[3], len;
        q->patch = p == 0 ? 0 : 1;
        q->faces = (int *)malloc(sizeof(int) * m->nf);
        q->uvs = (float *)malloc(sizeof(float) * 6 * m->nf);
        for (i = 0; i < 3; i++)
            for (c = 0; c < 3; c++) cc[c] += m->pos[3 * m->tri[3 * seed + i] + c] / 3.0;
        /* tangent frame at the seed */
        e1[0] = fabs(n0[0]) < 0.9 ? 1 : 0, e1[1] = fabs(n0[0]) < 0.9 ? 0 : 1, e1[2] = 0;
        len = e1[0] * n0[0] + e1[1] * n0[1];
        for (c = 0; c < 3; c++) e1[c] -= len * n0[c];
        len = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
        for (c = 0; c < 3; c++) e1[c] /= len;
        e2[0] = n0[1] * e1[2] - n0[2] * e1[1];
        e2[1] = n0[2] * e1[0] - n0[0] * e1[2];
        e2[2] = n0[0] * e1[1] - n0[1] * e1[0];
        for (f = 0; f < m->nf; f++) {
            int in = p == 0;
            for (i = 0; i < 3 && !in; i++) {
                const float *v = m->pos + 3 * m->tri[3 * f + i];
                double d2 = 0;
                for (c = 0; c < 3; c++) d2 += (v[c] - cc[c]) * (v[c] - cc[c]);
                in = d2 < R * R;
            }
            if (!in) continue;
            for (i = 0; i < 3; i++) {
                const float *v = m->pos + 3 * m->tri[3 * f + i];
                float *uv = q->uvs + 6 * q->nfaces + 2 * i;
                if (p == 0) {
                    uv[0] = (float)(0.05 + 0.9 * (v[a0] - lo[a0]) / ext);
                    uv[1] = (float)(0.05 + 0.9 * (v[a1] - lo[a1]) / ext);
                } else {
                    paste_uv(v, cc, e1, e2, R, uv);
                }
            }
            q->faces[q->nfaces++] = f;
        }
    }
}

static void handmade_free(handmade *H)
{
    int p;
    for (p = 0; p < H->t.npastes; p++) {
        free(H->t.pastes[p].faces);
        free(H->t.pastes[p].uvs);
    }
    free(H->t.pastes);
    free(H->t.patch_size);
    for (p = 0; p < 2; p++) {
        free(H->patches[p].pixels);
        free(H->values[p].pixels);
    }
}

static void free_mesh(lapped_mesh *m)
{
    free(m->positions);
    free(m->face_start);
    free(m->face_verts);
}

static double now(void) { return (double)clock() / CLOCKS_PER_SEC; }

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* A small deterministic generator for sample points. */
static double rnd(unsigned long long *s)
{
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*s >> 11) / 9007199254740992.0;
}

/* ---- checks ------------------------------------------------------------------ */

/* Every triangle in exactly one chart; each chart a connected disc
 * (Euler characteristic 1) whose normals lie within the cone around its
 * seed's, flattened without flips. Returns the number of charts. */
static int check_partition(const pw_trimesh *m, const pw_atlas_charts *C, double cone)
{
    int *seen = (int *)calloc((size_t)m->nf, sizeof(int)), *vmark = (int *)malloc(sizeof(int) * m->nv);
    int *queue = (int *)malloc(sizeof(int) * m->nf), c, i, k, bad_cone = 0, bad_disc = 0, bad_flip = 0;
    double cosc = cos(cone * 3.14159265358979 / 180.0) - 1e-5;
    for (i = 0; i < m->nv; i++) vmark[i] = -1;
    CHECK_EQ_INT(C->start[C->n], m->nf);
    for (c = 0; c < C->n; c++) {
        int seed = C->faces[C->start[c]], V = 0, B = 0, F = C->start[c + 1] - C->start[c], head = 0, tail = 0;
        const float *ns = m->normal + 3 * seed;
        for (i = C->start[c]; i < C->start[c + 1]; i++) {
            int f = C->faces[i];
            const float *n = m->normal + 3 * f;
            double t[6];
            seen[f]++;
            CHECK_EQ_INT(C->chart[f], c);
            if (n[0] * ns[0] + n[1] * ns[1] + n[2] * ns[2] < cosc) bad_cone++;
            for (k = 0; k < 6; k++) t[k] = C->uv[6 * f + k];
            if (!(pw__atlas_area2(t) > 0)) bad_flip++;
            for (k = 0; k < 3; k++) {
                int v = m->tri[3 * f + k], g = pw_trimesh_across(m, f, k);
                if (vmark[v] != c) vmark[v] = c, V++;
                if (g < 0 || C->chart[g] != c) B++;
            }
        }
        /* connected: breadth-first over the chart's faces */
        queue[tail++] = seed;
        seen[seed] += 1000;
        while (head < tail) {
            int f = queue[head++];
            for (k = 0; k < 3; k++) {
                int g = pw_trimesh_across(m, f, k);
                if (g >= 0 && C->chart[g] == c && seen[g] < 1000) seen[g] += 1000, queue[tail++] = g;
            }
        }
        if (tail != F || V - (3 * F + B) / 2 + F != 1) bad_disc++;
    }
    for (i = 0; i < m->nf; i++) CHECKF(seen[i] == 1001, "triangle %d is in %d charts", i, seen[i] % 1000);
    CHECKF(bad_cone == 0, "%d triangles outside their chart's normal cone", bad_cone);
    CHECKF(bad_disc == 0, "%d charts are not connected discs", bad_disc);
    CHECKF(bad_flip == 0, "%d triangles flipped in their chart", bad_flip);
    free(seen);
    free(vmark);
    free(queue);
    return C->n;
}

typedef struct idbuf {
    int *id, *count, size;
    int value;
} idbuf;

static void id_texel(void *user, int x, int y, float b0, float b1, float b2)
{
    idbuf *B = (idbuf *)user;
    (void)b0, (void)b1, (void)b2;
    B->id[y * B->size + x] = B->value;
    B->count[y * B->size + x]++;
}

/* The atlas rasterized: chart id of each texel (-1 none). Checks that no
 * texel is claimed twice (pw_raster_tri's fill rule shares edges exactly),
 * that coordinates keep floor(gutter/2) pixels from the left and bottom
 * border and the rest of the gutter from the others, and that texels of
 * different charts are at least `gutter` apart. */
static int *check_overlap(const pw_trimesh *m, const pw_atlas_charts *C, const lapped_atlas *at, int g,
                          int *ntexels)
{
    int n = at->image.width, f, k, x, y, twice = 0, border = 0, close = 0;
    idbuf B;
    B.size = n;
    B.id = (int *)malloc(sizeof(int) * n * n);
    B.count = (int *)calloc((size_t)n * n, sizeof(int));
    for (k = 0; k < n * n; k++) B.id[k] = -1;
    for (f = 0; f < m->nf; f++) {
        const float *uv = at->uvs + 6 * f;
        for (k = 0; k < 6; k++)
            if (!(uv[k] * n >= g / 2 - 1e-3 && uv[k] * n <= n - (g - g / 2) + 1e-3)) border++;
        B.value = C->chart[f];
        {
            const float tri[6] = {uv[0] * n, (1 - uv[1]) * n, uv[2] * n, (1 - uv[3]) * n, uv[4] * n, (1 - uv[5]) * n};
            pw_raster_tri(tri, n, n, id_texel, &B);
        }
    }
    *ntexels = 0;
    for (y = 0; y < n; y++)
        for (x = 0; x < n; x++) {
            int id = B.id[y * n + x], dx, dy;
            if (B.count[y * n + x] > 1) twice++;
            if (id < 0) continue;
            ++*ntexels;
            for (dy = -(g - 1); dy <= g - 1; dy++)
                for (dx = -(g - 1); dx <= g - 1; dx++) {
                    int X = x + dx, Y = y + dy;
                    if (X >= 0 && Y >= 0 && X < n && Y < n && B.id[Y * n + X] >= 0 && B.id[Y * n + X] != id) close++;
                }
        }
    CHECKF(twice == 0, "%d texels claimed by two triangles", twice);
    CHECKF(border == 0, "%d coordinates within the gutter of the image border", border);
    CHECKF(close == 0, "%d texel pairs of different charts closer than the gutter", close);
    free(B.count);
    return B.id;
}

/* Singular values of the map from triangle f (its own plane) to the atlas
 * (pixels). */
static void tri_sigma(const pw_trimesh *m, const float *uv, int f, double size, double *s1, double *s2)
{
    double x[3], y[3], a, b, c, d, det, tr, disc, ia, ib, ic, id;
    pw__atlas_frame(m, f, x, y);
    /* M maps (x1 - x0, y1 - y0) and (x2 - x0, y2 - y0) to the uv edges */
    det = x[1] * y[2] - x[2] * y[1];
    ia = y[2] / det, ib = -x[2] / det, ic = -y[1] / det, id = x[1] / det; /* inverse of [x1 x2; y1 y2] */
    {
        double u1 = (uv[2] - uv[0]) * size, v1 = (uv[3] - uv[1]) * size;
        double u2 = (uv[4] - uv[0]) * size, v2 = (uv[5] - uv[1]) * size;
        a = u1 * ia + u2 * ic, b = u1 * ib + u2 * id, c = v1 * ia + v2 * ic, d = v1 * ib + v2 * id;
    }
    tr = a * a + b * b + c * c + d * d;
    det = a * d - b * c;
    disc = sqrt(fabs(tr * tr - 4 * det * det));
    *s1 = sqrt((tr + disc) / 2);
    *s2 = sqrt(fabs(tr - disc) / 2);
}

typedef struct wval {
    double v, w;
} wval;

static int cmp_wval(const void *a, const void *b)
{
    double x = ((const wval *)a)->v, y = ((const wval *)b)->v;
    return x < y ? -1 : x > y;
}

/* The value at which the weights reach fraction q. */
static double wquantile(wval *a, int n, double q)
{
    double total = 0, acc = 0;
    int i;
    qsort(a, (size_t)n, sizeof *a, cmp_wval);
    for (i = 0; i < n; i++) total += a[i].w;
    for (i = 0; i < n; i++)
        if ((acc += a[i].w) >= q * total) return a[i].v;
    return a[n - 1].v;
}

/* Distortion (singular-value ratio, area-weighted median and 95th
 * percentile) and the spread of texel density over charts. */
static void measure_maps(const pw_trimesh *m, const pw_atlas_charts *C, const lapped_atlas *at,
                         double *med, double *p95, double *spread, double *density)
{
    wval *r = (wval *)malloc(sizeof(wval) * m->nf);
    double *apx = (double *)calloc((size_t)C->n, sizeof(double)), *a3 = (double *)calloc((size_t)C->n, sizeof(double));
    double lo = 1e300, hi = 0;
    int f, c;
    for (f = 0; f < m->nf; f++) {
        double s1, s2;
        tri_sigma(m, at->uvs + 6 * f, f, at->image.width, &s1, &s2);
        r[f].v = s2 > 0 ? s1 / s2 : 1e9;
        r[f].w = m->area[f];
        apx[C->chart[f]] += s1 * s2 * m->area[f];
        a3[C->chart[f]] += m->area[f];
    }
    *med = wquantile(r, m->nf, 0.5);
    *p95 = wquantile(r, m->nf, 0.95);
    for (c = 0; c < C->n; c++) {
        double d = sqrt(apx[c] / a3[c]);
        if (apx[c] < 16) continue; /* under 16 texels: rounding of the coordinates shows */
        if (d < lo) lo = d;
        if (d > hi) hi = d;
    }
    *spread = hi / lo;
    *density = sqrt((lo * lo + hi * hi) / 2);
    free(r);
    free(apx);
    free(a3);
}

typedef struct evalcheck {
    lapped__look look;
    const lapped_image *img;
    int f, bad;
} evalcheck;

static void eval_texel(void *user, int x, int y, float b0, float b1, float b2)
{
    evalcheck *E = (evalcheck *)user;
    float b[3], out[4], alpha;
    const float *px = E->img->pixels + (size_t)(y * E->img->width + x) * E->img->channels;
    int k;
    b[0] = b0, b[1] = b1, b[2] = b2;
    lapped__eval(&E->look, E->f, b, out, &alpha);
    for (k = 0; k < E->img->channels; k++)
        if (px[k] != out[k] * alpha + 0.5f * (1.0f - alpha)) E->bad++;
}

/* Every covered texel holds exactly the lapped texture at its centre. */
static void check_texel_centres(const pw_trimesh *m, const lapped__index *ix, const lapped_texture *t,
                                const pw_image *pv, const pw_image *vv, const lapped_atlas *at)
{
    evalcheck E;
    int n = at->image.width;
    E.look.ix = ix;
    E.look.t = t;
    E.look.patches = pv;
    E.look.values = vv;
    E.img = &at->image;
    E.bad = 0;
    for (E.f = 0; E.f < m->nf; E.f++) {
        const float *uv = at->uvs + 6 * E.f;
        {
            const float tri[6] = {uv[0] * n, (1 - uv[1]) * n, uv[2] * n, (1 - uv[3]) * n, uv[4] * n, (1 - uv[5]) * n};
            pw_raster_tri(tri, n, n, eval_texel, &E);
        }
    }
    CHECKF(E.bad == 0, "%d texel channels differ from the lapped texture at their centre", E.bad);
}

/* Bilinear lookups of the atlas at random surface points against the
 * lapped texture there: errors (largest channel) at points whose four
 * texels all belong to the point's chart ("inside") and at all points.
 * Where the texture itself changes steeply within a texel (the hand-made
 * pastes have a few such places) no atlas can follow it: hence quantiles. */
typedef struct errstats {
    double p99, p999, max;
} errstats;

static errstats quantiles(double *e, int n)
{
    errstats q = {0, 0, 0};
    if (n == 0) return q;
    qsort(e, (size_t)n, sizeof(double), cmp_double);
    q.p99 = e[(int)(0.99 * n)];
    q.p999 = e[(int)(0.999 * n)];
    q.max = e[n - 1];
    return q;
}

static void check_samples(const pw_trimesh *m, const pw_atlas_charts *C, const lapped__index *ix,
                          const lapped_texture *t, const pw_image *pv, const pw_image *vv, const lapped_atlas *at,
                          const int *ids, errstats *in, errstats *all)
{
    enum { N = 20000 };
    double *cum = (double *)malloc(sizeof(double) * m->nf), *ein = (double *)malloc(sizeof(double) * N);
    double *eall = (double *)malloc(sizeof(double) * N);
    unsigned long long seed = 12345;
    pw_image img = lapped__pw_image(&at->image);
    lapped__look L;
    int f, i, nin = 0, n = at->image.width;
    L.ix = ix;
    L.t = t;
    L.patches = pv;
    L.values = vv;
    for (f = 0; f < m->nf; f++) cum[f] = (f ? cum[f - 1] : 0) + m->area[f];
    for (i = 0; i < N; i++) {
        double r = rnd(&seed) * cum[m->nf - 1], s = sqrt(rnd(&seed)), q = rnd(&seed), u = 0, v = 0, err = 0;
        int lo = 0, hi = m->nf - 1, k, x0, y0, inside = 1;
        float b[3], out[4], alpha, got[4];
        while (lo < hi) {
            int mid = (lo + hi) / 2;
            if (cum[mid] < r) lo = mid + 1;
            else hi = mid;
        }
        f = lo;
        b[0] = (float)(1 - s), b[1] = (float)(s * (1 - q)), b[2] = (float)(s * q);
        for (k = 0; k < 3; k++) u += b[k] * at->uvs[6 * f + 2 * k], v += b[k] * at->uvs[6 * f + 2 * k + 1];
        pw_image_sample_bilinear(&img, (float)(u * n), (float)((1 - v) * n), got);
        lapped__eval(&L, f, b, out, &alpha);
        for (k = 0; k < img.c; k++) {
            double d = fabs(got[k] - (out[k] * alpha + 0.5 * (1 - alpha)));
            if (d > err) err = d;
        }
        x0 = (int)floor(u * n - 0.5), y0 = (int)floor((1 - v) * n - 0.5);
        for (k = 0; k < 4; k++) {
            int X = x0 + (k & 1), Y = y0 + (k >> 1);
            if (X < 0 || Y < 0 || X >= n || Y >= n || ids[Y * n + X] != C->chart[f]) inside = 0;
        }
        if (inside) ein[nin++] = err;
        eall[i] = err;
    }
    *in = quantiles(ein, nin);
    *all = quantiles(eall, N);
    free(cum);
    free(ein);
    free(eall);
}

/* Every texel within `gutter` (chessboard) of a covered texel is filled:
 * the test colours are within [0.1, 0.9], the background is 0. */
static void check_gutter(const lapped_atlas *at, const int *ids, int g)
{
    int n = at->image.width, c = at->image.channels, x, y, k, empty = 0;
    for (y = 0; y < n; y++)
        for (x = 0; x < n; x++) {
            int dx, dy, near = 0;
            for (dy = -g; dy <= g && !near; dy++)
                for (dx = -g; dx <= g && !near; dx++) {
                    int X = x + dx, Y = y + dy;
                    near = X >= 0 && Y >= 0 && X < n && Y < n && ids[Y * n + X] >= 0;
                }
            if (!near) continue;
            for (k = 0; k < c; k++)
                if (!(at->image.pixels[(size_t)(y * n + x) * c + k] >= 0.05f)) {
                    empty++;
                    break;
                }
        }
    CHECKF(empty == 0, "%d texels within the gutter are not filled", empty);
}

/* Writes the atlas and a rendering of the mesh textured with it to
 * $LAPPED_ATLAS_OUT/atlas_NAME.png and render_NAME.png, if set. */
static void write_pictures(const char *name, const pw_trimesh *m, const lapped_atlas *at)
{
    const char *dir = getenv("LAPPED_ATLAS_OUT");
    char path[1024];
    pw_image img = lapped__pw_image(&at->image), out;
    pw_texture tex;
    pw_fb fb;
    pw_draw d;
    pw_camera cam;
    pw_err e;
    float bg[4] = {1, 1, 1, 1}, dir3[3] = {-0.55f, -0.45f, -0.7f};
    if (!dir || !*dir) return;
    pw_err_clear(&e);
    snprintf(path, sizeof path, "%s/atlas_%s.png", dir, name);
    pw_image_save(path, &img, &e);
    memset(&out, 0, sizeof out);
    if (pw_texture_create(NULL, &tex, &img, 0, &e) || pw_fb_create(NULL, &fb, 800, 600, 2, bg, &e)) return;
    cam = pw_camera_frame(m->pos, m->nv, dir3, NULL, 40.0f, 800.0f / 600.0f);
    memset(&d, 0, sizeof d);
    d.positions = m->pos, d.nv = m->nv, d.tris = m->tri, d.ntris = m->nf;
    d.uvs = at->uvs, d.tex = &tex, d.lighting = PW_LIGHT_CAMERA, d.wrap = PW_WRAP_CLAMP;
    if (!pw_render_draw(&fb, &cam, &d, &e) && !pw_fb_resolve(&fb, &out, 3, &e)) {
        snprintf(path, sizeof path, "%s/render_%s.png", dir, name);
        pw_image_save(path, &out, &e);
    }
    CHECKF(e.code == 0, "pictures: %s", e.msg);
    pw_image_free(NULL, &out);
    pw_fb_free(&fb);
    pw_texture_free(NULL, &tex);
}

/* lapped_bake_atlas of the patches p (and values v, or NULL), as many as
 * t has, with atlas options ao (NULL: those of o) and options o (NULL: the
 * defaults). */
static lapped_result bake(const lapped_mesh *mesh, const lapped_texture *t, const lapped_image *p,
                          const lapped_image *v, const lapped_atlas_options *ao, const lapped_options *o,
                          lapped_atlas *out, lapped_error *err)
{
    lapped_options opt = o ? *o : lapped_default_options();
    lapped_source src;
    src.patches = p;
    src.npatches = t ? t->npatches : 0;
    src.values = v;
    if (ao) opt.atlas = *ao;
    return lapped_bake_atlas(mesh, t, &src, &opt, out, err);
}

/* Bakes the hand-made lapped texture of `mesh` into an atlas (cone angle
 * `cone`, `gutter`) and checks everything; fill must reach fill_floor. */
static void check_mesh_with(const char *name, const lapped_mesh *mesh, int npastes, int size, double cone, int gutter,
                            double fill_floor)
{
    pw_trimesh m;
    pw_atlas_charts C;
    pw_atlas_job job;
    lapped__index ix;
    handmade H;
    lapped_atlas at;
    lapped_atlas_options ao;
    lapped_error err;
    pw_err e;
    pw_image pv[2];
    double t0, t1, t2, med, p95, spread, dens;
    errstats in, all;
    int *ids, ntex, r;
    pw_err_clear(&e);
    REQUIRE(lapped__mesh_init(NULL, mesh, &m, &e) == PW_OK);
    make_texture(&m, npastes, &H);
    memset(&ao, 0, sizeof ao);
    ao.size = size;
    ao.cone_angle = (float)cone;
    ao.gutter = gutter;
    t0 = now();
    r = bake(mesh, &H.t, H.patches, NULL, &ao, NULL, &at, &err);
    t1 = now();
    CHECKF(r == LAPPED_OK, "%s: %s", name, err.message);
    if (r != LAPPED_OK) {
        handmade_free(&H);
        pw_trimesh_free(NULL, &m);
        return;
    }
    memset(&job, 0, sizeof job);
    job.m = &m;
    job.cone = (float)cone;
    REQUIRE(pw_atlas_charts_build(&job, &C, &e) == PW_OK);
    t2 = now();
    CHECK_EQ_INT(check_partition(&m, &C, cone), at.ncharts);
    CHECK_EQ_INT(at.ntris, m.nf);
    CHECK_EQ_INT(at.image.channels, 3);
    ids = check_overlap(&m, &C, &at, gutter, &ntex);
    measure_maps(&m, &C, &at, &med, &p95, &spread, &dens);
    REQUIRE(lapped__index_build(NULL, &H.t, &ix, &e) == PW_OK);
    pv[0] = lapped__pw_image(&H.patches[0]);
    pv[1] = lapped__pw_image(&H.patches[1]);
    check_texel_centres(&m, &ix, &H.t, pv, pv, &at);
    check_samples(&m, &C, &ix, &H.t, pv, pv, &at, ids, &in, &all);
    check_gutter(&at, ids, gutter);
    pwt_info("%s: %d triangles, %d charts, fill %.3f (texels %.3f), distortion (sigma1/sigma2, area-weighted) "
             "median %.3f p95 %.3f, density %.1f texels/unit, chart spread %.4f, bake %.2f s (charts alone %.2f s)",
             name, m.nf, at.ncharts, at.fill, (double)ntex / ((double)size * size), med, p95, dens, spread,
             t1 - t0, t2 - t1);
    pwt_info("%s: |atlas - lapped texture| at random points: inside charts p99 %.4f p99.9 %.4f max %.4f; "
             "all p99 %.4f p99.9 %.4f max %.4f", name, in.p99, in.p999, in.max, all.p99, all.p999, all.max);
    CHECKF(at.fill >= fill_floor, "%s: fill %.3f below %.2f", name, at.fill, fill_floor);
    CHECKF(spread < 1.01, "%s: texel density varies by %.4f between charts", name, spread);
    CHECKF(med < 1.1 && p95 < 1.5, "%s: distortion median %.3f p95 %.3f", name, med, p95);
    CHECKF(in.p99 < 0.01 && in.p999 < 0.05, "%s: atlas inside charts differs from the texture (p99 %.4f, "
           "p99.9 %.4f)", name, in.p99, in.p999);
    CHECKF(all.p99 < 0.02, "%s: atlas differs from the texture (p99 %.4f)", name, all.p99);
    write_pictures(name, &m, &at);
    free(ids);
    lapped__index_free(NULL, &ix);
    pw_atlas_charts_free(NULL, &C);
    lapped_atlas_free(&at);
    handmade_free(&H);
    pw_trimesh_free(NULL, &m);
}

static void check_mesh(const char *name, const lapped_mesh *mesh, int npastes, int size, double fill_floor)
{
    check_mesh_with(name, mesh, npastes, size, 60.0, 2, fill_floor);
}

/* ---- cases ---------------------------------------------------------------------- */

static void t_icosphere(void)
{
    lapped_mesh m = make_icosphere(4);
    check_mesh("icosphere", &m, 12, 1024, 0.5);
    free_mesh(&m);
}

static void t_torus(void)
{
    lapped_mesh m = make_torus(96, 48, 1.0, 0.35);
    check_mesh("torus", &m, 12, 1024, 0.5);
    free_mesh(&m);
}

static void t_box(void)
{
    lapped_mesh m = make_box(24);
    check_mesh("box", &m, 12, 1024, 0.5);
    free_mesh(&m);
}

static void t_disc(void)
{
    lapped_mesh m = make_disc(30, 96);
    check_mesh("disc", &m, 8, 512, 0.5);
    free_mesh(&m);
}

/* Other cone angles and gutters (odd ones pad one pixel more to the right
 * and top), at a smaller size. */
static void t_options(void)
{
    lapped_mesh m = make_icosphere(3), t = make_torus(48, 24, 1.0, 0.35);
    check_mesh_with("icosphere cone 20", &m, 6, 512, 20.0, 2, 0.4);
    check_mesh_with("icosphere cone 120", &m, 6, 512, 120.0, 2, 0.4);
    check_mesh_with("torus gutter 1", &t, 6, 512, 60.0, 1, 0.4);
    check_mesh_with("torus gutter 3", &t, 6, 512, 60.0, 3, 0.4);
    check_mesh_with("torus gutter 8", &t, 6, 512, 60.0, 8, 0.3);
    check_mesh_with("torus 2048 gutter 3", &t, 6, 2048, 60.0, 3, 0.4); /* grid cells of 2 pixels */
    free_mesh(&m);
    free_mesh(&t);
}

/* A single triangle, and two separate components. */
static void t_small_meshes(void)
{
    builder b;
    lapped_mesh m;
    memset(&b, 0, sizeof b);
    b_vert(&b, 0, 0, 0), b_vert(&b, 1, 0, 0), b_vert(&b, 0.2, 0.7, 0.1);
    b_tri(&b, 0, 1, 2);
    m = b_done(&b);
    check_mesh_with("one triangle", &m, 1, 64, 60.0, 2, 0.3);
    free_mesh(&m);
    memset(&b, 0, sizeof b);
    b_vert(&b, 0, 0, 0), b_vert(&b, 1, 0, 0), b_vert(&b, 1, 1, 0), b_vert(&b, 0, 1, 0);
    b_vert(&b, 3, 0, 0), b_vert(&b, 3, 1, 0), b_vert(&b, 3, 1, 1), b_vert(&b, 3, 0, 1);
    b_quad(&b, 0, 1, 2, 3);
    b_quad(&b, 4, 5, 6, 7);
    m = b_done(&b);
    check_mesh_with("two squares", &m, 2, 64, 60.0, 2, 0.4); /* side by side: 2 (30x30) / 64^2 */
    free_mesh(&m);
}

static void data_case(const char *file, const char *name, int size, double floor_)
{
    lapped_mesh m;
    if (!load_data_mesh(file, &m)) return;
    check_mesh(name, &m, 16, size, floor_);
    free_mesh(&m);
}

static void t_cow(void) { data_case("meshes/cow.off", "cow", 1024, 0.5); }
static void t_homer(void) { data_case("meshes/homer.off", "homer", 1024, 0.5); }
static void t_camel(void) { data_case("meshes/camel.off", "camel", 1024, 0.5); }
static void t_armadillo(void) { data_case("meshes/armadillo.off", "armadillo", 1024, 0.5); }
static void t_bunny(void) { data_case("meshes/bunny00.off", "bunny", 1024, 0.5); }
static void t_elephant(void) { data_case("meshes/elephant.off", "elephant", 1024, 0.5); }

/* A small mesh and its hand-made texture, for the cases below. */
static int small_setup(lapped_mesh *mesh, pw_trimesh *m, handmade *H)
{
    pw_err e;
    pw_err_clear(&e);
    *mesh = make_torus(32, 16, 1.0, 0.4);
    if (lapped__mesh_init(NULL, mesh, m, &e)) return 0;
    make_texture(m, 6, H);
    return 1;
}

static void small_free(lapped_mesh *mesh, pw_trimesh *m, handmade *H)
{
    handmade_free(H);
    pw_trimesh_free(NULL, m);
    free_mesh(mesh);
}

static void t_deterministic(void)
{
    lapped_mesh mesh = make_icosphere(3);
    pw_trimesh m;
    handmade H;
    lapped_atlas a, b;
    lapped_atlas_options ao;
    lapped_error err;
    pw_err e;
    pw_err_clear(&e);
    REQUIRE(lapped__mesh_init(NULL, &mesh, &m, &e) == PW_OK);
    make_texture(&m, 8, &H);
    memset(&ao, 0, sizeof ao);
    ao.size = 256;
    REQUIRE(bake(&mesh, &H.t, H.patches, NULL, &ao, NULL, &a, &err) == LAPPED_OK);
    REQUIRE(bake(&mesh, &H.t, H.patches, NULL, &ao, NULL, &b, &err) == LAPPED_OK);
    CHECK(a.ncharts == b.ncharts && a.fill == b.fill);
    CHECK(!memcmp(a.uvs, b.uvs, sizeof(float) * 6 * m.nf));
    CHECK(!memcmp(a.image.pixels, b.image.pixels, sizeof(float) * 3 * 256 * 256));
    lapped_atlas_free(&a);
    lapped_atlas_free(&b);
    handmade_free(&H);
    pw_trimesh_free(NULL, &m);
    free_mesh(&mesh);
}

/* Extra channels (§1: "extends trivially to bump maps..."): one-channel
 * values baked through the same charts and pastes. */
static void t_values(void)
{
    lapped_mesh mesh;
    pw_trimesh m;
    handmade H;
    lapped_atlas a, rgb;
    lapped_atlas_options ao;
    lapped_error err;
    lapped__index ix;
    pw_image pv[2], vv[2];
    pw_err e;
    pw_err_clear(&e);
    REQUIRE(small_setup(&mesh, &m, &H));
    memset(&ao, 0, sizeof ao);
    ao.size = 256;
    REQUIRE(bake(&mesh, &H.t, H.patches, H.values, &ao, NULL, &a, &err) == LAPPED_OK);
    REQUIRE(bake(&mesh, &H.t, H.patches, NULL, &ao, NULL, &rgb, &err) == LAPPED_OK);
    CHECK_EQ_INT(a.image.channels, 1);
    CHECK(!memcmp(a.uvs, rgb.uvs, sizeof(float) * 6 * m.nf)); /* the same charts */
    REQUIRE(lapped__index_build(NULL, &H.t, &ix, &e) == PW_OK);
    pv[0] = lapped__pw_image(&H.patches[0]), pv[1] = lapped__pw_image(&H.patches[1]);
    vv[0] = lapped__pw_image(&H.values[0]), vv[1] = lapped__pw_image(&H.values[1]);
    check_texel_centres(&m, &ix, &H.t, pv, vv, &a);
    lapped__index_free(NULL, &ix);
    lapped_atlas_free(&a);
    lapped_atlas_free(&rgb);
    small_free(&mesh, &m, &H);
}

typedef struct membuf {
    char *data;
    size_t n, cap;
} membuf;

static int mem_write(void *ctx, const void *data, size_t size)
{
    membuf *b = (membuf *)ctx;
    if (b->n + size > b->cap) {
        b->cap = 2 * (b->n + size);
        b->data = (char *)realloc(b->data, b->cap);
    }
    memcpy(b->data + b->n, data, size);
    b->n += size;
    return 0;
}

static int cmp_uv(const void *a, const void *b) { return memcmp(a, b, 2 * sizeof(float)); }

/* The OBJ reads back (pw_mesh_read_memory) with the same positions, the
 * triangles of the fan triangulation in order, one vt per distinct
 * coordinate pair, and each corner's atlas coordinates. */
static void t_obj(void)
{
    lapped_mesh mesh;
    pw_trimesh m;
    handmade H;
    lapped_atlas a;
    lapped_atlas_options ao;
    lapped_error err;
    membuf obj = {0, 0, 0}, mtl = {0, 0, 0};
    pw_mesh back;
    pw_err e;
    float *sorted;
    int i, k, distinct = 0, corners_ok = 1;
    pw_err_clear(&e);
    REQUIRE(small_setup(&mesh, &m, &H));
    memset(&ao, 0, sizeof ao);
    ao.size = 256;
    REQUIRE(bake(&mesh, &H.t, H.patches, NULL, &ao, NULL, &a, &err) == LAPPED_OK);
    REQUIRE(lapped_write_obj(&mesh, &a, "torus.mtl", mem_write, &obj, &err) == LAPPED_OK);
    REQUIRE(lapped_write_mtl("torus.png", mem_write, &mtl, &err) == LAPPED_OK);
    mem_write(&mtl, "", 1);
    CHECK(strstr(mtl.data, "newmtl lapped") && strstr(mtl.data, "map_Kd torus.png"));
    CHECK(obj.n > 0 && strstr(obj.data, "mtllib torus.mtl") && strstr(obj.data, "usemtl lapped"));
    REQUIRE(pw_mesh_read_memory(NULL, obj.data, obj.n, "atlas.obj", &back, &e) == PW_OK);
    CHECK_EQ_INT(back.nv, mesh.nverts);
    CHECK(!memcmp(back.pos, mesh.positions, sizeof(float) * 3 * mesh.nverts));
    CHECK_EQ_INT(back.nf, m.nf);
    sorted = (float *)malloc(sizeof(float) * 6 * m.nf);
    memcpy(sorted, a.uvs, sizeof(float) * 6 * m.nf);
    qsort(sorted, (size_t)3 * m.nf, 2 * sizeof(float), cmp_uv);
    for (i = 0; i < 3 * m.nf; i++) distinct += i == 0 || cmp_uv(sorted + 2 * i, sorted + 2 * i - 2);
    CHECK_EQ_INT(back.nuv, distinct);
    REQUIRE(back.fuv && back.nf == m.nf);
    for (i = 0; i < m.nf; i++)
        for (k = 0; k < 3; k++) {
            int c = back.fstart[i] + k;
            if (back.fstart[i + 1] - back.fstart[i] != 3 || back.fv[c] != m.tri[3 * i + k] ||
                memcmp(back.uv + 2 * back.fuv[c], a.uvs + 6 * i + 2 * k, 2 * sizeof(float)))
                corners_ok = 0;
        }
    CHECK(corners_ok);
    /* without a material: no mtllib, no usemtl */
    obj.n = 0;
    REQUIRE(lapped_write_obj(&mesh, &a, NULL, mem_write, &obj, &err) == LAPPED_OK);
    mem_write(&obj, "", 1);
    CHECK(!strstr(obj.data, "mtllib") && !strstr(obj.data, "usemtl"));
    free(sorted);
    free(obj.data);
    free(mtl.data);
    pw_mesh_free(NULL, &back);
    lapped_atlas_free(&a);
    small_free(&mesh, &m, &H);
}

/* Bakes with one thing changed; expects `code` and a message naming
 * `needle`, and a zeroed atlas. */
static void expect_bad(const char *what, const lapped_mesh *mesh, const lapped_texture *t, const lapped_image *p,
                       const lapped_image *v, const lapped_atlas_options *ao, lapped_result code, const char *needle)
{
    lapped_atlas a;
    lapped_error err;
    lapped_result r;
    memset(&err, 0, sizeof err);
    r = bake(mesh, t, p, v, ao, NULL, &a, &err);
    CHECKF(r == code, "%s: got %d (%s), wanted %d", what, (int)r, err.message, (int)code);
    CHECKF(strstr(err.message, needle) != NULL, "%s: message \"%s\" does not name \"%s\"", what, err.message, needle);
    CHECKF(a.uvs == NULL && a.image.pixels == NULL && a.ntris == 0, "%s: atlas not zeroed", what);
    lapped_atlas_free(&a);
}

static void t_bad_inputs(void)
{
    lapped_mesh mesh, big;
    pw_trimesh m;
    handmade H;
    lapped_atlas_options ao, bad;
    lapped_image p3[2], v2[2];
    lapped_atlas a;
    lapped_error err;
    float saved;
    int save;
    REQUIRE(small_setup(&mesh, &m, &H));
    memset(&ao, 0, sizeof ao);
    ao.size = 128;
    save = H.t.ntris, H.t.ntris = m.nf + 1;
    expect_bad("ntris", &mesh, &H.t, H.patches, NULL, &ao, LAPPED_ERR_INVALID, "triangles");
    H.t.ntris = save, save = H.t.npatches, H.t.npatches = 1;
    expect_bad("patch index", &mesh, &H.t, H.patches, NULL, &ao, LAPPED_ERR_INVALID, "patch 1");
    H.t.npatches = save, save = H.t.patch_size[0], H.t.patch_size[0] = 32;
    expect_bad("patch size", &mesh, &H.t, H.patches, NULL, &ao, LAPPED_ERR_INVALID, "patch 0");
    H.t.patch_size[0] = save;
    p3[0] = H.patches[0], p3[1] = H.patches[1], p3[1].channels = 3;
    expect_bad("patch channels", &mesh, &H.t, p3, NULL, &ao, LAPPED_ERR_INVALID, "channels");
    v2[0] = H.values[0], v2[1] = H.values[1], v2[1].width = 24;
    expect_bad("value size", &mesh, &H.t, H.patches, v2, &ao, LAPPED_ERR_INVALID, "value image 1");
    v2[1] = H.patches[1];
    expect_bad("value channels", &mesh, &H.t, H.patches, v2, &ao, LAPPED_ERR_INVALID, "value image 1");
    expect_bad("no patches", &mesh, &H.t, NULL, NULL, &ao, LAPPED_ERR_INVALID, "patches");
    expect_bad("no texture", &mesh, NULL, H.patches, NULL, &ao, LAPPED_ERR_INVALID, "texture");
    expect_bad("no mesh", NULL, &H.t, H.patches, NULL, &ao, LAPPED_ERR_INVALID, "mesh");
    save = H.t.pastes[1].faces[0], H.t.pastes[1].faces[0] = m.nf;
    expect_bad("paste face", &mesh, &H.t, H.patches, NULL, &ao, LAPPED_ERR_INVALID, "paste 1");
    H.t.pastes[1].faces[0] = save, saved = H.t.pastes[0].uvs[3], H.t.pastes[0].uvs[3] = (float)sqrt(-1.0);
    expect_bad("paste uv", &mesh, &H.t, H.patches, NULL, &ao, LAPPED_ERR_INVALID, "paste 0");
    H.t.pastes[0].uvs[3] = saved;
    bad = ao, bad.size = 8;
    expect_bad("small size", &mesh, &H.t, H.patches, NULL, &bad, LAPPED_ERR_INVALID, "size");
    bad = ao, bad.size = 100000;
    expect_bad("large size", &mesh, &H.t, H.patches, NULL, &bad, LAPPED_ERR_LIMIT, "size");
    bad = ao, bad.cone_angle = -5;
    expect_bad("negative cone", &mesh, &H.t, H.patches, NULL, &bad, LAPPED_ERR_INVALID, "cone");
    bad = ao, bad.cone_angle = (float)sqrt(-1.0);
    expect_bad("NaN cone", &mesh, &H.t, H.patches, NULL, &bad, LAPPED_ERR_INVALID, "cone");
    bad = ao, bad.cone_angle = 200;
    expect_bad("wide cone", &mesh, &H.t, H.patches, NULL, &bad, LAPPED_ERR_INVALID, "cone");
    bad = ao, bad.gutter = -1;
    expect_bad("negative gutter", &mesh, &H.t, H.patches, NULL, &bad, LAPPED_ERR_INVALID, "gutter");
    bad = ao, bad.gutter = 65;
    expect_bad("wide gutter", &mesh, &H.t, H.patches, NULL, &bad, LAPPED_ERR_INVALID, "gutter");
    CHECK(bake(&mesh, &H.t, H.patches, NULL, &ao, NULL, NULL, &err) == LAPPED_ERR_INVALID);
    { /* a source whose patch count is not the texture's, and none */
        lapped_options o = lapped_default_options();
        lapped_source src;
        lapped_atlas a;
        o.atlas = ao;
        src.patches = H.patches, src.npatches = 1, src.values = NULL;
        CHECKF(lapped_bake_atlas(&mesh, &H.t, &src, &o, &a, &err) == LAPPED_ERR_INVALID &&
               strstr(err.message, "made with 2 patches, the source has 1"), "%s", err.message);
        CHECKF(lapped_bake_atlas(&mesh, &H.t, NULL, &o, &a, &err) == LAPPED_ERR_INVALID &&
               strstr(err.message, "no patches"), "%s", err.message);
    }
    /* a mesh with too many charts for a tiny atlas */
    big = make_icosphere(4);
    {
        pw_trimesh bm;
        handmade BH;
        pw_err e;
        pw_err_clear(&e);
        REQUIRE(lapped__mesh_init(NULL, &big, &bm, &e) == PW_OK);
        make_texture(&bm, 2, &BH);
        bad = ao, bad.size = 16, bad.cone_angle = 5;
        expect_bad("too many charts", &big, &BH.t, BH.patches, NULL, &bad, LAPPED_ERR_LIMIT, "charts do not fit");
        handmade_free(&BH);
        pw_trimesh_free(NULL, &bm);
    }
    free_mesh(&big);
    /* the OBJ writer checks the atlas against the mesh */
    REQUIRE(bake(&mesh, &H.t, H.patches, NULL, &ao, NULL, &a, &err) == LAPPED_OK);
    {
        membuf b = {0, 0, 0};
        a.ntris--;
        CHECK(lapped_write_obj(&mesh, &a, NULL, mem_write, &b, &err) == LAPPED_ERR_INVALID);
        CHECK(strstr(err.message, "triangles") != NULL);
        a.ntris++;
        CHECK(lapped_write_obj(&mesh, &a, NULL, NULL, &b, &err) == LAPPED_ERR_INVALID);
        CHECK(lapped_write_obj(&mesh, &a, "bad\nname", mem_write, &b, &err) == LAPPED_ERR_INVALID);
        CHECK(lapped_write_mtl("x.png", NULL, &b, &err) == LAPPED_ERR_INVALID);
        free(b.data);
    }
    lapped_atlas_free(&a);
    small_free(&mesh, &m, &H);
}

/* Every allocation failure is reported as such and leaks nothing. */
static void t_alloc_failures(void)
{
    lapped_mesh mesh = make_icosphere(1);
    pw_trimesh m;
    handmade H;
    lapped_atlas_options ao;
    lapped_options o = lapped_default_options();
    pwt_alloc_state st = {0, 0, -1};
    lapped_atlas a;
    lapped_error err;
    pw_err e;
    long total, k, bad = 0, leaks = 0;
    pw_err_clear(&e);
    REQUIRE(lapped__mesh_init(NULL, &mesh, &m, &e) == PW_OK);
    make_texture(&m, 3, &H);
    memset(&ao, 0, sizeof ao);
    ao.size = 64;
    o.allocator.malloc_fn = pwt_malloc, o.allocator.realloc_fn = pwt_realloc;
    o.allocator.free_fn = pwt_free, o.allocator.user = &st;
    REQUIRE(bake(&mesh, &H.t, H.patches, NULL, &ao, &o, &a, &err) == LAPPED_OK);
    lapped_atlas_free(&a);
    total = st.calls;
    CHECK_EQ_INT(st.live, 0);
    for (k = 0; k < total; k++) {
        lapped_result r;
        st.calls = 0, st.live = 0, st.fail_after = k;
        r = bake(&mesh, &H.t, H.patches, NULL, &ao, &o, &a, &err);
        if (r == LAPPED_OK) lapped_atlas_free(&a);
        else if (r != LAPPED_ERR_NOMEM) bad++;
        if (st.live) leaks++;
    }
    pwt_info("%ld allocations per bake of %d triangles, each made to fail once", total, m.nf);
    CHECKF(bad == 0, "%ld failures reported as something else than NOMEM", bad);
    CHECKF(leaks == 0, "%ld failures leaked memory", leaks);
    handmade_free(&H);
    pw_trimesh_free(NULL, &m);
    free_mesh(&mesh);
}

static int cancel_after(void *user, float done, const char *stage)
{
    (void)done, (void)stage;
    return --*(int *)user < 0;
}

static void t_cancel(void)
{
    lapped_mesh mesh;
    pw_trimesh m;
    handmade H;
    lapped_atlas_options ao;
    lapped_options o = lapped_default_options();
    lapped_atlas a;
    lapped_error err;
    int n, calls = 1000000, k;
    REQUIRE(small_setup(&mesh, &m, &H));
    memset(&ao, 0, sizeof ao);
    ao.size = 128;
    o.progress = cancel_after, o.progress_user = &calls;
    REQUIRE(bake(&mesh, &H.t, H.patches, NULL, &ao, &o, &a, &err) == LAPPED_OK);
    lapped_atlas_free(&a);
    n = 1000000 - calls;
    CHECK(n > 2);
    for (k = 0; k < n; k += n / 4 + 1) {
        calls = k;
        CHECK(bake(&mesh, &H.t, H.patches, NULL, &ao, &o, &a, &err) == LAPPED_ERR_CANCELLED);
        CHECK(a.uvs == NULL);
    }
    small_free(&mesh, &m, &H);
}

/* The whole pipeline: a lapped texture made by lapped_create on a
 * built-in mesh, baked; every covered texel holds the lapped texture at its
 * centre. With LAPPED_ATLAS_OUT set, also writes the atlas, a rendering of
 * it, the OBJ and the MTL. */
static void t_pipeline(void)
{
    lapped_options o = lapped_default_options();
    lapped_mesh mesh;
    lapped_image tex, patch;
    lapped_source src;
    lapped_texture t;
    lapped_atlas at;
    lapped_error err;
    pw_trimesh m;
    lapped__index ix;
    pw_image pv;
    pw_err e;
    double t0;
    pw_err_clear(&e);
    o.scale = 0.5f;
    REQUIRE(lapped_builtin_mesh("bumpy", &o, &mesh, &err) == LAPPED_OK);
    REQUIRE(lapped_builtin_exemplar("scales", 96, &o, &tex, &err) == LAPPED_OK);
    REQUIRE(lapped_make_patch(&tex, NULL, &o, &patch, &err) == LAPPED_OK);
    src.patches = &patch, src.npatches = 1, src.values = NULL;
    CHECKF(lapped_create(&mesh, &src, &o, &t, &err) == LAPPED_OK, "lapped_create: %s", err.message);
    if (err.code == LAPPED_OK) {
        t0 = now();
        CHECKF(bake(&mesh, &t, &patch, NULL, NULL, &o, &at, &err) == LAPPED_OK, "%s", err.message);
        if (err.code == LAPPED_OK) {
            REQUIRE(lapped__mesh_init(NULL, &mesh, &m, &e) == PW_OK);
            REQUIRE(lapped__index_build(NULL, &t, &ix, &e) == PW_OK);
            pv = lapped__pw_image(&patch);
            check_texel_centres(&m, &ix, &t, &pv, &pv, &at);
            pwt_info("bumpy: %d triangles, %d pastes, %d charts, fill %.3f, atlas %dx%d in %.2f s", m.nf,
                     t.npastes, at.ncharts, at.fill, at.image.width, at.image.height, now() - t0);
            write_pictures("pipeline", &m, &at);
            if (getenv("LAPPED_ATLAS_OUT")) {
                char path[1024];
                FILE *f;
                snprintf(path, sizeof path, "%s/pipeline.obj", getenv("LAPPED_ATLAS_OUT"));
                if ((f = fopen(path, "wb")) != NULL) {
                    membuf b = {0, 0, 0};
                    lapped_write_obj(&mesh, &at, "pipeline.mtl", mem_write, &b, &err);
                    fwrite(b.data, 1, b.n, f);
                    fclose(f);
                    free(b.data);
                }
            }
            lapped__index_free(NULL, &ix);
            pw_trimesh_free(NULL, &m);
            lapped_atlas_free(&at);
        }
        lapped_texture_free(&t);
    }
    lapped_image_free(&patch);
    lapped_image_free(&tex);
    lapped_mesh_free(&mesh);
}

/* The calipers' rectangle against all edges of random convex hulls. */
static void t_min_rect(void)
{
    unsigned long long s = 7;
    double pts[2 * 200], hull[2 * 201];
    int trial, worse = 0;
    for (trial = 0; trial < 500; trial++) {
        int n = 3 + trial % 150, h, i, k;
        double best = 1e300, got = 0, lo[2] = {0, 0}, hi[2] = {0, 0};
        for (i = 0; i < n; i++) {
            double a = rnd(&s) * 6.283185307, r = trial % 3 ? sqrt(rnd(&s)) : 1.0;
            pts[2 * i] = r * cos(a) * (1 + trial % 5), pts[2 * i + 1] = r * sin(a);
        }
        h = pw__atlas_hull(pts, n, hull);
        for (i = 0; i <= h; i++) { /* h: the calipers' edge; others: brute force */
            double d[2], area;
            if (i == h) {
                pw__atlas_min_rect_dir(hull, h, d);
            } else {
                double dx = hull[2 * ((i + 1) % h)] - hull[2 * i], dy = hull[2 * ((i + 1) % h) + 1] - hull[2 * i + 1];
                d[0] = dx / sqrt(dx * dx + dy * dy), d[1] = dy / sqrt(dx * dx + dy * dy);
            }
            for (k = 0; k < h; k++) {
                double x = d[0] * hull[2 * k] + d[1] * hull[2 * k + 1], y = -d[1] * hull[2 * k] + d[0] * hull[2 * k + 1];
                if (k == 0 || x < lo[0]) lo[0] = x;
                if (k == 0 || x > hi[0]) hi[0] = x;
                if (k == 0 || y < lo[1]) lo[1] = y;
                if (k == 0 || y > hi[1]) hi[1] = y;
            }
            area = (hi[0] - lo[0]) * (hi[1] - lo[1]);
            if (i == h) got = area;
            else if (area < best) best = area;
        }
        if (got > best * (1 + 1e-9)) worse++;
    }
    CHECKF(worse == 0, "%d hulls where the calipers missed the minimal rectangle", worse);
}

static const pwt_case cases[] = {
    {"atlas_min_rect", t_min_rect},
    {"atlas_icosphere", t_icosphere},
    {"atlas_torus", t_torus},
    {"atlas_box", t_box},
    {"atlas_disc", t_disc},
    {"atlas_options", t_options},
    {"atlas_small_meshes", t_small_meshes},
    {"atlas_values", t_values},
    {"atlas_deterministic", t_deterministic},
    {"atlas_obj", t_obj},
    {"atlas_bad_inputs", t_bad_inputs},
    {"atlas_alloc_failures", t_alloc_failures},
    {"atlas_cancel", t_cancel},
    {"atlas_pipeline", t_pipeline},
    {"atlas_cow", t_cow},
    {"atlas_homer", t_homer},
    {"atlas_camel", t_camel},
    {"atlas_armadillo", t_armadillo},
    {"atlas_bunny", t_bunny},
    {"atlas_elephant", t_elephant},
};
PWT_MAIN(cases)
