/* Knot insertion, refinement, degree elevation, splitting, Bezier extraction, reversal,
 * transposition and rigid motion of NURBS curves and surfaces, and the Bernstein <-> power
 * conversions: each must leave the geometry unchanged (or change it exactly as documented), on
 * random rational curves and surfaces, and must reject bad arguments without touching the
 * output. */
#include "brep/nurbs.h"
#include "check.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { TRIALS = 200, GRID = 30, MAX_KNOTS = 64, MAX_PTS = 40 };
static const double TOL = 1e-12;

/* ---------------------------------------------------------------- random inputs ------------ */

/* Clamped knots of degree p on a random domain, with up to 4 distinct interior knots, each
 * repeated up to p times, at least 0.06 of the domain apart; returns the point count. */
static int random_knots(double *U, int p, check_rng *r)
{
    double a = check_rng_uniform(r, -3, 3), len = check_rng_uniform(r, 0.5, 4);
    int d = check_rng_int(r, 0, 4), m = 0;
    double gaps[5], total = 0;
    for (int k = 0; k <= d; k++)
        total += gaps[k] = check_rng_uniform(r, 0.3, 1.0);
    for (int k = 0; k <= p; k++)
        U[m++] = a;
    double x = a;
    for (int k = 0; k < d; k++) {
        x += len * gaps[k] / total;
        int mult = check_rng_int(r, 0, 2) == 0 ? check_rng_int(r, 1, p) : 1;
        for (int j = 0; j < mult; j++)
            U[m++] = x;
    }
    for (int k = 0; k <= p; k++)
        U[m++] = a + len;
    return m - p - 1;
}

static void random_points(double *P, double *W, long count, check_rng *r)
{
    for (long i = 0; i < count; i++) {
        for (int k = 0; k < 3; k++)
            P[3 * i + k] = check_rng_uniform(r, -1, 1);
        W[i] = check_rng_uniform(r, 0.5, 2);
    }
}

static void random_curve(cb_nurbs_curve_t c, check_rng *r)
{
    double U[MAX_KNOTS], P[3 * MAX_PTS], W[MAX_PTS];
    int p = check_rng_int(r, 1, 5);
    int n = random_knots(U, p, r);
    random_points(P, W, n, r);
    cb_error err;
    cb_status st = cb_nurbs_curve_make(c, p, U, n + p + 1, P, W, n, &err);
    CHECK(st == CB_OK, "random curve: %s", err.msg);
}

static void random_surface(cb_nurbs_surface_t s, check_rng *r)
{
    static double P[3 * MAX_PTS * MAX_PTS], W[MAX_PTS * MAX_PTS];
    double U[MAX_KNOTS], V[MAX_KNOTS];
    int pu = check_rng_int(r, 1, 5), pv = check_rng_int(r, 1, 5);
    int nu = random_knots(U, pu, r), nv = random_knots(V, pv, r);
    random_points(P, W, (long)nu * nv, r);
    cb_error err;
    cb_status st =
        cb_nurbs_surface_make(s, pu, pv, U, nu + pu + 1, V, nv + pv + 1, P, W, nu, nv, &err);
    CHECK(st == CB_OK, "random surface: %s", err.msg);
}

static int mult_of(const double *U, int nk, double u)
{
    int m = 0;
    for (int k = 0; k < nk; k++)
        m += U[k] == u;
    return m;
}

/* A parameter strictly inside the domain: an existing interior knot one time in three (when
 * its multiplicity is at most max_mult), otherwise a random value. */
static double pick_param(const double *U, int n, int p, int max_mult, check_rng *r)
{
    if (n > p + 1 && check_rng_int(r, 0, 2) == 0) {
        double u = U[check_rng_int(r, p + 1, n - 1)];
        if (mult_of(U, n + p + 1, u) <= max_mult)
            return u;
    }
    double u;
    do
        u = check_rng_uniform(r, U[p], U[n]);
    while (!(u > U[p]));
    return u;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Up to 8 refinement knots, sorted, none raising a multiplicity above p. */
static int random_refinement(double *X, const double *U, int n, int p, check_rng *r)
{
    double cand[8];
    int nc = check_rng_int(r, 1, 8), nx = 0;
    for (int k = 0; k < nc; k++)
        cand[k] = pick_param(U, n, p, p, r);
    qsort(cand, (size_t)nc, sizeof *cand, cmp_double);
    for (int k = 0; k < nc; k++)
        if (mult_of(U, n + p + 1, cand[k]) + mult_of(X, nx, cand[k]) < p)
            X[nx++] = cand[k];
    return nx;
}

/* ---------------------------------------------------------------- comparisons -------------- */

/* Diagonal of the box around the Euclidean control points: the scale of every tolerance. */
static double net_size(const double *cw, long count)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (long i = 0; i < count; i++)
        for (int k = 0; k < 3; k++) {
            double x = cw[4 * i + k] / cw[4 * i + 3];
            lo[k] = fmin(lo[k], x);
            hi[k] = fmax(hi[k], x);
        }
    return cb_vec3_dist(lo, hi);
}

/* Grid point k of n on [a, b], ending exactly at b. */
static double lerp_grid(double a, double b, int k, int n)
{
    return k == n ? b : a + (b - a) * k / n;
}

/* How the parameters of the second object relate to those of the first. */
typedef enum { SAME_PARAMS, REVERSE_U, REVERSE_V, SWAP_UV } param_map;

/* Largest distance between x(c(u)) and d(u), or d(a + b - u) when reversed, over a grid on
 * [a, b], relative to the net of c; x may be NULL for no motion. */
static double curve_dev_map(const cb_nurbs_curve_t c, const cb_nurbs_curve_t d, double a,
                            double b, param_map map, const cb_xform *x)
{
    double worst = 0;
    for (int k = 0; k <= 10 * GRID; k++) {
        double u = lerp_grid(a, b, k, 10 * GRID), p[3], q[3];
        cb_nurbs_curve_eval(p, c, u);
        if (x)
            cb_xform_apply_point(p, x, p);
        cb_nurbs_curve_eval(q, d, map == REVERSE_U ? a + b - u : u);
        worst = fmax(worst, cb_vec3_dist(p, q));
    }
    return worst / net_size(c->cw, c->n);
}

static double curve_dev(const cb_nurbs_curve_t c, const cb_nurbs_curve_t d, double a, double b)
{
    return curve_dev_map(c, d, a, b, SAME_PARAMS, NULL);
}

