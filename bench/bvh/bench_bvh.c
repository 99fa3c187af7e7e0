/* BVH import (and export) throughput of libbvh, and peak memory against the decoded data.
 *
 * usage: bench_bvh [--reps N] [--min-ms MS] [--threads 0|1] [--no-write] FILE...
 *
 * For each file: parse time measured like the three.js peer does (each of N reps repeats the
 * parse until MS milliseconds have passed and records the time per call; the median rep is
 * reported), from the file (reading included) and from memory; the writer's time to /dev/null;
 * and, in a fresh child process, the peak resident memory a single import adds, beside the bytes
 * the skeleton and animation hold. Prints a line per file and `RESULT {json}` lines like the peers.
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "rigflow/bvh.h"

static int reps = 5;
static double min_ms = 300;
static rf_bvh_read_opts read_opts; /* .threads from --threads */

static double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

typedef bool (*job_fn)(void *arg);

/* Median over reps of the time per call, each rep calling `job` until min_ms have passed. */
static double time_job(job_fn job, void *arg)
{
    double t[64];
    int n = reps < 64 ? reps : 64;
    for (int r = 0; r < n; r++) {
        int calls = 0;
        double t0 = now_ms(), el;
        do {
            if (!job(arg))
                return -1;
            calls++;
        } while ((el = now_ms() - t0) < min_ms);
        t[r] = el / calls;
    }
    qsort(t, (size_t)n, sizeof *t, cmp_double);
    return n % 2 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2]);
}

typedef struct job {
    const char *path;
    const char *text;
    size_t size;
    const rf_skeleton *s;
    const rf_animation *a;
    FILE *sink;
} job;

static char err[4096];

static bool parse_file(void *arg)
{
    job *j = arg;
    rf_skeleton *s;
    rf_animation *a;
    if (!rf_bvh_read_file(j->path, &read_opts, &s, &a, err, sizeof err))
        return false;
    rf_skeleton_free(s);
    rf_animation_free(a);
    return true;
}

static bool parse_memory(void *arg)
{
    job *j = arg;
    rf_skeleton *s;
    rf_animation *a;
    if (!rf_bvh_read_memory(j->text, j->size, j->path, &read_opts, &s, &a, err, sizeof err))
        return false;
    rf_skeleton_free(s);
    rf_animation_free(a);
    return true;
}

static bool write_sink(void *arg)
{
    job *j = arg;
    rewind(j->sink);
    return rf_bvh_write_stream(j->sink, "/dev/null", j->s, j->a, NULL, err, sizeof err);
}

static char *read_all(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    rewind(f);
    char *buf = n >= 0 ? malloc((size_t)n + 1) : NULL;
    if (buf && fread(buf, 1, (size_t)n, f) != (size_t)n) {
        free(buf);
        buf = NULL;
    }
    fclose(f);
    *size = (size_t)n;
    return buf;
}

/* A "Vm...:" field of /proc/self/status in kB, or -1. */
static long status_kb(const char *field)
{
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    long v = -1;
    size_t n = strlen(field);
    while (f && fgets(line, sizeof line, f))
        if (strncmp(line, field, n) == 0)
            v = strtol(line + n, NULL, 10);
    if (f)
        fclose(f);
    return v;
}

/* Bytes the imported data holds: the animation's arrays and the skeleton with its names. */
static double decoded_bytes(const rf_skeleton *s, const rf_animation *a)
{
    double b = (double)a->frame_count * a->joint_count * 7 * sizeof(float) + a->joint_count;
    b += sizeof *s + (double)s->joint_count * sizeof(rf_joint);
    for (uint32_t i = 0; i < s->joint_count; i++)
        b += strlen(s->joints[i].name) + 1;
    return b;
}

/* In a fresh process (bench_bvh --peak FILE): the peak resident memory one import adds, from
 * the high-water mark reset (clear_refs 5) just before the import and read after it. A forked
 * child would not do: it shares the parent's heap, already resident from earlier imports. */
static int peak_child(const char *path)
{
    FILE *c = fopen("/proc/self/clear_refs", "w");
    if (c) {
        fputs("5", c);
        fclose(c);
    }
    long base = status_kb("VmHWM:");
    rf_skeleton *s;
    rf_animation *a;
    if (!rf_bvh_read_file(path, NULL, &s, &a, err, sizeof err))
        return 1;
    printf("%.0f\n", (double)(status_kb("VmHWM:") - base) * 1024);
    return 0;
}

