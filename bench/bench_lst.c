/* bench_lst: lst.h (Takayama et al. 2008) on one core.
 *   1. fill (lst_create) of the built-in sphere tetrahedralized to about 5K,
 *      20K and 100K tetrahedra, for every texture type (0, 1-a, 1-b, 2-a,
 *      2-b) with the default fields and a 64^3 exemplar, plus the kiwi
 *      (2-b with its painted depth) at 5K; the exponent of time against
 *      tetrahedra (least-squares slope in log-log) per type.
 *   2. a plane cut through the middle at each size (mesh split, pastes
 *      updated).
 *   3. a 200-slice volume rendering (§5.1.2), 640x480, of the 5K kiwi.
 *   4. memory: peak resident set size after each size, and the model's
 *      size on disk (model file + the exemplar and masks as gzip NRRD).
 *   5. direct evaluation (lst_eval) of 100K random points of the kiwi.
 * Targets (the issue): fill of 5K under 0.5 s, 100K under 10 s, a cut under
 * 20 ms at 5K. The paper's Table 1 (64^3 exemplars, a 2.3 GHz notebook):
 * fill 18-416 s for 1-5K tetrahedra, cut 31-187 ms, 2.7-14.5 MB.
 * Times are wall-clock medians (bench.h) with the process CPU time of the
 * median run beside them (the machine is shared). An optional argument
 * limits the ladder to the first N sizes. */
#include "bench.h"
#include <string.h>
#include <sys/resource.h>
#define LST_IMPLEMENTATION
#include "../lst.h"

#define NSIZES 3
static const int sizes[NSIZES] = {5000, 20000, 100000};
static const int runs[NSIZES] = {5, 3, 1};
static const char *const type_names[5] = {"0", "1-a", "1-b", "2-a", "2-b"};
static const char *const exemplars[5] = {"spots", "fibers", "layers", "fibers", "rings"};

static double cpu_now(void) { return (double)clock() / CLOCKS_PER_SEC; }

static long peak_rss_kb(void)
{
    struct rusage u;
    getrusage(RUSAGE_SELF, &u);
    return u.ru_maxrss;
}

static int count_write(void *ctx, const void *data, size_t size)
{
    (void)data;
    *(size_t *)ctx += size;
    return 0;
}

static int tets_of(const char *surface, int n, lst_mesh *s, lst_tetmesh *m)
{
    lst_options o = lst_default_options();
    lst_error err;
    o.tet.target_tets = n;
    o.tet.uniform = 1; /* the paper's lattice: n tetrahedra (the graded default adds some 5x near the surface) */
    if (lst_builtin_mesh(surface, &o, s, &err) || lst_tetrahedralize(s, &o, m, NULL, &err)) {
        fprintf(stderr, "bench_lst: %s\n", err.message);
        return 0;
    }
    return 1;
}

/* One fill; returns wall seconds (cpu in *cpu), the model in *model. */
static double fill(const lst_tetmesh *m, const lst_mesh *s, const lst_volume *ex, lst_options *o, lst_model *model, double *cpu)
{
    lst_error err;
    double t0 = bench_now(), c0 = cpu_now();
    lst_source src;
    src.exemplar = ex, src.values = NULL;
    if (lst_create(m, s, &src, o, model, &err)) {
        fprintf(stderr, "bench_lst: %s\n", err.message);
        exit(1);
    }
    *cpu = cpu_now() - c0;
    return bench_now() - t0;
}

/* Median of `n` fills (the first n-1 models freed, the last kept), with
 * the CPU time of the median run. */
static bench_stat fill_stat(const lst_tetmesh *m, const lst_mesh *s, const lst_volume *ex, lst_options *o, int n, lst_model *keep,
                            double *cpu)
{
    double t[8], c[8], order[8];
    int i, med = 0;
    for (i = 0; i < n; i++) {
        t[i] = order[i] = fill(m, s, ex, o, keep, &c[i]);
        if (i + 1 < n) lst_model_free(keep);
    }
    bench_stats(order, n);
    for (i = 0; i < n; i++)
        if (t[i] == order[n / 2]) med = i;
    *cpu = c[med];
    return bench_stats(t, n);
}

static size_t disk_size(const lst_model *model, const lst_volume *ex)
{
    size_t n = 0;
    lst_error err;
    int k;
    lst_write_model(model, count_write, &n, &err);
    lst_write_volume(ex, count_write, &n, &err);
    for (k = 0; k < model->masks.count; k++) lst_write_volume(&model->masks.volumes[k], count_write, &n, &err);
    return n;
}

/* A row of the summary table: patchwork's time (with the CPU time of the
 * median run when cpu >= 0), no peer, the paper's figure. */
