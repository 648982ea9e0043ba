/* B-spline curves and surfaces: the simple and complex (rational) instance forms, knot
 * multiplicities expanded, unclamped knot vectors clamped exactly by knot insertion, the result
 * checked by cb_nurbs_*_make. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/step_internal.h"

/* How the knots of a B-spline are given: explicitly (..._WITH_KNOTS), or implied by the form
 * (ISO 10303-42 4.3.4 and 4.3.5: uniform, quasi-uniform and piecewise Bezier curves and
 * surfaces carry no knots). */
typedef enum { BS_KNOTS_EXPLICIT, BS_KNOTS_UNIFORM, BS_KNOTS_QUASI_UNIFORM, BS_KNOTS_BEZIER } bs_knots;

/* The attributes a B-spline instance carries, wherever its form puts them. */
typedef struct {
    const step_node *deg[2], *points, *mults[2], *knots[2], *weights;
    bs_knots form;
} bs_view;

/* The subtype of B_SPLINE_CURVE (surface = 0) or B_SPLINE_SURFACE (1) that r holds, and its
 * part; NULL if none. */
static const step_part *bs_subtype(step_file *f, const step_rec *r, int surface, bs_knots *form)
{
    static const step_type types[2][4] = {
        {STEP_T_B_SPLINE_CURVE_WITH_KNOTS, STEP_T_UNIFORM_CURVE, STEP_T_QUASI_UNIFORM_CURVE,
         STEP_T_BEZIER_CURVE},
        {STEP_T_B_SPLINE_SURFACE_WITH_KNOTS, STEP_T_UNIFORM_SURFACE, STEP_T_QUASI_UNIFORM_SURFACE,
         STEP_T_BEZIER_SURFACE}};
    for (int k = 0; k < 4; k++) {
        const step_part *p = step_part_of(f, r, types[surface][k]);
        if (p) {
            *form = (bs_knots)k;
            return p;
        }
    }
    return NULL;
}

/* Finds the attributes of a curve (surface = 0) or surface (surface = 1) instance. */
static cb_status bs_view_of(bs_view *v, step_file *f, const step_rec *r, int surface)
{
    memset(v, 0, sizeof *v);
    const step_part *pk = bs_subtype(f, r, surface, &v->form);
    if (!pk)
        return step_fail(f, r, NULL, CB_ERR_UNSUPPORTED,
                         "a B-spline %s without its knots: none of %s_WITH_KNOTS, UNIFORM_%s, "
                         "QUASI_UNIFORM_%s, BEZIER_%s",
                         surface ? "surface" : "curve",
                         surface ? "B_SPLINE_SURFACE" : "B_SPLINE_CURVE",
                         surface ? "SURFACE" : "CURVE", surface ? "SURFACE" : "CURVE",
                         surface ? "SURFACE" : "CURVE");
    int explicit_knots = v->form == BS_KNOTS_EXPLICIT;
    const step_node *a;
    if (!r->complex) {
        /* name, degree(s), points, form, closed flag(s), self_intersect, then for the
         * _WITH_KNOTS form multiplicities, knots, knot_spec */
        int n_base = surface ? 8 : 6;
        if (!(a = step_args(f, r, pk, n_base + (explicit_knots ? (surface ? 5 : 3) : 0))))
            return f->err->status;
        a = step_next(a);
        v->deg[0] = a;
        if (surface)
            v->deg[1] = a = step_next(a);
        v->points = a = step_next(a);
        /* form, closed flag(s) and self_intersect come before the multiplicities */
        for (int k = 0; k < (surface ? 5 : 4); k++)
            a = step_next(a);
    } else {
        const step_part *pb =
            step_part_of(f, r, surface ? STEP_T_B_SPLINE_SURFACE : STEP_T_B_SPLINE_CURVE);
        if (!pb)
            return step_fail(f, r, NULL, CB_ERR_PARSE, "complex instance without %s",
                             surface ? "B_SPLINE_SURFACE" : "B_SPLINE_CURVE");
        if (!(a = step_args(f, r, pb, surface ? 7 : 5)))
            return f->err->status;
        v->deg[0] = a;
        if (surface)
            v->deg[1] = a = step_next(a);
        v->points = step_next(a);
        if (!(a = step_args(f, r, pk, explicit_knots ? (surface ? 5 : 3) : 0)))
            return f->err->status;
        const step_part *pr = step_part_of(
            f, r, surface ? STEP_T_RATIONAL_B_SPLINE_SURFACE : STEP_T_RATIONAL_B_SPLINE_CURVE);
        if (pr && !(v->weights = step_args(f, r, pr, 1)))
            return f->err->status;
    }
    if (!explicit_knots)
        return CB_OK;
    v->mults[0] = a;
    if (surface) {
        v->mults[1] = a = step_next(a);
        v->knots[0] = a = step_next(a);
        v->knots[1] = step_next(a);
    } else {
        v->knots[0] = step_next(a);
    }
    return CB_OK;
}

