/* Assimp import (librfassimp) on every model in $RF_DATA_DIR/models, and GLB export (librfgltf)
 * checked by the Khronos glTF-Validator and by re-importing.
 *
 * Expected values come from outside rigflow's code:
 * - joint counts: ../shared/data/README.md's table of rigged models (vrm_sample: its 27 nodes
 *   less the 4 mesh nodes, since a node tree without skin becomes a skeleton of its transform
 *   nodes);
 * - root joint: the rig's top node in `assimp info FILE`'s node hierarchy;
 * - clip counts and joint positions: printed by tests/import/expected.py, which reads the glTF
 *   JSON itself (node TRS composed down the scene) or, for the other formats, the XML of
 *   `assimp dump FILE` (node matrices composed down the tree). Positions are world positions of
 *   the node rest pose, so they are compared with rest_pose=node;
 * - girl.glb bind pose: the inverse of the skin's inverseBindMatrices read from the file (same
 *   script, see test_bind_pose);
 * - durations: the glTF animation input accessors' max, and `assimp dump`'s duration/tick_cnt.
 * Tests skip with a message when $RF_DATA_DIR is absent.
 */
#ifndef _DEFAULT_SOURCE
#define _DEFAULT_SOURCE /* popen, mkstemps */
#endif
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmocka.h>

#include "validate.h"

#include "rigflow/aimport.h"
#include "rigflow/gltf-write.h"

typedef struct rf_expected_pos {
    const char *joint;
    double x, y, z;
} rf_expected_pos;

typedef struct rf_expected_model {
    const char *file;
    unsigned joints;
    const char *root;
    unsigned clips;
    rf_expected_pos pos[3];
} rf_expected_model;

