/* Joint roles (sdk/analysis/roles.c) on a hand-built IK-style biped whose answers are known
 * by construction: a placement root on the floor carrying the feet, a pole in front of a knee, an
 * IK target on a foot, a socket on the head, an axis-and-unit conversion node inside the spine;
 * the same roles with the names removed; a clip that turns the root makes it body. Then the
 * shared data's IK rigs (skipped without $RF_DATA_DIR). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <unistd.h>

#include <cmocka.h>

#include "rigflow/aimport.h"
#include "rigflow/analysis.h"
#include "rt-fixtures.h"

enum {
    ROOT,
    HIPS,
    AXIS,
    SPINE,
    HEAD,
    THIGH_L,
    SHIN_L,
    FOOT_L,
    THIGH_R,
    SHIN_R,
    FOOT_R,
    POLE_L,
    TARGET_L,
    SOCKET,
    N
};

static rf_skeleton *ik_biped(void)
{
    rf_skeleton *s = rf_skeleton_new(N);
    rf_quat id = rf_quat_identity();
    fx_joint(s, ROOT, "a", -1, rf_v3(0, 0, 0), id);
    fx_joint(s, HIPS, "b", ROOT, rf_v3(0, 1, 0), id);
    /* A conversion node at the spine's pivot: turned 90 degrees and scaled 100 times; the spine
     * under it undoes both (its world scale is 1 again), so the body is unchanged. */
    fx_joint(s, AXIS, "c", HIPS, rf_v3(0, 0.1, 0), fx_rot(rf_v3(1, 0, 0), 90));
    s->joints[AXIS].rest.s = rf_v3(100, 100, 100);
    fx_joint(s, SPINE, "d", AXIS, rf_v3(0, 0, 0), fx_rot(rf_v3(1, 0, 0), -90));
    s->joints[SPINE].rest.s = rf_v3(0.01, 0.01, 0.01);
    fx_joint(s, HEAD, "e", SPINE, rf_v3(0, 0.5, 0), id);
    fx_joint(s, THIGH_L, "f", HIPS, rf_v3(0.2, 0, 0), id);
    fx_joint(s, SHIN_L, "g", THIGH_L, rf_v3(0, -0.5, 0), id);
    fx_joint(s, FOOT_L, "h", ROOT, rf_v3(0.2, 0.05, 0), id);
    fx_joint(s, THIGH_R, "i", HIPS, rf_v3(-0.2, 0, 0), id);
    fx_joint(s, SHIN_R, "j", THIGH_R, rf_v3(0, -0.5, 0), id);
    fx_joint(s, FOOT_R, "k", ROOT, rf_v3(-0.2, 0.05, 0), id);
    fx_joint(s, POLE_L, "l", ROOT, rf_v3(0.2, 0.5, 0.6), id);
    fx_joint(s, TARGET_L, "m", ROOT, rf_v3(0.2, 0.05, 0), id);
    fx_joint(s, SOCKET, "n", HEAD, rf_v3(0, 0.3, 0), id);
    fx_end_site(s, HEAD, rf_v3(0, 0.2, 0));
    fx_end_site(s, FOOT_L, rf_v3(0, 0, 0.2));
    fx_end_site(s, FOOT_R, rf_v3(0, 0, 0.2));
    const int unweighted[] = {ROOT, AXIS, POLE_L, TARGET_L, SOCKET};
    for (size_t i = 0; i < sizeof unweighted / sizeof *unweighted; i++)
        s->joints[unweighted[i]].flags |= RF_JOINT_UNWEIGHTED;
    return s;
}

static void check_biped_roles(const rf_joint_roles *r)
{
    assert_int_equal(r->role[ROOT], RF_ROLE_PLACEMENT);
    assert_int_equal(r->role[AXIS], RF_ROLE_AXIS);
    assert_int_equal(r->role[POLE_L], RF_ROLE_IK_POLE);
    assert_int_equal(r->body_joint[POLE_L], SHIN_L);
    assert_int_equal(r->role[TARGET_L], RF_ROLE_IK_TARGET);
    assert_int_equal(r->body_joint[TARGET_L], FOOT_L);
    assert_int_equal(r->role[SOCKET], RF_ROLE_HELPER);
    assert_int_equal(r->body_joint[SOCKET], HEAD);
    const int body[] = {HIPS, SPINE, HEAD, THIGH_L, SHIN_L, FOOT_L, THIGH_R, SHIN_R, FOOT_R};
    for (size_t i = 0; i < sizeof body / sizeof *body; i++)
        assert_int_equal(r->role[body[i]], RF_ROLE_BODY);
}

static void test_roles_biped(void **state)
{
    (void)state;
    rf_skeleton *s = ik_biped();
    rf_joint_roles *r = rf_joint_roles_find(s, NULL, NULL, 0);
    assert_non_null(r);
    check_biped_roles(r);
    rf_joint_roles_free(r);
    rf_skeleton_free(s);
}

