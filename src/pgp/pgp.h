/* pgp.h - material-space texturing with a periodic global parameterization.
 *
 * A single-file C library implementing "Material Space Texturing" (Nicolas
 * Ray, Bruno Lévy, Huamin Wang, Greg Turk, Bruno Vallet, Computer Graphics
 * Forum 2009): §1, a material-space tile synthesised from key textures
 * (TILE SYNTHESIS below); §2 and §3, a triangle mesh of any genus gets
 * texture coordinates (s, t, m) into a material-space tile (a 3D texture
 * periodic in s and t, with a material axis m; a plain periodic 2D texture
 * is the one-layer case) that follow constraints on orientation, scale and
 * material, and are updated locally when a constraint is edited.
 *
 *   - §2.1 effect area: each edit recomputes only the triangles within a
 *     radius of its constraint (greedy, in order of distance); everything
 *     outside keeps its values, so edits are local and continuous.
 *   - §2.2 interpolation: scale and material by Laplacian smoothing with the
 *     constraints locked (m clamped to [0,1], scale kept above a floor);
 *     orientation by smoothing unit directions (singularities emerge from
 *     the geometry); without orientation constraints the field is a global
 *     up direction projected on the surface, or the direction of least
 *     curvature.
 *   - §2.3 periodic global parameterization: a unit complex number per
 *     vertex for s and one for t, solved in the least-squares sense from
 *     the per-edge rotations alpha_ij = 2 pi e_ij . (g_T + g_T')/2 with
 *     g = d / S; per-corner coordinates recovered with integer jumps (Eq. 4).
 *   - §2.3 uses cotangent edge weights by default (the printed A_T + A_T'
 *     pushes the distortion into small triangles; PGP_WEIGHTS_AREA keeps it).
 *   - rendering: one lookup per pixel; in the vortex triangles (where s or t
 *     winds, about 1% of them) the coordinates of Knöppel et al.'s stripe
 *     patterns (2015), generalised to s and t, end or fork the pattern at a
 *     point with no ghost and no seam (PGP_FIX_CLEAN, beyond the paper).
 *     §3 is kept (PGP_FIX_PAPER): singular 1-rings (distorted triangles or
 *     edges whose two triangles disagree) drawn with three lookups (one per
 *     corner's point of view) blended barycentrically. The tile is sampled
 *     with mipmaps, wrapping in s and t, clamped and interpolated in m.
 *
 * TILE SYNTHESIS (§1; morph.c, synth.c)
 *   pgp_synthesize_tile builds the material-space tile itself from two or
 *   more key textures and their feature masks (painted by the user, or
 *   computed from the luminance or its gradient, pgp_feature_mask):
 *   - keys are resampled to size x size (never cropped) and made tileable
 *     by graph-cut quilting onto a torus when their wrap-around seam shows;
 *   - §1.1 the masks' periodic signed distances (exact EDT) are morphed
 *     over N >> M steps: advection along grad phi_N by bilinear splatting,
 *     interior dilation inside the target features, sweeping towards
 *     phi_N; the M + 1 masks kept are the steps H(m) at which each layer
 *     flips about as many texels as the next (speed-adaptive subsampling;
 *     pgp_morph_masks alone);
 *   - §1.2 each layer is synthesised under its mask from each end key on
 *     indirection pyramids (coarse to fine, texels in random order, 5x5
 *     colour and 3x3 mask neighbourhoods reduced by PCA, a kd-tree search
 *     with a usage penalty that keeps the colour histograms, everything
 *     periodic), and the two syntheses are blended by m/M;
 *   - more keys chain pairwise morphs; single-tile mode (Fig. 14)
 *     synthesises every layer under one key's mask, to hide its period.
 *   It is the long computation of the family: a progress callback reports
 *   and can cancel (8 layers of 256 x 256: about 12 s on one core).
 *       pgp_key keys[2] = {{&spots, NULL}, {&stripes, NULL}};
 *       pgp_options opt = pgp_default_options();
 *       opt.synth.size = 256;
 *       opt.synth.layers = 8;
 *       if (pgp_synthesize_tile(keys, 2, &opt.synth, &tile, NULL, &err) ||
 *           pgp_save_tile("spots_to_stripes.nrrd", &tile, &err))
 *           fprintf(stderr, "%s\n", err.message);
 *
 * USAGE
 *   In exactly one C or C++ file:
 *       #define PGP_IMPLEMENTATION
 *       #include "pgp.h"
 *   PATCHWORK_IMPLEMENTATION turns on every patchwork header included after
 *   it. Build macros: PGP_STATIC (all functions static), PW_MALLOC /
 *   PW_REALLOC / PW_FREE (all or none), PW_ASSERT, PW_NO_STDIO, the PW_MAX_*
 *   size limits, as in every patchwork header, and PW_THREADS: rendering,
 *   tile synthesis and the solves of pgp_create and the edits on several
 *   threads (POSIX threads; link with -pthread; pgp_render_options.threads,
 *   pgp_synth_options.threads and pgp_options.threads, 0 = one per
 *   processor), the same picture, tile and map for any count.
 *   PW_NO_RENDER and PW_NO_PNG leave out the renderer (pgp_render fails
 *   with PGP_ERR_UNSUPPORTED) and the PNG codec (loading or saving PNG fails
 *   the same way): faster builds for programs that only compute (docs/api.md).
 *
 * MINIMAL EXAMPLE
 *       pgp_options opt = pgp_default_options();
 *       pgp_constraint fur = {PGP_CONSTRAINT_MATERIAL, 120, {1.0f, 0.0f, 0.0f}, 0.0f};
 *       pgp_mesh mesh;
 *       pgp_tile tile;
 *       pgp_map map = {0};                     (zeroed: pgp_map_free is safe)
 *       pgp_image picture;
 *       pgp_error err;
 *       opt.scale = 0.2f;                      (tile side, mesh units)
 *       opt.constraints = &fur;                (m = 1 at vertex 120)
 *       opt.nconstraints = 1;
 *       if (pgp_load_mesh("bunny.obj", &opt, &mesh, &err) ||
 *           pgp_load_tile("fur.nrrd", &opt, &tile, &err) ||
 *           pgp_create(&mesh, &opt, &map, &err) ||
 *           pgp_render(&map, &tile, &opt.render, &picture, &err) ||
 *           pgp_save_image("bunny.png", &picture, &err))
 *           fprintf(stderr, "%s\n", err.message);
 *       pgp_map_free(&map);                    (each object made has its _free)
 *   Constraints can also be added, edited and removed after pgp_create
 *   (pgp_add_constraint, pgp_edit_constraint, pgp_remove_constraint), or
 *   read from a file (pgp_load_constraints, then opt.constraints =
 *   cons.items, opt.nconstraints = cons.count).
 *
 * CONVENTIONS
 *   Fallible calls return pgp_result (PGP_OK == 0) and fill err->message.
 *   Images are floats in [0,1], row 0 at the top; t = 0 is the bottom row of
 *   a tile (OBJ/OpenGL). Meshes are flat arrays of polygons, counter-
 *   clockwise, fan-triangulated (corner 0, k, k+1); every face index is a
 *   triangle of that triangulation. The same inputs give byte-identical
 *   results.
 *
 * Licence: MIT or public domain, at your choice; see the end of the file.
 */
