/* commands.h — one entry point per `colibri` command. Each takes its own argv (argv[0] is the
 * command name) and returns the process exit status: 0 success, 1 failure, 2 bad usage. */
#ifndef CB_CLI_COMMANDS_H
#define CB_CLI_COMMANDS_H

int cb_cli_info(int argc, char **argv);
int cb_cli_model(int argc, char **argv);
int cb_cli_check(int argc, char **argv);
int cb_cli_ssi(int argc, char **argv);

#endif
