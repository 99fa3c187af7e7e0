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

/* ---- a single free chain: the same sweeps, in world space ----
 * The chain's state is its joints' world positions (w->cpos), bone vectors (w->coff: from each
 * joint to the next) and world rotations (w->crot), by position along the chain. Every turn a
 * sweep makes is a world rotation about a joint, so positions and bone vectors can follow the
 * turns directly; local rotations are worked out once, at the end.
 *
 * A sweep is a chain of dependent square roots with time to spare between them, while carrying
 * its turns into the chain's state is much arithmetic with little waiting; and the next sweep
 * needs the new positions but not the new world rotations. So each sweep also applies the
 * rotations the previous one left pending (w->cpend), in that spare time. */

/* Applies the pending turns of chain joints [from, to). */
static void apply_pending(rf_ikc_work *w, uint32_t from, uint32_t to)
{
    for (uint32_t k = from; k < to; k++)
        w->crot[k] = rf_quat_mul(w->cpend[k], w->crot[k]);
}

/* One backward sweep over the chain; joints from `pending` on have a pending turn. Turning joint
 * k by the shortest rotation from u = E - X to v = T - X puts the effector on the ray towards
 * the target at its old distance, E = X + v |u| / |v|, so the sweep needs no rotation of E. Each
 * turn is kept unnormalised, q = (u x v, |u||v| + u.v), in w->turn, with 1 / |q|^2 in w->acc_w.
 * Returns true, with *first the last chain index turned, as soon as E is within tolerance;
 * *moved tells whether any joint turned by 2e-10 rad or more. */
static bool chain_sweep(rf_ikc_solve *s, uint32_t m, uint32_t pending, rf_vec3 *E, bool *moved,
                        uint32_t *first)
{
    rf_ikc_work *w = s->w;
    rf_vec3 T = rf_ikc_goal(s->pb, 0)->target;
    double tol2 = s->pb->tolerance * s->pb->tolerance;
    for (uint32_t k = m; k-- > 0;) {
        rf_vec3 X = w->cpos[k], u = rf_v3_sub(*E, X), v = rf_v3_sub(T, X);
        double lv = rf_v3_len2(v), uv = sqrt(rf_v3_len2(u) * lv), d = rf_v3_dot(u, v);
        rf_vec3 vs = rf_v3_scale(v, 1.0 / lv); /* independent of E: off the chain */
        rf_quat q = rf_quat_identity();
        double inv_qq = 1;
        if (uv > 1e-300) {
            if (d > -uv * (1 - 1e-12)) {
                rf_vec3 c = rf_v3_cross(u, v);
                q = rf_quat_make(c.x, c.y, c.z, uv + d);
                inv_qq = 1.0 / rf_quat_dot(q, q);
                /* sin^2 of half the angle, as the general form measures a turn: from the cross
                 * product, exact for tiny angles where 1 - cos (from uv - d) is all rounding */
                *moved = *moved || rf_v3_len2(c) * inv_qq >= 1e-20;
            } else {
                q = rf_quat_from_two_vectors(u, v); /* opposite: a unit half turn */
                *moved = true;
            }
            *E = rf_v3_add(X, rf_v3_scale(vs, uv));
        }
        w->turn[k] = q, w->acc_w[k] = inv_qq;
        if (k >= pending)
            w->crot[k] = rf_quat_mul(w->cpend[k], w->crot[k]);
        if (rf_v3_len2(rf_v3_sub(*E, T)) <= tol2) {
            apply_pending(w, pending, k);
            *first = k;
            return true;
        }
    }
    *first = 0;
    return false;
}

/* v turned by the rotation of q, which need not be unit, given 1 / |q|^2: q v q* / |q|^2 with
 * q = (c, w), that is ((w^2 - c.c) v + 2 (c.v) c + 2 w (c x v)) / |q|^2. No square root (the
 * positions, which the next sweep waits for, need none), and every term scales with |q|^2, so
 * it is as exact for small |q| as for unit ones. */
static inline rf_vec3 rotate_scaled(rf_quat q, double inv_qq, rf_vec3 v)
{
    rf_vec3 c = rf_v3(q.x, q.y, q.z), cxv = rf_v3_cross(c, v);
    double a = (q.w * q.w - rf_v3_len2(c)) * inv_qq, b = 2 * rf_v3_dot(c, v) * inv_qq;
    double k = 2 * q.w * inv_qq;
    return rf_v3(a * v.x + b * c.x + k * cxv.x, a * v.y + b * c.y + k * cxv.y,
                 a * v.z + b * c.z + k * cxv.z);
}

