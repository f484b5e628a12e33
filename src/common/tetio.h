/* tetio: tetrahedral mesh files, TetGen .node/.ele and MEDIT .mesh.
 *
 * Readers (from memory; `name` only appears in messages):
 *   TetGen (wias-berlin.de/software/tetgen/fformats.html): a .node file
 *     "<points> <dimension 3> <attributes> <boundary markers 0|1>" and one
 *     line per point "<index> <x> <y> <z> [attributes] [marker]"; an .ele
 *     file "<tetrahedra> <nodes per tet 4|10> <region attribute 0|1>" and
 *     "<index> <n1> ... <nk> [attribute]". Indices start at 0 or 1 (the
 *     first point decides, as in TetGen) and must follow each other; the
 *     .ele corners use the same numbering; of a 10-node (quadratic)
 *     tetrahedron the 4 corners are kept. '#' starts a comment. Dimension 2
 *     is PW_ERR_UNSUPPORTED.
 *   MEDIT ASCII .mesh (INRIA's format, as TetGen -g and Gmsh write it):
 *     keywords MeshVersionFormatted, Dimension 3, Vertices (x y z ref),
 *     Tetrahedra (a b c d ref, 1-based), End; the blocks Edges, Triangles,
 *     Quadrilaterals, Hexahedra, Prisms, Corners, Ridges, Required*,
 *     Normals, Tangents, NormalAtVertices, TangentAtVertices and
 *     TangentAtEdges are skipped; any other keyword, binary .meshb files
 *     and Dimension 2 are PW_ERR_UNSUPPORTED. Numbers may wrap lines freely.
 * Both readers refuse, naming the file, line and element: truncated data,
 * counts the data cannot hold (checked before allocating), sizes over
 * PW_MAX_MESH_ELEMENTS, indices out of range, non-finite coordinates; and,
 * through pw_tetmesh_check, degenerate tetrahedra (negatively oriented ones
 * are flipped).
 * Writers: pw_tetgen_write_node / _ele (0-based, "# written by patchwork"),
 * pw_medit_write (MeshVersionFormatted 1, Vertices, Tetrahedra, End); floats
 * with 9 significant digits, so write -> read is exact.
 *
 *   pw_tetgen_read_memory, pw_medit_read_memory, pw_tetgen_write_node,
 *   pw_tetgen_write_ele, pw_medit_write, pw_tetmesh_load, pw_tetmesh_save */
#ifndef PW__TETIO_V1
#define PW__TETIO_V1

#include "base.h"
#include "text.h"
#include "tetmesh.h"

/* ---- shared pieces ---------------------------------------------------------- */

/* A count: a non-negative integer within the mesh limit, and at most one
 * element per `min_bytes` of data left (so an absurd count fails before
 * anything is allocated). */
PW__DEF int pw__tio_count(pw__sc *s, const char *what, long long v, size_t min_bytes, int *out)
{
    if (v < 0) return pw__sc_fail(s, PW_ERR_PARSE, "negative %s (%lld)", what, v);
    if (v > PW_MAX_MESH_ELEMENTS)
        return pw__sc_fail(s, PW_ERR_LIMIT, "%s is %lld, over the limit of %d", what, v, PW_MAX_MESH_ELEMENTS);
    if ((unsigned long long)v > (unsigned long long)(s->end - s->p) / min_bytes + 1)
        return pw__sc_fail(s, PW_ERR_PARSE, "%lld %s announced, the file is too short for them", v, what);
    *out = (int)v;
    return PW_OK;
}

/* A coordinate: finite, and as a float. */
PW__DEF int pw__tio_coord(pw__sc *s, float *out, const char *what, long long index)
{
    double x;
    int r = pw__sc_num(s, &x, what, index);
    if (r != PW_OK) return r;
    *out = pw__num_to_float(x);
    if (!pw_is_finite(*out)) return pw__sc_fail(s, PW_ERR_INVALID, "%s %lld has a non-finite coordinate", what, index);
    return PW_OK;
}

/* ---- TetGen ------------------------------------------------------------------- */

/* Reads the integers of a header line into v[0..n): the first `required`
 * must be there, the others default to 0. */
