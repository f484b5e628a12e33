/* bench_pgp: pgp.h's mapping (Ray, Lévy, Wang, Turk, Vallet 2009, §2-§3)
 * on one core.
 *   1. pgp_create over a ladder of about 5K, 20K, 75K and 300K triangles
 *      (CGAL's mushroom, 4,608 triangles, refined by 1-to-4 midpoint
 *      subdivision), the tile side a fixed fraction of the bounding-box
 *      diagonal, split into its stages through the progress callback:
 *      field (triangle mesh, connection, default field smoothed over the
 *      mesh), PGP (the two periodic solves and the per-corner recovery of
 *      Eq. 4) and the §3 singularity detection; the exponent of time
 *      against triangles.
 *   2. local updates (§2.1): an orientation, a scale and a material
 *      constraint whose effect area holds about 25% of the mesh, and an
 *      orientation constraint over about 10K triangles.
 *   3. the paper's Table 1 at its size: CGAL's armadillo (52,000
 *      triangles, a raw scan) against the 50K-triangle "Dragon 2": the
 *      field stage against "Interpolate orientation", PGP against
 *      "Initialize (u,v)", and the three 25%-area constraints.
 *   4. issue 17: pgp_create with the paper's area weights, the default
 *      cotangent weights and --field smooth on CGAL's elephant, cow, knot
 *      and mushroom at S = diag/10 (vortices, singular share, time), and
 *      the cost of a frame with the clean fix against §3's rendering.
 *   `bench_pgp issue17` runs section 4 alone.
 *   Targets: the whole initialisation of the ~75K rung under 1 s; a local
 *   update touching 10K triangles under 0.2 s.
 * Without `make data` it falls back to the built-in "bumpy" mesh. */
#include "bench.h"
#define PGP_IMPLEMENTATION
#include "../pgp.h"

#define MESH_FILE "data/meshes/mushroom.off"
#define SCALE_FRACTION 0.05f
#define NRUNGS 4
#define TARGET_RUNG 2
#define NSTAGES 3

/* Stage boundaries, timed by the progress callback: pgp_create reports
 * "periodic global parameterization" when the fields are done and
 * "singularities" when the coordinates are. */
typedef struct stage_clock {
    double t0, mark[NSTAGES];
} stage_clock;

static int on_progress(void *user, float done, const char *stage)
{
    stage_clock *c = (stage_clock *)user;
    (void)done;
    if (!strcmp(stage, "periodic global parameterization")) c->mark[0] = bench_now();
    if (!strcmp(stage, "singularities")) c->mark[1] = bench_now();
    return 0;
}

typedef struct create_job {
    const pgp_mesh *mesh;
    pgp_options opt;
    stage_clock clock;
    double stage[NSTAGES][64];
    int n, fail, nsing;
} create_job;

static void run_create(void *arg)
{
    create_job *j = (create_job *)arg;
    pgp_map map;
    pgp_error err;
    j->opt.progress = on_progress;
    j->opt.progress_user = &j->clock;
    j->clock.t0 = bench_now();
    if (pgp_create(j->mesh, &j->opt, &map, &err)) {
        printf("pgp_create failed: %s\n", err.message);
        j->fail = 1;
        return;
    }
    j->clock.mark[2] = bench_now();
    if (j->n < 64) {
        j->stage[0][j->n] = j->clock.mark[0] - j->clock.t0;
        j->stage[1][j->n] = j->clock.mark[1] - j->clock.mark[0];
        j->stage[2][j->n] = j->clock.mark[2] - j->clock.mark[1];
        j->n++;
    }
    j->nsing = pgp_map_singular(&map, NULL);
    pgp_map_free(&map);
}

