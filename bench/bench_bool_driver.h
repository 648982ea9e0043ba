/* bench_bool_driver.h — the Boolean benchmarks beside Open CASCADE (bench_bool: the cases of the
 * Booleans issue; bench_scenarios: the shipped scenarios) are one program over two suites of
 * cases. For each case and each of union, intersection and A - B: the median, least and largest
 * time of RUNS runs of cb_bool_run on 1 and 2 threads with its phases (intersection,
 * splitting, sewing), the peak resident memory, the result's validity, faces and B-rep volume
 * against the case's reference within its bar; and, when the path of the OCCT comparator
 * (occt_bool, built by scripts/setup-bench) is given, the same figures from
 * BRepAlgoAPI_Fuse / Common / Cut (parallel mode) on the same solids written as STEP, and the
 * time ratio. A table on stdout, optionally a JSON file.
 *
 * Peak memory: ru_maxrss is a high-water mark of a whole process, so every case runs in a fresh
 * process (the program started again with --case, or occt_bool with one operation) and its
 * figure is read by wait4 when it ends (bench_spawn.h). Beside each figure, the peak of a
 * process that only builds the case (Colibri) or only reads the two STEP files (OCCT): the
 * operation's own share is the difference.
 *
 * Usage: PROG [RUNS [OCCT_BOOL [JSON_OUT [SHARED]]]]
 *   RUNS default 3; "-" for no OCCT or no JSON; SHARED the directory holding models/
 *   (default ../shared).
 * Internal: PROG --case K OP RUNS SHARED   (OP -1: build case K only)
 *           PROG --step K DIR SHARED       (write its operands as DIR/case_K_{a,b}.step)
 * Header-only: every bench_*.c is a program of its own; define _DEFAULT_SOURCE (wait4) before
 * any include. */
#ifndef CB_BENCH_BOOL_DRIVER_H
#define CB_BENCH_BOOL_DRIVER_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bench/bench_spawn.h"
#include "bench/bench_stats.h"
#include "boolean/bool.h"
#include "brep/mass.h"
#include "io/json.h"
#include "io/step_write.h"
#include "models/models.h"

/* One side's figures for one case and operation. t[k]: median, min, max seconds on k + 1
 * threads (OCCT: its parallel mode, in t[0] only); phase[k]: Colibri's median seconds of the
 * intersection, splitting and sewing phases on k + 1 threads. peak, base: KiB of the case's
 * process and of a process that only loads the inputs; -1 when not measured. */
typedef struct {
    int done, valid, faces;
    double volume, t[2][3], phase[2][3];
    long peak, base;
    char msg[96];
} bool_side;

static inline void bool_side_init(bool_side *s)
{
    memset(s, 0, sizeof *s);
    s->volume = NAN;
    s->peak = s->base = -1;
}

/* In a case's own process: op of a and b RUNS times on 1 and on 2 threads (runs <= MAX_RUNS);
 * validity (cb_topo_validate), faces and B-rep volume of the last 2-thread result. */
static inline void bool_side_measure(bool_side *o, cb_bool_op op, const cb_topo_body *a,
                                     const cb_topo_body *b, int runs)
{
    bool_side_init(o);
    for (int th = 0; th < 2; th++) {
        double t[4][MAX_RUNS];
        cb_context ctx;
        cb_context_init(&ctx);
        ctx.threads = th + 1;
        for (int r = 0; r < runs; r++) {
            cb_topo_body *res = NULL;
            cb_bool_stats s;
            cb_error err;
            double t0 = now();
            cb_status st = cb_bool_run(&res, &s, op, a, b, NULL, &ctx, &err);
            t[0][r] = now() - t0;
            t[1][r] = s.time_ssi;
            t[2][r] = s.time_split;
            t[3][r] = s.time_build;
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
                o->faces = res->n_faces;
                o->done = 1;
            }
            cb_topo_body_free(res);
        }
        stats3(o->t[th], t[0], runs);
        for (int p = 0; p < 3; p++) {
            double range[3];
            stats3(range, t[p + 1], runs);
            o->phase[th][p] = range[0];
        }
    }
}

