/* args.c — the option values, the progress line and the clock every command shares. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "brep/topo.h"
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

void cb_cli_move_init(cb_cli_move *m)
{
    memset(m, 0, sizeof *m);
    m->axis[2] = 1;
}

int cb_cli_move_parse(cb_cli_move *m, int argc, char **argv, int *k, const char *command)
{
    const char *a = argv[*k];
    int rotate = !strcmp(a, "--rotate-b");
    if (!rotate && strcmp(a, "--translate-b"))
        return 0;
    int n = rotate ? 4 : 3;
    double v[4];
    for (int i = 0; i < n; i++) {
        char *end = NULL;
        v[i] = *k + 1 + i < argc ? strtod(argv[*k + 1 + i], &end) : NAN;
        if (!end || end == argv[*k + 1 + i] || *end || !isfinite(v[i])) {
            fprintf(stderr, "colibri: %s: %s needs %d numbers\n", command, a, n);
            return -1;
        }
    }
    if (rotate && v[3] != 0 && !(fabs(v[0]) + fabs(v[1]) + fabs(v[2]) > 0)) {
        fprintf(stderr, "colibri: %s: --rotate-b: the axis is zero\n", command);
        return -1;
    }
    if (rotate) {
        memcpy(m->axis, v, sizeof m->axis);
        m->deg = v[3];
    } else {
        memcpy(m->shift, v, sizeof m->shift);
    }
    *k += n;
    m->set = 1;
    return 1;
}

void cb_cli_move_apply(const cb_cli_move *m, cb_topo_body *b)
{
    if (!m->set)
        return;
    cb_xform r, t, x;
    const double origin[3] = {0, 0, 0};
    if (m->deg != 0)
        cb_xform_rotation(&r, origin, m->axis, m->deg * 3.14159265358979323846 / 180);
    else
        cb_xform_identity(&r);
    cb_xform_translation(&t, m->shift);
    cb_xform_compose(&x, &t, &r);
    cb_topo_body_transform(b, &x);
}