PW__DEF int pw__tio_header(pw__sc *s, long long *v, int n, int required, const char *what)
{
    int k, r;
    pw__sc_skip_empty(s);
    for (k = 0; k < n; k++) {
        v[k] = 0;
        if (k >= required && pw__sc_eol(s)) continue;
        if ((r = pw__sc_int(s, &v[k], what, -1)) != PW_OK) return r;
    }
    if (!pw__sc_eol(s)) return pw__sc_fail(s, PW_ERR_PARSE, "unexpected text after the %s", what);
    pw__sc_next_line(s);
    return PW_OK;
}

/* The leading index of element i: base + i (base is taken from element 0). */
PW__DEF int pw__tio_index(pw__sc *s, long long *base, int i, const char *what)
{
    long long id;
    int r;
    pw__sc_skip_empty(s);
    if ((r = pw__sc_int(s, &id, what, i)) != PW_OK) return r;
    if (i == 0 && (id == 0 || id == 1)) *base = id;
    else if (i == 0) return pw__sc_fail(s, PW_ERR_PARSE, "the first %s is numbered %lld (0 or 1 expected)", what, id);
    if (id != *base + i)
        return pw__sc_fail(s, PW_ERR_PARSE, "%s %d is numbered %lld, expected %lld", what, i, id, *base + i);
    return PW_OK;
}

/* Skips `n` trailing numbers of an element line and checks the line ends. */
PW__DEF int pw__tio_rest(pw__sc *s, int n, const char *what, long long index)
{
    double x;
    int k, r;
    for (k = 0; k < n; k++)
        if ((r = pw__sc_num(s, &x, what, index)) != PW_OK) return r;
    if (!pw__sc_eol(s))
        return pw__sc_fail(s, PW_ERR_PARSE, "%s %lld: unexpected text at the end of the line", what, index);
    pw__sc_next_line(s);
    return PW_OK;
}

PW__DEF int pw__tetgen_nodes(const pw_alloc *a, pw__sc *s, pw_tetmesh *m, long long *base, int *extra, pw_err *e)
{
    long long h[4];
    int nv, i, k, r;
    if ((r = pw__tio_header(s, h, 4, 2, "node header")) != PW_OK) return r;
    if (h[1] != 3)
        return pw__sc_fail(s, h[1] == 2 ? PW_ERR_UNSUPPORTED : PW_ERR_PARSE, "dimension %lld (only 3 is supported)",
                           h[1]);
    if (h[2] < 0 || h[2] > 1000 || h[3] < 0 || h[3] > 1)
        return pw__sc_fail(s, PW_ERR_PARSE, "bad attribute (%lld) or marker (%lld) count", h[2], h[3]);
    if ((r = pw__tio_count(s, "points", h[0], 8, &nv)) != PW_OK) return r;
    *extra = (int)(h[2] + h[3]);
    if (!(m->pos = (float *)pw_alloc_array(a, (size_t)nv * 3, sizeof(float), "tetrahedral mesh vertices", e)))
        return PW_ERR_NOMEM;
    m->nv = nv;
    for (i = 0; i < nv; i++) {
        if ((r = pw__tio_index(s, base, i, "point")) != PW_OK) return r;
        for (k = 0; k < 3; k++)
            if ((r = pw__tio_coord(s, m->pos + 3 * i + k, "point", i)) != PW_OK) return r;
        if ((r = pw__tio_rest(s, *extra, "point", i)) != PW_OK) return r;
    }
    pw__sc_skip_empty(s);
    if (s->p < s->end) return pw__sc_fail(s, PW_ERR_PARSE, "unexpected text after the last point");
    return PW_OK;
}