/* The knot vector (n + p + 1 values) that a form without explicit knots implies for n control
 * points of degree p (ISO 10303-42, B_SPLINE_CURVE's knot definitions): uniform -p, -p + 1,
 * ..., n, each once (so the curve is unclamped and is clamped exactly afterwards, its domain
 * [0, n - p]); quasi-uniform 0, 1, ..., n - p with the ends p + 1 times; piecewise Bezier 0, 1,
 * ..., (n - 1) / p with the ends p + 1 times and the interior values p times, which needs
 * n - 1 to be a multiple of p. */
static cb_status implied_knots(double **out, int *n_out, step_file *f, const step_rec *r,
                               bs_knots form, int n, int p, const char *dir)
{
    if (form == BS_KNOTS_BEZIER && (n - 1) % p)
        return step_fail(f, r, NULL, CB_ERR_INVALID,
                         "%spiecewise Bezier form with %d control points of degree %d: "
                         "%d - 1 is not a multiple of %d",
                         dir, n, p, n, p);
    if (n < p + 1)
        return step_fail(f, r, NULL, CB_ERR_INVALID, "%s%d control points for degree %d", dir, n,
                         p);
    int m = n + p + 1;
    double *U = malloc((size_t)m * sizeof *U);
    if (!U)
        return cb_error_set(f->err, CB_ERR_NOMEM, "%s: no memory for %d knots", f->path, m);
    for (int k = 0; k < m; k++) {
        switch (form) {
        case BS_KNOTS_UNIFORM: U[k] = k - p; break;
        case BS_KNOTS_QUASI_UNIFORM:
            U[k] = k <= p ? 0 : k >= n ? n - p : k - p;
            break;
        default: /* Bezier: the interior knots p times each */
            U[k] = k <= p ? 0 : k >= n ? (n - 1) / p : (k - 1) / p;
            break;
        }
    }
    *out = U;
    *n_out = m;
    return CB_OK;
}

/* Expands (multiplicities, values) into a knot vector. Multiplicities must lie in
 * [1, deg + 1], so the expansion is at most deg + 1 times the file's list. */
static cb_status expand_knots(double **out, int *n_out, step_file *f, const step_rec *r,
                              const step_node *mults, const step_node *knots, int deg,
                              const char *dir)
{
    char what[48];
    snprintf(what, sizeof what, "%sknot multiplicities", dir);
    cb_status st = step_get_list(f, r, mults, what, 1, 1 << 24);
    if (st)
        return st;
    snprintf(what, sizeof what, "%sknots", dir);
    if ((st = step_get_list(f, r, knots, what, 1, 1 << 24)))
        return st;
    if (mults->n != knots->n)
        return step_fail(f, r, mults, CB_ERR_INVALID, "%d %sknot multiplicities for %d knot values",
                         mults->n, dir, knots->n);
    long total = 0;
    const step_node *m = mults + 1;
    for (int k = 0; k < mults->n; k++, m = step_next(m)) {
        long mk;
        snprintf(what, sizeof what, "%sknot multiplicity %d", dir, k + 1);
        if ((st = step_get_int(f, r, m, what, 1, deg + 1, &mk)))
            return st;
        total += mk;
    }
    double *U = malloc((size_t)total * sizeof *U);
    if (!U)
        return cb_error_set(f->err, CB_ERR_NOMEM, "%s: no memory for %ld knots", f->path, total);
    int n = 0;
    m = mults + 1;
    const step_node *x = knots + 1;
    for (int k = 0; k < knots->n; k++, m = step_next(m), x = step_next(x)) {
        double u;
        snprintf(what, sizeof what, "%sknot %d", dir, k + 1);
        if ((st = step_get_real(f, r, x, what, &u))) {
            free(U);
            return st;
        }
        for (long j = 0; j < m->ival; j++)
            U[n++] = u;
    }
    *out = U;
    *n_out = n;
    return CB_OK;
}

