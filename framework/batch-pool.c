/* The worker pool: processes forked from the command once its plugins are loaded, so a job costs
 * a pipe message, a parse and a validation beyond its own work (no exec, no plugin loading), and
 * a plugin that crashes takes down one job, not the batch.
 *
 * Each worker reads job indices from its own pipe and answers each with its manifest record
 * (length-prefixed JSON) on another. The parent alone writes the manifest and the terminal. A
 * worker that dies mid-job shows as end-of-file on its pipe: the job is recorded as crashed with
 * the signal or exit status, and a fresh worker is forked in its place. Workers die with the
 * parent (PR_SET_PDEATHSIG), so a killed batch leaves no orphan writing files. Ctrl-C (or the
 * SIGTERM of a cancelled Slurm task) stops handing out jobs and interrupts the running ones,
 * whose outputs the engine then removes; interrupted jobs are not recorded, a rerun does them.
 */
#define _GNU_SOURCE /* sched_getaffinity, pipe2 */
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <glib/gstdio.h>
#include <nettle/sha2.h>

#include "batch.h"

typedef struct worker {
    pid_t pid;
    int job_fd;        /* parent -> worker: job indices */
    int result_fd;     /* worker -> parent: records */
    rf_batch_job *job; /* the job it runs, or NULL when idle */
    gint64 started;    /* monotonic µs when the job was handed over */
    bool timed_out;    /* killed for running longer than --job-timeout */
} worker;

static volatile sig_atomic_t stop_requested; /* parent: SIGINT or SIGTERM (C11 7.14.1.1) */
static volatile sig_atomic_t job_cancelled;  /* worker: the engine's cancel flag */

static void on_stop(int sig)
{
    stop_requested = 1;
    if (sig == SIGINT)
        signal(SIGINT, SIG_DFL); /* a second Ctrl-C ends the batch at once */
}

static void on_cancel(int sig)
{
    (void)sig;
    job_cancelled = 1;
}

static void set_handler(int sig, void (*fn)(int))
{
    struct sigaction sa = {.sa_handler = fn}; /* no SA_RESTART: poll and read return EINTR */
    sigemptyset(&sa.sa_mask);
    sigaction(sig, &sa, NULL);
}

static bool read_full(int fd, void *buf, size_t n)
{
    for (size_t got = 0; got < n;) {
        ssize_t r = read(fd, (char *)buf + got, n - got);
        if (r < 0 && errno == EINTR)
            continue;
        if (r <= 0)
            return false;
        got += (size_t)r;
    }
    return true;
}

static bool write_full(int fd, const void *buf, size_t n)
{
    for (size_t put = 0; put < n;) {
        ssize_t w = write(fd, (const char *)buf + put, n - put);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return false;
        put += (size_t)w;
    }
    return true;
}

/* ---- in the worker ---- */

/* SHA-256 of a file as 64 hex digits, and its size; false with errno set when the file cannot
 * be read to its end. nettle, not GChecksum: it uses the CPU's SHA instructions, and every job
 * pays for hashing its outputs. */
static bool hash_file(const char *path, char hex[2 * SHA256_DIGEST_SIZE + 1], json_int_t *size)
{
    static uint8_t buf[1 << 18];
    struct sha256_ctx ctx;
    sha256_init(&ctx);
    *size = 0;
    int fd = g_open(path, O_RDONLY | O_CLOEXEC, 0);
    if (fd < 0)
        return false;
    ssize_t n;
    while ((n = read(fd, buf, sizeof buf)) != 0) {
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0) {
            int e = errno;
            close(fd);
            errno = e;
            return false;
        }
        sha256_update(&ctx, (size_t)n, buf);
        *size += n;
    }
    close(fd);
    uint8_t digest[SHA256_DIGEST_SIZE];
    sha256_digest(&ctx, sizeof digest, digest);
    for (int i = 0; i < SHA256_DIGEST_SIZE; i++)
        g_snprintf(hex + 2 * i, 3, "%02x", digest[i]);
    return true;
}

/* The outputs' records, or NULL with *error set when one cannot be read back: a hash of what
 * could be read would record a file the job never wrote as done. */
