/* tiled.h - seamless, singularity-free tiled textures on quad meshes.
 *
 * A single-file C library implementing "Texture Mapping Using Tiled
 * Textures" (Avneet Kaur, MS thesis, Texas A&M University, 2003): every quad
 * of a mesh gets one square tile of a *tiled texture*, chosen so that the
 * tiles on both sides of every edge continue each other's pattern. No
 * parametrisation, no seams, no singularities, any genus.
 *
 *   - Any polygon mesh: when not all faces are quads, Catmull-Clark
 *     subdivision makes it all quads first (thesis ch. VI); more levels can
 *     be added before mapping (smaller tiles) or after it, carrying the
 *     texture along (a smooth surface, as in the thesis's Figs. 30-31).
 *   - Case 2 (ch. III.1.2, generalised in ch. VI): n boundary pairs; the two
 *     half-edges of every edge get complementary types 2k and 2k+1; the
 *     tiled texture holds all (2n)^4 tiles in a (2n)^2 x (2n)^2 grid.
 *   - Case 1 (ch. III.1.1): one self-matching boundary on all four sides, a
 *     grid x grid set of tiles, random tile, rotation and mirroring per quad.
 *   - Tile-set synthesis from any exemplar image (the thesis used "a variant
 *     of image quilting"): Wang-tile style diamonds with graph-cut seams.
 *   - Validation of hand-made tiled textures, guard bands for filtering,
 *     OBJ + MTL output and a software renderer.
 *
 * USAGE
 *   In exactly one C or C++ file:
 *       #define TILED_IMPLEMENTATION
 *       #include "tiled.h"
 *   elsewhere just #include "tiled.h". PATCHWORK_IMPLEMENTATION turns on the
 *   implementation of every patchwork header included after it.
 *
 * BUILD MACROS (define before including the implementation)
 *   TILED_STATIC           make every function static (private to one file)
 *   PW_MALLOC(sz), PW_REALLOC(p,sz), PW_FREE(p)
 *                          replace malloc/realloc/free (define all or none);
 *                          a run-time allocator can also be set in
 *                          tiled_options.allocator
 *   PW_ASSERT(x)           replace assert() (programmer errors only; bad
 *                          input never asserts)
 *   PW_NO_STDIO            drop the FILE* convenience functions
 *   PW_NO_RENDER, PW_NO_PNG  leave out the renderer (tiled_render fails with
 *                          TILED_ERR_UNSUPPORTED) and the PNG codec (loading
 *                          or saving PNG fails the same way): faster builds
 *                          for programs that only compute (docs/api.md)
 *   PW_THREADS             render and synthesise tiles on several threads
 *                          (POSIX threads; link with -pthread):
 *                          tiled_render_options.threads and
 *                          tiled_options.threads, 0 = one per processor; the
 *                          picture and the tile set are the same for any count
 *   PW_MAX_IMAGE_DIM, PW_MAX_IMAGE_PIXELS, PW_MAX_MESH_ELEMENTS,
 *   PW_MAX_FACE_DEGREE     size limits checked on input (see base module)
 *
 * MINIMAL EXAMPLE
 *       tiled_options opt = tiled_default_options();
 *       tiled_mesh mesh, quads;
 *       tiled_image exemplar, picture;
 *       tiled_tileset tiles;
 *       tiled_error err;
 *       if (tiled_load_mesh("cube.obj", &opt, &mesh, &err) ||
 *           tiled_load_image("pebbles.ppm", &opt, &exemplar, &err) ||
 *           tiled_synthesize(&exemplar, &opt, &tiles, &err) ||
 *           tiled_map(&mesh, &tiles.layout, &opt, &quads, &err) ||
 *           tiled_save_image("tiles.png", &tiles.atlas, &err) ||
 *           tiled_save_obj("cube_tiled.obj", &quads, "tiles.png", &err) ||
 *           tiled_render(&quads, &tiles, &opt.render, &picture, &err) ||
 *           tiled_save_image("cube.png", &picture, &err))
 *           fprintf(stderr, "%s\n", err.message);
 *       (then free everything with tiled_mesh_free, tiled_image_free,
 *        tiled_tileset_free)
 *
 * THE TILED TEXTURE (atlas) LAYOUT
 *   Tiles are T x T pixels. Each sits in a cell of C = T + 2g pixels with a
 *   guard band of g pixels on every side holding the pattern that continues
 *   across that side (what the neighbouring tile shows), so bilinear and
 *   mipmapped lookups near a tile's border never bleed another tile in. The
 *   atlas is N x N cells (N = (2n)^2 in case 2, N = grid in case 1); cell
 *   (col, row) starts at pixel (col*C, row*C) counted from the BOTTOM-LEFT
 *   (texture coordinates put v = 0 at the bottom row of the image).
 *   tiled_tileset.max_mip_level is the last mip level that never mixes two
 *   tiles (C is a multiple of 2^level and 2^level <= g): cap a renderer's
 *   mip chain there. With guard = TILED_NO_GUARD (g = 0) this is exactly
 *   the thesis's layout.
 *
 *   Case 2 tile names: a quad's sides are walked counter-clockwise from the
 *   lower-left corner of its tile: e0 bottom, e1 right, e2 top, e3 left,
 *   each a boundary type in 0..2n-1. The tile e0e1e2e3 sits at column
 *   e0*2n + e1, row e2*2n + e3. Its corner i (0 lower-left, 1 lower-right,
 *   2 upper-right, 3 upper-left) has texture coordinates
 *       u_i = (col*C + g + j*T) / W,  v_i = (row*C + g + (i/2)*T) / W,
 *   j = ((i+1) mod 4)/2 (integer division), W = N*C. (The thesis's Fig. 29
 *   prints the u offset as floor(j/2), which is always 0: a typo.)
 *
 *   Boundary types pair up: the side pattern of type 2k, walked
 *   counter-clockwise around its tile, continues into the type-(2k+1)
 *   pattern rotated by 180 degrees, because the two faces of an edge walk
 *   it in opposite directions.
 *
 * CONVENTIONS
 *   Every fallible call returns tiled_result (TILED_OK == 0) and, when err
 *   is not NULL, fills err->message with a sentence naming what was wrong
 *   (file, line, element index). The same inputs and seed give
 *   byte-identical outputs on every platform. Images are floats in [0,1],
 *   row 0 at the top. Meshes are flat arrays; faces are counter-clockwise.
 *
 * Licence: MIT or public domain, at your choice; see the end of the file.
 */
