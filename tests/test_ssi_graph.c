/* test_ssi_graph.c — whole B-spline surfaces with exactly known intersections: graph pairs
 * (cb_model_graph_pair: P the graph of S f, Q the graph of S (f + h / 2^j), Q parametrised
 * differently, both with interior knots and both moved by one rigid motion), so that the
 * intersection is the designed curve h = 0 over the unit square, lifted to P. One case per
 * topology class of the paper's Fig. 1, a tangent line between boundary curves, a loop of
 * radius 1e-3, and transversal loops across several patches of both surfaces.
 *
 * For each: every patch pair certified; the exact number of curve components (curves joined
 * where they share an end point, bit for bit), closed curves and isolated points; every
 * tangential flag against the truth (a curve is tangential exactly when it lies on a squared
 * factor of h); every output point within tol of both surfaces at its own parameters and on the
 * designed curve; every point of the designed curve within 1e-4 of the output; the same output
 * bit for bit on 1 and 2 threads. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "models/models.h"
#include "ssi/ssi.h"
#include "tests/check.h"

/* ---------------------------------------------------------------- the designed curves ------ */

/* A piece of the zero set of h in the unit square: a circle, a line u = a or v = a, a point. */
typedef enum { CIRCLE, LINE_U, LINE_V, POINT } prim_kind;

typedef struct {
    prim_kind kind;
    double a, b, r; /* circle: centre (a, b), radius r; line: a; point: (a, b) */
    int squared;    /* a double factor of h: the surfaces are tangent along it */
} prim;

#define MAX_PRIMS 5

typedef struct {
    const char *name;
    cb_model_poly h;
    prim truth[MAX_PRIMS];
    int n_truth;
    int components, closed, points; /* curve components, closed curves, isolated points */
    /* 1: curves run along P's patch sides into its corners, where their ends meet at split
     * points of the clipping (P's side parameter held) that no exact data identifies: joined
     * within tolerance (regions of width ~0); 0: every join certified */
    int within;
} graph_case;

/* Distance in the (u, v) square from (u, v) to the primitive. */
static double prim_dist(const prim *p, double u, double v)
{
    switch (p->kind) {
    case CIRCLE:
        return fabs(hypot(u - p->a, v - p->b) - p->r);
    case LINE_U:
        return fabs(u - p->a);
    case LINE_V:
        return fabs(v - p->a);
    default:
        return hypot(u - p->a, v - p->b);
    }
}

/* Nearest primitive to (u, v), its distance in *d. */
static const prim *nearest_prim(const graph_case *c, double u, double v, double *d)
{
    const prim *best = NULL;
    *d = INFINITY;
    for (int k = 0; k < c->n_truth; k++) {
        double e = prim_dist(c->truth + k, u, v);
        if (e < *d) {
            *d = e;
            best = c->truth + k;
        }
    }
    return best;
}

/* ---------------------------------------------------------------- the output --------------- */

static double dist3(const double *a, const double *b)
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2]));
}

static double seg_dist(const double *X, const double *p, const double *q)
{
    double d[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
    double w[3] = {X[0] - p[0], X[1] - p[1], X[2] - p[2]};
    double dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    double t = dd > 0 ? (w[0] * d[0] + w[1] * d[1] + w[2] * d[2]) / dd : 0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    double Y[3] = {p[0] + t * d[0], p[1] + t * d[1], p[2] + t * d[2]};
    return dist3(X, Y);
}

/* Distance from X to the output: curves' polylines and isolated points. */
static double output_dist(const cb_ssi_result_t r, const double X[3])
{
    double m = INFINITY;
    for (slong c = 0; c < r->n_curves; c++) {
        const cb_ssi_curve *cv = r->curve + c;
        for (slong i = 0; i < cv->n; i++)
            m = fmin(m, i + 1 < cv->n ? seg_dist(X, cv->pt[i].xyz, cv->pt[i + 1].xyz)
                                      : dist3(X, cv->pt[i].xyz));
        if (cv->closed && cv->n > 1)
            m = fmin(m, seg_dist(X, cv->pt[cv->n - 1].xyz, cv->pt[0].xyz));
    }
    for (slong k = 0; k < r->n_points; k++)
        m = fmin(m, dist3(X, r->point[k].p.xyz));
    return m;
}

static int find(int *parent, int i)
{
    while (parent[i] != i)
        i = parent[i] = parent[parent[i]];
    return i;
}

static int same_point(const cb_ssi_point *a, const cb_ssi_point *b)
{
    return a->xyz[0] == b->xyz[0] && a->xyz[1] == b->xyz[1] && a->xyz[2] == b->xyz[2];
}

/* Curve components: curves joined where one's end point is another's end point exactly. */
static int components(const cb_ssi_result_t r)
{
    int n = (int)r->n_curves, count = n;
    int *parent = malloc(sizeof(int) * (size_t)(n ? n : 1));
    for (int i = 0; i < n; i++)
        parent[i] = i;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < i; j++) {
            const cb_ssi_curve *a = r->curve + i, *b = r->curve + j;
            if (!a->n || !b->n)
                continue;
            const cb_ssi_point *ea[2] = {a->pt, a->pt + a->n - 1},
                               *eb[2] = {b->pt, b->pt + b->n - 1};
            int meet = 0;
            for (int x = 0; x < 2; x++)
                for (int y = 0; y < 2; y++)
                    meet |= same_point(ea[x], eb[y]);
            int ri = find(parent, i), rj = find(parent, j);
            if (meet && ri != rj) {
                parent[ri] = rj;
                count--;
            }
        }
    free(parent);
    return count;
}