/* A measured side as two lines for the parent (bool_side_parse reads them back). */
static inline void bool_side_print(const bool_side *o)
{
    printf("%d %d %d %.17g", o->done, o->valid, o->faces, o->volume);
    for (int th = 0; th < 2; th++)
        printf(" %.9f %.9f %.9f %.9f %.9f %.9f", o->t[th][0], o->t[th][1], o->t[th][2],
               o->phase[th][0], o->phase[th][1], o->phase[th][2]);
    printf("\n%s\n", o->msg);
}

/* Reads bool_side_print's lines from text into o (peak and base untouched); 0 when they are
 * not there. */
static inline int bool_side_parse(bool_side *o, const char *text)
{
    double *t0 = o->t[0], *t1 = o->t[1], *p0 = o->phase[0], *p1 = o->phase[1];
    if (sscanf(text, "%d %d %d %lf %lf %lf %lf %lf %lf %lf %lf %lf %lf %lf %lf %lf", &o->done,
               &o->valid, &o->faces, &o->volume, t0, t0 + 1, t0 + 2, p0, p0 + 1, p0 + 2, t1,
               t1 + 1, t1 + 2, p1, p1 + 1, p1 + 2) != 16)
        return 0;
    const char *l2 = strchr(text, '\n');
    if (l2)
        snprintf(o->msg, sizeof o->msg, "%.*s", (int)strcspn(l2 + 1, "\n"), l2 + 1);
    return 1;
}

/* spawn_read's output as a string (at most cap - 1 bytes). */
static inline int spawn_text(char *out, size_t cap, char *const argv[], long *peak_kib)
{
    size_t got;
    int rc = spawn_read(out, cap - 1, &got, argv, peak_kib);
    out[got] = 0;
    return rc;
}

/* Open CASCADE's union, intersection and A - B of the STEP files a and b through the
 * comparator occt (RUNS runs each), one process per operation and one that only reads the
 * files (o[k].base); o[k].done = 0 with a message when it could not run or OCCT reports an
 * error. */
static inline void occt_bool_run(bool_side o[3], const char *occt, const char *a, const char *b,
                                 int runs)
{
    static const char *const names[3] = {"union", "intersection", "difference"};
    char out[1024], rs[16], opname[16], occt_path[1024], pa[1024], pb[1024];
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
        bool_side_init(o + k);
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
        o[k].faces = faces;
        o[k].volume = error ? NAN : v;
        for (int q = 0; q < 3; q++)
            o[k].t[0][q] = 1e-3 * ms[q];
        if (error)
            snprintf(o[k].msg, sizeof o[k].msg, "OCCT reports an error");
    }
}

/* fails (no result), invalid (the validator rejects it), ok / WRONG (volume within / outside
 * bar of ref) or, where there is no reference (ref NaN), valid. */
static inline const char *bool_verdict(const bool_side *o, double ref, double bar)
{
    if (!o->done)
        return "fails";
    if (!o->valid)
        return "invalid";
    if (isnan(ref))
        return "valid";
    return fabs(o->volume - ref) <= bar ? "ok" : "WRONG";
}

/* |v - ref| relative to |ref|, absolute where ref is 0. */
static inline double rel_err(double v, double ref)
{
    return ref != 0 ? fabs(v - ref) / fabs(ref) : fabs(v);
}

static inline double mib(long kib)
{
    return kib < 0 ? NAN : kib / 1024.0;
}

static inline void json_times(FILE *f, const double t[3])
{
    fprintf(f, "{\"median\": %.6f, \"min\": %.6f, \"max\": %.6f}", t[0], t[1], t[2]);
}

static inline void json_number(FILE *f, double v)
{
    if (isfinite(v))
        fprintf(f, "%.17g", v);
    else
        fputs("null", f);
}

/* "key": {...} for one side; extra, when not NULL, is more members (JSON text starting with
 * ", ") put before the closing brace. */