#ifndef TILED_H
#define TILED_H

#define TILED_VERSION_MAJOR 0
#define TILED_VERSION_MINOR 9
#define TILED_VERSION_PATCH 0
#define TILED_VERSION_STRING "0.9.0"

#include <stddef.h>

#ifndef TILEDDEF
#ifdef TILED_STATIC
#if defined(__GNUC__) || defined(__clang__)
#define TILEDDEF static __attribute__((unused))
#else
#define TILEDDEF static
#endif
#else
#define TILEDDEF extern
#endif
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* Result codes (the same values in every patchwork header). */
typedef enum tiled_result {
    TILED_OK = 0,
    TILED_ERR_NOMEM = 1,       /* an allocation failed */
    TILED_ERR_IO = 2,          /* a file could not be opened, read or written */
    TILED_ERR_PARSE = 3,       /* malformed or truncated file */
    TILED_ERR_UNSUPPORTED = 4, /* valid input using an unsupported feature */
    TILED_ERR_LIMIT = 5,       /* a size exceeds a documented limit */
    TILED_ERR_INVALID = 6,     /* invalid argument or value (NaN, out of range) */
    TILED_ERR_TOPOLOGY = 7,    /* non-manifold or inconsistently oriented mesh */
    TILED_ERR_DEGENERATE = 8,  /* degenerate geometry (no faces, repeated vertex) */
    TILED_ERR_CANCELLED = 9,   /* the progress callback asked to stop */
    TILED_ERR_NOCONVERGE = 10  /* (unused by tiled.h; shared numbering) */
} tiled_result;

/* What went wrong: the code and a message naming the problem. */
typedef struct tiled_error {
    tiled_result code;
    char message[256];
} tiled_error;

