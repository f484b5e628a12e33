/* lst.h - lapped solid textures: solid exemplars pasted inside a model.
 *
 * A single-file C library implementing "Lapped Solid Textures: Filling a
 * Model with Anisotropic Textures" (Kenshi Takayama, Makoto Okabe, Takashi
 * Ijiri, Takeo Igarashi, SIGGRAPH 2008): the inside of a closed surface,
 * cut into tetrahedra, is filled with overlapping copies of a small solid
 * texture (a cubic array of colours) aligned with a volumetric tensor field,
 * until every tetrahedron is covered. What is stored is the tetrahedral mesh
 * and, per paste, the 3D texture coordinates of its tetrahedra: no voxel
 * grid of the model ever exists, so large models cost little memory.
 * Section numbers refer to the paper.
 *
 *   - §3 every texture type of the classification: 0 (isotropic), 1-a
 *     (one axis: fibres), 1-b (depth-varying: layers), 2-a (three distinct
 *     axes), 2-b (three axes, depth-varying). 2-c and 2-d are not supported,
 *     as in the paper (see LST_TYPE_*).
 *   - tetrahedral meshes: TetGen .node/.ele and MEDIT .mesh files, or the
 *     built-in tetrahedralizer (isosurface stuffing) of a closed surface.
 *   - §5.2.1 a 3D "splotch" alpha mask with a fall-off of 5-10% of the
 *     exemplar size, or the exemplar's own alpha; §5.2.7 outer, middle and
 *     inner masks for depth-varying textures.
 *   - §5.2.2 fields: a depth field by thin-plate (r^3) radial basis
 *     functions from constraints painted on surface faces (single face,
 *     flood fill stopped at creases) or put at points (strokes); without
 *     constraints, the normalised distance to the surface. Vectors and
 *     scales by Laplacian smoothing over the mesh with barycentric point
 *     constraints (Eqs. 1-2, sparse least squares), depth-aware weights
 *     exp(-(d_i - d_j)^2) for 2-a/2-b, directions orthogonalised against the
 *     depth gradient; scale 1/|grad depth| for 1-b/2-b; tensor per
 *     tetrahedron the average of its vertices'.
 *   - §5.2.3-5.2.6 pasting: a random uncovered seed tetrahedron, the affine
 *     map of its tensor, clump growth (similar tensor, partly inside the
 *     mask), least-squares texture coordinates with the positional
 *     constraint (normal equations, incomplete-Cholesky conjugate
 *     gradients), regrowth where the warped mask is uncovered, coverage
 *     accumulated at fixed sample points in every tetrahedron (165 as in the
 *     paper by default); a tetrahedron seeded again centres its next paste
 *     at its least-covered sample point, so the fill always ends.
 *   - §5.2.7 depth-varying models: the depth is the v texture coordinate,
 *     the positional constraint (0.5, d_seed, 0.5), the mask chosen by depth.
 *   - §4.6 manual pasting at a point with an orientation and a scale.
 *   - §5.1 rendering: the surface composited with each triangle's ordered
 *     pastes; §5.1.1 cuts by a plane, by any scalar field, or by a stroke
 *     (RBF field), with marching tetrahedra, the mesh split along the cut so
 *     that later cuts work; §5.1.2 volume rendering by slices composited
 *     with alpha; an extra channel (displacement) carried like colour, and
 *     displacement mapping of the surface (Figs. 1c, 4d).
 *   - glTF 2.0 export: the visible boundary (surface and cut faces) with
 *     the model's colour baked into a texture atlas (lst_bake_atlas,
 *     lst_save_gltf), and the camera lst_render uses.
 *
 * USAGE
 *   In exactly one C or C++ file:
 *       #define LST_IMPLEMENTATION
 *       #include "lst.h"
 *   PATCHWORK_IMPLEMENTATION turns on every patchwork header included after
 *   it. Build macros: LST_STATIC (all functions static), PW_MALLOC /
 *   PW_REALLOC / PW_FREE (all or none), PW_ASSERT, PW_NO_STDIO, the PW_MAX_*
 *   size limits, as in every patchwork header, and PW_THREADS: rendering and
 *   lst_create's coverage on several threads (POSIX threads; link with
 *   -pthread; lst_render_options.threads and lst_options.threads, 0 = one
 *   per processor), the same picture and pastes for any count.
 *   PW_NO_RENDER and PW_NO_PNG leave out the renderer (lst_render and
 *   lst_render_volume fail with LST_ERR_UNSUPPORTED) and the PNG codec
 *   (loading or saving PNG fails the same way): faster builds for programs that only compute (docs/api.md).
 *
 * MINIMAL EXAMPLE
 *       lst_options opt = lst_default_options();
 *       lst_mesh surface;
 *       lst_tetmesh tets;
 *       lst_volume texture;
 *       lst_source src = {&texture, NULL};         (no extra channel)
 *       lst_model model;
 *       lst_image picture;
 *       lst_error err;
 *       const float cut[4] = {0, 0, 1, 0};          (keep z <= 0)
 *       opt.type = LST_TYPE_1B;                     (layers along the depth)
 *       if (lst_load_mesh("fruit.obj", &opt, &surface, &err) ||
 *           lst_tetrahedralize(&surface, &opt, &tets, NULL, &err) ||
 *           lst_builtin_exemplar("layers", 64, &opt, &texture, NULL, &err) ||
 *           lst_create(&tets, &surface, &src, &opt, &model, &err) ||
 *           lst_cut_plane(&model, cut, &err) ||
 *           lst_render(&model, &opt.render, &picture, &err) ||
 *           lst_save_image("fruit.png", &picture, &err))
 *           fprintf(stderr, "%s\n", err.message);
 *
 * CONVENTIONS
 *   Fallible calls return lst_result (LST_OK == 0) and fill err->message.
 *   Images are floats in [0,1], row 0 at the top. A volume's texture
 *   coordinates (u, v, w) span the unit cube: u along x (columns, left to
 *   right), v up the rows (v = 0 is the bottom row y = height-1, as in
 *   images), w along the slices (w = 0 the first); the v axis is the depth
 *   axis of depth-varying textures (v = 0 the outer skin) and u the fibre
 *   axis of types 1-a, 2-a and 2-b. Tetrahedra are positively oriented
 *   ((b-a) x (c-a) . (d-a) > 0; readers flip the others). The same inputs
 *   and seed give byte-identical results.
 *
 * Licence: MIT or public domain, at your choice; see the end of the file.
 */
