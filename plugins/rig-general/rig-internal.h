/* Internal interfaces of librigauto, between mesh clean-up, skeleton extraction and bone heat. */
#ifndef RF_RIG_INTERNAL_H
#define RF_RIG_INTERNAL_H

#include <stdio.h>

#include "rig.h"

#define RF_RIG_NONE UINT32_MAX

#if defined(__GNUC__) || defined(__clang__)
#define RF_RIG_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define RF_RIG_PRINTF(a, b)
#endif

/* A triangle mesh in doubles. */
typedef struct rf_rig_geo {
    uint32_t nv, nt;
    double *p;   /* [nv][3] */
    uint32_t *t; /* [nt][3] */
} rf_rig_geo;

/* The cleaned mesh and how each input vertex reaches the proxy the work is done on. */
typedef struct rf_rig_prep {
    rf_rig_geo proxy;     /* welded, specks removed, simplified when big */
    uint32_t *to_proxy;   /* [input vertex] proxy vertex whose weights it takes, or NONE (speck,
                           * stray vertex: weighted like the proxy vertex nearest it) */
    double lo[3], hi[3];  /* bounding box of the proxy */
    double longest;       /* its longest edge, > 0 */
    uint32_t *proxy_part; /* [proxy vertex] loose part */
    uint32_t proxy_parts;
} rf_rig_prep;

/* The skeleton in world positions while it is built. */
typedef struct rf_rig_skel {
    uint32_t n;
    double *pos;     /* [n][3] world pivot */
    int32_t *parent; /* [n], parents first */
    double *tip;     /* [n][3] end of a leaf's bone */
    uint8_t *has_tip;
    uint8_t *owns_in; /* [n] or NULL: the bone from the joint's parent moves the joint itself */
} rf_rig_skel;

/* A bone for weighting: the segment a..b moved by joint `joint`. */
typedef struct rf_rig_bone {
    double a[3], b[3];
    uint32_t joint;
} rf_rig_bone;

/* A binary min-heap of (key, id) for Dijkstra's algorithm; stale entries are skipped by the
 * caller (lazy deletion). */
typedef struct rf_rig_heap {
    size_t n, cap;
    double *key;
    uint32_t *id;
} rf_rig_heap;
bool rf_rig_heap_push(rf_rig_heap *h, double key, uint32_t id);
bool rf_rig_heap_pop(rf_rig_heap *h, double *key, uint32_t *id);
void rf_rig_heap_free(rf_rig_heap *h);

/* printf into err; returns false so callers can `return rf_rig_fail(...)`. */
bool rf_rig_fail(char *err, size_t n, const char *fmt, ...) RF_RIG_PRINTF(3, 4);

/* How a step of the rigger ended, returned beside the reason it writes into err. A lack of
 * memory is no fact about the body: a caller that would read a failed step as an answer (no up
 * found, the other first pass kept) passes it on instead (rig.c, rig-frame.c). */
typedef enum rf_rig_status {
    RF_RIG_OK = 0,
    RF_RIG_REFUSED,   /* the body cannot be rigged so: err says why */
    RF_RIG_NO_MEMORY, /* an allocation failed: err says in which step */
} rf_rig_status;
/* printf into err; return RF_RIG_REFUSED and RF_RIG_NO_MEMORY, for `return rf_rig_oom(...)`. */
rf_rig_status rf_rig_refuse(char *err, size_t n, const char *fmt, ...) RF_RIG_PRINTF(3, 4);
rf_rig_status rf_rig_oom(char *err, size_t n, const char *fmt, ...) RF_RIG_PRINTF(3, 4);

/* Whether cleaning and weighting a mesh of this size fits in `available` bytes (when `known`);
 * if not, says in err how much it needs and what to do. */
bool rf_rig_memory_fits(uint64_t vertices, uint64_t triangles, bool known, uint64_t available,
                        char *err, size_t n);
/* Whether bone heat over `vertices` proxy vertices for `joints` joints fits the same way. */
bool rf_rig_heat_fits(uint64_t vertices, uint64_t joints, bool known, uint64_t available, char *err,
                      size_t n);
/* The mesh checked and cleaned into out (rf_rig_prep); on failure nothing is held. */
rf_rig_status rf_rig_prepare(const rf_mesh *m, const rf_rig_options *o, rf_rig_prep *out,
                             rf_rig_stats *st, char *err, size_t n);
void rf_rig_prep_free(rf_rig_prep *p);

/* The frame a mesh is rigged in (rig-frame.c): the file's up as y and its forward, or the body's
 * longest principal axis across up, as z, so the voxel grid meets a body the same way at any
 * facing. */
