/* colibri — command-line front end. */
#include <stdio.h>
#include <string.h>

#include "cli/commands.h"

static void usage(FILE *out)
{
    fprintf(out,
            "usage: colibri [--timeout SECONDS] [--max-memory MB] COMMAND [options] [files]\n"
            "\n"
            "Solid Booleans on B-rep models with B-spline faces.\n"
            "\n"
            "commands:\n"
            "  info FILE     load a model (.step, .stp, .bpt) and print its counts, surface\n"
            "                types, bounds and validation (--json for one JSON object)\n"
            "  model NAME    build a shipped model (hummingbird, cardan, bracket) in a given\n"
            "                pose and write it\n"
            "                as STEP (-o FILE.step)\n"
            "  check MESH    check that a mesh (.stl, .obj, .ply, .off) is closed, manifold,\n"
            "                outward and free of self-intersections; print its volume\n"
            "  ssi A B       intersection curves of the faces of two STEP models\n"
            "  mesh MODEL    tessellate a STEP model into a checked watertight mesh\n"
            "                (-o OUT.stl|obj|ply|off, --tol T)\n"
            "  bool OP A B   union, intersection or difference of two STEP solids\n"
            "                (-o OUT.step|stl|obj|ply|off, --json REPORT)\n"
            "  demo          every shipped Boolean scenario in all three operations, against\n"
            "                its reference volume; meshes and pictures to out/\n"
            "\n"
            "Run 'colibri COMMAND --help' for the options of a command.\n"
            "\n"
            "global options (before COMMAND):\n"
            "  --timeout SECONDS  stop after this wall time (a number > 0): the process ends at\n"
            "                     once with 'colibri: timed out after SECONDS s' and exit status\n"
            "                     1. A hard stop, not a cancellation: nothing is cleaned up and a\n"
            "                     file being written is left incomplete\n"
            "  --max-memory MB    limit the address space to MB megabytes (a whole number >= 1);\n"
            "                     allocations beyond it fail and the command stops with an\n"
            "                     out-of-memory message and exit status 1. Ignored, with a note,\n"
            "                     by AddressSanitizer builds\n"
            "\n"
            "Exit status: 0 success; 1 the command ran and its verdict is negative (model\n"
            "invalid, mesh check failed, intersection failed or unsupported); 2 bad usage or an\n"
            "input that cannot be used (missing, unreadable, malformed, wrong format).\n");
}

int cb_cli_input_exit(cb_status st)
{
    return st == CB_ERR_NOMEM ? 1 : 2;
}

int main(int argc, char **argv)
{
    cb_cli_limits lim;
    cb_cli_limits_init(&lim);
    int k = 1;
    while (k < argc) {
        int used = cb_cli_limits_parse(&lim, argc, argv, k);
        if (used < 0)
            return 2;
        if (!used)
            break;
        k += used;
    }
    if (k >= argc) {
        usage(stderr);
        return 2;
    }
    const char *cmd = argv[k];
    if (!strcmp(cmd, "--help") || !strcmp(cmd, "-h") || !strcmp(cmd, "help")) {
        usage(stdout);
        return 0;
    }
    if (!strcmp(cmd, "--version")) {
        printf("colibri %s\n", COLIBRI_VERSION);
        return 0;
    }
    static const struct {
        const char *name;
        int (*run)(int argc, char **argv);
    } commands[] = {{"info", cb_cli_info},
                    {"model", cb_cli_model},
                    {"check", cb_cli_check},
                    {"ssi", cb_cli_ssi},
                    {"mesh", cb_cli_mesh},
                    {"bool", cb_cli_bool}, {"demo", cb_cli_demo}};
    for (size_t c = 0; c < sizeof commands / sizeof *commands; c++)
        if (!strcmp(cmd, commands[c].name)) {
            int code = cb_cli_limits_apply(&lim);
            return code ? code : commands[c].run(argc - k, argv + k);
        }
    fprintf(stderr, "colibri: unknown command '%s'\n", cmd);
    usage(stderr);
    return 2;
}
