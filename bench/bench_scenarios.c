/* The shipped Boolean scenarios (cb_model_scenario: the two hummingbirds, the Cardan-joint
 * scenarios analytic and B-spline), Colibri beside Open CASCADE: for each scenario and each of
 * union, intersection and A - B, the median time of RUNS runs of cb_bool_run on 1 and 2
 * threads, the result's validity and B-rep volume against the reference within its error bar;
 * and, when the path of the OCCT comparator (occt_bool, built by scripts/setup-bench) is given,
 * the same figures from Open CASCADE on the same solids written as STEP, and the time ratio.
 * Usage: bench_scenarios [RUNS [OCCT_BOOL [JSON_OUT]]]   (RUNS default 3; "-" for no OCCT) */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "boolean/bool.h"
#include "brep/mass.h"
#include "io/json.h"
#include "io/step_write.h"
#include "models/models.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int cmp(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

typedef struct {
    int done, valid;
    double volume, t[2]; /* median seconds on 1 and 2 threads */
    char msg[96];
} side;

/* Colibri: op k on s, RUNS runs on each thread count. */
static void run_colibri(side *o, const cb_model_scenario *s, int k, int runs)
{
    static const cb_bool_op ops[3] = {CB_BOOL_UNION, CB_BOOL_INTERSECTION, CB_BOOL_DIFFERENCE};
    memset(o, 0, sizeof *o);
    o->volume = NAN;
    for (int th = 0; th < 2; th++) {
        double t[64];
        cb_context ctx;
        cb_context_init(&ctx);
        ctx.threads = th + 1;
        for (int r = 0; r < runs; r++) {
            cb_topo_body *res = NULL;
            cb_error err;
            double t0 = now();
            cb_status st = cb_bool_run(&res, NULL, ops[k], s->a, s->b, NULL, &ctx, &err);
            t[r] = now() - t0;
            if (st) {
                snprintf(o->msg, sizeof o->msg, "%.90s", err.msg);
                o->done = 0;
            } else if (th == 1 && r == runs - 1) {
                cb_topo_report rep;
                cb_topo_report_init(&rep);
                o->valid = !cb_topo_validate(&rep, res, res->tol, 9, &err) && rep.n == 0;
                cb_topo_report_clear(&rep);
                cb_mass_props m;
                if (!cb_mass_body(&m, res, CB_MASS_REL_TOL, NULL, &err))
                    o->volume = m.volume;
                o->done = 1;
            }
            cb_topo_body_free(res);
        }
        qsort(t, (size_t)runs, sizeof *t, cmp);
        o->t[th] = t[runs / 2];
    }
}

/* Open CASCADE through the comparator on the STEP files; o->done = 0 when it could not run. */
static void run_occt(side o[3], const char *occt, const char *a, const char *b, int runs)
{
    memset(o, 0, 3 * sizeof *o);
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "'%s' %d '%s' '%s'", occt, runs, a, b);
    FILE *p = popen(cmd, "r");
    if (!p)
        return;
    for (int k = 0; k < 3; k++) {
        char op[32];
        int error, valid, faces;
        double ms, v;
        if (fscanf(p, "%31s %lf %d %d %d %lf", op, &ms, &error, &valid, &faces, &v) != 6)
            break;
        o[k].done = !error;
        o[k].valid = valid;
        o[k].volume = error ? NAN : v;
        o[k].t[0] = o[k].t[1] = 1e-3 * ms;
        if (error)
            snprintf(o[k].msg, sizeof o[k].msg, "OCCT reports an error");
    }
    pclose(p);
}

static const char *verdict(const side *o, double ref, double bar)
{
    if (!o->done)
        return "fails";
    if (!o->valid)
        return "invalid";
    return fabs(o->volume - ref) <= bar ? "ok" : "WRONG";
}

static void json_side(FILE *f, const char *key, const side *o, double ref, double bar)
{
    fprintf(f, "\"%s\": {\"verdict\": \"%s\", \"valid\": %s, \"volume\": ", key,
            verdict(o, ref, bar), o->valid ? "true" : "false");
    if (isfinite(o->volume))
        fprintf(f, "%.17g", o->volume);
    else
        fputs("null", f);
    fprintf(f, ", \"time_s\": [%.6f, %.6f]}", o->t[0], o->t[1]);
}

