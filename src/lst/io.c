/* io.c: the model file, the constraint files and the file conveniences of
 * lst.h.
 *
 * A model file records a lapped solid textured model (what §6's Table 1
 * calls its size, without the exemplars, which are NRRD files):
 *
 *     lst 1
 *     nodes N
 *     <x> <y> <z>                                  (N lines)
 *     tets M
 *     <a> <b> <c> <d>                              (M lines, 0-based nodes)
 *     exemplars E
 *     exemplar <index> <nx> <ny> <nz>              (E lines)
 *     pastes K
 *     paste <exemplar-index> <tet-count>           (K blocks, in compositing order)
 *     <tet> <u0> <v0> <w0> ... <u3> <v3> <w3>      (the tet's 4 nodes, in order)
 *
 * Texture coordinates are in exemplar space (the unit cube is the
 * exemplar). Numbers are written so that they read back exactly, whatever
 * the locale. */
#include "builtin.c"

/* ---- writing the model -------------------------------------------------------------------- */

static void lst__wb_line(pw__wb *b, const char *word, const long long *v, int n)
{
    int k;
    pw__wb_str(b, word);
    for (k = 0; k < n; k++) pw__wb_int(b, v[k], ' ');
    pw__wb_str(b, "\n");
}

/* The numbering of what a model file holds: the visible tetrahedra and
 * the nodes they use (-1: not written). */
typedef struct lst__visible_part {
    int *tmap, *vmap; /* per tetrahedron, per node: its new number or -1 */
    int nt, nv;       /* how many are written */
} lst__visible_part;

/* Fills *vis (its maps allocated here); returns 0 on allocation failure. */
static int lst__visible(const pw_alloc *a, const lst_model *m, lst__visible_part *vis, pw_err *e)
{
    int t, k, *tmap, *vmap;
    vis->tmap = tmap = (int *)pw_alloc_array(a, (size_t)m->mesh.ntets, sizeof(int), "model writer", e);
    vis->vmap = vmap = (int *)pw_alloc_array(a, (size_t)m->mesh.nverts, sizeof(int), "model writer", e);
    if (!tmap || !vmap) return 0;
    vis->nt = vis->nv = 0;
    for (k = 0; k < m->mesh.nverts; k++) vmap[k] = -1;
    for (t = 0; t < m->mesh.ntets; t++) {
        tmap[t] = m->removed && m->removed[t] ? -1 : vis->nt++;
        for (k = 0; tmap[t] >= 0 && k < 4; k++)
            if (vmap[m->mesh.tets[4 * t + k]] < 0) vmap[m->mesh.tets[4 * t + k]] = 0;
    }
    for (k = 0; k < m->mesh.nverts; k++)
        if (vmap[k] == 0) vmap[k] = vis->nv++;
    return 1;
}

static void lst__write_mesh_part(pw__wb *b, const lst_model *m, const lst__visible_part *vis)
{
    const int *tmap = vis->tmap, *vmap = vis->vmap;
    int nt = vis->nt, nv = vis->nv;
    long long v[4];
    int t, k;
    v[0] = nv;
    lst__wb_line(b, "nodes", v, 1);
    for (k = 0; k < m->mesh.nverts; k++)
        if (vmap[k] >= 0) {
            pw__wb_float(b, m->mesh.positions[3 * k]);
            pw__wb_float(b, m->mesh.positions[3 * k + 1]);
            pw__wb_float(b, m->mesh.positions[3 * k + 2]);
            pw__wb_str(b, "\n");
        }
    v[0] = nt;
    lst__wb_line(b, "tets", v, 1);
    for (t = 0; t < m->mesh.ntets; t++)
        if (tmap[t] >= 0) {
            for (k = 0; k < 4; k++) v[k] = vmap[m->mesh.tets[4 * t + k]];
            lst__wb_line(b, "", v, 4);
        }
}