/* Runs peak_child in a new process of this program; bytes, or -1. */
static double import_peak(const char *path)
{
    int fd[2];
    if (pipe(fd) != 0)
        return -1;
    pid_t pid = fork();
    if (pid == 0) {
        dup2(fd[1], 1);
        close(fd[0]);
        close(fd[1]);
        execl("/proc/self/exe", "bench_bvh", "--peak", path, (char *)NULL);
        _exit(127);
    }
    close(fd[1]);
    char buf[64] = {0};
    ssize_t n = pid > 0 ? read(fd[0], buf, sizeof buf - 1) : -1;
    close(fd[0]);
    int status = 1;
    if (pid > 0)
        waitpid(pid, &status, 0);
    return n > 0 && status == 0 ? atof(buf) : -1;
}

static int bench_file(const char *path, bool with_write)
{
    job j = {.path = path};
    rf_skeleton *s;
    rf_animation *a;
    j.text = read_all(path, &j.size);
    if (!j.text || !rf_bvh_read_file(path, NULL, &s, &a, err, sizeof err)) {
        fprintf(stderr, "bench_bvh: %s\n", j.text ? err : strerror(errno));
        return 1;
    }
    double mb = j.size / 1e6, frames = a->frame_count, joints = a->joint_count;
    double ms_file = time_job(parse_file, &j), ms_mem = time_job(parse_memory, &j), ms_write = -1;
    if (with_write) {
        j.s = s, j.a = a, j.sink = fopen("/dev/null", "w");
        ms_write = j.sink ? time_job(write_sink, &j) : -1;
        if (j.sink)
            fclose(j.sink);
    }
    double peak = import_peak(path), decoded = decoded_bytes(s, a);
    const char *name = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
    printf("%-24s %7.3f MB %6.0f frames %3.0f joints | import %8.3f ms %7.1f MB/s %9.0f frames/s "
           "(memory: %7.1f MB/s) | peak RSS +%.2f MB = %.2fx decoded %.2f MB",
           name, mb, frames, joints, ms_file, mb / (ms_file / 1e3), frames / (ms_file / 1e3),
           mb / (ms_mem / 1e3), peak / 1e6, peak / decoded, decoded / 1e6);
    if (ms_write > 0)
        printf(" | export %.1f MB/s", mb / (ms_write / 1e3));
    printf("\n");
    printf("RESULT {\"file\":\"%s\",\"metric\":\"parse\",\"ms\":%.4f,\"MBps\":%.2f,\"fps\":%.1f,"
           "\"jfps\":%.1f,\"frames\":%.0f,\"joints\":%.0f,\"mem_MBps\":%.2f,\"peak_MB\":%.3f,"
           "\"decoded_MB\":%.3f,\"rss_ratio\":%.3f,\"threads\":%d}\n",
           path, ms_file, mb / (ms_file / 1e3), frames / (ms_file / 1e3),
           frames * joints / (ms_file / 1e3), frames, joints, mb / (ms_mem / 1e3), peak / 1e6,
           decoded / 1e6, peak / decoded, read_opts.threads);
    if (ms_write > 0)
        printf("RESULT {\"file\":\"%s\",\"metric\":\"write\",\"ms\":%.4f,\"MBps\":%.2f}\n", path,
               ms_write, mb / (ms_write / 1e3));
    fflush(stdout);
    rf_skeleton_free(s);
    rf_animation_free(a);
    free((char *)j.text);
    return 0;
}

int main(int argc, char **argv)
{
    const char *usage =
        "usage: bench_bvh [--reps N] [--min-ms MS] [--threads 0|1] [--no-write] FILE...\n";
    bool with_write = true;
    int status = 0, first = argc;
    if (argc == 3 && strcmp(argv[1], "--peak") == 0)
        return peak_child(argv[2]);
    for (int i = 1; i < argc && first == argc; i++) {
        if (strcmp(argv[i], "--reps") == 0 && i + 1 < argc)
            reps = atoi(argv[++i]);
        else if (strcmp(argv[i], "--min-ms") == 0 && i + 1 < argc)
            min_ms = atof(argv[++i]);
        else if (strcmp(argv[i], "--threads") == 0 && i + 1 < argc)
            read_opts.threads = atoi(argv[++i]);
        else if (strcmp(argv[i], "--no-write") == 0)
            with_write = false;
        else if (argv[i][0] == '-' || reps < 1 || min_ms < 0)
            break;
        else
            first = i;
    }
    if (first == argc || reps < 1 || min_ms < 0) {
        fputs(usage, stderr);
        return 2;
    }
    for (int i = first; i < argc; i++)
        status |= bench_file(argv[i], with_write);
    return status;
}