#ifndef PGP_H
#define PGP_H

#define PGP_VERSION_MAJOR 0
#define PGP_VERSION_MINOR 9
#define PGP_VERSION_PATCH 0
#define PGP_VERSION_STRING "0.9.0"

#include <stddef.h>

#ifndef PGPDEF
#ifdef PGP_STATIC
#if defined(__GNUC__) || defined(__clang__)
#define PGPDEF static __attribute__((unused))
#else
#define PGPDEF static
#endif
#else
#define PGPDEF extern
#endif
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* Result codes (the same values in every patchwork header). */
typedef enum pgp_result {
    PGP_OK = 0,
    PGP_ERR_NOMEM = 1,       /* an allocation failed */
    PGP_ERR_IO = 2,          /* a file could not be opened, read or written */
    PGP_ERR_PARSE = 3,       /* malformed or truncated file */
    PGP_ERR_UNSUPPORTED = 4, /* valid input using an unsupported feature */
    PGP_ERR_LIMIT = 5,       /* a size exceeds a limit  */
    PGP_ERR_INVALID = 6,     /* invalid argument or value (NaN, out of range) */
    PGP_ERR_TOPOLOGY = 7,    /* non-manifold or inconsistently oriented mesh */
    PGP_ERR_DEGENERATE = 8,  /* degenerate geometry (no faces, zero area) */
    PGP_ERR_CANCELLED = 9,   /* the progress callback asked to stop */
    PGP_ERR_NOCONVERGE = 10  /* an iterative solver did not converge */
} pgp_result;

typedef struct pgp_error {
    pgp_result code;
    char message[256];
} pgp_error;

