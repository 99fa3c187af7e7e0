/* The clip driver: frame range, output rate (slerp resampling), each slot's sample time (delays,
 * the half cycle of mirrored inputs), and the detection of that cycle. */
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include <rigflow/memory.h>
#include <rigflow/model-copy.h>
#include <rigflow/prefault.h>

#include "rt-internal.h"

/* Position of time t in a clip, in frames, clamped; snapped to a whole frame when within
 * rounding of one so that exact frames are read, not interpolated. */
static double rt_frame_pos(const rf_animation *a, double t)
{
    double x = t * a->fps, last = a->frame_count ? a->frame_count - 1 : 0;
    double r = nearbyint(x);
    if (fabs(x - r) < 1e-6)
        x = r;
    return x < 0 ? 0 : x > last ? last : x;
}

void rf_rt_sample(const rf_animation *a, double t, float *rot, float *tr)
{
    double x = rt_frame_pos(a, t);
    uint32_t f0 = (uint32_t)x, n = a->joint_count;
    double u = x - f0;
    const float *r0 = a->rotations + (size_t)f0 * n * 4, *t0 = a->translations + (size_t)f0 * n * 3;
    if (u == 0 || f0 + 1 >= a->frame_count) {
        memcpy(rot, r0, (size_t)n * 4 * sizeof *rot);
        memcpy(tr, t0, (size_t)n * 3 * sizeof *tr);
        return;
    }
    const float *r1 = r0 + (size_t)n * 4, *t1 = t0 + (size_t)n * 3;
    for (uint32_t j = 0; j < n; j++) {
        rf_quat a0 = rf_quat_make(r0[j * 4], r0[j * 4 + 1], r0[j * 4 + 2], r0[j * 4 + 3]);
        rf_quat a1 = rf_quat_make(r1[j * 4], r1[j * 4 + 1], r1[j * 4 + 2], r1[j * 4 + 3]);
        rf_quat q = rf_quat_slerp(rf_quat_normalize(a0), rf_quat_normalize(a1), u);
        rot[j * 4] = (float)q.x, rot[j * 4 + 1] = (float)q.y;
        rot[j * 4 + 2] = (float)q.z, rot[j * 4 + 3] = (float)q.w;
        for (int c = 0; c < 3; c++)
            tr[j * 3 + c] = (float)(t0[j * 3 + c] + (t1[j * 3 + c] - t0[j * 3 + c]) * u);
    }
}

double rf_rt_slot_time(const rf_retarget *rt, uint32_t s, double t)
{
    const rf_rt_slot *slot = &rt->slots[s];
    const rf_animation *a = rt->src[slot->source].anim;
    double end = a->frame_count ? (a->frame_count - 1) / a->fps : 0;
    double ts = t + slot->offset;
    if (slot->wrap > 0 && ts > end + 1e-9)
        ts -= slot->wrap; /* half a cycle on: the same phase a cycle earlier */
    return ts;
}

/* The pose of slot s at output time t: straight from the clip on a whole frame, else sampled
 * into the slot's scratch. */
static rf_rt_pose rt_slot_pose(const rf_retarget *rt, rf_rt_work *w, uint32_t s, double t)
{
    const rf_animation *a = rt->src[rt->slots[s].source].anim;
    double ts = rf_rt_slot_time(rt, s, t);
    double x = rt_frame_pos(a, ts);
    uint32_t n = a->joint_count;
    if (x == floor(x)) {
        size_t f = (size_t)x;
        return (rf_rt_pose){a->rotations + f * n * 4, a->translations + f * n * 3};
    }
    float *rot = w->scratch_rot + (size_t)s * rt->max_src_n * 4;
    float *tr = w->scratch_tr + (size_t)s * rt->max_src_n * 3;
    rf_rt_sample(a, ts, rot, tr);
    return (rf_rt_pose){rot, tr};
}

double rf_retarget_start_time(const rf_retarget *rt)
{
    return rt->opt.first_frame / rt->src[0].anim->fps;
}

double rf_retarget_output_fps(const rf_retarget *rt)
{
    return rt->opt.fps > 0 ? rt->opt.fps : rt->src[0].anim->fps;
}

/* Frames of output for the option's range; 0 when the range is empty. A double: a file's frame
 * time can make it any size (1e300 s a frame), beyond what a frame index holds. */
