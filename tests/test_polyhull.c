/* Tests of the polygonal hull of a texture patch (src/lapped/polyhull.h,
 * Praun et al. 2000 §3.3): containment of every non-transparent pixel,
 * simplicity, orientation, vertex counts, added area, queries against brute
 * force, speed. */
#include "../src/lapped/polyhull.h"
#include "../src/common/rng.h"
#include "../src/common/vec.h"
#include "../src/common/image.h"
#include "pwtest.h"
#include <time.h>

/* Does the triangle uv[0..5] meet the hull? One of its edges meets it, or
 * the hull lies inside the triangle (then so does its first vertex). */
static int polyhull_triangle_hits(const pw_polyhull *h, const float uv[6])
{
    double o[3], x, y;
    int k;
    if (!h || !h->uv || h->n < 3 || !uv) return 0;
    for (k = 0; k < 3; k++)
        if (pw_polyhull_segment_hits(h, uv[2 * k], uv[2 * k + 1], uv[(2 * k + 2) % 6], uv[(2 * k + 3) % 6])) return 1;
    x = h->uv[0];
    y = h->uv[1];
    for (k = 0; k < 3; k++)
        o[k] = pw__hull_orient(uv[2 * k], uv[2 * k + 1], uv[(2 * k + 2) % 6], uv[(2 * k + 3) % 6], x, y);
    return (o[0] > 0 && o[1] > 0 && o[2] > 0) || (o[0] < 0 && o[1] < 0 && o[2] < 0);
}

/* The area enclosed, in texture coordinates (the unit square has area 1). */
static double polyhull_area(const pw_polyhull *h)
{
    double s = 0.0;
    int i, j;
    if (!h || !h->uv) return 0.0;
    for (i = 0, j = h->n - 1; i < h->n; j = i++)
        s += (double)h->uv[2 * j] * h->uv[2 * i + 1] - (double)h->uv[2 * i] * h->uv[2 * j + 1];
    return 0.5 * s;
}

/* ------------------------------------------------------------ masks */

typedef struct mask {
    int w, h;
    float *a; /* w*h alpha */
} mask;

static int mask_new(mask *m, int w, int h)
{
    m->w = w;
    m->h = h;
    m->a = (float *)calloc((size_t)w * h, sizeof(float));
    return m->a != NULL;
}

static void disc(mask *m, float cx, float cy, float r, float val)
{
    int x, y;
    for (y = 0; y < m->h; y++)
        for (x = 0; x < m->w; x++) {
            float dx = (float)x + 0.5f - cx, dy = (float)y + 0.5f - cy;
            if (dx * dx + dy * dy <= r * r) m->a[y * m->w + x] = val;
        }
}

/* A star-shaped blob r(theta) = R (1 + sum of a few harmonics). */
static void splotch(mask *m, uint64_t seed)
{
    pw_rng r = pw_rng_seed(seed, 77);
    double amp[6], ph[6];
    int k, x, y;
    for (k = 2; k < 6; k++) {
        amp[k] = (0.05 + 0.12 * pw_rng_double(&r)) * 2.0 / k;
        ph[k] = 6.283185307 * pw_rng_double(&r);
    }
    for (y = 0; y < m->h; y++)
        for (x = 0; x < m->w; x++) {
            double dx = (x + 0.5 - 0.5 * m->w) / (0.5 * m->w), dy = (y + 0.5 - 0.5 * m->h) / (0.5 * m->h);
            double rho = sqrt(dx * dx + dy * dy), c = rho > 0 ? dx / rho : 1, s = rho > 0 ? dy / rho : 0;
            double ck = c, sk = s, rr = 1.0, t;
            for (k = 2; k < 6; k++) {
                t = ck * c - sk * s; /* angle k theta */
                sk = sk * c + ck * s;
                ck = t;
                rr += amp[k] * (ck * pw_cos(ph[k]) - sk * pw_sin(ph[k]));
            }
            if (rho <= 0.75 * rr) m->a[y * m->w + x] = (float)(1.0 - rho / 2);
        }
}