#ifndef LST_H
#define LST_H

#define LST_VERSION_MAJOR 0
#define LST_VERSION_MINOR 9
#define LST_VERSION_PATCH 0
#define LST_VERSION_STRING "0.9.0"

#include <stddef.h>

#ifndef LSTDEF
#ifdef LST_STATIC
#if defined(__GNUC__) || defined(__clang__)
#define LSTDEF static __attribute__((unused))
#else
#define LSTDEF static
#endif
#else
#define LSTDEF extern
#endif
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* Result codes (the same values in every patchwork header). */
typedef enum lst_result {
    LST_OK = 0,
    LST_ERR_NOMEM = 1,       /* an allocation failed */
    LST_ERR_IO = 2,          /* a file could not be opened, read or written */
    LST_ERR_PARSE = 3,       /* malformed or truncated file */
    LST_ERR_UNSUPPORTED = 4, /* valid input using an unsupported feature */
    LST_ERR_LIMIT = 5,       /* a size exceeds a limit (or would need too many pastes) */
    LST_ERR_INVALID = 6,     /* invalid argument or value (NaN, out of range) */
    LST_ERR_TOPOLOGY = 7,    /* open, non-manifold, overlapping or self-intersecting input */
    LST_ERR_DEGENERATE = 8,  /* degenerate geometry (no tetrahedra, zero volume) */
    LST_ERR_CANCELLED = 9,   /* the progress callback asked to stop */
    LST_ERR_NOCONVERGE = 10  /* an iterative solver did not converge */
} lst_result;

typedef struct lst_error {
    lst_result code;
    char message[256];
} lst_error;

/* Optional run-time allocator; NULL functions mean malloc/realloc/free (or
 * the PW_MALLOC macros). Objects remember the allocator that made them. */
typedef struct lst_allocator {
    void *(*malloc_fn)(void *user, size_t size);
    void *(*realloc_fn)(void *user, void *ptr, size_t size);
    void (*free_fn)(void *user, void *ptr);
    void *user;
} lst_allocator;

typedef int (*lst_progress_fn)(void *user, float done, const char *stage);
typedef int (*lst_write_fn)(void *ctx, const void *data, size_t size);

/* Work split across threads (rendering: bands of the frame; lst_create:
 * the tetrahedra of each paste's coverage). A parallel for, for embedders with their own job system: run task(ctx, i) once for
 * every i in [0, n), on any threads, in any order, and return when all
 * have run. Results never depend on the order or the thread count. */
typedef void (*lst_task_fn)(void *ctx, int index);
typedef void (*lst_parallel_fn)(void *pool, int n, lst_task_fn task, void *ctx);

/* width*height pixels of `channels` floats in [0,1], row 0 at the top. */
typedef struct lst_image {
    int width, height, channels;
    float *pixels;
    int bits; /* sample depth read from a file (8 or 16); 0 means 8 */
    lst_allocator allocator;
} lst_image;

/* A closed polygon surface; corners of face f are face_start[f] ..
 * face_start[f+1]-1, counter-clockwise seen from outside. Polygons are
 * fan-triangulated (corners 0, k, k+1) and face indices in constraints
 * are triangles of that triangulation. */
