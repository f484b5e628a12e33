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
 *   4. peer (when bench/probe.sh found OSMesa at build time): the same
 *      lapped texture composited by Mesa's llvmpipe through OSMesa, the
 *      GL way of the paper's runtime pasting (§4): the base pass, then one
 *      blended, textured draw per paste, interleaved round by round with
 *      lapped_render (bench/peer_gl.h).
 * Times are wall-clock medians (bench.h); lapped_create and the renders
 * also print the median process CPU time, which helps on a shared machine.
 * Without `make data` it falls back to the built-in "bumpy" mesh and
 * "scales" texture and says so. An optional argument replaces the scale
 * fraction (to explore; the figures quoted use the default). */
#include "bench.h"
#define LAPPED_IMPLEMENTATION
#include "../lapped.h"
#ifdef BENCH_OSMESA
#include "peer_gl.h"
#endif

#define MESH_FILE "data/meshes/mushroom.off"
#define TEXTURE_FILE "data/textures/cracked.ppm"
/* Patch side = SCALE_FRACTION x bounding-box diagonal, the same on every
 * rung; found by experiment so that the ~75K rung needs > 1,000 pastes
 * (0.07: about 1,200 on every rung; 0.032 gives about 5,800). */
#define SCALE_FRACTION 0.07f
#define NRUNGS 4
#define TARGET_RUNG 2

/* ---- timing ---------------------------------------------------------------- */

