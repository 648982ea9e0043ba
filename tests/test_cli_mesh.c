/* `colibri mesh`: exit codes, text and JSON output, the file written (read back and checked
 * by `colibri check`), and the --quiet and --threads flags (the mesh the same for any count). */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "check_cli.h"

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

static const char *shared_dir(void)
{
    const char *d = getenv("COLIBRI_SHARED");
    return d ? d : "../shared";
}

int main(void)
{
    char args[2048], out[512], model[1024];
    const char *tmp = getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp";
    snprintf(model, sizeof model, "%s/models/ujoint_fork.step", shared_dir());

    cli_expect("mesh --help", 0, "usage: colibri mesh MODEL -o OUT");
    cli_expect("mesh", 2, "usage: colibri mesh");
    snprintf(args, sizeof args, "mesh '%s'", model);
    cli_expect(args, 2, "usage: colibri mesh"); /* no -o */
    snprintf(args, sizeof args, "mesh '%s' -o x.stl --tol -1", model);
    cli_expect(args, 2, "--tol needs a positive number");
    snprintf(args, sizeof args, "mesh '%s' -o x.stl --bogus", model);
    cli_expect(args, 2, "usage: colibri mesh");
    snprintf(args, sizeof args, "mesh '%s' -o x.xyz", model);
    cli_expect(args, 2, "unknown mesh format");
    cli_expect("mesh /nonexistent/model.step -o x.stl", 2, "cannot open");

    /* A malformed STEP file is an unusable input: 2. */
    snprintf(out, sizeof out, "%s/colibri_mesh_%d_bad.step", tmp, (int)getpid());
    FILE *f = fopen(out, "w");
    CHECK(f != NULL, "cannot write %s", out);
    if (f) {
        fputs("ISO-10303-21;\nDATA;\n#1 = B_SPLINE_SURFACE_WITH_KNOTS(;\nENDSEC;\n", f);
        fclose(f);
        snprintf(args, sizeof args, "mesh '%s' -o x.stl", out);
        int code = cli_run(args);
        CHECK(code == 2, "malformed STEP: exit %d\n%s", code, cli_out);
        remove(out);
    }

    /* A good run: text output, then the file read back by colibri check. */
    snprintf(out, sizeof out, "%s/colibri_mesh_%d.off", tmp, (int)getpid());
    snprintf(args, sizeof args, "mesh '%s' -o '%s' --tol 0.2", model, out);
    cli_expect(args, 0, "result: pass");
    CHECK(strstr(cli_out, "self-intersections: none") != NULL, "%s", cli_out);
    CHECK(strstr(cli_out, "mesh volume: 81") != NULL, "volume not near 81046:\n%s", cli_out);
    snprintf(args, sizeof args, "check '%s'", out);
    cli_expect(args, 0, "result: pass");

    /* JSON: one object with the counts and the verdict; quiet stderr when not a terminal. */
    snprintf(args, sizeof args, "mesh '%s' -o '%s' --tol 0.2 --json", model, out);
    cli_expect(args, 0, "\"passed\": true");
    CHECK(cli_out[0] == '{' && strstr(cli_out, "}\n") != NULL &&
              strchr(cli_out, '\n') == strrchr(cli_out, '\n'),
          "not one JSON line:\n%s", cli_out);
    CHECK(strstr(cli_out, "\"triangles\": ") != NULL && strstr(cli_out, "\"volume\": 81") != NULL,
          "%s", cli_out);
    CHECK(strstr(cli_out, "tessellate") == NULL, "progress shown off a terminal:\n%s", cli_out);

    /* --quiet: no summary, no progress; --json still prints its object. --threads N: the
     * mesh written is the same, byte for byte, on 1 and 2 threads. */
    char out2[512];
    snprintf(out2, sizeof out2, "%s/colibri_mesh_%d_2.off", tmp, (int)getpid());
    snprintf(args, sizeof args, "mesh '%s' -o '%s' --tol 0.2 --quiet --threads 1", model, out);
    int code = cli_run(args);
    CHECK(code == 0 && cli_out[0] == '\0', "%s: exit %d, output:\n%s", args, code, cli_out);
    snprintf(args, sizeof args, "mesh --threads 2 '%s' --quiet -o '%s' --tol 0.2", model, out2);
    code = cli_run(args);
    CHECK(code == 0 && cli_out[0] == '\0', "%s: exit %d, output:\n%s", args, code, cli_out);
    char *m1 = slurp(out), *m2 = slurp(out2);
    CHECK(m1 && m2 && !strcmp(m1, m2), "meshes on 1 and 2 threads differ (%s, %s)", out, out2);
    free(m1);
    free(m2);
    snprintf(args, sizeof args, "mesh '%s' -o '%s' --tol 0.2 --quiet --json --threads 0", model,
             out);
    cli_expect(args, 0, "\"passed\": true");
    CHECK(cli_out[0] == '{' && strchr(cli_out, '\n') == cli_out + strlen(cli_out) - 1,
          "--quiet --json: not one JSON line:\n%s", cli_out);
    /* Errors still speak under --quiet. */
    cli_expect("mesh /nonexistent/model.step -o x.stl --quiet", 2, "cannot open");
    snprintf(args, sizeof args, "mesh '%s' -o /nonexistent/dir/x.off --tol 0.2 --quiet", model);
    cli_expect(args, 1, "x.off");
    static const char *const bad[] = {"--threads -1", "--threads abc", "--threads ''",
                                      "--threads 2.5", "--threads 5000"};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        snprintf(args, sizeof args, "mesh '%s' -o x.stl --quiet %s", model, bad[k]);
        cli_expect(args, 2, "--threads needs a count in [0, 4096]");
    }
    snprintf(args, sizeof args, "mesh '%s' -o x.stl --threads", model);
    cli_expect(args, 2, "usage: colibri mesh");
    remove(out);
    remove(out2);
    return check_report("test_cli_mesh");
}
