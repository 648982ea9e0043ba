/* The SSI topology cases, Colibri beside Open CASCADE: surface pairs whose intersection has a
 * known topology, with the time of cb_ssi_surfaces on 1 and 2 threads (median, min, max of
 * RUNS runs), the number of curve components and isolated points it finds against the true
 * ones, and, when the OCCT comparator (occt_ssi) is given, the same from GeomInt_IntSS (the
 * engine of GeomAPI_IntSS, which also returns its isolated points) on the same two surfaces.
 *
 * The cases (Yang, Jia, Yan, ACM TOG 2023):
 *   - graph pairs of the Fig. 1 classes (cb_model_graph_pair, models.h, the surfaces of
 *     tests/test_ssi_graph.c): P the biquadratic graph of S f over the unit square, Q the graph
 *     of S (f + h / 2^j), parametrised differently, both with an interior knot per direction
 *     and moved by one rigid motion, so that they meet exactly where the designed integer
 *     polynomial h vanishes: crossing loops, an isolated contact beside two branches, boundary
 *     curves, touching loops, mirrored loops apart and touching, a tangential loop, three
 *     isolated contacts, a tangent line between boundary curves, a loop of radius 1e-3, three
 *     loops across patches. Every control point is exact in binary (the tangencies survive
 *     only if nothing is rounded);
 *   - the paper's Example 2 (appendix A): its rational bicubic P over [0, 1]^2 and Q over
 *     [-1, 1] x [0, 2], power coefficients turned into integer homogeneous control points;
 *   - the torus/ellipsoid pairs of its Table 4, analytic for Colibri; for OCCT the torus is a
 *     Geom_ToroidalSurface and the ellipsoid (OCCT has none) its exact rational B-spline.
 *
 * Topology figures: curve components (curves joined where one comes within 100 tol of
 * another: at shared end points, crossings and contacts, which OCCT need not split its curves
 * at) and isolated points (points farther than that from every curve). Verdicts: ok (both
 * counts right), gaps (right only when curves within 1e-3 of the model size are joined: ends
 * that stop short of a node), WRONG, refused (Colibri reported patch pairs it could not
 * certify), fails (an error), - (true topology not established). d(C,O), d(O,C): largest
 * distance, relative to the model size, of one side's curve points from the other's polylines
 * (a branch one side lacks shows there; Colibri's chords may stand 1e-3 of the size off the
 * curve, so d(O,C) up to that is agreement).
 *
 * Memory: the peak resident memory of a process that runs the case once (Colibri: this
 * program as `bench_ssi_cases --peak K`, 2 threads; OCCT: the comparator's process, which
 * times RUNS runs), each started by posix_spawn (bench_spawn.h).
 *
 * Usage: bench_ssi_cases [RUNS [OCCT_SSI [JSON_OUT]]]   (RUNS default 3; "-": no OCCT) */
#define _DEFAULT_SOURCE /* wait4 (bench_spawn.h), fmemopen */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "brep/analytic.h"
#include "bench/bench_spawn.h"
#include "bench/bench_ssi_pair.h"
#include "bench/bench_stats.h"
#include "io/json.h"
#include "models/models.h"
#include "ssi/ssi.h"

/* ---------------------------------------------------------------- cases -------------------- */

typedef struct {
    const char *name, *cls;  /* case and the Fig. 1 class or source */
    int components, points;  /* true topology: curve components, isolated points */
    const char *truth;       /* in words */
    cb_ssi_surface A, B;
    cb_nurbs_surface_t na, nb; /* NURBS sides (owned) */
    /* What OCCT gets: the NURBS sides, or the analytic torus and the ellipsoid's B-spline. */
    int occt_torus_a;
    cb_nurbs_surface_t occt_b;
    int max_phi_degree; /* the SSI's limit for this case; 0: the default */
} ssi_case;

/* Graph pair for h (see the header): returns 0 when the generator refuses h. */
static int graph_pair(ssi_case *c, const cb_model_poly *h)
{
    cb_model_graph g;
    cb_error err;
    if (cb_model_graph_pair(c->na, c->nb, &g, h, &err) != CB_OK) {
        fprintf(stderr, "%s: %s\n", c->name, err.msg);
        return 0;
    }
    cb_ssi_surface_set_nurbs(&c->A, c->na);
    cb_ssi_surface_set_nurbs(&c->B, c->nb);
    return 1;
}

