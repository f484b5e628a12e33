/* bench_render: the software renderer on a 100K-triangle textured torus at
 * 1024x1024 with 2x2 supersampling and trilinear filtering: one opaque
 * frame (clear, draw, resolve), and the lapped-texture runtime path (10
 * blended passes over the same surface, each with its own uvs and an RGBA
 * patch, depth-tested LEQUAL against the opaque pass). */
#include "bench.h"
#include "../src/common/render.h"

#define NU 250 /* around the ring */
#define NV 200 /* around the tube: 2 * NU * NV = 100000 triangles */

typedef struct scene {
    float *pos, *uv, *puv;
    int *tri;
    int nv, nt;
    pw_texture tex, patch;
    pw_camera cam;
    pw_fb fb;
    pw_image out;
} scene;

/* Procedural texture: checker with hashed per-texel noise (deterministic). */
static void make_texture(pw_image *img, int n, int alpha_disc)
{
    int x, y, k;
    pw_image_alloc(NULL, img, n, n, 4, NULL);
    for (y = 0; y < n; y++)
        for (x = 0; x < n; x++) {
            float *p = img->px + ((size_t)y * n + x) * 4;
            unsigned h = (unsigned)(x * 73856093u) ^ (unsigned)(y * 19349663u);
            float noise = (float)((h * 2654435761u) >> 24) / 255.0f;
            int c = ((x / 32) + (y / 32)) & 1;
            float dx = (x + 0.5f) / n - 0.5f, dy = (y + 0.5f) / n - 0.5f;
            for (k = 0; k < 3; k++) p[k] = (c ? 0.8f : 0.25f) + 0.15f * noise * (k + 1) / 3;
            p[3] = alpha_disc ? pw_clampf((0.5f - sqrtf(dx * dx + dy * dy)) * 8.0f, 0.0f, 1.0f) : 1.0f;
        }
}

static void make_torus(scene *s)
{
    int i, j, k, c = 0;
    s->nv = NU * NV;
    s->nt = 2 * NU * NV;
    s->pos = (float *)malloc(sizeof(float) * 3 * s->nv);
    s->tri = (int *)malloc(sizeof(int) * 3 * s->nt);
    s->uv = (float *)malloc(sizeof(float) * 6 * s->nt);
    s->puv = (float *)malloc(sizeof(float) * 6 * s->nt);
    for (j = 0; j < NV; j++)
        for (i = 0; i < NU; i++) {
            double a = 6.283185307179586 * i / NU, b = 6.283185307179586 * j / NV;
            float *p = s->pos + 3 * (j * NU + i);
            p[0] = (float)((1.0 + 0.4 * cos(b)) * cos(a));
            p[1] = (float)(0.4 * sin(b));
            p[2] = (float)((1.0 + 0.4 * cos(b)) * sin(a));
        }
    for (j = 0; j < NV; j++)
        for (i = 0; i < NU; i++) {
            int i1 = (i + 1) % NU, j1 = (j + 1) % NV;
            int q[6] = {j * NU + i, j * NU + i1, j1 * NU + i1, j * NU + i, j1 * NU + i1, j1 * NU + i};
            int ij[6][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 0}, {1, 1}, {0, 1}};
            for (k = 0; k < 6; k++) {
                s->tri[c * 3 + k] = q[k];
                s->uv[c * 6 + 2 * k] = 8.0f * (float)(i + ij[k][0]) / NU;
                s->uv[c * 6 + 2 * k + 1] = 2.0f * (float)(j + ij[k][1]) / NV;
            }
            c += 2;
        }
}

static pw_draw base_draw(const scene *s)
{
    pw_draw d;
    memset(&d, 0, sizeof d);
    d.positions = s->pos;
    d.nv = s->nv;
    d.tris = s->tri;
    d.ntris = s->nt;
    d.uvs = s->uv;
    d.tex = &s->tex;
    d.lighting = PW_LIGHT_CAMERA;
    return d;
}

