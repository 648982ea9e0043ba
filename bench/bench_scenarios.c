/* The shipped Boolean scenarios (cb_model_scenario: the two hummingbirds, the Cardan-joint
 * scenarios analytic and B-spline, the bracket), Colibri beside Open CASCADE: for each scenario
 * and each of union, intersection and A - B, the median, least and largest time of RUNS runs of
 * cb_bool_run on 1 and 2 threads, the peak resident memory, the result's validity and B-rep
 * volume against the reference within its error bar; and, when the path of the OCCT comparator
 * (occt_bool, built by scripts/setup-bench) is given, the same figures from Open CASCADE on the
 * same solids written as STEP, and the time ratio.
 *
 * Peak memory: ru_maxrss is a high-water mark of a whole process, so every case runs in a fresh
 * process (this program started again with --case, or occt_bool with one operation) and its
 * figure is read by wait4 when it ends (bench_spawn.h). Beside each figure, the peak of a
 * process that only builds the scenario (Colibri) or only reads the two STEP files (OCCT): the
 * operation's own share is the difference.
 *
 * Usage: bench_scenarios [RUNS [OCCT_BOOL [JSON_OUT]]]   (RUNS default 3; "-" for no OCCT)
 * Internal: bench_scenarios --case K OP RUNS   (OP -1: build scenario K only)
 *           bench_scenarios --step K DIR       (write its two operands as DIR/NAME_{a,b}.step) */
#define _DEFAULT_SOURCE /* wait4: the rusage of one child, not of all of them */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "boolean/bool.h"
#include "brep/mass.h"
#include "bench/bench_spawn.h"
#include "bench/bench_stats.h"
#include "io/json.h"
#include "io/step_write.h"
#include "models/models.h"

/* One side's figures for one case. t[k]: median, min, max seconds on k + 1 threads (OCCT: its
 * parallel mode, in t[0] only). peak, base: KiB of the case's process and of the process that
 * only loads the inputs; -1 when not measured. */
typedef struct {
    int done, valid;
    double volume, t[2][3];
    long peak, base;
    char msg[96];
} side;

/* ---------------------------------------------------------------- children ----------------- */

/* spawn_read's output as a string (at most cap - 1 bytes). */
static int spawn_text(char *out, size_t cap, char *const argv[], long *peak_kib)
{
    size_t got;
    int rc = spawn_read(out, cap - 1, &got, argv, peak_kib);
    out[got] = 0;
    return rc;
}

/* --case K OP RUNS: builds scenario k and prints "NAME REF0 REF1 REF2 BAR0 BAR1 BAR2"; with
 * OP >= 0 runs that operation RUNS times on 1 and on 2 threads and prints
 * "DONE VALID VOLUME T1MED T1MIN T1MAX T2MED T2MIN T2MAX" and the error message, if any, on a
 * third line. Validity and volume are those of the last 2-thread run. */
static int case_mode(int k, int op, int runs)
{
    static const cb_bool_op ops[3] = {CB_BOOL_UNION, CB_BOOL_INTERSECTION, CB_BOOL_DIFFERENCE};
    cb_model_scenario s;
    cb_error err;
    if (cb_model_scenario_load(&s, k, &err)) {
        fprintf(stderr, "bench_scenarios: scenario %d: %s\n", k, err.msg);
        return 1;
    }
    printf("%s %.17g %.17g %.17g %.17g %.17g %.17g\n", s.name, s.ref[0], s.ref[1], s.ref[2],
           s.bar[0], s.bar[1], s.bar[2]);
    if (op >= 0) {
        side o;
        memset(&o, 0, sizeof o);
        o.volume = NAN;
        for (int th = 0; th < 2; th++) {
            double t[MAX_RUNS];
            cb_context ctx;
            cb_context_init(&ctx);
            ctx.threads = th + 1;
            for (int r = 0; r < runs; r++) {
                cb_topo_body *res = NULL;
                double t0 = now();
                cb_status st = cb_bool_run(&res, NULL, ops[op], s.a, s.b, NULL, &ctx, &err);
                t[r] = now() - t0;
                if (st) {
                    snprintf(o.msg, sizeof o.msg, "%.90s", err.msg);
                    o.done = 0;
                } else if (th == 1 && r == runs - 1) {
                    cb_topo_report rep;
                    cb_topo_report_init(&rep);
                    o.valid = !cb_topo_validate(&rep, res, res->tol, 9, &err) && rep.n == 0;
                    cb_topo_report_clear(&rep);
                    cb_mass_props m;
                    if (!cb_mass_body(&m, res, CB_MASS_REL_TOL, NULL, &err))
                        o.volume = m.volume;
                    o.done = 1;
                }
                cb_topo_body_free(res);
            }
            stats3(o.t[th], t, runs);
        }
        printf("%d %d %.17g %.9f %.9f %.9f %.9f %.9f %.9f\n%s\n", o.done, o.valid, o.volume,
               o.t[0][0], o.t[0][1], o.t[0][2], o.t[1][0], o.t[1][1], o.t[1][2], o.msg);
    }
    cb_model_scenario_clear(&s);
    return 0;
}

