/* spline_iv.c — interval arithmetic, polynomial Bezier patches and certified roots of a
 * patch's iso-curve against another patch (see ssi/spline.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ssi/spline.h"

static int iv_has0(_cb_iv a)
{
    return a.lo <= 0 && a.hi >= 0;
}

static double iv_mid(_cb_iv a)
{
    return 0.5 * a.lo + 0.5 * a.hi;
}

static double iv_w(_cb_iv a)
{
    return a.hi - a.lo;
}

/* ---------------------------------------------------------------- patches ------------------ */

cb_status _cb_ssi_bez_set(_cb_ssi_bez *b, const cb_nurbs_surface_struct *s, cb_error *err)
{
    memset(b, 0, sizeof(*b));
    if (s->n_u != s->deg_u + 1 || s->n_v != s->deg_v + 1 || s->deg_u < 1 || s->deg_v < 1)
        return cb_error_set(err, CB_ERR_INVALID,
                            "ssi: not a single Bezier patch of degree >= 1 (%d x %d points, "
                            "degree %d, %d)",
                            s->n_u, s->n_v, s->deg_u, s->deg_v);
    double w0 = s->cw[3];
    int np = s->n_u * s->n_v;
    for (int k = 0; k < np; k++) {
        if (!(s->cw[4 * k + 3] > 0))
            return cb_error_set(err, CB_ERR_UNSUPPORTED,
                                "ssi: weight %g <= 0 at control point %d: the subdivision route "
                                "needs positive weights (convex hulls)",
                                s->cw[4 * k + 3], k);
        if (s->cw[4 * k + 3] != w0)
            b->rat = 1;
    }
    b->m = s->deg_u;
    b->n = s->deg_v;
    b->dim = 3 + b->rat;
    b->pts = malloc((size_t)(b->dim * np) * sizeof(double));
    if (!b->pts)
        return cb_error_set(err, CB_ERR_NOMEM, "ssi: no memory for a Bezier patch");
    for (int k = 0; k < np; k++) {
        if (b->rat)
            memcpy(b->pts + 4 * k, s->cw + 4 * k, 4 * sizeof(double));
        else
            for (int q = 0; q < 3; q++)
                b->pts[3 * k + q] = s->cw[4 * k + q] / w0;
    }
    cb_nurbs_surface_domain(s, b->dom);
    return CB_OK;
}

void _cb_ssi_bez_clear(_cb_ssi_bez *b)
{
    free(b->pts);
    memset(b, 0, sizeof(*b));
}

/* de Casteljau on d + 1 points of dim values c (destroyed): value at t and derivative. */
static void dc(double *val, double *der, double *c, int d, double t, int dim)
{
    for (int r = 1; r < d; r++)
        for (int i = 0; i + r <= d; i++)
            for (int q = 0; q < dim; q++)
                c[dim * i + q] += t * (c[dim * i + dim + q] - c[dim * i + q]);
    for (int q = 0; q < dim; q++) {
        double diff = c[dim + q] - c[q];
        val[q] = c[q] + t * diff;
        if (der)
            der[q] = d * diff;
    }
}

void _cb_ssi_bez_eval(double X[3], double Xu[3], double Xv[3], const _cb_ssi_bez *b, double u,
                      double v)
{
    int D = b->dim;
    double row[4 * (CB_MAX_DEGREE + 1)], cu[4 * (CB_MAX_DEGREE + 1)], cv[4 * (CB_MAX_DEGREE + 1)];
    double P[4], Pu[4], Pv[4], dummy[4];
    for (int i = 0; i <= b->m; i++) {
        memcpy(row, b->pts + D * i * (b->n + 1), (size_t)(D * (b->n + 1)) * sizeof(double));
        dc(cu + D * i, cv + D * i, row, b->n, v, D);
    }
    dc(P, Pu, cu, b->m, u, D);
    dc(Pv, dummy, cv, b->m, u, D);
    if (!b->rat) {
        memcpy(X, P, 3 * sizeof(double));
        memcpy(Xu, Pu, 3 * sizeof(double));
        memcpy(Xv, Pv, 3 * sizeof(double));
        return;
    }
    for (int q = 0; q < 3; q++) {
        X[q] = P[q] / P[3];
        Xu[q] = (Pu[q] - X[q] * Pu[3]) / P[3];
        Xv[q] = (Pv[q] - X[q] * Pv[3]) / P[3];
    }
}

