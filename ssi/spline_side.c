/* spline_side.c — sides of two polynomial Bezier patches that lie on each other (see ssi/spline.h
 * _cb_ssi_coside): a curve along patch sides, where the boundary-root search of the subdivision
 * route meets a continuum of roots and cannot end (tolerance-certificates.md section 6). The
 * sides are paired by projecting their ends on each other; the pairing is then proved by the
 * Bernstein coefficients of the difference of the two sides over the common range. */
#include <math.h>
#include <string.h>

#include "brep/geom.h"
#include "ssi/spline.h"
#include "ssi/ssi_tol.h"

/* Sides paired only over a range longer than this (local parameters): shorter is a corner. */
#define MIN_RANGE 1e-9
/* A strip across a side wider than this fraction of the patch is no strip (a patch of a few
 * tol): the side is left to the usual search. */
#define MAX_STRIP 1e-3

/* Point X and derivative D along side `side` of B at w. */
static void side_eval(double X[3], double D[3], const _cb_ssi_bez *B, int side, double w)
{
    double Xu[3], Xv[3];
    double u = side == 0 ? 0 : side == 1 ? 1 : w, v = side == 2 ? 0 : side == 3 ? 1 : w;
    _cb_ssi_bez_eval(X, Xu, Xv, B, u, v);
    memcpy(D, side < 2 ? Xv : Xu, 3 * sizeof(double));
}

/* The parameter *w in [0, 1] of the point of B's side nearest X (Gauss-Newton from the nearest
 * of 17 samples), and its distance. Only chooses the pairing, which is proved afterwards. */
static double side_project(double *w, const _cb_ssi_bez *B, int side, const double X[3])
{
    double best = HUGE_VAL, bw = 0, Y[3], D[3];
    for (int k = 0; k <= 16; k++) {
        side_eval(Y, D, B, side, k / 16.0);
        double d = cb_vec3_dist(X, Y);
        if (d < best) {
            best = d;
            bw = k / 16.0;
        }
    }
    for (int it = 0; it < 40; it++) {
        side_eval(Y, D, B, side, bw);
        double g = 0, h = 0;
        for (int q = 0; q < 3; q++) {
            g += D[q] * (Y[q] - X[q]);
            h += D[q] * D[q];
        }
        if (!(h > 0))
            break;
        double nw = fmin(1, fmax(0, bw - g / h));
        int done = fabs(nw - bw) < 1e-16;
        bw = nw;
        if (done)
            break;
    }
    side_eval(Y, D, B, side, bw);
    *w = bw;
    return cb_vec3_dist(X, Y);
}

/* The side's control points as point intervals (3 per point); its degree. */
static int side_net(_cb_iv *out, const _cb_ssi_bez *B, int side)
{
    int cnt = side < 2 ? B->n + 1 : B->m + 1;
    for (int k = 0; k < cnt; k++) {
        int i = side == 0 ? 0 : side == 1 ? B->m : k, j = side == 2 ? 0 : side == 3 ? B->n : k;
        for (int q = 0; q < 3; q++)
            out[3 * k + q] = _cb_iv_pt(B->pts[3 * (i * (B->n + 1) + j) + q]);
    }
    return cnt - 1;
}

/* In place: degree d to d + 1 (d + 2 points of room). */
static void elevate(_cb_iv *c, int d)
{
    memcpy(c + 3 * (d + 1), c + 3 * d, 3 * sizeof(_cb_iv));
    for (int k = d; k >= 1; k--) {
        _cb_iv a = _cb_iv_div(_cb_iv_pt(k), _cb_iv_pt(d + 1)), b = _cb_iv_sub(_cb_iv_pt(1), a);
        for (int q = 0; q < 3; q++)
            c[3 * k + q] = _cb_iv_add(_cb_iv_mul(a, c[3 * (k - 1) + q]), _cb_iv_mul(b, c[3 * k + q]));
    }
}

/* Bound of |P's side at t0 + x (t1 - t0) - Q's side at m0 + x (m1 - m0)| over x in [0, 1]: the
 * largest Euclidean norm of the Bernstein coefficients of the difference, both sides restricted
 * to their ranges and raised to one degree. */
static double side_gap(const _cb_ssi_bez *P, int sp, const _cb_ssi_bez *Q, int sq, double t0,
                       double t1, double m0, double m1)
{
    _cb_iv a[3 * (CB_MAX_DEGREE + 2)], b[3 * (CB_MAX_DEGREE + 2)];
    int da = side_net(a, P, sp), db = side_net(b, Q, sq);
    _cb_ssi_restrict_iv(a, da, 3, 0, 1, t0, t1);
    _cb_ssi_restrict_iv(b, db, 3, 0, 1, fmin(m0, m1), fmax(m0, m1));
    if (m0 > m1)
        for (int k = 0; k < (db + 1) / 2; k++)
            for (int q = 0; q < 3; q++) {
                _cb_iv t = b[3 * k + q];
                b[3 * k + q] = b[3 * (db - k) + q];
                b[3 * (db - k) + q] = t;
            }
    for (; da < db && da < CB_MAX_DEGREE; da++)
        elevate(a, da);
    for (; db < da && db < CB_MAX_DEGREE; db++)
        elevate(b, db);
    if (da != db)
        return HUGE_VAL;
    double w = 0;
    for (int k = 0; k <= da; k++) {
        double s = 0;
        for (int q = 0; q < 3; q++) {
            _cb_iv d = _cb_iv_sub(a[3 * k + q], b[3 * k + q]);
            double m = fmax(fabs(d.lo), fabs(d.hi));
            s = _cb_iv_up(s + _cb_iv_up(m * m));
        }
        w = fmax(w, _cb_iv_up(sqrt(s)));
    }
    return isfinite(w) ? w : HUGE_VAL;
}

