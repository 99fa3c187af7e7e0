/* `rigflow map`. Builds the graph of pipelines/map.json in memory (import nodes for the sources
 * and the target, a matcher, a mapping.write node when -o is given) and runs it through the
 * engine, so the command and the pipeline can never disagree. The matcher itself prints the
 * explanation (--explain) and the timing (--repeat); this file only wires the graph. */
#include <jansson.h>
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "map-cmd.h"

typedef struct rf_map_cmd_opts {
    char *output;
    char *matcher;
    gboolean explain;
    int repeat;
    char **params;
} rf_map_cmd_opts;

/* An import node for `path` with the importer the plugins say reads it (see
 * rf_registry_importer_for), or NULL after saying that none does. */
static json_t *rf_map_cmd_import_node(const rf_registry *reg, const char *id, const char *path)
{
    const char *param = NULL;
    const rf_node_desc *d = rf_registry_importer_for(reg, path, &param);
    if (!d) {
        g_autofree char *shown = rf_printable(path);
        fprintf(stderr,
                "rigflow map: %s: no installed importer reads this file (see rigflow "
                "plugins)\n",
                shown);
        return NULL;
    }
    return json_pack("{s:s, s:s, s:{s:s}}", "id", id, "type", d->type, "params", param, path);
}

/* Node ids follow pipelines/map.json: source (then source2, source3...), target, map, save; so
 * -p map.threshold=60 means the same here as with rigflow run. */
static char *rf_map_cmd_source_id(int i)
{
    return i == 0 ? g_strdup("source") : g_strdup_printf("source%d", i + 1);
}

static json_t *rf_map_cmd_graph(const rf_registry *reg, char **files, int nsources,
                                const rf_map_cmd_opts *o)
{
    json_t *nodes = json_array(), *srcs = json_array(), *clips = json_array();
    bool found = true;
    for (int i = 0; i < nsources; i++) {
        g_autofree char *id = rf_map_cmd_source_id(i);
        g_autofree char *port = g_strdup_printf("%s.skeleton", id);
        g_autofree char *clip = g_strdup_printf("%s.animation", id);
        json_t *node = rf_map_cmd_import_node(reg, id, files[i]);
        found = found && node;
        json_array_append_new(nodes, node ? node : json_null());
        json_array_append_new(srcs, json_string(port));
        json_array_append_new(clips, json_string(clip));
    }
    json_t *target = rf_map_cmd_import_node(reg, "target", files[nsources]);
    if (!found || !target) {
        json_decref(target), json_decref(nodes), json_decref(srcs), json_decref(clips);
        return NULL;
    }
    json_array_append_new(nodes, target);
    json_t *params = json_object(); /* only what was asked: another matcher may lack these */
    if (o->explain)
        json_object_set_new(params, "explain", json_true());
    if (o->repeat > 1)
        json_object_set_new(params, "repeat", json_integer(o->repeat));
    json_t *inputs = json_pack("{s:s, s:O}", "target", "target.skeleton", "sources", srcs);
    if (!o->matcher || strcmp(o->matcher, "skeletal-similarity") == 0) {
        /* the clips give the pose to analyse when a rest pose is no body */
        json_object_set_new(inputs, "target_animation", json_string("target.animation"));
        json_object_set(inputs, "source_animations", clips);
    }
    json_decref(clips);
    json_array_append_new(nodes, json_pack("{s:s, s:s, s:o, s:o}", "id", "map", "type",
                                           o->matcher ? o->matcher : "skeletal-similarity",
                                           "inputs", inputs, "params", params));
    if (o->output)
        json_array_append_new(nodes, json_pack("{s:s, s:s, s:{s:s, s:s, s:o}, s:{s:s}}", "id",
                                               "save", "type", "mapping.write", "inputs", "mapping",
                                               "map.mapping", "target", "target.skeleton",
                                               "sources", srcs, "params", "path", o->output));
    else
        json_decref(srcs);
    return json_pack("{s:s, s:i, s:o}", "format", "rigflow.pipeline", "version", 1, "nodes", nodes);
}

