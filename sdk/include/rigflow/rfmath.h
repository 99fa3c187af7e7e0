/* rigflow SDK: shared math. vec3, quaternions, 4x4 matrices and TRS transforms, in double
 * precision.
 *
 * Everything here is header-only (static inline) so that plugins link nothing from the host.
 * Conventions: right-handed coordinates; quaternions are (x, y, z, w) with w the scalar part and
 * rotate vectors actively (v' = q v q*); q1 * q2 applies q2 first; matrices are column-major
 * (element (row r, column c) at m[c * 4 + r]), as in glTF and OpenGL; a transform maps local
 * coordinates to its parent's: p' = t + r * (s * p).
 * All functions are pure and thread-safe; none allocates.
 */
#ifndef RIGFLOW_RFMATH_H
#define RIGFLOW_RFMATH_H

#include <math.h>
#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

#define RF_PI 3.14159265358979323846

typedef struct rf_vec3 {
    double x, y, z;
} rf_vec3;

typedef struct rf_quat {
    double x, y, z, w;
} rf_quat;

typedef struct rf_mat4 {
    double m[16];
} rf_mat4;

/* Translation, rotation, scale. Composition is exact for uniform scale; with non-uniform scale
 * under a rotated child the product is not a TRS and rf_xform_mul keeps the per-axis scale
 * product, the usual approximation of animation tools. */
typedef struct rf_xform {
    rf_vec3 t;
    rf_quat r;
    rf_vec3 s;
} rf_xform;

/* ---- vec3 ---- */

