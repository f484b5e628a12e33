/* bench_io: patchwork's mesh readers and PNG writer against the command-line
 * tools Debian ships for the same jobs:
 *   - read a large OBJ, and the same mesh as binary PLY: bench/meshinfo
 *     (patchwork's reader, prints the counts) against `assimp info FILE -r -s`
 *     (assimp-utils: Assimp's importer without post-processing, prints the
 *     counts); the mesh is CGAL's refined_elephant (88,928 triangles)
 *     subdivided twice, 1.42M triangles;
 *   - write a PNG: `patchwork convert IN.ppm OUT.png` against
 *     `pnmtopng IN.ppm > OUT.png` (netpbm) on GIMP's 1920x1080 splash
 *     screen (gimp-data), as RGB.
 * Fairness: both sides are whole commands, read the same file from the page
 * cache (a warm-up round first) and write to the same kind of place; each
 * is also run on a trivial input (one triangle, one pixel) in the same
 * round, and that start-up time (exec, dynamic linking, Assimp's importer
 * registry...) is subtracted round by round, so the figures are the work
 * that grows with the input. CPU times are the children's (getrusage).
 * A tool that is not installed is skipped and said so; BENCH_NO_PEERS
 * ("assimp", "pnmtopng", "all") skips them on purpose. */
#include "bench.h"
#include "../src/common/png.h"
#include "../src/common/mesh.h"
#include <spawn.h>
#include <fcntl.h>
#include <sys/wait.h>
#include <sys/resource.h>

extern char **environ;

#define ROUNDS 5     /* rounds for the meshes */
#define PNG_ROUNDS 3 /* the PNG rounds take seconds each */

/* What the profiles show where patchwork is not clearly faster (printed
 * only then). */
#define MESH_NOTE "no cause recorded: patchwork was the faster on the machine of bench/results.md"
#define PNG_NOTE "both spend most of the time in the LZ77 match search (perf: patchwork's pw__longest_match ~70%, " \
                 "zlib's longest_match ~60%) at comparable effort; the output sizes are in bench_io's output"

/* One command, run once per call; the children's CPU time of each call is
 * recorded (bench_interleave only sees the parent's). */
typedef struct cmd {
    const char *argv[8];
    char out[512]; /* its stdout goes here */
    double cpu[ROUNDS + 1]; /* per call: the warm-up, then the rounds */
    int calls, fail;
} cmd;

