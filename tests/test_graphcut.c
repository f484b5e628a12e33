/* Tests of src/common/graphcut.h: Boykov-Kolmogorov max-flow checked
 * against an Edmonds-Karp reference written here, on random graphs, grids
 * and image-quilting seams whose answer is known. */
#include "../src/common/graphcut.h"
#include "../src/common/rng.h"
#include "pwtest.h"

/* ---- reference: Edmonds-Karp on a dense capacity matrix ----------------- */

/* Nodes 0..n-1 of the graph plus S = n and T = n + 1. */
typedef struct ref_graph {
    int n, nn;   /* graph nodes, nn = n + 2 */
    double *cap; /* nn*nn original capacities */
    double *res; /* nn*nn residual capacities */
    int *queue, *prev;
} ref_graph;

static void ref_init(ref_graph *r, int n)
{
    r->n = n;
    r->nn = n + 2;
    r->cap = (double *)calloc((size_t)r->nn * r->nn, sizeof(double));
    r->res = (double *)calloc((size_t)r->nn * r->nn, sizeof(double));
    r->queue = (int *)malloc(sizeof(int) * (size_t)r->nn);
    r->prev = (int *)malloc(sizeof(int) * (size_t)r->nn);
}

static void ref_free(ref_graph *r)
{
    free(r->cap);
    free(r->res);
    free(r->queue);
    free(r->prev);
}

static void ref_add(ref_graph *r, int i, int j, double c) { r->cap[i * r->nn + j] += c; }

/* BFS in the residual graph from S; prev[] = -1 for unreached nodes. */
static int ref_bfs(ref_graph *r)
{
    int head = 0, tail = 0, i, j, s = r->n, nn = r->nn;
    for (i = 0; i < nn; i++) r->prev[i] = -1;
    r->prev[s] = s;
    r->queue[tail++] = s;
    while (head < tail) {
        i = r->queue[head++];
        for (j = 0; j < nn; j++)
            if (r->prev[j] < 0 && r->res[i * nn + j] > 0) {
                r->prev[j] = i;
                r->queue[tail++] = j;
            }
    }
    return r->prev[r->n + 1] >= 0;
}

static double ref_maxflow(ref_graph *r)
{
    int nn = r->nn, t = r->n + 1, v;
    double flow = 0;
    memcpy(r->res, r->cap, sizeof(double) * (size_t)nn * nn);
    while (ref_bfs(r)) {
        double bn = HUGE_VAL;
        for (v = t; v != r->n; v = r->prev[v])
            if (r->res[r->prev[v] * nn + v] < bn) bn = r->res[r->prev[v] * nn + v];
        for (v = t; v != r->n; v = r->prev[v]) {
            r->res[r->prev[v] * nn + v] -= bn;
            r->res[v * nn + r->prev[v]] += bn;
        }
        flow += bn;
    }
    ref_bfs(r); /* leaves prev[] marking the source side of the minimal cut */
    return flow;
}

/* Capacity of the cut whose source side is given by pw_graph_in_source. */
static double cut_capacity(const ref_graph *r, const pw_graph *g)
{
    int i, j, nn = r->nn;
    double c = 0;
    for (i = 0; i < nn; i++)
        for (j = 0; j < nn; j++) {
            int si = i == r->n || (i < r->n && pw_graph_in_source(g, i));
            int sj = j == r->n || (j < r->n && pw_graph_in_source(g, j));
            if (si && !sj) c += r->cap[i * nn + j];
        }
    return c;
}

/* ---- graph builders ----------------------------------------------------- */

/* Adds an edge to both graphs. */
static void both_edge(pw_graph *g, ref_graph *r, int i, int j, double cij, double cji)
{
    pw_err e;
    pw_err_clear(&e);
    if (pw_graph_add_edge(g, i, j, cij, cji, &e) == PW_OK) {
        ref_add(r, i, j, cij);
        ref_add(r, j, i, cji);
    }
}

