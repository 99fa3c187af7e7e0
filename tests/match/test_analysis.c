/* Skeleton analysis on hand-built skeletons: axes whichever way a body faces, sides by geometry,
 * section types, helpers, forests, and degenerate input that must not crash. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include <cmocka.h>

#include "rigflow/analysis.h"
#include "skel-build.h"

static const rf_section *section_of(const rf_analysis *a, const rf_skeleton *s, const char *name)
{
    int32_t j = sb_find(s, name);
    assert_true(j >= 0);
    assert_true(a->joints[j].section >= 0);
    return &a->sections[a->joints[j].section];
}

static void assert_near_dir(rf_vec3 got, rf_vec3 want)
{
    if (rf_v3_dot(rf_v3_normalize(got), rf_v3_normalize(want)) < 0.99)
        fail_msg("direction (%.3f %.3f %.3f), expected (%.3f %.3f %.3f)", got.x, got.y, got.z,
                 want.x, want.y, want.z);
}

static void assert_section(const rf_analysis *a, const rf_skeleton *s, const char *joint,
                           rf_section_type type, rf_side side)
{
    const rf_section *sec = section_of(a, s, joint);
    if (sec->type != type || sec->side != side)
        fail_msg("%s is in a %s %s section, expected %s %s", joint, rf_side_name(sec->side),
                 rf_section_type_name(sec->type), rf_side_name(side), rf_section_type_name(type));
}

static void check_biped_sections(const rf_analysis *a, const rf_skeleton *s)
{
    assert_section(a, s, "hips", RF_SECTION_SPINE, RF_SIDE_CENTER);
    assert_section(a, s, "chest", RF_SECTION_SPINE, RF_SIDE_CENTER);
    assert_section(a, s, "neck", RF_SECTION_HEAD, RF_SIDE_CENTER);
    assert_section(a, s, "head", RF_SECTION_HEAD, RF_SIDE_CENTER);
    assert_section(a, s, "l_arm", RF_SECTION_ARM, RF_SIDE_LEFT);
    assert_section(a, s, "l_clavicle", RF_SECTION_ARM, RF_SIDE_LEFT);
    assert_section(a, s, "r_forearm", RF_SECTION_ARM, RF_SIDE_RIGHT);
    assert_section(a, s, "l_finger", RF_SECTION_HAND, RF_SIDE_LEFT);
    assert_section(a, s, "r_thumb", RF_SECTION_HAND, RF_SIDE_RIGHT);
    assert_section(a, s, "l_thigh", RF_SECTION_LEG, RF_SIDE_LEFT);
    assert_section(a, s, "r_toe", RF_SECTION_LEG, RF_SIDE_RIGHT);
}

static void test_biped(void **state)
{
    (void)state;
    rf_skeleton *s = sb_build(sb_biped, SB_COUNT(sb_biped));
    rf_analysis *a = rf_analyze(s, NULL);
    assert_non_null(a);
    assert_near_dir(a->up, rf_v3(0, 1, 0));
    assert_near_dir(a->forward, rf_v3(0, 0, 1));
    assert_near_dir(a->left, rf_v3(1, 0, 0));
    assert_true(a->symmetry > 0.9);
    check_biped_sections(a, s);
    /* the thumb is the forward-most digit of its fan */
    assert_int_equal(section_of(a, s, "l_thumb")->pair_rank, 0);
    assert_int_equal(a->joints[sb_find(s, "l_arm")].mirror, sb_find(s, "r_arm"));
    rf_analysis_free(a);
    rf_skeleton_free(s);
}

/* The same body turned to face every way, and lying with +Z up: detected, not assumed. */
static void test_biped_facing(void **state)
{
    (void)state;
    const double yaws[] = {0, 90, 180, 270, 35};
    for (size_t i = 0; i < sizeof yaws / sizeof yaws[0]; i++) {
        for (int zup = 0; zup < 2; zup++) {
            rf_quat r = rf_quat_from_axis_angle(rf_v3(0, 1, 0), yaws[i] * RF_PI / 180);
            if (zup)
                r = rf_quat_mul(rf_quat_from_axis_angle(rf_v3(1, 0, 0), RF_PI / 2), r);
            rf_skeleton *s = sb_build_xf(sb_biped, SB_COUNT(sb_biped), r, 37.0, rf_v3(5, -2, 9));
            rf_analysis *a = rf_analyze(s, NULL);
            assert_non_null(a);
            assert_near_dir(a->up, rf_quat_rotate(r, rf_v3(0, 1, 0)));
            assert_near_dir(a->forward, rf_quat_rotate(r, rf_v3(0, 0, 1)));
            check_biped_sections(a, s);
            rf_analysis_free(a);
            rf_skeleton_free(s);
        }
    }
}

static void test_quadruped(void **state)
{
    (void)state;
    rf_skeleton *s = sb_build(sb_quadruped, SB_COUNT(sb_quadruped));
    rf_analysis *a = rf_analyze(s, NULL);
    assert_non_null(a);
    assert_near_dir(a->up, rf_v3(0, 1, 0));
    assert_near_dir(a->forward, rf_v3(0, 0, -1));
    assert_section(a, s, "pelvis", RF_SECTION_SPINE, RF_SIDE_CENTER);
    assert_section(a, s, "chest", RF_SECTION_SPINE, RF_SIDE_CENTER);
    assert_section(a, s, "head", RF_SECTION_HEAD, RF_SIDE_CENTER);
    assert_section(a, s, "tail2", RF_SECTION_TAIL, RF_SIDE_CENTER);
    assert_section(a, s, "fl1", RF_SECTION_LEG, RF_SIDE_LEFT);
    assert_section(a, s, "hr3", RF_SECTION_LEG, RF_SIDE_RIGHT);
    /* front legs rank before hind legs, and sit at the front end of the body */
    assert_int_equal(section_of(a, s, "fl1")->pair_rank, 0);
    assert_int_equal(section_of(a, s, "hl1")->pair_rank, 1);
    assert_true(section_of(a, s, "fl1")->body_pos > 0.8);
    assert_true(section_of(a, s, "hl1")->body_pos < 0.2);
    /* the hock bends backward, the front knee (carpus) forward or not at all */
    assert_true(a->joints[sb_find(s, "hl3")].bend < 0);
    rf_analysis_free(a);
    rf_skeleton_free(s);
}

/* The quadruped with its tail raised high above its head: the elevation cue votes backwards,
 * the feet forwards; the feet win, the dissent is kept and named. */
static void test_facing_dissent(void **state)
{
    (void)state;
    sb_joint js[SB_COUNT(sb_quadruped)];
    memcpy(js, sb_quadruped, sizeof js);
    for (size_t i = 0; i < SB_COUNT(js); i++)
        if (strncmp(js[i].name, "tail", 4) == 0 ||
            (js[i].parent && strcmp(js[i].parent, "tail3") == 0))
            js[i].y += 1.0 + 0.3 * (double)(js[i].z - 0.5);
    rf_skeleton *s = sb_build(js, SB_COUNT(js));
    rf_analysis *a = rf_analyze(s, NULL);
    assert_non_null(a);
    assert_near_dir(a->forward, rf_v3(0, 0, -1));
    int d = rf_forward_dissent(a);
    assert_true(d >= 0);
    assert_string_equal(rf_forward_cue_names[d], "elevation");
    assert_true(a->forward_cues[0] > 0); /* the feet agreed */
    rf_analysis_free(a);
    rf_skeleton_free(s);
    /* the plain quadruped: every cue agrees */
    s = sb_build(sb_quadruped, SB_COUNT(sb_quadruped));
    a = rf_analyze(s, NULL);
    assert_int_equal(rf_forward_dissent(a), -1);
    rf_analysis_free(a);
    rf_skeleton_free(s);
}

/* A bird facing -Z: wings folded back along the body, longer than the short legs it stands
 * on. The wings hang "down" towards the tail if the tail end were the ground; the toes spread
 * flat under the body say where the ground is. Up is +Y, the ground cue agreeing. */
static const sb_joint sb_bird[] = {
    {"hips", NULL, 0, 0.40, 0.10, 0},        {"chest", "hips", 0, 0.45, -0.15, 0},
    {"neck1", "chest", 0, 0.55, -0.20, 0},   {"neck2", "neck1", 0, 0.68, -0.22, 0},
    {"head", "neck2", 0, 0.80, -0.25, 0},    {".", "head", 0, 0.80, -0.40, 0},
    {"tail", "hips", 0, 0.42, 0.20, 0},      {".", "tail", 0, 0.44, 0.32, 0},
    {"wl1", "chest", -0.06, 0.50, -0.15, 0}, {"wl2", "wl1", -0.12, 0.48, 0.15, 0},
    {"wl3", "wl2", -0.14, 0.46, 0.45, 0},    {".", "wl3", -0.14, 0.44, 0.80, 0},
    {"wr1", "chest", 0.06, 0.50, -0.15, 0},  {"wr2", "wr1", 0.12, 0.48, 0.15, 0},
    {"wr3", "wr2", 0.14, 0.46, 0.45, 0},     {".", "wr3", 0.14, 0.44, 0.80, 0},
    {"ll1", "hips", -0.05, 0.38, 0.10, 0},   {"ll2", "ll1", -0.06, 0.25, 0.00, 0},
    {"ll3", "ll2", -0.06, 0.12, 0.10, 0},    {"ll4", "ll3", -0.06, 0.02, 0.08, 0},
    {"lt1", "ll4", -0.06, 0.02, 0.08, 0},    {".", "lt1", -0.09, 0.0, -0.02, 0},
    {"lt2", "ll4", -0.06, 0.02, 0.08, 0},    {".", "lt2", -0.06, 0.0, -0.04, 0},
    {"lt3", "ll4", -0.06, 0.02, 0.08, 0},    {".", "lt3", -0.03, 0.0, -0.02, 0},
    {"lt4", "ll4", -0.06, 0.02, 0.08, 0},    {".", "lt4", -0.06, 0.0, 0.14, 0},
    {"rl1", "hips", 0.05, 0.38, 0.10, 0},    {"rl2", "rl1", 0.06, 0.25, 0.00, 0},
    {"rl3", "rl2", 0.06, 0.12, 0.10, 0},     {"rl4", "rl3", 0.06, 0.02, 0.08, 0},
    {"rt1", "rl4", 0.06, 0.02, 0.08, 0},     {".", "rt1", 0.09, 0.0, -0.02, 0},
    {"rt2", "rl4", 0.06, 0.02, 0.08, 0},     {".", "rt2", 0.06, 0.0, -0.04, 0},
    {"rt3", "rl4", 0.06, 0.02, 0.08, 0},     {".", "rt3", 0.03, 0.0, -0.02, 0},
    {"rt4", "rl4", 0.06, 0.02, 0.08, 0},     {".", "rt4", 0.06, 0.0, 0.14, 0},
};

