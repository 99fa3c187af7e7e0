/* The skeletal-similarity matcher: weight sets, every metric, the duplicate-bone removal against
 * brute force (including the thesis's Tables 3 and 4), facing, several sources, preference,
 * blending, the mirror setting, reversed knees, threshold, explanations, degenerate input. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "match-similarity/similarity.h"
#include "skel-build.h"

static rf_skeleton *biped_facing(double yaw_degrees)
{
    rf_quat r = rf_quat_from_axis_angle(rf_v3(0, 1, 0), yaw_degrees * RF_PI / 180);
    return sb_build_xf(sb_biped, SB_COUNT(sb_biped), r, 1, rf_v3(0, 0, 0));
}

static rf_mapping *match1(const rf_skeleton *t, const rf_skeleton *s, const rf_ms_options *o)
{
    char err[256];
    const rf_skeleton *src[1] = {s};
    rf_mapping *m = rf_ms_match(t, src, 1, o, NULL, err, sizeof err);
    if (!m)
        fail_msg("%s", err);
    return m;
}

/* The source joint (by name) driving the target joint `name`, or NULL when unmapped. */
static const char *driver(const rf_mapping *m, const rf_skeleton *t, const rf_skeleton *const *s,
                          const char *name, uint32_t *source)
{
    int32_t j = sb_find(t, name);
    assert_true(j >= 0);
    const rf_map_entry *e = &m->entries[j];
    if (!e->input_count)
        return NULL;
    if (source)
        *source = e->inputs[0].source;
    return s[e->inputs[0].source]->joints[e->inputs[0].joint].name;
}

static void assert_driver(const rf_mapping *m, const rf_skeleton *t, const rf_skeleton *s,
                          const char *name, const char *want)
{
    const rf_skeleton *src[1] = {s};
    const char *got = driver(m, t, src, name, NULL);
    if ((got == NULL) != (want == NULL) || (got && strcmp(got, want) != 0))
        fail_msg("%s is driven by %s, expected %s", name, got ? got : "nothing",
                 want ? want : "nothing");
}

static double metric(const rf_mapping *m, const rf_skeleton *t, const char *joint, const char *name)
{
    int32_t j = sb_find(t, joint);
    for (uint32_t k = 0; k < m->metric_count; k++)
        if (strcmp(m->metric_names[k], name) == 0)
            return m->entries[j].metrics[k];
    fail_msg("no metric %s", name);
    return 0;
}

static void test_weight_sets(void **state)
{
    (void)state;
    rf_ms_weights w;
    uint32_t pref;
    assert_true(rf_ms_weight_set("default", &w, &pref));
    const double table1[] = {30, 50, 15, 10, 15, 16, 5, 0};
    for (int i = 0; i < 8; i++)
        assert_true(w.w[i] == table1[i]);
    assert_true(w.w[RF_MS_BODY_POSITION] > 0 && w.w[RF_MS_DIGIT_ORDER] > 0);
    assert_true(rf_ms_weight_set("thesis", &w, &pref));
    assert_true(w.w[RF_MS_BODY_POSITION] == 0 && w.w[RF_MS_DIGIT_ORDER] == 0);
    assert_true(rf_ms_weight_set("prefer-2", &w, &pref));
    assert_int_equal(pref, 2);
    assert_true(w.w[RF_MS_PREFERENCE] == 10);
    assert_true(rf_ms_weight_set("thesis-prefer-0", &w, &pref));
    assert_false(rf_ms_weight_set("prefer-", &w, &pref));
    assert_false(rf_ms_weight_set("heavy", &w, &pref));
    assert_string_equal(rf_ms_metric_names[RF_MS_SAME_SIDE], "same_side");
}

/* ---- assignment against brute force ---- */

/* Lowest total over every order-preserving matching that uses each bone of the shorter side
 * exactly once, by enumeration. */
static double brute_assign(const double *cost, uint32_t n, uint32_t m, uint32_t i, uint32_t k,
                           uint32_t left_t, uint32_t left_s)
{
    if (n >= m ? left_s == 0 : left_t == 0)
        return 0;
    double best = INFINITY;
    for (uint32_t a = i; a < n; a++)
        for (uint32_t b = k; b < m; b++) {
            if (n >= m ? b != k : a != i) /* the shorter side may not skip */
                continue;
            double rest = brute_assign(cost, n, m, a + 1, b + 1, left_t - 1, left_s - 1);
            best = fmin(best, cost[a * m + b] + rest);
        }
    return best;
}

/* Lowest total over every order-preserving partial matching, each bone left out costing skip. */
static double brute_align(const double *cost, uint32_t n, uint32_t m, uint32_t i, uint32_t k,
                          double skip)
{
    if (i == n || k == m)
        return skip * ((n - i) + (m - k));
    double best = cost[i * m + k] + brute_align(cost, n, m, i + 1, k + 1, skip);
    best = fmin(best, skip + brute_align(cost, n, m, i + 1, k, skip));
    return fmin(best, skip + brute_align(cost, n, m, i, k + 1, skip));
}

static double total_of_match(const double *cost, uint32_t n, uint32_t m, const int32_t *match,
                             double skip)
{
    double t = 0;
    uint32_t used = 0;
    int32_t last = -1;
    for (uint32_t i = 0; i < n; i++) {
        if (match[i] < 0) {
            t += skip;
            continue;
        }
        assert_true(match[i] > last && (uint32_t)match[i] < m); /* order kept, no duplicate */
        last = match[i];
        t += cost[i * m + (uint32_t)match[i]];
        used++;
    }
    return t + skip * (m - used);
}

static void test_assign_thesis_tables(void **state)
{
    (void)state;
    /* Table 3: limb bones 1..4 of the target against A, B, C of the source; X is not allowed. */
    const double X = 1e9;
    const double cost[4 * 3] = {0.2, X, X, 0.4, 0.3, X, X, 0.1, 0.2, X, X, 0.3};
    int32_t match[4];
    double total = rf_ms_assign(cost, 4, 3, match);
    assert_true(fabs(total - 0.6) < 1e-9); /* Table 4: 1A 3B 4C, 0.6 */
    assert_int_equal(match[0], 0);
    assert_int_equal(match[1], -1);
    assert_int_equal(match[2], 1);
    assert_int_equal(match[3], 2);
}

static void test_assign_brute_force(void **state)
{
    (void)state;
    srand(11);
    for (int round = 0; round < 400; round++) {
        uint32_t n = 1 + (uint32_t)rand() % 6, m = 1 + (uint32_t)rand() % 6;
        double cost[36];
        for (uint32_t i = 0; i < n * m; i++)
            cost[i] = (rand() % 1000) / 1000.0;
        int32_t match[6];
        double dp = rf_ms_assign(cost, n, m, match);
        double brute = brute_assign(cost, n, m, 0, 0, n, m);
        assert_true(fabs(dp - brute) < 1e-9);
        uint32_t matched = 0;
        for (uint32_t i = 0; i < n; i++)
            matched += match[i] >= 0;
        assert_int_equal(matched, n < m ? n : m);
        assert_true(fabs(total_of_match(cost, n, m, match, 0) - dp) < 1e-9);

        double skip = (rand() % 600) / 1000.0;
        double al = rf_ms_align(cost, n, m, skip, match);
        assert_true(fabs(al - brute_align(cost, n, m, 0, 0, skip)) < 1e-9);
        assert_true(fabs(total_of_match(cost, n, m, match, skip) - al) < 1e-9);
    }
    int32_t none[1];
    assert_true(rf_ms_assign(NULL, 0, 3, none) == 0);
}

/* A price for skipping that is not a finite number >= 0 is refused, every match -1 (an infinite
 * one left the walk back without a step and it read beyond the table). */
static void test_align_refuses_bad_skip(void **state)
{
    (void)state;
    const double cost[6] = {0.1, 0.5, 0.9, 0.4, 0.2, 0.7};
    const double bad[] = {INFINITY, -INFINITY, NAN, -0.5};
    for (size_t b = 0; b < sizeof bad / sizeof bad[0]; b++) {
        int32_t match[3] = {7, 7, 7};
        assert_true(rf_ms_align(cost, 3, 2, bad[b], match) == -1);
        assert_int_equal(match[0], -1);
        assert_int_equal(match[2], -1);
    }
    int32_t match[3];
    assert_true(rf_ms_align(cost, 3, 2, 0.0, match) >= 0);
}

/* ---- metrics ---- */

