/* limits.c — the global options that bound a whole run: --timeout (wall time) and
 * --max-memory (address space).
 *
 * The timeout is a hard stop: commands make their own cb_context, so there is no context to
 * cancel from here; instead SIGALRM (setitimer, ITIMER_REAL) runs a handler that only writes a
 * message prepared in advance (write(2)) and leaves with _exit(1), both async-signal-safe. A
 * file being written at that moment is left incomplete.
 *
 * The memory limit is RLIMIT_AS: past it malloc returns NULL and the library reports
 * CB_ERR_NOMEM, which the commands turn into exit status 1. AddressSanitizer reserves terabytes
 * of address space for its shadow memory and aborts when a mapping fails, so a sanitizer build
 * says that it ignores the option rather than crash.
 *
 * GMP, MPFR and FLINT (under the exact and interval arithmetic of ssi/) cannot report a failed
 * allocation: by default they print their own message and abort(). Their allocation functions
 * are replaced here by ones that, on failure, write "colibri: out of memory ..." and _exit(1),
 * so running out of memory there ends like it does elsewhere (status 1, a message) rather
 * than with SIGABRT. This is the command's choice; the library leaves these hooks alone. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <unistd.h>

#include <flint/flint.h>
#include <gmp.h>

#include "cli/commands.h"

#if defined(__SANITIZE_ADDRESS__)
#define CB_CLI_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define CB_CLI_ASAN 1
#endif
#endif
#ifndef CB_CLI_ASAN
#define CB_CLI_ASAN 0
#endif

/* Longest accepted timeout: a year, far inside what setitimer takes. */
static const double MAX_TIMEOUT_S = 365.0 * 24 * 3600;

/* The line the SIGALRM handler writes, formatted before the timer is armed. */
static char timeout_msg[96];
static size_t timeout_len;

static void on_timeout(int sig)
{
    (void)sig;
    if (write(STDERR_FILENO, timeout_msg, timeout_len) < 0) {
        /* Nothing more can be done from a signal handler. */
    }
    _exit(1);
}

/* Written when GMP or FLINT finds no memory: formatted once the limit is known. */
static char oom_msg[160] = "colibri: out of memory in the exact arithmetic (GMP/FLINT)\n";
static size_t oom_len;

static _Noreturn void out_of_memory(void)
{
    if (!oom_len)
        oom_len = strlen(oom_msg);
    if (write(STDERR_FILENO, oom_msg, oom_len) < 0) {
        /* Nothing more can be done. */
    }
    _exit(1);
}

static void *checked(void *p, size_t size)
{
    if (!p && size)
        out_of_memory();
    return p;
}

static void *gmp_alloc(size_t size)
{
    return checked(malloc(size), size);
}

static void *gmp_realloc(void *p, size_t old, size_t size)
{
    (void)old;
    return checked(realloc(p, size), size);
}

static void gmp_free(void *p, size_t size)
{
    (void)size;
    free(p);
}

static void *flint_alloc(size_t size)
{
    return checked(malloc(size), size);
}

static void *flint_calloc_checked(size_t n, size_t size)
{
    return checked(calloc(n, size), n * size);
}

static void *flint_realloc_checked(void *p, size_t size)
{
    return checked(realloc(p, size), size);
}

/* Installs the allocation functions above (before any GMP or FLINT number exists). */
static void install_allocators(long long max_memory_mb)
{
    if (max_memory_mb > 0)
        snprintf(oom_msg, sizeof oom_msg,
                 "colibri: out of memory in the exact arithmetic (GMP/FLINT) under "
                 "--max-memory %lld MB\n",
                 max_memory_mb);
    oom_len = strlen(oom_msg);
    mp_set_memory_functions(gmp_alloc, gmp_realloc, gmp_free);
    __flint_set_memory_functions(flint_alloc, flint_calloc_checked, flint_realloc_checked, free);
}

void cb_cli_limits_init(cb_cli_limits *lim)
{
    lim->timeout_s = 0;
    lim->max_memory_mb = 0;
}

int cb_cli_limits_parse(cb_cli_limits *lim, int argc, char **argv, int k)
{
    const char *opt = argv[k];
    int timeout = !strcmp(opt, "--timeout"), memory = !strcmp(opt, "--max-memory");
    if (!timeout && !memory)
        return 0;
    if (k + 1 >= argc) {
        fprintf(stderr, "colibri: %s needs a value (see colibri --help)\n", opt);
        return -1;
    }
    const char *val = argv[k + 1];
    char *end;
    errno = 0;
    if (timeout) {
        double s = strtod(val, &end);
        if (end == val || *end || errno || !(s > 0) || !(s <= MAX_TIMEOUT_S)) {
            fprintf(stderr,
                    "colibri: --timeout needs a number of seconds > 0 (at most %.0f), not '%s'\n",
                    MAX_TIMEOUT_S, val);
            return -1;
        }
        lim->timeout_s = s;
    } else {
        long long mb = strtoll(val, &end, 10);
        /* The byte count must fit rlim_t and size_t alike. */
        long long most = (long long)(((size_t)-1 >> 1) >> 20);
        if (end == val || *end || errno || mb < 1 || mb > most) {
            fprintf(stderr,
                    "colibri: --max-memory needs a whole number of megabytes >= 1, not '%s'\n",
                    val);
            return -1;
        }
        lim->max_memory_mb = mb;
    }
    return 2;
}

static int apply_timeout(double s)
{
    snprintf(timeout_msg, sizeof timeout_msg, "colibri: timed out after %g s\n", s);
    timeout_len = strlen(timeout_msg);
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_timeout;
    sigemptyset(&sa.sa_mask);
    struct itimerval it;
    memset(&it, 0, sizeof it);
    it.it_value.tv_sec = (time_t)s;
    it.it_value.tv_usec = (suseconds_t)((s - (double)it.it_value.tv_sec) * 1e6);
    if (it.it_value.tv_sec == 0 && it.it_value.tv_usec == 0)
        it.it_value.tv_usec = 1;
    if (sigaction(SIGALRM, &sa, NULL) || setitimer(ITIMER_REAL, &it, NULL)) {
        fprintf(stderr, "colibri: --timeout: cannot set the timer: %s\n", strerror(errno));
        return 2;
    }
    return 0;
}

static int apply_memory(long long mb)
{
    if (CB_CLI_ASAN) {
        fprintf(stderr, "colibri: --max-memory is ignored in an AddressSanitizer build (its "
                        "shadow memory needs an unlimited address space)\n");
        return 0;
    }
    struct rlimit rl;
    if (getrlimit(RLIMIT_AS, &rl)) {
        fprintf(stderr, "colibri: --max-memory: cannot read the limit: %s\n", strerror(errno));
        return 2;
    }
    rlim_t want = (rlim_t)mb << 20;
    if (rl.rlim_max != RLIM_INFINITY && want > rl.rlim_max) {
        fprintf(stderr, "colibri: --max-memory %lld: above the hard limit of %llu MB\n", mb,
                (unsigned long long)(rl.rlim_max >> 20));
        return 2;
    }
    rl.rlim_cur = want;
    if (setrlimit(RLIMIT_AS, &rl)) {
        fprintf(stderr, "colibri: --max-memory: cannot set the limit: %s\n", strerror(errno));
        return 2;
    }
    return 0;
}

int cb_cli_limits_apply(const cb_cli_limits *lim)
{
    int code = 0;
    install_allocators(lim->max_memory_mb);
    if (lim->max_memory_mb > 0)
        code = apply_memory(lim->max_memory_mb);
    if (!code && lim->timeout_s > 0)
        code = apply_timeout(lim->timeout_s);
    return code;
}
