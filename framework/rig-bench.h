/* `rigflow rig-bench`: every rigger plugin on rigged models with their rig ignored, measured
 * against the artist's rig, as CSV (doc/autorig.md). */
#ifndef RF_RIG_BENCH_H
#define RF_RIG_BENCH_H

#include "rigflow-host.h"

/* argv[0] is "rig-bench". Options: --rigger NAME... --list; then the model files. Prints
 * `rigger,model,body,artist_joints,joints,cd_j2j,cd_j2b,cd_b2b,precision,recall,l1,unweighted,
 * seconds,status` rows to stdout; refusals are rows too (status names the reason), notes go to
 * stderr. Returns an rf_exit code. */
int rf_cmd_rig_bench(rf_registry *reg, int argc, char **argv);

#endif
