/* `rigflow map SOURCE... TARGET [-o OUT.json] [--explain] [--repeat N]`: maps the
 * target's joints onto one or more source skeletons, the same graph as pipelines/map.json. */
#ifndef RIGFLOW_MAP_CMD_H
#define RIGFLOW_MAP_CMD_H

#include "rigflow-host.h"

/* argv[0] is "map". Returns RF_EXIT_OK, RF_EXIT_USAGE for a bad command line, RF_EXIT_VALIDATION
 * for a bad parameter, or RF_EXIT_RUN when a file cannot be imported or mapped. */
int rf_cmd_map(rf_registry *reg, int argc, char **argv);

#endif
