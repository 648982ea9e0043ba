/* mesh_shapes.c — meshes of simple solids (see mesh_shapes.h). */
#include "brep/mesh_shapes.h"

#include <limits.h>
#include <math.h>

static double orient3(const double *a, const double *b, const double *c, const double *d)
{
    double u[3], v[3], w[3];
    for (int k = 0; k < 3; k++) {
        u[k] = b[k] - a[k];
        v[k] = c[k] - a[k];
        w[k] = d[k] - a[k];
    }
    return u[0] * (v[1] * w[2] - v[2] * w[1]) + u[1] * (v[2] * w[0] - v[0] * w[2]) +
           u[2] * (v[0] * w[1] - v[1] * w[0]);
}

/* Appends the vertices of pts then the triangles, cleaning m first and again on failure. */
static cb_status build(cb_mesh_t m, const double (*pts)[3], int nv, const int (*tri)[3], int nt,
                       cb_error *err)
{
    cb_mesh_clear(m);
    cb_status st = cb_mesh_reserve(m, nv, nt, err);
    for (int v = 0; !st && v < nv; v++)
        st = cb_mesh_append_vertex(m, pts[v], err);
    for (int f = 0; !st && f < nt; f++)
        st = cb_mesh_append_triangle(m, tri[f][0], tri[f][1], tri[f][2], err);
    if (st)
        cb_mesh_clear(m);
    return st;
}

