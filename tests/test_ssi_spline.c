/* test_ssi_spline.c — B-spline/B-spline intersection by the subdivision route (ssi/spline.h):
 * interval enclosures (polynomial and rational patches), a paraboloid against a tilted plane
 * (closed form circle), two crossing spline cylinders, a loop of radius 1e-3, a touching pair
 * (must be reported, not dropped), a patch against itself (coincident), a rational bicubic
 * against a plane, an analytic cylinder against a B-spline of degree 7 (converted), two patches
 * sharing a side, thread-count independence. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "brep/mass.h"
#include "check.h"
#include "io/step.h"
#include "io/step_write.h"
#include "models/models.h"
#include "ssi/dixon.h"
#include "ssi/implicit.h"
#include "ssi/spline.h"
#include "ssi/ssi.h"

static double now_s(void)
{
    struct timespec ts;
    timespec_get(&ts, TIME_UTC);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Bicubic graph x = u, y = v, z = c - (u - .5)^2 - (v - .5)^2 on [0,1]^2 (exact control net:
 * linear and quadratic precision of the Bernstein basis), with the knot 0.5 inserted both ways
 * (4 Bezier patches). */
static void paraboloid(cb_nurbs_surface_t s, double c)
{
    const double t1[4] = {0, 1.0 / 3, 2.0 / 3, 1}, t2[4] = {0, 0, 1.0 / 3, 1};
    double pts[48], knots[8] = {0, 0, 0, 0, 1, 1, 1, 1};
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            /* -(u - .5)^2 = -u^2 + u - .25 in Bernstein form. */
            double fu = -t2[i] + t1[i] - 0.25, fv = -t2[j] + t1[j] - 0.25;
            pts[3 * (4 * i + j)] = t1[i];
            pts[3 * (4 * i + j) + 1] = t1[j];
            pts[3 * (4 * i + j) + 2] = c + fu + fv;
        }
    cb_error err;
    cb_nurbs_surface_make(s, 3, 3, knots, 8, knots, 8, pts, NULL, 4, 4, &err);
    cb_nurbs_surface_insert_knot(s, s, CB_DIR_U, 0.5, 1, &err);
    cb_nurbs_surface_insert_knot(s, s, CB_DIR_V, 0.5, 1, &err);
}

/* The plane z = z0 + alpha (x - 0.5) as a bicubic patch: a square of side 2 centred at
 * (0.5, 0.5) in xy, turned by theta, so its parameter lines are not those of the paraboloid. */
static void tilted_plane(cb_nurbs_surface_t s, double z0, double alpha, double theta)
{
    double a[3] = {2 * cos(theta), 2 * sin(theta), 0}, b[3] = {-2 * sin(theta), 2 * cos(theta), 0};
    a[2] = alpha * a[0];
    b[2] = alpha * b[0];
    double o[3] = {0.5 - 0.5 * a[0] - 0.5 * b[0], 0.5 - 0.5 * a[1] - 0.5 * b[1], 0};
    o[2] = z0 + alpha * (o[0] - 0.5);
    double pts[48], knots[8] = {0, 0, 0, 0, 1, 1, 1, 1};
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            for (int q = 0; q < 3; q++)
                pts[3 * (4 * i + j) + q] = o[q] + a[q] * i / 3.0 + b[q] * j / 3.0;
    cb_error err;
    cb_nurbs_surface_make(s, 3, 3, knots, 8, knots, 8, pts, NULL, 4, 4, &err);
}

/* Polynomial cylinder about an axis: 4 cubic quarter arcs (the usual 0.5523 handle; radius
 * error 2.7e-4 r) around, one cubic span of length len along. axis 0: along x (circle in yz),
 * 2: along z (circle in xy); phase turns the seam; off shifts the circle centre. */
static void spline_cylinder(cb_nurbs_surface_t s, int axis, double r, double len, double phase,
                            const double off[2])
{
    const double k = 0.5522847498;
    double ku[17] = {0, 0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 3, 3, 4, 4, 4, 4};
    double kv[8] = {0, 0, 0, 0, 1, 1, 1, 1};
    double pts[13 * 4 * 3];
    for (int i = 0; i < 13; i++) {
        int q = i / 3, l = i % 3;
        double a0 = phase + q * CB_SSI_PI / 2, a1 = a0 + CB_SSI_PI / 2, c[2];
        if (i == 12) {
            c[0] = cos(phase);
            c[1] = sin(phase);
        } else if (l == 0) {
            c[0] = cos(a0);
            c[1] = sin(a0);
        } else if (l == 1) {
            c[0] = cos(a0) - k * sin(a0);
            c[1] = sin(a0) + k * cos(a0);
        } else {
            c[0] = cos(a1) + k * sin(a1);
            c[1] = sin(a1) - k * cos(a1);
        }
        for (int j = 0; j < 4; j++) {
            double w = -len / 2 + len * j / 3.0, p[3];
            double x = off[0] + r * c[0], y = off[1] + r * c[1];
            if (axis == 2) {
                p[0] = x;
                p[1] = y;
                p[2] = w;
            } else {
                p[0] = w;
                p[1] = x;
                p[2] = y;
            }
            for (int d = 0; d < 3; d++)
                pts[3 * (4 * i + j) + d] = p[d];
        }
    }
    cb_error err;
    cb_nurbs_surface_make(s, 3, 3, ku, 17, kv, 8, pts, NULL, 13, 4, &err);
}

static double dist_on(const cb_nurbs_surface_t s, const double uv[2], const double X[3])
{
    double p[3];
    cb_nurbs_surface_eval(p, s, uv[0], uv[1]);
    return sqrt((p[0] - X[0]) * (p[0] - X[0]) + (p[1] - X[1]) * (p[1] - X[1]) +
                (p[2] - X[2]) * (p[2] - X[2]));
}

/* Largest distance of a curve point to A and B at its own parameters. */
static double max_dist(const cb_ssi_result_t r, const cb_nurbs_surface_t a,
                       const cb_nurbs_surface_t b)
{
    double m = 0;
    for (slong c = 0; c < r->n_curves; c++)
        for (slong i = 0; i < r->curve[c].n; i++) {
            const cb_ssi_point *p = r->curve[c].pt + i;
            m = fmax(m, fmax(dist_on(a, p->uv_a, p->xyz), dist_on(b, p->uv_b, p->xyz)));
        }
    return m;
}

static cb_status run(cb_ssi_result_t r, const cb_nurbs_surface_t a, const cb_nurbs_surface_t b,
                     const cb_ssi_opts *o, const char *name)
{
    cb_ssi_surface A, B;
    cb_ssi_surface_set_nurbs(&A, a);
    cb_ssi_surface_set_nurbs(&B, b);
    cb_error err;
    cb_error_clear(&err);
    cb_ssi_result_init(r);
    double t0 = now_s();
    cb_status st = cb_ssi_surfaces(r, &A, &B, -1, -1, o, &err);
    CHECK(st == CB_OK, "%s: %s", name, err.msg);
    slong npts = 0;
    for (slong c = 0; c < r->n_curves; c++)
        npts += r->curve[c].n;
    printf("%-30s %.3f s: curves %ld (%ld points), pairs %ld culled %ld subdivided %ld "
           "certified %ld within tolerance %ld failed %ld, sub-pairs %ld, max dist %.1e (tol "
           "%.1e)\n",
           name, now_s() - t0, (long)r->n_curves, (long)npts, (long)r->pairs_total,
           (long)r->pairs_culled, (long)r->pairs_subdivided, (long)r->pairs_certified,
           (long)r->pairs_within_tolerance, (long)r->n_failed, (long)r->subpairs,
           max_dist(r, a, b), r->tol);
    /* Outcomes: every pair counted once; a curve is certified unless a join in it was made
     * within tolerance (then a region says where). */
    int uncertified = 0;
    for (slong c = 0; c < r->n_curves; c++)
        uncertified += !r->curve[c].certified;
    CHECK(r->pairs_certified + r->pairs_within_tolerance + r->pairs_culled + r->n_failed >=
                  r->pairs_total &&
              (uncertified == 0 || r->n_regions > 0),
          "%s: %ld + %ld + %ld + %ld refused of %ld pairs, %d curves not certified, %ld regions",
          name, (long)r->pairs_certified, (long)r->pairs_within_tolerance,
          (long)r->pairs_culled, (long)r->n_failed, (long)r->pairs_total, uncertified,
          (long)r->n_regions);
    return st;
}

/* Every curve and pair certified, nothing within tolerance. */
static void check_certified(const cb_ssi_result_t r, const char *name)
{
    int uncertified = 0;
    for (slong c = 0; c < r->n_curves; c++)
        uncertified += !r->curve[c].certified;
    CHECK(uncertified == 0 && r->pairs_within_tolerance == 0 && r->n_regions == 0,
          "%s: %d curves not certified, %ld pairs within tolerance, %ld regions", name,
          uncertified, (long)r->pairs_within_tolerance, (long)r->n_regions);
}

/* Interval evaluation must enclose the point evaluation anywhere in the box. */
/* The widest interval enclosure of b at 500 random points of [0, 1]^2; bad counts the points
 * whose floating-point value (within 1e-14) it does not hold. */
static double widest_at_points(const _cb_ssi_bez *b, check_rng *rng, int *bad)
{
    double widest = 0;
    for (int trial = 0; trial < 500; trial++) {
        double u = check_rng_uniform(rng, 0, 1), v = check_rng_uniform(rng, 0, 1);
        _cb_iv X[3], Xu[3], Xv[3];
        _cb_ssi_bez_eval_iv(X, Xu, Xv, b, _cb_iv_pt(u), _cb_iv_pt(v));
        double p[3], pu[3], pv[3];
        _cb_ssi_bez_eval(p, pu, pv, b, u, v);
        for (int q = 0; q < 3; q++) {
            *bad += !(p[q] >= X[q].lo - 1e-14 && p[q] <= X[q].hi + 1e-14);
            widest = fmax(widest, X[q].hi - X[q].lo);
        }
    }
    return widest;
}

