/* lapped.h - lapped textures: overlapping texture patches pasted over a mesh.
 *
 * A single-file C library implementing "Lapped Textures" (Emil Praun, Adam
 * Finkelstein, Hugues Hoppe, SIGGRAPH 2000) and the authors' hindsights:
 * copies of one or more texture patches are pasted onto surface patches grown
 * over a triangle mesh, each parametrised so that the texture follows a
 * tangent field (orientation and scale), until the mesh is covered. Alpha
 * fall-off at the patch borders hides the seams. Section numbers refer to the
 * paper.
 *
 *   - §3.1 texture patches: alpha from the image, from a mask, or generated
 *     (circle, irregular splotch) with a fall-off near the border.
 *   - §3.2 tangent fields: global up, constraints interpolated with Gaussian
 *     radial basis functions over geodesic distance, a per-face frame given
 *     by the caller, isotropic (orientation propagated while growing), or
 *     principal curvature directions (the paper's future work).
 *   - §3.3 surface patch growth around a random uncovered point, disc
 *     topology, growth limited by a polygonal hull of the patch (2D
 *     progressive hull), distortion limit, Maillot's initial parametrisation.
 *   - §3.4 least-squares alignment of the parametrisation with the field
 *     (conjugate gradients, warm start), or least-squares conformal maps for
 *     isotropic textures (hindsights).
 *   - §3.6 coverage of every face, to place the next paste and to stop.
 *   - §4 both renderings: runtime pasting (the ordered pastes composited with
 *     alpha, hidden faces removed) and a texture atlas (charts, automatic
 *     packing, baking) exported as OBJ + MTL + image.
 *
 * USAGE
 *   In exactly one C or C++ file:
 *       #define LAPPED_IMPLEMENTATION
 *       #include "lapped.h"
 *   PATCHWORK_IMPLEMENTATION turns on every patchwork header included after
 *   it. Build macros: LAPPED_STATIC (all functions static), PW_MALLOC /
 *   PW_REALLOC / PW_FREE (all or none), PW_ASSERT, PW_NO_STDIO, the PW_MAX_*
 *   size limits, as in every patchwork header, and PW_THREADS: rendering and
 *   lapped_create's coverage on several threads (POSIX threads; link with
 *   -pthread; lapped_render_options.threads and lapped_options.threads, 0 =
 *   one per processor), the same picture and pastes for any count.
 *   PW_NO_RENDER and PW_NO_PNG leave out the renderer (lapped_render fails
 *   with LAPPED_ERR_UNSUPPORTED) and the PNG codec (loading or saving PNG fails
 *   the same way): faster builds for programs that only compute (docs/api.md).
 *
 * MINIMAL EXAMPLE
 *       lapped_options opt = lapped_default_options();
 *       lapped_mesh mesh;
 *       lapped_image texture, patch, picture;
 *       lapped_source src;
 *       lapped_texture lt;
 *       lapped_error err;
 *       opt.field = LAPPED_FIELD_UP;          (texture "up" follows opt.up, +Y)
 *       opt.scale = 0.3f;                     (patch side, in mesh units)
 *       src.patches = &patch;                 (the patches to paste: one here)
 *       src.npatches = 1;
 *       src.values = NULL;
 *       if (lapped_load_mesh("bunny.obj", &opt, &mesh, &err) ||
 *           lapped_load_image("fur.png", &opt, &texture, &err) ||
 *           lapped_make_patch(&texture, NULL, &opt, &patch, &err) ||
 *           lapped_create(&mesh, &src, &opt, &lt, &err) ||
 *           lapped_render(&mesh, &lt, &src, &opt.render, &picture, &err) ||
 *           lapped_save_image("bunny.png", &picture, &err))
 *           fprintf(stderr, "%s\n", err.message);
 *       (then free everything with lapped_mesh_free, lapped_image_free,
 *        lapped_texture_free)
 *
 *   Settings live in lapped_options: the §3.2 field (field, up, scale,
 *   constraints, face_t/face_s, smoothing), the patches (alpha, falloff),
 *   growth, and the sub-options render (lapped_render) and atlas
 *   (lapped_bake_atlas), all filled by lapped_default_options(). Constraint
 *   files hold "orient F DX DY DZ [SCALE [RADIUS [WEIGHT]]]" lines
 *   (lapped_load_constraints; docs/lapped.md).
 *
 * CONVENTIONS
 *   Fallible calls return lapped_result (LAPPED_OK == 0) and fill
 *   err->message; on success it is empty or holds a warning (a deprecated
 *   constraint file format) that a program may show. Images are floats in
 *   [0,1], row 0 at the top; texture coordinates put (0,0) at the
 *   bottom-left of a patch image and (1,1) at its top-right. Meshes are flat arrays of polygons, counter-clockwise;
 *   polygons are fan-triangulated (corner 0, k, k+1) and every face index in
 *   a result is a triangle of that triangulation, in order. The same inputs
 *   and seed give byte-identical results.
 *
 * Licence: MIT or public domain, at your choice; see the end of the file.
 */