typedef struct rf_rig_frame {
    rf_quat q;                    /* the file's axes into the frame's */
    bool turned;                  /* false: the file's own axes */
    float *positions;             /* the turned positions `in` borrows; owned */
    bool up_assumed;              /* the file declares no up and the body showed none: +y assumed */
    char up_note[RF_RIG_UP_NOTE]; /* how the up was found when the file declares none, or "" */
} rf_rig_frame;
/* The up of a body whose file declares none (rig-frame.c): the general rigger's curve skeleton
 * made in the file's axes, read by the skeleton analysis and snapped to the nearest of the
 * file's six axis directions, taken when the analysis is sure enough and the body stands over
 * its lowest points along it. */
typedef struct rf_rig_up {
    rf_vec3 axis;       /* the axis direction the analysis read, snapped; zero when none */
    bool found;         /* axis is the body's up */
    rf_vec3 read;       /* the analysis's up before snapping (zero when it could not run) */
    double confidence;  /* the analysis's up_confidence */
    double support;     /* rf_rig_support along axis (NAN without one, or without a footprint) */
    const char *source; /* the analysis's up_source, or why there is none (static) */
    char why[200];      /* when no curve skeleton could be read: the rigger's reason, else "" */
    bool narrow;        /* found under the standing bar by a sure reading (rf_rig_read_narrow) */
} rf_rig_up;
/* False when out of memory (out then holds nothing found). */
bool rf_rig_body_up(const rf_mesh *m, const rf_rig_options *o, rf_rig_up *out);
/* How squarely m stands over its lowest points under up u (positive: its centre over them),
 * as a fraction of its footprint's size, into *margin: NAN when its lowest points or its
 * footprint make no area. False when out of memory. */
bool rf_rig_support(const rf_mesh *m, rf_vec3 u, double *margin);

/* The mesh as the rigger sees it in its frame: *in borrows mesh's arrays but the positions, and
 * o is opts with up and forward turned. False when out of memory. */
bool rf_rig_frame_enter(const rf_mesh *mesh, const rf_rig_options *opts, rf_rig_frame *f,
                        rf_mesh *in, rf_rig_options *o);
/* What the frame decided about up, into st (may be NULL). */
void rf_rig_frame_stats(const rf_rig_frame *f, rf_rig_stats *st);
/* The rig made in the frame turned back to the file's axes: s's joints, end sites and axes;
 * skinned's positions (mesh's again) and inverse binds. Either may be NULL. Frees f's copy. */
void rf_rig_frame_leave(rf_rig_frame *f, const rf_mesh *mesh, rf_skeleton *s, rf_mesh *skinned);

/* The facing the skeleton analysis reads on the general rigger's rig of the prepared body p
 * (its curve skeleton k laid out on a copy by rf_rig_general_place, read with o's up and
 * forward as hints, as the general rigger's rig is named), made level; zero into *out when it
 * lies along up. False when out of memory. */
bool rf_rig_placed_facing(const rf_rig_prep *p, const rf_rig_skel *k, const rf_rig_options *o,
                          rf_vec3 *out);

/* The facing of the prepared body p (o: its frame's up, no forward declared) the skeleton
 * analysis reads on the general rigger's skeletons of it turned by each quarter turn about up,
 * pooled; zero into *out when none is read. k is the general rigger's curve skeleton of p
 * unturned (read with its limbs laid on a copy: rf_rig_general_place), or NULL to have it made
 * here (the template rigger). False when out of memory. */
bool rf_rig_pooled_facing(const rf_rig_prep *p, const rf_rig_skel *k, const rf_rig_options *o,
                          rf_vec3 *out);

/* The curve skeleton; its root at the thickest point, or at the solid voxel nearest `seed` when
 * seed is not NULL. The body's mirror plane into mirror[4] when not NULL: points p with
 * mirror[0..2] . p = mirror[3], the normal zero when the body has none. Into stand[4] when not
 * NULL: where a pair of legs the bands misjudged as bumps leaves the body (rf_rig_stands_on),
 * stand[3] 1 when there is one, else 0. */
rf_rig_status rf_rig_extract(const rf_rig_prep *p, const rf_rig_options *o, const double *seed,
                             double *mirror, double *stand, rf_rig_skel *out, char *err, size_t n);
void rf_rig_skel_free(rf_rig_skel *s);
/* A copy of k into *out; false (out empty) when out of memory. */
bool rf_rig_skel_copy(const rf_rig_skel *k, rf_rig_skel *out);

/* The bones of a skeleton (one per parent-child pair and per leaf tip; a lone joint is a point).
 * Returns the count, *out malloc'd, or 0 when out of memory. */
