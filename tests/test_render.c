/* Tests of the rasterizer (src/common/raster.h) and the renderer
 * (src/common/render.h). A few scenes are written to /tmp/pw_render_*.ppm
 * for a visual check. */
#define PW_THREADS
#include "../src/common/render.h"
#include "../src/common/rng.h"
#include "pwtest.h"

/* ------------------------------------------------------------ helpers */

#define CW 96
#define CH 80
static int cover[CW * CH];

static void count_px(void *user, int x, int y, float b0, float b1, float b2)
{
    (void)b0;
    (void)b1;
    (void)b2;
    if (x < 0 || y < 0 || x >= CW || y >= CH) {
        *(int *)user += 1; /* out-of-viewport pixel reported */
        return;
    }
    cover[y * CW + x]++;
}

static void count_span(void *user, int y, int xa, int xb)
{
    int x;
    if (y < 0 || y >= CH || xa < 0 || xb > CW || xa >= xb) {
        *(int *)user += 1;
        return;
    }
    for (x = xa; x < xb; x++) cover[y * CW + x]++;
}

static float frand(pw_rng *r, float lo, float hi) { return lo + (hi - lo) * pw_rng_float(r); }

static int write_ppm(const char *path, const pw_image *img)
{
    FILE *f = fopen(path, "wb");
    int i, k;
    if (!f) return 0;
    fprintf(f, "P6\n%d %d\n255\n", img->w, img->h);
    for (i = 0; i < img->w * img->h; i++)
        for (k = 0; k < 3; k++) {
            float v = img->px[i * img->c + (img->c >= 3 ? k : 0)];
            fputc((int)(pw_clampf(v, 0.0f, 1.0f) * 255.0f + 0.5f), f);
        }
    return fclose(f) == 0;
}

/* A mesh under construction. */
typedef struct mesh {
    float *pos, *uv, *nrm;
    int *tri;
    int nv, nt;
} mesh;

static void mesh_free(mesh *m)
{
    free(m->pos);
    free(m->uv);
    free(m->nrm);
    free(m->tri);
    memset(m, 0, sizeof *m);
}

/* Grid of (n+1) x (n+1) vertices over p(s, t), s, t in [0, 1], two
 * triangles per cell, corner uvs = (s, t) * uvscale. */
static void mesh_grid(mesh *m, int n, void (*p)(float s, float t, float *out), float uvscale)
{
    int i, j, k, c = 0;
    m->nv = (n + 1) * (n + 1);
    m->nt = 2 * n * n;
    m->pos = (float *)malloc(sizeof(float) * 3 * m->nv);
    m->uv = (float *)malloc(sizeof(float) * 6 * m->nt);
    m->tri = (int *)malloc(sizeof(int) * 3 * m->nt);
    m->nrm = NULL;
    for (j = 0; j <= n; j++)
        for (i = 0; i <= n; i++) p((float)i / n, (float)j / n, m->pos + 3 * (j * (n + 1) + i));
    for (j = 0; j < n; j++)
        for (i = 0; i < n; i++) {
            int v00 = j * (n + 1) + i, v10 = v00 + 1, v01 = v00 + n + 1, v11 = v01 + 1;
            int quad[6] = {v00, v10, v11, v00, v11, v01};
            int ij[6][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 0}, {1, 1}, {0, 1}};
            for (k = 0; k < 6; k++) {
                m->tri[c * 3 + k] = quad[k];
                m->uv[c * 6 + 2 * k] = uvscale * (float)(i + ij[k][0]) / n;
                m->uv[c * 6 + 2 * k + 1] = uvscale * (float)(j + ij[k][1]) / n;
            }
            c += 2;
        }
}

static void p_quad(float s, float t, float *o) /* [-1,1]^2 at z = 0, facing +z */
{
    o[0] = 2 * s - 1;
    o[1] = 2 * t - 1;
    o[2] = 0;
}

static void p_torus(float s, float t, float *o)
{
    float a = 6.283185307f * s, b = 6.283185307f * t, R = 1.0f, r = 0.4f;
    o[0] = (R + r * cosf(b)) * cosf(a);
    o[1] = r * sinf(b);
    o[2] = (R + r * cosf(b)) * sinf(a);
}

/* Camera looking at the z = 0 plane from +z so that [-1,1]^2 fills the view. */
static pw_camera cam_front(void)
{
    pw_camera c;
    memset(&c, 0, sizeof c);
    c.fovy_deg = 45.0f;
    c.eye[2] = (float)(1.0 / pw__tan_deg(22.5));
    c.up[1] = 1.0f;
    c.znear = 0.1f;
    c.zfar = 10.0f;
    return c;
}

static pw_draw draw_of(const mesh *m)
{
    pw_draw d;
    memset(&d, 0, sizeof d);
    d.positions = m->pos;
    d.nv = m->nv;
    d.tris = m->tri;
    d.ntris = m->nt;
    d.uvs = m->uv;
    return d;
}

static const float *fb_px(const pw_image *img, int x, int y) { return img->px + ((size_t)y * img->w + x) * img->c; }

/* ------------------------------------------------------------- raster */

/* Random triangulation of the rectangle [x0,x1] x [y0,y1]: jittered grid,
 * random diagonals, random windings; every pixel centre inside the
 * rectangle must be covered exactly once, those outside never. */
static void t_raster_triangulation(void)
{
    pw_rng r = pw_rng_seed(1, 1);
    int trial, bad = 0, stray = 0;
    for (trial = 0; trial < 60; trial++) {
        int n = 2 + (int)pw_rng_below(&r, 9), m = 2 + (int)pw_rng_below(&r, 7), i, j, x, y;
        float X0 = frand(&r, -20, 20), Y0 = frand(&r, -20, 20), X1 = frand(&r, 50, 120),
              Y1 = frand(&r, 40, 100), gx[12][12], gy[12][12];
        if (trial % 3 == 0) { /* vertices exactly on pixel centres and edges through them */
            X0 = 3.5f;
            Y0 = 2.5f;
            X1 = 3.5f + 8 * n;
            Y1 = 2.5f + 8 * m;
        }
        memset(cover, 0, sizeof cover);
        for (j = 0; j <= m; j++)
            for (i = 0; i <= n; i++) {
                gx[j][i] = X0 + (X1 - X0) * i / n;
                gy[j][i] = Y0 + (Y1 - Y0) * j / m;
                if (i > 0 && i < n && trial % 3 != 0) gx[j][i] += frand(&r, -0.3f, 0.3f) * (X1 - X0) / n;
                if (j > 0 && j < m && trial % 3 != 0) gy[j][i] += frand(&r, -0.3f, 0.3f) * (Y1 - Y0) / m;
                if (trial % 3 == 0) {
                    gx[j][i] = (float)(int)gx[j][i] + 0.5f;
                    gy[j][i] = (float)(int)gy[j][i] + 0.5f;
                }
            }
        for (j = 0; j < m; j++)
            for (i = 0; i < n; i++) {
                float *a = &gx[j][i], *b = &gx[j][i + 1], *c = &gx[j + 1][i + 1], *d = &gx[j + 1][i];
                float ay = gy[j][i], by = gy[j][i + 1], cy = gy[j + 1][i + 1], dy = gy[j + 1][i];
                int diag = (int)pw_rng_below(&r, 2), w1 = (int)pw_rng_below(&r, 2),
                    w2 = (int)pw_rng_below(&r, 2);
                if (diag) {
                    if (w1) {
                        const float tri[6] = {*a, ay, *b, by, *c, cy};
                        pw_raster_tri(tri, CW, CH, count_px, &stray);
                    } else {
                        const float tri[6] = {*a, ay, *c, cy, *b, by};
                        pw_raster_tri(tri, CW, CH, count_px, &stray);
                    }
                    if (w2) {
                        const float tri[6] = {*a, ay, *c, cy, *d, dy};
                        pw_raster_tri(tri, CW, CH, count_px, &stray);
                    } else {
                        const float tri[6] = {*c, cy, *a, ay, *d, dy};
                        pw_raster_tri(tri, CW, CH, count_px, &stray);
                    }
                } else {
                    if (w1) {
                        const float tri[6] = {*a, ay, *b, by, *d, dy};
                        pw_raster_tri(tri, CW, CH, count_px, &stray);
                    } else {
                        const float tri[6] = {*b, by, *a, ay, *d, dy};
                        pw_raster_tri(tri, CW, CH, count_px, &stray);
                    }
                    if (w2) {
                        const float tri[6] = {*b, by, *c, cy, *d, dy};
                        pw_raster_tri(tri, CW, CH, count_px, &stray);
                    } else {
                        const float tri[6] = {*d, dy, *c, cy, *b, by};
                        pw_raster_tri(tri, CW, CH, count_px, &stray);
                    }
                }
            }
        for (y = 0; y < CH; y++)
            for (x = 0; x < CW; x++) {
                float cx = x + 0.5f, cyy = y + 0.5f;
                int in = cx > X0 && cx < X1 && cyy > Y0 && cyy < Y1;
                int on = cx == X0 || cx == X1 || cyy == Y0 || cyy == Y1;
                if (on) continue; /* the outer boundary belongs to whoever is across */
                if (cover[y * CW + x] != in) bad++;
            }
    }
    CHECK_EQ_INT(bad, 0);
    CHECK_EQ_INT(stray, 0);
}

/* A fan of triangles around a vertex sitting on a pixel centre, and a
 * square split along both diagonals: exactly one owner per pixel. */
static void t_raster_fan(void)
{
    int k, n = 7, x, y, bad = 0, stray = 0;
    float cx = 40.5f, cy = 30.5f;
    memset(cover, 0, sizeof cover);
    for (k = 0; k < n; k++) {
        /* polygon vertices on pixel centres too, so many centres lie on edges */
        float a0 = 6.283185307f * k / n, a1 = 6.283185307f * (k + 1) / n;
        float x0 = (float)(int)(cx + 20 * cosf(a0)) + 0.5f, y0 = (float)(int)(cy + 20 * sinf(a0)) + 0.5f;
        float x1 = (float)(int)(cx + 20 * cosf(a1)) + 0.5f, y1 = (float)(int)(cy + 20 * sinf(a1)) + 0.5f;
        {
            const float tri[6] = {cx, cy, x0, y0, x1, y1};
            pw_raster_tri(tri, CW, CH, count_px, &stray);
        }
    }
    CHECK_EQ_INT(cover[30 * CW + 40], 1);
    for (y = 0; y < CH; y++)
        for (x = 0; x < CW; x++)
            if (cover[y * CW + x] > 1) bad++;
    CHECK_EQ_INT(bad, 0);
    /* square [10.5, 30.5]^2 in four triangles meeting at its centre */
    memset(cover, 0, sizeof cover);
    {
        const float tri[6] = {10.5f, 10.5f, 30.5f, 10.5f, 20.5f, 20.5f};
        pw_raster_tri(tri, CW, CH, count_px, &stray);
    }
    {
        const float tri[6] = {30.5f, 10.5f, 30.5f, 30.5f, 20.5f, 20.5f};
        pw_raster_tri(tri, CW, CH, count_px, &stray);
    }
    {
        const float tri[6] = {30.5f, 30.5f, 10.5f, 30.5f, 20.5f, 20.5f};
        pw_raster_tri(tri, CW, CH, count_px, &stray);
    }
    {
        const float tri[6] = {20.5f, 20.5f, 10.5f, 30.5f, 10.5f, 10.5f};
        pw_raster_tri(tri, CW, CH, count_px, &stray);
    }
    for (y = 11; y < 30; y++)
        for (x = 11; x < 30; x++)
            if (cover[y * CW + x] != 1) bad++;
    CHECK_EQ_INT(bad, 0);
    CHECK_EQ_INT(stray, 0);
}

