/* The ik.fabrik node type: a FABRIK solver on a rigflow.ik-solver port. */
#include <string.h>

#include "fabrik.h"

static const rf_param_desc params[] = {RF_IKC_COMMON_PARAMS};

static bool process(void *self, const rf_host *host, rf_node *node)
{
    return rf_ikc_node_process(&rf_ik_fabrik_api, self, host, node);
}

static const void *get_extension(const char *id)
{
    return strcmp(id, RF_IK_EXTENSION) == 0 ? &rf_ik_fabrik_api : NULL;
}

static const rf_node_desc fabrik_node = {
    sizeof(rf_node_desc),
    "ik.fabrik",
    RF_KIND_IK,
    "FABRIK inverse kinematics (Aristidou & Lasenby 2011): several end effectors through "
    "sub-base centroids and goal weights; honours hinge, cone, twist limits and locked joints "
    "(Aristidou et al. 2016).",
    0,
    NULL,
    1,
    &rf_ikc_solver_output,
    sizeof params / sizeof params[0],
    params,
    rf_ikc_node_create,
    process,
    rf_ikc_node_destroy,
    get_extension,
};

static const rf_node_desc *const nodes[] = {&fabrik_node};

RF_PLUGIN_EXPORT const rf_plugin_entry rigflow_plugin_entry = {
    RF_ABI_VERSION_INIT,
    sizeof(rf_plugin_entry),
    "org.rigflow.ik-fabrik",
    "FABRIK IK solver",
    "0.1.0",
    "FABRIK inverse kinematics with several end effectors and joint limits",
    NULL,
    NULL,
    1,
    nodes,
};
