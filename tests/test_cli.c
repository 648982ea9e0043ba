/* The colibri command: exit codes and messages of every command (binary from COLIBRI_BINARY). */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "check_cli.h"

int main(void)
{
    const char *shared = getenv("COLIBRI_SHARED");
    char args[1024];
    cli_expect("", 2, "usage: colibri COMMAND");
    cli_expect("--help", 0, "commands:");
    cli_expect("--version", 0, "colibri ");
    cli_expect("frobnicate", 2, "unknown command 'frobnicate'");
    cli_expect("info --help", 0, "usage: colibri info");
    cli_expect("info", 2, "usage: colibri info");
    cli_expect("info a b", 2, "usage: colibri info");
    cli_expect("info /nonexistent.bpt", 1, "/nonexistent.bpt: cannot open");
    snprintf(args, sizeof args, "info '%s/models/teapot.bpt'", shared ? shared : "../shared");
    cli_expect(args, 0, "32 patches");
    snprintf(args, sizeof args, "info '%s/models/SOURCES.md'", shared ? shared : "../shared");
    cli_expect(args, 1, "SOURCES.md: unknown model format");
    /* A .bpt path that cannot be opened says so. */
    snprintf(args, sizeof args, "info /dev/null/x.bpt");
    cli_expect(args, 1, "x.bpt: cannot open");
    /* STEP models: text and JSON summaries, rejected files, bad options. */
    const char *sh = shared ? shared : "../shared";
    snprintf(args, sizeof args, "info '%s/models/ujoint_cross.step'", sh);
    cli_expect(args, 0, "1 solid, 1 shell, 8 faces, 14 edges, 8 vertices");
    cli_expect(args, 0, "validation (tolerance 1e-07): valid");
    snprintf(args, sizeof args, "info --json '%s/models/ujoint_fork.step'", sh);
    cli_expect(args, 0, "\"solids\": 1, \"shells\": 1, \"faces\": 17, \"edges\": 54");
    cli_expect(args, 0, "\"surface_types\": {\"cylinder\": 7, \"plane\": 7, \"sphere\": 3}");
    cli_expect(args, 0, "\"valid\": true, \"problems\": []");
    snprintf(args, sizeof args, "info '%s/models/trj5_k1-al-214.stp' --json", sh);
    cli_expect(args, 0, "\"surface_types\": {\"bspline\": 39}");
    cli_expect(args, 0, "\"unit_mm\": 10,");
    /* linkrods' edges stray 4.1e-4 from their surfaces: invalid at its own 2e-5, valid at 5e-4. */
    snprintf(args, sizeof args, "info '%s/models/linkrods.step' --json", sh);
    cli_expect(args, 0, "\"valid\": false");
    snprintf(args, sizeof args, "info '%s/models/linkrods.step' --tol 5e-4", sh);
    cli_expect(args, 0, "validation (tolerance 0.0005): valid");
    char bad[64], want[160];
    snprintf(bad, sizeof bad, "/tmp/colibri_cli_bad_%ld.step", (long)getpid());
    FILE *f = fopen(bad, "w");
    fputs("ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n#1=MANIFOLD_SOLID_BREP('',#2);\n"
          "#2=CLOSED_SHELL('',(#3));\nENDSEC;\nEND-ISO-10303-21;\n",
          f);
    fclose(f);
    snprintf(args, sizeof args, "info %s", bad);
    snprintf(want, sizeof want, "%s:6: #2 CLOSED_SHELL: face: #3 is not defined", bad);
    cli_expect(args, 1, want);
    remove(bad);
    cli_expect("info /nonexistent/x.step --json", 1, "x.step: cannot open");
    cli_expect("info x.step --tol abc", 2, "--tol needs a positive number");
    cli_expect("info x.step --bogus", 2, "usage: colibri info");
    return check_report("cli");
}