/* --step K DIR: writes scenario k's operands for the OCCT comparator. */
static int step_mode(int k, const char *dir)
{
    cb_model_scenario s;
    cb_error err;
    if (cb_model_scenario_load(&s, k, &err)) {
        fprintf(stderr, "bench_scenarios: scenario %d: %s\n", k, err.msg);
        return 1;
    }
    char pa[512], pb[512];
    snprintf(pa, sizeof pa, "%s/%s_a.step", dir, s.name);
    snprintf(pb, sizeof pb, "%s/%s_b.step", dir, s.name);
    int bad = cb_step_write(s.a, pa, s.name, &err) || cb_step_write(s.b, pb, s.name, &err);
    if (bad)
        fprintf(stderr, "bench_scenarios: %s: %s\n", s.name, err.msg);
    cb_model_scenario_clear(&s);
    return bad;
}

/* ---------------------------------------------------------------- one scenario ------------- */

typedef struct {
    char name[64];
    double ref[3], bar[3];
    side c[3], o[3];
    int have_occt;
} scenario_row;

/* Colibri's three operations on scenario k, each in its own process; 0 when it could not be
 * built. */
static int run_colibri(scenario_row *row, int k, int runs)
{
    char out[1024], ks[16], ops[16], rs[16];
    char *argv[] = {"/proc/self/exe", "--case", ks, ops, rs, NULL};
    snprintf(ks, sizeof ks, "%d", k);
    snprintf(rs, sizeof rs, "%d", runs);
    snprintf(ops, sizeof ops, "-1");
    long base;
    if (spawn_text(out, sizeof out, argv, &base) != 0 ||
        sscanf(out, "%63s %lf %lf %lf %lf %lf %lf", row->name, row->ref, row->ref + 1,
               row->ref + 2, row->bar, row->bar + 1, row->bar + 2) != 7)
        return 0;
    for (int op = 0; op < 3; op++) {
        side *c = row->c + op;
        memset(c, 0, sizeof *c);
        c->volume = NAN;
        c->base = base;
        snprintf(ops, sizeof ops, "%d", op);
        int st = spawn_text(out, sizeof out, argv, &c->peak);
        const char *l2 = strchr(out, '\n');
        if (st != 0 || !l2 ||
            sscanf(l2 + 1, "%d %d %lf %lf %lf %lf %lf %lf %lf", &c->done, &c->valid,
                   &c->volume, c->t[0], c->t[0] + 1, c->t[0] + 2, c->t[1], c->t[1] + 1,
                   c->t[1] + 2) != 9) {
            c->done = 0;
            snprintf(c->msg, sizeof c->msg, "the case's process failed (status %d)", st);
            continue;
        }
        const char *l3 = strchr(l2 + 1, '\n');
        if (l3)
            snprintf(c->msg, sizeof c->msg, "%.*s", (int)strcspn(l3 + 1, "\n"), l3 + 1);
    }
    return 1;
}

/* Open CASCADE through the comparator on the STEP files, one process per operation;
 * o[k].done = 0 when it could not run. */
static void run_occt(side o[3], const char *occt, const char *a, const char *b, int runs)
{
    static const char *const names[3] = {"union", "intersection", "difference"};
    char out[1024], rs[16], opname[16], occt_path[1024], pa[512], pb[512];
    snprintf(rs, sizeof rs, "%d", runs);
    snprintf(occt_path, sizeof occt_path, "%s", occt);
    snprintf(pa, sizeof pa, "%s", a);
    snprintf(pb, sizeof pb, "%s", b);
    char *argv[] = {occt_path, rs, pa, pb, opname, NULL};
    long base;
    snprintf(opname, sizeof opname, "none");
    if (spawn_text(out, sizeof out, argv, &base) != 0)
        base = -1;
    for (int k = 0; k < 3; k++) {
        memset(o + k, 0, sizeof *o);
        o[k].volume = NAN;
        o[k].base = base;
        snprintf(opname, sizeof opname, "%s", names[k]);
        char op[32];
        int error, valid, faces;
        double ms[3], v;
        if (spawn_text(out, sizeof out, argv, &o[k].peak) != 0 ||
            sscanf(out, "%31s %lf %lf %lf %d %d %d %lf", op, ms, ms + 1, ms + 2, &error, &valid,
                   &faces, &v) != 8) {
            snprintf(o[k].msg, sizeof o[k].msg, "the comparator failed");
            continue;
        }
        o[k].done = !error;
        o[k].valid = valid;
        o[k].volume = error ? NAN : v;
        for (int q = 0; q < 3; q++)
            o[k].t[0][q] = 1e-3 * ms[q];
        if (error)
            snprintf(o[k].msg, sizeof o[k].msg, "OCCT reports an error");
    }
}

