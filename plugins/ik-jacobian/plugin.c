/* Three node types on the Jacobian solvers: ik.jacobian-transpose, ik.jacobian-pinv, ik.dls. */
#include <string.h>

#include "jacobian.h"

#define MAX_STEP_PARAM                                                                             \
    {                                                                                              \
        sizeof(rf_param_desc), "max-step", RF_PARAM_FLOAT, RF_PARAM_HAS_RANGE, 0, NULL, 0, 1e9,    \
            NULL, "largest target displacement per step, length units (0: the mean bone length)"   \
    }

static const rf_param_desc step_params[] = {RF_IKC_COMMON_PARAMS, MAX_STEP_PARAM};
static const rf_param_desc dls_params[] = {
    RF_IKC_COMMON_PARAMS,
    MAX_STEP_PARAM,
    RF_PARAM_DESC_FLOAT("damping", 0, 0, 1e9,
                        "damping lambda, length units (0: 0.1 x the mean bone length)"),
};

static bool create_step(const rf_host *host, rf_node *node, void **self)
{
    if (!rf_ikc_node_create(host, node, self))
        return false;
    ((rf_ik_config *)*self)->max_step = host->param_float(node, "max-step");
    return true;
}

static bool create_dls(const rf_host *host, rf_node *node, void **self)
{
    if (!create_step(host, node, self))
        return false;
    ((rf_ik_config *)*self)->damping = host->param_float(node, "damping");
    return true;
}

RF_IKC_NODE_TYPE(jt, &rf_ik_jt_api, "ik.jacobian-transpose",
                 "Jacobian transpose inverse kinematics (Buss): steps along J^T e with the step "
                 "length that minimises the linearised error; several goals; honours hinge, cone, "
                 "twist limits and locked joints by projection.",
                 step_params, create_step);

RF_IKC_NODE_TYPE(pinv, &rf_ik_pinv_api, "ik.jacobian-pinv",
                 "Jacobian pseudoinverse inverse kinematics through the SVD (Buss); several goals; "
                 "honours hinge, cone, twist limits and locked joints by projection.",
                 step_params, create_step);

RF_IKC_NODE_TYPE(dls, &rf_ik_dls_api, "ik.dls",
                 "Damped least squares inverse kinematics (Buss): J^T (J J^T + lambda^2 I)^-1 e; "
                 "several goals; honours hinge, cone, twist limits and locked joints by "
                 "projection.",
                 dls_params, create_dls);

static const rf_node_desc *const nodes[] = {&jt_node, &pinv_node, &dls_node};

RF_PLUGIN_DEFINE(
    "org.rigflow.ik-jacobian", "Jacobian IK solvers", "0.1.0",
    "Jacobian transpose, pseudoinverse (SVD) and damped least squares inverse kinematics", nodes);