typedef struct lst_mesh {
    int nverts;
    float *positions; /* nverts*3 */
    int nfaces;
    int *face_start; /* nfaces+1 */
    int *face_verts; /* face_start[nfaces] */
    lst_allocator allocator;
} lst_mesh;

/* A tetrahedral mesh: tetrahedron t has corners tets[4t..4t+3], positively
 * oriented. */
typedef struct lst_tetmesh {
    int nverts;
    float *positions; /* nverts*3 */
    int ntets;
    int *tets; /* ntets*4 */
    lst_allocator allocator;
} lst_tetmesh;

/* A solid exemplar or mask: width x height x depth voxels of `channels`
 * floats (1 gray, 2 gray+alpha, 3 RGB, 4 RGBA), x fastest:
 * voxels[((z*height + y)*width + x)*channels + c]. Voxel (x, y, z) is
 * centred at texture coordinates ((x+.5)/width, 1-(y+.5)/height,
 * (z+.5)/depth). */
typedef struct lst_volume {
    int width, height, depth, channels;
    float *voxels;
    lst_allocator allocator;
} lst_volume;

/* §3 texture types. 2-c and 2-d (variation along two or three axes) are
 * not supported: as the paper says, a tiling method is not effective for
 * textures that can be tiled along one axis or none. */
typedef enum lst_type {
    LST_TYPE_0 = 0,  /* isotropic: random orientation per paste; scale from the user */
    LST_TYPE_1A = 1, /* one axis (fibres): u along the direction field, the others random */
    LST_TYPE_1B = 2, /* depth-varying layers: v = depth, u and w random around it;
                        scale 1/|grad depth| */
    LST_TYPE_2A = 3, /* three axes: v along grad depth, u along the direction field
                        (orthogonalised), w = u x v; scale from the user */
    LST_TYPE_2B = 4  /* as 2-a, and depth-varying: v = depth, scale 1/|grad depth| */
} lst_type;

/* §4.1-4.5 user guidance: depth constraints (§4.3, 0 outermost, 1
 * innermost; they steer the RBF depth field), directions and scales
 * (interpolated by Laplacian smoothing). */
typedef enum lst_constraint_kind {
    LST_CONSTRAINT_DEPTH_FACE = 0, /* one surface triangle (single-face-fill tool) */
    LST_CONSTRAINT_DEPTH_FILL,     /* the triangles reachable from `face` without crossing an
                                      edge sharper than `crease` (multi-face-fill tool) */
    LST_CONSTRAINT_DEPTH_POINT,    /* a point (the stroke tool: strokes are sampled points) */
    LST_CONSTRAINT_DIRECTION,      /* the exemplar's u axis at `point` (types 1-a, 2-a, 2-b) */
    LST_CONSTRAINT_SCALE           /* the exemplar's side at `point` (types 0, 1-a, 2-a) */
} lst_constraint_kind;

typedef struct lst_constraint {
    lst_constraint_kind kind;
    int face;           /* DEPTH_FACE, DEPTH_FILL: a triangle of the surface */
    float point[3];     /* DEPTH_POINT, DIRECTION, SCALE */
    float direction[3]; /* DIRECTION (any length but 0) */
    float value;        /* depth in [0,1] (DEPTH_*) or the exemplar's side, mesh units (SCALE, > 0) */
    float crease;       /* DEPTH_FILL: dihedral angle, degrees, at which the fill stops; 0: 30 */
} lst_constraint;

/* Constraints allocated by the library (files, built-in ones); free with
 * lst_constraints_free. */
typedef struct lst_constraints {
    int count;
    lst_constraint *items;
    lst_allocator allocator;
} lst_constraints;

/* §5.2.1 alpha masks. */
typedef enum lst_mask_mode {
    LST_MASK_AUTO = 0,    /* the exemplar's alpha (4 channels) for homogeneous types,
                             else the splotch (always for 1-b and 2-b) */
    LST_MASK_SPLOTCH = 1, /* the built-in splotch (and its outer/middle/inner copies) */
    LST_MASK_EXEMPLAR = 2 /* the exemplar's alpha (types 0, 1-a, 2-a; 4 channels) */
} lst_mask_mode;

/* The masks pasting uses (one-channel alpha volumes), allocated by the
 * library; free with lst_masks_free. */
typedef struct lst_masks {
    int count;
    lst_volume *volumes;
    lst_allocator allocator;
} lst_masks;

/* The fields of §5.2.2, per vertex and per tetrahedron. */
typedef struct lst_field {
    int nverts, ntets;
    float *depth; /* nverts depths in [0,1] (1-b, 2-a, 2-b), or NULL */
    float *frame; /* ntets*9: the images of the exemplar's u, v, w axes (columns R, S, T of
                     the tensor, each as long as the exemplar's side there). For types 0
                     and 1-x the axes without a field are an arbitrary frame that pasting
                     re-draws at random */
    lst_allocator allocator;
} lst_field;

