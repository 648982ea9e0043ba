/* test_ssi_trace.c — the SSI driver (ssi/ssi.h) on surface pairs with known intersections:
 * analytic surfaces against bicubic B-spline graphs z = f(x, y) whose control nets are exact
 * (x = u, y = v by linear precision), so the intersection curves are known in closed form. */
#include <math.h>
#include <stdlib.h>

#include "check.h"
#include "ssi/ssi.h"

/* Bernstein coefficients (degree deg, 2 or 3) of a u^2 + b u + c on [0, 1]. Degree 2 keeps
 * dyadic data dyadic, so the surface is exactly the graph of the quadratic. */
static void quad_bern(double *out, int deg, double a, double b, double c)
{
    const double u1[2][4] = {{0, 0.5, 1, 0}, {0, 1.0 / 3, 2.0 / 3, 1}};
    const double u2[2][4] = {{0, 0, 1, 0}, {0, 0, 1.0 / 3, 1}};
    for (int i = 0; i <= deg; i++)
        out[i] = a * u2[deg - 2][i] + b * u1[deg - 2][i] + c;
}

/* Bezier patch of degree (deg, deg) over [0,1]^2 with x = u, y = v, z = fu(u) + fv(v), fu and
 * fv the quadratics (au, bu, cu), (av, bv, cv); with split, the knot 0.5 inserted in each
 * direction (4 Bezier patches). */
static void graph_patch(cb_nurbs_surface_t s, const double qu[3], const double qv[3], int split,
                        int deg)
{
    double bu[4], bv[4], u1[4], pts[48], knots[8];
    int n = deg + 1;
    quad_bern(bu, deg, qu[0], qu[1], qu[2]);
    quad_bern(bv, deg, qv[0], qv[1], qv[2]);
    quad_bern(u1, deg, 0, 1, 0);
    for (int k = 0; k < n; k++) {
        knots[k] = 0;
        knots[n + k] = 1;
    }
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            pts[3 * (n * i + j)] = u1[i];
            pts[3 * (n * i + j) + 1] = u1[j];
            pts[3 * (n * i + j) + 2] = bu[i] + bv[j];
        }
    cb_error err;
    cb_nurbs_surface_make(s, deg, deg, knots, 2 * n, knots, 2 * n, pts, NULL, n, n, &err);
    if (split) {
        cb_nurbs_surface_insert_knot(s, s, CB_DIR_U, 0.5, 1, &err);
        cb_nurbs_surface_insert_knot(s, s, CB_DIR_V, 0.5, 1, &err);
    }
}

static void frame_at(cb_frame *f, double x, double y, double z, const double *axis,
                     const double *ref)
{
    const double o[3] = {x, y, z}, zax[3] = {0, 0, 1};
    cb_error err;
    cb_frame_make(f, o, axis ? axis : zax, ref, &err);
}

static double dist_to(const cb_ssi_surface *S, const cb_ssi_point *p, int a)
{
    double q[3];
    const double *uv = a ? p->uv_a : p->uv_b;
    if (S->kind == CB_SSI_ANALYTIC)
        cb_analytic_eval(q, &S->analytic, uv[0], uv[1]);
    else
        cb_nurbs_surface_eval(q, S->nurbs, uv[0], uv[1]);
    return sqrt((q[0] - p->xyz[0]) * (q[0] - p->xyz[0]) + (q[1] - p->xyz[1]) * (q[1] - p->xyz[1]) +
                (q[2] - p->xyz[2]) * (q[2] - p->xyz[2]));
}

/* Largest distance of any output point to A and B, at its own parameters. */
static double max_dist(const cb_ssi_result_t r, const cb_ssi_surface *A, const cb_ssi_surface *B)
{
    double m = 0;
    for (slong c = 0; c < r->n_curves; c++)
        for (slong i = 0; i < r->curve[c].n; i++) {
            m = fmax(m, dist_to(A, r->curve[c].pt + i, 1));
            m = fmax(m, dist_to(B, r->curve[c].pt + i, 0));
        }
    for (slong q = 0; q < r->n_points; q++) {
        m = fmax(m, dist_to(A, &r->point[q].p, 1));
        m = fmax(m, dist_to(B, &r->point[q].p, 0));
    }
    return m;
}

static slong total_points(const cb_ssi_result_t r)
{
    slong n = 0;
    for (slong c = 0; c < r->n_curves; c++)
        n += r->curve[c].n;
    return n;
}

