/* Pipeline files: parsing, the structural checks, command-line overrides.
 *
 *   { "format": "rigflow.pipeline", "version": 1, "description": "...",
 *     "nodes": [ { "id": "source", "type": "bvh.import", "params": { "path": "walk.bvh" } },
 *                { "id": "export", "type": "bvh.export", "params": { "path": "out.bvh" },
 *                  "inputs": { "skeleton": "source.skeleton", "animation": "source.animation" } } ]
 * }
 *
 * Structural problems are collected, not fatal, so that validation can report them together with
 * every later problem of the nodes that are well-formed. See doc/pipeline-format.md.
 */
#include <string.h>

#include "pipeline-internal.h"

static void node_free(gpointer data)
{
    rf_node *n = data;
    g_free(n->id);
    g_free(n->type);
    g_free(n->pointer);
    g_free(n->error);
    rf_node_clear_bindings(n);
    g_free(n);
}

void rf_pipeline_free(rf_pipeline *p)
{
    if (!p)
        return;
    rf_pipeline_reset_run(p);
    g_ptr_array_unref(p->nodes);
    g_hash_table_destroy(p->by_id);
    g_hash_table_destroy(p->overrides);
    g_ptr_array_unref(p->load_diags);
    if (p->order)
        g_array_free(p->order, TRUE);
    if (p->temp_files)
        g_ptr_array_unref(p->temp_files);
    if (p->syncs)
        g_ptr_array_unref(p->syncs);
    json_decref(p->root);
    g_free(p->name);
    g_free(p->dir);
    g_free(p);
}

/* Node ids name nodes in "node.port" edges and "-p node.param=" overrides: no dots, no blanks. */
static bool id_ok(const char *id)
{
    if (!*id)
        return false;
    for (const char *c = id; *c; c++)
        if (!g_ascii_isalnum(*c) && *c != '_' && *c != '-')
            return false;
    return true;
}

static bool edge_ok(json_t *v)
{
    if (json_is_string(v))
        return true;
    if (!json_is_array(v) || json_array_size(v) == 0)
        return false;
    size_t i;
    json_t *e;
    json_array_foreach(v, i, e) if (!json_is_string(e)) return false;
    return true;
}

#define LOAD_ERR(p, n, ptr, ...)                                                                   \
    rf_diags_add((p)->load_diags, (p)->name, 0, 0, (n), (ptr), __VA_ARGS__)

static void check_node_keys(rf_pipeline *p, rf_node *n)
{
    const char *key;
    json_t *v;
    json_object_foreach(n->json, key, v)
    {
        if (strcmp(key, "id") && strcmp(key, "type") && strcmp(key, "params") &&
            strcmp(key, "inputs") && strcmp(key, "comment")) {
            g_autofree char *ptr = g_strdup_printf("%s/%s", n->pointer, key);
            LOAD_ERR(p, n->id, ptr,
                     "unknown key '%s' (a node has id, type, params, inputs, comment)", key);
            n->malformed = true;
        }
    }
}

static void check_node_inputs(rf_pipeline *p, rf_node *n)
{
    json_t *inputs = json_object_get(n->json, "inputs");
    if (!inputs)
        return;
    if (!json_is_object(inputs)) {
        g_autofree char *ptr = g_strdup_printf("%s/inputs", n->pointer);
        LOAD_ERR(p, n->id, ptr, "inputs must be an object of port names to \"node.port\" edges");
        n->malformed = true;
        return;
    }
    const char *port;
    json_t *v;
    json_object_foreach(inputs, port, v)
    {
        if (edge_ok(v))
            continue;
        g_autofree char *ptr = g_strdup_printf("%s/inputs/%s", n->pointer, port);
        LOAD_ERR(p, n->id, ptr, "expected \"node.port\" or a list of them for input '%s'", port);
        n->malformed = true;
    }
}

