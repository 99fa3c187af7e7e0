/* rigflow batch: the command, and the plan it runs.
 *
 * The plan is the cross product of the --over globs (the first --over varies slowest). A job's
 * name joins one part per --over with '@': the input's path relative to the folder part of its
 * glob, without its extension, escaped so that the name is a plain file name ('/' becomes '+',
 * every byte outside [A-Za-z0-9._-] becomes %XX, a leading '.' becomes %2E). When dropping
 * extensions would give two inputs of one --over the same part, that --over keeps them. Escaping
 * is one-to-one and distinct files have distinct relative paths, so names never collide; the
 * outputs of a job are DIR/NAME + the extension of the output parameter's value (DIR/NAME.NODE-
 * PARAM.EXT when two outputs share an extension). doc/batch.md has examples.
 */
#define _GNU_SOURCE /* sched_getaffinity, pipe2 */
#include <errno.h>
#include <glob.h>
#include <sched.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <glib/gstdio.h>

#include "batch.h"

static void over_free(gpointer data)
{
    rf_batch_over *o = data;
    g_free(o->param);
    g_free(o->pattern);
    g_ptr_array_unref(o->paths);
    g_ptr_array_unref(o->names);
    g_free(o);
}

static void output_free(gpointer data)
{
    rf_batch_output *o = data;
    g_free(o->param);
    g_free(o->suffix);
    g_free(o);
}

static void job_free(gpointer data)
{
    rf_batch_job *j = data;
    g_free(j->name);
    g_ptr_array_unref(j->assign);
    g_ptr_array_unref(j->outputs);
    g_ptr_array_unref(j->inputs);
    json_decref(j->params);
    g_free(j);
}

void rf_batch_free(rf_batch *b)
{
    if (!b)
        return;
    g_free(b->pipeline);
    g_free(b->pipeline_text);
    g_free(b->out);
    g_free(b->state);
    g_ptr_array_unref(b->overs);
    g_ptr_array_unref(b->outputs);
    g_ptr_array_unref(b->jobs);
    g_free(b);
}

/* ---- job names ---- */

static void escape_part(GString *s, const char *rel)
{
    for (const unsigned char *c = (const unsigned char *)rel; *c; c++) {
        if (*c == '/')
            g_string_append_c(s, '+');
        else if (g_ascii_isalnum(*c) || *c == '_' || *c == '-' || (*c == '.' && c != (void *)rel))
            g_string_append_c(s, (char)*c);
        else
            g_string_append_printf(s, "%%%02X", *c);
    }
}

/* `rel` without the extension of its last component ("a/b.c.bvh" -> "a/b.c"). */
static char *drop_extension(const char *rel)
{
    const char *slash = strrchr(rel, '/');
    const char *base = slash ? slash + 1 : rel;
    const char *dot = strrchr(base, '.');
    return g_strndup(rel, dot && dot > base ? (gsize)(dot - rel) : strlen(rel));
}

static char *escaped(const char *rel)
{
    GString *s = g_string_new(NULL);
    escape_part(s, rel);
    return g_string_free(s, FALSE);
}

/* Fills o->names from the matches' paths relative to `base` (see the rule above). */
static void name_matches(rf_batch_over *o, GPtrArray *rels)
{
    g_autoptr(GHashTable) seen = g_hash_table_new_full(g_str_hash, g_str_equal, g_free, NULL);
    bool keep_ext = false;
    for (guint i = 0; i < rels->len && !keep_ext; i++) {
        char *stem = drop_extension(g_ptr_array_index(rels, i));
        keep_ext = !g_hash_table_add(seen, stem);
    }
    for (guint i = 0; i < rels->len; i++) {
        const char *rel = g_ptr_array_index(rels, i);
        g_autofree char *stem = keep_ext ? g_strdup(rel) : drop_extension(rel);
        g_ptr_array_add(o->names, escaped(stem));
    }
}

/* ---- the plan ---- */

static bool has_glob_chars(const char *s)
{
    return strpbrk(s, "*?[") != NULL;
}

static int glob_error;