/* The source of lapped_create and lapped_render: one patch. */
static lapped_source one_patch(const lapped_image *patch)
{
    lapped_source src;
    src.patches = patch;
    src.npatches = 1;
    src.values = NULL;
    return src;
}

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
    lapped_source src = one_patch(j->patch);
    lapped_error err;
    lapped_texture_free(&j->t);
    if (lapped_create(j->mesh, &src, &j->opt, &j->t, &err)) {
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
    lapped_source src = one_patch(j->patch);
    lapped_image pic;
    lapped_error err;
    if (lapped_render(j->mesh, j->t, &src, &j->ro, &pic, &err)) {
        printf("lapped_render failed: %s\n", err.message);
        j->fail = 1;
    }
    lapped_image_free(&pic);
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

/* Rows of the summary: the first rung (the paper's mesh size) and the
 * target rung, with the paper's figure (§5). */
static void summary_rows(const lapped_mesh *mesh, const int *npastes, const bench_stat *s, const double *cpu,
                         int builtin)
{
    static const int rung[2] = {0, TARGET_RUNG};
    static const char *const paper[2] = {"20 s - 6 min for meshes of ~5,000 faces (733 MHz Pentium III, 2000)", "-"};
    char task[200], fig[80], t0[32], t1[32], sp[80];
    int k;
    for (k = 0; k < 2; k++) {
        const bench_stat *q = &s[rung[k]];
        snprintf(task, sizeof task, "lapped_create, %s %d triangles, %d pastes", builtin ? "built-in bumpy" : "mushroom",
                 mesh[rung[k]].nfaces, npastes[rung[k]]);
        snprintf(fig, sizeof fig, "%s (cpu %s)", bench_fmt_time(q->median, t0, sizeof t0),
                 bench_fmt_time(cpu[rung[k]], t1, sizeof t1));
        snprintf(sp, sizeof sp, "%d runs; %s..%s", q->runs, bench_fmt_time(q->min, t0, sizeof t0),
                 bench_fmt_time(q->max, t1, sizeof t1));
        bench_row(task, fig, "-", "no peer implements lapped textures", NULL, paper[k], sp, NULL);
    }
}

/* ---- 4. the peer: the same pastes composited by Mesa's llvmpipe -------------- */

#ifdef BENCH_OSMESA
typedef struct gl_lapped {
    gl_peer g;
    gl_mesh mesh;
    GLuint tex;
    int *first, *count, n; /* index range of each paste; [0] is the base pass */
    float bg[3];
} gl_lapped;

/* The mesh (base pass) and every paste in GL buffers, the patch as a
 * texture, lapped_render's camera and lighting; 0 on success. */
static int gl_lapped_setup(gl_lapped *L, const lapped_mesh *mesh, const lapped_texture *t, const lapped_image *patch,
                           int size)
{
    int w = size, h = size, ss = 1, p, i, k, *tris;
    float vd[3] = {0, 0, 0}, up[3] = {0, 0, 0}, *normals = (float *)malloc(sizeof(float) * 3 * (size_t)mesh->nverts);
    pw_image pimg = lapped__pw_image(patch);
    pw_camera cam;
    pw_draw d;
    memset(L, 0, sizeof *L);
    pw_view_defaults(&w, &h, &ss, vd, up, L->bg); /* lapped_render's defaults */
    cam = pw_camera_frame(mesh->positions, mesh->nverts, vd, up, 35.0f, (float)w / (float)h);
    tris = (int *)malloc(sizeof(int) * 3 * (size_t)mesh->nfaces);
    L->first = (int *)malloc(sizeof(int) * ((size_t)t->npastes + 1));
    L->count = (int *)malloc(sizeof(int) * ((size_t)t->npastes + 1));
    if (!normals || !tris || !L->first || !L->count || gl_peer_init(&L->g, w, h)) return free(normals), free(tris), 1;
    for (i = 0; i < mesh->nfaces; i++) /* the ladder's faces are triangles */
        for (k = 0; k < 3; k++) tris[3 * i + k] = mesh->face_verts[mesh->face_start[i] + k];
    memset(&d, 0, sizeof d);
    d.positions = mesh->positions, d.nv = mesh->nverts, d.tris = tris, d.ntris = mesh->nfaces;
    pw__smooth_normals(&d, normals); /* as lapped_render: once, from the whole mesh */
    L->first[0] = gl_mesh_add(&L->mesh, mesh->positions, normals, tris, mesh->nfaces, NULL);
    L->count[0] = 3 * mesh->nfaces;
    for (p = 0; p < t->npastes && L->first[p] >= 0; p++) {
        const lapped_paste *q = &t->pastes[p];
        for (i = 0; i < q->nfaces; i++)
            for (k = 0; k < 3; k++) tris[3 * i + k] = mesh->face_verts[mesh->face_start[q->faces[i]] + k];
        L->first[p + 1] = gl_mesh_add(&L->mesh, mesh->positions, normals, tris, q->nfaces, q->uvs);
        L->count[p + 1] = 3 * q->nfaces;
    }
    L->n = p + 1;
    free(normals);
    free(tris);
    if (L->first[L->n - 1] < 0 || L->n != t->npastes + 1) return 1;
    gl_mesh_upload(&L->mesh);
    L->tex = gl_peer_texture(&pimg, 1);
    gl_peer_camera(&L->g, &cam);
    return !L->tex || glGetError() != GL_NO_ERROR;
}

static void gl_lapped_free(gl_lapped *L)
{
    gl_peer_free(&L->g);
    free(L->first);
    free(L->count);
}

/* One frame: the grey base pass (lapped_render's colour and ambient), then
 * each paste blended over it in order. */
static void gl_lapped_frame(void *arg)
{
    static const float grey[4] = {0.5f, 0.5f, 0.5f, 1.0f}, white[4] = {1.0f, 1.0f, 1.0f, 1.0f};
    gl_lapped *L = (gl_lapped *)arg;
    int p;
    gl_peer_begin(&L->g, 1, L->bg);
    gl_peer_draw(&L->g, L->first[0], L->count[0], 0, grey, 0.3f, 0);
    for (p = 1; p < L->n; p++)
        if (L->count[p]) gl_peer_draw(&L->g, L->first[p], L->count[p], L->tex, white, 0.3f, 1);
    gl_peer_end(&L->g, 1);
}

static void pw_lapped_frame(void *arg) { run_render(arg); }
#endif

/* Section 4: lapped_render against llvmpipe compositing the same pastes. */
static void peer_compositing(render_job *rj, const lapped_texture *t, long drawn)
{
    char task[200];
    snprintf(task, sizeof task, "composite a lapped texture (%d pastes, %ld paste triangles over %d) at %dx%d",
             t->npastes, drawn, rj->mesh->nfaces, rj->ro.width, rj->ro.height);
#ifdef BENCH_OSMESA
    {
        gl_lapped L;
        bench_multi m;
        void (*fn[2])(void *) = {pw_lapped_frame, gl_lapped_frame};
        void *arg[2];
        char path[256];
        if (bench_peer_disabled("osmesa")) {
            bench_peer("OSMesa", "skipped: disabled by BENCH_NO_PEERS");
            return;
        }
        if (gl_lapped_setup(&L, rj->mesh, t, rj->patch, rj->ro.width)) {
            printf("OSMesa setup failed\n");
            bench_peer("OSMesa", "skipped: context or shader setup failed");
            return;
        }
        bench_peer("OSMesa", L.g.renderer);
        rj->t = t;
        arg[0] = rj, arg[1] = &L;
        bench_interleave(&m, fn, arg, 2, 5, 1);
        printf("peer: %s (LP_NUM_THREADS=%d), base pass + one blended draw per paste:\n", L.g.renderer, L.g.threads);
        bench_report("  patchwork lapped_render", bench_multi_stat(&m, 0, NULL), 0, "");
        bench_report("  OSMesa llvmpipe, same pastes", bench_multi_stat(&m, 1, NULL), 0, "");
        bench_row_pair(task, &m, 1, "Mesa llvmpipe (OSMesa), 1 thread", "\"display in real time\" (GeForce, 2000)",
                       "batched shading, 8-bit texels and bands that skip the pastes they do not reach (1.59 -> "
                       "1.28, 2026-12-03); on one thread the frame is drawn in 4 bands (a quarter of the frame's "
                       "samples at a time), so the base pass walks the mesh 4 times (44 of 143 ms of CPU); perf "
                       "puts about 45% in shading (texel fetch and filter, mip level, lighting, blending into float "
                       "RGBA), where llvmpipe runs JIT-compiled SIMD code over 4x4 pixel blocks of 8-bit colour");
        snprintf(path, sizeof path, "%s/lapped-gl.ppm", bench_data_dir());
        gl_peer_save_ppm(&L.g, path);
        {
            lapped_image pic;
            lapped_source src = one_patch(rj->patch);
            lapped_error err;
            snprintf(path, sizeof path, "%s/lapped-pw.png", bench_data_dir());
            if (lapped_render(rj->mesh, t, &src, &rj->ro, &pic, &err) == LAPPED_OK) {
                pw_image im = lapped__pw_image(&pic);
                printf("  the two pictures differ by %.2f/255 on average\n", gl_peer_diff(&L.g, &im));
                lapped_save_image(path, &pic, &err);
                lapped_image_free(&pic);
            }
        }
        gl_lapped_free(&L);
    }
#else
    {
        char a[32];
        bench_stat s;
        rj->t = t;
        s = bench_time(run_render, rj, 3);
        bench_peer("OSMesa", "skipped: libosmesa6-dev not found when bench_lapped was built");
        bench_row(task, bench_fmt_time(s.median, a, sizeof a), "skipped", "OSMesa (libosmesa6-dev) not found",
                  NULL, "\"display in real time\" (GeForce, 2000)", NULL, NULL);
    }
#endif
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
        if (lapped_builtin_exemplar("scales", 128, &opt, &texture, &err)) {
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
    { /* the built-in mesh is smaller: subdivided up to the first rung */
        bench_mesh base, rung[NRUNGS];
        BENCH_MESH_COPY(base, mesh[0]);
        if (bench_ladder(&base, rung, NRUNGS, 4500)) return printf("subdivision failed\n"), 1;
        for (i = 0; i < NRUNGS; i++) BENCH_MESH_COPY(mesh[i], rung[i]);
    }
    diag = bench_bbox_diagonal(mesh[0].positions, mesh[0].nverts);
    opt.field = LAPPED_FIELD_UP;
    opt.scale = frac * diag;
    printf("mesh: %s (%d triangles), 1-to-4 midpoint subdivision per rung%s\n",
           builtin_mesh ? "built-in \"bumpy\"" : MESH_FILE, mesh[0].nfaces,
           builtin_mesh ? " [data/ absent: run `make data` for the real mesh]" : "");
    printf("patch: %s (%dx%d, %s alpha), field UP, scale %.4f x bbox diagonal = %.5g mesh units, "
           "seed 0\n",
           builtin_tex ? "built-in \"scales\" 128 px" : TEXTURE_FILE, patch.width, patch.height,
           texture.channels % 2 == 0 ? "the image's" : "splotch", frac,
           opt.scale);
    printf("paper: 20 s to 6 min for ~5,000-face meshes on a 733 MHz Pentium III\n\n");

    printf("lapped_create, one core:\n");
    printf("%9s %7s %5s %23s %6s %9s %11s %10s %7s %5s %7s\n", "triangles", "pastes", "runs",
           "median (min..max) s", "cpu s", "pastes/s", "triangles/s", "tris/paste", "layers", "hard", "wall s");
    cj.patch = &patch;
    cj.opt = opt;
    for (i = 0; i < NRUNGS; i++) {
        double r0 = bench_now();
        cj.mesh = &mesh[i];
        s[i] = bench_time_cpu(run_create, &cj, runs[i], i < 2, &cpu[i]);
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
    summary_rows(mesh, npastes, s, cpu, builtin_mesh);
    bench_growth("lapped_create", slope, "triangles, 4 rungs 4.6K..295K (mushroom ladder, ~1,200 pastes each)", NULL);

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
        rs_bare = bench_time_cpu(run_render, &rj, 7, 1, &rc_bare);
        rj.t = &one;
        rs_one = bench_time_cpu(run_render, &rj, 7, 1, &rc_one);
        rj.t = &full;
        rs_full = bench_time_cpu(run_render, &rj, 5, 1, &rc_full);
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
        peer_compositing(&rj, &full, drawn);
        printf("\n");
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
