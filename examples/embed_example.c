/* embed_example.c: what a program that embeds patchwork needs, shown with
 * lapped.h (the other headers have the same hooks):
 *   cc -O2 -I.. embed_example.c -lm && ./a.out
 *
 *   - memory I/O: the mesh is read from a string, the result is written as
 *     a binary glTF into a growing buffer (no file is touched until the end);
 *   - a progress callback that cancels: the first run stops at 30%, returns
 *     LAPPED_ERR_CANCELLED and leaves nothing allocated;
 *   - a custom allocator: every allocation goes through it (here: counting
 *     the live blocks). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#define LAPPED_IMPLEMENTATION
#include "../lapped.h"

/* counts the blocks it hands out that are not freed yet */
static void *my_realloc(void *user, void *ptr, size_t n)
{
    void *p = realloc(ptr, n);
    if (p && !ptr) ++*(long *)user;
    return p;
}
static void *my_malloc(void *user, size_t n) { return my_realloc(user, NULL, n); }
static void my_free(void *user, void *ptr)
{
    if (ptr) --*(long *)user;
    free(ptr);
}

static int stop_at_30(void *user, float done, const char *stage) { return *(int *)user && done > 0.3f && stage; }
typedef struct buffer {
    unsigned char *data;
    size_t size;
} buffer;
static int to_buffer(void *ctx, const void *data, size_t n)
{
    buffer *b = (buffer *)ctx;
    unsigned char *grown = (unsigned char *)realloc(b->data, b->size + n);
    if (!grown) return -1; /* non-zero: the library reports LAPPED_ERR_IO */
    memcpy(grown + b->size, data, n);
    b->data = grown;
    b->size += n;
    return 0;
}

/* a regular octahedron, as an OBJ held in memory */
static const char octahedron[] = "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n"
                                 "f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n";

int main(void)
{
    long live = 0;
    int cancel = 1, ok;
    lapped_options opt = lapped_default_options();
    lapped_source src = {0};
    lapped_mesh mesh = {0};
    lapped_image texture = {0}, patch = {0};
    lapped_texture lt = {0}; /* a failed call leaves its output zeroed: freeing is always safe */
    lapped_atlas atlas = {0};
    lapped_error err;
    buffer glb = {NULL, 0};
    FILE *f;
    opt.allocator.malloc_fn = my_malloc;
    opt.allocator.realloc_fn = my_realloc;
    opt.allocator.free_fn = my_free;
    opt.allocator.user = &live;
    opt.progress = stop_at_30;
    opt.progress_user = &cancel;
    opt.scale = 0.6f;
    opt.atlas.size = 256;
    src.patches = &patch;
    src.npatches = 1;
    ok = lapped_read_mesh(octahedron, sizeof octahedron - 1, "octahedron.obj", &opt, &mesh, &err) == LAPPED_OK &&
         lapped_builtin_exemplar("dots", 64, &opt, &texture, &err) == LAPPED_OK &&
         lapped_make_patch(&texture, NULL, &opt, &patch, &err) == LAPPED_OK;
    if (ok && lapped_create(&mesh, &src, &opt, &lt, &err) == LAPPED_ERR_CANCELLED)
        printf("cancelled at 30%%: %s; %ld blocks live (the mesh, texture and patch)\n", err.message, live);
    cancel = 0;
    ok = ok && lapped_create(&mesh, &src, &opt, &lt, &err) == LAPPED_OK &&
         lapped_bake_atlas(&mesh, &lt, &src, &opt, &atlas, &err) == LAPPED_OK &&
         lapped_write_gltf(&mesh, &atlas, NULL, to_buffer, &glb, &err) == LAPPED_OK;
    if (ok && (f = fopen("embed_example.glb", "wb")) != NULL) {
        ok = fwrite(glb.data, 1, glb.size, f) == glb.size;
        ok = fclose(f) == 0 && ok;
    }
    if (ok)
        printf("%d pastes; %lu bytes of glTF in memory, saved as embed_example.glb\n", lt.npastes,
               (unsigned long)glb.size);
    else fprintf(stderr, "embed_example: %s\n", err.message);
    lapped_atlas_free(&atlas);
    lapped_texture_free(&lt);
    lapped_image_free(&patch);
    lapped_image_free(&texture);
    lapped_mesh_free(&mesh);
    free(glb.data);
    printf("%ld blocks still allocated after the frees\n", live);
    return ok && live == 0 ? 0 : 1;
}
