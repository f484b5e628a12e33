/* subdiv: Catmull-Clark subdivision (Catmull and Clark 1978) with
 * boundaries.
 *
 * One step turns every face of degree d into d quads, one per corner, so
 * the result is all quads whatever the input. Output vertices, in this
 * order (deterministic, and what callers index by):
 *   [0, nv)            vertex points, one per input vertex (same index)
 *   [nv, nv+ne)        edge points, one per edge of the half-edge mesh
 *   [nv+ne, nv+ne+nf)  face points, one per input face
 * Output face h (one per input half-edge / corner) is the quad
 *   (vertex fv[h], edge of h, face of h, edge of prev(h)),
 * counter-clockwise like its face, so the quads of input face f are faces
 * fstart[f] .. fstart[f+1]-1 of the output.
 *
 * Rules:
 *   face point      centroid of the face's corners
 *   edge point      interior: (a + b + F1 + F2)/4; boundary: midpoint (a+b)/2
 *   vertex point    interior, n edges: (Q + 2R + (n-3)S)/n, with Q the mean of
 *                   the n adjacent face points, R the mean of the n edge
 *                   midpoints, S the old position
 *                   boundary: 3/4 S + 1/8 (A + B), A and B its two neighbours
 *                   along the boundary (the cubic B-spline rule, so the
 *                   boundary evolves as a curve of its own)
 *                   boundary corner (a vertex with a single face) and
 *                   isolated vertex: kept in place, so that the corners of an
 *                   open patch stay put
 * Texture coordinates are not carried. */
#ifndef PW__SUBDIV_V1
#define PW__SUBDIV_V1

#include "halfedge.h"

/* Writes the face points (at out + 3*(nv+ne)) and the edge points. */
PW__DEF void pw__cc_face_edge_points(const pw_hmesh *hm, const float *pos, float *out)
{
    float *fp = out + 3 * ((size_t)hm->nv + hm->ne), *ep = out + 3 * (size_t)hm->nv;
    int f, h, k, e;
    for (f = 0; f < hm->nf; f++) {
        double s[3] = {0, 0, 0}, inv = 1.0 / (hm->fstart[f + 1] - hm->fstart[f]);
        for (h = hm->fstart[f]; h < hm->fstart[f + 1]; h++)
            for (k = 0; k < 3; k++) s[k] += pos[3 * hm->fv[h] + k];
        for (k = 0; k < 3; k++) fp[3 * f + k] = (float)(s[k] * inv);
    }
    for (e = 0; e < hm->ne; e++) {
        int g = hm->edgeh[e], t = hm->twin[g];
        const float *a = pos + 3 * hm->fv[g], *b = pos + 3 * pw_he_dest(hm, g);
        for (k = 0; k < 3; k++) {
            if (t < 0) ep[3 * e + k] = (float)(0.5 * ((double)a[k] + b[k]));
            else
                ep[3 * e + k] =
                    (float)(0.25 * ((double)a[k] + b[k] + fp[3 * hm->hface[g] + k] + fp[3 * hm->hface[t] + k]));
        }
    }
}

/* Boundary vertex point: 3/4 S + 1/8 (A + B); A is the end of the boundary
 * half-edge leaving v, B the start of the boundary half-edge entering it,
 * found by turning counter-clockwise to the last face. */
PW__DEF void pw__cc_boundary_point(const pw_hmesh *hm, const float *pos, int v, float *out)
{
    int h = hm->vout[v], g, k, guard = 0;
    const float *s = pos + 3 * v, *a = pos + 3 * pw_he_dest(hm, h), *b;
    while ((g = pw_he_ccw(hm, h)) >= 0 && guard++ < hm->nh) h = g;
    b = pos + 3 * hm->fv[pw_he_prev(hm, h)];
    for (k = 0; k < 3; k++) out[k] = (float)(0.75 * s[k] + 0.125 * ((double)a[k] + b[k]));
}

/* Vertex points. Interior: (Q + 2R + (n-3)S)/n = (n-2)/n S + (sum of the n
 * face points + sum of the n neighbours)/n^2, accumulated per half-edge
 * leaving v (each gives one face and one neighbour). acc: nv*3 doubles,
 * cnt: nv ints, both zeroed. */