/* clang-format off */
static const rf_expected_model rf_models[] = {
    {"BCN_Epileptic.X", 54, "B_Root_Pelvis_L", 1,
     {{"B_Root_Pelvis_L", 0, 0.038155, -0.12913}, {"B_Hand_Right", -0.267494, -0.0701603, -0.130333},
      {"B_Cheek_Right", -0.0341804, 0.604453, -0.0491048}}},
    {"Fox.glb", 24, "_rootJoint", 3,
     {{"_rootJoint", 0, 0, 0}, {"b_LeftHand_011", 6.94305, 6.69459, 17.8388},
      {"b_RightFoot02_022", -6.96533, 0.984619, -32.8871}}},
    {"RiggedFigure.glb", 19, "nodes[2]", 1,
     {{"nodes[2]", 2.79397e-09, 0.686, 1.41566e-07}, {"nodes[14]", -0.306, 0.964, -0.0229996},
      {"nodes[6]", -0.0795761, 0.022, 0.0324999}}},
    {"RobotExpressive.glb", 43, "Bone", 14,
     {{"Bone", -0.00319546, -0.00588517, -0.195048}, {"Ring2.L", 3.15171, 2.26435, 0.302121},
      {"PoleTarget.R", -0.648434, 1.0522, 1.51444}}},
    {"Testwuson.X", 38, "Root", 3,
     {{"Root", 0, 0.522834, -0.009935}, {"Spine_Front01", 0, 1.06549, 0.032932},
      {"ForeLeg_R_05", -0.274943, 0.112701, 0.59689}}},
    {"Wizard.glb", 32, "Root", 11,
     {{"Root", -0.00131147, -0.00241537, -0.000114684}, {"Shoulder.R", -0.125464, 1.67409, 0.0239134},
      {"PoleTarget.R", -0.210007, 0.722117, 0.963032}}},
    {"animation_with_skeleton.fbx", 15, "Armature", 1,
     {{"Armature", -3614.02, 0, 0}, {"Bone.006", -829.07, 365.023, 0.00249111},
      {"Bone.013", 2949.14, 3.62107, 0.00306785}}},
    {"creatures/animala_horse.b3d", 16, "cube", 1,
     {{"cube", 0, 0, 0}, {"Leg.FrontA.L", -0.25, 1.45, -0.75}, {"Leg.BackB.R", 0.25, 0.71, 0.75}}},
    {"creatures/animalia_angelfish.b3d", 2, "Body", 1,
     {{"Body", 0, 0.2, -0.1}, {"Tail", 0, 0.2, 0.13}, {"Tail", 0, 0.2, 0.13}}},
    {"creatures/animalia_bat.b3d", 15, "cube.003", 1,
     {{"cube.003", 0, 0, 0}, {"Leg.L", -0.094, 0.03, 0.17}, {"Wing.L.GP", -0.126, 0.125, -0.11}}},
    {"creatures/animalia_bird.b3d", 13, "cube.002", 1,
     {{"cube.002", 0, 0, 0}, {"LowerWing.L", -0.374, 0.439, -0.0249878},
      {"Leg.L.IK", -0.063, 0.017, 0.062013}}},
    {"creatures/animalia_bull_frog.b3d", 15, "cube", 1,
     {{"cube", 0, 0, 0}, {"Arm.L", -0.28, 0.25, -0.156}, {"Shoulder.L", -0.28, 0.25, -0.156}}},
    {"creatures/animalia_cat.b3d", 14, "Root", 1,
     {{"Root", 0, 0.8, 0.125}, {"Arm.R", 0.126, 0.28, -0.250001}, {"Shoulder.L", -0.126, 0.28, -0.25}}},
    {"creatures/animalia_fox.b3d", 9, "Torso", 1,
     {{"Torso", 0.045, 0.25, 0.2516}, {"Leg.Rear.R", 0.125, 0.25, 0.2516}, {"Tail", 0.045, 0.55752, 0.3028}}},
    {"creatures/animalia_owl.b3d", 8, "Torso", 1,
     {{"Torso", 0, 0.25, 0.03}, {"Leg.R", 0.126, 0.25, 0.03}, {"Leg.L", -0.126, 0.25, 0.03}}},
    {"creatures/animalia_wolf.b3d", 14, "Root", 1,
     {{"Root", 0, 1.1, 0.125}, {"Arm.R", 0.126, 0.44, -0.31}, {"Shoulder.L", -0.126, 0.44, -0.31}}},
    {"creatures/draconis_fire_dragon.b3d", 41, "cube.002", 1,
     {{"cube.002", 0, 0, 0}, {"Neck.2", 0, 2.102, -2.099}, {"Leg.IK.L", -0.5, 0.16, 0.5}}},
    {"creatures/draconis_jungle_wyvern.b3d", 41, "cube.052", 1,
     {{"cube.052", 0, 0, 0}, {"Head", 0, 2.2, -2.9}, {"Wing.IK.L", -3.653, 2.0625, -2.125}}},
    {"girl.glb", 24, "Armature", 2,
     {{"Armature", 0, 0.622455, 0}, {"LowerArm.R", -0.208459, 0.930297, 0.231959},
      {"IKLegTarget.R", -0.0295907, 0.372379, -0.490196}}},
    {"greenman.glb", 13, "Armature", 4,
     {{"Armature", 0, 0, 0}, {"hand_R", -0.796805, 0.757933, -0.0353015},
      {"socket_hand_R", -1.3112, 0.662115, -0.0100863}}},
    {"huesitos.fbx", 10, "Armature", 1,
     {{"Armature", -4.024, 0, -307.135}, {"Bone.005", 199.443, 211.188, -388.825},
      {"Bone.008", -4.024, 462.308, -307.135}}},
    {"ogre/fish.mesh", 5, "Bone01", 1,
     {{"Bone01", -3.95093, 0, 0.002657}, {"Bone02", -0.98531, 7.32e-08, 0.020957},
      {"Bone04", 2.71064, -6.85797e-06, -1.71184}}},
    {"ogre/ninja.mesh", 28, "Joint1", 20,
     {{"Joint1", 0.185046, 0.51196, 0}, {"Joint14", -14.158, 159.936, 5.74418},
      {"Joint27", -13.4503, 0.450196, -11.4725}}},
    {"simple_skin.gltf", 2, "nodes[1]", 1,
     {{"nodes[1]", 0, 1, 0}, {"nodes[2]", 0, 1, 0}, {"nodes[2]", 0, 1, 0}}},
    {"vrm_sample.glb", 23, "Hips", 0,
     {{"Hips", 0, 0.5, 0}, {"Shoulder.L", 0.1, 1, 0}, {"Toes.L", 0.1, -1.06821e-08, 0.1}}},
};
/* clang-format on */

