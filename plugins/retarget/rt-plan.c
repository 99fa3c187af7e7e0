/* Set-up of a retargeting plan: checks the inputs, resolves every mapping input against its
 * source's rest (alignment rotations, segment corrections, slots), plans the chains whose
 * unmapped joints share a rotation, and picks the joints that carry root motion. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rigflow/analysis.h"
#include "rigflow/text.h"

#include "rt-internal.h"

void rf_rt_fail(char *err, size_t err_size, const char *fmt, ...)
{
    if (!err || !err_size)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, err_size, fmt, ap);
    va_end(ap);
}

void rf_retarget_options_default(rf_retarget_options *o)
{
    memset(o, 0, sizeof *o);
    o->rest_frame = -1;
    o->last_frame = -1;
    o->ground = RF_RT_GROUND_AUTO;
    o->contact = true;
    o->contact_height = 0.12;
    o->contact_speed = 0.6;
    o->contact_blend = 0.15;
    o->hold_floor = true;
}

/* ---- checks ---- */

static bool rt_check_skeleton(const rf_skeleton *s, const char *what, char *err, size_t err_size)
{
    if (!s || !s->joint_count) {
        rf_rt_fail(err, err_size, "%s has no joints", what);
        return false;
    }
    int64_t bad = rf_skeleton_misordered(s);
    char why[416];
    if (bad >= 0)
        rf_rt_fail(err, err_size, "%s: %s", what,
                   rf_skeleton_order_error(s, (uint32_t)bad, why, sizeof why));
    return bad < 0;
}

static bool rt_check(const rf_rt_source *sources, uint32_t count, const rf_skeleton *target,
                     const rf_mapping *m, char *err, size_t err_size)
{
    char what[64];
    if (!count) {
        rf_rt_fail(err, err_size, "no source");
        return false;
    }
    if (!rt_check_skeleton(target, "the target skeleton", err, err_size))
        return false;
    for (uint32_t k = 0; k < count; k++) {
        snprintf(what, sizeof what, "source skeleton %u", k);
        if (!rt_check_skeleton(sources[k].skeleton, what, err, err_size))
            return false;
        const rf_animation *a = sources[k].animation;
        if (!a || a->joint_count != sources[k].skeleton->joint_count || !(a->fps > 0)) {
            rf_rt_fail(err, err_size,
                       "source %u: the clip does not fit its skeleton (%u joints, clip %u, fps "
                       "%g)",
                       k, sources[k].skeleton->joint_count, a ? a->joint_count : 0, a ? a->fps : 0);
            return false;
        }
    }
    if (!m || m->target_joint_count != target->joint_count) {
        rf_rt_fail(err, err_size, "the mapping has %u entries but the target has %u joints",
                   m ? m->target_joint_count : 0, target->joint_count);
        return false;
    }
    uint32_t mapped = 0;
    for (uint32_t j = 0; j < m->target_joint_count; j++) {
        const rf_map_entry *e = &m->entries[j];
        for (uint32_t i = 0; i < e->input_count; i++) {
            const rf_map_input *in = &e->inputs[i];
            if (in->source >= count || in->joint >= sources[in->source].skeleton->joint_count ||
                !(in->weight > 0) || !isfinite(in->delay)) {
                rf_rt_fail(err, err_size,
                           "mapping entry %u input %u: source %u joint %u weight %g delay %g "
                           "does not fit the %u source(s)",
                           j, i, in->source, in->joint, in->weight, in->delay, count);
                return false;
            }
        }
        mapped += e->input_count > 0;
    }
    if (!mapped) {
        rf_rt_fail(err, err_size, "the mapping maps no target joint");
        return false;
    }
    return true;
}

/* ---- the mapped tree ---- */

/* Nearest mapped proper ancestor of every target joint along its body parents (an anchored
 * foot's is its shin, not the placement root it hangs from), or -1. */
static void rt_mapped_parents(const rf_retarget *rt, int32_t *mp)
{
    for (uint32_t j = 0; j < rt->n; j++) {
        int32_t p = rt->lparent[j];
        for (uint32_t guard = 0; p >= 0 && !rt->mapping->entries[p].input_count && guard < rt->n;
             guard++)
            p = rt->lparent[p];
        mp[j] = p >= 0 && rt->mapping->entries[p].input_count ? p : RF_RT_NONE;
    }
}

/* Mapped joints below j (in the mapped tree) counted for every joint. */
static void rt_mapped_weight(const rf_retarget *rt, const int32_t *mp, uint32_t *w)
{
    memset(w, 0, rt->n * sizeof *w);
    for (uint32_t j = 0; j < rt->n; j++) {
        if (!rt->mapping->entries[j].input_count)
            continue;
        for (int32_t a = mp[j], guard = 0; a >= 0 && guard < (int32_t)rt->n; a = mp[a], guard++)
            w[a]++;
    }
}

static rf_vec3 rt_tpos(const rf_retarget *rt, uint32_t j)
{
    return rt->t_rest_world[j].t;
}

/* The mapped child of mapped joint j that its rotation aims along: the one continuing the bone
 * into j best (mapped parent to j), or for a top joint the one leading to most mapped joints.
 * -1 when j has no mapped child at a distance. */
static int32_t rt_primary_child(const rf_retarget *rt, uint32_t j, const int32_t *mp,
                                const uint32_t *weight, double eps)
{
    rf_vec3 in = rf_v3(0, 0, 0);
    if (mp[j] >= 0)
        in = rf_v3_normalize(rf_v3_sub(rt_tpos(rt, j), rt_tpos(rt, (uint32_t)mp[j])));
    int32_t best = RF_RT_NONE;
    double best_score = -INFINITY;
    for (uint32_t c = 0; c < rt->n; c++) {
        if (mp[c] != (int32_t)j || !rt->mapping->entries[c].input_count)
            continue;
        rf_vec3 d = rf_v3_sub(rt_tpos(rt, c), rt_tpos(rt, j));
        if (rf_v3_len(d) <= eps)
            continue;
        double score = rf_v3_len2(in) > 0 ? rf_v3_dot(rf_v3_normalize(d), in) : weight[c];
        if (score > best_score)
            best_score = score, best = (int32_t)c;
    }
    return best;
}

/* The first input of target joint c reading source k, or NULL. */
static const rf_map_input *rt_input_from(const rf_mapping *m, uint32_t c, uint32_t k)
{
    const rf_map_entry *e = &m->entries[c];
    for (uint32_t i = 0; i < e->input_count; i++)
        if (e->inputs[i].source == k)
            return &e->inputs[i];
    return NULL;
}

