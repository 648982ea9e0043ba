/* commands.h — one entry point per `colibri` command. Each takes its own argv (argv[0] is the
 * command name) and returns the process exit status: 0 success; 1 the command ran and its
 * verdict is negative (model invalid, a mesh check failed, the work failed numerically or is
 * unsupported); 2 bad usage or an input that cannot be used (missing, unreadable, malformed,
 * of the wrong format). */
#ifndef CB_CLI_COMMANDS_H
#define CB_CLI_COMMANDS_H

#include "brep/status.h"
#include "brep/topo.h"

int cb_cli_info(int argc, char **argv);
int cb_cli_model(int argc, char **argv);
int cb_cli_check(int argc, char **argv);
int cb_cli_ssi(int argc, char **argv);
int cb_cli_mesh(int argc, char **argv);
int cb_cli_bool(int argc, char **argv);
int cb_cli_demo(int argc, char **argv);

/* Option values (cli/args.c): 0 with the value stored, or 2 (the exit status) after printing
 * what the option needs. --tol: a positive finite number; --threads: a count in [0, 4096]. */
int cb_cli_tol_arg(double *tol, const char *s);
int cb_cli_threads_arg(int *threads, const char *s);

/* B moved before the work (B against a moved copy of itself): turned by deg degrees about
 * axis through the origin, then shifted. */
typedef struct {
    double axis[3], deg, shift[3];
    int set;
} cb_cli_move;

void cb_cli_move_init(cb_cli_move *m);

/* If argv[*k] is --rotate-b AX AY AZ DEG or --translate-b X Y Z, reads it into m, advances *k
 * past its values and returns 1; 0 when it is neither; -1 after printing what it needs
 * (command names the command in the message; exit status 2). */
int cb_cli_move_parse(cb_cli_move *m, int argc, char **argv, int *k, const char *command);

/* Applies m to b (nothing when no option was given). */
void cb_cli_move_apply(const cb_cli_move *m, cb_topo_body *b);

/* A cb_context progress callback drawing "stage NN%" on stderr when the whole percentage
 * changes; user points to an int holding the last one drawn (start it at -1). */
void cb_cli_progress(void *user, double fraction, const char *stage);

/* Seconds of a monotonic clock, for elapsed times. */
double cb_cli_seconds(void);

/* Exit status for a file that could not be read or written with status st: 2 (the input
 * cannot be used), except 1 when memory ran out. */
int cb_cli_input_exit(cb_status st);

/* Global options (cli/limits.c), given before the command name: --timeout SECONDS stops the
 * process after that wall time (a hard stop: SIGALRM, message, exit status 1), --max-memory MB
 * caps its address space (RLIMIT_AS), so that allocations fail and commands exit with 1. */
typedef struct {
    double timeout_s;        /* 0: no timeout */
    long long max_memory_mb; /* 0: no limit */
} cb_cli_limits;

void cb_cli_limits_init(cb_cli_limits *lim);

/* If argv[k] is a global option, reads it and its value into lim and returns the number of
 * arguments used (2); returns 0 when argv[k] is not a global option, and -1 after printing
 * why when its value is missing or bad (exit status 2). */
int cb_cli_limits_parse(cb_cli_limits *lim, int argc, char **argv, int k);

/* Puts the limits in force for the rest of the process: 0, or the exit status (2) after
 * printing why they cannot be set. */
int cb_cli_limits_apply(const cb_cli_limits *lim);

#endif
