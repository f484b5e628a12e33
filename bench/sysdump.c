/* sysdump: the sparse systems that lapped.h, pgp.h and lst.h really build, dumped
 * from real runs on real meshes for bench_sparse, which solves them with
 * patchwork's own solvers and with Eigen's.
 *
 * PW_SOLVE_HOOK (sparse.h) shows every system a solver is given, with its
 * right-hand side, warm start and tolerance. Each generator below runs one
 * method on one mesh; of the systems seen in each stage of the run (the
 * stage named by the method's progress callback) the largest is kept (the
 * first of equal size), then written as Matrix Market files into DIR
 * (default build/bench-data/systems):
 *   NAME.mtx (matrix), NAME.b.mtx (right-hand side), NAME.x0.mtx (warm start),
 * and one line per system in DIR/index.txt:
 *   NAME kind method stage mesh n nnz tol max_iter
 * kind is the solver the header called: pcg (IC(0)-preconditioned CG on a
 * real SPD matrix), zpcg (the same on a complex Hermitian one), zamg (CG with
 * the multigrid preconditioner of zamg.h on a large one), lsq (CGLS on
 * a rectangular one), cg (Jacobi CG).
 *
 * Adding a method is one line in `generators`: a function that runs it on
 * a mesh. Nothing here is timed. */
#include "bench.h"

static void sysdump_hook(const char *kind, const void *A, const double *b, const double *x, const void *opts);
#define PW_SOLVE_HOOK(kind, A, b, x, opts) sysdump_hook(kind, (const void *)(A), b, x, (const void *)(opts))
#define LAPPED_IMPLEMENTATION
#include "../lapped.h"
#define PGP_IMPLEMENTATION
#include "../pgp.h"
#define LST_IMPLEMENTATION
#include "../lst.h"
#include "mm.h"

#define MAX_KEPT 64

/* One kept system. */
typedef struct kept {
    char method[16], stage[40], mesh[40];
    const char *kind;
    mm_csr A;
    double *b, *x0, tol;
    int max_iter;
} kept;

static struct {
    kept sys[MAX_KEPT];
    int n;
    const char *method, *mesh;
    char stage[40];
} G;

static int on_progress(void *user, float done, const char *stage)
{
    char *p;
    (void)user, (void)done;
    if (!strcmp(stage, "conjugate gradients")) return 0; /* a solver's own reports: the stage goes on */
    if (!strcmp(stage, "periodic global parameterization")) stage = "PGP";
    if (!strncmp(stage, "atlas", 5)) stage = "atlas"; /* charts, packing, baking */
    snprintf(G.stage, sizeof G.stage, "%s", stage);
    for (p = G.stage; *p; p++)
        if (*p == ' ') *p = '-';
    return 0;
}

static double *copy_doubles(const double *v, size_t n)
{
    double *c = (double *)malloc(sizeof(double) * (n + 1));
    if (c) memcpy(c, v, sizeof(double) * n);
    return c;
}

/* The slot of the current method/mesh/stage and this solver: an existing entry, or a new one. */
static kept *slot(const char *kind)
{
    int i;
    for (i = 0; i < G.n; i++)
        if (!strcmp(G.sys[i].method, G.method) && !strcmp(G.sys[i].mesh, G.mesh) &&
            !strcmp(G.sys[i].stage, G.stage) && !strcmp(G.sys[i].kind, kind))
            return &G.sys[i];
    if (G.n == MAX_KEPT) return NULL;
    memset(&G.sys[G.n], 0, sizeof G.sys[G.n]);
    snprintf(G.sys[G.n].method, sizeof G.sys[G.n].method, "%s", G.method);
    snprintf(G.sys[G.n].mesh, sizeof G.sys[G.n].mesh, "%s", G.mesh);
    snprintf(G.sys[G.n].stage, sizeof G.sys[G.n].stage, "%s", G.stage);
    G.sys[G.n].kind = kind;
    return &G.sys[G.n++];
}

