/* The ik.ccd node type: a CCD solver on a rigflow.ik-solver port. */
#include <string.h>

#include "ccd.h"

static const rf_param_desc params[] = {RF_IKC_COMMON_PARAMS};

static bool process(void *self, const rf_host *host, rf_node *node)
{
    return rf_ikc_node_process(&rf_ik_ccd_api, self, host, node);
}

static const void *get_extension(const char *id)
{
    return strcmp(id, RF_IK_EXTENSION) == 0 ? &rf_ik_ccd_api : NULL;
}

static const rf_node_desc ccd_node = {
    sizeof(rf_node_desc),
    "ik.ccd",
    RF_KIND_IK,
    "Cyclic Coordinate Descent, backward sweep from the effector to the chain root (Kenwright "
    "2012); several goals by weighted averaging at shared joints; honours hinge, cone, twist "
    "limits and locked joints by projecting each turn.",
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

static const rf_node_desc *const nodes[] = {&ccd_node};

RF_PLUGIN_EXPORT const rf_plugin_entry rigflow_plugin_entry = {
    RF_ABI_VERSION_INIT,
    sizeof(rf_plugin_entry),
    "org.rigflow.ik-ccd",
    "CCD IK solver",
    "0.1.0",
    "Cyclic Coordinate Descent inverse kinematics",
    NULL,
    NULL,
    1,
    nodes,
};
