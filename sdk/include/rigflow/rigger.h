/* rigflow SDK: the rigger capability. A node type of kind RF_KIND_RIGGER may offer this table
 * through get_extension(RF_RIGGER_EXTENSION), so `rigflow rig-bench` (and any host) can call the
 * rigger's core directly on meshes it loads itself, timing the plugin's own code. */
#ifndef RIGFLOW_RIGGER_H
#define RIGFLOW_RIGGER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "model.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RF_RIGGER_EXTENSION "rigflow.rigger/1"

typedef struct rf_rigger_api {
    uint32_t size;    /* sizeof(rf_rigger_api) */
    const char *name; /* short name for tables, e.g. "general" */
    const char *doc;  /* one line */
    /* Rigs `mesh` (borrowed; any skin it has must be ignored) with the node type's default
     * parameters. On success returns true with a new skeleton (its rest pose is the pose the mesh
     * is bound in) and a new copy of the mesh skinned to it, every vertex weighted; on failure
     * false with a message in err (err_size bytes) and nothing allocated. (transfer full: free
     * with rf_skeleton_free and rf_mesh_free) */
    bool (*rig)(const rf_mesh *mesh, rf_skeleton **skeleton, rf_mesh **skinned, char *err,
                size_t err_size);
    /* Appended (read it only when `size` covers it, RF_HAS_FIELD; may be NULL): weights `mesh`
     * to a given `skeleton` (both borrowed; the mesh's own skin ignored) with the rigger's
     * skinning alone, as skinning methods are compared given the same skeleton. inverse_bind
     * ([joint_count], model space to joint space in the pose the mesh is in) places the joints;
     * NULL means the skeleton's rest pose. Joints flagged RF_JOINT_UNWEIGHTED get no weights.
     * Returns a new skinned copy (inverse binds set) or false with a message in err. */
    bool (*skin)(const rf_mesh *mesh, const rf_skeleton *skeleton, const rf_mat4 *inverse_bind,
                 rf_mesh **skinned, char *err, size_t err_size);
    /* Appended (RF_HAS_FIELD; may be NULL): as `rig`, with the body's up and forward read from
     * `axes` as the node's `axes` input reads them (the skeleton an importer makes of a file
     * even with its rig ignored carries the up and forward the file declares; NULL: none), so
     * a caller timing or comparing riggers outside a pipeline runs what the pipeline runs. */
    bool (*rig_axes)(const rf_mesh *mesh, const rf_skeleton *axes, rf_skeleton **skeleton,
                     rf_mesh **skinned, char *err, size_t err_size);
} rf_rigger_api;

#ifdef __cplusplus
}
#endif

#endif
