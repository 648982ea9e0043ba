/* test_step_corpus — every file of the shared corpus of real STEP files (../shared/corpus/step/,
 * 222 files from many CAD systems) loaded by `colibri info --json`, each in a process of its
 * own with a wall-time limit, and scored against Open CASCADE's figures by the rules of
 * bench/step_corpus.h (the same code as bench_step_corpus): ok (same number of solids, valid,
 * volume within 1e-6 of OCCT's), not_loaded, solids, invalid, no_volume, volume, timeout,
 * crash, loaded.
 *
 * tests/step_corpus/expected.txt holds the outcome of every file as Colibri reads it today. The
 * test FAILS on a crash, on a file the list does not hold, and on a file that does worse than
 * listed: an `ok` file that is no longer ok, a file that loaded and now does not, one that
 * ended and now times out. It only PRINTS a file that does better or differently (update the
 * list). Files are run two at a time.
 *
 * Time limits: 120 s per file in an optimised build: the slowest files that end take 30 s
 * alone on a quiet 2-core machine (the volume integration of trj3_s1-ug-214.stp and
 * trj4_s1-ug-214.stp), twice that beside the rest of the suite; bug33398.step does not end
 * (listed as timeout). The whole run takes about 3 minutes on 2 cores beside other work. Under
 * AddressSanitizer (colibri itself is the sanitizer build, several times slower) every fourth
 * file only, with 240 s each, and a listed file that now times out is printed, not failed: the
 * sanitizer build is there to find memory errors, which it does on the files that end.
 *
 * Without ../shared (COLIBRI_SHARED) the test says so and is skipped (exit status 77).
 *
 * Usage: test_step_corpus [--update [FILE]] [--only SUBSTR]
 *   --update writes the outcomes seen in this run (to FILE, default the source tree's
 *   tests/step_corpus/expected.txt) and does not fail on differences from the old list.
 *   COLIBRI_BINARY (set by ctest) is the colibri to run, COLIBRI_SOURCE the source tree. */
#define _DEFAULT_SOURCE
#include "bench/step_corpus.h"

#include "check.h"

#if defined(__SANITIZE_ADDRESS__)
#define STEPC_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define STEPC_ASAN 1
#endif
#endif
#ifndef STEPC_ASAN
#define STEPC_ASAN 0
#endif

static const double LIMIT_S = STEPC_ASAN ? 240 : 120;
static const int STRIDE = STEPC_ASAN ? 4 : 1;
enum { SKIP = 77, JOBS = 2 };

typedef struct {
    char file[128];
    int outcome;
} expectation;

static expectation *expected;
static int n_expected;

static int read_expected(const char *path)
{
    FILE *fp = fopen(path, "r");
    if (!fp)
        return -1;
    char line[512];
    int cap = 0;
    while (fgets(line, sizeof line, fp)) {
        char file[128], outcome[32];
        if (line[0] == '#' || sscanf(line, "%127s %31s", file, outcome) != 2)
            continue;
        if (n_expected == cap) {
            cap = cap ? 2 * cap : 256;
            expectation *e = realloc(expected, (size_t)cap * sizeof *e);
            if (!e)
                break;
            expected = e;
        }
        snprintf(expected[n_expected].file, sizeof expected[n_expected].file, "%s", file);
        expected[n_expected].outcome = stepc_outcome_parse(outcome);
        CHECK(expected[n_expected].outcome >= 0, "%s: %s: unknown outcome '%s'", path, file,
              outcome);
        n_expected++;
    }
    fclose(fp);
    return 0;
}

static int expected_of(const char *file)
{
    for (int k = 0; k < n_expected; k++)
        if (!strcmp(expected[k].file, file))
            return expected[k].outcome;
    return -1;
}

/* 1 when `now` is worse than `was` (see the top). */
static int worse(int was, int now)
{
    if (now == STEPC_CRASH)
        return 1;
    if (was == now)
        return 0;
    if (was == STEPC_OK)
        return 1;
    if (now == STEPC_TIMEOUT)
        return !STEPC_ASAN;
    int loaded_before = was != STEPC_NOT_LOADED && was != STEPC_TIMEOUT && was != STEPC_CRASH;
    return loaded_before && now == STEPC_NOT_LOADED;
}

static int n_done;