/* As curve_dev_map for surfaces, on a grid x grid lattice over box. */
static double surface_dev_map(const cb_nurbs_surface_t s, const cb_nurbs_surface_t t,
                              const double box[4], int grid, param_map map, const cb_xform *x)
{
    double worst = 0;
    for (int i = 0; i <= grid; i++)
        for (int j = 0; j <= grid; j++) {
            double u = lerp_grid(box[0], box[1], i, grid), v = lerp_grid(box[2], box[3], j, grid);
            double p[3], q[3];
            cb_nurbs_surface_eval(p, s, u, v);
            if (x)
                cb_xform_apply_point(p, x, p);
            if (map == REVERSE_U)
                u = box[0] + box[1] - u;
            if (map == REVERSE_V)
                v = box[2] + box[3] - v;
            if (map == SWAP_UV)
                cb_nurbs_surface_eval(q, t, v, u);
            else
                cb_nurbs_surface_eval(q, t, u, v);
            worst = fmax(worst, cb_vec3_dist(p, q));
        }
    return worst / net_size(s->cw, (long)s->n_u * s->n_v);
}

static double surface_dev(const cb_nurbs_surface_t s, const cb_nurbs_surface_t t,
                          const double box[4], int grid)
{
    return surface_dev_map(s, t, box, grid, SAME_PARAMS, NULL);
}

/* A rotation about a random axis through a random point, then a random translation. */
static void random_motion(cb_xform *x, check_rng *r)
{
    double axis[3], point[3], shift[3];
    for (int k = 0; k < 3; k++) {
        axis[k] = check_rng_uniform(r, -1, 1);
        point[k] = check_rng_uniform(r, -2, 2);
        shift[k] = check_rng_uniform(r, -5, 5);
    }
    cb_xform rot, move;
    cb_xform_rotation(&rot, point, axis, check_rng_uniform(r, -3.14, 3.14));
    cb_xform_translation(&move, shift);
    cb_xform_compose(x, &move, &rot);
}

static int knots_equal(const double *A, const double *B, int n)
{
    return memcmp(A, B, (size_t)n * sizeof *A) == 0;
}

static int curve_same(const cb_nurbs_curve_t a, const cb_nurbs_curve_t b)
{
    return a->deg == b->deg && a->n == b->n && knots_equal(a->knots, b->knots, a->n + a->deg + 1) &&
           knots_equal(a->cw, b->cw, 4 * a->n);
}

static int surface_same(const cb_nurbs_surface_t a, const cb_nurbs_surface_t b)
{
    return a->deg_u == b->deg_u && a->deg_v == b->deg_v && a->n_u == b->n_u &&
           a->n_v == b->n_v && knots_equal(a->knots_u, b->knots_u, a->n_u + a->deg_u + 1) &&
           knots_equal(a->knots_v, b->knots_v, a->n_v + a->deg_v + 1) &&
           knots_equal(a->cw, b->cw, 4 * a->n_u * a->n_v);
}

/* Sorted union (with repetition) of U and X. */
static int merge_knots(double *out, const double *U, int nu, const double *X, int nx)
{
    memcpy(out, U, (size_t)nu * sizeof *out);
    memcpy(out + nu, X, (size_t)nx * sizeof *out);
    qsort(out, (size_t)(nu + nx), sizeof *out, cmp_double);
    return nu + nx;
}

/* U with every distinct value's multiplicity raised by t. */
static int elevated_knots(double *out, const double *U, int nk, int t)
{
    int m = 0;
    for (int k = 0; k < nk; k++) {
        out[m++] = U[k];
        if (k + 1 == nk || U[k + 1] != U[k])
            for (int j = 0; j < t; j++)
                out[m++] = U[k];
    }
    return m;
}

/* The knots of U below u (right = 0) or above it (right = 1), clamped with p + 1 copies of u. */
static int half_knots(double *out, const double *U, int nk, int p, double u, int right)
{
    int m = 0;
    if (right)
        for (int k = 0; k <= p; k++)
            out[m++] = u;
    for (int k = 0; k < nk; k++)
        if (right ? U[k] > u : U[k] < u)
            out[m++] = U[k];
    if (!right)
        for (int k = 0; k <= p; k++)
            out[m++] = u;
    return m;
}

static int distinct_interior(const double *U, int n, int p)
{
    int d = 0;
    for (int k = p + 1; k < n; k++)
        d += U[k] != U[k - 1];
    return d;
}

static const double *knots_along(const cb_nurbs_surface_t s, cb_dir dir, int *n, int *p)
{
    *n = dir == CB_DIR_U ? s->n_u : s->n_v;
    *p = dir == CB_DIR_U ? s->deg_u : s->deg_v;
    return dir == CB_DIR_U ? s->knots_u : s->knots_v;
}

static void report(const char *what, double worst)
{
    printf("  %-34s max relative deviation %.2e\n", what, worst);
}

/* ---------------------------------------------------------------- curves ------------------- */

/* Knot insertion (single and multiple, into a copy or in place) and refinement must not move
 * the curve, and must give exactly the merged knot vector. */
static void test_curve_insert_refine(check_rng *r)
{
    cb_nurbs_curve_t c, d;
    cb_nurbs_curve_init(c);
    cb_nurbs_curve_init(d);
    cb_error err;
    double worst_ins = 0, worst_ref = 0, X[8], K[MAX_KNOTS + 8];
    for (int trial = 0; trial < TRIALS; trial++) {
        random_curve(c, r);
        int p = c->deg, n = c->n, nk = n + p + 1;
        double a, b;
        cb_nurbs_curve_domain(c, &a, &b);
        double u = pick_param(c->knots, n, p, p - 1, r);
        int times = check_rng_int(r, 1, p - mult_of(c->knots, nk, u));
        cb_status st;
        if (trial % 2) {
            cb_nurbs_curve_set(d, c, &err);
            st = cb_nurbs_curve_insert_knot(d, d, u, times, &err);
        } else
            st = cb_nurbs_curve_insert_knot(d, c, u, times, &err);
        for (int k = 0; k < times; k++)
            X[k] = u;
        merge_knots(K, c->knots, nk, X, times);
        double dev = st ? INFINITY : curve_dev(c, d, a, b);
        worst_ins = fmax(worst_ins, dev);
        CHECK(st == CB_OK && cb_nurbs_curve_validate(d, &err) == CB_OK, "trial %d: %s", trial,
              err.msg);
        CHECK(d->n == n + times && d->deg == p && knots_equal(d->knots, K, nk + times),
              "trial %d: insert %.17g x%d: n %d -> %d, knots differ", trial, u, times, n, d->n);
        CHECK(dev <= TOL, "trial %d: insert %.17g x%d (degree %d): deviation %g", trial, u, times,
              p, dev);

        int nx = random_refinement(X, c->knots, n, p, r);
        st = cb_nurbs_curve_refine_knots(d, c, X, nx, &err);
        merge_knots(K, c->knots, nk, X, nx);
        dev = st ? INFINITY : curve_dev(c, d, a, b);
        worst_ref = fmax(worst_ref, dev);
        CHECK(st == CB_OK && cb_nurbs_curve_validate(d, &err) == CB_OK, "trial %d: %s", trial,
              err.msg);
        CHECK(d->n == n + nx && knots_equal(d->knots, K, nk + nx),
              "trial %d: refine by %d knots: n %d -> %d, knots differ", trial, nx, n, d->n);
        CHECK(dev <= TOL, "trial %d: refine by %d knots (degree %d): deviation %g", trial, nx, p,
              dev);
    }
    report("curve knot insertion", worst_ins);
    report("curve knot refinement", worst_ref);
    cb_nurbs_curve_clear(c);
    cb_nurbs_curve_clear(d);
}

