/* tile3: sampling a material-space tile (Ray et al. 2009, §2: "a 3D
 * texture, indexed by (s,t,m) coordinates, where (s,t) denote the tileable
 * spatial coordinates, and where m denotes the material axis").
 *
 * A pw_tile3 is built from a pw_volume of c = 1-4 channels (gray,
 * gray+alpha, RGB, RGBA), x = W by y = H texels per layer and z = M layers.
 * Each layer becomes a pw_texture (render.h): premultiplied RGBA in 16-bit
 * fixed point with its own box-filtered mip chain, any size, so that the
 * layers never mix within a level and filtering across m is exactly the
 * linear blend between two layers.
 *
 * pw_tile3_sample(tile, s, t, m, lod, out):
 *   s, t  wrap with period 1 in both directions: the tile is periodic, so
 *         s and s + 1 (and s = 0 and s = 1) read the same texels. Texel
 *         (i, j) of a layer (column i, row j counted from the top, as in the
 *         volume and in pw_image) has its centre at
 *         s = (i + 0.5) / W, t = 1 - (j + 0.5) / H: t = 0 is the bottom row
 *         (OBJ/OpenGL convention, as render.h).
 *   m     the material coordinate, clamped to [0, 1] (the paper clamps the
 *         interpolated material, §2.2); layer k sits at m = k / (M - 1) and
 *         m between two layers blends them linearly. One layer ignores m.
 *   lod   log2 of the footprint in level-0 texels (as pw_texture_sample):
 *         bilinear within a level, linear between the two nearest levels,
 *         clamped to the chain (lod <= 0: level 0).
 *   out   premultiplied RGBA in [0, 1] (divide by out[3] for straight
 *         colour); gray is replicated, alpha is 1 without an alpha channel.
 * NaN coordinates read as 0. No libm call on the sampling path: the result
 * is the same on every platform.
 *
 *   pw_tile3_create, pw_tile3_free, pw_tile3_sample */
#ifndef PW__TILE3_V1
#define PW__TILE3_V1

#include "../common/nrrd.h"
#include "../common/render.h"

typedef struct pw_tile3 {
    int w, h;          /* texels per layer, at level 0 */
    int m;             /* layers along the material axis */
    int nlevels;       /* mip levels of every layer */
    pw_texture *layer; /* m textures, layer k at m = k / (m - 1) */
} pw_tile3;

PW__DEF void pw_tile3_free(const pw_alloc *a, pw_tile3 *t)
{
    int k;
    if (!t) return;
    for (k = 0; t->layer && k < t->m; k++) pw_texture_free(a, &t->layer[k]);
    pw_free(a, t->layer);
    memset(t, 0, sizeof *t);
}

/* Builds the tile from vol (x = W, y = H, z = M layers), each layer with a
 * mip chain of at most max_levels levels (0: the full chain down to 1x1).
 * Layers are limited as images are (PW_MAX_IMAGE_DIM, _PIXELS). Free with
 * pw_tile3_free. */
PW__DEF int pw_tile3_create(const pw_alloc *a, pw_tile3 *t, const pw_volume *vol, int max_levels, pw_err *e)
{
    int k, rc;
    memset(t, 0, sizeof *t);
    if ((rc = pw__volume_check(vol, e))) return rc;
    if ((rc = pw__image_check_size("material-space tile", (uint64_t)vol->x, (uint64_t)vol->y, e))) return rc;
    t->layer = (pw_texture *)pw_calloc_array(a, (size_t)vol->z, sizeof(pw_texture), "material-space tile layers", e);
    if (!t->layer) return PW_ERR_NOMEM;
    t->w = vol->x;
    t->h = vol->y;
    t->m = vol->z;
    for (k = 0; k < vol->z && !rc; k++) {
        pw_image img; /* a view of layer k, not a copy */
        img.w = vol->x;
        img.h = vol->y;
        img.c = vol->c;
        img.bits = 8;
        img.px = vol->px + (size_t)k * vol->x * vol->y * vol->c;
        rc = pw_texture_create(a, &t->layer[k], &img, max_levels, e);
    }
    if (rc) {
        pw_tile3_free(a, t);
        return rc;
    }
    t->nlevels = t->layer[0].nlevels;
    return PW_OK;
}

/* Samples the tile at (s, t, m) with mip level lod; see the top of this
 * module. out: premultiplied RGBA in [0, 1]. */
PW__DEF void pw_tile3_sample(const pw_tile3 *tile, float s, float t, float m, float lod, float out[4])
{
    const float scale = 1.0f / 65535.0f;
    float a[4], b[4], p, f = 0.0f;
    int k0 = 0, i;
    if (tile->m > 1) {
        /* clamped (NaN -> 0), then layer k0 and the fraction towards k0 + 1 */
        m = m > 0.0f ? (m < 1.0f ? m : 1.0f) : 0.0f;
        p = m * (float)(tile->m - 1);
        k0 = (int)p;
        if (k0 >= tile->m - 1) k0 = tile->m - 1;
        else f = p - (float)k0;
    }
    pw__tex_trilinear(&tile->layer[k0], s, t, lod, PW_WRAP_REPEAT, a);
    if (f > 0.0f) {
        pw__tex_trilinear(&tile->layer[k0 + 1], s, t, lod, PW_WRAP_REPEAT, b);
        for (i = 0; i < 4; i++) a[i] += f * (b[i] - a[i]);
    }
    for (i = 0; i < 4; i++) out[i] = pw_clampf(a[i] * scale, 0.0f, 1.0f); /* the weights' rounding may pass 1 */
}

#endif /* PW__TILE3_V1 */
