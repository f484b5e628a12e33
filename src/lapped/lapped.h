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
 *   PW_REALLOC / PW_FREE (all or none), PW_ASSERT, PW_NO_STDIO, and the
 *   PW_MAX_* size limits, as in every patchwork header.
 *
 * MINIMAL EXAMPLE
 *       lapped_options opt = lapped_default_options();
 *       lapped_mesh mesh;
 *       lapped_image texture, patch, picture;
 *       lapped_texture lt;
 *       lapped_error err;
 *       opt.field.mode = LAPPED_FIELD_UP;     (texture "up" follows +Y)
 *       opt.field.scale = 0.3f;               (patch side, in mesh units)
 *       if (lapped_load_mesh("bunny.obj", &opt, &mesh, &err) ||
 *           lapped_load_image("fur.png", &opt, &texture, &err) ||
 *           lapped_make_patch(&texture, NULL, &opt, &patch, &err) ||
 *           lapped_create(&mesh, &patch, 1, &opt, &lt, &err) ||
 *           lapped_render(&mesh, &lt, &patch, NULL, NULL, &picture, &err) ||
 *           lapped_save_image("bunny.png", &picture, &err))
 *           fprintf(stderr, "%s\n", err.message);
 *
 * CONVENTIONS
 *   Fallible calls return lapped_result (LAPPED_OK == 0) and fill
 *   err->message. Images are floats in [0,1], row 0 at the top; texture
 *   coordinates put (0,0) at the bottom-left of a patch image and (1,1) at
 *   its top-right. Meshes are flat arrays of polygons, counter-clockwise;
 *   polygons are fan-triangulated (corner 0, k, k+1) and every face index in
 *   a result is a triangle of that triangulation, in order. The same inputs
 *   and seed give byte-identical results.
 *
 * Licence: MIT or public domain, at your choice; see the end of the file.
 */
#ifndef LAPPED_H
#define LAPPED_H

#define LAPPED_VERSION_MAJOR 1
#define LAPPED_VERSION_MINOR 0
#define LAPPED_VERSION_PATCH 0
#define LAPPED_VERSION_STRING "1.0.0"

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
    int *face_start;  /* nfaces+1 */
    int *face_verts;  /* face_start[nfaces] */
    lapped_allocator allocator;
} lapped_mesh;

/* §3.1 alpha of a texture patch. */
enum {
    LAPPED_ALPHA_AUTO = 0, /* the image's alpha if it has one, else a splotch */
    LAPPED_ALPHA_IMAGE,    /* the image's alpha channel (2 or 4 channels) */
    LAPPED_ALPHA_MASK,     /* a separate mask image (its first channel) */
    LAPPED_ALPHA_CIRCLE,   /* the disc inscribed in the image */
    LAPPED_ALPHA_SPLOTCH   /* an irregular blob (the paper's "splotch") */
};

/* §3.2 tangent field modes. */
enum {
    LAPPED_FIELD_UP = 0,      /* `up` projected onto every face */
    LAPPED_FIELD_ISOTROPIC,   /* scale only; orientation propagated while growing */
    LAPPED_FIELD_CONSTRAINTS, /* constraints interpolated by Gaussian RBFs of
                                 geodesic (Dijkstra) distance */
    LAPPED_FIELD_FACES,       /* a frame per triangle given by the caller */
    LAPPED_FIELD_CURVATURE    /* direction of least curvature, smoothed */
};

/* A user constraint (§3.2): at triangle `face`, texture up along `direction`
 * (projected onto the face) and patch size `scale` (0: the field's scale);
 * its Gaussian has standard deviation `radius` (mesh units, 0: 2*scale) and
 * weight `weight` (0: 1). */
typedef struct lapped_constraint {
    int face;
    float direction[3];
    float scale, radius, weight;
} lapped_constraint;

typedef struct lapped_field {
    int mode;                  /* LAPPED_FIELD_*; default LAPPED_FIELD_UP */
    float up[3];               /* UP: default (0,1,0) */
    float scale;               /* side of a texture patch on the surface, mesh units;
                                  0: a tenth of the bounding-box diagonal */
    const lapped_constraint *constraints; /* CONSTRAINTS */
    int nconstraints;
    const float *face_t;       /* FACES: ntris*3 "up" vectors (|T| = scale) */
    const float *face_s;       /* FACES: ntris*3 "right" vectors, or NULL for T x N */
    int smoothing;             /* CURVATURE: smoothing iterations; default 20 */
} lapped_field;

typedef struct lapped_options {
    lapped_field field;
    int alpha;                 /* lapped_make_patch: LAPPED_ALPHA_*; default AUTO */
    float falloff;             /* alpha fall-off width at the patch border, pixels;
                                  default 3 (§3.1) */
    int lscm;                  /* isotropic field: least-squares conformal maps
                                  (hindsights) instead of field alignment */
    float coverage;            /* opacity every point must reach; default 0.99 */
    float max_distortion;      /* growth stops where a face's mapped frame is
                                  stretched beyond this factor; default 2 */
    float early;               /* fraction of the pastes seeded preferably at high
                                  curvature and field discontinuities; default 0.25 */
    int max_pastes;            /* refuse inputs needing more; default 200000 */
    int keep_hidden;           /* 1: keep triangles that later pastes hide (§4 removes
                                  them); each paste is then a whole surface patch */
    unsigned long long seed;   /* default 0 */
    lapped_allocator allocator;
    lapped_progress_fn progress;
    void *progress_user;
} lapped_options;

