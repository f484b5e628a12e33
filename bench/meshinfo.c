/* meshinfo FILE: reads a mesh (OBJ, OFF, PLY) with patchwork's reader and
 * prints its counts, as `assimp info FILE -r -s` does with Assimp's:
 * bench_io times the two commands on the same files. */
#include <stdio.h>
#include "../src/common/mesh.h"

int main(int argc, char **argv)
{
    pw_mesh m;
    pw_err e;
    pw_err_clear(&e);
    if (argc != 2) return fprintf(stderr, "usage: meshinfo FILE\n"), 2;
    if (pw_mesh_load(NULL, argv[1], &m, &e)) return fprintf(stderr, "meshinfo: %s\n", e.msg), 1;
    printf("%s: %d vertices, %d faces, %d corners\n", argv[1], m.nv, m.nf, m.fstart[m.nf]);
    pw_mesh_free(NULL, &m);
    return 0;
}
