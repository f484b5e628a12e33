/* fuzz_gltf: the binary glTF writer on whatever mesh the readers accept.
 *
 * The input is read as a mesh (any format pw_mesh_read_memory takes); a
 * mesh that reads gets per-corner texture coordinates from the input's
 * bytes, a small texture, and maybe a camera, and is written as GLB twice.
 * Checked, aborting when one fails:
 *   - the two files are the same bytes (determinism);
 *   - the container: magic, version, total length, a JSON chunk and a BIN
 *     chunk, each 4-byte aligned, the JSON's brackets balanced outside
 *     strings and every byte printable;
 *   - read back from the BIN chunk through the JSON's bufferViews: every
 *     index is below the vertex count, and every triangle of the fan
 *     triangulation has, corner by corner, the mesh's position and the
 *     corner's (u, 1 - v) bit for bit; every normal is unit length;
 *   - a write that fails does so with a code and a message. */
#define FZ_NAME "fuzz_gltf"
#include "fuzz.h"
#include "../src/common/mesh.h"
#include "../src/common/gltf.h"

static uint32_t fz_le32(const unsigned char *p) { return p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24; }

static float fz_lef(const unsigned char *p)
{
    uint32_t u = fz_le32(p);
    float f;
    memcpy(&f, &u, 4);
    return f;
}

/* The k-th bufferView's offset and length, from the JSON (our writer lists
 * "byteOffset" then "byteLength" in each). */
static void fz_view(const char *json, size_t n, int k, size_t *off, size_t *len)
{
    const char *p = strstr(json, "\"bufferViews\":[");
    int i;
    FZ_CHECK(p != NULL);
    for (i = 0; i <= k; i++) {
        p = strstr(p + 1, "\"byteOffset\":");
        FZ_CHECK(p != NULL && (size_t)(p - json) < n);
    }
    *off = strtoul(p + 13, NULL, 10);
    p = strstr(p, "\"byteLength\":");
    FZ_CHECK(p != NULL);
    *len = strtoul(p + 13, NULL, 10);
}

static void fz_container(const pw_buf *g, char **json, const unsigned char **bin, size_t *binlen)
{
    size_t jl, i;
    int depth = 0, str = 0;
    FZ_CHECK(g->size >= 28 && !memcmp(g->data, "glTF", 4) && fz_le32(g->data + 4) == 2 && fz_le32(g->data + 8) == g->size);
    jl = fz_le32(g->data + 12);
    FZ_CHECK(jl % 4 == 0 && !memcmp(g->data + 16, "JSON", 4) && 20 + jl + 8 <= g->size);
    *binlen = fz_le32(g->data + 20 + jl);
    FZ_CHECK(*binlen % 4 == 0 && !memcmp(g->data + 24 + jl, "BIN\0", 4) && 28 + jl + *binlen == g->size);
    *json = (char *)calloc(jl + 1, 1);
    memcpy(*json, g->data + 20, jl);
    for (i = 0; i < jl; i++) {
        char c = (*json)[i];
        FZ_CHECK(c >= 0x20 && c < 0x7f);
        if (str) str = !(c == '"' && (*json)[i - 1] != '\\');
        else if (c == '"') str = 1;
        else if (c == '{' || c == '[') depth++;
        else if (c == '}' || c == ']') FZ_CHECK(--depth >= 0);
    }
    FZ_CHECK(depth == 0 && !str);
    *bin = g->data + 28 + jl;
}

/* Corner c's texture coordinate, from the input bytes. */
static void fz_uv(const uint8_t *d, size_t n, int c, float *uv)
{
    uv[0] = (float)d[(size_t)(2 * c) % n] / 64.0f - 1.0f;
    uv[1] = (float)d[(size_t)(2 * c + 1) % n] / 128.0f;
}

