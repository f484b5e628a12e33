/* halfedge: half-edge connectivity of a polygon mesh.
 *
 * Half-edges are the corners of the source mesh: half-edge h belongs to the
 * face whose corners include h (fstart[f] <= h < fstart[f+1]) and runs from
 * fv[h] to the next corner of that face, so no face needs a "next" array.
 * The build copies fstart and fv (the source mesh may be freed) and refuses
 * what a half-edge structure cannot represent:
 *   PW_ERR_INVALID     a vertex index out of range
 *   PW_ERR_DEGENERATE  a face with fewer than 3 corners or a repeated vertex
 *   PW_ERR_TOPOLOGY    an edge used by more than two faces, two faces
 *                      traversing an edge in the same direction (flipped
 *                      orientation), a vertex whose faces form several fans
 * Isolated vertices are allowed (vout = -1).
 *
 * Build cost: O(corners). Half-edges are counting-sorted by origin vertex;
 * the twin of a->b is found by scanning the short list of half-edges leaving
 * b. No per-element allocation, no comparison sort. */
#ifndef PW__HALFEDGE_V1
#define PW__HALFEDGE_V1

#include "mesh.h"

typedef struct pw_hmesh {
    int nv, nf, nh, ne;
    int *fstart;   /* nf+1, owned copy: half-edges of face f are fstart[f]..fstart[f+1]-1 */
    int *fv;       /* nh, owned copy: origin vertex of each half-edge */
    int *twin;     /* nh: the opposite half-edge, -1 on the boundary */
    int *hface;    /* nh: face of each half-edge */
    int *hedge;    /* nh: edge of each half-edge */
    int *edgeh;    /* ne: the lower-index half-edge of each edge (the only one on the boundary) */
    int *vout;     /* nv: an outgoing half-edge, the boundary one on the boundary; -1 if isolated */
    int nboundary; /* boundary half-edges (= boundary edges) */
    int nloops;    /* boundary loops (holes) */
} pw_hmesh;

/* Next and previous half-edge around the same face. */
PW__DEF int pw_he_next(const pw_hmesh *hm, int h)
{
    int f = hm->hface[h];
    return h + 1 < hm->fstart[f + 1] ? h + 1 : hm->fstart[f];
}
PW__DEF int pw_he_prev(const pw_hmesh *hm, int h)
{
    int f = hm->hface[h];
    return h > hm->fstart[f] ? h - 1 : hm->fstart[f + 1] - 1;
}
PW__DEF int pw_he_origin(const pw_hmesh *hm, int h) { return hm->fv[h]; }
PW__DEF int pw_he_dest(const pw_hmesh *hm, int h) { return hm->fv[pw_he_next(hm, h)]; }

/* The next half-edge leaving the same vertex, counter-clockwise seen from
 * outside (into the neighbouring face across the previous edge); -1 when
 * that edge is on the boundary. Starting from vout[v] this visits every
 * face around v once. */
PW__DEF int pw_he_ccw(const pw_hmesh *hm, int h) { return hm->twin[pw_he_prev(hm, h)]; }

/* The same clockwise; -1 when h is on the boundary. */
PW__DEF int pw_he_cw(const pw_hmesh *hm, int h) { return hm->twin[h] < 0 ? -1 : pw_he_next(hm, hm->twin[h]); }

/* For a boundary half-edge h, the next boundary half-edge of the same
 * boundary loop (they follow each other head to tail). */
PW__DEF int pw_he_boundary_next(const pw_hmesh *hm, int h) { return hm->vout[pw_he_dest(hm, h)]; }

PW__DEF void pw_hmesh_free(const pw_alloc *a, pw_hmesh *hm)
{
    if (!hm) return;
    pw_free(a, hm->fstart);
    pw_free(a, hm->fv);
    pw_free(a, hm->twin);
    pw_free(a, hm->hface);
    pw_free(a, hm->hedge);
    pw_free(a, hm->edgeh);
    pw_free(a, hm->vout);
    memset(hm, 0, sizeof *hm);
}

/* Checks faces (index range, repeated vertices), fills hface, marks every
 * twin unknown (-2) and counts the half-edges leaving each vertex into
 * count[v+1] (count: nv+1 zeros). `stamp` (nv ints, all -1) remembers the
 * last face that used each vertex. */
