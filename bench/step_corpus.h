/* step_corpus.h — loading the shared corpus of real STEP files (../shared/corpus/step/) with
 * `colibri info --json`, each file in a process of its own with a wall-time limit, and scoring
 * the result against Open CASCADE's figures (../shared/corpus/occt-reference.json, see
 * ../shared/corpus/SOURCES.md). Shared by bench/bench_step_corpus.c (the table) and
 * tests/test_step_corpus.c (the regression test); header-only, as every bench and test is a
 * program of its own. Define _DEFAULT_SOURCE before any include.
 *
 * Outcome classes, checked in this order:
 *   crash      the process ended by a signal, or its exit status is none of 0, 1, 2, or its
 *              JSON could not be read, or a sanitizer reported an error on stderr;
 *   timeout    still running at the limit (killed);
 *   not loaded exit status 2 (an input that cannot be used): the reader's message;
 *   solids     loaded with a number of solids other than OCCT's (OCCT expands assemblies
 *              into placed instances);
 *   invalid    loaded, not valid (exit status 1: `colibri info` validates the body);
 *   no volume  valid, but the volume and area were not integrated (mass_error);
 *   volume     the volume, converted to mm^3 by unit_mm, differs from OCCT's by more than
 *              STEPC_REL_TOL relative (where OCCT has no volume: the area, in mm^2);
 *   ok         the same number of solids, valid, the same volume (or area).
 * A file OCCT transfers nothing from (`"occt": null`) is `ok` when Colibri refuses it too,
 * with a message (exit status 2), and `loaded` when Colibri reads something. */
#ifndef CB_BENCH_STEP_CORPUS_H
#define CB_BENCH_STEP_CORPUS_H

#include <ctype.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

extern char **environ;

/* Relative agreement asked of the volume (or area) against OCCT's, whose integration converged
 * to about 1e-7 (SOURCES.md). */
#define STEPC_REL_TOL 1e-6

typedef enum {
    STEPC_OK,
    STEPC_NOT_LOADED,
    STEPC_SOLIDS,
    STEPC_INVALID,
    STEPC_NO_VOLUME,
    STEPC_VOLUME,
    STEPC_TIMEOUT,
    STEPC_CRASH,
    STEPC_LOADED, /* OCCT found no shape, Colibri read one */
    STEPC_N_OUTCOMES
} stepc_outcome;

static const char *const STEPC_NAMES[STEPC_N_OUTCOMES] = {
    "ok", "not_loaded", "solids", "invalid", "no_volume", "volume", "timeout", "crash", "loaded"};

static inline int stepc_outcome_parse(const char *s)
{
    for (int k = 0; k < STEPC_N_OUTCOMES; k++)
        if (!strcmp(s, STEPC_NAMES[k]))
            return k;
    return -1;
}

/* ---------------------------------------------------------------- OCCT's figures ----------- */

typedef struct {
    char file[128];
    int has_occt;         /* 0: "occt": null */
    int solids, shells, faces;
    int valid;
    double volume, area;  /* NAN where null */
} stepc_ref;

/* The text after "key": inside [p, end), or NULL. */
static inline const char *stepc_value(const char *p, const char *end, const char *key)
{
    char pat[64];
    int n = snprintf(pat, sizeof pat, "\"%s\":", key);
    for (const char *q = p; q && q + n <= end; q++) {
        q = memchr(q, '"', (size_t)(end - q));
        if (!q || q + n > end)
            return NULL;
        if (!memcmp(q, pat, (size_t)n)) {
            q += n;
            while (q < end && isspace((unsigned char)*q))
                q++;
            return q;
        }
    }
    return NULL;
}

static inline double stepc_number(const char *p, const char *end, const char *key)
{
    const char *v = stepc_value(p, end, key);
    if (!v || !strncmp(v, "null", 4))
        return NAN;
    char *e;
    double x = strtod(v, &e);
    return e == v ? NAN : x;
}

