/* Poses other than the rest pose: recognising a rest pose that is no body, and viewing a
 * skeleton in a frame of its clip instead (see analysis.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rigflow/analysis.h"

/* The skeleton's leaves; UINT32_MAX when out of memory. */
static uint32_t leaf_count(const rf_skeleton *s)
{
    uint8_t *has_child = calloc(s->joint_count ? s->joint_count : 1, 1);
    if (!has_child)
        return UINT32_MAX;
    for (uint32_t j = 0; j < s->joint_count; j++) {
        int32_t p = s->joints[j].parent;
        if (p >= 0 && (uint32_t)p < s->joint_count)
            has_child[p] = 1;
    }
    uint32_t leaves = 0;
    for (uint32_t j = 0; j < s->joint_count; j++)
        leaves += !has_child[j];
    free(has_child);
    return leaves;
}

/* World pivots of the rest pose; parents come before children (bad parents count as roots).
 * NULL when out of memory. */
static rf_vec3 *rest_pivots(const rf_skeleton *s)
{
    rf_xform *world = malloc((s->joint_count ? s->joint_count : 1) * sizeof *world);
    rf_vec3 *pos = malloc((s->joint_count ? s->joint_count : 1) * sizeof *pos);
    if (!world || !pos) { /* pivots never computed must not be read as a pose */
        free(world), free(pos);
        return NULL;
    }
    for (uint32_t j = 0; j < s->joint_count; j++) {
        int32_t p = s->joints[j].parent;
        bool ok = p >= 0 && (uint32_t)p < j;
        world[j] = ok ? rf_xform_mul(world[p], s->joints[j].rest) : s->joints[j].rest;
        pos[j] = world[j].t;
    }
    free(world);
    return pos;
}

/* A bone from a root is a placement (the hips' height above the origin), not part of the body:
 * the line is fitted to the joints below the roots and to the bones between them. */
static bool in_body(const rf_skeleton *s, uint32_t j)
{
    int32_t p = s->joints[j].parent;
    return p >= 0 && (uint32_t)p < j;
}

bool rf_pose_degenerate_check(const rf_skeleton *s, bool *degenerate)
{
    *degenerate = false;
    if (!s || s->joint_count < 4)
        return true;
    uint32_t leaves = leaf_count(s);
    if (leaves == UINT32_MAX)
        return false;
    if (leaves < 3)
        return true;
    rf_vec3 *pos = rest_pivots(s);
    if (!pos)
        return false;
    /* The line: through the centroid along the longest bone (on a degenerate pose every bone
     * lies on it; on a body no line fits, whichever is tried). */
    rf_vec3 c = rf_v3(0, 0, 0), axis = rf_v3(0, 0, 0);
    double longest = 0, count = 0;
    for (uint32_t j = 0; j < s->joint_count; j++) {
        if (!in_body(s, j))
            continue;
        c = rf_v3_add(c, pos[j]), count++;
        int32_t p = s->joints[j].parent;
        double len = in_body(s, (uint32_t)p) ? rf_v3_dist(pos[j], pos[p]) : 0;
        if (len > longest)
            longest = len, axis = rf_v3_scale(rf_v3_sub(pos[j], pos[p]), 1.0 / len);
    }
    c = rf_v3_scale(c, count > 0 ? 1.0 / count : 0);
    double off2 = 0, lo = INFINITY, hi = -INFINITY;
    for (uint32_t j = 0; j < s->joint_count; j++) {
        if (!in_body(s, j))
            continue;
        rf_vec3 d = rf_v3_sub(pos[j], c);
        double along = rf_v3_dot(d, axis);
        off2 += rf_v3_len2(rf_v3_sub(d, rf_v3_scale(axis, along))) / count;
        lo = fmin(lo, along), hi = fmax(hi, along);
    }
    free(pos);
    *degenerate = longest > 0 && isfinite(off2) && sqrt(off2) < 0.03 * (hi - lo);
    return true;
}

bool rf_pose_degenerate(const rf_skeleton *s)
{
    bool degenerate;
    return rf_pose_degenerate_check(s, &degenerate) && degenerate;
}