/* t x for a point t: _cb_iv_mul's result (its other two products repeat these two), at half
 * the products: the boundary-root searches evaluate most patches at points. */
static _cb_iv mul_pt(double t, _cb_iv x)
{
    double p0 = t * x.lo, p1 = t * x.hi;
    _cb_iv r = {_cb_iv_dn(p0 < p1 ? p0 : p1), _cb_iv_up(p0 < p1 ? p1 : p0)};
    return r;
}

/* Interval de Casteljau of the d + 1 points c (dim values each, overwritten) at t: val, and der
 * the derivative.
 * At a point t the steps take the convex form (1 - t) a + t b, which carries the widths of a and
 * b over unchanged. The difference form a + t (b - a) widens by 1 + 2 t per step (a and b each
 * enter twice), 3^8 round-offs through a bicubic-by-quintic patch's two directions: the
 * patches of bench_ssi_corpus crossing_loops/param/1, coordinates below 1.6, came out 1e-12
 * wide at a point, the Krawczyk operator's centre term M F(c) 2e-8 wide where the surfaces
 * nearly touch (|M| 2e4), and boundary roots there went unproved down to the search's floor
 * (boxes 1e-13 wide), half of the searches failing. 1 - t is exact for t in [1/2, 1]
 * (Sterbenz) and often below; where it is, it multiplies as a point.
 * Over an interval t the difference form is kept: it is tight in t (a wide t multiplies only
 * b - a), where the convex form multiplies |a| + |b| by t's width. */
static void dc_iv(_cb_iv *val, _cb_iv *der, _cb_iv *c, int d, _cb_iv t, int dim)
{
    if (t.lo == t.hi) {
        const double s = 1 - t.lo;
        const int exact = t.lo >= 0 && t.lo <= 1 && 1 - s == t.lo;
        const _cb_iv omt = _cb_iv_sub(_cb_iv_pt(1), t);
        for (int r = 1; r <= d; r++)
            for (int i = 0; i + r <= d; i++)
                for (int q = 0; q < dim; q++) {
                    _cb_iv a = c[dim * i + q], b = c[dim * i + dim + q];
                    _cb_iv v = _cb_iv_add(exact ? mul_pt(s, a) : _cb_iv_mul(omt, a),
                                          mul_pt(t.lo, b));
                    if (r < d)
                        c[dim * i + q] = v;
                    else
                        val[q] = v;
                }
    } else {
        for (int r = 1; r <= d; r++)
            for (int i = 0; i + r <= d; i++)
                for (int q = 0; q < dim; q++) {
                    _cb_iv a = c[dim * i + q], b = c[dim * i + dim + q];
                    _cb_iv v = _cb_iv_add(a, _cb_iv_mul(t, _cb_iv_sub(b, a)));
                    if (r < d)
                        c[dim * i + q] = v;
                    else
                        val[q] = v;
                }
    }
    if (d == 0)
        for (int q = 0; q < dim; q++)
            val[q] = c[q];
    for (int q = 0; q < dim && der; q++)
        der[q] = d == 0 ? _cb_iv_pt(0)
                        : _cb_iv_mul(_cb_iv_pt((double)d), _cb_iv_sub(c[dim + q], c[q]));
}

_cb_iv _cb_iv_div(_cb_iv x, _cb_iv w)
{
    if (!(w.lo > 0)) {
        _cb_iv all = {-HUGE_VAL, HUGE_VAL};
        return all;
    }
    double q0 = x.lo / w.lo, q1 = x.lo / w.hi, q2 = x.hi / w.lo, q3 = x.hi / w.hi;
    _cb_iv r = {_cb_iv_dn(fmin(fmin(q0, q1), fmin(q2, q3))),
                _cb_iv_up(fmax(fmax(q0, q1), fmax(q2, q3)))};
    return r;
}