/* A folder that does not exist is no match; one that cannot be read stops the expansion. */
static int on_glob_error(const char *path, int err)
{
    (void)path;
    if (err == ENOENT || err == ENOTDIR)
        return 0;
    glob_error = err;
    return 1;
}

/* Expands one --over node.param=GLOB into regular files, sorted. */
static rf_batch_over *expand_over(const char *spec)
{
    const char *eq = strchr(spec, '='), *dot = strchr(spec, '.');
    if (!eq || !dot || dot > eq || dot == spec || eq == dot + 1 || !eq[1]) {
        fprintf(stderr, "rigflow batch: --over '%s': expected node.param=GLOB\n", spec);
        return NULL;
    }
    rf_batch_over *o = g_new0(rf_batch_over, 1);
    o->param = g_strndup(spec, (gsize)(eq - spec));
    o->pattern = g_strdup(eq + 1);
    o->paths = g_ptr_array_new_with_free_func(g_free);
    o->names = g_ptr_array_new_with_free_func(g_free);
    /* the folder part before the first glob character: names are relative to it */
    const char *meta = has_glob_chars(o->pattern) ? strpbrk(o->pattern, "*?[") : NULL;
    const char *end = meta ? meta : o->pattern + strlen(o->pattern);
    gsize base_len = 0;
    for (const char *c = o->pattern; c < end; c++)
        if (*c == '/')
            base_len = (gsize)(c - o->pattern) + 1;
    glob_t g;
    glob_error = 0;
    int rc = glob(o->pattern, 0, on_glob_error, &g);
    g_autoptr(GPtrArray) rels = g_ptr_array_new_with_free_func(g_free);
    for (size_t i = 0; rc == 0 && i < g.gl_pathc; i++) {
        if (!g_file_test(g.gl_pathv[i], G_FILE_TEST_IS_REGULAR))
            continue;
        g_ptr_array_add(o->paths, g_canonicalize_filename(g.gl_pathv[i], NULL));
        g_ptr_array_add(rels, g_strdup(g.gl_pathv[i] + base_len));
    }
    if (rc == 0)
        globfree(&g);
    if (o->paths->len == 0) {
        fprintf(stderr, "rigflow batch: --over %s=", o->param);
        rf_text_fputs(o->pattern, stderr, 0);
        fprintf(stderr, ": %s%s\n", rc == GLOB_ABORTED ? "a folder could not be read: " : "",
                rc == GLOB_ABORTED ? g_strerror(glob_error) : "matches no file");
        over_free(o);
        return NULL;
    }
    name_matches(o, rels);
    return o;
}

/* Stores each output parameter that has a value, with its suffix. */
static void collect_output(const char *node, const char *param, const char *path, void *data)
{
    GPtrArray *outs = data;
    if (!*path)
        return;
    g_autofree char *base = g_path_get_basename(path);
    const char *dot = strrchr(base, '.');
    rf_batch_output *o = g_new0(rf_batch_output, 1);
    o->param = g_strdup_printf("%s.%s", node, param);
    o->suffix = g_strdup(dot ? dot : ""); /* ".glb", also for a value given as just ".glb" */
    g_ptr_array_add(outs, o);
}

static void qualify_shared_suffixes(GPtrArray *outs)
{
    g_autoptr(GHashTable) count = g_hash_table_new(g_str_hash, g_str_equal);
    for (guint i = 0; i < outs->len; i++) {
        rf_batch_output *o = g_ptr_array_index(outs, i);
        gpointer n = g_hash_table_lookup(count, o->suffix);
        g_hash_table_insert(count, o->suffix, GINT_TO_POINTER(GPOINTER_TO_INT(n) + 1));
    }
    g_autoptr(GPtrArray) qualified = g_ptr_array_new_with_free_func(g_free);
    for (guint i = 0; i < outs->len; i++) {
        rf_batch_output *o = g_ptr_array_index(outs, i);
        if (GPOINTER_TO_INT(g_hash_table_lookup(count, o->suffix)) < 2) {
            g_ptr_array_add(qualified, NULL);
            continue;
        }
        g_autofree char *tag = g_strdelimit(g_strdup(o->param), ".", '-');
        g_ptr_array_add(qualified, g_strdup_printf(".%s%s", tag, o->suffix));
    }
    for (guint i = 0; i < outs->len; i++) {
        rf_batch_output *o = g_ptr_array_index(outs, i);
        char *q = g_ptr_array_index(qualified, i);
        if (q) {
            g_free(o->suffix);
            o->suffix = g_strdup(q);
        }
    }
}