static void lst__write_pastes_part(pw__wb *b, const lst_model *m, const int *tmap)
{
    long long v[4];
    int p, i, k, j, n = 0;
    for (p = 0; p < m->npastes; p++) {
        for (i = 0; i < m->pastes[p].ntets && tmap[m->pastes[p].tets[i]] < 0; i++) {
        }
        n += i < m->pastes[p].ntets;
    }
    v[0] = n;
    lst__wb_line(b, "pastes", v, 1);
    for (p = 0; p < m->npastes; p++) {
        const lst_paste *q = &m->pastes[p];
        int cnt = 0;
        for (i = 0; i < q->ntets; i++) cnt += tmap[q->tets[i]] >= 0;
        if (!cnt) continue;
        v[0] = q->exemplar;
        v[1] = cnt;
        lst__wb_line(b, "paste", v, 2);
        for (i = 0; i < q->ntets; i++) {
            if (tmap[q->tets[i]] < 0) continue;
            pw__wb_int(b, tmap[q->tets[i]], 0);
            for (k = 0; k < 4; k++)
                for (j = 0; j < 3; j++) pw__wb_float(b, q->uvw[3 * q->corners[4 * i + k] + j]);
            pw__wb_str(b, "\n");
        }
    }
}

LSTDEF lst_result lst_write_model(const lst_model *m, lst_write_fn fn, void *ctx, lst_error *err)
{
    pw_alloc a;
    pw__wb b;
    pw_err e;
    long long v[4];
    lst__visible_part vis;
    int k;
    pw_err_clear(&e);
    vis.tmap = vis.vmap = NULL;
    if (!m || !fn || !m->mesh.tets) {
        pw_fail(&e, PW_ERR_INVALID, "lst_write_model: NULL argument or empty model");
        return lst__done(&e, err);
    }
    a = lst__alloc(&m->allocator);
    if (lst__visible(&a, m, &vis, &e)) {
        memset(&b, 0, sizeof b);
        b.w = fn;
        b.ctx = ctx;
        pw__wb_str(&b, "lst 1\n");
        lst__write_mesh_part(&b, m, &vis);
        v[0] = m->masks.count;
        lst__wb_line(&b, "exemplars", v, 1);
        for (k = 0; k < m->masks.count; k++) {
            v[0] = k;
            v[1] = m->masks.volumes[k].width;
            v[2] = m->masks.volumes[k].height;
            v[3] = m->masks.volumes[k].depth;
            lst__wb_line(&b, "exemplar", v, 4);
        }
        lst__write_pastes_part(&b, m, vis.tmap);
        pw__wb_done(&b, &e);
    }
    pw_free(&a, vis.tmap);
    pw_free(&a, vis.vmap);
    return lst__done(&e, err);
}

/* ---- reading the model ---------------------------------------------------------------------- */

/* A count announced in the file, at most one per `min_bytes` left. */
static int lst__read_count(pw__sc *s, const char *keyword, size_t min_bytes, int *out)
{
    long long v;
    int r = pw__sc_read_ints(s, keyword, &v, 1, 0, PW_MAX_MESH_ELEMENTS);
    if (r != PW_OK) return r;
    if ((unsigned long long)v > (unsigned long long)(s->end - s->p) / min_bytes + 1)
        return pw__sc_fail(s, PW_ERR_PARSE, "%lld %s announced, the file is too short for them", v, keyword);
    *out = (int)v;
    return PW_OK;
}

static int lst__read_mesh_part(pw__sc *s, const pw_alloc *a, lst_model *m, pw_err *e)
{
    long long c;
    int nv, nt, i, k, r;
    if ((r = lst__read_count(s, "nodes", 6, &nv)) != PW_OK) return r;
    if (!(m->mesh.positions = (float *)pw_alloc_array(a, (size_t)nv * 3, sizeof(float), "model nodes", e)))
        return PW_ERR_NOMEM;
    m->mesh.nverts = nv;
    for (i = 0; i < nv; i++) {
        pw__sc_skip_empty(s);
        for (k = 0; k < 3; k++)
            if ((r = pw__tio_coord(s, m->mesh.positions + 3 * i + k, "node", i)) != PW_OK) return r;
        if ((r = pw__tio_rest(s, 0, "node", i)) != PW_OK) return r;
    }
    if ((r = lst__read_count(s, "tets", 8, &nt)) != PW_OK) return r;
    m->mesh.tets = (int *)pw_alloc_array(a, (size_t)nt * 4, sizeof(int), "model tetrahedra", e);
    m->removed = (unsigned char *)pw_calloc_array(a, (size_t)nt, 1, "model tetrahedra", e);
    if (!m->mesh.tets || !m->removed) return PW_ERR_NOMEM;
    m->mesh.ntets = nt;
    for (i = 0; i < nt; i++) {
        pw__sc_skip_empty(s);
        for (k = 0; k < 4; k++) {
            if ((r = pw__sc_int(s, &c, "tetrahedron", i)) != PW_OK) return r;
            if (c < 0 || c >= nv)
                return pw__sc_fail(s, PW_ERR_INVALID, "tetrahedron %d: node %lld does not exist", i, c);
            m->mesh.tets[4 * i + k] = (int)c;
        }
        if ((r = pw__tio_rest(s, 0, "tetrahedron", i)) != PW_OK) return r;
    }
    return PW_OK;
}

