/* The contact pass: which target joints are feet (end effectors near the floor in the aligned
 * rest), when their source counterparts touch the ground (low and slow, relative to the leg),
 * and pinning them there through whatever IK solver is connected, so they do not slide. */
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include <rigflow/prefault.h>

#include "rt-internal.h"

/* ---- effectors ---- */

/* Height of target joint j's source counterpart (its first input) over the lowest point of that
 * source's rest, in the source's leg lengths: the source's body says what touches the ground. */
static double rt_source_height(const rf_retarget *rt, uint32_t j)
{
    const rf_rt_input *in = rt->in + rt->tj[j].first_input;
    const rf_rt_src *src = &rt->src[in->source];
    return (rf_rt_height(src->up, src->rest_world[in->joint].t) - src->lowest) / src->leg;
}

/* Every joint is looked at: a body child placed from j (a foot under a placement root) may come
 * before it in the file. */
static bool rt_has_mapped_child(const rf_retarget *rt, const int32_t *mp, uint32_t j)
{
    for (uint32_t c = 0; c < rt->n; c++)
        if (mp[c] == (int32_t)j && rt->tj[c].kind == RF_RT_MAPPED)
            return true;
    return false;
}

/* The lowest point of the target's rest (joints and tips) along up. */
static double rt_target_rest_low(const rf_retarget *rt)
{
    double low = INFINITY;
    for (uint32_t j = 0; j < rt->n; j++) {
        low = fmin(low, rf_rt_height(rt->up, rt->t_rest_world[j].t));
        if (rf_v3_len2(rt->t_tip[j]) > 0)
            low =
                fmin(low, rf_rt_height(rt->up, rf_xform_point(rt->t_rest_world[j], rt->t_tip[j])));
    }
    return low;
}

/* The source joint a foot at target joint e's bone tip follows: e's source joint stands high,
 * but a foot hangs below it in the source (unmapped: the target's chain ends sooner). The
 * lowest source joint under it, climbed while its parent is still low (a toe's ankle); -1 when
 * nothing under it is low. */
static int32_t rt_source_foot_below(const rf_retarget *rt, uint32_t e, double low)
{
    const rf_rt_input *in = rt->in + rt->tj[e].first_input;
    const rf_rt_src *src = &rt->src[in->source];
    int32_t best = RF_RT_NONE;
    double best_h = INFINITY;
    for (uint32_t c = in->joint + 1; c < src->n; c++) {
        double h = (rf_rt_height(src->up, src->rest_world[c].t) - src->lowest) / src->leg;
        if (h <= low && h < best_h && rf_rt_carries(src->skel, (int32_t)in->joint, c))
            best = (int32_t)c, best_h = h;
    }
    while (best >= 0) {
        int32_t p = src->skel->joints[best].parent;
        if (p < 0 || p == (int32_t)in->joint ||
            (rf_rt_height(src->up, src->rest_world[p].t) - src->lowest) / src->leg > low)
            break;
        best = p;
    }
    return best;
}

/* Whether target joint e's bone is a leg's last, standing down to its tip on the target's floor
 * at rest: then the tip is a foot (a foot bone lying along the floor, a biped's, is not).
 * RT_TIP_CHAIN below a mapped limb joint (pinned with e and that joint as the chain),
 * RT_TIP_AIM hanging from the body itself (a one-bone leg: e alone is turned to aim its tip at
 * the pin; a chain would turn the torso), else RT_TIP_NONE. */
enum { RT_TIP_NONE = 0, RT_TIP_CHAIN = 1, RT_TIP_AIM = 2 };
static uint8_t rt_tip_foot(const rf_retarget *rt, const int32_t *mp, uint32_t e, double rest_low,
                           double low)
{
    int32_t p = rt->lparent[e];
    if (rf_v3_len2(rt->t_tip[e]) == 0 || p < 0 || mp[e] != p)
        return RT_TIP_NONE;
    rf_vec3 tip = rf_xform_point(rt->t_rest_world[e], rt->t_tip[e]);
    rf_vec3 bone = rf_v3_sub(rt->t_rest_world[e].t, tip);
    if (!(rf_rt_height(rt->up, bone) > 0.7 * rf_v3_len(bone)) ||
        rf_rt_height(rt->up, tip) - rest_low > low * rt->leg_target)
        return RT_TIP_NONE;
    return rt->tj[p].root_motion || rt->t_centerline[p] ? RT_TIP_AIM : RT_TIP_CHAIN;
}

static void rt_effector_add(rf_retarget *rt, uint32_t f, uint32_t src_joint, uint8_t tip)
{
    for (uint32_t i = 0; i < rt->effector_count; i++)
        if (rt->effectors[i] == f)
            return;
    rt->effector_src[rt->effector_count] = src_joint;
    rt->effector_tip[rt->effector_count] = tip;
    rt->effectors[rt->effector_count++] = f;
}

/* A foot: from the end of a mapped chain whose source joint is near the source's floor, climb
 * while the mapped parent's source joint is still low (a toe's ankle); the highest low joint is
 * the one pinned. It needs two bones above it for the solvers. A chain end whose source joint
 * stands high but has the source's foot below it, and whose own bone's tip stands on the
 * target's floor at rest (a horse's leg of two bones), is a foot at that tip, pinned with the
 * joint and the limb joint above it as the chain. */
bool rf_rt_effectors_prepare(rf_retarget *rt)
{
    int32_t *mp = malloc(rt->n * sizeof *mp);
    rt->effectors = malloc(rt->n * sizeof *rt->effectors);
    rt->effector_src = malloc(rt->n * sizeof *rt->effector_src);
    rt->effector_tip = malloc(rt->n ? rt->n : 1);
    if (!mp || !rt->effectors || !rt->effector_src || !rt->effector_tip) {
        free(mp);
        return false;
    }
    for (uint32_t j = 0; j < rt->n; j++) { /* along body parents: an anchored foot's is its shin */
        int32_t p = rt->lparent[j];
        for (uint32_t guard = 0; p >= 0 && rt->tj[p].kind != RF_RT_MAPPED && guard < rt->n; guard++)
            p = rt->lparent[p];
        mp[j] = p;
    }
    const double low = 0.25;
    double rest_low = rt_target_rest_low(rt);
    for (uint32_t e = 0; e < rt->n; e++) {
        if (rt->tj[e].kind != RF_RT_MAPPED || rt_has_mapped_child(rt, mp, e))
            continue;
        if (rt_source_height(rt, e) > low) {
            int32_t foot = rt_source_foot_below(rt, e, low);
            uint8_t tip = foot >= 0 ? rt_tip_foot(rt, mp, e, rest_low, low) : RT_TIP_NONE;
            if (tip)
                rt_effector_add(rt, e, (uint32_t)foot, tip);
            continue;
        }
        uint32_t f = e;
        while (mp[f] >= 0 && rt_source_height(rt, (uint32_t)mp[f]) <= low)
            f = (uint32_t)mp[f];
        int32_t p = rt->lparent[f];
        uint32_t sj = rt->in[rt->tj[f].first_input].joint;
        /* The source's foot on a target joint standing high, its bone's tip on the floor (a
         * horse's hock driven by a human's ankle): the tip is the foot. */
        bool high = rf_rt_height(rt->up, rt->t_rest_world[e].t) - rest_low > low * rt->leg_target;
        uint8_t tip = f == e && high ? rt_tip_foot(rt, mp, e, rest_low, low) : RT_TIP_NONE;
        if (tip)
            rt_effector_add(rt, e, sj, tip);
        else if (p >= 0 && rt->lparent[p] >= 0 && !rt->tj[f].root_motion)
            rt_effector_add(rt, f, sj, RT_TIP_NONE);
    }
    free(mp);
    return true;
}

rf_vec3 rf_rt_effector_point(const rf_retarget *rt, const rf_xform *world, uint32_t e)
{
    uint32_t j = rt->effectors[e];
    return rt->effector_tip[e] ? rf_xform_point(world[j], rt->t_tip[j]) : world[j].t;
}

void rf_rt_effector_source(const rf_retarget *rt, uint32_t e, uint32_t *source, uint32_t *joint)
{
    const rf_rt_input *in = rt->in + rt->tj[rt->effectors[e]].first_input;
    *source = in->source;
    *joint = rt->effector_src[e];
}

/* ---- contacts ---- */

/* The slot effector e's input reads. */
static uint32_t rt_effector_slot(const rf_retarget *rt, uint32_t e)
{
    return rt->in[rt->tj[rt->effectors[e]].first_input].slot;
}

/* Marks in need[] what the sole of source joint j reads (rf_rt_over_floor): j, everything below
 * it and its ancestors (what their world transforms are made from). */
static void rt_sole_need(const rf_rt_src *src, int32_t j, uint8_t *need)
{
    for (int32_t a = j; a >= 0 && !need[a]; a = src->parent[a])
        need[a] = 1;
    for (uint32_t c = (uint32_t)j + 1; c < src->n; c++)
        need[c] = need[c] ||
                  (src->parent[c] >= j && need[src->parent[c]] && rf_rt_carries(src->skel, j, c));
}

/* The source joints the tracks of slot s read: each effector's sole. */
static void rt_track_need(const rf_retarget *rt, uint32_t s, uint8_t *need)
{
    const rf_rt_src *src = &rt->src[rt->slots[s].source];
    memset(need, 0, src->n);
    for (uint32_t e = 0; e < rt->effector_count; e++)
        if (rt_effector_slot(rt, e) == s)
            rt_sole_need(src, (int32_t)rt->effector_src[e], need);
}

/* Slot s's tracks, a chunk of frames at a time (rf_rt_chunk), with scratch of its own (one
 * thread's share). */