/* What a render draws. */
typedef enum lst_show {
    LST_SHOW_COLOR = 0,  /* the texture */
    LST_SHOW_VALUES = 1, /* the extra channel (its first component) in gray */
    LST_SHOW_PASTES = 2, /* a flat colour per paste: where the clumps are */
    LST_SHOW_DEPTH = 3   /* u, v, w of the topmost paste as red, green, blue */
} lst_show;

typedef struct lst_render_options {
    int width, height;        /* default 800 x 600 */
    int supersample;          /* default 2 */
    float view_dir[3];        /* default (-0.55,-0.45,-0.7) */
    float up[3];              /* default (0,1,0) */
    float background[3];      /* default white */
    lst_show show;            /* default LST_SHOW_COLOR */
    int unlit;                /* 1: no shading, the texture as it is */
    float displace;           /* displacement mapping: the surface moved along its normal by
                             this times (values - 0.5), mesh units; 0: none */
    int subdivide;            /* with displacement: each surface triangle split into 4^k; default 2 */
    int threads;              /* rendering threads: 0 (default) one per processor when the
                                implementation is built with PW_THREADS (POSIX threads;
                                link with -pthread), else 1; n: at most n. With more
                                than one, the allocator is called from several threads */
    lst_parallel_fn parallel; /* optional: the caller's parallel for, used instead of threads */
    void *parallel_pool;      /* its first argument */
} lst_render_options;

typedef struct lst_volume_options {
    int slices;    /* §5.1.2: default 200 */
    float opacity; /* opacity of a slab one hundredth of the model's diagonal thick
                             at full density; default 0.3 */
    int density;   /* 0 (default): density = 1 - luminance of the colour (dark is
                             dense); k >= 1: the extra channel's component k-1 */
} lst_volume_options;

/* Settings of the built-in tetrahedralizer (lst_tetrahedralize). */
typedef struct lst_tet_options {
    double cell;     /* lattice spacing, mesh units; 0: chosen from target_tets */
    int target_tets; /* approximate tetrahedron count of the inside (the uniform lattice's whole
                        count); default 20000 (0: 20000) */
    int uniform;     /* 1: the uniform body-centred cubic lattice (proven dihedral bounds
                        10.2..161.7, parts thinner than a cell lost); 0 (default): graded, finer
                        where the surface bends, is thin or nearly touches itself */
    double fit;      /* graded: the bend of the surface allowed inside one lattice tetrahedron,
                        as a fraction of the bounding-box diagonal (the boundary lands within
                        about 1.5 times it); default 0.0025 (0: 0.0025), at most 0.1 */
    int strict;      /* 1: refuse a surface whose triangles cross, naming the first pair */
    double max_hole; /* holes whose perimeters are at most this fraction of the bounding-box diagonal
                        are closed; default 0.05 (0: 0.05); negative: open surfaces refused */
} lst_tet_options;

/* Settings of the texture atlas (lst_bake_atlas), as lapped.h's. */
typedef struct lst_atlas_options {
    int size;         /* atlas image side, pixels (16..8192); default 1024 */
    float cone_angle; /* max angle between a chart's normals and its
                                centre's, degrees, in (0, 180]; default 60 */
    int gutter;       /* pixels between charts (and to the image border), filled
                                by dilation, 1..64 and at most size/8; default 2 */
} lst_atlas_options;

typedef struct lst_options {
    lst_type type;                     /* default LST_TYPE_0 */
    float scale;                       /* exemplar side in mesh units where no scale constraint
                                 reaches (0, 1-a, 2-a); 0: a fifth of the bounding-box
                                 diagonal */
    const lst_constraint *constraints; /* depths, directions and scales; may be NULL. Without a
                                          depth constraint, the depth is the normalised distance
                                          to the surface */
    int nconstraints;
    float axis[3];             /* the direction where no direction constraint is given;
                                 zero: the principal axis of the shape */
    const lst_field *field;    /* NULL: computed (lst_compute_field); else these fields */
    lst_mask_mode mask;        /* default LST_MASK_AUTO */
    float mask_radius;         /* splotch mean radius, fraction of the side; default 0.4 */
    float falloff;             /* splotch fall-off width, fraction of the side; default 0.08 */
    int samples;               /* coverage samples per tetrahedron: the barycentric
                                 lattice of this order, (n+1)(n+2)(n+3)/6 points;
                                 default 8 (165 points, §5.2.6) */
    float coverage;            /* opacity every sample must reach; default 0.99 */
    float max_angle;           /* clump growth: the largest angle, degrees, between a
                                 field axis of a tetrahedron and the seed's; default 50 */
    float max_stretch;         /* clump growth: the largest ratio of scales; default 2 */
    float layer_weight;        /* k in the 2-a/2-b smoothing weights exp(-(k(d_i-d_j))^2);
                                 default 1 (the paper's) */
    float constraint_weight;   /* weight of a constraint row (Eq. 2) against a Laplacian
                                 row (Eq. 1); default 10 */
    int rbf_centers;           /* most centres of the depth RBF (farthest points of the
                                 constraints); default 400 */
    int keep_hidden;           /* 1: keep the paste entries of tetrahedra that a later
                                 paste's opaque core covers entirely (default: drop them) */
    int max_pastes;            /* refuse inputs needing more; default 200000 */
    unsigned long long seed;   /* default 0 */
    int threads;               /* lst_create's coverage threads, as render.threads: 0 (default)
                                 one per processor with PW_THREADS, else 1; the pastes are
                                 the same for any number */
    lst_parallel_fn parallel;  /* optional: the caller's parallel for, used instead of threads */
    void *parallel_pool;       /* its first argument */
    lst_render_options render; /* lst_render's settings (callers pass &opt.render) */
    lst_tet_options tet;       /* lst_tetrahedralize's */
    lst_volume_options volume; /* lst_render_volume's (callers pass &opt.volume) */
    lst_atlas_options atlas;   /* lst_bake_atlas's */
    lst_allocator allocator;
    lst_progress_fn progress;
    void *progress_user;
} lst_options;

