/* colibri info: load a model and print what it holds. */
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "brep/nurbs.h"
#include "cli/commands.h"
#include "io/bpt.h"

static const char INFO_USAGE[] =
    "usage: colibri info FILE\n"
    "\n"
    "Loads a model and prints its patches, degrees, control points and bounds.\n"
    "Formats, by extension: .bpt (Bezier patch text, e.g. the Newell teapot).\n"
    "\n"
    "example:\n"
    "  colibri info ../shared/models/teapot.bpt\n";

static int has_extension(const char *path, const char *ext)
{
    const char *dot = strrchr(path, '.');
    return dot && !strcasecmp(dot + 1, ext);
}

static void print_patches(const char *path, const cb_nurbs_surface_struct *p, int n)
{
    long points = 0;
    int rational = 0, max_du = 0, max_dv = 0;
    for (int k = 0; k < n; k++) {
        points += (long)p[k].n_u * p[k].n_v;
        max_du = p[k].deg_u > max_du ? p[k].deg_u : max_du;
        max_dv = p[k].deg_v > max_dv ? p[k].deg_v : max_dv;
        for (long i = 0; i < (long)p[k].n_u * p[k].n_v; i++)
            if (p[k].cw[4 * i + 3] != 1.0) {
                rational++;
                break;
            }
    }
    printf("%s: %d patches (%d rational), %ld control points, degrees up to (%d, %d)\n", path,
           n, rational, points, max_du, max_dv);
}

int cb_cli_info(int argc, char **argv)
{
    if (argc == 2 && !strcmp(argv[1], "--help")) {
        fputs(INFO_USAGE, stdout);
        return 0;
    }
    if (argc != 2 || argv[1][0] == '-') {
        fputs(INFO_USAGE, stderr);
        return 2;
    }
    const char *path = argv[1];
    if (!has_extension(path, "bpt")) {
        fprintf(stderr, "colibri: %s: unknown model format (known: .bpt)\n", path);
        return 1;
    }
    cb_error err;
    cb_error_clear(&err);
    cb_nurbs_surface_struct *patches;
    int n;
    if (cb_bpt_read(&patches, &n, path, &err)) {
        fprintf(stderr, "colibri: %s\n", err.msg);
        return 1;
    }
    print_patches(path, patches, n);
    cb_nurbs_surface_array_free(patches, n);
    return 0;
}