#ifndef LAPPED_H
#define LAPPED_H

#define LAPPED_VERSION_MAJOR 0
#define LAPPED_VERSION_MINOR 9
#define LAPPED_VERSION_PATCH 0
#define LAPPED_VERSION_STRING "0.9.0"

#include <stddef.h>

#ifndef LAPPEDDEF
#ifdef LAPPED_STATIC
#if defined(__GNUC__) || defined(__clang__)
#define LAPPEDDEF static __attribute__((unused))
#else
#define LAPPEDDEF static
#endif
#else
#define LAPPEDDEF extern
#endif
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* Result codes (the same values in every patchwork header). */
typedef enum lapped_result {
    LAPPED_OK = 0,
    LAPPED_ERR_NOMEM = 1,       /* an allocation failed */
    LAPPED_ERR_IO = 2,          /* a file could not be opened, read or written */
    LAPPED_ERR_PARSE = 3,       /* malformed or truncated file */
    LAPPED_ERR_UNSUPPORTED = 4, /* valid input using an unsupported feature */
    LAPPED_ERR_LIMIT = 5,       /* a size exceeds a limit (or would need too many pastes) */
    LAPPED_ERR_INVALID = 6,     /* invalid argument or value (NaN, out of range) */
    LAPPED_ERR_TOPOLOGY = 7,    /* non-manifold or inconsistently oriented mesh */
    LAPPED_ERR_DEGENERATE = 8,  /* degenerate geometry (no faces, zero area) */
    LAPPED_ERR_CANCELLED = 9,   /* the progress callback asked to stop */
    LAPPED_ERR_NOCONVERGE = 10  /* an iterative solver did not converge */
} lapped_result;

typedef struct lapped_error {
    lapped_result code;
    char message[256];
} lapped_error;

/* Optional run-time allocator; NULL functions mean malloc/realloc/free (or
 * the PW_MALLOC macros). Objects remember the allocator that made them. */
typedef struct lapped_allocator {
    void *(*malloc_fn)(void *user, size_t size);
    void *(*realloc_fn)(void *user, void *ptr, size_t size);
    void (*free_fn)(void *user, void *ptr);
    void *user;
} lapped_allocator;

typedef int (*lapped_progress_fn)(void *user, float done, const char *stage);
typedef int (*lapped_write_fn)(void *ctx, const void *data, size_t size);

/* Work split across threads (rendering: bands of the frame; lapped_create:
 * the triangles of each paste painted into the coverage). A parallel
 * for, for embedders with their own job system: run task(ctx, i) once for
 * every i in [0, n), on any threads, in any order, and return when all
 * have run. Results never depend on the order or the thread count. */
typedef void (*lapped_task_fn)(void *ctx, int index);
typedef void (*lapped_parallel_fn)(void *pool, int n, lapped_task_fn task, void *ctx);

