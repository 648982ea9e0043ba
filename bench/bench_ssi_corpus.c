/* The randomized SSI corpus of graph cases (issue 22, class 2), Colibri beside Open CASCADE:
 * pairs of whole B-spline surfaces with a designed intersection (cb_graph_case, models.h: every
 * class of the paper's Fig. 1 and more, in the exact pose of the shipped graph pairs, with
 * generic parametrisations under an axis-permuting motion, and fully generic), each run in a
 * process of its own with a time limit, scored by one set of rules (bench_ssi_score.h):
 *   pass     topology right (closed and open components, isolated points, no broken curve;
 *            Colibri's tangential flags), every output point on both surfaces and on the
 *            designed curve, the designed curve covered;
 *   refused  Colibri reported patch pairs it could not certify (or an error); OCCT: not done;
 *   WRONG    reported done (Colibri: every pair certified) but the result fails a rule;
 *   crash    the process ended on a signal or without a readable result;
 *   timeout  stopped at the time limit.
 * Colibri runs cb_ssi_surfaces with the default tolerance (1e-6 of the model size), chords of
 * 5e-5 of the size (the coverage bound is 2e-4) and 1 thread; OCCT GeomInt_IntSS (occt_ssi, the
 * comparator of bench_ssi_cases) with the same tolerance.
 *
 * Usage: bench_ssi_corpus [--occt OCCT_SSI] [--json OUT] [--timeout S] [--counts E P G]
 *                         [--only TEXT] [--threads N] [--list] [--dump]
 *   --counts: cases per class in the exact, param and generic poses (default 2 3 9: 210 cases)
 *   --only:   only the cases whose id ("class/pose/index") starts with TEXT
 *   --dump:   each output's curves and points in the design plane
 * (bench_ssi_corpus --child CLASS POSE INDEX THREADS is the per-case process.) */
#define _DEFAULT_SOURCE /* kill, poll */
#include <errno.h>
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

#include "bench/bench_spawn.h"
#include "bench/bench_ssi_pair.h"
#include "bench/bench_ssi_score.h"
#include "io/json.h"
#include "models/models.h"
#include "ssi/ssi.h"

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* ---------------------------------------------------------------- the child ---------------- */

static int child(int cls, int pose, int index, int threads)
{
    cb_graph_case c;
    cb_graph_case_init(&c);
    cb_error err;
    cb_error_clear(&err);
    if (cb_graph_case_make(&c, cls, pose, index, &err)) {
        printf("B %s\n", err.msg);
        return 0;
    }
    ssc_run run;
    ssc_output o;
    memset(&o, 0, sizeof o);
    if (!ssc_colibri(&run, &o, &c, threads, now))
        return 1;
    printf("R %d %ld %.6f %.17g %ld %ld %ld", run.status, run.failed, run.time, run.tol,
           run.subpairs, run.pairs, run.subdivided);
    for (int i = 0; i < SSC_N_REASONS; i++)
        printf(" %ld", run.reason[i]);
    printf("\nM %s\n", run.msg);
    for (int k = 0; k < run.n_where; k++)
        printf("W %.6f %.6f %.6f\n", run.where[k][0], run.where[k][1], run.where[k][2]);
    for (int k = 0; k < o.n_curves; k++) {
        const ssc_curve *cv = o.curve + k;
        printf("C %d %d %d\n", cv->n, cv->closed, cv->tangential);
        for (int i = 0; i < cv->n; i++)
            printf("%.17g %.17g %.17g\n", cv->p[3 * i], cv->p[3 * i + 1], cv->p[3 * i + 2]);
    }
    for (int k = 0; k < o.n_points; k++)
        printf("P %.17g %.17g %.17g\n", o.point[3 * k], o.point[3 * k + 1], o.point[3 * k + 2]);
    printf("E\n");
    ssc_output_clear(&o);
    cb_graph_case_clear(&c);
    return 0;
}

/* ---------------------------------------------------------------- processes ---------------- */

