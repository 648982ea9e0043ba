/* Booleans (cb_bool_run): time per phase (intersection, splitting, sewing) for each case and
 * operation on 1 and 2 threads, the median and range of RUNS runs, with the result's faces and
 * its B-rep volume against the closed form where there is one.
 * Usage: bench_bool [RUNS] (default 3). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "boolean/bool.h"
#include "brep/mass.h"
#include "brep/prim.h"
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

static cb_topo_body *cylinder(const double o[3], const double axis[3], int as_nurbs)
{
    cb_frame f;
    cb_error err;
    double ref[3] = {0, 0, 1};
    cb_topo_body *b = NULL;
    if (cb_frame_make(&f, o, axis, ref, &err) || cb_prim_cylinder(&b, &f, 1, 4, as_nurbs, 0, &err))
        fprintf(stderr, "bench_bool: cylinder: %s\n", err.msg);
    return b;
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
            printf("%-22s %-12s %dT", c->name, cb_bool_op_name(ops[k]), threads);
            if (st) {
                printf("  failed: %s\n", err.msg);
            } else {
                for (int p = 0; p < 4; p++)
                    qsort(t + p * runs, (size_t)runs, sizeof(double), cmp);
                cb_mass_props m;
                double v = cb_mass_body(&m, res, 1e-10, NULL, &err) ? NAN : m.volume;
                printf("  ssi %7.3f  split %7.3f  sew %7.3f  total %7.3f s [%.3f, %.3f]  faces %4d"
                       "  V %.10g",
                       t[runs / 2], t[runs + runs / 2], t[2 * runs + runs / 2],
                       t[3 * runs + runs / 2], t[3 * runs], t[4 * runs - 1], res->n_faces, v);
                if (!isnan(c->exact[k]))
                    printf(" (rel %.1e)", fabs(v - c->exact[k]) / c->exact[k]);
                printf("\n");
            }
            fflush(stdout);
            cb_topo_body_free(res);
            free(t);
        }
}

int main(int argc, char **argv)
{
    int runs = argc > 1 ? atoi(argv[1]) : 3;
    if (runs < 1)
        runs = 1;
    cb_error err;
    bench_case cases[6];
    int n = 0;
    double vi = 16.0 / 3, vc = 4 * PI;
    double ox[3] = {-2, 0, 0}, x[3] = {1, 0, 0}, oy[3] = {0, -2, 0}, y[3] = {0, 1, 0};
    for (int nurbs = 0; nurbs < 2; nurbs++)
        cases[n++] = (bench_case){nurbs ? "steinmetz NURBS" : "steinmetz", cylinder(ox, x, nurbs),
                                  cylinder(oy, y, nurbs), {2 * vc - vi, vi, vc - vi}};
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
        cases[n++] = (bench_case){nurbs ? "cross into base NURBS" : "cross into base", a, b,
                                  {v.a_union_b, v.a_inter_b, v.a_minus_b}};
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
    cases[n++] = (bench_case){"two hummingbirds", a, b, {NAN, NAN, NAN}};
    printf("median of %d runs per row; 1T / 2T: threads\n", runs);
    for (int k = 0; k < n; k++) {
        if (cases[k].a && cases[k].b)
            run_case(cases + k, runs);
        cb_topo_body_free(cases[k].a);
        cb_topo_body_free(cases[k].b);
    }
    return 0;
}