/* One paste: a clump of tetrahedra and the texture coordinates of their
 * corners. Corners are shared within a paste (the map is continuous). */
typedef struct lst_paste {
    int exemplar; /* mask index (§5.2.7: 0 outer, 1 middle, 2 inner for 1-b/2-b) */
    int ntets;
    int *tets;    /* ntets tetrahedra */
    int *corners; /* ntets*4: index into verts/uvw of each tetrahedron corner, in order */
    int nverts;
    int *verts; /* nverts tetrahedral-mesh vertices */
    float *uvw; /* nverts*3 texture coordinates (the unit cube is the exemplar) */
} lst_paste;

/* A lapped solid textured model. */
typedef struct lst_model {
    lst_tetmesh mesh;       /* the model's own copy; cuts refine it */
    unsigned char *removed; /* ntets: 1 where a cut took the tetrahedron away */
    int type;               /* LST_TYPE_* it was made with (-1: read from a file) */
    lst_volume texture;     /* the exemplar's colour (1-3 channels: alpha was made a mask) */
    lst_volume values;      /* an extra channel (displacement...), or empty */
    lst_masks masks;        /* paste p uses masks.volumes[p.exemplar] */
    int npastes;
    lst_paste *pastes;    /* in compositing order: later over earlier */
    double layers;        /* mean pastes per tetrahedron */
    double layers_before; /* ... before hidden entries were dropped */
    lst_allocator allocator;
} lst_model;

LSTDEF lst_options lst_default_options(void);
LSTDEF const char *lst_result_string(lst_result r);

/* ---- tetrahedral meshes ---- */

/* Tetrahedralizes the inside of a closed, oriented surface (isosurface
 * stuffing, Labelle & Shewchuk 2007: dihedral angles 10.2-161.7 degrees,
 * the boundary within about a cell of the surface). The solid is where the
 * surface's generalised winding number is at least 1/2, so a closed surface
 * whose triangles cross is filled (counted in the report) unless strict;
 * zero-area triangles are skipped; small holes are closed (each said in a
 * warning in err->message, code LST_OK). Settings:
 * opt->tet. report (may be NULL) receives what the input held and how well
 * the tetrahedra fit it (the fit costs about 0.1-0.5 s). Other open
 * surfaces and non-manifold ones are refused with a message naming the
 * problem (for an open one: how many holes, and where the largest is). */
typedef struct lst_tet_report {
    long crossing_pairs;   /* triangle pairs of the surface that cross */
    int skipped_triangles; /* zero-area triangles the solid does not depend on */
    int closed_holes;      /* small holes of an open surface closed (see max_hole) */
    int pieces;            /* connected components of the tetrahedra (joined by shared faces) */
    int surface_pieces;    /* pieces of the solid the surface encloses (crossing parts counted apart),
                              -1: not counted (too many components) */
    double fit_max;        /* two-sided distance between the boundary of the tetrahedra and the surface
                              (dense area-weighted samples both ways), largest, over the surface's
                              bounding-box diagonal */
    double fit_p99;        /* the same, the larger of the two 99th percentiles */
    int fragments;         /* graded: bits of parts thinner than the smallest cell, cut off from
                              the rest and dropped */
} lst_tet_report;
LSTDEF lst_result lst_tetrahedralize(const lst_mesh *surface, const lst_options *opt, lst_tetmesh *out,
                                     lst_tet_report *report, lst_error *err);
/* Checks a caller's mesh (indices, orientation, zero volumes, faces shared by
 * more than two tetrahedra, overlaps), flipping negative tetrahedra; reports
 * the dihedral angle range in degrees (either pointer may be NULL). */
