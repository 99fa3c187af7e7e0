/* Problem checking, the per-solve work area and result filling shared by the IK solvers. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ikcommon.h"

#define GROW(ptr, count) ((ptr) = realloc((ptr), (size_t)(count) * sizeof *(ptr)))

bool rf_ikc_work_reserve(rf_ikc_work *w, uint32_t joints, uint32_t goals)
{
    if (joints > w->cap_joints) {
        if (!GROW(w->world, joints) || !GROW(w->pos, joints) || !GROW(w->ref, joints) ||
            !GROW(w->bone_axis, joints) || !GROW(w->bone_len, joints) || !GROW(w->weight, joints) ||
            !GROW(w->driver, joints) || !GROW(w->rel, joints) || !GROW(w->first, joints) ||
            !GROW(w->next, joints) || !GROW(w->chain, joints) || !GROW(w->acc, joints) ||
            !GROW(w->turn, joints) || !GROW(w->acc_w, joints) || !GROW(w->goals, joints) ||
            !GROW(w->flags, joints))
            return false; /* what did grow stays owned by w and is freed with it */
        w->cap_joints = joints;
    }
    if (goals > w->cap_goals) {
        if (!GROW(w->pivot, goals) || !GROW(w->reach, goals) || !GROW(w->err, goals) ||
            !GROW(w->eff, goals))
            return false;
        w->cap_goals = goals;
    }
    return true;
}

void rf_ikc_work_free(rf_ikc_work *w)
{
    free(w->world), free(w->pos), free(w->ref), free(w->bone_axis), free(w->bone_len);
    free(w->weight), free(w->driver), free(w->rel), free(w->first), free(w->next);
    free(w->chain), free(w->acc), free(w->turn), free(w->acc_w), free(w->goals), free(w->flags);
    free(w->pivot), free(w->reach), free(w->err), free(w->eff);
    memset(w, 0, sizeof *w);
}

uint32_t rf_ikc_config_joints(const rf_ik_config *cfg)
{
    return cfg && cfg->max_joints ? cfg->max_joints : 256;
}

uint32_t rf_ikc_config_goals(const rf_ik_config *cfg)
{
    return cfg && cfg->max_goals ? cfg->max_goals : 8;
}

void *rf_ikc_state_new(size_t size, const rf_ik_config *cfg, char *err, size_t err_size)
{
    rf_ikc_work *w = calloc(1, size);
    if (!w || !rf_ikc_work_reserve(w, rf_ikc_config_joints(cfg), rf_ikc_config_goals(cfg))) {
        rf_ikc_state_free(w);
        snprintf(err, err_size, "out of memory");
        return NULL;
    }
    return w;
}

void rf_ikc_state_free(void *state)
{
    if (!state)
        return;
    rf_ikc_work_free(state);
    free(state);
}

const rf_ik_goal *rf_ikc_goal(const rf_ik_problem *pb, uint32_t i)
{
    size_t stride = pb->goals[0].size;
    return (const rf_ik_goal *)((const char *)pb->goals + stride * i);
}

const rf_ik_constraint *rf_ikc_constraint(const rf_ik_problem *pb, uint32_t j)
{
    if (!pb->constraints)
        return NULL;
    size_t stride = pb->constraints[0].size;
    const rf_ik_constraint *c =
        (const rf_ik_constraint *)((const char *)pb->constraints + stride * j);
    return c->flags ? c : NULL;
}

/* ---- checking ---- */

#define REFUSE(res, ...) (snprintf((res)->message, sizeof(res)->message, __VA_ARGS__), false)

static bool finite_xform(rf_xform x)
{
    /* One test for all ten: a NaN or infinity anywhere makes the sum one (an overflowing sum
     * of huge finite values is refused too, which no skeleton has). Runs per joint per solve. */
    double sum = x.t.x + x.t.y + x.t.z + x.r.x + x.r.y + x.r.z + x.r.w + x.s.x + x.s.y + x.s.z;
    return isfinite(sum) && x.s.x > 0 && x.s.y > 0 && x.s.z > 0;
}

