/* The rigflow command's subcommands. Each takes the loaded registry and its own argv (argv[0] is
 * the subcommand's name) and returns an exit code from enum rf_exit. */
#ifndef RIGFLOW_COMMANDS_H
#define RIGFLOW_COMMANDS_H

#include "rigflow-host.h"

typedef int (*rf_command_fn)(rf_registry *reg, int argc, char **argv);

/* Prints diagnostics to stderr as "rigflow: <severity>: <diag>" lines. */
void rf_print_diags(const GPtrArray *diags, const char *severity);

/* Parses a subcommand's options; on failure prints the error and a usage hint to stderr. Returns
 * false then (the caller exits with RF_EXIT_USAGE). */
/* True if FILE's name is UTF-8; if not, says so on stderr for command NAME (the pipelines a
 * command builds are JSON, which holds only UTF-8 text, so such a name cannot be passed on). */
bool rf_check_utf8_name(const char *name, const char *file);
bool rf_parse_options(const char *name, const char *args, const char *summary,
                      const GOptionEntry *entries, int *argc, char ***argv);

/* The build folder when this command is the one built there (its folder, or the folder above
 * libtool's .libs, holds config.status), else NULL. (transfer full) */
char *rf_build_tree_dir(void);
/* The path of the pipeline file `name` that ships with rigflow (pipelines/NAME): the source
 * tree's when this command is a build tree's, else the installed one. (transfer full) */
char *rf_pipeline_file(const char *name);

/* Runs a validated pipeline as `rigflow run` does: progress on a terminal, Ctrl-C stops it at the
 * next check and removes every output (a second Ctrl-C stops at once), the run's errors printed.
 * Returns RF_EXIT_OK, RF_EXIT_RUN or RF_EXIT_CANCELLED. */
int rf_run_interruptible(rf_pipeline *p, const rf_registry *reg, bool profile, bool quiet);
/* As rf_run_interruptible, the run's errors added to diags instead of printed (for commands that
 * report them in their own output, as rig-bench's rows do). */
int rf_run_interruptible_diags(rf_pipeline *p, const rf_registry *reg, bool profile, bool quiet,
                               GPtrArray *diags);
/* As rf_run_interruptible_diags, quiet, the nodes' result lines printed on `out` (NULL: stdout;
 * rf_run_options.out). */
int rf_run_interruptible_out(rf_pipeline *p, const rf_registry *reg, FILE *out, GPtrArray *diags);

int rf_cmd_plugins(rf_registry *reg, int argc, char **argv);
int rf_cmd_describe(rf_registry *reg, int argc, char **argv);
int rf_cmd_plugin_check(rf_registry *reg, int argc, char **argv);

#endif
