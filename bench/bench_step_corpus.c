/* bench_step_corpus — every file of the shared corpus of real STEP files
 * (../shared/corpus/step/, 222 files from many CAD systems) loaded by `colibri info --json`,
 * each in a process of its own with a wall-time limit, and scored against Open CASCADE's
 * figures (occt-reference.json) by the rules of bench/step_corpus.h: same number of solids,
 * valid, volume within 1e-6 of OCCT's after unit conversion. Prints one row per file, the
 * counts per outcome on the files OCCT reads as valid solids and on all files, and the reasons
 * of the files not loaded, by count.
 *
 * Usage: bench_step_corpus [--shared DIR] [--colibri EXE] [--timeout S] [-j N]
 *                          [--only SUBSTR] [--json OUT]
 *   --shared   the shared directory (default $COLIBRI_SHARED or ../shared)
 *   --colibri  the command (default build/cli/colibri)
 *   --timeout  seconds per file (default 30)
 *   -j         files loaded at a time (default 1)
 *   --json     one JSON object per file, one a line */
#define _DEFAULT_SOURCE
#include "bench/step_corpus.h"

#include "io/json.h"

typedef struct {
    int rows;
} progress;

static void on_done(stepc_run *r, void *arg)
{
    (void)arg;
    stepc_score(r);
    printf("%-44.44s %-10s %3d/%-3d %9.2e %6.1f  %.110s\n", r->ref->file, STEPC_NAMES[r->outcome],
           r->solids, r->ref->has_occt ? r->ref->solids : -1, r->rel_err, r->elapsed, r->detail);
    fflush(stdout);
}

typedef struct {
    char key[160];
    int count;
    char example[128];
} reason;

static int reason_cmp(const void *a, const void *b)
{
    const reason *x = a, *y = b;
    return y->count != x->count ? y->count - x->count : strcmp(x->key, y->key);
}