/* width*height pixels of `channels` floats in [0,1], row 0 at the top. */
typedef struct lapped_image {
    int width, height, channels;
    float *pixels;
    int bits; /* sample depth read from a file (8 or 16); 0 means 8 */
    lapped_allocator allocator;
} lapped_image;

/* A polygon mesh; corners of face f are face_start[f] .. face_start[f+1]-1. */
typedef struct lapped_mesh {
    int nverts;
    float *positions; /* nverts*3 */
    int nfaces;
    int *face_start; /* nfaces+1 */
    int *face_verts; /* face_start[nfaces] */
    lapped_allocator allocator;
} lapped_mesh;

/* §3.1 alpha of a texture patch. */
typedef enum lapped_alpha {
    LAPPED_ALPHA_AUTO = 0, /* the image's alpha if it has one, else a splotch */
    LAPPED_ALPHA_IMAGE,    /* the image's alpha channel (2 or 4 channels) */
    LAPPED_ALPHA_MASK,     /* a separate mask image (its first channel) */
    LAPPED_ALPHA_CIRCLE,   /* the disc inscribed in the image */
    LAPPED_ALPHA_SPLOTCH   /* an irregular blob (the paper's "splotch") */
} lapped_alpha;

/* §3.2 tangent field modes. */
typedef enum lapped_field_mode {
    LAPPED_FIELD_UP = 0,      /* `up` projected onto every face */
    LAPPED_FIELD_ISOTROPIC,   /* scale only; orientation propagated while growing */
    LAPPED_FIELD_CONSTRAINTS, /* constraints interpolated by Gaussian RBFs of
                                 geodesic (Dijkstra) distance */
    LAPPED_FIELD_FACES,       /* a frame per triangle given by the caller */
    LAPPED_FIELD_CURVATURE    /* direction of least curvature, smoothed */
} lapped_field_mode;

/* A user constraint (§3.2): at triangle `face`, texture up along `direction`
 * (projected onto the face) and patch size `scale` (0: the field's scale);
 * its Gaussian has standard deviation `radius` (mesh units, 0: 2*scale) and
 * weight `weight` (0: 1). */
typedef struct lapped_constraint {
    int face;
    float direction[3];
    float scale, radius, weight;
} lapped_constraint;

/* The constraints of a constraint file (lapped_read_constraints), made by
 * the library: count items, freed with lapped_constraints_free. */
typedef struct lapped_constraints {
    int count;
    lapped_constraint *items;
    lapped_allocator allocator;
} lapped_constraints;

/* Texture filtering of lapped_render. */
typedef enum lapped_filter {
    LAPPED_FILTER_TRILINEAR = 0, /* mipmapped (default) */
    LAPPED_FILTER_BILINEAR,      /* level 0 only */
    LAPPED_FILTER_NEAREST        /* level 0, nearest texel */
} lapped_filter;

typedef struct lapped_render_options {
    int width, height;           /* default 800 x 600 */
    int supersample;             /* default 2 */
    float view_dir[3];           /* default (-0.55,-0.45,-0.7) */
    float up[3];                 /* default (0,1,0) */
    float background[3];         /* default white */
    lapped_filter filter;        /* default LAPPED_FILTER_TRILINEAR */
    int threads;                 /* rendering threads: 0 (default) one per processor when the
                                implementation is built with PW_THREADS (POSIX threads;
                                link with -pthread), else 1; n: at most n. With more
                                than one, the allocator is called from several threads */
    lapped_parallel_fn parallel; /* optional: the caller's parallel for, used instead of threads */
    void *parallel_pool;         /* its first argument */
} lapped_render_options;

typedef struct lapped_atlas_options {
    int size;         /* atlas image side, pixels; default 1024 */
    float cone_angle; /* max angle between a chart's normals and its
                                centre's, degrees; default 60 */
    int gutter;       /* pixels between charts (and to the image border), filled
                                by dilation; default 2 (1 lets bilinear lookups at a
                                border touch the neighbouring chart) */
} lapped_atlas_options;

