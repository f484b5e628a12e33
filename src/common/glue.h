/* glue: what every method header needs between its public types and the
 * shared core.
 *
 * Each header has its own prefixed public types (tiled_image, lapped_image,
 * ...) with the same fields, so that a program can include several headers
 * without clashes. The logic that deals with them (checking a caller's
 * image, encoding an image in a named format) works on the shared pw_ types
 * here; PW_PUBLIC_GLUE(prefix) then writes the field-by-field conversions
 * once for every header. */
#ifndef PW__GLUE_V1
#define PW__GLUE_V1

#include "base.h"
#include "image.h"
#include "png.h"
#include "mesh.h"
#include "render.h"

/* Checks an image that came from a caller: size, channel count, and every
 * sample a finite number. `what` names it in the message. */
PW__DEF int pw_image_validate(const pw_image *im, const char *what, pw_err *e)
{
    size_t k, n;
    if (!im->px || im->w < 1 || im->h < 1 || im->c < 1 || im->c > 4)
        return pw_fail(e, PW_ERR_INVALID, "%s: empty image or bad channel count", what);
    if (im->w > PW_MAX_IMAGE_DIM || im->h > PW_MAX_IMAGE_DIM || (int64_t)im->w * im->h > PW_MAX_IMAGE_PIXELS)
        return pw_fail(e, PW_ERR_LIMIT, "%s: %dx%d pixels is over the limit", what, im->w, im->h);
    n = (size_t)im->w * im->h * im->c;
    for (k = 0; k < n; k++)
        if (!pw_is_finite(im->px[k]))
            return pw_fail(e, PW_ERR_INVALID, "%s: pixel %lu is not a finite number", what, (unsigned long)(k / im->c));
    return PW_OK;
}

/* Encodes an image as "png", "pam", "ppm" or "pgm", converting the channels
 * to what PPM (3) and PGM (1) hold. */
PW__DEF int pw_image_encode(const pw_alloc *a, const pw_image *img, const char *format, pw_write_fn fn, void *ctx,
                            pw_err *e)
{
    pw_image conv;
    int want = 0, r;
    if (!format) return pw_fail(e, PW_ERR_INVALID, "no image format given");
    if (!strcmp(format, "ppm")) want = 3;
    else if (!strcmp(format, "pgm")) want = 1;
    else if (strcmp(format, "png") && strcmp(format, "pam"))
        return pw_fail(e, PW_ERR_UNSUPPORTED, "unknown image format '%s' (png, ppm, pgm, pam)", format);
    if (want && want != img->c) {
        if ((r = pw_image_convert(a, img, want, &conv, e)) != PW_OK) return r;
        r = pw_image_write_pnm(&conv, 0, 0, fn, ctx, e);
        pw_image_free(a, &conv);
        return r;
    }
    if (want) return pw_image_write_pnm(img, 0, 0, fn, ctx, e);
    if (!strcmp(format, "pam")) return pw_image_write_pam(img, 0, fn, ctx, e);
    return pw_png_write(a, img, 0, fn, ctx, e);
}

#ifndef PW_NO_STDIO
typedef struct pw__encode_job {
    const pw_alloc *a;
    const pw_image *img;
    const char *format;
} pw__encode_job;

PW__DEF int pw__encode_body(void *arg, pw_write_fn w, void *ctx, pw_err *e)
{
    const pw__encode_job *j = (const pw__encode_job *)arg;
    return pw_image_encode(j->a, j->img, j->format, w, ctx, e);
}

/* What every X_save_image does: img (a caller's, or NULL: checked, the
 * path names it in messages) in the format path's extension names
 * (pw_image_format_of), converted to the channels that format holds
 * (pw_image_encode). */
PW__DEF int pw_image_save_as(const pw_alloc *a, const char *path, const pw_image *img, pw_err *e)
{
    pw__encode_job j;
    int r;
    j.a = a;
    j.img = img;
    j.format = pw_image_format_of(path);
    if (!j.format)
        return pw_fail(e, PW_ERR_UNSUPPORTED, "%s: unknown image extension (use .png, .ppm, .pgm, .pam)", path);
    if (!img) return pw_fail(e, PW_ERR_INVALID, "%s: empty image (none given)", path);
    if ((r = pw_image_validate(img, path, e)) != PW_OK) return r;
    return pw_write_file(path, pw__encode_body, &j, e);
}
#endif

/* Fills the zero fields of a view (public render options) with the
 * defaults every method shares: 800x600, 2x2 supersampling, looking along
 * (-0.55,-0.45,-0.7) with +Y up, on white. */