/* Optional run-time allocator; NULL functions mean malloc/realloc/free (or
 * the PW_MALLOC macros). Objects remember the allocator that made them. */
typedef struct pgp_allocator {
    void *(*malloc_fn)(void *user, size_t size);
    void *(*realloc_fn)(void *user, void *ptr, size_t size);
    void (*free_fn)(void *user, void *ptr);
    void *user;
} pgp_allocator;

typedef int (*pgp_progress_fn)(void *user, float done, const char *stage);
typedef int (*pgp_write_fn)(void *ctx, const void *data, size_t size);

/* Work split across threads (rendering: bands of the frame). A parallel
 * for, for embedders with their own job system: run task(ctx, i) once for
 * every i in [0, n), on any threads, in any order, and return when all
 * have run. Results never depend on the order or the thread count. */
typedef void (*pgp_task_fn)(void *ctx, int index);
typedef void (*pgp_parallel_fn)(void *pool, int n, pgp_task_fn task, void *ctx);

/* width*height pixels of `channels` floats in [0,1], row 0 at the top. */
typedef struct pgp_image {
    int width, height, channels;
    float *pixels;
    int bits; /* sample depth read from a file (8 or 16); 0 means 8 */
    pgp_allocator allocator;
} pgp_image;

/* A polygon mesh; corners of face f are face_start[f] .. face_start[f+1]-1. */
typedef struct pgp_mesh {
    int nverts;
    float *positions; /* nverts*3 */
    int nfaces;
    int *face_start; /* nfaces+1 */
    int *face_verts; /* face_start[nfaces] */
    pgp_allocator allocator;
} pgp_mesh;

/* A material-space tile: `layers` slices of width x height texels with
 * `channels` floats each (1..4), slice k at m = k / (layers - 1); rows from
 * the top, t = 0 at the bottom row. Periodic in s and t. */
typedef struct pgp_tile {
    int width, height, layers, channels;
    float *pixels; /* layers*height*width*channels */
    pgp_allocator allocator;
} pgp_tile;

/* Orientation field where no orientation constraint reaches (§2.2). */
typedef enum pgp_field_mode {
    PGP_FIELD_UP = 0,       /* `up` projected onto every triangle */
    PGP_FIELD_CURVATURE = 1 /* direction of least curvature, smoothed */
} pgp_field_mode;

/* Edge weights of the §2.3 energy. */
typedef enum pgp_weights {
    PGP_WEIGHTS_COTAN = 0, /* cotangent weights (cot a + cot b) / 2, floored at 0.05: the energy is
                              the integral of |grad s - g|^2 over the surface, so distortion costs
                              the same per unit area in small and large triangles */
    PGP_WEIGHTS_AREA = 1   /* the paper's A_T + A_T': the energy per unit area grows with the
                              triangles' area, and the solve pushes distortion into the small
                              ones (kept for comparison) */
} pgp_weights;

/* Rendering of the vortices (pgp_render_options.fix). */
typedef enum pgp_fix {
    PGP_FIX_CLEAN = 0, /* beyond the paper: one lookup everywhere; in each vortex triangle the
                          coordinates of Knöppel et al. 2015's stripe patterns, generalised to
                          s and t, so the pattern ends or forks at a point, with no ghost and
                          no seam (about 1% of the triangles on CGAL's meshes) */
    PGP_FIX_OFF = 1,   /* one lookup of the Eq. (4) coordinates everywhere: a seam at every
                          vortex */
    PGP_FIX_ALL = 2,   /* §3's three blended lookups on every triangle (a reference) */
    PGP_FIX_PAPER = 3  /* §3: three lookups, one per corner's point of view, blended, on the
                          triangles with a singular corner (ghosts where they disagree) */
} pgp_fix;

/* What pgp_render draws (pgp_render_options.show). */
typedef enum pgp_show {
    PGP_SHOW_TILE = 0,     /* the tile */
    PGP_SHOW_MATERIAL = 1, /* the material m in gray */
    PGP_SHOW_SPECIAL = 2,  /* the tile, the triangles drawn specially (see fix) in red */
    PGP_SHOW_GHOSTS = 3    /* white, red where a final colour mixes lookups whose (s, t)
                              differ by more than a tenth of a period */
} pgp_show;

/* Rendering settings (pgp_options.render; pgp_render takes a pointer to
 * them, NULL for the defaults). The tile is always sampled one way:
 * trilinear mipmaps in s and t, linear in m. */
