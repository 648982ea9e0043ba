/* NURBS evaluation, derivatives and input validation (brep/nurbs_core.c, brep/nurbs_eval.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "brep/nurbs.h"
#include "check.h"

enum { TRIALS = 300 };

/* Clamped knots on [0, 1] with distinct interior knots at least `gap` apart, so that points
 * kept `gap / 4` inside a span see a smooth curve for finite differences. */
static void random_knots(double *U, int n, int p, check_rng *r)
{
    int interior = n - p - 1;
    double gap = 1.0 / (interior + 1);
    for (int k = 0; k <= p; k++) {
        U[k] = 0.0;
        U[n + k] = 1.0;
    }
    for (int k = 0; k < interior; k++)
        U[p + 1 + k] = gap * (k + 1) + check_rng_uniform(r, -0.2, 0.2) * gap;
}

static void random_curve(cb_nurbs_curve_t c, check_rng *r)
{
    int p = check_rng_int(r, 1, 5), n = p + 1 + check_rng_int(r, 0, 5);
    double U[64], P[3 * 32], W[32];
    random_knots(U, n, p, r);
    for (int i = 0; i < n; i++) {
        for (int k = 0; k < 3; k++)
            P[3 * i + k] = check_rng_uniform(r, -1, 1);
        W[i] = check_rng_uniform(r, 0.5, 2.0);
    }
    cb_nurbs_curve_make(c, p, U, n + p + 1, P, W, n, NULL);
}

static void random_surface(cb_nurbs_surface_t s, check_rng *r)
{
    int pu = check_rng_int(r, 1, 4), pv = check_rng_int(r, 1, 4);
    int nu = pu + 1 + check_rng_int(r, 0, 4), nv = pv + 1 + check_rng_int(r, 0, 4);
    double Uu[64], Uv[64], P[3 * 81], W[81];
    random_knots(Uu, nu, pu, r);
    random_knots(Uv, nv, pv, r);
    for (int i = 0; i < nu * nv; i++) {
        for (int k = 0; k < 3; k++)
            P[3 * i + k] = check_rng_uniform(r, -1, 1);
        W[i] = check_rng_uniform(r, 0.5, 2.0);
    }
    cb_nurbs_surface_make(s, pu, pv, Uu, nu + pu + 1, Uv, nv + pv + 1, P, W, nu, nv, NULL);
}

/* A parameter inside a random span, at least a quarter of the span from its ends. */
static double inner_param(const double *U, int n, int p, check_rng *r)
{
    int span = check_rng_int(r, p, n - 1);
    double a = U[span], b = U[span + 1];
    return check_rng_uniform(r, a + 0.25 * (b - a), b - 0.25 * (b - a));
}

/* Cox-de Boor recursion straight from the definition: an independent reference. */
static double basis_ref(const double *U, int i, int p, double u)
{
    if (p == 0)
        return (U[i] <= u && u < U[i + 1]) ? 1.0 : 0.0;
    double a = 0.0, b = 0.0;
    if (U[i + p] > U[i])
        a = (u - U[i]) / (U[i + p] - U[i]) * basis_ref(U, i, p - 1, u);
    if (U[i + p + 1] > U[i + 1])
        b = (U[i + p + 1] - u) / (U[i + p + 1] - U[i + 1]) * basis_ref(U, i + 1, p - 1, u);
    return a + b;
}

static double max_abs3(const double a[3], const double b[3])
{
    double m = 0;
    for (int k = 0; k < 3; k++)
        m = fmax(m, fabs(a[k] - b[k]));
    return m;
}

static void test_basis(check_rng *r)
{
    for (int t = 0; t < TRIALS; t++) {
        cb_nurbs_curve_t c;
        cb_nurbs_curve_init(c);
        random_curve(c, r);
        int p = c->deg;
        double u = check_rng_uniform(r, 0, 1);
        int span = cb_bspline_find_span(c->n, p, c->knots, u);
        CHECK(c->knots[span] <= u && u < c->knots[span + 1], "trial %d: span %d for u=%g", t,
              span, u);
        double N[CB_MAX_BASIS], ders[3 * CB_MAX_BASIS], sum = 0, dsum = 0, err = 0;
        cb_bspline_basis(N, span, u, p, c->knots);
        cb_bspline_basis_derivs(ders, span, u, p, c->knots, 2);
        for (int j = 0; j <= p; j++) {
            sum += N[j];
            dsum += ders[(p + 1) + j];
            err = fmax(err, fabs(N[j] - basis_ref(c->knots, span - p + j, p, u)));
            err = fmax(err, fabs(N[j] - ders[j]));
        }
        CHECK(fabs(sum - 1) < 1e-14, "trial %d: partition of unity off by %g", t, sum - 1);
        CHECK(fabs(dsum) < 1e-10, "trial %d: derivatives of basis sum to %g", t, dsum);
        CHECK(err < 1e-14, "trial %d: basis differs from Cox-de Boor by %g", t, err);
        cb_nurbs_curve_clear(c);
    }
}

