/* Knot insertion, knot refinement, splitting and Bezier decomposition of NURBS curves and
 * surfaces (The NURBS Book A5.4, A5.6).
 *
 * Inserting one knot r times is done as refinement by (u, ..., u): A5.4 computes the same
 * convex combinations as A5.1 but builds the result in its output array alone, with no work
 * row, which matters for surfaces, whose "points" are whole rows of the control net. A split
 * raises the knot to multiplicity p and cuts the control polygon at it. */
#include "brep/nurbs_internal.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

int _cb_bspline_breakpoints(double *bk, const double *U, int n, int p)
{
    int count = 0;
    if (bk)
        bk[0] = U[p];
    for (int k = p + 1; k <= n; k++)
        if (U[k] > U[k - 1]) {
            count++;
            if (bk)
                bk[count] = U[k];
        }
    return count;
}

static int knot_mult(const double *U, int n, int p, double u)
{
    int mult = 0;
    for (int k = 0; k <= n + p; k++)
        mult += U[k] == u;
    return mult;
}

/* Point i of a strip of dim-wide points, dim being the local of that name. */
#define PT(A, i) ((A) + (size_t)(i) * (size_t)dim)

void _cb_bspline_refine_knots(double *UQ, double *Q, const double *U, const double *P, int n,
                              int p, int dim, const double *X, int nx)
{
    size_t row = (size_t)dim * sizeof *Q;
    if (nx == 0) {
        memcpy(UQ, U, (size_t)(n + p + 1) * sizeof *UQ);
        memcpy(Q, P, (size_t)n * row);
        return;
    }
    /* Book notation: r is the last index of X, m the last index of U. */
    int r = nx - 1, m = n + p;
    int a = cb_bspline_find_span(n, p, U, X[0]);
    int b = cb_bspline_find_span(n, p, U, X[r]) + 1;
    memcpy(Q, P, (size_t)(a - p + 1) * row);
    memcpy(PT(Q, b - 1 + nx), PT(P, b - 1), (size_t)(n - b + 1) * row);
    memcpy(UQ, U, (size_t)(a + 1) * sizeof *UQ);
    memcpy(UQ + b + p + nx, U + b + p, (size_t)(m - b - p + 1) * sizeof *UQ);
    int i = b + p - 1, k = b + p + r;
    for (int j = r; j >= 0; j--) {
        while (X[j] <= U[i] && i > a) {
            memcpy(PT(Q, k - p - 1), PT(P, i - p - 1), row);
            UQ[k] = U[i];
            k--;
            i--;
        }
        memcpy(PT(Q, k - p - 1), PT(Q, k - p), row);
        for (int l = 1; l <= p; l++) {
            int ind = k - p + l;
            double alpha = UQ[k + l] - X[j];
            if (alpha == 0.0)
                memcpy(PT(Q, ind - 1), PT(Q, ind), row);
            else {
                alpha /= UQ[k + l] - U[i - p + l];
                _cb_vec_lerp(PT(Q, ind - 1), alpha, PT(Q, ind - 1), PT(Q, ind), dim);
            }
        }
        UQ[k] = X[j];
        k--;
    }
}

void _cb_bspline_extract_bezier(double *Q, const double *U, const double *P, int n, int p,
                                int dim)
{
    size_t row = (size_t)dim * sizeof *Q, seg = (size_t)(p + 1) * (size_t)dim;
    double alphas[CB_MAX_BASIS];
    int m = n + p, a = p, b = p + 1;
    double *cur = Q;
    memcpy(cur, P, (size_t)(p + 1) * row);
    while (b < m) {
        int i = b;
        while (b < m && U[b + 1] == U[b])
            b++;
        int mult = b - i + 1;
        if (mult < p) {
            /* Raise U[b] to multiplicity p; the points that fall off the right end start the
             * next segment. */
            double numer = U[b] - U[a];
            for (int j = p; j > mult; j--)
                alphas[j - mult - 1] = numer / (U[a + j] - U[a]);
            int r = p - mult;
            for (int j = 1; j <= r; j++) {
                int save = r - j, s = mult + j;
                for (int k = p; k >= s; k--)
                    _cb_vec_lerp(PT(cur, k), alphas[k - s], PT(cur, k), PT(cur, k - 1), dim);
                if (b < m)
                    memcpy(PT(cur + seg, save), PT(cur, p), row);
            }
        }
        if (b < m) {
            cur += seg;
            memcpy(PT(cur, p - mult), PT(P, b - mult), (size_t)(mult + 1) * row);
            a = b;
            b++;
        }
    }
}