static void on_done(stepc_run *r, void *arg)
{
    (void)arg;
    stepc_score(r);
    n_done++;
    int was = expected_of(r->ref->file), now = (int)r->outcome;
    if (was < 0) {
        CHECK(0, "%s: %s (%s), not in the list of expected outcomes", r->ref->file,
              STEPC_NAMES[now], r->detail);
        return;
    }
    CHECK(!worse(was, now), "%s: %s, listed as %s (%s)", r->ref->file, STEPC_NAMES[now],
          STEPC_NAMES[was], r->detail);
    if (was != now && !worse(was, now))
        printf("%s: now %s, listed as %s (%s): update tests/step_corpus/expected.txt\n",
               r->ref->file, STEPC_NAMES[now], STEPC_NAMES[was], r->detail);
}

int main(int argc, char **argv)
{
    const char *shared = getenv("COLIBRI_SHARED"), *colibri = getenv("COLIBRI_BINARY"),
               *source = getenv("COLIBRI_SOURCE"), *only = NULL, *update = NULL;
    char default_list[1024];
    snprintf(default_list, sizeof default_list, "%s/tests/step_corpus/expected.txt",
             source ? source : ".");
    for (int k = 1; k < argc; k++) {
        if (!strcmp(argv[k], "--update"))
            update = k + 1 < argc && argv[k + 1][0] != '-' ? argv[++k] : default_list;
        else if (!strcmp(argv[k], "--only") && k + 1 < argc)
            only = argv[++k];
        else {
            fprintf(stderr, "usage: test_step_corpus [--update [FILE]] [--only SUBSTR]\n");
            return 2;
        }
    }
    if (update && (only || STRIDE > 1)) {
        fprintf(stderr, "test_step_corpus: --update needs every file: no --only, no sanitizer "
                        "build\n");
        return 2;
    }
    if (!shared)
        shared = "../shared";
    char ref_path[1024];
    snprintf(ref_path, sizeof ref_path, "%s/corpus/occt-reference.json", shared);
    if (access(ref_path, R_OK)) {
        printf("test_step_corpus: skipped: %s is missing (the shared STEP corpus is not beside "
               "the checkout)\n",
               ref_path);
        return SKIP;
    }
    if (!colibri || access(colibri, X_OK)) {
        fprintf(stderr, "test_step_corpus: COLIBRI_BINARY (%s) is not an executable\n",
                colibri ? colibri : "unset");
        return 1;
    }
    if (read_expected(default_list) && !update) {
        fprintf(stderr, "test_step_corpus: %s: %s\n", default_list, strerror(errno));
        return 1;
    }
    stepc_ref *refs;
    int n_refs;
    if (stepc_read_refs(&refs, &n_refs, ref_path))
        return 1;
    stepc_run *runs = calloc((size_t)n_refs, sizeof *runs);
    int n = 0;
    for (int k = 0; k < n_refs; k++) {
        if (only ? !strstr(refs[k].file, only) : k % STRIDE)
            continue;
        runs[n].ref = &refs[k];
        snprintf(runs[n].path, sizeof runs[n].path, "%s/corpus/step/%s", shared, refs[k].file);
        n++;
    }
    double t0 = stepc_now();
    stepc_run_all(runs, n, colibri, LIMIT_S, JOBS, on_done, NULL);
    int count[STEPC_N_OUTCOMES] = {0};
    for (int k = 0; k < n; k++)
        count[runs[k].outcome]++;
    printf("%d files in %.1f s (%d at a time, %.0f s each at most):", n, stepc_now() - t0, JOBS,
           LIMIT_S);
    for (int c = 0; c < STEPC_N_OUTCOMES; c++)
        if (count[c])
            printf(" %s %d", STEPC_NAMES[c], count[c]);
    printf("\n");
    CHECK(n_done == n, "%d of %d files scored", n_done, n);
    if (update) {
        FILE *fp = fopen(update, "w");
        if (!fp) {
            fprintf(stderr, "%s: %s\n", update, strerror(errno));
            return 1;
        }
        fprintf(fp, "# Outcome of every file of ../shared/corpus/step/ as `colibri info --json` "
                    "reads it,\n# scored against Open CASCADE (bench/step_corpus.h); written by "
                    "test_step_corpus --update.\n");
        for (int k = 0; k < n; k++)
            fprintf(fp, "%-48s %-10s %s\n", runs[k].ref->file, STEPC_NAMES[runs[k].outcome],
                    runs[k].detail);
        fclose(fp);
        printf("wrote %s\n", update);
        check_failed_count = 0;
    }
    for (int k = 0; k < n; k++)
        free(runs[k].out);
    free(runs);
    free(refs);
    free(expected);
    return check_report("test_step_corpus");
}
