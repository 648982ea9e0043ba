/* Distance from a point to a face surface: closed forms for the elementary surfaces, a reduced
 * one-parameter search for surfaces of revolution and extrusion, sample grid plus Newton steps
 * for B-splines and the ellipsoid. Every value returned is the distance to an actual surface
 * point, so it never understates the true distance. */
#include <stdlib.h>
#include <string.h>

#include "brep/topo.h"

static const double PI = 3.14159265358979323846;

enum { MAX_GRID = 96, N_STARTS = 3 };

/* Parameter box of a B-spline profile or conic, for the one-parameter searches. */
static void curve_range(const cb_topo_curve *c, double *a, double *b)
{
    if (c->kind == CB_CURVE_NURBS) {
        cb_nurbs_curve_domain(c->nurbs, a, b);
    } else {
        *a = 0.0;
        *b = 2.0 * PI;
    }
}

cb_status cb_topo_projector_init(cb_topo_projector *pr, const cb_topo_surface *s, cb_error *err)
{
    memset(pr, 0, sizeof *pr);
    pr->s = s;
    if (s->kind == CB_SURFACE_NURBS) {
        cb_nurbs_surface_domain(s->nurbs, pr->box);
        int nu = 4 * (s->nurbs->n_u - s->nurbs->deg_u) + 1,
            nv = 4 * (s->nurbs->n_v - s->nurbs->deg_v) + 1;
        pr->nu = nu > MAX_GRID ? MAX_GRID : nu;
        pr->nv = nv > MAX_GRID ? MAX_GRID : nv;
    } else if (s->kind == CB_SURFACE_ANALYTIC && s->analytic.kind == CB_ANALYTIC_ELLIPSOID) {
        double box[4] = {0.0, 2.0 * PI, -0.5 * PI, 0.5 * PI};
        memcpy(pr->box, box, sizeof box);
        pr->nu = 48;
        pr->nv = 25;
    } else {
        return CB_OK;
    }
    pr->grid = malloc((size_t)pr->nu * pr->nv * 3 * sizeof *pr->grid);
    if (!pr->grid)
        return cb_error_set(err, CB_ERR_NOMEM, "projector: no memory for a %d x %d grid", pr->nu,
                            pr->nv);
    for (int i = 0; i < pr->nu; i++)
        for (int j = 0; j < pr->nv; j++) {
            double u = pr->box[0] + (pr->box[1] - pr->box[0]) * i / (pr->nu - 1);
            double v = pr->box[2] + (pr->box[3] - pr->box[2]) * j / (pr->nv - 1);
            double d[6][3];
            cb_topo_surface_eval_derivs(d, s, u, v);
            memcpy(pr->grid + 3 * ((size_t)i * pr->nv + j), d[0], sizeof d[0]);
        }
    return CB_OK;
}

void cb_topo_projector_clear(cb_topo_projector *pr)
{
    free(pr->grid);
    memset(pr, 0, sizeof *pr);
}

/* Newton steps on |S(u, v) - p|^2 / 2 from (u, v), inside the box; returns the least distance
 * met. The full Hessian is used where it is positive definite, Gauss-Newton elsewhere. */
static double surface_newton(const cb_topo_surface *s, const double box[4], const double p[3],
                             double u, double v)
{
    double best = HUGE_VAL;
    for (int it = 0; it < 30; it++) {
        double d[6][3], r[3];
        cb_topo_surface_eval_derivs(d, s, u, v);
        for (int i = 0; i < 3; i++)
            r[i] = d[0][i] - p[i];
        best = fmin(best, cb_vec3_norm(r));
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
        if (!(det > 0))
            break;
        double du = (hc * gu - hb * gv) / det, dv = (ha * gv - hb * gu) / det;
        double nu = fmin(box[1], fmax(box[0], u - du)), nv = fmin(box[3], fmax(box[2], v - dv));
        double scale = fabs(box[0]) + fabs(box[1]) + fabs(box[2]) + fabs(box[3]) + 1.0;
        if (fabs(nu - u) + fabs(nv - v) <= 1e-15 * scale)
            break;
        u = nu;
        v = nv;
    }
    return best;
}