/* Optional run-time allocator; NULL functions mean malloc/realloc/free (or
 * the PW_MALLOC macros). Objects remember the allocator that made them. */
typedef struct tiled_allocator {
    void *(*malloc_fn)(void *user, size_t size);
    void *(*realloc_fn)(void *user, void *ptr, size_t size);
    void (*free_fn)(void *user, void *ptr);
    void *user;
} tiled_allocator;

/* Progress callback: `done` in [0,1]; return non-zero to cancel. */
typedef int (*tiled_progress_fn)(void *user, float done, const char *stage);

/* Output sink for the tiled_write_* functions: return 0 on success. */
typedef int (*tiled_write_fn)(void *ctx, const void *data, size_t size);

/* Work split across threads (rendering: bands of the frame). A parallel
 * for, for embedders with their own job system: run task(ctx, i) once for
 * every i in [0, n), on any threads, in any order, and return when all
 * have run. Results never depend on the order or the thread count. */
typedef void (*tiled_task_fn)(void *ctx, int index);
typedef void (*tiled_parallel_fn)(void *pool, int n, tiled_task_fn task, void *ctx);

/* An image: width*height pixels of `channels` floats in [0,1] (1 gray,
 * 2 gray+alpha, 3 RGB, 4 RGBA), row 0 at the top. */
typedef struct tiled_image {
    int width, height, channels;
    float *pixels;             /* width*height*channels, pixels[(y*width + x)*channels + c] */
    int bits;                  /* sample depth the image was read with (8 or 16); 0 means 8 */
    tiled_allocator allocator; /* set by the library on images it allocates */
} tiled_image;

/* A polygon mesh. Corners of face f are face_start[f] .. face_start[f+1]-1,
 * counter-clockwise seen from outside. Outputs of tiled_map also carry
 * per-corner texture coordinates and tile assignments. */
typedef struct tiled_mesh {
    int nverts;
    float *positions; /* nverts*3 */
    int nfaces;
    int *face_start;   /* nfaces+1 */
    int *face_verts;   /* face_start[nfaces] vertex indices */
    float *uvs;        /* face_start[nfaces]*2 per-corner texture coordinates, or NULL */
    int *corner_types; /* face_start[nfaces]: boundary type of the half-edge that
                         leaves each corner (to the next corner), or NULL */
    int *face_tiles;   /* nfaces: tile index row*N + col in the atlas, or NULL */
    tiled_allocator allocator;
} tiled_mesh;

#define TILED_NO_GUARD (-1)

/* How tiles are laid out in the tiled texture; see the top of the file. */
typedef struct tiled_layout {
    int case_number; /* 2 (default): n boundary pairs; 1: one self-matching boundary */
    int pairs;       /* case 2: n, boundary types 0..2n-1; default 1 (16 tiles), max 4 */
    int grid;        /* case 1: tiles per row and column; default 4 (16 tiles) */
    int tile_size;   /* T, pixels; default: from the exemplar (power of two nearest
                        its smaller side, 16..256), or from the tiled image */
    int guard;       /* g, pixels; 0: default (T/8 rounded to a power of two, >= 2);
                        TILED_NO_GUARD: none, the thesis's exact layout */
} tiled_layout;

/* Texture filtering of tiled_render. */
typedef enum tiled_filter {
    TILED_FILTER_TRILINEAR = 0, /* mipmapped, levels capped at max_mip_level (default) */
    TILED_FILTER_BILINEAR = 1,  /* level 0 only */
    TILED_FILTER_NEAREST = 2    /* level 0, nearest texel */
} tiled_filter;

/* Render settings. Zero-initialised means defaults. */
typedef struct tiled_render_options {
    int width, height;          /* default 800 x 600 */
    int supersample;            /* samples per pixel along each axis; default 2 */
    float view_dir[3];          /* direction the camera looks along; default (-0.55,-0.45,-0.7) */
    float up[3];                /* world direction shown upwards; default (0,1,0) */
    float background[3];        /* default (1,1,1) */
    tiled_filter filter;        /* default TILED_FILTER_TRILINEAR */
    int threads;                /* rendering threads: 0 (default) one per processor when the
                                implementation is built with PW_THREADS (POSIX threads;
                                link with -pthread), else 1; n: at most n. With more
                                than one, the allocator is called from several threads */
    tiled_parallel_fn parallel; /* optional: the caller's parallel for, used instead of threads */
    void *parallel_pool;        /* its first argument */
} tiled_render_options;