/* Loads the pipeline with the -p values and the first job's inputs, validates it (a typo fails
 * before any worker starts) and reads which outputs it writes. */
static int probe_pipeline(rf_batch *b, const rf_registry *reg)
{
    g_autoptr(GPtrArray) diags = rf_diags_new();
    g_autofree char *dir = g_path_get_dirname(b->pipeline);
    rf_pipeline *p = rf_pipeline_load_string(b->pipeline_text, b->pipeline, dir, diags);
    for (char **kv = b->params; p && kv && *kv; kv++)
        rf_pipeline_override(p, *kv, diags);
    for (guint i = 0; p && i < b->overs->len; i++) {
        rf_batch_over *o = g_ptr_array_index(b->overs, i);
        g_autofree char *kv = g_strdup_printf("%s=%s", o->param, (char *)o->paths->pdata[0]);
        rf_pipeline_override(p, kv, diags);
    }
    if (p)
        rf_pipeline_validate(p, reg, diags);
    if (!p || diags->len) {
        rf_print_diags(diags, "error");
        fprintf(stderr, "rigflow batch: %s: the pipeline is invalid with the first job's inputs\n",
                b->pipeline);
        rf_pipeline_free(p);
        return RF_EXIT_VALIDATION;
    }
    rf_pipeline_foreach_output(p, collect_output, b->outputs);
    rf_pipeline_free(p);
    qualify_shared_suffixes(b->outputs);
    return RF_EXIT_OK;
}

static void add_input(rf_batch_job *j, const char *path)
{
    if (g_file_test(path, G_FILE_TEST_IS_REGULAR))
        g_ptr_array_add(j->inputs, g_canonicalize_filename(path, NULL));
}

static bool is_output(const rf_batch *b, const char *param)
{
    for (guint i = 0; i < b->outputs->len; i++)
        if (strcmp(((rf_batch_output *)b->outputs->pdata[i])->param, param) == 0)
            return true;
    return false;
}

static void assign(rf_batch_job *j, const char *param, const char *value)
{
    g_ptr_array_add(j->assign, g_strdup_printf("%s=%s", param, value));
    json_object_set_new(j->params, param, json_string(value));
}

/* The job at position `index` of the cross product; pick[i] is the match of --over i. */
static rf_batch_job *make_job(rf_batch *b, guint index, const guint *pick)
{
    rf_batch_job *j = g_new0(rf_batch_job, 1);
    j->index = index;
    j->assign = g_ptr_array_new_with_free_func(g_free);
    j->outputs = g_ptr_array_new_with_free_func(g_free);
    j->inputs = g_ptr_array_new_with_free_func(g_free);
    j->params = json_object();
    add_input(j, b->pipeline);
    for (char **kv = b->params; kv && *kv; kv++) {
        const char *eq = strchr(*kv, '=');
        g_autofree char *param = g_strndup(*kv, (gsize)(eq - *kv));
        assign(j, param, eq + 1);
        if (!is_output(b, param)) /* an output's value only gives its extension */
            add_input(j, eq + 1);
    }
    GString *name = g_string_new(NULL);
    for (guint i = 0; i < b->overs->len; i++) {
        rf_batch_over *o = g_ptr_array_index(b->overs, i);
        const char *path = g_ptr_array_index(o->paths, pick[i]);
        assign(j, o->param, path);
        add_input(j, path);
        if (i)
            g_string_append_c(name, '@');
        g_string_append(name, g_ptr_array_index(o->names, pick[i]));
    }
    j->name = g_string_free(name, FALSE);
    for (guint i = 0; i < b->outputs->len; i++) {
        rf_batch_output *o = g_ptr_array_index(b->outputs, i);
        g_autofree char *file = g_strconcat(j->name, o->suffix, NULL);
        char *path = g_build_filename(b->out, file, NULL);
        assign(j, o->param, path);
        g_ptr_array_add(j->outputs, path);
    }
    return j;
}