static void test_curve_eval(check_rng *r)
{
    double worst_d1 = 0, worst_d2 = 0;
    for (int t = 0; t < TRIALS; t++) {
        cb_nurbs_curve_t c;
        cb_nurbs_curve_init(c);
        random_curve(c, r);
        double a, b, p0[3], p1[3];
        cb_nurbs_curve_domain(c, &a, &b);
        cb_nurbs_curve_eval(p0, c, a);
        cb_nurbs_curve_eval(p1, c, b);
        double e0[3], e1[3];
        for (int k = 0; k < 3; k++) {
            e0[k] = c->cw[k] / c->cw[3];
            e1[k] = c->cw[4 * (c->n - 1) + k] / c->cw[4 * (c->n - 1) + 3];
        }
        CHECK(max_abs3(p0, e0) < 1e-14 && max_abs3(p1, e1) < 1e-14,
              "trial %d: clamped curve does not interpolate its end points", t);

        double u = inner_param(c->knots, c->n, c->deg, r);
        double d[3][3], ref[3];
        cb_nurbs_curve_eval_derivs(d, c, u);
        cb_nurbs_curve_eval(ref, c, u);
        CHECK(max_abs3(d[0], ref) < 1e-14, "trial %d: eval_derivs point differs from eval", t);
        /* Fourth-order central differences; h leaves the evaluation inside the span. */
        double h = 1e-3, f[5][3];
        for (int k = -2; k <= 2; k++)
            cb_nurbs_curve_eval(f[k + 2], c, u + k * h);
        double e1d = 0, e2d = 0, scale = 1;
        for (int k = 0; k < 3; k++) {
            double fd1 = (f[0][k] - 8 * f[1][k] + 8 * f[3][k] - f[4][k]) / (12 * h);
            double fd2 = (-f[0][k] + 16 * f[1][k] - 30 * f[2][k] + 16 * f[3][k] - f[4][k]) /
                         (12 * h * h);
            e1d = fmax(e1d, fabs(fd1 - d[1][k]));
            e2d = fmax(e2d, fabs(fd2 - d[2][k]));
            scale = fmax(scale, fmax(fabs(d[1][k]), fabs(d[2][k])));
        }
        worst_d1 = fmax(worst_d1, e1d / scale);
        worst_d2 = fmax(worst_d2, e2d / scale);
        CHECK(e1d <= 1e-6 * scale && e2d <= 1e-4 * scale,
              "trial %d: u=%g derivative errors %g %g (scale %g)", t, u, e1d, e2d, scale);
        cb_nurbs_curve_clear(c);
    }
    printf("curve derivatives vs finite differences: worst relative %.2e (1st) %.2e (2nd)\n",
           worst_d1, worst_d2);
}

/* de Casteljau on homogeneous points: an independent evaluator for Bezier curves. */
static void casteljau(double out[3], const double *cw, int p, double t)
{
    double q[CB_MAX_BASIS][4];
    memcpy(q, cw, sizeof(double) * 4 * (p + 1));
    for (int k = 1; k <= p; k++)
        for (int i = 0; i <= p - k; i++)
            for (int j = 0; j < 4; j++)
                q[i][j] = (1 - t) * q[i][j] + t * q[i + 1][j];
    for (int j = 0; j < 3; j++)
        out[j] = q[0][j] / q[0][3];
}

