/* What the rigger plugins' nodes share (rig-node.c, built into each plugin): progress through
 * the host, and the outputs (skeleton, skinned mesh, a one-frame rest clip) with a log line. */
#ifndef RF_RIG_NODE_H
#define RF_RIG_NODE_H

#include <rigflow/rigflow.h>

#include "rig.h"

/* The inputs and parameters every rigger node has (rf_rig_node_options reads them). */
#define RF_RIG_NODE_INPUTS                                                                         \
    RF_PORT_DESC("mesh", RF_TYPE_MESH, 0,                                                          \
                 "the mesh to rig (any skin it has is ignored): one body, loose parts allowed"),   \
        RF_PORT_DESC("axes", RF_TYPE_SKELETON, RF_PORT_OPTIONAL,                                   \
                     "the importer's skeleton (even an empty one): its up and forward, as the "    \
                     "file declares them, are kept; an up it does not declare (OBJ, STL, PLY), "   \
                     "or no axes at all, is found from the body (+y when none is: a warning)")
#define RF_RIG_NODE_PARAMS                                                                         \
    RF_PARAM_DESC_INT("resolution", RF_RIG_RESOLUTION, 16, 256,                                    \
                      "voxels along the longest bounding-box edge for the skeleton"),              \
        RF_PARAM_DESC_INT("proxy_triangles", RF_RIG_PROXY_TRIANGLES, 1000, 1000000,                \
                          "meshes above this are simplified into a proxy for the weights"),        \
        RF_PARAM_DESC_FLOAT("speck_size", RF_RIG_SPECK_SIZE, 0.001, 0.5,                           \
                            "loose parts smaller than this fraction of the mesh's diagonal are "   \
                            "specks"),                                                             \
        RF_PARAM_DESC_FLOAT("segment", RF_RIG_SEGMENT, 0.02, 1,                                    \
                            "bone length, as a fraction of the longest bounding-box edge"),        \
        RF_PARAM_DESC_BOOL("visibility", 1,                                                        \
                           "heat a vertex only from bones it can see (ray casting); false: from "  \
                           "the nearest bone")

typedef struct rf_rig_node_ctx {
    const rf_host *host;
    rf_node *node;
} rf_rig_node_ctx;

/* An rf_rig_progress_fn for a node; user is an rf_rig_node_ctx. */
void rf_rig_node_progress(void *user, double fraction);

/* The options every rigger node reads: resolution, proxy_triangles, speck_size, segment,
 * visibility, and the axes port. */
rf_rig_options rf_rig_node_options(const rf_host *host, rf_node *node);
/* The defaults with the up and forward `axes` carries (NULL: none), for the extension's rig_axes.
 */
rf_rig_options rf_rig_axes_options(const rf_skeleton *axes);

/* Logs what the rigger did and hands s and m (owned) to the node's outputs with a rest clip. */
bool rf_rig_node_output(const rf_host *host, rf_node *node, rf_skeleton *s, rf_mesh *m,
                        const rf_rig_stats *st);

/* The rigger extension's skin call, the same for every rigger: bone heat on a given skeleton. */
bool rf_rig_node_skin(const rf_mesh *mesh, const rf_skeleton *skeleton, const rf_mat4 *inverse_bind,
                      rf_mesh **skinned, char *err, size_t err_size);

#endif
