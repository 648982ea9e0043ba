/* args.c — the option values, the progress line and the clock every command shares. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "cli/commands.h"

int cb_cli_tol_arg(double *tol, const char *s)
{
    char *end;
    double t = strtod(s, &end);
    if (end == s || *end || !(t > 0) || !isfinite(t)) {
        fprintf(stderr, "colibri: --tol needs a positive number, not '%s'\n", s);
        return 2;
    }
    *tol = t;
    return 0;
}

int cb_cli_threads_arg(int *threads, const char *s)
{
    char *end;
    long n = strtol(s, &end, 10);
    if (end == s || *end || n < 0 || n > 4096) {
        fprintf(stderr, "colibri: --threads needs a count in [0, 4096], not '%s'\n", s);
        return 2;
    }
    *threads = (int)n;
    return 0;
}

void cb_cli_progress(void *user, double fraction, const char *stage)
{
    int *last = user, pct = (int)(100 * fraction);
    if (pct == *last)
        return;
    *last = pct;
    fprintf(stderr, "\r%s %3d%%", stage, pct);
    fflush(stderr);
}

double cb_cli_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}
