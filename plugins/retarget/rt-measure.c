/* Measures of any target clip against the plan's sources, with one definition for our output and
 * for a peer's: direction fidelity of the mapped bones, foot skate during source contacts, and how
 * far the feet in contact are from the floor compared with the source's. The definitions depend
 * only on the mapping and the geometry, not on how the clip was made. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rt-internal.h"

/* Frames a clip is measured on at most. */
#define RT_MEASURE_FRAMES 1024u

typedef struct rt_measure_work {
    rf_xform *t_world;
    rf_xform **s_local, **s_world;
    float *rot, *tr;
    double *angles;   /* [frame][bone] degrees */
    rf_vec3 *src_pos; /* [eff][frame] */
    rf_vec3 *t_eff;   /* [eff][frame] the target's effector points, for the skate */
    double *t_sole;   /* [eff][frame] the target feet's soles, heights along up */
    double *src_sole; /* [eff][frame] */
    uint8_t *contact;
    uint8_t **need; /* [source][joint] what the fidelity angles read and what carries it */
} rt_measure_work;

static void rt_mw_free(rt_measure_work *w, uint32_t sources)
{
    for (uint32_t k = 0; k < sources; k++) {
        if (w->s_local)
            free(w->s_local[k]);
        if (w->s_world)
            free(w->s_world[k]);
        if (w->need)
            free(w->need[k]);
    }
    free(w->t_world), free(w->s_local), free(w->s_world), free(w->rot), free(w->tr), free(w->need);
    free(w->angles), free(w->src_pos), free(w->src_sole), free(w->contact), free(w->t_eff),
        free(w->t_sole);
}

static bool rt_mw_alloc(rt_measure_work *w, const rf_retarget *rt, uint32_t frames)
{
    size_t m = rt->max_src_n, ef = (size_t)rt->effector_count * frames;
    w->t_world = malloc(rt->n * sizeof *w->t_world);
    w->s_local = calloc(rt->source_count, sizeof *w->s_local);
    w->s_world = calloc(rt->source_count, sizeof *w->s_world);
    w->need = calloc(rt->source_count, sizeof *w->need);
    w->rot = malloc(m * 4 * sizeof *w->rot);
    w->tr = malloc(m * 3 * sizeof *w->tr);
    w->angles = malloc(((size_t)frames * rt->bone_count + 1) * sizeof *w->angles);
    w->src_pos = malloc((ef ? ef : 1) * sizeof *w->src_pos);
    w->src_sole = malloc((ef ? ef : 1) * sizeof *w->src_sole);
    w->t_eff = malloc((ef ? ef : 1) * sizeof *w->t_eff);
    w->t_sole = malloc((ef ? ef : 1) * sizeof *w->t_sole);
    if (!w->t_sole || !w->t_world || !w->s_local || !w->s_world || !w->need || !w->rot || !w->tr ||
        !w->angles || !w->src_pos || !w->src_sole || !w->t_eff)
        return false;
    for (uint32_t k = 0; k < rt->source_count; k++) {
        w->s_local[k] = malloc(m * sizeof **w->s_local);
        w->s_world[k] = malloc(m * sizeof **w->s_world);
        w->need[k] = calloc(m ? m : 1, 1);
        if (!w->s_local[k] || !w->s_world[k] || !w->need[k])
            return false;
    }
    return true;
}

/* Marks source k's joint j and what carries it (a marked joint's carriers are marked). */
static void rt_need_chain(const rf_retarget *rt, uint8_t *need, uint32_t k, uint32_t j)
{
    const rf_joint *joints = rt->src[k].skel->joints;
    for (int32_t x = (int32_t)j; x >= 0 && !need[x]; x = joints[x].parent)
        need[x] = 1;
}

/* The source joint a one-bone limb j points at (rt_chain_reach in rt-plan.c: the end of the
 * source limb it stands for), or -1: its direction is measured against that line, as it is
 * driven. */
static int32_t rt_reach_of(const rf_retarget *rt, uint32_t j)
{
    const rf_rt_tjoint *tj = &rt->tj[j];
    if (tj->kind != RF_RT_MAPPED || tj->input_count != 1)
        return -1;
    const rf_rt_input *in = &rt->in[tj->first_input];
    return (in->flags & RF_RT_IN_CORRECT) ? in->seg_end : -1;
}

