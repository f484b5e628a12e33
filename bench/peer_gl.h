/* peer_gl.h: Mesa's software rasterizer, llvmpipe through OSMesa (Debian:
 * libosmesa6-dev), as the peer of patchwork's renderer in bench_render and
 * bench_lapped. Compiled only when bench/probe.sh finds OSMesa (the
 * Makefile then defines BENCH_OSMESA and links -lOSMesa).
 *
 * What it draws is what pw_render_draw draws, the way a GL program would:
 * the mesh in a vertex and an index buffer (one vertex per distinct
 * position + texture coordinate pair, built once), the texture uploaded
 * once as premultiplied RGBA8 with a box-filtered mip chain, sampled
 * trilinearly; per-pixel Lambert + ambient lighting from a camera-space
 * light, two-sided, in a GLSL program; premultiplied "over" blending;
 * depth test LESS (LEQUAL without depth writes for passes over the
 * surface); the same perspective camera. A frame ends with glFinish (the
 * picture is then in the caller's memory); with samples = 4 it renders
 * into a 4x multisampled framebuffer resolved by a blit, the analogue of
 * patchwork's 2x2 supersampling.
 *
 * llvmpipe is multi-threaded: LP_NUM_THREADS (default 1 here, set before
 * the context is made; an LP_NUM_THREADS already in the environment wins)
 * decides, so that it draws on one core as patchwork does. */
#ifndef PW_BENCH_PEER_GL_H
#define PW_BENCH_PEER_GL_H

#define GL_GLEXT_PROTOTYPES
#include <GL/osmesa.h>
#include <GL/gl.h>
#include <GL/glext.h>

typedef struct gl_peer {
    OSMesaContext ctx;
    unsigned char *buf;
    int w, h, threads;
    GLuint prog, fbo, rb[2];
    GLint u_tex, u_use_tex, u_tint, u_light, u_ambient;
    char renderer[160];
} gl_peer;

/* Vertex and index buffers: interleaved position, normal, uv (8 floats). */
typedef struct gl_mesh {
    GLuint vbo, ibo;
    float *v;   /* while building */
    GLuint *ix; /* while building */
    int nv, ni, vcap, icap;
} gl_mesh;

static const char *const gl__vs =
    "#version 120\n"
    "varying vec3 n; varying vec2 uv;\n"
    "void main() { n = gl_NormalMatrix * gl_Normal; uv = gl_MultiTexCoord0.xy; gl_Position = ftransform(); }\n";
static const char *const gl__fs =
    "#version 120\n"
    "uniform sampler2D tex; uniform int use_tex; uniform vec4 tint; uniform vec3 light; uniform float ambient;\n"
    "varying vec3 n; varying vec2 uv;\n"
    "void main() {\n"
    "  vec3 m = gl_FrontFacing ? n : -n;\n"
    "  float d = dot(m, m) > 0.0 ? max(dot(normalize(m), light), 0.0) : 1.0;\n"
    "  vec4 c = tint;\n"
    "  if (use_tex != 0) c *= texture2D(tex, uv);\n"
    "  c.rgb *= ambient + (1.0 - ambient) * d;\n"
    "  gl_FragColor = c;\n"
    "}\n";

static GLuint gl__shader(GLenum kind, const char *src)
{
    GLuint s = glCreateShader(kind);
    GLint ok = 0;
    glShaderSource(s, 1, &src, NULL);
    glCompileShader(s);
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    return ok ? s : 0;
}

/* A w x h RGBA8 context with a 24-bit depth buffer and the shading program,
 * plus a 4x multisampled framebuffer of the same size. Returns 0 on success. */
