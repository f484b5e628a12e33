/* Tests of src/common/halfedge.h and src/common/subdiv.h: half-edge
 * invariants and topology on grids, cubes, tori and a genus-2 solid; the
 * errors for non-manifold and flipped input; Catmull-Clark counts, limit
 * behaviour and boundaries. */
#include "../src/common/subdiv.h"
#include "pwtest.h"

/* Number of edges at vertex v (0 if isolated). */
static int hmesh_valence(const pw_hmesh *hm, int v)
{
    int h = hm->vout[v], n = 0, start = h;
    if (h < 0) return 0;
    do {
        n++;
        h = pw_he_ccw(hm, h);
    } while (h >= 0 && h != start);
    return h < 0 ? n + 1 : n; /* an open fan has one more edge than faces */
}

/* Total genus of an orientable surface with `ncomp` components and
 * hm->nloops boundary loops: chi = 2c - 2g - b. */
static int hmesh_genus(const pw_hmesh *hm, int ncomp) { return (2 * ncomp - pw_hmesh_euler(hm) - hm->nloops) / 2; }

/* ---- procedural meshes ---------------------------------------------------- */

/* A mesh under construction with fixed capacity. */
typedef struct tmesh {
    pw_mesh m;
    int capv, capf, capc;
} tmesh;

/* `levels` Catmull-Clark steps of a polygon mesh (0 copies it); fails with
 * the half-edge build's errors on meshes it cannot represent. */
static int subdivide_levels(const pw_alloc *a, const pw_mesh *m, int levels, pw_mesh *out, pw_err *e)
{
    pw_mesh cur, next;
    pw_hmesh hm;
    int i, r;
    memset(out, 0, sizeof *out);
    if (levels < 0) return pw_fail(e, PW_ERR_INVALID, "subdivide: negative level count %d", levels);
    if ((r = pw_mesh_copy(a, m, &cur, e))) return r;
    pw_free(a, cur.uv); /* not carried */
    pw_free(a, cur.fuv);
    cur.uv = NULL;
    cur.fuv = NULL;
    cur.nuv = 0;
    for (i = 0; i < levels; i++) {
        if ((r = pw_hmesh_from_mesh(a, &cur, &hm, e))) break;
        r = pw_catmull_clark(a, &hm, cur.pos, &next, e);
        pw_hmesh_free(a, &hm);
        if (r) break;
        pw_mesh_free(a, &cur);
        cur = next;
    }
    if (r) {
        pw_mesh_free(a, &cur);
        return r;
    }
    *out = cur;
    return PW_OK;
}

static void tm_init(tmesh *t, int capv, int capf, int capc)
{
    pw_mesh_alloc(NULL, &t->m, capv, capf, capc, 0, NULL);
    t->m.nv = 0;
    t->m.nf = 0;
    t->capv = capv, t->capf = capf, t->capc = capc;
}
static int tm_vertex(tmesh *t, double x, double y, double z)
{
    float *p = t->m.pos + 3 * t->m.nv;
    p[0] = (float)x, p[1] = (float)y, p[2] = (float)z;
    return t->m.nv++;
}
static void tm_face(tmesh *t, int n, const int *v)
{
    int c = t->m.fstart[t->m.nf], i;
    for (i = 0; i < n; i++) t->m.fv[c + i] = v[i];
    t->m.fstart[++t->m.nf] = c + n;
}
static void tm_quad(tmesh *t, int a, int b, int c, int d)
{
    int v[4];
    v[0] = a, v[1] = b, v[2] = c, v[3] = d;
    tm_face(t, 4, v);
}

/* nx x ny quads in the plane z = 0, counter-clockwise seen from +z. */
static pw_mesh make_grid(int nx, int ny)
{
    tmesh t;
    int i, j;
    tm_init(&t, (nx + 1) * (ny + 1), nx * ny, 4 * nx * ny);
    for (j = 0; j <= ny; j++)
        for (i = 0; i <= nx; i++) tm_vertex(&t, i, j, 0);
    for (j = 0; j < ny; j++)
        for (i = 0; i < nx; i++) {
            int a = j * (nx + 1) + i;
            tm_quad(&t, a, a + 1, a + nx + 2, a + nx + 1);
        }
    return t.m;
}

/* A torus of nu x nv quads (major radius 2, minor 0.5), outward normals. */
static pw_mesh make_torus(int nu, int nv)
{
    tmesh t;
    int i, j;
    const double tau = 6.283185307179586;
    tm_init(&t, nu * nv, nu * nv, 4 * nu * nv);
    for (i = 0; i < nu; i++)
        for (j = 0; j < nv; j++) {
            double u = tau * i / nu, v = tau * j / nv, r = 2.0 + 0.5 * cos(v);
            tm_vertex(&t, r * cos(u), r * sin(u), 0.5 * sin(v));
        }
    for (i = 0; i < nu; i++)
        for (j = 0; j < nv; j++) {
            int i1 = (i + 1) % nu, j1 = (j + 1) % nv;
            tm_quad(&t, i * nv + j, i1 * nv + j, i1 * nv + j1, i * nv + j1);
        }
    return t.m;
}

