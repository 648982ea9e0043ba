/* Reversal, transposition and rigid motion of NURBS curves and surfaces, and the plumbing that
 * runs a strip operation along either direction of a surface (see nurbs_internal.h). */
#include "brep/nurbs_internal.h"

#include <string.h>

cb_status _cb_nurbs_curve_check(const cb_nurbs_curve_t c, cb_error *err)
{
    if (!c->knots || !c->cw || c->deg < 1 || c->deg > CB_MAX_DEGREE || c->n < c->deg + 1)
        return cb_error_set(err, CB_ERR_INVALID,
                            "curve is empty or malformed (degree %d, %d control points)", c->deg,
                            c->n);
    return CB_OK;
}

cb_status _cb_nurbs_surface_check(const cb_nurbs_surface_t s, cb_dir dir, cb_error *err)
{
    if (!s->knots_u || !s->knots_v || !s->cw || s->deg_u < 1 || s->deg_u > CB_MAX_DEGREE ||
        s->deg_v < 1 || s->deg_v > CB_MAX_DEGREE || s->n_u < s->deg_u + 1 ||
        s->n_v < s->deg_v + 1)
        return cb_error_set(err, CB_ERR_INVALID,
                            "surface is empty or malformed (degrees %d x %d, %d x %d control "
                            "points)",
                            s->deg_u, s->deg_v, s->n_u, s->n_v);
    if (dir != CB_DIR_U && dir != CB_DIR_V)
        return cb_error_set(err, CB_ERR_INVALID, "direction %d is neither CB_DIR_U nor CB_DIR_V",
                            (int)dir);
    return CB_OK;
}

_cb_nurbs_along _cb_nurbs_surface_along(const cb_nurbs_surface_t s, cb_dir dir)
{
    if (dir == CB_DIR_U)
        return (_cb_nurbs_along){s->knots_u, s->n_u, s->deg_u, "u "};
    return (_cb_nurbs_along){s->knots_v, s->n_v, s->deg_v, "v "};
}

void _cb_cw_transpose(double *dst, const double *src, int rows, int cols)
{
    for (int i = 0; i < rows; i++)
        for (int j = 0; j < cols; j++)
            memcpy(dst + 4 * ((size_t)j * rows + i), src + 4 * ((size_t)i * cols + j),
                   4 * sizeof *dst);
}

cb_status _cb_nurbs_surface_alloc_u(cb_nurbs_surface_t r, const cb_nurbs_surface_t w, int deg_u,
                                    int n_u, cb_error *err)
{
    cb_status st = cb_nurbs_surface_alloc(r, deg_u, w->deg_v, n_u, w->n_v, err);
    if (!st)
        memcpy(r->knots_v, w->knots_v, (size_t)(w->n_v + w->deg_v + 1) * sizeof *r->knots_v);
    return st;
}

cb_status _cb_nurbs_surface_apply(cb_nurbs_surface_t out, const cb_nurbs_surface_t s, cb_dir dir,
                                  _cb_nurbs_surface_op op, const void *arg, cb_error *err)
{
    cb_nurbs_surface_t view, r;
    cb_nurbs_surface_init(view);
    cb_nurbs_surface_init(r);
    const cb_nurbs_surface_struct *w = s;
    cb_status st = CB_OK;
    if (dir == CB_DIR_V) {
        st = cb_nurbs_surface_transpose(view, s, err);
        w = view;
    }
    if (!st)
        st = op(r, w, arg, err);
    if (!st && dir == CB_DIR_V)
        st = cb_nurbs_surface_transpose(r, r, err);
    if (!st)
        cb_nurbs_surface_swap(out, r);
    cb_nurbs_surface_clear(view);
    cb_nurbs_surface_clear(r);
    return st;
}

