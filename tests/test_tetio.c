/* Tests of src/common/tetio.h (TetGen .node/.ele and MEDIT .mesh) and of
 * the adjacency, boundary, ring and point-location parts of tetmesh.h:
 * round trips, TetGen's own output (when the tetgen binary is installed),
 * and a clear error for every kind of bad input. */
#define _POSIX_C_SOURCE 200809L
#include "../src/common/tetio.h"
#include "../src/common/shapes.h"
#include "pwtest.h"

/* Two tetrahedra sharing face (1 2 3): a bipyramid. */
/* pw_tetgen_read_memory on two files given by value. */
static int tg_read(const pw_alloc *a, pw_memfile node, pw_memfile ele, pw_tetmesh *out, pw_err *e)
{
    return pw_tetgen_read_memory(a, &node, &ele, out, e);
}

static const float bipyr_pos[15] = {0, 0, -1, 1, 0, 0, 0, 1, 0, -1, -1, 0, 0, 0, 1};
static const int bipyr_tet[8] = {0, 1, 2, 3, 4, 1, 3, 2};

static pw_tetmesh bipyramid(float *pos, int *tet)
{
    pw_tetmesh m;
    memcpy(pos, bipyr_pos, sizeof bipyr_pos);
    memcpy(tet, bipyr_tet, sizeof bipyr_tet);
    m.nv = 5, m.pos = pos, m.nt = 2, m.tet = tet;
    return m;
}

/* A cube split into 6 tetrahedra around its diagonal 0-6, then refined n
 * times per axis: (n^3 cubes, 6 n^3 tetrahedra), all positive. */
static int cube_mesh(int n, pw_tetmesh *m)
{
    static const int split[6][4] = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6}, {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
    static const int corner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    int x, y, z, k, j, t = 0, s = n + 1;
    m->nv = s * s * s, m->nt = 6 * n * n * n;
    m->pos = (float *)malloc(sizeof(float) * 3 * (size_t)m->nv);
    m->tet = (int *)malloc(sizeof(int) * 4 * (size_t)m->nt);
    if (!m->pos || !m->tet) return 0;
    for (z = 0; z < s; z++)
        for (y = 0; y < s; y++)
            for (x = 0; x < s; x++) {
                float *p = m->pos + 3 * ((z * s + y) * s + x);
                p[0] = (float)x / n, p[1] = (float)y / n, p[2] = (float)z / n;
            }
    for (z = 0; z < n; z++)
        for (y = 0; y < n; y++)
            for (x = 0; x < n; x++)
                for (k = 0; k < 6; k++, t++)
                    for (j = 0; j < 4; j++) {
                        const int *c = corner[split[k][j]];
                        m->tet[4 * t + j] = ((z + c[2]) * s + y + c[1]) * s + x + c[0];
                    }
    return 1;
}

static void free_mesh(pw_tetmesh *m) { pw_tetmesh_free(NULL, m); }

static void t_check_flips(void)
{
    float pos[15];
    int tet[8];
    pw_tetmesh m = bipyramid(pos, tet);
    pw_err e;
    pw_err_clear(&e);
    tet[2] = 1, tet[1] = 2; /* the first one turned inside out */
    CHECK(pw_tet_volume6(&m, 0) < 0.0);
    REQUIRE(pw_tetmesh_check(&m, "t", &e) == PW_OK);
    CHECK(pw_tet_volume6(&m, 0) > 0.0 && pw_tet_volume6(&m, 1) > 0.0);
}