static void test_bird_ground(void **state)
{
    (void)state;
    rf_skeleton *s = sb_build(sb_bird, SB_COUNT(sb_bird));
    rf_analysis *a = rf_analyze(s, NULL);
    assert_non_null(a);
    assert_near_dir(a->up, rf_v3(0, 1, 0));
    assert_true(a->up_cues[1] > 0); /* the ground agreed */
    rf_analysis_free(a);
    /* forced: no cue votes */
    rf_analysis_options o = {.up = rf_v3(0, 1, 0)};
    a = rf_analyze(s, &o);
    assert_true(a->up_cues[0] == 0 && a->up_cues[1] == 0 && a->up_cues[2] == 0);
    assert_int_equal(rf_up_dissent(a), -1);
    rf_analysis_free(a);
    rf_skeleton_free(s);
    /* the quadruped stands on four feet: both cues agree, no warning */
    s = sb_build(sb_quadruped, SB_COUNT(sb_quadruped));
    a = rf_analyze(s, NULL);
    assert_true(a->up_cues[0] > 0 && a->up_cues[1] > 0);
    assert_int_equal(rf_up_dissent(a), -1);
    rf_analysis_free(a);
    rf_skeleton_free(s);
}

/* A dragon facing -Z: the quadruped's body and legs without end sites (the hind feet end at the
 * ankle pointing down, the forelegs short of the ground, as in rigs without end sites), and
 * wings folded back from the chest, each two and a half legs' reach, ending in a fan of three
 * long membrane fingers. Were the head end up, the wings would hang; a wing votes half for up,
 * so the legs read +Y (with the wings voting in full, up was read as -Z: the test fails). */
static void test_dragon_folded_wings(void **state)
{
    (void)state;
    sb_joint js[SB_COUNT(sb_quadruped) + 24];
    size_t n = 0;
    for (size_t i = 0; i < SB_COUNT(sb_quadruped); i++) {
        const sb_joint *q = &sb_quadruped[i];
        bool foot = q->name[0] == '.' && strlen(q->parent) == 3 && q->parent[2] == '4';
        bool fore_foot = !strcmp(q->name, "fl4") || !strcmp(q->name, "fr4");
        if (foot || fore_foot)
            continue;
        js[n] = *q;
        if (!strcmp(q->name, "fl3") || !strcmp(q->name, "fr3"))
            js[n].y = 0.2; /* a dragon's forelegs, no foot measured */
        n++;
    }
    static const char *const names[2][12] = {
        {"wl1", "wl2", "wl3", "wl4", "wl5", ".", "wl6", "wl7", ".", "wl8", "wl9", "."},
        {"wr1", "wr2", "wr3", "wr4", "wr5", ".", "wr6", "wr7", ".", "wr8", "wr9", "."}};
    for (int side = 0; side < 2; side++) {
        double x = side ? 0.1 : -0.1;
        const char *const *nm = names[side];
        /* shoulder, elbow, wrist; then three fingers of two bones fanning from the wrist */
        js[n++] = (sb_joint){nm[0], "chest", x, 1.10, -0.40, 0};
        js[n++] = (sb_joint){nm[1], nm[0], 3 * x, 1.00, 0.20, 0};
        js[n++] = (sb_joint){nm[2], nm[1], 4 * x, 0.95, 0.80, 0};
        for (int f = 0; f < 3; f++) {
            double spread = 0.8 * x * (f - 1);
            js[n++] = (sb_joint){nm[3 + 3 * f], nm[2], 4 * x, 0.95, 0.80, 0};
            js[n++] = (sb_joint){nm[4 + 3 * f], nm[3 + 3 * f], 4 * x + spread, 0.92, 1.45, 0};
            js[n++] = (sb_joint){nm[5 + 3 * f], nm[4 + 3 * f], 4 * x + 2 * spread, 0.88, 2.10, 0};
        }
    }
    rf_skeleton *s = sb_build(js, n);
    rf_analysis *a = rf_analyze(s, NULL);
    assert_non_null(a);
    assert_near_dir(a->up, rf_v3(0, 1, 0));
    assert_near_dir(a->forward, rf_v3(0, 0, -1));
    assert_int_equal(section_of(a, s, "wl9")->side, RF_SIDE_LEFT);
    assert_int_equal(section_of(a, s, "fr3")->side, RF_SIDE_RIGHT);
    rf_analysis_free(a);
    rf_skeleton_free(s);
}

/* An insect facing +Z whose six sprawled legs all hang from one thorax joint: the head chain
 * starts a thorax away from it, the abdomen on its pivot, carried higher than the head (the
 * elevation votes backwards) and the feet end straight down (no flat foot to go by). The
 * thorax's bone runs to the head: the hierarchy cue reads the facing, whichever way the body
 * is turned, and the elevation's dissent is kept. */
static void add_insect_leg(sb_joint *js, size_t *n, char (*names)[8], int side, int pair)
{
    double sweep = 0.6 * (1 - pair), x = side ? -1 : 1, len = sqrt(1 + sweep * sweep);
    double ox = x / len, oz = sweep / len;
    double hip[3] = {0.06 * x, 0.27, 0}, knee[3] = {hip[0] + 0.3 * ox, 0.40, 0.3 * oz};
    double ankle[3] = {knee[0] + 0.05 * ox, 0.02, knee[2] + 0.05 * oz};
    const double *pts[3] = {hip, knee, ankle};
    for (int k = 0; k < 3; k++) {
        snprintf(names[*n], 8, "%c%d%d", side ? 'r' : 'l', pair, k);
        js[*n] =
            (sb_joint){names[*n], k ? names[*n - 1] : "thorax", pts[k][0], pts[k][1], pts[k][2], 0};
        (*n)++;
    }
    js[*n] = (sb_joint){".", names[*n - 1], ankle[0], 0, ankle[2], 0};
    (*n)++;
}

static void test_insect_one_girdle(void **state)
{
    (void)state;
    sb_joint js[40] = {
        {"thorax", NULL, 0, 0.30, 0, 0},       {"neck", "thorax", 0, 0.31, 0.35, 0},
        {"head", "neck", 0, 0.32, 0.42, 0},    {".", "head", 0, 0.32, 0.55, 0},
        {"abd1", "thorax", 0, 0.30, -0.02, 0}, {"abd2", "abd1", 0, 0.36, -0.20, 0},
        {"abd3", "abd2", 0, 0.42, -0.40, 0},   {".", "abd3", 0, 0.45, -0.60, 0},
    };
    char names[40][8];
    size_t n = 8;
    for (int side = 0; side < 2; side++)
        for (int pair = 0; pair < 3; pair++)
            add_insect_leg(js, &n, names, side, pair);
    const double yaws[] = {0, 90, 180, 270};
    for (size_t i = 0; i < sizeof yaws / sizeof yaws[0]; i++) {
        rf_quat r = rf_quat_from_axis_angle(rf_v3(0, 1, 0), yaws[i] * RF_PI / 180);
        rf_skeleton *s = sb_build_xf(js, n, r, 3.0, rf_v3(1, 0, -2));
        rf_analysis *a = rf_analyze(s, NULL);
        assert_non_null(a);
        assert_near_dir(a->up, rf_v3(0, 1, 0));
        assert_near_dir(a->forward, rf_quat_rotate(r, rf_v3(0, 0, 1)));
        assert_string_equal(a->forward_source, "hierarchy");
        assert_string_equal(rf_forward_cue_names[rf_forward_dissent(a)], "elevation");
        assert_section(a, s, "head", RF_SECTION_HEAD, RF_SIDE_CENTER);
        assert_section(a, s, "abd3", RF_SECTION_TAIL, RF_SIDE_CENTER);
        rf_analysis_free(a);
        rf_skeleton_free(s);
    }
}

/* Twist leaves inside the forearms and thighs (Unreal's mannequin) are part of their segment:
 * helpers, not digits, and the hands keep their two digits. A thumb at the wrist is no roll. */
/* A forearm cut in two straight halves (Rigify's deform bones) before a hand bone longer than
 * 0.6 of the half but not of the whole forearm: the hand is still a hand bone, so its digits are
 * measured from the wrist. The finger's knuckle then lies at |knuckle - wrist| / (that + the
 * finger's length) of its section, by hand 0.14 / 0.22 (from the hand's tip, as when the half
 * was taken for the forearm, 0.43). */