static bool is_ancestor_or_self(const int32_t *parents, int32_t a, int32_t j)
{
    while (j >= 0 && j != a)
        j = parents[j];
    return j == a;
}

static bool check_joints(const rf_ik_problem *pb, rf_ik_result *res)
{
    for (uint32_t j = 0; j < pb->joint_count; j++) {
        if (pb->parents[j] < -1 || pb->parents[j] >= (int32_t)j)
            return REFUSE(res, "joint %u: parent %d is not an earlier joint", j, pb->parents[j]);
        if (!finite_xform(pb->pose[j]))
            return REFUSE(res, "joint %u: start pose is not finite or has a scale <= 0", j);
    }
    return true;
}

static bool check_constraint(const rf_ik_constraint *c, uint32_t j, rf_ik_result *res)
{
    if (c->size < sizeof(rf_ik_constraint))
        return REFUSE(res, "joint %u: constraint size %u is too small", j, c->size);
    if ((c->flags & RF_IK_LIMIT_HINGE) && (c->flags & (RF_IK_LIMIT_CONE | RF_IK_LIMIT_TWIST)))
        return REFUSE(res, "joint %u: a hinge cannot also have cone or twist limits", j);
    if ((c->flags & RF_IK_LIMIT_HINGE) &&
        (!rf_v3_isfinite(c->axis) || rf_v3_len2(c->axis) == 0 || !(c->min_angle <= c->max_angle)))
        return REFUSE(res, "joint %u: hinge needs a non-zero axis and min_angle <= max_angle", j);
    if ((c->flags & RF_IK_LIMIT_CONE) && !(c->cone_angle >= 0 && c->cone_angle <= RF_PI))
        return REFUSE(res, "joint %u: cone_angle %g is not in [0, pi]", j, c->cone_angle);
    if ((c->flags & RF_IK_LIMIT_TWIST) && !(c->twist_min <= c->twist_max))
        return REFUSE(res, "joint %u: twist_min must be <= twist_max", j);
    if (!rf_v3_isfinite(c->bone_axis))
        return REFUSE(res, "joint %u: bone_axis is not finite", j);
    return true;
}

static bool check_goal(const rf_ik_problem *pb, const rf_ik_goal *g, uint32_t i, rf_ik_result *res)
{
    if (g->size < sizeof(rf_ik_goal))
        return REFUSE(res, "goal %u: size %u is too small", i, g->size);
    if (g->effector >= pb->joint_count)
        return REFUSE(res, "goal %u: effector joint %u does not exist (the problem has %u joints)",
                      i, g->effector, pb->joint_count);
    if (!rf_v3_isfinite(g->target))
        return REFUSE(res, "goal %u: target (%g, %g, %g) is not finite", i, g->target.x,
                      g->target.y, g->target.z);
    if (!(g->weight > 0) || !isfinite(g->weight))
        return REFUSE(res, "goal %u: weight %g must be a positive number", i, g->weight);
    if (g->chain_root != -1 &&
        (g->chain_root < 0 || g->chain_root >= (int32_t)pb->joint_count ||
         !is_ancestor_or_self(pb->parents, g->chain_root, (int32_t)g->effector)))
        return REFUSE(res, "goal %u: chain_root %d is not an ancestor of effector %u", i,
                      g->chain_root, g->effector);
    if (g->chain_root == (int32_t)g->effector || pb->parents[g->effector] < 0)
        return REFUSE(res, "goal %u: effector %u has no joint above it to move", i, g->effector);
    rf_quat o = g->orientation;
    if ((g->flags & RF_IK_GOAL_ORIENTATION) &&
        (!isfinite(o.x + o.y + o.z + o.w) || rf_quat_dot(o, o) < 1e-12))
        return REFUSE(res, "goal %u: orientation is not a finite non-zero quaternion", i);
    if ((g->flags & RF_IK_GOAL_POLE) && !rf_v3_isfinite(g->pole))
        return REFUSE(res, "goal %u: pole is not finite", i);
    return true;
}