/* A body mapped onto itself: every joint to itself, each metric at its full weight. */
static void test_identity_and_metrics(void **state)
{
    (void)state;
    rf_skeleton *s = biped_facing(0);
    rf_mapping *m = match1(s, s, NULL);
    assert_int_equal(m->metric_count, RF_MS_METRIC_COUNT);
    for (uint32_t j = 0; j < s->joint_count; j++) {
        assert_int_equal(m->entries[j].input_count, 1);
        assert_int_equal(m->entries[j].inputs[0].joint, j);
        assert_int_equal(m->entries[j].inputs[0].flags, 0);
    }
    assert_true(metric(m, s, "l_forearm", "same_side") == 30);
    assert_true(metric(m, s, "l_forearm", "same_type") == 50);
    assert_true(metric(m, s, "l_forearm", "similar_type") == 0);
    assert_true(metric(m, s, "l_forearm", "bone_count") == 10);
    assert_true(fabs(metric(m, s, "l_forearm", "orientation") - 15) < 1e-9);
    assert_true(fabs(metric(m, s, "l_forearm", "sequence") - 16) < 1e-9);
    assert_true(metric(m, s, "l_forearm", "continuity") == 5);
    assert_true(metric(m, s, "l_forearm", "preference") == 0);
    assert_true(metric(m, s, "l_forearm", "body_position") == 20);
    assert_true(metric(m, s, "l_thumb", "digit_order") == 20);
    int32_t f = sb_find(s, "l_forearm");
    double sum = 0;
    for (uint32_t k = 0; k < m->metric_count; k++)
        sum += m->entries[f].metrics[k];
    assert_true(fabs(m->entries[f].score - sum) < 1e-9);
    assert_string_equal(m->sections[f], "arm");
    assert_string_equal(m->sides[f], "left");
    rf_mapping_free(m);
    rf_skeleton_free(s);
}

/* Orientation falls quadratically from full points to none at the angle given. */
static void test_orientation_falloff(void **state)
{
    (void)state;
    rf_skeleton *s = biped_facing(0);
    rf_skeleton *t = biped_facing(0);
    /* turn the target's left forearm 20 degrees down: its end moves, nothing else */
    int32_t hand = sb_find(t, "l_hand");
    rf_vec3 off = t->joints[hand].rest.t;
    double len = rf_v3_len(off), a = 20 * RF_PI / 180;
    t->joints[hand].rest.t = rf_v3(len * cos(a), -len * sin(a), off.z);
    double dir_angle = rf_v3_angle(off, t->joints[hand].rest.t) * 180 / RF_PI;
    rf_ms_options o = {0};
    o.orientation_angle = 40;
    rf_mapping *m = match1(t, s, &o);
    double want = 15 * (1 - pow(dir_angle / 40, 2));
    assert_true(fabs(metric(m, t, "l_forearm", "orientation") - want) < 0.2);
    assert_driver(m, t, s, "l_forearm", "l_forearm");
    rf_mapping_free(m);
    /* the thesis: the maximum angle is the orientation weight, 15 degrees */
    o = (rf_ms_options){0};
    o.thesis = true;
    m = match1(t, s, &o);
    assert_true(metric(m, t, "l_forearm", "orientation") == 0);
    rf_mapping_free(m);
    rf_skeleton_free(s);
    rf_skeleton_free(t);
}

/* Facing +Z onto facing -Z (and a quarter turn): sides come from the bodies, never the axes. */
static void test_facing(void **state)
{
    (void)state;
    const double yaws[] = {180, 90};
    rf_skeleton *s = biped_facing(0);
    for (int i = 0; i < 2; i++) {
        rf_skeleton *t = biped_facing(yaws[i]);
        rf_mapping *m = match1(t, s, NULL);
        for (uint32_t j = 0; j < t->joint_count; j++) {
            assert_int_equal(m->entries[j].input_count, 1);
            assert_string_equal(s->joints[m->entries[j].inputs[0].joint].name, t->joints[j].name);
        }
        rf_mapping_free(m);
        rf_skeleton_free(t);
    }
    rf_skeleton_free(s);
}

/* A biped onto a quadruped: forelegs take the arms, hind legs the legs, the tail stays
 * unmapped (no counterpart of the same type). */
static void test_biped_onto_quadruped(void **state)
{
    (void)state;
    rf_skeleton *s = biped_facing(0);
    rf_skeleton *t = sb_build(sb_quadruped, SB_COUNT(sb_quadruped));
    rf_ms_options homology = {0};
    homology.forelegs_arms = true;
    rf_mapping *m = match1(t, s, &homology);
    assert_driver(m, t, s, "pelvis", "hips");
    assert_driver(m, t, s, "chest", "chest");
    assert_driver(m, t, s, "head", "head");
    assert_driver(m, t, s, "fl1", "l_arm");
    assert_driver(m, t, s, "fr2", "r_forearm");
    assert_driver(m, t, s, "hl1", "l_thigh");
    assert_driver(m, t, s, "hr2", "r_shin");
    assert_driver(m, t, s, "tail2", NULL);
    assert_true(metric(m, t, "fl1", "body_position") > 15);
    rf_mapping_free(m);
    rf_skeleton_free(s);
    rf_skeleton_free(t);
}

/* Whether target joint `name` is driven with RF_MAP_MIRROR (half a cycle later). */
static bool phased(const rf_mapping *m, const rf_skeleton *t, const char *name)
{
    const rf_map_entry *e = &m->entries[sb_find(t, name)];
    return e->input_count && (e->inputs[0].flags & RF_MAP_MIRROR);
}

/* The gait rule: forelegs standing on the floor under a source that walks on two legs take the
 * source's leg of their side half a cycle later (a trot); the hind legs are unchanged. A source on
 * four legs, or a biped target, keeps every limb on its counterpart in phase. */
static void test_gait(void **state)
{
    (void)state;
    rf_skeleton *s = biped_facing(0);
    rf_skeleton *q = sb_build(sb_quadruped, SB_COUNT(sb_quadruped));
    rf_mapping *m = match1(q, s, NULL);
    assert_driver(m, q, s, "fl1", "l_thigh");
    assert_driver(m, q, s, "fl2", "l_shin");
    assert_driver(m, q, s, "fr1", "r_thigh");
    assert_driver(m, q, s, "fr2", "r_shin");
    assert_driver(m, q, s, "hl1", "l_thigh");
    assert_driver(m, q, s, "hr2", "r_shin");
    assert_driver(m, q, s, "chest", "chest");
    assert_driver(m, q, s, "tail2", NULL);
    assert_true(phased(m, q, "fl1") && phased(m, q, "fr2"));
    assert_false(phased(m, q, "hl1") || phased(m, q, "hr2") || phased(m, q, "chest"));
    rf_mapping_free(m);
    m = match1(q, q, NULL); /* four legs onto four legs */
    assert_driver(m, q, q, "fl2", "fl2");
    assert_driver(m, q, q, "hr2", "hr2");
    for (uint32_t j = 0; j < q->joint_count; j++)
        assert_false(m->entries[j].input_count && (m->entries[j].inputs[0].flags & RF_MAP_MIRROR));
    rf_mapping_free(m);
    m = match1(s, s, NULL); /* two legs onto two legs */
    assert_driver(m, s, s, "l_arm", "l_arm");
    for (uint32_t j = 0; j < s->joint_count; j++)
        assert_false(m->entries[j].input_count && (m->entries[j].inputs[0].flags & RF_MAP_MIRROR));
    rf_mapping_free(m);
    /* the quadruped onto the biped: its arms keep the forelegs (the rule reads the target's) */
    m = match1(s, q, NULL);
    assert_driver(m, s, q, "l_arm", "fl1");
    assert_false(phased(m, s, "l_arm"));
    rf_mapping_free(m);
    rf_skeleton_free(s);
    rf_skeleton_free(q);
}

/* sb_quadruped with its head (joints 5 and 6: the head and its tip) replaced by `head`, n joints
 * hanging from its neck or from one another; returns the joint count. */
static size_t quadruped_with_head(sb_joint *out, const sb_joint *head, size_t n)
{
    size_t k = 0;
    for (size_t i = 0; i < SB_COUNT(sb_quadruped); i++)
        if (i != 5 && i != 6)
            out[k++] = sb_quadruped[i];
    for (size_t i = 0; i < n; i++)
        out[k++] = head[i];
    return k;
}

/* A quadruped as artists build one: the chest joint sits behind the shoulders and its bone ends
 * where the forelegs leave and the neck starts (the animalia cat's Torso and Neck), unlike
 * sb_quadruped's chest, which sits where the forelegs leave with its bone running up to the neck
 * as a curve skeleton's girdle joint does. */
