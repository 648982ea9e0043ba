/* check_cli.h — running the colibri binary (COLIBRI_BINARY) from a test and checking its exit
 * code and output. Include after check.h, with _POSIX_C_SOURCE defined (popen). */
#ifndef CB_TEST_CHECK_CLI_H
#define CB_TEST_CHECK_CLI_H

#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

/* stdout and stderr of the last cli_run, together. */
static char cli_out[1 << 16];

/* Runs `colibri ARGS` through the shell; returns its exit code (-1 if it did not exit). */
static inline int cli_run(const char *args)
{
    const char *bin = getenv("COLIBRI_BINARY");
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "'%s' %s 2>&1", bin ? bin : "colibri", args);
    FILE *p = popen(cmd, "r");
    if (!p)
        return -1;
    size_t len = fread(cli_out, 1, sizeof cli_out - 1, p);
    cli_out[len] = '\0';
    int st = pclose(p);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

/* Checks that `colibri ARGS` exits with `code` and prints `text`. */
static inline void cli_expect(const char *args, int code, const char *text)
{
    int got = cli_run(args);
    CHECK(got == code, "colibri %s: exit %d, expected %d; output:\n%s", args, got, code,
          cli_out);
    CHECK(strstr(cli_out, text) != NULL, "colibri %s: output lacks '%s':\n%s", args, text,
          cli_out);
}

#endif
