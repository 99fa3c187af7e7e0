/* Skeletal-similarity joint mapping: the method of Weijden (2014, "Skeletal similarity based
 * automatic joint mapping for performance animation") with what it lacked (doc/matching.md).
 *
 * Every target joint is scored against every source joint of every source by weighted metrics
 * (Table 1 of the thesis, plus body position and digit order); the best candidate wins; a target
 * section then takes the source section most of its joints chose, and the duplicate-bone removal
 * assigns joints along the two sections in order by dynamic programming (Tables 3-4); matches
 * under the threshold stay unmapped. The library is linked by the skeletal-similarity plugin,
 * the tests and the benchmark.
 */
#ifndef RF_SIMILARITY_H
#define RF_SIMILARITY_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include <rigflow/model.h>

#include "rigflow/analysis.h"

typedef enum rf_ms_metric {
    RF_MS_SAME_SIDE = 0, /* both on the same side (left, center, right): 30 */
    RF_MS_SAME_TYPE,     /* same section type: 50 */
    RF_MS_SIMILAR_TYPE,  /* a similar type (arm and hand, spine and tail...): up to 15 */
    RF_MS_BONE_COUNT,    /* sections of equal bone count: 10 */
    RF_MS_ORIENTATION,   /* bone directions in each body's frame: up to 15, quadratic falloff */
    RF_MS_SEQUENCE,      /* same place along the section: 16 */
    RF_MS_CONTINUITY,    /* same source as the parent's match, parent matched to parent: 5 */
    RF_MS_PREFERENCE,    /* the preferred source: 10 in the prefer-N sets, else 0 */
    RF_MS_BODY_POSITION, /* limbs at the same place along the body (front legs, arms): 20 */
    RF_MS_DIGIT_ORDER,   /* digits in the same order across their fan (thumb first): 20 */
    RF_MS_METRIC_COUNT
} rf_ms_metric;

/* "same_side", "same_type", ... (static) */
extern const char *const rf_ms_metric_names[RF_MS_METRIC_COUNT];

typedef struct rf_ms_weights {
    double w[RF_MS_METRIC_COUNT];
} rf_ms_weights;

/* The named weight sets: "default", "thesis" (Table 5's default: the thesis's metrics only),
 * "prefer-N" (default plus 10 for source N, counted from 0) and "thesis-prefer-N". Returns false
 * for an unknown name. *preferred gets the preferred source (0 when none). */
bool rf_ms_weight_set(const char *name, rf_ms_weights *out, uint32_t *preferred);

typedef enum rf_ms_mirror {
    RF_MS_MIRROR_NONE = 0,
    RF_MS_MIRROR_SWAP,  /* the thesis: every second pair of legs takes its other side's source */
    RF_MS_MIRROR_PHASE, /* keep sides; flag every second pair RF_MAP_MIRROR for the retargeter */
} rf_ms_mirror;

/* Options: zero-initialised means the default set, threshold 80, duplicate removal on. */
typedef struct rf_ms_options {
    const rf_ms_weights *weights; /* NULL: the default set */
    uint32_t preferred_source;    /* the source the preference metric favours */
    bool threshold_given;         /* use `threshold` instead of the default 80 */
    double threshold;             /* minimum total score of a match */
    bool keep_duplicates;         /* no duplicate-bone removal: each joint keeps its best match */
    bool thesis;                  /* the thesis as written: sequence by index, ratio-only removal,
                                   * arm/leg types without body roles, 15-degree orientation */
    rf_ms_mirror mirror;
    bool no_reverse;          /* do not flag knees that bend the other way */
    bool blend;               /* an input from every source that maps a joint, equal weights */
    double orientation_angle; /* degrees where orientation points reach zero; 0: 45 (the
                               * thesis: the orientation weight, i.e. 15) */
    const uint8_t *disabled;  /* [source_count] non-zero: ignore that source; may be NULL */
    rf_analysis_options target_analysis; /* forced axes, leg threshold... */
    rf_analysis_options source_analysis;
    bool forelegs_arms; /* forelegs on the floor keep the source's arms (homology) even when every
                         * source walks on two legs; false: the gait rule (gait.c) */
    bool girdle_neck;   /* correspondence, not motion: a girdle joint whose bone runs past the
                         * source's neck pivot takes the source's neck (where its skin lies), not
                         * its chest, and the spine before it the rest of the source's trunk
                         * (match.c, neck_at_girdle); a headless trunk's girdle joint takes the
                         * source's head (head_at_girdle); a limb without digits keeps the
                         * source's fist (lent_hand); a limb that lacks the source's first
                         * bones counts from where its pivots lie (steps_from_body); a girdle
                         * bone past the source's skull pivot takes the skull
                         * (girdle_past_skull) */
} rf_ms_options;

