/* core.c: pgp.h's glue to the shared core, its defaults, and the mapping
 * object every stage fills. Section numbers refer to Ray, Lévy, Wang, Turk
 * and Vallet 2009 ("Material Space Texturing"). */
#include "../common/base.h"
#include "../common/vec.h"
#include "../common/image.h"
#include "../common/deflate.h"
#include "../common/png.h"
#include "../common/mesh.h"
#include "../common/halfedge.h"
#include "../common/sparse.h"
#include "../common/zsparse.h"
#include "../common/render.h"
#include "../common/nrrd.h"
#include "tile3.h"
#include "../common/trimesh.h"
#include "../common/dirfield.h"
#include "../common/periodic.h"
#include "../common/glue.h"
#include "pgp.h"

typedef char pgp__codes_match[(int)PGP_ERR_NOCONVERGE == PW_ERR_NOCONVERGE ? 1 : -1];

PW_PUBLIC_GLUE(pgp);
PW_PUBLIC_IMAGE_FREE(pgp, PGPDEF);
PW_PUBLIC_MESH_FREE(pgp, PGPDEF);

/* The defaults of tile synthesis (pgp_options.synth). */
static pgp_synth_options pgp__synth_defaults(void)
{
    pgp_synth_options o;
    memset(&o, 0, sizeof o);
    o.size = 128;
    o.layers = 8;
    o.coarse_passes = 20;
    o.fine_passes = 4;
    o.color_window = 5;
    o.mask_window = 3;
    o.color_dims = 5;
    o.mask_dims = 3;
    o.mask_weight = 2.0f;
    o.usage_weight = 0.2f;
    o.search_eps = 1.0f;
    o.search_buckets = 64;
    return o;
}

PGPDEF pgp_options pgp_default_options(void)
{
    pgp_options o;
    memset(&o, 0, sizeof o);
    o.up[1] = 1.0f;
    o.min_scale = 0.05f;
    o.smoothing = 20;
    o.singular_distortion = 0.5f;
    pw_view_defaults(&o.render.width, &o.render.height, &o.render.supersample, o.render.view_dir, o.render.up,
                     o.render.background);
    o.render.zoom = 1.0f;
    o.synth = pgp__synth_defaults();
    return o;
}

PGPDEF const char *pgp_result_string(pgp_result r) { return pw_result_string((int)r); }

/* Zero fields of the caller's options take their defaults. */
static pgp_options pgp__options(const pgp_options *opt)
{
    pgp_options d = pgp_default_options(), o;
    if (!opt) return d;
    o = *opt;
    if (o.up[0] == 0.0f && o.up[1] == 0.0f && o.up[2] == 0.0f) memcpy(o.up, d.up, sizeof o.up);
    if (o.min_scale == 0.0f) o.min_scale = d.min_scale;
    if (o.smoothing == 0) o.smoothing = d.smoothing;
    if (o.singular_distortion == 0.0f) o.singular_distortion = d.singular_distortion;
    return o;
}

static pw_progress pgp__progress(const pgp_options *o)
{
    pw_progress p;
    p.fn = o->progress;
    p.user = o->progress_user;
    return p;
}

PGPDEF void pgp_tile_free(pgp_tile *t)
{
    pw_alloc a;
    if (!t) return;
    a = pgp__alloc(&t->allocator);
    pw_free(&a, t->pixels);
    memset(t, 0, sizeof *t);
}

PGPDEF void pgp_area_free(pgp_area *area)
{
    pw_alloc a;
    if (!area) return;
    a = pgp__alloc(&area->allocator);
    pw_free(&a, area->faces);
    memset(area, 0, sizeof *area);
}

PGPDEF void pgp_field_free(pgp_field *field)
{
    pw_alloc a;
    if (!field) return;
    a = pgp__alloc(&field->allocator);
    pw_free(&a, field->dir);
    pw_free(&a, field->scale);
    pw_free(&a, field->material);
    memset(field, 0, sizeof *field);
}

PGPDEF void pgp_constraints_free(pgp_constraints *c)
{
    pw_alloc a;
    if (!c) return;
    a = pgp__alloc(&c->allocator);
    pw_free(&a, c->items);
    memset(c, 0, sizeof *c);
}

/* The checks of a constraint that need no map (§2.2: m in [0, 1], S > 0, a
 * direction that is finite and not zero, a finite radius, an index that
 * can exist). The message names the element. */