/* Builds one node from nodes[index], recording what is malformed. */
static rf_node *parse_node(rf_pipeline *p, json_t *obj, size_t index)
{
    rf_node *n = g_new0(rf_node, 1);
    n->pipeline = p;
    n->pointer = g_strdup_printf("/nodes/%zu", index);
    n->json = obj;
    if (!json_is_object(obj)) {
        LOAD_ERR(p, NULL, n->pointer, "expected a node object");
        n->malformed = true;
        return n;
    }
    json_t *id = json_object_get(obj, "id"), *type = json_object_get(obj, "type");
    if (json_is_string(id) && id_ok(json_string_value(id)))
        n->id = g_strdup(json_string_value(id));
    else {
        LOAD_ERR(p, NULL, n->pointer,
                 "every node needs an \"id\": a string of letters, digits, "
                 "'_' or '-'");
        n->malformed = true;
    }
    if (json_is_string(type))
        n->type = g_strdup(json_string_value(type));
    else {
        LOAD_ERR(p, n->id, n->pointer, "every node needs a \"type\" string (see rigflow plugins)");
        n->malformed = true;
    }
    json_t *params = json_object_get(obj, "params");
    if (params && !json_is_object(params)) {
        g_autofree char *ptr = g_strdup_printf("%s/params", n->pointer);
        LOAD_ERR(p, n->id, ptr, "params must be an object of parameter names to values");
        n->malformed = true;
    }
    check_node_keys(p, n);
    check_node_inputs(p, n);
    return n;
}

static void parse_nodes(rf_pipeline *p, json_t *nodes)
{
    size_t i;
    json_t *obj;
    json_array_foreach(nodes, i, obj)
    {
        rf_node *n = parse_node(p, obj, i);
        n->index = p->nodes->len;
        g_ptr_array_add(p->nodes, n);
        if (!n->id)
            continue;
        rf_node *first = g_hash_table_lookup(p->by_id, n->id);
        if (first) {
            LOAD_ERR(p, n->id, n->pointer, "duplicate node id (first used at %s)", first->pointer);
            n->malformed = true;
        } else
            g_hash_table_insert(p->by_id, n->id, n);
    }
}

static void check_header(rf_pipeline *p)
{
    json_t *r = p->root;
    json_t *format = json_object_get(r, "format"), *version = json_object_get(r, "version");
    if (!json_is_string(format) || strcmp(json_string_value(format), RF_PIPELINE_FORMAT) != 0)
        LOAD_ERR(p, NULL, "/format", "expected \"format\": \"%s\"", RF_PIPELINE_FORMAT);
    if (!json_is_integer(version))
        LOAD_ERR(p, NULL, "/version", "expected \"version\": %d", RF_PIPELINE_VERSION);
    else if (json_integer_value(version) != RF_PIPELINE_VERSION)
        LOAD_ERR(p, NULL, "/version",
                 "pipeline format version %" JSON_INTEGER_FORMAT
                 " is not supported: this rigflow reads version %d",
                 json_integer_value(version), RF_PIPELINE_VERSION);
    const char *key;
    json_t *v;
    json_object_foreach(r, key, v)
    {
        if (strcmp(key, "format") && strcmp(key, "version") && strcmp(key, "nodes") &&
            strcmp(key, "description")) {
            g_autofree char *ptr = g_strdup_printf("/%s", key);
            LOAD_ERR(p, NULL, ptr,
                     "unknown key '%s' (expected format, version, description, nodes)", key);
        }
    }
}

static rf_pipeline *pipeline_from_json(json_t *root, const char *name, const char *dir)
{
    rf_pipeline *p = g_new0(rf_pipeline, 1);
    p->name = g_strdup(name);
    /* absolute, so that paths resolve the same whatever the current folder is later */
    p->dir = g_canonicalize_filename(dir ? dir : ".", NULL);
    p->root = root;
    p->nodes = g_ptr_array_new_with_free_func(node_free);
    p->by_id = g_hash_table_new(g_str_hash, g_str_equal);
    p->overrides = g_hash_table_new_full(g_str_hash, g_str_equal, g_free, g_free);
    p->load_diags = rf_diags_new();
    if (!json_is_object(root)) {
        LOAD_ERR(p, NULL, "", "expected a JSON object with format, version and nodes");
        return p;
    }
    check_header(p);
    json_t *nodes = json_object_get(root, "nodes");
    if (!json_is_array(nodes) || json_array_size(nodes) == 0)
        LOAD_ERR(p, NULL, "/nodes", "expected \"nodes\": a non-empty list of node objects");
    else
        parse_nodes(p, nodes);
    return p;
}

