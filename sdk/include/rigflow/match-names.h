/* Joint mapping by names: each joint name is normalised (namespace and rig prefixes dropped,
 * split at separators, case changes and digits, side tokens such as L, Left, .L, _l read as a
 * side, synonyms such as pelvis/hips or upperarm/arm folded to one concept, a per-file running
 * index dropped), then every target joint takes the source joint with the most similar
 * normalised name on the same side. Linked by the "names" plugin and by skeletal-similarity's
 * strategy=names, so strategies can be compared on the same data. */
#ifndef RF_NAMES_H
#define RF_NAMES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <rigflow/model.h>

/* A normalised name: its side (0 none, 1 left, 2 right) and concept words, e.g. "LeftUpLeg" and
 * "thigh.L" both give side 1 and "thigh". */
typedef struct rf_name_key {
    int side;
    char words[128]; /* canonical words separated by single spaces */
} rf_name_key;

/* Normalises one name. `drop_index` drops a final number (a file-wide running index). */
void rf_name_normalize(const char *name, bool drop_index, rf_name_key *out);

/* How alike two normalised names are, 0 (nothing shared, or opposite sides) to 1 (same). */
double rf_name_similarity(const rf_name_key *a, const rf_name_key *b);

/* Maps target joints to the source joint with the most similar name; matches below min_score
 * (0..1; 0 means 0.5) stay unmapped. One metric, "name", holds the similarity times 100.
 * Returns NULL with a message in err when out of memory or without sources.
 * (transfer full: free with rf_mapping_free) */
rf_mapping *rf_names_match(const rf_skeleton *target, const rf_skeleton *const *sources,
                           uint32_t source_count, double min_score, char *err, size_t err_size);

#endif
