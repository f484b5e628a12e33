/* image: float images and their file formats.
 *
 * A pw_image holds w*h pixels of c channels (1 gray, 2 gray+alpha, 3 RGB,
 * 4 RGBA) as floats in [0,1], row 0 at the top (file order). Texture
 * lookups use the OBJ/OpenGL convention: v = 0 is the bottom row. `bits`
 * remembers the sample depth of the source (8 or 16) so that a round trip
 * writes what was read. */
#ifndef PW__IMAGE_V1
#define PW__IMAGE_V1

typedef struct pw_image {
    int w, h, c;
    int bits;
    float *px; /* w*h*c, px[(y*w + x)*c + k] */
} pw_image;

/* Allocates a zeroed w x h x c image (bits = 8). Checks the limits. */
PW__DEF int pw_image_alloc(const pw_alloc *a, pw_image *img, int w, int h, int c, pw_err *e)
{
    memset(img, 0, sizeof *img);
    if (w <= 0 || h <= 0 || c < 1 || c > 4)
        return pw_fail(e, PW_ERR_INVALID, "invalid image size %dx%d with %d channels", w, h, c);
    if (w > PW_MAX_IMAGE_DIM || h > PW_MAX_IMAGE_DIM || (int64_t)w * h > PW_MAX_IMAGE_PIXELS)
        return pw_fail(e, PW_ERR_LIMIT, "image %dx%d exceeds the limit of %d pixels", w, h,
                       PW_MAX_IMAGE_PIXELS);
    img->px = (float *)pw_calloc_array(a, (size_t)w * h * c, sizeof(float), "image", e);
    if (!img->px) return PW_ERR_NOMEM;
    img->w = w;
    img->h = h;
    img->c = c;
    img->bits = 8;
    return PW_OK;
}

PW__DEF void pw_image_free(const pw_alloc *a, pw_image *img)
{
    if (!img) return;
    pw_free(a, img->px);
    memset(img, 0, sizeof *img);
}

#endif /* PW__IMAGE_V1 */
