/* The rf_host table: the services a plugin reaches while one of its nodes is created or run. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "pipeline-internal.h"

static const char *const level_names[] = {"error", "warning", "info", "debug"};

/* Errors always; debug lines with RIGFLOW_DEBUG; warnings and information unless --quiet, which
 * promises errors only (doc/cli.md). */
static bool level_shown(rf_node *node, rf_log_level level)
{
    if (level == RF_LOG_ERROR)
        return true;
    if (level == RF_LOG_DEBUG)
        return g_getenv("RIGFLOW_DEBUG") != NULL;
    return !(node && node->pipeline->opts && node->pipeline->opts->quiet);
}

static void host_log(rf_node *node, rf_log_level level, const char *fmt, ...)
{
    if (level > RF_LOG_DEBUG)
        level = RF_LOG_DEBUG;
    if (!level_shown(node, level))
        return;
    va_list ap;
    va_start(ap, fmt);
    g_autofree char *raw = g_strdup_vprintf(fmt, ap);
    va_end(ap);
    g_autofree char *msg = rf_printable(raw); /* plugins quote bytes from files */
    if (node && node->held) { /* printed in the run's order, after the nodes before it */
        g_autofree char *line =
            g_strdup_printf("rigflow: node '%s': %s: %s\n", node->id, level_names[level], msg);
        rf_held_log(node->held, line);
    } else if (node)
        fprintf(stderr, "rigflow: node '%s': %s: %s\n", node->id, level_names[level], msg);
    else
        fprintf(stderr, "rigflow: %s: %s\n", level_names[level], msg);
}

static FILE *host_out(rf_node *node)
{
    if (node && node->held)
        return rf_held_out(node->held);
    return node && node->pipeline->opts && node->pipeline->opts->out ? node->pipeline->opts->out
                                                                     : stdout;
}

static void host_error(rf_node *node, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    g_free(node->error);
    node->error = g_strdup_vprintf(fmt, ap);
    va_end(ap);
}

static void host_progress(rf_node *node, double fraction)
{
    const rf_run_options *o = node->pipeline->opts;
    if (!o || !o->progress || o->quiet || node->held) /* a line of one node on the terminal */
        return;
    gint64 now = g_get_monotonic_time();
    if (now - node->last_progress < 100000 && fraction < 1.0) /* redraw at most 10 times a second */
        return;
    node->last_progress = now;
    fraction = fraction < 0 ? 0 : fraction > 1 ? 1 : fraction;
    fprintf(stderr, "\r%s: %3.0f%%\033[K", node->id, fraction * 100.0);
    if (fraction >= 1.0)
        fputs("\r\033[K", stderr);
    fflush(stderr);
}

static bool host_cancelled(rf_node *node)
{
    const rf_run_options *o = node->pipeline->opts;
    return o && o->cancel_flag && *o->cancel_flag;
}

static const char *host_node_id(rf_node *node)
{
    return node->id;
}

/* The value of a declared parameter when its declared type is one `getter` reads, or NULL
 * (logged) for a name or type the node never declared: a plugin bug, not a user error. */
static const rf_pvalue *param_value(rf_node *node, const char *name, const char *getter,
                                    bool (*reads)(uint32_t type))
{
    int i = rf_desc_param_index(node->desc, name);
    if (i < 0 || !node->params) {
        host_log(node, RF_LOG_ERROR, "plugin bug: node type %s asked for undeclared parameter '%s'",
                 node->type, name);
        return NULL;
    }
    const rf_pvalue *v = &node->params[i];
    if (!reads(v->type)) {
        host_log(node, RF_LOG_ERROR,
                 "plugin bug: %s parameter '%s' of node type %s read with %s; it reads 0",
                 rf_param_type_name(v->type), name, node->type, getter);
        return NULL;
    }
    return v;
}

static bool is_bool(uint32_t t)
{
    return t == RF_PARAM_BOOL;
}
static bool is_int(uint32_t t)
{
    return t == RF_PARAM_INT;
}
/* An integer parameter reads as a float too: the conversion is exact enough and loses no sign. */
static bool is_number(uint32_t t)
{
    return t == RF_PARAM_INT || t == RF_PARAM_FLOAT;
}
static bool is_text(uint32_t t)
{
    return t >= RF_PARAM_STRING && t <= RF_PARAM_OUTPUT_PATH;
}
static bool is_output(uint32_t t)
{
    return t == RF_PARAM_OUTPUT_PATH;
}

