/* SSI of real STEP models against moved copies, Colibri beside Open CASCADE's
 * BRepAlgoAPI_Section: for each case, cb_ssi_bodies on 1 and 2 threads (median, min, max of
 * RUNS runs), then cb_bool_ssi_trim (the curves clipped to the trimmed faces), with the counts
 * (face pairs with output, curves, isolated points, patch pairs culled, certified and not
 * certified, subdivision pairs), the largest distance of an output point to each surface, the
 * total length of the trimmed curves, whether 1 and 2 threads gave bit-identical points, and
 * the peak memory; and, when the OCCT comparator (occt_section) is given, the section of the
 * same two solids in OCCT's parallel and serial modes: done / errors, edges, vertices, total
 * edge length, time, and the ratio of the times.
 *
 * The cases: B is turned about the z axis through a centre (file units), done as Colibri's
 * `colibri ssi --rotate-b 0 0 1 DEG --translate-b ...` does it (about the origin, then
 * moved; the program prints the move). trj5 against itself turned 30 degrees about (9, 0, 0)
 * (the file is in cm); the Cardan fork against the cross moved by (-100, 0, 0); linkrods
 * against itself turned 30 degrees about the centre of its box.
 *
 * Peak memory: every case runs in a fresh process (this program started again with --case;
 * bench_spawn.h says why), beside the peak of a process that only reads the two files. OCCT's
 * figures come the same way from occt_section.
 *
 * Usage: bench_ssi_models [RUNS] [--shared DIR] [--occt OCCT_SECTION] [--json OUT]
 *                         [--only CASE] [--limit SECONDS]
 *   RUNS default 1 (the trj5 case takes minutes); DIR holds models/ (default $COLIBRI_SHARED,
 *   else ../shared); without --occt (or with "-") Colibri alone. --limit: a case's Colibri
 *   runs are cancelled (cb_context_cancel, checked before each face pair) once they have taken
 *   that long, and the row says how far they got (default 0: no limit).
 * Internal: bench_ssi_models --case K RUNS DIR LIMIT   (RUNS 0: only read the files) */
#define _DEFAULT_SOURCE /* wait4: the rusage of one child, not of all of them */
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench_spawn.h"
#include "bench/bench_ssi_same.h"
#include "bench/bench_stats.h"
#include "boolean/bool.h"
#include "io/json.h"
#include "io/step.h"
#include "ssi/ssi.h"

typedef struct {
    const char *name, *a, *b; /* case, and the two files in DIR/models */
    double deg;               /* B turned by deg about the z axis through centre */
    double centre[3];
    double shift[3]; /* then moved by shift (file units) */
} model_case;

#define N_CASES 3

/* Fast cases first, so that their figures are out before trj5's minutes. */
static const model_case CASES[N_CASES] = {
    {"ujoint", "ujoint_fork.step", "ujoint_cross.step", 0, {0, 0, 0}, {-100, 0, 0}},
    {"linkrods", "linkrods.step", "linkrods.step", 30, {5.63514, 3.25, 1}, {0, 0, 0}},
    {"trj5", "trj5_k1-al-214.stp", "trj5_k1-al-214.stp", 30, {9, 0, 0}, {0, 0, 0}},
};

/* The move about the origin: x -> R x + t with t = shift + c - R c. */
static void case_move(double t[3], const model_case *c)
{
    double a = c->deg * 3.14159265358979323846 / 180, co = cos(a), si = sin(a);
    t[0] = c->shift[0] + c->centre[0] - (co * c->centre[0] - si * c->centre[1]);
    t[1] = c->shift[1] + c->centre[1] - (si * c->centre[0] + co * c->centre[1]);
    t[2] = c->shift[2];
}

/* Colibri's figures for one case, passed from the child process as raw bytes (the child is
 * this same program, so the layout is shared). t: cb_ssi_bodies on 1 and 2 threads, median,
 * min, max; the counts are those of the 2-thread run. */
typedef struct {
    int ok;
    double unit_mm, tol, t[2][3], t_trim[2];
    int faces_a, faces_b;
    long pairs_out[2], curves[2], points[2]; /* before, after trimming */
    long total, culled, empty, certified, failed, subdivided, subpairs;
    long failed_face_pairs;
    long coincident; /* face pairs found on one surface: no curve, by design (cb_ssi_coincident) */
    double dist_a, dist_b, length; /* length of the trimmed curves, file units */
    int same[2];                   /* 1 and 2 threads bit-identical: before, after trimming */
    char failures[600];            /* what the uncertified pairs are, or the error */
} colibri_row;