static void both_tweights(pw_graph *g, ref_graph *r, int i, double cs, double ct)
{
    if (pw_graph_add_tweights(g, i, cs, ct) == PW_OK) {
        ref_add(r, r->n, i, cs);
        ref_add(r, i, r->n + 1, ct);
    }
}

/* Integer capacity in 0..9, zero with probability 1/4. */
static double small_cap(pw_rng *rng)
{
    return pw_rng_below(rng, 4) == 0 ? 0.0 : (double)pw_rng_below(rng, 10);
}

/* A random graph with parallel edges, zero capacities, isolated nodes and
 * repeated, sometimes two-sided, terminal weights. */
static void random_graph(pw_graph *g, ref_graph *r, int n, pw_rng *rng)
{
    int k, edges = (int)pw_rng_below(rng, (uint32_t)(3 * n + 1));
    pw_err e;
    pw_err_clear(&e);
    pw_graph_init(g, NULL, n, 2, &e);
    ref_init(r, n);
    for (k = 0; k < edges && n > 1; k++) {
        int i = (int)pw_rng_below(rng, (uint32_t)n), j = (int)pw_rng_below(rng, (uint32_t)n);
        if (i != j) both_edge(g, r, i, j, small_cap(rng), small_cap(rng));
    }
    for (k = 0; k < n; k++) {
        int reps = (int)pw_rng_below(rng, 3), q;
        for (q = 0; q < reps; q++) both_tweights(g, r, k, small_cap(rng), small_cap(rng));
    }
}

/* A w x h 4-connected grid with random capacities (integers or not) and
 * terminal weights on a random subset of nodes. */
static void random_grid(pw_graph *g, ref_graph *r, int w, int h, int integer, pw_rng *rng)
{
    int x, y;
    pw_err e;
    pw_err_clear(&e);
    pw_graph_init(g, NULL, w * h, 2 * w * h, &e);
    if (r) ref_init(r, w * h);
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            int i = y * w + x;
            double c1 = integer ? small_cap(rng) : 10 * pw_rng_double(rng);
            double c2 = integer ? small_cap(rng) : 10 * pw_rng_double(rng);
            if (x + 1 < w) {
                if (r) both_edge(g, r, i, i + 1, c1, c1);
                else pw_graph_add_edge(g, i, i + 1, c1, c1, &e);
            }
            if (y + 1 < h) {
                if (r) both_edge(g, r, i, i + w, c2, c2 + 1);
                else pw_graph_add_edge(g, i, i + w, c2, c2 + 1, &e);
            }
            if (pw_rng_below(rng, 4) == 0) {
                double cs = integer ? small_cap(rng) * 3 : 30 * pw_rng_double(rng);
                double ct = integer ? small_cap(rng) * 3 : 30 * pw_rng_double(rng);
                if (r) both_tweights(g, r, i, cs, ct);
                else pw_graph_add_tweights(g, i, cs, ct);
            }
        }
}

/* Compares flow, cut capacity and the cut itself (the minimal source set is
 * unique, so BK's and the reference's must agree node for node). */
static void check_against_ref(pw_graph *g, ref_graph *r, double tol, const char *what)
{
    double flow, ref = ref_maxflow(r), cut;
    int i, diff = 0;
    pw_err e;
    pw_err_clear(&e);
    CHECKF(pw_graph_maxflow(g, &flow, &e) == PW_OK, "%s: %s", what, e.msg);
    cut = cut_capacity(r, g);
    CHECKF(fabs(flow - ref) <= tol, "%s: flow %.17g, reference %.17g", what, flow, ref);
    CHECKF(fabs(cut - flow) <= tol, "%s: cut %.17g, flow %.17g", what, cut, flow);
    if (tol == 0)
        for (i = 0; i < r->n; i++) diff += pw_graph_in_source(g, i) != (r->prev[i] >= 0);
    CHECKF(diff == 0, "%s: %d nodes on a different side", what, diff);
}

