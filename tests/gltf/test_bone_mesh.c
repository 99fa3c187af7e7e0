/* The exporter's bone mesh (plugins/convert/bone-mesh.c), checked against figures worked out by
 * hand: each bone a closed double pyramid whose base is a square of half-diagonal r = L/10, so
 * its volume is (1/3) * 2r^2 * L = L^3 / 150, wound outwards (positive signed volume), every
 * vertex wholly on the bone's parent joint; coincident joints draw nothing. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "../../plugins/convert/bone-mesh.h"

/* A chain root -> a (2 up) -> b (coincident with a: a helper) -> c (3 along x from b). */
static rf_skeleton *chain(void)
{
    rf_skeleton *s = calloc(1, sizeof *s);
    s->size = sizeof *s;
    s->joint_count = 4;
    s->joints = calloc(4, sizeof *s->joints);
    rf_vec3 t[4] = {{0, 0, 0}, {0, 2, 0}, {0, 0, 0}, {3, 0, 0}};
    for (int j = 0; j < 4; j++) {
        s->joints[j].parent = j - 1;
        s->joints[j].rest.t = t[j];
        s->joints[j].rest.r = (rf_quat){0, 0, 0, 1};
        s->joints[j].rest.s = rf_v3(1, 1, 1);
    }
    return s;
}

/* Signed volume of triangles [first, first + count) (divergence theorem). */
static double volume(const rf_mesh *m, uint32_t first, uint32_t count)
{
    double v = 0;
    for (uint32_t t = first; t < first + count; t++) {
        const float *p[3];
        for (int k = 0; k < 3; k++)
            p[k] = m->positions + (size_t)m->triangles[t * 3 + (uint32_t)k] * 3;
        rf_vec3 a = rf_v3(p[0][0], p[0][1], p[0][2]), b = rf_v3(p[1][0], p[1][1], p[1][2]),
                c = rf_v3(p[2][0], p[2][1], p[2][2]);
        v += rf_v3_dot(a, rf_v3_cross(b, c)) / 6;
    }
    return v;
}

static void test_two_bones(void **state)
{
    (void)state;
    rf_skeleton *s = chain();
    char err[256];
    rf_mesh *m = rf_cv_bone_mesh(s, NULL, 0, err, sizeof err);
    assert_non_null(m);
    assert_int_equal(m->vertex_count, 12); /* root->a and b->c; a->b has no length */
    assert_int_equal(m->triangle_count, 16);
    assert_float_equal(volume(m, 0, 8), 8.0 / 150, 1e-5);
    assert_float_equal(volume(m, 8, 8), 27.0 / 150, 1e-5);
    for (uint32_t v = 0; v < 12; v++) {
        assert_int_equal(m->skin_joints[v * 4], v < 6 ? 0 : 2);
        assert_float_equal(m->skin_weights[v * 4], 1.0, 0);
        assert_float_equal(m->skin_weights[v * 4 + 1], 0.0, 0);
    }
    rf_mesh_free(m);
    rf_skeleton_free(s);
}

/* A clip of n frames on s's joints at rest, joint j's local translation moved by `by` times the
 * frame number along x. */
static rf_animation *sliding(const rf_skeleton *s, uint32_t n, uint32_t j, double by)
{
    rf_animation *a = rf_animation_new(s->joint_count, n, 30);
    for (uint32_t f = 0; f < n; f++)
        for (uint32_t k = 0; k < s->joint_count; k++) {
            rf_vec3 t = s->joints[k].rest.t;
            if (k == j)
                t.x += by * f;
            rf_animation_set_translation(a, f, k, t);
        }
    return a;
}

/* A bone whose child walks away from its parent in a clip (a BVH root at the origin under the
 * hips that carry the walk) is not drawn: on the parent it would stand still while the body
 * leaves it. A child held within 5% of its bone's length (mocap noise) keeps its bone. */
static void test_sliding_child(void **state)
{
    (void)state;
    rf_skeleton *s = chain();
    char err[256];
    /* a's bone is 2 long: 0.09 over 10 frames (4.5%) is noise, 0.2 a step (100%) a walk */
    const rf_animation *clips[2] = {sliding(s, 10, 1, 0.01), NULL};
    rf_mesh *m = rf_cv_bone_mesh(s, clips, 1, err, sizeof err);
    assert_non_null(m);
    assert_int_equal(m->vertex_count, 12);
    rf_mesh_free(m);
    clips[1] = sliding(s, 10, 1, 0.2);
    m = rf_cv_bone_mesh(s, clips, 2, err, sizeof err);
    assert_non_null(m);
    assert_int_equal(m->vertex_count, 6); /* b->c alone */
    for (uint32_t v = 0; v < 6; v++)
        assert_int_equal(m->skin_joints[v * 4], 2);
    rf_mesh_free(m);
    /* a clip made for another skeleton says nothing of this one's bones */
    rf_animation *other = rf_animation_new(3, 10, 30);
    const rf_animation *mismatched[1] = {other};
    m = rf_cv_bone_mesh(s, mismatched, 1, err, sizeof err);
    assert_non_null(m);
    assert_int_equal(m->vertex_count, 12);
    rf_mesh_free(m);
    rf_animation_free(other);
    rf_animation_free((rf_animation *)clips[0]);
    rf_animation_free((rf_animation *)clips[1]);
    rf_skeleton_free(s);
}