/* ---------------------------------------------------------------- exact clamping ----------- */

/* Inserts u once into the strip (U: n + p + 1 knots, P: n points of dim doubles), for u with
 * U[p] <= u < U[n]; U and P must have room for one more knot and point (Boehm, The NURBS Book
 * A5.1 with r = 1). */
static void insert_once(double *U, double *P, int n, int p, int dim, double u)
{
    int k = p;
    while (k + 1 < n && U[k + 1] <= u)
        k++;
    memmove(P + (size_t)(k + 1) * dim, P + (size_t)k * dim, (size_t)(n - k) * dim * sizeof *P);
    for (int i = k; i >= k - p + 1; i--) {
        double alpha = (u - U[i]) / (U[i + p] - U[i]);
        double *q = P + (size_t)i * dim, *prev = P + (size_t)(i - 1) * dim;
        for (int c = 0; c < dim; c++)
            q[c] = alpha * q[c] + (1.0 - alpha) * prev[c];
    }
    memmove(U + k + 2, U + k + 1, (size_t)(n + p - k) * sizeof *U);
    U[k + 1] = u;
}

/* Clamps the start of the strip: a = U[p] is inserted until it has multiplicity p, then the
 * knots before its first copy and the points that only act before a are dropped and one more
 * copy of a is put in front. The curve on [a, U[n]] is unchanged. U and P need room for p more
 * knots and points. */
static void clamp_start(double *U, double *P, int *n, int p, int dim)
{
    double a = U[p];
    int mult = 0;
    for (int k = 0; k < *n + p + 1; k++)
        mult += U[k] == a;
    for (; mult < p; mult++)
        insert_once(U, P, (*n)++, p, dim, a);
    int i0 = 0;
    while (U[i0] != a)
        i0++;
    if (i0 == 0)
        return;
    int drop = i0 - 1;
    memmove(U, U + drop, (size_t)(*n + p + 1 - drop) * sizeof *U);
    U[0] = a;
    memmove(P, P + (size_t)drop * dim, (size_t)(*n - drop) * dim * sizeof *P);
    *n -= drop;
}

/* Reverses the strip: knots negated and reversed, points reversed (the same curve run
 * backwards, exactly). */
static void reverse_strip(double *U, double *P, int n, int p, int dim)
{
    int m = n + p + 1;
    for (int i = 0, j = m - 1; i <= j; i++, j--) {
        double t = U[i];
        U[i] = -U[j];
        U[j] = -t;
    }
    for (int i = 0, j = n - 1; i < j; i++, j--)
        for (int c = 0; c < dim; c++) {
            double t = P[(size_t)i * dim + c];
            P[(size_t)i * dim + c] = P[(size_t)j * dim + c];
            P[(size_t)j * dim + c] = t;
        }
}

static int is_clamped(const double *U, int n, int p)
{
    for (int k = 1; k <= p; k++)
        if (U[k] != U[0] || U[n + p - k] != U[n + p])
            return 0;
    return 1;
}

/* Clamps both ends of a strip whose knot vector is non-decreasing with a non-empty domain.
 * *U and *P are reallocated to hold the 2 p extra knots and points insertion may add. */
