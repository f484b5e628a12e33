/* edit.c: the public editing calls of a mapping. §2.1 (Ray, Lévy, Wang,
 * Turk and Vallet 2009, "Material Space Texturing"): "When the user
 * specifies or edits a constraint, we compute an effect area around the
 * constraint ... by a classical greedy algorithm that visits the triangles
 * in order of increasing distance to the nearest constraint"; the
 * interpolations and the (s,t) solve are then limited to that area, with
 * everything on its boundary locked, so that an edit is local and
 * continuous. Every call here (a constraint added, edited or removed, the
 * constraints given to pgp_create) runs those steps (pgp__edit, solve.c)
 * around its constraint. */
#include "solve.c"

/* The triangles around a constraint: its triangle, or a vertex's fan. */
static int pgp__edit_constraint(pgp__state *P, const pgp_constraint *c, pgp_area *area, pw_err *e)
{
    int *seeds, n = 0, h, r;
    pgp__seeds sd;
    sd.tri = &c->element;
    sd.n = 1;
    sd.radius = c->radius;
    if (c->kind == PGP_CONSTRAINT_ORIENT) return pgp__edit(P, c->kind, &sd, area, e);
    seeds = (int *)pw_alloc_array(&P->a, (size_t)P->pp.m.nf, sizeof(int), "effect area", e);
    if (!seeds) return PW_ERR_NOMEM;
    for (h = 0; h < 3 * P->pp.m.nf; h++)
        if (P->pp.m.tri[h] == c->element) seeds[n++] = h / 3;
    sd.tri = seeds;
    sd.n = n;
    r = pgp__edit(P, c->kind, &sd, area, e);
    pw_free(&P->a, seeds);
    return r;
}

/* Checks a constraint against the map: pgp__check_values, an element that
 * exists, and a direction that is not normal to its triangle. */
static int pgp__check_constraint(const pgp__state *P, const pgp_constraint *c, pw_err *e)
{
    double z[2];
    int r = pgp__check_values(c, e);
    if (r == PW_OK)
        r = c->kind == PGP_CONSTRAINT_ORIENT ? pgp__check_face(P, c->element, e) : pgp__check_vertex(P, c->element, e);
    if (r == PW_OK && c->kind == PGP_CONSTRAINT_ORIENT && !pw_df_project(&P->pp.m, c->element, pw_v3_load(c->value), z))
        return pw_fail(e, PW_ERR_INVALID, "orientation (%g, %g, %g) at triangle %d is normal to the triangle",
                       (double)c->value[0], (double)c->value[1], (double)c->value[2], c->element);
    return r;
}

/* Adds a constraint and applies it; *id its index. */
static int pgp__add(pgp__state *P, const pgp_constraint *c, int *id, pgp_area *area, pw_err *e)
{
    pgp__constraint k;
    k.c = *c;
    k.alive = 1;
    if (pgp__check_constraint(P, &k.c, e) != PW_OK ||
        pw_grow(&P->a, (void **)&P->con, &P->concap, (size_t)P->ncon + 1, sizeof k, "constraints", e) != PW_OK)
        return e->code;
    P->con[P->ncon++] = k;
    if (pgp__edit_constraint(P, &k.c, area, e) != PW_OK) P->con[--P->ncon].alive = 0;
    else if (id) *id = P->ncon - 1;
    return e->code;
}

/* pgp_options.constraints, one by one, each as pgp_add_constraint. */
static int pgp__add_options(pgp__state *P, const pgp_options *o, pw_err *e)
{
    char msg[sizeof e->msg];
    int i, code;
    if (o->nconstraints < 0 || (o->nconstraints > 0 && !o->constraints))
        return pw_fail(e, PW_ERR_INVALID, "options: %d constraints and %s array", o->nconstraints,
                       o->constraints ? "an" : "no");
    for (i = 0; i < o->nconstraints; i++)
        if ((code = pgp__add(P, &o->constraints[i], NULL, NULL, e)) != PW_OK) { /* name it */
            memcpy(msg, e->msg, sizeof msg);
            pw_err_clear(e);
            return pw_fail(e, code, "constraint %d: %s", i, msg);
        }
    return PW_OK;
}

PGPDEF pgp_result pgp_create(const pgp_mesh *mesh, const pgp_options *opt, pgp_map *out, pgp_error *err)
{
    pw_err pe;
    pw_err_clear(&pe);
    if (out) memset(out, 0, sizeof *out);
    if (!out) pw_fail(&pe, PW_ERR_INVALID, "pgp_create: NULL output");
    else if (pgp__create_map(mesh, opt, out, &pe) != PW_OK || (opt && pgp__add_options(out->state, opt, &pe) != PW_OK))
        pgp_map_free(out);
    return pgp__done(&pe, err);
}

PGPDEF pgp_result pgp_add_constraint(pgp_map *map, const pgp_constraint *c, int *id, pgp_area *area, pgp_error *err)
{
    pw_err pe;
    pw_err_clear(&pe);
    if (area) memset(area, 0, sizeof *area);
    if (!map || !map->state || !c)
        pw_fail(&pe, PW_ERR_INVALID, "pgp_add_constraint: NULL or empty map, or NULL constraint");
    else pgp__add(map->state, c, id, area, &pe);
    return pgp__done(&pe, err);
}

/* The live constraint `id`, or an error. */
static pgp__constraint *pgp__find(pgp_map *map, int id, pw_err *e)
{
    pgp__state *P = map ? map->state : NULL;
    if (!P) {
        pw_fail(e, PW_ERR_INVALID, "NULL or empty map");
        return (pgp__constraint *)NULL;
    }
    if (id < 0 || id >= P->ncon || !P->con[id].alive) {
        pw_fail(e, PW_ERR_INVALID, "there is no constraint %d", id);
        return NULL;
    }
    return &P->con[id];
}

PGPDEF pgp_result pgp_edit_constraint(pgp_map *map, int id, const float value[3], pgp_area *area, pgp_error *err)
{
    pgp__constraint *c, old;
    pw_err pe;
    pw_err_clear(&pe);
    if (area) memset(area, 0, sizeof *area);
    if ((c = pgp__find(map, id, &pe)) != NULL && !value) pw_fail(&pe, PW_ERR_INVALID, "NULL value");
    if (pe.code == PW_OK) {
        old = *c;
        memcpy(c->c.value, value, sizeof(float) * (c->c.kind == PGP_CONSTRAINT_ORIENT ? 3 : 1));
        if (pgp__check_constraint(map->state, &c->c, &pe) != PW_OK ||
            pgp__edit_constraint(map->state, &c->c, area, &pe) != PW_OK)
            *c = old;
    }
    return pgp__done(&pe, err);
}

PGPDEF pgp_result pgp_remove_constraint(pgp_map *map, int id, pgp_area *area, pgp_error *err)
{
    pgp__constraint *c;
    pw_err pe;
    pw_err_clear(&pe);
    if (area) memset(area, 0, sizeof *area);
    if ((c = pgp__find(map, id, &pe)) != NULL) {
        c->alive = 0;
        if (pgp__edit_constraint(map->state, &c->c, area, &pe) != PW_OK) c->alive = 1;
    }
    return pgp__done(&pe, err);
}
