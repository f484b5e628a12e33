/* cmd_convert.c: `patchwork convert IN OUT`, image format conversion. */
#include <stdio.h>
#include <string.h>
#include "cli.h"

int cmd_convert(int argc, char **argv)
{
    tiled_image img;
    tiled_error err;
    cli_outputs outs;
    if (argc == 2 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h"))) {
        printf("usage: patchwork convert IN OUT\n\nConverts an image (PNG, PPM, PGM, PAM, GIMP "
               ".pat) to PNG, PPM, PGM or PAM, by OUT's extension.\n");
        return 0;
    }
    if (argc != 3) {
        cli_error("convert", "usage: patchwork convert IN OUT");
        return 1;
    }
    memset(&outs, 0, sizeof outs);
    if (tiled_load_image(argv[1], NULL, &img, &err) != TILED_OK) {
        cli_error("convert", "%s", err.message);
        return 1;
    }
    if (cli_write_image(&outs, argv[2], &img, &err) != TILED_OK) {
        cli_abort(&outs);
        tiled_image_free(&img);
        cli_error("convert", "%s", err.message);
        return 1;
    }
    tiled_image_free(&img);
    if (cli_commit(&outs, &err) != TILED_OK) {
        cli_error("convert", "%s", err.message);
        return 1;
    }
    return 0;
}