int cb_topo_projector_starts(double (*uv)[2], int max, const cb_topo_projector *pr,
                             const double p[3])
{
    int idx[CB_TOPO_MAX_STARTS];
    double dist[CB_TOPO_MAX_STARTS];
    if (max > CB_TOPO_MAX_STARTS)
        max = CB_TOPO_MAX_STARTS;
    for (int k = 0; k < max; k++) {
        idx[k] = -1;
        dist[k] = HUGE_VAL;
    }
    for (int k = 0; k < pr->nu * pr->nv; k++) {
        const double *g = pr->grid + 3 * (size_t)k;
        double d = cb_vec3_dist(g, p);
        if (!(d < dist[max - 1]))
            continue;
        /* A point sampled many times (a pole row, a degenerate side) gives at most two
         * starts: its starts differ only in a parameter Newton cannot move there (S_u vanishes
         * at a pole), and would crowd out the samples beside them, so a point near the pole
         * was never searched for beyond it. Two, so that a seam's two lifts both stay. */
        int dup = 0;
        for (int j = 0; j < max && idx[j] >= 0; j++)
            dup += cb_vec3_dist(pr->grid + 3 * (size_t)idx[j], g) <=
                   1e-13 * (1.0 + cb_vec3_norm(g));
        if (dup >= 2)
            continue;
        for (int j = 0; j < max; j++)
            if (d < dist[j]) {
                for (int m = max - 1; m > j; m--) {
                    dist[m] = dist[m - 1];
                    idx[m] = idx[m - 1];
                }
                dist[j] = d;
                idx[j] = k;
                break;
            }
    }
    int n = 0;
    for (; n < max && idx[n] >= 0; n++) {
        uv[n][0] = pr->box[0] + (pr->box[1] - pr->box[0]) * (idx[n] / pr->nv) / (pr->nu - 1);
        uv[n][1] = pr->box[2] + (pr->box[3] - pr->box[2]) * (idx[n] % pr->nv) / (pr->nv - 1);
    }
    return n;
}

/* Grid search then Newton from the N_STARTS nearest samples. */
static double grid_distance(const cb_topo_projector *pr, const double p[3])
{
    double uv[N_STARTS][2];
    int n = cb_topo_projector_starts(uv, N_STARTS, pr, p);
    double best = HUGE_VAL;
    for (int j = 0; j < n; j++)
        best = fmin(best, surface_newton(pr->s, pr->box, p, uv[j][0], uv[j][1]));
    return best;
}

/* Surfaces of revolution and extrusion reduce to a curve problem: the distance from p to the
 * circle swept by C(v) is |(rho, h)(C(v)) - (rho, h)(p)| in the meridian plane; the distance to
 * the line C(u) + t dir is the distance of the projections across dir. */
static double reduced_gap(const cb_topo_surface *s, const double q[3], const double p[3])
{
    double a[3], b[3];
    for (int i = 0; i < 3; i++) {
        a[i] = q[i] - (s->kind == CB_SURFACE_REVOLUTION ? s->frame.o[i] : 0.0);
        b[i] = p[i] - (s->kind == CB_SURFACE_REVOLUTION ? s->frame.o[i] : 0.0);
    }
    if (s->kind == CB_SURFACE_REVOLUTION) {
        const double *z = s->frame.z;
        double ha = cb_vec3_dot(a, z), hb = cb_vec3_dot(b, z), ra[3], rb[3];
        for (int i = 0; i < 3; i++) {
            ra[i] = a[i] - ha * z[i];
            rb[i] = b[i] - hb * z[i];
        }
        return hypot(cb_vec3_norm(ra) - cb_vec3_norm(rb), ha - hb);
    }
    double d[3] = {s->dir[0], s->dir[1], s->dir[2]}, g[3];
    cb_vec3_normalize(d);
    for (int i = 0; i < 3; i++)
        g[i] = a[i] - b[i];
    double along = cb_vec3_dot(g, d);
    for (int i = 0; i < 3; i++)
        g[i] -= along * d[i];
    return cb_vec3_norm(g);
}

