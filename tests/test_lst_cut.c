/* Tests of lst.h's views (§5.1): cuts split the mesh into a valid,
 * conforming mesh that keeps the right volume and allows further cuts
 * (§5.1.1); cross-sections agree with direct evaluation of the pasted
 * texture at the same points, in the split mesh and in the rendered image;
 * stroke fields cut along the stroke; volume rendering (§5.1.2); surface
 * rendering, displacement and the other views; determinism of images. */
#define LST_STATIC /* static: only what the tests call is compiled */
#define LST_IMPLEMENTATION
#include "../lst.h"
#include "pwtest.h"

/* lst_create with the exemplar and its extra channel (may be NULL) as arguments. */
static lst_result create_model(const lst_tetmesh *m, const lst_mesh *s, const lst_volume *ex, const lst_volume *val,
                               const lst_options *o, lst_model *out, lst_error *err)
{
    lst_source src;
    src.exemplar = ex, src.values = val;
    return lst_create(m, s, &src, o, out, err);
}

static int make_model(const char *surface, int type, const char *exemplar, int n, lst_model *model)
{
    lst_options o = lst_default_options();
    lst_mesh s;
    lst_tetmesh m;
    lst_volume ex, val;
    lst_error err;
    int ok;
    o.tet.target_tets = n, o.tet.uniform = 1; /* a small uniform fill: stuffing tests cover the graded one */
    o.type = type;
    if (lst_builtin_mesh(surface, &o, &s, &err) || lst_tetrahedralize(&s, &o, &m, NULL, &err)) return 0;
    if (lst_builtin_exemplar(exemplar, 32, &o, &ex, &val, &err)) return 0;
    ok = create_model(&m, &s, &ex, &val, &o, model, &err) == LST_OK;
    lst_volume_free(&ex), lst_volume_free(&val), lst_tetmesh_free(&m), lst_mesh_free(&s);
    return ok;
}

/* A deep copy of a model's mesh and pastes (textures shared by pointer:
 * the copy is only evaluated, and freed with free_copy). */
static int copy_model(const lst_model *a, lst_model *b)
{
    int p;
    *b = *a;
    b->mesh.positions = (float *)malloc(sizeof(float) * 3 * (size_t)a->mesh.nverts);
    b->mesh.tets = (int *)malloc(sizeof(int) * 4 * (size_t)a->mesh.ntets);
    b->removed = (unsigned char *)malloc((size_t)a->mesh.ntets);
    b->pastes = (lst_paste *)malloc(sizeof(lst_paste) * (size_t)a->npastes);
    memcpy(b->mesh.positions, a->mesh.positions, sizeof(float) * 3 * (size_t)a->mesh.nverts);
    memcpy(b->mesh.tets, a->mesh.tets, sizeof(int) * 4 * (size_t)a->mesh.ntets);
    memcpy(b->removed, a->removed, (size_t)a->mesh.ntets);
    for (p = 0; p < a->npastes; p++) {
        const lst_paste *q = &a->pastes[p];
        lst_paste *r = &b->pastes[p];
        *r = *q;
        r->tets = (int *)malloc(sizeof(int) * (size_t)q->ntets);
        r->corners = (int *)malloc(sizeof(int) * 4 * (size_t)q->ntets);
        r->verts = (int *)malloc(sizeof(int) * (size_t)q->nverts);
        r->uvw = (float *)malloc(sizeof(float) * 3 * (size_t)q->nverts);
        memcpy(r->tets, q->tets, sizeof(int) * (size_t)q->ntets);
        memcpy(r->corners, q->corners, sizeof(int) * 4 * (size_t)q->ntets);
        memcpy(r->verts, q->verts, sizeof(int) * (size_t)q->nverts);
        memcpy(r->uvw, q->uvw, sizeof(float) * 3 * (size_t)q->nverts);
    }
    return 1;
}