typedef struct rt_tracks {
    const rf_retarget *rt;
    rf_rt_chunks *chunks;
    uint32_t s, frames;
    double fps, start;
    const uint8_t *need;
    const uint32_t *below, *below_count; /* [effector][source n], [effector]: rf_rt_below */
    rf_vec3 *pos;
    double *sole;
    bool ok;
} rt_tracks;

/* Frame f's track values from its source pose `world`. */
static void rt_track_frame(const rt_tracks *t, uint32_t k, uint32_t f, const rf_xform *world)
{
    const rf_retarget *rt = t->rt;
    for (uint32_t e = 0; e < rt->effector_count; e++) {
        if (rt_effector_slot(rt, e) != t->s)
            continue;
        uint32_t j = rt->effector_src[e];
        t->pos[(size_t)e * t->frames + f] = world[j].t;
        t->sole[(size_t)e * t->frames + f] = rf_rt_over_floor_below(
            rt, k, world, t->below + (size_t)e * rt->max_src_n, t->below_count[e]);
    }
}

/* Frames [f, end) two at a time (rf_rt_source_world_two), the last one alone, into pose. */
static void rt_tracks_chunk(const rt_tracks *t, uint32_t f, uint32_t end, rf_rt_source_pose *pose)
{
    const rf_retarget *rt = t->rt;
    uint32_t k = rt->slots[t->s].source;
    for (; f + 1 < end; f += 2) {
        double at[2] = {rf_rt_slot_time(rt, t->s, t->start + f / t->fps),
                        rf_rt_slot_time(rt, t->s, t->start + (f + 1) / t->fps)};
        rf_rt_source_world_two(rt, k, at, pose, t->need);
        rt_track_frame(t, k, f, pose[0].world);
        rt_track_frame(t, k, f + 1, pose[1].world);
    }
    if (f < end) {
        rf_rt_source_world_some(rt, k, rf_rt_slot_time(rt, t->s, t->start + f / t->fps),
                                pose[0].local, pose[0].world, pose[0].rot, pose[0].tr, t->need);
        rt_track_frame(t, k, f, pose[0].world);
    }
}

static void *rt_tracks_run(void *arg)
{
    rt_tracks *t = arg;
    const rf_retarget *rt = t->rt;
    size_t m = rt->max_src_n ? rt->max_src_n : 1;
    rf_rt_source_pose pose[2];
    t->ok = true;
    for (int i = 0; i < 2; i++) {
        pose[i].local = malloc(m * sizeof *pose[i].local);
        pose[i].world = malloc(m * sizeof *pose[i].world);
        pose[i].rot = malloc(m * 4 * sizeof *pose[i].rot);
        pose[i].tr = malloc(m * 3 * sizeof *pose[i].tr);
        t->ok = t->ok && pose[i].local && pose[i].world && pose[i].rot && pose[i].tr;
    }
    uint32_t first, end;
    while (t->ok && rf_rt_chunk(t->chunks, &first, &end))
        rt_tracks_chunk(t, first, end, pose);
    if (!t->ok) /* out of memory: the other thread takes the rest, or fails too */
        rf_rt_chunks_stop(t->chunks);
    for (int i = 0; i < 2; i++)
        free(pose[i].local), free(pose[i].world), free(pose[i].rot), free(pose[i].tr);
    return NULL;
}

/* World positions of every effector's source joint at each output frame, and the heights of
 * their soles over the source floor in source leg lengths, each at its input's sample time
 * (half a cycle away for a mirrored input). A long clip's frames are shared with a second
 * thread, as the retarget's are: frames are independent. */
static bool rt_source_tracks(const rf_retarget *rt, uint32_t frames, double fps, double start,
                             rf_vec3 *pos, double *sole)
{
    uint8_t *need = malloc(rt->max_src_n ? rt->max_src_n : 1);
    size_t effectors = rt->effector_count ? rt->effector_count : 1;
    uint32_t *below = malloc(effectors * (rt->max_src_n ? rt->max_src_n : 1) * sizeof *below);
    uint32_t *below_count = malloc(effectors * sizeof *below_count);
    bool ok = need && below && below_count;
    for (uint32_t e = 0; ok && e < rt->effector_count; e++)
        below_count[e] =
            rf_rt_below(rt->src[rt->in[rt->tj[rt->effectors[e]].first_input].source].skel,
                        rt->effector_src[e], below + (size_t)e * rt->max_src_n);
    for (uint32_t s = 0; ok && s < rt->slot_count; s++) {
        bool used = false;
        for (uint32_t e = 0; e < rt->effector_count; e++)
            used = used || rt_effector_slot(rt, e) == s;
        if (!used)
            continue;
        rt_track_need(rt, s, need);
        rf_rt_chunks chunks;
        rf_rt_chunks_init(&chunks, frames);
        rt_tracks a = {rt,   &chunks, s,           frames, fps,  start,
                       need, below,   below_count, pos,    sole, false},
                  b = a;
        pthread_t thread;
        bool two = (uint64_t)frames * rt->src[rt->slots[s].source].n >= RT_THREAD_MIN &&
                   pthread_create(&thread, NULL, rt_tracks_run, &b) == 0;
        rt_tracks_run(&a);
        if (two)
            pthread_join(thread, NULL);
        ok = a.ok && (!two || b.ok);
    }
    free(need), free(below), free(below_count);
    return ok;
}

/* Contact runs shorter than `min` frames are dropped, gaps shorter than `min` filled. */
static void rt_clean_runs(uint8_t *c, uint32_t frames, uint32_t min)
{
    for (int pass = 0; pass < 2; pass++) {
        uint8_t want = pass == 0 ? 0 : 1; /* first fill gaps (runs of 0), then drop runs of 1 */
        for (uint32_t f = 0; f < frames;) {
            uint32_t g = f;
            while (g < frames && c[g] == c[f])
                g++;
            bool inner = f > 0 && g < frames;
            if (c[f] == want && g - f < min && (inner || want == 1))
                memset(c + f, !want, g - f);
            f = g;
        }
    }
}

uint8_t *rf_rt_detect_contacts(const rf_retarget *rt, uint32_t frames, double fps, double start,
                               rf_vec3 *src_pos, double *src_sole)
{
    size_t count = (size_t)rt->effector_count * frames;
    uint8_t *c = calloc(count ? count : 1, 1);
    rf_vec3 *pos = src_pos ? src_pos : malloc((count ? count : 1) * sizeof *pos);
    double *sole = src_sole ? src_sole : malloc((count ? count : 1) * sizeof *sole);
    if (pos != src_pos)
        rf_prefault(pos, count * sizeof *pos);
    if (sole != src_sole)
        rf_prefault(sole, count * sizeof *sole);
    bool ok = c && pos && sole && rt_source_tracks(rt, frames, fps, start, pos, sole);
    if (sole != src_sole)
        free(sole);
    if (!ok) {
        free(c);
        if (pos != src_pos)
            free(pos);
        return NULL;
    }
    for (uint32_t e = 0; e < rt->effector_count; e++) {
        uint32_t k, j;
        rf_rt_effector_source(rt, e, &k, &j);
        const rf_rt_src *src = &rt->src[k];
        const rf_vec3 *p = pos + (size_t)e * frames;
        double lowest = INFINITY;
        for (uint32_t f = 0; f < frames; f++)
            lowest = fmin(lowest, rf_rt_height(src->up, p[f]));
        for (uint32_t f = 0; f < frames && frames > 1; f++) {
            uint32_t a = f ? f - 1 : 0, b = f + 1 < frames ? f + 1 : f;
            rf_vec3 d = rf_rt_horizontal(src->up, rf_v3_sub(p[b], p[a]));
            double speed = rf_v3_len(d) * fps / (b - a) / src->leg;
            double height = (rf_rt_height(src->up, p[f]) - lowest) / src->leg;
            c[(size_t)e * frames + f] =
                height <= rt->opt.contact_height && speed <= rt->opt.contact_speed;
        }
        rt_clean_runs(c + (size_t)e * frames, frames, (uint32_t)ceil(0.05 * fps));
    }
    if (pos != src_pos)
        free(pos);
    return c;
}

/* Whether effector e is a foot of another pair of legs driven half a cycle later (RF_RT_IN_PHASE:
 * a quadruped's forefoot under a biped's foot). */
static bool rt_effector_phase(const rf_retarget *rt, uint32_t e)
{
    const rf_rt_tjoint *tj = &rt->tj[rt->effectors[e]];
    return tj->kind == RF_RT_MAPPED && tj->input_count &&
           (rt->in[tj->first_input].flags & RF_RT_IN_PHASE);
}

/* Whether effector e is a foot driven half a cycle later that steps (rt_phase_step): one its
 * solver's chain can lift. A one-bone leg hanging from the body (RT_TIP_AIM) is only turned
 * about its pivot, so its tip cannot rise off the floor without swinging along it: it keeps its
 * source's contacts half a cycle later and is dragged along (rt_phase_drag). Stepping, the
 * animalia fox's forefeet slid more (26 and 54% of the height a second -> 37 and 68). */
bool rf_rt_effector_steps(const rf_retarget *rt, uint32_t e)
{
    return rt_effector_phase(rt, e) && rt->effector_tip[e] != RT_TIP_AIM;
}

/* Every foot aimed about its pivot (RT_TIP_AIM), none pinned through a solver's chain. */
bool rf_rt_feet_rigid(const rf_retarget *rt)
{
    for (uint32_t e = 0; e < rt->effector_count; e++)
        if (rt->effector_tip[e] != RT_TIP_AIM)
            return false;
    return rt->effector_count > 0;
}