/* ---- cases -------------------------------------------------------------- */

static void t_random_small_graphs(void)
{
    pw_rng rng = pw_rng_seed(2024, 1);
    int k, nonzero = 0;
    for (k = 0; k < 600 && !pwt_failed_; k++) {
        pw_graph g;
        ref_graph r;
        char what[32];
        /* mostly tiny graphs, then some denser ones with longer adoptions */
        int n = k < 450 ? 1 + (int)pw_rng_below(&rng, 14) : 15 + (int)pw_rng_below(&rng, 30);
        random_graph(&g, &r, n, &rng);
        snprintf(what, sizeof what, "graph %d (n=%d)", k, n);
        check_against_ref(&g, &r, 0, what);
        nonzero += g.flow > 0;
        pw_graph_free(&g);
        ref_free(&r);
    }
    CHECK(nonzero > 300); /* the generator makes interesting graphs */
}

static void t_random_grids(void)
{
    pw_rng rng = pw_rng_seed(77, 2);
    int k;
    for (k = 0; k < 60 && !pwt_failed_; k++) {
        pw_graph g;
        ref_graph r;
        char what[48];
        int w = 2 + (int)pw_rng_below(&rng, 11), h = 2 + (int)pw_rng_below(&rng, 11);
        int integer = k % 2 == 0;
        random_grid(&g, &r, w, h, integer, &rng);
        snprintf(what, sizeof what, "grid %d (%dx%d, %s)", k, w, h, integer ? "int" : "real");
        check_against_ref(&g, &r, integer ? 0 : 1e-9, what);
        pw_graph_free(&g);
        ref_free(&r);
    }
}

/* Image-quilting seam (Kwatra et al. 2003): old patch A and new patch B
 * overlap on a w x h region; the left column must come from A (infinite
 * source link), the right one from B (infinite sink link). A is random
 * two-colour noise and B equals A on columns c and c+1 only, so the seam
 * cost M(s,t) = |A(s)-B(s)| + |A(t)-B(t)| (scaled by 10, plus 1 so that
 * every link costs something) is smallest, 1, between columns c and c+1:
 * the one minimum cut is the straight seam there, of capacity h. */
static void t_straight_seam(void)
{
    int w = 24, h = 17, c, x, y;
    pw_rng rng = pw_rng_seed(5, 5);
    unsigned char A[17][24], B[17][24];
    for (c = 1; c < w - 2; c += 4) {
        pw_graph g;
        double flow;
        int wrong = 0;
        pw_err e;
        pw_err_clear(&e);
        for (y = 0; y < h; y++)
            for (x = 0; x < w; x++) {
                A[y][x] = (unsigned char)pw_rng_below(&rng, 2);
                B[y][x] = (unsigned char)(x == c || x == c + 1 ? A[y][x] : 1 - A[y][x]);
            }
        REQUIRE(pw_graph_init(&g, NULL, w * h, 2 * w * h, &e) == PW_OK);
        for (y = 0; y < h; y++)
            for (x = 0; x < w; x++) {
                int i = y * w + x;
                double d = A[y][x] != B[y][x];
                if (x + 1 < w) {
                    double m = 10 * (d + (A[y][x + 1] != B[y][x + 1])) + 1;
                    pw_graph_add_edge(&g, i, i + 1, m, m, &e);
                }
                if (y + 1 < h) {
                    double m = 10 * (d + (A[y + 1][x] != B[y + 1][x])) + 1;
                    pw_graph_add_edge(&g, i, i + w, m, m, &e);
                }
            }
        for (y = 0; y < h; y++) {
            pw_graph_add_tweights(&g, y * w, HUGE_VAL, 0);
            pw_graph_add_tweights(&g, y * w + w - 1, 0, HUGE_VAL);
        }
        REQUIRE(e.code == PW_OK);
        CHECKF(pw_graph_maxflow(&g, &flow, &e) == PW_OK, "%s", e.msg);
        CHECKF(flow == h, "seam at %d: flow %g", c, flow);
        for (y = 0; y < h; y++)
            for (x = 0; x < w; x++) wrong += pw_graph_in_source(&g, y * w + x) != (x <= c);
        CHECKF(wrong == 0, "seam at %d: %d pixels on the wrong side", c, wrong);
        pw_graph_free(&g);
    }
}