static inline void json_bool_side(FILE *f, const char *key, const bool_side *o, double ref,
                                  double bar, int occt, const char *extra)
{
    fprintf(f, "\"%s\": {\"verdict\": \"%s\", \"valid\": %s, \"faces\": %d, \"volume\": ", key,
            bool_verdict(o, ref, bar), o->valid ? "true" : "false", o->faces);
    json_number(f, o->volume);
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
    if (extra)
        fputs(extra, f);
    fputs("}", f);
}

/* ---------------------------------------------------------------- suites ------------------- */

/* One case: its name (no newline), its operands (owned by the case) and the references of
 * A u B, A n B and A - B with their absolute bars (NaN: no reference). */
typedef struct {
    char name[64];
    cb_topo_body *a, *b;
    double ref[3], bar[3];
} bench_bool_case;

/* A suite: its cases 0 .. n_cases - 1, built one at a time in the process that runs them. */
typedef struct {
    const char *prog;  /* the program's name, for messages */
    const char *title; /* heading of the volume table */
    int n_cases;
    /* Fills c (zeroed before) with case k; shared: the directory holding models/. */
    cb_status (*build)(bench_bool_case *c, int k, const char *shared, cb_error *err);
} bench_bool_suite;

/* Shipped scenario k (cb_model_scenario_load) as a case: its name, references and bars; its
 * operands move into c. */
static inline cb_status bench_bool_scenario_case(bench_bool_case *c, int k, cb_error *err)
{
    cb_model_scenario s;
    cb_status st = cb_model_scenario_load(&s, k, err);
    if (st)
        return st;
    snprintf(c->name, sizeof c->name, "%s", s.name);
    c->a = s.a;
    c->b = s.b;
    memcpy(c->ref, s.ref, sizeof c->ref);
    memcpy(c->bar, s.bar, sizeof c->bar);
    return CB_OK;
}

static inline void bench_bool_case_clear(bench_bool_case *c)
{
    cb_topo_body_free(c->a);
    cb_topo_body_free(c->b);
    c->a = c->b = NULL;
}

static inline cb_status bench_bool_case_build(const bench_bool_suite *s, bench_bool_case *c,
                                              int k, const char *shared, cb_error *err)
{
    memset(c, 0, sizeof *c);
    if (k < 0 || k >= s->n_cases)
        return cb_error_set(err, CB_ERR_INVALID, "no case %d (%d cases)", k, s->n_cases);
    cb_status st = s->build(c, k, shared, err);
    if (st)
        bench_bool_case_clear(c);
    return st;
}

/* --case K OP RUNS SHARED: builds case k and prints "REF0 REF1 REF2 BAR0 BAR1 BAR2" and its name
 * on a line of its own; with OP in 0 .. 2 runs that operation (bool_side_measure) and prints its
 * figures on the next two lines (bool_side_print). */
static inline int bench_bool_case_mode(const bench_bool_suite *s, int k, int op, int runs,
                                       const char *shared)
{
    static const cb_bool_op ops[3] = {CB_BOOL_UNION, CB_BOOL_INTERSECTION, CB_BOOL_DIFFERENCE};
    bench_bool_case c;
    cb_error err;
    if (bench_bool_case_build(s, &c, k, shared, &err)) {
        fprintf(stderr, "%s: case %d: %s\n", s->prog, k, err.msg);
        return 1;
    }
    printf("%.17g %.17g %.17g %.17g %.17g %.17g\n%s\n", c.ref[0], c.ref[1], c.ref[2], c.bar[0],
           c.bar[1], c.bar[2], c.name);
    if (op >= 0 && op < 3) {
        bool_side o;
        bool_side_measure(&o, ops[op], c.a, c.b, runs < 1 || runs > MAX_RUNS ? 1 : runs);
        bool_side_print(&o);
    }
    bench_bool_case_clear(&c);
    return 0;
}