typedef struct bary_check {
    float v[6];
    double max_sum_err, max_pos_err, min_b;
    int n, check_pos;
} bary_check;

static void bary_px(void *user, int x, int y, float b0, float b1, float b2)
{
    bary_check *c = (bary_check *)user;
    double px = b0 * c->v[0] + b1 * c->v[2] + b2 * c->v[4] - (x + 0.5);
    double py = b0 * c->v[1] + b1 * c->v[3] + b2 * c->v[5] - (y + 0.5);
    double s = fabs((double)b0 + b1 + b2 - 1.0), e = sqrt(px * px + py * py);
    if (s > c->max_sum_err) c->max_sum_err = s;
    if (c->check_pos && e > c->max_pos_err) c->max_pos_err = e;
    if (b0 < c->min_b) c->min_b = b0;
    if (b1 < c->min_b) c->min_b = b1;
    if (b2 < c->min_b) c->min_b = b2;
    c->n++;
}

static void t_raster_barycentrics(void)
{
    pw_rng r = pw_rng_seed(2, 1);
    bary_check c;
    int trial, k;
    memset(&c, 0, sizeof c);
    c.check_pos = 1;
    for (trial = 0; trial < 300; trial++) {
        for (k = 0; k < 6; k++) c.v[k] = frand(&r, -10, 100);
        pw_raster_tri(c.v, CW, CH, bary_px, &c);
    }
    /* far vertices: the clipped path uses the triangle's own planes (the
     * centre cannot be checked in float at this scale) */
    c.check_pos = 0;
    for (trial = 0; trial < 50; trial++) {
        for (k = 0; k < 6; k++) c.v[k] = frand(&r, -3e6f, 3e6f);
        pw_raster_tri(c.v, CW, CH, bary_px, &c);
    }
    REQUIRE(c.n > 10000);
    CHECKF(c.max_sum_err < 1e-5, "barycentric sum off by %g", c.max_sum_err);
    CHECKF(c.max_pos_err < 1e-3, "centre off by %g", c.max_pos_err);
    CHECKF(c.min_b > -1e-3, "negative barycentric %g", c.min_b);
    pwt_info("%d pixels, max |sum-1| %.2g, max centre error %.2g px", c.n, c.max_sum_err,
             c.max_pos_err);
}

static void t_raster_degenerate(void)
{
    pw_rng r = pw_rng_seed(3, 1);
    int trial, stray = 0, x;
    float nan = (float)strtod("nan", NULL), inf = (float)strtod("inf", NULL);
    memset(cover, 0, sizeof cover);
    for (trial = 0; trial < 500; trial++) {
        float px = (float)(int)frand(&r, 0, 90) + (float)pw_rng_below(&r, 64) / 64.0f;
        float py = (float)(int)frand(&r, 0, 70) + (float)pw_rng_below(&r, 64) / 64.0f;
        float dx = (float)((int)pw_rng_below(&r, 21) - 10), dy = (float)((int)pw_rng_below(&r, 21) - 10);
        float t1 = (float)pw_rng_below(&r, 5), t2 = -(float)pw_rng_below(&r, 5);
        {
            const float tri[6] = {px, py, px + t1 * dx, py + t1 * dy, px + t2 * dx, py + t2 * dy};
            pw_raster_tri(tri, CW, CH, count_px, &stray);
        }
        {
            const float tri[6] = {px, py, px, py, px + dx, py + dy};
            pw_raster_tri(tri, CW, CH, count_px, &stray);
        }
        {
            const float tri[6] = {px, py, px, py, px, py};
            pw_raster_tri(tri, CW, CH, count_px, &stray);
        }
    }
    {
        const float tri[6] = {nan, 0, 50, 50, 0, 50};
        pw_raster_tri(tri, CW, CH, count_px, &stray);
    }
    {
        const float tri[6] = {inf, 0, 50, 50, 0, 50};
        pw_raster_tri(tri, CW, CH, count_px, &stray);
    }
    {
        const float tri[6] = {0, 0, 50, 50, 0, 50};
        pw_raster_tri(tri, 0, CH, count_px, &stray);
    } /* empty viewport */
    {
        const float tri[6] = {0, 0, 50, 50, 0, 50};
        pw_raster_tri(tri, CW, -3, count_px, &stray);
    }
    for (x = 0; x < CW * CH; x++) stray += cover[x];
    CHECK_EQ_INT(stray, 0);
}

/* Clipping: triangles larger than the viewport, far beyond it (clipped to
 * the guard square), and the same coverage as in a larger viewport. */
static void t_raster_clipping(void)
{
    pw_rng r = pw_rng_seed(4, 1);
    static int big[300 * 300];
    int trial, x, y, bad = 0, stray = 0;
    for (trial = 0; trial < 200; trial++) {
        float v[6];
        int k;
        for (k = 0; k < 6; k++) v[k] = frand(&r, -100, 200);
        memset(cover, 0, sizeof cover);
        pw_raster_tri(v, CW, CH, count_px, &stray);
        /* reference: the same triangle shifted into a larger viewport, read
         * straight from its edge functions */
        memset(big, 0, sizeof big);
        {
            pw_raster_grid g;
            pw_raster_edges s;
            double dv[6];
            for (k = 0; k < 6; k++) dv[k] = (double)v[k] + 100.0;
            pw_raster_grid_init(&g, 300, 300);
            if (pw_raster_setup(&s, &g, dv))
                for (y = s.y0; y < s.y1; y++) {
                    int xa, xb;
                    if (pw_raster_span(&s, y, &xa, &xb))
                        for (x = xa; x < xb; x++) big[y * 300 + x] = 1;
                }
        }
        for (y = 0; y < CH; y++)
            for (x = 0; x < CW; x++)
                if (cover[y * CW + x] != big[(y + 100) * 300 + x + 100]) bad++;
    }
    /* two far triangles sharing an edge through the viewport cover it once */
    memset(cover, 0, sizeof cover);
    {
        const float tri[6] = {-1e7f, -3e6f, 2e7f, 1e6f, 1e5f, 3e7f};
        pw_raster_tri(tri, CW, CH, count_px, &stray);
    }
    {
        const float tri[6] = {-1e7f, -3e6f, 2e7f, 1e6f, -2e5f, -4e7f};
        pw_raster_tri(tri, CW, CH, count_px, &stray);
    }
    for (x = 0; x < CW * CH; x++)
        if (cover[x] != 1) bad++;
    /* one triangle enclosing the viewport with vertices at 1e30 */
    memset(cover, 0, sizeof cover);
    {
        const float tri[6] = {-1e30f, -1e30f, 1e30f, -1e30f, 0, 1e30f};
        pw_raster_tri(tri, CW, CH, count_px, &stray);
    }
    for (x = 0; x < CW * CH; x++)
        if (cover[x] != 1) bad++;
    CHECK_EQ_INT(bad, 0);
    CHECK_EQ_INT(stray, 0);
}

/* Independent reference: is the centre of pixel (x, y) inside the triangle
 * v snapped to 1/2^bits, by the top-left rule? */
static int ref_covered(const double *v, int bits, int x, int y)
{
    int64_t X[3], Y[3], one = (int64_t)1 << bits, px = x * one + one / 2, py = y * one + one / 2, area;
    int k, sgn;
    for (k = 0; k < 3; k++) {
        X[k] = (int64_t)floor(v[2 * k] * one + 0.5);
        Y[k] = (int64_t)floor(v[2 * k + 1] * one + 0.5);
    }
    area = (X[1] - X[0]) * (Y[2] - Y[0]) - (Y[1] - Y[0]) * (X[2] - X[0]);
    if (area == 0) return 0;
    sgn = area > 0 ? 1 : -1;
    for (k = 0; k < 3; k++) {
        int a = (k + 1) % 3, b = (k + 2) % 3;
        int64_t E = sgn * ((X[b] - X[a]) * (py - Y[a]) - (Y[b] - Y[a]) * (px - X[a]));
        int64_t gx = sgn * (Y[a] - Y[b]), gy = sgn * (X[b] - X[a]);
        if (E < 0 || (E == 0 && !(gx > 0 || (gx == 0 && gy > 0)))) return 0;
    }
    return 1;
}

/* Spans are exact: for ordinary, thin, huge and axis-aligned triangles,
 * one row at a time (pw_raster_span), walking down the rows
 * (pw_raster_next), without the walker (pw__raster_row, the renderer's
 * path for narrow triangles), per pixel (pw_raster_tri) and as runs
 * (pw_raster_tri_spans) all match the reference at every pixel. */
static void t_raster_spans(void)
{
    static int ref[CW * CH];
    pw_rng r = pw_rng_seed(5, 1);
    pw_raster_grid g;
    int trial, bad = 0, stray = 0, k, x, y, npx = 0;
    pw_raster_grid_init(&g, CW, CH);
    for (trial = 0; trial < 1500; trial++) {
        float v[6];
        double dv[6];
        pw_raster_edges s;
        float sc = trial % 10 == 0 ? 2.0e3f : (trial % 10 == 1 ? 4.0f : 150.0f);
        for (k = 0; k < 6; k++) v[k] = frand(&r, -sc * 0.3f, sc);
        if (trial % 7 == 0) /* a sliver */
            for (k = 0; k < 2; k++) v[4 + k] = 0.5f * (v[k] + v[2 + k]) + frand(&r, -0.01f, 0.01f);
        if (trial % 5 == 1) { /* horizontal and vertical edges through pixel centres */
            for (k = 0; k < 6; k++) v[k] = (float)(int)v[k] + 0.5f * (float)(trial % 2);
            v[3] = v[1];
            v[4] = v[2];
        }
        for (k = 0; k < 6; k++) dv[k] = v[k];
        for (y = 0; y < CH; y++)
            for (x = 0; x < CW; x++) npx += ref[y * CW + x] = ref_covered(dv, g.bits, x, y);
        memset(cover, 0, sizeof cover);
        if (pw_raster_setup(&s, &g, dv))
            for (y = s.y0; y < s.y1; y++) {
                int xa = 0, xb = 0, has = pw_raster_span(&s, y, &xa, &xb), wa = 0, wb = 0;
                int walk = pw_raster_next(&s, &wa, &wb);
                if (walk != has || (has && (wa != xa || wb != xb))) bad++;
                for (x = xa; has && x < xb; x++) cover[y * CW + x]++;
            }
        if (memcmp(ref, cover, sizeof ref)) bad++;
        memset(cover, 0, sizeof cover); /* the runs found without the walker (narrow triangles) */
        if (pw__raster_setup_edges(&s, &g, dv))
            for (y = s.y0; y < s.y1; y++) {
                int xa = 0, xb = 0;
                if (pw__raster_row(&s, y, &xa, &xb))
                    for (x = xa; x < xb; x++) cover[y * CW + x]++;
            }
        if (memcmp(ref, cover, sizeof ref)) bad++;
        memset(cover, 0, sizeof cover);
        pw_raster_tri(v, CW, CH, count_px, &stray);
        if (memcmp(ref, cover, sizeof ref)) bad++;
        memset(cover, 0, sizeof cover);
        pw_raster_tri_spans(v, CW, CH, count_span, &stray);
        if (memcmp(ref, cover, sizeof ref)) bad++;
    }
    pwt_info("%d covered pixels checked", npx);
    CHECK_EQ_INT(bad, 0);
    CHECK_EQ_INT(stray, 0);
}

