/* colibri demo: every shipped Boolean scenario in all three operations, checked against its
 * reference volume, with the result meshes and pictures written out. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "boolean/bool.h"
#include "cli/commands.h"
#include "cli/result.h"
#include "io/mesh.h"
#include "models/models.h"

static const char DEMO_USAGE[] =
    "usage: colibri demo [--out DIR] [--only NAME] [--threads N] [--quiet]\n"
    "\n"
    "Runs the shipped Boolean scenarios — two overlapping hummingbirds (312 bicubic B-spline\n"
    "faces each) and the Cardan-joint scenarios, with analytic and with B-spline faces — in\n"
    "union, intersection and difference (A - B). Each result is validated, its volume\n"
    "integrated on the B-rep and compared with the scenario's reference volume, which comes\n"
    "from closed forms (Cardan) or from an estimate by vertical lines through both birds that\n"
    "uses no Boolean code (models/README.md); the result is tessellated, the mesh checked\n"
    "(closed, manifold, self-intersections) and written to DIR as NAME_OP.stl, NAME_OP.obj and a\n"
    "picture NAME_OP.svg. Prints one table row per operation:\n"
    "  ok       valid, mesh closed and manifold without self-intersections, volume within the\n"
    "           error bar of the reference; \"ok (solids touch)\", \"ok (touches itself)\":\n"
    "           the mesh meets itself, its triangles touching there and none crossing, where\n"
    "           the result's solids touch each other or the solid touches itself (a union of\n"
    "           operands that touch along a line: not a manifold solid there, as the exact\n"
    "           union is not)\n"
    "  WRONG    a result that fails one of those (the column says which)\n"
    "  refused  the operation stopped with a message (a configuration not handled yet, or a\n"
    "           face pair whose intersection could not be certified): no result, by design\n"
    "\n"
    "Error bars (absolute): closed forms, 1e-6 of the reference plus 1e-9 (V(A) + V(B)); the\n"
    "birds, three standard deviations of the estimate of V(A n B).\n"
    "\n"
    "options:\n"
    "  --out DIR     where the meshes and pictures go (default out; created if missing)\n"
    "  --only NAME   only the scenarios whose name contains NAME (e.g. hummingbirds,\n"
    "                cross_into_base, _nurbs)\n"
    "  --threads N   threads (default 0: all hardware threads)\n"
    "  --quiet       no progress on stderr\n"
    "\n"
    "Exit status: 0 no row is WRONG (refused rows are counted in the summary), 1 some row is\n"
    "WRONG or a scenario could not be built, 2 bad usage or DIR cannot be made.\n";

/* Writes the mesh as STL, OBJ and SVG under dir; 0 or -1 with the reason in err. */
static int write_outputs(const char *dir, const char *name, const char *op, const cb_mesh_t mesh,
                         cb_error *err)
{
    static const char *const ext[2] = {"stl", "obj"};
    char path[4096], title[256];
    for (int k = 0; k < 2; k++) {
        snprintf(path, sizeof path, "%s/%s_%s.%s", dir, name, op, ext[k]);
        if (cb_mesh_write(path, mesh, NULL, err))
            return -1;
    }
    snprintf(path, sizeof path, "%s/%s_%s.svg", dir, name, op);
    snprintf(title, sizeof title, "colibri: %s, %s", name, op);
    return cb_mesh_write_svg(path, mesh, title, 800, err) ? -1 : 0;
}

typedef struct {
    int ok, wrong, refused;
} tally;

static void run_op(tally *t, const cb_model_scenario *L, int opk, const char *dir,
                   cb_context *ctx)
{
    static const cb_bool_op ops[3] = {CB_BOOL_UNION, CB_BOOL_INTERSECTION, CB_BOOL_DIFFERENCE};
    const char *op = cb_bool_op_name(ops[opk]);
    cb_error err;
    cb_error_clear(&err);
    cb_topo_body *res = NULL;
    cb_bool_stats stats;
    double t0 = cb_cli_seconds();
    cb_status st = cb_bool_run(&res, &stats, ops[opk], L->a, L->b, NULL, ctx, &err);
    double t_bool = cb_cli_seconds() - t0;
    printf("%-26s %-12s ", L->name, op);
    if (st) {
        printf("%13s %13s %9s %8s %-16s %7.2f  refused: %s\n", "-", "-", "-", "-", "-", t_bool,
               err.msg);
        t->refused++;
        fflush(stdout);
        return;
    }
    cb_mesh_t mesh;
    cb_mesh_init(mesh);
    cb_cli_result r;
    cb_cli_result_check(&r, res, mesh, ctx);
    double ref = L->ref[opk], dv = r.volume - ref;
    double rel = ref != 0 ? fabs(dv) / fabs(ref) : fabs(dv);
    int in_bar = fabs(dv) <= L->bar[opk];
    char mesh_txt[32];
    if (!r.mesh_done)
        snprintf(mesh_txt, sizeof mesh_txt, "not made");
    else if (r.triangles == 0)
        snprintf(mesh_txt, sizeof mesh_txt, "empty");
    else
        snprintf(mesh_txt, sizeof mesh_txt, "%s%s%s", r.closed ? "C" : "-", r.manifold ? "M" : "-",
                 r.self_intersections == 0 ? "S" : r.self_intersections < 0 ? "?" : "x");
    const char *why = !r.valid || !r.mesh_ok ? r.message
                      : !in_bar                ? "volume outside the error bar"
                                               : NULL;
    if (r.mesh_done && r.triangles > 0 && write_outputs(dir, L->name, op, mesh, &err) && !why)
        why = err.msg;
    const char *note = why                           ? why
                       : !r.touching                 ? ""
                       : r.solids >= 2               ? " (solids touch)"
                                                     : " (touches itself)";
    printf("%13.9g %13.9g %9.2e %8.1e %-16s %7.2f  %s%s\n", r.volume, ref, rel, L->bar[opk],
           mesh_txt, cb_cli_seconds() - t0, why ? "WRONG: " : "ok", note);
    fflush(stdout);
    if (why)
        t->wrong++;
    else
        t->ok++;
    cb_mesh_clear(mesh);
    cb_topo_body_free(res);
}

