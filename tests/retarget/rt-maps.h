/* Reads the name correspondences of tests/retarget/maps (one text file per target) into a
 * mapping, for the data tests and the benchmarks: one "target_joint source_joint [mirror]" per
 * line, '#' starts a comment. The names are resolved here, outside the retargeter, which only ever
 * sees indices. */
#ifndef RF_RT_MAPS_H
#define RF_RT_MAPS_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <rigflow/rigflow.h>

/* The mapping of `target` from source 0 = `source` read from `path`, or NULL with a message. */
static inline rf_mapping *rt_map_read(const char *path, const rf_skeleton *target,
                                      const rf_skeleton *source, char *err, size_t err_size)
{
    FILE *f = fopen(path, "r");
    if (!f) {
        snprintf(err, err_size, "%.300s: cannot open", path);
        return NULL;
    }
    rf_mapping *m = rf_mapping_new(target->joint_count, 1);
    char line[512];
    int no = 0;
    while (m && fgets(line, sizeof line, f)) {
        no++;
        char t[200], s[200], flag[32] = "";
        char *hash = strchr(line, '#');
        if (hash)
            *hash = 0;
        int got = sscanf(line, "%199s %199s %31s", t, s, flag);
        if (got <= 0)
            continue;
        int32_t jt = got >= 2 ? rf_skeleton_find(target, t) : -1;
        int32_t js = got >= 2 ? rf_skeleton_find(source, s) : -1;
        if (jt < 0 || js < 0 || (got == 3 && strcmp(flag, "mirror") != 0)) {
            snprintf(err, err_size, "%.300s:%d: unknown joint or flag in '%.60s %.60s %.20s'", path,
                     no, t, got >= 2 ? s : "", flag);
            rf_mapping_free(m);
            m = NULL;
            break;
        }
        rf_map_entry *e = &m->entries[jt];
        rf_map_input *in = realloc(e->inputs, (e->input_count + 1) * sizeof *in);
        if (!in) {
            rf_mapping_free(m);
            m = NULL;
            break;
        }
        e->inputs = in;
        in[e->input_count++] = (rf_map_input){0, (uint32_t)js, 1, 0, got == 3 ? RF_MAP_MIRROR : 0};
    }
    fclose(f);
    if (!m && !*err)
        snprintf(err, err_size, "%.300s: out of memory", path);
    return m;
}

#endif
