/* `rigflow rig-bench`: every rigger plugin on rigged models with their rig ignored, measured
 * against the artist's rig, as CSV (doc/autorig.md). */
#ifndef RF_RIG_BENCH_H
#define RF_RIG_BENCH_H

#include "rigflow-host.h"

/* argv[0] is "rig-bench". Options: --rigger NAME... --list --joint-map --joints --look
 * --look-frames; then the model files. Prints one CSV row per model and rigger to stdout (the
 * columns in --help: the rig against the artist's, then the look_ columns); refusals are rows
 * too (status names the reason), notes go to stderr. Returns an rf_exit code. */
int rf_cmd_rig_bench(rf_registry *reg, int argc, char **argv);

#endif
