/* Random skeletons with ground truth known by construction, for testing joint mapping on bodies
 * nobody tuned it to: bipeds, quadrupeds and winged creatures with random bone counts,
 * proportions, poses, scale, facing, up axis, rig conventions (BVH-like offsets with end sites,
 * or Blender-like bones along +Y without them), meaningless names and helper bones.
 *
 * Every joint carries a label saying what it is (e.g. "L.arm.2" the left upper arm, "spine" with
 * its place along the spine); gen_accepts() says whether a source joint is a right match for a
 * target joint, by the same homology rules as the hand-written truth files. */
#ifndef RF_TEST_GEN_H
#define RF_TEST_GEN_H

#include <stdbool.h>
#include <stdint.h>

#include <rigflow/model.h>

typedef enum gen_plan { GEN_BIPED, GEN_QUADRUPED, GEN_DRAGON, GEN_PLAN_COUNT } gen_plan;

typedef enum gen_part {
    GEN_HELPER = 0, /* IK target or pole: map to nothing */
    GEN_PELVIS,     /* first spine joint (the rear girdle) */
    GEN_SPINE,      /* between pelvis and chest; place = fraction along */
    GEN_CHEST,      /* last spine joint (the front girdle) */
    GEN_NECK,       /* place = fraction along the neck */
    GEN_HEAD,
    GEN_TAIL,   /* place = fraction along the tail */
    GEN_FORE,   /* arm or foreleg segment: seg 0 clavicle/scapula, 1 upper, 2 lower, 3 hand,
                 * 4 foreleg toe */
    GEN_HIND,   /* leg segment: 0 hip offset, 1 thigh, 2 shin, 3 foot/metatarsus, 4 toe */
    GEN_DIGIT,  /* finger: digit 0 is the thumb, seg from 1 */
    GEN_WING,   /* wing segment 1 upper, 2 lower; wing fingers are GEN_DIGIT with wing set */
    GEN_GROUND, /* a ground root: another ground root or nothing */
    GEN_JAW,    /* a jaw under the skull: another jaw or nothing */
    GEN_EYE,    /* an eye: the other body's eye on that side, or nothing */
} gen_part;

typedef struct gen_label {
    gen_part part;
    int side;     /* 0 center, 1 left, 2 right */
    int seg;      /* segment or digit segment */
    int digit;    /* finger index, 0 = thumb */
    int fingers;  /* fingers in this joint's hand, thumb included */
    bool wing;    /* a wing's digit */
    double place; /* 0..1 along spine, neck or tail */
} gen_label;

typedef struct gen_skel {
    rf_skeleton *s;
    gen_label *label; /* [joint_count] */
    gen_plan plan;
    /* The body as built, in the skeleton's frame (for meshes made around it): each joint's bone
     * from its pivot to where it ends (its continuing child, or its tip), whatever the rig
     * convention wrote; the up and forward the body was turned to, and its scale. */
    rf_vec3 *bone_from, *bone_to; /* [joint_count] */
    rf_vec3 up, forward;
    double scale;
} gen_skel;

/* A random skeleton of `plan` from `seed`. (transfer full: gen_free) */
gen_skel gen_make(gen_plan plan, uint64_t seed);
void gen_free(gen_skel *g);

/* Whether mapping target joint t onto source joint j (-1: unmapped) is right. */
bool gen_accepts(const gen_skel *target, uint32_t t, const gen_skel *source, int32_t j);
/* Whether it puts a left joint on a right one or the reverse. */
bool gen_swapped(const gen_skel *target, uint32_t t, const gen_skel *source, int32_t j);

#endif
