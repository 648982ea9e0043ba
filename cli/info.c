/* colibri info: load a model and print what it holds. */
#include <stdio.h>
#include <string.h>

#include "brep/nurbs.h"
#include "cli/commands.h"
#include "io/bpt.h"

int cb_cli_info(int argc, char **argv)
{
    if (argc != 2 || argv[1][0] == '-') {
        fprintf(argc == 2 && !strcmp(argv[1], "--help") ? stdout : stderr,
                "usage: colibri info FILE\n");
        return argc == 2 && !strcmp(argv[1], "--help") ? 0 : 2;
    }
    cb_error err;
    cb_error_clear(&err);
    cb_nurbs_surface_struct *patches;
    int n;
    if (cb_bpt_read(&patches, &n, argv[1], &err)) {
        fprintf(stderr, "colibri: %s\n", err.msg);
        return 1;
    }
    printf("%s: %d patches\n", argv[1], n);
    cb_nurbs_surface_array_free(patches, n);
    return 0;
}
