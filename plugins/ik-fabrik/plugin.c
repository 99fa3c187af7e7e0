/* The ik.fabrik node type: a FABRIK solver on a rigflow.ik-solver port. */
#include <string.h>

#include "fabrik.h"

static const rf_param_desc params[] = {RF_IKC_COMMON_PARAMS};

RF_IKC_NODE_TYPE(
    fabrik, &rf_ik_fabrik_api, "ik.fabrik",
    "FABRIK inverse kinematics (Aristidou & Lasenby 2011): several end effectors through "
    "sub-base centroids and goal weights; honours hinge, cone, twist limits and locked joints "
    "(Aristidou et al. 2016).",
    params, rf_ikc_node_create);

static const rf_node_desc *const nodes[] = {&fabrik_node};

RF_PLUGIN_DEFINE("org.rigflow.ik-fabrik", "FABRIK IK solver", "0.1.0",
                 "FABRIK inverse kinematics with several end effectors and joint limits", nodes);