static const char *rf_data_dir(void)
{
    const char *d = getenv("RF_DATA_DIR");
    static char buf[4096];
    snprintf(buf, sizeof buf, "%s/models/Fox.glb", d ? d : "");
    return d && access(buf, R_OK) == 0 ? d : NULL;
}

#define RF_NEED_DATA()                                                                             \
    do {                                                                                           \
        if (!rf_data_dir()) {                                                                      \
            print_message("RF_DATA_DIR/models not found (../shared/data): skipped\n");             \
            skip();                                                                                \
        }                                                                                          \
    } while (0)

static char *rf_model(const char *file)
{
    static char buf[4096];
    snprintf(buf, sizeof buf, "%s/models/%s", rf_data_dir(), file);
    return buf;
}

static void rf_import_ok(const char *path, const rf_ai_options *o, rf_ai_result *r)
{
    char err[1024] = "";
    bool ok = rf_ai_import(path, o, r, NULL, NULL, err, sizeof err);
    if (!ok)
        print_error("%s\n", err);
    assert_true(ok);
}

static rf_vec3 rf_world(const rf_skeleton *s, const char *joint)
{
    int32_t j = rf_skeleton_find(s, joint);
    if (j < 0)
        print_error("no joint '%s'\n", joint);
    assert_true(j >= 0);
    rf_xform *w = calloc(s->joint_count, sizeof *w);
    assert_non_null(w);
    rf_skeleton_world_rest(s, w);
    rf_vec3 p = w[j].t;
    free(w);
    return p;
}

static void rf_assert_near(rf_vec3 got, double x, double y, double z, double rel, const char *what)
{
    rf_vec3 want = rf_v3(x, y, z);
    double tol = rel * fmax(1.0, rf_v3_len(want));
    if (rf_v3_dist(got, want) > tol)
        print_error("%s: got (%g %g %g), expected (%g %g %g)\n", what, got.x, got.y, got.z, x, y,
                    z);
    assert_true(rf_v3_dist(got, want) <= tol);
}

/* ---- every model ---- */

static void rf_check_names_unique(const rf_skeleton *s)
{
    for (uint32_t i = 0; i < s->joint_count; i++) {
        assert_non_null(s->joints[i].name);
        assert_int_equal(rf_skeleton_find(s, s->joints[i].name), (int32_t)i);
        assert_true(s->joints[i].parent < (int32_t)i);
    }
}

static void test_every_model(void **state)
{
    (void)state;
    RF_NEED_DATA();
    for (size_t i = 0; i < sizeof rf_models / sizeof *rf_models; i++) {
        const rf_expected_model *e = &rf_models[i];
        rf_ai_options o = {.rest = RF_AI_REST_NODE, .require_skeleton = true};
        rf_ai_result r;
        print_message("%s\n", e->file);
        rf_import_ok(rf_model(e->file), &o, &r);
        assert_int_equal(r.skeleton->joint_count, e->joints);
        assert_string_equal(r.skeleton->joints[0].name, e->root);
        assert_int_equal(r.skeleton->joints[0].parent, -1);
        assert_int_equal(r.clip_count, e->clips);
        rf_check_names_unique(r.skeleton);
        for (int k = 0; k < 3; k++)
            rf_assert_near(rf_world(r.skeleton, e->pos[k].joint), e->pos[k].x, e->pos[k].y,
                           e->pos[k].z, 1e-4, e->pos[k].joint);
        assert_int_equal(r.animation->joint_count, e->joints);
        assert_true(r.animation->frame_count >= 1);
        rf_ai_result_clear(&r);
    }
}

/* ---- refusals and traps ---- */

