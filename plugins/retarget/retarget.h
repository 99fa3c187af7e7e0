/* Motion retargeting between different skeletons (convenience library libretarget).
 *
 * Linked by the retarget plugin, the tests and the benchmarks. doc/retargeting.md explains the
 * method; in short:
 *
 * - Set-up (rf_retarget_new, once per clip): world rest transforms of every skeleton, the source
 *   rest pose (the skeleton's, or a frame of its clip when the rest is degenerate), per mapped
 *   target joint and per mapping input an alignment rotation that turns the target's rest bone
 *   directions onto the source's (so a T-pose source drives an A-pose or arms-down target), the
 *   plan of chains of different length (unmapped joints between mapped ones share the rotation),
 *   leg lengths, floors and the root scale. Everything a frame needs is allocated here.
 * - Per frame (rf_retarget_frame): the caller hands in one source pose per sample slot (a slot is
 *   a source clip at a time offset: delays and the half-cycle of mirrored inputs); the frame
 *   function transfers world-space rotations relative to the rests, places the root, and writes
 *   the target's local pose. It allocates nothing, so live input can drive it frame by frame.
 * - Per clip (rf_retarget_clip): the frame range, resampling to an output rate with slerp, the
 *   slots' times, then rf_retarget_contacts pins feet with an IK solver.
 * - Measures (rf_retarget_measure): direction fidelity and foot skate of any target animation
 *   (ours or a peer's) against the sources, with the same definitions everywhere.
 *
 * No joint is ever recognised by name: everything comes from the mapping and the geometry.
 */
#ifndef RF_RETARGET_H
#define RF_RETARGET_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include <rigflow/ik.h>
#include <rigflow/rigflow.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Where the target's floor is (see doc/retargeting.md, "Root motion"). */
typedef enum rf_rt_ground {
    RF_RT_GROUND_AUTO = 0, /* a skeleton whose root rests at the origin (a BVH-style rest with no
                            * placement) has its floor on the origin's plane; any other stands
                            * on the lowest point of its rest pose. A source whose clip's feet
                            * stay away from that floor uses the clip's own floor. */
    RF_RT_GROUND_REST,     /* floors from the lowest rest points (source: of its clip) */
    RF_RT_GROUND_WORLD,    /* both floors on the origin's plane: heights scale from there */
} rf_rt_ground;

typedef struct rf_retarget_options {
    int32_t rest_frame;   /* source rest pose: -1 the skeleton's unless degenerate (every bone
                           * on one line, as with Maya joint orients), then frame 0; >= 0 that
                           * frame of every source clip */
    uint32_t first_frame; /* first source frame (of source 0's clip) */
    int32_t last_frame;   /* last source frame, inclusive; -1 the clip's last */
    double fps;           /* output rate; 0 keeps source 0's */
    bool in_place;        /* no horizontal root motion (height kept) */
    rf_rt_ground ground;
    double root_scale;     /* root motion scale; 0: the leg length (hip height) ratio */
    double cycle;          /* seconds of a motion cycle for mirrored inputs; 0: detected */
    bool contact;          /* pin feet during source contacts (needs an IK solver) */
    double contact_height; /* contact when the source effector is this low over its floor, in
                            * source leg lengths */
    double contact_speed;  /* ... and this slow horizontally, in leg lengths per second */
    double contact_blend;  /* seconds to ease out of a pin */
    bool hold_floor;       /* with a mesh: no higher over the floor than the source, scaled by
                            * the legs, in any frame (rf_retarget_mesh_hold) */
} rf_retarget_options;

/* The defaults: automatic rest, whole clip, source rate, root motion, auto ground, contact pass
 * on with height 0.12, speed 0.6 and 0.15 s of blend, floor held. */
void rf_retarget_options_default(rf_retarget_options *o);

/* One source: a skeleton and its clip (the clip must have the skeleton's joint count). */
typedef struct rf_rt_source {
    const rf_skeleton *skeleton;
    const rf_animation *animation;
} rf_rt_source;

/* The per-clip plan. Opaque. */
typedef struct rf_retarget rf_retarget;

/* Plans retargeting `source_count` sources onto `target` through `mapping` (one entry per target
 * joint; inputs name sources by index in `sources`). Everything is borrowed and must outlive the
 * plan. Returns NULL with a message in err when the inputs disagree (joint counts, indices out of
 * range, no mapped joint) or memory runs out. */
