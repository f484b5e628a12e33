/* bench_million: pgp_create and lapped_create on a ladder up to a
 * million-triangle scan (issue 21): CGAL's bunny00 (75K triangles, a range
 * scan) and its 1-to-4 midpoint subdivisions, 300K and 1.2M triangles (the
 * built-in bumpy mesh subdivided to the same sizes without `make data`).
 * Each run is a child process (fork), so that its CPU time and its peak
 * resident memory (getrusage of the child) are its own; one run per rung,
 * the default options, tile side / paste scale a tenth of the diagonal.
 * lapped_create's paste count is set by the scale, so at 1.2M each paste
 * holds 16 times the triangles of 75K (docs/performance.md).
 * The peak counts what the child inherits (the ladder's meshes, printed as
 * the parent's resident set). Prints the growth exponent of each over the
 * ladder. `bench_million pgp` (or `lapped`) runs that method alone. */
#define _DEFAULT_SOURCE /* wait4 */
#include "bench.h"
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#define PGP_IMPLEMENTATION
#include "../pgp.h"
#define LAPPED_IMPLEMENTATION
#include "../lapped.h"

#define NRUNGS 3
#define MESH_FILE "data/meshes/bunny00.off"

/* What a child reports: CPU seconds of the call, 0 on success. */
typedef struct outcome {
    double cpu;
    int fail;
} outcome;

static outcome run_pgp(const bench_mesh *bm)
{
    pgp_options opt = pgp_default_options();
    pgp_mesh m;
    pgp_map map;
    pgp_error err;
    outcome o;
    double c0;
    memset(&m, 0, sizeof m);
    BENCH_MESH_COPY(m, *bm);
    opt.scale = 0.1f * bench_bbox_diagonal(bm->positions, bm->nverts);
    c0 = bench_cpu_now();
    o.fail = pgp_create(&m, &opt, &map, &err) != PGP_OK;
    o.cpu = bench_cpu_now() - c0;
    if (o.fail) fprintf(stderr, "pgp_create: %s\n", err.message);
    return o;
}

static outcome run_lapped(const bench_mesh *bm)
{
    lapped_options opt = lapped_default_options();
    lapped_mesh m;
    lapped_image tex, patch;
    lapped_source src;
    lapped_texture t;
    lapped_error err;
    outcome o;
    double c0;
    memset(&m, 0, sizeof m);
    BENCH_MESH_COPY(m, *bm);
    o.cpu = 0.0;
    o.fail = lapped_builtin_exemplar("scales", 128, &opt, &tex, &err) != LAPPED_OK ||
             lapped_make_patch(&tex, NULL, &opt, &patch, &err) != LAPPED_OK;
    if (o.fail) return o;
    opt.scale = 0.1f * bench_bbox_diagonal(bm->positions, bm->nverts);
    src.patches = &patch;
    src.npatches = 1;
    src.values = NULL;
    c0 = bench_cpu_now();
    o.fail = lapped_create(&m, &src, &opt, &t, &err) != LAPPED_OK;
    o.cpu = bench_cpu_now() - c0;
    if (o.fail) fprintf(stderr, "lapped_create: %s\n", err.message);
    return o;
}

/* Runs fn on bm in a child: its outcome and its peak resident set (MB). */
static outcome in_child(outcome (*fn)(const bench_mesh *), const bench_mesh *bm, double *peak_mb)
{
    outcome o;
    struct rusage ru;
    int fd[2], status;
    pid_t pid;
    o.fail = 1;
    o.cpu = 0.0;
    *peak_mb = 0.0;
    if (pipe(fd)) return o;
    fflush(stdout);
    if ((pid = fork()) == 0) {
        outcome c = fn(bm);
        ssize_t w = write(fd[1], &c, sizeof c);
        _exit(w == (ssize_t)sizeof c ? 0 : 1);
    }
    close(fd[1]);
    if (pid > 0 && read(fd[0], &o, sizeof o) != (ssize_t)sizeof o) o.fail = 1;
    close(fd[0]);
    if (pid > 0 && wait4(pid, &status, 0, &ru) == pid) *peak_mb = ru.ru_maxrss / 1024.0;
    return o;
}

