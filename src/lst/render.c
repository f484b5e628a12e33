/* render.c: §5.1, showing a model. Every point of a tetrahedron is the
 * composite of the pastes that hold it, in order (later over earlier):
 * each paste's texture coordinates are interpolated from the
 * tetrahedron's corners, its mask gives the alpha, the exemplar the
 * colour. The surface and the faces a cut opened are drawn with that
 * composite (§5.1: "each surface triangle is rendered multiple times using
 * the texture coordinates in its assigned list, with alpha blending"; here
 * the list is composited per pixel by the renderer's shader hook, which
 * gives the same image in one pass), §5.1.2 volume rendering draws slices
 * back to front, and direct evaluation at points serves the checks. */
#include "paste.c"

/* ---- which pastes hold each tetrahedron --------------------------------------------------- */

/* For tetrahedron t, entries start[t] .. start[t+1]-1 of paste[] and
 * slot[] (the place of t in that paste), in paste order. */
typedef struct lst__index {
    int *start, *paste, *slot;
} lst__index;

static void lst__index_free(const pw_alloc *a, lst__index *ix)
{
    pw_free(a, ix->start);
    pw_free(a, ix->paste);
    pw_free(a, ix->slot);
    memset(ix, 0, sizeof *ix);
}

static int lst__index_build(const pw_alloc *a, const lst_model *m, lst__index *ix, pw_err *e)
{
    size_t total = 0;
    int p, k, t, nt = m->mesh.ntets;
    memset(ix, 0, sizeof *ix);
    for (p = 0; p < m->npastes; p++) total += (size_t)m->pastes[p].ntets;
    ix->start = (int *)pw_calloc_array(a, (size_t)nt + 1, sizeof(int), "paste index", e);
    ix->paste = (int *)pw_alloc_array(a, total, sizeof(int), "paste index", e);
    ix->slot = (int *)pw_alloc_array(a, total, sizeof(int), "paste index", e);
    if (!ix->start || !ix->paste || !ix->slot) {
        lst__index_free(a, ix);
        return PW_ERR_NOMEM;
    }
    for (p = 0; p < m->npastes; p++)
        for (k = 0; k < m->pastes[p].ntets; k++) ix->start[m->pastes[p].tets[k] + 1]++;
    for (t = 0; t < nt; t++) ix->start[t + 1] += ix->start[t];
    for (p = 0; p < m->npastes; p++) /* counting sort: paste order is kept within each tetrahedron */
        for (k = 0; k < m->pastes[p].ntets; k++) {
            int at = ix->start[m->pastes[p].tets[k]]++;
            ix->paste[at] = p;
            ix->slot[at] = k;
        }
    for (t = nt; t > 0; t--) ix->start[t] = ix->start[t - 1];
    ix->start[0] = 0;
    return PW_OK;
}

/* Everything evaluation needs. */
typedef struct lst__view {
    const lst_model *m;
    lst__index ix;
    pw_volume tex, val, mask[64];
    int show;
    const pw_alloc *a;
} lst__view;

static void lst__view_free(lst__view *v) { lst__index_free(v->a, &v->ix); }

/* A model usable for rendering: mesh, texture and masks present, paste
 * indices within range. */
static int lst__check_model(const lst_model *m, pw_err *e)
{
    int p, k;
    if (!m || !m->mesh.tets || m->mesh.ntets < 1) return pw_fail(e, PW_ERR_INVALID, "empty model");
    if (!m->texture.voxels) return pw_fail(e, PW_ERR_INVALID, "the model has no texture (load the exemplar into it)");
    if (m->masks.count < 1 || m->masks.count > 64)
        return pw_fail(e, PW_ERR_INVALID, "the model has %d masks", m->masks.count);
    for (k = 0; k < m->masks.count; k++)
        if (!m->masks.volumes[k].voxels || m->masks.volumes[k].channels != 1)
            return pw_fail(e, PW_ERR_INVALID, "mask %d of the model is missing or has more than one channel", k);
    for (p = 0; p < m->npastes; p++) {
        const lst_paste *q = &m->pastes[p];
        if (q->exemplar < 0 || q->exemplar >= m->masks.count)
            return pw_fail(e, PW_ERR_INVALID, "paste %d uses mask %d of %d", p, q->exemplar, m->masks.count);
        for (k = 0; k < q->ntets; k++)
            if (q->tets[k] < 0 || q->tets[k] >= m->mesh.ntets)
                return pw_fail(e, PW_ERR_INVALID, "paste %d uses tetrahedron %d of %d", p, q->tets[k], m->mesh.ntets);
        for (k = 0; k < 4 * q->ntets; k++)
            if (q->corners[k] < 0 || q->corners[k] >= q->nverts)
                return pw_fail(e, PW_ERR_INVALID, "paste %d: a corner uses vertex %d of %d", p, q->corners[k],
                               q->nverts);
    }
    return PW_OK;
}

static int lst__view_init(const pw_alloc *a, const lst_model *m, int show, lst__view *v, pw_err *e)
{
    int k;
    memset(v, 0, sizeof *v);
    if (lst__check_model(m, e)) return e->code;
    if (show == LST_SHOW_VALUES && !m->values.voxels)
        return pw_fail(e, PW_ERR_INVALID, "the model has no extra channel to show");
    v->m = m;
    v->show = show;
    v->a = a;
    v->tex = lst__pw_volume(&m->texture);
    if (m->values.voxels) v->val = lst__pw_volume(&m->values);
    for (k = 0; k < m->masks.count; k++) v->mask[k] = lst__pw_volume(&m->masks.volumes[k]);
    return lst__index_build(a, m, &v->ix, e);
}