/* Options. Zero-initialised means defaults; tiled_default_options() returns
 * them filled in. */
/* The field the tiles follow in the mode for any mesh (tiled_options.scale),
 * as pgp.h's: a tile's t axis along +y projected onto the surface, or along
 * the direction of least curvature. */
typedef enum tiled_field { TILED_FIELD_UP = 0, TILED_FIELD_CURVATURE = 1 } tiled_field;

/* What the mode for any mesh did (tiled_options.stats). A cell is one
 * square of the integer grid of the periodic parameterization: one tile. */
typedef struct tiled_grid_stats {
    int triangles;        /* triangles of the input (polygons fan-triangulated) */
    int vortex_triangles; /* of them, where the grid winds (a T-junction):
                             cut into a fan around the pattern's end point */
    int pieces;           /* faces of the output: triangles cut along the grid */
    int cells;            /* cells, one tile each */
    int special_cells;    /* cells covering more than 1.5 cells of the grid or
                             their own neighbour: a vortex's face left whole */
    int cut_vortices;     /* vortices whose face was cut in two along the
                             isoline through them (the others: special) */
    int grid_edges;       /* cell sides shared by two cells */
    int mismatched_edges; /* of them, sides whose types could not be made partners */
    int same_tile_edges;  /* of them, the same tile on both sides */
    int repeated_edges;   /* of them, a (tile, side, tile) seen on an earlier edge */
} tiled_grid_stats;

typedef struct tiled_options {
    tiled_layout layout;
    float scale;                 /* > 0: the mode for any triangle or polygon mesh
                                (beyond the thesis): tiles of this side, in mesh
                                units, on the integer grid of a periodic global
                                parameterization (as pgp.h's), every cell one
                                tile matching its neighbours; 0 (default): one
                                tile per quad */
    tiled_field field;           /* with scale: the field the tiles follow */
    tiled_grid_stats *stats;     /* with scale: filled in when not NULL */
    unsigned long long seed;     /* RNG seed; default 0 */
    int subdivide;               /* extra Catmull-Clark levels once the mesh is all
                                quads, before mapping (more, smaller tiles);
                                default 0 */
    int smooth;                  /* Catmull-Clark levels after mapping, carrying the
                                texture coordinates along (thesis Figs. 30, 31):
                                a smooth surface, each tile still spanning one
                                original quad; default 0 */
    int no_mirror;               /* case 1: do not mirror tiles (rotation only) */
    int fixed_start;             /* 1: always start the tile walk at a face's first
                                corner instead of a random one (thesis's
                                "further randomness" off; with scale: no
                                random half turn per cell); default 0 */
    int threads;                 /* tile synthesis threads, as render.threads: 0 (default)
                                one per processor with PW_THREADS, else 1; the tile set
                                is the same for any number */
    tiled_parallel_fn parallel;  /* optional: the caller's parallel for, used instead of threads */
    void *parallel_pool;         /* its first argument */
    tiled_render_options render; /* tiled_render's settings (pass &opt.render) */
    tiled_allocator allocator;
    tiled_progress_fn progress; /* may be NULL; with threads, called from the thread that
                                composes the first share of the tiles */
    void *progress_user;
} tiled_options;

/* A tile set: its resolved layout and the tiled texture with guard bands. */
typedef struct tiled_tileset {
    tiled_layout layout; /* every field resolved (no zero defaults left) */
    int tiles_per_side;  /* N: the atlas is N x N cells */
    int max_mip_level;   /* mip levels 0..this never mix two tiles */
    tiled_image atlas;   /* N*(T+2g) pixels square */
} tiled_tileset;

/* One tile side whose pattern does not continue into its partners'. */
typedef struct tiled_side_mismatch {
    int tile;   /* tile index row*N + col */
    int side;   /* 0 bottom, 1 right, 2 top, 3 left */
    int type;   /* its boundary type */
    float seam; /* mean colour jump across the side, 0..1 */
} tiled_side_mismatch;