/* Degree elevation 1..3 times must not move the curve; every knot gains `times` copies. */
static void test_curve_elevate(check_rng *r)
{
    cb_nurbs_curve_t c, d;
    cb_nurbs_curve_init(c);
    cb_nurbs_curve_init(d);
    cb_error err;
    double worst = 0, K[4 * MAX_KNOTS];
    for (int trial = 0; trial < TRIALS; trial++) {
        random_curve(c, r);
        int p = c->deg, n = c->n, t = check_rng_int(r, 1, 3);
        double a, b;
        cb_nurbs_curve_domain(c, &a, &b);
        int nk = elevated_knots(K, c->knots, n + p + 1, t);
        int spans = distinct_interior(c->knots, n, p) + 1;
        cb_status st = cb_nurbs_curve_elevate_degree(d, c, t, &err);
        double dev = st ? INFINITY : curve_dev(c, d, a, b);
        worst = fmax(worst, dev);
        CHECK(st == CB_OK && cb_nurbs_curve_validate(d, &err) == CB_OK, "trial %d: %s", trial,
              err.msg);
        CHECK(d->deg == p + t && d->n == n + t * spans && d->n + d->deg + 1 == nk &&
                  knots_equal(d->knots, K, nk),
              "trial %d: degree %d + %d: got degree %d, %d points (expected %d), knots differ",
              trial, p, t, d->deg, d->n, n + t * spans);
        CHECK(dev <= TOL, "trial %d: degree %d + %d, %d spans: deviation %g", trial, p, t, spans,
              dev);
    }
    report("curve degree elevation", worst);

    /* A5.9 as printed takes a wrong knot in its knot removal when the knot before the one
     * removed has low multiplicity and the degree is high; degree 10 with interior
     * multiplicities 1, 3, 1 moved the curve by 10% of its size. */
    double U[] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 2, 2, 2, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4};
    double P[3 * 16], W[16];
    random_points(P, W, 16, r);
    cb_error_clear(&err);
    cb_status st = cb_nurbs_curve_make(c, 10, U, 27, P, W, 16, &err);
    if (!st)
        st = cb_nurbs_curve_elevate_degree(d, c, 1, &err);
    double dev = st ? INFINITY : curve_dev(c, d, 0, 4);
    CHECK(dev <= TOL, "degree 10 + 1, multiplicities 1, 3, 1: deviation %g (%s)", dev, err.msg);
    report("curve degree 10 + 1 (A5.9 erratum)", dev);
    cb_nurbs_curve_clear(c);
    cb_nurbs_curve_clear(d);
}

/* Each half of a split reproduces its part of the curve on its own domain [a, u] or [u, b]. */
static void test_curve_split(check_rng *r)
{
    cb_nurbs_curve_t c, l, h;
    cb_nurbs_curve_init(c);
    cb_nurbs_curve_init(l);
    cb_nurbs_curve_init(h);
    cb_error err;
    double worst = 0, K[MAX_KNOTS];
    for (int trial = 0; trial < TRIALS; trial++) {
        random_curve(c, r);
        int p = c->deg, n = c->n, nk = n + p + 1;
        double a, b, la, lb, ha, hb;
        cb_nurbs_curve_domain(c, &a, &b);
        double u = pick_param(c->knots, n, p, p, r);
        cb_status st = cb_nurbs_curve_split(l, h, c, u, &err);
        CHECK(st == CB_OK && cb_nurbs_curve_validate(l, &err) == CB_OK &&
                  cb_nurbs_curve_validate(h, &err) == CB_OK,
              "trial %d: split at %.17g: %s", trial, u, err.msg);
        if (st)
            continue;
        cb_nurbs_curve_domain(l, &la, &lb);
        cb_nurbs_curve_domain(h, &ha, &hb);
        CHECK(la == a && lb == u && ha == u && hb == b,
              "trial %d: split at %.17g: halves [%g, %g] [%g, %g]", trial, u, la, lb, ha, hb);
        int m = half_knots(K, c->knots, nk, p, u, 0);
        CHECK(l->n + p + 1 == m && knots_equal(l->knots, K, m), "trial %d: left knots", trial);
        m = half_knots(K, c->knots, nk, p, u, 1);
        CHECK(h->n + p + 1 == m && knots_equal(h->knots, K, m), "trial %d: right knots", trial);
        double dev = fmax(curve_dev(c, l, a, u), curve_dev(c, h, u, b));
        worst = fmax(worst, dev);
        CHECK(dev <= TOL, "trial %d: split at %.17g (degree %d): deviation %g", trial, u, p, dev);
        /* In place: the input itself receives the left half. */
        cb_nurbs_curve_set(l, c, &err);
        st = cb_nurbs_curve_split(l, h, l, u, &err);
        dev = st ? INFINITY : curve_dev(c, l, a, u);
        CHECK(dev <= TOL, "trial %d: in-place split: deviation %g", trial, dev);
    }
    report("curve split", worst);
    cb_nurbs_curve_clear(c);
    cb_nurbs_curve_clear(l);
    cb_nurbs_curve_clear(h);
}

/* Bezier segments: one per non-empty span, degree p, p + 1 points, clamped knots on the span,
 * each equal to the curve on its span. */
