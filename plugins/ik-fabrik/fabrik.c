/* FABRIK: Forward And Backward Reaching Inverse Kinematics (Aristidou & Lasenby 2011), with
 * several end effectors and joint limits (Aristidou, Chrysanthou & Lasenby 2016).
 *
 * Each iteration moves joint positions, not angles. The forward pass places every effector on
 * its target and walks towards the pivots, putting each joint on the line to the joint below it
 * at the bone's length. Where branches meet (a sub-base), each branch proposes a position and the
 * joint goes to their centroid, weighted by the goals below each branch. The backward pass starts
 * again from the fixed pivots and walks out to the effectors.
 *
 * Two forms of the backward pass:
 *   - a single unconstrained chain is pure positions, as in the 2011 paper (including its
 *     closed-form straight chain for an unreachable target), turned into rotations once at the
 *     end;
 *   - otherwise the backward pass works on rotations: each joint turns (minimal swing, keeping
 *     its roll) so the path joints it drives point at their forward-pass positions, then the
 *     rotation is projected into its limits (hinge, cone, twist) and the next joints follow by
 *     forward kinematics. So limits hold exactly after every iteration, and rigid parts (locked
 *     joints, two arms fixed to one chest) stay rigid.
 * As in the 2016 paper, limits also act in the forward pass (forward_limit), and a joint that
 * drives a hinge rolls so that the hinge's plane holds its target direction (hinge_roll).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fabrik.h"

typedef struct fabrik_state {
    rf_ikc_work w;
} fabrik_state;

/* ---- a single unconstrained chain: positions only ---- */

/* Puts p[k+1] on the line from p[k] towards `toward` at the bone's length. */
static inline rf_vec3 place(rf_vec3 from, rf_vec3 toward, double len)
{
    return rf_v3_add(from, rf_v3_scale(rf_v3_normalize(rf_v3_sub(toward, from)), len));
}

static uint32_t chain_iterate(rf_ikc_solve *s, uint32_t m)
{
    rf_ikc_work *w = s->w;
    const uint32_t *c = w->chain;
    rf_vec3 *p = w->pos, t = rf_ikc_goal(s->pb, 0)->target, base;
    for (uint32_t k = 0; k <= m; k++)
        p[c[k]] = w->world[c[k]].t;
    base = p[c[0]];
    double tol2 = s->pb->tolerance * s->pb->tolerance;
    if (rf_v3_len2(rf_v3_sub(p[c[m]], t)) <= tol2 || s->pb->max_iterations == 0)
        return 0;
    if (rf_v3_dist(base, t) >= w->reach[0]) { /* unreachable: the straight line, at once */
        for (uint32_t k = 0; k < m; k++)
            p[c[k + 1]] = place(p[c[k]], t, w->bone_len[c[k + 1]]);
        return 1;
    }
    uint32_t it = 0;
    while (it < s->pb->max_iterations) {
        p[c[m]] = t; /* forward: effector on the target, towards the pivot */
        for (uint32_t k = m; k-- > 0;)
            p[c[k]] = place(p[c[k + 1]], p[c[k]], w->bone_len[c[k + 1]]);
        p[c[0]] = base; /* backward: pivot back in place, out to the effector */
        for (uint32_t k = 0; k < m; k++)
            p[c[k + 1]] = place(p[c[k]], p[c[k + 1]], w->bone_len[c[k + 1]]);
        it++;
        if (rf_v3_len2(rf_v3_sub(p[c[m]], t)) <= tol2)
            break;
    }
    return it;
}

/* Turns each chain joint, pivot first, so the next joint lands on its solved position. */
static void chain_to_rotations(rf_ikc_solve *s, uint32_t m)
{
    rf_ikc_work *w = s->w;
    for (uint32_t k = 0; k < m; k++) {
        uint32_t j = w->chain[k], c = w->chain[k + 1];
        rf_ikc_fk_joint(s, j);
        rf_ikc_fk_joint(s, c);
        rf_vec3 u = rf_v3_sub(w->world[c].t, w->world[j].t);
        rf_vec3 v = rf_v3_sub(w->pos[c], w->world[j].t);
        rf_ikc_set_world_rot(s, j, rf_quat_mul(rf_ikc_turn(u, v), w->world[j].r));
    }
}