PW__DEF int pw__hm_faces(pw_hmesh *hm, int *stamp, int *count, pw_err *e)
{
    int f, h;
    for (f = 0; f < hm->nf; f++) {
        int b = hm->fstart[f], end = hm->fstart[f + 1];
        for (h = b; h < end; h++) {
            int v = hm->fv[h];
            if (v < 0 || v >= hm->nv)
                return pw_fail(e, PW_ERR_INVALID,
                               "half-edge mesh: face %d, corner %d: vertex index %d out of range (%d vertices)", f,
                               h - b, v, hm->nv);
            if (stamp[v] == f)
                return pw_fail(e, PW_ERR_DEGENERATE, "half-edge mesh: face %d uses vertex %d twice", f, v);
            stamp[v] = f;
            hm->hface[h] = f;
            hm->twin[h] = -2;
            count[v + 1]++;
        }
    }
    return PW_OK;
}

/* Counting sort of half-edges by origin: the half-edges leaving v are
 * oh[ostart[v]] .. oh[ostart[v+1]-1], in increasing order, and odest[k] is
 * the destination of oh[k] (kept beside it so that searching a vertex's
 * list reads contiguous memory). */
PW__DEF void pw__hm_sort(const pw_hmesh *hm, int *ostart, int *oh, int *odest)
{
    int v, h, f;
    for (v = 0; v < hm->nv; v++) ostart[v + 1] += ostart[v]; /* counted by pw__hm_faces */
    for (f = 0; f < hm->nf; f++) {
        int b = hm->fstart[f], end = hm->fstart[f + 1];
        for (h = b; h < end; h++) {
            int k = ostart[hm->fv[h]]++;
            oh[k] = h;
            odest[k] = hm->fv[h + 1 < end ? h + 1 : b];
        }
    }
    for (v = hm->nv; v > 0; v--) ostart[v] = ostart[v - 1]; /* the fill advanced each start */
    ostart[0] = 0;
}

/* "2, 5 and 9" from an ascending list of faces. */
PW__DEF void pw__hm_face_list(char *buf, size_t cap, const int *f, int n)
{
    size_t len = 0;
    int i;
    buf[0] = 0;
    for (i = 0; i < n && i < 6 && len < cap; i++)
        len += (size_t)snprintf(buf + len, cap - len, "%s%d", i == 0 ? "" : i + 1 == n ? " and " : ", ", f[i]);
    if (n > 6 && len < cap) snprintf(buf + len, cap - len, ", ... (%d faces)", n);
}

/* The half-edges sorted by origin (pw__hm_sort): those leaving v are
 * h[start[v]] .. h[start[v+1]-1], and dest[k] is the destination of h[k]. */
typedef struct pw__hm_out {
    const int *start, *h, *dest;
} pw__hm_out;

/* The error for edge a-b: more than two faces, or two faces in the same
 * direction (counted again here: the error path only). */
PW__DEF int pw__hm_edge_error(const pw_hmesh *hm, const pw__hm_out *o, int a, int b, pw_err *e)
{
    const int *ostart = o->start, *oh = o->h, *odest = o->dest;
    int faces[8], n = 0, same = 0, opp = 0, k, i, j;
    char list[96];
    for (k = ostart[a]; k < ostart[a + 1]; k++)
        if (odest[k] == b) {
            same++;
            if (n < 8) faces[n++] = hm->hface[oh[k]];
        }
    for (k = ostart[b]; k < ostart[b + 1]; k++)
        if (odest[k] == a) {
            opp++;
            if (n < 8) faces[n++] = hm->hface[oh[k]];
        }
    for (i = 1; i < n; i++) /* insertion sort: at most 8 */
        for (j = i; j > 0 && faces[j - 1] > faces[j]; j--) {
            k = faces[j];
            faces[j] = faces[j - 1];
            faces[j - 1] = k;
        }
    if (same + opp > 2) {
        pw__hm_face_list(list, sizeof list, faces, n);
        if (same + opp > n) snprintf(list + strlen(list), sizeof list - strlen(list), " (%d faces)", same + opp);
        return pw_fail(e, PW_ERR_TOPOLOGY, "non-manifold edge v%d-v%d: used by faces %s", a, b, list);
    }
    return pw_fail(e, PW_ERR_TOPOLOGY, "inconsistent orientation: faces %d and %d both traverse edge v%d->v%d",
                   faces[0], faces[1], a, b);
}

