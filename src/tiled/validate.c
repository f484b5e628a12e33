/* validate.c: checks a hand-made tiled texture (the thesis's Figs. 39,
 * 40 were partly drawn by hand): against ch. III.1, every tile side must
 * continue into every side it can meet on a mesh. */
#include "layout.c"

static float tiled__dist(const float *p, const float *q, int c)
{
    float s = 0.0f;
    int k;
    for (k = 0; k < c; k++) s += (p[k] - q[k]) * (p[k] - q[k]);
    return sqrtf(s);
}

/* Mean colour jump between horizontally and vertically neighbouring
 * pixels inside tiles: what a seam should not exceed. */
static float tiled__interior_jump(const pw_image *img, const tiled__geom *gm)
{
    double sum = 0.0;
    long count = 0;
    int t, i, j;
    for (t = 0; t < gm->N * gm->N; t++)
        for (j = 0; j + 1 < gm->T; j++)
            for (i = 0; i + 1 < gm->T; i++) {
                const float *p = tiled__plain_px(img, gm, t, i, j);
                sum += tiled__dist(p, tiled__plain_px(img, gm, t, i + 1, j), img->c);
                sum += tiled__dist(p, tiled__plain_px(img, gm, t, i, j + 1), img->c);
                count += 2;
            }
    return count ? (float)(sum / (double)count) : 0.0f;
}

/* One side of one tile: side (0..3, tiled__from_side's order) of tile. */
typedef struct tiled__side {
    int tile, side;
} tiled__side;

/* Mean jump across side `here` when it meets side `there` of another tile
 * (reversed walk; `mirrored` compares the partner walked the same way, as
 * happens when case-1 tiles are mirrored). */
static float tiled__seam(const pw_image *img, const tiled__geom *gm, tiled__side here, tiled__side there, int mirrored)
{
    int t = here.tile, s = here.side, pt = there.tile, ps = there.side;
    double sum = 0.0;
    int a, T = gm->T;
    for (a = 0; a < T; a++) {
        int i, j, pi, pj;
        tiled__from_side(s, T, a, 0, &i, &j);
        tiled__from_side(ps, T, mirrored ? a : T - 1 - a, 0, &pi, &pj);
        sum += tiled__dist(tiled__plain_px(img, gm, t, i, j), tiled__plain_px(img, gm, pt, pi, pj), img->c);
    }
    return (float)(sum / T);
}

/* Mean seam of side (t, s) against up to 64 sides of the partner type. */
static float tiled__side_seam(const pw_image *img, const tiled__geom *gm, int case1, int mirror, tiled__side here,
                              int type)
{
    tiled__side there;
    int u, us, types[4], n = 0;
    double sum = 0.0;
    for (u = 0; u < gm->N * gm->N && n < 64; u++) {
        tiled__tile_types(gm, case1, u, types);
        for (us = 0; us < 4 && n < 64; us++) {
            if (types[us] != tiled__partner(case1, type)) continue;
            there.tile = u;
            there.side = us;
            sum += tiled__seam(img, gm, here, there, 0);
            n++;
            if (mirror) {
                sum += tiled__seam(img, gm, here, there, 1);
                n++;
            }
        }
    }
    return n ? (float)(sum / n) : 0.0f;
}

/* Records a failing side, keeping the list sorted worst first. */
static void tiled__note_bad(tiled_validation *rep, int t, int s, int type, float seam)
{
    int k, n = rep->nbad < TILED_MAX_MISMATCHES ? rep->nbad : TILED_MAX_MISMATCHES;
    rep->nbad++;
    if (n == TILED_MAX_MISMATCHES && seam <= rep->bad[n - 1].seam) return;
    if (n == TILED_MAX_MISMATCHES) n--;
    for (k = n; k > 0 && rep->bad[k - 1].seam < seam; k--) rep->bad[k] = rep->bad[k - 1];
    rep->bad[k].tile = t;
    rep->bad[k].side = s;
    rep->bad[k].type = type;
    rep->bad[k].seam = seam;
}

/* A side passes when its seam is at most twice the typical jump between
 * neighbouring pixels inside tiles (plus one 8-bit step): matching sides
 * continue the pattern, so their seams look like interior neighbours. */
TILEDDEF tiled_result tiled_validate_tiles(const tiled_image *tiles, const tiled_options *opt, tiled_validation *report,
                                           tiled_error *err)
{
    tiled_options o = tiled__options(opt);
    tiled_layout l;
    pw_err pe;
    pw_err_clear(&pe);
    if (report) memset(report, 0, sizeof *report);
    if (!report) pw_fail(&pe, PW_ERR_INVALID, "tiled_validate_tiles: NULL report");
    else if (tiled__layout_of_image(&o.layout, tiles, &l, &pe) == PW_OK) {
        pw_image img = tiled__pw_image(tiles);
        tiled__geom gm = tiled__geometry(&l);
        int case1 = l.case_number == 1, t, s, types[4];
        gm.g = 0;
        gm.C = gm.T;
        report->interior = tiled__interior_jump(&img, &gm);
        report->threshold = 2.0f * report->interior + 1.0f / 255.0f;
        for (t = 0; t < gm.N * gm.N; t++) {
            tiled__tile_types(&gm, case1, t, types);
            for (s = 0; s < 4; s++) {
                tiled__side here;
                float seam;
                here.tile = t;
                here.side = s;
                seam = tiled__side_seam(&img, &gm, case1, case1 && !o.no_mirror, here, types[s]);
                report->sides_checked++;
                if (seam > report->worst) report->worst = seam;
                if (seam > report->threshold) tiled__note_bad(report, t, s, types[s], seam);
            }
        }
    }
    return tiled__done(&pe, err);
}