/* A foot driven half a cycle later moves with the body now and its leg half a cycle later: its
 * source's leg is down when the source's body, half a cycle later, stands over it, not when this
 * body does. Under CMU 01_01 the Fox's forefeet, in their source's contacts, stood over the floor
 * (0.1-0.2 leg at the middle of each) and moved at 1.5 leg/s, and between them went through it
 * (every frame of the swing, at 2.2 leg/s) and were held at its level, sliding. Such a foot is
 * down where its own motion is, read as a source foot is: its sole (`sole`, [eff][frames],
 * heights along up in the clip read) within contact_height leg lengths of its low (the 10th
 * percentile over the clip: one frame deep through the floor does not set it). */
bool rf_rt_phase_contacts(const rf_retarget *rt, uint32_t frames, double fps, const double *sole,
                          uint8_t *contact)
{
    double *low = malloc((frames ? frames : 1) * sizeof *low);
    if (!low)
        return false;
    for (uint32_t e = 0; frames && e < rt->effector_count; e++) {
        if (!rf_rt_effector_steps(rt, e))
            continue;
        const double *h = sole + (size_t)e * frames;
        memcpy(low, h, frames * sizeof *low);
        double lowest = rf_rt_select(low, frames, frames / 10);
        uint8_t *c = contact + (size_t)e * frames;
        for (uint32_t f = 0; f < frames; f++)
            c[f] = h[f] <= lowest + rt->opt.contact_height * rt->leg_target;
        rt_clean_runs(c, frames, (uint32_t)ceil(0.05 * fps));
    }
    free(low);
    return true;
}

/* ---- pinning ---- */

typedef struct rt_pin_work {
    rf_xform *local, *world, *before;
    int32_t *parents;
    /* The IK problem: chains of two bones up each effector's body parents, three joints a goal,
     * posed from the frame's world transforms (so a foot placed from its shin under a placement
     * root solves as one hanging from it). */
    uint32_t *chain;    /* [eff * 3] target joints: hip, knee, effector */
    int32_t *cparent;   /* [eff * 3] */
    rf_xform *clocal;   /* [eff * 3] */
    rf_xform *want;     /* [n] solved world transforms */
    uint8_t *solved;    /* [n] */
    uint8_t *need;      /* [n] joints whose world the pass reads: the feet, what is below them
                         * (their soles), their chains and the ancestors of all these */
    uint32_t *below;    /* each effector's joints below it, itself first, effector after effector */
    uint32_t *below_at; /* [eff + 1] where each effector's run starts in below */
    rf_ik_goal *goals;
    rf_vec3 *target_pos; /* [eff][frames] target effector positions before pinning */
    double *target_sole; /* [eff][frames] heights of the target feet's soles */
    double *clear_sole;  /* [eff][frames] the same, held out of the floor */
    rf_quat *target_rot; /* [eff][frames] the target feet's world rotations before pinning */
    rf_quat *held;       /* [eff][frames] a planted foot's world rotation, w = NAN: its own */
    uint32_t *goal_eff;  /* [eff] the effector of each goal of a frame */
    double *src_sole;    /* [eff][frames] the source's soles over its floor, in its legs */
    rf_vec3 *pin;        /* [eff][frames] the goal, or NaN when free */
} rt_pin_work;

static void rt_pin_work_free(rt_pin_work *w)
{
    free(w->local), free(w->world), free(w->before), free(w->parents), free(w->goals);
    free(w->chain), free(w->cparent), free(w->clocal), free(w->want), free(w->solved);
    free(w->need), free(w->below), free(w->below_at);
    free(w->target_pos), free(w->target_sole), free(w->clear_sole), free(w->target_rot),
        free(w->held), free(w->goal_eff), free(w->src_sole), free(w->pin);
}

/* Marks j and its hierarchy ancestors in need. */
static void rt_need_up(const rf_retarget *rt, uint8_t *need, int32_t j)
{
    for (; j >= 0 && !need[j]; j = rt->target->joints[j].parent)
        need[j] = 1;
}

/* The joints the pass reads, and each effector's joints below it. */
static void rt_pin_need(const rf_retarget *rt, rt_pin_work *w)
{
    uint32_t at = 0;
    for (uint32_t e = 0; e < rt->effector_count; e++) {
        int32_t eff = (int32_t)rt->effectors[e],
                knee = rt->effector_tip[e] ? eff : rt->lparent[eff];
        rt_need_up(rt, w->need, eff);
        rt_need_up(rt, w->need, knee);
        rt_need_up(rt, w->need, knee >= 0 ? rt->lparent[knee] : RF_RT_NONE);
        int32_t hip = knee >= 0 ? rt->lparent[knee] : RF_RT_NONE;
        rt_need_up(rt, w->need, hip >= 0 ? rt->lparent[hip] : RF_RT_NONE); /* rt_phase_whole_leg */
        w->below_at[e] = at;
        for (uint32_t c = (uint32_t)eff; c < rt->n; c++)
            if (rf_rt_carries(rt->target, eff, c))
                w->below[at++] = c, w->need[c] = 1;
    }
    w->below_at[rt->effector_count] = at;
}

/* The lowest height of effector e's joints and tips (its sole) in world; with the skinned mesh,
 * also of the vertices they carry that reach farthest, as a skeleton's sole would stand (a
 * mesh's toes can reach under the floor where the joints do not). */
static double rt_pin_sole(const rf_retarget *rt, const rt_pin_work *w, uint32_t e,
                          const rf_xform *world)
{
    double low = INFINITY, mesh = INFINITY;
    for (uint32_t i = w->below_at[e]; i < w->below_at[e + 1]; i++) {
        uint32_t c = w->below[i];
        low = fmin(low, rf_rt_height(rt->up, world[c].t));
        if (rf_v3_len2(rt->t_tip[c]) > 0)
            low = fmin(low, rf_rt_height(rt->up, rf_xform_point(world[c], rt->t_tip[c])));
        for (uint32_t k = 0; rt->t_hull && k < RF_RT_HULL; k++)
            mesh = fmin(mesh, rf_rt_height(rt->up, rf_xform_point(world[c],
                                                                  rt->t_hull[c * RF_RT_HULL + k])));
    }
    return fmin(low, mesh + rt->floor_target - rt->mesh_floor);
}

static bool rt_pin_work_alloc(rt_pin_work *w, const rf_retarget *rt, uint32_t frames)
{
    size_t n = rt->n, ef = (size_t)rt->effector_count * frames;
    w->local = malloc(n * sizeof *w->local);
    w->world = malloc(n * sizeof *w->world);
    w->before = malloc(n * sizeof *w->before);
    w->parents = malloc(n * sizeof *w->parents);
    w->goals = calloc(rt->effector_count ? rt->effector_count : 1, sizeof *w->goals);
    w->target_pos = malloc((ef ? ef : 1) * sizeof *w->target_pos);
    w->target_sole = malloc((ef ? ef : 1) * sizeof *w->target_sole);
    w->clear_sole = malloc((ef ? ef : 1) * sizeof *w->clear_sole);
    w->target_rot = malloc((ef ? ef : 1) * sizeof *w->target_rot);
    w->held = malloc((ef ? ef : 1) * sizeof *w->held);
    w->goal_eff = malloc((rt->effector_count ? rt->effector_count : 1) * sizeof *w->goal_eff);
    w->src_sole = malloc((ef ? ef : 1) * sizeof *w->src_sole);
    w->pin = malloc((ef ? ef : 1) * sizeof *w->pin);
    size_t c = (rt->effector_count ? rt->effector_count : 1) * 3;
    w->chain = malloc(c * sizeof *w->chain);
    w->cparent = malloc(c * sizeof *w->cparent);
    w->clocal = malloc(c * sizeof *w->clocal);
    w->want = malloc(n * sizeof *w->want);
    w->solved = malloc(n ? n : 1);
    w->need = calloc(n ? n : 1, 1);
    w->below = malloc((c / 3 * n + 1) * sizeof *w->below);
    w->below_at = malloc((c / 3 + 1) * sizeof *w->below_at);
    if (!w->local || !w->world || !w->before || !w->parents || !w->goals || !w->target_pos ||
        !w->target_sole || !w->clear_sole || !w->target_rot || !w->held || !w->goal_eff ||
        !w->src_sole || !w->pin || !w->chain || !w->cparent || !w->clocal || !w->want ||
        !w->solved || !w->need || !w->below || !w->below_at)
        return false;
    /* the per-frame arrays: every frame of every foot is written */
    rf_prefault(w->target_pos, ef * sizeof *w->target_pos);
    rf_prefault(w->target_sole, ef * sizeof *w->target_sole);
    rf_prefault(w->src_sole, ef * sizeof *w->src_sole);
    rf_prefault(w->pin, ef * sizeof *w->pin);
    rt_pin_need(rt, w);
    for (uint32_t j = 0; j < n; j++)
        w->parents[j] = rt->target->joints[j].parent;
    return true;
}

/* How far (in leg lengths, horizontally) a foot driven half a cycle later may be held from where
 * the motion puts it. CMU 01_01's walk onto the Fox, the animalia wolf and horse (forelegs' tilt
 * p90 in degrees, skate over all feet in leg/s): set down again past 0.5 26-62, 0.85-0.99;
 * dragged along (rt_phase_drag) past 0.5 33-71, 0.68-0.82; past 0.25 26-55, 0.80-0.90; past
 * 0.15 25-51, 0.87-0.92. */
#define RT_PHASE_DRIFT 0.25

/* Whether the body stands on two pairs of legs, one driven half a cycle later (a quadruped under
 * a biped's walk): every foot of it is then kept out of the floor between its contacts too
 * (rt_pins). Its height is set by the legs in phase; the forefeet, kept out of the floor, no
 * longer raised the whole clip at the end (the Fox under the whole of CMU 01_01: 2.4 units ->
 * 0.05), and its hind feet, which that raise had held over the floor, went through it between their
 * contacts (least -10.3% of the height, the sweep's floor p95 7.4 -> 10.3; now 8.3). A biped's
 * feet are left as they were: held out of the floor, greenman's under the Fox's Walk stood
 * 4.6% of the height over it in the median frame. */
