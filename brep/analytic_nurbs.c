/* Exact rational B-spline forms of circular arcs and of the analytic surfaces. */
#include "brep/analytic.h"

#include <float.h>
#include <math.h>
#include <string.h>

static const double pi = 3.14159265358979323846;

enum { ARC_MAX_SEGS = 4, ARC_MAX_POINTS = 2 * ARC_MAX_SEGS + 1 };

/* Whether angle a is a whole number of quarter turns, to its rounding: its quarter count in
 * *q (0 to 3). */
static int quarter_turn(double a, int *q)
{
    double k = a / (0.5 * pi), r = nearbyint(k);
    if (!(fabs(k - r) <= 8 * DBL_EPSILON * fmax(1.0, fabs(k))))
        return 0;
    *q = (int)(((long)r % 4 + 4) % 4);
    return 1;
}

/* The unit arc t -> (cos t, sin t), t in [a0, a1] (at most one turn), as n rational quadratic
 * Bezier segments of equal angle <= pi/2 (The NURBS Book A7.1): 2 n + 1 points xy with weights
 * w, and 2 n + 4 knots, the interior ones doubled at the segment angles. Returns n. End points
 * of segments are computed from their angles, so they are the exact circle points to round-off
 * and the parameter at a knot equals the angle. With exact set, segments that are quarter
 * turns between whole quarter angles are written exactly in binary instead: end points 0 and
 * +-1, middle points at the corners of the circumscribed square (the sum of the ends), and
 * weights 1, 1, 2, the tangent-half-angle form of a quarter circle, in place of 1, cos(pi/4)
 * rounded, 1 (the same arc under a Moebius change of its parameter); the weights of segment k
 * are multiplied by 2^k, which leaves each segment's curve unchanged and makes the shared end
 * weights agree. */
static int unit_arc(double xy[ARC_MAX_POINTS][2], double w[ARC_MAX_POINTS],
                    double knots[ARC_MAX_POINTS + 3], double a0, double a1, int exact)
{
    double span = a1 - a0;
    int n = span <= 0.5 * pi ? 1 : span <= pi ? 2 : span <= 1.5 * pi ? 3 : 4;
    double th[ARC_MAX_SEGS + 1];
    for (int k = 0; k < n; k++)
        th[k] = a0 + span * k / n;
    th[n] = a1;
    for (int k = 0; k <= n; k++) {
        xy[2 * k][0] = cos(th[k]);
        xy[2 * k][1] = sin(th[k]);
        w[2 * k] = 1.0;
    }
    for (int k = 0; k < n; k++) {
        /* The middle point sits on the bisector where the end tangents meet, at distance
         * 1 / cos(half angle); its weight cos(half angle) makes the segment circular. */
        double half = 0.5 * (th[k + 1] - th[k]), mid = th[k] + half, wm = cos(half);
        xy[2 * k + 1][0] = cos(mid) / wm;
        xy[2 * k + 1][1] = sin(mid) / wm;
        w[2 * k + 1] = wm;
    }
    int q[ARC_MAX_SEGS + 1];
    for (int k = 0; exact && k <= n; k++)
        exact = quarter_turn(th[k], &q[k]) && (k == 0 || q[k] == (q[k - 1] + 1) % 4);
    if (exact) {
        static const double C[4] = {1, 0, -1, 0}, S[4] = {0, 1, 0, -1};
        double scale = 1.0;
        for (int k = 0; k <= n; k++) {
            xy[2 * k][0] = C[q[k]];
            xy[2 * k][1] = S[q[k]];
            w[2 * k] = scale;
            if (k < n) {
                xy[2 * k + 1][0] = C[q[k]] + C[q[k + 1]];
                xy[2 * k + 1][1] = S[q[k]] + S[q[k + 1]];
                w[2 * k + 1] = scale;
            }
            scale *= 2.0;
        }
    }
    knots[0] = knots[1] = knots[2] = a0;
    for (int k = 1; k < n; k++)
        knots[2 * k + 1] = knots[2 * k + 2] = th[k];
    knots[2 * n + 1] = knots[2 * n + 2] = knots[2 * n + 3] = a1;
    return n;
}

