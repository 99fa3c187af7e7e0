/* Slurm: a batch as a job array. Task I of N runs `rigflow batch ... --shard I/N`, the jobs whose
 * index % N is I, each shard with its own manifest and lock in the shared DIR. --status merges
 * the manifests with what squeue and scontrol say of the array's tasks (no accounting database
 * is assumed: sacct may be off); --resubmit submits the same script again for the tasks whose
 * jobs failed or never ran, and each resubmitted shard skips what already finished.
 *
 * DIR/rigflow-batch/ holds plan.json (the job names), slurm.sbatch (the script) and slurm.json
 * (the shard count and every submission's array job id).
 */
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include <glib/gstdio.h>

#include "batch.h"

/* ---- submitting ---- */

static void append_quoted(GString *s, const char *arg)
{
    g_autofree char *q = g_shell_quote(arg);
    g_string_append_printf(s, " %s", q);
}

/* Options of the submitting command that the array's tasks must not repeat. */
static int skip_count(const char *arg)
{
    static const char *const with_value[] = {"--partition", "--array-size", "--time", "--mem",
                                             "--jobs",      "-j",           "--out",  "-o"};
    if (!strcmp(arg, "--slurm"))
        return 1;
    for (size_t i = 0; i < G_N_ELEMENTS(with_value); i++) {
        if (!strcmp(arg, with_value[i]))
            return 2;
        if (g_str_has_prefix(arg, with_value[i]) && arg[strlen(with_value[i])] == '=')
            return 1;
        if (with_value[i][1] != '-' && g_str_has_prefix(arg, with_value[i]) && arg[2])
            return 1; /* -j4 */
    }
    return 0;
}

/* The command that runs where rigflow was started from: the libtool wrapper in a build tree. */
static char *self_path(void)
{
    g_autofree char *exe = g_file_read_link("/proc/self/exe", NULL);
    if (!exe)
        return g_strdup("rigflow");
    g_autofree char *dir = g_path_get_dirname(exe);
    g_autofree char *base = g_path_get_basename(exe);
    if (g_str_has_suffix(dir, "/.libs")) { /* .libs/rigflow or .libs/lt-rigflow */
        g_autofree char *up = g_path_get_dirname(dir);
        char *wrapper = g_build_filename(up, base + (g_str_has_prefix(base, "lt-") ? 3 : 0), NULL);
        if (g_file_test(wrapper, G_FILE_TEST_IS_EXECUTABLE))
            return wrapper;
        g_free(wrapper);
    }
    return g_steal_pointer(&exe);
}

/* The folders the plugins were loaded from, so that the tasks load the same ones. */
static char *plugin_folders(const rf_registry *reg)
{
    GString *s = g_string_new(NULL);
    for (guint i = 0; i < rf_registry_plugin_count(reg); i++) {
        g_autofree char *dir = g_path_get_dirname(rf_plugin_path(rf_registry_plugin(reg, i)));
        g_autofree char *abs = g_canonicalize_filename(dir, NULL);
        g_autofree char *bounded = g_strdup_printf(":%s:", s->str);
        g_autofree char *needle = g_strdup_printf(":%s:", abs);
        if (!strstr(bounded, needle))
            g_string_append_printf(s, "%s%s", s->len ? ":" : "", abs);
    }
    return g_string_free(s, FALSE);
}

/* A value sbatch reads from a #SBATCH line as one word: in double quotes (sbatch splits the line
 * at spaces), with no quote, backslash or line break inside, which that quoting cannot hold. */
static bool sbatch_word_ok(const char *what, const char *value)
{
    if (!value || !strpbrk(value, "\"\\\n"))
        return true;
    fprintf(stderr, "rigflow batch: %s '", what);
    rf_text_fputs(value, stderr, 0);
    fprintf(stderr, "' holds a quote, a backslash or a line break, which a #SBATCH line cannot\n");
    return false;
}