static cb_status clamp_strip(double **U, double **P, int *n, int p, int dim, step_file *f)
{
    double *U2 = realloc(*U, (size_t)(*n + 3 * p + 1) * sizeof *U2);
    if (U2)
        *U = U2;
    double *P2 = U2 ? realloc(*P, (size_t)(*n + 2 * p) * dim * sizeof *P2) : NULL;
    if (P2)
        *P = P2;
    if (!U2 || !P2)
        return cb_error_set(f->err, CB_ERR_NOMEM, "%s: no memory to clamp a B-spline", f->path);
    clamp_start(*U, *P, n, p, dim);
    reverse_strip(*U, *P, *n, p, dim);
    clamp_start(*U, *P, n, p, dim);
    reverse_strip(*U, *P, *n, p, dim);
    return CB_OK;
}

/* 1 when U (n + p + 1 knots) can be clamped: non-decreasing, non-empty domain. Anything else
 * is left to cb_nurbs_*_make to reject with its own message. */
static int clampable(const double *U, int n_knots, int n, int p)
{
    if (n_knots != n + p + 1 || n < p + 1)
        return 0;
    for (int k = 1; k < n_knots; k++)
        if (!(U[k] >= U[k - 1]))
            return 0;
    return U[n] > U[p];
}

/* ---------------------------------------------------------------- control points ----------- */

/* Reads n point references into pts (3 doubles each) and, if weights is given, n weights. */
static cb_status read_points(double *pts, step_file *f, const step_rec *r, const step_node *list,
                             int dim)
{
    const step_node *x = list + 1;
    for (int i = 0; i < list->n; i++, x = step_next(x)) {
        const step_rec *q;
        char what[48];
        snprintf(what, sizeof what, "control point %d", i + 1);
        cb_status st = step_get_ref(f, r, x, what, &q);
        if (!st)
            st = step_point(f, q, dim, pts + 3 * (size_t)i);
        if (st)
            return st;
    }
    return CB_OK;
}

static cb_status read_reals(double *w, step_file *f, const step_rec *r, const step_node *list,
                            const char *what)
{
    const step_node *x = list + 1;
    for (int i = 0; i < list->n; i++, x = step_next(x)) {
        cb_status st = step_get_real(f, r, x, what, &w[i]);
        if (st)
            return st;
    }
    return CB_OK;
}

static int any_weight_not_one(const double *w, long n)
{
    for (long i = 0; w && i < n; i++)
        if (w[i] != 1.0)
            return 1;
    return 0;
}

/* ---------------------------------------------------------------- curves ------------------- */

cb_status step_bspline_curve(step_file *f, const step_rec *r, int dim, cb_nurbs_curve_t out)
{
    bs_view v;
    cb_status st = bs_view_of(&v, f, r, 0);
    long deg;
    if (st || (st = step_get_int(f, r, v.deg[0], "degree", 1, CB_MAX_DEGREE, &deg)) ||
        (st = step_get_list(f, r, v.points, "control points", 2, 1 << 24)))
        return st;
    int n = v.points->n;
    if (v.weights && (st = step_get_list(f, r, v.weights, "weights", n, n)))
        return st;
    double *U = NULL, *pts = malloc((size_t)n * 3 * sizeof *pts), *w = NULL, *cw = NULL;
    int nk = 0;
    if (!pts || (v.weights && !(w = malloc((size_t)n * sizeof *w)))) {
        st = cb_error_set(f->err, CB_ERR_NOMEM, "%s: no memory for %d control points", f->path, n);
        goto done;
    }
    if ((st = read_points(pts, f, r, v.points, dim)) ||
        (w && (st = read_reals(w, f, r, v.weights, "weight"))) ||
        (st = v.form == BS_KNOTS_EXPLICIT
                  ? expand_knots(&U, &nk, f, r, v.mults[0], v.knots[0], (int)deg, "")
                  : implied_knots(&U, &nk, f, r, v.form, n, (int)deg, "")))
        goto done;
    int p = (int)deg;
    if (clampable(U, nk, n, p) && !is_clamped(U, n, p)) {
        if (!(cw = malloc((size_t)n * 4 * sizeof *cw))) {
            st = cb_error_set(f->err, CB_ERR_NOMEM, "%s: no memory", f->path);
            goto done;
        }
        for (int i = 0; i < n; i++) {
            double wi = w ? w[i] : 1.0;
            for (int c = 0; c < 3; c++)
                cw[4 * i + c] = wi * pts[3 * i + c];
            cw[4 * i + 3] = wi;
        }
        if ((st = clamp_strip(&U, &cw, &n, p, 4, f)))
            goto done;
        nk = n + p + 1;
        double *pts2 = realloc(pts, (size_t)n * 3 * sizeof *pts);
        double *w2 = pts2 && w ? realloc(w, (size_t)n * sizeof *w) : w;
        if (pts2)
            pts = pts2;
        if (w2)
            w = w2;
        if (!pts2 || (w && !w2)) {
            st = cb_error_set(f->err, CB_ERR_NOMEM, "%s: no memory", f->path);
            goto done;
        }
        for (int i = 0; i < n; i++) {
            for (int c = 0; c < 3; c++)
                pts[3 * i + c] = cw[4 * i + c] / cw[4 * i + 3];
            if (w)
                w[i] = cw[4 * i + 3];
        }
    }
    st = cb_nurbs_curve_make(out, p, U, nk, pts, any_weight_not_one(w, n) ? w : NULL, n, f->err);
    if (st)
        step_fail_prefix(f, r, f->err);
done:
    free(U);
    free(pts);
    free(w);
    free(cw);
    return st;
}

