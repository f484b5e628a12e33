/* render: a small deterministic software renderer for textured triangle meshes.
 *
 * Pieces:
 *   pw_camera    perspective camera (eye, target, up, vertical field of view,
 *                near and far distances); pw_camera_frame fits a mesh in view.
 *   pw_texture   an image as premultiplied 16-bit RGBA with a box-filtered mip
 *                chain (any size, optionally capped), sampled nearest,
 *                bilinear or trilinear, wrapping or clamping; the renderer
 *                filters an 8-bit copy unless the source has 16 bits.
 *   pw_fb        framebuffer: w x h pixels of ss x ss samples, float RGBA and
 *                float depth per sample; pw_fb_resolve box-filters it into a
 *                pw_image.
 *   pw_render_draw draws one triangle mesh (pw_draw) into a framebuffer.
 *   pw_render_frame renders a whole frame band by band (a band: a few rows
 *                of the frame, every draw clipped to them), on several
 *                threads when asked (pw_parallel of parallel.h: PW_THREADS
 *                or the caller's parallel-for), the same picture bit for bit.
 *
 * Conventions. Image rows go down (row 0 at the top); texture coordinate
 * v = 0 is the BOTTOM row of the texture image (OBJ/OpenGL). Triangles whose
 * vertices appear counter-clockwise on screen are front-facing. Colours are
 * stored premultiplied by alpha. Depth is stored as q = 1 / (distance along
 * the view axis): 0 is "nothing drawn", larger is nearer, and q is exactly
 * affine in screen space, which makes it cheap and precise to interpolate.
 *
 * Pipeline of a draw. Vertices are transformed once; each triangle gets
 * homogeneous screen-space planes (Olano & Greer 1997: the adjugate of the
 * matrix of its homogeneous vertices gives 1/w and every attribute divided
 * by w as affine functions of the screen position, so interpolation is
 * perspective-correct and the screen derivatives of the texture coordinates
 * are exact, per pixel). Triangles crossing the near plane are clipped in
 * homogeneous space; coverage comes from the exact fixed-point rasterizer of
 * raster.h on the sample grid, so meshes are watertight.
 *   Opaque draws (PW_BLEND_REPLACE) use a visibility buffer: the first phase
 *   only tests and writes depth and the triangle id of each sample; a second
 *   phase shades each pixel once per distinct visible triangle and writes
 *   the colour to that triangle's samples (the shading rate of multisample
 *   anti-aliasing), so hidden surfaces cost no texture lookups.
 *   Blended draws (PW_BLEND_OVER) shade immediately, in triangle order (the
 *   order matters for blending): per pixel, the samples the triangle covers
 *   and that pass the depth test are blended with one shaded colour.
 * Shading happens at the pixel centre when the triangle covers all samples of
 * the pixel, otherwise at the first covered sample; the mip level comes from
 * the pixel footprint. Pixels are shaded in batches of 64, each step of the
 * shading (perspective divide, mip level, lighting, texels and filter) over
 * the whole batch before the next, so that the processor overlaps pixels
 * (each pixel's colour is computed as if alone). Triangles a few samples
 * wide find their runs by testing the edges at each candidate sample
 * rather than with the rasterizer's row walker (the same samples).
 *
 * Draws that only test depth (no_depth_write, as the passes of lapped
 * textures) first check each triangle against a coarse depth (the farthest
 * stored depth of each 8x8-sample tile, rebuilt only after depth changed)
 * and skip triangles that are hidden everywhere under it.
 *
 * Memory: 24 bytes per sample held, i.e. 24 ss^2 bytes per pixel (96 at
 * ss = 2): 16 colour (premultiplied float RGBA, so that hundreds of blended
 * passes keep their precision), 4 depth, 4 visibility id. A framebuffer
 * holds a band of the frame or all of it; pw_render_frame keeps the bands
 * under way to a quarter of the frame (24 bytes per pixel of the frame at
 * ss = 2, plus 12 for an RGB picture). Draws add scratch kept in the
 * framebuffer for the next draw: 40 bytes per vertex (+12 with computed
 * normals), 80 bytes per triangle, and for blended draws 8 bytes per pixel
 * column plus 4 ss bytes per sample column and 4 bytes per 64 samples. A
 * texture holds 12 bytes per texel (16-bit premultiplied RGBA and its 8-bit
 * copy; 8 for 16-bit sources, which have no copy), times about 4/3 for the
 * mip chain.
 *
 * Determinism: fixed orders within a band, bands that share nothing but the
 * read-only inputs (every band sees every draw, and the sample grid, the
 * snapping and the triangle planes do not depend on the band), and no libm
 * call whose rounding varies across platforms on any path that reaches a
 * pixel (tan and log2 are computed here from + - * /; sqrt is exactly
 * rounded by IEEE 754). The same picture for any band size and thread count.
 *
 * Example: a textured, lit mesh to an RGB image.
 *
 *     pw_fb fb; pw_texture tex; pw_image out; pw_draw d; pw_camera cam;
 *     pw_fb_create(NULL, &fb, 800, 600, 2, NULL, &err);
 *     pw_texture_create(NULL, &tex, &img, 0, &err);
 *     cam = pw_camera_frame(pos, nv, NULL, NULL, 40.0f, 800.0f / 600.0f);
 *     memset(&d, 0, sizeof d);
 *     d.positions = pos; d.nv = nv; d.tris = tris; d.ntris = nt;
 *     d.uvs = uvs; d.tex = &tex; d.lighting = PW_LIGHT_CAMERA;
 *     pw_render_draw(&fb, &cam, &d, &err);
 *     pw_fb_resolve(&fb, &out, 3, &err);
 *
 * Lapped textures at run time: draw the mesh once opaque, then each patch
 * with its own uvs and RGBA texture, in order, with d.blend = PW_BLEND_OVER,
 * d.depth_test = PW_DEPTH_LEQUAL and d.no_depth_write = 1. */
#ifndef PW__RENDER_V1
#define PW__RENDER_V1

#include "raster.h"
#include "parallel.h"
#include "vec.h"
#include "image.h"

/* SSE2 (every x86-64) filters, blends and clamps the four channels of a
 * texel or a pixel at once, and finds the texture coordinates, mip levels,
 * lighting and texel addresses of four pixels at once, with the same float
 * operations in the same order as the portable C, so the pictures are the
 * same bit for bit; define PW_NO_SIMD to use the C. */
#if defined(__SSE2__) && !defined(PW_NO_SIMD)
#include <emmintrin.h>
#define PW__SSE2 1
#endif

enum { PW_FILTER_TRILINEAR = 0, PW_FILTER_BILINEAR = 1, PW_FILTER_NEAREST = 2 };
enum { PW_WRAP_REPEAT = 0, PW_WRAP_CLAMP = 1 };
enum { PW_BLEND_REPLACE = 0, PW_BLEND_OVER = 1 };
enum { PW_DEPTH_LESS = 0, PW_DEPTH_LEQUAL = 1, PW_DEPTH_ALWAYS = 2 };
enum { PW_LIGHT_NONE = 0, PW_LIGHT_CAMERA = 1, PW_LIGHT_WORLD = 2 };
enum { PW_CULL_NONE = 0, PW_CULL_BACK = 1, PW_CULL_FRONT = 2 };

#define PW_FB_MAX_SS 8         /* samples per pixel side */
#define PW_FB_NONE 0xFFFFFFFFu /* visibility id of an untouched sample */
#define PW_TEXTURE_MAX_LEVELS 32
#define PW_DEPTH_TOLERANCE 1e-4f /* default relative slack of PW_DEPTH_LEQUAL */

/* ---------------------------------------------------------------- camera */

typedef struct pw_camera {
    float eye[3], target[3], up[3]; /* world space; up need not be orthogonal */
    float fovy_deg;                 /* vertical field of view, in (0, 180) degrees */
    float znear, zfar;              /* clipping distances along the view axis, 0 < znear < zfar */
} pw_camera;

/* The camera set up for one draw, in double precision. Screen coordinates
 * are in samples (x right, y down); a vertex at view coordinates (xv, yv, w)
 * (w = distance along the view axis) has homogeneous screen coordinates
 * (cx w + fx xv, cy w - fy yv, w). */
typedef struct pw__view {
    double eye[3], r[3], u[3], f[3]; /* right, up, forward unit vectors */
    double fx, fy, cx, cy, znear, zfar;
} pw__view;

/* double to float without the undefined behaviour of converting a value
 * beyond the float range (absurd inputs): clamps to +-FLT_MAX. */
PW__DEF float pw__f(double x) { return x > FLT_MAX ? FLT_MAX : (x < -FLT_MAX ? -FLT_MAX : (float)x); }

/* tan of an angle in degrees, 0 < deg < 180, from the sine and cosine
 * series: the same bits on every platform, unlike libm's tan. */
PW__DEF double pw__tan_deg(double deg)
{
    double x = (deg > 90.0 ? 180.0 - deg : deg) * (3.14159265358979323846 / 180.0);
    double x2 = x * x, s = x, c = 1.0, ts = x, tc = 1.0;
    int i;
    for (i = 1; i < 16; i++) {
        ts *= -x2 / (double)((2 * i) * (2 * i + 1));
        tc *= -x2 / (double)((2 * i - 1) * (2 * i));
        s += ts;
        c += tc;
    }
    return deg > 90.0 ? -s / c : s / c;
}

/* Camera basis from eye, target and up; returns 0 if they are degenerate. */
PW__DEF int pw__camera_basis(const pw_camera *cam, pw__view *v)
{
    double up[3];
    int k;
    for (k = 0; k < 3; k++) {
        v->eye[k] = cam->eye[k];
        v->f[k] = (double)cam->target[k] - cam->eye[k];
        up[k] = cam->up[k];
    }
    if (!(pw_norm3(v->f) > 0.0) || !pw_is_finite(pw_dot3(v->f, v->f))) return 0;
    pw_cross3(v->f, up, v->r);
    if (!(pw_norm3(v->r) > 1e-9 * sqrt(pw_dot3(up, up)))) return 0;
    pw_cross3(v->r, v->f, v->u);
    return pw_is_finite(pw_dot3(v->r, v->r)) && pw_is_finite(pw_dot3(v->eye, v->eye));
}

/* Sets up the view for a sw x sh sample grid. */
PW__DEF int pw__view_init(pw__view *v, const pw_camera *cam, int sw, int sh, pw_err *e)
{
    double t;
    if (!(cam->fovy_deg > 0.0f && cam->fovy_deg < 180.0f))
        return pw_fail(e, PW_ERR_INVALID, "camera: field of view %g degrees outside (0, 180)", (double)cam->fovy_deg);
    if (!(cam->znear > 0.0f && cam->zfar > cam->znear) || !pw_is_finite(cam->zfar))
        return pw_fail(e, PW_ERR_INVALID, "camera: need 0 < znear < zfar (znear %g, zfar %g)", (double)cam->znear,
                       (double)cam->zfar);
    if (!pw__camera_basis(cam, v))
        return pw_fail(e, PW_ERR_INVALID,
                       "camera: eye, target and up must be finite, eye != target, up not along the view");
    t = pw__tan_deg(0.5 * cam->fovy_deg);
    v->fy = 0.5 * sh / t;
    v->fx = v->fy; /* square samples */
    v->cx = 0.5 * sw;
    v->cy = 0.5 * sh;
    v->znear = cam->znear;
    v->zfar = cam->zfar;
    return PW_OK;
}

/* Projects world point p for a w x h image: out = pixel x, pixel y (row 0 at
 * the top), distance along the view axis. Returns 1 if p is at least znear
 * in front of the camera (out[0..1] are then valid), 0 otherwise or if the
 * camera is invalid. */
PW__DEF int pw_camera_project(const pw_camera *cam, int w, int h, const float p[3], float out[3])
{
    pw__view v;
    double d[3], xv, yv, wv;
    int k;
    if (w <= 0 || h <= 0 || pw__view_init(&v, cam, w, h, NULL) != PW_OK) return 0;
    for (k = 0; k < 3; k++) d[k] = (double)p[k] - v.eye[k];
    xv = pw_dot3(d, v.r);
    yv = pw_dot3(d, v.u);
    wv = pw_dot3(d, v.f);
    out[2] = pw__f(wv);
    if (!(wv >= v.znear)) return 0;
    out[0] = pw__f(v.cx + v.fx * xv / wv);
    out[1] = pw__f(v.cy - v.fy * yv / wv);
    return 1;
}

/* Centre (of the bounding box) and radius (farthest vertex from it) of the
 * finite vertices of pos[nv*3]; radius 1 around the origin if there are none. */
PW__DEF void pw__bounding_sphere(const float *pos, int nv, double *c, double *r)
{
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    int i, k, n = 0;
    for (i = 0; i < nv; i++) {
        const float *p = pos + 3 * i;
        if (!pw_is_finite(p[0]) || !pw_is_finite(p[1]) || !pw_is_finite(p[2])) continue;
        for (k = 0; k < 3; k++) {
            if (!n || p[k] < lo[k]) lo[k] = p[k];
            if (!n || p[k] > hi[k]) hi[k] = p[k];
        }
        n++;
    }
    for (k = 0; k < 3; k++) c[k] = 0.5 * (lo[k] + hi[k]);
    *r = 0.0;
    for (i = 0; i < nv; i++) {
        const float *p = pos + 3 * i;
        double d[3];
        if (!pw_is_finite(p[0]) || !pw_is_finite(p[1]) || !pw_is_finite(p[2])) continue;
        for (k = 0; k < 3; k++) d[k] = p[k] - c[k];
        if (pw_dot3(d, d) > *r) *r = pw_dot3(d, d);
    }
    *r = sqrt(*r);
    if (!(*r > 0.0)) *r = n ? 1e-3 * (1.0 + sqrt(pw_dot3(c, c))) : 1.0;
}

/* The orthonormal basis pw_camera_frame measures the mesh in: right rt, up
 * up and view vd from the centre c, with the image centre at lateral offset
 * (ox, oy) from c (0 until the framing has found it). */
typedef struct pw__view_basis {
    double c[3], rt[3], up[3], vd[3];
    double ox, oy;
} pw__view_basis;

/* Where the finite vertices lie in view basis b: the lateral extent (lo, hi
 * in x and y) and the depth range along the view. */
PW__DEF void pw__view_extent(const float *pos, int nv, const pw__view_basis *b, double lo[3], double hi[3])
{
    const double *c = b->c, *rt = b->rt, *up = b->up, *vd = b->vd;
    int i, k, n = 0;
    for (k = 0; k < 3; k++) lo[k] = hi[k] = 0.0;
    for (i = 0; i < nv; i++) {
        const float *p = pos + 3 * i;
        double d[3], q[3];
        if (!pw_is_finite(p[0]) || !pw_is_finite(p[1]) || !pw_is_finite(p[2])) continue;
        for (k = 0; k < 3; k++) d[k] = p[k] - c[k];
        q[0] = pw_dot3(d, rt);
        q[1] = pw_dot3(d, up);
        q[2] = pw_dot3(d, vd);
        for (k = 0; k < 3; k++) {
            if (!n || q[k] < lo[k]) lo[k] = q[k];
            if (!n || q[k] > hi[k]) hi[k] = q[k];
        }
        n++;
    }
}

