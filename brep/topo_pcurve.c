/* Parameter space of faces: point inversion on surfaces (with periods and seams), the part of
 * a pcurve a coedge uses, and the computation of missing pcurves by projecting edges. */
#include <stdlib.h>
#include <string.h>

#include "brep/topo.h"

static const double PI = 3.14159265358979323846;
static const double TWO_PI = 6.283185307179586;

enum {
    N_STARTS = 3,       /* grid samples tried as Newton starts in a global search */
    N_VERIFY = 16,      /* test points of an exact (line, conic) pcurve */
    MAX_NODES = 20000,  /* Hermite nodes of one pcurve before giving up */
    N_PROFILE = 128     /* profile samples of a global search on revolutions and extrusions */
};

/* ---------------------------------------------------------------- inverter ----------------- */

/* Parameter range and periodicity of a profile curve (revolution v, extrusion u). */
static void profile_range(const cb_topo_curve *c, double tol, double *lo, double *hi,
                          double *period)
{
    *period = 0;
    if (c->kind == CB_CURVE_CIRCLE || c->kind == CB_CURVE_ELLIPSE) {
        *lo = 0;
        *hi = TWO_PI;
        *period = TWO_PI;
    } else if (c->kind == CB_CURVE_NURBS) {
        double a[3], b[3];
        cb_nurbs_curve_domain(c->nurbs, lo, hi);
        cb_topo_curve_eval(a, c, *lo);
        cb_topo_curve_eval(b, c, *hi);
        if (cb_vec3_dist(a, b) <= tol)
            *period = *hi - *lo;
    } else {
        *lo = -HUGE_VAL;
        *hi = HUGE_VAL;
    }
}

/* Whether the B-spline's boundary curves at the two ends of direction dir coincide. */
static int nurbs_closed(const cb_nurbs_surface_t s, const double box[4], int dir, double tol)
{
    for (int k = 0; k <= 8; k++) {
        double a[3], b[3], w = box[2 - 2 * dir] + (box[3 - 2 * dir] - box[2 - 2 * dir]) * k / 8;
        if (dir == 0) {
            cb_nurbs_surface_eval(a, s, box[0], w);
            cb_nurbs_surface_eval(b, s, box[1], w);
        } else {
            cb_nurbs_surface_eval(a, s, w, box[2]);
            cb_nurbs_surface_eval(b, s, w, box[3]);
        }
        if (cb_vec3_dist(a, b) > tol)
            return 0;
    }
    return 1;
}

cb_status cb_topo_inverter_init(cb_topo_inverter *inv, const cb_topo_surface *s, double tol,
                                cb_error *err)
{
    memset(inv, 0, sizeof *inv);
    inv->s = s;
    double box[4] = {-HUGE_VAL, HUGE_VAL, -HUGE_VAL, HUGE_VAL};
    switch (s->kind) {
    case CB_SURFACE_ANALYTIC:
        if (s->analytic.kind != CB_ANALYTIC_PLANE) {
            box[0] = 0;
            box[1] = inv->period[0] = TWO_PI;
        }
        if (s->analytic.kind == CB_ANALYTIC_SPHERE || s->analytic.kind == CB_ANALYTIC_ELLIPSOID) {
            box[2] = -0.5 * PI;
            box[3] = 0.5 * PI;
        } else if (s->analytic.kind == CB_ANALYTIC_TORUS) {
            box[2] = 0;
            box[3] = inv->period[1] = TWO_PI;
        }
        break;
    case CB_SURFACE_NURBS:
        cb_nurbs_surface_domain(s->nurbs, box);
        for (int d = 0; d < 2; d++)
            if (nurbs_closed(s->nurbs, box, d, tol))
                inv->period[d] = box[2 * d + 1] - box[2 * d];
        break;
    case CB_SURFACE_REVOLUTION:
        box[0] = 0;
        box[1] = inv->period[0] = TWO_PI;
        profile_range(&s->profile, tol, &box[2], &box[3], &inv->period[1]);
        break;
    case CB_SURFACE_EXTRUSION:
        profile_range(&s->profile, tol, &box[0], &box[1], &inv->period[0]);
        break;
    }
    memcpy(inv->box, box, sizeof box);
    memcpy(inv->lift, inv->period, sizeof inv->lift);
    if (s->kind == CB_SURFACE_ANALYTIC &&
        (s->analytic.kind == CB_ANALYTIC_SPHERE || s->analytic.kind == CB_ANALYTIC_ELLIPSOID))
        inv->lift[1] = TWO_PI;
    return cb_topo_projector_init(&inv->pr, s, err);
}

void cb_topo_inverter_clear(cb_topo_inverter *inv)
{
    cb_topo_projector_clear(&inv->pr);
    memset(inv, 0, sizeof *inv);
}

/* x moved by whole periods into [lo, lo + period). */
static double wrap(double x, double lo, double period)
{
    return x - period * floor((x - lo) / period);
}

/* Whether direction d evaluates a B-spline parameter, which must be wrapped into its domain;
 * the angles of analytic surfaces and revolutions are periodic by themselves. */
static int needs_wrap(const cb_topo_inverter *inv, int d)
{
    const cb_topo_surface *s = inv->s;
    if (!(inv->period[d] > 0))
        return 0;
    if (s->kind == CB_SURFACE_NURBS)
        return 1;
    int profile_dir = s->kind == CB_SURFACE_REVOLUTION ? 1 : 0;
    return (s->kind == CB_SURFACE_REVOLUTION || s->kind == CB_SURFACE_EXTRUSION) &&
           d == profile_dir && s->profile.kind == CB_CURVE_NURBS;
}

void cb_topo_inverter_eval_derivs(double d[6][3], const cb_topo_inverter *inv, double u,
                                  double v)
{
    if (needs_wrap(inv, 0))
        u = wrap(u, inv->box[0], inv->period[0]);
    if (needs_wrap(inv, 1))
        v = wrap(v, inv->box[2], inv->period[1]);
    cb_topo_surface_eval_derivs(d, inv->s, u, v);
}

void cb_topo_inverter_eval(double p[3], const cb_topo_inverter *inv, double u, double v)
{
    double d[6][3];
    cb_topo_inverter_eval_derivs(d, inv, u, v);
    memcpy(p, d[0], sizeof d[0]);
}

/* The inner knot of direction k of a B-spline surface where it is only C0 (multiplicity >=
 * degree: a crease, e.g. the corner of an extruded polyline) within 1e-4 of the knot range of
 * x, in *knot: 1; else 0. */
static int near_crease(double *knot, const cb_topo_surface *s, int k, double x)
{
    if (s->kind != CB_SURFACE_NURBS)
        return 0;
    const cb_nurbs_surface_struct *n = s->nurbs;
    int deg = k ? n->deg_v : n->deg_u, m = (k ? n->n_v : n->n_u) + deg + 1;
    const double *kn = k ? n->knots_v : n->knots_u;
    double near = 1e-4 * (kn[m - 1] - kn[0]);
    for (int i = deg + 1; i < m - deg - 1;) {
        int j = i;
        while (j + 1 < m - deg - 1 && kn[j + 1] == kn[i])
            j++;
        if (j - i + 1 >= deg && fabs(x - kn[i]) <= near) {
            *knot = kn[i];
            return 1;
        }
        i = j + 1;
    }
    return 0;
}

static double newton_from(double uv[2], const cb_topo_inverter *inv, const double p[3],
                          int retry);

/* Newton steps on |S(u, v) - p|^2 / 2 from uv; non-periodic parameters stay in the box and a
 * periodic one moves at most a quarter period per step (so a start near the answer keeps its
 * lift). Leaves the best point met in uv and returns its distance. */
static double newton(double uv[2], const cb_topo_inverter *inv, const double p[3])
{
    return newton_from(uv, inv, p, 1);
}

