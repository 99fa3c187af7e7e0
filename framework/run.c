/* Running a validated pipeline: create every node (per-clip set-up) so parameter problems surface
 * before long work, process them in dependency order, and only then move the output files into
 * place. Each OUTPUT_PATH is written by its node to a temporary file in the target's folder; a
 * failed or interrupted run removes them all, so it never leaves a half-written file behind. */
#include <errno.h>
#include <fcntl.h>
#include <glib/gstdio.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "pipeline-internal.h"

#define RUN_ERR(n, ...) rf_diags_add(diags, (n)->pipeline->name, 0, 0, (n)->id, NULL, __VA_ARGS__)

rf_node *rf_run_node_at(rf_pipeline *p, guint i)
{
    return g_ptr_array_index(p->nodes, g_array_index(p->order, guint, i));
}

static bool cancelled(const rf_pipeline *p)
{
    return p->opts && p->opts->cancel_flag && *p->opts->cancel_flag;
}

void rf_pipeline_reset_run(rf_pipeline *p)
{
    for (guint i = 0; i < p->nodes->len; i++) {
        rf_node *n = g_ptr_array_index(p->nodes, i);
        if (n->created && n->desc->destroy)
            n->desc->destroy(n->self);
        n->created = false;
        n->self = NULL;
        n->ran = n->ok = false;
        for (uint32_t k = 0; n->outputs && k < n->desc->output_count; k++)
            rf_output_clear(&n->outputs[k]);
        g_clear_pointer(&n->outputs, g_free);
        g_clear_pointer(&n->error, g_free);
    }
}

/* The temporary name keeps the target's extension, so that exporters which pick a format by
 * extension see the right one, and cuts the stem so that the name, 11 bytes longer than the
 * target's, stays within a file name's 255 bytes: a target of a long name could not be written
 * at all ("File name too long"). */
#define RF_TEMP_STEM_MAX 200
#define RF_TEMP_EXT_MAX 32

static const char *temp_ext(const char *base)
{
    const char *ext = strrchr(base, '.');
    return ext && strlen(ext) <= RF_TEMP_EXT_MAX ? ext : NULL;
}

char *rf_output_temp_prefix(const char *target)
{
    g_autofree char *base = g_path_get_basename(target);
    const char *ext = temp_ext(base);
    gsize stem = ext ? (gsize)(ext - base) : strlen(base);
    return g_strdup_printf(".%.*s.rf-", (int)MIN(stem, RF_TEMP_STEM_MAX), base);
}

/* A temporary file beside `target`, hidden, named as above. */
static char *make_temp(const char *target, GError **error)
{
    g_autofree char *dir = g_path_get_dirname(target);
    g_autofree char *base = g_path_get_basename(target);
    const char *ext = temp_ext(base);
    g_autofree char *prefix = rf_output_temp_prefix(target);
    char *tmpl = g_strdup_printf("%s/%sXXXXXX%s", dir, prefix, ext ? ext : "");
    int fd = g_mkstemp(tmpl);
    if (fd < 0) {
        int e = errno;
        g_set_error(error, G_FILE_ERROR, g_file_error_from_errno(e),
                    "cannot write in folder %s: %s", dir, g_strerror(e));
        g_free(tmpl);
        return NULL;
    }
    close(fd);
    return tmpl;
}