/* ---------------------------------------------------------------- surfaces ----------------- */

/* Checks that a list of rows is a rectangular n_u x n_v array; rows of what. */
static cb_status check_grid(step_file *f, const step_rec *r, const step_node *grid,
                            const char *what, int *n_u, int *n_v)
{
    cb_status st = step_get_list(f, r, grid, what, 2, 1 << 24);
    if (st)
        return st;
    const step_node *row = grid + 1;
    for (int i = 0; i < grid->n; i++, row = step_next(row)) {
        char w[64];
        snprintf(w, sizeof w, "%s row %d", what, i + 1);
        int want = i ? *n_v : 2;
        if ((st = step_get_list(f, r, row, w, want, i ? want : 1 << 24)))
            return st;
        if (!i)
            *n_v = row->n;
    }
    *n_u = grid->n;
    return CB_OK;
}

/* Homogeneous points of the n_u x n_v net (u outer), transposed when along v. */
static void to_strip(double *cw, const double *pts, const double *w, int n_u, int n_v,
                     int transpose)
{
    for (int i = 0; i < n_u; i++)
        for (int j = 0; j < n_v; j++) {
            long s = (long)i * n_v + j, d = transpose ? (long)j * n_u + i : s;
            double wi = w ? w[s] : 1.0;
            for (int c = 0; c < 3; c++)
                cw[4 * d + c] = wi * pts[3 * s + c];
            cw[4 * d + 3] = wi;
        }
}

/* Clamps the net along one direction (dir 0: u) in place of pts / w, n_u, n_v, U. */
static cb_status clamp_net(double **pts, double **w, int *n_u, int *n_v, double **U, int p, int dir,
                           step_file *f)
{
    int rows = dir ? *n_v : *n_u, cols = dir ? *n_u : *n_v;
    double *cw = malloc((size_t)rows * cols * 4 * sizeof *cw);
    if (!cw)
        return cb_error_set(f->err, CB_ERR_NOMEM, "%s: no memory", f->path);
    to_strip(cw, *pts, *w, *n_u, *n_v, dir);
    cb_status st = clamp_strip(U, &cw, &rows, p, 4 * cols, f);
    if (st) {
        free(cw);
        return st;
    }
    int nu = dir ? cols : rows, nv = dir ? rows : cols;
    double *pts2 = realloc(*pts, (size_t)nu * nv * 3 * sizeof *pts2);
    if (pts2)
        *pts = pts2;
    double *w2 = pts2 && *w ? realloc(*w, (size_t)nu * nv * sizeof *w2) : *w;
    if (w2)
        *w = w2;
    if (!pts2 || (*w && !w2)) {
        free(cw);
        return cb_error_set(f->err, CB_ERR_NOMEM, "%s: no memory", f->path);
    }
    for (int i = 0; i < nu; i++)
        for (int j = 0; j < nv; j++) {
            const double *q = cw + 4 * (dir ? (long)j * nu + i : (long)i * nv + j);
            long d = (long)i * nv + j;
            for (int c = 0; c < 3; c++)
                (*pts)[3 * d + c] = q[c] / q[3];
            if (*w)
                (*w)[d] = q[3];
        }
    *n_u = nu;
    *n_v = nv;
    free(cw);
    return CB_OK;
}