/* Without -o the mapping is printed: one line per target joint. */
static void rf_map_cmd_print(const rf_pipeline *p, int nsources)
{
    const rf_mapping *m = rf_pipeline_result(p, "map", "mapping");
    const rf_skeleton *t = rf_pipeline_result(p, "target", "skeleton");
    if (!m || !t)
        return;
    const rf_skeleton *src[64] = {0};
    for (int i = 0; i < nsources && i < 64; i++) {
        g_autofree char *id = rf_map_cmd_source_id(i);
        src[i] = rf_pipeline_result(p, id, "skeleton");
    }
    uint32_t mapped = 0;
    for (uint32_t j = 0; j < m->target_joint_count && j < t->joint_count; j++) {
        const rf_map_entry *e = &m->entries[j];
        g_autofree char *target = rf_printable(t->joints[j].name);
        printf("%-28s", target);
        for (uint32_t k = 0; k < e->input_count; k++) {
            const rf_map_input *in = &e->inputs[k];
            const rf_skeleton *s = in->source < 64 ? src[in->source] : NULL;
            g_autofree char *name =
                rf_printable(s && in->joint < s->joint_count ? s->joints[in->joint].name : "?");
            printf(" <- %u:%s%s%s", in->source, name,
                   in->flags & RF_MAP_REVERSE ? " (reverse)" : "",
                   in->flags & RF_MAP_MIRROR ? " (half a cycle later)" : "");
        }
        printf(e->input_count ? "  score %.1f\n" : " (unmapped)\n", e->score);
        mapped += e->input_count > 0;
    }
    printf("%u of %u target joints mapped\n", mapped, m->target_joint_count);
}

static int rf_map_cmd_run(rf_registry *reg, char **files, int nsources, const rf_map_cmd_opts *o)
{
    for (int i = 0; i <= nsources; i++)
        if (!rf_check_utf8_name("map", files[i]))
            return RF_EXIT_VALIDATION;
    json_t *graph = rf_map_cmd_graph(reg, files, nsources, o);
    char *text = graph ? json_dumps(graph, JSON_COMPACT) : NULL;
    json_decref(graph);
    g_autofree char *cwd = g_get_current_dir();
    g_autoptr(GPtrArray) diags = rf_diags_new();
    rf_pipeline *p = text ? rf_pipeline_load_string(text, "map", cwd, diags) : NULL;
    free(text);
    for (char **kv = o->params; p && kv && *kv; kv++)
        rf_pipeline_override(p, *kv, diags);
    if (!p || !rf_pipeline_validate(p, reg, diags) || diags->len) {
        rf_print_diags(diags, "error");
        rf_pipeline_free(p);
        return RF_EXIT_VALIDATION;
    }
    int code = rf_run_interruptible(p, reg, false, true); /* Ctrl-C: 130, no -o file left */
    if (code == RF_EXIT_OK && !o->output && !o->explain)
        rf_map_cmd_print(p, nsources);
    rf_pipeline_free(p);
    return code;
}

int rf_cmd_map(rf_registry *reg, int argc, char **argv)
{
    rf_map_cmd_opts o = {.repeat = 1};
    const GOptionEntry entries[] = {
        {"output", 'o', 0, G_OPTION_ARG_FILENAME, &o.output,
         "Write the mapping file (doc/formats/mapping.md); without it the mapping is printed",
         "OUT.json"},
        {"explain", 0, 0, G_OPTION_ARG_NONE, &o.explain,
         "Print the three best candidates of every target joint with their per-metric scores, "
         "and the sections and sides found",
         NULL},
        {"repeat", 0, 0, G_OPTION_ARG_INT, &o.repeat,
         "Map N times after importing once; prints map_us_median=<value> on stderr", "N"},
        {"matcher", 'm', 0, G_OPTION_ARG_STRING, &o.matcher,
         "Matcher node type (default skeletal-similarity; names for name matching)", "TYPE"},
        {"param", 'p', 0, G_OPTION_ARG_STRING_ARRAY, &o.params,
         "Override a parameter, as in rigflow run (node ids: source, source2..., target, map, "
         "save)",
         "NODE.PARAM=VALUE"},
        {NULL, 0, 0, 0, NULL, NULL, NULL}};
    int code = RF_EXIT_USAGE;
    bool parsed =
        rf_parse_options("map", "SOURCE... TARGET",
                         "Map the joints of TARGET onto the SOURCE skeletons (doc/matching.md).",
                         entries, &argc, &argv);
    if (!parsed)
        code = RF_EXIT_USAGE;
    else if (argc < 3)
        fprintf(stderr, "rigflow map: expected at least one SOURCE and a TARGET file\n");
    else if (o.repeat < 1)
        fprintf(stderr, "rigflow map: --repeat needs a count of at least 1\n");
    else
        code = rf_map_cmd_run(reg, argv + 1, argc - 2, &o);
    g_free(o.output);
    g_free(o.matcher);
    g_strfreev(o.params);
    return code;
}
