/* test_ssi_contract.c — the SSI's outcomes (ssi/ssi.h, ssi/ssi_tol.h): coincidence only by
 * proof, never by samples; curve ends joined by the certified graphs, never by distance; every
 * result certified, resolved within tolerance (with its region), or refused.
 *
 * Each case is one a sampled or distance-based rule gets wrong: a patch whose 5 x 5 grid of
 * points lies on the plane while it bulges by about 1 between them (five crossing lines, not a
 * coincidence), two transversal lines 4 tol apart (two curves, not one), a patch within 0.4 tol
 * of a plane but not on it (a coincidence within tolerance, not an exact one), a patch on a
 * plane exactly, and the same for bicubic patches in the subdivision route. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "ssi/ssi.h"

#define PI 3.14159265358979323846

/* Bernstein coefficients b[0..d] of the polynomial with power coefficients a[0..d] on [0, 1]:
 * b_i = sum_{k<=i} C(i, k) / C(d, k) a_k. */
static void to_bernstein(double *b, const double *a, int d)
{
    for (int i = 0; i <= d; i++) {
        double s = 0;
        for (int k = 0; k <= i; k++) {
            double cik = 1, cdk = 1;
            for (int j = 0; j < k; j++) {
                cik = cik * (i - j) / (j + 1);
                cdk = cdk * (d - j) / (j + 1);
            }
            s += cik / cdk * a[k];
        }
        b[i] = s;
    }
}

/* The Bezier patch x = u, y = v, z = f(u) over [0, 1]^2, f of degree d (power coefficients
 * a[0..d], d >= 1), degree 1 in v. x = u in degree d: control x_i = i / d. */
static void graph_u(cb_nurbs_surface_t s, const double *a, int d)
{
    double bz[16], pts[3 * 32], ku[32], kv[4] = {0, 0, 1, 1};
    to_bernstein(bz, a, d);
    for (int i = 0; i <= d; i++)
        for (int j = 0; j < 2; j++) {
            double *p = pts + 3 * (2 * i + j);
            p[0] = (double)i / d;
            p[1] = j;
            p[2] = bz[i];
        }
    for (int k = 0; k <= d; k++) {
        ku[k] = 0;
        ku[d + 1 + k] = 1;
    }
    cb_error err;
    CHECK(cb_nurbs_surface_make(s, d, 1, ku, 2 * d + 2, kv, 4, pts, NULL, d + 1, 2, &err) ==
              CB_OK,
          "graph patch: %s", err.msg);
}

/* The plane z = 0 as an analytic surface over [-1, 2]^2, or as a bilinear B-spline there. */
static void plane_analytic(cb_ssi_surface *S, cb_analytic_surface *a)
{
    static const double range[4] = {-1, 2, -1, 2};
    cb_frame f;
    const double o[3] = {0, 0, 0}, z[3] = {0, 0, 1}, x[3] = {1, 0, 0};
    cb_error err;
    CHECK(cb_frame_make(&f, o, z, x, &err) == CB_OK, "frame: %s", err.msg);
    CHECK(cb_analytic_plane(a, &f, &err) == CB_OK, "plane: %s", err.msg);
    cb_ssi_surface_set_analytic(S, a, range);
}

static void plane_nurbs(cb_nurbs_surface_t s, double z)
{
    const double pts[12] = {-1, -1, z, -1, 2, z, 2, -1, z, 2, 2, z};
    const double k[4] = {0, 0, 1, 1};
    cb_error err;
    CHECK(cb_nurbs_surface_make(s, 1, 1, k, 4, k, 4, pts, NULL, 2, 2, &err) == CB_OK,
          "plane patch: %s", err.msg);
}

static void run(cb_ssi_result_t r, const cb_ssi_surface *A, const cb_ssi_surface *B, double tol,
                const char *name)
{
    cb_ssi_opts o;
    cb_ssi_opts_default(&o);
    o.tol = tol;
    o.spline_max_subpairs = 2000;
    /* The routes' own proofs are under test: the B-spline planes are not to take the closed
     * forms (whose coincidences are tolerance comparisons of the fitted analytic surfaces). */
    o.recognise = 0;
    o.chord = 1e-3;
    cb_error err;
    cb_error_clear(&err);
    cb_ssi_result_init(r);
    CHECK(cb_ssi_surfaces(r, A, B, -1, -1, &o, &err) == CB_OK, "%s: %s", name, err.msg);
}