/* ------------------------------------------------------------- render */

/* Renders d with cam into a fresh w x h x ss framebuffer; resolves to RGBA. */
static int render1(const pw_draw *d, int nd, const pw_camera *cam, int w, int h, int ss,
                   const float *bg, pw_image *out)
{
    pw_fb fb;
    pw_err e;
    int i, r;
    pw_err_clear(&e);
    if (pw_fb_create(NULL, &fb, w, h, ss, bg, &e)) return 0;
    for (i = 0; i < nd; i++)
        if ((r = pw_render_draw(&fb, cam, d + i, &e)) != PW_OK) {
            pwt_info("draw %d failed: %s", i, e.msg);
            pw_fb_free(&fb);
            return 0;
        }
    r = pw_fb_resolve(&fb, out, 4, &e);
    pw_fb_free(&fb);
    return r == PW_OK;
}

/* A texture image whose texel (i, j) (row j from the top) has a distinct colour. */
static void make_coded(pw_image *img, int w, int h)
{
    int i, j;
    pw_image_alloc(NULL, img, w, h, 3, NULL);
    for (j = 0; j < h; j++)
        for (i = 0; i < w; i++) {
            float *p = img->px + (j * w + i) * 3;
            p[0] = (float)i / w;
            p[1] = (float)j / h;
            p[2] = (float)((i + j) % 2);
        }
}

/* Reference bilinear interpolation of a 3-channel image at texel
 * coordinates (tx, ty) (texel centres at integers, rows from the top),
 * wrapping around. */
static void bilinear_ref(const pw_image *img, float tx, float ty, float *out)
{
    int x0 = (int)floorf(tx), y0 = (int)floorf(ty), k, i, j;
    float fx = tx - (float)x0, fy = ty - (float)y0;
    for (k = 0; k < 3; k++) out[k] = 0.0f;
    for (j = 0; j < 2; j++)
        for (i = 0; i < 2; i++) {
            int x = ((x0 + i) % img->w + img->w) % img->w, y = ((y0 + j) % img->h + img->h) % img->h;
            float wgt = (i ? fx : 1 - fx) * (j ? fy : 1 - fy);
            for (k = 0; k < 3; k++) out[k] += wgt * img->px[(y * img->w + x) * 3 + k];
        }
}

/* A textured quad facing the camera reproduces its texture, the image's top
 * row at the top (v = 0 is the bottom row of the texture): nearest, then
 * trilinear from a 16-bit source (filtered in 16 bits) and from an 8-bit one
 * (filtered on 8-bit texels: within half a unit of 8 bits). */
static void t_render_textured_quad(void)
{
    mesh m;
    pw_image img, out;
    pw_texture tex;
    pw_camera cam = cam_front();
    pw_draw d;
    int x, y, k, bad = 0, f;
    float bg[4] = {0, 0, 0, 1};
    make_coded(&img, 8, 8);
    mesh_grid(&m, 3, p_quad, 1.0f);
    d = draw_of(&m);
    d.tex = &tex;
    for (f = 0; f < 3; f++) {
        const float tol = f == 2 ? 0.5f / 255.0f + 2e-5f : 2e-5f;
        img.bits = f == 1 ? 16 : 8;
        REQUIRE(pw_texture_create(NULL, &tex, &img, 0, NULL) == PW_OK);
        d.filter = f ? PW_FILTER_TRILINEAR : PW_FILTER_NEAREST;
        REQUIRE(render1(&d, 1, &cam, 64, 64, 1, bg, &out));
        for (y = 0; y < 64; y++)
            for (x = 0; x < 64; x++) {
                const float *p = fb_px(&out, x, y);
                float t[3];
                if (f == 0) memcpy(t, img.px + ((y / 8) * 8 + x / 8) * 3, sizeof t);
                else bilinear_ref(&img, (x + 0.5f) / 8 - 0.5f, (y + 0.5f) / 8 - 0.5f, t);
                for (k = 0; k < 3; k++)
                    if (fabsf(p[k] - t[k]) > tol) bad++;
            }
        /* bottom-left pixel shows the bottom-left texel (v = 0, u = 0) */
        if (f == 0) {
            CHECK_NEAR(fb_px(&out, 0, 63)[1], 7.0f / 8, 2e-5);
            CHECK_NEAR(fb_px(&out, 63, 0)[0], 7.0f / 8, 2e-5);
        }
        pw_image_free(NULL, &out);
        pw_texture_free(NULL, &tex);
    }
    CHECK_EQ_INT(bad, 0);
    pw_image_free(NULL, &img);
    mesh_free(&m);
}

static void make_checker(pw_image *img, int n, int cell)
{
    int x, y;
    pw_image_alloc(NULL, img, n, n, 3, NULL);
    for (y = 0; y < n; y++)
        for (x = 0; x < n; x++) {
            float *p = img->px + (y * n + x) * 3;
            int c = ((x / cell) + (y / cell)) & 1;
            p[0] = c ? 0.95f : 0.2f;
            p[1] = c ? 0.85f : 0.3f;
            p[2] = c ? 0.6f : 0.6f;
            if (y < n / 8) p[0] = 1.0f, p[1] = 0.2f, p[2] = 0.2f; /* a red band marks v ~ 1 */
        }
}

/* Ray through pixel centre (px, py) of a w x h image against the plane
 * y = 0; returns the hit (x, z) or 0. */
static int floor_hit(const pw_camera *cam, int w, int h, double px, double py, double *hx, double *hz)
{
    pw__view v;
    double dir[3], t;
    int k;
    if (pw__view_init(&v, cam, w, h, NULL)) return 0;
    for (k = 0; k < 3; k++)
        dir[k] = v.f[k] + (px - v.cx) / v.fx * v.r[k] - (py - v.cy) / v.fy * v.u[k];
    if (!(dir[1] < -1e-9)) return 0;
    t = -v.eye[1] / dir[1];
    *hx = v.eye[0] + t * dir[0];
    *hz = v.eye[2] + t * dir[2];
    return 1;
}

static int checker_at(double u, double v) { return ((int)floor(2 * u) + (int)floor(2 * v)) & 1; }

/* Distance of (u, v) to the nearest checker line (lines every 0.5). */
static double checker_margin(double u, double v)
{
    double a = 2 * u - floor(2 * u), b = 2 * v - floor(2 * v);
    a = a < 0.5 ? a : 1 - a;
    b = b < 0.5 ? b : 1 - b;
    return 0.5 * (a < b ? a : b);
}

/* The checker parity that screen-space affine interpolation of the corner
 * uvs would give at pixel point (px, py), or -1 outside both triangles. */
static int affine_checker(const pw_camera *cam, int W, int H, const float *pos, const int *tri,
                          const float *uv, double px, double py)
{
    double P[4][2];
    int k, t;
    for (k = 0; k < 4; k++) {
        float o[3];
        pw_camera_project(cam, W, H, pos + 3 * k, o);
        P[k][0] = o[0];
        P[k][1] = o[1];
    }
    for (t = 0; t < 2; t++) {
        const double *A = P[tri[3 * t]], *B = P[tri[3 * t + 1]], *C = P[tri[3 * t + 2]];
        double den = (B[0] - A[0]) * (C[1] - A[1]) - (B[1] - A[1]) * (C[0] - A[0]);
        double b1 = ((px - A[0]) * (C[1] - A[1]) - (py - A[1]) * (C[0] - A[0])) / den;
        double b2 = ((B[0] - A[0]) * (py - A[1]) - (B[1] - A[1]) * (px - A[0])) / den;
        double b0 = 1 - b1 - b2;
        if (b0 < 0 || b1 < 0 || b2 < 0) continue;
        return checker_at(b0 * uv[6 * t] + b1 * uv[6 * t + 2] + b2 * uv[6 * t + 4],
                          b0 * uv[6 * t + 1] + b1 * uv[6 * t + 3] + b2 * uv[6 * t + 5]);
    }
    return -1;
}

/* The floor of t_render_perspective with a finer checker, trilinear-
 * filtered, for the eye. */
static void floor_picture(pw_draw *d, const pw_camera *cam, int w, int h, const float *bg)
{
    pw_image img, out;
    pw_texture tex;
    make_checker(&img, 64, 8);
    if (pw_texture_create(NULL, &tex, &img, 0, NULL) == PW_OK) {
        d->tex = &tex;
        d->filter = PW_FILTER_TRILINEAR;
        if (render1(d, 1, cam, w, h, 2, bg, &out)) {
            write_ppm("/tmp/pw_render_floor_trilinear.ppm", &out);
            pw_image_free(NULL, &out);
        }
        pw_texture_free(NULL, &tex);
    }
    pw_image_free(NULL, &img);
}

/* A floor quad receding in depth, drawn as just two triangles: the checker
 * squares land where the analytic projection puts them. An affine (screen-
 * space) interpolation of the same uvs is checked to fail, so the test can
 * tell the two apart. */
static void t_render_perspective(void)
{
    float pos[12] = {-4, 0, -1, 4, 0, -1, 4, 0, -21, -4, 0, -21};
    float uv[12] = {-4, 1, 4, 1, 4, 21, -4, 1, 4, 21, -4, 21}; /* (x, -z) per corner */
    int tri[6] = {0, 1, 2, 0, 2, 3};
    float chk[12] = {1, 1, 1, 0, 0, 0, 0, 0, 0, 1, 1, 1}, bg[4] = {0.5f, 0.5f, 0.5f, 1};
    pw_image img, out;
    pw_texture tex;
    pw_draw d;
    pw_camera cam;
    int W = 160, H = 120, x, y, tested = 0, bad = 0, affine_bad = 0;
    img.w = img.h = 2;
    img.c = 3;
    img.bits = 8;
    img.px = chk; /* top row: white, black; bottom: black, white */
    REQUIRE(pw_texture_create(NULL, &tex, &img, 1, NULL) == PW_OK);
    memset(&d, 0, sizeof d);
    memset(&cam, 0, sizeof cam);
    d.positions = pos;
    d.nv = 4;
    d.tris = tri;
    d.ntris = 2;
    d.uvs = uv;
    d.tex = &tex;
    d.filter = PW_FILTER_NEAREST;
    cam.eye[1] = 1.0f;
    cam.target[2] = -6.0f;
    cam.up[1] = 1.0f;
    cam.fovy_deg = 60.0f;
    cam.znear = 0.1f;
    cam.zfar = 100.0f;
    REQUIRE(render1(&d, 1, &cam, W, H, 1, bg, &out));
    write_ppm("/tmp/pw_render_floor_nearest.ppm", &out);
    for (y = 0; y < H; y++)
        for (x = 0; x < W; x++) {
            double hx, hz, hx2, hz2, u, v, foot;
            int expect, got;
            if (!floor_hit(&cam, W, H, x + 0.5, y + 0.5, &hx, &hz)) continue;
            if (!floor_hit(&cam, W, H, x + 1.5, y + 1.5, &hx2, &hz2)) continue;
            if (hx < -3.9 || hx > 3.9 || hz > -1.1 || hz < -20.9) continue;
            u = hx;
            v = -hz;
            foot = fabs(hx2 - hx) + fabs(hz2 - hz);
            if (checker_margin(u, v) < foot) continue;
            tested++;
            /* texel (0,0) of the image (top-left) is white and sits at v in
             * [0.5, 1): so white <=> checker parity 1 */
            expect = checker_at(u, v);
            got = fb_px(&out, x, y)[0] > 0.5f;
            if (got != expect) bad++;
            if (affine_checker(&cam, W, H, pos, tri, uv, x + 0.5, y + 0.5) != expect) affine_bad++;
        }
    pwt_info("%d pixels tested, %d wrong (affine interpolation: %d wrong)", tested, bad, affine_bad);
    CHECK(tested > 2000);
    CHECK_EQ_INT(bad, 0);
    CHECK(affine_bad > tested / 10);
    pw_image_free(NULL, &out);
    pw_texture_free(NULL, &tex);
    floor_picture(&d, &cam, W * 2, H * 2, bg);
}