static int gl_peer_init(gl_peer *g, int w, int h)
{
    GLuint vs, fs;
    GLint ok = 0;
    const char *t;
    memset(g, 0, sizeof *g);
    setenv("LP_NUM_THREADS", "1", 0);
    t = getenv("LP_NUM_THREADS");
    g->threads = t ? atoi(t) : 0;
    g->w = w, g->h = h;
    g->buf = (unsigned char *)malloc((size_t)w * h * 4);
    g->ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, NULL);
    if (!g->buf || !g->ctx || !OSMesaMakeCurrent(g->ctx, g->buf, GL_UNSIGNED_BYTE, w, h)) return 1;
    snprintf(g->renderer, sizeof g->renderer, "%s, %s", (const char *)glGetString(GL_RENDERER),
             (const char *)glGetString(GL_VERSION));
    vs = gl__shader(GL_VERTEX_SHADER, gl__vs);
    fs = gl__shader(GL_FRAGMENT_SHADER, gl__fs);
    if (!vs || !fs) return 1;
    g->prog = glCreateProgram();
    glAttachShader(g->prog, vs);
    glAttachShader(g->prog, fs);
    glLinkProgram(g->prog);
    glGetProgramiv(g->prog, GL_LINK_STATUS, &ok);
    if (!ok) return 1;
    g->u_tex = glGetUniformLocation(g->prog, "tex");
    g->u_use_tex = glGetUniformLocation(g->prog, "use_tex");
    g->u_tint = glGetUniformLocation(g->prog, "tint");
    g->u_light = glGetUniformLocation(g->prog, "light");
    g->u_ambient = glGetUniformLocation(g->prog, "ambient");
    glGenFramebuffers(1, &g->fbo);
    glGenRenderbuffers(2, g->rb);
    glBindRenderbuffer(GL_RENDERBUFFER, g->rb[0]);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, 4, GL_RGBA8, w, h);
    glBindRenderbuffer(GL_RENDERBUFFER, g->rb[1]);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, 4, GL_DEPTH_COMPONENT24, w, h);
    glBindFramebuffer(GL_FRAMEBUFFER, g->fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, g->rb[0]);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, g->rb[1]);
    ok = glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glUseProgram(g->prog);
    glUniform1i(g->u_tex, 0);
    glEnable(GL_DEPTH_TEST);
    return !ok || glGetError() != GL_NO_ERROR;
}

static void gl_peer_free(gl_peer *g)
{
    if (g->ctx) OSMesaDestroyContext(g->ctx);
    free(g->buf);
    memset(g, 0, sizeof *g);
}

/* Projection and view of cam (pw__camera_basis's right/up/forward frame). */
static void gl_peer_camera(const gl_peer *g, const pw_camera *cam)
{
    double f[3], up[3], r[3], u[3], e[3], m[16], t = pw__tan_deg(0.5 * cam->fovy_deg), a = (double)g->w / g->h;
    double zn = cam->znear, zf = cam->zfar;
    int k;
    for (k = 0; k < 3; k++) f[k] = (double)cam->target[k] - cam->eye[k], up[k] = cam->up[k], e[k] = cam->eye[k];
    pw_norm3(f);
    pw_cross3(f, up, r);
    pw_norm3(r);
    pw_cross3(r, f, u);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glFrustum(-zn * t * a, zn * t * a, -zn * t, zn * t, zn, zf);
    memset(m, 0, sizeof m);
    for (k = 0; k < 3; k++) m[4 * k] = r[k], m[4 * k + 1] = u[k], m[4 * k + 2] = -f[k];
    m[12] = -pw_dot3(r, e);
    m[13] = -pw_dot3(u, e);
    m[14] = pw_dot3(f, e);
    m[15] = 1.0;
    glMatrixMode(GL_MODELVIEW);
    glLoadMatrixd(m);
}

/* img (RGBA floats, straight alpha, row 0 at the top) as a premultiplied
 * RGBA8 texture with its mip chain; clamp or repeat. */
