/* Conservative boxes of surfaces over parameter rectangles: control nets of exact or split
 * B-spline forms, and balls swept about an axis or along a direction. */
#include <stdlib.h>
#include <string.h>

#include "brep/face.h"

static const double TWO_PI = 6.28318530717958647692;
static const double HALF_PI = 1.57079632679489661923;

static void box_union(cb_aabb *a, const cb_aabb *b)
{
    for (int i = 0; i < 3; i++) {
        a->lo[i] = fmin(a->lo[i], b->lo[i]);
        a->hi[i] = fmax(a->hi[i], b->hi[i]);
    }
}

static void box_empty(cb_aabb *b)
{
    for (int i = 0; i < 3; i++) {
        b->lo[i] = HUGE_VAL;
        b->hi[i] = -HUGE_VAL;
    }
}

/* Keeps a range non-empty: rational forms reject empty ranges. */
static void widen(double *lo, double *hi)
{
    double m = 1e-12 * (1 + fabs(*lo) + fabs(*hi));
    if (*hi - *lo < m) {
        double c = 0.5 * (*lo + *hi);
        *lo = c - m;
        *hi = c + m;
    }
}

static cb_status analytic_box(cb_aabb *box, const cb_analytic_surface *a, const double uv[4],
                              cb_error *err)
{
    double u0 = uv[0], u1 = uv[1], v0 = uv[2], v1 = uv[3];
    if (a->kind != CB_ANALYTIC_PLANE && u1 - u0 > TWO_PI)
        u1 = u0 + TWO_PI;
    if (a->kind == CB_ANALYTIC_TORUS && v1 - v0 > TWO_PI)
        v1 = v0 + TWO_PI;
    if ((a->kind == CB_ANALYTIC_SPHERE || a->kind == CB_ANALYTIC_ELLIPSOID) &&
        (v0 < -HALF_PI * (1 + 1e-12) || v1 > HALF_PI * (1 + 1e-12))) {
        /* A latitude range past a pole: the whole surface. */
        u0 = 0;
        u1 = TWO_PI;
        v0 = -HALF_PI;
        v1 = HALF_PI;
    }
    widen(&u0, &u1);
    widen(&v0, &v1);
    if (a->kind == CB_ANALYTIC_SPHERE || a->kind == CB_ANALYTIC_ELLIPSOID) {
        v0 = fmax(v0, -HALF_PI);
        v1 = fmin(v1, HALF_PI);
    }
    /* Angular ranges in pieces of at most a quarter turn (a hair more from rounding is
     * absorbed by the rational form's own split), whose control nets hug their arcs. */
    double uc[6], vc[7];
    int nu = 1, nv = 1;
    uc[0] = u0;
    uc[1] = u1;
    vc[0] = v0;
    vc[1] = v1;
    if (a->kind != CB_ANALYTIC_PLANE) {
        nu = (int)fmax(1, ceil((u1 - u0) / HALF_PI - 1e-9));
        for (int k = 0; k <= nu; k++)
            uc[k] = k == nu ? u1 : u0 + (u1 - u0) * k / nu;
    }
    if (a->kind == CB_ANALYTIC_TORUS || a->kind == CB_ANALYTIC_SPHERE ||
        a->kind == CB_ANALYTIC_ELLIPSOID) {
        nv = (int)fmax(1, ceil((v1 - v0) / HALF_PI - 1e-9));
        for (int k = 0; k <= nv; k++)
            vc[k] = k == nv ? v1 : v0 + (v1 - v0) * k / nv;
    }
    if (a->kind == CB_ANALYTIC_CONE) {
        double apex = -a->r1 / tan(a->angle);
        if (apex > v0 && apex < v1) {
            vc[1] = apex;
            vc[2] = v1;
            nv = 2;
        }
    }
    box_empty(box);
    cb_nurbs_surface_t s;
    cb_nurbs_surface_init(s);
    cb_status st = CB_OK;
    for (int i = 0; i < nu && !st; i++)
        for (int j = 0; j < nv && !st; j++) {
            cb_aabb b;
            st = cb_analytic_to_nurbs(s, a, uc[i], uc[i + 1], vc[j], vc[j + 1], err);
            if (!st) {
                cb_nurbs_surface_aabb(&b, s);
                box_union(box, &b);
            }
        }
    cb_nurbs_surface_clear(s);
    return st;
}

/* The sub-patch of s over the rectangle where it lies in the domain; a rectangle reaching out
 * of the domain (a lifted periodic range) takes the whole domain in that direction. */