static void test_curve_bezier(check_rng *r)
{
    cb_nurbs_curve_t c;
    cb_nurbs_curve_init(c);
    cb_error err;
    double worst = 0;
    for (int trial = 0; trial < TRIALS; trial++) {
        random_curve(c, r);
        int p = c->deg;
        cb_nurbs_curve_struct *segs = NULL;
        int ns = -1;
        cb_status st = cb_nurbs_curve_extract_bezier(&segs, &ns, c, &err);
        int expect = distinct_interior(c->knots, c->n, p) + 1;
        CHECK(st == CB_OK && ns == expect, "trial %d: %d segments, expected %d: %s", trial, ns,
              expect, err.msg);
        if (st)
            continue;
        double prev = c->knots[p];
        for (int k = 0; k < ns; k++) {
            cb_nurbs_curve_struct *q = &segs[k];
            double a = q->knots[0], b = q->knots[2 * p + 1];
            int clamped = q->deg == p && q->n == p + 1 && a == prev && b > a;
            for (int j = 0; j <= p; j++)
                clamped &= q->knots[j] == a && q->knots[p + 1 + j] == b;
            CHECK(clamped, "trial %d: segment %d not a clamped Bezier on [%g, %g]", trial, k, a,
                  b);
            double dev = curve_dev(c, q, a, b);
            worst = fmax(worst, dev);
            CHECK(dev <= TOL, "trial %d: segment %d of %d (degree %d): deviation %g", trial, k,
                  ns, p, dev);
            prev = b;
        }
        CHECK(prev == c->knots[c->n], "trial %d: segments end at %g", trial, prev);
        cb_nurbs_curve_array_free(segs, ns);
    }
    report("curve Bezier extraction", worst);
    cb_nurbs_curve_clear(c);
}

/* reverse: out(a + b - u) = c(u) on the same domain, twice = identity up to knot round-off;
 * transform commutes with evaluation and keeps the knots. The reverse deviation is larger than
 * the others because a + b - u itself rounds. */
static void test_curve_reverse_transform(check_rng *r)
{
    cb_nurbs_curve_t c, d;
    cb_nurbs_curve_init(c);
    cb_nurbs_curve_init(d);
    cb_error err;
    double worst_rev = 0, worst_xf = 0;
    for (int trial = 0; trial < TRIALS; trial++) {
        random_curve(c, r);
        double a, b, da, db;
        cb_nurbs_curve_domain(c, &a, &b);
        cb_status st = cb_nurbs_curve_reverse(d, c, &err);
        CHECK(st == CB_OK && cb_nurbs_curve_validate(d, &err) == CB_OK, "trial %d: %s", trial,
              err.msg);
        cb_nurbs_curve_domain(d, &da, &db);
        CHECK(da == a && db == b, "trial %d: reversed domain [%g, %g] != [%g, %g]", trial, da,
              db, a, b);
        double dev = curve_dev_map(c, d, a, b, REVERSE_U, NULL);
        worst_rev = fmax(worst_rev, dev);
        CHECK(dev <= TOL, "trial %d: reversed curve deviates by %g", trial, dev);
        cb_nurbs_curve_reverse(d, d, &err);
        double kdev = 0;
        for (int k = 0; k < c->n + c->deg + 1; k++)
            kdev = fmax(kdev, fabs(d->knots[k] - c->knots[k]) / (b - a));
        CHECK(kdev <= TOL && knots_equal(d->cw, c->cw, 4 * c->n),
              "trial %d: reverse twice: knots move by %g or points differ", trial, kdev);

        cb_xform x;
        random_motion(&x, r);
        cb_nurbs_curve_set(d, c, &err);
        cb_nurbs_curve_transform(d, &x);
        dev = curve_dev_map(c, d, a, b, SAME_PARAMS, &x);
        worst_xf = fmax(worst_xf, dev);
        CHECK(dev <= TOL && knots_equal(d->knots, c->knots, c->n + c->deg + 1),
              "trial %d: transformed curve deviates by %g", trial, dev);
    }
    report("curve reverse", worst_rev);
    report("curve transform", worst_xf);
    cb_nurbs_curve_clear(c);
    cb_nurbs_curve_clear(d);
}

/* ---------------------------------------------------------------- surfaces ----------------- */

/* Checks that d is s with the knots along dir replaced by K (nk values), degree along dir raised
 * to deg, and the other direction untouched. */
static int surface_shape(const cb_nurbs_surface_t d, const cb_nurbs_surface_t s, cb_dir dir,
                         int deg, const double *K, int nk)
{
    int n, p, on, op;
    const double *D = knots_along(d, dir, &n, &p);
    const double *O = knots_along(d, !dir, &on, &op);
    int sn, sp;
    const double *SO = knots_along(s, !dir, &sn, &sp);
    return p == deg && n + p + 1 == nk && knots_equal(D, K, nk) && on == sn && op == sp &&
           knots_equal(O, SO, on + op + 1);
}

/* Surface knot insertion and refinement along either direction leave the surface unchanged. */
static void test_surface_insert_refine(check_rng *r)
{
    cb_nurbs_surface_t s, d;
    cb_nurbs_surface_init(s);
    cb_nurbs_surface_init(d);
    cb_error err;
    double worst_ins = 0, worst_ref = 0, X[8], K[MAX_KNOTS + 8], box[4];
    for (int trial = 0; trial < TRIALS; trial++) {
        random_surface(s, r);
        cb_nurbs_surface_domain(s, box);
        cb_dir dir = (cb_dir)check_rng_int(r, 0, 1);
        int n, p;
        const double *U = knots_along(s, dir, &n, &p);
        double u = pick_param(U, n, p, p - 1, r);
        int times = check_rng_int(r, 1, p - mult_of(U, n + p + 1, u));
        cb_status st;
        if (trial % 2) {
            cb_nurbs_surface_set(d, s, &err);
            st = cb_nurbs_surface_insert_knot(d, d, dir, u, times, &err);
        } else
            st = cb_nurbs_surface_insert_knot(d, s, dir, u, times, &err);
        for (int k = 0; k < times; k++)
            X[k] = u;
        int nk = merge_knots(K, U, n + p + 1, X, times);
        double dev = st ? INFINITY : surface_dev(s, d, box, GRID);
        worst_ins = fmax(worst_ins, dev);
        CHECK(st == CB_OK && cb_nurbs_surface_validate(d, &err) == CB_OK, "trial %d: %s", trial,
              err.msg);
        CHECK(!st && surface_shape(d, s, dir, p, K, nk),
              "trial %d: insert %c = %.17g x%d: wrong counts or knots", trial, "uv"[dir], u,
              times);
        CHECK(dev <= TOL, "trial %d: insert %c = %.17g x%d (degrees %d, %d): deviation %g",
              trial, "uv"[dir], u, times, s->deg_u, s->deg_v, dev);

        int nx = random_refinement(X, U, n, p, r);
        st = cb_nurbs_surface_refine_knots(d, s, dir, X, nx, &err);
        nk = merge_knots(K, U, n + p + 1, X, nx);
        dev = st ? INFINITY : surface_dev(s, d, box, GRID);
        worst_ref = fmax(worst_ref, dev);
        CHECK(st == CB_OK && cb_nurbs_surface_validate(d, &err) == CB_OK, "trial %d: %s", trial,
              err.msg);
        CHECK(!st && surface_shape(d, s, dir, p, K, nk),
              "trial %d: refine %c by %d knots: wrong counts or knots", trial, "uv"[dir], nx);
        CHECK(dev <= TOL, "trial %d: refine %c by %d knots: deviation %g", trial, "uv"[dir], nx,
              dev);
    }
    report("surface knot insertion", worst_ins);
    report("surface knot refinement", worst_ref);
    cb_nurbs_surface_clear(s);
    cb_nurbs_surface_clear(d);
}