static json_t *hash_outputs(const rf_batch_job *job, char **error)
{
    json_t *a = json_array();
    for (guint i = 0; i < job->outputs->len; i++) {
        const char *path = g_ptr_array_index(job->outputs, i);
        char hex[2 * SHA256_DIGEST_SIZE + 1];
        json_int_t size;
        if (!hash_file(path, hex, &size)) {
            *error = g_strdup_printf("cannot read back its output %s to record it: %s", path,
                                     g_strerror(errno));
            json_decref(a);
            return NULL;
        }
        json_array_append_new(
            a, json_pack("{s:s, s:I, s:s}", "path", path, "size", size, "sha256", hex));
    }
    return a;
}

/* A job whose outputs cannot be recorded has failed: its outputs go, as a failed job's do. */
static void drop_outputs(const rf_batch_job *job)
{
    for (guint i = 0; i < job->outputs->len; i++)
        g_unlink(g_ptr_array_index(job->outputs, i));
}

/* Every diagnostic of the run on one line. */
static char *join_diags(GPtrArray *diags)
{
    GString *s = g_string_new(NULL);
    for (guint i = 0; i < diags->len; i++) {
        g_autofree char *line = rf_diag_format(g_ptr_array_index(diags, i));
        g_string_append_printf(s, "%s%s", i ? "; " : "", line);
    }
    return g_string_free(s, FALSE);
}

static bool run_pipeline(const rf_batch *b, const rf_registry *reg, const rf_batch_job *job,
                         GPtrArray *diags)
{
    g_autofree char *dir = g_path_get_dirname(b->pipeline);
    rf_pipeline *p = rf_pipeline_load_string(b->pipeline_text, b->pipeline, dir, diags);
    for (guint i = 0; p && i < job->assign->len; i++)
        rf_pipeline_override(p, g_ptr_array_index(job->assign, i), diags);
    bool ok = p && diags->len == 0 && rf_pipeline_validate(p, reg, diags);
    rf_run_options opts;
    rf_run_options_init(&opts);
    opts.cancel_flag = &job_cancelled;
    ok = ok && rf_pipeline_run(p, reg, &opts, diags);
    rf_pipeline_free(p);
    return ok;
}

/* This process's CPU time: beside the wall time, it tells waiting (I/O, a loaded machine) from
 * work. */
static double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec / 1e9;
}

/* Runs one job with its stdout and stderr in its log file; returns its record. A job whose log
 * cannot be opened is not run: what it prints would go to the batch's terminal, mixed with the
 * other workers' jobs and lost for the record. */
static json_t *run_job(const rf_batch *b, const rf_registry *reg, const rf_batch_job *job)
{
    g_autofree char *file = g_strconcat(job->name, ".log", NULL);
    g_autofree char *log = g_build_filename(b->state, "logs", file, NULL);
    int fd = g_open(log, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (fd < 0) {
        g_autofree char *error =
            g_strdup_printf("cannot open its log %s: %s", log, g_strerror(errno));
        return rf_batch_record(job, "failed", error, NULL, 0);
    }
    int saved_out = dup(1), saved_err = dup(2);
    dup2(fd, 1);
    dup2(fd, 2);
    close(fd);
    gint64 t0 = g_get_monotonic_time();
    double cpu0 = cpu_seconds();
    g_autoptr(GPtrArray) diags = rf_diags_new();
    bool ok = run_pipeline(b, reg, job, diags);
    rf_print_diags(diags, "error");
    fflush(stdout);
    fflush(stderr);
    dup2(saved_out, 1);
    dup2(saved_err, 2);
    close(saved_out);
    close(saved_err);
    double seconds = (double)(g_get_monotonic_time() - t0) / 1e6;
    g_autofree char *error = ok ? NULL : join_diags(diags);
    json_t *outputs = ok ? hash_outputs(job, &error) : NULL;
    if (ok && !outputs) { /* the summary and the manifest give the error */
        drop_outputs(job);
        ok = false;
    }
    const char *status = ok ? "done" : job_cancelled ? "interrupted" : "failed";
    double cpu = cpu_seconds() - cpu0;
    json_t *rec = rf_batch_record(job, status, error, outputs, seconds);
    json_object_set_new(rec, "cpu_seconds", json_real(cpu));
    return rec;
}

static G_GNUC_NORETURN void worker_main(const rf_batch *b, const rf_registry *reg, int job_fd,
                                        int result_fd, pid_t parent)
{
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != parent) /* the parent died before prctl took effect */
        _exit(0);
    set_handler(SIGINT, on_cancel);
    set_handler(SIGTERM, on_cancel);
    signal(SIGPIPE, SIG_IGN);
    guint32 index;
    while (read_full(job_fd, &index, sizeof index) && index < b->jobs->len) {
        job_cancelled = 0; /* an interrupt was for the job before (the parent stops on Ctrl-C) */
        json_t *rec = run_job(b, reg, g_ptr_array_index(b->jobs, index));
        char *text = json_dumps(rec, JSON_COMPACT | JSON_SORT_KEYS);
        json_decref(rec);
        guint32 len = (guint32)strlen(text);
        bool sent = write_full(result_fd, &len, sizeof len) && write_full(result_fd, text, len);
        free(text);
        if (!sent)
            break;
    }
    _exit(0); /* no atexit handlers: they belong to the parent (its stdio buffers, plugins) */
}