/* Hard constraints on both sides of a uniform grid: a small square of
 * pixels forced to the sink in the middle of a field forced to the source
 * along the border. With uniform costs the cheapest closed seam hugs the
 * square, so the flow is the square's perimeter. */
static void t_enclosed_region(void)
{
    int w = 20, h = 20, x, y, wrong = 0;
    pw_graph g;
    double flow;
    pw_err e;
    pw_err_clear(&e);
    REQUIRE(pw_graph_init(&g, NULL, w * h, 0, &e) == PW_OK);
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            int i = y * w + x, inside = x >= 8 && x < 12 && y >= 7 && y < 10;
            if (x + 1 < w) pw_graph_add_edge(&g, i, i + 1, 1, 1, &e);
            if (y + 1 < h) pw_graph_add_edge(&g, i, i + w, 1, 1, &e);
            if (inside) pw_graph_add_tweights(&g, i, 0, HUGE_VAL);
            if (x == 0 || y == 0 || x == w - 1 || y == h - 1)
                pw_graph_add_tweights(&g, i, HUGE_VAL, 0);
        }
    CHECKF(pw_graph_maxflow(&g, &flow, &e) == PW_OK, "%s", e.msg);
    CHECKF(flow == 2 * (4 + 3), "flow %g", flow);
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            int inside = x >= 8 && x < 12 && y >= 7 && y < 10;
            wrong += pw_graph_in_source(&g, y * w + x) == inside;
        }
    CHECK_EQ_INT(wrong, 0);
    pw_graph_free(&g);
}

static void t_zero_and_isolated(void)
{
    pw_graph g;
    double flow;
    pw_err e;
    pw_err_clear(&e);
    /* 0: source only; 1: sink only; 2: isolated; 3: joined to 0 by a zero
     * edge; 4: joined to 0 with capacity only towards 0; 5: zero t-links */
    REQUIRE(pw_graph_init(&g, NULL, 6, 0, &e) == PW_OK);
    pw_graph_add_tweights(&g, 0, 5, 0);
    pw_graph_add_tweights(&g, 1, 0, 5);
    pw_graph_add_edge(&g, 0, 3, 0, 0, &e);
    pw_graph_add_edge(&g, 4, 0, 7, 0, &e);
    pw_graph_add_tweights(&g, 5, 0, 0);
    REQUIRE(pw_graph_maxflow(&g, &flow, &e) == PW_OK);
    CHECK(flow == 0);
    CHECK(pw_graph_in_source(&g, 0));
    CHECK(!pw_graph_in_source(&g, 1));
    CHECK(!pw_graph_in_source(&g, 2));
    CHECK(!pw_graph_in_source(&g, 3));
    CHECK(!pw_graph_in_source(&g, 4));
    CHECK(!pw_graph_in_source(&g, 5));
    CHECK(!pw_graph_in_source(&g, -1));
    CHECK(!pw_graph_in_source(&g, 6));
    pw_graph_free(&g);
    /* an empty graph */
    REQUIRE(pw_graph_init(&g, NULL, 0, 0, &e) == PW_OK);
    CHECK(pw_graph_maxflow(&g, &flow, &e) == PW_OK);
    CHECK(flow == 0);
    pw_graph_free(&g);
}

/* Both t-links positive: the common part is flow at once; accumulation
 * over several calls nets out. */