typedef struct pgp_render_options {
    int width, height;        /* default 800 x 600 */
    int supersample;          /* default 2 */
    float view_dir[3];        /* default (-0.55,-0.45,-0.7) */
    float up[3];              /* default (0,1,0) */
    float background[3];      /* default white */
    pgp_fix fix;              /* how vortices and singular triangles are drawn; default
                                CLEAN */
    pgp_show show;            /* default TILE */
    float zoom;               /* > 1: a close-up, the field of view divided by zoom,
                                looking at `center` from the same direction; default 1
                                (the whole mesh; 0 or less is the same) */
    float center[3];          /* the point a close-up looks at (used when zoom > 1) */
    int threads;              /* rendering threads: 0 (default) one per processor when the
                                implementation is built with PW_THREADS (POSIX threads;
                                link with -pthread), else 1; n: at most n. With more
                                than one, the allocator is called from several threads */
    pgp_parallel_fn parallel; /* optional: the caller's parallel for, used instead of threads */
    void *parallel_pool;      /* its first argument */
} pgp_render_options;

/* Masks computed from a key when none is given (§1: "constructed
 * automatically"), on the luminance (colour over white where there is
 * alpha) smoothed by a 3x3 binomial filter, thresholded by Otsu's method. */
typedef enum pgp_mask {
    PGP_MASK_DARK = 0,    /* features are darker than the threshold (spots, grain, mortar) */
    PGP_MASK_BRIGHT = 1,  /* features are brighter */
    PGP_MASK_GRADIENT = 2 /* features are where the gradient magnitude is above its threshold */
} pgp_mask;

/* Keys that do not tile are made tileable by graph-cut quilting onto a
 * torus (§1, [KdE*03]; the mask is cut with the colours). */
typedef enum pgp_tileable {
    PGP_TILEABLE_AUTO = 0, /* quilt a key when its wrap-around seam (mean difference between
                              the last and first column, or row) exceeds twice the mean
                              difference between neighbouring columns (rows) inside it */
    PGP_TILEABLE_KEEP = 1, /* take every key as it is */
    PGP_TILEABLE_MAKE = 2  /* quilt every key */
} pgp_tileable;

/* Tile synthesis settings (§1; pgp_options.synth; the synthesis calls take
 * a pointer to them, NULL for the defaults). */
typedef struct pgp_synth_options {
    int size;                 /* tile side in texels; every key (and mask) is resampled
                            periodically to size x size (bilinear up, box filter down;
                            never cropped); default 128, 16 to 4096 */
    int layers;               /* layers of the tile (m from 0 to 1); the keys sit at evenly
                            spaced layers, the first at 0 and the last at layers-1;
                            default 8 */
    int single;               /* 1: single-tile mode (Fig. 14): one key, every layer
                            synthesised with the key's own mask, to hide periodicity */
    pgp_tileable tileable;    /* default AUTO */
    pgp_mask auto_mask;       /* default DARK */
    int steps;                /* §1.1 advection steps N per morph; 0: at least 16 per layer and
                            enough that dt <= 1/2 texel */
    int uniform;              /* 1: layers at n = m N / M instead of the speed-adaptive H(m) */
    int levels;               /* §1.2 pyramid levels; 0: halve while the side stays even and
                            at least 32 texels */
    int coarse_passes;        /* optimisation passes at the coarsest level; default 20 */
    int fine_passes;          /* ... at every finer level; default 4 */
    int color_window;         /* side of the colour neighbourhood (odd); default 5 */
    int mask_window;          /* side of the mask neighbourhood (odd); default 3 */
    int color_dims;           /* PCA coefficients kept of a colour neighbourhood; default 5, at
                            most 8 */
    int mask_dims;            /* ... of a mask neighbourhood; default 3, at most 8 */
    float mask_weight;        /* scale of the mask coefficients ("scaled by two"); default 2 */
    float usage_weight;       /* usage penalty: each current use of an input texel costs this
                            fraction of the input vectors' total variance; default 0.2;
                            negative: no penalty */
    float search_eps;         /* nearest neighbours within a factor 1 + eps of the nearest
                            distance, as the paper's ANN; default 1; negative: exact */
    int search_buckets;       /* ... scanning at most this many kd-tree buckets (of 8 input
                            texels) per search, ANN's bound on the points visited;
                            default 64; negative: no bound. With search_eps < 0 and
                            search_buckets < 0 every match is the exact nearest one */
    unsigned long long seed;  /* random pixel order and single-tile initialisation, and the
                            noise of the built-in tiles (pgp_builtin_tile); default 0 */
    int threads;              /* synthesis threads, as pgp_render_options.threads: 0 (default)
                             one per processor with PW_THREADS, else 1. The two ends of
                             each morph run side by side; the tile is the same for any
                             number */
    pgp_parallel_fn parallel; /* optional: the caller's parallel for, used instead of threads */
    void *parallel_pool;      /* its first argument */
    pgp_allocator allocator;
    pgp_progress_fn progress; /* may cancel: non-zero return stops with PGP_ERR_CANCELLED; with
                             threads, called from the thread of each morph's first end */
    void *progress_user;
} pgp_synth_options;

