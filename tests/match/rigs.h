/* Random skeletons built the way production rigs are built, with ground truth by construction:
 * a second generator, written from how Mixamo, Rigify, Unreal's mannequin, Blender IK rigs,
 * Quaternius and Minetest creatures and insect rigs lay out their bones rather than from what the
 * matcher assumes (gen.h is the first). doc/matching.md lists its conventions.
 *
 * Plans: humanoids (fingers whose first joint sits at the knuckle, palm bones or not, twist and
 * roll joints mid-limb as leaves or as split segments, spines of 1-5 and necks of 1-3 joints,
 * arms in T, A or down pose, some with a second pair of arms or with wings), quadrupeds
 * (plantigrade or digitigrade three-segment legs, scapulae, necks of 3-7, tails of 0-10),
 * hexapods (upright or sprawled legs), dragons and birds. Every rig: random proportions and bone
 * counts, scale 0.01-100, facing +Z, -Z, +X or -X, Y or Z up, BVH-like offsets or Blender-like
 * bones along +Y, meaningless names; a third of them carry helpers (ground and placement roots,
 * an axis-conversion node, IK targets and poles).
 *
 * Each joint carries a label (what it is); rigs_accepts() says whether a source joint is a right
 * match for a target joint. Labels can be written by hand for a real skeleton too (the test
 * labels CMU's by name), so real and generated sources are judged by one rule. */
#ifndef RF_TEST_RIGS_H
#define RF_TEST_RIGS_H

#include <stdbool.h>
#include <stdint.h>

#include <rigflow/model.h>

typedef enum rigs_plan {
    RIGS_HUMANOID,
    RIGS_QUADRUPED,
    RIGS_HEXAPOD,
    RIGS_DRAGON,
    RIGS_BIRD,
    RIGS_PLAN_COUNT
} rigs_plan;

typedef enum rigs_part {
    RIGS_HELPER = 0, /* IK target, pole: maps to nothing */
    RIGS_ROOT,       /* ground root, placement root, axis-conversion node: nothing or a root */
    RIGS_PELVIS,     /* the spine's first joint (rear girdle); a one-joint body is a pelvis */
    RIGS_SPINE,      /* between pelvis and chest: index of count */
    RIGS_CHEST,      /* the spine's last joint (front girdle, where the arms hang) */
    RIGS_NECK,       /* index of count */
    RIGS_HEAD,
    RIGS_JAW,   /* nothing or a jaw */
    RIGS_TAIL,  /* index of count (an insect's abdomen too) */
    RIGS_LIMB,  /* seg 0 girdle (clavicle, scapula, hip offset, coxa), 1 upper, 2 lower, 3 hand or
                 * foot (metatarsus, tarsus), 4 toe */
    RIGS_DIGIT, /* seg 0 palm bone at the wrist, 1 first phalanx (at the knuckle), 2, 3 */
    RIGS_PART_COUNT
} rigs_part;

typedef enum rigs_role {
    RIGS_NO_ROLE = 0,
    RIGS_FORE,  /* arms, forelegs, an insect's front legs */
    RIGS_MID,   /* a second pair of arms, an insect's middle legs */
    RIGS_HIND,  /* legs, hind legs */
    RIGS_WINGS, /* wings (a bird's forelimbs) */
} rigs_role;

typedef struct rigs_label {
    uint8_t part;  /* rigs_part */
    uint8_t side;  /* 0 center, 1 left, 2 right */
    uint8_t role;  /* limbs and digits: rigs_role */
    uint8_t seg;   /* limb segment, digit segment */
    uint8_t index; /* chains: place in the chain from its root end */
    uint8_t count; /* chains: joints in the chain; digits: fingers of the fan, thumb aside */
    uint8_t digit; /* rank among the fingers across the fan (a thumb: 0) */
    bool thumb;    /* an opposable digit (set apart from the others) */
    bool twist;    /* a twist or roll joint inside segment `seg` */
    bool foot;     /* a digit of a foot (toes) */
} rigs_label;

typedef struct rigs_skel {
    rf_skeleton *s;
    rigs_label *label; /* [joint_count] */
    rigs_plan plan;
    bool helpers;        /* built with helpers */
    int facing;          /* 0 +Z, 1 +X, 2 -Z, 3 -X */
    rf_vec3 up, forward; /* the body's axes as built, in the skeleton's space */
} rigs_skel;

/* A random skeleton of `plan` from `seed`. (transfer full: rigs_free) */
rigs_skel rigs_make(rigs_plan plan, uint64_t seed);
void rigs_free(rigs_skel *g);
extern const char *const rigs_plan_names[RIGS_PLAN_COUNT];
extern const char *const rigs_part_names[RIGS_PART_COUNT];

/* Whether mapping target joint t onto source joint j (-1: unmapped) is right. */
bool rigs_accepts(const rigs_skel *target, uint32_t t, const rigs_skel *source, int32_t j);
/* Whether it puts a left joint on a right one or the reverse. */
bool rigs_swapped(const rigs_skel *target, uint32_t t, const rigs_skel *source, int32_t j);

#endif
