/* rigflow SDK: how much more memory the process may take, to refuse work that cannot fit.
 *
 * Linux overcommits: a malloc of more than the machine has succeeds, and the process is killed
 * later, mid-run, by the out-of-memory killer, with no message naming the input. A node facing
 * an input whose size it can estimate (a scan of 100 million vertices) asks first and refuses
 * with the figures. The answer is the smallest of what the system has available (MemAvailable),
 * what the process's control group and those above it may still take (cgroup v2 memory.max
 * less memory.current, or v1's memory.limit_in_bytes less memory.usage_in_bytes: a Slurm job's
 * allocation, a container's limit) and what its address-space
 * limit leaves (ulimit -v less its size). Only files under /proc and /sys are read, with ISO C's
 * stdio, so the header builds anywhere; where none of them is found it says nothing is known.
 */
#ifndef RIGFLOW_MEMORY_H
#define RIGFLOW_MEMORY_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The number after `key` on a line of a /proc file ("MemAvailable:  123 kB"), in bytes
 * (`unit` multiplies it: 1024 for kB). */
static inline bool rf_memory_read_key(const char *path, const char *key, uint64_t unit,
                                      uint64_t *out)
{
    FILE *f = fopen(path, "r");
    char line[256];
    bool found = false;
    size_t n = strlen(key);
    while (f && !found && fgets(line, sizeof line, f)) {
        unsigned long long v;
        if (!strncmp(line, key, n) && sscanf(line + n, " %llu", &v) == 1)
            *out = (uint64_t)v * unit, found = true;
    }
    if (f)
        fclose(f);
    return found;
}

/* The first number of a file ("max" reads as no limit). */
static inline bool rf_memory_read_number(const char *path, uint64_t *out)
{
    FILE *f = fopen(path, "r");
    unsigned long long v;
    bool found = f && fscanf(f, "%llu", &v) == 1;
    if (f)
        fclose(f);
    if (found)
        *out = (uint64_t)v;
    return found;
}

/* Lowers *best to `v` when it is smaller or nothing was known. */
static inline void rf_memory_least(bool *known, uint64_t *best, uint64_t v)
{
    if (!*known || v < *best)
        *best = v;
    *known = true;
}

/* The least that cgroup v2 directory `dir` (under `root`) and each cgroup above it may still
 * take (memory.max less memory.current) into *best. The limit is often set above the process's
 * own cgroup: Slurm limits the job and runs the task in job/step/user/task cgroups whose
 * memory.max reads "max". dir is cut back in place, one level at a time. */
static inline void rf_memory_cgroup(const char *root, char *dir, const char *max_file,
                                    const char *used_file, bool *known, uint64_t *best)
{
    char path[1024];
    for (;;) {
        uint64_t max, used;
        /* a path cut short names another file: such a level is skipped */
        int n = snprintf(path, sizeof path, "%s%s/%s", root, dir, max_file);
        bool limited = n > 0 && (size_t)n < sizeof path && rf_memory_read_number(path, &max);
        n = snprintf(path, sizeof path, "%s%s/%s", root, dir, used_file);
        if (limited && n > 0 && (size_t)n < sizeof path && rf_memory_read_number(path, &used))
            rf_memory_least(known, best, max > used ? max - used : 0);
        char *slash = strrchr(dir, '/');
        if (!slash)
            break;
        *slash = '\0';
    }
}

/* rf_memory_available reading the proc file system mounted at `proc` and the cgroup
 * hierarchies at `cgroup` (v2 there, v1's memory controller in its memory/; tests point them at
 * made-up trees). A cgroup path longer than the
 * line read is cut: its cgroup is not found, those above it are. */
static inline bool rf_memory_available_at(const char *proc, const char *cgroup, uint64_t *bytes)
{
    bool known = false;
    uint64_t best = 0, v, used;
    char path[1024], line[512], v1[1024];
    snprintf(path, sizeof path, "%s/meminfo", proc);
    if (rf_memory_read_key(path, "MemAvailable:", 1024, &v))
        rf_memory_least(&known, &best, v);
    /* the process's own cgroup: v2's line "0::/path" of /proc/self/cgroup, or v1's memory
     * controller, "N:memory:/path" (its limit in memory.limit_in_bytes under cgroup/memory;
     * "no limit" there is a number near 2^63, harmless as a least) */
    snprintf(path, sizeof path, "%s/self/cgroup", proc);
    snprintf(v1, sizeof v1, "%s/memory", cgroup);
    FILE *f = fopen(path, "r");
    while (f && fgets(line, sizeof line, f)) {
        line[strcspn(line, "\n")] = '\0';
        char *v1_dir = strstr(line, ":memory:");
        if (strncmp(line, "0::", 3) == 0)
            rf_memory_cgroup(cgroup, line + 3, "memory.max", "memory.current", &known, &best);
        else if (v1_dir)
            rf_memory_cgroup(v1, v1_dir + 8, "memory.limit_in_bytes", "memory.usage_in_bytes",
                             &known, &best);
    }
    if (f)
        fclose(f);
    char status[1024];
    snprintf(path, sizeof path, "%s/self/limits", proc);
    snprintf(status, sizeof status, "%s/self/status", proc);
    if (rf_memory_read_key(path, "Max address space", 1, &v) &&
        rf_memory_read_key(status, "VmSize:", 1024, &used))
        rf_memory_least(&known, &best, v > used ? v - used : 0);
    *bytes = best;
    return known;
}

/* The bytes this process can still allocate and use, as far as the system tells; false when
 * it tells nothing (another system: then the caller goes ahead). */
static inline bool rf_memory_available(uint64_t *bytes)
{
    return rf_memory_available_at("/proc", "/sys/fs/cgroup", bytes);
}

#ifdef __cplusplus
}
#endif

#endif