typedef struct lapped_options {
    /* §3.2 the tangent field */
    lapped_field_mode field;              /* default LAPPED_FIELD_UP */
    float up[3];                          /* UP: default (0,1,0) */
    float scale;                          /* side of a texture patch on the surface, mesh units;
                                  0: a tenth of the bounding-box diagonal; lapped_create
                                  refuses a field whose S or T, at any triangle, is under
                                  1e-5 or over 20 times the diagonal */
    const lapped_constraint *constraints; /* CONSTRAINTS */
    int nconstraints;
    const float *face_t;          /* FACES: ntris*3 "up" vectors (|T| = scale) */
    const float *face_s;          /* FACES: ntris*3 "right" vectors, or NULL for T x N */
    int smoothing;                /* CURVATURE: smoothing iterations; default 20 */
    lapped_alpha alpha;           /* lapped_make_patch; default LAPPED_ALPHA_AUTO */
    float falloff;                /* alpha fall-off width at the patch border, pixels;
                                  default 3 (§3.1) */
    int lscm;                     /* isotropic field: least-squares conformal maps
                                  (hindsights) instead of field alignment */
    float coverage;               /* opacity every point must reach; default 0.99 */
    float max_distortion;         /* growth stops where a face's mapped frame is
                                  stretched beyond this factor; default 2 */
    float early;                  /* fraction of the pastes seeded preferably at high
                                  curvature and field discontinuities; default 0.25 */
    int max_pastes;               /* refuse inputs needing more; default 200000 */
    int keep_hidden;              /* 1: keep triangles that later pastes hide (§4 removes
                                  them); each paste is then a whole surface patch */
    unsigned long long seed;      /* default 0 */
    int threads;                  /* lapped_create's coverage threads, as render.threads: 0
                                  (default) one per processor with PW_THREADS, else 1; the
                                  pastes are the same for any number */
    lapped_parallel_fn parallel;  /* optional: the caller's parallel for, used instead of threads */
    void *parallel_pool;          /* its first argument */
    lapped_render_options render; /* lapped_render's settings (pass &opt.render) */
    lapped_atlas_options atlas;   /* lapped_bake_atlas's settings */
    lapped_allocator allocator;
    lapped_progress_fn progress;
    void *progress_user;
} lapped_options;

/* §3.2 the field lapped_compute_field computes: per triangle of the fan
 * triangulation, t ("up", |t| = scale) and s ("right"), ntris*3 each. */
typedef struct lapped_field {
    int ntris;
    float *s;
    float *t;
    lapped_allocator allocator;
} lapped_field;

/* The texture patches a lapped texture pastes: npatches RGBA images (alpha
 * in channel 4). values: NULL, or one image per patch, aligned with it,
 * holding another channel (bump, displacement...) that lapped_render and
 * lapped_bake_atlas show with the patches' alpha; lapped_create ignores it. */
typedef struct lapped_source {
    const lapped_image *patches;
    int npatches;
    const lapped_image *values;
} lapped_source;

/* One paste (§3.5): patch index and, per surface-patch triangle, the
 * texture coordinates of its three corners (in the triangle's vertex order). */
typedef struct lapped_paste {
    int patch;
    int nfaces;
    int *faces; /* nfaces triangle indices */
    float *uvs; /* nfaces*6 */
} lapped_paste;

/* A lapped texture: the ordered pastes (later over earlier). */
typedef struct lapped_texture {
    int ntris; /* triangles of the mesh it was made for */
    int npatches;
    int *patch_size; /* npatches*2: width, height of each patch image */
    int npastes;
    lapped_paste *pastes;
    double layers;        /* mean pastes per triangle after hidden ones were removed */
    double layers_before; /* ... before (the paper reports 1.5-3.2 after) */
    int hard_edges;       /* pastes whose growth stopped at the distortion limit */
    lapped_allocator allocator;
} lapped_texture;