/* The range of projected tangents (x - ox)/(dist + z) of the vertices in
 * view basis b, in out[0..1] (x) and out[2..3] (y). */
PW__DEF void pw__projected_range(const float *pos, int nv, const pw__view_basis *b, double dist, double out[4])
{
    const double *c = b->c, *rt = b->rt, *up = b->up, *vd = b->vd;
    double ox = b->ox, oy = b->oy;
    int i, k, n = 0;
    for (k = 0; k < 4; k++) out[k] = 0.0;
    for (i = 0; i < nv; i++) {
        const float *p = pos + 3 * i;
        double d[3], w, q[2];
        if (!pw_is_finite(p[0]) || !pw_is_finite(p[1]) || !pw_is_finite(p[2])) continue;
        for (k = 0; k < 3; k++) d[k] = p[k] - c[k];
        w = dist + pw_dot3(d, vd);
        q[0] = (pw_dot3(d, rt) - ox) / w;
        q[1] = (pw_dot3(d, up) - oy) / w;
        for (k = 0; k < 2; k++) {
            if (!n || q[k] < out[2 * k]) out[2 * k] = q[k];
            if (!n || q[k] > out[2 * k + 1]) out[2 * k + 1] = q[k];
        }
        n++;
    }
}

/* The smallest distance from the framing centre at which every vertex
 * (lateral offset x, y from the image centre ox, oy; depth z toward the
 * far side) fits in half-angles with tangents tx, ty. */
PW__DEF double pw__fit_distance(const float *pos, int nv, const pw__view_basis *b, double tx, double ty)
{
    const double *c = b->c, *rt = b->rt, *up = b->up, *vd = b->vd;
    double ox = b->ox, oy = b->oy;
    double dist = 0.0;
    int i, k;
    for (i = 0; i < nv; i++) {
        const float *p = pos + 3 * i;
        double d[3], need;
        if (!pw_is_finite(p[0]) || !pw_is_finite(p[1]) || !pw_is_finite(p[2])) continue;
        for (k = 0; k < 3; k++) d[k] = p[k] - c[k];
        need = fabs(pw_dot3(d, rt) - ox) / tx - pw_dot3(d, vd);
        if (fabs(pw_dot3(d, up) - oy) / ty - pw_dot3(d, vd) > need)
            need = fabs(pw_dot3(d, up) - oy) / ty - pw_dot3(d, vd);
        if (need > dist) dist = need;
    }
    return dist;
}

/* A camera looking along view_dir (NULL: -z) with the given up (NULL: +y;
 * replaced if parallel to the view) that frames the mesh pos[nv*3]: the
 * image centre is the middle of the mesh's extent across the view, and the
 * camera is as close as it can be with every vertex inside the field of
 * view shrunk by 5% (vertical fovy_deg, horizontal from aspect = width /
 * height); near and far enclose the mesh. Invalid fovy (outside (0, 180))
 * becomes 45, invalid aspect 1. */
PW__DEF pw_camera pw_camera_frame(const float *pos, int nv, const float view_dir[3], const float up[3], float fovy_deg,
                                  float aspect)
{
    pw_camera cam;
    pw__view_basis B;
    double c[3], r, vd[3] = {0, 0, -1}, u[3] = {0, 1, 0}, x[3], y[3], lo[3], hi[3], t, tx, dist, ox, oy;
    int k;
    if (view_dir)
        for (k = 0; k < 3; k++) vd[k] = view_dir[k];
    if (!(pw_norm3(vd) > 0.0) || !pw_is_finite(vd[0] + vd[1] + vd[2])) {
        vd[0] = vd[1] = 0.0;
        vd[2] = -1.0;
    }
    if (up)
        for (k = 0; k < 3; k++) u[k] = up[k];
    pw_cross3(vd, u, x);
    if (!(pw_dot3(x, x) > 1e-12 * pw_dot3(u, u)) || !pw_is_finite(pw_dot3(u, u))) {
        u[0] = fabs(vd[1]) < 0.9 ? 0.0 : 1.0; /* any up not along the view */
        u[1] = fabs(vd[1]) < 0.9 ? 1.0 : 0.0;
        u[2] = 0.0;
        pw_cross3(vd, u, x);
    }
    pw_norm3(x);
    pw_cross3(x, vd, y); /* unit: vd and x are orthonormal */
    if (!(fovy_deg > 0.0f && fovy_deg < 180.0f)) fovy_deg = 45.0f;
    if (!(aspect > 0.0f) || !pw_is_finite(aspect)) aspect = 1.0f;
    pw__bounding_sphere(pos, pos ? nv : 0, c, &r);
    t = 0.95 * pw__tan_deg(0.5 * fovy_deg);
    tx = t * aspect;
    for (k = 0; k < 3; k++) {
        B.c[k] = c[k];
        B.rt[k] = x[k];
        B.up[k] = y[k];
        B.vd[k] = vd[k];
    }
    B.ox = B.oy = 0.0;
    pw__view_extent(pos, pos ? nv : 0, &B, lo, hi);
    B.ox = 0.5 * (lo[0] + hi[0]);
    B.oy = 0.5 * (lo[1] + hi[1]);
    for (k = 0; k < 4; k++) { /* centre the perspective image, not the orthographic one */
        double range[4];
        dist = pos ? pw__fit_distance(pos, nv, &B, tx, t) : 0.0;
        if (dist < -lo[2] + 0.05 * r) dist = -lo[2] + 0.05 * r; /* the eye stays outside */
        if (!pos || k == 3) break;
        pw__projected_range(pos, nv, &B, dist, range);
        B.ox += 0.5 * (range[0] + range[1]) * dist;
        B.oy += 0.5 * (range[2] + range[3]) * dist;
    }
    ox = B.ox;
    oy = B.oy;
    for (k = 0; k < 3; k++) {
        cam.target[k] = pw__f(c[k] + ox * x[k] + oy * y[k]);
        cam.eye[k] = pw__f(cam.target[k] - vd[k] * dist);
        cam.up[k] = (float)u[k];
    }
    cam.fovy_deg = fovy_deg;
    cam.znear = pw__f(0.9 * (dist + lo[2]));
    cam.zfar = pw__f(1.1 * (dist + hi[2]) + 1e-6 * r);
    return cam;
}

/* --------------------------------------------------------------- texture */

typedef struct pw_texture {
    int w, h;    /* level 0 size */
    int nlevels; /* levels built: 1 (no mipmaps) .. full chain down to 1x1 */
    int lw[PW_TEXTURE_MAX_LEVELS], lh[PW_TEXTURE_MAX_LEVELS];
    /* premultiplied RGBA in 16-bit fixed point (65535 = 1), row 0 = top
     * (v = 1). 16 bits keep 8- and 16-bit opaque sources exact and halve the
     * memory traffic of floats, which dominates the cost of texturing. */
    uint16_t *level[PW_TEXTURE_MAX_LEVELS];
    /* the same rounded to 8 bits (255 = 1), which the renderer filters
     * when the source is not a 16-bit image (bits != 16): half the bytes
     * and a short conversion per texel, and within half a unit of 8 bits.
     * NULL for 16-bit sources, which the renderer filters in 16 bits. */
    uint8_t *level8[PW_TEXTURE_MAX_LEVELS];
} pw_texture;

/* Area-weighted box filter of n samples (stride sst floats, 4 channels) down
 * to m <= n (stride dst): output i averages the input over [i n/m, (i+1) n/m),
 * which handles odd sizes exactly (no texel is dropped or counted twice). */
PW__DEF void pw__box_1d(const float *src, int n, ptrdiff_t sst, float *dst, int m, ptrdiff_t dstr)
{
    double scale = (double)n / m;
    int i, j, k;
    for (i = 0; i < m; i++) {
        double a = i * scale, b = (i + 1) * scale, acc[4] = {0, 0, 0, 0};
        int j0 = (int)a, j1 = (int)b;
        if (j1 < b) j1++;
        if (j1 > n) j1 = n;
        for (j = j0; j < j1; j++) {
            double wgt = (b < j + 1 ? b : j + 1) - (a > j ? a : j);
            for (k = 0; k < 4; k++) acc[k] += wgt * src[j * sst + k];
        }
        for (k = 0; k < 4; k++) dst[i * dstr + k] = (float)(acc[k] / scale);
    }
}

/* Box-filters level L of t, held as floats in src, into level L + 1 in dst:
 * horizontal pass into tmp (lw[L + 1] x lh[L]), then vertical. */
PW__DEF void pw__mip_down(const pw_texture *t, int L, const float *src, float *dst, float *tmp)
{
    int W = t->lw[L], H = t->lh[L], W2 = t->lw[L + 1], H2 = t->lh[L + 1];
    int y, x;
    for (y = 0; y < H; y++) pw__box_1d(src + (size_t)y * W * 4, W, 4, tmp + (size_t)y * W2 * 4, W2, 4);
    for (x = 0; x < W2; x++)
        pw__box_1d(tmp + (size_t)x * 4, H, (ptrdiff_t)W2 * 4, dst + (size_t)x * 4, H2, (ptrdiff_t)W2 * 4);
}

/* Converts any channel count to premultiplied float RGBA. */
PW__DEF void pw__tex_convert(const pw_image *img, float *out)
{
    size_t i, n = (size_t)img->w * img->h;
    for (i = 0; i < n; i++) {
        const float *p = img->px + i * img->c;
        float r = p[0], g = p[0], b = p[0], a = 1.0f;
        if (img->c >= 3) {
            g = p[1];
            b = p[2];
        }
        if (img->c == 2) a = p[1];
        if (img->c == 4) a = p[3];
        a = pw_clampf(a, 0.0f, 1.0f);
        out[4 * i] = r * a;
        out[4 * i + 1] = g * a;
        out[4 * i + 2] = b * a;
        out[4 * i + 3] = a;
    }
}

/* Float level to 16-bit and to 8-bit fixed point, clamped to [0, 1] (NaN
 * becomes 0). */
PW__DEF void pw__tex_quantise(const float *src, size_t n, uint16_t *dst, uint8_t *dst8)
{
    size_t i;
    for (i = 0; i < n; i++) {
        float v = src[i] > 0.0f ? (src[i] < 1.0f ? src[i] : 1.0f) : 0.0f;
        dst[i] = (uint16_t)(v * 65535.0f + 0.5f);
        if (dst8) dst8[i] = (uint8_t)(v * 255.0f + 0.5f);
    }
}

/* Level sizes: each halves the previous, rounding down, at least 1. */
PW__DEF void pw__tex_sizes(pw_texture *t, int max_levels)
{
    if (max_levels <= 0 || max_levels > PW_TEXTURE_MAX_LEVELS) max_levels = PW_TEXTURE_MAX_LEVELS;
    t->nlevels = 1;
    while (t->nlevels < max_levels && (t->lw[t->nlevels - 1] > 1 || t->lh[t->nlevels - 1] > 1)) {
        t->lw[t->nlevels] = t->lw[t->nlevels - 1] > 1 ? t->lw[t->nlevels - 1] / 2 : 1;
        t->lh[t->nlevels] = t->lh[t->nlevels - 1] > 1 ? t->lh[t->nlevels - 1] / 2 : 1;
        t->nlevels++;
    }
}

/* Builds a texture from img (1 gray, 2 gray+alpha, 3 RGB, 4 RGBA; values
 * clamped to [0, 1]) with a mip chain of at most max_levels levels (0: the
 * full chain down to 1x1; 1: no mipmaps, e.g. for atlases whose tiles must
 * not mix). Each level halves the size (rounding down, at least 1) with an
 * area-weighted box filter of premultiplied colour, computed in float from
 * the level above, so transparent texels do not bleed their colour. Free
 * with pw_texture_free. */
PW__DEF int pw_texture_create(const pw_alloc *a, pw_texture *t, const pw_image *img, int max_levels, pw_err *e)
{
    size_t total = 0, off = 0, n0;
    uint16_t *data;
    float *cur, *next = NULL, *tmp = NULL;
    int L;
    memset(t, 0, sizeof *t);
    if (!img || !img->px || img->w <= 0 || img->h <= 0 || img->c < 1 || img->c > 4)
        return pw_fail(e, PW_ERR_INVALID, "texture: invalid source image");
    t->w = t->lw[0] = img->w;
    t->h = t->lh[0] = img->h;
    pw__tex_sizes(t, max_levels);
    for (L = 0; L < t->nlevels; L++) total += (size_t)t->lw[L] * t->lh[L] * 4;
    n0 = (size_t)t->w * t->h * 4;
    /* 16-bit levels, then (not for 16-bit sources) 8-bit ones */
    data = (uint16_t *)pw_alloc_array(a, total, img->bits == 16 ? 2 : 3, "texture", e);
    cur = data ? (float *)pw_alloc_array(a, n0, sizeof(float), "texture scratch", e) : NULL;
    if (cur && t->nlevels > 1) {
        next = (float *)pw_alloc_array(a, n0 / 2 + 4, sizeof(float), "texture scratch", e);
        /* the horizontal pass holds lw[1] x h texels (for a 1-wide texture
         * that is the whole level, not half of it) */
        tmp = next ? (float *)pw_alloc_array(a, (size_t)t->lw[1] * t->h * 4 + 4, sizeof(float), "texture scratch", e)
                   : NULL;
    }
    if (!cur || (t->nlevels > 1 && !tmp)) {
        pw_free(a, data);
        pw_free(a, cur);
        pw_free(a, next);
        memset(t, 0, sizeof *t);
        return PW_ERR_NOMEM;
    }
    pw__tex_convert(img, cur);
    for (L = 0; L < t->nlevels; L++) {
        size_t n = (size_t)t->lw[L] * t->lh[L] * 4;
        t->level[L] = data + off;
        t->level8[L] = img->bits == 16 ? NULL : (uint8_t *)(data + total) + off;
        off += n;
        pw__tex_quantise(cur, n, t->level[L], t->level8[L]);
        if (L + 1 < t->nlevels) {
            float *sw;
            pw__mip_down(t, L, cur, next, tmp);
            sw = cur;
            cur = next;
            next = sw;
        }
    }
    pw_free(a, cur);
    pw_free(a, next);
    pw_free(a, tmp);
    return PW_OK;
}

/* Makes the outermost ring of texels of every level larger than min_size
 * in both directions transparent (premultiplied zero). Lapped textures
 * (Praun et al. 2000, §4) paste patches with clamped texture coordinates,
 * which repeat the border texels outside the patch: "the texture patch must
 * have a border of transparent pixels at all mipmap levels finer than
 * 2x2", so the levels are built and then cleared here (min_size = 2). */
