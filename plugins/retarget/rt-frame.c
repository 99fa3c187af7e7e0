/* The per-frame work: forward kinematics of each slot's source pose, the world-space transfer of
 * every mapped joint's rotation relative to the rests, the chains that share a rotation, and the
 * root's placement. Reads only the plan and its scratch; never allocates. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rt-internal.h"

rf_quat rf_rt_quat_pow(rf_quat q, double t)
{
    return rf_quat_slerp(rf_quat_identity(), q, t);
}

static inline rf_quat rt_load(const float *q)
{
    return rf_quat_make(q[0], q[1], q[2], q[3]);
}

static inline void rt_store(float *out, rf_quat q)
{
    out[0] = (float)q.x, out[1] = (float)q.y, out[2] = (float)q.z, out[3] = (float)q.w;
}

/* What the frame loop reads per target joint, packed so a frame walks one small array. */
enum rf_rt_hot_mode {
    RT_HOT_REST = 0, /* world = parent's * k (the rest local rotation) */
    RT_HOT_FAST,     /* one plain input: world = source world (slot, joint) * k */
    RT_HOT_LOCAL,    /* FAST, and its parent is FAST from the source joint's parent: then
                      * local = conj(parent's k) * source local * k, no world rotation needed */
    RT_HOT_FULL,     /* anything else a mapped joint may need (rt_mapped) */
    RT_HOT_SHARED,   /* a share of its chain's rotation */
};

typedef struct rf_rt_hot {
    int32_t parent;
    uint8_t mode;  /* rf_rt_hot_mode */
    uint8_t moves; /* its translation moves: root motion or an animated source translation */
    uint8_t world; /* something reads its world rotation (LOCAL joints only skip it) */
    uint32_t slot, joint;
    rf_quat k;
    rf_quat kp; /* LOCAL: conj of the parent's k */
} rf_rt_hot;

/* Marks source joint j of source k and its ancestors as needing a world rotation. */
static void rt_need_rot(rf_retarget *rt, uint32_t k, int32_t j)
{
    rf_rt_src *src = &rt->src[k];
    for (; j >= 0 && !src->need_rot[j]; j = src->parent[j])
        src->need_rot[j] = 1;
}

/* The source world rotations the frames read: FAST and FULL inputs (with the parents reverse
 * reads and the segment ends corrections read), and everything under a needed position. */
static void rt_need_rots(rf_retarget *rt)
{
    for (uint32_t j = 0; j < rt->n; j++) {
        const rf_rt_tjoint *tj = &rt->tj[j];
        const rf_rt_hot *h = &rt->hot[j];
        if (h->mode != RT_HOT_FAST && h->mode != RT_HOT_FULL && !h->moves)
            continue;
        for (uint32_t i = 0; i < tj->input_count; i++) {
            const rf_rt_input *in = rt->in + tj->first_input + i;
            rt_need_rot(rt, in->source, (int32_t)in->joint);
            rt_need_rot(rt, in->source, in->parent);
            if (in->seg_end >= 0)
                rt_need_rot(rt, in->source, in->seg_end);
        }
    }
    for (uint32_t k = 0; k < rt->source_count; k++)
        for (uint32_t j = 0; j < rt->src[k].n; j++)
            if (rt->src[k].need_pos[j])
                rt_need_rot(rt, k, (int32_t)j);
}