/* Total surface area, for the radius of an effect area of a given size. */
static double surface_area(const pgp_mesh *m)
{
    double a = 0.0;
    int f;
    for (f = 0; f < m->nfaces; f++) {
        const float *p = m->positions + 3 * m->face_verts[3 * f], *q = m->positions + 3 * m->face_verts[3 * f + 1];
        const float *r = m->positions + 3 * m->face_verts[3 * f + 2];
        double u[3], v[3], c[3];
        int k;
        for (k = 0; k < 3; k++) u[k] = q[k] - p[k], v[k] = r[k] - p[k];
        c[0] = u[1] * v[2] - u[2] * v[1], c[1] = u[2] * v[0] - u[0] * v[2], c[2] = u[0] * v[1] - u[1] * v[0];
        a += 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    }
    return a;
}

typedef struct edit_job {
    pgp_map *map;
    int kind; /* 0 orientation, 1 scale, 2 material */
    int face, vertex, id, area, fail;
    float radius;
} edit_job;

/* One local update: the constraint is added the first time, then its
 * value edited back and forth (each edit recomputes the same area). */
static void run_edit(void *arg)
{
    edit_job *j = (edit_job *)arg;
    static int flip;
    pgp_area area;
    pgp_error err;
    pgp_constraint c;
    float dir[3] = {1.0f, 0.0f, 0.0f}, value[3] = {0.0f, 0.0f, 0.0f};
    int r;
    flip = !flip;
    if (j->kind == 0) dir[2] = flip ? 1.0f : -1.0f;
    value[0] = j->kind == 0 ? dir[0] : j->kind == 1 ? (flip ? 0.6f : 0.4f) : (flip ? 1.0f : 0.5f);
    value[1] = dir[1], value[2] = dir[2];
    if (j->id < 0) {
        c.kind = j->kind == 0 ? PGP_CONSTRAINT_ORIENT : j->kind == 1 ? PGP_CONSTRAINT_SCALE : PGP_CONSTRAINT_MATERIAL;
        c.element = j->kind == 0 ? j->face : j->vertex;
        memcpy(c.value, value, sizeof c.value);
        c.radius = j->radius;
        r = pgp_add_constraint(j->map, &c, &j->id, &area, &err);
    } else
        r = pgp_edit_constraint(j->map, j->id, value, &area, &err);
    if (r) {
        printf("local update failed: %s\n", err.message);
        j->fail = 1;
        return;
    }
    j->area = area.nfaces;
    pgp_area_free(&area);
}

/* Medians of the per-stage times recorded by run_create. */
static void stage_medians(create_job *j, double out[NSTAGES])
{
    int k;
    for (k = 0; k < NSTAGES; k++) out[k] = bench_stats(j->stage[k], j->n).median;
}

static int edit_bench(pgp_map *map, const pgp_mesh *mesh, const pgp_options *opt, double fraction, int kind,
                      const char *what, double *median, const char *paper)
{
    static const char *const kinds[3] = {"orientation", "scale", "material"};
    edit_job ej;
    bench_stat s;
    double area = surface_area(mesh);
    memset(&ej, 0, sizeof ej);
    ej.map = map;
    ej.kind = kind;
    ej.id = -1;
    ej.face = mesh->nfaces / 2;
    ej.vertex = mesh->face_verts[3 * ej.face];
    ej.radius = (float)sqrt(fraction * area / 3.14159265358979);
    (void)opt;
    { /* geodesic discs over the dual graph hold less than pi r^2: one
         correction from a trial edit brings the area near the target */
        pgp_constraint c = {PGP_CONSTRAINT_ORIENT, 0, {1.0f, 0.0f, 0.0f}, 0.0f};
        pgp_area trial;
        pgp_error err;
        int id;
        c.element = ej.face, c.radius = ej.radius;
        if (pgp_add_constraint(map, &c, &id, &trial, &err) ||
            pgp_remove_constraint(map, id, NULL, &err))
            return printf("trial edit failed: %s\n", err.message), 1;
        if (trial.nfaces > 0) ej.radius *= (float)sqrt(fraction * mesh->nfaces / trial.nfaces);
        pgp_area_free(&trial);
    }
    s = bench_time_cpu(run_edit, &ej, 5, 1, NULL);
    if (ej.fail) return 1;
    printf("  %-11s %-10s radius %.4g: %6d triangles (%4.1f%%)  median %8.1f ms (%.1f..%.1f, %d runs)\n",
           kinds[kind], what, (double)ej.radius, ej.area, 100.0 * ej.area / mesh->nfaces, s.median * 1e3,
           s.min * 1e3, s.max * 1e3, s.runs);
    *median = s.median;
    if (paper) { /* a row of the summary */
        char task[160], fig[32], sp[96], t0[32], t1[32];
        snprintf(task, sizeof task, "pgp %s constraint, %s of %d triangles (%d edited)", kinds[kind], what, mesh->nfaces,
                 ej.area);
        snprintf(sp, sizeof sp, "%d runs; %s..%s", s.runs, bench_fmt_time(s.min, t0, sizeof t0),
                 bench_fmt_time(s.max, t1, sizeof t1));
        bench_row(task, bench_fmt_time(s.median, fig, sizeof fig), "-", "no peer implements the method", NULL, paper,
                  sp, NULL);
    }
    return 0;
}

