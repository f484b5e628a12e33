/* fuzz_stuffing: the built-in tetrahedralizer (src/common/stuffing.h) on a
 * fuzzed small surface. A 4-byte header picks the surface and the options:
 *
 *   h[0]  bits 0-1 surface: 0 raw (the rest is a vertex count byte, then
 *         3 signed bytes per vertex in 1/16 units, then 3 index bytes per
 *         triangle, modulo the count), 1 a geosphere and 2 a torus whose
 *         vertices the rest moves (3 signed bytes each, scaled by h[3]),
 *         3 OFF text;
 *         bit 2 strict, bit 3 an explicit cell (h[2]),
 *         bit 4 a counting allocator, bit 5 tetrahedralize twice,
 *         bits 6-7 the progress call that cancels (0: none)
 *   h[1]  target_tets = 50 + 4 (h[1] >> 1); bit 0: the uniform lattice (else
 *         the graded one, at a coarse fit of 0.05 + 0.05 h[2] / 256)
 *   h[2]  cell = (32 + h[2]) / 256 of the largest box extent
 *   h[3]  how far the bytes move the built-in shapes' vertices
 *
 * Work is bounded: at most FZ_MAX_TRIS triangles, about 1K tetrahedra or a
 * cell of at least 1/8 of the box, a coarse graded fit, and lattices of at
 * most 2^13 vertices (uniform) or tetrahedra (graded). Any refusal is fine; crashes, leaks,
 * sanitizer reports and the following are not:
 *   - a refusal carries its code and a message and hands nothing out;
 *   - a result has positively oriented tetrahedra with indices in range and
 *     finite coordinates, is conforming (pw_stuff_boundary), keeps its
 *     dihedral angles within the documented 10.2..161.7 degrees (uniform)
 *     or the tested 8..168 (graded), and has
 *     every boundary vertex on the input surface (or, when small holes were
 *     closed, on the closing fans: that check is skipped then);
 *   - made twice from the same input it is bit-identical;
 *   - with the counting allocator, every block goes back. */
#define PW_MAX_STUFF_LATTICE (1 << 13) /* bounded work: larger lattices are refused */
#include "../src/common/stuffing.h"
#include "../src/common/shapes.h"
#include <stdint.h>
#include <stdlib.h>

#define FZ_MAX_TRIS 400

typedef struct fz_alloc {
    long live;
} fz_alloc;

static void *fz_malloc(void *u, size_t n)
{
    void *p = malloc(n);
    if (p) ((fz_alloc *)u)->live++;
    return p;
}

static void *fz_realloc(void *u, void *p, size_t n)
{
    void *q = realloc(p, n);
    if (q && !p) ((fz_alloc *)u)->live++;
    return q;
}

static void fz_free(void *u, void *p)
{
    if (p) ((fz_alloc *)u)->live--;
    free(p);
}

static int fz_cancel(void *user, float done, const char *stage)
{
    (void)done, (void)stage;
    return --*(int *)user == 0;
}

/* The raw surface: a count byte, 3 bytes per vertex, 3 per triangle. */
static int fz_raw(const uint8_t *d, size_t n, pw_mesh *m)
{
    int nv, nt, i, k;
    pw_err e;
    if (n < 1) return 0;
    nv = 4 + d[0] % 60, d++, n--;
    if (n < (size_t)nv * 3) return 0;
    nt = (int)((n - (size_t)nv * 3) / 3);
    if (nt < 1 || nt > FZ_MAX_TRIS) return 0;
    pw_err_clear(&e);
    if (pw_mesh_alloc(NULL, m, nv, nt, 3 * nt, 0, &e) != PW_OK) return 0;
    for (i = 0; i < 3 * nv; i++) m->pos[i] = (float)(int8_t)d[i] / 16.0f;
    for (i = 0; i < 3 * nt; i++) m->fv[i] = d[3 * nv + i] % nv;
    for (k = 0; k <= nt; k++) m->fstart[k] = 3 * k;
    return 1;
}

/* A built-in closed shape whose vertices the bytes move. */
static int fz_shape(int torus, const uint8_t *d, size_t n, float scale, pw_mesh *m)
{
    pw_mesh s;
    pw_err e;
    size_t i;
    pw_err_clear(&e);
    if ((torus ? pw_shape_torus(NULL, 8, 5, 0, &s, &e) : pw_shape_geosphere(NULL, 2, &s, &e)) != PW_OK) return 0;
    for (i = 0; i < n && i < 3 * (size_t)s.nv; i++) s.pos[i] += (float)(int8_t)d[i] * scale;
    if (pw_mesh_triangulate(NULL, &s, m, NULL, &e) != PW_OK) {
        pw_mesh_free(NULL, &s);
        return 0;
    }
    pw_mesh_free(NULL, &s);
    return 1;
}