static inline rf_vec3 rf_v3(double x, double y, double z)
{
    rf_vec3 v = {x, y, z};
    return v;
}
static inline rf_vec3 rf_v3_add(rf_vec3 a, rf_vec3 b)
{
    return rf_v3(a.x + b.x, a.y + b.y, a.z + b.z);
}
static inline rf_vec3 rf_v3_sub(rf_vec3 a, rf_vec3 b)
{
    return rf_v3(a.x - b.x, a.y - b.y, a.z - b.z);
}
static inline rf_vec3 rf_v3_scale(rf_vec3 a, double k)
{
    return rf_v3(a.x * k, a.y * k, a.z * k);
}
static inline rf_vec3 rf_v3_mul(rf_vec3 a, rf_vec3 b)
{
    return rf_v3(a.x * b.x, a.y * b.y, a.z * b.z);
}
static inline double rf_v3_dot(rf_vec3 a, rf_vec3 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
static inline rf_vec3 rf_v3_cross(rf_vec3 a, rf_vec3 b)
{
    return rf_v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline double rf_v3_len2(rf_vec3 a)
{
    return rf_v3_dot(a, a);
}
static inline double rf_v3_len(rf_vec3 a)
{
    return sqrt(rf_v3_dot(a, a));
}
static inline double rf_v3_dist(rf_vec3 a, rf_vec3 b)
{
    return rf_v3_len(rf_v3_sub(a, b));
}
static inline rf_vec3 rf_v3_lerp(rf_vec3 a, rf_vec3 b, double t)
{
    return rf_v3_add(a, rf_v3_scale(rf_v3_sub(b, a), t));
}
/* Unit vector along a; the zero vector when a has no usable length (so callers can test it). */
static inline rf_vec3 rf_v3_normalize(rf_vec3 a)
{
    double l = rf_v3_len(a);
    return l > 1e-300 ? rf_v3_scale(a, 1.0 / l) : rf_v3(0, 0, 0);
}
static inline bool rf_v3_isfinite(rf_vec3 a)
{
    return isfinite(a.x) && isfinite(a.y) && isfinite(a.z);
}
/* Angle in radians between two non-zero vectors, in [0, pi]; 0 when either is zero. */
static inline double rf_v3_angle(rf_vec3 a, rf_vec3 b)
{
    /* atan2 of |a x b| and a . b stays accurate near 0 and pi, where acos of the dot does not. */
    return atan2(rf_v3_len(rf_v3_cross(a, b)), rf_v3_dot(a, b));
}

/* ---- quaternions ---- */

static inline rf_quat rf_quat_identity(void)
{
    rf_quat q = {0, 0, 0, 1};
    return q;
}
static inline rf_quat rf_quat_make(double x, double y, double z, double w)
{
    rf_quat q = {x, y, z, w};
    return q;
}
static inline rf_quat rf_quat_mul(rf_quat a, rf_quat b)
{
    return rf_quat_make(a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
                        a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
                        a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w,
                        a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z);
}
/* The inverse of a unit quaternion. */
static inline rf_quat rf_quat_conj(rf_quat q)
{
    return rf_quat_make(-q.x, -q.y, -q.z, q.w);
}
static inline double rf_quat_dot(rf_quat a, rf_quat b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w;
}
/* Unit quaternion along q; the identity when q is zero or not finite. */
static inline rf_quat rf_quat_normalize(rf_quat q)
{
    double l = sqrt(rf_quat_dot(q, q));
    if (!(l > 1e-300) || !isfinite(l))
        return rf_quat_identity();
    return rf_quat_make(q.x / l, q.y / l, q.z / l, q.w / l);
}
static inline rf_quat rf_quat_neg(rf_quat q)
{
    return rf_quat_make(-q.x, -q.y, -q.z, -q.w);
}
/* Rotate v by unit quaternion q. */
static inline rf_vec3 rf_quat_rotate(rf_quat q, rf_vec3 v)
{
    /* v + 2w (u x v) + 2 u x (u x v), u the vector part: fewer operations than q v q*. */
    rf_vec3 u = rf_v3(q.x, q.y, q.z);
    rf_vec3 c = rf_v3_scale(rf_v3_cross(u, v), 2.0);
    return rf_v3_add(rf_v3_add(v, rf_v3_scale(c, q.w)), rf_v3_cross(u, c));
}
/* Rotation of `angle` radians about `axis` (need not be unit; identity for a zero axis). */
static inline rf_quat rf_quat_from_axis_angle(rf_vec3 axis, double angle)
{
    rf_vec3 n = rf_v3_normalize(axis);
    double s = sin(angle * 0.5);
    if (rf_v3_len2(n) == 0.0)
        return rf_quat_identity();
    return rf_quat_make(n.x * s, n.y * s, n.z * s, cos(angle * 0.5));
}
/* The shortest rotation taking direction a onto direction b (neither need be unit). For opposite
 * directions the half-turn axis is any perpendicular; for a zero vector, the identity. */
static inline rf_quat rf_quat_from_two_vectors(rf_vec3 a, rf_vec3 b)
{
    rf_vec3 u = rf_v3_normalize(a), v = rf_v3_normalize(b);
    if (rf_v3_len2(u) == 0.0 || rf_v3_len2(v) == 0.0)
        return rf_quat_identity();
    double d = rf_v3_dot(u, v);
    if (d < -1.0 + 1e-12) {
        rf_vec3 axis = rf_v3_cross(rf_v3(1, 0, 0), u);
        if (rf_v3_len2(axis) < 1e-12)
            axis = rf_v3_cross(rf_v3(0, 1, 0), u);
        return rf_quat_from_axis_angle(axis, RF_PI);
    }
    rf_vec3 c = rf_v3_cross(u, v);
    return rf_quat_normalize(rf_quat_make(c.x, c.y, c.z, 1.0 + d));
}
/* Spherical interpolation along the shorter arc; t in [0, 1]. */
static inline rf_quat rf_quat_slerp(rf_quat a, rf_quat b, double t)
{
    double d = rf_quat_dot(a, b);
    if (d < 0) {
        b = rf_quat_neg(b);
        d = -d;
    }
    if (d > 0.9995) { /* nearly parallel: nlerp is exact to rounding and avoids 0/0 */
        return rf_quat_normalize(rf_quat_make(a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t,
                                              a.z + (b.z - a.z) * t, a.w + (b.w - a.w) * t));
    }
    double th = acos(d), s = sin(th);
    double ka = sin((1 - t) * th) / s, kb = sin(t * th) / s;
    return rf_quat_make(a.x * ka + b.x * kb, a.y * ka + b.y * kb, a.z * ka + b.z * kb,
                        a.w * ka + b.w * kb);
}
/* Rotation angle in radians between two unit quaternions, in [0, pi]. From the relative rotation's
 * vector and scalar parts with atan2, which stays exact for tiny angles where acos of a dot
 * product near 1 cannot resolve anything below about 1e-8. */
static inline double rf_quat_angle(rf_quat a, rf_quat b)
{
    rf_quat d = rf_quat_mul(rf_quat_conj(a), b);
    return 2.0 * atan2(sqrt(d.x * d.x + d.y * d.y + d.z * d.z), fabs(d.w));
}

/* ---- 4x4 matrices (column-major) ---- */

static inline rf_mat4 rf_mat4_identity(void)
{
    rf_mat4 r = {{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}};
    return r;
}
static inline rf_mat4 rf_mat4_mul(rf_mat4 a, rf_mat4 b)
{
    rf_mat4 r;
    for (int c = 0; c < 4; c++)
        for (int row = 0; row < 4; row++) {
            double s = 0;
            for (int k = 0; k < 4; k++)
                s += a.m[k * 4 + row] * b.m[c * 4 + k];
            r.m[c * 4 + row] = s;
        }
    return r;
}
static inline rf_vec3 rf_mat4_point(rf_mat4 a, rf_vec3 p)
{
    return rf_v3(a.m[0] * p.x + a.m[4] * p.y + a.m[8] * p.z + a.m[12],
                 a.m[1] * p.x + a.m[5] * p.y + a.m[9] * p.z + a.m[13],
                 a.m[2] * p.x + a.m[6] * p.y + a.m[10] * p.z + a.m[14]);
}
static inline rf_vec3 rf_mat4_dir(rf_mat4 a, rf_vec3 d)
{
    return rf_v3(a.m[0] * d.x + a.m[4] * d.y + a.m[8] * d.z,
                 a.m[1] * d.x + a.m[5] * d.y + a.m[9] * d.z,
                 a.m[2] * d.x + a.m[6] * d.y + a.m[10] * d.z);
}
/* General inverse by cofactors. Returns false (and leaves *out untouched) for a singular or
 * non-finite matrix. */
static inline bool rf_mat4_invert(rf_mat4 a, rf_mat4 *out)
{
    const double *m = a.m;
    double inv[16];
    inv[0] = m[5] * m[10] * m[15] - m[5] * m[11] * m[14] - m[9] * m[6] * m[15] +
             m[9] * m[7] * m[14] + m[13] * m[6] * m[11] - m[13] * m[7] * m[10];
    inv[4] = -m[4] * m[10] * m[15] + m[4] * m[11] * m[14] + m[8] * m[6] * m[15] -
             m[8] * m[7] * m[14] - m[12] * m[6] * m[11] + m[12] * m[7] * m[10];
    inv[8] = m[4] * m[9] * m[15] - m[4] * m[11] * m[13] - m[8] * m[5] * m[15] +
             m[8] * m[7] * m[13] + m[12] * m[5] * m[11] - m[12] * m[7] * m[9];
    inv[12] = -m[4] * m[9] * m[14] + m[4] * m[10] * m[13] + m[8] * m[5] * m[14] -
              m[8] * m[6] * m[13] - m[12] * m[5] * m[10] + m[12] * m[6] * m[9];
    inv[1] = -m[1] * m[10] * m[15] + m[1] * m[11] * m[14] + m[9] * m[2] * m[15] -
             m[9] * m[3] * m[14] - m[13] * m[2] * m[11] + m[13] * m[3] * m[10];
    inv[5] = m[0] * m[10] * m[15] - m[0] * m[11] * m[14] - m[8] * m[2] * m[15] +
             m[8] * m[3] * m[14] + m[12] * m[2] * m[11] - m[12] * m[3] * m[10];
    inv[9] = -m[0] * m[9] * m[15] + m[0] * m[11] * m[13] + m[8] * m[1] * m[15] -
             m[8] * m[3] * m[13] - m[12] * m[1] * m[11] + m[12] * m[3] * m[9];
    inv[13] = m[0] * m[9] * m[14] - m[0] * m[10] * m[13] - m[8] * m[1] * m[14] +
              m[8] * m[2] * m[13] + m[12] * m[1] * m[10] - m[12] * m[2] * m[9];
    inv[2] = m[1] * m[6] * m[15] - m[1] * m[7] * m[14] - m[5] * m[2] * m[15] + m[5] * m[3] * m[14] +
             m[13] * m[2] * m[7] - m[13] * m[3] * m[6];
    inv[6] = -m[0] * m[6] * m[15] + m[0] * m[7] * m[14] + m[4] * m[2] * m[15] -
             m[4] * m[3] * m[14] - m[12] * m[2] * m[7] + m[12] * m[3] * m[6];
    inv[10] = m[0] * m[5] * m[15] - m[0] * m[7] * m[13] - m[4] * m[1] * m[15] +
              m[4] * m[3] * m[13] + m[12] * m[1] * m[7] - m[12] * m[3] * m[5];
    inv[14] = -m[0] * m[5] * m[14] + m[0] * m[6] * m[13] + m[4] * m[1] * m[14] -
              m[4] * m[2] * m[13] - m[12] * m[1] * m[6] + m[12] * m[2] * m[5];
    inv[3] = -m[1] * m[6] * m[11] + m[1] * m[7] * m[10] + m[5] * m[2] * m[11] -
             m[5] * m[3] * m[10] - m[9] * m[2] * m[7] + m[9] * m[3] * m[6];
    inv[7] = m[0] * m[6] * m[11] - m[0] * m[7] * m[10] - m[4] * m[2] * m[11] + m[4] * m[3] * m[10] +
             m[8] * m[2] * m[7] - m[8] * m[3] * m[6];
    inv[11] = -m[0] * m[5] * m[11] + m[0] * m[7] * m[9] + m[4] * m[1] * m[11] - m[4] * m[3] * m[9] -
              m[8] * m[1] * m[7] + m[8] * m[3] * m[5];
    inv[15] = m[0] * m[5] * m[10] - m[0] * m[6] * m[9] - m[4] * m[1] * m[10] + m[4] * m[2] * m[9] +
              m[8] * m[1] * m[6] - m[8] * m[2] * m[5];
    double det = m[0] * inv[0] + m[1] * inv[4] + m[2] * inv[8] + m[3] * inv[12];
    if (det == 0.0 || !isfinite(det))
        return false;
    for (int i = 0; i < 16; i++)
        out->m[i] = inv[i] / det;
    return true;
}

/* ---- TRS transforms ---- */

static inline rf_xform rf_xform_identity(void)
{
    rf_xform x = {{0, 0, 0}, {0, 0, 0, 1}, {1, 1, 1}};
    return x;
}
static inline rf_vec3 rf_xform_point(rf_xform a, rf_vec3 p)
{
    return rf_v3_add(a.t, rf_quat_rotate(a.r, rf_v3_mul(a.s, p)));
}
/* parent * child: the child's transform expressed in the parent's parent space. */
static inline rf_xform rf_xform_mul(rf_xform parent, rf_xform child)
{
    rf_xform r;
    r.t = rf_xform_point(parent, child.t);
    r.r = rf_quat_normalize(rf_quat_mul(parent.r, child.r));
    r.s = rf_v3_mul(parent.s, child.s);
    return r;
}
/* The inverse transform (exact for uniform scale; a zero scale axis inverts to zero). */
static inline rf_xform rf_xform_invert(rf_xform a)
{
    rf_xform r;
    r.r = rf_quat_conj(a.r);
    r.s = rf_v3(a.s.x != 0 ? 1.0 / a.s.x : 0, a.s.y != 0 ? 1.0 / a.s.y : 0,
                a.s.z != 0 ? 1.0 / a.s.z : 0);
    r.t = rf_v3_mul(r.s, rf_quat_rotate(r.r, rf_v3_scale(a.t, -1.0)));
    return r;
}
static inline rf_mat4 rf_xform_to_mat4(rf_xform a)
{
    rf_quat q = a.r;
    double xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z;
    double xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z;
    double wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
    rf_mat4 m = {{(1 - 2 * (yy + zz)) * a.s.x, 2 * (xy + wz) * a.s.x, 2 * (xz - wy) * a.s.x, 0,
                  2 * (xy - wz) * a.s.y, (1 - 2 * (xx + zz)) * a.s.y, 2 * (yz + wx) * a.s.y, 0,
                  2 * (xz + wy) * a.s.z, 2 * (yz - wx) * a.s.z, (1 - 2 * (xx + yy)) * a.s.z, 0,
                  a.t.x, a.t.y, a.t.z, 1}};
    return m;
}
/* Decompose an affine matrix without shear into TRS. A reflection (negative determinant) is
 * carried by a negative x scale. Returns false for a singular or non-finite matrix. */
static inline bool rf_mat4_to_xform(rf_mat4 a, rf_xform *out)
{
    rf_vec3 c0 = rf_v3(a.m[0], a.m[1], a.m[2]), c1 = rf_v3(a.m[4], a.m[5], a.m[6]);
    rf_vec3 c2 = rf_v3(a.m[8], a.m[9], a.m[10]);
    double sx = rf_v3_len(c0), sy = rf_v3_len(c1), sz = rf_v3_len(c2);
    if (!(sx > 0 && sy > 0 && sz > 0) || !isfinite(sx + sy + sz))
        return false;
    if (rf_v3_dot(rf_v3_cross(c0, c1), c2) < 0)
        sx = -sx;
    c0 = rf_v3_scale(c0, 1 / sx), c1 = rf_v3_scale(c1, 1 / sy), c2 = rf_v3_scale(c2, 1 / sz);
    /* Shepperd's method: pick the largest diagonal term for stability. */
    double tr = c0.x + c1.y + c2.z;
    rf_quat q;
    if (tr > 0) {
        double s = sqrt(tr + 1.0) * 2;
        q = rf_quat_make((c1.z - c2.y) / s, (c2.x - c0.z) / s, (c0.y - c1.x) / s, 0.25 * s);
    } else if (c0.x > c1.y && c0.x > c2.z) {
        double s = sqrt(1.0 + c0.x - c1.y - c2.z) * 2;
        q = rf_quat_make(0.25 * s, (c1.x + c0.y) / s, (c2.x + c0.z) / s, (c1.z - c2.y) / s);
    } else if (c1.y > c2.z) {
        double s = sqrt(1.0 + c1.y - c0.x - c2.z) * 2;
        q = rf_quat_make((c1.x + c0.y) / s, 0.25 * s, (c2.y + c1.z) / s, (c2.x - c0.z) / s);
    } else {
        double s = sqrt(1.0 + c2.z - c0.x - c1.y) * 2;
        q = rf_quat_make((c2.x + c0.z) / s, (c2.y + c1.z) / s, 0.25 * s, (c0.y - c1.x) / s);
    }
    out->t = rf_v3(a.m[12], a.m[13], a.m[14]);
    out->r = rf_quat_normalize(q);
    out->s = rf_v3(sx, sy, sz);
    return true;
}

#ifdef __cplusplus
}
#endif

#endif