/* A colour per paste, from its index. */
static void lst__paste_colour(int p, float *c)
{
    uint64_t h = pw_hash64(0x9A57E, (uint64_t)p);
    int k;
    for (k = 0; k < 3; k++) c[k] = 0.25f + 0.7f * (float)((h >> (16 * k)) & 0xFFFF) / 65535.0f;
}

/* The model at barycentric point l of tetrahedron t: the pastes composited
 * from the top down (front to back in paste order), stopping when opaque.
 * rgba: straight colour (or what `show` asks for) and total opacity;
 * values (may be NULL): the extra channel composited the same way. */
static void lst__eval(const lst__view *v, int t, const double *l, float *rgba, float *values)
{
    float acc[4] = {0, 0, 0, 0}, vacc[4] = {0, 0, 0, 0}, T = 1.0f, col[4], vv[4];
    int i, k, j, nc = v->tex.c, vc = v->val.px && (values || v->show == LST_SHOW_VALUES) ? v->val.c : 0;
    for (i = v->ix.start[t + 1] - 1; i >= v->ix.start[t] && T > 1.0f / 1024.0f; i--) {
        const lst_paste *p = &v->m->pastes[v->ix.paste[i]];
        const int *c = p->corners + 4 * v->ix.slot[i];
        double w[3];
        float al, wt;
        for (j = 0; j < 3; j++)
            w[j] = l[0] * p->uvw[3 * c[0] + j] + l[1] * p->uvw[3 * c[1] + j] + l[2] * p->uvw[3 * c[2] + j] +
                   l[3] * p->uvw[3 * c[3] + j];
        al = lst__mask_alpha(&v->mask[p->exemplar], w[0], w[1], w[2]);
        if (!(al > 0.0f)) continue;
        wt = T * al;
        if (v->show == LST_SHOW_PASTES) lst__paste_colour(v->ix.paste[i], col);
        else if (v->show == LST_SHOW_DEPTH) {
            col[0] = (float)w[0];
            col[1] = (float)w[1];
            col[2] = (float)w[2];
        } else lst__sample(&v->tex, w[0], w[1], w[2], col);
        if (v->show == LST_SHOW_COLOR && nc == 1) col[1] = col[2] = col[0];
        for (k = 0; k < 3; k++) acc[k] += wt * col[k];
        if (vc) {
            lst__sample(&v->val, w[0], w[1], w[2], vv);
            for (k = 0; k < vc; k++) vacc[k] += wt * vv[k];
        }
        T *= 1.0f - al;
    }
    acc[3] = 1.0f - T;
    for (k = 0; k < 3; k++) rgba[k] = acc[3] > 0.0f ? acc[k] / acc[3] : 0.0f;
    rgba[3] = acc[3];
    if (v->show == LST_SHOW_VALUES) rgba[0] = rgba[1] = rgba[2] = acc[3] > 0.0f ? vacc[0] / acc[3] : 0.0f;
    for (k = 0; values && k < vc; k++) values[k] = acc[3] > 0.0f ? vacc[k] / acc[3] : 0.0f;
}

/* ---- direct evaluation at points -------------------------------------------------------------- */

LSTDEF lst_result lst_eval(const lst_model *model, const float *points, int n, float *rgba, float *values,
                           lst_error *err)
{
    pw_alloc a;
    pw_tetmesh m;
    pw_tetgrid grid;
    lst__view v;
    pw_err e;
    int i, k;
    pw_err_clear(&e);
    if (!model || (n > 0 && (!points || !rgba)) || n < 0) {
        pw_fail(&e, PW_ERR_INVALID, "lst_eval: NULL argument or negative count");
        return lst__done(&e, err);
    }
    a = lst__alloc(&model->allocator);
    if (lst__view_init(&a, model, LST_SHOW_COLOR, &v, &e) != PW_OK) return lst__done(&e, err);
    m = lst__pw_tets(&model->mesh);
    if (pw_tetgrid_build(&a, &m, &grid, &e) == PW_OK) {
        for (i = 0; i < n; i++) {
            double p[3] = {points[3 * i], points[3 * i + 1], points[3 * i + 2]}, l[4];
            int t = pw_tetgrid_locate(&grid, &m, p, l);
            if (t >= 0 && model->removed && model->removed[t]) t = -1;
            if (t < 0) {
                memset(rgba + 4 * i, 0, 4 * sizeof(float));
                for (k = 0; values && k < v.val.c; k++) values[(size_t)i * v.val.c + k] = 0.0f;
                continue;
            }
            lst__eval(&v, t, l, rgba + 4 * i, values ? values + (size_t)i * v.val.c : NULL);
        }
        pw_tetgrid_free(&a, &grid);
    }
    lst__view_free(&v);
    return lst__done(&e, err);
}

/* ---- triangles to draw ---------------------------------------------------------------------------- */

/* Triangles and, per triangle, the tetrahedron that holds it and the
 * barycentric coordinates (in that tetrahedron) of its three corners, so
 * that the shader can evaluate the model anywhere on it. */
typedef struct lst__tris {
    int n, nv;
    float *pos;     /* nv*3 (owned, or NULL when the mesh's positions are used) */
    int *tri;       /* n*3 */
    int *tet;       /* n */
    float *bary;    /* n*12 */
    float *normals; /* nv*3 smooth vertex normals (lst__tris_normals), or NULL: computed per draw */
    size_t ncap, vcap;
} lst__tris;

