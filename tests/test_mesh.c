/* Tests of src/common/mesh.h: the OBJ, OFF, PLY and STL readers, the OBJ/MTL
 * writers, and the small mesh utilities. */
#include "../src/common/mesh.h"
#include "pwtest.h"
#include <locale.h>

/* ---- helpers -------------------------------------------------------------- */

static int rd(const char *text, const char *name, pw_mesh *m, pw_err *e)
{
    pw_err_clear(e);
    return pw_mesh_read_memory(NULL, text, strlen(text), name, m, e);
}

/* Reads text expecting failure with `code` and a message containing both
 * fragments; the output mesh must be left empty. */
static void expect_err_(int line, const char *text, const char *name, int code, const char *f1,
                        const char *f2)
{
    pw_mesh m;
    pw_err e;
    int r = rd(text, name, &m, &e);
    if (r != code) pwt_fail_(__FILE__, line, "expected code %d, got %d (%s)", code, r, e.msg);
    if (!strstr(e.msg, f1)) pwt_fail_(__FILE__, line, "message '%s' lacks '%s'", e.msg, f1);
    if (!strstr(e.msg, f2)) pwt_fail_(__FILE__, line, "message '%s' lacks '%s'", e.msg, f2);
    if (m.pos || m.fv || m.nf) pwt_fail_(__FILE__, line, "output mesh not empty after an error");
    if (r == PW_OK) pw_mesh_free(NULL, &m);
}
#define EXPECT_ERR(text, name, code, f1, f2) expect_err_(__LINE__, text, name, code, f1, f2)

static int face_deg(const pw_mesh *m, int f) { return m->fstart[f + 1] - m->fstart[f]; }

static int same_mesh(const pw_mesh *a, const pw_mesh *b)
{
    int nc;
    if (a->nv != b->nv || a->nf != b->nf) return 0;
    if (memcmp(a->pos, b->pos, (size_t)a->nv * 3 * sizeof(float))) return 0;
    if (memcmp(a->fstart, b->fstart, ((size_t)a->nf + 1) * sizeof(int))) return 0;
    nc = a->fstart[a->nf];
    if (memcmp(a->fv, b->fv, (size_t)nc * sizeof(int))) return 0;
    if ((a->uv == NULL) != (b->uv == NULL) || a->nuv != b->nuv) return 0;
    if (a->uv && (memcmp(a->uv, b->uv, (size_t)a->nuv * 2 * sizeof(float)) ||
                  memcmp(a->fuv, b->fuv, (size_t)nc * sizeof(int))))
        return 0;
    return 1;
}

/* The counting, failing allocator of pwtest.h, also tracking the largest
 * request. */
typedef struct talloc {
    pwt_alloc_state s;
    size_t largest;
} talloc;
static void *t_malloc(void *u, size_t n)
{
    talloc *t = (talloc *)u;
    if (n > t->largest) t->largest = n;
    return pwt_malloc(&t->s, n);
}
static void *t_realloc(void *u, void *p, size_t n)
{
    talloc *t = (talloc *)u;
    if (n > t->largest) t->largest = n;
    return pwt_realloc(&t->s, p, n);
}
static void t_free(void *u, void *p) { pwt_free(&((talloc *)u)->s, p); }
static pw_alloc make_alloc(talloc *t, int budget)
{
    pw_alloc a;
    t->s.calls = 0;
    t->s.live = 0;
    t->s.fail_after = budget;
    t->largest = 0;
    a.malloc_fn = t_malloc;
    a.realloc_fn = t_realloc;
    a.free_fn = t_free;
    a.user = t;
    return a;
}

static int buf_write(void *ctx, const void *data, size_t size) { return pw_buf_write(ctx, data, size); }

/* ---- OBJ ------------------------------------------------------------------ */

static void t_obj_basic(void)
{
    const char *text =
        "# a comment\r\n"
        "\r\n"
        "v 0 0 0\r\n"
        "v\t1.5 0 0   \r\n"
        "v 1 1 0 1.0\n"          /* w */
        "v 0 1e0 -0.0 0.5 0.5 0.5\n" /* vertex colours */
        "v -2.5E-1 .5 +3.\n"
        "  # indented comment\n"
        "f 1 2 3 4\n"
        "f 1 2 5\t\n"
        "f 1 3 4 5 2   # trailing comment\n";
    pw_mesh m;
    pw_err e;
    REQUIRE(rd(text, "basic.obj", &m, &e) == PW_OK);
    CHECK_EQ_INT(m.nv, 5);
    CHECK_EQ_INT(m.nf, 3);
    CHECK_EQ_INT(face_deg(&m, 0), 4);
    CHECK_EQ_INT(face_deg(&m, 1), 3);
    CHECK_EQ_INT(face_deg(&m, 2), 5);
    CHECK(m.pos[3] == 1.5f && m.pos[12] == -0.25f && m.pos[13] == 0.5f && m.pos[14] == 3.0f);
    CHECK(m.fv[4] == 0 && m.fv[5] == 1 && m.fv[6] == 4);
    CHECK(m.uv == NULL && m.fuv == NULL && m.nuv == 0);
    pw_mesh_free(NULL, &m);
}

static void t_obj_forms(void)
{
    const char *text =
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
        "vt 0 0\nvt 1 0\nvt 1 1 0\nvt 0 1\n"
        "vn 0 0 1\n"
        "f 1/1 2/2 3/3\n"
        "f 1/1/1 3/3/1 4/4/1\n"
        "f -4/-4 -2/-2 -1/-1\n"; /* relative: vertices 1 3 4 */
    pw_mesh m;
    pw_err e;
    REQUIRE(rd(text, "forms.obj", &m, &e) == PW_OK);
    CHECK_EQ_INT(m.nf, 3);
    REQUIRE(m.uv != NULL && m.fuv != NULL);
    CHECK_EQ_INT(m.nuv, 4);
    CHECK(m.fv[6] == 0 && m.fv[7] == 2 && m.fv[8] == 3);
    CHECK(m.fuv[6] == 0 && m.fuv[7] == 2 && m.fuv[8] == 3);
    CHECK(m.uv[4] == 1.0f && m.uv[5] == 1.0f);
    pw_mesh_free(NULL, &m);

    /* a//c everywhere: no texture coordinates kept */
    REQUIRE(rd("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n", "n.obj", &m, &e) == PW_OK);
    CHECK(m.uv == NULL && m.fuv == NULL);
    pw_mesh_free(NULL, &m);

    /* one face without vt: uvs dropped for the whole mesh */
    REQUIRE(rd("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\nf 1 3 2\n", "m.obj", &m, &e) == PW_OK);
    CHECK(m.uv == NULL && m.fuv == NULL && m.nuv == 0);
    pw_mesh_free(NULL, &m);

    /* "a/b/" tolerated */
    REQUIRE(rd("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1/ 2/1/ 3/1/\n", "m.obj", &m, &e) == PW_OK);
    CHECK(m.fuv != NULL);
    pw_mesh_free(NULL, &m);
}

