/* test_bool_trim.c — the SSI of two bodies restricted to their trimmed faces
 * (cb_bool_ssi_trim): a box with a round hole, whose top face is a square with a hole, against
 * boxes and spheres placed so that the untrimmed surfaces meet where the faces do not. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "boolean/bool.h"
#include "brep/geom.h"
#include "brep/prim.h"
#include "check.h"

static cb_topo_body *box(double x0, double y0, double z0, double x1, double y1, double z1)
{
    const double lo[3] = {x0, y0, z0}, hi[3] = {x1, y1, z1};
    cb_topo_body *b = NULL;
    cb_error err;
    CHECK(cb_prim_box(&b, NULL, lo, hi, 0, 0, &err) == CB_OK, "box: %s", err.msg);
    return b;
}

static cb_topo_body *sphere(double x, double y, double z, double r)
{
    const double c[3] = {x, y, z}, ax[3] = {0, 0, 1};
    cb_frame f;
    cb_topo_body *b = NULL;
    cb_error err;
    CHECK(cb_frame_make(&f, c, ax, NULL, &err) == CB_OK &&
              cb_prim_sphere(&b, &f, r, 0, 0, &err) == CB_OK,
          "sphere: %s", err.msg);
    return b;
}

/* [0, 2]^3 with a hole of radius 0.5 along z through (1, 1). */
static cb_topo_body *holed_box(void)
{
    const double c[3] = {1, 1, -1}, ax[3] = {0, 0, 1};
    cb_frame f;
    cb_topo_body *cyl = NULL, *out = NULL, *b = box(0, 0, 0, 2, 2, 2);
    cb_error err;
    cb_status st = cb_frame_make(&f, c, ax, NULL, &err);
    if (!st)
        st = cb_prim_cylinder(&cyl, &f, 0.5, 4, 0, 0, &err);
    if (!st)
        st = cb_bool_run(&out, NULL, CB_BOOL_DIFFERENCE, b, cyl, NULL, NULL, &err);
    CHECK(st == CB_OK && out, "holed box: %s", err.msg);
    cb_topo_body_free(b);
    cb_topo_body_free(cyl);
    return out;
}

/* The SSI of a and b, before (r0) and after (r) trimming. */
static int intersect(cb_ssi_result_t r0, cb_ssi_result_t r, const cb_topo_body *a,
                     const cb_topo_body *b)
{
    cb_ssi_opts o;
    cb_error err;
    cb_ssi_opts_default(&o);
    o.threads = 1;
    cb_ssi_result_init(r0);
    cb_ssi_result_init(r);
    cb_status st = cb_ssi_bodies(r0, a, b, &o, &err);
    CHECK(st == CB_OK && r0->n_failed == 0, "ssi: %s (%ld failed)", err.msg, (long)r0->n_failed);
    if (st == CB_OK)
        st = cb_ssi_bodies(r, a, b, &o, &err);
    if (st == CB_OK)
        st = cb_bool_ssi_trim(r, a, b, r->tol, &err);
    CHECK(st == CB_OK, "trim: %s", err.msg);
    return st == CB_OK;
}

/* Curves of r lying on the line x = x0, z = z0 (all points within 1e-9): their count, and the
 * y extents of the first two in ylo, yhi, ordered by ylo. */
static int on_line(const cb_ssi_result_t r, double x0, double z0, double ylo[2], double yhi[2])
{
    int n = 0;
    for (slong c = 0; c < r->n_curves; c++) {
        const cb_ssi_curve *cv = r->curve + c;
        double lo = HUGE_VAL, hi = -HUGE_VAL;
        int on = 1;
        for (slong i = 0; i < cv->n && on; i++) {
            on = fabs(cv->pt[i].xyz[0] - x0) < 1e-9 && fabs(cv->pt[i].xyz[2] - z0) < 1e-9;
            lo = fmin(lo, cv->pt[i].xyz[1]);
            hi = fmax(hi, cv->pt[i].xyz[1]);
        }
        if (!on)
            continue;
        if (n < 2) {
            ylo[n] = lo;
            yhi[n] = hi;
        }
        n++;
    }
    if (n >= 2 && ylo[1] < ylo[0]) {
        double t = ylo[0];
        ylo[0] = ylo[1];
        ylo[1] = t;
        t = yhi[0];
        yhi[0] = yhi[1];
        yhi[1] = t;
    }
    return n;
}