/* What a constraint sets (§2). */
typedef enum pgp_constraint_kind {
    PGP_CONSTRAINT_ORIENT = 0, /* the tile's s axis along value[0..2] at a triangle */
    PGP_CONSTRAINT_SCALE,      /* the tile side value[0] (mesh units, > 0) at a vertex */
    PGP_CONSTRAINT_MATERIAL    /* the material value[0] in [0, 1] at a vertex */
} pgp_constraint_kind;

/* A user constraint (§2). */
typedef struct pgp_constraint {
    pgp_constraint_kind kind;
    int element;    /* ORIENT: a triangle; SCALE, MATERIAL: a vertex (0-based) */
    float value[3]; /* ORIENT: the direction; SCALE, MATERIAL: value[0] */
    float radius;   /* effect radius, mesh units, geodesic; 0 or less: the whole mesh */
} pgp_constraint;

/* Constraints read from a file (pgp_read_constraints), freed by
 * pgp_constraints_free. */
typedef struct pgp_constraints {
    int count;
    pgp_constraint *items; /* count */
    pgp_allocator allocator;
} pgp_constraints;

/* A texture atlas of the mapping (pgp_bake_atlas), as lapped.h's. */
typedef struct pgp_atlas_options {
    int size;         /* atlas image side, pixels; default 1024 (16..8192) */
    float cone_angle; /* max angle between a chart's normals and its centre's,
                                degrees; default 60 */
    int gutter;       /* pixels between charts, filled by dilation; default 2 */
} pgp_atlas_options;

typedef struct pgp_options {
    pgp_field_mode field;              /* default UP */
    float up[3];                       /* default (0,1,0): the tile's t axis follows it */
    float scale;                       /* tile side in mesh units where no scale constraint
                                reaches; 0: a tenth of the bounding-box diagonal.
                                pgp_create refuses a side given here over 10 diagonals
                                (one flat colour) or under 2 mean edge lengths
                                (periods the triangles cannot carry) */
    float material;                    /* m where no material constraint reaches; default 0 */
    float min_scale;                   /* floor of the interpolated scale (§2.2 epsilon), as a
                                fraction of `scale`; default 0.05 */
    int smoothing;                     /* CURVATURE: smoothing sweeps; default 20 */
    float singular_distortion;         /* §3: a triangle is distorted when
                                |grad s - g_s|^2 / |g_s|^2 (or for t) exceeds this;
                                default 0.5 */
    pgp_weights weights;               /* default COTAN */
    float integrable;                  /* beyond the paper: 0 (default) follows the field; > 0
                                rotates the field and varies the tile side smoothly
                                (within [1/2, 2] of `scale`, its mean kept) to cancel
                                the curl of the gradients the PGP must follow (each
                                uncancelled turn is a vortex): fewer vortices for less
                                alignment. Larger values let the field stray further
                                (1: the CLI's --field smooth). The UP field is then
                                tried along `up` and two axes perpendicular to it and
                                the one leaving the fewest vortices kept (up on a tie) */
    const pgp_constraint *constraints; /* nconstraints constraints pgp_create applies
                                after building the map, in order, each exactly as
                                pgp_add_constraint would (its own effect area and
                                solve); their ids are 0, 1, ...; default none */
    int nconstraints;
    int threads;               /* threads of pgp_create's and the edits' solves (s and t
                                side by side, holding two copies of the system; the
                                field's multigrid sweeps and the products of its
                                conjugate gradients), as render.threads: 0 (default) one
                                per processor with PW_THREADS, else 1; the map is the
                                same, bit for bit, for any number */
    pgp_parallel_fn parallel;  /* optional: the caller's parallel for, used instead of threads */
    void *parallel_pool;       /* its first argument */
    pgp_render_options render; /* pgp_render's settings (pass &opt.render) */
    pgp_synth_options synth;   /* tile synthesis settings (pass &opt.synth) */
    pgp_atlas_options atlas;   /* pgp_bake_atlas's */
    pgp_allocator allocator;
    pgp_progress_fn progress;
    void *progress_user;
} pgp_options;