static void fz_roundtrip(const pw_mesh *m, const float *cuv, const pw_buf *g)
{
    char *json;
    const unsigned char *bin;
    size_t binlen, io, il, po, pl, no, nl, uo, ul;
    int f, i, t = 0, k, nv;
    fz_container(g, &json, &bin, &binlen);
    fz_view(json, strlen(json), 0, &io, &il);
    fz_view(json, strlen(json), 1, &po, &pl);
    fz_view(json, strlen(json), 2, &no, &nl);
    fz_view(json, strlen(json), 3, &uo, &ul);
    FZ_CHECK(io + il <= binlen && po + pl <= binlen && no + nl <= binlen && uo + ul <= binlen);
    nv = (int)(pl / 12);
    FZ_CHECK(pl % 12 == 0 && nl == pl && ul == (size_t)nv * 8);
    for (i = 0; i < nv; i++) {
        float x = fz_lef(bin + no + 12 * i), y = fz_lef(bin + no + 12 * i + 4), z = fz_lef(bin + no + 12 * i + 8);
        FZ_CHECK(fabsf(x * x + y * y + z * z - 1.0f) < 1e-4f);
    }
    for (f = 0; f < m->nf; f++)
        for (i = m->fstart[f] + 1; i + 1 < m->fstart[f + 1]; i++, t++) {
            const int c[3] = {m->fstart[f], i, i + 1};
            FZ_CHECK((size_t)(12 * t + 12) <= il);
            for (k = 0; k < 3; k++) {
                uint32_t v = fz_le32(bin + io + 12 * t + 4 * k);
                int j;
                FZ_CHECK(v < (uint32_t)nv);
                for (j = 0; j < 3; j++) FZ_CHECK(fz_lef(bin + po + 12 * v + 4 * j) == m->pos[3 * m->fv[c[k]] + j]);
                FZ_CHECK(fz_lef(bin + uo + 8 * v) == cuv[2 * c[k]] && fz_lef(bin + uo + 8 * v + 4) == 1.0f - cuv[2 * c[k] + 1]);
            }
        }
    FZ_CHECK((size_t)(12 * t) == il);
    free(json);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    pw_mesh m;
    pw_err e;
    pw_image tex;
    pw_gltf_part part;
    pw_gltf_scene scene;
    pw_camera cam;
    pw_buf a, b;
    float *cuv;
    int r1, r2, c;
    pw_err_clear(&e);
    if (size == 0 || pw_mesh_read_memory(NULL, data, size, "fuzz", &m, &e) != PW_OK) return 0;
    cuv = (float *)malloc(sizeof(float) * 2 * (size_t)m.fstart[m.nf]);
    for (c = 0; c < m.fstart[m.nf]; c++) fz_uv(data, size, c, cuv + 2 * c);
    memset(&part, 0, sizeof part);
    part.name = size % 2 ? "fuzz \"mesh\"\n" : NULL;
    part.nv = m.nv, part.pos = m.pos, part.nf = m.nf, part.fstart = m.fstart, part.fv = m.fv, part.corner_uv = cuv;
    part.repeat = data[0] & 1;
    FZ_CHECK(pw_image_alloc(NULL, &tex, 1 + data[0] % 7, 1 + data[size - 1] % 5, 1 + data[0] % 4, &e) == PW_OK);
    part.texture = data[0] & 2 ? &tex : NULL;
    memset(&scene, 0, sizeof scene);
    scene.parts = &part, scene.nparts = 1, scene.generator = "fuzz";
    if (data[0] & 4) {
        static const float zero[3] = {0, 0, 0}; /* the default view */
        cam = pw_gltf_view_camera(m.pos, m.nv, 64, 48, zero, zero, &scene.aspect);
        scene.camera = &cam;
    }
    memset(&a, 0, sizeof a), memset(&b, 0, sizeof b);
    r1 = pw_gltf_write(NULL, &scene, pw_buf_write, &a, &e);
    if (r1 != PW_OK) fz_check_failure(r1, e.code, e.msg, sizeof e.msg);
    pw_err_clear(&e);
    r2 = pw_gltf_write(NULL, &scene, pw_buf_write, &b, &e);
    FZ_CHECK(r1 == r2 && a.size == b.size && (a.size == 0 || !memcmp(a.data, b.data, a.size)));
    if (r1 == PW_OK) fz_roundtrip(&m, cuv, &a);
    free(a.data), free(b.data), free(cuv);
    pw_image_free(NULL, &tex);
    pw_mesh_free(NULL, &m);
    return 0;
}