/* A texture atlas (§4): per-triangle-corner coordinates into one image. */
typedef struct lapped_atlas {
    int ntris;
    float *uvs; /* ntris*6, (0,0) bottom-left of the image */
    int ncharts;
    float fill; /* fraction of the image covered by charts */
    lapped_image image;
} lapped_atlas;

LAPPEDDEF lapped_options lapped_default_options(void);
LAPPEDDEF const char *lapped_result_string(lapped_result r);

/* §3.1: an RGBA patch from a texture: alpha per opt->alpha (from `mask`
 * with LAPPED_ALPHA_MASK), then faded to zero over opt->falloff pixels at
 * the border of the opaque region. */
LAPPEDDEF lapped_result lapped_make_patch(const lapped_image *texture, const lapped_image *mask,
                                          const lapped_options *opt, lapped_image *out, lapped_error *err);

/* §3.2: the field per triangle (opt->field and the fields after it),
 * allocated with opt's allocator; free it with lapped_field_free. For
 * LAPPED_FIELD_ISOTROPIC, t is an arbitrary unit direction times the scale
 * (growth propagates its own). */
LAPPEDDEF lapped_result lapped_compute_field(const lapped_mesh *mesh, const lapped_options *opt, lapped_field *out,
                                             lapped_error *err);
LAPPEDDEF void lapped_field_free(lapped_field *f);

/* §3: covers the mesh with pastes of src's patches (one chosen at random
 * per paste; src->values is not used). */
LAPPEDDEF lapped_result lapped_create(const lapped_mesh *mesh, const lapped_source *src, const lapped_options *opt,
                                      lapped_texture *out, lapped_error *err);
LAPPEDDEF void lapped_texture_free(lapped_texture *t);

/* §4 runtime pasting: the mesh drawn once per paste, in order, each paste's
 * triangles textured with its patch (or with src->values when not NULL)
 * and composited with the patch's alpha. ro: NULL for the defaults; callers
 * with options pass &opt.render. */
LAPPEDDEF lapped_result lapped_render(const lapped_mesh *mesh, const lapped_texture *t, const lapped_source *src,
                                      const lapped_render_options *ro, lapped_image *out, lapped_error *err);

/* §4 texture atlas: charts, packing (opt->atlas; opt NULL: the defaults),
 * and the lapped texture (or src->values, as above) baked into one image. */
LAPPEDDEF lapped_result lapped_bake_atlas(const lapped_mesh *mesh, const lapped_texture *t, const lapped_source *src,
                                          const lapped_options *opt, lapped_atlas *out, lapped_error *err);
LAPPEDDEF void lapped_atlas_free(lapped_atlas *a);

/* Built-in data for demos and tests. Meshes: "sphere" (icosphere),
 * "torus", "bumpy" (a displaced sphere), "disc" (with a boundary).
 * Textures: "scales", "stripes", "dots". */
LAPPEDDEF lapped_result lapped_builtin_mesh(const char *name, const lapped_options *opt, lapped_mesh *out,
                                            lapped_error *err);
LAPPEDDEF lapped_result lapped_builtin_exemplar(const char *name, int size, const lapped_options *opt,
                                                lapped_image *out, lapped_error *err);

/* Files. The paste file format ("lapped-pastes 1") is documented in
 * docs/lapped.md. */
LAPPEDDEF lapped_result lapped_write_pastes(const lapped_texture *t, lapped_write_fn fn, void *ctx, lapped_error *err);
LAPPEDDEF lapped_result lapped_read_pastes(const void *data, size_t size, const char *name, const lapped_options *opt,
                                           lapped_texture *out, lapped_error *err);
/* Constraint file (UTF-8 text; a byte-order mark is skipped): one
 * constraint per line, "orient F DX DY DZ [SCALE [RADIUS [WEIGHT]]]" (0 or
 * omitted: the defaults of lapped_constraint), '#' starts a comment, blank
 * lines are ignored; an unknown keyword is an error naming the line. Old
 * positional lines ("F DX DY DZ ...", no keyword) are still read, and the
 * call then succeeds with a warning in err->message (code LAPPED_OK).
 * out->items is allocated with opt's allocator; free it with
 * lapped_constraints_free. */