LSTDEF lst_result lst_tetmesh_check(lst_tetmesh *mesh, double *min_dihedral, double *max_dihedral, lst_error *err);
/* The boundary triangles of a tetrahedral mesh, outward, as a surface
 * sharing its vertices (in order of tetrahedron, then face). */
LSTDEF lst_result lst_tetmesh_surface(const lst_tetmesh *mesh, const lst_options *opt, lst_mesh *out, lst_error *err);

/* ---- exemplars and fields ---- */

/* §5 procedural exemplars of side `size` (0: 64): "layers" (1-b: strata
 * along v with a thin skin), "fibers" (1-a: streaks along u), "spots" (0:
 * isotropic blobs), "rings" (2-b: tree rings along v, bark at v = 0, grain
 * along u), "kiwi" (2-b: skin, flesh, a ring of seeds, core). values (may
 * be NULL) receives a one-channel displacement channel. */
LSTDEF lst_result lst_builtin_exemplar(const char *name, int size, const lst_options *opt, lst_volume *color,
                                       lst_volume *values, lst_error *err);
/* §5.2.1/§5.2.7 the masks pasting would use with this exemplar and these
 * options (1 or 3 one-channel volumes). */
LSTDEF lst_result lst_make_masks(const lst_volume *exemplar, const lst_options *opt, lst_masks *out, lst_error *err);
LSTDEF void lst_masks_free(lst_masks *masks);
/* §5.2.2 the depth, vector, scale and tensor fields. surface: the surface
 * that depth constraints name faces of (NULL: the mesh's boundary). */
LSTDEF lst_result lst_compute_field(const lst_tetmesh *mesh, const lst_mesh *surface, const lst_options *opt,
                                    lst_field *out, lst_error *err);
LSTDEF void lst_field_free(lst_field *f);

/* ---- filling ---- */

/* The texture a model is made of: the solid exemplar, and optionally
 * another channel of the same size (displacement...), carried along for
 * rendering. */
typedef struct lst_source {
    const lst_volume *exemplar;
    const lst_volume *values; /* NULL: none */
} lst_source;

/* §5.2 fills the mesh: pastes until every tetrahedron is covered. */
LSTDEF lst_result lst_create(const lst_tetmesh *mesh, const lst_mesh *surface, const lst_source *src,
                             const lst_options *opt, lst_model *out, lst_error *err);
/* §4.6 a manual paste: centred at `point`, its u axis along u_axis and v
 * along v_axis (made orthogonal), of side `scale` (mesh units), with mask
 * `mask` (an index into the model's masks). */
typedef struct lst_paste_spec {
    float point[3];
    float u_axis[3];
    float v_axis[3];
    float scale;
    int mask;
} lst_paste_spec;
/* One more paste on top of the model. */
LSTDEF lst_result lst_paste_at(lst_model *model, const lst_paste_spec *spec, const lst_options *opt, lst_error *err);
LSTDEF void lst_model_free(lst_model *model);

/* The model at points (n*3): straight RGB and total opacity in rgba (n*4;
 * zero outside the visible tetrahedra), the extra channel in values (n
 * floats per component, may be NULL). Direct evaluation, for checks. */
LSTDEF lst_result lst_eval(const lst_model *model, const float *points, int n, float *rgba, float *values,
                           lst_error *err);

/* ---- cuts (§5.1.1) ---- */

/* Splits the mesh along the plane n.x = d (plane = nx, ny, nz, d) and
 * removes what lies on the side n.x > d. Crossings within a thousandth of
 * an edge of a vertex move onto it (no slivers thinner than that). Like
 * every cut, it is built aside and committed at the end: a failure leaves
 * the model as it was. */
LSTDEF lst_result lst_cut_plane(lst_model *model, const float plane[4], lst_error *err);
/* The same along the zero set of a field given at the vertices (nverts of
 * model->mesh): removes phi > 0. */
LSTDEF lst_result lst_cut_field(lst_model *model, const float *phi, lst_error *err);
/* The field of a stroke (points, n >= 2) seen along view_dir: RBF
 * interpolation (Turk & O'Brien 1999) that is 0 on the stroke swept along
 * the view, positive on its right (view_dir x tangent), at every vertex of
 * the model into phi. */
LSTDEF lst_result lst_stroke_field(const lst_model *model, const float *points, int n, const float view_dir[3],
                                   float *phi, lst_error *err);
/* Everything visible again (the refined mesh stays). */
LSTDEF void lst_uncut(lst_model *model);

/* ---- rendering (§5.1) ---- */

/* The visible boundary (surface and cut faces), each triangle composited
 * with its ordered pastes. Exemplars are sampled trilinearly without mip
 * levels (at the scales pasting uses they are magnified on screen; the
 * supersampling takes care of the rest). ro: NULL or &opt.render (NULL:
 * the defaults). */