cb_status step_bspline_surface(step_file *f, const step_rec *r, cb_nurbs_surface_t out)
{
    bs_view v;
    long deg[2];
    int n_u, n_v, wu, wv;
    cb_status st = bs_view_of(&v, f, r, 1);
    if (st || (st = step_get_int(f, r, v.deg[0], "u degree", 1, CB_MAX_DEGREE, &deg[0])) ||
        (st = step_get_int(f, r, v.deg[1], "v degree", 1, CB_MAX_DEGREE, &deg[1])) ||
        (st = check_grid(f, r, v.points, "control points", &n_u, &n_v)))
        return st;
    if (v.weights) {
        if ((st = check_grid(f, r, v.weights, "weights", &wu, &wv)))
            return st;
        if (wu != n_u || wv != n_v)
            return step_fail(f, r, v.weights, CB_ERR_INVALID,
                             "%d x %d weights for %d x %d control points", wu, wv, n_u, n_v);
    }
    if ((long)n_u * n_v > (1L << 26))
        return step_fail(f, r, v.points, CB_ERR_INVALID, "%d x %d control points is too many", n_u,
                         n_v);
    size_t count = (size_t)n_u * n_v;
    double *U[2] = {NULL, NULL}, *pts = malloc(count * 3 * sizeof *pts), *w = NULL;
    int nk[2] = {0, 0};
    if (!pts || (v.weights && !(w = malloc(count * sizeof *w)))) {
        st = cb_error_set(f->err, CB_ERR_NOMEM, "%s: no memory for %zu control points", f->path,
                          count);
        goto done;
    }
    const step_node *row = v.points + 1, *wrow = v.weights ? v.weights + 1 : NULL;
    for (int i = 0; i < n_u && !st; i++, row = step_next(row)) {
        st = read_points(pts + 3 * (size_t)i * n_v, f, r, row, 3);
        if (!st && wrow) {
            st = read_reals(w + (size_t)i * n_v, f, r, wrow, "weight");
            wrow = step_next(wrow);
        }
    }
    if (st)
        goto done;
    for (int dir = 0; dir < 2; dir++) {
        const char *name = dir ? "v " : "u ";
        st = v.form == BS_KNOTS_EXPLICIT
                 ? expand_knots(&U[dir], &nk[dir], f, r, v.mults[dir], v.knots[dir], (int)deg[dir],
                                name)
                 : implied_knots(&U[dir], &nk[dir], f, r, v.form, dir ? n_v : n_u, (int)deg[dir],
                                 name);
        if (st)
            goto done;
    }
    for (int dir = 0; dir < 2; dir++) {
        int n = dir ? n_v : n_u, p = (int)deg[dir];
        if (clampable(U[dir], nk[dir], n, p) && !is_clamped(U[dir], n, p)) {
            if ((st = clamp_net(&pts, &w, &n_u, &n_v, &U[dir], p, dir, f)))
                goto done;
            nk[dir] = (dir ? n_v : n_u) + p + 1;
        }
    }
    st = cb_nurbs_surface_make(out, (int)deg[0], (int)deg[1], U[0], nk[0], U[1], nk[1], pts,
                               any_weight_not_one(w, (long)n_u * n_v) ? w : NULL, n_u, n_v, f->err);
    if (st)
        step_fail_prefix(f, r, f->err);
done:
    free(U[0]);
    free(U[1]);
    free(pts);
    free(w);
    return st;
}