PW__DEF void pw_texture_clear_border(pw_texture *t, int min_size)
{
    int L, x, y;
    for (L = 0; t && L < t->nlevels; L++) {
        int W = t->lw[L], H = t->lh[L];
        uint16_t *p = t->level[L];
        uint8_t *p8 = t->level8[L];
        if (W <= min_size || H <= min_size) continue;
        memset(p, 0, (size_t)W * 4 * sizeof(uint16_t));                           /* top row */
        memset(p + (size_t)(H - 1) * W * 4, 0, (size_t)W * 4 * sizeof(uint16_t)); /* bottom row */
        if (p8) {
            memset(p8, 0, (size_t)W * 4);
            memset(p8 + (size_t)(H - 1) * W * 4, 0, (size_t)W * 4);
        }
        for (y = 1; y < H - 1; y++)
            for (x = 0; x < 4; x++) {
                p[((size_t)y * W) * 4 + x] = 0;         /* left column */
                p[((size_t)y * W + W - 1) * 4 + x] = 0; /* right column */
                if (p8) p8[((size_t)y * W) * 4 + x] = p8[((size_t)y * W + W - 1) * 4 + x] = 0;
            }
    }
}

PW__DEF void pw_texture_free(const pw_alloc *a, pw_texture *t)
{
    if (!t) return;
    pw_free(a, t->level[0]);
    memset(t, 0, sizeof *t);
}

/* Brings a coordinate into [0, 1]: the fractional part (repeat) or a clamp.
 * Non-finite and absurdly large values become 0 (no float-to-int overflow). */
PW__DEF float pw__tex_wrap(float u, int wrap)
{
    float f;
    if (!(u > -1e9f && u < 1e9f)) return 0.0f;
    if (wrap == PW_WRAP_CLAMP) return u < 0.0f ? 0.0f : (u > 1.0f ? 1.0f : u);
    f = (float)(int)u;
    if (f > u) f -= 1.0f;
    return u - f;
}

/* The four texels of the bilinear lookup in level L of wrapped coordinates
 * u, v in [0, 1] (their offsets in the level, in channels) and their
 * weights, which sum to wgt. Texel centres sit at (i + 0.5) / W. */
PW__DEF void pw__tex_taps(const pw_texture *t, int L, float u, float v, int wrap, float wgt, ptrdiff_t *p, float *w)
{
    const int W = t->lw[L], H = t->lh[L];
    const float cx = u * (float)W - 0.5f, cy = (1.0f - v) * (float)H - 0.5f; /* >= -0.5 */
    int x0 = (int)(cx + 1.0f) - 1, y0 = (int)(cy + 1.0f) - 1, x1 = x0 + 1, y1 = y0 + 1;
    const float fx = cx - (float)x0, fy = cy - (float)y0, gy = wgt * fy, hy = wgt - gy;
    if (wrap == PW_WRAP_CLAMP) {
        if (x0 < 0) x0 = 0;
        if (y0 < 0) y0 = 0;
        if (x1 > W - 1) x1 = W - 1;
        if (y1 > H - 1) y1 = H - 1;
    } else {
        if (x0 < 0) x0 += W;
        if (y0 < 0) y0 += H;
        if (x1 >= W) x1 -= W;
        if (y1 >= H) y1 -= H;
    }
    p[0] = ((ptrdiff_t)y0 * W + x0) * 4;
    p[1] = ((ptrdiff_t)y0 * W + x1) * 4;
    p[2] = ((ptrdiff_t)y1 * W + x0) * 4;
    p[3] = ((ptrdiff_t)y1 * W + x1) * 4;
    w[0] = hy - hy * fx;
    w[1] = hy * fx;
    w[2] = gy - gy * fx;
    w[3] = gy * fx;
}

/* The eight texels of a trilinear lookup of wrapped coordinates at mip
 * level lod (clamped to the chain), weighed to sum to scale: four in level
 * *L, four in level *L + 1 (the first four again, weighed 0, when one level
 * suffices). */
PW__DEF void pw__tex_taps8(const pw_texture *t, float u, float v, float lod, int wrap, float scale, int *L,
                           ptrdiff_t *p, float *w)
{
    int k;
    *L = 0;
    u = pw__tex_wrap(u, wrap);
    v = pw__tex_wrap(v, wrap);
    if (lod >= (float)(t->nlevels - 1)) {
        *L = t->nlevels - 1;
        lod = 0.0f;
    } else if (lod > 0.0f) {
        *L = (int)lod;
        lod -= (float)*L;
    } else {
        lod = 0.0f;
    }
    pw__tex_taps(t, *L, u, v, wrap, scale - scale * lod, p, w);
    if (lod > 0.0f) {
        pw__tex_taps(t, *L + 1, u, v, wrap, scale * lod, p + 4, w + 4);
        return;
    }
    for (k = 0; k < 4; k++) {
        p[4 + k] = p[k] - (ptrdiff_t)t->lw[*L] * t->lh[*L] * 4; /* level L again, as seen from L + 1 */
        w[4 + k] = 0.0f;
    }
}

/* Trilinear lookup of wrapped coordinates at mip level lod (clamped to the
 * chain), in 16-bit units. The channel loop is one compilers vectorise. */
PW__DEF void pw__tex_trilinear(const pw_texture *t, float u, float v, float lod, int wrap, float *out)
{
    const uint16_t *a, *b;
    ptrdiff_t p[8];
    float w[8];
    int L, k;
    pw__tex_taps8(t, u, v, lod, wrap, 1.0f, &L, p, w);
    a = t->level[L];
    b = a + (size_t)t->lw[L] * t->lh[L] * 4; /* level L + 1 follows level L */
    for (k = 0; k < 4; k++)
        out[k] = ((w[0] * (float)a[p[0] + k] + w[1] * (float)a[p[1] + k]) +
                  (w[2] * (float)a[p[2] + k] + w[3] * (float)a[p[3] + k])) +
                 ((w[4] * (float)b[p[4] + k] + w[5] * (float)b[p[5] + k]) +
                  (w[6] * (float)b[p[6] + k] + w[7] * (float)b[p[7] + k]));
}

#ifdef PW__SSE2
/* Per lane: mask ? a : b (mask from a comparison: all ones or zeros). */
PW__DEF __m128 pw__select4(__m128 mask, __m128 a, __m128 b)
{
    return _mm_or_ps(_mm_and_ps(mask, a), _mm_andnot_ps(mask, b));
}

/* The four channels of the 8-bit texel at px, times w. */
PW__DEF __m128 pw__texel8(const uint8_t *px, float w)
{
    const __m128i z = _mm_setzero_si128();
    int32_t v;
    memcpy(&v, px, sizeof v);
    return _mm_mul_ps(_mm_cvtepi32_ps(_mm_unpacklo_epi16(_mm_unpacklo_epi8(_mm_cvtsi32_si128(v), z), z)),
                      _mm_set1_ps(w));
}
#endif

/* The eight weighed texels of pw__tex_taps8's lookup in the 8-bit levels
 * (level L and L + 1), summed. */
PW__DEF void pw__tex_fetch8(const pw_texture *t, int L, const ptrdiff_t *p, const float *w, float *out)
{
    const uint8_t *a = t->level8[L], *b = a + (size_t)t->lw[L] * t->lh[L] * 4;
#ifdef PW__SSE2
    _mm_storeu_ps(out, _mm_add_ps(_mm_add_ps(_mm_add_ps(pw__texel8(a + p[0], w[0]), pw__texel8(a + p[1], w[1])),
                                             _mm_add_ps(pw__texel8(a + p[2], w[2]), pw__texel8(a + p[3], w[3]))),
                                  _mm_add_ps(_mm_add_ps(pw__texel8(b + p[4], w[4]), pw__texel8(b + p[5], w[5])),
                                             _mm_add_ps(pw__texel8(b + p[6], w[6]), pw__texel8(b + p[7], w[7])))));
#else
    {
        int k;
        for (k = 0; k < 4; k++)
            out[k] = ((w[0] * (float)a[p[0] + k] + w[1] * (float)a[p[1] + k]) +
                      (w[2] * (float)a[p[2] + k] + w[3] * (float)a[p[3] + k])) +
                     ((w[4] * (float)b[p[4] + k] + w[5] * (float)b[p[5] + k]) +
                      (w[6] * (float)b[p[6] + k] + w[7] * (float)b[p[7] + k]));
    }
#endif
}

/* The same in the 8-bit levels, times scale (1/255: premultiplied RGBA). */
PW__DEF void pw__tex_trilinear8(const pw_texture *t, float u, float v, float lod, int wrap, float scale, float *out)
{
    ptrdiff_t p[8];
    float w[8];
    int L;
    pw__tex_taps8(t, u, v, lod, wrap, scale, &L, p, w);
    pw__tex_fetch8(t, L, p, w, out);
}

#ifdef PW__SSE2
/* pw__tex_taps8 of four lookups at once (u[j], v[j], lod[j]): lookup j's
 * level in L[j], its texels and weights in p[8 j ..], w[8 j ..]; the same
 * float operations as the scalar code, so the same taps. */
typedef struct pw__taps4 {
    const float *u, *v, *lod; /* the four lookups */
    int L[4];
    ptrdiff_t p[32];
    float w[32];
} pw__taps4;

/* pw__tex_wrap of four coordinates. */
PW__DEF __m128 pw__tex_wrap4(__m128 u, int wrap)
{
    const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f);
    const __m128 ok = _mm_and_ps(_mm_cmpgt_ps(u, _mm_set1_ps(-1e9f)), _mm_cmplt_ps(u, _mm_set1_ps(1e9f)));
    __m128 r;
    if (wrap == PW_WRAP_CLAMP) {
        r = pw__select4(_mm_cmplt_ps(u, zero), zero, pw__select4(_mm_cmpgt_ps(u, one), one, u));
    } else {
        __m128 f = _mm_cvtepi32_ps(_mm_cvttps_epi32(_mm_and_ps(ok, u)));
        f = pw__select4(_mm_cmpgt_ps(f, u), _mm_sub_ps(f, one), f);
        r = _mm_sub_ps(u, f);
    }
    return _mm_and_ps(ok, r);
}

/* Per lane: x < lo ? x + add_lo : (x > hi ? x + add_hi : x), in integers. */
PW__DEF __m128i pw__fold4(__m128i x, __m128i lo, __m128i add_lo, __m128i hi, __m128i add_hi)
{
    const __m128i below = _mm_cmplt_epi32(x, lo), above = _mm_cmpgt_epi32(x, hi);
    return _mm_add_epi32(x, _mm_or_si128(_mm_and_si128(below, add_lo), _mm_and_si128(above, add_hi)));
}

/* Per lane a * b + c, for products and sums below 2^31 (SSE2 multiplies
 * two lanes at a time). */
PW__DEF __m128i pw__madd4(__m128i a, __m128i b, __m128i c)
{
    const __m128i even = _mm_mul_epu32(a, b), odd = _mm_mul_epu32(_mm_srli_si128(a, 4), _mm_srli_si128(b, 4));
    return _mm_add_epi32(_mm_unpacklo_epi32(_mm_shuffle_epi32(even, _MM_SHUFFLE(0, 0, 2, 0)),
                                            _mm_shuffle_epi32(odd, _MM_SHUFFLE(0, 0, 2, 0))),
                         c);
}

/* pw__tex_taps of the four lookups in their levels lv[j] (lookup j's taps
 * at p[8 j + k0 ..], w[8 j + k0 ..]), weights summing to wgt; the level's
 * offsets must stay below 2^31. */
PW__DEF void pw__tex_taps4(const pw_texture *t, const int *lv, __m128 u, __m128 v, __m128 wgt, int wrap, int k0,
                           pw__taps4 *T)
{
    const __m128i W = _mm_setr_epi32(t->lw[lv[0]], t->lw[lv[1]], t->lw[lv[2]], t->lw[lv[3]]);
    const __m128i H = _mm_setr_epi32(t->lh[lv[0]], t->lh[lv[1]], t->lh[lv[2]], t->lh[lv[3]]);
    const __m128i one = _mm_set1_epi32(1), zero = _mm_setzero_si128();
    const __m128 half = _mm_set1_ps(0.5f), onef = _mm_set1_ps(1.0f);
    const __m128 cx = _mm_sub_ps(_mm_mul_ps(u, _mm_cvtepi32_ps(W)), half);
    const __m128 cy = _mm_sub_ps(_mm_mul_ps(_mm_sub_ps(onef, v), _mm_cvtepi32_ps(H)), half);
    __m128i x0 = _mm_sub_epi32(_mm_cvttps_epi32(_mm_add_ps(cx, onef)), one);
    __m128i y0 = _mm_sub_epi32(_mm_cvttps_epi32(_mm_add_ps(cy, onef)), one);
    __m128i x1 = _mm_add_epi32(x0, one), y1 = _mm_add_epi32(y0, one);
    const __m128 fx = _mm_sub_ps(cx, _mm_cvtepi32_ps(x0)), fy = _mm_sub_ps(cy, _mm_cvtepi32_ps(y0));
    const __m128 gy = _mm_mul_ps(wgt, fy), hy = _mm_sub_ps(wgt, gy);
    const __m128i W1 = _mm_sub_epi32(W, one), H1 = _mm_sub_epi32(H, one);
    __m128 w0 = _mm_sub_ps(hy, _mm_mul_ps(hy, fx)), w1 = _mm_mul_ps(hy, fx);
    __m128 w2 = _mm_sub_ps(gy, _mm_mul_ps(gy, fx)), w3 = _mm_mul_ps(gy, fx);
    __m128 p0, p1, p2, p3;
    int j;
    if (wrap == PW_WRAP_CLAMP) { /* x < 0: 0; x > W - 1: W - 1 */
        x0 = _mm_andnot_si128(_mm_cmplt_epi32(x0, zero), x0);
        y0 = _mm_andnot_si128(_mm_cmplt_epi32(y0, zero), y0);
        x1 = pw__fold4(x1, zero, zero, W1, _mm_sub_epi32(W1, x1));
        y1 = pw__fold4(y1, zero, zero, H1, _mm_sub_epi32(H1, y1));
    } else { /* x < 0: x + W; x >= W: x - W */
        x0 = pw__fold4(x0, zero, W, W1, _mm_sub_epi32(zero, W));
        y0 = pw__fold4(y0, zero, H, H1, _mm_sub_epi32(zero, H));
        x1 = pw__fold4(x1, zero, W, W1, _mm_sub_epi32(zero, W));
        y1 = pw__fold4(y1, zero, H, H1, _mm_sub_epi32(zero, H));
    }
    p0 = _mm_castsi128_ps(_mm_slli_epi32(pw__madd4(y0, W, x0), 2)); /* offsets in channels */
    p1 = _mm_castsi128_ps(_mm_slli_epi32(pw__madd4(y0, W, x1), 2));
    p2 = _mm_castsi128_ps(_mm_slli_epi32(pw__madd4(y1, W, x0), 2));
    p3 = _mm_castsi128_ps(_mm_slli_epi32(pw__madd4(y1, W, x1), 2));
    _MM_TRANSPOSE4_PS(w0, w1, w2, w3); /* per lookup: its four taps */
    _MM_TRANSPOSE4_PS(p0, p1, p2, p3);
    for (j = 0; j < 4; j++) {
        const __m128 wj = j == 0 ? w0 : j == 1 ? w1 : j == 2 ? w2 : w3;
        const __m128i pj = _mm_castps_si128(j == 0 ? p0 : j == 1 ? p1 : j == 2 ? p2 : p3);
        ptrdiff_t *p = T->p + 8 * j + k0;
        _mm_storeu_ps(T->w + 8 * j + k0, wj);
        if (sizeof(ptrdiff_t) == 8) { /* non-negative: widened by zeros */
            _mm_storeu_si128((__m128i *)p, _mm_unpacklo_epi32(pj, zero));
            _mm_storeu_si128((__m128i *)(p + 2), _mm_unpackhi_epi32(pj, zero));
        } else {
            _mm_storeu_si128((__m128i *)p, pj);
        }
    }
}