/* ---- in the parent ---- */

typedef struct pool {
    rf_batch *b;
    const rf_registry *reg;
    GArray *workers;    /* worker */
    GPtrArray *pending; /* records received, not yet in the manifest */
    int mfd;
    rf_batch_stats *stats;
    guint finished; /* jobs answered this run (any status) */
    guint todo;
    gint64 t0, last_progress;
    bool tty;
} pool;

static bool spawn(pool *p, worker *w)
{
    int jobs[2], results[2];
    if (pipe2(jobs, O_CLOEXEC) != 0)
        return false;
    if (pipe2(results, O_CLOEXEC) != 0) {
        close(jobs[0]);
        close(jobs[1]);
        return false;
    }
    fflush(NULL); /* else the child's exit could write the parent's buffered output again */
    pid_t parent = getpid(), pid = fork();
    if (pid == 0) {
        for (guint i = 0; i < p->workers->len; i++) { /* keep no other worker's pipe open */
            worker *o = &g_array_index(p->workers, worker, i);
            if (o != w && o->pid > 0) {
                close(o->job_fd);
                close(o->result_fd);
            }
        }
        close(p->mfd);
        close(jobs[1]);
        close(results[0]);
        worker_main(p->b, p->reg, jobs[0], results[1], parent);
    }
    close(jobs[0]);
    close(results[1]);
    if (pid < 0) {
        close(jobs[1]);
        close(results[0]);
        return false;
    }
    *w = (worker){.pid = pid, .job_fd = jobs[1], .result_fd = results[0]};
    return true;
}

static void clear_progress(pool *p)
{
    if (p->tty && !p->b->quiet)
        fputs("\r\033[K", stderr);
}

static void format_duration(char *buf, size_t n, double s)
{
    if (s >= 3600)
        g_snprintf(buf, n, "%dh%02dm", (int)(s / 3600), (int)(s / 60) % 60);
    else
        g_snprintf(buf, n, "%dm%02ds", (int)(s / 60), (int)s % 60);
}

/* On a terminal a line redrawn 5 times a second; elsewhere (logs, Slurm) a line every 10 s. */
static void progress(pool *p, bool force)
{
    gint64 now = g_get_monotonic_time();
    if (p->b->quiet || (!force && now - p->last_progress < (p->tty ? 200000 : 10000000)))
        return;
    p->last_progress = now;
    double elapsed = (double)(now - p->t0) / 1e6;
    double rate = elapsed > 0 ? p->finished / elapsed : 0;
    char eta[32] = "?";
    if (rate > 0)
        format_duration(eta, sizeof eta, (p->todo - p->finished) / rate);
    rf_batch_stats *s = p->stats;
    fprintf(stderr, "%srigflow batch: %u/%u jobs, %u failed, %u crashed, %.2f jobs/s, ETA %s%s",
            p->tty ? "\r\033[K" : "", p->finished, p->todo, s->failed, s->crashed, rate, eta,
            p->tty ? "" : "\n");
    fflush(stderr);
}

static void report_failure(pool *p, const char *what, const char *name, const char *error)
{
    char *line = g_strdup_printf("%s %s: %s", what, name, error ? error : "no reason given");
    clear_progress(p);
    fputs("rigflow batch: ", stderr);
    rf_text_fputs(line, stderr, 0);
    fputc('\n', stderr);
    g_ptr_array_add(p->stats->failures, line);
}

