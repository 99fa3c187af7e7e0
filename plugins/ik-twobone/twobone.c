/* Analytic two-bone IK (shoulder-elbow-wrist, hip-knee-ankle): closed form, one pass, exact.
 *
 * 1. Bend the middle joint so the root-to-effector distance equals the target distance (clamped
 *    to what the two bones can span). The effector turns on a circle about the bend axis through
 *    the middle joint; with r = root - mid and v = effector - mid, the wanted distance d gives
 *    r . v(theta) = (|r|^2 + |v|^2 - d^2) / 2, i.e. A cos(theta) + B sin(theta) = C, solved in
 *    closed form. With the axis normal to both bones this is the law of cosines; written this way
 *    it also serves a hinge whose axis is not normal to the bones.
 * 2. Swing the root so the effector lies on the line to the target.
 * 3. With a pole, turn the root about that line so the middle joint sits on the pole's side
 *    (rf_ikc_finish does this, for every solver).
 *
 * The bend axis is the middle joint's hinge axis when it has one, else the normal of the plane
 * the bones are in (or, for a straight chain, of the plane through the target and the pole).
 * Limits are kept by projecting each rotation into them, so a limited joint may leave the target
 * short rather than break its limit: there is no search inside the limits.
 */
#include <stdio.h>
#include <stdlib.h>

#include "twobone.h"

typedef struct twobone_state {
    rf_ikc_work w;
} twobone_state;

static rf_vec3 any_normal(rf_vec3 d)
{
    rf_vec3 n = rf_v3_cross(d, rf_v3(1, 0, 0));
    return rf_v3_len2(n) > 1e-12 * rf_v3_len2(d) ? n : rf_v3_cross(d, rf_v3(0, 0, 1));
}

/* The axis to bend the middle joint about (unit, problem space). */
static rf_vec3 bend_axis(rf_ikc_solve *s, const rf_ik_goal *g, uint32_t r, uint32_t m)
{
    const rf_ik_constraint *c = rf_ikc_constraint(s->pb, m);
    if (c && (c->flags & RF_IK_LIMIT_HINGE))
        return rf_ikc_hinge_axis_world(s, m);
    rf_vec3 R = s->w->world[r].t, M = s->w->world[m].t, E = s->w->world[g->effector].t;
    rf_vec3 n = rf_v3_cross(rf_v3_sub(M, R), rf_v3_sub(E, M));
    if (rf_v3_len2(n) > 1e-18 * rf_v3_len2(rf_v3_sub(E, R)) * rf_v3_len2(rf_v3_sub(E, R)))
        return rf_v3_normalize(n);
    /* Straight: bend in the plane of the bone and the pole (else the target). */
    rf_vec3 bone = rf_v3_sub(E, R), toward = rf_v3_sub(g->target, R);
    if (g->flags & RF_IK_GOAL_POLE)
        toward = rf_v3_sub(g->pole, R);
    n = rf_v3_cross(bone, toward);
    return rf_v3_normalize(
        rf_v3_len2(n) > 1e-18 * rf_v3_len2(bone) * rf_v3_len2(toward) ? n : any_normal(bone));
}

/* The turn about unit axis k through M that brings E to distance d from R, closest to no turn. */
static double bend_angle(rf_vec3 R, rf_vec3 M, rf_vec3 E, rf_vec3 k, double d)
{
    rf_vec3 r = rf_v3_sub(R, M), v = rf_v3_sub(E, M);
    rf_vec3 v_par = rf_v3_scale(k, rf_v3_dot(v, k)), v_perp = rf_v3_sub(v, v_par);
    double C = 0.5 * (rf_v3_len2(r) + rf_v3_len2(v) - d * d) - rf_v3_dot(r, v_par);
    double A = rf_v3_dot(r, v_perp), B = rf_v3_dot(r, rf_v3_cross(k, v_perp));
    double amp = hypot(A, B);
    if (!(amp > 1e-12 * (rf_v3_len2(r) + rf_v3_len2(v))))
        return 0; /* the effector's circle is centred on the root's axis: every angle is equal */
    double phi = atan2(B, A), cosv = fmax(-1.0, fmin(1.0, C / amp)), delta = acos(cosv);
    double t1 = remainder(phi + delta, 2 * RF_PI), t2 = remainder(phi - delta, 2 * RF_PI);
    return fabs(t1) <= fabs(t2) ? t1 : t2;
}