/* newton; retry: where it stops short of p at a crease (the derivatives there are those of
 * one span, which need not lead towards p at all: a start a rounding above the corner of an
 * extruded polyline cannot move along the face below it), start again just below and just
 * above it. */
static double newton_from(double uv[2], const cb_topo_inverter *inv, const double p[3],
                          int retry)
{
    double u = uv[0], v = uv[1], best = HUGE_VAL;
    for (int it = 0; it < 40; it++) {
        double d[6][3], r[3];
        cb_topo_inverter_eval_derivs(d, inv, u, v);
        for (int i = 0; i < 3; i++)
            r[i] = d[0][i] - p[i];
        double dist = cb_vec3_norm(r);
        if (dist < best) {
            best = dist;
            uv[0] = u;
            uv[1] = v;
        }
        double gu = cb_vec3_dot(r, d[1]), gv = cb_vec3_dot(r, d[2]);
        double a = cb_vec3_dot(d[1], d[1]), b = cb_vec3_dot(d[1], d[2]),
               c = cb_vec3_dot(d[2], d[2]);
        double ha = a + cb_vec3_dot(r, d[3]), hb = b + cb_vec3_dot(r, d[4]),
               hc = c + cb_vec3_dot(r, d[5]);
        if (!(ha > 0 && ha * hc - hb * hb > 0)) {
            ha = a;
            hb = b;
            hc = c;
        }
        double det = ha * hc - hb * hb;
        if (!(det > 1e-300))
            break;
        double step[2] = {(hc * gu - hb * gv) / det, (ha * gv - hb * gu) / det}, x[2] = {u, v};
        double moved = 0;
        for (int k = 0; k < 2; k++) {
            double s = step[k];
            if (inv->period[k] > 0)
                s = fmax(-0.25 * inv->period[k], fmin(0.25 * inv->period[k], s));
            double nx = x[k] - s;
            if (!(inv->period[k] > 0))
                nx = fmin(inv->box[2 * k + 1], fmax(inv->box[2 * k], nx));
            moved += fabs(nx - x[k]) * sqrt(k ? c : a);
            x[k] = nx;
        }
        u = x[0];
        v = x[1];
        if (moved <= 1e-15 * (cb_vec3_norm(d[0]) + 1.0))
            break;
    }
    if (retry && best > 1e-9 * (cb_vec3_norm(p) + 1.0))
        for (int k = 0; k < 2; k++) {
            double lo = inv->box[2 * k], hi = inv->box[2 * k + 1], knot;
            if (!near_crease(&knot, inv->s, k, uv[k]) || !(hi > lo))
                continue;
            double at[2] = {uv[0], uv[1]};
            for (int side = -1; side <= 1; side += 2) {
                double w[2] = {at[0], at[1]};
                w[k] = knot + side * 1e-6 * (hi - lo);
                double d = newton_from(w, inv, p, 0);
                if (d < best) {
                    best = d;
                    memcpy(uv, w, sizeof w);
                }
            }
        }
    return best;
}

/* Closed form for the analytic surfaces but the ellipsoid: writes uv, leaves a parameter the
 * point does not determine (on the axis, on a torus core circle) at its value in uv, and
 * returns 1; 0 for the other surfaces. */
static int closed_form(double uv[2], const cb_topo_surface *s, const double p[3])
{
    if (s->kind != CB_SURFACE_ANALYTIC || s->analytic.kind == CB_ANALYTIC_ELLIPSOID)
        return 0;
    const cb_analytic_surface *a = &s->analytic;
    double l[3];
    cb_frame_to_local(l, &a->frame, p);
    double rho = hypot(l[0], l[1]);
    /* Below this the angle about the axis is lost in the rounding of l. */
    int on_axis = rho <= 1e-13 * (cb_vec3_norm(l) + a->r1);
    if (a->kind == CB_ANALYTIC_PLANE) {
        uv[0] = l[0];
        uv[1] = l[1];
        return 1;
    }
    if (!on_axis)
        uv[0] = atan2(l[1], l[0]);
    switch (a->kind) {
    case CB_ANALYTIC_CYLINDER: uv[1] = l[2]; break;
    case CB_ANALYTIC_CONE: {
        /* Foot on the generator (r + v tan a, v) of the meridian half plane holding p, or of
         * the opposite one, whichever is nearer: the cone has two nappes, and on the far one
         * (r + v tan a < 0: screw.step's face 6) the point lies across the axis from the
         * generator of its angle, half a turn round. The distances are the projector's. */
        double sa = sin(a->angle), ca = cos(a->angle);
        double s = rho;
        if (fabs((-rho - a->r1) * ca - l[2] * sa) < fabs((rho - a->r1) * ca - l[2] * sa)) {
            s = -rho;
            if (!on_axis)
                uv[0] = atan2(-l[1], -l[0]);
        }
        uv[1] = (s - a->r1) * sa * ca + l[2] * ca * ca;
        break;
    }
    case CB_ANALYTIC_SPHERE: uv[1] = atan2(l[2], rho); break;
    case CB_ANALYTIC_TORUS:
        if (a->r1 < a->r2 && fabs(hypot(rho + a->r1, l[2]) - a->r2) + 1e-9 * a->r2 <
                                 fabs(hypot(rho - a->r1, l[2]) - a->r2)) {
            /* The lemon of a spindle torus (R + r cos v < 0): the point lies across the
             * axis from its tube circle, half a turn round. (Near the axis, where the two
             * meet, the apple's parameters as for any torus.) */
            if (!on_axis)
                uv[0] = atan2(-l[1], -l[0]);
            uv[1] = atan2(l[2], -rho - a->r1);
        } else if (fabs(rho - a->r1) + fabs(l[2]) > 1e-13 * a->r1) {
            uv[1] = atan2(l[2], rho - a->r1);
        }
        break;
    default: break;
    }
    return 1;
}

/* Global start for revolutions and extrusions: the profile sampled, the other parameter in
 * closed form per sample (the angle turning the sample towards p; the offset along the
 * extrusion direction). */