static void free_copy(lst_model *b)
{
    int p;
    for (p = 0; p < b->npastes; p++) free(b->pastes[p].tets), free(b->pastes[p].corners), free(b->pastes[p].verts), free(b->pastes[p].uvw);
    free(b->pastes), free(b->mesh.positions), free(b->mesh.tets), free(b->removed);
}

static double volume_kept(const lst_model *m)
{
    pw_tetmesh tm = lst__pw_tets(&m->mesh);
    double v = 0.0;
    int t;
    for (t = 0; t < tm.nt; t++)
        if (!m->removed[t]) v += pw_tet_volume6(&tm, t) / 6.0;
    return v;
}

/* The split mesh is valid and conforming; volumes add up; the kept part
 * lies on the kept side; a second cut works on the refined mesh. */
static void t_cut_mesh(void)
{
    lst_model m;
    lst_error err;
    pw_err e;
    pw_tetmesh tm;
    int *nb, t, k, wrong = 0;
    float plane[4] = {0.3f, 1.0f, 0.2f, 0.15f}, plane2[4] = {1, 0, 0, -0.2f};
    double v0, v1, vall;
    REQUIRE(make_model("sphere", LST_TYPE_0, "spots", 2500, &m));
    v0 = volume_kept(&m);
    REQUIRE(lst_cut_plane(&m, plane, &err) == LST_OK);
    tm = lst__pw_tets(&m.mesh);
    pw_err_clear(&e);
    CHECK(pw_tetmesh_check(&tm, "cut", &e) == PW_OK);
    nb = (int *)malloc(sizeof(int) * 4 * (size_t)tm.nt);
    CHECKF(pw_tetmesh_neighbors(NULL, &tm, nb, &e) == PW_OK, "%s", e.msg);
    free(nb);
    v1 = volume_kept(&m);
    lst_uncut(&m);
    vall = volume_kept(&m);
    CHECK_NEAR(vall, v0, 1e-4 * v0);
    CHECK(v1 > 0.2 * v0 && v1 < 0.8 * v0);
    REQUIRE(lst_cut_plane(&m, plane, &err) == LST_OK);
    for (t = 0; t < m.mesh.ntets; t++)
        if (!m.removed[t])
            for (k = 0; k < 4; k++) {
                const float *p = m.mesh.positions + 3 * m.mesh.tets[4 * t + k];
                wrong += plane[0] * p[0] + plane[1] * p[1] + plane[2] * p[2] - plane[3] > 1e-4f;
            }
    CHECK_EQ_INT(wrong, 0);
    REQUIRE(lst_cut_plane(&m, plane2, &err) == LST_OK);
    tm = lst__pw_tets(&m.mesh);
    nb = (int *)malloc(sizeof(int) * 4 * (size_t)tm.nt);
    CHECK(pw_tetmesh_neighbors(NULL, &tm, nb, &e) == PW_OK);
    free(nb);
    CHECK(volume_kept(&m) < v1);
    pwt_info("two cuts: %d tetrahedra, kept volume %.4f of %.4f", m.mesh.ntets, volume_kept(&m), v0);
    lst_model_free(&m);
}

/* §5.1.1 "the texture coordinates for each triangle on the cross-section
 * are obtained by linearly interpolating the texture coordinates of the
 * original tetrahedron": points of the cut faces evaluated in the split
 * mesh equal the uncut model evaluated at the same points. */
