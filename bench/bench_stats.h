/* bench_stats.h — what the side-by-side benchmarks (bench_scenarios, bench_ssi_cases) share for
 * their timings: a monotonic clock, and the median, least and largest of a set of runs.
 * Header-only: every bench_*.c is a program of its own. */
#ifndef CB_BENCH_STATS_H
#define CB_BENCH_STATS_H

#include <stdlib.h>
#include <time.h>

/* Runs per case at most. */
#define MAX_RUNS 64

static inline double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static inline int cmp_double(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

/* Median, least and largest of t[0 .. n) (sorted in place), n >= 1. */
static inline void stats3(double out[3], double *t, int n)
{
    qsort(t, (size_t)n, sizeof *t, cmp_double);
    out[0] = t[n / 2];
    out[1] = t[0];
    out[2] = t[n - 1];
}

#endif