void _cb_ssi_net_eucl(_cb_iv *out, const _cb_iv *net, int np, int dim)
{
    for (int k = 0; k < np; k++)
        for (int q = 0; q < 3; q++)
            out[3 * k + q] = dim == 4 ? _cb_iv_div(net[4 * k + q], net[4 * k + 3])
                                      : net[3 * k + q];
}

void _cb_ssi_bez_eval_iv(_cb_iv X[3], _cb_iv Xu[3], _cb_iv Xv[3], const _cb_ssi_bez *b, _cb_iv u,
                         _cb_iv v)
{
    int D = b->dim;
    _cb_iv row[4 * (CB_MAX_DEGREE + 1)], cu[4 * (CB_MAX_DEGREE + 1)], cv[4 * (CB_MAX_DEGREE + 1)];
    _cb_iv P[4], Pu[4], Pv[4];
    for (int i = 0; i <= b->m; i++) {
        for (int k = 0; k < D * (b->n + 1); k++)
            row[k] = _cb_iv_pt(b->pts[D * i * (b->n + 1) + k]);
        dc_iv(cu + D * i, cv + D * i, row, b->n, v, D);
    }
    dc_iv(P, Pu, cu, b->m, u, D);
    dc_iv(Pv, NULL, cv, b->m, u, D);
    if (!b->rat) {
        memcpy(X, P, 3 * sizeof(_cb_iv));
        memcpy(Xu, Pu, 3 * sizeof(_cb_iv));
        memcpy(Xv, Pv, 3 * sizeof(_cb_iv));
        return;
    }
    /* Over [0,1]^2 the weight is a convex combination of the control weights: the interval
     * de Casteljau enclosure (widened by the dependency on u and v) is cut to their range, which
     * keeps it away from 0. Outside, an enclosure through 0 divides to the whole line. */
    if (u.lo >= 0 && u.hi <= 1 && v.lo >= 0 && v.hi <= 1) {
        double wl = HUGE_VAL, wh = -HUGE_VAL;
        for (int k = 0; k < (b->m + 1) * (b->n + 1); k++) {
            wl = fmin(wl, b->pts[4 * k + 3]);
            wh = fmax(wh, b->pts[4 * k + 3]);
        }
        P[3].lo = fmax(P[3].lo, wl);
        P[3].hi = fmin(P[3].hi, wh);
    }
    for (int q = 0; q < 3; q++) {
        X[q] = _cb_iv_div(P[q], P[3]);
        Xu[q] = _cb_iv_div(_cb_iv_sub(Pu[q], _cb_iv_mul(X[q], Pu[3])), P[3]);
        Xv[q] = _cb_iv_div(_cb_iv_sub(Pv[q], _cb_iv_mul(X[q], Pv[3])), P[3]);
    }
}

void _cb_ssi_split_iv_at(_cb_iv *lo, _cb_iv *hi, const _cb_iv *c, int d, int stride, int dim,
                         _cb_iv t)
{
    _cb_iv w[4 * (CB_MAX_DEGREE + 1)];
    const _cb_iv omt = _cb_iv_sub(_cb_iv_pt(1), t);
    for (int k = 0; k <= d; k++)
        memcpy(w + dim * k, c + (size_t)k * stride, (size_t)dim * sizeof(_cb_iv));
    for (int r = 0; r <= d; r++) {
        memcpy(lo + (size_t)r * stride, w, (size_t)dim * sizeof(_cb_iv));
        memcpy(hi + (size_t)(d - r) * stride, w + dim * (d - r), (size_t)dim * sizeof(_cb_iv));
        for (int k = 0; k + r < d; k++)
            for (int q = 0; q < dim; q++)
                w[dim * k + q] = _cb_iv_add(_cb_iv_mul(omt, w[dim * k + q]),
                                            _cb_iv_mul(t, w[dim * k + dim + q]));
    }
}