static const sb_joint artist_quadruped[] = {
    {"pelvis", NULL, 0, 1.00, 0.50, 0},    {"spine", "pelvis", 0, 1.05, 0.20, 0},
    {"chest", "spine", 0, 1.05, -0.05, 0}, {"neck", "chest", 0, 1.05, -0.42, 0},
    {"head", "neck", 0, 1.30, -0.70, 0},   {".", "head", 0, 1.30, -0.95, 0},
    {"tail1", "pelvis", 0, 1.05, 0.60, 0}, {"tail2", "tail1", 0, 0.95, 0.85, 0},
    {".", "tail2", 0, 0.80, 1.10, 0},      {"fl1", "chest", -0.15, 0.90, -0.40, 0},
    {"fl2", "fl1", -0.15, 0.50, -0.36, 0}, {"fl3", "fl2", -0.15, 0.05, -0.42, 0},
    {".", "fl3", -0.15, 0.0, -0.52, 0},    {"fr1", "chest", 0.15, 0.90, -0.40, 0},
    {"fr2", "fr1", 0.15, 0.50, -0.36, 0},  {"fr3", "fr2", 0.15, 0.05, -0.42, 0},
    {".", "fr3", 0.15, 0.0, -0.52, 0},     {"hl1", "pelvis", -0.15, 0.90, 0.50, 0},
    {"hl2", "hl1", -0.15, 0.50, 0.40, 0},  {"hl3", "hl2", -0.15, 0.05, 0.52, 0},
    {".", "hl3", -0.15, 0.0, 0.44, 0},     {"hr1", "pelvis", 0.15, 0.90, 0.50, 0},
    {"hr2", "hr1", 0.15, 0.50, 0.40, 0},   {"hr3", "hr2", 0.15, 0.05, 0.52, 0},
    {".", "hr3", 0.15, 0.0, 0.44, 0},
};

/* A target without a head (girdle=neck): greenman's curve skeleton (sb_blob_rig: root, a chest
 * carrying both arms, no head) against an artist's rig of such a blob (the pelvis joint carrying
 * the arms, the legs and a one-joint head pivoting where the arms leave, whose skin is the whole
 * top of the body): the chest takes the head; not by default, where it is left to the root's
 * pelvis; not where the source has a chest joint of its own carrying the arms (the chest takes
 * it). */
static const sb_joint blob_artist[] = {
    {"body_low", NULL, 0, 0.45, 0, 0},        {"body_up", "body_low", 0, 0.84, 0, 0},
    {".", "body_up", 0, 1.60, 0, 0},          {"hand_L", "body_low", 0.80, 0.78, 0, 0},
    {".", "hand_L", 1.30, 0.74, 0, 0},        {"hand_R", "body_low", -0.80, 0.78, 0, 0},
    {".", "hand_R", -1.30, 0.74, 0, 0},       {"hip_L", "body_low", 0.40, 0.40, 0, 0},
    {"leg_L", "hip_L", 0.45, 0.20, 0, 0},     {".", "leg_L", 0.45, 0.0, 0, 0},
    {"hip_R", "body_low", -0.40, 0.40, 0, 0}, {"leg_R", "hip_R", -0.45, 0.20, 0, 0},
    {".", "leg_R", -0.45, 0.0, 0, 0},
};

static rf_skeleton *build_axes(const sb_joint *js, size_t n)
{
    rf_skeleton *s = sb_build(js, n);
    s->up = rf_v3(0, 1, 0), s->forward = rf_v3(0, 0, 1);
    return s;
}

/* What --explain prints for t mapped onto s with options o (malloc'd). */
static char *explained(const rf_skeleton *t, const rf_skeleton *s, const rf_ms_options *o)
{
    rf_ms_explain e = {0};
    char err[256], *text = NULL;
    size_t size = 0;
    const rf_skeleton *src[1] = {s};
    rf_mapping *m = rf_ms_match(t, src, 1, o, &e, err, sizeof err);
    assert_non_null(m);
    FILE *out = open_memstream(&text, &size);
    rf_ms_explain_print(&e, m, t, src, out);
    fclose(out);
    rf_ms_explain_clear(&e);
    rf_mapping_free(m);
    return text;
}

static void test_headless_target(void **state)
{
    (void)state;
    rf_skeleton *t = build_axes(sb_blob_rig, SB_COUNT(sb_blob_rig));
    rf_skeleton *s = build_axes(blob_artist, SB_COUNT(blob_artist));
    rf_ms_options o = {.forelegs_arms = true, .girdle_neck = true};
    rf_mapping *m = match1(t, s, &o);
    assert_driver(m, t, s, "root", "body_low");
    assert_driver(m, t, s, "chest", "body_up");
    assert_driver(m, t, s, "r0", "hand_R");
    rf_mapping_free(m);
    /* --explain says why */
    char *text = explained(t, s, &o);
    assert_non_null(strstr(text, "chest (center spine) <- 0:body_up"));
    assert_non_null(strstr(text, "ending a trunk without a head takes the source's head"));
    free(text);
    o.girdle_neck = false;
    m = match1(t, s, &o);
    assert_driver(m, t, s, "root", "body_low");
    assert_driver(m, t, s, "chest", NULL);
    rf_mapping_free(m);
    /* a source with a chest joint of its own carrying the arms, the head above it */
    sb_joint chest[SB_COUNT(blob_artist) + 1];
    size_t n = 0;
    for (size_t i = 0; i < SB_COUNT(blob_artist); i++) {
        chest[n] = blob_artist[i];
        if (strcmp(chest[n].name, "body_up") == 0) {
            chest[n++] = (sb_joint){"chest", "body_low", 0, 0.78, 0, 0};
            chest[n] = blob_artist[i];
            chest[n].parent = "chest", chest[n].y = 1.0;
        } else if (strncmp(chest[n].name, "hand_", 5) == 0) {
            chest[n].parent = "chest";
        }
        n++;
    }
    rf_skeleton *sc = build_axes(chest, n);
    o.girdle_neck = true;
    m = match1(t, sc, &o);
    assert_driver(m, t, sc, "chest", "chest");
    rf_mapping_free(m);
    rf_skeleton_free(sc);
    rf_skeleton_free(s);
    rf_skeleton_free(t);
}

/* A source whose trunk links carry no skin (girdle=neck): an artist's biped whose spine, chest
 * and neck joints are unweighted, the hips' skin running over the whole trunk and the head's
 * over the neck (RobotExpressive's Abdomen, Torso and Neck). A target joint given one of them
 * takes the joint holding the skin about it, the nearer of the nearest weighted ancestor and
 * the next weighted joint of its section: the spine and the chest the hips, the neck the head.
 * By default (motion) they keep the links, which carry the turn their children follow. */
static void test_skinless_links(void **state)
{
    (void)state;
    sb_joint links[SB_COUNT(sb_biped)];
    for (size_t i = 0; i < SB_COUNT(sb_biped); i++) {
        links[i] = sb_biped[i];
        if (strcmp(links[i].name, "spine") == 0 || strcmp(links[i].name, "chest") == 0 ||
            strcmp(links[i].name, "neck") == 0)
            links[i].flags |= RF_JOINT_UNWEIGHTED;
    }
    rf_skeleton *t = build_axes(sb_biped, SB_COUNT(sb_biped));
    rf_skeleton *s = build_axes(links, SB_COUNT(links));
    rf_ms_options o = {.forelegs_arms = true};
    rf_mapping *m = match1(t, s, &o);
    assert_driver(m, t, s, "spine", "spine");
    assert_driver(m, t, s, "chest", "chest");
    assert_driver(m, t, s, "neck", "neck");
    rf_mapping_free(m);
    o.girdle_neck = true;
    m = match1(t, s, &o);
    assert_driver(m, t, s, "hips", "hips");
    assert_driver(m, t, s, "spine", "hips");
    assert_driver(m, t, s, "chest", "hips");
    assert_driver(m, t, s, "neck", "head");
    assert_driver(m, t, s, "head", "head");
    assert_driver(m, t, s, "l_arm", "l_arm");
    rf_mapping_free(m);
    /* --explain says why */
    char *text = explained(t, s, &o);
    assert_non_null(strstr(text, "its match carries no skin"));
    free(text);
    rf_skeleton_free(s);
    rf_skeleton_free(t);
}

