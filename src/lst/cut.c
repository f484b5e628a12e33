/* cut.c: §5.1.1, cutting a model along the zero set of a scalar field
 * given at the vertices (a plane's signed distance, or the RBF field of a
 * stroke). Marching tetrahedra (Treece et al. 1999) finds where the field
 * crosses each edge; "the tetrahedral mesh is subdivided on the
 * cross-section to allow subsequent cutting operations": every crossed
 * tetrahedron is split into tetrahedra on either side, each paste gets the
 * new vertices with texture coordinates interpolated along the cut edges,
 * and the side where the field is positive is removed from view. The
 * faces the cut opened are then ordinary boundary faces, drawn with the
 * composite of their pastes. */
#include "render.c"

/* The crossed edges: (lower vertex, upper vertex) -> new vertex, in an
 * open-addressing table. */
typedef struct lst__edges {
    uint64_t *key;
    int *id;
    size_t mask;
} lst__edges;

static int *lst__edge_find(lst__edges *E, int a, int b, int insert)
{
    uint64_t k = ((uint64_t)(uint32_t)(a < b ? a : b) << 32 | (uint32_t)(a < b ? b : a)) + 1;
    size_t h = (size_t)((k * 0x9E3779B97F4A7C15ULL) >> 21) & E->mask;
    while (E->key[h] && E->key[h] != k) h = (h + 1) & E->mask;
    if (!E->key[h]) {
        if (!insert) return NULL;
        E->key[h] = k;
        E->id[h] = -1;
    }
    return &E->id[h];
}

/* The split of one tetrahedron: up to 12 sub-tetrahedra (global corners),
 * each on the negative (kept) or positive (removed) side. */
typedef struct lst__split {
    int n;
    int tet[12][4];
    unsigned char side[12]; /* 1: positive, removed */
} lst__split;

/* Field values snapped: a crossing within a thousandth of an edge's length
 * of a vertex moves onto that vertex (phi = 0), so that no sliver thinner
 * than that is made. */
static void lst__snap(const pw_tetrings *g, double *phi, int nv)
{
    int v, j;
    for (v = 0; v < nv; v++)
        for (j = g->start[v]; j < g->start[v + 1]; j++) {
            int u = g->adj[j];
            double s;
            if (u < v || !(phi[v] * phi[u] < 0.0)) continue;
            s = phi[v] / (phi[v] - phi[u]);
            if (s < 1e-3) phi[v] = 0.0;
            else if (s > 1.0 - 1e-3) phi[u] = 0.0;
        }
}

static int lst__sign(double x) { return x < 0.0 ? -1 : (x > 0.0 ? 1 : 0); }

/* The cut polygon's vertices of tetrahedron corners c (signs sg) in cyclic
 * order: the zero corners and the crossing points (one quad only when two
 * corners are on each side). */
static int lst__cut_polygon(const int *c, const int *sg, lst__edges *E, int *out)
{
    int neg[4], pos[4], nn = 0, np = 0, k, n = 0, i, j;
    for (k = 0; k < 4; k++) {
        if (sg[k] < 0) neg[nn++] = k;
        else if (sg[k] > 0) pos[np++] = k;
        else out[n++] = c[k];
    }
    if (nn == 2 && np == 2) {
        out[0] = *lst__edge_find(E, c[neg[0]], c[pos[0]], 0);
        out[1] = *lst__edge_find(E, c[neg[0]], c[pos[1]], 0);
        out[2] = *lst__edge_find(E, c[neg[1]], c[pos[1]], 0);
        out[3] = *lst__edge_find(E, c[neg[1]], c[pos[0]], 0);
        return 4;
    }
    for (i = 0; i < nn; i++)
        for (j = 0; j < np; j++) out[n++] = *lst__edge_find(E, c[neg[i]], c[pos[j]], 0);
    return n;
}

/* Face k of the tetrahedron clipped to side sd (-1 or 1): its corners on
 * that side or on the cut, and the crossing points, in order. */
static int lst__clip_face(const int *c, const int *sg, int k, int sd, lst__edges *E, int *out)
{
    int f[3], m, n = 0;
    pw_tet_face(k, f);
    for (m = 0; m < 3; m++) {
        int i = f[m], j = f[(m + 1) % 3];
        if (sg[i] == sd || sg[i] == 0) out[n++] = c[i];
        if (sg[i] * sg[j] < 0) out[n++] = *lst__edge_find(E, c[i], c[j], 0);
    }
    return n;
}