PW__DEF int pw__tetgen_tets(const pw_alloc *a, pw__sc *s, pw_tetmesh *m, long long base, pw_err *e)
{
    long long h[3], ebase = 0, c;
    int nt, i, k, r, per;
    if ((r = pw__tio_header(s, h, 3, 2, "element header")) != PW_OK) return r;
    if (h[1] != 4 && h[1] != 10)
        return pw__sc_fail(s, PW_ERR_UNSUPPORTED, "%lld nodes per tetrahedron (4 or 10 expected)", h[1]);
    if (h[2] < 0 || h[2] > 1) return pw__sc_fail(s, PW_ERR_PARSE, "bad region attribute count %lld", h[2]);
    per = (int)h[1];
    if ((r = pw__tio_count(s, "tetrahedra", h[0], 10, &nt)) != PW_OK) return r;
    if (!(m->tet = (int *)pw_alloc_array(a, (size_t)nt * 4, sizeof(int), "tetrahedra", e))) return PW_ERR_NOMEM;
    m->nt = nt;
    for (i = 0; i < nt; i++) {
        if ((r = pw__tio_index(s, &ebase, i, "tetrahedron")) != PW_OK) return r;
        for (k = 0; k < per; k++) {
            if ((r = pw__sc_int(s, &c, "tetrahedron", i)) != PW_OK) return r;
            if (c < base || c >= base + m->nv)
                return pw__sc_fail(s, PW_ERR_INVALID, "tetrahedron %d: point %lld does not exist (%lld..%lld)", i, c,
                                   base, base + m->nv - 1);
            if (k < 4) m->tet[4 * i + k] = (int)(c - base);
        }
        if ((r = pw__tio_rest(s, (int)h[2], "tetrahedron", i)) != PW_OK) return r;
    }
    pw__sc_skip_empty(s);
    if (s->p < s->end) return pw__sc_fail(s, PW_ERR_PARSE, "unexpected text after the last tetrahedron");
    return PW_OK;
}

/* A file's bytes held in memory, and its name for messages (NULL: none). */
typedef struct pw_memfile {
    const void *data;
    size_t size;
    const char *name;
} pw_memfile;

PW__DEF pw_memfile pw_memfile_of(const void *data, size_t size, const char *name)
{
    pw_memfile f;
    f.data = data;
    f.size = size;
    f.name = name;
    return f;
}

/* Reads a TetGen .node file and its .ele file. */
PW__DEF int pw_tetgen_read_memory(const pw_alloc *a, const pw_memfile *node, const pw_memfile *ele, pw_tetmesh *out,
                                  pw_err *e)
{
    const char *ele_name = ele->name ? ele->name : "ele";
    pw__sc s;
    long long base = 0;
    int extra, r;
    memset(out, 0, sizeof *out);
    pw__sc_init(&s, node->data, node->size, node->name ? node->name : "node", 0, e);
    r = pw__tetgen_nodes(a, &s, out, &base, &extra, e);
    if (r == PW_OK) {
        pw__sc_init(&s, ele->data, ele->size, ele_name, 0, e);
        r = pw__tetgen_tets(a, &s, out, base, e);
    }
    if (r == PW_OK) r = pw_tetmesh_check(out, ele_name, e);
    if (r != PW_OK) pw_tetmesh_free(a, out);
    return r;
}

PW__DEF int pw_tetgen_write_node(const pw_tetmesh *m, pw_write_fn w, void *ctx, pw_err *e)
{
    pw__wb b;
    int v, k;
    memset(&b, 0, sizeof b);
    b.w = w;
    b.ctx = ctx;
    pw__wb_str(&b, "# written by patchwork\n");
    pw__wb_int(&b, m->nv, 0);
    pw__wb_str(&b, " 3 0 0\n");
    for (v = 0; v < m->nv; v++) {
        pw__wb_int(&b, v, 0);
        for (k = 0; k < 3; k++) pw__wb_float(&b, m->pos[3 * v + k]);
        pw__wb_str(&b, "\n");
    }
    return pw__wb_done(&b, e);
}

PW__DEF int pw_tetgen_write_ele(const pw_tetmesh *m, pw_write_fn w, void *ctx, pw_err *e)
{
    pw__wb b;
    int t, k;
    memset(&b, 0, sizeof b);
    b.w = w;
    b.ctx = ctx;
    pw__wb_str(&b, "# written by patchwork\n");
    pw__wb_int(&b, m->nt, 0);
    pw__wb_str(&b, " 4 0\n");
    for (t = 0; t < m->nt; t++) {
        pw__wb_int(&b, t, 0);
        for (k = 0; k < 4; k++) pw__wb_int(&b, m->tet[4 * t + k], ' ');
        pw__wb_str(&b, "\n");
    }
    return pw__wb_done(&b, e);
}

/* ---- MEDIT ---------------------------------------------------------------------- */

