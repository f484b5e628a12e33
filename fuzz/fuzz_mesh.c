/* fuzz_mesh: the OBJ/OFF/PLY/STL readers, then the half-edge build and
 * Catmull-Clark on whatever they accept. Besides crashes it checks
 * properties, aborting when one fails:
 *   - a mesh a reader accepts passes pw_mesh_validate;
 *   - OBJ write -> read reproduces it exactly;
 *   - Catmull-Clark of a mesh the half-edge build accepts is again
 *     accepted, with the same Euler characteristic and boundary loops;
 *   - every failure carries a known code and a message. */
#include "../src/common/subdiv.h"
#include <stdlib.h>

static int fz_write(void *ctx, const void *data, size_t size) { return pw_buf_write(ctx, data, size); }

static void fz_check_err(int r, const pw_err *e)
{
    if (r <= 0 || r >= PW_ERR__COUNT || e->code != r || !e->msg[0]) abort();
}

static void fz_roundtrip(const pw_mesh *m)
{
    pw_buf b;
    pw_mesh r;
    pw_err e;
    int nc = m->fstart[m->nf];
    memset(&b, 0, sizeof b);
    pw_err_clear(&e);
    if (pw_mesh_write_obj(m, "x.mtl", "x", fz_write, &b, &e) != PW_OK) abort();
    pw_err_clear(&e);
    if (pw_mesh_read_obj(NULL, b.data, b.size, "roundtrip", &r, &e) != PW_OK) abort();
    if (r.nv != m->nv || r.nf != m->nf || memcmp(r.pos, m->pos, (size_t)m->nv * 3 * sizeof(float)) ||
        memcmp(r.fstart, m->fstart, ((size_t)m->nf + 1) * sizeof(int)) ||
        memcmp(r.fv, m->fv, (size_t)nc * sizeof(int)) || (r.fuv == NULL) != (m->fuv == NULL))
        abort();
    if (m->fuv && (r.nuv != m->nuv || memcmp(r.uv, m->uv, (size_t)m->nuv * 2 * sizeof(float)) ||
                   memcmp(r.fuv, m->fuv, (size_t)nc * sizeof(int))))
        abort();
    pw_mesh_free(NULL, &r);
    free(b.data);
}

/* Half-edge invariants: twins pair opposite half-edges of one edge, edges
 * are numbered once, vout leaves its vertex (on the boundary if it is). */
static void fz_invariants(const pw_hmesh *hm)
{
    int h, nb = 0;
    for (h = 0; h < hm->nh; h++) {
        int t = hm->twin[h], e = hm->hedge[h];
        if (pw_he_prev(hm, pw_he_next(hm, h)) != h) abort();
        if (e < 0 || e >= hm->ne || (hm->edgeh[e] != h && hm->edgeh[e] != t)) abort();
        if (t < 0) {
            nb++;
            if (hm->twin[hm->vout[hm->fv[h]]] >= 0) abort();
            continue;
        }
        if (t == h || hm->twin[t] != h || hm->hedge[t] != e || pw_he_origin(hm, t) != pw_he_dest(hm, h) ||
            pw_he_dest(hm, t) != pw_he_origin(hm, h))
            abort();
    }
    if (nb != hm->nboundary || hm->ne != (hm->nh + nb) / 2) abort();
    for (h = 0; h < hm->nv; h++)
        if (hm->vout[h] >= 0 && hm->fv[hm->vout[h]] != h) abort();
}

static void fz_topology(const pw_mesh *m)
{
    pw_hmesh hm, hs;
    pw_mesh s, t;
    pw_err e;
    int r;
    pw_err_clear(&e);
    r = pw_hmesh_from_mesh(NULL, m, &hm, &e);
    if (r) {
        fz_check_err(r, &e);
        return;
    }
    fz_invariants(&hm);
    if (hm.nh <= 20000) {
        int nc = 0;
        pw_err_clear(&e);
        if (pw_hmesh_components(NULL, &hm, NULL, &nc, &e) != PW_OK) abort();
        if (pw_catmull_clark(NULL, &hm, m->pos, &s, &e) != PW_OK) abort();
        if (pw_mesh_validate(&s, &e) != PW_OK) abort();
        if (pw_hmesh_from_mesh(NULL, &s, &hs, &e) != PW_OK) abort();
        if (pw_hmesh_euler(&hs) != pw_hmesh_euler(&hm) || hs.nloops != hm.nloops) abort();
        pw_hmesh_free(NULL, &hs);
        pw_mesh_free(NULL, &s);
        if (pw_mesh_triangulate(NULL, m, &t, NULL, &e) != PW_OK) abort();
        pw_mesh_free(NULL, &t);
    }
    pw_hmesh_free(NULL, &hm);
}

typedef int (*fz_reader)(const pw_alloc *, const void *, size_t, const char *, pw_mesh *, pw_err *);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const fz_reader readers[5] = {pw_mesh_read_memory, pw_mesh_read_obj, pw_mesh_read_off,
                                         pw_mesh_read_ply, pw_mesh_read_stl};
    int k;
    for (k = 0; k < 5; k++) {
        pw_mesh m;
        pw_err e;
        int r;
        pw_err_clear(&e);
        r = readers[k](NULL, data, size, "fuzz", &m, &e);
        if (r) {
            fz_check_err(r, &e);
            if (m.pos || m.fv || m.fstart || m.nf || m.nv) abort(); /* nothing handed out */
            continue;
        }
        if (pw_mesh_validate(&m, &e) != PW_OK || m.nf == 0) abort();
        if (k == 0) { /* the others read the same mesh when they succeed */
            fz_roundtrip(&m);
            fz_topology(&m);
        }
        pw_mesh_free(NULL, &m);
    }
    return 0;
}
