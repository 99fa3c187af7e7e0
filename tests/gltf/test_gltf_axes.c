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

/* ---- the turn as a whole: what a glTF reader draws from the turned copies is the original
 * character turned (an invariant, with no figure taken from the code under test) ---- */

static rf_mat4 local_at(const rf_skeleton *s, const rf_animation *a, uint32_t f, uint32_t j)
{
    rf_xform x = s->joints[j].rest;
    if (a)
        x.t = rf_animation_translation(a, f, j), x.r = rf_animation_rotation(a, f, j);
    return rf_xform_to_mat4(x); /* matrices, as readers compose nodes (shear survives) */
}

/* Skinned position of vertex v at frame f, as glTF defines it: the sum over influences of
 * weight * world(joint) * inverse bind * position; inverse binds the mesh's when it has one per
 * joint, else the inverse world rest (what the writer writes). */
static rf_vec3 skinned(const rf_skeleton *s, const rf_animation *a, const rf_mesh *m, uint32_t f,
                       uint32_t v)
{
    rf_mat4 world[8], rest[8];
    for (uint32_t j = 0; j < s->joint_count; j++) {
        int32_t p = s->joints[j].parent;
        rf_mat4 l = local_at(s, a, f, j), r = local_at(s, NULL, 0, j);
        world[j] = p < 0 ? l : rf_mat4_mul(world[p], l);
        rest[j] = p < 0 ? r : rf_mat4_mul(rest[p], r);
    }
    rf_vec3 pos = rf_v3(m->positions[v * 3], m->positions[v * 3 + 1], m->positions[v * 3 + 2]);
    rf_vec3 sum = rf_v3(0, 0, 0);
    for (int k = 0; k < 4; k++) {
        uint32_t j = m->skin_joints[v * 4 + (uint32_t)k];
        float w = m->skin_weights[v * 4 + (uint32_t)k];
        rf_mat4 ib;
        if (m->inverse_bind && m->bind_count == s->joint_count)
            ib = m->inverse_bind[j];
        else
            assert_true(rf_mat4_invert(rest[j], &ib));
        sum = rf_v3_add(sum, rf_v3_scale(rf_mat4_point(rf_mat4_mul(world[j], ib), pos), w));
    }
    return sum;
}

static void near_tol(rf_vec3 got, rf_vec3 want, double tol)
{
    assert_float_equal(got.x, want.x, tol);
    assert_float_equal(got.y, want.y, tol);
    assert_float_equal(got.z, want.z, tol);
}

/* Two roots (one scaled unevenly and turned), a child each; Z up facing +X (an FBX scene). */
static rf_skeleton *two_roots(void)
{
    rf_skeleton *s = rf_skeleton_new(4);
    s->joints[1].parent = 0, s->joints[3].parent = 2;
    s->joints[0].rest = (rf_xform){
        rf_v3(0.2, -0.1, 1), rf_quat_from_axis_angle(rf_v3(1, 2, 0.5), 0.7), rf_v3(1, 2, 0.5)};
    s->joints[1].rest.t = rf_v3(0, 0.3, 0.8);
    s->joints[1].rest.r = rf_quat_from_axis_angle(rf_v3(0, 1, 1), -0.4);
    s->joints[2].rest.t = rf_v3(-0.5, 0.4, 0.2);
    s->joints[3].rest.t = rf_v3(0.6, 0, 0.1);
    s->up = rf_v3(0, 0, 1), s->forward = rf_v3(1, 0, 0);
    return s;
}

static rf_animation *clip_of(const rf_skeleton *s)
{
    rf_animation *a = rf_animation_new(4, 3, 30);
    for (uint32_t f = 0; f < 3; f++)
        for (uint32_t j = 0; j < 4; j++) {
            rf_xform x = s->joints[j].rest;
            rf_animation_set_translation(a, f, j, rf_v3_add(x.t, rf_v3(0.1 * f, 0.05 * j, 0)));
            rf_animation_set_rotation(
                a, f, j, rf_quat_mul(x.r, rf_quat_from_axis_angle(rf_v3(j, 1, f), 0.3 * f)));
        }
    a->channels[0] = RF_CHANNEL_ROTATION | RF_CHANNEL_TRANSLATION,
    a->channels[3] = RF_CHANNEL_ROTATION;
    return a;
}