/* Union of random discs plus salt noise near them: ragged, may have holes
 * and several components. */
static void blobs(mask *m, uint64_t seed, int ndisc, float salt)
{
    pw_rng r = pw_rng_seed(seed, 5);
    int k, i;
    for (k = 0; k < ndisc; k++) {
        float cx = pw_rng_float(&r) * m->w, cy = pw_rng_float(&r) * m->h;
        float rad = (0.03f + 0.15f * pw_rng_float(&r)) * (float)(m->w < m->h ? m->w : m->h);
        disc(m, cx, cy, rad, 0.2f + 0.8f * pw_rng_float(&r));
    }
    for (i = 0; i < m->w * m->h; i++) {
        float u = pw_rng_float(&r);
        if (u < salt) m->a[i] = m->a[i] > 0 ? 0.0f : 1.0f; /* holes and specks */
    }
}

/* ------------------------------------------------------------ checks */

/* Even-odd point in polygon, no tolerance (brute force reference). */
static int inside_raw(const pw_polyhull *h, double x, double y)
{
    int i, j, in = 0;
    for (i = 0, j = h->n - 1; i < h->n; j = i++) {
        double xi = h->uv[2 * i], yi = h->uv[2 * i + 1], xj = h->uv[2 * j], yj = h->uv[2 * j + 1];
        if ((yi > y) != (yj > y) && x < xj + (y - yj) * (xi - xj) / (yi - yj)) in = !in;
    }
    return in;
}

static double orient(double ax, double ay, double bx, double by, double cx, double cy)
{
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
}

/* Closed segments ab and cd intersect (exact predicates on doubles). */
static int seg_meet(const double *a, const double *b, const double *c, const double *d)
{
    double o1 = orient(a[0], a[1], b[0], b[1], c[0], c[1]), o2 = orient(a[0], a[1], b[0], b[1], d[0], d[1]);
    double o3 = orient(c[0], c[1], d[0], d[1], a[0], a[1]), o4 = orient(c[0], c[1], d[0], d[1], b[0], b[1]);
    if (o1 == 0 && o2 == 0) { /* collinear: overlap of projections */
        int k = fabs(a[0] - b[0]) > fabs(a[1] - b[1]) ? 0 : 1;
        double lo1 = a[k] < b[k] ? a[k] : b[k], hi1 = a[k] < b[k] ? b[k] : a[k];
        double lo2 = c[k] < d[k] ? c[k] : d[k], hi2 = c[k] < d[k] ? d[k] : c[k];
        return lo1 <= hi2 && lo2 <= hi1;
    }
    return ((o1 <= 0 && o2 >= 0) || (o1 >= 0 && o2 <= 0)) && ((o3 <= 0 && o4 >= 0) || (o3 >= 0 && o4 <= 0));
}

static void vtx(const pw_polyhull *h, int i, double *p)
{
    i %= h->n;
    p[0] = h->uv[2 * i];
    p[1] = h->uv[2 * i + 1];
}

/* Simple: non-adjacent edges never meet; adjacent edges meet only at their
 * shared vertex (no fold-back). */
static int is_simple(const pw_polyhull *h)
{
    int i, j;
    for (i = 0; i < h->n; i++)
        for (j = i + 1; j < h->n; j++) {
            double a[2], b[2], c[2], d[2];
            vtx(h, i, a);
            vtx(h, i + 1, b);
            vtx(h, j, c);
            vtx(h, j + 1, d);
            if (j == i + 1 || (i == 0 && j == h->n - 1)) {
                /* adjacent: the far endpoint of one must not lie on the other */
                const double *s = j == i + 1 ? a : c, *m = j == i + 1 ? b : a, *t = j == i + 1 ? d : b;
                if (orient(s[0], s[1], m[0], m[1], t[0], t[1]) == 0 &&
                    (t[0] - m[0]) * (s[0] - m[0]) + (t[1] - m[1]) * (s[1] - m[1]) > 0)
                    return 0;
                continue;
            }
            if (seg_meet(a, b, c, d)) return 0;
        }
    return 1;
}

