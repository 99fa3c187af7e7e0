/* Mapping files (doc/formats/mapping.md): JSON that names joints, so a user can read a mapping,
 * edit it and feed it back, whole or as a partial file of overrides. The convenience library
 * libmapfile is linked by the mapping.read / mapping.write nodes, the tests and
 * the fuzzers.
 *
 * Reading is two steps: parse (syntax and structure, no skeletons needed) and resolve (names
 * against the skeletons, as a whole mapping or as overrides on another). Both report every
 * problem they find at once, one per line, "FILE:LINE:COL: ..." for syntax and "FILE: at
 * /joints/3/inputs/0/weight: ..." for structure.
 */
#ifndef RF_MAPFILE_H
#define RF_MAPFILE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include <rigflow/model-copy.h>
#include <rigflow/model.h>

#define RF_MAPFILE_FORMAT "rigflow.mapping"
#define RF_MAPFILE_VERSION 1

typedef struct rf_mapfile_input {
    uint32_t source;
    char *joint;
    double weight; /* > 0; 1 when the file leaves it out */
    double delay;  /* seconds; 0 when left out */
    bool reverse, mirror;
} rf_mapfile_input;

typedef struct rf_mapfile_joint {
    char *target;
    uint32_t input_count;
    rf_mapfile_input *inputs;
    double score;
    double *metrics;      /* [rf_mapfile.metric_count], 0 where the file has none */
    char *section, *side; /* or NULL */
} rf_mapfile_joint;

typedef struct rf_mapfile {
    char *name;            /* the file as named when parsed (for messages), or NULL */
    char *target;          /* path of the target file, or NULL */
    uint32_t source_count; /* paths of the source files */
    char **sources;
    uint32_t metric_count;
    char **metric_names;
    uint32_t joint_count;
    rf_mapfile_joint *joints;
} rf_mapfile;

/* Parses mapping JSON held in memory (`size` bytes, no terminator needed); `name` names it in
 * messages. Returns NULL with every problem in err (err_size bytes, lines separated by '\n'). */
rf_mapfile *rf_mapfile_parse(const char *data, size_t size, const char *name, char *err,
                             size_t err_size);
/* The same from a file. */
rf_mapfile *rf_mapfile_read(const char *path, char *err, size_t err_size);
void rf_mapfile_free(rf_mapfile *f);

/* A whole mapping from the file: joints it does not list stay unmapped. Fails, listing every
 * unknown target joint and source joint and every source index beyond `source_count`.
 * (transfer full) */
rf_mapping *rf_mapfile_resolve(const rf_mapfile *f, const rf_skeleton *target,
                               const rf_skeleton *const *sources, uint32_t source_count, char *err,
                               size_t err_size);

/* `base` with every joint the file lists replaced by the file's entry (overrides), checked like
 * rf_mapfile_resolve. (transfer full) */
rf_mapping *rf_mapfile_apply(const rf_mapfile *f, const rf_mapping *base, const rf_skeleton *target,
                             const rf_skeleton *const *sources, uint32_t source_count, char *err,
                             size_t err_size);

/* Writes `m` with one entry for every target joint (inputs empty when unmapped). Joint names
 * come from the skeletons, paths from their names. Returns false with a message in err. */
bool rf_mapfile_write(FILE *out, const rf_mapping *m, const rf_skeleton *target,
                      const rf_skeleton *const *sources, uint32_t source_count, char *err,
                      size_t err_size);
bool rf_mapfile_write_path(const char *path, const rf_mapping *m, const rf_skeleton *target,
                           const rf_skeleton *const *sources, uint32_t source_count, char *err,
                           size_t err_size);

#endif