/* Quad [x0,x1] x [y0,y1] at depth z (facing +z), counter-clockwise. */
static void quad_at(float *pos, int *tri, float x0, float y0, float x1, float y1, float z)
{
    float p[12];
    int t[6] = {0, 1, 2, 0, 2, 3};
    p[0] = x0, p[1] = y0, p[3] = x1, p[4] = y0, p[6] = x1, p[7] = y1, p[9] = x0, p[10] = y1;
    p[2] = p[5] = p[8] = p[11] = z;
    memcpy(pos, p, sizeof p);
    memcpy(tri, t, sizeof t);
}

static pw_draw draw_quad(const float *pos, const int *tri, float r, float g, float b, float a)
{
    pw_draw d;
    memset(&d, 0, sizeof d);
    d.positions = pos;
    d.nv = 4;
    d.tris = tri;
    d.ntris = 2;
    d.color[0] = r;
    d.color[1] = g;
    d.color[2] = b;
    d.color[3] = a;
    return d;
}

/* The near quad hides the far one whatever the drawing order. */
static void t_render_depth(void)
{
    float near_p[12], far_p[12], bg[4] = {0, 0, 0, 1};
    int near_t[6], far_t[6], order;
    pw_camera cam = cam_front();
    quad_at(near_p, near_t, -0.8f, -0.8f, 0.3f, 0.3f, 0.3f);
    quad_at(far_p, far_t, -0.3f, -0.3f, 0.8f, 0.8f, -0.3f);
    for (order = 0; order < 2; order++) {
        pw_draw d[2];
        pw_image out;
        d[order] = draw_quad(near_p, near_t, 1, 0, 0, 1);
        d[1 - order] = draw_quad(far_p, far_t, 0, 0, 1, 1);
        REQUIRE(render1(d, 2, &cam, 64, 64, 1, bg, &out));
        /* screen (32, 32) is the world origin: both quads there, red wins */
        CHECK_NEAR(fb_px(&out, 32, 32)[0], 1.0, 1e-6);
        CHECK_NEAR(fb_px(&out, 32, 32)[2], 0.0, 1e-6);
        CHECK_NEAR(fb_px(&out, 36, 28)[0], 1.0, 1e-6); /* still inside the near quad */
        CHECK_NEAR(fb_px(&out, 50, 14)[2], 1.0, 1e-6); /* far quad only (top right) */
        CHECK_NEAR(fb_px(&out, 4, 60)[0], 1.0, 1e-6);  /* near quad only (bottom left) */
        CHECK_NEAR(fb_px(&out, 2, 2)[0] + fb_px(&out, 2, 2)[2], 0.0, 1e-6);
        pw_image_free(NULL, &out);
    }
}

/* Two blended passes over an opaque one equal the analytic "over" (to the
 * 16-bit precision of textures: a 16-bit source is filtered in 16 bits). */
static void t_render_blend_over(void)
{
    float pos[12], bg[4] = {0, 0, 0, 1}, uv[12] = {0, 0, 1, 0, 1, 1, 0, 0, 1, 1, 0, 1};
    float px[4] = {0.0f, 1.0f, 0.0f, 0.25f}; /* straight RGBA green, alpha 1/4 */
    int tri[6], x, bad = 0;
    pw_camera cam = cam_front();
    pw_image img, out;
    pw_texture tex;
    pw_draw d[3];
    img.w = img.h = 1;
    img.c = 4;
    img.bits = 16;
    img.px = px;
    REQUIRE(pw_texture_create(NULL, &tex, &img, 0, NULL) == PW_OK);
    quad_at(pos, tri, -1.5f, -1.5f, 1.5f, 1.5f, 0.0f);
    d[0] = draw_quad(pos, tri, 1, 0, 0, 1);
    d[1] = draw_quad(pos, tri, 0, 0, 1, 0.5f);
    d[2] = draw_quad(pos, tri, 1, 1, 1, 1);
    d[1].blend = d[2].blend = PW_BLEND_OVER;
    d[1].depth_test = d[2].depth_test = PW_DEPTH_LEQUAL;
    d[1].no_depth_write = d[2].no_depth_write = 1;
    d[2].tex = &tex;
    d[2].uvs = uv;
    REQUIRE(render1(d, 3, &cam, 32, 32, 2, bg, &out));
    for (x = 0; x < 32 * 32; x++) {
        const float *p = out.px + 4 * x;
        /* red, then blue at 1/2: (.5, 0, .5); then green at 1/4 */
        if (fabsf(p[0] - 0.375f) > 2e-5f || fabsf(p[1] - 0.25f) > 2e-5f ||
            fabsf(p[2] - 0.375f) > 2e-5f || fabsf(p[3] - 1.0f) > 2e-5f)
            bad++;
    }
    CHECK_EQ_INT(bad, 0);
    pw_image_free(NULL, &out);
    /* over a transparent background the alpha accumulates too */
    bg[3] = 0.0f;
    REQUIRE(render1(d + 1, 2, &cam, 8, 8, 1, bg, &out));
    CHECK_NEAR(fb_px(&out, 4, 4)[3], 1 - 0.5 * 0.75, 2e-5);
    pw_image_free(NULL, &out);
    pw_texture_free(NULL, &tex);
}

/* A second pass over the same mesh with LEQUAL (no depth write) touches
 * exactly the samples the first pass left visible, also when the triangles
 * list their corners in another order. */
static void t_render_lequal(void)
{
    mesh m;
    pw_fb fb;
    pw_camera cam;
    pw_draw d;
    float vd[3] = {0.3f, -0.6f, -1.0f}, bg[4] = {0, 0, 0, 1};
    int *rot, i, pass, bad = 0, drawn = 0;
    size_t n, s;
    mesh_grid(&m, 60, p_torus, 4.0f);
    cam = pw_camera_frame(m.pos, m.nv, vd, NULL, 40.0f, 1.0f);
    REQUIRE(pw_fb_create(NULL, &fb, 128, 128, 2, bg, NULL) == PW_OK);
    d = draw_of(&m);
    d.uvs = NULL;
    d.color[0] = d.color[3] = 1.0f;
    REQUIRE(pw_render_draw(&fb, &cam, &d, NULL) == PW_OK);
    rot = (int *)malloc(sizeof(int) * 3 * m.nt);
    for (i = 0; i < m.nt; i++) {
        rot[3 * i] = m.tri[3 * i + 1];
        rot[3 * i + 1] = m.tri[3 * i + 2];
        rot[3 * i + 2] = m.tri[3 * i];
    }
    n = (size_t)fb.sw * fb.sh;
    for (pass = 0; pass < 2; pass++) {
        d.blend = PW_BLEND_OVER;
        d.depth_test = PW_DEPTH_LEQUAL;
        d.no_depth_write = 1;
        d.color[0] = 0.0f;
        d.color[1] = pass == 0 ? 1.0f : 0.0f;
        d.color[2] = pass == 1 ? 1.0f : 0.0f;
        d.tris = pass == 0 ? m.tri : rot;
        REQUIRE(pw_render_draw(&fb, &cam, &d, NULL) == PW_OK);
        for (s = 0; s < n; s++) {
            const float *c = fb.color + 4 * s;
            int touched = fb.depth[s] > 0.0f;
            drawn += touched && pass == 0;
            if (touched && c[pass + 1] != 1.0f) bad++;
            if (!touched && (c[0] != 0.0f || c[1] != 0.0f || c[2] != 0.0f)) bad++;
        }
    }
    pwt_info("%d samples drawn, %d mismatches", drawn, bad);
    CHECK(drawn > (int)n / 5);
    CHECK_EQ_INT(bad, 0);
    free(rot);
    pw_fb_free(&fb);
    mesh_free(&m);
}

/* A minified one-texel checkerboard: trilinear filtering picks a coarse mip
 * level and shows grey; with the chain capped at one level it aliases. */
static void t_render_mip_levels(void)
{
    mesh m;
    pw_image img, out;
    pw_texture tex;
    pw_camera cam = cam_front();
    pw_draw d;
    int i, cap;
    float bg[4] = {0, 0, 0, 1};
    pw_image_alloc(NULL, &img, 64, 64, 1, NULL);
    for (i = 0; i < 64 * 64; i++) img.px[i] = (float)((i % 64 + i / 64) % 2);
    mesh_grid(&m, 1, p_quad, 1.0f);
    d = draw_of(&m);
    for (cap = 0; cap < 2; cap++) {
        float dev = 0.0f;
        REQUIRE(pw_texture_create(NULL, &tex, &img, cap ? 1 : 0, NULL) == PW_OK);
        CHECK_EQ_INT(tex.nlevels, cap ? 1 : 7);
        d.tex = &tex;
        REQUIRE(render1(&d, 1, &cam, 10, 10, 1, bg, &out));
        for (i = 0; i < 100; i++)
            if (fabsf(out.px[4 * i] - 0.5f) > dev) dev = fabsf(out.px[4 * i] - 0.5f);
        pwt_info("max |pixel - grey| with %s: %.3f", cap ? "1 level" : "full chain", dev);
        if (cap) CHECK(dev > 0.2f);
        else CHECK(dev < 0.02f);
        pw_image_free(NULL, &out);
        pw_texture_free(NULL, &tex);
    }
    pw_image_free(NULL, &img);
    mesh_free(&m);
}

/* Mip chain of a non-power-of-two image: sizes halve rounding down and the
 * box filter keeps the mean. v = 0 is the bottom row. */
