/* The cross (spider) of the Cardan joint: a cube with four cylindrical arms (models.h). */
#include <math.h>

#include "models/cardan_internal.h"

cb_status cb_cardan_build_cross(cb_topo_body **out, const cb_cardan_params *p, cb_error *err)
{
    const double a = p->cross.half_size, r = p->cross.arm_radius, L = p->cross.arm_reach;
    cb_build bd;
    cb_status st = cb_build_start(&bd, p, 2 * L, err);
    if (st)
        return st;
    /* Cube vertex k has coordinate i at +a when bit i of k is set; e[lo][hi] joins k = lo, hi. */
    int v[8], e[8][8] = {{0}};
    for (int k = 0; k < 8; k++) {
        const double q[3] = {k & 1 ? a : -a, k & 2 ? a : -a, k & 4 ? a : -a};
        v[k] = cb_build_vertex(&bd, q);
    }
    for (int k = 0; k < 8; k++)
        for (int i = 0; i < 3; i++)
            if (!(k & 1 << i))
                e[k][k | 1 << i] = bd.st ? 0 : cb_build_line(&bd, v[k], v[k | 1 << i]);
    /* Arm m leaves the cube face of axis m / 2 (x or y) on side m % 2 (+ for 1). Its seam lies
     * on its left side seen from +z (direction z x d), off the top and bottom lines where
     * the scenarios put tangent contacts. */
    cb_build_tube arm[4];
    for (int m = 0; m < 4; m++) {
        double o[3] = {0, 0, 0}, d[3] = {0, 0, 0}, left[3];
        d[m / 2] = m % 2 ? 1 : -1;
        o[m / 2] = a * d[m / 2];
        left[0] = -d[1];
        left[1] = d[0];
        left[2] = 0;
        cb_build_tube_edges(&bd, &arm[m], o, d, left, r, L - a);
    }
    for (int i = 0; i < 3; i++)
        for (int side = 0; side < 2; side++) {
            /* In-plane axes u, w with e_u x e_w the outward normal; corners counter-clockwise
             * about it. */
            int u = (i + 1) % 3, w = (i + 2) % 3;
            if (!side) {
                int tmp = u;
                u = w;
                w = tmp;
            }
            const int base = side << i;
            const int corner[4] = {base, base | 1 << u, base | 1 << u | 1 << w, base | 1 << w};
            double o[3] = {0, 0, 0}, n[3] = {0, 0, 0}, x[3] = {0, 0, 0}, pts[4][3];
            o[i] = side ? a : -a;
            n[i] = side ? 1 : -1;
            x[u] = 1;
            int es[4][2];
            for (int k = 0; k < 4; k++) {
                int c0 = corner[k], c1 = corner[(k + 1) % 4];
                int lo = c0 < c1 ? c0 : c1, hi = c0 < c1 ? c1 : c0;
                es[k][0] = e[lo][hi];
                es[k][1] = c0 == lo;
                for (int j = 0; j < 3; j++)
                    pts[k][j] = c0 & 1 << j ? a : -a;
            }
            cb_build_polygon_face(&bd, o, n, x, 4, (const double(*)[3])pts);
            cb_build_loop(&bd, 4, (const int(*)[2])es);
            if (i < 2) {
                /* The arm's circle, clockwise about the face normal: a hole. */
                const int hole[1][2] = {{arm[2 * i + side].c0, 0}};
                cb_build_loop(&bd, 1, hole);
            }
        }
    for (int m = 0; m < 4; m++) {
        cb_build_tube_face(&bd, &arm[m], 1);
        cb_build_cap_face(&bd, &arm[m]);
    }
    return cb_build_finish(out, &bd, "cross");
}
