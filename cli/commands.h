/* commands.h — one entry point per `colibri` command. Each takes its own argv (argv[0] is the
 * command name) and returns the process exit status: 0 success; 1 the command ran and its
 * verdict is negative (model invalid, a mesh check failed, the work failed numerically or is
 * unsupported); 2 bad usage or an input that cannot be used (missing, unreadable, malformed,
 * of the wrong format). */
#ifndef CB_CLI_COMMANDS_H
#define CB_CLI_COMMANDS_H

#include "brep/status.h"

int cb_cli_info(int argc, char **argv);
int cb_cli_model(int argc, char **argv);
int cb_cli_check(int argc, char **argv);
int cb_cli_ssi(int argc, char **argv);
int cb_cli_mesh(int argc, char **argv);

/* Exit status for a file that could not be read or written with status st: 2 (the input
 * cannot be used), except 1 when memory ran out. */
int cb_cli_input_exit(cb_status st);

#endif