static cb_status nurbs_box(cb_aabb *box, const cb_nurbs_surface_t s, const double uv[4],
                           cb_error *err)
{
    double dom[4];
    cb_nurbs_surface_domain(s, dom);
    cb_nurbs_surface_t part, rest;
    cb_nurbs_surface_init(part);
    cb_nurbs_surface_init(rest);
    cb_status st = cb_nurbs_surface_set(part, s, err);
    for (int i = 0; i < 2 && !st; i++) {
        double lo = dom[2 * i], hi = dom[2 * i + 1], eps = 1e-9 * (hi - lo);
        if (uv[2 * i] < lo - eps || uv[2 * i + 1] > hi + eps)
            continue;
        if (uv[2 * i] > lo + eps && uv[2 * i] < hi - eps)
            st = cb_nurbs_surface_split(rest, part, part, (cb_dir)i, uv[2 * i], err);
        if (!st && uv[2 * i + 1] < hi - eps && uv[2 * i + 1] > fmax(lo, uv[2 * i]) + eps)
            st = cb_nurbs_surface_split(part, rest, part, (cb_dir)i, uv[2 * i + 1], err);
    }
    if (!st)
        cb_nurbs_surface_aabb(box, part);
    cb_nurbs_surface_clear(part);
    cb_nurbs_surface_clear(rest);
    return st;
}

/* Balls (centre, radius) holding curve c over [t0, t1]: the control points of a B-spline
 * (its whole domain), the chord's midball of a line, the circumscribed ball of a conic. */
typedef struct {
    double c[3], r;
} ball;

static int curve_balls(ball *out, int max, const cb_topo_curve *c, double t0, double t1)
{
    if (c->kind == CB_CURVE_LINE) {
        double p[3], q[3];
        cb_topo_curve_eval(p, c, t0);
        cb_topo_curve_eval(q, c, t1);
        for (int i = 0; i < 3; i++)
            out[0].c[i] = 0.5 * (p[i] + q[i]);
        out[0].r = 0.5 * cb_vec3_dist(p, q);
        return 1;
    }
    if (c->kind != CB_CURVE_NURBS) {
        memcpy(out[0].c, c->frame.o, sizeof out[0].c);
        out[0].r = fmax(c->r1, c->r2);
        return 1;
    }
    int n = c->nurbs->n;
    for (int k = 0; k < n && k < max; k++) {
        const double *w = c->nurbs->cw + 4 * k;
        for (int i = 0; i < 3; i++)
            out[k].c[i] = w[i] / w[3];
        out[k].r = 0;
    }
    return n;
}

static cb_status swept_box(cb_aabb *box, const cb_topo_surface *s, const double uv[4],
                           cb_error *err)
{
    int rev = s->kind == CB_SURFACE_REVOLUTION;
    double t0 = rev ? uv[2] : uv[0], t1 = rev ? uv[3] : uv[1];
    const cb_topo_curve *pc = &s->profile;
    int n = pc->kind == CB_CURVE_NURBS ? pc->nurbs->n : 1;
    ball *bl = malloc((size_t)n * sizeof *bl);
    if (!bl)
        return cb_error_set(err, CB_ERR_NOMEM, "surface box: out of memory");
    n = curve_balls(bl, n, pc, t0, t1);
    box_empty(box);
    for (int k = 0; k < n; k++) {
        cb_aabb b;
        if (rev) {
            const double *o = s->frame.o, *z = s->frame.z;
            double d[3] = {bl[k].c[0] - o[0], bl[k].c[1] - o[1], bl[k].c[2] - o[2]};
            double h = cb_vec3_dot(d, z), r[3] = {d[0] - h * z[0], d[1] - h * z[1],
                                                  d[2] - h * z[2]};
            double rho = cb_vec3_norm(r);
            for (int i = 0; i < 3; i++) {
                double ext = rho * sqrt(fmax(0, 1 - z[i] * z[i])) + bl[k].r;
                b.lo[i] = o[i] + h * z[i] - ext;
                b.hi[i] = o[i] + h * z[i] + ext;
            }
        } else {
            for (int i = 0; i < 3; i++) {
                double a = uv[2] * s->dir[i], c = uv[3] * s->dir[i];
                b.lo[i] = bl[k].c[i] - bl[k].r + fmin(a, c);
                b.hi[i] = bl[k].c[i] + bl[k].r + fmax(a, c);
            }
        }
        box_union(box, &b);
    }
    free(bl);
    return CB_OK;
}

cb_status cb_face_surface_box(cb_aabb *box, const cb_topo_surface *s, const double uv[4],
                              cb_error *err)
{
    for (int i = 0; i < 4; i++)
        if (!isfinite(uv[i]))
            return cb_error_set(err, CB_ERR_INVALID,
                                "surface box: parameter rectangle not finite (%g %g %g %g)",
                                uv[0], uv[1], uv[2], uv[3]);
    cb_status st;
    switch (s->kind) {
    case CB_SURFACE_ANALYTIC:
        st = analytic_box(box, &s->analytic, uv, err);
        break;
    case CB_SURFACE_NURBS:
        st = nurbs_box(box, s->nurbs, uv, err);
        break;
    default:
        st = swept_box(box, s, uv, err);
        break;
    }
    if (st)
        return st;
    /* Evaluated points differ from the control net's hull by their round-off. */
    double m = 0;
    for (int i = 0; i < 3; i++)
        m = fmax(m, fmax(fabs(box->lo[i]), fabs(box->hi[i])));
    for (int i = 0; i < 3; i++) {
        box->lo[i] -= 1e-12 * m;
        box->hi[i] += 1e-12 * m;
    }
    return CB_OK;
}