static void profile_start(double uv[2], const cb_topo_inverter *inv, const double p[3])
{
    const cb_topo_surface *s = inv->s;
    const cb_topo_curve *c = &s->profile;
    int rev = s->kind == CB_SURFACE_REVOLUTION;
    double lo = inv->box[rev ? 2 : 0], hi = inv->box[rev ? 3 : 1];
    if (c->kind == CB_CURVE_LINE) {
        double t, q[3];
        double d0 = cb_topo_curve_project(&t, c, p, 0, 0);
        cb_topo_curve_eval(q, c, t);
        double reach = (2 * d0 + cb_vec3_dist(q, s->frame.o) + cb_vec3_dist(p, s->frame.o)) /
                           c->r1 + 1.0;
        lo = t - reach;
        hi = t + reach;
    }
    double best = HUGE_VAL, dd[3];
    memcpy(dd, s->dir, sizeof dd);
    double dd2 = cb_vec3_dot(dd, dd);
    for (int k = 0; k <= N_PROFILE; k++) {
        double t = lo + (hi - lo) * k / N_PROFILE, q[3], w[2], d[6][3];
        cb_topo_curve_eval(q, c, t);
        if (rev) {
            const double *z = s->frame.z, *o = s->frame.o;
            double a[3], b[3], x[3];
            for (int i = 0; i < 3; i++) {
                a[i] = q[i] - o[i];
                b[i] = p[i] - o[i];
            }
            double ha = cb_vec3_dot(a, z), hb = cb_vec3_dot(b, z);
            for (int i = 0; i < 3; i++) {
                a[i] -= ha * z[i];
                b[i] -= hb * z[i];
            }
            cb_vec3_cross(x, a, b);
            w[0] = atan2(cb_vec3_dot(x, z), cb_vec3_dot(a, b));
            w[1] = t;
        } else {
            double g[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
            w[0] = t;
            w[1] = dd2 > 0 ? cb_vec3_dot(g, dd) / dd2 : 0;
        }
        cb_topo_inverter_eval_derivs(d, inv, w[0], w[1]);
        double dist = cb_vec3_dist(d[0], p);
        if (dist < best) {
            best = dist;
            uv[0] = w[0];
            uv[1] = w[1];
        }
    }
}

/* Global search: closed form, or the best Newton result from the starts. */
static double invert_global(double uv[2], const cb_topo_inverter *inv, const double p[3])
{
    const cb_topo_surface *s = inv->s;
    if (closed_form(uv, s, p)) {
        double q[3];
        cb_topo_inverter_eval(q, inv, uv[0], uv[1]);
        return cb_vec3_dist(q, p);
    }
    const cb_topo_projector *pr = &inv->pr;
    if (!pr->grid) {
        profile_start(uv, inv, p);
        return newton(uv, inv, p);
    }
    double starts[N_STARTS][2];
    int n = cb_topo_projector_starts(starts, N_STARTS, pr, p);
    double best = HUGE_VAL;
    for (int j = 0; j < n; j++) {
        double w[2] = {starts[j][0], starts[j][1]};
        double d = newton(w, inv, p);
        if (d < best) {
            best = d;
            uv[0] = w[0];
            uv[1] = w[1];
        }
    }
    return best;
}

/* Shifts the periodic parameters of uv by whole periods to the lift nearest ref. */
static void lift_near(double uv[2], const cb_topo_inverter *inv, const double ref[2])
{
    for (int k = 0; k < 2; k++)
        if (inv->period[k] > 0)
            uv[k] += inv->period[k] * round((ref[k] - uv[k]) / inv->period[k]);
}

double cb_topo_inverter_invert(double uv[2], const cb_topo_inverter *inv, const double p[3],
                               const double guess[2])
{
    if (!guess) {
        /* A parameter the point leaves free (u at a pole) starts at the box's low end. */
        uv[0] = isfinite(inv->box[0]) ? inv->box[0] : 0;
        uv[1] = isfinite(inv->box[2]) ? inv->box[2] : 0;
        double d = invert_global(uv, inv, p);
        for (int k = 0; k < 2; k++)
            if (inv->period[k] > 0)
                uv[k] = wrap(uv[k], inv->box[2 * k], inv->period[k]);
        return d;
    }
    double w[2] = {guess[0], guess[1]}, q[3];
    if (closed_form(w, inv->s, p)) {
        lift_near(w, inv, guess);
        memcpy(uv, w, sizeof w);
        cb_topo_inverter_eval(q, inv, uv[0], uv[1]);
        return cb_vec3_dist(q, p);
    }
    double local = newton(w, inv, p);
    /* A local minimum farther than the global one: the guess was in the wrong basin. */
    double g[2] = {guess[0], guess[1]}, global = local;
    if (local > 1e-9 * (cb_vec3_norm(p) + 1.0))
        global = invert_global(g, inv, p);
    if (global < 0.5 * local) {
        lift_near(g, inv, guess);
        memcpy(uv, g, sizeof g);
        return global;
    }
    memcpy(uv, w, sizeof w);
    return local;
}

/* ---------------------------------------------------------------- 2D curves ---------------- */

/* Moves a 2D curve by (du, dv). */
static void shift_curve(cb_topo_curve *c, double du, double dv)
{
    if (c->kind != CB_CURVE_NURBS) {
        c->frame.o[0] += du;
        c->frame.o[1] += dv;
        return;
    }
    for (int k = 0; k < c->nurbs->n; k++) {
        double *q = c->nurbs->cw + 4 * k;
        q[0] += q[3] * du;
        q[1] += q[3] * dv;
    }
}

/* The 2D segment from a (at t0) to b (at t1) as a line, or a constant degree-1 B-spline when
 * a = b. */
static cb_status make_segment(cb_topo_curve *c, const double a[2], const double b[2], double t0,
                              double t1, cb_error *err)
{
    double dir[3] = {b[0] - a[0], b[1] - a[1], 0};
    double len = cb_vec3_normalize(dir);
    cb_topo_curve_clear(c);
    if (len > 0) {
        c->kind = CB_CURVE_LINE;
        c->r1 = len / (t1 - t0);
        memcpy(c->frame.z, dir, sizeof dir);
        double x[3] = {-dir[1], dir[0], 0}, y[3] = {0, 0, 1};
        memcpy(c->frame.x, x, sizeof x);
        memcpy(c->frame.y, y, sizeof y);
        c->frame.o[0] = a[0] - t0 * c->r1 * dir[0];
        c->frame.o[1] = a[1] - t0 * c->r1 * dir[1];
        c->frame.o[2] = 0;
        return CB_OK;
    }
    double knots[4] = {t0, t0, t1, t1}, pts[6] = {a[0], a[1], 0, a[0], a[1], 0};
    c->kind = CB_CURVE_NURBS;
    return cb_nurbs_curve_make(c->nurbs, 1, knots, 4, pts, NULL, 2, err);
}

/* ---------------------------------------------------------------- one pcurve --------------- */

typedef struct {
    double t, uv[2], d[2];
} node;

/* Foot of C(t) on the surface, tracked from guess; the surface point is written to foot. */
static void foot_at(double uv[2], double foot[3], const cb_topo_inverter *inv,
                    const cb_topo_curve *cv, double t, const double guess[2])
{
    double p[3];
    cb_topo_curve_eval(p, cv, t);
    cb_topo_inverter_invert(uv, inv, p, guess);
    cb_topo_inverter_eval(foot, inv, uv[0], uv[1]);
}

/* d(uv)/dt at node n: S_u u' + S_v v' = C'(t) in the least-squares sense, by the
 * pseudo-inverse of J^T J so a singular Jacobian (pole) gives the minimum-norm rate. */
static void node_rate(node *n, const cb_topo_inverter *inv, const cb_topo_curve *cv)
{
    double c[3][3], d[6][3];
    cb_topo_curve_eval_derivs(c, cv, n->t);
    cb_topo_inverter_eval_derivs(d, inv, n->uv[0], n->uv[1]);
    double a = cb_vec3_dot(d[1], d[1]), b = cb_vec3_dot(d[1], d[2]), e = cb_vec3_dot(d[2], d[2]);
    double g[2] = {cb_vec3_dot(d[1], c[1]), cb_vec3_dot(d[2], c[1])}, det = a * e - b * b;
    if (det > 1e-10 * (a + e) * (a + e)) {
        n->d[0] = (e * g[0] - b * g[1]) / det;
        n->d[1] = (a * g[1] - b * g[0]) / det;
        return;
    }
    /* Rank one: M ~ lambda q q^T with q the dominant column direction. */
    double q[2] = {a >= e ? a : b, a >= e ? b : e}, len = hypot(q[0], q[1]), lam = a + e;
    n->d[0] = n->d[1] = 0;
    if (len > 0 && lam > 0) {
        q[0] /= len;
        q[1] /= len;
        double s = (q[0] * g[0] + q[1] * g[1]) / lam;
        n->d[0] = s * q[0];
        n->d[1] = s * q[1];
    }
}

/* Cubic Hermite value between nodes a and b at t. */
static void hermite(double uv[2], const node *a, const node *b, double t)
{
    double h = b->t - a->t, s = (t - a->t) / h, s2 = s * s, s3 = s2 * s;
    double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2,
           h11 = s3 - s2;
    for (int k = 0; k < 2; k++)
        uv[k] = h00 * a->uv[k] + h10 * h * a->d[k] + h01 * b->uv[k] + h11 * h * b->d[k];
}

int cb_topo_inverter_collapsed(const cb_topo_inverter *inv, double u, double v)
{
    double dd[6][3];
    cb_topo_inverter_eval_derivs(dd, inv, u, v);
    int bits = 0;
    for (int d = 0; d < 2; d++)
        if (cb_vec3_norm(dd[1 + d]) <= 1e-9 * cb_vec3_norm(dd[2 - d]))
            bits |= 1 << d;
    return bits;
}

void cb_topo_settle_poles(double *uv, size_t stride, int n, const cb_topo_inverter *inv)
{
#define UV(k) ((double *)((char *)uv + (size_t)(k) * stride))
    for (int d = 0; d < 2; d++)
        for (int k = 0; k < n;) {
            int e = k;
            for (; e < n; e++)
                if (!(cb_topo_inverter_collapsed(inv, UV(e)[0], UV(e)[1]) & (1 << d)))
                    break;
            /* points k .. e - 1 collapse in direction d */
            int from = k > 0 ? k - 1 : e < n ? e : -1;
            for (int j = k; j < e && from >= 0; j++)
                UV(j)[d] = UV(from)[d];
            k = e > k ? e : k + 1;
        }
#undef UV
}

/* Largest |S(q(t)) - foot(t)| over n test points of a candidate exact pcurve q on [t0, t1]. */
static double exact_deviation(const cb_topo_curve *q, const cb_topo_inverter *inv,
                              const cb_topo_curve *cv, double t0, double t1, int n)
{
    double worst = 0;
    for (int k = 0; k <= n; k++) {
        double t = t0 + (t1 - t0) * (k + 0.5) / (n + 1), w[3], uv[2], foot[3], p[3];
        cb_topo_curve_eval(w, q, t);
        foot_at(uv, foot, inv, cv, t, w);
        cb_topo_inverter_eval(p, inv, w[0], w[1]);
        worst = fmax(worst, cb_vec3_dist(p, foot));
    }
    return worst;
}

/* Largest |S(q(t)) - C(t)| of the Hermite cubic q between nodes a and b, against the curve
 * itself, at the piece's quarter points. */
static double bridge_deviation(const node *a, const node *b, const cb_topo_inverter *inv,
                               const cb_topo_curve *cv)
{
    double worst = 0;
    for (int j = 1; j <= 3; j++) {
        double t = a->t + 0.25 * j * (b->t - a->t), w[2], p[3], c[3];
        hermite(w, a, b, t);
        cb_topo_inverter_eval(p, inv, w[0], w[1]);
        cb_topo_curve_eval(c, cv, t);
        worst = fmax(worst, cb_vec3_dist(p, c));
    }
    return worst;
}

/* A conic on a plane is the same conic in the plane's (u, v): centre and axes in the plane's
 * local coordinates, parameter unchanged. */
static int plane_conic(cb_topo_curve *out, const cb_topo_surface *s, const cb_topo_curve *cv)
{
    if (s->kind != CB_SURFACE_ANALYTIC || s->analytic.kind != CB_ANALYTIC_PLANE ||
        (cv->kind != CB_CURVE_CIRCLE && cv->kind != CB_CURVE_ELLIPSE))
        return 0;
    const cb_frame *f = &s->analytic.frame;
    double o[3];
    cb_frame_to_local(o, f, cv->frame.o);
    cb_topo_curve_clear(out);
    out->kind = cv->kind;
    out->r1 = cv->r1;
    out->r2 = cv->r2;
    out->frame.o[0] = o[0];
    out->frame.o[1] = o[1];
    out->frame.x[0] = cb_vec3_dot(cv->frame.x, f->x);
    out->frame.x[1] = cb_vec3_dot(cv->frame.x, f->y);
    out->frame.y[0] = cb_vec3_dot(cv->frame.y, f->x);
    out->frame.y[1] = cb_vec3_dot(cv->frame.y, f->y);
    cb_vec3_cross(out->frame.z, out->frame.x, out->frame.y);
    return 1;
}

/* Initial sample parameters of [t0, t1]: the knots of a B-spline edge, at most pi/4 of a conic,
 * else quarters. Returns the count (>= 2) written to t (capacity cap). */
static int initial_params(double *t, int cap, const cb_topo_curve *cv, double t0, double t1)
{
    int n = 4;
    if (cv->kind == CB_CURVE_CIRCLE || cv->kind == CB_CURVE_ELLIPSE)
        n = (int)ceil((t1 - t0) / (0.25 * PI));
    if (n < 4)
        n = 4;
    int m = 0;
    if (cv->kind == CB_CURVE_NURBS && cv->nurbs->n - cv->nurbs->deg + 1 <= cap - 8) {
        const cb_nurbs_curve_struct *c = cv->nurbs;
        t[m++] = t0;
        for (int k = c->deg + 1; k < c->n; k++)
            if (c->knots[k] > t[m - 1] && c->knots[k] < t1)
                t[m++] = c->knots[k];
        t[m++] = t1;
        if (m >= 5)
            return m;
        m = 0;
    }
    for (int k = 0; k <= n; k++)
        t[m++] = t0 + (t1 - t0) * k / n;
    return m;
}

/* Appends a node to the growable array. */
static cb_status push_node(node **nd, int *n, int *cap, int at, const node *x, cb_error *err)
{
    if (*n == *cap) {
        int c = 2 * *cap;
        node *p = realloc(*nd, (size_t)c * sizeof *p);
        if (!p)
            return cb_error_set(err, CB_ERR_NOMEM, "pcurve: out of memory");
        *nd = p;
        *cap = c;
    }
    memmove(*nd + at + 1, *nd + at, (size_t)(*n - at) * sizeof **nd);
    (*nd)[at] = *x;
    (*n)++;
    return CB_OK;
}

/* The pcurve of edge e on the surface of inv, parameterised like the edge curve over
 * [t0, t1]; written to out (initialised). */
static cb_status edge_pcurve(cb_topo_curve *out, const cb_topo_body *b, int e,
                             const cb_topo_inverter *inv, double tol, cb_error *err)
{
    const cb_topo_edge *ed = &b->edges[e];
    const cb_topo_curve *cv = &b->curves[ed->curve];
    double t0 = ed->t0, t1 = ed->t1, ts[1024], etol = fmax(tol, ed->tol);
    int n = initial_params(ts, 1024, cv, t0, t1), cap = 64 > 2 * n ? 64 : 2 * n;
    node *nd = malloc((size_t)cap * sizeof *nd);
    if (!nd)
        return cb_error_set(err, CB_ERR_NOMEM, "pcurve: out of memory");
    double foot[3];
    for (int k = 0; k < n; k++) {
        nd[k].t = ts[k];
        foot_at(nd[k].uv, foot, inv, cv, ts[k], k ? nd[k - 1].uv : NULL);
    }
    cb_topo_settle_poles(nd[0].uv, sizeof *nd, n, inv);
    cb_status st = CB_OK;
    /* Exact forms first: they are tested like the fit, so a miss only costs the test. */
    if (plane_conic(out, inv->s, cv) && exact_deviation(out, inv, cv, t0, t1, N_VERIFY) <= tol)
        goto done;
    if ((st = make_segment(out, nd[0].uv, nd[n - 1].uv, t0, t1, err)))
        goto done;
    if (exact_deviation(out, inv, cv, t0, t1, N_VERIFY) <= tol)
        goto done;
    for (int k = 0; k < n; k++)
        node_rate(&nd[k], inv, cv);
    /* Bisect pieces until the Hermite cubic meets the feet at its three test points. */
    for (int k = 0; k + 1 < n && !st;) {
        double worst = 0, h = nd[k + 1].t - nd[k].t;
        for (int j = 1; j <= 3; j++) {
            double t = nd[k].t + 0.25 * j * h, w[2], uv[2], p[3];
            hermite(w, &nd[k], &nd[k + 1], t);
            foot_at(uv, foot, inv, cv, t, w);
            cb_topo_inverter_eval(p, inv, w[0], w[1]);
            worst = fmax(worst, cb_vec3_dist(p, foot));
        }
        if (worst <= tol) {
            k++;
            continue;
        }
        int tiny = h <= 1e-12 * (t1 - t0);
        if (tiny && bridge_deviation(&nd[k], &nd[k + 1], inv, cv) <= etol) {
            /* The feet jump here (the curve passes a concave crease of the surface off it,
             * equidistant from both sheets): a piece the bisection cannot shorten further
             * is kept where it stays within the edge's tolerance of the curve itself. */
            k++;
            continue;
        }
        if (tiny || n >= MAX_NODES) {
            st = cb_error_set(err, CB_ERR_NUMERIC,
                              "edge %d: pcurve fit stuck at t = %g (deviation %.3g > %.3g): no "
                              "continuous image in the parameter plane",
                              e, nd[k].t, worst, tol);
            break;
        }
        node mid;
        mid.t = nd[k].t + 0.5 * h;
        hermite(mid.uv, &nd[k], &nd[k + 1], mid.t);
        foot_at(mid.uv, foot, inv, cv, mid.t, mid.uv);
        node_rate(&mid, inv, cv);
        st = push_node(&nd, &n, &cap, k + 1, &mid, err);
    }
    if (!st) {
        int np = 3 * (n - 1) + 1, nk = np + 4;
        double *pts = malloc((size_t)np * 3 * sizeof *pts), *kn = malloc((size_t)nk * sizeof *kn);
        if (!pts || !kn) {
            st = cb_error_set(err, CB_ERR_NOMEM, "pcurve: out of memory");
        } else {
            for (int j = 0; j < 4; j++) {
                kn[j] = t0;
                kn[nk - 1 - j] = t1;
            }
            for (int k = 1; k + 1 < n; k++)
                for (int j = 0; j < 3; j++)
                    kn[4 + 3 * (k - 1) + j] = nd[k].t;
            for (int k = 0; k + 1 < n; k++) {
                double h = nd[k + 1].t - nd[k].t, *q = pts + 9 * k;
                for (int i = 0; i < 2; i++) {
                    q[i] = nd[k].uv[i];
                    q[3 + i] = nd[k].uv[i] + h / 3 * nd[k].d[i];
                    q[6 + i] = nd[k + 1].uv[i] - h / 3 * nd[k + 1].d[i];
                    q[9 + i] = nd[k + 1].uv[i];
                }
                q[2] = q[5] = q[8] = q[11] = 0;
            }
            cb_topo_curve_clear(out);
            out->kind = CB_CURVE_NURBS;
            st = cb_nurbs_curve_make(out->nurbs, 3, kn, nk, pts, NULL, np, err);
        }
        free(pts);
        free(kn);
    }
done:
    free(nd);
    return st;
}

/* ---------------------------------------------------------------- coedge range ------------- */

void cb_topo_pcurve_eval(double uv[3], const cb_topo_curve *pc, double s)
{
    if (pc->kind == CB_CURVE_NURBS) {
        double lo, hi;
        cb_nurbs_curve_domain(pc->nurbs, &lo, &hi);
        /* Only a closed pcurve wraps, and only on a real overrun: an edge range may exceed an
         * open pcurve's domain by its own rounding, which evaluation clamps. */
        double slack = 1e-9 * (hi - lo), a[3], z[3];
        if (s < lo - slack || s > hi + slack) {
            cb_nurbs_curve_eval(a, pc->nurbs, lo);
            cb_nurbs_curve_eval(z, pc->nurbs, hi);
            if (cb_vec3_dist(a, z) <= 1e-12 * (fabs(a[0]) + fabs(a[1]) + 1.0))
                s = wrap(s, lo, hi - lo);
        }
    }
    cb_topo_curve_eval(uv, pc, s);
}

double cb_topo_edge_distance(const cb_topo_body *b, int e, const double p[3])
{
    const cb_topo_edge *ed = &b->edges[e];
    const cb_topo_curve *cv = &b->curves[ed->curve];
    double t, q[3];
    double d = cb_topo_curve_project(&t, cv, p, ed->t0, ed->t1);
    if (cv->kind == CB_CURVE_NURBS)
        return d;
    /* Lines and conics were searched whole: outside the edge's range the nearest edge point
     * is an end. */
    if (cv->kind != CB_CURVE_LINE)
        t = ed->t0 + wrap(t - ed->t0, 0, TWO_PI);
    if (t >= ed->t0 && t <= ed->t1)
        return d;
    cb_topo_curve_eval(q, cv, ed->t0);
    d = cb_vec3_dist(q, p);
    cb_topo_curve_eval(q, cv, ed->t1);
    return fmin(d, cb_vec3_dist(q, p));
}

/* 3D distance from p to the surface point of pcurve pc at s. */
static double image_gap(const cb_topo_curve *pc, const cb_topo_inverter *inv, const double p[3],
                        double s)
{
    double w[3], q[3];
    cb_topo_pcurve_eval(w, pc, s);
    cb_topo_inverter_eval(q, inv, w[0], w[1]);
    return cb_vec3_dist(q, p);
}

/* Projects the 3D point p onto the image of 2D curve pc on the surface. Starts: the nearest
 * pcurve point in (u, v) to the lifts of p's inversion, and for a bounded pcurve 64 samples of
 * [lo, hi] (the (u, v) metric can be far from the 3D one near a collapsed boundary); the best
 * is refined by golden-section search on the 3D distance. Returns that distance. A line
 * pcurve on a periodic surface passes over p once per period, at distances equal up to
 * rounding: among lifts within tie of the nearest, the one whose parameter is nearest
 * `prefer` is taken, so that both ends of a coedge come from the same turn. */
static double project_on_pcurve(double *s, const cb_topo_curve *pc, const cb_topo_inverter *inv,
                                const double p[3], double lo, double hi, double prefer,
                                double tie)
{
    double uv[2], best = HUGE_VAL, nearest = HUGE_VAL, h = 0;
    cb_topo_inverter_invert(uv, inv, p, NULL);
    for (int i = -1; i <= 1; i++)
        for (int j = -1; j <= 1; j++) {
            if ((i && !(inv->lift[0] > 0)) || (j && !(inv->lift[1] > 0)))
                continue;
            double w[3] = {uv[0] + i * inv->lift[0], uv[1] + j * inv->lift[1], 0}, x;
            cb_topo_curve_project(&x, pc, w, lo, hi);
            double d = image_gap(pc, inv, p, x);
            if (d < nearest - tie ||
                (d <= nearest + tie && fabs(x - prefer) < fabs(*s - prefer))) {
                best = d;
                *s = x;
            }
            nearest = fmin(nearest, d);
        }
    if (pc->kind != CB_CURVE_LINE) {
        h = (hi - lo) / 64;
        for (int k = 0; k <= 64; k++) {
            double d = image_gap(pc, inv, p, lo + h * k);
            if (d < best) {
                best = d;
                *s = lo + h * k;
            }
        }
    }
    if (h > 0) {
        const double g = 0.6180339887498949;
        double a = fmax(lo, *s - h), z = fmin(hi, *s + h);
        double x1 = z - g * (z - a), x2 = a + g * (z - a);
        double f1 = image_gap(pc, inv, p, x1), f2 = image_gap(pc, inv, p, x2);
        for (int it = 0; it < 60; it++) {
            if (f1 < f2) {
                z = x2;
                x2 = x1;
                f2 = f1;
                x1 = z - g * (z - a);
                f1 = image_gap(pc, inv, p, x1);
            } else {
                a = x1;
                x1 = x2;
                f1 = f2;
                x2 = a + g * (z - a);
                f2 = image_gap(pc, inv, p, x2);
            }
        }
        double x = f1 < f2 ? x1 : x2, d = fmin(f1, f2);
        if (d < best) {
            best = d;
            *s = x;
        }
    }
    return best;
}

double cb_topo_pcurve_convention_gap(const cb_topo_curve *pc, const cb_topo_body *b, int e,
                                     const cb_topo_inverter *inv, double tol)
{
    const cb_topo_edge *ed = &b->edges[e];
    /* The edge's parameters must lie in a B-spline pcurve's domain: a rational arc evaluated
     * outside it continues along its conic and can match by accident (an edge at
     * [2 pi, 2 pi + a] against a pcurve on [0, a]). */
    if (pc->kind == CB_CURVE_NURBS) {
        double lo, hi;
        cb_nurbs_curve_domain(pc->nurbs, &lo, &hi);
        double slack = 1e-9 * (hi - lo);
        if (ed->t0 < lo - slack || ed->t1 > hi + slack)
            return HUGE_VAL;
    }
    double gap = 0;
    for (int k = 0; k < 3 && gap <= tol; k++) {
        double x = ed->t0 + (ed->t1 - ed->t0) * k / 2, w[3], p[3], q[3];
        cb_topo_curve_eval(w, pc, x);
        cb_topo_inverter_eval(p, inv, w[0], w[1]);
        cb_topo_curve_eval(q, &b->curves[ed->curve], x);
        double d = cb_vec3_dist(p, q);
        if (isnan(d))
            return HUGE_VAL;
        gap = fmax(gap, d);
    }
    return gap;
}

double cb_topo_coedge_pcurve_range(double *s0, double *s1, const cb_topo_body *b, int c,
                                   const cb_topo_inverter *inv, double tol)
{
    const cb_topo_coedge *co = &b->coedges[c];
    const cb_topo_edge *ed = &b->edges[co->edge];
    const cb_topo_curve *pc = &b->pcurves[co->pcurve], *cv = &b->curves[ed->curve];
    int forward = co->sense == ed->same_sense;
    double gap = cb_topo_pcurve_convention_gap(pc, b, co->edge, inv, tol);
    if (gap <= tol) {
        *s0 = forward ? ed->t0 : ed->t1;
        *s1 = forward ? ed->t1 : ed->t0;
        return gap;
    }
    double ends[2][3], lo = 0, hi = TWO_PI, t[2];
    cb_topo_curve_eval(ends[0], cv, ed->t0);
    cb_topo_curve_eval(ends[1], cv, ed->t1);
    if (pc->kind == CB_CURVE_NURBS)
        cb_nurbs_curve_domain(pc->nurbs, &lo, &hi);
    gap = 0;
    for (int k = 0; k < 2; k++)
        gap = fmax(gap, project_on_pcurve(&t[k], pc, inv, ends[k], lo, hi, k ? ed->t1 : ed->t0,
                                          tol));
    double len = hi - lo, a[3], z[3];
    cb_topo_curve_eval(a, pc, lo);
    cb_topo_curve_eval(z, pc, hi);
    int closed_pc = pc->kind != CB_CURVE_LINE && cb_vec3_dist(a, z) <= 1e-12 * (len + 1.0);
    int closed_edge = ed->v[0] == ed->v[1];
    if (closed_edge && !closed_pc && pc->kind == CB_CURVE_NURBS) {
        /* A B-spline pcurve once round a period of the surface (its ends a period apart in
         * (u, v), one point on the surface): the projections of the edge's one end cannot
         * tell its two ends apart, and the edge uses it whole. */
        double pa[3], pz[3];
        cb_topo_inverter_eval(pa, inv, a[0], a[1]);
        cb_topo_inverter_eval(pz, inv, z[0], z[1]);
        if (cb_vec3_dist(pa, pz) <= tol) {
            closed_pc = 1;
            t[0] = lo;
        }
    }
    if (closed_edge && closed_pc) {
        /* A closed edge: the whole pcurve, which starts where it ends, the way round the edge
         * runs: the pcurve's point a quarter along lies nearer the edge's point a quarter
         * along than to its point three quarters along. */
        t[1] = t[0] + len;
        double q[2][3], w[3], p[3];
        for (int k = 0; k < 2; k++)
            cb_topo_curve_eval(q[k], cv, ed->t0 + (0.25 + 0.5 * k) * (ed->t1 - ed->t0));
        cb_topo_pcurve_eval(w, pc, t[0] + 0.25 * len);
        cb_topo_inverter_eval(p, inv, w[0], w[1]);
        if (cb_vec3_dist(p, q[1]) < cb_vec3_dist(p, q[0])) {
            double sw = t[0];
            t[0] = t[1];
            t[1] = sw;
        }
    } else if (closed_pc) {
        /* A closed pcurve can reach t[1] either way round: take the arc whose middle is on the
         * edge (it may run through the domain's end, hence the shift by its length). */
        if (t[1] < t[0])
            t[1] += len;
        double w[3], p[3];
        cb_topo_pcurve_eval(w, pc, 0.5 * (t[0] + t[1]));
        cb_topo_inverter_eval(p, inv, w[0], w[1]);
        if (cb_topo_edge_distance(b, co->edge, p) > tol)
            t[1] -= len;
    }
    *s0 = t[forward ? 0 : 1];
    *s1 = t[forward ? 1 : 0];
    return gap;
}

/* ---------------------------------------------------------------- all coedges -------------- */

typedef struct {
    cb_topo_body *b;
    cb_topo_inverter *inv; /* per surface, ready[s] when initialised */
    char *ready, *fresh, *degenerate;
    double tol;
} job;

static cb_status inverter_of(job *j, int s, cb_error *err)
{
    if (j->ready[s])
        return CB_OK;
    cb_status st = cb_topo_inverter_init(&j->inv[s], &j->b->surfaces[s], j->tol, err);
    if (!st)
        j->ready[s] = 1;
    return st;
}

static const cb_topo_inverter *face_inverter(const job *j, int c)
{
    const cb_topo_body *b = j->b;
    return &j->inv[b->faces[b->loops[b->coedges[c].loop].face].surface];
}

/* (u, v) where coedge c starts (end = 0) or ends, following the convention. */
static void coedge_uv(double uv[2], const cb_topo_body *b, int c, int end)
{
    const cb_topo_coedge *co = &b->coedges[c];
    const cb_topo_edge *ed = &b->edges[co->edge];
    int at_t1 = (co->sense == ed->same_sense) == end;
    double w[3];
    cb_topo_curve_eval(w, &b->pcurves[co->pcurve], at_t1 ? ed->t1 : ed->t0);
    uv[0] = w[0];
    uv[1] = w[1];
}

/* Largest distance from S(a) of the surface along the (u, v) segment a -> b: 0 for equal
 * points, tiny for points on one collapsed line (a pole). */
double cb_topo_inverter_spread(const cb_topo_inverter *inv, const double a[2],
                               const double b[2])
{
    double pa[3], worst = 0;
    cb_topo_inverter_eval(pa, inv, a[0], a[1]);
    for (int k = 1; k <= 4; k++) {
        double p[3], s = k / 4.0;
        cb_topo_inverter_eval(p, inv, a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]));
        worst = fmax(worst, cb_vec3_dist(p, pa));
    }
    return worst;
}