static void lst__tris_free(const pw_alloc *a, lst__tris *t)
{
    pw_free(a, t->pos);
    pw_free(a, t->tri);
    pw_free(a, t->tet);
    pw_free(a, t->bary);
    pw_free(a, t->normals);
    memset(t, 0, sizeof *t);
}

/* Room for one more triangle (the three arrays grow together). */
static int lst__tris_room(const pw_alloc *a, lst__tris *t, pw_err *e)
{
    size_t cap = t->ncap ? 2 * t->ncap : 256;
    void *p;
    if ((size_t)t->n < t->ncap) return PW_OK;
    if (!(p = pw_realloc(a, t->tet, cap * sizeof(int)))) goto nomem;
    t->tet = (int *)p;
    if (!(p = pw_realloc(a, t->tri, cap * 3 * sizeof(int)))) goto nomem;
    t->tri = (int *)p;
    if (!(p = pw_realloc(a, t->bary, cap * 12 * sizeof(float)))) goto nomem;
    t->bary = (float *)p;
    t->ncap = cap;
    return PW_OK;
nomem:
    return pw_fail(e, PW_ERR_NOMEM, "out of memory growing a triangle list to %lu", (unsigned long)cap);
}

#ifndef PW_NO_RENDER /* only the renderer adds vertices of its own */
/* Adds a vertex at p (own positions); returns its index or -1. */
static int lst__tris_vertex(const pw_alloc *a, lst__tris *t, const double *p, pw_err *e)
{
    if (pw_grow(a, (void **)&t->pos, &t->vcap, ((size_t)t->nv + 1) * 3, sizeof(float), "triangles", e)) return -1;
    t->pos[3 * t->nv] = (float)p[0];
    t->pos[3 * t->nv + 1] = (float)p[1];
    t->pos[3 * t->nv + 2] = (float)p[2];
    return t->nv++;
}
#endif

/* The visible boundary faces: cut = 0 those on the model's surface, 1 those
 * a cut opened (the neighbour across was removed). Vertices are the
 * mesh's. */
static int lst__boundary_tris(const pw_alloc *a, const lst_model *m, const int *nb, int cut, lst__tris *out, pw_err *e)
{
    int f, k, c[3];
    memset(out, 0, sizeof *out);
    out->nv = m->mesh.nverts;
    for (f = 0; f < 4 * m->mesh.ntets; f++) {
        int t = f >> 2, o = nb[f];
        float *b;
        if (m->removed[t] || (cut ? (o < 0 || !m->removed[o >> 2]) : o >= 0)) continue;
        if (lst__tris_room(a, out, e)) return PW_ERR_NOMEM;
        pw_tet_face(f & 3, c);
        b = out->bary + 12 * out->n;
        memset(b, 0, 12 * sizeof(float));
        for (k = 0; k < 3; k++) {
            out->tri[3 * out->n + k] = m->mesh.tets[4 * t + c[k]];
            b[4 * k + c[k]] = 1.0f;
        }
        out->tet[out->n++] = t;
    }
    return PW_OK;
}

#ifndef PW_NO_RENDER
typedef struct lst__shading {
    const lst__view *v;
    const lst__tris *tris;
    int mode;          /* 0 opaque surface; 1 volume slice */
    float alpha_scale; /* volume: opacity per unit density */
    int density;       /* volume: 0 luminance, k > 0 values channel k-1 */
} lst__shading;

/* The renderer's shader: a triangle point to barycentric coordinates in
 * its tetrahedron, then the composite; opaque for the surface of the
 * solid, the density's opacity for a volume slice. */
static void lst__shade(void *user, int tri, float b1, float b2, const float db[4], float rgba[4])
{
    const lst__shading *S = (const lst__shading *)user;
    const float *b = S->tris->bary + 12 * (size_t)tri;
    float b0 = 1.0f - b1 - b2, vals[4] = {0, 0, 0, 0}, d;
    double l[4];
    int k;
    (void)db;
    for (k = 0; k < 4; k++) l[k] = b0 * b[k] + b1 * b[4 + k] + b2 * b[8 + k];
    lst__eval(S->v, S->tris->tet[tri], l, rgba, S->mode && S->density ? vals : NULL);
    if (S->mode == 0) {
        rgba[3] = 1.0f;
        return;
    }
    d = S->density == 0 ? 1.0f - (0.299f * rgba[0] + 0.587f * rgba[1] + 0.114f * rgba[2]) : vals[S->density - 1];
    rgba[3] *= pw_clampf(S->alpha_scale * d, 0.0f, 1.0f);
}

/* Render options with every zero field replaced by its default. */
static lst_render_options lst__render_options(const lst_render_options *ro)
{
    lst_render_options o;
    if (ro) o = *ro;
    else memset(&o, 0, sizeof o);
    pw_view_defaults(&o.width, &o.height, &o.supersample, o.view_dir, o.up, o.background);
    if (o.subdivide <= 0) o.subdivide = 2;
    return o;
}

static int lst__check_render(const lst_render_options *o, pw_err *e)
{
    if (o->show < LST_SHOW_COLOR || o->show > LST_SHOW_DEPTH)
        return pw_fail(e, PW_ERR_INVALID, "render: show %d is invalid", (int)o->show);
    if (!pw_is_finite(o->displace) || o->subdivide > 6)
        return pw_fail(e, PW_ERR_INVALID, "render: displacement %g or subdivision %d is invalid", o->displace,
                       o->subdivide);
    if (o->width < 1 || o->height < 1 || o->width > PW_MAX_IMAGE_DIM || o->height > PW_MAX_IMAGE_DIM ||
        o->supersample < 1 || o->supersample > PW_FB_MAX_SS)
        return pw_fail(e, PW_ERR_INVALID, "render: size %dx%d with %dx%d samples is invalid", o->width, o->height,
                       o->supersample, o->supersample);
    return PW_OK;
}