static void test_spider_refused_where_skeleton_required(void **state)
{
    (void)state;
    RF_NEED_DATA();
    rf_ai_options o = {.require_skeleton = true};
    rf_ai_result r;
    char err[1024];
    assert_false(rf_ai_import(rf_model("spider.fbx"), &o, &r, NULL, NULL, err, sizeof err));
    assert_non_null(strstr(err, "spider.fbx"));
    assert_non_null(strstr(err, "no skeleton"));
    assert_null(r.skeleton);
    /* Where only a mesh is wanted it imports: 20 rigid parts per the data README (19 meshes,
     * one instanced twice, per `assimp info`), not skinned. */
    o.require_skeleton = false;
    rf_import_ok(rf_model("spider.fbx"), &o, &r);
    assert_int_equal(r.skeleton->joint_count, 0);
    assert_non_null(r.mesh);
    assert_true(r.mesh->vertex_count > 0);
    assert_null(r.mesh->skin_joints);
    assert_true(r.mesh->part_count >= 19);
    rf_ai_result_clear(&r);
}

static void test_missing_file_named(void **state)
{
    (void)state;
    rf_ai_result r;
    char err[1024];
    assert_false(rf_ai_import("/nonexistent/model.glb", NULL, &r, NULL, NULL, err, sizeof err));
    assert_non_null(strstr(err, "/nonexistent/model.glb"));
}

/* .x is left-handed in the file; what comes out must be right-handed: with up +Y and the toes
 * ahead of the ankles giving the facing, the left hip lies on up x forward (the left in a
 * right-handed frame). */
static void test_x_comes_out_right_handed(void **state)
{
    (void)state;
    RF_NEED_DATA();
    rf_ai_result r;
    rf_import_ok(rf_model("BCN_Epileptic.X"), NULL, &r);
    const rf_skeleton *s = r.skeleton;
    rf_vec3 fwd = rf_v3_sub(rf_world(s, "B_Toe_Left"), rf_world(s, "B_Ankle_Left"));
    fwd.y = 0;
    rf_vec3 left = rf_v3_sub(rf_world(s, "B_Hip_Left"), rf_world(s, "B_Hip_Right"));
    assert_true(rf_v3_dot(rf_v3_cross(rf_v3(0, 1, 0), fwd), left) > 0);
    rf_ai_result_clear(&r);
}

/* B3D creatures fail Assimp's validation (a key one tick past the end): imported anyway, keys
 * clamped. `assimp dump` gives the horse's clip duration="220" tick_cnt="60": 220/60 s, resampled
 * at 60 fps (keys on every tick) = 221 frames. */
static void test_b3d_imports_with_keys_clamped(void **state)
{
    (void)state;
    RF_NEED_DATA();
    rf_ai_result r;
    rf_import_ok(rf_model("creatures/animala_horse.b3d"), NULL, &r);
    assert_int_equal(r.clip_count, 1);
    assert_true(fabs(r.clips[0].duration - 220.0 / 60.0) < 1e-9);
    assert_true(fabs(r.animation->fps - 60.0) < 1e-9);
    assert_int_equal(r.animation->frame_count, 221);
    rf_ai_result_clear(&r);
}

/* glTF times are seconds in the file and milliseconds in Assimp. Fox's clips, from the animation
 * input accessors' max: Survey 3.4166667 s (83 keys), Walk 0.7083333 s (18), Run 1.1583333 s. */
static void test_gltf_clips_in_seconds(void **state)
{
    (void)state;
    RF_NEED_DATA();
    rf_ai_result r;
    rf_ai_options o = {.clip = "Walk"};
    rf_import_ok(rf_model("Fox.glb"), &o, &r);
    assert_int_equal(r.clip_count, 3);
    assert_string_equal(r.clips[0].name, "Survey");
    assert_string_equal(r.clips[1].name, "Walk");
    assert_string_equal(r.clips[2].name, "Run");
    assert_true(fabs(r.clips[0].duration - 3.4166667) < 1e-4);
    assert_true(fabs(r.clips[1].duration - 0.7083333) < 1e-4);
    assert_true(fabs(r.clips[2].duration - 1.1583333) < 1e-4);
    assert_int_equal(r.selected_clip, 1);
    assert_string_equal(r.animation->name, "Walk");
    assert_true(fabs(r.animation->fps - 24.0) < 1e-9); /* keys every 1/24 s */
    assert_int_equal(r.animation->frame_count, 18);
    float first = r.animation->rotations[4 * 5];
    rf_ai_result_clear(&r);
    o.clip = "1"; /* the same clip by index */
    rf_import_ok(rf_model("Fox.glb"), &o, &r);
    assert_string_equal(r.animation->name, "Walk");
    assert_true(r.animation->rotations[4 * 5] == first);
    rf_ai_result_clear(&r);
    char err[1024];
    o.clip = "Gallop";
    assert_false(rf_ai_import(rf_model("Fox.glb"), &o, &r, NULL, NULL, err, sizeof err));
    assert_non_null(strstr(err, "Fox.glb"));
    assert_non_null(strstr(err, "'Survey'"));
}