rf_skeleton *rf_posed_view(const rf_skeleton *s, const rf_animation *anim, uint32_t frame)
{
    if (!s || !anim || anim->joint_count != s->joint_count || anim->frame_count == 0)
        return NULL;
    rf_skeleton *v = malloc(sizeof *v);
    rf_joint *joints = malloc((s->joint_count ? s->joint_count : 1) * sizeof *joints);
    if (!v || !joints) {
        free(v);
        free(joints);
        return NULL;
    }
    *v = *s;
    memcpy(joints, s->joints, s->joint_count * sizeof *joints);
    if (frame >= anim->frame_count)
        frame = anim->frame_count - 1;
    const float *r = anim->rotations + (size_t)frame * s->joint_count * 4;
    const float *t = anim->translations + (size_t)frame * s->joint_count * 3;
    for (uint32_t j = 0; j < s->joint_count; j++) {
        joints[j].rest.t = rf_v3(t[3 * j], t[3 * j + 1], t[3 * j + 2]);
        joints[j].rest.r =
            rf_quat_normalize(rf_quat_make(r[4 * j], r[4 * j + 1], r[4 * j + 2], r[4 * j + 3]));
    }
    v->joints = joints;
    if (RF_HAS_FIELD(s, rf_skeleton, bind))
        v->bind = NULL; /* analyse this pose, not the skin's */
    return v;
}

void rf_posed_free(rf_skeleton *view)
{
    if (!view)
        return;
    free(view->joints);
    free(view);
}

/* How well a pose shows the body: the joints in limbs that mirror a limb of as many bones, into
 * *pairs. False when out of memory (a pose not analysed would score as no body at all). */
static bool pose_score(const rf_skeleton *view, uint32_t *pairs)
{
    rf_analysis *a = rf_analyze(view, NULL);
    *pairs = 0;
    for (uint32_t k = 0; a && k < a->section_count; k++) {
        const rf_section *sec = &a->sections[k];
        if (sec->mirror >= 0 && a->sections[sec->mirror].bone_count == sec->bone_count)
            *pairs += sec->bone_count;
    }
    rf_analysis_free(a);
    return a != NULL;
}

rf_skeleton *rf_posed_best(const rf_skeleton *s, const rf_animation *anim, int32_t *frame)
{
    *frame = -1;
    rf_skeleton *best = rf_posed_mean(s, anim);
    uint32_t best_score, score;
    if (!best || !pose_score(best, &best_score)) {
        rf_posed_free(best);
        return NULL;
    }
    uint32_t samples = anim->frame_count < 16 ? anim->frame_count : 16;
    for (uint32_t i = 0; i < samples; i++) {
        uint32_t f = (uint32_t)((uint64_t)i * anim->frame_count / samples);
        /* the clip fits (the mean pose was made): a view not made, or not scored, is out of
         * memory, and the best of the others would be another pose */
        rf_skeleton *v = rf_posed_view(s, anim, f);
        if (!v || !pose_score(v, &score)) {
            rf_posed_free(v), rf_posed_free(best);
            *frame = -1;
            return NULL;
        }
        if (score > best_score) {
            rf_posed_free(best);
            best = v, best_score = score, *frame = (int32_t)f;
        } else {
            rf_posed_free(v);
        }
    }
    return best;
}

rf_skeleton *rf_posed_mean(const rf_skeleton *s, const rf_animation *anim)
{
    rf_skeleton *v = rf_posed_view(s, anim, 0);
    if (!v)
        return NULL;
    uint32_t n = s->joint_count;
    for (uint32_t j = 0; j < n; j++) {
        rf_quat first = v->joints[j].rest.r, sum = rf_quat_make(0, 0, 0, 0);
        rf_vec3 t = rf_v3(0, 0, 0);
        for (uint32_t f = 0; f < anim->frame_count; f++) {
            const float *r = anim->rotations + ((size_t)f * n + j) * 4;
            const float *x = anim->translations + ((size_t)f * n + j) * 3;
            rf_quat q = rf_quat_make(r[0], r[1], r[2], r[3]);
            if (rf_quat_dot(q, first) < 0) /* q and -q are one rotation: sum one hemisphere */
                q = rf_quat_neg(q);
            sum = rf_quat_make(sum.x + q.x, sum.y + q.y, sum.z + q.z, sum.w + q.w);
            t = rf_v3_add(t, rf_v3(x[0], x[1], x[2]));
        }
        if (rf_quat_dot(sum, sum) > 1e-24)
            v->joints[j].rest.r = rf_quat_normalize(sum);
        v->joints[j].rest.t = rf_v3_scale(t, 1.0 / anim->frame_count);
    }
    return v;
}