/* Appends the tetrahedra of one side: the polytope coned from its lowest
 * vertex over every face (fan-triangulated from its own lowest vertex)
 * that does not contain it. Lowest-vertex rules make the triangulation of
 * each face depend on the face alone, so neighbouring tetrahedra agree. */
static void lst__cone(int faces[5][6], const int *fn, int nf, int sd, const float *pos, lst__split *s)
{
    int apex = -1, f, i, k, lo;
    for (f = 0; f < nf; f++)
        for (i = 0; i < fn[f]; i++)
            if (apex < 0 || faces[f][i] < apex) apex = faces[f][i];
    for (f = 0; f < nf; f++) {
        for (i = 0, k = 0, lo = 0; i < fn[f]; i++) {
            k |= faces[f][i] == apex;
            if (faces[f][i] < faces[f][lo]) lo = i;
        }
        if (k) continue;
        for (i = 1; i + 1 < fn[f] && s->n < 12; i++) {
            int *t = s->tet[s->n];
            double u[3], v[3], w[3], vol;
            t[0] = apex;
            t[1] = faces[f][lo];
            t[2] = faces[f][(lo + i) % fn[f]];
            t[3] = faces[f][(lo + i + 1) % fn[f]];
            for (k = 0; k < 3; k++) {
                u[k] = (double)pos[3 * t[1] + k] - pos[3 * t[0] + k];
                v[k] = (double)pos[3 * t[2] + k] - pos[3 * t[0] + k];
                w[k] = (double)pos[3 * t[3] + k] - pos[3 * t[0] + k];
            }
            vol = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
                  u[2] * (v[0] * w[1] - v[1] * w[0]);
            if (vol == 0.0) continue;
            if (vol < 0.0) {
                k = t[2];
                t[2] = t[3];
                t[3] = k;
            }
            s->side[s->n++] = (unsigned char)(sd > 0);
        }
    }
}

/* Splits tetrahedron corners c with signs sg (both sides present). */
static void lst__split_tet(const int *c, const int *sg, lst__edges *E, const float *pos, lst__split *s)
{
    int faces[5][6], fn[5], nf, k, sd;
    s->n = 0;
    for (sd = -1; sd <= 1; sd += 2) {
        nf = 0;
        for (k = 0; k < 4; k++)
            if ((fn[nf] = lst__clip_face(c, sg, k, sd, E, faces[nf])) >= 3) nf++;
        fn[nf] = lst__cut_polygon(c, sg, E, faces[nf]);
        nf++;
        lst__cone(faces, fn, nf, sd, pos, s);
    }
}

/* The refinement under way. */
typedef struct lst__cutter {
    const pw_alloc *a;
    lst_model *m;
    int nv0, nt0, nnew, nsplit;
    int *sg; /* nv0 signs */
    lst__edges E;
    int *elo, *ehi; /* per new vertex: the edge it splits (lower, upper) */
    double *es;     /* ... and where, from lower to upper */
    int *sub_start; /* nt0+1: sub-tetrahedra of each tetrahedron (0 or >= 2 when split) */
    int *sub;       /* 4 per sub-tetrahedron */
    unsigned char *side;
    int *first_new; /* nt0: index of its second sub-tetrahedron in the new mesh */
    int nt;         /* the new mesh: nt tetrahedra, tets, removed flags */
    int *tets;
    unsigned char *rem;
    int **ptets, **pcorners, *pn; /* per paste: its new entries, until committed */
} lst__cutter;

static void lst__cutter_free(lst__cutter *C)
{
    const pw_alloc *a = C->a;
    int p;
    pw_free(a, C->sg);
    pw_free(a, C->E.key);
    pw_free(a, C->E.id);
    pw_free(a, C->elo);
    pw_free(a, C->ehi);
    pw_free(a, C->es);
    pw_free(a, C->sub_start);
    pw_free(a, C->sub);
    pw_free(a, C->side);
    pw_free(a, C->first_new);
    pw_free(a, C->tets);
    pw_free(a, C->rem);
    for (p = 0; p < C->m->npastes; p++) {
        if (C->ptets) pw_free(a, C->ptets[p]);
        if (C->pcorners) pw_free(a, C->pcorners[p]);
    }
    pw_free(a, C->ptets);
    pw_free(a, C->pcorners);
    pw_free(a, C->pn);
}