/* The fraction (x - w0) / (w1 - w0) as an interval within [0, 1]. */
static _cb_iv fraction(double x, double w0, double w1)
{
    _cb_iv t = _cb_iv_div(_cb_iv_sub(_cb_iv_pt(x), _cb_iv_pt(w0)),
                          _cb_iv_sub(_cb_iv_pt(w1), _cb_iv_pt(w0)));
    t.lo = fmax(t.lo, 0);
    t.hi = fmin(t.hi, 1);
    return t;
}

void _cb_ssi_restrict_iv(_cb_iv *c, int d, int dim, double w0, double w1, double a, double b)
{
    _cb_iv lo[4 * (CB_MAX_DEGREE + 1)], hi[4 * (CB_MAX_DEGREE + 1)];
    size_t sz = (size_t)(dim * (d + 1)) * sizeof(_cb_iv);
    if (b < w1) {
        _cb_ssi_split_iv_at(lo, hi, c, d, dim, dim, fraction(b, w0, w1));
        memcpy(c, lo, sz);
    }
    if (a > w0) {
        _cb_ssi_split_iv_at(lo, hi, c, d, dim, dim, fraction(a, w0, b));
        memcpy(c, hi, sz);
    }
}

void _cb_ssi_split_iv(_cb_iv *lo, _cb_iv *hi, const _cb_iv *c, int d, int stride, int dim)
{
    _cb_iv w[4 * (CB_MAX_DEGREE + 1)];
    const _cb_iv half = {0.5, 0.5};
    for (int k = 0; k <= d; k++)
        memcpy(w + dim * k, c + (size_t)k * stride, (size_t)dim * sizeof(_cb_iv));
    for (int r = 0; r <= d; r++) {
        memcpy(lo + (size_t)r * stride, w, (size_t)dim * sizeof(_cb_iv));
        memcpy(hi + (size_t)(d - r) * stride, w + dim * (d - r), (size_t)dim * sizeof(_cb_iv));
        for (int k = 0; k + r < d; k++)
            for (int q = 0; q < dim; q++)
                w[dim * k + q] =
                    _cb_iv_mul(half, _cb_iv_add(w[dim * k + q], w[dim * k + dim + q]));
    }
}

/* ---------------------------------------------------------------- edge/surface roots ------- */

typedef struct {
    const _cb_ssi_bez *C, *S;
    int dir;
    double c;
} edge_sys;

/* F = E(w) - S(a, b) and its Jacobian [E_w, -S_a, -S_b] over the box y. */
static void sys_iv(_cb_iv F[3], _cb_iv J[3][3], const edge_sys *e, const _cb_iv y[3])
{
    _cb_iv E[3], Eu[3], Ev[3], S[3], Sa[3], Sb[3];
    if (e->dir == 0)
        _cb_ssi_bez_eval_iv(E, Eu, Ev, e->C, _cb_iv_pt(e->c), y[0]);
    else
        _cb_ssi_bez_eval_iv(E, Eu, Ev, e->C, y[0], _cb_iv_pt(e->c));
    _cb_ssi_bez_eval_iv(S, Sa, Sb, e->S, y[1], y[2]);
    for (int q = 0; q < 3; q++) {
        F[q] = _cb_iv_sub(E[q], S[q]);
        if (J) {
            J[q][0] = e->dir == 0 ? Ev[q] : Eu[q];
            J[q][1] = _cb_iv_sub(_cb_iv_pt(0), Sa[q]);
            J[q][2] = _cb_iv_sub(_cb_iv_pt(0), Sb[q]);
        }
    }
}

static void sys_pt(double F[3], double J[3][3], const edge_sys *e, const double y[3])
{
    double E[3], Eu[3], Ev[3], S[3], Sa[3], Sb[3];
    if (e->dir == 0)
        _cb_ssi_bez_eval(E, Eu, Ev, e->C, e->c, y[0]);
    else
        _cb_ssi_bez_eval(E, Eu, Ev, e->C, y[0], e->c);
    _cb_ssi_bez_eval(S, Sa, Sb, e->S, y[1], y[2]);
    for (int q = 0; q < 3; q++) {
        F[q] = E[q] - S[q];
        J[q][0] = e->dir == 0 ? Ev[q] : Eu[q];
        J[q][1] = -Sa[q];
        J[q][2] = -Sb[q];
    }
}