/* Whole-period shift (du, dv) of a pcurve starting at `start` so it continues from `prev`:
 * none when the joint already closes on the surface (equal points or a pole line), else the
 * lift nearest prev. */
static void joint_shift(double sh[2], const cb_topo_inverter *inv, const double prev[2],
                        const double start[2], double tol)
{
    sh[0] = sh[1] = 0;
    if (cb_topo_inverter_spread(inv, prev, start) <= tol)
        return;
    double w[2] = {start[0], start[1]};
    lift_near(w, inv, prev);
    sh[0] = w[0] - start[0];
    sh[1] = w[1] - start[1];
}

/* The other coedge of seam edge e in face f, or -1. */
static int seam_partner(const cb_topo_body *b, int c)
{
    int e = b->coedges[c].edge, f = b->loops[b->coedges[c].loop].face;
    for (int k = b->edge_start[e]; k < b->edge_start[e + 1]; k++) {
        int o = b->edge_coedges[k];
        if (o != c && b->loops[b->coedges[o].loop].face == f)
            return o;
    }
    return -1;
}

/* Whether the line of the surface through (u, v) = p along a periodic direction collapses to
 * a point (a pole): the half turn from p stays within tol of S(p). */
static int at_pole(const cb_topo_inverter *inv, const double p[2], double tol)
{
    for (int i = 0; i < 2; i++) {
        double q[2] = {p[0], p[1]};
        q[i] += 0.5 * inv->period[i];
        if (inv->period[i] > 0 && cb_topo_inverter_spread(inv, p, q) <= tol)
            return 1;
    }
    return 0;
}