/* One scored candidate. */
typedef struct rf_ms_candidate {
    uint32_t source, joint;
    double total;
    double metrics[RF_MS_METRIC_COUNT];
} rf_ms_candidate;

/* What the matcher saw, for `--explain`: the analyses and the best three candidates per target
 * joint. Zero-initialise; free with rf_ms_explain_clear. */
typedef struct rf_ms_explain {
    rf_analysis *target;
    rf_analysis **sources;
    uint32_t source_count;
    uint32_t joint_count;
    rf_ms_candidate *top; /* [joint_count * 3] */
    uint8_t *top_count;   /* [joint_count] */
    double threshold;     /* the score a match needed */
    uint32_t gait_legs;   /* forelegs driven by the sources' legs half a cycle later (gait.c) */
    uint8_t *settled;     /* [joint_count] how a joint was assigned apart from its own section
                           * (3: a girdle joint that took a neck, girdle=neck; 4: a headless
                           * trunk's girdle joint that took the head), or NULL */
} rf_ms_explain;

/* Maps the target's joints onto the sources'. Returns NULL with a message in err when out of
 * memory or when there is nothing to map from. `explain` may be NULL.
 * (transfer full: free with rf_mapping_free) */
rf_mapping *rf_ms_match(const rf_skeleton *target, const rf_skeleton *const *sources,
                        uint32_t source_count, const rf_ms_options *opts, rf_ms_explain *explain,
                        char *err, size_t err_size);

/* Warnings first (facing cues that disagree); per target joint: its section and side, what it
 * was mapped to and why (the metric that put the winner ahead of the runner-up, or the section
 * alignment, or the threshold), the three best candidates with every metric; then the analyses
 * of all skeletons. */
void rf_ms_explain_print(const rf_ms_explain *e, const rf_mapping *m, const rf_skeleton *target,
                         const rf_skeleton *const *sources, FILE *out);
void rf_ms_explain_clear(rf_ms_explain *e);

/* The duplicate-bone removal's assignment: matches n target bones and m source bones in order
 * (i < i' implies k < k'), every bone of the smaller side exactly once, minimising the summed
 * cost[i * m + k]. Writes each target bone's source bone or -1 into match[n]; returns the total
 * cost, or -1 when out of memory. O(n m) time and space. */
double rf_ms_assign(const double *cost, uint32_t n, uint32_t m, int32_t *match);

/* The assignment this matcher uses beyond the thesis: the same order-preserving matching, but
 * either side may leave any bone out at a price of `skip` (an alignment), so extra bones on both
 * sides (a hip offset here, a toe there) need not shift the rest. Returns -1 (every match -1)
 * when out of memory or when `skip` is not a finite number >= 0. */
double rf_ms_align(const double *cost, uint32_t n, uint32_t m, double skip, int32_t *match);
/* The same with a price per bone for leaving it out (skip_t[n], skip_s[m]; NULL: `skip`). */
double rf_ms_align_priced(const double *cost, uint32_t n, uint32_t m, double skip,
                          const double *skip_t, const double *skip_s, int32_t *match);

/* The price of leaving a bone out in the matcher's assignment (a match costs 0 for bones at the
 * same place, about 0.3 per bone of shift or per landmark it crosses). */
#define RF_MS_SKIP_COST 0.4

#endif
