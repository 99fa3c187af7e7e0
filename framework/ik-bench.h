/* `rigflow ik-bench`: every IK solver plugin on the standard workloads, as CSV. */
#ifndef RIGFLOW_IK_BENCH_H
#define RIGFLOW_IK_BENCH_H

#include "rigflow-host.h"

/* argv[0] is "ik-bench". Options: --solver NAME... --workload NAME... --bvh FILE --min-time S
 * --reps N --list. Prints `solver,workload,us_per_solve,converged,mean_error,mean_iterations`
 * rows to stdout; notes (skipped combinations) to stderr. Returns an rf_exit code. */
int rf_cmd_ik_bench(rf_registry *reg, int argc, char **argv);

#endif