cb_status cb_nurbs_surface_transpose(cb_nurbs_surface_t out, const cb_nurbs_surface_t s,
                                     cb_error *err)
{
    cb_status st = _cb_nurbs_surface_check(s, CB_DIR_U, err);
    if (st)
        return st;
    cb_nurbs_surface_t t;
    cb_nurbs_surface_init(t);
    if ((st = cb_nurbs_surface_alloc(t, s->deg_v, s->deg_u, s->n_v, s->n_u, err)))
        return st;
    memcpy(t->knots_u, s->knots_v, (size_t)(s->n_v + s->deg_v + 1) * sizeof *t->knots_u);
    memcpy(t->knots_v, s->knots_u, (size_t)(s->n_u + s->deg_u + 1) * sizeof *t->knots_v);
    _cb_cw_transpose(t->cw, s->cw, s->n_u, s->n_v);
    cb_nurbs_surface_swap(out, t);
    cb_nurbs_surface_clear(t);
    return CB_OK;
}

void _cb_bspline_reverse(double *UQ, double *Q, const double *U, const double *P, int n, int p,
                         int dim)
{
    /* a + b - x rounds, so the ends might not map onto each other exactly; measuring each
     * knot from its nearer end keeps the domain [a, b] bit for bit. */
    double a = U[p], b = U[n], mid = 0.5 * (a + b);
    int m = n + p;
    for (int k = 0; k <= m; k++) {
        double x = U[m - k];
        UQ[k] = x <= mid ? b - (x - a) : a + (b - x);
    }
    for (int i = 0; i < n; i++)
        memcpy(Q + (size_t)i * dim, P + (size_t)(n - 1 - i) * dim, (size_t)dim * sizeof *Q);
}

cb_status cb_nurbs_curve_reverse(cb_nurbs_curve_t out, const cb_nurbs_curve_t c, cb_error *err)
{
    cb_status st = _cb_nurbs_curve_check(c, err);
    if (st)
        return st;
    cb_nurbs_curve_t r;
    cb_nurbs_curve_init(r);
    if ((st = cb_nurbs_curve_alloc(r, c->deg, c->n, err)))
        return st;
    _cb_bspline_reverse(r->knots, r->cw, c->knots, c->cw, c->n, c->deg, 4);
    cb_nurbs_curve_swap(out, r);
    cb_nurbs_curve_clear(r);
    return CB_OK;
}

static cb_status reverse_u(cb_nurbs_surface_t r, const cb_nurbs_surface_t w, const void *arg,
                           cb_error *err)
{
    (void)arg;
    cb_status st = _cb_nurbs_surface_alloc_u(r, w, w->deg_u, w->n_u, err);
    if (!st)
        _cb_bspline_reverse(r->knots_u, r->cw, w->knots_u, w->cw, w->n_u, w->deg_u, 4 * w->n_v);
    return st;
}

cb_status cb_nurbs_surface_reverse(cb_nurbs_surface_t out, const cb_nurbs_surface_t s,
                                   cb_dir dir, cb_error *err)
{
    cb_status st = _cb_nurbs_surface_check(s, dir, err);
    if (st)
        return st;
    return _cb_nurbs_surface_apply(out, s, dir, reverse_u, NULL, err);
}

/* (w x, w y, w z, w) -> (R (w x, w y, w z) + w t, w): the motion of (x, y, z), weight kept. */
static void transform_points(double *cw, long count, const cb_xform *x)
{
    for (long i = 0; i < count; i++) {
        double *q = cw + 4 * i;
        double r[3];
        cb_xform_apply_vector(r, x, q);
        for (int k = 0; k < 3; k++)
            q[k] = r[k] + q[3] * x->t[k];
    }
}

void cb_nurbs_curve_transform(cb_nurbs_curve_t c, const cb_xform *x)
{
    if (c->cw)
        transform_points(c->cw, c->n, x);
}

void cb_nurbs_surface_transform(cb_nurbs_surface_t s, const cb_xform *x)
{
    if (s->cw)
        transform_points(s->cw, (long)s->n_u * s->n_v, x);
}