/* ---------------------------------------------------------------- argument checks --------- */

static cb_status check_inside(const double *U, int n, int p, double u, const char *dir,
                              const char *noun, cb_error *err)
{
    if (!(u > U[p] && u < U[n]))
        return cb_error_set(err, CB_ERR_INVALID,
                            "%s%s %.17g is not strictly inside the domain (%.17g, %.17g)", dir,
                            noun, u, U[p], U[n]);
    return CB_OK;
}

static cb_status check_insert(const double *U, int n, int p, double u, int times,
                              const char *dir, cb_error *err)
{
    if (times < 0)
        return cb_error_set(err, CB_ERR_INVALID, "%sknot insertion: times = %d is negative", dir,
                            times);
    cb_status st = check_inside(U, n, p, u, dir, "knot", err);
    if (st)
        return st;
    int mult = knot_mult(U, n, p, u);
    if (mult + times > p)
        return cb_error_set(err, CB_ERR_INVALID,
                            "%sinserting knot %.17g %d times gives multiplicity %d > degree %d",
                            dir, u, times, mult + times, p);
    return CB_OK;
}

static cb_status check_refine(const double *U, int n, int p, const double *x, int nx,
                              const char *dir, cb_error *err)
{
    if (nx < 0 || nx > INT_MAX / 2 - n - p)
        return cb_error_set(err, CB_ERR_INVALID, "%srefinement knot count %d out of range", dir,
                            nx);
    if (nx > 0 && !x)
        return cb_error_set(err, CB_ERR_INVALID, "%sno refinement knots given", dir);
    for (int k = 0; k < nx; k++) {
        if (!(x[k] > U[p] && x[k] < U[n]))
            return cb_error_set(err, CB_ERR_INVALID,
                                "%srefinement knot %d (%.17g) is not strictly inside the "
                                "domain (%.17g, %.17g)",
                                dir, k, x[k], U[p], U[n]);
        if (k > 0 && x[k] < x[k - 1])
            return cb_error_set(err, CB_ERR_INVALID,
                                "%srefinement knots not non-decreasing at knot %d (%.17g < "
                                "%.17g)",
                                dir, k, x[k], x[k - 1]);
    }
    for (int k = 0; k < nx;) {
        int run = 1;
        while (k + run < nx && x[k + run] == x[k])
            run++;
        int mult = knot_mult(U, n, p, x[k]) + run;
        if (mult > p)
            return cb_error_set(err, CB_ERR_INVALID,
                                "%srefinement knot %.17g would have multiplicity %d > degree %d",
                                dir, x[k], mult, p);
        k += run;
    }
    return CB_OK;
}

static cb_status check_split(const double *U, int n, int p, double u, const void *lo,
                             const void *hi, const char *dir, cb_error *err)
{
    if (lo == hi)
        return cb_error_set(err, CB_ERR_INVALID,
                            "split: the two halves must go to distinct objects");
    return check_inside(U, n, p, u, dir, "split parameter", err);
}

/* ---------------------------------------------------------------- insertion, refinement ---- */

cb_status cb_nurbs_curve_refine_knots(cb_nurbs_curve_t out, const cb_nurbs_curve_t c,
                                      const double *x, int nx, cb_error *err)
{
    cb_status st = _cb_nurbs_curve_check(c, err);
    if (!st)
        st = check_refine(c->knots, c->n, c->deg, x, nx, "", err);
    if (st)
        return st;
    cb_nurbs_curve_t r;
    cb_nurbs_curve_init(r);
    if ((st = cb_nurbs_curve_alloc(r, c->deg, c->n + nx, err)))
        return st;
    _cb_bspline_refine_knots(r->knots, r->cw, c->knots, c->cw, c->n, c->deg, 4, x, nx);
    cb_nurbs_curve_swap(out, r);
    cb_nurbs_curve_clear(r);
    return CB_OK;
}

