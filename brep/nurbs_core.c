/* Construction, copying and validation of NURBS curves and surfaces. */
#include "brep/nurbs.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

void cb_nurbs_curve_init(cb_nurbs_curve_t c) { memset(c, 0, sizeof *c); }

void cb_nurbs_curve_clear(cb_nurbs_curve_t c)
{
    free(c->knots);
    free(c->cw);
    memset(c, 0, sizeof *c);
}

void cb_nurbs_curve_swap(cb_nurbs_curve_t a, cb_nurbs_curve_t b)
{
    cb_nurbs_curve_struct t = *a;
    *a = *b;
    *b = t;
}

/* The count limit keeps every size computation far from int overflow. */
enum { MAX_DEGREE = CB_MAX_DEGREE, MAX_POINTS = 1 << 22 };

static cb_status check_sizes(int deg, int n, const char *what, cb_error *err)
{
    if (deg < 1 || deg > MAX_DEGREE)
        return cb_error_set(err, CB_ERR_INVALID, "%sdegree %d out of range [1, %d]", what, deg,
                            MAX_DEGREE);
    if (n < deg + 1 || n > MAX_POINTS)
        return cb_error_set(err, CB_ERR_INVALID,
                            "%s%d control points for degree %d (need %d to %d)", what, n, deg,
                            deg + 1, MAX_POINTS);
    return CB_OK;
}

cb_status cb_nurbs_curve_alloc(cb_nurbs_curve_t c, int deg, int n, cb_error *err)
{
    cb_status st = check_sizes(deg, n, "", err);
    if (st)
        return st;
    double *knots = calloc((size_t)(n + deg + 1), sizeof *knots);
    double *cw = calloc((size_t)n * 4, sizeof *cw);
    if (!knots || !cw) {
        free(knots);
        free(cw);
        return cb_error_set(err, CB_ERR_NOMEM, "no memory for a curve of %d control points", n);
    }
    cb_nurbs_curve_clear(c);
    c->deg = deg;
    c->n = n;
    c->knots = knots;
    c->cw = cw;
    return CB_OK;
}

/* Checks one knot vector: length, finiteness, monotonicity, clamping, non-empty domain. */
static cb_status check_knots(const double *U, int n_knots, int deg, int n, const char *what,
                             cb_error *err)
{
    if (n_knots != n + deg + 1)
        return cb_error_set(err, CB_ERR_INVALID,
                            "%s%d knots given, %d expected (%d control points, degree %d)", what,
                            n_knots, n + deg + 1, n, deg);
    for (int k = 0; k < n_knots; k++)
        if (!isfinite(U[k]))
            return cb_error_set(err, CB_ERR_INVALID, "%sknot %d is not finite", what, k);
    for (int k = 1; k < n_knots; k++)
        if (U[k] < U[k - 1])
            return cb_error_set(err, CB_ERR_INVALID,
                                "%sknots not non-decreasing at knot %d (%.17g < %.17g)", what, k,
                                U[k], U[k - 1]);
    for (int k = 1; k <= deg; k++) {
        if (U[k] != U[0])
            return cb_error_set(err, CB_ERR_INVALID,
                                "%sknot vector not clamped at the start: knot %d differs from "
                                "knot 0 (multiplicity %d expected)",
                                what, k, deg + 1);
        if (U[n_knots - 1 - k] != U[n_knots - 1])
            return cb_error_set(err, CB_ERR_INVALID,
                                "%sknot vector not clamped at the end: knot %d differs from "
                                "knot %d (multiplicity %d expected)",
                                what, n_knots - 1 - k, n_knots - 1, deg + 1);
    }
    if (!(U[n] > U[deg]))
        return cb_error_set(err, CB_ERR_INVALID, "%sempty parameter domain [%.17g, %.17g]", what,
                            U[deg], U[n]);
    if (U[deg + 1] == U[deg] || U[n - 1] == U[n])
        return cb_error_set(err, CB_ERR_INVALID,
                            "%san end knot has multiplicity above degree + 1 = %d", what,
                            deg + 1);
    for (int k = deg + 1; k < n;) {
        int mult = 1;
        while (k + mult < n && U[k + mult] == U[k])
            mult++;
        if (mult > deg)
            return cb_error_set(err, CB_ERR_INVALID,
                                "%sinterior knot %d (%.17g) has multiplicity %d > degree %d",
                                what, k, U[k], mult, deg);
        k += mult;
    }
    return CB_OK;
}

static cb_status check_points(const double *cw, long n, const char *what, cb_error *err)
{
    for (long i = 0; i < n; i++) {
        const double *p = cw + 4 * i;
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]) || !isfinite(p[3]))
            return cb_error_set(err, CB_ERR_INVALID, "%scontrol point %ld is not finite", what,
                                i);
        if (!(p[3] > 0))
            return cb_error_set(err, CB_ERR_INVALID, "%sweight %ld is %.17g, must be > 0", what,
                                i, p[3]);
    }
    return CB_OK;
}

