/* `rigflow report`: the retarget pipeline with its HTML report (doc/report.md). The graph is the
 * file pipelines/retarget.json itself, read from where it is installed, or from the source tree
 * when the command runs from a build tree; without --glb its export node is left out. */
#include <jansson.h>
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "report-cmd.h"

/* The pipeline as text, without its export node when no GLB is asked for. */
static char *rf_report_graph(const char *path, bool export, GPtrArray *diags)
{
    json_error_t e;
    json_t *root = json_load_file(path, 0, &e);
    if (!root) {
        rf_diags_add(diags, path, e.line, e.column, NULL, NULL,
                     "cannot read the retarget pipeline: %s", e.text);
        return NULL;
    }
    json_t *nodes = json_object_get(root, "nodes");
    for (size_t i = 0; !export && json_is_array(nodes) && i < json_array_size(nodes); i++) {
        const char *id = json_string_value(json_object_get(json_array_get(nodes, i), "id"));
        if (id && strcmp(id, "export") == 0) {
            json_array_remove(nodes, i);
            break;
        }
    }
    char *text = json_dumps(root, JSON_COMPACT);
    json_decref(root);
    return text;
}

static int rf_report_run(rf_registry *reg, const char *source, const char *target, const char *out,
                         const char *glb, char **params)
{
    g_autofree char *path = rf_pipeline_file("retarget.json");
    g_autoptr(GPtrArray) diags = rf_diags_new();
    char *text = rf_report_graph(path, glb != NULL, diags);
    g_autofree char *dir = g_path_get_dirname(path);
    rf_pipeline *p = text ? rf_pipeline_load_string(text, path, dir, diags) : NULL;
    free(text);
    g_autofree char *s = g_strdup_printf("source.path=%s", source);
    g_autofree char *t = g_strdup_printf("target.path=%s", target);
    g_autofree char *r = g_strdup_printf("report.path=%s", out);
    g_autofree char *x = glb ? g_strdup_printf("export.path=%s", glb) : NULL;
    const char *fixed[] = {s, t, r, x};
    for (size_t i = 0; p && i < 4; i++)
        if (fixed[i])
            rf_pipeline_override(p, fixed[i], diags);
    for (char **kv = params; p && kv && *kv; kv++)
        rf_pipeline_override(p, *kv, diags);
    bool valid = p && rf_pipeline_validate(p, reg, diags);
    rf_registry_take_diags(reg, diags); /* a plugin opened for the pipeline and refused */
    if (!valid || diags->len) {
        rf_print_diags(diags, "error");
        rf_pipeline_free(p);
        return RF_EXIT_VALIDATION;
    }
    int code = rf_run_interruptible(p, reg, false, g_getenv("RIGFLOW_QUIET") != NULL);
    rf_pipeline_free(p);
    if (code == RF_EXIT_OK)
        printf("wrote %s\n", out);
    return code;
}

int rf_cmd_report(rf_registry *reg, int argc, char **argv)
{
    char *out = NULL, *glb = NULL, **params = NULL;
    const GOptionEntry entries[] = {
        {"output", 'o', 0, G_OPTION_ARG_FILENAME, &out, "The HTML page to write (doc/report.md)",
         "OUT.html"},
        {"glb", 0, 0, G_OPTION_ARG_FILENAME, &glb, "Also write the retargeted character",
         "OUT.glb"},
        {"param", 'p', 0, G_OPTION_ARG_STRING_ARRAY, &params,
         "Override a parameter of pipelines/retarget.json, as in rigflow run (node ids: source, "
         "target, map, ik, retarget, export, measure, report)",
         "NODE.PARAM=VALUE"},
        {NULL, 0, 0, 0, NULL, NULL, NULL}};
    int code = RF_EXIT_USAGE;
    if (!rf_parse_options("report", "SOURCE TARGET",
                          "Retarget SOURCE's clip onto TARGET and write a self-contained HTML page "
                          "of both skeletons, the mapping, both motions and the measures.",
                          entries, &argc, &argv))
        code = RF_EXIT_USAGE;
    else if (argc != 3)
        fprintf(stderr, "rigflow report: expected a SOURCE and a TARGET file\n");
    else if (!out)
        fprintf(stderr, "rigflow report: -o OUT.html is required\n");
    else
        code = rf_report_run(reg, argv[1], argv[2], out, glb, params);
    g_free(out);
    g_free(glb);
    g_strfreev(params);
    return code;
}