/* Every curve certified, nothing within tolerance or refused, no region. */
static void check_certified(const cb_ssi_result_t r, const char *name)
{
    int all = 1;
    for (slong c = 0; c < r->n_curves; c++)
        all &= r->curve[c].certified;
    for (slong q = 0; q < r->n_points; q++)
        all &= r->point[q].certified;
    CHECK(all && r->pairs_within_tolerance == 0 && r->n_failed == 0 && r->n_regions == 0 &&
              r->status == CB_OK,
          "%s: curves certified %d, pairs within tolerance %ld, refused %ld, regions %ld (%s)",
          name, all, (long)r->pairs_within_tolerance, (long)r->n_failed, (long)r->n_regions,
          r->n_failed ? r->failed[0].msg : "");
}

/* ---------------------------------------------------------------- five lines --------------- */

/* z = c u (u - 1/4)(u - 1/2)(u - 3/4)(u - 1): zero on the grid lines u = i / 4 of a 5 x 5
 * sample, bulging by up to 1.05 (c = 300) between them. The plane z = 0 crosses it along the
 * five lines x = 0, 1/4, 1/2, 3/4, 1. */
static void test_wavy(void)
{
    const double c = 300;
    /* u (u - 1/4)(u - 1/2)(u - 3/4)(u - 1) = u^5 - 5/2 u^4 + 35/16 u^3 - 25/32 u^2 + 3/32 u. */
    const double a[6] = {0, c * 3.0 / 32, -c * 25.0 / 32, c * 35.0 / 16, -c * 5.0 / 2, c};
    cb_nurbs_surface_t q, pn;
    cb_nurbs_surface_init(q);
    cb_nurbs_surface_init(pn);
    graph_u(q, a, 5);
    plane_nurbs(pn, 0);
    double bulge = 0;
    for (int k = 0; k <= 1000; k++) {
        double X[3];
        cb_nurbs_surface_eval(X, q, k / 1000.0, 0.5);
        bulge = fmax(bulge, fabs(X[2]));
    }
    CHECK(bulge > 0.9 && bulge < 1.2, "wavy patch: bulge %g", bulge);
    for (int form = 0; form < 2; form++) {
        const char *name = form ? "wavy patch x B-spline plane" : "wavy patch x analytic plane";
        cb_analytic_surface pa;
        cb_ssi_surface P, Q;
        if (form)
            cb_ssi_surface_set_nurbs(&P, pn);
        else
            plane_analytic(&P, &pa);
        cb_ssi_surface_set_nurbs(&Q, q);
        cb_ssi_result_t r;
        run(r, &P, &Q, 1e-6, name);
        CHECK(r->n_coincident == 0 && r->pairs_coincident == 0, "%s: %ld coincidence records",
              name, (long)r->n_coincident);
        CHECK(r->n_curves == 5, "%s: %ld curves, expected the five lines", name,
              (long)r->n_curves);
        /* Each a line x = i / 4 from y = 0 to y = 1, one per i. */
        int seen[5] = {0, 0, 0, 0, 0};
        for (slong k = 0; k < r->n_curves; k++) {
            const cb_ssi_curve *cv = r->curve + k;
            double x0 = cv->pt[0].xyz[0], dx = 0, ylo = HUGE_VAL, yhi = -HUGE_VAL;
            for (slong i = 0; i < cv->n; i++) {
                dx = fmax(dx, fabs(cv->pt[i].xyz[0] - x0));
                ylo = fmin(ylo, cv->pt[i].xyz[1]);
                yhi = fmax(yhi, cv->pt[i].xyz[1]);
            }
            int i = (int)lround(4 * x0);
            CHECK(i >= 0 && i <= 4 && fabs(x0 - i / 4.0) <= 1e-6 && dx <= 1e-6 && ylo <= 1e-6 &&
                      yhi >= 1 - 1e-6,
                  "%s: curve %ld at x %.9g (spread %g), y in [%g, %g]", name, (long)k, x0, dx,
                  ylo, yhi);
            if (i >= 0 && i <= 4)
                seen[i]++;
        }
        CHECK(seen[0] == 1 && seen[1] == 1 && seen[2] == 1 && seen[3] == 1 && seen[4] == 1,
              "%s: lines at x = 0, 1/4, 1/2, 3/4, 1 found %d %d %d %d %d times", name, seen[0],
              seen[1], seen[2], seen[3], seen[4]);
        check_certified(r, name);
        cb_ssi_result_clear(r);
    }
    cb_nurbs_surface_clear(q);
    cb_nurbs_surface_clear(pn);
}

