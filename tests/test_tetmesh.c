/* Tests of src/common/tetmesh.h: orientation, face order and dihedral
 * angles on tetrahedra whose angles are known in closed form. */
#include "../src/common/tetmesh.h"
#include "pwtest.h"

/* The regular tetrahedron: every dihedral angle is acos(1/3) = 70.5288 deg. */
static const float regular_pos[12] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
/* The corner of a unit cube: three right angles at the origin edges, the
 * others acos(1/sqrt(3)) = 54.7356 deg. */
static const float corner_pos[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};

static pw_tetmesh one_tet(const float *pos, int *tet)
{
    pw_tetmesh m;
    m.nv = 4;
    m.pos = (float *)pos;
    m.nt = 1;
    m.tet = tet;
    return m;
}

static void t_volume_sign(void)
{
    int tet[4] = {0, 1, 2, 3}, flipped[4] = {1, 0, 2, 3};
    pw_tetmesh m = one_tet(corner_pos, tet);
    CHECK(fabs(pw_tet_volume6(&m, 0) - 1.0) < 1e-12);
    m.tet = flipped;
    CHECK(fabs(pw_tet_volume6(&m, 0) + 1.0) < 1e-12);
}

/* Each face's normal (by the right-hand rule) points away from the
 * opposite corner. */
static void t_face_outward(void)
{
    int tet[4] = {0, 1, 2, 3}, k, f[3];
    for (k = 0; k < 4; k++) {
        const float *a, *b, *c, *o = corner_pos + 3 * tet[k];
        double u[3], v[3], n[3], w[3];
        int i;
        pw_tet_face(k, f);
        CHECK(f[0] != k && f[1] != k && f[2] != k);
        a = corner_pos + 3 * tet[f[0]];
        b = corner_pos + 3 * tet[f[1]];
        c = corner_pos + 3 * tet[f[2]];
        for (i = 0; i < 3; i++) {
            u[i] = b[i] - a[i];
            v[i] = c[i] - a[i];
            w[i] = o[i] - a[i];
        }
        n[0] = u[1] * v[2] - u[2] * v[1];
        n[1] = u[2] * v[0] - u[0] * v[2];
        n[2] = u[0] * v[1] - u[1] * v[0];
        CHECKF(n[0] * w[0] + n[1] * w[1] + n[2] * w[2] < 0, "face %d points inward", k);
    }
}

static void t_dihedral_known(void)
{
    int tet[4] = {0, 1, 2, 3};
    double lo, hi;
    pw_tetmesh m = one_tet(regular_pos, tet);
    pw_tet_dihedral_range(&m, &lo, &hi);
    CHECKF(fabs(lo - 70.528779) < 1e-4 && fabs(hi - 70.528779) < 1e-4, "regular: %g %g", lo, hi);
    m = one_tet(corner_pos, tet);
    pw_tet_dihedral_range(&m, &lo, &hi);
    CHECKF(fabs(lo - 54.735610) < 1e-4 && fabs(hi - 90.0) < 1e-4, "corner: %g %g", lo, hi);
    m.nt = 0;
    pw_tet_dihedral_range(&m, &lo, &hi);
    CHECK(lo == 0.0 && hi == 0.0);
}

/* A flat tetrahedron has a zero angle: the range must say so. */
static void t_dihedral_flat(void)
{
    static const float flat[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
    int tet[4] = {0, 1, 2, 3};
    double lo, hi;
    pw_tetmesh m = one_tet(flat, tet);
    pw_tet_dihedral_range(&m, &lo, &hi);
    CHECKF(lo < 1e-6, "flat tetrahedron: min %g", lo);
}

static const pwt_case cases[] = {
    {"tetmesh/volume_sign", t_volume_sign},
    {"tetmesh/face_outward", t_face_outward},
    {"tetmesh/dihedral_known", t_dihedral_known},
    {"tetmesh/dihedral_flat", t_dihedral_flat},
};
PWT_MAIN(cases)