static bool rt_trots(const rf_retarget *rt)
{
    for (uint32_t e = 0; e < rt->effector_count; e++)
        if (rt_effector_phase(rt, e))
            return true;
    return false;
}

/* The frames rt_pins reads a foot's position and sole at, of any foot: during its contacts and
 * the contact_blend after each; every frame for a body with feet driven half a cycle later
 * (rt_trots). */
static uint8_t *rt_pins_read(const rf_retarget *rt, const uint8_t *contact, uint32_t frames,
                             double fps)
{
    uint32_t blend = (uint32_t)ceil(rt->opt.contact_blend * fps);
    uint8_t *read = calloc(frames ? frames : 1, 1);
    bool trot = rt_trots(rt);
    for (uint32_t e = 0; read && e < rt->effector_count; e++) {
        const uint8_t *c = contact + (size_t)e * frames;
        uint32_t since = UINT32_MAX; /* as in rt_pins */
        if (trot)
            memset(read, 1, frames);
        for (uint32_t f = 0; f < frames; f++) {
            if (c[f])
                since = 0;
            else if (since != UINT32_MAX)
                since++;
            read[f] |= since <= blend;
        }
    }
    return read;
}

/* A pin of a foot driven half a cycle later held at most RT_PHASE_DRIFT legs (horizontally) from
 * where the motion puts the foot `at`: dragged along behind it beyond that, not left behind. */
static rf_vec3 rt_phase_drag(const rf_retarget *rt, rf_vec3 anchor, rf_vec3 at)
{
    rf_vec3 off = rf_rt_horizontal(rt->up, rf_v3_sub(anchor, at));
    double len = rf_v3_len(off), most = RT_PHASE_DRIFT * rt->leg_target;
    if (!(len > most))
        return anchor;
    return rf_v3_sub(anchor, rf_v3_scale(off, 1.0 - most / len));
}

/* A step of a foot driven half a cycle later (rt_phase_step): from where it stood to where it
 * lands, over RT_PHASE_STEP seconds. */
typedef struct rt_step {
    uint32_t first, frames; /* frames == 0: not stepping */
    rf_vec3 from, to;
} rt_step;

/* Seconds a step takes, and how high its arc rises over the motion, in leg lengths. The arc
 * clears twice the contact height, so the measure reads the foot as lifted for most of the step
 * (rf_rt_phase_contacts), not as sliding. */
#define RT_PHASE_STEP 0.2
#define RT_PHASE_LIFT 0.25

/* Starts a step for a foot driven half a cycle later whose pin `anchor` lies more than
 * RT_PHASE_DRIFT legs (horizontally) behind where the motion puts it at frame f: it lands where
 * the motion puts it at the step's end, as far ahead along the way it moves as it was let fall
 * behind, so the next step comes a whole drift later. Returns false when it needs none. */
static bool rt_phase_step(const rf_retarget *rt, const rf_vec3 *p, uint32_t f, uint32_t frames,
                          double fps, rf_vec3 anchor, rt_step *st)
{
    rf_vec3 off = rf_rt_horizontal(rt->up, rf_v3_sub(p[f], anchor));
    double len = rf_v3_len(off), most = RT_PHASE_DRIFT * rt->leg_target;
    if (!(len > most))
        return false;
    uint32_t n = (uint32_t)fmax(2, ceil(RT_PHASE_STEP * fps));
    uint32_t end = f + n < frames ? f + n : frames - 1;
    st->first = f, st->frames = n, st->from = anchor;
    rf_vec3 ahead = rf_rt_horizontal(rt->up, rf_v3_sub(p[end], anchor));
    double a = rf_v3_len(ahead);
    st->to = rf_v3_add(p[end], a > 0 ? rf_v3_scale(ahead, most / a) : rf_v3(0, 0, 0));
    return true;
}

/* Where a stepping foot is at frame f: eased along the floor from `from` to `to`, raised on an
 * arc over the motion's height (p, with the lift out of the floor already in `lift`). */
static rf_vec3 rt_step_at(const rf_retarget *rt, const rt_step *st, uint32_t f, rf_vec3 p,
                          rf_vec3 lift)
{
    double u = (double)(f - st->first + 1) / st->frames;
    double ease = u * u * (3 - 2 * u);
    rf_vec3 along = rf_v3_add(st->from, rf_v3_scale(rf_v3_sub(st->to, st->from), ease));
    rf_vec3 at = rf_v3_add(p, rf_rt_horizontal(rt->up, rf_v3_sub(along, p)));
    double arc = sin(RF_PI * u) * RT_PHASE_LIFT * rt->leg_target;
    return rf_v3_add(rf_v3_add(at, lift), rf_v3_scale(rt->up, arc / rf_v3_len2(rt->up)));
}

/* The goal of every effector at every frame: during a contact, the horizontal position where it
 * began, and no lower than the height that puts its sole over the target's floor as the
 * source's is over its own (the foot can still roll); for contact_blend seconds after it, easing
 * back to the free motion. Every foot of a body with feet driven half a cycle later is also
 * lifted out of the floor where it would go through it between contacts (rt_trots), and such a
 * foot steps when the body has moved on from its pin (rt_phase_step) or, on a one-bone leg, has
 * its pin dragged along (rt_phase_drag). */
static uint32_t rt_pins(const rf_retarget *rt, const uint8_t *contact, uint32_t frames, double fps,
                        rt_pin_work *w)
{
    uint32_t taken = 0; /* steps */
    uint32_t blend = (uint32_t)ceil(rt->opt.contact_blend * fps);
    bool trot = rt_trots(rt);
    for (uint32_t e = 0; e < rt->effector_count; e++) {
        size_t at = (size_t)e * frames;
        const uint8_t *c = contact + at;
        const rf_vec3 *p = w->target_pos + at;
        rf_vec3 *pin = w->pin + at, anchor = p[0], lift = rf_v3(0, 0, 0);
        uint32_t since = UINT32_MAX; /* frames since the last contact ended */
        bool phase = rt_effector_phase(rt, e), steps = rf_rt_effector_steps(rt, e);
        rt_step st = {0};
        rf_quat *held = w->held + at, turn = rf_quat_identity();
        for (uint32_t f = 0; f < frames; f++) {
            bool stepping = false;
            held[f] = rf_quat_make(0, 0, 0, NAN);
            if (c[f]) {
                /* A foot driven half a cycle later is planted while the body moves on with the
                 * source: dragged along behind the body past RT_PHASE_DRIFT, it slid as fast as
                 * the body moved (the Fox's forefeet 1.0-1.2 leg/s under CMU 01_01); one that
                 * can step steps instead, lifted, and lands ahead. */
                if (f == 0 || !c[f - 1])
                    anchor = p[f], st.frames = 0, turn = w->target_rot[at + f];
                else if (phase && !steps)
                    anchor = rt_phase_drag(rt, anchor, p[f]);
                else if (steps && !st.frames && rt_phase_step(rt, p, f, frames, fps, anchor, &st))
                    anchor = st.to, taken++;
                stepping = steps && st.frames && f < st.first + st.frames;
                if (steps && st.frames && !stepping)
                    st.frames = 0, turn = w->target_rot[at + f];
                /* A planted foot that steps keeps its turn from where it was set down: its
                 * source's foot rolls heel to toe in a stance that is not this foot's. */
                if (steps && !stepping)
                    held[f] = turn;
                /* Only up: a foot through the floor is lifted out of it (one driven half a cycle
                 * later onto the floor, its contacts its own); pulling a floating
                 * foot down would stretch the leg out of reach (the root placement keeps the
                 * feet at the floor on average). */
                double want = rt->floor_target + (steps ? 0 : w->src_sole[at + f]) * rt->leg_target;
                lift = rf_v3_scale(rt->up, fmax(0, want - w->target_sole[at + f]));
                since = 0;
            } else if (since != UINT32_MAX) {
                since++;
            }
            rf_vec3 off = rf_v3_add(rf_rt_horizontal(rt->up, rf_v3_sub(anchor, p[f])), lift);
            double keep = c[f] ? 1 : since <= blend ? 1.0 - (double)since / (blend + 1) : 0;
            pin[f] = keep > 0 ? rf_v3_add(p[f], rf_v3_scale(off, keep)) : rf_v3(NAN, NAN, NAN);
            if (stepping)
                pin[f] = rt_step_at(rt, &st, f, p[f], lift);
            double under = rt->floor_target - w->target_sole[at + f];
            if ((phase || trot) && keep == 0 && under > 0)
                pin[f] = rf_v3_add(p[f], rf_v3_scale(rt->up, under));
        }
    }
    return taken;
}

static void rt_pose_of(const rf_retarget *rt, const rf_animation *a, uint32_t f, rf_xform *local,
                       const uint8_t *need)
{
    for (uint32_t j = 0; j < rt->n; j++) {
        if (!need[j])
            continue;
        local[j].t = rf_animation_translation(a, f, j);
        local[j].r = rf_quat_normalize(rf_animation_rotation(a, f, j));
        local[j].s = rt->target->joints[j].rest.s;
    }
}

/* Flattened: run on every frame by both passes, with rf_xform_mul called it spent as much
 * moving 80-byte transforms in and out as multiplying them. */
__attribute__((flatten)) static void rt_fk(const rf_retarget *rt, const rf_xform *local,
                                           rf_xform *world, const uint8_t *need)
{
    for (uint32_t j = 0; j < rt->n; j++) {
        if (!need[j])
            continue;
        int32_t p = rt->target->joints[j].parent;
        world[j] = p < 0 ? local[j] : rf_xform_mul(world[p], local[j]);
    }
}

/* The transform of `child` in `parent`'s frame. */
static rf_xform rt_relative(rf_xform parent, rf_xform child)
{
    return rf_xform_mul(rf_xform_invert(parent), child);
}

