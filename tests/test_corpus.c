/* test_corpus — the committed subset of the randomized differential corpus (tests/corpus/,
 * written by Open CASCADE's STEP writer through bench/corpus/occt_corpus.cpp --subset), replayed
 * in-process through the library without OCCT.
 *
 * Each case's STEP files are read (cb_step_read) and each of union, intersection and A - B run
 * as `colibri bool` runs it: cb_bool_run, then the CLI's own checks of the result
 * (cb_cli_result_check, cli/result.c, compiled into this test: validation, B-rep volume,
 * tessellation, CGAL mesh checks with touching told from crossing). Only the CLI's check that an
 * operand does not cross itself is left out (OCCT's primitives do not). The outcome is scored by
 * the corpus's rules (bench/corpus/corpus.h, the same code as bench_corpus): pass, refused,
 * WRONG, crash, timeout; each run has a time limit, enforced by a watchdog thread that cancels
 * the run's context (cancellation is looked at between face pairs, face splits and faces of the
 * checks, so a run may overshoot by one such step).
 *
 * tests/corpus/expected.txt says for every case and operation what Colibri does today: `pass`,
 * or `known VERDICT: reason`. The test FAILS on any WRONG (or a crash, which ends it), on a
 * `pass` run that does not pass, and on a run the file does not list; it only PRINTS a `known`
 * run that now passes (update the file) or whose verdict changed.
 *
 * Time limits: 40 s per run in an optimised build (the slowest run takes 5.5 s on a quiet
 * 2-core machine, 3 times that under load). Under AddressSanitizer (2-4 times slower; the whole
 * subset took 100 s of CPU and up to 10 minutes of wall time beside the rest of the suite on a
 * loaded machine) a deterministic stride: every second case of cases.json (the cases are
 * grouped by configuration, 4 each, so every configuration keeps 2), with 80 s per run; a
 * `pass` run stopped at that limit is printed, not failed (it is a pass in Release; the
 * sanitizer build is there to find memory errors, which it does on the runs that end).
 *
 * Usage: test_corpus [--update [FILE]] [--only SUBSTR] [--verbose]
 *   --update writes the expectations seen in this run (to FILE, default the source tree's
 *   tests/corpus/expected.txt) and does not fail on differences from the old file; see
 *   tests/README.md. COLIBRI_SOURCE (set by ctest) locates tests/corpus. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench/corpus/corpus.h"
#include "boolean/bool.h"
#include "brep/mesh.h"
#include "cli/result.h"
#include "io/step.h"
#include "check.h"

#if defined(__SANITIZE_ADDRESS__)
#define CORPUS_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define CORPUS_ASAN 1
#endif
#endif
#ifndef CORPUS_ASAN
#define CORPUS_ASAN 0
#endif

/* Seconds per run (one case, one operation); under the sanitizer, every STRIDE-th case only. */
static const double LIMIT_S = CORPUS_ASAN ? 80 : 40;
static const int STRIDE = CORPUS_ASAN ? 2 : 1;

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* ---------------------------------------------------------------- the watchdog ------------- */

typedef struct {
    cb_context *ctx;
    double limit;
    int done;
    pthread_mutex_t m;
    pthread_cond_t cv;
} watchdog;

static void *watch(void *p)
{
    watchdog *w = p;
    struct timespec until;
    clock_gettime(CLOCK_REALTIME, &until);
    double s = floor(w->limit);
    until.tv_sec += (time_t)s;
    until.tv_nsec += (long)((w->limit - s) * 1e9);
    if (until.tv_nsec >= 1000000000L) {
        until.tv_sec++;
        until.tv_nsec -= 1000000000L;
    }
    pthread_mutex_lock(&w->m);
    int rc = 0;
    while (!w->done && rc != ETIMEDOUT)
        rc = pthread_cond_timedwait(&w->cv, &w->m, &until);
    if (!w->done)
        cb_context_cancel(w->ctx);
    pthread_mutex_unlock(&w->m);
    return NULL;
}

/* ---------------------------------------------------------------- one run ------------------ */