/* One opaque frame: clear, draw, resolve. */
static void frame(void *arg)
{
    scene *s = (scene *)arg;
    pw_draw d = base_draw(s);
    pw_fb_clear(&s->fb);
    pw_render_draw(&s->fb, &s->cam, &d, NULL);
    pw_image_free(NULL, &s->out);
    pw_fb_resolve(&s->fb, &s->out, 3, NULL);
}

/* The draw alone (into an already drawn framebuffer: the depth test then
 * rejects nothing that was visible, so the work is the same). */
static void draw_only(void *arg)
{
    scene *s = (scene *)arg;
    pw_draw d = base_draw(s);
    d.depth_test = PW_DEPTH_LEQUAL;
    pw_render_draw(&s->fb, &s->cam, &d, NULL);
}

/* Ten blended patch passes over the opaque surface (lapped textures). */
static void lapped_passes(void *arg)
{
    scene *s = (scene *)arg;
    pw_draw d = base_draw(s);
    int p, t;
    d.tex = &s->patch;
    d.uvs = s->puv;
    d.blend = PW_BLEND_OVER;
    d.depth_test = PW_DEPTH_LEQUAL;
    d.no_depth_write = 1;
    d.wrap = PW_WRAP_CLAMP;
    for (p = 0; p < 10; p++) {
        /* per-pass uvs: a shifted copy, as each patch has its own coordinates */
        for (t = 0; t < 6 * s->nt; t++) s->puv[t] = s->uv[t] * 0.7f - 0.3f * (float)(p % 4);
        pw_render_draw(&s->fb, &s->cam, &d, NULL);
    }
}

static void uv_update_only(void *arg)
{
    scene *s = (scene *)arg;
    int p, t;
    for (p = 0; p < 10; p++)
        for (t = 0; t < 6 * s->nt; t++) s->puv[t] = s->uv[t] * 0.7f - 0.3f * (float)(p % 4);
}

int main(void)
{
    static scene s;
    pw_image img, pimg;
    float vd[3] = {0.0f, -0.8f, -1.0f}, bg[4] = {0.1f, 0.1f, 0.12f, 1.0f};
    bench_stat st, su;
    make_torus(&s);
    make_texture(&img, 512, 0);
    make_texture(&pimg, 128, 1);
    if (pw_texture_create(NULL, &s.tex, &img, 0, NULL) ||
        pw_texture_create(NULL, &s.patch, &pimg, 0, NULL) ||
        pw_fb_create(NULL, &s.fb, 1024, 1024, 2, bg, NULL)) {
        printf("setup failed\n");
        return 1;
    }
    s.cam = pw_camera_frame(s.pos, s.nv, vd, NULL, 40.0f, 1.0f);
    printf("torus: %d triangles, %d vertices; 1024x1024, 2x2 samples, trilinear, lit\n", s.nt, s.nv);
    st = bench_time(frame, &s, 7);
    bench_report("render 100K tris 1024^2 ss2 frame", st, s.nt, "tri");
    st = bench_time(draw_only, &s, 7);
    bench_report("render 100K tris 1024^2 ss2 draw only", st, s.nt, "tri");
    frame(&s);
    st = bench_time(lapped_passes, &s, 5);
    su = bench_time(uv_update_only, &s, 5);
    st.median -= su.median;
    st.min -= su.median;
    st.max -= su.median;
    bench_report("render 10 blended passes (uv update excl.)", st, 10.0 * s.nt, "tri");
    st.median /= 10;
    st.min /= 10;
    st.max /= 10;
    bench_report("render one blended pass", st, s.nt, "tri");
    pw_image_free(NULL, &s.out);
    pw_fb_free(&s.fb);
    pw_texture_free(NULL, &s.tex);
    pw_texture_free(NULL, &s.patch);
    pw_image_free(NULL, &img);
    pw_image_free(NULL, &pimg);
    free(s.pos);
    free(s.tri);
    free(s.uv);
    free(s.puv);
    return 0;
}