/* After the girdle joint takes the source's neck (girdle=neck), the rest of the target's spine
 * is aligned again with the whole source spine, both placed from where their limbs leave: a
 * curve skeleton whose girdle joint sits where its arms leave (c3) against an artist's spine
 * whose chest joint (Torso) pivots well below the shoulders, its clavicles rising to the arms
 * (the Wizard's, as both rigs place them): c3 takes the neck and c2, below it, the chest; before,
 * c2 kept the abdomen and the chest drove nothing. c3's bone then runs past the artist's skull
 * pivot, in the bodies' frames, and it takes the head (girdle_past_skull); with the skull pivot
 * higher, the neck. The artist's hands are fists (a fist digit and a thumb), the curve
 * skeleton's arms end at the fist without digits. */
static const sb_joint trunk_artist[] = {
    {"hips", NULL, 0, 1.03, 0, 0},
    {"abdomen", "hips", 0, 1.24, 0, 0},
    {"torso", "abdomen", 0, 1.56, 0, 0},
    {"neck", "torso", 0, 2.00, 0, 0},
    {"head", "neck", 0, 2.13, 0, 0},
    {".", "head", 0, 2.90, 0, 0},
    {"shoulder_l", "torso", 0.13, 1.70, 0, 0},
    {"arm_l", "shoulder_l", 0.32, 1.87, 0, 0},
    {"forearm_l", "arm_l", 0.71, 1.87, 0, 0},
    {"fist_l", "forearm_l", 1.16, 1.86, 0, 0},
    {"fist1_l", "fist_l", 1.29, 1.86, 0, 0},
    {".", "fist1_l", 1.40, 1.85, 0, 0},
    {"thumb_l", "forearm_l", 1.16, 1.86, 0, 0},
    {"thumb1_l", "thumb_l", 1.22, 1.82, 0.08, 0},
    {".", "thumb1_l", 1.26, 1.80, 0.12, 0},
    {"shoulder_r", "torso", -0.13, 1.70, 0, 0},
    {"arm_r", "shoulder_r", -0.32, 1.87, 0, 0},
    {"forearm_r", "arm_r", -0.71, 1.87, 0, 0},
    {"fist_r", "forearm_r", -1.16, 1.86, 0, 0},
    {"fist1_r", "fist_r", -1.29, 1.86, 0, 0},
    {".", "fist1_r", -1.40, 1.85, 0, 0},
    {"thumb_r", "forearm_r", -1.16, 1.86, 0, 0},
    {"thumb1_r", "thumb_r", -1.22, 1.82, 0.08, 0},
    {".", "thumb1_r", -1.26, 1.80, 0.12, 0},
    {"thigh_l", "hips", 0.20, 1.00, 0, 0},
    {"shin_l", "thigh_l", 0.20, 0.60, 0.02, 0},
    {"foot_l", "shin_l", 0.20, 0.06, 0, 0},
    {".", "foot_l", 0.20, 0.0, 0.20, 0},
    {"thigh_r", "hips", -0.20, 1.00, 0, 0},
    {"shin_r", "thigh_r", -0.20, 0.60, 0.02, 0},
    {"foot_r", "shin_r", -0.20, 0.06, 0, 0},
    {".", "foot_r", -0.20, 0.0, 0.20, 0},
};

static const sb_joint trunk_rig[] = {
    {"c0", NULL, 0, 0.93, 0, 0},
    {"c1", "c0", 0, 1.35, 0, 0},
    {"c2", "c1", 0, 1.76, 0, 0},
    {"c3", "c2", 0, 2.11, 0, 0},
    {"h0", "c3", 0, 2.27, 0, 0},
    {"h1", "h0", 0, 2.75, 0, 0},
    {".", "h1", 0, 2.95, 0, 0},
    {"a0_l", "c3", 0.22, 2.04, 0, 0},
    {"a1_l", "a0_l", 0.25, 2.03, 0, 0},
    {"a2_l", "a1_l", 0.61, 1.92, 0, 0},
    {"a3_l", "a2_l", 1.23, 1.85, 0, 0},
    {".", "a3_l", 1.40, 1.84, 0, 0},
    {"a0_r", "c3", -0.22, 2.04, 0, 0},
    {"a1_r", "a0_r", -0.25, 2.03, 0, 0},
    {"a2_r", "a1_r", -0.61, 1.92, 0, 0},
    {"a3_r", "a2_r", -1.23, 1.85, 0, 0},
    {".", "a3_r", -1.40, 1.84, 0, 0},
    {"l0_l", "c0", 0.15, 0.74, 0, 0},
    {"l1_l", "l0_l", 0.25, 0.24, 0.02, 0},
    {"l2_l", "l1_l", 0.25, 0.05, 0, 0},
    {".", "l2_l", 0.25, 0.0, 0.15, 0},
    {"l0_r", "c0", -0.15, 0.74, 0, 0},
    {"l1_r", "l0_r", -0.25, 0.24, 0.02, 0},
    {"l2_r", "l1_r", -0.25, 0.05, 0, 0},
    {".", "l2_r", -0.25, 0.0, 0.15, 0},
};

static void test_spine_before_girdle(void **state)
{
    (void)state;
    rf_skeleton *t = build_axes(trunk_rig, SB_COUNT(trunk_rig));
    rf_skeleton *s = build_axes(trunk_artist, SB_COUNT(trunk_artist));
    rf_ms_options o = {.forelegs_arms = true, .girdle_neck = true};
    rf_mapping *m = match1(t, s, &o);
    assert_driver(m, t, s, "c0", "hips");
    /* c3's bone (2.11 to 2.27) has its middle past the artist's skull pivot (2.13): the head */
    assert_driver(m, t, s, "c3", "head");
    assert_driver(m, t, s, "c2", "torso");
    /* the mitten hand against the fist: the arm's last joint keeps the fist the alignment gave
     * it (left to the forearm by the threshold before: no same type) */
    assert_driver(m, t, s, "a2_l", "forearm_l");
    assert_driver(m, t, s, "a3_l", "fist_l");
    assert_driver(m, t, s, "a3_r", "fist_r");
    rf_mapping_free(m);
    /* by default (motion) the fist drives no arm joint */
    o.girdle_neck = false;
    m = match1(t, s, &o);
    assert_driver(m, t, s, "a3_l", NULL);
    rf_mapping_free(m);
    rf_skeleton_free(s);
    /* the artist's skull pivot above that middle (2.25): c3 keeps the neck */
    sb_joint high[SB_COUNT(trunk_artist)];
    for (size_t i = 0; i < SB_COUNT(trunk_artist); i++) {
        high[i] = trunk_artist[i];
        if (strcmp(high[i].name, "head") == 0)
            high[i].y = 2.25;
    }
    s = build_axes(high, SB_COUNT(high));
    o.girdle_neck = true;
    m = match1(t, s, &o);
    assert_driver(m, t, s, "c3", "neck");
    assert_driver(m, t, s, "c2", "torso");
    rf_mapping_free(m);
    rf_skeleton_free(s);
    rf_skeleton_free(t);
}

/* girdle=neck: a target girdle joint whose forelimbs leave at its pivot (none of its bone behind
 * them) and whose bone runs on past the source's neck pivot is the neck's first bone, and its
 * skin is the neck's: it takes the source's first neck joint and its head chain the rest of the
 * source's head. sb_quadruped's chest bone runs from where its forelegs leave, 0.28 up and
 * forward to its neck joint: its middle lies 0.10 of the body's height past the forelegs, where
 * the biped's neck starts 0.03 past its upper arms and the artist quadruped's 0.02 past its
 * forelegs. Only on the target's side, and not by default (the joint carrying the limbs drives
 * them as a chest for motion); a target whose chest ends where its limbs leave (the biped's
 * chest: its arms leave three quarters along it; the artist quadruped's) keeps the chest. Head
 * chain joints whose bone lies past the source's skull pivot take the skull. A
 * source whose head is one joint, pivoting where the neck starts (the animalia bat's Head), has
 * no joint left for the head chain: the girdle joint takes it and so does the head chain. */