/* pw__tex_taps8 of T's four lookups. */
PW__DEF void pw__tex_taps8x4(const pw_texture *t, int wrap, float scale, pw__taps4 *T)
{
    const __m128 u = pw__tex_wrap4(_mm_loadu_ps(T->u), wrap), v = pw__tex_wrap4(_mm_loadu_ps(T->v), wrap);
    float frac[4];
    int j, k, L1[4];
    for (j = 0; j < 4; j++) { /* the level split, as pw__tex_taps8 */
        float lod = T->lod[j];
        T->L[j] = 0;
        if (lod >= (float)(t->nlevels - 1)) {
            T->L[j] = t->nlevels - 1;
            lod = 0.0f;
        } else if (lod > 0.0f) {
            T->L[j] = (int)lod;
            lod -= (float)T->L[j];
        } else {
            lod = 0.0f;
        }
        frac[j] = lod;
        L1[j] = lod > 0.0f ? T->L[j] + 1 : T->L[j];
    }
    {
        const __m128 s = _mm_set1_ps(scale), sl = _mm_mul_ps(s, _mm_loadu_ps(frac));
        pw__tex_taps4(t, T->L, u, v, _mm_sub_ps(s, sl), wrap, 0, T);
        pw__tex_taps4(t, L1, u, v, sl, wrap, 4, T);
    }
    for (j = 0; j < 4; j++)
        if (!(frac[j] > 0.0f))
            for (k = 0; k < 4; k++) { /* level L again, as seen from L + 1 */
                T->p[8 * j + 4 + k] = T->p[8 * j + k] - (ptrdiff_t)t->lw[T->L[j]] * t->lh[T->L[j]] * 4;
                T->w[8 * j + 4 + k] = 0.0f;
            }
}
#endif

/* Samples texture t at (u, v) (v = 0 at the bottom) with the given filter
 * and wrap mode; lod (log2 of the footprint in level-0 texels) selects and
 * blends mip levels for PW_FILTER_TRILINEAR and is ignored otherwise
 * (PW_FILTER_NEAREST and _BILINEAR read level 0). out = premultiplied RGBA. */
PW__DEF void pw_texture_sample(const pw_texture *t, float u, float v, float lod, int filter, int wrap, float out[4])
{
    const float s = 1.0f / 65535.0f;
    float a[4];
    int k;
    if (filter == PW_FILTER_NEAREST) {
        int x, y;
        const uint16_t *p;
        u = pw__tex_wrap(u, wrap);
        v = pw__tex_wrap(v, wrap);
        x = (int)(u * (float)t->w);
        y = (int)((1.0f - v) * (float)t->h);
        if (x >= t->w) x = wrap == PW_WRAP_CLAMP ? t->w - 1 : 0;
        if (y >= t->h) y = wrap == PW_WRAP_CLAMP ? t->h - 1 : 0;
        p = t->level[0] + ((size_t)y * t->w + x) * 4;
        for (k = 0; k < 4; k++) out[k] = (float)p[k] * s;
        return;
    }
    pw__tex_trilinear(t, u, v, filter == PW_FILTER_TRILINEAR ? lod : 0.0f, wrap, a);
    for (k = 0; k < 4; k++) out[k] = pw_clampf(a[k] * s, 0.0f, 1.0f); /* the weights' rounding may pass 1 */
}

/* log2(x) from the exponent bits and the series of atanh: about 2e-5
 * accurate, and the same on every platform. Tiny, zero, negative and NaN
 * inputs give -100. */
PW__DEF float pw__log2f(float x)
{
    uint32_t bits;
    float m, s, s2;
    int ex;
    if (!(x > 1e-30f)) return -100.0f;
    if (x > 1e30f) return 100.0f;
    memcpy(&bits, &x, sizeof bits);
    ex = (int)((bits >> 23) & 255u) - 127;
    bits = (bits & 0x007FFFFFu) | 0x3F800000u;
    memcpy(&m, &bits, sizeof m); /* mantissa in [1, 2) */
    s = (m - 1.0f) / (m + 1.0f);
    s2 = s * s;
    return (float)ex + s * (2.8853900818f + s2 * (0.9617966939f + s2 * (0.5770780164f + s2 * 0.4121985831f)));
}

/* PW_NO_RENDER leaves out the rest: what the methods compute without
 * drawing still needs the camera (glTF export frames its view with
 * pw_camera_frame) and the textures (pgp's tile3.h samples its tile
 * through them). */
#ifndef PW_NO_RENDER

/* ----------------------------------------------------------- framebuffer */

typedef struct pw_fb {
    int w, h, ss;   /* pixels; ss x ss samples per pixel */
    int sw, sh;     /* sample grid: w*ss x h*ss, sample (x, y) centred at ((x+.5)/ss, (y+.5)/ss) pixels */
    int y0, bh;     /* the sample rows held: [y0, y0 + bh), a band of the frame (all of it
                      unless made by pw_fb_create_band); draws cover only these */
    int band_rows;  /* pixel rows a band can hold */
    float bg[4];    /* background, straight RGBA */
    float *color;   /* sw*bh*4 premultiplied RGBA, sample (x, y) at ((y-y0)*sw + x)*4, row 0 at the top */
    float *depth;   /* sw*bh, q = 1/(distance along the view axis); 0 = nothing drawn */
    uint32_t *vis;  /* sw*bh triangle ids of the opaque draw under way; PW_FB_NONE between draws */
    double *vbuf;   /* draw scratch: transformed vertices */
    float *nbuf;    /* draw scratch: computed normals */
    float *pbuf;    /* draw scratch: triangle planes */
    uint64_t *mbuf; /* draw scratch: sample masks of a pixel row (all zero between uses) */
    float *qbuf;    /* draw scratch: depths of ss sample rows */
    float *zmin;    /* coarse depth: per tile of PW__ZT x PW__ZT samples of the band, the smallest q */
    int zvalid;     /* zmin matches depth; set 0 if you write depth yourself */
    size_t vcap, ncap, pcap, mcap, qcap, zcap;
    const pw_alloc *alloc;
} pw_fb;

/* Colour to background, depth to "nothing drawn". */
PW__DEF void pw_fb_clear(pw_fb *fb)
{
    size_t i, row, n;
    float c[4];
    PW_ASSERT(fb && fb->color);
    row = (size_t)fb->sw * 4;
    n = (size_t)fb->sw * fb->bh;
    c[0] = fb->bg[0] * fb->bg[3];
    c[1] = fb->bg[1] * fb->bg[3];
    c[2] = fb->bg[2] * fb->bg[3];
    c[3] = fb->bg[3];
    for (i = 0; i < (size_t)fb->sw; i++) memcpy(fb->color + 4 * i, c, sizeof c);
    for (i = 1; i < (size_t)fb->bh; i++) memcpy(fb->color + i * row, fb->color, row * sizeof(float));
    memset(fb->depth, 0, n * sizeof(float));
    fb->zvalid = 0;
}

PW__DEF void pw_fb_free(pw_fb *fb)
{
    if (!fb) return;
    pw_free(fb->alloc, fb->color);
    pw_free(fb->alloc, fb->depth);
    pw_free(fb->alloc, fb->vis);
    pw_free(fb->alloc, fb->vbuf);
    pw_free(fb->alloc, fb->nbuf);
    pw_free(fb->alloc, fb->pbuf);
    pw_free(fb->alloc, fb->mbuf);
    pw_free(fb->alloc, fb->qbuf);
    pw_free(fb->alloc, fb->zmin);
    memset(fb, 0, sizeof *fb);
}

/* Creates a cleared framebuffer for a w x h frame with ss x ss samples per
 * pixel (1 <= ss <= PW_FB_MAX_SS) and background bg (straight RGBA; NULL:
 * opaque black) that holds band_rows pixel rows at a time (0 or >= h: the
 * whole frame), the first band selected. The allocator a (may be NULL) must
 * outlive the framebuffer. */
PW__DEF int pw_fb_create_band(const pw_alloc *a, pw_fb *fb, int w, int h, int ss, int band_rows, const float bg[4],
                              pw_err *e)
{
    size_t n;
    memset(fb, 0, sizeof *fb);
    if (w <= 0 || h <= 0 || ss < 1 || ss > PW_FB_MAX_SS || band_rows < 0)
        return pw_fail(e, PW_ERR_INVALID, "framebuffer: invalid size %dx%d with %dx%d samples", w, h, ss, ss);
    if (w > PW_MAX_IMAGE_DIM || h > PW_MAX_IMAGE_DIM || (int64_t)w * h * ss * ss > (int64_t)PW_MAX_IMAGE_PIXELS)
        return pw_fail(e, PW_ERR_LIMIT, "framebuffer: %dx%d with %dx%d samples exceeds the limit", w, h, ss, ss);
    fb->w = w;
    fb->h = h;
    fb->ss = ss;
    fb->sw = w * ss;
    fb->sh = h * ss;
    fb->band_rows = band_rows == 0 || band_rows > h ? h : band_rows;
    fb->bh = fb->band_rows * ss;
    fb->alloc = a;
    fb->bg[3] = 1.0f;
    if (bg) memcpy(fb->bg, bg, sizeof fb->bg);
    n = (size_t)fb->sw * fb->bh;
    fb->color = (float *)pw_alloc_array(a, n * 4, sizeof(float), "framebuffer colour", e);
    fb->depth = fb->color ? (float *)pw_alloc_array(a, n, sizeof(float), "framebuffer depth", e) : NULL;
    fb->vis = fb->depth ? (uint32_t *)pw_alloc_array(a, n, sizeof(uint32_t), "framebuffer ids", e) : NULL;
    if (!fb->vis) {
        pw_fb_free(fb);
        return PW_ERR_NOMEM;
    }
    memset(fb->vis, 0xFF, n * sizeof(uint32_t));
    pw_fb_clear(fb);
    return PW_OK;
}

/* The same holding the whole frame. */
PW__DEF int pw_fb_create(const pw_alloc *a, pw_fb *fb, int w, int h, int ss, const float bg[4], pw_err *e)
{
    return pw_fb_create_band(a, fb, w, h, ss, 0, bg, e);
}

/* Selects the band that starts at pixel row `row` (cleared). */
PW__DEF void pw_fb_set_band(pw_fb *fb, int row)
{
    int rows = fb->h - row < fb->band_rows ? fb->h - row : fb->band_rows;
    PW_ASSERT(row >= 0 && row < fb->h);
    fb->y0 = row * fb->ss;
    fb->bh = rows * fb->ss;
    pw_fb_clear(fb);
}

/* Box-filters the samples of each pixel of the band into the same rows of
 * out (the frame's size, 3 or 4 channels): 4 gives straight RGBA, 3 the
 * premultiplied colour (i.e. composited over black, which is the colour
 * itself wherever alpha is 1). Clamped to [0,1]. */
PW__DEF void pw_fb_resolve_band(const pw_fb *fb, pw_image *out)
{
    const size_t srow = (size_t)fb->sw * 4;
    const float inv = 1.0f / (float)(fb->ss * fb->ss);
    const int channels = out->c, row0 = fb->y0 / fb->ss;
    int x, y, i, j, k;
    PW_ASSERT(fb->color && out->w == fb->w && out->h == fb->h && (channels == 3 || channels == 4));
    if (fb->ss == 1 && channels == 3) { /* one sample per pixel, premultiplied: a clamped copy */
        const float *src = fb->color;
        float *o = out->px + (size_t)row0 * fb->w * 3;
        size_t i = 0, n = (size_t)fb->w * fb->bh;
#ifdef PW__SSE2
        { /* max(x, 0) then min(., 1): 0 for NaN, as below; the fourth lane is the next pixel's, written again */
            const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f);
            for (; i + 1 < n; i++)
                _mm_storeu_ps(o + 3 * i, _mm_min_ps(_mm_max_ps(_mm_loadu_ps(src + 4 * i), zero), one));
        }
#endif
        for (; i < n; i++)
            for (k = 0; k < 3; k++)
                o[3 * i + k] = src[4 * i + k] > 0.0f ? (src[4 * i + k] < 1.0f ? src[4 * i + k] : 1.0f) : 0.0f;
        return;
    }
    for (y = 0; y < fb->bh / fb->ss; y++) {
        const float *blk = fb->color + (size_t)y * fb->ss * srow;
        float *o = out->px + (size_t)(row0 + y) * fb->w * channels;
        for (x = 0; x < fb->w; x++, blk += 4 * fb->ss, o += channels) {
            float acc[4], r = 0.0f, g = 0.0f, b = 0.0f, a = 0.0f;
            for (j = 0; j < fb->ss; j++) {
                const float *smp = blk + j * srow;
                for (i = 0; i < fb->ss; i++, smp += 4) {
                    r += smp[0];
                    g += smp[1];
                    b += smp[2];
                    a += smp[3];
                }
            }
            acc[0] = r * inv;
            acc[1] = g * inv;
            acc[2] = b * inv;
            acc[3] = a * inv;
            if (channels == 4 && acc[3] > 0.0f)
                for (k = 0; k < 3; k++) acc[k] /= acc[3];
            for (k = 0; k < channels; k++) o[k] = acc[k] > 0.0f ? (acc[k] < 1.0f ? acc[k] : 1.0f) : 0.0f;
        }
    }
}

/* A framebuffer holding the whole frame into out (allocated here with the
 * framebuffer's allocator; free with pw_image_free), as pw_fb_resolve_band. */
PW__DEF int pw_fb_resolve(const pw_fb *fb, pw_image *out, int channels, pw_err *e)
{
    int r;
    PW_ASSERT(fb && fb->color && out && fb->bh == fb->sh);
    if (channels != 3 && channels != 4) {
        memset(out, 0, sizeof *out);
        return pw_fail(e, PW_ERR_INVALID, "resolve: %d channels (need 3 or 4)", channels);
    }
    r = pw_image_alloc(fb->alloc, out, fb->w, fb->h, channels, e);
    if (r) return r;
    pw_fb_resolve_band(fb, out);
    return PW_OK;
}

/* ------------------------------------------------------------------ draw */

