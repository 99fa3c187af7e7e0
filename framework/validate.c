/* Staged pipeline validation. Every stage reports all it finds, each problem with the node id and
 * JSON pointer and what was expected; a node that failed a stage is not checked by later ones, so
 * a missing plugin is reported once, not again as an unknown port and a type mismatch.
 *   structure (pipeline.c) -> node types -> params -> ports and edges -> required inputs
 *   -> cycles -> port types
 */
#include <errno.h>
#include <string.h>

#include "pipeline-internal.h"

#define ERR(n, ptr, ...) rf_diags_add(diags, (n)->pipeline->name, 0, 0, (n)->id, (ptr), __VA_ARGS__)

static void conn_free(gpointer data)
{
    rf_conn *c = data;
    g_free(c->node);
    g_free(c->port);
    g_free(c->pointer);
    g_free(c);
}

void rf_node_clear_bindings(rf_node *n)
{
    if (!n->desc)
        return;
    if (n->inputs)
        for (uint32_t i = 0; i < n->desc->input_count; i++)
            g_ptr_array_unref(n->inputs[i]);
    g_clear_pointer(&n->inputs, g_free);
    if (n->params)
        for (uint32_t i = 0; i < n->desc->param_count; i++) {
            g_free(n->params[i].s);
            g_free(n->params[i].target);
        }
    g_clear_pointer(&n->params, g_free);
}

/* ---- node types ---- */

static void stage_types(rf_pipeline *p, const rf_registry *reg, GPtrArray *diags)
{
    for (guint i = 0; i < p->nodes->len; i++) {
        rf_node *n = g_ptr_array_index(p->nodes, i);
        rf_node_clear_bindings(n);
        n->desc = NULL;
        if (n->bad || !n->type)
            continue;
        n->desc = rf_registry_find(reg, n->type, &n->plugin);
        if (!n->desc) {
            g_autofree char *ptr = g_strdup_printf("%s/type", n->pointer);
            ERR(n, ptr, "plugin not installed: %s (`rigflow plugins` lists the node types found)",
                n->type);
            n->bad = true;
            continue;
        }
        n->inputs = g_new0(GPtrArray *, n->desc->input_count ? n->desc->input_count : 1);
        for (uint32_t k = 0; k < n->desc->input_count; k++)
            n->inputs[k] = g_ptr_array_new_with_free_func(conn_free);
        n->params = g_new0(rf_pvalue, n->desc->param_count ? n->desc->param_count : 1);
    }
}

/* ---- params ---- */

static char *param_names(const rf_node_desc *d)
{
    GString *s = g_string_new(NULL);
    for (uint32_t i = 0; i < d->param_count; i++)
        g_string_append_printf(s, "%s%s", i ? ", " : "", d->params[i].name);
    return g_string_free(s, FALSE);
}

static bool in_choices(const char *choices, const char *v)
{
    g_auto(GStrv) list = g_strsplit(choices, "|", -1);
    return g_strv_contains((const char *const *)list, v);
}

/* Types a value given on the command line as text by the parameter's declaration. Returns a new
 * reference, or NULL when the text does not read as that type. */
static json_t *type_override(const rf_param_desc *d, const char *text)
{
    char *end = NULL;
    switch (d->type) {
    case RF_PARAM_BOOL:
        if (!strcmp(text, "true") || !strcmp(text, "1"))
            return json_true();
        if (!strcmp(text, "false") || !strcmp(text, "0"))
            return json_false();
        return NULL;
    case RF_PARAM_INT: {
        errno = 0;
        gint64 v = g_ascii_strtoll(text, &end, 10);
        return *text && !*end && !errno ? json_integer(v) : NULL;
    }
    case RF_PARAM_FLOAT: {
        double v = g_ascii_strtod(text, &end);
        return *text && !*end ? json_real(v) : NULL;
    }
    default:
        return json_string(text);
    }
}

static bool is_path(rf_param_type t)
{
    return t == RF_PARAM_INPUT_PATH || t == RF_PARAM_OUTPUT_PATH;
}

/* A path resolved against `base` unless absolute. */
static char *resolve(const char *base, const char *path)
{
    if (!*path || g_path_is_absolute(path))
        return g_strdup(path);
    return g_canonicalize_filename(path, base);
}