static int lst__read_exemplars_part(pw__sc *s, const pw_alloc *a, lst_model *m, pw_err *e)
{
    long long v[4];
    int n, k, r;
    if ((r = lst__read_count(s, "exemplars", 10, &n)) != PW_OK) return r;
    if (n < 1 || n > 64) return pw__sc_fail(s, PW_ERR_LIMIT, "%d exemplars (1 to 64 expected)", n);
    if (!(m->masks.volumes = (lst_volume *)pw_calloc_array(a, (size_t)n, sizeof(lst_volume), "masks", e)))
        return PW_ERR_NOMEM;
    m->masks.count = n;
    m->masks.allocator = lst__allocator(a);
    for (k = 0; k < n; k++) {
        if ((r = pw__sc_read_ints(s, "exemplar", v, 4, 0, 65536)) != PW_OK) return r;
        if (v[0] != k) return pw__sc_fail(s, PW_ERR_PARSE, "exemplar %lld listed where exemplar %d belongs", v[0], k);
        if (v[1] < 1 || v[2] < 1 || v[3] < 1) return pw__sc_fail(s, PW_ERR_PARSE, "exemplar %d has an empty size", k);
        m->masks.volumes[k].width = (int)v[1];
        m->masks.volumes[k].height = (int)v[2];
        m->masks.volumes[k].depth = (int)v[3];
        m->masks.volumes[k].channels = 1;
        m->masks.volumes[k].allocator = lst__allocator(a);
    }
    return PW_OK;
}

/* One "<tet> u0 v0 w0 ... u3 v3 w3" line (entry i) of paste P->q: corners
 * that share a node and its coordinates share a vertex (P->loc: per node,
 * its local index in the paste whose number is in P->stamp). */
static int lst__read_entry(pw__sc *s, const pw_alloc *a, const lst_model *m, lst__paste_build *P, int i, pw_err *e)
{
    lst_paste *q = P->q;
    int *vstamp = P->stamp, *vloc = P->loc, id = P->id;
    size_t *cap = &P->cap;
    long long t;
    double x;
    float w[12];
    int k, j, r;
    pw__sc_skip_empty(s);
    if ((r = pw__sc_int(s, &t, "paste entry", i)) != PW_OK) return r;
    if (t < 0 || t >= m->mesh.ntets)
        return pw__sc_fail(s, PW_ERR_INVALID, "paste entry %d: tetrahedron %lld does not exist", i, t);
    for (k = 0; k < 12; k++) {
        if ((r = pw__sc_num(s, &x, "paste entry", i)) != PW_OK) return r;
        w[k] = pw__num_to_float(x);
        if (!pw_is_finite(w[k]))
            return pw__sc_fail(s, PW_ERR_INVALID, "paste entry %d: a texture coordinate is not finite", i);
    }
    if ((r = pw__tio_rest(s, 0, "paste entry", i)) != PW_OK) return r;
    q->tets[i] = (int)t;
    for (k = 0; k < 4; k++) {
        int node = m->mesh.tets[4 * t + k], li = vstamp[node] == id ? vloc[node] : -1;
        if (li < 0 || memcmp(q->uvw + 3 * li, w + 3 * k, 3 * sizeof(float)) != 0) {
            size_t old = *cap;
            float *grown;
            if (pw_grow(a, (void **)&q->verts, cap, (size_t)q->nverts + 1, sizeof(int), "paste", e))
                return PW_ERR_NOMEM;
            if (*cap != old) {
                if (!(grown = (float *)pw_realloc(a, q->uvw, (*cap) * 3 * sizeof(float)))) {
                    *cap = old; /* verts grew, uvw did not: keep them consistent for the next try */
                    return pw_fail(e, PW_ERR_NOMEM, "out of memory reading a paste");
                }
                q->uvw = grown;
            }
            li = q->nverts++;
            q->verts[li] = node;
            for (j = 0; j < 3; j++) q->uvw[3 * li + j] = w[3 * k + j];
            vstamp[node] = id;
            vloc[node] = li;
        }
        q->corners[4 * i + k] = li;
    }
    return PW_OK;
}