static cb_status check_range(double a, double b, const char *what, cb_error *err)
{
    if (!(isfinite(a) && isfinite(b) && a < b))
        return cb_error_set(err, CB_ERR_INVALID, "%s range [%.17g, %.17g] is empty or not finite",
                            what, a, b);
    return CB_OK;
}

/* A non-empty angle range of at most one turn. b = a + 2 pi as computed in double counts as one
 * turn even where the rounding makes b - a exceed 2 pi by an ulp, so full turns built the
 * obvious way are accepted without a tolerance. */
static cb_status check_angle_range(double a, double b, const char *what, cb_error *err)
{
    cb_status st = check_range(a, b, what, err);
    if (!st && !(b - a <= 2.0 * pi || b <= a + 2.0 * pi))
        st = cb_error_set(err, CB_ERR_INVALID,
                          "%s range [%.17g, %.17g] spans %.17g, more than 2 pi", what, a, b, b - a);
    return st;
}

static cb_status arc(cb_nurbs_curve_t c, const double center[3], const double xdir[3],
                     const double ydir[3], double radius, double a0, double a1, int exact,
                     cb_error *err)
{
    for (int i = 0; i < 3; i++)
        if (!isfinite(center[i]) || !isfinite(xdir[i]) || !isfinite(ydir[i]))
            return cb_error_set(err, CB_ERR_INVALID,
                                "arc: center, xdir or ydir is not finite (coordinate %c)",
                                "xyz"[i]);
    if (!(isfinite(radius) && radius > 0))
        return cb_error_set(err, CB_ERR_INVALID, "arc: radius %.17g must be finite and > 0",
                            radius);
    double nrm[3];
    cb_vec3_cross(nrm, xdir, ydir);
    if (nrm[0] == 0 && nrm[1] == 0 && nrm[2] == 0)
        return cb_error_set(err, CB_ERR_INVALID,
                            "arc: xdir and ydir are zero or parallel; they span no plane");
    cb_status st = check_angle_range(a0, a1, "arc: angle", err);
    if (st)
        return st;
    double xy[ARC_MAX_POINTS][2], w[ARC_MAX_POINTS], knots[ARC_MAX_POINTS + 3];
    int n = unit_arc(xy, w, knots, a0, a1, exact);
    int np = 2 * n + 1;
    cb_nurbs_curve_t t;
    cb_nurbs_curve_init(t);
    if ((st = cb_nurbs_curve_alloc(t, 2, np, err)))
        return st;
    memcpy(t->knots, knots, (size_t)(np + 3) * sizeof *knots);
    for (int k = 0; k < np; k++) {
        double *cw = t->cw + 4 * k;
        for (int i = 0; i < 3; i++)
            cw[i] = w[k] * (center[i] + radius * (xy[k][0] * xdir[i] + xy[k][1] * ydir[i]));
        cw[3] = w[k];
    }
    cb_nurbs_curve_swap(c, t);
    cb_nurbs_curve_clear(t);
    return CB_OK;
}

cb_status cb_nurbs_curve_arc(cb_nurbs_curve_t c, const double center[3], const double xdir[3],
                             const double ydir[3], double radius, double a0, double a1,
                             cb_error *err)
{
    return arc(c, center, xdir, ydir, radius, a0, a1, 0, err);
}

cb_status cb_nurbs_curve_arc_exact(cb_nurbs_curve_t c, const double center[3],
                                   const double xdir[3], const double ydir[3], double radius,
                                   double a0, double a1, cb_error *err)
{
    return arc(c, center, xdir, ydir, radius, a0, a1, 1, err);
}