/* The same curves and points, in the same order, bit for bit. */
static int same_output(const cb_ssi_result_t a, const cb_ssi_result_t b)
{
    if (a->n_curves != b->n_curves || a->n_points != b->n_points)
        return 0;
    for (slong k = 0; k < a->n_curves; k++) {
        const cb_ssi_curve *x = a->curve + k, *y = b->curve + k;
        if (x->n != y->n || x->closed != y->closed || x->tangential != y->tangential ||
            memcmp(x->pt, y->pt, (size_t)x->n * sizeof *x->pt))
            return 0;
    }
    for (slong k = 0; k < a->n_points; k++)
        if (memcmp(&a->point[k].p, &b->point[k].p, sizeof a->point[k].p))
            return 0;
    return 1;
}

/* ---------------------------------------------------------------- one case ----------------- */

static void run_case(const graph_case *c)
{
    cb_nurbs_surface_t P, Q;
    cb_nurbs_surface_init(P);
    cb_nurbs_surface_init(Q);
    cb_model_graph g;
    cb_error err;
    cb_status st = cb_model_graph_pair(P, Q, &g, &c->h, &err);
    CHECK(st == CB_OK, "%s: %s", c->name, err.msg);
    if (st != CB_OK)
        return;
    cb_ssi_surface A, B;
    cb_ssi_surface_set_nurbs(&A, P);
    cb_ssi_surface_set_nurbs(&B, Q);
    cb_ssi_opts o;
    cb_ssi_opts_default(&o);
    /* Chords well inside the 1e-4 coverage asked of the polylines (the model is about 1). */
    o.chord = 1e-5;
    cb_ssi_result_t r, r1;
    cb_ssi_result_init(r);
    cb_ssi_result_init(r1);
    o.threads = 2;
    st = cb_ssi_surfaces(r, &A, &B, -1, -1, &o, &err);
    CHECK(st == CB_OK && r->n_failed == 0, "%s: every patch pair certified: %s", c->name,
          err.msg);
    o.threads = 1;
    st = cb_ssi_surfaces(r1, &A, &B, -1, -1, &o, &err);
    CHECK(st == CB_OK && same_output(r, r1), "%s: 1 and 2 threads give different output",
          c->name);
    cb_ssi_result_clear(r1);

    /* Outcomes (ssi/ssi_tol.h): every pair certified, every curve and point too, nothing
     * resolved within tolerance: the graphs and the exact side roots decide every join. */
    int uncertified = 0;
    for (slong k = 0; k < r->n_curves; k++)
        uncertified += !r->curve[k].certified;
    for (slong k = 0; k < r->n_points; k++)
        uncertified += !r->point[k].certified;
    double widest = 0;
    for (slong k = 0; k < r->n_regions; k++)
        widest = fmax(widest, r->region[k].width);
    if (c->within)
        CHECK(r->pairs_within_tolerance > 0 && r->n_regions > 0 && widest <= 1e-12 &&
                  r->pairs_certified + r->pairs_within_tolerance + r->pairs_culled ==
                      r->pairs_total,
              "%s: %ld pairs within tolerance, %ld regions up to %g wide, %ld of %ld pairs "
              "certified (%ld culled)",
              c->name, (long)r->pairs_within_tolerance, (long)r->n_regions, widest,
              (long)r->pairs_certified, (long)r->pairs_total, (long)r->pairs_culled);
    else
        CHECK(uncertified == 0 && r->pairs_within_tolerance == 0 && r->n_regions == 0 &&
                  r->pairs_certified + r->pairs_culled == r->pairs_total,
              "%s: %d curves or points not certified, %ld pairs within tolerance, %ld regions, "
              "%ld of %ld pairs certified (%ld culled)",
              c->name, uncertified, (long)r->pairs_within_tolerance, (long)r->n_regions,
              (long)r->pairs_certified, (long)r->pairs_total, (long)r->pairs_culled);

    int closed = 0;
    for (slong k = 0; k < r->n_curves; k++)
        closed += r->curve[k].closed;
    int comp = components(r);
    CHECK(comp == c->components, "%s: %d curve components, expected %d", c->name, comp,
          c->components);
    CHECK(closed == c->closed, "%s: %d closed curves, expected %d", c->name, closed, c->closed);
    CHECK(r->n_points == c->points, "%s: %ld isolated points, expected %d", c->name,
          (long)r->n_points, c->points);

    /* Each output point: on both surfaces, on the designed curve, with the flag of the factor it
     * lies on. */
    double worst_surf = 0, worst_truth = 0;
    int bad_flag = 0;
    for (slong k = 0; k < r->n_curves; k++) {
        const cb_ssi_curve *cv = r->curve + k;
        for (slong i = 0; i < cv->n; i++) {
            const cb_ssi_point *p = cv->pt + i;
            double Xa[3], Xb[3], d;
            cb_nurbs_surface_eval(Xa, P, p->uv_a[0], p->uv_a[1]);
            cb_nurbs_surface_eval(Xb, Q, p->uv_b[0], p->uv_b[1]);
            worst_surf = fmax(worst_surf, fmax(dist3(Xa, p->xyz), dist3(Xb, p->xyz)));
            nearest_prim(c, p->uv_a[0], p->uv_a[1], &d);
            worst_truth = fmax(worst_truth, d);
        }
        /* The flag belongs to the whole curve: judge it at its middle point, away from nodes
         * where a transversal curve meets a tangential one. */
        if (cv->n) {
            double d;
            const cb_ssi_point *mid = cv->pt + cv->n / 2;
            const prim *pr = nearest_prim(c, mid->uv_a[0], mid->uv_a[1], &d);
            if (pr && pr->squared != cv->tangential) {
                bad_flag++;
                fprintf(stderr, "%s: curve %ld at (%.4f, %.4f): tangential %d\n", c->name,
                        (long)k, mid->uv_a[0], mid->uv_a[1], cv->tangential);
            }
        }
    }
    for (slong k = 0; k < r->n_points; k++) {
        const cb_ssi_isolated *p = r->point + k;
        double Xa[3], Xb[3], d;
        cb_nurbs_surface_eval(Xa, P, p->p.uv_a[0], p->p.uv_a[1]);
        cb_nurbs_surface_eval(Xb, Q, p->p.uv_b[0], p->p.uv_b[1]);
        worst_surf = fmax(worst_surf, fmax(dist3(Xa, p->p.xyz), dist3(Xb, p->p.xyz)));
        const prim *pr = nearest_prim(c, p->p.uv_a[0], p->p.uv_a[1], &d);
        worst_truth = fmax(worst_truth, d);
        /* Two surfaces meet in an isolated point only where they touch. */
        if (!pr || pr->kind != POINT || !p->tangential)
            bad_flag++;
    }
    CHECK(worst_surf <= r->tol, "%s: an output point %.2e from a surface (tol %.1e)", c->name,
          worst_surf, r->tol);
    /* 1e-4 as for the coverage: along a curve of tangential contact the surfaces stay within
     * tol of each other over a band about sqrt(tol) wide, so its points are that far off in
     * parameters while within tol of both surfaces. */
    CHECK(worst_truth <= 1e-4, "%s: an output point %.2e off the designed curve (in u, v)",
          c->name, worst_truth);
    CHECK(bad_flag == 0, "%s: %d tangential flags wrong", c->name, bad_flag);

    /* Coverage: the designed curve, sampled, lifted to P and moved, lies within 1e-4 of the
     * output (the model is about 1 across). */
    double worst_cover = 0;
    for (int k = 0; k < c->n_truth; k++) {
        const prim *pr = c->truth + k;
        int n = pr->kind == POINT ? 1 : 2000;
        for (int i = 0; i < n; i++) {
            double u, v, w = pr->kind == CIRCLE ? (double)i / n : (double)i / (n - 1);
            if (pr->kind == CIRCLE) {
                u = pr->a + pr->r * cos(2 * CB_SSI_PI * w);
                v = pr->b + pr->r * sin(2 * CB_SSI_PI * w);
            } else if (pr->kind == LINE_U) {
                u = pr->a;
                v = w;
            } else if (pr->kind == LINE_V) {
                u = w;
                v = pr->a;
            } else {
                u = pr->a;
                v = pr->b;
            }
            if (u < 0 || u > 1 || v < 0 || v > 1)
                continue;
            double X[3];
            cb_model_graph_point(X, &g, u, v);
            worst_cover = fmax(worst_cover, output_dist(r, X));
        }
    }
    CHECK(worst_cover <= 1e-4, "%s: the designed curve is %.2e from the output", c->name,
          worst_cover);
    printf("%-26s curves %2ld (components %d, closed %d), points %ld, pairs %ld (culled %ld, "
           "subdivided %ld), off surfaces %.1e, off curve %.1e, cover %.1e\n",
           c->name, (long)r->n_curves, comp, closed, (long)r->n_points, (long)r->pairs_total,
           (long)r->pairs_culled, (long)r->pairs_subdivided, worst_surf, worst_truth,
           worst_cover);
    cb_ssi_result_clear(r);
    cb_nurbs_surface_clear(P);
    cb_nurbs_surface_clear(Q);
}