typedef enum { RUN_OK, RUN_CRASH, RUN_TIMEOUT } run_end;

/* Runs argv with stdout into a growing buffer *out (NUL-terminated, free it), stopped by
 * SIGKILL after timeout seconds. Returns how it ended; *code its exit status. */
static run_end run_timed(char **out, size_t *len, char *const argv[], double timeout, int *code,
                         double *wall)
{
    *out = NULL;
    *len = 0;
    *code = -1;
    int fd[1];
    pid_t pid;
    double t0 = now();
    if (spawn_piped(&pid, fd, argv))
        return RUN_CRASH;
    size_t cap = 1 << 16;
    char *buf = malloc(cap);
    int killed = 0;
    if (!buf)
        kill(pid, SIGKILL);
    while (buf) {
        double left = timeout - (now() - t0);
        if (left <= 0) {
            kill(pid, SIGKILL);
            killed = 1;
            break;
        }
        struct pollfd p = {fd[0], POLLIN, 0};
        int k = poll(&p, 1, (int)fmin(left * 1000 + 1, 1000));
        if (k < 0 && errno == EINTR)
            continue;
        if (k <= 0)
            continue;
        if (*len + 4096 + 1 > cap) {
            char *b = realloc(buf, cap *= 2);
            if (!b) {
                /* No room for its output: stop it rather than leave it blocked on the pipe. */
                kill(pid, SIGKILL);
                break;
            }
            buf = b;
        }
        ssize_t n = read(fd[0], buf + *len, cap - *len - 1);
        if (n <= 0)
            break;
        *len += (size_t)n;
    }
    close(fd[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    *wall = now() - t0;
    if (buf)
        buf[*len] = 0;
    *out = buf;
    if (killed)
        return RUN_TIMEOUT;
    if (WIFSIGNALED(status))
        return RUN_CRASH;
    *code = WEXITSTATUS(status);
    return RUN_OK;
}

/* ---------------------------------------------------------------- one side ----------------- */

typedef enum { V_PASS, V_REFUSED, V_WRONG, V_CRASH, V_TIMEOUT, V_NOT_RUN } verdict;
static const char *const VERDICT[6] = {"pass", "refused", "WRONG", "crash", "timeout", "-"};

typedef struct {
    verdict v;
    ssc_run run; /* time < 0 unknown; run.failed: Colibri's patch pairs not certified, OCCT's
                    not done */
    ssc_output out;
    ssc_score score;
} side;

/* Parses the child's output into s (not the verdict). Returns 0 when unreadable. */
static int parse_colibri(side *s, char *text)
{
    char *save = NULL, *line = strtok_r(text, "\n", &save);
    int have_r = 0, ended = 0;
    double *pts = NULL;
    ssc_run *r = &s->run;
    while (line) {
        if (line[0] == 'B') {
            snprintf(r->msg, sizeof r->msg, "not built: %.200s", line + 2);
            break;
        } else if (line[0] == 'R') {
            have_r = sscanf(line + 2, "%d %ld %lf %lf %ld %ld %ld %ld %ld %ld %ld %ld", &r->status,
                            &r->failed, &r->time, &r->tol, &r->subpairs, &r->pairs,
                            &r->subdivided, r->reason, r->reason + 1, r->reason + 2,
                            r->reason + 3, r->reason + 4) == 12;
        } else if (line[0] == 'M') {
            snprintf(r->msg, sizeof r->msg, "%s", line[1] ? line + 2 : "");
        } else if (line[0] == 'W' && r->n_where < SSC_WHERE) {
            double *w = r->where[r->n_where];
            r->n_where += sscanf(line + 2, "%lf %lf %lf", w, w + 1, w + 2) == 3;
        } else if (line[0] == 'C') {
            int n, closed, tang;
            if (sscanf(line + 2, "%d %d %d", &n, &closed, &tang) != 3 || n < 0)
                break;
            double *m = realloc(pts, (size_t)(n + 1) * 3 * sizeof(double));
            if (!m)
                break;
            pts = m;
            int ok = 1;
            for (int i = 0; i < n && ok; i++) {
                line = strtok_r(NULL, "\n", &save);
                ok = line && sscanf(line, "%lf %lf %lf", pts + 3 * i, pts + 3 * i + 1,
                                    pts + 3 * i + 2) == 3;
            }
            if (!ok || !ssc_output_add_curve(&s->out, pts, n, closed, tang))
                break;
        } else if (line[0] == 'P') {
            double X[3];
            if (sscanf(line + 2, "%lf %lf %lf", X, X + 1, X + 2) != 3 ||
                !ssc_output_add_point(&s->out, X))
                break;
        } else if (line[0] == 'E') {
            ended = 1;
            break;
        }
        line = strtok_r(NULL, "\n", &save);
    }
    free(pts);
    return have_r && ended;
}

/* occt_ssi's output: "MEDIAN MIN MAX DONE NL NP", curves "L n" and n points, points "P x y z". */
static int parse_occt(side *s, char *text)
{
    double ms[3];
    int done, nl, np, used = 0;
    if (sscanf(text, "%lf %lf %lf %d %d %d%n", ms, ms + 1, ms + 2, &done, &nl, &np, &used) != 6 ||
        nl < 0 || np < 0)
        return 0;
    s->run.time = 1e-3 * ms[0];
    s->run.failed = !done;
    if (!done)
        snprintf(s->run.msg, sizeof s->run.msg, "GeomInt_IntSS: not done");
    char *p = text + used;
    double *pts = NULL;
    int ok = 1;
    for (int i = 0; i < nl && ok; i++) {
        int n, k;
        ok = sscanf(p, " L %d%n", &n, &k) == 1 && n >= 0;
        if (!ok)
            break;
        p += k;
        pts = realloc(pts, (size_t)(n + 1) * 3 * sizeof(double));
        for (int j = 0; j < n && ok; j++) {
            ok = sscanf(p, "%lf %lf %lf%n", pts + 3 * j, pts + 3 * j + 1, pts + 3 * j + 2, &k) ==
                 3;
            p += k;
        }
        ok = ok && ssc_output_add_curve(&s->out, pts, n, -1, -1);
    }
    for (int i = 0; i < np && ok; i++) {
        double X[3];
        int k;
        ok = sscanf(p, " P %lf %lf %lf%n", X, X + 1, X + 2, &k) == 3 &&
             ssc_output_add_point(&s->out, X);
        p += k;
    }
    free(pts);
    return ok;
}

/* Each curve of an output in the design plane: points, ends, flags (--dump). */
static void dump(const char *who, const side *s, const cb_graph_case *c)
{
    printf("    %s: %d curves, %d points\n", who, s->out.n_curves, s->out.n_points);
    for (int k = 0; k < s->out.n_curves; k++) {
        const ssc_curve *cv = s->out.curve + k;
        double a[3] = {0}, b[3] = {0};
        if (cv->n) {
            cb_graph_case_design(a, c, cv->p);
            cb_graph_case_design(b, c, cv->p + 3 * (cv->n - 1));
        }
        printf("      curve %d: %d points, (%.6f, %.6f) -> (%.6f, %.6f), closed %d, tangential "
               "%d\n",
               k, cv->n, a[0], a[1], b[0], b[1], cv->closed, cv->tangential);
    }
    for (int k = 0; k < s->out.n_points; k++) {
        double a[3];
        cb_graph_case_design(a, c, s->out.point + 3 * k);
        printf("      point %d: (%.6f, %.6f)\n", k, a[0], a[1]);
    }
    for (int k = 0; k < s->run.n_where; k++)
        printf("      not certified: region about (%.6f, %.6f), %.2g across\n",
               s->run.where[k][0], s->run.where[k][1], s->run.where[k][2]);
}

static void judge(side *s, const cb_graph_case *c, double tol)
{
    if (s->run.failed) {
        s->v = V_REFUSED;
        return;
    }
    if (!ssc_score_output(&s->score, c, &s->out, tol)) {
        s->v = V_CRASH;
        snprintf(s->run.msg, sizeof s->run.msg, "scoring ran out of memory");
        return;
    }
    s->v = s->score.topology_ok && s->score.geometry_ok ? V_PASS : V_WRONG;
}

/* ---------------------------------------------------------------- the table ---------------- */

/* Cases grouped by side and by the kind of their failure, for the summary. */
#define MAX_GROUPS 64
typedef struct {
    char kind[80];
    int side, count;
    char ids[400];
} group;

static group groups[MAX_GROUPS];
static int n_groups;

static void group_add(int sd, const char *kind, const char *id)
{
    int k = 0;
    while (k < n_groups && (groups[k].side != sd || strcmp(groups[k].kind, kind)))
        k++;
    if (k == n_groups) {
        if (n_groups == MAX_GROUPS)
            return;
        n_groups++;
        groups[k].side = sd;
        snprintf(groups[k].kind, sizeof groups[k].kind, "%.79s", kind);
    }
    group *g = groups + k;
    size_t len = strlen(g->ids);
    if (len + strlen(id) + 8 < sizeof g->ids)
        snprintf(g->ids + len, sizeof g->ids - len, "%s%s", len ? " " : "", id);
    else if (!strstr(g->ids, " ..."))
        snprintf(g->ids + len, sizeof g->ids - len, " ...");
    g->count++;
}

/* The kind of a failure: the refusal reason, or the rule a WRONG result broke. */
static const char *failure_kind(const side *s, const cb_graph_case *t, int occt_side, char *buf,
                                size_t n)
{
    if (s->v == V_REFUSED && !occt_side)
        return ssc_refusal_class(&s->run, buf, n);
    if (s->v == V_WRONG) {
        const ssc_score *c = &s->score;
        if (!c->topology_ok) {
            /* The first count that differs, in this order. */
            if (c->broken)
                snprintf(buf, n, "WRONG topology (a curve broken)");
            else if (c->points != t->points)
                snprintf(buf, n, "WRONG topology (isolated points %s)",
                         c->points < t->points ? "missed" : "extra");
            else if (c->closed != t->closed)
                snprintf(buf, n, "WRONG topology (closed curves %s)",
                         c->closed < t->closed ? "missed" : "extra");
            else
                snprintf(buf, n, "WRONG topology (open curves %s)",
                         c->open < t->open ? "missed" : "extra");
        }
        else
            snprintf(buf, n, "WRONG geometry (%s)",
                     c->bad_flags ? "tangential flags" : c->res > SSC_RES ? "off the surfaces"
                     : c->overlap > SSC_OVERLAP                        ? "a piece twice"
                     : c->off_tight > SSC_OFF || c->off_loose > SSC_LOOSE
                         ? "off the designed curve"
                         : "the designed curve not covered");
        return buf;
    }
    snprintf(buf, n, "%s%s%.60s", VERDICT[s->v], s->run.msg[0] ? ": " : "", s->run.msg);
    return buf;
}

typedef struct {
    int n[CB_GRAPH_POSE_COUNT][2][6]; /* pose, side, verdict */
    double log_ratio;                 /* sum of log(C / O) over cases both finished */
    int n_ratio;
    double t[2]; /* summed seconds */
} class_row;

static void json_side(FILE *f, const char *key, const side *s, int occt_side)
{
    fprintf(f, "\"%s\": {\"verdict\": \"%s\", \"time_s\": %.6f", key, VERDICT[s->v],
            s->run.time);
    if (s->v == V_PASS || s->v == V_WRONG)
        fprintf(f,
                ", \"closed\": %d, \"open\": %d, \"points\": %d, \"broken\": %d, "
                "\"bad_flags\": %d, \"residual_tol\": %.3g, \"off_size\": [%.3g, %.3g], "
                "\"overlap\": %.3g, \"cover_size\": [%.3g, %.3g]",
                s->score.closed, s->score.open, s->score.points, s->score.broken,
                s->score.bad_flags, s->score.res, s->score.off_tight, s->score.off_loose,
                isfinite(s->score.overlap) ? s->score.overlap : -1,
                isfinite(s->score.cover_tight) ? s->score.cover_tight : -1,
                isfinite(s->score.cover_loose) ? s->score.cover_loose : -1);
    fprintf(f, ", \"curves\": %d, \"points_out\": %d", s->out.n_curves, s->out.n_points);
    if (!occt_side && s->v != V_TIMEOUT && s->v != V_CRASH)
        fprintf(f, ", \"patch_pairs\": %ld, \"subdivided\": %ld", s->run.pairs,
                s->run.subdivided);
    if (s->v == V_REFUSED && occt_side == 0)
        fprintf(f,
                ", \"pairs_not_certified\": %ld, \"subpairs\": %ld, \"no_direction\": %ld, "
                "\"ambiguous_roots\": %ld, \"several_branches\": %ld, \"march_failed\": %ld, "
                "\"over_budget\": %ld",
                s->run.failed, s->run.subpairs, s->run.reason[0], s->run.reason[1],
                s->run.reason[2], s->run.reason[3], s->run.reason[4]);
    const char *why = s->v == V_WRONG ? s->score.why : s->run.msg;
    if (why[0]) {
        fputs(", \"reason\": ", f);
        cb_json_string(f, why);
    }
    fputs("}", f);
}

int main(int argc, char **argv)
{
    if (argc == 6 && !strcmp(argv[1], "--child"))
        return child(atoi(argv[2]), atoi(argv[3]), atoi(argv[4]), atoi(argv[5]));
    const char *occt = NULL, *json_path = NULL, *only = NULL;
    double timeout = 60;
    int counts[CB_GRAPH_POSE_COUNT] = {2, 3, 9}, threads = 1, list = 0, dumps = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--occt") && i + 1 < argc)
            occt = argv[++i];
        else if (!strcmp(argv[i], "--json") && i + 1 < argc)
            json_path = argv[++i];
        else if (!strcmp(argv[i], "--timeout") && i + 1 < argc)
            timeout = atof(argv[++i]);
        else if (!strcmp(argv[i], "--only") && i + 1 < argc)
            only = argv[++i];
        else if (!strcmp(argv[i], "--threads") && i + 1 < argc)
            threads = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--list"))
            list = 1;
        else if (!strcmp(argv[i], "--dump"))
            dumps = 1;
        else if (!strcmp(argv[i], "--counts") && i + 3 < argc)
            for (int p = 0; p < CB_GRAPH_POSE_COUNT; p++)
                counts[p] = atoi(argv[++i]);
        else {
            fprintf(stderr,
                    "usage: bench_ssi_corpus [--occt OCCT_SSI] [--json OUT] [--timeout S] "
                    "[--counts E P G] [--only TEXT] [--threads N] [--list] [--dump]\n");
            return 2;
        }
    }
    if (occt && access(occt, X_OK)) {
        fprintf(stderr, "bench_ssi_corpus: %s is not executable; OCCT not run\n", occt);
        occt = NULL;
    }
    FILE *json = NULL;
    if (json_path && !(json = fopen(json_path, "w"))) {
        fprintf(stderr, "bench_ssi_corpus: cannot write %s\n", json_path);
        return 1;
    }
    char dir[] = "/tmp/colibri_ssic_XXXXXX", path[64]; /* mkdtemp replaces the Xs */
    if (occt && !mkdtemp(dir)) {
        fprintf(stderr, "bench_ssi_corpus: cannot make a temporary directory\n");
        return 1;
    }
    snprintf(path, sizeof path, "%s/pair.txt", dir);
    printf("SSI corpus of graph cases: Colibri (cb_ssi_surfaces, %d thread%s)%s, %.0f s limit "
           "per case and side\n",
           threads, threads == 1 ? "" : "s", occt ? " and OCCT (GeomInt_IntSS)" : "", timeout);
    printf("%-28s %-28s | %-8s %8s %-40s |", "case", "truth", "Colibri", "time/s", "reason");
    if (occt)
        printf(" %-8s %8s %s", "OCCT", "time/s", "reason");
    printf("\n");
    if (json)
        fprintf(json, "{\"timeout_s\": %g, \"threads\": %d, \"cases\": [", timeout, threads);
    class_row rows[CB_GRAPH_CLASS_COUNT];
    memset(rows, 0, sizeof rows);
    int first = 1, n_cases = 0, not_built = 0;
    double t_start = now();
    for (int cls = 0; cls < CB_GRAPH_CLASS_COUNT; cls++)
        for (int pose = 0; pose < CB_GRAPH_POSE_COUNT; pose++)
            for (int index = 0; index < counts[pose]; index++) {
                cb_graph_case c;
                cb_graph_case_init(&c);
                cb_error err;
                char id[64];
                snprintf(id, sizeof id, "%s/%s/%d", cb_graph_class_name(cls),
                         cb_graph_pose_name(pose), index);
                if (only && strncmp(id, only, strlen(only)))
                    continue;
                if (cb_graph_case_make(&c, cls, pose, index, &err)) {
                    printf("%-28s not built: %s\n", id, err.msg);
                    not_built++;
                    continue;
                }
                if (list) {
                    printf("%-28s %-28s P (%d, %d) %d x %d, Q (%d, %d) %d x %d, size %.3g, "
                           "%d shared knot lines%s\n",
                           c.id, c.truth, c.P->deg_u, c.P->deg_v, c.P->n_u, c.P->n_v,
                           c.Q->deg_u, c.Q->deg_v, c.Q->n_u, c.Q->n_v, c.size, c.shared_knots,
                           c.q_larger ? ", Q larger" : "");
                    cb_graph_case_clear(&c);
                    continue;
                }
                n_cases++;
                side sd[2];
                memset(sd, 0, sizeof sd);
                sd[1].v = V_NOT_RUN;
                double tol = 1e-6 * c.size, wall;
                /* Colibri in a child process. */
                {
                    char a1[16], a2[16], a3[16], a4[16], *out;
                    size_t len;
                    int code;
                    snprintf(a1, sizeof a1, "%d", cls);
                    snprintf(a2, sizeof a2, "%d", pose);
                    snprintf(a3, sizeof a3, "%d", index);
                    snprintf(a4, sizeof a4, "%d", threads);
                    char *const av[] = {argv[0], "--child", a1, a2, a3, a4, NULL};
                    run_end e = run_timed(&out, &len, av, timeout, &code, &wall);
                    side *s = sd;
                    s->run.time = -1;
                    if (e == RUN_TIMEOUT) {
                        s->v = V_TIMEOUT;
                        s->run.time = wall;
                    } else if (e == RUN_CRASH || !out || !parse_colibri(s, out) ||
                               code != 0) {
                        s->v = V_CRASH;
                        if (!s->run.msg[0])
                            snprintf(s->run.msg, sizeof s->run.msg, "%s",
                                     e == RUN_CRASH ? "ended on a signal"
                                                    : "no readable result");
                    } else {
                        tol = s->run.tol;
                        judge(s, &c, tol);
                    }
                    free(out);
                }
                /* OCCT in a child process, same tolerance. */
                if (occt) {
                    side *s = sd + 1;
                    s->run.time = -1;
                    FILE *f = fopen(path, "w");
                    if (f) {
                        bench_write_nurbs(f, c.P);
                        bench_write_nurbs(f, c.Q);
                        fclose(f);
                    }
                    char stol[32], *out;
                    size_t len;
                    int code;
                    snprintf(stol, sizeof stol, "%.17g", tol);
                    char *const av[] = {(char *)occt, "1", stol, path, NULL};
                    run_end e = run_timed(&out, &len, av, timeout, &code, &wall);
                    if (e == RUN_TIMEOUT) {
                        s->v = V_TIMEOUT;
                        s->run.time = wall;
                    } else if (e == RUN_CRASH || code != 0 || !out || !parse_occt(s, out)) {
                        s->v = V_CRASH;
                        snprintf(s->run.msg, sizeof s->run.msg, "%s",
                                 e == RUN_CRASH ? "ended on a signal" : "no readable result");
                    } else {
                        judge(s, &c, tol);
                    }
                    free(out);
                }
                class_row *row = rows + cls;
                for (int k = 0; k < 2; k++) {
                    row->n[pose][k][sd[k].v]++;
                    if (sd[k].run.time > 0)
                        row->t[k] += sd[k].run.time;
                }
                if (occt && sd[0].v <= V_WRONG && sd[1].v <= V_WRONG && sd[0].run.time > 0 &&
                    sd[1].run.time > 0) {
                    row->log_ratio += log(sd[0].run.time / sd[1].run.time);
                    row->n_ratio++;
                }
                printf("%-28s %-28s | %-8s %8.3f %-40.40s |", c.id, c.truth, VERDICT[sd[0].v],
                       sd[0].run.time, sd[0].v == V_WRONG ? sd[0].score.why : sd[0].run.msg);
                if (occt)
                    printf(" %-8s %8.3f %.60s", VERDICT[sd[1].v], sd[1].run.time,
                           sd[1].v == V_WRONG ? sd[1].score.why : sd[1].run.msg);
                printf("\n");
                for (int k = 0; k < (occt ? 2 : 1); k++)
                    if (sd[k].v != V_PASS) {
                        char b[120];
                        group_add(k, failure_kind(sd + k, &c, k, b, sizeof b), c.id);
                    }
                if (sd[0].v == V_REFUSED) {
                    char b[80];
                    printf("    Colibri refused: %ld pairs not certified, mostly %s\n",
                           sd[0].run.failed, ssc_refusal_class(&sd[0].run, b, sizeof b));
                }
                if (dumps)
                    for (int k = 0; k < (occt ? 2 : 1); k++)
                        dump(k ? "OCCT" : "Colibri", sd + k, &c);
                fflush(stdout);
                if (json) {
                    fprintf(json, "%s\n {\"id\": ", first ? "" : ",");
                    cb_json_string(json, c.id);
                    fprintf(json, ", \"class\": \"%s\", \"fig1\": \"%s\", \"pose\": \"%s\", ",
                            cb_graph_class_name(cls), cb_graph_class_fig(cls),
                            cb_graph_pose_name(pose));
                    fprintf(json, "\"truth\": {\"closed\": %d, \"open\": %d, \"points\": %d, "
                                  "\"text\": ",
                            c.closed, c.open, c.points);
                    cb_json_string(json, c.truth);
                    fprintf(json,
                            "}, \"tol\": %.3g, \"size\": %.4g, \"P\": [%d, %d, %d, %d], "
                            "\"Q\": [%d, %d, %d, %d], \"shared_knot_lines\": %d, "
                            "\"q_larger\": %d, ",
                            tol, c.size, c.P->deg_u, c.P->deg_v, c.P->n_u, c.P->n_v, c.Q->deg_u,
                            c.Q->deg_v, c.Q->n_u, c.Q->n_v, c.shared_knots, c.q_larger);
                    if (sd[0].v == V_REFUSED) {
                        char b[80];
                        fputs("\"refusal_class\": ", json);
                        cb_json_string(json, ssc_refusal_class(&sd[0].run, b, sizeof b));
                        fputs(", ", json);
                    }
                    json_side(json, "colibri", sd, 0);
                    if (occt) {
                        fputs(", ", json);
                        json_side(json, "occt", sd + 1, 1);
                    }
                    fputs("}", json);
                    first = 0;
                }
                for (int k = 0; k < 2; k++)
                    ssc_output_clear(&sd[k].out);
                cb_graph_case_clear(&c);
            }
    if (list)
        return 0;

    /* The table: class x pose, pass / refused / WRONG / crash / timeout for each side. */
    printf("\n%d cases (%d not built), %.0f s. Per class and pose: Colibri pass/refused/WRONG/"
           "crash/timeout%s; time ratio C/O: geometric mean over the cases both finished\n",
           n_cases, not_built, now() - t_start, occt ? " | OCCT the same" : "");
    printf("%-17s %-4s", "class", "Fig1");
    for (int p = 0; p < CB_GRAPH_POSE_COUNT; p++)
        printf(" | %-*s", occt ? 25 : 12, cb_graph_pose_name(p));
    printf(" | %s\n", occt ? "C/O" : "");
    int tot[CB_GRAPH_POSE_COUNT][2][6];
    memset(tot, 0, sizeof tot);
    for (int cls = 0; cls < CB_GRAPH_CLASS_COUNT; cls++) {
        printf("%-17s %-4s", cb_graph_class_name(cls), cb_graph_class_fig(cls));
        for (int p = 0; p < CB_GRAPH_POSE_COUNT; p++) {
            const int *a = rows[cls].n[p][0], *b = rows[cls].n[p][1];
            char cb[32], ob[32];
            snprintf(cb, sizeof cb, "%d/%d/%d/%d/%d", a[0], a[1], a[2], a[3], a[4]);
            snprintf(ob, sizeof ob, "%d/%d/%d/%d/%d", b[0], b[1], b[2], b[3], b[4]);
            if (occt)
                printf(" | %-12s %-12s", cb, ob);
            else
                printf(" | %-12s", cb);
            for (int k = 0; k < 2; k++)
                for (int v = 0; v < 6; v++)
                    tot[p][k][v] += rows[cls].n[p][k][v];
        }
        if (occt && rows[cls].n_ratio)
            printf(" | %.3g\n", exp(rows[cls].log_ratio / rows[cls].n_ratio));
        else
            printf(" |\n");
    }
    printf("%-17s %-4s", "all", "");
    for (int p = 0; p < CB_GRAPH_POSE_COUNT; p++) {
        const int *a = tot[p][0], *b = tot[p][1];
        char cb[32], ob[32];
        snprintf(cb, sizeof cb, "%d/%d/%d/%d/%d", a[0], a[1], a[2], a[3], a[4]);
        snprintf(ob, sizeof ob, "%d/%d/%d/%d/%d", b[0], b[1], b[2], b[3], b[4]);
        if (occt)
            printf(" | %-12s %-12s", cb, ob);
        else
            printf(" | %-12s", cb);
    }
    printf(" |\n");
    for (int k = 0; k < (occt ? 2 : 1); k++) {
        printf("\n%s: cases not passed, by %s\n", k ? "OCCT" : "Colibri",
               k ? "kind" : "the dominant refusal reason (sub-patch pairs counted most) or kind");
        for (int g = 0; g < n_groups; g++)
            if (groups[g].side == k)
                printf("  %3d  %s: %s\n", groups[g].count, groups[g].kind, groups[g].ids);
    }
    if (json) {
        fputs("\n], \"table\": [", json);
        for (int cls = 0; cls < CB_GRAPH_CLASS_COUNT; cls++) {
            fprintf(json, "%s\n {\"class\": \"%s\"", cls ? "," : "", cb_graph_class_name(cls));
            for (int p = 0; p < CB_GRAPH_POSE_COUNT; p++)
                for (int k = 0; k < (occt ? 2 : 1); k++) {
                    fprintf(json, ", \"%s_%s\": {", k ? "occt" : "colibri",
                            cb_graph_pose_name(p));
                    for (int v = 0; v < 5; v++)
                        fprintf(json, "%s\"%s\": %d", v ? ", " : "", VERDICT[v],
                                rows[cls].n[p][k][v]);
                    fputs("}", json);
                }
            if (occt && rows[cls].n_ratio)
                fprintf(json, ", \"time_ratio_c_o\": %.4g",
                        exp(rows[cls].log_ratio / rows[cls].n_ratio));
            fputs("}", json);
        }
        fputs("\n]}\n", json);
        fclose(json);
    }
    if (occt) {
        remove(path);
        rmdir(dir);
    }
    return 0;
}