/* Moves the fresh pcurves of loop l's coedges in chain k by (du, dv). */
static void shift_chain(job *j, int l, const int *chain, int k, const double sh[2])
{
    const cb_topo_loop *lp = &j->b->loops[l];
    for (int m = 0; m < lp->count; m++) {
        int c = lp->first + m;
        if (chain[m] == k && j->fresh[c] && !j->degenerate[c])
            shift_curve(&j->b->pcurves[j->b->coedges[c].pcurve], sh[0], sh[1]);
    }
}

/* The periodic direction across seam coedge c (the one its pcurve does not run along), and
 * the side of c the face lies on in it: +1 when the face lies to the left of c in (u, v) and
 * that left points up that direction (same_sense 1; the right for same_sense 0), else -1. */
static int seam_side(const job *j, int c, const cb_topo_inverter *inv, int *dir)
{
    double s0[2], s1[2];
    coedge_uv(s0, j->b, c, 0);
    coedge_uv(s1, j->b, c, 1);
    *dir = inv->period[0] > 0 && fabs(s1[0] - s0[0]) <= fabs(s1[1] - s0[1]) ? 0 : 1;
    double d[2] = {s1[0] - s0[0], s1[1] - s0[1]}, left[2] = {-d[1], d[0]};
    int same = j->b->faces[j->b->loops[j->b->coedges[c].loop].face].same_sense;
    return (same ? 1 : -1) * left[*dir] > 0 ? 1 : -1;
}