static cb_model_poly mul(cb_model_poly a, cb_model_poly b)
{
    return cb_model_poly_mul(&a, &b);
}

static cb_model_poly lin(long long a, long long b, long long c)
{
    return cb_model_poly_linear(a, b, c);
}

static cb_model_poly circle(long long a, long long b, long long c, long long r2)
{
    return cb_model_poly_circle(a, b, c, r2);
}

/* The paper's Example 2 (appendix A; the P of its Example 1): models/paper.c. */
static int example2(ssi_case *c)
{
    cb_error err;
    if (cb_model_paper_example2(c->na, c->nb, &err) != CB_OK)
        return 0;
    cb_ssi_surface_set_nurbs(&c->A, c->na);
    cb_ssi_surface_set_nurbs(&c->B, c->nb);
    return 1;
}

/* Table 4 of the paper: torus (centre, normal, R, r) and ellipsoid (centre, x axis, y axis,
 * semi-axes a, b, c along them and their cross product). */
static int torus_ellipsoid(ssi_case *c, const double tc[3], const double tn[3], double R,
                           double r, const double ec[3], const double ex[3], const double ey[3],
                           double a, double b, double cc)
{
    static const double tor[4] = {0, 2 * CB_SSI_PI, 0, 2 * CB_SSI_PI};
    static const double ell[4] = {0, 2 * CB_SSI_PI, -CB_SSI_PI / 2, CB_SSI_PI / 2};
    cb_frame ft, fe;
    cb_analytic_surface t, e;
    cb_error err;
    double ez[3] = {ex[1] * ey[2] - ex[2] * ey[1], ex[2] * ey[0] - ex[0] * ey[2],
                    ex[0] * ey[1] - ex[1] * ey[0]};
    if (cb_frame_make(&ft, tc, tn, NULL, &err) || cb_analytic_torus(&t, &ft, R, r, &err) ||
        cb_frame_make(&fe, ec, ez, ex, &err) || cb_analytic_ellipsoid(&e, &fe, a, b, cc, &err) ||
        cb_analytic_to_nurbs(c->occt_b, &e, ell[0], ell[1], ell[2], ell[3], &err))
        return 0;
    cb_ssi_surface_set_analytic(&c->A, &t, tor);
    cb_ssi_surface_set_analytic(&c->B, &e, ell);
    c->occt_torus_a = 1;
    return 1;
}

#define N_GRAPH 12
#define N_CASES (N_GRAPH + 6)

