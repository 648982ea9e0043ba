/* nurbs.h — rational B-spline curves and surfaces in homogeneous form.
 *
 * Control points are stored homogeneous, (w x, w y, w z, w), so that every algorithm below
 * (knot insertion, refinement, degree elevation, splitting, Bezier extraction) is the
 * polynomial algorithm applied to 4-vectors and is exact up to round-off. Knot vectors are
 * clamped: the first and last knots have multiplicity degree + 1. The parameter domain of a
 * curve is [knots[deg], knots[n]].
 *
 * Output arguments come first. Unless stated otherwise an output may be the same object as the
 * input (the result is built aside and swapped in), and on failure the output is left as it
 * was. Objects must be initialised with _init before any other call and released with _clear.
 *
 * References: L. Piegl, W. Tiller, The NURBS Book, 2nd ed., Springer 1997 (algorithm numbers
 * A2.1 ... A5.9 are cited where used). */
#ifndef CB_NURBS_H
#define CB_NURBS_H

#include "brep/geom.h"
#include "brep/status.h"

typedef enum { CB_DIR_U = 0, CB_DIR_V = 1 } cb_dir;

/* ---------------------------------------------------------------- B-spline basis ----------- */

/* Largest degree any routine accepts, so that basis work arrays live on the stack. */
#define CB_MAX_DEGREE 32
#define CB_MAX_BASIS (CB_MAX_DEGREE + 1)

/* Index of the knot span [U[k], U[k+1]) that holds u, for n control points of degree p;
 * u at the right end of the domain maps to the last non-empty span; u outside the domain is
 * clamped to it (A2.1). */
int cb_bspline_find_span(int n, int p, const double *U, double u);

/* The p + 1 non-zero basis functions N[span-p .. span] at u (A2.2). */
void cb_bspline_basis(double *N, int span, double u, int p, const double *U);

/* Basis functions and their derivatives up to order k (k <= p allowed; higher orders are 0):
 * ders[i * (p + 1) + j] = d^i/du^i N_{span-p+j,p}(u), for i = 0..k (A2.3). */
void cb_bspline_basis_derivs(double *ders, int span, double u, int p, const double *U, int k);

/* ---------------------------------------------------------------- curves ------------------- */

typedef struct {
    int deg;       /* degree, >= 1 */
    int n;         /* number of control points, >= deg + 1 */
    double *knots; /* n + deg + 1 values, clamped, non-decreasing */
    double *cw;    /* n homogeneous points (w x, w y, w z, w), w > 0 */
} cb_nurbs_curve_struct;
typedef cb_nurbs_curve_struct cb_nurbs_curve_t[1];

void cb_nurbs_curve_init(cb_nurbs_curve_t c);
void cb_nurbs_curve_clear(cb_nurbs_curve_t c);
void cb_nurbs_curve_swap(cb_nurbs_curve_t a, cb_nurbs_curve_t b);

/* Resizes c to degree deg and n control points; knots and points are zeroed. */
cb_status cb_nurbs_curve_alloc(cb_nurbs_curve_t c, int deg, int n, cb_error *err);

/* Builds c from raw data as a file or a caller gives it: n_knots knots, n_points Euclidean
 * points (x, y, z consecutive) and their weights (NULL for a polynomial curve). Every
 * inconsistency is rejected with a message that names it: degree < 1, wrong counts, knots not
 * non-decreasing or not clamped, NaN/Inf anywhere, weights <= 0. */
cb_status cb_nurbs_curve_make(cb_nurbs_curve_t c, int deg, const double *knots, int n_knots,
                              const double *points, const double *weights, int n_points,
                              cb_error *err);

cb_status cb_nurbs_curve_set(cb_nurbs_curve_t dst, const cb_nurbs_curve_t src, cb_error *err);

/* Checks the invariants listed in the struct; on failure names the first offending item. */
cb_status cb_nurbs_curve_validate(const cb_nurbs_curve_t c, cb_error *err);