static void test_enclosure(void)
{
    cb_nurbs_surface_t s;
    cb_nurbs_surface_init(s);
    check_rng rng = {7};
    double pts[48], knots[8] = {0, 0, 0, 0, 1, 1, 1, 1};
    for (int k = 0; k < 48; k++)
        pts[k] = check_rng_uniform(&rng, -1, 1);
    cb_error err;
    cb_nurbs_surface_make(s, 3, 3, knots, 8, knots, 8, pts, NULL, 4, 4, &err);
    _cb_ssi_bez b;
    CHECK(_cb_ssi_bez_set(&b, s, &err) == CB_OK, "bez_set: %s", err.msg);
    int bad = 0;
    for (int trial = 0; trial < 2000; trial++) {
        double w = ldexp(1, -check_rng_int(&rng, 0, 30));
        double u0 = check_rng_uniform(&rng, 0, 1 - w), v0 = check_rng_uniform(&rng, 0, 1 - w);
        _cb_iv U = {u0, u0 + w}, V = {v0, v0 + w}, X[3], Xu[3], Xv[3];
        _cb_ssi_bez_eval_iv(X, Xu, Xv, &b, U, V);
        double u = u0 + w * check_rng_uniform(&rng, 0, 1),
               v = v0 + w * check_rng_uniform(&rng, 0, 1);
        double p[3], pu[3], pv[3];
        _cb_ssi_bez_eval(p, pu, pv, &b, u, v);
        for (int q = 0; q < 3; q++)
            bad += !(p[q] >= X[q].lo - 1e-15 * (1 + fabs(p[q])) &&
                     p[q] <= X[q].hi + 1e-15 * (1 + fabs(p[q]))) ||
                   !(pu[q] >= Xu[q].lo - 1e-14 && pu[q] <= Xu[q].hi + 1e-14) ||
                   !(pv[q] >= Xv[q].lo - 1e-14 && pv[q] <= Xv[q].hi + 1e-14);
        double d[6][3];
        cb_nurbs_surface_eval_derivs(d, s, u, v);
        for (int q = 0; q < 3; q++)
            bad += fabs(d[0][q] - p[q]) > 1e-14 || fabs(d[1][q] - pu[q]) > 1e-12 ||
                   fabs(d[2][q] - pv[q]) > 1e-12;
    }
    CHECK(bad == 0, "%d enclosure or evaluation failures", bad);
    /* A rational patch: the same enclosure property for X = P / w and its quotient-rule
     * partials, and agreement with the NURBS evaluator. */
    double wts[16];
    for (int k = 0; k < 16; k++)
        wts[k] = check_rng_uniform(&rng, 0.5, 2);
    cb_nurbs_surface_t rs;
    cb_nurbs_surface_init(rs);
    cb_nurbs_surface_make(rs, 3, 3, knots, 8, knots, 8, pts, wts, 4, 4, &err);
    _cb_ssi_bez rb;
    CHECK(_cb_ssi_bez_set(&rb, rs, &err) == CB_OK && rb.rat == 1 && rb.dim == 4,
          "rational patch: %s", err.msg);
    bad = 0;
    for (int trial = 0; trial < 2000 && rb.rat; trial++) {
        double w = ldexp(1, -check_rng_int(&rng, 0, 30));
        double u0 = check_rng_uniform(&rng, 0, 1 - w), v0 = check_rng_uniform(&rng, 0, 1 - w);
        _cb_iv U = {u0, u0 + w}, V = {v0, v0 + w}, X[3], Xu[3], Xv[3];
        _cb_ssi_bez_eval_iv(X, Xu, Xv, &rb, U, V);
        double u = u0 + w * check_rng_uniform(&rng, 0, 1),
               v = v0 + w * check_rng_uniform(&rng, 0, 1);
        double p[3], pu[3], pv[3], d[6][3];
        _cb_ssi_bez_eval(p, pu, pv, &rb, u, v);
        cb_nurbs_surface_eval_derivs(d, rs, u, v);
        for (int q = 0; q < 3; q++) {
            int e = !(p[q] >= X[q].lo - 1e-15 * (1 + fabs(p[q])) &&
                      p[q] <= X[q].hi + 1e-15 * (1 + fabs(p[q]))) ||
                    !(pu[q] >= Xu[q].lo - 1e-13 && pu[q] <= Xu[q].hi + 1e-13) ||
                    !(pv[q] >= Xv[q].lo - 1e-13 && pv[q] <= Xv[q].hi + 1e-13) ||
                    fabs(d[0][q] - p[q]) > 1e-14 || fabs(d[1][q] - pu[q]) > 1e-11 ||
                    fabs(d[2][q] - pv[q]) > 1e-11;
            if (e && bad < 3)
                fprintf(stderr, "trial %d q %d: p %.17g in [%.17g, %.17g] vs %.17g; pu %.17g in "
                        "[%.17g, %.17g] vs %.17g; pv %.17g in [%.17g, %.17g] vs %.17g\n", trial, q,
                        p[q], X[q].lo, X[q].hi, d[0][q], pu[q], Xu[q].lo, Xu[q].hi, d[1][q],
                        pv[q], Xv[q].lo, Xv[q].hi, d[2][q]);
            bad += e;
        }
    }
    CHECK(bad == 0, "rational: %d enclosure or evaluation failures", bad);
    /* A rational patch of bidegree (6, 10), as CAD systems write sweeps: at a point the
     * enclosure holds the point evaluation and stays near round-off (interval de Casteljau in
     * the difference form alone widens by 1 + 2t per step, about 1e-7 here, too wide for the
     * root proofs of the boundary points). */
    double hk_u[14], hk_v[22], hp[3 * 77], hw[77];
    for (int k = 0; k < 14; k++)
        hk_u[k] = k < 7 ? 0 : 1;
    for (int k = 0; k < 22; k++)
        hk_v[k] = k < 11 ? 0 : 1;
    for (int k = 0; k < 77; k++) {
        for (int q = 0; q < 3; q++)
            hp[3 * k + q] = check_rng_uniform(&rng, 2, 8);
        hw[k] = check_rng_uniform(&rng, 0.9, 1.1);
    }
    cb_nurbs_surface_t hs;
    cb_nurbs_surface_init(hs);
    cb_nurbs_surface_make(hs, 6, 10, hk_u, 14, hk_v, 22, hp, hw, 7, 11, &err);
    _cb_ssi_bez hb;
    CHECK(_cb_ssi_bez_set(&hb, hs, &err) == CB_OK && hb.rat == 1, "(6, 10) patch: %s", err.msg);
    bad = 0;
    double widest = hb.rat ? widest_at_points(&hb, &rng, &bad) : 0;
    CHECK(bad == 0 && widest < 1e-12,
          "(6, 10) patch at points: %d enclosure failures, widest enclosure %.3g", bad, widest);
    _cb_ssi_bez_clear(&hb);
    cb_nurbs_surface_clear(hs);
    /* A polynomial patch of bidegree (5, 3), coordinates up to 1.6 as in the SSI corpus: at a
     * point the enclosure stays within a few dozen round-offs (the difference form's 3^8 growth
     * made it 1e-12 wide, and near a tangency the boundary roots unprovable). */
    double pk_u[12], pk_v[8], pp[3 * 24];
    for (int k = 0; k < 12; k++)
        pk_u[k] = k < 6 ? 0 : 1;
    for (int k = 0; k < 8; k++)
        pk_v[k] = k < 4 ? 0 : 1;
    for (int k = 0; k < 3 * 24; k++)
        pp[k] = check_rng_uniform(&rng, -1.6, 1.6);
    cb_nurbs_surface_t ps;
    cb_nurbs_surface_init(ps);
    cb_nurbs_surface_make(ps, 5, 3, pk_u, 12, pk_v, 8, pp, NULL, 6, 4, &err);
    _cb_ssi_bez pb;
    CHECK(_cb_ssi_bez_set(&pb, ps, &err) == CB_OK && pb.rat == 0, "(5, 3) patch: %s", err.msg);
    bad = 0;
    widest = widest_at_points(&pb, &rng, &bad);
    printf("(5, 3) patch at points: widest enclosure %.3g\n", widest);
    CHECK(bad == 0 && widest < 2e-14,
          "(5, 3) patch at points: %d enclosure failures, widest enclosure %.3g", bad, widest);
    _cb_ssi_bez_clear(&pb);
    cb_nurbs_surface_clear(ps);
    _cb_ssi_bez_clear(&rb);
    _cb_ssi_bez_clear(&b);
    cb_nurbs_surface_clear(s);
    cb_nurbs_surface_clear(rs);
}

/* Circle (x - .5 + alpha/2)^2 + (y - .5)^2 = R^2 where the paraboloid z = c - (x-.5)^2 -
 * (y-.5)^2 meets z = z0 + alpha (x - .5), c - z0 = R^2 - alpha^2 / 4. Returns the largest
 * deviation of the curve points from that circle (in xy and in z on the plane). */
static double circle_error(const cb_ssi_result_t r, double R, double alpha, double z0)
{
    double m = 0;
    for (slong c = 0; c < r->n_curves; c++)
        for (slong i = 0; i < r->curve[c].n; i++) {
            const double *x = r->curve[c].pt[i].xyz;
            m = fmax(m, fabs(hypot(x[0] - 0.5 + alpha / 2, x[1] - 0.5) - R));
            m = fmax(m, fabs(x[2] - z0 - alpha * (x[0] - 0.5)));
        }
    return m;
}

static int same_result(const cb_ssi_result_t a, const cb_ssi_result_t b)
{
    int same =
        a->n_curves == b->n_curves && a->n_points == b->n_points && a->n_failed == b->n_failed;
    for (slong c = 0; same && c < a->n_curves; c++) {
        same = a->curve[c].n == b->curve[c].n && a->curve[c].closed == b->curve[c].closed;
        for (slong i = 0; same && i < a->curve[c].n; i++)
            same = !memcmp(a->curve[c].pt + i, b->curve[c].pt + i, sizeof(cb_ssi_point));
    }
    return same;
}

