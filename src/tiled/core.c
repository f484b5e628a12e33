/* core.c: tiled.h's glue to the shared core, its defaults, result
 * strings, frees, and the checks of caller-made input. The implementation
 * follows Kaur 2003, "Texture Mapping Using Tiled Textures" (MS thesis,
 * Texas A&M University); chapter numbers in every part refer to it, and
 * the parts come in its order: layout (ch. III.1), mapping (ch. III.2,
 * VI), synthesis (ch. III.1.3), validation, built-in data, rendering and
 * files. */
#include "../common/base.h"
#include "../common/vec.h"
#include "../common/rng.h"
#include "../common/image.h"
#include "../common/deflate.h"
#include "../common/png.h"
#include "../common/mesh.h"
#include "../common/shapes.h"
#include "../common/halfedge.h"
#include "../common/subdiv.h"
#include "../common/sparse.h"
#include "../common/zsparse.h"
#include "../common/trimesh.h"
#include "../common/heap.h"
#include "../common/dirfield.h"
#include "../common/periodic.h"
#include "../common/raster.h"
#include "../common/render.h"
#include "../common/graphcut.h"
#include "../common/quilt.h"
#include "../common/glue.h"
#include "../common/gltf.h"
#include "tiled.h"

/* ---- glue between the public types and the shared core ------------------ */

/* The public result codes repeat the shared ones. */
typedef char tiled__codes_match[(int)TILED_ERR_NOCONVERGE == PW_ERR_NOCONVERGE ? 1 : -1];

PW_PUBLIC_GLUE(tiled);
PW_PUBLIC_IMAGE_FREE(tiled, TILEDDEF);

/* Moves a pw_mesh's geometry into a public mesh (texture coordinates of a
 * loaded file are dropped: tiled.h computes its own). */
TILEDDEF tiled_options tiled_default_options(void)
{
    tiled_options o;
    memset(&o, 0, sizeof o);
    o.layout.case_number = 2;
    o.layout.pairs = 1;
    o.layout.grid = 4;
    pw_view_defaults(&o.render.width, &o.render.height, &o.render.supersample, o.render.view_dir, o.render.up,
                     o.render.background);
    return o;
}

TILEDDEF const char *tiled_result_string(tiled_result r) { return pw_result_string((int)r); }

static tiled_options tiled__options(const tiled_options *opt) { return opt ? *opt : tiled_default_options(); }

static pw_progress tiled__progress(const tiled_options *o)
{
    pw_progress p;
    p.fn = o->progress;
    p.user = o->progress_user;
    return p;
}

/* Checks a caller-made mesh before anything trusts it. */
static int tiled__check_mesh(const tiled_mesh *m, pw_err *e)
{
    int f, k;
    if (!m || !m->positions || !m->face_start || !m->face_verts)
        return pw_fail(e, PW_ERR_INVALID, "mesh has NULL arrays");
    if (m->nverts < 3 || m->nverts > PW_MAX_MESH_ELEMENTS || m->nfaces > PW_MAX_MESH_ELEMENTS)
        return pw_fail(e, PW_ERR_INVALID, "mesh has %d vertices and %d faces", m->nverts, m->nfaces);
    if (m->nfaces < 1) return pw_fail(e, PW_ERR_DEGENERATE, "mesh has no faces");
    if (m->face_start[0] != 0) return pw_fail(e, PW_ERR_INVALID, "face_start[0] must be 0 (got %d)", m->face_start[0]);
    for (f = 0; f < m->nfaces; f++) {
        int d = m->face_start[f + 1] - m->face_start[f];
        if (d < 3 || d > PW_MAX_FACE_DEGREE || m->face_start[f + 1] > PW_MAX_MESH_ELEMENTS)
            return pw_fail(e, PW_ERR_DEGENERATE, "face %d has %d corners", f, d);
    }
    for (k = 0; k < m->face_start[m->nfaces]; k++)
        if (m->face_verts[k] < 0 || m->face_verts[k] >= m->nverts)
            return pw_fail(e, PW_ERR_INVALID, "face corner %d refers to vertex %d of %d", k, m->face_verts[k],
                           m->nverts);
    for (k = 0; k < 3 * m->nverts; k++)
        if (!pw_is_finite(m->positions[k]))
            return pw_fail(e, PW_ERR_INVALID, "vertex %d has a non-finite coordinate", k / 3);
    return PW_OK;
}

TILEDDEF void tiled_mesh_free(tiled_mesh *m)
{
    pw_alloc a;
    if (!m) return;
    a = tiled__alloc(&m->allocator);
    pw_free(&a, m->positions);
    pw_free(&a, m->face_start);
    pw_free(&a, m->face_verts);
    pw_free(&a, m->uvs);
    pw_free(&a, m->corner_types);
    pw_free(&a, m->face_tiles);
    memset(m, 0, sizeof *m);
}

TILEDDEF void tiled_tileset_free(tiled_tileset *ts)
{
    if (!ts) return;
    tiled_image_free(&ts->atlas);
    memset(ts, 0, sizeof *ts);
}