static void solve_goal(rf_ikc_solve *s, const rf_ik_goal *g)
{
    rf_ikc_work *w = s->w;
    uint32_t e = g->effector, m = (uint32_t)s->pb->parents[e], r = (uint32_t)s->pb->parents[m];
    rf_vec3 T = g->target;
    if (w->flags[m] & RF_IKC_MOVABLE) {
        rf_vec3 k = bend_axis(s, g, r, m);
        double angle = bend_angle(w->world[r].t, w->world[m].t, w->world[e].t, k,
                                  rf_v3_dist(T, w->world[r].t));
        rf_ikc_set_world_rot(s, m, rf_quat_mul(rf_quat_from_axis_angle(k, angle), w->world[m].r));
        rf_ikc_fk_joint(s, e);
    }
    if (!(w->flags[r] & RF_IKC_MOVABLE))
        return;
    rf_vec3 R = w->world[r].t;
    rf_quat aim = rf_quat_from_two_vectors(rf_v3_sub(w->world[e].t, R), rf_v3_sub(T, R));
    rf_ikc_set_world_rot(s, r, rf_quat_mul(aim, w->world[r].r));
    rf_ikc_fk_joint(s, m);
    rf_ikc_fk_joint(s, e);
}

/* Every goal's chain must be exactly two bones long (checked before anything is written). */
static bool check_shape(const rf_ik_problem *pb, rf_ik_result *res)
{
    for (uint32_t i = 0; i < pb->goal_count; i++) {
        const rf_ik_goal *g = rf_ikc_goal(pb, i);
        uint32_t bones = 0;
        for (int32_t j = (int32_t)g->effector; pb->parents[j] >= 0 && j != g->chain_root;
             j = pb->parents[j])
            bones++;
        if (bones != 2) {
            snprintf(res->message, sizeof res->message,
                     "goal %u: the two-bone solver needs a chain of 2 bones, this one has %u "
                     "(set chain_root to the effector's grandparent)",
                     i, bones);
            return false;
        }
    }
    return true;
}

static void *twobone_create(const rf_ik_config *cfg, char *err, size_t err_size)
{
    return rf_ikc_state_new(sizeof(twobone_state), cfg, err, err_size);
}

static bool twobone_solve(void *state, const rf_ik_problem *pb, rf_ik_result *res)
{
    twobone_state *st = state;
    rf_ikc_solve s;
    if (!rf_ikc_check(pb, res) || !check_shape(pb, res) || !rf_ikc_begin(&s, pb, res, &st->w))
        return false;
    uint32_t it = 0;
    if (pb->max_iterations > 0 && rf_ikc_errors(&s) > pb->tolerance) {
        for (uint32_t i = 0; i < s.goal_count; i++)
            solve_goal(&s, rf_ikc_goal(pb, i));
        it = 1;
    }
    rf_ikc_finish(&s, it);
    return true;
}

const rf_ik_solver_api rf_ik_twobone_api = {
    sizeof(rf_ik_solver_api),
    "twobone",
    "analytic two-bone IK (law of cosines) with a pole vector",
    RF_IK_LIMIT_HINGE | RF_IK_LIMIT_CONE | RF_IK_LIMIT_TWIST | RF_IK_LOCKED,
    RF_IK_CAP_ORIENTATION | RF_IK_CAP_POLE | RF_IK_CAP_TWO_BONE,
    twobone_create,
    twobone_solve,
    rf_ikc_state_free,
};