static bool host_param_bool(rf_node *node, const char *name)
{
    const rf_pvalue *v = param_value(node, name, "param_bool", is_bool);
    return v ? v->b : false;
}
static int64_t host_param_int(rf_node *node, const char *name)
{
    const rf_pvalue *v = param_value(node, name, "param_int", is_int);
    return v ? v->i : 0;
}
static double host_param_float(rf_node *node, const char *name)
{
    const rf_pvalue *v = param_value(node, name, "param_float", is_number);
    if (!v)
        return 0;
    return v->type == RF_PARAM_INT ? (double)v->i : v->f;
}
static const char *host_param_string(rf_node *node, const char *name)
{
    const rf_pvalue *v = param_value(node, name, "param_string", is_text);
    return v && v->s ? v->s : "";
}
static const char *host_param_output_target(rf_node *node, const char *name)
{
    const rf_pvalue *v = param_value(node, name, "param_output_target", is_output);
    return v && v->target ? v->target : "";
}

static GPtrArray *input_conns(rf_node *node, const char *port)
{
    int i = rf_desc_input_index(node->desc, port);
    if (i < 0) {
        host_log(node, RF_LOG_ERROR, "plugin bug: node type %s asked for undeclared input '%s'",
                 node->type, port);
        return NULL;
    }
    return node->inputs[i];
}

static uint32_t host_input_count(rf_node *node, const char *port)
{
    GPtrArray *c = input_conns(node, port);
    return c ? c->len : 0;
}

static const void *host_input(rf_node *node, const char *port, uint32_t index)
{
    GPtrArray *c = input_conns(node, port);
    if (!c || index >= c->len)
        return NULL;
    rf_conn *conn = g_ptr_array_index(c, index);
    return conn->src->outputs[conn->src_port].data;
}

/* The data model's structs by port type, with their oldest layout. */
static const struct {
    const char *type;
    size_t size, min;
} model_layouts[] = {
    {RF_TYPE_SKELETON, sizeof(rf_skeleton), RF_SKELETON_SIZE_1_0},
    {RF_TYPE_ANIMATION, sizeof(rf_animation), RF_ANIMATION_SIZE_1_0},
    {RF_TYPE_MESH, sizeof(rf_mesh), RF_MESH_SIZE_1_0},
    {RF_TYPE_MAPPING, sizeof(rf_mapping), RF_MAPPING_SIZE_1_0},
    {RF_TYPE_CLIPS, sizeof(rf_clip_list), RF_CLIP_LIST_SIZE_1_1},
};

/* What consumers of a value of port type `type` read: the value itself, or, when a plugin of an
 * older minor made it smaller than this build's struct, a copy of its head with the appended
 * fields zero (they still point into the original, which the producer's destroy frees). NULL
 * for a value smaller than its type's oldest layout. */
static void *model_view(rf_node *node, const char *port, const char *type, void *data)
{
    for (size_t k = 0; data && k < G_N_ELEMENTS(model_layouts); k++) {
        if (strcmp(type, model_layouts[k].type) != 0)
            continue;
        uint32_t size;
        memcpy(&size, data, sizeof size); /* every model struct starts with its size */
        if (size < model_layouts[k].min) {
            host_log(node, RF_LOG_ERROR,
                     "plugin bug: output '%s' (%s) declares size %u, below "
                     "the %zu bytes of its oldest layout",
                     port, type, size, model_layouts[k].min);
            return NULL;
        }
        if (size >= model_layouts[k].size)
            return data;
        void *view = g_malloc0(model_layouts[k].size);
        memcpy(view, data, size);
        uint32_t ours = (uint32_t)model_layouts[k].size; /* the copy is a struct of this build */
        memcpy(view, &ours, sizeof ours);
        return view;
    }
    return data;
}

void rf_output_clear(rf_output *o)
{
    if (o->data && o->data != o->owned)
        g_free(o->data);
    if (o->owned && o->destroy)
        o->destroy(o->owned);
    *o = (rf_output){0};
}

static bool host_set_output(rf_node *node, const char *port, void *data, rf_destroy_fn destroy)
{
    int i = rf_desc_output_index(node->desc, port);
    if (i < 0 || node->outputs[i].set) {
        host_log(node, RF_LOG_ERROR, "plugin bug: output '%s' is %s", port,
                 i < 0 ? "not declared" : "set twice");
        if (destroy && data)
            destroy(data);
        return false;
    }
    void *view = model_view(node, port, node->desc->outputs[i].type, data);
    if (data && !view) {
        if (destroy)
            destroy(data);
        return false;
    }
    node->outputs[i] = (rf_output){view, destroy, true, data};
    return true;
}

static const rf_host host_table = {
    .size = sizeof(rf_host),
    .abi = RF_ABI_VERSION_INIT,
    .log = host_log,
    .error = host_error,
    .progress = host_progress,
    .cancelled = host_cancelled,
    .node_id = host_node_id,
    .param_bool = host_param_bool,
    .param_int = host_param_int,
    .param_float = host_param_float,
    .param_string = host_param_string,
    .param_output_target = host_param_output_target,
    .input_count = host_input_count,
    .input = host_input,
    .set_output = host_set_output,
    .out = host_out,
};

const rf_host *rf_host_table(void)
{
    return &host_table;
}
