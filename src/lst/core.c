/* core.c: lst.h's glue to the shared core, its defaults, the conversions
 * between its public types and the shared ones, and small math shared by
 * the stages. Section numbers refer to Takayama, Okabe, Ijiri and
 * Igarashi 2008. */
#include "../common/base.h"
#include "../common/vec.h"
#include "../common/rng.h"
#include "../common/image.h"
#include "../common/deflate.h"
#include "../common/png.h"
#include "../common/text.h"
#include "../common/mesh.h"
#include "../common/shapes.h"
#include "../common/halfedge.h"
#include "../common/trimesh.h"
#include "../common/heap.h"
#include "../common/sparse.h"
#include "../common/raster.h"
#include "../common/render.h"
#include "../common/atlas.h"
#include "../common/nrrd.h"
#include "../common/tetmesh.h"
#include "../common/tetio.h"
#include "../common/stuffing.h"
#include "../common/edt.h"
#include "../common/pca.h"
#include "../common/glue.h"
#include "../common/gltf.h"
#include "lst.h"

typedef char lst__codes_match[(int)LST_ERR_NOCONVERGE == PW_ERR_NOCONVERGE ? 1 : -1];

PW_PUBLIC_GLUE(lst);
PW_PUBLIC_IMAGE_FREE(lst, LSTDEF);
PW_PUBLIC_MESH_FREE(lst, LSTDEF);

LSTDEF lst_options lst_default_options(void)
{
    lst_options o;
    memset(&o, 0, sizeof o);
    o.mask_radius = 0.4f;
    o.falloff = 0.08f;
    o.samples = 8;
    o.coverage = 0.99f;
    o.max_angle = 50.0f;
    o.max_stretch = 2.0f;
    o.layer_weight = 1.0f;
    o.constraint_weight = 10.0f;
    o.rbf_centers = 400;
    o.max_pastes = 200000;
    pw_view_defaults(&o.render.width, &o.render.height, &o.render.supersample, o.render.view_dir, o.render.up,
                     o.render.background);
    o.render.subdivide = 2;
    o.tet.target_tets = 20000;
    o.tet.max_hole = 0.05;
    o.tet.fit = 0.0025;
    o.volume.slices = 200;
    o.volume.opacity = 0.3f;
    o.atlas.size = PW_ATLAS_SIZE;
    o.atlas.cone_angle = PW_ATLAS_CONE;
    o.atlas.gutter = PW_ATLAS_GUTTER;
    return o;
}

LSTDEF const char *lst_result_string(lst_result r) { return pw_result_string((int)r); }

/* Options with every zero field replaced by its default. */
static lst_options lst__options(const lst_options *opt)
{
    lst_options d = lst_default_options(), o = opt ? *opt : d;
    if (!(o.mask_radius > 0.0f)) o.mask_radius = d.mask_radius;
    if (!(o.falloff > 0.0f)) o.falloff = d.falloff;
    if (o.samples <= 0) o.samples = d.samples;
    if (!(o.coverage > 0.0f)) o.coverage = d.coverage;
    if (!(o.max_angle > 0.0f)) o.max_angle = d.max_angle;
    if (!(o.max_stretch > 1.0f)) o.max_stretch = d.max_stretch;
    if (!(o.layer_weight > 0.0f)) o.layer_weight = d.layer_weight;
    if (!(o.constraint_weight > 0.0f)) o.constraint_weight = d.constraint_weight;
    if (o.rbf_centers <= 0) o.rbf_centers = d.rbf_centers;
    if (o.max_pastes <= 0) o.max_pastes = d.max_pastes;
    return o;
}