static void t_tweights_common_part(void)
{
    pw_graph g;
    double flow;
    pw_err e;
    pw_err_clear(&e);
    REQUIRE(pw_graph_init(&g, NULL, 2, 1, &e) == PW_OK);
    pw_graph_add_tweights(&g, 0, 5, 3);  /* net +2, flow 3 */
    pw_graph_add_tweights(&g, 0, 1, 4);  /* net -1, flow 3 + 3 */
    pw_graph_add_tweights(&g, 1, 10, 0); /* net +10 */
    pw_graph_add_edge(&g, 1, 0, 0.5, 0, &e);
    REQUIRE(pw_graph_maxflow(&g, &flow, &e) == PW_OK);
    CHECK(flow == 6.5);
    CHECK(!pw_graph_in_source(&g, 0)); /* its source link carries common flow */
    CHECK(pw_graph_in_source(&g, 1));
    /* a second call continues from the residual graph: nothing left */
    REQUIRE(pw_graph_maxflow(&g, &flow, &e) == PW_OK);
    CHECK(flow == 6.5);
    /* capacity added afterwards is picked up */
    pw_graph_add_edge(&g, 1, 0, 3, 0, &e);
    REQUIRE(pw_graph_maxflow(&g, &flow, &e) == PW_OK);
    CHECK(flow == 7); /* node 0 had 0.5 left towards the sink */
    CHECK(pw_graph_in_source(&g, 0));
    pw_graph_add_tweights(&g, 0, 0, 4);
    REQUIRE(pw_graph_maxflow(&g, &flow, &e) == PW_OK);
    CHECK(flow == 9.5); /* the new edge's remaining 2.5 */
    CHECK(!pw_graph_in_source(&g, 0));
    pw_graph_free(&g);
}

/* Resets g to the chain source -> 0 -> 1 -> 2 -> sink: infinite terminal
 * links and edge 0->1, edge 1->2 of capacities `fwd` and `rev`. */
static int infinite_chain(pw_graph *g, double fwd, double rev, pw_err *e)
{
    int rc;
    pw_err_clear(e);
    if ((rc = pw_graph_reset(g, 3, e)) != PW_OK) return rc;
    pw_graph_add_tweights(g, 0, HUGE_VAL, 0);
    pw_graph_add_tweights(g, 2, 0, HUGE_VAL);
    pw_graph_add_edge(g, 0, 1, HUGE_VAL, 0, e);
    pw_graph_add_edge(g, 1, 2, fwd, rev, e);
    return PW_OK;
}

static void t_invalid_input(void)
{
    pw_graph g;
    double flow;
    pw_err e;
    pw_err_clear(&e);
    CHECK(pw_graph_init(&g, NULL, -3, 0, &e) == PW_ERR_INVALID);
    pw_err_clear(&e);
    REQUIRE(pw_graph_init(&g, NULL, 4, 0, &e) == PW_OK);
    CHECK(pw_graph_add_edge(&g, 0, 4, 1, 1, &e) == PW_ERR_INVALID);
    CHECKF(strstr(e.msg, "(0, 4)") != NULL, "message: %s", e.msg);
    pw_err_clear(&e);
    CHECK(pw_graph_add_edge(&g, 2, 2, 1, 1, &e) == PW_ERR_INVALID);
    pw_err_clear(&e);
    CHECK(pw_graph_add_edge(&g, 0, 1, -1, 1, &e) == PW_ERR_INVALID);
    pw_err_clear(&e);
    CHECK(pw_graph_add_edge(&g, 0, 1, 1, sqrt(-1.0), &e) == PW_ERR_INVALID);
    CHECK(pw_graph_add_tweights(&g, 9, 1, 1) == PW_ERR_INVALID);
    CHECK(pw_graph_add_tweights(&g, 1, -2, 1) == PW_ERR_INVALID);
    CHECK(pw_graph_add_tweights(&g, 1, HUGE_VAL, 0) == PW_OK);
    CHECK(pw_graph_add_tweights(&g, 1, 0, HUGE_VAL) == PW_ERR_INVALID);
    /* the first bad call is reported again by maxflow */
    pw_err_clear(&e);
    CHECK(pw_graph_maxflow(&g, &flow, &e) == PW_ERR_INVALID);
    CHECKF(strstr(e.msg, "(0, 4)") != NULL, "message: %s", e.msg);
    /* reset forgets it */
    REQUIRE(infinite_chain(&g, HUGE_VAL, 3, &e) == PW_OK);
    REQUIRE(e.code == PW_OK);
    CHECK(pw_graph_maxflow(&g, &flow, &e) == PW_ERR_INVALID); /* unbounded */
    CHECKF(strstr(e.msg, "infinite") != NULL, "message: %s", e.msg);
    /* an infinite edge in the other direction is fine */
    REQUIRE(infinite_chain(&g, 3, HUGE_VAL, &e) == PW_OK);
    CHECK(pw_graph_maxflow(&g, &flow, &e) == PW_OK);
    CHECK(flow == 3);
    CHECK(pw_graph_in_source(&g, 1));
    pw_graph_free(&g);
}