/* ---- the general form: trees, limits, rigid parts ---- */

/* The forward pass's limits (Aristidou et al. 2016 constrain both passes): bone vector `bone`
 * from joint p to the joint it drives, turned into p's cone or hinge plane and range as seen from
 * p's parent's frame of the last backward pass (the only frame known this early). Twist has no
 * position to act on here; the backward pass keeps it. */
static rf_vec3 forward_limit(rf_ikc_solve *s, uint32_t p, rf_vec3 bone)
{
    const rf_ik_constraint *c = rf_ikc_constraint(s->pb, p);
    if (!c || (c->flags & RF_IK_LOCKED))
        return bone;
    double len = rf_v3_len(bone);
    rf_quat frame = rf_quat_mul(rf_ikc_parent_rot(s, p), s->w->ref[p]);
    rf_vec3 rest = rf_quat_rotate(frame, rf_v3_normalize(s->w->rel[s->w->first[p]].t));
    if (c->flags & RF_IK_LIMIT_HINGE) {
        rf_vec3 a = rf_v3_normalize(rf_quat_rotate(frame, c->axis));
        double angle = rf_ikc_angle_about(a, rest, bone);
        angle = fmax(c->min_angle, fmin(c->max_angle, angle));
        return rf_v3_scale(rf_quat_rotate(rf_quat_from_axis_angle(a, angle), rest), len);
    }
    if (!(c->flags & RF_IK_LIMIT_CONE) || rf_v3_angle(rest, bone) <= c->cone_angle)
        return bone;
    rf_vec3 axis = rf_v3_cross(rest, bone);
    return rf_v3_scale(rf_quat_rotate(rf_quat_from_axis_angle(axis, c->cone_angle), rest), len);
}

/* Forward pass: positions from the effectors towards the pivots, centroids at sub-bases. Each
 * path joint pushes its proposal for its parent into acc once its own position is final. */
static void forward_pass(rf_ikc_solve *s)
{
    rf_ikc_work *w = s->w;
    for (uint32_t j = 0; j < s->n; j++)
        w->acc[j] = rf_v3(0, 0, 0), w->acc_w[j] = 0;
    for (uint32_t i = 0; i < s->goal_count; i++) {
        const rf_ik_goal *g = rf_ikc_goal(s->pb, i);
        w->acc[g->effector] = rf_v3_add(w->acc[g->effector], rf_v3_scale(g->target, g->weight));
        w->acc_w[g->effector] += g->weight;
    }
    for (uint32_t j = s->n; j-- > 0;) {
        if (!(w->flags[j] & RF_IKC_ON_PATH))
            continue;
        if (w->driver[j] < 0 || !(w->acc_w[j] > 0)) {
            w->pos[j] = w->world[j].t; /* a pivot stays where it is */
            continue;
        }
        w->pos[j] = rf_v3_scale(w->acc[j], 1.0 / w->acc_w[j]);
        int32_t p = s->pb->parents[j];
        rf_vec3 proposal = place(w->pos[j], w->world[p].t, w->bone_len[j]);
        if (s->constrained && w->driver[j] == p && w->first[p] == (int32_t)j && w->next[j] < 0)
            proposal =
                rf_v3_sub(w->pos[j], forward_limit(s, (uint32_t)p, rf_v3_sub(w->pos[j], proposal)));
        w->acc[p] = rf_v3_add(w->acc[p], rf_v3_scale(proposal, w->weight[j]));
        w->acc_w[p] += w->weight[j];
    }
}

/* The rotation of movable joint j (world transform current) that best points the path joints it
 * drives at their forward-pass positions: the weighted mean of each one's minimal swing (or
 * hinge turn), which is exact for the usual single driven joint. */