static void test_hand_on_cut_forearm(void **state)
{
    (void)state;
    sb_joint js[SB_COUNT(sb_biped) + 2];
    size_t n = 0;
    for (size_t i = 0; i < SB_COUNT(sb_biped); i++) {
        js[n] = sb_biped[i];
        double side = js[n].x < 0 ? -1 : 1;
        const char *nm = js[n].name, *par = js[n].parent ? js[n].parent : "";
        if (!strcmp(nm + 1, "_hand"))
            js[n].parent = side > 0 ? "l_fore2" : "r_fore2";
        if (!strcmp(nm + 1, "_finger"))
            js[n].x = 0.86 * side;
        if (!strcmp(nm, ".") && !strcmp(par + 1, "_finger"))
            js[n].x = 0.94 * side;
        n++;
        if (!strcmp(nm + 1, "_forearm"))
            js[n++] = (sb_joint){side > 0 ? "l_fore2" : "r_fore2", nm, 0.59 * side, 1.50, -0.03, 0};
    }
    rf_skeleton *s = sb_build(js, n);
    rf_analysis *a = rf_analyze(s, NULL);
    assert_non_null(a);
    assert_section(a, s, "l_finger", RF_SECTION_HAND, RF_SIDE_LEFT);
    double u0 = a->joints[sb_find(s, "l_finger")].u0;
    if (fabs(u0 - 0.14 / 0.22) > 0.01)
        fail_msg("the knuckle at %.3f of its digit, expected %.3f", u0, 0.14 / 0.22);
    assert_true(fabs(a->joints[sb_find(s, "r_finger")].u0 - 0.14 / 0.22) < 0.01);
    rf_analysis_free(a);
    rf_skeleton_free(s);
}

static void test_roll_leaves(void **state)
{
    (void)state;
    sb_joint js[SB_COUNT(sb_biped) + 4];
    memcpy(js, sb_biped, sizeof sb_biped);
    size_t n = SB_COUNT(sb_biped);
    js[n++] = (sb_joint){"l_fore_twist", "l_forearm", 0.62, 1.50, -0.03, 0};
    js[n++] = (sb_joint){".", "l_fore_twist", 0.68, 1.50, -0.025, 0};
    js[n++] = (sb_joint){"r_fore_twist", "r_forearm", -0.62, 1.50, -0.03, 0};
    js[n++] = (sb_joint){".", "r_fore_twist", -0.68, 1.50, -0.025, 0};
    rf_skeleton *s = sb_build(js, n);
    rf_analysis *a = rf_analyze(s, NULL);
    assert_non_null(a);
    assert_int_equal(section_of(a, s, "l_fore_twist")->type, RF_SECTION_HELPER);
    assert_int_equal(section_of(a, s, "r_fore_twist")->type, RF_SECTION_HELPER);
    assert_section(a, s, "l_hand", RF_SECTION_ARM, RF_SIDE_LEFT);
    assert_section(a, s, "l_thumb", RF_SECTION_HAND, RF_SIDE_LEFT);
    rf_analysis_free(a);
    rf_skeleton_free(s);
}

static void test_strip(void **state)
{
    (void)state;
    const sb_joint strip[] = {{"a", NULL, 0, 1, 0, 0}, {"b", "a", 0, 2, 0, 0}};
    rf_skeleton *s = sb_build(strip, 2);
    rf_analysis *a = rf_analyze(s, NULL);
    assert_non_null(a);
    assert_int_equal(a->section_count, 1);
    assert_int_equal(a->sections[0].type, RF_SECTION_SPINE);
    assert_int_equal(a->sections[0].bone_count, 2);
    assert_true(a->joints[0].u0 <= a->joints[1].u0);
    rf_analysis_free(a);
    rf_skeleton_free(s);
}

/* Every joint ends up in exactly one section, and the sections' joint lists agree. */
static void check_consistent(const rf_analysis *a)
{
    uint32_t total = 0;
    for (uint32_t k = 0; k < a->section_count; k++) {
        total += a->sections[k].bone_count;
        for (uint32_t i = 0; i < a->sections[k].bone_count; i++) {
            uint32_t j = rf_section_joints(a, k)[i];
            assert_true(j < a->joint_count);
            assert_int_equal(a->joints[j].section, (int32_t)k);
            assert_int_equal(a->joints[j].index, i);
            assert_true(isfinite(a->joints[j].u0) && isfinite(a->joints[j].u1));
        }
    }
    assert_int_equal(total, a->joint_count);
    assert_true(rf_v3_isfinite(a->up) && rf_v3_isfinite(a->forward));
    assert_true(fabs(rf_v3_len(a->up) - 1) < 1e-9 && fabs(rf_v3_dot(a->up, a->forward)) < 1e-9);
}

static void test_degenerate(void **state)
{
    (void)state;
    rf_analysis *a = rf_analyze(NULL, NULL);
    assert_non_null(a);
    assert_int_equal(a->section_count, 0);
    rf_analysis_free(a);
    rf_skeleton *s = rf_skeleton_new(0);
    a = rf_analyze(s, NULL);
    assert_int_equal(a->joint_count, 0);
    rf_analysis_free(a);
    rf_skeleton_free(s);

    s = rf_skeleton_new(1); /* one joint */
    a = rf_analyze(s, NULL);
    check_consistent(a);
    rf_analysis_free(a);
    rf_skeleton_free(s);

    s = rf_skeleton_new(12); /* all coincident: a chain and a star at the origin */
    for (uint32_t i = 1; i < 12; i++)
        s->joints[i].parent = i < 6 ? (int32_t)i - 1 : 0;
    a = rf_analyze(s, NULL);
    check_consistent(a);
    rf_analysis_free(a);

    /* non-finite numbers, zero scale, parents that are not before their children */
    s->joints[3].rest.t = rf_v3(NAN, 1, INFINITY);
    s->joints[4].rest.r = rf_quat_make(NAN, 0, 0, 0);
    s->joints[5].rest.s = rf_v3(0, 0, 0);
    s->joints[7].parent = 11;
    s->joints[8].parent = -7;
    s->joints[9].parent = 9;
    s->joints[2].flags = RF_JOINT_HAS_END_SITE;
    s->joints[2].end_site = rf_v3(NAN, 0, 0);
    a = rf_analyze(s, NULL);
    check_consistent(a);
    rf_analysis_free(a);
    rf_skeleton_free(s);
}

/* A 100 000-joint chain and a wide random tree: no recursion, no quadratic blow-up. The bar is
 * a blow-up's, about ten times what the two take on a quiet machine (a quadratic step here takes
 * hours), so a loaded machine cannot trip it; the analysis's speed itself is bench/match's. */
static void test_large(void **state)
{
    (void)state;
    uint32_t n = 100000;
    rf_skeleton *s = rf_skeleton_new(n);
    for (uint32_t i = 1; i < n; i++) {
        s->joints[i].parent = (int32_t)i - 1;
        s->joints[i].rest.t = rf_v3(0.001 * (i % 7), 0.01, 0);
    }
    clock_t t0 = clock();
    rf_analysis *a = rf_analyze(s, NULL);
    check_consistent(a);
    rf_analysis_free(a);
    srand(7);
    for (uint32_t i = 1; i < n; i++) {
        s->joints[i].parent = (int32_t)(i < 20000 ? 0 : (uint32_t)rand() % i);
        s->joints[i].rest.t = rf_v3(rand() % 100 - 50, rand() % 100 - 50, rand() % 100 - 50);
    }
    a = rf_analyze(s, NULL);
    check_consistent(a);
    rf_analysis_free(a);
    double seconds = (double)(clock() - t0) / CLOCKS_PER_SEC;
    print_message("two 100000-joint analyses: %.2f s\n", seconds);
    assert_true(seconds < 120);
    rf_skeleton_free(s);
}

static void test_forced_axes(void **state)
{
    (void)state;
    rf_skeleton *s = sb_build(sb_biped, SB_COUNT(sb_biped));
    rf_analysis_options o = {0};
    o.up = rf_v3(0, 0, 2);
    o.forward = rf_v3(1, 0, 0.5);
    rf_analysis *a = rf_analyze(s, &o);
    assert_near_dir(a->up, rf_v3(0, 0, 1));
    assert_near_dir(a->forward, rf_v3(1, 0, 0));
    assert_string_equal(a->up_source, "forced");
    assert_string_equal(a->forward_source, "forced");
    check_consistent(a);
    rf_analysis_free(a);
    rf_skeleton_free(s);
}

/* Axes forced on a body with one arm (no mirror pairs): the plane they define is the plane,
 * its two off-plane joints have no mirror image, so the symmetry (analysis.h: the fraction of
 * off-plane joints with a mirror image) is 0, not the 1 of a body with every joint on it. */
static void test_forced_plane_unmatched(void **state)
{
    (void)state;
    static const sb_joint one_arm[] = {
        {"hips", NULL, 0, 1.0, 0, 0},       {"spine", "hips", 0, 1.5, 0, 0},
        {"head", "spine", 0, 2.0, 0, 0},    {".", "head", 0, 2.3, 0, 0},
        {"arm", "spine", 0.5, 1.2, 0.6, 0}, {"hand", "arm", 1.1, 0.7, 1.2, 0},
        {"leg", "hips", 0, 0.5, 0, 0},      {"foot", "leg", 0, 0.0, 0.1, 0},
    };
    rf_skeleton *s = sb_build(one_arm, SB_COUNT(one_arm));
    rf_analysis_options o = {0};
    o.up = rf_v3(0, 1, 0), o.forward = rf_v3(0, 0, 1);
    rf_analysis *a = rf_analyze(s, &o);
    assert_near_dir(a->plane_normal, rf_v3(1, 0, 0));
    assert_float_equal(a->symmetry, 0, 0);
    check_consistent(a);
    rf_analysis_free(a);
    rf_skeleton_free(s);
}

