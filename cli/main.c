/* patchwork: the command-line face of the four libraries. */
#include <stdio.h>
#include <string.h>
#include "cli.h"

static void usage(FILE *f)
{
    fprintf(f, "usage: patchwork COMMAND [options]\n"
               "\n"
               "Texture meshes by example (single-header C libraries, see README.md).\n"
               "\n"
               "commands:\n"
               "  tiled    seamless tiled textures on quad meshes (Kaur 2003)\n"
               "  lapped   lapped textures: patches pasted along a tangent field (Praun et al. 2000)\n"
               "  pgp      material-space texturing: periodic (s,t,m) tiles (Ray et al. 2009)\n"
               "  pgp-tile material-space tile synthesis: keys morphed along m (Ray et al. 2009)\n"
               "  lst      lapped solid textures: solid exemplars filling a model (Takayama et al. 2008)\n"
               "  demo     render every method on built-in data into a folder (default out/)\n"
               "  convert  convert an image between PNG, PPM, PGM, PAM (and read GIMP .pat)\n"
               "\n"
               "  patchwork COMMAND --help   options of one command\n"
               "  patchwork --version\n");
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        usage(stderr);
        return 1;
    }
    if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") || !strcmp(argv[1], "help")) {
        usage(stdout);
        return 0;
    }
    if (!strcmp(argv[1], "--version")) {
        printf("patchwork %s (tiled.h %s, lapped.h %s, pgp.h %s, lst.h %s)\n", TILED_VERSION_STRING,
               TILED_VERSION_STRING, LAPPED_VERSION_STRING, PGP_VERSION_STRING, LST_VERSION_STRING);
        return 0;
    }
    if (!strcmp(argv[1], "tiled")) return cmd_tiled(argc - 1, argv + 1);
    if (!strcmp(argv[1], "lapped")) return cmd_lapped(argc - 1, argv + 1);
    if (!strcmp(argv[1], "pgp")) return cmd_pgp(argc - 1, argv + 1);
    if (!strcmp(argv[1], "pgp-tile")) return cmd_pgp_tile(argc - 1, argv + 1);
    if (!strcmp(argv[1], "lst")) return cmd_lst(argc - 1, argv + 1);
    if (!strcmp(argv[1], "demo")) return cmd_demo(argc - 1, argv + 1);
    if (!strcmp(argv[1], "convert")) return cmd_convert(argc - 1, argv + 1);
    fprintf(stderr, "patchwork: unknown command '%s' (try patchwork --help)\n", argv[1]);
    return 1;
}
