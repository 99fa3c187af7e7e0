/* The "names" matcher: normalisation (case, separators, side tokens, prefixes, synonyms, running
 * indices) and mapping two rigs named in different schemes. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "rigflow/match-names.h"

static void assert_key(const char *name, int side, const char *words)
{
    rf_name_key k;
    rf_name_normalize(name, false, &k);
    if (k.side != side || strcmp(k.words, words) != 0)
        fail_msg("%s normalises to side %d \"%s\", expected side %d \"%s\"", name, k.side, k.words,
                 side, words);
}

static double similarity(const char *a, const char *b)
{
    rf_name_key x, y;
    rf_name_normalize(a, false, &x);
    rf_name_normalize(b, false, &y);
    return rf_name_similarity(&x, &y);
}

static void test_normalize(void **state)
{
    (void)state;
    assert_key("LeftUpLeg", 1, "thigh");
    assert_key("mixamorig:LeftUpLeg", 1, "thigh");
    assert_key("thigh.L", 1, "thigh");
    assert_key("Thigh_l", 1, "thigh");
    assert_key("Bip01 R Thigh", 2, "thigh");
    assert_key("RightForeArm", 2, "forearm");
    assert_key("lowerarm_r", 2, "forearm");
    assert_key("UpperArm.R", 2, "upperarm");
    assert_key("Hips", 0, "pelvis");
    assert_key("pelvis", 0, "pelvis");
    assert_key("LHipJoint", 1, "hipjoint");
    assert_key("spine_01", 0, "spine 1");
    assert_key("Spine1", 0, "spine 1");
    assert_key("LeftCollar", 1, "clavicle");
    assert_key("LThumb", 1, "thumb");
    rf_name_key k;
    rf_name_normalize("b_LeftLeg01_015", true, &k); /* a file-wide running index dropped */
    assert_int_equal(k.side, 1);
    assert_string_equal(k.words, "shin 1");
    rf_name_normalize("", false, &k);
    assert_string_equal(k.words, "");
    rf_name_normalize(NULL, false, &k);
    assert_int_equal(k.side, 0);
}

static void test_similarity(void **state)
{
    (void)state;
    assert_true(similarity("LeftHand", "hand.L") == 1);
    assert_true(similarity("LeftHand", "hand.R") == 0); /* the other side */
    assert_true(similarity("Hips", "Hip.L") == 0);
    assert_true(similarity("LeftShoulder", "clavicle_l") > 0.5); /* Mixamo's shoulder */
    assert_true(similarity("LeftShoulder", "upperarm_l") > 0.5); /* Boxing's shoulder */
    assert_true(similarity("Spine1", "Spine2") > 0.5 && similarity("Spine1", "Spine2") < 1);
    assert_true(similarity("Joint3", "Joint4") < 1);
}

static rf_skeleton *named(const char *const *names, uint32_t n)
{
    rf_skeleton *s = rf_skeleton_new(n);
    for (uint32_t i = 0; i < n; i++) {
        s->joints[i].name = strdup(names[i]);
        s->joints[i].parent = i ? 0 : -1;
    }
    return s;
}

static void test_match(void **state)
{
    (void)state;
    static const char *const mixamo[] = {
        "mixamorig:Hips",      "mixamorig:Spine",        "mixamorig:Neck",
        "mixamorig:Head",      "mixamorig:LeftArm",      "mixamorig:RightForeArm",
        "mixamorig:LeftUpLeg", "mixamorig:RightToeBase", "mixamorig:HeadTop_End"};
    static const char *const rigify[] = {"pelvis",      "spine",     "neck",    "head",
                                         "upper_arm.L", "forearm.R", "thigh.L", "toe.R"};
    rf_skeleton *t = named(mixamo, 9), *s = named(rigify, 8);
    const rf_skeleton *src[1] = {s};
    char err[128];
    rf_mapping *m = rf_names_match(t, src, 1, 0, err, sizeof err);
    assert_non_null(m);
    assert_int_equal(m->metric_count, 1);
    assert_string_equal(m->metric_names[0], "name");
    for (uint32_t j = 0; j < 8; j++) {
        assert_int_equal(m->entries[j].input_count, 1);
        assert_int_equal(m->entries[j].inputs[0].joint, j);
        assert_true(m->entries[j].metrics[0] > 50);
    }
    assert_int_equal(m->entries[8].input_count, 0); /* HeadTop_End: nothing alike enough */
    rf_mapping_free(m);
    assert_null(rf_names_match(t, src, 0, 0, err, sizeof err));
    rf_skeleton_free(t);
    rf_skeleton_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_normalize),
        cmocka_unit_test(test_similarity),
        cmocka_unit_test(test_match),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