static bool prepare_param(rf_node *n, uint32_t i, GPtrArray *diags)
{
    const rf_param_desc *d = &n->desc->params[i];
    rf_pvalue *v = &n->params[i];
    if (d->type == RF_PARAM_INPUT_PATH && v->s && *v->s && g_access(v->s, R_OK) != 0) {
        RUN_ERR(n, "cannot read input file %s (parameter '%s'): %s", v->s, d->name,
                g_strerror(errno));
        return false;
    }
    if (d->type != RF_PARAM_OUTPUT_PATH || !v->target || !*v->target)
        return true;
    /* a folder cannot be replaced by a file: found at commit, it stopped the run only after all
     * the work, with the outputs committed before it already in place */
    if (g_file_test(v->target, G_FILE_TEST_IS_DIR)) {
        RUN_ERR(n, "cannot write %s (parameter '%s'): it is a folder; name a file", v->target,
                d->name);
        return false;
    }
    g_autoptr(GError) error = NULL;
    g_free(v->s);
    v->s = make_temp(v->target, &error);
    if (!v->s) {
        RUN_ERR(n, "cannot write %s (parameter '%s'): %s", v->target, d->name, error->message);
        return false;
    }
    g_ptr_array_add(n->pipeline->temp_files, g_strdup(v->s));
    return true;
}

static bool create_node(rf_node *n, GPtrArray *diags)
{
    n->outputs = g_new0(rf_output, n->desc->output_count ? n->desc->output_count : 1);
    for (uint32_t i = 0; i < n->desc->param_count; i++)
        if (!prepare_param(n, i, diags))
            return false;
    if (n->desc->create && !n->desc->create(rf_host_table(), n, &n->self)) {
        RUN_ERR(n, "%s could not start: %s", n->type, n->error ? n->error : "no reason given");
        return false;
    }
    n->created = true;
    return true;
}

/* ---- outputs to disk ---- */

/* The fsync of one finished output, begun on a thread of its own as soon as its node has
 * finished: the disk's journal commit (0.3-7 ms for a 3.2 MB GLB here) then runs beside the
 * nodes after it instead of after all of them. The rename into place still waits for it and for
 * the whole run to succeed. */
typedef struct rf_file_sync {
    char *path;      /* the temporary file */
    GThread *thread; /* NULL when no thread could start: commit syncs it itself */
    int err;         /* errno of open or fsync, 0 once flushed */
} rf_file_sync;

static gpointer file_sync_main(gpointer data)
{
    rf_file_sync *fs = data;
    int fd = g_open(fs->path, O_RDWR, 0);
    fs->err = fd < 0 || fsync(fd) != 0 ? errno : 0;
    if (fd >= 0)
        close(fd);
    return NULL;
}

/* Waits for the sync's thread (once) and frees it; the array's free function. */
static void file_sync_free(gpointer data)
{
    rf_file_sync *fs = data;
    if (fs->thread)
        g_thread_join(fs->thread);
    g_free(fs->path);
    g_free(fs);
}

/* Begins the fsync of every output file node n wrote. */
static void start_syncs(rf_node *n)
{
    rf_pipeline *p = n->pipeline;
    for (uint32_t k = 0; k < n->desc->param_count; k++) {
        const rf_pvalue *v = &n->params[k];
        if (n->desc->params[k].type != RF_PARAM_OUTPUT_PATH || !v->s)
            continue;
        if (!p->syncs)
            p->syncs = g_ptr_array_new_with_free_func(file_sync_free);
        rf_file_sync *fs = g_new0(rf_file_sync, 1);
        fs->path = g_strdup(v->s);
        fs->thread = g_thread_try_new("rf-fsync", file_sync_main, fs, NULL);
        g_ptr_array_add(p->syncs, fs);
    }
}

void rf_node_process(rf_node *n)
{
    gint64 t0 = g_get_monotonic_time();
    n->ok = n->desc->process(n->self, rf_host_table(), n);
    n->took = g_get_monotonic_time() - t0;
    n->ran = true;
}

bool rf_node_report(rf_node *n, GPtrArray *diags)
{
    if (!n->ran) { /* a node of a group the run was interrupted before */
        RUN_ERR(n, "interrupted before this node ran");
        return false;
    }
    const rf_run_options *o = n->pipeline->opts;
    if (o && o->profile)
        fprintf(stderr, "profile: node %s (%s): %.3f ms\n", n->id, n->type,
                (double)n->took / 1000.0);
    if (!n->ok) {
        RUN_ERR(n, "%s failed: %s", n->type,
                cancelled(n->pipeline) ? "interrupted"
                : n->error             ? n->error
                                       : "no reason given");
        return false;
    }
    for (uint32_t k = 0; k < n->desc->output_count; k++)
        if (!n->outputs[k].set) {
            RUN_ERR(n, "%s finished without producing its output '%s'", n->type,
                    n->desc->outputs[k].name);
            return false;
        }
    start_syncs(n);
    return true;
}