/* The boundary surface of a set of unit voxels (cells[x][y][z] of an
 * X*Y*Z box), one outward quad per exposed voxel face; only lattice
 * points used by a face become vertices. */
static pw_mesh make_voxels(int X, int Y, int Z, const char *cells)
{
    tmesh t;
    int *id = (int *)malloc(sizeof(int) * (size_t)(X + 1) * (Y + 1) * (Z + 1));
    int dims[3], x[3], a, s, k;
    dims[0] = X, dims[1] = Y, dims[2] = Z;
    for (k = 0; k < (X + 1) * (Y + 1) * (Z + 1); k++) id[k] = -1;
    tm_init(&t, (X + 1) * (Y + 1) * (Z + 1), 6 * X * Y * Z, 24 * X * Y * Z);
#define CELL(p) (p[0] >= 0 && p[1] >= 0 && p[2] >= 0 && p[0] < X && p[1] < Y && p[2] < Z && \
                 cells[(p[0] * Y + p[1]) * Z + p[2]])
    for (x[0] = 0; x[0] < X; x[0]++)
        for (x[1] = 0; x[1] < Y; x[1]++)
            for (x[2] = 0; x[2] < Z; x[2]++) {
                if (!CELL(x)) continue;
                for (a = 0; a < 3; a++)
                    for (s = -1; s <= 1; s += 2) {
                        int n[3], q[4], c;
                        static const int off[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
                        n[0] = x[0], n[1] = x[1], n[2] = x[2];
                        n[a] += s;
                        if (CELL(n)) continue;
                        for (c = 0; c < 4; c++) {
                            int p[3], oc = s > 0 ? c : 3 - c, li;
                            p[0] = x[0], p[1] = x[1], p[2] = x[2];
                            p[a] += s > 0;
                            p[(a + 1) % 3] += off[oc][0];
                            p[(a + 2) % 3] += off[oc][1];
                            li = (p[0] * (Y + 1) + p[1]) * (Z + 1) + p[2];
                            if (id[li] < 0) id[li] = tm_vertex(&t, p[0], p[1], p[2]);
                            q[c] = id[li];
                        }
                        tm_face(&t, 4, q);
                    }
            }
#undef CELL
    (void)dims;
    free(id);
    return t.m;
}

static pw_mesh make_cube(void)
{
    static const char one = 1;
    pw_mesh m = make_voxels(1, 1, 1, &one);
    int i;
    for (i = 0; i < m.nv * 3; i++) m.pos[i] = 2.0f * m.pos[i] - 1.0f; /* [-1,1]^3 */
    return m;
}

/* A 3x5x1 slab with two square holes: genus 2. */
static pw_mesh make_genus2(void)
{
    char cells[15];
    int i;
    for (i = 0; i < 15; i++) cells[i] = 1;
    cells[1 * 5 + 1] = 0;
    cells[1 * 5 + 3] = 0;
    return make_voxels(3, 5, 1, cells);
}

static int build(const pw_mesh *m, pw_hmesh *hm, pw_err *e)
{
    pw_err_clear(e);
    return pw_hmesh_from_mesh(NULL, m, hm, e);
}

/* ---- invariants ----------------------------------------------------------- */