int main(int argc, char **argv)
{
    static const char *const names[2] = {"pgp_create", "lapped_create"};
    outcome (*const fns[2])(const bench_mesh *) = {run_pgp, run_lapped};
    pgp_options opt = pgp_default_options();
    pgp_mesh mesh;
    pgp_error err;
    bench_mesh base, rung[NRUNGS];
    double faces[NRUNGS], cpu[2][NRUNGS], mb[2][NRUNGS];
    int builtin = 0, i, k, k0 = 0, k1 = 2;
    if (argc > 1) { /* one method by name */
        for (k0 = 0; k0 < 2 && strncmp(names[k0], argv[1], strlen(argv[1])) != 0; k0++) continue;
        if (k0 == 2) return printf("usage: bench_million [pgp | lapped]\n"), 1;
        k1 = k0 + 1;
    }
    if (pgp_load_mesh(MESH_FILE, &opt, &mesh, &err)) {
        builtin = 1;
        if (pgp_builtin_mesh("bumpy", &opt, &mesh, &err)) return printf("no mesh: %s\n", err.message), 1;
    }
    BENCH_MESH_COPY(base, mesh);
    if (bench_ladder(&base, rung, NRUNGS, 70000)) return printf("subdivision failed\n"), 1;
    printf("mesh: %s, 1-to-4 midpoint subdivision per rung%s; one run per rung in a child process\n",
           builtin ? "built-in \"bumpy\"" : MESH_FILE " (CGAL's bunny scan)",
           builtin ? " [data/ absent: run `make data` for the scan]" : "");
    {
        struct rusage self;
        getrusage(RUSAGE_SELF, &self);
        printf("the ladder's meshes: peak RSS %.0f MB in this process\n", self.ru_maxrss / 1024.0);
    }
    printf("%-14s %10s %10s %12s\n", "", "triangles", "cpu s", "peak RSS MB");
    for (i = 0; i < NRUNGS; i++) {
        faces[i] = rung[i].nfaces;
        for (k = k0; k < k1; k++) {
            outcome o = in_child(fns[k], &rung[i], &mb[k][i]);
            if (o.fail) return printf("%s failed on %d triangles\n", names[k], rung[i].nfaces), 1;
            cpu[k][i] = o.cpu;
            printf("%-14s %10d %10.2f %12.0f\n", names[k], rung[i].nfaces, o.cpu, mb[k][i]);
        }
    }
    for (k = k0; k < k1; k++) {
        char task[96], fig[64], over[96], note[96];
        int top = NRUNGS - 1;
        double b = bench_loglog_slope(faces, cpu[k], top + 1);
        printf("%s: cpu time ~ triangles^%.2f over %.0fK..%.0fK\n", names[k], b, faces[0] / 1e3, faces[top] / 1e3);
        snprintf(task, sizeof task, "%s, %s %.2fM triangles (one core)", names[k], builtin ? "bumpy" : "bunny00",
                 faces[top] / 1e6);
        snprintf(fig, sizeof fig, "cpu %.1f s, peak %.0f MB", cpu[k][top], mb[k][top]);
        snprintf(note, sizeof note, "75K: %.2f s, %.0f MB; 300K: %.2f s, %.0f MB", cpu[k][0], mb[k][0], cpu[k][1],
                 mb[k][1]);
        bench_row(task, fig, "-", "no peer implements the method", NULL, NULL, "1 run per rung", note);
        snprintf(over, sizeof over, "triangles, %s ladder %.0fK..%.2fM", builtin ? "bumpy" : "bunny00",
                 faces[0] / 1e3, faces[top] / 1e6);
        bench_growth(names[k], b, over, NULL);
    }
    pgp_mesh_free(&mesh);
    return 0;
}