static bool check_range(rf_node *n, const rf_param_desc *d, double v, const char *ptr,
                        GPtrArray *diags)
{
    if (!(d->flags & RF_PARAM_HAS_RANGE) || (v >= d->min && v <= d->max))
        return true;
    ERR(n, ptr, "parameter '%s' = %g is out of range: expected %s in [%g, %g]", d->name, v,
        rf_param_type_name(d->type), d->min, d->max);
    return false;
}

/* Checks one given value against its declaration and stores it. */
static bool bind_param(rf_node *n, int idx, json_t *v, const char *base, const char *ptr,
                       GPtrArray *diags)
{
    const rf_param_desc *d = &n->desc->params[idx];
    rf_pvalue *pv = &n->params[idx];
    bool ok = (d->type == RF_PARAM_BOOL && json_is_boolean(v)) ||
              (d->type == RF_PARAM_INT && json_is_integer(v)) ||
              (d->type == RF_PARAM_FLOAT && json_is_number(v)) ||
              (d->type >= RF_PARAM_STRING && json_is_string(v));
    if (!ok) {
        ERR(n, ptr, "parameter '%s' expects %s%s", d->name, d->type == RF_PARAM_INT ? "an " : "a ",
            rf_param_type_name(d->type));
        return false;
    }
    if (d->type == RF_PARAM_BOOL)
        pv->b = json_is_true(v);
    else if (d->type == RF_PARAM_INT) {
        pv->i = json_integer_value(v);
        return check_range(n, d, (double)pv->i, ptr, diags);
    } else if (d->type == RF_PARAM_FLOAT) {
        pv->f = json_number_value(v);
        return check_range(n, d, pv->f, ptr, diags);
    } else if (d->type == RF_PARAM_ENUM && !in_choices(d->choices, json_string_value(v))) {
        g_auto(GStrv) choices = g_strsplit(d->choices, "|", -1);
        g_autofree char *list = g_strjoinv(", ", choices);
        ERR(n, ptr, "parameter '%s' = \"%s\": expected one of %s", d->name, json_string_value(v),
            list);
        return false;
    } else if (is_path(d->type)) {
        char *resolved = resolve(base, json_string_value(v));
        g_free(d->type == RF_PARAM_OUTPUT_PATH ? pv->target : pv->s);
        *(d->type == RF_PARAM_OUTPUT_PATH ? &pv->target : &pv->s) = resolved;
    } else {
        g_free(pv->s);
        pv->s = g_strdup(json_string_value(v));
    }
    return true;
}

static void bind_default(rf_node *n, uint32_t idx, const char *base)
{
    const rf_param_desc *d = &n->desc->params[idx];
    rf_pvalue *pv = &n->params[idx];
    pv->type = d->type;
    pv->b = d->default_number != 0;
    pv->i = (int64_t)d->default_number;
    pv->f = d->default_number;
    const char *s = d->default_string ? d->default_string : "";
    if (d->type == RF_PARAM_OUTPUT_PATH)
        pv->target = resolve(base, s);
    else
        pv->s = is_path(d->type) ? resolve(base, s) : g_strdup(s);
}

static bool param_given(rf_node *n, uint32_t idx)
{
    json_t *params = json_object_get(n->json, "params");
    json_t *v = params ? json_object_get(params, n->desc->params[idx].name) : NULL;
    return v &&
           !(json_is_string(v) && !*json_string_value(v) && is_path(n->desc->params[idx].type));
}

static bool node_params(rf_node *n, GPtrArray *diags)
{
    bool ok = true;
    for (uint32_t i = 0; i < n->desc->param_count; i++) {
        bind_default(n, i, n->pipeline->dir);
        if ((n->desc->params[i].flags & RF_PARAM_REQUIRED) && !param_given(n, i)) {
            ERR(n, n->pointer, "missing required parameter '%s' (%s: %s)", n->desc->params[i].name,
                rf_param_type_name(n->desc->params[i].type),
                n->desc->params[i].doc ? n->desc->params[i].doc : "");
            ok = false;
        }
    }
    json_t *params = json_object_get(n->json, "params");
    const char *name;
    json_t *v;
    json_object_foreach(params, name, v)
    {
        g_autofree char *ptr = g_strdup_printf("%s/params/%s", n->pointer, name);
        int idx = rf_desc_param_index(n->desc, name);
        if (idx < 0) {
            g_autofree char *names = param_names(n->desc);
            ERR(n, ptr, "unknown parameter '%s': node type %s has %s%s", name, n->type,
                *names ? "parameters " : "no parameters", names);
            ok = false;
            continue;
        }
        g_autofree char *key = g_strdup_printf("%s.%s", n->id, name);
        const char *cwd = g_hash_table_lookup(n->pipeline->overrides, key);
        json_t *typed =
            cwd ? type_override(&n->desc->params[idx], json_string_value(v)) : json_incref(v);
        if (!typed) {
            ERR(n, ptr, "parameter '%s' = \"%s\": expected %s", name, json_string_value(v),
                rf_param_type_name(n->desc->params[idx].type));
            ok = false;
            continue;
        }
        ok &= bind_param(n, idx, typed, cwd ? cwd : n->pipeline->dir, ptr, diags);
        json_decref(typed);
    }
    return ok;
}