/* Checks every structural invariant; returns the number of violations. */
static int check_invariants(const pw_hmesh *hm)
{
    int h, v, e, bad = 0, nb = 0;
    int *seen = (int *)calloc((size_t)hm->ne + 1, sizeof(int));
    for (h = 0; h < hm->nh; h++) {
        int t = hm->twin[h], n = pw_he_next(hm, h), k, g = h;
        bad += pw_he_prev(hm, n) != h || hm->hface[n] != hm->hface[h];
        for (k = 0; k < hm->fstart[hm->hface[h] + 1] - hm->fstart[hm->hface[h]]; k++) g = pw_he_next(hm, g);
        bad += g != h; /* next cycles around the face */
        if (t >= 0) {
            bad += hm->twin[t] != h || pw_he_origin(hm, t) != pw_he_dest(hm, h) ||
                   pw_he_dest(hm, t) != pw_he_origin(hm, h) || hm->hedge[t] != hm->hedge[h] || t == h;
        } else
            nb++;
        e = hm->hedge[h];
        bad += e < 0 || e >= hm->ne;
        if (e >= 0 && e < hm->ne) {
            seen[e]++;
            bad += hm->edgeh[e] != (t >= 0 && t < h ? t : h);
        }
    }
    for (e = 0; e < hm->ne; e++) {
        int h0 = hm->edgeh[e];
        bad += seen[e] != (hm->twin[h0] >= 0 ? 2 : 1);
    }
    bad += nb != hm->nboundary || hm->ne != (hm->nh + nb) / 2;
    for (v = 0; v < hm->nv; v++) {
        int h0 = hm->vout[v], g, count = 0, deg = 0, boundary = 0;
        for (h = 0; h < hm->nh; h++)
            if (hm->fv[h] == v) deg++, boundary |= hm->twin[h] < 0;
        if (h0 < 0) {
            bad += deg != 0;
            continue;
        }
        bad += hm->fv[h0] != v || (boundary && hm->twin[h0] >= 0);
        for (g = h0; g >= 0 && count <= deg; g = pw_he_ccw(hm, g)) {
            count++;
            if (pw_he_ccw(hm, g) == h0) break;
        }
        bad += count != deg; /* one fan visits every outgoing half-edge */
    }
    free(seen);
    return bad;
}

static int components(const pw_hmesh *hm)
{
    int n = -1;
    pw_err e;
    pw_err_clear(&e);
    pw_hmesh_components(NULL, hm, NULL, &n, &e);
    return n;
}

/* ---- topology tests ------------------------------------------------------- */

static void t_grid(void)
{
    pw_mesh m = make_grid(4, 3);
    pw_hmesh hm;
    pw_err e;
    int v, interior = 0, boundary = 0;
    REQUIRE(build(&m, &hm, &e) == PW_OK);
    CHECK_EQ_INT(check_invariants(&hm), 0);
    CHECK_EQ_INT(hm.nh, 48);
    CHECK_EQ_INT(hm.ne, 4 * 4 + 5 * 3);
    CHECK_EQ_INT(hm.nboundary, 14);
    CHECK_EQ_INT(hm.nloops, 1);
    CHECK_EQ_INT(pw_hmesh_euler(&hm), 1);
    CHECK_EQ_INT(components(&hm), 1);
    CHECK_EQ_INT(hmesh_genus(&hm, 1), 0);
    for (v = 0; v < hm.nv; v++) {
        int val = hmesh_valence(&hm, v);
        if (hm.twin[hm.vout[v]] < 0) boundary++;
        else {
            interior++;
            CHECK_EQ_INT(val, 4);
        }
    }
    CHECK_EQ_INT(interior, 3 * 2);
    CHECK_EQ_INT(boundary, 14);
    CHECK_EQ_INT(hmesh_valence(&hm, 0), 2);  /* corner */
    CHECK_EQ_INT(hmesh_valence(&hm, 1), 3);  /* side */
    /* walking the boundary loop visits every boundary edge once */
    {
        int h0 = hm.vout[0], h = h0, n = 0;
        do {
            CHECK(hm.twin[h] < 0);
            h = pw_he_boundary_next(&hm, h);
            n++;
        } while (h != h0 && n <= 14);
        CHECK_EQ_INT(n, 14);
    }
    pw_hmesh_free(NULL, &hm);
    pw_mesh_free(NULL, &m);
}

static void t_closed(void)
{
    pw_mesh cube = make_cube(), torus = make_torus(12, 8), g2 = make_genus2();
    pw_hmesh hm;
    pw_err e;
    REQUIRE(build(&cube, &hm, &e) == PW_OK);
    CHECK_EQ_INT(check_invariants(&hm), 0);
    CHECK(hm.nv == 8 && hm.ne == 12 && hm.nf == 6 && hm.nboundary == 0 && hm.nloops == 0);
    CHECK_EQ_INT(pw_hmesh_euler(&hm), 2);
    CHECK_EQ_INT(hmesh_genus(&hm, components(&hm)), 0);
    pw_hmesh_free(NULL, &hm);
    REQUIRE(build(&torus, &hm, &e) == PW_OK);
    CHECK_EQ_INT(check_invariants(&hm), 0);
    CHECK_EQ_INT(pw_hmesh_euler(&hm), 0);
    CHECK_EQ_INT(hmesh_genus(&hm, components(&hm)), 1);
    pw_hmesh_free(NULL, &hm);
    REQUIRE(build(&g2, &hm, &e) == PW_OK);
    CHECK_EQ_INT(check_invariants(&hm), 0);
    CHECK_EQ_INT(hm.nloops, 0);
    CHECK_EQ_INT(pw_hmesh_euler(&hm), -2);
    CHECK_EQ_INT(components(&hm), 1);
    CHECK_EQ_INT(hmesh_genus(&hm, 1), 2);
    pw_hmesh_free(NULL, &hm);
    pw_mesh_free(NULL, &cube);
    pw_mesh_free(NULL, &torus);
    pw_mesh_free(NULL, &g2);
}

