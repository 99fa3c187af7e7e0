/* Internals of libmapfile: error lists and joint name lookup. */
#ifndef RF_MAPFILE_INTERNAL_H
#define RF_MAPFILE_INTERNAL_H

#include <errno.h>
#include <stdio.h>

#include "mapfile.h"

#define RF_ERRS_MAX 20

/* Problems collected into the caller's buffer, one "NAME: message" per line; the first
 * RF_ERRS_MAX are kept and the rest counted. */
typedef struct rf_errs {
    char *buf;
    size_t size, used;
    unsigned count;
    const char *name;
} rf_errs;

void rf_errs_add(rf_errs *e, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
void rf_errs_finish(rf_errs *e);

/* Joint index by name for one skeleton, in O(1) per lookup. */
typedef struct rf_name_index {
    const rf_skeleton *s;
    uint32_t *slot; /* joint + 1, 0 for empty */
    uint32_t mask;
} rf_name_index;

bool rf_name_index_init(rf_name_index *ix, const rf_skeleton *s);
int32_t rf_name_index_find(const rf_name_index *ix, const char *name);
void rf_name_index_clear(rf_name_index *ix);

#endif
