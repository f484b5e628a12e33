/* bench_threads: the work issue 21 spreads on threads that the other
 * benchmarks time on one, each on 1 and on 2 threads (wall time, rounds
 * interleaved after a warm-up, bench_threads_row), the results compared
 * bit for bit:
 *   1. lapped_create on the bunny (75K triangles, data/meshes/bunny00.off;
 *      the built-in "bumpy" without data), the built-in "scales" patch at
 *      256 px, defaults: the coverage (each paste painted in shares of its
 *      triangles, the pruning in shares of the mesh) runs on threads, the
 *      growth and the solves on one.
 *   2. lst_create of the built-in kiwi (type 2-b, painted depth, 64^3) in
 *      a uniform lattice of about 5K tetrahedra (bench_lst's): the coverage
 *      of each clump runs on threads.
 *   3. lst_render_volume of that kiwi, 200 slices at 640x480 (the frame's
 *      bands on threads).
 *   4. pgp_create on the bunny (75K triangles) and its 1-to-4 subdivision
 *      (300K), tile side a tenth of the diagonal: the PGP's s and t
 *      systems solved side by side, one on each thread; the field's
 *      multigrid sweeps, residuals and transfers, products of CG and
 *      Galerkin products, and the Eq. (4) recovery on threads; the mesh
 *      set-up, the assembly and the field's aggregation on one.
 * Built with PW_THREADS (POSIX threads; each create call keeps one crew of
 * threads for all its parallel-fors). The whole create is timed, so its
 * speed-up is bounded by the parts still on one thread; the coverage stage
 * alone is timed too (stage_row): its parallel-fors go through a timing
 * parallel-for that runs them on 1 or 2 threads. */
#include "bench.h"
#define PW_THREADS
#define PATCHWORK_IMPLEMENTATION
#include "../lapped.h"
#include "../lst.h"
#include "../pgp.h"

/* ---- the coverage stage alone ---- */

/* A create call's parallel-fors through stage_for, which runs each on
 * `inner` (1 thread, or a crew of 2 as the create's own) and adds up their
 * wall time. The create's threads are 2 for both, so its shares are the
 * same and only where they run differs. runs[]: the sum of each call. */
typedef struct stage {
    pw_parallel inner;
    double sum, runs[16];
    int nruns;
} stage;

static void stage_for(void *pool, int n, pw_task_fn task, void *ctx)
{
    stage *s = (stage *)pool;
    double t0 = bench_now();
    pw_parallel_for(&s->inner, n, task, ctx);
    s->sum += bench_now() - t0;
}

static void stage_init(stage *s, int threads)
{
    memset(s, 0, sizeof *s);
    s->inner = pw_parallel_make(threads, NULL, NULL);
    pw_parallel_start(&s->inner);
}

static int stage_cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* Runs fn on one (stage st[0], 1 thread) and two (st[1], 2 threads) `rounds`
 * times interleaved after a warm-up each; prints the stage's medians. */
static void stage_row(const char *task, void (*fn)(void *), void *one, void *two, stage *st, int rounds)
{
    char fa[32], fb[32], ratio[32], sp[160];
    double med[2];
    int r, k;
    for (r = 0; r <= rounds; r++) {
        for (k = 0; k < 2; k++) {
            st[k].sum = 0.0;
            fn(k ? two : one);
            if (r > 0) st[k].runs[st[k].nruns++] = st[k].sum;
        }
    }
    for (k = 0; k < 2; k++) {
        qsort(st[k].runs, (size_t)st[k].nruns, sizeof(double), stage_cmp);
        med[k] = st[k].runs[st[k].nruns / 2];
        pw_parallel_stop(&st[k].inner);
    }
    printf("threads: %s: 1 thread %s, 2 threads %s, speed-up %.2fx (medians of %d rounds)\n", task,
           bench_fmt_time(med[0], fa, sizeof fa), bench_fmt_time(med[1], fb, sizeof fb), med[0] / med[1], rounds);
    snprintf(ratio, sizeof ratio, "%.2f", med[1] / med[0]);
    snprintf(sp, sizeof sp, "%d rounds, wall time of the stage's parallel-fors; speed-up %.2fx", rounds,
             med[0] / med[1]);
    bench_row(task, fb, fa, "the same on 1 thread", ratio, NULL, sp, NULL);
}