/* Same input, same flow to the bit and same cut, also after a reset that
 * reuses the memory. */
static void t_determinism(void)
{
    pw_graph g1, g2;
    pw_rng r1 = pw_rng_seed(42, 9), r2 = pw_rng_seed(42, 9), r3 = pw_rng_seed(42, 9);
    double f1, f2, f3;
    int i, diff = 0, diff3 = 0, n = 80 * 60;
    pw_err e;
    pw_err_clear(&e);
    random_grid(&g1, NULL, 80, 60, 0, &r1);
    random_grid(&g2, NULL, 80, 60, 0, &r2);
    REQUIRE(pw_graph_maxflow(&g1, &f1, &e) == PW_OK);
    REQUIRE(pw_graph_maxflow(&g2, &f2, &e) == PW_OK);
    CHECK(memcmp(&f1, &f2, sizeof f1) == 0);
    for (i = 0; i < n; i++) diff += pw_graph_in_source(&g1, i) != pw_graph_in_source(&g2, i);
    CHECK_EQ_INT(diff, 0);
    /* rebuild g2 in place through reset */
    REQUIRE(pw_graph_reset(&g2, n, &e) == PW_OK);
    {
        pw_graph tmp;
        random_grid(&tmp, NULL, 80, 60, 0, &r3); /* the same calls, replayed into g2 */
        for (i = 0; i < tmp.narcs; i += 2) {
            int a = tmp.arcs[i + 1].head, b = tmp.arcs[i].head;
            pw_graph_add_edge(&g2, a, b, tmp.arcs[i].rcap, tmp.arcs[i + 1].rcap, &e);
        }
        for (i = 0; i < n; i++)
            if (tmp.nodes[i].tr != 0)
                pw_graph_add_tweights(&g2, i, tmp.nodes[i].tr > 0 ? tmp.nodes[i].tr : 0,
                                      tmp.nodes[i].tr < 0 ? -tmp.nodes[i].tr : 0);
        g2.flow += tmp.flow; /* the common t-link parts */
        pw_graph_free(&tmp);
    }
    REQUIRE(pw_graph_maxflow(&g2, &f3, &e) == PW_OK);
    CHECKF(f3 == f1, "%.17g vs %.17g", f3, f1);
    for (i = 0; i < n; i++) diff3 += pw_graph_in_source(&g1, i) != pw_graph_in_source(&g2, i);
    CHECK_EQ_INT(diff3, 0);
    pw_graph_free(&g1);
    pw_graph_free(&g2);
}

