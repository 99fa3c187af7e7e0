/* Shared math (sdk/include/rigflow/rfmath.h), checked against values worked out by hand. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <rigflow/model.h>

#define EPS 1e-12
static void near(double a, double b, double eps)
{
    assert_true(fabs(a - b) <= eps);
}
static void near_v(rf_vec3 a, rf_vec3 b, double eps)
{
    near(a.x, b.x, eps), near(a.y, b.y, eps), near(a.z, b.z, eps);
}

static void quarter_turn_about_z(void **state)
{
    (void)state;
    rf_quat q = rf_quat_from_axis_angle(rf_v3(0, 0, 2), RF_PI / 2);
    near(q.w, sqrt(0.5), EPS), near(q.z, sqrt(0.5), EPS);
    near_v(rf_quat_rotate(q, rf_v3(1, 0, 0)), rf_v3(0, 1, 0), EPS);
    near_v(rf_quat_rotate(q, rf_v3(0, 1, 0)), rf_v3(-1, 0, 0), EPS);
}

static void product_applies_right_operand_first(void **state)
{
    (void)state;
    rf_quat z = rf_quat_from_axis_angle(rf_v3(0, 0, 1), RF_PI / 2);
    rf_quat x = rf_quat_from_axis_angle(rf_v3(1, 0, 0), RF_PI / 2);
    /* x first takes Y to Z, then z leaves Z alone */
    near_v(rf_quat_rotate(rf_quat_mul(z, x), rf_v3(0, 1, 0)), rf_v3(0, 0, 1), EPS);
    /* z first takes Y to -X, then x leaves X alone */
    near_v(rf_quat_rotate(rf_quat_mul(x, z), rf_v3(0, 1, 0)), rf_v3(-1, 0, 0), EPS);
}

static void two_vectors(void **state)
{
    (void)state;
    rf_vec3 a = rf_v3(1, 2, 3), b = rf_v3(-2, 0.5, 1);
    rf_quat q = rf_quat_from_two_vectors(a, b);
    near_v(rf_v3_normalize(rf_quat_rotate(q, a)), rf_v3_normalize(b), 1e-12);
    /* opposite vectors: a half turn about some perpendicular */
    q = rf_quat_from_two_vectors(rf_v3(1, 0, 0), rf_v3(-3, 0, 0));
    near_v(rf_quat_rotate(q, rf_v3(1, 0, 0)), rf_v3(-1, 0, 0), 1e-12);
    q = rf_quat_from_two_vectors(rf_v3(0, 0, 0), rf_v3(1, 0, 0));
    near(q.w, 1, 0);
}

static void slerp_halfway(void **state)
{
    (void)state;
    rf_quat a = rf_quat_identity(), b = rf_quat_from_axis_angle(rf_v3(0, 1, 0), RF_PI / 2);
    rf_quat h = rf_quat_slerp(a, b, 0.5);
    near(rf_quat_angle(a, h), RF_PI / 4, 1e-12);
    near(rf_quat_angle(h, b), RF_PI / 4, 1e-12);
    /* the shorter arc is taken when b is given with the opposite sign */
    h = rf_quat_slerp(a, rf_quat_neg(b), 0.5);
    near(rf_quat_angle(a, h), RF_PI / 4, 1e-12);
}

static void tiny_angles_resolved(void **state)
{
    (void)state;
    rf_quat a = rf_quat_from_axis_angle(rf_v3(1, 2, 3), 0.7);
    rf_quat b = rf_quat_mul(a, rf_quat_from_axis_angle(rf_v3(0, 1, 0), 1e-10));
    near(rf_quat_angle(a, b), 1e-10, 1e-16);
    near(rf_quat_angle(a, rf_quat_neg(a)), 0, 1e-15); /* q and -q are one rotation */
    near(rf_quat_angle(rf_quat_identity(), rf_quat_from_axis_angle(rf_v3(0, 0, 1), RF_PI)), RF_PI,
         1e-12);
}

static void xform_compose_and_invert(void **state)
{
    (void)state;
    rf_xform parent = {rf_v3(1, 2, 3), rf_quat_from_axis_angle(rf_v3(0, 0, 1), RF_PI / 2),
                       rf_v3(2, 2, 2)};
    rf_xform child = {rf_v3(1, 0, 0), rf_quat_identity(), rf_v3(1, 1, 1)};
    /* child origin: scaled to (2,0,0), turned to (0,2,0), moved to (1,4,3) */
    rf_xform w = rf_xform_mul(parent, child);
    near_v(w.t, rf_v3(1, 4, 3), EPS);
    rf_xform back = rf_xform_mul(rf_xform_invert(parent), w);
    near_v(back.t, child.t, EPS);
    near(rf_quat_angle(back.r, child.r), 0, 1e-7);
    near_v(back.s, child.s, EPS);
}

static void matrices_agree_with_transforms(void **state)
{
    (void)state;
    rf_xform a = {rf_v3(-1, 0.5, 4), rf_quat_normalize(rf_quat_make(0.1, -0.7, 0.2, 0.6)),
                  rf_v3(1.5, 1.5, 1.5)};
    rf_mat4 m = rf_xform_to_mat4(a), inv;
    rf_vec3 p = rf_v3(0.3, -2, 7);
    near_v(rf_mat4_point(m, p), rf_xform_point(a, p), 1e-12);
    assert_true(rf_mat4_invert(m, &inv));
    rf_mat4 id = rf_mat4_mul(m, inv);
    for (int i = 0; i < 16; i++)
        near(id.m[i], (i % 5) == 0 ? 1 : 0, 1e-12);
    rf_xform back;
    assert_true(rf_mat4_to_xform(m, &back));
    near_v(back.t, a.t, 1e-12), near_v(back.s, a.s, 1e-12);
    near(rf_quat_angle(back.r, a.r), 0, 1e-7);
    rf_mat4 zero = {{0}};
    assert_false(rf_mat4_invert(zero, &inv));
}

static void skeleton_world_rest(void **state)
{
    (void)state;
    rf_skeleton *s = rf_skeleton_new(3);
    s->joints[1].parent = 0, s->joints[2].parent = 1;
    s->joints[0].rest.t = rf_v3(0, 1, 0);
    s->joints[1].rest.r = rf_quat_from_axis_angle(rf_v3(0, 0, 1), RF_PI / 2);
    s->joints[1].rest.t = rf_v3(0, 1, 0);
    s->joints[2].rest.t = rf_v3(1, 0, 0); /* turned by its parent to point along +Y */
    rf_xform w[3];
    rf_skeleton_world_rest(s, w);
    near_v(w[2].t, rf_v3(0, 3, 0), EPS);
    rf_skeleton_free(s);
}

static void animation_overflow_refused(void **state)
{
    (void)state;
    assert_null(rf_animation_new(UINT32_MAX, UINT32_MAX, 30));
    rf_animation *a = rf_animation_new(2, 3, 30);
    assert_non_null(a);
    near(rf_animation_rotation(a, 2, 1).w, 1, 0);
    rf_animation_free(a);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(quarter_turn_about_z),
        cmocka_unit_test(product_applies_right_operand_first),
        cmocka_unit_test(two_vectors),
        cmocka_unit_test(slerp_halfway),
        cmocka_unit_test(tiny_angles_resolved),
        cmocka_unit_test(xform_compose_and_invert),
        cmocka_unit_test(matrices_agree_with_transforms),
        cmocka_unit_test(skeleton_world_rest),
        cmocka_unit_test(animation_overflow_refused),
    };
    return cmocka_run_group_tests_name("math", tests, NULL, NULL);
}