double cb_nurbs_arc_angle(double a0, double a1, int exact, double t)
{
    if (!(a0 < a1) || !(t > a0))
        return a0;
    if (t >= a1)
        return a1;
    double xy[ARC_MAX_POINTS][2], w[ARC_MAX_POINTS], knots[ARC_MAX_POINTS + 3];
    int n = unit_arc(xy, w, knots, a0, a1, exact), k = 0;
    /* segment k spans knots[2k + 2] .. knots[2k + 3] (the interior knots are doubled) */
    while (k + 1 < n && t >= knots[2 * k + 3])
        k++;
    double t0 = knots[2 * k + 2], t1 = knots[2 * k + 3];
    if (t <= t0)
        return t0;
    if (t >= t1)
        return t1;
    double s = (t - t0) / (t1 - t0), b[3] = {(1 - s) * (1 - s), 2 * s * (1 - s), s * s};
    double p[2] = {0, 0};
    for (int i = 0; i < 3; i++) {
        const double *q = xy[2 * k + i];
        p[0] += b[i] * w[2 * k + i] * q[0];
        p[1] += b[i] * w[2 * k + i] * q[1];
    }
    /* The angle from the segment's first point, which lies at angle t0 (at most a quarter
     * turn away, so atan2 needs no lifting), of the homogeneous point: dividing by its
     * weight (> 0) would not change it. */
    const double *q0 = xy[2 * k];
    double phi = atan2(q0[0] * p[1] - q0[1] * p[0], q0[0] * p[0] + q0[1] * p[1]);
    return fmin(fmax(t0 + phi, t0), t1);
}

cb_status cb_nurbs_surface_revolve(cb_nurbs_surface_t out, const cb_nurbs_curve_t profile,
                                   const double o[3], const double z[3], double a0, double a1,
                                   int exact, cb_error *err)
{
    double zn = cb_vec3_norm(z);
    for (int i = 0; i < 3; i++)
        if (!isfinite(o[i]) || !isfinite(z[i]))
            return cb_error_set(err, CB_ERR_INVALID,
                                "revolve: axis point or direction not finite (coordinate %c)",
                                "xyz"[i]);
    if (!(fabs(zn - 1.0) <= 1e-12))
        return cb_error_set(err, CB_ERR_INVALID,
                            "revolve: axis direction of length %.17g is not a unit vector", zn);
    cb_status st = check_angle_range(a0, a1, "revolve: angle", err);
    if (st)
        return st;
    double xy[ARC_MAX_POINTS][2], w[ARC_MAX_POINTS], knots[ARC_MAX_POINTS + 3];
    int nu = 2 * unit_arc(xy, w, knots, a0, a1, exact) + 1, p = profile->deg, nv = profile->n;
    cb_nurbs_surface_t t;
    cb_nurbs_surface_init(t);
    if ((st = cb_nurbs_surface_alloc(t, 2, p, nu, nv, err)))
        return st;
    memcpy(t->knots_u, knots, (size_t)(nu + 3) * sizeof *knots);
    memcpy(t->knots_v, profile->knots, (size_t)(nv + p + 1) * sizeof *knots);
    /* A point q turned by the angle u about the axis is o + h z + cos u r + sin u (z x r), r
     * the part of q - o across the axis and h its height: affine in (cos u, sin u), so the
     * unit arc's control points (x, y) give the turned profile's, and the weights multiply
     * (The NURBS Book A8.1, any profile, planar or not). */
    for (int j = 0; j < nv; j++) {
        const double *pw = profile->cw + 4 * j;
        double wj = pw[3], q[3], r[3], zr[3];
        for (int i = 0; i < 3; i++)
            q[i] = pw[i] / wj - o[i];
        double h = cb_vec3_dot(q, z);
        for (int i = 0; i < 3; i++)
            r[i] = q[i] - h * z[i];
        cb_vec3_cross(zr, z, r);
        for (int i = 0; i < nu; i++) {
            double *cw = cb_nurbs_surface_cw(t, i, j), wt = w[i] * wj;
            for (int k = 0; k < 3; k++)
                cw[k] = wt * (o[k] + h * z[k] + xy[i][0] * r[k] + xy[i][1] * zr[k]);
            cw[3] = wt;
        }
    }
    cb_nurbs_surface_swap(out, t);
    cb_nurbs_surface_clear(t);
    return CB_OK;
}