/* Draws triangle list t (positions: its own or those of the mesh of the
 * model S->v shows). */
static int lst__draw_tris(pw_fb *fb, const pw_camera *cam, const lst__tris *t, lst__shading *S,
                          const lst_render_options *o, pw_err *e)
{
    const lst_model *m = S->v->m;
    pw_draw d;
    if (t->n == 0) return PW_OK;
    S->tris = t;
    memset(&d, 0, sizeof d);
    d.positions = t->pos ? t->pos : m->mesh.positions;
    d.nv = t->nv;
    d.tris = t->tri;
    d.ntris = t->n;
    d.lighting = o->unlit || S->mode ? PW_LIGHT_NONE : PW_LIGHT_CAMERA;
    d.ambient = 0.35f;
    d.normals = t->normals;
    d.shader = lst__shade;
    d.shader_user = S;
    if (S->mode) {
        d.blend = PW_BLEND_OVER;
        d.depth_test = PW_DEPTH_ALWAYS;
        d.no_depth_write = 1;
    }
    return pw_render_draw(fb, cam, &d, e);
}

/* The smooth normals of a lit triangle list, once for every band. */
static int lst__tris_normals(const pw_alloc *a, const lst_model *m, lst__tris *t, pw_err *e)
{
    pw_draw d;
    if (t->n == 0) return PW_OK;
    memset(&d, 0, sizeof d);
    d.positions = t->pos ? t->pos : m->mesh.positions;
    d.nv = t->nv;
    d.tris = t->tri;
    d.ntris = t->n;
    return (t->normals = pw_draw_normals(a, &d, e)) != NULL ? PW_OK : PW_ERR_NOMEM;
}

/* The positions of the vertices of visible tetrahedra (for framing). */
static int lst__visible_positions(const pw_alloc *a, const lst_model *m, float **out, int *n, pw_err *e)
{
    unsigned char *used = (unsigned char *)pw_calloc_array(a, (size_t)m->mesh.nverts, 1, "framing", e);
    int t, k, v;
    *n = 0;
    *out = (float *)pw_alloc_array(a, (size_t)m->mesh.nverts * 3, sizeof(float), "framing", e);
    if (!used || !*out) {
        pw_free(a, used);
        pw_free(a, *out);
        *out = NULL;
        return PW_ERR_NOMEM;
    }
    for (t = 0; t < m->mesh.ntets; t++)
        for (k = 0; k < 4 && !m->removed[t]; k++) used[m->mesh.tets[4 * t + k]] = 1;
    for (v = 0; v < m->mesh.nverts; v++)
        if (used[v]) memcpy(*out + 3 * (*n)++, m->mesh.positions + 3 * v, 3 * sizeof(float));
    pw_free(a, used);
    if (*n > 0) return PW_OK;
    pw_free(a, *out);
    *out = NULL;
    return pw_fail(e, PW_ERR_DEGENERATE, "nothing to render: every tetrahedron was cut away");
}

/* ---- displacement mapping (§6, Figs. 1c and 4d) ------------------------------------------------ */

/* Area-weighted vertex normals of triangle list t (mesh vertices). */
static int lst__vertex_normals(const pw_alloc *a, const lst_model *m, const lst__tris *t, float **out, pw_err *e)
{
    int i, k, j;
    if (!(*out = (float *)pw_calloc_array(a, (size_t)m->mesh.nverts * 3, sizeof(float), "normals", e)))
        return PW_ERR_NOMEM;
    for (i = 0; i < t->n; i++) {
        double p[3][3], u[3], w[3], n[3];
        for (k = 0; k < 3; k++)
            for (j = 0; j < 3; j++) p[k][j] = m->mesh.positions[3 * t->tri[3 * i + k] + j];
        for (j = 0; j < 3; j++) {
            u[j] = p[1][j] - p[0][j];
            w[j] = p[2][j] - p[0][j];
        }
        pw_cross3(u, w, n);
        for (k = 0; k < 3; k++)
            for (j = 0; j < 3; j++) (*out)[3 * t->tri[3 * i + k] + j] += (float)n[j];
    }
    return PW_OK;
}

/* The surface s being subdivided k x k and displaced into out, and its
 * shared vertices: mesh corners by index, edge points by (lower vertex,
 * upper vertex, step from the lower one) in an open-addressing table,
 * interior points unshared. */
typedef struct lst__subdiv {
    int *corner;   /* nv: subdivided vertex of each mesh vertex, or -1 */
    uint64_t *key; /* table of edge points */
    int *val;
    size_t mask;
    const pw_alloc *a;
    const lst__view *v; /* evaluates the displacement channel */
    const lst__tris *s; /* the surface triangles */
    const float *vn;    /* their smooth vertex normals */
    int k;              /* grid steps per triangle side */
    double amount;      /* displacement per unit of (value - 0.5) */
    lst__tris *out;
    pw_err *e;
} lst__subdiv;