/* No job may write a file another job writes or any job reads (--out DIR inside an input
 * folder, with the inputs' extension). */
static bool outputs_distinct(const rf_batch *b, const rf_batch_job *j, GHashTable *seen)
{
    for (guint k = 0; k < j->outputs->len; k++) {
        const char *out = g_ptr_array_index(j->outputs, k);
        for (guint i = 0; i < b->overs->len; i++) {
            GPtrArray *paths = ((rf_batch_over *)b->overs->pdata[i])->paths;
            if (g_ptr_array_find_with_equal_func(paths, out, g_str_equal, NULL)) {
                fprintf(stderr,
                        "rigflow batch: job %s would overwrite its input %s: choose "
                        "another --out\n",
                        j->name, out);
                return false;
            }
        }
        if (!g_hash_table_add(seen, (gpointer)out)) {
            fprintf(stderr,
                    "rigflow batch: two jobs would write %s: give outputs distinct extensions\n",
                    out);
            return false;
        }
    }
    return true;
}

static bool make_jobs(rf_batch *b)
{
    guint n = b->overs->len;
    g_autofree guint *pick = g_new0(guint, n ? n : 1);
    g_autoptr(GHashTable) seen = g_hash_table_new(g_str_hash, g_str_equal);
    for (guint index = 0;; index++) {
        rf_batch_job *j = make_job(b, index, pick);
        g_ptr_array_add(b->jobs, j);
        if (!outputs_distinct(b, j, seen))
            return false;
        guint i = n; /* odometer: the last --over varies fastest */
        while (i > 0) {
            rf_batch_over *o = g_ptr_array_index(b->overs, i - 1);
            if (++pick[i - 1] < o->paths->len)
                break;
            pick[--i] = 0;
        }
        if (i == 0)
            return true;
    }
}

static int default_workers(void)
{
    cpu_set_t set;
    if (sched_getaffinity(0, sizeof set, &set) == 0 && CPU_COUNT(&set) > 0)
        return CPU_COUNT(&set);
    return (int)g_get_num_processors();
}

static bool parse_shard(const char *text, int *shard, int *shards)
{
    char *end;
    long i = strtol(text, &end, 10);
    if (end == text || *end != '/')
        return false;
    const char *rest = end + 1;
    long n = strtol(rest, &end, 10);
    if (end == rest || *end || n < 1 || n > 1000000 || i < 0 || i >= n)
        return false;
    *shard = (int)i;
    *shards = (int)n;
    return true;
}

/* Builds the plan from the command line; returns an exit code (RF_EXIT_OK with *out set). */
static int make_plan(const rf_registry *reg, const char *pipeline, char **overs, char **params,
                     const char *out, rf_batch **result)
{
    rf_batch *b = g_new0(rf_batch, 1);
    b->overs = g_ptr_array_new_with_free_func(over_free);
    b->outputs = g_ptr_array_new_with_free_func(output_free);
    b->jobs = g_ptr_array_new_with_free_func(job_free);
    b->params = params;
    b->pipeline = g_canonicalize_filename(pipeline, NULL);
    b->out = g_canonicalize_filename(out, NULL);
    b->state = g_build_filename(b->out, RF_BATCH_STATE, NULL);
    g_autoptr(GError) error = NULL;
    if (!g_file_get_contents(b->pipeline, &b->pipeline_text, NULL, &error)) {
        fprintf(stderr, "rigflow batch: cannot read pipeline: %s\n", error->message);
        rf_batch_free(b);
        return RF_EXIT_VALIDATION; /* as rigflow run */
    }
    for (char **kv = params; kv && *kv; kv++) {
        const char *eq = strchr(*kv, '='), *dot = strchr(*kv, '.');
        if (!eq || !dot || dot > eq) {
            fprintf(stderr, "rigflow batch: -p '%s': expected node.param=value\n", *kv);
            rf_batch_free(b);
            return RF_EXIT_USAGE;
        }
    }
    for (char **spec = overs; *spec; spec++) {
        rf_batch_over *o = expand_over(*spec);
        if (!o) {
            rf_batch_free(b);
            return RF_EXIT_USAGE;
        }
        g_ptr_array_add(b->overs, o);
    }
    int code = probe_pipeline(b, reg);
    if (code == RF_EXIT_OK && !make_jobs(b))
        code = RF_EXIT_USAGE;
    if (code != RF_EXIT_OK) {
        rf_batch_free(b);
        return code;
    }
    *result = b;
    return RF_EXIT_OK;
}