/* Flushes a finished output to disk (waiting for the fsync start_syncs began, or making it
 * here) and gives it the permissions a new file would have had: mkstemp made it 0600. */
static bool finish_file(rf_pipeline *p, const char *path, GError **error)
{
    rf_file_sync *fs = NULL;
    for (guint i = 0; p->syncs && !fs && i < p->syncs->len; i++)
        if (strcmp(((rf_file_sync *)g_ptr_array_index(p->syncs, i))->path, path) == 0)
            fs = g_ptr_array_index(p->syncs, i);
    int err;
    if (fs && fs->thread) {
        g_thread_join(fs->thread);
        fs->thread = NULL;
        err = fs->err;
    } else {
        rf_file_sync here = {.path = (char *)path};
        file_sync_main(&here);
        err = here.err;
    }
    if (err) {
        g_set_error(error, G_FILE_ERROR, g_file_error_from_errno(err), "%s", g_strerror(err));
        return false;
    }
    mode_t mask = umask(0);
    umask(mask);
    (void)g_chmod(path, 0666 & ~mask); /* as before: a file system without modes keeps its own */
    return true;
}

static bool commit_outputs(rf_pipeline *p, GPtrArray *diags)
{
    for (guint i = 0; i < p->order->len; i++) {
        rf_node *n = rf_run_node_at(p, i);
        for (uint32_t k = 0; k < n->desc->param_count; k++) {
            rf_pvalue *v = &n->params[k];
            if (n->desc->params[k].type != RF_PARAM_OUTPUT_PATH || !v->s)
                continue;
            g_autoptr(GError) error = NULL;
            if (!finish_file(p, v->s, &error) || g_rename(v->s, v->target) != 0) {
                RUN_ERR(n, "cannot write %s: %s", v->target,
                        error ? error->message : g_strerror(errno));
                return false;
            }
            guint idx;
            if (g_ptr_array_find_with_equal_func(p->temp_files, v->s, g_str_equal, &idx))
                g_ptr_array_remove_index(p->temp_files, idx);
        }
    }
    return true;
}

static void discard_outputs(rf_pipeline *p)
{
    if (p->syncs) /* every fsync thread joined before its file goes */
        g_ptr_array_set_size(p->syncs, 0);
    for (guint i = 0; i < p->temp_files->len; i++)
        g_unlink(g_ptr_array_index(p->temp_files, i));
    g_ptr_array_set_size(p->temp_files, 0);
}

static bool run_nodes(rf_pipeline *p, GPtrArray *diags)
{
    for (guint i = 0; i < p->order->len; i++)
        if (!create_node(rf_run_node_at(p, i), diags))
            return false;
    guint jobs = p->opts->jobs;
    for (guint i = 0; i < p->order->len;) {
        rf_node *n = rf_run_node_at(p, i);
        if (cancelled(p)) {
            RUN_ERR(n, "interrupted before this node ran");
            return false;
        }
        if (!rf_run_group(p, i, jobs, &i, diags))
            return false;
    }
    return true;
}

/* The caller's options into *out, this librigflow's struct: the fields its `size` covers (a
 * size of 0, a struct zero-initialised without rf_run_options_init, covers those through `out`),
 * the others at their defaults. A longer struct (a caller built against a newer librigflow) is
 * refused when a field this one does not know is set: a run must not ignore an option. */