LSTDEF lst_result lst_render(const lst_model *model, const lst_render_options *ro, lst_image *out, lst_error *err);
/* §5.1.2 volume rendering: slices perpendicular to the view, composited
 * back to front with an opacity from the density. ro, vo: NULL (the
 * defaults) or &opt.render, &opt.volume. */
LSTDEF lst_result lst_render_volume(const lst_model *model, const lst_render_options *ro, const lst_volume_options *vo,
                                    lst_image *out, lst_error *err);

/* ---- built-in data ---- */

/* Surfaces: "sphere", "torus", "bumpy", "kiwi" (an egg-shaped fruit along
 * z), "tree" (a trunk along z with two branches), and two thin shapes that
 * test the tetrahedralizer: "dumbbell" (two unit balls, a neck 1% of the
 * diagonal thick) and "star" (a ball with 12 long thin spikes). */
LSTDEF lst_result lst_builtin_mesh(const char *name, const lst_options *opt, lst_mesh *out, lst_error *err);
/* The constraints that go with a built-in surface ("kiwi": depth 0 on the
 * skin and 1 along the axis, direction along the axis; "tree": depth 0 on
 * the bark, 1 along the pith of trunk and branches, direction along
 * them; "torus": directions around the ring, no depth). */
LSTDEF lst_result lst_builtin_constraints(const char *name, const lst_mesh *surface, const lst_options *opt,
                                          lst_constraints *out, lst_error *err);

/* ---- files ---- */

/* The model file ("lst 1", documented in docs/lst.md): nodes, tetrahedra,
 * exemplar sizes, pastes with per-tetrahedron texture coordinates. Only
 * the visible tetrahedra are written (a cut model is saved as cut). */
LSTDEF lst_result lst_write_model(const lst_model *model, lst_write_fn fn, void *ctx, lst_error *err);
/* Reads a model file: mesh and pastes; the texture and masks are not in
 * it (they are NRRD files): masks.count is set from the file, the volumes
 * are empty until the caller fills them (lst_make_masks, lst_load_volume). */
LSTDEF lst_result lst_read_model(const void *data, size_t size, const char *name, const lst_options *opt,
                                 lst_model *out, lst_error *err);
/* Constraint files (documented in docs/lst.md), one constraint a line:
 * "face F D", "fill F D [CREASE]", "point X Y Z D", "depth-stroke D X Y Z
 * X Y Z ...", "dir X Y Z DX DY DZ", "dir-stroke X Y Z X Y Z ..."
 * (directions along the polyline), "scale X Y Z S"; '#' comments, blank
 * lines and a byte-order mark skipped. */
LSTDEF lst_result lst_read_constraints(const void *data, size_t size, const char *name, const lst_options *opt,
                                       lst_constraints *out, lst_error *err);
LSTDEF void lst_constraints_free(lst_constraints *c);
/* Tetrahedral meshes: TetGen .node + .ele, MEDIT .mesh. */
LSTDEF lst_result lst_read_tetgen(const void *node, size_t node_size, const void *ele, size_t ele_size,
                                  const char *name, const lst_options *opt, lst_tetmesh *out, lst_error *err);
LSTDEF lst_result lst_read_medit(const void *data, size_t size, const char *name, const lst_options *opt,
                                 lst_tetmesh *out, lst_error *err);
LSTDEF lst_result lst_write_tetgen(const lst_tetmesh *mesh, lst_write_fn node_fn, void *node_ctx, lst_write_fn ele_fn,
                                   void *ele_ctx, lst_error *err);
LSTDEF lst_result lst_write_medit(const lst_tetmesh *mesh, lst_write_fn fn, void *ctx, lst_error *err);
/* Volumes: NRRD (uint8, uint16 or float; sizes C X Y Z or X Y Z; raw or
 * gzip); written as uint8, gzip-compressed. */
LSTDEF lst_result lst_read_volume(const void *data, size_t size, const char *name, const lst_options *opt,
                                  lst_volume *out, lst_error *err);
LSTDEF lst_result lst_write_volume(const lst_volume *vol, lst_write_fn fn, void *ctx, lst_error *err);
/* Surfaces: OBJ, OFF, PLY, STL. */
LSTDEF lst_result lst_read_mesh(const void *data, size_t size, const char *name, const lst_options *opt, lst_mesh *out,
                                lst_error *err);
/* A surface (e.g. the boundary from lst_tetmesh_surface) as OBJ: positions
 * and polygon faces. */
LSTDEF lst_result lst_write_obj(const lst_mesh *mesh, lst_write_fn fn, void *ctx, lst_error *err);
/* Images: PNG, PPM/PGM/PAM, GIMP .pat. */
LSTDEF lst_result lst_read_image(const void *data, size_t size, const char *name, const lst_options *opt,
                                 lst_image *out, lst_error *err);
