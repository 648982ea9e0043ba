/* corpus_run.h — running one Boolean of two STEP files through Colibri (`colibri bool OP A B
 * -o X.stl --json R.json --quiet`) or Open CASCADE (`occt_bool 1 A B OP`) as a subprocess with a
 * time limit, and reading what it did into a corpus_outcome (corpus.h), shared by the runners
 * of the randomized corpus (bench_corpus: primitives; bench_parts: real parts against moved
 * copies) so that both read the tools alike.
 *
 * Each process is started by posix_spawn in a process group of its own and killed with the
 * group at the time limit. Times: Colibri's is the Boolean's own (intersection + splitting +
 * sewing from its report, without reading the files or checking the result), OCCT's its
 * Boolean's build time; the wall time of each process is kept too. OCCT's volume is in
 * millimetres (its reader converts), Colibri's in the file's unit.
 * Header-only (static inline); define _DEFAULT_SOURCE before any include. */
#ifndef CB_BENCH_CORPUS_RUN_H
#define CB_BENCH_CORPUS_RUN_H

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "bench/corpus/corpus.h"
#include "io/json.h"

extern char **environ;

static inline double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Runs argv (argv[0] a path) with stdout into out_path and stderr into err_path, in a process
 * group of its own, killing the group after timeout seconds. Returns the exit status, or -1
 * when it could not start, ended on a signal (*sig) or was stopped (*timed_out). */