/* girl.glb's node rest differs from its bind pose. Bind world positions are the inverses of the
 * skin's inverseBindMatrices in the file: Root (0, 0.622455, 0), Head (0, 1.183759, 0), Foot.L
 * (0.029591, 0.027044, -0.013102); node rest world Head is (0.0231015, 1.1625, 0.146439). */
static void test_bind_pose(void **state)
{
    (void)state;
    RF_NEED_DATA();
    rf_ai_result r;
    rf_import_ok(rf_model("girl.glb"), NULL, &r); /* default: bind */
    const rf_skeleton *s = r.skeleton;
    assert_int_equal(s->rest_source, RF_REST_BIND);
    assert_non_null(s->bind);
    rf_assert_near(rf_world(s, "Root"), 0, 0.622455, 0, 1e-5, "Root");
    rf_assert_near(rf_world(s, "Head"), 0, 1.183759, 0, 1e-5, "Head");
    rf_assert_near(rf_world(s, "Foot.L"), 0.029591, 0.027044, -0.013102, 1e-5, "Foot.L");
    rf_ai_result_clear(&r);
    rf_ai_options o = {.rest = RF_AI_REST_NODE};
    rf_import_ok(rf_model("girl.glb"), &o, &r);
    assert_int_equal(r.skeleton->rest_source, RF_REST_NODE);
    assert_non_null(r.skeleton->bind); /* both poses are there */
    rf_assert_near(rf_world(r.skeleton, "Head"), 0.0231015, 1.1625, 0.146439, 1e-5, "Head");
    rf_ai_result_clear(&r);
}

/* Helpers stay joints, flagged unweighted: girl's IK targets and poles (skin joints with no
 * weight), the wolf's hip and shoulder helpers (animated nodes beside the body). */
static void test_helpers_unweighted(void **state)
{
    (void)state;
    RF_NEED_DATA();
    rf_ai_result r;
    rf_import_ok(rf_model("girl.glb"), NULL, &r);
    const rf_skeleton *s = r.skeleton;
    assert_true(s->joints[rf_skeleton_find(s, "IKLegTarget.L")].flags & RF_JOINT_UNWEIGHTED);
    assert_true(s->joints[rf_skeleton_find(s, "IKLegPole.R")].flags & RF_JOINT_UNWEIGHTED);
    assert_false(s->joints[rf_skeleton_find(s, "Head")].flags & RF_JOINT_UNWEIGHTED);
    rf_ai_result_clear(&r);
    rf_import_ok(rf_model("creatures/animalia_wolf.b3d"), NULL, &r);
    s = r.skeleton;
    assert_true(s->joints[rf_skeleton_find(s, "Hip.R")].flags & RF_JOINT_UNWEIGHTED);
    assert_false(s->joints[rf_skeleton_find(s, "Head")].flags & RF_JOINT_UNWEIGHTED);
    rf_ai_result_clear(&r);
}

/* A leaf without an end site ends where the skin it carries ends. The animalia fox's legs are
 * boxes hung from pivots at the body's middle height, the hind ones beside the torso's pivot: a
 * guess from the parent's distance put the hind legs' tips 0.06 to the side at the pivot's
 * height. Each leg's box reaches the floor, so its tip lies at the mesh's lowest point (measured
 * here from the vertices), under the pivot; a joint with children gets no end site. */
