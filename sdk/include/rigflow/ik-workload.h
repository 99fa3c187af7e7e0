/* IK workloads and their measurement, shared by `rigflow ik-bench` and the ik.compare report node
 * (libikworkload.la, linked statically into both; not an ABI: names use the rf_ikw_ prefix).
 *
 * The workloads follow ../shared/peers/README.md, so that the peers' numbers compare: links of
 * length 1 in a straight rest pose, targets uniform in direction at 0.2-0.9 of the reach (the
 * peers' LCG, seed 99, reset per workload), the pose reset before each solve, success = every
 * effector within the tolerance (1e-3).
 *   chainN-itK       N in 2, 5, 10, 30 links, iteration cap K in 10, 50
 *   tree2-itK        the DLS peer's tree: 3-link spine, rigid chest, two 3-link arms, two goals
 *   arm-itK, leg-itK, spinearm-itK
 *                    limbs of a real skeleton (the CMU 01_01 BVH): shoulder-elbow-wrist,
 *                    hip-knee-ankle, and lower back to the left hand (6 bones)
 *   ...-lim          the same with joint limits (hinge knees and elbows, cones, twist)
 */
#ifndef RIGFLOW_IK_WORKLOAD_H
#define RIGFLOW_IK_WORKLOAD_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include <rigflow/ik.h>

typedef struct rf_ikw {
    char name[48];
    uint32_t joint_count;
    int32_t *parents;
    rf_xform *pose;           /* the start pose of every solve */
    rf_ik_constraint *limits; /* [joint_count] or NULL */
    uint32_t goal_count;      /* goals per sample */
    rf_ik_goal *goals;        /* [goal_count] templates: effector, chain_root */
    uint32_t sample_count;
    rf_vec3 *targets; /* [sample_count][goal_count] */
    double tolerance;
    uint32_t max_iterations;
} rf_ikw;

/* Every workload name, in a fixed order (NULL-terminated, static). */
const char *const *rf_ikw_names(void);
/* True when `name` selects workload `workload`: equal (a full name selects only itself), or a
 * prefix ending at a '-' boundary
 * ("chain10" selects chain10-it10, chain10-it50, and their -lim forms), or a family name
 * ("chain" selects every chain). */
bool rf_ikw_matches(const char *name, const char *workload);
/* True for the workloads that need the BVH skeleton. */
bool rf_ikw_needs_bvh(const char *name);

/* Makes workload `name`. `bvh_path` is the skeleton for the limb workloads (may be NULL for
 * the others). NULL with a message in err on failure. (transfer full: rf_ikw_free) */
rf_ikw *rf_ikw_make(const char *name, const char *bvh_path, char *err, size_t err_size);
void rf_ikw_free(rf_ikw *w);
/* Keeps only the first `count` samples (fewer for charts). */
void rf_ikw_truncate(rf_ikw *w, uint32_t count);

typedef struct rf_ikw_stats {
    double us_per_solve;    /* median over reps of the mean time of one solve */
    double converged;       /* fraction of samples with every goal within tolerance */
    double mean_error;      /* mean position error over samples and goals */
    double mean_iterations; /* mean iterations used */
} rf_ikw_stats;

/* Solves every sample once for accuracy, then times whole passes: `reps` times, each repeating
 * passes for at least `min_seconds` (0 skips timing). Returns 1, or 0 when the solver refuses
 * the workload's shape (message in msg: e.g. two-bone on a 10-link chain), or -1 on an error. */
int rf_ikw_run(const rf_ik_solver_api *api, void *state, const rf_ikw *w, double min_seconds,
               int reps, rf_ikw_stats *stats, char *msg, size_t msg_size);

/* The CSV header row (with newline) and one row. */
void rf_ikw_csv_header(FILE *out);
void rf_ikw_csv_row(FILE *out, const char *solver, const char *workload, const rf_ikw_stats *s);

/* An SVG line chart of mean error (log scale) against the iteration cap (log scale), one line
 * per series; NAN values are left out. ys is [series][xs_count]. Returns false on a write error. */
bool rf_ikw_write_svg(FILE *out, const char *title, uint32_t series, const char *const *names,
                      uint32_t xs_count, const double *xs, const double *ys);

/* The iteration caps the chart samples. */
#define RF_IKW_CHART_CAPS 12
extern const double rf_ikw_chart_caps[RF_IKW_CHART_CAPS];

#endif
