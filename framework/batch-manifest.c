/* The batch's memory: a manifest of JSON lines, one per finished job, and a lock.
 *
 * A line is written with one write() on an O_APPEND descriptor and fsynced before the next, so a
 * crash or kill -9 loses at most the line being written, never an earlier one; a torn last line
 * is ignored on reading. Each shard of a Slurm array has its own manifest (appends from several
 * hosts to one file are not atomic on NFS); readers merge them all, the newest record of a job
 * winning. The lock is an fcntl record lock (it works across NFS with lockd and dies with its
 * process), in a file that names the holder.
 */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <glib/gstdio.h>

#include "batch.h"

static char *shard_suffix(const rf_batch *b)
{
    return b->shards ? g_strdup_printf("-shard-%d-of-%d", b->shard, b->shards) : g_strdup("");
}

/* Who holds the lock on fd: the file names its holder (escaped: its bytes reach the terminal);
 * else the kernel's pid. */
static void describe_holder(int fd, char *holder, size_t n)
{
    char text[256];
    ssize_t got = pread(fd, text, sizeof text - 1, 0);
    text[got > 0 ? got : 0] = '\0';
    rf_text_escape(g_strchomp(text), holder, n, 0);
    struct flock who = {.l_type = F_WRLCK, .l_whence = SEEK_SET};
    if (!*holder && fcntl(fd, F_GETLK, &who) == 0 && who.l_type != F_UNLCK)
        g_snprintf(holder, n, "pid %ld", (long)who.l_pid);
    if (!*holder)
        g_strlcpy(holder, "holder unknown", n);
}

static void refuse(const rf_batch *b, const char *path, int fd)
{
    char holder[256];
    describe_holder(fd, holder, sizeof holder);
    fprintf(stderr, "rigflow batch: %s is in use by another batch (%s); lock: %s\n", b->out, holder,
            path);
}

bool rf_batch_lock_holder(const char *state, const char *name, char *holder, size_t n)
{
    g_autofree char *path = g_build_filename(state, name, NULL);
    int fd = g_open(path, O_RDONLY | O_CLOEXEC, 0);
    if (fd < 0)
        return false;
    struct flock who = {.l_type = F_WRLCK, .l_whence = SEEK_SET};
    bool held = fcntl(fd, F_GETLK, &who) == 0 && who.l_type != F_UNLCK;
    if (held)
        describe_holder(fd, holder, n);
    close(fd);
    return held;
}

/* True, after saying so, when another process holds the lock file `name` in the state folder. */
static bool held_elsewhere(const rf_batch *b, const char *name)
{
    char holder[256];
    if (!rf_batch_lock_holder(b->state, name, holder, sizeof holder))
        return false;
    g_autofree char *path = g_build_filename(b->state, name, NULL);
    fprintf(stderr, "rigflow batch: %s is in use by another batch (%s); lock: %s\n", b->out, holder,
            path);
    return true;
}

/* True, after saying so, when a shard of a Slurm array holds its lock in the state folder. */
static bool shard_running(const rf_batch *b)
{
    g_autoptr(GDir) dir = g_dir_open(b->state, 0, NULL);
    const char *name;
    while (dir && (name = g_dir_read_name(dir)))
        if (g_str_has_prefix(name, "lock-shard-") && held_elsewhere(b, name))
            return true;
    return false;
}

/* A whole batch and the shards of a Slurm array on the same DIR exclude each other too. */
static bool others_running(const rf_batch *b)
{
    return b->shards ? held_elsewhere(b, "lock") : shard_running(b);
}

bool rf_batch_busy(const rf_batch *b)
{
    return held_elsewhere(b, "lock") || shard_running(b);
}