/* Runs A x B; prints the figures the report quotes. */
static cb_status run(cb_ssi_result_t r, const cb_ssi_surface *A, const cb_ssi_surface *B,
                     int threads, const char *name)
{
    cb_ssi_opts o;
    cb_ssi_opts_default(&o);
    o.threads = threads;
    cb_error err;
    cb_error_clear(&err);
    cb_ssi_result_init(r);
    cb_status st = cb_ssi_surfaces(r, A, B, -1, -1, &o, &err);
    CHECK(st == CB_OK, "%s: %s", name, err.msg);
    CHECK(r->status == CB_OK, "%s: %ld pairs not certified: %s", name, (long)r->n_failed,
          r->n_failed ? r->failed[0].msg : "");
    printf("%-28s curves %ld points %ld polyline pts %ld pairs %ld culled %ld empty %ld "
           "certified %ld failed %ld maxdist %.2e tol %.1e\n",
           name, (long)r->n_curves, (long)r->n_points, (long)total_points(r),
           (long)r->pairs_total, (long)r->pairs_culled, (long)r->pairs_empty,
           (long)r->pairs_certified, (long)r->n_failed, max_dist(r, A, B), r->tol);
    CHECK(max_dist(r, A, B) <= r->tol, "%s: max distance %g > tol %g", name, max_dist(r, A, B),
          r->tol);
    /* Outcomes: every curve, point and pair certified; nothing within tolerance. */
    int uncertified = 0;
    for (slong c = 0; c < r->n_curves; c++)
        uncertified += !r->curve[c].certified;
    for (slong q = 0; q < r->n_points; q++)
        uncertified += !r->point[q].certified;
    CHECK(uncertified == 0 && r->pairs_within_tolerance == 0 && r->n_regions == 0 &&
              r->pairs_certified + r->pairs_culled == r->pairs_total,
          "%s: %d curves or points not certified, %ld pairs within tolerance, %ld regions", name,
          uncertified, (long)r->pairs_within_tolerance, (long)r->n_regions);
    return st;
}

/* Every curve point is at distance rad from (cx, cy) in the xy-plane. */
static double radius_error(const cb_ssi_result_t r, double cx, double cy, double rad)
{
    double m = 0;
    for (slong c = 0; c < r->n_curves; c++)
        for (slong i = 0; i < r->curve[c].n; i++) {
            const double *x = r->curve[c].pt[i].xyz;
            m = fmax(m, fabs(hypot(x[0] - cx, x[1] - cy) - rad));
        }
    return m;
}

static const double PARA_U[3] = {1, -1, 0.25}, PARA_V[3] = {1, -1, 0.25};
static const double INF_RANGE[4] = {-HUGE_VAL, HUGE_VAL, -HUGE_VAL, HUGE_VAL};

static void plane_at(cb_ssi_surface *S, double z)
{
    cb_frame f;
    cb_analytic_surface a;
    cb_error err;
    frame_at(&f, 0, 0, z, NULL, NULL);
    cb_analytic_plane(&a, &f, &err);
    cb_ssi_surface_set_analytic(S, &a, INF_RANGE);
}

/* Plane z = 0.3 across the paraboloid z = (x-.5)^2 + (y-.5)^2 on one patch: the circle of
 * radius sqrt(0.3) leaves the unit square near the edge midpoints, leaving 4 corner arcs. */
static void test_plane_patch(void)
{
    cb_nurbs_surface_t s;
    cb_nurbs_surface_init(s);
    graph_patch(s, PARA_U, PARA_V, 0, 3);
    cb_ssi_surface A, B;
    plane_at(&A, 0.3);
    cb_ssi_surface_set_nurbs(&B, s);
    cb_ssi_result_t r;
    run(r, &A, &B, 1, "plane x patch (4 arcs)");
    CHECK(r->n_curves == 4 && r->n_points == 0, "curves %ld points %ld", (long)r->n_curves,
          (long)r->n_points);
    for (slong c = 0; c < r->n_curves; c++)
        CHECK(!r->curve[c].closed && !r->curve[c].tangential, "curve %ld flags", (long)c);
    CHECK(radius_error(r, 0.5, 0.5, sqrt(0.3)) < 1e-6, "radius error %g",
          radius_error(r, 0.5, 0.5, sqrt(0.3)));
    cb_ssi_result_clear(r);
    cb_nurbs_surface_clear(s);
}

/* Sphere centre (0.5, 0.5, 1), R^2 = 0.09 + 0.91^2 meets the paraboloid where z = 0.09 (a
 * circle of radius 0.3) and z = 0.91 (radius 0.954, outside the patch). Four patches: the
 * circle crosses all of them and must come out as one closed curve. */