/* Makes the new pcurves of loop l continuous (each starts where the previous ends), puts the
 * two uses of a seam edge on its two sides, and lifts the loop into the first period.
 * The loop falls into chains joined at poles (joints where a periodic line of the surface
 * collapses) and at collapsed edges, across which nothing fixes the lift. A seam edge
 * used in two chains puts the second chain a period away from the first, on the side where
 * the face lies of each use (the face lies on both sides of its seam), so that all chains
 * agree: a sphere face cut along a circle through both of its seam's pieces (a Boolean's
 * result read back: [seam, arc, seam, seam, arc, seam]) had each pair moved on its own, its
 * chains two periods apart, and bounded the cap instead of the rest. Returns CB_ERR_NOMEM. */
static cb_status settle_loop(job *j, int l)
{
    cb_topo_body *b = j->b;
    const cb_topo_loop *lp = &b->loops[l];
    const cb_topo_inverter *inv = face_inverter(j, lp->first);
    int *chain = malloc((size_t)(2 * lp->count + 1) * sizeof *chain), *placed = chain + lp->count;
    if (!chain)
        return CB_ERR_NOMEM;
    /* The walk starts at a pcurve from the file, so the new ones join it, or else at one that
     * is no seam. */
    int anchor = -1, n_chains = 0;
    for (int k = 0; k < lp->count && anchor < 0; k++)
        if (!j->fresh[lp->first + k] && !j->degenerate[lp->first + k])
            anchor = k;
    for (int k = 0; k < lp->count && anchor < 0; k++) {
        int c = lp->first + k;
        if (!j->degenerate[c] && seam_partner(b, c) < 0)
            anchor = k;
    }
    if (anchor < 0)
        anchor = 0;
    double prev[2];
    int have_prev = 0;
    for (int m = 0; m < lp->count; m++) {
        int k = (anchor + m) % lp->count, c = lp->first + k;
        chain[k] = -1;
        if (j->degenerate[c]) {
            have_prev = 0;
            continue;
        }
        double start[2];
        coedge_uv(start, b, c, 0);
        if (!have_prev || at_pole(inv, prev, j->tol))
            placed[n_chains++] = 0;
        chain[k] = n_chains - 1;
        if (have_prev && j->fresh[c]) {
            double sh[2];
            joint_shift(sh, inv, prev, start, j->tol);
            shift_curve(&b->pcurves[b->coedges[c].pcurve], sh[0], sh[1]);
        }
        coedge_uv(prev, b, c, 1);
        have_prev = 1;
    }
    /* Chains holding a pcurve from the file stay where the file put them. */
    for (int k = 0; k < lp->count; k++)
        if (chain[k] >= 0 && (!j->fresh[lp->first + k] || chain[k] == chain[anchor]))
            placed[chain[k]] = 1;
    for (int progress = 1; progress;) {
        progress = 0;
        for (int k = 0; k < lp->count; k++) {
            int c = lp->first + k, o = seam_partner(b, c);
            if (chain[k] < 0 || !placed[chain[k]] || o < 0 || b->coedges[o].loop != l)
                continue;
            int ko = o - lp->first, dir;
            if (chain[ko] < 0 || placed[chain[ko]])
                continue;
            int side = seam_side(j, o, inv, &dir);
            double a[2], z[2], P = inv->period[dir], sh[2] = {0, 0};
            coedge_uv(a, b, c, 0);
            coedge_uv(z, b, o, 0);
            /* o on the low side of its seam when the face lies above it. */
            double target = a[dir] - side * P;
            sh[dir] = P * round((target - z[dir]) / P);
            shift_chain(j, l, chain, chain[ko], sh);
            placed[chain[ko]] = 1;
            progress = 1;
        }
    }
    free(chain);
    /* Seam uses still on one side: move the later one across, towards its neighbours. */
    for (int m = 0; m < lp->count; m++) {
        int c = lp->first + (anchor + m) % lp->count, o = seam_partner(b, c);
        if (o < 0 || !j->fresh[c] || j->degenerate[c] || b->coedges[o].loop != l)
            continue;
        int k_o = (o - lp->first - anchor + lp->count) % lp->count;
        if (k_o < m)
            continue;
        double a[2], z[2];
        coedge_uv(a, b, c, 0);
        coedge_uv(z, b, o, 1);
        if (fabs(a[0] - z[0]) + fabs(a[1] - z[1]) > 0.5 * (inv->period[0] + inv->period[1]))
            continue; /* already apart */
        double s0[2], s1[2];
        coedge_uv(s0, b, o, 0);
        coedge_uv(s1, b, o, 1);
        /* The seam runs along the periodic direction it does not move in. */
        int dir = inv->period[0] > 0 && fabs(s1[0] - s0[0]) <= fabs(s1[1] - s0[1]) ? 0 : 1;
        double P = inv->period[dir], sign = 1;
        int pc = lp->first + (o - lp->first + lp->count - 1) % lp->count,
            nc = lp->first + (o - lp->first + 1) % lp->count;
        double pe[2], ns[2];
        coedge_uv(pe, b, pc, 1);
        coedge_uv(ns, b, nc, 0);
        double score[2];
        for (int sgn = 0; sgn < 2; sgn++) {
            double sh = sgn ? -P : P, a0[2] = {s0[0], s0[1]}, a1[2] = {s1[0], s1[1]};
            a0[dir] += sh;
            a1[dir] += sh;
            score[sgn] = hypot(a0[0] - pe[0], a0[1] - pe[1]) + hypot(a1[0] - ns[0], a1[1] - ns[1]);
        }
        if (fabs(score[0] - score[1]) > 1e-9 * P) {
            sign = score[0] < score[1] ? 1 : -1;
        } else {
            /* No neighbour decides: the face lies to the left of the coedge in (u, v) when
             * same_sense is 1, so the side is where that left points away from. */
            double d[2] = {s1[0] - s0[0], s1[1] - s0[1]}, left[2] = {-d[1], d[0]};
            int same = b->faces[lp->face].same_sense;
            double toward = (same ? 1 : -1) * left[dir];
            sign = toward < 0 ? 1 : -1;
        }
        double sh[2] = {0, 0};
        sh[dir] = sign * P;
        shift_curve(&b->pcurves[b->coedges[o].pcurve], sh[0], sh[1]);
    }
    /* Lift the loop so the middle of its range lies in the first period, unless it holds
     * pcurves from the file, to which the new ones were joined. */
    for (int k = 0; k < lp->count; k++)
        if (!j->fresh[lp->first + k] && !j->degenerate[lp->first + k])
            return CB_OK;
    double lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL};
    for (int k = 0; k < lp->count; k++)
        for (int end = 0; end < 2; end++) {
            int c = lp->first + k;
            if (!j->fresh[c] || j->degenerate[c])
                continue;
            double w[2];
            coedge_uv(w, b, c, end);
            for (int i = 0; i < 2; i++) {
                lo[i] = fmin(lo[i], w[i]);
                hi[i] = fmax(hi[i], w[i]);
            }
        }
    double sh[2] = {0, 0};
    for (int i = 0; i < 2; i++)
        if (inv->period[i] > 0 && lo[i] <= hi[i]) {
            double c = 0.5 * (lo[i] + hi[i]);
            sh[i] = wrap(c, inv->box[2 * i], inv->period[i]) - c;
        }
    for (int k = 0; k < lp->count; k++) {
        int c = lp->first + k;
        if (j->fresh[c] && !j->degenerate[c])
            shift_curve(&b->pcurves[b->coedges[c].pcurve], sh[0], sh[1]);
    }
    return CB_OK;
}