int main(int argc, char **argv)
{
    int runs = argc > 1 ? atoi(argv[1]) : 3;
    if (runs < 1 || runs > 64)
        runs = 3;
    const char *occt = argc > 2 && strcmp(argv[2], "-") ? argv[2] : NULL;
    if (occt && access(occt, X_OK))
        occt = NULL;
    FILE *json = argc > 3 ? fopen(argv[3], "w") : NULL;
    char dir[] = "/tmp/colibri_bench_XXXXXX";
    if (!mkdtemp(dir)) {
        fprintf(stderr, "bench_scenarios: cannot make a temporary directory\n");
        return 1;
    }
    printf("Booleans on the shipped scenarios, %d run%s each (median); volumes against the "
           "references (rel.err; verdict ok within the bar)\n",
           runs, runs == 1 ? "" : "s");
    printf("%-24s %-12s %13s | %13s %9s %-7s %7s %7s |", "scenario", "operation", "reference",
           "Colibri", "rel.err", "verdict", "1 th/s", "2 th/s");
    if (occt)
        printf(" %13s %9s %-7s %7s %7s", "OCCT 7.6", "rel.err", "verdict", "s", "C2/O");
    printf("\n");
    if (json)
        fputs("[", json);
    int first = 1, n = cb_model_scenario_count();
    for (int k = 0; k < n; k++) {
        cb_model_scenario s;
        cb_error err;
        if (cb_model_scenario_load(&s, k, &err)) {
            printf("scenario %d: %s\n", k, err.msg);
            continue;
        }
        char pa[256], pb[256];
        snprintf(pa, sizeof pa, "%s/%s_a.step", dir, s.name);
        snprintf(pb, sizeof pb, "%s/%s_b.step", dir, s.name);
        side oc[3];
        int have_occt = occt && !cb_step_write(s.a, pa, s.name, &err) &&
                        !cb_step_write(s.b, pb, s.name, &err);
        if (have_occt)
            run_occt(oc, occt, pa, pb, runs);
        for (int op = 0; op < 3; op++) {
            side c;
            run_colibri(&c, &s, op, runs);
            double ref = s.ref[op], bar = s.bar[op];
            double rc = ref != 0 ? fabs(c.volume - ref) / fabs(ref) : fabs(c.volume);
            printf("%-24s %-12s %13.9g | %13.9g %9.2e %-7s %7.3f %7.3f |", s.name,
                   cb_bool_op_name((cb_bool_op)op), ref, c.volume, rc, verdict(&c, ref, bar),
                   c.t[0], c.t[1]);
            if (have_occt) {
                double ro = ref != 0 ? fabs(oc[op].volume - ref) / fabs(ref) : fabs(oc[op].volume);
                printf(" %13.9g %9.2e %-7s %7.3f %7.2f", oc[op].volume, ro,
                       verdict(oc + op, ref, bar), oc[op].t[0],
                       oc[op].t[0] > 0 ? c.t[1] / oc[op].t[0] : NAN);
            }
            printf("\n");
            if (json) {
                fprintf(json, "%s\n {\"scenario\": ", first ? "" : ",");
                cb_json_string(json, s.name);
                fprintf(json, ", \"op\": \"%s\", \"reference\": %.17g, \"bar\": %.3g, ",
                        cb_bool_op_name((cb_bool_op)op), ref, bar);
                json_side(json, "colibri", &c, ref, bar);
                if (have_occt) {
                    fputs(", ", json);
                    json_side(json, "occt", oc + op, ref, bar);
                }
                fputs("}", json);
                first = 0;
            }
            fflush(stdout);
        }
        remove(pa);
        remove(pb);
        cb_model_scenario_clear(&s);
    }
    if (json) {
        fputs("\n]\n", json);
        fclose(json);
    }
    rmdir(dir);
    return 0;
}
