/* util.c: argument parsing and all-or-nothing output files for the CLI. */
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "cli.h"

void cli_error(const char *cmd, const char *fmt, ...)
{
    va_list ap;
    fprintf(stderr, "patchwork %s: ", cmd);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
}

int cli_is(const cli_args *a, const char *name)
{
    size_t n = strlen(name);
    const char *s = a->argv[a->i];
    return !strncmp(s, name, n) && (s[n] == 0 || s[n] == '=');
}

int cli_value(cli_args *a, const char **value)
{
    const char *s = a->argv[a->i], *eq = strchr(s, '=');
    if (eq && !strncmp(s, "--", 2)) {
        *value = eq + 1;
        return 1;
    }
    if (a->i + 1 >= a->argc) {
        cli_error(a->cmd, "%s needs a value", s);
        return 0;
    }
    *value = a->argv[++a->i];
    return 1;
}

int cli_int(cli_args *a, int lo, int hi, int *out)
{
    const char *flag = a->argv[a->i], *v;
    char *end;
    long x;
    if (!cli_value(a, &v)) return 0;
    errno = 0;
    x = strtol(v, &end, 10);
    if (errno || end == v || *end || x < lo || x > hi) {
        cli_error(a->cmd, "%.*s: '%s' is not a whole number in %d..%d", (int)strcspn(flag, "="), flag, v, lo, hi);
        return 0;
    }
    *out = (int)x;
    return 1;
}

int cli_float(cli_args *a, float lo, float hi, float *out)
{
    const char *flag = a->argv[a->i], *v;
    char *end;
    if (!cli_value(a, &v)) return 0;
    *out = strtof(v, &end);
    if (end == v || *end || !(*out >= lo && *out <= hi)) {
        int n = (int)strcspn(flag, "=");
        if (hi >= 1e20f && lo <= -1e20f) cli_error(a->cmd, "%.*s: '%s' is not a finite number", n, flag, v);
        else if (hi >= 1e20f && lo > 0.0f && lo <= 1e-20f)
            cli_error(a->cmd, "%.*s: '%s' is not a positive number", n, flag, v);
        else cli_error(a->cmd, "%.*s: '%s' is not a number in %g..%g", n, flag, v, (double)lo, (double)hi);
        return 0;
    }
    return 1;
}

int cli_u64(cli_args *a, unsigned long long *out)
{
    const char *flag = a->argv[a->i], *v;
    char *end;
    if (!cli_value(a, &v)) return 0;
    errno = 0;
    *out = strtoull(v, &end, 10);
    if (errno || end == v || *end || *v == '-') {
        cli_error(a->cmd, "%.*s: '%s' is not a non-negative whole number", (int)strcspn(flag, "="), flag, v);
        return 0;
    }
    return 1;
}

int cli_size(cli_args *a, int *w, int *h)
{
    const char *v;
    char *end, *end2;
    long x, y;
    if (!cli_value(a, &v)) return 0;
    x = strtol(v, &end, 10);
    y = (*end == 'x' || *end == 'X') ? strtol(end + 1, &end2, 10) : -1;
    if (y < 0 || *end2 || x < 16 || y < 16 || x > 8192 || y > 8192) {
        cli_error(a->cmd, "--size: '%s' is not WIDTHxHEIGHT with both in 16..8192", v);
        return 0;
    }
    *w = (int)x;
    *h = (int)y;
    return 1;
}

int cli_parse_vec3(const char *v, float out[3])
{
    const char *p = v;
    char *end;
    int k;
    for (k = 0; k < 3; k++) {
        while (*p == ' ' || (k > 0 && *p == ',')) p++;
        out[k] = strtof(p, &end);
        if (end == p || !(out[k] == out[k] && out[k] - out[k] == 0.0f)) return 0;
        p = end;
    }
    while (*p == ' ') p++;
    return !*p;
}

/* A direction: three finite numbers, not all zero. */
static int vec3(const char *v, float *out)
{
    return cli_parse_vec3(v, out) && (out[0] != 0.0f || out[1] != 0.0f || out[2] != 0.0f);
}

int cli_vec3(cli_args *a, float out[3])
{
    const char *flag = a->argv[a->i], *v;
    if (!cli_value(a, &v)) return 0;
    if (vec3(v, out)) return 1;
    cli_error(a->cmd, "%.40s: '%s' is not a direction X,Y,Z (three finite numbers, not all zero)", flag, v);
    return 0;
}

