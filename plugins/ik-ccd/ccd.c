/* Cyclic Coordinate Descent, the backward variant as Kenwright describes it: one iteration turns
 * each joint once, from the one nearest the effector up to the chain root, so that the line from
 * the joint to the effector points at the target; it stops as soon as the effector is within the
 * tolerance, even in the middle of a sweep.
 *
 * Limits are kept by projecting each joint's new rotation into its limits right after the turn
 * (hinge joints turn about their axis only: the effector and target directions are projected on
 * the hinge plane first). With several goals a joint shared by their chains turns by the weighted
 * mean of the rotations each goal wants (Hecker's averaging at branches).
 */
#include <stdlib.h>

#include "ccd.h"

typedef struct ccd_state {
    rf_ikc_work w;
} ccd_state;

/* The world rotation goal i asks of joint j (hinge: about its axis only). */
static rf_quat wanted_turn(rf_ikc_solve *s, uint32_t j, uint32_t i, const rf_vec3 *axis)
{
    rf_vec3 x = s->w->world[j].t;
    rf_vec3 u = rf_v3_sub(s->w->eff[i], x), v = rf_v3_sub(rf_ikc_goal(s->pb, i)->target, x);
    if (axis)
        return rf_quat_from_axis_angle(*axis, rf_ikc_angle_about(*axis, u, v));
    return rf_quat_from_two_vectors(u, v);
}

/* Weighted mean of the turns the goals below j ask for (a single goal: its turn). */
static rf_quat mean_turn(rf_ikc_solve *s, uint32_t j)
{
    const rf_ik_constraint *c = rf_ikc_constraint(s->pb, j);
    rf_vec3 axis;
    const rf_vec3 *hinge = NULL;
    if (c && (c->flags & RF_IK_LIMIT_HINGE))
        axis = rf_ikc_hinge_axis_world(s, j), hinge = &axis;
    rf_quat sum = rf_quat_make(0, 0, 0, 0);
    uint32_t count = 0;
    rf_quat only = rf_quat_identity();
    for (uint32_t i = 0; i < s->goal_count; i++) {
        const rf_ik_goal *g = rf_ikc_goal(s->pb, i);
        if (!(s->w->goals[j] & (1ull << i)) || g->effector == j)
            continue;
        rf_quat q = wanted_turn(s, j, i, hinge);
        if (rf_quat_dot(q, sum) < 0)
            q = rf_quat_neg(q);
        sum = rf_quat_make(sum.x + g->weight * q.x, sum.y + g->weight * q.y,
                           sum.z + g->weight * q.z, sum.w + g->weight * q.w);
        only = q, count++;
    }
    return count == 1 ? only : rf_quat_normalize(sum);
}

/* Turns joint j; moves the running effectors below it. Returns the angle turned. */
static double turn_joint(rf_ikc_solve *s, uint32_t j)
{
    rf_ikc_work *w = s->w;
    rf_quat before = w->world[j].r;
    rf_quat after = rf_ikc_set_world_rot(s, j, rf_quat_mul(mean_turn(s, j), before));
    rf_quat delta = rf_quat_mul(after, rf_quat_conj(before));
    rf_vec3 x = w->world[j].t;
    for (uint32_t i = 0; i < s->goal_count; i++)
        if ((w->goals[j] & (1ull << i)) && rf_ikc_goal(s->pb, i)->effector != j)
            w->eff[i] = rf_v3_add(x, rf_quat_rotate(delta, rf_v3_sub(w->eff[i], x)));
    return 2.0 * acos(fmin(1.0, fabs(delta.w)));
}

static bool within_tolerance(const rf_ikc_solve *s)
{
    double tol2 = s->pb->tolerance * s->pb->tolerance;
    for (uint32_t i = 0; i < s->goal_count; i++)
        if (rf_v3_len2(rf_v3_sub(s->w->eff[i], rf_ikc_goal(s->pb, i)->target)) > tol2)
            return false;
    return true;
}

static void load_effectors(rf_ikc_solve *s)
{
    for (uint32_t i = 0; i < s->goal_count; i++)
        s->w->eff[i] = s->w->world[rf_ikc_goal(s->pb, i)->effector].t;
}

static uint32_t ccd_iterate(rf_ikc_solve *s)
{
    load_effectors(s);
    if (within_tolerance(s))
        return 0;
    uint32_t it = 0;
    while (it < s->pb->max_iterations) {
        double largest = 0;
        bool done = false;
        it++;
        /* Ancestors keep their transforms while a joint turns (the sweep goes upwards), so
         * world[j] stays exact; only the effectors below are moved along. */
        for (uint32_t j = s->n; j-- > 0 && !done;) {
            if (!(s->w->flags[j] & RF_IKC_MOVABLE))
                continue;
            largest = fmax(largest, turn_joint(s, j));
            done = within_tolerance(s);
        }
        rf_ikc_fk(s); /* descendants of the turned joints */
        load_effectors(s);
        if (done || largest < 1e-10) /* reached, or nothing moves any more (unreachable) */
            break;
    }
    return it;
}

static void *ccd_create(const rf_ik_config *cfg, char *err, size_t err_size)
{
    return rf_ikc_state_new(sizeof(ccd_state), cfg, err, err_size);
}

static bool ccd_solve(void *state, const rf_ik_problem *pb, rf_ik_result *res)
{
    ccd_state *st = state;
    rf_ikc_solve s;
    if (!rf_ikc_begin(&s, pb, res, &st->w))
        return false;
    uint32_t it = s.goal_count ? ccd_iterate(&s) : 0;
    rf_ikc_finish(&s, it);
    return true;
}

const rf_ik_solver_api rf_ik_ccd_api = {
    sizeof(rf_ik_solver_api),
    "ccd",
    "Cyclic Coordinate Descent, backward sweep (Kenwright), limits by projection",
    RF_IK_LIMIT_HINGE | RF_IK_LIMIT_CONE | RF_IK_LIMIT_TWIST | RF_IK_LOCKED,
    RF_IK_CAP_MULTI_GOAL | RF_IK_CAP_ORIENTATION,
    ccd_create,
    ccd_solve,
    rf_ikc_state_free,
};