/* --step K DIR SHARED: writes case k's operands as DIR/case_K_a.step and _b.step. */
static inline int bench_bool_step_mode(const bench_bool_suite *s, int k, const char *dir,
                                       const char *shared)
{
    bench_bool_case c;
    cb_error err;
    if (bench_bool_case_build(s, &c, k, shared, &err)) {
        fprintf(stderr, "%s: case %d: %s\n", s->prog, k, err.msg);
        return 1;
    }
    char pa[512], pb[512];
    snprintf(pa, sizeof pa, "%s/case_%d_a.step", dir, k);
    snprintf(pb, sizeof pb, "%s/case_%d_b.step", dir, k);
    int bad = cb_step_write(c.a, pa, c.name, &err) || cb_step_write(c.b, pb, c.name, &err);
    if (bad)
        fprintf(stderr, "%s: %s: %s\n", s->prog, c.name, err.msg);
    bench_bool_case_clear(&c);
    return bad;
}

/* ---------------------------------------------------------------- one case's row ----------- */

typedef struct {
    char name[64];
    double ref[3], bar[3];
    bool_side c[3], o[3];
    int have_occt;
} bench_bool_row;

/* Colibri's three operations on case k, each in its own process; 0 when it could not be
 * built. */
static inline int bench_bool_run_colibri(bench_bool_row *row, int k, int runs, const char *shared)
{
    char out[2048], ks[16], ops[16], rs[16], sh[1024];
    char *argv[] = {"/proc/self/exe", "--case", ks, ops, rs, sh, NULL};
    snprintf(ks, sizeof ks, "%d", k);
    snprintf(rs, sizeof rs, "%d", runs);
    snprintf(sh, sizeof sh, "%s", shared);
    snprintf(ops, sizeof ops, "-1");
    long base;
    const char *l2;
    if (spawn_text(out, sizeof out, argv, &base) != 0 ||
        sscanf(out, "%lf %lf %lf %lf %lf %lf", row->ref, row->ref + 1, row->ref + 2, row->bar,
               row->bar + 1, row->bar + 2) != 6 ||
        !(l2 = strchr(out, '\n')))
        return 0;
    snprintf(row->name, sizeof row->name, "%.*s", (int)strcspn(l2 + 1, "\n"), l2 + 1);
    for (int op = 0; op < 3; op++) {
        bool_side *c = row->c + op;
        bool_side_init(c);
        c->base = base;
        snprintf(ops, sizeof ops, "%d", op);
        int st = spawn_text(out, sizeof out, argv, &c->peak);
        const char *l3 = strchr(out, '\n');
        l3 = l3 ? strchr(l3 + 1, '\n') : NULL;
        if (st != 0 || !l3 || !bool_side_parse(c, l3 + 1)) {
            c->done = 0;
            snprintf(c->msg, sizeof c->msg, "the case's process failed (status %d)", st);
        }
    }
    return 1;
}

/* Case k written as STEP by a child (--step) and run through the comparator. */
static inline void bench_bool_run_occt(bench_bool_row *row, int k, int runs, const char *occt,
                                       const char *dir, const char *shared)
{
    char out[256], ks[16], dirs[512], sh[1024], pa[600], pb[600];
    char *argv[] = {"/proc/self/exe", "--step", ks, dirs, sh, NULL};
    snprintf(ks, sizeof ks, "%d", k);
    snprintf(dirs, sizeof dirs, "%s", dir);
    snprintf(sh, sizeof sh, "%s", shared);
    snprintf(pa, sizeof pa, "%s/case_%d_a.step", dir, k);
    snprintf(pb, sizeof pb, "%s/case_%d_b.step", dir, k);
    long peak;
    row->have_occt = spawn_text(out, sizeof out, argv, &peak) == 0;
    if (row->have_occt)
        occt_bool_run(row->o, occt, pa, pb, runs);
    remove(pa);
    remove(pb);
}

/* ---------------------------------------------------------------- output ------------------- */

/* Relative difference of the two sides' volumes (absolute where both are 0). */
static inline double bool_side_diff(const bool_side *c, const bool_side *o)
{
    double m = fmax(fabs(c->volume), fabs(o->volume));
    return m > 0 ? fabs(c->volume - o->volume) / m : fabs(c->volume - o->volume);
}