/* Inverse of a 3 x 3 matrix; 0 when (nearly) singular. */
static int inv3(double M[3][3], const double A[3][3])
{
    double c[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
            c[i][j] = A[i1][j1] * A[i2][j2] - A[i1][j2] * A[i2][j1];
        }
    double det = A[0][0] * c[0][0] + A[0][1] * c[0][1] + A[0][2] * c[0][2];
    double scale = 0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            scale = fmax(scale, fabs(A[i][j]));
    if (!(fabs(det) > 1e-14 * scale * scale * scale))
        return 0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            M[i][j] = c[j][i] / det;
    return 1;
}

/* Newton from y (at most iters steps); 1 when it converged. */
static int newton3(double y[3], const edge_sys *e, int iters)
{
    for (int it = 0; it < iters; it++) {
        double F[3], J[3][3], M[3][3];
        sys_pt(F, J, e, y);
        if (!inv3(M, J))
            return 0;
        double step = 0;
        for (int i = 0; i < 3; i++) {
            double d = M[i][0] * F[0] + M[i][1] * F[1] + M[i][2] * F[2];
            y[i] -= d;
            step = fmax(step, fabs(d));
        }
        if (!isfinite(step) || step > 10)
            return 0;
        if (step < 1e-15)
            return 1;
    }
    return 1;
}

/* Krawczyk operator of the box Y about c: 1 when K is inside the interior of Y (one simple
 * root in Y, inside K), -1 when K misses Y (no root in Y), 0 otherwise. */