static double rt_output_frames(const rf_retarget *rt)
{
    const rf_animation *a = rt->src[0].anim;
    if (!a->frame_count)
        return 0;
    uint32_t last = rt->opt.last_frame < 0 || (uint32_t)rt->opt.last_frame >= a->frame_count
                        ? a->frame_count - 1
                        : (uint32_t)rt->opt.last_frame;
    if (rt->opt.first_frame > last)
        return 0;
    double duration = (last - rt->opt.first_frame) / a->fps;
    return floor(duration * rf_retarget_output_fps(rt) + 1e-9) + 1;
}

/* Whether a clip of `joints` x `frames` fits in `left` bytes (when `known`), counted twice: the
 * nodes after the retarget (an exporter's buffer, a measure's poses) hold about as much again. A
 * 200,000-joint target under a long clip would otherwise be killed partway through by the
 * system, with no message. */
bool rf_rt_output_fits(uint32_t joints, uint32_t frames, bool known, uint64_t left, char *err,
                       size_t err_size)
{
    double bytes = 2.0 * joints * (double)frames * 7 * sizeof(float);
    if (!known || bytes <= (double)left)
        return true;
    rf_rt_fail(err, err_size,
               "the retargeted clip would hold %u joints x %u frames, about %.1f GB with what the "
               "nodes after it keep, and %.1f GB of memory is left: retarget fewer frames "
               "(retarget.first_frame, retarget.last_frame) or at a lower retarget.fps",
               joints, frames, bytes / 1e9, (double)left / 1e9);
    return false;
}

/* The output clip, its arrays left unset: every frame writes every value (rf_animation_new
 * would fill the rotations with identities first, one more pass over the memory). Freed with
 * rf_animation_free like any clip. */
static rf_animation *rt_output_new(const rf_retarget *rt, uint32_t frames)
{
    size_t n = (size_t)rt->n * frames;
    if (rt->n && n / rt->n != frames)
        return NULL;
    rf_animation *out = calloc(1, sizeof *out);
    if (!out)
        return NULL;
    out->size = sizeof *out;
    out->joint_count = rt->n, out->frame_count = frames;
    out->fps = rf_retarget_output_fps(rt);
    /* a measure of the clip compares it with the same window of the sources */
    out->source_start = rf_retarget_start_time(rt);
    out->rotations = malloc((n ? n : 1) * 4 * sizeof *out->rotations);
    out->translations = malloc((n ? n : 1) * 3 * sizeof *out->translations);
    out->channels = calloc(rt->n ? rt->n : 1, 1);
    const char *name = rt->src[0].anim->name;
    out->name = rf_strdup(name);
    if (!out->rotations || !out->translations || !out->channels || (name && !out->name)) {
        rf_animation_free(out);
        return NULL;
    }
    rf_prefault(out->rotations, n * 4 * sizeof *out->rotations);
    rf_prefault(out->translations, n * 3 * sizeof *out->translations);
    for (uint32_t j = 0; j < rt->n; j++)
        out->channels[j] =
            (uint8_t)(RF_CHANNEL_ROTATION |
                      (rt->tj[j].root_motion || rt->tj[j].translate ? RF_CHANNEL_TRANSLATION : 0));
    return out;
}

/* Frames [first, end) of the clip into out, with scratch w. */
static void rt_frames(const rf_retarget *rt, rf_rt_work *w, rf_animation *out, uint32_t first,
                      uint32_t end)
{
    double start = rf_retarget_start_time(rt), fps = out->fps;
    size_t n = rt->n;
    for (uint32_t f = first; f < end; f++) {
        double t = start + f / fps;
        for (uint32_t s = 0; s < rt->slot_count; s++)
            w->poses[s] = rt_slot_pose(rt, w, s, t);
        rf_rt_frame(rt, w, w->poses, out->rotations + f * n * 4, out->translations + f * n * 3);
    }
}

/* A helper thread taking chunks of a long clip (rf_rt_chunk) with scratch of its own. */
typedef struct rt_half {
    const rf_retarget *rt;
    rf_rt_work work;
    rf_animation *out;
    rf_rt_chunks *chunks;
} rt_half;

static void *rt_half_run(void *arg)
{
    rt_half *h = arg;
    uint32_t first, end;
    while (rf_rt_chunk(h->chunks, &first, &end))
        rt_frames(h->rt, &h->work, h->out, first, end);
    return NULL;
}

