/* corpus.h — the randomized differential corpus of primitive Booleans (bench/corpus/
 * occt_corpus.cpp writes it): reading its cases file and the one set of scoring rules, shared by
 * the runner (bench/bench_corpus.c, Colibri and Open CASCADE as subprocesses) and the committed
 * subset's test (tests/test_corpus.c, Colibri in-process), so that every tool and every route is
 * scored alike.
 *
 * cases.json holds one case per line (the generator writes it so): a JSON object with at least
 * "id", "config", "pose", "faces", "a", "b" (file names beside cases.json), "va", "vb", "vi"
 * (true volumes of A, B and A n B), "touching" and "description". Each line is read on its own
 * by key lookup; this is no general JSON reader.
 *
 * Scoring, for one case and one operation (union, intersection, A - B), the truth being
 * V(A) + V(B) - V(A n B), V(A n B) and V(A) - V(A n B):
 *   timeout  the tool was stopped at the time limit;
 *   crash    it ended on a signal;
 *   refused  it reported an error (its reason kept);
 *   WRONG    it reported success but the result is not valid, its mesh is open or crosses
 *            itself (or touches itself where the exact result is a manifold solid: only cases
 *            flagged "touching" may), or its volume is off the truth by more than
 *            1e-6 |truth| + 1e-9 (V(A) + V(B)): the worst outcome;
 *   pass     otherwise.
 * Header-only (static inline): the runner and the test are programs of their own. */
#ifndef CB_BENCH_CORPUS_H
#define CB_BENCH_CORPUS_H

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    char id[96], config[48], pose[16], faces[16], a[128], b[128], desc[256];
    int draw;
    double va, vb, vi;
    int touching;
} corpus_case;

/* The operations in the order of cb_bool_op: union, intersection, difference. */
static const char *const corpus_op_names[3] = {"union", "intersection", "difference"};

/* The value text of "key": in one JSON line (just after the colon and blanks); NULL if absent. */
static inline const char *corpus_json_value(const char *line, const char *key)
{
    char pat[64];
    snprintf(pat, sizeof pat, "\"%s\":", key);
    const char *p = strstr(line, pat);
    if (!p)
        return NULL;
    p += strlen(pat);
    while (*p == ' ')
        p++;
    return p;
}

/* "key": "text" into out (escapes are not expected in our files and are kept as they are);
 * 0 if absent. */
static inline int corpus_json_string(char *out, size_t n, const char *line, const char *key)
{
    const char *p = corpus_json_value(line, key);
    if (!p || *p != '"')
        return 0;
    p++;
    size_t k = 0;
    while (*p && *p != '"' && k + 1 < n) {
        if (*p == '\\' && p[1])
            out[k++] = *p++;
        out[k++] = *p++;
    }
    out[k] = 0;
    return 1;
}

/* "key": number (or null: NaN); NaN if absent. */
static inline double corpus_json_number(const char *line, const char *key)
{
    const char *p = corpus_json_value(line, key);
    if (!p || !strncmp(p, "null", 4))
        return NAN;
    char *end;
    double v = strtod(p, &end);
    return end == p ? NAN : v;
}

/* "key": true / false; -1 if absent. */
static inline int corpus_json_bool(const char *line, const char *key)
{
    const char *p = corpus_json_value(line, key);
    if (!p)
        return -1;
    return !strncmp(p, "true", 4) ? 1 : !strncmp(p, "false", 5) ? 0 : -1;
}

/* Reads the cases of path (a cases.json) into a new array *cases of *n (free it); 0 on success,
 * else -1 with the reason in msg. */