rf_retarget *rf_retarget_new(const rf_rt_source *sources, uint32_t source_count,
                             const rf_skeleton *target, const rf_mapping *mapping,
                             const rf_retarget_options *opts, char *err, size_t err_size);
void rf_retarget_free(rf_retarget *rt);

/* ---- per frame ---- */

/* Sample slots: each is one source pose at a time offset from the output time. */
uint32_t rf_retarget_slot_count(const rf_retarget *rt);
/* The source index of slot `i` and its offset in seconds (negative: the past). */
void rf_retarget_slot(const rf_retarget *rt, uint32_t i, uint32_t *source, double *offset);

/* The pose of one slot for one frame: local rotations [joint][4] (x, y, z, w) and translations
 * [joint][3], laid out as one frame of an rf_animation. (borrowed) */
typedef struct rf_rt_pose {
    const float *rotations;
    const float *translations;
} rf_rt_pose;

/* Retargets one frame: `poses` has one entry per slot; writes the target's local rotations
 * (joint_count x 4) and translations (joint_count x 3). Never allocates. */
void rf_retarget_frame(rf_retarget *rt, const rf_rt_pose *poses, float *rotations,
                       float *translations);

/* ---- per clip ---- */

typedef bool (*rf_rt_progress_fn)(void *user, double fraction); /* false cancels */

/* Retargets the clip range at the output rate. Returns the target animation (transfer full) or
 * NULL with a message in err (cancelled, out of memory). `progress` may be NULL. */
rf_animation *rf_retarget_clip(rf_retarget *rt, rf_rt_progress_fn progress, void *user, char *err,
                               size_t err_size);

/* Time in source 0's clip, in seconds, of output frame 0, and the output rate. */
double rf_retarget_start_time(const rf_retarget *rt);
double rf_retarget_output_fps(const rf_retarget *rt);

/* What the contact pass did. */
typedef struct rf_rt_contact_stats {
    uint32_t effectors;      /* target joints pinned when in contact */
    uint32_t contact_frames; /* effector-frames in contact */
    uint32_t solves;         /* IK calls */
    uint32_t failures;       /* solves the solver refused */
    double max_error;        /* largest residual distance to a pin, target units */
    uint32_t steps;          /* steps of feet driven half a cycle later (the body moved on) */
} rf_rt_contact_stats;

/* Pins the target's end effectors where the source's are in contact, through `solver` (any
 * rf_ik_solver_api: two-bone chains are used). `anim` is the output of rf_retarget_clip for
 * this plan; it is modified in place. Returns false with a message when a solve is refused and
 * the pass cannot go on. */
bool rf_retarget_contacts(rf_retarget *rt, rf_animation *anim, const rf_ik_solver *solver,
                          rf_rt_contact_stats *stats, char *err, size_t err_size);

/* What keeping the parts that are not feet above the floor did. */
typedef struct rf_rt_parts_stats {
    uint32_t frames; /* frames in which a part was lifted */
    uint32_t turns;  /* joints turned to lift one */
} rf_rt_parts_stats;

/* Keeps driven joints that are not feet (high in the aligned rest: wings, tails, a quadruped's
 * chest or head, hands) above the target's floor: a joint whose pivot goes under it is lifted
 * onto it by turning its nearest driven ancestor standing over the floor, the part keeping its
 * horizontal direction. Run after the contact pass on its output. False when out of memory. */
bool rf_retarget_parts_above(rf_retarget *rt, rf_animation *anim, rf_rt_parts_stats *stats);

/* Keeps each driven joint of the target's centerline (spine, neck, tail; not the root-motion
 * joints, not a joint hanging from a placement node, whose turn is the heading) within the turn
 * off its rest that the target's own clip `reference` gives it, plus RF_RT_TURN_SLACK degrees:
 * a neck or a tail made for a small range tears at its seams when a source bends it through its
 * own. Joints the reference never turns are left alone (it says nothing of them). Returns the
 * number of joints limited in at least one frame; -1 when out of memory. */
#define RF_RT_TURN_SLACK 5.0
int rf_retarget_limit_turns(rf_retarget *rt, rf_animation *anim, const rf_animation *reference);

/* ---- facts found at set-up ---- */