/* Unit boundary edges of the pixel set (the "polygon with vertices at all
 * the boundary pixels" before any simplification). */
static long boundary_edges(const mask *m)
{
    long n = 0;
    int x, y, k;
    for (y = 0; y < m->h; y++)
        for (x = 0; x < m->w; x++) {
            if (!(m->a[y * m->w + x] > 0)) continue;
            for (k = 0; k < 4; k++) {
                int nx = x + (k == 0 ? -1 : k == 1 ? 1 : 0), ny = y + (k == 2 ? -1 : k == 3 ? 1 : 0);
                if (nx < 0 || ny < 0 || nx >= m->w || ny >= m->h || !(m->a[ny * m->w + nx] > 0)) n++;
            }
        }
    return n;
}

static long mask_area(const mask *m)
{
    long n = 0;
    int i;
    for (i = 0; i < m->w * m->h; i++) n += m->a[i] > 0;
    return n;
}

/* Every corner of every non-transparent pixel is in the hull; returns the
 * number of misses. */
static long uncovered(const mask *m, const pw_polyhull *h)
{
    long miss = 0;
    int x, y, k;
    for (y = 0; y < m->h; y++)
        for (x = 0; x < m->w; x++) {
            if (!(m->a[y * m->w + x] > 0)) continue;
            for (k = 0; k < 4; k++) {
                float u = (float)(x + (k & 1)) / (float)m->w, v = 1.0f - (float)(y + (k >> 1)) / (float)m->h;
                if (!pw_polyhull_contains(h, u, v)) miss++;
            }
        }
    return miss;
}

/* Distance from segment pq to the hull boundary (brute force). */
static double seg_boundary_dist(const pw_polyhull *h, const double *p, const double *q)
{
    double best = 1e30;
    int i;
    for (i = 0; i < h->n; i++) {
        double a[2], b[2], d2;
        vtx(h, i, a);
        vtx(h, i + 1, b);
        d2 = pw__hull_sseg2(p, q, a, b);
        if (d2 < best) best = d2;
    }
    return sqrt(best);
}

/* Brute force: does the segment pass through the hull? Splits it at every
 * crossing with an edge line and tests the pieces' midpoints and the ends. */
static int seg_brute(const pw_polyhull *h, const double *p, const double *q)
{
    double ts[130];
    int nt = 0, i, j;
    ts[nt++] = 0.0;
    ts[nt++] = 1.0;
    for (i = 0; i < h->n && nt < 128; i++) {
        double a[2], b[2], dx = q[0] - p[0], dy = q[1] - p[1], ex, ey, den, t;
        vtx(h, i, a);
        vtx(h, i + 1, b);
        ex = b[0] - a[0];
        ey = b[1] - a[1];
        den = dx * ey - dy * ex;
        if (den == 0) continue;
        t = ((a[0] - p[0]) * ey - (a[1] - p[1]) * ex) / den;
        if (t > 0 && t < 1) ts[nt++] = t;
    }
    for (i = 1; i < nt; i++) /* insertion sort */
        for (j = i; j > 0 && ts[j] < ts[j - 1]; j--) {
            double t = ts[j];
            ts[j] = ts[j - 1];
            ts[j - 1] = t;
        }
    for (i = 0; i < nt; i++) {
        double t = ts[i];
        if (inside_raw(h, p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1]))) return 1;
        if (i + 1 < nt) {
            t = 0.5 * (ts[i] + ts[i + 1]);
            if (inside_raw(h, p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1]))) return 1;
        }
    }
    return 0;
}