static void t_render_texture_npot(void)
{
    pw_image img;
    pw_texture tex;
    pw_rng r = pw_rng_seed(6, 1);
    int i, L, k;
    float s[4];
    pw_image_alloc(NULL, &img, 5, 3, 3, NULL);
    for (i = 0; i < 15 * 3; i++) img.px[i] = pw_rng_float(&r);
    REQUIRE(pw_texture_create(NULL, &tex, &img, 0, NULL) == PW_OK);
    CHECK_EQ_INT(tex.nlevels, 3);
    CHECK_EQ_INT(tex.lw[1] * 10 + tex.lh[1], 21);
    CHECK_EQ_INT(tex.lw[2] * 10 + tex.lh[2], 11);
    for (L = 0; L < tex.nlevels; L++) {
        double mean[3] = {0, 0, 0};
        int n = tex.lw[L] * tex.lh[L];
        for (i = 0; i < n; i++)
            for (k = 0; k < 3; k++) mean[k] += tex.level[L][4 * i + k] / 65535.0 / n;
        for (k = 0; k < 3; k++) {
            double ref = 0;
            for (i = 0; i < 15; i++) ref += img.px[3 * i + k] / 15.0;
            CHECK_NEAR(mean[k], ref, 3e-5);
        }
    }
    /* nearest lookups: v near 1 is the top row, v near 0 the bottom */
    pw_texture_sample(&tex, 0.1f, 0.95f, 0, PW_FILTER_NEAREST, PW_WRAP_REPEAT, s);
    CHECK_NEAR(s[0], img.px[0], 2e-5);
    pw_texture_sample(&tex, 0.1f, 0.05f, 0, PW_FILTER_NEAREST, PW_WRAP_REPEAT, s);
    CHECK_NEAR(s[0], img.px[30], 2e-5);
    pw_texture_sample(&tex, 1.1f, -0.95f, 0, PW_FILTER_NEAREST, PW_WRAP_REPEAT, s);
    CHECK_NEAR(s[0], img.px[30], 2e-5);
    pw_texture_sample(&tex, -3.0f, 7.0f, 0, PW_FILTER_BILINEAR, PW_WRAP_CLAMP, s);
    CHECK_NEAR(s[0], img.px[0], 2e-5);
    pw_texture_sample(&tex, 0.5f, 0.5f, 100.0f, PW_FILTER_TRILINEAR, PW_WRAP_REPEAT, s);
    CHECK_NEAR(s[0], tex.level[2][0] / 65535.0, 1e-6);
    pw_texture_free(NULL, &tex);
    pw_image_free(NULL, &img);
}

/* Textures one texel wide or high (fuzz_lapped_files found that the mip
 * chain of a 1 x h texture overran its scratch buffer): every level keeps
 * the mean, under the sanitizers nothing is written out of bounds. */
static void t_render_texture_thin(void)
{
    static const int size[4][2] = {{1, 3}, {1, 17}, {9, 1}, {1, 1}};
    pw_rng r = pw_rng_seed(9, 2);
    int c, i, L;
    for (c = 0; c < 4; c++) {
        pw_image img;
        pw_texture tex;
        int n0 = size[c][0] * size[c][1];
        double ref = 0.0;
        REQUIRE(pw_image_alloc(NULL, &img, size[c][0], size[c][1], 1, NULL) == PW_OK);
        for (i = 0; i < n0; i++) ref += (img.px[i] = pw_rng_float(&r)) / n0;
        REQUIRE(pw_texture_create(NULL, &tex, &img, 0, NULL) == PW_OK);
        for (L = 0; L < tex.nlevels; L++) {
            double mean = 0.0;
            int n = tex.lw[L] * tex.lh[L];
            for (i = 0; i < n; i++) mean += tex.level[L][4 * i] / 65535.0 / n;
            CHECKF(fabs(mean - ref) < 1e-4, "%dx%d level %d: mean %g vs %g", size[c][0], size[c][1], L, mean, ref);
        }
        CHECK_EQ_INT(tex.lw[tex.nlevels - 1] * tex.lh[tex.nlevels - 1], 1);
        pw_texture_free(NULL, &tex);
        pw_image_free(NULL, &img);
    }
}

/* Supersampling gives fractional coverage along a slanted edge. */
static void t_render_supersampling(void)
{
    float pos[9] = {-0.9f, -0.8f, 0, 0.9f, -0.6f, 0, 0.1f, 0.9f, 0}, bg[4] = {0, 0, 0, 1};
    int tri[3] = {0, 1, 2}, ss;
    pw_camera cam = cam_front();
    for (ss = 1; ss <= 4; ss += 3) {
        pw_draw d;
        pw_image out;
        int i, frac = 0, full = 0;
        memset(&d, 0, sizeof d);
        d.positions = pos;
        d.nv = 3;
        d.tris = tri;
        d.ntris = 1;
        REQUIRE(render1(&d, 1, &cam, 48, 48, ss, bg, &out));
        for (i = 0; i < 48 * 48; i++) {
            frac += out.px[4 * i] > 0.01f && out.px[4 * i] < 0.99f;
            full += out.px[4 * i] >= 0.99f;
        }
        pwt_info("ss=%d: %d fractional pixels, %d full", ss, frac, full);
        CHECK(full > 300);
        if (ss == 1) CHECK_EQ_INT(frac, 0);
        else CHECK(frac > 60);
        pw_image_free(NULL, &out);
    }
}

/* pw_camera_frame keeps every vertex of random meshes in the image. */
static void t_render_camera_frame(void)
{
    pw_rng r = pw_rng_seed(7, 1);
    int trial, i, k, outside = 0;
    float pos[3 * 300];
    for (trial = 0; trial < 40; trial++) {
        float vd[3], up[3] = {0, 1, 0}, sc[3], o[3], lo[2] = {1e9f, 1e9f}, hi[2] = {-1e9f, -1e9f};
        float aspect = trial % 3 == 0 ? 2.0f : (trial % 3 == 1 ? 0.5f : 1.0f);
        int w = (int)(100 * aspect), h = 100;
        pw_camera cam;
        for (k = 0; k < 3; k++) {
            vd[k] = frand(&r, -1, 1);
            sc[k] = frand(&r, 0.01f, 10);
            if (trial % 4 == 1) sc[k] = sc[0]; /* a cube-like cloud fills the view */
        }
        if (trial == 0) vd[0] = vd[2] = 0; /* looking straight down +-y, along up */
        for (i = 0; i < 300; i++)
            for (k = 0; k < 3; k++) pos[3 * i + k] = 5.0f + sc[k] * frand(&r, -1, 1);
        cam = pw_camera_frame(pos, 300, vd, up, 20.0f + trial * 3.0f, aspect);
        for (i = 0; i < 300; i++) {
            if (!pw_camera_project(&cam, w, h, pos + 3 * i, o) || o[0] < 0 || o[0] >= w ||
                o[1] < 0 || o[1] >= h || o[2] > cam.zfar)
                outside++;
            for (k = 0; k < 2; k++) {
                if (o[k] < lo[k]) lo[k] = o[k];
                if (o[k] > hi[k]) hi[k] = o[k];
            }
        }
        if (trial % 4 == 1)
            CHECKF(hi[0] - lo[0] > 0.4f * w || hi[1] - lo[1] > 0.4f * h, "trial %d: mesh too small", trial);
    }
    CHECK_EQ_INT(outside, 0);
}

/* Box [-1,1]^3 seen from inside: near-plane clipping covers the screen. */
static void t_render_near_clip(void)
{
    static const float bp[24] = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1,
                                 -1, -1, 1,  1, -1, 1,  1, 1, 1,  -1, 1, 1};
    static const int bt[36] = {0, 1, 2, 0, 2, 3, 4, 6, 5, 4, 7, 6, 0, 4, 5, 0, 5, 1,
                               3, 2, 6, 3, 6, 7, 0, 3, 7, 0, 7, 4, 1, 5, 6, 1, 6, 2};
    pw_rng r = pw_rng_seed(8, 1);
    float bg[4] = {0, 0, 0, 1};
    int trial, bad = 0, k;
    for (trial = 0; trial < 30; trial++) {
        pw_camera cam;
        pw_draw d;
        pw_image out;
        int i;
        memset(&cam, 0, sizeof cam);
        memset(&d, 0, sizeof d);
        for (k = 0; k < 3; k++) {
            cam.eye[k] = frand(&r, -0.95f, 0.95f);
            cam.target[k] = cam.eye[k] + frand(&r, -1, 1);
        }
        /* close to a face, looking into it or along it: the face must stay
         * beyond znear across the view: farther than znear times the slope of
         * the corner rays (about 2.2 here) */
        if (trial < 6) {
            cam.eye[trial % 3] = trial < 3 ? 0.95f : -0.95f;
            cam.target[trial % 3] = trial < 3 ? 2.0f : cam.eye[trial % 3];
        }
        cam.up[0] = 0.3f;
        cam.up[1] = 1.0f;
        cam.fovy_deg = 100.0f;
        cam.znear = 0.01f;
        cam.zfar = 10.0f;
        d.positions = bp;
        d.nv = 8;
        d.tris = bt;
        d.ntris = 12;
        d.lighting = PW_LIGHT_CAMERA;
        d.light_dir[2] = 1.0f;
        d.ambient = 0.5f;
        REQUIRE(render1(&d, 1, &cam, 40, 30, 2, bg, &out));
        for (i = 0; i < 40 * 30; i++)
            if (!(out.px[4 * i] >= 0.5f - 1e-6f && out.px[4 * i] <= 1.0f)) bad++;
        pw_image_free(NULL, &out);
        /* on a face, an edge or a corner: partial coverage, but no garbage */
        cam.eye[0] = trial % 2 ? 1.0f : cam.eye[0];
        cam.eye[1] = trial % 3 ? -1.0f : cam.eye[1];
        cam.znear = trial % 4 ? 1e-6f : 0.5f;
        REQUIRE(render1(&d, 1, &cam, 40, 30, 2, bg, &out));
        for (i = 0; i < 40 * 30 * 4; i++)
            if (!(out.px[i] >= 0.0f && out.px[i] <= 1.0f)) bad++;
        pw_image_free(NULL, &out);
    }
    CHECK_EQ_INT(bad, 0);
}

/* Lambert lighting, two-sided, with face culling by winding. */
static void t_render_lighting(void)
{
    float pos[12], bg[4] = {0, 0, 0, 1};
    int tri[6], cw[6] = {0, 2, 1, 0, 3, 2}, k;
    pw_camera cam = cam_front();
    pw_image out;
    pw_draw d;
    quad_at(pos, tri, -2, -2, 2, 2, 0);
    d = draw_quad(pos, tri, 1, 1, 1, 1);
    d.lighting = PW_LIGHT_CAMERA;
    d.ambient = 0.2f;
    for (k = 0; k < 6; k++) {
        float expect = 1.0f;
        d.tris = (k & 1) ? cw : tri;
        d.lighting = k < 4 ? PW_LIGHT_CAMERA : PW_LIGHT_WORLD;
        d.light_dir[0] = k >= 2 && k < 4 ? 1.0f : 0.0f;
        d.light_dir[2] = k >= 2 && k < 4 ? 0.0f : (k < 2 ? 1.0f : -1.0f);
        if (k >= 2) expect = 0.2f; /* grazing light, or light from behind */
        REQUIRE(render1(&d, 1, &cam, 16, 16, 1, bg, &out));
        CHECKF(fabsf(fb_px(&out, 8, 8)[0] - expect) < 1e-5f, "case %d: %g, expected %g", k,
               fb_px(&out, 8, 8)[0], expect);
        pw_image_free(NULL, &out);
    }
    /* counter-clockwise (as seen) is the front: culled only with CULL_FRONT */
    for (k = 0; k < 4; k++) {
        d.tris = (k & 1) ? cw : tri;
        d.cull = k < 2 ? PW_CULL_BACK : PW_CULL_FRONT;
        d.lighting = PW_LIGHT_NONE;
        REQUIRE(render1(&d, 1, &cam, 16, 16, 1, bg, &out));
        CHECK_EQ_INT(fb_px(&out, 8, 8)[0] > 0.5f, (k == 0 || k == 3));
        pw_image_free(NULL, &out);
    }
}

