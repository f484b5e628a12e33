/* tetmesh: the tetrahedral mesh that lapped solid textures work on, and its
 * quality figures.
 *
 * A pw_tetmesh is nv vertices (pos, nv*3 floats) and nt tetrahedra (tet,
 * nt*4 vertex indices). Tetrahedra are positively oriented: with corners
 * a, b, c, d, (b - a) x (c - a) . (d - a) > 0, so the faces opposite each
 * corner, listed by pw_tet_face, have outward normals by the right-hand
 * rule. Readers and the built-in tetrahedralizer produce this orientation
 * (flipping tetrahedra given the other way round) and refuse degenerate
 * (zero-volume) tetrahedra.
 *
 *   pw_tetmesh_free, pw_tet_volume6, pw_tet_face, pw_tet_dihedral_range */
#ifndef PW__TETMESH_V1
#define PW__TETMESH_V1

#include "base.h"
#include "vec.h"

typedef struct pw_tetmesh {
    int nv;     /* vertices */
    float *pos; /* nv*3 */
    int nt;     /* tetrahedra */
    int *tet;   /* nt*4, positively oriented */
} pw_tetmesh;

PW__DEF void pw_tetmesh_free(const pw_alloc *a, pw_tetmesh *m)
{
    if (!m) return;
    pw_free(a, m->pos);
    pw_free(a, m->tet);
    memset(m, 0, sizeof *m);
}

/* Six times the signed volume of tetrahedron t (positive when oriented as
 * documented above), in double precision. */
PW__DEF double pw_tet_volume6(const pw_tetmesh *m, int t)
{
    const float *p0 = m->pos + 3 * m->tet[4 * t], *p1 = m->pos + 3 * m->tet[4 * t + 1];
    const float *p2 = m->pos + 3 * m->tet[4 * t + 2], *p3 = m->pos + 3 * m->tet[4 * t + 3];
    double ax = (double)p1[0] - p0[0], ay = (double)p1[1] - p0[1], az = (double)p1[2] - p0[2];
    double bx = (double)p2[0] - p0[0], by = (double)p2[1] - p0[1], bz = (double)p2[2] - p0[2];
    double cx = (double)p3[0] - p0[0], cy = (double)p3[1] - p0[1], cz = (double)p3[2] - p0[2];
    return ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
}

/* The three corners (as indices 0..3 into the tetrahedron) of the face
 * opposite corner k, ordered so that its normal points out of the
 * tetrahedron. */
PW__DEF void pw_tet_face(int k, int out[3])
{
    static const int face[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    out[0] = face[k][0];
    out[1] = face[k][1];
    out[2] = face[k][2];
}

/* The smallest and largest dihedral angle, in degrees, over all
 * tetrahedra (the quality figures the lst paper and TetGen report). An
 * empty mesh gives 0 and 0. Uses acos from libm: this is a report, not a
 * result that has to be bit-identical across platforms. */
PW__DEF void pw_tet_dihedral_range(const pw_tetmesh *m, double *min_deg, double *max_deg)
{
    static const int edge[6][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2},
                                   {1, 2, 0, 3}, {1, 3, 0, 2}, {2, 3, 0, 1}};
    double lo = 180.0, hi = 0.0;
    int t, k;
    for (t = 0; t < m->nt; t++) {
        for (k = 0; k < 6; k++) {
            /* the angle along edge (a,b) between the faces (a,b,c) and (a,b,d) */
            const float *a = m->pos + 3 * m->tet[4 * t + edge[k][0]];
            const float *b = m->pos + 3 * m->tet[4 * t + edge[k][1]];
            const float *c = m->pos + 3 * m->tet[4 * t + edge[k][2]];
            const float *d = m->pos + 3 * m->tet[4 * t + edge[k][3]];
            double u[3], v[3], w[3], n1[3], n2[3], l1, l2, cosang, ang;
            int i;
            for (i = 0; i < 3; i++) {
                u[i] = (double)b[i] - a[i];
                v[i] = (double)c[i] - a[i];
                w[i] = (double)d[i] - a[i];
            }
            n1[0] = u[1] * v[2] - u[2] * v[1];
            n1[1] = u[2] * v[0] - u[0] * v[2];
            n1[2] = u[0] * v[1] - u[1] * v[0];
            n2[0] = u[1] * w[2] - u[2] * w[1];
            n2[1] = u[2] * w[0] - u[0] * w[2];
            n2[2] = u[0] * w[1] - u[1] * w[0];
            l1 = sqrt(n1[0] * n1[0] + n1[1] * n1[1] + n1[2] * n1[2]);
            l2 = sqrt(n2[0] * n2[0] + n2[1] * n2[1] + n2[2] * n2[2]);
            if (l1 <= 0.0 || l2 <= 0.0) {
                lo = 0.0;
                continue;
            }
            cosang = (n1[0] * n2[0] + n1[1] * n2[1] + n1[2] * n2[2]) / (l1 * l2);
            if (cosang > 1.0) cosang = 1.0;
            if (cosang < -1.0) cosang = -1.0;
            ang = acos(cosang) * (180.0 / 3.14159265358979323846);
            if (ang < lo) lo = ang;
            if (ang > hi) hi = ang;
        }
    }
    if (m->nt == 0) lo = hi = 0.0;
    *min_deg = lo;
    *max_deg = hi;
}

#endif /* PW__TETMESH_V1 */