static rf_quat aim_rotation(rf_ikc_solve *s, uint32_t j)
{
    rf_ikc_work *w = s->w;
    const rf_ik_constraint *con = rf_ikc_constraint(s->pb, j);
    bool hinge = con && (con->flags & RF_IK_LIMIT_HINGE);
    rf_vec3 axis = hinge ? rf_ikc_hinge_axis_world(s, j) : rf_v3(0, 0, 0);
    rf_xform x = w->world[j];
    rf_quat sum = rf_quat_make(0, 0, 0, 0);
    double angle = 0, wsum = 0;
    for (int32_t c = w->first[j]; c >= 0; c = w->next[c]) {
        rf_vec3 u = rf_v3_sub(rf_xform_point(x, w->rel[c].t), x.t);
        rf_vec3 v = rf_v3_sub(w->pos[c], x.t);
        double wc = w->weight[c];
        wsum += wc;
        if (hinge) {
            angle += wc * rf_ikc_angle_about(axis, u, v);
            continue;
        }
        rf_quat q = rf_ikc_turn(u, v);
        if (rf_quat_dot(q, sum) < 0)
            q = rf_quat_neg(q);
        sum = rf_quat_make(sum.x + wc * q.x, sum.y + wc * q.y, sum.z + wc * q.z, sum.w + wc * q.w);
    }
    rf_quat turn =
        hinge ? rf_quat_from_axis_angle(axis, wsum > 0 ? angle / wsum : 0) : rf_quat_normalize(sum);
    return rf_quat_mul(turn, x.r);
}

/* How far hinge angle `a` is outside [lo, hi] (0 inside). */
static double outside(double a, double lo, double hi)
{
    return a < lo ? lo - a : a > hi ? a - hi : 0;
}

/* The roll of j about its bone d, of the (up to) two that let c's bone (u, now) reach the
 * direction `want` by bending about c's hinge axis a, that leaves c's bend most within its range.
 * A bend keeps the bone's angle to the axis, so the roll must give a . want = |want| (a . u/|u|)
 * (0 for the usual axis normal to the bone: the bend plane then holds `want`). */
static double best_roll(rf_ikc_solve *s, uint32_t c, rf_vec3 d, rf_vec3 a, rf_vec3 u, rf_vec3 want)
{
    const rf_ik_constraint *hc = rf_ikc_constraint(s->pb, c);
    /* a rolled by phi about d: a_par + cos(phi) a_perp + sin(phi) d x a_perp */
    rf_vec3 a_par = rf_v3_scale(d, rf_v3_dot(a, d)), a_perp = rf_v3_sub(a, a_par);
    double A = rf_v3_dot(a_perp, want), B = rf_v3_dot(rf_v3_cross(d, a_perp), want);
    double C = rf_v3_dot(a_par, want) - rf_v3_len(want) * rf_v3_dot(a, rf_v3_normalize(u));
    double amp = hypot(A, B);
    if (amp < 1e-12)
        return 0;
    double phi = atan2(B, A), delta = acos(fmax(-1.0, fmin(1.0, -C / amp)));
    rf_quat q = rf_quat_normalize(rf_quat_mul(rf_quat_conj(s->w->ref[c]), s->local[c].r));
    double now = rf_ikc_twist_angle(q, rf_v3_normalize(hc->axis)), best = 0, cost = INFINITY;
    for (int k = 0; k < 2; k++) {
        double roll = remainder(phi + (k ? -delta : delta), 2 * RF_PI);
        rf_quat r = rf_quat_from_axis_angle(d, roll);
        double bend = now + rf_ikc_angle_about(rf_quat_rotate(r, a), rf_quat_rotate(r, u), want);
        double miss = outside(remainder(bend, 2 * RF_PI), hc->min_angle, hc->max_angle);
        if (miss < cost - 1e-12 || (fabs(miss - cost) <= 1e-12 && fabs(roll) < fabs(best)))
            cost = miss, best = roll;
    }
    return best;
}

/* A hinge bends only in its plane, and the joint above it decides where that plane lies by its
 * roll about its own bone, which aiming alone (a minimal swing) never changes. So when the one
 * joint j drives is a hinge, j also rolls (within its own limits) until the hinge's plane holds
 * the direction the hinge's bone should take. Aristidou et al. 2016 reorient joint frames for
 * hinges in the same spirit. j's world transform must be current. */