static cb_status copy_curve(cb_topo_curve *dst, const cb_topo_curve *src, cb_error *err)
{
    cb_topo_curve_clear(dst);
    dst->kind = src->kind;
    dst->frame = src->frame;
    dst->r1 = src->r1;
    dst->r2 = src->r2;
    return src->kind == CB_CURVE_NURBS ? cb_nurbs_curve_set(dst->nurbs, src->nurbs, err) : CB_OK;
}

/* Stores curve q (moved out of q) as the new pcurve of coedge c. */
static cb_status attach(job *j, int c, cb_topo_curve *q, cb_error *err)
{
    int k = cb_topo_body_add_pcurve(j->b);
    if (k < 0)
        return cb_error_set(err, CB_ERR_NOMEM, "pcurve: out of memory");
    cb_topo_curve_clear(&j->b->pcurves[k]);
    j->b->pcurves[k] = *q;
    cb_topo_curve_init(q);
    j->b->coedges[c].pcurve = k;
    j->fresh[c] = 1;
    return CB_OK;
}

/* (u, v) at the joint of degenerate coedge c with its neighbour (side -1: the previous one's
 * end, +1: the next one's start); the inverted vertex when the neighbour has no pcurve. */
static void neighbour_uv(double uv[2], const job *j, int c, int side)
{
    const cb_topo_body *b = j->b;
    const cb_topo_loop *lp = &b->loops[b->coedges[c].loop];
    int n = lp->first + (c - lp->first + lp->count + side) % lp->count;
    if (b->coedges[n].pcurve >= 0 && !j->degenerate[n]) {
        coedge_uv(uv, b, n, side < 0);
        return;
    }
    const cb_topo_edge *ed = &b->edges[b->coedges[c].edge];
    int at_end = (side > 0) == (b->coedges[c].sense != 0);
    cb_topo_inverter_invert(uv, face_inverter(j, c), b->vertices[ed->v[at_end]].p, NULL);
}