static void t_check_errors(void)
{
    float pos[15];
    int tet[8];
    pw_tetmesh m;
    pw_err e;
    m = bipyramid(pos, tet);
    pw_err_clear(&e);
    tet[5] = 7;
    CHECK(pw_tetmesh_check(&m, "t", &e) == PW_ERR_INVALID && strstr(e.msg, "tetrahedron 1 uses vertex 7"));
    m = bipyramid(pos, tet);
    pw_err_clear(&e);
    tet[1] = 0;
    CHECK(pw_tetmesh_check(&m, "t", &e) == PW_ERR_DEGENERATE && strstr(e.msg, "twice"));
    m = bipyramid(pos, tet);
    pw_err_clear(&e);
    pos[14] = 0.0f; /* vertex 4 into the plane of 1 2 3 */
    CHECK(pw_tetmesh_check(&m, "t", &e) == PW_ERR_DEGENERATE && strstr(e.msg, "zero volume"));
    m = bipyramid(pos, tet);
    pw_err_clear(&e);
    pos[3] = NAN;
    CHECK(pw_tetmesh_check(&m, "t", &e) == PW_ERR_INVALID && strstr(e.msg, "vertex 1"));
}

static void t_neighbors(void)
{
    float pos[15];
    int tet[8], nb[8], *faces, nf, k;
    pw_tetmesh m = bipyramid(pos, tet);
    pw_err e;
    pw_err_clear(&e);
    REQUIRE(pw_tetmesh_neighbors(NULL, &m, nb, &e) == PW_OK);
    CHECK_EQ_INT(nb[0], 4 + 0); /* face opposite corner 0 of each is (1 2 3) */
    CHECK_EQ_INT(nb[4], 0);
    for (k = 1; k < 4; k++) CHECK(nb[k] < 0 && nb[4 + k] < 0);
    REQUIRE(pw_tetmesh_boundary(NULL, &m, nb, &faces, &nf, &e) == PW_OK);
    CHECK_EQ_INT(nf, 6);
    CHECK_EQ_INT(faces[0], 1);
    CHECK_EQ_INT(faces[5], 7);
    free(faces);
}

static void t_neighbors_overlap(void)
{
    float pos[15];
    int tet[8], nb[8];
    pw_tetmesh m = bipyramid(pos, tet);
    pw_err e;
    pw_err_clear(&e);
    pos[14] = -0.5f; /* vertex 4 on the same side as vertex 0: the two overlap */
    REQUIRE(pw_tetmesh_check(&m, "t", &e) == PW_OK);
    CHECK(pw_tetmesh_neighbors(NULL, &m, nb, &e) == PW_ERR_TOPOLOGY && strstr(e.msg, "overlap"));
}

static void t_neighbors_three(void)
{
    static const float p[18] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 1, 1, 1};
    int tet[12] = {3, 0, 1, 2, 4, 0, 2, 1, 5, 0, 1, 2}, nb[12];
    pw_tetmesh m;
    pw_err e;
    pw_err_clear(&e);
    m.nv = 6, m.pos = (float *)p, m.nt = 3, m.tet = tet;
    REQUIRE(pw_tetmesh_check(&m, "t", &e) == PW_OK);
    CHECK(pw_tetmesh_neighbors(NULL, &m, nb, &e) == PW_ERR_TOPOLOGY);
}

/* A refined cube: each interior face is shared, the boundary is the 12 n^2
 * triangles of its six sides, the volumes add up to 1. */
static void t_cube_adjacency(void)
{
    pw_tetmesh m;
    pw_tetrings g;
    pw_err e;
    int *nb, *faces, nf, t, v, maxdeg = 0;
    double vol = 0.0;
    pw_err_clear(&e);
    REQUIRE(cube_mesh(4, &m));
    REQUIRE(pw_tetmesh_check(&m, "cube", &e) == PW_OK);
    nb = (int *)malloc(sizeof(int) * 4 * (size_t)m.nt);
    REQUIRE(pw_tetmesh_neighbors(NULL, &m, nb, &e) == PW_OK);
    REQUIRE(pw_tetmesh_boundary(NULL, &m, nb, &faces, &nf, &e) == PW_OK);
    CHECK_EQ_INT(nf, 12 * 16);
    for (t = 0; t < m.nt; t++) vol += pw_tet_volume6(&m, t) / 6.0;
    CHECK_NEAR(vol, 1.0, 1e-6);
    REQUIRE(pw_tetmesh_rings(NULL, &m, &g, &e) == PW_OK);
    for (v = 0; v < m.nv; v++) {
        int d = g.start[v + 1] - g.start[v], k;
        for (k = g.start[v] + 1; k < g.start[v + 1]; k++) CHECK(g.adj[k - 1] < g.adj[k]);
        if (d > maxdeg) maxdeg = d;
        CHECK(d >= 3);
    }
    CHECK_EQ_INT(g.sstart[m.nv], 4 * m.nt);
    CHECK(maxdeg <= 14);
    pw_tetrings_free(NULL, &g);
    free(faces);
    free(nb);
    free_mesh(&m);
}