/* Pairs half-edge h = a->b with the one b->a, if any. The common case,
 * one b->a not yet paired, needs no more checks: a second a->b would find
 * it taken. Otherwise the half-edges a->b (same) and b->a (opp) are counted
 * to catch bad edges. */
PW__DEF int pw__hm_pair(pw_hmesh *hm, const pw__hm_out *o, int h, int b, pw_err *e)
{
    const int *ostart = o->start, *oh = o->h, *odest = o->dest;
    int a = hm->fv[h], same = 0, opp = 0, g = -1, k;
    for (k = ostart[b]; k < ostart[b + 1]; k++)
        if (odest[k] == a) {
            opp++;
            g = oh[k];
        }
    if (opp != 1 || hm->twin[g] != -2) {
        for (k = ostart[a]; k < ostart[a + 1]; k++) same += odest[k] == b;
        if (same + opp > 2 || same > 1) return pw__hm_edge_error(hm, o, a, b, e);
    }
    hm->twin[h] = g;
    if (g >= 0) hm->twin[g] = h;
    else hm->nboundary++;
    return PW_OK;
}

/* Pairs every half-edge with its opposite, in half-edge order (so the
 * first bad edge reported is deterministic). */
PW__DEF int pw__hm_twins(pw_hmesh *hm, const pw__hm_out *o, pw_err *e)
{
    int h, f, r;
    hm->nboundary = 0; /* twins were set to -2 (not yet paired) by pw__hm_faces */
    for (f = 0; f < hm->nf; f++) {
        int b = hm->fstart[f], end = hm->fstart[f + 1];
        for (h = b; h < end; h++)
            if (hm->twin[h] == -2 && (r = pw__hm_pair(hm, o, h, hm->fv[h + 1 < end ? h + 1 : b], e))) return r;
    }
    hm->ne = (hm->nh + hm->nboundary) / 2;
    return PW_OK;
}

/* Fans around v, counted exactly (error path only): each open fan starts
 * at a boundary half-edge; what is left forms closed cycles. */
PW__DEF int pw__hm_count_fans(const pw_hmesh *hm, const int *ostart, const int *oh, unsigned char *mark, int v)
{
    int k, fans = 0, pass;
    for (pass = 0; pass < 2; pass++)
        for (k = ostart[v]; k < ostart[v + 1]; k++) {
            int h = oh[k], guard = 0;
            if (mark[h] || (pass == 0 && hm->twin[h] >= 0)) continue;
            fans++;
            while (h >= 0 && !mark[h] && guard++ <= ostart[v + 1] - ostart[v]) {
                mark[h] = 1;
                h = pw_he_ccw(hm, h);
            }
        }
    return fans;
}

PW__DEF int pw__hm_fan_error(const pw_hmesh *hm, const int *ostart, const int *oh, int v, const pw_alloc *a, pw_err *e)
{
    unsigned char *mark = (unsigned char *)pw_calloc_array(a, (size_t)hm->nh, 1, "fan marks", e);
    int fans;
    if (!mark) return PW_ERR_NOMEM;
    fans = pw__hm_count_fans(hm, ostart, oh, mark, v);
    pw_free(a, mark);
    return pw_fail(e, PW_ERR_TOPOLOGY, "non-manifold vertex %d: its faces form %d separate fans", v, fans);
}

/* Chooses vout (the lowest boundary half-edge leaving v, else the lowest
 * one) and checks that the faces around v form a single fan: walking
 * counter-clockwise from vout must meet every outgoing half-edge. */
PW__DEF int pw__hm_vertices(pw_hmesh *hm, const int *ostart, const int *oh, const pw_alloc *a, pw_err *e)
{
    int v, k;
    for (v = 0; v < hm->nv; v++) {
        int lo = ostart[v], deg = ostart[v + 1] - lo, start, h, count = 1;
        if (deg == 0) {
            hm->vout[v] = -1;
            continue;
        }
        start = oh[lo];
        for (k = lo; k < lo + deg; k++)
            if (hm->twin[oh[k]] < 0) {
                start = oh[k];
                break;
            }
        hm->vout[v] = start;
        for (h = pw_he_ccw(hm, start); h >= 0 && h != start && count <= deg; h = pw_he_ccw(hm, h)) count++;
        if (count != deg) return pw__hm_fan_error(hm, ostart, oh, v, a, e);
    }
    return PW_OK;
}