/* Raw Euclidean points and weights as given by a caller, before they are made homogeneous. */
static cb_status check_raw_points(const double *points, const double *weights, long n,
                                  const char *what, cb_error *err)
{
    if (!points)
        return cb_error_set(err, CB_ERR_INVALID, "%sno control points given", what);
    for (long i = 0; i < n; i++) {
        for (int k = 0; k < 3; k++)
            if (!isfinite(points[3 * i + k]))
                return cb_error_set(err, CB_ERR_INVALID,
                                    "%scontrol point %ld coordinate %c is not finite", what, i,
                                    "xyz"[k]);
        if (weights && !isfinite(weights[i]))
            return cb_error_set(err, CB_ERR_INVALID, "%sweight %ld is not finite", what, i);
        if (weights && !(weights[i] > 0))
            return cb_error_set(err, CB_ERR_INVALID, "%sweight %ld is %.17g, must be > 0", what,
                                i, weights[i]);
    }
    return CB_OK;
}

static void to_homogeneous(double *cw, const double *points, const double *weights, long n)
{
    for (long i = 0; i < n; i++) {
        double w = weights ? weights[i] : 1.0;
        cw[4 * i + 0] = w * points[3 * i + 0];
        cw[4 * i + 1] = w * points[3 * i + 1];
        cw[4 * i + 2] = w * points[3 * i + 2];
        cw[4 * i + 3] = w;
    }
}

cb_status cb_nurbs_curve_make(cb_nurbs_curve_t c, int deg, const double *knots, int n_knots,
                              const double *points, const double *weights, int n_points,
                              cb_error *err)
{
    cb_status st = check_sizes(deg, n_points, "", err);
    if (!st && !knots)
        st = cb_error_set(err, CB_ERR_INVALID, "no knots given");
    if (!st)
        st = check_knots(knots, n_knots, deg, n_points, "", err);
    if (!st)
        st = check_raw_points(points, weights, n_points, "", err);
    if (st)
        return st;
    cb_nurbs_curve_t t;
    cb_nurbs_curve_init(t);
    if ((st = cb_nurbs_curve_alloc(t, deg, n_points, err)))
        return st;
    memcpy(t->knots, knots, (size_t)n_knots * sizeof *knots);
    to_homogeneous(t->cw, points, weights, n_points);
    cb_nurbs_curve_swap(c, t);
    cb_nurbs_curve_clear(t);
    return CB_OK;
}

cb_status cb_nurbs_curve_set(cb_nurbs_curve_t dst, const cb_nurbs_curve_t src, cb_error *err)
{
    if (dst == src)
        return CB_OK;
    cb_nurbs_curve_t t;
    cb_nurbs_curve_init(t);
    cb_status st = cb_nurbs_curve_alloc(t, src->deg, src->n, err);
    if (st)
        return st;
    memcpy(t->knots, src->knots, (size_t)(src->n + src->deg + 1) * sizeof *t->knots);
    memcpy(t->cw, src->cw, (size_t)src->n * 4 * sizeof *t->cw);
    cb_nurbs_curve_swap(dst, t);
    cb_nurbs_curve_clear(t);
    return CB_OK;
}

cb_status cb_nurbs_curve_validate(const cb_nurbs_curve_t c, cb_error *err)
{
    cb_status st = check_sizes(c->deg, c->n, "", err);
    if (!st && (!c->knots || !c->cw))
        st = cb_error_set(err, CB_ERR_INVALID, "curve has no storage");
    if (!st)
        st = check_knots(c->knots, c->n + c->deg + 1, c->deg, c->n, "", err);
    if (!st)
        st = check_points(c->cw, c->n, "", err);
    return st;
}

void cb_nurbs_curve_domain(const cb_nurbs_curve_t c, double *a, double *b)
{
    *a = c->knots[c->deg];
    *b = c->knots[c->n];
}

void cb_nurbs_surface_init(cb_nurbs_surface_t s) { memset(s, 0, sizeof *s); }

void cb_nurbs_surface_clear(cb_nurbs_surface_t s)
{
    free(s->knots_u);
    free(s->knots_v);
    free(s->cw);
    memset(s, 0, sizeof *s);
}

void cb_nurbs_surface_swap(cb_nurbs_surface_t a, cb_nurbs_surface_t b)
{
    cb_nurbs_surface_struct t = *a;
    *a = *b;
    *b = t;
}

