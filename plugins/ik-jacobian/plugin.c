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
    {sizeof(rf_param_desc), "damping", RF_PARAM_FLOAT, RF_PARAM_HAS_RANGE, 0, NULL, 0, 1e9, NULL,
     "damping lambda, length units (0: 0.1 x the mean bone length)"},
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

static bool process_jt(void *self, const rf_host *host, rf_node *node)
{
    return rf_ikc_node_process(&rf_ik_jt_api, self, host, node);
}
static bool process_pinv(void *self, const rf_host *host, rf_node *node)
{
    return rf_ikc_node_process(&rf_ik_pinv_api, self, host, node);
}
static bool process_dls(void *self, const rf_host *host, rf_node *node)
{
    return rf_ikc_node_process(&rf_ik_dls_api, self, host, node);
}

static const void *ext_jt(const char *id)
{
    return strcmp(id, RF_IK_EXTENSION) == 0 ? &rf_ik_jt_api : NULL;
}
static const void *ext_pinv(const char *id)
{
    return strcmp(id, RF_IK_EXTENSION) == 0 ? &rf_ik_pinv_api : NULL;
}
static const void *ext_dls(const char *id)
{
    return strcmp(id, RF_IK_EXTENSION) == 0 ? &rf_ik_dls_api : NULL;
}

#define COUNT(a) (sizeof(a) / sizeof((a)[0]))

static const rf_node_desc jt_node = {
    sizeof(rf_node_desc),
    "ik.jacobian-transpose",
    RF_KIND_IK,
    "Jacobian transpose inverse kinematics (Buss): steps along J^T e with the step length that "
    "minimises the linearised error; several goals; honours hinge, cone, twist limits and locked "
    "joints by projection.",
    0,
    NULL,
    1,
    &rf_ikc_solver_output,
    COUNT(step_params),
    step_params,
    create_step,
    process_jt,
    rf_ikc_node_destroy,
    ext_jt};

static const rf_node_desc pinv_node = {
    sizeof(rf_node_desc),
    "ik.jacobian-pinv",
    RF_KIND_IK,
    "Jacobian pseudoinverse inverse kinematics through the SVD (Buss); several goals; honours "
    "hinge, cone, twist limits and locked joints by projection.",
    0,
    NULL,
    1,
    &rf_ikc_solver_output,
    COUNT(step_params),
    step_params,
    create_step,
    process_pinv,
    rf_ikc_node_destroy,
    ext_pinv};

static const rf_node_desc dls_node = {
    sizeof(rf_node_desc),
    "ik.dls",
    RF_KIND_IK,
    "Damped least squares inverse kinematics (Buss): J^T (J J^T + lambda^2 I)^-1 e; several "
    "goals; honours hinge, cone, twist limits and locked joints by projection.",
    0,
    NULL,
    1,
    &rf_ikc_solver_output,
    COUNT(dls_params),
    dls_params,
    create_dls,
    process_dls,
    rf_ikc_node_destroy,
    ext_dls};

static const rf_node_desc *const nodes[] = {&jt_node, &pinv_node, &dls_node};

RF_PLUGIN_EXPORT const rf_plugin_entry rigflow_plugin_entry = {
    RF_ABI_VERSION_INIT,
    sizeof(rf_plugin_entry),
    "org.rigflow.ik-jacobian",
    "Jacobian IK solvers",
    "0.1.0",
    "Jacobian transpose, pseudoinverse (SVD) and damped least squares inverse kinematics",
    NULL,
    NULL,
    COUNT(nodes),
    nodes,
};