/* A triangle mesh and how to draw it. Zero-initialised fields are defaults. */
typedef struct pw_draw {
    const float *positions; /* nv*3 world-space vertex positions */
    int nv;
    const int *tris; /* ntris*3 vertex indices */
    int ntris;
    const float *uvs;      /* ntris*3*2 texture coordinates per triangle corner (v = 0 at the
                               bottom of the texture); required with a texture, else ignored */
    const float *normals;  /* nv*3 per-vertex normals; NULL: smooth area-weighted normals
                               computed from the mesh. Used only when lit */
    int flat;              /* 1: flat shading, one normal per face (normals ignored) */
    const pw_texture *tex; /* NULL: the constant colour alone */
    float color[4];        /* straight RGBA multiplied with the texture; all zero: opaque white */
    int filter;            /* PW_FILTER_TRILINEAR (default), _BILINEAR, _NEAREST (level 0) */
    int wrap;              /* PW_WRAP_REPEAT (default), PW_WRAP_CLAMP */
    int blend;             /* PW_BLEND_REPLACE (default: write the colour, alpha included),
                               PW_BLEND_OVER (rgba = src + (1 - src alpha) dst, premultiplied) */
    int depth_test;        /* PW_DEPTH_LESS (default: passes where nearer than what is
                               stored), PW_DEPTH_LEQUAL (also where as near, within a
                               tolerance, so a second pass over the same surface passes),
                               PW_DEPTH_ALWAYS. Samples beyond zfar never pass */
    float depth_tolerance; /* relative slack of LEQUAL: passes if q > (1 - tol) q_stored
                               (q = 1/depth); 0: PW_DEPTH_TOLERANCE */
    int no_depth_write;    /* 1: depth is tested but not written */
    int no_color_write;    /* 1: depth only (a depth pre-pass) */
    int cull;              /* PW_CULL_NONE (default: two-sided), PW_CULL_BACK, PW_CULL_FRONT */
    int lighting;          /* PW_LIGHT_NONE (default: unlit), PW_LIGHT_CAMERA, PW_LIGHT_WORLD:
                               Lambert + ambient, the light direction in camera space (x right,
                               y up, z toward the viewer) or in world space. Two-sided: back
                               faces are lit with their normals reversed */
    float light_dir[3];    /* direction toward the light; zero: (-0.3, 0.4, 1) in camera space */
    float ambient;         /* brightness of unlit parts, in [0, 1]; 0: 0.25; negative: none */
    /* Optional, replaces the texture: the straight RGBA of triangle `tri` at
     * the point of barycentric coordinates (1 - b1 - b2, b1, b2) (perspective-
     * correct, corners in the triangle's order), given db = (db1/dx, db1/dy,
     * db2/dx, db2/dy) per pixel for filtering. Multiplied into the colour as
     * a texture lookup would be; uvs are not needed. */
    void (*shader)(void *user, int tri, float b1, float b2, const float db[4], float rgba[4]);
    void *shader_user;
    const double *projected; /* optional: the vertices as pw_draw_project gives them for
                                this camera and frame size, so that the bands of a frame
                                (and the passes of a lapped texture) project the mesh once */
} pw_draw;

#define PW__ZT 8      /* coarse depth tile, in samples */
#define PW__NARROW 16 /* triangles at most this many samples wide skip the row walker */
#define PW__NPL 20    /* floats per triangle: planes q(3) U(3) V(3) N(9), origin(2) */
#define PW__OX 18
#define PW__OY 19

/* Pixels waiting to be shaded, together: shading one pixel is a long chain
 * of dependent steps (perspective divide, mip level, texel addresses,
 * texels, filter, lighting), so each step runs over the whole batch before
 * the next, and the processor overlaps the pixels. */
#define PW__BATCH 64
typedef struct pw__batch {
    int n;
    int t[PW__BATCH];   /* triangle */
    float x[PW__BATCH]; /* shading point on the sample grid */
    float y[PW__BATCH];
    int px[PW__BATCH]; /* pixel */
    int py[PW__BATCH];
    uint64_t mask[PW__BATCH]; /* blended draws: the samples to blend */
    float col[4 * PW__BATCH]; /* shaded colour, premultiplied */
} pw__batch;

/* Everything a draw needs in its inner loops. */
typedef struct pw__ctx {
    pw_fb *fb;
    const pw_draw *d;
    pw__view view;
    pw_raster_grid grid;
    const double *vh;     /* per vertex: X, Y, W (homogeneous), X/W, Y/W */
    const float *normals; /* per vertex, or NULL (flat or unlit) */
    float *planes;        /* per triangle, PW__NPL floats */
    const float *zmin;    /* coarse depth of draws that do not write depth, or NULL */
    uint64_t *mask;       /* blended draws: per pixel of a row, its samples that passed */
    float *qbuf;          /* blended draws: their depths, ss sample rows */
    const pw_texture *tex;
    int filter, wrap, blend, lit, cull, dwrite, cwrite;
    float tint[4], light[3], ambient, dfac, qfar, ss;
    int bx0, by0, bx1, by1; /* sample box touched by an opaque draw */
    pw__batch *batch;       /* pixels waiting to be shaded */
} pw__ctx;

/* Checks the draw description; names the first problem found. */
PW__DEF int pw__draw_check(const pw_draw *d, pw_err *e)
{
    int i;
    if (d->nv < 0 || d->ntris < 0)
        return pw_fail(e, PW_ERR_INVALID, "draw: negative counts (%d vertices, %d triangles)", d->nv, d->ntris);
    if (d->nv > PW_MAX_MESH_ELEMENTS || d->ntris > PW_MAX_MESH_ELEMENTS)
        return pw_fail(e, PW_ERR_LIMIT, "draw: %d vertices, %d triangles exceed the limit %d", d->nv, d->ntris,
                       PW_MAX_MESH_ELEMENTS);
    if ((d->nv > 0 && !d->positions) || (d->ntris > 0 && !d->tris))
        return pw_fail(e, PW_ERR_INVALID, "draw: missing positions or triangle indices");
    if (d->tex && (!d->uvs || d->tex->nlevels < 1 || !d->tex->level[0]))
        return pw_fail(e, PW_ERR_INVALID, "draw: a texture needs uvs and a built mip chain");
    if ((unsigned)d->filter > 2u || (unsigned)d->wrap > 1u || (unsigned)d->blend > 1u || (unsigned)d->depth_test > 2u ||
        (unsigned)d->cull > 2u || (unsigned)d->lighting > 2u)
        return pw_fail(e, PW_ERR_INVALID, "draw: unknown filter, wrap, blend, depth, cull or lighting mode");
    for (i = 0; i < 3 * d->ntris; i++)
        if (d->tris[i] < 0 || d->tris[i] >= d->nv)
            return pw_fail(e, PW_ERR_INVALID, "draw: triangle %d, corner %d: vertex index %d outside [0, %d)", i / 3,
                           i % 3, d->tris[i], d->nv);
    return PW_OK;
}

PW__DEF int pw__finite3(const float *p) { return pw_is_finite(p[0]) && pw_is_finite(p[1]) && pw_is_finite(p[2]); }

/* Homogeneous screen coordinates of every vertex; W = -DBL_MAX marks a
 * vertex with non-finite coordinates (its triangles are skipped). */
PW__DEF void pw__transform_vertex(const pw__view *v, const float *p, double *o)
{
    double q[3], xv, yv, w;
    int k;
    if (!pw__finite3(p)) {
        o[0] = o[1] = o[3] = o[4] = 0.0;
        o[2] = -DBL_MAX;
        return;
    }
    for (k = 0; k < 3; k++) q[k] = (double)p[k] - v->eye[k];
    xv = pw_dot3(q, v->r);
    yv = pw_dot3(q, v->u);
    w = pw_dot3(q, v->f);
    o[0] = v->cx * w + v->fx * xv;
    o[1] = v->cy * w - v->fy * yv;
    o[2] = w;
    o[3] = w >= v->znear ? o[0] / w : 0.0;
    o[4] = w >= v->znear ? o[1] / w : 0.0;
}

/* Transforms the vertices the draw uses: all of them, or, when it draws
 * few triangles of many vertices (a paste of a lapped texture is a small
 * part of the whole mesh), only the corners of its triangles (a shared
 * corner twice, which gives the same values). */
PW__DEF void pw__transform(const pw__view *v, const pw_draw *d, double *vh)
{
    int i;
    if ((size_t)d->ntris * 3 < (size_t)d->nv)
        for (i = 0; i < 3 * d->ntris; i++) pw__transform_vertex(v, d->positions + 3 * d->tris[i], vh + 5 * d->tris[i]);
    else
        for (i = 0; i < d->nv; i++) pw__transform_vertex(v, d->positions + 3 * i, vh + 5 * i);
}

/* The range [*lo, *hi] of screen rows (in samples) that the corners of d's
 * triangles project to under view v, exactly as pw_render_draw projects
 * them (vh: every vertex of d transformed by pw__transform under v);
 * returns 0 (the draw may reach any row) if some corner is not at least
 * znear in front or not finite. A band [y0, y0 + bh] that the range misses
 * (*hi < y0 or *lo > y0 + bh) gets nothing from the draw: each of its
 * triangles lies above or below the band (pw__offscreen), so a frame drawn
 * in bands may skip the draw there. */
PW__DEF int pw__draw_rows(const pw__view *v, const pw_draw *d, const double *vh, double *lo, double *hi)
{
    int i;
    *lo = -DBL_MAX;
    *hi = DBL_MAX;
    for (i = 0; i < 3 * d->ntris; i++) {
        const double *o = vh + 5 * (size_t)d->tris[i];
        if (!(o[2] >= v->znear)) {
            *lo = -DBL_MAX;
            *hi = DBL_MAX;
            return 0;
        }
        if (i == 0 || o[4] < *lo) *lo = o[4];
        if (i == 0 || o[4] > *hi) *hi = o[4];
    }
    return 1;
}

/* Unnormalised normal of triangle t (its area-weighted direction). */
PW__DEF void pw__face_normal(const pw_draw *d, int t, double *n)
{
    const float *p0 = d->positions + 3 * d->tris[3 * t], *p1 = d->positions + 3 * d->tris[3 * t + 1],
                *p2 = d->positions + 3 * d->tris[3 * t + 2];
    double a[3], b[3];
    int k;
    for (k = 0; k < 3; k++) {
        a[k] = (double)p1[k] - p0[k];
        b[k] = (double)p2[k] - p0[k];
    }
    pw_cross3(a, b, n);
}

/* Smooth vertex normals: area-weighted sums of the face normals, unit length. */
PW__DEF void pw__smooth_normals(const pw_draw *d, float *out)
{
    int t, i, k;
    memset(out, 0, sizeof(float) * 3 * (size_t)d->nv);
    for (t = 0; t < d->ntris; t++) {
        double n[3];
        const int *ix = d->tris + 3 * t;
        if (!pw__finite3(d->positions + 3 * ix[0]) || !pw__finite3(d->positions + 3 * ix[1]) ||
            !pw__finite3(d->positions + 3 * ix[2]))
            continue;
        pw__face_normal(d, t, n);
        for (i = 0; i < 3; i++)
            for (k = 0; k < 3; k++) out[3 * ix[i] + k] += pw__f(n[k]);
    }
    for (i = 0; i < d->nv; i++) {
        double n[3];
        for (k = 0; k < 3; k++) n[k] = out[3 * i + k];
        pw_norm3(n);
        for (k = 0; k < 3; k++) out[3 * i + k] = (float)n[k];
    }
}

/* One plane: the attribute a_k at the vertices interpolated perspective-
 * correctly and divided by w, as c0 (x - ox) + c1 (y - oy) + c2. Rows r_k of
 * the adjugate, already divided by the determinant, give u_k = b_k / w. */
PW__DEF void pw__plane(double r[3][3], const double *a, double ox, double oy, float *out)
{
    double c[3];
    int j;
    for (j = 0; j < 3; j++) c[j] = a[0] * r[0][j] + a[1] * r[1][j] + a[2] * r[2][j];
    out[0] = pw__f(c[0]);
    out[1] = pw__f(c[1]);
    out[2] = pw__f(c[0] * ox + c[1] * oy + c[2]);
}

/* Rows of the adjugate of the matrix of triangle t's homogeneous vertices,
 * divided by its determinant: u_k(x, y) = r_k . (x, y, 1) is the
 * barycentric b_k divided by w. Returns 0 if the triangle is seen edge-on
 * (its plane passes through the eye) or culled. */
PW__DEF int pw__tri_adjugate(const pw__ctx *c, int t, double r[3][3], double *det)
{
    const int *ix = c->d->tris + 3 * (size_t)t;
    const double *h0 = c->vh + 5 * (size_t)ix[0], *h1 = c->vh + 5 * (size_t)ix[1], *h2 = c->vh + 5 * (size_t)ix[2];
    double scale;
    int i, j;
    pw_cross3(h1, h2, r[0]);
    pw_cross3(h2, h0, r[1]);
    pw_cross3(h0, h1, r[2]);
    *det = pw_dot3(h0, r[0]);
    scale = sqrt(pw_dot3(h0, h0) * pw_dot3(h1, h1) * pw_dot3(h2, h2));
    if (!(fabs(*det) > 1e-12 * scale)) return 0;
    /* det < 0: counter-clockwise as seen by the viewer, i.e. front-facing */
    if ((c->cull == PW_CULL_BACK && *det > 0.0) || (c->cull == PW_CULL_FRONT && *det < 0.0)) return 0;
    scale = 1.0 / *det;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) r[i][j] *= scale;
    return 1;
}

/* Depth plane q = 1/w of triangle t, relative to an integer origin near its
 * screen polygon poly[n] so that float evaluation does not cancel; r and
 * det receive the adjugate for the attribute planes (pw__attr_planes). */
PW__DEF int pw__tri_planes(const pw__ctx *c, int t, const double *poly, int n, float *pl, double r[3][3], double *det)
{
    double ox = 0.0, oy = 0.0, one[3] = {1.0, 1.0, 1.0};
    int i;
    if (!pw__tri_adjugate(c, t, r, det)) return 0;
    for (i = 0; i < n; i++) {
        ox += poly[2 * i] / n;
        oy += poly[2 * i + 1] / n;
    }
    ox = floor((ox > 0.0 ? (ox < c->fb->sw ? ox : c->fb->sw) : 0.0) + 0.5);
    oy = floor((oy > 0.0 ? (oy < c->fb->sh ? oy : c->fb->sh) : 0.0) + 0.5);
    pw__plane(r, one, ox, oy, pl);
    pl[PW__OX] = (float)ox;
    pl[PW__OY] = (float)oy;
    return 1;
}

/* Attribute planes of triangle t (U/w, V/w, N/w) from the adjugate r and
 * determinant det of pw__tri_planes: set up with the depth plane of every
 * triangle that covers a sample of a draw that writes colour (set up later,
 * they would read the vertices and the triangle's planes again, from
 * memory). */
PW__DEF void pw__attr_planes(const pw__ctx *c, int t, float *pl, double r[3][3], double det)
{
    const pw_draw *d = c->d;
    double a[3], fn[3], sgn, ox = pl[PW__OX], oy = pl[PW__OY];
    int i, k;
    if (d->shader) { /* barycentric coordinates b1, b2 in the places of u, v */
        for (k = 0; k < 2; k++) {
            for (i = 0; i < 3; i++) a[i] = i == k + 1 ? 1.0 : 0.0;
            pw__plane(r, a, ox, oy, pl + 3 + 3 * k);
        }
    } else if (c->tex) {
        const float *uv = d->uvs + 6 * (size_t)t;
        for (k = 0; k < 2; k++) {
            for (i = 0; i < 3; i++) a[i] = uv[2 * i + k];
            pw__plane(r, a, ox, oy, pl + 3 + 3 * k);
        }
    }
    if (c->lit) {
        sgn = det > 0.0 ? -1.0 : 1.0; /* two-sided: back faces turn their normals around */
        if (!c->normals) pw__face_normal(d, t, fn);
        for (k = 0; k < 3; k++) {
            for (i = 0; i < 3; i++) a[i] = sgn * (c->normals ? (double)c->normals[3 * d->tris[3 * t + i] + k] : fn[k]);
            pw__plane(r, a, ox, oy, pl + 9 + 3 * k);
        }
    }
}