/* ---- slots ---- */

static uint32_t rt_slot_for(rf_retarget *rt, uint32_t source, double offset)
{
    for (uint32_t s = 0; s < rt->slot_count; s++)
        if (rt->slots[s].source == source && fabs(rt->slots[s].offset - offset) < 1e-9)
            return s;
    rt->slots[rt->slot_count].source = source;
    rt->slots[rt->slot_count].offset = offset;
    return rt->slot_count++;
}

/* ---- alignment ---- */

/* Segment pairs of one input: target rest vector, source rest vector, source joint at the end. */
typedef struct rt_pair {
    rf_vec3 t, s;
    int32_t end; /* source joint ending the segment, -1 for a tip */
    bool primary;
} rt_pair;

static rf_vec3 rt_tip_world(rf_xform w, rf_vec3 tip)
{
    return rf_v3_sub(rf_xform_point(w, tip), w.t);
}

/* The pair of segment j -> c for input `in` into *out; a segment of no length on either side (a
 * joint sitting on its parent, as CMU's LowerBack on its Hips) is carried on to c's primary
 * mapped child, and so on. False when no segment with a length is found. */
static bool rt_pair_of(const rf_retarget *rt, uint32_t j, uint32_t c, const rf_map_input *in,
                       const int32_t *primary, rt_pair *out)
{
    const rf_rt_src *src = &rt->src[in->source];
    double eps_t = 1e-6 * rt->size, eps_s = 1e-6 * src->size;
    for (int32_t at = (int32_t)c, hops = 0; at >= 0; at = primary[at], hops++) {
        const rf_map_input *ci = rt_input_from(rt->mapping, (uint32_t)at, in->source);
        if (!ci)
            return false;
        rf_vec3 vt = rf_v3_sub(rt_tpos(rt, (uint32_t)at), rt_tpos(rt, j));
        rf_vec3 vs = rf_v3_sub(src->rest_world[ci->joint].t, src->rest_world[in->joint].t);
        if (rf_v3_len(vt) > eps_t && rf_v3_len(vs) > eps_s) {
            /* Only a direct segment may steer j's rotation frame by frame. */
            *out = (rt_pair){vt, vs, hops ? RF_RT_NONE : (int32_t)ci->joint, false};
            return true;
        }
    }
    return false;
}

/* The joint farthest from source joint j along the run of single children below it, when the run
 * holds two joints or more (a leg's knee, ankle and toe; an arm's elbow and wrist, up to where
 * the fingers branch), else -1. A target limb of one bone (a low-poly creature's rigid leg)
 * mapped to j stands for that whole run: it points where the run reaches, not where j's own bone
 * turns, or it copies a thigh's swing and lean while the knee's bend never reaches it, and its
 * foot lands where the source's foot never was. The toe, not the ankle: it is what stands on the
 * floor through a step, as the one bone's tip does (the cat's feet skated 0.102 leg/s aimed
 * along the ankle, 0.065 along the toe). */
static int32_t rt_chain_reach(const rf_rt_src *src, uint32_t j)
{
    int32_t at = (int32_t)j, far = -1;
    uint32_t links = 0;
    double best = 0;
    for (;;) {
        int32_t only = -1;
        uint32_t kids = 0;
        for (uint32_t c = 0; c < src->n; c++)
            if (src->skel->joints[c].parent == at)
                only = (int32_t)c, kids++;
        if (kids != 1)
            break;
        at = only, links++;
        double d = rf_v3_len(rf_v3_sub(src->rest_world[at].t, src->rest_world[j].t));
        if (d > best)
            best = d, far = at;
    }
    return links >= 2 ? far : -1;
}

/* The pairs of target joint j for input `in`: one per mapped child that the same source drives,
 * or the bones' tips when j has no mapped child. The primary child's pair is flagged; when it
 * has none, the longest pair stands in. */
static uint32_t rt_pairs(const rf_retarget *rt, uint32_t j, const rf_map_input *in,
                         const int32_t *mp, const int32_t *primary, rt_pair *pairs, uint32_t max)
{
    const rf_rt_src *src = &rt->src[in->source];
    uint32_t count = 0;
    int32_t first = RF_RT_NONE, longest = RF_RT_NONE;
    bool has_child = false;
    for (uint32_t c = 0; c < rt->n && count < max; c++) {
        if (mp[c] != (int32_t)j || !rt->mapping->entries[c].input_count)
            continue;
        has_child = true;
        if (!rt_pair_of(rt, j, c, in, primary, &pairs[count]))
            continue;
        if ((int32_t)c == primary[j])
            first = (int32_t)count;
        if (longest < 0 || rf_v3_len(pairs[count].t) > rf_v3_len(pairs[longest].t))
            longest = (int32_t)count;
        count++;
    }
    if (count)
        pairs[first >= 0 ? first : longest].primary = true;
    if (!has_child && rf_v3_len2(rt->t_tip[j]) > 0 && rf_v3_len2(src->tip[in->joint]) > 0) {
        rf_vec3 vt = rt_tip_world(rt->t_rest_world[j], rt->t_tip[j]);
        rf_vec3 vs = rt_tip_world(src->rest_world[in->joint], src->tip[in->joint]);
        int32_t end = rt->t_centerline[j] ? RF_RT_NONE : rt_chain_reach(src, in->joint);
        if (end >= 0)
            vs = rf_v3_sub(src->rest_world[end].t, src->rest_world[in->joint].t);
        pairs[count++] = (rt_pair){vt, vs, end, true};
    }
    return count;
}

double rf_rt_twist_fit(rf_vec3 n, const rf_vec3 *a, const rf_vec3 *b, uint32_t count)
{
    double sin_sum = 0, cos_sum = 0;
    for (uint32_t i = 0; i < count; i++) {
        rf_vec3 pa = rf_v3_sub(a[i], rf_v3_scale(n, rf_v3_dot(a[i], n)));
        rf_vec3 pb = rf_v3_sub(b[i], rf_v3_scale(n, rf_v3_dot(b[i], n)));
        sin_sum += rf_v3_dot(rf_v3_cross(pa, pb), n);
        cos_sum += rf_v3_dot(pa, pb);
    }
    return sin_sum == 0 && cos_sum == 0 ? 0 : atan2(sin_sum, cos_sum);
}

/* Beyond this angle between the target's body axis (the top mapped joint to the farthest mapped
 * joint on the centerline) and the source's, once the body frames are aligned, the bodies have
 * different plans (a level quadruped spine under an upright biped's), not different poses. */