static inline void bench_bool_print(const bench_bool_suite *s, const bench_bool_row *rows, int n,
                                    int runs, int occt)
{
    printf("%s: volumes against the references (rel.err, absolute where the reference is 0; "
           "verdict ok within the bar, valid where there is no reference)\n",
           s->title);
    printf("%-27s %-12s %13s | %13s %5s %9s %-7s |", "case", "operation", "reference", "Colibri",
           "faces", "rel.err", "verdict");
    if (occt)
        printf(" %13s %5s %9s %-7s | %8s", "OCCT 7.6", "faces", "rel.err", "verdict", "C vs O");
    printf("\n");
    for (int k = 0; k < n; k++)
        for (int op = 0; op < 3; op++) {
            const bench_bool_row *r = rows + k;
            const bool_side *c = r->c + op, *o = r->o + op;
            printf("%-27s %-12s %13.10g | %13.10g %5d %9.2e %-7s |", r->name,
                   cb_bool_op_name((cb_bool_op)op), r->ref[op], c->volume, c->faces,
                   rel_err(c->volume, r->ref[op]), bool_verdict(c, r->ref[op], r->bar[op]));
            if (r->have_occt)
                printf(" %13.10g %5d %9.2e %-7s | %8.1e", o->volume, o->faces,
                       rel_err(o->volume, r->ref[op]), bool_verdict(o, r->ref[op], r->bar[op]),
                       bool_side_diff(c, o));
            printf("\n");
        }
    printf("\nTime in seconds, median of %d run%s (in brackets the least and largest total), each "
           "case in a fresh process; Colibri's phases: intersection, splitting, sewing; peak "
           "resident memory of that process in MiB (in brackets: of one that only builds or "
           "reads the inputs); C2/O: Colibri's 2-thread median over OCCT's\n",
           runs, runs == 1 ? "" : "s");
    printf("%-27s %-12s | %-44s | %-30s %-14s |", "case", "operation",
           "Colibri 1 thread: ssi split sew total", "2 threads: ssi total", "peak MiB");
    if (occt)
        printf(" %-22s %-14s %6s", "OCCT (parallel)", "peak MiB", "C2/O");
    printf("\n");
    for (int k = 0; k < n; k++)
        for (int op = 0; op < 3; op++) {
            const bench_bool_row *r = rows + k;
            const bool_side *c = r->c + op, *o = r->o + op;
            printf("%-27s %-12s | %6.3f %6.3f %6.3f %6.3f [%6.3f %6.3f] | %6.3f %6.3f [%6.3f "
                   "%6.3f] %6.1f (%5.1f) |",
                   r->name, cb_bool_op_name((cb_bool_op)op), c->phase[0][0], c->phase[0][1],
                   c->phase[0][2], c->t[0][0], c->t[0][1], c->t[0][2], c->phase[1][0],
                   c->t[1][0], c->t[1][1], c->t[1][2], mib(c->peak), mib(c->base));
            if (r->have_occt)
                printf(" %6.3f [%6.3f %6.3f] %6.1f (%5.1f) %6.2f", o->t[0][0], o->t[0][1],
                       o->t[0][2], mib(o->peak), mib(o->base),
                       o->t[0][0] > 0 ? c->t[1][0] / o->t[0][0] : NAN);
            printf("\n");
        }
    for (int k = 0; k < n; k++)
        for (int op = 0; op < 3; op++) {
            const bench_bool_row *r = rows + k;
            if (!r->c[op].done && r->c[op].msg[0])
                printf("%s %s, Colibri: %s\n", r->name, cb_bool_op_name((cb_bool_op)op),
                       r->c[op].msg);
            if (r->have_occt && !r->o[op].done && r->o[op].msg[0])
                printf("%s %s, OCCT: %s\n", r->name, cb_bool_op_name((cb_bool_op)op),
                       r->o[op].msg);
        }
}