/* Clips a triangle crossing the near plane in homogeneous coordinates and
 * projects the polygon (3 or 4 vertices) to the screen. Each intersection is
 * computed from the endpoint with the smaller vertex index, so the two
 * triangles sharing an edge get the same point. */
PW__DEF int pw__near_clip(const pw__ctx *c, const int *ix, const double *const *h, double *poly)
{
    double zn = c->view.znear;
    int i, m = 0;
    for (i = 0; i < 3; i++) {
        int j = (i + 1) % 3, pin = h[i][2] >= zn, qin = h[j][2] >= zn;
        if (pin) {
            poly[2 * m] = h[i][3];
            poly[2 * m + 1] = h[i][4];
            m++;
        }
        if (pin != qin) {
            const double *a = ix[i] < ix[j] ? h[i] : h[j], *b = ix[i] < ix[j] ? h[j] : h[i];
            double t = (zn - a[2]) / (b[2] - a[2]); /* the point is on the near plane: w = zn */
            poly[2 * m] = (a[0] + t * (b[0] - a[0])) / zn;
            poly[2 * m + 1] = (a[1] + t * (b[1] - a[1])) / zn;
            m++;
        }
    }
    return m;
}

/* Samples of one piece into the depth and visibility buffers (opaque draws
 * and depth-only draws): a sample passes if its q = 1/depth > dfac * stored
 * (LESS: dfac 1, LEQUAL: 1 - tolerance, ALWAYS: 0) and q is within the far
 * plane; then depth and/or the triangle id are written. Sample centres
 * x + 0.5 are stepped in float, exactly (integers < 2^24), so q is the same
 * whichever loop computes it. */
PW__DEF void pw__raster_vis(pw__ctx *c, pw_raster_edges *s, uint32_t id, const float *pl)
{
    pw_fb *fb = c->fb;
    const float ox = pl[PW__OX], oy = pl[PW__OY], qx = pl[0], dfac = c->dfac, qfar = c->qfar;
    const int dwrite = c->dwrite, cwrite = c->cwrite;
    int y, x, xa, xb;
    for (y = s->y0; y < s->y1; y++) {
        const float qrow = pl[1] * ((float)y + 0.5f - oy) + pl[2];
        float *dp = fb->depth + (size_t)(y - fb->y0) * fb->sw, fx;
        uint32_t *vp = fb->vis + (size_t)(y - fb->y0) * fb->sw;
        if (!pw__raster_row(s, y, &xa, &xb)) continue;
        fx = (float)xa + 0.5f - ox;
        for (x = xa; x < xb; x++, fx += 1.0f) {
            const float q = qx * fx + qrow;
            if (q > dp[x] * dfac && q >= qfar) {
                if (dwrite) dp[x] = q;
                if (cwrite) vp[x] = id;
            }
        }
    }
    if (s->x0 < c->bx0) c->bx0 = s->x0;
    if (s->y0 < c->by0) c->by0 = s->y0;
    if (s->x1 > c->bx1) c->bx1 = s->x1;
    if (s->y1 > c->by1) c->by1 = s->y1;
}

/* A shading point of triangle t: its attribute planes pl (PW__NPL floats),
 * the sample's offset (dx, dy) from the planes' origin, and iq = 1/q, the
 * perspective divisor there. */
typedef struct pw__shade_pt {
    int t;
    const float *pl;
    float dx, dy, iq;
} pw__shade_pt;

/* Mip level at a shading point: the exact screen derivatives of the
 * perspective-correct (u, v) from the planes (d(U/q)/dx = (U_x - u q_x) / q),
 * scaled to one pixel, give the footprint in level-0 texels. */
PW__DEF float pw__tex_lod(const pw__ctx *c, const float *pl, float u, float v, float iq)
{
    const pw_texture *t = c->tex;
    float su = c->ss * iq * (float)t->w, sv = c->ss * iq * (float)t->h;
    float ux = (pl[3] - u * pl[0]) * su, uy = (pl[4] - u * pl[1]) * su;
    float vx = (pl[6] - v * pl[0]) * sv, vy = (pl[7] - v * pl[1]) * sv;
    float rx = ux * ux + vx * vx, ry = uy * uy + vy * vy;
    return 0.5f * pw__log2f(rx > ry ? rx : ry);
}

/* The caller's shader at a shading point: barycentric coordinates and
 * their derivatives per pixel, as pw__tex_lod finds them for u, v. Writes
 * its colour, premultiplied, to tx. */
PW__DEF void pw__shade_custom(const pw__ctx *c, const pw__shade_pt *P, float *tx)
{
    const float *pl = P->pl, dx = P->dx, dy = P->dy, iq = P->iq;
    float b1 = (pl[3] * dx + pl[4] * dy + pl[5]) * iq, b2 = (pl[6] * dx + pl[7] * dy + pl[8]) * iq;
    float db[4], rgba[4], s = c->ss * iq;
    int k;
    db[0] = (pl[3] - b1 * pl[0]) * s;
    db[1] = (pl[4] - b1 * pl[1]) * s;
    db[2] = (pl[6] - b2 * pl[0]) * s;
    db[3] = (pl[7] - b2 * pl[1]) * s;
    c->d->shader(c->d->shader_user, P->t, b1, b2, db, rgba);
    for (k = 0; k < 3; k++) tx[k] = rgba[k] * rgba[3];
    tx[3] = rgba[3];
}

/* Lambert + ambient factor at an offset (dx, dy) from the planes' origin. */
PW__DEF float pw__light(const pw__ctx *c, const float *pl, float dx, float dy)
{
    float n0 = pl[9] * dx + pl[10] * dy + pl[11], n1 = pl[12] * dx + pl[13] * dy + pl[14];
    float n2 = pl[15] * dx + pl[16] * dy + pl[17], nn = n0 * n0 + n1 * n1 + n2 * n2;
    float dif = 1.0f;
    if (nn > 0.0f) dif = (n0 * c->light[0] + n1 * c->light[1] + n2 * c->light[2]) / sqrtf(nn);
    if (!(dif > 0.0f)) dif = 0.0f;
    return c->ambient + (1.0f - c->ambient) * dif;
}

#ifdef PW__SSE2
/* pw__log2f of four values at once, the same float operations. */
PW__DEF __m128 pw__log2f4(__m128 x)
{
    const __m128i bits = _mm_castps_si128(x);
    const __m128 ex = _mm_cvtepi32_ps(
        _mm_sub_epi32(_mm_and_si128(_mm_srli_epi32(bits, 23), _mm_set1_epi32(255)), _mm_set1_epi32(127)));
    const __m128 m =
        _mm_castsi128_ps(_mm_or_si128(_mm_and_si128(bits, _mm_set1_epi32(0x007FFFFF)), _mm_set1_epi32(0x3F800000)));
    const __m128 one = _mm_set1_ps(1.0f), s = _mm_div_ps(_mm_sub_ps(m, one), _mm_add_ps(m, one)), s2 = _mm_mul_ps(s, s);
    __m128 r = _mm_add_ps(_mm_set1_ps(0.5770780164f), _mm_mul_ps(s2, _mm_set1_ps(0.4121985831f)));
    r = _mm_add_ps(_mm_set1_ps(0.9617966939f), _mm_mul_ps(s2, r));
    r = _mm_add_ps(_mm_set1_ps(2.8853900818f), _mm_mul_ps(s2, r));
    r = _mm_add_ps(ex, _mm_mul_ps(s, r));
    r = pw__select4(_mm_cmpgt_ps(x, _mm_set1_ps(1e30f)), _mm_set1_ps(100.0f), r);
    return pw__select4(_mm_cmpgt_ps(x, _mm_set1_ps(1e-30f)), r, _mm_set1_ps(-100.0f));
}

/* The planes of pixels i .. i + 3 of batch b, transposed: P[k] holds
 * coefficient k of each pixel's triangle. */
PW__DEF void pw__planes4(const pw__ctx *c, const pw__batch *b, int i, __m128 P[PW__NPL])
{
    const float *p0 = c->planes + (size_t)b->t[i] * PW__NPL, *p1 = c->planes + (size_t)b->t[i + 1] * PW__NPL;
    const float *p2 = c->planes + (size_t)b->t[i + 2] * PW__NPL, *p3 = c->planes + (size_t)b->t[i + 3] * PW__NPL;
    int k;
    for (k = 0; k < PW__NPL; k += 4) {
        __m128 r0 = _mm_loadu_ps(p0 + k), r1 = _mm_loadu_ps(p1 + k), r2 = _mm_loadu_ps(p2 + k),
               r3 = _mm_loadu_ps(p3 + k);
        _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
        P[k] = r0;
        P[k + 1] = r1;
        P[k + 2] = r2;
        P[k + 3] = r3;
    }
}

/* What pw__shade_batch computes per pixel before the texture lookup, for
 * pixels i .. i + 3 at once, with the same float operations in the same
 * order as the scalar loops (perspective divisor, texture coordinates and
 * mip level when tex, lighting when lit). */
PW__DEF void pw__shade_coords4(const pw__ctx *c, const pw__batch *b, int i, int tex, float *dx, float *dy, float *iq,
                               float *uvl)
{
    __m128 P[PW__NPL], X, Y, q, r;
    pw__planes4(c, b, i, P);
    X = _mm_sub_ps(_mm_loadu_ps(b->x + i), P[PW__OX]);
    Y = _mm_sub_ps(_mm_loadu_ps(b->y + i), P[PW__OY]);
    q = _mm_add_ps(_mm_add_ps(_mm_mul_ps(P[0], X), _mm_mul_ps(P[1], Y)), P[2]);
    q = pw__select4(_mm_cmpgt_ps(q, _mm_set1_ps(1e-30f)), q, _mm_set1_ps(1e-30f));
    r = _mm_div_ps(_mm_set1_ps(1.0f), q);
    _mm_storeu_ps(dx + i, X);
    _mm_storeu_ps(dy + i, Y);
    _mm_storeu_ps(iq + i, r);
    if (tex) { /* uvl: u, v, lod, light rows of PW__BATCH */
        __m128 u = _mm_mul_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(P[3], X), _mm_mul_ps(P[4], Y)), P[5]), r);
        __m128 v = _mm_mul_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(P[6], X), _mm_mul_ps(P[7], Y)), P[8]), r);
        __m128 lod = _mm_setzero_ps();
        _mm_storeu_ps(uvl + i, u);
        _mm_storeu_ps(uvl + PW__BATCH + i, v);
        if (c->filter == PW_FILTER_TRILINEAR) {
            const __m128 su = _mm_mul_ps(_mm_mul_ps(_mm_set1_ps(c->ss), r), _mm_set1_ps((float)c->tex->w));
            const __m128 sv = _mm_mul_ps(_mm_mul_ps(_mm_set1_ps(c->ss), r), _mm_set1_ps((float)c->tex->h));
            const __m128 ux = _mm_mul_ps(_mm_sub_ps(P[3], _mm_mul_ps(u, P[0])), su);
            const __m128 uy = _mm_mul_ps(_mm_sub_ps(P[4], _mm_mul_ps(u, P[1])), su);
            const __m128 vx = _mm_mul_ps(_mm_sub_ps(P[6], _mm_mul_ps(v, P[0])), sv);
            const __m128 vy = _mm_mul_ps(_mm_sub_ps(P[7], _mm_mul_ps(v, P[1])), sv);
            const __m128 rx = _mm_add_ps(_mm_mul_ps(ux, ux), _mm_mul_ps(vx, vx));
            const __m128 ry = _mm_add_ps(_mm_mul_ps(uy, uy), _mm_mul_ps(vy, vy));
            lod = _mm_mul_ps(_mm_set1_ps(0.5f), pw__log2f4(pw__select4(_mm_cmpgt_ps(rx, ry), rx, ry)));
        }
        _mm_storeu_ps(uvl + 2 * PW__BATCH + i, lod);
    }
    if (c->lit) {
        const __m128 n0 = _mm_add_ps(_mm_add_ps(_mm_mul_ps(P[9], X), _mm_mul_ps(P[10], Y)), P[11]);
        const __m128 n1 = _mm_add_ps(_mm_add_ps(_mm_mul_ps(P[12], X), _mm_mul_ps(P[13], Y)), P[14]);
        const __m128 n2 = _mm_add_ps(_mm_add_ps(_mm_mul_ps(P[15], X), _mm_mul_ps(P[16], Y)), P[17]);
        const __m128 nn = _mm_add_ps(_mm_add_ps(_mm_mul_ps(n0, n0), _mm_mul_ps(n1, n1)), _mm_mul_ps(n2, n2));
        const __m128 ln =
            _mm_add_ps(_mm_add_ps(_mm_mul_ps(n0, _mm_set1_ps(c->light[0])), _mm_mul_ps(n1, _mm_set1_ps(c->light[1]))),
                       _mm_mul_ps(n2, _mm_set1_ps(c->light[2])));
        __m128 dif =
            pw__select4(_mm_cmpgt_ps(nn, _mm_setzero_ps()), _mm_div_ps(ln, _mm_sqrt_ps(nn)), _mm_set1_ps(1.0f));
        dif = pw__select4(_mm_cmpgt_ps(dif, _mm_setzero_ps()), dif, _mm_setzero_ps());
        _mm_storeu_ps(uvl + 3 * PW__BATCH + i,
                      _mm_add_ps(_mm_set1_ps(c->ambient), _mm_mul_ps(_mm_set1_ps(1.0f - c->ambient), dif)));
    }
}
#endif

/* Shades the batch: pixel i is triangle t[i] at sample-grid point (x[i],
 * y[i]): tint x texture (or the caller's shader), lit, premultiplied RGBA
 * into col. Step by step over the batch, each pixel computed as alone.
 * Filtered texture lookups read the 8-bit levels (16-bit sources: the
 * 16-bit ones). */