/* Round RGBA patch: opaque in the middle, fading at the border. */
static void make_patch(pw_image *img, int n, float r, float g, float b)
{
    int x, y;
    pw_image_alloc(NULL, img, n, n, 4, NULL);
    for (y = 0; y < n; y++)
        for (x = 0; x < n; x++) {
            float *p = img->px + (y * n + x) * 4;
            float dx = (x + 0.5f) / n - 0.5f, dy = (y + 0.5f) / n - 0.5f;
            float rr = sqrtf(dx * dx + dy * dy) * 2, stripe = (float)(((x + y) / 6) & 1);
            p[0] = r * (0.7f + 0.3f * stripe);
            p[1] = g * (0.7f + 0.3f * stripe);
            p[2] = b * (0.7f + 0.3f * stripe);
            p[3] = pw_clampf((1.0f - rr) * 4.0f, 0.0f, 1.0f);
        }
}

/* A textured lit torus, then patches pasted over it as lapped textures
 * do (per-patch uvs, LEQUAL, over), rendered twice: byte-identical. */
static void scene_torus(pw_fb *fb, mesh *m, const pw_texture *tex, const pw_texture *patch,
                        float *puv)
{
    float vd[3] = {0.2f, -0.7f, -1.0f};
    pw_camera cam = pw_camera_frame(m->pos, m->nv, vd, NULL, 35.0f, (float)fb->w / fb->h);
    pw_draw d = draw_of(m);
    int p, t, k;
    d.tex = tex;
    d.lighting = PW_LIGHT_CAMERA;
    pw_fb_clear(fb);
    pw_render_draw(fb, &cam, &d, NULL);
    d.tex = patch;
    d.uvs = puv;
    d.blend = PW_BLEND_OVER;
    d.depth_test = PW_DEPTH_LEQUAL;
    d.no_depth_write = 1;
    d.wrap = PW_WRAP_CLAMP;
    for (p = 0; p < 6; p++) { /* patch p: planar projection around a point of the torus */
        float c[3], a = 6.283185307f * p / 6;
        c[0] = cosf(a) * 1.2f;
        c[1] = 0.3f;
        c[2] = sinf(a) * 1.2f;
        for (t = 0; t < m->nt; t++)
            for (k = 0; k < 3; k++) {
                const float *q = m->pos + 3 * m->tri[3 * t + k];
                puv[6 * t + 2 * k] = 0.5f + (q[0] - c[0]) * 1.2f + 0.3f * (q[2] - c[2]);
                puv[6 * t + 2 * k + 1] = 0.5f + (q[2] - c[2]) * 1.2f - 0.3f * (q[0] - c[0]);
            }
        pw_render_draw(fb, &cam, &d, NULL);
    }
}

static void t_render_determinism(void)
{
    mesh m;
    pw_image img, pimg, out;
    pw_texture tex, patch;
    pw_fb fb[2];
    float *puv, bg[4] = {0.15f, 0.15f, 0.2f, 1};
    int i;
    mesh_grid(&m, 80, p_torus, 1.0f);
    for (i = 0; i < m.nt * 6; i++) m.uv[i] *= (i % 2) ? 2.0f : 6.0f;
    make_checker(&img, 128, 16);
    make_patch(&pimg, 64, 0.9f, 0.5f, 0.1f);
    REQUIRE(pw_texture_create(NULL, &tex, &img, 0, NULL) == PW_OK);
    REQUIRE(pw_texture_create(NULL, &patch, &pimg, 0, NULL) == PW_OK);
    puv = (float *)malloc(sizeof(float) * 6 * m.nt);
    for (i = 0; i < 2; i++) {
        REQUIRE(pw_fb_create(NULL, &fb[i], 320, 240, 2, bg, NULL) == PW_OK);
        scene_torus(&fb[i], &m, &tex, &patch, puv);
    }
    CHECK(memcmp(fb[0].color, fb[1].color, sizeof(float) * 4 * fb[0].sw * fb[0].sh) == 0);
    CHECK(memcmp(fb[0].depth, fb[1].depth, sizeof(float) * fb[0].sw * fb[0].sh) == 0);
    if (pw_fb_resolve(&fb[0], &out, 3, NULL) == PW_OK) {
        write_ppm("/tmp/pw_render_torus.ppm", &out);
        pw_image_free(NULL, &out);
    }
    for (i = 0; i < 2; i++) pw_fb_free(&fb[i]);
    free(puv);
    pw_texture_free(NULL, &tex);
    pw_texture_free(NULL, &patch);
    pw_image_free(NULL, &img);
    pw_image_free(NULL, &pimg);
    mesh_free(&m);
}

/* Band rendering (pw_fb_create_band, pw_render_frame) and threads: the
 * torus scene with lapped-style passes, drawn whole, band by band with
 * bands of 1, 7 and 13 rows, by pw_render_frame on one thread, on 2 and 3
 * threads, and through a caller's parallel-for that runs the bands in
 * reverse, the bands with the mesh projected once (pw_draw_project): every
 * picture is the same, bit for bit. */
typedef struct band_scene {
    const mesh *m;
    const pw_texture *tex, *patch;
    float *puv[6];
    pw_camera cam;
    const double *projected; /* NULL: every draw projects the mesh */
} band_scene;

static int band_draw(void *user, pw_fb *fb, pw_err *e)
{
    band_scene *S = (band_scene *)user;
    pw_draw d = draw_of(S->m);
    int p, r;
    d.tex = S->tex;
    d.lighting = PW_LIGHT_CAMERA;
    d.projected = S->projected;
    r = pw_render_draw(fb, &S->cam, &d, e);
    d.tex = S->patch;
    d.blend = PW_BLEND_OVER;
    d.depth_test = PW_DEPTH_LEQUAL;
    d.no_depth_write = 1;
    d.wrap = PW_WRAP_CLAMP;
    for (p = 0; p < 6 && r == PW_OK; p++) {
        d.uvs = S->puv[p];
        r = pw_render_draw(fb, &S->cam, &d, e);
    }
    return r;
}

static void reverse_for(void *pool, int n, pw_task_fn task, void *ctx)
{
    int i;
    *(int *)pool += n;
    for (i = n - 1; i >= 0; i--) task(ctx, i);
}

static void t_render_bands(void)
{
    static const int rows[3] = {1, 7, 13};
    mesh m;
    pw_image img, pimg, ref, out;
    pw_texture tex, patch;
    pw_fb fb;
    pw_frame f;
    pw_parallel par;
    band_scene S;
    float vd[3] = {0.2f, -0.7f, -1.0f}, bg[4] = {0.15f, 0.15f, 0.2f, 1};
    size_t bytes;
    int i, p, t, k, y, size, calls = 0;
    mesh_grid(&m, 60, p_torus, 1.0f);
    make_checker(&img, 128, 16);
    make_patch(&pimg, 64, 0.9f, 0.5f, 0.1f);
    REQUIRE(pw_texture_create(NULL, &tex, &img, 0, NULL) == PW_OK);
    REQUIRE(pw_texture_create(NULL, &patch, &pimg, 0, NULL) == PW_OK);
    S.m = &m;
    S.tex = &tex;
    S.patch = &patch;
    for (p = 0; p < 6; p++) {
        float c[3], a = 6.283185307f * p / 6;
        c[0] = cosf(a) * 1.2f;
        c[1] = 0.3f;
        c[2] = sinf(a) * 1.2f;
        S.puv[p] = (float *)malloc(sizeof(float) * 6 * m.nt);
        for (t = 0; t < m.nt; t++)
            for (k = 0; k < 3; k++) {
                const float *q = m.pos + 3 * m.tri[3 * t + k];
                S.puv[p][6 * t + 2 * k] = 0.5f + (q[0] - c[0]) * 1.2f + 0.3f * (q[2] - c[2]);
                S.puv[p][6 * t + 2 * k + 1] = 0.5f + (q[2] - c[2]) * 1.2f - 0.3f * (q[0] - c[0]);
            }
    }
    for (size = 0; size < 2; size++) {
        int W = size ? 301 : 320, H = size ? 157 : 240, ss = size ? 3 : 2;
        pw_draw whole = draw_of(&m);
        S.cam = pw_camera_frame(m.pos, m.nv, vd, NULL, 35.0f, (float)W / H);
        S.projected = NULL;
        REQUIRE(pw_fb_create(NULL, &fb, W, H, ss, bg, NULL) == PW_OK);
        REQUIRE(band_draw(&S, &fb, NULL) == PW_OK);
        REQUIRE(pw_fb_resolve(&fb, &ref, 3, NULL) == PW_OK);
        pw_fb_free(&fb);
        bytes = sizeof(float) * 3 * W * H;
        memset(&f, 0, sizeof f);
        f.w = W;
        f.h = H;
        f.ss = ss;
        memcpy(f.bg, bg, sizeof bg);
        f.channels = 3;
        f.draw = band_draw;
        f.user = &S;
        REQUIRE(pw_draw_project(NULL, &f, &S.cam, &whole, NULL) == PW_OK);
        S.projected = whole.projected;
        for (i = 0; i < 3; i++) {
            REQUIRE(pw_image_alloc(NULL, &out, W, H, 3, NULL) == PW_OK);
            REQUIRE(pw_fb_create_band(NULL, &fb, W, H, ss, rows[i], bg, NULL) == PW_OK);
            for (y = 0; y < H; y += rows[i]) {
                pw_fb_set_band(&fb, y);
                REQUIRE(band_draw(&S, &fb, NULL) == PW_OK);
                pw_fb_resolve_band(&fb, &out);
            }
            pw_fb_free(&fb);
            CHECKF(memcmp(out.px, ref.px, bytes) == 0, "%dx%d: bands of %d rows differ from the whole frame",
                      W, H, rows[i]);
            pw_image_free(NULL, &out);
        }
        memset(&par, 0, sizeof par);
        for (i = 0; i < 4; i++) {
            par.threads = i < 3 ? i + 1 : 0;
            par.run = i == 3 ? reverse_for : NULL;
            par.pool = &calls;
            f.par = i ? &par : NULL;
            REQUIRE(pw_render_frame(NULL, &f, &out, NULL) == PW_OK);
            CHECKF(memcmp(out.px, ref.px, bytes) == 0, "%dx%d: pw_render_frame (%s %d) differs", W, H,
                      i == 3 ? "caller's parallel-for" : "threads", par.threads);
            pw_image_free(NULL, &out);
        }
        pw_free(NULL, (void *)whole.projected);
        pw_image_free(NULL, &ref);
    }
    CHECK(calls > 2); /* the caller's parallel-for ran the bands */
    f.channels = 2;
    CHECK(pw_render_frame(NULL, &f, &out, NULL) == PW_ERR_INVALID && out.px == NULL);
    for (p = 0; p < 6; p++) free(S.puv[p]);
    pw_texture_free(NULL, &tex);
    pw_texture_free(NULL, &patch);
    pw_image_free(NULL, &img);
    pw_image_free(NULL, &pimg);
    mesh_free(&m);
}