static void lst_row(const char *task, bench_stat st, double cpu, const char *paper)
{
    char fig[80], sp[96], t0[32], t1[32], c[32];
    snprintf(sp, sizeof sp, "%d run%s; %s..%s", st.runs, st.runs == 1 ? "" : "s", bench_fmt_time(st.min, t0, sizeof t0),
             bench_fmt_time(st.max, t1, sizeof t1));
    bench_fmt_time(st.median, fig, sizeof fig);
    if (cpu >= 0.0) snprintf(fig + strlen(fig), sizeof fig - strlen(fig), " (cpu %s)", bench_fmt_time(cpu, c, sizeof c));
    bench_row(task, fig, "-", "no peer implements the method", NULL, paper, sp, NULL);
}

/* One timed plane cut (it changes the model, so it is timed once); returns seconds. */
static double cut_bench(lst_model *model, const char *label)
{
    const float plane[4] = {0.2f, 0.1f, 1.0f, 0.05f};
    lst_error err;
    double t0 = bench_now();
    int nt = model->mesh.ntets;
    if (lst_cut_plane(model, plane, &err)) {
        fprintf(stderr, "bench_lst: %s\n", err.message);
        exit(1);
    }
    t0 = bench_now() - t0;
    printf("%-44s %9.3f ms  (%d -> %d tetrahedra)\n", label, 1e3 * t0, nt, model->mesh.ntets);
    return t0;
}

typedef struct eval_job {
    const lst_model *model;
    float *pts, *rgba;
    int n;
} eval_job;

static void eval_run(void *arg)
{
    eval_job *j = (eval_job *)arg;
    lst_error err;
    lst_eval(j->model, j->pts, j->n, j->rgba, NULL, &err);
}

static void eval_bench(const lst_model *model)
{
    eval_job j;
    int k;
    j.model = model, j.n = 100000;
    j.pts = (float *)malloc(sizeof(float) * 3 * (size_t)j.n);
    j.rgba = (float *)malloc(sizeof(float) * 4 * (size_t)j.n);
    for (k = 0; k < 3 * j.n; k++) j.pts[k] = (float)((double)pw_hash64(9, (uint64_t)k) / 18446744073709551616.0 * 1.6 - 0.8);
    bench_report("direct evaluation, 100K points (kiwi 5K)", bench_time(eval_run, &j, 3), j.n, "points");
    free(j.pts), free(j.rgba);
}

static void volume_bench(void)
{
    lst_options o = lst_default_options();
    lst_mesh s;
    lst_tetmesh m;
    lst_volume ex, val;
    lst_model model;
    lst_render_options ro;
    lst_volume_options vo;
    lst_image img;
    lst_error err;
    lst_constraints c;
    double cpu, t0, c0;
    bench_stat st;
    if (!tets_of("kiwi", 5000, &s, &m)) exit(1);
    o.type = LST_TYPE_2B;
    lst_builtin_constraints("kiwi", &s, &o, &c, &err);
    o.constraints = c.items, o.nconstraints = c.count;
    lst_builtin_exemplar("kiwi", 64, &o, &ex, &val, &err);
    st = fill_stat(&m, &s, &ex, &o, 3, &model, &cpu);
    bench_report("fill kiwi 2-b (painted depth), 5K", st, 0, NULL);
    lst_row("lst fill, kiwi 5K tetrahedra (type 2-b, painted depth, 64^3)", st, cpu,
            "Table 1: 18-416 s for 1,089-5,012 tetrahedra (64^3 exemplars, 2.3 GHz notebook, 2008)");
    printf("%-44s %d tetrahedra, %d pastes, %.2f per tetrahedron, cpu %.3f s\n", "", m.ntets, model.npastes, model.layers, cpu);
    printf("%-44s %.1f MB on disk\n", "kiwi model size", disk_size(&model, &ex) / 1048576.0);
    memset(&ro, 0, sizeof ro);
    memset(&vo, 0, sizeof vo);
    ro.width = 640, ro.height = 480, ro.supersample = 1;
    vo.slices = 200;
    t0 = bench_now(), c0 = cpu_now();
    if (lst_render_volume(&model, &ro, &vo, &img, &err)) {
        fprintf(stderr, "bench_lst: %s\n", err.message);
        exit(1);
    }
    t0 = bench_now() - t0;
    printf("%-44s %9.3f ms  (cpu %.3f s; the paper: about 3 s on a GPU)\n", "volume rendering, 200 slices, 640x480",
           1e3 * t0, cpu_now() - c0);
    st.median = st.min = st.max = t0, st.runs = 1;
    lst_row("lst volume rendering, 200 slices, 640x480 (kiwi 5K, one core)", st, -1.0, "about 3 s (GPU, 2008)");
    lst_image_free(&img);
    eval_bench(&model);
    t0 = cut_bench(&model, "cut, kiwi 5K");
    st.median = st.min = st.max = t0, st.runs = 1;
    lst_row("lst plane cut, kiwi 5K tetrahedra (mesh split, pastes updated)", st, -1.0, "Table 1: 31-187 ms");
    lst_model_free(&model);
    lst_constraints_free(&c);
    lst_volume_free(&ex), lst_volume_free(&val), lst_tetmesh_free(&m), lst_mesh_free(&s);
}

