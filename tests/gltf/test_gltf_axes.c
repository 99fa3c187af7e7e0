/* The glTF writer turns a character whose skeleton declares other axes to glTF's (+Y up, the front
 * at +Z: glTF 2.0, "Coordinate System and Units"). Expected values are worked out by hand: Z-up
 * facing -Y (a Blender scene) is a quarter turn about X, (x, y, z) -> (x, z, -y); Y-up facing -Z
 * is a half turn about Y, (x, y, z) -> (-x, y, -z). The round trip writes a two-joint skinned
 * triangle facing -Z and reads it back through Assimp: joints, vertices and the skin's bind all
 * turned, the declared axes glTF's. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include <rigflow/aimport.h>
#include <rigflow/gltf-write.h>

#include "../../sdk/formats/gltf/gltf-axes.h"

static void near(rf_vec3 got, double x, double y, double z)
{
    assert_float_equal(got.x, x, 1e-6);
    assert_float_equal(got.y, y, 1e-6);
    assert_float_equal(got.z, z, 1e-6);
}

static void turns_by_hand(void **state)
{
    (void)state;
    rf_quat q = rf_gw_axes_turn(rf_v3(0, 0, 1), rf_v3(0, -1, 0));
    near(rf_quat_rotate(q, rf_v3(1, 2, 3)), 1, 3, -2);
    q = rf_gw_axes_turn(rf_v3(0, 1, 0), rf_v3(0, 0, -1));
    near(rf_quat_rotate(q, rf_v3(1, 2, 3)), -1, 2, -3);
    /* a facing that leans is made level first: -Z tipped up still faces -Z */
    q = rf_gw_axes_turn(rf_v3(0, 1, 0), rf_v3(0, 0.5, -1));
    near(rf_quat_rotate(q, rf_v3(1, 2, 3)), -1, 2, -3);
    /* glTF's own axes, unknown up, and a facing along up leave or only stand the content */
    near(rf_quat_rotate(rf_gw_axes_turn(rf_v3(0, 1, 0), rf_v3(0, 0, 1)), rf_v3(1, 2, 3)), 1, 2, 3);
    near(rf_quat_rotate(rf_gw_axes_turn(rf_v3(0, 0, 0), rf_v3(1, 0, 0)), rf_v3(1, 2, 3)), 1, 2, 3);
    near(rf_quat_rotate(rf_gw_axes_turn(rf_v3(0, 1, 0), rf_v3(0, 0, 0)), rf_v3(1, 2, 3)), 1, 2, 3);
    q = rf_gw_axes_turn(rf_v3(0, 0, 1), rf_v3(0, 0, 2));
    near(rf_quat_rotate(q, rf_v3(0, 0, 1)), 0, 1, 0);
}

/* Root at (0, 1, 0), a child one unit along -Z (its front), a triangle on the child. */
static void character(rf_skeleton **s, rf_mesh **m)
{
    *s = rf_skeleton_new(2);
    (*s)->joints[1].parent = 0;
    (*s)->joints[0].rest.t = rf_v3(0, 1, 0);
    (*s)->joints[1].rest.t = rf_v3(0, 0, -1);
    (*s)->up = rf_v3(0, 1, 0), (*s)->forward = rf_v3(0, 0, -1);
    *m = rf_mesh_new();
    static const float pos[9] = {0.5f, 1, -1, -0.5f, 1, -1, 0, 2, -1};
    static const uint32_t tri[3] = {0, 1, 2};
    (*m)->vertex_count = 3, (*m)->triangle_count = 1;
    (*m)->positions = malloc(sizeof pos), (*m)->triangles = malloc(sizeof tri);
    memcpy((*m)->positions, pos, sizeof pos), memcpy((*m)->triangles, tri, sizeof tri);
    (*m)->skin_joints = calloc(12, sizeof *(*m)->skin_joints);
    (*m)->skin_weights = calloc(12, sizeof *(*m)->skin_weights);
    for (int v = 0; v < 3; v++)
        (*m)->skin_joints[v * 4] = 1, (*m)->skin_weights[v * 4] = 1;
}

static void round_trip(void **state)
{
    (void)state;
    rf_skeleton *s;
    rf_mesh *m;
    character(&s, &m);
    char path[] = "/tmp/rf-axes-XXXXXX.glb", err[512];
    int fd = mkstemps(path, 4);
    assert_true(fd >= 0);
    close(fd);
    assert_true(rf_gltf_write_file(path, NULL, s, NULL, m, NULL, err, sizeof err));
    /* the caller's data is left as it was */
    near(s->joints[1].rest.t, 0, 0, -1);
    assert_float_equal(m->positions[2], -1, 0);
    rf_ai_result r;
    rf_ai_options o = {.require_skeleton = true};
    bool ok = rf_ai_import(path, &o, &r, NULL, NULL, err, sizeof err);
    unlink(path);
    assert_true(ok);
    assert_int_equal(r.skeleton->joint_count, 2);
    rf_xform w[2];
    rf_skeleton_world_rest(r.skeleton, w);
    near(w[0].t, 0, 1, 0);
    near(w[1].t, 0, 1, 1); /* the front now at +Z */
    near(rf_v3(r.mesh->positions[0], r.mesh->positions[1], r.mesh->positions[2]), -0.5, 1, 1);
    near(rf_v3(r.mesh->positions[6], r.mesh->positions[7], r.mesh->positions[8]), 0, 2, 1);
    near(r.skeleton->up, 0, 1, 0);
    near(r.skeleton->forward, 0, 0, 1);
    rf_ai_result_clear(&r);
    rf_skeleton_free(s);
    rf_mesh_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(turns_by_hand),
        cmocka_unit_test(round_trip),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
