/* Internals of libretarget shared by its files: the plan made at set-up (rt-plan.c, rt-body.c),
 * read by the frame function (rt-frame.c), the clip driver (rt-clip.c), the contact pass
 * (rt-contact.c) and the measures (rt-measure.c). Names use the rf_rt_ prefix; nothing here is
 * part of any ABI.
 */
#ifndef RF_RT_INTERNAL_H
#define RF_RT_INTERNAL_H

#include <stdatomic.h>

#include "retarget.h"

#define RF_RT_NONE (-1)
#define RF_RT_HULL 14

/* Internal flags of an input, beside the mapping's RF_MAP_* bits. */
enum rf_rt_input_flags {
    RF_RT_IN_CORRECT = 1u << 8, /* swing the delta so the source segment's direction is exact
                                 * (the source segment is not one rigid bone) */
    RF_RT_IN_REFLECT = 1u << 9, /* mirrored from the other side of the body: reflect */
    RF_RT_IN_KIND = 1u << 11,   /* a limb's root driven by a source joint of another kind: it
                                 * takes its turns, not its direction (rt_input_resolve) */
    RF_RT_IN_LEVEL = 1u << 10,  /* a centerline bone of another body plan: its tilt away from
                                 * the source's up is limited (rf_rt_level) */
    RF_RT_IN_PHASE = 1u << 12,  /* a limb driven half a cycle later by the source's limb of its
                                 * own side (a quadruped's foreleg under a biped's leg): another
                                 * pair of legs, whose reach says nothing of the body's height */
    RF_RT_IN_WHOLE = 1u << 13,  /* on the first input of the root of a limb held whole
                                 * (rt_rigid_limbs): its motion swings it against its parent's,
                                 * never twists it, and no farther than whole_limit */
};

/* One mapping input, resolved against its source's rest. */
typedef struct rf_rt_input {
    uint32_t slot;     /* sample slot it reads */
    uint32_t source;   /* source index */
    uint32_t joint;    /* source joint */
    int32_t parent;    /* source joint's parent (for reverse), or -1 */
    int32_t seg_end;   /* source joint ending the primary segment (RF_RT_IN_CORRECT), or -1 */
    rf_vec3 seg_local; /* unit primary segment direction at rest, in the source joint's frame */
    rf_quat align;     /* A: turns the target's rest directions onto this source's */
    rf_quat rest_inv;  /* conj(source rest world rotation) */
    rf_quat C;         /* conj(source rest world rotation) * A */
    rf_quat K;         /* C * target rest world rotation: world rotation = Qs(f) * K */
    rf_quat parent_rest_inv; /* conj of the source parent's rest world rotation (reverse) */
    double weight;           /* normalised over the joint's inputs */
    uint32_t flags;          /* rf_map_flags | rf_rt_input_flags */
    rf_vec3 whole_axis;      /* RF_RT_IN_WHOLE: the limb's reach at rest, aligned, unit */
    double whole_limit;      /* RF_RT_IN_WHOLE: the swing its reach leaves it over the floor */
} rf_rt_input;

typedef enum rf_rt_kind {
    RF_RT_REST = 0, /* keeps its rest local rotation (unmapped leaves, joints above the body) */
    RF_RT_MAPPED,   /* driven by its inputs */
    RF_RT_SHARED,   /* unmapped between mapped joints: takes a share of the chain's rotation */
} rf_rt_kind;

/* One joint of a chain whose rotation is shared: the owner first, then the unmapped joints. */
typedef struct rf_rt_link {
    uint32_t joint;
    double share; /* cumulative fraction of the chain's rotation, (0, 1] */
    rf_vec3 bone; /* rest world vector to the next link (or the chain's end), aligned by A */
} rf_rt_link;