static void stage_params(rf_pipeline *p, GPtrArray *diags)
{
    for (guint i = 0; i < p->nodes->len; i++) {
        rf_node *n = g_ptr_array_index(p->nodes, i);
        if (n->desc && !n->bad && !node_params(n, diags))
            n->bad = true;
    }
}

/* Two output parameters naming one file: the second rename into place would silently replace
 * the first's output. Paths compare after lexical canonicalisation (a/./b.glb is a/b.glb). */
static void stage_outputs(rf_pipeline *p, GPtrArray *diags)
{
    g_autoptr(GHashTable) seen = g_hash_table_new_full(g_str_hash, g_str_equal, g_free, g_free);
    for (guint i = 0; i < p->nodes->len; i++) {
        rf_node *n = g_ptr_array_index(p->nodes, i);
        for (uint32_t k = 0; n->desc && !n->bad && k < n->desc->param_count; k++) {
            const char *t = n->params[k].target;
            if (n->desc->params[k].type != RF_PARAM_OUTPUT_PATH || !t || !*t)
                continue;
            char *key = g_canonicalize_filename(t, NULL);
            const char *first = g_hash_table_lookup(seen, key);
            if (first) {
                ERR(n, n->pointer,
                    "parameter '%s' writes %s, as %s does: one output would "
                    "replace the other",
                    n->desc->params[k].name, t, first);
                g_free(key);
            } else {
                g_hash_table_insert(
                    seen, key,
                    g_strdup_printf("node '%s' parameter '%s'", n->id, n->desc->params[k].name));
            }
        }
    }
}

/* ---- ports and edges ---- */

static char *port_list(const rf_port_desc *ports, uint32_t count)
{
    if (!count)
        return g_strdup("none");
    GString *s = g_string_new(NULL);
    for (uint32_t i = 0; i < count; i++)
        g_string_append_printf(s, "%s%s (%s)", i ? ", " : "", ports[i].name, ports[i].type);
    return g_string_free(s, FALSE);
}

/* Resolves one "node.port" edge. Returns false when it reported a problem. */
static bool bind_edge(rf_node *n, uint32_t port, const char *edge, const char *ptr,
                      GPtrArray *diags)
{
    const char *dot = strchr(edge, '.');
    if (!dot || dot == edge || !dot[1]) {
        ERR(n, ptr, "edge \"%s\": expected \"node.port\"", edge);
        return false;
    }
    g_autofree char *src_id = g_strndup(edge, (gsize)(dot - edge));
    rf_node *src = g_hash_table_lookup(n->pipeline->by_id, src_id);
    if (!src) {
        ERR(n, ptr, "input '%s' refers to node '%s', which this pipeline does not have",
            n->desc->inputs[port].name, src_id);
        return false;
    }
    if (!src->desc)
        return true; /* the upstream node is already reported */
    int out = rf_desc_output_index(src->desc, dot + 1);
    if (out < 0) {
        g_autofree char *outs = port_list(src->desc->outputs, src->desc->output_count);
        ERR(n, ptr, "node '%s' (%s) has no output '%s'; its outputs are: %s", src_id, src->type,
            dot + 1, outs);
        return false;
    }
    rf_conn *c = g_new0(rf_conn, 1);
    c->node = g_strdup(src_id);
    c->port = g_strdup(dot + 1);
    c->src = src;
    c->src_port = (uint32_t)out;
    c->pointer = g_strdup(ptr);
    g_ptr_array_add(n->inputs[port], c);
    return true;
}