/* Two equal loops side by side whose extremes in y are irrational (radius sqrt(2) / 10) put
 * two folds over one irrational critical value of Q's first parameter, which the topology
 * refuses ("not in generic position"); the graph case "mirrored loops, irrational" passes
 * because the pair is then swept along Q's second parameter. Without that fallback the pairs
 * must be reported not certified, or be the two loops (found by the subdivision route), never
 * anything else passed off as a result. */
static void test_non_generic(void)
{
    cb_model_poly a = cb_model_poly_circle(10, 3, 5, 2), b = cb_model_poly_circle(10, 7, 5, 2);
    cb_model_poly h = cb_model_poly_mul(&a, &b);
    cb_nurbs_surface_t P, Q;
    cb_nurbs_surface_init(P);
    cb_nurbs_surface_init(Q);
    cb_model_graph g;
    cb_error err;
    cb_status st = cb_model_graph_pair(P, Q, &g, &h, &err);
    CHECK(st == CB_OK, "non-generic: %s", err.msg);
    cb_ssi_surface A, B;
    cb_ssi_surface_set_nurbs(&A, P);
    cb_ssi_surface_set_nurbs(&B, Q);
    cb_ssi_opts o;
    cb_ssi_opts_default(&o);
    o.topo_transpose = 0;
    cb_ssi_result_t r;
    cb_ssi_result_init(r);
    st = cb_ssi_surfaces(r, &A, &B, -1, -1, &o, &err);
    int generic_msg = 0, closed = 0;
    for (slong k = 0; k < r->n_failed; k++)
        generic_msg |= strstr(r->failed[k].msg, "generic position") != NULL;
    for (slong k = 0; k < r->n_curves; k++)
        closed += r->curve[k].closed;
    /* The pairs the topology refuses may go on to the subdivision route, whose answer is
     * certified: then it must be the two loops. */
    int refused = r->status != CB_OK && r->n_failed > 0 && generic_msg;
    int two_loops = r->status == CB_OK && r->n_failed == 0 && r->n_curves == 2 && closed == 2 &&
                    r->n_points == 0;
    CHECK(st == CB_OK && (refused || two_loops),
          "non-generic without the transposed sweep: status %d, %ld pairs reported not "
          "certified, %ld curves (%d closed), %ld points", (int)r->status, (long)r->n_failed,
          (long)r->n_curves, closed, (long)r->n_points);
    printf("non-generic without the transposed sweep: %s (%ld pairs subdivided)\n",
           refused ? "refused" : "two loops", (long)r->pairs_subdivided);
    cb_ssi_result_clear(r);
    cb_nurbs_surface_clear(P);
    cb_nurbs_surface_clear(Q);
}