static int lst__read_pastes_part(pw__sc *s, const pw_alloc *a, lst_model *m, pw_err *e)
{
    long long v[2];
    int n, p, i, r, *vstamp, *vloc;
    if ((r = lst__read_count(s, "pastes", 10, &n)) != PW_OK) return r;
    if (!(m->pastes = (lst_paste *)pw_calloc_array(a, (size_t)n, sizeof(lst_paste), "pastes", e))) return PW_ERR_NOMEM;
    vstamp = (int *)pw_alloc_array(a, (size_t)m->mesh.nverts, sizeof(int), "model reader", e);
    vloc = (int *)pw_alloc_array(a, (size_t)m->mesh.nverts, sizeof(int), "model reader", e);
    r = !vstamp || !vloc ? PW_ERR_NOMEM : PW_OK;
    for (i = 0; r == PW_OK && i < m->mesh.nverts; i++) vstamp[i] = -1;
    for (p = 0; p < n && r == PW_OK; p++) {
        lst_paste *q = &m->pastes[p];
        lst__paste_build P;
        P.q = q;
        P.id = p;
        P.stamp = vstamp;
        P.loc = vloc;
        P.cap = 0;
        m->npastes = p + 1;
        if ((r = pw__sc_read_ints(s, "paste", v, 2, 0, PW_MAX_MESH_ELEMENTS)) != PW_OK) break;
        if (v[0] >= m->masks.count)
            r = pw__sc_fail(s, PW_ERR_PARSE, "paste %d uses exemplar %lld of %d", p, v[0], m->masks.count);
        else if (v[1] < 1 || v[1] > (long long)(s->end - s->p) / 26 + 1)
            r = pw__sc_fail(s, PW_ERR_PARSE, "paste %d announces %lld tetrahedra, the file is too short for them", p,
                            v[1]);
        if (r != PW_OK) break;
        q->exemplar = (int)v[0];
        q->tets = (int *)pw_alloc_array(a, (size_t)v[1], sizeof(int), "paste", e);
        q->corners = (int *)pw_alloc_array(a, (size_t)v[1] * 4, sizeof(int), "paste", e);
        if (!q->tets || !q->corners) r = PW_ERR_NOMEM;
        q->ntets = r == PW_OK ? (int)v[1] : 0;
        for (i = 0; i < q->ntets && r == PW_OK; i++) r = lst__read_entry(s, a, m, &P, i, e);
    }
    pw_free(a, vstamp);
    pw_free(a, vloc);
    if (r == PW_OK) {
        pw__sc_skip_empty(s);
        if (s->p < s->end) r = pw__sc_fail(s, PW_ERR_PARSE, "unexpected text after the last paste");
    }
    return r;
}

static void lst__model_stats(lst_model *m)
{
    size_t tot = 0;
    int p;
    for (p = 0; p < m->npastes; p++) tot += (size_t)m->pastes[p].ntets;
    m->layers = m->layers_before = m->mesh.ntets ? (double)tot / m->mesh.ntets : 0.0;
}

LSTDEF lst_result lst_read_model(const void *data, size_t size, const char *name, const lst_options *opt,
                                 lst_model *out, lst_error *err)
{
    lst_options o = lst__options(opt);
    pw_alloc a = lst__alloc(&o.allocator);
    long long v;
    pw__sc s;
    pw_err e;
    pw_err_clear(&e);
    if (out) memset(out, 0, sizeof *out);
    if (!out || (!data && size)) {
        pw_fail(&e, PW_ERR_INVALID, "lst_read_model: NULL argument");
        return lst__done(&e, err);
    }
    out->allocator = out->mesh.allocator = lst__allocator(&a);
    out->type = -1; /* not recorded in the file */
    pw__sc_init(&s, data, size, name ? name : "model", 0, &e);
    if (pw__sc_read_ints(&s, "lst", &v, 1, 1, 1) == PW_OK && lst__read_mesh_part(&s, &a, out, &e) == PW_OK) {
        if (lst__check_tets(&out->mesh, &e) == PW_OK && lst__read_exemplars_part(&s, &a, out, &e) == PW_OK &&
            lst__read_pastes_part(&s, &a, out, &e) == PW_OK)
            lst__model_stats(out);
    }
    if (e.code != PW_OK) lst_model_free(out);
    return lst__done(&e, err);
}