/* The blended path with opaque colours and depth writes draws what the
 * opaque (visibility-buffer) path draws, for several sample counts; with
 * the eye close to the mesh (near-plane clipping) too. */
static void t_render_paths_agree(void)
{
    mesh m;
    pw_image img, out[2];
    pw_texture tex;
    float vd[3] = {0.4f, -0.5f, -1.0f}, bg[4] = {0.2f, 0.3f, 0.4f, 1};
    int ss, path, i, close, W = 120, H = 80;
    mesh_grid(&m, 40, p_torus, 1.0f);
    for (i = 0; i < m.nt * 6; i++) m.uv[i] *= 4.0f;
    make_checker(&img, 64, 8);
    REQUIRE(pw_texture_create(NULL, &tex, &img, 0, NULL) == PW_OK);
    for (close = 0; close < 2; close++)
        for (ss = 1; ss <= 3; ss++) {
            pw_camera cam = pw_camera_frame(m.pos, m.nv, vd, NULL, 50.0f, 1.5f);
            double sum = 0.0, mx = 0.0;
            if (close) { /* the eye inside the tube */
                cam.eye[0] = 1.0f;
                cam.eye[1] = 0.0f;
                cam.eye[2] = 0.0f;
                cam.target[2] = 1.0f;
                cam.znear = 0.01f;
            }
            for (path = 0; path < 2; path++) {
                pw_draw d = draw_of(&m);
                d.tex = &tex;
                d.lighting = PW_LIGHT_WORLD;
                d.blend = path ? PW_BLEND_OVER : PW_BLEND_REPLACE;
                REQUIRE(render1(&d, 1, &cam, W, H, ss, bg, &out[path]));
            }
            for (i = 0; i < W * H * 4; i++) {
                double diff = fabs(out[0].px[i] - out[1].px[i]);
                sum += diff;
                if (diff > mx) mx = diff;
            }
            if (close && ss == 2) write_ppm("/tmp/pw_render_inside.ppm", &out[1]);
            pwt_info("ss %d%s: mean |opaque - blended| %.2g, max %.2g", ss, close ? " (eye inside)" : "",
                     sum / (W * H * 4), mx);
            CHECK(sum / (W * H * 4) < 2e-3);
            CHECK(mx < 0.25);
            pw_image_free(NULL, &out[0]);
            pw_image_free(NULL, &out[1]);
        }
    pw_texture_free(NULL, &tex);
    pw_image_free(NULL, &img);
    mesh_free(&m);
}

/* Garbage meshes (huge, tiny, infinite and NaN coordinates and uvs, random
 * indices) under random cameras and every mode: no crash, no undefined
 * behaviour (run under the sanitizers), colours stay in [0, 1]. */
static void t_render_garbage(void)
{
    pw_rng r = pw_rng_seed(9, 1);
    float pos[3 * 40], uv[6 * 60], px[4 * 4] = {1, 0, 0, 1, 0, 1, 0, 0.5f, 0, 0, 1, 0, 1, 1, 1, 1};
    float specials[6] = {1e30f, -1e30f, 3e38f, 1e-30f, 0.0f, 0.0f};
    int tri[3 * 60], trial, i, bad = 0, drawn = 0;
    pw_image img;
    pw_texture tex;
    specials[4] = (float)strtod("inf", NULL);
    specials[5] = (float)strtod("nan", NULL);
    img.w = img.h = 2;
    img.c = 4;
    img.bits = 8;
    img.px = px;
    REQUIRE(pw_texture_create(NULL, &tex, &img, 0, NULL) == PW_OK);
    for (trial = 0; trial < 60; trial++) {
        pw_camera cam;
        pw_draw d;
        pw_image out;
        float vd[3];
        for (i = 0; i < 3 * 40; i++) pos[i] = frand(&r, -2, 2) * (trial % 3 == 0 ? 1e3f : 1.0f);
        for (i = 0; i < 3; i++) vd[i] = frand(&r, -1, 1);
        cam = pw_camera_frame(pos, 40, vd, NULL, frand(&r, 1, 179), frand(&r, 0.2f, 5));
        for (i = 0; i < 3 * 40; i++)
            if (pw_rng_below(&r, 20) == 0) pos[i] = specials[pw_rng_below(&r, 6)];
        for (i = 0; i < 6 * 60; i++) {
            uv[i] = frand(&r, -3, 3);
            if (pw_rng_below(&r, 20) == 0) uv[i] = specials[pw_rng_below(&r, 6)];
        }
        for (i = 0; i < 3 * 60; i++) tri[i] = (int)pw_rng_below(&r, 40);
        if (trial % 4 == 1) { /* the eye among the triangles */
            for (i = 0; i < 3; i++) cam.eye[i] = frand(&r, -1, 1);
            cam.znear = 1e-6f;
        }
        memset(&d, 0, sizeof d);
        d.positions = pos;
        d.nv = 40;
        d.tris = tri;
        d.ntris = 60;
        d.uvs = uv;
        d.tex = trial % 5 ? &tex : NULL;
        d.filter = trial % 3;
        d.wrap = trial % 2;
        d.blend = (trial / 2) % 2;
        d.depth_test = trial % 3;
        d.lighting = trial % 3;
        d.flat = trial % 7 == 0;
        d.cull = (trial / 3) % 3;
        if (!render1(&d, 1, &cam, 24 + trial % 5, 16 + trial % 3, 1 + trial % 4, NULL, &out)) continue;
        drawn++;
        for (i = 0; i < out.w * out.h * 4; i++)
            if (!(out.px[i] >= 0.0f && out.px[i] <= 1.0f)) bad++;
        pw_image_free(NULL, &out);
    }
    CHECK_EQ_INT(bad, 0);
    CHECK_EQ_INT(drawn, 60);
    pw_texture_free(NULL, &tex);
}

/* Bad input gives an error code and a message, never a crash. */
static void t_render_errors(void)
{
    float pos[12];
    int tri[6], bad_tri[6] = {0, 1, 2, 0, 2, 4};
    pw_camera cam = cam_front(), bad_cam;
    pw_fb fb;
    pw_err e;
    pw_draw d;
    pw_image out, img;
    pw_texture tex;
    quad_at(pos, tri, -1, -1, 1, 1, 0);
    REQUIRE(pw_fb_create(NULL, &fb, 8, 8, 1, NULL, NULL) == PW_OK);
    d = draw_quad(pos, bad_tri, 1, 1, 1, 1);
    pw_err_clear(&e);
    CHECK_EQ_INT(pw_render_draw(&fb, &cam, &d, &e), PW_ERR_INVALID);
    CHECK(strstr(e.msg, "triangle 1") != NULL);
    d.tris = tri;
    bad_cam = cam;
    bad_cam.fovy_deg = 0;
    CHECK_EQ_INT(pw_render_draw(&fb, &bad_cam, &d, NULL), PW_ERR_INVALID);
    bad_cam = cam;
    memcpy(bad_cam.target, bad_cam.eye, sizeof bad_cam.eye);
    CHECK_EQ_INT(pw_render_draw(&fb, &bad_cam, &d, NULL), PW_ERR_INVALID);
    bad_cam = cam;
    bad_cam.up[1] = 0;
    bad_cam.up[2] = 1;
    CHECK_EQ_INT(pw_render_draw(&fb, &bad_cam, &d, NULL), PW_ERR_INVALID);
    make_coded(&img, 4, 4);
    REQUIRE(pw_texture_create(NULL, &tex, &img, 0, NULL) == PW_OK);
    d.tex = &tex;
    CHECK_EQ_INT(pw_render_draw(&fb, &cam, &d, NULL), PW_ERR_INVALID);
    d.tex = NULL;
    d.blend = 7;
    CHECK_EQ_INT(pw_render_draw(&fb, &cam, &d, NULL), PW_ERR_INVALID);
    d.blend = 0;
    /* non-finite positions: those triangles are skipped */
    pos[0] = (float)strtod("nan", NULL);
    CHECK_EQ_INT(pw_render_draw(&fb, &cam, &d, NULL), PW_OK);
    CHECK_EQ_INT(pw_fb_resolve(&fb, &out, 2, NULL), PW_ERR_INVALID);
    pw_fb_free(&fb);
    pw_texture_free(NULL, &tex);
    pw_image_free(NULL, &img);
    CHECK_EQ_INT(pw_fb_create(NULL, &fb, 8, 8, 9, NULL, NULL), PW_ERR_INVALID);
    CHECK_EQ_INT(pw_fb_create(NULL, &fb, 0, 8, 1, NULL, NULL), PW_ERR_INVALID);
    CHECK_EQ_INT(pw_fb_create(NULL, &fb, 1 << 20, 8, 1, NULL, NULL), PW_ERR_LIMIT);
    CHECK(pw_texture_create(NULL, &tex, NULL, 0, NULL) == PW_ERR_INVALID);
}


/* A caller's shader (pw_draw.shader) gets perspective-correct barycentric
 * coordinates and their derivatives per pixel: on a triangle facing the
 * camera they are affine in the pixel position. */
typedef struct shader_probe {
    float db[4];
    int calls;
} shader_probe;

static void probe_shader(void *user, int tri, float b1, float b2, const float db[4], float rgba[4])
{
    shader_probe *p = (shader_probe *)user;
    (void)tri;
    memcpy(p->db, db, sizeof p->db);
    p->calls++;
    rgba[0] = b1, rgba[1] = b2, rgba[2] = 0.0f, rgba[3] = 1.0f;
}

static void t_render_shader(void)
{
    static const float pos[9] = {-1, -1, 0, 1, -1, 0, -1, 1, 0};
    static const int tri[3] = {0, 1, 2};
    const int W = 64, H = 64;
    pw_camera cam = cam_front();
    shader_probe probe;
    pw_fb fb;
    pw_image out;
    pw_draw d;
    pw_err e;
    double worst = 0.0;
    int x, y, n = 0;
    memset(&d, 0, sizeof d);
    memset(&probe, 0, sizeof probe);
    d.positions = pos, d.nv = 3, d.tris = tri, d.ntris = 1;
    d.shader = probe_shader, d.shader_user = &probe;
    CHECK(pw_fb_create(NULL, &fb, W, H, 1, NULL, &e) == PW_OK);
    CHECK(pw_render_draw(&fb, &cam, &d, &e) == PW_OK);
    CHECK(pw_fb_resolve(&fb, &out, 3, &e) == PW_OK);
    for (y = 0; y < H; y++)
        for (x = 0; x < W; x++) {
            double wx = (x + 0.5) / W * 2.0 - 1.0, wy = 1.0 - (y + 0.5) / H * 2.0;
            double b1 = (wx + 1.0) / 2.0, b2 = (wy + 1.0) / 2.0;
            const float *px = fb_px(&out, x, y);
            if (b1 + b2 > 0.97) continue; /* near the diagonal edge: partial coverage */
            worst = fabs(px[0] - b1) > worst ? fabs(px[0] - b1) : worst;
            worst = fabs(px[1] - b2) > worst ? fabs(px[1] - b2) : worst;
            n++;
        }
    CHECKF(n > 1500 && worst < 2e-3, "%d pixels, largest barycentric error %g", n, worst);
    CHECKF(probe.calls > 0 && fabs(probe.db[0] - 1.0 / W) < 1e-4 && fabs(probe.db[1]) < 1e-4 &&
               fabs(probe.db[2]) < 1e-4 && fabs(probe.db[3] + 1.0 / H) < 1e-4,
           "derivatives %g %g %g %g", probe.db[0], probe.db[1], probe.db[2], probe.db[3]);
    pw_image_free(NULL, &out);
    pw_fb_free(&fb);
}