static void test_surface_elevate(check_rng *r)
{
    cb_nurbs_surface_t s, d;
    cb_nurbs_surface_init(s);
    cb_nurbs_surface_init(d);
    cb_error err;
    double worst = 0, K[4 * MAX_KNOTS], box[4];
    for (int trial = 0; trial < TRIALS; trial++) {
        random_surface(s, r);
        cb_nurbs_surface_domain(s, box);
        cb_dir dir = (cb_dir)check_rng_int(r, 0, 1);
        int n, p, t = check_rng_int(r, 1, 3);
        const double *U = knots_along(s, dir, &n, &p);
        int nk = elevated_knots(K, U, n + p + 1, t);
        const cb_nurbs_surface_struct *src = s;
        if (trial % 2) {
            cb_nurbs_surface_set(d, s, &err);
            src = d;
        }
        cb_status st = cb_nurbs_surface_elevate_degree(d, src, dir, t, &err);
        double dev = st ? INFINITY : surface_dev(s, d, box, GRID);
        worst = fmax(worst, dev);
        CHECK(st == CB_OK && cb_nurbs_surface_validate(d, &err) == CB_OK, "trial %d: %s", trial,
              err.msg);
        CHECK(!st && surface_shape(d, s, dir, p + t, K, nk),
              "trial %d: elevate %c degree %d + %d: wrong counts or knots", trial, "uv"[dir], p,
              t);
        CHECK(dev <= TOL, "trial %d: elevate %c degree %d + %d: deviation %g", trial, "uv"[dir],
              p, t, dev);
    }
    report("surface degree elevation", worst);
    cb_nurbs_surface_clear(s);
    cb_nurbs_surface_clear(d);
}

static void test_surface_split(check_rng *r)
{
    cb_nurbs_surface_t s, lo, hi;
    cb_nurbs_surface_init(s);
    cb_nurbs_surface_init(lo);
    cb_nurbs_surface_init(hi);
    cb_error err;
    double worst = 0, K[MAX_KNOTS], box[4], lbox[4], hbox[4];
    for (int trial = 0; trial < TRIALS; trial++) {
        random_surface(s, r);
        cb_nurbs_surface_domain(s, box);
        cb_dir dir = (cb_dir)check_rng_int(r, 0, 1);
        int n, p;
        const double *U = knots_along(s, dir, &n, &p);
        double u = pick_param(U, n, p, p, r);
        cb_status st = cb_nurbs_surface_split(lo, hi, s, dir, u, &err);
        CHECK(st == CB_OK && cb_nurbs_surface_validate(lo, &err) == CB_OK &&
                  cb_nurbs_surface_validate(hi, &err) == CB_OK,
              "trial %d: split %c at %.17g: %s", trial, "uv"[dir], u, err.msg);
        if (st)
            continue;
        cb_nurbs_surface_domain(lo, lbox);
        cb_nurbs_surface_domain(hi, hbox);
        double elbox[4], ehbox[4];
        memcpy(elbox, box, sizeof box);
        memcpy(ehbox, box, sizeof box);
        elbox[2 * dir + 1] = u;
        ehbox[2 * dir] = u;
        CHECK(!memcmp(lbox, elbox, sizeof box) && !memcmp(hbox, ehbox, sizeof box),
              "trial %d: split %c at %.17g: wrong half domains", trial, "uv"[dir], u);
        int m = half_knots(K, U, n + p + 1, p, u, 0);
        CHECK(surface_shape(lo, s, dir, p, K, m), "trial %d: low half knots", trial);
        m = half_knots(K, U, n + p + 1, p, u, 1);
        CHECK(surface_shape(hi, s, dir, p, K, m), "trial %d: high half knots", trial);
        double dev = fmax(surface_dev(s, lo, elbox, GRID), surface_dev(s, hi, ehbox, GRID));
        worst = fmax(worst, dev);
        CHECK(dev <= TOL, "trial %d: split %c at %.17g: deviation %g", trial, "uv"[dir], u, dev);
        cb_nurbs_surface_set(hi, s, &err);
        st = cb_nurbs_surface_split(lo, hi, hi, dir, u, &err);
        dev = st ? INFINITY : surface_dev(s, hi, ehbox, GRID);
        CHECK(dev <= TOL, "trial %d: in-place split: deviation %g", trial, dev);
    }
    report("surface split", worst);
    cb_nurbs_surface_clear(s);
    cb_nurbs_surface_clear(lo);
    cb_nurbs_surface_clear(hi);
}

/* Bezier patches tile the domain span by span and each reproduces the surface on its box. */
static void test_surface_bezier(check_rng *r)
{
    cb_nurbs_surface_t s;
    cb_nurbs_surface_init(s);
    cb_error err;
    double worst = 0;
    for (int trial = 0; trial < TRIALS; trial++) {
        random_surface(s, r);
        int pu = s->deg_u, pv = s->deg_v;
        double bu[MAX_KNOTS], bv[MAX_KNOTS];
        int eu = 0, ev = 0;
        bu[0] = s->knots_u[pu];
        bv[0] = s->knots_v[pv];
        for (int k = pu + 1; k <= s->n_u; k++)
            if (s->knots_u[k] != s->knots_u[k - 1])
                bu[++eu] = s->knots_u[k];
        for (int k = pv + 1; k <= s->n_v; k++)
            if (s->knots_v[k] != s->knots_v[k - 1])
                bv[++ev] = s->knots_v[k];
        cb_nurbs_surface_struct *pt = NULL;
        int npu = -1, npv = -1;
        cb_status st = cb_nurbs_surface_extract_bezier(&pt, &npu, &npv, s, &err);
        CHECK(st == CB_OK && npu == eu && npv == ev,
              "trial %d: %d x %d patches, expected %d x %d: %s", trial, npu, npv, eu, ev,
              err.msg);
        if (st || npu != eu || npv != ev) {
            if (!st)
                cb_nurbs_surface_array_free(pt, npu * npv);
            continue;
        }
        for (int i = 0; i < npu; i++)
            for (int j = 0; j < npv; j++) {
                cb_nurbs_surface_struct *q = &pt[i * npv + j];
                int ok = q->deg_u == pu && q->deg_v == pv && q->n_u == pu + 1 && q->n_v == pv + 1;
                for (int k = 0; ok && k <= pu; k++)
                    ok = q->knots_u[k] == bu[i] && q->knots_u[pu + 1 + k] == bu[i + 1];
                for (int k = 0; ok && k <= pv; k++)
                    ok = q->knots_v[k] == bv[j] && q->knots_v[pv + 1 + k] == bv[j + 1];
                CHECK(ok, "trial %d: patch (%d, %d) is not a clamped Bezier patch on its span",
                      trial, i, j);
                if (!ok)
                    continue;
                double box[4] = {bu[i], bu[i + 1], bv[j], bv[j + 1]};
                double dev = surface_dev(s, q, box, 10);
                worst = fmax(worst, dev);
                CHECK(dev <= TOL, "trial %d: patch (%d, %d) of %d x %d: deviation %g", trial, i,
                      j, npu, npv, dev);
            }
        cb_nurbs_surface_array_free(pt, npu * npv);
    }
    report("surface Bezier extraction", worst);
    cb_nurbs_surface_clear(s);
}

