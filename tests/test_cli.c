/* The colibri command: exit codes and messages of every command (binary from COLIBRI_BINARY).
 * Exit status: 0 success, 1 a negative verdict (invalid model, failed check), 2 bad usage or an
 * input that cannot be used. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "check_cli.h"

/* The number after "key": in the output of the last run (NaN if absent). */
static double json_number(const char *key)
{
    char pat[64];
    snprintf(pat, sizeof pat, "\"%s\": ", key);
    const char *at = strstr(cli_out, pat);
    return at ? strtod(at + strlen(pat), NULL) : NAN;
}

/* The whole of a file, NUL-terminated (NULL if it cannot be read). */
static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    char *text = NULL;
    size_t len = 0, cap = 0, got;
    char chunk[4096];
    while ((got = fread(chunk, 1, sizeof chunk, f)) > 0) {
        if (len + got + 1 > cap) {
            cap = 2 * (len + got + 1);
            text = realloc(text, cap);
        }
        memcpy(text + len, chunk, got);
        len += got;
    }
    fclose(f);
    if (text)
        text[len] = '\0';
    return text;
}

static void write_file(const char *path, const char *data, size_t len)
{
    FILE *f = fopen(path, "wb");
    CHECK(f != NULL, "cannot write %s", path);
    if (!f)
        return;
    fwrite(data, 1, len, f);
    fclose(f);
}

/* `colibri info` on `text` with the first `from` replaced by `to`, written to path: exit code
 * `code` and a message holding `want` (where "@" stands for the path). */
static void info_corrupted(const char *path, const char *text, const char *from, const char *to,
                           int code, const char *want)
{
    const char *at = strstr(text, from);
    CHECK(at != NULL, "test setup: '%s' not in the model", from);
    if (!at)
        return;
    size_t head = (size_t)(at - text), len = strlen(text) - strlen(from) + strlen(to);
    char *out = malloc(len + 1);
    memcpy(out, text, head);
    strcpy(out + head, to);
    strcat(out, at + strlen(from));
    write_file(path, out, len);
    free(out);
    char args[1200], msg[1200];
    snprintf(args, sizeof args, "info %s", path);
    const char *mark = strchr(want, '@');
    if (mark)
        snprintf(msg, sizeof msg, "%.*s%s%s", (int)(mark - want), want, path, mark + 1);
    else
        snprintf(msg, sizeof msg, "%s", want);
    cli_expect(args, code, msg);
}

/* Every class of unusable STEP input gives exit 2 and a message naming file:line and #id;
 * a model that reads but fails validation gives 1. The corruptions are made on
 * ujoint_cross.step, whose lines 33-39 read
 *   #21 = EDGE_CURVE('',#22,#24,#26,.T.);
 *   #22 = VERTEX_POINT('',#23);
 *   #23 = CARTESIAN_POINT('',(85.,100.,0.));
 *   ...
 *   #27 = LINE('',#28,#29); */
static void test_bad_step(const char *sh)
{
    char model[1024], path[128], args[1200];
    snprintf(model, sizeof model, "%s/models/ujoint_cross.step", sh);
    char *text = slurp(model);
    CHECK(text != NULL, "cannot read %s", model);
    if (!text)
        return;
    snprintf(path, sizeof path, "/tmp/colibri_cli_step_%ld.step", (long)getpid());
    info_corrupted(path, text, "#22 = VERTEX_POINT('',#23);", "#22 = VERTEX_POINT('',#99999);",
                   2, "@:34: #22 VERTEX_POINT: vertex_geometry: #99999 is not defined");
    info_corrupted(path, text, "#22 = VERTEX_POINT('',#23);", "#22 = VERTEX_POINT('',#23)", 2,
                   "@:35: #22 VERTEX_POINT: expected ';'");
    info_corrupted(path, text, "#27 = LINE('',#28,#29);",
                   "#27 = SURFACE_CURVE('',#27,(),.CURVE_3D.);", 2,
                   "@:39: #27 SURFACE_CURVE: cyclic reference");
    info_corrupted(path, text, "#27 = LINE('',#28,#29);", "#27 = LINE('',#28);", 2,
                   "@:39: #27 LINE: 2 parameters given, 3 expected");
    info_corrupted(path, text, "#21 = EDGE_CURVE('',#22,#24,#26,.T.);",
                   "#21 = EDGE_CURVE('',#22,#24,#26,1.5);", 2,
                   "@:33: #21 EDGE_CURVE: same_sense: .T. or .F. expected, found a real");
    info_corrupted(path, text, "#22 = VERTEX_POINT('',#23);", "#22 = VERTEX_POINT('',#22);", 2,
                   "@:34: #22 VERTEX_POINT: CARTESIAN_POINT expected");
    info_corrupted(path, text, "(85.,100.,0.)", "(1e300,100.,0.)", 2,
                   "@:35: #23 CARTESIAN_POINT: coordinate 1 is 1e+300, beyond");
    info_corrupted(path, text, "(85.,100.,0.)", "(1e999,100.,0.)", 2,
                   "@:35: #23 CARTESIAN_POINT: number 1e999 is not a finite double");
    /* Truncated inside an entity: the instance cut is named, at its line. */
    const char *cut = strstr(text, "#185 = B_SPLINE_CURVE_WITH_KNOTS(");
    CHECK(cut != NULL, "test setup: #185 not in the model");
    if (cut) {
        int line = 1;
        for (const char *c = text; c < cut; c++)
            line += *c == '\n';
        write_file(path, text, (size_t)(cut - text) + 60);
        snprintf(args, sizeof args, "info %s", path);
        char want[256];
        snprintf(want, sizeof want, "%s:%d: #185 B_SPLINE_CURVE_WITH_KNOTS: ", path, line);
        cli_expect(args, 2, want);
    }
    /* Empty file, binary garbage. */
    write_file(path, "", 0);
    snprintf(args, sizeof args, "info %s", path);
    cli_expect(args, 2, "empty file");
    char garbage[256];
    for (int k = 0; k < 256; k++)
        garbage[k] = (char)(k * 37 + 11);
    write_file(path, garbage, sizeof garbage);
    char want[256];
    snprintf(want, sizeof want, "%s:1: not a STEP file", path);
    cli_expect(args, 2, want);
    /* Read, but invalid: vertex #23 moved by 1 (far beyond the 0.0117 cap on edge
     * tolerances) leaves the edges at it off their vertex. */
    info_corrupted(path, text, "(85.,100.,0.)", "(85.,100.,1.)", 1,
                   "edge 2: curve start is 0.707 from vertex 0");
    cli_expect(args, 1, "4 edges deviate beyond the cap");
    snprintf(args, sizeof args, "info %s --json", path);
    cli_expect(args, 1, "\"valid\": false");
    cli_expect(args, 1, "\"edges_over_cap\": 4");
    remove(path);
    free(text);
}