/* ---------------------------------------------------------------- output ------------------- */

static const char *verdict(const side *o, double ref, double bar)
{
    if (!o->done)
        return "fails";
    if (!o->valid)
        return "invalid";
    return fabs(o->volume - ref) <= bar ? "ok" : "WRONG";
}

static double rel_err(double v, double ref)
{
    return ref != 0 ? fabs(v - ref) / fabs(ref) : fabs(v);
}

static double mib(long kib)
{
    return kib < 0 ? NAN : kib / 1024.0;
}

static void json_times(FILE *f, const double t[3])
{
    fprintf(f, "{\"median\": %.6f, \"min\": %.6f, \"max\": %.6f}", t[0], t[1], t[2]);
}

static void json_side(FILE *f, const char *key, const side *o, double ref, double bar, int occt)
{
    fprintf(f, "\"%s\": {\"verdict\": \"%s\", \"valid\": %s, \"volume\": ", key,
            verdict(o, ref, bar), o->valid ? "true" : "false");
    if (isfinite(o->volume))
        fprintf(f, "%.17g", o->volume);
    else
        fputs("null", f);
    fputs(", \"time_s\": ", f);
    if (occt) {
        json_times(f, o->t[0]);
    } else {
        fputs("{\"threads_1\": ", f);
        json_times(f, o->t[0]);
        fputs(", \"threads_2\": ", f);
        json_times(f, o->t[1]);
        fputs("}", f);
    }
    fprintf(f, ", \"peak_kib\": %ld, \"load_peak_kib\": %ld", o->peak, o->base);
    if (o->msg[0]) {
        fputs(", \"message\": ", f);
        cb_json_string(f, o->msg);
    }
    fputs("}", f);
}

static void print_tables(const scenario_row *rows, int n, int runs, int occt)
{
    printf("Booleans on the shipped scenarios: volumes against the references (rel.err; verdict "
           "ok within the bar)\n");
    printf("%-24s %-12s %13s | %13s %9s %-7s |", "scenario", "operation", "reference", "Colibri",
           "rel.err", "verdict");
    if (occt)
        printf(" %13s %9s %-7s", "OCCT 7.6", "rel.err", "verdict");
    printf("\n");
    for (int k = 0; k < n; k++)
        for (int op = 0; op < 3; op++) {
            const scenario_row *r = rows + k;
            const side *c = r->c + op, *o = r->o + op;
            printf("%-24s %-12s %13.9g | %13.9g %9.2e %-7s |", r->name,
                   cb_bool_op_name((cb_bool_op)op), r->ref[op], c->volume,
                   rel_err(c->volume, r->ref[op]), verdict(c, r->ref[op], r->bar[op]));
            if (r->have_occt)
                printf(" %13.9g %9.2e %-7s", o->volume, rel_err(o->volume, r->ref[op]),
                       verdict(o, r->ref[op], r->bar[op]));
            printf("\n");
        }
    printf("\nTime in seconds, median [min max] of %d run%s, each case in a fresh process; peak "
           "resident memory of that process in MiB (in brackets: of one that only loads the "
           "inputs)\n",
           runs, runs == 1 ? "" : "s");
    printf("%-24s %-12s | %-22s %-22s %-14s |", "scenario", "operation", "Colibri 1 thread",
           "2 threads", "peak MiB");
    if (occt)
        printf(" %-22s %-14s %6s", "OCCT (parallel)", "peak MiB", "C2/O");
    printf("\n");
    for (int k = 0; k < n; k++)
        for (int op = 0; op < 3; op++) {
            const scenario_row *r = rows + k;
            const side *c = r->c + op, *o = r->o + op;
            printf("%-24s %-12s |", r->name, cb_bool_op_name((cb_bool_op)op));
            for (int th = 0; th < 2; th++)
                printf(" %6.3f [%6.3f %6.3f]", c->t[th][0], c->t[th][1], c->t[th][2]);
            printf(" %6.1f (%5.1f) |", mib(c->peak), mib(c->base));
            if (r->have_occt)
                printf(" %6.3f [%6.3f %6.3f] %6.1f (%5.1f) %6.2f", o->t[0][0], o->t[0][1],
                       o->t[0][2], mib(o->peak), mib(o->base),
                       o->t[0][0] > 0 ? c->t[1][0] / o->t[0][0] : NAN);
            printf("\n");
        }
    for (int k = 0; k < n; k++)
        for (int op = 0; op < 3; op++) {
            const scenario_row *r = rows + k;
            if (!r->c[op].done && r->c[op].msg[0])
                printf("%s %s, Colibri: %s\n", r->name, cb_bool_op_name((cb_bool_op)op),
                       r->c[op].msg);
            if (r->have_occt && !r->o[op].done && r->o[op].msg[0])
                printf("%s %s, OCCT: %s\n", r->name, cb_bool_op_name((cb_bool_op)op),
                       r->o[op].msg);
        }
}