static void test_bezier_eval(check_rng *r)
{
    for (int t = 0; t < TRIALS; t++) {
        int p = check_rng_int(r, 1, 9);
        double U[2 * CB_MAX_BASIS], P[3 * CB_MAX_BASIS], W[CB_MAX_BASIS];
        for (int k = 0; k <= p; k++) {
            U[k] = 0;
            U[p + 1 + k] = 1;
            W[k] = check_rng_uniform(r, 0.5, 2);
            for (int j = 0; j < 3; j++)
                P[3 * k + j] = check_rng_uniform(r, -1, 1);
        }
        cb_nurbs_curve_t c;
        cb_nurbs_curve_init(c);
        CHECK(cb_nurbs_curve_make(c, p, U, 2 * p + 2, P, W, p + 1, NULL) == CB_OK, "trial %d", t);
        double u = check_rng_uniform(r, 0, 1), a[3], b[3];
        cb_nurbs_curve_eval(a, c, u);
        casteljau(b, c->cw, p, u);
        CHECK(max_abs3(a, b) < 1e-13, "trial %d: degree %d u=%g de Boor vs de Casteljau %g", t,
              p, u, max_abs3(a, b));
        cb_nurbs_curve_clear(c);
    }
}

static void test_surface_eval(check_rng *r)
{
    double worst[6] = {0};
    for (int t = 0; t < TRIALS; t++) {
        cb_nurbs_surface_t s;
        cb_nurbs_surface_init(s);
        random_surface(s, r);
        double u = inner_param(s->knots_u, s->n_u, s->deg_u, r);
        double v = inner_param(s->knots_v, s->n_v, s->deg_v, r);
        double d[6][3], p[3];
        cb_nurbs_surface_eval_derivs(d, s, u, v);
        cb_nurbs_surface_eval(p, s, u, v);
        CHECK(max_abs3(d[0], p) < 1e-14, "trial %d: eval_derivs point differs from eval", t);

        /* Iso-curve check: fixing v, S(., v) is a rational curve whose control points are the
         * column-wise combinations; compare against the curve evaluator. */
        int sv = cb_bspline_find_span(s->n_v, s->deg_v, s->knots_v, v);
        double Nv[CB_MAX_BASIS];
        cb_bspline_basis(Nv, sv, v, s->deg_v, s->knots_v);
        cb_nurbs_curve_t iso;
        cb_nurbs_curve_init(iso);
        cb_nurbs_curve_alloc(iso, s->deg_u, s->n_u, NULL);
        memcpy(iso->knots, s->knots_u, sizeof(double) * (s->n_u + s->deg_u + 1));
        for (int i = 0; i < s->n_u; i++)
            for (int b = 0; b <= s->deg_v; b++)
                for (int k = 0; k < 4; k++)
                    iso->cw[4 * i + k] += Nv[b] * cb_nurbs_surface_cw(s, i, sv - s->deg_v + b)[k];
        double cd[3][3];
        cb_nurbs_curve_eval_derivs(cd, iso, u);
        CHECK(max_abs3(cd[0], d[0]) < 1e-13 && max_abs3(cd[1], d[1]) < 1e-11 &&
                  max_abs3(cd[2], d[3]) < 1e-9,
              "trial %d: surface and iso-curve derivatives differ", t);
        cb_nurbs_curve_clear(iso);

        double h = 1e-3, scale = 1, e[6] = {0};
        double f[5][5][3];
        for (int a = -2; a <= 2; a++)
            for (int b = -2; b <= 2; b++)
                cb_nurbs_surface_eval(f[a + 2][b + 2], s, u + a * h, v + b * h);
        static const double c1[5] = {1.0 / 12, -8.0 / 12, 0, 8.0 / 12, -1.0 / 12};
        static const double c2[5] = {-1.0 / 12, 16.0 / 12, -30.0 / 12, 16.0 / 12, -1.0 / 12};
        for (int k = 0; k < 3; k++) {
            double su = 0, sv2 = 0, suu = 0, svv = 0, suv = 0;
            for (int a = 0; a < 5; a++) {
                su += c1[a] * f[a][2][k];
                sv2 += c1[a] * f[2][a][k];
                suu += c2[a] * f[a][2][k];
                svv += c2[a] * f[2][a][k];
                for (int b = 0; b < 5; b++)
                    suv += c1[a] * c1[b] * f[a][b][k];
            }
            double fd[6] = {0, su / h, sv2 / h, suu / (h * h), suv / (h * h), svv / (h * h)};
            for (int m = 1; m < 6; m++) {
                e[m] = fmax(e[m], fabs(fd[m] - d[m][k]));
                scale = fmax(scale, fabs(d[m][k]));
            }
        }
        for (int m = 1; m < 6; m++)
            worst[m] = fmax(worst[m], e[m] / scale);
        CHECK(e[1] <= 1e-6 * scale && e[2] <= 1e-6 * scale && e[3] <= 1e-4 * scale &&
                  e[4] <= 1e-4 * scale && e[5] <= 1e-4 * scale,
              "trial %d: (u,v)=(%g,%g) derivative errors %g %g %g %g %g (scale %g)", t, u, v,
              e[1], e[2], e[3], e[4], e[5], scale);
        cb_nurbs_surface_clear(s);
    }
    printf("surface derivatives vs finite differences: worst relative Su %.1e Sv %.1e Suu %.1e "
           "Suv %.1e Svv %.1e\n",
           worst[1], worst[2], worst[3], worst[4], worst[5]);
}