/* Builds case k into c (NURBS parts initialised by the caller). */
static int build_case(ssi_case *c, int k)
{
    static const double X[3] = {1, 0, 0}, Y[3] = {0, 1, 0}, Z[3] = {0, 0, 1};
    cb_model_poly h = lin(0, 0, 0);
    switch (k) {
    case 0:
        *c = (ssi_case){.name = "one loop", .cls = "control", .components = 1, .truth = "1 loop"};
        h = circle(4, 2, 2, 1);
        break;
    case 1:
        *c = (ssi_case){.name = "crossing loops", .cls = "Fig.1a", .components = 1,
                        .truth = "2 loops, 2 nodes"};
        h = mul(circle(10, 4, 4, 9), circle(10, 6, 5, 9));
        break;
    case 2:
        *c = (ssi_case){.name = "isolated contact", .cls = "Fig.1b", .components = 2, .points = 1,
                        .truth = "2 branches + 1 point"};
        h = mul(circle(4, 2, 2, 0), mul(lin(4, 0, -1), lin(4, 0, -3)));
        break;
    case 3:
        *c = (ssi_case){.name = "boundary curves", .cls = "Fig.1c", .components = 1,
                        .truth = "2 sides + arc"};
        h = mul(mul(lin(1, 0, 0), lin(0, 1, 0)), circle(2, 0, 0, 1));
        break;
    case 4:
        *c = (ssi_case){.name = "tangent line, sides", .cls = "Fig.1d", .components = 1,
                        .truth = "4 sides + tangent"};
        h = mul(mul(mul(lin(1, 0, 0), lin(-1, 0, 1)), mul(lin(0, 1, 0), lin(0, -1, 1))),
                mul(lin(2, 0, -1), lin(2, 0, -1)));
        break;
    case 5:
        *c = (ssi_case){.name = "loops touching", .cls = "Fig.1e", .components = 1,
                        .truth = "2 loops, 1 contact"};
        h = mul(circle(10, 3, 5, 4), circle(20, 13, 10, 9));
        break;
    case 6:
        *c = (ssi_case){.name = "mirrored, touching", .cls = "Fig.1e", .components = 1,
                        .truth = "2 loops, 1 contact"};
        h = mul(circle(10, 3, 5, 4), circle(10, 7, 5, 4));
        break;
    case 7:
        *c = (ssi_case){.name = "mirrored loops", .cls = "symmetry", .components = 2,
                        .truth = "2 loops"};
        h = mul(circle(8, 2, 4, 1), circle(8, 6, 4, 1));
        break;
    case 8:
        *c = (ssi_case){.name = "tangential loop", .cls = "Fig.1f", .components = 1,
                        .truth = "1 tangent loop"};
        h = mul(circle(4, 2, 2, 1), circle(4, 2, 2, 1));
        break;
    case 9:
        *c = (ssi_case){.name = "three contacts", .cls = "Fig.1g", .points = 3,
                        .truth = "3 points"};
        h = mul(circle(4, 1, 1, 0), mul(circle(4, 2, 3, 0), circle(4, 3, 2, 0)));
        break;
    case 10:
        *c = (ssi_case){.name = "small loop 1e-3", .cls = "small loop", .components = 1,
                        .truth = "1 loop, r 1e-3"};
        h = circle(1000, 500, 500, 1);
        break;
    case 11:
        *c = (ssi_case){.name = "three loops", .cls = "patches", .components = 3,
                        .truth = "3 loops"};
        h = mul(circle(32, 16, 16, 16), mul(circle(32, 6, 22, 16), circle(32, 24, 11, 9)));
        break;
    case N_GRAPH:
        /* Fig. 14 is phi = 0 in Q's box: two arcs and a loop crossing them in two nodes. What
         * remains inside P's box has no count of its own; test_ssi_spline checks it against
         * sampled points of both surfaces. phi has bidegree (27, 24). */
        *c = (ssi_case){.name = "example 2", .cls = "App. A", .components = -1,
                        .truth = "Fig.14, clipped: ?", .max_phi_degree = 27};
        break;
    default:
        *c = (ssi_case){.name = NULL};
        break;
    }
    cb_nurbs_surface_init(c->na);
    cb_nurbs_surface_init(c->nb);
    cb_nurbs_surface_init(c->occt_b);
    if (k < N_GRAPH)
        return graph_pair(c, &h);
    if (k == N_GRAPH)
        return example2(c);
    /* Table 4, examples 1 to 5. Expected topology from the local shape at the points where the
     * ellipsoid's axes meet the torus' equators (ex. 1: its tips touch the outer equator from
     * inside; 3, 5: saddle contacts, nodes; 4: a touch at (3, 0, 0) and a node at (-1, 0, 0)),
     * confirmed by the sign changes of the ellipsoid's equation on a 1000 x 1000 grid of the
     * torus' parameters (components; the contacts as rounding-sized specks). */
    static const struct {
        double tc[3], R, r, ec[3];
        int yz; /* ellipsoid axes: 0 x, y; 1 y, z */
        double a, b, c;
        int components, points;
        const char *truth;
    } t4[5] = {{{0, 0, 0}, 4, 1, {0, 0, 0}, 0, 1, 5, 2, 2, 2, "2 loops + 2 points"},
               {{1, 0, 0}, 3, 1, {0, 0, 0}, 1, 3, 4, 2, 1, 0, "1 loop"},
               {{0, 0, 0}, 3, 1, {0, 0, 0}, 1, 4, 3, 2, 1, 0, "1 curve, 4 nodes"},
               {{0, 0, 0}, 2, 1, {1, 0, 0}, 0, 2, 2, 1, 1, 1, "curve+node, 1 point"},
               {{0, 0, 0}, 3, 1, {0, 0, 0}, 1, 3, 4, 2, 1, 0, "1 curve, 2 nodes"}};
    static const char *const names[5] = {"torus-ellipsoid 1", "torus-ellipsoid 2",
                                         "torus-ellipsoid 3", "torus-ellipsoid 4",
                                         "torus-ellipsoid 5"};
    int e = k - N_GRAPH - 1;
    c->name = names[e];
    c->cls = "Table 4";
    c->components = t4[e].components;
    c->points = t4[e].points;
    c->truth = t4[e].truth;
    return torus_ellipsoid(c, t4[e].tc, Z, t4[e].R, t4[e].r, t4[e].ec, t4[e].yz ? Y : X,
                           t4[e].yz ? Z : Y, t4[e].a, t4[e].b, t4[e].c);
}