/* Carries the sweep's turns into the chain's positions, and leaves them pending for the world
 * rotations. Joint k's new world rotation is q_first ... q_k R_k: its own turn came first, then
 * each joint above it turned it along. So one running product Q serves the whole chain: it
 * turns the bone vectors (the positions follow) and, normalised, the world rotations. Its norm
 * is the product of the turns' norms, known from the sweep, so Q itself is normalised only when
 * its norm drifts far from 1 (long chains). */
static void chain_commit(rf_ikc_solve *s, uint32_t m, uint32_t first)
{
    rf_ikc_work *w = s->w;
    rf_quat Q = w->turn[first];
    double inv = w->acc_w[first]; /* 1 / |Q|^2 */
    for (uint32_t k = first; k < m; k++) {
        if (k > first)
            Q = rf_quat_mul(Q, w->turn[k]), inv *= w->acc_w[k];
        w->coff[k] = rotate_scaled(Q, inv, w->coff[k]);
        w->cpos[k + 1] = rf_v3_add(w->cpos[k], w->coff[k]);
        double n = sqrt(inv); /* for the world rotations, which the next sweep does not wait for */
        w->cpend[k] = rf_quat_make(Q.x * n, Q.y * n, Q.z * n, Q.w * n);
        if (!(inv > 1e-100 && inv < 1e100)) /* before it could overflow or underflow */
            Q = w->cpend[k], inv = 1;
    }
}

/* The local rotations of the chain from its world rotations. */
static void chain_locals(rf_ikc_solve *s, uint32_t m)
{
    rf_ikc_work *w = s->w;
    rf_quat parent = rf_ikc_parent_rot(s, s->chain[0]);
    for (uint32_t k = 0; k < m; k++) {
        rf_quat l = rf_quat_mul(rf_quat_conj(parent), w->crot[k]);
        double n = 1.0 / sqrt(rf_quat_dot(l, l));
        s->local[s->chain[k]].r = rf_quat_make(l.x * n, l.y * n, l.z * n, l.w * n);
        parent = w->crot[k];
    }
}

static uint32_t chain_iterate(rf_ikc_solve *s, uint32_t m)
{
    rf_ikc_work *w = s->w;
    const uint32_t *c = s->chain;
    rf_vec3 T = rf_ikc_goal(s->pb, 0)->target, E = w->cpos[m];
    if (rf_v3_len2(rf_v3_sub(E, T)) <= s->pb->tolerance * s->pb->tolerance)
        return 0;
    for (uint32_t k = 0; k < m; k++) {
        w->crot[k] = w->world[c[k]].r;
        w->coff[k] = rf_v3_sub(w->cpos[k + 1], w->cpos[k]);
    }
    uint32_t it = 0, first = m; /* m: nothing pending */
    while (it < s->pb->max_iterations) {
        bool moved = false;
        it++;
        bool done = chain_sweep(s, m, first, &E, &moved, &first);
        chain_commit(s, m, first);
        E = w->cpos[m];
        if (done || !moved) /* reached, or nothing turns any more (unreachable) */
            break;
    }
    if (it > 0) {
        apply_pending(w, first, m);
        chain_locals(s, m);
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
    if (!rf_ikc_start(&s, pb, res, &st->w))
        return false;
    if (rf_ikc_is_free_chain(&s)) {
        uint32_t m = rf_ikc_chain_begin(&s);
        rf_ikc_chain_finish(&s, m, chain_iterate(&s, m));
        return true;
    }
    rf_ikc_prepare(&s);
    rf_ikc_finish_current(&s, s.goal_count > 0 ? ccd_iterate(&s) : 0);
    return true;
}

const rf_ik_solver_api rf_ik_ccd_api = {
    sizeof(rf_ik_solver_api),
    "ccd",
    "Cyclic Coordinate Descent, backward sweep (Kenwright), limits by projection",
    RF_IK_LIMIT_HINGE | RF_IK_LIMIT_CONE | RF_IK_LIMIT_TWIST | RF_IK_LOCKED,
    RF_IK_CAP_MULTI_GOAL | RF_IK_CAP_ORIENTATION | RF_IK_CAP_POLE,
    ccd_create,
    ccd_solve,
    rf_ikc_state_free,
};