/* Skips blanks, newlines and comments: MEDIT is a stream of tokens. */
PW__DEF void pw__medit_skip(pw__sc *s)
{
    for (;;) {
        pw__sc_skip_ws(s);
        if (s->p < s->end && *s->p == '#') pw__sc_next_line(s);
        else return;
    }
}

PW__DEF int pw__medit_int(pw__sc *s, long long *v, const char *what, long long index)
{
    pw__medit_skip(s);
    return pw__sc_int(s, v, what, index);
}

PW__DEF int pw__medit_coord(pw__sc *s, float *out, const char *what, long long index)
{
    pw__medit_skip(s);
    return pw__tio_coord(s, out, what, index);
}

/* Blocks skipped, with the numbers per entry. */
PW__DEF int pw__medit_skippable(const char *w, size_t n)
{
    static const char *const names[] = {"Edges",
                                        "Triangles",
                                        "Quadrilaterals",
                                        "Hexahedra",
                                        "Prisms",
                                        "Corners",
                                        "Ridges",
                                        "RequiredVertices",
                                        "RequiredEdges",
                                        "RequiredTriangles",
                                        "RequiredQuadrilaterals",
                                        "Normals",
                                        "Tangents",
                                        "NormalAtVertices",
                                        "TangentAtVertices",
                                        "TangentAtEdges"};
    static const int per[] = {3, 4, 5, 9, 7, 1, 1, 1, 1, 1, 1, 3, 3, 2, 2, 3};
    size_t k;
    for (k = 0; k < sizeof per / sizeof per[0]; k++)
        if (pw__sc_is(w, n, names[k])) return per[k];
    return 0;
}

PW__DEF int pw__medit_block(pw__sc *s, int per, const char *what, int *count)
{
    long long v;
    int r = pw__medit_int(s, &v, what, -1);
    if (r == PW_OK) r = pw__tio_count(s, what, v, (size_t)per * 2, count);
    return r;
}

PW__DEF int pw__medit_vertices(const pw_alloc *a, pw__sc *s, pw_tetmesh *m, pw_err *e)
{
    long long ref;
    int n, i, k, r;
    if (m->pos) return pw__sc_fail(s, PW_ERR_PARSE, "a second Vertices block");
    if ((r = pw__medit_block(s, 4, "vertices", &n)) != PW_OK) return r;
    if (!(m->pos = (float *)pw_alloc_array(a, (size_t)n * 3, sizeof(float), "tetrahedral mesh vertices", e)))
        return PW_ERR_NOMEM;
    m->nv = n;
    for (i = 0; i < n; i++) {
        for (k = 0; k < 3; k++)
            if ((r = pw__medit_coord(s, m->pos + 3 * i + k, "vertex", i)) != PW_OK) return r;
        if ((r = pw__medit_int(s, &ref, "vertex reference", i)) != PW_OK) return r;
    }
    return PW_OK;
}

PW__DEF int pw__medit_tets(const pw_alloc *a, pw__sc *s, pw_tetmesh *m, pw_err *e)
{
    long long c;
    int n, i, k, r;
    if (m->tet) return pw__sc_fail(s, PW_ERR_PARSE, "a second Tetrahedra block");
    if (!m->pos) return pw__sc_fail(s, PW_ERR_PARSE, "Tetrahedra before Vertices");
    if ((r = pw__medit_block(s, 5, "tetrahedra", &n)) != PW_OK) return r;
    if (!(m->tet = (int *)pw_alloc_array(a, (size_t)n * 4, sizeof(int), "tetrahedra", e))) return PW_ERR_NOMEM;
    m->nt = n;
    for (i = 0; i < n; i++)
        for (k = 0; k < 5; k++) {
            if ((r = pw__medit_int(s, &c, "tetrahedron", i)) != PW_OK) return r;
            if (k == 4) continue; /* the reference (region) number */
            if (c < 1 || c > m->nv)
                return pw__sc_fail(s, PW_ERR_INVALID, "tetrahedron %d: vertex %lld does not exist (1..%d)", i, c,
                                   m->nv);
            m->tet[4 * i + k] = (int)(c - 1);
        }
    return PW_OK;
}