/* Bound of |partial of B across side `side`| over the patch: the degree times the largest
 * difference of control points in that direction. */
static double across_bound(const _cb_ssi_bez *B, int side)
{
    int m = B->m, n = B->n, u = side < 2;
    double L = 0;
    for (int i = 0; i + (u ? 1 : 0) <= m; i++)
        for (int j = 0; j + (u ? 0 : 1) <= n; j++) {
            const double *p = B->pts + 3 * (i * (n + 1) + j);
            const double *r = B->pts + 3 * ((i + u) * (n + 1) + j + !u);
            L = fmax(L, _cb_iv_up(cb_vec3_dist(p, r) * (1 + 0x1p-50)));
        }
    return (u ? m : n) * L;
}

double _cb_ssi_coside_mu(const _cb_ssi_coside *r, double t)
{
    if (t == r->t0)
        return r->m0;
    if (t == r->t1)
        return r->m1;
    return r->m0 + (t - r->t0) * ((r->m1 - r->m0) / (r->t1 - r->t0));
}

double _cb_ssi_coside_tau(const _cb_ssi_coside *r, double mu)
{
    if (mu == r->m0)
        return r->t0;
    if (mu == r->m1)
        return r->t1;
    return r->t0 + (mu - r->m0) * ((r->t1 - r->t0) / (r->m1 - r->m0));
}

int _cb_ssi_cosides_find(_cb_ssi_coside *out, int cap, const _cb_ssi_bez *P, const _cb_ssi_bez *Q,
                         double tol)
{
    if (P->rat || Q->rat || !(tol > 0))
        return 0;
    int n = 0;
    for (int sp = 0; sp < 4 && n < cap; sp++)
        for (int sq = 0; sq < 4 && n < cap; sq++) {
            /* Ends of either side near the other: (t, mu, which of them is exact). */
            double pt[4][2];
            int exact[4][2], np = 0;
            for (int e = 0; e < 2; e++) {
                double X[3], D[3], w;
                side_eval(X, D, P, sp, e);
                if (side_project(&w, Q, sq, X) <= tol) {
                    pt[np][0] = e;
                    pt[np][1] = w;
                    exact[np][0] = 1;
                    exact[np++][1] = 0;
                }
                side_eval(X, D, Q, sq, e);
                if (side_project(&w, P, sp, X) <= tol) {
                    pt[np][0] = w;
                    pt[np][1] = e;
                    exact[np][0] = 0;
                    exact[np++][1] = 1;
                }
            }
            if (np < 2)
                continue;
            /* The common range's ends: the least and the largest t, each with the exact value
             * of any end that lands on it. */
            int lo = 0, hi = 0;
            for (int k = 1; k < np; k++) {
                if (pt[k][0] < pt[lo][0])
                    lo = k;
                if (pt[k][0] > pt[hi][0])
                    hi = k;
            }
            double t[2] = {pt[lo][0], pt[hi][0]}, m[2] = {pt[lo][1], pt[hi][1]};
            for (int x = 0; x < 2; x++)
                for (int k = 0; k < np; k++)
                    if (fabs(pt[k][0] - t[x]) <= MIN_RANGE && fabs(pt[k][1] - m[x]) <= MIN_RANGE) {
                        if (exact[k][0])
                            t[x] = pt[k][0];
                        if (exact[k][1])
                            m[x] = pt[k][1];
                    }
            if (!(t[1] - t[0] > MIN_RANGE) || !(fabs(m[1] - m[0]) > MIN_RANGE))
                continue;
            /* A side collapsed to a point (a pole) is no curve: the range's ends more than tol
             * apart in 3D. */
            double X0[3], X1[3], D[3];
            side_eval(X0, D, P, sp, t[0]);
            side_eval(X1, D, P, sp, t[1]);
            if (!(cb_vec3_dist(X0, X1) > tol))
                continue;
            double w = side_gap(P, sp, Q, sq, t[0], t[1], m[0], m[1]);
            if (!(w <= CB_SSI_COSIDE_WIDTH * tol))
                continue;
            double lp = across_bound(P, sp), lq = across_bound(Q, sq);
            double ep = CB_SSI_COSIDE_STRIP * tol / lp, eq = CB_SSI_COSIDE_STRIP * tol / lq;
            if (!(ep > 0 && ep <= MAX_STRIP && eq > 0 && eq <= MAX_STRIP))
                continue;
            _cb_ssi_coside *r = out + n++;
            r->sp = sp;
            r->sq = sq;
            r->t0 = t[0];
            r->t1 = t[1];
            r->m0 = m[0];
            r->m1 = m[1];
            r->width = w;
            /* Rounded down: the strip stays within CB_SSI_COSIDE_STRIP tol. */
            r->ep = ep * (1 - 0x1p-50);
            r->eq = eq * (1 - 0x1p-50);
        }
    return n;
}