bool rf_rt_hot_init(rf_retarget *rt)
{
    /* Run again when the inputs' flags change after the plan (rt_trunk_lean). */
    free(rt->hot);
    for (uint32_t k = 0; k < rt->source_count; k++)
        free(rt->src[k].need_rot), rt->src[k].need_rot = NULL;
    rt->hot = calloc(rt->n ? rt->n : 1, sizeof *rt->hot);
    if (!rt->hot)
        return false;
    for (uint32_t j = 0; j < rt->n; j++) {
        const rf_rt_tjoint *tj = &rt->tj[j];
        const rf_rt_input *in = rt->in + tj->first_input;
        rf_rt_hot *h = &rt->hot[j];
        h->parent = tj->parent;
        h->moves = tj->root_motion || tj->translate;
        h->k = tj->rest_local;
        if (tj->kind == RF_RT_SHARED) {
            h->mode = RT_HOT_SHARED;
        } else if (tj->kind == RF_RT_MAPPED) {
            bool fast =
                tj->input_count == 1 && !(in->flags & ~(uint32_t)RF_MAP_MIRROR) && tj->owner < 0;
            h->mode = fast ? RT_HOT_FAST : RT_HOT_FULL;
            h->slot = in->slot, h->joint = in->joint, h->k = in->K;
        }
    }
    /* Parents come first: a FAST joint whose parent is FAST (or LOCAL) from the same slot's
     * parent joint needs only local rotations. */
    for (uint32_t j = 0; j < rt->n; j++) {
        rf_rt_hot *h = &rt->hot[j];
        const rf_rt_hot *p = h->parent >= 0 ? &rt->hot[h->parent] : NULL;
        const rf_rt_src *src = h->mode == RT_HOT_FAST ? &rt->src[rt->slots[h->slot].source] : NULL;
        if (src && p && (p->mode == RT_HOT_FAST || p->mode == RT_HOT_LOCAL) && p->slot == h->slot &&
            src->parent[h->joint] == (int32_t)p->joint && !h->moves && rt->anchor[j] < 0 &&
            rt->anchor[h->parent] < 0) {
            h->mode = RT_HOT_LOCAL;
            h->kp = rf_quat_conj(p->k);
        }
    }
    /* World rotations: every joint that is not LOCAL makes one (and its output reads its
     * parent's), and a world rotation is made from the parent's: children before parents. */
    for (uint32_t j = 0; j < rt->n; j++)
        rt->hot[j].world =
            rt->hot[j].mode != RT_HOT_LOCAL || rt->hot[j].moves || rt->anchor[j] >= 0;
    for (uint32_t j = rt->n; j-- > 0;)
        if (rt->hot[j].world && rt->hot[j].parent >= 0)
            rt->hot[rt->hot[j].parent].world = 1;
    for (uint32_t k = 0; k < rt->source_count; k++) {
        rt->src[k].need_rot = calloc(rt->src[k].n ? rt->src[k].n : 1, 1);
        if (!rt->src[k].need_rot)
            return false;
    }
    rt_need_rots(rt);
    return true;
}

bool rf_rt_work_init(const rf_retarget *rt, rf_rt_work *w)
{
    size_t n = rt->n ? rt->n : 1, slots = rt->slot_count ? rt->slot_count : 1;
    size_t m = rt->max_src_n ? rt->max_src_n : 1;
    memset(w, 0, sizeof *w);
    w->q = malloc(n * sizeof *w->q);
    w->chain_rot = malloc(n * sizeof *w->chain_rot);
    w->chain_base = malloc(n * sizeof *w->chain_base);
    w->s_rot = calloc(slots, sizeof *w->s_rot);
    w->s_pos = calloc(slots, sizeof *w->s_pos);
    w->poses = calloc(slots, sizeof *w->poses);
    w->scratch_rot = malloc(slots * m * 4 * sizeof *w->scratch_rot);
    w->scratch_tr = malloc(slots * m * 3 * sizeof *w->scratch_tr);
    w->tw = malloc(n * sizeof *w->tw);
    bool ok = w->q && w->chain_rot && w->chain_base && w->s_rot && w->s_pos && w->poses &&
              w->scratch_rot && w->scratch_tr && w->tw;
    for (uint32_t s = 0; ok && s < rt->slot_count; s++) {
        w->s_rot[s] = malloc(m * sizeof **w->s_rot);
        w->s_pos[s] = malloc(m * sizeof **w->s_pos);
        ok = w->s_rot[s] && w->s_pos[s];
    }
    return ok;
}

void rf_rt_work_free(const rf_retarget *rt, rf_rt_work *w)
{
    for (uint32_t s = 0; s < rt->slot_count; s++) {
        if (w->s_rot)
            free(w->s_rot[s]);
        if (w->s_pos)
            free(w->s_pos[s]);
    }
    free(w->q), free(w->chain_rot), free(w->chain_base), free(w->s_rot), free(w->s_pos);
    free(w->poses), free(w->scratch_rot), free(w->scratch_tr), free(w->tw);
    memset(w, 0, sizeof *w);
}

