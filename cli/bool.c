/* colibri bool: union, intersection or difference of two STEP solids, checked and written. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "boolean/bool.h"
#include "brep/mesh_check.h"
#include "brep/tess.h"
#include "cli/commands.h"
#include "cli/result.h"
#include "io/json.h"
#include "io/mesh.h"
#include "io/step.h"
#include "io/step_write.h"

static const char BOOL_USAGE[] =
    "usage: colibri bool union|intersection|difference A.step B.step -o OUT\n"
    "                    [--json REPORT.json] [--tol T] [--threads N] [--quiet]\n"
    "                    [--rotate-b AX AY AZ DEG] [--translate-b X Y Z]\n"
    "\n"
    "Computes A u B, A n B or A - B of two closed solids read from STEP files, validates the\n"
    "result, integrates its volume and area on the B-rep, tessellates it and checks the mesh\n"
    "(closed, manifold, self-intersections: CGAL), and writes OUT: a STEP B-rep (.step, .stp)\n"
    "or the mesh (.stl, .obj, .ply, .off). The intersection curves of every face pair must be\n"
    "certified or resolved within tolerance (a region smaller than the tolerance, or surfaces\n"
    "within it of each other; the summary says how many): a refused pair (tangent or\n"
    "coincident faces the intersection does not handle yet) makes the operation fail with its\n"
    "name, never a guessed result.\n"
    "\n"
    "options:\n"
    "  -o OUT            the result file (required)\n"
    "  --json REPORT     write the report as JSON: op, status, message, volume, area, solids,\n"
    "                    faces, valid, mesh {triangles, closed, manifold, self_intersections,\n"
    "                    volume}, ssi {pairs {certified, within_tolerance, refused},\n"
    "                    within_tolerance_regions} (null when the intersection did not run),\n"
    "                    time_s {ssi, split, classify, total}\n"
    "  --tol T           tolerance in model units (default 1e-6 of the operands' box diagonal)\n"
    "  --threads N       threads for the intersections (default 0: all hardware threads)\n"
    "  --quiet           no progress and no text summary; errors still go to stderr\n"
    "  --rotate-b AX AY AZ DEG  turn B by DEG degrees about the axis (AX, AY, AZ) through the\n"
    "                    origin before the operation (B against a moved copy of itself)\n"
    "  --translate-b X Y Z  then move B by (X, Y, Z)\n"
    "\n"
    "An empty result (operands that do not overlap, or only touch) is valid, with volume 0: a\n"
    "mesh file gets no triangle, and no STEP file is written (STEP has no empty solid).\n"
    "\n"
    "Each operand's surface is first meshed and checked by CGAL: one that crosses itself is\n"
    "refused (exit 2), since inside and outside mean nothing there.\n"
    "\n"
    "Exit status: 0 a valid closed result was written, 1 the operation failed or its result\n"
    "is not valid (the message says why), 2 bad usage or an operand that cannot be read.\n"
    "\n"
    "example:\n"
    "  colibri model hummingbird -o a.step\n"
    "  colibri model hummingbird -o b.step --translate 0.3 0.1 0.05\n"
    "  colibri bool union a.step b.step -o birds.stl --json birds.json\n";

static int has_extension(const char *path, const char *ext)
{
    const char *dot = strrchr(path, '.');
    return dot && !strcasecmp(dot + 1, ext);
}

typedef struct {
    const char *op;
    int ok;
    char message[CB_ERROR_MSG_LEN + 32];
    cb_cli_result r;
    double t_ssi, t_split, t_build, t_total;
    int have_ssi; /* the intersection ran: ssi counts below */
    long ssi_certified, ssi_within_tolerance, ssi_refused, ssi_regions;
} report;

static void json_number(FILE *f, double v)
{
    if (isfinite(v))
        fprintf(f, "%.17g", v);
    else
        fputs("null", f);
}

static int write_report(const char *path, const report *r)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return 0;
    fputs("{\"op\": ", f);
    cb_json_string(f, r->op);
    fprintf(f, ", \"status\": \"%s\", \"message\": ", r->ok ? "ok" : "error");
    cb_json_string(f, r->message);
    const cb_cli_result *c = &r->r;
    fputs(", \"volume\": ", f);
    json_number(f, c->volume);
    fputs(", \"area\": ", f);
    json_number(f, c->area);
    fprintf(f, ", \"solids\": %d, \"faces\": %d, \"valid\": %s", c->solids, c->faces,
            c->valid ? "true" : "false");
    if (c->mesh_done) {
        fprintf(f,
                ", \"mesh\": {\"triangles\": %d, \"closed\": %s, \"manifold\": %s, "
                "\"self_intersections\": %d, \"volume\": ",
                c->triangles, c->closed ? "true" : "false", c->manifold ? "true" : "false",
                c->self_intersections);
        json_number(f, c->mesh_volume);
        fputc('}', f);
    } else {
        fputs(", \"mesh\": null", f);
    }
    if (r->have_ssi)
        fprintf(f,
                ", \"ssi\": {\"pairs\": {\"certified\": %ld, \"within_tolerance\": %ld, "
                "\"refused\": %ld}, \"within_tolerance_regions\": %ld}",
                r->ssi_certified, r->ssi_within_tolerance, r->ssi_refused, r->ssi_regions);
    else
        fputs(", \"ssi\": null", f);
    fprintf(f,
            ", \"time_s\": {\"ssi\": %.3f, \"split\": %.3f, \"classify\": %.3f, \"total\": "
            "%.3f}}\n",
            r->t_ssi, r->t_split, r->t_build, r->t_total);
    return fclose(f) == 0;
}

