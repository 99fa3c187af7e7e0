/* Euler angles <-> quaternions for BVH rotation channels. */
#include <ctype.h>
#include <math.h>

#include "bvh-math.h"
#include "rigflow/bvh.h"

static const int order_axes[6][3] = {
    {2, 1, 0}, /* ZYX */
    {2, 0, 1}, /* ZXY */
    {1, 0, 2}, /* YXZ */
    {1, 2, 0}, /* YZX */
    {0, 1, 2}, /* XYZ */
    {0, 2, 1}, /* XZY */
};

void rf_bvh_order_axes(rf_bvh_order order, int axes[3])
{
    unsigned o = (unsigned)order < 6 ? (unsigned)order : 0;
    for (int i = 0; i < 3; i++)
        axes[i] = order_axes[o][i];
}

bool rf_bvh_order_parse(const char *text, rf_bvh_order *order)
{
    for (unsigned o = 0; o < 6; o++) {
        bool same = text[0] && text[1] && text[2] && !text[3];
        for (int i = 0; same && i < 3; i++)
            same = toupper((unsigned char)text[i]) == "XYZ"[order_axes[o][i]];
        if (same) {
            *order = (rf_bvh_order)o;
            return true;
        }
    }
    return false;
}

rf_quat rf_bvh_euler_to_quat(const int *axes, const double *degrees, int count)
{
    rf_quat q = rf_quat_identity();
    for (int i = 0; i < count; i++) {
        double s, c;
        bvh_sincos_half(&degrees[i], &s, &c, 1);
        bvh_sincos_half_fix(&degrees[i], &s, &c, 1);
        q = rf_quat_mul(q, bvh_axis_quat(axes[i], s, c));
    }
    return q;
}

/* Element (row, col) of the rotation matrix of unit quaternion q. */
static double rot_elem(rf_quat q, int row, int col)
{
    double v[3] = {q.x, q.y, q.z};
    if (row == col)
        return 1 - 2 * (v[(row + 1) % 3] * v[(row + 1) % 3] + v[(row + 2) % 3] * v[(row + 2) % 3]);
    /* off-diagonal: 2 (v_r v_c -+ w v_k), k the third axis; + when col follows row cyclically */
    int k = 3 - row - col;
    double sign = (col == (row + 1) % 3) ? -1.0 : 1.0;
    return 2 * (v[row] * v[col] + sign * q.w * v[k]);
}

static rf_quat axis_quat(int axis, double radians)
{
    double v[3] = {0, 0, 0};
    v[axis] = sin(radians * 0.5);
    return rf_quat_make(v[0], v[1], v[2], cos(radians * 0.5));
}

void rf_bvh_quat_to_euler(rf_quat q, rf_bvh_order order, double angles[3])
{
    int ax[3];
    rf_bvh_order_axes(order, ax);
    int a = ax[0], b = ax[1], c = ax[2];
    /* R = Ra(alpha) Rb(beta) Rc(gamma). With e = +1 for a cyclic order (XYZ, YZX, ZXY) and -1
     * otherwise: R[a][c] = e sin(beta), and R[a][a], R[a][b] carry cos(beta). */
    double e = (b == (a + 1) % 3) ? 1.0 : -1.0;
    q = rf_quat_normalize(q);
    double cb = hypot(rot_elem(q, a, a), rot_elem(q, a, b));
    double beta = atan2(e * rot_elem(q, a, c), cb), alpha;
    if (cb > 1e-9)
        alpha = atan2(-e * rot_elem(q, b, c), rot_elem(q, c, c));
    else /* gimbal lock: only alpha + gamma is defined; take gamma = 0 */
        alpha = atan2(e * rot_elem(q, c, b), rot_elem(q, b, b));
    /* gamma from what alpha and beta leave over, so the composition is exact even near lock. */
    rf_quat rest = rf_quat_mul(rf_quat_conj(axis_quat(b, beta)),
                               rf_quat_mul(rf_quat_conj(axis_quat(a, alpha)), q));
    double rv[3] = {rest.x, rest.y, rest.z};
    double gamma = 2 * atan2(rv[c], rest.w);
    if (gamma > RF_PI)
        gamma -= 2 * RF_PI;
    else if (gamma <= -RF_PI)
        gamma += 2 * RF_PI;
    angles[0] = alpha * (180.0 / RF_PI);
    angles[1] = beta * (180.0 / RF_PI);
    angles[2] = gamma * (180.0 / RF_PI);
}