/* Options a caller may get wrong, named in the message. */
static int lst__check_options(const lst_options *o, pw_err *e)
{
    int k;
    if (o->type < LST_TYPE_0 || o->type > LST_TYPE_2B)
        return pw_fail(e, PW_ERR_INVALID, "texture type %d is not one of 0, 1-a, 1-b, 2-a, 2-b (0..4)", (int)o->type);
    if (!pw_is_finite(o->scale) || o->scale < 0.0f) return pw_fail(e, PW_ERR_INVALID, "scale %g is invalid", o->scale);
    if (o->mask < LST_MASK_AUTO || o->mask > LST_MASK_EXEMPLAR)
        return pw_fail(e, PW_ERR_INVALID, "mask mode %d is invalid", (int)o->mask);
    if (o->mask_radius > 0.5f || o->falloff > 0.4f || o->falloff >= o->mask_radius)
        return pw_fail(e, PW_ERR_INVALID, "mask radius %g and fall-off %g: need fall-off < radius <= 0.5",
                       o->mask_radius, o->falloff);
    if (o->samples > 32) return pw_fail(e, PW_ERR_LIMIT, "sample lattice order %d is over 32", o->samples);
    if (o->coverage > 1.0f) return pw_fail(e, PW_ERR_INVALID, "coverage %g is over 1", o->coverage);
    if (o->threads < 0) return pw_fail(e, PW_ERR_INVALID, "threads %d (0: one per processor)", o->threads);
    if (o->max_angle > 180.0f) return pw_fail(e, PW_ERR_INVALID, "max_angle %g is over 180 degrees", o->max_angle);
    if (o->nconstraints < 0 || (o->nconstraints > 0 && !o->constraints))
        return pw_fail(e, PW_ERR_INVALID, "constraint array and count disagree");
    for (k = 0; k < o->nconstraints; k++)
        if (o->constraints[k].kind < LST_CONSTRAINT_DEPTH_FACE || o->constraints[k].kind > LST_CONSTRAINT_SCALE)
            return pw_fail(e, PW_ERR_INVALID, "constraint %d: unknown kind %d", k, (int)o->constraints[k].kind);
    if (!pw_is_finite(o->axis[0]) || !pw_is_finite(o->axis[1]) || !pw_is_finite(o->axis[2]))
        return pw_fail(e, PW_ERR_INVALID, "axis is not finite");
    return PW_OK;
}

static pw_progress lst__progress(const lst_options *o)
{
    pw_progress p;
    p.fn = o->progress;
    p.user = o->progress_user;
    return p;
}

/* Depth-varying types use the depth as the v texture coordinate (§5.2.7). */
static int lst__depth_varying(int type) { return type == LST_TYPE_1B || type == LST_TYPE_2B; }
/* Types with a depth field at all. */
static int lst__has_depth(int type) { return type == LST_TYPE_1B || type == LST_TYPE_2A || type == LST_TYPE_2B; }
/* Types with a direction field (the u axis). */
static int lst__has_direction(int type) { return type == LST_TYPE_1A || type == LST_TYPE_2A || type == LST_TYPE_2B; }

/* ---- public types and shared ones -------------------------------------------- */

static pw_tetmesh lst__pw_tets(const lst_tetmesh *t)
{
    pw_tetmesh m;
    m.nv = t->nverts;
    m.pos = t->positions;
    m.nt = t->ntets;
    m.tet = t->tets;
    return m;
}

static void lst__take_tets(pw_tetmesh *m, const pw_alloc *a, lst_tetmesh *t)
{
    t->nverts = m->nv;
    t->positions = m->pos;
    t->ntets = m->nt;
    t->tets = m->tet;
    t->allocator = lst__allocator(a);
    memset(m, 0, sizeof *m);
}

static pw_volume lst__pw_volume(const lst_volume *v)
{
    pw_volume p;
    p.c = v->channels;
    p.x = v->width;
    p.y = v->height;
    p.z = v->depth;
    p.px = v->voxels;
    return p;
}

static void lst__take_volume(pw_volume *p, const pw_alloc *a, lst_volume *v)
{
    v->channels = p->c;
    v->width = p->x;
    v->height = p->y;
    v->depth = p->z;
    v->voxels = p->px;
    v->allocator = lst__allocator(a);
    memset(p, 0, sizeof *p);
}