static void sbatch_line(GString *s, const char *option, const char *value)
{
    if (value)
        g_string_append_printf(s, "#SBATCH --%s=\"%s\"\n", option, value);
}

static char *script_text(const rf_batch *b, const rf_registry *reg, const rf_slurm_options *o,
                         char **argv, int tasks)
{
    GString *s = g_string_new("#!/bin/sh\n# rigflow batch as a Slurm job array: task I runs "
                              "shard I of the jobs (doc/batch.md).\n");
    g_string_append_printf(s, "#SBATCH --job-name=rigflow-batch\n#SBATCH --array=0-%d\n",
                           tasks - 1);
    g_auto(GStrv) parts = g_strsplit(b->state, "%", -1); /* '%' starts Slurm's patterns */
    g_autofree char *state = g_strjoinv("%%", parts);
    g_autofree char *log = g_strconcat(state, "/logs/slurm-%A_%a.out", NULL);
    sbatch_line(s, "output", log);
    sbatch_line(s, "partition", o->partition);
    sbatch_line(s, "time", o->time);
    sbatch_line(s, "mem", o->mem);
    g_autofree char *cwd = g_get_current_dir();
    g_autofree char *qcwd = g_shell_quote(cwd);
    g_autofree char *plugins = plugin_folders(reg);
    g_autofree char *qplugins = g_shell_quote(plugins);
    g_autofree char *self = self_path();
    g_string_append_printf(
        s, "cd %s || exit 1\nRIGFLOW_PLUGIN_PATH=%s\nexport RIGFLOW_PLUGIN_PATH\n", qcwd, qplugins);
    g_string_append(s, "exec");
    append_quoted(s, self);
    append_quoted(s, "batch");
    for (int i = 1; argv[i];) {
        int skip = skip_count(argv[i]);
        if (skip) {
            i += skip;
            continue;
        }
        append_quoted(s, argv[i++]);
    }
    append_quoted(s, "--out");
    append_quoted(s, b->out);
    g_string_append_printf(s,
                           " --shard \"$SLURM_ARRAY_TASK_ID/%d\" -j "
                           "\"${SLURM_CPUS_PER_TASK:-1}\"\n",
                           tasks);
    return g_string_free(s, FALSE);
}

static char *state_file(const char *state, const char *name)
{
    return g_build_filename(state, name, NULL);
}

/* Runs sbatch; returns the array's job id, or NULL after printing why. */
static char *sbatch(const char *script, const char *array)
{
    g_autoptr(GPtrArray) args = g_ptr_array_new();
    g_ptr_array_add(args, "sbatch");
    g_ptr_array_add(args, "--parsable");
    g_autofree char *opt = array ? g_strdup_printf("--array=%s", array) : NULL;
    if (opt)
        g_ptr_array_add(args, opt);
    g_ptr_array_add(args, (char *)script);
    g_ptr_array_add(args, NULL);
    g_autofree char *out = NULL, *err = NULL;
    int status = 0;
    g_autoptr(GError) error = NULL;
    if (!g_spawn_sync(NULL, (char **)args->pdata, NULL, G_SPAWN_SEARCH_PATH, NULL, NULL, &out, &err,
                      &status, &error)) {
        fprintf(stderr, "rigflow batch: cannot run sbatch: %s\n", error->message);
        return NULL;
    }
    if (!g_spawn_check_wait_status(status, NULL) || !out || !g_ascii_isdigit(out[0])) {
        fprintf(stderr, "rigflow batch: sbatch refused the job array:\n");
        rf_text_fputs(err, stderr, RF_TEXT_KEEP_LINES);
        return NULL;
    }
    out[strspn(out, "0123456789")] = '\0'; /* "123" or "123;cluster" */
    return g_steal_pointer(&out);
}