static void test_girdle_neck(void **state)
{
    (void)state;
    rf_skeleton *b = biped_facing(0);
    rf_skeleton *q = sb_build(sb_quadruped, SB_COUNT(sb_quadruped));
    rf_skeleton *a = sb_build(artist_quadruped, SB_COUNT(artist_quadruped));
    rf_ms_options o = {.forelegs_arms = true, .girdle_neck = true};
    const rf_skeleton *src[1] = {b};
    rf_ms_explain e = {0};
    char err[256], *text = NULL;
    size_t size = 0;
    rf_mapping *m = rf_ms_match(q, src, 1, &o, &e, err, sizeof err);
    assert_non_null(m);
    assert_driver(m, q, b, "chest", "neck");
    assert_driver(m, q, b, "neck", "head");
    assert_driver(m, q, b, "fl1", "l_arm");
    assert_driver(m, q, b, "hl1", "l_thigh");
    /* --explain says why the chest took a neck */
    FILE *out = open_memstream(&text, &size);
    rf_ms_explain_print(&e, m, q, src, out);
    fclose(out);
    assert_non_null(strstr(text, "chest (center spine) <- 0:neck"));
    assert_non_null(strstr(text, "takes the source's neck (girdle=neck)"));
    free(text);
    rf_ms_explain_clear(&e);
    rf_mapping_free(m);
    m = match1(q, a, &o);
    assert_driver(m, q, a, "chest", "neck");
    assert_driver(m, q, a, "neck", "head");
    assert_driver(m, q, a, "fl1", "fl1");
    rf_mapping_free(m);
    /* not by default */
    o.girdle_neck = false;
    m = match1(q, a, &o);
    assert_driver(m, q, a, "chest", "chest");
    assert_driver(m, q, a, "neck", "neck");
    rf_mapping_free(m);
    /* not where the target's chest ends at its limbs */
    o.girdle_neck = true;
    m = match1(a, q, &o);
    assert_driver(m, a, q, "chest", "chest");
    assert_driver(m, a, q, "neck", "neck");
    rf_mapping_free(m);
    /* the artist quadruped with a neck of two short joints and its skull joint at the head's
     * base (z -0.58): the target's neck bone (its middle 0.34 of the height past the forelegs,
     * the skull's pivot 0.14) lies in the skull; the alignment by places along the head chains
     * alone leaves it unmapped, following the chest's neck */
    sb_joint big[SB_COUNT(artist_quadruped) + 1];
    size_t nb = 0;
    for (size_t i = 0; i < SB_COUNT(artist_quadruped); i++) {
        big[nb] = artist_quadruped[i];
        if (strcmp(big[nb].name, "head") == 0) {
            big[nb++] = (sb_joint){"neck2", "neck", 0, 1.08, -0.50, 0};
            big[nb] = artist_quadruped[i];
            big[nb].parent = "neck2", big[nb].y = 1.12, big[nb].z = -0.58;
        }
        nb++;
    }
    rf_skeleton *bh = sb_build(big, nb);
    m = match1(q, bh, &o);
    assert_driver(m, q, bh, "chest", "neck");
    assert_driver(m, q, bh, "neck", "head");
    assert_driver(m, q, bh, "head", NULL);
    rf_mapping_free(m);
    rf_skeleton_free(bh);
    /* the artist quadruped with a one-joint head pivoting at the neck's place */
    sb_joint one[SB_COUNT(artist_quadruped)];
    size_t n = 0;
    for (size_t i = 0; i < SB_COUNT(artist_quadruped); i++) {
        if (strcmp(artist_quadruped[i].name, "neck") == 0)
            continue;
        one[n] = artist_quadruped[i];
        if (strcmp(one[n].name, "head") == 0)
            one[n].parent = "chest", one[n].y = 1.05, one[n].z = -0.42;
        n++;
    }
    rf_skeleton *h = sb_build(one, n);
    m = match1(q, h, &o);
    assert_driver(m, q, h, "chest", "head");
    assert_driver(m, q, h, "neck", "head");
    rf_mapping_free(m);
    rf_skeleton_free(h);
    m = match1(b, b, &o);
    assert_driver(m, b, b, "chest", "chest");
    assert_driver(m, b, b, "neck", "neck");
    assert_driver(m, b, b, "head", "head");
    rf_mapping_free(m);
    rf_skeleton_free(a);
    rf_skeleton_free(q);
    rf_skeleton_free(b);
}

/* A curve skeleton's head chain runs on past the skull to the snout's tip; an artist's skull
 * bone spans the whole head from where the neck enters it, longer than the neck. The target's
 * joint at the skull's place takes the source's skull, and its snout joint follows it unmapped:
 * driven by the source's skull at the chain's tip, the skull's skin would follow the neck. */
static void test_skull_before_snout(void **state)
{
    (void)state;
    /* the artist's: a short neck bone, the skull from the back of the head to the nose */
    const sb_joint artist[] = {
        {"neck", "chest", 0, 1.20, -0.60, 0},
        {"skull", "neck", 0, 1.30, -0.68, 0},
        {".", "skull", 0, 1.25, -1.05, 0},
    };
    /* the curve skeleton's: the same neck, a joint where the chain enters the head, one at the
     * snout, the tip at the nose */
    const sb_joint curve[] = {
        {"c_neck", "chest", 0, 1.20, -0.60, 0},
        {"c_skull", "c_neck", 0, 1.30, -0.68, 0},
        {"c_snout", "c_skull", 0, 1.28, -0.88, 0},
        {".", "c_snout", 0, 1.25, -1.05, 0},
    };
    sb_joint a[SB_COUNT(sb_quadruped) + 4], c[SB_COUNT(sb_quadruped) + 4];
    size_t na = quadruped_with_head(a, artist, SB_COUNT(artist));
    size_t nc = quadruped_with_head(c, curve, SB_COUNT(curve));
    rf_skeleton *s = sb_build(a, na), *t = sb_build(c, nc);
    rf_mapping *m = match1(t, s, NULL);
    assert_driver(m, t, s, "c_neck", "neck");
    assert_driver(m, t, s, "c_skull", "skull");
    assert_driver(m, t, s, "c_snout", NULL);
    rf_mapping_free(m);
    rf_skeleton_free(s);
    rf_skeleton_free(t);
}

/* A low-poly rig's leg of one joint at the hip against a leg of a short hip offset and three
 * bones (a curve skeleton's, from the spine to the hip and on): the one joint is the whole leg,
 * so it drives the offset, the chain's first joint, and the three bones follow it unmapped; a
 * leg of four real bones takes it at its first. Driving the first real bone instead left the
 * offset's skin to the pelvis. */
/* A leg joint of sb_quadruped ("fl1" .. "hr4"): its bone's number (1 to 4), else 0. */
static int leg_bone(const char *name)
{
    if (!name || strlen(name) != 3 || (name[0] != 'f' && name[0] != 'h') ||
        (name[1] != 'l' && name[1] != 'r') || name[2] < '1' || name[2] > '4')
        return 0;
    return name[2] - '0';
}

/* Rigs of one body paired joint for joint (girdle=neck): a curve skeleton's legs that start at
 * the knee, no offset at either socket (the ninja's, BCN_Epileptic's), against the biped's thigh,
 * shin, foot and toe: the knee joint takes the shin, whose pivot lies where it starts, not the
 * thigh its first real bone lines up with by count, and the ankle the foot; by default (motion)
 * the count decides as before. Legs that start with an offset bone at the hip count from the
 * shin where both their ends say so (the foot's pivot on the source's toe, the first real
 * bone's on its knee), not where the first real bone starts at the hip. The root sits low in
 * the crotch, just above the knees, as a curve skeleton's does where the legs branch off. */
static rf_skeleton *knee_legs(bool offset, bool from_knee)
{
    sb_joint j[SB_COUNT(sb_biped) + 4];
    size_t n = 0;
    for (size_t i = 0; i < SB_COUNT(sb_biped); i++) {
        const sb_joint *b = &sb_biped[i];
        const char *p = b->parent ? b->parent : "";
        if (strstr(b->name, "thigh") || strstr(b->name, "shin") || strstr(b->name, "foot") ||
            strstr(b->name, "toe") || strstr(p, "toe"))
            continue;
        j[n++] = *b;
        if (!b->parent) /* the root low in the crotch, just above the knees */
            j[n - 1].y = 0.62;
    }
    for (int side = 0; side < 2; side++) {
        double x = side ? -0.10 : 0.10;
        const char *const *nm = side ? (const char *const[]){"r_sock", "r_k0", "r_k1", "r_k2"}
                                     : (const char *const[]){"l_sock", "l_k0", "l_k1", "l_k2"};
        if (offset)
            j[n++] = (sb_joint){nm[0], "hips", x * 0.6, from_knee ? 0.56 : 0.96, 0, 0};
        j[n++] = (sb_joint){nm[1], offset ? nm[0] : "hips", x, from_knee ? 0.52 : 0.90, 0.03, 0};
        j[n++] = (sb_joint){nm[2], nm[1], x, 0.08, 0, 0};
        j[n++] = (sb_joint){nm[3], nm[2], x, 0.01, 0.13, 0};
        j[n++] = (sb_joint){".", nm[3], x, 0.0, 0.20, 0};
    }
    return build_axes(j, n);
}

