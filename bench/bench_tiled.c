/* bench_tiled: the tiled.h figures of the foundation issue. Half-edge
 * construction and Catmull-Clark throughput are in bench_mesh.
 *   - texture-coordinate assignment (AssignBoundaries + AssignTextureCoordinates)
 *     on a 1M-quad torus: target >= 50 M quads/s
 *   - tiled_map end to end on the same mesh (checks, half-edges, assignment)
 *   - tile-set synthesis: 16 tiles of 128 px from a 128 px exemplar: target < 1 s */
#include "bench.h"
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
    tiled__assign_uvs(&j->m.q, j->m.types, &j->gm, 0, &j->opt, j->coord, j->m.uv, j->m.tiles);
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

int main(void)
{
    job j;
    pw_alloc a;
    pw_err e;
    bench_stat s;
    memset(&j, 0, sizeof j);
    memset(&a, 0, sizeof a);
    pw_err_clear(&e);
    j.opt = tiled_default_options();
    j.layout = j.opt.layout;
    j.layout.tile_size = 64;
    if (tiled__resolve(&j.layout, 0, &j.layout, &e) || tiled__torus(&a, 1000, 1000, &j.mesh, &e) ||
        tiled__quadrangulate(&a, &j.mesh, 0, 0, NULL, &j.m.q, &j.m.hm, &e) ||
        tiled__mapped_arrays(&a, j.m.q.fstart[j.m.q.nf], j.m.q.nf, &j.m.uv, &j.m.types, &j.m.tiles, &e)) {
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
    j.opt.layout.tile_size = 128;
    if (tiled_builtin_exemplar("pebbles", 128, &j.opt, &j.ex, NULL)) return 1;
    s = bench_time(run_synth, &j, 5);
    bench_report("tiled: synthesis, 16 tiles of 128 px (pebbles)", s, 0, "");
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