static void run_op(corpus_outcome *o, const cb_topo_body *a, const cb_topo_body *b, int op)
{
    static const cb_bool_op ops[3] = {CB_BOOL_UNION, CB_BOOL_INTERSECTION, CB_BOOL_DIFFERENCE};
    corpus_outcome_init(o);
    cb_context ctx;
    cb_context_init(&ctx);
    ctx.threads = 1; /* ctest runs two tests at once on this kind of machine */
    watchdog w = {&ctx, LIMIT_S, 0, PTHREAD_MUTEX_INITIALIZER, PTHREAD_COND_INITIALIZER};
    pthread_t th;
    int watching = pthread_create(&th, NULL, watch, &w) == 0;
    double t0 = now_s();
    cb_topo_body *res = NULL;
    cb_error err;
    cb_error_clear(&err);
    cb_status st = cb_bool_run(&res, NULL, ops[op], a, b, NULL, &ctx, &err);
    if (st) {
        snprintf(o->message, sizeof o->message, "%.500s", err.msg);
    } else {
        cb_mesh_t mesh;
        cb_mesh_init(mesh);
        cb_cli_result r;
        cb_cli_result_check(&r, res, mesh, &ctx);
        cb_mesh_clear(mesh);
        o->reported_ok = r.valid && r.mesh_ok;
        snprintf(o->message, sizeof o->message, "%.500s", r.message);
        o->valid = r.valid;
        o->mesh_checked = r.mesh_done;
        o->closed = r.closed;
        o->clean = r.manifold && r.self_intersections == 0;
        o->touching_mesh = r.touching;
        o->crossing = r.crossing;
        o->volume = r.volume;
    }
    o->time_s = o->wall_s = now_s() - t0;
    if (watching) {
        pthread_mutex_lock(&w.m);
        w.done = 1;
        pthread_cond_signal(&w.cv);
        pthread_mutex_unlock(&w.m);
        pthread_join(th, NULL);
    }
    o->timed_out = cb_context_cancelled(&ctx);
    cb_topo_body_free(res);
}

/* ---------------------------------------------------------------- expectations ------------- */

typedef struct {
    char id[96];
    int op;
    int pass;          /* 1: pass; 0: known */
    char verdict[16];  /* of a known run */
    char reason[400];
} expectation;

static int op_index(const char *name)
{
    for (int k = 0; k < 3; k++)
        if (!strcmp(name, corpus_op_names[k]))
            return k;
    return -1;
}

/* Lines "ID OP pass" or "ID OP known VERDICT: REASON"; '#' starts a comment line. */
static int load_expectations(expectation **out, int *n, const char *path)
{
    *out = NULL;
    *n = 0;
    FILE *f = fopen(path, "r");
    if (!f)
        return -1;
    char line[1024];
    int cap = 0;
    while (fgets(line, sizeof line, f)) {
        line[strcspn(line, "\n")] = 0;
        if (!line[0] || line[0] == '#')
            continue;
        if (*n == cap) {
            cap = cap ? 2 * cap : 512;
            expectation *m = realloc(*out, (size_t)cap * sizeof **out);
            if (!m) {
                fclose(f);
                return -1;
            }
            *out = m;
        }
        expectation *e = *out + *n;
        memset(e, 0, sizeof *e);
        char op[32], kind[16];
        int used = 0;
        if (sscanf(line, "%95s %31s %15s %n", e->id, op, kind, &used) < 3 ||
            (e->op = op_index(op)) < 0)
            continue;
        e->pass = !strcmp(kind, "pass");
        if (!e->pass) {
            const char *rest = line + used;
            size_t k = strcspn(rest, ":");
            snprintf(e->verdict, sizeof e->verdict, "%.*s", (int)(k < 15 ? k : 15), rest);
            rest += k;
            if (*rest == ':')
                rest++;
            while (*rest == ' ')
                rest++;
            snprintf(e->reason, sizeof e->reason, "%s", rest);
        }
        (*n)++;
    }
    fclose(f);
    return 0;
}

static expectation *find_expectation(expectation *e, int n, const char *id, int op)
{
    for (int k = 0; k < n; k++)
        if (e[k].op == op && !strcmp(e[k].id, id))
            return e + k;
    return NULL;
}

/* ---------------------------------------------------------------- main --------------------- */