static void test_sphere_patches(void)
{
    cb_nurbs_surface_t s;
    cb_nurbs_surface_init(s);
    graph_patch(s, PARA_U, PARA_V, 1, 3);
    cb_frame f;
    cb_analytic_surface a;
    cb_error err;
    frame_at(&f, 0.5, 0.5, 1, NULL, NULL);
    cb_analytic_sphere(&a, &f, sqrt(0.09 + 0.91 * 0.91), &err);
    const double rng[4] = {0, 2 * CB_SSI_PI, -CB_SSI_PI / 2, CB_SSI_PI / 2};
    cb_ssi_surface A, B;
    cb_ssi_surface_set_analytic(&A, &a, rng);
    cb_ssi_surface_set_nurbs(&B, s);
    cb_ssi_result_t r1, r2;
    run(r1, &A, &B, 1, "sphere x 4 patches (1 loop)");
    CHECK(r1->n_curves == 1 && r1->n_points == 0, "curves %ld points %ld",
          (long)r1->n_curves, (long)r1->n_points);
    if (r1->n_curves == 1)
        CHECK(r1->curve[0].closed, "not closed");
    CHECK(radius_error(r1, 0.5, 0.5, 0.3) < 1e-6, "radius error %g",
          radius_error(r1, 0.5, 0.5, 0.3));
    /* Same input on 2 threads: the same curves, bit for bit. */
    run(r2, &A, &B, 2, "sphere x 4 patches, 2 thr");
    int same = r1->n_curves == r2->n_curves && r1->n_points == r2->n_points;
    for (slong c = 0; same && c < r1->n_curves; c++) {
        same = r1->curve[c].n == r2->curve[c].n;
        for (slong i = 0; same && i < r1->curve[c].n; i++)
            same = !memcmp(r1->curve[c].pt + i, r2->curve[c].pt + i, sizeof(cb_ssi_point));
    }
    CHECK(same, "1 and 2 threads differ");
    cb_ssi_result_clear(r1);
    cb_ssi_result_clear(r2);
    cb_nurbs_surface_clear(s);
}

/* Plane z = 0.09 on the 4-patch paraboloid: one closed circle stitched across 4 patches. */
static void test_plane_stitched(void)
{
    cb_nurbs_surface_t s;
    cb_nurbs_surface_init(s);
    graph_patch(s, PARA_U, PARA_V, 1, 3);
    cb_ssi_surface A, B;
    plane_at(&A, 0.09);
    cb_ssi_surface_set_nurbs(&B, s);
    cb_ssi_result_t r;
    run(r, &B, &A, 2, "4 patches x plane (1 loop)");
    CHECK(r->n_curves == 1 && r->n_points == 0, "curves %ld points %ld", (long)r->n_curves,
          (long)r->n_points);
    if (r->n_curves == 1)
        CHECK(r->curve[0].closed, "not closed");
    CHECK(radius_error(r, 0.5, 0.5, 0.3) < 1e-6, "radius error %g",
          radius_error(r, 0.5, 0.5, 0.3));
    cb_ssi_result_clear(r);
    cb_nurbs_surface_clear(s);
}

/* The bump z = -(x-.5)^2 - (y-.5)^2 touches the plane z = 0 at (0.5, 0.5, 0) only. */
static void test_tangent_point(void)
{
    const double qu[3] = {-1, 1, -0.25}, qv[3] = {-1, 1, -0.25};
    cb_nurbs_surface_t s;
    cb_nurbs_surface_init(s);
    graph_patch(s, qu, qv, 0, 2);
    cb_ssi_surface A, B;
    plane_at(&A, 0);
    cb_ssi_surface_set_nurbs(&B, s);
    cb_ssi_result_t r;
    run(r, &A, &B, 1, "plane tangent to bump");
    CHECK(r->n_curves == 0 && r->n_points == 1, "curves %ld points %ld", (long)r->n_curves,
          (long)r->n_points);
    if (r->n_points == 1) {
        const double *x = r->point[0].p.xyz;
        CHECK(fabs(x[0] - 0.5) < 1e-6 && fabs(x[1] - 0.5) < 1e-6 && fabs(x[2]) < 1e-6,
              "point (%g %g %g)", x[0], x[1], x[2]);
        CHECK(r->point[0].tangential, "not tangential");
    }
    cb_ssi_result_clear(r);
    cb_nurbs_surface_clear(s);
}