/* Checks the result into rep (cli/result.h) and writes out. Returns the exit status. */
static int finish(report *rep, cb_topo_body *res, const char *out, int quiet, cb_context *ctx)
{
    cb_error err;
    cb_error_clear(&err);
    cb_mesh_t mesh;
    cb_mesh_init(mesh);
    cb_cli_result *r = &rep->r;
    cb_cli_result_check(r, res, mesh, ctx);
    snprintf(rep->message, sizeof rep->message, "%s", r->message);
    int code = r->valid && r->mesh_ok ? 0 : 1;
    cb_status st = CB_OK;
    int step = has_extension(out, "step") || has_extension(out, "stp");
    if (step && res->n_faces == 0)
        fprintf(stderr, "colibri: the result is empty: no STEP file written (a STEP solid needs "
                        "a face)\n");
    else if (step)
        st = cb_step_write(res, out, "colibri boolean", &err);
    else
        st = r->mesh_done ? cb_mesh_write(out, mesh, NULL, &err) : CB_OK;
    if (st) {
        fprintf(stderr, "colibri: %s\n", err.msg);
        code = 2;
    }
    cb_mesh_clear(mesh);
    if (!quiet) {
        if (res->n_faces == 0)
            printf("result: empty (the operands do not overlap, or touch only)\n");
        else
            printf("result: %d solid%s, %d faces, %s\n", r->solids, r->solids == 1 ? "" : "s",
                   r->faces, r->valid ? "valid" : "NOT valid");
        printf("volume %.12g, area %.12g (B-rep, model units)\n", r->volume, r->area);
        if (r->mesh_done)
            printf("mesh: %d triangles, closed %s, manifold %s, self-intersections %s, volume "
                   "%.10g\n",
                   r->triangles, r->closed ? "yes" : "no", r->manifold ? "yes" : "no",
                   r->self_intersections < 0   ? "not checked"
                   : r->self_intersections ? "yes"
                                           : "none",
                   r->mesh_volume);
        if (r->touching && r->valid && r->mesh_ok)
            printf("%s\n", r->message);
    }
    /* A result refused by its checks is an error: said on stderr, with --quiet too. */
    if (!r->valid || !r->mesh_ok)
        fprintf(stderr, "colibri: %s\n", r->message);
    return code;
}

/* Whether body b's surface crosses itself, by its mesh (default tolerances) and CGAL: 1 with
 * the reason in msg, 0 when it does not or cannot be told (a body that cannot be meshed is
 * left to cb_bool_run's own checks). */
static int crosses_itself(const cb_topo_body *b, cb_context *ctx, char *msg, size_t n)
{
    cb_error err;
    cb_mesh_t mesh;
    cb_mesh_init(mesh);
    cb_mesh_check_report r;
    int bad = !cb_tess_body(mesh, b, NULL, ctx, &err) && !cb_mesh_check(&r, mesh, &err) &&
              r.self_intersections == 1;
    if (bad)
        snprintf(msg, n, "its surface crosses itself (the CGAL check of its %d-triangle mesh)",
                 r.triangles);
    cb_mesh_clear(mesh);
    return bad;
}

