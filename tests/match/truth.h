/* Ground-truth files (tests/match/truth/README.md) and scoring a mapping against them. Shared by
 * the accuracy test and the benchmark. */
#ifndef RF_TEST_TRUTH_H
#define RF_TEST_TRUTH_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include <rigflow/model.h>

#define TRUTH_MAX_ACCEPT 8

typedef struct truth_joint {
    char name[96];
    char side; /* 'L', 'R', 'C' */
    int accept_count;
    char accept[TRUTH_MAX_ACCEPT][96]; /* "-" for unmapped */
} truth_joint;

typedef struct truth {
    char file[256];
    char source[512], target[512]; /* relative to RF_DATA_DIR */
    bool creature;
    int count;
    truth_joint *joints;
} truth;

/* Reads one .truth file; false with a message on stderr. */
bool truth_read(const char *path, truth *t);
void truth_free(truth *t);

/* Loads a skeleton from RF_DATA_DIR/rel through the BVH or Assimp importer; a BVH rest pose
 * that is no body is replaced by a frame of its clip, as the matcher node does with the clip
 * connected (rf_posed_best). (transfer full) */
rf_skeleton *truth_load(const char *data_dir, const char *rel);

typedef struct truth_score {
    int joints, correct, swapped;
    int missing; /* target joints the file does not list, or names the skeletons lack */
    int by_type_joints[16], by_type_correct[16];
} truth_score;

/* Scores mapping m (from `source` onto `target`) against t; with `verbose` prints every wrong
 * joint. Section types come from the mapping's labels. */
void truth_score_mapping(const truth *t, const rf_mapping *m, const rf_skeleton *target,
                         const rf_skeleton *source, truth_score *s, FILE *verbose);

/* Section type names in by_type order. */
extern const char *const truth_type_names[16];

#endif