static void t_section_matches_eval(void)
{
    lst_model m, orig;
    lst_error err;
    pw_alloc a;
    lst__view v;
    pw_err e;
    pw_tetmesh tm;
    int *nb, f, k, n = 0;
    float plane[4] = {0.2f, -0.4f, 1.0f, 0.1f};
    double worst = 0.0;
    memset(&a, 0, sizeof a);
    pw_err_clear(&e);
    REQUIRE(make_model("kiwi", LST_TYPE_2B, "kiwi", 3000, &m));
    REQUIRE(copy_model(&m, &orig));
    REQUIRE(lst_cut_plane(&m, plane, &err) == LST_OK);
    tm = lst__pw_tets(&m.mesh);
    nb = (int *)malloc(sizeof(int) * 4 * (size_t)tm.nt);
    REQUIRE(pw_tetmesh_neighbors(NULL, &tm, nb, &e) == PW_OK);
    REQUIRE(lst__view_init(&a, &m, LST_SHOW_COLOR, &v, &e) == PW_OK);
    for (f = 0; f < 4 * tm.nt; f++) {
        double l[4] = {0.2, 0.3, 0.5, 0.0}, tmp;
        float p[3] = {0, 0, 0}, c1[4], c2[4];
        int t = f >> 2, kk = f & 3, j;
        if (m.removed[t] || nb[f] < 0 || !m.removed[nb[f] >> 2]) continue; /* a face the cut opened */
        tmp = l[kk], l[kk] = l[3], l[3] = tmp; /* zero at the opposite corner */
        for (k = 0; k < 4; k++)
            for (j = 0; j < 3; j++) p[j] += (float)l[k] * m.mesh.positions[3 * m.mesh.tets[4 * t + k] + j];
        lst__eval(&v, t, l, c1, NULL);
        REQUIRE(lst_eval(&orig, p, 1, c2, NULL, &err) == LST_OK);
        for (k = 0; k < 4; k++) worst = fabs(c1[k] - c2[k]) > worst ? fabs(c1[k] - c2[k]) : worst;
        n++;
    }
    pwt_info("%d cut faces: largest difference from direct evaluation %.2g", n, worst);
    CHECK(n > 50);
    CHECK(worst < 2e-3);
    lst__view_free(&v);
    free(nb);
    free_copy(&orig);
    lst_model_free(&m);
}

/* The same in the rendered section: the cut seen face on, unlit; pixels
 * whose centre projects inside the cut are compared with direct
 * evaluation at the point of the plane behind them. */
static void t_section_image(void)
{
    lst_model m, orig;
    lst_render_options ro;
    lst_image img;
    lst_error err;
    pw_camera cam;
    float plane[4] = {0, 0, 1, 0.05f}, *pos;
    double sum = 0.0;
    int x, y, n = 0, nv, big = 0;
    pw_err e;
    REQUIRE(make_model("kiwi", LST_TYPE_2B, "kiwi", 3000, &m));
    REQUIRE(copy_model(&m, &orig));
    REQUIRE(lst_cut_plane(&m, plane, &err) == LST_OK);
    memset(&ro, 0, sizeof ro);
    ro.width = 200, ro.height = 160, ro.supersample = 1, ro.unlit = 1;
    ro.view_dir[2] = -1, ro.up[1] = 1;
    REQUIRE(lst_render(&m, &ro, &img, &err) == LST_OK);
    pw_err_clear(&e);
    REQUIRE(lst__visible_positions(NULL, &m, &pos, &nv, &e) == PW_OK);
    cam = pw_camera_frame(pos, nv, ro.view_dir, ro.up, 35.0f, 200.0f / 160.0f);
    free(pos);
    for (y = 4; y < 160; y += 7)
        for (x = 4; x < 200; x += 7) { /* the ray through the pixel centre meets z = 0.05 */
            double d[3], t;
            float p[3], rgba[4], q[3];
            int k;
            pw__view vw;
            if (!pw__view_init(&vw, &cam, 200, 160, &e)) {
                for (k = 0; k < 3; k++)
                    d[k] = vw.f[k] + ((x + 0.5 - vw.cx) / vw.fx) * vw.r[k] - ((y + 0.5 - vw.cy) / vw.fy) * vw.u[k];
                t = (0.05 - vw.eye[2]) / d[2];
                for (k = 0; k < 3; k++) p[k] = (float)(vw.eye[k] + t * d[k]);
            }
            REQUIRE(lst_eval(&orig, p, 1, rgba, NULL, &err) == LST_OK);
            if (rgba[3] < 0.5f || !pw_camera_project(&cam, 200, 160, p, q)) continue;
            {
                const float *px = img.pixels + 3 * ((size_t)y * 200 + x);
                double dd = fabs(px[0] - rgba[0]) + fabs(px[1] - rgba[1]) + fabs(px[2] - rgba[2]);
                sum += dd, n++, big += dd > 0.15;
            }
        }
    pwt_info("%d pixels of the section: mean colour difference from direct evaluation %.4f, %d above 0.15", n,
             n ? sum / n : 0.0, big);
    CHECK(n > 100);
    CHECK(sum / n < 0.03);
    CHECK(big * 20 < n);
    lst_image_free(&img);
    free_copy(&orig);
    lst_model_free(&m);
}