static void t_components_and_isolated(void)
{
    static const char cells[3] = {1, 0, 1}; /* two cubes apart */
    pw_mesh m = make_voxels(3, 1, 1, cells);
    pw_hmesh hm;
    pw_err e;
    int comp[12], n = 0, f;
    REQUIRE(build(&m, &hm, &e) == PW_OK);
    REQUIRE(hm.nf == 12);
    CHECK_EQ_INT(pw_hmesh_components(NULL, &hm, comp, &n, &e), PW_OK);
    CHECK_EQ_INT(n, 2);
    for (f = 0; f < 6; f++) CHECK(comp[f] == 0 && comp[f + 6] == 1);
    CHECK_EQ_INT(pw_hmesh_euler(&hm), 4);
    CHECK_EQ_INT(hmesh_genus(&hm, n), 0);
    pw_hmesh_free(NULL, &hm);
    /* isolated vertices: allowed, vout = -1, not part of the Euler count */
    {
        static const int fs[2] = {0, 3}, fv[3] = {0, 2, 4};
        REQUIRE(pw_hmesh_build(NULL, 6, 1, fs, fv, &hm, &e) == PW_OK);
        CHECK(hm.vout[1] == -1 && hm.vout[3] == -1 && hm.vout[5] == -1 && hm.vout[2] >= 0);
        CHECK_EQ_INT(pw_hmesh_euler(&hm), 1);
        CHECK_EQ_INT(hm.nloops, 1);
        CHECK_EQ_INT(check_invariants(&hm), 0);
        CHECK_EQ_INT(hmesh_valence(&hm, 1), 0);
        pw_hmesh_free(NULL, &hm);
    }
    pw_mesh_free(NULL, &m);
}

static void t_mixed_degrees(void)
{
    /* a square split into a triangle, a quad and a pentagon-like fan */
    tmesh t;
    pw_hmesh hm;
    pw_err e;
    int f0[3], f1[5], f2[4];
    tm_init(&t, 7, 3, 12);
    tm_vertex(&t, 0, 0, 0), tm_vertex(&t, 2, 0, 0), tm_vertex(&t, 2, 2, 0), tm_vertex(&t, 0, 2, 0);
    tm_vertex(&t, 1, 1, 0), tm_vertex(&t, 1, 0, 0), tm_vertex(&t, 2, 1, 0);
    f0[0] = 0, f0[1] = 5, f0[2] = 4;
    f1[0] = 5, f1[1] = 1, f1[2] = 6, f1[3] = 2, f1[4] = 4;
    f2[0] = 0, f2[1] = 4, f2[2] = 2, f2[3] = 3;
    tm_face(&t, 3, f0), tm_face(&t, 5, f1), tm_face(&t, 4, f2);
    REQUIRE(build(&t.m, &hm, &e) == PW_OK);
    CHECK_EQ_INT(check_invariants(&hm), 0);
    CHECK_EQ_INT(pw_hmesh_euler(&hm), 1);
    CHECK_EQ_INT(hm.nloops, 1);
    pw_hmesh_free(NULL, &hm);
    pw_mesh_free(NULL, &t.m);
}

/* ---- errors --------------------------------------------------------------- */

static void expect_build_(int line, const pw_mesh *m, int code, const char *f1, const char *f2)
{
    pw_hmesh hm;
    pw_err e;
    int r = build(m, &hm, &e);
    if (r != code) pwt_fail_(__FILE__, line, "expected %d, got %d (%s)", code, r, e.msg);
    if (!strstr(e.msg, f1)) pwt_fail_(__FILE__, line, "message '%s' lacks '%s'", e.msg, f1);
    if (!strstr(e.msg, f2)) pwt_fail_(__FILE__, line, "message '%s' lacks '%s'", e.msg, f2);
    if (hm.twin || hm.fv || hm.nh) pwt_fail_(__FILE__, line, "output not empty after an error");
    if (r == PW_OK) pw_hmesh_free(NULL, &hm);
}
#define EXPECT_BUILD(m, code, f1, f2) expect_build_(__LINE__, m, code, f1, f2)

