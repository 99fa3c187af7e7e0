/* Skeleton analysis: what each joint of an arbitrary skeleton is for, from geometry and hierarchy
 * alone (never names). Shared by the matchers, the retargeters and the riggers, in tree or out:
 * link `pkg-config --libs rigflow-analysis` (a static library needing only libm).
 *
 * What it finds (doc/matching.md explains how):
 * - up, forward and left axes, detected from the skeleton (limbs hanging to the ground, feet and
 *   toes, knees, the head end, symmetry) unless forced, with a confidence for each;
 * - the symmetry plane, the centerline and the side (left, center, right) of every joint, from
 *   mirrored subtrees of matching shape; left and right come from the axes, never from names;
 * - sections: chains of joints typed spine, head (neck and head), tail, arm, hand, leg, foot,
 *   appendage (ears, eyes, jaw, fins) and root (joints above the body, e.g. a ground root), plus
 *   helpers (IK targets, poles, sockets, control and end-marker joints) that nothing should drive;
 * - per joint: its section, its place in it (index and position along the chain measured in
 *   length, so zero-length joints do not shift anything), its bone direction and length, and its
 *   mirror image on the other side.
 *
 * Works on any tree or forest, including degenerate input (no joints, one joint, zero-length
 * bones, coincident joints, non-finite numbers, bad parent indices): it never crashes and never
 * recurses, so a 100 000-joint chain is fine; cost is O(n log n) in the number of joints.
 */
#ifndef RF_ANALYSIS_H
#define RF_ANALYSIS_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include <rigflow/model.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum rf_side {
    RF_SIDE_CENTER = 0,
    RF_SIDE_LEFT,
    RF_SIDE_RIGHT,
} rf_side;

typedef enum rf_section_type {
    RF_SECTION_NONE = 0,  /* not placed (only for joints of an empty analysis) */
    RF_SECTION_ROOT,      /* center joints above the body: ground roots, armature nodes */
    RF_SECTION_SPINE,     /* the centerline between the limb girdles (or all of it) */
    RF_SECTION_HEAD,      /* neck and head: the centerline beyond the front girdle */
    RF_SECTION_TAIL,      /* the centerline beyond the rear girdle */
    RF_SECTION_ARM,       /* a limb whose end stays above the leg threshold */
    RF_SECTION_HAND,      /* digits at the end (or along) an arm */
    RF_SECTION_LEG,       /* a limb reaching down below the leg threshold */
    RF_SECTION_FOOT,      /* digits of a leg, or a foot detached from its leg */
    RF_SECTION_APPENDAGE, /* short branches of the head, tail or spine: ears, eyes, jaw, fins */
    RF_SECTION_HELPER,    /* IK targets, poles, sockets, end markers: not part of the body */
    RF_SECTION_TYPE_COUNT
} rf_section_type;

/* rf_section.flags */
enum rf_section_flags {
    RF_SECFL_WING = 1u << 0,     /* an arm carrying digits before its last bone, or a fan of long
                                  * digits (wing fingers) */
    RF_SECFL_FAN = 1u << 1,      /* one digit of a fan of parallel children */
    RF_SECFL_REVERSE = 1u << 2,  /* a spine part that runs from the root toward the rear girdle */
    RF_SECFL_DETACHED = 1u << 3, /* attached by proximity (its joints hang from another root) */
    RF_SECFL_THUMB = 1u << 4,    /* the digit of its fan that stands apart (rank 0) */
};

