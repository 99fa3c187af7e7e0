/* Assimp import: clips, and resampling of Assimp's keys to a fixed frame rate.
 *
 * Times: Assimp gives key times in ticks and ticks per second per clip (glTF: milliseconds, so
 * 1000; .x: often 4800; Ogre: seconds; B3D: frames). Everything here converts to seconds first.
 * Frame rate: the clip's own key rate when its keys sit on a regular grid of 10 to 240 per
 * second (resampling is then exact: every key lands on a frame), else 30 fps; the fps option
 * overrides both. Keys are interpolated linearly (positions) and by slerp (rotations), held at the
 * ends, and clamped into [0, duration]: some files (the B3D creatures) carry a key past the end.
 * Scale keys are not kept (rf_animation has no scale channel).
 */
#include <ctype.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "aimport-internal.h"

#define RF_AI_DEFAULT_FPS 30.0

static double rf_ai_tps(const struct aiAnimation *a)
{
    /* Assimp documents 0 as "not specified"; its own viewer then assumes 25. */
    return a->mTicksPerSecond > 0 ? a->mTicksPerSecond : 25.0;
}

typedef struct rf_ai_times {
    double *v;
    size_t n, cap;
} rf_ai_times;

static void rf_ai_times_push(rf_ai_times *t, double x)
{
    if (t->n == t->cap) {
        size_t cap = t->cap ? t->cap * 2 : 256;
        double *v = realloc(t->v, cap * sizeof *v);
        if (!v)
            return; /* the rate estimate then uses fewer samples */
        t->v = v, t->cap = cap;
    }
    t->v[t->n++] = x;
}

static void rf_ai_collect(rf_ai_times *keys, const double *times, size_t n, size_t stride,
                          double tps)
{
    for (size_t k = 0; k < n; k++)
        rf_ai_times_push(keys, *(const double *)((const char *)times + k * stride) / tps);
}

/* True when every key lies within `tol` frames of the grid t0 + k / rate. */
static bool rf_ai_on_grid(const rf_ai_times *keys, double t0, double rate, double tol)
{
    for (size_t k = 0; k < keys->n; k++) {
        double f = (keys->v[k] - t0) * rate;
        if (fabs(f - round(f)) > tol)
            return false;
    }
    return true;
}

/* The clip's key rate if its keys lie on a regular grid, else 0. The rate comes from the span of
 * the channel with the most keys (gaps between neighbours are too noisy: key times went through
 * float32 in most files), and is snapped to a whole number only when the snapped grid still holds
 * every key within a thousandth of a frame (a BVH "Frame Time: 0.0083333" is 120.0005 fps, and
 * snapping it would drift by a hundredth of a frame over a long clip). */
static double rf_ai_key_rate(const struct aiAnimation *a)
{
    rf_ai_times keys = {0};
    double tps = rf_ai_tps(a), rate = 0, t0 = 0;
    unsigned most = 0;
    for (unsigned ch = 0; ch < a->mNumChannels; ch++) {
        const struct aiNodeAnim *na = a->mChannels[ch];
        if (na->mNumPositionKeys)
            rf_ai_collect(&keys, &na->mPositionKeys[0].mTime, na->mNumPositionKeys,
                          sizeof *na->mPositionKeys, tps);
        if (na->mNumRotationKeys)
            rf_ai_collect(&keys, &na->mRotationKeys[0].mTime, na->mNumRotationKeys,
                          sizeof *na->mRotationKeys, tps);
        unsigned n = na->mNumRotationKeys > na->mNumPositionKeys ? na->mNumRotationKeys
                                                                 : na->mNumPositionKeys;
        if (n > most && n >= 2) {
            const struct aiVectorKey *pk = na->mPositionKeys;
            const struct aiQuatKey *rk = na->mRotationKeys;
            bool rot = na->mNumRotationKeys >= na->mNumPositionKeys;
            double first = (rot ? rk[0].mTime : pk[0].mTime) / tps;
            double last = (rot ? rk[n - 1].mTime : pk[n - 1].mTime) / tps;
            if (last > first)
                most = n, t0 = first, rate = (n - 1) / (last - first);
        }
    }
    if (rate > 0 && !rf_ai_on_grid(&keys, t0, rate, 1e-2))
        rate = 0;
    if (rate > 0 && rf_ai_on_grid(&keys, t0, round(rate), 1e-3))
        rate = round(rate);
    free(keys.v);
    return rate;
}

