/* colibri — command-line front end. */
#include <stdio.h>
#include <string.h>

#include "cli/commands.h"

static void usage(FILE *out)
{
    fprintf(out,
            "usage: colibri COMMAND [options] [files]\n"
            "\n"
            "Solid Booleans on B-rep models with B-spline faces.\n"
            "\n"
            "commands:\n"
            "  info FILE     load a model (.step, .stp, .bpt) and print its counts, surface\n"
            "                types, bounds and validation (--json for one JSON object)\n"
            "  model NAME    build a shipped model (hummingbird) in a given pose and write it\n"
            "                as STEP (-o FILE.step)\n"
            "  check MESH    check that a mesh (.stl, .obj, .ply, .off) is closed, manifold,\n"
            "                outward and free of self-intersections; print its volume\n"
            "  ssi A B       intersection curves of the faces of two STEP models\n"
            "  mesh MODEL    tessellate a STEP model into a checked watertight mesh\n"
            "                (-o OUT.stl|obj|ply|off, --tol T)\n"
            "\n"
            "Run 'colibri COMMAND --help' for the options of a command.\n"
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
    if (argc < 2) {
        usage(stderr);
        return 2;
    }
    const char *cmd = argv[1];
    if (!strcmp(cmd, "--help") || !strcmp(cmd, "-h") || !strcmp(cmd, "help")) {
        usage(stdout);
        return 0;
    }
    if (!strcmp(cmd, "--version")) {
        printf("colibri %s\n", COLIBRI_VERSION);
        return 0;
    }
    if (!strcmp(cmd, "info"))
        return cb_cli_info(argc - 1, argv + 1);
    if (!strcmp(cmd, "model"))
        return cb_cli_model(argc - 1, argv + 1);
    if (!strcmp(cmd, "check"))
        return cb_cli_check(argc - 1, argv + 1);
    if (!strcmp(cmd, "ssi"))
        return cb_cli_ssi(argc - 1, argv + 1);
    if (!strcmp(cmd, "mesh"))
        return cb_cli_mesh(argc - 1, argv + 1);
    fprintf(stderr, "colibri: unknown command '%s'\n", cmd);
    usage(stderr);
    return 2;
}
