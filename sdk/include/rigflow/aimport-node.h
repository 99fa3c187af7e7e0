/* The parameters, outputs and process step of an Assimp-backed import node, shared by the
 * assimp.import node and the generic import node (plugins/convert), which must agree. */
#ifndef RF_AIMPORT_NODE_H
#define RF_AIMPORT_NODE_H

#include <rigflow/rigflow.h>

#include <rigflow/aimport.h>

#define RF_AI_NODE_PARAM_COUNT 6
#define RF_AI_NODE_OUTPUT_COUNT 4

/* path, clip, rest_pose, fps, require_skeleton, ignore_rig. (static) */
extern const rf_param_desc rf_ai_node_params[RF_AI_NODE_PARAM_COUNT];
/* skeleton, animation, mesh, clips. (static) */
extern const rf_port_desc rf_ai_node_outputs[RF_AI_NODE_OUTPUT_COUNT];

/* Reads the parameters, imports through Assimp and sets every output; false after host->error. */
bool rf_ai_node_import(const rf_host *host, rf_node *node);

/* Hands the result's skeleton, animation, mesh (an empty one when NULL) and clip list to the host
 * and clears *r. False after host->error. */
bool rf_ai_node_outputs_set(const rf_host *host, rf_node *node, rf_ai_result *r);

#endif