/* Source world rotations (and the positions the frame needs) of slot s from its local pose. */
static void rt_source_fk(const rf_retarget *rt, rf_rt_work *w, uint32_t s, const rf_rt_pose *pose)
{
    const rf_rt_src *src = &rt->src[rt->slots[s].source];
    const int32_t *parent = src->parent;
    rf_quat *q = w->s_rot[s];
    rf_vec3 *p = w->s_pos[s];
    const uint8_t *need = src->need_rot;
    for (uint32_t j = 0; j < src->n; j++) {
        if (!need[j])
            continue; /* only LOCAL joints read it, through its local rotation */
        int32_t par = parent[j];
        rf_quat l = rt_load(pose->rotations + (size_t)j * 4);
        q[j] = par < 0 ? rf_quat_mul(src->turn, l) : rf_quat_mul(q[par], l);
        if (!src->need_pos[j])
            continue;
        const float *t = pose->translations + (size_t)j * 3;
        rf_vec3 lt = rf_v3(t[0], t[1], t[2]);
        /* The parent's world scale is its rest's: clips carry no scale. */
        p[j] = par < 0 ? rf_quat_rotate(src->turn, lt)
                       : rf_v3_add(p[par],
                                   rf_quat_rotate(q[par], rf_v3_mul(src->rest_world[par].s, lt)));
    }
}

/* Largest tilt (swing away from up) a centerline bone of another body plan takes from its source.
 * An upright biped leans its spine and pelvis by 30-60 degrees when it crouches, jumps or bends
 * over; laid on a level quadruped's or a dragon's spine, the same lean drives its head into the
 * floor and lifts its hindquarters. Its turn about up (where it faces) is kept whole. */
#define RT_LEVEL_TILT (10.0 * RF_PI / 180.0)

/* Delta d split into its twist about unit `axis` and the swing that follows it (d = swing *
 * twist), the swing's angle eased into `limit` (a tanh: continuous, near the delta's for small
 * swings; none at 0). Returns the eased swing. */
static rf_quat rt_swing_eased(rf_quat d, rf_vec3 axis, double limit, rf_quat *twist)
{
    double along = d.x * axis.x + d.y * axis.y + d.z * axis.z;
    rf_quat t = rf_quat_make(axis.x * along, axis.y * along, axis.z * along, d.w);
    double tl = sqrt(along * along + d.w * d.w);
    *twist = tl > 1e-12 ? rf_quat_make(t.x / tl, t.y / tl, t.z / tl, t.w / tl) : rf_quat_identity();
    rf_quat swing = rf_quat_mul(d, rf_quat_conj(*twist));
    if (swing.w < 0)
        swing = rf_quat_neg(swing);
    double s = sqrt(swing.x * swing.x + swing.y * swing.y + swing.z * swing.z);
    if (!(s > 1e-12))
        return rf_quat_identity();
    double angle = 2 * atan2(s, swing.w);
    double eased = limit > 0 ? limit * tanh(angle / limit) : 0;
    return rf_quat_from_axis_angle(rf_v3(swing.x / s, swing.y / s, swing.z / s), eased);
}

/* World delta d split into its turn about up and its tilt; the tilt's angle eased into `limit`. */
rf_quat rf_rt_level(rf_quat d, rf_vec3 up, double limit)
{
    rf_quat twist;
    rf_quat swing = rt_swing_eased(d, up, limit, &twist);
    return rf_quat_mul(swing, twist);
}

/* The source joint's world delta from its rest, corrected, reversed or mirrored as flagged, times
 * the alignment. */
static rf_quat rt_input_motion_raw(const rf_retarget *rt, const rf_rt_work *w,
                                   const rf_rt_input *in)
{
    const rf_quat *q = w->s_rot[in->slot];
    rf_quat m = rf_quat_mul(q[in->joint], in->C);
    if (in->flags & RF_RT_IN_CORRECT) {
        const rf_vec3 *p = w->s_pos[in->slot];
        rf_vec3 now = rf_quat_rotate(q[in->joint], in->seg_local);
        rf_vec3 want = rf_v3_sub(p[in->seg_end], p[in->joint]);
        m = rf_quat_mul(rf_quat_from_two_vectors(now, want), m);
    }
    if (!(in->flags & (RF_MAP_REVERSE | RF_RT_IN_REFLECT)))
        return m;
    rf_quat d = rf_quat_mul(q[in->joint], in->rest_inv);
    if (in->flags & RF_MAP_REVERSE) {
        /* Keep the parent's motion, play the joint's own rotation backwards. */
        rf_quat dp =
            in->parent >= 0 ? rf_quat_mul(q[in->parent], in->parent_rest_inv) : rf_quat_identity();
        rf_quat own = rf_quat_mul(rf_quat_conj(dp), d);
        d = rf_quat_mul(dp, rf_quat_conj(own));
    }
    if (in->flags & RF_RT_IN_REFLECT)
        d = rf_rt_reflect(d, rt->src[in->source].left);
    return rf_quat_mul(d, in->align);
}