int rf_batch_lock(const rf_batch *b)
{
    g_autofree char *suffix = shard_suffix(b);
    g_autofree char *name = g_strconcat("lock", suffix, NULL);
    g_autofree char *path = g_build_filename(b->state, name, NULL);
    int fd = g_open(path, O_RDWR | O_CREAT | O_CLOEXEC, 0666);
    if (fd < 0) {
        fprintf(stderr, "rigflow batch: cannot create the lock %s: %s\n", path, g_strerror(errno));
        return -1;
    }
    struct flock fl = {.l_type = F_WRLCK, .l_whence = SEEK_SET};
    if (fcntl(fd, F_SETLK, &fl) != 0) {
        refuse(b, path, fd);
        close(fd);
        return -1;
    }
    if (others_running(b)) {
        close(fd);
        return -1;
    }
    g_autofree char *me = g_strdup_printf("pid %ld on %s\n", (long)getpid(), g_get_host_name());
    if (ftruncate(fd, 0) != 0 || pwrite(fd, me, strlen(me), 0) < 0)
        fprintf(stderr, "rigflow batch: warning: cannot write the lock %s\n", path);
    return fd;
}

/* Cuts a torn last line (a crash or a full disk in the middle of a write) off the manifest:
 * appended to, it would swallow the next record too. This process holds the manifest's lock. */
static bool drop_torn_tail(int fd)
{
    struct stat st;
    if (fstat(fd, &st) != 0)
        return false;
    char buf[4096];
    for (off_t end = st.st_size; end > 0;) {
        off_t start = end > (off_t)sizeof buf ? end - (off_t)sizeof buf : 0;
        ssize_t got = pread(fd, buf, (size_t)(end - start), start);
        if (got != end - start)
            return false;
        for (ssize_t i = got - 1; i >= 0; i--)
            if (buf[i] == '\n')
                return start + i + 1 == st.st_size || ftruncate(fd, start + i + 1) == 0;
        end = start;
    }
    return st.st_size == 0 || ftruncate(fd, 0) == 0;
}

int rf_batch_manifest_open(const rf_batch *b)
{
    g_autofree char *suffix = shard_suffix(b);
    g_autofree char *name = g_strconcat("manifest", suffix, ".jsonl", NULL);
    g_autofree char *path = g_build_filename(b->state, name, NULL);
    int fd = g_open(path, O_RDWR | O_CREAT | O_APPEND | O_CLOEXEC, 0666);
    if (fd >= 0 && !drop_torn_tail(fd)) {
        close(fd);
        fd = -1;
    }
    if (fd < 0)
        fprintf(stderr, "rigflow batch: cannot open the manifest %s: %s\n", path,
                g_strerror(errno));
    return fd;
}

bool rf_batch_manifest_append(int fd, json_t *record)
{
    char *text = json_dumps(record, JSON_COMPACT | JSON_SORT_KEYS);
    if (!text)
        return false;
    g_autofree char *line = g_strconcat(text, "\n", NULL);
    free(text);
    size_t len = strlen(line);
    off_t end = lseek(fd, 0, SEEK_END);
    ssize_t n = write(fd, line, len);
    if (n >= 0 && (size_t)n < len) /* a full disk or a file size limit: the rest says why */
        n = write(fd, line + n, len - (size_t)n) == (ssize_t)(len - (size_t)n) ? (ssize_t)len : -1;
    if (n != (ssize_t)len || fsync(fd) != 0) {
        int e = errno;
        if (end >= 0 && ftruncate(fd, end) != 0) /* no torn line for the next record to join */
            e = errno;
        fprintf(stderr, "rigflow batch: cannot write the manifest: %s\n", g_strerror(e));
        return false;
    }
    return true;
}

static void load_file(GHashTable *records, const char *path)
{
    g_autofree char *text = NULL;
    if (!g_file_get_contents(path, &text, NULL, NULL))
        return;
    g_auto(GStrv) lines = g_strsplit(text, "\n", -1);
    for (char **l = lines; *l; l++) {
        json_t *rec = **l ? json_loads(*l, 0, NULL) : NULL; /* a torn last line does not parse */
        const char *job = json_string_value(json_object_get(rec, "job"));
        if (!job) {
            json_decref(rec);
            continue;
        }
        json_t *old = g_hash_table_lookup(records, job);
        double t_old = json_real_value(json_object_get(old, "end"));
        if (old && t_old > json_real_value(json_object_get(rec, "end"))) {
            json_decref(rec);
            continue;
        }
        g_hash_table_replace(records, g_strdup(job), rec);
    }
}

