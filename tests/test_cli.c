/* The colibri command: exit codes and messages of every command (binary from COLIBRI_BINARY). */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "check.h"

static char out[1 << 16];

/* Runs `colibri ARGS`, capturing stdout and stderr together into `out`; returns the exit code. */
static int run(const char *args)
{
    const char *bin = getenv("COLIBRI_BINARY");
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "'%s' %s 2>&1", bin ? bin : "colibri", args);
    FILE *p = popen(cmd, "r");
    if (!p)
        return -1;
    size_t len = fread(out, 1, sizeof out - 1, p);
    out[len] = '\0';
    int st = pclose(p);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static void expect(const char *args, int code, const char *text)
{
    int got = run(args);
    CHECK(got == code, "colibri %s: exit %d, expected %d; output:\n%s", args, got, code, out);
    CHECK(strstr(out, text) != NULL, "colibri %s: output lacks '%s':\n%s", args, text, out);
}

int main(void)
{
    const char *shared = getenv("COLIBRI_SHARED");
    char args[1024];
    expect("", 2, "usage: colibri COMMAND");
    expect("--help", 0, "commands:");
    expect("--version", 0, "colibri ");
    expect("frobnicate", 2, "unknown command 'frobnicate'");
    expect("info --help", 0, "usage: colibri info");
    expect("info", 2, "usage: colibri info");
    expect("info a b", 2, "usage: colibri info");
    expect("info /nonexistent.bpt", 1, "/nonexistent.bpt: cannot open");
    snprintf(args, sizeof args, "info '%s/models/teapot.bpt'", shared ? shared : "../shared");
    expect(args, 0, "32 patches");
    snprintf(args, sizeof args, "info '%s/models/SOURCES.md'", shared ? shared : "../shared");
    expect(args, 1, "SOURCES.md: unknown model format");
    /* A .bpt path that cannot be opened says so. */
    snprintf(args, sizeof args, "info /dev/null/x.bpt");
    expect(args, 1, "x.bpt: cannot open");
    return check_report("cli");
}