/* 1 true, 0 false, -1 absent. */
static inline int stepc_bool(const char *p, const char *end, const char *key)
{
    const char *v = stepc_value(p, end, key);
    return !v ? -1 : !strncmp(v, "true", 4) ? 1 : !strncmp(v, "false", 5) ? 0 : -1;
}

/* A JSON string value (no escapes expected in file names; \" and \\ are undone). */
static inline int stepc_string(char *out, size_t n, const char *p, const char *end,
                               const char *key)
{
    const char *v = stepc_value(p, end, key);
    if (!v || *v != '"')
        return 0;
    size_t k = 0;
    for (v++; v < end && *v != '"'; v++) {
        if (*v == '\\' && v + 1 < end)
            v++;
        if (k + 1 < n)
            out[k++] = *v;
    }
    out[k] = '\0';
    return 1;
}

/* The end of the JSON object or array starting at p (one past its closing bracket), strings
 * skipped; NULL if it does not close before end. */
static inline const char *stepc_close(const char *p, const char *end)
{
    int depth = 0;
    for (; p < end; p++) {
        if (*p == '"') {
            for (p++; p < end && *p != '"'; p++)
                if (*p == '\\')
                    p++;
        } else if (*p == '{' || *p == '[') {
            depth++;
        } else if (*p == '}' || *p == ']') {
            if (--depth == 0)
                return p + 1;
        }
    }
    return NULL;
}

static inline char *stepc_slurp(const char *path, size_t *len)
{
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return NULL;
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap + 1);
    size_t got;
    while (buf && (got = fread(buf + n, 1, cap - n, fp)) > 0) {
        n += got;
        if (n == cap) {
            char *b2 = realloc(buf, 2 * cap + 1);
            if (!b2) {
                free(buf);
                buf = NULL;
                break;
            }
            buf = b2;
            cap *= 2;
        }
    }
    fclose(fp);
    if (buf)
        buf[n] = '\0';
    *len = n;
    return buf;
}

/* Reads occt-reference.json (an array of {file, occt}) into a new array *refs of *n (free it);
 * 0 on success, -1 with a message on stderr. */
static inline int stepc_read_refs(stepc_ref **refs, int *n, const char *path)
{
    size_t len;
    char *buf = stepc_slurp(path, &len);
    *refs = NULL;
    *n = 0;
    if (!buf) {
        fprintf(stderr, "%s: %s\n", path, strerror(errno));
        return -1;
    }
    const char *p = buf, *end = buf + len;
    int cap = 0;
    while ((p = memchr(p, '{', (size_t)(end - p)))) {
        const char *q = stepc_close(p, end);
        if (!q)
            break;
        if (*n == cap) {
            cap = cap ? 2 * cap : 256;
            stepc_ref *r2 = realloc(*refs, (size_t)cap * sizeof **refs);
            if (!r2)
                break;
            *refs = r2;
        }
        stepc_ref *r = &(*refs)[*n];
        memset(r, 0, sizeof *r);
        if (!stepc_string(r->file, sizeof r->file, p, q, "file")) {
            fprintf(stderr, "%s: an entry without \"file\"\n", path);
            free(buf);
            return -1;
        }
        const char *o = stepc_value(p, q, "occt");
        r->volume = r->area = NAN;
        if (o && *o == '{') {
            const char *oe = stepc_close(o, q);
            r->has_occt = 1;
            r->solids = (int)stepc_number(o, oe, "solids");
            r->shells = (int)stepc_number(o, oe, "shells");
            r->faces = (int)stepc_number(o, oe, "faces");
            r->valid = stepc_bool(o, oe, "valid") == 1;
            r->volume = stepc_number(o, oe, "volume");
            r->area = stepc_number(o, oe, "area");
        }
        (*n)++;
        p = q;
    }
    free(buf);
    if (!*n) {
        fprintf(stderr, "%s: no entries\n", path);
        return -1;
    }
    return 0;
}

/* The files OCCT reads as valid solids: the acceptance set of issue 25 (130 files). */
static inline int stepc_occt_valid(const stepc_ref *r)
{
    return r->has_occt && r->valid && r->solids > 0;
}