static void t_nonmanifold_edge(void)
{
    tmesh t;
    int f[3];
    static const char cells[4] = {1, 0, 0, 1}; /* two cubes sharing an edge */
    pw_mesh m2;
    tm_init(&t, 5, 3, 9);
    tm_vertex(&t, 0, 0, 0), tm_vertex(&t, 1, 0, 0), tm_vertex(&t, 0, 1, 0), tm_vertex(&t, 0, -1, 0);
    tm_vertex(&t, 0, 0, 1);
    f[0] = 0, f[1] = 1, f[2] = 2, tm_face(&t, 3, f);
    f[0] = 1, f[1] = 0, f[2] = 3, tm_face(&t, 3, f);
    f[0] = 0, f[1] = 1, f[2] = 4, tm_face(&t, 3, f);
    EXPECT_BUILD(&t.m, PW_ERR_TOPOLOGY, "non-manifold edge v0-v1", "used by faces 0, 1 and 2");
    pw_mesh_free(NULL, &t.m);
    m2 = make_voxels(2, 2, 1, cells);
    EXPECT_BUILD(&m2, PW_ERR_TOPOLOGY, "non-manifold edge", "faces");
    pw_mesh_free(NULL, &m2);
}

static void t_flipped_face(void)
{
    pw_mesh m = make_grid(3, 3);
    int *q = m.fv + m.fstart[4], tmp; /* the middle quad */
    char want[64];
    tmp = q[1], q[1] = q[3], q[3] = tmp;
    /* corner order 5 6 10 9 becomes 5 9 10 6: the edges to faces 1, 3, 5, 7 reverse; the
     * first one met in half-edge order is in face 1 (5->6) vs face 4 */
    snprintf(want, sizeof want, "faces 1 and 4 both traverse edge v6->v5");
    EXPECT_BUILD(&m, PW_ERR_TOPOLOGY, "inconsistent orientation", want);
    pw_mesh_free(NULL, &m);
}

static void t_nonmanifold_vertex(void)
{
    static const char cells[8] = {1, 0, 0, 0, 0, 0, 0, 1}; /* cubes (0,0,0) and (1,1,1) */
    pw_mesh m = make_voxels(2, 2, 2, cells);
    tmesh t;
    int f[3], shared = -1, v;
    char want[64];
    for (v = 0; v < m.nv; v++)
        if (m.pos[3 * v] == 1 && m.pos[3 * v + 1] == 1 && m.pos[3 * v + 2] == 1) shared = v;
    snprintf(want, sizeof want, "non-manifold vertex %d:", shared);
    EXPECT_BUILD(&m, PW_ERR_TOPOLOGY, want, "its faces form 2 separate fans");
    pw_mesh_free(NULL, &m);
    /* a bowtie: two triangles meeting at vertex 2 */
    tm_init(&t, 5, 2, 6);
    tm_vertex(&t, 0, 0, 0), tm_vertex(&t, 1, 0, 0), tm_vertex(&t, 1, 1, 0), tm_vertex(&t, 2, 1, 0), tm_vertex(&t, 2, 2, 0);
    f[0] = 0, f[1] = 1, f[2] = 2, tm_face(&t, 3, f);
    f[0] = 2, f[1] = 3, f[2] = 4, tm_face(&t, 3, f);
    EXPECT_BUILD(&t.m, PW_ERR_TOPOLOGY, "non-manifold vertex 2", "2 separate fans");
    pw_mesh_free(NULL, &t.m);
    /* a chain of three cubes meeting at corners */
    {
        static const char c3[27] = {1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1};
        pw_mesh m3 = make_voxels(3, 3, 3, c3);
        EXPECT_BUILD(&m3, PW_ERR_TOPOLOGY, "non-manifold vertex", "2 separate fans");
        pw_mesh_free(NULL, &m3);
    }
}

static void t_degenerate_and_invalid(void)
{
    static const int fs[3] = {0, 3, 6}, rep[6] = {0, 1, 2, 0, 2, 2}, oor[6] = {0, 1, 2, 0, 2, 7};
    static const int fs2[2] = {0, 2}, two[2] = {0, 1}, fsbad[2] = {1, 4};
    pw_hmesh hm;
    pw_err e;
    pw_err_clear(&e);
    CHECK_EQ_INT(pw_hmesh_build(NULL, 4, 2, fs, rep, &hm, &e), PW_ERR_DEGENERATE);
    CHECK(strstr(e.msg, "face 1 uses vertex 2 twice") != NULL);
    pw_err_clear(&e);
    CHECK_EQ_INT(pw_hmesh_build(NULL, 4, 2, fs, oor, &hm, &e), PW_ERR_INVALID);
    CHECK(strstr(e.msg, "face 1, corner 2: vertex index 7 out of range (4 vertices)") != NULL);
    pw_err_clear(&e);
    CHECK_EQ_INT(pw_hmesh_build(NULL, 4, 1, fs2, two, &hm, &e), PW_ERR_DEGENERATE);
    CHECK(strstr(e.msg, "face 0 has 2 corners") != NULL);
    pw_err_clear(&e);
    CHECK_EQ_INT(pw_hmesh_build(NULL, 4, 1, fsbad, oor, &hm, &e), PW_ERR_INVALID);
    pw_err_clear(&e);
    CHECK_EQ_INT(pw_hmesh_build(NULL, -1, 1, fs, oor, &hm, &e), PW_ERR_INVALID);
    /* no faces: an empty but valid structure */
    pw_err_clear(&e);
    REQUIRE(pw_hmesh_build(NULL, 3, 0, fs, NULL, &hm, &e) == PW_OK);
    CHECK(hm.nh == 0 && hm.ne == 0 && hm.vout[0] == -1);
    pw_hmesh_free(NULL, &hm);
}

