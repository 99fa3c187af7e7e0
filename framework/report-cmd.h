/* `rigflow report SOURCE TARGET -o OUT.html [--glb OUT.glb] [-p NODE.PARAM=VALUE]...`: runs
 * pipelines/retarget.json (the installed one, or the source tree's from a build tree) with its
 * report node writing OUT.html, so the command and the pipeline can never disagree. */
#ifndef RIGFLOW_REPORT_CMD_H
#define RIGFLOW_REPORT_CMD_H

#include "rigflow-host.h"

/* argv[0] is "report". Returns RF_EXIT_OK, RF_EXIT_USAGE for a bad command line,
 * RF_EXIT_VALIDATION when the pipeline or a parameter is refused, RF_EXIT_RUN when a node fails. */
int rf_cmd_report(rf_registry *reg, int argc, char **argv);

#endif