static bool save_json(json_t *j, const char *path)
{
    g_autofree char *tmp = g_strconcat(path, ".tmp", NULL);
    bool ok = json_dump_file(j, tmp, JSON_INDENT(1)) == 0 && g_rename(tmp, path) == 0;
    if (!ok)
        fprintf(stderr, "rigflow batch: cannot write %s: %s\n", path, g_strerror(errno));
    return ok;
}

static bool add_submission(const char *state, json_t *slurm, const char *id, const char *array)
{
    json_t *subs = json_object_get(slurm, "submissions");
    json_array_append_new(subs, json_pack("{s:s, s:s, s:f}", "job_id", id, "array", array, "time",
                                          (double)g_get_real_time() / 1e6));
    g_autofree char *path = state_file(state, "slurm.json");
    return save_json(slurm, path);
}

int rf_batch_slurm_submit(rf_batch *b, const rf_registry *reg, const rf_slurm_options *o,
                          char **argv)
{
    if (!sbatch_word_ok("--out", b->out) || !sbatch_word_ok("--partition", o->partition) ||
        !sbatch_word_ok("--time", o->time) || !sbatch_word_ok("--mem", o->mem))
        return RF_EXIT_USAGE;
    guint jobs = b->jobs->len;
    int tasks = o->array_size > 0 ? o->array_size : 1000;
    tasks = (int)MIN((guint)tasks, jobs);
    g_autofree char *text = script_text(b, reg, o, argv, tasks);
    g_autofree char *script = state_file(b->state, "slurm.sbatch");
    g_autoptr(GError) error = NULL;
    if (!g_file_set_contents(script, text, -1, &error)) {
        fprintf(stderr, "rigflow batch: cannot write %s: %s\n", script, error->message);
        return RF_EXIT_RUN;
    }
    g_chmod(script, 0755);
    rf_batch_write_plan(b);
    g_autofree char *id = sbatch(script, NULL);
    if (!id)
        return RF_EXIT_RUN;
    g_autofree char *array = g_strdup_printf("0-%d", tasks - 1);
    json_t *slurm = json_pack("{s:i, s:[]}", "shards", tasks, "submissions");
    bool ok = add_submission(b->state, slurm, id, array);
    json_decref(slurm);
    printf("rigflow batch: submitted %u jobs as Slurm array %s (%d tasks); follow it with "
           "rigflow batch --status %s\n",
           jobs, id, tasks, b->out);
    return ok ? RF_EXIT_OK : RF_EXIT_RUN;
}

/* ---- what Slurm says ---- */

typedef enum task_state { TASK_UNKNOWN, TASK_PENDING, TASK_RUNNING, TASK_ENDED } task_state;

static task_state state_of(const char *s)
{
    if (!strcmp(s, "PENDING") || !strcmp(s, "REQUEUED") || !strcmp(s, "CONFIGURING"))
        return TASK_PENDING;
    if (!strcmp(s, "RUNNING") || !strcmp(s, "COMPLETING") || !strcmp(s, "SUSPENDED"))
        return TASK_RUNNING;
    return TASK_ENDED;
}

/* Runs a Slurm client and returns its output, or NULL. A busy controller makes clients time out
 * now and then: those are retried, a refusal (a job Slurm forgot) is not. */
static char *run_tool(const char *const *argv)
{
    for (int attempt = 0; attempt < 3; attempt++) {
        g_autofree char *out = NULL, *err = NULL;
        int status = 0;
        if (!g_spawn_sync(NULL, (char **)argv, NULL, G_SPAWN_SEARCH_PATH, NULL, NULL, &out, &err,
                          &status, NULL))
            return NULL;
        if (g_spawn_check_wait_status(status, NULL))
            return g_steal_pointer(&out);
        if (!err || (!strstr(err, "timed out") && !strstr(err, "Unable to contact")))
            return NULL;
        g_usleep(500000);
    }
    return NULL;
}