/* ---------------------------------------------------------------- two close lines ---------- */

/* z = k (u - a)(u - b) with b - a = 4 tol, k = 1e4: the plane z = 0 crosses the patch along
 * the lines x = a and x = b, 4 tol apart, transversally (slopes -+0.04). Two curves, certified;
 * a merge of ends within 10 tol made them one. */
static void test_close_lines(void)
{
    const double tol = 1e-6, a = 0.5 - 2 * tol, b = 0.5 + 2 * tol, k = 1e4;
    const double c[3] = {k * a * b, -k * (a + b), k};
    cb_nurbs_surface_t q, pn;
    cb_nurbs_surface_init(q);
    cb_nurbs_surface_init(pn);
    graph_u(q, c, 2);
    plane_nurbs(pn, 0);
    for (int form = 0; form < 2; form++) {
        const char *name = form ? "lines 4 tol apart, B-spline plane"
                                : "lines 4 tol apart, analytic plane";
        cb_analytic_surface pa;
        cb_ssi_surface P, Q;
        if (form)
            cb_ssi_surface_set_nurbs(&P, pn);
        else
            plane_analytic(&P, &pa);
        cb_ssi_surface_set_nurbs(&Q, q);
        cb_ssi_result_t r;
        run(r, &P, &Q, tol, name);
        CHECK(r->n_curves == 2, "%s: %ld curves, expected 2", name, (long)r->n_curves);
        if (r->n_curves == 2) {
            double x0 = r->curve[0].pt[0].xyz[0], x1 = r->curve[1].pt[0].xyz[0];
            double lo = fmin(x0, x1), hi = fmax(x0, x1);
            CHECK(fabs(lo - a) <= 0.1 * tol && fabs(hi - b) <= 0.1 * tol,
                  "%s: lines at x %.12g and %.12g, expected %.12g and %.12g", name, lo, hi, a, b);
        }
        CHECK(r->n_coincident == 0, "%s: %ld coincidence records", name, (long)r->n_coincident);
        check_certified(r, name);
        cb_ssi_result_clear(r);
    }
    cb_nurbs_surface_clear(q);
    cb_nurbs_surface_clear(pn);
}

/* ---------------------------------------------------------------- near and exact ----------- */

/* A patch z = h + g(u) with every point within 0.5 tol of the plane z = 0 but not on it (h =
 * 0.3 tol, g a slope of 0.1 tol): a coincidence within tolerance with its region, not exact;
 * z = 0 exactly: an exact coincidence, certified, no region. */