static void test_paraboloid_plane(void)
{
    const double R = 0.3, alpha = 0.2, z0 = -(R * R - alpha * alpha / 4);
    cb_nurbs_surface_t p, q;
    cb_nurbs_surface_init(p);
    cb_nurbs_surface_init(q);
    paraboloid(p, 0);
    tilted_plane(q, z0, alpha, 0.3);
    cb_ssi_opts o;
    cb_ssi_opts_default(&o);
    o.tol = 1e-7;
    o.threads = 1;
    /* The algebraic route (the plane implicit, phi of bidegree (2, 2)): the circle's folds
     * lie on the patch sides y = 1/2 up to the rounding of the turned plane, 2^-53 away,
     * which the topology separates only with deep enough fibre partitions. */
    cb_ssi_result_t r0;
    run(r0, p, q, &o, "paraboloid x plane, algebraic");
    CHECK(r0->status == CB_OK && r0->n_failed == 0 && r0->pairs_subdivided == 0,
          "algebraic: %ld pairs not certified, %ld subdivided: %s", (long)r0->n_failed,
          (long)r0->pairs_subdivided, r0->n_failed ? r0->failed[0].msg : "");
    CHECK(r0->n_curves == 1 && r0->n_points == 0 && circle_error(r0, R, alpha, z0) < 1e-6,
          "algebraic: curves %ld points %ld", (long)r0->n_curves, (long)r0->n_points);
    if (r0->n_curves == 1)
        CHECK(r0->curve[0].closed, "algebraic: the circle is not closed");
    cb_ssi_result_clear(r0);
    /* The subdivision route on the same pair (max_phi_degree 1 keeps it off the algebraic
     * route). */
    o.max_phi_degree = 1;
    cb_ssi_result_t r1, r2;
    run(r1, p, q, &o, "paraboloid x plane, 1 thr");
    check_certified(r1, "paraboloid x plane, 1 thr");
    CHECK(r1->status == CB_OK && r1->n_failed == 0, "%ld pairs not certified: %s",
          (long)r1->n_failed, r1->n_failed ? r1->failed[0].msg : "");
    CHECK(r1->pairs_subdivided == 4, "pairs by subdivision %ld", (long)r1->pairs_subdivided);
    CHECK(r1->n_curves == 1 && r1->n_points == 0, "curves %ld points %ld", (long)r1->n_curves,
          (long)r1->n_points);
    if (r1->n_curves == 1)
        CHECK(r1->curve[0].closed && r1->curve[0].n > 20, "closed %d, %ld points",
              r1->curve[0].closed, (long)r1->curve[0].n);
    CHECK(max_dist(r1, p, q) <= 1e-7, "distance to the surfaces %g", max_dist(r1, p, q));
    CHECK(circle_error(r1, R, alpha, z0) < 1e-6, "circle error %g", circle_error(r1, R, alpha, z0));
    /* The polyline goes around once: its xy angles about the centre cover the circle. */
    if (r1->n_curves == 1) {
        double turn = 0;
        const cb_ssi_curve *c = r1->curve;
        for (slong i = 0; i + 1 < c->n; i++) {
            double a0 = atan2(c->pt[i].xyz[1] - 0.5, c->pt[i].xyz[0] - 0.5 + alpha / 2);
            double a1 = atan2(c->pt[i + 1].xyz[1] - 0.5, c->pt[i + 1].xyz[0] - 0.5 + alpha / 2);
            double d = a1 - a0;
            d -= 2 * CB_SSI_PI * nearbyint(d / (2 * CB_SSI_PI));
            turn += d;
        }
        CHECK(fabs(fabs(turn) - 2 * CB_SSI_PI) < 1e-9, "winding %g", turn / (2 * CB_SSI_PI));
    }
    o.threads = 2;
    run(r2, p, q, &o, "paraboloid x plane, 2 thr");
    check_certified(r2, "paraboloid x plane, 2 thr");
    CHECK(same_result(r1, r2), "1 and 2 threads differ");
    /* Swapping the surfaces swaps the parameters, not the curve count. */
    cb_ssi_result_t r3;
    o.threads = 1;
    run(r3, q, p, &o, "plane x paraboloid");
    check_certified(r3, "plane x paraboloid");
    CHECK(r3->n_curves == 1 && r3->n_failed == 0 && circle_error(r3, R, alpha, z0) < 1e-6,
          "swapped: curves %ld failed %ld", (long)r3->n_curves, (long)r3->n_failed);
    CHECK(max_dist(r3, q, p) <= 1e-7, "swapped distance %g", max_dist(r3, q, p));
    cb_ssi_result_clear(r1);
    cb_ssi_result_clear(r2);
    cb_ssi_result_clear(r3);
    cb_nurbs_surface_clear(p);
    cb_nurbs_surface_clear(q);
}

static void test_cylinders(void)
{
    const double R1 = 1, R2 = 0.6, off2[2] = {0.1, 0}, off1[2] = {0, 0};
    cb_nurbs_surface_t a, b;
    cb_nurbs_surface_init(a);
    cb_nurbs_surface_init(b);
    spline_cylinder(a, 2, R1, 4, 0.3, off1);
    spline_cylinder(b, 0, R2, 4, 0.7, off2);
    cb_ssi_opts o;
    cb_ssi_opts_default(&o);
    o.threads = 1;
    cb_ssi_result_t r1, r2;
    run(r1, a, b, &o, "cylinders r 1 x 0.6, 1 thr");
    check_certified(r1, "cylinders r 1 x 0.6, 1 thr");
    CHECK(r1->status == CB_OK && r1->n_failed == 0, "%ld pairs not certified: %s",
          (long)r1->n_failed, r1->n_failed ? r1->failed[0].msg : "");
    CHECK(r1->n_curves == 2 && r1->n_points == 0, "curves %ld points %ld", (long)r1->n_curves,
          (long)r1->n_points);
    double side[2] = {0, 0};
    for (slong c = 0; c < r1->n_curves && c < 2; c++) {
        CHECK(r1->curve[c].closed, "curve %ld not closed", (long)c);
        side[c] = r1->curve[c].pt[0].xyz[0];
    }
    /* One loop on each side of the large cylinder's axis (x > 0 and x < 0). */
    CHECK(side[0] * side[1] < 0, "loops on x = %g and %g", side[0], side[1]);
    CHECK(max_dist(r1, a, b) <= r1->tol, "distance %g > tol %g", max_dist(r1, a, b), r1->tol);
    /* Against the true cylinders: the spline ones deviate by up to 2.7e-4 r. */
    double dev = 0;
    for (slong c = 0; c < r1->n_curves; c++)
        for (slong i = 0; i < r1->curve[c].n; i++) {
            const double *x = r1->curve[c].pt[i].xyz;
            dev = fmax(dev, fabs(hypot(x[0], x[1]) - R1));
            dev = fmax(dev, fabs(hypot(x[1] - off2[0], x[2] - off2[1]) - R2));
        }
    CHECK(dev < 3e-4, "deviation from the round cylinders %g", dev);
    o.threads = 2;
    run(r2, a, b, &o, "cylinders r 1 x 0.6, 2 thr");
    check_certified(r2, "cylinders r 1 x 0.6, 2 thr");
    CHECK(same_result(r1, r2), "1 and 2 threads differ");
    cb_ssi_result_clear(r1);
    cb_ssi_result_clear(r2);
    cb_nurbs_surface_clear(a);
    cb_nurbs_surface_clear(b);
}

/* A loop of radius 1e-3: the normals differ by ~2e-3 there, so it needs sub-patches of about
 * that size; it must come out as one closed curve, certified. */
static void test_small_loop(void)
{
    const double R = 1e-3, alpha = 0.2, z0 = -(R * R - alpha * alpha / 4);
    cb_nurbs_surface_t p, q;
    cb_nurbs_surface_init(p);
    cb_nurbs_surface_init(q);
    paraboloid(p, 0);
    tilted_plane(q, z0, alpha, 0.3);
    cb_ssi_opts o;
    cb_ssi_opts_default(&o);
    o.tol = 1e-9;
    o.chord = 1e-5;
    cb_ssi_result_t r;
    run(r, p, q, &o, "small loop r = 1e-3");
    check_certified(r, "small loop r = 1e-3");
    CHECK(r->status == CB_OK && r->n_failed == 0, "%ld pairs not certified: %s", (long)r->n_failed,
          r->n_failed ? r->failed[0].msg : "");
    CHECK(r->n_curves == 1, "curves %ld", (long)r->n_curves);
    if (r->n_curves == 1)
        CHECK(r->curve[0].closed && r->curve[0].n >= 8, "closed %d, %ld points", r->curve[0].closed,
              (long)r->curve[0].n);
    CHECK(circle_error(r, R, alpha, z0) < 1e-8, "circle error %g", circle_error(r, R, alpha, z0));
    CHECK(max_dist(r, p, q) <= 1e-9, "distance %g", max_dist(r, p, q));
    cb_ssi_result_clear(r);

    /* Touching at one point (R = 0) by the subdivision route (a planar patch is implicitised,
     * so max_phi_degree 1 keeps this pair off the algebraic route): no direction exists near
     * the contact, so that region must be reported with a box around (x, y) = (0.4, 0.5),
     * never dropped. */
    cb_nurbs_surface_t q0;
    cb_nurbs_surface_init(q0);
    tilted_plane(q0, alpha * alpha / 4, alpha, 0.3);
    o.spline_max_depth = 12;
    o.max_phi_degree = 1;
    run(r, p, q0, &o, "touching at a point");
    CHECK(r->status != CB_OK && r->n_failed >= 1, "touch not reported: %ld failures",
          (long)r->n_failed);
    int boxed = 0;
    for (slong k = 0; k < r->n_failed; k++) {
        const cb_ssi_failure *f = r->failed + k;
        boxed |= f->has_box && f->box_a[0] <= 0.4 && f->box_a[1] >= 0.4 && f->box_a[2] <= 0.5 &&
                 f->box_a[3] >= 0.5 && f->box_a[1] - f->box_a[0] < 0.01;
    }
    CHECK(boxed, "no small failure box around the contact (%ld failures: %s)", (long)r->n_failed,
          r->n_failed ? r->failed[0].msg : "");
    cb_ssi_result_clear(r);
    cb_nurbs_surface_clear(p);
    cb_nurbs_surface_clear(q);
    cb_nurbs_surface_clear(q0);
}

