/* `rigflow inspect FILE`: what an importer makes of a file (skeleton tree with rest positions,
 * clips, meshes), so a user sees what was imported before building a pipeline on it. */
#ifndef RIGFLOW_INSPECT_H
#define RIGFLOW_INSPECT_H

#include "rigflow-host.h"

/* argv[0] is "inspect". Returns RF_EXIT_OK, RF_EXIT_USAGE for a bad command line, or
 * RF_EXIT_RUN when the file cannot be imported (the reason is printed to stderr). */
int rf_cmd_inspect(rf_registry *reg, int argc, char **argv);

#endif