/* ---- running ---- */

static bool in_shard(const rf_batch *b, const rf_batch_job *j)
{
    return b->shards == 0 || (int)(j->index % (guint)b->shards) == b->shard;
}

/* The jobs of this shard that a rerun must do: no record, a failure, or something changed. */
static GPtrArray *jobs_to_do(rf_batch *b, rf_batch_stats *stats)
{
    g_autoptr(GHashTable) records = rf_batch_manifest_load(b->state);
    GPtrArray *todo = g_ptr_array_new();
    for (guint i = 0; i < b->jobs->len; i++) {
        rf_batch_job *j = g_ptr_array_index(b->jobs, i);
        if (!in_shard(b, j))
            continue;
        stats->total++;
        if (rf_batch_record_current(j, g_hash_table_lookup(records, j->name)))
            stats->skipped++;
        else
            g_ptr_array_add(todo, j);
    }
    return todo;
}

/* The job list of a whole batch, for --status and --resubmit. */
void rf_batch_write_plan(const rf_batch *b)
{
    json_t *names = json_array();
    for (guint i = 0; i < b->jobs->len; i++)
        json_array_append_new(names, json_string(((rf_batch_job *)b->jobs->pdata[i])->name));
    json_t *plan =
        json_pack("{s:s, s:s, s:o}", "pipeline", b->pipeline, "out", b->out, "jobs", names);
    g_autofree char *path = g_build_filename(b->state, "plan.json", NULL);
    g_autofree char *tmp = g_strconcat(path, ".tmp", NULL);
    if (json_dump_file(plan, tmp, JSON_COMPACT) != 0 || g_rename(tmp, path) != 0)
        fprintf(stderr, "rigflow batch: warning: cannot write %s\n", path);
    json_decref(plan);
}

static void print_summary(const rf_batch_stats *s, double seconds, bool interrupted)
{
    guint ran = s->done + s->failed + s->crashed;
    printf("rigflow batch: %u job%s: %u done, %u failed, %u crashed, %u skipped (finished before)",
           s->total, s->total == 1 ? "" : "s", s->done, s->failed, s->crashed, s->skipped);
    if (interrupted || s->no_worker)
        printf(", %u not finished (%s)", s->total - ran - s->skipped,
               interrupted ? "interrupted" : "no worker process could start");
    if (s->unrecorded)
        printf(", %u not recorded in the manifest (a rerun does them again)", s->unrecorded);
    printf("; %.1f s", seconds);
    if (ran && seconds > 0)
        printf(", %.2f jobs/s", ran / seconds);
    printf("\n");
    for (guint i = 0; i < s->failures->len; i++) {
        rf_text_fputs(g_ptr_array_index(s->failures, i), stdout, 0);
        printf("\n");
    }
}

static bool make_state_dirs(const rf_batch *b)
{
    g_autofree char *logs = g_build_filename(b->state, "logs", NULL);
    if (g_mkdir_with_parents(logs, 0777) != 0) {
        fprintf(stderr, "rigflow batch: cannot create %s: %s\n", logs, g_strerror(errno));
        return false;
    }
    return true;
}