uint32_t rf_rig_bones(const rf_rig_skel *s, rf_rig_bone **out);

/* Distance from point q to segment b, and the closest point into c. */
double rf_rig_seg_dist(const double q[3], const rf_rig_bone *b, double c[3]);

/* Every leaf joint of k without an end site and with a parent gets one (has_tip set): on from
 * the joint along its bone's axis (axis[joint * 3], unit, in world; zero or axis NULL: its
 * parent's direction) as far as its parent's bone is long. With axes, a bone to a child on its
 * parent's axis is the parent's (owns_in cleared) and a joint with no child on its axis gets a
 * bone along it (rig-heat.c). False when out of memory. */
bool rf_rig_leaf_tips(const rf_rig_prep *p, rf_rig_skel *k, const double *axis);

/* A grid over the proxy's vertices, for the vertex nearest a point (rig-heat.c). */
typedef struct rf_rig_near rf_rig_near;
rf_rig_near *rf_rig_near_new(const rf_rig_prep *p); /* NULL when out of memory */
void rf_rig_near_free(rf_rig_near *gr);
uint32_t rf_rig_near_vertex(const rf_rig_near *gr, const double q[3]); /* NONE: no vertex */

/* Bone-heat weights on the proxy: w[vertex * joints + joint], rows summing to 1. boxed ([joints],
 * zeroed, or NULL) gets the joints inside a low-poly box that one joint above them moves alone. */
bool rf_rig_heat(const rf_rig_prep *p, const rf_rig_skel *s, const rf_rig_options *o, double **w,
                 uint8_t *boxed, rf_rig_stats *st, char *err, size_t n);

/* The defaults filled in (rig.c). */
rf_rig_options rf_rig_defaults(const rf_rig_options *opts);

/* The general rigger's curve skeleton, cut into joints: extracted twice (the second time from
 * where the feet meet) and rooted at the hips (rig.c). */
rf_rig_status rf_rig_curve(const rf_rig_prep *p, const rf_rig_options *o, rf_rig_skel *k, char *err,
                           size_t n);

/* k as an rf_skeleton (rest = bind, unrotated joints); named by the skeleton analysis when
 * `named` is not NULL (its up and forward as hints), else unnamed. NULL when out of memory. */
rf_skeleton *rf_rig_skeleton(const rf_rig_skel *k, const rf_rig_options *named);

/* Bone heat for k on the proxy, carried to a skinned copy of `mesh` into *skinned; joints of
 * `s` (k as a skeleton) whose bone won no vertex are flagged unweighted. */
bool rf_rig_weigh(const rf_mesh *mesh, const rf_rig_prep *p, const rf_rig_skel *k,
                  const rf_rig_options *o, rf_skeleton *s, rf_mesh **skinned, rf_rig_stats *st,
                  char *err, size_t n);

/* The proxy's surface for ray casts (rig-place.c); NULL when Embree fails. */
typedef struct rf_rig_surface rf_rig_surface;
rf_rig_surface *rf_rig_surface_make(const rf_rig_geo *g);
void rf_rig_surface_free(rf_rig_surface *s);

/* Distance along the unit direction dir from p to the first triangle, INFINITY when none. */
double rf_rig_surface_hit(const rf_rig_surface *s, const double p[3], const double dir[3]);

/* Moves p to the centre of the mesh's cross-section through it, square to dir: the area
 * centroid of the fan of points where rays in that plane meet the surface, twice refined. False,
 * p unchanged, when a ray finds no surface within `reach` (the section is not closed around p)
 * or the centre lies over `limit` away. */
bool rf_rig_centre(const rf_rig_surface *s, double p[3], const double dir[3], double reach,
                   double limit);

/* Every joint of k moved to the centre of the proxy's cross-section square to its bone (the
 * halfway direction at a bend), within a quarter of the longest edge for the rays and 4% of it
 * for the move; each from where the curve put it, not from its moved parent. The curve
 * skeleton's nodes are centroids of geodesic bands, which lean where a band cuts a limb at a
 * slant or a limb merges with the body. A joint whose section is not closed stays. False when
 * out of memory (k unchanged). */
bool rf_rig_skel_centre(const rf_rig_prep *p, rf_rig_skel *k);

/* The joints of k flagged in `which` moved along `axis` to fraction `at` of the way through
 * the mesh from its surface behind them (-axis) to its surface ahead (+axis); a joint without
 * surface both ways within a quarter of the longest edge stays. False when out of memory (its
 * surface not made: k unchanged, which would be another rig). */