/* ---- Catmull-Clark -------------------------------------------------------- */

static int subdivide(const pw_mesh *m, pw_mesh *out)
{
    pw_hmesh hm;
    pw_err e;
    int r = build(m, &hm, &e);
    if (r) return r;
    r = pw_catmull_clark(NULL, &hm, m->pos, out, &e);
    pw_hmesh_free(NULL, &hm);
    return r;
}

static void t_cc_counts(void)
{
    pw_mesh cube = make_cube(), s1, s2;
    pw_hmesh hm;
    pw_err e;
    int f;
    REQUIRE(subdivide(&cube, &s1) == PW_OK);
    CHECK_EQ_INT(s1.nv, 8 + 12 + 6);
    CHECK_EQ_INT(s1.nf, 24);
    for (f = 0; f < s1.nf; f++) CHECK_EQ_INT(s1.fstart[f + 1] - s1.fstart[f], 4);
    for (f = 0; f < s1.nf; f++) CHECK_EQ_INT(s1.fv[4 * f], cube.fv[f]); /* quad h starts at corner h */
    REQUIRE(subdivide(&s1, &s2) == PW_OK);
    CHECK_EQ_INT(s2.nv, 98);
    CHECK_EQ_INT(s2.nf, 96);
    REQUIRE(build(&s2, &hm, &e) == PW_OK);
    CHECK_EQ_INT(check_invariants(&hm), 0);
    CHECK_EQ_INT(pw_hmesh_euler(&hm), 2);
    pw_hmesh_free(NULL, &hm);
    pw_mesh_free(NULL, &s2);
    pw_mesh_free(NULL, &s1);
    pw_mesh_free(NULL, &cube);
}

static void t_cc_cube_limit(void)
{
    pw_mesh cur = make_cube(), next;
    int level, i, k;
    float prev_max = 1.0f;
    for (level = 1; level <= 5; level++) {
        float maxc = 0, lo[3], hi[3];
        REQUIRE(subdivide(&cur, &next) == PW_OK);
        if (level == 1) /* corner (1,1,1), n = 3: (Q + 2R)/3 = (1/3 + 4/3)/3 = 5/9 */
            for (k = 0; k < 3; k++) CHECK_NEAR(fabs(next.pos[k]), 5.0 / 9.0, 1e-6);
        for (i = 0; i < next.nv * 3; i++) {
            CHECK(next.pos[i] >= -1.0f && next.pos[i] <= 1.0f); /* inside the closed cube */
            if (fabs(next.pos[i]) > maxc) maxc = (float)fabs(next.pos[i]);
        }
        pw_mesh_bounds(&next, lo, hi);
        for (k = 0; k < 3; k++) CHECK_NEAR(lo[k], -hi[k], 1e-6); /* symmetric */
        CHECK_NEAR(hi[0], hi[1], 1e-6);
        CHECK_NEAR(hi[1], hi[2], 1e-6);
        CHECK(maxc <= prev_max); /* the hull shrinks toward the limit surface */
        prev_max = maxc;
        pw_mesh_free(NULL, &cur);
        cur = next;
    }
    /* the original corners converge: their change gets small */
    {
        pw_mesh more;
        REQUIRE(subdivide(&cur, &more) == PW_OK);
        for (i = 0; i < 8 * 3; i++) CHECK_NEAR(more.pos[i], cur.pos[i], 2e-3);
        /* limit of a valence-3 corner: (n^2 S + 4 sum(edge neighbours) + sum(diagonal
         * neighbours)) / (n (n + 5)) = (9 + 4 - 1) / 24 = 1/2 for the cube [-1,1]^3 */
        for (i = 0; i < 8 * 3; i++) CHECK_NEAR(fabs(more.pos[i]), 0.5, 1e-3);
        pwt_info("cube corner after 6 levels: %.6f (limit 0.5)", fabs(more.pos[0]));
        pw_mesh_free(NULL, &more);
    }
    pw_mesh_free(NULL, &cur);
}