static double rf_ai_pick_fps(const struct aiAnimation *a, double requested)
{
    if (requested > 0)
        return requested;
    double rate = rf_ai_key_rate(a);
    return rate >= 10 && rate <= 240 ? rate : RF_AI_DEFAULT_FPS;
}

bool rf_ai_list_clips(rf_ai_ctx *c, const rf_ai_options *o, rf_ai_result *r)
{
    const struct aiScene *s = c->scene;
    if (!s->mNumAnimations)
        return true;
    r->clips = calloc(s->mNumAnimations, sizeof *r->clips);
    if (!r->clips)
        return rf_ai_fail(c, "out of memory");
    r->clip_count = s->mNumAnimations;
    for (unsigned i = 0; i < s->mNumAnimations; i++) {
        const struct aiAnimation *a = s->mAnimations[i];
        rf_ai_clip *clip = &r->clips[i];
        char name[64];
        snprintf(name, sizeof name, "clip%u", i);
        clip->name = rf_strdup(a->mName.data[0] ? a->mName.data : name);
        if (!clip->name)
            return rf_ai_fail(c, "out of memory");
        clip->duration = a->mDuration > 0 ? a->mDuration / rf_ai_tps(a) : 0;
        clip->fps = rf_ai_pick_fps(a, o->fps);
        /* A hostile duration (1e30 s) must not overflow the conversion: such a clip is refused
         * for its size when selected. */
        double frames = floor(clip->duration * clip->fps + 0.5) + 1;
        clip->frames = frames < UINT_MAX ? (unsigned)frames : UINT_MAX;
    }
    return true;
}

bool rf_ai_select_clip(rf_ai_ctx *c, const char *spec, int *index)
{
    const struct aiScene *s = c->scene;
    unsigned n = s->mNumAnimations;
    *index = n ? 0 : -1;
    if (!spec || !*spec || strcmp(spec, RF_AI_ALL_CLIPS) == 0)
        return true; /* every clip: the first is the one on the animation output */
    bool digits = true;
    for (const char *p = spec; *p; p++)
        digits = digits && isdigit((unsigned char)*p);
    if (digits && strtoul(spec, NULL, 10) < n) {
        *index = (int)strtoul(spec, NULL, 10);
        return true;
    }
    for (unsigned i = 0; i < n; i++)
        if (strcmp(s->mAnimations[i]->mName.data, spec) == 0) {
            *index = (int)i;
            return true;
        }
    char names[512] = "";
    for (unsigned i = 0; i < n && strlen(names) < sizeof names - 80; i++)
        snprintf(names + strlen(names), sizeof names - strlen(names), "%s%u '%.60s'", i ? ", " : "",
                 i, s->mAnimations[i]->mName.data);
    return rf_ai_fail(c, "no clip '%s': expected a name or an index among %u clips (%s)", spec, n,
                      n ? names : "none");
}

/* ---- sampling ---- */

static double rf_ai_clamp(double t, double lo, double hi)
{
    return t < lo ? lo : t > hi ? hi : t;
}

/* Position of the key interval holding time t: keys [k, k+1] and the blend u in [0, 1]. Times
 * are clamped into [0, end] first. `cursor` starts at 0 and only moves forward. */
static void rf_ai_locate(const double *times, size_t stride, unsigned n, double t, double end,
                         unsigned *cursor, unsigned *k, double *u)
{
#define RF_AI_T(i) rf_ai_clamp(*(const double *)((const char *)times + (i)*stride), 0, end)
    while (*cursor + 1 < n && RF_AI_T(*cursor + 1) <= t)
        (*cursor)++;
    *k = *cursor;
    *u = 0;
    if (*k + 1 < n && t > RF_AI_T(*k)) {
        double span = RF_AI_T(*k + 1) - RF_AI_T(*k);
        *u = span > 0 ? rf_ai_clamp((t - RF_AI_T(*k)) / span, 0, 1) : 0;
    }
#undef RF_AI_T
}