static int *lst__edge_slot(lst__subdiv *sd, int a, int b, int step)
{
    uint64_t k = ((uint64_t)(uint32_t)a << 40) ^ ((uint64_t)(uint32_t)b << 12) ^ (uint64_t)step ^ 0x8000000000000000ULL;
    size_t h = (size_t)((k * 0x9E3779B97F4A7C15ULL) >> 17) & sd->mask;
    while (sd->key[h] && sd->key[h] != k) h = (h + 1) & sd->mask;
    if (!sd->key[h]) {
        sd->key[h] = k;
        sd->val[h] = -1;
    }
    return &sd->val[h];
}

/* Point (i, j) of the k x k grid on surface triangle f, displaced along
 * the interpolated normal by amount * (value - 0.5). */
static int lst__displaced_point(const lst__subdiv *sd, int f, int i, int j)
{
    const lst__view *v = sd->v;
    const lst__tris *s = sd->s;
    const float *vn = sd->vn;
    int k = sd->k;
    const int *c = s->tri + 3 * f;
    double b[3] = {1.0 - (double)(i + j) / k, (double)i / k, (double)j / k}, p[3] = {0, 0, 0}, n[3] = {0, 0, 0}, l[4];
    float rgba[4], val[4] = {0.5f, 0.5f, 0.5f, 0.5f};
    int q, r;
    for (q = 0; q < 4; q++)
        l[q] = b[0] * s->bary[12 * f + q] + b[1] * s->bary[12 * f + 4 + q] + b[2] * s->bary[12 * f + 8 + q];
    for (q = 0; q < 3; q++)
        for (r = 0; r < 3; r++) {
            p[r] += b[q] * v->m->mesh.positions[3 * c[q] + r];
            n[r] += b[q] * vn[3 * c[q] + r];
        }
    pw_norm3(n);
    lst__eval(v, s->tet[f], l, rgba, val);
    for (r = 0; r < 3; r++) p[r] += n[r] * sd->amount * (val[0] - 0.5);
    return lst__tris_vertex(sd->a, sd->out, p, sd->e);
}

/* The index of grid point (i, j) of triangle f, shared where the point is
 * a corner or on an edge. */
static int lst__grid_vertex(lst__subdiv *sd, int f, int i, int j)
{
    const int *c = sd->s->tri + 3 * f;
    int k = sd->k;
    int *slot = NULL, x, y, step;
    if (i + j == 0 || i == k || j == k) slot = &sd->corner[c[i == k ? 1 : (j == k ? 2 : 0)]];
    else if (j == 0 || i == 0 || i + j == k) { /* on edge (x, y) at `step` from x */
        x = j == 0 ? c[0] : (i == 0 ? c[0] : c[1]);
        y = j == 0 ? c[1] : (i == 0 ? c[2] : c[2]);
        step = j == 0 ? i : (i == 0 ? j : j);
        if (x > y) {
            int tmp = x;
            x = y;
            y = tmp;
            step = k - step;
        }
        slot = lst__edge_slot(sd, x, y, step);
    }
    if (slot && *slot >= 0) return *slot;
    x = lst__displaced_point(sd, f, i, j);
    if (slot) *slot = x;
    return x;
}

/* Adds sub-triangle (p, q, r) of surface triangle f, grid points given as
 * (i, j) pairs, with their barycentric coordinates in f's tetrahedron. */
static int lst__sub_tri(const lst__subdiv *sd, int f, const int *idx, int ij[3][2])
{
    const lst__tris *s = sd->s;
    lst__tris *out = sd->out;
    int q, r, k = sd->k;
    if (lst__tris_room(sd->a, out, sd->e)) return PW_ERR_NOMEM;
    for (q = 0; q < 3; q++) {
        double b[3] = {1.0 - (double)(ij[q][0] + ij[q][1]) / k, (double)ij[q][0] / k, (double)ij[q][1] / k};
        out->tri[3 * out->n + q] = idx[q];
        for (r = 0; r < 4; r++)
            out->bary[12 * out->n + 4 * q + r] =
                (float)(b[0] * s->bary[12 * f + r] + b[1] * s->bary[12 * f + 4 + r] + b[2] * s->bary[12 * f + 8 + r]);
    }
    out->tet[out->n++] = s->tet[f];
    return PW_OK;
}

static int lst__subdivide_face(lst__subdiv *sd, int f)
{
    int i, j, idx[3], tri, q, k = sd->k;
    for (j = 0; j < k; j++)
        for (i = 0; i + j < k; i++)
            for (tri = 0; tri < (i + j + 1 < k ? 2 : 1); tri++) {
                int ij[3][2];
                if (tri == 0) {
                    ij[0][0] = i;
                    ij[0][1] = j;
                    ij[1][0] = i + 1;
                    ij[1][1] = j;
                    ij[2][0] = i;
                    ij[2][1] = j + 1;
                } else {
                    ij[0][0] = i + 1;
                    ij[0][1] = j;
                    ij[1][0] = i + 1;
                    ij[1][1] = j + 1;
                    ij[2][0] = i;
                    ij[2][1] = j + 1;
                }
                for (q = 0; q < 3; q++)
                    if ((idx[q] = lst__grid_vertex(sd, f, ij[q][0], ij[q][1])) < 0) return PW_ERR_NOMEM;
                if (lst__sub_tri(sd, f, idx, ij)) return PW_ERR_NOMEM;
            }
    return PW_OK;
}

/* The surface triangles split k x k and moved along the normal by the
 * extra channel: "first subdividing the surface mesh and then moving each
 * vertex along its normal direction according to the displacement value
 * sampled there" (§6). */