/* Unweighted leaves (IK target, pole, socket) are helpers, an unweighted joint on its only child
 * is a control joint, and a weighted foot parented to the ground root joins its leg. */
static void test_helpers_and_forest(void **state)
{
    (void)state;
    sb_joint js[SB_COUNT(sb_biped) + 8];
    size_t n = 0;
    js[n++] = (sb_joint){"ground", NULL, 0, 0, 0, RF_JOINT_UNWEIGHTED};
    js[n++] = (sb_joint){"ctrl", "ground", 0, 1.0, 0, RF_JOINT_UNWEIGHTED};
    for (size_t i = 0; i < SB_COUNT(sb_biped); i++) {
        js[n] = sb_biped[i];
        if (!js[n].parent)
            js[n].parent = "ctrl";
        if (strcmp(js[n].name, "l_foot") == 0) /* the foot hangs from the ground root */
            js[n].parent = "ground";
        n++;
    }
    js[n++] = (sb_joint){"ik_target", "ground", 0.1, 0.08, 0, RF_JOINT_UNWEIGHTED};
    js[n++] = (sb_joint){"pole", "ground", 0.1, 0.5, 0.6, RF_JOINT_UNWEIGHTED};
    rf_skeleton *s = sb_build(js, n);
    rf_analysis *a = rf_analyze(s, NULL);
    check_consistent(a);
    assert_section(a, s, "ik_target", RF_SECTION_HELPER, RF_SIDE_LEFT);
    assert_int_equal(section_of(a, s, "pole")->type, RF_SECTION_HELPER);
    assert_int_equal(section_of(a, s, "ground")->type, RF_SECTION_ROOT);
    assert_true(a->joints[sb_find(s, "ctrl")].flags & RF_JI_CONTROL);
    assert_section(a, s, "l_foot", RF_SECTION_LEG, RF_SIDE_LEFT);
    assert_int_equal(a->joints[sb_find(s, "l_foot")].logical_parent, sb_find(s, "l_shin"));
    check_biped_sections(a, s);
    rf_analysis_free(a);
    rf_skeleton_free(s);
}

/* Rewrites a skeleton built with identity rests the way Blender exports it: every joint turned
 * so its bone runs along local +Y towards its first child (a leaf keeps its parent's turn), no
 * end sites. */
static void blenderize(rf_skeleton *s)
{
    uint32_t n = s->joint_count;
    rf_vec3 *pos = calloc(n, sizeof *pos);
    rf_quat *world = calloc(n, sizeof *world);
    for (uint32_t i = 0; i < n; i++) {
        int32_t p = s->joints[i].parent;
        pos[i] = p >= 0 ? rf_v3_add(pos[p], s->joints[i].rest.t) : s->joints[i].rest.t;
    }
    for (uint32_t i = 0; i < n; i++) {
        int32_t p = s->joints[i].parent, child = -1;
        for (uint32_t k = i + 1; k < n && child < 0; k++)
            child = s->joints[k].parent == (int32_t)i ? (int32_t)k : -1;
        world[i] = p >= 0 ? world[p] : rf_quat_identity();
        if (child >= 0)
            world[i] = rf_quat_from_two_vectors(rf_v3(0, 1, 0), rf_v3_sub(pos[child], pos[i]));
        else if (s->joints[i].flags & RF_JOINT_HAS_END_SITE) /* a leaf aims at its end site */
            world[i] = rf_quat_from_two_vectors(rf_v3(0, 1, 0), s->joints[i].end_site);
        rf_quat pr = p >= 0 ? world[p] : rf_quat_identity();
        s->joints[i].rest.t =
            rf_quat_rotate(rf_quat_conj(pr), p >= 0 ? rf_v3_sub(pos[i], pos[p]) : pos[i]);
        s->joints[i].rest.r = rf_quat_normalize(rf_quat_mul(rf_quat_conj(pr), world[i]));
        s->joints[i].flags &= ~(uint32_t)RF_JOINT_HAS_END_SITE;
    }
    free(pos);
    free(world);
}

/* A mesh skinned to the head alone (a VRM sample's UI quads) says nothing about the limbs:
 * they stay limbs, not helpers. A weighted bone folding back from the skull into the body (the
 * quads' "Meter") is not part of the head. Bones along +Y, as Blender writes them. */
static void test_partial_skin_and_fold(void **state)
{
    (void)state;
    sb_joint js[SB_COUNT(sb_biped) + 1];
    size_t n = 0;
    for (size_t i = 0; i < SB_COUNT(sb_biped); i++) {
        if (sb_biped[i].name[0] == '.')
            continue;
        js[n] = sb_biped[i];
        js[n].flags = strcmp(js[n].name, "head") == 0 ? 0 : RF_JOINT_UNWEIGHTED;
        n++;
    }
    js[n++] = (sb_joint){"badge", "head", 0, 1.30, 0.02, 0};
    rf_skeleton *s = sb_build(js, n);
    blenderize(s);
    rf_analysis *a = rf_analyze(s, NULL);
    check_consistent(a);
    assert_near_dir(a->up, rf_v3(0, 1, 0));
    assert_section(a, s, "l_forearm", RF_SECTION_ARM, RF_SIDE_LEFT);
    assert_section(a, s, "r_shin", RF_SECTION_LEG, RF_SIDE_RIGHT);
    assert_section(a, s, "head", RF_SECTION_HEAD, RF_SIDE_CENTER);
    assert_int_not_equal(a->joints[sb_find(s, "badge")].section,
                         a->joints[sb_find(s, "head")].section);
    rf_analysis_free(a);
    rf_skeleton_free(s);
}

/* A quadruped facing -Z, bones along +Y and no end sites (as Blender writes them), whose hind
 * legs are digitigrade: the shin runs back and down to a hock above the ground, cut in two by a
 * twist joint, and the foot is a leaf bone aimed forward and down at a ground it does not reach
 * (its tip is only guessed). The shin's lower half lies flatter than the foot; counted as the
 * foot it voted backwards (0.3 * 0.83^2 = 0.21 per leg against the forefeet's 0.15 measured to
 * their last pivot: feet -0.115). The foot is the leaf, measured along its own bone: the hind
 * feet are steep and do not vote; each forefoot (0.02 up over 0.06 forward: flat 0.95) votes
 * 0.3 * 0.95^2 = 0.27 forward. */
static void test_digitigrade_foot_leaf(void **state)
{
    (void)state;
    static const sb_joint hind[] = {
        {"hl1", "pelvis", -0.15, 0.88, 0.50, 0}, {"hl2", "hl1", -0.15, 0.48, 0.40, 0},
        {"hl3", "hl2", -0.15, 0.40, 0.52, 0},    {"hl4", "hl3", -0.15, 0.32, 0.64, 0},
        {".", "hl4", -0.15, 0.03, 0.50, 0},      {"hr1", "pelvis", 0.15, 0.88, 0.50, 0},
        {"hr2", "hr1", 0.15, 0.48, 0.40, 0},     {"hr3", "hr2", 0.15, 0.40, 0.52, 0},
        {"hr4", "hr3", 0.15, 0.32, 0.64, 0},     {".", "hr4", 0.15, 0.03, 0.50, 0},
    };
    sb_joint js[SB_COUNT(sb_quadruped)];
    size_t n = 0;
    for (size_t i = 0; i < SB_COUNT(sb_quadruped); i++) {
        const char *name = sb_quadruped[i].name, *parent = sb_quadruped[i].parent;
        bool hind_leg = name[0] == 'h' && name[1] != 'e';
        bool hind_end = name[0] == '.' && parent[0] == 'h' && parent[1] != 'e';
        if (!hind_leg && !hind_end)
            js[n++] = sb_quadruped[i];
    }
    memcpy(js + n, hind, sizeof hind);
    n += SB_COUNT(hind);
    rf_skeleton *s = sb_build(js, n);
    blenderize(s);
    rf_analysis *a = rf_analyze(s, NULL);
    assert_non_null(a);
    check_consistent(a);
    assert_near_dir(a->up, rf_v3(0, 1, 0));
    assert_near_dir(a->forward, rf_v3(0, 0, -1));
    assert_float_equal(a->forward_cues[0], 2 * 0.3 * 0.9, 0.01); /* flat^2 = 0.06^2 / 0.004 */
    assert_section(a, s, "hl4", RF_SECTION_LEG, RF_SIDE_LEFT);
    rf_analysis_free(a);
    rf_skeleton_free(s);
}

/* A sitting frog facing +Z: each hind leg's shin runs back and down from the hip and its foot
 * forward again along the ground, so the tip farthest from the hip is the heel. The foot that
 * votes for the facing is the chain's last bone (toes forward), not the bone reaching farthest
 * (the shin, pointing back); the head, higher at the front, agrees. Any yaw, any scale. */