/* Brute force: area of the hull clipped by a triangle (Sutherland-Hodgman). */
static double clip_area(const pw_polyhull *h, const float *tri)
{
    static double bx[2][4096], by[2][4096];
    double t[6];
    int n = h->n, k, i, cur = 0;
    double s = 0;
    for (k = 0; k < 6; k++) t[k] = tri[k];
    if (orient(t[0], t[1], t[2], t[3], t[4], t[5]) < 0) { /* make it counter-clockwise */
        double x = t[2], y = t[3];
        t[2] = t[4], t[3] = t[5], t[4] = x, t[5] = y;
    }
    for (i = 0; i < n; i++) bx[0][i] = h->uv[2 * i], by[0][i] = h->uv[2 * i + 1];
    for (k = 0; k < 3 && n > 0; k++) {
        double ax = t[2 * k], ay = t[2 * k + 1], cx = t[(2 * k + 2) % 6], cy = t[(2 * k + 3) % 6];
        int m = 0;
        for (i = 0; i < n && m < 4000; i++) {
            int j = (i + 1) % n;
            double pi = orient(ax, ay, cx, cy, bx[cur][i], by[cur][i]);
            double pj = orient(ax, ay, cx, cy, bx[cur][j], by[cur][j]);
            if (pi >= 0) bx[!cur][m] = bx[cur][i], by[!cur][m++] = by[cur][i];
            if ((pi >= 0) != (pj >= 0)) {
                double f = pi / (pi - pj);
                bx[!cur][m] = bx[cur][i] + f * (bx[cur][j] - bx[cur][i]);
                by[!cur][m++] = by[cur][i] + f * (by[cur][j] - by[cur][i]);
            }
        }
        cur = !cur;
        n = m;
    }
    for (i = 0; i < n; i++) s += bx[cur][i] * by[cur][(i + 1) % n] - bx[cur][(i + 1) % n] * by[cur][i];
    return 0.5 * s;
}

/* Random segments and triangles near the hull: the queries agree with brute
 * force except within 1e-5 of the boundary. Returns disagreements. */
static int query_mismatches(const pw_polyhull *h, uint64_t seed, int *hits)
{
    pw_rng r = pw_rng_seed(seed, 9);
    int k, bad = 0;
    *hits = 0;
    for (k = 0; k < 2000; k++) {
        double p[2], q[2];
        float tri[6];
        int j, fast, slow;
        double len = k % 2 ? 0.05 : 0.4;
        p[0] = -0.2 + 1.4 * pw_rng_double(&r);
        p[1] = -0.2 + 1.4 * pw_rng_double(&r);
        q[0] = p[0] + len * (pw_rng_double(&r) - 0.5);
        q[1] = p[1] + len * (pw_rng_double(&r) - 0.5);
        p[0] = (float)p[0], p[1] = (float)p[1], q[0] = (float)q[0], q[1] = (float)q[1];
        fast = pw_polyhull_segment_hits(h, (float)p[0], (float)p[1], (float)q[0], (float)q[1]);
        slow = seg_brute(h, p, q);
        *hits += fast;
        if (fast != slow && seg_boundary_dist(h, p, q) > 1e-5) bad++;
        for (j = 0; j < 6; j++) tri[j] = (float)((j % 2 ? p[1] : p[0]) + len * (pw_rng_double(&r) - 0.5));
        fast = polyhull_triangle_hits(h, tri);
        slow = fabs(clip_area(h, tri)) > 1e-12;
        if (fast != slow) {
            double a[2], b[2], dmin = 1e30;
            for (j = 0; j < 3; j++) {
                double d;
                a[0] = tri[2 * j], a[1] = tri[2 * j + 1], b[0] = tri[(2 * j + 2) % 6], b[1] = tri[(2 * j + 3) % 6];
                d = seg_boundary_dist(h, a, b);
                dmin = d < dmin ? d : dmin;
            }
            if (dmin > 1e-5) bad++;
        }
    }
    return bad;
}