/* Names carry nothing: the same rig without any gives the same roles. */
static void test_roles_no_names(void **state)
{
    (void)state;
    rf_skeleton *s = ik_biped();
    for (uint32_t j = 0; j < s->joint_count; j++)
        free(s->joints[j].name), s->joints[j].name = NULL;
    rf_joint_roles *r = rf_joint_roles_find(s, NULL, NULL, 0);
    assert_non_null(r);
    check_biped_roles(r);
    rf_joint_roles_free(r);
    rf_skeleton_free(s);
}

/* A clip that turns the unweighted root makes it a mover of the body; a still clip changes
 * nothing. */
static void test_roles_motion(void **state)
{
    (void)state;
    rf_skeleton *s = ik_biped();
    rf_animation *a = fx_rest_clip(s, 4, 30);
    const rf_animation *clips[1] = {a};
    rf_joint_roles *r = rf_joint_roles_find(s, NULL, clips, 1);
    check_biped_roles(r);
    rf_joint_roles_free(r);
    rf_animation_set_rotation(a, 2, ROOT, fx_rot(rf_v3(0, 1, 0), 30));
    r = rf_joint_roles_find(s, NULL, clips, 1);
    assert_int_equal(r->role[ROOT], RF_ROLE_BODY);
    assert_true(r->turned[ROOT]);
    rf_joint_roles_free(r);
    rf_animation_free(a);
    rf_skeleton_free(s);
}

/* Degenerate input: no joints, one joint, NaN offsets. */
static void test_roles_degenerate(void **state)
{
    (void)state;
    rf_skeleton *s = rf_skeleton_new(0);
    rf_joint_roles *r = rf_joint_roles_find(s, NULL, NULL, 0);
    assert_non_null(r);
    assert_int_equal(r->joint_count, 0);
    rf_joint_roles_free(r);
    rf_skeleton_free(s);
    s = ik_biped();
    s->joints[POLE_L].rest.t = rf_v3(NAN, 0, 0);
    r = rf_joint_roles_find(s, NULL, NULL, 0);
    assert_non_null(r);
    assert_int_equal(r->role[ROOT], RF_ROLE_PLACEMENT);
    rf_joint_roles_free(r);
    rf_skeleton_free(s);
}

/* ---- the shared data ---- */

static rf_ai_result load(const char *rel)
{
    rf_ai_result r;
    char path[4096], err[1024];
    const char *d = getenv("RF_DATA_DIR");
    snprintf(path, sizeof path, "%s/%s", d ? d : "", rel);
    if (!d || !*d || access(path, R_OK) != 0) {
        print_message("%s not found (RF_DATA_DIR, ../shared/data): skipped\n", rel);
        skip();
    }
    bool ok = rf_ai_import(path, NULL, &r, NULL, NULL, err, sizeof err);
    if (!ok)
        print_error("%s\n", err);
    assert_true(ok);
    return r;
}

/* The role of the joint named `name` (the test reads names; the roles never do). */
static int role_of(const rf_ai_result *m, const rf_joint_roles *r, const char *name, int *body)
{
    int32_t j = rf_skeleton_find(m->skeleton, name);
    assert_true(j >= 0);
    if (body)
        *body = r->body_joint[j];
    return r->role[j];
}

static void test_roles_data(void **state)
{
    (void)state;
    static const struct {
        const char *file, *joint, *body;
        rf_joint_role role;
    } want[] = {
        {"models/Wizard.glb", "Root", NULL, RF_ROLE_PLACEMENT},
        {"models/Wizard.glb", "PoleTarget.L", "LowerLeg.L", RF_ROLE_IK_POLE},
        {"models/Wizard.glb", "Foot.L", NULL, RF_ROLE_BODY},
        {"models/RobotExpressive.glb", "PoleTarget.R", "LowerLeg.R", RF_ROLE_IK_POLE},
        {"models/RobotExpressive.glb", "Body", NULL, RF_ROLE_BODY},
        {"models/girl.glb", "IKLegTarget.L", "Foot.L", RF_ROLE_IK_TARGET},
        {"models/girl.glb", "IKLegPole.R", "LowerLeg.R", RF_ROLE_IK_POLE},
        {"models/Fox.glb", "b_Root_00", NULL, RF_ROLE_AXIS},
        {"models/Fox.glb", "b_Hip_01", NULL, RF_ROLE_BODY},
    };
    for (size_t i = 0; i < sizeof want / sizeof *want; i++) {
        rf_ai_result m = load(want[i].file);
        const rf_animation *clips[1] = {m.animation};
        rf_joint_roles *r = rf_joint_roles_find(m.skeleton, m.mesh, clips, 1);
        int body = -1;
        int got = role_of(&m, r, want[i].joint, &body);
        if (got != (int)want[i].role)
            print_error("%s %s: %s, expected %s\n", want[i].file, want[i].joint,
                        rf_joint_role_name(got), rf_joint_role_name(want[i].role));
        assert_int_equal(got, want[i].role);
        if (want[i].body)
            assert_int_equal(body, rf_skeleton_find(m.skeleton, want[i].body));
        rf_joint_roles_free(r);
        rf_ai_result_clear(&m);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_roles_biped),  cmocka_unit_test(test_roles_no_names),
        cmocka_unit_test(test_roles_motion), cmocka_unit_test(test_roles_degenerate),
        cmocka_unit_test(test_roles_data),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