/* Checks the frame and range shared by the parabola and the hyperbola. */
static cb_status conic_args(const double o[3], const double xdir[3], const double ydir[3],
                            double t0, double t1, const char *what, cb_error *err)
{
    for (int i = 0; i < 3; i++)
        if (!isfinite(o[i]) || !isfinite(xdir[i]) || !isfinite(ydir[i]))
            return cb_error_set(err, CB_ERR_INVALID, "%s: frame not finite (coordinate %c)",
                                what, "xyz"[i]);
    double nrm[3];
    cb_vec3_cross(nrm, xdir, ydir);
    if (nrm[0] == 0 && nrm[1] == 0 && nrm[2] == 0)
        return cb_error_set(err, CB_ERR_INVALID, "%s: xdir and ydir are zero or parallel", what);
    if (!(isfinite(t0) && isfinite(t1) && t0 < t1))
        return cb_error_set(err, CB_ERR_INVALID, "%s: range [%.17g, %.17g] is empty", what, t0,
                            t1);
    return CB_OK;
}

cb_status cb_nurbs_curve_parabola(cb_nurbs_curve_t c, const double vertex[3],
                                  const double xdir[3], const double ydir[3], double focal,
                                  double t0, double t1, cb_error *err)
{
    cb_status st = conic_args(vertex, xdir, ydir, t0, t1, "parabola", err);
    if (st)
        return st;
    if (!(isfinite(focal) && focal > 0))
        return cb_error_set(err, CB_ERR_INVALID, "parabola: focal distance %.17g must be > 0",
                            focal);
    cb_nurbs_curve_t t;
    cb_nurbs_curve_init(t);
    if ((st = cb_nurbs_curve_alloc(t, 2, 3, err)))
        return st;
    const double kx[3] = {t0 * t0, t0 * t1, t1 * t1}, ky[3] = {2 * t0, t0 + t1, 2 * t1};
    for (int k = 0; k < 3; k++) {
        double *cw = t->cw + 4 * k;
        for (int i = 0; i < 3; i++)
            cw[i] = vertex[i] + focal * (kx[k] * xdir[i] + ky[k] * ydir[i]);
        cw[3] = 1;
        t->knots[k] = t0;
        t->knots[3 + k] = t1;
    }
    cb_nurbs_curve_swap(c, t);
    cb_nurbs_curve_clear(t);
    return CB_OK;
}

cb_status cb_nurbs_curve_hyperbola(cb_nurbs_curve_t c, const double center[3],
                                   const double xdir[3], const double ydir[3], double a, double b,
                                   double t0, double t1, cb_error *err)
{
    /* cosh 700 ~ 5e303: beyond it the points overflow. */
    const double max_t = 700, max_seg = 2;
    cb_status st = conic_args(center, xdir, ydir, t0, t1, "hyperbola", err);
    if (st)
        return st;
    if (!(isfinite(a) && a > 0 && isfinite(b) && b > 0))
        return cb_error_set(err, CB_ERR_INVALID, "hyperbola: semi-axes %.17g, %.17g must be > 0",
                            a, b);
    if (fabs(t0) > max_t || fabs(t1) > max_t)
        return cb_error_set(err, CB_ERR_INVALID, "hyperbola: range [%.17g, %.17g] beyond +-%g",
                            t0, t1, max_t);
    int n = (int)ceil((t1 - t0) / max_seg);
    if (n < 1)
        n = 1;
    cb_nurbs_curve_t t;
    cb_nurbs_curve_init(t);
    if ((st = cb_nurbs_curve_alloc(t, 2, 2 * n + 1, err)))
        return st;
    for (int k = 0; k <= 2 * n; k++) {
        /* even k: a segment end at s = t0 + (k / 2) (t1 - t0) / n; odd k: a shoulder point */
        double *cw = t->cw + 4 * k, cx, cy, w;
        double s0 = t0 + (t1 - t0) * (k / 2) / n, s1 = t0 + (t1 - t0) * (k / 2 + 1) / n;
        if (k == 2 * n)
            s0 = t1;
        if (k % 2 == 0) {
            cx = a * cosh(s0);
            cy = b * sinh(s0);
            w = 1;
        } else {
            double m = 0.5 * (s0 + s1), h = 0.5 * (s1 - s0);
            w = cosh(h);
            cx = a * cosh(m) / w;
            cy = b * sinh(m) / w;
        }
        for (int i = 0; i < 3; i++)
            cw[i] = w * (center[i] + cx * xdir[i] + cy * ydir[i]);
        cw[3] = w;
    }
    /* knots t0 x3, the interior segment ends twice, t1 x3 */
    int m = 0;
    for (int k = 0; k < 3; k++)
        t->knots[m++] = t0;
    for (int j = 1; j < n; j++) {
        double s = t0 + (t1 - t0) * j / n;
        t->knots[m++] = s;
        t->knots[m++] = s;
    }
    for (int k = 0; k < 3; k++)
        t->knots[m++] = t1;
    cb_nurbs_curve_swap(c, t);
    cb_nurbs_curve_clear(t);
    return CB_OK;
}

