/* `rigflow plugins` and `rigflow describe`: what is installed and how to use it. */
#include <stdio.h>
#include <string.h>

#include "commands.h"

int rf_cmd_plugins(rf_registry *reg, int argc, char **argv)
{
    if (!rf_parse_options("plugins", "", "List the plugins found on the search path.", NULL, &argc,
                          &argv))
        return RF_EXIT_USAGE;
    guint n = rf_registry_plugin_count(reg);
    if (n == 0)
        printf("no plugins found (set RIGFLOW_PLUGIN_PATH or use --plugin-path)\n");
    for (guint i = 0; i < n; i++) {
        const rf_plugin *p = rf_registry_plugin(reg, i);
        const rf_plugin_entry *e = rf_plugin_entry_of(p);
        printf("%s %s (%s, ABI %u.%u.%u)\n  %s\n  file: %s\n", e->id, e->version ? e->version : "",
               e->name, e->abi.major, e->abi.minor, e->abi.patch,
               e->description ? e->description : "", rf_plugin_path(p));
        for (uint32_t k = 0; k < e->node_count; k++)
            printf("  node type %-22s %s\n", e->nodes[k]->type, rf_kind_name(e->nodes[k]->kind));
    }
    return RF_EXIT_OK;
}

static void describe_ports(const char *title, const rf_port_desc *ports, uint32_t count)
{
    printf("%s:%s\n", title, count ? "" : " none");
    for (uint32_t i = 0; i < count; i++) {
        const rf_port_desc *p = &ports[i];
        printf("  %-18s %-20s%s%s %s\n", p->name, p->type,
               (p->flags & RF_PORT_OPTIONAL) ? " optional" : "",
               (p->flags & RF_PORT_MULTIPLE) ? " multiple" : "", p->doc ? p->doc : "");
    }
}

static void describe_default(const rf_param_desc *d)
{
    if (d->flags & RF_PARAM_REQUIRED)
        printf("required");
    else if (d->type == RF_PARAM_BOOL)
        printf("default %s", d->default_number != 0 ? "true" : "false");
    else if (d->type == RF_PARAM_INT || d->type == RF_PARAM_FLOAT)
        printf("default %g", d->default_number);
    else
        printf("default \"%s\"", d->default_string ? d->default_string : "");
    if (d->flags & RF_PARAM_HAS_RANGE)
        printf(", range [%g, %g]", d->min, d->max);
    if (d->type == RF_PARAM_ENUM)
        printf(", one of %s", d->choices);
}

static void describe_params(const rf_node_desc *d)
{
    printf("parameters:%s\n", d->param_count ? "" : " none");
    for (uint32_t i = 0; i < d->param_count; i++) {
        const rf_param_desc *p = &d->params[i];
        printf("  %-18s %-12s ", p->name, rf_param_type_name(p->type));
        describe_default(p);
        printf("\n      %s\n", p->doc ? p->doc : "");
    }
}

int rf_cmd_describe(rf_registry *reg, int argc, char **argv)
{
    if (!rf_parse_options("describe", "NODE_TYPE", "Show a node type's ports and parameters.", NULL,
                          &argc, &argv))
        return RF_EXIT_USAGE;
    if (argc != 2) {
        fprintf(stderr, "rigflow describe: expected one NODE_TYPE (see rigflow plugins)\n");
        return RF_EXIT_USAGE;
    }
    const rf_plugin *plugin = NULL;
    const rf_node_desc *d = rf_registry_find(reg, argv[1], &plugin);
    if (!d) {
        fprintf(stderr, "rigflow describe: plugin not installed: %s (see rigflow plugins)\n",
                argv[1]);
        return RF_EXIT_USAGE;
    }
    printf("%s (%s) from %s\n  %s\n  %s\n\n", d->type, rf_kind_name(d->kind),
           rf_plugin_path(plugin), d->doc ? d->doc : "",
           d->flags & RF_NODE_CONCURRENT
               ? "processes beside the nodes it does not depend on (rigflow run --jobs)"
               : "processes alone");
    describe_ports("inputs", d->inputs, d->input_count);
    describe_ports("outputs", d->outputs, d->output_count);
    describe_params(d);
    return RF_EXIT_OK;
}
