/* The import step of an Assimp-backed import node (rigflow/aimport-node.h), in a file of its own
 * so that the descriptors and the output glue (aimport-node.c) link without Assimp. */
#include "rigflow/aimport-node.h"

typedef struct rf_ai_node_log {
    const rf_host *host;
    rf_node *node;
} rf_ai_node_log;

static void rf_ai_node_log_fn(void *user, int level, const char *message)
{
    rf_ai_node_log *l = user;
    l->host->log(l->node, level <= 1 ? RF_LOG_WARNING : RF_LOG_INFO, "%s", message);
}

bool rf_ai_node_import(const rf_host *host, rf_node *node)
{
    rf_ai_options o = {0};
    const char *path = host->param_string(node, "path");
    o.clip = host->param_string(node, "clip");
    o.fps = host->param_float(node, "fps");
    o.require_skeleton = host->param_bool(node, "require_skeleton");
    o.ignore_rig = host->param_bool(node, "ignore_rig");
    if (!rf_ai_rest_parse(host->param_string(node, "rest_pose"), &o.rest)) {
        host->error(node, "rest_pose: expected bind or node");
        return false;
    }
    rf_ai_node_log l = {host, node};
    rf_ai_result r;
    char err[1024];
    if (!rf_ai_import(path, &o, &r, rf_ai_node_log_fn, &l, err, sizeof err)) {
        host->error(node, "%s", err);
        return false;
    }
    return rf_ai_node_outputs_set(host, node, &r);
}