typedef struct rf_rt_info {
    double leg_source;   /* source 0's hip height over the lowest point of its rest */
    double leg_target;   /* the target's, in its rest aligned to the source's */
    double root_scale;   /* the scale applied to root motion */
    double floor_source; /* source 0's floor height, along up */
    double floor_target; /* the target's floor height */
    double ground_shift; /* vertical correction of the last clip so its feet sit over the floor
                          * as the source's do (target units) */
    double cycle;        /* seconds, for mirrored inputs (0 when there are none) */
    int32_t rest_frame;  /* the frame source 0's rest came from, or -1 for its skeleton */
    uint32_t mapped;     /* target joints with inputs */
    uint32_t shared;     /* unmapped target joints sharing a chain's rotation */
    uint32_t effectors;  /* candidate end effectors for the contact pass */
    uint32_t dropped;    /* mapping inputs dropped: on target placement, axis or helper joints,
                          * or from source placement or axis joints */
    uint32_t anchored;   /* target joints placed from the body joint they belong to (their
                          * hierarchy parent does not carry them) */
    int32_t top_from;    /* a placement or axis joint whose inputs drive the body's top joint
                          * `top_to` instead (the top had none), or -1 */
    int32_t top_to;
    uint32_t whole;      /* limbs held whole from their roots (wings: rt_rigid_limbs) */
    int32_t whole_first; /* the first such root, or -1 */
} rf_rt_info;

void rf_retarget_info(const rf_retarget *rt, rf_rt_info *info);

/* ---- measures ---- */

#define RF_RT_REPORT_FEET 8

typedef struct rf_rt_report {
    /* Direction fidelity over mapped bones (a target joint and its only mapped child, both
     * driven by one undelayed input from the same source): the angle between the target bone's
     * world direction and the source bone's, per frame. Degrees. */
    double fidelity_mean, fidelity_max, fidelity_p95;
    uint32_t fidelity_bones;
    /* Foot skate: horizontal speed of a target effector while its source counterpart is in
     * contact, in target leg lengths per second (mean over contact frames); the source's own,
     * in source leg lengths per second, for reference. */
    double skate_target, skate_source;
    uint32_t contact_frames; /* effector-frames in contact (with the frame before) */
    /* Ground: mean difference, over contact frames, between the height of the target foot's
     * sole (its lowest joint or bone tip, toes included) over the target floor and the source
     * foot's over the source floor, each in its own leg lengths (0 when the target's feet touch
     * its ground as the source's touch theirs). */
    double ground_error;
    uint32_t frames;
    /* The skate foot by foot, for the first RF_RT_REPORT_FEET feet (of `effectors`): the target
     * joint pinned, its mean speed over its own contact frames (leg lengths per second) and how
     * many there were. One foot sliding hides in the mean over all: a quadruped's forefeet driven
     * half a cycle later against its hind feet. */
    uint32_t effectors;
    uint32_t foot_joint[RF_RT_REPORT_FEET];
    double foot_skate[RF_RT_REPORT_FEET];
    uint32_t foot_frames[RF_RT_REPORT_FEET];
    /* How many of the sources' feet those `effectors` follow (distinct source joints): a
     * quadruped's four feet follow a biped's two. A foot the target lacks (a foreleg whose skin
     * does not reach the floor at rest, driven by the source's arm) shows as fewer `effectors`
     * than a body of its kind has, the source's count unchanged. */
    uint32_t source_feet;
} rf_rt_report;

/* Measures `anim` (a clip for the plan's target whose frame 0 is at time `start` of the source
 * clips, at its own fps) against the plan's sources; a clip longer than 1024 frames on one frame
 * in k (at most 1024 frames, contacts and speeds read on that timeline; `frames` says how many).
 * Works on any such clip, ours or another tool's. Returns false with a message when the clip does
 * not fit the target or memory runs out. */
bool rf_retarget_measure(rf_retarget *rt, const rf_animation *anim, double start,
                         rf_rt_report *report, char *err, size_t err_size);
/* The same, also appending the per-frame figures to `series` (may be NULL) when it is made for
 * anim's frames: direction error (mean and worst bone), each foot's contacts, foot skate. */
bool rf_retarget_measure_series(rf_retarget *rt, const rf_animation *anim, double start,
                                rf_rt_report *report, rf_measures *series, char *err,
                                size_t err_size);

/* ---- measures on the skinned mesh (rt-mesh.c) ---- */