static void t_barycentric_locate(void)
{
    pw_tetmesh m;
    pw_tetgrid g;
    pw_rng rng = pw_rng_seed(3, 1);
    pw_err e;
    int i, k, bad = 0;
    pw_err_clear(&e);
    REQUIRE(cube_mesh(5, &m));
    REQUIRE(pw_tetgrid_build(NULL, &m, &g, &e) == PW_OK);
    for (i = 0; i < 2000; i++) {
        double p[3], l[4], q[3] = {0, 0, 0};
        int t;
        for (k = 0; k < 3; k++) p[k] = pw_rng_double(&rng);
        t = pw_tetgrid_locate(&g, &m, p, l);
        if (t < 0) {
            bad++;
            continue;
        }
        for (k = 0; k < 4; k++) {
            int j;
            if (l[k] < -1e-6) bad++;
            for (j = 0; j < 3; j++) q[j] += l[k] * m.pos[3 * m.tet[4 * t + k] + j];
        }
        for (k = 0; k < 3; k++)
            if (fabs(q[k] - p[k]) > 1e-6) bad++;
    }
    CHECK_EQ_INT(bad, 0);
    {
        double out[3] = {1.5, 0.5, 0.5}, l[4];
        CHECK_EQ_INT(pw_tetgrid_locate(&g, &m, out, l), -1);
    }
    pw_tetgrid_free(NULL, &g);
    free_mesh(&m);
}

/* ---- files ---------------------------------------------------------------------- */

static int same_mesh(const pw_tetmesh *a, const pw_tetmesh *b)
{
    return a->nv == b->nv && a->nt == b->nt && !memcmp(a->pos, b->pos, sizeof(float) * 3 * (size_t)a->nv) &&
           !memcmp(a->tet, b->tet, sizeof(int) * 4 * (size_t)a->nt);
}

static void t_tetgen_roundtrip(void)
{
    pw_tetmesh m, back;
    pw_buf node, ele;
    pw_err e;
    int k;
    pw_err_clear(&e);
    REQUIRE(cube_mesh(3, &m));
    for (k = 0; k < m.nv; k++) m.pos[3 * k] = m.pos[3 * k] * 0.7f + 1e-3f / 3.0f; /* digits that need care */
    REQUIRE(pw_tetmesh_check(&m, "cube", &e) == PW_OK);
    memset(&node, 0, sizeof node);
    memset(&ele, 0, sizeof ele);
    REQUIRE(pw_tetgen_write_node(&m, pw_buf_write, &node, &e) == PW_OK);
    REQUIRE(pw_tetgen_write_ele(&m, pw_buf_write, &ele, &e) == PW_OK);
    REQUIRE(tg_read(NULL, pw_memfile_of(node.data, node.size, "c.node"), pw_memfile_of(ele.data, ele.size, "c.ele"),
                    &back, &e) == PW_OK);
    CHECK(same_mesh(&m, &back));
    free_mesh(&back);
    free(node.data);
    free(ele.data);
    memset(&node, 0, sizeof node);
    REQUIRE(pw_medit_write(&m, pw_buf_write, &node, &e) == PW_OK);
    REQUIRE(pw_medit_read_memory(NULL, node.data, node.size, "c.mesh", &back, &e) == PW_OK);
    CHECK(same_mesh(&m, &back));
    free_mesh(&back);
    free(node.data);
    free_mesh(&m);
}

/* What TetGen writes: 1-based numbering, attributes, markers, comments,
 * 10-node tetrahedra. */