#define TILED_MAX_MISMATCHES 64

/* Report of tiled_validate_tiles. */
typedef struct tiled_validation {
    int sides_checked;
    int nbad;                                      /* sides that do not match (all of them counted) */
    float interior;                                /* typical jump between neighbouring pixels inside tiles */
    float threshold;                               /* a side fails when its seam exceeds this */
    float worst;                                   /* largest seam found */
    tiled_side_mismatch bad[TILED_MAX_MISMATCHES]; /* the first ones, worst first */
} tiled_validation;

/* Defaults and messages. */
TILEDDEF tiled_options tiled_default_options(void);
TILEDDEF const char *tiled_result_string(tiled_result r);

/* Tile sets ------------------------------------------------------------ */

/* Builds an edge-matched tile set from an exemplar image (opt->layout says
 * which case, how many pairs or tiles, tile size and guard). The exemplar
 * should be homogeneous and isotropic: tiles are rotated on the mesh. */
TILEDDEF tiled_result tiled_synthesize(const tiled_image *exemplar, const tiled_options *opt, tiled_tileset *out,
                                       tiled_error *err);

/* Wraps a user-made tiled texture laid out as in the thesis (no guard
 * bands: (2n)^2 x (2n)^2 tiles in case 2, grid x grid in case 1, square)
 * into a tile set with guard bands. Does not check that sides match: see
 * tiled_validate_tiles. */
TILEDDEF tiled_result tiled_tileset_from_image(const tiled_image *tiles, const tiled_options *opt, tiled_tileset *out,
                                               tiled_error *err);

/* Checks a user-made tiled texture (thesis layout, no guard bands): every
 * side must continue into every side it can meet on a mesh. Returns
 * TILED_OK when the check ran; report->nbad says how many sides fail. */
TILEDDEF tiled_result tiled_validate_tiles(const tiled_image *tiles, const tiled_options *opt, tiled_validation *report,
                                           tiled_error *err);

TILEDDEF void tiled_tileset_free(tiled_tileset *ts);

/* Mapping -------------------------------------------------------------- */

/* Assigns a tile to every quad: Catmull-Clark until all faces are quads
 * (plus opt->subdivide levels), AssignBoundaries, then
 * AssignTextureCoordinates for `layout` (use the tile set's), then
 * opt->smooth levels of Catmull-Clark that carry the mapping along. The
 * output mesh has uvs, corner_types (-1 on edges made by smoothing) and
 * face_tiles.
 * With opt->scale > 0, any mesh instead: a periodic global parameterization
 * (s, t) along opt->field, with tiles of side opt->scale (2 mean edge
 * lengths to 10 bounding-box diagonals; opt->subdivide levels of
 * Catmull-Clark first make a coarse mesh fine enough, opt->smooth must be
 * 0); the triangles are cut along the
 * integer grid lines, every grid cell gets the tile its four sides' types
 * name and every shared side partner types. The output's faces are the
 * pieces (polygons in one cell each, corner_types -1 inside cells). */
TILEDDEF tiled_result tiled_map(const tiled_mesh *in, const tiled_layout *layout, const tiled_options *opt,
                                tiled_mesh *out, tiled_error *err);

/* Renders a mapped mesh with its tile set's atlas. */
TILEDDEF tiled_result tiled_render(const tiled_mesh *mapped, const tiled_tileset *ts, const tiled_render_options *ro,
                                   tiled_image *out, tiled_error *err);

/* How wide tiled_render draws a tile, in pixels: the median over faces of
 * a tile side's world length (from each face's areas in world and texture
 * space) at the distance of the framed mesh's centre. Below about 16
 * pixels the texture cannot be seen: the mesh has too many quads for this
 * method (one tile per quad), see tiled_map. */
TILEDDEF tiled_result tiled_drawn_tile_size(const tiled_mesh *mapped, const tiled_tileset *ts,
                                            const tiled_render_options *ro, float *pixels, tiled_error *err);

/* Built-in data ----------------------------------------------------------- */

