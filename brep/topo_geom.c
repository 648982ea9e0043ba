/* Geometry of edges and faces: evaluation, rigid motions, nearest points on curves. */
#include <string.h>

#include "brep/topo.h"

static const double TWO_PI = 6.283185307179586;

void cb_topo_curve_init(cb_topo_curve *c)
{
    memset(c, 0, sizeof *c);
    cb_nurbs_curve_init(c->nurbs);
}

void cb_topo_curve_clear(cb_topo_curve *c)
{
    cb_nurbs_curve_clear(c->nurbs);
    cb_topo_curve_init(c);
}

const char *cb_curve_kind_name(cb_curve_kind kind)
{
    switch (kind) {
    case CB_CURVE_LINE: return "line";
    case CB_CURVE_CIRCLE: return "circle";
    case CB_CURVE_ELLIPSE: return "ellipse";
    case CB_CURVE_NURBS: return "bspline";
    }
    return "unknown";
}

/* o + a x + b y + c z of a frame, without the origin when o is 0. */
static void combine(double p[3], const cb_frame *f, int with_origin, double a, double b, double c)
{
    for (int i = 0; i < 3; i++)
        p[i] = (with_origin ? f->o[i] : 0.0) + a * f->x[i] + b * f->y[i] + c * f->z[i];
}

void cb_topo_curve_eval_derivs(double d[3][3], const cb_topo_curve *c, double t)
{
    const cb_frame *f = &c->frame;
    switch (c->kind) {
    case CB_CURVE_LINE:
        combine(d[0], f, 1, 0, 0, t * c->r1);
        combine(d[1], f, 0, 0, 0, c->r1);
        combine(d[2], f, 0, 0, 0, 0);
        return;
    case CB_CURVE_CIRCLE:
    case CB_CURVE_ELLIPSE: {
        double cs = cos(t), sn = sin(t);
        combine(d[0], f, 1, c->r1 * cs, c->r2 * sn, 0);
        combine(d[1], f, 0, -c->r1 * sn, c->r2 * cs, 0);
        combine(d[2], f, 0, -c->r1 * cs, -c->r2 * sn, 0);
        return;
    }
    case CB_CURVE_NURBS: cb_nurbs_curve_eval_derivs(d, c->nurbs, t); return;
    }
}

void cb_topo_curve_eval(double p[3], const cb_topo_curve *c, double t)
{
    if (c->kind == CB_CURVE_NURBS) {
        cb_nurbs_curve_eval(p, c->nurbs, t);
        return;
    }
    double d[3][3];
    cb_topo_curve_eval_derivs(d, c, t);
    memcpy(p, d[0], sizeof d[0]);
}

/* Newton steps on g(t) = |C(t) - p|^2 / 2 from t, kept inside [a, b]; returns the best t. */
static double curve_newton(const cb_topo_curve *c, const double p[3], double t, double a, double b)
{
    double best = t, best_d = HUGE_VAL;
    for (int it = 0; it < 30; it++) {
        double d[3][3], r[3];
        cb_topo_curve_eval_derivs(d, c, t);
        for (int i = 0; i < 3; i++)
            r[i] = d[0][i] - p[i];
        double dist = cb_vec3_norm(r);
        if (dist < best_d) {
            best_d = dist;
            best = t;
        }
        double g = cb_vec3_dot(r, d[1]), h = cb_vec3_dot(d[1], d[1]) + cb_vec3_dot(r, d[2]);
        if (!(h > 0))
            h = cb_vec3_dot(d[1], d[1]);
        if (!(h > 0))
            break;
        double step = g / h, nt = fmin(b, fmax(a, t - step));
        if (fabs(nt - t) <= 1e-15 * (fabs(a) + fabs(b) + 1.0))
            break;
        t = nt;
    }
    return best;
}

double cb_topo_curve_project(double *t, const cb_topo_curve *c, const double p[3], double a,
                             double b)
{
    double l[3], q[3];
    switch (c->kind) {
    case CB_CURVE_LINE:
        cb_frame_to_local(l, &c->frame, p);
        *t = l[2] / c->r1;
        break;
    case CB_CURVE_CIRCLE:
        cb_frame_to_local(l, &c->frame, p);
        *t = atan2(l[1], l[0]);
        if (*t < 0)
            *t += TWO_PI;
        break;
    default: {
        if (c->kind == CB_CURVE_ELLIPSE) {
            a = 0;
            b = TWO_PI;
        } else {
            double lo, hi;
            cb_nurbs_curve_domain(c->nurbs, &lo, &hi);
            a = fmax(a, lo);
            b = fmin(b, hi);
            if (!(a < b)) {
                a = lo;
                b = hi;
            }
        }
        /* Samples: enough per knot span that the nearest one lies in the basin of the true
         * nearest point for curves that do not fold within a span. */
        int n = c->kind == CB_CURVE_NURBS ? 8 * (c->nurbs->n - c->nurbs->deg) + 8 : 64;
        if (n > 2048)
            n = 2048;
        /* Newton starts on the nearest chord of the samples, not at the nearest sample: a
         * closed curve's first and last samples coincide, and from the wrong one the step
         * points out of [a, b] and stays clamped there. */
        double best = a, best_d = HUGE_VAL, prev[3];
        for (int k = 0; k <= n; k++) {
            cb_topo_curve_eval(q, c, a + (b - a) * k / n);
            double l = 0, dist = k ? cb_seg3_nearest(&l, prev, q, p) : HUGE_VAL;
            if (dist < best_d) {
                best_d = dist;
                best = a + (b - a) * (k - 1 + l) / n;
            }
            memcpy(prev, q, sizeof prev);
        }
        *t = curve_newton(c, p, best, a, b);
        if (c->kind == CB_CURVE_ELLIPSE && *t >= TWO_PI)
            *t -= TWO_PI;
    }
    }
    cb_topo_curve_eval(q, c, *t);
    return cb_vec3_dist(q, p);
}