/* What a person sees of a clip on a skinned character, from sampled frames (linear blend
 * skinning of the mesh by the clip's poses). Lengths are fractions of the mesh's rest height
 * (its extent along up when skinned in the skeleton's rest pose). */
typedef struct rf_rt_mesh_report {
    uint32_t frames; /* frames sampled */
    double height;   /* rest height of the mesh, model units */
    uint32_t seams;  /* pairs of vertices close at rest that follow different joints and do not
                      * face each other (two surfaces touching part as the limbs move) */
    double seam_p99; /* torn limbs: p99 over seams and frames of how far apart each pair
                      * drifted from its rest distance */
    double seam_max;
    double floor_median; /* the lowest vertex over the rest floor (lowest rest vertex), per frame,
                          * signed (negative: sinking): the median frame */
    double floor_p95;    /* p95 over frames of its distance from the floor, either way */
    double floating;     /* fraction of frames whose lowest vertex is over 3% above the floor */
    double sinking;      /* ... over 3% below it */
    double parts_below;  /* fraction of frames where a part high at rest (over 15% of the height:
                          * not a foot; a wing, a tail, a head) goes over 1% under the floor */
    double parts_depth;  /* the deepest such part, under the floor */
    uint32_t edges;      /* mesh edges measured */
    double stretch_p99;  /* p99 over edges and frames of |length / rest length - 1| */
    bool rigid; /* the target is a node tree whose meshes hang rigidly on a few nodes (no skin
                 * for the body): the floor figures are of its joints, bone tips and those
                 * meshes, and no seams or edges are measured (rf_retarget_mesh_measure) */
    /* Stretch per part, so one torn limb does not hide in the whole mesh's figure: a part is the
     * vertices one joint carries most (its heaviest weight), and an edge counts in the part of
     * each of its ends, so the edges between two parts, where a limb tears, count in both. Parts
     * with fewer than 12 edges are not measured alone (a handful of edges at a bend is no limb). */
    uint32_t parts;          /* parts measured */
    double part_stretch_p99; /* the worst part's p99 over its edges and frames, as stretch_p99 */
    uint32_t part_joint;     /* the worst part's joint (an index into the skeleton) */
    uint32_t part_edges;     /* the worst part's edges */
    /* Torn limbs per pair of parts, so one limb pulled off its neighbour does not hide in the
     * whole mesh's seams: the seams grouped by the two joints carrying their ends most, each
     * group of 4 seams or more measured alone. */
    uint32_t seam_parts;      /* pairs of parts measured */
    double seam_part_p99;     /* the worst pair's p99 over its seams and frames, as seam_p99 */
    uint32_t seam_joints[2];  /* its two joints (indices into the skeleton, the smaller first) */
    uint32_t seam_part_seams; /* its seams */
    /* Volume kept by the closed loose parts that are solids (rt-volume.c), so a box crushed or
     * flattened between joints, which neither tears nor stretches much, is seen. */
    uint32_t volume_parts; /* parts measured */
    double volume_p95;     /* the worst part's p95 over frames of |volume / rest volume - 1| */
    uint32_t volume_joint; /* the joint carrying most of that part */
} rf_rt_mesh_report;

/* ---- retarget.measure's JSON report (rt-report.c) ---- */

/* The measures as JSON: `r`'s figures, the feet, and "mesh" and "mesh_reference" from clip and
 * ref (each may be NULL: left out), joint names from `s`; a figure that is not finite is null.
 * NULL when out of memory. (transfer full; json_t is jansson's) */
struct json_t;
struct json_t *rf_rt_report_json(const rf_rt_report *r, const rf_rt_mesh_report *clip,
                                 const rf_rt_mesh_report *ref, const rf_skeleton *s);
/* rf_rt_report_json written to f on one line (6 significant digits); false when out of memory
 * or the write fails. */
bool rf_rt_report_write(FILE *f, const rf_rt_report *r, const rf_rt_mesh_report *clip,
                        const rf_rt_mesh_report *ref, const rf_skeleton *s);

/* Whether the target's mesh can stand for the body under a clip of this plan: 1 when it can, 0
 * when it cannot (err says why: not skinned, bound to other joints, skinned to too few joints to
 * stand for the body, or, when `rigid` is given, taken as a node tree's rigid parts: *rigid), -1
 * out of memory. The mesh passes below refuse such a mesh the same way; once it is usable, their
 * false means memory ran out. */