/* All frames of the clip: shared with a second thread when the clip is long and one can be
 * had, else on this one. Frames are independent, so the threads need no other coordination.
 * Progress is reported as chunks are taken here; when it says stop, the helper's next chunk is
 * its last. */
static bool rt_all_frames(rf_retarget *rt, rf_animation *out, rf_rt_progress_fn progress,
                          void *user)
{
    uint32_t frames = out->frame_count, first, end;
    rf_rt_chunks chunks;
    rf_rt_chunks_init(&chunks, frames);
    rt_half h = {rt, {0}, out, &chunks};
    pthread_t thread;
    bool two = (uint64_t)frames * rt->n >= RT_THREAD_MIN && rf_rt_work_init(rt, &h.work) &&
               pthread_create(&thread, NULL, rt_half_run, &h) == 0;
    bool ok = true;
    while (ok && rf_rt_chunk(&chunks, &first, &end)) {
        rt_frames(rt, &rt->work, out, first, end);
        ok = !progress || progress(user, (double)end / frames);
    }
    if (!ok)
        rf_rt_chunks_stop(&chunks);
    if (two)
        pthread_join(thread, NULL);
    rf_rt_work_free(rt, &h.work);
    return ok;
}

rf_animation *rf_retarget_clip(rf_retarget *rt, rf_rt_progress_fn progress, void *user, char *err,
                               size_t err_size)
{
    double count = rt_output_frames(rt);
    if (!(count >= 1)) {
        uint32_t have = rt->src[0].anim->frame_count;
        if (!have)
            rf_rt_fail(err, err_size, "the source clip has no frames: nothing to retarget");
        else if (rt->opt.first_frame >= have)
            rf_rt_fail(err, err_size,
                       "first_frame %u is past the source clip's last frame (%u frames: 0..%u)",
                       rt->opt.first_frame, have, have - 1);
        else
            rf_rt_fail(err, err_size, "the frame range %u..%d is empty (the clip has %u frames)",
                       rt->opt.first_frame, rt->opt.last_frame, have);
        return NULL;
    }
    if (!(count < UINT32_MAX)) {
        rf_rt_fail(err, err_size,
                   "the clip would be %.3g frames at %g fps (its %u frames span %.3g s): check "
                   "the source's frame time",
                   count, rf_retarget_output_fps(rt), rt->src[0].anim->frame_count,
                   (rt->src[0].anim->frame_count - 1) / rt->src[0].anim->fps);
        return NULL;
    }
    uint32_t frames = (uint32_t)count;
    uint64_t left = 0;
    bool known = rf_memory_available(&left);
    if (!rf_rt_output_fits(rt->n, frames, known, left, err, err_size))
        return NULL;
    rf_animation *out = rt_output_new(rt, frames);
    if (!out) {
        rf_rt_fail(err, err_size, "out of memory for %u frames", frames);
        return NULL;
    }
    if (!rt_all_frames(rt, out, progress, user)) {
        rf_animation_free(out);
        rf_rt_fail(err, err_size, "cancelled");
        return NULL;
    }
    if (!rf_rt_carry_root(rt, out) || !rf_rt_ground_fix(rt, out)) {
        rf_animation_free(out);
        rf_rt_fail(err, err_size, "out of memory");
        return NULL;
    }
    return out;
}

/* ---- poses for the measures and the contact pass ---- */

void rf_rt_target_fk(const rf_retarget *rt, const rf_animation *anim, uint32_t f, rf_xform *world)
{
    const rf_joint *joints = rt->target->joints;
    for (uint32_t j = 0; j < rt->n; j++) {
        rf_xform x = {rf_animation_translation(anim, f, j),
                      rf_quat_normalize(rf_animation_rotation(anim, f, j)), joints[j].rest.s};
        int32_t p = joints[j].parent;
        world[j] = p < 0 ? x : rf_xform_mul(world[p], x);
    }
}

void rf_rt_source_world(const rf_retarget *rt, uint32_t k, double t, rf_xform *local,
                        rf_xform *world, float *rot, float *tr)
{
    rf_rt_source_world_some(rt, k, t, local, world, rot, tr, NULL);
}