typedef struct rf_rt_tjoint {
    uint8_t kind;     /* rf_rt_kind */
    bool root_motion; /* a top mapped joint: its translation carries the root motion */
    bool translate;   /* another mapped joint whose source translation is animated */
    int32_t parent;
    uint32_t first_input, input_count; /* MAPPED */
    int32_t owner; /* SHARED: the mapped joint owning the chain; MAPPED: itself when it owns
                    * a shared chain, else -1 */
    uint32_t first_link, link_count; /* owners: the chain (rf_retarget.links) */
    double share;                    /* MAPPED owner and SHARED: this joint's cumulative share */
    rf_vec3 chord;      /* owners: rest world vector from the owner to the chain's end, unit */
    rf_quat rest_local; /* rest local rotation */
    rf_quat rest_world; /* rest world rotation */
    rf_quat align;      /* MAPPED: the inputs' alignments blended (constant) */
    rf_xform parent_world_inv; /* root_motion: inverse rest world transform of the parent */
} rf_rt_tjoint;

/* A sample slot: one source at one time offset. */
typedef struct rf_rt_slot {
    uint32_t source;
    double offset; /* seconds added to the output time */
    double wrap;   /* mirrored inputs: the cycle, subtracted when the time runs past the clip */
} rf_rt_slot;

/* Per source, found at set-up. */
typedef struct rf_rt_src {
    const rf_skeleton *skel;
    const rf_animation *anim;
    uint32_t n;
    int32_t rest_frame;   /* -1: the skeleton's rest */
    rf_xform *rest_local; /* [n] the rest pose used (skeleton's or the frame's) */
    rf_xform *rest_world; /* [n] */
    rf_vec3 *skel_pos;    /* [n] world positions of the skeleton's own rest (root placement) */
    rf_vec3 *tip;         /* [n] bone tips in the joint's local rest frame (end sites, children or
                           * a guess from the analysis), zero when none */
    uint8_t *need_pos;    /* [n] the frame function needs this joint's world position */
    int32_t *parent;      /* [n] parents, packed for the frame loop */
    uint8_t *need_rot;    /* [n] the frame function needs this joint's world rotation */
    rf_vec3 up, forward, left; /* body axes (unit, orthogonal) */
    rf_quat turn;              /* turns the source's world into the target's (the inverse of the
                                * body turn, about the origin): every world pose of the source
                                * is read turned by it, at its roots (rf_rt_source_root) */
    rf_vec3 center;            /* a point on the symmetry plane */
    double size;               /* extent of the rest pose (tolerances) */
    double leg;                /* hip height over the lowest rest point */
    bool on_legs;              /* its hips stand over a quarter of its rest's height */
    double lowest;             /* that lowest point's height along up */
    double floor;              /* floor height along up (rf_rt_over_floor counts from it) */
    double stand;              /* the floor once the target's is measured on its mesh
                                * (rf_rt_floors_measured): where it stands in its clip
                                * (rt_clip_floor) for a rest hanging from the origin, else
                                * floor */
    uint8_t *above;            /* [n] joints above the hips (placement roots): never its lowest
                                * point */
    double scale;              /* root motion scale for this source */
} rf_rt_src;

/* The world transform of a source root joint whose local transform is `local`: turned into the
 * target's frame. */
static inline rf_xform rf_rt_source_root(const rf_rt_src *src, rf_xform local)
{
    local.t = rf_quat_rotate(src->turn, local.t);
    local.r = rf_quat_mul(src->turn, local.r);
    return local;
}

/* The scratch of one thread's frames, allocated once per thread and clip. */
typedef struct rf_rt_work {
    rf_quat *q;          /* [n] target world rotations */
    rf_quat *chain_rot;  /* [n] owners: the chain's own rotation solved this frame */
    rf_quat *chain_base; /* [n] owners: the motion of the owner's parent this frame */
    rf_quat **s_rot;     /* [slot][source n] source world rotations */
    rf_vec3 **s_pos;     /* [slot][source n] source world positions (joints with need_pos) */
    rf_rt_pose *poses;   /* [slot] the clip driver's poses */
    float *scratch_rot;  /* [slot][max source n][4] sampled poses */
    float *scratch_tr;   /* [slot][max source n][3] */
    rf_xform *tw;        /* [n] target world transforms (the placement of anchored joints) */
} rf_rt_work;

struct rf_retarget {
    rf_retarget_options opt;
    const rf_skeleton *target;
    const rf_mapping *mapping; /* the caller's, less inputs on or from placement and axis
                                * joints (own_map) */
    rf_mapping *own_map;
    uint32_t source_count;
    rf_rt_src *src;

