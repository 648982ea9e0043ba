/* ssi_recog.c — B-spline faces that are the exact rational forms of planes, cylinders and
 * spheres, routed to the closed forms of the analytic/analytic code (see
 * _cb_ssi_recognised_pair). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ssi/ssi.h"
#include "ssi/ssi_tol.h"

/* Knots and weights must agree with the conversion's to this relative amount (they are
 * computed the same way, so in practice they agree bit for bit). */
#define RECOG_REL 1e-12

static void sub3(double d[3], const double a[3], const double b[3])
{
    for (int k = 0; k < 3; k++)
        d[k] = a[k] - b[k];
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static double norm3(const double a[3]) { return sqrt(dot3(a, a)); }

static void cross3(double c[3], const double a[3], const double b[3])
{
    double t[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                   a[0] * b[1] - a[1] * b[0]};
    memcpy(c, t, sizeof t);
}

/* Euclidean control point (i, j); 0 if its weight is not positive. */
static int ctrl(double p[3], const cb_nurbs_surface_struct *s, int i, int j)
{
    const double *cw = s->cw + 4 * ((long)i * s->n_v + j);
    if (!(cw[3] > 0))
        return 0;
    for (int k = 0; k < 3; k++)
        p[k] = cw[k] / cw[3];
    return 1;
}

/* s equals c (same degrees, counts, knots and weights to RECOG_REL, Euclidean control points
 * within delta). */
static int same_net(const cb_nurbs_surface_struct *s, const cb_nurbs_surface_struct *c,
                    double delta)
{
    if (s->deg_u != c->deg_u || s->deg_v != c->deg_v || s->n_u != c->n_u || s->n_v != c->n_v)
        return 0;
    for (int d = 0; d < 2; d++) {
        const double *ks = d ? s->knots_v : s->knots_u, *kc = d ? c->knots_v : c->knots_u;
        int n = d ? s->n_v + s->deg_v + 1 : s->n_u + s->deg_u + 1;
        double span = fabs(ks[n - 1] - ks[0]) + fabs(ks[0]) + fabs(ks[n - 1]);
        for (int k = 0; k < n; k++)
            if (!(fabs(ks[k] - kc[k]) <= RECOG_REL * span))
                return 0;
    }
    for (int i = 0; i < s->n_u; i++)
        for (int j = 0; j < s->n_v; j++) {
            double p[3], q[3], e[3];
            const double *ws = s->cw + 4 * ((long)i * s->n_v + j) + 3;
            const double *wc = c->cw + 4 * ((long)i * c->n_v + j) + 3;
            if (!ctrl(p, s, i, j) || !ctrl(q, c, i, j) || !(fabs(*ws - *wc) <= RECOG_REL * *wc))
                return 0;
            sub3(e, p, q);
            if (!(norm3(e) <= delta))
                return 0;
        }
    return 1;
}

/* Checks the candidate a over [u0, u1] x [v0, v1] (stored in range) against s: its exact
 * rational form over the range must be s's net. */
static int confirm(const cb_nurbs_surface_struct *s, const cb_analytic_surface *a,
                   double range[4], double u0, double u1, double v0, double v1, double delta)
{
    range[0] = u0;
    range[1] = u1;
    range[2] = v0;
    range[3] = v1;
    cb_nurbs_surface_t c;
    cb_nurbs_surface_init(c);
    cb_error err;
    int ok = cb_analytic_to_nurbs(c, a, range[0], range[1], range[2], range[3], &err) == CB_OK &&
             same_net(s, c, delta);
    cb_nurbs_surface_clear(c);
    return ok;
}

/* A plane: bilinear, non-rational (equal weights), its parameters unit-speed and orthogonal. */
static int recog_plane(cb_analytic_surface *a, double range[4], const cb_nurbs_surface_struct *s,
                       double delta)
{
    if (s->deg_u != 1 || s->deg_v != 1 || s->n_u != 2 || s->n_v != 2)
        return 0;
    double u0 = s->knots_u[0], u1 = s->knots_u[3], v0 = s->knots_v[0], v1 = s->knots_v[3];
    if (!(u1 > u0 && v1 > v0))
        return 0;
    double p00[3], p10[3], p01[3], x[3], y[3], z[3], o[3];
    if (!ctrl(p00, s, 0, 0) || !ctrl(p10, s, 1, 0) || !ctrl(p01, s, 0, 1))
        return 0;
    sub3(x, p10, p00);
    sub3(y, p01, p00);
    for (int k = 0; k < 3; k++) {
        x[k] /= u1 - u0;
        y[k] /= v1 - v0;
    }
    cross3(z, x, y);
    if (!(norm3(z) > 0.5))
        return 0;
    for (int k = 0; k < 3; k++)
        o[k] = p00[k] - u0 * x[k] - v0 * y[k];
    cb_frame f;
    cb_error err;
    if (cb_frame_make(&f, o, z, x, &err) != CB_OK || cb_analytic_plane(a, &f, &err) != CB_OK)
        return 0;
    return confirm(s, a, range, u0, u1, v0, v1, delta);
}

/* The middle point (tau = 1/2) of the rational quadratic with control points p0, m, p2 and
 * weights 1, w, 1. */
static void arc_mid(double q[3], const double p0[3], const double m[3], const double p2[3],
                    double w)
{
    for (int k = 0; k < 3; k++)
        q[k] = (p0[k] + 2 * w * m[k] + p2[k]) / (2 + 2 * w);
}

/* Centre c and radius of the circle through the ends p0, p2 and the middle (weight w of m)
 * of a rational quadratic arc; 0 when the three points are collinear. */
static int arc_circle(double c[3], double *rad, const double p0[3], const double m[3],
                      const double p2[3], double w)
{
    double q[3], e1[3], e2[3], n[3], t[3], t1[3], r0[3];
    arc_mid(q, p0, m, p2, w);
    sub3(e1, q, p0);
    sub3(e2, p2, p0);
    cross3(n, e1, e2);
    double nn = dot3(n, n);
    if (!(nn > 0))
        return 0;
    /* c = p0 + ((|e1|^2 e2 - |e2|^2 e1) x n) / (2 |n|^2) */
    for (int k = 0; k < 3; k++)
        t[k] = dot3(e1, e1) * e2[k] - dot3(e2, e2) * e1[k];
    cross3(t1, t, n);
    for (int k = 0; k < 3; k++)
        c[k] = p0[k] + t1[k] / (2 * nn);
    sub3(r0, p0, c);
    *rad = norm3(r0);
    return *rad > 0;
}

/* The direction x of angle 0 about the unit axis z, given the unit direction r (normal to z)
 * of angle a0: r turned back by a0 (y = z x x). */
static void angle_zero(double x[3], const double z[3], const double r[3], double a0)
{
    double t[3];
    cross3(t, z, r);
    for (int k = 0; k < 3; k++)
        x[k] = cos(a0) * r[k] - sin(a0) * t[k];
}

/* A cylinder: degree (2, 1), a circular arc in u (knots of cb_analytic_to_nurbs: the angles)
 * times a unit-speed line in v along the axis. */
static int recog_cylinder(cb_analytic_surface *a, double range[4],
                          const cb_nurbs_surface_struct *s, double delta)
{
    if (s->deg_u != 2 || s->deg_v != 1 || s->n_v != 2 || s->n_u < 3 || s->n_u % 2 == 0 ||
        s->n_u > 9)
        return 0;
    double a0 = s->knots_u[0], a1 = s->knots_u[s->n_u + 2], v0 = s->knots_v[0],
           v1 = s->knots_v[3];
    if (!(a1 > a0 && v1 > v0))
        return 0;
    double p0[3], p0v[3], m[3], p2[3], z[3];
    if (!ctrl(p0, s, 0, 0) || !ctrl(p0v, s, 0, 1) || !ctrl(m, s, 1, 0) || !ctrl(p2, s, 2, 0))
        return 0;
    sub3(z, p0v, p0);
    double len = norm3(z);
    if (!(len > 0))
        return 0;
    for (int k = 0; k < 3; k++)
        z[k] /= len;
    /* The first arc's circle: its ends and its middle (tau = 1/2). */
    double c[3], rad, r0[3], x[3], o[3];
    if (!arc_circle(c, &rad, p0, m, p2, s->cw[4 * (1 * s->n_v) + 3]))
        return 0;
    sub3(r0, p0, c);
    for (int k = 0; k < 3; k++) {
        r0[k] /= rad;
        o[k] = c[k] - v0 * z[k];
    }
    angle_zero(x, z, r0, a0);
    cb_frame f;
    cb_error err;
    if (cb_frame_make(&f, o, z, x, &err) != CB_OK || cb_analytic_cylinder(a, &f, rad, &err) != CB_OK)
        return 0;
    return confirm(s, a, range, a0, a1, v0, v1, delta);
}

/* A sphere: degree (2, 2), circular arcs in u (parallels, the angles as knots) and in v
 * (meridians, the latitudes as knots). The first meridian arc gives the centre and radius,
 * the parallel farthest from the axis the axis' direction (u turns positively about it), the
 * first control point of that parallel the direction of angle u0. */
static int recog_sphere(cb_analytic_surface *a, double range[4], const cb_nurbs_surface_struct *s,
                        double delta)
{
    if (s->deg_u != 2 || s->deg_v != 2 || s->n_u < 3 || s->n_u % 2 == 0 || s->n_u > 9 ||
        s->n_v < 3 || s->n_v % 2 == 0 || s->n_v > 9)
        return 0;
    double u0 = s->knots_u[0], u1 = s->knots_u[s->n_u + 2], v0 = s->knots_v[0],
           v1 = s->knots_v[s->n_v + 2];
    if (!(u1 > u0 && v1 > v0))
        return 0;
    double p0[3], m[3], p2[3], o[3], rad;
    /* The first meridian's circle (u's weight is 1 at i = 0): centre and radius. */
    if (!ctrl(p0, s, 0, 0) || !ctrl(m, s, 0, 1) || !ctrl(p2, s, 0, 2) ||
        !arc_circle(o, &rad, p0, m, p2, s->cw[4 * 1 + 3] / s->cw[3]))
        return 0;
    double z[3] = {0, 0, 0}, best = 0, x0[3] = {0, 0, 0};
    for (int j = 0; j < s->n_v; j += 2) {
        double c0[3], cm[3], c2[3], cq[3], f1[3], f2[3], cn[3];
        if (!ctrl(c0, s, 0, j) || !ctrl(cm, s, 1, j) || !ctrl(c2, s, 2, j))
            return 0;
        arc_mid(cq, c0, cm, c2, s->cw[4 * ((long)1 * s->n_v + j) + 3] /
                                    s->cw[4 * ((long)0 * s->n_v + j) + 3]);
        sub3(f1, cq, c0);
        sub3(f2, c2, c0);
        cross3(cn, f1, f2);
        double len = norm3(cn);
        if (len > best) {
            best = len;
            for (int k = 0; k < 3; k++) {
                z[k] = cn[k] / len;
                x0[k] = c0[k] - o[k];
            }
        }
    }
    if (!(best > 0))
        return 0;
    /* x0 less its component along the axis: the direction of angle u0. */
    double along = dot3(x0, z), x[3];
    for (int k = 0; k < 3; k++)
        x0[k] -= along * z[k];
    double lx = norm3(x0);
    if (!(lx > 0))
        return 0;
    for (int k = 0; k < 3; k++)
        x0[k] /= lx;
    angle_zero(x, z, x0, u0);
    cb_frame f;
    cb_error err;
    if (cb_frame_make(&f, o, z, x, &err) != CB_OK || cb_analytic_sphere(a, &f, rad, &err) != CB_OK)
        return 0;
    return confirm(s, a, range, u0, u1, v0, v1, delta);
}

int _cb_ssi_recognise(cb_analytic_surface *a, double range[4], const cb_nurbs_surface_struct *s,
                      double delta)
{
    return recog_plane(a, range, s, delta) || recog_cylinder(a, range, s, delta) ||
           recog_sphere(a, range, s, delta);
}

/* B-spline parameter of the analytic angle u on a direction of arcs (knots k[0 .. n + 2], n
 * control points; periodic: u may be given modulo the turn): on the arc segment [t0, t1] of
 * half angle h (weights 1, cos h, 1) the angle phi from the segment's middle and the local
 * parameter tau satisfy tan(phi / 2) = tan(h / 2) (2 tau - 1) (the rational quadratic circle is
 * a Moebius reparameterisation of tan(phi / 2), fixed by tau = 0, 1/2, 1). */
static double arc_param(const double *k, int n, int periodic, double u)
{
    double a0 = k[0], a1 = k[n + 2], per = 2 * CB_SSI_PI;
    if (periodic && (u < a0 || u > a1)) {
        /* An angle given modulo the turn: the representative nearest the range. */
        double w = a0 + fmod(fmod(u - a0, per) + per, per);
        if (w > a1 && w - per >= a0 - (w - a1))
            w -= per;
        u = w;
    }
    u = fmin(fmax(u, a0), a1);
    int nseg = (n - 1) / 2;
    int j = 0;
    while (j < nseg - 1 && u > k[2 * j + 3])
        j++;
    double t0 = k[2 * j + 1], t1 = k[2 * j + 3];
    if (j == 0)
        t0 = k[0];
    double h = 0.5 * (t1 - t0);
    if (!(h > 0))
        return u;
    double tau = 0.5 * (1 + tan(0.5 * (u - t0 - h)) / tan(0.5 * h));
    tau = fmin(fmax(tau, 0), 1);
    return t0 + tau * (t1 - t0);
}

void _cb_ssi_recog_param(double out[2], const cb_nurbs_surface_struct *s,
                         const cb_analytic_surface *a, const double uv[2])
{
    int arcs_u = a->kind == CB_ANALYTIC_CYLINDER || a->kind == CB_ANALYTIC_SPHERE;
    out[0] = arcs_u ? arc_param(s->knots_u, s->n_u, 1, uv[0]) : uv[0];
    out[1] = a->kind == CB_ANALYTIC_SPHERE ? arc_param(s->knots_v, s->n_v, 0, uv[1]) : uv[1];
}

/* The same B-spline exactly: degrees, counts, knots and homogeneous control points. */
static int identical(const cb_nurbs_surface_struct *a, const cb_nurbs_surface_struct *b)
{
    if (a->deg_u != b->deg_u || a->deg_v != b->deg_v || a->n_u != b->n_u || a->n_v != b->n_v)
        return 0;
    for (int k = 0; k < a->n_u + a->deg_u + 1; k++)
        if (a->knots_u[k] != b->knots_u[k])
            return 0;
    for (int k = 0; k < a->n_v + a->deg_v + 1; k++)
        if (a->knots_v[k] != b->knots_v[k])
            return 0;
    for (int k = 0; k < 4 * a->n_u * a->n_v; k++)
        if (a->cw[k] != b->cw[k])
            return 0;
    return 1;
}

static double nurbs_dist(const cb_nurbs_surface_struct *s, const double uv[2], const double X[3])
{
    double p[3], d[3];
    cb_nurbs_surface_eval(p, s, uv[0], uv[1]);
    sub3(d, p, X);
    return norm3(d);
}

cb_status _cb_ssi_recognised_pair(cb_ssi_result_t r, const cb_ssi_surface *A,
                                  const cb_ssi_surface *B, int face_a, int face_b,
                                  const cb_ssi_opts *opts, int *done, cb_error *err)
{
    *done = 0;
    const cb_ssi_surface *in[2] = {A, B};
    cb_ssi_surface S[2];
    int rec[2] = {0, 0};
    for (int k = 0; k < 2; k++) {
        S[k] = *in[k];
        if (in[k]->kind != CB_SSI_NURBS)
            continue;
        const cb_nurbs_surface_struct *n = in[k]->nurbs;
        /* Control points within delta of the conversion: a thousandth of the tolerance (the
         * default tolerance relative to the net's own size when none is given). */
        double delta = CB_SSI_RECOGNISE * opts->tol;
        if (!(opts->tol > 0)) {
            cb_aabb b;
            cb_nurbs_surface_aabb(&b, n);
            double d[3];
            sub3(d, b.hi, b.lo);
            delta = 1e-9 * norm3(d);
        }
        cb_analytic_surface a;
        double range[4];
        if (!_cb_ssi_recognise(&a, range, n, delta))
            return CB_OK;
        cb_ssi_surface_set_analytic(S + k, &a, range);
        rec[k] = 1;
    }
    if (!rec[0] && !rec[1])
        return CB_OK;
    cb_ssi_result_t t;
    cb_ssi_result_init(t);
    cb_error e2; /* a failure here only means: take the B-spline route */
    cb_error_clear(&e2);
    cb_status st = _cb_ssi_analytic_pair(t, S, S + 1, face_a, face_b, opts, &e2);
    /* Only the closed forms are taken: the general route would certify the same surfaces as
     * the B-spline route does. */
    if (st == CB_OK && t->pairs_closed_form > 0 && t->n_failed == 0 && t->status == CB_OK) {
        t->max_dist_a = t->max_dist_b = 0;
        for (slong c = 0; c <= t->n_curves; c++) {
            slong np = c < t->n_curves ? t->curve[c].n : t->n_points;
            for (slong i = 0; i < np; i++) {
                cb_ssi_point *p = c < t->n_curves ? t->curve[c].pt + i : &t->point[i].p;
                double *uv[2] = {p->uv_a, p->uv_b};
                double dist[2];
                for (int k = 0; k < 2; k++) {
                    if (rec[k])
                        _cb_ssi_recog_param(uv[k], in[k]->nurbs, &S[k].analytic, uv[k]);
                    if (rec[k]) {
                        dist[k] = nurbs_dist(in[k]->nurbs, uv[k], p->xyz);
                    } else {
                        double q[3], d[3];
                        cb_analytic_eval(q, &S[k].analytic, uv[k][0], uv[k][1]);
                        sub3(d, q, p->xyz);
                        dist[k] = norm3(d);
                    }
                }
                t->max_dist_a = fmax(t->max_dist_a, dist[0]);
                t->max_dist_b = fmax(t->max_dist_b, dist[1]);
            }
        }
        /* Regions in the B-splines' parameters; a coincidence of the analytic forms is exact
         * for the B-splines only when they are the same net (they are the analytic surfaces
         * within CB_SSI_RECOGNISE tol, not exactly). */
        for (slong k = 0; k < t->n_regions; k++) {
            double *box[2] = {t->region[k].box_a, t->region[k].box_b};
            for (int q = 0; q < 2; q++) {
                if (!rec[q])
                    continue;
                double lo[2] = {box[q][0], box[q][2]}, hi[2] = {box[q][1], box[q][3]};
                _cb_ssi_recog_param(lo, in[q]->nurbs, &S[q].analytic, lo);
                _cb_ssi_recog_param(hi, in[q]->nurbs, &S[q].analytic, hi);
                box[q][0] = fmin(lo[0], hi[0]);
                box[q][1] = fmax(lo[0], hi[0]);
                box[q][2] = fmin(lo[1], hi[1]);
                box[q][3] = fmax(lo[1], hi[1]);
            }
        }
        int same = A->kind == CB_SSI_NURBS && B->kind == CB_SSI_NURBS &&
                   identical(A->nurbs, B->nurbs);
        for (slong k = 0; k < t->n_coincident && !same; k++) {
            cb_ssi_coincident *c = t->coincident + k;
            if (!c->exact)
                continue;
            c->exact = 0;
            c->width = CB_SSI_RECOGNISE * t->tol;
            t->pairs_certified--;
            t->pairs_within_tolerance++;
            cb_ssi_region *g = _cb_ssi_add_region(t, CB_SSI_REGION_COINCIDENCE, c->face_a,
                                                  c->face_b, -1, -1, c->width);
            if (!g) {
                cb_ssi_result_clear(t);
                return cb_error_set(err, CB_ERR_NOMEM,
                                    "ssi: out of memory recording coincident surfaces");
            }
            for (int q = 0; q < 2; q++) {
                double *bx = q ? g->box_b : g->box_a;
                if (in[q]->kind == CB_SSI_NURBS)
                    cb_nurbs_surface_domain(in[q]->nurbs, bx);
                else
                    memcpy(bx, in[q]->range, 4 * sizeof(double));
            }
            for (int q = 0; q < 3; q++) {
                g->lo[q] = -HUGE_VAL;
                g->hi[q] = HUGE_VAL;
            }
            for (int k2 = 0; k2 < 2; k2++) {
                if (in[k2]->kind != CB_SSI_NURBS)
                    continue;
                cb_aabb b;
                cb_nurbs_surface_aabb(&b, in[k2]->nurbs);
                for (int q = 0; q < 3; q++) {
                    g->lo[q] = fmax(g->lo[q], b.lo[q]);
                    g->hi[q] = fmin(g->hi[q], b.hi[q]);
                }
            }
        }
        r->tol = t->tol;
        if (_cb_ssi_result_move(r, t) != CB_OK) {
            cb_ssi_result_clear(t);
            return cb_error_set(err, CB_ERR_NOMEM,
                                "ssi: out of memory collecting the closed-form result");
        }
        *done = 1;
    }
    cb_ssi_result_clear(t);
    return CB_OK;
}