static inline int corpus_load(corpus_case **cases, int *n, const char *path, char *msg,
                              size_t msgn)
{
    *cases = NULL;
    *n = 0;
    FILE *f = fopen(path, "r");
    if (!f) {
        snprintf(msg, msgn, "%s: cannot open", path);
        return -1;
    }
    static char line[8192];
    int cap = 0, lineno = 0;
    while (fgets(line, sizeof line, f)) {
        lineno++;
        if (!strchr(line, '{'))
            continue;
        if (*n == cap) {
            cap = cap ? 2 * cap : 256;
            corpus_case *m = realloc(*cases, (size_t)cap * sizeof **cases);
            if (!m) {
                snprintf(msg, msgn, "%s: out of memory", path);
                fclose(f);
                free(*cases);
                *cases = NULL;
                *n = 0;
                return -1;
            }
            *cases = m;
        }
        corpus_case *c = *cases + *n;
        memset(c, 0, sizeof *c);
        c->va = corpus_json_number(line, "va");
        c->vb = corpus_json_number(line, "vb");
        c->vi = corpus_json_number(line, "vi");
        c->touching = corpus_json_bool(line, "touching");
        double draw = corpus_json_number(line, "draw");
        c->draw = isfinite(draw) ? (int)draw : 0;
        corpus_json_string(c->desc, sizeof c->desc, line, "description");
        if (!corpus_json_string(c->id, sizeof c->id, line, "id") ||
            !corpus_json_string(c->config, sizeof c->config, line, "config") ||
            !corpus_json_string(c->pose, sizeof c->pose, line, "pose") ||
            !corpus_json_string(c->faces, sizeof c->faces, line, "faces") ||
            !corpus_json_string(c->a, sizeof c->a, line, "a") ||
            !corpus_json_string(c->b, sizeof c->b, line, "b") || !isfinite(c->va) ||
            !isfinite(c->vb) || !isfinite(c->vi) || c->touching < 0) {
            snprintf(msg, msgn, "%s:%d: a case lacks one of id, config, pose, faces, a, b, va, "
                                "vb, vi, touching",
                     path, lineno);
            fclose(f);
            free(*cases);
            *cases = NULL;
            *n = 0;
            return -1;
        }
        (*n)++;
    }
    fclose(f);
    if (*n == 0) {
        snprintf(msg, msgn, "%s: no case", path);
        return -1;
    }
    return 0;
}

/* The true volume of operation op (0 union, 1 intersection, 2 difference A - B). */
static inline double corpus_truth(const corpus_case *c, int op)
{
    return op == 0 ? c->va + c->vb - c->vi : op == 1 ? c->vi : c->va - c->vi;
}

/* The error bar: 1e-6 of the truth (the integration and the tolerances of a tool working at
 * 1e-6 of the model size) plus 1e-9 of the operands' volumes (so that an empty truth gets a
 * bar at the scale of the model). */
static inline double corpus_bar(const corpus_case *c, int op)
{
    return 1e-6 * fabs(corpus_truth(c, op)) + 1e-9 * (c->va + c->vb);
}

typedef enum {
    CORPUS_PASS,
    CORPUS_REFUSED,
    CORPUS_WRONG,
    CORPUS_CRASH,
    CORPUS_TIMEOUT
} corpus_verdict;

static const char *const corpus_verdict_names[5] = {"pass", "refused", "WRONG", "crash",
                                                     "timeout"};

/* What one tool did on one case and operation. */
typedef struct {
    int timed_out;         /* stopped at the time limit */
    int signal;            /* ended on this signal (0: it ended normally) */
    int reported_ok;       /* it reported success */
    char message[512];     /* its reason when it did not */
    int valid;             /* the tool's validator accepts the result */
    int mesh_checked;      /* the fields below are set (Colibri; OCCT's result is not meshed) */
    int closed, clean;     /* mesh closed; manifold with no self-intersection */
    int touching_mesh;     /* it meets itself only where triangles touch, none crossing */
    int crossing;          /* pairs of triangles found crossing */
    double volume;         /* the result's volume (NaN: none) */
    double time_s, wall_s; /* the operation's own time; the whole process's (NaN: unknown) */
} corpus_outcome;

static inline void corpus_outcome_init(corpus_outcome *o)
{
    memset(o, 0, sizeof *o);
    o->volume = o->time_s = o->wall_s = NAN;
}