void cb_nurbs_curve_domain(const cb_nurbs_curve_t c, double *a, double *b);
void cb_nurbs_curve_eval(double p[3], const cb_nurbs_curve_t c, double u);
/* d[0] = C(u), d[1] = C'(u), d[2] = C''(u) (A4.2). */
void cb_nurbs_curve_eval_derivs(double d[3][3], const cb_nurbs_curve_t c, double u);

/* Inserts knot u (inside the domain) `times` times; fails if the multiplicity would exceed
 * the degree (A5.1). */
cb_status cb_nurbs_curve_insert_knot(cb_nurbs_curve_t out, const cb_nurbs_curve_t c, double u,
                                     int times, cb_error *err);
/* Inserts the nx knots x (non-decreasing, inside the domain) at once (A5.4). */
cb_status cb_nurbs_curve_refine_knots(cb_nurbs_curve_t out, const cb_nurbs_curve_t c,
                                      const double *x, int nx, cb_error *err);
/* Raises the degree by `times` >= 0 without changing the curve (A5.9). */
cb_status cb_nurbs_curve_elevate_degree(cb_nurbs_curve_t out, const cb_nurbs_curve_t c,
                                        int times, cb_error *err);
/* Splits at u strictly inside the domain: left covers [a, u], right [u, b]. left and right
 * must be distinct objects; either may be c itself. */
cb_status cb_nurbs_curve_split(cb_nurbs_curve_t left, cb_nurbs_curve_t right,
                               const cb_nurbs_curve_t c, double u, cb_error *err);
/* Reverses the direction: out(a + b - u) = c(u) on the same domain [a, b]. */
cb_status cb_nurbs_curve_reverse(cb_nurbs_curve_t out, const cb_nurbs_curve_t c, cb_error *err);
/* Decomposes c into its rational Bezier segments, in parameter order; segment k is a curve of
 * the same degree with deg + 1 control points and knots clamped on its own interval. The array
 * is allocated here and released with cb_nurbs_curve_array_free (A5.6). */
cb_status cb_nurbs_curve_extract_bezier(cb_nurbs_curve_struct **segs, int *n_segs,
                                        const cb_nurbs_curve_t c, cb_error *err);
void cb_nurbs_curve_array_free(cb_nurbs_curve_struct *arr, int n);
/* Applies a rigid motion to the control points (exact for rational curves: w is untouched). */
void cb_nurbs_curve_transform(cb_nurbs_curve_t c, const cb_xform *x);

/* ---------------------------------------------------------------- surfaces ----------------- */

typedef struct {
    int deg_u, deg_v;          /* degrees, >= 1 */
    int n_u, n_v;              /* control points in u and v */
    double *knots_u, *knots_v; /* clamped, non-decreasing, n + deg + 1 values */
    double *cw;                /* n_u * n_v homogeneous points (wx, wy, wz, w), u outer */
} cb_nurbs_surface_struct;
typedef cb_nurbs_surface_struct cb_nurbs_surface_t[1];

/* Pointer to the homogeneous control point (i, j). */
static inline double *cb_nurbs_surface_cw(const cb_nurbs_surface_t s, int i, int j)
{
    return s->cw + 4 * ((long)i * s->n_v + j);
}

void cb_nurbs_surface_init(cb_nurbs_surface_t s);
void cb_nurbs_surface_clear(cb_nurbs_surface_t s);
void cb_nurbs_surface_swap(cb_nurbs_surface_t a, cb_nurbs_surface_t b);
cb_status cb_nurbs_surface_alloc(cb_nurbs_surface_t s, int deg_u, int deg_v, int n_u, int n_v,
                                 cb_error *err);
/* As cb_nurbs_curve_make; points are n_u * n_v Euclidean points, u outer (index i * n_v + j),
 * weights likewise or NULL. */
cb_status cb_nurbs_surface_make(cb_nurbs_surface_t s, int deg_u, int deg_v,
                                const double *knots_u, int n_knots_u, const double *knots_v,
                                int n_knots_v, const double *points, const double *weights,
                                int n_u, int n_v, cb_error *err);
cb_status cb_nurbs_surface_set(cb_nurbs_surface_t dst, const cb_nurbs_surface_t src,
                               cb_error *err);