/* The world rotation input `in` asks of its target joint's aligned rest: the source joint's world
 * delta from its rest, corrected, reversed, mirrored or levelled as flagged, times the
 * alignment. */
static rf_quat rt_input_motion(const rf_retarget *rt, const rf_rt_work *w, const rf_rt_input *in)
{
    rf_quat m = rt_input_motion_raw(rt, w, in);
    if (!(in->flags & RF_RT_IN_LEVEL))
        return m;
    rf_quat d = rf_quat_mul(m, rf_quat_conj(in->align));
    /* A body carried on four legs, two pairs driven by one pair half a cycle apart, takes none
     * of a biped's lean: the lean is how a biped balances over two legs. Leaned up to 10
     * degrees, the Fox pitched nose-down a median 7.9 degrees through CMU 01_01's walk, its
     * forefeet went 9 units (of a 31 leg) under the floor and the raise that took them out left
     * its hind feet hovering (median 9.9% of its height over the floor; 4.7% level). */
    double limit = rt->level_flat ? 0 : RT_LEVEL_TILT;
    return rf_quat_mul(rf_rt_level(d, rt->src[in->source].up, limit), in->align);
}

/* Weighted blend of the inputs' motions, each turned to the first one's hemisphere. */
static rf_quat rt_blend(const rf_retarget *rt, const rf_rt_work *w, const rf_rt_tjoint *tj)
{
    const rf_rt_input *in = rt->in + tj->first_input;
    rf_quat first = rt_input_motion(rt, w, &in[0]);
    if (tj->input_count == 1)
        return first;
    rf_quat sum = rf_quat_make(first.x * in[0].weight, first.y * in[0].weight,
                               first.z * in[0].weight, first.w * in[0].weight);
    for (uint32_t i = 1; i < tj->input_count; i++) {
        rf_quat m = rt_input_motion(rt, w, &in[i]);
        double k = rf_quat_dot(m, first) < 0 ? -in[i].weight : in[i].weight;
        sum.x += k * m.x, sum.y += k * m.y, sum.z += k * m.z, sum.w += k * m.w;
    }
    return rf_quat_normalize(sum);
}

/* The motion of joint p this frame: its world rotation relative to the aligned rest (the
 * identity while the aligned rest itself is being made). */
static rf_quat rt_motion_of(const rf_retarget *rt, const rf_rt_work *w, int32_t p)
{
    if (p < 0 || !rt->w0)
        return rf_quat_identity();
    return rf_quat_mul(w->q[p], rf_quat_conj(rt->w0[p]));
}

/* The chain's own rotation D (after its parent's motion `base`) such that turning each link by
 * its share of D lays the chain's end along the direction the whole motion `m` gives the chord.
 * Each correction turns the chord by about the mean share of it, so it is scaled up by its
 * inverse; a few suffice. */