PW__DEF void pw__shade_batch(const pw__ctx *c, pw__batch *b)
{
    float dx[PW__BATCH], dy[PW__BATCH], iq[PW__BATCH], uvl[4 * PW__BATCH];
    float *u = uvl, *v = uvl + PW__BATCH, *lod = uvl + 2 * PW__BATCH, *lk = uvl + 3 * PW__BATCH;
    const float *pl;
    const int n = b->n, tex = c->tex && !c->d->shader;
    int i, i0 = 0, k;
#ifdef PW__SSE2
    pw__taps4 T4;
    int i4; /* pixels before i4 take their taps four at a time: offsets below 2^31 */
    for (; i0 + 4 <= n; i0 += 4) pw__shade_coords4(c, b, i0, tex, dx, dy, iq, uvl);
    i4 = tex && (size_t)c->tex->w * c->tex->h < ((size_t)1 << 29) ? i0 : 0;
#endif
    for (i = i0; i < n; i++) { /* the perspective divisor */
        float q;
        pl = c->planes + (size_t)b->t[i] * PW__NPL;
        dx[i] = b->x[i] - pl[PW__OX];
        dy[i] = b->y[i] - pl[PW__OY];
        q = pl[0] * dx[i] + pl[1] * dy[i] + pl[2];
        if (!(q > 1e-30f)) q = 1e-30f; /* only reachable through rounding at a near-plane edge */
        iq[i] = 1.0f / q;
    }
    for (i = i0; tex && i < n; i++) { /* texture coordinates and mip level */
        pl = c->planes + (size_t)b->t[i] * PW__NPL;
        u[i] = (pl[3] * dx[i] + pl[4] * dy[i] + pl[5]) * iq[i];
        v[i] = (pl[6] * dx[i] + pl[7] * dy[i] + pl[8]) * iq[i];
        lod[i] = c->filter == PW_FILTER_TRILINEAR ? pw__tex_lod(c, pl, u[i], v[i], iq[i]) : 0.0f;
    }
    for (i = c->lit ? i0 : 0; i < n; i++)
        lk[i] = c->lit ? pw__light(c, c->planes + (size_t)b->t[i] * PW__NPL, dx[i], dy[i]) : 1.0f;
    for (i = 0; i < n; i++) {
        float tx[4] = {1.0f, 1.0f, 1.0f, 1.0f}, *o = b->col + 4 * i;
        if (tex && c->filter == PW_FILTER_NEAREST) {
            pw_texture_sample(c->tex, u[i], v[i], 0.0f, c->filter, c->wrap, tx);
        } else if (tex && c->tex->level8[0]) {
#ifdef PW__SSE2
            if (i < i4 && i % 4 == 0) { /* the taps of pixels i .. i + 3 */
                T4.u = u + i;
                T4.v = v + i;
                T4.lod = lod + i;
                pw__tex_taps8x4(c->tex, c->wrap, 1.0f / 255.0f, &T4);
            }
            if (i < i4) pw__tex_fetch8(c->tex, T4.L[i % 4], T4.p + 8 * (i % 4), T4.w + 8 * (i % 4), tx);
            else pw__tex_trilinear8(c->tex, u[i], v[i], lod[i], c->wrap, 1.0f / 255.0f, tx);
#else
            pw__tex_trilinear8(c->tex, u[i], v[i], lod[i], c->wrap, 1.0f / 255.0f, tx);
#endif
        } else if (tex) { /* a 16-bit source */
            pw__tex_trilinear(c->tex, u[i], v[i], lod[i], c->wrap, tx);
            for (k = 0; k < 4; k++) tx[k] *= 1.0f / 65535.0f;
        } else if (c->d->shader) {
            pw__shade_pt P;
            P.t = b->t[i];
            P.pl = c->planes + (size_t)b->t[i] * PW__NPL;
            P.dx = dx[i];
            P.dy = dy[i];
            P.iq = iq[i];
            pw__shade_custom(c, &P, tx);
        }
#ifdef PW__SSE2
        _mm_storeu_ps(o, _mm_mul_ps(_mm_mul_ps(_mm_loadu_ps(c->tint), _mm_loadu_ps(tx)),
                                    _mm_setr_ps(lk[i], lk[i], lk[i], 1.0f))); /* times 1: exact */
#else
        for (k = 0; k < 3; k++) o[k] = c->tint[k] * tx[k] * lk[i];
        o[3] = c->tint[3] * tx[3];
#endif
    }
}

/* Shades triangle t at sample-grid point (x, y) alone (a batch of one) into
 * out. */
PW__DEF void pw__shade1(const pw__ctx *c, int t, float x, float y, float *out)
{
    pw__batch one;
    one.n = 1;
    one.t[0] = t;
    one.x[0] = x;
    one.y[0] = y;
    pw__shade_batch(c, &one);
    memcpy(out, one.col, 4 * sizeof(float));
}

/* Shades the pending batch and writes it: an opaque draw's pixels get the
 * colour in all their samples, a blended draw's are blended "over" in the
 * samples of their masks (in the order they were queued), with their
 * depths from the row buffer c->qbuf when the draw writes depth (it then
 * flushes every pixel row). */
PW__DEF void pw__batch_flush(pw__ctx *c)
{
    pw__batch *b = c->batch;
    pw_fb *fb = c->fb;
    const int ss = fb->ss, over = c->blend == PW_BLEND_OVER;
    int i, j, k;
    if (!b->n) return;
    pw__shade_batch(c, b);
    for (i = 0; i < b->n; i++) {
        const float *col = b->col + 4 * i, keep = 1.0f - col[3];
        const uint64_t mask = b->mask[i];
        for (j = 0; j < ss; j++) { /* sample row j, sample k of it: bit j ss + k */
            const size_t row = (size_t)(b->py[i] * ss + j - fb->y0) * fb->sw + (size_t)b->px[i] * ss;
            for (k = 0; k < ss; k++) {
                float *d = fb->color + (row + k) * 4;
                if (!over) {
                    memcpy(d, col, 4 * sizeof(float));
                    continue;
                }
                if (!(mask >> (j * ss + k) & 1)) continue;
#ifdef PW__SSE2
                _mm_storeu_ps(d, _mm_add_ps(_mm_loadu_ps(col), _mm_mul_ps(_mm_set1_ps(keep), _mm_loadu_ps(d))));
#else
                d[0] = col[0] + keep * d[0];
                d[1] = col[1] + keep * d[1];
                d[2] = col[2] + keep * d[2];
                d[3] = col[3] + keep * d[3];
#endif
                if (c->dwrite) fb->depth[row + k] = c->qbuf[(size_t)j * fb->sw + (size_t)b->px[i] * ss + k];
            }
        }
    }
    b->n = 0;
}

/* Queues pixel (px, py) of triangle t, shaded at sample-grid point (x, y),
 * with the samples mask (blended draws); flushes a full batch. */
PW__DEF void pw__batch_push(pw__ctx *c, int t, int px, int py, float x, float y, uint64_t mask)
{
    pw__batch *b = c->batch;
    b->t[b->n] = t;
    b->px[b->n] = px;
    b->py[b->n] = py;
    b->x[b->n] = x;
    b->y[b->n] = y;
    b->mask[b->n] = mask;
    if (++b->n == PW__BATCH) pw__batch_flush(c);
}

/* Second phase of an opaque draw: each pixel of the touched box is shaded
 * once per distinct visible triangle, and the visibility ids are reset. */
PW__DEF void pw__shade_vis(pw__ctx *c)
{
    pw_fb *fb = c->fb;
    const int ss = fb->ss, n = ss * ss;
    const int px0 = c->bx0 / ss, py0 = c->by0 / ss, px1 = (c->bx1 + ss - 1) / ss, py1 = (c->by1 + ss - 1) / ss;
    const float half = 0.5f * (float)ss;
    uint32_t ids[PW_FB_MAX_SS * PW_FB_MAX_SS];
    size_t off[PW_FB_MAX_SS * PW_FB_MAX_SS];
    int px, py, k, m;
    for (k = 0; k < n; k++) off[k] = (size_t)(k / ss) * fb->sw + (size_t)(k % ss);
    for (py = py0; py < py1; py++) {
        size_t base = (size_t)(py * ss - fb->y0) * fb->sw + (size_t)px0 * ss;
        for (px = px0; px < px1; px++, base += ss) {
            uint32_t *vis = fb->vis + base, first = vis[0], any = first;
            int same = 1;
            for (k = 0; k < n; k++) {
                ids[k] = vis[off[k]];
                same &= ids[k] == first;
                any &= ids[k];
            }
            if (any == PW_FB_NONE) continue; /* all untouched (the AND of the ids) */
            for (k = 0; k < n; k++) vis[off[k]] = PW_FB_NONE;
            if (same) { /* the usual case: one triangle covers the pixel */
                pw__batch_push(c, (int)first, px, py, (float)(px * ss) + half, (float)(py * ss) + half, 0);
                continue;
            }
            for (k = 0; k < n; k++) {
                float *dst = fb->color + (base + off[k]) * 4;
                if (ids[k] == PW_FB_NONE) continue;
                for (m = 0; m < k && ids[m] != ids[k]; m++) {
                }
                if (m < k) memcpy(dst, fb->color + (base + off[m]) * 4, 4 * sizeof(float));
                else
                    pw__shade1(c, (int)ids[k], (float)(px * ss + k % ss) + 0.5f, (float)(py * ss + k / ss) + 0.5f, dst);
            }
        }
    }
    pw__batch_flush(c);
}

/* Queues pixel (px, py) of a blended draw with the samples of mask (bit
 * j*ss + i: sample i of sample row j) that passed the depth test: shaded at
 * the pixel centre when every sample is covered, else at the first covered
 * sample. */
PW__DEF void pw__over_pixel(pw__ctx *c, int t, int px, int py, uint64_t mask)
{
    const int ss = c->fb->ss, n = ss * ss;
    const uint64_t full = n == 64 ? ~(uint64_t)0 : ((uint64_t)1 << n) - 1;
    int k;
    if (mask == full) {
        pw__batch_push(c, t, px, py, (float)(px * ss) + 0.5f * ss, (float)(py * ss) + 0.5f * ss, mask);
        return;
    }
    for (k = 0; !(mask >> k & 1); k++) {
    }
    pw__batch_push(c, t, px, py, (float)(px * ss + k % ss) + 0.5f, (float)(py * ss + k / ss) + 0.5f, mask);
}

/* One piece of a blended draw, pixel row by pixel row: the depth test marks
 * the passing samples of the ss sample rows in per-pixel masks (keeping
 * their depths), then each marked pixel is queued to be shaded once and
 * blended. Draws that do not write depth keep the queue across rows and
 * triangles (blending in queue order keeps the draw's order, and their
 * depth tests do not depend on what is pending). */
PW__DEF void pw__raster_over(pw__ctx *c, pw_raster_edges *s, int t, const float *pl)
{
    pw_fb *fb = c->fb;
    const int ss = fb->ss;
    const float ox = pl[PW__OX], oy = pl[PW__OY], qx = pl[0], dfac = c->dfac, qfar = c->qfar;
    uint64_t *mask = c->mask;
    int py, j, x, xa, xb, px;
    for (py = s->y0 / ss; py * ss < s->y1; py++) {
        int lo = INT_MAX, hi = INT_MIN;
        for (j = 0; j < ss; j++) {
            const int y = py * ss + j;
            const float qrow = pl[1] * ((float)y + 0.5f - oy) + pl[2];
            const float *dp = fb->depth + (size_t)(y - fb->y0) * fb->sw;
            float *qr = c->qbuf + (size_t)j * fb->sw, fx;
            int i;
            if (y < s->y0 || y >= s->y1 || !pw__raster_row(s, y, &xa, &xb)) continue;
            fx = (float)xa + 0.5f - ox;
            px = xa / ss;
            i = xa - px * ss;
            if (px < lo) lo = px;
            if ((xb - 1) / ss >= hi) hi = (xb - 1) / ss + 1;
            for (x = xa; x < xb; x++, fx += 1.0f) {
                const float q = qx * fx + qrow;
                if (q > dp[x] * dfac && q >= qfar) {
                    qr[x] = q;
                    mask[px] |= (uint64_t)1 << (j * ss + i);
                }
                if (++i == ss) {
                    i = 0;
                    px++;
                }
            }
        }
        for (px = lo; px < hi; px++)
            if (mask[px]) {
                pw__over_pixel(c, t, px, py, mask[px]);
                mask[px] = 0;
            }
        if (c->dwrite) pw__batch_flush(c);
    }
}

/* True if the projected triangle lies entirely on one side of the screen
 * or of the band. */
PW__DEF int pw__offscreen(const pw__ctx *c, const double *p)
{
    double w = c->fb->sw, y0 = c->fb->y0, y1 = c->fb->y0 + c->fb->bh;
    return (p[0] < 0 && p[2] < 0 && p[4] < 0) || (p[0] > w && p[2] > w && p[4] > w) ||
           (p[1] < y0 && p[3] < y0 && p[5] < y0) || (p[1] > y1 && p[3] > y1 && p[5] > y1);
}

/* Builds the coarse depth: the smallest stored q of each tile of the band. */
PW__DEF void pw__zmin_build(pw_fb *fb)
{
    const int tw = (fb->sw + PW__ZT - 1) / PW__ZT;
    int x, y;
    for (x = 0; x < tw * ((fb->bh + PW__ZT - 1) / PW__ZT); x++) fb->zmin[x] = FLT_MAX;
    for (y = 0; y < fb->bh; y++) {
        const float *d = fb->depth + (size_t)y * fb->sw;
        float *z = fb->zmin + (size_t)(y / PW__ZT) * tw;
        for (x = 0; x < fb->sw; x++)
            if (d[x] < z[x / PW__ZT]) z[x / PW__ZT] = d[x];
    }
    fb->zvalid = 1;
}

/* True if triangle h (all in front, screen box p) certainly fails the depth
 * test everywhere: its nearest point (largest q, at a vertex since q is
 * affine on the screen), with a margin for rounding, is behind every stored
 * sample of the tiles under its box. Boxes of many tiles are not tested. */
PW__DEF int pw__hidden(const pw__ctx *c, const double *const *h, const double *p)
{
    const int tw = (c->fb->sw + PW__ZT - 1) / PW__ZT, th = (c->fb->bh + PW__ZT - 1) / PW__ZT;
    double lo[2], hi[2], qmax = 0.0;
    float zm = FLT_MAX;
    int k, t0[2], t1[2], tx, ty;
    for (k = 0; k < 2; k++) {
        double o = k ? c->fb->y0 : 0.0; /* tile rows count from the band's first row */
        lo[k] =
            (p[k] < p[k + 2] ? (p[k] < p[k + 4] ? p[k] : p[k + 4]) : (p[k + 2] < p[k + 4] ? p[k + 2] : p[k + 4])) - o;
        hi[k] =
            (p[k] > p[k + 2] ? (p[k] > p[k + 4] ? p[k] : p[k + 4]) : (p[k + 2] > p[k + 4] ? p[k + 2] : p[k + 4])) - o;
        t0[k] = (int)pw_clampf((float)lo[k], 0.0f, (float)(c->fb->sw + c->fb->sh)) / PW__ZT;
        t1[k] = (int)pw_clampf((float)hi[k], 0.0f, (float)(c->fb->sw + c->fb->sh)) / PW__ZT;
    }
    if (t1[0] >= tw) t1[0] = tw - 1;
    if (t1[1] >= th) t1[1] = th - 1;
    if ((t1[0] - t0[0] + 1) * (t1[1] - t0[1] + 1) > 16) return 0;
    for (k = 0; k < 3; k++)
        if (1.0 / h[k][2] > qmax) qmax = 1.0 / h[k][2];
    for (ty = t0[1]; ty <= t1[1]; ty++)
        for (tx = t0[0]; tx <= t1[0]; tx++)
            if (c->zmin[(size_t)ty * tw + tx] < zm) zm = c->zmin[(size_t)ty * tw + tx];
    return qmax * 1.001 <= (double)zm * c->dfac;
}

