/* Test fixture for report.html: a node sending measures about a target joint given by its
 * `joint` parameter (any number, as a third-party measuring plugin might send), so the report's
 * handling of a joint the target does not have can be checked. */
#include <rigflow/measures.h>
#include <rigflow/plugin.h>

static bool measures_process(void *self, const rf_host *host, rf_node *node)
{
    (void)self;
    rf_measures *m = rf_measures_new(2, 30);
    float *v =
        m ? rf_measures_add(m, "error", "deg", (int32_t)host->param_int(node, "joint"), 0) : NULL;
    if (!v) {
        rf_measures_free(m);
        host->error(node, "out of memory");
        return false;
    }
    v[0] = 1, v[1] = 2;
    return host->set_output(node, "measures", m, rf_measures_free);
}

static const rf_port_desc measures_outputs[] = {
    RF_PORT_DESC("measures", RF_TYPE_MEASURES, 0, "one series about `joint`"),
};

static const rf_param_desc measures_params[] = {
    RF_PARAM_DESC_INT("joint", 0, -1000000, 1000000, "the target joint the series is about"),
};

static const rf_node_desc measures_node = {
    .size = sizeof(rf_node_desc),
    .type = "test.measures",
    .kind = RF_KIND_REPORT,
    .doc = "sends one series about the joint its parameter names",
    RF_NODE_OUTPUTS(measures_outputs),
    RF_NODE_PARAMS(measures_params),
    .process = measures_process,
};
static const rf_node_desc *const nodes[] = {&measures_node};

RF_PLUGIN_EXPORT const rf_plugin_entry rigflow_plugin_entry = {
    .abi = RF_ABI_VERSION_INIT,
    .size = sizeof(rf_plugin_entry),
    .id = "org.rigflow.test.measures",
    .name = "report test fixture",
    .version = "1.0",
    .description = "a node sending measures about any joint number",
    .node_count = 1,
    .nodes = nodes,
};