PW__DEF void pw__cc_vertex_points(const pw_hmesh *hm, const float *pos, float *out, double *acc, int *cnt)
{
    const float *fp = out + 3 * ((size_t)hm->nv + hm->ne);
    int h, v, k;
    for (h = 0; h < hm->nh; h++) {
        int o = hm->fv[h], d = pw_he_dest(hm, h), f = hm->hface[h];
        for (k = 0; k < 3; k++) acc[3 * o + k] += (double)fp[3 * f + k] + pos[3 * d + k];
        cnt[o]++;
    }
    for (v = 0; v < hm->nv; v++) {
        int n = cnt[v], h0 = hm->vout[v];
        if (h0 < 0 || (hm->twin[h0] < 0 && n == 1)) { /* isolated, or a corner */
            for (k = 0; k < 3; k++) out[3 * v + k] = pos[3 * v + k];
        } else if (hm->twin[h0] < 0) {
            pw__cc_boundary_point(hm, pos, v, out + 3 * v);
        } else {
            double a = (double)(n - 2) / n, c = 1.0 / ((double)n * n);
            for (k = 0; k < 3; k++) out[3 * v + k] = (float)(a * pos[3 * v + k] + c * acc[3 * v + k]);
        }
    }
}

/* The quads: output face h = (v, edge of h, face, edge of prev(h)). */
PW__DEF void pw__cc_quads(const pw_hmesh *hm, pw_mesh *out)
{
    int h, eb = hm->nv, fb = hm->nv + hm->ne;
    for (h = 0; h < hm->nh; h++) {
        int *q = out->fv + 4 * (size_t)h;
        q[0] = hm->fv[h];
        q[1] = eb + hm->hedge[h];
        q[2] = fb + hm->hface[h];
        q[3] = eb + hm->hedge[pw_he_prev(hm, h)];
        out->fstart[h + 1] = 4 * h + 4;
    }
    out->fstart[0] = 0;
}

/* One Catmull-Clark step of the half-edge mesh hm with positions pos
 * (hm->nv*3). out receives a new all-quad mesh (free with pw_mesh_free). */
PW__DEF int pw_catmull_clark(const pw_alloc *a, const pw_hmesh *hm, const float *pos, pw_mesh *out, pw_err *e)
{
    int64_t nv2 = (int64_t)hm->nv + hm->ne + hm->nf, nc2 = 4 * (int64_t)hm->nh;
    double *acc;
    int *cnt, r;
    memset(out, 0, sizeof *out);
    if (!pos && hm->nv > 0) return pw_fail(e, PW_ERR_INVALID, "Catmull-Clark: no positions");
    if (nv2 > PW_MAX_MESH_ELEMENTS || nc2 > PW_MAX_MESH_ELEMENTS)
        return pw_fail(e, PW_ERR_LIMIT, "Catmull-Clark: the result (%ld vertices, %ld corners) exceeds the limit of %d",
                       (long)nv2, (long)nc2, PW_MAX_MESH_ELEMENTS);
    if ((r = pw_mesh_alloc(a, out, (int)nv2, hm->nh, (int)nc2, 0, e))) return r;
    acc = (double *)pw_calloc_array(a, (size_t)hm->nv * 3, sizeof(double), "Catmull-Clark sums", e);
    cnt = (int *)pw_calloc_array(a, (size_t)hm->nv, sizeof(int), "Catmull-Clark valences", e);
    if (!acc || !cnt) {
        pw_free(a, acc);
        pw_free(a, cnt);
        pw_mesh_free(a, out);
        return PW_ERR_NOMEM;
    }
    pw__cc_face_edge_points(hm, pos, out->pos);
    pw__cc_vertex_points(hm, pos, out->pos, acc, cnt);
    pw__cc_quads(hm, out);
    pw_free(a, acc);
    pw_free(a, cnt);
    return PW_OK;
}

#endif /* PW__SUBDIV_V1 */
