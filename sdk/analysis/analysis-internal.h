/* Internals shared by the stages of the skeleton analysis (analysis.c runs them in order):
 * geom.c (positions, tips, bone-axis convention, helpers), symmetry.c (mirror plane, center and
 * limbs), axes.c (up, forward), body.c (root chain, detached parts, the logical tree),
 * sections.c (sections and per-joint measures). Every tree walk goes through `order` (parents
 * before children), never through recursion.
 */
#ifndef RF_ANALYSIS_INTERNAL_H
#define RF_ANALYSIS_INTERNAL_H

#include "rigflow/analysis.h"

#define RF_NONE (-1)

typedef struct rf_awork {
    const rf_skeleton *skel;
    rf_analysis_options opt;
    rf_analysis *a;
    uint32_t n;

    const rf_xform *local; /* the pose analysed: rest or bind, per joint (borrowed) */
    rf_xform *world;
    int32_t *file_parent; /* sanitised: -1 or a smaller index */
    int32_t *parent;      /* logical parent: file parent, or the proximity attachment */
    uint32_t *child_off;  /* CSR of logical children, helpers excluded: [n + 1] */
    uint32_t *child_idx;
    uint32_t *order; /* non-helper joints, parents first; order_count of them */
    uint32_t order_count;
    uint32_t *hlp_order; /* every joint, parents first (for helpers too) */

    uint8_t *helper;    /* never part of the body (IK targets, poles, sockets, end markers) */
    uint8_t *weighted;  /* 1 weighted, 0 unweighted */
    bool weights_known; /* the skeleton says which joints carry skin weights */

    int conv_axis;    /* bone-along axis of the rig (0 x, 1 y, 2 z) or -1 when it has none */
    int conv_sign;    /* its usual sign, +1 or -1 */
    int8_t *own_sign; /* per joint sign of the axis (0 when unknown) */
    uint8_t *tip_set; /* tip from an end site or an end marker: keep it */

    double eps; /* coincidence tolerance */
    double tol; /* symmetry tolerance */

    /* symmetry and limbs (over the non-helper tree) */
    uint8_t *center;     /* on the centerline */
    int32_t *limb_of;    /* first joint of the limb containing the joint, or -1 for center */
    rf_vec3 *sub_sum;    /* sum of pivots in the subtree */
    uint32_t *sub_count; /* joints in the subtree */
    double *sub_len;     /* summed bone length in the subtree */
    uint64_t *hash;      /* topology of the subtree */
    rf_vec3 plane_n, plane_p;
    bool have_plane;
    struct rf_grid *grid; /* spatial hash of the pivots in `order`, built on first use */

    /* body */
    int32_t top;         /* first joint of the body below the root chain */
    uint8_t *root_chain; /* ground roots and armature joints above the body */
    uint8_t *detached;   /* attached by proximity */
    rf_vec3 *attach_pt;  /* where each joint's bone chain leaves its logical parent */
    int32_t rear, front; /* spine path ends (girdle joints), -1 without girdles */
} rf_awork;

/* geom.c */
bool rf_an_prepare(rf_awork *w);
bool rf_an_geometry(rf_awork *w);
void rf_an_tips(rf_awork *w);
bool rf_an_helpers(rf_awork *w);
bool rf_an_build_tree(rf_awork *w);
rf_vec3 rf_an_axis_dir(const rf_awork *w, uint32_t j, int sign);
/* The body's reference axes (left, up, forward): the up and forward forced by the caller or
 * declared by the file, made orthonormal, else the coordinate axes x, y, z. Whatever the
 * analysis measures or snaps along fixed axes uses these, so a skeleton turned together with
 * its declared axes reads as it does unturned; axes along the coordinate axes give the
 * coordinates themselves, so an unturned body reads exactly as before. */
void rf_an_frame(const rf_awork *w, rf_vec3 ax[3]);

/* symmetry.c. Like every stage that allocates, these return false only when out of memory: a
 * stage never falls back to a default in place of what it could not measure (rf_analyze then
 * gives NULL, never another analysis). */
bool rf_an_subtree_stats(rf_awork *w);
bool rf_an_symmetry(rf_awork *w);
bool rf_an_classify(rf_awork *w);
double rf_an_plane_dist(const rf_awork *w, rf_vec3 p);
bool rf_an_mirrors(rf_awork *w);
/* Re-centres the plane on its twin pairs, its normal kept. */
bool rf_an_recentre(rf_awork *w);
/* Drops the spatial hash (when `order` changes); rebuilt on next use. */
void rf_an_grid_reset(rf_awork *w);

/* axes.c */
bool rf_an_axes(rf_awork *w);

/* body.c */
bool rf_an_body(rf_awork *w);

/* sections.c, measure.c */
bool rf_an_sections(rf_awork *w);
bool rf_an_measure(rf_awork *w);

/* Small growable array of uint32_t used by the stages. */
typedef struct rf_u32vec {
    uint32_t *v;
    uint32_t n, cap;
} rf_u32vec;
bool rf_u32vec_push(rf_u32vec *a, uint32_t x);

static inline bool rf_an_is_leaf(const rf_awork *w, uint32_t j)
{
    return w->child_off[j] == w->child_off[j + 1];
}
static inline uint32_t rf_an_child_count(const rf_awork *w, uint32_t j)
{
    return w->child_off[j + 1] - w->child_off[j];
}
static inline rf_vec3 rf_an_pos(const rf_awork *w, uint32_t j)
{
    return w->a->joints[j].pos;
}
static inline double rf_an_height(const rf_awork *w, rf_vec3 p)
{
    return rf_v3_dot(p, w->a->up);
}

#endif