static void t_cc_grid_boundary(void)
{
    pw_mesh cur = make_grid(3, 2), next;
    int level, v;
    for (level = 0; level < 3; level++) {
        pw_hmesh hm;
        pw_err e;
        REQUIRE(subdivide(&cur, &next) == PW_OK);
        REQUIRE(build(&next, &hm, &e) == PW_OK);
        CHECK_EQ_INT(hm.nloops, 1);
        CHECK_EQ_INT(pw_hmesh_euler(&hm), 1);
        for (v = 0; v < next.nv; v++) {
            const float *p = next.pos + 3 * v;
            CHECK(p[2] == 0.0f);
            CHECK(p[0] >= 0 && p[0] <= 3 && p[1] >= 0 && p[1] <= 2);
            if (hm.vout[v] >= 0 && hm.twin[hm.vout[v]] < 0) /* boundary stays on the rectangle */
                CHECKF(p[0] == 0 || p[0] == 3 || p[1] == 0 || p[1] == 2, "boundary vertex %d at (%g, %g)", v,
                       (double)p[0], (double)p[1]);
        }
        /* the rectangle's corners stay put */
        CHECK(next.pos[0] == 0 && next.pos[1] == 0);
        CHECK(next.pos[3 * 3] == 3 && next.pos[3 * 3 + 1] == 0);
        pw_hmesh_free(NULL, &hm);
        pw_mesh_free(NULL, &cur);
        cur = next;
    }
    pw_mesh_free(NULL, &cur);
}

static void t_cc_mixed(void)
{
    tmesh t;
    pw_mesh out;
    int f[3];
    tm_init(&t, 4, 2, 7);
    tm_vertex(&t, 0, 0, 0), tm_vertex(&t, 1, 0, 0), tm_vertex(&t, 1, 1, 0), tm_vertex(&t, 0, 1, 0);
    f[0] = 0, f[1] = 1, f[2] = 2, tm_face(&t, 3, f);
    f[0] = 0, f[1] = 2, f[2] = 3, tm_face(&t, 3, f);
    REQUIRE(subdivide(&t.m, &out) == PW_OK);
    CHECK_EQ_INT(out.nv, 4 + 5 + 2);
    CHECK_EQ_INT(out.nf, 6);
    /* face points are centroids, the inner edge point averages ends and face points */
    CHECK_NEAR(out.pos[3 * 9], 2.0 / 3.0, 1e-6);
    CHECK_NEAR(out.pos[3 * 9 + 1], 1.0 / 3.0, 1e-6);
    CHECK_NEAR(out.pos[3 * 10], 1.0 / 3.0, 1e-6);
    {
        int e, found = 0;
        for (e = 4; e < 9; e++)
            if (fabs(out.pos[3 * e] - 0.5) < 1e-6 && fabs(out.pos[3 * e + 1] - 0.5) < 1e-6) found++;
        CHECK_EQ_INT(found, 1);
    }
    /* a single triangle: every vertex a corner, kept */
    t.m.nf = 1;
    pw_mesh_free(NULL, &out);
    REQUIRE(subdivide(&t.m, &out) == PW_OK);
    CHECK(out.pos[3] == 1.0f && out.pos[4] == 0.0f);
    pw_mesh_free(NULL, &out);
    pw_mesh_free(NULL, &t.m);
}

static void t_subdivide_levels(void)
{
    pw_mesh g2 = make_genus2(), out;
    pw_hmesh hm;
    pw_err e;
    pw_err_clear(&e);
    REQUIRE(subdivide_levels(NULL, &g2, 2, &out, &e) == PW_OK);
    REQUIRE(build(&out, &hm, &e) == PW_OK);
    CHECK_EQ_INT(hm.nf, g2.fstart[g2.nf] * 4);
    CHECK_EQ_INT(hmesh_genus(&hm, components(&hm)), 2);
    pw_hmesh_free(NULL, &hm);
    pw_mesh_free(NULL, &out);
    REQUIRE(subdivide_levels(NULL, &g2, 0, &out, &e) == PW_OK);
    CHECK(out.nf == g2.nf);
    pw_mesh_free(NULL, &out);
    CHECK_EQ_INT(subdivide_levels(NULL, &g2, -1, &out, &e), PW_ERR_INVALID);
    pw_mesh_free(NULL, &g2);
}

static void t_deterministic(void)
{
    pw_mesh t = make_torus(9, 7), a, b;
    REQUIRE(subdivide(&t, &a) == PW_OK);
    REQUIRE(subdivide(&t, &b) == PW_OK);
    CHECK(memcmp(a.pos, b.pos, (size_t)a.nv * 3 * sizeof(float)) == 0);
    CHECK(memcmp(a.fv, b.fv, (size_t)a.fstart[a.nf] * sizeof(int)) == 0);
    pw_mesh_free(NULL, &a);
    pw_mesh_free(NULL, &b);
    pw_mesh_free(NULL, &t);
}