/* A stroke seen along z cuts like the plane through it: straight stroke
 * along y at x = 0.1; vertices right of it (view x tangent: -z x +y = +x)
 * are positive. */
static void t_stroke_cut(void)
{
    lst_model m;
    lst_error err;
    float stroke[12] = {0.1f, -0.6f, 0.0f, 0.1f, -0.2f, 0.0f, 0.1f, 0.2f, 0.0f, 0.1f, 0.6f, 0.0f}, view[3] = {0, 0, -1};
    float *phi;
    int v, wrong = 0, t, k;
    REQUIRE(make_model("sphere", LST_TYPE_0, "spots", 2000, &m));
    phi = (float *)malloc(sizeof(float) * (size_t)m.mesh.nverts);
    REQUIRE(lst_stroke_field(&m, stroke, 4, view, phi, &err) == LST_OK);
    for (v = 0; v < m.mesh.nverts; v++) {
        float x = m.mesh.positions[3 * v];
        if (fabsf(x - 0.1f) > 0.1f) wrong += (phi[v] > 0) != (x > 0.1f);
    }
    CHECK_EQ_INT(wrong, 0);
    REQUIRE(lst_cut_field(&m, phi, &err) == LST_OK);
    for (t = 0; t < m.mesh.ntets; t++)
        if (!m.removed[t])
            for (k = 0; k < 4; k++) wrong += m.mesh.positions[3 * m.mesh.tets[4 * t + k]] > 0.15f;
    CHECK_EQ_INT(wrong, 0);
    CHECK(lst_stroke_field(&m, stroke, 1, view, phi, &err) == LST_ERR_INVALID);
    free(phi);
    lst_model_free(&m);
}

/* A cut whose plane misses the model changes nothing; one that takes
 * everything leaves nothing to render (a clear error). */
static void t_cut_extremes(void)
{
    lst_model m;
    lst_error err;
    lst_image img;
    float miss[4] = {1, 0, 0, 5}, all[4] = {1, 0, 0, -5}, zero[4] = {0, 0, 0, 1}, nan4[4] = {NAN, 0, 0, 0};
    int nt;
    REQUIRE(make_model("sphere", LST_TYPE_0, "spots", 1500, &m));
    nt = m.mesh.ntets;
    REQUIRE(lst_cut_plane(&m, miss, &err) == LST_OK);
    CHECK_EQ_INT(m.mesh.ntets, nt);
    REQUIRE(lst_cut_plane(&m, all, &err) == LST_OK);
    CHECK(lst_render(&m, NULL, &img, &err) == LST_ERR_DEGENERATE && strstr(err.message, "cut away"));
    CHECK(lst_cut_plane(&m, zero, &err) == LST_ERR_INVALID);
    CHECK(lst_cut_plane(&m, nan4, &err) == LST_ERR_INVALID);
    lst_uncut(&m);
    REQUIRE(lst_render(&m, NULL, &img, &err) == LST_OK);
    lst_image_free(&img);
    lst_model_free(&m);
}

/* Surface rendering: the model fills the middle of the image, the
 * background the corners; the same call twice gives the same pixels; the
 * other views render. */