LAPPEDDEF lapped_result lapped_read_constraints(const void *data, size_t size, const char *name,
                                                const lapped_options *opt, lapped_constraints *out, lapped_error *err);
LAPPEDDEF void lapped_constraints_free(lapped_constraints *c);
LAPPEDDEF lapped_result lapped_read_mesh(const void *data, size_t size, const char *name, const lapped_options *opt,
                                         lapped_mesh *out, lapped_error *err);
LAPPEDDEF lapped_result lapped_read_image(const void *data, size_t size, const char *name, const lapped_options *opt,
                                          lapped_image *out, lapped_error *err);
/* format: "png", "ppm", "pgm", "pam" */
LAPPEDDEF lapped_result lapped_write_image(const lapped_image *img, const char *format, lapped_write_fn fn, void *ctx,
                                           lapped_error *err);
/* OBJ of the triangulated mesh with the atlas's per-corner coordinates;
 * mtllib/usemtl when mtl_name is not NULL. */
LAPPEDDEF lapped_result lapped_write_obj(const lapped_mesh *mesh, const lapped_atlas *atlas, const char *mtl_name,
                                         lapped_write_fn fn, void *ctx, lapped_error *err);
/* Binary glTF 2.0 (.glb, one self-contained file): the triangulated mesh
 * with the atlas's per-corner coordinates and the atlas image as its base
 * colour (PNG inside), sampled LINEAR / LINEAR_MIPMAP_LINEAR with
 * CLAMP_TO_EDGE (the gutters keep lookups inside a chart). With view (not
 * NULL), the file also holds the camera lapped_render frames with those
 * options. See src/common/gltf.h. */
LAPPEDDEF lapped_result lapped_write_gltf(const lapped_mesh *mesh, const lapped_atlas *atlas,
                                          const lapped_render_options *view, lapped_write_fn fn, void *ctx,
                                          lapped_error *err);
LAPPEDDEF lapped_result lapped_write_mtl(const char *texture_name, lapped_write_fn fn, void *ctx, lapped_error *err);
#ifndef PW_NO_STDIO
LAPPEDDEF lapped_result lapped_load_mesh(const char *path, const lapped_options *opt, lapped_mesh *out,
                                         lapped_error *err);
LAPPEDDEF lapped_result lapped_load_image(const char *path, const lapped_options *opt, lapped_image *out,
                                          lapped_error *err);
LAPPEDDEF lapped_result lapped_save_image(const char *path, const lapped_image *img, lapped_error *err);
LAPPEDDEF lapped_result lapped_save_pastes(const char *path, const lapped_texture *t, lapped_error *err);
/* The OBJ of the atlas's mesh and, when texture_path is not NULL, an MTL
 * beside it (obj_path with .mtl) whose map_Kd names texture_path (save the
 * atlas image there with lapped_save_image). */
LAPPEDDEF lapped_result lapped_save_obj(const char *obj_path, const lapped_mesh *mesh, const lapped_atlas *atlas,
                                        const char *texture_path, lapped_error *err);
/* lapped_write_gltf into the file path (.glb). */
LAPPEDDEF lapped_result lapped_save_gltf(const char *path, const lapped_mesh *mesh, const lapped_atlas *atlas,
                                         const lapped_render_options *view, lapped_error *err);
LAPPEDDEF lapped_result lapped_load_pastes(const char *path, const lapped_options *opt, lapped_texture *out,
                                           lapped_error *err);
LAPPEDDEF lapped_result lapped_load_constraints(const char *path, const lapped_options *opt, lapped_constraints *out,
                                                lapped_error *err);
#endif

LAPPEDDEF void lapped_mesh_free(lapped_mesh *m);
LAPPEDDEF void lapped_image_free(lapped_image *img);

#ifdef __cplusplus
}
#endif

#endif /* LAPPED_H */