#define RT_BODY_PLAN_ANGLE (45.0 * RF_PI / 180.0)

/* The rotation turning the target's rest directions onto the source's: the primary pair
 * exactly, starting from the parent's alignment (so the twist follows the body's), then turned
 * about the primary direction to fit the other pairs best. A centerline bone (`keep`) keeps the
 * parent's alignment: only limbs are aligned. */
static rf_quat rt_align(const rt_pair *pairs, uint32_t count, rf_quat ref, bool keep)
{
    int32_t p = RF_RT_NONE;
    for (uint32_t i = 0; i < count; i++)
        if (pairs[i].primary)
            p = (int32_t)i;
    if (p < 0)
        return ref;
    if (keep)
        return ref;
    rf_vec3 from = rf_quat_rotate(ref, pairs[p].t);
    rf_quat a = rf_quat_mul(rf_quat_from_two_vectors(from, pairs[p].s), ref);
    rf_vec3 n = rf_v3_normalize(pairs[p].s), ta[16], sb[16];
    uint32_t m = 0;
    for (uint32_t i = 0; i < count && m < 16; i++)
        if ((int32_t)i != p)
            ta[m] = rf_quat_rotate(a, pairs[i].t), sb[m++] = pairs[i].s;
    double angle = rf_rt_twist_fit(n, ta, sb, m);
    return rf_quat_normalize(rf_quat_mul(rf_quat_from_axis_angle(n, angle), a));
}

/* The alignment of the nearest mapped ancestor's input from the same source, or none: the
 * source is read in the target's frame (rt_source_turn, rt-body.c), body frames aligned. */
static rf_quat rt_parent_align(const rf_retarget *rt, uint32_t j, uint32_t source,
                               const int32_t *mp)
{
    for (int32_t a = mp[j]; a >= 0; a = mp[a]) {
        const rf_rt_tjoint *tj = &rt->tj[a];
        for (uint32_t i = 0; i < tj->input_count; i++)
            if (rt->in[tj->first_input + i].source == source)
                return rt->in[tj->first_input + i].align;
    }
    return rf_quat_identity();
}

/* Whether source joint j and target joint t lie on opposite sides of their bodies (each side
 * read on its own skeleton's left axis, which the analysis finds from geometry). */
static bool rt_opposite_side(const rf_retarget *rt, const rf_rt_src *src, uint32_t j, uint32_t t)
{
    double ss = rf_v3_dot(rf_v3_sub(src->rest_world[j].t, src->center), src->left) / src->size;
    double ts = rf_v3_dot(rf_v3_sub(rt_tpos(rt, t), rt->center), rt->left) / rt->size;
    return (ss > 0.01 && ts < -0.01) || (ss < -0.01 && ts > 0.01);
}

/* Beyond this angle between a limb root's rest direction and where its source joint points, both
 * at rest and in most of the clip, the two are not the same bone in another pose (a T-pose arm
 * onto a hanging leg: 90 degrees at rest, 15 in the clip) but bones of another kind (a human
 * clavicle, sideways, onto a quadruped's shoulder blade, downward: 110 degrees in both). */
#define RT_LIMB_ROOT_ANGLE (60.0 * RF_PI / 180.0)

/* The median over 32 frames spread over source k's clip of the angle (radians) between direction
 * `want` (in the source's rest world frame) and the source segment from joint j along its rest
 * vector `rest` (to joint `end`, or a tip when end < 0), each frame's segment turned back by its
 * hierarchy parent's turn off rest: where the joint points in the body, in the clip's poses.
 * *leg: in some of those frames the joint's part of the body is the lowest (within 5% of the
 * source's size): a leg, whose direction must be followed for its foot to land. */
static double rt_clip_angle(const rf_retarget *rt, uint32_t k, uint32_t j, int32_t end,
                            rf_vec3 rest, rf_vec3 want, bool *leg)
{
    const rf_rt_src *src = &rt->src[k];
    enum { RT_TYPICAL_FRAMES = 32 };
    size_t m = rt->max_src_n ? rt->max_src_n : src->n;
    rf_xform *local = malloc(m * sizeof *local), *world = malloc(m * sizeof *world);
    float *rot = malloc(m * 4 * sizeof *rot), *tr = malloc(m * 3 * sizeof *tr);
    double angle[RT_TYPICAL_FRAMES];
    uint32_t frames = src->anim->frame_count, count = 0;
    rf_vec3 local_rest = rf_quat_rotate(rf_quat_conj(src->rest_world[j].r), rest);
    int32_t p = src->skel->joints[j].parent;
    *leg = false;
    for (uint32_t i = 0; local && world && rot && tr && i < RT_TYPICAL_FRAMES && frames; i++) {
        uint32_t f = (uint32_t)((uint64_t)i * (frames - 1) / (RT_TYPICAL_FRAMES - 1));
        rf_rt_source_world(rt, k, f / src->anim->fps, local, world, rot, tr);
        rf_vec3 d =
            end >= 0 ? rf_v3_sub(world[end].t, world[j].t) : rf_quat_rotate(world[j].r, local_rest);
        if (p >= 0) /* undo the parent's turn off its rest */
            d = rf_quat_rotate(rf_quat_mul(src->rest_world[p].r, rf_quat_conj(world[p].r)), d);
        angle[count++] = rf_v3_angle(d, want);
        double low = INFINITY;
        for (uint32_t r = 0; r < src->n; r++)
            if (src->skel->joints[r].parent < 0)
                low = fmin(low, rf_rt_sole(src->skel, world, src->tip, src->up, r));
        *leg = *leg || rf_rt_sole(src->skel, world, src->tip, src->up, j) <= low + 0.05 * src->size;
    }
    free(local), free(world), free(rot), free(tr);
    return count ? rf_rt_select(angle, count, count / 2) : 0;
}