static int lst__displace(const pw_alloc *a, const lst__view *v, const lst__tris *s, const lst_render_options *o,
                         lst__tris *out, pw_err *e)
{
    lst__subdiv sd;
    float *vn = NULL;
    int k = 1 << o->subdivide, f, r = PW_OK;
    size_t cap = 16;
    memset(out, 0, sizeof *out);
    memset(&sd, 0, sizeof sd);
    while (cap < (size_t)s->n * 3 * (size_t)k) cap *= 2;
    sd.mask = cap - 1;
    sd.corner = (int *)pw_alloc_array(a, (size_t)v->m->mesh.nverts, sizeof(int), "subdivision", e);
    sd.key = (uint64_t *)pw_calloc_array(a, cap, sizeof(uint64_t), "subdivision", e);
    sd.val = (int *)pw_alloc_array(a, cap, sizeof(int), "subdivision", e);
    if (!sd.corner || !sd.key || !sd.val || lst__vertex_normals(a, v->m, s, &vn, e)) r = PW_ERR_NOMEM;
    sd.a = a;
    sd.v = v;
    sd.s = s;
    sd.vn = vn;
    sd.k = k;
    sd.amount = o->displace;
    sd.out = out;
    sd.e = e;
    for (f = 0; r == PW_OK && f < v->m->mesh.nverts; f++) sd.corner[f] = -1;
    for (f = 0; r == PW_OK && f < s->n; f++) r = lst__subdivide_face(&sd, f);
    pw_free(a, sd.corner);
    pw_free(a, sd.key);
    pw_free(a, sd.val);
    pw_free(a, vn);
    if (r != PW_OK) lst__tris_free(a, out);
    return r;
}

/* ---- lst_render ------------------------------------------------------------------------------------ */

/* The camera that frames the visible part. */
static int lst__camera(const pw_alloc *a, const lst_model *m, const lst_render_options *o, pw_camera *cam, pw_err *e)
{
    float *pos;
    int n, r;
    if ((r = lst__visible_positions(a, m, &pos, &n, e)) != PW_OK) return r;
    *cam = pw_camera_frame(pos, n, o->view_dir, o->up, 35.0f, (float)o->width / (float)o->height);
    pw_free(a, pos);
    return PW_OK;
}

/* The picture, band by band (pw_render_frame), each band drawn by draw(user). */
static int lst__render_frame(const pw_alloc *a, const lst_render_options *o, pw_frame_draw_fn draw, void *user,
                             pw_image *pic, pw_err *e)
{
    pw_frame f;
    pw_parallel par;
    par = lst__parallel(o);
    pw_frame_init(&f, o->width, o->height, o->supersample, o->background, &par);
    f.draw = draw;
    f.user = user;
    return pw_render_frame(a, &f, pic, e);
}

/* What every band of lst_render draws (read only: bands may run on
 * several threads, each with its own shading state). */
typedef struct lst__surface {
    const lst_model *m;
    const lst__view *v;
    const lst__tris *outer, *cut;
    const lst_render_options *o;
    pw_camera cam;
} lst__surface;

static int lst__surface_band(void *user, pw_fb *fb, pw_err *e)
{
    const lst__surface *B = (const lst__surface *)user;
    lst__shading S;
    int r;
    memset(&S, 0, sizeof S);
    S.v = B->v;
    r = lst__draw_tris(fb, &B->cam, B->outer, &S, B->o, e);
    if (r == PW_OK) r = lst__draw_tris(fb, &B->cam, B->cut, &S, B->o, e);
    return r;
}

static int lst__render(const pw_alloc *a, const lst_model *m, const lst_render_options *o, pw_image *pic, pw_err *e)
{
    lst__view v;
    lst__tris outer, cut, disp;
    lst__surface B;
    int *nb = NULL, r;
    pw_tetmesh tm = lst__pw_tets(&m->mesh);
    memset(&outer, 0, sizeof outer);
    memset(&cut, 0, sizeof cut);
    memset(&disp, 0, sizeof disp);
    if ((r = lst__view_init(a, m, o->show, &v, e)) != PW_OK) return r;
    if (o->displace != 0.0f && !m->values.voxels)
        r = pw_fail(e, PW_ERR_INVALID, "displacement needs the model's extra channel");
    if (r == PW_OK && !(nb = (int *)pw_alloc_array(a, (size_t)m->mesh.ntets * 4, sizeof(int), "face adjacency", e)))
        r = PW_ERR_NOMEM;
    if (r == PW_OK) r = pw_tetmesh_neighbors(a, &tm, nb, e);
    if (r == PW_OK) r = lst__boundary_tris(a, m, nb, 0, &outer, e);
    if (r == PW_OK) r = lst__boundary_tris(a, m, nb, 1, &cut, e);
    if (r == PW_OK && o->displace != 0.0f) r = lst__displace(a, &v, &outer, o, &disp, e);
    if (r == PW_OK && !o->unlit) r = lst__tris_normals(a, m, o->displace != 0.0f ? &disp : &outer, e);
    if (r == PW_OK && !o->unlit) r = lst__tris_normals(a, m, &cut, e);
    B.m = m;
    B.v = &v;
    B.outer = o->displace != 0.0f ? &disp : &outer;
    B.cut = &cut;
    B.o = o;
    if (r == PW_OK) r = lst__camera(a, m, o, &B.cam, e);
    if (r == PW_OK) r = lst__render_frame(a, o, lst__surface_band, &B, pic, e);
    lst__tris_free(a, &outer);
    lst__tris_free(a, &cut);
    lst__tris_free(a, &disp);
    pw_free(a, nb);
    lst__view_free(&v);
    return r;
}