static void test_near_and_exact(void)
{
    const double tol = 1e-6;
    for (int exact = 0; exact < 2; exact++)
        for (int form = 0; form < 2; form++) {
            char name[96];
            snprintf(name, sizeof name, "patch %s the plane, %s", exact ? "on" : "0.4 tol off",
                     form ? "B-spline plane" : "analytic plane");
            const double c[3] = {exact ? 0 : 0.3 * tol, exact ? 0 : 0.1 * tol, 0};
            cb_nurbs_surface_t q, pn;
            cb_nurbs_surface_init(q);
            cb_nurbs_surface_init(pn);
            graph_u(q, c, 2);
            plane_nurbs(pn, 0);
            cb_analytic_surface pa;
            cb_ssi_surface P, Q;
            if (form)
                cb_ssi_surface_set_nurbs(&P, pn);
            else
                plane_analytic(&P, &pa);
            cb_ssi_surface_set_nurbs(&Q, q);
            cb_ssi_result_t r;
            run(r, &P, &Q, tol, name);
            CHECK(r->n_curves == 0 && r->n_points == 0 && r->n_failed == 0 &&
                      r->n_coincident == 1 && r->pairs_coincident == 1,
                  "%s: %ld curves, %ld points, %ld refused, %ld coincidence records", name,
                  (long)r->n_curves, (long)r->n_points, (long)r->n_failed,
                  (long)r->n_coincident);
            if (r->n_coincident == 1) {
                const cb_ssi_coincident *cr = r->coincident;
                if (exact) {
                    CHECK(cr->exact == 1 && cr->width == 0 && r->pairs_certified == 1 &&
                              r->pairs_within_tolerance == 0 && r->n_regions == 0,
                          "%s: exact %d width %g, pairs certified %ld, within %ld, regions %ld",
                          name, cr->exact, cr->width, (long)r->pairs_certified,
                          (long)r->pairs_within_tolerance, (long)r->n_regions);
                } else {
                    /* The proved bound: at least the true largest distance 0.4 tol, at most
                     * tol. */
                    CHECK(cr->exact == 0 && cr->width >= 0.4 * tol * (1 - 1e-9) &&
                              cr->width <= tol && r->pairs_certified == 0 &&
                              r->pairs_within_tolerance == 1 && r->n_regions == 1,
                          "%s: exact %d width %g, pairs certified %ld, within %ld, regions %ld",
                          name, cr->exact, cr->width, (long)r->pairs_certified,
                          (long)r->pairs_within_tolerance, (long)r->n_regions);
                    if (r->n_regions == 1) {
                        const cb_ssi_region *g = r->region;
                        CHECK(g->kind == CB_SSI_REGION_COINCIDENCE && g->width == cr->width &&
                                  g->box_b[0] == 0 && g->box_b[1] == 1 && g->lo[2] <= 0.3 * tol &&
                                  g->hi[2] >= 0.4 * tol * (1 - 1e-12),
                              "%s: region kind %d width %g, Q box [%g, %g], z [%g, %g]", name,
                              g->kind, g->width, g->box_b[0], g->box_b[1], g->lo[2], g->hi[2]);
                    }
                }
            }
            cb_ssi_result_clear(r);
            cb_nurbs_surface_clear(q);
            cb_nurbs_surface_clear(pn);
        }
}

/* ---------------------------------------------------------------- subdivision route -------- */

/* A bicubic patch P (a non-planar graph) and patches Q on it: Q = P exactly (the same net),
 * Q = P raised by 0.3 tol (within tolerance), and Q = P degree-raised to 5 in u plus the wave
 * of test_wavy (its 5 x 5 grid on P, bulging by about 1): not coincident. Bicubic against
 * bicubic or (5, 3), phi's degree is beyond the algebraic route: these take the subdivision
 * route. */