static void case_clear(ssi_case *c)
{
    cb_nurbs_surface_clear(c->na);
    cb_nurbs_surface_clear(c->nb);
    cb_nurbs_surface_clear(c->occt_b);
}

/* ---------------------------------------------------------------- topology figures --------- */

typedef struct {
    int n;
    double *p; /* 3 n */
} polyline;

typedef struct {
    int n_curves, n_points;
    polyline *curve;
    double *point; /* 3 n_points */
} curve_set;

static void curve_set_clear(curve_set *s)
{
    for (int k = 0; k < s->n_curves; k++)
        free(s->curve[k].p);
    free(s->curve);
    free(s->point);
    memset(s, 0, sizeof *s);
}

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Distance between the segments [p0, p1] and [q0, q1] (closest points, clamped). */
static double seg_seg(const double *p0, const double *p1, const double *q0, const double *q1)
{
    double d1[3], d2[3], r[3];
    for (int i = 0; i < 3; i++) {
        d1[i] = p1[i] - p0[i];
        d2[i] = q1[i] - q0[i];
        r[i] = p0[i] - q0[i];
    }
    double a = dot3(d1, d1), e = dot3(d2, d2), f = dot3(d2, r), s = 0, t = 0;
    if (a <= 0 && e <= 0) {
        s = t = 0;
    } else if (a <= 0) {
        t = fmin(fmax(f / e, 0), 1);
    } else {
        double c = dot3(d1, r);
        if (e <= 0) {
            s = fmin(fmax(-c / a, 0), 1);
        } else {
            double b = dot3(d1, d2), den = a * e - b * b;
            s = den > 0 ? fmin(fmax((b * f - c * e) / den, 0), 1) : 0;
            t = (b * s + f) / e;
            if (t < 0) {
                t = 0;
                s = fmin(fmax(-c / a, 0), 1);
            } else if (t > 1) {
                t = 1;
                s = fmin(fmax((b - c) / a, 0), 1);
            }
        }
    }
    double d = 0;
    for (int i = 0; i < 3; i++) {
        double x = p0[i] + s * d1[i] - q0[i] - t * d2[i];
        d += x * x;
    }
    return sqrt(d);
}

static double point_curve(const double *X, const polyline *c)
{
    double best = HUGE_VAL;
    for (int i = 0; i + 1 < c->n || (i == 0 && c->n == 1); i++)
        best = fmin(best, seg_seg(X, X, c->p + 3 * i, c->p + 3 * (c->n > 1 ? i + 1 : i)));
    return best;
}

/* Distance between two polylines, or some value <= eps once one below it is found. */
static double curve_curve(const polyline *a, const polyline *b, double eps)
{
    double best = HUGE_VAL;
    for (int i = 0; i + 1 < a->n && best > eps; i++)
        for (int j = 0; j + 1 < b->n && best > eps; j++)
            best = fmin(best, seg_seg(a->p + 3 * i, a->p + 3 * i + 3, b->p + 3 * j,
                                      b->p + 3 * j + 3));
    return best;
}

static int find(int *parent, int i)
{
    while (parent[i] != i)
        i = parent[i] = parent[parent[i]];
    return i;
}

/* Curve components (curves within eps of each other joined) and isolated points (farther than
 * eps from every curve and from each other). */