/* A caller's volume: sizes within the limit, 1-4 channels, finite voxels. */
static int lst__check_volume(const lst_volume *v, const char *what, pw_err *e)
{
    size_t n, k;
    if (!v || !v->voxels || v->width < 1 || v->height < 1 || v->depth < 1 || v->channels < 1 || v->channels > 4)
        return pw_fail(e, PW_ERR_INVALID, "%s: empty volume or bad channel count", what);
    if (pw__volume_check_size(what, (uint64_t)v->width, (uint64_t)v->height, (uint64_t)v->depth, e)) return e->code;
    n = (size_t)v->width * v->height * v->depth * v->channels;
    for (k = 0; k < n; k++)
        if (!pw_is_finite(v->voxels[k]))
            return pw_fail(e, PW_ERR_INVALID, "%s: voxel %lu is not a finite number", what,
                           (unsigned long)(k / v->channels));
    return PW_OK;
}

/* A caller's tetrahedral mesh, checked without changing it (orientation
 * included: lst_tetmesh_check flips, the other calls refuse). */
static int lst__check_tets(const lst_tetmesh *t, pw_err *e)
{
    pw_tetmesh m;
    int k;
    if (!t || !t->positions || !t->tets || t->ntets < 1 || t->nverts < 4)
        return pw_fail(e, PW_ERR_DEGENERATE, "tetrahedral mesh: empty");
    if (t->nverts > PW_MAX_MESH_ELEMENTS || t->ntets > PW_MAX_MESH_ELEMENTS)
        return pw_fail(e, PW_ERR_LIMIT, "tetrahedral mesh: %d vertices, %d tetrahedra exceed the limit", t->nverts,
                       t->ntets);
    m = lst__pw_tets(t);
    for (k = 0; k < 4 * m.nt; k++)
        if (m.tet[k] < 0 || m.tet[k] >= m.nv)
            return pw_fail(e, PW_ERR_INVALID, "tetrahedron %d uses vertex %d of %d", k / 4, m.tet[k], m.nv);
    for (k = 0; k < 3 * m.nv; k++)
        if (!pw_is_finite(m.pos[k])) return pw_fail(e, PW_ERR_INVALID, "vertex %d is not finite", k / 3);
    for (k = 0; k < m.nt; k++) {
        double len = pw__tet_longest_edge(&m, k);
        if (!(pw_tet_volume6(&m, k) > 1e-12 * len * len * len))
            return pw_fail(e, PW_ERR_DEGENERATE, "tetrahedron %d is degenerate or negatively oriented", k);
    }
    return PW_OK;
}

LSTDEF void lst_tetmesh_free(lst_tetmesh *m)
{
    pw_alloc a;
    if (!m) return;
    a = lst__alloc(&m->allocator);
    pw_free(&a, m->positions);
    pw_free(&a, m->tets);
    memset(m, 0, sizeof *m);
}

LSTDEF void lst_volume_free(lst_volume *v)
{
    pw_alloc a;
    if (!v) return;
    a = lst__alloc(&v->allocator);
    pw_free(&a, v->voxels);
    memset(v, 0, sizeof *v);
}

LSTDEF void lst_field_free(lst_field *f)
{
    pw_alloc a;
    if (!f) return;
    a = lst__alloc(&f->allocator);
    pw_free(&a, f->depth);
    pw_free(&a, f->frame);
    memset(f, 0, sizeof *f);
}

LSTDEF void lst_masks_free(lst_masks *masks)
{
    pw_alloc a;
    int k;
    if (!masks) return;
    a = lst__alloc(&masks->allocator);
    for (k = 0; masks->volumes && k < masks->count; k++) lst_volume_free(&masks->volumes[k]);
    pw_free(&a, masks->volumes);
    memset(masks, 0, sizeof *masks);
}

static void lst__paste_free(const pw_alloc *a, lst_paste *p)
{
    pw_free(a, p->tets);
    pw_free(a, p->corners);
    pw_free(a, p->verts);
    pw_free(a, p->uvw);
    memset(p, 0, sizeof *p);
}

LSTDEF void lst_model_free(lst_model *m)
{
    pw_alloc a;
    int p;
    if (!m) return;
    a = lst__alloc(&m->allocator);
    for (p = 0; p < m->npastes; p++) lst__paste_free(&a, &m->pastes[p]);
    pw_free(&a, m->pastes);
    lst_masks_free(&m->masks);
    lst_volume_free(&m->texture);
    lst_volume_free(&m->values);
    pw_free(&a, m->removed);
    lst_tetmesh_free(&m->mesh);
    memset(m, 0, sizeof *m);
}