static double reduced_at(const cb_topo_surface *s, const double p[3], double t)
{
    double q[3];
    cb_topo_curve_eval(q, &s->profile, t);
    return reduced_gap(s, q, p);
}

/* Samples the profile parameter, then golden-section search around the best sample. */
static double reduced_distance(const cb_topo_surface *s, const double p[3])
{
    const cb_topo_curve *c = &s->profile;
    double a, b;
    if (c->kind == CB_CURVE_LINE) {
        /* The nearest swept point lies within |p - C(t*)| of p, so its parameter lies within
         * a bounded window around the projection t* of p on the line. */
        double t0, d0 = cb_topo_curve_project(&t0, c, p, 0, 0);
        double q[3];
        cb_topo_curve_eval(q, c, t0);
        double reach =
            (2.0 * d0 + cb_vec3_dist(q, s->frame.o) + cb_vec3_dist(p, s->frame.o)) / c->r1 + 1.0;
        a = t0 - reach;
        b = t0 + reach;
    } else {
        curve_range(c, &a, &b);
    }
    int n = c->kind == CB_CURVE_NURBS ? 8 * (c->nurbs->n - c->nurbs->deg) + 64 : 256;
    if (n > 4096)
        n = 4096;
    double best_t = a, best = HUGE_VAL, h = (b - a) / n;
    for (int k = 0; k <= n; k++) {
        double t = a + h * k, d = reduced_at(s, p, t);
        if (d < best) {
            best = d;
            best_t = t;
        }
    }
    const double g = 0.6180339887498949;
    /* A conic is periodic: its bracket may cross 0 = 2 pi. */
    int periodic = c->kind == CB_CURVE_CIRCLE || c->kind == CB_CURVE_ELLIPSE;
    double lo = periodic ? best_t - h : fmax(a, best_t - h);
    double hi = periodic ? best_t + h : fmin(b, best_t + h);
    double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
    double f1 = reduced_at(s, p, x1), f2 = reduced_at(s, p, x2);
    for (int it = 0; it < 60; it++) {
        if (f1 < f2) {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - g * (hi - lo);
            f1 = reduced_at(s, p, x1);
        } else {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + g * (hi - lo);
            f2 = reduced_at(s, p, x2);
        }
    }
    return fmin(best, fmin(f1, f2));
}

/* Closed-form distances to the elementary surfaces (both nappes of the cone, as its
 * parameterisation covers v on both sides of the apex). */
static double analytic_distance(const cb_analytic_surface *a, const double p[3])
{
    double l[3];
    cb_frame_to_local(l, &a->frame, p);
    double rho = hypot(l[0], l[1]);
    switch (a->kind) {
    case CB_ANALYTIC_PLANE: return fabs(l[2]);
    case CB_ANALYTIC_CYLINDER: return fabs(rho - a->r1);
    case CB_ANALYTIC_SPHERE: return fabs(cb_vec3_norm(l) - a->r1);
    case CB_ANALYTIC_TORUS:
        /* The tube's circle on the far side of the axis too: a spindle torus (R < r) reaches
         * across the axis, its lemon part nearer the far circle. */
        return fmin(fabs(hypot(rho - a->r1, l[2]) - a->r2), fabs(hypot(rho + a->r1, l[2]) - a->r2));
    case CB_ANALYTIC_CONE: {
        double c = cos(a->angle), s = sin(a->angle);
        return fmin(fabs((rho - a->r1) * c - l[2] * s), fabs((-rho - a->r1) * c - l[2] * s));
    }
    default: return HUGE_VAL;
    }
}

double cb_topo_projector_distance(const cb_topo_projector *pr, const double p[3])
{
    const cb_topo_surface *s = pr->s;
    if (pr->grid)
        return grid_distance(pr, p);
    if (s->kind == CB_SURFACE_ANALYTIC)
        return analytic_distance(&s->analytic, p);
    return reduced_distance(s, p);
}