/* Resolves one input of mapped target joint j. */
static void rt_input_resolve(rf_retarget *rt, uint32_t j, const rf_map_input *in, rf_rt_input *out,
                             const int32_t *mp, const int32_t *primary)
{
    const rf_rt_src *src = &rt->src[in->source];
    rt_pair pairs[64];
    uint32_t count = rt_pairs(rt, j, in, mp, primary, pairs, 63);
    out->source = in->source;
    out->joint = in->joint;
    out->flags = in->flags & (RF_MAP_REVERSE | RF_MAP_MIRROR);
    /* A joint placed from the body joint it belongs to (a foot under a placement root) bends
     * against that joint, not against its parent in the file: a reversal a matcher read off the
     * file's tree (the Robot's feet under CMU, played backwards, pitched 40-70 degrees toe-down
     * in every crouch) does not hold for it. */
    if (rt->anchor[j] >= 0)
        out->flags &= ~(uint32_t)RF_MAP_REVERSE;
    out->parent = src->skel->joints[in->joint].parent;
    out->seg_end = RF_RT_NONE;
    if ((in->flags & RF_MAP_MIRROR) && rt_opposite_side(rt, src, in->joint, j)) {
        out->flags |= RF_RT_IN_REFLECT;
        for (uint32_t i = 0; i < count; i++)
            pairs[i].s = rf_rt_reflect_v(pairs[i].s, src->left);
    }
    if ((in->flags & RF_MAP_MIRROR) && !(out->flags & RF_RT_IN_REFLECT) && !rt->t_centerline[j])
        out->flags |= RF_RT_IN_PHASE;
    bool keep = rt->t_centerline[j] && rt->plan_differs;
    if (keep)
        out->flags |= RF_RT_IN_LEVEL;
    /* Any centerline bone keeps the body's alignment too: a neck or a tail is built differently
     * from one animal to the next, and turning it onto the source's rest direction held
     * Testwuson's neck 60 degrees off its rest under the Fox's Walk (a crease behind the head).
     * A degenerate rest has no directions of its own to keep. */
    keep = keep || (rt->t_centerline[j] && !rt->t_degenerate);
    /* The root of a limb driven half a cycle later by the source's leg (a quadruped's shoulder
     * blade or upper arm under a biped's hip joint or thigh) is a bone of another kind: it takes
     * its source's turns, not its direction, while the bones below are aligned so the leg lands
     * as the source's does. Aligned onto CMU's hip joint, sideways, Testwuson's shoulder blades
     * tore the skin over them (torn limbs p99 5.5% of the height, 3.4 with the blades kept). */
    keep = keep || ((out->flags & RF_RT_IN_PHASE) && mp[j] >= 0 && rt->t_centerline[mp[j]] &&
                    !rt->t_degenerate);
    rf_quat ref = rt_parent_align(rt, j, in->source, mp);
    /* A limb's root (off the centerline, hanging from it) driven by a source joint of another
     * kind takes that joint's turn off its rest, as the centerline does, instead of its shape:
     * aligned onto CMU's clavicle, sideways, Testwuson's shoulder blades stood 110-116 degrees
     * off their rest, down, in every frame, crushing the skin over them. Never a leg's: its
     * foot must land where the source's does. */
    for (uint32_t i = 0; i < count && !keep && !rt->t_degenerate && !rt->t_centerline[j] &&
                         mp[j] >= 0 && rt->t_centerline[mp[j]];
         i++) {
        rf_vec3 want = rf_quat_rotate(ref, pairs[i].t);
        bool leg;
        keep = pairs[i].primary && rf_v3_angle(want, pairs[i].s) > RT_LIMB_ROOT_ANGLE &&
               rt_clip_angle(rt, in->source, in->joint, pairs[i].end, pairs[i].s, want, &leg) >
                   RT_LIMB_ROOT_ANGLE &&
               !leg;
        out->flags |= keep ? RF_RT_IN_KIND : 0;
    }
    /* A top joint with three directions or more (a quadruped's hips: legs, spine, tail) carries
     * the body's attitude: its alignment is the body frames' (the identity: the source is read
     * in the target's frame, body frames aligned), so a level source keeps it level. Laying it by
     * its directions tilts it wherever the two bodies are built differently: a horse's rising tail
     * laid along the Fox's hanging one tilted the horse 45 degrees, and a fit of all of them still
     * pitched the cat (whose forelegs hang from its one torso bone, low, where the Fox's shoulders
     * are high) and the horse nose up. */
    out->align = mp[j] < 0 && count >= 3 && !keep && !rt->t_degenerate
                     ? ref
                     : rt_align(pairs, count, ref, keep);
    rf_quat rs = src->rest_world[in->joint].r;
    for (uint32_t i = 0; i < count; i++) {
        if (!pairs[i].primary || pairs[i].end < 0 || (out->flags & RF_MAP_REVERSE))
            continue;
        /* A child hanging from the joint moves with its rotation (its own translation, when
         * animated, is carried over separately); a segment through other joints does not. */
        uint32_t e = (uint32_t)pairs[i].end;
        if (src->skel->joints[e].parent == (int32_t)in->joint)
            continue;
        rf_vec3 u = rf_v3_sub(src->rest_world[e].t, src->rest_world[in->joint].t);
        out->flags |= RF_RT_IN_CORRECT;
        out->seg_end = (int32_t)e;
        out->seg_local = rf_quat_rotate(rf_quat_conj(rs), rf_v3_normalize(u));
    }
    out->rest_inv = rf_quat_conj(rs);
    out->C = rf_quat_mul(out->rest_inv, out->align);
    out->K = rf_quat_normalize(rf_quat_mul(out->C, rt->t_rest_world[j].r));
    out->parent_rest_inv =
        out->parent >= 0 ? rf_quat_conj(src->rest_world[out->parent].r) : rf_quat_identity();
}

/* Blend of the inputs' alignments with their weights, sign-aligned. */
static rf_quat rt_blend_align(const rf_rt_input *in, uint32_t count)
{
    rf_quat sum = {0, 0, 0, 0}, first = in[0].align;
    for (uint32_t i = 0; i < count; i++) {
        rf_quat a = in[i].align;
        double s = rf_quat_dot(a, first) < 0 ? -in[i].weight : in[i].weight;
        sum.x += s * a.x, sum.y += s * a.y, sum.z += s * a.z, sum.w += s * a.w;
    }
    return rf_quat_normalize(sum);
}

/* Whether the target's body lies differently from source 0's: compares the axis from the top
 * mapped joint to the farthest mapped centerline joint in both rests. */
