/* bench_lapped: lapped.h (Praun, Finkelstein, Hoppe 2000) on one core.
 *   1. lapped_create over a ladder of about 5K, 20K, 75K and 300K triangles:
 *      a real mesh (CGAL's mushroom, 4,608 triangles, so that x16 = 73,728
 *      and x64 = 294,912 land on the rungs) refined by 1-to-4 midpoint
 *      subdivision, at a texture scale that is a fixed fraction of the
 *      bounding-box diagonal, so the paste count stays about constant and
 *      the growth with the triangle count shows; then the exponent of time
 *      against triangles (least-squares slope in log-log).
 *   2. target: the ~75K rung needs more than 1,000 pastes and takes < 2 s.
 *   3. runtime pasting (lapped_render, 1024x1024, no supersampling) of the
 *      ~75K rung against drawing the mesh once through the same function.
 * Times are wall-clock medians (bench.h); lapped_create and the renders
 * also print the median process CPU time, which helps on a shared machine.
 * Without `make data` it falls back to the built-in "bumpy" mesh and
 * "scales" texture and says so. An optional argument replaces the scale
 * fraction (to explore; the figures quoted use the default). */
#include "bench.h"
#define LAPPED_IMPLEMENTATION
#include "../lapped.h"

#define MESH_FILE "data/meshes/mushroom.off"
#define TEXTURE_FILE "data/textures/cracked.ppm"
/* Patch side = SCALE_FRACTION x bounding-box diagonal, the same on every
 * rung; found by experiment so that the ~75K rung needs > 1,000 pastes
 * (0.07: about 1,200 on every rung; 0.032 gives about 5,800). */
#define SCALE_FRACTION 0.07f
#define NRUNGS 4
#define TARGET_RUNG 2

/* ---- 1-to-4 midpoint subdivision ------------------------------------------ */

/* Edge-midpoint table: open addressing on the (smaller, larger) vertex pair. */
typedef struct edge_map {
    long long *key;
    int *mid;
    size_t mask;
} edge_map;

static int edge_mid(edge_map *em, lapped_mesh *out, int a, int b)
{
    long long k = a < b ? (long long)a << 32 | (unsigned)b : (long long)b << 32 | (unsigned)a;
    size_t h = (size_t)((unsigned long long)k * 0x9E3779B97F4A7C15ull >> 20) & em->mask;
    int c;
    while (em->key[h] != -1 && em->key[h] != k) h = (h + 1) & em->mask;
    if (em->key[h] == k) return em->mid[h];
    em->key[h] = k;
    em->mid[h] = c = out->nverts++;
    for (int i = 0; i < 3; i++)
        out->positions[3 * c + i] = 0.5f * (out->positions[3 * a + i] + out->positions[3 * b + i]);
    return c;
}

/* Every triangle of `in` (all faces must be triangles) split in four at its
 * edge midpoints: the surface stays the same flat triangles, which is all
 * the timing needs. Orientation is kept. */
static int subdivide(const lapped_mesh *in, lapped_mesh *out)
{
    size_t cap = 1;
    int ne = 3 * in->nfaces, f; /* at most this many edges */
    edge_map em;
    while (cap < (size_t)ne * 2) cap <<= 1;
    memset(out, 0, sizeof *out);
    em.key = (long long *)malloc(cap * sizeof *em.key);
    em.mid = (int *)malloc(cap * sizeof *em.mid);
    em.mask = cap - 1;
    out->positions = (float *)malloc(sizeof(float) * 3 * ((size_t)in->nverts + ne));
    out->face_start = (int *)malloc(sizeof(int) * (4 * (size_t)in->nfaces + 1));
    out->face_verts = (int *)malloc(sizeof(int) * 12 * (size_t)in->nfaces);
    if (!em.key || !em.mid || !out->positions || !out->face_start || !out->face_verts) return 1;
    memset(em.key, 0xff, cap * sizeof *em.key);
    memcpy(out->positions, in->positions, sizeof(float) * 3 * in->nverts);
    out->nverts = in->nverts;
    for (f = 0; f < in->nfaces; f++) {
        const int *v = in->face_verts + in->face_start[f];
        int m[3], t, k, q[4][3];
        if (in->face_start[f + 1] - in->face_start[f] != 3) return 1;
        for (k = 0; k < 3; k++) m[k] = edge_mid(&em, out, v[k], v[(k + 1) % 3]);
        q[0][0] = v[0], q[0][1] = m[0], q[0][2] = m[2];
        q[1][0] = m[0], q[1][1] = v[1], q[1][2] = m[1];
        q[2][0] = m[2], q[2][1] = m[1], q[2][2] = v[2];
        q[3][0] = m[0], q[3][1] = m[1], q[3][2] = m[2];
        for (t = 0; t < 4; t++)
            for (k = 0; k < 3; k++) out->face_verts[12 * f + 3 * t + k] = q[t][k];
    }
    out->nfaces = 4 * in->nfaces;
    for (f = 0; f <= out->nfaces; f++) out->face_start[f] = 3 * f;
    free(em.key);
    free(em.mid);
    return 0;
}

