/* The ik.twobone node type: an analytic two-bone solver on a rigflow.ik-solver port. */
#include <string.h>

#include "twobone.h"

static const rf_param_desc params[] = {RF_IKC_COMMON_PARAMS};

RF_IKC_NODE_TYPE(
    twobone, &rf_ik_twobone_api, "ik.twobone",
    "Analytic two-bone inverse kinematics (law of cosines) for limbs such as arm and leg: one "
    "pass, exact; a pole vector chooses the bend plane; the middle joint's hinge axis is the bend "
    "axis; limits are kept by projection. Chains of exactly two bones per goal.",
    params, rf_ikc_node_create);

static const rf_node_desc *const nodes[] = {&twobone_node};

RF_PLUGIN_DEFINE("org.rigflow.ik-twobone", "Two-bone IK solver", "0.1.0",
                 "Analytic two-bone inverse kinematics with a pole vector", nodes);
