/* rigflow SDK: how much more memory the process may take, to refuse work that cannot fit.
 *
 * Linux overcommits: a malloc of more than the machine has succeeds, and the process is killed
 * later, mid-run, by the out-of-memory killer, with no message naming the input. A node facing
 * an input whose size it can estimate (a scan of 100 million vertices) asks first and refuses
 * with the figures. The answer is the smallest of what the system has available (MemAvailable),
 * what the process's control group may still take (cgroup v2 memory.max less memory.current: a
 * Slurm job's allocation, a container's limit) and what its address-space limit leaves (ulimit
 * -v less its size). Only files under /proc and /sys are read, with ISO C's stdio, so the header
 * builds anywhere; where none of them is found it says nothing is known.
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

/* The bytes this process can still allocate and use, as far as the system tells; false when
 * it tells nothing (another system: then the caller goes ahead). */
static inline bool rf_memory_available(uint64_t *bytes)
{
    bool known = false;
    uint64_t best = 0, v, used;
    if (rf_memory_read_key("/proc/meminfo", "MemAvailable:", 1024, &v))
        rf_memory_least(&known, &best, v);
    /* the process's own cgroup v2 (the line "0::/path" of /proc/self/cgroup) */
    FILE *f = fopen("/proc/self/cgroup", "r");
    char line[512], path[600];
    while (f && fgets(line, sizeof line, f)) {
        if (strncmp(line, "0::", 3) != 0)
            continue;
        line[strcspn(line, "\n")] = '\0';
        snprintf(path, sizeof path, "/sys/fs/cgroup%s/memory.max", line + 3);
        uint64_t max;
        if (rf_memory_read_number(path, &max)) {
            snprintf(path, sizeof path, "/sys/fs/cgroup%s/memory.current", line + 3);
            if (rf_memory_read_number(path, &used))
                rf_memory_least(&known, &best, max > used ? max - used : 0);
        }
    }
    if (f)
        fclose(f);
    if (rf_memory_read_key("/proc/self/limits", "Max address space", 1, &v) &&
        rf_memory_read_key("/proc/self/status", "VmSize:", 1024, &used))
        rf_memory_least(&known, &best, v > used ? v - used : 0);
    *bytes = best;
    return known;
}

#ifdef __cplusplus
}
#endif

#endif
