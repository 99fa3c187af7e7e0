/* `rigflow rig-bench`: every rigger plugin on rigged models with their rig ignored, measured
 * against the artist's rig, as CSV (doc/autorig.md). */
#ifndef RF_RIG_BENCH_H
#define RF_RIG_BENCH_H

#include <jansson.h>

#include "rigflow-host.h"

/* How each model is moved before it is rigged (--turn, --axis, --scale, --offset): through a
 * `transform` node after each import, so the artist's rig and the bare mesh, and the look's
 * mesh, move alike. */
typedef struct rf_rig_move {
    bool on;
    bool fixed_axes; /* the declared up and forward stay as the file declares them */
    double turn, scale;
    char axis[96], offset[96]; /* the transform node's parameter text, checked */
} rf_rig_move;

/* Whether node type `d` declares an input port `name` (a rigger reading the mesh's axes). */
bool rf_rig_has_input(const rf_node_desc *d, const char *name);

/* Appends to `graph` a transform node `to` moving node `from`'s skeleton and mesh as `m` says,
 * and points every input that read `from`'s skeleton or mesh at the transform's. False when out
 * of memory (the graph is then incomplete and its validation names what is missing). */
bool rf_rig_move_insert(json_t *graph, const rf_rig_move *m, const char *from, const char *to);

/* argv[0] is "rig-bench". Options: --rigger NAME... --list --joint-map --joints --look
 * --look-frames; then the model files. Prints one CSV row per model and rigger to stdout (the
 * columns in --help: the rig against the artist's, then the look_ columns); refusals are rows
 * too (status names the reason), notes go to stderr. Returns an rf_exit code. */
int rf_cmd_rig_bench(rf_registry *reg, int argc, char **argv);

#endif
