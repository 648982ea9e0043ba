/* bench_corpus — runs the randomized differential corpus (bench/corpus/occt_corpus.cpp) through
 * Colibri and, where given, Open CASCADE, and scores both by the same rules (bench/corpus/
 * corpus.h): pass, refused (with the tool's reason), WRONG, crash, timeout.
 *
 * For every case of CASEDIR/cases.json and each of union, intersection and A - B: Colibri as a
 * subprocess, `colibri bool OP A B -o X.stl --json R.json --quiet` (its exit status and JSON
 * report: status, message, volume, validity, mesh checks, phase times), and, with --occt,
 * `occt_bool 1 A B OP` (BRepAlgoAPI_Fuse / Common / Cut: error flag, BRepCheck validity, volume).
 * Each process is started by posix_spawn in a process group of its own and killed with the
 * group at the time limit. Times: Colibri's is the Boolean's own (intersection + splitting +
 * sewing from its report, without reading the files or checking the result), OCCT's its
 * Boolean's build time; the wall time of each process is kept in the JSON.
 *
 * Output: a table by configuration x pose x faces (counts of each verdict for both tools, median
 * times and their ratio C/O over the runs both tools passed), totals per
 * configuration, pose and face kind, every WRONG / crash / timeout with its reason, and the
 * refusal reasons by count (numbers stripped); with --json, every run.
 *
 * Usage: bench_corpus CASEDIR [--colibri PATH] [--occt PATH] [--timeout S] [--json OUT]
 *                     [--only REGEX] [--threads N]
 *   --colibri  the colibri binary (default build/cli/colibri)
 *   --occt     the occt_bool comparator (default: none, no OCCT columns)
 *   --timeout  seconds per run of either tool (default 60)
 *   --only     only cases whose id matches the extended regular expression
 *   --threads  passed to colibri (default: its own, all hardware threads) */
#define _DEFAULT_SOURCE
#include <math.h>
#include <regex.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bench/corpus/corpus.h"
#include "bench/corpus/corpus_run.h"
#include "io/json.h"

/* ---------------------------------------------------------------- results and tables ------- */

typedef corpus_side side;