/* check and ssi: unusable files give 2, a failed check 1. */
static void test_other_commands(const char *sh)
{
    char path[128], args[1200];
    snprintf(path, sizeof path, "/tmp/colibri_cli_mesh_%ld.off", (long)getpid());
    const char *tri = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    write_file(path, tri, strlen(tri));
    snprintf(args, sizeof args, "check %s", path);
    cli_expect(args, 1, "closed: no (3 boundary edges)");
    write_file(path, "OFF\nabc def\n", 12);
    cli_expect(args, 2, path);
    remove(path);
    cli_expect("check /nonexistent/x.stl", 2, "x.stl: cannot open");
    snprintf(args, sizeof args, "check '%s/models/SOURCES.md'", sh);
    cli_expect(args, 2, "unknown mesh format");
    cli_expect("check", 2, "usage: colibri check");
    snprintf(args, sizeof args, "ssi /nonexistent/a.step '%s/models/ujoint_cross.step'", sh);
    cli_expect(args, 2, "a.step: cannot open");
    cli_expect("ssi a.step", 2, "two STEP files are needed");
    cli_expect("model hummingbird -o /nonexistent/dir/bird.step", 2, "bird.step");
    cli_expect("model sparrow -o x.step", 2, "unknown model 'sparrow'");
}

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
    cli_expect("info /nonexistent.bpt", 2, "/nonexistent.bpt: cannot open");
    snprintf(args, sizeof args, "info '%s/models/teapot.bpt'", shared ? shared : "../shared");
    cli_expect(args, 0, "32 patches");
    snprintf(args, sizeof args, "info '%s/models/SOURCES.md'", shared ? shared : "../shared");
    cli_expect(args, 2, "SOURCES.md: unknown model format");
    /* A .bpt path that cannot be opened says so. */
    snprintf(args, sizeof args, "info /dev/null/x.bpt");
    cli_expect(args, 2, "x.bpt: cannot open");
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
    /* linkrods' edges stray up to 4.14e-4 from their surfaces, twenty times the file's 2e-5:
     * the reader raises edge tolerances to their deviation (+5%), and the model is valid. The
     * largest is within 10% of Open CASCADE's 4.13e-4. */
    snprintf(args, sizeof args, "info '%s/models/linkrods.step' --json", sh);
    cli_expect(args, 0, "\"valid\": true");
    cli_expect(args, 0, "\"edges_over_cap\": 0");
    int raised = (int)json_number("edges_tol_raised");
    double largest = json_number("max_edge_tol");
    CHECK(raised > 0 && raised <= 108 && fabs(largest - 4.13e-4) <= 0.1 * 4.13e-4,
          "linkrods: %d edge tolerances raised, largest %g", raised, largest);
    snprintf(args, sizeof args, "info '%s/models/linkrods.step'", sh);
    char want[200];
    snprintf(want, sizeof want,
             "edge tolerances: %d raised above the file's 2e-05, largest %.3g (cap 0.000561)",
             raised, largest);
    cli_expect(args, 0, want);
    cli_expect(args, 0, "validation (tolerance 2e-05): valid");
    snprintf(args, sizeof args, "info '%s/models/linkrods.step' --tol 5e-4", sh);
    cli_expect(args, 0, "validation (tolerance 0.0005): valid");
    snprintf(args, sizeof args, "info '%s/models/ujoint_cross.step' --json", sh);
    cli_expect(args, 0, "\"edges_tol_raised\": 0, \"edges_over_cap\": 0");
    char bad[64];
    snprintf(bad, sizeof bad, "/tmp/colibri_cli_bad_%ld.step", (long)getpid());
    FILE *f = fopen(bad, "w");
    fputs("ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n#1=MANIFOLD_SOLID_BREP('',#2);\n"
          "#2=CLOSED_SHELL('',(#3));\nENDSEC;\nEND-ISO-10303-21;\n",
          f);
    fclose(f);
    snprintf(args, sizeof args, "info %s", bad);
    snprintf(want, sizeof want, "%s:6: #2 CLOSED_SHELL: face: #3 is not defined", bad);
    cli_expect(args, 2, want);
    remove(bad);
    cli_expect("info /nonexistent/x.step --json", 2, "x.step: cannot open");
    cli_expect("info x.step --tol abc", 2, "--tol needs a positive number");
    cli_expect("info x.step --bogus", 2, "usage: colibri info");
    test_bad_step(sh);
    test_other_commands(sh);
    return check_report("cli");
}