static void test_no_bone(void **state)
{
    (void)state;
    rf_skeleton *s = chain();
    s->joint_count = 1; /* a lone root */
    char err[256];
    assert_null(rf_cv_bone_mesh(s, NULL, 0, err, sizeof err));
    assert_non_null(strstr(err, "no bone"));
    s->joint_count = 4;
    rf_skeleton_free(s);
}

/* A skeleton whose parents do not all come before their children breaks the model's contract
 * (rigflow/model.h) and nothing upstream refuses it: it is refused by name, never read out of
 * bounds. */
static void test_parent_order(void **state)
{
    (void)state;
    rf_skeleton *s = chain();
    char err[256] = "";
    s->joints[1].parent = 3;                  /* after its child */
    s->joints[1].name = strdup("arm\x1b[2J"); /* from a file: reaches the message escaped */
    assert_null(rf_cv_bone_mesh(s, NULL, 0, err, sizeof err));
    assert_string_equal(err, "joint 1 'arm\\x1b[2J' has parent 3 '#3': expected parents before "
                             "children");
    s->joints[1].parent = 70000; /* past the end */
    err[0] = '\0';
    assert_null(rf_cv_bone_mesh(s, NULL, 0, err, sizeof err));
    assert_non_null(strstr(err, "joint 1 'arm\\x1b[2J' has parent 70000 '#70000'"));
    rf_skeleton_free(s);
}

/* A rest pose that is not a number is named, not drawn around ("no bone" would be a guess). */
static void test_nan_rest(void **state)
{
    (void)state;
    rf_skeleton *s = chain();
    char err[256] = "";
    s->joints[3].rest.t.y = NAN;
    assert_null(rf_cv_bone_mesh(s, NULL, 0, err, sizeof err));
    assert_string_equal(err, "joint 3 '#3': its rest position is not finite");
    s->joints[3].name = strdup("tip\x07");
    assert_null(rf_cv_bone_mesh(s, NULL, 0, err, sizeof err));
    assert_string_equal(err, "joint 3 'tip\\x07': its rest position is not finite");
    rf_skeleton_free(s);
}

/* The joint index is 16 bits: 65536 joints are drawn (a chain: the last bone on joint 65534,
 * 65535 bones of 6 vertices and 8 triangles), one more is refused with the limit. */
static void test_joint_limit(void **state)
{
    (void)state;
    uint32_t n = 65536;
    rf_skeleton *s = calloc(1, sizeof *s);
    s->size = sizeof *s;
    s->joint_count = n;
    s->joints = calloc(n + 1, sizeof *s->joints);
    for (uint32_t j = 0; j <= n; j++) {
        s->joints[j].parent = (int32_t)j - 1;
        s->joints[j].rest = (rf_xform){{j ? 1 : 0, 0, 0}, {0, 0, 0, 1}, {1, 1, 1}};
    }
    char err[256] = "";
    rf_mesh *m = rf_cv_bone_mesh(s, NULL, 0, err, sizeof err);
    assert_non_null(m);
    assert_int_equal(m->vertex_count, 65535u * 6);
    assert_int_equal(m->triangle_count, 65535u * 8);
    assert_int_equal(m->skin_joints[(size_t)(m->vertex_count - 1) * 4], 65534);
    assert_float_equal(m->positions[(size_t)(m->vertex_count - 6) * 3 + 3], 65535.0, 0);
    for (size_t i = 0; i < (size_t)m->triangle_count * 3; i++)
        assert_true(m->triangles[i] < m->vertex_count);
    rf_mesh_free(m);
    s->joint_count = n + 1;
    assert_null(rf_cv_bone_mesh(s, NULL, 0, err, sizeof err));
    assert_non_null(strstr(err, "65536"));
    rf_skeleton_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_two_bones), cmocka_unit_test(test_sliding_child),
        cmocka_unit_test(test_no_bone),   cmocka_unit_test(test_parent_order),
        cmocka_unit_test(test_nan_rest),  cmocka_unit_test(test_joint_limit),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
