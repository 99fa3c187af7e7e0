/* The ik.twobone node type: an analytic two-bone solver on a rigflow.ik-solver port. */
#include <string.h>

#include "twobone.h"

static const rf_param_desc params[] = {RF_IKC_COMMON_PARAMS};

static bool process(void *self, const rf_host *host, rf_node *node)
{
    return rf_ikc_node_process(&rf_ik_twobone_api, self, host, node);
}

static const void *get_extension(const char *id)
{
    return strcmp(id, RF_IK_EXTENSION) == 0 ? &rf_ik_twobone_api : NULL;
}

static const rf_node_desc twobone_node = {
    sizeof(rf_node_desc),
    "ik.twobone",
    RF_KIND_IK,
    "Analytic two-bone inverse kinematics (law of cosines) for limbs such as arm and leg: one "
    "pass, exact; a pole vector chooses the bend plane; the middle joint's hinge axis is the bend "
    "axis; limits are kept by projection. Chains of exactly two bones per goal.",
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

static const rf_node_desc *const nodes[] = {&twobone_node};

RF_PLUGIN_EXPORT const rf_plugin_entry rigflow_plugin_entry = {
    RF_ABI_VERSION_INIT,
    sizeof(rf_plugin_entry),
    "org.rigflow.ik-twobone",
    "Two-bone IK solver",
    "0.1.0",
    "Analytic two-bone inverse kinematics with a pole vector",
    NULL,
    NULL,
    1,
    nodes,
};