/* Triangle t: cull, clip, set up its depth plane and rasterize its pieces. */
PW__DEF void pw__draw_tri(pw__ctx *c, int t)
{
    const int *ix = c->d->tris + 3 * (size_t)t;
    const double *h[3], R = c->grid.range;
    double poly[8], r[3][3], det;
    pw_raster_edges pieces[PW_RASTER_MAX_PIECES];
    float *pl = c->planes + (size_t)t * PW__NPL;
    int k, n = 3, np, nin = 0, nfar = 0, inside = 1;
    for (k = 0; k < 3; k++) {
        h[k] = c->vh + 5 * (size_t)ix[k];
        if (h[k][2] == -DBL_MAX) return;
        nin += h[k][2] >= c->view.znear;
        nfar += h[k][2] > c->view.zfar;
    }
    if (nin == 0 || nfar == 3) return;
    if (nin == 3) {
        for (k = 0; k < 3; k++) {
            poly[2 * k] = h[k][3];
            poly[2 * k + 1] = h[k][4];
            inside &= poly[2 * k] >= -R && poly[2 * k] <= R && poly[2 * k + 1] >= -R && poly[2 * k + 1] <= R;
        }
        if (pw__offscreen(c, poly) || (c->zmin && pw__hidden(c, h, poly))) return;
    } else {
        n = pw__near_clip(c, ix, h, poly);
        inside = 0;
    }
    if (!pw__tri_planes(c, t, poly, n, pl, r, &det)) return;
    /* the usual case (in front, within the raster range) needs no clipping */
    if (inside) { /* narrow triangles find their runs without the row walker */
        np = pw__raster_setup_edges(pieces, &c->grid, poly);
        if (np && pieces[0].x1 - pieces[0].x0 > PW__NARROW) pw__raster_walk_init(pieces);
    } else {
        np = pw_raster_polygon(&c->grid, poly, n, pieces);
    }
    if (np && c->cwrite) pw__attr_planes(c, t, pl, r, det);
    for (k = 0; k < np; k++) {
        if (c->blend == PW_BLEND_OVER && c->cwrite) pw__raster_over(c, pieces + k, t, pl);
        else pw__raster_vis(c, pieces + k, (uint32_t)t, pl);
    }
}

/* Grows the framebuffer's draw scratch for d. */
PW__DEF int pw__draw_scratch(pw_fb *fb, const pw_draw *d, int need_normals, pw_err *e)
{
    size_t oldm = fb->mcap;
    if ((!d->projected &&
         pw_grow(fb->alloc, (void **)&fb->vbuf, &fb->vcap, (size_t)d->nv * 5, sizeof(double), "render vertices", e)) ||
        pw_grow(fb->alloc, (void **)&fb->pbuf, &fb->pcap, (size_t)d->ntris * PW__NPL, sizeof(float),
                "render triangle planes", e) ||
        (need_normals &&
         pw_grow(fb->alloc, (void **)&fb->nbuf, &fb->ncap, (size_t)d->nv * 3, sizeof(float), "render normals", e)))
        return e ? e->code : PW_ERR_NOMEM;
    if (d->blend == PW_BLEND_OVER &&
        (pw_grow(fb->alloc, (void **)&fb->mbuf, &fb->mcap, (size_t)fb->w, sizeof(uint64_t), "render sample masks", e) ||
         pw_grow(fb->alloc, (void **)&fb->qbuf, &fb->qcap, (size_t)fb->sw * fb->ss, sizeof(float),
                 "render sample depths", e)))
        return e ? e->code : PW_ERR_NOMEM;
    if (fb->mcap > oldm) memset(fb->mbuf, 0, fb->mcap * sizeof(uint64_t));
    if (d->no_depth_write && d->depth_test != PW_DEPTH_ALWAYS &&
        pw_grow(fb->alloc, (void **)&fb->zmin, &fb->zcap,
                (size_t)((fb->sw + PW__ZT - 1) / PW__ZT) * ((fb->band_rows * fb->ss + PW__ZT - 1) / PW__ZT),
                sizeof(float), "render coarse depth", e))
        return e ? e->code : PW_ERR_NOMEM;
    return PW_OK;
}

/* Shading and depth constants of a draw. */
PW__DEF void pw__ctx_init(pw__ctx *c, pw_fb *fb, const pw_draw *d)
{
    static const float def_light[3] = {-0.3f, 0.4f, 1.0f};
    const float *l = d->light_dir;
    double lw[3];
    float tol = d->depth_tolerance > 0.0f ? d->depth_tolerance : PW_DEPTH_TOLERANCE;
    int k, cam = d->lighting == PW_LIGHT_CAMERA;
    c->fb = fb;
    c->d = d;
    c->tex = d->tex;
    c->filter = d->filter;
    c->wrap = d->wrap;
    c->blend = d->blend;
    c->cull = d->cull;
    c->lit = d->lighting != PW_LIGHT_NONE;
    c->dwrite = !d->no_depth_write;
    c->cwrite = !d->no_color_write;
    c->ss = (float)fb->ss;
    c->dfac = d->depth_test == PW_DEPTH_LESS ? 1.0f : (d->depth_test == PW_DEPTH_LEQUAL ? 1.0f - tol : 0.0f);
    if (c->dfac < 0.0f) c->dfac = 0.0f;
    c->qfar = (float)(1.0 / c->view.zfar);
    for (k = 0; k < 4; k++) c->tint[k] = d->color[k];
    if (d->color[0] == 0.0f && d->color[1] == 0.0f && d->color[2] == 0.0f && d->color[3] == 0.0f)
        c->tint[0] = c->tint[1] = c->tint[2] = c->tint[3] = 1.0f;
    for (k = 0; k < 3; k++) c->tint[k] *= c->tint[3];
    if (l[0] == 0.0f && l[1] == 0.0f && l[2] == 0.0f) {
        l = def_light;
        cam = 1;
    }
    for (k = 0; k < 3; k++) /* camera space: x right, y up, z toward the viewer */
        lw[k] = cam ? l[0] * c->view.r[k] + l[1] * c->view.u[k] - l[2] * c->view.f[k] : l[k];
    pw_norm3(lw);
    for (k = 0; k < 3; k++) c->light[k] = (float)lw[k];
    c->ambient = d->ambient == 0.0f ? 0.25f : pw_clampf(d->ambient, 0.0f, 1.0f);
    c->bx0 = fb->sw;
    c->by0 = fb->sh;
    c->bx1 = c->by1 = 0;
}

/* Draws the mesh d into fb as seen by cam. Returns PW_OK, or PW_ERR_INVALID
 * (bad camera, index out of range, texture without uvs...), PW_ERR_LIMIT or
 * PW_ERR_NOMEM with nothing drawn. Triangles with non-finite vertices are
 * skipped. */
PW__DEF int pw_render_draw(pw_fb *fb, const pw_camera *cam, const pw_draw *d, pw_err *e)
{
    pw__ctx c;
    pw__batch batch;
    int r, t, need_normals;
    PW_ASSERT(fb && fb->color && cam && d);
    memset(&c, 0, sizeof c);
    batch.n = 0;
    c.batch = &batch;
    if ((r = pw__draw_check(d, e)) != PW_OK) return r;
    if ((r = pw__view_init(&c.view, cam, fb->sw, fb->sh, e)) != PW_OK) return r;
    pw_raster_grid_init(&c.grid, fb->sw, fb->sh);
    c.grid.row0 = fb->y0;
    c.grid.row1 = fb->y0 + fb->bh;
    need_normals = d->lighting != PW_LIGHT_NONE && !d->flat && !d->normals;
    if ((r = pw__draw_scratch(fb, d, need_normals, e)) != PW_OK) return r;
    pw__ctx_init(&c, fb, d);
    if (!d->projected) pw__transform(&c.view, d, fb->vbuf);
    c.vh = d->projected ? d->projected : fb->vbuf;
    c.planes = fb->pbuf;
    c.mask = fb->mbuf;
    c.qbuf = fb->qbuf;
    if (need_normals) pw__smooth_normals(d, fb->nbuf);
    c.normals = (c.lit && !d->flat) ? (d->normals ? d->normals : fb->nbuf) : NULL;
    /* draws that only test depth (the passes of lapped textures) skip the
     * triangles hidden under the coarse depth, kept while nothing writes */
    if (!c.dwrite && d->depth_test != PW_DEPTH_ALWAYS) {
        if (!fb->zvalid) pw__zmin_build(fb);
        c.zmin = fb->zmin;
    } else if (c.dwrite) {
        fb->zvalid = 0;
    }
    for (t = 0; t < d->ntris; t++) pw__draw_tri(&c, t);
    pw__batch_flush(&c); /* a blended draw's last pixels */
    if (c.cwrite && c.blend == PW_BLEND_REPLACE && c.bx1 > c.bx0) pw__shade_vis(&c);
    return PW_OK;
}

/* The smooth vertex normals a lit draw of d without normals computes
 * (area-weighted), allocated (free with pw_free): for a frame drawn in
 * bands, computed once and given to every band's draw (d->normals). NULL if
 * out of memory. */
PW__DEF float *pw_draw_normals(const pw_alloc *a, const pw_draw *d, pw_err *e)
{
    float *n = (float *)pw_alloc_array(a, (size_t)d->nv * 3 + 1, sizeof(float), "vertex normals", e);
    if (n) pw__smooth_normals(d, n);
    return n;
}

/* ---------------------------------------------------------------- frames */

/* Draws one band: the caller's draws into fb (a band of the frame, already
 * cleared). Called once per band, maybe on several threads at once: it may
 * only read what the bands share. */
typedef int (*pw_frame_draw_fn)(void *user, pw_fb *fb, pw_err *e);

typedef struct pw_frame {
    int w, h, ss; /* pixels, samples per pixel side */
    float bg[4];  /* background, straight RGBA */
    int channels; /* of the picture: 3 or 4 (see pw_fb_resolve_band) */
    pw_frame_draw_fn draw;
    void *user;
    const pw_parallel *par; /* NULL: one thread */
} pw_frame;

typedef struct pw__frame_run {
    const pw_alloc *a;
    const pw_frame *f;
    pw_image *out;
    int rows;     /* pixel rows per band */
    int *codes;   /* per band: its result */
    pw_err *errs; /* per band: its message */
} pw__frame_run;

PW__DEF void pw__frame_band(void *ctx, int band)
{
    pw__frame_run *R = (pw__frame_run *)ctx;
    const pw_frame *f = R->f;
    pw_fb fb;
    pw_err_clear(&R->errs[band]);
    R->codes[band] = pw_fb_create_band(R->a, &fb, f->w, f->h, f->ss, R->rows, f->bg, &R->errs[band]);
    if (R->codes[band] != PW_OK) return;
    pw_fb_set_band(&fb, band * R->rows);
    R->codes[band] = f->draw(f->user, &fb, &R->errs[band]);
    if (R->codes[band] == PW_OK) pw_fb_resolve_band(&fb, R->out);
    pw_fb_free(&fb);
}

/* A frame of w x h pixels of ss x ss samples over an opaque background
 * (RGB), an RGB picture, drawn by draw(user) under par (NULL: one thread). */
PW__DEF void pw_frame_init(pw_frame *f, int w, int h, int ss, const float bg[3], const pw_parallel *par)
{
    memset(f, 0, sizeof *f);
    f->w = w;
    f->h = h;
    f->ss = ss;
    memcpy(f->bg, bg, 3 * sizeof(float));
    f->bg[3] = 1.0f;
    f->channels = 3;
    f->par = par;
}

/* Sets d->projected to d's vertices as pw_render_draw projects them under
 * cam into the samples of frame f (allocated: free it with pw_free), so
 * that the draws of every band share one projection. Only the corners of
 * d's triangles are projected when they are fewer than its vertices.
 * PW_OK, PW_ERR_INVALID (the camera) or PW_ERR_NOMEM, d->projected NULL. */
PW__DEF int pw_draw_project(const pw_alloc *a, const pw_frame *f, const pw_camera *cam, pw_draw *d, pw_err *e)
{
    pw__view v;
    double *vh;
    int r;
    d->projected = NULL;
    if ((r = pw__view_init(&v, cam, f->w * f->ss, f->h * f->ss, e)) != PW_OK) return r;
    if (!(vh = (double *)pw_alloc_array(a, (size_t)d->nv * 5 + 1, sizeof(double), "projected vertices", e)))
        return PW_ERR_NOMEM;
    pw__transform(&v, d, vh);
    d->projected = vh;
    return PW_OK;
}

/* The usual band: one draw (pw_frame_draw1 as the user pointer). */
typedef struct pw_frame_draw1 {
    const pw_draw *d;
    const pw_camera *cam;
} pw_frame_draw1;

PW__DEF int pw_frame_draw1_fn(void *user, pw_fb *fb, pw_err *e)
{
    const pw_frame_draw1 *D = (const pw_frame_draw1 *)user;
    return pw_render_draw(fb, D->cam, D->d, e);
}

/* Renders a frame band by band into out (allocated here): the bands are
 * small enough that those under way hold at most a quarter of the frame's
 * samples (24 bytes each: at 2 x 2 samples, 24 bytes per pixel of the frame
 * besides the picture's own 12 or 16), and band-parallel under f->par. The
 * picture is the same, bit for bit, for any band size and thread count:
 * bands split the rows of one sample grid, and every band sees every draw.
 * An error is that of the first failing band. */
PW__DEF int pw_render_frame(const pw_alloc *a, const pw_frame *f, pw_image *out, pw_err *e)
{
    pw__frame_run R;
    int width = pw_parallel_width(f->par), nb, k, r;
    memset(out, 0, sizeof *out);
    if (f->channels != 3 && f->channels != 4)
        return pw_fail(e, PW_ERR_INVALID, "render: %d channels (need 3 or 4)", f->channels);
    if (f->w <= 0 || f->h <= 0 || f->ss < 1 || f->ss > PW_FB_MAX_SS)
        return pw_fail(e, PW_ERR_INVALID, "framebuffer: invalid size %dx%d with %dx%d samples", f->w, f->h, f->ss,
                       f->ss);
    R.rows = (f->h + 4 * width - 1) / (4 * width);
    if (R.rows < 8) R.rows = 8;
    nb = (f->h + R.rows - 1) / R.rows;
    if ((r = pw_image_alloc(a, out, f->w, f->h, f->channels, e)) != PW_OK) return r;
    R.a = a;
    R.f = f;
    R.out = out;
    R.codes = (int *)pw_alloc_array(a, (size_t)nb, sizeof(int), "render bands", e);
    R.errs = R.codes ? (pw_err *)pw_alloc_array(a, (size_t)nb, sizeof(pw_err), "render bands", e) : NULL;
    if (!R.errs) {
        pw_free(a, R.codes);
        pw_image_free(a, out);
        return PW_ERR_NOMEM;
    }
    pw_parallel_for(f->par, nb, pw__frame_band, &R);
    for (k = 0, r = PW_OK; k < nb && r == PW_OK; k++)
        if ((r = R.codes[k]) != PW_OK && e) *e = R.errs[k];
    pw_free(a, R.codes);
    pw_free(a, R.errs);
    if (r != PW_OK) pw_image_free(a, out);
    return r;
}

#endif /* PW_NO_RENDER */

#endif /* PW__RENDER_V1 */