static void topology(int *components, int *points, const curve_set *s, double eps)
{
    int n = s->n_curves, *parent = malloc((size_t)(n + 1) * sizeof(int));
    for (int i = 0; i < n; i++)
        parent[i] = i;
    for (int i = 0; i < n; i++)
        for (int j = i + 1; j < n; j++)
            if (find(parent, i) != find(parent, j) &&
                curve_curve(s->curve + i, s->curve + j, eps) <= eps)
                parent[find(parent, i)] = find(parent, j);
    *components = 0;
    for (int i = 0; i < n; i++)
        *components += find(parent, i) == i;
    free(parent);
    *points = 0;
    for (int k = 0; k < s->n_points; k++) {
        const double *X = s->point + 3 * k;
        int near = 0;
        for (int i = 0; i < n && !near; i++)
            near = point_curve(X, s->curve + i) <= eps;
        for (int j = 0; j < k && !near; j++) {
            const double *Y = s->point + 3 * j;
            near = sqrt((X[0] - Y[0]) * (X[0] - Y[0]) + (X[1] - Y[1]) * (X[1] - Y[1]) +
                        (X[2] - Y[2]) * (X[2] - Y[2])) <= eps;
        }
        *points += !near;
    }
}

/* Largest distance of a's curve points from b's curves (0 when a has none, infinite when b
 * has none but a has some). */
static double directed(const curve_set *a, const curve_set *b)
{
    double worst = 0;
    for (int i = 0; i < a->n_curves; i++)
        for (int k = 0; k < a->curve[i].n; k++) {
            double best = HUGE_VAL;
            for (int j = 0; j < b->n_curves; j++)
                best = fmin(best, point_curve(a->curve[i].p + 3 * k, b->curve + j));
            worst = fmax(worst, best);
        }
    return worst;
}

/* ---------------------------------------------------------------- the two sides ------------ */

typedef struct {
    int done, failed; /* failed: patch pairs not certified */
    int curves, points, components, isolated;
    int loose_components, loose_isolated; /* joined within 1e-3 of the model size */
    double t[2][3]; /* median, min, max; Colibri on 1 and 2 threads, OCCT in t[0] */
    double peak_mib; /* peak resident memory of a process running the case once (2 threads
                        for Colibri, parallel for OCCT); < 0 unknown */
    char msg[120];
    curve_set set;
} side;

static void run_colibri(side *o, const ssi_case *c, int runs, double *tol)
{
    memset(o, 0, sizeof *o);
    for (int th = 0; th < 2; th++) {
        double t[MAX_RUNS];
        for (int r = 0; r < runs; r++) {
            cb_ssi_opts opts;
            cb_ssi_opts_default(&opts);
            opts.threads = th + 1;
            if (c->max_phi_degree > 0)
                opts.max_phi_degree = c->max_phi_degree;
            cb_ssi_result_t res;
            cb_ssi_result_init(res);
            cb_error err;
            cb_error_clear(&err);
            double t0 = now();
            cb_status st = cb_ssi_surfaces(res, &c->A, &c->B, -1, -1, &opts, &err);
            t[r] = now() - t0;
            if (st) {
                snprintf(o->msg, sizeof o->msg, "%.110s", err.msg);
            } else if (th == 1 && r == runs - 1) {
                o->done = 1;
                o->failed = (int)res->n_failed;
                if (res->n_failed)
                    snprintf(o->msg, sizeof o->msg, "%.110s", res->failed[0].msg);
                o->curves = (int)res->n_curves;
                o->points = (int)res->n_points;
                *tol = res->tol;
                curve_set *s = &o->set;
                s->n_curves = o->curves;
                s->curve = calloc((size_t)o->curves + 1, sizeof(polyline));
                for (int i = 0; i < o->curves; i++) {
                    const cb_ssi_curve *cv = res->curve + i;
                    s->curve[i].n = (int)cv->n;
                    s->curve[i].p = malloc((size_t)cv->n * 3 * sizeof(double));
                    for (slong j = 0; j < cv->n; j++)
                        memcpy(s->curve[i].p + 3 * j, cv->pt[j].xyz, 3 * sizeof(double));
                }
                s->n_points = o->points;
                s->point = malloc(((size_t)o->points + 1) * 3 * sizeof(double));
                for (int i = 0; i < o->points; i++)
                    memcpy(s->point + 3 * i, res->point[i].p.xyz, 3 * sizeof(double));
            }
            cb_ssi_result_clear(res);
        }
        stats3(o->t[th], t, runs);
    }
}