/* Skips a block of `per` numbers per entry. */
PW__DEF int pw__medit_skip_block(pw__sc *s, int per, const char *what)
{
    double x;
    int n, i, r;
    if ((r = pw__medit_block(s, per, what, &n)) != PW_OK) return r;
    for (i = 0; i < n * per; i++) {
        pw__medit_skip(s);
        if ((r = pw__sc_num(s, &x, what, i / per)) != PW_OK) return r;
    }
    return PW_OK;
}

/* One keyword and its block; *done at End (or the end of the data). */
PW__DEF int pw__medit_keyword(const pw_alloc *a, pw__sc *s, pw_tetmesh *m, int *done, pw_err *e)
{
    long long v;
    size_t n;
    const char *w;
    char tok[32], name[40];
    int per;
    pw__medit_skip(s);
    w = pw__sc_word(s, &n);
    if (n == 0 || pw__sc_is(w, n, "End")) {
        (*done = 1);
        return PW_OK;
    }
    if (pw__sc_is(w, n, "MeshVersionFormatted")) return pw__medit_int(s, &v, "MeshVersionFormatted", -1);
    if (pw__sc_is(w, n, "Dimension")) {
        int r = pw__medit_int(s, &v, "Dimension", -1);
        if (r == PW_OK && v != 3) return pw__sc_fail(s, PW_ERR_UNSUPPORTED, "Dimension %lld (only 3 is supported)", v);
        return r;
    }
    if (pw__sc_is(w, n, "Vertices")) return pw__medit_vertices(a, s, m, e);
    if (pw__sc_is(w, n, "Tetrahedra")) return pw__medit_tets(a, s, m, e);
    if ((per = pw__medit_skippable(w, n)) != 0) {
        snprintf(name, sizeof name, "%.*s", (int)(n < 30 ? n : 30), w);
        return pw__medit_skip_block(s, per, name);
    }
    return pw__sc_fail(s, PW_ERR_UNSUPPORTED, "unknown MEDIT keyword '%s'", pw__sc_tok(s, w, tok));
}

PW__DEF int pw_medit_read_memory(const pw_alloc *a, const void *data, size_t size, const char *name, pw_tetmesh *out,
                                 pw_err *e)
{
    pw__sc s;
    int done = 0, r = PW_OK;
    const unsigned char *u = (const unsigned char *)data;
    memset(out, 0, sizeof *out);
    if (!name) name = "mesh";
    pw__sc_init(&s, data, size, name, 0, e);
    if (size >= 4 && !u[1] && !u[2] && ((u[0] == 1 && !u[3]) || (!u[0] && u[3] == 1)))
        return pw_fail(e, PW_ERR_UNSUPPORTED, "%s: binary MEDIT (.meshb) files are not supported", name);
    while (!done && r == PW_OK) r = pw__medit_keyword(a, &s, out, &done, e);
    if (r == PW_OK && (!out->pos || !out->tet))
        r = pw__sc_fail(&s, PW_ERR_PARSE, "no %s block", out->pos ? "Tetrahedra" : "Vertices");
    if (r == PW_OK) r = pw_tetmesh_check(out, name, e);
    if (r != PW_OK) pw_tetmesh_free(a, out);
    return r;
}

PW__DEF int pw_medit_write(const pw_tetmesh *m, pw_write_fn w, void *ctx, pw_err *e)
{
    pw__wb b;
    int v, t, k;
    memset(&b, 0, sizeof b);
    b.w = w;
    b.ctx = ctx;
    pw__wb_str(&b, "MeshVersionFormatted 1\nDimension 3\n# written by patchwork\nVertices\n");
    pw__wb_int(&b, m->nv, 0);
    pw__wb_str(&b, "\n");
    for (v = 0; v < m->nv; v++) {
        for (k = 0; k < 3; k++) pw__wb_float(&b, m->pos[3 * v + k]);
        pw__wb_str(&b, " 0\n");
    }
    pw__wb_str(&b, "Tetrahedra\n");
    pw__wb_int(&b, m->nt, 0);
    pw__wb_str(&b, "\n");
    for (t = 0; t < m->nt; t++) {
        for (k = 0; k < 4; k++) pw__wb_int(&b, m->tet[4 * t + k] + 1, ' ');
        pw__wb_str(&b, " 0\n");
    }
    pw__wb_str(&b, "End\n");
    return pw__wb_done(&b, e);
}