cb_status cb_nurbs_curve_insert_knot(cb_nurbs_curve_t out, const cb_nurbs_curve_t c, double u,
                                     int times, cb_error *err)
{
    cb_status st = _cb_nurbs_curve_check(c, err);
    if (!st)
        st = check_insert(c->knots, c->n, c->deg, u, times, "", err);
    if (st)
        return st;
    double x[CB_MAX_DEGREE];
    for (int k = 0; k < times; k++)
        x[k] = u;
    return cb_nurbs_curve_refine_knots(out, c, x, times, err);
}

struct refine_arg {
    const double *x;
    int nx;
};

static cb_status refine_u(cb_nurbs_surface_t r, const cb_nurbs_surface_t w, const void *arg,
                          cb_error *err)
{
    const struct refine_arg *a = arg;
    cb_status st = _cb_nurbs_surface_alloc_u(r, w, w->deg_u, w->n_u + a->nx, err);
    if (!st)
        _cb_bspline_refine_knots(r->knots_u, r->cw, w->knots_u, w->cw, w->n_u, w->deg_u,
                                 4 * w->n_v, a->x, a->nx);
    return st;
}

cb_status cb_nurbs_surface_refine_knots(cb_nurbs_surface_t out, const cb_nurbs_surface_t s,
                                        cb_dir dir, const double *x, int nx, cb_error *err)
{
    cb_status st = _cb_nurbs_surface_check(s, dir, err);
    if (st)
        return st;
    _cb_nurbs_along k = _cb_nurbs_surface_along(s, dir);
    if ((st = check_refine(k.knots, k.n, k.deg, x, nx, k.name, err)))
        return st;
    struct refine_arg arg = {x, nx};
    return _cb_nurbs_surface_apply(out, s, dir, refine_u, &arg, err);
}

cb_status cb_nurbs_surface_insert_knot(cb_nurbs_surface_t out, const cb_nurbs_surface_t s,
                                       cb_dir dir, double t, int times, cb_error *err)
{
    cb_status st = _cb_nurbs_surface_check(s, dir, err);
    if (st)
        return st;
    _cb_nurbs_along k = _cb_nurbs_surface_along(s, dir);
    if ((st = check_insert(k.knots, k.n, k.deg, t, times, k.name, err)))
        return st;
    double x[CB_MAX_DEGREE];
    for (int j = 0; j < times; j++)
        x[j] = t;
    return cb_nurbs_surface_refine_knots(out, s, dir, x, times, err);
}

/* ---------------------------------------------------------------- splitting --------------- */

/* Cuts a strip at u, whose multiplicity there is exactly p (knots U[f .. f + p - 1]): the left
 * half keeps points 0 .. f - 1, the right f - 1 .. n - 1, each clamped at u. */
static int cut_index(const double *U, int n, int p, double u)
{
    return cb_bspline_find_span(n, p, U, u) - p + 1;
}

static int cut_count(int n, int f, int right) { return right ? n - f + 1 : f; }

static void cut_strip(double *UH, double *PH, const double *U, const double *P, int n, int p,
                      int dim, int f, int right)
{
    size_t row = (size_t)dim * sizeof *PH;
    double u = U[f];
    if (right) {
        for (int k = 0; k <= p; k++)
            UH[k] = u;
        memcpy(UH + p + 1, U + f + p, (size_t)(n + 1 - f) * sizeof *UH);
        memcpy(PH, PT(P, f - 1), (size_t)(n - f + 1) * row);
    } else {
        memcpy(UH, U, (size_t)(f + p) * sizeof *UH);
        UH[f + p] = u;
        memcpy(PH, P, (size_t)f * row);
    }
}

static cb_status curve_half(cb_nurbs_curve_t h, const cb_nurbs_curve_t t, double u, int right,
                            cb_error *err)
{
    int f = cut_index(t->knots, t->n, t->deg, u);
    cb_status st = cb_nurbs_curve_alloc(h, t->deg, cut_count(t->n, f, right), err);
    if (!st)
        cut_strip(h->knots, h->cw, t->knots, t->cw, t->n, t->deg, 4, f, right);
    return st;
}