/* Whether effector e, a foot at its bone's tip driven half a cycle later, is solved with the
 * two limb bones above its joint instead of its own bone and the one above: a step lifts it
 * (rt_phase_step). The Fox's forefoot at its hand's tip, turned about the elbow and the wrist,
 * could not rise (the forearm stayed on the floor and the paw slid along it while stepping); a
 * horse's two-bone leg hanging from the body keeps its chain. */
static bool rt_phase_whole_leg(const rf_retarget *rt, uint32_t e)
{
    if (rt->effector_tip[e] != RT_TIP_CHAIN || !rt_effector_phase(rt, e))
        return false;
    int32_t knee = rt->lparent[rt->effectors[e]], hip = knee >= 0 ? rt->lparent[knee] : -1;
    return hip >= 0 && !rt->tj[hip].root_motion && !rt->t_centerline[hip];
}

/* Poses the problem's chains from the frame's world transforms: one goal per pinned effector. */
static uint32_t rt_chains_pose(const rf_retarget *rt, uint32_t f, uint32_t frames, rt_pin_work *w)
{
    uint32_t count = 0;
    for (uint32_t e = 0; e < rt->effector_count; e++) {
        rf_vec3 pin = w->pin[(size_t)e * frames + f];
        if (isnan(pin.x))
            continue;
        bool tip = rt->effector_tip[e];
        if (rt->effector_tip[e] == RT_TIP_AIM)
            continue; /* a one-bone leg: rt_aim_frame */
        uint32_t eff = rt->effectors[e];
        if (rt_phase_whole_leg(rt, e)) {
            /* the joint carrying the tip goes where puts the tip on the pin, turned as it is
             * held (rt_chains_write) */
            rf_quat held = w->held[(size_t)e * frames + f];
            rf_xform turn = w->before[eff];
            turn.t = rf_v3(0, 0, 0), turn.r = isnan(held.w) ? turn.r : held;
            pin = rf_v3_sub(pin, rf_xform_point(turn, rt->t_tip[eff]));
            tip = false;
        }
        uint32_t knee = tip ? eff : (uint32_t)rt->lparent[eff];
        uint32_t hip = (uint32_t)rt->lparent[knee], b = count * 3;
        w->chain[b] = hip, w->chain[b + 1] = knee, w->chain[b + 2] = eff;
        w->cparent[b] = -1, w->cparent[b + 1] = (int32_t)b, w->cparent[b + 2] = (int32_t)b + 1;
        w->clocal[b] = w->before[hip];
        w->clocal[b + 1] = rt_relative(w->before[hip], w->before[knee]);
        /* A foot at the bone's tip ends the chain at a point of the joint's own frame. */
        w->clocal[b + 2] = tip ? (rf_xform){rt->t_tip[eff], rf_quat_identity(), rf_v3(1, 1, 1)}
                               : rt_relative(w->before[knee], w->before[eff]);
        w->goal_eff[count] = e;
        w->goals[count] = rf_ik_goal_make(b + 2, pin);
        w->goals[count++].chain_root = (int32_t)b;
    }
    return count;
}

/* Writes the solved chains back into the hierarchy's local pose of frame f (each effector keeps
 * its world rotation), then places the anchored joints again from their moved body joints. */
static void rt_chains_write(const rf_retarget *rt, rf_animation *a, uint32_t f, uint32_t frames,
                            uint32_t count, rt_pin_work *w)
{
    memset(w->solved, 0, rt->n);
    for (uint32_t g = 0; g < count; g++) {
        uint32_t b = g * 3;
        rf_xform hip = w->clocal[b], knee = rf_xform_mul(hip, w->clocal[b + 1]);
        w->want[w->chain[b]] = hip, w->want[w->chain[b + 1]] = knee;
        w->solved[w->chain[b]] = w->solved[w->chain[b + 1]] = 1;
        if (w->chain[b + 2] == w->chain[b + 1])
            continue; /* a foot at the bone's tip: the knee's own turn places it */
        rf_xform eff = rf_xform_mul(knee, w->clocal[b + 2]);
        rf_quat held = w->held[(size_t)w->goal_eff[g] * frames + f];
        eff.r = isnan(held.w) ? w->before[w->chain[b + 2]].r : held;
        w->want[w->chain[b + 2]] = eff, w->solved[w->chain[b + 2]] = 1;
    }
    for (uint32_t j = 0; j < rt->n; j++) {
        if (!w->need[j])
            continue; /* neither solved nor under a solved joint's parent chain */
        int32_t p = rt->target->joints[j].parent;
        rf_xform pw = p >= 0 ? w->world[p] : rf_xform_identity();
        if (w->solved[j]) {
            rf_xform l = rt_relative(pw, w->want[j]);
            w->local[j].t = l.t, w->local[j].r = rf_quat_normalize(l.r);
            rf_animation_set_rotation(a, f, j, w->local[j].r);
            rf_animation_set_translation(a, f, j, w->local[j].t);
        }
        w->world[j] = p >= 0 ? rf_xform_mul(pw, w->local[j]) : w->local[j];
    }
    if (rt->anchored)
        rf_rt_place_anchored(rt, a->rotations + (size_t)f * rt->n * 4,
                             a->translations + (size_t)f * rt->n * 3, NULL, w->world);
}

/* Turns each pinned one-bone leg of frame f (world transforms in w->world) about its pivot so its
 * tip points at its pin: the nearest its tip can come with the bone's length kept. */
static void rt_aim_frame(const rf_retarget *rt, rf_animation *a, uint32_t f, uint32_t frames,
                         rt_pin_work *w)
{
    bool aimed = false;
    for (uint32_t e = 0; e < rt->effector_count; e++) {
        rf_vec3 pin = w->pin[(size_t)e * frames + f];
        if (rt->effector_tip[e] != RT_TIP_AIM || isnan(pin.x))
            continue;
        uint32_t j = rt->effectors[e];
        rf_vec3 pivot = w->world[j].t;
        rf_vec3 now = rf_v3_sub(rf_xform_point(w->world[j], rt->t_tip[j]), pivot);
        rf_vec3 want = rf_v3_sub(pin, pivot);
        if (!(rf_v3_len2(now) > 0) || !(rf_v3_len2(want) > 0))
            continue;
        rf_quat r = rf_quat_mul(rf_quat_from_two_vectors(now, want), w->world[j].r);
        int32_t p = rt->target->joints[j].parent;
        rf_quat pr = p >= 0 ? w->world[p].r : rf_quat_identity();
        w->local[j].r = rf_quat_normalize(rf_quat_mul(rf_quat_conj(pr), r));
        w->world[j].r = r;
        rf_animation_set_rotation(a, f, j, w->local[j].r);
        aimed = true;
    }
    if (aimed && rt->anchored)
        rf_rt_place_anchored(rt, a->rotations + (size_t)f * rt->n * 4,
                             a->translations + (size_t)f * rt->n * 3, NULL, w->world);
}

/* Solves frame f's goals through the connected solver, then aims the one-bone legs. */
static bool rt_solve_frame(const rf_retarget *rt, rf_animation *a, uint32_t f, uint32_t frames,
                           const rf_ik_solver *solver, rt_pin_work *w, rf_rt_contact_stats *st,
                           char *err, size_t err_size)
{
    bool pinned = false; /* most frames of most clips pin nothing: skip their pose */
    for (uint32_t e = 0; e < rt->effector_count && !pinned; e++)
        pinned = !isnan(w->pin[(size_t)e * frames + f].x);
    if (!pinned)
        return true;
    rt_pose_of(rt, a, f, w->local, w->need);
    rt_fk(rt, w->local, w->before, w->need);
    memcpy(w->world, w->before, rt->n * sizeof *w->world);
    uint32_t count = rt_chains_pose(rt, f, frames, w);
    if (count) {
        rf_ik_problem pb = {sizeof pb, count * 3, w->cparent,
                            w->clocal, NULL,      NULL,
                            count,     w->goals,  1e-4 * rt->leg_target,
                            32};
        rf_ik_result res;
        memset(&res, 0, sizeof res);
        res.size = sizeof res;
        res.pose = w->clocal;
        st->solves++;
        if (!solver->api->solve(solver->state, &pb, &res)) {
            st->failures++;
            rf_rt_fail(err, err_size, "the IK solver refused frame %u: %s", f, res.message);
            return false;
        }
        st->max_error = fmax(st->max_error, res.max_error);
        rt_chains_write(rt, a, f, frames, count, w);
    }
    rt_aim_frame(rt, a, f, frames, w);
    return true;
}

