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

/* Iterations without a new best error after which a solve gives up (an unreachable target, or
 * one the limits keep out of reach): 4, and more where joints have limits. Under limits the error
 * often stays flat for several iterations (a bone pressed against its cone or hinge stop) and
 * then falls again once the joints above have turned enough. Giving up after 4 there cost a
 * tenth of the converged targets (ik-bench it50-lim workloads, converged after 4 / 20 / never
 * giving up: chain10 89% / 99% / 99.3%, chain5 85% / 97%, tree2 61% / 71% / 72%). */
#define PATIENCE 4
#define LIMITED_PATIENCE 20

/* ---- a single free chain: positions only ---- */

/* Puts a point on the line from `from` towards `toward` at the bone's length. */
static inline rf_vec3 place(rf_vec3 from, rf_vec3 toward, double len)
{
    return rf_v3_add(from, rf_v3_scale(rf_v3_normalize(rf_v3_sub(toward, from)), len));
}

/* The factor that stretches a vector of squared length d2 to length len (0 for a zero vector, as
 * rf_v3_normalize gives): len / |d| as sqrt(d2) * (len / d2), so that the square root and the
 * division run side by side rather than one after the other. These placements, one after
 * another, are the solver's whole cost on long chains. */
static inline double stretch(double len, double d2)
{
    return d2 > 1e-300 ? sqrt(d2) * (len / d2) : 0;
}

/* place() for the iterations. */
static inline rf_vec3 place_fast(rf_vec3 from, rf_vec3 toward, double len)
{
    rf_vec3 d = rf_v3_sub(toward, from);
    return rf_v3_add(from, rf_v3_scale(d, stretch(len, rf_v3_len2(d))));
}

/* The iterations on the chain's positions p (w->cpos, pivot first) with bone lengths len.
 * The forward pass stops below the pivot, which the backward pass puts back anyway; and its
 * first placement, of p[m-1] from the target, is along the direction the last backward placement
 * of p[m] found from p[m-1] (negated), so each iteration normalises 2m - 2 directions, not 2m.
 * The running point stays in a register from one placement to the next. Iterations stop at the
 * tolerance, the cap, or after PATIENCE without improvement, as in the general form. */
static uint32_t chain_iterate(rf_ikc_solve *s, uint32_t m)
{
    rf_ikc_work *w = s->w;
    rf_vec3 *p = w->cpos, t = rf_ikc_goal(s->pb, 0)->target, base = p[0];
    const double *len = w->clen, last = w->clen[m - 1];
    double tol2 = s->pb->tolerance * s->pb->tolerance, best = rf_v3_dist(p[m], t);
    if (best * best <= tol2 || s->pb->max_iterations == 0)
        return 0;
    if (rf_v3_dist(base, t) >= w->reach[0]) { /* unreachable: the straight line, at once */
        for (uint32_t k = 0; k < m; k++)
            p[k + 1] = place(p[k], t, len[k]);
        return 1;
    }
    rf_vec3 d = rf_v3_sub(t, p[m - 1]); /* p[m] - p[m-1] as a backward pass would leave it */
    double f = stretch(last, rf_v3_len2(d));
    uint32_t it = 0, stalled = 0;
    while (it < s->pb->max_iterations) {
        rf_vec3 q = rf_v3_sub(t, rf_v3_scale(d, f)), top = q; /* forward, from the target */
        for (uint32_t k = m - 1; k-- > 1;)
            p[k] = q = place_fast(q, p[k], len[k]);
        q = base; /* backward, from the pivot (never moved); the forward pass's p[m-1] from a
                   * register, not from a store just made */
        for (uint32_t k = 0; k + 1 < m; k++)
            p[k + 1] = q = place_fast(q, k + 2 == m ? top : p[k + 1], len[k]);
        d = rf_v3_sub(t, q);
        double d2 = rf_v3_len2(d);
        f = stretch(last, d2);
        p[m] = rf_v3_add(q, rf_v3_scale(d, f));
        it++;
        /* the effector is on the line from p[m-1] to the target, |d| from it: off it by
         * | |d| - last | (by |d| when d is too short to have a direction) */
        double dl = sqrt(d2), miss = fabs(d2 > 1e-300 ? dl - last : dl);
        if (miss * miss <= tol2)
            break;
        stalled = miss < best * (1 - 1e-9) ? 0 : stalled + 1; /* relative: any unit */
        best = fmin(best, miss);
        if (stalled >= PATIENCE) /* a target the chain cannot reach though within its length */
            break;
    }
    return it;
}

