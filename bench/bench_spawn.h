/* bench_spawn.h — a benchmark's child process and its peak memory: ru_maxrss is a high-water
 * mark of a whole process, so the benchmarks that report memory per case (bench_scenarios,
 * bench_ssi_models) run each case in a process of its own and read its figure by wait4 when it
 * ends. Children are started by posix_spawn, not fork: a forked child's page tables copy the
 * parent's resident memory, and the kernel carries that over exec into the child's ru_maxrss.
 * Header-only: every bench_*.c is a program of its own; define _DEFAULT_SOURCE (wait4) before
 * any include. */
#ifndef CB_BENCH_SPAWN_H
#define CB_BENCH_SPAWN_H

#include <spawn.h>
#include <stddef.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

extern char **environ;

/* Starts argv[0] with its stdout into a pipe: 0 with *pid and *rfd (the pipe's read end, to
 * close), -1 when it could not be started (nothing left open). */
static inline int spawn_piped(pid_t *pid, int *rfd, char *const argv[])
{
    int fd[2];
    if (pipe(fd))
        return -1;
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_adddup2(&fa, fd[1], 1);
    posix_spawn_file_actions_addclose(&fa, fd[0]);
    posix_spawn_file_actions_addclose(&fa, fd[1]);
    int rc = posix_spawn(pid, argv[0], &fa, NULL, argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    close(fd[1]);
    if (rc) {
        close(fd[0]);
        return -1;
    }
    *rfd = fd[0];
    return 0;
}

/* Starts argv[0] with stdout into a pipe, reads at most cap bytes of it into out (*got of
 * them), waits for it and returns its exit status (-1: could not start or killed); *peak_kib
 * its ru_maxrss. */
static inline int spawn_read(void *out, size_t cap, size_t *got, char *const argv[], long *peak_kib)
{
    int fd[1];
    *peak_kib = -1;
    *got = 0;
    pid_t pid;
    if (spawn_piped(&pid, fd, argv))
        return -1;
    ssize_t n;
    while (*got < cap && (n = read(fd[0], (char *)out + *got, cap - *got)) > 0)
        *got += (size_t)n;
    /* Drain what did not fit so that the child never blocks on a full pipe. */
    char sink[4096];
    while (read(fd[0], sink, sizeof sink) > 0)
        ;
    close(fd[0]);
    int status;
    struct rusage ru;
    if (wait4(pid, &status, 0, &ru) != pid)
        return -1;
    *peak_kib = ru.ru_maxrss;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

#endif