static int krawczyk(_cb_iv K[3], const edge_sys *e, const _cb_iv Y[3], const double c[3])
{
    _cb_iv FY[3], JY[3][3], Fc[3], cc[3];
    sys_iv(FY, JY, e, Y);
    for (int i = 0; i < 3; i++)
        cc[i] = _cb_iv_pt(c[i]);
    sys_iv(Fc, NULL, e, cc);
    double Jm[3][3], M[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            Jm[i][j] = iv_mid(JY[i][j]);
    if (!inv3(M, Jm))
        return 0;
    int inside = 1, miss = 0;
    for (int i = 0; i < 3; i++) {
        _cb_iv k = _cb_iv_pt(c[i]);
        for (int j = 0; j < 3; j++)
            k = _cb_iv_sub(k, _cb_iv_mul(_cb_iv_pt(M[i][j]), Fc[j]));
        for (int j = 0; j < 3; j++) {
            _cb_iv a = _cb_iv_pt(i == j ? 1 : 0);
            for (int l = 0; l < 3; l++)
                a = _cb_iv_sub(a, _cb_iv_mul(_cb_iv_pt(M[i][l]), JY[l][j]));
            k = _cb_iv_add(k, _cb_iv_mul(a, _cb_iv_sub(Y[j], _cb_iv_pt(c[j]))));
        }
        K[i] = k;
        if (!(k.lo > Y[i].lo && k.hi < Y[i].hi))
            inside = 0;
        if (k.hi < Y[i].lo || k.lo > Y[i].hi)
            miss = 1;
    }
    return miss ? -1 : inside;
}

/* 1 when 0 is outside the enclosure of F over B (natural or mean value form). */
static int excluded(const edge_sys *e, const _cb_iv B[3])
{
    _cb_iv F[3], J[3][3], Fc[3], cc[3];
    sys_iv(F, J, e, B);
    if (!iv_has0(F[0]) || !iv_has0(F[1]) || !iv_has0(F[2]))
        return 1;
    double c[3];
    for (int i = 0; i < 3; i++) {
        c[i] = iv_mid(B[i]);
        cc[i] = _cb_iv_pt(c[i]);
    }
    sys_iv(Fc, NULL, e, cc);
    for (int q = 0; q < 3; q++) {
        _cb_iv m = Fc[q];
        for (int j = 0; j < 3; j++)
            m = _cb_iv_add(m, _cb_iv_mul(J[q][j], _cb_iv_sub(B[j], _cb_iv_pt(c[j]))));
        if (!iv_has0(m))
            return 1;
    }
    return 0;
}

static int iv_inside(_cb_iv a, _cb_iv b)
{
    return a.lo >= b.lo && a.hi <= b.hi;
}

static int iv_inside_strict(_cb_iv a, _cb_iv b)
{
    return a.lo > b.lo && a.hi < b.hi;
}

static int iv_meets(_cb_iv a, _cb_iv b)
{
    return a.lo <= b.hi && b.lo <= a.hi;
}

typedef struct {
    _cb_iv Y[3], K[3];
} found;

/* A search box with the control points of the curve and surface pieces over it. */
typedef struct {
    _cb_iv B[3];
    _cb_iv *cn, *sn;
} sbox;

static void hull(double lo[3], double hi[3], const _cb_iv *net, int np)
{
    for (int q = 0; q < 3; q++) {
        lo[q] = HUGE_VAL;
        hi[q] = -HUGE_VAL;
    }
    for (int k = 0; k < np; k++)
        for (int q = 0; q < 3; q++) {
            lo[q] = fmin(lo[q], net[3 * k + q].lo);
            hi[q] = fmax(hi[q], net[3 * k + q].hi);
        }
}

/* Range of d . p over the enclosed points (rounding covered by a relative margin). */
static void project(double r[2], const double d[3], const _cb_iv *net, int np)
{
    double lo = HUGE_VAL, hi = -HUGE_VAL, mag = 0;
    for (int k = 0; k < np; k++) {
        double l = 0, h = 0;
        for (int q = 0; q < 3; q++) {
            const _cb_iv x = net[3 * k + q];
            l += d[q] >= 0 ? d[q] * x.lo : d[q] * x.hi;
            h += d[q] >= 0 ? d[q] * x.hi : d[q] * x.lo;
            mag = fmax(mag, fabs(d[q]) * fmax(fabs(x.lo), fabs(x.hi)));
        }
        lo = fmin(lo, l);
        hi = fmax(hi, h);
    }
    r[0] = lo - 1e-14 * mag;
    r[1] = hi + 1e-14 * mag;
}

static void sub3(double r[3], const _cb_iv *a, const _cb_iv *b)
{
    for (int q = 0; q < 3; q++)
        r[q] = (a[q].lo + a[q].hi) * 0.5 - (b[q].lo + b[q].hi) * 0.5;
}

static void cross3(double c[3], const double a[3], const double b[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* 1 when the hulls of the curve piece (nc points) and the surface piece (m, n) are proved
 * apart along the world axes, the surface's corner normal or its in-plane directions
 * (Euclidean nets). */
static int hulls_apart_e(const _cb_iv *cn, int nc, const _cb_iv *sn, int m, int n)
{
    double cl[3], ch[3], sl[3], sh[3];
    hull(cl, ch, cn, nc);
    hull(sl, sh, sn, (m + 1) * (n + 1));
    for (int q = 0; q < 3; q++)
        if (ch[q] < sl[q] || sh[q] < cl[q])
            return 1;
    double du[3], dv[3], nn[3], ax[5][3];
    sub3(du, sn + 3 * (m * (n + 1)), sn);
    sub3(dv, sn + 3 * n, sn);
    cross3(nn, du, dv);
    memcpy(ax[0], nn, sizeof nn);
    memcpy(ax[1], du, sizeof du);
    memcpy(ax[2], dv, sizeof dv);
    cross3(ax[3], nn, du);
    cross3(ax[4], nn, dv);
    for (int x = 0; x < 5; x++) {
        double rc[2], rs[2];
        project(rc, ax[x], cn, nc);
        project(rs, ax[x], sn, (m + 1) * (n + 1));
        if (rc[1] < rs[0] || rs[1] < rc[0])
            return 1;
    }
    return 0;
}

/* The same for nets of dc (curve) and ds (surface) values per point; work holds
 * 3 (nc + (m + 1)(n + 1)) intervals. */
static int hulls_apart(const _cb_iv *cn, int nc, int dcv, const _cb_iv *sn, int m, int n, int dsv,
                       _cb_iv *work)
{
    if (dcv == 3 && dsv == 3)
        return hulls_apart_e(cn, nc, sn, m, n);
    _cb_ssi_net_eucl(work, cn, nc, dcv);
    _cb_ssi_net_eucl(work + 3 * nc, sn, (m + 1) * (n + 1), dsv);
    return hulls_apart_e(work, nc, work + 3 * nc, m, n);
}

int _cb_ssi_edge_roots(_cb_ssi_edge_root *roots, int cap, int *n, const _cb_ssi_bez *C, int dir,
                       double c, double w0, double w1, const _cb_iv *cnet, const _cb_ssi_bez *S,
                       const double box[4], const _cb_iv *snet, int budget, long *spent)
{
    edge_sys e = {C, S, dir, c};
    _cb_iv D[3] = {{w0, w1}, {box[0], box[1]}, {box[2], box[3]}};
    const double minw = 1e-13;
    int dc_ = dir == 0 ? C->n : C->m, nc = dc_ + 1, m = S->m, ns = S->n, np = (m + 1) * (ns + 1);
    enum { MAXSTACK = 200, MAXFOUND = 32 };
    sbox *stack = malloc(MAXSTACK * sizeof(sbox));
    const int Dc = C->dim, Ds = S->dim;
    const size_t per = (size_t)(Dc * nc + Ds * np);
    _cb_iv *pool = malloc((size_t)MAXSTACK * per * sizeof(_cb_iv));
    _cb_iv *tmp = malloc(per * sizeof(_cb_iv));
    _cb_iv *hwork = malloc((size_t)(3 * (nc + np)) * sizeof(_cb_iv));
    if (!stack || !pool || !tmp || !hwork) {
        /* Out of memory: the roots are not known, which the caller treats as ambiguous and
         * reports the pair uncertified rather than guessing. */
        free(stack);
        free(pool);
        free(tmp);
        free(hwork);
        return 0;
    }
    for (int k = 0; k < MAXSTACK; k++) {
        stack[k].cn = pool + (size_t)k * per;
        stack[k].sn = stack[k].cn + Dc * nc;
    }
    found fd[MAXFOUND];
    int sp = 0, nf = 0, ok = 1, work = 0;
    memcpy(stack[0].B, D, sizeof D);
    memcpy(stack[0].cn, cnet, (size_t)(Dc * nc) * sizeof(_cb_iv));
    memcpy(stack[0].sn, snet, (size_t)(Ds * np) * sizeof(_cb_iv));
    sp = 1;
    double dw = fmax(w1 - w0, fmax(box[1] - box[0], box[3] - box[2]));
    while (sp > 0 && ok) {
        sbox *top = stack + --sp;
        _cb_iv B[3];
        memcpy(B, top->B, sizeof B);
        if (++work > budget) {
            ok = 0;
            break;
        }
        if (hulls_apart(top->cn, nc, Dc, top->sn, m, ns, Ds, hwork))
            continue;
        double bw = fmax(iv_w(B[0]), fmax(iv_w(B[1]), iv_w(B[2])));
        if (bw <= dw / 4) {
            if (excluded(&e, B))
                continue;
            /* Try to prove one root in a box Y holding B: centred on a Newton point when
             * Newton stays near B, else on B's centre. */
            double y[3], mid[3];
            for (int i = 0; i < 3; i++)
                y[i] = mid[i] = iv_mid(B[i]);
            int conv = newton3(y, &e, 8);
            for (int i = 0; i < 3 && conv; i++)
                if (fabs(y[i] - mid[i]) > iv_w(B[i]))
                    conv = 0;
            if (!conv)
                memcpy(y, mid, sizeof y);
            _cb_iv Y[3], K[3];
            for (int i = 0; i < 3; i++) {
                double pad = 0.05 * iv_w(B[i]) + 1e-15;
                Y[i].lo = fmin(B[i].lo, y[i]) - pad;
                Y[i].hi = fmax(B[i].hi, y[i]) + pad;
            }
            int kr = krawczyk(K, &e, Y, y);
            if (kr < 0)
                continue;
            if (kr > 0) {
                int in_d = 1, out_d = 0;
                for (int i = 0; i < 3; i++) {
                    in_d &= iv_inside_strict(K[i], D[i]);
                    out_d |= !iv_meets(K[i], D[i]);
                }
                if (out_d)
                    continue;
                if (!in_d) {
                    ok = 0;
                    break;
                }
                int dup = 0;
                for (int f = 0; f < nf && !dup && ok; f++) {
                    int a = 1, b = 1, mt = 1;
                    for (int i = 0; i < 3; i++) {
                        a &= iv_inside(K[i], fd[f].Y[i]);
                        b &= iv_inside(fd[f].K[i], Y[i]);
                        mt &= iv_meets(K[i], fd[f].K[i]);
                    }
                    if (a || b)
                        dup = 1;
                    else if (mt)
                        ok = 0;
                }
                if (dup || !ok)
                    continue;
                if (nf == MAXFOUND || *n >= cap) {
                    ok = 0;
                    break;
                }
                memcpy(fd[nf].Y, Y, sizeof Y);
                memcpy(fd[nf].K, K, sizeof K);
                nf++;
                _cb_ssi_edge_root *r = roots + (*n)++;
                double z[3];
                for (int i = 0; i < 3; i++)
                    z[i] = iv_mid(K[i]);
                newton3(z, &e, 6);
                for (int i = 0; i < 3; i++) {
                    /* The root is in K; a Newton point that left it is replaced by K's
                     * centre. */
                    r->y[i] = (z[i] >= K[i].lo && z[i] <= K[i].hi) ? z[i] : iv_mid(K[i]);
                    r->k[i] = K[i];
                }
                continue;
            }
        }
        /* Split B along its widest side, with the curve or surface piece. */
        int d = 0;
        for (int i = 1; i < 3; i++)
            if (iv_w(B[i]) > iv_w(B[d]))
                d = i;
        if (iv_w(B[d]) < minw || sp + 2 > MAXSTACK) {
            ok = 0;
            break;
        }
        double h = iv_mid(B[d]);
        sbox *lo = stack + sp, *hi = stack + sp + 1;
        /* top is at index sp (just popped): copy it aside before overwriting. */
        memcpy(tmp, top->cn, per * sizeof(_cb_iv));
        const _cb_iv *tc = tmp, *ts = tmp + Dc * nc;
        memcpy(lo->B, B, sizeof B);
        memcpy(hi->B, B, sizeof B);
        lo->B[d].hi = h;
        hi->B[d].lo = h;
        if (d == 0) {
            _cb_ssi_split_iv(lo->cn, hi->cn, tc, dc_, Dc, Dc);
            memcpy(lo->sn, ts, (size_t)(Ds * np) * sizeof(_cb_iv));
            memcpy(hi->sn, ts, (size_t)(Ds * np) * sizeof(_cb_iv));
        } else {
            memcpy(lo->cn, tc, (size_t)(Dc * nc) * sizeof(_cb_iv));
            memcpy(hi->cn, tc, (size_t)(Dc * nc) * sizeof(_cb_iv));
            if (d == 1)
                for (int j = 0; j <= ns; j++)
                    _cb_ssi_split_iv(lo->sn + Ds * j, hi->sn + Ds * j, ts + Ds * j, m,
                                     Ds * (ns + 1), Ds);
            else
                for (int i = 0; i <= m; i++)
                    _cb_ssi_split_iv(lo->sn + Ds * i * (ns + 1), hi->sn + Ds * i * (ns + 1),
                                     ts + Ds * i * (ns + 1), ns, Ds, Ds);
        }
        /* Depth first, lower half next. */
        sbox t = stack[sp];
        stack[sp] = stack[sp + 1];
        stack[sp + 1] = t;
        sp += 2;
    }
    free(hwork);
    free(tmp);
    free(pool);
    free(stack);
    *spent += work;
    return ok;
}