/* One bad-input case for curves: the call must fail with `want`, name the problem, and leave
 * the output curve as it was. */
static void expect_bad_curve(const char *name, int deg, const double *U, int nk, const double *P,
                             const double *W, int n, const char *const *words)
{
    cb_nurbs_curve_t c;
    cb_nurbs_curve_init(c);
    double U0[] = {0, 0, 1, 1}, P0[] = {0, 0, 0, 1, 1, 1};
    cb_nurbs_curve_make(c, 1, U0, 4, P0, NULL, 2, NULL);
    double before = c->cw[4];
    cb_error err;
    cb_error_clear(&err);
    cb_status st = cb_nurbs_curve_make(c, deg, U, nk, P, W, n, &err);
    CHECK(st == CB_ERR_INVALID, "%s: status %d", name, st);
    CHECK(err.status == st && check_msg_has(err.msg, words), "%s: message '%s'", name, err.msg);
    CHECK(c->deg == 1 && c->n == 2 && c->cw[4] == before, "%s: output changed on failure", name);
    cb_nurbs_curve_clear(c);
}

static void test_bad_input(void)
{
    double U[] = {0, 0, 0, 0.5, 1, 1, 1};
    double P[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    double W[] = {1, 2, 1, 1};
    expect_bad_curve("degree 0", 0, U, 7, P, W, 4, (const char *const[]){"degree 0", NULL});
    expect_bad_curve("degree -3", -3, U, 7, P, W, 4, (const char *const[]){"degree -3", NULL});
    expect_bad_curve("too few points", 2, U, 7, P, W, 2,
                     (const char *const[]){"2 control points", "degree 2", NULL});
    expect_bad_curve("knot count", 2, U, 6, P, W, 4,
                     (const char *const[]){"6 knots given, 7 expected", NULL});
    double Ud2[] = {0, 0, 0, 0.7, 0.5, 1, 1};
    expect_bad_curve("decreasing knots", 2, Ud2, 7, P, W, 4,
                     (const char *const[]){"non-decreasing", "knot 4", NULL});
    double Uc[] = {0, 0, 0.2, 0.5, 1, 1, 1};
    expect_bad_curve("unclamped start", 2, Uc, 7, P, W, 4,
                     (const char *const[]){"not clamped at the start", NULL});
    double Ue[] = {0, 0, 0, 0.5, 0.8, 1, 1};
    expect_bad_curve("unclamped end", 2, Ue, 7, P, W, 4,
                     (const char *const[]){"not clamped at the end", NULL});
    double Un[] = {0, 0, 0, NAN, 1, 1, 1};
    expect_bad_curve("NaN knot", 2, Un, 7, P, W, 4,
                     (const char *const[]){"knot 3 is not finite", NULL});
    double Ui[] = {0, 0, 0, 0.5, 1, 1, INFINITY};
    expect_bad_curve("Inf knot", 2, Ui, 7, P, W, 4,
                     (const char *const[]){"knot 6 is not finite", NULL});
    double Pn[] = {0, 0, 0, 1, 0, 0, 1, NAN, 0, 0, 1, 0};
    expect_bad_curve("NaN point", 2, U, 7, Pn, W, 4,
                     (const char *const[]){"control point 2", "y", "not finite", NULL});
    double Pi[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, -INFINITY};
    expect_bad_curve("Inf point", 2, U, 7, Pi, W, 4,
                     (const char *const[]){"control point 3", "z", "not finite", NULL});
    double Wz[] = {1, 0, 1, 1}, Wn[] = {1, 1, -2, 1}, Wnan[] = {1, 1, 1, NAN};
    expect_bad_curve("zero weight", 2, U, 7, P, Wz, 4,
                     (const char *const[]){"weight 1", "must be > 0", NULL});
    expect_bad_curve("negative weight", 2, U, 7, P, Wn, 4,
                     (const char *const[]){"weight 2", "must be > 0", NULL});
    expect_bad_curve("NaN weight", 2, U, 7, P, Wnan, 4,
                     (const char *const[]){"weight 3", "not finite", NULL});
    double Um[] = {0, 0, 0, 0.5, 0.5, 0.5, 1, 1, 1};
    double P6[18] = {0};
    expect_bad_curve("interior multiplicity", 2, Um, 9, P6, NULL, 6,
                     (const char *const[]){"multiplicity 3 > degree 2", NULL});
    double Uz[] = {0, 0, 0, 0, 0, 0};
    expect_bad_curve("empty domain", 2, Uz, 6, P, NULL, 3,
                     (const char *const[]){"empty parameter domain", NULL});
    expect_bad_curve("no knots", 2, NULL, 7, P, W, 4, (const char *const[]){"no knots", NULL});
    expect_bad_curve("no points", 2, U, 7, NULL, W, 4,
                     (const char *const[]){"no control points", NULL});

    /* Surfaces report which direction is wrong. */
    cb_nurbs_surface_t s;
    cb_nurbs_surface_init(s);
    double Uu[] = {0, 0, 1, 1}, Uv[] = {0, 0, 0, 1, 1, 1}, Ps[18] = {0};
    cb_error err;
    CHECK(cb_nurbs_surface_make(s, 1, 2, Uu, 4, Uv, 6, Ps, NULL, 2, 3, &err) == CB_OK, "%s",
          err.msg);
    CHECK(cb_nurbs_surface_make(s, 1, 2, Uu, 4, Uv, 5, Ps, NULL, 2, 3, &err) == CB_ERR_INVALID &&
              strstr(err.msg, "v: 5 knots given, 6 expected"),
          "surface v knot count: '%s'", err.msg);
    CHECK(cb_nurbs_surface_make(s, 0, 2, Uu, 4, Uv, 6, Ps, NULL, 2, 3, &err) == CB_ERR_INVALID &&
              strstr(err.msg, "u: degree 0"),
          "surface u degree: '%s'", err.msg);
    double Wsz[6] = {1, 1, 1, 1, 0, 1};
    CHECK(cb_nurbs_surface_make(s, 1, 2, Uu, 4, Uv, 6, Ps, Wsz, 2, 3, &err) == CB_ERR_INVALID &&
              strstr(err.msg, "weight 4"),
          "surface weight: '%s'", err.msg);
    CHECK(s->deg_u == 1 && s->n_v == 3, "surface changed by a failed make");
    /* validate catches corruption made after construction. */
    s->cw[4 * 5 + 3] = -1;
    CHECK(cb_nurbs_surface_validate(s, &err) == CB_ERR_INVALID && strstr(err.msg, "weight 5"),
          "validate weight: '%s'", err.msg);
    s->cw[4 * 5 + 3] = 1;
    s->knots_v[3] = 0.5;
    CHECK(cb_nurbs_surface_validate(s, &err) == CB_ERR_INVALID &&
              strstr(err.msg, "v: knot vector not clamped at the end"),
          "validate knots: '%s'", err.msg);
    cb_nurbs_surface_clear(s);
    CHECK(cb_nurbs_surface_validate(s, &err) == CB_ERR_INVALID, "cleared surface validates");

    CHECK(cb_nurbs_surface_alloc(s, 3, 3, 4000, 4000, &err) == CB_ERR_INVALID &&
              strstr(err.msg, "exceed"),
          "oversized surface: '%s'", err.msg);
}

int main(void)
{
    check_rng r = {12345};
    test_basis(&r);
    test_curve_eval(&r);
    test_bezier_eval(&r);
    test_surface_eval(&r);
    test_bad_input();
    return check_report("nurbs_eval");
}