/* "3", "4-7", "1,3,5-6%2": calls set for each task index. */
static void each_task(const char *list, task_state st, task_state *tasks, int n)
{
    g_autofree char *copy = g_strndup(list, strcspn(list, "% \t\n"));
    g_auto(GStrv) parts = g_strsplit(copy, ",", -1);
    for (char **p = parts; *p; p++) {
        char *end;
        long a = strtol(*p, &end, 10), z = *end == '-' ? strtol(end + 1, NULL, 10) : a;
        for (long i = a; i <= z && i < n; i++)
            if (i >= 0)
                tasks[i] = st;
    }
}

static const char *field(const char *line, const char *key, char *buf, size_t n)
{
    const char *at = strstr(line, key);
    if (!at)
        return NULL;
    at += strlen(key);
    size_t len = strcspn(at, " \t\n");
    g_strlcpy(buf, at, MIN(n, len + 1));
    return buf;
}

/* Finished tasks, while Slurm still remembers them (MinJobAge). */
static void ask_scontrol(const char *id, task_state *tasks, char **slurm_state, int n)
{
    const char *argv[] = {"scontrol", "-o", "show", "job", id, NULL};
    g_autofree char *out = run_tool(argv);
    g_auto(GStrv) lines = g_strsplit(out ? out : "", "\n", -1);
    for (char **l = lines; *l; l++) {
        char task[256], state[64];
        if (!field(*l, "ArrayTaskId=", task, sizeof task) ||
            !field(*l, "JobState=", state, sizeof state))
            continue;
        each_task(task, state_of(state), tasks, n);
        long k = strtol(task, NULL, 10);
        if (k >= 0 && k < n && !strchr(task, '-') && !strchr(task, ',')) {
            g_free(slurm_state[k]);
            slurm_state[k] = g_strdup(state);
        }
    }
}

/* Pending and running tasks, from the live queue. */
static void ask_squeue(const char *id, task_state *tasks, int n)
{
    const char *argv[] = {"squeue", "-h", "-r", "-j", id, "-o", "%K %T", NULL};
    g_autofree char *out = run_tool(argv);
    g_auto(GStrv) lines = g_strsplit(out ? out : "", "\n", -1);
    for (char **l = lines; *l; l++) {
        char task[256], state[64];
        if (sscanf(*l, "%255s %63s", task, state) == 2)
            each_task(task, state_of(state), tasks, n);
    }
}

/* ---- --status and --resubmit ---- */

typedef struct status {
    char *state;
    json_t *plan, *slurm;
    GHashTable *records;
    int shards;
    char local[256];    /* who runs the whole batch here now, or "" */
    task_state *tasks;  /* [shards], from the newest submission that ran each task */
    char **task_states; /* [shards] Slurm's word for ended tasks, or NULL */
    guint done, failed, running, pending, missing;
    GPtrArray *problems; /* lines to print */
    GArray *redo;        /* shard indices holding failed or missing jobs */
} status;

static void status_clear(status *s)
{
    g_free(s->state);
    json_decref(s->plan);
    json_decref(s->slurm);
    if (s->records)
        g_hash_table_unref(s->records);
    g_free(s->tasks);
    if (s->task_states)
        g_strfreev(s->task_states);
    if (s->problems)
        g_ptr_array_unref(s->problems);
    if (s->redo)
        g_array_unref(s->redo);
}

static void ask_slurm(status *s)
{
    s->tasks = g_new0(task_state, s->shards);
    s->task_states = g_new0(char *, s->shards + 1);
    json_t *subs = json_object_get(s->slurm, "submissions");
    size_t i;
    json_t *sub;
    json_array_foreach(subs, i, sub)
    {
        const char *id = json_string_value(json_object_get(sub, "job_id"));
        if (!id)
            continue;
        /* a later submission's tasks replace an earlier one's: it ran them again */
        g_autofree task_state *fresh = g_new0(task_state, s->shards);
        ask_scontrol(id, fresh, s->task_states, s->shards);
        ask_squeue(id, fresh, s->shards);
        for (int k = 0; k < s->shards; k++)
            if (fresh[k] != TASK_UNKNOWN)
                s->tasks[k] = fresh[k];
    }
}

