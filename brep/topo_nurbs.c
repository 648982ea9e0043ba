/* Exact rational B-spline forms of topology curves and surfaces, and the map from the
 * B-spline's parameters back to the curve's or surface's own. */
#include <math.h>
#include <string.h>

#include "brep/topo.h"

static const double TWO_PI = 6.283185307179586;

cb_status cb_topo_curve_to_nurbs(cb_nurbs_curve_t out, const cb_topo_curve *c, double t0,
                                 double t1, int exact, cb_error *err)
{
    if (c->kind == CB_CURVE_NURBS) {
        double a, b;
        cb_nurbs_curve_domain(c->nurbs, &a, &b);
        cb_nurbs_curve_t tmp, rest;
        cb_nurbs_curve_init(tmp);
        cb_nurbs_curve_init(rest);
        cb_status st = cb_nurbs_curve_set(tmp, c->nurbs, err);
        /* Only a range strictly inside the domain cuts it: the rest keeps its knots, so the
         * parameter stays the curve's own. */
        if (!st && t0 > a && t0 < b)
            st = cb_nurbs_curve_split(rest, tmp, tmp, t0, err);
        if (!st && t1 > fmax(a, t0) && t1 < b)
            st = cb_nurbs_curve_split(tmp, rest, tmp, t1, err);
        if (!st)
            cb_nurbs_curve_swap(out, tmp);
        cb_nurbs_curve_clear(tmp);
        cb_nurbs_curve_clear(rest);
        return st;
    }
    if (!(isfinite(t0) && isfinite(t1) && t0 < t1))
        return cb_error_set(err, CB_ERR_INVALID, "%s: range [%.17g, %.17g] is empty or not finite",
                            cb_curve_kind_name(c->kind), t0, t1);
    if (c->kind == CB_CURVE_LINE) {
        /* Degree 1 through C(t0) and C(t1): linear in t like the line, so the parameter is t. */
        double pts[6], knots[4] = {t0, t0, t1, t1};
        cb_topo_curve_eval(pts, c, t0);
        cb_topo_curve_eval(pts + 3, c, t1);
        return cb_nurbs_curve_make(out, 1, knots, 4, pts, NULL, 2, err);
    }
    if (t1 - t0 > TWO_PI && !(t1 <= t0 + TWO_PI))
        return cb_error_set(err, CB_ERR_INVALID, "%s: range [%.17g, %.17g] is more than a turn",
                            cb_curve_kind_name(c->kind), t0, t1);
    /* The ellipse is the unit circle's affine image: the same arc with scaled axes. A circle
     * is evaluated as the ellipse with r2 (set equal to r1), so it takes the same form. */
    const cb_frame *f = &c->frame;
    double x[3], y[3];
    for (int i = 0; i < 3; i++) {
        x[i] = c->r1 * f->x[i];
        y[i] = c->r2 * f->y[i];
    }
    return exact ? cb_nurbs_curve_arc_exact(out, f->o, x, y, 1.0, t0, t1, err)
                 : cb_nurbs_curve_arc(out, f->o, x, y, 1.0, t0, t1, err);
}

double cb_topo_curve_nurbs_param(const cb_topo_curve *c, double t0, double t1, int exact,
                                 double s)
{
    if (c->kind == CB_CURVE_CIRCLE || c->kind == CB_CURVE_ELLIPSE)
        return cb_nurbs_arc_angle(t0, t1, exact, s);
    return s;
}

/* The profile extruded: S(u, v) = profile(u) + v dir over v in [v0, v1], degree 1 in v (the
 * homogeneous points move by w v dir, so rational profiles stay exact). */