/* reverse along either direction (same domain, reversing twice restores the points),
 * transpose (twice is the identity) and rigid motion of surfaces. */
static void test_surface_reverse_transpose_transform(check_rng *r)
{
    cb_nurbs_surface_t s, d;
    cb_nurbs_surface_init(s);
    cb_nurbs_surface_init(d);
    cb_error err;
    double worst_rev = 0, worst_tr = 0, worst_xf = 0, box[4], dbox[4];
    for (int trial = 0; trial < TRIALS; trial++) {
        random_surface(s, r);
        cb_nurbs_surface_domain(s, box);
        cb_dir dir = (cb_dir)check_rng_int(r, 0, 1);
        cb_status st = cb_nurbs_surface_reverse(d, s, dir, &err);
        CHECK(st == CB_OK && cb_nurbs_surface_validate(d, &err) == CB_OK, "trial %d: %s", trial,
              err.msg);
        cb_nurbs_surface_domain(d, dbox);
        CHECK(!memcmp(box, dbox, sizeof box), "trial %d: reverse changed the domain", trial);
        double dev = surface_dev_map(s, d, box, GRID, dir == CB_DIR_U ? REVERSE_U : REVERSE_V,
                                     NULL);
        worst_rev = fmax(worst_rev, dev);
        CHECK(dev <= TOL, "trial %d: reversed along %c: deviation %g", trial, "uv"[dir], dev);
        cb_nurbs_surface_reverse(d, d, dir, &err);
        CHECK(knots_equal(d->cw, s->cw, 4 * s->n_u * s->n_v),
              "trial %d: reversing twice along %c changes the control points", trial, "uv"[dir]);

        st = cb_nurbs_surface_transpose(d, s, &err);
        CHECK(st == CB_OK && d->deg_u == s->deg_v && d->n_u == s->n_v &&
                  knots_equal(d->knots_u, s->knots_v, s->n_v + s->deg_v + 1),
              "trial %d: transpose: wrong shape", trial);
        dev = surface_dev_map(s, d, box, GRID, SWAP_UV, NULL);
        worst_tr = fmax(worst_tr, dev);
        CHECK(dev <= TOL, "trial %d: transpose: deviation %g", trial, dev);
        cb_nurbs_surface_transpose(d, d, &err);
        CHECK(surface_same(d, s), "trial %d: transposing twice is not the identity", trial);

        cb_xform x;
        random_motion(&x, r);
        cb_nurbs_surface_transform(d, &x);
        dev = surface_dev_map(s, d, box, GRID, SAME_PARAMS, &x);
        worst_xf = fmax(worst_xf, dev);
        CHECK(dev <= TOL, "trial %d: transformed surface deviates by %g", trial, dev);
    }
    report("surface reverse", worst_rev);
    report("surface transpose", worst_tr);
    report("surface transform", worst_xf);
    cb_nurbs_surface_clear(s);
    cb_nurbs_surface_clear(d);
}

/* ---------------------------------------------------------------- Bernstein / power -------- */

/* f(t) from Bernstein coefficients on [a, b] by de Casteljau. */
static double bernstein_eval(const double *bern, int deg, double a, double b, double t)
{
    double w[16], s = (t - a) / (b - a);
    memcpy(w, bern, (size_t)(deg + 1) * sizeof *w);
    for (int k = 1; k <= deg; k++)
        for (int i = 0; i + k <= deg; i++)
            w[i] = (1 - s) * w[i] + s * w[i + 1];
    return w[0];
}

/* f(t) from power coefficients by Horner; *scale gets sum |pw[k]| |t|^k, the size of the
 * terms Horner rounds. */
static double power_eval(const double *pw, int deg, double t, double *scale)
{
    double f = 0, g = 0;
    for (int k = deg; k >= 0; k--) {
        f = f * t + pw[k];
        g = g * fabs(t) + fabs(pw[k]);
    }
    *scale = g;
    return f;
}

static double max_abs(const double *x, int n)
{
    double m = 0;
    for (int k = 0; k < n; k++)
        m = fmax(m, fabs(x[k]));
    return m;
}

/* max |x - y| / max |x|. */
static double rel_diff(const double *x, const double *y, int n)
{
    double d = 0;
    for (int k = 0; k < n; k++)
        d = fmax(d, fabs(x[k] - y[k]));
    return d / max_abs(x, n);
}

/* A random interval [a, b] that holds 0 and is at least 0.25 long: there the power basis in t
 * is well conditioned, so 1e-12 is a fair bound for any correct method; far from 0 the power
 * coefficients themselves lose digits, whatever computes them. */
static void random_interval(double *a, double *b, check_rng *r)
{
    *a = -check_rng_uniform(r, 0, 1.5);
    *b = fmax(*a + 0.25, check_rng_uniform(r, 0, 1.5));
}

/* Round trips both ways, agreement of both forms at random points, aliased output, exact known
 * cases, and the same for the tensor versions. */