static void test_folded_hind_feet(void **state)
{
    (void)state;
    static const sb_joint frog[] = {
        {"torso", NULL, 0, 0.23, -0.18, 0},        {"head", "torso", 0, 0.40, 0.25, 0},
        {".", "head", 0, 0.30, 0.50, 0},           {"l_leg", "torso", 0.28, 0.23, -0.18, 0},
        {"l_foot", "l_leg", 0.28, 0.03, -0.40, 0}, {".", "l_foot", 0.32, 0.03, -0.08, 0},
        {"r_leg", "torso", -0.28, 0.23, -0.18, 0}, {"r_foot", "r_leg", -0.28, 0.03, -0.40, 0},
        {".", "r_foot", -0.32, 0.03, -0.08, 0},    {"l_arm", "torso", 0.28, 0.25, 0.16, 0},
        {".", "l_arm", 0.26, 0.0, 0.18, 0},        {"r_arm", "torso", -0.28, 0.25, 0.16, 0},
        {".", "r_arm", -0.26, 0.0, 0.18, 0},
    };
    const double yaws[] = {0, 90, 180, 270, 35};
    for (size_t i = 0; i < SB_COUNT(yaws); i++) {
        rf_quat r = rf_quat_from_axis_angle(rf_v3(0, 1, 0), yaws[i] * RF_PI / 180);
        rf_skeleton *s = sb_build_xf(frog, SB_COUNT(frog), r, 3.0, rf_v3(1, 0, -4));
        rf_analysis *a = rf_analyze(s, NULL);
        assert_non_null(a);
        check_consistent(a);
        assert_near_dir(a->up, rf_v3(0, 1, 0));
        assert_near_dir(a->forward, rf_quat_rotate(r, rf_v3(0, 0, 1)));
        assert_true(a->forward_cues[0] > 0); /* the feet agree */
        rf_analysis_free(a);
        rf_skeleton_free(s);
    }
}

/* The curve skeleton the general rigger drew in the animalia bat (positions rounded), which lies
 * on its belly with its wings spread level (+Y up, facing -Z: its mesh spans 0.34 in Y against
 * 1.5 across and 0.76 along, its feet on y = 0). Its legs trail back along the ground, so under
 * -Z (stood on its tail) its limbs hang a little better than under +Y, where they lie flat:
 * the file's declared +Y decides the close call. Any yaw. */
static void test_lying_bat_declared_up(void **state)
{
    (void)state;
    static const sb_joint bat[] = {
        {"spine0", NULL, 0, 0.094, 0.078, 0},
        {"spine1", "spine0", 0, 0.120, -0.143, 0},
        {"head", "spine1", 0, 0.163, -0.328, 0},
        {".", "head", 0.055, 0.219, -0.328, 0},
        {"ear_r", "spine1", -0.137, 0.258, -0.203, 0},
        {".", "ear_r", -0.172, 0.344, -0.203, 0},
        {"ear_l", "spine1", 0.137, 0.258, -0.203, 0},
        {".", "ear_l", 0.172, 0.344, -0.203, 0},
        {"leg_r0", "spine0", -0.048, 0.062, 0.147, 0},
        {"leg_r1", "leg_r0", -0.097, 0.030, 0.218, 0},
        {"leg_r2", "leg_r1", -0.152, 0.003, 0.387, 0},
        {"leg_r3", "leg_r2", -0.158, 0.002, 0.398, 0},
        {".", "leg_r3", -0.172, 0.0, 0.422, 0},
        {"leg_l0", "spine0", 0.048, 0.062, 0.147, 0},
        {"leg_l1", "leg_l0", 0.097, 0.030, 0.218, 0},
        {"leg_l2", "leg_l1", 0.152, 0.003, 0.387, 0},
        {"leg_l3", "leg_l2", 0.158, 0.002, 0.398, 0},
        {".", "leg_l3", 0.172, 0.0, 0.422, 0},
        {"arm_r0", "spine1", -0.115, 0.122, -0.078, 0},
        {"arm_r1", "arm_r0", -0.131, 0.122, -0.069, 0},
        {"arm_r2", "arm_r1", -0.277, 0.125, 0.012, 0},
        {"arm_r3", "arm_r2", -0.710, 0.125, 0.046, 0},
        {".", "arm_r3", -0.750, 0.125, -0.133, 0},
        {"arm_l0", "spine1", 0.115, 0.122, -0.078, 0},
        {"arm_l1", "arm_l0", 0.131, 0.122, -0.069, 0},
        {"arm_l2", "arm_l1", 0.277, 0.125, 0.012, 0},
        {"arm_l3", "arm_l2", 0.710, 0.125, 0.046, 0},
        {".", "arm_l3", 0.750, 0.125, -0.133, 0},
    };
    const double yaws[] = {0, 90, 200};
    for (size_t i = 0; i < SB_COUNT(yaws); i++) {
        rf_quat r = rf_quat_from_axis_angle(rf_v3(0, 1, 0), yaws[i] * RF_PI / 180);
        rf_skeleton *s = sb_build_xf(bat, SB_COUNT(bat), r, 2.0, rf_v3(0, 0, 0));
        s->up = rf_v3(0, 1, 0);
        rf_analysis *a = rf_analyze(s, NULL);
        assert_non_null(a);
        check_consistent(a);
        assert_near_dir(a->up, rf_v3(0, 1, 0));
        rf_analysis_free(a);
        rf_skeleton_free(s);
    }
}

/* A quadruped rooted the way a curve skeleton is: the root low between the hind legs, the spine
 * rising from it to the pelvis and running forward, the tail leaving the pelvis upwards and then
 * back. The rear girdle (the root) carries no tail, so the chain behind it off the spine is the
 * tail, all of it: its first bone turns from the spine's, which is no reason to cut the chain. */
static void test_tail_off_spine(void **state)
{
    (void)state;
    static const sb_joint quad[] = {
        {"root", NULL, 0, 0.85, 0.50, 0},        {"pelvis", "root", 0, 1.00, 0.50, 0},
        {"spine1", "pelvis", 0, 1.05, 0.20, 0},  {"spine2", "spine1", 0, 1.05, -0.10, 0},
        {"chest", "spine2", 0, 1.00, -0.40, 0},  {"neck", "chest", 0, 1.20, -0.60, 0},
        {"head", "neck", 0, 1.35, -0.75, 0},     {".", "head", 0, 1.30, -0.95, 0},
        {"tail1", "pelvis", 0, 1.10, 0.55, 0},   {"tail2", "tail1", 0, 1.05, 0.75, 0},
        {"tail3", "tail2", 0, 0.95, 0.95, 0},    {".", "tail3", 0, 0.85, 1.15, 0},
        {"fl1", "chest", -0.15, 0.90, -0.40, 0}, {"fl2", "fl1", -0.15, 0.50, -0.36, 0},
        {"fl3", "fl2", -0.15, 0.10, -0.42, 0},   {"fl4", "fl3", -0.15, 0.02, -0.50, 0},
        {".", "fl4", -0.15, 0.0, -0.56, 0},      {"fr1", "chest", 0.15, 0.90, -0.40, 0},
        {"fr2", "fr1", 0.15, 0.50, -0.36, 0},    {"fr3", "fr2", 0.15, 0.10, -0.42, 0},
        {"fr4", "fr3", 0.15, 0.02, -0.50, 0},    {".", "fr4", 0.15, 0.0, -0.56, 0},
        {"hl1", "root", -0.15, 0.80, 0.50, 0},   {"hl2", "hl1", -0.15, 0.55, 0.40, 0},
        {"hl3", "hl2", -0.15, 0.30, 0.55, 0},    {"hl4", "hl3", -0.15, 0.03, 0.50, 0},
        {".", "hl4", -0.15, 0.0, 0.44, 0},       {"hr1", "root", 0.15, 0.80, 0.50, 0},
        {"hr2", "hr1", 0.15, 0.55, 0.40, 0},     {"hr3", "hr2", 0.15, 0.30, 0.55, 0},
        {"hr4", "hr3", 0.15, 0.03, 0.50, 0},     {".", "hr4", 0.15, 0.0, 0.44, 0},
    };
    const double yaws[] = {0, 90, 215};
    for (size_t i = 0; i < SB_COUNT(yaws); i++) {
        rf_quat r = rf_quat_from_axis_angle(rf_v3(0, 1, 0), yaws[i] * RF_PI / 180);
        rf_skeleton *s = sb_build_xf(quad, SB_COUNT(quad), r, 1.5, rf_v3(2, 0, 1));
        rf_analysis *a = rf_analyze(s, NULL);
        assert_non_null(a);
        check_consistent(a);
        assert_near_dir(a->forward, rf_quat_rotate(r, rf_v3(0, 0, -1)));
        assert_section(a, s, "tail1", RF_SECTION_TAIL, RF_SIDE_CENTER);
        assert_section(a, s, "tail3", RF_SECTION_TAIL, RF_SIDE_CENTER);
        assert_int_equal(section_of(a, s, "tail1")->bone_count, 3);
        assert_section(a, s, "hl2", RF_SECTION_LEG, RF_SIDE_LEFT);
        rf_analysis_free(a);
        rf_skeleton_free(s);
    }
}

/* A rest pose with every bone along +X (Maya joint orients at zero rotation) is no body; the
 * clip shows it: its first frame repeats the line, the next two are the biped. */