cb_status cb_nurbs_surface_validate(const cb_nurbs_surface_t s, cb_error *err);

/* box = {u0, u1, v0, v1}. */
void cb_nurbs_surface_domain(const cb_nurbs_surface_t s, double box[4]);
void cb_nurbs_surface_eval(double p[3], const cb_nurbs_surface_t s, double u, double v);
/* d[0] = S, d[1] = S_u, d[2] = S_v, d[3] = S_uu, d[4] = S_uv, d[5] = S_vv (A4.4). */
void cb_nurbs_surface_eval_derivs(double d[6][3], const cb_nurbs_surface_t s, double u, double v);

/* The surface operations act along one parameter direction; their contracts are those of the
 * curve operations of the same name. */
cb_status cb_nurbs_surface_insert_knot(cb_nurbs_surface_t out, const cb_nurbs_surface_t s,
                                       cb_dir dir, double t, int times, cb_error *err);
cb_status cb_nurbs_surface_refine_knots(cb_nurbs_surface_t out, const cb_nurbs_surface_t s,
                                        cb_dir dir, const double *x, int nx, cb_error *err);
cb_status cb_nurbs_surface_elevate_degree(cb_nurbs_surface_t out, const cb_nurbs_surface_t s,
                                          cb_dir dir, int times, cb_error *err);
cb_status cb_nurbs_surface_split(cb_nurbs_surface_t lo, cb_nurbs_surface_t hi,
                                 const cb_nurbs_surface_t s, cb_dir dir, double t,
                                 cb_error *err);
cb_status cb_nurbs_surface_reverse(cb_nurbs_surface_t out, const cb_nurbs_surface_t s,
                                   cb_dir dir, cb_error *err);
/* Swaps the roles of u and v: out(v, u) = s(u, v). */
cb_status cb_nurbs_surface_transpose(cb_nurbs_surface_t out, const cb_nurbs_surface_t s,
                                     cb_error *err);
/* Decomposes s into its rational Bezier patches: *n_pu patches along u times *n_pv along v,
 * patch (i, j) at index i * n_pv + j; each has (deg_u + 1) x (deg_v + 1) control points and
 * knots clamped on its own parameter box (read it with cb_nurbs_surface_domain). */
cb_status cb_nurbs_surface_extract_bezier(cb_nurbs_surface_struct **patches, int *n_pu,
                                          int *n_pv, const cb_nurbs_surface_t s, cb_error *err);
void cb_nurbs_surface_array_free(cb_nurbs_surface_struct *arr, int n);
void cb_nurbs_surface_transform(cb_nurbs_surface_t s, const cb_xform *x);

/* ---------------------------------------------------------------- polynomial bases --------- */

/* Converts f(t) = sum_i bern[i] B_{i,deg}((t - a) / (b - a)) on [a, b] (a != b) to the power
 * basis in t itself: f(t) = sum_k pow[k] t^k. out may alias in. */
void cb_bernstein_to_power(double *pow, const double *bern, int deg, double a, double b);
void cb_power_to_bernstein(double *bern, const double *pow, int deg, double a, double b);
/* Tensor-product versions: (m + 1) x (n + 1) coefficients, u outer, on [u0,u1] x [v0,v1]. */
void cb_bernstein_to_power_2d(double *pow, const double *bern, int m, int n, double u0,
                              double u1, double v0, double v1);
void cb_power_to_bernstein_2d(double *bern, const double *pow, int m, int n, double u0,
                              double u1, double v0, double v1);
/* Product of two tensor Bernstein polynomials on one box: a of bidegree (m, n) and b of
 * bidegree (p, q) ((m + 1) x (n + 1) and (p + 1) x (q + 1) coefficients, u outer) give out of
 * bidegree (m + p, n + q). bound (may be NULL) receives per coefficient a bound on the
 * round-off of the computed value, so that the exact product's coefficient lies within
 * bound[k] of out[k] when a and b are taken as exact. out must not alias a or b. */
void cb_bernstein_mul_2d(double *out, double *bound, const double *a, const double *b, int m,
                         int n, int p, int q);

#endif