static bool rt_plan_differs(const rf_retarget *rt, const int32_t *mp)
{
    if (rt->t_degenerate)
        return false; /* a rest that is no body has no plan to keep */
    int32_t top = RF_RT_NONE, far = RF_RT_NONE;
    for (uint32_t j = 0; j < rt->n && top < 0; j++)
        if (rt->mapping->entries[j].input_count && mp[j] < 0)
            top = (int32_t)j;
    double best = 0;
    for (uint32_t j = 0; top >= 0 && j < rt->n; j++) {
        const rf_map_input *in = rt_input_from(rt->mapping, j, 0);
        double d = rf_v3_dist(rt_tpos(rt, j), rt_tpos(rt, (uint32_t)top));
        if (in && rt->t_centerline[j] && d > best)
            best = d, far = (int32_t)j;
    }
    const rf_map_input *a = top >= 0 ? rt_input_from(rt->mapping, (uint32_t)top, 0) : NULL;
    const rf_map_input *b = far >= 0 ? rt_input_from(rt->mapping, (uint32_t)far, 0) : NULL;
    if (!a || !b)
        return false;
    const rf_rt_src *src = &rt->src[0];
    rf_vec3 vt = rf_v3_sub(rt_tpos(rt, (uint32_t)far), rt_tpos(rt, (uint32_t)top));
    rf_vec3 vs = rf_v3_sub(src->rest_world[b->joint].t, src->rest_world[a->joint].t);
    return rf_v3_angle(vt, vs) > RT_BODY_PLAN_ANGLE;
}

static bool rt_inputs(rf_retarget *rt, const int32_t *mp, const int32_t *primary)
{
    rt->plan_differs = rt_plan_differs(rt, mp);
    uint32_t total = 0;
    for (uint32_t j = 0; j < rt->n; j++)
        total += rt->mapping->entries[j].input_count;
    rt->in = calloc(total ? total : 1, sizeof *rt->in);
    rt->slots = calloc(total ? total : 1, sizeof *rt->slots);
    if (!rt->in || !rt->slots)
        return false;
    for (uint32_t j = 0; j < rt->n; j++) {
        const rf_map_entry *e = &rt->mapping->entries[j];
        rf_rt_tjoint *tj = &rt->tj[j];
        if (!e->input_count)
            continue;
        tj->kind = RF_RT_MAPPED;
        tj->first_input = rt->input_count;
        tj->input_count = e->input_count;
        double wsum = 0;
        for (uint32_t i = 0; i < e->input_count; i++)
            wsum += e->inputs[i].weight;
        for (uint32_t i = 0; i < e->input_count; i++) {
            const rf_map_input *in = &e->inputs[i];
            rf_rt_input *out = &rt->in[rt->input_count++];
            rt_input_resolve(rt, j, in, out, mp, primary);
            rt->level_flat = rt->level_flat || (out->flags & RF_RT_IN_PHASE);
            out->weight = in->weight / wsum;
            double offset = -in->delay + ((in->flags & RF_MAP_MIRROR) ? 0.5 * rt->cycle : 0);
            out->slot = rt_slot_for(rt, in->source, offset);
            if (in->flags & RF_MAP_MIRROR)
                rt->slots[out->slot].wrap = rt->cycle;
        }
        tj->align = rt_blend_align(rt->in + tj->first_input, tj->input_count);
    }
    return true;
}

/* ---- chains whose unmapped joints share the rotation ---- */

static bool rt_chains(rf_retarget *rt, const int32_t *primary)
{
    rt->links = calloc(rt->n, sizeof *rt->links);
    if (!rt->links)
        return false;
    for (uint32_t j = 0; j < rt->n; j++)
        rt->tj[j].owner = RF_RT_NONE;
    for (uint32_t j = 0; j < rt->n; j++) {
        rf_rt_tjoint *tj = &rt->tj[j];
        if (tj->kind != RF_RT_MAPPED || primary[j] < 0)
            continue;
        uint32_t c = (uint32_t)primary[j], n = 0;
        if (!rf_rt_carries(rt->target, (int32_t)j, c))
            continue; /* an anchored child: placed from j, no chain between */
        bool body = true;
        for (int32_t u = rt->target->joints[c].parent; u != (int32_t)j;
             u = rt->target->joints[u].parent)
            n++, body = body && rt->t_role[u] == RF_ROLE_BODY;
        if (!body)
            continue; /* an axis node between: it never moves, c is turned on its own */
        if (!n)
            continue; /* the mapped child hangs from j directly: no chain */
        tj->owner = (int32_t)j;
        tj->first_link = rt->link_count;
        tj->link_count = n + 1;
        tj->chord = rf_v3_normalize(rf_v3_sub(rt_tpos(rt, c), rt_tpos(rt, j)));
        /* Links top down: walk up from c, filling from the end. */
        uint32_t next = c;
        for (uint32_t k = n + 1; k-- > 0;) {
            uint32_t joint = k == 0 ? j : (uint32_t)rt->target->joints[next].parent;
            rf_rt_link *l = &rt->links[tj->first_link + k];
            l->joint = joint;
            l->share = (double)(k + 1) / (n + 1);
            l->bone = rf_quat_rotate(tj->align, rf_v3_sub(rt_tpos(rt, next), rt_tpos(rt, joint)));
            if (k > 0) {
                rt->tj[joint].kind = RF_RT_SHARED;
                rt->tj[joint].owner = (int32_t)j;
            }
            rt->tj[joint].share = l->share;
            next = joint;
        }
        rt->link_count += n + 1;
    }
    return true;
}

/* ---- root motion, positions the frame needs ---- */

static void rt_mark_pos(rf_rt_src *src, int32_t j)
{
    for (; j >= 0 && !src->need_pos[j]; j = src->skel->joints[j].parent)
        src->need_pos[j] = 1;
}

/* Whether source joint j's translation is keyed and moves in its clip (files that key every
 * joint's position, as Maya exports do, mostly repeat the offset). */
static bool rt_translation_moves(const rf_rt_src *src, uint32_t j)
{
    if (!(src->anim->channels[j] & RF_CHANNEL_TRANSLATION))
        return false;
    rf_vec3 rest = src->rest_local[j].t;
    for (uint32_t f = 0; f < src->anim->frame_count; f++)
        if (rf_v3_dist(rf_animation_translation(src->anim, f, j), rest) > 1e-6 * src->size)
            return true;
    return false;
}