/* The complete property check of one mask; returns the hull's vertex count. */
static int check_mask(const char *name, const mask *m, int maxv, int quiet)
{
    pw_polyhull h;
    pw_err e;
    long miss, be = boundary_edges(m), area = mask_area(m);
    int bad, hits, nv, k, out_of_image = 0;
    double ha;
    pw_err_clear(&e);
    if (pw_polyhull_build(NULL, m->a, m->w, m->h, 1, maxv, &h, &e) != PW_OK) {
        CHECKF(0, "%s: build failed: %s", name, e.msg);
        return 0;
    }
    miss = uncovered(m, &h);
    CHECKF(miss == 0, "%s: %ld pixel corners outside the hull", name, miss);
    CHECKF(is_simple(&h), "%s: the hull intersects itself", name);
    ha = polyhull_area(&h);
    CHECKF(ha > 0, "%s: not counter-clockwise (area %g)", name, ha);
    CHECKF(h.n >= 3 && h.n <= (maxv ? maxv : 32) + 0, "%s: %d vertices", name, h.n);
    for (k = 0; k < 2 * h.n; k++) out_of_image += !(h.uv[k] >= 0.0f && h.uv[k] <= 1.0f);
    CHECKF(out_of_image == 0, "%s: %d coordinates outside the image", name, out_of_image);
    bad = query_mismatches(&h, (uint64_t)be, &hits);
    CHECKF(bad == 0, "%s: %d queries disagree with brute force", name, bad);
    if (!quiet)
        pwt_info("%s %dx%d: %ld boundary edges -> %d vertices; area %.4g px^2 vs %ld px (ratio %.3f); "
                 "%d/2000 segments hit", name, m->w, m->h, be, h.n, ha * m->w * m->h, area,
                 ha * m->w * m->h / (double)area, hits);
    nv = h.n;
    pw_polyhull_free(NULL, &h);
    return nv;
}

/* Vertex count of the unsimplified rectilinear polygon (only free
 * collapses run with an unreachable target). */
static int corners(const mask *m)
{
    pw_polyhull h;
    int n;
    if (pw_polyhull_build(NULL, m->a, m->w, m->h, 1, 1 << 30, &h, NULL) != PW_OK) return -1;
    n = h.n;
    CHECK(is_simple(&h));
    CHECK(uncovered(m, &h) == 0);
    CHECK_NEAR(polyhull_area(&h) * m->w * m->h, (double)mask_area(m), 1e-3 * mask_area(m) + 1e-6);
    pw_polyhull_free(NULL, &h);
    return n;
}

/* ------------------------------------------------------------ cases */

static void t_circle(void)
{
    mask m;
    int r[3] = {5, 40, 120}, k;
    for (k = 0; k < 3; k++) {
        char name[32];
        int c;
        REQUIRE(mask_new(&m, 2 * r[k] + 6, 2 * r[k] + 6));
        disc(&m, (float)m.w / 2, (float)m.h / 2, (float)r[k], 1.0f);
        c = corners(&m);
        snprintf(name, sizeof name, "circle r=%d (%d corners)", r[k], c);
        check_mask(name, &m, 0, 0);
        if (k == 1 || k == 2) {
            pw_polyhull h;
            REQUIRE(pw_polyhull_build(NULL, m.a, m.w, m.h, 1, 0, &h, NULL) == PW_OK);
            CHECKF(polyhull_area(&h) * m.w * m.h < 1.04 * mask_area(&m), "circle r=%d: the 32-gon adds %.1f%%",
                   r[k], 100 * (polyhull_area(&h) * m.w * m.h / mask_area(&m) - 1));
            pw_polyhull_free(NULL, &h);
        }
        if (k == 2) { /* a circle needs few vertices, and more allow a tighter fit */
            pw_polyhull h8, h64;
            REQUIRE(pw_polyhull_build(NULL, m.a, m.w, m.h, 1, 8, &h8, NULL) == PW_OK);
            REQUIRE(pw_polyhull_build(NULL, m.a, m.w, m.h, 1, 64, &h64, NULL) == PW_OK);
            CHECK(h8.n <= 8 && h64.n <= 64);
            CHECK(polyhull_area(&h64) < polyhull_area(&h8));
            CHECK(uncovered(&m, &h8) == 0 && uncovered(&m, &h64) == 0);
            pwt_info("circle r=120: area ratio %.4f with 8 vertices, %.4f with 64",
                     polyhull_area(&h8) * m.w * m.h / mask_area(&m),
                     polyhull_area(&h64) * m.w * m.h / mask_area(&m));
            pw_polyhull_free(NULL, &h8);
            pw_polyhull_free(NULL, &h64);
        }
        free(m.a);
    }
}

