/* The shared IK pieces against their definitions: the SVD reconstructs its matrix with orthonormal
 * factors, the Cholesky solve solves, limit projection lands inside the limits and leaves
 * rotations already inside alone. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <string.h>

#include <cmocka.h>

#include "ik-fixtures.h"
#include "rigflow/ik-common.h"

#define DEG (RF_PI / 180.0)

static void test_svd_reconstructs(void **unused)
{
    (void)unused;
    enum { M = 3, N = 7 };
    double A[M * N], B[M * N], U[M * M], sigma[M];
    fx_lcg g = {5};
    for (int i = 0; i < M * N; i++)
        A[i] = 2 * fx_rnd(&g) - 1;
    A[2 * N + 3] = 0, A[2 * N + 4] = 1e-9; /* a nearly dependent row still works */
    rf_ikc_svd(A, M, N, B, U, sigma);
    for (int r = 0; r < M; r++) /* A = sum_k u_k (B_k)^T, B_k = sigma_k v_k */
        for (int c = 0; c < N; c++) {
            double sum = 0;
            for (int k = 0; k < M; k++)
                sum += U[k * M + r] * B[k * N + c];
            assert_float_equal(sum, A[r * N + c], 1e-12);
        }
    for (int a = 0; a < M; a++)
        for (int b = 0; b < M; b++) {
            double uu = 0, vv = 0;
            for (int r = 0; r < M; r++)
                uu += U[a * M + r] * U[b * M + r];
            for (int c = 0; c < N; c++)
                vv += B[a * N + c] * B[b * N + c];
            assert_float_equal(uu, a == b, 1e-12);                           /* U orthonormal */
            assert_float_equal(vv, a == b ? sigma[a] * sigma[a] : 0, 1e-12); /* B orthogonal */
        }
}

static void test_cholesky_solves(void **unused)
{
    (void)unused;
    double S[9] = {4, 2, 0.4, 2, 5, 1, 0.4, 1, 3}, S0[9], b[3] = {1, -2, 0.5}, b0[3];
    memcpy(S0, S, sizeof S), memcpy(b0, b, sizeof b);
    assert_true(rf_ikc_cholesky_solve(S, b, 3));
    for (int r = 0; r < 3; r++)
        assert_float_equal(S0[r * 3] * b[0] + S0[r * 3 + 1] * b[1] + S0[r * 3 + 2] * b[2], b0[r],
                           1e-12);
    double bad[4] = {1, 2, 2, 1}, v[2] = {1, 1}; /* indefinite */
    assert_false(rf_ikc_cholesky_solve(bad, v, 2));
}

static rf_quat random_rotation(fx_lcg *g)
{
    rf_vec3 axis = fx_target(g, 1);
    return rf_quat_from_axis_angle(axis, (2 * fx_rnd(g) - 1) * RF_PI);
}

static void test_projection_lands_inside(void **unused)
{
    (void)unused;
    rf_ik_constraint hinge = {.size = sizeof hinge, .flags = RF_IK_LIMIT_HINGE};
    hinge.axis = rf_v3(1, 0, 0), hinge.min_angle = -20 * DEG, hinge.max_angle = 110 * DEG;
    rf_ik_constraint cone = {.size = sizeof cone, .flags = RF_IK_LIMIT_CONE | RF_IK_LIMIT_TWIST};
    cone.cone_angle = 50 * DEG, cone.twist_min = -30 * DEG, cone.twist_max = 10 * DEG;
    rf_vec3 bone = rf_v3(0, 1, 0);
    fx_lcg g = {11};
    for (int k = 0; k < 500; k++) {
        rf_quat q = random_rotation(&g);
        rf_quat h = rf_ikc_project(&hinge, bone, q), c = rf_ikc_project(&cone, bone, q);
        assert_true(fx_limit_violation(&hinge, bone, rf_quat_identity(), h) < 1e-9);
        assert_true(fx_limit_violation(&cone, bone, rf_quat_identity(), c) < 1e-9);
        /* projecting again changes nothing */
        assert_true(rf_quat_angle(h, rf_ikc_project(&hinge, bone, h)) < 1e-6);
        assert_true(rf_quat_angle(c, rf_ikc_project(&cone, bone, c)) < 1e-6);
    }
    /* inside already: untouched */
    rf_quat inside = rf_quat_from_axis_angle(rf_v3(1, 0, 0), 60 * DEG);
    assert_true(rf_quat_angle(inside, rf_ikc_project(&hinge, bone, inside)) < 1e-9);
    assert_true(rf_quat_angle(inside, rf_ikc_project(&cone, bone, inside)) > 1e-3); /* 60 > 50 */
}

static void test_twist_and_angle_about(void **unused)
{
    (void)unused;
    rf_vec3 y = rf_v3(0, 1, 0);
    rf_quat q = rf_quat_mul(rf_quat_from_axis_angle(rf_v3(1, 0, 0), 0.4),
                            rf_quat_from_axis_angle(y, 0.7)); /* swing after a 0.7 rad twist */
    assert_float_equal(rf_ikc_twist_angle(q, y), 0.7, 1e-12);
    assert_float_equal(rf_ikc_angle_about(y, rf_v3(1, 5, 0), rf_v3(0, -3, -1)), RF_PI / 2, 1e-12);
    assert_float_equal(rf_ikc_angle_about(y, rf_v3(0, 1, 0), rf_v3(1, 0, 0)), 0, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_svd_reconstructs),
        cmocka_unit_test(test_cholesky_solves),
        cmocka_unit_test(test_projection_lands_inside),
        cmocka_unit_test(test_twist_and_angle_about),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