int main(int argc, char **argv)
{
    const char *update = NULL, *only = NULL;
    int verbose = 0;
    const char *src = getenv("COLIBRI_SOURCE");
    char dir[1024], manifest[1100], expect_path[1100];
    snprintf(dir, sizeof dir, "%s/tests/corpus", src ? src : ".");
    snprintf(manifest, sizeof manifest, "%s/cases.json", dir);
    snprintf(expect_path, sizeof expect_path, "%s/expected.txt", dir);
    for (int k = 1; k < argc; k++) {
        if (!strcmp(argv[k], "--update"))
            update = k + 1 < argc && argv[k + 1][0] != '-' ? argv[++k] : expect_path;
        else if (!strcmp(argv[k], "--only") && k + 1 < argc)
            only = argv[++k];
        else if (!strcmp(argv[k], "--verbose"))
            verbose = 1;
        else {
            fprintf(stderr, "usage: test_corpus [--update [FILE]] [--only SUBSTR] [--verbose]\n");
            return 2;
        }
    }
    corpus_case *cases;
    int n;
    char msg[1200];
    if (corpus_load(&cases, &n, manifest, msg, sizeof msg)) {
        CHECK(0, "%s", msg);
        return check_report("test_corpus");
    }
    expectation *ex = NULL;
    int nex = 0;
    if (load_expectations(&ex, &nex, expect_path) && !update)
        CHECK(0, "%s: cannot read the expectations (test_corpus --update writes them)",
              expect_path);
    FILE *up = NULL;
    if (update) {
        if (!(up = fopen(update, "w"))) {
            fprintf(stderr, "test_corpus: cannot write %s\n", update);
            return 1;
        }
        fprintf(up, "# Expected outcome of every run of the committed corpus subset (cases.json), "
                    "written by\n# `test_corpus --update` (tests/README.md): ID OP pass, or ID OP "
                    "known VERDICT: REASON.\n");
    }
    int counts[5] = {0}, now_pass = 0, changed = 0, runs = 0;
    double t_all = now_s(), slowest = 0;
    char slowest_id[160] = "";
    for (int i = 0; i < n; i++) {
        const corpus_case *c = cases + i;
        if ((only && !strstr(c->id, only)) || (!update && i % STRIDE))
            continue;
        char pa[1300], pb[1300];
        snprintf(pa, sizeof pa, "%s/%s", dir, c->a);
        snprintf(pb, sizeof pb, "%s/%s", dir, c->b);
        cb_topo_body *a = NULL, *b = NULL;
        cb_error err;
        cb_status rs = cb_step_read(&a, pa, &err);
        if (!rs)
            rs = cb_step_read(&b, pb, &err);
        for (int op = 0; op < 3; op++) {
            corpus_outcome o;
            if (rs) {
                corpus_outcome_init(&o);
                snprintf(o.message, sizeof o.message, "%.500s", err.msg);
            } else {
                run_op(&o, a, b, op);
            }
            char why[512];
            corpus_verdict v = corpus_score(&o, c, op, why, sizeof why);
            if (CORPUS_ASAN && v == CORPUS_TIMEOUT)
                snprintf(why, sizeof why, "timed out (%.0f s, sanitizer build)", LIMIT_S);
            counts[v]++;
            runs++;
            if (isfinite(o.wall_s) && o.wall_s > slowest) {
                slowest = o.wall_s;
                snprintf(slowest_id, sizeof slowest_id, "%s %s", c->id, corpus_op_names[op]);
            }
            if (verbose)
                printf("%-44s %-12s %-7s %6.2f s  %s\n", c->id, corpus_op_names[op],
                       corpus_verdict_names[v], o.wall_s, why);
            if (up) {
                if (v == CORPUS_PASS)
                    fprintf(up, "%s %s pass\n", c->id, corpus_op_names[op]);
                else
                    fprintf(up, "%s %s known %s: %s\n", c->id, corpus_op_names[op],
                            corpus_verdict_names[v], why);
            }
            /* Never acceptable, whatever the file says. */
            CHECK(v != CORPUS_WRONG, "%s %s: WRONG: %s", c->id, corpus_op_names[op], why);
            if (update)
                continue;
            expectation *e = find_expectation(ex, nex, c->id, op);
            CHECK(e != NULL, "%s %s: not in %s (run test_corpus --update)", c->id,
                  corpus_op_names[op], expect_path);
            if (!e)
                continue;
            if (e->pass) {
                int asan_slow = CORPUS_ASAN && v == CORPUS_TIMEOUT;
                if (asan_slow)
                    printf("test_corpus: %s %s: a pass in Release, stopped at %.0f s under the "
                           "sanitizer\n",
                           c->id, corpus_op_names[op], LIMIT_S);
                else
                    CHECK(v == CORPUS_PASS, "%s %s: expected to pass: %s: %s", c->id,
                          corpus_op_names[op], corpus_verdict_names[v], why);
            } else if (v == CORPUS_PASS) {
                now_pass++;
                printf("test_corpus: %s %s now PASSES (was known %s: %s): update "
                       "tests/corpus/expected.txt (test_corpus --update)\n",
                       c->id, corpus_op_names[op], e->verdict, e->reason);
            } else if (strcmp(e->verdict, corpus_verdict_names[v])) {
                changed++;
                printf("test_corpus: %s %s: known %s, now %s: %s\n", c->id, corpus_op_names[op],
                       e->verdict, corpus_verdict_names[v], why);
            }
        }
        cb_topo_body_free(a);
        cb_topo_body_free(b);
    }
    /* The file and the cases agree, whichever of them ran. */
    for (int k = 0; !update && k < nex; k++) {
        int found = 0;
        for (int i = 0; i < n && !found; i++)
            found = !strcmp(cases[i].id, ex[k].id);
        CHECK(found, "%s %s: in %s but not in the cases", ex[k].id, corpus_op_names[ex[k].op],
              expect_path);
    }
    printf("test_corpus: %d runs (%d cases x 3), %.1f s, limit %.0f s per run%s: pass %d, refused "
           "%d, WRONG %d, crash %d, timeout %d; slowest %.2f s (%s)\n",
           runs, runs / 3, now_s() - t_all, LIMIT_S,
           CORPUS_ASAN ? " (sanitizer build: every second case)" : "",
           counts[0], counts[1], counts[2], counts[3], counts[4], slowest, slowest_id);
    if (now_pass || changed)
        printf("test_corpus: %d known runs now pass, %d changed verdict: update the expectations "
               "(tests/README.md)\n",
               now_pass, changed);
    if (up)
        fclose(up);
    free(ex);
    free(cases);
    return check_report("test_corpus");
}