    uint32_t n; /* target joints */
    rf_rt_tjoint *tj;
    rf_rt_input *in;
    uint32_t input_count;
    rf_rt_link *links;
    uint32_t link_count;
    rf_rt_slot *slots;
    uint32_t slot_count;

    rf_vec3 up;                     /* the target's up (unit) */
    rf_vec3 forward, left, center;  /* the target's body axes and symmetry plane */
    uint8_t *t_centerline;          /* [n] the joint lies on the target's centerline (analysis) */
    int32_t *t_mirror;              /* [n] the joint mirrored across the target's symmetry plane
                                     * (analysis), or RF_RT_NONE */
    int32_t *t_logical;             /* [n] parents in the target's analysed tree */
    uint8_t *t_role;                /* [n] rf_joint_role of every target joint */
    struct rf_joint_roles *t_roles; /* the target's roles while the plan is made */

    /* Joints their hierarchy parent does not carry (rt-roles.c): a foot under a placement root,
     * a limb that is a root of its own, an IK target or pole. Each is placed every frame from
     * the body joint it belongs to, rigidly as at rest. */
    int32_t *lparent;       /* [n] the body parent: the anchor, or the hierarchy parent */
    int32_t *anchor;        /* [n] the body joint placing it, or -1 (its parent carries it) */
    rf_xform *anchor_off;   /* [n] anchored joints: rest transform in the anchor's frame */
    uint32_t *lorder;       /* [n] every joint after its hierarchy parent and its anchor */
    uint32_t anchored;      /* joints with an anchor */
    uint8_t *t_need;        /* [n] world transforms the placement reads (anchors, parents) */
    uint8_t *t_tip_set;     /* [n] tips set to where a part placed from the joint begins */
    uint32_t dropped;       /* mapping inputs dropped (on or from placement and axis joints) */
    int32_t top_from;       /* a frame joint whose inputs drive the body's top, or -1 */
    int32_t top_to;         /* that top joint, or -1 */
    bool t_degenerate;      /* the target's rest is no body: align every bone */
    bool plan_differs;      /* the bodies lie differently (an upright biped onto a level
                             * quadruped): centerline bones keep their own rest directions */
    uint32_t t_hip;         /* the target's hips: the joint its legs are measured from */
    bool level_flat;        /* the target stands on legs driven half a cycle later too
                             * (RF_RT_IN_PHASE): its levelled centerline takes no lean */
    double size;            /* extent of the target's rest (tolerances) */
    rf_vec3 t_own_up;       /* the analysis's up of the target's rest (from its limbs), which a
                             * rest lying across the file's up does not share */
    rf_xform *t_rest_world; /* [n] the target's rest */
    rf_vec3 *t_tip;         /* [n] target bone tips in the joint's local frame, zero when none */
    rf_vec3 *t_hull;        /* [n][RF_RT_HULL] with a skinned mesh (rf_retarget_mesh_floor): the
                             * vertices each joint carries most that reach farthest along 14
                             * directions, in its rest frame (its pivot when it carries none);
                             * NULL without */
    double mesh_floor;      /* with t_hull: the rest mesh's lowest vertex along up */
    int32_t *t_whole;       /* [n] the root of the limb that moves whole with the joint
                             * (rt_rigid_limbs: a wing held at its rest turns past its root), the
                             * root itself included, or -1 */
    double leg_target;      /* hip height in the aligned rest */
    rf_vec3 *t_aligned;     /* [n] world positions in the aligned rest (the target posed like the
                             * sources' rests) */
    double aligned_low;     /* lowest height of that pose */
    uint8_t *t_above;       /* [n] placement joints above the target's hips */
    double floor_target;
    double t_rest_low;   /* the lowest point of the target's rest (joints and bone tips of the
                          * body below its placement joints), along up */
    double ground_shift; /* the clip's vertical correction (rf_rt_ground_fix), target units */
    double cycle;
    bool root_motion_on; /* false while measuring the aligned rest */

    /* Measure and contact definitions (rt-plan.c). */
    uint32_t *bones; /* pairs (target joint, its only mapped child) measured for fidelity */
    uint32_t bone_count;
    uint32_t *effectors; /* target end effectors (feet) */
    uint32_t effector_count;
    uint32_t *effector_src; /* [effector] the source joint whose contacts it follows */
    uint8_t *effector_tip;  /* [effector] the foot is the joint's bone tip (a horse's leg of two
                             * bones): pinned with the joint and the one above as the chain */