/* Section 3: Table 1 of the paper at its own size, on a real scan. */
static int paper_rows(void)
{
    static const char *const paper_init[2] = {"Interpolate orientation: 8.9 s (50K-triangle Dragon 2, 2009)",
                                              "Initialize (u,v): 7.4 s (50K-triangle Dragon 2, 2009)"};
    static const char *const paper_edit[3] = {"4 s (50K, ROI ~25%, 2009)", "3.7 s (50K, ROI ~25%, 2009)",
                                              "1 s (50K, ROI ~25%, 2009)"};
    static const char *const stage[2] = {"field (orientation)", "PGP (u,v)"};
    pgp_options opt = pgp_default_options();
    pgp_mesh mesh;
    pgp_map map;
    pgp_error err;
    create_job *cj = (create_job *)calloc(1, sizeof *cj);
    double med[NSTAGES], cpu, upd;
    int k;
    if (!cj) return 1;
    if (pgp_load_mesh("data/meshes/armadillo.off", &opt, &mesh, &err)) {
        printf("paper-size rows skipped: %s\n", err.message);
        free(cj);
        return 0;
    }
    opt.scale = SCALE_FRACTION * bench_bbox_diagonal(mesh.positions, mesh.nverts);
    cj->mesh = &mesh;
    cj->opt = opt;
    bench_time_cpu(run_create, cj, 3, 0, &cpu);
    if (cj->fail) return 1;
    stage_medians(cj, med);
    printf("armadillo (%d triangles, the paper's 50K): field %.3f s, PGP %.3f s, singular %.3f s (median of %d)\n",
           mesh.nfaces, med[0], med[1], med[2], cj->n);
    for (k = 0; k < 2; k++) {
        char task[160], fig[32], sp[96], t0[32], t1[32];
        double lo = cj->stage[k][0], hi = lo;
        int r;
        for (r = 1; r < cj->n; r++) lo = cj->stage[k][r] < lo ? cj->stage[k][r] : lo, hi = cj->stage[k][r] > hi ? cj->stage[k][r] : hi;
        snprintf(task, sizeof task, "pgp_create %s stage, armadillo %d triangles", stage[k], mesh.nfaces);
        snprintf(sp, sizeof sp, "%d runs; %s..%s", cj->n, bench_fmt_time(lo, t0, sizeof t0), bench_fmt_time(hi, t1, sizeof t1));
        bench_row(task, bench_fmt_time(med[k], fig, sizeof fig), "-", "no peer implements the method", NULL,
                  paper_init[k], sp, k ? "the singularity detection that follows is not included" : NULL);
    }
    if (pgp_create(&mesh, &opt, &map, &err)) return printf("pgp_create failed: %s\n", err.message), 1;
    for (k = 0; k < 3; k++)
        if (edit_bench(&map, &mesh, &opt, 0.25, k, "25% area", &upd, paper_edit[k])) return 1;
    pgp_map_free(&map);
    pgp_mesh_free(&mesh);
    free(cj);
    return 0;
}

/* ---- issue 17: weights, integrability, the clean rendering ----------------------------- */