static void bicubic(cb_nurbs_surface_t s, double lift, int wave)
{
    /* z = f(x, y) with Bernstein coefficients chosen freely (a non-planar cubic graph). */
    static const double zb[4][4] = {{0, 0.2, 0.1, 0.3},
                                    {0.25, -0.1, 0.4, 0.2},
                                    {0.1, 0.5, -0.2, 0.15},
                                    {0.3, 0.1, 0.2, 0}};
    int du = wave ? 5 : 3;
    double pts[3 * 6 * 4], ku[12], kv[8] = {0, 0, 0, 0, 1, 1, 1, 1};
    double wb[6] = {0, 0, 0, 0, 0, 0};
    if (wave) {
        const double c = 300;
        const double a[6] = {0, c * 3.0 / 32, -c * 25.0 / 32, c * 35.0 / 16, -c * 5.0 / 2, c};
        to_bernstein(wb, a, 5);
    }
    for (int j = 0; j < 4; j++) {
        /* Column j of the cubic in u, degree-raised to du: b'_i = sum C(3,k) C(2,i-k) / C(5,i). */
        double col[6];
        for (int i = 0; i <= du; i++) {
            if (du == 3) {
                col[i] = zb[i][j];
                continue;
            }
            double s = 0;
            for (int k = 0; k <= 3; k++) {
                int l = i - k;
                if (l < 0 || l > 2)
                    continue;
                double c3[4] = {1, 3, 3, 1}, c2[3] = {1, 2, 1}, c5[6] = {1, 5, 10, 10, 5, 1};
                s += c3[k] * c2[l] / c5[i] * zb[k][j];
            }
            col[i] = s;
        }
        for (int i = 0; i <= du; i++) {
            double *p = pts + 3 * (4 * i + j);
            p[0] = (double)i / du;
            p[1] = j / 3.0;
            p[2] = col[i] + lift + wb[i];
        }
    }
    for (int k = 0; k <= du; k++) {
        ku[k] = 0;
        ku[du + 1 + k] = 1;
    }
    cb_error err;
    CHECK(cb_nurbs_surface_make(s, du, 3, ku, 2 * du + 2, kv, 8, pts, NULL, du + 1, 4, &err) ==
              CB_OK,
          "bicubic: %s", err.msg);
}

static void test_subdivision(void)
{
    const double tol = 1e-6;
    cb_nurbs_surface_t p, q;
    cb_nurbs_surface_init(p);
    cb_nurbs_surface_init(q);
    bicubic(p, 0, 0);
    cb_ssi_surface P, Q;
    cb_ssi_surface_set_nurbs(&P, p);
    for (int c = 0; c < 3; c++) {
        const char *name = c == 0   ? "bicubic x itself (subdivision route)"
                           : c == 1 ? "bicubic x itself raised 0.3 tol (subdivision route)"
                                    : "bicubic x wavy degree-5 copy (subdivision route)";
        bicubic(q, c == 1 ? 0.3 * tol : 0, c == 2);
        cb_ssi_surface_set_nurbs(&Q, q);
        cb_ssi_result_t r;
        run(r, &P, &Q, tol, name);
        CHECK(r->pairs_subdivided == 1, "%s: %ld pairs subdivided", name,
              (long)r->pairs_subdivided);
        if (c < 2) {
            CHECK(r->n_coincident == 1 && r->n_curves == 0 && r->n_failed == 0,
                  "%s: %ld coincidence records, %ld curves, %ld refused", name,
                  (long)r->n_coincident, (long)r->n_curves, (long)r->n_failed);
            if (r->n_coincident == 1)
                CHECK(c == 0 ? r->coincident[0].exact == 1 && r->pairs_certified == 1 &&
                                   r->n_regions == 0
                             : r->coincident[0].exact == 0 &&
                                   r->coincident[0].width >= 0.3 * tol * (1 - 1e-9) &&
                                   r->coincident[0].width <= tol &&
                                   r->pairs_within_tolerance == 1 && r->n_regions == 1,
                      "%s: exact %d width %g, certified %ld, within %ld, regions %ld", name,
                      r->coincident[0].exact, r->coincident[0].width, (long)r->pairs_certified,
                      (long)r->pairs_within_tolerance, (long)r->n_regions);
        } else {
            /* No coincidence: the subdivision route runs. Q meets P along its own sides u = 0,
             * 1 (the wave vanishes there), where every sub-pair touching them has ambiguous
             * boundary roots, so the route runs out of its budget and refuses the pair with the
             * box of what it could not certify; never a coincidence, never a guess. */
            CHECK(r->n_coincident == 0 && r->pairs_coincident == 0,
                  "%s: %ld coincidence records", name, (long)r->n_coincident);
            CHECK(r->n_failed == 1 && r->failed[0].has_box && r->status != CB_OK,
                  "%s: %ld refused, status %d", name, (long)r->n_failed, r->status);
        }
        cb_ssi_result_clear(r);
    }
    cb_nurbs_surface_clear(p);
    cb_nurbs_surface_clear(q);
}

int main(void)
{
    test_wavy();
    test_close_lines();
    test_near_and_exact();
    test_subdivision();
    return check_report("test_ssi_contract");
}