/* Points of r outside the closed region lo <= p <= hi minus the open hole, by more than d. */
static int points_outside(const cb_ssi_result_t r, const double lo[3], const double hi[3],
                          double d)
{
    int bad = 0;
    for (slong c = 0; c < r->n_curves; c++)
        for (slong i = 0; i < r->curve[c].n; i++) {
            const double *p = r->curve[c].pt[i].xyz;
            int out = hypot(p[0] - 1, p[1] - 1) < 0.5 - d;
            for (int k = 0; k < 3; k++)
                out |= p[k] < lo[k] - d || p[k] > hi[k] + d;
            bad += out;
        }
    return bad;
}

/* B's face x = 1 crosses A's top face z = 2 along y in [0, 2], but the hole takes y in
 * (0.5, 1.5) out of that face: two segments, ending on the hole's circle. */
static void test_line_across_hole(const cb_topo_body *A)
{
    cb_topo_body *B = box(1, -1, -1, 3, 3, 3);
    cb_ssi_result_t r0, r;
    if (A && B && intersect(r0, r, A, B)) {
        double ylo[2], yhi[2];
        int n0 = on_line(r0, 1, 2, ylo, yhi);
        CHECK(n0 == 1 && fabs(ylo[0]) < 1e-9 && fabs(yhi[0] - 2) < 1e-9,
              "untrimmed: %d curves on the top line, first y in [%g, %g]", n0, ylo[0], yhi[0]);
        int n = on_line(r, 1, 2, ylo, yhi);
        CHECK(n == 2 && fabs(ylo[0]) < 1e-9 && fabs(yhi[0] - 0.5) < 1e-6 &&
                  fabs(ylo[1] - 1.5) < 1e-6 && fabs(yhi[1] - 2) < 1e-9,
              "trimmed: %d curves on the top line, y in [%g, %g] and [%g, %g]", n, ylo[0],
              yhi[0], ylo[1], yhi[1]);
        n = on_line(r, 1, 0, ylo, yhi);
        CHECK(n == 2 && fabs(yhi[0] - 0.5) < 1e-6 && fabs(ylo[1] - 1.5) < 1e-6,
              "trimmed: %d curves on the bottom line", n);
        const double lo[3] = {1, 0, 0}, hi[3] = {2, 2, 2};
        int out0 = points_outside(r0, lo, hi, 1e-6), out = points_outside(r, lo, hi, 1e-6);
        CHECK(out0 > 0 && out == 0,
              "points off both faces: %d untrimmed (expected some), %d trimmed", out0, out);
        /* Every trimmed point stays on both surfaces. */
        CHECK(r->max_dist_a == r0->max_dist_a && r->max_dist_b == r0->max_dist_b,
              "distances %g %g", r->max_dist_a, r->max_dist_b);
    }
    cb_ssi_result_clear(r0);
    cb_ssi_result_clear(r);
    cb_topo_body_free(B);
}

/* The SSI may give a curve as few points as it likes (a closed-form line: points as far apart
 * as it chooses). The top line of test_line_across_hole is replaced by two points: at y =
 * -0.7 (off A's face) and 0.8 (over the hole), its stretch y in [0, 0.5] inside both faces
 * lying between them; at y = 0.2 and 1.9 (both inside), the hole in between. The trim finds
 * the stretches from where the chords cross the faces' loops, not from the points alone. */