/* The crossed edges become new vertices, appended to the mesh. */
static int lst__cut_vertices(lst__cutter *C, const double *phi, pw_err *e)
{
    pw_tetmesh tm = lst__pw_tets(&C->m->mesh);
    size_t cap = 16, ne = (size_t)6 * tm.nt;
    static const int ed[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
    int t, k, n = 0, i;
    float *grown;
    while (cap < 2 * ne) cap *= 2;
    C->E.mask = cap - 1;
    C->E.key = (uint64_t *)pw_calloc_array(C->a, cap, sizeof(uint64_t), "cut edges", e);
    C->E.id = (int *)pw_alloc_array(C->a, cap, sizeof(int), "cut edges", e);
    C->elo = (int *)pw_alloc_array(C->a, ne, sizeof(int), "cut edges", e);
    C->ehi = (int *)pw_alloc_array(C->a, ne, sizeof(int), "cut edges", e);
    C->es = (double *)pw_alloc_array(C->a, ne, sizeof(double), "cut edges", e);
    if (!C->E.key || !C->E.id || !C->elo || !C->ehi || !C->es) return PW_ERR_NOMEM;
    for (t = 0; t < tm.nt; t++)
        for (k = 0; k < 6; k++) {
            int a = tm.tet[4 * t + ed[k][0]], b = tm.tet[4 * t + ed[k][1]], *id;
            if (C->sg[a] * C->sg[b] >= 0) continue;
            id = lst__edge_find(&C->E, a, b, 1);
            if (*id >= 0) continue;
            if (a > b) {
                i = a;
                a = b;
                b = i;
            }
            *id = tm.nv + n;
            C->elo[n] = a;
            C->ehi[n] = b;
            C->es[n] = phi[a] / (phi[a] - phi[b]);
            n++;
        }
    C->nnew = n;
    if (!(grown = (float *)pw_realloc(C->a, C->m->mesh.positions, ((size_t)tm.nv + n) * 3 * sizeof(float))))
        return pw_fail(e, PW_ERR_NOMEM, "out of memory adding %d cut vertices", n);
    C->m->mesh.positions = grown;
    for (i = 0; i < n; i++)
        for (k = 0; k < 3; k++) {
            double pa = grown[3 * C->elo[i] + k], pb = grown[3 * C->ehi[i] + k];
            grown[3 * (tm.nv + i) + k] = (float)(pa + C->es[i] * (pb - pa));
        }
    return PW_OK;
}

/* Every crossed tetrahedron split (the others have no sub-tetrahedra). */
static int lst__cut_split(lst__cutter *C, pw_err *e)
{
    const int *tet = C->m->mesh.tets;
    size_t cap = 0, scap = 0;
    int t, k, n = 0;
    lst__split s;
    if (!(C->sub_start = (int *)pw_alloc_array(C->a, (size_t)C->nt0 + 1, sizeof(int), "cut", e))) return PW_ERR_NOMEM;
    for (t = 0; t < C->nt0; t++) {
        int sg[4], neg = 0, pos = 0;
        C->sub_start[t] = n;
        for (k = 0; k < 4; k++) {
            sg[k] = C->sg[tet[4 * t + k]];
            neg += sg[k] < 0;
            pos += sg[k] > 0;
        }
        if (!neg || !pos) continue;
        lst__split_tet(tet + 4 * t, sg, &C->E, C->m->mesh.positions, &s);
        if (pw_grow(C->a, (void **)&C->sub, &cap, (size_t)(n + s.n) * 4, sizeof(int), "cut", e) ||
            pw_grow(C->a, (void **)&C->side, &scap, (size_t)(n + s.n), 1, "cut", e))
            return PW_ERR_NOMEM;
        memcpy(C->sub + 4 * (size_t)n, s.tet, (size_t)s.n * 4 * sizeof(int));
        memcpy(C->side + n, s.side, (size_t)s.n);
        n += s.n;
        C->nsplit++;
    }
    C->sub_start[C->nt0] = n;
    return PW_OK;
}

static int lst__nsub(const lst__cutter *C, int t) { return C->sub_start[t + 1] - C->sub_start[t]; }

/* The new tetrahedra and what is removed: a split tetrahedron's first
 * sub-tetrahedron takes its place, the others go to the end. */
static int lst__cut_mesh(lst__cutter *C, pw_err *e)
{
    const lst_model *m = C->m;
    int t, k, j, n = C->nt0;
    C->nt = C->nt0;
    for (t = 0; t < C->nt0; t++) C->nt += lst__nsub(C, t) > 0 ? lst__nsub(C, t) - 1 : 0;
    C->tets = (int *)pw_alloc_array(C->a, (size_t)C->nt * 4, sizeof(int), "cut mesh", e);
    C->rem = (unsigned char *)pw_alloc_array(C->a, (size_t)C->nt, 1, "cut mesh", e);
    C->first_new = (int *)pw_alloc_array(C->a, (size_t)C->nt0, sizeof(int), "cut mesh", e);
    if (!C->tets || !C->rem || !C->first_new) return PW_ERR_NOMEM;
    for (t = 0; t < C->nt0; t++) {
        int ns = lst__nsub(C, t), neg = 0;
        for (k = 0; k < 4; k++) neg += C->sg[m->mesh.tets[4 * t + k]] < 0;
        C->first_new[t] = n;
        if (!ns) {
            memcpy(C->tets + 4 * t, m->mesh.tets + 4 * t, 4 * sizeof(int));
            C->rem[t] = m->removed[t] || !neg; /* all on the positive side (or on the cut) */
            continue;
        }
        for (j = 0; j < ns; j++) {
            int at = j == 0 ? t : n++;
            memcpy(C->tets + 4 * at, C->sub + 4 * (C->sub_start[t] + j), 4 * sizeof(int));
            C->rem[at] = (unsigned char)(m->removed[t] || C->side[C->sub_start[t] + j]);
        }
    }
    return PW_OK;
}

/* One paste while its vertices are added (cutting it, reading it): paste
 * q (number id), the capacity of its growing vertex arrays, and per mesh
 * vertex the paste that last added it (stamp) and its local index there
 * (loc). */
typedef struct lst__paste_build {
    lst_paste *q;
    int id;
    int *stamp, *loc;
    size_t cap;
} lst__paste_build;

/* The local vertex of paste P->q for mesh vertex g, a corner of old
 * tetrahedron c (corners local in lc): an old vertex is that corner's; a
 * new one is added once per paste, its texture coordinates interpolated
 * along the cut edge. Returns -1 on failure. */
static int lst__cut_local(lst__cutter *C, lst__paste_build *P, const int *c, const int *lc, int g, pw_err *e)
{
    lst_paste *q = P->q;
    int *stamp = P->stamp, *loc = P->loc, id = P->id;
    size_t *cap = &P->cap;
    int k, ka = 0, kb = 0, n = g - C->nv0, j;
    size_t old;
    if (g < C->nv0) {
        for (k = 0; k < 3 && c[k] != g; k++) {
        }
        return lc[k];
    }
    if (stamp[n] == id) return loc[n];
    for (k = 0; k < 4; k++) {
        ka = c[k] == C->elo[n] ? k : ka;
        kb = c[k] == C->ehi[n] ? k : kb;
    }
    old = *cap;
    if (pw_grow(C->a, (void **)&q->verts, cap, (size_t)q->nverts + 1, sizeof(int), "cut paste", e)) return -1;
    if (*cap != old) {
        float *w = (float *)pw_realloc(C->a, q->uvw, *cap * 3 * sizeof(float));
        if (!w) {
            *cap = old;
            pw_fail(e, PW_ERR_NOMEM, "out of memory growing a paste");
            return -1;
        }
        q->uvw = w;
    }
    for (j = 0; j < 3; j++)
        q->uvw[3 * q->nverts + j] =
            (float)((1.0 - C->es[n]) * q->uvw[3 * lc[ka] + j] + C->es[n] * q->uvw[3 * lc[kb] + j]);
    q->verts[q->nverts] = g;
    stamp[n] = id;
    loc[n] = q->nverts;
    return q->nverts++;
}

/* Paste q's entries with the split tetrahedra replaced by their
 * sub-tetrahedra (in the same place of the list, so the compositing order
 * is kept), into new arrays; new vertices are appended to q (unused until
 * the new entries are committed). */
static int lst__cut_paste(lst__cutter *C, int id, int *stamp, int *loc, pw_err *e)
{
    lst_paste *q = &C->m->pastes[id];
    const int *old = C->m->mesh.tets;
    int i, j, k, extra = 0, n = 0, *tets, *corners;
    lst__paste_build P;
    P.q = q;
    P.id = id;
    P.stamp = stamp;
    P.loc = loc;
    P.cap = (size_t)q->nverts;
    for (i = 0; i < q->ntets; i++) extra += lst__nsub(C, q->tets[i]) > 0 ? lst__nsub(C, q->tets[i]) - 1 : 0;
    C->ptets[id] = tets = (int *)pw_alloc_array(C->a, (size_t)q->ntets + extra, sizeof(int), "cut paste", e);
    C->pcorners[id] = corners =
        (int *)pw_alloc_array(C->a, ((size_t)q->ntets + extra) * 4, sizeof(int), "cut paste", e);
    if (!tets || !corners) return PW_ERR_NOMEM;
    for (i = 0; i < q->ntets; i++) {
        int t = q->tets[i], ns = lst__nsub(C, t), lc[4];
        memcpy(lc, q->corners + 4 * i, sizeof lc);
        if (!ns) {
            tets[n] = t;
            memcpy(corners + 4 * n++, lc, sizeof lc);
            continue;
        }
        for (j = 0; j < ns; j++, n++) {
            tets[n] = j == 0 ? t : C->first_new[t] + j - 1;
            for (k = 0; k < 4; k++) {
                int g = C->sub[4 * (C->sub_start[t] + j) + k];
                if ((corners[4 * n + k] = lst__cut_local(C, &P, old + 4 * t, lc, g, e)) < 0)
                    return e->code ? e->code : PW_ERR_NOMEM;
            }
        }
    }
    C->pn[id] = n;
    return PW_OK;
}

static int lst__cut_pastes(lst__cutter *C, pw_err *e)
{
    int np = C->m->npastes, p, r = PW_OK, k, *stamp, *loc;
    C->ptets = (int **)pw_calloc_array(C->a, (size_t)np + 1, sizeof(int *), "cut", e);
    C->pcorners = (int **)pw_calloc_array(C->a, (size_t)np + 1, sizeof(int *), "cut", e);
    C->pn = (int *)pw_alloc_array(C->a, (size_t)np + 1, sizeof(int), "cut", e);
    stamp = (int *)pw_alloc_array(C->a, (size_t)C->nnew + 1, sizeof(int), "cut", e);
    loc = (int *)pw_alloc_array(C->a, (size_t)C->nnew + 1, sizeof(int), "cut", e);
    if (!C->ptets || !C->pcorners || !C->pn || !stamp || !loc) r = PW_ERR_NOMEM;
    for (k = 0; r == PW_OK && k < C->nnew; k++) stamp[k] = -1;
    for (p = 0; r == PW_OK && p < np; p++) r = lst__cut_paste(C, p, stamp, loc, e);
    pw_free(C->a, stamp);
    pw_free(C->a, loc);
    return r;
}

/* Nothing below can fail: the new mesh and entries replace the old. */
static void lst__cut_commit(lst__cutter *C)
{
    lst_model *m = C->m;
    int p;
    pw_free(C->a, m->mesh.tets);
    pw_free(C->a, m->removed);
    m->mesh.tets = C->tets;
    m->removed = C->rem;
    C->tets = NULL;
    C->rem = NULL;
    m->mesh.ntets = C->nt;
    m->mesh.nverts = C->nv0 + C->nnew;
    for (p = 0; p < m->npastes; p++) {
        lst_paste *q = &m->pastes[p];
        pw_free(C->a, q->tets);
        pw_free(C->a, q->corners);
        q->tets = C->ptets[p];
        q->corners = C->pcorners[p];
        q->ntets = C->pn[p];
        C->ptets[p] = C->pcorners[p] = NULL;
    }
}

/* The cut of §5.1.1 along phi = 0 (phi: one value per vertex, snapped in
 * place). Everything is built aside and committed at the end, so that a
 * failure leaves the model as it was (pastes may keep a few unused
 * vertices, the position array some unused room). */
static int lst__cut(const pw_alloc *a, lst_model *m, double *phi, pw_err *e)
{
    lst__cutter C;
    pw_tetmesh tm = lst__pw_tets(&m->mesh);
    pw_tetrings g;
    int v, r;
    memset(&C, 0, sizeof C);
    C.a = a;
    C.m = m;
    C.nv0 = tm.nv;
    C.nt0 = tm.nt;
    if ((r = pw_tetmesh_rings(a, &tm, &g, e)) != PW_OK) return r;
    lst__snap(&g, phi, tm.nv);
    pw_tetrings_free(a, &g);
    if (!(C.sg = (int *)pw_alloc_array(a, (size_t)tm.nv, sizeof(int), "cut", e))) return PW_ERR_NOMEM;
    for (v = 0; v < tm.nv; v++) C.sg[v] = lst__sign(phi[v]);
    if ((r = lst__cut_vertices(&C, phi, e)) == PW_OK && (r = lst__cut_split(&C, e)) == PW_OK &&
        (r = lst__cut_mesh(&C, e)) == PW_OK && (r = lst__cut_pastes(&C, e)) == PW_OK)
        lst__cut_commit(&C);
    lst__cutter_free(&C);
    return r;
}

static int lst__check_cuttable(const lst_model *m, pw_err *e)
{
    if (!m || !m->mesh.tets || !m->mesh.positions || m->mesh.ntets < 1)
        return pw_fail(e, PW_ERR_INVALID, "cut: empty model");
    if (!m->removed) return pw_fail(e, PW_ERR_INVALID, "cut: the model has no visibility flags");
    return PW_OK;
}

/* Runs a cut on the model with phi (nverts values, freed here). */
static lst_result lst__cut_with(lst_model *m, double *phi, pw_err *e, lst_error *err)
{
    pw_alloc a = lst__alloc(&m->allocator);
    lst__cut(&a, m, phi, e);
    pw_free(&a, phi);
    return lst__done(e, err);
}

LSTDEF lst_result lst_cut_plane(lst_model *model, const float plane[4], lst_error *err)
{
    pw_alloc a;
    pw_err e;
    double *phi, n[3];
    int v, k;
    pw_err_clear(&e);
    if (!plane) pw_fail(&e, PW_ERR_INVALID, "cut: NULL plane");
    if (e.code || lst__check_cuttable(model, &e)) return lst__done(&e, err);
    for (k = 0; k < 3; k++) n[k] = plane[k];
    if (!(pw_norm3(n) > 0.0) || !pw_is_finite(n[0] + n[1] + n[2] + plane[3])) {
        pw_fail(&e, PW_ERR_INVALID, "cut: the plane (%g %g %g %g) has no normal or is not finite", plane[0], plane[1],
                plane[2], plane[3]);
        return lst__done(&e, err);
    }
    a = lst__alloc(&model->allocator);
    if (!(phi = (double *)pw_alloc_array(&a, (size_t)model->mesh.nverts, sizeof(double), "cut field", &e)))
        return lst__done(&e, err);
    for (v = 0; v < model->mesh.nverts; v++) {
        const float *p = model->mesh.positions + 3 * v;
        phi[v] = (double)plane[0] * p[0] + (double)plane[1] * p[1] + (double)plane[2] * p[2] - plane[3];
    }
    return lst__cut_with(model, phi, &e, err);
}

LSTDEF lst_result lst_cut_field(lst_model *model, const float *field, lst_error *err)
{
    pw_alloc a;
    pw_err e;
    double *phi;
    int v;
    pw_err_clear(&e);
    if (!field) pw_fail(&e, PW_ERR_INVALID, "cut: NULL field");
    if (e.code || lst__check_cuttable(model, &e)) return lst__done(&e, err);
    for (v = 0; v < model->mesh.nverts; v++)
        if (!pw_is_finite(field[v])) {
            pw_fail(&e, PW_ERR_INVALID, "cut: the field at vertex %d is not finite", v);
            return lst__done(&e, err);
        }
    a = lst__alloc(&model->allocator);
    if (!(phi = (double *)pw_alloc_array(&a, (size_t)model->mesh.nverts, sizeof(double), "cut field", &e)))
        return lst__done(&e, err);
    for (v = 0; v < model->mesh.nverts; v++) phi[v] = field[v];
    return lst__cut_with(model, phi, &e, err);
}

LSTDEF void lst_uncut(lst_model *model)
{
    if (model && model->removed) memset(model->removed, 0, (size_t)model->mesh.ntets);
}

/* A stroke as drawn: n points (xyz) seen along view. */
typedef struct lst__stroke {
    const float *pts;
    int n;
    double view[3];
} lst__stroke;

/* The stroke's constraints (Turk & O'Brien's normal constraints): 0 on each
 * stroke point and on its copies swept along the view (up to L either way), +h and -h
 * at offsets h to its right and left (right: view x tangent). */
static int lst__stroke_points(const pw_alloc *a, const lst__stroke *st, double h, double L, lst__pts *out, pw_err *e)
{
    const float *pts = st->pts;
    const double *view = st->view;
    int n = st->n, i, k, s, side;
    for (i = 0; i < n; i++) {
        const float *p0 = pts + 3 * (i > 0 ? i - 1 : 0), *p1 = pts + 3 * (i + 1 < n ? i + 1 : n - 1);
        double t[3], r[3], q[3];
        for (k = 0; k < 3; k++) t[k] = (double)p1[k] - p0[k];
        pw_cross3(view, t, r);
        if (!(pw_norm3(r) > 0.0)) continue;
        for (s = -2; s <= 2; s++)
            for (side = -1; side <= 1; side++) {
                for (k = 0; k < 3; k++) q[k] = pts[3 * i + k] + 0.5 * s * L * view[k] + side * h * r[k];
                if (lst__pts_add(a, out, q, side * h, e)) return PW_ERR_NOMEM;
            }
    }
    return PW_OK;
}

LSTDEF lst_result lst_stroke_field(const lst_model *model, const float *points, int n, const float view_dir[3],
                                   float *phi, lst_error *err)
{
    pw_alloc a;
    pw_err e;
    lst__pts pts;
    lst__rbf rbf;
    lst__stroke st;
    double diag, org[3] = {0, 0, 0}, p[3];
    int k, v;
    pw_err_clear(&e);
    memset(&pts, 0, sizeof pts);
    if (!model || !model->mesh.positions || !points || n < 2 || !view_dir || !phi) {
        pw_fail(&e, PW_ERR_INVALID, "lst_stroke_field: NULL argument or fewer than 2 points");
        return lst__done(&e, err);
    }
    st.pts = points;
    st.n = n;
    for (k = 0; k < 3; k++) st.view[k] = view_dir[k];
    for (k = 0; k < 3 * n; k++)
        if (!pw_is_finite(points[k])) pw_fail(&e, PW_ERR_INVALID, "stroke point %d is not finite", k / 3);
    if (e.code == PW_OK && !(pw_norm3(st.view) > 0.0))
        pw_fail(&e, PW_ERR_INVALID, "stroke: the view direction is zero");
    if (e.code != PW_OK) return lst__done(&e, err);
    a = lst__alloc(&model->allocator);
    diag = lst__diagonal(model->mesh.positions, model->mesh.nverts);
    if (!(diag > 0.0)) diag = 1.0;
    for (k = 0; k < 3 * n; k++) org[k % 3] += points[k] / n;
    if (lst__stroke_points(&a, &st, 0.02 * diag, diag, &pts, &e) == PW_OK && pts.n == 0)
        pw_fail(&e, PW_ERR_INVALID, "stroke: every segment is parallel to the view");
    memcpy(rbf.o, org, sizeof rbf.o);
    rbf.s = diag;
    if (e.code == PW_OK && lst__rbf_fit(&a, &pts, 600, &rbf, &e) == PW_OK) {
        for (v = 0; v < model->mesh.nverts; v++) {
            for (k = 0; k < 3; k++) p[k] = model->mesh.positions[3 * v + k];
            phi[v] = (float)lst__rbf_eval(&rbf, p, NULL);
        }
        lst__rbf_free(&a, &rbf);
    }
    lst__pts_free(&a, &pts);
    return lst__done(&e, err);
}
