/* rig-bench --look: how a motion looks on each auto-rig (doc/autorig.md, "rig-bench"). */
#ifndef RF_RIG_BENCH_LOOK_H
#define RF_RIG_BENCH_LOOK_H

#include "rig-bench.h"
#include "rigflow-host.h"

/* The figures of one look, as retarget.measure gives them on the mesh, in % of the mesh's
 * height; NaN where not measured. */
typedef struct rf_rig_look {
    double stretch_p99;  /* edge stretch p99 over the whole mesh */
    double part_p99;     /* the same in the worst part (the vertices one joint carries most) */
    double seam_p99;     /* torn limbs: p99 drift of seams between parts of different joints */
    double floor_median; /* the lowest vertex over the rest floor, median frame, signed */
    double floor_p95;    /* its p95 either way */
    double parts_below;  /* the frames whose parts high at rest (wings, tails, a prop held
                          * high) go over 1% of the height under the floor, in % of the frames */
    /* How the motion's directions came through, from the skeleton alone: retarget.measure's
     * direction fidelity (degrees between each mapped bone and its source bone, mean and p95
     * over bones and frames), and the feet the retarget found on the rig (its contact pass pins
     * them) and the source's feet they follow. A leg without a foot is driven as an arm: the
     * mesh may then stretch less while it swings the wrong way, which only these see. */
    double fidelity_mean, fidelity_p95;
    double feet, source_feet;
    double volume_off; /* % its rest volume the worst closed solid part strays by, p95 over the
                        * frames (a box crushed or flattened); NaN with no solid part */
    char joint[128];  /* the worst part's joint, escaped by retarget.measure */
    char status[400]; /* "ok", or why the look was not measured */
} rf_rig_look;

/* What every look of a bench run shares: the motion file and how much of it, and the pipeline. */
typedef struct rf_rig_look_setup {
    char *motion;            /* NULL: no look asked for */
    int frames;              /* source frames from the first; 0: the whole motion */
    char *dir;               /* a folder of our own for the measure's reports */
    FILE *lines;             /* where the pipeline's nodes print their lines (not the CSV) */
    const rf_rig_move *move; /* how the model is moved before it is rigged (borrowed) */
    char *pipeline;          /* pipelines/scan-to-animation.json, where it was read */
    json_t *graph;           /* its JSON, read once */
    bool no_axes;            /* the rigger given no up or forward (rig-bench --no-axes) */
} rf_rig_look_setup;

/* The frames the look's measure samples, spread over the motion played (retarget.measure's
 * mesh_frames): one every 0.19 s of the CMU walk's 2752 frames, so the crouches before its
 * jumps, a third of a second each, are seen; the pipeline's 24 stepped over them. */
#define RF_RIG_LOOK_SAMPLES 120

/* Checks the motion file, reads the pipeline file and makes the folder; false after saying on
 * stderr what is wrong. `frames`: the motion's first frames to play, 0 for all of it. The look
 * plays on the model moved as `move` says (borrowed: it must outlive the setup), the mesh that was
 * rigged. */
bool rf_rig_look_begin(rf_rig_look_setup *s, const char *motion, int frames,
                       const rf_rig_move *move);
void rf_rig_look_end(rf_rig_look_setup *s);

/* Sets every figure to NaN, the joint to "" and the status to `status`. */
void rf_rig_look_none(rf_rig_look *l, const char *status);

/* Runs pipelines/scan-to-animation.json without its export on `model` (its rig ignored, moved
 * as the setup says) with its rigger node of type `rigger`: the mesh rigged, the motion mapped
 * onto the new rig by the skeletal-similarity matcher, retargeted (feet pinned, the clip on the
 * skin's floor) and measured by retarget.measure. A failure is a status in `out`.
 * Returns RF_EXIT_CANCELLED on Ctrl-C, else RF_EXIT_OK. */
int rf_rig_look_run(const rf_registry *reg, const rf_rig_look_setup *s, const rf_node_desc *rigger,
                    const char *model, rf_rig_look *out);

#endif