static void t_obj_continuation_and_skipped(void)
{
    const char *text =
        "mtllib scene.mtl\n"
        "o thing\n"
        "g group1 group2\n"
        "s off\n"
        "usemtl stone\n"
        "v 0 0 \\\n"
        "  0\n"
        "v 1 0 0\nv 1 1 0\nv 0 1 0\n"
        "l 1 2\n"
        "p 3\n"
        "f 1 2 \\\r\n"
        "3 \\  \n"
        "4\n"
        "f 1 3 4\n";
    pw_mesh m;
    pw_err e;
    REQUIRE(rd(text, "cont.obj", &m, &e) == PW_OK);
    CHECK_EQ_INT(m.nv, 4);
    CHECK_EQ_INT(m.nf, 2);
    CHECK_EQ_INT(face_deg(&m, 0), 4);
    pw_mesh_free(NULL, &m);
    /* the line number after continuations still counts physical lines */
    EXPECT_ERR("v 0 0 \\\n0\nv 1 \\\n 0 0\nbogus 1\n", "c.obj", PW_ERR_PARSE, "c.obj:5:", "bogus");
}

static void t_obj_errors(void)
{
    EXPECT_ERR("v 0 0 0\nv 1 0 0\nv 0 1 0\nfoo 1 2\nf 1 2 3\n", "k.obj", PW_ERR_PARSE,
               "k.obj:4:", "unknown OBJ keyword 'foo'");
    EXPECT_ERR("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "r.obj", PW_ERR_INVALID, "r.obj:4:",
               "vertex index 4 out of range");
    EXPECT_ERR("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", "r.obj", PW_ERR_INVALID, ":4:", "index -4");
    EXPECT_ERR("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "z.obj", PW_ERR_INVALID, ":4:", "start at 1");
    EXPECT_ERR("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/2 2/1 3/1\n", "t.obj", PW_ERR_INVALID, ":5:",
               "texture coordinate index 2");
    EXPECT_ERR("v 0 0 0\nv 1 0 0\n\nf 1 2\n", "d.obj", PW_ERR_DEGENERATE, "d.obj:4:", "2 corners");
    EXPECT_ERR("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 nan 0\nf 1 2 3\n", "n.obj", PW_ERR_INVALID, "n.obj:4:",
               "vertex 3 has a non-finite coordinate");
    EXPECT_ERR("v 0 0 0\nv 1 0 0\nv 0 1e39 0\n", "big.obj", PW_ERR_INVALID, ":3:", "non-finite");
    EXPECT_ERR("v 0 0 0\nv 1 0 inf\n", "i.obj", PW_ERR_INVALID, ":2:", "non-finite");
    EXPECT_ERR("v 0 0 0\nv 1 0\n", "trunc.obj", PW_ERR_PARSE, "trunc.obj:2:", "missing");
    EXPECT_ERR("v 0 0 0\nv 1 0 1.2.3\n", "mal.obj", PW_ERR_PARSE, ":2:", "malformed number '1.2.3'");
    EXPECT_ERR("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3x\n", "c.obj", PW_ERR_PARSE, ":4:", "malformed corner '3x'");
    EXPECT_ERR("v 0 0 0\nv 1 0 0\nv 0 1 0\n", "empty.obj", PW_ERR_DEGENERATE, "empty.obj", "no faces");
    EXPECT_ERR("", "nothing.obj", PW_ERR_DEGENERATE, "nothing.obj", "no faces");
    EXPECT_ERR("\x01\x02\x03\x04", "bin.obj", PW_ERR_PARSE, "bin.obj:1:", "unknown OBJ keyword");
}

static void t_obj_face_degree_limit(void)
{
    pw_buf b;
    pw_mesh m;
    pw_err e;
    int i;
    char line[32];
    memset(&b, 0, sizeof b);
    for (i = 0; i <= PW_MAX_FACE_DEGREE; i++) {
        snprintf(line, sizeof line, "v %d 0 0\n", i);
        pw_buf_write(&b, line, strlen(line));
    }
    pw_buf_write(&b, "f", 1);
    for (i = 0; i <= PW_MAX_FACE_DEGREE; i++) {
        snprintf(line, sizeof line, " %d", i + 1);
        pw_buf_write(&b, line, strlen(line));
    }
    pw_buf_write(&b, "\n", 1);
    pw_err_clear(&e);
    CHECK_EQ_INT(pw_mesh_read_obj(NULL, b.data, b.size, "deg.obj", &m, &e), PW_ERR_LIMIT);
    CHECK(strstr(e.msg, "deg.obj:") && strstr(e.msg, "corners"));
    free(b.data);
}

/* ---- writer and round trips ---------------------------------------------- */

static void make_quad_uv_mesh(pw_mesh *m)
{
    static const float pos[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5f, 1.5f, 1e-7f};
    static const int fv[] = {0, 1, 2, 3, 3, 2, 4};
    static const float uv[] = {0, 0, 1, 0, 1, 1, 0, 1, 0.5f, 0.25f};
    static const int fuv[] = {0, 1, 2, 3, 3, 2, 4};
    REQUIRE(pw_mesh_alloc(NULL, m, 5, 2, 7, 1, NULL) == PW_OK);
    memcpy(m->pos, pos, sizeof pos);
    m->fstart[0] = 0, m->fstart[1] = 4, m->fstart[2] = 7;
    memcpy(m->fv, fv, sizeof fv);
    m->nuv = 5;
    memcpy(m->uv, uv, sizeof uv);
    memcpy(m->fuv, fuv, sizeof fuv);
}

static void t_obj_roundtrip(void)
{
    pw_mesh m, r;
    pw_err e;
    pw_buf b;
    make_quad_uv_mesh(&m);
    memset(&b, 0, sizeof b);
    pw_err_clear(&e);
    REQUIRE(pw_mesh_write_obj(&m, "out.mtl", "tiles", buf_write, &b, &e) == PW_OK);
    pw_buf_write(&b, "", 1);
    CHECK(strstr((char *)b.data, "mtllib out.mtl\n") != NULL);
    CHECK(strstr((char *)b.data, "usemtl tiles\n") != NULL);
    CHECK(strstr((char *)b.data, "f 1/1 2/2 3/3 4/4\n") != NULL);
    CHECK(strstr((char *)b.data, "vt 0.5 0.25\n") != NULL);
    REQUIRE(pw_mesh_read_obj(NULL, b.data, b.size - 1, "rt.obj", &r, &e) == PW_OK);
    CHECK(same_mesh(&m, &r));
    pw_mesh_free(NULL, &r);
    free(b.data);
    /* without uvs: plain "f a b c" */
    pw_free(NULL, m.uv), pw_free(NULL, m.fuv);
    m.uv = NULL, m.fuv = NULL, m.nuv = 0;
    memset(&b, 0, sizeof b);
    REQUIRE(pw_mesh_write_obj(&m, NULL, NULL, buf_write, &b, &e) == PW_OK);
    pw_buf_write(&b, "", 1);
    CHECK(strstr((char *)b.data, "f 1 2 3 4\n") != NULL && !strstr((char *)b.data, "mtllib"));
    REQUIRE(pw_mesh_read_obj(NULL, b.data, b.size - 1, "rt.obj", &r, &e) == PW_OK);
    CHECK(same_mesh(&m, &r));
    pw_mesh_free(NULL, &r);
    pw_mesh_free(NULL, &m);
    free(b.data);
}

/* Every float bit pattern class survives write -> read exactly. */
static void t_obj_float_roundtrip(void)
{
    pw_mesh m, r;
    pw_err e;
    pw_buf b;
    uint32_t s = 12345;
    int i, n = 3000;
    REQUIRE(pw_mesh_alloc(NULL, &m, n, 1, 3, 0, NULL) == PW_OK);
    for (i = 0; i < 3 * n; i++) {
        uint32_t bits;
        float f;
        do {
            s = s * 1664525u + 1013904223u;
            bits = s ^ (s >> 7) << 3;
            memcpy(&f, &bits, 4);
        } while (!pw_is_finite(f));
        m.pos[i] = f;
    }
    m.pos[0] = FLT_MIN, m.pos[1] = FLT_MAX, m.pos[2] = -1.40129846e-45f;
    m.fstart[1] = 3, m.fv[0] = 0, m.fv[1] = 1, m.fv[2] = 2;
    memset(&b, 0, sizeof b);
    pw_err_clear(&e);
    REQUIRE(pw_mesh_write_obj(&m, NULL, NULL, buf_write, &b, &e) == PW_OK);
    r.nv = 0;
    CHECKF(pw_mesh_read_obj(NULL, b.data, b.size, "f.obj", &r, &e) == PW_OK, "%s", e.msg);
    REQUIRE(r.nv == n);
    CHECKF(memcmp(m.pos, r.pos, (size_t)n * 3 * sizeof(float)) == 0, "positions differ after a round trip");
    pw_mesh_free(NULL, &r);
    pw_mesh_free(NULL, &m);
    free(b.data);
}

static void t_mtl(void)
{
    pw_buf b;
    pw_err e;
    memset(&b, 0, sizeof b);
    pw_err_clear(&e);
    REQUIRE(pw_mesh_write_mtl("tiles", "atlas.png", buf_write, &b, &e) == PW_OK);
    pw_buf_write(&b, "", 1);
    CHECK(strstr((char *)b.data, "newmtl tiles\n") != NULL);
    CHECK(strstr((char *)b.data, "Kd 1 1 1\n") != NULL);
    CHECK(strstr((char *)b.data, "map_Kd atlas.png\n") != NULL);
    free(b.data);
    memset(&b, 0, sizeof b);
    CHECK_EQ_INT(pw_mesh_write_mtl("bad\nname", "a.png", buf_write, &b, &e), PW_ERR_INVALID);
    free(b.data);
}

static int fail_write(void *ctx, const void *data, size_t size)
{
    (void)ctx, (void)data, (void)size;
    return -1;
}

static void t_writer_errors(void)
{
    pw_mesh m;
    pw_err e;
    make_quad_uv_mesh(&m);
    pw_err_clear(&e);
    CHECK_EQ_INT(pw_mesh_write_obj(&m, NULL, NULL, fail_write, NULL, &e), PW_ERR_IO);
    m.fv[2] = 7; /* out of range */
    pw_err_clear(&e);
    CHECK_EQ_INT(pw_mesh_write_obj(&m, NULL, NULL, fail_write, NULL, &e), PW_ERR_INVALID);
    CHECK(strstr(e.msg, "face 0, corner 2") != NULL);
    m.fv[2] = 2;
    m.pos[4] = (float)NAN;
    pw_err_clear(&e);
    CHECK_EQ_INT(pw_mesh_write_obj(&m, NULL, NULL, fail_write, NULL, &e), PW_ERR_INVALID);
    CHECK(strstr(e.msg, "vertex 1 has a non-finite") != NULL);
    pw_mesh_free(NULL, &m);
}

static void t_locale(void)
{
    pw_mesh m;
    pw_buf b;
    pw_err e;
    const char *loc = setlocale(LC_NUMERIC, "de_DE.UTF-8");
    if (!loc) loc = setlocale(LC_NUMERIC, "fr_FR.UTF-8");
    if (!loc) {
        pwt_skip("no locale with a decimal comma installed");
        return;
    }
    make_quad_uv_mesh(&m);
    memset(&b, 0, sizeof b);
    pw_err_clear(&e);
    REQUIRE(pw_mesh_write_obj(&m, NULL, NULL, buf_write, &b, &e) == PW_OK);
    pw_buf_write(&b, "", 1);
    CHECK(strstr((char *)b.data, "v 0.5 1.5 1.00000001e-7\n") != NULL);
    CHECK(strchr((char *)b.data, ',') == NULL);
    setlocale(LC_NUMERIC, "C");
    pw_mesh_free(NULL, &m);
    free(b.data);
}

#ifndef PW_NO_STDIO
static void t_files(void)
{
    pw_mesh m, r;
    pw_err e;
    FILE *f;
    char text[256];
    size_t n;
    make_quad_uv_mesh(&m);
    pw_err_clear(&e);
    REQUIRE(pw_mesh_save_obj("/tmp/pw_test_mesh.obj", &m, "pw_test_mesh.mtl", "m", &e) == PW_OK);
    REQUIRE(pw_mesh_save_mtl("/tmp/pw_test_mesh.mtl", "m", "tex.ppm", &e) == PW_OK);
    REQUIRE(pw_mesh_load(NULL, "/tmp/pw_test_mesh.obj", &r, &e) == PW_OK);
    CHECK(same_mesh(&m, &r));
    pw_mesh_free(NULL, &r);
    f = fopen("/tmp/pw_test_mesh.mtl", "rb");
    REQUIRE(f != NULL);
    n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = 0;
    CHECK(strstr(text, "map_Kd tex.ppm") != NULL);
    pw_err_clear(&e);
    CHECK_EQ_INT(pw_mesh_load(NULL, "/nonexistent/x.obj", &r, &e), PW_ERR_IO);
    CHECK(strstr(e.msg, "/nonexistent/x.obj") != NULL);
    pw_err_clear(&e);
    CHECK_EQ_INT(pw_mesh_save_obj("/nonexistent/x.obj", &m, NULL, NULL, &e), PW_ERR_IO);
    remove("/tmp/pw_test_mesh.obj");
    remove("/tmp/pw_test_mesh.mtl");
    pw_mesh_free(NULL, &m);
}
#endif

/* ---- OFF ------------------------------------------------------------------ */

static void t_off_variants(void)
{
    pw_mesh m;
    pw_err e;
    /* counts on the keyword line, comments everywhere, face colours */
    REQUIRE(rd("# Output of a tool\n#CBP\n\nOFF 4 2 0 # counts\n# vertices\n0 0 0\n1 0 0 # right\n\n1 1 0\n0 1 0\n"
               "3 0 1 2 255 0 0\n3 0 2 3 0.5 0.5 0.5 1\n",
               "a.off", &m, &e) == PW_OK);
    CHECK(m.nv == 4 && m.nf == 2 && m.fv[5] == 3 && m.pos[6] == 1.0f);
    pw_mesh_free(NULL, &m);
    /* COFF with RGB and RGBA vertex colours, CRLF */
    REQUIRE(rd("COFF\r\n4 1 0\r\n0 0 0 1 0 0\r\n1 0 0 0 1 0 1\r\n1 1 0 0 0 1\r\n0 1 0 255 255 255 255\r\n4 0 1 2 3\r\n",
               "c.off", &m, &e) == PW_OK);
    CHECK(m.nv == 4 && m.nf == 1 && face_deg(&m, 0) == 4);
    pw_mesh_free(NULL, &m);
    /* NOFF, CNOFF, STOFF, STCNOFF */
    REQUIRE(rd("NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n", "n.off", &m, &e) == PW_OK);
    pw_mesh_free(NULL, &m);
    REQUIRE(rd("CNOFF\n3 1 0\n0 0 0 0 0 1 1 0 0\n1 0 0 0 0 1 1 0 0\n0 1 0 0 0 1 1 0 0\n3 0 1 2\n", "cn.off", &m, &e) == PW_OK);
    pw_mesh_free(NULL, &m);
    REQUIRE(rd("STOFF\n3 1 0\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n", "st.off", &m, &e) == PW_OK);
    pw_mesh_free(NULL, &m);
    REQUIRE(rd("STCNOFF\n3 1\n0 0 0 0 0 1 1 0 0 1 0 0\n1 0 0 0 0 1 1 0 0 1 1 0\n0 1 0 0 0 1 1 0 0 1 0 1\n3 0 1 2\n",
               "stcn.off", &m, &e) == PW_OK);
    CHECK(m.nf == 1 && m.pos[3] == 1.0f);
    pw_mesh_free(NULL, &m);
    /* counts on separate lines; trailing data after the faces ignored */
    REQUIRE(rd("OFF\n3\n1\n0 0 0\n1 0 0\n0 1 0\n3 2 1 0\n", "s.off", &m, &e) == PW_OK);
    CHECK(m.fv[0] == 2);
    pw_mesh_free(NULL, &m);
    /* no keyword at all: recognised from the name, or by pw_mesh_read_off */
    REQUIRE(rd("3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "bare.off", &m, &e) == PW_OK);
    pw_mesh_free(NULL, &m);
    pw_err_clear(&e);
    REQUIRE(pw_mesh_read_off(NULL, "3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", 32, NULL, &m, &e) == PW_OK);
    pw_mesh_free(NULL, &m);
}

static void t_off_errors(void)
{
    EXPECT_ERR("4OFF\n3 1 0\n0 0 0 1\n1 0 0 1\n0 1 0 1\n3 0 1 2\n", "h.off", PW_ERR_UNSUPPORTED, "h.off:1:", "4OFF");
    EXPECT_ERR("nOFF\n4\n3 1 0\n", "n.off", PW_ERR_UNSUPPORTED, "n.off:1:", "nOFF");
    EXPECT_ERR("OFF\n3 1 0\n0 0 0\n1 0 0\n", "t.off", PW_ERR_PARSE, "t.off:", "truncated");
    EXPECT_ERR("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n                \n", "t2.off", PW_ERR_PARSE, "t2.off:",
               "end of file after 1 of 2 faces");
    EXPECT_ERR("OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n# pad\n", "v.off", PW_ERR_PARSE, "v.off:4:", "vertex 1");
    EXPECT_ERR("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "i.off", PW_ERR_INVALID, "i.off:6:",
               "face 0: vertex index 3 out of range (3 vertices)");
    EXPECT_ERR("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", "i.off", PW_ERR_INVALID, ":6:", "index -1");
    EXPECT_ERR("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n# pad\n", "d.off", PW_ERR_DEGENERATE, "d.off:6:", "2 corners");
    EXPECT_ERR("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n# pad\n", "m.off", PW_ERR_PARSE, "m.off:6:", "face 0");
    EXPECT_ERR("OFF\n3 1 0\n0 0 0\n1 NaN 0\n0 1 0\n3 0 1 2\n", "nan.off", PW_ERR_INVALID, "nan.off:4:",
               "vertex 1 has a non-finite coordinate");
    EXPECT_ERR("OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n", "e.off", PW_ERR_DEGENERATE, "e.off", "no faces");
    EXPECT_ERR("OFF\n-3 1 0\n", "neg.off", PW_ERR_PARSE, "neg.off:2:", "negative");
    EXPECT_ERR("OFF\nthree 1 0\n", "w.off", PW_ERR_PARSE, "w.off:2: header: number of vertices", "malformed integer 'three'");
    EXPECT_ERR("OFF\n", "eof.off", PW_ERR_PARSE, "eof.off:2: header: number of vertices", "missing");
    EXPECT_ERR("OFX\n3 1 0\n", "k.off", PW_ERR_PARSE, "k.off:1:", "expected the OFF keyword");
}

/* A header claiming 2^31 (or merely more than the data holds) elements is
 * refused before anything of that size is allocated. */
static void t_huge_counts(void)
{
    static const char *const texts[] = {
        "OFF\n2147483648 1 0\n0 0 0\n",
        "OFF\n100000000 100000000 0\n0 0 0\n",
        "ply\nformat ascii 1.0\nelement vertex 2147483648\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n",
        "ply\nformat binary_little_endian 1.0\nelement vertex 100000000\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\1\2\3\4",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nelement junk 2000000000\nproperty float w\n"
        "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"};
    static const int codes[] = {PW_ERR_LIMIT, PW_ERR_PARSE, PW_ERR_LIMIT, PW_ERR_PARSE, PW_ERR_PARSE, PW_OK};
    size_t i;
    for (i = 0; i < sizeof texts / sizeof texts[0]; i++) {
        talloc t;
        pw_alloc a = make_alloc(&t, -1);
        pw_mesh m;
        pw_err e;
        int r;
        pw_err_clear(&e);
        r = pw_mesh_read_memory(&a, texts[i], strlen(texts[i]), "huge", &m, &e);
        CHECKF(r == codes[i], "case %d: code %d (%s)", (int)i, r, e.msg);
        CHECKF(t.largest < 100000, "case %d: allocated %lu bytes", (int)i, (unsigned long)t.largest);
        if (r == PW_OK) pw_mesh_free(&a, &m);
        CHECK_EQ_INT(t.s.live, 0);
    }
}

static void put_be32(pw_buf *b, uint32_t v)
{
    unsigned char c[4];
    c[0] = (unsigned char)(v >> 24), c[1] = (unsigned char)(v >> 16), c[2] = (unsigned char)(v >> 8), c[3] = (unsigned char)v;
    pw_buf_write(b, c, 4);
}
static void put_bef(pw_buf *b, float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    put_be32(b, u);
}

static void t_off_binary(void)
{
    pw_buf b;
    pw_mesh m;
    pw_err e;
    int i;
    memset(&b, 0, sizeof b);
    pw_buf_write(&b, "COFF BINARY # comment\n", 22);
    put_be32(&b, 4), put_be32(&b, 2), put_be32(&b, 0);
    for (i = 0; i < 4; i++) {
        put_bef(&b, (float)(i & 1)), put_bef(&b, (float)(i >> 1)), put_bef(&b, 0.25f);
        put_bef(&b, 1), put_bef(&b, 0), put_bef(&b, 0), put_bef(&b, 1); /* RGBA */
    }
    put_be32(&b, 3), put_be32(&b, 0), put_be32(&b, 1), put_be32(&b, 3), put_be32(&b, 0);
    put_be32(&b, 3), put_be32(&b, 0), put_be32(&b, 3), put_be32(&b, 2), put_be32(&b, 3);
    put_bef(&b, 1), put_bef(&b, 1), put_bef(&b, 1);
    pw_err_clear(&e);
    REQUIRE(pw_mesh_read_memory(NULL, b.data, b.size, "bin.off", &m, &e) == PW_OK);
    CHECK(m.nv == 4 && m.nf == 2 && m.pos[3] == 1.0f && m.pos[5] == 0.25f && m.fv[2] == 3 && m.fv[4] == 3);
    pw_mesh_free(NULL, &m);
    /* truncated in the last face's colour */
    pw_err_clear(&e);
    CHECK_EQ_INT(pw_mesh_read_memory(NULL, b.data, b.size - 2, "bin.off", &m, &e), PW_ERR_PARSE);
    CHECK(strstr(e.msg, "bin.off") && strstr(e.msg, "face 1"));
    /* index out of range */
    b.data[b.size - 12 - 8 + 3] = 9;
    pw_err_clear(&e);
    CHECK_EQ_INT(pw_mesh_read_memory(NULL, b.data, b.size, "bin.off", &m, &e), PW_ERR_INVALID);
    CHECK(strstr(e.msg, "face 1: vertex index 9 out of range") != NULL);
    free(b.data);
}

/* ---- PLY ------------------------------------------------------------------ */

static const char *ply_ascii =
    "ply\r\n"
    "format ascii 1.0\r\n"
    "comment made by hand\r\n"
    "obj_info nothing\r\n"
    "element vertex 4\r\n"
    "property double x\r\n"
    "property float y\r\n"
    "property float z\r\n"
    "property uchar red\r\n"
    "property list uchar float extra\r\n"
    "element face 2\r\n"
    "property list uchar int vertex_indices\r\n"
    "property int label\r\n"
    "element edge 1\r\n"
    "property int vertex1\r\n"
    "property int vertex2\r\n"
    "end_header\r\n"
    "0 0 0 255 0\r\n"
    "1 0 0 255 2 0.5 0.5\r\n"
    "1 1 0.5 0 1 7\r\n"
    "0 1 0 0 0\r\n"
    "4 0 1 2 3 -1\r\n"
    "3 0 2 3\r\n 17\r\n" /* any whitespace separates values */
    "0 1\r\n";

static void t_ply_ascii(void)
{
    pw_mesh m;
    pw_err e;
    REQUIRE(rd(ply_ascii, "a.ply", &m, &e) == PW_OK);
    CHECK(m.nv == 4 && m.nf == 2 && face_deg(&m, 0) == 4 && face_deg(&m, 1) == 3);
    CHECK(m.pos[8] == 0.5f && m.fv[6] == 3 && m.uv == NULL);
    pw_mesh_free(NULL, &m);
    /* texture coordinates and the vertex_index alias */
    REQUIRE(rd("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
               "property float s\nproperty float t\nelement face 1\nproperty list uint8 uint32 vertex_index\n"
               "end_header\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 0.75\n3 0 1 2\n",
               "uv.ply", &m, &e) == PW_OK);
    REQUIRE(m.uv != NULL && m.fuv != NULL);
    CHECK(m.nuv == 3 && m.uv[5] == 0.75f && m.fuv[2] == 2);
    pw_mesh_free(NULL, &m);
    REQUIRE(rd("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
               "property float texture_u\nproperty float texture_v\nelement face 1\nproperty list uchar int vertex_indices\n"
               "end_header\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 0.5\n3 0 1 2\n",
               "uv2.ply", &m, &e) == PW_OK);
    CHECK(m.uv != NULL && m.uv[5] == 0.5f);
    pw_mesh_free(NULL, &m);
}

/* Writes the same mesh as ply_ascii in binary with many types. */
static void write_scalar(pw_buf *b, int big, int size, const void *le_bytes)
{
    unsigned char t[8];
    int i;
    for (i = 0; i < size; i++) t[i] = ((const unsigned char *)le_bytes)[big ? size - 1 - i : i];
    pw_buf_write(b, t, (size_t)size);
}
static int host_big(void)
{
    uint16_t x = 1;
    unsigned char c;
    memcpy(&c, &x, 1);
    return c == 0;
}
static void put_le(pw_buf *b, int big, int size, const void *host)
{
    unsigned char t[8];
    int i;
    if (host_big())
        for (i = 0; i < size; i++) t[i] = ((const unsigned char *)host)[size - 1 - i];
    else
        memcpy(t, host, (size_t)size);
    write_scalar(b, big, size, t);
}

static void make_binary_ply(pw_buf *b, int big)
{
    static const double xs[4] = {0, 1, 1, 0};
    static const float ys[4] = {0, 0, 1, 1};
    static const short zs[4] = {0, 0, -3, 0};
    const char *hdr_fmt =
        "ply\nformat %s 1.0\ncomment binary test\n"
        "element vertex 4\nproperty float64 x\nproperty uchar flags\nproperty float32 y\n"
        "property list ushort int8 junk\nproperty int16 z\nproperty uint t\n"
        "element material 2\nproperty float r\nproperty double g\n"
        "element face 2\nproperty int label\nproperty list uint8 uint32 vertex_indices\n"
        "property list int short extra\n"
        "element edge 1\nproperty list uchar int pair\n"
        "end_header\n";
    char hdr[1024];
    int i, k;
    snprintf(hdr, sizeof hdr, hdr_fmt, big ? "binary_big_endian" : "binary_little_endian");
    memset(b, 0, sizeof *b);
    pw_buf_write(b, hdr, strlen(hdr));
    for (i = 0; i < 4; i++) {
        unsigned char fl = 7;
        unsigned short nj = (unsigned short)i;
        signed char j = -5;
        unsigned int t = 0xDEADBEEFu;
        put_le(b, big, 8, &xs[i]);
        pw_buf_write(b, &fl, 1);
        put_le(b, big, 4, &ys[i]);
        put_le(b, big, 2, &nj);
        for (k = 0; k < i; k++) pw_buf_write(b, &j, 1);
        put_le(b, big, 2, &zs[i]);
        put_le(b, big, 4, &t);
    }
    for (i = 0; i < 2; i++) {
        float r = 0.5f;
        double g = 0.25;
        put_le(b, big, 4, &r);
        put_le(b, big, 8, &g);
    }
    for (i = 0; i < 2; i++) {
        static const unsigned int f0[4] = {0, 1, 2, 3}, f1[3] = {0, 2, 3};
        int label = 42, nx = 1;
        short x = -1;
        unsigned char n = (unsigned char)(i == 0 ? 4 : 3);
        put_le(b, big, 4, &label);
        pw_buf_write(b, &n, 1);
        for (k = 0; k < n; k++) put_le(b, big, 4, i == 0 ? &f0[k] : &f1[k]);
        put_le(b, big, 4, &nx);
        put_le(b, big, 2, &x);
    }
    {
        unsigned char n = 2;
        int v0 = 0, v1 = 1;
        pw_buf_write(b, &n, 1);
        put_le(b, big, 4, &v0);
        put_le(b, big, 4, &v1);
    }
}

static void t_ply_binary(void)
{
    int big;
    for (big = 0; big < 2; big++) {
        pw_buf b;
        pw_mesh m;
        pw_err e;
        size_t cut;
        make_binary_ply(&b, big);
        pw_err_clear(&e);
        REQUIRE(pw_mesh_read_memory(NULL, b.data, b.size, "bin.ply", &m, &e) == PW_OK);
        CHECK(m.nv == 4 && m.nf == 2 && face_deg(&m, 0) == 4 && face_deg(&m, 1) == 3);
        CHECK(m.pos[3] == 1.0f && m.pos[7] == 1.0f && m.pos[8] == -3.0f && m.fv[6] == 3);
        CHECK(m.uv == NULL);
        pw_mesh_free(NULL, &m);
        /* every truncation fails cleanly, naming a byte offset */
        for (cut = b.size - 1; cut > b.size - 60; cut--) {
            pw_err_clear(&e);
            CHECKF(pw_mesh_read_memory(NULL, b.data, cut, "bin.ply", &m, &e) == PW_ERR_PARSE,
                   "cut at %lu: %s", (unsigned long)cut, e.msg);
            CHECK(strstr(e.msg, "bin.ply") != NULL);
        }
        free(b.data);
    }
}

/* EXPECT_ERR on an ASCII PLY file of 3 vertices and 1 face whose header
 * (10 lines) is followed by `body`. */
static void expect_ply_err_(int line, const char *body, const char *name, int code, const char *f1,
                            const char *f2)
{
    static const char vhdr[] =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    char text[1024];
    snprintf(text, sizeof text, "%s%s", vhdr, body);
    expect_err_(line, text, name, code, f1, f2);
}
#define EXPECT_PLY_ERR(body, name, code, f1, f2) expect_ply_err_(__LINE__, body, name, code, f1, f2)

static void t_ply_errors(void)
{
    EXPECT_ERR("ply\nformat ascii 1.0\nelement vertex 3\n", "h.ply", PW_ERR_PARSE, "h.ply:", "end_header");
    EXPECT_ERR("ply\nformat binary_middle_endian 1.0\nend_header\n", "f.ply", PW_ERR_UNSUPPORTED, "f.ply:2:", "binary_middle_endian");
    EXPECT_ERR("ply\nformat ascii 2.0\nend_header\n", "f.ply", PW_ERR_UNSUPPORTED, "f.ply:2:", "version");
    EXPECT_ERR("ply\nformat ascii 1.0\nelement vertex 3\nproperty float128 x\nend_header\n", "t.ply", PW_ERR_PARSE, "t.ply:4:",
               "unknown property type 'float128'");
    EXPECT_ERR("ply\nformat ascii 1.0\nelement vertex 3\nbogus\nend_header\n", "k.ply", PW_ERR_PARSE, "k.ply:4:", "'bogus'");
    EXPECT_ERR("ply\nformat ascii 1.0\nproperty float x\nend_header\n", "p.ply", PW_ERR_PARSE, "p.ply:3:", "before any element");
    EXPECT_ERR("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n", "xyz.ply",
               PW_ERR_PARSE, "xyz.ply", "x, y and z");
    EXPECT_ERR("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n"
               "0 0 0\n1 0 0\n0 1 0\n", "pc.ply", PW_ERR_DEGENERATE, "pc.ply", "no faces");
    EXPECT_ERR("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
               "element face 1\nproperty int label\nend_header\n0 0 0\n1 0 0\n0 1 0\n5\n", "nf.ply", PW_ERR_PARSE, "nf.ply",
               "vertex_indices");
    EXPECT_PLY_ERR("0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "i.ply", PW_ERR_INVALID, "i.ply:13:",
                   "face 0: vertex index 3 out of range");
    EXPECT_PLY_ERR("0 0 0\n1 0 0\n0 1 0\n3 0 1 1.5\n", "i.ply", PW_ERR_INVALID, "i.ply:13:", "index 1.5");
    EXPECT_PLY_ERR("0 0 0\n1 inf 0\n0 1 0\n3 0 1 2\n", "n.ply", PW_ERR_INVALID, "n.ply:11:",
                   "vertex 1 has a non-finite coordinate");
    EXPECT_PLY_ERR("0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "d.ply", PW_ERR_DEGENERATE, "d.ply:13:", "face 0 has 2 corners");
    EXPECT_PLY_ERR("0 0 0\n1 0 0\n0 1 0\n3 0 1", "tr.ply", PW_ERR_PARSE, "tr.ply:13:", "end of file in face 0");
    EXPECT_PLY_ERR("0 0 0\n1 0 x\n0 1 0\n3 0 1 2\n", "x.ply", PW_ERR_PARSE, "x.ply:11:", "malformed number 'x'");
    EXPECT_PLY_ERR("0 0 0\n1 0 0\n0 1 0\n-3 0 1 2\n", "c.ply", PW_ERR_PARSE, "c.ply:13:", "bad list length");
    EXPECT_ERR("ply\nformat ascii 1.0\nelement vertex 3\nelement vertex 3\nend_header\n", "2v.ply", PW_ERR_PARSE, ":4:",
               "second 'vertex'");
    EXPECT_ERR("plyx\n", "m.ply", PW_ERR_PARSE, "m.ply", "not a PLY file");
}

/* ---- detection, utilities -------------------------------------------------- */

static void t_detect(void)
{
    pw_mesh m;
    pw_err e;
    const char *tri_off = "# comment first\nOFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    REQUIRE(rd(tri_off, "no-extension", &m, &e) == PW_OK); /* keyword after comments */
    pw_mesh_free(NULL, &m);
    REQUIRE(rd(ply_ascii, NULL, &m, &e) == PW_OK); /* magic */
    pw_mesh_free(NULL, &m);
    REQUIRE(rd("\xEF\xBB\xBFv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "bom.txt", &m, &e) == PW_OK);
    pw_mesh_free(NULL, &m);
    /* OBJ syntax in a file named .off is read as OFF and refused clearly */
    EXPECT_ERR("v 0 0 0\n", "wrong.OFF", PW_ERR_PARSE, "wrong.OFF:1:", "expected the OFF keyword");
    EXPECT_ERR("v 0 0 0\n", "wrong.ply", PW_ERR_PARSE, "wrong.ply", "not a PLY file");
}

static void t_triangulate(void)
{
    pw_mesh m, t;
    pw_err e;
    int *map = NULL, i;
    static const int expect[] = {0, 1, 2, 0, 2, 3, 3, 2, 4};
    make_quad_uv_mesh(&m);
    pw_err_clear(&e);
    REQUIRE(pw_mesh_triangulate(NULL, &m, &t, &map, &e) == PW_OK);
    CHECK_EQ_INT(t.nf, 3);
    CHECK_EQ_INT(t.fstart[3], 9);
    for (i = 0; i < 9; i++) CHECK_EQ_INT(t.fv[i], expect[i]);
    CHECK(map[0] == 0 && map[1] == 0 && map[2] == 1);
    CHECK(t.fuv && t.fuv[5] == 3 && t.nuv == 5 && t.uv[9] == 0.25f);
    CHECK(memcmp(t.pos, m.pos, 15 * sizeof(float)) == 0);
    pw_free(NULL, map);
    pw_mesh_free(NULL, &t);
    REQUIRE(pw_mesh_triangulate(NULL, &m, &t, NULL, &e) == PW_OK);
    pw_mesh_free(NULL, &t);
    m.fstart[1] = 2; /* a 2-gon */
    pw_err_clear(&e);
    CHECK_EQ_INT(pw_mesh_triangulate(NULL, &m, &t, &map, &e), PW_ERR_DEGENERATE);
    CHECK(map == NULL && t.pos == NULL);
    pw_mesh_free(NULL, &m);
}

static void t_utils(void)
{
    pw_mesh m, c;
    pw_err e;
    float lo[3], hi[3];
    make_quad_uv_mesh(&m);
    pw_mesh_bounds(&m, lo, hi);
    CHECK(lo[0] == 0 && lo[1] == 0 && lo[2] == 0 && hi[0] == 1 && hi[1] == 1.5f && hi[2] == 1e-7f);
    pw_err_clear(&e);
    REQUIRE(pw_mesh_copy(NULL, &m, &c, &e) == PW_OK);
    CHECK(same_mesh(&m, &c));
    CHECK(c.pos != m.pos && c.uv != m.uv);
    CHECK_EQ_INT(pw_mesh_validate(&c, &e), PW_OK);
    pw_mesh_free(NULL, &c);
    pw_mesh_free(NULL, &m);
    pw_mesh_free(NULL, &m); /* freeing twice is harmless: the struct is zeroed */
    memset(&m, 0, sizeof m);
    pw_mesh_bounds(&m, lo, hi);
    CHECK(lo[0] == 0 && hi[2] == 0);
    CHECK_EQ_INT(pw_mesh_alloc(NULL, &m, PW_MAX_MESH_ELEMENTS + 1, 1, 3, 0, &e), PW_ERR_LIMIT);
    pw_err_clear(&e);
    CHECK_EQ_INT(pw_mesh_alloc(NULL, &m, -1, 1, 3, 0, &e), PW_ERR_INVALID);
    REQUIRE(pw_mesh_alloc(NULL, &m, 3, 1, 3, 1, NULL) == PW_OK);
    CHECK(m.nuv == 3 && m.fuv[2] == 2 && m.uv[5] == 0.0f);
    pw_mesh_free(NULL, &m);
}

/* Every allocation failure in every reader is reported and leaks nothing. */
static void t_alloc_failures(void)
{
    pw_buf bin;
    const char *texts[4];
    size_t sizes[4];
    int i;
    make_binary_ply(&bin, 1);
    texts[0] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\nf 3/1 2/1 1/1\n";
    texts[1] = "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 2 1 0\n";
    texts[2] = ply_ascii;
    texts[3] = (const char *)bin.data;
    for (i = 0; i < 4; i++) sizes[i] = i == 3 ? bin.size : strlen(texts[i]);
    for (i = 0; i < 4; i++) {
        int budget, ok = 0;
        for (budget = 0; budget < 200 && !ok; budget++) {
            talloc t;
            pw_alloc a = make_alloc(&t, budget);
            pw_mesh m;
            pw_err e;
            int r;
            pw_err_clear(&e);
            r = pw_mesh_read_memory(&a, texts[i], sizes[i], "alloc", &m, &e);
            if (r == PW_OK) {
                ok = 1;
                pw_mesh_free(&a, &m);
            } else
                CHECKF(r == PW_ERR_NOMEM, "format %d budget %d: %d %s", i, budget, r, e.msg);
            CHECKF(t.s.live == 0, "format %d budget %d: %ld blocks leaked", i, budget, t.s.live);
        }
        CHECK(ok);
    }
    free(bin.data);
}

/* The float formatter: 9 significant digits, shortest form, same values
 * as printf's %.9g. */
static void t_float_format(void)
{
    static const float vals[] = {0.0f, 1.0f, -1.5f, 0.5f, 1e-7f, 123456789.0f, 16777216.0f, 1e9f, 1e10f,
                                 3.14159265f, 0.0001f, 0.00001f, 1e-6f, FLT_MAX, FLT_MIN, -2.5e-40f, 100.0f, 0.1f};
    static const char *const want[] = {"0", "1", "-1.5", "0.5", "1.00000001e-7", "123456792", "16777216", "1e9", "1e10",
                                       "3.14159274", "9.99999975e-5", "9.99999975e-6", "9.99999997e-7",
                                       "3.40282347e38", "1.17549435e-38", "-2.50000054e-40", "100", "0.100000001"};
    size_t i;
    char buf[32];
    for (i = 0; i < sizeof vals / sizeof vals[0]; i++) {
        int n = pw__num_format(buf, vals[i]);
        double back;
        buf[n] = 0;
        CHECKF(strcmp(buf, want[i]) == 0, "%.9g printed as '%s', expected '%s'", (double)vals[i], buf, want[i]);
        CHECK(pw__num_parse(buf, buf + n, &back) == buf + n && pw__num_to_float(back) == vals[i]);
    }
    {
        int n = pw__num_format(buf, -0.0f);
        buf[n] = 0;
        CHECK(strcmp(buf, "-0") == 0);
    }
}

/* On random bit patterns the formatter gives the digits of printf's %.9g
 * (same value once parsed, ties rounded to even alike) and reads back to
 * the same float. */
static void t_float_format_random(void)
{
    uint32_t st = 99;
    int i, bad = 0, ties = 0;
    for (i = 0; i < 200000; i++) {
        char a[32], b[40];
        uint32_t bits;
        float f;
        double va, vb;
        int n;
        st = st * 1664525u + 1013904223u;
        bits = st ^ (st >> 13) << 7;
        memcpy(&f, &bits, 4);
        if (!pw_is_finite(f)) continue;
        n = pw__num_format(a, f);
        a[n] = 0;
        snprintf(b, sizeof b, "%.9g", (double)f);
        va = strtod(a, NULL), vb = strtod(b, NULL);
        if ((float)va != f) bad++;
        if (va != vb) ties++;
    }
    CHECK_EQ_INT(bad, 0);
    CHECK_EQ_INT(ties, 0);
}

/* Number parsing agrees with strtod (in the C locale) on typical inputs. */
static void t_numbers(void)
{
    static const char *const nums[] = {"0", "-0", "1", "-1.5", "3.14159265358979", "1e10", "1E-10", "+2.5e+3",
                                       ".5", "5.", "0.1", "0.44719999999999999", "123456789012345678901234",
                                       "1e-45", "3.4028234e38", "1.17549435e-38", "0.000000000000000000001"};
    size_t i;
    for (i = 0; i < sizeof nums / sizeof nums[0]; i++) {
        double v = 0;
        const char *end = nums[i] + strlen(nums[i]);
        const char *q = pw__num_parse(nums[i], end, &v);
        CHECKF(q == end, "%s not fully parsed", nums[i]);
        CHECKF(pw__num_to_float(v) == (float)strtod(nums[i], NULL), "%s: %.9g vs %.9g", nums[i], v,
               strtod(nums[i], NULL));
    }
}

/* ---- real data ------------------------------------------------------------ */

static void t_real_data(void)
{
    static const char *const files[] = {"meshes/elephant.off", "meshes/cube_quad.off", "meshes/mesh_with_colors.off",
                                        "meshes/cactus.off", "meshes/sphere.ply", "meshes/colored_tetra.ply",
                                        "meshes/blobby-shuffled.off"};
    static const int nv[] = {2775, 8, 8, 620, 162, 4, 2027}, nf[] = {5558, 6, 4, 1236, 320, 4, 4050};
    size_t i;
    int found = 0;
    for (i = 0; i < sizeof files / sizeof files[0]; i++) {
        const char *path = pwt_data_opt(files[i]);
        pw_mesh m;
        pw_err e;
        if (!path) continue;
        found++;
        pw_err_clear(&e);
        if (pw_mesh_load(NULL, path, &m, &e)) {
            CHECKF(0, "%s: %s", path, e.msg);
            continue;
        }
        CHECKF(m.nv == nv[i] && m.nf == nf[i], "%s: %d vertices, %d faces", path, m.nv, m.nf);
        CHECK_EQ_INT(pw_mesh_validate(&m, &e), PW_OK);
        pw_mesh_free(NULL, &m);
    }
    if (!found) pwt_data("meshes/elephant.off"); /* reports the skip */
    else pwt_info("%d real meshes read", found);
}

static void t_b9_point_cloud(void)
{
    const char *p = pwt_data("meshes/b9.ply");
    pw_mesh m;
    pw_err e;
    if (!p) return;
    pw_err_clear(&e);
    CHECK_EQ_INT(pw_mesh_load(NULL, p, &m, &e), PW_ERR_DEGENERATE);
    CHECK(strstr(e.msg, "no faces") && strstr(e.msg, "22300 vertices"));
}

/* ---- STL ------------------------------------------------------------------- */

/* A tetrahedron as ASCII STL: 4 facets, 12 corners on 4 positions (one of
 * them written -0 in one facet and 0 in the others). */
static const char stl_ascii[] =
    "solid tet\n"
    "  facet normal 0 0 -1\n    outer loop\n      vertex 0 0 0\n      vertex 0 1 0\n      vertex 1 0 0\n    endloop\n  endfacet\n"
    "  facet normal 0 -1 0\n    outer loop\n      vertex -0 0 0\n      vertex 1 0 0\n      vertex 0 0 1\n    endloop\n  endfacet\n"
    "  facet normal -1 0 0\n    outer loop\n      vertex 0 0 0\n      vertex 0 0 1\n      vertex 0 1 0\n    endloop\n  endfacet\n"
    "  facet normal 1 1 1\n    outer loop\n      vertex 1 0 0\n      vertex 0 1 0\n      vertex 0 0 1\n    endloop\n  endfacet\n"
    "endsolid tet\n";

/* The same as binary STL (a header beginning with "solid", as exporters
 * often write), into buf; returns its size. */
static size_t stl_binary(unsigned char *buf, int count_delta)
{
    static const float c[4][3][3] = {{{0, 0, 0}, {0, 1, 0}, {1, 0, 0}},
                                     {{-0.0f, 0, 0}, {1, 0, 0}, {0, 0, 1}},
                                     {{0, 0, 0}, {0, 0, 1}, {0, 1, 0}},
                                     {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    uint32_t n = 4 + count_delta;
    int t, k, j;
    memset(buf, 0, 84 + 4 * 50);
    memcpy(buf, "solid exported by a CAD program", 31);
    buf[80] = (unsigned char)n, buf[81] = (unsigned char)(n >> 8), buf[82] = (unsigned char)(n >> 16), buf[83] = (unsigned char)(n >> 24);
    for (t = 0; t < 4; t++)
        for (k = 0; k < 3; k++)
            for (j = 0; j < 3; j++) {
                uint32_t u;
                memcpy(&u, &c[t][k][j], 4);
                buf[84 + 50 * t + 12 + 12 * k + 4 * j] = (unsigned char)u;
                buf[84 + 50 * t + 13 + 12 * k + 4 * j] = (unsigned char)(u >> 8);
                buf[84 + 50 * t + 14 + 12 * k + 4 * j] = (unsigned char)(u >> 16);
                buf[84 + 50 * t + 15 + 12 * k + 4 * j] = (unsigned char)(u >> 24);
            }
    return 84 + 4 * 50;
}

static void t_stl(void)
{
    unsigned char bin[84 + 4 * 50];
    size_t n = stl_binary(bin, 0);
    pw_mesh a, b;
    pw_err e;
    int k;
    REQUIRE(rd(stl_ascii, "tet.stl", &a, &e) == PW_OK);
    pw_err_clear(&e);
    REQUIRE(pw_mesh_read_memory(NULL, bin, n, "tet.stl", &b, &e) == PW_OK);
    CHECK(a.nv == 4 && a.nf == 4 && a.fstart[4] == 12 && !a.uv);
    CHECK(b.nv == a.nv && b.nf == a.nf && !memcmp(a.pos, b.pos, 12 * sizeof(float)) && !memcmp(a.fv, b.fv, 12 * sizeof(int)));
    for (k = 0; k < 12; k++) CHECK(a.fv[k] >= 0 && a.fv[k] < 4);
    pw_mesh_free(NULL, &a);
    pw_mesh_free(NULL, &b);
    /* by content, whatever the name says */
    CHECK(rd(stl_ascii, "scan.obj", &a, &e) == PW_OK && a.nf == 4);
    pw_mesh_free(NULL, &a);
    pw_err_clear(&e);
    CHECK(pw_mesh_read_memory(NULL, bin, n, NULL, &b, &e) == PW_OK && b.nf == 4);
    pw_mesh_free(NULL, &b);
}

static void t_stl_errors(void)
{
    unsigned char bin[84 + 4 * 50];
    size_t n = stl_binary(bin, 1);
    pw_mesh m;
    pw_err e;
    float nan = 0.0f / 0.0f;
    uint32_t u;
    pw_err_clear(&e);
    CHECK(pw_mesh_read_memory(NULL, bin, n, "five.stl", &m, &e) == PW_ERR_PARSE && strstr(e.msg, "claims 5 triangles") &&
          strstr(e.msg, "five.stl"));
    n = stl_binary(bin, 0);
    memcpy(&u, &nan, 4);
    bin[84 + 50 + 12 + 4] = (unsigned char)u, bin[84 + 50 + 13 + 4] = (unsigned char)(u >> 8);
    bin[84 + 50 + 14 + 4] = (unsigned char)(u >> 16), bin[84 + 50 + 15 + 4] = (unsigned char)(u >> 24);
    pw_err_clear(&e);
    CHECK(pw_mesh_read_memory(NULL, bin, n, "nan.stl", &m, &e) == PW_ERR_INVALID && strstr(e.msg, "triangle 1"));
    EXPECT_ERR("solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 1 0\n  endfacet\nendsolid\n",
               "x.stl", PW_ERR_PARSE, "x.stl:7", "expected 'endloop'");
    EXPECT_ERR("solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n", "x.stl", PW_ERR_PARSE, "x.stl",
               "expected 'vertex'");
    EXPECT_ERR("solid empty\nendsolid empty\n", "x.stl", PW_ERR_DEGENERATE, "x.stl", "");
    EXPECT_ERR("tiny", "x.stl", PW_ERR_PARSE, "not an STL file", "x.stl");
}

static const pwt_case cases[] = {
    {"obj_basic", t_obj_basic},
    {"stl", t_stl},
    {"stl_errors", t_stl_errors},
    {"obj_forms", t_obj_forms},
    {"obj_continuation_and_skipped", t_obj_continuation_and_skipped},
    {"obj_errors", t_obj_errors},
    {"obj_face_degree_limit", t_obj_face_degree_limit},
    {"obj_roundtrip", t_obj_roundtrip},
    {"obj_float_roundtrip", t_obj_float_roundtrip},
    {"mtl", t_mtl},
    {"writer_errors", t_writer_errors},
    {"writer_locale", t_locale},
#ifndef PW_NO_STDIO
    {"files", t_files},
#endif
    {"off_variants", t_off_variants},
    {"off_errors", t_off_errors},
    {"off_binary", t_off_binary},
    {"huge_counts", t_huge_counts},
    {"ply_ascii", t_ply_ascii},
    {"ply_binary", t_ply_binary},
    {"ply_errors", t_ply_errors},
    {"detect", t_detect},
    {"triangulate", t_triangulate},
    {"utils", t_utils},
    {"alloc_failures", t_alloc_failures},
    {"numbers", t_numbers},
    {"float_format", t_float_format},
    {"float_format_random", t_float_format_random},
    {"real_data", t_real_data},
    {"b9_point_cloud", t_b9_point_cloud},
};
PWT_MAIN(cases)
