/* STEP import figures per shared model: parse time (median, min, max of N runs), validation
 * time, and the peak resident memory of a fresh process that reads the model once, next to
 * that of one that reads nothing. Usage: bench_step [SHARED_DIR] [N] (run from bench/ of the
 * build tree, or give its path: it starts itself again for the memory figures). */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#include "io/step.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* Reads `path` once (or nothing for "-") and prints this process's peak RSS in KiB: run as a
 * fresh process so that nothing else counts. */
static int peak_mode(const char *path)
{
    cb_topo_body *b = NULL;
    cb_error err;
    if (strcmp(path, "-") && cb_step_read(&b, path, &err) != CB_OK)
        return 1;
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    printf("%ld\n", ru.ru_maxrss);
    cb_topo_body_free(b);
    return 0;
}

/* Peak RSS (KiB) of a fresh copy of this program reading `path` ("-": nothing), -1 on error. */
static long fresh_peak_kb(const char *self, const char *path)
{
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "'%s' --peak '%s'", self, path);
    FILE *p = popen(cmd, "r");
    long kb = -1;
    if (p) {
        if (fscanf(p, "%ld", &kb) != 1)
            kb = -1;
        pclose(p);
    }
    return kb;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
    if (argc == 3 && !strcmp(argv[1], "--peak"))
        return peak_mode(argv[2]);
    const char *shared = argc > 1 ? argv[1] : "../shared";
    int runs = argc > 2 ? atoi(argv[2]) : 15;
    if (runs < 1 || runs > 1000) {
        fprintf(stderr, "bench_step: N must be in [1, 1000]\n");
        return 2;
    }
    static const char *const models[] = {"trj5_k1-al-214.stp", "linkrods.step",
                                         "ujoint_fork.step", "ujoint_cross.step"};
    printf("%-20s %9s %9s %9s %9s %6s %6s %9s\n", "model", "parse ms", "min", "max",
           "valid ms", "faces", "edges", "peak KiB");
    int status = 0;
    for (size_t m = 0; m < sizeof models / sizeof *models; m++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/models/%s", shared, models[m]);
        double *t = malloc((size_t)runs * sizeof *t);
        cb_topo_body *b = NULL;
        cb_error err;
        int ok = 1;
        for (int r = 0; r < runs && ok; r++) {
            cb_topo_body_free(b);
            double t0 = now();
            ok = cb_step_read(&b, path, &err) == CB_OK;
            t[r] = now() - t0;
        }
        if (!ok) {
            printf("%-20s failed: %s\n", models[m], err.msg);
            status = 1;
            free(t);
            continue;
        }
        qsort(t, (size_t)runs, sizeof *t, cmp_double);
        cb_topo_report rep;
        cb_topo_report_init(&rep);
        double t0 = now();
        cb_topo_validate(&rep, b, 0, 9, &err);
        double tv = now() - t0;
        printf("%-20s %9.2f %9.2f %9.2f %9.2f %6d %6d %9ld\n", models[m], 1e3 * t[runs / 2],
               1e3 * t[0], 1e3 * t[runs - 1], 1e3 * tv, b->n_faces, b->n_edges,
               fresh_peak_kb(argv[0], path));
        cb_topo_report_clear(&rep);
        cb_topo_body_free(b);
        free(t);
    }
    printf("%-20s %69ld\n", "(reading nothing)", fresh_peak_kb(argv[0], "-"));
    return status;
}