/* z = y^2 touches the plane z = 0 along its boundary curve y = 0. */
static void test_boundary_touch(void)
{
    const double qu[3] = {0, 0, 0}, qv[3] = {1, 0, 0};
    cb_nurbs_surface_t s;
    cb_nurbs_surface_init(s);
    graph_patch(s, qu, qv, 0, 2);
    cb_ssi_surface A, B;
    plane_at(&A, 0);
    cb_ssi_surface_set_nurbs(&B, s);
    cb_ssi_result_t r;
    run(r, &A, &B, 1, "plane along boundary");
    CHECK(r->n_curves == 1 && r->n_points == 0, "curves %ld points %ld", (long)r->n_curves,
          (long)r->n_points);
    if (r->n_curves == 1) {
        const cb_ssi_curve *c = r->curve;
        CHECK(c->tangential && !c->closed, "flags tangential %d closed %d", c->tangential,
              c->closed);
        double y = 0;
        for (slong i = 0; i < c->n; i++)
            y = fmax(y, fabs(c->pt[i].xyz[1]));
        CHECK(y < 1e-9 && fabs(fabs(c->pt[c->n - 1].xyz[0] - c->pt[0].xyz[0]) - 1) < 1e-9,
              "not the side y = 0: |y| <= %g, ends x %g, %g", y, c->pt[0].xyz[0],
              c->pt[c->n - 1].xyz[0]);
    }
    cb_ssi_result_clear(r);
    cb_nurbs_surface_clear(s);
}

/* The cylinder of radius 0.3 about the vertical axis through (0.4375, 0.5625) meets the paraboloid
 * in a curve around the axis, which crosses the cylinder's seam u = 0 (its frame's x direction is
 * the world x axis, and the circle goes all round). */
static void test_cylinder_seam(void)
{
    cb_nurbs_surface_t s;
    cb_nurbs_surface_init(s);
    graph_patch(s, PARA_U, PARA_V, 1, 2);
    cb_frame f;
    cb_analytic_surface a;
    cb_error err;
    const double xref[3] = {1, 0, 0};
    frame_at(&f, 0.4375, 0.5625, -1, NULL, xref);
    cb_analytic_cylinder(&a, &f, 0.3, &err);
    const double rng[4] = {0, 2 * CB_SSI_PI, 0, 3};
    cb_ssi_surface A, B;
    cb_ssi_surface_set_analytic(&A, &a, rng);
    cb_ssi_surface_set_nurbs(&B, s);
    cb_ssi_result_t r;
    run(r, &A, &B, 2, "cylinder seam x 4 patches");
    CHECK(r->n_curves == 1 && r->n_points == 0, "curves %ld points %ld", (long)r->n_curves,
          (long)r->n_points);
    if (r->n_curves == 1) {
        CHECK(r->curve[0].closed, "not closed");
        double umin = 10, umax = -10, zerr;
        for (slong i = 0; i < r->curve[0].n; i++) {
            umin = fmin(umin, r->curve[0].pt[i].uv_a[0]);
            umax = fmax(umax, r->curve[0].pt[i].uv_a[0]);
        }
        CHECK(umin >= 0 && umax < 2 * CB_SSI_PI && umax - umin > 6, "u in [%g, %g]", umin,
              umax);
        zerr = radius_error(r, 0.4375, 0.5625, 0.3);
        CHECK(zerr < 1e-6, "distance to the axis off by %g", zerr);
    }
    cb_ssi_result_clear(r);
    cb_nurbs_surface_clear(s);
}

/* Two circles of radius 0.3 about (0.4, 0.4) and (0.6, 0.5), crossing at two points: the zero
 * set of z = 9 h(u, v) / 2^14, h the product of their equations, a degree-4 graph patch over
 * [0, 1]^2 (9 clears the odd part of the Bernstein denominators, 2^14 brings z to the size of
 * the square: exact data), cut by the plane z = 0.
 * The critical values 0.1, 0.3, 0.7, 0.9 (the circles' folds) are rational, so the helping
 * lines beside them lie a round-off distance away, where doubles see the near-double roots of
 * the other circle's fold as real: the branch's rank must be read where the root count is the
 * edge's (an arc from the helping line at 0.3 to the fold at 0.1 was one chord, 0.28 long,
 * until it was). Checks: four arcs between the two crossing points, every output point on a
 * circle, and every point of both circles within 2e-3 of the polylines (the chord tolerance
 * is 1e-3 of the size). */