/* ---- small math ------------------------------------------------------------------ */

/* exp(x) for x <= 0 from + - * / only (the same bits everywhere): halved
 * until small, a Taylor series, squared back. Relative error ~1e-15. */
static double lst__exp_neg(double x)
{
    double s, t;
    int k, halvings = 0;
    if (!(x > -700.0)) return 0.0;
    while (x < -0.25) {
        x *= 0.5;
        halvings++;
    }
    s = t = 1.0;
    for (k = 1; k < 14; k++) s += (t *= x / k);
    while (halvings--) s *= s;
    return s;
}

/* Normalises v; returns its former length (0 leaves it unchanged). */
/* A unit vector orthogonal to unit n: the cross product with the axis n
 * is least aligned with (deterministic). */
static void lst__any_perp(const double *n, double *out)
{
    double ax[3] = {0, 0, 0};
    int k = fabs(n[0]) <= fabs(n[1]) && fabs(n[0]) <= fabs(n[2]) ? 0 : (fabs(n[1]) <= fabs(n[2]) ? 1 : 2);
    ax[k] = 1.0;
    pw_cross3(n, ax, out);
    pw_norm3(out);
}

/* Inverse of the 3x3 matrix m (row-major); returns the determinant (0:
 * singular, inv untouched). */
static double lst__inv3(const double m[9], double inv[9])
{
    double c0 = m[4] * m[8] - m[5] * m[7], c1 = m[5] * m[6] - m[3] * m[8], c2 = m[3] * m[7] - m[4] * m[6];
    double det = m[0] * c0 + m[1] * c1 + m[2] * c2;
    if (det == 0.0 || !pw_is_finite(det)) return 0.0;
    inv[0] = c0 / det;
    inv[1] = (m[2] * m[7] - m[1] * m[8]) / det;
    inv[2] = (m[1] * m[5] - m[2] * m[4]) / det;
    inv[3] = c1 / det;
    inv[4] = (m[0] * m[8] - m[2] * m[6]) / det;
    inv[5] = (m[2] * m[3] - m[0] * m[5]) / det;
    inv[6] = c2 / det;
    inv[7] = (m[1] * m[6] - m[0] * m[7]) / det;
    inv[8] = (m[0] * m[4] - m[1] * m[3]) / det;
    return det;
}

/* The unit eigenvector of the largest eigenvalue of a symmetric 3x3 matrix
 * (row-major), by the shared cyclic Jacobi method (sqrt only); its largest
 * component made positive so that the result does not depend on rounding. */
static void lst__principal(const double s[9], double out[3])
{
    double c[9], v[9];
    int k, best = 0;
    memcpy(c, s, sizeof c);
    pw__pca_jacobi(c, v, 3);
    for (k = 1; k < 3; k++)
        if (c[4 * k] > c[4 * best]) best = k;
    for (k = 0; k < 3; k++) out[k] = v[3 * k + best];
    k = fabs(out[0]) >= fabs(out[1]) && fabs(out[0]) >= fabs(out[2]) ? 0 : (fabs(out[1]) >= fabs(out[2]) ? 1 : 2);
    if (out[k] < 0.0) {
        out[0] = -out[0];
        out[1] = -out[1];
        out[2] = -out[2];
    }
}

/* The bounding-box diagonal of nv points. */
static double lst__diagonal(const float *pos, int nv)
{
    double lo[3], hi[3], d = 0.0;
    int v, k;
    for (k = 0; k < 3; k++) lo[k] = hi[k] = nv > 0 ? pos[k] : 0.0;
    for (v = 1; v < nv; v++)
        for (k = 0; k < 3; k++) {
            if (pos[3 * v + k] < lo[k]) lo[k] = pos[3 * v + k];
            if (pos[3 * v + k] > hi[k]) hi[k] = pos[3 * v + k];
        }
    for (k = 0; k < 3; k++) d += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    return sqrt(d);
}