/* OCCT's figures in one mode (parallel, serial). */
typedef struct {
    int ok, done, errors, edges, vertices;
    double t[3], length; /* seconds; mm */
    long peak;
} occt_row;

/* ---------------------------------------------------------------- the Colibri side --------- */

static int cmp_pair(const void *x, const void *y)
{
    const long *a = x, *b = y;
    return (*a > *b) - (*a < *b);
}

/* Distinct face pairs with a curve or an isolated point. */
static long pairs_with_output(const cb_ssi_result_t r, int faces_b)
{
    long n = (long)(r->n_curves + r->n_points), *k = malloc(((size_t)n + 1) * sizeof(long));
    for (slong c = 0; c < r->n_curves; c++)
        k[c] = (long)r->curve[c].face_a * faces_b + r->curve[c].face_b;
    for (slong p = 0; p < r->n_points; p++)
        k[r->n_curves + p] = (long)r->point[p].face_a * faces_b + r->point[p].face_b;
    qsort(k, (size_t)n, sizeof *k, cmp_pair);
    long d = 0;
    for (long i = 0; i < n; i++)
        d += !i || k[i] != k[i - 1];
    free(k);
    return d;
}

static double polyline_length(const cb_ssi_result_t r)
{
    double s = 0;
    for (slong c = 0; c < r->n_curves; c++)
        for (slong i = 1; i < r->curve[c].n; i++) {
            const double *p = r->curve[c].pt[i - 1].xyz, *q = r->curve[c].pt[i].xyz;
            s += sqrt((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) +
                      (q[2] - p[2]) * (q[2] - p[2]));
        }
    return s;
}

/* The uncertified pairs by the surface types of their faces and status, so that the table
 * says what they are: "N bspline/bspline (unsupported); ...; first: MESSAGE". */
static void describe_failures(colibri_row *o, const cb_ssi_result_t r, const cb_topo_body *a,
                              const cb_topo_body *b)
{
    enum { KINDS = 8 };
    char key[KINDS][96];
    long count[KINDS];
    int nk = 0;
    long *fp = malloc(((size_t)r->n_failed + 1) * sizeof(long));
    for (slong k = 0; k < r->n_failed; k++) {
        const cb_ssi_failure *f = r->failed + k;
        fp[k] = (long)f->face_a * b->n_faces + f->face_b;
        char s[96];
        snprintf(s, sizeof s, "%s/%s (%s)",
                 cb_topo_surface_type_name(a->surfaces + a->faces[f->face_a].surface),
                 cb_topo_surface_type_name(b->surfaces + b->faces[f->face_b].surface),
                 cb_status_name(f->status));
        int i = 0;
        while (i < nk && strcmp(key[i], s))
            i++;
        if (i == nk && nk < KINDS) {
            memcpy(key[nk], s, sizeof s);
            count[nk++] = 0;
        }
        if (i < nk)
            count[i]++;
    }
    qsort(fp, (size_t)r->n_failed, sizeof *fp, cmp_pair);
    o->failed_face_pairs = 0;
    for (slong k = 0; k < r->n_failed; k++)
        o->failed_face_pairs += !k || fp[k] != fp[k - 1];
    free(fp);
    size_t len = 0, cap = sizeof o->failures;
    for (int i = 0; i < nk && len < cap; i++)
        len += (size_t)snprintf(o->failures + len, cap - len, "%s%ld %s", i ? "; " : "",
                                count[i], key[i]);
    if (r->n_failed && len < cap)
        snprintf(o->failures + len, cap - len, "; first: faces %d, %d: %s", r->failed[0].face_a,
                 r->failed[0].face_b, r->failed[0].msg);
}

/* The case's time limit: SIGALRM cancels its runs (an atomic store, safe in a handler), and
 * the progress reports say which fraction of the face pairs the running call had done. */
static cb_context limit_ctx;
static double limit_done;

static void limit_reached(int sig)
{
    (void)sig;
    cb_context_cancel(&limit_ctx);
}

static void limit_progress(void *user, double fraction, const char *stage)
{
    (void)user;
    (void)stage;
    limit_done = fraction;
}

/* --case K RUNS DIR LIMIT: reads case k's files, moves B, and with RUNS > 0 runs the SSI RUNS
 * times on 1 and 2 threads and the trimming after each thread count's last run, all cancelled
 * after LIMIT seconds when LIMIT > 0; writes a colibri_row to stdout. */