static void test_crossing_circles(void)
{
    /* Power coefficients (u^i v^j, i, j <= 2) of (10u - a)^2 + (10v - b)^2 - 9. */
    double c1[3][3] = {{0}}, c2[3][3] = {{0}}, h[5][5] = {{0}};
    const double ab[2][2] = {{4, 4}, {6, 5}};
    for (int k = 0; k < 2; k++) {
        double(*c)[3] = k ? c2 : c1;
        double a = ab[k][0], b = ab[k][1];
        c[0][0] = a * a + b * b - 9;
        c[1][0] = -20 * a;
        c[2][0] = 100;
        c[0][1] = -20 * b;
        c[0][2] = 100;
    }
    for (int i = 0; i <= 2; i++)
        for (int j = 0; j <= 2; j++)
            for (int k = 0; k <= 2; k++)
                for (int l = 0; l <= 2; l++)
                    h[i + k][j + l] += 9 * c1[i][j] * c2[k][l] / 16384;
    /* Bernstein coefficients of degree (4, 4): b_ij = sum C(i,k) C(j,l) / (C(4,k) C(4,l))
     * a_kl; x = u, y = v by linear precision. */
    static const double C4[5] = {1, 4, 6, 4, 1};
    double pts[75], knots[10];
    for (int k = 0; k < 5; k++) {
        knots[k] = 0;
        knots[5 + k] = 1;
    }
    for (int i = 0; i <= 4; i++)
        for (int j = 0; j <= 4; j++) {
            double z = 0;
            for (int k = 0; k <= i; k++)
                for (int l = 0; l <= j; l++) {
                    double cik = 1, cjl = 1;
                    for (int q = 0; q < k; q++)
                        cik = cik * (i - q) / (q + 1);
                    for (int q = 0; q < l; q++)
                        cjl = cjl * (j - q) / (q + 1);
                    z += cik * cjl / (C4[k] * C4[l]) * h[k][l];
                }
            pts[3 * (5 * i + j)] = i / 4.0;
            pts[3 * (5 * i + j) + 1] = j / 4.0;
            pts[3 * (5 * i + j) + 2] = z;
        }
    cb_nurbs_surface_t s;
    cb_nurbs_surface_init(s);
    cb_error err;
    CHECK(cb_nurbs_surface_make(s, 4, 4, knots, 10, knots, 10, pts, NULL, 5, 5, &err) == CB_OK,
          "crossing circles: patch: %s", err.msg);
    cb_ssi_surface A, B;
    plane_at(&A, 0);
    cb_ssi_surface_set_nurbs(&B, s);
    cb_ssi_result_t r;
    run(r, &A, &B, 1, "plane x two crossing circles");
    CHECK(r->n_curves == 4 && r->n_points == 0, "crossing circles: %ld curves, %ld points",
          (long)r->n_curves, (long)r->n_points);
    double on = 0, cover = 0;
    for (slong c = 0; c < r->n_curves; c++)
        for (slong i = 0; i < r->curve[c].n; i++) {
            const double *x = r->curve[c].pt[i].xyz;
            on = fmax(on, fmin(fabs(hypot(x[0] - 0.4, x[1] - 0.4) - 0.3),
                               fabs(hypot(x[0] - 0.6, x[1] - 0.5) - 0.3)));
        }
    for (int k = 0; k < 2; k++)
        for (int q = 0; q < 2000; q++) {
            double a = 2 * 3.14159265358979323846 * q / 2000;
            double X[2] = {ab[k][0] / 10 + 0.3 * cos(a), ab[k][1] / 10 + 0.3 * sin(a)}, d = 1;
            if (X[0] < 0 || X[0] > 1 || X[1] < 0 || X[1] > 1)
                continue;
            for (slong c = 0; c < r->n_curves; c++)
                for (slong i = 1; i < r->curve[c].n; i++) {
                    const double *p = r->curve[c].pt[i - 1].xyz, *e = r->curve[c].pt[i].xyz;
                    double dx = e[0] - p[0], dy = e[1] - p[1], L2 = dx * dx + dy * dy;
                    double t = L2 > 0 ? ((X[0] - p[0]) * dx + (X[1] - p[1]) * dy) / L2 : 0;
                    t = t < 0 ? 0 : t > 1 ? 1 : t;
                    d = fmin(d, hypot(X[0] - p[0] - t * dx, X[1] - p[1] - t * dy));
                }
            cover = fmax(cover, d);
        }
    CHECK(on < 1e-9 && cover < 2e-3,
          "crossing circles: points off the circles by %g, circles off the polylines by %g",
          on, cover);
    printf("two crossing circles: points on the circles to %.1e, circles covered to %.1e\n", on,
           cover);
    cb_ssi_result_clear(r);
    cb_nurbs_surface_clear(s);
}

int main(void)
{
    test_plane_patch();
    test_plane_stitched();
    test_sphere_patches();
    test_tangent_point();
    test_boundary_touch();
    test_cylinder_seam();
    test_crossing_circles();
    return check_report("test_ssi_trace");
}