typedef struct weights_job {
    int fail; /* first: interleave3 reads it */
    const pgp_mesh *mesh;
    pgp_options opt;
    int vortices, singular;
} weights_job;

/* CPU medians (med[3]) of `runs` runs of fn on each of three jobs (size
 * bytes apart, each starting with its int fail flag), one of each in turn,
 * so that the host's load hits the three alike; 1 if a run failed. */
static int interleave3(void (*fn)(void *), void *jobs, size_t size, int runs, double med[3])
{
    double t[3][16];
    int r, k;
    for (r = 0; r < runs && r < 16; r++)
        for (k = 0; k < 3; k++) {
            void *job = (char *)jobs + (size_t)k * size;
            double c0 = bench_cpu_now();
            fn(job);
            t[k][r] = bench_cpu_now() - c0;
            if (*(int *)job) return 1;
        }
    for (k = 0; k < 3; k++) med[k] = bench_stats(t[k], r).median;
    return 0;
}

static void run_weights(void *arg)
{
    weights_job *j = (weights_job *)arg;
    pgp_map map;
    pgp_error err;
    if (pgp_create(j->mesh, &j->opt, &map, &err)) {
        printf("pgp_create failed: %s\n", err.message);
        j->fail = 1;
        return;
    }
    j->vortices = pgp_map_vortices(&map, NULL);
    j->singular = pgp_map_singular(&map, NULL);
    pgp_map_free(&map);
}

/* CPU medians of pgp_create on one mesh at S = diag/10 with the paper's
 * area weights, the default cotangent weights and options.integrable = 1,
 * interleaved (one run of each in turn), so that the host's load hits the
 * three alike. */
static int weights_rows(const char *file)
{
    static const char *const what[3] = {"area weights (paper)", "cotangent weights", "--field smooth"};
    weights_job j[3];
    double med[3];
    pgp_options opt = pgp_default_options();
    pgp_mesh mesh;
    pgp_error err;
    int k;
    if (pgp_load_mesh(file, &opt, &mesh, &err)) return printf("  %s skipped: %s\n", file, err.message), 0;
    for (k = 0; k < 3; k++) {
        memset(&j[k], 0, sizeof j[k]);
        j[k].mesh = &mesh, j[k].opt = opt;
    }
    j[0].opt.weights = PGP_WEIGHTS_AREA;
    j[2].opt.integrable = 1.0f;
    if (interleave3(run_weights, j, sizeof j[0], 7, med)) return 1;
    for (k = 0; k < 3; k++)
        printf("  %-26s %-22s %6d triangles %4d vortices singular %5.1f%%  init %7.1f ms (%.2fx area)\n", file, what[k],
               mesh.nfaces, j[k].vortices, 100.0 * j[k].singular / mesh.nfaces, 1e3 * med[k], med[k] / med[0]);
    pgp_mesh_free(&mesh);
    return 0;
}

typedef struct render_job {
    int fail; /* first: interleave3 reads it */
    const pgp_map *map;
    const pgp_tile *tile;
    pgp_render_options ro;
} render_job;

static void run_render(void *arg)
{
    render_job *j = (render_job *)arg;
    pgp_image img;
    pgp_error err;
    if (pgp_render(j->map, j->tile, &j->ro, &img, &err)) {
        printf("pgp_render failed: %s\n", err.message);
        j->fail = 1;
        return;
    }
    pgp_image_free(&img);
}

/* A frame of 800 x 600 (2 x 2 samples) with the clean fix against §3's
 * three lookups, on the same map and tile, interleaved. */
