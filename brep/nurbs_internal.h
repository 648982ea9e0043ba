/* nurbs_internal.h — inner routines shared by the NURBS operation files; not a public API.
 *
 * Every algorithm is written once on a "strip": a B-spline of degree p with n control "points"
 * of dim doubles each, point i at P + i * dim, and knots U[0 .. n + p]. A curve is a strip with
 * dim = 4. A surface seen along u is a strip with dim = 4 * n_v, because its control points are
 * stored u outer, so row i is contiguous; an operation along v transposes the surface, works
 * along u and transposes back (_cb_nurbs_surface_apply).
 *
 * The leading underscore marks what is private to the NURBS files. The strip routines
 * (_cb_bspline_*, _cb_cw_*) check nothing: arguments are valid, outputs are sized by the caller
 * and never overlap the inputs. */
#ifndef CB_NURBS_INTERNAL_H
#define CB_NURBS_INTERNAL_H

#include "brep/nurbs.h"

#include <stddef.h>

/* Number of non-empty knot spans in the domain of (U, n, p); when bk is not NULL, also writes
 * their count + 1 distinct bounds, increasing, from U[p] to U[n]. */
int _cb_bspline_breakpoints(double *bk, const double *U, int n, int p);

/* Inserts the nx knots X (non-decreasing, strictly inside the domain, no resulting multiplicity
 * above p) into the strip (U, P): writes n + nx points to Q and n + p + 1 + nx knots to UQ
 * (A5.4). */
void _cb_bspline_refine_knots(double *UQ, double *Q, const double *U, const double *P, int n,
                              int p, int dim, const double *X, int nx);

/* Writes the rational Bezier segments of the strip, in parameter order, each p + 1 points,
 * to Q: _cb_bspline_breakpoints(NULL, U, n, p) * (p + 1) * dim doubles (A5.6). */
void _cb_bspline_extract_bezier(double *Q, const double *U, const double *P, int n, int p,
                                int dim);

/* Raises the degree of the strip by t >= 0 (p + t <= CB_MAX_DEGREE): writes n + t * s points
 * to Q and n + p + 1 + t * (s + 1) knots to UQ, s = _cb_bspline_breakpoints(NULL, U, n, p)
 * (A5.9). Needs 3 p + t + 1 points of scratch, so it can fail with CB_ERR_NOMEM. */
cb_status _cb_bspline_elevate_degree(double *UQ, double *Q, const double *U, const double *P,
                                     int n, int p, int dim, int t, cb_error *err);

/* Reverses the strip on the same domain [U[p], U[n]]; the end knots map exactly. */
void _cb_bspline_reverse(double *UQ, double *Q, const double *U, const double *P, int n, int p,
                         int dim);

/* dst[j][i] = src[i][j] for a rows x cols block of homogeneous points. */
void _cb_cw_transpose(double *dst, const double *src, int rows, int cols);

/* d = alpha x + (1 - alpha) y on dim doubles; d may be x or y. */
static inline void _cb_vec_lerp(double *d, double alpha, const double *x, const double *y,
                                int dim)
{
    double beta = 1.0 - alpha;
    for (int k = 0; k < dim; k++)
        d[k] = alpha * x[k] + beta * y[k];
}

/* Entry checks shared by the operations: storage present and sizes in range (not a full
 * validation, which stays the caller's job); for surfaces also a known direction. */
cb_status _cb_nurbs_curve_check(const cb_nurbs_curve_t c, cb_error *err);
cb_status _cb_nurbs_surface_check(const cb_nurbs_surface_t s, cb_dir dir, cb_error *err);

/* Knot vector, control point count and degree of s along dir, and "u " or "v " to prefix
 * messages with. */
typedef struct {
    const double *knots;
    int n, deg;
    const char *name;
} _cb_nurbs_along;
_cb_nurbs_along _cb_nurbs_surface_along(const cb_nurbs_surface_t s, cb_dir dir);

/* An operation along u: builds r (initialised, empty) from w; arg carries its parameters. */
typedef cb_status (*_cb_nurbs_surface_op)(cb_nurbs_surface_t r, const cb_nurbs_surface_t w,
                                          const void *arg, cb_error *err);

/* Runs op along dir (on s, or on its transpose with the result transposed back) and stores the
 * result in out; out may be s and is left as it was on failure. */
cb_status _cb_nurbs_surface_apply(cb_nurbs_surface_t out, const cb_nurbs_surface_t s, cb_dir dir,
                                  _cb_nurbs_surface_op op, const void *arg, cb_error *err);

/* Allocates r with w's v direction (degree, count and knots copied) and deg_u, n_u. */
cb_status _cb_nurbs_surface_alloc_u(cb_nurbs_surface_t r, const cb_nurbs_surface_t w, int deg_u,
                                    int n_u, cb_error *err);

#endif
