/* Booleans (cb_bool_run): time per phase (intersection, splitting, sewing) for each case and
 * operation on 1 and 2 threads, the median and range of RUNS runs, with the result's faces and
 * its B-rep volume against the closed form where there is one. The cases of the Booleans
 * issue, analytic and as B-splines (cb_analytic_to_nurbs nets): the Steinmetz bicylinder, the
 * tricylinder (the Steinmetz solid against the third cylinder), the lens of two unit spheres,
 * a unit sphere on a corner of a box, a torus cut by a box through its centre plane, two boxes
 * sharing a face, a sphere touching a box, a cylinder lying on a box, a cylinder in a hole of
 * its radius; the Cardan cross into its base; two hummingbirds; and the universal joint of the
 * shared models (fork against the cross moved by (-100, 0, 0)).
 * Usage: bench_bool [RUNS [SHARED]] (RUNS default 3; SHARED: the directory holding models/,
 * default ../shared). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "boolean/bool.h"
#include "brep/mass.h"
#include "brep/prim.h"
#include "io/step.h"
#include "models/models.h"

#define PI 3.14159265358979323846

typedef struct {
    const char *name;
    cb_topo_body *a, *b;
    double exact[3]; /* union, intersection, difference; NaN: none */
} bench_case;

static int cmp(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

static cb_topo_body *cylinder(const double o[3], const double axis[3], const double ref[3],
                              double r, double h, int as_nurbs)
{
    cb_frame f;
    cb_error err;
    cb_topo_body *b = NULL;
    if (cb_frame_make(&f, o, axis, ref, &err) || cb_prim_cylinder(&b, &f, r, h, as_nurbs, 0, &err))
        fprintf(stderr, "bench_bool: cylinder: %s\n", err.msg);
    return b;
}

static cb_topo_body *box(const double lo[3], const double hi[3], int as_nurbs)
{
    cb_error err;
    cb_topo_body *b = NULL;
    if (cb_prim_box(&b, NULL, lo, hi, as_nurbs, 0, &err))
        fprintf(stderr, "bench_bool: box: %s\n", err.msg);
    return b;
}

static cb_topo_body *sphere(const double c[3], double r, int as_nurbs)
{
    cb_frame f;
    cb_error err;
    const double z[3] = {0, 0, 1}, x[3] = {1, 0, 0};
    cb_topo_body *b = NULL;
    if (cb_frame_make(&f, c, z, x, &err) || cb_prim_sphere(&b, &f, r, as_nurbs, 0, &err))
        fprintf(stderr, "bench_bool: sphere: %s\n", err.msg);
    return b;
}

/* "base" followed by " NURBS" for B-spline operands, allocated (the case owns it). */
static char *case_name(const char *base, int nurbs)
{
    char buf[64];
    snprintf(buf, sizeof buf, "%s%s", base, nurbs ? " NURBS" : "");
    return strdup(buf);
}

/* op of a and b, untimed (an operand of a case); NULL on failure. */
static cb_topo_body *boolean(cb_bool_op op, const cb_topo_body *a, const cb_topo_body *b)
{
    cb_topo_body *res = NULL;
    cb_error err;
    if (!a || !b || cb_bool_run(&res, NULL, op, a, b, NULL, NULL, &err)) {
        fprintf(stderr, "bench_bool: operand: %s\n", a && b ? err.msg : "missing");
        return NULL;
    }
    return res;
}

static void run_case(const bench_case *c, int runs)
{
    static const cb_bool_op ops[3] = {CB_BOOL_UNION, CB_BOOL_INTERSECTION, CB_BOOL_DIFFERENCE};
    for (int k = 0; k < 3; k++)
        for (int threads = 1; threads <= 2; threads++) {
            double *t = malloc((size_t)runs * 4 * sizeof(double));
            if (!t)
                return;
            cb_topo_body *res = NULL;
            cb_error err;
            cb_status st = CB_OK;
            for (int r = 0; r < runs && !st; r++) {
                cb_context ctx;
                cb_context_init(&ctx);
                ctx.threads = threads;
                cb_bool_stats s;
                cb_topo_body_free(res);
                res = NULL;
                st = cb_bool_run(&res, &s, ops[k], c->a, c->b, NULL, &ctx, &err);
                t[r] = s.time_ssi;
                t[runs + r] = s.time_split;
                t[2 * runs + r] = s.time_build;
                t[3 * runs + r] = s.time_ssi + s.time_split + s.time_build;
            }
            printf("%-27s %-12s %dT", c->name, cb_bool_op_name(ops[k]), threads);
            if (st) {
                printf("  failed: %s\n", err.msg);
            } else {
                for (int p = 0; p < 4; p++)
                    qsort(t + p * runs, (size_t)runs, sizeof(double), cmp);
                cb_mass_props m;
                double v = cb_mass_body(&m, res, 1e-10, NULL, &err) ? NAN : m.volume;
                printf("  ssi %7.3f  split %7.3f  sew %7.3f  total %7.3f s [%.3f, "
                       "%.3f]  faces %4d"
                       "  V %.10g",
                       t[runs / 2], t[runs + runs / 2], t[2 * runs + runs / 2],
                       t[3 * runs + runs / 2], t[3 * runs], t[4 * runs - 1], res->n_faces, v);
                if (c->exact[k] == 0)
                    printf(" (abs %.1e)", fabs(v));
                else if (!isnan(c->exact[k]))
                    printf(" (rel %.1e)", fabs(v - c->exact[k]) / c->exact[k]);
                printf("\n");
            }
            fflush(stdout);
            cb_topo_body_free(res);
            free(t);
        }
}

#define MAX_CASES 32

int main(int argc, char **argv)
{
    int runs = argc > 1 ? atoi(argv[1]) : 3;
    if (runs < 1)
        runs = 1;
    const char *shared = argc > 2 ? argv[2] : "../shared";
    cb_error err;
    bench_case cases[MAX_CASES];
    int n = 0;
    const double vi = 16.0 / 3, vc = 4 * PI, ball = 4 * PI / 3;
    const double ox[3] = {-2, 0, 0}, x[3] = {1, 0, 0}, oy[3] = {0, -2, 0}, y[3] = {0, 1, 0};
    const double oz[3] = {0, 0, -2}, z[3] = {0, 0, 1};
    for (int nurbs = 0; nurbs < 2; nurbs++) {
        cases[n++] = (bench_case){case_name("steinmetz", nurbs),
                                  cylinder(ox, x, z, 1, 4, nurbs),
                                  cylinder(oy, y, z, 1, 4, nurbs),
                                  {2 * vc - vi, vi, vc - vi}};
        cb_topo_body *ab = boolean(CB_BOOL_INTERSECTION, cases[n - 1].a, cases[n - 1].b);
        double tri = 8 * (2 - sqrt(2.0));
        cases[n++] = (bench_case){case_name("tricylinder", nurbs),
                                  ab,
                                  cylinder(oz, z, x, 1, 4, nurbs),
                                  {vi + vc - tri, tri, vi - tri}};
        const double c0[3] = {0, 0, 0}, c1[3] = {1, 0, 0}, lens = 5 * PI / 12;
        cases[n++] = (bench_case){case_name("lens", nurbs),
                                  sphere(c0, 1, nurbs),
                                  sphere(c1, 1, nurbs),
                                  {2 * ball - lens, lens, ball - lens}};
        const double lo[3] = {0, 0, 0}, hi[3] = {2, 2, 2}, corner[3] = {2, 2, 2};
        cases[n++] = (bench_case){case_name("sphere on a corner", nurbs),
                                  box(lo, hi, nurbs),
                                  sphere(corner, 1, nurbs),
                                  {8 + 7 * ball / 8, ball / 8, 8 - ball / 8}};
        cb_frame f;
        cb_topo_body *T = NULL;
        const double tlo[3] = {-3, -3, -1}, thi[3] = {3, 3, 0}, half = PI * PI * 2 * 0.25;
        if (cb_frame_make(&f, c0, z, x, &err) || cb_prim_torus(&T, &f, 2, 0.5, nurbs, 0, &err))
            fprintf(stderr, "bench_bool: torus: %s\n", err.msg);
        cases[n++] = (bench_case){
            case_name("torus and box", nurbs), T, box(tlo, thi, nurbs), {36 + half, half, half}};
        const double lo2[3] = {2, 0, 0}, hi2[3] = {4, 2, 2}, top[3] = {1, 1, 3};
        cases[n++] = (bench_case){case_name("boxes sharing a face", nurbs),
                                  box(lo, hi, nurbs),
                                  box(lo2, hi2, nurbs),
                                  {16, 0, 8}};
        cases[n++] = (bench_case){case_name("sphere touching a box", nurbs),
                                  box(lo, hi, nurbs),
                                  sphere(top, 1, nurbs),
                                  {8 + ball, 0, 8}};
        const double ol[3] = {-1, 1, 2.5}, op[3] = {1, 1, -1};
        cases[n++] = (bench_case){case_name("cylinder on a box", nurbs),
                                  box(lo, hi, nurbs),
                                  cylinder(ol, x, z, 0.5, 4, nurbs),
                                  {8 + PI, 0, 8}};
        cb_topo_body *A = box(lo, hi, nurbs), *P = cylinder(op, z, x, 0.5, 4, nurbs);
        cb_topo_body *H = boolean(CB_BOOL_DIFFERENCE, A, P);
        cb_topo_body_free(A);
        cb_topo_body_free(P);
        cases[n++] = (bench_case){case_name("cylinder in its hole", nurbs),
                                  H,
                                  cylinder(op, z, y, 0.5, 4, nurbs),
                                  {8 + PI / 2, 0, 8 - PI / 2}};
    }
    for (int nurbs = 0; nurbs < 2; nurbs++) {
        cb_cardan_scenario sc;
        cb_cardan_volumes v;
        cb_topo_body *a = NULL, *b = NULL;
        if (cb_cardan_scenario_find(&sc, "cross_into_base", &err))
            return 1;
        sc.a.as_nurbs = sc.b.as_nurbs = nurbs;
        if (cb_cardan_scenario_volumes(&v, &sc, &err) || cb_model_cardan(&a, &sc.a, &err) ||
            cb_model_cardan(&b, &sc.b, &err)) {
            fprintf(stderr, "bench_bool: cardan: %s\n", err.msg);
            return 1;
        }
        cases[n++] = (bench_case){
            case_name("cross into base", nurbs), a, b, {v.a_union_b, v.a_inter_b, v.a_minus_b}};
    }
    cb_hummingbird_params p;
    cb_hummingbird_params_default(&p);
    cb_topo_body *a = NULL, *b = NULL;
    if (cb_model_hummingbird(&a, &p, &err))
        return 1;
    p.translate[0] += 0.25;
    p.translate[1] += 0.08;
    p.translate[2] += 0.05;
    if (cb_model_hummingbird(&b, &p, &err) || cb_topo_compute_pcurves(a, a->tol, &err) ||
        cb_topo_compute_pcurves(b, b->tol, &err)) {
        fprintf(stderr, "bench_bool: hummingbird: %s\n", err.msg);
        return 1;
    }
    cases[n++] = (bench_case){case_name("two hummingbirds", 0), a, b, {NAN, NAN, NAN}};
    /* The universal joint: no closed form; the identities are in tests/test_bool_op.c. */
    cb_topo_body *u[2] = {NULL, NULL};
    for (int k = 0; k < 2; k++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/models/%s", shared,
                 k ? "ujoint_cross.step" : "ujoint_fork.step");
        if (cb_step_read(u + k, path, &err))
            fprintf(stderr, "bench_bool: %s\n", err.msg);
    }
    if (u[1]) {
        cb_xform t;
        const double shift[3] = {-100, 0, 0};
        cb_xform_translation(&t, shift);
        cb_topo_body_transform(u[1], &t);
    }
    cases[n++] = (bench_case){case_name("ujoint", 0), u[0], u[1], {NAN, NAN, NAN}};
    printf("median of %d runs per row; 1T / 2T: threads\n", runs);
    for (int k = 0; k < n; k++) {
        if (cases[k].a && cases[k].b)
            run_case(cases + k, runs);
        else
            printf("%-27s operands could not be built\n", cases[k].name);
        cb_topo_body_free(cases[k].a);
        cb_topo_body_free(cases[k].b);
        free((char *)cases[k].name);
    }
    return 0;
}