typedef struct {
    int case_index, op;
    side c, o;
} run_result;

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double median(double *v, int n)
{
    if (n == 0)
        return NAN;
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* Whether OCCT ran (times are then taken over the runs both tools passed). */
static int have_occt;

typedef struct {
    int n, c[5], o[5];
    int timed;             /* runs both tools passed */
    double ct_med, ot_med; /* their median times */
} tally;

/* Tallies the runs selected by keep (by config / pose / faces; NULL: any). */
static tally tally_of(const run_result *r, int nr, const corpus_case *cases, const char *config,
                      const char *pose, const char *faces, double *scratch_c, double *scratch_o)
{
    tally t;
    memset(&t, 0, sizeof t);
    int m = 0;
    for (int k = 0; k < nr; k++) {
        const corpus_case *c = cases + r[k].case_index;
        if ((config && strcmp(c->config, config)) || (pose && strcmp(c->pose, pose)) ||
            (faces && strcmp(c->faces, faces)))
            continue;
        t.n++;
        t.c[r[k].c.v]++;
        t.o[r[k].o.v]++;
        /* Times of runs both tools got right only: a quick refusal says nothing of speed. */
        if (r[k].c.v == CORPUS_PASS && isfinite(r[k].c.o.time_s) &&
            (!have_occt || (r[k].o.v == CORPUS_PASS && isfinite(r[k].o.o.time_s)))) {
            scratch_c[m] = r[k].c.o.time_s;
            scratch_o[m] = r[k].o.o.time_s;
            m++;
        }
    }
    t.timed = m;
    t.ct_med = median(scratch_c, m);
    t.ot_med = median(scratch_o, m);
    return t;
}

static void print_tally(const char *label, const tally *t, int occt)
{
    printf("%-40s %4d | %4d %4d %4d %4d %4d |", label, t->n, t->c[0], t->c[1], t->c[2], t->c[3],
           t->c[4]);
    if (occt && t->timed)
        printf(" %4d %4d %4d %4d %4d | %4d %8.4f %8.4f %6.2f", t->o[0], t->o[1], t->o[2], t->o[3],
               t->o[4], t->timed, t->ct_med, t->ot_med,
               t->ot_med > 0 ? t->ct_med / t->ot_med : NAN);
    else if (occt)
        printf(" %4d %4d %4d %4d %4d | %4d %8s %8s %6s", t->o[0], t->o[1], t->o[2], t->o[3],
               t->o[4], 0, "-", "-", "-");
    else if (t->timed)
        printf(" %4d %8.4f", t->timed, t->ct_med);
    else
        printf(" %4d %8s", 0, "-");
    printf("\n");
}

typedef struct {
    char reason[400];
    int count;
    char example[128];
} reason_count;

static int cmp_reason(const void *a, const void *b)
{
    const reason_count *x = a, *y = b;
    return y->count - x->count;
}

/* Refusal reasons of one tool (tool 0 Colibri, 1 OCCT) by count, numbers stripped. */
static void print_reasons(const run_result *r, int nr, const corpus_case *cases, int tool)
{
    reason_count *rc = calloc((size_t)nr + 1, sizeof *rc);
    int n = 0;
    for (int k = 0; rc && k < nr; k++) {
        const side *s = tool ? &r[k].o : &r[k].c;
        if (s->v != CORPUS_REFUSED)
            continue;
        char cls[400];
        corpus_reason_class(cls, sizeof cls, s->why, cases + r[k].case_index);
        int j = 0;
        while (j < n && strcmp(rc[j].reason, cls))
            j++;
        if (j == n) {
            snprintf(rc[j].reason, sizeof rc[j].reason, "%s", cls);
            snprintf(rc[j].example, sizeof rc[j].example, "%s %s", cases[r[k].case_index].id,
                     corpus_op_names[r[k].op]);
            n++;
        }
        rc[j].count++;
    }
    if (!rc)
        return;
    qsort(rc, (size_t)n, sizeof *rc, cmp_reason);
    printf("\n%s refusals by reason (numbers as #; count, reason, first case):\n",
           tool ? "OCCT" : "Colibri");
    for (int j = 0; j < n; j++)
        printf("%5d  %s  [%s]\n", rc[j].count, rc[j].reason, rc[j].example);
    free(rc);
}

static int usage(void)
{
    fprintf(stderr, "usage: bench_corpus CASEDIR [--colibri PATH] [--occt PATH] [--timeout S] "
                    "[--json OUT] [--only REGEX] [--threads N]\n");
    return 2;
}

int main(int argc, char **argv)
{
    run_opts ro = {"build/cli/colibri", NULL, NULL, NULL, 60, 0};
    const char *json_path = NULL, *only = NULL;
    for (int k = 1; k < argc; k++) {
        if (!strcmp(argv[k], "--colibri") && k + 1 < argc)
            ro.colibri = argv[++k];
        else if (!strcmp(argv[k], "--occt") && k + 1 < argc)
            ro.occt = argv[++k];
        else if (!strcmp(argv[k], "--timeout") && k + 1 < argc)
            ro.timeout = atof(argv[++k]);
        else if (!strcmp(argv[k], "--json") && k + 1 < argc)
            json_path = argv[++k];
        else if (!strcmp(argv[k], "--only") && k + 1 < argc)
            only = argv[++k];
        else if (!strcmp(argv[k], "--threads") && k + 1 < argc)
            ro.threads = atoi(argv[++k]);
        else if (argv[k][0] != '-' && !ro.dir)
            ro.dir = argv[k];
        else
            return usage();
    }
    if (!ro.dir || !(ro.timeout > 0))
        return usage();
    if (access(ro.colibri, X_OK)) {
        fprintf(stderr, "bench_corpus: %s is not an executable (--colibri)\n", ro.colibri);
        return 2;
    }
    if (ro.occt && access(ro.occt, X_OK)) {
        fprintf(stderr, "bench_corpus: %s is not an executable (--occt)\n", ro.occt);
        return 2;
    }
    regex_t re;
    if (only && regcomp(&re, only, REG_EXTENDED | REG_NOSUB)) {
        fprintf(stderr, "bench_corpus: bad regular expression '%s'\n", only);
        return 2;
    }
    char path[1024], msg[1200];
    snprintf(path, sizeof path, "%s/cases.json", ro.dir);
    corpus_case *cases;
    int n;
    if (corpus_load(&cases, &n, path, msg, sizeof msg)) {
        fprintf(stderr, "bench_corpus: %s\n", msg);
        return 2;
    }
    char tmp[] = "/tmp/colibri_corpus_XXXXXX"; /* mkdtemp's template: it replaces the Xs */
    if (!mkdtemp(tmp)) {
        fprintf(stderr, "bench_corpus: cannot make a temporary directory\n");
        return 1;
    }
    ro.tmp = tmp;
    run_result *r = calloc((size_t)n * 3, sizeof *r);
    double *sc = malloc((size_t)n * 3 * sizeof *sc), *so = malloc((size_t)n * 3 * sizeof *so);
    if (!r || !sc || !so) {
        fprintf(stderr, "bench_corpus: out of memory\n");
        return 1;
    }
    int nr = 0, selected = 0;
    double t0 = now_s();
    int tty = isatty(STDERR_FILENO);
    for (int i = 0; i < n; i++) {
        if (only && regexec(&re, cases[i].id, 0, NULL, 0))
            continue;
        selected++;
        for (int op = 0; op < 3; op++) {
            run_result *x = r + nr++;
            x->case_index = i;
            x->op = op;
            if (tty)
                fprintf(stderr, "bench_corpus: case %d of %d, %.0f s: %s %s          \r", i + 1,
                        n, now_s() - t0, cases[i].id, corpus_op_names[op]);
            char pa[1024], pb[1024];
            snprintf(pa, sizeof pa, "%s/%s", ro.dir, cases[i].a);
            snprintf(pb, sizeof pb, "%s/%s", ro.dir, cases[i].b);
            run_colibri(&x->c.o, pa, pb, op, &ro);
            x->c.v = corpus_score(&x->c.o, cases + i, op, x->c.why, sizeof x->c.why);
            if (ro.occt) {
                run_occt(&x->o.o, pa, pb, op, &ro);
                x->o.v = corpus_score(&x->o.o, cases + i, op, x->o.why, sizeof x->o.why);
            } else {
                corpus_outcome_init(&x->o.o);
                x->o.v = CORPUS_REFUSED;
                snprintf(x->o.why, sizeof x->o.why, "not run");
            }
        }
    }
    double elapsed = now_s() - t0;
    if (tty)
        fprintf(stderr, "%100s\r", "");
    int occt = have_occt = ro.occt != NULL;

    printf("Corpus %s: %d cases x 3 operations, time limit %g s per run; verdicts pass / refused "
           "/ WRONG / crash / timeout; times: over the runs both tools passed (both), the medians "
           "of the Boolean's own seconds (Colibri's report gives milliseconds) and their ratio "
           "C/O\n",
           ro.dir, selected, ro.timeout);
    printf("%-40s %4s | %-24s |", "configuration pose faces", "runs", "Colibri pass ref WRNG crsh tmo");
    if (occt)
        printf(" %-24s | %4s %8s %8s %6s", "OCCT    pass ref WRNG crsh tmo", "both", "C s", "O s",
               "C/O");
    else
        printf(" %4s %8s", "pass", "C s");
    printf("\n");
    static const char *const poses[3] = {"axis", "translated", "rotated"};
    static const char *const kinds[2] = {"analytic", "nurbs"};
    /* Configurations in the order they first appear. */
    const char **configs = calloc((size_t)n, sizeof *configs);
    int nc = 0;
    for (int k = 0; configs && k < nr; k++) {
        const char *cf = cases[r[k].case_index].config;
        int j = 0;
        while (j < nc && strcmp(configs[j], cf))
            j++;
        if (j == nc)
            configs[nc++] = cf;
    }
    char label[128];
    for (int j = 0; j < nc; j++)
        for (int p = 0; p < 3; p++)
            for (int f = 0; f < 2; f++) {
                tally t = tally_of(r, nr, cases, configs[j], poses[p], kinds[f], sc, so);
                if (!t.n)
                    continue;
                snprintf(label, sizeof label, "%s %s %s", configs[j], poses[p], kinds[f]);
                print_tally(label, &t, occt);
            }
    printf("\nBy configuration:\n");
    for (int j = 0; j < nc; j++) {
        tally t = tally_of(r, nr, cases, configs[j], NULL, NULL, sc, so);
        print_tally(configs[j], &t, occt);
    }
    printf("\nBy pose and faces:\n");
    for (int p = 0; p < 3; p++) {
        tally t = tally_of(r, nr, cases, NULL, poses[p], NULL, sc, so);
        print_tally(poses[p], &t, occt);
    }
    for (int f = 0; f < 2; f++) {
        tally t = tally_of(r, nr, cases, NULL, NULL, kinds[f], sc, so);
        print_tally(kinds[f], &t, occt);
    }
    tally all = tally_of(r, nr, cases, NULL, NULL, NULL, sc, so);
    print_tally("all", &all, occt);

    printf("\nColibri WRONG / crash / timeout:\n");
    for (int k = 0; k < nr; k++)
        if (r[k].c.v >= CORPUS_WRONG)
            printf("  %s %s: %s: %s\n", cases[r[k].case_index].id, corpus_op_names[r[k].op],
                   corpus_verdict_names[r[k].c.v], r[k].c.why);
    if (occt) {
        printf("\nOCCT WRONG / crash / timeout:\n");
        for (int k = 0; k < nr; k++)
            if (r[k].o.v >= CORPUS_WRONG)
                printf("  %s %s: %s: %s\n", cases[r[k].case_index].id, corpus_op_names[r[k].op],
                       corpus_verdict_names[r[k].o.v], r[k].o.why);
    }
    print_reasons(r, nr, cases, 0);
    if (occt)
        print_reasons(r, nr, cases, 1);
    printf("\n%d runs in %.0f s\n", nr, elapsed);

    if (json_path) {
        FILE *f = fopen(json_path, "w");
        if (!f) {
            fprintf(stderr, "bench_corpus: cannot write %s\n", json_path);
        } else {
            fprintf(f, "{\"casedir\": ");
            cb_json_string(f, ro.dir);
            fprintf(f, ", \"timeout_s\": %g, \"runs\": [", ro.timeout);
            for (int k = 0; k < nr; k++) {
                const corpus_case *c = cases + r[k].case_index;
                fprintf(f, "%s\n {\"id\": \"%s\", \"config\": \"%s\", \"pose\": \"%s\", "
                           "\"faces\": \"%s\", \"op\": \"%s\", \"touching\": %s, \"truth\": %.17g, "
                           "\"bar\": %.3g, ",
                        k ? "," : "", c->id, c->config, c->pose, c->faces,
                        corpus_op_names[r[k].op], c->touching ? "true" : "false",
                        corpus_truth(c, r[k].op), corpus_bar(c, r[k].op));
                corpus_json_side(f, "colibri", &r[k].c);
                if (occt) {
                    fputs(", ", f);
                    corpus_json_side(f, "occt", &r[k].o);
                }
                fputs("}", f);
            }
            fputs("\n]}\n", f);
            fclose(f);
        }
    }
    char p2[700];
    const char *files[] = {"result.stl", "report.json", "stdout.txt", "stderr.txt",
                           "occt_stdout.txt", "occt_stderr.txt"};
    for (size_t k = 0; k < sizeof files / sizeof *files; k++) {
        snprintf(p2, sizeof p2, "%s/%s", tmp, files[k]);
        remove(p2);
    }
    rmdir(tmp);
    if (only)
        regfree(&re);
    free(configs);
    free(sc);
    free(so);
    free(r);
    free(cases);
    return 0;
}