static cb_status extrude(cb_nurbs_surface_t out, const cb_nurbs_curve_t prof, const double dir[3],
                         double v0, double v1, cb_error *err)
{
    if (!(isfinite(v0) && isfinite(v1) && v0 < v1))
        return cb_error_set(err, CB_ERR_INVALID,
                            "extrusion: v range [%.17g, %.17g] is empty or not finite", v0, v1);
    cb_nurbs_surface_t t;
    cb_nurbs_surface_init(t);
    cb_status st = cb_nurbs_surface_alloc(t, prof->deg, 1, prof->n, 2, err);
    if (st)
        return st;
    memcpy(t->knots_u, prof->knots, (size_t)(prof->n + prof->deg + 1) * sizeof(double));
    t->knots_v[0] = t->knots_v[1] = v0;
    t->knots_v[2] = t->knots_v[3] = v1;
    for (int i = 0; i < prof->n; i++) {
        const double *pw = prof->cw + 4 * i;
        for (int j = 0; j < 2; j++) {
            double *cw = cb_nurbs_surface_cw(t, i, j), v = j ? v1 : v0;
            for (int k = 0; k < 3; k++)
                cw[k] = pw[k] + pw[3] * v * dir[k];
            cw[3] = pw[3];
        }
    }
    cb_nurbs_surface_swap(out, t);
    cb_nurbs_surface_clear(t);
    return CB_OK;
}

cb_status cb_topo_surface_to_nurbs(cb_nurbs_surface_t out, const cb_topo_surface *s,
                                   const double range[4], int exact, cb_error *err)
{
    switch (s->kind) {
    case CB_SURFACE_ANALYTIC:
        return exact ? cb_analytic_to_nurbs_exact(out, &s->analytic, range[0], range[1],
                                                  range[2], range[3], err)
                     : cb_analytic_to_nurbs(out, &s->analytic, range[0], range[1], range[2],
                                            range[3], err);
    case CB_SURFACE_NURBS: return cb_nurbs_surface_set(out, s->nurbs, err);
    case CB_SURFACE_REVOLUTION:
    case CB_SURFACE_EXTRUSION: break;
    }
    int rev = s->kind == CB_SURFACE_REVOLUTION;
    const double *pr = range + (rev ? 2 : 0), *sw = range + (rev ? 0 : 2);
    cb_nurbs_curve_t prof;
    cb_nurbs_curve_init(prof);
    cb_status st = cb_topo_curve_to_nurbs(prof, &s->profile, pr[0], pr[1], exact, err);
    if (!st)
        st = rev ? cb_nurbs_surface_revolve(out, prof, s->frame.o, s->frame.z, sw[0], sw[1],
                                            exact, err)
                 : extrude(out, prof, s->dir, sw[0], sw[1], err);
    cb_nurbs_curve_clear(prof);
    if (st)
        cb_error_prefix(err, "%s profile: ", rev ? "revolution" : "extrusion");
    return st;
}

void cb_topo_surface_nurbs_param(double uv[2], const cb_topo_surface *s, const double range[4],
                                 int exact, const double st[2])
{
    double u = st[0], v = st[1];
    switch (s->kind) {
    case CB_SURFACE_ANALYTIC: {
        cb_analytic_kind k = s->analytic.kind;
        if (k != CB_ANALYTIC_PLANE)
            u = cb_nurbs_arc_angle(range[0], range[1], exact, u);
        if (k == CB_ANALYTIC_SPHERE || k == CB_ANALYTIC_ELLIPSOID || k == CB_ANALYTIC_TORUS)
            v = cb_nurbs_arc_angle(range[2], range[3], exact, v);
        break;
    }
    case CB_SURFACE_NURBS: break;
    case CB_SURFACE_REVOLUTION:
        u = cb_nurbs_arc_angle(range[0], range[1], exact, u);
        v = cb_topo_curve_nurbs_param(&s->profile, range[2], range[3], exact, v);
        break;
    case CB_SURFACE_EXTRUSION:
        u = cb_topo_curve_nurbs_param(&s->profile, range[0], range[1], exact, u);
        break;
    }
    uv[0] = u;
    uv[1] = v;
}