PW__DEF void pw_view_defaults(int *width, int *height, int *supersample, float view_dir[3], float up[3],
                              float background[3])
{
    static const float view[3] = {-0.55f, -0.45f, -0.7f}, y[3] = {0.0f, 1.0f, 0.0f};
    if (!*width) *width = 800;
    if (!*height) *height = 600;
    if (!*supersample) *supersample = 2;
    if (!view_dir[0] && !view_dir[1] && !view_dir[2]) memcpy(view_dir, view, sizeof view);
    if (!up[0] && !up[1] && !up[2]) memcpy(up, y, sizeof y);
    if (!background[0] && !background[1] && !background[2]) background[0] = background[1] = background[2] = 1.0f;
}

/* PW_PUBLIC_GLUE(p) defines, for a header whose public types are
 * p_allocator, p_image, p_error and p_result (fields as in tiled.h):
 *   pw_alloc    p__alloc(const p_allocator *)       a shared allocator (NULL: default)
 *   p_allocator p__allocator(const pw_alloc *)      and back
 *   p_result    p__done(const pw_err *, p_error *)  copies an error out, returns its code
 *   pw_image    p__pw_image(const p_image *)        a view, no copy
 *   void        p__take_image(pw_image *, const pw_alloc *, p_image *)  moves pixels out
 *   pw_mesh     p__pw_mesh(const p_mesh *)          a view of the shared fields, no copy
 *   int         p__check_image(const p_image *, const char *what, pw_err *)
 *   int         p__encode(const p_image *, const char *format, pw_write_fn, void *, pw_err *)
 *   p_result    p__left_out(const char *what, const char *macro, p_error *)
 *               PW_ERR_UNSUPPORTED, "what compiled out (macro)": the stubs that stand
 *               for the calls PW_NO_RENDER leaves out */