/* The mapping of a mesh, made by pgp_create, edited by the constraint
 * calls, freed by pgp_map_free. The fields are for reading. */
typedef struct pgp_map {
    int nverts, ntris;
    int *tris;                   /* ntris*3 vertex indices, counter-clockwise (the fan
                      triangulation of the mesh's faces) */
    float *coords;               /* ntris*9: s, t, m of corners 0, 1, 2, the Eq. (4) coordinates
                      (before the rendering fix), kept current by pgp_create and by
                      every edit */
    struct pgp_map_state *state; /* private: solver, fields, constraints */
    pgp_allocator allocator;
} pgp_map;

/* Triangles an edit recomputed (§2.1), freed by pgp_area_free. */
typedef struct pgp_area {
    int nfaces;
    int *faces;
    pgp_allocator allocator;
} pgp_area;

/* The interpolated fields of a map after its edits (§2.2), freed by
 * pgp_field_free. */
typedef struct pgp_field {
    int ntris, nverts;
    float *dir;      /* ntris*3: d_s per triangle, unit */
    float *scale;    /* nverts: the tile side S_i */
    float *material; /* nverts: m_i */
    pgp_allocator allocator;
} pgp_field;

/* What a mapping came to (issue 17: say what happened). Shares of the
 * surface are area-weighted, over the Eq. (4) coordinates: stretched when
 * the singular values of S (grad s, grad t) leave [1/1.3, 1.3] (more than
 * 30% of stretch or compression), sheared when grad s and grad t are more
 * than 20 degrees away from perpendicular. */
typedef struct pgp_stats {
    int triangles, vortices;  /* pgp_map_vortices */
    int singular;             /* §3's singular triangles (pgp_map_singular) */
    float stretched, sheared; /* shares of the surface, in [0, 1] */
    float mean_edge;          /* mean edge length */
    float diagonal;           /* bounding-box diagonal */
    float scale;              /* the default tile side (options.scale or its default) */
} pgp_stats;

/* Every field filled in, sub-options (render, synth) included. */
PGPDEF pgp_options pgp_default_options(void);
PGPDEF const char *pgp_result_string(pgp_result r);

/* Builds the mapping of a mesh into *out: the default field, scale and
 * material, the initial parameterization (one vertex locked, §2.3), then
 * opt->constraints one by one. On failure *out is zeroed. */
PGPDEF pgp_result pgp_create(const pgp_mesh *mesh, const pgp_options *opt, pgp_map *out, pgp_error *err);
PGPDEF void pgp_map_free(pgp_map *map);

/* Constraints (§2). Each call recomputes the effect area: the triangles
 * within c->radius of the constraint, in order of distance; the rest is
 * locked. On success *id (if not NULL) names the constraint and *area (if
 * not NULL) lists the triangles recomputed. */
PGPDEF pgp_result pgp_add_constraint(pgp_map *map, const pgp_constraint *c, int *id, pgp_area *area, pgp_error *err);
/* A new value for constraint `id` (the direction for ORIENT, value[0] for
 * SCALE and MATERIAL), recomputed over the same radius. */
PGPDEF pgp_result pgp_edit_constraint(pgp_map *map, int id, const float value[3], pgp_area *area, pgp_error *err);
PGPDEF pgp_result pgp_remove_constraint(pgp_map *map, int id, pgp_area *area, pgp_error *err);
PGPDEF void pgp_area_free(pgp_area *area);

/* Singular triangles (§3, those with a corner whose 1-ring is singular):
 * flags[ntris] set to 0/1 when flags is not NULL; returns their number. */
PGPDEF int pgp_map_singular(const pgp_map *map, unsigned char *flags);
/* Vortices: triangles around which s or t winds by a whole period (the
 * T-junctions and poles of the parameterization, the seeds of the singular
 * 1-rings). flags[ntris] set to 0 or 1 (s winds) + 2 (t winds) when flags
 * is not NULL; returns the number of triangles with a vortex. */
PGPDEF int pgp_map_vortices(const pgp_map *map, unsigned char *flags);
/* Triangles pgp_render draws specially with fix mode `fix`: flags[ntris]
 * set to 0/1 when flags is not NULL; returns their number. */
PGPDEF int pgp_map_special(const pgp_map *map, pgp_fix fix, unsigned char *flags);
PGPDEF void pgp_map_stats(const pgp_map *map, pgp_stats *out);
/* The interpolated fields, allocated with the map's allocator. */
PGPDEF pgp_result pgp_map_field(const pgp_map *map, pgp_field *out, pgp_error *err);
PGPDEF void pgp_field_free(pgp_field *field);