static void write_json(FILE *json, const scenario_row *rows, int n, int runs)
{
    fprintf(json, "{\"runs\": %d, \"cases\": [", runs);
    int first = 1;
    for (int k = 0; k < n; k++)
        for (int op = 0; op < 3; op++) {
            const scenario_row *r = rows + k;
            fprintf(json, "%s\n {\"scenario\": ", first ? "" : ",");
            cb_json_string(json, r->name);
            fprintf(json, ", \"op\": \"%s\", \"reference\": %.17g, \"bar\": %.3g, ",
                    cb_bool_op_name((cb_bool_op)op), r->ref[op], r->bar[op]);
            json_side(json, "colibri", r->c + op, r->ref[op], r->bar[op], 0);
            if (r->have_occt) {
                fputs(", ", json);
                json_side(json, "occt", r->o + op, r->ref[op], r->bar[op], 1);
            }
            fputs("}", json);
            first = 0;
        }
    fputs("\n]}\n", json);
}

int main(int argc, char **argv)
{
    if (argc == 5 && !strcmp(argv[1], "--case"))
        return case_mode(atoi(argv[2]), atoi(argv[3]), atoi(argv[4]));
    if (argc == 4 && !strcmp(argv[1], "--step"))
        return step_mode(atoi(argv[2]), argv[3]);
    int runs = argc > 1 ? atoi(argv[1]) : 3;
    if (runs < 1 || runs > MAX_RUNS)
        runs = 3;
    const char *occt = argc > 2 && strcmp(argv[2], "-") ? argv[2] : NULL;
    if (occt && access(occt, X_OK))
        occt = NULL;
    FILE *json = NULL;
    if (argc > 3 && !(json = fopen(argv[3], "w"))) {
        fprintf(stderr, "bench_scenarios: cannot write %s\n", argv[3]);
        return 1;
    }
    char dir[] = "/tmp/colibri_bench_XXXXXX";
    if (!mkdtemp(dir)) {
        fprintf(stderr, "bench_scenarios: cannot make a temporary directory\n");
        return 1;
    }
    /* This process only starts the others and keeps their figures: nothing heavy runs here. */
    int n = cb_model_scenario_count(), got = 0, status = 0;
    scenario_row *rows = calloc((size_t)n, sizeof *rows);
    for (int k = 0; k < n; k++) {
        scenario_row *row = rows + got;
        fprintf(stderr, "bench_scenarios: scenario %d of %d\r", k + 1, n);
        if (!run_colibri(row, k, runs)) {
            fprintf(stderr, "bench_scenarios: scenario %d could not be built\n", k);
            status = 1;
            continue;
        }
        if (occt) {
            char out[256], ks[16], dirs[sizeof dir];
            char *sargv[] = {"/proc/self/exe", "--step", ks, dirs, NULL};
            snprintf(ks, sizeof ks, "%d", k);
            snprintf(dirs, sizeof dirs, "%s", dir);
            long peak;
            char pa[512], pb[512];
            snprintf(pa, sizeof pa, "%s/%s_a.step", dir, row->name);
            snprintf(pb, sizeof pb, "%s/%s_b.step", dir, row->name);
            row->have_occt = spawn_text(out, sizeof out, sargv, &peak) == 0;
            if (row->have_occt)
                run_occt(row->o, occt, pa, pb, runs);
            remove(pa);
            remove(pb);
        }
        got++;
    }
    fprintf(stderr, "%40s\r", "");
    print_tables(rows, got, runs, occt != NULL);
    if (json) {
        write_json(json, rows, got, runs);
        fclose(json);
    }
    free(rows);
    rmdir(dir);
    return status;
}