/* Procedural meshes, scaled to fit [-1,1]^3: "cube", "torus" (24x12 quads),
 * "double-torus" (genus 2, quads), "icosahedron" (triangles), "grid" (open
 * 12x12 quads, with a boundary). */
TILEDDEF tiled_result tiled_builtin_mesh(const char *name, const tiled_options *opt, tiled_mesh *out, tiled_error *err);
/* Procedural exemplars, size x size pixels, RGB, periodic, isotropic:
 * "pebbles", "spots", "lichen". The seed in opt varies them. */
TILEDDEF tiled_result tiled_builtin_exemplar(const char *name, int size, const tiled_options *opt, tiled_image *out,
                                             tiled_error *err);

/* Files ------------------------------------------------------------------ */

/* Meshes: OBJ, OFF (COFF/NOFF...), PLY (ASCII and binary), by content. */
TILEDDEF tiled_result tiled_read_mesh(const void *data, size_t size, const char *name, const tiled_options *opt,
                                      tiled_mesh *out, tiled_error *err);
/* Images: PPM, PGM, PAM (8/16 bit), PNG, GIMP .pat, by content. */
TILEDDEF tiled_result tiled_read_image(const void *data, size_t size, const char *name, const tiled_options *opt,
                                       tiled_image *out, tiled_error *err);
/* format: "png", "ppm", "pgm", "pam" (ppm/pgm pick by channel count). */
TILEDDEF tiled_result tiled_write_image(const tiled_image *img, const char *format, tiled_write_fn fn, void *ctx,
                                        tiled_error *err);
/* OBJ with per-corner vt; mtllib/usemtl lines when mtl_name is not NULL. */
TILEDDEF tiled_result tiled_write_obj(const tiled_mesh *m, const char *mtl_name, tiled_write_fn fn, void *ctx,
                                      tiled_error *err);
/* Binary glTF 2.0 (.glb, one self-contained file): the mesh with its
 * per-corner coordinates and, when texture is not NULL, the tiled texture
 * as its base colour (PNG inside), sampled LINEAR / LINEAR_MIPMAP_LINEAR
 * with CLAMP_TO_EDGE (the tiles' guard bands keep bilinear lookups at a
 * tile's border inside that tile). Vertices are split at texture seams;
 * normals are the mesh's smooth vertex normals. With view (not NULL), the
 * file also holds the camera tiled_render frames with those options, so
 * that a viewer opens it as tiled_render draws it. See src/common/gltf.h. */
TILEDDEF tiled_result tiled_write_gltf(const tiled_mesh *m, const tiled_image *texture,
                                       const tiled_render_options *view, tiled_write_fn fn, void *ctx,
                                       tiled_error *err);
/* An MTL file with one material "tiled" whose map_Kd is texture_name. */
TILEDDEF tiled_result tiled_write_mtl(const char *texture_name, tiled_write_fn fn, void *ctx, tiled_error *err);
#ifndef PW_NO_STDIO
TILEDDEF tiled_result tiled_load_mesh(const char *path, const tiled_options *opt, tiled_mesh *out, tiled_error *err);
TILEDDEF tiled_result tiled_load_image(const char *path, const tiled_options *opt, tiled_image *out, tiled_error *err);
/* Format from the extension: .png .ppm .pgm .pnm .pam */
TILEDDEF tiled_result tiled_save_image(const char *path, const tiled_image *img, tiled_error *err);
/* Writes obj_path and, when texture_path is not NULL, an MTL beside it
 * (obj_path with .mtl) whose map_Kd names texture_path. */
TILEDDEF tiled_result tiled_save_obj(const char *obj_path, const tiled_mesh *m, const char *texture_path,
                                     tiled_error *err);
/* tiled_write_gltf into the file path (.glb). */
TILEDDEF tiled_result tiled_save_gltf(const char *path, const tiled_mesh *m, const tiled_image *texture,
                                      const tiled_render_options *view, tiled_error *err);
#endif

TILEDDEF void tiled_mesh_free(tiled_mesh *m);
TILEDDEF void tiled_image_free(tiled_image *img);

#ifdef __cplusplus
}
#endif

#endif /* TILED_H */
