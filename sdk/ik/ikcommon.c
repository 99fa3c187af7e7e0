/* Problem checking, the per-solve work area and result filling shared by the IK solvers. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rigflow/ik-common.h"

#define GROW(ptr, count) ((ptr) = realloc((ptr), (size_t)(count) * sizeof *(ptr)))

bool rf_ikc_work_reserve(rf_ikc_work *w, uint32_t joints, uint32_t goals)
{
    if (joints > w->cap_joints) {
        if (!GROW(w->world, joints) || !GROW(w->pos, joints) || !GROW(w->ref, joints) ||
            !GROW(w->bone_axis, joints) || !GROW(w->bone_len, joints) || !GROW(w->weight, joints) ||
            !GROW(w->driver, joints) || !GROW(w->rel, joints) || !GROW(w->first, joints) ||
            !GROW(w->next, joints) || !GROW(w->acc, joints) || !GROW(w->turn, joints) ||
            !GROW(w->acc_w, joints) || !GROW(w->goals, joints) || !GROW(w->flags, joints) ||
            !GROW(w->cpos, joints) || !GROW(w->coff, joints) || !GROW(w->crot, joints) ||
            !GROW(w->cpend, joints) || !GROW(w->clen, joints) || !GROW(w->plan_parents, joints) ||
            !GROW(w->plan_limits, joints) || !GROW(w->path, joints))
            return false; /* what did grow stays owned by w and is freed with it */
        w->cap_joints = joints;
    }
    if (goals > w->cap_goals) {
        if (!GROW(w->pivot, goals) || !GROW(w->reach, goals) || !GROW(w->err, goals) ||
            !GROW(w->eff, goals) || !GROW(w->plan_goal, 2 * (size_t)goals))
            return false;
        w->cap_goals = goals;
    }
    return true;
}