static void test_legs_from_the_knee(void **state)
{
    (void)state;
    rf_skeleton *s = build_axes(sb_biped, SB_COUNT(sb_biped)), *t = knee_legs(false, true);
    rf_ms_options o = {.forelegs_arms = true, .girdle_neck = true};
    rf_mapping *m = match1(t, s, &o);
    assert_driver(m, t, s, "l_k0", "l_shin");
    assert_driver(m, t, s, "r_k0", "r_shin");
    assert_driver(m, t, s, "l_k1", "l_foot");
    assert_driver(m, t, s, "r_k2", "r_toe");
    rf_mapping_free(m);
    o.girdle_neck = false;
    m = match1(t, s, &o);
    assert_driver(m, t, s, "l_k0", "l_thigh");
    rf_mapping_free(m);
    rf_skeleton_free(t);
    /* an offset at each socket, just above the knee: its foot's pivot on the source's toe and
     * its first real bone's at the source's knee, the leg counts from the shin (the ninja's arms,
     * from an offset at the body's side by the elbow); an offset at the hip and a first real
     * bone from there over thigh and shin: from the thigh */
    o.girdle_neck = true;
    for (int knee = 0; knee < 2; knee++) {
        t = knee_legs(true, knee);
        m = match1(t, s, &o);
        assert_driver(m, t, s, "l_k0", knee ? "l_shin" : "l_thigh");
        assert_driver(m, t, s, "r_k0", knee ? "r_shin" : "r_thigh");
        if (knee)
            assert_driver(m, t, s, "r_k2", "r_toe");
        rf_mapping_free(m);
        rf_skeleton_free(t);
    }
    rf_skeleton_free(s);
}

/* A back rooted in its middle (Testwuson's Root, BCN_Epileptic's pelvis root): the artist's
 * spine runs forward from the root to the chest and a reverse spine back from it to the pelvis,
 * which carries the hind legs and the tail; sb_quadruped, rooted at its pelvis as the general
 * rigger roots a trunk, runs one spine forward. Under girdle=neck the target's pelvis takes the
 * source's (by default, and without the rule, the source's root), and its spine's middle, in
 * front of the source's back spine, the forward spine's joint whose bone holds its own's middle. */
static const sb_joint mid_rooted[] = {
    {"root", NULL, 0, 1.00, 0.00, 0},      {"front", "root", 0, 1.05, -0.20, 0},
    {"chest", "front", 0, 1.05, -0.40, 0}, {"neck", "chest", 0, 1.20, -0.60, 0},
    {"head", "neck", 0, 1.35, -0.75, 0},   {".", "head", 0, 1.30, -0.95, 0},
    {"back", "root", 0, 1.05, 0.12, 0},    {"hips", "back", 0, 1.00, 0.40, 0},
    {"tail1", "hips", 0, 1.05, 0.60, 0},   {"tail2", "tail1", 0, 0.95, 0.85, 0},
    {".", "tail2", 0, 0.80, 1.10, 0},      {"fl1", "chest", -0.15, 0.90, -0.40, 0},
    {"fl2", "fl1", -0.15, 0.50, -0.36, 0}, {"fl3", "fl2", -0.15, 0.05, -0.42, 0},
    {".", "fl3", -0.15, 0.0, -0.52, 0},    {"fr1", "chest", 0.15, 0.90, -0.40, 0},
    {"fr2", "fr1", 0.15, 0.50, -0.36, 0},  {"fr3", "fr2", 0.15, 0.05, -0.42, 0},
    {".", "fr3", 0.15, 0.0, -0.52, 0},     {"hl1", "hips", -0.15, 0.90, 0.50, 0},
    {"hl2", "hl1", -0.15, 0.50, 0.40, 0},  {"hl3", "hl2", -0.15, 0.05, 0.52, 0},
    {".", "hl3", -0.15, 0.0, 0.44, 0},     {"hr1", "hips", 0.15, 0.90, 0.50, 0},
    {"hr2", "hr1", 0.15, 0.50, 0.40, 0},   {"hr3", "hr2", 0.15, 0.05, 0.52, 0},
    {".", "hr3", 0.15, 0.0, 0.44, 0},
};

static void test_trunk_from_rear(void **state)
{
    (void)state;
    rf_skeleton *s = build_axes(mid_rooted, SB_COUNT(mid_rooted));
    rf_skeleton *t = build_axes(sb_quadruped, SB_COUNT(sb_quadruped));
    s->forward = t->forward = rf_v3(0, 0, -1);
    rf_ms_options o = {.forelegs_arms = true, .girdle_neck = true};
    rf_mapping *m = match1(t, s, &o);
    assert_driver(m, t, s, "pelvis", "hips");
    assert_driver(m, t, s, "hl1", "hl1");
    assert_driver(m, t, s, "spine2", "front");
    rf_mapping_free(m);
    /* --explain says why */
    char *text = explained(t, s, &o);
    assert_non_null(strstr(text, "pelvis (center spine) <- 0:hips"));
    assert_non_null(strstr(text, "lying behind where the source's reverse spine starts"));
    free(text);
    o.girdle_neck = false;
    m = match1(t, s, &o);
    const rf_skeleton *src[1] = {s};
    const char *got = driver(m, t, src, "pelvis", NULL);
    assert_true(got == NULL || strcmp(got, "hips") != 0);
    rf_mapping_free(m);
    rf_skeleton_free(s);
    rf_skeleton_free(t);
}

/* A trunk rooted at the front, as the general rigger roots the Fox: the root at the shoulders
 * (by the source's neck pivot, as the Fox's lies 0.034 of the longest edge from its artist's
 * b_Neck_04) carrying the forelegs and the head, a reverse spine back to the hips carrying the tail
 * and hind legs, against sb_quadruped rooted at its pelvis. Under girdle=neck the root takes the
 * source's chest and the hips its pelvis (by default, and without the rule, the root takes the
 * source's pelvis, the alignment's first joint). */
static const sb_joint front_rooted[] = {
    {"root", NULL, 0, 1.05, -0.50, 0},     {"mid", "root", 0, 1.05, 0.05, 0},
    {"hips", "mid", 0, 1.00, 0.50, 0},     {"neck", "root", 0, 1.20, -0.60, 0},
    {"head", "neck", 0, 1.35, -0.75, 0},   {".", "head", 0, 1.30, -0.95, 0},
    {"tail1", "hips", 0, 1.05, 0.60, 0},   {"tail2", "tail1", 0, 0.95, 0.85, 0},
    {".", "tail2", 0, 0.80, 1.10, 0},      {"fl1", "root", -0.15, 0.90, -0.40, 0},
    {"fl2", "fl1", -0.15, 0.50, -0.36, 0}, {"fl3", "fl2", -0.15, 0.05, -0.42, 0},
    {".", "fl3", -0.15, 0.0, -0.52, 0},    {"fr1", "root", 0.15, 0.90, -0.40, 0},
    {"fr2", "fr1", 0.15, 0.50, -0.36, 0},  {"fr3", "fr2", 0.15, 0.05, -0.42, 0},
    {".", "fr3", 0.15, 0.0, -0.52, 0},     {"hl1", "hips", -0.15, 0.90, 0.50, 0},
    {"hl2", "hl1", -0.15, 0.50, 0.40, 0},  {"hl3", "hl2", -0.15, 0.05, 0.52, 0},
    {".", "hl3", -0.15, 0.0, 0.44, 0},     {"hr1", "hips", 0.15, 0.90, 0.50, 0},
    {"hr2", "hr1", 0.15, 0.50, 0.40, 0},   {"hr3", "hr2", 0.15, 0.05, 0.52, 0},
    {".", "hr3", 0.15, 0.0, 0.44, 0},
};

static void test_trunk_from_front(void **state)
{
    (void)state;
    rf_skeleton *s = build_axes(sb_quadruped, SB_COUNT(sb_quadruped));
    rf_skeleton *t = build_axes(front_rooted, SB_COUNT(front_rooted));
    s->forward = t->forward = rf_v3(0, 0, -1);
    rf_ms_options o = {.forelegs_arms = true, .girdle_neck = true};
    rf_mapping *m = match1(t, s, &o);
    assert_driver(m, t, s, "root", "chest");
    assert_driver(m, t, s, "hips", "pelvis");
    assert_driver(m, t, s, "hl1", "hl1");
    rf_mapping_free(m);
    o.girdle_neck = false;
    m = match1(t, s, &o);
    const rf_skeleton *src[1] = {s};
    const char *got = driver(m, t, src, "root", NULL);
    assert_true(got == NULL || strcmp(got, "chest") != 0);
    rf_mapping_free(m);
    rf_skeleton_free(s);
    rf_skeleton_free(t);
}