/* ---------------------------------------------------------------- the cases ---------------- */

static cb_model_poly mul(cb_model_poly a, cb_model_poly b)
{
    return cb_model_poly_mul(&a, &b);
}

static cb_model_poly sq(cb_model_poly a)
{
    return cb_model_poly_mul(&a, &a);
}

static cb_model_poly lin(long long a, long long b, long long c)
{
    return cb_model_poly_linear(a, b, c);
}

static cb_model_poly circle(long long a, long long b, long long c, long long r2)
{
    return cb_model_poly_circle(a, b, c, r2);
}

int main(void)
{
    graph_case cases[] = {
        {.name = "Fig.1a crossing loops",
         .h = mul(circle(10, 4, 4, 9), circle(10, 6, 5, 9)),
         .truth = {{CIRCLE, .4, .4, .3, 0}, {CIRCLE, .6, .5, .3, 0}},
         .n_truth = 2,
         .components = 1},
        {.name = "Fig.1b contact + branches",
         .h = mul(circle(4, 2, 2, 0), mul(lin(4, 0, -1), lin(4, 0, -3))),
         .truth = {{POINT, .5, .5, 0, 1}, {LINE_U, .25, 0, 0, 0}, {LINE_U, .75, 0, 0, 0}},
         .n_truth = 3,
         .components = 2,
         .points = 1},
        {.name = "Fig.1c boundary curves",
         .h = mul(mul(lin(1, 0, 0), lin(0, 1, 0)), circle(2, 0, 0, 1)),
         .truth = {{LINE_U, 0, 0, 0, 0}, {LINE_V, 0, 0, 0, 0}, {CIRCLE, 0, 0, .5, 0}},
         .n_truth = 3,
         .components = 1,
         .within = 1},
        {.name = "Fig.1e loops touching",
         .h = mul(circle(10, 3, 5, 4), circle(20, 13, 10, 9)),
         .truth = {{CIRCLE, .3, .5, .2, 0}, {CIRCLE, .65, .5, .15, 0}},
         .n_truth = 2,
         .components = 1},
        /* Mirror images: two folds over one critical value of Q's s, a rational one (7/19 or
         * 12/13 of Q's Bezier patches), handled exactly. */
        {.name = "mirrored loops",
         .h = mul(circle(8, 2, 4, 1), circle(8, 6, 4, 1)),
         .truth = {{CIRCLE, .25, .5, .125, 0}, {CIRCLE, .75, .5, .125, 0}},
         .n_truth = 2,
         .components = 2,
         .closed = 2},
        /* Over an irrational critical value (radius sqrt(2) / 10): refused along Q's first
         * parameter, certified along its second (test_non_generic). */
        {.name = "mirrored loops, irrational",
         .h = mul(circle(10, 3, 5, 2), circle(10, 7, 5, 2)),
         .truth = {{CIRCLE, .3, .5, 0.14142135623730950, 0},
                   {CIRCLE, .7, .5, 0.14142135623730950, 0}},
         .n_truth = 2,
         .components = 2,
         .closed = 2},
        {.name = "mirrored loops touching",
         .h = mul(circle(10, 3, 5, 4), circle(10, 7, 5, 4)),
         .truth = {{CIRCLE, .3, .5, .2, 0}, {CIRCLE, .7, .5, .2, 0}},
         .n_truth = 2,
         .components = 1},
        {.name = "Fig.1f tangential loop",
         .h = sq(circle(4, 2, 2, 1)),
         .truth = {{CIRCLE, .5, .5, .25, 1}},
         .n_truth = 1,
         .components = 1,
         .closed = 1},
        {.name = "Fig.1g three contacts",
         .h = mul(circle(4, 1, 1, 0), mul(circle(4, 2, 3, 0), circle(4, 3, 2, 0))),
         .truth = {{POINT, .25, .25, 0, 1}, {POINT, .5, .75, 0, 1}, {POINT, .75, .5, 0, 1}},
         .n_truth = 3,
         .points = 3},
        {.name = "tangent line, sides",
         .h = mul(mul(mul(lin(1, 0, 0), lin(-1, 0, 1)), mul(lin(0, 1, 0), lin(0, -1, 1))),
                  sq(lin(2, 0, -1))),
         .truth = {{LINE_U, 0, 0, 0, 0},
                   {LINE_U, 1, 0, 0, 0},
                   {LINE_V, 0, 0, 0, 0},
                   {LINE_V, 1, 0, 0, 0},
                   /* on P's interior knot line u = 1/2 and on Q's t = 0 */
                   {LINE_U, .5, 0, 0, 1}},
         .n_truth = 5,
         .components = 1,
         .within = 1},
        {.name = "loop of radius 1e-3",
         .h = circle(1000, 500, 500, 1),
         .truth = {{CIRCLE, .5, .5, 1e-3, 0}},
         .n_truth = 1,
         .components = 1,
         .closed = 1},
        {.name = "three loops, many patches",
         .h = mul(circle(32, 16, 16, 16), mul(circle(32, 6, 22, 16), circle(32, 24, 11, 9))),
         .truth = {{CIRCLE, .5, .5, .125, 0}, {CIRCLE, .1875, .6875, .125, 0},
                   {CIRCLE, .75, .34375, .09375, 0}},
         .n_truth = 3,
         .components = 3,
         .closed = 3},
    };
    for (size_t k = 0; k < sizeof cases / sizeof *cases; k++)
        run_case(cases + k);
    test_non_generic();
    return check_report("test_ssi_graph");
}