static GLuint gl_peer_texture(const pw_image *img, int clamp)
{
    size_t n = (size_t)img->w * img->h, i;
    unsigned char *p = (unsigned char *)malloc(n * 4);
    GLuint t = 0;
    int y, k;
    if (!p || img->c != 4) return free(p), 0;
    for (y = 0; y < img->h; y++) /* GL's first row is the bottom one (v = 0) */
        for (i = 0; i < (size_t)img->w; i++) {
            const float *s = img->px + ((size_t)(img->h - 1 - y) * img->w + i) * 4;
            for (k = 0; k < 4; k++)
                p[((size_t)y * img->w + i) * 4 + k] =
                    (unsigned char)(pw_clampf(k < 3 ? s[k] * s[3] : s[3], 0.0f, 1.0f) * 255.0f + 0.5f);
        }
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, img->w, img->h, 0, GL_RGBA, GL_UNSIGNED_BYTE, p);
    glGenerateMipmap(GL_TEXTURE_2D);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, clamp ? GL_CLAMP_TO_EDGE : GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, clamp ? GL_CLAMP_TO_EDGE : GL_REPEAT);
    free(p);
    return t;
}

/* Appends triangles tris[0..nt) (vertex indices into pos/normals; uvs per
 * corner, nt*6, or NULL) to the buffers being built, one vertex per
 * distinct (vertex, uv) pair; returns the first index of the range (the
 * range has 3 nt indices), or -1 when out of memory. */
static int gl_mesh_add(gl_mesh *m, const float *pos, const float *normals, const int *tris, int nt, const float *uvs)
{
    size_t cap = 1, mask, h;
    int *sv, *out, c, first = m->ni;
    while (cap < (size_t)nt * 6) cap <<= 1;
    mask = cap - 1;
    sv = (int *)malloc(cap * sizeof *sv);  /* per slot: the vertex, -1 when empty */
    out = (int *)malloc(cap * sizeof *out); /* per slot: its index in the buffers */
    if (m->nv + 3 * nt > m->vcap) m->vcap = 2 * (m->nv + 3 * nt), m->v = (float *)realloc(m->v, sizeof(float) * 8 * m->vcap);
    if (m->ni + 3 * nt > m->icap) m->icap = 2 * (m->ni + 3 * nt), m->ix = (GLuint *)realloc(m->ix, sizeof(GLuint) * m->icap);
    if (!sv || !out || !m->v || !m->ix) return free(sv), free(out), -1;
    memset(sv, 0xff, cap * sizeof *sv);
    for (c = 0; c < 3 * nt; c++) {
        int vi = tris[c];
        float uv[2];
        unsigned bits[2];
        uv[0] = uvs ? uvs[2 * c] : 0.0f, uv[1] = uvs ? uvs[2 * c + 1] : 0.0f;
        memcpy(bits, uv, sizeof bits);
        h = (size_t)(((unsigned long long)(unsigned)vi << 32 ^ bits[0] * 2654435761u ^ bits[1]) *
                     0x9E3779B97F4A7C15ull >> 17) & mask;
        for (; sv[h] != -1; h = (h + 1) & mask)
            if (sv[h] == vi && !memcmp(m->v + 8 * out[h] + 6, uv, sizeof uv)) break;
        if (sv[h] == -1) {
            float *v = m->v + 8 * m->nv;
            memcpy(v, pos + 3 * vi, 12);
            memcpy(v + 3, normals + 3 * vi, 12);
            memcpy(v + 6, uv, 8);
            sv[h] = vi;
            out[h] = m->nv++;
        }
        m->ix[m->ni++] = (GLuint)out[h];
    }
    free(sv);
    free(out);
    return first;
}

/* Uploads what gl_mesh_add collected; the CPU copies are freed. */
static void gl_mesh_upload(gl_mesh *m)
{
    glGenBuffers(1, &m->vbo);
    glGenBuffers(1, &m->ibo);
    glBindBuffer(GL_ARRAY_BUFFER, m->vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)sizeof(float) * 8 * m->nv, m->v, GL_STATIC_DRAW);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m->ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)sizeof(GLuint) * m->ni, m->ix, GL_STATIC_DRAW);
    glEnableClientState(GL_VERTEX_ARRAY);
    glEnableClientState(GL_NORMAL_ARRAY);
    glEnableClientState(GL_TEXTURE_COORD_ARRAY);
    glVertexPointer(3, GL_FLOAT, 32, (const void *)0);
    glNormalPointer(GL_FLOAT, 32, (const void *)12);
    glTexCoordPointer(2, GL_FLOAT, 32, (const void *)24);
    free(m->v);
    free(m->ix);
    m->v = NULL, m->ix = NULL;
}