static void test_leaf_ends_from_skin(void **state)
{
    (void)state;
    RF_NEED_DATA();
    rf_ai_result r;
    rf_import_ok(rf_model("creatures/animalia_fox.b3d"), NULL, &r);
    const rf_skeleton *s = r.skeleton;
    const rf_mesh *m = r.mesh;
    double low = INFINITY, high = -INFINITY;
    for (uint32_t v = 0; v < m->vertex_count; v++)
        low = fmin(low, m->positions[(size_t)v * 3 + 1]),
        high = fmax(high, m->positions[(size_t)v * 3 + 1]);
    rf_xform *w = calloc(s->joint_count, sizeof *w);
    assert_non_null(w);
    rf_skeleton_world_rest(s, w);
    const char *legs[] = {"Leg.Rear.R", "Leg.Rear.L", "Leg.Front.R", "Leg.Front.L"};
    for (int i = 0; i < 4; i++) {
        int32_t j = rf_skeleton_find(s, legs[i]);
        assert_true(j >= 0);
        assert_true(s->joints[j].flags & RF_JOINT_HAS_END_SITE);
        rf_vec3 tip = rf_xform_point(w[j], s->joints[j].end_site), at = w[j].t;
        if (fabs(tip.y - low) > 0.02 * (high - low))
            print_error("%s: tip at height %g, the mesh's lowest point %g\n", legs[i], tip.y, low);
        assert_true(fabs(tip.y - low) <= 0.02 * (high - low));
        assert_true(hypot(tip.x - at.x, tip.z - at.z) < 0.5 * (at.y - tip.y));
    }
    assert_false(s->joints[rf_skeleton_find(s, "Torso")].flags & RF_JOINT_HAS_END_SITE);
    free(w);
    rf_ai_result_clear(&r);
}

/* BCN_Epileptic: three meshes (Torso, Head, Legs) share one skeleton. `assimp info -r FILE`
 * (raw, no post-processing) counts 15378 vertices and 5126 faces in all. */
static void test_meshes_share_one_skeleton(void **state)
{
    (void)state;
    RF_NEED_DATA();
    rf_ai_result r;
    rf_import_ok(rf_model("BCN_Epileptic.X"), NULL, &r);
    const rf_mesh *m = r.mesh;
    assert_non_null(m);
    assert_int_equal(m->part_count, 3);
    assert_int_equal(m->vertex_count, 15378);
    assert_int_equal(m->triangle_count, 5126);
    assert_int_equal(m->bind_count, r.skeleton->joint_count);
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        double sum = 0;
        for (int k = 0; k < 4; k++) {
            assert_true(m->skin_joints[v * 4 + k] < r.skeleton->joint_count);
            sum += m->skin_weights[v * 4 + k];
        }
        assert_true(fabs(sum - 1.0) < 1e-5);
    }
    rf_ai_result_clear(&r);
}

static void test_axes(void **state)
{
    (void)state;
    RF_NEED_DATA();
    rf_ai_result r;
    rf_import_ok(rf_model("Fox.glb"), NULL, &r); /* glTF 2.0: +Y up, front +Z */
    assert_true(rf_v3_dist(r.skeleton->up, rf_v3(0, 1, 0)) < 1e-12);
    assert_true(rf_v3_dist(r.skeleton->forward, rf_v3(0, 0, 1)) < 1e-12);
    /* the Fox's head is ahead of its tail along +Z (data README: glTF faces +Z) */
    assert_true(rf_world(r.skeleton, "b_Head_05").z > rf_world(r.skeleton, "b_Tail03_014").z);
    rf_ai_result_clear(&r);
    rf_import_ok(rf_model("creatures/animalia_wolf.b3d"), NULL, &r); /* B3D declares no facing */
    assert_true(rf_v3_dist(r.skeleton->up, rf_v3(0, 1, 0)) < 1e-12);
    assert_true(rf_v3_len(r.skeleton->forward) == 0);
    rf_ai_result_clear(&r);
}

/* ---- GLB export: validator and round trip ---- */

/* Angle between two rotations, accurate near zero (2 acos of a dot product near 1 is not). */
static double rf_rot_diff(rf_quat a, rf_quat b)
{
    rf_quat d = rf_quat_mul(rf_quat_conj(rf_quat_normalize(a)), rf_quat_normalize(b));
    return 2.0 * atan2(sqrt(d.x * d.x + d.y * d.y + d.z * d.z), fabs(d.w));
}