/* The source joints rt_frame_angles reads, by the same choice of source and joints: each
 * measured bone's mapped joint and, for a bone to a mapped child, the child's. Only these and
 * their carriers are posed at each measured frame (rf_rt_source_world_some poses a joint the
 * same way whatever else it poses); the benchmark clip's hands and toes are left out: 1.5 M of
 * the node's 36.4 M instructions. */
static void rt_mw_need(const rf_retarget *rt, rt_measure_work *w)
{
    for (uint32_t b = 0; b < rt->bone_count; b++) {
        uint32_t j = rt->bones[b * 2], c = rt->bones[b * 2 + 1];
        const rf_map_input *ij = &rt->mapping->entries[j].inputs[0];
        rt_need_chain(rt, w->need[ij->source], ij->source, ij->joint);
        if (c != j)
            rt_need_chain(rt, w->need[ij->source], ij->source,
                          rt->mapping->entries[c].inputs[0].joint);
        else if (rt_reach_of(rt, j) >= 0)
            rt_need_chain(rt, w->need[ij->source], ij->source, (uint32_t)rt_reach_of(rt, j));
    }
}

/* The world direction of bone (j, c) in a pose: to the mapped child, or along j's tip. */
static rf_vec3 rt_bone_dir(const rf_xform *world, uint32_t j, uint32_t c, rf_vec3 tip)
{
    if (c != j)
        return rf_v3_sub(world[c].t, world[j].t);
    return rf_v3_sub(rf_xform_point(world[j], tip), world[j].t);
}

/* Fidelity angles of every measured bone at one frame (sources already posed). */
static void rt_frame_angles(const rf_retarget *rt, rt_measure_work *w, double *angles)
{
    for (uint32_t b = 0; b < rt->bone_count; b++) {
        uint32_t j = rt->bones[b * 2], c = rt->bones[b * 2 + 1];
        const rf_map_input *ij = &rt->mapping->entries[j].inputs[0];
        const rf_xform *sw = w->s_world[ij->source];
        uint32_t sc = c == j ? ij->joint : rt->mapping->entries[c].inputs[0].joint;
        rf_vec3 td = rt_bone_dir(w->t_world, j, c, rt->t_tip[j]);
        rf_vec3 sd =
            rt_bone_dir(sw, ij->joint, c == j ? ij->joint : sc, rt->src[ij->source].tip[ij->joint]);
        int32_t reach = c == j ? rt_reach_of(rt, j) : -1;
        if (reach >= 0)
            sd = rf_v3_sub(sw[reach].t, sw[ij->joint].t);
        angles[b] = rf_v3_angle(td, sd) * 180.0 / RF_PI;
    }
}

static void rt_fidelity(const rf_retarget *rt, rt_measure_work *w, uint32_t frames, rf_rt_report *r)
{
    size_t count = (size_t)frames * rt->bone_count;
    r->fidelity_bones = rt->bone_count;
    if (!count)
        return;
    double sum = 0, max = 0;
    for (size_t i = 0; i < count; i++)
        sum += w->angles[i], max = fmax(max, w->angles[i]);
    r->fidelity_mean = sum / count;
    r->fidelity_max = max;
    r->fidelity_p95 = rf_rt_select(w->angles, count, (size_t)(0.95 * (count - 1)));
}

/* Ground: for each effector in contact at each frame, how far its sole is over the target's
 * floor against how far the source's is over its own, each in its own leg lengths. */
static double rt_ground(const rf_retarget *rt, const rt_measure_work *w, uint32_t frames)
{
    double sum = 0;
    uint32_t count = 0;
    for (size_t i = 0; i < (size_t)rt->effector_count * frames; i++) {
        if (!w->contact[i])
            continue;
        /* at the input's own sample time; a foot whose contacts are its own motion's stands on
         * the floor in them (rf_rt_phase_contacts) */
        double hs = rf_rt_effector_steps(rt, (uint32_t)(i / frames)) ? 0 : w->src_sole[i];
        sum += fabs((w->t_sole[i] - rt->floor_target) / rt->leg_target - hs);
        count++;
    }
    return count ? sum / count : 0;
}