static int fz_off(const uint8_t *d, size_t n, pw_mesh *m)
{
    pw_mesh s;
    pw_err e;
    int ok;
    pw_err_clear(&e);
    if (pw_mesh_read_off(NULL, d, n, "fuzz", &s, &e) != PW_OK) return 0;
    ok = s.fstart[s.nf] <= 3 * FZ_MAX_TRIS && pw_mesh_triangulate(NULL, &s, m, NULL, &e) == PW_OK;
    pw_mesh_free(NULL, &s);
    return ok && m->nf <= FZ_MAX_TRIS;
}

static void fz_check_mesh(const pw_mesh *s, const pw_tetmesh *t, int closed_holes, int uniform)
{
    int k, *btri = NULL, nb = 0;
    double lo, hi, mag = 0.0;
    pw_stuff_fit fit;
    pw_stuff_tris in;
    pw_err e;
    if (t->nv <= 0 || t->nt <= 0 || !t->pos || !t->tet) abort();
    for (k = 0; k < 3 * t->nv; k++)
        if (!pw_is_finite(t->pos[k])) abort();
    for (k = 0; k < 4 * t->nt; k++)
        if (t->tet[k] < 0 || t->tet[k] >= t->nv) abort();
    for (k = 0; k < t->nt; k++)
        if (!(pw_tet_volume6(t, k) > 0.0)) abort();
    pw_err_clear(&e);
    if (pw_stuff_boundary(NULL, t, &btri, &nb, &e) != PW_OK || nb == 0) abort();
    pw_free(NULL, btri);
    pw_tet_dihedral_range(t, &lo, &hi);
    if (uniform ? lo < 10.2 - 1e-3 || hi > 161.7 + 1e-3 : lo < 8.0 || hi > 168.0) abort();
    in = pw_stuff_tris_of(s->pos, s->nv, s->fv, s->nf);
    if (pw_stuff_fit_measure(NULL, &in, t, 2000, &fit, &e) != PW_OK) abort();
    for (k = 0; k < 3 * s->nv; k++) mag = fabs(s->pos[k]) > mag ? fabs(s->pos[k]) : mag;
    if (!closed_holes && fit.to_surface_max > 1e-6 * (mag + fit.diag)) abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    pw_mesh m;
    pw_tetmesh t, u;
    pw_stuff_tris in;
    pw_err e;
    pw_stuff_options o = pw_stuff_default_options();
    pw_stuff_info info;
    pw_progress p;
    fz_alloc fa = {0};
    pw_alloc al;
    int ok, r, calls, mode;
    if (size < 4) return 0;
    mode = data[0] & 3;
    memset(&m, 0, sizeof m);
    if (mode == 0) ok = fz_raw(data + 4, size - 4, &m);
    else if (mode == 3) ok = fz_off(data + 4, size - 4, &m);
    else ok = fz_shape(mode == 2, data + 4, size - 4, (float)data[3] / 256.0f * 0.3f / 128.0f, &m);
    if (!ok) return 0;
    o.strict = (data[0] >> 2) & 1, o.info = &info;
    o.target_tets = 50 + 4 * (data[1] >> 1);
    o.uniform = data[1] & 1;
    if (!o.uniform) o.fit = 0.05 + 0.05 * data[2] / 256.0;
    if (data[0] & 8) {
        float lo[3], hi[3], ext = 0.0f;
        int k;
        pw_mesh_bounds(&m, lo, hi);
        for (k = 0; k < 3; k++) ext = hi[k] - lo[k] > ext ? hi[k] - lo[k] : ext;
        o.cell = ext * (32.0 + data[2]) / 256.0;
        if (!(o.cell > 0.0)) o.cell = 0.0;
    }
    al.malloc_fn = fz_malloc, al.realloc_fn = fz_realloc, al.free_fn = fz_free, al.user = &fa;
    calls = data[0] >> 6;
    p.fn = fz_cancel, p.user = &calls;
    pw_err_clear(&e);
    in = pw_stuff_tris_of(m.pos, m.nv, m.fv, m.nf);
    r = pw_stuff_tetrahedralize((data[0] & 16) ? &al : NULL, &in, &o, calls ? &p : NULL, &t, &e);
    if (r != PW_OK) {
        if (r <= 0 || r >= PW_ERR__COUNT || e.code != r || !e.msg[0] || t.pos || t.tet || t.nt || t.nv) abort();
    } else {
        fz_check_mesh(&m, &t, info.closed_holes, o.uniform);
        if (data[0] & 32) {
            pw_err_clear(&e);
            if (pw_stuff_tetrahedralize(NULL, &in, &o, NULL, &u, &e) != PW_OK) abort();
            if (u.nv != t.nv || u.nt != t.nt || memcmp(u.pos, t.pos, sizeof(float) * 3 * (size_t)t.nv) ||
                memcmp(u.tet, t.tet, sizeof(int) * 4 * (size_t)t.nt))
                abort();
            pw_tetmesh_free(NULL, &u);
        }
        pw_tetmesh_free((data[0] & 16) ? &al : NULL, &t);
    }
    if (fa.live != 0) abort();
    pw_mesh_free(NULL, &m);
    return 0;
}