static void record(pool *p, json_t *rec)
{
    const char *status = json_string_value(json_object_get(rec, "status"));
    const char *name = json_string_value(json_object_get(rec, "job"));
    p->finished++;
    if (g_strcmp0(status, "interrupted") == 0) {
        p->stats->interrupted++;
        return; /* not in the manifest: a rerun does it */
    }
    if (!rf_batch_manifest_append(p->mfd, rec))
        p->stats->unrecorded++; /* a rerun does it again: the batch must not say all is well */
    if (g_strcmp0(status, "done") == 0) {
        p->stats->done++;
        return;
    }
    bool crashed = g_strcmp0(status, "crashed") == 0;
    if (crashed)
        p->stats->crashed++;
    else
        p->stats->failed++;
    report_failure(p, crashed ? "crashed" : "failed", name ? name : "?",
                   json_string_value(json_object_get(rec, "error")));
}

/* Records what arrived. Called after the idle workers got their next job, so that the
 * manifest's fsync overlaps their work instead of delaying it. */
static void flush_pending(pool *p)
{
    for (guint i = 0; i < p->pending->len; i++)
        record(p, g_ptr_array_index(p->pending, i));
    g_ptr_array_set_size(p->pending, 0);
}

static char *death_reason(int status)
{
    if (WIFSIGNALED(status))
        return g_strdup_printf("killed by signal %d (%s)", WTERMSIG(status),
                               g_strsignal(WTERMSIG(status)));
    return g_strdup_printf("exited with status %d", WIFEXITED(status) ? WEXITSTATUS(status) : -1);
}

/* The worker's pipe closed: it died, during its job if it had one. */
static void worker_died(pool *p, worker *w)
{
    int status = 0;
    while (waitpid(w->pid, &status, 0) < 0 && errno == EINTR)
        ;
    close(w->job_fd);
    close(w->result_fd);
    w->pid = 0;
    if (!w->job)
        return;
    g_autofree char *why =
        w->timed_out ? g_strdup_printf("stopped after running longer than --job-timeout %g s",
                                       p->b->job_timeout)
                     : death_reason(status);
    g_autofree char *error = g_strdup_printf("%s%s; its log: %s/logs/%s.log",
                                             w->timed_out ? "" : "the worker process died: ", why,
                                             p->b->state, w->job->name);
    rf_batch_clean_temps(p->b, w->job); /* the engine had no chance to */
    double seconds = (double)(g_get_monotonic_time() - w->started) / 1e6;
    g_ptr_array_add(p->pending, rf_batch_record(w->job, w->timed_out ? "failed" : "crashed", error,
                                                NULL, seconds));
    w->job = NULL;
    w->timed_out = false;
}

static void receive(pool *p, worker *w)
{
    guint32 len;
    g_autofree char *text = NULL;
    bool ok = read_full(w->result_fd, &len, sizeof len);
    if (ok) {
        text = g_malloc((gsize)len + 1);
        ok = read_full(w->result_fd, text, len);
        text[len] = '\0';
    }
    json_t *rec = ok ? json_loads(text, 0, NULL) : NULL;
    if (!rec) {
        worker_died(p, w);
        return;
    }
    g_ptr_array_add(p->pending, rec);
    w->job = NULL;
}

/* Hands `job` to `w`, starting a worker first when the slot has none. A worker that died while
 * idle (killed from outside) is replaced once; a fresh worker that cannot take a job means
 * something is wrong with the machine, and the batch stops. */
static bool dispatch(pool *p, worker *w, rf_batch_job *job)
{
    guint32 index = job->index;
    for (int attempt = 0; attempt < 2; attempt++) {
        if (w->pid == 0 && !spawn(p, w)) {
            fprintf(stderr, "rigflow batch: cannot start a worker process: %s\n",
                    g_strerror(errno));
            return false;
        }
        if (write_full(w->job_fd, &index, sizeof index)) {
            w->job = job;
            w->started = g_get_monotonic_time();
            return true;
        }
        worker_died(p, w);
    }
    fprintf(stderr, "rigflow batch: worker processes die before taking a job\n");
    return false;
}