static int render_rows(const pgp_mesh *mesh, const char *name)
{
    static const pgp_fix fix[3] = {PGP_FIX_CLEAN, PGP_FIX_PAPER, PGP_FIX_OFF};
    static const char *const what[3] = {"clean (default)", "paper (section 3)", "none (one lookup)"};
    pgp_options opt = pgp_default_options();
    pgp_map map;
    pgp_tile tile;
    pgp_error err;
    render_job j[3];
    double med[3];
    int k;
    if (pgp_create(mesh, &opt, &map, &err) || pgp_builtin_tile("bricks", 256, &opt, &tile, &err))
        return printf("render rows failed: %s\n", err.message), 1;
    for (k = 0; k < 3; k++) {
        memset(&j[k], 0, sizeof j[k]);
        j[k].map = &map, j[k].tile = &tile, j[k].ro.fix = fix[k];
    }
    if (interleave3(run_render, j, sizeof j[0], 5, med)) return 1;
    for (k = 0; k < 3; k++)
        printf("  %-10s fix %-18s drawn specially %5.1f%%  frame %7.1f ms (%.2fx paper)\n", name, what[k],
               100.0 * pgp_map_special(&map, fix[k], NULL) / map.ntris, 1e3 * med[k], med[k] / med[1]);
    pgp_tile_free(&tile);
    pgp_map_free(&map);
    return 0;
}

static int issue17_rows(const pgp_mesh *rung0, const char *rung0_name)
{
    static const char *const files[4] = {"data/meshes/elephant.off", "data/meshes/cow.off", "data/meshes/knot.off",
                                         "data/meshes/mushroom.off"};
    pgp_options opt = pgp_default_options();
    pgp_mesh m;
    pgp_error err;
    int i;
    printf("weights and integrability at S = diag/10 (CPU medians of 7, interleaved):\n");
    for (i = 0; i < 4; i++)
        if (weights_rows(files[i])) return 1;
    printf("rendering, 800x600 with 2x2 samples, bricks (CPU medians of 5, interleaved):\n");
    if (pgp_load_mesh(files[0], &opt, &m, &err) == PGP_OK) {
        i = render_rows(&m, "elephant");
        pgp_mesh_free(&m);
        if (i) return 1;
    }
    return render_rows(rung0, rung0_name);
}