cb_status cb_nurbs_curve_split(cb_nurbs_curve_t left, cb_nurbs_curve_t right,
                               const cb_nurbs_curve_t c, double u, cb_error *err)
{
    cb_status st = _cb_nurbs_curve_check(c, err);
    if (!st)
        st = check_split(c->knots, c->n, c->deg, u, left, right, "", err);
    if (st)
        return st;
    cb_nurbs_curve_t t, l, r;
    cb_nurbs_curve_init(t);
    cb_nurbs_curve_init(l);
    cb_nurbs_curve_init(r);
    int times = c->deg - knot_mult(c->knots, c->n, c->deg, u);
    st = cb_nurbs_curve_insert_knot(t, c, u, times, err);
    if (!st)
        st = curve_half(l, t, u, 0, err);
    if (!st)
        st = curve_half(r, t, u, 1, err);
    if (!st) {
        cb_nurbs_curve_swap(left, l);
        cb_nurbs_curve_swap(right, r);
    }
    cb_nurbs_curve_clear(t);
    cb_nurbs_curve_clear(l);
    cb_nurbs_curve_clear(r);
    return st;
}

struct half_arg {
    double u;
    int right;
};

static cb_status half_u(cb_nurbs_surface_t r, const cb_nurbs_surface_t w, const void *arg,
                        cb_error *err)
{
    const struct half_arg *h = arg;
    int f = cut_index(w->knots_u, w->n_u, w->deg_u, h->u);
    cb_status st = _cb_nurbs_surface_alloc_u(r, w, w->deg_u, cut_count(w->n_u, f, h->right), err);
    if (!st)
        cut_strip(r->knots_u, r->cw, w->knots_u, w->cw, w->n_u, w->deg_u, 4 * w->n_v, f,
                  h->right);
    return st;
}

cb_status cb_nurbs_surface_split(cb_nurbs_surface_t lo, cb_nurbs_surface_t hi,
                                 const cb_nurbs_surface_t s, cb_dir dir, double t,
                                 cb_error *err)
{
    cb_status st = _cb_nurbs_surface_check(s, dir, err);
    if (st)
        return st;
    _cb_nurbs_along k = _cb_nurbs_surface_along(s, dir);
    if ((st = check_split(k.knots, k.n, k.deg, t, lo, hi, k.name, err)))
        return st;
    cb_nurbs_surface_t ref, a, b;
    cb_nurbs_surface_init(ref);
    cb_nurbs_surface_init(a);
    cb_nurbs_surface_init(b);
    int times = k.deg - knot_mult(k.knots, k.n, k.deg, t);
    st = cb_nurbs_surface_insert_knot(ref, s, dir, t, times, err);
    if (!st)
        st = _cb_nurbs_surface_apply(a, ref, dir, half_u, &(struct half_arg){t, 0}, err);
    if (!st)
        st = _cb_nurbs_surface_apply(b, ref, dir, half_u, &(struct half_arg){t, 1}, err);
    if (!st) {
        cb_nurbs_surface_swap(lo, a);
        cb_nurbs_surface_swap(hi, b);
    }
    cb_nurbs_surface_clear(ref);
    cb_nurbs_surface_clear(a);
    cb_nurbs_surface_clear(b);
    return st;
}

/* ---------------------------------------------------------------- Bezier decomposition ---- */

static void bezier_knots(double *K, int p, double a, double b)
{
    for (int k = 0; k <= p; k++) {
        K[k] = a;
        K[p + 1 + k] = b;
    }
}

