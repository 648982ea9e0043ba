/* B-spline basis functions and evaluation of NURBS curves and surfaces with derivatives. */
#include "brep/nurbs.h"

#include <string.h>

int cb_bspline_find_span(int n, int p, const double *U, double u)
{
    if (u >= U[n])
        return n - 1;
    if (u <= U[p])
        return p;
    int lo = p, hi = n;
    int mid = (lo + hi) / 2;
    while (u < U[mid] || u >= U[mid + 1]) {
        if (u < U[mid])
            hi = mid;
        else
            lo = mid;
        mid = (lo + hi) / 2;
    }
    return mid;
}

void cb_bspline_basis(double *N, int span, double u, int p, const double *U)
{
    double left[CB_MAX_BASIS], right[CB_MAX_BASIS];
    N[0] = 1.0;
    for (int j = 1; j <= p; j++) {
        left[j] = u - U[span + 1 - j];
        right[j] = U[span + j] - u;
        double saved = 0.0;
        for (int r = 0; r < j; r++) {
            double temp = N[r] / (right[r + 1] + left[j - r]);
            N[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        N[j] = saved;
    }
}

void cb_bspline_basis_derivs(double *ders, int span, double u, int p, const double *U, int k)
{
    double ndu[CB_MAX_BASIS][CB_MAX_BASIS], a[2][CB_MAX_BASIS];
    double left[CB_MAX_BASIS], right[CB_MAX_BASIS];
    ndu[0][0] = 1.0;
    for (int j = 1; j <= p; j++) {
        left[j] = u - U[span + 1 - j];
        right[j] = U[span + j] - u;
        double saved = 0.0;
        for (int r = 0; r < j; r++) {
            /* Lower triangle: knot differences; upper: basis functions. */
            ndu[j][r] = right[r + 1] + left[j - r];
            double temp = ndu[r][j - 1] / ndu[j][r];
            ndu[r][j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    int w = p + 1;
    for (int j = 0; j <= p; j++)
        ders[j] = ndu[j][p];
    int kk = k < p ? k : p;
    for (int r = 0; r <= p; r++) {
        int s1 = 0, s2 = 1;
        a[0][0] = 1.0;
        for (int q = 1; q <= kk; q++) {
            double d = 0.0;
            int rk = r - q, pk = p - q;
            if (r >= q) {
                a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
                d = a[s2][0] * ndu[rk][pk];
            }
            int j1 = rk >= -1 ? 1 : -rk;
            int j2 = (r - 1 <= pk) ? q - 1 : p - r;
            for (int j = j1; j <= j2; j++) {
                a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][rk + j];
                d += a[s2][j] * ndu[rk + j][pk];
            }
            if (r <= pk) {
                a[s2][q] = -a[s1][q - 1] / ndu[pk + 1][r];
                d += a[s2][q] * ndu[r][pk];
            }
            ders[q * w + r] = d;
            int t = s1;
            s1 = s2;
            s2 = t;
        }
    }
    double f = p;
    for (int q = 1; q <= kk; q++) {
        for (int j = 0; j <= p; j++)
            ders[q * w + j] *= f;
        f *= p - q;
    }
    for (int q = kk + 1; q <= k; q++)
        for (int j = 0; j <= p; j++)
            ders[q * w + j] = 0.0;
}

/* Euclidean derivatives of A / w from homogeneous derivatives (quotient rule, A4.2). */
static void curve_rational_derivs(double d[3][3], const double h[3][4])
{
    for (int i = 0; i < 3; i++) {
        double c0 = h[0][i] / h[0][3];
        double c1 = (h[1][i] - h[1][3] * c0) / h[0][3];
        double c2 = (h[2][i] - 2.0 * h[1][3] * c1 - h[2][3] * c0) / h[0][3];
        d[0][i] = c0;
        d[1][i] = c1;
        d[2][i] = c2;
    }
}

void cb_nurbs_curve_eval_derivs(double d[3][3], const cb_nurbs_curve_t c, double u)
{
    int p = c->deg;
    int span = cb_bspline_find_span(c->n, p, c->knots, u);
    double ders[3 * CB_MAX_BASIS];
    cb_bspline_basis_derivs(ders, span, u, p, c->knots, 2);
    double h[3][4];
    memset(h, 0, sizeof h);
    for (int k = 0; k <= 2; k++)
        for (int j = 0; j <= p; j++) {
            const double *pw = c->cw + 4 * (span - p + j);
            double b = ders[k * (p + 1) + j];
            for (int i = 0; i < 4; i++)
                h[k][i] += b * pw[i];
        }
    curve_rational_derivs(d, h);
}

void cb_nurbs_curve_eval(double p[3], const cb_nurbs_curve_t c, double u)
{
    int deg = c->deg;
    int span = cb_bspline_find_span(c->n, deg, c->knots, u);
    double N[CB_MAX_BASIS], h[4] = {0, 0, 0, 0};
    cb_bspline_basis(N, span, u, deg, c->knots);
    for (int j = 0; j <= deg; j++) {
        const double *pw = c->cw + 4 * (span - deg + j);
        for (int i = 0; i < 4; i++)
            h[i] += N[j] * pw[i];
    }
    for (int i = 0; i < 3; i++)
        p[i] = h[i] / h[3];
}

void cb_nurbs_surface_eval(double p[3], const cb_nurbs_surface_t s, double u, double v)
{
    int pu = s->deg_u, pv = s->deg_v;
    int su = cb_bspline_find_span(s->n_u, pu, s->knots_u, u);
    int sv = cb_bspline_find_span(s->n_v, pv, s->knots_v, v);
    double Nu[CB_MAX_BASIS], Nv[CB_MAX_BASIS], h[4] = {0, 0, 0, 0};
    cb_bspline_basis(Nu, su, u, pu, s->knots_u);
    cb_bspline_basis(Nv, sv, v, pv, s->knots_v);
    for (int a = 0; a <= pu; a++) {
        double row[4] = {0, 0, 0, 0};
        for (int b = 0; b <= pv; b++) {
            const double *pw = cb_nurbs_surface_cw(s, su - pu + a, sv - pv + b);
            for (int i = 0; i < 4; i++)
                row[i] += Nv[b] * pw[i];
        }
        for (int i = 0; i < 4; i++)
            h[i] += Nu[a] * row[i];
    }
    for (int i = 0; i < 3; i++)
        p[i] = h[i] / h[3];
}

void cb_nurbs_surface_eval_derivs(double d[6][3], const cb_nurbs_surface_t s, double u, double v)
{
    int pu = s->deg_u, pv = s->deg_v;
    int su = cb_bspline_find_span(s->n_u, pu, s->knots_u, u);
    int sv = cb_bspline_find_span(s->n_v, pv, s->knots_v, v);
    double du[3 * CB_MAX_BASIS], dv[3 * CB_MAX_BASIS];
    cb_bspline_basis_derivs(du, su, u, pu, s->knots_u, 2);
    cb_bspline_basis_derivs(dv, sv, v, pv, s->knots_v, 2);
    /* h[k][l] = d^{k+l} A / du^k dv^l for k + l <= 2, homogeneous. */
    double h[3][3][4];
    memset(h, 0, sizeof h);
    for (int a = 0; a <= pu; a++)
        for (int b = 0; b <= pv; b++) {
            const double *pw = cb_nurbs_surface_cw(s, su - pu + a, sv - pv + b);
            for (int k = 0; k <= 2; k++)
                for (int l = 0; k + l <= 2; l++) {
                    double f = du[k * (pu + 1) + a] * dv[l * (pv + 1) + b];
                    for (int i = 0; i < 4; i++)
                        h[k][l][i] += f * pw[i];
                }
        }
    double w = h[0][0][3], wu = h[1][0][3], wv = h[0][1][3];
    double wuu = h[2][0][3], wuv = h[1][1][3], wvv = h[0][2][3];
    for (int i = 0; i < 3; i++) {
        double S = h[0][0][i] / w;
        double Su = (h[1][0][i] - wu * S) / w;
        double Sv = (h[0][1][i] - wv * S) / w;
        d[0][i] = S;
        d[1][i] = Su;
        d[2][i] = Sv;
        d[3][i] = (h[2][0][i] - 2.0 * wu * Su - wuu * S) / w;
        d[4][i] = (h[1][1][i] - wu * Sv - wv * Su - wuv * S) / w;
        d[5][i] = (h[0][2][i] - 2.0 * wv * Sv - wvv * S) / w;
    }
}
