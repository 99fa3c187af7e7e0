/* The ik.ccd node type: a CCD solver on a rigflow.ik-solver port. */
#include <string.h>

#include "ccd.h"

static const rf_param_desc params[] = {RF_IKC_COMMON_PARAMS};

RF_IKC_NODE_TYPE(
    ccd, &rf_ik_ccd_api, "ik.ccd",
    "Cyclic Coordinate Descent, backward sweep from the effector to the chain root (Kenwright "
    "2012); several goals by weighted averaging at shared joints; honours hinge, cone, twist "
    "limits and locked joints by projecting each turn.",
    params, rf_ikc_node_create);

static const rf_node_desc *const nodes[] = {&ccd_node};

RF_PLUGIN_DEFINE("org.rigflow.ik-ccd", "CCD IK solver", "0.1.0",
                 "Cyclic Coordinate Descent inverse kinematics", nodes);
