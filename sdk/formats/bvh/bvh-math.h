/* Euler angle helpers inlined into the BVH reader's per-frame loop. */
#ifndef RIGFLOW_PLUGINS_BVH_MATH_H
#define RIGFLOW_PLUGINS_BVH_MATH_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "rigflow/rfmath.h"

/* The sine and cosine Taylor polynomials of bvh_sincos_half, written once for scalars and
 * vectors (x and x2 must be plain variables). */
#define BVH_SINCOS_POLY(x, x2, sn, cs)                                                             \
    do {                                                                                           \
        sn = 1.0 / 121645100408832000 * -x2 + 1.0 / 355687428096000; /* x^19, x^17 */              \
        sn = sn * x2 - 1.0 / 1307674368000;                                                        \
        sn = sn * x2 + 1.0 / 6227020800;                                                           \
        sn = sn * x2 - 1.0 / 39916800;                                                             \
        sn = sn * x2 + 1.0 / 362880;                                                               \
        sn = sn * x2 - 1.0 / 5040;                                                                 \
        sn = sn * x2 + 1.0 / 120;                                                                  \
        sn = sn * x2 - 1.0 / 6;                                                                    \
        sn = (sn * x2 + 1.0) * x;                                                                  \
        cs = 1.0 / 2432902008176640000 * x2 - 1.0 / 6402373705728000; /* x^20, x^18 */             \
        cs = cs * x2 + 1.0 / 20922789888000;                                                       \
        cs = cs * x2 - 1.0 / 87178291200;                                                          \
        cs = cs * x2 + 1.0 / 479001600;                                                            \
        cs = cs * x2 - 1.0 / 3628800;                                                              \
        cs = cs * x2 + 1.0 / 40320;                                                                \
        cs = cs * x2 - 1.0 / 720;                                                                  \
        cs = cs * x2 + 1.0 / 24;                                                                   \
        cs = cs * x2 - 0.5;                                                                        \
        cs = cs * x2 + 1.0;                                                                        \
    } while (0)

#define BVH_ROUND_MAGIC 6755399441055744.0 /* 1.5 * 2^52: x + M - M rounds x to an integer */

#if defined(__GNUC__) && defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
#define BVH_VECTOR 1
typedef double bvh_v2d __attribute__((vector_size(16)));
typedef unsigned long long bvh_v2u __attribute__((vector_size(16)));
#else
#define BVH_VECTOR 0
#endif

/* sin and cos of half of each angle deg[i] (degrees) into s[i], c[i]: the half-angle sines and
 * cosines of rotation quaternions. The reduction h - 180k to [-90, 90] degrees is exact
 * (Sterbenz's lemma), so Taylor polynomials on [-pi/2, pi/2] reach double precision (terms to
 * x^19 and x^20, truncation below 3e-16), and (-1)^k is the low bit of k's rounding sum moved
 * to the sign. No branches: two angles at a time in SSE2 registers, and a frame's angles all
 * together, which leaves the per-joint work independent multiplications.
 * Angles of 1e15 degrees or more are left to bvh_sincos_half_fix. */
static inline void bvh_sincos_half(const double *deg, double *s, double *c, size_t n)
{
    size_t i = 0;
#if BVH_VECTOR
    for (; i + 2 <= n; i += 2) {
        bvh_v2d h, sn, cs;
        memcpy(&h, deg + i, sizeof h);
        h = h * 0.5;
        bvh_v2d t = h * (1.0 / 180) + BVH_ROUND_MAGIC;
        bvh_v2u flip = (bvh_v2u)t << 63;
        bvh_v2d k = t - BVH_ROUND_MAGIC;
        bvh_v2d x = (h - k * 180.0) * (RF_PI / 180.0), x2 = x * x;
        BVH_SINCOS_POLY(x, x2, sn, cs);
        sn = (bvh_v2d)((bvh_v2u)sn ^ flip);
        cs = (bvh_v2d)((bvh_v2u)cs ^ flip);
        memcpy(s + i, &sn, sizeof sn);
        memcpy(c + i, &cs, sizeof cs);
    }
#endif
    for (; i < n; i++) {
        double h = deg[i] * 0.5, sn, cs;
        double k = (h * (1.0 / 180) + BVH_ROUND_MAGIC) - BVH_ROUND_MAGIC;
        double x = (h - k * 180.0) * (RF_PI / 180.0), x2 = x * x;
        double sign = k - 2.0 * ((k * 0.5 + BVH_ROUND_MAGIC) - BVH_ROUND_MAGIC) != 0 ? -1.0 : 1.0;
        BVH_SINCOS_POLY(x, x2, sn, cs);
        s[i] = sign * sn;
        c[i] = sign * cs;
    }
}

