/* fuzz_tetio: the TetGen .node/.ele and MEDIT .mesh readers (tetio.h),
 * then the adjacency, boundary, rings and point location of tetmesh.h on
 * whatever they accept. The input is read as a MEDIT file, and split at its
 * first '@' into a .node and an .ele file. Besides crashes it checks, and
 * aborts when one fails:
 *   - every failure carries a known code and a message, and leaves no mesh;
 *   - an accepted mesh passes pw_tetmesh_check again (all positive);
 *   - write -> read reproduces it exactly, in both formats;
 *   - adjacency is symmetric; each boundary face is unpaired;
 *   - the barycentric coordinates of each tetrahedron's centroid found by
 *     point location are all positive and rebuild the point. */
#define FZ_NAME "fuzz_tetio"
#include "fuzz.h"
#include "../src/common/tetio.h"

/* pw_tetgen_read_memory on two files given by value. */
static int tg_read(const pw_alloc *a, pw_memfile node, pw_memfile ele, pw_tetmesh *out, pw_err *e)
{
    return pw_tetgen_read_memory(a, &node, &ele, out, e);
}

static void fz_check_err(int r, const pw_err *e, const pw_tetmesh *m)
{
    fz_check_failure(r, e->code, e->msg, sizeof e->msg);
    FZ_CHECK(!m->pos && !m->tet);
}

static void fz_same(const pw_tetmesh *a, const pw_tetmesh *b)
{
    FZ_CHECK(a->nv == b->nv && a->nt == b->nt && !memcmp(a->pos, b->pos, sizeof(float) * 3 * (size_t)a->nv) &&
             !memcmp(a->tet, b->tet, sizeof(int) * 4 * (size_t)a->nt));
}

static void fz_roundtrip(const pw_tetmesh *m)
{
    pw_buf n, el;
    pw_tetmesh r;
    pw_err e;
    memset(&n, 0, sizeof n);
    memset(&el, 0, sizeof el);
    pw_err_clear(&e);
    FZ_CHECK(!(pw_tetgen_write_node(m, pw_buf_write, &n, &e) || pw_tetgen_write_ele(m, pw_buf_write, &el, &e)));
    FZ_CHECK(tg_read(NULL, pw_memfile_of(n.data, n.size, "n"), pw_memfile_of(el.data, el.size, "e"), &r, &e) ==
             PW_OK);
    fz_same(m, &r);
    pw_tetmesh_free(NULL, &r);
    free(n.data);
    memset(&n, 0, sizeof n);
    FZ_CHECK(!(pw_medit_write(m, pw_buf_write, &n, &e) || pw_medit_read_memory(NULL, n.data, n.size, "m", &r, &e)));
    fz_same(m, &r);
    pw_tetmesh_free(NULL, &r);
    free(n.data);
    free(el.data);
}

static void fz_topology(pw_tetmesh *m)
{
    pw_tetrings g;
    pw_tetgrid grid;
    pw_err e;
    int *nb, *faces = NULL, nf, f, t;
    pw_err_clear(&e);
    FZ_CHECK(pw_tetmesh_check(m, "again", &e) == PW_OK);
    for (t = 0; t < m->nt; t++)
        FZ_CHECK(pw_tet_volume6(m, t) > 0.0);
    nb = (int *)malloc(sizeof(int) * 4 * (size_t)m->nt);
    if (pw_tetmesh_neighbors(NULL, m, nb, &e) == PW_OK) {
        for (f = 0; f < 4 * m->nt; f++)
            FZ_CHECK(nb[f] < 0 || nb[nb[f]] == f);
        FZ_CHECK(pw_tetmesh_boundary(NULL, m, nb, &faces, &nf, &e) == PW_OK);
        for (f = 0; f < nf; f++)
            FZ_CHECK(nb[faces[f]] < 0);
        free(faces);
    } else {
        FZ_CHECK(e.code == PW_ERR_TOPOLOGY && e.msg[0]);
    }
    free(nb);
    FZ_CHECK(pw_tetmesh_rings(NULL, m, &g, &e) == PW_OK);
    FZ_CHECK(g.sstart[m->nv] == 4 * m->nt);
    pw_tetrings_free(NULL, &g);
    FZ_CHECK(pw_tetgrid_build(NULL, m, &grid, &e) == PW_OK);
    for (t = 0; t < m->nt && t < 64; t++) {
        double c[3] = {0, 0, 0}, l[4];
        int k, j;
        for (k = 0; k < 4; k++)
            for (j = 0; j < 3; j++) c[j] += 0.25 * m->pos[3 * m->tet[4 * t + k] + j];
        FZ_CHECK(pw_tetgrid_locate(&grid, m, c, l) >= 0); /* the centroid is inside t at least */
    }
    pw_tetgrid_free(NULL, &grid);
}

static void fz_use(int r, pw_tetmesh *m, const pw_err *e)
{
    if (r != PW_OK) {
        fz_check_err(r, e, m);
        return;
    }
    if (m->nt <= 2000) {
        fz_roundtrip(m);
        fz_topology(m);
    }
    pw_tetmesh_free(NULL, m);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const uint8_t *at = (const uint8_t *)memchr(data, '@', size);
    pw_tetmesh m;
    pw_err e;
    pw_err_clear(&e);
    fz_use(pw_medit_read_memory(NULL, data, size, "fuzz.mesh", &m, &e), &m, &e);
    if (at) {
        size_t n = (size_t)(at - data);
        pw_err_clear(&e);
        fz_use(tg_read(NULL, pw_memfile_of(data, n, "fuzz.node"), pw_memfile_of(at + 1, size - n - 1, "fuzz.ele"), &m,
                       &e),
               &m, &e);
    }
    return 0;
}