int cli_view_flag(cli_args *a, float view_dir[3], float up[3], int *supersample, int *threads)
{
    static const char *const axes[6] = {"x", "y", "z", "-x", "-y", "-z"};
    const char *v;
    int k;
    if (cli_is(a, "--supersample")) return cli_int(a, 1, 8, supersample);
    if (cli_is(a, "--threads")) return cli_int(a, 1, 256, threads);
    if (cli_is(a, "--view")) return cli_vec3(a, view_dir);
    if (!cli_is(a, "--view-up")) return -1;
    if (!cli_value(a, &v)) return 0;
    for (k = 0; k < 6; k++)
        if (!strcmp(v, axes[k])) {
            up[0] = up[1] = up[2] = 0.0f;
            up[k % 3] = k < 3 ? 1.0f : -1.0f;
            return 1;
        }
    if (vec3(v, up)) return 1;
    cli_error(a->cmd, "--view-up: '%s' is not x, y, z, -x, -y, -z or X,Y,Z", v);
    return 0;
}

int cli_is_procedural(const char *s, const char **name)
{
    if (strncmp(s, "procedural:", 11)) return 0;
    *name = s + 11;
    return 1;
}

int cli_staged(const cli_outputs *o, const char *path)
{
    int k;
    for (k = 0; k < o->n; k++)
        if (!strcmp(o->final_path[k], path)) return 1;
    return 0;
}

const char *cli_stage(cli_outputs *o, const char *path)
{
    if (o->n >= 16 || strlen(path) + 9 > sizeof o->final_path[0] || cli_staged(o, path)) return NULL;
    strcpy(o->final_path[o->n], path);
    snprintf(o->tmp_path[o->n], sizeof o->tmp_path[0], "%s.partial", path);
    return o->tmp_path[o->n++];
}

tiled_result cli_commit(cli_outputs *o, tiled_error *err)
{
    int k;
    for (k = 0; k < o->n; k++)
        if (rename(o->tmp_path[k], o->final_path[k]) != 0) {
            err->code = TILED_ERR_IO;
            snprintf(err->message, sizeof err->message,
                     "%.200s: cannot move the finished file "
                     "into place (%s)",
                     o->final_path[k], strerror(errno));
            for (; k < o->n; k++) remove(o->tmp_path[k]);
            return err->code;
        }
    return TILED_OK;
}

void cli_abort(cli_outputs *o)
{
    int k;
    for (k = 0; k < o->n; k++) remove(o->tmp_path[k]);
    o->n = 0;
}

int cli_finish(const char *cmd, cli_outputs *o, int failed, const char *message)
{
    tiled_error err;
    if (failed) {
        cli_abort(o);
        cli_error(cmd, "%s", message);
        return 1;
    }
    if (cli_commit(o, &err) != TILED_OK) {
        cli_error(cmd, "%s", err.message);
        return 1;
    }
    return 0;
}

/* Whether path ends in ext, ignoring case. */
static int has_ext(const char *path, const char *ext)
{
    size_t n = strlen(path), m = strlen(ext), i;
    if (n < m) return 0;
    for (i = 0; i < m; i++) {
        char c = path[n - m + i];
        if ((c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c) != ext[i]) return 0;
    }
    return 1;
}

/* Whether a file can be created where path names one: the staged
 * temporary name is created and removed again. 0 with errno set if not. */
static int writable(const char *path)
{
    char tmp[1100];
    FILE *f;
    snprintf(tmp, sizeof tmp, "%.1000s.partial", path);
    if (!(f = fopen(tmp, "wb"))) return 0;
    fclose(f);
    remove(tmp);
    return 1;
}

int cli_check_outputs(const char *cmd, const cli_out *outs, int n)
{
    static const char *const need[] = {NULL,
                                       "an image (.png .ppm .pgm .pam)",
                                       "an .obj file",
                                       "a .glb file (binary glTF)",
                                       "a .nrrd file",
                                       "a .pam file",
                                       "a prefix (written as PREFIX_00.png, ...)"};
    int k;
    for (k = 0; k < n; k++) {
        const cli_out *o = &outs[k];
        int ok;
        if (!o->path) continue;
        switch (o->kind) {
        case CLI_OUT_IMAGE: ok = cli_image_format(o->path) != NULL; break;
        case CLI_OUT_OBJ: ok = has_ext(o->path, ".obj"); break;
        case CLI_OUT_GLB: ok = has_ext(o->path, ".glb"); break;
        case CLI_OUT_NRRD: ok = has_ext(o->path, ".nrrd"); break;
        case CLI_OUT_PAM: ok = has_ext(o->path, ".pam"); break;
        default: ok = 1;
        }
        if (!ok) {
            cli_error(cmd, "%s %s: give %s", o->flag, o->path, need[o->kind]);
            return 0;
        }
        if (!writable(o->path)) {
            cli_error(cmd, "%s %s: cannot write there (%s)", o->flag, o->path, strerror(errno));
            return 0;
        }
    }
    return 1;
}