static void test_one_bone_leg(void **state)
{
    (void)state;
    static const char *const first[] = {"fl1", "fr1", "hl1", "hr1"};
    sb_joint a[SB_COUNT(sb_quadruped)], c[SB_COUNT(sb_quadruped) + 2];
    size_t na = 0, nc = 0;
    for (size_t i = 0; i < SB_COUNT(sb_quadruped); i++) {
        sb_joint j = sb_quadruped[i];
        int bone = leg_bone(j.name), under = leg_bone(j.parent);
        /* the low-poly rig: each leg's first joint with the foot's tip as its end site */
        if (bone == 4)
            a[na++] = (sb_joint){
                ".", first[(j.name[0] == 'h') * 2 + (j.name[1] == 'r')], j.x, 0.0, j.z, 0};
        else if (bone <= 1 && !(j.name[0] == '.' && under > 0))
            a[na++] = j;
    }
    for (size_t i = 0; i < SB_COUNT(sb_quadruped); i++) {
        sb_joint j = sb_quadruped[i];
        /* the hind legs hang from a short offset beside the pelvis and lose their toe bone */
        if (strcmp(j.name, "hl1") == 0 || strcmp(j.name, "hr1") == 0) {
            bool l = j.name[1] == 'l';
            c[nc++] = (sb_joint){l ? "hl0" : "hr0", "pelvis", l ? -0.08 : 0.08, 0.98, 0.50, 0};
            j.parent = l ? "hl0" : "hr0";
        }
        if (strcmp(j.name, "hl4") == 0 || strcmp(j.name, "hr4") == 0)
            j.name = ".";
        if (strcmp(j.parent ? j.parent : "", "hl4") == 0 ||
            strcmp(j.parent ? j.parent : "", "hr4") == 0)
            continue;
        c[nc++] = j;
    }
    rf_skeleton *s = sb_build(a, na), *t = sb_build(c, nc);
    rf_mapping *m = match1(t, s, NULL);
    assert_driver(m, t, s, "hl0", "hl1");
    assert_driver(m, t, s, "hr0", "hr1");
    assert_driver(m, t, s, "hl1", NULL);
    assert_driver(m, t, s, "hl2", NULL);
    assert_driver(m, t, s, "fl1", "fl1");
    assert_driver(m, t, s, "fr2", NULL);
    rf_mapping_free(m);
    rf_skeleton_free(s);
    rf_skeleton_free(t);
}

/* Similar types map only when the threshold lets them: a target's thumb onto a source without
 * hands (the main finger goes with the arm: the source arm is too short to drive it). */
static void test_threshold_and_similar(void **state)
{
    (void)state;
    const sb_joint plain[] = {
        {"hips", NULL, 0, 1, 0, 0},
        {"chest", "hips", 0, 1.4, 0, 0},
        {"head", "chest", 0, 1.6, 0, 0},
        {".", "head", 0, 1.8, 0, 0},
        {"l_arm", "chest", 0.15, 1.5, 0, 0},
        {"l_fore", "l_arm", 0.45, 1.5, 0, 0},
        {".", "l_fore", 0.75, 1.5, 0, 0},
        {"r_arm", "chest", -0.15, 1.5, 0, 0},
        {"r_fore", "r_arm", -0.45, 1.5, 0, 0},
        {".", "r_fore", -0.75, 1.5, 0, 0},
        {"l_leg", "hips", 0.1, 0.95, 0, 0},
        {"l_shin", "l_leg", 0.1, 0.5, 0.05, 0},
        {".", "l_shin", 0.1, 0.0, 0.0, 0},
        {"r_leg", "hips", -0.1, 0.95, 0, 0},
        {"r_shin", "r_leg", -0.1, 0.5, 0.05, 0},
        {".", "r_shin", -0.1, 0.0, 0.0, 0},
    };
    rf_skeleton *s = sb_build(plain, SB_COUNT(plain));
    rf_skeleton *t = biped_facing(0);
    rf_mapping *m = match1(t, s, NULL);
    assert_driver(m, t, s, "l_finger", NULL);
    assert_driver(m, t, s, "l_forearm", "l_fore");
    rf_mapping_free(m);
    rf_ms_options o = {0};
    o.threshold_given = true, o.threshold = 0;
    m = match1(t, s, &o);
    const rf_skeleton *src[1] = {s};
    assert_non_null(driver(m, t, src, "l_thumb", NULL));
    assert_true(metric(m, t, "l_thumb", "similar_type") > 0);
    assert_true(metric(m, t, "l_thumb", "same_type") == 0);
    rf_mapping_free(m);
    o.threshold = 1e5; /* nothing reaches it */
    m = match1(t, s, &o);
    for (uint32_t j = 0; j < t->joint_count; j++)
        assert_int_equal(m->entries[j].input_count, 0);
    rf_mapping_free(m);
    rf_skeleton_free(s);
    rf_skeleton_free(t);
}

/* More target bones than source bones: duplicates when asked to keep them, none otherwise. */
static void test_duplicates(void **state)
{
    (void)state;
    rf_skeleton *s = biped_facing(0);
    sb_joint js[SB_COUNT(sb_biped) + 1];
    size_t n = 0;
    for (size_t i = 0; i < SB_COUNT(sb_biped); i++) { /* a second forearm bone on each arm */
        js[n] = sb_biped[i];
        if (strcmp(js[n].name, "l_hand") == 0)
            js[n].parent = "l_forearm2";
        n++;
        if (strcmp(sb_biped[i].name, "l_forearm") == 0)
            js[n++] = (sb_joint){"l_forearm2", "l_forearm", 0.59, 1.50, -0.03, 0};
    }
    rf_skeleton *t = sb_build(js, n);
    rf_mapping *m = match1(t, s, NULL);
    int32_t a = sb_find(t, "l_forearm"), b = sb_find(t, "l_forearm2");
    bool same = m->entries[a].input_count && m->entries[b].input_count &&
                m->entries[a].inputs[0].joint == m->entries[b].inputs[0].joint;
    assert_false(same);
    rf_mapping_free(m);
    rf_ms_options o = {0};
    o.keep_duplicates = true;
    m = match1(t, s, &o);
    same = m->entries[a].input_count && m->entries[b].input_count &&
           m->entries[a].inputs[0].joint == m->entries[b].inputs[0].joint;
    assert_true(same);
    rf_mapping_free(m);
    rf_skeleton_free(s);
    rf_skeleton_free(t);
}

/* Several sources: continuity keeps a section with one source; the preference picks which;
 * a disabled source is left out; blending takes one input from every source. */
static void test_several_sources(void **state)
{
    (void)state;
    rf_skeleton *a = biped_facing(0), *b = biped_facing(180), *c = biped_facing(90);
    rf_skeleton *t = biped_facing(30);
    const rf_skeleton *src[3] = {a, b, c};
    char err[256];
    rf_mapping *m = rf_ms_match(t, src, 3, NULL, NULL, err, sizeof err);
    for (uint32_t j = 0; j < t->joint_count; j++) {
        assert_int_equal(m->entries[j].input_count, 1);
        assert_string_equal(
            src[m->entries[j].inputs[0].source]->joints[m->entries[j].inputs[0].joint].name,
            t->joints[j].name);
    }
    rf_mapping_free(m);

    rf_ms_weights w;
    rf_ms_options o = {0};
    assert_true(rf_ms_weight_set("prefer-2", &w, &o.preferred_source));
    o.weights = &w;
    m = rf_ms_match(t, src, 3, &o, NULL, err, sizeof err);
    for (uint32_t j = 0; j < t->joint_count; j++)
        assert_int_equal(m->entries[j].inputs[0].source, 2);
    assert_true(metric(m, t, "head", "preference") == 10);
    rf_mapping_free(m);

    uint8_t disabled[3] = {1, 0, 0};
    o = (rf_ms_options){0};
    o.disabled = disabled;
    m = rf_ms_match(t, src, 3, &o, NULL, err, sizeof err);
    for (uint32_t j = 0; j < t->joint_count; j++)
        assert_int_not_equal(m->entries[j].inputs[0].source, 0);
    rf_mapping_free(m);

    o = (rf_ms_options){0};
    o.blend = true;
    m = rf_ms_match(t, src, 3, &o, NULL, err, sizeof err);
    for (uint32_t j = 0; j < t->joint_count; j++) {
        assert_int_equal(m->entries[j].input_count, 3);
        for (uint32_t k = 0; k < 3; k++) {
            assert_int_equal(m->entries[j].inputs[k].source, k);
            assert_true(fabsf(m->entries[j].inputs[k].weight - 1.0f / 3) < 1e-6f);
        }
    }
    rf_mapping_free(m);
    uint8_t all[3] = {1, 1, 1};
    o = (rf_ms_options){0};
    o.disabled = all;
    assert_null(rf_ms_match(t, src, 3, &o, NULL, err, sizeof err));
    rf_skeleton_free(a), rf_skeleton_free(b), rf_skeleton_free(c), rf_skeleton_free(t);
}