/* ---- constraint files --------------------------------------------------------------------------- */

/* The numbers left on the line (at most max) into v; returns how many. */
static int lst__read_numbers(pw__sc *s, double *v, int max, const char *what, int line, int *n)
{
    int r;
    *n = 0;
    while (!pw__sc_eol(s)) {
        if (*n == max) return pw__sc_fail(s, PW_ERR_LIMIT, "%s %d: more than %d numbers on the line", what, line, max);
        if ((r = pw__sc_num(s, &v[*n], what, line)) != PW_OK) return r;
        if (!pw_is_finite(v[*n])) return pw__sc_fail(s, PW_ERR_INVALID, "%s %d: a number is not finite", what, line);
        (*n)++;
    }
    pw__sc_next_line(s);
    return PW_OK;
}

#define LST__LINE_MAX 3000  /* numbers on one constraint line (a stroke of 1000 points) */
#define LST__STROKE_STEPS 8 /* samples per stroke segment */

/* The keywords of a constraint file, and what each line holds. */
static const char *const lst__keywords[7] = {"face", "fill", "point", "depth-stroke", "dir", "dir-stroke", "scale"};
static const char *const lst__syntax[7] = {
    "face F D",           "fill F D [CREASE]",          "point X Y Z D", "depth-stroke D X Y Z X Y Z ...",
    "dir X Y Z DX DY DZ", "dir-stroke X Y Z X Y Z ...", "scale X Y Z S"};

/* Whether cnt numbers fit keyword k. */
static int lst__count_ok(int k, int cnt)
{
    switch (k) {
    case 0: return cnt == 2;
    case 1: return cnt == 2 || cnt == 3;
    case 3: return cnt >= 4 && (cnt - 1) % 3 == 0;
    case 4: return cnt == 6;
    case 5: return cnt >= 6 && cnt % 3 == 0;
    default: return cnt == 4; /* point, scale */
    }
}

/* §4.3 the stroke tool: a depth polyline, each segment sampled. */
static int lst__depth_stroke(const pw_alloc *a, const double *v, int cnt, lst__cset *c, pw_err *e)
{
    int i, k, r = PW_OK;
    for (i = 0; r == PW_OK && i < (cnt - 1) / 3; i++) {
        const double *p = v + 1 + 3 * i, *q = i + 1 < (cnt - 1) / 3 ? p + 3 : p;
        for (k = 0; r == PW_OK && k < (q == p ? 1 : LST__STROKE_STEPS); k++) {
            double t = (double)k / LST__STROKE_STEPS,
                   x[3] = {p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1]), p[2] + t * (q[2] - p[2])};
            r = lst__add_constraint(a, c, lst__constraint(LST_CONSTRAINT_DEPTH_POINT, 0, x, NULL, v[0], 0.0), e);
        }
    }
    return r;
}