static bool bind_port(rf_node *n, const char *name, json_t *v, GPtrArray *diags)
{
    g_autofree char *ptr = g_strdup_printf("%s/inputs/%s", n->pointer, name);
    int port = rf_desc_input_index(n->desc, name);
    if (port < 0) {
        g_autofree char *ins = port_list(n->desc->inputs, n->desc->input_count);
        ERR(n, ptr, "unknown input port '%s': node type %s has inputs: %s", name, n->type, ins);
        return false;
    }
    if (json_is_array(v) && json_array_size(v) > 1 &&
        !(n->desc->inputs[port].flags & RF_PORT_MULTIPLE)) {
        ERR(n, ptr, "input '%s' takes one connection, not %zu", name, json_array_size(v));
        return false;
    }
    bool ok = true;
    if (json_is_string(v))
        return bind_edge(n, (uint32_t)port, json_string_value(v), ptr, diags);
    size_t i;
    json_t *e;
    json_array_foreach(v, i, e)
    {
        g_autofree char *eptr = g_strdup_printf("%s/%zu", ptr, i);
        ok &= bind_edge(n, (uint32_t)port, json_string_value(e), eptr, diags);
    }
    return ok;
}

static bool node_required(rf_node *n, GPtrArray *diags)
{
    bool ok = true;
    for (uint32_t i = 0; i < n->desc->input_count; i++) {
        const rf_port_desc *in = &n->desc->inputs[i];
        json_t *inputs = json_object_get(n->json, "inputs");
        if ((in->flags & RF_PORT_OPTIONAL) || (inputs && json_object_get(inputs, in->name)))
            continue;
        ERR(n, n->pointer, "missing required input '%s' (%s)", in->name, in->type);
        ok = false;
    }
    return ok;
}

static void stage_ports(rf_pipeline *p, GPtrArray *diags)
{
    for (guint i = 0; i < p->nodes->len; i++) {
        rf_node *n = g_ptr_array_index(p->nodes, i);
        if (!n->desc || !n->inputs)
            continue;
        bool ok = true;
        const char *name;
        json_t *v;
        json_t *inputs = json_object_get(n->json, "inputs");
        json_object_foreach(inputs, name, v) ok &= bind_port(n, name, v, diags);
        ok &= node_required(n, diags);
        if (!ok)
            n->bad = true;
    }
}

/* ---- cycles and order ---- */

/* Reports the cycle that closes at `cur`, the nodes from pos[cur] to the end of `path`. */
static void report_path(rf_pipeline *p, GArray *path, const gint *pos, guint cur, bool *reported,
                        GPtrArray *diags)
{
    GString *names = g_string_new(NULL);
    for (guint i = path->len; i-- > (guint)pos[cur];) { /* appended: prepending is quadratic */
        guint k = g_array_index(path, guint, i);
        reported[k] = true;
        g_string_append(names, ((rf_node *)g_ptr_array_index(p->nodes, k))->id);
        g_string_append(names, " <- ");
    }
    rf_node *first = g_ptr_array_index(p->nodes, cur);
    g_string_append(names, first->id);
    rf_diags_add(diags, p->name, 0, 0, first->id, first->pointer,
                 "cycle: %s (each node needs the next one's output)", names->str);
    g_string_free(names, TRUE);
}

/* Walks back from a node left over by the topological sort, which must lead into a cycle, and
 * reports that cycle unless it was reported already. `pos` (-1 for every node) is scratch space,
 * handed back as it came. */
static void report_cycle(rf_pipeline *p, guint start, guint *pending, bool *reported, gint *pos,
                         GPtrArray *diags)
{
    g_autoptr(GArray) path = g_array_new(FALSE, FALSE, sizeof(guint));
    guint cur = start;
    while (pos[cur] < 0 && !reported[cur]) {
        pos[cur] = (gint)path->len;
        g_array_append_val(path, cur);
        rf_node *n = g_ptr_array_index(p->nodes, cur);
        guint next = cur;
        for (uint32_t k = 0; k < n->desc->input_count && next == cur; k++)
            for (guint e = 0; e < n->inputs[k]->len; e++) {
                rf_conn *c = g_ptr_array_index(n->inputs[k], e);
                guint s = c->src->index;
                if (pending[s]) {
                    next = s;
                    break;
                }
            }
        cur = next;
    }
    if (!reported[cur])
        report_path(p, path, pos, cur, reported, diags);
    for (guint i = 0; i < path->len; i++)
        pos[g_array_index(path, guint, i)] = -1;
}

/* The nodes reading each node's outputs, one entry per edge, in node order: users[first[i]] to
 * users[first[i + 1]] read node i. Built once so that the sort is linear in nodes and edges
 * instead of scanning every edge for each node done. */