/* Four vertices shared by joints 1 and 3, with normals, tangents and a morph target; inverse
 * binds of the rest pose moved a little (a bind pose that is not the rest), `binds` of them. */
static rf_mesh *skin_of(const rf_skeleton *s, uint32_t binds)
{
    rf_mesh *m = rf_mesh_new();
    static const float pos[12] = {0.1f, 0.2f, 1.5f, -0.3f, 0.5f, 1.2f, 0.4f, -0.2f, 0.9f, 0, 0, 2};
    static const uint32_t tri[6] = {0, 1, 2, 0, 2, 3};
    m->vertex_count = 4, m->triangle_count = 2;
    m->positions = malloc(sizeof pos), m->triangles = malloc(sizeof tri);
    memcpy(m->positions, pos, sizeof pos), memcpy(m->triangles, tri, sizeof tri);
    m->normals = malloc(sizeof pos), m->tangents = calloc(16, sizeof(float));
    for (int i = 0; i < 12; i++)
        m->normals[i] = (float)(i % 3 == 1);
    for (int v = 0; v < 4; v++)
        m->tangents[v * 4] = 1, m->tangents[v * 4 + 3] = v % 2 ? -1.0f : 1.0f;
    m->skin_joints = calloc(16, sizeof *m->skin_joints);
    m->skin_weights = calloc(16, sizeof *m->skin_weights);
    for (int v = 0; v < 4; v++) {
        m->skin_joints[v * 4] = 1, m->skin_joints[v * 4 + 1] = 3;
        m->skin_weights[v * 4] = 0.25f * (float)v,
                            m->skin_weights[v * 4 + 1] = 1 - 0.25f * (float)v;
    }
    m->morph_target_count = 1;
    m->morph_targets = calloc(1, sizeof *m->morph_targets);
    m->morph_targets[0] = rf_morph_target_new("smile", 4);
    m->morph_targets[0]->normals = calloc(12, sizeof(float));
    for (int i = 0; i < 12; i++)
        m->morph_targets[0]->positions[i] = 0.01f * (float)i,
        m->morph_targets[0]->normals[i] = 0.02f;
    m->bind_count = binds;
    m->inverse_bind = calloc(binds, sizeof *m->inverse_bind);
    rf_xform w[4];
    rf_skeleton_world_rest(s, w);
    for (uint32_t j = 0; j < binds; j++) {
        rf_xform b = w[j % 4];
        b.t = rf_v3_add(b.t, rf_v3(0.05, 0.02 * j, -0.01));
        m->inverse_bind[j] = rf_xform_to_mat4(rf_xform_invert(b));
    }
    return m;
}

