/* The node type side shared by every solver plugin: a node's state is its rf_ik_config, and each
 * run hands a freshly made solver to whichever nodes are connected to its "solver" port. */
#include <stdlib.h>

#include "rigflow/ik-common.h"

const rf_port_desc rf_ikc_solver_output =
    RF_PORT_DESC("solver", RF_TYPE_IK_SOLVER, 0,
                 "the configured solver, for nodes that take a rigflow.ik-solver input");

bool rf_ikc_node_create(const rf_host *host, rf_node *node, void **self)
{
    rf_ik_config *cfg = calloc(1, sizeof *cfg);
    if (!cfg) {
        host->error(node, "out of memory");
        return false;
    }
    cfg->size = sizeof *cfg;
    cfg->max_joints = (uint32_t)host->param_int(node, "max-joints");
    cfg->max_goals = (uint32_t)host->param_int(node, "max-goals");
    *self = cfg;
    return true;
}

bool rf_ikc_node_process(const rf_ik_solver_api *api, void *self, const rf_host *host,
                         rf_node *node)
{
    char err[160] = "";
    void *state = api->create((const rf_ik_config *)self, err, sizeof err);
    if (!state) {
        host->error(node, "cannot make the %s solver: %s", api->name, err);
        return false;
    }
    rf_ik_solver *value = rf_ik_solver_new(api, state, host->node_id(node));
    if (!value) {
        host->error(node, "out of memory");
        return false;
    }
    return host->set_output(node, "solver", value, rf_ik_solver_free);
}

void rf_ikc_node_destroy(void *self)
{
    free(self);
}