/* A patch against itself: no direction exists anywhere, so subdivision alone could only
 * report it; the coincidence test finds every patch pair on one surface first. */
static void test_coincident(void)
{
    cb_nurbs_surface_t p;
    cb_nurbs_surface_init(p);
    paraboloid(p, 0);
    cb_ssi_opts o;
    cb_ssi_opts_default(&o);
    cb_ssi_result_t r;
    run(r, p, p, &o, "patch x itself");
    /* The paraboloid is one polynomial surface cut into 4 Bezier patches: every patch pair,
     * neighbours included (each patch continued lies on the same surface), is coincident, so
     * the pair is one coincidence record and nothing is left uncertified. Proved, not
     * sampled (ssi_coincide.c): a patch against itself exactly (the 4 diagonal pairs,
     * certified); a patch against a neighbour only within round-off, since the patches come
     * from knot insertion in floating point (12 pairs within tolerance, regions that narrow). */
    CHECK(r->n_failed == 0 && r->status == CB_OK && r->n_curves == 0,
          "failures %ld status %d curves %ld", (long)r->n_failed, r->status, (long)r->n_curves);
    CHECK(r->n_coincident == 1 && r->pairs_coincident == 16 &&
              r->coincident[0].patch_pairs == 16 && r->coincident[0].same_normal == 1 &&
              r->coincident[0].whole == 1,
          "coincident records %ld, patch pairs %ld", (long)r->n_coincident,
          (long)r->pairs_coincident);
    double widest = 0;
    for (slong k = 0; k < r->n_regions; k++)
        widest = fmax(widest, r->region[k].width);
    CHECK(r->pairs_certified == 4 && r->pairs_within_tolerance == 12 && r->n_regions == 12 &&
              r->n_coincident == 1 && !r->coincident[0].exact &&
              r->coincident[0].width == widest && widest <= 1e-9 * r->tol,
          "patch x itself: %ld certified, %ld within tolerance, %ld regions up to %g (tol %g)",
          (long)r->pairs_certified, (long)r->pairs_within_tolerance, (long)r->n_regions, widest,
          r->tol);
    cb_ssi_result_clear(r);
    cb_nurbs_surface_clear(p);
}

/* A biquadratic paraboloid z = -(x - 1/2)^2 - (y - 1/2)^2 and its tangent plane at
 * (3/8, 1/2), a bicubic patch, every coefficient dyadic, so the contact is exact: the planar
 * patch is implicitised and the algebraic route proves one isolated point there, tangential,
 * where subdivision could only report the region uncertified. */
static void test_touch_exact(void)
{
    const double t[3] = {0, 0.5, 1}, f[3] = {-0.25, 0.25, -0.25}, al = 0.25;
    double pq[27], knots[6] = {0, 0, 0, 1, 1, 1};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            pq[3 * (3 * i + j)] = t[i];
            pq[3 * (3 * i + j) + 1] = t[j];
            pq[3 * (3 * i + j) + 2] = f[i] + f[j];
        }
    cb_nurbs_surface_t a, b;
    cb_nurbs_surface_init(a);
    cb_nurbs_surface_init(b);
    cb_error err;
    CHECK(cb_nurbs_surface_make(a, 2, 2, knots, 6, knots, 6, pq, NULL, 3, 3, &err) == CB_OK,
          "paraboloid: %s", err.msg);
    tilted_plane(b, al * al / 4, al, 0);
    cb_ssi_opts o;
    cb_ssi_opts_default(&o);
    cb_ssi_result_t r;
    run(r, a, b, &o, "touching at a point, exact");
    check_certified(r, "touching at a point, exact");
    CHECK(r->status == CB_OK && r->n_failed == 0 && r->n_curves == 0 && r->n_points == 1 &&
              r->pairs_subdivided == 0,
          "status %d, %ld failed, %ld curves, %ld points, %ld subdivided", r->status,
          (long)r->n_failed, (long)r->n_curves, (long)r->n_points, (long)r->pairs_subdivided);
    if (r->n_points == 1) {
        const cb_ssi_isolated *p = r->point;
        CHECK(p->tangential && fabs(p->p.xyz[0] - 0.375) < 1e-9 && fabs(p->p.xyz[1] - 0.5) < 1e-9 &&
                  fabs(p->p.xyz[2] + 1.0 / 64) < 1e-9 && fabs(p->p.uv_a[0] - 0.375) < 1e-9 &&
                  fabs(p->p.uv_a[1] - 0.5) < 1e-9,
              "contact at (%g, %g, %g), uv (%g, %g)", p->p.xyz[0], p->p.xyz[1], p->p.xyz[2],
              p->p.uv_a[0], p->p.uv_a[1]);
    }
    cb_ssi_result_clear(r);
    cb_nurbs_surface_clear(a);
    cb_nurbs_surface_clear(b);
}

/* Two bicubic patches sharing a side over part of it (as two faces sharing an edge): P over
 * x in [0, 1], Q on the other side of the plane x = 0, Q's side s = 0 P's side u = 0 over
 * [0.2, 0.9], reversed (de Casteljau in doubles: the two agree to round-off only). Found and
 * proved by _cb_ssi_cosides_find, not when the sides differ by 1e-4; the intersection is that
 * side, a curve within tolerance with a "side" region (refused before: the boundary-root search
 * meets a continuum of roots along it). */
static void test_shared_side(void)
{
    double pp[48], qp[48], knots[8] = {0, 0, 0, 0, 1, 1, 1, 1};
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            pp[3 * (4 * i + j)] = i / 3.0;
            pp[3 * (4 * i + j) + 1] = j / 3.0;
            pp[3 * (4 * i + j) + 2] = 0.1 * sin(1.7 * i + 2.3 * j + 0.4);
        }
    /* P's side u = 0 over [0.2, 0.9], reversed: split at 0.9, then the low part at 0.2 / 0.9. */
    double c[12], lo[12], hi[12];
    for (int j = 0; j < 4; j++)
        memcpy(c + 3 * j, pp + 3 * j, 3 * sizeof(double));
    for (int pass = 0; pass < 2; pass++) {
        double t = pass ? 0.2 / 0.9 : 0.9, w[12];
        memcpy(w, c, sizeof w);
        for (int r = 0; r <= 3; r++) {
            memcpy(lo + 3 * r, w, 3 * sizeof(double));
            memcpy(hi + 3 * (3 - r), w + 3 * (3 - r), 3 * sizeof(double));
            for (int k = 0; k + r < 3; k++)
                for (int q = 0; q < 3; q++)
                    w[3 * k + q] += t * (w[3 * k + 3 + q] - w[3 * k + q]);
        }
        memcpy(c, pass ? hi : lo, sizeof c);
    }
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            const double *e = c + 3 * (3 - j);
            qp[3 * (4 * i + j)] = e[0] - 0.2 * i;
            qp[3 * (4 * i + j) + 1] = e[1] + 0.03 * i * j;
            qp[3 * (4 * i + j) + 2] = e[2] + 0.15 * i - 0.02 * i * i;
        }
    cb_nurbs_surface_t a, b;
    cb_nurbs_surface_init(a);
    cb_nurbs_surface_init(b);
    cb_error err;
    CHECK(cb_nurbs_surface_make(a, 3, 3, knots, 8, knots, 8, pp, NULL, 4, 4, &err) == CB_OK &&
              cb_nurbs_surface_make(b, 3, 3, knots, 8, knots, 8, qp, NULL, 4, 4, &err) == CB_OK,
          "shared side: %s", err.msg);
    _cb_ssi_bez P, Q;
    CHECK(_cb_ssi_bez_set(&P, a, &err) == CB_OK && _cb_ssi_bez_set(&Q, b, &err) == CB_OK,
          "shared side: %s", err.msg);
    _cb_ssi_coside cs[8];
    int n = _cb_ssi_cosides_find(cs, 8, &P, &Q, 1e-6);
    CHECK(n == 1 && cs[0].sp == 0 && cs[0].sq == 0 && fabs(cs[0].t0 - 0.2) < 1e-9 &&
              fabs(cs[0].t1 - 0.9) < 1e-9 && cs[0].m0 == 1 && cs[0].m1 == 0 &&
              cs[0].width < 1e-12 && cs[0].ep > 0 && cs[0].eq > 0,
          "cosides %d: sides %d %d, t [%.12g, %.12g], mu %g %g, width %g", n,
          n ? cs[0].sp : -1, n ? cs[0].sq : -1, n ? cs[0].t0 : 0, n ? cs[0].t1 : 0,
          n ? cs[0].m0 : 0, n ? cs[0].m1 : 0, n ? cs[0].width : 0);
    Q.pts[3 * 1 + 2] += 1e-4;
    CHECK(_cb_ssi_cosides_find(cs, 8, &P, &Q, 1e-6) == 0, "sides 1e-4 apart taken as one");
    _cb_ssi_bez_clear(&P);
    _cb_ssi_bez_clear(&Q);

    cb_ssi_opts o;
    cb_ssi_opts_default(&o);
    cb_ssi_result_t r;
    run(r, a, b, &o, "shared side");
    int sides = 0;
    for (slong g = 0; g < r->n_regions; g++)
        sides += r->region[g].kind == CB_SSI_REGION_SIDE && r->region[g].width <= 0.5 * r->tol;
    CHECK(r->status == CB_OK && r->n_failed == 0 && r->n_curves == 1 && r->n_points == 0 &&
              sides >= 1 && r->pairs_within_tolerance >= 1,
          "status %d, %ld failed, %ld curves, %ld points, %d side regions", r->status,
          (long)r->n_failed, (long)r->n_curves, (long)r->n_points, sides);
    if (r->n_curves == 1) {
        const cb_ssi_curve *cv = r->curve;
        double X0[3], X1[3], d[6][3];
        cb_nurbs_surface_eval_derivs(d, a, 0, 0.2);
        memcpy(X0, d[0], sizeof X0);
        cb_nurbs_surface_eval_derivs(d, a, 0, 0.9);
        memcpy(X1, d[0], sizeof X1);
        const double *e0 = cv->pt[0].xyz, *e1 = cv->pt[cv->n - 1].xyz;
        double d0 = fmin(hypot(hypot(e0[0] - X0[0], e0[1] - X0[1]), e0[2] - X0[2]),
                         hypot(hypot(e1[0] - X0[0], e1[1] - X0[1]), e1[2] - X0[2]));
        double d1 = fmin(hypot(hypot(e0[0] - X1[0], e0[1] - X1[1]), e0[2] - X1[2]),
                         hypot(hypot(e1[0] - X1[0], e1[1] - X1[1]), e1[2] - X1[2]));
        double off = 0;
        for (slong i = 0; i < cv->n; i++)
            off = fmax(off, fabs(cv->pt[i].xyz[0]));
        CHECK(!cv->closed && !cv->certified && d0 < 1e-9 && d1 < 1e-9 && off < 1e-12 &&
                  max_dist(r, a, b) <= r->tol,
              "closed %d certified %d, ends %g and %g from the side's, %g off x = 0, distance %g",
              cv->closed, cv->certified, d0, d1, off, max_dist(r, a, b));
    }
    cb_ssi_result_clear(r);
    cb_nurbs_surface_clear(a);
    cb_nurbs_surface_clear(b);
}