static void rt_root_motion(rf_retarget *rt, const int32_t *mp)
{
    for (uint32_t j = 0; j < rt->n; j++) {
        rf_rt_tjoint *tj = &rt->tj[j];
        tj->parent = rt->target->joints[j].parent;
        tj->rest_local = rf_quat_normalize(rt->target->joints[j].rest.r);
        tj->rest_world = rt->t_rest_world[j].r;
        tj->root_motion = tj->kind == RF_RT_MAPPED && mp[j] < 0 && rt->anchor[j] < 0;
        for (uint32_t i = 0; !tj->root_motion && rt->anchor[j] < 0 && i < tj->input_count; i++) {
            const rf_rt_input *in = &rt->in[tj->first_input + i];
            tj->translate = tj->translate || rt_translation_moves(&rt->src[in->source], in->joint);
        }
        if (tj->root_motion)
            tj->parent_world_inv = tj->parent >= 0 ? rf_xform_invert(rt->t_rest_world[tj->parent])
                                                   : rf_xform_identity();
        for (uint32_t i = 0; i < tj->input_count; i++) {
            const rf_rt_input *in = &rt->in[tj->first_input + i];
            rf_rt_src *src = &rt->src[in->source];
            if (tj->root_motion)
                rt_mark_pos(src, (int32_t)in->joint);
            if (in->flags & RF_RT_IN_CORRECT) {
                rt_mark_pos(src, (int32_t)in->joint);
                rt_mark_pos(src, in->seg_end);
            }
        }
    }
}

/* ---- measured bones and contact effectors ---- */

/* A target joint measured for direction fidelity: one undelayed, unflagged input. */
static bool rt_plain(const rf_retarget *rt, uint32_t j)
{
    const rf_map_entry *e = &rt->mapping->entries[j];
    return e->input_count == 1 && e->inputs[0].delay == 0 && !e->inputs[0].flags;
}

static bool rt_bones(rf_retarget *rt, const int32_t *mp)
{
    rt->bones = calloc(rt->n * 2, sizeof *rt->bones);
    if (!rt->bones)
        return false;
    for (uint32_t j = 0; j < rt->n; j++) {
        if (!rt_plain(rt, j))
            continue;
        uint32_t kids = 0, only = 0;
        for (uint32_t c = 0; c < rt->n; c++)
            if (mp[c] == (int32_t)j && rt->mapping->entries[c].input_count)
                kids++, only = c;
        bool child_ok =
            kids == 1 && rt_plain(rt, only) &&
            rt->mapping->entries[only].inputs[0].source == rt->mapping->entries[j].inputs[0].source;
        const rf_map_input *in = &rt->mapping->entries[j].inputs[0];
        bool tip_ok = kids == 0 && rf_v3_len2(rt->t_tip[j]) > 0 &&
                      rf_v3_len2(rt->src[in->source].tip[in->joint]) > 0;
        if (!child_ok && !tip_ok)
            continue;
        rt->bones[rt->bone_count * 2] = j;
        rt->bones[rt->bone_count * 2 + 1] = child_ok ? only : j; /* j itself: its tip */
        rt->bone_count++;
    }
    return true;
}

/* ---- the plan ---- */

static bool rt_alloc_frame(rf_retarget *rt)
{
    rt->rest_tr = malloc((rt->n ? rt->n : 1) * 3 * sizeof *rt->rest_tr);
    if (!rt->rest_tr || !rf_rt_hot_init(rt) || !rf_rt_work_init(rt, &rt->work))
        return false;
    for (uint32_t j = 0; j < rt->n; j++) {
        rf_vec3 t = rt->target->joints[j].rest.t;
        rt->rest_tr[j * 3] = (float)t.x, rt->rest_tr[j * 3 + 1] = (float)t.y;
        rt->rest_tr[j * 3 + 2] = (float)t.z;
    }
    return true;
}

/* A limb that cannot hang as its source's does: off the centerline, driven by a source joint in
 * the upper half of its source (an arm, not a leg), reaching from its root more than RT_HANG
 * times its root's height over the target's lowest point. Its joints past the root keep their
 * rest turns, so it moves whole from its root; a human's arm bends at the elbow and the wrist,
 * and laid on such a limb those bends fold it through the floor and fan the pieces of its
 * membrane apart. Human arms reach 0.4 to 0.8 times their shoulders' height, legs about 1, a
 * bird's folded wings 2, the wings of the random dragons (bench/creatures.sh) 1.54 to 2.9 and
 * the shared dragons' 3 to 3.6. A limb clear of the floor at rest (rt_limb_clear: a wing) is
 * held from RT_HANG_CLEAR (the owl's wings and greenman's long arm, 1.37, are not); one reaching
 * down to the floor (a bull frog's splayed legs, 1.6 to 1.7, driven by arms: its feet) only
 * from RT_HANG (the bat's legs, 5). */
#define RT_HANG 2.5
#define RT_HANG_CLEAR 1.5

/* Whether the limb from joint r stands clear of the floor at rest: its joints and bone tips past
 * r all over a quarter of r's height over the rest's lowest point `low` (a wing spread at the
 * shoulder's height), not reaching down to it (a leg the body stands on, which the parts pass
 * must not lift as a whole: the bat's artist rig under the Fox's Run sank into the floor). */
static bool rt_limb_clear(const rf_retarget *rt, uint32_t r, rf_vec3 up, double low)
{
    double bar = low + 0.25 * (rf_rt_height(up, rt->t_rest_world[r].t) - low);
    for (uint32_t c = r + 1; c < rt->n; c++) {
        if (!rf_rt_carries(rt->target, (int32_t)r, c))
            continue;
        rf_xform w = rt->t_rest_world[c];
        if (rf_rt_height(up, w.t) < bar || rf_rt_height(up, rf_xform_point(w, rt->t_tip[c])) < bar)
            return false;
    }
    return true;
}

/* The up a rest is measured along for limbs that cannot hang: its own (the analysis's, from its
 * limbs) when it lies more than 45 degrees across the one it is retargeted along. Lying on its
 * back, a human's shoulders stand no more than the body's thickness over its lowest point, and
 * its arms, reaching many times that, were held whole as wings; standing as its source has it
 * stand, they hang. A rest that is no body (all its bones on one line) has no up of its own. */
static rf_vec3 rt_hang_up(const rf_retarget *rt)
{
    if (!rt->t_degenerate && rf_v3_len2(rt->t_own_up) > 0.5 &&
        rf_v3_dot(rt->t_own_up, rt->up) < sqrt(0.5))
        return rf_v3_normalize(rt->t_own_up);
    return rt->up;
}

/* The farthest joint or bone tip of the limb from joint r, from r's pivot at rest. */
static rf_vec3 rt_limb_reach(const rf_retarget *rt, uint32_t r)
{
    rf_vec3 o = rt->t_rest_world[r].t, far = rf_v3(0, 0, 0);
    for (uint32_t c = r + 1; c < rt->n; c++) {
        if (!rf_rt_carries(rt->target, (int32_t)r, c))
            continue;
        rf_vec3 p = rf_v3_sub(rt->t_rest_world[c].t, o);
        far = rf_v3_len2(p) > rf_v3_len2(far) ? p : far;
        if (rf_v3_len2(rt->t_tip[c]) > 0) {
            p = rf_v3_sub(rf_xform_point(rt->t_rest_world[c], rt->t_tip[c]), o);
            far = rf_v3_len2(p) > rf_v3_len2(far) ? p : far;
        }
    }
    return far;
}