static void note_redo(status *s, int shard)
{
    for (guint i = 0; i < s->redo->len; i++)
        if (g_array_index(s->redo, int, i) == shard)
            return;
    g_array_append_val(s->redo, shard);
}

static void classify(status *s, const char *name, int index)
{
    json_t *rec = g_hash_table_lookup(s->records, name);
    const char *st = json_string_value(json_object_get(rec, "status"));
    int shard = s->shards ? index % s->shards : -1;
    task_state task = shard >= 0 ? s->tasks[shard] : *s->local ? TASK_RUNNING : TASK_UNKNOWN;
    if (g_strcmp0(st, "done") == 0) {
        s->done++;
    } else if (task == TASK_RUNNING) {
        s->running++;
    } else if (task == TASK_PENDING) {
        s->pending++;
    } else if (rec) {
        s->failed++;
        const char *error = json_string_value(json_object_get(rec, "error"));
        g_ptr_array_add(s->problems, g_strdup_printf("%s %s: %s", st ? st : "failed", name,
                                                     error ? error : "no reason given"));
        if (shard >= 0)
            note_redo(s, shard);
    } else {
        s->missing++;
        const char *why = shard >= 0 && s->task_states[shard] ? s->task_states[shard] : NULL;
        g_ptr_array_add(s->problems, why ? g_strdup_printf("missing %s: its array task %d ended %s",
                                                           name, shard, why)
                                         : g_strdup_printf("missing %s: no record", name));
        if (shard >= 0)
            note_redo(s, shard);
    }
}

/* The plan and slurm.json are files: a damaged one is refused, naming it, before its names index
 * anything. A submission never has more array tasks than jobs. */
static bool state_files_sane(status *s, const char *plan, const char *slurm)
{
    json_t *jobs = json_object_get(s->plan, "jobs");
    for (size_t i = 0; i < json_array_size(jobs); i++)
        if (!json_is_string(json_array_get(jobs, i))) {
            fprintf(stderr, "rigflow batch: %s: job %zu is not a name\n", plan, i);
            return false;
        }
    if (!s->slurm)
        return true;
    json_t *shards = json_object_get(s->slurm, "shards");
    json_int_t n = json_integer_value(shards);
    if (!json_is_integer(shards) || n < 1 || (size_t)n > json_array_size(jobs)) {
        fprintf(stderr, "rigflow batch: %s: %" JSON_INTEGER_FORMAT " array tasks for %zu jobs\n",
                slurm, n, json_array_size(jobs));
        return false;
    }
    s->shards = (int)n;
    return true;
}

static bool load_status(status *s, const char *dir)
{
    g_autofree char *abs = g_canonicalize_filename(dir, NULL);
    s->state = g_build_filename(abs, RF_BATCH_STATE, NULL);
    g_autofree char *plan = state_file(s->state, "plan.json");
    g_autofree char *slurm = state_file(s->state, "slurm.json");
    s->plan = json_load_file(plan, 0, NULL);
    if (!json_is_array(json_object_get(s->plan, "jobs"))) {
        fprintf(stderr, "rigflow batch: %s is not a batch folder (no readable %s)\n", dir, plan);
        return false;
    }
    s->slurm = json_load_file(slurm, 0, NULL); /* NULL for a local batch */
    if (!state_files_sane(s, plan, slurm))
        return false;
    s->records = rf_batch_manifest_load(s->state);
    s->problems = g_ptr_array_new_with_free_func(g_free);
    s->redo = g_array_new(FALSE, FALSE, sizeof(int));
    if (s->shards > 0)
        ask_slurm(s);
    else if (!rf_batch_lock_holder(s->state, "lock", s->local, sizeof s->local))
        *s->local = '\0';
    size_t i;
    json_t *name;
    json_array_foreach(json_object_get(s->plan, "jobs"), i, name)
        classify(s, json_string_value(name), (int)i);
    return true;
}