static double children_cpu(void)
{
    struct rusage u;
    getrusage(RUSAGE_CHILDREN, &u);
    return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

/* Runs argv with stdout to `out` (stderr too if `both`, else discarded): 0
 * if it exited 0, 1 if it failed, 2 if it could not be started. */
static int spawn2(const char *const *argv, const char *out, int both)
{
    posix_spawn_file_actions_t fa;
    pid_t pid;
    int st = 0, r;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, out, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (both) posix_spawn_file_actions_adddup2(&fa, 1, 2);
    else posix_spawn_file_actions_addopen(&fa, 2, "/dev/null", O_WRONLY, 0);
    r = posix_spawnp(&pid, argv[0], &fa, NULL, (char *const *)argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    if (r != 0) return 2;
    if (waitpid(pid, &st, 0) < 0) return 1;
    return !WIFEXITED(st) || WEXITSTATUS(st) != 0;
}

static int spawn(const char *const *argv, const char *out) { return spawn2(argv, out, 0); }

static void run_cmd(void *arg)
{
    cmd *c = (cmd *)arg;
    double c0 = children_cpu();
    c->fail |= spawn(c->argv, c->out) != 0;
    if (c->calls <= ROUNDS) c->cpu[c->calls] = children_cpu() - c0;
    c->calls++;
}

/* The first line of `path` containing `what`, into buf ("" if none). */
static const char *grep_line(const char *path, const char *what, char *buf, size_t size)
{
    FILE *f = fopen(path, "r");
    char line[512];
    buf[0] = '\0';
    while (f && fgets(line, sizeof line, f))
        if (strstr(line, what)) {
            line[strcspn(line, "\r\n")] = '\0';
            snprintf(buf, size, "%s", line + strspn(line, " \t"));
            break;
        }
    if (f) fclose(f);
    return buf;
}

static long file_size(const char *path)
{
    FILE *f = fopen(path, "rb");
    long n = -1;
    if (f && fseek(f, 0, SEEK_END) == 0) n = ftell(f);
    if (f) fclose(f);
    return n;
}

/* The peer `name`'s version (the line of `argv`'s output that holds
 * `what`), or NULL with the reason in *why when it cannot run. */
static const char *peer_version(const char *name, const char *const *argv, const char *what, char *buf,
                                size_t size, const char **why)
{
    char out[512];
    *why = "disabled by BENCH_NO_PEERS";
    if (bench_peer_disabled(name)) return NULL;
    snprintf(out, sizeof out, "%s/io-probe.txt", bench_data_dir());
    *why = "not installed";
    if (spawn2(argv, out, 1) == 2) return NULL;
    grep_line(out, what, buf, size);
    return buf[0] ? buf : name;
}

/* ---- inputs ------------------------------------------------------------------ */

static int fwrite_fn(void *ctx, const void *data, size_t size) { return fwrite(data, 1, size, (FILE *)ctx) != size; }

static int save_mesh(const char *path, const pw_mesh *m, int ply)
{
    FILE *f = fopen(path, "wb");
    pw_err e;
    int bad;
    pw_err_clear(&e);
    if (!f) return 1;
    bad = ply ? bench_write_ply(fwrite_fn, f, m->nv, m->pos, m->nf, m->fstart, m->fv)
              : pw_mesh_write_obj(m, NULL, NULL, fwrite_fn, f, &e) != PW_OK;
    return (fclose(f) != 0) | bad;
}

/* The big mesh (refined_elephant x16) and a one-triangle file, OBJ and PLY. */
static int make_meshes(const char *dir, int *nfaces)
{
    static const float tri_pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    static const int tri_start[2] = {0, 3}, tri_fv[3] = {0, 1, 2};
    pw_mesh m, t;
    pw_err e;
    bench_mesh b, r[3];
    char path[512];
    int i, bad = 0;
    pw_err_clear(&e);
    if (pw_mesh_load(NULL, "data/meshes/refined_elephant.off", &m, &e)) return printf("bench_io: %s\n", e.msg), 1;
    b.nverts = m.nv, b.positions = m.pos, b.nfaces = m.nf, b.face_start = m.fstart, b.face_verts = m.fv;
    if (bench_ladder(&b, r, 3, 0)) return 1;
    memset(&t, 0, sizeof t);
    m.nv = r[2].nverts, m.pos = r[2].positions, m.nf = r[2].nfaces, m.fstart = r[2].face_start, m.fv = r[2].face_verts;
    t.nv = 3, t.pos = (float *)tri_pos, t.nf = 1, t.fstart = (int *)tri_start, t.fv = (int *)tri_fv;
    for (i = 0; i < 4; i++) {
        snprintf(path, sizeof path, "%s/io-%s.%s", dir, i < 2 ? "big" : "tri", i % 2 ? "ply" : "obj");
        bad |= save_mesh(path, i < 2 ? &m : &t, i % 2);
    }
    *nfaces = m.nf;
    for (i = 0; i < 3; i++) bench_mesh_free(&r[i]);
    return bad;
}

/* GIMP's splash screen as an RGB PPM, and a one-pixel PPM. */
static int make_images(const char *dir, int *w, int *h)
{
    pw_image img, rgb, one;
    pw_err e;
    char path[512];
    int bad;
    pw_err_clear(&e);
    if (pw_image_load(NULL, "/usr/share/gimp/2.0/images/gimp-splash.png", &img, &e)) return 1;
    bad = pw_image_convert(NULL, &img, 3, &rgb, &e) != PW_OK;
    snprintf(path, sizeof path, "%s/io-splash.ppm", dir);
    if (!bad) bad = pw_image_save(path, &rgb, &e) != PW_OK;
    *w = img.w, *h = img.h;
    if (!bad) bad = pw_image_alloc(NULL, &one, 1, 1, 3, &e) != PW_OK;
    if (!bad) {
        one.px[0] = one.px[1] = one.px[2] = 0.5f;
        snprintf(path, sizeof path, "%s/io-1px.ppm", dir);
        bad = pw_image_save(path, &one, &e) != PW_OK;
        pw_image_free(NULL, &one);
    }
    pw_image_free(NULL, &img);
    if (!bad) pw_image_free(NULL, &rgb);
    return bad;
}

/* ---- measurement --------------------------------------------------------------- */

/* Copies the children's CPU times of the measured rounds into m (the
 * calls after the warm-up one). */
static void child_cpu(bench_multi *m, cmd *const *c, int n)
{
    int k, r;
    for (k = 0; k < n; k++)
        for (r = 0; r < m->runs; r++) m->c[k][r] = c[k]->cpu[r + 1];
}

/* Patchwork's and the peer's commands on the big and the trivial input,
 * interleaved; the row compares big minus trivial, round by round. Without
 * a peer (peer_big NULL) patchwork's figure alone, with `peer` saying why. */
static void compare(const char *task, cmd *pw_big, cmd *pw_triv, cmd *peer_big, cmd *peer_triv, const char *peer,
                    const char *note, int rounds)
{
    static const char *const who[4] = {"patchwork input  ", "peer input       ", "patchwork trivial",
                                       "peer trivial     "};
    cmd *c[4];
    void (*fn[4])(void *) = {run_cmd, run_cmd, run_cmd, run_cmd};
    void *arg[4];
    bench_multi m, net;
    int k, r, n = peer_big ? 4 : 2, h = n / 2;
    c[0] = pw_big, c[h] = pw_triv;
    if (peer_big) c[1] = peer_big, c[3] = peer_triv;
    for (k = 0; k < n; k++) arg[k] = c[k];
    bench_interleave(&m, fn, arg, n, rounds, 1);
    child_cpu(&m, c, n);
    printf("%s:\n", task);
    for (k = 0; k < n; k++) {
        double cpu;
        bench_stat st = bench_multi_stat(&m, k, &cpu);
        printf("  %s median %9.2f ms (%.2f..%.2f, %d rounds) cpu %8.2f ms%s  [%s]\n", who[peer_big ? k : 2 * k],
               st.median * 1e3, st.min * 1e3, st.max * 1e3, st.runs, cpu * 1e3, c[k]->fail ? " FAILED" : "",
               c[k]->argv[0]);
    }
    net.n = h, net.runs = m.runs;
    for (r = 0; r < m.runs; r++)
        for (k = 0; k < h; k++) {
            net.t[k][r] = m.t[k][r] - m.t[k + h][r];
            net.c[k][r] = m.c[k][r] - m.c[k + h][r];
        }
    if (pw_big->fail || (peer_big && peer_big->fail))
        bench_row(task, "failed", "failed", peer, NULL, NULL, NULL, "a command failed: see bench_io's output");
    else if (peer_big)
        bench_row_pair(task, &net, 1, peer, NULL, note);
    else {
        char a[80], t0[32], t1[32];
        double cpu;
        bench_stat st = bench_multi_stat(&net, 0, &cpu);
        snprintf(a, sizeof a, "%s (cpu %s)", bench_fmt_time(st.median, t0, sizeof t0), bench_fmt_time(cpu, t1, sizeof t1));
        bench_row(task, a, "skipped", peer, NULL, NULL, NULL, NULL);
    }
}

static void cmd_init(cmd *c, const char *out, const char *a0, const char *a1, const char *a2, const char *a3,
                     const char *a4)
{
    memset(c, 0, sizeof *c);
    c->argv[0] = a0, c->argv[1] = a1, c->argv[2] = a2, c->argv[3] = a3, c->argv[4] = a4;
    snprintf(c->out, sizeof c->out, "%s", out);
}

static void mesh_rows(const char *dir, const char *build, const char *assimp, const char *why, int nfaces)
{
    static const char *const ext[2] = {"obj", "ply"};
    char big[512], tri[512], info[512], out[512], task[200], v[128];
    int i;
    snprintf(info, sizeof info, "%s/bench/meshinfo", build);
    snprintf(out, sizeof out, "%s/io-out.txt", dir);
    for (i = 0; i < 2; i++) {
        cmd pb, pt, ab, at;
        snprintf(big, sizeof big, "%s/io-big.%s", dir, ext[i]);
        snprintf(tri, sizeof tri, "%s/io-tri.%s", dir, ext[i]);
        snprintf(task, sizeof task, "read a %.2fM-triangle %s (%.0f MB), whole command minus start-up", nfaces / 1e6,
                 i ? "binary PLY" : "OBJ", file_size(big) / 1e6);
        cmd_init(&pb, out, info, big, NULL, NULL, NULL);
        cmd_init(&pt, out, info, tri, NULL, NULL, NULL);
        if (!assimp) {
            compare(task, &pb, &pt, NULL, NULL, why, NULL, ROUNDS);
            continue;
        }
        cmd_init(&ab, out, "assimp", "info", big, "-r", "-s");
        cmd_init(&at, out, "assimp", "info", tri, "-r", "-s");
        compare(task, &pb, &pt, &ab, &at, assimp, MESH_NOTE, ROUNDS);
        spawn(ab.argv, out);
        printf("  assimp's own report of its last import: %s\n", grep_line(out, "import took", v, sizeof v));
    }
}

static void png_rows(const char *dir, const char *build, const char *pnmtopng, const char *why, int w, int h)
{
    char in[512], one[512], out_pw[512], out_nb[512], cli[512], task[200];
    cmd pb, pt, nb, nt;
    snprintf(in, sizeof in, "%s/io-splash.ppm", dir);
    snprintf(one, sizeof one, "%s/io-1px.ppm", dir);
    snprintf(out_pw, sizeof out_pw, "%s/io-out-pw.png", dir);
    snprintf(out_nb, sizeof out_nb, "%s/io-out-netpbm.png", dir);
    snprintf(cli, sizeof cli, "%s/patchwork", build);
    snprintf(task, sizeof task, "write a %dx%d RGB PNG from PPM, whole command minus start-up", w, h);
    cmd_init(&pb, "/dev/null", cli, "convert", in, out_pw, NULL);
    cmd_init(&pt, "/dev/null", cli, "convert", one, out_pw, NULL);
    if (!pnmtopng) {
        compare(task, &pb, &pt, NULL, NULL, why, NULL, PNG_ROUNDS);
        return;
    }
    cmd_init(&nb, out_nb, "pnmtopng", in, NULL, NULL, NULL);
    cmd_init(&nt, out_nb, "pnmtopng", one, NULL, NULL, NULL);
    compare(task, &pb, &pt, &nb, &nt, pnmtopng, PNG_NOTE, PNG_ROUNDS);
    spawn(pb.argv, "/dev/null"); /* the outputs of the big input, for their sizes */
    spawn(nb.argv, out_nb);
    printf("  output: patchwork %ld bytes, pnmtopng %ld bytes (input %ld bytes)\n", file_size(out_pw),
           file_size(out_nb), file_size(in));
}

int main(void)
{
    static const char *const assimp_v[] = {"assimp", "version", NULL};
    static const char *const netpbm_v[] = {"pnmtopng", "-version", NULL};
    const char *dir = bench_data_dir(), *build = getenv("BENCH_BUILD"), *assimp, *pnmtopng, *why;
    char va[128], vn[128], name_a[160], name_n[160], why_a[96], why_n[96];
    int nfaces = 0, w = 0, h = 0;
    double t0 = bench_now();
    if (!build || !*build) build = "build";
    assimp = peer_version("assimp", assimp_v, "Version", va, sizeof va, &why);
    if (assimp == va && !strncmp(va, "Version ", 8)) { /* "Version 5.2 -debug ...": "5.2" */
        memmove(va, va + 8, strlen(va + 8) + 1);
        va[strcspn(va, " (")] = '\0';
    }
    snprintf(name_a, sizeof name_a, "assimp info -r -s (Assimp %s)", assimp ? assimp : "");
    snprintf(why_a, sizeof why_a, "assimp (assimp-utils): %s", why);
    bench_peer("assimp (assimp-utils)", assimp ? name_a : why);
    pnmtopng = peer_version("pnmtopng", netpbm_v, "Netpbm Version", vn, sizeof vn, &why);
    snprintf(name_n, sizeof name_n, "pnmtopng (%s)", pnmtopng && strstr(pnmtopng, "Version: ") ?
             strstr(pnmtopng, "Version: ") + 9 : "netpbm");
    snprintf(why_n, sizeof why_n, "pnmtopng (netpbm): %s", why);
    bench_peer("pnmtopng (netpbm)", pnmtopng ? name_n : why);
    if (make_meshes(dir, &nfaces))
        bench_row("read a large OBJ and PLY", "skipped", "-", "-", "-", "-", "-",
                  "data/meshes/refined_elephant.off not found: run `make data`");
    else
        mesh_rows(dir, build, assimp ? name_a : NULL, why_a, nfaces);
    if (make_images(dir, &w, &h))
        bench_row("write a large PNG", "skipped", "-", "-", "-", "-", "-",
                  "/usr/share/gimp/2.0/images/gimp-splash.png not found (gimp-data)");
    else
        png_rows(dir, build, pnmtopng ? name_n : NULL, why_n, w, h);
    printf("whole bench: %.1f s\n", bench_now() - t0);
    return 0;
}