static void check_turned(uint32_t binds)
{
    rf_skeleton *s = two_roots();
    rf_animation *a = clip_of(s);
    rf_mesh *m = skin_of(s, binds);
    const rf_animation *clips[2] = {a, NULL};
    rf_gw_axes x;
    assert_true(rf_gw_axes_conform(&x, s, clips, 2, m));
    assert_ptr_not_equal(x.skeleton, s), assert_ptr_not_equal(x.mesh, m);
    assert_ptr_not_equal(x.animations[0], a), assert_null(x.animations[1]);
    rf_quat q = rf_gw_axes_turn(s->up, s->forward);
    near(rf_quat_rotate(q, rf_v3(0, 0, 1)), 0, 1, 0); /* Z up, +X front: (x, y, z) -> (y, z, x) */
    near(rf_quat_rotate(q, rf_v3(1, 0, 0)), 0, 0, 1);
    for (uint32_t f = 0; f < 3; f++)
        for (uint32_t v = 0; v < 4; v++)
            near_tol(skinned(x.skeleton, x.animations[0], x.mesh, f, v),
                     rf_quat_rotate(q, skinned(s, a, m, f, v)), 1e-5);
    for (uint32_t v = 0; v < 4; v++) { /* the rest pose too, and the raw attributes */
        near_tol(skinned(x.skeleton, NULL, x.mesh, 0, v),
                 rf_quat_rotate(q, skinned(s, NULL, m, 0, v)), 1e-5);
        const float *n = m->normals + v * 3, *t = m->tangents + v * 4;
        const float *d = m->morph_targets[0]->positions + v * 3;
        const float *dn = m->morph_targets[0]->normals + v * 3;
        near_tol(
            rf_v3(x.mesh->normals[v * 3], x.mesh->normals[v * 3 + 1], x.mesh->normals[v * 3 + 2]),
            rf_quat_rotate(q, rf_v3(n[0], n[1], n[2])), 1e-6);
        near_tol(rf_v3(x.mesh->tangents[v * 4], x.mesh->tangents[v * 4 + 1],
                       x.mesh->tangents[v * 4 + 2]),
                 rf_quat_rotate(q, rf_v3(t[0], t[1], t[2])), 1e-6);
        assert_float_equal(x.mesh->tangents[v * 4 + 3], t[3], 0);
        const float *xd = x.mesh->morph_targets[0]->positions + v * 3;
        const float *xdn = x.mesh->morph_targets[0]->normals + v * 3;
        near_tol(rf_v3(xd[0], xd[1], xd[2]), rf_quat_rotate(q, rf_v3(d[0], d[1], d[2])), 1e-6);
        near_tol(rf_v3(xdn[0], xdn[1], xdn[2]), rf_quat_rotate(q, rf_v3(dn[0], dn[1], dn[2])),
                 1e-6);
    }
    assert_memory_equal(x.animations[0]->channels, a->channels, 4); /* what the source keyed */
    near(x.skeleton->up, 0, 1, 0), near(x.skeleton->forward, 0, 0, 1);
    near_tol(x.skeleton->joints[0].rest.s, rf_v3(1, 2, 0.5), 0); /* scale is the root's own */
    rf_gw_axes_clear(&x, 2);
    rf_animation_free(a), rf_mesh_free(m), rf_skeleton_free(s);
}

static void several_roots_and_clips(void **state)
{
    (void)state;
    check_turned(4);
}

/* An inverse_bind of another count than the joints is not the skin's (the writer binds at rest) */
static void other_bind_count(void **state)
{
    (void)state;
    check_turned(3);
}

/* glTF's own axes, or none declared: the caller's data is written, no copy made (the writer's
 * speed and its bytes stay as they were). */
static void no_copy_on_gltf_axes(void **state)
{
    (void)state;
    rf_skeleton *s = two_roots();
    rf_animation *a = clip_of(s);
    rf_mesh *m = skin_of(s, 4);
    const rf_animation *clips[1] = {a};
    rf_vec3 axes[3][2] = {{{0, 1, 0}, {0, 0, 1}}, {{0, 0, 0}, {0, 0, 0}}, {{0, 2, 0}, {0, 0, 3}}};
    for (int i = 0; i < 3; i++) {
        s->up = axes[i][0], s->forward = axes[i][1];
        rf_gw_axes x;
        assert_true(rf_gw_axes_conform(&x, s, clips, 1, m));
        assert_ptr_equal(x.skeleton, s), assert_ptr_equal(x.mesh, m);
        assert_ptr_equal(x.animations[0], a);
        assert_null(x.own_skeleton), assert_null(x.own_mesh), assert_null(x.own_animations);
        rf_gw_axes_clear(&x, 1);
    }
    rf_animation_free(a), rf_mesh_free(m), rf_skeleton_free(s);
}

/* A facing that is not a number is no facing: the content is still stood up on its declared up,
 * as with a zero facing; an up that is not a number turns nothing. */
static void nan_axes(void **state)
{
    (void)state;
    near(rf_quat_rotate(rf_gw_axes_turn(rf_v3(0, 0, 1), rf_v3(NAN, 0, 0)), rf_v3(0, 0, 1)), 0, 1,
         0);
    near(rf_quat_rotate(rf_gw_axes_turn(rf_v3(0, 0, 1), rf_v3(INFINITY, 0, 1)), rf_v3(0, 0, 1)), 0,
         1, 0);
    near(rf_quat_rotate(rf_gw_axes_turn(rf_v3(0, NAN, 1), rf_v3(1, 0, 0)), rf_v3(1, 2, 3)), 1, 2,
         3);
}