/* Skate: effector speeds while in contact, the target's positions from its FK at the measured
 * frames (w->t_eff), the source's from the contact detection; `frames` samples one frame in `step`
 * of the clip, `fps` the samples' rate; `per_frame`, when given, gets the fastest foot in contact
 * at each sampled frame of the clip. */
static void rt_skate(const rf_retarget *rt, uint32_t frames, uint32_t step, double fps,
                     const rt_measure_work *w, rf_rt_report *r, float *per_frame)
{
    uint32_t count = 0, s_count = 0;
    double t_sum = 0, s_sum = 0;
    rf_vec3 *prev = malloc((rt->effector_count ? rt->effector_count : 1) * sizeof *prev);
    if (!prev)
        return;
    for (uint32_t f = 0; f < frames; f++) {
        for (uint32_t e = 0; e < rt->effector_count; e++) {
            size_t i = (size_t)e * frames + f;
            rf_vec3 p = w->t_eff[i];
            if (f > 0 && w->contact[i] && w->contact[i - 1]) {
                uint32_t k, j;
                rf_rt_effector_source(rt, e, &k, &j);
                const rf_rt_src *src = &rt->src[k];
                rf_vec3 dt = rf_rt_horizontal(rt->up, rf_v3_sub(p, prev[e]));
                rf_vec3 ds = rf_rt_horizontal(src->up, rf_v3_sub(w->src_pos[i], w->src_pos[i - 1]));
                double speed = rf_v3_len(dt) * fps / rt->leg_target;
                float *at = per_frame ? &per_frame[(size_t)f * step] : NULL;
                t_sum += speed;
                /* the source's reference over the feet whose contacts are its own */
                if (!rf_rt_effector_steps(rt, e))
                    s_sum += rf_v3_len(ds) * fps / src->leg, s_count++;
                if (e < RF_RT_REPORT_FEET)
                    r->foot_skate[e] += speed, r->foot_frames[e]++;
                if (at)
                    *at = isnan(*at) ? (float)speed : fmaxf(*at, (float)speed);
                count++;
            }
            prev[e] = p;
        }
    }
    free(prev);
    r->effectors = rt->effector_count;
    for (uint32_t e = 0; e < rt->effector_count && e < RF_RT_REPORT_FEET; e++) {
        r->foot_joint[e] = rt->effectors[e];
        r->foot_skate[e] = r->foot_frames[e] ? r->foot_skate[e] / r->foot_frames[e] : 0;
    }
    r->contact_frames = count;
    r->skate_target = count ? t_sum / count : 0;
    r->skate_source = s_count ? s_sum / s_count : 0;
}

/* How many distinct source joints the target's feet follow (their sources' feet). */
static uint32_t rt_source_feet(const rf_retarget *rt)
{
    uint32_t n = 0;
    for (uint32_t e = 0; e < rt->effector_count; e++) {
        uint32_t k, j, seen = 0;
        rf_rt_effector_source(rt, e, &k, &j);
        for (uint32_t d = 0; d < e && !seen; d++) {
            uint32_t kd, jd;
            rf_rt_effector_source(rt, d, &kd, &jd);
            seen = kd == k && jd == j;
        }
        n += !seen;
    }
    return n;
}

/* The per-frame figures behind the report, as series for the nodes after the measure. */
static bool rt_series(const rf_retarget *rt, const rt_measure_work *w, uint32_t frames,
                      uint32_t step, rf_measures *out)
{
    float *mean =
        rf_measures_add(out, "direction error, mean over bones", "deg", -1, RF_SERIES_HIGHER_WORSE);
    float *max = mean ? rf_measures_add(out, "direction error, worst bone", "deg", -1,
                                        RF_SERIES_HIGHER_WORSE)
                      : NULL;
    if (!max)
        return false;
    for (uint32_t f = 0; f < frames && rt->bone_count; f++) {
        const double *a = w->angles + (size_t)f * rt->bone_count;
        double sum = 0, worst = 0;
        for (uint32_t b = 0; b < rt->bone_count; b++)
            sum += a[b], worst = fmax(worst, a[b]);
        mean[(size_t)f * step] = (float)(sum / rt->bone_count);
        max[(size_t)f * step] = (float)worst;
    }
    for (uint32_t e = 0; e < rt->effector_count; e++) {
        float *c =
            rf_measures_add(out, "contact", "", (int32_t)rt->effectors[e], RF_SERIES_CONTACT);
        if (!c)
            return false;
        for (uint32_t f = 0; f < frames; f++)
            c[(size_t)f * step] = w->contact[(size_t)e * frames + f] ? 1.0f : 0.0f;
    }
    if (!rt->effector_count)
        rf_measures_warn(out, "no feet found on the target: foot skate and contacts not measured");
    return true;
}