static void test_sparse_line(const cb_topo_body *A)
{
    static const struct {
        double y0, y1;
        int n;               /* curves on the top line after trimming */
        double lo[2], hi[2]; /* their y extents */
    } cases[] = {{-0.7, 0.8, 1, {0, 0}, {0.5, 0}}, {0.2, 1.9, 2, {0.2, 1.5}, {0.5, 1.9}}};
    cb_topo_body *B = box(1, -1, -1, 3, 3, 3);
    for (int k = 0; k < 2 && B; k++) {
        cb_ssi_opts o;
        cb_error err;
        cb_ssi_opts_default(&o);
        o.threads = 1;
        cb_ssi_result_t r;
        cb_ssi_result_init(r);
        cb_status st = cb_ssi_bodies(r, A, B, &o, &err);
        CHECK(st == CB_OK, "ssi: %s", err.msg);
        int found = 0;
        for (slong c = 0; c < r->n_curves && !st; c++) {
            cb_ssi_curve *cv = r->curve + c;
            cb_ssi_point a = cv->pt[0], b = cv->pt[cv->n - 1];
            if (!(fabs(a.xyz[0] - 1) < 1e-9 && fabs(a.xyz[2] - 2) < 1e-9 &&
                  fabs(b.xyz[0] - 1) < 1e-9 && fabs(b.xyz[2] - 2) < 1e-9 &&
                  fabs(b.xyz[1] - a.xyz[1]) > 1))
                continue;
            /* planes: the parameters are affine in y along the line */
            double y[2] = {cases[k].y0, cases[k].y1};
            for (int e = 0; e < 2; e++) {
                double f = (y[e] - a.xyz[1]) / (b.xyz[1] - a.xyz[1]);
                cb_ssi_point *q = cv->pt + e;
                for (int j = 0; j < 3; j++)
                    q->xyz[j] = a.xyz[j] + f * (b.xyz[j] - a.xyz[j]);
                for (int j = 0; j < 2; j++) {
                    q->uv_a[j] = a.uv_a[j] + f * (b.uv_a[j] - a.uv_a[j]);
                    q->uv_b[j] = a.uv_b[j] + f * (b.uv_b[j] - a.uv_b[j]);
                }
            }
            cv->n = 2;
            found++;
        }
        CHECK(found == 1, "case %d: %d top lines in the SSI (expected 1)", k, found);
        if (!st && (st = cb_bool_ssi_trim(r, A, B, r->tol, &err)))
            CHECK(0, "trim: %s", err.msg);
        if (!st) {
            double ylo[2] = {NAN, NAN}, yhi[2] = {NAN, NAN};
            int n = on_line(r, 1, 2, ylo, yhi), good = n == cases[k].n;
            for (int j = 0; j < n && j < 2 && good; j++)
                good = fabs(ylo[j] - cases[k].lo[j]) < 1e-6 && fabs(yhi[j] - cases[k].hi[j]) < 1e-6;
            CHECK(good, "case %d (points at y %g, %g): %d curves on the top line (expected %d), "
                        "y in [%g, %g] and [%g, %g]",
                  k, cases[k].y0, cases[k].y1, n, cases[k].n, ylo[0], yhi[0], ylo[1], yhi[1]);
        }
        cb_ssi_result_clear(r);
    }
    cb_topo_body_free(B);
}

/* B's bottom face z = 1 cuts the hole's cylinder in a whole circle, which crosses the
 * cylinder face's seam: it stays one closed curve; and the four sides of A in segments. */
static void test_circle_across_seam(const cb_topo_body *A)
{
    cb_topo_body *B = box(-1, -1, 1, 3, 3, 5);
    cb_ssi_result_t r0, r;
    if (A && B && intersect(r0, r, A, B)) {
        int closed = 0, on_circle = 0;
        for (slong c = 0; c < r->n_curves; c++) {
            const cb_ssi_curve *cv = r->curve + c;
            closed += cv->closed;
            int round = 1;
            for (slong i = 0; i < cv->n; i++)
                round &= fabs(hypot(cv->pt[i].xyz[0] - 1, cv->pt[i].xyz[1] - 1) - 0.5) < 1e-6 &&
                         fabs(cv->pt[i].xyz[2] - 1) < 1e-9;
            on_circle += round;
            if (cv->closed)
                CHECK(round && cv->n > 8 &&
                          !memcmp(cv->pt[0].xyz, cv->pt[cv->n - 1].xyz, sizeof cv->pt[0].xyz),
                      "closed curve of %ld points off the circle or not closed", (long)cv->n);
        }
        CHECK(r->n_curves == 5 && closed == 1 && on_circle == 1,
              "%ld curves (expected 5), %d closed and %d on the circle (expected 1)",
              (long)r->n_curves, closed, on_circle);
    }
    cb_ssi_result_clear(r0);
    cb_ssi_result_clear(r);
    cb_topo_body_free(B);
}