/* Numbers the edges in half-edge order. */
PW__DEF void pw__hm_edges(pw_hmesh *hm)
{
    int h, ne = 0;
    for (h = 0; h < hm->nh; h++) {
        int t = hm->twin[h];
        if (t >= 0 && t < h) continue;
        hm->hedge[h] = ne;
        if (t >= 0) hm->hedge[t] = ne;
        hm->edgeh[ne++] = h;
    }
}

/* Counts boundary loops; `mark` holds nh ints. */
PW__DEF void pw__hm_loops(pw_hmesh *hm, int *mark)
{
    int h;
    hm->nloops = 0;
    if (hm->nboundary == 0) return; /* closed */
    memset(mark, 0, (size_t)hm->nh * sizeof(int));
    for (h = 0; h < hm->nh; h++) {
        int g = h, guard = 0;
        if (hm->twin[h] >= 0 || mark[h]) continue;
        hm->nloops++;
        do {
            mark[g] = 1;
            g = pw_he_boundary_next(hm, g);
        } while (g != h && g >= 0 && guard++ < hm->nboundary);
    }
}

PW__DEF int pw__hm_alloc(const pw_alloc *a, pw_hmesh *hm, pw_err *e)
{
    size_t nh = (size_t)hm->nh;
    hm->fv = (int *)pw_alloc_array(a, nh, sizeof(int), "half-edge origins", e);
    hm->twin = (int *)pw_alloc_array(a, nh, sizeof(int), "half-edge twins", e);
    hm->hface = (int *)pw_alloc_array(a, nh, sizeof(int), "half-edge faces", e);
    hm->hedge = (int *)pw_alloc_array(a, nh, sizeof(int), "half-edge edges", e);
    hm->vout = (int *)pw_alloc_array(a, (size_t)hm->nv, sizeof(int), "vertex half-edges", e);
    return hm->fv && hm->twin && hm->hface && hm->hedge && hm->vout ? PW_OK : PW_ERR_NOMEM;
}

/* Checks the face offsets and copies them: fstart[0] = 0, each face at
 * least 3 corners, the total within PW_MAX_MESH_ELEMENTS. */
PW__DEF int pw__hm_offsets(const pw_alloc *a, pw_hmesh *hm, const int *fstart, pw_err *e)
{
    int f;
    if (hm->nv < 0 || hm->nf < 0 || !fstart || hm->nv > PW_MAX_MESH_ELEMENTS || hm->nf > PW_MAX_MESH_ELEMENTS)
        return pw_fail(e, PW_ERR_INVALID, "half-edge mesh: bad sizes (%d vertices, %d faces)", hm->nv, hm->nf);
    if (fstart[0] != 0) return pw_fail(e, PW_ERR_INVALID, "half-edge mesh: fstart[0] is %d, must be 0", fstart[0]);
    for (f = 0; f < hm->nf; f++) {
        if (fstart[f + 1] > PW_MAX_MESH_ELEMENTS)
            return pw_fail(e, PW_ERR_LIMIT, "half-edge mesh: more than %d corners", PW_MAX_MESH_ELEMENTS);
        if (fstart[f + 1] < fstart[f] + 3)
            return pw_fail(e, PW_ERR_DEGENERATE, "half-edge mesh: face %d has %ld corners (at least 3 needed)", f,
                           (long)fstart[f + 1] - fstart[f]);
    }
    hm->nh = fstart[hm->nf];
    hm->fstart = (int *)pw_alloc_array(a, (size_t)hm->nf + 1, sizeof(int), "half-edge faces", e);
    if (!hm->fstart) return PW_ERR_NOMEM;
    memcpy(hm->fstart, fstart, ((size_t)hm->nf + 1) * sizeof(int));
    return PW_OK;
}

/* Runs the build steps after allocation; tmp holds nv+1 + nh ints. The
 * sorted half-edge list lives in hedge until the edges are numbered. */