static int pgp__check_values(const pgp_constraint *c, pw_err *e)
{
    const char *what = c->kind == PGP_CONSTRAINT_ORIENT ? "triangle" : "vertex";
    const float *v = c->value;
    if (c->kind != PGP_CONSTRAINT_ORIENT && c->kind != PGP_CONSTRAINT_SCALE && c->kind != PGP_CONSTRAINT_MATERIAL)
        return pw_fail(e, PW_ERR_INVALID, "unknown constraint kind %d", (int)c->kind);
    if (c->element < 0) return pw_fail(e, PW_ERR_INVALID, "%s %d does not exist", what, c->element);
    if (!pw_is_finite(c->radius))
        return pw_fail(e, PW_ERR_INVALID, "effect radius %g is not finite", (double)c->radius);
    if (c->kind == PGP_CONSTRAINT_ORIENT && (!pw_is_finite(v[0]) || !pw_is_finite(v[1]) || !pw_is_finite(v[2]) ||
                                             (v[0] == 0.0f && v[1] == 0.0f && v[2] == 0.0f)))
        return pw_fail(e, PW_ERR_INVALID, "orientation (%g, %g, %g) at triangle %d is zero or not finite", (double)v[0],
                       (double)v[1], (double)v[2], c->element);
    if (c->kind == PGP_CONSTRAINT_SCALE && !(v[0] > 0.0f && pw_is_finite(v[0])))
        return pw_fail(e, PW_ERR_INVALID, "scale %g at vertex %d is not a positive finite number", (double)v[0],
                       c->element);
    if (c->kind == PGP_CONSTRAINT_MATERIAL && !(v[0] >= 0.0f && v[0] <= 1.0f))
        return pw_fail(e, PW_ERR_INVALID, "material %g at vertex %d is not in [0, 1]", (double)v[0], c->element);
    return PW_OK;
}

/* ---- the mapping ---------------------------------------------------------- */

/* A constraint of the map (§2); removed ones stay in the list, dead, so
 * that ids stay valid. */
typedef struct pgp__constraint {
    pgp_constraint c;
    int alive;
} pgp__constraint;

typedef struct pgp_map_state pgp__state;

/* What pgp_map.state points to. */
struct pgp_map_state {
    pw_alloc a;
    pgp_options o;
    float *pos;           /* nv*3, the map's own copy of the positions */
    pw_periodic pp;       /* the mesh, the field, s and t (src/common/periodic.h);
                             pp.sfac is the integrability factor of S_i (1 but
                             with options.integrable, pgp__integrable) */
    float *mat;           /* nv: m_i */
    unsigned char *vsing; /* nv: singular 1-ring (§3) */
    unsigned char *fsing; /* nf: a corner's 1-ring is singular */
    int nsing;
    pgp__constraint *con;
    int ncon;
    size_t concap;
    pw_parallel par; /* options.threads, parallel, parallel_pool: pp.run's */
};

static int pgp__check_vertex(const pgp__state *P, int v, pw_err *e)
{
    if (v < 0 || v >= P->pp.m.nv)
        return pw_fail(e, PW_ERR_INVALID, "vertex %d does not exist (the mesh has %d)", v, P->pp.m.nv);
    return PW_OK;
}

static int pgp__check_face(const pgp__state *P, int f, pw_err *e)
{
    if (f < 0 || f >= P->pp.m.nf)
        return pw_fail(e, PW_ERR_INVALID, "triangle %d does not exist (the mesh has %d)", f, P->pp.m.nf);
    return PW_OK;
}

/* The map's state, or NULL for a NULL or zeroed map. */
static const pgp__state *pgp__state_of(const pgp_map *map) { return map ? map->state : NULL; }

PGPDEF int pgp_map_singular(const pgp_map *map, unsigned char *flags)
{
    const pgp__state *P = pgp__state_of(map);
    if (!P) return 0;
    if (flags) memcpy(flags, P->fsing, (size_t)P->pp.m.nf);
    return P->nsing;
}

PGPDEF pgp_result pgp_map_field(const pgp_map *map, pgp_field *out, pgp_error *err)
{
    const pgp__state *P = pgp__state_of(map);
    pw_alloc a;
    pw_err pe;
    int f;
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (!out || !P) {
        pw_fail(&pe, PW_ERR_INVALID, "pgp_map_field: NULL or empty map, or NULL output");
        return pgp__done(&pe, err);
    }
    a = P->a;
    out->dir = (float *)pw_alloc_array(&a, (size_t)P->pp.m.nf * 3, sizeof(float), "field", &pe);
    out->scale = (float *)pw_alloc_array(&a, (size_t)P->pp.m.nv, sizeof(float), "field", &pe);
    out->material = (float *)pw_alloc_array(&a, (size_t)P->pp.m.nv, sizeof(float), "field", &pe);
    out->allocator = pgp__allocator(&a);
    if (!out->dir || !out->scale || !out->material) {
        pgp_field_free(out);
        return pgp__done(&pe, err);
    }
    out->ntris = P->pp.m.nf;
    out->nverts = P->pp.m.nv;
    for (f = 0; f < P->pp.m.nf; f++) pw_v3_store(out->dir + 3 * f, pw_periodic_dir3(&P->pp, f, 0));
    memcpy(out->scale, P->pp.scale, sizeof(float) * (size_t)P->pp.m.nv);
    memcpy(out->material, P->mat, sizeof(float) * (size_t)P->pp.m.nv);
    return pgp__done(&pe, err);
}