/* ---- lapped_create ---- */

typedef struct lapped_job {
    const lapped_mesh *mesh;
    lapped_source src;
    lapped_options opt;
    lapped_texture t; /* the last result, kept for the comparison */
} lapped_job;

static void lapped_run(void *arg)
{
    lapped_job *j = (lapped_job *)arg;
    lapped_error err;
    lapped_texture_free(&j->t);
    if (lapped_create(j->mesh, &j->src, &j->opt, &j->t, &err)) printf("lapped_create failed: %s\n", err.message);
}

static int lapped_same(void *a, void *b)
{
    const lapped_texture *x = &((lapped_job *)a)->t, *y = &((lapped_job *)b)->t;
    int p;
    if (!x->pastes || x->npastes != y->npastes || x->layers != y->layers) return 0;
    for (p = 0; p < x->npastes; p++)
        if (x->pastes[p].nfaces != y->pastes[p].nfaces ||
            memcmp(x->pastes[p].faces, y->pastes[p].faces, sizeof(int) * (size_t)x->pastes[p].nfaces) ||
            memcmp(x->pastes[p].uvs, y->pastes[p].uvs, sizeof(float) * 6 * (size_t)x->pastes[p].nfaces))
            return 0;
    return 1;
}

static void lapped_threads(void)
{
    lapped_options opt = lapped_default_options();
    lapped_mesh mesh;
    lapped_image ex, patch;
    lapped_error err;
    lapped_job j[2];
    stage st[2];
    char task[160];
    int k, builtin = 0;
    if (lapped_load_mesh("data/meshes/bunny00.off", &opt, &mesh, &err)) {
        builtin = 1;
        if (lapped_builtin_mesh("bumpy", &opt, &mesh, &err)) {
            printf("no mesh: %s\n", err.message);
            return;
        }
    }
    if (lapped_builtin_exemplar("scales", 256, &opt, &ex, &err) || lapped_make_patch(&ex, NULL, &opt, &patch, &err)) {
        printf("no patch: %s\n", err.message);
        return;
    }
    for (k = 0; k < 2; k++) {
        memset(&j[k], 0, sizeof j[k]);
        j[k].mesh = &mesh;
        j[k].src.patches = &patch;
        j[k].src.npatches = 1;
        j[k].opt = opt;
        j[k].opt.threads = k + 1;
    }
    snprintf(task, sizeof task, "lapped_create on 2 threads (coverage), %s (%d triangles), scales 256 px",
             builtin ? "built-in bumpy" : "bunny00", mesh.nfaces);
    bench_threads_row(task, lapped_run, &j[0], &j[1], 5, lapped_same);
    printf("  %d pastes\n", j[0].t.npastes);
    for (k = 0; k < 2; k++) {
        stage_init(&st[k], k + 1);
        j[k].opt.threads = 2;
        j[k].opt.parallel = stage_for;
        j[k].opt.parallel_pool = &st[k];
    }
    snprintf(task, sizeof task, "lapped_create's coverage stage on 2 threads, %s, scales 256 px",
             builtin ? "built-in bumpy" : "bunny00");
    stage_row(task, lapped_run, &j[0], &j[1], st, 5);
    for (k = 0; k < 2; k++) lapped_texture_free(&j[k].t);
    lapped_image_free(&patch);
    lapped_image_free(&ex);
    lapped_mesh_free(&mesh);
}

/* ---- lst_create and lst_render_volume ---- */

typedef struct lst_job {
    const lst_tetmesh *tets;
    const lst_mesh *surface;
    lst_source src;
    lst_options opt;
    lst_model model; /* the last fill, kept */
    lst_image img;   /* the last volume rendering, kept */
    const lst_model *show;
} lst_job;