rf_pipeline *rf_pipeline_load_string(const char *text, const char *name, const char *dir,
                                     GPtrArray *diags)
{
    json_error_t err;
    json_t *root = json_loads(text, JSON_REJECT_DUPLICATES, &err);
    if (!root) {
        rf_diags_add(diags, name, err.line, err.column, NULL, NULL, "JSON syntax error: %s",
                     err.text);
        return NULL;
    }
    return pipeline_from_json(root, name, dir);
}

rf_pipeline *rf_pipeline_load(const char *path, GPtrArray *diags)
{
    g_autofree char *text = NULL;
    g_autoptr(GError) error = NULL;
    if (!g_file_get_contents(path, &text, NULL, &error)) {
        rf_diags_add(diags, path, 0, 0, NULL, NULL, "cannot read pipeline: %s", error->message);
        return NULL;
    }
    g_autofree char *dir = g_path_get_dirname(path);
    return rf_pipeline_load_string(text, path, dir, diags);
}

bool rf_pipeline_override(rf_pipeline *p, const char *assignment, GPtrArray *diags)
{
    const char *eq = strchr(assignment, '='), *dot = strchr(assignment, '.');
    if (!eq || !dot || dot > eq || dot == assignment || eq == dot + 1) {
        rf_diags_add(diags, NULL, 0, 0, NULL, NULL, "override '%s': expected node.param=value",
                     assignment);
        return false;
    }
    g_autofree char *node_id = g_strndup(assignment, (gsize)(dot - assignment));
    g_autofree char *param = g_strndup(dot + 1, (gsize)(eq - dot - 1));
    rf_node *n = g_hash_table_lookup(p->by_id, node_id);
    if (!n || !json_is_object(n->json)) {
        rf_diags_add(diags, p->name, 0, 0, NULL, NULL,
                     "override '%s': the pipeline has no node '%s'", assignment, node_id);
        return false;
    }
    json_t *params = json_object_get(n->json, "params");
    if (!params) {
        params = json_object();
        json_object_set_new(n->json, "params", params);
    }
    if (!json_is_object(params))
        return false; /* already reported as a structural error */
    /* Kept as text: validation types it by the parameter's declaration. JSON holds only UTF-8:
     * a name or value that is not must be refused here, or validation would read the file's
     * value (a number, say) as this override's text. */
    if (json_object_set_new(params, param, json_string(eq + 1)) != 0) {
        rf_diags_add(diags, p->name, 0, 0, NULL, NULL,
                     "override '%s': expected UTF-8 text in the parameter name and value",
                     assignment);
        return false;
    }
    /* A path given on the command line is relative to where the user is, not to the pipeline. */
    g_hash_table_insert(p->overrides, g_strdup_printf("%s.%s", node_id, param),
                        g_get_current_dir());
    return true;
}

static int find_port(const rf_port_desc *ports, uint32_t count, const char *name)
{
    for (uint32_t i = 0; i < count; i++)
        if (strcmp(ports[i].name, name) == 0)
            return (int)i;
    return -1;
}

int rf_desc_param_index(const rf_node_desc *d, const char *name)
{
    for (uint32_t i = 0; i < d->param_count; i++)
        if (strcmp(d->params[i].name, name) == 0)
            return (int)i;
    return -1;
}
int rf_desc_input_index(const rf_node_desc *d, const char *name)
{
    return find_port(d->inputs, d->input_count, name);
}
int rf_desc_output_index(const rf_node_desc *d, const char *name)
{
    return find_port(d->outputs, d->output_count, name);
}

const void *rf_pipeline_result(const rf_pipeline *p, const char *node, const char *port)
{
    rf_node *n = g_hash_table_lookup(p->by_id, node);
    if (!n || !n->desc || !n->outputs)
        return NULL;
    int i = rf_desc_output_index(n->desc, port);
    return i < 0 ? NULL : n->outputs[i].data;
}