static void test_bernstein(check_rng *r)
{
    /* The two values at a point agree up to the rounding of the terms each evaluation sums:
     * the Bernstein coefficients (which also bound the error of the conversion) and Horner's. */
    double worst_rt = 0, worst_pt = 0;
    for (int trial = 0; trial < TRIALS; trial++) {
        int deg = check_rng_int(r, 0, 6);
        double a, b;
        random_interval(&a, &b, r);
        double bern[8], pw[8], back[8], alias[8], scale;
        for (int k = 0; k <= deg; k++)
            bern[k] = check_rng_uniform(r, -1, 1);
        cb_bernstein_to_power(pw, bern, deg, a, b);
        cb_power_to_bernstein(back, pw, deg, a, b);
        double rt = rel_diff(bern, back, deg + 1);
        cb_bernstein_to_power(back, back, deg, a, b);
        rt = fmax(rt, rel_diff(pw, back, deg + 1));
        memcpy(alias, bern, sizeof bern);
        cb_bernstein_to_power(alias, alias, deg, a, b);
        int same = !memcmp(alias, pw, (size_t)(deg + 1) * sizeof *pw);
        worst_rt = fmax(worst_rt, rt);
        CHECK(rt <= TOL, "trial %d: degree %d on [%g, %g]: round trip error %g", trial, deg, a, b,
              rt);
        CHECK(same, "trial %d: aliased output differs", trial);
        for (int k = 0; k < 10; k++) {
            double t = check_rng_uniform(r, a, b);
            double fb = bernstein_eval(bern, deg, a, b, t), fp = power_eval(pw, deg, t, &scale);
            double dev = fabs(fb - fp) / (scale + max_abs(bern, deg + 1));
            worst_pt = fmax(worst_pt, dev);
            CHECK(dev <= TOL, "trial %d: degree %d on [%g, %g] at %g: %.17g vs %.17g", trial, deg,
                  a, b, t, fb, fp);
        }
    }
    report("Bernstein <-> power round trip", worst_rt);
    report("Bernstein vs power at points", worst_pt);

    /* t^2 on [0, 1] has Bernstein coefficients (0, 0, 1); on [1, 3] they are (1, 3, 9). */
    double sq[3] = {0, 0, 1}, out[3];
    cb_power_to_bernstein(out, sq, 2, 0, 1);
    CHECK(out[0] == 0 && out[1] == 0 && out[2] == 1, "t^2 on [0, 1]: %g %g %g", out[0], out[1],
          out[2]);
    cb_power_to_bernstein(out, sq, 2, 1, 3);
    CHECK(out[0] == 1 && out[1] == 3 && out[2] == 9, "t^2 on [1, 3]: %g %g %g", out[0], out[1],
          out[2]);
    cb_bernstein_to_power(out, out, 2, 1, 3);
    CHECK(out[0] == 0 && out[1] == 0 && out[2] == 1, "back to t^2: %g %g %g", out[0], out[1],
          out[2]);

    double worst2 = 0;
    for (int trial = 0; trial < TRIALS; trial++) {
        int m = check_rng_int(r, 0, 4), n = check_rng_int(r, 0, 4), cnt = (m + 1) * (n + 1);
        double u0, u1, v0, v1;
        random_interval(&u0, &u1, r);
        random_interval(&v0, &v1, r);
        double bern[25], pw[25], back[25];
        for (int k = 0; k < cnt; k++)
            bern[k] = check_rng_uniform(r, -1, 1);
        cb_bernstein_to_power_2d(pw, bern, m, n, u0, u1, v0, v1);
        cb_power_to_bernstein_2d(back, pw, m, n, u0, u1, v0, v1);
        double rt = rel_diff(bern, back, cnt);
        cb_bernstein_to_power_2d(back, back, m, n, u0, u1, v0, v1);
        rt = fmax(rt, rel_diff(pw, back, cnt));
        memcpy(back, bern, sizeof bern);
        cb_bernstein_to_power_2d(back, back, m, n, u0, u1, v0, v1);
        int same = !memcmp(back, pw, (size_t)cnt * sizeof *pw);
        /* At a random point: de Casteljau along v per row, then along u; power by Horner along
         * v per row, then along u, with the term size sum |p_ij| |u|^i |v|^j. */
        double u = check_rng_uniform(r, u0, u1), v = check_rng_uniform(r, v0, v1);
        double rowb[5], rowp[5], rows[5], scale;
        for (int i = 0; i <= m; i++) {
            rowb[i] = bernstein_eval(bern + i * (n + 1), n, v0, v1, v);
            rowp[i] = power_eval(pw + i * (n + 1), n, v, &rows[i]);
        }
        double fb = bernstein_eval(rowb, m, u0, u1, u), fp = power_eval(rowp, m, u, &scale);
        power_eval(rows, m, fabs(u), &scale);
        double pt = fabs(fb - fp) / (scale + max_abs(bern, cnt));
        worst2 = fmax(worst2, fmax(rt, pt));
        CHECK(rt <= TOL && pt <= TOL && same,
              "trial %d: 2d degree %d x %d: round trip %g, point %g, aliasing %s", trial, m, n, rt,
              pt, same ? "ok" : "differs");
    }
    report("Bernstein <-> power 2d", worst2);
}

/* ---------------------------------------------------------------- bad input ---------------- */

/* Runs call, which reports into e, and checks it is rejected as invalid with a message holding
 * word while `unchanged` (evaluated after the call) holds. */
#define EXPECT_INVALID(call, word, unchanged, what)                                            \
    do {                                                                                       \
        cb_error_clear(&e);                                                                    \
        cb_status st_ = (call);                                                                \
        const char *parts_[] = {word, NULL};                                                   \
        CHECK(st_ == CB_ERR_INVALID && check_msg_has(e.msg, parts_) && (unchanged),            \
              "%s: status %d, message \"%s\" (want \"%s\")", what, (int)st_, e.msg, word);     \
    } while (0)