bool rf_retarget_contacts(rf_retarget *rt, rf_animation *anim, const rf_ik_solver *solver,
                          rf_rt_contact_stats *stats, char *err, size_t err_size)
{
    memset(stats, 0, sizeof *stats);
    stats->effectors = rt->effector_count;
    uint32_t frames = anim->frame_count;
    if (!rt->effector_count || frames < 2)
        return true;
    rt_pin_work w = {0};
    uint8_t *contact = NULL;
    bool ok = rt_pin_work_alloc(&w, rt, frames) &&
              (contact = rf_rt_detect_contacts(rt, frames, anim->fps, rf_retarget_start_time(rt),
                                               NULL, w.src_sole));
    if (!ok) {
        rt_pin_work_free(&w);
        rf_rt_fail(err, err_size, "out of memory");
        return false;
    }
    uint8_t *read = rt_pins_read(rt, contact, frames, anim->fps);
    for (uint32_t f = 0; read && f < frames; f++) {
        if (!read[f]) { /* nothing pinned: the values are never read */
            for (uint32_t e = 0; e < rt->effector_count; e++) {
                w.target_pos[(size_t)e * frames + f] = rf_v3(0, 0, 0);
                w.target_rot[(size_t)e * frames + f] = rf_quat_identity();
                w.target_sole[(size_t)e * frames + f] = 0;
            }
            continue;
        }
        rt_pose_of(rt, anim, f, w.local, w.need);
        rt_fk(rt, w.local, w.world, w.need);
        for (uint32_t e = 0; e < rt->effector_count; e++) {
            w.target_pos[(size_t)e * frames + f] = rf_rt_effector_point(rt, w.world, e);
            w.target_rot[(size_t)e * frames + f] = w.world[rt->effectors[e]].r;
            w.target_sole[(size_t)e * frames + f] = rt_pin_sole(rt, &w, e, w.world);
        }
    }
    if (!read) {
        free(contact);
        rt_pin_work_free(&w);
        rf_rt_fail(err, err_size, "out of memory");
        return false;
    }
    free(read);
    /* the feet driven half a cycle later by their own motion, as the clip will show it: held out
     * of the floor where they would go through it (rt_pins) */
    for (size_t i = 0; i < (size_t)rt->effector_count * frames; i++)
        w.clear_sole[i] = fmax(w.target_sole[i], rt->floor_target);
    if (!rf_rt_phase_contacts(rt, frames, anim->fps, w.clear_sole, contact)) {
        free(contact);
        rt_pin_work_free(&w);
        rf_rt_fail(err, err_size, "out of memory");
        return false;
    }
    for (size_t i = 0; i < (size_t)rt->effector_count * frames; i++)
        stats->contact_frames += contact[i];
    stats->steps = rt_pins(rt, contact, frames, anim->fps, &w);
    for (uint32_t f = 0; ok && f < frames; f++)
        ok = rt_solve_frame(rt, anim, f, frames, solver, &w, stats, err, err_size);
    free(contact);
    rt_pin_work_free(&w);
    return ok;
}

/* ---- parts that are not feet stay above the floor ---- */

/* The largest turn that lifts a part (radians). */
#define RT_LIFT_MAX (90.0 * RF_PI / 180.0)

/* Marks the joints that may touch the floor: each foot, what is below it and its chain. */
static void rt_feet_mask(const rf_retarget *rt, uint8_t *foot)
{
    memset(foot, 0, rt->n);
    for (uint32_t e = 0; e < rt->effector_count; e++) {
        int32_t eff = (int32_t)rt->effectors[e], knee = rt->lparent[eff];
        for (uint32_t c = 0; c < rt->n; c++)
            foot[c] = foot[c] || rf_rt_carries(rt->target, eff, c);
        if (knee >= 0)
            foot[knee] = 1;
    }
}

/* Parts that are not feet: driven joints high in the aligned rest (a quarter of the leg over its
 * lowest point), neither a foot nor in a foot's chain. */
static void rt_parts_mask(const rf_retarget *rt, const uint8_t *foot, uint8_t *part)
{
    for (uint32_t j = 0; j < rt->n; j++)
        part[j] = !foot[j] && rt->tj[j].kind != RF_RT_REST && !rt->tj[j].root_motion &&
                  rf_rt_height(rt->up, rt->t_aligned[j]) - rt->aligned_low > 0.25 * rt->leg_target;
}

/* Lifts point p of frame f (world `world`, local `local`) to the floor by turning joint a (an
 * ancestor of the part) about its pivot, keeping the part's horizontal direction; false when the
 * floor is out of the turn's reach. */
static bool rt_lift_turn(const rf_retarget *rt, rf_xform *local, const rf_xform *world, uint32_t a,
                         rf_vec3 p, double floor_h)
{
    rf_vec3 v = rf_v3_sub(p, world[a].t);
    double len = rf_v3_len(v), want = floor_h - rf_rt_height(rt->up, world[a].t);
    rf_vec3 h = rf_rt_horizontal(rt->up, v);
    if (!(len > 0) || fabs(want) >= len || rf_v3_len2(h) == 0)
        return false;
    rf_vec3 to = rf_v3_add(rf_v3_scale(rf_v3_normalize(h), sqrt(len * len - want * want)),
                           rf_v3_scale(rt->up, want));
    if (rf_v3_angle(v, to) > RT_LIFT_MAX)
        return false; /* a turn this large would fold the part: leave it, the measure says so */
    rf_quat turn = rf_quat_from_two_vectors(v, to);
    int32_t pa = rt->target->joints[a].parent;
    rf_quat pr = pa >= 0 ? world[pa].r : rf_quat_identity();
    local[a].r = rf_quat_normalize(rf_quat_mul(rf_quat_conj(pr), rf_quat_mul(turn, world[a].r)));
    return true;
}

/* The point of part j deepest under its floor this frame: its pivot and its bone's tip against
 * the skeleton's floor, and with the skinned mesh, the vertices it carries that reach farthest (a
 * wing's membrane reaches far past its bones) against the mesh's floor, into *floor_h. Both
 * floors are raised by `clear`, how far the source stands over its own this frame (a jump). */
static rf_vec3 rt_part_low(const rf_retarget *rt, const rf_xform *world, uint32_t j, double clear,
                           double *floor_h)
{
    rf_vec3 p = world[j].t;
    *floor_h = rt->floor_target + clear;
    double depth = *floor_h - rf_rt_height(rt->up, p);
    uint32_t count = rt->t_hull ? RF_RT_HULL : 0;
    for (uint32_t k = 0; k <= count; k++) {
        rf_vec3 c = k < count ? rt->t_hull[(size_t)j * RF_RT_HULL + k] : rt->t_tip[j];
        rf_vec3 q = rf_xform_point(world[j], c);
        double floor = (k < count ? rt->mesh_floor : rt->floor_target) + clear;
        if (floor - rf_rt_height(rt->up, q) > depth)
            p = q, *floor_h = floor, depth = floor - rf_rt_height(rt->up, q);
    }
    return p;
}

/* rt_part_low of part j, or, for the root of a limb that moves whole (rt->t_whole), the deepest
 * of its joints' points: the limb is one part, lifted at its root. */
static rf_vec3 rt_limb_low(const rf_retarget *rt, const rf_xform *world, uint32_t j, double clear,
                           double *floor_h)
{
    rf_vec3 p = rt_part_low(rt, world, j, clear, floor_h);
    if (rt->t_whole[j] != (int32_t)j)
        return p;
    double depth = *floor_h - rf_rt_height(rt->up, p);
    /* the limb's joints hang from j in the file's tree, whose parents come before their children
     * (rf_skeleton) */
    for (uint32_t c = j + 1; c < rt->n; c++) {
        double h;
        rf_vec3 q = rt->t_whole[c] == (int32_t)j ? rt_part_low(rt, world, c, clear, &h) : p;
        if (rt->t_whole[c] == (int32_t)j && h - rf_rt_height(rt->up, q) > depth)
            p = q, *floor_h = h, depth = h - rf_rt_height(rt->up, q);
    }
    return p;
}

/* Turns an ancestor of part j so its point p sits on the floor: the nearest driven ancestor over
 * the floor first, then the next ones up its limb when the floor is out of a turn's reach (a
 * wing hanging from an arm is lifted at the shoulder, not folded at the wrist). Never a joint
 * carrying a foot, nor, for a part off the centerline, a centerline joint (the chest would tilt
 * for one wing). The root of a limb that moves whole turns itself: its joints past it keep their
 * rest turns, and it hangs from the centerline. The joint turned, or -1. */
static int32_t rt_lift_joint(const rf_retarget *rt, rf_xform *local, const rf_xform *world,
                             const uint8_t *holds, uint32_t j, rf_vec3 p, double floor_h)
{
    int32_t from = rt->t_whole[j] == (int32_t)j ? (int32_t)j : rt->lparent[j];
    for (int32_t a = from; a >= 0; a = rt->lparent[a]) {
        if (holds[a] || rt->tj[a].root_motion || (rt->t_centerline[a] && !rt->t_centerline[j]))
            return -1; /* turning a joint that carries a foot would lift the foot */
        if (rt->tj[a].kind == RF_RT_REST || rf_rt_height(rt->up, world[a].t) < floor_h ||
            !rf_rt_carries(rt->target, a, j))
            continue;
        if (rt_lift_turn(rt, local, world, (uint32_t)a, p, floor_h))
            return a;
    }
    return -1;
}

/* The sources' poses of one output frame, each joint made when first asked for: a part under
 * its floor asks about one source sole, which reads a few joints of the source's (its chain
 * and what is below it), so the rest of the source's body is not posed. */
typedef struct rt_src_poses {
    uint32_t frame;
    uint8_t *have;    /* [slot][source n]: the joints of world[slot] made at `frame` */
    uint8_t *need;    /* [source n] */
    rf_xform **world; /* [slot][source n] */
    rf_xform *local;
    float *rot, *tr;
} rt_src_poses;

static void rt_src_poses_free(const rf_retarget *rt, rt_src_poses *sp)
{
    for (uint32_t s = 0; sp->world && s < rt->slot_count; s++)
        free(sp->world[s]);
    free(sp->have), free(sp->need), free(sp->world), free(sp->local), free(sp->rot), free(sp->tr);
}

static bool rt_src_poses_init(const rf_retarget *rt, rt_src_poses *sp)
{
    size_t m = rt->max_src_n ? rt->max_src_n : 1, slots = rt->slot_count ? rt->slot_count : 1;
    sp->have = calloc(slots * m, 1), sp->need = malloc(m);
    sp->world = calloc(slots, sizeof *sp->world);
    sp->local = malloc(m * sizeof *sp->local);
    sp->rot = malloc(m * 4 * sizeof *sp->rot), sp->tr = malloc(m * 3 * sizeof *sp->tr);
    bool ok = sp->have && sp->need && sp->world && sp->local && sp->rot && sp->tr;
    for (uint32_t s = 0; ok && s < rt->slot_count; s++)
        ok = (sp->world[s] = malloc(m * sizeof **sp->world)) != NULL;
    if (!ok)
        rt_src_poses_free(rt, sp);
    return ok;
}