static inline void bench_bool_json(FILE *json, const bench_bool_row *rows, int n, int runs)
{
    fprintf(json, "{\"runs\": %d, \"cases\": [", runs);
    int first = 1;
    for (int k = 0; k < n; k++)
        for (int op = 0; op < 3; op++) {
            const bench_bool_row *r = rows + k;
            const bool_side *c = r->c + op;
            fprintf(json, "%s\n {\"case\": ", first ? "" : ",");
            cb_json_string(json, r->name);
            fprintf(json, ", \"op\": \"%s\", \"reference\": ", cb_bool_op_name((cb_bool_op)op));
            json_number(json, r->ref[op]);
            fputs(", \"bar\": ", json);
            json_number(json, r->bar[op]);
            fputs(", ", json);
            char phases[256];
            snprintf(phases, sizeof phases,
                     ", \"phases_median_s\": {\"threads_1\": {\"ssi\": %.6f, \"split\": %.6f, "
                     "\"sew\": %.6f}, \"threads_2\": {\"ssi\": %.6f, \"split\": %.6f, \"sew\": "
                     "%.6f}}",
                     c->phase[0][0], c->phase[0][1], c->phase[0][2], c->phase[1][0],
                     c->phase[1][1], c->phase[1][2]);
            json_bool_side(json, "colibri", c, r->ref[op], r->bar[op], 0, phases);
            if (r->have_occt) {
                fputs(", ", json);
                json_bool_side(json, "occt", r->o + op, r->ref[op], r->bar[op], 1, NULL);
            }
            fputs("}", json);
            first = 0;
        }
    fputs("\n]}\n", json);
}

/* The program: the internal modes, or every case of the suite with the table (and JSON). */
static inline int bench_bool_main(const bench_bool_suite *s, int argc, char **argv)
{
    if (argc == 6 && !strcmp(argv[1], "--case"))
        return bench_bool_case_mode(s, atoi(argv[2]), atoi(argv[3]), atoi(argv[4]), argv[5]);
    if (argc == 5 && !strcmp(argv[1], "--step"))
        return bench_bool_step_mode(s, atoi(argv[2]), argv[3], argv[4]);
    int runs = argc > 1 ? atoi(argv[1]) : 3;
    if (runs < 1 || runs > MAX_RUNS)
        runs = 3;
    const char *occt = argc > 2 && strcmp(argv[2], "-") ? argv[2] : NULL;
    const char *shared = argc > 4 ? argv[4] : "../shared";
    if (occt && access(occt, X_OK)) {
        fprintf(stderr, "%s: %s is not an executable: no OCCT columns\n", s->prog, occt);
        occt = NULL;
    }
    FILE *json = NULL;
    if (argc > 3 && strcmp(argv[3], "-") && !(json = fopen(argv[3], "w"))) {
        fprintf(stderr, "%s: cannot write %s\n", s->prog, argv[3]);
        return 1;
    }
    char dir[] = "/tmp/colibri_bench_XXXXXX"; /* mkdtemp's template: it replaces the Xs */
    if (occt && !mkdtemp(dir)) {
        fprintf(stderr, "%s: cannot make a temporary directory\n", s->prog);
        if (json)
            fclose(json);
        return 1;
    }
    /* This process only starts the others and keeps their figures: nothing heavy runs here. */
    bench_bool_row *rows = calloc((size_t)s->n_cases, sizeof *rows);
    int got = 0, status = 0;
    for (int k = 0; rows && k < s->n_cases; k++) {
        bench_bool_row *row = rows + got;
        fprintf(stderr, "%s: case %d of %d\r", s->prog, k + 1, s->n_cases);
        if (!bench_bool_run_colibri(row, k, runs, shared)) {
            fprintf(stderr, "%s: case %d could not be built\n", s->prog, k);
            status = 1;
            continue;
        }
        if (occt)
            bench_bool_run_occt(row, k, runs, occt, dir, shared);
        got++;
    }
    fprintf(stderr, "%60s\r", "");
    if (rows)
        bench_bool_print(s, rows, got, runs, occt != NULL);
    if (json) {
        if (rows)
            bench_bool_json(json, rows, got, runs);
        fclose(json);
    }
    if (occt)
        rmdir(dir);
    free(rows);
    return rows ? status : 1;
}

#endif