/* Allocation failures at every step are reported and leak nothing. */
static void t_alloc_failures(void)
{
    pw_mesh m = make_genus2();
    int budget, ok = 0;
    for (budget = 0; budget < 100 && !ok; budget++) {
        pwt_alloc_state t = {0, 0, budget};
        pw_alloc a = {pwt_malloc, pwt_realloc, pwt_free, &t};
        pw_mesh out;
        pw_err e;
        int r;
        pw_err_clear(&e);
        r = subdivide_levels(&a, &m, 2, &out, &e);
        if (r == PW_OK) ok = 1, pw_mesh_free(&a, &out);
        else CHECKF(r == PW_ERR_NOMEM, "budget %d: %s", budget, e.msg);
        CHECKF(t.live == 0, "budget %d: %ld blocks leaked", budget, t.live);
    }
    CHECK(ok);
    pw_mesh_free(NULL, &m);
}

/* ---- real data ------------------------------------------------------------ */

static void t_real_data(void)
{
    static const char *const files[] = {"meshes/elephant.off", "meshes/torus_quad.off", "meshes/double-torus-example.off",
                                        "meshes/sphere.ply", "meshes/elephant-with-holes.off", "meshes/cube_poly.off"};
    static const int genus[] = {3, 1, 2, 0, 3, 0}, loops[] = {0, 0, 0, 0, 106, 0};
    size_t i;
    int found = 0;
    for (i = 0; i < sizeof files / sizeof files[0]; i++) {
        const char *path = pwt_data_opt(files[i]);
        pw_mesh m, s;
        pw_hmesh hm;
        pw_err e;
        if (!path) continue;
        found++;
        pw_err_clear(&e);
        if (pw_mesh_load(NULL, path, &m, &e) || build(&m, &hm, &e)) {
            CHECKF(0, "%s: %s", path, e.msg);
            continue;
        }
        CHECKF(check_invariants(&hm) == 0, "%s: invariants", path);
        CHECKF(hmesh_genus(&hm, components(&hm)) == genus[i] && hm.nloops == loops[i], "%s: genus %d, %d loops",
               path, hmesh_genus(&hm, components(&hm)), hm.nloops);
        CHECK_EQ_INT(pw_catmull_clark(NULL, &hm, m.pos, &s, &e), PW_OK);
        CHECK_EQ_INT(s.nf, hm.nh);
        pw_mesh_free(NULL, &s);
        pw_hmesh_free(NULL, &hm);
        pw_mesh_free(NULL, &m);
    }
    if (!found) pwt_data("meshes/elephant.off");
    else pwt_info("%d real meshes checked", found);
}

static void t_real_data_errors(void)
{
    static const char *const files[] = {"meshes/blobby-shuffled.off", "meshes/polygon_mesh.off"};
    static const char *const frags[] = {"inconsistent orientation: faces 0 and 3272 both traverse edge v671->v417",
                                        "non-manifold vertex 4113: its faces form 3 separate fans"};
    int i, found = 0;
    for (i = 0; i < 2; i++) {
        const char *path = pwt_data_opt(files[i]);
        pw_mesh m;
        if (!path) continue;
        found++;
        {
            pw_err e;
            pw_err_clear(&e);
            REQUIRE(pw_mesh_load(NULL, path, &m, &e) == PW_OK);
        }
        EXPECT_BUILD(&m, PW_ERR_TOPOLOGY, frags[i], "");
        pw_mesh_free(NULL, &m);
    }
    if (!found) pwt_data("meshes/blobby-shuffled.off");
}

static const pwt_case cases[] = {
    {"grid", t_grid},
    {"closed_cube_torus_genus2", t_closed},
    {"components_and_isolated", t_components_and_isolated},
    {"mixed_degrees", t_mixed_degrees},
    {"nonmanifold_edge", t_nonmanifold_edge},
    {"flipped_face", t_flipped_face},
    {"nonmanifold_vertex", t_nonmanifold_vertex},
    {"degenerate_and_invalid", t_degenerate_and_invalid},
    {"cc_counts", t_cc_counts},
    {"cc_cube_limit", t_cc_cube_limit},
    {"cc_grid_boundary", t_cc_grid_boundary},
    {"cc_mixed", t_cc_mixed},
    {"subdivide_levels", t_subdivide_levels},
    {"deterministic", t_deterministic},
    {"alloc_failures", t_alloc_failures},
    {"real_data", t_real_data},
    {"real_data_errors", t_real_data_errors},
};
PWT_MAIN(cases)