/* Keeps a copy of the system if it is the largest of its slot so far. */
static void sysdump_hook(const char *kind, const void *A, const double *b, const double *x, const void *opts)
{
    const pw_cg_options *o = (const pw_cg_options *)opts;
    int cplx = !strcmp(kind, "zpcg") || !strcmp(kind, "zamg"), n, m, nnz, w;
    const int *rowptr, *col;
    const double *val;
    kept *s;
    if (!G.method || !(s = slot(kind))) return;
    if (cplx) {
        const pw_zcsr *Z = (const pw_zcsr *)A;
        n = m = Z->n, rowptr = Z->rowptr, col = Z->col, val = Z->val;
    } else {
        const pw_csr *R = (const pw_csr *)A;
        n = R->n, m = R->m, rowptr = R->rowptr, col = R->col, val = R->val;
    }
    if (s->A.rowptr && s->A.m >= m) return;
    nnz = rowptr[n];
    w = cplx ? 2 : 1;
    mm_csr_free(&s->A);
    free(s->b);
    free(s->x0);
    s->tol = o && o->tol > 0 ? o->tol : 1e-8; /* pw_cg_default_options */
    s->max_iter = o && o->max_iter > 0 ? o->max_iter : (10 * m > 1000 ? 10 * m : 1000); /* sparse.h */
    s->A.n = n, s->A.m = m, s->A.cplx = cplx;
    s->A.rowptr = (int *)malloc(sizeof(int) * ((size_t)n + 1));
    s->A.col = (int *)malloc(sizeof(int) * ((size_t)nnz + 1));
    if (s->A.rowptr) memcpy(s->A.rowptr, rowptr, sizeof(int) * ((size_t)n + 1));
    if (s->A.col) memcpy(s->A.col, col, sizeof(int) * (size_t)nnz);
    s->A.val = copy_doubles(val, (size_t)w * nnz);
    s->b = copy_doubles(b, (size_t)w * n);
    s->x0 = copy_doubles(x, (size_t)w * m);
    if (!s->A.rowptr || !s->A.col || !s->A.val || !s->b || !s->x0) { /* out of memory: forget the slot */
        mm_csr_free(&s->A);
        free(s->b), free(s->x0);
        s->b = s->x0 = NULL;
    }
}

/* ---- generators: one method on one mesh ------------------------------------- */

/* A mesh from data/meshes, refined `levels` times by 1-to-4 subdivision. */
static int load_mesh(const char *file, int levels, lapped_mesh *out)
{
    lapped_options opt = lapped_default_options();
    lapped_error err;
    bench_mesh base, rung[4];
    int i;
    if (lapped_load_mesh(file, &opt, out, &err)) return printf("sysdump: %s\n", err.message), 1;
    BENCH_MESH_COPY(base, *out);
    if (bench_ladder(&base, rung, levels + 1, 0)) return printf("sysdump: subdivision failed\n"), 1;
    for (i = 0; i < levels; i++) bench_mesh_free(&rung[i]);
    BENCH_MESH_COPY(*out, rung[levels]);
    return 0;
}

/* lapped_create as bench_lapped runs it (field UP, patch side 0.07 of the
 * bounding-box diagonal, GIMP's "cracked" pattern with a splotch). */
static int lapped_run(const lapped_mesh *mesh, int atlas)
{
    lapped_options opt = lapped_default_options();
    lapped_image texture, patch;
    lapped_source src;
    lapped_texture t;
    lapped_error err;
    int r;
    if (lapped_load_image("data/textures/cracked.ppm", &opt, &texture, &err) &&
        lapped_builtin_exemplar("scales", 128, &opt, &texture, &err))
        return printf("sysdump: %s\n", err.message), 1;
    opt.field = LAPPED_FIELD_UP;
    opt.scale = 0.07f * bench_bbox_diagonal(mesh->positions, mesh->nverts);
    opt.progress = on_progress;
    src.patches = &patch, src.npatches = 1, src.values = NULL;
    r = lapped_make_patch(&texture, NULL, &opt, &patch, &err) || lapped_create(mesh, &src, &opt, &t, &err);
    if (!r && atlas) {
        lapped_atlas at;
        snprintf(G.stage, sizeof G.stage, "atlas");
        if ((r = lapped_bake_atlas(mesh, &t, &src, &opt, &at, &err)) == LAPPED_OK) lapped_atlas_free(&at);
    }
    if (r) printf("sysdump: lapped: %s\n", err.message);
    else lapped_texture_free(&t);
    lapped_image_free(&texture);
    if (!r) lapped_image_free(&patch);
    return r;
}