LSTDEF lst_result lst_render(const lst_model *model, const lst_render_options *ro, lst_image *out, lst_error *err)
{
    lst_render_options o = lst__render_options(ro);
    pw_alloc a;
    pw_image pic;
    pw_err e;
    pw_err_clear(&e);
    if (out) memset(out, 0, sizeof *out);
    if (!model || !out) {
        pw_fail(&e, PW_ERR_INVALID, "lst_render: NULL argument");
        return lst__done(&e, err);
    }
    a = lst__alloc(&model->allocator);
    memset(&pic, 0, sizeof pic);
    if (lst__check_render(&o, &e) == PW_OK && lst__render(&a, model, &o, &pic, &e) == PW_OK)
        lst__take_image(&pic, &a, out);
    return lst__done(&e, err);
}

/* ---- §5.1.2 volume rendering --------------------------------------------------------------------- */

/* What every band of a volume rendering draws: the slices, back to front,
 * of the tetrahedra whose picture (rows ylo..yhi) meets the band. */
typedef struct lst__volume_frame {
    const pw_alloc *a;
    const lst_model *m;
    const lst__view *v;
    const lst_render_options *o;
    pw_tetmesh tm;
    const double *phi; /* per vertex: the distance along the view */
    const float *rows; /* per tetrahedron: its first and last picture row */
    double zmax, dz;
    int slices, density;
    float alpha_scale;
    pw_camera cam;
} lst__volume_frame;

/* Marching tetrahedra on tetrahedron t of V->tm: the triangles (1 or 2)
 * of the level set phi = z (phi: at its corners), their corners on the
 * edges, appended to out with their own vertices. */
static int lst__slice_tet(const lst__volume_frame *V, int t, const double *phi, double z, lst__tris *out, pw_err *e)
{
    const pw_alloc *a = V->a;
    const pw_tetmesh *m = &V->tm;
    int neg[4], pos[4], nn = 0, np = 0, k, q, r, cnt, edges[4][2];
    for (k = 0; k < 4; k++) {
        if (phi[k] < z) neg[nn++] = k;
        else pos[np++] = k;
    }
    if (nn == 0 || np == 0) return PW_OK;
    if (nn == 2) { /* a quad: edges in cyclic order */
        edges[0][0] = neg[0];
        edges[0][1] = pos[0];
        edges[1][0] = neg[0];
        edges[1][1] = pos[1];
        edges[2][0] = neg[1];
        edges[2][1] = pos[1];
        edges[3][0] = neg[1];
        edges[3][1] = pos[0];
        cnt = 4;
    } else {
        int lone = nn == 1 ? neg[0] : pos[0], *others = nn == 1 ? pos : neg;
        for (k = 0; k < 3; k++) {
            edges[k][0] = lone;
            edges[k][1] = others[k];
        }
        cnt = 3;
    }
    for (q = 0; q < cnt - 2; q++) {
        static const int fan[2][3] = {{0, 1, 2}, {0, 2, 3}};
        if (lst__tris_room(a, out, e)) return PW_ERR_NOMEM;
        memset(out->bary + 12 * out->n, 0, 12 * sizeof(float));
        for (k = 0; k < 3; k++) {
            const int *ed = edges[fan[q][k]];
            double s = (z - phi[ed[0]]) / (phi[ed[1]] - phi[ed[0]]), p[3];
            for (r = 0; r < 3; r++)
                p[r] = (1.0 - s) * m->pos[3 * m->tet[4 * t + ed[0]] + r] + s * m->pos[3 * m->tet[4 * t + ed[1]] + r];
            if ((out->tri[3 * out->n + k] = lst__tris_vertex(a, out, p, e)) < 0) return PW_ERR_NOMEM;
            out->bary[12 * out->n + 4 * k + ed[0]] = (float)(1.0 - s);
            out->bary[12 * out->n + 4 * k + ed[1]] = (float)s;
        }
        out->tet[out->n++] = t;
    }
    return PW_OK;
}

static int lst__volume_band(void *user, pw_fb *fb, pw_err *e)
{
    const lst__volume_frame *V = (const lst__volume_frame *)user;
    const float r0 = (float)(fb->y0 / fb->ss) - 1.0f, r1 = (float)((fb->y0 + fb->bh) / fb->ss) + 1.0f;
    lst__tris sl;
    lst__shading S;
    double ph[4];
    int t, k, s, r = PW_OK;
    memset(&sl, 0, sizeof sl);
    memset(&S, 0, sizeof S);
    S.v = V->v;
    S.mode = 1;
    S.density = V->density;
    S.alpha_scale = V->alpha_scale;
    for (s = 0; r == PW_OK && s < V->slices; s++) { /* back to front */
        double z = V->zmax - (s + 0.5) * V->dz;
        sl.n = sl.nv = 0;
        for (t = 0; r == PW_OK && t < V->tm.nt; t++) {
            if (V->m->removed[t] || V->rows[2 * t + 1] < r0 || V->rows[2 * t] > r1) continue;
            for (k = 0; k < 4; k++) ph[k] = V->phi[V->tm.tet[4 * t + k]];
            r = lst__slice_tet(V, t, ph, z, &sl, e);
        }
        if (r == PW_OK) r = lst__draw_tris(fb, &V->cam, &sl, &S, V->o, e);
    }
    lst__tris_free(V->a, &sl);
    return r;
}

/* The picture rows each tetrahedron covers (all of them when a corner is
 * not in front of the camera). */