static void t_splotch(void)
{
    mask m;
    int k;
    for (k = 0; k < 6; k++) {
        char name[48];
        REQUIRE(mask_new(&m, 64 + 37 * k, 48 + 53 * k));
        splotch(&m, (uint64_t)k);
        snprintf(name, sizeof name, "splotch %d (%d corners)", k, corners(&m));
        check_mask(name, &m, k == 5 ? 12 : 0, k > 2);
        free(m.a);
    }
}

static void t_blobs(void)
{
    mask m;
    int k, worst = 0;
    for (k = 0; k < 40; k++) {
        char name[48];
        int n;
        REQUIRE(mask_new(&m, 20 + 7 * k, 30 + 5 * k));
        blobs(&m, (uint64_t)k, 1 + k % 7, k % 3 == 0 ? 0.0f : 0.01f * (float)(k % 4));
        if (mask_area(&m) == 0) m.a[0] = 1;
        snprintf(name, sizeof name, "blobs %d", k);
        n = check_mask(name, &m, k % 5 == 0 ? 6 : 0, k != 39);
        worst = n > worst ? n : worst;
        free(m.a);
    }
    pwt_info("40 random masks (holes, specks, several components): at most %d vertices", worst);
}

static void t_components(void)
{
    mask m;
    REQUIRE(mask_new(&m, 200, 120));
    disc(&m, 30, 30, 20, 1);
    disc(&m, 160, 40, 15, 1);
    disc(&m, 100, 100, 10, 1);
    m.a[5 * 200 + 190] = 1; /* a lone speck */
    m.a[119 * 200 + 0] = 1; /* and one in a corner */
    check_mask("four separate components", &m, 0, 0);
    memset(m.a, 0, sizeof(float) * 200 * 120);
    disc(&m, 100, 60, 50, 1); /* a ring with an island inside */
    disc(&m, 100, 60, 40, 0);
    disc(&m, 100, 60, 10, 1);
    check_mask("ring with island", &m, 0, 0);
    memset(m.a, 0, sizeof(float) * 200 * 120);
    {
        int x, y; /* checkerboard: every pixel its own 4-component */
        for (y = 40; y < 80; y++)
            for (x = 60; x < 140; x++) m.a[y * 200 + x] = (float)((x + y) & 1);
    }
    check_mask("checkerboard", &m, 0, 0);
    free(m.a);
}

static void t_border(void)
{
    mask m;
    int x, y;
    REQUIRE(mask_new(&m, 90, 70));
    for (y = 0; y < 70; y++)
        for (x = 0; x < 90; x++) m.a[y * 90 + x] = 1; /* everything */
    CHECK(check_mask("full image", &m, 0, 0) == 4);
    memset(m.a, 0, sizeof(float) * 90 * 70);
    disc(&m, 0, 0, 40, 1);   /* quarter disc in a corner */
    disc(&m, 90, 35, 20, 1); /* half disc on the right */
    for (x = 0; x < 90; x++) m.a[69 * 90 + x] = 1; /* the bottom row */
    check_mask("touching the border", &m, 0, 0);
    free(m.a);
}

static void t_tiny(void)
{
    mask m;
    pw_polyhull h;
    REQUIRE(mask_new(&m, 1, 1));
    m.a[0] = 0.5f;
    CHECK(check_mask("1x1 image", &m, 0, 0) == 4);
    free(m.a);
    REQUIRE(mask_new(&m, 9, 7));
    m.a[3 * 9 + 4] = 1e-30f;
    CHECK(check_mask("single pixel", &m, 0, 0) == 4);
    REQUIRE(pw_polyhull_build(NULL, m.a, 9, 7, 1, 0, &h, NULL) == PW_OK);
    CHECK_NEAR(polyhull_area(&h), 1.0 / 63, 1e-7);
    CHECK(pw_polyhull_contains(&h, 4.5f / 9, 1 - 3.5f / 7));
    CHECK(!pw_polyhull_contains(&h, 2.5f / 9, 1 - 3.5f / 7));
    CHECK(pw_polyhull_segment_hits(&h, 0.0f, 1 - 3.5f / 7, 1.0f, 1 - 3.5f / 7));
    CHECK(!pw_polyhull_segment_hits(&h, 0.0f, 0.1f, 1.0f, 0.1f));
    pw_polyhull_free(NULL, &h);
    free(m.a);
}