/* Joint j of a source pose sampled into rot and tr: its local and world transforms. */
static inline void rt_source_joint(const rf_rt_src *src, uint32_t j, rf_xform *local,
                                   rf_xform *world, const float *rot, const float *tr)
{
    const float *q = rot + j * 4, *p = tr + j * 3;
    local[j].r = rf_quat_normalize(rf_quat_make(q[0], q[1], q[2], q[3]));
    local[j].t = rf_v3(p[0], p[1], p[2]);
    local[j].s = src->skel->joints[j].rest.s;
    int32_t par = src->skel->joints[j].parent;
    world[j] = par < 0 ? rf_rt_source_root(src, local[j]) : rf_xform_mul(world[par], local[j]);
}

__attribute__((flatten)) void rf_rt_source_world_some(const rf_retarget *rt, uint32_t k, double t,
                                                      rf_xform *local, rf_xform *world, float *rot,
                                                      float *tr, const uint8_t *need)
{
    const rf_rt_src *src = &rt->src[k];
    rf_rt_sample(src->anim, t, rot, tr);
    for (uint32_t j = 0; j < src->n; j++)
        if (!need || need[j])
            rt_source_joint(src, j, local, world, rot, tr);
}

__attribute__((flatten)) void rf_rt_source_world_two(const rf_retarget *rt, uint32_t k,
                                                     const double t[2], rf_rt_source_pose pose[2],
                                                     const uint8_t *need)
{
    const rf_rt_src *src = &rt->src[k];
    rf_rt_sample(src->anim, t[0], pose[0].rot, pose[0].tr);
    rf_rt_sample(src->anim, t[1], pose[1].rot, pose[1].tr);
    for (uint32_t j = 0; j < src->n; j++)
        if (!need || need[j])
            for (int i = 0; i < 2; i++)
                rt_source_joint(src, j, pose[i].local, pose[i].world, pose[i].rot, pose[i].tr);
}

/* ---- the cycle of mirrored inputs ---- */

/* Mean angular distance between the rotations of the joints in `use` at frames f and f + lag. */
static double rt_lag_distance(const rf_animation *a, const uint8_t *use, uint32_t lag)
{
    double sum = 0;
    uint32_t count = 0, n = a->joint_count;
    for (uint32_t f = 0; f + lag < a->frame_count; f++)
        for (uint32_t j = 0; j < n; j++) {
            if (!use[j])
                continue;
            const float *p = a->rotations + ((size_t)f * n + j) * 4;
            const float *q = a->rotations + ((size_t)(f + lag) * n + j) * 4;
            double d = fabs(p[0] * q[0] + p[1] * q[1] + p[2] * q[2] + p[3] * q[3]);
            sum += 1 - fmin(d, 1), count++;
        }
    return count ? sum / count : INFINITY;
}

/* The first lag at which the pose nearly repeats: past the first peak of the distance, the first
 * local minimum within a tenth of the way from the deepest minimum to that peak. */
static uint32_t rt_first_repeat(const double *d, uint32_t count)
{
    uint32_t peak = 0;
    while (peak + 1 < count && d[peak + 1] >= d[peak])
        peak++;
    double low = INFINITY;
    for (uint32_t i = peak; i < count; i++)
        low = fmin(low, d[i]);
    double bar = low + 0.1 * (d[peak] - low);
    for (uint32_t i = peak + 1; i < count; i++)
        if (d[i] <= bar && (i + 1 == count || d[i] <= d[i + 1]))
            return i;
    return count;
}

/* The period of source k's motion, from the joints that mirrored inputs read: the lag (between
 * 0.2 s and half the clip, at most 4 s) at which the pose first repeats. A clip with no repeat
 * gives its own length. */
double rf_rt_detect_cycle(const rf_retarget *rt, uint32_t k)
{
    const rf_animation *a = rt->src[k].anim;
    double clip = a->frame_count > 1 ? (a->frame_count - 1) / a->fps : 1;
    /* lags in frames, bounded in double first: a file may claim any rate (1e300 fps), and a
     * double beyond uint32_t's range does not convert */
    uint32_t hi = a->frame_count / 2;
    uint32_t lo = (uint32_t)fmin(ceil(0.2 * a->fps), (double)hi + 1);
    hi = (uint32_t)fmin(floor(4 * a->fps), (double)hi);
    if (lo < 1)
        lo = 1;
    if (hi <= lo)
        return clip;
    uint8_t *use = calloc(a->joint_count ? a->joint_count : 1, 1);
    double *d = malloc((hi - lo + 1) * sizeof *d);
    uint32_t found = hi - lo + 1;
    if (use && d) {
        for (uint32_t j = 0; j < rt->n; j++)
            for (uint32_t i = 0; i < rt->mapping->entries[j].input_count; i++) {
                const rf_map_input *in = &rt->mapping->entries[j].inputs[i];
                if (in->source == k && (in->flags & RF_MAP_MIRROR))
                    use[in->joint] = 1;
            }
        for (uint32_t lag = lo; lag <= hi; lag++)
            d[lag - lo] = rt_lag_distance(a, use, lag);
        found = rt_first_repeat(d, hi - lo + 1);
    }
    free(use);
    free(d);
    return found <= hi - lo ? (found + lo) / a->fps : clip;
}