static void t_tetgen_variants(void)
{
    static const char node[] = "# comment\n5 3 1 1\n1 0 0 -1 7.5 1\n2 1 0 0 0 1\n 3 0 1 0 0 0 # x\n4 -1 -1 0 2 1\n\n5 0 0 1 0 1\n";
    static const char ele[] = "2 10 1\n1 1 2 3 4 1 1 1 1 1 1 -1\n2 5 2 4 3 1 1 1 1 1 1 -2\n";
    static const char medit[] = "MeshVersionFormatted 2\nDimension\n3\nVertices\n5\n0 0 -1 0\n1 0 0 0 0 1 0 0\n-1 -1 0 0\n"
                                "0 0 1 3\n# c\nTriangles 1\n1 2 3 0\nTetrahedra 2\n1 2 3 4 1\n5 2 4 3 1\nCorners 1 1\nEnd\n";
    pw_tetmesh m;
    pw_err e;
    pw_err_clear(&e);
    REQUIRE(tg_read(NULL, pw_memfile_of(node, sizeof node - 1, "v.node"), pw_memfile_of(ele, sizeof ele - 1, "v.ele"),
                    &m, &e) == PW_OK);
    CHECK_EQ_INT(m.nv, 5);
    CHECK_EQ_INT(m.nt, 2);
    CHECK_EQ_INT(m.tet[4], 4);
    CHECK(pw_tet_volume6(&m, 0) > 0.0 && pw_tet_volume6(&m, 1) > 0.0);
    free_mesh(&m);
    REQUIRE(pw_medit_read_memory(NULL, medit, sizeof medit - 1, "v.mesh", &m, &e) == PW_OK);
    CHECK_EQ_INT(m.nv, 5);
    CHECK_EQ_INT(m.nt, 2);
    CHECK(m.pos[3 * 3 + 1] == -1.0f);
    free_mesh(&m);
}

typedef struct bad_case {
    const char *node, *ele, *what;
    int code;
} bad_case;

static void t_tetgen_bad(void)
{
    static const char okn[] = "4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n";
    static const char oke[] = "1 4 0\n0 0 1 2 3\n";
    static const bad_case cases[] = {
        {"", oke, "node header", PW_ERR_PARSE},
        {"4 2 0 0\n", oke, "dimension 2", PW_ERR_UNSUPPORTED},
        {"9999999 3 0 0\n0 0 0 0\n", oke, "too short", PW_ERR_PARSE},
        {"999999999999 3 0 0\n", oke, "over the limit", PW_ERR_LIMIT},
        {"4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n", oke, "point 3", PW_ERR_PARSE},
        {"4 3 0 0\n0 0 0 0\n1 1 0 0\n3 0 1 0\n2 0 0 1\n", oke, "numbered 3", PW_ERR_PARSE},
        {"4 3 0 0\n0 0 0 0\n1 1 0 nan\n2 0 1 0\n3 0 0 1\n", oke, "non-finite", PW_ERR_INVALID},
        {"4 3 0 0\n0 0 0 0 9\n1 1 0 0\n2 0 1 0\n3 0 0 1\n", oke, "unexpected text", PW_ERR_PARSE},
        {"4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 x\n", oke, "malformed", PW_ERR_PARSE},
        {okn, "1 4 0\n0 0 1 2 4\n", "point 4 does not exist", PW_ERR_INVALID},
        {okn, "1 4 0\n0 0 1 2\n", "missing", PW_ERR_PARSE},
        {okn, "1 6 0\n0 0 1 2 3 0 0\n", "nodes per", PW_ERR_UNSUPPORTED},
        {okn, "2 4 0\n0 0 1 2 3\n", "tetrahedron 1", PW_ERR_PARSE},
        {okn, "1 4 0\n0 0 1 2 3\n1 0 1 2 3\n", "after the last", PW_ERR_PARSE},
        {okn, "1 4 0\n0 0 1 2 2\n", "twice", PW_ERR_DEGENERATE},
        {"4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 1 1 0\n", oke, "zero volume", PW_ERR_DEGENERATE},
    };
    size_t k;
    for (k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        pw_tetmesh m;
        pw_err e;
        int r;
        pw_err_clear(&e);
        r = tg_read(NULL, pw_memfile_of(cases[k].node, strlen(cases[k].node), "b.node"),
                    pw_memfile_of(cases[k].ele, strlen(cases[k].ele), "b.ele"), &m, &e);
        CHECKF(r == cases[k].code && strstr(e.msg, cases[k].what) && !m.pos && !m.tet,
               "case %d: code %d, message '%s' (expected %d, '%s')", (int)k, r, e.msg, cases[k].code, cases[k].what);
    }
}