typedef struct rf_ai_track {
    const struct aiNodeAnim *na; /* NULL: the joint is not keyed */
    unsigned pos_cursor, rot_cursor;
    rf_xform base;   /* the node's own transform, used where a channel has no key */
    rf_xform parent; /* static ancestors of a root joint, identity otherwise */
} rf_ai_track;

static rf_xform rf_ai_sample(rf_ai_track *tr, double t, double end)
{
    rf_xform x = tr->base;
    const struct aiNodeAnim *na = tr->na;
    unsigned k;
    double u;
    if (na && na->mNumPositionKeys) {
        rf_ai_locate(&na->mPositionKeys[0].mTime, sizeof *na->mPositionKeys, na->mNumPositionKeys,
                     t, end, &tr->pos_cursor, &k, &u);
        const struct aiVector3D *a = &na->mPositionKeys[k].mValue;
        const struct aiVector3D *b = &na->mPositionKeys[u > 0 ? k + 1 : k].mValue;
        x.t = rf_v3_lerp(rf_v3(a->x, a->y, a->z), rf_v3(b->x, b->y, b->z), u);
    }
    if (na && na->mNumRotationKeys) {
        rf_ai_locate(&na->mRotationKeys[0].mTime, sizeof *na->mRotationKeys, na->mNumRotationKeys,
                     t, end, &tr->rot_cursor, &k, &u);
        const struct aiQuaternion *a = &na->mRotationKeys[k].mValue;
        const struct aiQuaternion *b = &na->mRotationKeys[u > 0 ? k + 1 : k].mValue;
        rf_quat qa = rf_quat_normalize(rf_quat_make(a->x, a->y, a->z, a->w));
        rf_quat qb = rf_quat_normalize(rf_quat_make(b->x, b->y, b->z, b->w));
        x.r = rf_quat_slerp(qa, qb, u);
    }
    return rf_xform_mul(tr->parent, x);
}

static bool rf_ai_tracks(rf_ai_ctx *c, const struct aiAnimation *a, rf_ai_track *tracks)
{
    for (unsigned j = 0; j < c->joint_count; j++) {
        int n = c->joint_node[j], p = c->node_parent[n];
        rf_xform base = rf_xform_identity();
        rf_mat4_to_xform(rf_ai_mat4(&c->nodes[n]->mTransformation), &base);
        tracks[j].base = base;
        tracks[j].parent = rf_xform_identity();
        if (p >= 0 && c->joint_of[p] < 0)
            rf_mat4_to_xform(c->node_global[p], &tracks[j].parent);
    }
    unsigned ignored = 0;
    for (unsigned ch = 0; a && ch < a->mNumChannels; ch++) {
        int n = rf_ai_find_node(c, a->mChannels[ch]->mNodeName.data);
        if (n >= 0 && c->joint_of[n] >= 0)
            tracks[c->joint_of[n]].na = a->mChannels[ch];
        else
            ignored++;
    }
    if (ignored)
        rf_ai_logf(c, 2, "%s: clip '%s': %u channels drive nodes outside the skeleton (ignored)",
                   c->path, a->mName.data, ignored);
    return true;
}

static void rf_ai_set_channels(rf_animation *anim, const rf_ai_track *tracks)
{
    for (uint32_t j = 0; j < anim->joint_count; j++) {
        const struct aiNodeAnim *na = tracks[j].na;
        if (!na)
            continue;
        if (na->mNumRotationKeys)
            anim->channels[j] |= RF_CHANNEL_ROTATION;
        if (na->mNumPositionKeys)
            anim->channels[j] |= RF_CHANNEL_TRANSLATION;
    }
}

