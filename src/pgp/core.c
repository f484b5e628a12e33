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
#include "../common/tile3.h"
#include "../common/trimesh.h"
#include "../common/dirfield.h"
#include "../common/glue.h"
#include "pgp.h"

typedef char pgp__codes_match[(int)PGP_ERR_NOCONVERGE == PW_ERR_NOCONVERGE ? 1 : -1];

PW_PUBLIC_GLUE(pgp);

static void pgp__take_mesh(pw_mesh *m, const pw_alloc *a, pgp_mesh *t)
{
    memset(t, 0, sizeof *t);
    t->nverts = m->nv;
    t->positions = m->pos;
    t->nfaces = m->nf;
    t->face_start = m->fstart;
    t->face_verts = m->fv;
    t->allocator = pgp__allocator(a);
    pw_free(a, m->uv);
    pw_free(a, m->fuv);
    memset(m, 0, sizeof *m);
}

PGPDEF pgp_options pgp_default_options(void)
{
    pgp_options o;
    memset(&o, 0, sizeof o);
    o.up[1] = 1.0f;
    o.min_scale = 0.05f;
    o.smoothing = 20;
    o.singular_distortion = 0.5f;
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

PGPDEF void pgp_image_free(pgp_image *img)
{
    pw_alloc a;
    if (!img) return;
    a = pgp__alloc(&img->allocator);
    pw_free(&a, img->pixels);
    memset(img, 0, sizeof *img);
}

PGPDEF void pgp_mesh_free(pgp_mesh *m)
{
    pw_alloc a;
    if (!m) return;
    a = pgp__alloc(&m->allocator);
    pw_free(&a, m->positions);
    pw_free(&a, m->face_start);
    pw_free(&a, m->face_verts);
    memset(m, 0, sizeof *m);
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

/* ---- the mapping ---------------------------------------------------------- */

enum { PGP__ORIENT = 0, PGP__SCALE = 1, PGP__MATERIAL = 2 };

/* A user constraint (§2): orientation at a triangle, scale or material at a
 * vertex; its effect radius; removed ones stay in the list, dead. */
typedef struct pgp__constraint {
    int kind, index, alive;
    float value[3];
    float radius;
} pgp__constraint;

struct pgp_map {
    pw_alloc a;
    pgp_options o;
    float *pos;           /* nv*3, the map's own copy of the positions */
    pw_trimesh m;
    float *conn;          /* dirfield connection, 3nf*2 */
    double *dual;         /* dual edge lengths per half-edge (Dijkstra) */
    double *base;         /* nf*2: default field direction per triangle (frame) */
    double *dir;          /* nf*2: d_s per triangle, unit, in the triangle frame */
    float *scale;         /* nv: S_i */
    float *sfac;          /* nv: the integrability factor of S_i (1 but with
                             options.integrable, pgp__integrable) */
    float *mat;           /* nv: m_i */
    double *zs, *zt;      /* nv*2: the unit complex unknowns of s and t (§2.3) */
    float *stm;           /* nf*9: per corner s, t, m (Eq. 4) */
    int *forder, *vorder; /* triangles and vertices in breadth-first order: the
                             order of the unknowns of every solve */
    unsigned char *vsing; /* nv: singular 1-ring (§3) */
    unsigned char *fsing; /* nf: a corner's 1-ring is singular */
    int nsing;
    float scale0;         /* default tile side */
    pgp__constraint *con;
    int ncon;
    size_t concap;
};

/* The frame of triangle f as 3D vectors (u along its first edge, v = N x u). */
static void pgp__frame(const pgp_map *P, int f, pw_v3 *u, pw_v3 *v) { pw_df_frame(&P->m, f, u, v); }

/* d_s (k = 0) or d_t = N x d_s (k = 1) of triangle f in 3D. */
static pw_v3 pgp__dir3(const pgp_map *P, int f, int k)
{
    pw_v3 u, v, d;
    double x = P->dir[2 * f], y = P->dir[2 * f + 1];
    pgp__frame(P, f, &u, &v);
    if (k == 1) { /* rot90 in the frame */
        double t = x;
        x = -y;
        y = t;
    }
    d = pw_v3_add(pw_v3_scale(u, (float)x), pw_v3_scale(v, (float)y));
    return d;
}

/* S^T = (S_i + S_j + S_k) / 3 (§2.3), each S_i times its integrability
 * factor. */
static double pgp__face_scale(const pgp_map *P, int f)
{
    const int *t = P->m.tri + 3 * f;
    return ((double)P->scale[t[0]] * P->sfac[t[0]] + (double)P->scale[t[1]] * P->sfac[t[1]] +
            (double)P->scale[t[2]] * P->sfac[t[2]]) / 3.0;
}

/* g = d / S^T for s (k = 0) or t (k = 1). */
static pw_v3 pgp__grad(const pgp_map *P, int f, int k)
{
    return pw_v3_scale(pgp__dir3(P, f, k), (float)(1.0 / pgp__face_scale(P, f)));
}

static int pgp__check_vertex(const pgp_map *P, int v, pw_err *e)
{
    if (v < 0 || v >= P->m.nv)
        return pw_fail(e, PW_ERR_INVALID, "vertex %d does not exist (the mesh has %d)", v, P->m.nv);
    return PW_OK;
}

static int pgp__check_face(const pgp_map *P, int f, pw_err *e)
{
    if (f < 0 || f >= P->m.nf)
        return pw_fail(e, PW_ERR_INVALID, "triangle %d does not exist (the mesh has %d)", f, P->m.nf);
    return PW_OK;
}

PGPDEF int pgp_triangle_count(const pgp_map *map) { return map ? map->m.nf : 0; }
PGPDEF int pgp_vertex_count(const pgp_map *map) { return map ? map->m.nv : 0; }

PGPDEF void pgp_get_coords(const pgp_map *map, float *stm)
{
    if (map && stm) memcpy(stm, map->stm, sizeof(float) * 9 * (size_t)map->m.nf);
}

PGPDEF int pgp_get_singular(const pgp_map *map, unsigned char *flags)
{
    if (!map) return 0;
    if (flags) memcpy(flags, map->fsing, (size_t)map->m.nf);
    return map->nsing;
}

PGPDEF void pgp_get_field(const pgp_map *map, float *ds, float *scale, float *material)
{
    int f;
    if (!map) return;
    for (f = 0; ds && f < map->m.nf; f++) pw_v3_store(ds + 3 * f, pgp__dir3(map, f, 0));
    if (scale) memcpy(scale, map->scale, sizeof(float) * (size_t)map->m.nv);
    if (material) memcpy(material, map->mat, sizeof(float) * (size_t)map->m.nv);
}
