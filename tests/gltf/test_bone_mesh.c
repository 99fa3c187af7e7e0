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
    rf_mesh *m = rf_cv_bone_mesh(s, err, sizeof err);
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

static void test_no_bone(void **state)
{
    (void)state;
    rf_skeleton *s = chain();
    s->joint_count = 1; /* a lone root */
    char err[256];
    assert_null(rf_cv_bone_mesh(s, err, sizeof err));
    assert_non_null(strstr(err, "no bone"));
    s->joint_count = 4;
    rf_skeleton_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_two_bones),
        cmocka_unit_test(test_no_bone),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