int cb_cli_bool(int argc, char **argv)
{
    const char *files[2] = {NULL, NULL}, *out = NULL, *json = NULL, *opname = NULL;
    int quiet = 0, threads = 0, nf = 0, moved;
    double tol = 0;
    cb_cli_move move;
    cb_cli_move_init(&move);
    for (int k = 1; k < argc; k++) {
        if (!strcmp(argv[k], "--help")) {
            fputs(BOOL_USAGE, stdout);
            return 0;
        }
        if (!strcmp(argv[k], "--quiet")) {
            quiet = 1;
        } else if (!strcmp(argv[k], "-o") && k + 1 < argc) {
            out = argv[++k];
        } else if (!strcmp(argv[k], "--json") && k + 1 < argc) {
            json = argv[++k];
        } else if (!strcmp(argv[k], "--threads") && k + 1 < argc) {
            if (cb_cli_threads_arg(&threads, argv[++k]))
                return 2;
        } else if (!strcmp(argv[k], "--tol") && k + 1 < argc) {
            if (cb_cli_tol_arg(&tol, argv[++k]))
                return 2;
        } else if ((moved = cb_cli_move_parse(&move, argc, argv, &k, "bool")) != 0) {
            if (moved < 0)
                return 2;
        } else if (argv[k][0] == '-' && argv[k][1]) {
            fprintf(stderr, "colibri: bool: unknown option '%s'\n", argv[k]);
            fputs(BOOL_USAGE, stderr);
            return 2;
        } else if (!opname) {
            opname = argv[k];
        } else if (nf < 2) {
            files[nf++] = argv[k];
        } else {
            fputs(BOOL_USAGE, stderr);
            return 2;
        }
    }
    cb_bool_op op;
    if (!opname || nf < 2 || !out) {
        fputs(BOOL_USAGE, stderr);
        return 2;
    }
    if (!strcmp(opname, "union"))
        op = CB_BOOL_UNION;
    else if (!strcmp(opname, "intersection"))
        op = CB_BOOL_INTERSECTION;
    else if (!strcmp(opname, "difference"))
        op = CB_BOOL_DIFFERENCE;
    else {
        fprintf(stderr,
                "colibri: bool: unknown operation '%s' (union, intersection or difference)\n",
                opname);
        return 2;
    }
    cb_error err;
    cb_error_clear(&err);
    cb_mesh_format fmt;
    if (!has_extension(out, "step") && !has_extension(out, "stp") &&
        cb_mesh_format_of_path(&fmt, out, &err)) {
        fprintf(stderr, "colibri: %s (or .step, .stp)\n", err.msg);
        return 2;
    }
    double t0 = cb_cli_seconds();
    cb_topo_body *body[2] = {NULL, NULL};
    for (int k = 0; k < 2; k++) {
        cb_status rs = cb_step_read(body + k, files[k], &err);
        if (rs) {
            fprintf(stderr, "colibri: %s\n", err.msg);
            cb_topo_body_free(body[0]);
            return cb_cli_input_exit(rs);
        }
    }
    cb_cli_move_apply(&move, body[1]);
    cb_context ctx;
    cb_context_init(&ctx);
    ctx.threads = threads;
    int shown = -1;
    if (!quiet && isatty(STDERR_FILENO)) {
        ctx.progress = cb_cli_progress;
        ctx.user = &shown;
    }
    /* A Boolean needs solids whose boundaries do not cross themselves: inside and outside
     * mean nothing otherwise, and the result would be silently wrong. */
    for (int k = 0; k < 2; k++) {
        char why[160];
        if (crosses_itself(body[k], &ctx, why, sizeof why)) {
            fprintf(stderr, "colibri: bool: operand %c (%s): %s\n", "AB"[k], files[k], why);
            cb_topo_body_free(body[0]);
            cb_topo_body_free(body[1]);
            return 2;
        }
    }
    cb_context_progress_reset(&ctx);
    cb_bool_opts o;
    cb_bool_opts_init(&o);
    o.tol = tol;
    cb_bool_stats stats;
    cb_topo_body *res = NULL;
    report rep;
    memset(&rep, 0, sizeof rep);
    rep.op = cb_bool_op_name(op);
    rep.r.volume = rep.r.area = NAN;
    cb_status st = cb_bool_run(&res, &stats, op, body[0], body[1], &o, &ctx, &err);
    rep.t_ssi = stats.time_ssi;
    rep.t_split = stats.time_split;
    rep.t_build = stats.time_build;
    rep.have_ssi = stats.ssi_done;
    rep.ssi_certified = stats.ssi_certified;
    rep.ssi_within_tolerance = stats.ssi_within_tolerance;
    rep.ssi_refused = stats.ssi_refused;
    rep.ssi_regions = stats.ssi_regions;
    int code;
    if (st) {
        snprintf(rep.message, sizeof rep.message, "%s", err.msg);
        fprintf(stderr, "%scolibri: %s\n", shown >= 0 ? "\n" : "", err.msg);
        code = st == CB_ERR_INVALID ? 2 : 1;
    } else {
        if (!quiet) {
            printf("%s: %d intersection curves, %d cuts; pieces kept: A %d of %d, B %d of %d\n",
                   rep.op, stats.curves, stats.cuts, stats.kept[0], stats.pieces[0],
                   stats.kept[1], stats.pieces[1]);
            printf("intersection: %ld patch pairs certified, %ld resolved within tolerance "
                   "(%ld regions), %ld refused\n",
                   stats.ssi_certified, stats.ssi_within_tolerance, stats.ssi_regions,
                   stats.ssi_refused);
        }
        code = finish(&rep, res, out, quiet, &ctx);
        rep.ok = code == 0;
    }
    if (shown >= 0)
        fputc('\n', stderr);
    rep.t_total = cb_cli_seconds() - t0;
    if (json && !write_report(json, &rep)) {
        fprintf(stderr, "colibri: cannot write %s\n", json);
        code = 2;
    }
    cb_topo_body_free(res);
    cb_topo_body_free(body[0]);
    cb_topo_body_free(body[1]);
    return code;
}