static void test_degenerate_rest(void **state)
{
    (void)state;
    rf_skeleton *body = sb_build(sb_biped, SB_COUNT(sb_biped));
    rf_skeleton *line = sb_build(sb_biped, SB_COUNT(sb_biped));
    uint32_t n = line->joint_count;
    for (uint32_t j = 1; j < n; j++)
        line->joints[j].rest.t = rf_v3(rf_v3_len(body->joints[j].rest.t), 0, 0);
    const sb_joint strip[] = {{"a", NULL, 0, 1, 0, 0}, {"b", "a", 0, 2, 0, 0}};
    rf_skeleton *chain = sb_build(strip, 2);
    assert_true(rf_pose_degenerate(line));
    assert_false(rf_pose_degenerate(body));
    assert_false(rf_pose_degenerate(chain)); /* a straight chain may be straight */
    rf_animation *clip = rf_animation_new(n, 3, 30);
    for (uint32_t f = 0; f < 3; f++)
        for (uint32_t j = 0; j < n; j++) {
            rf_vec3 t = (f == 0 ? line : body)->joints[j].rest.t;
            float *r = clip->rotations + ((size_t)f * n + j) * 4,
                  *x = clip->translations + ((size_t)f * n + j) * 3;
            r[0] = r[1] = r[2] = 0, r[3] = 1;
            x[0] = (float)t.x, x[1] = (float)t.y, x[2] = (float)t.z;
        }
    rf_skeleton *frame9 = rf_posed_view(line, clip, 9); /* clamped to the last frame */
    assert_non_null(frame9);
    assert_false(rf_pose_degenerate(frame9));
    rf_animation *other = rf_animation_new(n - 1, 1, 30);
    assert_null(rf_posed_view(line, other, 0)); /* made for another skeleton */
    int32_t frame;
    rf_skeleton *best = rf_posed_best(line, clip, &frame);
    assert_non_null(best);
    rf_analysis *a = rf_analyze(best, NULL);
    check_consistent(a);
    assert_near_dir(a->up, rf_v3(0, 1, 0));
    check_biped_sections(a, best);
    rf_analysis_free(a);
    rf_posed_free(best);
    rf_posed_free(frame9);
    rf_animation_free(clip);
    rf_animation_free(other);
    rf_skeleton_free(body);
    rf_skeleton_free(line);
    rf_skeleton_free(chain);
}

/* A weapon socket in one hand (a short leaf the other hand lacks) is a prop, not a finger: the
 * hands keep the same shape on both sides. */
static void test_socket(void **state)
{
    (void)state;
    sb_joint js[SB_COUNT(sb_biped) + 1];
    size_t n = 0;
    for (size_t i = 0; i < SB_COUNT(sb_biped); i++)
        js[n++] = sb_biped[i];
    js[n++] = (sb_joint){"r_socket", "r_hand", -0.75, 1.49, -0.03, 0};
    rf_skeleton *s = sb_build(js, n);
    rf_analysis *a = rf_analyze(s, NULL);
    check_consistent(a);
    assert_true(a->joints[sb_find(s, "r_socket")].flags & RF_JI_UNPAIRED);
    assert_int_equal(section_of(a, s, "r_socket")->type, RF_SECTION_HELPER);
    check_biped_sections(a, s);
    assert_int_equal(section_of(a, s, "r_finger")->bone_count,
                     section_of(a, s, "l_finger")->bone_count);
    rf_analysis_free(a);
    rf_skeleton_free(s);
}

/* A head whose only child is a leaf hung below it (a display card, a prop): the head's bone goes
 * on up from the neck rather than turning down to the card (a retarget would stand it on its
 * head). Checked against the rig's geometry: the tip is over the head's pivot. */
static void test_folded_leaf(void **state)
{
    (void)state;
    sb_joint js[SB_COUNT(sb_biped) + 1];
    size_t n = 0;
    for (size_t i = 0; i < SB_COUNT(sb_biped); i++)
        if (!(sb_biped[i].parent && !strcmp(sb_biped[i].parent, "head")))
            js[n++] = sb_biped[i];
    js[n++] = (sb_joint){"card", "head", 0, 1.30, 0.05, 0};
    rf_skeleton *s = sb_build(js, n);
    rf_analysis *a = rf_analyze(s, NULL);
    assert_non_null(a);
    const rf_joint_info *head = &a->joints[sb_find(s, "head")];
    assert_true(head->tip.y > head->pos.y + 0.05);
    rf_analysis_free(a);
    /* Folding back less than 120 degrees (a foot under a shin) still ends the bone. */
    js[n - 1] = (sb_joint){"card", "head", 0, 1.65, 0.20, 0};
    rf_skeleton_free(s);
    s = sb_build(js, n);
    a = rf_analyze(s, NULL);
    assert_non_null(a);
    head = &a->joints[sb_find(s, "head")];
    assert_true(fabs(head->tip.z - 0.20) < 1e-9 && fabs(head->tip.y - 1.65) < 1e-9);
    rf_analysis_free(a);
    rf_skeleton_free(s);
}

/* Arms hanging to mid-thigh stay arms by default and become legs with a higher threshold. */
static void test_leg_threshold(void **state)
{
    (void)state;
    sb_joint js[SB_COUNT(sb_biped)];
    memcpy(js, sb_biped, sizeof js);
    for (size_t i = 0; i < SB_COUNT(sb_biped); i++) {
        const char *nm = js[i].name[0] == '.' ? js[i].parent : js[i].name;
        bool arm =
            strstr(nm, "arm") || strstr(nm, "hand") || strstr(nm, "finger") || strstr(nm, "thumb");
        if (arm && strcmp(nm, "l_arm") && strcmp(nm, "r_arm")) { /* hang down from the shoulder */
            double out = fabs(js[i].x) - 0.18;
            js[i].y = 1.50 - out * 1.1;
            js[i].x = js[i].x > 0 ? 0.2 : -0.2;
        }
    }
    rf_skeleton *s = sb_build(js, SB_COUNT(sb_biped));
    rf_analysis *a = rf_analyze(s, NULL);
    assert_section(a, s, "l_forearm", RF_SECTION_ARM, RF_SIDE_LEFT);
    rf_analysis_free(a);
    rf_analysis_options o = {0};
    o.leg_threshold = 0.6;
    a = rf_analyze(s, &o);
    assert_section(a, s, "l_forearm", RF_SECTION_LEG, RF_SIDE_LEFT);
    rf_analysis_free(a);
    rf_skeleton_free(s);
}

/* Positions along a section grow, the spine ends at its front girdle. */
static void test_measures(void **state)
{
    (void)state;
    rf_skeleton *s = sb_build(sb_biped, SB_COUNT(sb_biped));
    rf_analysis *a = rf_analyze(s, NULL);
    for (uint32_t k = 0; k < a->section_count; k++) {
        const uint32_t *js = rf_section_joints(a, k);
        for (uint32_t i = 0; i + 1 < a->sections[k].bone_count; i++)
            assert_true(a->joints[js[i]].u0 <= a->joints[js[i + 1]].u0 + 1e-12);
        assert_true(a->sections[k].length > 0);
    }
    assert_true(fabs(a->joints[sb_find(s, "chest")].u0 - 1.0) < 1e-9);
    assert_true(a->joints[sb_find(s, "chest")].flags & RF_JI_GIRDLE);
    assert_true(a->joints[sb_find(s, "hips")].flags & RF_JI_GIRDLE);
    assert_string_equal(rf_section_type_name(RF_SECTION_APPENDAGE), "appendage");
    rf_section_type t;
    assert_true(rf_section_type_parse("foot", &t) && t == RF_SECTION_FOOT);
    assert_false(rf_section_type_parse("wing", &t));
    rf_analysis_free(a);
    rf_skeleton_free(s);
}

/* A curve skeleton cut by the general rigger from a wizard holding a staff in his right hand
 * (world positions of its joints, the file declaring +Y up): the legs' first joints are a tenth
 * of the body apart in height, so the plane between them tilts by 6 degrees and misses the arms;
 * the staff on the right arm outweighs the left arm. The plane holds the declared up, the spine
 * carrying the staff stays on the centerline, the arms and legs pair, and the staff is the right
 * hand's, not the spine's. */
static const sb_joint staff_rig[] = {
    {"hips", NULL, -0.019, 0.927, -0.016, 0},       {"spine", "hips", 0.057, 1.348, -0.074, 0},
    {"chest", "spine", -0.005, 1.754, -0.028, 0},   {"top", "chest", 0.009, 2.110, -0.053, 0},
    {"l_leg", "hips", 0.285, 0.588, -0.071, 0},     {"l_shin", "l_leg", 0.248, 0.254, -0.053, 0},
    {".l_end", "l_shin", 0.25, 0.0, -0.05, 0},      {"r_leg", "hips", -0.224, 0.493, -0.071, 0},
    {"r_shin", "r_leg", -0.250, 0.239, -0.053, 0},  {".r_end", "r_shin", -0.25, 0.0, -0.05, 0},
    {"neck", "top", 0.0, 2.448, -0.038, 0},         {"head", "neck", 0.0, 2.807, -0.090, 0},
    {"crown", "head", 0.023, 2.947, -0.330, 0},     {".crown_end", "crown", 0.03, 3.0, -0.4, 0},
    {"l_arm", "top", 0.793, 1.856, -0.051, 0},      {"l_fore", "l_arm", 0.865, 1.845, -0.048, 0},
    {"l_hand", "l_fore", 1.185, 1.852, -0.038, 0},  {".l_hand_end", "l_hand", 1.3, 1.85, -0.04, 0},
    {"r_arm", "top", -0.817, 1.869, -0.046, 0},     {"r_fore", "r_arm", -0.884, 1.868, -0.048, 0},
    {"r_hand", "r_fore", -1.008, 1.885, -0.039, 0}, {"grip", "r_hand", -1.347, 1.864, 0.015, 0},
    {"staff", "grip", -1.304, 1.821, -0.330, 0},    {"staff1", "staff", -1.302, 1.820, -0.657, 0},
    {"staff2", "staff1", -1.318, 1.817, -1.034, 0}, {".staff_end", "staff2", -1.32, 1.81, -1.3, 0},
    {"knob", "grip", -1.455, 1.831, -0.041, 0},     {"staff_top", "grip", -1.303, 1.815, 0.482, 0},
};