static bool run_options_take(const rf_run_options *in, rf_run_options *out, const char *name,
                             GPtrArray *diags)
{
    *out = (rf_run_options){.size = sizeof *out};
    if (!in)
        return true;
    size_t n = in->size ? in->size : RF_RUN_OPTIONS_SIZE_1;
    const unsigned char *bytes = (const unsigned char *)in;
    for (size_t i = sizeof *out; i < n; i++)
        if (bytes[i]) {
            rf_diags_add(diags, name, 0, 0, NULL, NULL,
                         "the run's options set a field this librigflow does not know (the "
                         "host was built against a newer one: its options are %zu bytes, these "
                         "%zu)",
                         n, sizeof *out);
            return false;
        }
    memcpy(out, in, MIN(n, sizeof *out));
    out->size = sizeof *out;
    return true;
}

bool rf_pipeline_run(rf_pipeline *p, const rf_registry *reg, const rf_run_options *opts,
                     GPtrArray *diags)
{
    (void)reg; /* node types were bound at validation; kept for symmetry and future lookups */
    if (!p->valid || !p->order) {
        rf_diags_add(diags, p->name, 0, 0, NULL, NULL, "the pipeline must validate before it runs");
        return false;
    }
    if (!run_options_take(opts, &p->run_opts, p->name, diags))
        return false;
    rf_pipeline_reset_run(p);
    p->opts = &p->run_opts;
    if (!p->temp_files)
        p->temp_files = g_ptr_array_new_with_free_func(g_free);
    bool ok = run_nodes(p, diags) && !cancelled(p);
    gint64 t0 = g_get_monotonic_time();
    ok = ok && commit_outputs(p, diags);
    if (ok && p->opts->profile)
        fprintf(stderr, "profile: outputs flushed and moved into place: %.3f ms\n",
                (double)(g_get_monotonic_time() - t0) / 1000.0);
    if (!ok && cancelled(p))
        rf_diags_add(diags, p->name, 0, 0, NULL, NULL, "run interrupted: no output was written");
    discard_outputs(p);
    for (guint i = 0; i < p->nodes->len; i++) { /* node state is per run; outputs stay readable */
        rf_node *n = g_ptr_array_index(p->nodes, i);
        if (n->created && n->desc->destroy)
            n->desc->destroy(n->self);
        n->created = false;
        n->self = NULL;
    }
    return ok;
}

bool rf_node_type_try_create(const rf_registry *reg, const char *type, GPtrArray *diags)
{
    g_autofree char *text = g_strdup_printf(
        "{\"format\": \"%s\", \"version\": %d, \"nodes\": [{\"id\": \"n\", \"type\": \"%s\"}]}",
        RF_PIPELINE_FORMAT, RF_PIPELINE_VERSION, type);
    g_autoptr(GPtrArray) ignored = rf_diags_new(); /* unconnected inputs are expected here */
    rf_pipeline *p = rf_pipeline_load_string(text, type, ".", diags);
    if (!p)
        return false;
    rf_pipeline_validate(p, reg, ignored);
    rf_node *n = g_ptr_array_index(p->nodes, 0);
    bool ok = n->desc && n->params;
    if (!ok)
        rf_diags_add(diags, NULL, 0, 0, "n", NULL, "node type %s is not registered", type);
    p->temp_files = g_ptr_array_new_with_free_func(g_free);
    ok = ok && create_node(n, diags);
    discard_outputs(p);
    rf_pipeline_free(p); /* destroys what create made */
    return ok;
}

void rf_pipeline_foreach_output(const rf_pipeline *p, rf_output_param_fn fn, void *data)
{
    for (guint i = 0; p->valid && i < p->nodes->len; i++) {
        const rf_node *n = g_ptr_array_index(p->nodes, i);
        for (uint32_t k = 0; n->desc && n->params && k < n->desc->param_count; k++)
            if (n->desc->params[k].type == RF_PARAM_OUTPUT_PATH)
                fn(n->id, n->desc->params[k].name, n->params[k].target ? n->params[k].target : "",
                   data);
    }
}