/* The plane patch: bilinear, and the B-spline parameter equals (u, v) everywhere. */
static cb_status plane_to_nurbs(cb_nurbs_surface_t out, const cb_analytic_surface *s, double u0,
                                double u1, double v0, double v1, cb_error *err)
{
    cb_nurbs_surface_t t;
    cb_nurbs_surface_init(t);
    cb_status st = cb_nurbs_surface_alloc(t, 1, 1, 2, 2, err);
    if (st)
        return st;
    double us[2] = {u0, u1}, vs[2] = {v0, v1};
    for (int k = 0; k < 2; k++) {
        t->knots_u[2 * k] = t->knots_u[2 * k + 1] = us[k];
        t->knots_v[2 * k] = t->knots_v[2 * k + 1] = vs[k];
    }
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) {
            double *cw = cb_nurbs_surface_cw(t, i, j);
            cb_analytic_eval(cw, s, us[i], vs[j]);
            cw[3] = 1.0;
        }
    cb_nurbs_surface_swap(out, t);
    cb_nurbs_surface_clear(t);
    return CB_OK;
}

/* Rejects the ranges the kind cannot take (beyond the finite, non-empty check). */
static cb_status check_kind_ranges(const cb_analytic_surface *s, double u0, double u1, double v0,
                                   double v1, cb_error *err)
{
    const char *name = cb_analytic_kind_name(s->kind);
    cb_status st = check_angle_range(u0, u1, "u", err);
    if (st)
        return cb_error_prefix(err, "%s: ", name);
    switch (s->kind) {
    case CB_ANALYTIC_SPHERE:
    case CB_ANALYTIC_ELLIPSOID:
        if (v0 < -0.5 * pi || v1 > 0.5 * pi)
            return cb_error_set(err, CB_ERR_INVALID,
                                "%s: v range [%.17g, %.17g] leaves [-pi/2, pi/2]", name, v0, v1);
        return CB_OK;
    case CB_ANALYTIC_TORUS:
        if ((st = check_angle_range(v0, v1, "v", err)))
            return cb_error_prefix(err, "%s: ", name);
        return CB_OK;
    case CB_ANALYTIC_CONE: {
        double apex = -s->r1 / tan(s->angle);
        if (v0 < apex && apex < v1)
            return cb_error_set(err, CB_ERR_INVALID,
                                "cone: v range [%.17g, %.17g] crosses the apex at v = %.17g", v0,
                                v1, apex);
        return CB_OK;
    }
    default: return CB_OK;
    }
}