cb_status cb_nurbs_curve_extract_bezier(cb_nurbs_curve_struct **segs, int *n_segs,
                                        const cb_nurbs_curve_t c, cb_error *err)
{
    cb_status st = _cb_nurbs_curve_check(c, err);
    if (st)
        return st;
    int p = c->deg, ns = _cb_bspline_breakpoints(NULL, c->knots, c->n, p);
    size_t seg = (size_t)(p + 1) * 4;
    double *bk = malloc((size_t)(ns + 1) * sizeof *bk);
    double *Q = malloc((size_t)ns * seg * sizeof *Q);
    cb_nurbs_curve_struct *arr = calloc((size_t)ns, sizeof *arr);
    if (!bk || !Q || !arr)
        st = cb_error_set(err, CB_ERR_NOMEM, "no memory for %d Bezier segments", ns);
    else {
        _cb_bspline_breakpoints(bk, c->knots, c->n, p);
        _cb_bspline_extract_bezier(Q, c->knots, c->cw, c->n, p, 4);
        for (int k = 0; k < ns && !st; k++)
            if (!(st = cb_nurbs_curve_alloc(&arr[k], p, p + 1, err))) {
                memcpy(arr[k].cw, Q + k * seg, seg * sizeof *Q);
                bezier_knots(arr[k].knots, p, bk[k], bk[k + 1]);
            }
    }
    free(bk);
    free(Q);
    if (st) {
        if (arr)
            cb_nurbs_curve_array_free(arr, ns);
        return st;
    }
    *segs = arr;
    *n_segs = ns;
    return CB_OK;
}

cb_status cb_nurbs_surface_extract_bezier(cb_nurbs_surface_struct **patches, int *n_pu,
                                          int *n_pv, const cb_nurbs_surface_t s, cb_error *err)
{
    cb_status st = _cb_nurbs_surface_check(s, CB_DIR_U, err);
    if (st)
        return st;
    int pu = s->deg_u, pv = s->deg_v, nv = s->n_v;
    int nsu = _cb_bspline_breakpoints(NULL, s->knots_u, s->n_u, pu);
    int nsv = _cb_bspline_breakpoints(NULL, s->knots_v, nv, pv);
    /* Strips along u give nsu slabs of (pu + 1) x n_v points; each slab, transposed, is a strip
     * along v whose segments, transposed back, are the patches. */
    size_t slab = (size_t)(pu + 1) * nv * 4, patch = (size_t)(pu + 1) * (pv + 1) * 4;
    double *bu = malloc((size_t)(nsu + 1) * sizeof *bu);
    double *bv = malloc((size_t)(nsv + 1) * sizeof *bv);
    double *slabs = malloc((size_t)nsu * slab * sizeof *slabs);
    double *slab_t = malloc(slab * sizeof *slab_t);
    double *segs_t = malloc((size_t)nsv * patch * sizeof *segs_t);
    long count = (long)nsu * nsv;
    cb_nurbs_surface_struct *arr = calloc((size_t)count, sizeof *arr);
    if (!bu || !bv || !slabs || !slab_t || !segs_t || !arr)
        st = cb_error_set(err, CB_ERR_NOMEM, "no memory for %d x %d Bezier patches", nsu, nsv);
    else {
        _cb_bspline_breakpoints(bu, s->knots_u, s->n_u, pu);
        _cb_bspline_breakpoints(bv, s->knots_v, nv, pv);
        _cb_bspline_extract_bezier(slabs, s->knots_u, s->cw, s->n_u, pu, nv * 4);
        for (int i = 0; i < nsu && !st; i++) {
            _cb_cw_transpose(slab_t, slabs + i * slab, pu + 1, nv);
            _cb_bspline_extract_bezier(segs_t, s->knots_v, slab_t, nv, pv, (pu + 1) * 4);
            for (int j = 0; j < nsv && !st; j++) {
                cb_nurbs_surface_struct *q = &arr[(long)i * nsv + j];
                if (!(st = cb_nurbs_surface_alloc(q, pu, pv, pu + 1, pv + 1, err))) {
                    _cb_cw_transpose(q->cw, segs_t + j * patch, pv + 1, pu + 1);
                    bezier_knots(q->knots_u, pu, bu[i], bu[i + 1]);
                    bezier_knots(q->knots_v, pv, bv[j], bv[j + 1]);
                }
            }
        }
    }
    free(bu);
    free(bv);
    free(slabs);
    free(slab_t);
    free(segs_t);
    if (st) {
        if (arr)
            cb_nurbs_surface_array_free(arr, (int)count);
        return st;
    }
    *patches = arr;
    *n_pu = nsu;
    *n_pv = nsv;
    return CB_OK;
}