GHashTable *rf_batch_manifest_load(const char *state)
{
    GHashTable *records =
        g_hash_table_new_full(g_str_hash, g_str_equal, g_free, (GDestroyNotify)json_decref);
    g_autoptr(GDir) dir = g_dir_open(state, 0, NULL);
    const char *name;
    while (dir && (name = g_dir_read_name(dir))) {
        if (!g_str_has_prefix(name, "manifest") || !g_str_has_suffix(name, ".jsonl"))
            continue;
        g_autofree char *path = g_build_filename(state, name, NULL);
        load_file(records, path);
    }
    return records;
}

static json_t *file_json(const char *path)
{
    struct stat st;
    if (g_stat(path, &st) != 0)
        return json_pack("{s:s, s:n}", "path", path, "size");
    json_int_t ns = (json_int_t)st.st_mtim.tv_sec * 1000000000 + st.st_mtim.tv_nsec;
    return json_pack("{s:s, s:I, s:I}", "path", path, "size", (json_int_t)st.st_size, "mtime_ns",
                     ns);
}

json_t *rf_batch_inputs_json(const rf_batch_job *job)
{
    json_t *a = json_array();
    for (guint i = 0; i < job->inputs->len; i++)
        json_array_append_new(a, file_json(g_ptr_array_index(job->inputs, i)));
    return a;
}

json_t *rf_batch_record(const rf_batch_job *job, const char *status, const char *error,
                        json_t *outputs, double seconds)
{
    return json_pack("{s:s, s:s, s:o, s:O, s:o, s:s?, s:f, s:f, s:s, s:i}", "job", job->name,
                     "status", status, "inputs", rf_batch_inputs_json(job), "params", job->params,
                     "outputs", outputs ? outputs : json_array(), "error", error, "seconds",
                     seconds, "end", (double)g_get_real_time() / 1e6, "host", g_get_host_name(),
                     "pid", (int)getpid());
}

/* Every output the record lists is still there with the size it had. */
static bool outputs_present(json_t *outputs)
{
    size_t i;
    json_t *o;
    json_array_foreach(outputs, i, o)
    {
        struct stat st;
        const char *path = json_string_value(json_object_get(o, "path"));
        if (!path || g_stat(path, &st) != 0 ||
            st.st_size != json_integer_value(json_object_get(o, "size")))
            return false;
    }
    return true;
}

bool rf_batch_record_current(const rf_batch_job *job, json_t *rec)
{
    if (!rec || g_strcmp0(json_string_value(json_object_get(rec, "status")), "done") != 0)
        return false;
    json_t *now = rf_batch_inputs_json(job);
    bool same = json_equal(now, json_object_get(rec, "inputs")) &&
                json_equal(job->params, json_object_get(rec, "params")) &&
                json_array_size(json_object_get(rec, "outputs")) == job->outputs->len &&
                outputs_present(json_object_get(rec, "outputs"));
    json_decref(now);
    return same;
}

/* The engine's temporary names are ".STEM.rf-XXXXXX[.EXT]" (framework/run.c, make_temp). */
static bool is_engine_temp(const char *name)
{
    const char *mark = strstr(name, ".rf-");
    if (name[0] != '.' || !mark || mark == name)
        return false;
    for (int i = 0; i < 6; i++)
        if (!g_ascii_isalnum(mark[4 + i]))
            return false;
    return mark[10] == '\0' || mark[10] == '.';
}

/* The temporary name of `output` starts with the engine's prefix for it. */
static bool temp_of(const char *name, const char *output)
{
    g_autofree char *prefix = rf_output_temp_prefix(output);
    return g_str_has_prefix(name, prefix);
}

static bool belongs_to(const char *name, const rf_batch_job *job)
{
    for (guint i = 0; job && i < job->outputs->len; i++)
        if (temp_of(name, g_ptr_array_index(job->outputs, i)))
            return true;
    return !job;
}

void rf_batch_clean_temps(const rf_batch *b, const rf_batch_job *job)
{
    g_autoptr(GDir) dir = g_dir_open(b->out, 0, NULL);
    const char *name;
    while (dir && (name = g_dir_read_name(dir))) {
        if (!is_engine_temp(name) || !belongs_to(name, job))
            continue;
        g_autofree char *path = g_build_filename(b->out, name, NULL);
        if (g_unlink(path) == 0 && !job && !b->quiet)
            fprintf(stderr, "rigflow batch: removed %s, left by an interrupted job\n", path);
    }
}