/* One paste (§3.5): patch index and, per surface-patch triangle, the
 * texture coordinates of its three corners (in the triangle's vertex order). */
typedef struct lapped_paste {
    int patch;
    int nfaces;
    int *faces;  /* nfaces triangle indices */
    float *uvs;  /* nfaces*6 */
} lapped_paste;

/* A lapped texture: the ordered pastes (later over earlier). */
typedef struct lapped_texture {
    int ntris;               /* triangles of the mesh it was made for */
    int npatches;
    int *patch_size;         /* npatches*2: width, height of each patch image */
    int npastes;
    lapped_paste *pastes;
    double layers;           /* mean pastes per triangle after hidden ones were removed */
    double layers_before;    /* ... before (the paper reports 1.5-3.2 after) */
    int hard_edges;          /* pastes whose growth stopped at the distortion limit */
    lapped_allocator allocator;
} lapped_texture;

typedef struct lapped_render_options {
    int width, height;       /* default 800 x 600 */
    int supersample;         /* default 2 */
    float view_dir[3];       /* default (-0.55,-0.45,-0.7) */
    float up[3];             /* default (0,1,0) */
    float background[3];     /* default white */
    int filter;              /* 0 trilinear (default), 1 bilinear, 2 nearest */
} lapped_render_options;

typedef struct lapped_atlas_options {
    int size;                /* atlas image side, pixels; default 1024 */
    float cone_angle;        /* max angle between a chart's normals and its
                                centre's, degrees; default 60 */
    int gutter;              /* pixels between charts (and to the image border), filled
                                by dilation; default 2 (1 lets bilinear lookups at a
                                border touch the neighbouring chart) */
} lapped_atlas_options;

/* A texture atlas (§4): per-triangle-corner coordinates into one image. */
typedef struct lapped_atlas {
    int ntris;
    float *uvs;              /* ntris*6, (0,0) bottom-left of the image */
    int ncharts;
    float fill;              /* fraction of the image covered by charts */
    lapped_image image;
} lapped_atlas;

LAPPEDDEF lapped_options lapped_default_options(void);
LAPPEDDEF const char *lapped_result_string(lapped_result r);

/* §3.1: an RGBA patch from a texture: alpha per opt->alpha (and opt->mask),
 * then faded to zero over opt->falloff pixels at the border of the opaque
 * region. */
LAPPEDDEF lapped_result lapped_make_patch(const lapped_image *texture, const lapped_image *mask,
                                          const lapped_options *opt, lapped_image *out,
                                          lapped_error *err);

/* §3.2: the field per triangle: t (ntris*3, |t| = scale) and s (ntris*3),
 * caller-allocated. For LAPPED_FIELD_ISOTROPIC, t is an arbitrary unit
 * direction times the scale (growth propagates its own). */
LAPPEDDEF lapped_result lapped_compute_field(const lapped_mesh *mesh, const lapped_options *opt,
                                             float *s, float *t, lapped_error *err);

/* §3: covers the mesh with pastes of the RGBA patches (alpha in channel 4;
 * one chosen at random per paste). */
LAPPEDDEF lapped_result lapped_create(const lapped_mesh *mesh, const lapped_image *patches,
                                      int npatches, const lapped_options *opt,
                                      lapped_texture *out, lapped_error *err);
LAPPEDDEF void lapped_texture_free(lapped_texture *t);

/* §4 runtime pasting: the mesh drawn once per paste, in order, each paste's
 * triangles textured with its patch and composited with alpha. `values`
 * (NULL: the patches) may hold another channel aligned with each patch
 * (bump, displacement...), shown with the patches' alpha. */
LAPPEDDEF lapped_result lapped_render(const lapped_mesh *mesh, const lapped_texture *t,
                                      const lapped_image *patches, const lapped_image *values,
                                      const lapped_render_options *ro, lapped_image *out,
                                      lapped_error *err);

/* §4 texture atlas: charts, packing, and the lapped texture (or another
 * channel, `values` as above) baked into one image. */
LAPPEDDEF lapped_result lapped_bake_atlas(const lapped_mesh *mesh, const lapped_texture *t,
                                          const lapped_image *patches, const lapped_image *values,
                                          const lapped_atlas_options *ao, const lapped_options *opt,
                                          lapped_atlas *out, lapped_error *err);
LAPPEDDEF void lapped_atlas_free(lapped_atlas *a);

/* Built-in data for demos and tests. Meshes: "sphere" (icosphere),
 * "torus", "bumpy" (a displaced sphere), "disc" (with a boundary).
 * Textures: "scales", "stripes", "dots". */
