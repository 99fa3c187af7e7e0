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
    return rf_ikc_turn(u, v);
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

/* Turns joint j; moves the running effectors below it. Returns sin^2 of half the angle turned
 * (a cheap monotonic measure of it). */
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
    return delta.x * delta.x + delta.y * delta.y + delta.z * delta.z; /* sin^2(angle / 2) */
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
        if (done || largest < 1e-20) /* reached, or nothing turns by 2e-10 rad any more */
            break;
    }
    return it;
}

/* ---- a single unconstrained chain: the same sweeps, in world space ---- */

/* One backward sweep over the chain (world transforms current). Turning joint k by the shortest
 * rotation from u = E - X to v = T - X puts the effector on the ray towards the target at its
 * old distance, E = X + v |u| / |v|, so the sweep needs no rotation of E; each turn is kept
 * unnormalised, (u x v, |u||v| + u.v), and normalised once when committed. Returns true, with
 * *first the last chain index turned, as soon as E is within tolerance; *moved tells whether
 * any joint turned by more than about 1e-10 rad. */
static bool chain_sweep(rf_ikc_solve *s, uint32_t m, rf_vec3 *E, bool *moved, uint32_t *first)
{
    rf_ikc_work *w = s->w;
    rf_vec3 T = rf_ikc_goal(s->pb, 0)->target;
    double tol2 = s->pb->tolerance * s->pb->tolerance;
    for (uint32_t k = m; k-- > 0;) {
        rf_vec3 X = w->world[w->chain[k]].t, u = rf_v3_sub(*E, X), v = rf_v3_sub(T, X);
        double lv = rf_v3_len2(v), uv = sqrt(rf_v3_len2(u) * lv), d = rf_v3_dot(u, v);
        rf_quat q = rf_quat_identity();
        if (uv > 1e-300) {
            rf_vec3 c = rf_v3_cross(u, v);
            q = d > -uv * (1 - 1e-12) ? rf_quat_make(c.x, c.y, c.z, uv + d)
                                      : rf_quat_from_two_vectors(u, v); /* opposite */
            *E = rf_v3_add(X, rf_v3_scale(v, uv / lv));
            *moved = *moved || uv - d > 1e-20 * uv;
        }
        w->turn[k] = q;
        if (rf_v3_len2(rf_v3_sub(*E, T)) <= tol2) {
            *first = k;
            return true;
        }
    }
    *first = 0;
    return false;
}

/* Folds the sweep's world turns into the local rotations and recomputes the chain's world
 * transforms. A joint's final world rotation is q_0 ... q_k R_k (every turn above it came later
 * and carried it along), so its local one is R_parent^-1 q_k R_k with the transforms from before
 * the sweep. */
static void chain_commit(rf_ikc_solve *s, uint32_t m, uint32_t first)
{
    rf_ikc_work *w = s->w;
    rf_quat parent_before = rf_ikc_parent_rot(s, w->chain[first]);
    for (uint32_t k = first; k < m; k++) {
        uint32_t j = w->chain[k];
        rf_quat before = w->world[j].r;
        rf_quat l = rf_quat_mul(rf_quat_conj(parent_before), rf_quat_mul(w->turn[k], before));
        double inv = 1.0 / sqrt(rf_quat_dot(l, l));
        s->local[j].r = rf_quat_make(l.x * inv, l.y * inv, l.z * inv, l.w * inv);
        parent_before = before;
    }
    for (uint32_t k = first; k <= m; k++)
        rf_ikc_fk_joint(s, w->chain[k]);
}

static uint32_t chain_iterate(rf_ikc_solve *s)
{
    uint32_t m = rf_ikc_collect_chain(s, 0), it = 0, first;
    rf_vec3 T = rf_ikc_goal(s->pb, 0)->target;
    rf_vec3 E = s->w->world[s->w->chain[m]].t;
    if (rf_v3_len2(rf_v3_sub(E, T)) <= s->pb->tolerance * s->pb->tolerance)
        return 0;
    while (it < s->pb->max_iterations) {
        bool moved = false;
        it++;
        bool done = chain_sweep(s, m, &E, &moved, &first);
        chain_commit(s, m, first);
        E = s->w->world[s->w->chain[m]].t;
        if (done || !moved) /* reached, or nothing turns any more (unreachable) */
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
    uint32_t it = 0;
    if (s.goal_count == 1 && !s.constrained && !s.branched)
        it = chain_iterate(&s);
    else if (s.goal_count > 0)
        it = ccd_iterate(&s);
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