static void transform_frame(cb_frame *f, const cb_xform *x)
{
    cb_xform_apply_point(f->o, x, f->o);
    cb_xform_apply_vector(f->x, x, f->x);
    cb_xform_apply_vector(f->y, x, f->y);
    cb_xform_apply_vector(f->z, x, f->z);
}

void cb_topo_curve_transform(cb_topo_curve *c, const cb_xform *x)
{
    if (c->kind == CB_CURVE_NURBS)
        cb_nurbs_curve_transform(c->nurbs, x);
    else
        transform_frame(&c->frame, x);
}

/* ---------------------------------------------------------------- surfaces ----------------- */

void cb_topo_surface_init(cb_topo_surface *s)
{
    memset(s, 0, sizeof *s);
    cb_nurbs_surface_init(s->nurbs);
    cb_topo_curve_init(&s->profile);
}

void cb_topo_surface_clear(cb_topo_surface *s)
{
    cb_nurbs_surface_clear(s->nurbs);
    cb_topo_curve_clear(&s->profile);
    cb_topo_surface_init(s);
}

const char *cb_topo_surface_type_name(const cb_topo_surface *s)
{
    switch (s->kind) {
    case CB_SURFACE_ANALYTIC: return cb_analytic_kind_name(s->analytic.kind);
    case CB_SURFACE_NURBS: return "bspline";
    case CB_SURFACE_REVOLUTION: return "revolution";
    case CB_SURFACE_EXTRUSION: return "extrusion";
    }
    return "unknown";
}

/* Turns v by the angle u about the unit axis z: the component along z stays, the rest turns
 * (with cos u and sin u given). */
static void turn(double out[3], const double v[3], const double z[3], double cs, double sn)
{
    double along = cb_vec3_dot(v, z), w[3], zw[3];
    for (int i = 0; i < 3; i++)
        w[i] = v[i] - along * z[i];
    cb_vec3_cross(zw, z, w);
    for (int i = 0; i < 3; i++)
        out[i] = along * z[i] + cs * w[i] + sn * zw[i];
}

void cb_topo_surface_eval_derivs(double d[6][3], const cb_topo_surface *s, double u, double v)
{
    switch (s->kind) {
    case CB_SURFACE_ANALYTIC: cb_analytic_eval_derivs(d, &s->analytic, u, v); return;
    case CB_SURFACE_NURBS: cb_nurbs_surface_eval_derivs(d, s->nurbs, u, v); return;
    case CB_SURFACE_REVOLUTION: {
        /* S = o + R(u)(C(v) - o); d/du R(u) w = R(u + pi/2) applied to the part across z. */
        double c[3][3], q[3], cs = cos(u), sn = sin(u);
        const double *z = s->frame.z, *o = s->frame.o;
        cb_topo_curve_eval_derivs(c, &s->profile, v);
        for (int i = 0; i < 3; i++)
            q[i] = c[0][i] - o[i];
        turn(d[0], q, z, cs, sn);
        turn(d[2], c[1], z, cs, sn);
        turn(d[5], c[2], z, cs, sn);
        double qa = cb_vec3_dot(q, z), va = cb_vec3_dot(c[1], z), tmp[3];
        /* The turning part of q and of C': derivatives in u drop the axial part. */
        turn(tmp, q, z, -sn, cs);
        for (int i = 0; i < 3; i++)
            d[1][i] = tmp[i] - qa * z[i];
        turn(tmp, q, z, -cs, -sn);
        for (int i = 0; i < 3; i++)
            d[3][i] = tmp[i] - qa * z[i];
        turn(tmp, c[1], z, -sn, cs);
        for (int i = 0; i < 3; i++)
            d[4][i] = tmp[i] - va * z[i];
        for (int i = 0; i < 3; i++)
            d[0][i] += o[i];
        return;
    }
    case CB_SURFACE_EXTRUSION: {
        double c[3][3];
        cb_topo_curve_eval_derivs(c, &s->profile, u);
        for (int i = 0; i < 3; i++) {
            d[0][i] = c[0][i] + v * s->dir[i];
            d[1][i] = c[1][i];
            d[2][i] = s->dir[i];
            d[3][i] = c[2][i];
            d[4][i] = 0.0;
            d[5][i] = 0.0;
        }
        return;
    }
    }
}

void cb_topo_surface_transform(cb_topo_surface *s, const cb_xform *x)
{
    switch (s->kind) {
    case CB_SURFACE_ANALYTIC: transform_frame(&s->analytic.frame, x); return;
    case CB_SURFACE_NURBS: cb_nurbs_surface_transform(s->nurbs, x); return;
    case CB_SURFACE_REVOLUTION:
    case CB_SURFACE_EXTRUSION:
        cb_topo_curve_transform(&s->profile, x);
        transform_frame(&s->frame, x);
        cb_xform_apply_vector(s->dir, x, s->dir);
        return;
    }
}