static void hinge_roll(rf_ikc_solve *s, uint32_t j)
{
    rf_ikc_work *w = s->w;
    int32_t c = w->first[j];
    if (c < 0 || w->next[c] >= 0 || s->pb->parents[c] != (int32_t)j || w->first[c] < 0 ||
        w->next[w->first[c]] >= 0 || !(w->flags[c] & RF_IKC_MOVABLE))
        return;
    const rf_ik_constraint *hc = rf_ikc_constraint(s->pb, (uint32_t)c);
    if (!hc || !(hc->flags & RF_IK_LIMIT_HINGE))
        return;
    rf_xform x = w->world[j];
    rf_vec3 Xc = rf_xform_point(x, w->rel[c].t), d = rf_v3_normalize(rf_v3_sub(Xc, x.t));
    rf_vec3 want = rf_v3_sub(w->pos[w->first[c]], Xc);
    if (rf_v3_len2(d) == 0 || rf_v3_len2(want) < 1e-24)
        return;
    rf_vec3 a = rf_v3_normalize(rf_quat_rotate(rf_quat_mul(x.r, w->ref[c]), hc->axis));
    rf_vec3 u = rf_quat_rotate(rf_quat_mul(x.r, s->local[c].r), w->rel[w->first[c]].t);
    double roll = best_roll(s, (uint32_t)c, d, a, u, want);
    if (roll != 0)
        rf_ikc_set_world_rot(s, j, rf_quat_mul(rf_quat_from_axis_angle(d, roll), x.r));
}

/* Backward pass: from the pivots outwards, rotations projected into the limits. Leaves every
 * world transform current. */
static void backward_pass(rf_ikc_solve *s)
{
    for (uint32_t j = 0; j < s->n; j++) {
        rf_ikc_fk_joint(s, j);
        if ((s->w->flags[j] & RF_IKC_MOVABLE) && s->w->first[j] >= 0) {
            rf_ikc_set_world_rot(s, j, aim_rotation(s, j));
            if (s->constrained)
                hinge_roll(s, j);
        }
    }
}

static uint32_t tree_iterate(rf_ikc_solve *s)
{
    double tol = s->pb->tolerance, err = rf_ikc_errors(s), best = err;
    uint32_t it = 0, stalled = 0;
    while (err > tol && it < s->pb->max_iterations) {
        forward_pass(s);
        backward_pass(s);
        it++;
        err = rf_ikc_errors(s);
        /* Unreachable or limit-bound goals stop improving: no point in spending the cap. */
        stalled = err < best - 1e-9 * (1 + best) ? 0 : stalled + 1;
        if (err < best)
            best = err;
        if (stalled >= 4)
            break;
    }
    return it;
}

/* ---- the solver table ---- */

static void *fabrik_create(const rf_ik_config *cfg, char *err, size_t err_size)
{
    return rf_ikc_state_new(sizeof(fabrik_state), cfg, err, err_size);
}

static bool fabrik_solve(void *state, const rf_ik_problem *pb, rf_ik_result *res)
{
    fabrik_state *st = state;
    rf_ikc_solve s;
    if (!rf_ikc_begin(&s, pb, res, &st->w))
        return false;
    uint32_t it = 0;
    if (s.goal_count == 1 && !s.constrained && !s.branched) {
        uint32_t m = rf_ikc_collect_chain(&s, 0);
        it = chain_iterate(&s, m);
        if (it > 0)
            chain_to_rotations(&s, m);
    } else if (s.goal_count > 0) {
        it = tree_iterate(&s);
    }
    rf_ikc_finish(&s, it);
    return true;
}

const rf_ik_solver_api rf_ik_fabrik_api = {
    sizeof(rf_ik_solver_api),
    "fabrik",
    "FABRIK (Aristidou & Lasenby 2011): several effectors via sub-base centroids, limits",
    RF_IK_LIMIT_HINGE | RF_IK_LIMIT_CONE | RF_IK_LIMIT_TWIST | RF_IK_LOCKED,
    RF_IK_CAP_MULTI_GOAL | RF_IK_CAP_ORIENTATION,
    fabrik_create,
    fabrik_solve,
    rf_ikc_state_free,
};