static int run_local(rf_batch *b, const rf_registry *reg)
{
    if (!make_state_dirs(b))
        return RF_EXIT_RUN;
    int lock = rf_batch_lock(b);
    if (lock < 0)
        return RF_EXIT_LOCKED;
    if (b->shards == 0) /* shards share DIR: another shard's temporary files are live */
        rf_batch_clean_temps(b, NULL);
    rf_batch_stats stats = {.failures = g_ptr_array_new_with_free_func(g_free)};
    g_autoptr(GPtrArray) todo = jobs_to_do(b, &stats);
    if (b->shards == 0)
        rf_batch_write_plan(b);
    int mfd = rf_batch_manifest_open(b);
    if (mfd < 0) {
        close(lock);
        g_ptr_array_unref(stats.failures);
        return RF_EXIT_RUN;
    }
    gint64 t0 = g_get_monotonic_time();
    bool finished = rf_batch_pool_run(b, reg, todo, mfd, &stats);
    print_summary(&stats, (double)(g_get_monotonic_time() - t0) / 1e6, !finished);
    close(mfd);
    close(lock);
    int code = !finished ? RF_EXIT_CANCELLED
               : stats.failed + stats.crashed + stats.unrecorded > 0 || stats.no_worker
                   ? RF_EXIT_RUN
                   : RF_EXIT_OK;
    g_ptr_array_unref(stats.failures);
    return code;
}

static void list_jobs(const rf_batch *b)
{
    for (guint i = 0; i < b->jobs->len; i++) {
        const rf_batch_job *j = g_ptr_array_index(b->jobs, i);
        if (!in_shard(b, j))
            continue;
        rf_text_fputs(j->name, stdout, 0);
        for (guint k = 0; k < j->outputs->len; k++) {
            printf("\t");
            rf_text_fputs(g_ptr_array_index(j->outputs, k), stdout, 0);
        }
        printf("\n");
    }
}

/* ---- the command ---- */

typedef struct batch_args {
    char **params, **overs;
    char *out, *shard, *status, *resubmit;
    int jobs;
    double job_timeout;
    gboolean slurm, list, quiet;
    rf_slurm_options slurm_opts;
} batch_args;

static void args_clear(batch_args *a)
{
    g_strfreev(a->params);
    g_strfreev(a->overs);
    g_free(a->out);
    g_free(a->shard);
    g_free(a->status);
    g_free(a->resubmit);
    g_free(a->slurm_opts.partition);
    g_free(a->slurm_opts.time);
    g_free(a->slurm_opts.mem);
}

static const char summary[] =
    "Run a pipeline once per combination of input files, on N worker processes (or as a Slurm\n"
    "job array), with a manifest that lets a rerun skip what already finished.\n\n"
    "  rigflow batch pipelines/retarget.json --over source.path='clips/*.bvh' \\\n"
    "      --over target.path='chars/*.glb' -p export.path=.glb --out out/\n\n"
    "Outputs are named DIR/CLIP@CHARACTER.EXT from the inputs (doc/batch.md).\n"
    "Exit status: 0 every job done, 1 a job failed or crashed, 2 usage error, 3 invalid\n"
    "pipeline, 5 DIR is in use by another batch, 6 (--status) jobs still queued, 130 interrupted.";