static int case_mode(int k, int runs, const char *dir, int limit)
{
    const model_case *c = CASES + k;
    colibri_row o;
    memset(&o, 0, sizeof o);
    cb_topo_body *body[2] = {NULL, NULL};
    cb_error err;
    cb_error_clear(&err);
    char path[2][1024];
    snprintf(path[0], sizeof path[0], "%s/models/%s", dir, c->a);
    snprintf(path[1], sizeof path[1], "%s/models/%s", dir, c->b);
    cb_status st = CB_OK;
    for (int s = 0; s < 2 && st == CB_OK; s++)
        st = cb_step_read(body + s, path[s], &err);
    if (st != CB_OK) {
        fprintf(stderr, "bench_ssi_models: %s\n", err.msg);
        cb_topo_body_free(body[0]);
        return 1;
    }
    double t[3];
    case_move(t, c);
    cb_xform rot, shift, x;
    const double origin[3] = {0, 0, 0}, z[3] = {0, 0, 1};
    cb_xform_rotation(&rot, origin, z, c->deg * 3.14159265358979323846 / 180);
    cb_xform_translation(&shift, t);
    cb_xform_compose(&x, &shift, &rot);
    cb_topo_body_transform(body[1], &x);
    o.unit_mm = body[1]->length_unit_mm;
    o.faces_a = body[0]->n_faces;
    o.faces_b = body[1]->n_faces;
    cb_ssi_result_t r[2];
    cb_ssi_result_init(r[0]);
    cb_ssi_result_init(r[1]);
    cb_context_init(&limit_ctx);
    limit_ctx.progress = limit_progress;
    if (limit > 0 && runs > 0) {
        signal(SIGALRM, limit_reached);
        alarm((unsigned)limit);
    }
    double started = now();
    for (int th = 0; th < 2 && runs > 0 && st == CB_OK; th++) {
        double ts[MAX_RUNS];
        int nq = 0;
        for (int q = 0; q < runs && st == CB_OK; q++, nq++) {
            cb_ssi_opts opts;
            cb_ssi_opts_default(&opts);
            opts.threads = th + 1;
            opts.cancel = &limit_ctx;
            opts.progress = &limit_ctx;
            cb_context_progress_reset(&limit_ctx);
            limit_done = 0;
            cb_ssi_result_clear(r[th]);
            cb_ssi_result_init(r[th]);
            double t0 = now();
            st = cb_ssi_bodies(r[th], body[0], body[1], &opts, &err);
            ts[q] = now() - t0;
            if (st == CB_ERR_CANCELLED)
                cb_error_set(&err, st,
                             "stopped at the limit of %d s (%.0f s in all): the %d-thread run "
                             "had done %.0f%% of its face pairs",
                             limit, now() - started, th + 1, 100 * limit_done);
        }
        stats3(o.t[th], ts, nq);
    }
    if (runs > 0 && st == CB_OK) {
        const cb_ssi_result_struct *R = r[1];
        o.tol = R->tol;
        o.pairs_out[0] = pairs_with_output(r[1], o.faces_b);
        o.curves[0] = (long)R->n_curves;
        o.points[0] = (long)R->n_points;
        o.total = (long)R->pairs_total;
        o.culled = (long)R->pairs_culled;
        o.empty = (long)R->pairs_empty;
        o.certified = (long)R->pairs_certified;
        o.failed = (long)R->n_failed;
        o.subdivided = (long)R->pairs_subdivided;
        o.subpairs = (long)R->subpairs;
        o.coincident = (long)R->n_coincident;
        o.dist_a = R->max_dist_a;
        o.dist_b = R->max_dist_b;
        o.same[0] = bench_ssi_same(r[0], r[1]);
        describe_failures(&o, r[1], body[0], body[1]);
        for (int th = 0; th < 2 && st == CB_OK; th++) {
            double t0 = now();
            st = cb_bool_ssi_trim(r[th], body[0], body[1], r[th]->tol, &err);
            o.t_trim[th] = now() - t0;
        }
    }
    if (runs > 0 && st == CB_OK) {
        o.pairs_out[1] = pairs_with_output(r[1], o.faces_b);
        o.curves[1] = (long)r[1]->n_curves;
        o.points[1] = (long)r[1]->n_points;
        o.length = polyline_length(r[1]);
        o.same[1] = bench_ssi_same(r[0], r[1]);
    }
    o.ok = st == CB_OK;
    if (!o.ok)
        snprintf(o.failures, sizeof o.failures, "%s", err.msg);
    cb_ssi_result_clear(r[0]);
    cb_ssi_result_clear(r[1]);
    cb_topo_body_free(body[0]);
    cb_topo_body_free(body[1]);
    return fwrite(&o, sizeof o, 1, stdout) == 1 ? 0 : 1;
}