int main(int argc, char **argv)
{
    int nsizes = argc > 1 ? atoi(argv[1]) : NSIZES, k, t;
    double times[5][NSIZES], counts[NSIZES], cuts[NSIZES];
    bench_stat slowest[NSIZES];
    int slowest_type[NSIZES];
    double slowest_cpu[NSIZES];
    lst_volume ex[5];
    lst_options o = lst_default_options();
    lst_error err;
    if (nsizes < 1 || nsizes > NSIZES) nsizes = NSIZES;
    for (t = 0; t < 5; t++) lst_builtin_exemplar(exemplars[t], 64, &o, &ex[t], NULL, &err);
    for (k = 0; k < nsizes; k++) {
        lst_mesh s;
        lst_tetmesh m;
        char label[96];
        if (!tets_of("sphere", sizes[k], &s, &m)) return 1;
        counts[k] = m.ntets;
        slowest[k].median = -1.0;
        for (t = 0; t < 5; t++) {
            lst_model model;
            double cpu;
            bench_stat st;
            o = lst_default_options();
            o.type = (lst_type)t;
            st = fill_stat(&m, NULL, &ex[t], &o, runs[k], &model, &cpu);
            times[t][k] = st.median;
            if (st.median > slowest[k].median) {
                slowest[k] = st;
                slowest_type[k] = t;
                slowest_cpu[k] = cpu;
            }
            snprintf(label, sizeof label, "fill sphere %dK, type %s", sizes[k] / 1000, type_names[t]);
            bench_report(label, st, m.ntets, "tets");
            printf("%-44s %d pastes, %.2f per tetrahedron, cpu %.3f s, %.1f MB on disk\n", "", model.npastes, model.layers,
                   cpu, disk_size(&model, &ex[t]) / 1048576.0);
            if (t == LST_TYPE_2B) {
                snprintf(label, sizeof label, "cut, sphere %dK", sizes[k] / 1000);
                cuts[k] = cut_bench(&model, label);
            }
            lst_model_free(&model);
        }
        printf("%-44s %.1f MB after the %dK sizes\n", "peak resident set size", peak_rss_kb() / 1024.0, sizes[k] / 1000);
        snprintf(label, sizeof label, "lst fill, sphere %d tetrahedra, slowest of the 5 types (%s), 64^3", m.ntets,
                 type_names[slowest_type[k]]);
        lst_row(label, slowest[k], slowest_cpu[k], k == 0 ? "Table 1: 18-416 s for 1,089-5,012 tetrahedra (2008)" : NULL);
        snprintf(label, sizeof label, "lst plane cut, sphere %d tetrahedra", m.ntets);
        slowest[k].median = slowest[k].min = slowest[k].max = cuts[k], slowest[k].runs = 1;
        lst_row(label, slowest[k], -1.0, k == 0 ? "Table 1: 31-187 ms" : NULL);
        lst_tetmesh_free(&m), lst_mesh_free(&s);
    }
    if (nsizes > 1)
        for (t = 0; t < 5; t++) {
            char method[48];
            double g = bench_loglog_slope(counts, times[t], nsizes);
            printf("growth of the fill, type %-3s                   time ~ tets^%.2f\n", type_names[t], g);
            snprintf(method, sizeof method, "lst_create, type %s", type_names[t]);
            bench_growth(method, g, "tetrahedra, sphere 5K..100K", NULL);
        }
    volume_bench();
    {
        double w5 = 0, w100 = 0;
        for (t = 0; t < 5; t++) w5 = times[t][0] > w5 ? times[t][0] : w5;
        for (t = 0; nsizes == NSIZES && t < 5; t++) w100 = times[t][2] > w100 ? times[t][2] : w100;
        printf("targets: fill 5K < 0.5 s (slowest type %.3f s: %s)", w5, w5 < 0.5 ? "met" : "NOT met");
        if (nsizes == NSIZES) printf(", 100K < 10 s (slowest type %.2f s: %s)", w100, w100 < 10.0 ? "met" : "NOT met");
        printf(", cut < 20 ms at 5K (above)\n");
    }
    for (t = 0; t < 5; t++) lst_volume_free(&ex[t]);
    return 0;
}