/* A direction stroke: its direction along each segment, sampled. */
static int lst__dir_stroke(const pw_alloc *a, const double *v, int cnt, lst__cset *c, pw_err *e)
{
    int i, k, r = PW_OK;
    for (i = 0; r == PW_OK && i + 1 < cnt / 3; i++) {
        const double *p = v + 3 * i, *q = p + 3;
        double d[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
        if (d[0] == 0.0 && d[1] == 0.0 && d[2] == 0.0) continue;
        for (k = 0; r == PW_OK && k < LST__STROKE_STEPS; k++) {
            double t = (k + 0.5) / LST__STROKE_STEPS, x[3] = {p[0] + t * d[0], p[1] + t * d[1], p[2] + t * d[2]};
            r = lst__add_constraint(a, c, lst__constraint(LST_CONSTRAINT_DIRECTION, 0, x, d, 0.0, 0.0), e);
        }
    }
    return r;
}

/* One line of a constraint file as read: keyword k (in lst__keywords)
 * and its numbers v (cnt of them). */
typedef struct lst__cline {
    int k;
    const double *v;
    int cnt;
} lst__cline;

/* The constraints of line ln (its count checked). */
static int lst__add_line(pw__sc *s, const pw_alloc *a, const lst__cline *ln, lst__cset *c, pw_err *e)
{
    const double *v = ln->v;
    int k = ln->k, cnt = ln->cnt;
    double depth = k == 2 ? v[3] : (k == 3 ? v[0] : v[1]);
    if (k <= 3 && !(depth >= 0.0 && depth <= 1.0)) return pw__sc_fail(s, PW_ERR_INVALID, "a depth is outside [0, 1]");
    if (k <= 1 && (v[0] < 0 || v[0] > PW_MAX_MESH_ELEMENTS || v[0] != floor(v[0])))
        return pw__sc_fail(s, PW_ERR_INVALID, "face %g is not a triangle index", v[0]);
    if (k == 4 && v[3] == 0.0 && v[4] == 0.0 && v[5] == 0.0) return pw__sc_fail(s, PW_ERR_INVALID, "a zero direction");
    if (k == 6 && !(v[3] > 0.0)) return pw__sc_fail(s, PW_ERR_INVALID, "scale %g is not positive", v[3]);
    switch (k) {
    case 0:
    case 1:
        return lst__add_constraint(a, c,
                                   lst__constraint(k == 0 ? LST_CONSTRAINT_DEPTH_FACE : LST_CONSTRAINT_DEPTH_FILL,
                                                   (int)v[0], NULL, NULL, v[1], cnt == 3 ? v[2] : 0.0),
                                   e);
    case 2: return lst__add_constraint(a, c, lst__constraint(LST_CONSTRAINT_DEPTH_POINT, 0, v, NULL, v[3], 0.0), e);
    case 3: return lst__depth_stroke(a, v, cnt, c, e);
    case 4: return lst__add_constraint(a, c, lst__constraint(LST_CONSTRAINT_DIRECTION, 0, v, v + 3, 0.0, 0.0), e);
    case 5: return lst__dir_stroke(a, v, cnt, c, e);
    default: return lst__add_constraint(a, c, lst__constraint(LST_CONSTRAINT_SCALE, 0, v, NULL, v[3], 0.0), e);
    }
}

/* One line of a constraint file. */
static int lst__constraint_line(pw__sc *s, const pw_alloc *a, double *v, lst__cset *c, int line, pw_err *e)
{
    size_t len;
    const char *w = pw__sc_word(s, &len);
    char tok[32];
    int cnt, r, k;
    for (k = 0; k < 7 && !pw__sc_is(w, len, lst__keywords[k]); k++) {
    }
    if (pw__sc_is(w, len, "stroke"))
        return pw__sc_fail(s, PW_ERR_PARSE,
                           "'stroke' is ambiguous: write 'depth-stroke D X Y Z X Y Z ...' for depths or "
                           "'dir-stroke X Y Z X Y Z ...' for directions");
    if (k == 7)
        return pw__sc_fail(s, PW_ERR_PARSE,
                           "unknown constraint '%s' (face, fill, point, depth-stroke, dir, dir-stroke, scale)",
                           pw__sc_tok(s, w, tok));
    if ((r = lst__read_numbers(s, v, LST__LINE_MAX, "constraint line", line, &cnt)) != PW_OK) return r;
    s->line--; /* messages below name the line just read */
    if (!lst__count_ok(k, cnt)) r = pw__sc_fail(s, PW_ERR_PARSE, "expected '%s'", lst__syntax[k]);
    else {
        lst__cline ln;
        ln.k = k;
        ln.v = v;
        ln.cnt = cnt;
        r = lst__add_line(s, a, &ln, c, e);
    }
    s->line++;
    return r;
}

/* Reads a constraint file line by line; '#' comments. */
static int lst__read_constraints(const pw_alloc *a, const void *data, size_t size, const char *name,
                                 lst_constraints *out, pw_err *e)
{
    pw__sc s;
    lst__cset c;
    double *v = (double *)pw_alloc_array(a, LST__LINE_MAX, sizeof(double), "constraint line", e);
    int line = 0, r = v ? PW_OK : PW_ERR_NOMEM;
    memset(&c, 0, sizeof c);
    pw__sc_init(&s, data, size, name, 0, e);
    for (pw__sc_skip_empty(&s); r == PW_OK && s.p < s.end; pw__sc_skip_empty(&s))
        r = lst__constraint_line(&s, a, v, &c, line++, e);
    if (r == PW_OK && c.n == 0) r = pw_fail(e, PW_ERR_PARSE, "%s: no constraints", s.name);
    pw_free(a, v);
    if (r != PW_OK) {
        pw_free(a, c.c);
        return r;
    }
    out->items = c.c;
    out->count = c.n;
    out->allocator = lst__allocator(a);
    return PW_OK;
}

LSTDEF lst_result lst_read_constraints(const void *data, size_t size, const char *name, const lst_options *opt,
                                       lst_constraints *out, lst_error *err)
{
    lst_options o = lst__options(opt);
    pw_alloc a = lst__alloc(&o.allocator);
    pw_err e;
    pw_err_clear(&e);
    if (out) memset(out, 0, sizeof *out);
    if (!out || (!data && size)) pw_fail(&e, PW_ERR_INVALID, "lst_read_constraints: NULL argument");
    else lst__read_constraints(&a, data, size, name ? name : "constraints", out, &e);
    return lst__done(&e, err);
}

LSTDEF void lst_constraints_free(lst_constraints *c)
{
    pw_alloc a;
    if (!c) return;
    a = lst__alloc(&c->allocator);
    pw_free(&a, c->items);
    memset(c, 0, sizeof *c);
}

/* ---- meshes, volumes, images ------------------------------------------------------------------ */

LSTDEF lst_result lst_read_tetgen(const void *node, size_t node_size, const void *ele, size_t ele_size,
                                  const char *name, const lst_options *opt, lst_tetmesh *out, lst_error *err)
{
    lst_options o = lst__options(opt);
    pw_alloc a = lst__alloc(&o.allocator);
    pw_tetmesh m;
    pw_err e;
    char nn[256], en[256];
    pw_err_clear(&e);
    if (out) memset(out, 0, sizeof *out);
    snprintf(nn, sizeof nn, "%s.node", name ? name : "tetgen");
    snprintf(en, sizeof en, "%s.ele", name ? name : "tetgen");
    if (!out || (!node && node_size) || (!ele && ele_size))
        pw_fail(&e, PW_ERR_INVALID, "lst_read_tetgen: NULL argument");
    else {
        pw_memfile fn = pw_memfile_of(node, node_size, nn), fe = pw_memfile_of(ele, ele_size, en);
        if (pw_tetgen_read_memory(&a, &fn, &fe, &m, &e) == PW_OK) lst__take_tets(&m, &a, out);
    }
    return lst__done(&e, err);
}

PW_PUBLIC_READ(lst, LSTDEF, medit, pw_tetmesh, lst_tetmesh, pw_medit_read_memory, lst__take_tets);

LSTDEF lst_result lst_write_tetgen(const lst_tetmesh *mesh, lst_write_fn node_fn, void *node_ctx, lst_write_fn ele_fn,
                                   void *ele_ctx, lst_error *err)
{
    pw_tetmesh m;
    pw_err e;
    pw_err_clear(&e);
    if (!mesh || !node_fn || !ele_fn) pw_fail(&e, PW_ERR_INVALID, "lst_write_tetgen: NULL argument");
    else if (lst__check_tets(mesh, &e) == PW_OK) {
        m = lst__pw_tets(mesh);
        if (pw_tetgen_write_node(&m, node_fn, node_ctx, &e) == PW_OK) pw_tetgen_write_ele(&m, ele_fn, ele_ctx, &e);
    }
    return lst__done(&e, err);
}

LSTDEF lst_result lst_write_medit(const lst_tetmesh *mesh, lst_write_fn fn, void *ctx, lst_error *err)
{
    pw_tetmesh m;
    pw_err e;
    pw_err_clear(&e);
    if (!mesh || !fn) pw_fail(&e, PW_ERR_INVALID, "lst_write_medit: NULL argument");
    else if (lst__check_tets(mesh, &e) == PW_OK) {
        m = lst__pw_tets(mesh);
        pw_medit_write(&m, fn, ctx, &e);
    }
    return lst__done(&e, err);
}

PW_PUBLIC_READ(lst, LSTDEF, volume, pw_volume, lst_volume, pw_nrrd_read_memory, lst__take_volume);

LSTDEF lst_result lst_write_volume(const lst_volume *vol, lst_write_fn fn, void *ctx, lst_error *err)
{
    pw_alloc a;
    pw_volume v;
    pw_err e;
    pw_err_clear(&e);
    if (!vol || !fn) pw_fail(&e, PW_ERR_INVALID, "lst_write_volume: NULL argument");
    else if (lst__check_volume(vol, "volume", &e) == PW_OK) {
        a = lst__alloc(&vol->allocator);
        v = lst__pw_volume(vol);
        pw_nrrd_write(&a, &v, 1, fn, ctx, &e);
    }
    return lst__done(&e, err);
}

PW_PUBLIC_IO(lst, LSTDEF);

LSTDEF lst_result lst_write_obj(const lst_mesh *mesh, lst_write_fn fn, void *ctx, lst_error *err)
{
    pw_mesh m;
    pw_err e;
    pw_err_clear(&e);
    if (!mesh || !fn) pw_fail(&e, PW_ERR_INVALID, "lst_write_obj: NULL argument");
    else {
        m = lst__pw_mesh(mesh);
        pw_mesh_write_obj(&m, NULL, NULL, fn, ctx, &e);
    }
    return lst__done(&e, err);
}

#ifndef PW_NO_STDIO
/* the public file loaders: each file read whole, then read from memory */
PW_PUBLIC_LOAD(lst, LSTDEF, mesh, lst_mesh);
PW_PUBLIC_LOAD(lst, LSTDEF, volume, lst_volume);
PW_PUBLIC_LOAD(lst, LSTDEF, model, lst_model);
PW_PUBLIC_LOAD(lst, LSTDEF, constraints, lst_constraints);
PW_PUBLIC_LOAD(lst, LSTDEF, image, lst_image);

LSTDEF lst_result lst_load_tetmesh(const char *path, const lst_options *opt, lst_tetmesh *out, lst_error *err)
{
    lst_options o = lst__options(opt);
    pw_alloc a = lst__alloc(&o.allocator);
    pw_tetmesh m;
    pw_err e;
    pw_err_clear(&e);
    if (out) memset(out, 0, sizeof *out);
    if (!path || !out) pw_fail(&e, PW_ERR_INVALID, "lst_load_tetmesh: NULL argument");
    else if (pw_tetmesh_load(&a, path, &m, &e) == PW_OK) lst__take_tets(&m, &a, out);
    return lst__done(&e, err);
}

LSTDEF lst_result lst_save_tetmesh(const char *path, const lst_tetmesh *mesh, lst_error *err)
{
    pw_tetmesh m;
    pw_err e;
    pw_err_clear(&e);
    if (!path || !mesh) pw_fail(&e, PW_ERR_INVALID, "lst_save_tetmesh: NULL argument");
    else if (lst__check_tets(mesh, &e) == PW_OK) {
        m = lst__pw_tets(mesh);
        pw_tetmesh_save(path, &m, &e);
    }
    return lst__done(&e, err);
}

typedef struct lst__job {
    const lst_volume *vol;
    const lst_model *model;
    const lst_mesh *mesh;
} lst__job;

static int lst__job_body(void *arg, pw_write_fn w, void *ctx, pw_err *e)
{
    const lst__job *j = (const lst__job *)arg;
    lst_error le;
    int r = j->vol    ? (int)lst_write_volume(j->vol, w, ctx, &le)
            : j->mesh ? (int)lst_write_obj(j->mesh, w, ctx, &le)
                      : (int)lst_write_model(j->model, w, ctx, &le);
    return r ? pw_fail(e, r, "%s", le.message) : PW_OK;
}

static lst_result lst__save(const char *path, lst__job *j, lst_error *err)
{
    pw_err e;
    pw_err_clear(&e);
    if (!path || (!j->vol && !j->model && !j->mesh)) pw_fail(&e, PW_ERR_INVALID, "save: NULL argument");
    else pw_write_file(path, lst__job_body, j, &e);
    return lst__done(&e, err);
}

PW_PUBLIC_SAVE_IMAGE(lst, LSTDEF);

LSTDEF lst_result lst_save_volume(const char *path, const lst_volume *vol, lst_error *err)
{
    lst__job j;
    memset(&j, 0, sizeof j);
    j.vol = vol;
    return lst__save(path, &j, err);
}

LSTDEF lst_result lst_save_model(const char *path, const lst_model *model, lst_error *err)
{
    lst__job j;
    memset(&j, 0, sizeof j);
    j.model = model;
    return lst__save(path, &j, err);
}
LSTDEF lst_result lst_save_obj(const char *path, const lst_mesh *mesh, lst_error *err)
{
    lst__job j;
    memset(&j, 0, sizeof j);
    j.mesh = mesh;
    return lst__save(path, &j, err);
}
#endif
