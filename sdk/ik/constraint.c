/* Joint limits as projections of a relative rotation q (reference^-1 * local) onto the allowed
 * set, so that every solver can enforce them the same way after it moves a joint.
 *
 * Cone and twist use the swing-twist split about the bone axis d: q = swing * twist, twist a
 * rotation about d, swing a rotation about an axis normal to d. The swing angle is the angle the
 * bone turns away from its reference direction (the cone limit), the twist angle the roll about
 * the bone (the twist limit); Aristidou et al. 2016 bound the same two quantities.
 */
#include "rigflow/ik-common.h"

static double wrap_angle(double a)
{
    while (a > RF_PI)
        a -= 2 * RF_PI;
    while (a <= -RF_PI)
        a += 2 * RF_PI;
    return a;
}

double rf_ikc_twist_angle(rf_quat q, rf_vec3 a)
{
    double p = q.x * a.x + q.y * a.y + q.z * a.z;
    return wrap_angle(2.0 * atan2(p, q.w));
}

/* The bound of [lo, hi] nearest to angle a on the circle, or a when inside. Nearest on the circle
 * matters: -170 degrees is closer to a 150 degree bound than to a 0 degree one. */
static double clamp_circular(double a, double lo, double hi)
{
    if (a >= lo && a <= hi)
        return a;
    double dlo = fabs(wrap_angle(a - lo)), dhi = fabs(wrap_angle(a - hi));
    return dlo <= dhi ? lo : hi;
}

static rf_quat project_hinge(const rf_ik_constraint *c, rf_quat q)
{
    rf_vec3 a = rf_v3_normalize(c->axis);
    double angle = clamp_circular(rf_ikc_twist_angle(q, a), c->min_angle, c->max_angle);
    return rf_quat_from_axis_angle(a, angle);
}

static rf_quat project_cone_twist(const rf_ik_constraint *c, rf_vec3 d, rf_quat q)
{
    double tw = rf_ikc_twist_angle(q, d);
    rf_quat twist = rf_quat_from_axis_angle(d, tw);
    rf_quat swing = rf_quat_mul(q, rf_quat_conj(twist));
    if (swing.w < 0)
        swing = rf_quat_neg(swing);
    if (c->flags & RF_IK_LIMIT_CONE) {
        double w = swing.w > 1 ? 1 : swing.w;
        double angle = 2.0 * acos(w);
        if (angle > c->cone_angle)
            swing = rf_quat_from_axis_angle(rf_v3(swing.x, swing.y, swing.z), c->cone_angle);
    }
    if (c->flags & RF_IK_LIMIT_TWIST) {
        double clamped = clamp_circular(tw, c->twist_min, c->twist_max);
        if (clamped != tw)
            twist = rf_quat_from_axis_angle(d, clamped);
    }
    return rf_quat_normalize(rf_quat_mul(swing, twist));
}

rf_quat rf_ikc_project(const rf_ik_constraint *c, rf_vec3 bone_axis, rf_quat q)
{
    if (!c || !c->flags)
        return q;
    if (c->flags & RF_IK_LOCKED)
        return rf_quat_identity();
    if (c->flags & RF_IK_LIMIT_HINGE)
        return project_hinge(c, q);
    return project_cone_twist(c, bone_axis, q);
}

double rf_ikc_angle_about(rf_vec3 a, rf_vec3 u, rf_vec3 v)
{
    rf_vec3 pu = rf_v3_sub(u, rf_v3_scale(a, rf_v3_dot(u, a)));
    rf_vec3 pv = rf_v3_sub(v, rf_v3_scale(a, rf_v3_dot(v, a)));
    /* relative to u and v: any unit of length */
    if (!(rf_v3_len2(pu) > 1e-24 * rf_v3_len2(u)) || !(rf_v3_len2(pv) > 1e-24 * rf_v3_len2(v)))
        return 0.0;
    return atan2(rf_v3_dot(a, rf_v3_cross(pu, pv)), rf_v3_dot(pu, pv));
}