void rf_ikc_work_free(rf_ikc_work *w)
{
    free(w->world), free(w->pos), free(w->ref), free(w->bone_axis), free(w->bone_len);
    free(w->weight), free(w->driver), free(w->rel), free(w->first), free(w->next);
    free(w->acc), free(w->turn), free(w->acc_w), free(w->goals), free(w->flags);
    free(w->pivot), free(w->reach), free(w->err), free(w->eff);
    free(w->cpos), free(w->coff), free(w->crot), free(w->cpend), free(w->clen);
    free(w->plan_parents), free(w->plan_limits), free(w->plan_goal), free(w->path);
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

/* ---- checking ---- */

#define REFUSE(res, ...) (snprintf((res)->message, sizeof(res)->message, __VA_ARGS__), false)

static bool finite_xform(rf_xform x)
{
    /* One test for all ten: a NaN or infinity anywhere makes the sum one (an overflowing sum
     * of huge finite values is refused too, which no skeleton has). Runs per joint per solve. */
    double sum = x.t.x + x.t.y + x.t.z + x.r.x + x.r.y + x.r.z + x.r.w + x.s.x + x.s.y + x.s.z;
    return isfinite(sum) && x.s.x > 0 && x.s.y > 0 && x.s.z > 0;
}

/* Coordinates and scales beyond this are refused: the solvers square distances and multiply
 * squares, which would overflow to infinity and then to NaN. No skeleton comes near (1e30 metres
 * is far beyond the observable universe; in millimetres, a thousand times further still). */
#define MAX_COORD 1e30

static double max_abs(rf_vec3 v)
{
    return fmax(fabs(v.x), fmax(fabs(v.y), fabs(v.z)));
}

static bool is_ancestor_or_self(const int32_t *parents, int32_t a, int32_t j)
{
    while (j >= 0 && j != a)
        j = parents[j];
    return j == a;
}

/* With `known`, the parents are those of a plan, so checked already. */
static bool check_joints(const rf_ik_problem *pb, rf_ik_result *res, bool known)
{
    for (uint32_t j = 0; j < pb->joint_count; j++) {
        if (!known && (pb->parents[j] < -1 || pb->parents[j] >= (int32_t)j))
            return REFUSE(res, "joint %u: parent %d is not an earlier joint", j, pb->parents[j]);
        if (!finite_xform(pb->pose[j]))
            return REFUSE(res, "joint %u: start pose is not finite or has a scale <= 0", j);
    }
    return true;
}

static bool check_constraint(const rf_ik_constraint *c, uint32_t j, rf_ik_result *res)
{
    if (c->size < RF_IK_CONSTRAINT_SIZE_1_0)
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

/* With `known`, the effector and chain root are those of a plan, so checked already. */
static bool check_goal(const rf_ik_problem *pb, const rf_ik_goal *g, uint32_t i, rf_ik_result *res,
                       bool known)
{
    if (g->size < RF_IK_GOAL_SIZE_1_0)
        return REFUSE(res, "goal %u: size %u is too small", i, g->size);
    if (!known && g->effector >= pb->joint_count)
        return REFUSE(res, "goal %u: effector joint %u does not exist (the problem has %u joints)",
                      i, g->effector, pb->joint_count);
    if (!rf_v3_isfinite(g->target))
        return REFUSE(res, "goal %u: target (%g, %g, %g) is not finite", i, g->target.x,
                      g->target.y, g->target.z);
    if (!(max_abs(g->target) <= MAX_COORD))
        return REFUSE(res, "goal %u: target (%g, %g, %g) is out of range (coordinates up to %g)", i,
                      g->target.x, g->target.y, g->target.z, MAX_COORD);
    if (!(g->weight > 0) || !isfinite(g->weight))
        return REFUSE(res, "goal %u: weight %g must be a positive number", i, g->weight);
    if (!known && g->chain_root != -1 &&
        (g->chain_root < 0 || g->chain_root >= (int32_t)pb->joint_count ||
         !is_ancestor_or_self(pb->parents, g->chain_root, (int32_t)g->effector)))
        return REFUSE(res, "goal %u: chain_root %d is not an ancestor of effector %u", i,
                      g->chain_root, g->effector);
    if (!known && (g->chain_root == (int32_t)g->effector || pb->parents[g->effector] < 0))
        return REFUSE(res, "goal %u: effector %u has no joint above it to move", i, g->effector);
    rf_quat o = g->orientation;
    if ((g->flags & RF_IK_GOAL_ORIENTATION) &&
        (!isfinite(o.x + o.y + o.z + o.w) || rf_quat_dot(o, o) < 1e-12))
        return REFUSE(res, "goal %u: orientation is not a finite non-zero quaternion", i);
    if ((g->flags & RF_IK_GOAL_POLE) && !(max_abs(g->pole) <= MAX_COORD))
        return REFUSE(res, "goal %u: pole is not finite or out of range (coordinates up to %g)", i,
                      MAX_COORD);
    return true;
}

/* What every problem is checked for before its arrays are read. */
static bool check_header(const rf_ik_problem *pb, rf_ik_result *res)
{
    if (!res || res->size < RF_IK_RESULT_SIZE_1_0)
        return false; /* nowhere to say why */
    res->message[0] = '\0';
    if (!pb || pb->size < RF_IK_PROBLEM_SIZE_1_0)
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
    return true;
}

/* The rest of rf_ikc_check. With `known` (the structure is a plan's, so checked when the plan
 * was made) only values are checked, in the same order, so a problem is refused with the same
 * message either way; and constraints only when the plan has some. */
static bool check_body(const rf_ik_problem *pb, rf_ik_result *res, bool known, bool limited)
{
    if (!check_joints(pb, res, known))
        return false;
    for (uint32_t j = 0; pb->constraints && (!known || limited) && j < pb->joint_count; j++) {
        const rf_ik_constraint *c = rf_ikc_constraint(pb, j);
        if (c && !check_constraint(c, j, res))
            return false;
    }
    for (uint32_t i = 0; i < pb->goal_count; i++)
        if (!check_goal(pb, rf_ikc_goal(pb, i), i, res, known))
            return false;
    return true;
}

bool rf_ikc_check(const rf_ik_problem *pb, rf_ik_result *res)
{
    return check_header(pb, res) && check_body(pb, res, false, true);
}

/* ---- preparation ---- */

bool rf_ikc_fast_paths = true;

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

static uint32_t limit_flags(const rf_ik_problem *pb, uint32_t j)
{
    const rf_ik_constraint *c = rf_ikc_constraint(pb, j);
    return c ? c->flags : 0;
}

/* True when the problem has the structure the plan was made for: then every path, pivot and
 * driver is what the plan says. */
static bool plan_matches(const rf_ikc_work *w, const rf_ik_problem *pb)
{
    uint32_t n = pb->joint_count;
    if (w->plan_joints != n || w->plan_goals != pb->goal_count ||
        memcmp(w->plan_parents, pb->parents, n * sizeof *pb->parents) != 0)
        return false;
    for (uint32_t i = 0; i < pb->goal_count; i++) {
        const rf_ik_goal *g = rf_ikc_goal(pb, i);
        if (w->plan_goal[2 * i] != g->effector ||
            w->plan_goal[2 * i + 1] != (uint32_t)g->chain_root)
            return false;
    }
    if (!pb->constraints)
        return !w->plan_limited;
    for (uint32_t j = 0; j < n; j++)
        if (w->plan_limits[j] != limit_flags(pb, j))
            return false;
    return true;
}

/* Marks the path of goal i from its effector up to its pivot. */
static void mark_path(rf_ikc_solve *s, uint32_t i)
{
    const rf_ik_goal *g = rf_ikc_goal(s->pb, i);
    rf_ikc_work *w = s->w;
    int32_t j = (int32_t)g->effector;
    w->flags[j] |= RF_IKC_EFFECTOR | RF_IKC_ON_PATH;
    w->goals[j] |= 1ull << i;
    for (j = s->pb->parents[j]; j >= 0; j = s->pb->parents[j]) {
        w->flags[j] |= RF_IKC_ON_PATH;
        if (!(limit_flags(s->pb, (uint32_t)j) & RF_IK_LOCKED))
            w->flags[j] |= RF_IKC_MOVABLE;
        w->goals[j] |= 1ull << i;
        if (j == g->chain_root || s->pb->parents[j] < 0)
            break;
    }
    w->pivot[i] = (uint32_t)j;
}

/* Pivots, and the driver of every other path joint, with the lists of the joints each drives. */
static void link_drivers(rf_ikc_solve *s)
{
    rf_ikc_work *w = s->w;
    const int32_t *par = s->pb->parents;
    for (uint32_t j = 0; j < s->n; j++) {
        int32_t p = par[j];
        w->driver[j] = -1;
        if (!(w->flags[j] & RF_IKC_ON_PATH))
            continue;
        if (p < 0 || !(w->flags[p] & RF_IKC_ON_PATH) || (w->goals[p] & w->goals[j]) == 0) {
            w->flags[j] |= RF_IKC_PIVOT;
            continue;
        }
        w->driver[j] = (w->flags[p] & RF_IKC_MOVABLE) ? p : w->driver[p];
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

/* A single free chain's path: the effector's ancestors, root first, down to the effector. */
static void plan_free_chain(rf_ikc_solve *s)
{
    rf_ikc_work *w = s->w;
    w->path_bones = 0;
    if (s->goal_count != 1 || s->constrained || s->branched)
        return;
    uint32_t len = 0, above = 0;
    for (int32_t j = (int32_t)rf_ikc_goal(s->pb, 0)->effector; j >= 0; j = s->pb->parents[j])
        w->path[len++] = (uint32_t)j;
    for (uint32_t a = 0, b = len - 1; a < b; a++, b--) {
        uint32_t t = w->path[a];
        w->path[a] = w->path[b], w->path[b] = t;
    }
    while (w->path[above] != w->pivot[0])
        above++;
    w->path_above = above;
    w->path_bones = len - 1 - above;
}

/* Everything that follows from the problem's structure alone, remembered with the structure. */
static void build_plan(rf_ikc_solve *s)
{
    rf_ikc_work *w = s->w;
    const rf_ik_problem *pb = s->pb;
    w->plan_joints = 0; /* no plan while it is being made */
    for (uint32_t j = 0; j < s->n; j++)
        w->flags[j] = 0, w->goals[j] = 0;
    for (uint32_t i = 0; i < s->goal_count; i++)
        mark_path(s, i);
    link_drivers(s);
    count_branches(s);
    plan_free_chain(s);
    memcpy(w->plan_parents, pb->parents, s->n * sizeof *pb->parents);
    w->plan_limited = false;
    for (uint32_t j = 0; j < s->n; j++) {
        w->plan_limits[j] = limit_flags(pb, j);
        w->plan_limited = w->plan_limited || w->plan_limits[j];
    }
    for (uint32_t i = 0; i < s->goal_count; i++) {
        const rf_ik_goal *g = rf_ikc_goal(pb, i);
        w->plan_goal[2 * i] = g->effector;
        w->plan_goal[2 * i + 1] = (uint32_t)g->chain_root;
    }
    w->plan_constrained = s->constrained, w->plan_branched = s->branched;
    w->plan_goals = s->goal_count;
    w->plan_joints = s->n;
}

/* How far from the origin the start pose can put each joint, and its world scale: at most its
 * parent's distance plus its offset times the parent's largest scale (rotations keep lengths),
 * both refused beyond MAX_COORD. w->bone_len and w->weight serve as scratch (rf_ikc_prepare
 * fills them later). */
static bool check_extent(const rf_ik_problem *pb, rf_ik_result *res, rf_ikc_work *w)
{
    for (uint32_t j = 0; j < pb->joint_count; j++) {
        int32_t p = pb->parents[j];
        double scale = p < 0 ? 1 : w->weight[p], far = p < 0 ? 0 : w->bone_len[p];
        /* a vector is at most sqrt(3) times its largest component long */
        far += 1.7320508075688772 * max_abs(pb->pose[j].t) * scale;
        scale *= max_abs(pb->pose[j].s);
        if (!(far <= MAX_COORD && scale <= MAX_COORD))
            return REFUSE(res,
                          "joint %u: the start pose puts it up to %g from the origin at a scale of "
                          "%g (both are refused beyond %g)",
                          j, far, scale, MAX_COORD);
        w->bone_len[j] = far, w->weight[j] = scale;
    }
    return true;
}

bool rf_ikc_start(rf_ikc_solve *s, const rf_ik_problem *pb, rf_ik_result *res, rf_ikc_work *w)
{
    memset(s, 0, sizeof *s);
    if (!check_header(pb, res))
        return false;
    bool known = plan_matches(w, pb); /* then the work area is big enough too */
    if (!check_body(pb, res, known, w->plan_limited))
        return false;
    if (!known && !rf_ikc_work_reserve(w, pb->joint_count, pb->goal_count ? pb->goal_count : 1))
        return REFUSE(res, "out of memory for %u joints", pb->joint_count);
    if (!check_extent(pb, res, w))
        return false;
    s->pb = pb, s->res = res, s->local = res->pose, s->w = w;
    s->n = pb->joint_count, s->goal_count = pb->goal_count;
    for (uint32_t j = 0; j < s->n; j++) { /* one pass: may be in place */
        rf_xform x = pb->pose[j];
        x.r = unit(x.r);
        s->local[j] = x;
    }
    if (known)
        s->constrained = w->plan_constrained, s->branched = w->plan_branched;
    else
        build_plan(s);
    return true;
}

/* Weights, bone lengths, transforms relative to drivers and reach (world transforms current). */
static void measure_paths(rf_ikc_solve *s)
{
    rf_ikc_work *w = s->w;
    const int32_t *par = s->pb->parents;
    for (uint32_t j = 0; j < s->n; j++)
        w->weight[j] = 0;
    for (uint32_t i = 0; i < s->goal_count; i++) {
        double wt = rf_ikc_goal(s->pb, i)->weight;
        int32_t j = (int32_t)rf_ikc_goal(s->pb, i)->effector;
        for (; j != (int32_t)w->pivot[i]; j = par[j])
            w->weight[j] += wt;
        w->weight[j] += wt;
    }
    for (uint32_t j = 0; j < s->n; j++) {
        int32_t p = par[j];
        if (!(w->flags[j] & RF_IKC_ON_PATH))
            continue;
        w->bone_len[j] = p < 0 ? 0 : rf_v3_dist(w->world[j].t, w->world[p].t);
        if (w->driver[j] < 0)
            continue;
        bool direct = w->flags[p] & RF_IKC_MOVABLE;
        w->rel[j] = direct || w->driver[p] < 0 ? s->local[j] : rf_xform_mul(w->rel[p], s->local[j]);
    }
    for (uint32_t i = 0; i < s->goal_count; i++) {
        double reach = 0;
        for (int32_t j = (int32_t)rf_ikc_goal(s->pb, i)->effector; j != (int32_t)w->pivot[i];
             j = par[j])
            reach += w->bone_len[j];
        w->reach[i] = reach;
    }
}

void rf_ikc_prepare(rf_ikc_solve *s)
{
    const rf_ik_problem *pb = s->pb;
    rf_ikc_work *w = s->w;
    for (uint32_t j = 0; j < s->n; j++) {
        w->ref[j] = unit(pb->reference ? pb->reference[j].r : pb->pose[j].r);
        const rf_ik_constraint *c = rf_ikc_constraint(pb, j);
        if (c && (c->flags & (RF_IK_LIMIT_CONE | RF_IK_LIMIT_TWIST)))
            w->bone_axis[j] = bone_axis_of(s, j, c); /* only cone and twist use it */
    }
    rf_ikc_fk(s);
    measure_paths(s);
}

bool rf_ikc_begin(rf_ikc_solve *s, const rf_ik_problem *pb, rf_ik_result *res, rf_ikc_work *w)
{
    if (!rf_ikc_start(s, pb, res, w))
        return false;
    rf_ikc_prepare(s);
    return true;
}

/* ---- a single free chain ---- */

bool rf_ikc_is_free_chain(const rf_ikc_solve *s)
{
    /* a pole is met at the end, on world transforms the fast paths do not keep */
    return rf_ikc_fast_paths && s->w->path_bones > 0 &&
           !(rf_ikc_goal(s->pb, 0)->flags & RF_IK_GOAL_POLE);
}

uint32_t rf_ikc_chain_begin(rf_ikc_solve *s)
{
    rf_ikc_work *w = s->w;
    const uint32_t *c = w->path + w->path_above;
    uint32_t m = w->path_bones;
    for (uint32_t k = 0; k < w->path_above; k++)
        rf_ikc_fk_joint(s, w->path[k]);
    int32_t p = s->pb->parents[c[0]];
    rf_xform x = p < 0 ? s->local[c[0]] : rf_ikc_fk_step(&w->world[p], &s->local[c[0]]);
    for (uint32_t k = 0;; k++) { /* down the chain with the transform in registers */
        w->world[c[k]] = x, w->cpos[k] = x.t;
        if (k == m)
            break;
        x = rf_ikc_fk_step(&x, &s->local[c[k + 1]]);
    }
    double reach = 0; /* summed from the effector up, as measure_paths does */
    for (uint32_t k = m; k-- > 0;) {
        w->clen[k] = rf_v3_dist(w->cpos[k + 1], w->cpos[k]);
        reach += w->clen[k];
    }
    w->reach[0] = reach;
    s->chain = c;
    return m;
}

/* ---- kinematics ---- */

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

/* ---- poles ---- */

/* The joint that swivels goal i's chain: the highest movable joint of its path that no other
 * goal's path holds and above no other goal's effector, so that turning it about the line from
 * its origin to the effector moves this chain alone, and not the effector. -1 if none. */
static int32_t swivel_joint(const rf_ikc_solve *s, uint32_t i)
{
    const rf_ik_goal *g = rf_ikc_goal(s->pb, i);
    int32_t h = -1;
    for (int32_t j = s->pb->parents[g->effector]; j >= 0; j = s->pb->parents[j]) {
        if (s->w->goals[j] != 1ull << i)
            break;
        if (s->w->flags[j] & RF_IKC_MOVABLE)
            h = j;
        if ((uint32_t)j == s->w->pivot[i])
            break;
    }
    for (uint32_t k = 0; h >= 0 && k < s->goal_count; k++)
        if (k != i &&
            is_ancestor_or_self(s->pb->parents, h, (int32_t)rf_ikc_goal(s->pb, k)->effector))
            return -1;
    return h;
}

/* Turns goal i's chain about the line from its swivel joint to the effector, so that the
 * chain's bend (its inner joints' offsets from that line, summed; for two bones the middle
 * joint's) points at the pole. The effector is on the line, so it does not move, and nothing
 * but the swivel joint's rotation changes. Where that joint's limits do not allow the turn and
 * their projection would take the effector off its target, the turn is not made: a pole never
 * costs reach. World transforms current before and after. */
static void swivel_to_pole(rf_ikc_solve *s, uint32_t i)
{
    const rf_ik_goal *g = rf_ikc_goal(s->pb, i);
    int32_t h = swivel_joint(s, i);
    if (h < 0)
        return;
    rf_ikc_work *w = s->w;
    rf_vec3 H = w->world[h].t, axis = rf_v3_sub(w->world[g->effector].t, H), bend = {0, 0, 0};
    double size = w->reach[i]; /* the chain's length: what "straight" and "on the line" scale by */
    if (!(size > 0 && rf_v3_len2(axis) > 1e-24 * size * size))
        return;
    axis = rf_v3_normalize(axis);
    for (int32_t j = s->pb->parents[g->effector]; j != h; j = s->pb->parents[j])
        bend = rf_v3_add(bend, rf_v3_sub(w->world[j].t, H));
    /* both in units of the chain's length, as rf_ikc_angle_about's threshold takes them */
    double turn = rf_ikc_angle_about(axis, rf_v3_scale(bend, 1 / size),
                                     rf_v3_scale(rf_v3_sub(g->pole, H), 1 / size));
    if (turn == 0) /* a straight chain, or the pole on the line */
        return;
    double before = rf_v3_dist(w->world[g->effector].t, g->target);
    rf_quat keep = s->local[h].r;
    rf_ikc_set_world_rot(s, (uint32_t)h,
                         rf_quat_mul(rf_quat_from_axis_angle(axis, turn), w->world[h].r));
    rf_ikc_fk(s);
    double after = rf_v3_dist(w->world[g->effector].t, g->target);
    if (!(after <= fmax(before, s->pb->tolerance) * (1 + 1e-9))) { /* relative: any unit */
        s->local[h].r = keep;
        rf_ikc_fk(s);
    }
}

static void apply_poles(rf_ikc_solve *s)
{
    for (uint32_t i = 0; i < s->goal_count; i++)
        if (rf_ikc_goal(s->pb, i)->flags & RF_IK_GOAL_POLE)
            swivel_to_pole(s, i);
}

/* Rotation angle between two unit quaternions. atan2 of the difference's parts, not acos of the
 * dot product, which loses half the digits near zero. */
static double angle_between(rf_quat a, rf_quat b)
{
    rf_quat d = rf_quat_mul(rf_quat_conj(a), b);
    return 2 * atan2(sqrt(d.x * d.x + d.y * d.y + d.z * d.z), fabs(d.w));
}

/* Errors, status, max_error and reached from the current world transforms of the effectors and
 * pivots. */
static void report(rf_ikc_solve *s, uint32_t iterations)
{
    rf_ik_result *res = s->res;
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

void rf_ikc_finish_current(rf_ikc_solve *s, uint32_t iterations)
{
    apply_poles(s);
    if (apply_orientations(s))
        rf_ikc_fk(s); /* the turned effectors' descendants */
    report(s, iterations);
}

void rf_ikc_finish(rf_ikc_solve *s, uint32_t iterations)
{
    rf_ikc_fk(s);
    rf_ikc_finish_current(s, iterations);
}

void rf_ikc_chain_finish(rf_ikc_solve *s, uint32_t m, uint32_t iterations)
{
    const rf_ik_goal *g = rf_ikc_goal(s->pb, 0);
    if (!(g->flags & RF_IK_GOAL_ORIENTATION)) {
        /* The solvers leave the effector's position in w->cpos[m], as the solved rotations put
         * it to rounding: no forward kinematics just to measure the error. */
        s->w->world[g->effector].t = s->w->cpos[m];
    } else {
        for (uint32_t k = 0; k <= m; k++) /* the pivot's ancestors are current */
            rf_ikc_fk_joint(s, s->chain[k]);
        /* what rf_ikc_prepare would have set up for the effector's own limits */
        uint32_t e = g->effector;
        const rf_ik_constraint *c = rf_ikc_constraint(s->pb, e);
        s->w->ref[e] = unit(s->pb->reference ? s->pb->reference[e].r : s->pb->pose[e].r);
        if (c && (c->flags & (RF_IK_LIMIT_CONE | RF_IK_LIMIT_TWIST)))
            s->w->bone_axis[e] = bone_axis_of(s, e, c);
        apply_orientations(s);
    }
    report(s, iterations);
}