static bool parse_args(batch_args *a, int *argc, char ***argv)
{
    const GOptionEntry entries[] = {
        {"over", 0, 0, G_OPTION_ARG_STRING_ARRAY, &a->overs,
         "Run once per file matching GLOB (repeatable: the cross product)", "NODE.PARAM=GLOB"},
        {"param", 'p', 0, G_OPTION_ARG_STRING_ARRAY, &a->params,
         "Set a parameter for every job; for an output, only its extension counts",
         "NODE.PARAM=VALUE"},
        {"out", 'o', 0, G_OPTION_ARG_FILENAME, &a->out, "Output folder (default: batch-out)",
         "DIR"},
        {"jobs", 'j', 0, G_OPTION_ARG_INT, &a->jobs, "Jobs at a time (default: the cores)", "N"},
        {"job-timeout", 0, 0, G_OPTION_ARG_DOUBLE, &a->job_timeout,
         "Stop a job that runs longer (recorded as failed; default: no limit)", "SECONDS"},
        {"list", 0, 0, G_OPTION_ARG_NONE, &a->list, "Print each job's name and outputs; run none",
         NULL},
        {"shard", 0, 0, G_OPTION_ARG_STRING, &a->shard, "Run only jobs whose index % N is I",
         "I/N"},
        {"slurm", 0, 0, G_OPTION_ARG_NONE, &a->slurm, "Submit as a Slurm job array", NULL},
        {"partition", 0, 0, G_OPTION_ARG_STRING, &a->slurm_opts.partition, "Slurm partition", "P"},
        {"array-size", 0, 0, G_OPTION_ARG_INT, &a->slurm_opts.array_size,
         "Array tasks (default: one per job, at most 1000)", "N"},
        {"time", 0, 0, G_OPTION_ARG_STRING, &a->slurm_opts.time, "Time limit per array task", "T"},
        {"mem", 0, 0, G_OPTION_ARG_STRING, &a->slurm_opts.mem, "Memory per array task", "M"},
        {"status", 0, 0, G_OPTION_ARG_FILENAME, &a->status,
         "Report a batch's jobs (manifests and Slurm's queue)", "DIR"},
        {"resubmit", 0, 0, G_OPTION_ARG_FILENAME, &a->resubmit,
         "Submit again the array tasks of failed and missing jobs", "DIR"},
        {"quiet", 'q', 0, G_OPTION_ARG_NONE, &a->quiet, "No progress line", NULL},
        {NULL, 0, 0, 0, NULL, NULL, NULL}};
    return rf_parse_options("batch", "PIPELINE", summary, entries, argc, argv);
}

int rf_cmd_batch(rf_registry *reg, int argc, char **argv)
{
    g_auto(GStrv) original = g_strdupv(argv); /* the script of a Slurm array repeats it */
    batch_args a = {0};
    int code = RF_EXIT_USAGE;
    rf_batch *b = NULL;
    if (!parse_args(&a, &argc, &argv))
        goto done;
    if (a.status || a.resubmit) {
        code = argc == 1 ? (a.status ? rf_batch_status(a.status) : rf_batch_resubmit(a.resubmit))
                         : RF_EXIT_USAGE;
        if (argc != 1)
            fprintf(stderr, "rigflow batch: --status and --resubmit take only DIR\n");
        goto done;
    }
    if (argc != 2 || !a.overs) {
        fprintf(stderr, "rigflow batch: expected one PIPELINE and at least one --over "
                        "(see rigflow batch --help)\n");
        goto done;
    }
    if (a.jobs < 0 || a.job_timeout < 0 || (a.shard && a.slurm)) {
        fprintf(stderr, "rigflow batch: %s\n",
                a.shard && a.slurm ? "--shard and --slurm exclude each other"
                                   : "-j and --job-timeout expect positive numbers");
        goto done;
    }
    code = make_plan(reg, argv[1], a.overs, a.params, a.out ? a.out : "batch-out", &b);
    if (code != RF_EXIT_OK)
        goto done;
    if (a.shard && !parse_shard(a.shard, &b->shard, &b->shards)) {
        fprintf(stderr, "rigflow batch: --shard '%s': expected I/N with 0 <= I < N\n", a.shard);
        code = RF_EXIT_USAGE;
        goto done;
    }
    b->workers = a.jobs > 0 ? a.jobs : default_workers();
    b->job_timeout = a.job_timeout;
    b->quiet = a.quiet || g_getenv("RIGFLOW_QUIET") != NULL;
    if (a.list)
        list_jobs(b);
    else if (a.slurm)
        code = !make_state_dirs(b) ? RF_EXIT_RUN
               : rf_batch_busy(b)  ? RF_EXIT_LOCKED
                                   : rf_batch_slurm_submit(b, reg, &a.slurm_opts, original);
    else
        code = run_local(b, reg);
done:
    rf_batch_free(b);
    args_clear(&a);
    return code;
}