/* The mirror setting: every second pair of legs takes the other side's source (swap), or keeps
 * its side flagged to play half a cycle away (phase). */
static void test_mirror(void **state)
{
    (void)state;
    rf_skeleton *q = sb_build(sb_quadruped, SB_COUNT(sb_quadruped));
    rf_ms_options o = {0};
    o.mirror = RF_MS_MIRROR_SWAP;
    rf_mapping *m = match1(q, q, &o);
    assert_driver(m, q, q, "fl2", "fl2"); /* front pair kept */
    assert_driver(m, q, q, "hl2", "hr2"); /* hind pair swapped */
    assert_driver(m, q, q, "hr3", "hl3");
    rf_mapping_free(m);
    o.mirror = RF_MS_MIRROR_PHASE;
    m = match1(q, q, &o);
    assert_driver(m, q, q, "hl2", "hl2");
    assert_true(m->entries[sb_find(q, "hl2")].inputs[0].flags & RF_MAP_MIRROR);
    assert_false(m->entries[sb_find(q, "fl2")].inputs[0].flags & RF_MAP_MIRROR);
    rf_mapping_free(m);
    rf_skeleton_free(q);
}

/* A knee bending forward driving one bending backward is flagged reversed (thesis, chapter 6). */
static void test_reverse(void **state)
{
    (void)state;
    sb_joint bent[SB_COUNT(sb_biped)];
    memcpy(bent, sb_biped, sizeof bent);
    for (size_t i = 0; i < SB_COUNT(sb_biped); i++)
        if (strcmp(bent[i].name, "l_shin") == 0 || strcmp(bent[i].name, "r_shin") == 0)
            bent[i].z = 0.12; /* knees well forward */
    rf_skeleton *s = sb_build(bent, SB_COUNT(bent));
    for (size_t i = 0; i < SB_COUNT(sb_biped); i++)
        if (strcmp(bent[i].name, "l_shin") == 0 || strcmp(bent[i].name, "r_shin") == 0)
            bent[i].z = -0.12; /* a bird's backward knee */
    rf_skeleton *t = sb_build(bent, SB_COUNT(bent));
    rf_mapping *m = match1(t, s, NULL);
    assert_driver(m, t, s, "l_shin", "l_shin");
    assert_true(m->entries[sb_find(t, "l_shin")].inputs[0].flags & RF_MAP_REVERSE);
    assert_false(m->entries[sb_find(t, "l_arm")].inputs[0].flags & RF_MAP_REVERSE);
    rf_mapping_free(m);
    rf_ms_options o = {0};
    o.no_reverse = true;
    m = match1(t, s, &o);
    assert_false(m->entries[sb_find(t, "l_shin")].inputs[0].flags & RF_MAP_REVERSE);
    rf_mapping_free(m);
    rf_skeleton_free(s);
    rf_skeleton_free(t);
}

static void test_explain(void **state)
{
    (void)state;
    rf_skeleton *s = biped_facing(0), *t = biped_facing(180);
    const rf_skeleton *src[1] = {s};
    rf_ms_explain e = {0};
    char err[256], *text = NULL;
    size_t size = 0;
    rf_mapping *m = rf_ms_match(t, src, 1, NULL, &e, err, sizeof err);
    assert_non_null(e.target);
    assert_int_equal(e.joint_count, t->joint_count);
    for (uint32_t j = 0; j < e.joint_count; j++) {
        assert_true(e.top_count[j] >= 1 && e.top_count[j] <= 3);
        for (uint32_t k = 1; k < e.top_count[j]; k++)
            assert_true(e.top[j * 3 + k - 1].total >= e.top[j * 3 + k].total);
    }
    FILE *out = open_memstream(&text, &size);
    rf_ms_explain_print(&e, m, t, src, out);
    fclose(out);
    assert_non_null(strstr(text, "l_forearm (left arm) <- 0:l_forearm"));
    assert_non_null(strstr(text, "same_type=50"));
    assert_non_null(strstr(text, "sections:"));
    free(text);
    rf_ms_explain_clear(&e);
    rf_mapping_free(m);
    rf_skeleton_free(s);
    rf_skeleton_free(t);
}

static void test_degenerate(void **state)
{
    (void)state;
    char err[256];
    rf_skeleton *one = rf_skeleton_new(1), *none = rf_skeleton_new(0), *s = biped_facing(0);
    const rf_skeleton *src[2] = {s, NULL};
    assert_null(rf_ms_match(s, src, 0, NULL, NULL, err, sizeof err));
    assert_null(rf_ms_match(NULL, src, 1, NULL, NULL, err, sizeof err));
    assert_null(rf_ms_match(s, src, 2, NULL, NULL, err, sizeof err));
    rf_mapping *m = rf_ms_match(none, src, 1, NULL, NULL, err, sizeof err);
    assert_non_null(m);
    assert_int_equal(m->target_joint_count, 0);
    rf_mapping_free(m);
    const rf_skeleton *tiny[1] = {one};
    m = rf_ms_match(s, tiny, 1, NULL, NULL, err, sizeof err);
    assert_non_null(m);
    rf_mapping_free(m);
    m = rf_ms_match(one, src, 1, NULL, NULL, err, sizeof err);
    assert_non_null(m);
    rf_mapping_free(m);
    rf_ms_options o = {0};
    o.thesis = true;
    m = rf_ms_match(s, src, 1, &o, NULL, err, sizeof err);
    assert_non_null(m);
    assert_int_equal(m->entries[sb_find(s, "l_forearm")].inputs[0].joint,
                     (uint32_t)sb_find(s, "l_forearm"));
    rf_mapping_free(m);
    rf_skeleton_free(one), rf_skeleton_free(none), rf_skeleton_free(s);
}

/* Per-bone prices for leaving bones out (worked by hand): target bones a, b against source x,
 * a-x costs 0.3, b-x 0.2. At 0.4 a bone, leaving a out and matching b (0.6) beats the reverse
 * (0.7); when b costs 0.1 to leave out, matching a (0.4) wins. NULL prices are the flat ones. */
static void test_align_priced(void **state)
{
    (void)state;
    const double cost[2] = {0.3, 0.2};
    int32_t match[2];
    assert_true(fabs(rf_ms_align(cost, 2, 1, 0.4, match) - 0.6) < 1e-12);
    assert_int_equal(match[0], -1);
    assert_int_equal(match[1], 0);
    assert_true(fabs(rf_ms_align_priced(cost, 2, 1, 0.4, NULL, NULL, match) - 0.6) < 1e-12);
    assert_int_equal(match[1], 0);
    const double skip_t[2] = {0.4, 0.1}, skip_s[1] = {0.4};
    assert_true(fabs(rf_ms_align_priced(cost, 2, 1, 0.4, skip_t, skip_s, match) - 0.4) < 1e-12);
    assert_int_equal(match[0], 0);
    assert_int_equal(match[1], -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_weight_sets),
        cmocka_unit_test(test_assign_thesis_tables),
        cmocka_unit_test(test_assign_brute_force),
        cmocka_unit_test(test_align_priced),
        cmocka_unit_test(test_align_refuses_bad_skip),
        cmocka_unit_test(test_identity_and_metrics),
        cmocka_unit_test(test_orientation_falloff),
        cmocka_unit_test(test_facing),
        cmocka_unit_test(test_biped_onto_quadruped),
        cmocka_unit_test(test_gait),
        cmocka_unit_test(test_girdle_neck),
        cmocka_unit_test(test_headless_target),
        cmocka_unit_test(test_skinless_links),
        cmocka_unit_test(test_spine_before_girdle),
        cmocka_unit_test(test_skull_before_snout),
        cmocka_unit_test(test_one_bone_leg),
        cmocka_unit_test(test_legs_from_the_knee),
        cmocka_unit_test(test_trunk_from_rear),
        cmocka_unit_test(test_trunk_from_front),
        cmocka_unit_test(test_threshold_and_similar),
        cmocka_unit_test(test_duplicates),
        cmocka_unit_test(test_several_sources),
        cmocka_unit_test(test_mirror),
        cmocka_unit_test(test_reverse),
        cmocka_unit_test(test_explain),
        cmocka_unit_test(test_degenerate),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