static void test_staff_in_one_hand(void **state)
{
    (void)state;
    rf_skeleton *s = sb_build(staff_rig, SB_COUNT(staff_rig));
    s->up = rf_v3(0, 1, 0), s->forward = rf_v3(0, 0, 1);
    rf_analysis *a = rf_analyze(s, NULL);
    check_consistent(a);
    assert_near_dir(a->up, rf_v3(0, 1, 0));
    assert_near_dir(a->left, rf_v3(1, 0, 0));
    const char *spine[] = {"hips", "spine", "chest", "top"};
    for (size_t i = 0; i < 4; i++)
        assert_section(a, s, spine[i], RF_SECTION_SPINE, RF_SIDE_CENTER);
    assert_section(a, s, "head", RF_SECTION_HEAD, RF_SIDE_CENTER);
    assert_section(a, s, "l_shin", RF_SECTION_LEG, RF_SIDE_LEFT);
    assert_section(a, s, "r_shin", RF_SECTION_LEG, RF_SIDE_RIGHT);
    assert_section(a, s, "l_fore", RF_SECTION_ARM, RF_SIDE_LEFT);
    assert_section(a, s, "r_fore", RF_SECTION_ARM, RF_SIDE_RIGHT);
    assert_int_equal(a->joints[sb_find(s, "staff1")].side, RF_SIDE_RIGHT);
    assert_int_equal(section_of(a, s, "l_leg")->mirror, a->joints[sb_find(s, "r_leg")].section);
    rf_analysis_free(a);
    rf_skeleton_free(s);
}

/* A placement root on the floor at the origin, the body standing beside it (a clip's frame that
 * left the hips away from the origin): the root is no limb, however far off the body's plane. */
static void test_placement_root_off_plane(void **state)
{
    (void)state;
    sb_joint js[SB_COUNT(sb_biped) + 1];
    size_t n = 0;
    js[n++] = (sb_joint){"placement", NULL, 0, 0, 0, 0};
    for (size_t i = 0; i < SB_COUNT(sb_biped); i++) {
        js[n] = sb_biped[i];
        js[n].x += 0.3, js[n].z += 0.1;
        if (!js[n].parent)
            js[n].parent = "placement";
        n++;
    }
    rf_skeleton *s = sb_build(js, n);
    rf_analysis *a = rf_analyze(s, NULL);
    check_consistent(a);
    assert_near_dir(a->up, rf_v3(0, 1, 0));
    assert_near_dir(a->forward, rf_v3(0, 0, 1));
    rf_section_type t = section_of(a, s, "placement")->type;
    assert_true(t == RF_SECTION_ROOT || t == RF_SECTION_HELPER);
    check_biped_sections(a, s);
    rf_analysis_free(a);
    rf_skeleton_free(s);
}

/* The general rigger's curve skeleton of greenman (sb_blob_rig). The root is body (not a placement:
 * it lies under the body, along the declared up; not a ground root: nothing under it reaches the
 * ground), the chest on the centerline, the arms a left and a right arm mirroring each other;
 * turned about up with the declared forward. Before, no plane was proposed (the chains' centroids
 * are no mirror images), every joint read as centerline and the root as a placement helper. */
static void test_blob_uneven_arms(void **state)
{
    (void)state;
    const double yaws[] = {0, 30, 137, -61};
    for (size_t i = 0; i < SB_COUNT(yaws); i++) {
        rf_quat r = rf_quat_from_axis_angle(rf_v3(0, 1, 0), yaws[i] * RF_PI / 180);
        rf_skeleton *s = sb_build_xf(sb_blob_rig, SB_COUNT(sb_blob_rig), r, 1.0, rf_v3(0, 0, 0));
        s->up = rf_v3(0, 1, 0), s->forward = rf_quat_rotate(r, rf_v3(0, 0, 1));
        rf_analysis *a = rf_analyze(s, NULL);
        check_consistent(a);
        assert_near_dir(a->left, rf_quat_rotate(r, rf_v3(1, 0, 0)));
        assert_int_equal(section_of(a, s, "root")->type, RF_SECTION_SPINE);
        const rf_section *chest = section_of(a, s, "chest");
        assert_int_equal(chest->type, RF_SECTION_SPINE);
        assert_int_equal(chest->side, RF_SIDE_CENTER);
        const rf_section *l = section_of(a, s, "l2"), *rt = section_of(a, s, "r2");
        assert_int_equal(l->type, RF_SECTION_ARM);
        assert_int_equal(l->side, RF_SIDE_LEFT);
        assert_int_equal(rt->type, RF_SECTION_ARM);
        assert_int_equal(rt->side, RF_SIDE_RIGHT);
        assert_ptr_equal(&a->sections[l->mirror], rt);
        rf_analysis_free(a);
        rf_skeleton_free(s);
    }
}

/* A head whose chain leans a little to one side (a curve skeleton through a box head): all of
 * the neck's descendants lie on one side of the plane, as a hip offset's leg does, but nothing
 * mirrors them: the neck and head stay on the centerline, not an unpaired arm. */
static void test_head_leaning(void **state)
{
    (void)state;
    sb_joint js[SB_COUNT(sb_biped)];
    size_t n = 0;
    for (size_t i = 0; i < SB_COUNT(sb_biped); i++) {
        js[n] = sb_biped[i];
        if (!strcmp(js[n].name, "head"))
            js[n].x = 0.03;
        n++;
    }
    rf_skeleton *s = sb_build(js, n);
    rf_analysis *a = rf_analyze(s, NULL);
    check_consistent(a);
    check_biped_sections(a, s);
    rf_analysis_free(a);
    rf_skeleton_free(s);
}

/* The same wizard rigged with limbs laid out along the curves: the right arm runs on into the
 * staff, so the arms mirror each other only near the body and the best plane, between the legs,
 * tilts by 4.5 degrees. Once up is known the plane stands upright and is re-centred on its twin
 * pairs: the spine (its second joint 0.06 right of the hips) stays on the centerline. */
static const sb_joint staff_layout[] = {
    {"hips", NULL, -0.019, 0.927, -0.016, 0},       {"spine", "hips", 0.057, 1.348, -0.074, 0},
    {"chest", "spine", -0.005, 1.754, -0.028, 0},   {"top", "chest", 0.009, 2.110, -0.053, 0},
    {"neck", "top", 0.0, 2.448, -0.038, 0},         {"head", "neck", 0.0, 2.807, -0.090, 0},
    {"crown", "head", 0.023, 2.947, -0.330, 0},     {".", "crown", -0.051, 2.979, -0.625, 0},
    {"l_hip", "hips", 0.151, 0.738, -0.047, 0},     {"l_knee", "l_hip", 0.285, 0.588, -0.071, 0},
    {"l_ankle", "l_knee", 0.248, 0.241, -0.040, 0}, {"l_toe", "l_ankle", 0.250, 0.163, 0.040, 0},
    {".", "l_toe", 0.253, -0.003, 0.209, 0},        {"r_hip", "hips", -0.119, 0.715, -0.043, 0},
    {"r_knee", "r_hip", -0.224, 0.493, -0.071, 0},  {"r_ankle", "r_knee", -0.250, 0.232, -0.045, 0},
    {"r_toe", "r_ankle", -0.249, 0.162, 0.031, 0},  {".", "r_toe", -0.247, 0.014, 0.191, 0},
    {"l_clav", "top", 0.219, 2.042, -0.053, 0},     {"l_arm", "l_clav", 0.249, 2.032, -0.053, 0},
    {"l_fore", "l_arm", 0.610, 1.915, -0.052, 0},   {"l_hand", "l_fore", 1.227, 1.845, -0.054, 0},
    {".", "l_hand", 1.520, 1.803, -0.165, 0},       {"r_clav", "top", -0.360, 1.994, -0.050, 0},
    {"r_arm", "r_clav", -0.413, 1.977, -0.050, 0},  {"r_fore", "r_arm", -1.347, 1.830, 0.015, 0},
    {"staff", "r_fore", -1.307, 1.808, -0.793, 0},  {".", "staff", -1.307, 1.808, -1.346, 0},
};

static void test_staff_laid_out(void **state)
{
    (void)state;
    rf_skeleton *s = sb_build(staff_layout, SB_COUNT(staff_layout));
    s->up = rf_v3(0, 1, 0), s->forward = rf_v3(0, 0, 1);
    rf_analysis *a = rf_analyze(s, NULL);
    check_consistent(a);
    assert_near_dir(a->up, rf_v3(0, 1, 0));
    const char *spine[] = {"hips", "spine", "chest", "top"};
    for (size_t i = 0; i < 4; i++)
        assert_section(a, s, spine[i], RF_SECTION_SPINE, RF_SIDE_CENTER);
    assert_section(a, s, "head", RF_SECTION_HEAD, RF_SIDE_CENTER);
    assert_section(a, s, "l_knee", RF_SECTION_LEG, RF_SIDE_LEFT);
    assert_section(a, s, "r_knee", RF_SECTION_LEG, RF_SIDE_RIGHT);
    assert_int_equal(a->joints[sb_find(s, "l_fore")].side, RF_SIDE_LEFT);
    assert_int_equal(a->joints[sb_find(s, "r_fore")].side, RF_SIDE_RIGHT);
    rf_analysis_free(a);
    rf_skeleton_free(s);
}

/* A quadruped whose head carries a pair of long ears (a curve skeleton's ears, 0.55 of a leg's
 * reach): the ears hang from the head, not from a girdle, so the spine ends at the forelegs and
 * the head stays the head. */