static float bbox_diagonal(const lapped_mesh *m)
{
    float lo[3], hi[3], d = 0.0f;
    int v, k;
    for (k = 0; k < 3; k++) lo[k] = hi[k] = m->positions[k];
    for (v = 0; v < m->nverts; v++)
        for (k = 0; k < 3; k++) {
            float x = m->positions[3 * v + k];
            lo[k] = x < lo[k] ? x : lo[k];
            hi[k] = x > hi[k] ? x : hi[k];
        }
    for (k = 0; k < 3; k++) d += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    return sqrtf(d);
}

/* ---- timing ---------------------------------------------------------------- */

typedef struct create_job {
    const lapped_mesh *mesh;
    const lapped_image *patch;
    lapped_options opt;
    lapped_texture t; /* the last result, kept */
    int fail;
} create_job;

static void run_create(void *arg)
{
    create_job *j = (create_job *)arg;
    lapped_error err;
    lapped_texture_free(&j->t);
    if (lapped_create(j->mesh, j->patch, 1, &j->opt, &j->t, &err)) {
        printf("lapped_create failed: %s\n", err.message);
        j->fail = 1;
    }
}

typedef struct render_job {
    const lapped_mesh *mesh;
    const lapped_texture *t;
    const lapped_image *patch;
    lapped_render_options ro;
    int fail;
} render_job;

static void run_render(void *arg)
{
    render_job *j = (render_job *)arg;
    lapped_image pic;
    lapped_error err;
    if (lapped_render(j->mesh, j->t, j->patch, NULL, &j->ro, &pic, &err)) {
        printf("lapped_render failed: %s\n", err.message);
        j->fail = 1;
    }
    lapped_image_free(&pic);
}

/* Process CPU time: the machine may be shared, and CPU time is what one
 * core spent whatever else runs (wall time stays the headline figure). */
static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* bench_time with the warm-up call optional (a big rung would spend a
 * whole run, seconds, warming caches that one run fills anyway), and the
 * CPU time's median too. */
static bench_stat time_runs(void (*fn)(void *), void *arg, int runs, int warm, double *cpu_median)
{
    double t[64], c[64];
    int i;
    if (runs > 64) runs = 64;
    if (warm) fn(arg);
    for (i = 0; i < runs; i++) {
        double t0 = bench_now(), c0 = cpu_now();
        fn(arg);
        c[i] = cpu_now() - c0;
        t[i] = bench_now() - t0;
    }
    *cpu_median = bench_stats(c, runs).median;
    return bench_stats(t, runs);
}

/* The single-layer baseline for the render: one paste holding every
 * triangle, with the coordinates of the topmost paste that contains it
 * (after hidden-face removal the topmost paste of a triangle is never
 * removed, so every triangle has one). */
static int single_layer(const lapped_texture *t, lapped_texture *one, lapped_paste *p)
{
    int *done = (int *)calloc((size_t)t->ntris, sizeof(int)), q, i, n = 0;
    *one = *t;
    memset(p, 0, sizeof *p);
    p->faces = (int *)malloc(sizeof(int) * (size_t)t->ntris);
    p->uvs = (float *)malloc(sizeof(float) * 6 * (size_t)t->ntris);
    if (!done || !p->faces || !p->uvs) return 1;
    for (q = t->npastes - 1; q >= 0; q--)
        for (i = 0; i < t->pastes[q].nfaces; i++) {
            int f = t->pastes[q].faces[i];
            if (done[f]) continue;
            done[f] = 1;
            p->faces[n] = f;
            memcpy(p->uvs + 6 * n, t->pastes[q].uvs + 6 * i, sizeof(float) * 6);
            n++;
        }
    p->nfaces = n;
    p->patch = 0;
    one->npastes = 1;
    one->pastes = p;
    free(done);
    return n != t->ntris;
}