/* A seam-sized grid: the cut found has the capacity of the flow. */
static void t_large_grid_cut(void)
{
    int w = 300, h = 200, x, y, i;
    pw_graph g;
    pw_rng rng = pw_rng_seed(8, 8);
    float *hc = (float *)malloc(sizeof(float) * (size_t)(w * h));
    float *vc = (float *)malloc(sizeof(float) * (size_t)(w * h));
    double flow, cut = 0;
    pw_err e;
    pw_err_clear(&e);
    REQUIRE(pw_graph_init(&g, NULL, w * h, 2 * w * h, &e) == PW_OK);
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            i = y * w + x;
            hc[i] = (float)(pw_rng_double(&rng) + 0.01);
            vc[i] = (float)(pw_rng_double(&rng) + 0.01);
            if (x + 1 < w) pw_graph_add_edge(&g, i, i + 1, hc[i], hc[i], &e);
            if (y + 1 < h) pw_graph_add_edge(&g, i, i + w, vc[i], vc[i], &e);
        }
    for (y = 0; y < h; y++) {
        pw_graph_add_tweights(&g, y * w, HUGE_VAL, 0);
        pw_graph_add_tweights(&g, y * w + w - 1, 0, HUGE_VAL);
    }
    REQUIRE(pw_graph_maxflow(&g, &flow, &e) == PW_OK);
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            int s = pw_graph_in_source(&g, y * w + x);
            if (x + 1 < w && s != pw_graph_in_source(&g, y * w + x + 1)) cut += hc[y * w + x];
            if (y + 1 < h && s != pw_graph_in_source(&g, (y + 1) * w + x)) cut += vc[y * w + x];
        }
    CHECKF(fabs(cut - flow) <= 1e-9 * flow, "cut %.17g flow %.17g", cut, flow);
    CHECK(flow > 0 && flow < h * 1.02);
    for (y = 0; y < h; y++) {
        CHECK(pw_graph_in_source(&g, y * w));
        CHECK(!pw_graph_in_source(&g, y * w + w - 1));
    }
    pwt_info("%dx%d grid: flow %.4f", w, h, flow);
    free(hc);
    free(vc);
    pw_graph_free(&g);
}

static void t_alloc_failures(void)
{
    int budget, finished = 0;
    for (budget = 0; budget < 20 && !finished; budget++) {
        pwt_alloc_state f = {0, 0, budget};
        pw_alloc al = {pwt_malloc, pwt_realloc, pwt_free, &f};
        pw_graph g;
        double flow = -1;
        pw_err e;
        int i, rc;
        pw_err_clear(&e);
        rc = pw_graph_init(&g, &al, 200, 0, &e);
        for (i = 0; i + 1 < 200 && !rc; i++) rc = pw_graph_add_edge(&g, i, i + 1, 1, 1, &e);
        if (!rc) {
            pw_graph_add_tweights(&g, 0, 3, 0);
            pw_graph_add_tweights(&g, 199, 0, 3);
            rc = pw_graph_maxflow(&g, &flow, &e);
            CHECK(flow == 1);
        } else {
            /* a failed add_edge is also reported by maxflow */
            pw_err e2;
            pw_err_clear(&e2);
            if (g.nodes) CHECK(pw_graph_maxflow(&g, &flow, &e2) == PW_ERR_NOMEM);
        }
        CHECKF(rc == PW_OK || rc == PW_ERR_NOMEM, "budget %d: %d %s", budget, rc, e.msg);
        finished = rc == PW_OK;
        pw_graph_free(&g);
        CHECKF(f.live == 0, "budget %d: %ld blocks leaked", budget, f.live);
    }
    CHECK(finished);
}

static const pwt_case cases[] = {
    {"random_small_graphs", t_random_small_graphs},
    {"random_grids", t_random_grids},
    {"straight_seam", t_straight_seam},
    {"enclosed_region", t_enclosed_region},
    {"zero_and_isolated", t_zero_and_isolated},
    {"tweights_common_part", t_tweights_common_part},
    {"invalid_input", t_invalid_input},
    {"determinism", t_determinism},
    {"large_grid_cut", t_large_grid_cut},
    {"alloc_failures", t_alloc_failures},
};
PWT_MAIN(cases)