bool rf_ikc_check(const rf_ik_problem *pb, rf_ik_result *res)
{
    if (!res || res->size < sizeof(rf_ik_result))
        return false; /* nowhere to say why */
    res->message[0] = '\0';
    if (!pb || pb->size < sizeof(rf_ik_problem))
        return REFUSE(res, "problem missing or its size is too small");
    if (pb->joint_count == 0 || !pb->parents || !pb->pose)
        return REFUSE(res, "problem has no joints (joint_count, parents and pose are required)");
    if (!res->pose)
        return REFUSE(res, "result->pose is NULL: the caller provides the output pose");
    if (pb->goal_count > 0 && !pb->goals)
        return REFUSE(res, "goal_count is %u but goals is NULL", pb->goal_count);
    if (pb->goal_count > RF_IKC_MAX_GOALS)
        return REFUSE(res, "%u goals: at most %d per problem", pb->goal_count, RF_IKC_MAX_GOALS);
    if (!(pb->tolerance > 0) || !isfinite(pb->tolerance))
        return REFUSE(res, "tolerance %g must be a positive number", pb->tolerance);
    if (!check_joints(pb, res))
        return false;
    for (uint32_t j = 0; pb->constraints && j < pb->joint_count; j++) {
        const rf_ik_constraint *c = rf_ikc_constraint(pb, j);
        if (c && !check_constraint(c, j, res))
            return false;
    }
    for (uint32_t i = 0; i < pb->goal_count; i++)
        if (!check_goal(pb, rf_ikc_goal(pb, i), i, res))
            return false;
    return true;
}

/* ---- preparation ---- */

/* q normalised, skipping the square root when it already is unit (the usual case). */
static rf_quat unit(rf_quat q)
{
    double n = rf_quat_dot(q, q);
    return fabs(n - 1) < 1e-14 ? q : rf_quat_normalize(q);
}

/* Unit bone axis of j in its reference frame: the constraint's, else the first child's offset
 * (children have higher indices), else +y. */
static rf_vec3 bone_axis_of(const rf_ikc_solve *s, uint32_t j, const rf_ik_constraint *c)
{
    if (c && rf_v3_len2(c->bone_axis) > 0)
        return rf_v3_normalize(c->bone_axis);
    for (uint32_t k = j + 1; k < s->n; k++)
        if (s->pb->parents[k] == (int32_t)j && rf_v3_len2(s->local[k].t) > 0)
            return rf_v3_normalize(s->local[k].t); /* the reference frame is j's own at q = 1 */
    return rf_v3(0, 1, 0);
}

/* Marks the path of goal i from its effector up to its pivot. */
static void mark_path(rf_ikc_solve *s, uint32_t i)
{
    const rf_ik_goal *g = rf_ikc_goal(s->pb, i);
    rf_ikc_work *w = s->w;
    int32_t j = (int32_t)g->effector;
    w->flags[j] |= RF_IKC_EFFECTOR | RF_IKC_ON_PATH;
    w->goals[j] |= 1ull << i;
    w->weight[j] += g->weight;
    for (j = s->pb->parents[j]; j >= 0; j = s->pb->parents[j]) {
        const rf_ik_constraint *c = rf_ikc_constraint(s->pb, (uint32_t)j);
        w->flags[j] |= RF_IKC_ON_PATH;
        if (!c || !(c->flags & RF_IK_LOCKED))
            w->flags[j] |= RF_IKC_MOVABLE;
        w->goals[j] |= 1ull << i;
        w->weight[j] += g->weight;
        if (j == g->chain_root || s->pb->parents[j] < 0)
            break;
    }
    w->pivot[i] = (uint32_t)j;
}