cb_status cb_mesh_tetrahedron(cb_mesh_t m, const double p[4][3], cb_error *err)
{
    double o = orient3(p[0], p[1], p[2], p[3]);
    if (!(o != 0) || !isfinite(o)) {
        cb_mesh_clear(m);
        return cb_error_set(err, CB_ERR_INVALID, "tetrahedron: the four points are coplanar");
    }
    /* With p3 on the positive side of (p0, p1, p2), that face points away from it when
     * wound p0, p2, p1; the other faces follow. */
    static const int pos[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    static const int neg[4][3] = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
    return build(m, p, 4, o > 0 ? pos : neg, 4, err);
}

cb_status cb_mesh_box(cb_mesh_t m, const double lo[3], const double hi[3], cb_error *err)
{
    for (int k = 0; k < 3; k++)
        if (!(lo[k] < hi[k])) {
            cb_mesh_clear(m);
            return cb_error_set(err, CB_ERR_INVALID, "box: lo[%d] = %g is not below hi[%d] = %g",
                                k, lo[k], k, hi[k]);
        }
    /* Vertex i + 2 j + 4 k is the corner with x from hi when i = 1, y when j = 1, z when k = 1. */
    double p[8][3];
    for (int v = 0; v < 8; v++)
        for (int k = 0; k < 3; k++)
            p[v][k] = (v >> k) & 1 ? hi[k] : lo[k];
    static const int tri[12][3] = {{0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5},
                                   {0, 1, 5}, {0, 5, 4}, {2, 6, 7}, {2, 7, 3},
                                   {0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}};
    return build(m, (const double(*)[3])p, 8, tri, 12, err);
}

cb_status cb_mesh_icosphere(cb_mesh_t m, const double c[3], double r, int level, cb_error *err)
{
    cb_mesh_clear(m);
    if (!(r > 0) || !isfinite(r) || level < 0 || level > 10)
        return cb_error_set(err, CB_ERR_INVALID, "icosphere: radius %g, level %d", r, level);
    /* The golden ratio g: the icosahedron's vertices are (+-1, +-g, 0) and cyclic shifts. */
    const double g = 1.6180339887498949, s = 1 / sqrt(1 + g * g);
    const double ico[12][3] = {{-1, g, 0}, {1, g, 0},   {-1, -g, 0}, {1, -g, 0},
                               {0, -1, g}, {0, 1, g},   {0, -1, -g}, {0, 1, -g},
                                      {g, 0, -1}, {g, 0, 1},   {-g, 0, -1}, {-g, 0, 1}};
    static const int tri[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                   {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                   {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                   {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    /* On the unit sphere first; scaled and moved once at the end. */
    double p[12][3];
    for (int v = 0; v < 12; v++)
        for (int k = 0; k < 3; k++)
            p[v][k] = ico[v][k] * s;
    cb_status st = build(m, (const double(*)[3])p, 12, tri, 20, err);
    cb_mesh_t next;
    cb_mesh_init(next);
    for (int l = 0; !st && l < level; l++) {
        /* Each triangle becomes four around the midpoints of its sides. A side's midpoint is
         * computed from the same two doubles by both of its triangles, so the copies are
         * equal and merging exactly equal points shares them. */
        cb_mesh_clear(next);
        st = cb_mesh_reserve(next, m->n_vertices + 3 * m->n_triangles, 4 * m->n_triangles, err);
        for (int v = 0; !st && v < m->n_vertices; v++)
            st = cb_mesh_append_vertex(next, m->xyz + 3 * (size_t)v, err);
        for (int f = 0; !st && f < m->n_triangles; f++) {
            const int *t = m->tri + 3 * (size_t)f;
            int mid[3];
            for (int e = 0; !st && e < 3; e++) {
                const double *a = m->xyz + 3 * (size_t)t[e];
                const double *b = m->xyz + 3 * (size_t)t[(e + 1) % 3];
                double q[3] = {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
                double len = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
                for (int k = 0; k < 3; k++)
                    q[k] /= len;
                mid[e] = next->n_vertices;
                st = cb_mesh_append_vertex(next, q, err);
            }
            int four[4][3] = {{t[0], mid[0], mid[2]}, {mid[0], t[1], mid[1]},
                              {mid[2], mid[1], t[2]}, {mid[0], mid[1], mid[2]}};
            for (int k = 0; !st && k < 4; k++)
                st = cb_mesh_append_triangle(next, four[k][0], four[k][1], four[k][2], err);
        }
        if (!st)
            st = cb_mesh_merge_vertices(next, 0, NULL, err);
        if (!st) {
            cb_mesh_struct tmp = *m;
            *m = *next;
            *next = tmp;
        }
    }
    cb_mesh_clear(next);
    for (int v = 0; !st && v < m->n_vertices; v++)
        for (int k = 0; k < 3; k++)
            m->xyz[3 * v + k] = c[k] + r * m->xyz[3 * v + k];
    if (st)
        cb_mesh_clear(m);
    return st;
}

cb_status cb_mesh_torus(cb_mesh_t m, const double c[3], double R, double r, int nu, int nv,
                        cb_error *err)
{
    cb_mesh_clear(m);
    if (!(r > 0) || !(r < R) || !isfinite(R) || nu < 3 || nv < 3 ||
        (long long)nu * nv > INT_MAX / 2)
        return cb_error_set(err, CB_ERR_INVALID, "torus: radii %g, %g, samples %d x %d", R, r,
                            nu, nv);
    const double two_pi = 6.283185307179586;
    cb_status st = cb_mesh_reserve(m, nu * nv, 2 * nu * nv, err);
    for (int i = 0; !st && i < nu; i++)
        for (int j = 0; !st && j < nv; j++) {
            double u = two_pi * i / nu, v = two_pi * j / nv, w = R + r * cos(v);
            double p[3] = {c[0] + w * cos(u), c[1] + w * sin(u), c[2] + r * sin(v)};
            st = cb_mesh_append_vertex(m, p, err);
        }
    /* Counter-clockwise in (u, v) is outward: dP/du x dP/dv points away from the tube axis. */
    for (int i = 0; !st && i < nu; i++)
        for (int j = 0; !st && j < nv; j++) {
            int a = i * nv + j, b = (i + 1) % nu * nv + j, cc = (i + 1) % nu * nv + (j + 1) % nv,
                d = i * nv + (j + 1) % nv;
            st = cb_mesh_append_triangle(m, a, b, cc, err);
            if (!st)
                st = cb_mesh_append_triangle(m, a, cc, d, err);
        }
    if (st)
        cb_mesh_clear(m);
    return st;
}