const char *cli_image_format(const char *path)
{
    static const char *const ext[] = {".png", "png", ".ppm", "ppm", ".pnm", "ppm", ".pgm", "pgm", ".pam", "pam"};
    size_t k;
    for (k = 0; k < sizeof ext / sizeof ext[0]; k += 2)
        if (has_ext(path, ext[k])) return ext[k + 1];
    return NULL;
}

int cli_fwrite(void *ctx, const void *data, size_t size) { return fwrite(data, 1, size, (FILE *)ctx) == size ? 0 : -1; }

FILE *cli_open(cli_outputs *o, const char *path, char *msg, size_t size)
{
    const char *tmp;
    FILE *f;
    if (cli_staged(o, path)) {
        snprintf(msg, size, "%.200s: named by two outputs", path);
        return NULL;
    }
    tmp = cli_stage(o, path);
    f = tmp ? fopen(tmp, "wb") : NULL;
    if (!f)
        snprintf(msg, size, "%.200s: cannot open for writing (%s)", path, tmp ? strerror(errno) : "too many outputs");
    return f;
}

int cli_close(FILE *f, int ok, const char *path, char *msg, size_t size)
{
    if (fclose(f) != 0 && ok) {
        snprintf(msg, size, "%.200s: write error (disk full?)", path);
        return 0;
    }
    return ok;
}

tiled_image cli_image_view(int width, int height, int channels, float *pixels, int bits)
{
    tiled_image v;
    memset(&v, 0, sizeof v);
    v.width = width;
    v.height = height;
    v.channels = channels;
    v.pixels = pixels;
    v.bits = bits;
    return v;
}

int cli_write_view(cli_outputs *o, const char *final_path, const tiled_image *view, char message[256])
{
    tiled_error err;
    if (cli_write_image(o, final_path, view, &err) == TILED_OK) return 0;
    memcpy(message, err.message, sizeof err.message);
    return (int)err.code;
}

tiled_result cli_write_image(cli_outputs *o, const char *final_path, const tiled_image *img, tiled_error *err)
{
    const char *fmt = cli_image_format(final_path);
    tiled_result r;
    FILE *f;
    if (!fmt) {
        err->code = TILED_ERR_UNSUPPORTED;
        snprintf(err->message, sizeof err->message, "%.200s: unknown image extension (use .png, .ppm, .pgm, .pam)",
                 final_path);
        return err->code;
    }
    if (!(f = cli_open(o, final_path, err->message, sizeof err->message))) return err->code = TILED_ERR_IO;
    r = tiled_write_image(img, fmt, cli_fwrite, f, err);
    if (r == TILED_ERR_IO) snprintf(err->message, sizeof err->message, "%.200s: write error (disk full?)", final_path);
    if (!cli_close(f, r == TILED_OK, final_path, err->message, sizeof err->message)) r = TILED_ERR_IO;
    return err->code = r;
}

/* `path` with its extension replaced by `ext`. */
void cli_with_ext(const char *path, const char *ext, char *out, size_t size)
{
    const char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
    size_t n = dot && (!slash || dot > slash) ? (size_t)(dot - path) : strlen(path);
    snprintf(out, size, "%.*s%s", (int)n, path, ext);
}

/* The MTL names the texture by its path relative to the OBJ's folder when
 * both are in the same folder, else by the path as given. */
const char *cli_texture_ref(const char *obj, const char *texture)
{
    const char *so = strrchr(obj, '/'), *st = strrchr(texture, '/');
    size_t lo = so ? (size_t)(so - obj) : 0, lt = st ? (size_t)(st - texture) : 0;
    if (lo == lt && !strncmp(obj, texture, lo)) return st ? st + 1 : texture;
    return texture;
}