/* rf_joint_info.flags */
enum rf_joint_info_flags {
    RF_JI_ZERO_LENGTH = 1u << 0, /* the bone has no length (its tip is on its pivot) */
    RF_JI_TIP_GUESSED = 1u << 1, /* leaf without end site: tip estimated (see tip) */
    RF_JI_CONTROL = 1u << 2,     /* an unweighted joint sitting on its only child (CTRL nodes) */
    RF_JI_END_MARKER = 1u << 3,  /* an unweighted leaf marking its parent's tip ("_end" joints) */
    RF_JI_ROOT = 1u << 4,        /* the root of the body tree */
    RF_JI_GIRDLE = 1u << 5,      /* a center joint where a pair of limbs attaches */
    RF_JI_OFFSET = 1u << 6,      /* a limb's short first bone from the centerline (clavicle,
                                  * hip offset) */
    RF_JI_UNWEIGHTED = 1u << 7,  /* carries no skin weights, in a skeleton where others do */
    RF_JI_PLACEMENT = 1u << 8,   /* a root far from its one child's body (a clip's frame may put
                                  * the body metres from the origin): a helper, not in the body */
    RF_JI_UNPAIRED = 1u << 9,    /* an off-center leaf with no mirror where its parent's mirror
                                  * has fewer children (a weapon socket in one fist): a helper */
};

typedef struct rf_section {
    rf_section_type type;
    rf_side side;
    uint32_t flags;       /* rf_section_flags */
    uint32_t bone_count;  /* joints in the section */
    uint32_t first;       /* index of its first joint in rf_analysis.section_joints */
    double length;        /* total length, from the attachment point to the last tip (for a
                           * limb ending in a fan, to the end of its longest digit; for the
                           * spine, to its last pivot) */
    int32_t parent;       /* section this one hangs from, or -1 */
    int32_t attach_joint; /* joint it hangs from (may be in a helper or root section), or -1 */
    int32_t mirror;       /* the mirrored section on the other side, or -1 */
    double body_pos;      /* where it attaches along the body, 0 at the rear end of the
                           * centerline and 1 at the front end (0.5 when there is no axis) */
    uint32_t pair_rank;   /* limbs: rank among sections of the same type and side, counted
                           * from the front; digits: rank in their fan, the thumb (the digit
                           * standing apart from the limb's line) first, then the others from
                           * the forward-most */
    uint32_t pair_count;  /* how many sections share that type and side */
} rf_section;

typedef struct rf_joint_info {
    int32_t section; /* index into sections, -1 only for an empty analysis */
    uint32_t index;  /* position within the section's joints */
    rf_side side;
    uint32_t flags;         /* rf_joint_info_flags */
    int32_t mirror;         /* the joint mirrored across the symmetry plane, or -1 */
    int32_t logical_parent; /* parent in the analysed tree (differs from the file for detached
                             * parts attached by proximity), -1 for roots */
    rf_vec3 pos;            /* world pivot */
    rf_vec3 tip;            /* world end of the joint's bone */
    rf_vec3 dir;            /* unit direction of the bone; for a zero-length bone, of the next bone
                             * along the chain; zero when nothing gives one */
    double length;          /* |tip - pos| */
    double u0, u1;          /* pivot and tip as fractions of the section length, measured from its
                             * attachment point */
    double bend;            /* signed bend of the chain at this joint along forward, relative to
                             * the section length (positive: the joint sticks out forward) */
} rf_joint_info;

/* Options: zero-initialised is the default everywhere. */
typedef struct rf_analysis_options {
    rf_vec3 up;            /* non-zero: use this up axis instead of detecting it */
    rf_vec3 forward;       /* non-zero: use this forward axis (made perpendicular to up) */
    double leg_threshold;  /* a limb whose lowest end is below this fraction of the body's height
                            * above the ground is a leg; 0 means 0.25 */
    bool use_bind_pose;    /* analyse the skin's bind pose (rf_skeleton.bind) when there is one */
    bool ignore_file_axes; /* do not use rf_skeleton.up/forward even as a hint */
} rf_analysis_options;

/* The cues facing is voted from (axes.c). */
#define RF_FORWARD_CUE_COUNT 8
/* The cues up is voted from: how the limbs hang (and reach the lowest level), the ground the
 * feet span, the axis the file declares. */
#define RF_UP_CUE_COUNT 3