static void t_errors(void)
{
    float a[12] = {0};
    pw_polyhull h;
    pw_err e;
    pw_err_clear(&e);
    CHECK(pw_polyhull_build(NULL, a, 3, 4, 1, 0, &h, &e) == PW_ERR_INVALID);
    CHECK(strstr(e.msg, "fully transparent") != NULL);
    CHECK(h.n == 0 && h.uv == NULL);
    pw_err_clear(&e);
    CHECK(pw_polyhull_build(NULL, NULL, 3, 4, 1, 0, &h, &e) == PW_ERR_INVALID);
    a[5] = 1;
    pw_err_clear(&e);
    CHECK(pw_polyhull_build(NULL, a, 3, 4, 1, 2, &h, &e) == PW_ERR_INVALID);
    CHECK(pw_polyhull_build(NULL, a, 0, 4, 1, 0, &h, NULL) == PW_ERR_INVALID);
    CHECK(pw_polyhull_build(NULL, a, 3, 4, 0, 0, &h, NULL) == PW_ERR_INVALID);
    CHECK(pw_polyhull_build(NULL, a, 3, 4, 1, 3, &h, NULL) == PW_OK);
    CHECK(h.n == 4); /* a square cannot become a triangle by outward collapses */
    pw_polyhull_free(NULL, &h);
    pw_polyhull_free(NULL, &h); /* twice is fine */
    CHECK(!pw_polyhull_contains(&h, 0, 0));
    CHECK(!pw_polyhull_segment_hits(NULL, 0, 0, 1, 1));
}

static void t_stride_and_nan(void)
{
    /* RGBA with alpha in channel 3; NaN alpha counts as transparent */
    float px[8 * 6 * 4];
    pw_polyhull h;
    int i;
    for (i = 0; i < 8 * 6; i++) {
        px[4 * i] = px[4 * i + 1] = px[4 * i + 2] = 1.0f; /* opaque colour everywhere */
        px[4 * i + 3] = 0.0f;
    }
    px[4 * (2 * 8 + 3) + 3] = 1.0f;
    px[4 * (3 * 8 + 3) + 3] = 0.5f;
    px[4 * (4 * 8 + 5) + 3] = (float)sqrt(-1.0);
    REQUIRE(pw_polyhull_build(NULL, px + 3, 8, 6, 4, 0, &h, NULL) == PW_OK);
    CHECK(h.n == 4);
    CHECK_NEAR(polyhull_area(&h), 2.0 / 48, 1e-7);
    pw_polyhull_free(NULL, &h);
}

static void t_allocator(void)
{
    mask m;
    pwt_alloc_state st = {0, 0, -1};
    pw_alloc al;
    pw_polyhull h;
    long total, k;
    al.malloc_fn = pwt_malloc;
    al.realloc_fn = pwt_realloc;
    al.free_fn = pwt_free;
    al.user = &st;
    REQUIRE(mask_new(&m, 120, 100));
    blobs(&m, 3, 4, 0.0f);
    REQUIRE(pw_polyhull_build(&al, m.a, m.w, m.h, 1, 0, &h, NULL) == PW_OK);
    pw_polyhull_free(&al, &h);
    CHECK(st.live == 0);
    total = st.calls;
    for (k = 0; k < total; k++) { /* every allocation failing in turn */
        pw_err e;
        int r;
        st.calls = 0;
        st.fail_after = k;
        pw_err_clear(&e);
        r = pw_polyhull_build(&al, m.a, m.w, m.h, 1, 0, &h, &e);
        CHECKF(r == PW_ERR_NOMEM && h.uv == NULL, "failure at call %ld: result %d", k, r);
        CHECKF(st.live == 0, "leak after failure at call %ld", k);
    }
    pwt_info("%ld allocations, each made to fail in turn", total);
    free(m.a);
}

