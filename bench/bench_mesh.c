/* bench_mesh: half-edge build and Catmull-Clark on 1M-quad meshes, and the
 * OBJ/PLY readers on the same data. Target: build > 5 M faces/s. */
#include "bench.h"
#include "../src/common/subdiv.h"

/* n x n quads; wrap = 1 closes it into a torus (still 1M faces for n = 1000). */
static pw_mesh make_quads(int n, int wrap)
{
    pw_mesh m;
    int i, j, w = wrap ? n : n + 1;
    pw_mesh_alloc(NULL, &m, w * w, n * n, 4 * n * n, 0, NULL);
    for (j = 0; j < w; j++)
        for (i = 0; i < w; i++) {
            float *p = m.pos + 3 * (j * w + i);
            double u = 6.283185307179586 * i / n, v = 6.283185307179586 * j / n;
            if (wrap) {
                double r = 2.0 + 0.5 * cos(v);
                p[0] = (float)(r * cos(u)), p[1] = (float)(r * sin(u)), p[2] = (float)(0.5 * sin(v));
            } else
                p[0] = (float)i, p[1] = (float)j, p[2] = 0.0f;
        }
    for (j = 0; j < n; j++)
        for (i = 0; i < n; i++) {
            int f = j * n + i, i1 = wrap ? (i + 1) % n : i + 1, j1 = wrap ? (j + 1) % n : j + 1;
            int *q = m.fv + 4 * f;
            q[0] = j * w + i, q[1] = j * w + i1, q[2] = j1 * w + i1, q[3] = j1 * w + i;
            m.fstart[f + 1] = 4 * f + 4;
        }
    return m;
}

typedef struct job {
    pw_mesh *m;
    pw_hmesh hm;
    pw_mesh out;
    pw_buf buf;
    int fail;
} job;

static void run_build(void *arg)
{
    job *j = (job *)arg;
    pw_err e;
    pw_err_clear(&e);
    if (pw_hmesh_from_mesh(NULL, j->m, &j->hm, &e)) j->fail = 1, printf("build failed: %s\n", e.msg);
    pw_hmesh_free(NULL, &j->hm);
}

static void run_cc(void *arg)
{
    job *j = (job *)arg;
    pw_err e;
    pw_err_clear(&e);
    if (pw_catmull_clark(NULL, &j->hm, j->m->pos, &j->out, &e)) j->fail = 1, printf("CC failed: %s\n", e.msg);
    pw_mesh_free(NULL, &j->out);
}

static void run_read(void *arg)
{
    job *j = (job *)arg;
    pw_err e;
    pw_err_clear(&e);
    if (pw_mesh_read_memory(NULL, j->buf.data, j->buf.size, "bench", &j->out, &e))
        j->fail = 1, printf("read failed: %s\n", e.msg);
    pw_mesh_free(NULL, &j->out);
}

static int bench_write(void *ctx, const void *data, size_t size) { return pw_buf_write(ctx, data, size); }

int main(void)
{
    int wrap;
    for (wrap = 0; wrap < 2; wrap++) {
        pw_mesh m = make_quads(1000, wrap);
        job j;
        pw_err e;
        char name[96];
        bench_stat s;
        memset(&j, 0, sizeof j);
        j.m = &m;
        snprintf(name, sizeof name, "hmesh build, 1M-quad %s", wrap ? "torus" : "grid");
        s = bench_time(run_build, &j, 7);
        bench_report(name, s, m.nf, " faces");
        pw_err_clear(&e);
        if (pw_hmesh_from_mesh(NULL, &m, &j.hm, &e)) return 1;
        snprintf(name, sizeof name, "Catmull-Clark, 1M-quad %s (4M out)", wrap ? "torus" : "grid");
        s = bench_time(run_cc, &j, 5);
        bench_report(name, s, 4.0 * m.nf, " out faces");
        pw_hmesh_free(NULL, &j.hm);
        if (wrap) {
            memset(&j.buf, 0, sizeof j.buf);
            pw_mesh_write_obj(&m, NULL, NULL, bench_write, &j.buf, &e);
            s = bench_time(run_read, &j, 3);
            bench_report("OBJ read, 1M-quad torus", s, m.nf, " faces");
            free(j.buf.data);
            memset(&j.buf, 0, sizeof j.buf);
            bench_write_ply(bench_write, &j.buf, m.nv, m.pos, m.nf, m.fstart, m.fv);
            s = bench_time(run_read, &j, 5);
            bench_report("binary PLY read, 1M-quad torus", s, m.nf, " faces");
            free(j.buf.data);
        }
        pw_mesh_free(NULL, &m);
        if (j.fail) return 1;
    }
    return 0;
}
