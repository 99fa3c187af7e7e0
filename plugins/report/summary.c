/* report.summary: one line about whatever reaches it (a skeleton, an animation, a mapping), on
 * stdout, so a pipeline's user sees at a glance what was produced. */
#include "config.h"

#include <stdio.h>
#include <string.h>

#include <rigflow/plugin.h>
#include <rigflow/text.h>

static uint32_t root_count(const rf_skeleton *s)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < s->joint_count; i++)
        n += s->joints[i].parent < 0;
    return n;
}

static uint32_t mapped_count(const rf_mapping *m)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < m->target_joint_count; i++)
        n += m->entries[i].input_count > 0;
    return n;
}

static void describe(FILE *f, const rf_skeleton *s, const rf_animation *a, const rf_mapping *m)
{
    const char *sep = "";
    if (s) {
        fprintf(f, "%u joints (%u root%s)", s->joint_count, root_count(s),
                root_count(s) == 1 ? "" : "s");
        sep = ", ";
    }
    if (a) {
        fprintf(f, "%s%u frames at %g fps (%.2f s)", sep, a->frame_count, a->fps,
                a->fps > 0 ? a->frame_count / a->fps : 0.0);
        sep = ", ";
    }
    if (m)
        fprintf(f, "%s%u of %u target joints mapped from %u source%s", sep, mapped_count(m),
                m->target_joint_count, m->source_count, m->source_count == 1 ? "" : "s");
}

static bool summary_process(void *self, const rf_host *host, rf_node *node)
{
    (void)self;
    const rf_skeleton *s = host->input(node, "skeleton", 0);
    const rf_animation *a = host->input(node, "animation", 0);
    const rf_mapping *m = host->input(node, "mapping", 0);
    if (a && s && a->joint_count != s->joint_count) {
        host->error(node, "the animation has %u joints but the skeleton has %u", a->joint_count,
                    s->joint_count);
        return false;
    }
    const char *label = host->param_string(node, "label");
    FILE *out = rf_node_out(host, node);
    rf_text_fputs(*label ? label : host->node_id(node), out, 0); /* a pipeline file's text */
    fputs(": ", out);
    describe(out, s, a, m);
    fputs("\n", out);
    fflush(out);
    return true;
}

static const rf_port_desc summary_inputs[] = {
    RF_PORT_DESC("skeleton", RF_TYPE_SKELETON, RF_PORT_OPTIONAL, "skeleton to count"),
    RF_PORT_DESC("animation", RF_TYPE_ANIMATION, RF_PORT_OPTIONAL, "clip to measure"),
    RF_PORT_DESC("mapping", RF_TYPE_MAPPING, RF_PORT_OPTIONAL, "mapping to count"),
};

static const rf_param_desc summary_params[] = {
    RF_PARAM_DESC_STRING("label", "", "text before the summary (default: the node id)"),
};

static const rf_node_desc summary_node = {
    .size = sizeof(rf_node_desc),
    .type = "report.summary",
    .kind = RF_KIND_REPORT,
    .doc = "Prints one line on stdout: joint count, frames and duration, mapped joints.",
    RF_NODE_INPUTS(summary_inputs),
    RF_NODE_PARAMS(summary_params),
    .process = summary_process,
    .flags = RF_NODE_CONCURRENT,
};

extern const rf_node_desc rf_report_html_node; /* html.c */

static const rf_node_desc *const report_nodes[] = {&summary_node, &rf_report_html_node};

RF_PLUGIN_EXPORT const rf_plugin_entry rigflow_plugin_entry = {
    .abi = RF_ABI_VERSION_INIT,
    .size = sizeof(rf_plugin_entry),
    .id = "org.rigflow.report",
    .name = "Reports",
    .version = PACKAGE_VERSION,
    .description = "Summaries of skeletons, clips and mappings: one line, or an HTML page",
    .node_count = 2,
    .nodes = report_nodes,
};