bool rf_retarget_measure(rf_retarget *rt, const rf_animation *anim, double start,
                         rf_rt_report *report, char *err, size_t err_size)
{
    return rf_retarget_measure_series(rt, anim, start, report, NULL, err, err_size);
}

bool rf_retarget_measure_series(rf_retarget *rt, const rf_animation *anim, double start,
                                rf_rt_report *report, rf_measures *series, char *err,
                                size_t err_size)
{
    memset(report, 0, sizeof *report);
    if (!anim || anim->joint_count != rt->n || !(anim->fps > 0)) {
        rf_rt_fail(err, err_size, "the clip measured does not fit the target (%u joints, %u)",
                   anim ? anim->joint_count : 0, rt->n);
        return false;
    }
    /* A long clip is measured on one frame in `step` (at most RT_MEASURE_FRAMES of them), so the
     * measure stays a small part of a run; contacts and speeds are read on that timeline. */
    uint32_t step = (anim->frame_count + RT_MEASURE_FRAMES - 1) / RT_MEASURE_FRAMES;
    step = step ? step : 1;
    uint32_t frames = (anim->frame_count + step - 1) / step;
    double fps = anim->fps / step;
    rt_measure_work w = {0};
    bool ok = rt_mw_alloc(&w, rt, frames) &&
              (w.contact = rf_rt_detect_contacts(rt, frames, fps, start, w.src_pos, w.src_sole));
    if (!ok) {
        rt_mw_free(&w, rt->source_count);
        rf_rt_fail(err, err_size, "out of memory");
        return false;
    }
    rt_mw_need(rt, &w);
    for (uint32_t f = 0; f < frames; f++) {
        rf_rt_target_fk(rt, anim, f * step, w.t_world);
        for (uint32_t e = 0; e < rt->effector_count; e++) {
            w.t_eff[(size_t)e * frames + f] = rf_rt_effector_point(rt, w.t_world, e);
            w.t_sole[(size_t)e * frames + f] =
                rf_rt_sole(rt->target, w.t_world, rt->t_tip, rt->up, rt->effectors[e]);
        }
        for (uint32_t k = 0; k < rt->source_count; k++)
            rf_rt_source_world_some(rt, k, start + f / fps, w.s_local[k], w.s_world[k], w.rot, w.tr,
                                    w.need[k]);
        rt_frame_angles(rt, &w, w.angles + (size_t)f * rt->bone_count);
    }
    /* a foot driven half a cycle later that steps is down where its own motion is, as the
     * contact pass reads it (rf_rt_phase_contacts): its source's leg is down where the source's
     * body, half a cycle later, stands over it */
    if (!rf_rt_phase_contacts(rt, frames, fps, w.t_sole, w.contact)) {
        rt_mw_free(&w, rt->source_count);
        rf_rt_fail(err, err_size, "out of memory");
        return false;
    }
    report->ground_error = rt_ground(rt, &w, frames);
    report->frames = frames;
    float *skate = NULL;
    if (series && (!rt_series(rt, &w, frames, step, series) ||
                   !(skate = rf_measures_add(series, "foot skate, fastest foot in contact", "leg/s",
                                             -1, RF_SERIES_HIGHER_WORSE)))) {
        rt_mw_free(&w, rt->source_count);
        rf_rt_fail(err, err_size, "out of memory");
        return false;
    }
    rt_fidelity(rt, &w, frames, report); /* reorders the angles: after the series */
    rt_skate(rt, frames, step, fps, &w, report, skate);
    report->source_feet = rt_source_feet(rt);
    rt_mw_free(&w, rt->source_count);
    return true;
}