/* A sphere resting on the top plane touches it at one point: dropped over the hole, kept on
 * the face. */
static void test_touching_points(const cb_topo_body *A)
{
    static const struct {
        double x, y;
        int kept;
    } cases[] = {{1, 1, 0}, {0.25, 0.25, 1}};
    for (int k = 0; k < 2; k++) {
        cb_topo_body *B = sphere(cases[k].x, cases[k].y, 2.5, 0.5);
        cb_ssi_result_t r0, r;
        if (A && B && intersect(r0, r, A, B)) {
            CHECK(r0->n_points == 1 && r->n_points == cases[k].kept && r->n_curves == 0,
                  "sphere over (%g, %g): %ld points untrimmed, %ld trimmed (expected %d), %ld "
                  "curves",
                  cases[k].x, cases[k].y, (long)r0->n_points, (long)r->n_points, cases[k].kept,
                  (long)r->n_curves);
            if (r->n_points == 1)
                CHECK(fabs(r->point[0].p.xyz[0] - cases[k].x) < 1e-6 &&
                          fabs(r->point[0].p.xyz[2] - 2) < 1e-6,
                      "point at (%g, %g, %g)", r->point[0].p.xyz[0], r->point[0].p.xyz[1],
                      r->point[0].p.xyz[2]);
        }
        cb_ssi_result_clear(r0);
        cb_ssi_result_clear(r);
        cb_topo_body_free(B);
    }
}

/* A coedge without a pcurve: the face cannot be prepared, an error names it and r is
 * untouched; a tolerance that is not positive is refused. */
static void test_bad_input(const cb_topo_body *A)
{
    cb_topo_body *B = box(1, -1, -1, 3, 3, 3);
    cb_ssi_result_t r0, r;
    cb_error err;
    if (B && intersect(r0, r, A, B)) {
        slong n = r0->n_curves;
        B->coedges[3].pcurve = -1;
        cb_status st = cb_bool_ssi_trim(r0, A, B, r0->tol, &err);
        CHECK(st == CB_ERR_INVALID && r0->n_curves == n && strstr(err.msg, "pcurve"),
              "coedge without pcurve: %s: %s", cb_status_name(st), err.msg);
        st = cb_bool_ssi_trim(r, A, A, -1, &err);
        CHECK(st == CB_ERR_INVALID, "negative tolerance: %s", cb_status_name(st));
    }
    cb_ssi_result_clear(r0);
    cb_ssi_result_clear(r);
    cb_topo_body_free(B);
}

/* The B-spline quarter of a sphere: the NURBS unit sphere cut by the box x, y >= 0.2, so
 * that its face lies within one knot span in u (a quarter turn). strip: every coedge's pcurve
 * dropped, which makes the SSI take the whole surface (cb_ssi_bodies restricts a B-spline face
 * to the part of its surface its pcurves reach). */
static cb_topo_body *sphere_part(int strip)
{
    const double c[3] = {0, 0, 0}, ax[3] = {0, 0, 1}, lo[3] = {0.2, 0.2, -2},
                 hi[3] = {2, 2, 2};
    cb_frame f;
    cb_topo_body *s = NULL, *bx = NULL, *out = NULL;
    cb_error err;
    cb_status st = cb_frame_make(&f, c, ax, NULL, &err);
    if (!st)
        st = cb_prim_sphere(&s, &f, 1, 1, 0, &err);
    if (!st)
        st = cb_prim_box(&bx, NULL, lo, hi, 0, 0, &err);
    if (!st)
        st = cb_bool_run(&out, NULL, CB_BOOL_INTERSECTION, s, bx, NULL, NULL, &err);
    CHECK(st == CB_OK && out, "sphere part: %s", err.msg);
    cb_topo_body_free(s);
    cb_topo_body_free(bx);
    for (int k = 0; strip && out && k < out->n_coedges; k++)
        out->coedges[k].pcurve = -1;
    return out;
}