/* format: "png", "ppm", "pgm", "pam" */
LSTDEF lst_result lst_write_image(const lst_image *img, const char *format, lst_write_fn fn, void *ctx, lst_error *err);
#ifndef PW_NO_STDIO
LSTDEF lst_result lst_load_mesh(const char *path, const lst_options *opt, lst_mesh *out, lst_error *err);
LSTDEF lst_result lst_save_obj(const char *path, const lst_mesh *mesh, lst_error *err);
/* FILE.node (with FILE.ele beside it) or FILE.mesh. */
LSTDEF lst_result lst_load_tetmesh(const char *path, const lst_options *opt, lst_tetmesh *out, lst_error *err);
/* FILE.node (and FILE.ele) or FILE.mesh. */
LSTDEF lst_result lst_save_tetmesh(const char *path, const lst_tetmesh *mesh, lst_error *err);
LSTDEF lst_result lst_load_volume(const char *path, const lst_options *opt, lst_volume *out, lst_error *err);
LSTDEF lst_result lst_save_volume(const char *path, const lst_volume *vol, lst_error *err);
LSTDEF lst_result lst_save_model(const char *path, const lst_model *model, lst_error *err);
LSTDEF lst_result lst_load_model(const char *path, const lst_options *opt, lst_model *out, lst_error *err);
LSTDEF lst_result lst_load_constraints(const char *path, const lst_options *opt, lst_constraints *out, lst_error *err);
LSTDEF lst_result lst_load_image(const char *path, const lst_options *opt, lst_image *out, lst_error *err);
LSTDEF lst_result lst_save_image(const char *path, const lst_image *img, lst_error *err);
#endif

/* ---- glTF export: the visible boundary with a baked atlas ---- */

/* The visible boundary (what lst_render draws: the surface triangles left
 * after the cuts, then the faces the cuts opened) as its own triangle mesh
 * with a texture atlas. Vertices are only those the triangles use; a
 * vertex is written once per side (surface or cut) and once per fan where
 * pieces of the solid touch along an edge or at a vertex, so that the
 * mesh is a manifold. */
typedef struct lst_atlas {
    int nverts;
    float *positions; /* nverts*3 */
    int ntris;
    int *tris;  /* ntris*3, counter-clockwise seen from outside */
    float *uvs; /* ntris*6, per corner, (0,0) bottom-left of the image */
    int ncharts;
    float fill;      /* fraction of the image covered by charts */
    lst_image image; /* RGB: the model's colour (show = COLOR), unlit */
    lst_allocator allocator;
} lst_atlas;
/* Charts of the visible boundary (opt->atlas; opt NULL: the defaults),
 * packed into one image, each texel the model's colour at that point of
 * the boundary as lst_render shows it with show = LST_SHOW_COLOR and
 * unlit (the albedo: the composite of the pastes there). Displacement
 * (render.displace) is not baked. */
LSTDEF lst_result lst_bake_atlas(const lst_model *model, const lst_options *opt, lst_atlas *out, lst_error *err);
LSTDEF void lst_atlas_free(lst_atlas *atlas);
/* Binary glTF 2.0 (.glb, one self-contained file): the atlas's mesh with
 * its per-corner coordinates and the atlas image as its base colour (PNG
 * inside), sampled LINEAR / LINEAR_MIPMAP_LINEAR with CLAMP_TO_EDGE. With
 * view (not NULL), the file also holds the camera lst_render frames with
 * those options. See docs/gltf.md. */
LSTDEF lst_result lst_write_gltf(const lst_atlas *atlas, const lst_render_options *view, lst_write_fn fn, void *ctx,
                                 lst_error *err);
/* The atlas's mesh as OBJ with its per-corner coordinates; mtllib/usemtl
 * when mtl_name is not NULL. */
LSTDEF lst_result lst_write_atlas_obj(const lst_atlas *atlas, const char *mtl_name, lst_write_fn fn, void *ctx,
                                      lst_error *err);
/* The MTL an atlas OBJ names: material "lst" whose map_Kd is texture_name. */
LSTDEF lst_result lst_write_mtl(const char *texture_name, lst_write_fn fn, void *ctx, lst_error *err);
#ifndef PW_NO_STDIO
/* lst_write_gltf into the file path (.glb). */
LSTDEF lst_result lst_save_gltf(const char *path, const lst_atlas *atlas, const lst_render_options *view,
                                lst_error *err);
/* The OBJ of the atlas's mesh and, when texture_path is not NULL, an MTL
 * beside it (obj_path with .mtl) whose map_Kd names texture_path (save the
 * atlas image there with lst_save_image). */
LSTDEF lst_result lst_save_atlas_obj(const char *obj_path, const lst_atlas *atlas, const char *texture_path,
                                     lst_error *err);
#endif

LSTDEF void lst_mesh_free(lst_mesh *m);
LSTDEF void lst_tetmesh_free(lst_tetmesh *m);
LSTDEF void lst_volume_free(lst_volume *v);
LSTDEF void lst_image_free(lst_image *img);

#ifdef __cplusplus
}
#endif

#endif /* LST_H */