#if BVH_VECTOR && defined(__x86_64__)
#define BVH_AVX2 1
typedef double bvh_v4d __attribute__((vector_size(32)));
typedef unsigned long long bvh_v4u __attribute__((vector_size(32)));

/* bvh_sincos_half four angles at a time, for processors with AVX2 (check
 * __builtin_cpu_supports("avx2") first). The same operations in the same order, without fused
 * multiply-adds: the results are bit for bit those of bvh_sincos_half. */
__attribute__((target("avx2"))) static inline void
bvh_sincos_half_avx2(const double *deg, double *s, double *c, size_t n)
{
    size_t i = 0;
    for (; i + 4 <= n; i += 4) {
        bvh_v4d h, sn, cs;
        memcpy(&h, deg + i, sizeof h);
        h = h * 0.5;
        bvh_v4d t = h * (1.0 / 180) + BVH_ROUND_MAGIC;
        bvh_v4u flip = (bvh_v4u)t << 63;
        bvh_v4d k = t - BVH_ROUND_MAGIC;
        bvh_v4d x = (h - k * 180.0) * (RF_PI / 180.0), x2 = x * x;
        BVH_SINCOS_POLY(x, x2, sn, cs);
        sn = (bvh_v4d)((bvh_v4u)sn ^ flip);
        cs = (bvh_v4d)((bvh_v4u)cs ^ flip);
        memcpy(s + i, &sn, sizeof sn);
        memcpy(c + i, &cs, sizeof cs);
    }
    bvh_sincos_half(deg + i, s + i, c + i, n - i);
}
#else
#define BVH_AVX2 0
#endif

/* Redoes the angles bvh_sincos_half cannot reduce exactly (|deg| >= 1e15) with libm. */
static inline void bvh_sincos_half_fix(const double *deg, double *s, double *c, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        if (fabs(deg[i]) < 1e15)
            continue;
        double r = fmod(deg[i], 720.0) * (RF_PI / 360.0);
        s[i] = sin(r), c[i] = cos(r);
    }
}

/* Stores as floats (x, y, z, w) the quaternion Ra * Rb * Rc of three rotations about the
 * distinct axes ax[0..2] with half-angle sines s and cosines c; e is +1 when the axes are in
 * cyclic order, -1 otherwise. Multiplying out (ca + sa ea)(cb + sb eb)(cc + sc ec) with
 * ea eb = e ec, eb ec = e ea, ea ec = -e eb gives the four terms below: fewer operations than two
 * general quaternion products, and the same code for every order. */
static inline void bvh_euler3(const uint8_t *ax, double e, double sa, double ca, double sb,
                              double cb, double sc, double cc, float *out)
{
    /* Stored one by one straight to `out`: gathering them in a local array and copying that
     * would make the processor wait for four narrow stores to forward into one wide load. */
    double cacb = ca * cb, sasb = sa * sb, sacb = sa * cb, casb = ca * sb;
    out[3] = (float)(cacb * cc - e * sasb * sc);
    out[ax[0]] = (float)(sacb * cc + e * casb * sc);
    out[ax[1]] = (float)(casb * cc - e * sacb * sc);
    out[ax[2]] = (float)(cacb * sc + e * sasb * cc);
}

/* The rotation quaternion about axis 0 = X, 1 = Y, 2 = Z with half-angle sine s and cosine c. */
static inline rf_quat bvh_axis_quat(int axis, double s, double c)
{
    rf_quat q = {axis == 0 ? s : 0, axis == 1 ? s : 0, axis == 2 ? s : 0, c};
    return q;
}

#endif