/* How many times its root's height over `low` the limb from joint r reaches, for a limb's root
 * driven by an arm (off the centerline, hanging from it, its source joint in the upper half of
 * its source); -1 for any other joint. */
static double rt_hang_ratio(const rf_retarget *rt, uint32_t r, rf_vec3 up, double low)
{
    const rf_rt_tjoint *tr = &rt->tj[r];
    int32_t lp = rt->lparent[r];
    if (tr->kind != RF_RT_MAPPED || rt->t_centerline[r] || lp < 0 || !rt->t_centerline[lp])
        return -1;
    const rf_rt_input *in = &rt->in[tr->first_input];
    const rf_rt_src *src = &rt->src[in->source];
    double slow, shigh;
    rf_rt_span(src->skel, src->rest_world, src->tip, src->up, NULL, false, &slow, &shigh);
    if (rf_rt_height(src->up, src->rest_world[in->joint].t) < 0.5 * (slow + shigh))
        return -1; /* a leg */
    double h = rf_rt_height(up, rt->t_rest_world[r].t) - low;
    return h > 0 ? rf_v3_len(rt_limb_reach(rt, r)) / h : -1;
}

/* Holds the limb from root r whole: its joints past r keep their rest turns, and r's inputs
 * swing it as far as its reach leaves it clear of the floor (asin of its height over its reach),
 * without the twist of the source's bone: a human's upper arm turns about itself as the
 * forearm swings, and a wing taking that turn stood its membrane on edge. */
static void rt_hold_whole(rf_retarget *rt, uint32_t r, bool clear, double ratio)
{
    for (uint32_t c = r; c < rt->n; c++)
        if (rf_rt_carries(rt->target, (int32_t)r, c)) {
            rt->t_whole[c] = clear ? (int32_t)r : RF_RT_NONE;
            if (c != r)
                rt->tj[c].kind = RF_RT_REST;
        }
    rf_rt_input *in = &rt->in[rt->tj[r].first_input];
    in->flags |= RF_RT_IN_WHOLE;
    in->whole_axis = rf_quat_rotate(rt->tj[r].align, rf_v3_normalize(rt_limb_reach(rt, r)));
    in->whole_limit = asin(1 / ratio);
}

/* Whether joints a and b of source src mirror each other: b within 5% of the source's size of
 * a's reflection across its symmetry plane (a clip's skeleton is built symmetric). */
static bool rt_source_mirrors(const rf_rt_src *src, uint32_t a, uint32_t b)
{
    rf_vec3 image = rf_rt_reflect_p(src->rest_world[a].t, src->center, src->left);
    return rf_v3_dist(image, src->rest_world[b].t) < 0.05 * src->size;
}

/* The limb root across the body from limb root r: the analysis's mirror of r, or for a rig built
 * too lopsided for the analysis to pair, the other limb root (rt_hang_ratio) as clear of the
 * floor as r (rt_limb_clear) driven by the mirror of r's source joint, the nearest to r's
 * reflection across the symmetry plane. RF_RT_NONE when none: a template's tail laid along a
 * dragon's wing, driven by the walk's left leg, pairs with no leg. */
static int32_t rt_limb_partner(const rf_retarget *rt, uint32_t r, const double *ratio,
                               const uint8_t *clear)
{
    if (rt->t_mirror[r] >= 0)
        return rt->t_mirror[r];
    const rf_rt_input *in = &rt->in[rt->tj[r].first_input];
    rf_vec3 image = rf_rt_reflect_p(rt->t_rest_world[r].t, rt->center, rt->left);
    int32_t best = RF_RT_NONE;
    double near = INFINITY;
    for (uint32_t c = 0; c < rt->n; c++) {
        if (ratio[c] < 0 || c == r || clear[c] != clear[r])
            continue;
        const rf_rt_input *ic = &rt->in[rt->tj[c].first_input];
        if (ic->source != in->source ||
            !rt_source_mirrors(&rt->src[in->source], in->joint, ic->joint))
            continue;
        double d = rf_v3_dist(rt->t_rest_world[c].t, image);
        if (d < near)
            near = d, best = (int32_t)c;
    }
    return best;
}

/* Limbs that cannot hang (RT_HANG, RT_HANG_CLEAR) are held whole, a pair across the body both or
 * neither: an auto-rig built a little lopsided (greenman's arms, 1.9 and 1.4 times their roots'
 * heights) had one arm stuck out sideways while the other hung. */
static bool rt_rigid_limbs(rf_retarget *rt)
{
    size_t n = rt->n ? rt->n : 1;
    rt->t_whole = malloc(n * sizeof *rt->t_whole);
    double *ratio = malloc(n * sizeof *ratio);
    uint8_t *clear = malloc(n), *over = malloc(n);
    bool ok = rt->t_whole && ratio && clear && over;
    rf_vec3 up = rt_hang_up(rt);
    double low, high;
    rf_rt_span(rt->target, rt->t_rest_world, rt->t_tip, up, NULL, false, &low, &high);
    for (uint32_t j = 0; ok && j < rt->n; j++) {
        rt->t_whole[j] = RF_RT_NONE;
        ratio[j] = rt_hang_ratio(rt, j, up, low);
        clear[j] = ratio[j] > 0 && rt_limb_clear(rt, j, up, low);
        over[j] = ratio[j] > (clear[j] ? RT_HANG_CLEAR : RT_HANG);
    }
    for (uint32_t r = 0; ok && r < rt->n; r++) {
        int32_t m = over[r] ? rt_limb_partner(rt, r, ratio, clear) : RF_RT_NONE;
        if (over[r] && (m < 0 || ratio[m] < 0 || over[m]))
            rt_hold_whole(rt, r, clear[r], ratio[r]);
    }
    free(ratio), free(clear), free(over);
    return ok;
}