static void t_medit_bad(void)
{
    static const char *const cases[][2] = {
        {"MeshVersionFormatted 1\nDimension 2\n", "Dimension 2"},
        {"MeshVersionFormatted 1\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\nEnd\n", "no Tetrahedra"},
        {"Vertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\nTetrahedra\n1\n1 2 3 5 0\n", "vertex 5 does not exist"},
        {"Vertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\nTetrahedra\n1\n1 2 3\n", "missing"},
        {"Tetrahedra\n1\n1 2 3 4 0\n", "before Vertices"},
        {"Vertices\n100000\n0 0 0 0\n", "too short"},
        {"Vertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\nSolAtVertices 1\n", "unknown MEDIT keyword 'SolAtVertices'"},
        {"\x01\0\0\0\x02\0\0\0", "binary"},
        {"Vertices\n4\n0 0 0 0\n1 0 inf 0\n0 1 0 0\n0 0 1 0\n", "non-finite"},
    };
    size_t k;
    for (k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        pw_tetmesh m;
        pw_err e;
        size_t n = k == 7 ? 8 : strlen(cases[k][0]);
        pw_err_clear(&e);
        CHECKF(pw_medit_read_memory(NULL, cases[k][0], n, "b.mesh", &m, &e) != PW_OK && strstr(e.msg, cases[k][1]) &&
                   !m.pos && !m.tet,
               "case %d: '%s' (expected '%s')", (int)k, e.msg, cases[k][1]);
    }
}

/* Every allocation of a read made to fail in turn: NOMEM, nothing leaked. */
static void t_tetio_nomem(void)
{
    pw_tetmesh m, back;
    pw_buf node, ele, medit;
    pwt_alloc_state st = {0, 0, -1};
    pw_alloc al = {pwt_malloc, pwt_realloc, pwt_free, NULL};
    pw_err e;
    long k, total, bad = 0;
    al.user = &st;
    pw_err_clear(&e);
    REQUIRE(cube_mesh(2, &m));
    memset(&node, 0, sizeof node);
    memset(&ele, 0, sizeof ele);
    memset(&medit, 0, sizeof medit);
    REQUIRE(pw_tetgen_write_node(&m, pw_buf_write, &node, &e) == PW_OK && pw_tetgen_write_ele(&m, pw_buf_write, &ele, &e) == PW_OK);
    REQUIRE(pw_medit_write(&m, pw_buf_write, &medit, &e) == PW_OK);
    REQUIRE(tg_read(&al, pw_memfile_of(node.data, node.size, "n"), pw_memfile_of(ele.data, ele.size, "e"), &back,
                    &e) == PW_OK);
    pw_tetmesh_free(&al, &back);
    REQUIRE(pw_medit_read_memory(&al, medit.data, medit.size, "m", &back, &e) == PW_OK);
    pw_tetmesh_free(&al, &back);
    total = st.calls;
    for (k = 0; k < total; k++) {
        int r1, r2;
        st.calls = 0, st.live = 0, st.fail_after = k;
        pw_err_clear(&e);
        r1 = tg_read(&al, pw_memfile_of(node.data, node.size, "n"), pw_memfile_of(ele.data, ele.size, "e"), &back, &e);
        if (r1 == PW_OK) pw_tetmesh_free(&al, &back);
        pw_err_clear(&e);
        r2 = pw_medit_read_memory(&al, medit.data, medit.size, "m", &back, &e);
        if (r2 == PW_OK) pw_tetmesh_free(&al, &back);
        if ((r1 != PW_OK && r1 != PW_ERR_NOMEM) || (r2 != PW_OK && r2 != PW_ERR_NOMEM) || st.live) bad++;
    }
    CHECK_EQ_INT(bad, 0);
    free(node.data);
    free(ele.data);
    free(medit.data);
    free_mesh(&m);
}