static void lst_run(void *arg)
{
    lst_job *j = (lst_job *)arg;
    lst_error err;
    lst_model_free(&j->model);
    if (lst_create(j->tets, j->surface, &j->src, &j->opt, &j->model, &err))
        printf("lst_create failed: %s\n", err.message);
}

static int lst_same(void *a, void *b)
{
    const lst_model *x = &((lst_job *)a)->model, *y = &((lst_job *)b)->model;
    int p;
    if (!x->pastes || x->npastes != y->npastes || x->layers != y->layers) return 0;
    for (p = 0; p < x->npastes; p++)
        if (x->pastes[p].ntets != y->pastes[p].ntets || x->pastes[p].nverts != y->pastes[p].nverts ||
            memcmp(x->pastes[p].tets, y->pastes[p].tets, sizeof(int) * (size_t)x->pastes[p].ntets) ||
            memcmp(x->pastes[p].uvw, y->pastes[p].uvw, sizeof(float) * 3 * (size_t)x->pastes[p].nverts))
            return 0;
    return 1;
}

static void volume_run(void *arg)
{
    lst_job *j = (lst_job *)arg;
    lst_error err;
    lst_image_free(&j->img);
    if (lst_render_volume(j->show, &j->opt.render, &j->opt.volume, &j->img, &err))
        printf("lst_render_volume failed: %s\n", err.message);
}

static int volume_same(void *a, void *b)
{
    const lst_image *x = &((lst_job *)a)->img, *y = &((lst_job *)b)->img;
    return x->pixels && y->pixels && x->width == y->width && x->height == y->height &&
           !memcmp(x->pixels, y->pixels, sizeof(float) * (size_t)x->width * (size_t)x->height * (size_t)x->channels);
}

static void lst_threads(void)
{
    lst_options o = lst_default_options();
    lst_mesh s;
    lst_tetmesh m;
    lst_volume ex, val;
    lst_constraints c;
    lst_error err;
    lst_job j[2];
    stage st[2];
    char task[160];
    int k;
    o.tet.target_tets = 5000, o.tet.uniform = 1; /* bench_lst's kiwi */
    if (lst_builtin_mesh("kiwi", &o, &s, &err) || lst_tetrahedralize(&s, &o, &m, NULL, &err)) {
        printf("no kiwi: %s\n", err.message);
        return;
    }
    o.type = LST_TYPE_2B;
    if (lst_builtin_constraints("kiwi", &s, &o, &c, &err) || lst_builtin_exemplar("kiwi", 64, &o, &ex, &val, &err)) {
        printf("no kiwi: %s\n", err.message);
        return;
    }
    o.constraints = c.items, o.nconstraints = c.count;
    o.render.width = 640, o.render.height = 480, o.render.supersample = 1;
    o.volume.slices = 200;
    for (k = 0; k < 2; k++) {
        memset(&j[k], 0, sizeof j[k]);
        j[k].tets = &m;
        j[k].surface = &s;
        j[k].src.exemplar = &ex;
        j[k].src.values = &val;
        j[k].opt = o;
        j[k].opt.threads = j[k].opt.render.threads = k + 1;
    }
    snprintf(task, sizeof task, "lst_create on 2 threads (coverage), kiwi 2-b, %d tetrahedra", m.ntets);
    bench_threads_row(task, lst_run, &j[0], &j[1], 5, lst_same);
    printf("  %d pastes\n", j[0].model.npastes);
    for (k = 0; k < 2; k++) {
        stage_init(&st[k], k + 1);
        j[k].opt.threads = 2;
        j[k].opt.parallel = stage_for;
        j[k].opt.parallel_pool = &st[k];
    }
    snprintf(task, sizeof task, "lst_create's coverage stage on 2 threads, kiwi 2-b, %d tetrahedra", m.ntets);
    stage_row(task, lst_run, &j[0], &j[1], st, 5);
    for (k = 0; k < 2; k++) {
        j[k].opt.threads = k + 1;
        j[k].opt.parallel = NULL;
    }
    for (k = 0; k < 2; k++) j[k].show = &j[0].model;
    snprintf(task, sizeof task, "lst_render_volume on 2 threads, 200 slices, 640x480, kiwi %d tetrahedra", m.ntets);
    bench_threads_row(task, volume_run, &j[0], &j[1], 3, volume_same);
    for (k = 0; k < 2; k++) {
        lst_model_free(&j[k].model);
        lst_image_free(&j[k].img);
    }
    lst_constraints_free(&c);
    lst_volume_free(&ex), lst_volume_free(&val), lst_tetmesh_free(&m), lst_mesh_free(&s);
}