static void t_render(void)
{
    lst_model m;
    lst_render_options ro;
    lst_image a, b;
    lst_error err;
    size_t n;
    int show;
    REQUIRE(make_model("tree", LST_TYPE_2B, "rings", 2500, &m));
    memset(&ro, 0, sizeof ro);
    ro.width = 160, ro.height = 120;
    REQUIRE(lst_render(&m, &ro, &a, &err) == LST_OK);
    REQUIRE(lst_render(&m, &ro, &b, &err) == LST_OK);
    n = (size_t)a.width * a.height * 3;
    CHECK(!memcmp(a.pixels, b.pixels, n * sizeof(float)));
    CHECK(a.pixels[0] == 1.0f && a.pixels[1] == 1.0f); /* background corner */
    {
        const float *c = a.pixels + 3 * (60 * 160 + 80);
        CHECK(c[0] < 0.9f || c[1] < 0.9f || c[2] < 0.9f);
    }
    lst_image_free(&b);
    for (show = LST_SHOW_VALUES; show <= LST_SHOW_DEPTH; show++) {
        ro.show = show;
        REQUIRE(lst_render(&m, &ro, &b, &err) == LST_OK);
        CHECK(memcmp(a.pixels, b.pixels, n * sizeof(float)) != 0);
        lst_image_free(&b);
    }
    ro.show = LST_SHOW_COLOR, ro.displace = 0.05f, ro.subdivide = 1;
    REQUIRE(lst_render(&m, &ro, &b, &err) == LST_OK);
    CHECK(memcmp(a.pixels, b.pixels, n * sizeof(float)) != 0);
    lst_image_free(&b);
    ro.show = 7;
    CHECK(lst_render(&m, &ro, &b, &err) == LST_ERR_INVALID);
    lst_image_free(&a);
    lst_model_free(&m);
}

/* §5.1.2: a translucent volume: the middle of the image is darker than
 * the background, lighter than the opaque surface rendering's darkest
 * parts would allow... and it changes with the opacity. */
static void t_volume(void)
{
    lst_model m;
    lst_render_options ro;
    lst_volume_options vo;
    lst_image a, b;
    lst_error err;
    const float *c;
    REQUIRE(make_model("kiwi", LST_TYPE_2B, "kiwi", 2000, &m));
    memset(&ro, 0, sizeof ro);
    memset(&vo, 0, sizeof vo);
    ro.width = 120, ro.height = 100, ro.supersample = 1;
    vo.slices = 60;
    REQUIRE(lst_render_volume(&m, &ro, &vo, &a, &err) == LST_OK);
    c = a.pixels + 3 * (50 * 120 + 60);
    CHECK(a.pixels[0] == 1.0f);
    CHECK(c[0] + c[1] + c[2] < 2.9f);
    vo.opacity = 0.05f;
    REQUIRE(lst_render_volume(&m, &ro, &vo, &b, &err) == LST_OK);
    CHECK(b.pixels[3 * (50 * 120 + 60) + 1] > c[1]); /* more transparent: closer to white */
    lst_image_free(&b);
    vo.density = 1; /* the extra channel */
    REQUIRE(lst_render_volume(&m, &ro, &vo, &b, &err) == LST_OK);
    lst_image_free(&b);
    vo.density = 2;
    CHECK(lst_render_volume(&m, &ro, &vo, &b, &err) == LST_ERR_INVALID);
    vo.density = 0, vo.slices = -1;
    CHECK(lst_render_volume(&m, &ro, &vo, &b, &err) == LST_ERR_INVALID);
    lst_image_free(&a);
    lst_model_free(&m);
}

static const pwt_case cases[] = {
    {"cut_mesh", t_cut_mesh},
    {"section_matches_eval", t_section_matches_eval},
    {"section_image", t_section_image},
    {"stroke_cut", t_stroke_cut},
    {"cut_extremes", t_cut_extremes},
    {"render", t_render},
    {"volume", t_volume},
};
PWT_MAIN(cases)
