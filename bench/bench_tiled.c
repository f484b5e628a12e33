/* bench_tiled: the tiled.h figures of the foundation issue. Half-edge
 * construction and Catmull-Clark throughput are in bench_mesh.
 *   - texture-coordinate assignment (AssignBoundaries + AssignTextureCoordinates)
 *     on a 1M-quad torus: target >= 50 M quads/s
 *   - tiled_map end to end on the same mesh (checks, half-edges, assignment)
 *   - tile-set synthesis: 16 tiles of 128 px from a 128 px exemplar: target < 1 s */
#include "bench.h"
#define PW_THREADS
#define TILED_IMPLEMENTATION
#include "../tiled.h"

typedef struct job {
    tiled__mapped m;
    tiled_mesh mesh, out;
    tiled_layout layout;
    tiled_options opt;
    tiled_image ex;
    tiled_tileset ts;
    float *coord;
    tiled__geom gm;
} job;

static void run_assign(void *arg)
{
    job *j = (job *)arg;
    tiled__assign_boundaries(&j->m.hm, &j->layout, j->opt.seed, j->m.types);
    tiled__assign_uvs(&j->m, &j->gm, 0, &j->opt, j->coord);
}

static void run_map(void *arg)
{
    job *j = (job *)arg;
    tiled_error err;
    if (tiled_map(&j->mesh, &j->layout, &j->opt, &j->out, &err)) printf("map failed: %s\n", err.message);
    tiled_mesh_free(&j->out);
}

static void run_synth(void *arg)
{
    job *j = (job *)arg;
    tiled_error err;
    if (tiled_synthesize(&j->ex, &j->opt, &j->ts, &err)) printf("synthesis failed: %s\n", err.message);
    tiled_tileset_free(&j->ts);
}

/* A synthesis kept for comparison (the previous one freed first). */
static void run_synth_keep(void *arg)
{
    job *j = (job *)arg;
    tiled_error err;
    tiled_tileset_free(&j->ts);
    if (tiled_synthesize(&j->ex, &j->opt, &j->ts, &err)) printf("synthesis failed: %s\n", err.message);
}

static int same_tiles(void *a, void *b)
{
    const tiled_image *x = &((job *)a)->ts.atlas, *y = &((job *)b)->ts.atlas;
    return x->pixels && y->pixels && x->width == y->width && x->height == y->height &&
           !memcmp(x->pixels, y->pixels, sizeof(float) * x->width * x->height * x->channels);
}

/* Synthesis on 1 and 2 threads (the tiles shared among them). */
static void synth_threads(const job *base)
{
    job j[2];
    int k;
    for (k = 0; k < 2; k++) {
        j[k] = *base;
        memset(&j[k].ts, 0, sizeof j[k].ts);
        j[k].opt.threads = k + 1;
    }
    bench_threads_row("tiled_synthesize on 2 threads, 16 tiles of 128 px (pebbles)", run_synth_keep, &j[0], &j[1], 5,
                      same_tiles);
    for (k = 0; k < 2; k++) tiled_tileset_free(&j[k].ts);
}

/* A row of the summary: no peer, and the thesis gives no timings. */
static void row(const char *task, bench_stat s)
{
    char fig[32], sp[96], t0[32], t1[32];
    snprintf(sp, sizeof sp, "%d runs; %s..%s", s.runs, bench_fmt_time(s.min, t0, sizeof t0),
             bench_fmt_time(s.max, t1, sizeof t1));
    bench_row(task, bench_fmt_time(s.median, fig, sizeof fig), "-", "no peer implements the method", NULL,
              "the thesis reports no timings (SGI O2, interactive)", sp, NULL);
}

/* An n x n quad torus as a tiled_mesh. */
static int bench_torus(const pw_alloc *a, int n, tiled_mesh *out, pw_err *e)
{
    pw_mesh m;
    if (pw_shape_torus(a, n, n, 1, &m, e)) return 1;
    tiled__take_mesh(&m, a, out);
    return 0;
}

/* tiled_map on tori of 250^2, 500^2 and 1000^2 quads: the growth exponent. */
static void map_growth(const job *base)
{
    static const int side[3] = {250, 500, 1000};
    double quads[3], secs[3];
    int i;
    for (i = 0; i < 3; i++) {
        job j = *base;
        pw_alloc a;
        pw_err e;
        memset(&a, 0, sizeof a);
        pw_err_clear(&e);
        if (bench_torus(&a, side[i], &j.mesh, &e)) return;
        secs[i] = bench_time(run_map, &j, 3).median;
        quads[i] = (double)side[i] * side[i];
        tiled_mesh_free(&j.mesh);
    }
    printf("tiled: tiled_map growth, %.0fK..%.0fK quads: time ~ quads^%.2f\n", quads[0] / 1e3, quads[2] / 1e3,
           bench_loglog_slope(quads, secs, 3));
    bench_growth("tiled_map", bench_loglog_slope(quads, secs, 3), "quads, tori of 62.5K, 250K, 1M quads", NULL);
}

int main(void)
{
    job j;
    pw_alloc a;
    pw_err e;
    tiled_options quads;
    bench_stat s;
    memset(&j, 0, sizeof j);
    memset(&a, 0, sizeof a);
    pw_err_clear(&e);
    j.opt = tiled_default_options();
    j.opt.threads = 1; /* one thread but where the threads are compared */
    j.layout = j.opt.layout;
    j.layout.tile_size = 64;
    quads = j.opt; /* the torus is all quads: no subdivision, no smoothing */
    quads.subdivide = 0;
    quads.smooth = 0;
    if (tiled__resolve(&j.layout, 0, &j.layout, &e) || bench_torus(&a, 1000, &j.mesh, &e) ||
        tiled__quadrangulate(&a, &j.mesh, &quads, NULL, &j.m, &e) ||
        tiled__mapped_arrays(&a, &j.m, j.m.q.fstart[j.m.q.nf], j.m.q.nf, &e)) {
        printf("setup failed: %s\n", e.msg);
        return 1;
    }
    j.gm = tiled__geometry(&j.layout);
    j.coord = (float *)malloc(sizeof(float) * 2 * j.gm.N);
    tiled__coord_table(&j.gm, j.coord);
    s = bench_time(run_assign, &j, 9);
    bench_report("tiled: assign boundaries + coords, 1M quads", s, j.m.q.nf, " quads");
    s = bench_time(run_map, &j, 5);
    bench_report("tiled: tiled_map end to end, 1M quads", s, j.m.q.nf, " quads");
    row("tiled_map end to end, 1M-quad torus (half-edges, boundaries, coordinates)", s);
    map_growth(&j);
    j.opt.layout.tile_size = 128;
    if (tiled_builtin_exemplar("pebbles", 128, &j.opt, &j.ex, NULL)) return 1;
    s = bench_time(run_synth, &j, 5);
    bench_report("tiled: synthesis, 16 tiles of 128 px (pebbles)", s, 0, "");
    row("tiled_synthesize, 16 tiles of 128 px from a 128 px exemplar (pebbles)", s);
    synth_threads(&j);
    tiled_image_free(&j.ex);
    if (tiled_builtin_exemplar("spots", 128, &j.opt, &j.ex, NULL)) return 1;
    s = bench_time(run_synth, &j, 5);
    bench_report("tiled: synthesis, 16 tiles of 128 px (spots)", s, 0, "");
    tiled_image_free(&j.ex);
    tiled__mapped_free(&a, &j.m);
    tiled_mesh_free(&j.mesh);
    free(j.coord);
    return 0;
}