/* The comparator's input: the two surfaces (see occt_ssi.cpp for the format). */
static int write_pair(const char *path, const ssi_case *c)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return 0;
    if (c->occt_torus_a) {
        const cb_analytic_surface *t = &c->A.analytic;
        const cb_frame *fr = &t->frame;
        fprintf(f, "torus %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n",
                fr->o[0], fr->o[1], fr->o[2], fr->z[0], fr->z[1], fr->z[2], fr->x[0], fr->x[1],
                fr->x[2], t->r1, t->r2);
        bench_write_nurbs(f, c->occt_b);
    } else {
        bench_write_nurbs(f, c->na);
        bench_write_nurbs(f, c->nb);
    }
    return fclose(f) == 0;
}

static void run_occt(side *o, const char *occt, const char *path, int runs, double tol)
{
    memset(o, 0, sizeof *o);
    o->peak_mib = -1;
    char sruns[16], stol[32];
    snprintf(sruns, sizeof sruns, "%d", runs);
    snprintf(stol, sizeof stol, "%.17g", tol);
    char *const argv[] = {(char *)occt, sruns, stol, (char *)path, NULL};
    /* The comparator's whole output (its polylines), then parsed as a stream. */
    size_t cap = (size_t)64 << 20, got = 0;
    char *buf = malloc(cap);
    long kib;
    if (!buf)
        return;
    int rc = spawn_read(buf, cap - 1, &got, argv, &kib);
    buf[got] = 0;
    FILE *p = rc == 0 ? fmemopen(buf, got + 1, "r") : NULL;
    if (!p) {
        snprintf(o->msg, sizeof o->msg, "the comparator failed (exit %d)", rc);
        free(buf);
        return;
    }
    o->peak_mib = kib / 1024.0;
    double ms[3];
    int done;
    if (fscanf(p, "%lf %lf %lf %d %d %d", ms, ms + 1, ms + 2, &done, &o->curves, &o->points) ==
            6 &&
        o->curves >= 0 && o->points >= 0) {
        o->done = done;
        for (int q = 0; q < 3; q++)
            o->t[0][q] = 1e-3 * ms[q];
        curve_set *s = &o->set;
        s->curve = calloc((size_t)o->curves + 1, sizeof(polyline));
        s->point = malloc(((size_t)o->points + 1) * 3 * sizeof(double));
        int ok = 1;
        for (int i = 0; i < o->curves && ok; i++) {
            int n;
            ok = fscanf(p, " L %d", &n) == 1 && n >= 0;
            s->curve[i].p = malloc(((size_t)n + 1) * 3 * sizeof(double));
            s->curve[i].n = n;
            s->n_curves = i + 1;
            for (int j = 0; j < n && ok; j++)
                ok = fscanf(p, "%lf %lf %lf", s->curve[i].p + 3 * j, s->curve[i].p + 3 * j + 1,
                            s->curve[i].p + 3 * j + 2) == 3;
        }
        for (int i = 0; i < o->points && ok; i++) {
            ok = fscanf(p, " P %lf %lf %lf", s->point + 3 * i, s->point + 3 * i + 1,
                        s->point + 3 * i + 2) == 3;
            s->n_points = i + 1;
        }
        if (!ok) {
            o->done = 0;
            snprintf(o->msg, sizeof o->msg, "unreadable comparator output");
        } else if (!done) {
            snprintf(o->msg, sizeof o->msg, "GeomInt_IntSS: not done");
        }
    } else {
        snprintf(o->msg, sizeof o->msg, "the comparator failed");
    }
    fclose(p);
    free(buf);
}

/* Peak resident memory (MiB) of this program run as `--peak K`: a process that builds case K
 * and intersects it once on 2 threads (K = -1: builds nothing, the process's own floor); < 0
 * when it could not be run. *tol: the tolerance that run used (0 if unknown). */
static double colibri_peak(double *tol, const char *self, int k)
{
    char sk[16], out[64];
    snprintf(sk, sizeof sk, "%d", k);
    char *const argv[] = {(char *)self, "--peak", sk, NULL};
    size_t got;
    long kib;
    int rc = spawn_read(out, sizeof out - 1, &got, argv, &kib);
    out[got] = 0;
    *tol = 0;
    if (rc == 0 && sscanf(out, "%lf", tol) != 1)
        *tol = 0;
    return rc == 0 ? kib / 1024.0 : -1;
}