/* Example 1's P of the paper, (x, y, z) and its partial derivatives at (s, t). */
static void paper_p(double X[3], double Xs[3], double Xt[3], double s, double t)
{
    X[0] = (-32 * s * s * s + 96 * s * t * t + 48 * s * s - 96 * s * t - 48 * t * t + 6 * s +
            48 * t - 11) / 2;
    X[1] = (96 * s * s * t - 32 * t * t * t - 48 * s * s - 96 * s * t + 48 * t * t + 48 * s +
            6 * t - 11) / 2;
    X[2] = (24 * s * s - 24 * t * t - 24 * s + 24 * t) / 2;
    Xs[0] = (-96 * s * s + 96 * t * t + 96 * s - 96 * t + 6) / 2;
    Xs[1] = (192 * s * t - 96 * s - 96 * t + 48) / 2;
    Xs[2] = (48 * s - 24) / 2;
    Xt[0] = (192 * s * t - 96 * s - 96 * t + 48) / 2;
    Xt[1] = (96 * s * s - 96 * t * t - 96 * s + 96 * t + 6) / 2;
    Xt[2] = (-48 * t + 24) / 2;
}

/* Some (u, v) in [0, 1]^2 with P(u, v) = X within 1e-9: Newton from an 11 x 11 grid of starts
 * (P folds over itself, so one start is not enough). */
static int paper_p_inside(const double X[3])
{
    for (int a = 0; a <= 10; a++)
        for (int b = 0; b <= 10; b++) {
            double u = a / 10.0, v = b / 10.0, P[3], Pu[3], Pv[3];
            for (int it = 0; it < 50 && fabs(u) < 5 && fabs(v) < 5; it++) {
                paper_p(P, Pu, Pv, u, v);
                double A = 0, B = 0, C = 0, ru = 0, rv = 0;
                for (int k = 0; k < 3; k++) {
                    A += Pu[k] * Pu[k];
                    B += Pu[k] * Pv[k];
                    C += Pv[k] * Pv[k];
                    ru += Pu[k] * (X[k] - P[k]);
                    rv += Pv[k] * (X[k] - P[k]);
                }
                double det = A * C - B * B;
                if (!(fabs(det) > 0))
                    break;
                u += (C * ru - B * rv) / det;
                v += (A * rv - B * ru) / det;
            }
            paper_p(P, Pu, Pv, u, v);
            double d = sqrt((P[0] - X[0]) * (P[0] - X[0]) + (P[1] - X[1]) * (P[1] - X[1]) +
                            (P[2] - X[2]) * (P[2] - X[2]));
            if (d < 1e-9 && u > -1e-9 && u < 1 + 1e-9 && v > -1e-9 && v < 1 + 1e-9)
                return 1;
        }
    return 0;
}

/* Distance from X to the nearest polyline segment of r's curves. */
static double curve_dist(const cb_ssi_result_t r, const double X[3])
{
    double best = HUGE_VAL;
    for (slong c = 0; c < r->n_curves; c++)
        for (slong q = 0; q + 1 < r->curve[c].n; q++) {
            const double *p0 = r->curve[c].pt[q].xyz, *p1 = r->curve[c].pt[q + 1].xyz;
            double d[3], w[3], dd = 0, dw = 0;
            for (int k = 0; k < 3; k++) {
                d[k] = p1[k] - p0[k];
                w[k] = X[k] - p0[k];
                dd += d[k] * d[k];
                dw += d[k] * w[k];
            }
            double t = dd > 0 ? fmin(1, fmax(0, dw / dd)) : 0, e = 0;
            for (int k = 0; k < 3; k++)
                e += (w[k] - t * d[k]) * (w[k] - t * d[k]);
            best = fmin(best, sqrt(e));
        }
    return best;
}

/* The paper's Example 2 pair (appendix A), P folding over itself, with max_phi_degree 27 (phi
 * has bidegree (27, 24)): the algebraic route certifies it. Checked against a reference made
 * without the SSI: on 199 lines s = const of Q's domain the sign changes of F(Q(s, t)) (F the
 * implicit equation, test_ssi_dixon.c) bracket the points of P's surface, kept when a Newton
 * search finds them a preimage in P's box; each must lie within the chord of an output curve.
 * Every output point lies on both surfaces and in both domains; every curve end lies on a
 * domain's side or is shared with another curve (a node). Two branches cross at a node where
 * the curve meets P's self-intersection; before the samples were placed from the middle of a
 * curve, the node's preimage on the other sheet was continued along, and a branch inside P's
 * box was dropped with status OK (174 of 860 reference points missed). */
static void test_example2_pair(void)
{
    cb_nurbs_surface_t P, Q;
    cb_nurbs_surface_init(P);
    cb_nurbs_surface_init(Q);
    cb_error err;
    cb_status st = cb_model_paper_example2(P, Q, &err);
    CHECK(st == CB_OK, "example 2: %s", err.msg);
    cb_ssi_opts o;
    cb_ssi_opts_default(&o);
    o.max_phi_degree = 27;
    cb_ssi_result_t r;
    run(r, P, Q, &o, "example 2, algebraic");
    check_certified(r, "example 2, algebraic");
    CHECK(r->status == CB_OK && r->n_failed == 0 && r->pairs_subdivided == 0 && r->n_curves > 0,
          "example 2: status %d, %ld failed, %ld subdivided, %ld curves", r->status,
          (long)r->n_failed, (long)r->pairs_subdivided, (long)r->n_curves);
    CHECK(max_dist(r, P, Q) <= r->tol, "example 2: distance %g", max_dist(r, P, Q));
    int outside = 0, loose = 0;
    const double eps = 1e-9;
    for (slong c = 0; c < r->n_curves; c++) {
        const cb_ssi_curve *cv = r->curve + c;
        for (slong i = 0; i < cv->n; i++) {
            const double *a = cv->pt[i].uv_a, *b = cv->pt[i].uv_b;
            outside += a[0] < -eps || a[0] > 1 + eps || a[1] < -eps || a[1] > 1 + eps ||
                       b[0] < -1 - eps || b[0] > 1 + eps || b[1] < -eps || b[1] > 2 + eps;
        }
        for (int e = 0; e < 2 && !cv->closed; e++) {
            const cb_ssi_point *p = cv->pt + (e ? cv->n - 1 : 0);
            int side = fabs(p->uv_a[0]) < eps || fabs(p->uv_a[0] - 1) < eps ||
                       fabs(p->uv_a[1]) < eps || fabs(p->uv_a[1] - 1) < eps ||
                       fabs(p->uv_b[0] + 1) < eps || fabs(p->uv_b[0] - 1) < eps ||
                       fabs(p->uv_b[1]) < eps || fabs(p->uv_b[1] - 2) < eps;
            int shared = 0;
            for (slong d = 0; d < r->n_curves && !side && !shared; d++)
                for (int f = 0; f < 2 && !shared; f++) {
                    const cb_ssi_point *q = r->curve[d].pt + (f ? r->curve[d].n - 1 : 0);
                    shared = (d != c || f != e) && !memcmp(q->xyz, p->xyz, sizeof q->xyz);
                }
            loose += !side && !shared;
        }
    }
    CHECK(outside == 0 && loose == 0,
          "example 2: %d points outside the domains, %d curve ends inside both and unshared",
          outside, loose);

    cb_dixon_patch_t dp, dq;
    cb_dixon_pencil_t D;
    cb_implicit_t F;
    cb_dixon_patch_init(dp);
    cb_dixon_patch_init(dq);
    cb_dixon_pencil_init(D);
    cb_implicit_init(F);
    st = cb_dixon_patch_set_bezier(dp, P, &err);
    if (st == CB_OK)
        st = cb_dixon_pencil_set(D, dp, &err);
    if (st == CB_OK)
        st = cb_implicit_from_dixon(F, D, dp, &err);
    if (st == CB_OK)
        st = cb_dixon_patch_set_bezier(dq, Q, &err);
    CHECK(st == CB_OK, "example 2 reference: %s", err.msg);
    int nref = 0, missed = 0;
    /* The default chord is 1e-3 of the model size, the tolerance 1e-6 of it. */
    double far = 0, chord = 1e3 * r->tol;
    for (int i = 1; i < 200 && st == CB_OK; i++) {
        double sl = i / 200.0, prev = cb_phi_eval_direct_d(F, dq, sl, 0);
        for (int j = 1; j <= 2000; j++) {
            double lo = (j - 1) / 2000.0, hi = j / 2000.0, f = cb_phi_eval_direct_d(F, dq, sl, hi);
            if ((prev < 0) != (f < 0)) {
                double flo = prev;
                for (int k = 0; k < 60; k++) {
                    double m = 0.5 * (lo + hi), fm = cb_phi_eval_direct_d(F, dq, sl, m);
                    if ((fm < 0) == (flo < 0)) {
                        lo = m;
                        flo = fm;
                    } else {
                        hi = m;
                    }
                }
                double X[3];
                cb_nurbs_surface_eval(X, Q, 2 * sl - 1, 2 * lo);
                if (paper_p_inside(X)) {
                    double d = curve_dist(r, X);
                    nref++;
                    far = fmax(far, d);
                    missed += d > 2 * chord;
                }
            }
            prev = f;
        }
    }
    CHECK(nref > 400 && missed == 0, "example 2: %d of %d reference points farther than %g from "
          "the curves (farthest %g)", missed, nref, 2 * chord, far);
    cb_dixon_patch_clear(dp);
    cb_dixon_patch_clear(dq);
    cb_dixon_pencil_clear(D);
    cb_implicit_clear(F);
    cb_ssi_result_clear(r);
    cb_nurbs_surface_clear(P);
    cb_nurbs_surface_clear(Q);
}