/* Makes dir if missing: 0, or 2 after printing why not. */
static int make_dir(const char *dir)
{
    struct stat sb;
    if (!stat(dir, &sb)) {
        if (S_ISDIR(sb.st_mode))
            return 0;
        fprintf(stderr, "colibri: demo: %s exists and is not a directory\n", dir);
        return 2;
    }
    if (mkdir(dir, 0777)) {
        fprintf(stderr, "colibri: demo: cannot make %s: %s\n", dir, strerror(errno));
        return 2;
    }
    return 0;
}

int cb_cli_demo(int argc, char **argv)
{
    const char *dir = "out", *only = NULL;
    int threads = 0, quiet = 0;
    for (int k = 1; k < argc; k++) {
        if (!strcmp(argv[k], "--help")) {
            fputs(DEMO_USAGE, stdout);
            return 0;
        } else if (!strcmp(argv[k], "--quiet")) {
            quiet = 1;
        } else if (!strcmp(argv[k], "--out") && k + 1 < argc) {
            dir = argv[++k];
        } else if (!strcmp(argv[k], "--only") && k + 1 < argc) {
            only = argv[++k];
        } else if (!strcmp(argv[k], "--threads") && k + 1 < argc) {
            if (cb_cli_threads_arg(&threads, argv[++k]))
                return 2;
        } else {
            fprintf(stderr, "colibri: demo: unknown argument '%s'\n", argv[k]);
            fputs(DEMO_USAGE, stderr);
            return 2;
        }
    }
    int n = cb_model_scenario_count(), selected = 0;
    for (int k = 0; k < n; k++) {
        char name[64];
        cb_error e;
        selected += !cb_model_scenario_name(name, sizeof name, k, &e) &&
                    (!only || strstr(name, only) != NULL);
    }
    if (!selected) {
        fprintf(stderr, "colibri: demo: no scenario name contains '%s'\n", only);
        return 2;
    }
    int code = make_dir(dir);
    if (code)
        return code;
    cb_context ctx;
    cb_context_init(&ctx);
    ctx.threads = threads;
    int shown = -1;
    if (!quiet && isatty(STDERR_FILENO)) {
        ctx.progress = cb_cli_progress;
        ctx.user = &shown;
    }
    printf("%-26s %-12s %13s %13s %9s %8s %-16s %7s  %s\n", "scenario", "operation", "volume",
           "reference", "rel.err", "bar", "mesh", "time/s", "verdict");
    tally t = {0, 0, 0};
    int failed_builds = 0;
    double t0 = cb_cli_seconds();
    for (int k = 0; k < n; k++) {
        char name[64];
        cb_error err;
        cb_error_clear(&err);
        if (cb_model_scenario_name(name, sizeof name, k, &err) || (only && !strstr(name, only)))
            continue;
        cb_model_scenario L;
        cb_status st = cb_model_scenario_load(&L, k, &err);
        if (st) {
            printf("%-26s cannot be built: %s\n", name, err.msg);
            failed_builds++;
            continue;
        }
        for (int op = 0; op < 3; op++)
            run_op(&t, &L, op, dir, &ctx);
        cb_model_scenario_clear(&L);
    }
    if (shown >= 0)
        fputc('\n', stderr);
    printf("\nmesh: C closed, M manifold, S no self-intersection (x: some; ?: not checked)\n");
    printf("%d ok, %d WRONG, %d refused, %d scenario%s not built; %.1f s; meshes and pictures "
           "in %s/\n",
           t.ok, t.wrong, t.refused, failed_builds, failed_builds == 1 ? "" : "s",
           cb_cli_seconds() - t0, dir);
    return t.wrong || failed_builds ? 1 : 0;
}