/* ---- files ------------------------------------------------------------------------ */

#ifndef PW_NO_STDIO
/* `path` with its extension (after the last '.' of the last component)
 * replaced by `ext`, into out (size bytes); 0 if it does not fit. */
PW__DEF int pw__tio_sibling(const char *path, const char *ext, char *out, size_t size)
{
    size_t n = strlen(path), dot = n, i;
    for (i = n; i > 0 && path[i - 1] != '/' && path[i - 1] != '\\'; i--)
        if (path[i - 1] == '.') {
            dot = i - 1;
            break;
        }
    if (dot + strlen(ext) + 1 > size) return 0;
    memcpy(out, path, dot);
    strcpy(out + dot, ext);
    return 1;
}

/* Reads FILE.node with FILE.ele beside it, or FILE.mesh (by extension;
 * FILE.ele also finds FILE.node). */
PW__DEF int pw_tetmesh_load(const pw_alloc *a, const char *path, pw_tetmesh *out, pw_err *e)
{
    unsigned char *d1 = NULL, *d2 = NULL;
    size_t n1 = 0, n2 = 0;
    char node[1024], ele[1024];
    int r;
    memset(out, 0, sizeof *out);
    if (pw_has_ext(path, ".mesh")) {
        if ((r = pw_read_file(a, path, &d1, &n1, e)) != PW_OK) return r;
        r = pw_medit_read_memory(a, d1, n1, path, out, e);
        pw_free(a, d1);
        return r;
    }
    if (!pw_has_ext(path, ".node") && !pw_has_ext(path, ".ele"))
        return pw_fail(e, PW_ERR_UNSUPPORTED, "%s: tetrahedral meshes are .node (with .ele) or .mesh files", path);
    if (!pw__tio_sibling(path, ".node", node, sizeof node) || !pw__tio_sibling(path, ".ele", ele, sizeof ele))
        return pw_fail(e, PW_ERR_INVALID, "%s: path too long", path);
    if ((r = pw_read_file(a, node, &d1, &n1, e)) == PW_OK && (r = pw_read_file(a, ele, &d2, &n2, e)) == PW_OK) {
        pw_memfile fn = pw_memfile_of(d1, n1, node), fe = pw_memfile_of(d2, n2, ele);
        r = pw_tetgen_read_memory(a, &fn, &fe, out, e);
    }
    pw_free(a, d1);
    pw_free(a, d2);
    return r;
}

PW__DEF int pw__tio_node_body(void *arg, pw_write_fn w, void *ctx, pw_err *e)
{
    return pw_tetgen_write_node((const pw_tetmesh *)arg, w, ctx, e);
}
PW__DEF int pw__tio_ele_body(void *arg, pw_write_fn w, void *ctx, pw_err *e)
{
    return pw_tetgen_write_ele((const pw_tetmesh *)arg, w, ctx, e);
}
PW__DEF int pw__tio_medit_body(void *arg, pw_write_fn w, void *ctx, pw_err *e)
{
    return pw_medit_write((const pw_tetmesh *)arg, w, ctx, e);
}

/* Writes FILE.mesh, or FILE.node and FILE.ele (path ending in .node or .ele). */
PW__DEF int pw_tetmesh_save(const char *path, const pw_tetmesh *m, pw_err *e)
{
    char node[1024], ele[1024];
    int r;
    if (pw_has_ext(path, ".mesh")) return pw_write_file(path, pw__tio_medit_body, (void *)m, e);
    if (!pw_has_ext(path, ".node") && !pw_has_ext(path, ".ele"))
        return pw_fail(e, PW_ERR_UNSUPPORTED, "%s: tetrahedral meshes are written as .node/.ele or .mesh", path);
    if (!pw__tio_sibling(path, ".node", node, sizeof node) || !pw__tio_sibling(path, ".ele", ele, sizeof ele))
        return pw_fail(e, PW_ERR_INVALID, "%s: path too long", path);
    if ((r = pw_write_file(node, pw__tio_node_body, (void *)m, e)) != PW_OK) return r;
    return pw_write_file(ele, pw__tio_ele_body, (void *)m, e);
}
#endif

#endif /* PW__TETIO_V1 */