static double rf_max_motion_error(const rf_animation *a, const rf_animation *b)
{
    double worst = 0;
    for (uint32_t f = 0; f < a->frame_count; f++)
        for (uint32_t j = 0; j < a->joint_count; j++) {
            double ang =
                rf_rot_diff(rf_animation_rotation(a, f, j), rf_animation_rotation(b, f, j));
            worst = fmax(worst, ang);
        }
    return worst;
}

static void rf_round_trip(const char *file, const char *clip)
{
    rf_ai_options o = {.clip = clip};
    rf_ai_result a, b;
    rf_import_ok(rf_model(file), &o, &a);
    char out[] = "/tmp/rf-test-XXXXXX.glb", err[1024];
    int fd = mkstemps(out, 4);
    assert_true(fd >= 0);
    close(fd);
    bool ok = rf_gltf_write_file(out, NULL, a.skeleton, a.animation, a.mesh, NULL, err, sizeof err);
    if (!ok)
        print_error("%s\n", err);
    assert_true(ok);
    rf_gltf_check_valid(out);
    rf_import_ok(out, NULL, &b);
    assert_int_equal(b.skeleton->joint_count, a.skeleton->joint_count);
    rf_xform *wa = calloc(a.skeleton->joint_count, sizeof *wa);
    rf_xform *wb = calloc(a.skeleton->joint_count, sizeof *wb);
    rf_skeleton_world_rest(a.skeleton, wa);
    rf_skeleton_world_rest(b.skeleton, wb);
    double extent = 1e-9;
    for (uint32_t j = 0; j < a.skeleton->joint_count; j++)
        extent = fmax(extent, rf_v3_len(wa[j].t));
    for (uint32_t j = 0; j < a.skeleton->joint_count; j++) {
        assert_string_equal(a.skeleton->joints[j].name, b.skeleton->joints[j].name);
        assert_int_equal(a.skeleton->joints[j].parent, b.skeleton->joints[j].parent);
        assert_true(rf_v3_dist(wa[j].t, wb[j].t) < 1e-5 * extent);
    }
    free(wa), free(wb);
    assert_int_equal(b.animation->frame_count, a.animation->frame_count);
    assert_true(fabs(b.animation->fps - a.animation->fps) < 1e-9);
    assert_true(rf_max_motion_error(a.animation, b.animation) < 1e-4);
    assert_int_equal(b.mesh->vertex_count, a.mesh->vertex_count);
    rf_ai_result_clear(&a), rf_ai_result_clear(&b);
    unlink(out);
}

static void test_glb_fox(void **state)
{
    (void)state;
    RF_NEED_DATA();
    rf_round_trip("Fox.glb", "Walk");
}

static void test_glb_rigged_figure(void **state)
{
    (void)state;
    RF_NEED_DATA();
    rf_round_trip("RiggedFigure.glb", NULL);
}

static void test_glb_shared_skeleton(void **state)
{
    (void)state;
    RF_NEED_DATA();
    rf_round_trip("BCN_Epileptic.X", NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_model),
        cmocka_unit_test(test_spider_refused_where_skeleton_required),
        cmocka_unit_test(test_missing_file_named),
        cmocka_unit_test(test_x_comes_out_right_handed),
        cmocka_unit_test(test_b3d_imports_with_keys_clamped),
        cmocka_unit_test(test_gltf_clips_in_seconds),
        cmocka_unit_test(test_bind_pose),
        cmocka_unit_test(test_helpers_unweighted),
        cmocka_unit_test(test_leaf_ends_from_skin),
        cmocka_unit_test(test_meshes_share_one_skeleton),
        cmocka_unit_test(test_axes),
        cmocka_unit_test(test_glb_fox),
        cmocka_unit_test(test_glb_rigged_figure),
        cmocka_unit_test(test_glb_shared_skeleton),
    };
    return rf_gltf_exit_status(cmocka_run_group_tests_name("import", tests, NULL, NULL));
}