/* The child of colibri_peak. */
static int peak_child(int k)
{
    if (k < 0)
        return 0;
    ssi_case c;
    int ok = build_case(&c, k);
    if (ok) {
        cb_ssi_opts opts;
        cb_ssi_opts_default(&opts);
        opts.threads = 2;
        if (c.max_phi_degree > 0)
            opts.max_phi_degree = c.max_phi_degree;
        cb_ssi_result_t res;
        cb_ssi_result_init(res);
        cb_error err;
        ok = cb_ssi_surfaces(res, &c.A, &c.B, -1, -1, &opts, &err) == CB_OK;
        if (ok)
            printf("%.17g\n", res->tol);
        cb_ssi_result_clear(res);
    }
    case_clear(&c);
    return ok ? 0 : 1;
}

static const char *verdict(const side *o, const ssi_case *c)
{
    if (!o->done)
        return "fails";
    if (o->failed)
        return "refused";
    if (c->components < 0)
        return "-";
    if (o->components == c->components && o->isolated == c->points)
        return "ok";
    return o->loose_components == c->components && o->loose_isolated == c->points ? "gaps"
                                                                                  : "WRONG";
}

/* ---------------------------------------------------------------- main --------------------- */

/* A number, or null for what JSON cannot hold (no curves on one side: infinite distance). */
static void json_num(FILE *f, double x)
{
    if (isfinite(x))
        fprintf(f, "%.3g", x);
    else
        fputs("null", f);
}

static void json_side(FILE *f, const char *key, const side *o, const ssi_case *c, int occt)
{
    fprintf(f, "\"%s\": {\"verdict\": \"%s\", \"curves\": %d, \"points\": %d, \"components\": %d, "
               "\"isolated\": %d",
            key, verdict(o, c), o->curves, o->points, o->components, o->isolated);
    if (!occt)
        fprintf(f, ", \"not_certified\": %d", o->failed);
    for (int th = 0; th < (occt ? 1 : 2); th++)
        fprintf(f, ", \"time_s%s\": {\"median\": %.6f, \"min\": %.6f, \"max\": %.6f}",
                occt ? "" : (th ? "_threads_2" : "_threads_1"), o->t[th][0], o->t[th][1],
                o->t[th][2]);
    fputs(", \"peak_mib\": ", f);
    json_num(f, o->peak_mib);
    if (o->msg[0]) {
        fputs(", \"message\": ", f);
        cb_json_string(f, o->msg);
    }
    fputs("}", f);
}