/* Whether target joint j's source joint is down on its own floor at output frame f (its sole
 * within contact_height leg lengths of it). */
static bool rt_source_down(const rf_retarget *rt, rt_src_poses *sp, const rf_animation *anim,
                           uint32_t f, uint32_t j)
{
    const rf_rt_input *in = rt->in + rt->tj[j].first_input;
    const rf_rt_src *src = &rt->src[in->source];
    size_t m = rt->max_src_n ? rt->max_src_n : 1;
    uint8_t *have = sp->have + in->slot * m;
    if (sp->frame != f)
        memset(sp->have, 0, rt->slot_count * m), sp->frame = f;
    memset(sp->need, 0, src->n);
    rt_sole_need(src, (int32_t)in->joint, sp->need);
    bool any = false;
    for (uint32_t c = 0; c < src->n; c++) {
        sp->need[c] = sp->need[c] && !have[c];
        have[c] = have[c] || sp->need[c];
        any = any || sp->need[c];
    }
    if (any) {
        double t = rf_rt_slot_time(rt, in->slot, rf_retarget_start_time(rt) + f / anim->fps);
        rf_rt_source_world_some(rt, in->source, t, sp->local, sp->world[in->slot], sp->rot, sp->tr,
                                sp->need);
    }
    return rf_rt_over_floor(rt, in->source, sp->world[in->slot], (int32_t)in->joint) <=
           rt->opt.contact_height;
}

/* What the parts pass reads at every frame. */
typedef struct rt_parts {
    const rf_retarget *rt;
    rf_animation *anim;
    const uint8_t *part;  /* the parts kept above the floor */
    const uint8_t *all;   /* every joint */
    const uint8_t *holds; /* carries a foot in the hierarchy or body tree */
    const uint8_t *reach; /* the parts and their ancestors */
    const double *extent; /* [n] the farthest of a part's hull points and tip from its pivot */
    uint32_t step;        /* the source's clearance is read every `step` frames */
    double eps;
    /* [n] how far under joint j the lowest point rt_part_clear weighs for a part at or below it
     * can be in any frame (bone lengths at their longest in the clip, at the joints' scales);
     * -INFINITY with no such part */
    const double *hang;
} rt_parts;

/* Whether every point rt_part_low weighs for part j surely stands over its floor: the pivot's
 * height less the part's extent (at the joint's largest scale) clears the higher floor by a
 * margin far above rounding. rt_part_low's answer then cannot lift it, and most parts in most
 * frames are skipped without transforming their hull. */
static bool rt_part_clear(const rt_parts *c, const rf_xform *world, uint32_t j, double clear)
{
    const rf_retarget *rt = c->rt;
    rf_vec3 s = world[j].s;
    double reach = c->extent[j] * fmax(fabs(s.x), fmax(fabs(s.y), fabs(s.z)));
    double floor = (rt->t_hull ? fmax(rt->floor_target, rt->mesh_floor) : rt->floor_target) + clear;
    double h = rf_rt_height(rt->up, world[j].t);
    return h - reach > floor + 1e-9 * (fabs(h) + reach + fabs(floor) + 1);
}

/* Poses the parts and their ancestors at frame f, from the root down, leaving out what hangs
 * from a joint standing so high over the floor (by c->hang, with a margin far above rounding)
 * that every part there surely passes rt_part_clear: gone[j] is then 1 for that joint and 2 for
 * those below it, not posed. */
__attribute__((flatten)) static void rt_parts_pose(const rt_parts *c, uint32_t f, double clear,
                                                   rf_xform *local, rf_xform *world, uint8_t *gone)
{
    const rf_retarget *rt = c->rt;
    double floor = (rt->t_hull ? fmax(rt->floor_target, rt->mesh_floor) : rt->floor_target) + clear;
    for (uint32_t j = 0; j < rt->n; j++) {
        int32_t p = rt->target->joints[j].parent;
        gone[j] = p >= 0 && gone[p] ? 2 : 0;
        if (!c->reach[j] || gone[j])
            continue;
        local[j].t = rf_animation_translation(c->anim, f, j);
        local[j].r = rf_quat_normalize(rf_animation_rotation(c->anim, f, j));
        local[j].s = rt->target->joints[j].rest.s;
        world[j] = p < 0 ? local[j] : rf_xform_mul(world[p], local[j]);
        double h = rf_rt_height(rt->up, world[j].t), hang = c->hang[j];
        /* the joints past the root of a limb that moves whole are read with it (rt_limb_low):
         * its hang holds them */
        bool limb = rt->t_whole[j] >= 0 && rt->t_whole[j] != (int32_t)j;
        gone[j] = !limb && (hang == -INFINITY ||
                            h - hang > floor + 1e-6 * (fabs(h) + fabs(hang) + fabs(floor) + 1));
    }
}

/* Turns at most this many times for one part in one frame: each turn puts the point then
 * deepest on the floor, and another of the part's points may then be the deepest. */
#define RT_LIFT_ROUNDS 6

/* Lifts part j, its point p under floor_h, by turning its ancestors (rt_lift_joint): one turn
 * puts the deepest point on the floor and may leave another under it (a wing lifted by the tip
 * of its membrane keeps the membrane's other edge through the floor), so the part is turned
 * again from its new deepest point. A further turn is kept only where it leaves the part less
 * deep than before it: turned about another axis, it may put the first point back under. The
 * turns kept (local and world posed after them, the clip's rotations written). */
static uint32_t rt_part_lift(const rt_parts *c, uint32_t f, rf_xform *local, rf_xform *world,
                             uint32_t j, rf_vec3 p, double floor_h, double clear)
{
    const rf_retarget *rt = c->rt;
    uint32_t turns = 0;
    double depth = floor_h - rf_rt_height(rt->up, p);
    while (turns < RT_LIFT_ROUNDS && depth > 0) {
        int32_t a = rt_lift_joint(rt, local, world, c->holds, j, p, floor_h + c->eps);
        if (a < 0)
            break;
        rt_fk(rt, local, world, c->all);
        p = rt_limb_low(rt, world, j, clear, &floor_h);
        double now = floor_h - rf_rt_height(rt->up, p);
        if (turns > 0 && !(now < depth)) { /* undone: the clip still holds the last turn kept */
            local[a].r = rf_quat_normalize(rf_animation_rotation(c->anim, f, (uint32_t)a));
            rt_fk(rt, local, world, c->all);
            break;
        }
        rf_animation_set_rotation(c->anim, f, (uint32_t)a, local[a].r);
        turns++, depth = now;
    }
    return turns;
}

/* One frame of the parts pass, with scratch (local, world, sp, gone) of the caller's and the
 * source's clearance at frames (first + i) * step in clear[i] (rt_parts_clearance). */
static void rt_parts_frame(const rt_parts *c, uint32_t f, const double *clear_at, uint32_t first,
                           rf_xform *local, rf_xform *world, uint8_t *gone, rt_src_poses *sp,
                           rf_rt_parts_stats *st)
{
    const rf_retarget *rt = c->rt;
    uint32_t n = rt->n;
    /* Most frames have no part under its floor: the parts and their ancestors tell. The floor
     * stands as far over the target's as the source over its own (in a jump, in the air). */
    bool low = false;
    uint32_t i = f / c->step;
    double t = (double)(f - i * c->step) / c->step;
    double clear = (1 - t) * clear_at[i - first] + t * clear_at[i + 1 - first];
    rt_parts_pose(c, f, clear, local, world, gone);
    for (uint32_t j = 0; j < n && !low; j++) {
        double floor_h;
        low = c->part[j] && rt->anchor[j] < 0 && !gone[j] && !rt_part_clear(c, world, j, clear) &&
              !(rf_rt_height(rt->up, rt_limb_low(rt, world, j, clear, &floor_h)) >= floor_h);
    }
    if (!low)
        return;
    rt_pose_of(rt, c->anim, f, local, c->all);
    rt_fk(rt, local, world, c->all);
    bool lifted = false;
    sp->frame = UINT32_MAX;
    for (uint32_t j = 0; j < n; j++) {
        if (!c->part[j] || rt_part_clear(c, world, j, clear))
            continue;
        double floor_h;
        rf_vec3 p = rt_limb_low(rt, world, j, clear, &floor_h);
        if (rf_rt_height(rt->up, p) >= floor_h || rt->anchor[j] >= 0)
            continue;
        /* its source touches its own floor: so may it (a hand on all fours); a limb held whole
         * is lifted onto the floor all the same, its membrane's far edge no hand: left, the
         * bat's wings driven by the Fox's forelegs went 70% of its height through the floor */
        if (rt->t_whole[j] != (int32_t)j && rt_source_down(rt, sp, c->anim, f, j))
            continue;
        uint32_t turns = rt_part_lift(c, f, local, world, j, p, floor_h, clear);
        lifted = lifted || turns, st->turns += turns;
    }
    st->frames += lifted;
    if (lifted && rt->anchored)
        rf_rt_place_anchored(rt, c->anim->rotations + (size_t)f * n * 4,
                             c->anim->translations + (size_t)f * n * 3, NULL, world);
}

/* The clearance's step: how far the source stands over its own floor (rf_rt_clearance) is read
 * every tenth of a second, and rt_parts_frame interpolates between. Read at every frame of a
 * long clip it cost a fifth of the whole run; a jump takes half a second or more, so a tenth of
 * a second between reads misses little of it. */
static uint32_t rt_parts_step(const rf_animation *anim)
{
    uint32_t frames = anim->frame_count;
    /* Clamped before the conversion: a clip may claim any rate (1e300 fps). */
    double per = floor(anim->fps / 10);
    return per >= 1 ? (uint32_t)fmin(per, frames ? frames : 1) : 1;
}