cb_status cb_nurbs_surface_alloc(cb_nurbs_surface_t s, int deg_u, int deg_v, int n_u, int n_v,
                                 cb_error *err)
{
    cb_status st = check_sizes(deg_u, n_u, "u: ", err);
    if (!st)
        st = check_sizes(deg_v, n_v, "v: ", err);
    if (!st && (long)n_u * n_v > MAX_POINTS)
        st = cb_error_set(err, CB_ERR_INVALID, "%d x %d control points exceed the limit %d", n_u,
                          n_v, MAX_POINTS);
    if (st)
        return st;
    double *ku = calloc((size_t)(n_u + deg_u + 1), sizeof *ku);
    double *kv = calloc((size_t)(n_v + deg_v + 1), sizeof *kv);
    double *cw = calloc((size_t)n_u * (size_t)n_v * 4, sizeof *cw);
    if (!ku || !kv || !cw) {
        free(ku);
        free(kv);
        free(cw);
        return cb_error_set(err, CB_ERR_NOMEM, "no memory for a %d x %d surface", n_u, n_v);
    }
    cb_nurbs_surface_clear(s);
    s->deg_u = deg_u;
    s->deg_v = deg_v;
    s->n_u = n_u;
    s->n_v = n_v;
    s->knots_u = ku;
    s->knots_v = kv;
    s->cw = cw;
    return CB_OK;
}

cb_status cb_nurbs_surface_make(cb_nurbs_surface_t s, int deg_u, int deg_v,
                                const double *knots_u, int n_knots_u, const double *knots_v,
                                int n_knots_v, const double *points, const double *weights,
                                int n_u, int n_v, cb_error *err)
{
    cb_status st = check_sizes(deg_u, n_u, "u: ", err);
    if (!st)
        st = check_sizes(deg_v, n_v, "v: ", err);
    if (!st && (!knots_u || !knots_v))
        st = cb_error_set(err, CB_ERR_INVALID, "no knots given");
    if (!st)
        st = check_knots(knots_u, n_knots_u, deg_u, n_u, "u: ", err);
    if (!st)
        st = check_knots(knots_v, n_knots_v, deg_v, n_v, "v: ", err);
    if (!st)
        st = check_raw_points(points, weights, (long)n_u * n_v, "", err);
    if (st)
        return st;
    cb_nurbs_surface_t t;
    cb_nurbs_surface_init(t);
    if ((st = cb_nurbs_surface_alloc(t, deg_u, deg_v, n_u, n_v, err)))
        return st;
    memcpy(t->knots_u, knots_u, (size_t)n_knots_u * sizeof *knots_u);
    memcpy(t->knots_v, knots_v, (size_t)n_knots_v * sizeof *knots_v);
    to_homogeneous(t->cw, points, weights, (long)n_u * n_v);
    cb_nurbs_surface_swap(s, t);
    cb_nurbs_surface_clear(t);
    return CB_OK;
}

cb_status cb_nurbs_surface_set(cb_nurbs_surface_t dst, const cb_nurbs_surface_t src,
                               cb_error *err)
{
    if (dst == src)
        return CB_OK;
    cb_nurbs_surface_t t;
    cb_nurbs_surface_init(t);
    cb_status st = cb_nurbs_surface_alloc(t, src->deg_u, src->deg_v, src->n_u, src->n_v, err);
    if (st)
        return st;
    memcpy(t->knots_u, src->knots_u, (size_t)(src->n_u + src->deg_u + 1) * sizeof(double));
    memcpy(t->knots_v, src->knots_v, (size_t)(src->n_v + src->deg_v + 1) * sizeof(double));
    memcpy(t->cw, src->cw, (size_t)src->n_u * (size_t)src->n_v * 4 * sizeof(double));
    cb_nurbs_surface_swap(dst, t);
    cb_nurbs_surface_clear(t);
    return CB_OK;
}

cb_status cb_nurbs_surface_validate(const cb_nurbs_surface_t s, cb_error *err)
{
    cb_status st = check_sizes(s->deg_u, s->n_u, "u: ", err);
    if (!st)
        st = check_sizes(s->deg_v, s->n_v, "v: ", err);
    if (!st && (!s->knots_u || !s->knots_v || !s->cw))
        st = cb_error_set(err, CB_ERR_INVALID, "surface has no storage");
    if (!st)
        st = check_knots(s->knots_u, s->n_u + s->deg_u + 1, s->deg_u, s->n_u, "u: ", err);
    if (!st)
        st = check_knots(s->knots_v, s->n_v + s->deg_v + 1, s->deg_v, s->n_v, "v: ", err);
    if (!st)
        st = check_points(s->cw, (long)s->n_u * s->n_v, "", err);
    return st;
}

void cb_nurbs_surface_domain(const cb_nurbs_surface_t s, double box[4])
{
    box[0] = s->knots_u[s->deg_u];
    box[1] = s->knots_u[s->n_u];
    box[2] = s->knots_v[s->deg_v];
    box[3] = s->knots_v[s->n_v];
}

void cb_nurbs_curve_array_free(cb_nurbs_curve_struct *arr, int n)
{
    for (int k = 0; k < n; k++)
        cb_nurbs_curve_clear(&arr[k]);
    free(arr);
}

void cb_nurbs_surface_array_free(cb_nurbs_surface_struct *arr, int n)
{
    for (int k = 0; k < n; k++)
        cb_nurbs_surface_clear(&arr[k]);
    free(arr);
}