int main(int argc, char **argv)
{
    if (argc == 3 && !strcmp(argv[1], "--peak"))
        return peak_child(atoi(argv[2]));
    int runs = argc > 1 ? atoi(argv[1]) : 3;
    if (runs < 1 || runs > MAX_RUNS)
        runs = 3;
    const char *occt = argc > 2 && strcmp(argv[2], "-") ? argv[2] : NULL;
    if (occt && access(occt, X_OK))
        occt = NULL;
    FILE *json = NULL;
    if (argc > 3 && !(json = fopen(argv[3], "w"))) {
        fprintf(stderr, "bench_ssi_cases: cannot write %s\n", argv[3]);
        return 1;
    }
    char dir[] = "/tmp/colibri_ssi_XXXXXX", path[64]; /* mkdtemp replaces the Xs */
    if (occt && !mkdtemp(dir)) {
        fprintf(stderr, "bench_ssi_cases: cannot make a temporary directory\n");
        return 1;
    }
    snprintf(path, sizeof path, "%s/pair.txt", dir);
    double floor_tol, floor_mib = colibri_peak(&floor_tol, argv[0], -1);
    printf("SSI topology cases, %d run%s each: curve components + isolated points against the "
           "true ones; time in seconds, median [min max]; peak memory of one run in a process "
           "of its own, MiB (a process that only starts: %.1f)\n",
           runs, runs == 1 ? "" : "s", floor_mib);
    printf("%-19s %-10s %-22s | %-5s %-7s %-21s %-21s %6s |", "case", "class", "true topology",
           "C c+p", "verdict", "Colibri 1 thread", "2 threads", "MiB");
    if (occt)
        printf(" %-5s %-7s %-21s %6s %6s %8s %8s", "O c+p", "verdict", "OCCT", "MiB", "C2/O",
               "d(C,O)", "d(O,C)");
    printf("\n");
    if (json)
        fprintf(json, "{\"runs\": %d, \"cases\": [", runs);
    int status = 0;
    /* First every child process, while this one is still small: a spawned child's peak
     * includes this process's resident memory at the spawn (it shares it until exec). */
    side oc_all[N_CASES];
    double peak[N_CASES];
    int have[N_CASES];
    for (int k = 0; k < N_CASES; k++) {
        ssi_case c;
        have[k] = 0;
        peak[k] = -1;
        if (build_case(&c, k)) {
            /* The child reports the tolerance Colibri uses (1e-6 of the model size), which
             * OCCT is given too. */
            double tol = 0;
            peak[k] = colibri_peak(&tol, argv[0], k);
            have[k] = occt && tol > 0 && write_pair(path, &c);
            if (have[k])
                run_occt(oc_all + k, occt, path, runs, tol);
        }
        case_clear(&c);
    }
    for (int k = 0; k < N_CASES; k++) {
        ssi_case c;
        if (!build_case(&c, k)) {
            printf("case %d could not be built\n", k);
            case_clear(&c);
            status = 1;
            continue;
        }
        side co, oc;
        double tol = 0;
        run_colibri(&co, &c, runs, &tol);
        co.peak_mib = peak[k];
        /* Model size: tol is 1e-6 of it. */
        double eps = 100 * tol, size = tol / 1e-6, dco = NAN, doc = NAN;
        topology(&co.components, &co.isolated, &co.set, eps);
        topology(&co.loose_components, &co.loose_isolated, &co.set, 1e-3 * size);
        int have_occt = have[k];
        if (have_occt) {
            oc = oc_all[k];
            topology(&oc.components, &oc.isolated, &oc.set, eps);
            topology(&oc.loose_components, &oc.loose_isolated, &oc.set, 1e-3 * size);
        }
        char cc[16], oo[16];
        snprintf(cc, sizeof cc, "%d+%d", co.components, co.isolated);
        printf("%-19s %-10s %-22s | %-5s %-7s %6.3f [%5.3f %5.3f] %6.3f [%5.3f %5.3f] %6.1f |",
               c.name, c.cls, c.truth, co.done ? cc : "-", verdict(&co, &c), co.t[0][0],
               co.t[0][1], co.t[0][2], co.t[1][0], co.t[1][1], co.t[1][2], co.peak_mib);
        if (have_occt) {
            snprintf(oo, sizeof oo, "%d+%d", oc.components, oc.isolated);
            dco = directed(&co.set, &oc.set) / size;
            doc = directed(&oc.set, &co.set) / size;
            printf(" %-5s %-7s %6.3f [%5.3f %5.3f] %6.1f %6.2f %8.1e %8.1e", oc.done ? oo : "-",
                   verdict(&oc, &c), oc.t[0][0], oc.t[0][1], oc.t[0][2], oc.peak_mib,
                   oc.t[0][0] > 0 ? co.t[1][0] / oc.t[0][0] : NAN, dco, doc);
        }
        printf("\n");
        if (co.msg[0])
            printf("    Colibri: %s (%d pairs not certified)\n", co.msg, co.failed);
        if (have_occt && oc.msg[0])
            printf("    OCCT: %s\n", oc.msg);
        fflush(stdout);
        if (json) {
            fprintf(json, "%s\n {\"case\": ", k ? "," : "");
            cb_json_string(json, c.name);
            fputs(", \"class\": ", json);
            cb_json_string(json, c.cls);
            fprintf(json, ", \"true\": {\"components\": %d, \"isolated\": %d, \"text\": ",
                    c.components, c.points);
            cb_json_string(json, c.truth);
            fprintf(json, "}, \"tol\": %.3g, ", tol);
            json_side(json, "colibri", &co, &c, 0);
            if (have_occt) {
                fputs(", ", json);
                json_side(json, "occt", &oc, &c, 1);
                fputs(", \"d_colibri_occt\": ", json);
                json_num(json, dco);
                fputs(", \"d_occt_colibri\": ", json);
                json_num(json, doc);
            }
            fputs("}", json);
        }
        curve_set_clear(&co.set);
        if (have_occt)
            curve_set_clear(&oc.set);
        case_clear(&c);
    }
    if (json) {
        fputs("\n]}\n", json);
        fclose(json);
    }
    if (occt) {
        remove(path);
        rmdir(dir);
    }
    return status;
}