/* ---------------------------------------------------------------- the OCCT side ------------ */

static void run_occt(occt_row *o, const char *occt, const char *mode, const model_case *c,
                     const char *dir, double unit_mm, int runs)
{
    memset(o, 0, sizeof o[0]);
    char rs[16], pa[1024], pb[1024], deg[32], tv[3][32], exe[1024], md[16];
    double t[3];
    case_move(t, c);
    snprintf(exe, sizeof exe, "%s", occt);
    snprintf(md, sizeof md, "%s", mode);
    snprintf(rs, sizeof rs, "%d", runs);
    snprintf(pa, sizeof pa, "%s/models/%s", dir, c->a);
    snprintf(pb, sizeof pb, "%s/models/%s", dir, c->b);
    snprintf(deg, sizeof deg, "%.17g", c->deg);
    /* OCCT's reader converts to mm; Colibri keeps the file's unit. */
    for (int i = 0; i < 3; i++)
        snprintf(tv[i], sizeof tv[i], "%.17g", t[i] * unit_mm);
    char zero[] = "0", one[] = "1";
    char *argv[] = {exe, rs, pa, pb, zero, zero, one, deg, tv[0], tv[1], tv[2], md, NULL};
    char out[512];
    size_t got;
    if (spawn_read(out, sizeof out - 1, &got, argv, &o->peak) != 0)
        return;
    out[got] = 0;
    double ms[3];
    if (!strcmp(mode, "none")) {
        o->ok = 1;
    } else if (sscanf(out, "%lf %lf %lf %d %d %d %d %lf", ms, ms + 1, ms + 2, &o->done,
                      &o->errors, &o->edges, &o->vertices, &o->length) == 8) {
        o->ok = 1;
        for (int i = 0; i < 3; i++)
            o->t[i] = 1e-3 * ms[i];
    }
}

/* ---------------------------------------------------------------- main --------------------- */

static double mib(long kib)
{
    return kib < 0 ? NAN : kib / 1024.0;
}

/* A peak in MiB, or null when it was not measured (JSON has no NaN). */
static void json_mib(FILE *f, const char *key, long kib)
{
    if (kib < 0)
        fprintf(f, "\"%s\": null", key);
    else
        fprintf(f, "\"%s\": %.1f", key, mib(kib));
}

static void json_colibri(FILE *f, const colibri_row *o, long peak, long base)
{
    fprintf(f, "\"colibri\": {\"ok\": %s, \"tol\": %.3g, \"faces\": [%d, %d], ",
            o->ok ? "true" : "false", o->tol, o->faces_a, o->faces_b);
    for (int th = 0; th < 2; th++)
        fprintf(f, "\"time_s_threads_%d\": {\"median\": %.6f, \"min\": %.6f, \"max\": %.6f}, "
                   "\"trim_s_threads_%d\": %.6f, ",
                th + 1, o->t[th][0], o->t[th][1], o->t[th][2], th + 1, o->t_trim[th]);
    fprintf(f, "\"face_pairs_with_output\": [%ld, %ld], \"curves\": [%ld, %ld], "
               "\"isolated_points\": [%ld, %ld], \"patch_pairs\": {\"total\": %ld, "
               "\"culled\": %ld, \"proved_empty\": %ld, \"certified\": %ld, "
               "\"not_certified\": %ld, \"not_certified_face_pairs\": %ld, \"subdivision\": %ld, "
               "\"sub_patch_pairs\": %ld}, \"coincident_face_pairs\": %ld, "
               "\"max_dist_a\": %.3g, \"max_dist_b\": %.3g, \"length_mm\": %.9g, "
               "\"identical_1_2_threads\": [%s, %s], ",
            o->pairs_out[0], o->pairs_out[1], o->curves[0], o->curves[1], o->points[0],
            o->points[1], o->total, o->culled, o->empty, o->certified, o->failed,
            o->failed_face_pairs, o->subdivided, o->subpairs, o->coincident, o->dist_a, o->dist_b,
            o->length * o->unit_mm, o->same[0] ? "true" : "false", o->same[1] ? "true" : "false");
    json_mib(f, "peak_mib", peak);
    fputs(", ", f);
    json_mib(f, "read_only_peak_mib", base);
    fputs(", \"not_certified_summary\": ", f);
    cb_json_string(f, o->failures);
    fputs("}", f);
}