/* Drivers and transforms relative to them; pivots; bone lengths; reach per goal. */
static void prepare_paths(rf_ikc_solve *s)
{
    rf_ikc_work *w = s->w;
    const int32_t *par = s->pb->parents;
    for (uint32_t j = 0; j < s->n; j++) {
        int32_t p = par[j];
        bool on = w->flags[j] & RF_IKC_ON_PATH;
        w->driver[j] = -1;
        if (!on)
            continue;
        w->bone_len[j] = p < 0 ? 0 : rf_v3_dist(w->world[j].t, w->world[p].t);
        if (p < 0 || !(w->flags[p] & RF_IKC_ON_PATH) || (w->goals[p] & w->goals[j]) == 0) {
            w->flags[j] |= RF_IKC_PIVOT;
            continue;
        }
        bool direct = w->flags[p] & RF_IKC_MOVABLE;
        w->driver[j] = direct ? p : w->driver[p];
        w->rel[j] = direct || w->driver[p] < 0 ? s->local[j] : rf_xform_mul(w->rel[p], s->local[j]);
    }
    for (uint32_t j = 0; j < s->n; j++)
        w->first[j] = w->next[j] = -1;
    for (uint32_t c = s->n; c-- > 0;) { /* built backwards so each list is in index order */
        int32_t d = w->driver[c];
        if (d >= 0) {
            w->next[c] = w->first[d];
            w->first[d] = (int32_t)c;
        }
    }
    for (uint32_t i = 0; i < s->goal_count; i++) {
        double reach = 0;
        for (int32_t j = (int32_t)rf_ikc_goal(s->pb, i)->effector; j != (int32_t)w->pivot[i];
             j = par[j])
            reach += w->bone_len[j];
        w->reach[i] = reach;
    }
}

static void count_branches(rf_ikc_solve *s)
{
    rf_ikc_work *w = s->w;
    for (uint32_t j = 0; j < s->n; j++) {
        if ((w->flags[j] & RF_IKC_MOVABLE) && rf_ikc_constraint(s->pb, j))
            s->constrained = true;
        if (w->driver[j] >= 0 && (w->next[j] >= 0 || w->driver[j] != s->pb->parents[j]))
            s->branched = true; /* a driver with two joints, or a locked joint in between */
    }
}

bool rf_ikc_begin(rf_ikc_solve *s, const rf_ik_problem *pb, rf_ik_result *res, rf_ikc_work *w)
{
    memset(s, 0, sizeof *s);
    if (!rf_ikc_check(pb, res))
        return false;
    if (!rf_ikc_work_reserve(w, pb->joint_count, pb->goal_count ? pb->goal_count : 1))
        return REFUSE(res, "out of memory for %u joints", pb->joint_count);
    s->pb = pb, s->res = res, s->local = res->pose, s->w = w;
    s->n = pb->joint_count, s->goal_count = pb->goal_count;
    if (res->pose != pb->pose)
        memcpy(res->pose, pb->pose, s->n * sizeof *res->pose);
    for (uint32_t j = 0; j < s->n; j++) {
        w->ref[j] = unit(pb->reference ? pb->reference[j].r : pb->pose[j].r);
        s->local[j].r = unit(s->local[j].r);
        w->flags[j] = 0, w->goals[j] = 0, w->weight[j] = 0;
        const rf_ik_constraint *c = rf_ikc_constraint(pb, j);
        if (c && (c->flags & (RF_IK_LIMIT_CONE | RF_IK_LIMIT_TWIST)))
            w->bone_axis[j] = bone_axis_of(s, j, c); /* only cone and twist use it */
    }
    for (uint32_t i = 0; i < s->goal_count; i++)
        mark_path(s, i);
    rf_ikc_fk(s);
    prepare_paths(s);
    count_branches(s);
    return true;
}

/* ---- kinematics ---- */

uint32_t rf_ikc_collect_chain(rf_ikc_solve *s, uint32_t i)
{
    rf_ikc_work *w = s->w;
    uint32_t m = 0;
    for (int32_t j = (int32_t)rf_ikc_goal(s->pb, i)->effector; j != (int32_t)w->pivot[i];
         j = s->pb->parents[j])
        w->chain[m++] = (uint32_t)j;
    w->chain[m] = w->pivot[i];
    for (uint32_t a = 0, b = m; a < b; a++, b--) { /* reverse: pivot first */
        uint32_t t = w->chain[a];
        w->chain[a] = w->chain[b], w->chain[b] = t;
    }
    return m;
}

void rf_ikc_fk(rf_ikc_solve *s)
{
    for (uint32_t j = 0; j < s->n; j++)
        rf_ikc_fk_joint(s, j);
}