static void test_quadruped_ears(void **state)
{
    (void)state;
    sb_joint js[SB_COUNT(sb_quadruped) + 4];
    size_t n = 0;
    for (size_t i = 0; i < SB_COUNT(sb_quadruped); i++)
        js[n++] = sb_quadruped[i];
    js[n++] = (sb_joint){"l_ear", "head", -0.08, 1.42, -0.75, 0};
    js[n++] = (sb_joint){".", "l_ear", -0.36, 1.77, -0.72, 0};
    js[n++] = (sb_joint){"r_ear", "head", 0.08, 1.42, -0.75, 0};
    js[n++] = (sb_joint){".", "r_ear", 0.36, 1.77, -0.72, 0};
    rf_skeleton *s = sb_build(js, n);
    rf_analysis *a = rf_analyze(s, NULL);
    check_consistent(a);
    assert_near_dir(a->up, rf_v3(0, 1, 0));
    assert_near_dir(a->forward, rf_v3(0, 0, -1));
    assert_section(a, s, "chest", RF_SECTION_SPINE, RF_SIDE_CENTER);
    assert_section(a, s, "neck", RF_SECTION_HEAD, RF_SIDE_CENTER);
    assert_section(a, s, "head", RF_SECTION_HEAD, RF_SIDE_CENTER);
    assert_int_equal(section_of(a, s, "l_ear")->type, RF_SECTION_APPENDAGE);
    assert_int_equal(section_of(a, s, "fl2")->type, RF_SECTION_LEG);
    rf_analysis_free(a);
    rf_skeleton_free(s);
}

/* The general rigger's rig of the Wizard in /work/shared/data (rig-dump, to 4 decimals): a
 * biped with one arm reaching forward and down to a staff, declared +y up and +z forward. */
static const sb_joint wizard_auto[] = {
    {"spine0", NULL, -0.0192, 0.9265, -0.0156, 0},
    {"spine1", "spine0", 0.0573, 1.3475, -0.0739, 0},
    {"spine2", "spine1", -0.0049, 1.7543, -0.0277, 0},
    {"spine3", "spine2", 0.0088, 2.1103, -0.0532, 0},
    {"head0", "spine3", 0.0046, 2.2651, -0.0464, 0},
    {"head1", "head0", -0.0017, 2.7467, -0.0908, 0},
    {"head2", "head1", 0.0233, 2.9473, -0.3304, 0},
    {"l_leg0", "spine0", 0.1506, 0.7378, -0.0468, 0},
    {"l_leg1", "l_leg0", 0.2849, 0.5884, -0.0715, 0},
    {"l_leg2", "l_leg1", 0.2480, 0.2409, -0.0401, 0},
    {"l_leg3", "l_leg2", 0.2497, 0.1627, 0.0396, 0},
    {"r_leg0", "spine0", -0.1191, 0.7149, -0.0427, 0},
    {"r_leg1", "r_leg0", -0.2238, 0.4930, -0.0712, 0},
    {"r_leg2", "r_leg1", -0.2501, 0.2316, -0.0452, 0},
    {"r_leg3", "r_leg2", -0.2489, 0.1620, 0.0305, 0},
    {"l_arm0", "spine3", 0.2190, 2.0421, -0.0527, 0},
    {"l_arm1", "l_arm0", 0.2491, 2.0324, -0.0526, 0},
    {"l_arm2", "l_arm1", 0.6095, 1.9154, -0.0517, 0},
    {"l_arm3", "l_arm2", 1.2272, 1.8455, -0.0544, 0},
    {"r_arm0", "spine3", -0.3603, 1.9936, -0.0502, 0},
    {"r_arm1", "r_arm0", -0.4131, 1.9769, -0.0497, 0},
    {"r_arm2", "r_arm1", -1.3470, 1.8301, 0.0145, 0},
    {"r_arm3", "r_arm2", -1.3075, 1.8082, -0.7929, 0},
};

/* A skeleton turned about up together with its declared axes is the same body: every joint
 * keeps its section, type and side (the rigger's Wizard rig turned 30 degrees once read its
 * spine, neck and head as the left arm and hand). */
static void test_turned_with_declared_axes(void **state)
{
    (void)state;
    const sb_joint *rigs[] = {wizard_auto, sb_biped};
    const size_t counts[] = {SB_COUNT(wizard_auto), SB_COUNT(sb_biped)};
    const double yaws[] = {30, 137, -61, 90};
    for (size_t k = 0; k < 4; k++) { /* with up and forward declared, then up alone */
        bool up_only = k >= 2;
        rf_skeleton *s0 = sb_build(rigs[k % 2], counts[k % 2]);
        s0->up = rf_v3(0, 1, 0), s0->forward = rf_v3(0, 0, up_only ? 0 : 1);
        rf_analysis *a0 = rf_analyze(s0, NULL);
        assert_non_null(a0);
        for (size_t i = 0; i < sizeof yaws / sizeof yaws[0]; i++) {
            rf_quat r = rf_quat_from_axis_angle(rf_v3(0, 1, 0), yaws[i] * RF_PI / 180);
            rf_skeleton *s = sb_build_xf(rigs[k % 2], counts[k % 2], r, 1.0, rf_v3(0, 0, 0));
            s->up = rf_v3(0, 1, 0), s->forward = rf_quat_rotate(r, s0->forward);
            rf_analysis *a = rf_analyze(s, NULL);
            assert_non_null(a);
            assert_near_dir(a->up, a0->up);
            /* the size sets every tolerance: measured along the body's axes, not the file's */
            if (fabs(a->size - a0->size) > 1e-9 * a0->size)
                fail_msg("turned %.0f degrees: size %.6g, unturned %.6g", yaws[i], a->size,
                         a0->size);
            /* with up alone the facing comes from the body, so it turns with it too (the
             * coordinate +z it once fell back on read it facing back past 90 degrees) */
            if (rf_v3_dot(a->forward, rf_quat_rotate(r, a0->forward)) < 0.99)
                fail_msg("turned %.0f degrees%s: forward from %s, unturned from %s", yaws[i],
                         up_only ? " (up alone declared)" : "", a->forward_source,
                         a0->forward_source);
            for (uint32_t j = 0; j < s->joint_count; j++) {
                int32_t x = a0->joints[j].section, y = a->joints[j].section;
                rf_side sx = a0->joints[j].side, sy = a->joints[j].side;
                rf_section_type tx = x >= 0 ? a0->sections[x].type : RF_SECTION_NONE;
                rf_section_type ty = y >= 0 ? a->sections[y].type : RF_SECTION_NONE;
                if (tx != ty || sx != sy)
                    fail_msg("turned %.0f degrees%s: %s reads %s %s, unturned %s %s", yaws[i],
                             up_only ? " (up alone declared)" : "", s->joints[j].name,
                             rf_side_name(sy), rf_section_type_name(ty), rf_side_name(sx),
                             rf_section_type_name(tx));
            }
            rf_analysis_free(a);
            rf_skeleton_free(s);
        }
        rf_analysis_free(a0);
        rf_skeleton_free(s0);
    }
}

/* The rigger's Wizard rig declared facing -z, against the body (a file whose forward is wrong,
 * or a body turned by half a turn with the axes left as they were): its spine is still the
 * centerline, its head the head. Its spine wobbles 0.077 off the symmetry plane, and with the
 * centerline's limit at half the tolerance (0.078) it was an arm whenever the plane's offset
 * moved by 0.002, as it did with the facing reversed. */
static void test_declared_back(void **state)
{
    (void)state;
    for (int sign = -1; sign <= 1; sign += 2) {
        rf_skeleton *s = sb_build(wizard_auto, SB_COUNT(wizard_auto));
        s->up = rf_v3(0, 1, 0), s->forward = rf_v3(0, 0, sign);
        rf_analysis *a = rf_analyze(s, NULL);
        assert_non_null(a);
        assert_near_dir(a->forward, rf_v3(0, 0, sign));
        const char *spine[] = {"spine0", "spine1", "spine2", "spine3"};
        for (int i = 0; i < 4; i++)
            assert_section(a, s, spine[i], RF_SECTION_SPINE, RF_SIDE_CENTER);
        assert_section(a, s, "head2", RF_SECTION_HEAD, RF_SIDE_CENTER);
        assert_section(a, s, "l_arm2", RF_SECTION_ARM, sign > 0 ? RF_SIDE_LEFT : RF_SIDE_RIGHT);
        rf_analysis_free(a);
        rf_skeleton_free(s);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_biped),
        cmocka_unit_test(test_biped_facing),
        cmocka_unit_test(test_turned_with_declared_axes),
        cmocka_unit_test(test_declared_back),
        cmocka_unit_test(test_quadruped),
        cmocka_unit_test(test_facing_dissent),
        cmocka_unit_test(test_bird_ground),
        cmocka_unit_test(test_hand_on_cut_forearm),
        cmocka_unit_test(test_dragon_folded_wings),
        cmocka_unit_test(test_insect_one_girdle),
        cmocka_unit_test(test_roll_leaves),
        cmocka_unit_test(test_strip),
        cmocka_unit_test(test_degenerate),
        cmocka_unit_test(test_large),
        cmocka_unit_test(test_forced_axes),
        cmocka_unit_test(test_forced_plane_unmatched),
        cmocka_unit_test(test_helpers_and_forest),
        cmocka_unit_test(test_leg_threshold),
        cmocka_unit_test(test_measures),
        cmocka_unit_test(test_partial_skin_and_fold),
        cmocka_unit_test(test_digitigrade_foot_leaf),
        cmocka_unit_test(test_folded_hind_feet),
        cmocka_unit_test(test_lying_bat_declared_up),
        cmocka_unit_test(test_tail_off_spine),
        cmocka_unit_test(test_degenerate_rest),
        cmocka_unit_test(test_socket),
        cmocka_unit_test(test_folded_leaf),
        cmocka_unit_test(test_staff_in_one_hand),
        cmocka_unit_test(test_placement_root_off_plane),
        cmocka_unit_test(test_head_leaning),
        cmocka_unit_test(test_blob_uneven_arms),
        cmocka_unit_test(test_staff_laid_out),
        cmocka_unit_test(test_quadruped_ears),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