bool rf_rig_skel_across(const rf_rig_prep *p, rf_rig_skel *k, const uint8_t *which, rf_vec3 axis,
                        double at);
/* rf_rig_skel_across for joints that may lie in a sheet of no thickness (a wing modelled as one
 * surface), whose rays along it meet nothing: there the sheet's own reach each way along `axis`
 * is measured, in the plane of the joint's bone and `axis`. Joints with surface ahead but none
 * behind (outside the mesh) stay. False when out of memory (k unchanged). */
bool rf_rig_skel_chord(const rf_rig_prep *p, rf_rig_skel *k, const uint8_t *which, rf_vec3 axis,
                       double at);

/* Where the template rigger puts each joint along the curve it follows: fractions of the
 * curve's length from its start (rig-template.c; the values and how they were chosen are in
 * doc/autorig.md). A bend window [lo, hi] is searched for the sharpest bend, the fraction
 * itself used when the curve runs straight there. */
typedef struct rf_rig_tpl_layout {
    double spine[3];            /* Spine, Spine1, Spine2 from the hips to the neck's base */
    double neck_at;             /* a short torso: the neck's base along hips to head tip */
    double head;                /* Head along the neck's base to the head's tip */
    double shoulder, arm, hand; /* along the girdle to the hand's tip */
    double elbow, elbow_lo, elbow_hi;
    double upleg, knee, knee_lo, knee_hi;
    double ankle_rise;             /* biped ankle: the curve this far (fraction of the leg's height)
                                    * above its lowest point */
    double hock, hock_lo, hock_hi; /* a hind leg's ankle, at its bend */
    double toe;                    /* ToeBase, from the ankle to the tip */
    double tail[4];
    bool centre;   /* joints moved to the centre of the mesh's cross-section */
    double dorsal; /* then Hips, spine and neck this far through the body from the
                    * belly (quadruped) or the front (biped) to the back; 0: left */
} rf_rig_tpl_layout;

extern const rf_rig_tpl_layout rf_rig_tpl_humanoid, rf_rig_tpl_quadruped;

/* The kinds of limb a layout places joints along: an arm (clavicle, upper arm, elbow, hand), a
 * foreleg (the same joints, a quadruped's), a leg (hip, knee, ankle where the leg comes down to
 * the foot, toe) and a hind leg (its ankle a hock, at the curve's bend). */
typedef enum rf_rig_limb_kind {
    RF_RIG_LIMB_ARM,
    RF_RIG_LIMB_FORELEG,
    RF_RIG_LIMB_LEG,
    RF_RIG_LIMB_HIND_LEG,
} rf_rig_limb_kind;

/* The four joints of a limb of curve skeleton k laid as layout l places them along the curve
 * from joint `girdle` (where the limb leaves the body) through its first joint `first` to the
 * farthest end below it (a leg's curve leaving out what climbs above the girdle, up the
 * analysis's `up`): pivots into pos, the curve's end into tip (rig-template.c; the template
 * rigger's limbs and the general rigger's, one home for where artists put limb joints). With
 * `start` given (not NULL) the curve starts there instead of at the girdle's pivot: a chest
 * joint on the trunk at the height where the arms leave it. False when out of memory (no curve
 * read: pos and tip then all at the first joint, no place to use). */
bool rf_rig_limb_place(const rf_rig_skel *k, rf_vec3 up, uint32_t girdle, uint32_t first,
                       rf_rig_limb_kind kind, const rf_rig_tpl_layout *l, const double *start,
                       double pos[4][3], double tip[3]);
/* rf_rig_limb_place with the curve cut at arc length `reach` from its start when that is
 * shorter (0: the whole curve): a limb laid no farther than its mirror image reaches. False
 * when out of memory. */
bool rf_rig_limb_place_within(const rf_rig_skel *k, rf_vec3 up, uint32_t girdle, uint32_t first,
                              rf_rig_limb_kind kind, const rf_rig_tpl_layout *l,
                              const double *start, double reach, double pos[4][3], double tip[3]);
/* The length of the curve rf_rig_limb_place lays a limb's joints along, into *reach. False when
 * out of memory (*reach 0): read as a limb reaching nowhere, it would decide a prop cut or a
 * wing. */
bool rf_rig_limb_reach(const rf_rig_skel *k, rf_vec3 up, uint32_t girdle, uint32_t first,
                       rf_rig_limb_kind kind, const double *start, double *reach);

/* The arc length a limb whose curve reaches `reach` is laid within (rf_rig_limb_place_within)
 * beside its mirror image reaching `twin`: `twin` when the limb reaches more than
 * RF_RIG_PROP_REACH times as far (it carries a prop past its hand), else 0 (the whole curve).
 * Both riggers' rule (rig-template.c). */