static void rf_ai_fill_frames(rf_animation *anim, rf_ai_track *tracks, double tps, double end)
{
    for (uint32_t f = 0; f < anim->frame_count; f++) {
        double t = rf_ai_clamp(f / anim->fps * tps, 0, end);
        for (uint32_t j = 0; j < anim->joint_count; j++) {
            rf_xform x = rf_ai_sample(&tracks[j], t, end);
            /* Keep consecutive frames in one hemisphere so linear blends take the short way. */
            if (f > 0 && rf_quat_dot(x.r, rf_animation_rotation(anim, f - 1, j)) < 0)
                x.r = rf_quat_neg(x.r);
            rf_animation_set_rotation(anim, f, j, x.r);
            rf_animation_set_translation(anim, f, j, x.t);
        }
    }
}

static unsigned rf_ai_late_keys(const struct aiAnimation *a)
{
    unsigned late = 0;
    for (unsigned ch = 0; ch < a->mNumChannels; ch++) {
        const struct aiNodeAnim *na = a->mChannels[ch];
        for (unsigned k = 0; k < na->mNumPositionKeys; k++)
            late += na->mPositionKeys[k].mTime > a->mDuration || na->mPositionKeys[k].mTime < 0;
        for (unsigned k = 0; k < na->mNumRotationKeys; k++)
            late += na->mRotationKeys[k].mTime > a->mDuration || na->mRotationKeys[k].mTime < 0;
    }
    return late;
}

/* Without clips the animation is one frame of the rest pose, so exporters still have a frame. */
static bool rf_ai_rest_animation(rf_ai_ctx *c, const rf_skeleton *s, rf_animation **out)
{
    rf_animation *anim = rf_animation_new(s->joint_count, 1, RF_AI_DEFAULT_FPS);
    if (!anim || !(anim->name = rf_strdup("rest"))) {
        rf_animation_free(anim);
        return rf_ai_fail(c, "out of memory");
    }
    for (uint32_t j = 0; j < s->joint_count; j++) {
        rf_animation_set_rotation(anim, 0, j, s->joints[j].rest.r);
        rf_animation_set_translation(anim, 0, j, s->joints[j].rest.t);
    }
    *out = anim;
    return true;
}

bool rf_ai_build_animation(rf_ai_ctx *c, const rf_skeleton *s, int clip, const rf_ai_clip *info,
                           rf_animation **out)
{
    if (clip < 0)
        return rf_ai_rest_animation(c, s, out);
    const struct aiAnimation *a = c->scene->mAnimations[clip];
    /* Resampling makes frames x joints from a few keys: a clip a file says lasts years would ask
     * for more memory than the machine has. Refuse beyond half of it. */
    double need = (double)info->frames * (double)s->joint_count * 7 * sizeof(float);
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    double half = pages > 0 && page > 0 ? (double)pages * (double)page / 2 : 0;
    if (half > 0 && need > half)
        return rf_ai_fail(c,
                          "clip '%s' (%g s at %g fps: %u frames of %u joints) would take %.1f GB "
                          "of memory, more than half of this machine's %.1f GB: expected a "
                          "shorter clip",
                          info->name, info->duration, info->fps, info->frames, s->joint_count,
                          need / 1e9, 2 * half / 1e9);
    rf_animation *anim = rf_animation_new(s->joint_count, info->frames, info->fps);
    rf_ai_track *tracks = calloc(s->joint_count ? s->joint_count : 1, sizeof *tracks);
    if (!anim || !tracks || !(anim->name = rf_strdup(info->name))) {
        rf_animation_free(anim), free(tracks);
        return rf_ai_fail(c, "out of memory for %u frames of %u joints", info->frames,
                          s->joint_count);
    }
    unsigned late = rf_ai_late_keys(a);
    if (late)
        rf_ai_logf(c, 1, "%s: clip '%s': %u keys outside [0, %g] ticks clamped", c->path,
                   info->name, late, a->mDuration);
    double end = a->mDuration > 0 ? a->mDuration : 0;
    rf_ai_tracks(c, a, tracks);
    rf_ai_set_channels(anim, tracks);
    rf_ai_fill_frames(anim, tracks, rf_ai_tps(a), end);
    rf_ai_logf(c, 2, "%s: clip '%s': %g s at %g ticks/s, resampled to %u frames at %g fps", c->path,
               info->name, info->duration, rf_ai_tps(a), info->frames, info->fps);
    free(tracks);
    *out = anim;
    return true;
}