/* Turns each chain joint, pivot first, by the minimal swing that points its bone (as the turns
 * above it have carried it) at the solved position of the next joint. Bone k turns from u (its
 * start direction in its parent's frame, w->acc[k], carried by the parent's new rotation) to
 * v = p[k+1] - p[k]. Both are as long as the bone, len, to rounding (rotations keep lengths,
 * placements put joints at the bone's length), so the turn is (u x v, len^2 + u.v) with no
 * square root for |u||v|; it is normalised by its own length, computed, so it is exactly unit
 * and rounding in len^2 cannot build up from one joint's rotation to the next. */
static void chain_to_rotations(rf_ikc_solve *s, uint32_t m)
{
    rf_ikc_work *w = s->w;
    const uint32_t *c = s->chain;
    for (uint32_t k = 0; k < m; k++) { /* independent of the turns: before the sequential part */
        rf_vec3 bone = rf_v3_mul(w->world[c[k]].s, s->local[c[k + 1]].t);
        w->acc[k] = rf_quat_rotate(s->local[c[k]].r, bone);
        w->coff[k] = rf_v3_sub(w->cpos[k + 1], w->cpos[k]);
    }
    rf_quat parent = rf_ikc_parent_rot(s, c[0]);
    for (uint32_t k = 0; k < m; k++) {
        uint32_t j = c[k];
        rf_quat r = rf_quat_mul(parent, s->local[j].r); /* j's world rotation, carried */
        rf_vec3 u = rf_quat_rotate(parent, w->acc[k]), v = w->coff[k];
        double uv = w->clen[k] * w->clen[k], d = rf_v3_dot(u, v);
        rf_quat turned = r; /* a bone of length 0 has no direction to turn */
        if (uv > 1e-300 && d > -uv * (1 - 1e-12)) {
            rf_vec3 x = rf_v3_cross(u, v);
            rf_quat q = rf_quat_make(x.x, x.y, x.z, uv + d);
            double h = rf_quat_dot(q, q), n = sqrt(h) * (1.0 / h); /* side by side */
            turned = rf_quat_mul(rf_quat_make(q.x * n, q.y * n, q.z * n, q.w * n), r);
        } else if (uv > 1e-300) {
            turned = rf_quat_mul(rf_quat_from_two_vectors(u, v), r); /* opposite */
        }
        s->local[j].r = rf_ikc_unit(rf_quat_mul(rf_quat_conj(parent), turned));
        parent = turned;
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
    if (!(amp > 1e-12 * rf_v3_len(want)))
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
    rf_vec3 u = rf_quat_rotate(rf_quat_mul(x.r, s->local[c].r), w->rel[w->first[c]].t);
    if (rf_v3_len2(d) == 0 || !(rf_v3_len2(want) > 1e-24 * rf_v3_len2(u))) /* u: c's bone */
        return;
    rf_vec3 a = rf_v3_normalize(rf_quat_rotate(rf_quat_mul(x.r, w->ref[c]), hc->axis));
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
    uint32_t it = 0, stalled = 0, patience = s->constrained ? LIMITED_PATIENCE : PATIENCE;
    while (err > tol && it < s->pb->max_iterations) {
        forward_pass(s);
        backward_pass(s);
        it++;
        err = rf_ikc_errors(s);
        /* Unreachable or limit-bound goals stop improving: no point in spending the cap. */
        stalled = err < best * (1 - 1e-9) ? 0 : stalled + 1; /* relative: any unit */
        if (err < best)
            best = err;
        if (stalled >= patience)
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
    if (!rf_ikc_start(&s, pb, res, &st->w))
        return false;
    if (rf_ikc_is_free_chain(&s)) {
        uint32_t m = rf_ikc_chain_begin(&s);
        uint32_t it = chain_iterate(&s, m);
        if (it > 0)
            chain_to_rotations(&s, m);
        rf_ikc_chain_finish(&s, m, it);
        return true;
    }
    rf_ikc_prepare(&s);
    uint32_t it = s.goal_count > 0 ? tree_iterate(&s) : 0;
    rf_ikc_finish_current(&s, it);
    return true;
}

const rf_ik_solver_api rf_ik_fabrik_api = {
    sizeof(rf_ik_solver_api),
    "fabrik",
    "FABRIK (Aristidou & Lasenby 2011): several effectors via sub-base centroids, limits",
    RF_IK_LIMIT_HINGE | RF_IK_LIMIT_CONE | RF_IK_LIMIT_TWIST | RF_IK_LOCKED,
    RF_IK_CAP_MULTI_GOAL | RF_IK_CAP_ORIENTATION | RF_IK_CAP_POLE,
    fabrik_create,
    fabrik_solve,
    rf_ikc_state_free,
};