/* The SSI of a B-spline face restricted to the part of its surface its loops reach, against
 * the whole surface, both trimmed to the faces: a sphere meeting the surface only in a span the
 * face does not reach gives a curve on the whole surface and none on the restricted one
 * (nothing after trimming either way); one meeting the face gives one closed curve either
 * way, the same points. */
static void test_restricted_spans(void)
{
    cb_topo_body *A = sphere_part(0), *W = sphere_part(1);
    if (!A || !W) {
        cb_topo_body_free(A);
        cb_topo_body_free(W);
        return;
    }
    const double far[3] = {-0.7, -0.6, 0.1}, near[3] = {0.65, 0.6, 0.1};
    for (int k = 0; k < 2; k++) {
        cb_topo_body *B = sphere(k ? near[0] : far[0], k ? near[1] : far[1],
                                 k ? near[2] : far[2], 0.3);
        cb_ssi_result_t r0, r, w0, w;
        cb_ssi_opts o;
        cb_error err;
        cb_ssi_opts_default(&o);
        o.threads = 1;
        cb_ssi_result_init(w0);
        cb_ssi_result_init(w);
        int ok = B && intersect(r0, r, A, B);
        cb_status st = ok ? cb_ssi_bodies(w0, W, B, &o, &err) : CB_ERR_INVALID;
        if (st == CB_OK)
            st = cb_ssi_bodies(w, W, B, &o, &err);
        if (st == CB_OK) /* trimmed to A's loops: W is A without its pcurves */
            st = cb_bool_ssi_trim(w, A, B, w->tol, &err);
        CHECK(st == CB_OK, "whole surface: %s", err.msg);
        if (ok && st == CB_OK) {
            if (!k)
                CHECK(w0->n_curves > r0->n_curves && r->n_curves == 0 && w->n_curves == 0,
                      "far sphere: %ld curves on the whole surface, %ld on the restricted "
                      "one (untrimmed), %ld and %ld trimmed", (long)w0->n_curves,
                      (long)r0->n_curves, (long)w->n_curves, (long)r->n_curves);
            else
                CHECK(r->n_curves == 1 && w->n_curves == 1 && r->curve[0].closed &&
                          w->curve[0].closed,
                      "near sphere: %ld curves restricted, %ld whole (one closed wanted)",
                      (long)r->n_curves, (long)w->n_curves);
            if (k && r->n_curves == 1 && w->n_curves == 1) {
                /* every point of one curve within the tolerance of the other's polyline */
                double dmax = 0;
                for (int s = 0; s < 2; s++) {
                    const cb_ssi_curve *p = s ? w->curve : r->curve, *q = s ? r->curve : w->curve;
                    for (slong i = 0; i < p->n; i++) {
                        double best = HUGE_VAL, l;
                        for (slong j = 0; j + 1 < q->n; j++)
                            best = fmin(best, cb_seg3_nearest(&l, q->pt[j].xyz,
                                                              q->pt[j + 1].xyz, p->pt[i].xyz));
                        dmax = fmax(dmax, best);
                    }
                }
                /* the polylines' chords (sagitta 1e-3 of the size) bound how far apart their
                 * points may lie */
                CHECK(dmax <= 2e-3, "near sphere: the curves lie %g apart", dmax);
            }
        }
        cb_ssi_result_clear(r0);
        cb_ssi_result_clear(r);
        cb_ssi_result_clear(w0);
        cb_ssi_result_clear(w);
        cb_topo_body_free(B);
    }
    cb_topo_body_free(A);
    cb_topo_body_free(W);
}

int main(void)
{
    cb_topo_body *A = holed_box();
    test_line_across_hole(A);
    test_sparse_line(A);
    test_circle_across_seam(A);
    test_touching_points(A);
    if (A)
        test_bad_input(A);
    cb_topo_body_free(A);
    test_restricted_spans();
    return check_report("test_bool_trim");
}