int rf_retarget_mesh_usable(const rf_retarget *rt, const rf_mesh *mesh, const rf_animation *anim,
                            bool *rigid, char *err, size_t err_size);

/* Puts a clip of this plan (rf_retarget_clip's output) on the floor of the target's skinned
 * mesh: the lowest vertex of what stands on the floor at rest (the mesh less its parts over 15%
 * of its height at rest: wings, tails, heads, a quadruped's chest), in the median sampled frame
 * (up to 32 frames spread over the clip), is brought to the lowest vertex of the mesh at rest,
 * by moving the root-motion joints along up (anchored joints follow). Bone tips and joints say
 * where a foot ends only roughly; the mesh is what stands on the floor. It also keeps, per
 * joint, the vertices it carries that reach farthest, so rf_retarget_parts_above keeps the mesh
 * of parts that are not feet over the floor, not only their joints. *shift gets the move
 * (target units along up, may be NULL). False with a message when the mesh is not skinned to
 * the target (the clip is left as it was). */
bool rf_retarget_mesh_floor(rf_retarget *rt, rf_animation *anim, const rf_mesh *mesh, double *shift,
                            char *err, size_t err_size);

/* After the contact pass: in every frame where the lowest vertex of what stands on the floor at
 * rest (rf_retarget_mesh_floor) stands higher over the rest floor than the source's lowest point
 * over its own, scaled by the legs (above all in the source's jumps, where legs of another build
 * posed with the source's turns do not reach down as far as its hips rise), lowers the clip by
 * the difference through the root-motion joints. A frame standing lower is raised only on a body
 * whose feet are all one-bone legs hanging from it (rf_rt_feet_rigid): elsewhere a crouch is the
 * contact pass's, which bends the legs, but a rigid leg cannot be lifted out of the floor, and the
 * animalia cat sank into it through the frames the human's hips dropped (floor p95 12.6% of its
 * height, sinking in 25% of the frames). Read every tenth of a second and interpolated between,
 * so it comes and goes with the difference itself. *lowered gets how many frames were lowered,
 * *deepest the largest lowering (target units), *raised how many frames were raised. False
 * with a message as rf_retarget_mesh_floor. */
bool rf_retarget_mesh_hold(rf_retarget *rt, rf_animation *anim, const rf_mesh *mesh,
                           uint32_t *lowered, double *deepest, uint32_t *raised, char *err,
                           size_t err_size);

/* After rf_retarget_parts_above: when the whole mesh's lowest vertex in the median sampled frame
 * is still under the rest floor (parts the lift could not reach), raises the clip by as much, as
 * the floor did before parts were told apart. *shift gets the rise (0 when none). */
bool rf_retarget_mesh_clear(rf_retarget *rt, rf_animation *anim, const rf_mesh *mesh, double *shift,
                            char *err, size_t err_size);

/* rf_rt_mesh_measure of a clip of this plan (frame 0 at time `start` of the sources). A target
 * whose mesh hangs on too few joints to stand for the body (a node tree carrying a rigid mesh on
 * a node or two) is measured on what a viewer sees of it all the same: its joints, bone tips and
 * those meshes, for the floor only (report->rigid); a rigid part neither tears nor stretches. Its
 * floor
 * figures counted from where the source is: in each sampled frame the target's lowest vertex is
 * compared with the floor raised by how far the source's lowest point is over its own floor,
 * scaled by the legs (a jump is in the air on both sides, and is no float). */
bool rf_retarget_mesh_measure(rf_retarget *rt, const rf_mesh *mesh, const rf_animation *anim,
                              double start, uint32_t max_frames, rf_rt_mesh_report *report,
                              char *err, size_t err_size);

/* Measures `anim` (a clip for `skeleton`) on `mesh` skinned to it, over at most `max_frames`
 * frames spread over the clip (0: 24). `up` is the skeleton's up (zero: the skeleton's own, or
 * +Y). False with a message when the mesh is not skinned to this skeleton or memory runs out. */
bool rf_rt_mesh_measure(const rf_skeleton *skeleton, const rf_mesh *mesh, const rf_animation *anim,
                        rf_vec3 up, uint32_t max_frames, rf_rt_mesh_report *report, char *err,
                        size_t err_size);

#ifdef __cplusplus
}
#endif

#endif