double rf_ikc_errors(rf_ikc_solve *s)
{
    double worst = 0;
    for (uint32_t i = 0; i < s->goal_count; i++) {
        const rf_ik_goal *g = rf_ikc_goal(s->pb, i);
        double e = rf_v3_dist(s->w->world[g->effector].t, g->target);
        s->w->err[i] = e;
        if (e > worst)
            worst = e;
    }
    return worst;
}

rf_quat rf_ikc_constrain_local(const rf_ikc_solve *s, uint32_t j, rf_quat local)
{
    const rf_ik_constraint *c = rf_ikc_constraint(s->pb, j);
    if (!c)
        return local;
    rf_quat ref = s->w->ref[j];
    rf_quat q = rf_ikc_project(c, s->w->bone_axis[j], rf_quat_mul(rf_quat_conj(ref), local));
    return rf_quat_normalize(rf_quat_mul(ref, q));
}

rf_quat rf_ikc_set_world_rot(rf_ikc_solve *s, uint32_t j, rf_quat world_rot)
{
    rf_quat pr = rf_ikc_parent_rot(s, j);
    rf_quat local = rf_quat_normalize(rf_quat_mul(rf_quat_conj(pr), world_rot));
    s->local[j].r = rf_ikc_constrain_local(s, j, local);
    rf_ikc_fk_rot(s, j);
    return s->w->world[j].r;
}

rf_vec3 rf_ikc_hinge_axis_world(const rf_ikc_solve *s, uint32_t j)
{
    const rf_ik_constraint *c = rf_ikc_constraint(s->pb, j);
    rf_quat frame = rf_quat_mul(rf_ikc_parent_rot(s, j), s->w->ref[j]);
    return rf_v3_normalize(rf_quat_rotate(frame, c->axis));
}

/* ---- results ---- */

/* The effector's own rotation carries an orientation goal: the chain above places it, the
 * effector turns to the asked rotation, within its own limits. */
static bool apply_orientations(rf_ikc_solve *s)
{
    bool any = false;
    for (uint32_t i = 0; i < s->goal_count; i++) {
        const rf_ik_goal *g = rf_ikc_goal(s->pb, i);
        if (!(g->flags & RF_IK_GOAL_ORIENTATION))
            continue;
        const rf_ik_constraint *c = rf_ikc_constraint(s->pb, g->effector);
        if (c && (c->flags & RF_IK_LOCKED))
            continue;
        rf_ikc_set_world_rot(s, g->effector, rf_quat_normalize(g->orientation));
        any = true;
    }
    return any;
}

/* Rotation angle between two unit quaternions. atan2 of the difference's parts, not acos of the
 * dot product, which loses half the digits near zero. */
static double angle_between(rf_quat a, rf_quat b)
{
    rf_quat d = rf_quat_mul(rf_quat_conj(a), b);
    return 2 * atan2(sqrt(d.x * d.x + d.y * d.y + d.z * d.z), fabs(d.w));
}

void rf_ikc_finish(rf_ikc_solve *s, uint32_t iterations)
{
    rf_ik_result *res = s->res;
    rf_ikc_fk(s);
    if (apply_orientations(s))
        rf_ikc_fk(s); /* the turned effectors' descendants */
    res->max_error = rf_ikc_errors(s);
    res->iterations = iterations;
    res->reached = true;
    for (uint32_t i = 0; i < s->goal_count; i++) {
        const rf_ik_goal *g = rf_ikc_goal(s->pb, i);
        double e = s->w->err[i];
        double from_pivot = rf_v3_dist(s->w->world[s->w->pivot[i]].t, g->target);
        uint32_t st = e <= s->pb->tolerance ? RF_IK_REACHED : 0;
        if (!st && from_pivot - s->w->reach[i] > s->pb->tolerance)
            st |= RF_IK_UNREACHABLE;
        if (!(st & RF_IK_REACHED))
            res->reached = false;
        if (res->errors)
            res->errors[i] = e;
        if (res->status)
            res->status[i] = st;
        if (res->angle_errors)
            res->angle_errors[i] =
                (g->flags & RF_IK_GOAL_ORIENTATION)
                    ? angle_between(s->w->world[g->effector].r, rf_quat_normalize(g->orientation))
                    : 0.0;
    }
}