    /* What the frame loop reads per target joint, packed (rt-frame.c). */
    struct rf_rt_hot *hot;
    float *rest_tr;  /* [n][3] the target's rest translations, as output rows */
    rf_quat *w0;     /* [n] world rotations of the aligned rest, or NULL while it is made */
    rf_rt_work work; /* the scratch of rf_retarget_frame (the clip driver's helper thread
                      * has its own) */
    uint32_t max_src_n;
};

/* ---- rt-plan.c ---- */
/* Whether the output clip of joints x frames fits in `left` bytes of memory (when `known`);
 * if not, says in err how much it would take and what to change. */
bool rf_rt_output_fits(uint32_t joints, uint32_t frames, bool known, uint64_t left, char *err,
                       size_t err_size);
void rf_rt_fail(char *err, size_t err_size, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* ---- rt-body.c: rests, tips, axes, leg lengths, floors ---- */
/* Picks each source's rest, world rests, tips and axes. */
bool rf_rt_sources_prepare(rf_retarget *rt, char *err, size_t err_size);
/* Target rest, tips and up. */
bool rf_rt_target_prepare(rf_retarget *rt, char *err, size_t err_size);
/* Leg lengths, floors and root scales (after the plan is complete). */
bool rf_rt_ground_prepare(rf_retarget *rt, char *err, size_t err_size);
/* Moves the root-motion joints of a clip up or down so its lowest points sit over the target's
 * floor as the source's do over theirs. False when out of memory. */
bool rf_rt_ground_fix(rf_retarget *rt, rf_animation *out);
/* Whether the skeleton's unweighted flags say which joints are body: a skin on fewer than a
 * quarter of the joints (a node tree with a mesh hung on one or two nodes) says nothing, and
 * every joint then counts. */
bool rf_rt_weights_known(const rf_skeleton *s);
/* The lowest and highest points of a pose along up, into *low and *high: each counted joint's
 * pivot and bone tip (tip[j] in j's frame; a zero tip is none). A joint counts unless `skip`
 * (may be NULL) marks it or, with `weighted` and a skin that says which joints carry it
 * (rf_rt_weights_known), it carries none. False, *low INFINITY and *high -INFINITY, when no
 * joint counts. One walk for the floors, the legs' and bodies' heights and the reaches. */
bool rf_rt_span(const rf_skeleton *s, const rf_xform *world, const rf_vec3 *tip, rf_vec3 up,
                const uint8_t *skip, bool weighted, double *low, double *high);
/* With the target's skinned mesh its floor is measured (its lowest vertex at rest), not taken
 * from a convention; each source's floor is then measured too: where it stands in its clip
 * (the 5th percentile of its lowest points), not its rest's origin plane. CMU's BVH hangs its
 * body from the origin, but its toes stand 2-5% of its height over that plane in most frames:
 * counted from it, the contact pass kept a target's feet that high over the mesh's floor while
 * the parts pass held parts on the floor itself, and the measure read either as wrong. A rest
 * standing on its lowest point measures its floor already and keeps it. Without
 * a mesh both sides keep their rests' floors, so a skeleton retargeted onto itself gives back
 * its clip exactly. */
void rf_rt_floors_measured(rf_retarget *rt);
/* How far source k posed in `world` stands over its floor, in its leg lengths: its lowest point
 * (joints and bone tips; unweighted helpers and joints above the hips left out) or, for j >= 0,
 * the sole of joint j (it and what hangs from it). The one measure of the source's height over
 * the ground that the contact pass, the parts pass, the mesh floor and the measures share. */
double rf_rt_over_floor(const rf_retarget *rt, uint32_t k, const rf_xform *world, int32_t j);
/* How far source 0 stands over its floor (rf_rt_over_floor, never below 0) at `count` output
 * frames (frame[i], or i when frame is NULL; time start + frame / fps), scaled by the legs into
 * target units: how far over the target's floor the target should stand then (in a jump too).
 * False when out of memory. */
bool rf_rt_clearance(const rf_retarget *rt, double start, double fps, uint32_t count,
                     const uint32_t *frame, double *out);
/* Moves the root-motion joints of every frame of `out` by `shift` along up (the anchored joints
 * placed again after). False when out of memory. */
/* Hands a root-motion joint's horizontal motion up to the unmapped joints carrying skin above it
 * (rt-body.c). */
bool rf_rt_carry_root(rf_retarget *rt, rf_animation *out);
bool rf_rt_lift(rf_retarget *rt, rf_animation *out, double shift);
/* ... by shift[f] in frame f (one a frame). */
bool rf_rt_lift_each(rf_retarget *rt, rf_animation *out, const double *shift);
/* Below this many joint-frames a second thread costs more than it saves. */
#define RT_THREAD_MIN 65536

/* A long clip's frames shared between two threads in chunks of RT_CHUNK, taken in order from a
 * counter (rf_rt_chunk) rather than in fixed halves: on a busy machine a new thread started
 * 1-3 ms late (measured), and the thread that had finished its half waited for the other's whole
 * half at the join; now it takes more chunks. A frame is computed the same whichever thread
 * takes it. */
#define RT_CHUNK 256
typedef struct rf_rt_chunks {
    atomic_ullong next;
    uint32_t end;
} rf_rt_chunks;

static inline void rf_rt_chunks_init(rf_rt_chunks *c, uint32_t end)
{
    atomic_init(&c->next, 0);
    c->end = end;
}
/* The next chunk of frames [*first, *end); false when none is left. */
static inline bool rf_rt_chunk(rf_rt_chunks *c, uint32_t *first, uint32_t *end)
{
    unsigned long long f = atomic_fetch_add_explicit(&c->next, RT_CHUNK, memory_order_relaxed);
    if (f >= c->end)
        return false;
    *first = (uint32_t)f;
    *end = f + RT_CHUNK < c->end ? (uint32_t)(f + RT_CHUNK) : c->end;
    return true;
}
/* Ends the sharing early: later calls find nothing left. */
static inline void rf_rt_chunks_stop(rf_rt_chunks *c)
{
    atomic_store_explicit(&c->next, c->end, memory_order_relaxed);
}

/* A value keyed for sorting (a grid cell, an edge by its two vertices) and its qsort order by
 * key (rt-mesh.c). */
typedef struct rf_rt_cell {
    uint64_t key;
    uint32_t v;
} rf_rt_cell;
int rf_rt_cmp_cell(const void *a, const void *b);

/* The k-th smallest of `count` values, reordering them (rt-mesh.c). */
double rf_rt_select(double *v, size_t count, size_t k);

/* The closed loose parts of a skinned mesh that are solids of some size, for the volume each
 * keeps as a clip poses it (rt-volume.c). Vertices at the same position are welded to tell
 * closed from open; a part is its triangles first[p] .. first[p + 1] of tris[]. */
typedef struct rf_rt_volumes {
    uint32_t parts;
    uint32_t *first;  /* [parts + 1] */
    uint32_t *tris;   /* triangles by part */
    uint32_t *origin; /* [part] a vertex of it, the volumes taken about it */
    uint32_t *joint;  /* [part] the joint carrying most of its vertices */
    double *rest;     /* [part] signed volume at rest */
    uint8_t *keep;    /* [part] measured: a solid (rest volume at least 5% of its box's) whose
                       * box's diagonal is 2% of the height or more */
} rf_rt_volumes;

/* The parts of mesh m (rest: its vertices at rest; joints: the skeleton's count; height: the
 * mesh's) into v; false when out of memory (v empty). A mesh without triangles has none. */
bool rf_rt_volumes_find(const rf_mesh *m, const rf_vec3 *rest, uint32_t joints, double height,
                        rf_rt_volumes *v);
/* Each part's |volume / rest volume - 1| with the vertices at pos into off[part] (0 where not
 * measured). */
void rf_rt_volumes_at(const rf_rt_volumes *v, const rf_mesh *m, const rf_vec3 *pos, double *off);
void rf_rt_volumes_free(rf_rt_volumes *v);
/* A value with its weight (rf_rt_weighted_quantile). */
typedef struct rf_rt_weighted {
    double value, weight;
} rf_rt_weighted;
/* The weighted q-quantile of `count` values (reordering them): the least value whose weight with
 * that of every smaller value reaches q of the whole weight; 0 without values (rt-mesh.c). */
double rf_rt_weighted_quantile(rf_rt_weighted *v, size_t count, double q);
/* Height of the lowest point of joint j and everything below it (joints and bone tips, `tip`
 * in each joint's frame): the sole of a foot, toes included. */
double rf_rt_sole(const rf_skeleton *s, const rf_xform *world, const rf_vec3 *tip, rf_vec3 up,
                  uint32_t j);
/* Joint j and everything below it, in their order in the skeleton, into below[] (room for the
 * skeleton's joint count): what rf_rt_sole reads, listed once for a sole read at every frame. */
uint32_t rf_rt_below(const rf_skeleton *s, uint32_t j, uint32_t *below);
/* rf_rt_over_floor of source k's joint `below[0]` from its rf_rt_below list: the same value. */
double rf_rt_over_floor_below(const rf_retarget *rt, uint32_t k, const rf_xform *world,
                              const uint32_t *below, uint32_t count);
/* Height of p along up. */
static inline double rf_rt_height(rf_vec3 up, rf_vec3 p)
{
    return rf_v3_dot(up, p);
}
/* p without its component along up. */
static inline rf_vec3 rf_rt_horizontal(rf_vec3 up, rf_vec3 p)
{
    return rf_v3_sub(p, rf_v3_scale(up, rf_v3_dot(up, p)));
}

/* ---- rt-roles.c ---- */
/* Joint roles of the target and the sources, the mapping without placement and axis joints,
 * body parents and anchors. */
bool rf_rt_roles_prepare(rf_retarget *rt, char *err, size_t err_size);
/* Places the anchored joints of one frame: `rotations`/`translations` hold the hierarchy local
 * pose (rf_animation layout), `q` the world rotations of the mapped joints; world transforms go
 * to `tw`. Rewrites the anchored joints' local pose. */
void rf_rt_place_anchored(const rf_retarget *rt, float *rotations, float *translations,
                          const rf_quat *q, rf_xform *tw);
/* True when joint a is j or a hierarchy ancestor of j. */
bool rf_rt_carries(const rf_skeleton *s, int32_t a, uint32_t j);
/* Where effector e touches the floor in `world`: its joint, or its bone's tip. */
rf_vec3 rf_rt_effector_point(const rf_retarget *rt, const rf_xform *world, uint32_t e);

/* ---- rt-frame.c ---- */
/* Allocates w for the plan (false when out of memory); frees it. */
bool rf_rt_work_init(const rf_retarget *rt, rf_rt_work *w);
void rf_rt_work_free(const rf_retarget *rt, rf_rt_work *w);
/* Packs the frame loop's per-joint data (after the plan is complete). False when out of
 * memory. */
bool rf_rt_hot_init(rf_retarget *rt);
/* rf_retarget_frame with a given scratch. */
void rf_rt_frame(const rf_retarget *rt, rf_rt_work *w, const rf_rt_pose *poses, float *rotations,
                 float *translations);
/* The quaternion power q^t along the shorter arc. */
rf_quat rf_rt_quat_pow(rf_quat q, double t);
/* The world delta d with its tilt away from up eased into `limit` radians (none at 0), its turn
 * about up kept. */
rf_quat rf_rt_level(rf_quat d, rf_vec3 up, double limit);
/* The rotation about unit axis n that best turns the vectors a[i] onto b[i] (both already
 * perpendicular to n or not: only the parts perpendicular to n count). */
double rf_rt_twist_fit(rf_vec3 n, const rf_vec3 *a, const rf_vec3 *b, uint32_t count);
/* Reflects a rotation through the plane whose unit normal is n. */
static inline rf_quat rf_rt_reflect(rf_quat q, rf_vec3 n)
{
    rf_vec3 v = rf_v3(q.x, q.y, q.z);
    rf_vec3 r = rf_v3_sub(rf_v3_scale(n, 2 * rf_v3_dot(v, n)), v);
    return rf_quat_make(r.x, r.y, r.z, q.w);
}
/* Reflects a vector through the plane whose unit normal is n. */
static inline rf_vec3 rf_rt_reflect_v(rf_vec3 v, rf_vec3 n)
{
    return rf_v3_sub(v, rf_v3_scale(n, 2 * rf_v3_dot(v, n)));
}
/* Reflects a point through the plane through `center` whose unit normal is n. */
static inline rf_vec3 rf_rt_reflect_p(rf_vec3 p, rf_vec3 center, rf_vec3 n)
{
    return rf_v3_add(center, rf_rt_reflect_v(rf_v3_sub(p, center), n));
}

/* ---- rt-clip.c ---- */
/* The time slot s samples its source at for output time t (its offset; a mirrored slot's time
 * past the clip's end comes back a cycle). */
double rf_rt_slot_time(const rf_retarget *rt, uint32_t s, double t);
/* Samples source `k`'s clip at time t (seconds, clamped to the clip) into rot/tr (one frame). */
void rf_rt_sample(const rf_animation *a, double t, float *rot, float *tr);
/* Local pose of every target joint for frame f of anim, then world transforms into world. */
void rf_rt_target_fk(const rf_retarget *rt, const rf_animation *anim, uint32_t f, rf_xform *world);
/* World transforms of source k at time t (sampled), into world (scratch local of n entries). */
void rf_rt_source_world(const rf_retarget *rt, uint32_t k, double t, rf_xform *local,
                        rf_xform *world, float *rot, float *tr);
/* The same for the joints in `need` only (a joint's ancestors must be in it; NULL: all). */
void rf_rt_source_world_some(const rf_retarget *rt, uint32_t k, double t, rf_xform *local,
                             rf_xform *world, float *rot, float *tr, const uint8_t *need);
/* A source pose's scratch: local and world transforms, sampled rotations and translations. */
typedef struct rf_rt_source_pose {
    rf_xform *local, *world;
    float *rot, *tr;
} rf_rt_source_pose;
/* rf_rt_source_world_some at two times at once, each into its own pose: the same operations for
 * each, interleaved joint by joint, so the processor overlaps the two poses' chains (each joint
 * waits on its parent's world rotation, a square root and four divisions away). */
void rf_rt_source_world_two(const rf_retarget *rt, uint32_t k, const double t[2],
                            rf_rt_source_pose pose[2], const uint8_t *need);

/* ---- rt-contact.c ---- */
/* Per effector and output frame: 1 when the source counterpart is in contact ([eff][frames],
 * transfer full), and when not NULL the source effectors' world positions and the heights of
 * their soles over the source floor in source leg lengths ([eff][frames], the caller's); each
 * at the time its input samples the source. NULL when out of memory. */
uint8_t *rf_rt_detect_contacts(const rf_retarget *rt, uint32_t frames, double fps, double start,
                               rf_vec3 *src_pos, double *src_sole);
/* Whether effector e is a foot driven half a cycle later (RF_RT_IN_PHASE) that steps: its contacts
 * are its own motion's (rf_rt_phase_contacts), not its source's. */
bool rf_rt_effector_steps(const rf_retarget *rt, uint32_t e);
/* Whether the target stands on feet that are all one-bone legs hanging from the body (aimed about
 * their pivots by the contact pass, never bent): none of them can be lifted out of the floor. */
bool rf_rt_feet_rigid(const rf_retarget *rt);
/* The contacts of the feet driven half a cycle later (RF_RT_IN_PHASE) in `contact` replaced by
 * where their own motion is down: sole ([eff][frames], heights along up of the target feet's
 * soles in the clip read) within contact_height leg lengths of the target's floor. */
bool rf_rt_phase_contacts(const rf_retarget *rt, uint32_t frames, double fps, const double *sole,
                          uint8_t *contact);
/* Picks the end effectors (rt->effectors) from the aligned rest. */
bool rf_rt_effectors_prepare(rf_retarget *rt);
/* ---- rt-clip.c ---- */
double rf_rt_detect_cycle(const rf_retarget *rt, uint32_t k);
/* The source joint driving target effector e (its first input), and its source index. */
void rf_rt_effector_source(const rf_retarget *rt, uint32_t e, uint32_t *source, uint32_t *joint);

#endif