typedef struct rf_analysis {
    uint32_t joint_count;
    rf_joint_info *joints; /* [joint_count] */
    uint32_t section_count;
    rf_section *sections;     /* [section_count], parents before children */
    uint32_t *section_joints; /* joints of every section, section by section */

    rf_vec3 up, forward, left; /* unit, orthogonal; left = up x forward */
    double up_confidence;      /* 0 (a guess) .. 1 (unambiguous) */
    double forward_confidence;
    double symmetry;            /* fraction of off-plane joints with a mirror image, 0 .. 1 */
    const char *up_source;      /* "forced", "limbs", "file", "default": (static) */
    const char *forward_source; /* "forced", "feet", "knees", "head", "elevation", "file",
                                 * "lean" (the top of the centerline), "girdles", "hierarchy",
                                 * "default" */
    rf_vec3 plane_normal;       /* symmetry plane (normal = left), through plane_point */
    rf_vec3 plane_point;
    double size;   /* diagonal of the bounding box of all pivots and tips, > 0 */
    double height; /* extent along up, > 0 */
    double ground; /* lowest height along up */
    int32_t root;  /* the root of the body tree, -1 when there are no joints */
    /* How each facing cue voted, along the forward chosen: positive agreed, negative voted the
     * other way, 0 said nothing; in the order of rf_forward_cue_names. All zero when forced. */
    double forward_cues[RF_FORWARD_CUE_COUNT];
    /* How each up cue voted: its score for the up chosen minus its best score for another of
     * the four candidates (positive agreed, negative preferred another axis), in the order of
     * rf_up_cue_names. All zero when forced or when there are no limbs. */
    double up_cues[RF_UP_CUE_COUNT];
} rf_analysis;

/* "feet", "knees", "head", "elevation", "file", "lean", "girdles", "hierarchy" (static) */
extern const char *const rf_forward_cue_names[RF_FORWARD_CUE_COUNT];
/* The strongest cue that voted against the chosen forward, or -1 when none did. */
int rf_forward_dissent(const rf_analysis *a);
/* "limbs", "ground", "file" (static) */
extern const char *const rf_up_cue_names[RF_UP_CUE_COUNT];
/* The up cue that preferred another axis by the most, or -1 when none did: when up is a close
 * call (up_confidence under 0.25) any such cue, else one that preferred it by more than 0.5. */
int rf_up_dissent(const rf_analysis *a);

/* Analyses a skeleton. `opts` may be NULL. Returns NULL only when out of memory.
 * (transfer full: free with rf_analysis_free) */
rf_analysis *rf_analyze(const rf_skeleton *skeleton, const rf_analysis_options *opts);
void rf_analysis_free(rf_analysis *a);

/* The joints of section `s`, in hierarchical order, and their number. (borrowed) */
static inline const uint32_t *rf_section_joints(const rf_analysis *a, uint32_t s)
{
    return a->section_joints + a->sections[s].first;
}

/* "spine", "left", ... (static) */
const char *rf_section_type_name(rf_section_type type);
const char *rf_side_name(rf_side side);
/* Parses a section type name; false for anything else. */
bool rf_section_type_parse(const char *name, rf_section_type *type);

/* Writes a human-readable report: axes and how sure, symmetry, sections with their joints.
 * `skeleton` gives joint names and may be NULL. */
void rf_analysis_print(const rf_analysis *a, const rf_skeleton *skeleton, FILE *out);

/* ---- poses (pose.c) ---- */

/* Whether the rest pose is no body: a branched skeleton (three leaves or more) whose pivots all
 * lie on one line, as Maya joint orients leave them at zero rotation (every bone along its local
 * X). A straight chain (a strip, a fish) may be straight and is not degenerate. False also when
 * out of memory (rf_pose_degenerate_check tells the two apart). */
bool rf_pose_degenerate(const rf_skeleton *skeleton);

/* The skeleton posed at frame `frame` of `anim` (clamped to its frames): a copy whose joints
 * rest in that frame's local transforms, without a bind pose, so an analysis sees that pose.
 * Names are borrowed from `skeleton`, which must outlive the view. NULL when the animation is
 * for another joint count, has no frames, or out of memory. (transfer full: rf_posed_free) */
rf_skeleton *rf_posed_view(const rf_skeleton *skeleton, const rf_animation *anim, uint32_t frame);
void rf_posed_free(rf_skeleton *view);