static rf_quat rt_chain_solve(const rf_retarget *rt, const rf_rt_tjoint *tj, rf_quat base,
                              rf_quat m)
{
    const rf_rt_link *l = rt->links + tj->first_link;
    rf_quat inv_base = rf_quat_conj(base);
    rf_vec3 want = rf_quat_rotate(inv_base, rf_quat_rotate(m, tj->chord));
    rf_quat d = rf_quat_normalize(rf_quat_mul(inv_base, rf_quat_mul(m, rf_quat_conj(tj->align))));
    double lsum = 0, ssum = 0;
    for (uint32_t k = 0; k < tj->link_count; k++) {
        double len = rf_v3_len(l[k].bone);
        lsum += len, ssum += len * l[k].share;
    }
    double gain = ssum > 0 ? lsum / ssum : 1;
    for (int it = 0; it < 16; it++) {
        rf_vec3 chord = rf_v3(0, 0, 0);
        for (uint32_t k = 0; k < tj->link_count; k++)
            chord = rf_v3_add(chord, rf_quat_rotate(rf_rt_quat_pow(d, l[k].share), l[k].bone));
        double err = rf_v3_angle(chord, want);
        if (err < 1e-9)
            break;
        rf_vec3 axis = rf_v3_cross(chord, want);
        rf_quat fix = rf_quat_from_axis_angle(axis, fmin(gain * err, 0.5 * RF_PI));
        d = rf_quat_normalize(rf_quat_mul(fix, d));
    }
    return d;
}

/* World rotation of mapped joint j this frame, beyond the common case (several inputs, flags,
 * a chain to share). */
static rf_quat rt_mapped(const rf_retarget *rt, rf_rt_work *w, uint32_t j)
{
    const rf_rt_tjoint *tj = &rt->tj[j];
    rf_quat m = rt_blend(rt, w, tj);
    const rf_rt_input *in = &rt->in[tj->first_input];
    if (in->flags & RF_RT_IN_WHOLE) {
        /* The swing is eased against the body the limb hangs from: the source turning round
         * as it walks is no swing of its arm. */
        rf_quat body = rt_motion_of(rt, w, tj->parent), twist;
        rf_quat own = rf_quat_mul(rf_quat_conj(body), rf_quat_mul(m, rf_quat_conj(tj->align)));
        rf_quat swing = rt_swing_eased(own, in->whole_axis, in->whole_limit, &twist);
        return rf_quat_mul(rf_quat_mul(body, rf_quat_mul(swing, tj->align)), tj->rest_world);
    }
    if (tj->owner < 0)
        return rf_quat_mul(m, tj->rest_world);
    rf_quat base = rt_motion_of(rt, w, tj->parent);
    rf_quat d = rt_chain_solve(rt, tj, base, m);
    w->chain_base[j] = base;
    w->chain_rot[j] = d;
    return rf_quat_mul(rf_quat_mul(base, rf_rt_quat_pow(d, tj->share)),
                       rf_quat_mul(tj->align, tj->rest_world));
}

/* World rotation of a joint sharing the chain of its owner. */
static rf_quat rt_shared(const rf_retarget *rt, const rf_rt_work *w, const rf_rt_tjoint *tj)
{
    const rf_rt_tjoint *o = &rt->tj[tj->owner];
    rf_quat turn =
        rf_quat_mul(w->chain_base[tj->owner], rf_rt_quat_pow(w->chain_rot[tj->owner], tj->share));
    return rf_quat_mul(turn, rf_quat_mul(o->align, tj->rest_world));
}

/* Local translation of a root-motion joint: the source's displacement from its skeleton's rest,
 * scaled, horizontally from the target's rest position and vertically over the target's floor. */
static rf_vec3 rt_root(const rf_retarget *rt, const rf_rt_work *w, const rf_rt_tjoint *tj,
                       uint32_t j)
{
    rf_vec3 rest = rt->t_rest_world[j].t, pos = rf_v3(0, 0, 0);
    for (uint32_t i = 0; i < tj->input_count; i++) {
        const rf_rt_input *in = rt->in + tj->first_input + i;
        const rf_rt_src *src = &rt->src[in->source];
        rf_vec3 ps = w->s_pos[in->slot][in->joint];
        rf_vec3 h = rf_rt_horizontal(rt->up, rest);
        if (!rt->opt.in_place)
            h = rf_v3_add(
                h, rf_v3_scale(rf_rt_horizontal(src->up, rf_v3_sub(ps, src->skel_pos[in->joint])),
                               src->scale));
        double v = rt->floor_target + src->scale * (rf_rt_height(src->up, ps) - src->floor);
        pos = rf_v3_add(pos, rf_v3_scale(rf_v3_add(h, rf_v3_scale(rt->up, v)), in->weight));
    }
    return rf_xform_point(tj->parent_world_inv, pos);
}