/* The verdict of o against a true volume with its error bar; touching: whether the exact
 * result may touch itself. why gets a one-line reason (the tool's first line when refused).
 * The one rule behind corpus_score, for runners whose truth comes from elsewhere (bench_parts:
 * an estimate with its own bar). */
static inline corpus_verdict corpus_score_truth(const corpus_outcome *o, double truth, double bar,
                                                int touching, char *why, size_t n)
{
    if (o->timed_out) {
        snprintf(why, n, "timed out");
        return CORPUS_TIMEOUT;
    }
    if (o->signal) {
        snprintf(why, n, "killed by signal %d", o->signal);
        return CORPUS_CRASH;
    }
    if (!o->reported_ok) {
        size_t k = strcspn(o->message, "\n");
        snprintf(why, n, "%.*s", (int)(k < 400 ? k : 400), o->message[0] ? o->message : "(no reason given)");
        return CORPUS_REFUSED;
    }
    if (!o->valid) {
        snprintf(why, n, "reported success, but the result is not valid");
        return CORPUS_WRONG;
    }
    if (o->mesh_checked) {
        if (!o->closed) {
            snprintf(why, n, "reported success, but its mesh is open");
            return CORPUS_WRONG;
        }
        if (o->crossing > 0 || (!o->clean && !o->touching_mesh)) {
            snprintf(why, n, "reported success, but its mesh crosses itself");
            return CORPUS_WRONG;
        }
        if (!o->clean && !touching) {
            snprintf(why, n, "reported success, but its mesh touches itself where the exact "
                             "result is a manifold solid");
            return CORPUS_WRONG;
        }
    }
    if (!isfinite(o->volume) || fabs(o->volume - truth) > bar) {
        snprintf(why, n, "reported success with volume %.10g, truth %.10g (off by %.2e, bar %.2e)",
                 o->volume, truth, fabs(o->volume - truth), bar);
        return CORPUS_WRONG;
    }
    why[0] = 0;
    return CORPUS_PASS;
}

/* The verdict of o on case c, operation op (truth and bar as above). */
static inline corpus_verdict corpus_score(const corpus_outcome *o, const corpus_case *c, int op,
                                          char *why, size_t n)
{
    return corpus_score_truth(o, corpus_truth(c, op), corpus_bar(c, op), c->touching, why, n);
}

/* A reason with its numbers replaced by '#' and the case's file names by A.step / B.step, so
 * that the same failure on different cases reads the same (for counting reasons). */
static inline void corpus_reason_class(char *out, size_t n, const char *reason,
                                       const corpus_case *c)
{
    size_t k = 0, la = strlen(c->a), lb = strlen(c->b);
    const char *p = reason;
    while (*p && k + 8 < n) {
        if ((la && !strncmp(p, c->a, la)) || (lb && !strncmp(p, c->b, lb))) {
            /* The file's directory goes too: it depends on where the corpus was run. */
            while (k > 0 && out[k - 1] != ' ' && out[k - 1] != '(' && out[k - 1] != '\'')
                k--;
        }
        if (la && !strncmp(p, c->a, la)) {
            k += (size_t)snprintf(out + k, n - k, "A.step");
            p += la;
            continue;
        }
        if (lb && !strncmp(p, c->b, lb)) {
            k += (size_t)snprintf(out + k, n - k, "B.step");
            p += lb;
            continue;
        }
        int number = isdigit((unsigned char)*p) ||
                     ((*p == '-' || *p == '.') && isdigit((unsigned char)p[1]));
        if (number && (p == reason || !(isalpha((unsigned char)p[-1]) || p[-1] == '_'))) {
            p++;
            while (isdigit((unsigned char)*p) || *p == '.' ||
                   ((*p == 'e' || *p == 'E') &&
                    (isdigit((unsigned char)p[1]) ||
                     ((p[1] == '-' || p[1] == '+') && isdigit((unsigned char)p[2])))) ||
                   ((*p == '-' || *p == '+') && (p[-1] == 'e' || p[-1] == 'E')))
                p++;
            out[k++] = '#';
            continue;
        }
        out[k++] = *p++;
    }
    out[k] = 0;
}

#endif