int main(int argc, char **argv)
{
    static const int runs[NRUNGS] = {7, 5, 3, 3};
    pgp_options opt = pgp_default_options();
    pgp_mesh mesh[NRUNGS];
    pgp_error err;
    create_job *cj = (create_job *)calloc(1, sizeof *cj);
    double faces[NRUNGS], secs[NRUNGS], st[NRUNGS][NSTAGES], cpu, t0 = bench_now(), upd10k = 0, upd;
    int i, k, builtin = 0;
    static const char *const names[NSTAGES] = {"field", "PGP", "singular"};

    memset(mesh, 0, sizeof mesh);
    if (!cj) return 1;
    if (pgp_load_mesh(MESH_FILE, &opt, &mesh[0], &err)) {
        builtin = 1;
        if (pgp_builtin_mesh("bumpy", &opt, &mesh[0], &err)) return printf("no mesh: %s\n", err.message), 1;
    }
    { /* the built-in mesh is smaller: subdivided up to the first rung */
        bench_mesh base, rung[NRUNGS];
        BENCH_MESH_COPY(base, mesh[0]);
        if (bench_ladder(&base, rung, NRUNGS, 4500)) return printf("subdivision failed\n"), 1;
        for (i = 0; i < NRUNGS; i++) BENCH_MESH_COPY(mesh[i], rung[i]);
    }
    if (argc > 1 && !strcmp(argv[1], "issue17")) /* only section 4 */
        return issue17_rows(&mesh[0], builtin ? "bumpy" : "mushroom");
    opt.scale = SCALE_FRACTION * bench_bbox_diagonal(mesh[0].positions, mesh[0].nverts);
    printf("mesh: %s (%d triangles), 1-to-4 midpoint subdivision per rung%s\n",
           builtin ? "built-in \"bumpy\"" : MESH_FILE, mesh[0].nfaces,
           builtin ? " [data/ absent: run `make data` for the real mesh]" : "");
    printf("field UP, tile side %.3f x bbox diagonal = %.4g mesh units\n", SCALE_FRACTION, (double)opt.scale);
    printf("paper (Table 1, 2009 hardware): 50K-triangle dragon, orientation 8.9 s + (u,v) 7.4 s; "
           "1-4 s per constraint\n\n");
    printf("pgp_create, one core (stage medians from the progress callback):\n");
    printf("%9s %5s %23s %7s %8s %8s %9s %9s %8s\n", "triangles", "runs", "median (min..max) s", "cpu s",
           "field s", "PGP s", "singular", "tris/s", "singular");
    for (i = 0; i < NRUNGS; i++) {
        bench_stat s;
        memset(cj, 0, sizeof *cj);
        cj->mesh = &mesh[i];
        cj->opt = opt;
        s = bench_time_cpu(run_create, cj, runs[i], i < 2, &cpu);
        if (cj->fail) return 1;
        if (i < 2) { /* the warm-up run is not one of the samples */
            for (k = 0; k < NSTAGES; k++) memmove(cj->stage[k], cj->stage[k] + 1, sizeof(double) * (cj->n - 1));
            cj->n--;
        }
        stage_medians(cj, st[i]);
        faces[i] = mesh[i].nfaces;
        secs[i] = s.median;
        printf("%9d %5d %8.3f (%.3f..%.3f) %7.3f %8.3f %8.3f %9.3f %9.0f %7.1f%%\n", mesh[i].nfaces, s.runs,
               s.median, s.min, s.max, cpu, st[i][0], st[i][1], st[i][2], mesh[i].nfaces / s.median,
               100.0 * cj->nsing / mesh[i].nfaces);
        fflush(stdout);
    }
    printf("growth: time ~ triangles^%.2f (log-log least squares over %d rungs; 1.00 = linear)\n",
           bench_loglog_slope(faces, secs, NRUNGS), NRUNGS);
    bench_growth("pgp_create", bench_loglog_slope(faces, secs, NRUNGS), "triangles, 4 rungs 4.6K..295K (mushroom ladder)",
                 NULL);
    for (k = 0; k < NSTAGES; k++) {
        double y[NRUNGS];
        char method[64];
        for (i = 0; i < NRUNGS; i++) y[i] = st[i][k];
        printf("  %-8s ~ triangles^%.2f\n", names[k], bench_loglog_slope(faces, y, NRUNGS));
        snprintf(method, sizeof method, "pgp_create, %s stage", names[k]);
        if (k < 2) bench_growth(method, bench_loglog_slope(faces, y, NRUNGS), "triangles, the same 4 rungs", NULL);
    }
    printf("target: whole initialisation of %d triangles < 1 s: %s (%.3f s)\n\n", mesh[TARGET_RUNG].nfaces,
           secs[TARGET_RUNG] < 1.0 ? "met" : "NOT met", secs[TARGET_RUNG]);

    printf("local updates (§2.1), each an edit of one constraint recomputing its effect area:\n");
    for (i = 1; i < NRUNGS; i++) {
        pgp_map map;
        if (pgp_create(&mesh[i], &opt, &map, &err)) return printf("pgp_create failed: %s\n", err.message), 1;
        printf(" %d triangles:\n", mesh[i].nfaces);
        for (k = 0; k < 3; k++)
            if (edit_bench(&map, &mesh[i], &opt, 0.25, k, "25% area", &upd, NULL)) return 1;
        if (edit_bench(&map, &mesh[i], &opt, 10000.0 / mesh[i].nfaces, 0, "10K area", &upd, NULL)) return 1;
        if (i == TARGET_RUNG) upd10k = upd;
        pgp_map_free(&map);
    }
    printf("target: a local update touching ~10K triangles < 0.2 s: %s (%.3f s at %d triangles)\n\n",
           upd10k < 0.2 ? "met" : "NOT met", upd10k, mesh[TARGET_RUNG].nfaces);
    if (issue17_rows(&mesh[0], builtin ? "bumpy" : "mushroom")) return 1;
    printf("\n");
    printf("the paper's Table 1 at its size:\n");
    if (paper_rows()) return 1;
    printf("\n");
    printf("whole bench: %.1f s\n", bench_now() - t0);
    for (i = 0; i < NRUNGS; i++) pgp_mesh_free(&mesh[i]);
    free(cj);
    return 0;
}