/* "Slurm array tasks: 3 COMPLETED, 1 FAILED, 2 PENDING" */
static void print_tasks(const status *s)
{
    if (s->shards <= 0)
        return;
    static const char *const live[] = {"unknown", "PENDING", "RUNNING", "ended"};
    g_autoptr(GHashTable) count = g_hash_table_new(g_str_hash, g_str_equal);
    g_autoptr(GPtrArray) order = g_ptr_array_new();
    for (int k = 0; k < s->shards; k++) {
        const char *word =
            s->tasks[k] == TASK_ENDED && s->task_states[k] ? s->task_states[k] : live[s->tasks[k]];
        gpointer n = g_hash_table_lookup(count, word);
        if (!n)
            g_ptr_array_add(order, (gpointer)word);
        g_hash_table_insert(count, (gpointer)word, GINT_TO_POINTER(GPOINTER_TO_INT(n) + 1));
    }
    printf("Slurm array tasks:");
    for (guint i = 0; i < order->len; i++)
        printf("%s %d %s", i ? "," : "",
               GPOINTER_TO_INT(g_hash_table_lookup(count, order->pdata[i])),
               (char *)order->pdata[i]);
    printf("%s\n", g_hash_table_contains(count, "unknown")
                       ? " (unknown: Slurm no longer remembers them; see MinJobAge)"
                       : "");
}

int rf_batch_status(const char *dir)
{
    status s = {0};
    if (!load_status(&s, dir)) {
        status_clear(&s);
        return RF_EXIT_USAGE;
    }
    guint total = (guint)json_array_size(json_object_get(s.plan, "jobs"));
    printf("%s: %u jobs: %u done, %u failed, %u running, %u pending, %u missing\n", dir, total,
           s.done, s.failed, s.running, s.pending, s.missing);
    for (guint i = 0; i < s.problems->len; i++) {
        rf_text_fputs(g_ptr_array_index(s.problems, i), stdout, 0);
        printf("\n");
    }
    print_tasks(&s);
    if (*s.local)
        printf("a batch runs on this folder now (%s)\n", s.local);
    int code = s.running + s.pending  ? RF_EXIT_QUEUED
               : s.failed + s.missing ? RF_EXIT_RUN
                                      : RF_EXIT_OK;
    status_clear(&s);
    return code;
}

static int compare_int(gconstpointer a, gconstpointer b)
{
    return *(const int *)a - *(const int *)b;
}

int rf_batch_resubmit(const char *dir)
{
    status s = {0};
    if (!load_status(&s, dir)) {
        status_clear(&s);
        return RF_EXIT_USAGE;
    }
    int code = RF_EXIT_OK;
    g_autofree char *script = state_file(s.state, "slurm.sbatch");
    if (!s.slurm || !g_file_test(script, G_FILE_TEST_IS_REGULAR)) {
        fprintf(stderr,
                "rigflow batch: %s was not submitted to Slurm: run the batch again to "
                "redo its failed jobs\n",
                dir);
        code = RF_EXIT_USAGE;
    } else if (s.redo->len == 0) {
        printf("rigflow batch: nothing to resubmit (%u done, %u running, %u pending)\n", s.done,
               s.running, s.pending);
    } else {
        g_array_sort(s.redo, compare_int);
        GString *array = g_string_new(NULL);
        for (guint i = 0; i < s.redo->len; i++)
            g_string_append_printf(array, "%s%d", i ? "," : "", g_array_index(s.redo, int, i));
        g_autofree char *id = sbatch(script, array->str);
        if (id && add_submission(s.state, s.slurm, id, array->str))
            printf("rigflow batch: resubmitted %u failed and %u missing jobs as Slurm array %s "
                   "(tasks %s)\n",
                   s.failed, s.missing, id, array->str);
        else
            code = RF_EXIT_RUN;
        g_string_free(array, TRUE);
    }
    status_clear(&s);
    return code;
}