/* ---- TetGen's own output ----------------------------------------------------------- */

static int write_off(const char *path, const pw_mesh *s)
{
    FILE *f = fopen(path, "w");
    int v, t;
    if (!f) return 0;
    fprintf(f, "OFF\n%d %d 0\n", s->nv, s->nf);
    for (v = 0; v < s->nv; v++) fprintf(f, "%.9g %.9g %.9g\n", s->pos[3 * v], s->pos[3 * v + 1], s->pos[3 * v + 2]);
    for (t = 0; t < s->nf; t++) fprintf(f, "3 %d %d %d\n", s->fv[3 * t], s->fv[3 * t + 1], s->fv[3 * t + 2]);
    return fclose(f) == 0;
}

/* tetgen -pq1.4 on an icosphere: the output loads, is one closed solid
 * (every face paired or on the boundary), fills the sphere's volume, and
 * its angles are in TetGen's quality range. */
static void t_tetgen_output(void)
{
    pw_mesh s;
    pw_tetmesh m;
    pw_err e;
    char cmd[512];
    const char *off = pwt_tmp("tetio", 0, ".off"), *node = pwt_tmp("tetio", 0, ".1.node");
    double vol = 0.0, lo, hi;
    int *nb, *faces, nf, t;
    if (system("command -v tetgen >/dev/null 2>&1") != 0) {
        pwt_skip("tetgen is not installed");
        return;
    }
    pw_err_clear(&e);
    REQUIRE(pw_shape_geosphere(NULL, 4, &s, &e) == PW_OK);
    REQUIRE(write_off(off, &s));
    snprintf(cmd, sizeof cmd, "cd /tmp && tetgen -pq1.4Q %s >/dev/null 2>&1", off);
    REQUIRE(system(cmd) == 0);
    REQUIRE(pw_tetmesh_load(NULL, node, &m, &e) == PW_OK);
    for (t = 0; t < m.nt; t++) vol += pw_tet_volume6(&m, t) / 6.0;
    nb = (int *)malloc(sizeof(int) * 4 * (size_t)m.nt);
    REQUIRE(pw_tetmesh_neighbors(NULL, &m, nb, &e) == PW_OK);
    REQUIRE(pw_tetmesh_boundary(NULL, &m, nb, &faces, &nf, &e) == PW_OK);
    pw_tet_dihedral_range(&m, &lo, &hi);
    pwt_info("tetgen: %d vertices, %d tetrahedra, %d boundary faces, dihedral %.1f..%.1f deg, volume %.4f", m.nv, m.nt,
             nf, lo, hi, vol);
    CHECK(nf >= s.nf);
    CHECK(vol > 0.95 * 4.18879 && vol < 4.18879);
    CHECK(lo > 5.0 && hi < 175.0);
    snprintf(cmd, sizeof cmd, "rm -f /tmp/pw_test_tetio_%ld_0.*", (long)getpid());
    CHECK(system(cmd) == 0);
    free(faces);
    free(nb);
    free_mesh(&m);
    pw_mesh_free(NULL, &s);
}

static const pwt_case cases[] = {
    {"check_flips", t_check_flips},
    {"check_errors", t_check_errors},
    {"neighbors", t_neighbors},
    {"neighbors_overlap", t_neighbors_overlap},
    {"neighbors_three", t_neighbors_three},
    {"cube_adjacency", t_cube_adjacency},
    {"barycentric_locate", t_barycentric_locate},
    {"tetgen_roundtrip", t_tetgen_roundtrip},
    {"tetgen_variants", t_tetgen_variants},
    {"tetgen_bad", t_tetgen_bad},
    {"medit_bad", t_medit_bad},
    {"tetio_nomem", t_tetio_nomem},
    {"tetgen_output", t_tetgen_output},
};
PWT_MAIN(cases)