/* Starts a frame: multisampled (samples 4) or not, cleared to bg. */
static void gl_peer_begin(const gl_peer *g, int samples, const float bg[3])
{
    glBindFramebuffer(GL_FRAMEBUFFER, samples > 1 ? g->fbo : 0);
    glViewport(0, 0, g->w, g->h);
    glClearColor(bg[0], bg[1], bg[2], 1.0f);
    glDepthMask(GL_TRUE);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

/* Draws `count` indices from `first`: tex 0 for the tint alone; blend 1 for
 * a premultiplied "over" pass tested LEQUAL without depth writes. */
static void gl_peer_draw(const gl_peer *g, int first, int count, GLuint tex, const float tint[4], float ambient,
                         int blend)
{
    static const float light[3] = {-0.3f, 0.4f, 1.0f}; /* pw_render_draw's default, camera space */
    float l = 1.0f / sqrtf(light[0] * light[0] + light[1] * light[1] + light[2] * light[2]);
    glUniform1i(g->u_use_tex, tex != 0);
    glUniform4f(g->u_tint, tint[0] * tint[3], tint[1] * tint[3], tint[2] * tint[3], tint[3]);
    glUniform3f(g->u_light, light[0] * l, light[1] * l, light[2] * l);
    glUniform1f(g->u_ambient, ambient);
    glBindTexture(GL_TEXTURE_2D, tex);
    if (blend) {
        glEnable(GL_BLEND);
        glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
        glDepthFunc(GL_LEQUAL);
        glDepthMask(GL_FALSE);
    } else {
        glDisable(GL_BLEND);
        glDepthFunc(GL_LESS);
        glDepthMask(GL_TRUE);
    }
    glDrawElements(GL_TRIANGLES, count, GL_UNSIGNED_INT, (const void *)(sizeof(GLuint) * (size_t)first));
}

/* Ends a frame: resolves the multisampled one, waits for the picture. */
static void gl_peer_end(const gl_peer *g, int samples)
{
    if (samples > 1) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, g->fbo);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
        glBlitFramebuffer(0, 0, g->w, g->h, 0, 0, g->w, g->h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }
    glFinish();
}

/* Mean |difference| of the last picture from img (RGB floats, row 0 at the
 * top, the same size), in 1/255 steps: how alike the two renderers drew. */
static double gl_peer_diff(const gl_peer *g, const pw_image *img)
{
    double d = 0.0;
    int x, y, k;
    if (img->w != g->w || img->h != g->h || img->c < 3) return -1.0;
    for (y = 0; y < g->h; y++)
        for (x = 0; x < g->w; x++)
            for (k = 0; k < 3; k++) {
                double a = g->buf[((size_t)(g->h - 1 - y) * g->w + x) * 4 + k];
                double b = pw_clampf(img->px[((size_t)y * img->w + x) * img->c + k], 0.0f, 1.0f) * 255.0;
                d += fabs(a - b);
            }
    return d / (3.0 * g->w * g->h);
}

/* The last picture as a binary PPM (to compare with patchwork's by eye). */
static int gl_peer_save_ppm(const gl_peer *g, const char *path)
{
    FILE *f = fopen(path, "wb");
    int y, x;
    if (!f) return 1;
    fprintf(f, "P6\n%d %d\n255\n", g->w, g->h);
    for (y = g->h - 1; y >= 0; y--)
        for (x = 0; x < g->w; x++) fwrite(g->buf + ((size_t)y * g->w + x) * 4, 1, 3, f);
    return fclose(f) != 0;
}

#endif