LAPPEDDEF lapped_result lapped_builtin_mesh(const char *name, const lapped_options *opt,
                                            lapped_mesh *out, lapped_error *err);
LAPPEDDEF lapped_result lapped_builtin_texture(const char *name, int size, const lapped_options *opt,
                                               lapped_image *out, lapped_error *err);

/* Files. The paste file format ("lapped-pastes 1") is documented in
 * docs/lapped.md. */
LAPPEDDEF lapped_result lapped_write_pastes_to_func(const lapped_texture *t, lapped_write_fn fn,
                                                    void *ctx, lapped_error *err);
LAPPEDDEF lapped_result lapped_read_pastes_from_memory(const void *data, size_t size,
                                                       const char *name, const lapped_options *opt,
                                                       lapped_texture *out, lapped_error *err);
/* Constraints file: one constraint per line, "face dx dy dz [scale [radius
 * [weight]]]" (0 or omitted: the defaults of lapped_constraint), '#'
 * comments. *out is allocated with opt's allocator; free it with
 * lapped_free_constraints. */
LAPPEDDEF lapped_result lapped_read_constraints_from_memory(const void *data, size_t size,
                                                           const char *name, const lapped_options *opt,
                                                           lapped_constraint **out, int *count,
                                                           lapped_error *err);
LAPPEDDEF void lapped_free_constraints(lapped_constraint *c, const lapped_options *opt);
LAPPEDDEF lapped_result lapped_load_mesh_from_memory(const void *data, size_t size, const char *name,
                                                     const lapped_options *opt, lapped_mesh *out,
                                                     lapped_error *err);
LAPPEDDEF lapped_result lapped_load_image_from_memory(const void *data, size_t size,
                                                      const char *name, const lapped_options *opt,
                                                      lapped_image *out, lapped_error *err);
/* format: "png", "ppm", "pgm", "pam" */
LAPPEDDEF lapped_result lapped_write_image_to_func(const lapped_image *img, const char *format,
                                                   lapped_write_fn fn, void *ctx, lapped_error *err);
/* OBJ of the triangulated mesh with the atlas's per-corner coordinates;
 * mtllib/usemtl when mtl_name is not NULL. */
LAPPEDDEF lapped_result lapped_write_obj_to_func(const lapped_mesh *mesh, const lapped_atlas *atlas,
                                                 const char *mtl_name, lapped_write_fn fn,
                                                 void *ctx, lapped_error *err);
/* Binary glTF 2.0 (.glb, one self-contained file): the triangulated mesh
 * with the atlas's per-corner coordinates and the atlas image as its base
 * colour (PNG inside), sampled LINEAR / LINEAR_MIPMAP_LINEAR with
 * CLAMP_TO_EDGE (the gutters keep lookups inside a chart). With view (not
 * NULL), the file also holds the camera lapped_render frames with those
 * options. See src/common/gltf.h. */
LAPPEDDEF lapped_result lapped_write_gltf_to_func(const lapped_mesh *mesh, const lapped_atlas *atlas,
                                                  const lapped_render_options *view, lapped_write_fn fn, void *ctx,
                                                  lapped_error *err);
LAPPEDDEF lapped_result lapped_write_mtl_to_func(const char *texture_name, lapped_write_fn fn,
                                                 void *ctx, lapped_error *err);
#ifndef PW_NO_STDIO
LAPPEDDEF lapped_result lapped_load_mesh(const char *path, const lapped_options *opt,
                                         lapped_mesh *out, lapped_error *err);
LAPPEDDEF lapped_result lapped_load_image(const char *path, const lapped_options *opt,
                                          lapped_image *out, lapped_error *err);
LAPPEDDEF lapped_result lapped_save_image(const char *path, const lapped_image *img,
                                          lapped_error *err);
LAPPEDDEF lapped_result lapped_save_pastes(const char *path, const lapped_texture *t,
                                           lapped_error *err);
/* The OBJ of the atlas's mesh and, when texture_path is not NULL, an MTL
 * beside it (obj_path with .mtl) whose map_Kd names texture_path (save the
 * atlas image there with lapped_save_image). */
LAPPEDDEF lapped_result lapped_save_obj(const char *obj_path, const lapped_mesh *mesh, const lapped_atlas *atlas,
                                        const char *texture_path, lapped_error *err);
/* lapped_write_gltf_to_func into the file path (.glb). */
LAPPEDDEF lapped_result lapped_save_gltf(const char *path, const lapped_mesh *mesh, const lapped_atlas *atlas,
                                         const lapped_render_options *view, lapped_error *err);
LAPPEDDEF lapped_result lapped_load_pastes(const char *path, const lapped_options *opt,
                                           lapped_texture *out, lapped_error *err);
LAPPEDDEF lapped_result lapped_load_constraints(const char *path, const lapped_options *opt,
                                                lapped_constraint **out, int *count,
                                                lapped_error *err);
#endif

LAPPEDDEF void lapped_mesh_free(lapped_mesh *m);
LAPPEDDEF void lapped_image_free(lapped_image *img);

#ifdef __cplusplus
}
#endif

#endif /* LAPPED_H */