#define PW_PUBLIC_GLUE(p)                                                                                           \
    static PW__UNUSED pw_alloc p##__alloc(const p##_allocator *t)                                                   \
    {                                                                                                               \
        pw_alloc a;                                                                                                 \
        memset(&a, 0, sizeof a);                                                                                    \
        if (t) {                                                                                                    \
            a.malloc_fn = t->malloc_fn;                                                                             \
            a.realloc_fn = t->realloc_fn;                                                                           \
            a.free_fn = t->free_fn;                                                                                 \
            a.user = t->user;                                                                                       \
        }                                                                                                           \
        return a;                                                                                                   \
    }                                                                                                               \
    static PW__UNUSED p##_allocator p##__allocator(const pw_alloc *a)                                               \
    {                                                                                                               \
        p##_allocator t;                                                                                            \
        t.malloc_fn = a->malloc_fn;                                                                                 \
        t.realloc_fn = a->realloc_fn;                                                                               \
        t.free_fn = a->free_fn;                                                                                     \
        t.user = a->user;                                                                                           \
        return t;                                                                                                   \
    }                                                                                                               \
    static PW__UNUSED p##_result p##__done(const pw_err *pe, p##_error *err)                                        \
    {                                                                                                               \
        if (err) {                                                                                                  \
            err->code = (p##_result)pe->code;                                                                       \
            memcpy(err->message, pe->msg, sizeof err->message);                                                     \
        }                                                                                                           \
        return (p##_result)pe->code;                                                                                \
    }                                                                                                               \
    static PW__UNUSED pw_image p##__pw_image(const p##_image *t)                                                    \
    {                                                                                                               \
        pw_image v;                                                                                                 \
        v.w = t->width;                                                                                             \
        v.h = t->height;                                                                                            \
        v.c = t->channels;                                                                                          \
        v.bits = t->bits ? t->bits : 8;                                                                             \
        v.px = t->pixels;                                                                                           \
        return v;                                                                                                   \
    }                                                                                                               \
    static PW__UNUSED void p##__take_image(pw_image *v, const pw_alloc *a, p##_image *t)                            \
    {                                                                                                               \
        t->width = v->w;                                                                                            \
        t->height = v->h;                                                                                           \
        t->channels = v->c;                                                                                         \
        t->bits = v->bits;                                                                                          \
        t->pixels = v->px;                                                                                          \
        t->allocator = p##__allocator(a);                                                                           \
        memset(v, 0, sizeof *v);                                                                                    \
    }                                                                                                               \
    static PW__UNUSED int p##__check_image(const p##_image *t, const char *what, pw_err *e)                         \
    {                                                                                                               \
        pw_image v;                                                                                                 \
        if (!t) return pw_fail(e, PW_ERR_INVALID, "%s: empty image (none given)", what);                            \
        v = p##__pw_image(t);                                                                                       \
        return pw_image_validate(&v, what, e);                                                                      \
    }                                                                                                               \
    static PW__UNUSED int p##__encode(const p##_image *t, const char *format, pw_write_fn fn, void *ctx, pw_err *e) \
    {                                                                                                               \
        pw_image v = p##__pw_image(t);                                                                              \
        pw_alloc a = p##__alloc(&t->allocator);                                                                     \
        return pw_image_encode(&a, &v, format, fn, ctx, e);                                                         \
    }                                                                                                               \
    static PW__UNUSED pw_mesh p##__pw_mesh(const p##_mesh *t)                                                       \
    {                                                                                                               \
        pw_mesh m;                                                                                                  \
        memset(&m, 0, sizeof m);                                                                                    \
        m.nv = t->nverts;                                                                                           \
        m.pos = t->positions;                                                                                       \
        m.nf = t->nfaces;                                                                                           \
        m.fstart = t->face_start;                                                                                   \
        m.fv = t->face_verts;                                                                                       \
        return m;                                                                                                   \
    }                                                                                                               \
    static PW__UNUSED void p##__take_mesh(pw_mesh *m, const pw_alloc *a, p##_mesh *t)                               \
    {                                                                                                               \
        memset(t, 0, sizeof *t);                                                                                    \
        t->nverts = m->nv;                                                                                          \
        t->positions = m->pos;                                                                                      \
        t->nfaces = m->nf;                                                                                          \
        t->face_start = m->fstart;                                                                                  \
        t->face_verts = m->fv;                                                                                      \
        t->allocator = p##__allocator(a);                                                                           \
        pw_free(a, m->uv);                                                                                          \
        pw_free(a, m->fuv);                                                                                         \
        memset(m, 0, sizeof *m);                                                                                    \
    }                                                                                                               \
    static PW__UNUSED p##_result p##__left_out(const char *what, const char *macro, p##_error *err)                 \
    {                                                                                                               \
        pw_err pe;                                                                                                  \
        pw_err_clear(&pe);                                                                                          \
        pw_fail(&pe, PW_ERR_UNSUPPORTED, "%s compiled out (%s)", what, macro);                                      \
        return p##__done(&pe, err);                                                                                 \
    }                                                                                                               \
    static PW__UNUSED pw_parallel p##__parallel(const p##_render_options *ro)                                       \
    {                                                                                                               \
        return pw_parallel_make(ro->threads, ro->parallel, ro->parallel_pool);                                      \
    }                                                                                                               \
    typedef int p##__glue_defined /* so that the use ends with a semicolon */

/* PW_PUBLIC_IO(p, DEF) defines the public mesh and image I/O that every
 * header has, written once (DEF: the header's XDEF; the header's p_mesh
 * has the shared fields, p_write_fn is a pw_write_fn):
 *   DEF p_result p_read_mesh(const void *data, size_t size, const char *name, const p_options *, p_mesh *, p_error *)
 *   DEF p_result p_read_image(const void *data, size_t size, const char *name, const p_options *, p_image *,
 *                             p_error *)
 *   DEF p_result p_write_image(const p_image *, const char *format, p_write_fn, void *ctx, p_error *)
 * A reader takes the format from the bytes (a mesh: from the name's
 * extension when the bytes do not say), and the name in its messages.
 * PW_PUBLIC_READ(p, DEF, what, pwT, T, read, take) is one such reader,
 *   DEF p_result p_read_WHAT(const void *data, size_t size, const char *name, const p_options *, T *out, p_error *)
 * through the shared read(alloc, bytes, size, name, pwT *, pw_err *) and
 * take(pwT *, alloc, T *out), which moves the result into the public type. */
#define PW_PUBLIC_READ(p, DEF, what, pwT, T, read, take)                                                            \
    DEF p##_result p##_read_##what(const void *data, size_t size, const char *name, const p##_options *opt, T *out, \
                                   p##_error *err)                                                                  \
    {                                                                                                               \
        p##_options o = p##__options(opt);                                                                          \
        pw_alloc a = p##__alloc(&o.allocator);                                                                      \
        pwT v;                                                                                                      \
        pw_err pe;                                                                                                  \
        pw_err_clear(&pe);                                                                                          \
        if (out) memset(out, 0, sizeof *out);                                                                       \
        if (!out || (!data && size)) pw_fail(&pe, PW_ERR_INVALID, #p "_read_" #what ": NULL argument");             \
        else if (read(&a, (const unsigned char *)data, size, name ? name : #what, &v, &pe) == PW_OK)                \
            take(&v, &a, out);                                                                                      \
        return p##__done(&pe, err);                                                                                 \
    }                                                                                                               \
    typedef int p##__read_##what##_defined /* so that the use ends with a semicolon */
#define PW_PUBLIC_IO(p, DEF)                                                                             \
    PW_PUBLIC_READ(p, DEF, mesh, pw_mesh, p##_mesh, pw_mesh_read_memory, p##__take_mesh);                \
    PW_PUBLIC_READ(p, DEF, image, pw_image, p##_image, pw_image_read_memory, p##__take_image);           \
    DEF p##_result p##_write_image(const p##_image *img, const char *format, p##_write_fn fn, void *ctx, \
                                   p##_error *err)                                                       \
    {                                                                                                    \
        pw_err pe;                                                                                       \
        pw_err_clear(&pe);                                                                               \
        if (!fn) pw_fail(&pe, PW_ERR_INVALID, #p "_write_image: NULL writer");                           \
        else if (p##__check_image(img, "image", &pe) == PW_OK) p##__encode(img, format, fn, ctx, &pe);   \
        return p##__done(&pe, err);                                                                      \
    }                                                                                                    \
    typedef int p##__io_defined /* so that the use ends with a semicolon */

/* PW_PUBLIC_LOAD(p, DEF, what, T) defines the public loader of a file
 * (DEF: the header's XDEF), which every header writes the same way: the
 * whole file read, then handed to the header's own from-memory reader,
 *   DEF p_result p_load_WHAT(const char *path, const p_options *, T *out, p_error *)
 * reads path with p_read_WHAT (the path names the file in messages and
 * gives the format by its extension). A reader's warning on success (a
 * message with code 0) reaches the caller as well. Needs p__options and
 * stdio (not PW_NO_STDIO). */
#define PW_PUBLIC_LOAD(p, DEF, what, T)                                                              \
    DEF p##_result p##_load_##what(const char *path, const p##_options *opt, T *out, p##_error *err) \
    {                                                                                                \
        p##_options o = p##__options(opt);                                                           \
        pw_alloc a = p##__alloc(&o.allocator);                                                       \
        unsigned char *data;                                                                         \
        size_t size;                                                                                 \
        pw_err pe;                                                                                   \
        pw_err_clear(&pe);                                                                           \
        if (out) memset(out, 0, sizeof *out);                                                        \
        if (!path || !out) pw_fail(&pe, PW_ERR_INVALID, #p "_load_" #what ": NULL argument");        \
        else if (pw_read_file(&a, path, &data, &size, &pe) == PW_OK) {                               \
            p##_error le;                                                                            \
            memset(&le, 0, sizeof le);                                                               \
            if (p##_read_##what(data, size, path, &o, out, &le) != 0 || le.message[0])               \
                pw_fail(&pe, (int)le.code, "%s", le.message);                                        \
            pw_free(&a, data);                                                                       \
        }                                                                                            \
        return p##__done(&pe, err);                                                                  \
    }                                                                                                \
    typedef int p##__load_##what##_defined /* so that the use ends with a semicolon */

/* PW_PUBLIC_SAVE_IMAGE(p, DEF) defines
 *   DEF p_result p_save_image(const char *path, const p_image *img, p_error *)
 * with pw_image_save_as: the format by the extension, no file left on
 * failure. */
#define PW_PUBLIC_SAVE_IMAGE(p, DEF)                                                      \
    DEF p##_result p##_save_image(const char *path, const p##_image *img, p##_error *err) \
    {                                                                                     \
        pw_image v;                                                                       \
        pw_alloc a;                                                                       \
        pw_err pe;                                                                        \
        pw_err_clear(&pe);                                                                \
        memset(&a, 0, sizeof a);                                                          \
        if (img) {                                                                        \
            v = p##__pw_image(img);                                                       \
            a = p##__alloc(&img->allocator);                                              \
        }                                                                                 \
        if (!path) pw_fail(&pe, PW_ERR_INVALID, #p "_save_image: NULL path");             \
        else pw_image_save_as(&a, path, img ? &v : NULL, &pe);                            \
        return p##__done(&pe, err);                                                       \
    }                                                                                     \
    typedef int p##__save_image_defined /* so that the use ends with a semicolon */

/* The public frees of an image and of a mesh with the shared fields only
 * (DEF: the header's XDEF): with the allocator the object remembers, then
 * zeroed; NULL and zeroed objects are fine. */
#define PW_PUBLIC_IMAGE_FREE(p, DEF)        \
    DEF void p##_image_free(p##_image *img) \
    {                                       \
        pw_alloc a;                         \
        if (!img) return;                   \
        a = p##__alloc(&img->allocator);    \
        pw_free(&a, img->pixels);           \
        memset(img, 0, sizeof *img);        \
    }                                       \
    typedef int p##__image_free_defined
#define PW_PUBLIC_MESH_FREE(p, DEF)     \
    DEF void p##_mesh_free(p##_mesh *m) \
    {                                   \
        pw_alloc a;                     \
        if (!m) return;                 \
        a = p##__alloc(&m->allocator);  \
        pw_free(&a, m->positions);      \
        pw_free(&a, m->face_start);     \
        pw_free(&a, m->face_verts);     \
        memset(m, 0, sizeof *m);        \
    }                                   \
    typedef int p##__mesh_free_defined

#endif /* PW__GLUE_V1 */