static void json_occt(FILE *f, const char *key, const occt_row *o)
{
    fprintf(f, "\"%s\": {\"ok\": %s, \"done\": %s, \"has_errors\": %s, \"edges\": %d, "
               "\"vertices\": %d, \"length_mm\": %.9g, \"time_s\": {\"median\": %.6f, "
               "\"min\": %.6f, \"max\": %.6f}, ",
            key, o->ok ? "true" : "false", o->done ? "true" : "false",
            o->errors ? "true" : "false", o->edges, o->vertices, o->length, o->t[0], o->t[1],
            o->t[2]);
    json_mib(f, "peak_mib", o->peak);
    fputs("}", f);
}

int main(int argc, char **argv)
{
    if (argc == 6 && !strcmp(argv[1], "--case")) {
        int k = atoi(argv[2]), runs = atoi(argv[3]);
        if (k < 0 || k >= N_CASES || runs < 0 || runs > MAX_RUNS)
            return 2;
        return case_mode(k, runs, argv[4], atoi(argv[5]));
    }
    int runs = 1, limit = 0;
    const char *dir = getenv("COLIBRI_SHARED"), *occt = NULL, *json_path = NULL, *only = NULL;
    dir = dir ? dir : "../shared";
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--shared") && i + 1 < argc)
            dir = argv[++i];
        else if (!strcmp(argv[i], "--occt") && i + 1 < argc)
            occt = argv[++i];
        else if (!strcmp(argv[i], "--json") && i + 1 < argc)
            json_path = argv[++i];
        else if (!strcmp(argv[i], "--only") && i + 1 < argc)
            only = argv[++i];
        else if (!strcmp(argv[i], "--limit") && i + 1 < argc && atoi(argv[i + 1]) >= 0)
            limit = atoi(argv[++i]);
        else if (atoi(argv[i]) >= 1 && atoi(argv[i]) <= MAX_RUNS)
            runs = atoi(argv[i]);
        else {
            fprintf(stderr, "usage: bench_ssi_models [RUNS] [--shared DIR] [--occt OCCT_SECTION] "
                            "[--json OUT] [--only CASE] [--limit SECONDS]\n");
            return 2;
        }
    }
    if (occt && (!strcmp(occt, "-") || access(occt, X_OK)))
        occt = NULL;
    FILE *json = NULL;
    if (json_path && !(json = fopen(json_path, "w"))) {
        fprintf(stderr, "bench_ssi_models: cannot write %s\n", json_path);
        return 1;
    }
    char self[] = "/proc/self/exe", ks[16], rs[16], zero[] = "0", flag[] = "--case", dirbuf[1024];
    char ls[16];
    snprintf(rs, sizeof rs, "%d", runs);
    snprintf(ls, sizeof ls, "%d", limit);
    snprintf(dirbuf, sizeof dirbuf, "%s", dir);
    printf("SSI of STEP models against moved copies, %d run%s each; Colibri's time is "
           "cb_ssi_bodies, median [min max] s, trimming after it; OCCT: BRepAlgoAPI_Section "
           "(1 thread: serial mode; 2: parallel); lengths in mm\n",
           runs, runs == 1 ? "" : "s");
    printf("%-8s %3s | %9s %9s %5s %6s %6s %6s %4s %6s %8s %8s %8s %-24s %7s %10s |", "case",
           "thr", "fpairs", "curves", "pts", "pairs", "culled", "cert", "not", "subdiv",
           "subpairs", "dist A", "dist B", "Colibri SSI s", "trim s", "length");
    if (occt)
        printf(" %-24s %-4s %5s %5s %10s %6s", "OCCT section s", "done", "edges", "verts",
               "length", "C/O");
    printf("\n");
    if (json)
        fprintf(json, "{\"runs\": %d, \"cases\": [", runs);
    int status = 0, first = 1;
    for (int k = 0; k < N_CASES; k++) {
        const model_case *c = CASES + k;
        if (only && strcmp(only, c->name))
            continue;
        snprintf(ks, sizeof ks, "%d", k);
        char *base_argv[] = {self, flag, ks, zero, dirbuf, zero, NULL};
        char *case_argv[] = {self, flag, ks, rs, dirbuf, ls, NULL};
        colibri_row o;
        size_t got;
        long base = -1, peak = -1;
        memset(&o, 0, sizeof o);
        if (spawn_read(&o, sizeof o, &got, base_argv, &base) != 0 ||
            spawn_read(&o, sizeof o, &got, case_argv, &peak) != 0 || got != sizeof o) {
            printf("%-8s: the Colibri run failed (see above)\n", c->name);
            status = 1;
            continue;
        }
        occt_row oc[2], ob;
        if (occt) {
            run_occt(&ob, occt, "none", c, dir, o.unit_mm, runs);
            run_occt(oc, occt, "serial", c, dir, o.unit_mm, runs);
            run_occt(oc + 1, occt, "parallel", c, dir, o.unit_mm, runs);
        }
        for (int th = 0; th < 2; th++) {
            char fp[24], cv[24];
            snprintf(fp, sizeof fp, "%ld/%ld", o.pairs_out[0], o.pairs_out[1]);
            snprintf(cv, sizeof cv, "%ld/%ld", o.curves[0], o.curves[1]);
            printf("%-8s %3d | %9s %9s %5ld %6ld %6ld %6ld %4ld %6ld %8ld %8.1e %8.1e "
                   "%7.2f [%6.2f %6.2f] %7.3f %10.6g |",
                   c->name, th + 1, fp, cv, o.points[1], o.total, o.culled, o.certified, o.failed,
                   o.subdivided, o.subpairs, o.dist_a, o.dist_b, o.t[th][0], o.t[th][1],
                   o.t[th][2], o.t_trim[th], o.length * o.unit_mm);
            if (occt && oc[th].ok)
                printf(" %7.2f [%6.2f %6.2f] %-4s %5d %5d %10.6g %6.2f", oc[th].t[0],
                       oc[th].t[1], oc[th].t[2],
                       !oc[th].done ? "no" : (oc[th].errors ? "err" : "yes"), oc[th].edges,
                       oc[th].vertices, oc[th].length,
                       o.ok ? o.t[th][0] / oc[th].t[0] : NAN); /* no ratio for a stopped run */
            else if (occt)
                printf(" the comparator failed");
            printf("\n");
        }
        double t[3];
        case_move(t, c);
        printf("    B: turned %g deg about z through (%g, %g, %g), i.e. about the origin then "
               "moved by (%.17g, %.17g, %.17g); tol %.3g; unit %g mm; faces %d x %d\n",
               c->deg, c->centre[0], c->centre[1], c->centre[2], t[0], t[1], t[2], o.tol,
               o.unit_mm, o.faces_a, o.faces_b);
        printf("    1 and 2 threads bit-identical: %s before trimming, %s after; isolated points "
               "%ld before trimming; patch pairs proved empty %ld; face pairs on one surface (no "
               "curve) %ld\n",
               !o.ok ? "-" : o.same[0] ? "yes" : "NO", !o.ok ? "-" : o.same[1] ? "yes" : "NO",
               o.points[0], o.empty,
               o.coincident);
        printf("    peak memory: Colibri %.1f MiB (reading only %.1f)", mib(peak), mib(base));
        if (occt)
            printf("; OCCT serial %.1f, parallel %.1f MiB (reading only %.1f)", mib(oc[0].peak),
                   mib(oc[1].peak), mib(ob.peak));
        printf("\n");
        if (o.failed)
            printf("    not certified: %ld patch pairs in %ld face pairs: %s\n", o.failed,
                   o.failed_face_pairs, o.failures);
        if (!o.ok) {
            printf("    Colibri: %s\n", o.failures);
            status = 1;
        }
        fflush(stdout);
        if (json) {
            fprintf(json, "%s\n {\"case\": \"%s\", \"a\": \"%s\", \"b\": \"%s\", "
                          "\"turn_deg_about_z\": %.17g, \"centre\": [%.17g, %.17g, %.17g], "
                          "\"move_after_turn\": [%.17g, %.17g, %.17g], \"unit_mm\": %g, ",
                    first ? "" : ",", c->name, c->a, c->b, c->deg, c->centre[0], c->centre[1],
                    c->centre[2], t[0], t[1], t[2], o.unit_mm);
            json_colibri(json, &o, peak, base);
            if (occt) {
                fputs(", ", json);
                json_occt(json, "occt_serial", oc);
                fputs(", ", json);
                json_occt(json, "occt_parallel", oc + 1);
                fputs(", ", json);
                json_mib(json, "occt_read_only_peak_mib", ob.peak);
            }
            fputs("}", json);
        }
        first = 0;
    }
    if (json) {
        fputs("\n]}\n", json);
        fclose(json);
    }
    return status;
}