/* A rational bicubic (weight 2 at one inner control point, a bump) against a tilted plane
 * above its flat part: one closed curve around the bump, by the subdivision route, every point
 * on both. */
static void test_rational(void)
{
    double pts[48], wts[16], knots[8] = {0, 0, 0, 0, 1, 1, 1, 1};
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            pts[3 * (4 * i + j)] = i / 3.0;
            pts[3 * (4 * i + j) + 1] = j / 3.0;
            pts[3 * (4 * i + j) + 2] = (i == 1 && j == 2) ? 0.5 : 0;
            wts[4 * i + j] = (i == 1 && j == 1) ? 2 : 1;
        }
    cb_nurbs_surface_t a, b;
    cb_nurbs_surface_init(a);
    cb_nurbs_surface_init(b);
    cb_error err;
    cb_nurbs_surface_make(a, 3, 3, knots, 8, knots, 8, pts, wts, 4, 4, &err);
    tilted_plane(b, 0.1, 0.1, 0.2);
    cb_ssi_opts o;
    cb_ssi_opts_default(&o);
    cb_ssi_result_t r;
    /* The plane's patch is implicitised (phi of degree 3), or, with max_phi_degree 1, the
     * pair takes the subdivision route: one closed curve either way. */
    for (int route = 0; route < 2; route++) {
        o.max_phi_degree = route ? 1 : 12;
        run(r, a, b, &o, route ? "rational x bicubic, subdivision" : "rational x bicubic");
        check_certified(r, route ? "rational x bicubic, subdivision" : "rational x bicubic");
        CHECK(r->n_failed == 0 && r->status == CB_OK && r->n_curves == 1 &&
                  r->curve[0].closed && r->pairs_subdivided == route,
              "route %d: failures %ld status %d curves %ld subdivided %ld", route,
              (long)r->n_failed, r->status, (long)r->n_curves, (long)r->pairs_subdivided);
        CHECK(max_dist(r, a, b) <= 1e-7, "rational: distance to the surfaces %g",
              max_dist(r, a, b));
        cb_ssi_result_clear(r);
    }
    cb_nurbs_surface_clear(a);
    cb_nurbs_surface_clear(b);
}

/* The hummingbird against a posed copy (paper Fig. 12): every pair certified, every curve point
 * on both faces, every curve end continued by another curve (two closed surfaces meet in
 * closed curves; face pairs cut them at face boundaries), 1 and 2 threads identical. */
static void test_hummingbird(void)
{
    cb_hummingbird_params pa, pb;
    cb_hummingbird_params_default(&pa);
    cb_hummingbird_params_default(&pb);
    pb.axis[0] = 0.3;
    pb.axis[1] = 1;
    pb.axis[2] = 0.2;
    pb.angle_deg = 25;
    pb.translate[0] = 0.35;
    pb.translate[1] = 0.25;
    pb.translate[2] = 0.12;
    cb_topo_body *a = NULL, *b = NULL;
    cb_error err;
    cb_error_clear(&err);
    CHECK(cb_model_hummingbird(&a, &pa, &err) == CB_OK, "%s", err.msg);
    CHECK(cb_model_hummingbird(&b, &pb, &err) == CB_OK, "%s", err.msg);
    if (!a || !b)
        return;
    cb_ssi_result_t r[2];
    for (int k = 0; k < 2; k++) {
        cb_ssi_opts o;
        cb_ssi_opts_default(&o);
        o.threads = k + 1;
        cb_ssi_result_init(r[k]);
        double t0 = now_s();
        CHECK(cb_ssi_bodies(r[k], a, b, &o, &err) == CB_OK, "%s", err.msg);
        printf("hummingbird x posed copy, %d thr: %.2f s\n", k + 1, now_s() - t0);
    }
    const cb_ssi_result_struct *R = r[0];
    CHECK(R->status == CB_OK && R->n_failed == 0, "%ld pairs not certified: %s", (long)R->n_failed,
          R->n_failed ? R->failed[0].msg : "");
    char *hit = calloc((size_t)a->n_faces * (size_t)b->n_faces, 1);
    long pairs_hit = 0, lonely = 0, npts = 0;
    double dmax = 0;
    for (slong c = 0; c < R->n_curves; c++) {
        const cb_ssi_curve *cv = R->curve + c;
        char *h = hit + (size_t)cv->face_a * (size_t)b->n_faces + (size_t)cv->face_b;
        pairs_hit += !*h;
        *h = 1;
        npts += (long)cv->n;
        for (slong i = 0; i < cv->n; i++) {
            const cb_ssi_point *p = cv->pt + i;
            dmax = fmax(dmax,
                        dist_on(a->surfaces[a->faces[cv->face_a].surface].nurbs, p->uv_a, p->xyz));
            dmax = fmax(dmax,
                        dist_on(b->surfaces[b->faces[cv->face_b].surface].nurbs, p->uv_b, p->xyz));
        }
        if (cv->closed)
            continue;
        for (int e = 0; e < 2; e++) {
            const double *X = cv->pt[e ? cv->n - 1 : 0].xyz;
            int found = 0;
            for (slong d = 0; d < R->n_curves && !found; d++)
                for (int f = 0; f < 2 && !found; f++) {
                    const cb_ssi_curve *dv = R->curve + d;
                    const double *Y = dv->pt[f ? dv->n - 1 : 0].xyz;
                    found = !(d == c && f == e) &&
                            fabs(X[0] - Y[0]) + fabs(X[1] - Y[1]) + fabs(X[2] - Y[2]) <= 2 * R->tol;
                }
            lonely += !found;
        }
    }
    printf("hummingbird: %ld face pairs with a curve, %ld curves, %ld points, %ld Bezier pairs "
           "by subdivision, %ld sub-pairs, max dist %.1e (tol %.1e)\n",
           pairs_hit, (long)R->n_curves, npts, (long)R->pairs_subdivided, (long)R->subpairs, dmax,
           R->tol);
    CHECK(pairs_hit > 0 && R->n_curves >= pairs_hit, "face pairs %ld, curves %ld", pairs_hit,
          (long)R->n_curves);
    CHECK(dmax <= R->tol, "curve point %g from its face (tol %g)", dmax, R->tol);
    CHECK(lonely == 0, "%ld curve ends without a continuation", lonely);
    CHECK(same_result(r[0], r[1]), "1 and 2 threads differ");
    free(hit);
    cb_ssi_result_clear(r[0]);
    cb_ssi_result_clear(r[1]);
    cb_topo_body_free(a);
    cb_topo_body_free(b);
}

/* trj5_k1-al-214 (39 B-spline faces from Alias) against a copy moved by (0.5, 0.3, 0.2): five
 * patch pairs have critical fibres the curve topology cannot certify (not in generic
 * position); the subdivision route takes them over and certifies them, so every pair is
 * certified. */
static void test_fallback(void)
{
    const char *d = getenv("COLIBRI_SHARED");
    char path[1024];
    snprintf(path, sizeof path, "%s/models/trj5_k1-al-214.stp", d ? d : "../shared");
    cb_topo_body *A = NULL, *B = NULL;
    cb_error err;
    cb_status st = cb_step_read(&A, path, &err);
    if (!st)
        st = cb_step_read(&B, path, &err);
    CHECK(st == CB_OK, "%s: %s", path, err.msg);
    if (!st) {
        cb_xform x;
        const double t[3] = {0.5, 0.3, 0.2};
        cb_xform_translation(&x, t);
        cb_topo_body_transform(B, &x);
        cb_ssi_opts o;
        cb_ssi_opts_default(&o);
        o.threads = 2;
        cb_ssi_result_t r;
        cb_ssi_result_init(r);
        st = cb_ssi_bodies(r, A, B, &o, &err);
        CHECK(st == CB_OK && r->n_failed == 0,
              "trj5 against a moved copy: status %d, %ld pairs not certified (%s)", st,
              (long)r->n_failed, r->n_failed ? r->failed[0].msg : err.msg);
        printf("trj5 against a moved copy: %ld curves, %ld patch pairs certified, %ld within "
               "tolerance (%ld regions), %ld by subdivision, max distance %.2g / %.2g\n",
               (long)r->n_curves, (long)r->pairs_certified, (long)r->pairs_within_tolerance,
               (long)r->n_regions, (long)r->pairs_subdivided, r->max_dist_a, r->max_dist_b);
        CHECK(r->n_curves > 0 && r->max_dist_a <= r->tol && r->max_dist_b <= r->tol,
              "trj5: %ld curves, distances %g %g (tol %g)", (long)r->n_curves, r->max_dist_a,
              r->max_dist_b, r->tol);
        cb_ssi_result_clear(r);
    }
    cb_topo_body_free(A);
    cb_topo_body_free(B);
}