static int gen_lapped(const lapped_mesh *mesh) { return lapped_run(mesh, 0); }

/* The same, then its texture atlas baked (§4: the charts' least squares). */
static int gen_lapped_atlas(const lapped_mesh *mesh) { return lapped_run(mesh, 1); }

/* pgp_create as bench_pgp runs it (field UP, tile side 0.05 of the diagonal). */
static int gen_pgp(const lapped_mesh *mesh)
{
    pgp_options opt = pgp_default_options();
    pgp_mesh m;
    pgp_map map;
    pgp_error err;
    memset(&m, 0, sizeof m);
    BENCH_MESH_COPY(m, *mesh);
    opt.scale = 0.05f * bench_bbox_diagonal(mesh->positions, mesh->nverts);
    opt.progress = on_progress;
    if (pgp_create(&m, &opt, &map, &err)) return printf("sysdump: pgp: %s\n", err.message), 1;
    pgp_map_free(&map);
    return 0;
}

/* lst_create as a user would run it on a closed scan: the surface
 * tetrahedralized by the built-in stuffing to `tets`, type 2-a (directions
 * smoothed from four constraints with the depth-aware weights, the depth
 * the distance to the surface, the clumps' texture coordinates by least
 * squares), a 32^3 "fibers" exemplar at a tenth of the diagonal. */
static int lst_run(const lapped_mesh *mesh, int tets)
{
    lst_options opt = lst_default_options();
    lst_mesh s;
    lst_tetmesh m;
    lst_volume ex;
    lst_source src;
    lst_model model;
    lst_error err;
    lst_constraint fc[4];
    float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
    int i, k, r;
    memset(&s, 0, sizeof s);
    BENCH_MESH_COPY(s, *mesh);
    for (i = 0; i < mesh->nverts; i++)
        for (k = 0; k < 3; k++) {
            float v = mesh->positions[3 * i + k];
            lo[k] = v < lo[k] ? v : lo[k], hi[k] = v > hi[k] ? v : hi[k];
        }
    for (i = 0; i < 4; i++) { /* along the box's x extent, the direction turning from x to z */
        float f = (i + 0.5f) / 4.0f, a = 1.5707963f * f;
        memset(&fc[i], 0, sizeof fc[i]);
        fc[i].kind = LST_CONSTRAINT_DIRECTION;
        for (k = 0; k < 3; k++) fc[i].point[k] = 0.5f * (lo[k] + hi[k]);
        fc[i].point[0] = lo[0] + f * (hi[0] - lo[0]);
        fc[i].direction[0] = cosf(a), fc[i].direction[2] = sinf(a);
    }
    opt.tet.target_tets = tets;
    if (lst_tetrahedralize(&s, &opt, &m, NULL, &err)) return printf("sysdump: lst: %s\n", err.message), 1;
    if (lst_builtin_exemplar("fibers", 32, &opt, &ex, NULL, &err)) {
        lst_tetmesh_free(&m);
        return printf("sysdump: lst: %s\n", err.message), 1;
    }
    opt.type = LST_TYPE_2A;
    opt.scale = 0.1f * bench_bbox_diagonal(mesh->positions, mesh->nverts);
    opt.constraints = fc, opt.nconstraints = 4;
    opt.progress = on_progress;
    src.exemplar = &ex, src.values = NULL;
    r = lst_create(&m, &s, &src, &opt, &model, &err);
    if (r) printf("sysdump: lst: %s\n", err.message);
    else lst_model_free(&model);
    lst_volume_free(&ex);
    lst_tetmesh_free(&m);
    return r;
}

static int gen_lst_20k(const lapped_mesh *mesh) { return lst_run(mesh, 20000); }
static int gen_lst_100k(const lapped_mesh *mesh) { return lst_run(mesh, 100000); }

typedef struct generator {
    const char *method, *file;
    int levels;            /* 1-to-4 subdivisions of the file's mesh */
    const char *mesh_name; /* how the mesh is named in the dump */
    const char *first;     /* the stage before the first progress report */
    int (*run)(const lapped_mesh *);
} generator;