static bool rt_plan(rf_retarget *rt, char *err, size_t err_size)
{
    uint32_t n = rt->n;
    int32_t *mp = malloc(n * sizeof *mp), *primary = malloc(n * sizeof *primary);
    uint32_t *weight = malloc(n * sizeof *weight);
    bool ok = mp && primary && weight;
    if (ok) {
        rt_mapped_parents(rt, mp);
        rt_mapped_weight(rt, mp, weight);
        rt->leg_target = 0;
        for (uint32_t j = 0; j < n; j++)
            primary[j] = rt->mapping->entries[j].input_count
                             ? rt_primary_child(rt, j, mp, weight, 1e-6 * rt->size)
                             : RF_RT_NONE;
        ok = rt_inputs(rt, mp, primary) && rt_chains(rt, primary) && rt_rigid_limbs(rt);
    }
    if (ok) {
        rt_root_motion(rt, mp);
        ok = rt_bones(rt, mp) && rt_alloc_frame(rt);
    }
    if (ok)
        ok = rf_rt_ground_prepare(rt, err, err_size);
    else
        rf_rt_fail(err, err_size, "out of memory");
    free(weight);
    free(primary);
    free(mp);
    return ok;
}

static bool rt_any_mapped(const rf_mapping *m)
{
    for (uint32_t j = 0; j < m->target_joint_count; j++)
        if (m->entries[j].input_count)
            return true;
    return false;
}

static bool rt_wants_cycle(const rf_mapping *m)
{
    for (uint32_t j = 0; j < m->target_joint_count; j++)
        for (uint32_t i = 0; i < m->entries[j].input_count; i++)
            if (m->entries[j].inputs[i].flags & RF_MAP_MIRROR)
                return true;
    return false;
}

rf_retarget *rf_retarget_new(const rf_rt_source *sources, uint32_t source_count,
                             const rf_skeleton *target, const rf_mapping *mapping,
                             const rf_retarget_options *opts, char *err, size_t err_size)
{
    if (!rt_check(sources, source_count, target, mapping, err, err_size))
        return NULL;
    rf_retarget *rt = calloc(1, sizeof *rt);
    if (!rt || !(rt->src = calloc(source_count, sizeof *rt->src)) ||
        !(rt->tj = calloc(target->joint_count, sizeof *rt->tj))) {
        rf_retarget_free(rt);
        rf_rt_fail(err, err_size, "out of memory");
        return NULL;
    }
    if (opts)
        rt->opt = *opts;
    else
        rf_retarget_options_default(&rt->opt);
    rt->target = target, rt->mapping = mapping, rt->n = target->joint_count;
    rt->source_count = source_count;
    rt->root_motion_on = true;
    rt->top_from = rt->top_to = RF_RT_NONE;
    for (uint32_t k = 0; k < source_count; k++) {
        rt->src[k].skel = sources[k].skeleton, rt->src[k].anim = sources[k].animation;
        rt->src[k].n = sources[k].skeleton->joint_count;
        if (rt->src[k].n > rt->max_src_n)
            rt->max_src_n = rt->src[k].n;
    }
    bool ok = rf_rt_sources_prepare(rt, err, err_size) && rf_rt_target_prepare(rt, err, err_size) &&
              rf_rt_roles_prepare(rt, err, err_size);
    if (ok && !rt_any_mapped(rt->mapping)) {
        rf_rt_fail(err, err_size,
                   "the mapping maps only placement, axis-conversion or helper joints (%u "
                   "inputs dropped): no body joint is driven",
                   rt->dropped);
        ok = false;
    }
    if (ok && rt_wants_cycle(mapping))
        rt->cycle = rt->opt.cycle > 0 ? rt->opt.cycle : rf_rt_detect_cycle(rt, 0);
    ok = ok && rt_plan(rt, err, err_size);
    if (ok && !rf_rt_effectors_prepare(rt)) {
        rf_rt_fail(err, err_size, "out of memory");
        ok = false;
    }
    if (!ok) {
        rf_retarget_free(rt);
        return NULL;
    }
    return rt;
}

void rf_retarget_free(rf_retarget *rt)
{
    if (!rt)
        return;
    for (uint32_t k = 0; rt->src && k < rt->source_count; k++) {
        rf_rt_src *s = &rt->src[k];
        free(s->rest_local), free(s->rest_world), free(s->skel_pos), free(s->tip);
        free(s->need_pos), free(s->parent), free(s->need_rot), free(s->above);
    }
    rf_rt_work_free(rt, &rt->work);
    free(rt->src), free(rt->tj), free(rt->in), free(rt->links), free(rt->slots);
    free(rt->t_rest_world), free(rt->t_tip), free(rt->t_hull), free(rt->t_aligned),
        free(rt->t_centerline);
    free(rt->t_above), free(rt->bones), free(rt->effectors), free(rt->effector_src),
        free(rt->effector_tip), free(rt->hot), free(rt->rest_tr);
    free(rt->w0), free(rt->t_logical), free(rt->t_mirror), free(rt->t_role), free(rt->lparent),
        free(rt->anchor);
    free(rt->anchor_off), free(rt->lorder), free(rt->t_need), free(rt->t_tip_set);
    free(rt->t_whole);
    rf_mapping_free(rt->own_map);
    rf_joint_roles_free(rt->t_roles);
    free(rt);
}

uint32_t rf_retarget_slot_count(const rf_retarget *rt)
{
    return rt->slot_count;
}

void rf_retarget_slot(const rf_retarget *rt, uint32_t i, uint32_t *source, double *offset)
{
    *source = rt->slots[i].source;
    *offset = rt->slots[i].offset;
}

void rf_retarget_info(const rf_retarget *rt, rf_rt_info *info)
{
    memset(info, 0, sizeof *info);
    info->leg_source = rt->src[0].leg;
    info->leg_target = rt->leg_target;
    info->root_scale = rt->src[0].scale;
    info->floor_source = rt->src[0].floor;
    info->floor_target = rt->floor_target;
    info->ground_shift = rt->ground_shift;
    info->cycle = rt->cycle;
    info->rest_frame = rt->src[0].rest_frame;
    info->whole_first = RF_RT_NONE;
    for (uint32_t j = 0; j < rt->n; j++) {
        info->mapped += rt->tj[j].kind == RF_RT_MAPPED;
        info->shared += rt->tj[j].kind == RF_RT_SHARED;
        bool whole = rt->tj[j].kind == RF_RT_MAPPED &&
                     (rt->in[rt->tj[j].first_input].flags & RF_RT_IN_WHOLE);
        if (whole && !info->whole++)
            info->whole_first = (int32_t)j;
    }
    info->effectors = rt->effector_count;
    info->dropped = rt->dropped;
    info->anchored = rt->anchored;
    info->top_from = rt->top_from, info->top_to = rt->top_to;
}
