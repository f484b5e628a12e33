/* cli.h: shared helpers of the `patchwork` command. */
#ifndef PATCHWORK_CLI_H
#define PATCHWORK_CLI_H

#include <stdio.h>
#include "../tiled.h"
#include "../lapped.h"
#include "../pgp.h"
#include "../lst.h"

/* Argument cursor: `patchwork SUB --flag value ...`. */
typedef struct cli_args {
    int argc, i;
    char **argv;
    const char *cmd; /* subcommand name, for messages */
} cli_args;

/* Reports an error as one line on stderr: "patchwork CMD: message". */
void cli_error(const char *cmd, const char *fmt, ...);

/* Parses the value of the current flag (argv[i], possibly --flag=value).
 * On error prints a message and returns 0. */
int cli_value(cli_args *a, const char **value);
int cli_int(cli_args *a, int lo, int hi, int *out);
/* A finite number in lo..hi; the message gives the range. */
int cli_float(cli_args *a, float lo, float hi, float *out);
int cli_u64(cli_args *a, unsigned long long *out);
int cli_size(cli_args *a, int *w, int *h);
/* Three finite numbers "X,Y,Z" (commas or blanks between them) and nothing
 * else: 1, else 0. */
int cli_parse_vec3(const char *s, float out[3]);
/* A direction "X,Y,Z" (finite, not all zero). */
int cli_vec3(cli_args *a, float out[3]);
/* The view flags of every subcommand that renders: --view X,Y,Z, the
 * direction the camera looks along; --view-up, the world direction shown
 * upwards: X,Y,Z or an axis (x, y, z, -x, -y, -z; z for the Z-up scans of
 * many scanners and CAD programs); --supersample N, N x N samples per
 * pixel. Returns -1 when argv[i] is none of them, else 1 (parsed) or 0 (an
 * error, printed). */
int cli_view_flag(cli_args *a, float view_dir[3], float up[3], int *supersample, int *threads);
#define CLI_VIEW_USAGE                                                                   \
    "  --view X,Y,Z         the camera's direction of view (default -0.55,-0.45,-0.7)\n" \
    "  --view-up X,Y,Z|z    the world direction shown up (default y; z: Z-up scans)\n"   \
    "  --supersample N      N x N samples per pixel, 1..8 (default 2)\n"
/* True if argv[i] is `name` or `name=...`. */
int cli_is(const cli_args *a, const char *name);

/* Outputs are written to "<path>.partial" and renamed into place only when
 * every output of the command succeeded (cli_commit), so a failure never
 * leaves a half-written file behind (cli_abort removes the partial ones). */
typedef struct cli_outputs {
    int n;
    char final_path[16][1024];
    char tmp_path[16][1024];
} cli_outputs;

/* Registers an output; returns the temporary path to write, NULL if too
 * many or if the path is already registered (two outputs on one file). */
const char *cli_stage(cli_outputs *o, const char *path);
int cli_staged(const cli_outputs *o, const char *path);
tiled_result cli_commit(cli_outputs *o, tiled_error *err);
void cli_abort(cli_outputs *o);
/* The end of a command: when it failed, its outputs removed and `message`
 * printed; else its outputs moved into place. Returns the exit status. */
int cli_finish(const char *cmd, cli_outputs *o, int failed, const char *message);

/* Staged output files: cli_open opens the temporary file of `path` (NULL and
 * a message on failure); cli_close closes it and returns 1 if it was fully
 * written (ok and a clean close), else 0 with a message. cli_fwrite is a
 * write callback over FILE*. */
FILE *cli_open(cli_outputs *o, const char *path, char *msg, size_t size);
int cli_close(FILE *f, int ok, const char *path, char *msg, size_t size);
int cli_fwrite(void *ctx, const void *data, size_t size);

/* Writes an image (format from the extension of `final_path`) to the
 * staged temporary path. Returns TILED_OK or an error (message in err). */
tiled_result cli_write_image(cli_outputs *o, const char *final_path, const tiled_image *img, tiled_error *err);
/* The same for an image of another header (they share the fields): a
 * tiled_image view of it (no copy), and cli_write_image with the error
 * message into that header's message (256 bytes); returns the code. */
tiled_image cli_image_view(int width, int height, int channels, float *pixels, int bits);
int cli_write_view(cli_outputs *o, const char *final_path, const tiled_image *view, char message[256]);
/* Format name ("png", "ppm", "pgm", "pam") for a path, NULL if unknown. */
const char *cli_image_format(const char *path);

/* The outputs of a command, checked before any work (cli_check_outputs):
 * the extension fits the kind, and the folder accepts a file (else the
 * reason, errno's text). NULL paths are skipped. Returns 0 after printing
 * one error naming the flag. */
enum { CLI_OUT_ANY, CLI_OUT_IMAGE, CLI_OUT_OBJ, CLI_OUT_GLB, CLI_OUT_NRRD, CLI_OUT_PAM, CLI_OUT_PREFIX };
typedef struct cli_out {
    const char *flag, *path;
    int kind;
} cli_out;
int cli_check_outputs(const char *cmd, const cli_out *outs, int n);

/* `path` with its extension replaced by `ext`. */
void cli_with_ext(const char *path, const char *ext, char *out, size_t size);
/* How an MTL beside `obj` names `texture`: relative when in the same
 * folder, else as given. */
const char *cli_texture_ref(const char *obj, const char *texture);

/* "procedural:NAME" inputs. */
int cli_is_procedural(const char *s, const char **name);

int cmd_tiled(int argc, char **argv);
int cmd_demo(int argc, char **argv);
int cmd_convert(int argc, char **argv);
int cmd_lapped(int argc, char **argv);
int cmd_pgp(int argc, char **argv);
int cmd_pgp_tile(int argc, char **argv);
int cmd_lst(int argc, char **argv);

#endif
