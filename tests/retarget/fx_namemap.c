/* Test fixture plugin: node type test.name-map, a mapping from "target=source" name pairs, so
 * the retarget node can be driven through the host before (and besides) any matcher. */
#include <stdlib.h>
#include <string.h>

#include <rigflow/rigflow.h>

static bool fx_add(rf_mapping *m, const rf_skeleton *t, const rf_skeleton *s, const char *pair)
{
    char buf[256];
    const char *eq = strchr(pair, '=');
    size_t len = strcspn(pair, ",");
    if (!eq || eq - pair >= (long)len || len >= sizeof buf)
        return false;
    memcpy(buf, pair, len);
    buf[len] = 0;
    buf[eq - pair] = 0;
    int32_t jt = rf_skeleton_find(t, buf), js = rf_skeleton_find(s, buf + (eq - pair) + 1);
    if (jt < 0 || js < 0)
        return false;
    rf_map_entry *e = &m->entries[jt];
    e->inputs = calloc(1, sizeof *e->inputs);
    if (!e->inputs)
        return false;
    e->input_count = 1;
    e->inputs[0] = (rf_map_input){0, (uint32_t)js, 1, 0, 0};
    return true;
}

static bool fx_process(void *self, const rf_host *host, rf_node *node)
{
    (void)self;
    const rf_skeleton *t = host->input(node, "target", 0), *s = host->input(node, "sources", 0);
    rf_mapping *m = rf_mapping_new(t->joint_count, 1);
    const char *p = host->param_string(node, "pairs");
    while (m && *p) {
        if (!fx_add(m, t, s, p)) {
            host->error(node, "bad pair or unknown joint at '%s'", p);
            rf_mapping_free(m);
            return false;
        }
        p += strcspn(p, ",");
        p += *p == ',';
    }
    return m && host->set_output(node, "mapping", m, rf_mapping_free);
}

static const rf_port_desc fx_inputs[] = {
    RF_PORT_DESC("target", RF_TYPE_SKELETON, 0, "target skeleton"),
    RF_PORT_DESC("sources", RF_TYPE_SKELETON, RF_PORT_MULTIPLE, "source skeletons"),
};
static const rf_port_desc fx_outputs[] = {
    RF_PORT_DESC("mapping", RF_TYPE_MAPPING, 0, "the mapping"),
};
static const rf_param_desc fx_params[] = {
    RF_PARAM_DESC(.name = "pairs", .type = RF_PARAM_STRING, .flags = RF_PARAM_REQUIRED,
                  .doc = "target=source joint names, comma separated (source 0)"),
};
static const rf_node_desc fx_node = {
    .size = sizeof(rf_node_desc),
    .type = "test.name-map",
    .kind = RF_KIND_MATCHER,
    .doc = "Test fixture: a mapping from name pairs.",
    RF_NODE_INPUTS(fx_inputs),
    RF_NODE_OUTPUTS(fx_outputs),
    RF_NODE_PARAMS(fx_params),
    .process = fx_process,
};
static const rf_node_desc *const fx_nodes[] = {&fx_node};

RF_PLUGIN_EXPORT const rf_plugin_entry rigflow_plugin_entry = {
    .abi = RF_ABI_VERSION_INIT,
    .size = sizeof(rf_plugin_entry),
    .id = "org.rigflow.test.name-map",
    .name = "Name-pair mapping (test)",
    .version = "0",
    .description = "test fixture",
    .node_count = 1,
    .nodes = fx_nodes,
};