int main(int argc, char **argv)
{
    const char *shared = getenv("COLIBRI_SHARED"), *colibri = "build/cli/colibri", *only = NULL,
               *json = NULL;
    double timeout = 30;
    int jobs = 1;
    if (!shared)
        shared = "../shared";
    for (int k = 1; k < argc; k++) {
        if (!strcmp(argv[k], "--shared") && k + 1 < argc)
            shared = argv[++k];
        else if (!strcmp(argv[k], "--colibri") && k + 1 < argc)
            colibri = argv[++k];
        else if (!strcmp(argv[k], "--timeout") && k + 1 < argc)
            timeout = atof(argv[++k]);
        else if (!strcmp(argv[k], "-j") && k + 1 < argc)
            jobs = atoi(argv[++k]);
        else if (!strcmp(argv[k], "--only") && k + 1 < argc)
            only = argv[++k];
        else if (!strcmp(argv[k], "--json") && k + 1 < argc)
            json = argv[++k];
        else {
            fprintf(stderr,
                    "usage: bench_step_corpus [--shared DIR] [--colibri EXE] [--timeout S] "
                    "[-j N] [--only SUBSTR] [--json OUT]\n");
            return 2;
        }
    }
    if (access(colibri, X_OK)) {
        fprintf(stderr, "bench_step_corpus: %s is not executable (scripts/build release)\n",
                colibri);
        return 2;
    }
    char path[1024];
    snprintf(path, sizeof path, "%s/corpus/occt-reference.json", shared);
    stepc_ref *refs;
    int n_refs;
    if (stepc_read_refs(&refs, &n_refs, path))
        return 2;
    stepc_run *runs = calloc((size_t)n_refs, sizeof *runs);
    int n = 0;
    for (int k = 0; k < n_refs; k++) {
        if (only && !strstr(refs[k].file, only))
            continue;
        runs[n].ref = &refs[k];
        snprintf(runs[n].path, sizeof runs[n].path, "%s/corpus/step/%s", shared, refs[k].file);
        n++;
    }
    printf("%-44s %-10s %7s %9s %6s  %s\n", "file", "outcome", "sol/occ", "rel.err", "time/s",
           "detail");
    double t0 = stepc_now();
    stepc_run_all(runs, n, colibri, timeout, jobs, on_done, NULL);
    double wall = stepc_now() - t0;

    /* Counts per outcome: the OCCT-valid files, then all. */
    int count[2][STEPC_N_OUTCOMES] = {{0}}, total[2] = {0, 0};
    double cpu_sum = 0, slowest = 0;
    const char *slowest_file = "";
    for (int k = 0; k < n; k++) {
        const stepc_run *r = &runs[k];
        count[1][r->outcome]++;
        total[1]++;
        if (stepc_occt_valid(r->ref)) {
            count[0][r->outcome]++;
            total[0]++;
        }
        cpu_sum += r->elapsed;
        if (r->elapsed > slowest) {
            slowest = r->elapsed;
            slowest_file = r->ref->file;
        }
    }
    static const char *const LABELS[STEPC_N_OUTCOMES] = {
        "same solids, valid, volume within 1e-6 of OCCT's",
        "not loaded (exit 2, with the message)",
        "a different number of solids",
        "loaded but not valid",
        "valid but no volume",
        "volume differs by more than 1e-6",
        "timeout",
        "crash",
        "loaded where OCCT transfers nothing"};
    printf("\n| outcome | OCCT-valid solids (%d) | all files (%d) |\n|---|---|---|\n", total[0],
           total[1]);
    for (int c = 0; c < STEPC_N_OUTCOMES; c++)
        printf("| %s | %d | %d |\n", LABELS[c], count[0][c], count[1][c]);
    printf("(all files: a file OCCT transfers nothing from counts as the first row when Colibri "
           "refuses it with a message)\n");

    /* Reasons of the files not loaded, by count. */
    reason *rs = calloc((size_t)n + 1, sizeof *rs);
    int n_rs = 0;
    for (int k = 0; k < n; k++) {
        const stepc_run *r = &runs[k];
        if (r->status != 2 || r->timed_out)
            continue;
        char key[160];
        stepc_reason_key(key, sizeof key, r->detail);
        int j = 0;
        while (j < n_rs && strcmp(rs[j].key, key))
            j++;
        if (j == n_rs) {
            snprintf(rs[j].key, sizeof rs[j].key, "%s", key);
            snprintf(rs[j].example, sizeof rs[j].example, "%s", r->ref->file);
            n_rs++;
        }
        rs[j].count++;
    }
    qsort(rs, (size_t)n_rs, sizeof *rs, reason_cmp);
    printf("\nnot loaded (exit 2), by reason (numbers as N):\n");
    for (int j = 0; j < n_rs; j++)
        printf("%4d  %s  (e.g. %s)\n", rs[j].count, rs[j].key, rs[j].example);
    printf("\n%d files in %.1f s wall (-j %d), %.1f s summed, slowest %.1f s (%s); limit %.0f s\n",
           n, wall, jobs, cpu_sum, slowest, slowest_file, timeout);

    if (json) {
        FILE *fp = fopen(json, "w");
        if (!fp) {
            fprintf(stderr, "%s: %s\n", json, strerror(errno));
            return 2;
        }
        for (int k = 0; k < n; k++) {
            const stepc_run *r = &runs[k];
            fputs("{\"file\": ", fp);
            cb_json_string(fp, r->ref->file);
            fprintf(fp, ", \"outcome\": \"%s\", \"occt_valid\": %s, \"solids\": %d, "
                        "\"occt_solids\": %d, \"time\": %.3f, \"rel_err\": ",
                    STEPC_NAMES[r->outcome], stepc_occt_valid(r->ref) ? "true" : "false",
                    r->solids, r->ref->solids, r->elapsed);
            if (isnan(r->rel_err))
                fputs("null", fp);
            else
                fprintf(fp, "%.3e", r->rel_err);
            fputs(", \"detail\": ", fp);
            cb_json_string(fp, r->detail);
            fputs("}\n", fp);
        }
        fclose(fp);
    }
    for (int k = 0; k < n; k++)
        free(runs[k].out);
    free(rs);
    free(runs);
    free(refs);
    return 0;
}