/* Whether `text` holds a control byte (a raw ESC or BEL from a hostile name). */
static bool has_control(const char *text)
{
    for (const unsigned char *c = (const unsigned char *)text; *c; c++)
        if (*c < 0x20 || *c == 0x7f)
            return true;
    return false;
}

/* The writer refuses, naming the joint and writing nothing, a skeleton it cannot write as glTF:
 * a parent after its child (the contract of rigflow/model.h, unchecked by the host) and a rest
 * pose that is not finite (JSON has no NaN: the number was dropped from the node, leaving a
 * two-number translation that readers reject). The joint is named by its index and by its name
 * from the file, escaped: a name that sets a terminal's title reaches the message as text. */
static void refuses_broken_skeleton(void **state)
{
    (void)state;
    char dir[] = "/tmp/rf-axes-XXXXXX", path[64], err[512];
    assert_non_null(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/out.gltf", dir);
    rf_skeleton *s = two_roots();
    s->up = rf_v3(0, 1, 0), s->forward = rf_v3(0, 0, 1);
    s->joints[1].name = strdup("knee\x1b]0;owned\x07");
    s->joints[3].name = strdup("toe");
    assert_true(rf_gltf_write_file(path, NULL, s, NULL, NULL, NULL, err, sizeof err));
    assert_int_equal(unlink(path), 0);
    s->joints[3].parent = 3;
    assert_false(rf_gltf_write_file(path, "out.gltf", s, NULL, NULL, NULL, err, sizeof err));
    assert_string_equal(err, "out.gltf: joint 3 'toe' has parent 3 'toe': expected parents "
                             "before children");
    assert_int_not_equal(access(path, F_OK), 0);
    s->joints[3].parent = 7; /* past the end: no name to give, its index only */
    assert_false(rf_gltf_write_file(path, "out.gltf", s, NULL, NULL, NULL, err, sizeof err));
    assert_non_null(strstr(err, "joint 3 'toe' has parent 7 '#7'"));
    s->joints[3].parent = 2;
    for (int k = 0; k < 3; k++) {
        rf_xform keep = s->joints[1].rest;
        double *v[3] = {&s->joints[1].rest.t.y, &s->joints[1].rest.r.z, &s->joints[1].rest.s.x};
        *v[k] = NAN;
        assert_false(rf_gltf_write_file(path, "out.gltf", s, NULL, NULL, NULL, err, sizeof err));
        assert_string_equal(err, "out.gltf: joint 1 'knee\\x1b]0;owned\\x07': its rest pose is "
                                 "not finite");
        assert_false(has_control(err));
        assert_int_not_equal(access(path, F_OK), 0);
        s->joints[1].rest = keep;
    }
    /* a joint with no name: its index stands in */
    free(s->joints[1].name), s->joints[1].name = NULL;
    s->joints[1].rest.t.x = INFINITY;
    assert_false(rf_gltf_write_file(path, "out.gltf", s, NULL, NULL, NULL, err, sizeof err));
    assert_string_equal(err, "out.gltf: joint 1 '#1': its rest pose is not finite");
    s->joints[1].rest.t.x = 0;
    /* a clip's name comes from a file too */
    rf_animation *a = clip_of(s);
    a->name = strdup("walk\x1b[2J");
    a->fps = 0;
    assert_false(rf_gltf_write_file(path, "out.gltf", s, a, NULL, NULL, err, sizeof err));
    assert_string_equal(err, "out.gltf: animation 0 'walk\\x1b[2J': fps must be > 0 (got 0)");
    assert_int_not_equal(access(path, F_OK), 0);
    rf_animation_free(a);
    rmdir(dir);
    rf_skeleton_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(turns_by_hand),           cmocka_unit_test(round_trip),
        cmocka_unit_test(several_roots_and_clips), cmocka_unit_test(other_bind_count),
        cmocka_unit_test(no_copy_on_gltf_axes),    cmocka_unit_test(nan_axes),
        cmocka_unit_test(refuses_broken_skeleton),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