PW__DEF int pw__hm_steps(const pw_alloc *a, pw_hmesh *hm, int *tmp, pw_err *e)
{
    int *ostart = tmp, *odest = tmp + hm->nv + 1, *oh = hm->hedge, r, v;
    pw__hm_out out;
    out.start = ostart;
    out.h = oh;
    out.dest = odest;
    for (v = 0; v < hm->nv; v++) hm->vout[v] = -1;
    memset(ostart, 0, ((size_t)hm->nv + 1) * sizeof(int));
    if ((r = pw__hm_faces(hm, hm->vout, ostart, e))) return r;
    pw__hm_sort(hm, ostart, oh, odest);
    if ((r = pw__hm_twins(hm, &out, e))) return r;
    if ((r = pw__hm_vertices(hm, ostart, oh, a, e))) return r;
    hm->edgeh = (int *)pw_alloc_array(a, (size_t)hm->ne, sizeof(int), "edges", e);
    if (!hm->edgeh) return PW_ERR_NOMEM;
    pw__hm_edges(hm);
    pw__hm_loops(hm, odest);
    return PW_OK;
}

/* Builds the half-edge structure of a polygon mesh given as nv vertices, nf
 * faces, offsets fstart (nf+1) and corners fv (fstart[nf]); see the top of
 * the file for what is refused. */
PW__DEF int pw_hmesh_build(const pw_alloc *a, int nv, int nf, const int *fstart, const int *fv, pw_hmesh *out,
                           pw_err *e)
{
    int r, *tmp = NULL;
    memset(out, 0, sizeof *out);
    out->nv = nv;
    out->nf = nf;
    r = pw__hm_offsets(a, out, fstart, e);
    if (r == PW_OK && out->nh > 0 && !fv) r = pw_fail(e, PW_ERR_INVALID, "half-edge mesh: no corner array");
    if (r == PW_OK) r = pw__hm_alloc(a, out, e);
    if (r == PW_OK) {
        tmp = (int *)pw_alloc_array(a, (size_t)nv + 1 + (size_t)out->nh, sizeof(int), "half-edge sort", e);
        if (!tmp) r = PW_ERR_NOMEM;
    }
    if (r == PW_OK) {
        if (out->nh) memcpy(out->fv, fv, (size_t)out->nh * sizeof(int));
        r = pw__hm_steps(a, out, tmp, e);
    }
    pw_free(a, tmp);
    if (r) pw_hmesh_free(a, out);
    return r;
}

/* The same from a pw_mesh. */
PW__DEF int pw_hmesh_from_mesh(const pw_alloc *a, const pw_mesh *m, pw_hmesh *out, pw_err *e)
{
    return pw_hmesh_build(a, m->nv, m->nf, m->fstart, m->fv, out, e);
}

/* Connected components of faces (faces sharing an edge are connected).
 * Returns the count in *ncomp; face_comp (nf ints, may be NULL) receives
 * each face's component, numbered in order of their lowest face. */
PW__DEF int pw_hmesh_components(const pw_alloc *a, const pw_hmesh *hm, int *face_comp, int *ncomp, pw_err *e)
{
    int *comp = face_comp, *stack, f, n = 0, top;
    *ncomp = 0;
    stack =
        (int *)pw_alloc_array(a, (size_t)hm->nf + (face_comp ? 0 : (size_t)hm->nf), sizeof(int), "component stack", e);
    if (!stack) return PW_ERR_NOMEM;
    if (!comp) comp = stack + hm->nf;
    for (f = 0; f < hm->nf; f++) comp[f] = -1;
    for (f = 0; f < hm->nf; f++) {
        if (comp[f] >= 0) continue;
        comp[f] = n;
        stack[0] = f;
        top = 1;
        while (top > 0) { /* flood fill across edges */
            int g = stack[--top], h;
            for (h = hm->fstart[g]; h < hm->fstart[g + 1]; h++) {
                int t = hm->twin[h];
                if (t >= 0 && comp[hm->hface[t]] < 0) {
                    comp[hm->hface[t]] = n;
                    stack[top++] = hm->hface[t];
                }
            }
        }
        n++;
    }
    pw_free(a, stack);
    *ncomp = n;
    return PW_OK;
}

/* Euler characteristic V - E + F of the surface (isolated vertices are not
 * part of it and are not counted). */
PW__DEF int pw_hmesh_euler(const pw_hmesh *hm)
{
    int v, nv = 0;
    for (v = 0; v < hm->nv; v++) nv += hm->vout[v] >= 0;
    return nv - hm->ne + hm->nf;
}

#endif /* PW__HALFEDGE_V1 */
