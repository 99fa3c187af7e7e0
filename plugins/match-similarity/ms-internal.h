/* Internals of the skeletal-similarity matcher shared by metrics.c and match.c. */
#ifndef RF_MS_INTERNAL_H
#define RF_MS_INTERNAL_H

#include "similarity.h"

/* What a section is for when comparing: the analysis's type, with limbs by their role along the
 * body (a quadruped's front legs are forelimbs like a human's arms) unless in thesis mode. */
typedef enum rf_ms_kind {
    RF_MK_NONE = 0,
    RF_MK_ROOT,
    RF_MK_SPINE,
    RF_MK_SPINE_REVERSE,
    RF_MK_HEAD,
    RF_MK_TAIL,
    RF_MK_FORE,       /* arms, wings, front legs (thesis: arms) */
    RF_MK_HIND,       /* hind legs (thesis: legs) */
    RF_MK_FORE_DIGIT, /* hands (thesis: hands) */
    RF_MK_HIND_DIGIT, /* feet (thesis: feet) */
    RF_MK_APPENDAGE,
    RF_MK_HELPER,
    RF_MK_COUNT
} rf_ms_kind;

/* One analysed skeleton with what the metrics read. */
typedef struct rf_ms_skel {
    const rf_skeleton *skel;
    rf_analysis *a;
    uint8_t *kind;         /* [section] rf_ms_kind */
    uint32_t *count;       /* [section] joints that can be matched */
    double *digit_frac;    /* [section] rank across the fan, 0..1 */
    uint8_t *matchable;    /* [joint] */
    int32_t *anc;          /* [joint] nearest matchable ancestor, -1 */
    rf_vec3 *bdir;         /* [joint] bone direction in the body frame (left, up, forward) */
    rf_vec3 *bplace;       /* [joint] its pivot in the body frame, rf_ms_body_place */
    double bfwd, bscale;   /* that frame's forward origin (the joints' mean) and unit (the
                            * body's largest extent) */
    uint8_t *ends;         /* [joint] 1: the last matchable joint of its section, 2: the first,
                            * 4: in a head, the neck's last joint before the skull */
    int32_t *main_digit;   /* [joint] the middle non-thumb digit section of the fan hanging from
                            * the joint, or -1 */
    int32_t *step;         /* [joint] place in a limb or digit counted in joints from its first
                            * real bone (offsets -1, unweighted links share the next one's) */
    uint8_t role_types[2]; /* [fore, hind] bit 1: an arm of that role, bit 2: a leg */
} rf_ms_skel;

typedef struct rf_ms_ctx {
    const rf_ms_options *o;
    rf_ms_weights wt;
    double threshold;
    double angle;     /* degrees */
    double cos_angle; /* its cosine: bones further apart score nothing (no angle needed) */
    rf_ms_skel tgt;
    rf_ms_skel *src;
    uint32_t nsrc;
    uint8_t *flip;      /* [target section] side swapped (mirror option) */
    uint8_t *phase;     /* [target section] mapped with RF_MAP_MIRROR */
    uint8_t *gait;      /* [target section] a foreleg (or its foot) in the hind role (gait.c) */
    uint32_t gait_legs; /* forelegs so marked */
} rf_ms_ctx;

#define RF_MS_NO_SOURCE UINT32_MAX

/* The gait rule (gait.c): where the target's forelegs stand on the floor and every source walks
 * on two legs (arms off the floor), marks the forelegs and their feet in c->gait and gives them
 * the hind role, so each takes the source's leg of its side; match.c flags them RF_MAP_MIRROR.
 * Returns the forelegs marked (0 with forelegs_arms, the thesis strategy, or no such pair). */
uint32_t rf_ms_gait_setup(rf_ms_ctx *c);

bool rf_ms_skel_init(rf_ms_skel *s, const rf_skeleton *skel, const rf_analysis_options *ao,
                     bool thesis);
void rf_ms_skel_clear(rf_ms_skel *s);

/* Section-level metrics of target section ts against source section ss of source k. */
void rf_ms_section_metrics(const rf_ms_ctx *c, uint32_t ts, uint32_t k, uint32_t ss, double *m);
/* Joint-level metrics (orientation, sequence) of target joint t against source joint j. */
void rf_ms_joint_metrics(const rf_ms_ctx *c, uint32_t t, uint32_t k, uint32_t j, double *m);
/* The bone directions of target joint t and source joint j in their bodies' frames, the source's
 * mirrored when the two lie on opposite sides (left against right); false when either has none.
 * Inline: the orientation metric asks for every pair of joints. */
static inline bool rf_ms_body_dirs(const rf_ms_ctx *c, uint32_t t, uint32_t k, uint32_t j,
                                   rf_vec3 *a, rf_vec3 *b)
{
    *a = c->tgt.bdir[t], *b = c->src[k].bdir[j];
    if (rf_v3_len2(*a) == 0 || rf_v3_len2(*b) == 0)
        return false;
    rf_side st = c->tgt.a->joints[t].side, ss = c->src[k].a->joints[j].side;
    if (st != RF_SIDE_CENTER && ss != RF_SIDE_CENTER && st != ss)
        b->x = -b->x;
    return true;
}

/* Where world point p lies in skeleton s's body frame: across from the symmetry plane, up from
 * the ground, forward from the mean of the body's joints (a rig has no landmark along its length
 * that every rig shares), in the body's largest extent (its height, or the span of a flat body's
 * wings). Two rigs of one body compare there as they lie. */
static inline rf_vec3 rf_ms_body_place(const rf_ms_skel *s, rf_vec3 p)
{
    const rf_analysis *a = s->a;
    return rf_v3(rf_v3_dot(rf_v3_sub(p, a->plane_point), a->left) / s->bscale,
                 (rf_v3_dot(p, a->up) - a->ground) / s->bscale,
                 (rf_v3_dot(p, a->forward) - s->bfwd) / s->bscale);
}

/* The two per-joint metrics apart, so a candidate can be dropped before the dearer one. */
double rf_ms_orientation(const rf_ms_ctx *c, uint32_t t, uint32_t k, uint32_t j);
double rf_ms_sequence(const rf_ms_ctx *c, uint32_t t, uint32_t k, uint32_t j);
/* Continuity of candidate (k, j) for t given the choice made for t's matchable ancestor. */
double rf_ms_continuity(const rf_ms_ctx *c, const rf_ms_candidate *parent_choice, uint32_t k,
                        uint32_t j);

#endif