/* ---- pgp_create ---- */

typedef struct pgp_job {
    const pgp_mesh *mesh;
    pgp_options opt;
    float *coords; /* the last map's, kept */
    int vortices;
} pgp_job;

static void pgp_run(void *arg)
{
    pgp_job *j = (pgp_job *)arg;
    pgp_map map;
    pgp_error err;
    if (pgp_create(j->mesh, &j->opt, &map, &err)) {
        printf("pgp_create failed: %s\n", err.message);
        return;
    }
    free(j->coords);
    j->coords = (float *)malloc(sizeof(float) * 9 * (size_t)map.ntris);
    if (j->coords) memcpy(j->coords, map.coords, sizeof(float) * 9 * (size_t)map.ntris);
    j->vortices = pgp_map_vortices(&map, NULL);
    pgp_map_free(&map);
}

static int pgp_same(void *a, void *b)
{
    const pgp_job *x = (const pgp_job *)a, *y = (const pgp_job *)b;
    return x->coords && y->coords && !memcmp(x->coords, y->coords, sizeof(float) * 9 * (size_t)x->mesh->nfaces);
}

static void pgp_threads(void)
{
    pgp_options opt = pgp_default_options();
    pgp_mesh mesh, m;
    pgp_error err;
    bench_mesh rung[2];
    pgp_job j[2];
    char task[160];
    int i, k, builtin = 0;
    if (pgp_load_mesh("data/meshes/bunny00.off", &opt, &mesh, &err)) {
        builtin = 1;
        if (pgp_builtin_mesh("bumpy", &opt, &mesh, &err)) {
            printf("no mesh: %s\n", err.message);
            return;
        }
    }
    BENCH_MESH_COPY(rung[0], mesh);
    if (bench_ladder(&rung[0], rung, 2, 70000)) {
        printf("subdivision failed\n");
        return;
    }
    for (i = 0; i < 2; i++) {
        memset(&m, 0, sizeof m);
        BENCH_MESH_COPY(m, rung[i]);
        for (k = 0; k < 2; k++) {
            memset(&j[k], 0, sizeof j[k]);
            j[k].mesh = &m;
            j[k].opt = opt;
            j[k].opt.scale = 0.1f * bench_bbox_diagonal(rung[i].positions, rung[i].nverts);
            j[k].opt.threads = k + 1;
        }
        snprintf(task, sizeof task, "pgp_create on 2 threads (solves), %s (%d triangles)",
                 builtin ? "built-in bumpy" : "bunny00", m.nfaces);
        bench_threads_row(task, pgp_run, &j[0], &j[1], 5, pgp_same);
        printf("  %d vortices\n", j[0].vortices);
        for (k = 0; k < 2; k++) free(j[k].coords);
    }
    bench_mesh_free(&rung[0]);
    bench_mesh_free(&rung[1]);
}

/* With arguments, only the named parts (lapped, lst, pgp). */
static int wanted(int argc, char **argv, const char *name)
{
    int k;
    for (k = 1; k < argc; k++)
        if (!strcmp(argv[k], name)) return 1;
    return argc < 2;
}

int main(int argc, char **argv)
{
    if (wanted(argc, argv, "lapped")) lapped_threads();
    if (wanted(argc, argv, "lst")) lst_threads();
    if (wanted(argc, argv, "pgp")) pgp_threads();
    return 0;
}