/* ---------------------------------------------------------------- running colibri ---------- */

enum { STEPC_OUT_CAP = 1 << 20, STEPC_ERR_CAP = 4096 };

typedef struct {
    /* what was run */
    const stepc_ref *ref;
    char path[1024];
    /* the process */
    pid_t pid;
    int fd_out, fd_err;
    double start, elapsed;
    int status;           /* exit status; -1 killed by a signal */
    int signal;
    int timed_out;
    char *out;            /* stdout, NUL-terminated */
    size_t n_out;
    char err[STEPC_ERR_CAP];
    size_t n_err;
    /* the score */
    stepc_outcome outcome;
    int solids, valid;
    double volume_mm3, area_mm2, rel_err; /* NAN where absent */
    char detail[512];     /* the reader's message, a mass error, a validation problem */
} stepc_run;

static inline double stepc_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Starts `colibri info --json path` with stdout and stderr into pipes; 0 on success. */
static inline int stepc_start(stepc_run *run, const char *colibri)
{
    int po[2], pe[2];
    if (pipe(po))
        return -1;
    if (pipe(pe)) {
        close(po[0]);
        close(po[1]);
        return -1;
    }
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_adddup2(&fa, po[1], 1);
    posix_spawn_file_actions_adddup2(&fa, pe[1], 2);
    posix_spawn_file_actions_addclose(&fa, po[0]);
    posix_spawn_file_actions_addclose(&fa, po[1]);
    posix_spawn_file_actions_addclose(&fa, pe[0]);
    posix_spawn_file_actions_addclose(&fa, pe[1]);
    char *argv[] = {(char *)colibri, "info", "--json", run->path, NULL};
    int rc = posix_spawn(&run->pid, colibri, &fa, NULL, argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    close(po[1]);
    close(pe[1]);
    if (rc) {
        close(po[0]);
        close(pe[0]);
        return -1;
    }
    run->fd_out = po[0];
    run->fd_err = pe[0];
    fcntl(run->fd_out, F_SETFL, O_NONBLOCK);
    fcntl(run->fd_err, F_SETFL, O_NONBLOCK);
    run->out = malloc(STEPC_OUT_CAP + 1);
    run->n_out = run->n_err = 0;
    run->start = stepc_now();
    run->timed_out = 0;
    run->signal = 0;
    return run->out ? 0 : -1;
}

/* Reads what is available on fd into buf (cap bytes, the rest drained); 1 at end of file. */
static inline int stepc_drain(int fd, char *buf, size_t cap, size_t *n)
{
    char sink[4096];
    for (;;) {
        ssize_t got = *n < cap ? read(fd, buf + *n, cap - *n) : read(fd, sink, sizeof sink);
        if (got > 0) {
            if (*n < cap)
                *n += (size_t)got;
            continue;
        }
        if (got == 0)
            return 1;
        return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR ? 0 : 1;
    }
}

/* Drives up to `jobs` runs at a time over runs[0 .. n), each limited to limit_s seconds of wall
 * time (then SIGKILL); done(run, arg) is called as each ends. */
static inline void stepc_run_all(stepc_run *runs, int n, const char *colibri, double limit_s,
                                 int jobs, void (*done)(stepc_run *, void *), void *arg)
{
    enum { MAX_JOBS = 16 };
    if (jobs < 1)
        jobs = 1;
    if (jobs > MAX_JOBS)
        jobs = MAX_JOBS;
    stepc_run *live[MAX_JOBS];
    int open_fds[MAX_JOBS][2];
    int n_live = 0, next = 0;
    while (next < n || n_live) {
        while (n_live < jobs && next < n) {
            stepc_run *r = &runs[next++];
            if (stepc_start(r, colibri)) {
                r->status = -1;
                r->elapsed = 0;
                snprintf(r->err, sizeof r->err, "could not start %s", colibri);
                r->n_err = strlen(r->err);
                r->fd_out = r->fd_err = -1;
                done(r, arg);
                continue;
            }
            live[n_live] = r;
            open_fds[n_live][0] = open_fds[n_live][1] = 1;
            n_live++;
        }
        if (!n_live)
            break;
        struct pollfd pfd[2 * MAX_JOBS];
        int np = 0;
        for (int k = 0; k < n_live; k++) {
            pfd[np++] = (struct pollfd){.fd = open_fds[k][0] ? live[k]->fd_out : -1,
                                        .events = POLLIN};
            pfd[np++] = (struct pollfd){.fd = open_fds[k][1] ? live[k]->fd_err : -1,
                                        .events = POLLIN};
        }
        poll(pfd, (nfds_t)np, 100);
        double t = stepc_now();
        for (int k = 0; k < n_live; k++) {
            stepc_run *r = live[k];
            if (open_fds[k][0] && stepc_drain(r->fd_out, r->out, STEPC_OUT_CAP, &r->n_out))
                open_fds[k][0] = 0;
            if (open_fds[k][1] &&
                stepc_drain(r->fd_err, r->err, STEPC_ERR_CAP - 1, &r->n_err))
                open_fds[k][1] = 0;
            if (!r->timed_out && t - r->start > limit_s) {
                r->timed_out = 1;
                kill(r->pid, SIGKILL);
            }
            if (open_fds[k][0] || open_fds[k][1])
                continue;
            int status;
            if (waitpid(r->pid, &status, 0) != r->pid)
                status = -1;
            r->elapsed = stepc_now() - r->start;
            close(r->fd_out);
            close(r->fd_err);
            r->out[r->n_out] = '\0';
            r->err[r->n_err] = '\0';
            if (status != -1 && WIFEXITED(status)) {
                r->status = WEXITSTATUS(status);
            } else {
                r->status = -1;
                r->signal = status != -1 && WIFSIGNALED(status) ? WTERMSIG(status) : 0;
            }
            done(r, arg);
            live[k] = live[n_live - 1];
            open_fds[k][0] = open_fds[n_live - 1][0];
            open_fds[k][1] = open_fds[n_live - 1][1];
            n_live--;
            k--;
        }
    }
}

/* The first line of s into out, without the "colibri: " prefix and the path the message
 * starts with. */
static inline void stepc_first_line(char *out, size_t n, const char *s, const char *path)
{
    if (!strncmp(s, "colibri: ", 9))
        s += 9;
    size_t pl = strlen(path);
    if (!strncmp(s, path, pl) && s[pl] == ':')
        s += pl + 1;
    while (*s == ' ')
        s++;
    size_t k = 0;
    while (s[k] && s[k] != '\n' && k + 1 < n) {
        out[k] = s[k];
        k++;
    }
    out[k] = '\0';
}

/* Scores a finished run against its reference (see the top of this file). */
static inline void stepc_score(stepc_run *r)
{
    const stepc_ref *ref = r->ref;
    r->solids = -1;
    r->valid = 0;
    r->volume_mm3 = r->area_mm2 = r->rel_err = NAN;
    r->detail[0] = '\0';
    if (r->timed_out) {
        r->outcome = STEPC_TIMEOUT;
        snprintf(r->detail, sizeof r->detail, "killed after %.0f s", r->elapsed);
        return;
    }
    /* A sanitizer build reports through stderr and may exit with any status (1 by default). */
    if (strstr(r->err, "Sanitizer") || strstr(r->err, "runtime error:")) {
        r->outcome = STEPC_CRASH;
        const char *at = strstr(r->err, "Sanitizer") ? strstr(r->err, "Sanitizer")
                                                      : strstr(r->err, "runtime error:");
        snprintf(r->detail, sizeof r->detail, "%.200s", at);
        for (char *c = r->detail; *c; c++)
            if (*c == '\n')
                *c = ' ';
        return;
    }
    if (r->status == 2) {
        stepc_first_line(r->detail, sizeof r->detail, r->err, r->path);
        r->outcome = ref->has_occt ? STEPC_NOT_LOADED : STEPC_OK;
        return;
    }
    const char *o = r->out, *oe = r->out ? r->out + r->n_out : NULL;
    int valid = o ? stepc_bool(o, oe, "valid") : -1;
    double solids = o ? stepc_number(o, oe, "solids") : NAN;
    if ((r->status != 0 && r->status != 1) || valid < 0 || isnan(solids)) {
        r->outcome = STEPC_CRASH;
        if (r->signal)
            snprintf(r->detail, sizeof r->detail, "signal %d", r->signal);
        else
            snprintf(r->detail, sizeof r->detail, "exit status %d", r->status);
        if (r->n_err) {
            size_t k = strlen(r->detail);
            r->detail[k++] = ':';
            r->detail[k++] = ' ';
            stepc_first_line(r->detail + k, sizeof r->detail - k, r->err, r->path);
        }
        return;
    }
    r->solids = (int)solids;
    r->valid = valid;
    double unit = stepc_number(o, oe, "unit_mm");
    if (!(unit > 0))
        unit = 1;
    r->volume_mm3 = stepc_number(o, oe, "volume") * unit * unit * unit;
    r->area_mm2 = stepc_number(o, oe, "area") * unit * unit;
    if (!ref->has_occt) {
        r->outcome = STEPC_LOADED;
        return;
    }
    if (r->solids != ref->solids) {
        r->outcome = STEPC_SOLIDS;
        snprintf(r->detail, sizeof r->detail, "%d solids, OCCT %d", r->solids, ref->solids);
        return;
    }
    if (!valid) {
        r->outcome = STEPC_INVALID;
        const char *pr = stepc_value(o, oe, "problems");
        char msg[400] = "";
        /* the first problem: the string after '[' */
        if (pr && pr[0] == '[' && pr[1] == '"') {
            size_t k = 0;
            for (const char *q = pr + 2; q < oe && *q != '"' && k + 1 < sizeof msg; q++) {
                if (*q == '\\' && q + 1 < oe)
                    q++;
                msg[k++] = *q;
            }
            msg[k] = '\0';
        }
        snprintf(r->detail, sizeof r->detail, "%s", msg);
        return;
    }
    int by_area = isnan(ref->volume);
    double mine = by_area ? r->area_mm2 : r->volume_mm3, theirs = by_area ? ref->area : ref->volume;
    if (isnan(mine)) {
        r->outcome = STEPC_NO_VOLUME;
        stepc_string(r->detail, sizeof r->detail, o, oe, "mass_error");
        return;
    }
    if (isnan(theirs)) {
        r->outcome = STEPC_OK;
        return;
    }
    r->rel_err = fabs(mine - theirs) / fmax(fabs(theirs), 1e-300);
    if (r->rel_err > STEPC_REL_TOL) {
        r->outcome = STEPC_VOLUME;
        snprintf(r->detail, sizeof r->detail, "%s %.10g, OCCT %.10g", by_area ? "area" : "volume",
                 mine, theirs);
        return;
    }
    r->outcome = STEPC_OK;
}

/* The tally key of a message: the text after "line: #id " with digits runs and numbers
 * replaced by N, so that one kind of failure on many files counts once. */
static inline void stepc_reason_key(char *out, size_t n, const char *msg)
{
    const char *s = msg;
    /* skip "LINE: " */
    const char *c = strchr(s, ':');
    if (c && c > s) {
        const char *d = s;
        while (d < c && isdigit((unsigned char)*d))
            d++;
        if (d == c)
            s = c + 1;
    }
    while (*s == ' ')
        s++;
    if (*s == '#') {
        s++;
        while (isdigit((unsigned char)*s))
            s++;
        while (*s == ' ')
            s++;
    }
    size_t k = 0;
    while (*s && k + 2 < n) {
        if (isdigit((unsigned char)*s) || ((*s == '-' || *s == '.') && isdigit((unsigned char)s[1]))) {
            out[k++] = 'N';
            while (*s && (isdigit((unsigned char)*s) || *s == '.' || *s == 'e' || *s == 'E' ||
                          *s == '-' || *s == '+'))
                s++;
            continue;
        }
        out[k++] = *s++;
    }
    out[k] = '\0';
}

#endif