cb_status cb_topo_compute_pcurves(cb_topo_body *b, double tol, cb_error *err)
{
    if (!(tol > 0))
        return cb_error_set(err, CB_ERR_INVALID, "pcurves: tolerance %g is not positive", tol);
    cb_status st = b->edge_start ? CB_OK : cb_topo_body_index(b, err);
    if (st)
        return st;
    job j = {b, calloc((size_t)b->n_surfaces + 1, sizeof *j.inv),
             calloc((size_t)b->n_surfaces + 1, 1), calloc((size_t)b->n_coedges + 1, 1),
             calloc((size_t)b->n_coedges + 1, 1), tol};
    if (!j.inv || !j.ready || !j.fresh || !j.degenerate)
        st = cb_error_set(err, CB_ERR_NOMEM, "pcurves: out of memory");
    for (int c = 0; c < b->n_coedges && !st; c++)
        j.degenerate[c] = b->coedges[c].pcurve < 0 &&
                          !(cb_topo_edge_length(b, b->coedges[c].edge) > tol);
    cb_topo_curve q;
    cb_topo_curve_init(&q);
    for (int c = 0; c < b->n_coedges && !st; c++) {
        if (b->coedges[c].pcurve >= 0 || j.degenerate[c])
            continue;
        int f = b->loops[b->coedges[c].loop].face, o = seam_partner(b, c);
        if ((st = inverter_of(&j, b->faces[f].surface, err)))
            break;
        /* The second use of a seam edge starts as a copy: settle_loop moves it across. */
        if (o >= 0 && o < c && j.fresh[o])
            st = copy_curve(&q, &b->pcurves[b->coedges[o].pcurve], err);
        else
            st = edge_pcurve(&q, b, b->coedges[c].edge, face_inverter(&j, c), tol, err);
        if (st)
            cb_error_prefix(err, "coedge %d (face %d): ", c, f);
        else
            st = attach(&j, c, &q, err);
    }
    for (int l = 0; l < b->n_loops && !st; l++) {
        int any = 0;
        for (int k = 0; k < b->loops[l].count; k++)
            any |= j.fresh[b->loops[l].first + k];
        if (any && settle_loop(&j, l))
            st = cb_error_set(err, CB_ERR_NOMEM, "pcurves: out of memory");
    }
    for (int c = 0; c < b->n_coedges && !st; c++) {
        if (!j.degenerate[c])
            continue;
        const cb_topo_edge *ed = &b->edges[b->coedges[c].edge];
        if ((st = inverter_of(&j, b->faces[b->loops[b->coedges[c].loop].face].surface, err)))
            break;
        double a[2], z[2];
        neighbour_uv(a, &j, c, -1);
        neighbour_uv(z, &j, c, +1);
        int forward = b->coedges[c].sense == ed->same_sense;
        if (!(st = make_segment(&q, forward ? a : z, forward ? z : a, ed->t0, ed->t1, err)))
            st = attach(&j, c, &q, err);
    }
    cb_topo_curve_clear(&q);
    for (int s = 0; j.ready && s < b->n_surfaces; s++)
        if (j.ready[s])
            cb_topo_inverter_clear(&j.inv[s]);
    free(j.inv);
    free(j.ready);
    free(j.fresh);
    free(j.degenerate);
    return st;
}

cb_status cb_topo_repair_pcurves(cb_topo_body *b, double tol, int n_samples, int *dropped,
                                 cb_error *err)
{
    *dropped = 0;
    for (int f = 0; f < b->n_faces; f++) {
        const cb_topo_face *fc = &b->faces[f];
        cb_topo_inverter inv;
        int ready = 0;
        for (int l = fc->first; l < fc->first + fc->count; l++)
            for (int c = b->loops[l].first; c < b->loops[l].first + b->loops[l].count; c++) {
                if (b->coedges[c].pcurve < 0)
                    continue;
                if (!ready) {
                    cb_status st = cb_topo_inverter_init(&inv, &b->surfaces[fc->surface], tol,
                                                         err);
                    if (st)
                        return st;
                    ready = 1;
                }
                double range[2];
                double etol = fmax(tol, b->edges[b->coedges[c].edge].tol);
                if (cb_topo_coedge_pcurve_error(range, b, c, &inv, tol, n_samples) > etol) {
                    b->coedges[c].pcurve = -1;
                    (*dropped)++;
                }
            }
        if (ready)
            cb_topo_inverter_clear(&inv);
    }
    return cb_topo_compute_pcurves(b, tol, err);
}