/* §3: renders the mapped mesh textured with the tile (ro NULL: defaults). */
PGPDEF pgp_result pgp_render(const pgp_map *map, const pgp_tile *tile, const pgp_render_options *ro, pgp_image *out,
                             pgp_error *err);

/* The mapping for other programs: per-corner texture coordinates and one
 * image. From pgp_bake_atlas, charts of the mesh and the image of what
 * pgp_render draws (the tile through the coordinates, with the rendering
 * of vortices that opt->render.fix asks for, unlit); from pgp_tile_atlas,
 * the raw (s, t) of Eq. (4) and one layer of the tile, wrapped (repeat),
 * for a program with its own material-space shader (singular triangles
 * then show their seams, §3). */
typedef struct pgp_atlas {
    int ntris;
    float *uvs;  /* ntris*6, per corner, v = 0 at the bottom of the image */
    int ncharts; /* charts of a baked atlas (0 for the raw coordinates) */
    float fill;  /* fraction of the image the charts cover (1 for the raw) */
    int repeat;  /* 1: the coordinates wrap (the raw (s, t)); 0: within [0, 1] */
    pgp_image image;
} pgp_atlas;

/* Bakes the rendering into an atlas of opt->atlas's size (charts, packing
 * and baking as lapped.h's §4 atlas, src/common/atlas.h), each texel the
 * tile's colour there, mip level from the texel's footprint, as
 * opt->render.fix and .show say (over black where the tile has alpha). */
PGPDEF pgp_result pgp_bake_atlas(const pgp_map *map, const pgp_tile *tile, const pgp_options *opt, pgp_atlas *out,
                                 pgp_error *err);
/* The raw (s, t) per corner and the tile's layer at material m (0..1,
 * the two nearest layers blended). */
PGPDEF pgp_result pgp_tile_atlas(const pgp_map *map, const pgp_tile *tile, float m, pgp_atlas *out, pgp_error *err);
PGPDEF void pgp_atlas_free(pgp_atlas *atlas);

/* Binary glTF 2.0 (.glb, one self-contained file, src/common/gltf.h): the
 * triangulated mesh with the atlas's coordinates and image as its base
 * colour (sampled LINEAR / LINEAR_MIPMAP_LINEAR, CLAMP_TO_EDGE, or REPEAT
 * for pgp_tile_atlas's). With view (not NULL), the camera pgp_render frames
 * with those options (zoom included). */
PGPDEF pgp_result pgp_write_gltf(const pgp_map *map, const pgp_atlas *atlas, const pgp_render_options *view,
                                 pgp_write_fn fn, void *ctx, pgp_error *err);

/* Built-in data for demos and tests. Meshes: "sphere", "torus", "bumpy",
 * "grid" (a flat square, with a boundary). Tiles: "bricks" (bricks that
 * weather into pebbles along m, 4 layers), "stripes" (1 layer); their
 * noise follows opt->synth.seed. */
PGPDEF pgp_result pgp_builtin_mesh(const char *name, const pgp_options *opt, pgp_mesh *out, pgp_error *err);
PGPDEF pgp_result pgp_builtin_tile(const char *name, int size, const pgp_options *opt, pgp_tile *out, pgp_error *err);

/* Files and memory. Tiles: NRRD (uint8/uint16/float, dimension 4 with
 * sizes C W H M, or 3 with W H M, raw or gzip) or any 2D image (one
 * layer). Meshes: OBJ, OFF, PLY, STL. Images: PNG, PPM/PGM/PAM, GIMP .pat;
 * written as PNG, PPM, PGM or PAM (format "png", "ppm", "pgm", "pam"). */
PGPDEF pgp_result pgp_tile_from_image(const pgp_image *img, const pgp_options *opt, pgp_tile *out, pgp_error *err);
PGPDEF pgp_result pgp_read_tile(const void *data, size_t size, const char *name, const pgp_options *opt, pgp_tile *out,
                                pgp_error *err);
PGPDEF pgp_result pgp_write_tile(const pgp_tile *tile, pgp_write_fn fn, void *ctx, pgp_error *err);
PGPDEF pgp_result pgp_read_mesh(const void *data, size_t size, const char *name, const pgp_options *opt, pgp_mesh *out,
                                pgp_error *err);
PGPDEF pgp_result pgp_read_image(const void *data, size_t size, const char *name, const pgp_options *opt,
                                 pgp_image *out, pgp_error *err);