/* mushroom (4,608 triangles) and its subdivisions are bench_lapped's and
 * bench_pgp's ladder (without its 295K rung, whose Eigen solves alone would
 * take a minute); armadillo (52K) is a raw scan near the size of the
 * pgp paper's 50K-triangle dragon; CGAL's elephant (closed) is filled by lst
 * at 20K and 100K tetrahedra, the fill sizes. */
static const generator generators[] = {
    {"lapped", "data/meshes/mushroom.off", 0, "mushroom-4.6K", "setup", gen_lapped_atlas},
    {"lapped", "data/meshes/mushroom.off", 2, "mushroom-74K", "setup", gen_lapped},
    {"lapped", "data/meshes/armadillo.off", 0, "armadillo-52K", "setup", gen_lapped},
    {"pgp", "data/meshes/mushroom.off", 0, "mushroom-4.6K", "orientation", gen_pgp},
    {"pgp", "data/meshes/mushroom.off", 1, "mushroom-18K", "orientation", gen_pgp},
    {"pgp", "data/meshes/mushroom.off", 2, "mushroom-74K", "orientation", gen_pgp},
    {"pgp", "data/meshes/armadillo.off", 0, "armadillo-52K", "orientation", gen_pgp},
    {"lst", "data/meshes/elephant.off", 0, "elephant-20Ktets", "fields", gen_lst_20k},
    {"lst", "data/meshes/elephant.off", 0, "elephant-100Ktets", "fields", gen_lst_100k},
};

static int write_all(const char *dir)
{
    char path[512], name[160], comment[256];
    FILE *idx;
    int i, bad = 0;
    snprintf(path, sizeof path, "%s/index.txt", dir);
    if (!(idx = fopen(path, "w"))) return printf("sysdump: cannot write %s\n", path), 1;
    for (i = 0; i < G.n; i++) {
        kept *s = &G.sys[i];
        if (!s->A.rowptr) continue;
        snprintf(name, sizeof name, "%s-%s-%s", s->method, s->stage, s->mesh);
        snprintf(comment, sizeof comment, "patchwork %s system of %s, stage \"%s\", mesh %s; tol %g", s->kind,
                 s->method, s->stage, s->mesh, s->tol);
        snprintf(path, sizeof path, "%s/%s.mtx", dir, name);
        bad |= mm_write_csr(path, comment, &s->A);
        snprintf(path, sizeof path, "%s/%s.b.mtx", dir, name);
        bad |= mm_write_vec(path, s->b, s->A.n, s->A.cplx);
        snprintf(path, sizeof path, "%s/%s.x0.mtx", dir, name);
        bad |= mm_write_vec(path, s->x0, s->A.m, s->A.cplx);
        fprintf(idx, "%s %s %s %s %s %d %d %g %d\n", name, s->kind, s->method, s->stage, s->mesh, s->A.m,
                s->A.rowptr[s->A.n], s->tol, s->max_iter);
        printf("  %-52s %-5s n %7d nnz %8d tol %g\n", name, s->kind, s->A.m, s->A.rowptr[s->A.n], s->tol);
    }
    bad |= fclose(idx) != 0;
    if (bad) printf("sysdump: writing into %s failed\n", dir);
    return bad;
}

int main(int argc, char **argv)
{
    const char *dir = argc > 1 ? argv[1] : "build/bench-data/systems";
    double t0 = bench_now();
    size_t i;
    int bad = 0;
    printf("sysdump: the largest system of each stage of each run, into %s\n", dir);
    for (i = 0; i < sizeof generators / sizeof generators[0]; i++) {
        const generator *g = &generators[i];
        lapped_mesh mesh;
        if (load_mesh(g->file, g->levels, &mesh)) { /* data/ absent: nothing to dump from */
            printf("sysdump: skipped %s on %s (run `make data` for the CGAL meshes)\n", g->method, g->file);
            continue;
        }
        G.method = g->method, G.mesh = g->mesh_name;
        snprintf(G.stage, sizeof G.stage, "%s", g->first);
        bad |= g->run(&mesh);
        G.method = NULL;
        lapped_mesh_free(&mesh);
    }
    bad |= write_all(dir);
    printf("sysdump: %d systems in %.1f s\n", G.n, bench_now() - t0);
    for (i = 0; i < (size_t)G.n; i++) {
        mm_csr_free(&G.sys[i].A);
        free(G.sys[i].b);
        free(G.sys[i].x0);
    }
    return bad;
}