/* Every invalid argument class is rejected with a message naming it; outputs are untouched. */
static void test_bad_input(check_rng *r)
{
    cb_nurbs_curve_t c, out, keep, out2, keep2, empty;
    cb_nurbs_surface_t s, so, skeep, so2, skeep2, sempty;
    cb_nurbs_curve_struct *cs[] = {c, out, keep, out2, keep2, empty};
    cb_nurbs_surface_struct *ss[] = {s, so, skeep, so2, skeep2, sempty};
    for (int k = 0; k < 6; k++)
        cb_nurbs_curve_init(cs[k]);
    for (int k = 0; k < 6; k++)
        cb_nurbs_surface_init(ss[k]);
    cb_error e;
    double U[] = {0, 0, 0, 1, 1, 2, 3, 3, 3}, P[18], W[6];
    random_points(P, W, 6, r);
    CHECK(cb_nurbs_curve_make(c, 2, U, 9, P, W, 6, &e) == CB_OK, "%s", e.msg);
    random_curve(out, r);
    random_curve(out2, r);
    cb_nurbs_curve_set(keep, out, &e);
    cb_nurbs_curve_set(keep2, out2, &e);
    double nan = NAN;

    EXPECT_INVALID(cb_nurbs_curve_insert_knot(out, c, -0.5, 1, &e), "knot",
                   curve_same(out, keep), "insert below the domain");
    EXPECT_INVALID(cb_nurbs_curve_insert_knot(out, c, 3.5, 1, &e), "domain",
                   curve_same(out, keep), "insert above the domain");
    EXPECT_INVALID(cb_nurbs_curve_insert_knot(out, c, 0, 1, &e), "domain", curve_same(out, keep),
                   "insert at the domain start");
    EXPECT_INVALID(cb_nurbs_curve_insert_knot(out, c, nan, 1, &e), "nan", curve_same(out, keep),
                   "insert NaN");
    EXPECT_INVALID(cb_nurbs_curve_insert_knot(out, c, 0.5, -1, &e), "times",
                   curve_same(out, keep), "insert -1 times");
    EXPECT_INVALID(cb_nurbs_curve_insert_knot(out, c, 0.5, 3, &e), "multiplicity",
                   curve_same(out, keep), "insert beyond the degree");
    EXPECT_INVALID(cb_nurbs_curve_insert_knot(out, c, 1.0, 1, &e), "multiplicity",
                   curve_same(out, keep), "insert at a knot of full multiplicity");

    double unsorted[] = {0.5, 0.25}, outside[] = {0.5, 3.0}, withnan[] = {0.5, NAN};
    double triple[] = {1.5, 1.5, 1.5};
    EXPECT_INVALID(cb_nurbs_curve_refine_knots(out, c, unsorted, 2, &e), "non-decreasing",
                   curve_same(out, keep), "refine by an unsorted vector");
    EXPECT_INVALID(cb_nurbs_curve_refine_knots(out, c, outside, 2, &e), "domain",
                   curve_same(out, keep), "refine outside the domain");
    EXPECT_INVALID(cb_nurbs_curve_refine_knots(out, c, withnan, 2, &e), "nan",
                   curve_same(out, keep), "refine by NaN");
    EXPECT_INVALID(cb_nurbs_curve_refine_knots(out, c, triple, 3, &e), "multiplicity",
                   curve_same(out, keep), "refine beyond the degree");
    EXPECT_INVALID(cb_nurbs_curve_refine_knots(out, c, unsorted, -1, &e), "count",
                   curve_same(out, keep), "refine by a negative count");

    EXPECT_INVALID(cb_nurbs_curve_elevate_degree(out, c, -1, &e), "times", curve_same(out, keep),
                   "elevate -1 times");
    EXPECT_INVALID(cb_nurbs_curve_elevate_degree(out, c, CB_MAX_DEGREE, &e), "degree",
                   curve_same(out, keep), "elevate past the maximum degree");

    EXPECT_INVALID(cb_nurbs_curve_split(out, out2, c, 0.0, &e), "domain",
                   curve_same(out, keep) && curve_same(out2, keep2), "split at the domain start");
    EXPECT_INVALID(cb_nurbs_curve_split(out, out2, c, nan, &e), "split",
                   curve_same(out, keep) && curve_same(out2, keep2), "split at NaN");
    EXPECT_INVALID(cb_nurbs_curve_split(out, out, c, 1.5, &e), "distinct", curve_same(out, keep),
                   "split into one object");
    EXPECT_INVALID(cb_nurbs_curve_reverse(out, empty, &e), "empty", curve_same(out, keep),
                   "reverse an empty curve");

    random_surface(s, r);
    random_surface(so, r);
    random_surface(so2, r);
    cb_nurbs_surface_set(skeep, so, &e);
    cb_nurbs_surface_set(skeep2, so2, &e);
    double box[4];
    cb_nurbs_surface_domain(s, box);
    double umid = 0.5 * (box[0] + box[1]);
    EXPECT_INVALID(cb_nurbs_surface_insert_knot(so, s, CB_DIR_V, box[3] + 1, 1, &e), "v knot",
                   surface_same(so, skeep), "surface insert above the v domain");
    EXPECT_INVALID(cb_nurbs_surface_insert_knot(so, s, CB_DIR_U, umid, s->deg_u + 1, &e),
                   "multiplicity", surface_same(so, skeep), "surface insert beyond the degree");
    EXPECT_INVALID(cb_nurbs_surface_insert_knot(so, s, CB_DIR_U, umid, -2, &e), "times",
                   surface_same(so, skeep), "surface insert -2 times");
    EXPECT_INVALID(cb_nurbs_surface_insert_knot(so, s, (cb_dir)2, umid, 1, &e), "direction",
                   surface_same(so, skeep), "surface insert along direction 2");
    double sx[2] = {0.25 * box[2] + 0.75 * box[3], 0.5 * (box[2] + box[3])};
    EXPECT_INVALID(cb_nurbs_surface_refine_knots(so, s, CB_DIR_V, sx, 2, &e), "non-decreasing",
                   surface_same(so, skeep), "surface refine by an unsorted vector");
    sx[1] = nan;
    EXPECT_INVALID(cb_nurbs_surface_refine_knots(so, s, CB_DIR_V, sx, 2, &e), "nan",
                   surface_same(so, skeep), "surface refine by NaN");
    EXPECT_INVALID(cb_nurbs_surface_elevate_degree(so, s, CB_DIR_V, CB_MAX_DEGREE, &e), "degree",
                   surface_same(so, skeep), "surface elevate past the maximum degree");
    EXPECT_INVALID(cb_nurbs_surface_split(so, so2, s, CB_DIR_U, box[1], &e), "domain",
                   surface_same(so, skeep) && surface_same(so2, skeep2),
                   "surface split at the domain end");
    EXPECT_INVALID(cb_nurbs_surface_split(so, so, s, CB_DIR_U, umid, &e), "distinct",
                   surface_same(so, skeep), "surface split into one object");
    EXPECT_INVALID(cb_nurbs_surface_transpose(so, sempty, &e), "empty", surface_same(so, skeep),
                   "transpose an empty surface");

    for (int k = 0; k < 6; k++)
        cb_nurbs_curve_clear(cs[k]);
    for (int k = 0; k < 6; k++)
        cb_nurbs_surface_clear(ss[k]);
}

int main(void)
{
    check_rng r = {20240611};
    test_curve_insert_refine(&r);
    test_curve_elevate(&r);
    test_curve_split(&r);
    test_curve_bezier(&r);
    test_curve_reverse_transform(&r);
    test_surface_insert_refine(&r);
    test_surface_elevate(&r);
    test_surface_split(&r);
    test_surface_bezier(&r);
    test_surface_reverse_transpose_transform(&r);
    test_bernstein(&r);
    test_bad_input(&r);
    return check_report("nurbs_ops");
}