static guint busy_count(pool *p)
{
    guint n = 0;
    for (guint i = 0; i < p->workers->len; i++)
        n += g_array_index(p->workers, worker, i).job != NULL;
    return n;
}

static void interrupt_running(pool *p)
{
    for (guint i = 0; i < p->workers->len; i++) {
        worker *w = &g_array_index(p->workers, worker, i);
        if (w->job)
            kill(w->pid, SIGINT);
    }
}

/* A job past --job-timeout is stopped by killing its worker: a plugin stuck in a loop may never
 * look at the cancel flag. The worker's death then records the job as failed. */
static void stop_overdue(pool *p)
{
    if (p->b->job_timeout <= 0)
        return;
    gint64 now = g_get_monotonic_time();
    for (guint i = 0; i < p->workers->len; i++) {
        worker *w = &g_array_index(p->workers, worker, i);
        if (w->job && !w->timed_out && (double)(now - w->started) > p->b->job_timeout * 1e6) {
            w->timed_out = true;
            kill(w->pid, SIGKILL);
        }
    }
}

static void wait_results(pool *p)
{
    struct pollfd fds[p->workers->len];
    guint map[p->workers->len], n = 0;
    for (guint i = 0; i < p->workers->len; i++) {
        worker *w = &g_array_index(p->workers, worker, i);
        if (w->job) {
            fds[n] = (struct pollfd){.fd = w->result_fd, .events = POLLIN};
            map[n++] = i;
        }
    }
    if (poll(fds, n, 200) <= 0)
        return; /* timeout or a signal: the caller looks at the flag and the clock */
    for (guint k = 0; k < n; k++)
        if (fds[k].revents)
            receive(p, &g_array_index(p->workers, worker, map[k]));
}

static void shut_down(pool *p)
{
    for (guint i = 0; i < p->workers->len; i++) {
        worker *w = &g_array_index(p->workers, worker, i);
        if (w->pid == 0)
            continue;
        close(w->job_fd); /* end of file: the worker exits */
        close(w->result_fd);
        while (waitpid(w->pid, NULL, 0) < 0 && errno == EINTR)
            ;
    }
}

bool rf_batch_pool_run(rf_batch *b, const rf_registry *reg, GPtrArray *todo, int mfd,
                       rf_batch_stats *stats)
{
    if (todo->len == 0)
        return true;
    guint n = MIN((guint)MAX(b->workers, 1), todo->len);
    pool p = {.b = b,
              .reg = reg,
              .workers = g_array_sized_new(FALSE, TRUE, sizeof(worker), n),
              .pending = g_ptr_array_new_with_free_func((GDestroyNotify)json_decref),
              .mfd = mfd,
              .stats = stats,
              .todo = todo->len,
              .t0 = g_get_monotonic_time(),
              .last_progress = g_get_monotonic_time(),
              .tty = isatty(2) != 0};
    g_array_set_size(p.workers, n);
    stop_requested = 0;
    set_handler(SIGINT, on_stop);
    set_handler(SIGTERM, on_stop);
    void (*old_pipe)(int) = signal(SIGPIPE, SIG_IGN);
    bool forwarded = false, broken = false;
    for (guint next = 0;;) {
        for (guint i = 0; i < n && next < todo->len && !stop_requested && !broken; i++)
            if (!g_array_index(p.workers, worker, i).job)
                broken = !dispatch(&p, &g_array_index(p.workers, worker, i),
                                   g_ptr_array_index(todo, next++));
        flush_pending(&p);
        if (busy_count(&p) == 0 && (stop_requested || broken || next == todo->len))
            break;
        if (stop_requested && !forwarded) {
            interrupt_running(&p); /* when the signal came to this process alone */
            forwarded = true;
        }
        wait_results(&p);
        stop_overdue(&p);
        progress(&p, false);
    }
    if (p.tty)
        clear_progress(&p);
    else if (todo->len)
        progress(&p, true);
    shut_down(&p);
    flush_pending(&p);
    g_ptr_array_unref(p.pending);
    g_array_free(p.workers, TRUE);
    signal(SIGINT, SIG_DFL);
    signal(SIGTERM, SIG_DFL);
    signal(SIGPIPE, old_pipe);
    stats->no_worker = broken;
    return !stop_requested && stats->interrupted == 0; /* a worker may be interrupted alone */
}