double rf_rig_limb_prop_cut(double reach, double twin);
/* Whether a limb of `kind` reaching `reach` along its curve is a wing: an arm reaching more
 * than twice as far as the longest leg (`legs`, 0: none). */
bool rf_rig_is_wing(rf_rig_limb_kind kind, double reach, double legs);
/* Layout l into out, a wing's elbow and wrist in it when `wing` (rig.c, RF_RIG_WING_WRIST). */
void rf_rig_wing_layout(const rf_rig_tpl_layout *l, bool wing, rf_rig_tpl_layout *out);

/* How far point q lies along direction d (a height along up, a place along the facing). */
static inline double rf_rig_along(const double q[3], rf_vec3 d)
{
    return q[0] * d.x + q[1] * d.y + q[2] * d.z;
}

#define RF_RIG_MAX_LIMBS 16 /* limbs laid out again in one rig */

/* The limbs of a rig as laid (rig.c, rf_rig_relay), for rf_rig_feet_soles: n limbs, each's
 * four joints (hip, knee, ankle, toe) and the tip of its last bone. */
typedef struct rf_rig_feet {
    uint32_t n;
    double (*pos)[4][3];
    double (*tip)[3];
    const uint8_t *leg;    /* [n] limb i is a laid leg of a biped's layout */
    const int32_t *mirror; /* [n] its mirror image's index, or -1 */
} rf_rig_feet;

/* Each leg of f whose sole (the surface of proxy g under its ankle, nearer it than any other
 * leg's ankle) reaches well forward of where the leg stands on it and little behind has its toe
 * joint moved to the ball of that foot, its tip to the toes and a low ankle (not a hock) onto
 * the foot over where the leg stands; a pair alike, and not when its toe bones already lie along
 * their feet (rig-foot.c). Returns how many legs were laid so. */
uint32_t rf_rig_feet_soles(const rf_rig_geo *g, rf_vec3 up, rf_rig_feet *f);

/* An arm laid from girdle point g (pos: clavicle, upper arm, elbow, hand, by layout l) that hangs
 * beside the trunk gets its clavicle, upper arm and elbow moved to where the trunk's width across
 * the body says the shoulder is (rays on surface sf; longest: the mesh's longest edge); an arm
 * held out, or no shoulder found, is left as it is. Both riggers' rule (rig.c). */
void rf_rig_shoulder(const rf_rig_surface *sf, double longest, rf_vec3 up, const double g[3],
                     const rf_rig_tpl_layout *l, double pos[4][3]);

/* The general rigger's joints short of bone heat, in place on its curve skeleton k
 * (rf_rig_curve): limbs cut where the layouts given put their joints (NULL: the built-in ones)
 * and a level body's spine moved along its back (rig.c). False when out of memory. The fitting
 * of layouts (tests/rig/rig-fit --general) scores the general rigger through it. */
bool rf_rig_general_place(const rf_rig_prep *p, rf_rig_skel *k, const rf_rig_options *o,
                          const rf_rig_tpl_layout *humanoid, const rf_rig_tpl_layout *quadruped);

/* Head joint h of k moved down its bone to where the trunk enters the head's bulk, when the
 * bone rises within 45 degrees of `up` (rig.c; the general rigger's first head joint, the
 * template's Head). False when out of memory (h unmoved). */
bool rf_rig_head_base(const rf_rig_prep *p, rf_rig_skel *k, uint32_t h, rf_vec3 up, rf_vec3 fwd);

/* The template laid into curve skeleton k of the cleaned mesh p, as a working skeleton into
 * *out (names into names[joint], 24 bytes each, up to 40 joints), with the layouts given
 * (NULL: the built-in ones) and which template into *got. `facing`: when o declares no forward,
 * the body's as rf_rig_pooled_facing reads it, else as rf_rig_placed_facing does (a biped's
 * then unused; zero: none read). The template rigger's work
 * short of bone heat; the fitting of layouts (tests/rig/rig-fit) calls it many times. False with
 * the reason in err, *out then holding nothing. */
bool rf_rig_template_place(const rf_rig_prep *p, const rf_rig_skel *k, const rf_rig_options *o,
                           rf_vec3 facing, rf_rig_template_kind want,
                           const rf_rig_tpl_layout *humanoid, const rf_rig_tpl_layout *quadruped,
                           rf_rig_skel *out, char (*names)[24], rf_rig_template_kind *got,
                           rf_vec3 *up, rf_vec3 *forward, char *err, size_t n);

#endif
