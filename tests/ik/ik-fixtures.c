#include <math.h>
#include <string.h>

#include "ik-fixtures.h"

static void reset(fx_problem *f, uint32_t n)
{
    memset(f, 0, sizeof *f);
    f->n = n;
    for (uint32_t j = 0; j < n; j++) {
        f->parents[j] = (int32_t)j - 1;
        f->pose[j] = rf_xform_identity();
        f->limits[j].size = sizeof f->limits[j];
    }
}

void fx_chain(fx_problem *f, uint32_t links)
{
    reset(f, links + 1);
    for (uint32_t j = 1; j <= links; j++)
        f->pose[j].t = rf_v3(0, 1, 0);
    f->goals[0] = rf_ik_goal_make(links, rf_v3(0, (double)links, 0));
}

void fx_chain_lengths(fx_problem *f, const double *lengths, uint32_t links)
{
    reset(f, links + 1);
    for (uint32_t j = 1; j <= links; j++)
        f->pose[j].t = rf_v3(lengths[j - 1], 0, 0);
    f->goals[0] = rf_ik_goal_make(links, rf_v3(0, 0, 0));
}

void fx_tree(fx_problem *f)
{
    reset(f, 12);
    for (uint32_t j = 1; j < 12; j++)
        f->pose[j].t = rf_v3(0, 1, 0);
    f->parents[4] = 3, f->pose[4].t = rf_v3(1, 0, 0);
    f->parents[8] = 3, f->pose[8].t = rf_v3(-1, 0, 0);
    f->limits[3].flags = RF_IK_LOCKED; /* the chest: both arms hang off it rigidly */
    f->goals[0] = rf_ik_goal_make(7, rf_v3(1, 6, 0));
    f->goals[1] = rf_ik_goal_make(11, rf_v3(-1, 6, 0));
}

void fx_wire(fx_problem *f, uint32_t goals, double tol, uint32_t max_iterations)
{
    f->pb = (rf_ik_problem){sizeof f->pb, f->n,  f->parents, f->pose, NULL,
                            f->limits,    goals, f->goals,   tol,     max_iterations};
    memset(&f->res, 0, sizeof f->res);
    f->res.size = sizeof f->res;
    f->res.pose = f->out;
    f->res.errors = f->errors;
    f->res.angle_errors = f->angle_errors;
    f->res.status = f->status;
}

void fx_world(const fx_problem *f, rf_vec3 *pos, rf_quat *rot)
{
    rf_xform w[FX_MAX_JOINTS];
    for (uint32_t j = 0; j < f->n; j++) {
        int32_t p = f->parents[j];
        w[j] = p < 0 ? f->out[j] : rf_xform_mul(w[p], f->out[j]);
        if (pos)
            pos[j] = w[j].t;
        if (rot)
            rot[j] = w[j].r;
    }
}

double fx_rnd(fx_lcg *g)
{
    g->seed = g->seed * 1664525u + 1013904223u;
    return g->seed / 4294967296.0;
}

rf_vec3 fx_target(fx_lcg *g, double reach)
{
    double x, y, z;
    do {
        x = 2 * fx_rnd(g) - 1, y = 2 * fx_rnd(g) - 1, z = 2 * fx_rnd(g) - 1;
    } while (x * x + y * y + z * z > 1);
    double l = sqrt(x * x + y * y + z * z), r = reach * (0.2 + 0.7 * fx_rnd(g));
    return rf_v3(x / l * r, y / l * r, z / l * r);
}

static double excess(double a, double lo, double hi)
{
    return a < lo ? lo - a : a > hi ? a - hi : 0;
}

/* Twist about unit axis a of a unit quaternion: twice the angle of (a . v, w), wrapped. */
static double twist_of(rf_quat q, rf_vec3 a)
{
    double t = 2 * atan2(q.x * a.x + q.y * a.y + q.z * a.z, q.w);
    return t > RF_PI ? t - 2 * RF_PI : t <= -RF_PI ? t + 2 * RF_PI : t;
}

double fx_limit_violation(const rf_ik_constraint *c, rf_vec3 bone_axis, rf_quat ref, rf_quat local)
{
    rf_quat q = rf_quat_normalize(rf_quat_mul(rf_quat_conj(ref), local));
    double worst = 0;
    if (c->flags & RF_IK_LIMIT_HINGE) {
        rf_vec3 a = rf_v3_normalize(c->axis);
        rf_vec3 v = rf_v3(q.x, q.y, q.z);
        /* a pure hinge turn has its vector part along the axis */
        double off_axis = rf_v3_len(rf_v3_sub(v, rf_v3_scale(a, rf_v3_dot(v, a))));
        worst = fmax(worst, 2 * asin(fmin(1, off_axis)));
        worst = fmax(worst, excess(twist_of(q, a), c->min_angle, c->max_angle));
    }
    if (c->flags & RF_IK_LIMIT_CONE) {
        rf_vec3 turned = rf_quat_rotate(q, bone_axis);
        worst = fmax(worst, excess(rf_v3_angle(bone_axis, turned), 0, c->cone_angle));
    }
    if (c->flags & RF_IK_LIMIT_TWIST)
        worst = fmax(worst, excess(twist_of(q, bone_axis), c->twist_min, c->twist_max));
    if (c->flags & RF_IK_LOCKED)
        worst = fmax(worst, rf_quat_angle(ref, local));
    return worst;
}