static cb_status to_nurbs(cb_nurbs_surface_t out, const cb_analytic_surface *s, double u0,
                          double u1, double v0, double v1, int exact, cb_error *err)
{
    cb_status st = check_range(u0, u1, "u", err);
    if (!st)
        st = check_range(v0, v1, "v", err);
    if (st)
        return cb_error_prefix(err, "%s: ", cb_analytic_kind_name(s->kind));
    if (s->kind == CB_ANALYTIC_PLANE)
        return plane_to_nurbs(out, s, u0, u1, v0, v1, err);
    if ((st = check_kind_ranges(s, u0, u1, v0, v1, err)))
        return st;

    /* Parallel: the unit arc in u, scaled by (sx, sy). Profile: control points (rho_j, h_j)
     * with weights wv_j of the meridian, an affine image of the unit arc in v or a line. */
    double cu[ARC_MAX_POINTS][2], wu[ARC_MAX_POINTS], ku[ARC_MAX_POINTS + 3];
    double cv[ARC_MAX_POINTS][2], wv[ARC_MAX_POINTS], kv[ARC_MAX_POINTS + 3];
    double rho[ARC_MAX_POINTS], h[ARC_MAX_POINTS], sx = 1.0, sy = 1.0;
    int nu = 2 * unit_arc(cu, wu, ku, u0, u1, exact) + 1, nv, deg_v;
    if (s->kind == CB_ANALYTIC_CYLINDER || s->kind == CB_ANALYTIC_CONE) {
        /* The radius r + v tan a is linear in v, so a degree-1 profile reproduces it. */
        double ta = s->kind == CB_ANALYTIC_CONE ? tan(s->angle) : 0.0;
        deg_v = 1;
        nv = 2;
        kv[0] = kv[1] = v0;
        kv[2] = kv[3] = v1;
        rho[0] = s->r1 + v0 * ta;
        rho[1] = s->r1 + v1 * ta;
        h[0] = v0;
        h[1] = v1;
        wv[0] = wv[1] = 1.0;
    } else {
        /* rho = A + B cos v, h = C sin v, as in the local parameterisations of analytic.h. */
        double A = 0.0, B = s->r1, C = s->r1;
        if (s->kind == CB_ANALYTIC_TORUS) {
            A = s->r1;
            B = C = s->r2;
        } else if (s->kind == CB_ANALYTIC_ELLIPSOID) {
            B = 1.0;
            C = s->r3;
            sx = s->r1;
            sy = s->r2;
        }
        deg_v = 2;
        nv = 2 * unit_arc(cv, wv, kv, v0, v1, exact) + 1;
        for (int j = 0; j < nv; j++) {
            rho[j] = A + B * cv[j][0];
            h[j] = C * cv[j][1];
        }
    }
    cb_nurbs_surface_t t;
    cb_nurbs_surface_init(t);
    if ((st = cb_nurbs_surface_alloc(t, 2, deg_v, nu, nv, err)))
        return st;
    memcpy(t->knots_u, ku, (size_t)(nu + 3) * sizeof *ku);
    memcpy(t->knots_v, kv, (size_t)(nv + deg_v + 1) * sizeof *kv);
    /* Weights multiply, so the homogeneous surface factors into the two rational curves and the
     * image is exactly (sx rho cos, sy rho sin, h) of their points. */
    for (int i = 0; i < nu; i++)
        for (int j = 0; j < nv; j++) {
            double l[3] = {sx * rho[j] * cu[i][0], sy * rho[j] * cu[i][1], h[j]};
            double *cw = cb_nurbs_surface_cw(t, i, j), w = wu[i] * wv[j];
            cb_frame_to_world(cw, &s->frame, l);
            for (int k = 0; k < 3; k++)
                cw[k] *= w;
            cw[3] = w;
        }
    cb_nurbs_surface_swap(out, t);
    cb_nurbs_surface_clear(t);
    return CB_OK;
}

cb_status cb_analytic_to_nurbs(cb_nurbs_surface_t out, const cb_analytic_surface *s, double u0,
                               double u1, double v0, double v1, cb_error *err)
{
    return to_nurbs(out, s, u0, u1, v0, v1, 0, err);
}

cb_status cb_analytic_to_nurbs_exact(cb_nurbs_surface_t out, const cb_analytic_surface *s,
                                     double u0, double u1, double v0, double v1, cb_error *err)
{
    return to_nurbs(out, s, u0, u1, v0, v1, 1, err);
}