PGPDEF pgp_result pgp_write_image(const pgp_image *img, const char *format, pgp_write_fn fn, void *ctx, pgp_error *err);
/* OBJ: the triangulated mesh with `vt s t m` per corner, faces grouped as
 * `g regular` then `g singular`. mesh may be NULL; if given it must be the
 * map's. */
PGPDEF pgp_result pgp_write_obj(const pgp_mesh *mesh, const pgp_map *map, pgp_write_fn fn, void *ctx, pgp_error *err);
/* A constraints file (docs/pgp.md): UTF-8 text, one constraint per line,
 * "orient F dx dy dz", "scale V S", "material V m", and "radius R" for the
 * lines that follow (default 0: the whole mesh); '#' starts a comment. The
 * values are checked (finite, S > 0, m in [0, 1], indices >= 0); whether
 * the elements exist is checked when the constraints are applied. Errors
 * name the file and line. */
PGPDEF pgp_result pgp_read_constraints(const void *data, size_t size, const char *name, const pgp_options *opt,
                                       pgp_constraints *out, pgp_error *err);
#ifndef PW_NO_STDIO
PGPDEF pgp_result pgp_load_mesh(const char *path, const pgp_options *opt, pgp_mesh *out, pgp_error *err);
PGPDEF pgp_result pgp_load_image(const char *path, const pgp_options *opt, pgp_image *out, pgp_error *err);
PGPDEF pgp_result pgp_load_tile(const char *path, const pgp_options *opt, pgp_tile *out, pgp_error *err);
PGPDEF pgp_result pgp_load_constraints(const char *path, const pgp_options *opt, pgp_constraints *out, pgp_error *err);
PGPDEF pgp_result pgp_save_tile(const char *path, const pgp_tile *tile, pgp_error *err);
PGPDEF pgp_result pgp_save_image(const char *path, const pgp_image *img, pgp_error *err);
PGPDEF pgp_result pgp_save_obj(const char *path, const pgp_mesh *mesh, const pgp_map *map, pgp_error *err);
/* pgp_write_gltf into the file path (.glb). */
PGPDEF pgp_result pgp_save_gltf(const char *path, const pgp_map *map, const pgp_atlas *atlas,
                                const pgp_render_options *view, pgp_error *err);
#endif
PGPDEF void pgp_mesh_free(pgp_mesh *m);
PGPDEF void pgp_image_free(pgp_image *img);
PGPDEF void pgp_tile_free(pgp_tile *t);
PGPDEF void pgp_constraints_free(pgp_constraints *c);

/* ======================================================================
 * §1 Material-space tile synthesis (morph.c, synth.c)
 * ====================================================================== */

/* A key texture and its feature mask (§1). */
typedef struct pgp_key {
    const pgp_image *image; /* the key texture, 1-4 channels, any size */
    const pgp_image *mask;  /* its feature mask, the image's size: texels whose
                               luminance is above 1/2 are features (a PGM painted by
                               the user); NULL: computed, see auto_mask */
} pgp_key;

/* The feature mask of an image as computed when a key comes without one:
 * one channel, 1 on features and 0 elsewhere, the image's size. */
PGPDEF pgp_result pgp_feature_mask(const pgp_image *image, pgp_mask mode, const pgp_synth_options *opt, pgp_image *out,
                                   pgp_error *err);

/* §1.1 alone: the feature masks F_0 .. F_M (M = layers - 1, layers >= 2) of
 * the morph from mask0 to mask1 (same size, each with features and
 * background), as a one-channel tile of 0/1 texels, layer 0 = mask0 and
 * the last = mask1. */
PGPDEF pgp_result pgp_morph_masks(const pgp_image *mask0, const pgp_image *mask1, int layers,
                                  const pgp_synth_options *opt, pgp_tile *out, pgp_error *err);

/* §1: the material-space tile of nkeys keys (>= 2; exactly 1 in single-tile
 * mode): opt->layers layers of size x size texels, with the channels of the
 * richest key (gray < RGB, plus alpha if any key has it); consecutive keys
 * are morphed pairwise. masks (may be NULL) receives the feature mask of
 * every layer (one channel, 0/1). Key masks must have features and
 * background, except in single-tile mode. */
PGPDEF pgp_result pgp_synthesize_tile(const pgp_key *keys, int nkeys, const pgp_synth_options *opt, pgp_tile *out,
                                      pgp_tile *masks, pgp_error *err);
/* ---- end of §1 tile synthesis ---- */

#ifdef __cplusplus
}
#endif

#endif /* PGP_H */