int main(int argc, char **argv)
{
    static const int runs[NRUNGS] = {7, 5, 3, 3};
    lapped_options opt = lapped_default_options();
    lapped_mesh mesh[NRUNGS];
    lapped_image texture, patch;
    lapped_error err;
    create_job cj;
    render_job rj;
    bench_stat s[NRUNGS], rs_bare, rs_one, rs_full;
    double rc_bare, rc_one, rc_full;
    double faces[NRUNGS], secs[NRUNGS], cpu[NRUNGS], total = 0.0, t0 = bench_now(), slope;
    float frac = argc > 1 ? (float)atof(argv[1]) : SCALE_FRACTION, diag;
    int npastes[NRUNGS], i, builtin_mesh = 0, builtin_tex = 0;
    lapped_texture kept, bare, one;
    lapped_paste all;
    long drawn = 0;

    (void)bench_time; /* time_runs below also reports CPU time */
    memset(&cj, 0, sizeof cj);
    memset(mesh, 0, sizeof mesh);
    if (lapped_load_mesh(MESH_FILE, &opt, &mesh[0], &err)) {
        builtin_mesh = 1;
        if (lapped_builtin_mesh("bumpy", &opt, &mesh[0], &err)) {
            printf("no mesh: %s\n", err.message);
            return 1;
        }
    }
    if (lapped_load_image(TEXTURE_FILE, &opt, &texture, &err)) {
        builtin_tex = 1;
        if (lapped_builtin_texture("scales", 128, &opt, &texture, &err)) {
            printf("no texture: %s\n", err.message);
            return 1;
        }
    }
    if (lapped_make_patch(&texture, NULL, &opt, &patch, &err)) {
        printf("lapped_make_patch failed: %s\n", err.message);
        return 1;
    }
    /* the first rung: the mesh, subdivided until it has at least ~4.5K
     * triangles (the built-in one is smaller); then three more rungs */
    while (mesh[0].nfaces < 4500) {
        lapped_mesh m;
        if (subdivide(&mesh[0], &m)) return printf("subdivision failed\n"), 1;
        lapped_mesh_free(&mesh[0]);
        mesh[0] = m;
    }
    for (i = 1; i < NRUNGS; i++)
        if (subdivide(&mesh[i - 1], &mesh[i])) return printf("subdivision failed\n"), 1;
    diag = bbox_diagonal(&mesh[0]);
    opt.field.mode = LAPPED_FIELD_UP;
    opt.field.scale = frac * diag;
    printf("mesh: %s (%d triangles), 1-to-4 midpoint subdivision per rung%s\n",
           builtin_mesh ? "built-in \"bumpy\"" : MESH_FILE, mesh[0].nfaces,
           builtin_mesh ? " [data/ absent: run `make data` for the real mesh]" : "");
    printf("patch: %s (%dx%d, %s alpha), field UP, scale %.4f x bbox diagonal = %.5g mesh units, "
           "seed 0\n",
           builtin_tex ? "built-in \"scales\" 128 px" : TEXTURE_FILE, patch.width, patch.height,
           texture.channels % 2 == 0 ? "the image's" : "splotch", frac,
           opt.field.scale);
    printf("paper: 20 s to 6 min for ~5,000-face meshes on a 733 MHz Pentium III\n\n");

    printf("lapped_create, one core:\n");
    printf("%9s %7s %5s %23s %6s %9s %11s %10s %7s %5s %7s\n", "triangles", "pastes", "runs",
           "median (min..max) s", "cpu s", "pastes/s", "triangles/s", "tris/paste", "layers", "hard", "wall s");
    cj.patch = &patch;
    cj.opt = opt;
    for (i = 0; i < NRUNGS; i++) {
        double r0 = bench_now();
        cj.mesh = &mesh[i];
        s[i] = time_runs(run_create, &cj, runs[i], i < 2, &cpu[i]);
        if (cj.fail) return 1;
        npastes[i] = cj.t.npastes;
        faces[i] = mesh[i].nfaces;
        secs[i] = s[i].median;
        total = bench_now() - r0; /* this rung's wall time, warm-up included */
        /* cpu s: median process CPU time of one lapped_create */
        /* tris/paste: surface-patch size before hidden faces were removed;
         * hard: pastes whose growth stopped at the distortion limit */
        printf("%9d %7d %5d %8.3f (%.3f..%.3f) %6.3f %9.0f %11.0f %10.0f %7.2f %5d %7.1f\n", mesh[i].nfaces,
               npastes[i], s[i].runs, s[i].median, s[i].min, s[i].max, cpu[i], npastes[i] / s[i].median,
               mesh[i].nfaces / s[i].median, cj.t.layers_before * mesh[i].nfaces / npastes[i],
               cj.t.layers, cj.t.hard_edges, total);
        fflush(stdout);
        if (i == TARGET_RUNG) { /* kept for the render */
            kept = cj.t;
            memset(&cj.t, 0, sizeof cj.t);
        }
    }
    lapped_texture_free(&cj.t);
    slope = bench_loglog_slope(faces, secs, NRUNGS);
    printf("growth: time ~ triangles^%.2f (log-log least squares over %d rungs; 1.00 = linear)\n", slope,
           NRUNGS);
    printf("  step exponents:");
    for (i = 1; i < NRUNGS; i++)
        printf(" %.0fK->%.0fK %.2f", faces[i - 1] / 1e3, faces[i] / 1e3,
               log(secs[i] / secs[i - 1]) / log(faces[i] / faces[i - 1]));
    printf("\n");
    printf("  cpu-time growth: triangles^%.2f\n", bench_loglog_slope(faces, cpu, NRUNGS));
    printf("target: 75K faces, >1000 pastes, <2 s: %s (%d triangles, %d pastes in %.3f s; cpu %.3f s)\n\n",
           npastes[TARGET_RUNG] > 1000 && secs[TARGET_RUNG] < 2.0 ? "met" : "not met",
           mesh[TARGET_RUNG].nfaces, npastes[TARGET_RUNG], secs[TARGET_RUNG], cpu[TARGET_RUNG]);

    /* ---- 3. runtime pasting against drawing the mesh once ----------------
     * lapped_render always draws a base pass first (the whole mesh, mid-grey,
     * lit, writing depth), then each paste's triangles textured and blended
     * over it (depth LEQUAL, no depth write). Its fixed costs are the same
     * whatever the pastes: framebuffer clear, the patch's mip chain, resolve.
     * Baselines, both through lapped_render so they pay the same fixed costs:
     *   bare:   a lapped texture with no pastes: exactly one draw of the bare
     *           mesh (the base pass), i.e. "the mesh drawn once".
     *   1 layer: one paste holding every triangle once, with the coordinates
     *           of its topmost paste: the base pass plus one textured, blended
     *           pass over the whole mesh with realistic texture footprints --
     *           what a conventionally textured mesh costs in this renderer.
     * The lapped texture composites every paste (layers x triangles drawn). */
    {
        lapped_texture full = kept;
        int p;
        for (p = 0; p < full.npastes; p++) drawn += full.pastes[p].nfaces;
        bare = full;
        bare.npastes = 0;
        bare.pastes = NULL;
        if (single_layer(&full, &one, &all)) return printf("single-layer baseline failed\n"), 1;
        memset(&rj, 0, sizeof rj);
        rj.mesh = &mesh[TARGET_RUNG];
        rj.patch = &patch;
        rj.ro.width = rj.ro.height = 1024;
        rj.ro.supersample = 1;
        rj.t = &bare;
        rs_bare = time_runs(run_render, &rj, 7, 1, &rc_bare);
        rj.t = &one;
        rs_one = time_runs(run_render, &rj, 7, 1, &rc_one);
        rj.t = &full;
        rs_full = time_runs(run_render, &rj, 5, 1, &rc_full);
        if (rj.fail) return 1;
        printf("lapped_render 1024x1024, supersample 1, %d triangles:\n", mesh[TARGET_RUNG].nfaces);
        bench_report("  bare mesh (base pass only, 0 pastes)", rs_bare, 0, "");
        bench_report("  1 layer (base pass + 1 paste of all tris)", rs_one, 0, "");
        bench_report("  lapped texture (base pass + every paste)", rs_full, 0, "");
        printf("  %d pastes composited, %ld paste triangles drawn (%.2f per mesh triangle)\n",
               full.npastes, drawn, (double)drawn / mesh[TARGET_RUNG].nfaces);
        printf("  ratio lapped / bare mesh: %.1fx; lapped / 1 layer: %.1fx; marginal cost per paste: %.3f ms\n",
               rs_full.median / rs_bare.median, rs_full.median / rs_one.median,
               (rs_full.median - rs_one.median) / (full.npastes - 1) * 1e3);
        printf("  cpu medians: bare %.1f ms, 1 layer %.1f ms, lapped %.1f ms: ratios %.1fx and %.1fx\n\n",
               rc_bare * 1e3, rc_one * 1e3, rc_full * 1e3, rc_full / rc_bare, rc_full / rc_one);
        lapped_texture_free(&full);
        free(all.faces);
        free(all.uvs);
    }
    printf("whole bench: %.1f s\n", bench_now() - t0);
    for (i = 0; i < NRUNGS; i++) lapped_mesh_free(&mesh[i]);
    lapped_image_free(&texture);
    lapped_image_free(&patch);
    return 0;
}