static void lst__tet_rows(const lst__volume_frame *V, float *rows)
{
    int t, k;
    for (t = 0; t < V->tm.nt; t++) {
        float lo = 3e38f, hi = -3e38f, q[3];
        for (k = 0; k < 4; k++) {
            if (!pw_camera_project(&V->cam, V->o->width, V->o->height, V->tm.pos + 3 * V->tm.tet[4 * t + k], q)) {
                lo = -3e38f;
                hi = 3e38f;
                break;
            }
            lo = q[1] < lo ? q[1] : lo;
            hi = q[1] > hi ? q[1] : hi;
        }
        rows[2 * t] = lo;
        rows[2 * t + 1] = hi;
    }
}

static int lst__volume(const pw_alloc *a, const lst_model *m, const lst_render_options *o, const lst_volume_options *vo,
                       pw_image *pic, pw_err *e)
{
    lst__view v;
    lst__volume_frame V;
    double f[3], *phi = NULL, zmin = 1e300, zmax = -1e300;
    float *rows = NULL;
    int k, r;
    memset(&V, 0, sizeof V);
    V.tm = lst__pw_tets(&m->mesh);
    if ((r = lst__view_init(a, m, o->show, &v, e)) != PW_OK) return r;
    if (vo->density > 0 && (!m->values.voxels || vo->density > m->values.channels))
        r = pw_fail(e, PW_ERR_INVALID, "volume density from extra channel %d: the model has %d", vo->density,
                    m->values.voxels ? m->values.channels : 0);
    if (r == PW_OK) r = lst__camera(a, m, o, &V.cam, e);
    if (r == PW_OK && !(phi = (double *)pw_alloc_array(a, (size_t)V.tm.nv, sizeof(double), "volume slices", e)))
        r = PW_ERR_NOMEM;
    if (r == PW_OK && !(rows = (float *)pw_alloc_array(a, (size_t)V.tm.nt * 2, sizeof(float), "volume slices", e)))
        r = PW_ERR_NOMEM;
    for (k = 0; r == PW_OK && k < 3; k++) f[k] = (double)V.cam.target[k] - V.cam.eye[k];
    if (r == PW_OK) pw_norm3(f);
    for (k = 0; r == PW_OK && k < V.tm.nv; k++) { /* §5.1.2: the distance from the camera along the view */
        const float *p = V.tm.pos + 3 * k;
        phi[k] = (p[0] - V.cam.eye[0]) * f[0] + (p[1] - V.cam.eye[1]) * f[1] + (p[2] - V.cam.eye[2]) * f[2];
        zmin = phi[k] < zmin ? phi[k] : zmin;
        zmax = phi[k] > zmax ? phi[k] : zmax;
    }
    if (r == PW_OK) {
        V.a = a;
        V.m = m;
        V.v = &v;
        V.o = o;
        V.phi = phi;
        V.rows = rows;
        V.zmax = zmax;
        V.dz = (zmax - zmin) / vo->slices;
        V.slices = vo->slices;
        V.density = vo->density;
        V.alpha_scale = (float)(vo->opacity * V.dz / (0.01 * lst__diagonal(V.tm.pos, V.tm.nv)));
        lst__tet_rows(&V, rows);
        r = lst__render_frame(a, o, lst__volume_band, &V, pic, e);
    }
    pw_free(a, rows);
    pw_free(a, phi);
    lst__view_free(&v);
    return r;
}

LSTDEF lst_result lst_render_volume(const lst_model *model, const lst_render_options *ro,
                                    const lst_volume_options *vopt, lst_image *out, lst_error *err)
{
    lst_render_options o = lst__render_options(ro);
    lst_volume_options vo;
    pw_alloc a;
    pw_image pic;
    pw_err e;
    pw_err_clear(&e);
    if (out) memset(out, 0, sizeof *out);
    if (vopt) vo = *vopt;
    else memset(&vo, 0, sizeof vo);
    if (vo.slices == 0) vo.slices = 200;
    if (vo.opacity == 0.0f) vo.opacity = 0.3f;
    if (!model || !out) pw_fail(&e, PW_ERR_INVALID, "lst_render_volume: NULL argument");
    else if (vo.slices < 1 || vo.slices > 10000 || !(vo.opacity > 0.0f && vo.opacity <= 1000.0f) || vo.density < 0 ||
             vo.density > 4)
        pw_fail(&e, PW_ERR_INVALID, "volume rendering: %d slices, opacity %g or density channel %d is invalid",
                vo.slices, vo.opacity, vo.density);
    else if (lst__check_render(&o, &e) == PW_OK) {
        a = lst__alloc(&model->allocator);
        memset(&pic, 0, sizeof pic);
        if (lst__volume(&a, model, &o, &vo, &pic, &e) == PW_OK) lst__take_image(&pic, &a, out);
    }
    return lst__done(&e, err);
}

#else
LSTDEF lst_result lst_render(const lst_model *model, const lst_render_options *ro, lst_image *out, lst_error *err)
{
    (void)model;
    (void)ro;
    if (out) memset(out, 0, sizeof *out);
    return lst__left_out("rendering", "PW_NO_RENDER", err);
}

LSTDEF lst_result lst_render_volume(const lst_model *model, const lst_render_options *ro,
                                    const lst_volume_options *vopt, lst_image *out, lst_error *err)
{
    (void)model;
    (void)ro;
    (void)vopt;
    if (out) memset(out, 0, sizeof *out);
    return lst__left_out("rendering", "PW_NO_RENDER", err);
}
#endif /* PW_NO_RENDER */