/* ---- turns limited to the target's own range ---- */

/* The turn of local rotation q off rest r, in radians. */
static double rt_turn_off(rf_quat r, rf_quat q)
{
    rf_quat d = rf_quat_mul(rf_quat_conj(r), rf_quat_normalize(q));
    return 2 * acos(fmin(1, fabs(d.w)));
}

/* Turn d (a unit quaternion turned further than the limit) cut back to the limit about its own
 * axis: the shorter way's axis, turned by the limit (cos_half, sin_half of half of it). It is
 * d's power limit / turn, with the sines and cosines of the limit made once a joint instead of an
 * acos and three sines a frame. */
static rf_quat rt_turn_cut(rf_quat d, double cos_half, double sin_half)
{
    if (d.w < 0)
        d = rf_quat_neg(d);
    double len = sqrt(d.x * d.x + d.y * d.y + d.z * d.z), k = len > 0 ? sin_half / len : 0;
    return rf_quat_make(d.x * k, d.y * k, d.z * k, cos_half);
}

int rf_retarget_limit_turns(rf_retarget *rt, rf_animation *anim, const rf_animation *reference)
{
    const rf_skeleton *s = rt->target;
    if (!reference || reference->joint_count != rt->n || reference->frame_count < 2)
        return 0;
    int limited = 0;
    uint8_t *moved = NULL; /* [frame] turned here: its anchored joints are placed again */
    for (uint32_t j = 0; j < rt->n; j++) {
        int32_t p = s->joints[j].parent;
        if (!rt->t_centerline[j] || rt->tj[j].kind == RF_RT_REST || rt->tj[j].root_motion ||
            rt->anchor[j] >= 0 || p < 0 || rt->tj[p].kind == RF_RT_REST)
            continue;
        rf_quat rest = s->joints[j].rest.r;
        double own = 0;
        for (uint32_t f = 0; f < reference->frame_count; f++)
            own = fmax(own, rt_turn_off(rest, rf_animation_rotation(reference, f, j)));
        if (own < 0.5 * RF_PI / 180)
            continue;
        double limit = own + RF_RT_TURN_SLACK * RF_PI / 180;
        if (limit >= RF_PI) /* no turn exceeds a half turn: a clip at exactly one would be
                             * carried on past it */
            continue;
        /* Turned further than the limit when |cos(turn / 2)| is smaller: no acos per frame. */
        double cos_half = cos(0.5 * limit), sin_half = sin(0.5 * limit);
        bool any = false;
        for (uint32_t f = 0; f < anim->frame_count; f++) {
            rf_quat q = rf_quat_normalize(rf_animation_rotation(anim, f, j));
            if (fabs(rf_quat_dot(rest, q)) >= cos_half)
                continue;
            if (!moved && !(moved = calloc(anim->frame_count, 1)))
                return -1;
            rf_quat cut = rt_turn_cut(rf_quat_mul(rf_quat_conj(rest), q), cos_half, sin_half);
            q = rf_quat_normalize(rf_quat_mul(rest, cut));
            rf_animation_set_rotation(anim, f, j, q);
            any = true, moved[f] = 1;
        }
        limited += any;
    }
    rf_xform *tw = moved && rt->anchored ? malloc(rt->n * sizeof *tw) : NULL;
    for (uint32_t f = 0; tw && f < anim->frame_count; f++)
        if (moved[f])
            rf_rt_place_anchored(rt, anim->rotations + (size_t)f * rt->n * 4,
                                 anim->translations + (size_t)f * rt->n * 3, NULL, tw);
    bool ok = !(moved && rt->anchored && !tw);
    free(tw), free(moved);
    return ok ? limited : -1;
}