/* The SSE2 paths (texel filtering, the resolve's clamp) against the
 * portable C's formulas, bit for bit: random lookups at random mip levels
 * in both wrap modes, and framebuffer values with NaN, infinities, -0 and
 * values around 0 and 1. (test_render_portable runs every case here
 * again built with PW_NO_SIMD.) */
static void t_render_simd_exact(void)
{
    pw_image img, out;
    pw_texture tex;
    pw_fb fb;
    pw_rng rng = pw_rng_seed(7, 1);
    static const float special[8] = {0.0f, -0.0f, 1.0f, 0.5f, -1e-30f, 1.0000001f, 3.0e38f, -2.0f};
    const float bg[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    int i, k, bad = 0;
    make_checker(&img, 37, 5);
    REQUIRE(pw_texture_create(NULL, &tex, &img, 0, NULL) == PW_OK);
    for (i = 0; i < 20000; i++) {
        float u = 4.0f * pw_rng_float(&rng) - 2.0f, v = 4.0f * pw_rng_float(&rng) - 2.0f;
        float lod = 8.0f * pw_rng_float(&rng) - 1.0f, got[4], want[4], w[8];
        int wrap = i & 1 ? PW_WRAP_CLAMP : PW_WRAP_REPEAT, L;
        ptrdiff_t p[8];
        const uint8_t *a, *b;
        pw__tex_trilinear8(&tex, u, v, lod, wrap, 1.0f / 255.0f, got);
        pw__tex_taps8(&tex, u, v, lod, wrap, 1.0f / 255.0f, &L, p, w);
        a = tex.level8[L];
        b = a + (size_t)tex.lw[L] * tex.lh[L] * 4;
        for (k = 0; k < 4; k++)
            want[k] = ((w[0] * (float)a[p[0] + k] + w[1] * (float)a[p[1] + k]) +
                       (w[2] * (float)a[p[2] + k] + w[3] * (float)a[p[3] + k])) +
                      ((w[4] * (float)b[p[4] + k] + w[5] * (float)b[p[5] + k]) +
                       (w[6] * (float)b[p[6] + k] + w[7] * (float)b[p[7] + k]));
        bad += memcmp(got, want, sizeof got) != 0;
    }
    CHECKF(bad == 0, "%d of 20000 filtered lookups differ from the C formula", bad);
    REQUIRE(pw_fb_create(NULL, &fb, 33, 7, 1, bg, NULL) == PW_OK);
    for (i = 0; i < 33 * 7 * 4; i++) {
        float x = i % 3 == 0 ? special[(i / 3) % 8] : 3.0f * pw_rng_float(&rng) - 1.0f;
        fb.color[i] = i % 11 == 5 ? nanf("") : (i % 13 == 7 ? (i & 1 ? INFINITY : -INFINITY) : x);
    }
    REQUIRE(pw_fb_resolve(&fb, &out, 3, NULL) == PW_OK);
    for (i = 0, bad = 0; i < 33 * 7; i++)
        for (k = 0; k < 3; k++) {
            float x = fb.color[4 * i + k], want = x > 0.0f ? (x < 1.0f ? x : 1.0f) : 0.0f;
            bad += memcmp(&out.px[3 * i + k], &want, sizeof want) != 0;
        }
    CHECKF(bad == 0, "%d resolved values differ from the C clamp", bad);
    pw_image_free(NULL, &out);
    pw_fb_free(&fb);
    pw_texture_free(NULL, &tex);
    pw_image_free(NULL, &img);
}

#ifdef PW__SSE2
/* A float for the four-wide checks: mostly in [lo, hi), sometimes one of
 * the values that take other branches (NaN, infinities, huge, tiny). */
static float simd_value(pw_rng *rng, float lo, float hi)
{
    static const float odd[8] = {0.0f, -0.0f, 1e-35f, 1e35f, -1e35f, 1.0f, 2e9f, -2e9f};
    uint32_t k = pw_rng_below(rng, 40);
    if (k == 0) return nanf("");
    if (k == 1) return k & 1 ? INFINITY : -INFINITY;
    if (k < 10) return odd[k - 2];
    return lo + (hi - lo) * pw_rng_float(rng);
}

/* Bit for bit the same, or both NaN: which NaN an operation on two NaNs
 * gives depends on its operands' order, which the compiler may swap in the
 * scalar code, and every later step treats all NaNs alike. */
static int same_float(float a, float b) { return (a != a && b != b) || !memcmp(&a, &b, sizeof a); }

/* The four-wide shading steps (coordinates, mip level, lighting, log2,
 * trilinear taps) against the scalar code they stand for, bit for bit. */
static void t_render_simd_batch(void)
{
    pw_image img;
    pw_texture tex;
    pw__ctx c;
    pw__batch b;
    pw_rng rng = pw_rng_seed(11, 1);
    float planes[8 * PW__NPL], dx[PW__BATCH], dy[PW__BATCH], iq[PW__BATCH], uvl[4 * PW__BATCH];
    int round, i, j, bad_coords = 0, bad_log = 0, bad_taps = 0;
    make_checker(&img, 37, 5);
    REQUIRE(pw_texture_create(NULL, &tex, &img, 0, NULL) == PW_OK);
    memset(&c, 0, sizeof c);
    c.planes = planes;
    c.tex = &tex;
    c.lit = 1;
    c.ss = 2.0f;
    c.ambient = 0.3f;
    c.light[0] = -0.3f;
    c.light[1] = 0.4f;
    c.light[2] = 0.87f;
    for (round = 0; round < 500; round++) {
        c.filter = round % 3 == 2 ? PW_FILTER_BILINEAR : PW_FILTER_TRILINEAR;
        for (i = 0; i < 8 * PW__NPL; i++) planes[i] = simd_value(&rng, -2.0f, 2.0f);
        b.n = PW__BATCH;
        for (i = 0; i < PW__BATCH; i++) {
            b.t[i] = (int)pw_rng_below(&rng, 8);
            b.x[i] = simd_value(&rng, 0.0f, 500.0f);
            b.y[i] = simd_value(&rng, 0.0f, 500.0f);
        }
        for (i = 0; i < PW__BATCH; i += 4) pw__shade_coords4(&c, &b, i, 1, dx, dy, iq, uvl);
        for (i = 0; i < PW__BATCH; i++) {
            const float *pl = planes + (size_t)b.t[i] * PW__NPL;
            float X = b.x[i] - pl[PW__OX], Y = b.y[i] - pl[PW__OY], q = pl[0] * X + pl[1] * Y + pl[2], w[4];
            if (!(q > 1e-30f)) q = 1e-30f;
            w[0] = (pl[3] * X + pl[4] * Y + pl[5]) * (1.0f / q);
            w[1] = (pl[6] * X + pl[7] * Y + pl[8]) * (1.0f / q);
            w[2] = c.filter == PW_FILTER_TRILINEAR ? pw__tex_lod(&c, pl, w[0], w[1], 1.0f / q) : 0.0f;
            w[3] = pw__light(&c, pl, X, Y);
            bad_coords += !same_float(dx[i], X) || !same_float(dy[i], Y) || !same_float(iq[i], 1.0f / q);
            for (j = 0; j < 4; j++) bad_coords += !same_float(uvl[j * PW__BATCH + i], w[j]);
        }
        for (i = 0; i < PW__BATCH; i += 4) {
            float x[4], got[4];
            pw__taps4 T;
            for (j = 0; j < 4; j++) x[j] = simd_value(&rng, 0.0f, 4.0f);
            _mm_storeu_ps(got, pw__log2f4(_mm_loadu_ps(x)));
            for (j = 0; j < 4; j++) {
                float want = pw__log2f(x[j]);
                bad_log += !same_float(got[j], want);
            }
            T.u = uvl + i;
            T.v = uvl + PW__BATCH + i;
            T.lod = uvl + 2 * PW__BATCH + i;
            pw__tex_taps8x4(&tex, round & 1, 1.0f / 255.0f, &T);
            for (j = 0; j < 4; j++) {
                ptrdiff_t p[8];
                float w[8];
                int L;
                pw__tex_taps8(&tex, T.u[j], T.v[j], T.lod[j], round & 1, 1.0f / 255.0f, &L, p, w);
                bad_taps += L != T.L[j] || memcmp(p, T.p + 8 * j, sizeof p) || memcmp(w, T.w + 8 * j, sizeof w);
            }
        }
    }
    CHECKF(bad_coords == 0, "%d four-wide coordinates, mip levels or lights differ from the scalar code", bad_coords);
    CHECKF(bad_log == 0, "%d four-wide log2 values differ from pw__log2f", bad_log);
    CHECKF(bad_taps == 0, "%d four-wide trilinear taps differ from pw__tex_taps8", bad_taps);
    pw_texture_free(NULL, &tex);
    pw_image_free(NULL, &img);
}
#endif

/* test_render_portable builds this file with PW_NO_SIMD: its cases are
 * named portable/... */
#ifdef PW_NO_SIMD
#define CASE(name) "portable/" name
#else
#define CASE(name) name
#endif

static const pwt_case cases[] = {
    {CASE("raster_triangulation"), t_raster_triangulation},
    {CASE("raster_fan"), t_raster_fan},
    {CASE("raster_barycentrics"), t_raster_barycentrics},
    {CASE("raster_degenerate"), t_raster_degenerate},
    {CASE("raster_clipping"), t_raster_clipping},
    {CASE("raster_spans"), t_raster_spans},
    {CASE("render_textured_quad"), t_render_textured_quad},
    {CASE("render_perspective"), t_render_perspective},
    {CASE("render_depth"), t_render_depth},
    {CASE("render_blend_over"), t_render_blend_over},
    {CASE("render_lequal"), t_render_lequal},
    {CASE("render_mip_levels"), t_render_mip_levels},
    {CASE("render_texture_npot"), t_render_texture_npot},
    {CASE("render_texture_thin"), t_render_texture_thin},
    {CASE("render_supersampling"), t_render_supersampling},
    {CASE("render_camera_frame"), t_render_camera_frame},
    {CASE("render_near_clip"), t_render_near_clip},
    {CASE("render_lighting"), t_render_lighting},
    {CASE("render_determinism"), t_render_determinism},
    {CASE("render_bands"), t_render_bands},
    {CASE("render_paths_agree"), t_render_paths_agree},
    {CASE("render_garbage"), t_render_garbage},
    {CASE("render_errors"), t_render_errors},
    {CASE("render_shader"), t_render_shader},
    {CASE("render_simd_exact"), t_render_simd_exact},
#ifdef PW__SSE2
    {CASE("render_simd_batch"), t_render_simd_batch},
#endif
};
PWT_MAIN(cases)
