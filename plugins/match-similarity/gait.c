/* Forelegs on the ground driven by a two-legged source: the gait rule (doc/matching.md, "Forelegs
 * and a two-legged source").
 *
 * By homology a quadruped's forelegs take a human's arms, and the retargeter aligns directions:
 * a walk that holds its elbows bent folds the forelegs forward or lifts them level, and the
 * animal walks on its hind legs. Where the target's fore limbs are legs standing on the floor and
 * no source has fore limbs that reach it (arms only in the fore role, legs in the hind role), the
 * forelegs and their feet play the hind role instead: each takes the source's leg of its own
 * side, flagged RF_MAP_MIRROR (sampled half a cycle later), so the left fore steps with the
 * right hind, a trot. Decided from the analyses (section types, roles, heights), never from
 * names; `forelegs=arms` keeps the homology. */
#include <math.h>

#include "ms-internal.h"

/* The lowest point of section s and of the sections hanging from it (a foot, toes), along up,
 * over the analysis's ground, as a fraction of the body's height. */
static double section_low(const rf_analysis *a, uint32_t s)
{
    double low = INFINITY;
    for (uint32_t k = s; k < a->section_count; k++) { /* parents come before their children */
        int32_t p = (int32_t)k;
        while (p >= 0 && (uint32_t)p != s)
            p = a->sections[p].parent;
        if (p < 0)
            continue;
        const uint32_t *js = rf_section_joints(a, k);
        for (uint32_t i = 0; i < a->sections[k].bone_count; i++) {
            const rf_joint_info *j = &a->joints[js[i]];
            low = fmin(low, fmin(rf_v3_dot(j->pos, a->up), rf_v3_dot(j->tip, a->up)));
        }
    }
    return a->height > 0 ? (low - a->ground) / a->height : INFINITY;
}

/* A fore-role leg whose end stands on the floor at rest (within a tenth of the height). */
static bool foreleg_on_floor(const rf_ms_skel *t, uint32_t s)
{
    const rf_section *sec = &t->a->sections[s];
    return t->kind[s] == RF_MK_FORE && sec->type == RF_SECTION_LEG && section_low(t->a, s) < 0.1;
}

/* A source walks on two legs: its fore limbs (if any) are all arms, off the floor, and it has
 * hind legs. */
static bool two_legged(const rf_ms_skel *s)
{
    if (!(s->role_types[1] & 2) || (s->role_types[0] & 2))
        return false;
    for (uint32_t k = 0; k < s->a->section_count; k++)
        if (s->kind[k] == RF_MK_FORE && section_low(s->a, k) < 0.1)
            return false; /* an arm down on the floor: a body on all fours */
    return true;
}

uint32_t rf_ms_gait_setup(rf_ms_ctx *c)
{
    if (c->o->thesis || c->o->forelegs_arms)
        return 0;
    uint32_t enabled = 0;
    for (uint32_t k = 0; k < c->nsrc; k++) {
        if (c->o->disabled && c->o->disabled[k])
            continue;
        if (!two_legged(&c->src[k]))
            return 0;
        enabled++;
    }
    if (!enabled)
        return 0;
    const rf_analysis *a = c->tgt.a;
    uint32_t legs = 0;
    for (uint32_t s = 0; s < a->section_count; s++) { /* parents come before their children */
        int32_t p = a->sections[s].parent;
        bool digit =
            (a->sections[s].type == RF_SECTION_HAND || a->sections[s].type == RF_SECTION_FOOT) &&
            p >= 0 && c->gait[p];
        if (digit) {
            c->gait[s] = 1, c->tgt.kind[s] = RF_MK_HIND_DIGIT;
        } else if (foreleg_on_floor(&c->tgt, s)) {
            c->gait[s] = 1, c->tgt.kind[s] = RF_MK_HIND;
            legs++;
        }
    }
    return legs;
}