/* The source's clearance at the reads frames [first, end) interpolate between: reads
 * first / step .. (end - 1) / step + 1, each at its frame (the last frame past the end). Each
 * thread reads those of the chunks of frames it takes, so the reads are shared between the
 * threads as the frames are (a read between two chunks is made for each). */
static double *rt_parts_clearance(const rt_parts *c, uint32_t first, uint32_t end)
{
    uint32_t frames = c->anim->frame_count, step = c->step;
    uint32_t i0 = first / step, count = end > first ? (end - 1) / step + 2 - i0 : 1;
    uint32_t *at = malloc(count * sizeof *at);
    double *clear = malloc(count * sizeof *clear);
    for (uint32_t i = 0; at && i < count; i++) {
        uint64_t f = (uint64_t)(i0 + i) * step;
        at[i] = f < frames ? (uint32_t)f : (frames ? frames - 1 : 0);
    }
    bool ok = at && clear &&
              rf_rt_clearance(c->rt, rf_retarget_start_time(c->rt), c->anim->fps, count, at, clear);
    free(at);
    if (!ok)
        free(clear);
    return ok ? clear : NULL;
}

/* The parts pass's frames a chunk at a time (rf_rt_chunk), with scratch and counts of its own
 * (one thread's share: a frame reads and writes only itself). */
typedef struct rt_parts_share {
    const rt_parts *c;
    rf_rt_chunks *chunks;
    rf_rt_parts_stats st;
    bool ok;
} rt_parts_share;

static void *rt_parts_run(void *arg)
{
    rt_parts_share *sh = arg;
    size_t n = sh->c->rt->n ? sh->c->rt->n : 1;
    rf_xform *local = malloc(n * sizeof *local), *world = malloc(n * sizeof *world);
    uint8_t *gone = malloc(n);
    rt_src_poses sp = {0};
    bool poses = local && world && gone && rt_src_poses_init(sh->c->rt, &sp);
    uint32_t first, end;
    sh->ok = poses;
    while (sh->ok && rf_rt_chunk(sh->chunks, &first, &end)) {
        double *clear = rt_parts_clearance(sh->c, first, end);
        sh->ok = clear != NULL;
        for (uint32_t f = first; sh->ok && f < end; f++)
            rt_parts_frame(sh->c, f, clear, first / sh->c->step, local, world, gone, &sp, &sh->st);
        free(clear);
    }
    if (!sh->ok) /* out of memory: the other thread takes the rest, or fails too */
        rf_rt_chunks_stop(sh->chunks);
    if (poses)
        rt_src_poses_free(sh->c->rt, &sp);
    free(local), free(world), free(gone);
    return NULL;
}

/* Every frame of the parts pass: shared with a second thread for a long clip, as the
 * retarget's frames. */
static bool rt_parts_all(const rt_parts *c, rf_rt_parts_stats *st)
{
    uint32_t frames = c->anim->frame_count;
    rf_rt_chunks chunks;
    rf_rt_chunks_init(&chunks, frames);
    rt_parts_share a = {c, &chunks, {0, 0}, false}, b = a;
    pthread_t thread;
    bool two = (uint64_t)frames * c->rt->n >= RT_THREAD_MIN &&
               pthread_create(&thread, NULL, rt_parts_run, &b) == 0;
    rt_parts_run(&a);
    if (two)
        pthread_join(thread, NULL);
    st->frames = a.st.frames + b.st.frames; /* b's stay 0 when it did not run */
    st->turns = a.st.turns + b.st.turns;
    return a.ok && (!two || b.ok);
}

/* rt_parts.hang: from the leaves up, each joint's farthest weighed point of a part at or below
 * it. A bone's length is bounded by its longest translation in the clip at its parent's largest
 * scale (the world scales are the rest scales' products: the pass never animates scale). Read
 * before each frame's pose, it spares posing the arms of a body standing upright. */
static double *rt_parts_hang(const rf_retarget *rt, const rf_animation *anim, const uint8_t *part,
                             const uint8_t *reach, const double *extent)
{
    uint32_t n = rt->n;
    double *hang = malloc((n ? n : 1) * sizeof *hang), *bone = calloc(n ? n : 1, sizeof *bone);
    rf_vec3 *scale = malloc((n ? n : 1) * sizeof *scale);
    if (!hang || !bone || !scale) {
        free(hang), free(bone), free(scale);
        return NULL;
    }
    /* the longest squared, then one square root: the root is monotone and correctly rounded,
     * so this is the longest of the lengths exactly, without a root and an fmax call a frame */
    for (uint32_t f = 0; f < anim->frame_count; f++)
        for (uint32_t j = 0; j < n; j++) {
            double len2 = rf_v3_len2(rf_animation_translation(anim, f, j));
            if (reach[j] && len2 > bone[j])
                bone[j] = len2;
        }
    for (uint32_t j = 0; j < n; j++)
        bone[j] = sqrt(bone[j]);
    const rf_joint *joints = rt->target->joints;
    for (uint32_t j = 0; j < n; j++) {
        int32_t p = joints[j].parent;
        scale[j] = p < 0 ? joints[j].rest.s : rf_v3_mul(scale[p], joints[j].rest.s);
        rf_vec3 s = scale[j];
        double most = fmax(fabs(s.x), fmax(fabs(s.y), fabs(s.z)));
        hang[j] = part[j] && rt->anchor[j] < 0 ? extent[j] * most : -INFINITY;
    }
    for (uint32_t j = n; j-- > 0;) {
        int32_t p = joints[j].parent;
        if (p < 0 || hang[j] == -INFINITY)
            continue;
        rf_vec3 s = scale[p];
        double most = fmax(fabs(s.x), fmax(fabs(s.y), fabs(s.z)));
        hang[p] = fmax(hang[p], hang[j] + bone[j] * most);
    }
    for (uint32_t j = 0; j < n; j++)
        hang[j] *= rf_v3_len(rt->up); /* heights are read along up */
    free(bone), free(scale);
    return hang;
}

/* A limb that moves whole from its root (rt->t_whole) is one part, its root's: the joints past
 * the root are posed with it (reach) and its extent is the farthest of their pivots, tips and
 * hull points from the root's pivot, in the root's frame (a wing's membrane spans many times
 * the shoulder's height). Held part by part, the wing's joints past the root were no parts at
 * all (they keep their rest turns) and the root could turn no joint (only the centerline
 * carries it): the fire dragon's wings went a quarter of its height through the floor in the
 * CMU walk's crouches. */
static void rt_whole_limbs(const rf_retarget *rt, const uint8_t *part, uint8_t *reach,
                           double *extent)
{
    for (uint32_t c = 0; c < rt->n; c++) {
        int32_t r = rt->t_whole[c];
        if (r < 0 || r == (int32_t)c || !part[r])
            continue;
        reach[c] = 1;
        rf_xform root = rt->t_rest_world[r], at = rt->t_rest_world[c];
        double s = fmax(fabs(root.s.x), fmax(fabs(root.s.y), fabs(root.s.z)));
        uint32_t count = rt->t_hull ? RF_RT_HULL : 0;
        for (uint32_t k = 0; s > 0 && k <= count + 1; k++) {
            rf_vec3 q = k < count    ? rt->t_hull[(size_t)c * RF_RT_HULL + k]
                        : k == count ? rt->t_tip[c]
                                     : rf_v3(0, 0, 0);
            extent[r] = fmax(extent[r], rf_v3_dist(rf_xform_point(at, q), root.t) / s);
        }
    }
}

bool rf_retarget_parts_above(rf_retarget *rt, rf_animation *anim, rf_rt_parts_stats *st)
{
    memset(st, 0, sizeof *st);
    uint32_t n = rt->n;
    uint8_t *foot = malloc(n ? n : 1), *part = malloc(n ? n : 1), *all = malloc(n ? n : 1);
    uint8_t *holds = calloc(n ? n : 1, 1), *reach = calloc(n ? n : 1, 1);
    double *extent = calloc(n ? n : 1, sizeof *extent);
    if (!foot || !part || !all || !holds || !reach || !extent) {
        free(foot), free(part), free(all), free(holds), free(reach), free(extent);
        return false;
    }
    for (uint32_t j = 0; j < n; j++) {
        extent[j] = rf_v3_len(rt->t_tip[j]);
        for (uint32_t k = 0; rt->t_hull && k < RF_RT_HULL; k++)
            extent[j] = fmax(extent[j], rf_v3_len(rt->t_hull[(size_t)j * RF_RT_HULL + k]));
    }
    memset(all, 1, n);
    rt_feet_mask(rt, foot);
    rt_parts_mask(rt, foot, part);
    for (uint32_t e = 0; e < rt->effector_count; e++)
        for (int32_t a = rt->lparent[rt->effectors[e]], g = 0; a >= 0 && g < (int32_t)n;
             a = rt->lparent[a], g++)
            holds[a] = 1;
    for (uint32_t e = 0; e < rt->effector_count; e++)
        for (int32_t a = rt->target->joints[rt->effectors[e]].parent; a >= 0;
             a = rt->target->joints[a].parent)
            holds[a] = 1;
    for (uint32_t j = 0; j < n; j++)
        for (int32_t a = part[j] ? (int32_t)j : -1; a >= 0 && !reach[a];
             a = rt->target->joints[a].parent)
            reach[a] = 1;
    rt_whole_limbs(rt, part, reach, extent);
    double *hang = rt_parts_hang(rt, anim, part, reach, extent);
    rt_parts c = {
        rt,  anim, part, all, holds, reach, extent, rt_parts_step(anim), 1e-3 * rt->leg_target,
        hang};
    bool ok = hang && rt_parts_all(&c, st);
    free(foot), free(part), free(all), free(holds), free(reach), free(extent);
    free(hang);
    return ok;
}