static inline int run_limited(char *const argv[], const char *out_path, const char *err_path,
                       double timeout, int *timed_out, int *sig, double *wall)
{
    *timed_out = *sig = 0;
    *wall = NAN;
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, out_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&fa, 2, err_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawnattr_t at;
    posix_spawnattr_init(&at);
    posix_spawnattr_setflags(&at, POSIX_SPAWN_SETPGROUP);
    posix_spawnattr_setpgroup(&at, 0);
    pid_t pid;
    double t0 = now_s();
    int rc = posix_spawn(&pid, argv[0], &fa, &at, argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    posix_spawnattr_destroy(&at);
    if (rc) {
        FILE *e = fopen(err_path, "w");
        if (e) {
            fprintf(e, "cannot start %s: %s\n", argv[0], strerror(rc));
            fclose(e);
        }
        return -1;
    }
    int status = 0;
    long nap_us = 1000;
    for (;;) {
        pid_t w = waitpid(pid, &status, WNOHANG);
        if (w == pid)
            break;
        if (w < 0 && errno != EINTR)
            return -1;
        if (now_s() - t0 > timeout) {
            kill(-pid, SIGKILL);
            waitpid(pid, &status, 0);
            *timed_out = 1;
            *wall = now_s() - t0;
            return -1;
        }
        usleep((useconds_t)nap_us);
        if (nap_us < 20000)
            nap_us += nap_us / 2;
    }
    *wall = now_s() - t0;
    if (WIFSIGNALED(status)) {
        *sig = WTERMSIG(status);
        return -1;
    }
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/* The whole of a small file as a string (at most cap - 1 bytes); 0 when it cannot be read. */
static inline int slurp(char *out, size_t cap, const char *path)
{
    out[0] = 0;
    FILE *f = fopen(path, "r");
    if (!f)
        return 0;
    size_t n = fread(out, 1, cap - 1, f);
    out[n] = 0;
    fclose(f);
    return 1;
}

/* The first non-blank line of text into out, without a leading "colibri: ". */
static inline void first_line(char *out, size_t n, const char *text)
{
    while (*text == '\n' || *text == ' ')
        text++;
    if (!strncmp(text, "colibri: ", 9))
        text += 9;
    size_t k = strcspn(text, "\n");
    snprintf(out, n, "%.*s", (int)(k < n - 1 ? k : n - 1), text);
}

typedef struct {
    const char *colibri, *occt, *dir, *tmp;
    double timeout;
    int threads;
} run_opts;

static inline void run_colibri(corpus_outcome *o, const char *pa, const char *pb, int op,
                               const run_opts *ro)
{
    corpus_outcome_init(o);
    char stl[600], rep[600], out[600], err[600], th[16];
    snprintf(stl, sizeof stl, "%s/result.stl", ro->tmp);
    snprintf(rep, sizeof rep, "%s/report.json", ro->tmp);
    snprintf(out, sizeof out, "%s/stdout.txt", ro->tmp);
    snprintf(err, sizeof err, "%s/stderr.txt", ro->tmp);
    snprintf(th, sizeof th, "%d", ro->threads);
    remove(rep);
    remove(stl);
    char *argv[16];
    int k = 0;
    argv[k++] = (char *)ro->colibri;
    argv[k++] = "bool";
    argv[k++] = (char *)corpus_op_names[op];
    argv[k++] = (char *)pa;
    argv[k++] = (char *)pb;
    argv[k++] = "-o";
    argv[k++] = stl;
    argv[k++] = "--json";
    argv[k++] = rep;
    argv[k++] = "--quiet";
    if (ro->threads > 0) {
        argv[k++] = "--threads";
        argv[k++] = th;
    }
    argv[k] = NULL;
    int rc = run_limited(argv, out, err, ro->timeout, &o->timed_out, &o->signal, &o->wall_s);
    static char text[1 << 16];
    if (o->timed_out || o->signal)
        return;
    int have = slurp(text, sizeof text, rep) && strstr(text, "\"status\"");
    if (have) {
        char status[16] = "";
        corpus_json_string(status, sizeof status, text, "status");
        corpus_json_string(o->message, sizeof o->message, text, "message");
        o->reported_ok = rc == 0 && !strcmp(status, "ok");
        o->valid = corpus_json_bool(text, "valid") == 1;
        o->volume = corpus_json_number(text, "volume");
        const char *mesh = corpus_json_value(text, "mesh");
        if (mesh && *mesh == '{') {
            o->mesh_checked = 1;
            o->closed = corpus_json_bool(mesh, "closed") == 1;
            o->clean = corpus_json_bool(mesh, "manifold") == 1 &&
                       corpus_json_number(mesh, "self_intersections") == 0;
            /* cli/result.c says so when every contact of the mesh with itself was proved a
             * touching, none crossing. */
            o->touching_mesh = strstr(o->message, "none crossing") != NULL;
        }
        const char *t = corpus_json_value(text, "time_s");
        if (t)
            o->time_s = corpus_json_number(t, "ssi") + corpus_json_number(t, "split") +
                        corpus_json_number(t, "classify");
    }
    if (!o->reported_ok && !o->message[0]) {
        slurp(text, sizeof text, err);
        first_line(o->message, sizeof o->message, text);
        if (!o->message[0])
            snprintf(o->message, sizeof o->message, "exit status %d, no report", rc);
    }
}

static inline void run_occt(corpus_outcome *o, const char *pa, const char *pb, int op,
                            const run_opts *ro)
{
    corpus_outcome_init(o);
    char out[600], err[600];
    snprintf(out, sizeof out, "%s/occt_stdout.txt", ro->tmp);
    snprintf(err, sizeof err, "%s/occt_stderr.txt", ro->tmp);
    char *argv[] = {(char *)ro->occt, "1", (char *)pa, (char *)pb, (char *)corpus_op_names[op], NULL};
    int rc = run_limited(argv, out, err, ro->timeout, &o->timed_out, &o->signal, &o->wall_s);
    if (o->timed_out || o->signal)
        return;
    static char text[1 << 14];
    slurp(text, sizeof text, out);
    char name[32];
    double ms[3], v;
    int error, valid, faces;
    if (rc != 0 || sscanf(text, "%31s %lf %lf %lf %d %d %d %lf", name, ms, ms + 1, ms + 2, &error,
                          &valid, &faces, &v) != 8) {
        slurp(text, sizeof text, err);
        first_line(o->message, sizeof o->message, text);
        if (!o->message[0])
            snprintf(o->message, sizeof o->message, "occt_bool: exit status %d, no figures", rc);
        return;
    }
    o->time_s = 1e-3 * ms[0];
    if (error) {
        snprintf(o->message, sizeof o->message, "OCCT reports an error");
        return;
    }
    o->reported_ok = 1;
    o->valid = valid;
    o->volume = v;
}

/* One tool's run of one case: its outcome, verdict and the reason. */
typedef struct {
    corpus_outcome o;
    corpus_verdict v;
    char why[512];
} corpus_side;

/* One side as a JSON object under key: verdict, reason, volume, time_s, wall_s (null where
 * not known). */
static inline void corpus_json_side(FILE *f, const char *key, const corpus_side *s)
{
    fprintf(f, "\"%s\": {\"verdict\": \"%s\", \"reason\": ", key, corpus_verdict_names[s->v]);
    cb_json_string(f, s->why);
    fputs(", \"volume\": ", f);
    if (isfinite(s->o.volume))
        fprintf(f, "%.17g", s->o.volume);
    else
        fputs("null", f);
    fputs(", \"time_s\": ", f);
    if (isfinite(s->o.time_s))
        fprintf(f, "%.4f", s->o.time_s);
    else
        fputs("null", f);
    fputs(", \"wall_s\": ", f);
    if (isfinite(s->o.wall_s))
        fprintf(f, "%.4f", s->o.wall_s);
    else
        fputs("null", f);
    fputs("}", f);
}

#endif