/* trj5_k1-al-214 against its copy of bench_parts' draw 2 (seed 1: turned 57.2 degrees about
 * its centroid, written and read as a STEP file like the bench's copies): A's face 36, an
 * extruded polyline (flat spans), over v in [10, 12] (two patches), against the span v in
 * [9, 10] of B's face 32, a planar span of a strip closed in v. A line of the wall crosses the
 * span from its side v = 10 to its side u = 1. P is B's planar span (no Dixon pencil), whose
 * map continued past its box folds back over the plane: the clipping's continuation followed
 * a preimage outside the box from the first sample on, and the pair was certified with no
 * curve. */
static void test_planar_fold(void)
{
    const char *d = getenv("COLIBRI_SHARED");
    char path[1024], tmp[1024];
    snprintf(path, sizeof path, "%s/models/trj5_k1-al-214.stp", d ? d : "../shared");
    snprintf(tmp, sizeof tmp, "%s/colibri_planar_fold_%ld.step",
             getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp", (long)clock());
    cb_topo_body *A = NULL, *B = NULL;
    cb_error err;
    cb_mass_props m;
    cb_status st = cb_step_read(&A, path, &err);
    if (!st)
        st = cb_mass_body(&m, A, 1e-9, NULL, &err);
    if (!st)
        st = cb_step_read(&B, path, &err);
    if (!st) {
        const double axis[3] = {0.5948139459746077, -0.3172518645243878, -0.7386119577490714},
                     shift[3] = {2.013154756365914, -0.06120186343901141, -0.03312875963638283};
        cb_xform r, t, x;
        cb_xform_rotation(&r, m.centroid, axis, 57.19893298142382 * 3.14159265358979323846 / 180);
        cb_xform_translation(&t, shift);
        cb_xform_compose(&x, &t, &r);
        cb_topo_body_transform(B, &x);
        st = cb_step_write(B, tmp, "planar fold", &err);
        cb_topo_body_free(B);
        B = NULL;
        if (!st)
            st = cb_step_read(&B, tmp, &err);
        remove(tmp);
    }
    CHECK(st == CB_OK, "%s: %s", path, err.msg);
    cb_nurbs_surface_t a, b, rest;
    cb_nurbs_surface_init(a);
    cb_nurbs_surface_init(b);
    cb_nurbs_surface_init(rest);
    if (!st)
        st = cb_nurbs_surface_set(a, A->surfaces[A->faces[36].surface].nurbs, &err);
    if (!st)
        st = cb_nurbs_surface_set(b, B->surfaces[B->faces[32].surface].nurbs, &err);
    if (!st)
        st = cb_nurbs_surface_split(rest, a, a, CB_DIR_V, 10, &err);
    if (!st)
        st = cb_nurbs_surface_split(a, rest, a, CB_DIR_V, 12, &err);
    if (!st)
        st = cb_nurbs_surface_split(rest, b, b, CB_DIR_V, 9, &err);
    CHECK(st == CB_OK, "planar fold: nets: %s", err.msg);
    if (!st) {
        cb_ssi_result_t r;
        cb_ssi_result_init(r);
        cb_ssi_surface sa, sb;
        cb_ssi_surface_set_nurbs(&sa, a);
        cb_ssi_surface_set_nurbs(&sb, b);
        cb_ssi_opts o;
        cb_ssi_opts_default(&o);
        o.tol = 1e-4;
        o.chord = 1e-2;
        st = cb_ssi_surfaces(r, &sa, &sb, 36, 32, &o, &err);
        /* The piece inside both: from where the line enters the span (its side v = 10) to
         * where it leaves (u = 1), found as the Newton projections of the whole surfaces'
         * curve onto the span's sides. */
        const double e0[3] = {11.176, -2.28903, -0.0213246}, e1[3] = {11.176, -2.30673, -0.213024};
        double d0 = HUGE_VAL, d1 = HUGE_VAL;
        for (slong c = 0; c < r->n_curves; c++) {
            const cb_ssi_curve *cv = r->curve + c;
            for (int k = 0; k < 2; k++) {
                const double *X = cv->pt[k ? cv->n - 1 : 0].xyz;
                d0 = fmin(d0, hypot(hypot(X[0] - e0[0], X[1] - e0[1]), X[2] - e0[2]));
                d1 = fmin(d1, hypot(hypot(X[0] - e1[0], X[1] - e1[1]), X[2] - e1[2]));
            }
        }
        printf("planar fold: status %d, %ld curves, ends %.2g and %.2g from the piece's\n", st,
               (long)r->n_curves, d0, d1);
        CHECK(st == CB_OK && r->n_failed == 0 && d0 <= 1e-3 && d1 <= 1e-3,
              "planar fold: status %d, %ld refused, %ld curves, ends %g and %g off", st,
              (long)r->n_failed, (long)r->n_curves, d0, d1);
        cb_ssi_result_clear(r);
    }
    cb_nurbs_surface_clear(a);
    cb_nurbs_surface_clear(b);
    cb_nurbs_surface_clear(rest);
    cb_topo_body_free(A);
    cb_topo_body_free(B);
}

/* A bicubic graph pair: P the graph of a random cubic f over [0, 1]^2, Q the graph of f + h
 * parameterised over [-0.13, 1.07] x [-0.05, 1.11] (so no side of one lies on a side of the
 * other), both turned by one rotation of no special angle. The intersection is {h = 0}. */
static void graph_pair(cb_nurbs_surface_t a, cb_nurbs_surface_t b, const double hp[16],
                       unsigned seed)
{
    check_rng rng = {seed};
    double fp[16], qp[16], fb[16], qb[16], P[48], Q[48];
    for (int k = 0; k < 16; k++) {
        fp[k] = check_rng_uniform(&rng, -0.15, 0.15);
        qp[k] = fp[k] + hp[k];
    }
    const double dq[4] = {-0.13, 1.07, -0.05, 1.11};
    cb_power_to_bernstein_2d(fb, fp, 3, 3, 0, 1, 0, 1);
    cb_power_to_bernstein_2d(qb, qp, 3, 3, dq[0], dq[1], dq[2], dq[3]);
    double q[4] = {0.31, -0.52, 0.67, 0.43}, n = 0;
    for (int k = 0; k < 4; k++)
        n += q[k] * q[k];
    for (int k = 0; k < 4; k++)
        q[k] /= sqrt(n);
    double x = q[0], y = q[1], z = q[2], w = q[3];
    double R[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                      {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                      {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            double p[3] = {i / 3.0, j / 3.0, fb[4 * i + j]},
                   r[3] = {dq[0] + (dq[1] - dq[0]) * i / 3.0, dq[2] + (dq[3] - dq[2]) * j / 3.0,
                           qb[4 * i + j]};
            for (int c = 0; c < 3; c++) {
                P[3 * (4 * i + j) + c] = R[c][0] * p[0] + R[c][1] * p[1] + R[c][2] * p[2] + 0.1234;
                Q[3 * (4 * i + j) + c] = R[c][0] * r[0] + R[c][1] * r[1] + R[c][2] * r[2] + 0.1234;
            }
        }
    double kn[8] = {0, 0, 0, 0, 1, 1, 1, 1};
    cb_error err;
    CHECK(cb_nurbs_surface_make(a, 3, 3, kn, 8, kn, 8, P, NULL, 4, 4, &err) == CB_OK &&
              cb_nurbs_surface_make(b, 3, 3, kn, 8, kn, 8, Q, NULL, 4, 4, &err) == CB_OK,
          "graph pair: %s", err.msg);
}

/* The subdivision route where the surfaces are tangent (tolerance-certificates.md sections 2
 * and 5), on bicubic graph pairs in a turned pose: a node of two transversal lines (h = (x -
 * 1/2)(y - 1/2): P and Q tangent where they cross) comes out as four curves sharing one end
 * point exactly; an isolated contact (h = (x - 1/2)^2 + (y - 1/2)^2) as one isolated point;
 * both as regions resolved within the tolerance, every output point within tol of both
 * surfaces. A transversal circle stays certified with no such region; surfaces touching
 * along a line (h = (x - 1/2)^2) give that line, traced along its contact band. */
static void test_tangent_regions(void)
{
    double node[16] = {0}, contact[16] = {0}, circle[16] = {0}, line[16] = {0};
    node[0] = 0.25, node[4] = -0.5, node[1] = -0.5, node[5] = 1;
    contact[0] = 0.5, contact[4] = -1, contact[8] = 1, contact[1] = -1, contact[2] = 1;
    circle[0] = 0.47 * 0.47 + 0.53 * 0.53 - 0.061, circle[4] = -0.94, circle[8] = 1;
    circle[1] = -1.06, circle[2] = 1;
    line[0] = 0.25, line[4] = -1, line[8] = 1;
    const double *h[4] = {node, contact, circle, line};
    const char *names[4] = {"bicubic node", "bicubic contact point", "bicubic circle",
                            "bicubic tangential line"};
    for (int c = 0; c < 4; c++)
        for (unsigned seed = 1; seed <= 3; seed++) {
            cb_nurbs_surface_t a, b;
            cb_nurbs_surface_init(a);
            cb_nurbs_surface_init(b);
            graph_pair(a, b, h[c], seed);
            cb_ssi_opts o;
            cb_ssi_opts_default(&o);
            o.tol = 1e-6;
            o.threads = 1;
            cb_ssi_result_t r;
            run(r, a, b, &o, names[c]);
            if (c == 3) {
                /* One open tangential curve on x = 1/2 (P's u = 1/2: the valley of the
                 * distance, h's double zero), from P's side v = 0 to v = 1, within tolerance:
                 * the curve not certified, its band listed. */
                CHECK(r->status == CB_OK && r->n_failed == 0 && r->n_curves == 1 &&
                          r->n_points == 0,
                      "%s seed %u: %ld failures (%s), %ld curves, %ld points", names[c], seed,
                      (long)r->n_failed, r->n_failed ? r->failed[0].msg : "",
                      (long)r->n_curves, (long)r->n_points);
                if (r->n_curves == 1) {
                    const cb_ssi_curve *cv = r->curve;
                    double off = 0;
                    for (slong k = 0; k < cv->n; k++)
                        off = fmax(off, fabs(cv->pt[k].uv_a[0] - 0.5));
                    double v0 = fmin(cv->pt[0].uv_a[1], cv->pt[cv->n - 1].uv_a[1]),
                           v1 = fmax(cv->pt[0].uv_a[1], cv->pt[cv->n - 1].uv_a[1]);
                    CHECK(!cv->closed && cv->tangential && !cv->certified && off <= 1e-7 &&
                              v0 == 0 && v1 == 1,
                          "%s seed %u: closed %d tangential %d certified %d, u off 1/2 by %g, "
                          "v from %g to %g",
                          names[c], seed, cv->closed, cv->tangential, cv->certified, off, v0, v1);
                }
                int bands = 0;
                for (slong g = 0; g < r->n_regions; g++)
                    bands += r->region[g].kind == CB_SSI_REGION_CONTACT_BAND &&
                             r->region[g].width > 1000 * o.tol;
                CHECK(bands == 1 && r->pairs_within_tolerance == 1,
                      "%s seed %u: %d bands, %ld pairs within tolerance", names[c], seed, bands,
                      (long)r->pairs_within_tolerance);
                CHECK(max_dist(r, a, b) <= o.tol, "%s seed %u: distance %g", names[c], seed,
                      max_dist(r, a, b));
            } else {
                CHECK(r->status == CB_OK && r->n_failed == 0, "%s seed %u: %ld failures: %s",
                      names[c], seed, (long)r->n_failed, r->n_failed ? r->failed[0].msg : "");
                CHECK(max_dist(r, a, b) <= o.tol, "%s seed %u: distance %g", names[c], seed,
                      max_dist(r, a, b));
            }
            if (c == 0 && r->n_curves == 4) {
                /* four curves, each with one end on the shared node */
                const double *e0 = NULL;
                int at = 0;
                for (slong k = 0; k < 4; k++) {
                    const cb_ssi_curve *cv = r->curve + k;
                    for (int e = 0; e < 2; e++) {
                        const double *X = cv->pt[e ? cv->n - 1 : 0].xyz;
                        if (!e0 && cv->closed == 0) {
                            /* the node: the end shared by every curve */
                            for (slong k2 = 0; k2 < 4; k2++)
                                for (int e2 = 0; e2 < 2; e2++) {
                                    const cb_ssi_curve *c2 = r->curve + k2;
                                    const double *Y = c2->pt[e2 ? c2->n - 1 : 0].xyz;
                                    at += !memcmp(X, Y, sizeof(double[3]));
                                }
                            if (at == 4)
                                e0 = X;
                            at = 0;
                        }
                    }
                }
                CHECK(e0 != NULL, "%s seed %u: the four curves share no end point", names[c],
                      seed);
            } else if (c == 0) {
                CHECK(0, "%s seed %u: %ld curves, expected 4", names[c], seed,
                      (long)r->n_curves);
            }
            if (c < 2)
                CHECK(r->regions_within_tol == 1 && r->nodes_within_tol == (c == 0) &&
                          r->width_within_tol <= 1000 * o.tol,
                      "%s seed %u: %ld regions within tol, %ld nodes, width %g", names[c], seed,
                      (long)r->regions_within_tol, (long)r->nodes_within_tol,
                      r->width_within_tol);
            if (c == 2)
                CHECK(r->regions_within_tol == 0, "%s seed %u: %ld regions within tol",
                      names[c], seed, (long)r->regions_within_tol);
            /* Outcomes: the node's and the contact's regions listed (near node or contact
             * band; at the node also the stitching's near nodes of the pieces' round-off ends
             * around it), the pair within tolerance, the curves through the node not
             * certified; the circle certified throughout. */
            if (c < 2) {
                int kinds = 0, uncertified = 0;
                for (slong g = 0; g < r->n_regions; g++)
                    kinds += r->region[g].kind == CB_SSI_REGION_NEAR_NODE ||
                             r->region[g].kind == CB_SSI_REGION_CONTACT_BAND;
                for (slong k = 0; k < r->n_curves; k++)
                    uncertified += !r->curve[k].certified;
                for (slong k = 0; k < r->n_points; k++)
                    uncertified += !r->point[k].certified;
                CHECK(kinds >= 1 && kinds == r->n_regions && r->pairs_within_tolerance == 1 &&
                          r->pairs_certified == 0 &&
                          uncertified == (c == 0 ? (int)r->n_curves : (int)r->n_points),
                      "%s seed %u: %ld regions (%d tangent), %ld within tolerance, %ld "
                      "certified, %d not certified",
                      names[c], seed, (long)r->n_regions, kinds,
                      (long)r->pairs_within_tolerance, (long)r->pairs_certified, uncertified);
            }
            if (c == 2)
                check_certified(r, names[c]);
            if (c == 1)
                CHECK(r->n_curves == 0 && r->n_points == 1, "%s seed %u: %ld curves, %ld points",
                      names[c], seed, (long)r->n_curves, (long)r->n_points);
            if (c == 2)
                CHECK(r->n_curves == 1 && r->curve[0].closed && r->n_points == 0,
                      "%s seed %u: %ld curves, %ld points", names[c], seed, (long)r->n_curves,
                      (long)r->n_points);
            cb_ssi_result_clear(r);
            cb_nurbs_surface_clear(a);
            cb_nurbs_surface_clear(b);
        }
}

/* An analytic cylinder against a B-spline whose phi would have degree 2 x 7 = 14, above
 * max_phi_degree: the cylinder is written as its rational B-spline and the subdivision route
 * takes the pair (it was refused outright). The B-spline is the graph z = g(x) over [0,1]^2
 * with g a random polynomial of degree 7 (a (7, 1) Bezier patch with x = u, y = v), so the
 * curve is the cylinder's circle lifted onto the graph: every point within tol of both, one
 * closed certified curve round the whole circle, parameters on the cylinder its own. */
static void test_analytic_high_degree(void)
{
    check_rng rng = {29};
    double ku[16], kv[4] = {0, 0, 1, 1}, pts[3 * 16];
    for (int k = 0; k < 16; k++)
        ku[k] = k < 8 ? 0 : 1;
    for (int i = 0; i < 8; i++) {
        double z = check_rng_uniform(&rng, -0.2, 0.2);
        for (int j = 0; j < 2; j++) {
            pts[3 * (2 * i + j)] = i / 7.0;
            pts[3 * (2 * i + j) + 1] = j;
            pts[3 * (2 * i + j) + 2] = z;
        }
    }
    cb_error err;
    cb_nurbs_surface_t g;
    cb_nurbs_surface_init(g);
    CHECK(cb_nurbs_surface_make(g, 7, 1, ku, 16, kv, 4, pts, NULL, 8, 2, &err) == CB_OK,
          "graph: %s", err.msg);
    const double c[3] = {0.47, 0.52, 0}, axis[3] = {0, 0, 1}, R = 0.31;
    cb_frame f;
    cb_analytic_surface cyl;
    CHECK(cb_frame_make(&f, c, axis, NULL, &err) == CB_OK &&
              cb_analytic_cylinder(&cyl, &f, R, &err) == CB_OK,
          "cylinder: %s", err.msg);
    const double range[4] = {0, 2 * CB_SSI_PI, -1, 1};
    cb_ssi_surface A, B;
    cb_ssi_surface_set_analytic(&A, &cyl, range);
    cb_ssi_surface_set_nurbs(&B, g);
    cb_ssi_opts o;
    cb_ssi_opts_default(&o);
    o.tol = 1e-7;
    o.chord = 1e-4;
    o.threads = 1;
    cb_ssi_result_t r;
    cb_ssi_result_init(r);
    cb_status st = cb_ssi_surfaces(r, &A, &B, -1, -1, &o, &err);
    double dev = 0, udev = 0;
    int closed = r->n_curves == 1 && r->curve[0].closed;
    for (slong k = 0; k < r->n_curves; k++)
        for (slong i = 0; i < r->curve[k].n; i++) {
            const cb_ssi_point *p = r->curve[k].pt + i;
            double gz[3], cz[3];
            cb_nurbs_surface_eval(gz, g, p->xyz[0], p->xyz[1]);
            cb_analytic_eval(cz, &cyl, p->uv_a[0], p->uv_a[1]);
            dev = fmax(dev, fmax(fabs(hypot(p->xyz[0] - c[0], p->xyz[1] - c[1]) - R),
                                 fabs(p->xyz[2] - gz[2])));
            udev = fmax(udev, hypot(hypot(cz[0] - p->xyz[0], cz[1] - p->xyz[1]),
                                    cz[2] - p->xyz[2]));
        }
    CHECK(st == CB_OK && r->n_failed == 0 && closed && r->curve[0].certified &&
              r->pairs_subdivided > 0 && dev <= o.tol && udev <= o.tol,
          "cylinder x degree 7 graph: status %d, %ld refused (%s), %ld curves (closed %d), %ld "
          "pairs subdivided, deviation %.3g, on the cylinder at its parameters %.3g",
          (int)st, (long)r->n_failed, r->n_failed ? r->failed[0].msg : "-", (long)r->n_curves,
          closed, (long)r->pairs_subdivided, dev, udev);
    cb_ssi_result_clear(r);
    cb_nurbs_surface_clear(g);
}

int main(int argc, char **argv)
{
    if (argc > 1 && !strcmp(argv[1], "fallback")) {
        test_fallback();
        return check_report("test_ssi_spline");
    }
    test_enclosure();
    test_analytic_high_degree();
    test_paraboloid_plane();
    test_cylinders();
    test_small_loop();
    test_rational();
    test_touch_exact();
    test_shared_side();
    test_example2_pair();
    test_coincident();
    test_tangent_regions();
    test_hummingbird();
    test_fallback();
    test_planar_fold();
    return check_report("test_ssi_spline");
}