/* The skeleton in its clip's mean pose: per joint the average rotation (quaternions summed in
 * one hemisphere) and translation over every frame. A walk or run averages to a standing body,
 * arms and legs swinging both ways evening out. Same terms as rf_posed_view. */
rf_skeleton *rf_posed_mean(const rf_skeleton *skeleton, const rf_animation *anim);

/* The pose of the clip that shows the body best, for a skeleton whose rest pose is no body: the
 * mean pose or one of up to 16 frames spread over the clip, whichever puts the most joints in
 * limbs that mirror a limb of as many bones (the mean on ties). *frame gets the frame, or -1
 * for the mean pose. Same terms as rf_posed_view. */
rf_skeleton *rf_posed_best(const rf_skeleton *skeleton, const rf_animation *anim, int32_t *frame);

/* rf_pose_degenerate that tells a lack of memory apart: false only when out of memory (where
 * rf_pose_degenerate says "not degenerate"), else true with the answer in *degenerate. */
bool rf_pose_degenerate_check(const rf_skeleton *skeleton, bool *degenerate);

/* ---- joint roles (roles.c) ---- */

/* What a joint is for in a rigged character, beside the body's own joints. Found from geometry,
 * skin weights and motion (weighted or not, ever turned by a clip, on or off the body), never
 * from names. Placement and axis-conversion nodes never drive or receive body motion; helpers
 * are placed from the body joint they belong to. */
typedef enum rf_joint_role {
    RF_ROLE_BODY = 0,  /* carries skin, or moves joints that do (turned by a clip, inside the
                        * body's chain, or a limb's root beside the torso) */
    RF_ROLE_PLACEMENT, /* an unweighted joint above the body carrying all of it, or a root of its
                        * own, that only places it: never turned by the clips given, or (without
                        * clips) standing on the floor below the body */
    RF_ROLE_AXIS,      /* an unweighted, never-turned joint whose rest only turns or scales what
                        * hangs from it (an axis or unit conversion): above the body carrying all
                        * of it, or inside it on a bone's pivot swapping axes (quarter turns) or
                        * scaling */
    RF_ROLE_IK_TARGET, /* an unweighted joint carrying no body that sits on a body joint at rest
                        * (where an engine's IK pulls that joint) */
    RF_ROLE_IK_POLE,   /* an unweighted joint carrying no body, off the body, nearest the middle
                        * joint of a limb (where the knee or elbow points) */
    RF_ROLE_HELPER,    /* any other unweighted joint carrying no body (sockets, end markers) */
    RF_ROLE_COUNT
} rf_joint_role;

typedef struct rf_joint_roles {
    uint32_t joint_count;
    uint8_t *role;       /* [joint_count] rf_joint_role */
    int32_t *body_joint; /* [joint_count] IK targets, poles and helpers: the body joint they sit
                          * on or next to at rest (-1 when the skeleton has no body); -1 for the
                          * others */
    uint8_t *weighted;   /* [joint_count] 1 when it carries skin, or when the skin says nothing
                          * (it covers fewer than a quarter of the joints, or there is none) */
    uint8_t *turned;     /* [joint_count] 1 when a clip changes its rotation */
} rf_joint_roles;

/* The roles of every joint of `s`. `mesh` (may be NULL) says which joints carry skin weights
 * (without it, rf_joint.flags do; without either every joint is weighted); `clips` (clip_count
 * of them, may be NULL; clips for another joint count are skipped) say which joints move.
 * NULL only when out of memory. (transfer full: rf_joint_roles_free) */
rf_joint_roles *rf_joint_roles_find(const rf_skeleton *s, const rf_mesh *mesh,
                                    const rf_animation *const *clips, uint32_t clip_count);
void rf_joint_roles_free(rf_joint_roles *r);
/* "body", "placement", "axis", "ik-target", "ik-pole", "helper" (static) */
const char *rf_joint_role_name(rf_joint_role role);
/* Whether the role keeps a joint out of body motion (placement, axis conversion). */
static inline bool rf_joint_role_is_frame(rf_joint_role role)
{
    return role == RF_ROLE_PLACEMENT || role == RF_ROLE_AXIS;
}

#ifdef __cplusplus
}
#endif

#endif