/* Local translation of a mapped joint whose source translation moves (a hip under placement
 * roots, a stretching bone): the source's displacement from its rest offset, in world, scaled
 * like the root, turned into the target parent's frame. */
static rf_vec3 rt_translate(const rf_retarget *rt, const rf_rt_work *w, const rf_rt_tjoint *tj,
                            uint32_t j, const rf_rt_pose *poses)
{
    rf_vec3 d = rf_v3(0, 0, 0);
    for (uint32_t i = 0; i < tj->input_count; i++) {
        const rf_rt_input *in = rt->in + tj->first_input + i;
        const rf_rt_src *src = &rt->src[in->source];
        const float *t = poses[in->slot].translations + (size_t)in->joint * 3;
        rf_vec3 off = rf_v3_sub(rf_v3(t[0], t[1], t[2]), src->rest_local[in->joint].t);
        int32_t par = src->skel->joints[in->joint].parent;
        off = par >= 0
                  ? rf_quat_rotate(w->s_rot[in->slot][par], rf_v3_mul(src->rest_world[par].s, off))
                  : rf_quat_rotate(src->turn, off);
        d = rf_v3_add(d, rf_v3_scale(off, src->scale * in->weight));
    }
    rf_vec3 rest = rt->target->joints[j].rest.t;
    if (tj->parent < 0)
        return rf_v3_add(rest, d);
    rf_vec3 ps = rt->t_rest_world[tj->parent].s;
    rf_vec3 local = rf_quat_rotate(rf_quat_conj(w->q[tj->parent]), d);
    return rf_v3_add(rest, rf_v3(local.x / ps.x, local.y / ps.y, local.z / ps.z));
}

void rf_rt_frame(const rf_retarget *rt, rf_rt_work *w, const rf_rt_pose *poses, float *rotations,
                 float *translations)
{
    for (uint32_t s = 0; s < rt->slot_count; s++)
        rt_source_fk(rt, w, s, &poses[s]);
    /* Most joints keep their rest offsets: copy them all, then overwrite the moving ones. */
    memcpy(translations, rt->rest_tr, (size_t)rt->n * 3 * sizeof *translations);
    rf_quat *q = w->q;
    for (uint32_t j = 0; j < rt->n; j++) {
        const rf_rt_hot *h = &rt->hot[j];
        if (h->mode == RT_HOT_LOCAL) {
            /* conj(Qs(p) Kp) Qs(j) K = conj(Kp) Ls(j) K: the source's local rotation. */
            const float *l = poses[h->slot].rotations + (size_t)h->joint * 4;
            rf_quat local = rf_quat_mul(rf_quat_mul(h->kp, rt_load(l)), h->k);
            rt_store(rotations + (size_t)j * 4, local);
            if (h->world)
                q[j] = rf_quat_mul(q[h->parent], local);
            continue;
        }
        rf_quat parent = h->parent >= 0 ? q[h->parent] : rf_quat_identity();
        switch (h->mode) {
        case RT_HOT_FAST:
            q[j] = rf_quat_mul(w->s_rot[h->slot][h->joint], h->k);
            break;
        case RT_HOT_REST:
            q[j] = rf_quat_mul(parent, h->k);
            break;
        case RT_HOT_FULL:
            q[j] = rt_mapped(rt, w, j);
            break;
        default:
            q[j] = rt_shared(rt, w, &rt->tj[j]);
        }
        /* Products of unit quaternions stay unit to rounding; the output is float anyway. */
        rt_store(rotations + (size_t)j * 4, rf_quat_mul(rf_quat_conj(parent), q[j]));
        if (!h->moves || !rt->root_motion_on)
            continue;
        const rf_rt_tjoint *tj = &rt->tj[j];
        rf_vec3 t = tj->root_motion ? rt_root(rt, w, tj, j) : rt_translate(rt, w, tj, j, poses);
        float *out = translations + (size_t)j * 3;
        out[0] = (float)t.x, out[1] = (float)t.y, out[2] = (float)t.z;
    }
    if (rt->anchored)
        rf_rt_place_anchored(rt, rotations, translations, q, w->tw);
}

void rf_retarget_frame(rf_retarget *rt, const rf_rt_pose *poses, float *rotations,
                       float *translations)
{
    rf_rt_frame(rt, &rt->work, poses, rotations, translations);
}