static guint *edge_users(rf_pipeline *p, guint **first_out)
{
    guint count = p->nodes->len;
    guint *first = g_new0(guint, count + 1);
    for (guint i = 0; i < count; i++) {
        rf_node *n = g_ptr_array_index(p->nodes, i);
        for (uint32_t k = 0; n->inputs && k < n->desc->input_count; k++)
            for (guint e = 0; e < n->inputs[k]->len; e++)
                first[((rf_conn *)g_ptr_array_index(n->inputs[k], e))->src->index + 1]++;
    }
    for (guint i = 0; i < count; i++)
        first[i + 1] += first[i];
    g_autofree guint *fill = g_memdup2(first, (count + 1) * sizeof *first);
    guint *users = g_new(guint, first[count] ? first[count] : 1);
    for (guint i = 0; i < count; i++) {
        rf_node *n = g_ptr_array_index(p->nodes, i);
        for (uint32_t k = 0; n->inputs && k < n->desc->input_count; k++)
            for (guint e = 0; e < n->inputs[k]->len; e++)
                users[fill[((rf_conn *)g_ptr_array_index(n->inputs[k], e))->src->index]++] = i;
    }
    *first_out = first;
    return users;
}

/* Kahn's algorithm over the edges; what is left over lies on or behind a cycle. */
static void stage_order(rf_pipeline *p, GPtrArray *diags)
{
    guint count = p->nodes->len;
    g_autofree guint *pending = g_new0(guint, count); /* unresolved inputs per node */
    g_autofree bool *reported = g_new0(bool, count);
    for (guint i = 0; i < count; i++) {
        rf_node *n = g_ptr_array_index(p->nodes, i);
        for (uint32_t k = 0; n->inputs && k < n->desc->input_count; k++)
            pending[i] += n->inputs[k]->len;
    }
    g_autofree guint *first = NULL;
    g_autofree guint *users = edge_users(p, &first);
    p->order = g_array_new(FALSE, FALSE, sizeof(guint));
    for (guint i = 0; i < count; i++)
        if (!pending[i])
            g_array_append_val(p->order, i);
    for (guint head = 0; head < p->order->len; head++) {
        guint done = g_array_index(p->order, guint, head);
        for (guint u = first[done]; u < first[done + 1]; u++)
            if (--pending[users[u]] == 0)
                g_array_append_val(p->order, users[u]);
    }
    g_autofree gint *pos = g_new(gint, count ? count : 1);
    for (guint i = 0; i < count; i++)
        pos[i] = -1;
    for (guint i = 0; i < count; i++)
        if (pending[i] && !reported[i])
            report_cycle(p, i, pending, reported, pos, diags);
}

/* ---- port types ---- */

static void stage_port_types(rf_pipeline *p, GPtrArray *diags)
{
    for (guint i = 0; i < p->nodes->len; i++) {
        rf_node *n = g_ptr_array_index(p->nodes, i);
        for (uint32_t k = 0; n->inputs && k < n->desc->input_count; k++)
            for (guint e = 0; e < n->inputs[k]->len; e++) {
                rf_conn *c = g_ptr_array_index(n->inputs[k], e);
                const char *want = n->desc->inputs[k].type;
                const char *have = c->src->desc->outputs[c->src_port].type;
                if (strcmp(want, have) != 0)
                    ERR(n, c->pointer,
                        "input %s of node %s expects %s, but node %s's output %s is %s",
                        n->desc->inputs[k].name, n->id, want, c->node, c->port, have);
            }
    }
}

bool rf_pipeline_validate(rf_pipeline *p, const rf_registry *reg, GPtrArray *diags)
{
    guint before = diags->len;
    for (guint i = 0; i < p->load_diags->len; i++) {
        rf_diag *d = g_ptr_array_index(p->load_diags, i);
        rf_diags_add(diags, d->file, d->line, d->column, d->node, d->pointer, "%s", d->message);
    }
    for (guint i = 0; i < p->nodes->len; i++) { /* a re-validation starts from the load's verdict */
        rf_node *n = g_ptr_array_index(p->nodes, i);
        n->bad = n->malformed;
    }
    if (p->order)
        g_array_free(p->order, TRUE);
    p->order = NULL;
    stage_types(p, reg, diags);
    stage_params(p, diags);
    stage_outputs(p, diags);
    stage_ports(p, diags);
    stage_order(p, diags);
    stage_port_types(p, diags);
    p->valid = diags->len == before;
    return p->valid;
}