static double seconds(void) { return (double)clock() / CLOCKS_PER_SEC; }

static void t_speed(void)
{
    int sizes[3] = {128, 256, 512}, k, rep;
    for (k = 0; k < 3; k++) {
        mask m;
        pw_polyhull h;
        double t0, best = 1e9;
        int s = sizes[k], c;
        REQUIRE(mask_new(&m, s, s));
        splotch(&m, 11);
        c = corners(&m);
        for (rep = 0; rep < 5; rep++) {
            t0 = seconds();
            REQUIRE(pw_polyhull_build(NULL, m.a, s, s, 1, 0, &h, NULL) == PW_OK);
            t0 = seconds() - t0;
            best = t0 < best ? t0 : best;
            if (rep < 4) pw_polyhull_free(NULL, &h);
        }
        CHECKF(best < 0.1, "%dx%d took %.1f ms", s, s, best * 1e3);
        CHECK(polyhull_area(&h) * s * s < 1.05 * mask_area(&m)); /* a tight 32-gon */
        pwt_info("splotch %dx%d: %ld boundary edges, %d corners -> %d vertices in %.2f ms (best of 5), "
                 "area ratio %.3f", s, s, boundary_edges(&m), c, h.n, best * 1e3,
                 polyhull_area(&h) * s * s / mask_area(&m));
        pw_polyhull_free(NULL, &h);
        free(m.a);
    }
    { /* a ragged 512 mask: many components and holes */
        mask m;
        pw_polyhull h;
        double t0;
        REQUIRE(mask_new(&m, 512, 512));
        blobs(&m, 99, 30, 0.02f);
        t0 = seconds();
        REQUIRE(pw_polyhull_build(NULL, m.a, 512, 512, 1, 0, &h, NULL) == PW_OK);
        t0 = seconds() - t0;
        CHECKF(t0 < 0.5, "ragged 512x512 took %.1f ms", t0 * 1e3);
        pwt_info("ragged 512x512 (salt noise, many components): %d vertices in %.2f ms", h.n, t0 * 1e3);
        CHECK(uncovered(&m, &h) == 0);
        pw_polyhull_free(NULL, &h);
        free(m.a);
    }
}

/* A real GIMP pattern: its dark spots (luminance below 0.35) as the mask. */
static void t_leopard(void)
{
    const char *path = pwt_data("textures/leopard.ppm");
    unsigned char *data;
    size_t size;
    pw_image img;
    mask m;
    int i;
    if (!path) return;
    REQUIRE(pw_read_file(NULL, path, &data, &size, NULL) == PW_OK);
    REQUIRE(pw_image_read_pnm_memory(NULL, data, size, path, &img, NULL) == PW_OK);
    free(data);
    REQUIRE(mask_new(&m, img.w, img.h));
    for (i = 0; i < img.w * img.h; i++) {
        const float *p = img.px + (size_t)i * img.c;
        float lum = img.c >= 3 ? 0.299f * p[0] + 0.587f * p[1] + 0.114f * p[2] : p[0];
        m.a[i] = lum < 0.35f ? 1.0f : 0.0f;
    }
    check_mask("leopard.ppm dark spots", &m, 0, 0);
    check_mask("leopard.ppm dark spots, 100 vertices", &m, 100, 0);
    pw_image_free(NULL, &img);
    free(m.a);
}

static const pwt_case cases[] = {
    {"circle", t_circle},       {"splotch", t_splotch},   {"blobs", t_blobs},
    {"components", t_components}, {"border", t_border},   {"tiny", t_tiny},
    {"errors", t_errors},       {"stride_nan", t_stride_and_nan}, {"allocator", t_allocator},
    {"speed", t_speed},         {"leopard", t_leopard},
};
PWT_MAIN(cases)
