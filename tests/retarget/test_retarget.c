/* Retargeting on hand-built skeletons whose expected results are worked out by hand or follow
 * from an invariant: rest-pose alignment (T-pose onto A-pose), chains of different length, delay,
 * reverse, weights, mirror, root scale and ground, resampling, frame range, identity, a
 * degenerate source rest, the measures, and the contact pass through the two-bone solver. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>
#include <jansson.h>

#include "retarget.h"
#include "rt-internal.h"
#include "rt-fixtures.h"
#include "twobone.h"

#define X rf_v3(1, 0, 0)
#define Y rf_v3(0, 1, 0)
#define Z rf_v3(0, 0, 1)

/* ---- helpers ---- */

typedef struct run {
    rf_retarget *rt;
    rf_animation *out;
} run;

static run do_run(const rf_skeleton *src, const rf_animation *clip, const rf_skeleton *tgt,
                  const rf_mapping *m, const rf_retarget_options *o)
{
    char err[256] = "";
    rf_rt_source s = {src, clip};
    run r = {rf_retarget_new(&s, 1, tgt, m, o, err, sizeof err), NULL};
    if (!r.rt)
        print_message("plan: %s\n", err);
    assert_non_null(r.rt);
    r.out = rf_retarget_clip(r.rt, NULL, NULL, err, sizeof err);
    if (!r.out)
        print_message("clip: %s\n", err);
    assert_non_null(r.out);
    return r;
}

static void run_free(run *r)
{
    rf_animation_free(r->out);
    rf_retarget_free(r->rt);
}

static rf_retarget_options opts(void)
{
    rf_retarget_options o;
    rf_retarget_options_default(&o);
    return o;
}

static rf_quat local_rot(const rf_animation *a, uint32_t f, uint32_t j)
{
    return rf_quat_normalize(rf_animation_rotation(a, f, j));
}

/* Angle in degrees between two rotations. */
static double rot_diff(rf_quat a, rf_quat b)
{
    return rf_quat_angle(a, b) / DEG;
}

/* ---- skeletons ---- */

/* A torso with its arms held out sideways (a T-pose) and a head: chest, left upper arm,
 * forearm, hand (joints 1-3, along +X), the right arm (4-6) and the head (7). */
static rf_skeleton *arm_tpose(void)
{
    rf_skeleton *s = rf_skeleton_new(8);
    fx_joint(s, 0, "chest", -1, rf_v3(0, 0, 0), rf_quat_identity());
    fx_joint(s, 1, "upper", 0, rf_v3(0.5, 0, 0), rf_quat_identity());
    fx_joint(s, 2, "lower", 1, rf_v3(1, 0, 0), rf_quat_identity());
    fx_joint(s, 3, "hand", 2, rf_v3(1, 0, 0), rf_quat_identity());
    fx_end_site(s, 3, rf_v3(0.3, 0, 0));
    fx_joint(s, 4, "r_upper", 0, rf_v3(-0.5, 0, 0), rf_quat_identity());
    fx_joint(s, 5, "r_lower", 4, rf_v3(-1, 0, 0), rf_quat_identity());
    fx_joint(s, 6, "r_hand", 5, rf_v3(-1, 0, 0), rf_quat_identity());
    fx_end_site(s, 6, rf_v3(-0.3, 0, 0));
    fx_joint(s, 7, "head", 0, rf_v3(0, 0.6, 0), rf_quat_identity());
    fx_end_site(s, 7, rf_v3(0, 0.3, 0));
    return s;
}

/* The same torso shaped differently with both arms hanging 45 degrees down (an A-pose), the
 * bones along local +X (left) and -X (right). */
static rf_skeleton *arm_apose(void)
{
    rf_skeleton *s = rf_skeleton_new(8);
    fx_joint(s, 0, "c", -1, rf_v3(0, 0, 0), rf_quat_identity());
    fx_joint(s, 1, "u", 0, rf_v3(0.4, 0, 0), fx_rot(Z, -45));
    fx_joint(s, 2, "l", 1, rf_v3(0.8, 0, 0), rf_quat_identity());
    fx_joint(s, 3, "h", 2, rf_v3(0.7, 0, 0), rf_quat_identity());
    fx_end_site(s, 3, rf_v3(0.2, 0, 0));
    fx_joint(s, 4, "ru", 0, rf_v3(-0.4, 0, 0), fx_rot(Z, 45));
    fx_joint(s, 5, "rl", 4, rf_v3(-0.8, 0, 0), rf_quat_identity());
    fx_joint(s, 6, "rh", 5, rf_v3(-0.7, 0, 0), rf_quat_identity());
    fx_end_site(s, 6, rf_v3(-0.2, 0, 0));
    fx_joint(s, 7, "hd", 0, rf_v3(0, 0.5, 0), rf_quat_identity());
    fx_end_site(s, 7, rf_v3(0, 0.25, 0));
    return s;
}

/* Three frames: rest, then two poses of the upper arm and forearm. */
static rf_animation *arm_clip(const rf_skeleton *s)
{
    rf_animation *a = fx_rest_clip(s, 3, 10);
    rf_animation_set_rotation(a, 1, 1, fx_rot(Z, 30));
    rf_animation_set_rotation(a, 1, 2, fx_rot(Y, 40));
    rf_animation_set_rotation(a, 2, 1, rf_quat_mul(fx_rot(X, 50), fx_rot(Z, -20)));
    rf_animation_set_rotation(a, 2, 2, fx_rot(Z, 60));
    rf_animation_set_rotation(a, 2, 3, fx_rot(Y, -30));
    return a;
}

/* World direction from joint j to joint c (or along j's end site when c == j). */
static rf_vec3 bone_dir(const rf_skeleton *s, const rf_xform *w, uint32_t j, uint32_t c)
{
    if (c == j)
        return rf_v3_sub(rf_xform_point(w[j], s->joints[j].end_site), w[j].t);
    return rf_v3_sub(w[c].t, w[j].t);
}

/* ---- rest-pose alignment ---- */

static void tpose_drives_apose(void **state)
{
    (void)state;
    rf_skeleton *src = arm_tpose(), *tgt = arm_apose();
    rf_animation *clip = arm_clip(src);
    rf_mapping *m = fx_mapping(8, 1);
    fx_map_same(m, 8);
    rf_retarget_options o = opts();
    run r = do_run(src, clip, tgt, m, &o);
    rf_xform ws[8], wt[8];
    for (uint32_t f = 0; f < 3; f++) {
        fx_world(src, clip, f, ws);
        fx_world(tgt, r.out, f, wt);
        for (uint32_t j = 1; j < 8; j++) {
            uint32_t c = j == 3 || j >= 6 ? j : j + 1;
            assert_true(fx_angle(bone_dir(tgt, wt, j, c), bone_dir(src, ws, j, c)) < 1e-3);
        }
    }
    /* Frame 0 is the source's rest: the A-pose arm must be raised to the T-pose. */
    fx_world(tgt, r.out, 0, wt);
    assert_true(fx_angle(rf_v3_sub(wt[2].t, wt[1].t), X) < 1e-3);
    /* Frame 1 by hand: the upper arm turned 30 degrees up about Z. */
    fx_world(tgt, r.out, 1, wt);
    assert_true(fx_angle(rf_v3_sub(wt[2].t, wt[1].t), rf_v3(cos(30 * DEG), sin(30 * DEG), 0)) <
                1e-3);
    run_free(&r);
    rf_mapping_free(m), rf_animation_free(clip), rf_skeleton_free(src), rf_skeleton_free(tgt);
}

/* ---- chains of different length ---- */

/* A vertical chain root-a-b-c (c with a tip), and a target with unmapped joints between. */
static rf_skeleton *chain3(void)
{
    rf_skeleton *s = rf_skeleton_new(4);
    fx_joint(s, 0, "root", -1, rf_v3(0, 0, 0), rf_quat_identity());
    fx_joint(s, 1, "a", 0, rf_v3(0, 1, 0), rf_quat_identity());
    fx_joint(s, 2, "b", 1, rf_v3(0, 1, 0), rf_quat_identity());
    fx_joint(s, 3, "c", 2, rf_v3(0, 1, 0), rf_quat_identity());
    fx_end_site(s, 3, rf_v3(0, 0.5, 0));
    return s;
}

static rf_skeleton *chain5(void)
{
    rf_skeleton *s = rf_skeleton_new(6);
    fx_joint(s, 0, "root", -1, rf_v3(0, 0, 0), rf_quat_identity());
    fx_joint(s, 1, "a", 0, rf_v3(0, 1, 0), rf_quat_identity());
    fx_joint(s, 2, "u1", 1, rf_v3(0, 0.5, 0), rf_quat_identity());
    fx_joint(s, 3, "b", 2, rf_v3(0, 0.5, 0), rf_quat_identity());
    fx_joint(s, 4, "u2", 3, rf_v3(0, 0.6, 0), rf_quat_identity());
    fx_joint(s, 5, "c", 4, rf_v3(0, 0.6, 0), rf_quat_identity());
    fx_end_site(s, 5, rf_v3(0, 0.5, 0));
    return s;
}

static void chain3_drives_chain5(void **state)
{
    (void)state;
    rf_skeleton *src = chain3(), *tgt = chain5();
    rf_animation *clip = fx_rest_clip(src, 2, 10);
    rf_animation_set_rotation(clip, 1, 1, fx_rot(Z, 30));
    rf_animation_set_rotation(clip, 1, 2, fx_rot(X, 45));
    rf_mapping *m = fx_mapping(6, 1);
    fx_map(m, 0, 0, 0, 1, 0, 0), fx_map(m, 1, 0, 1, 1, 0, 0);
    fx_map(m, 3, 0, 2, 1, 0, 0), fx_map(m, 5, 0, 3, 1, 0, 0);
    rf_retarget_options o = opts();
    run r = do_run(src, clip, tgt, m, &o);
    rf_xform ws[4], wt[6];
    fx_world(src, clip, 1, ws);
    fx_world(tgt, r.out, 1, wt);
    /* The mapped joints land where the source's segments point. */
    assert_true(fx_angle(rf_v3_sub(wt[3].t, wt[1].t), rf_v3_sub(ws[2].t, ws[1].t)) < 1e-4);
    assert_true(fx_angle(rf_v3_sub(wt[5].t, wt[3].t), rf_v3_sub(ws[3].t, ws[2].t)) < 1e-4);
    /* By hand: the source segment turns 30 degrees about Z. a and u1 (two bones of 0.5) share
     * the chain's rotation t equally: the bones point at t/2 and t, the chord at 3t/4 = 30, so
     * t = 40 and each joint turns 20 degrees... */
    double a_local = rot_diff(local_rot(r.out, 1, 1), rf_quat_identity());
    double u1_local = rot_diff(local_rot(r.out, 1, 2), rf_quat_identity());
    assert_true(fabs(a_local - 20) < 1e-3);
    assert_true(fabs(u1_local - 20) < 1e-3);
    /* ... and a leaf without a mapping keeps its rest. */
    run_free(&r);
    rf_mapping_free(m), rf_animation_free(clip), rf_skeleton_free(src), rf_skeleton_free(tgt);
}

static void chain5_drives_chain3(void **state)
{
    (void)state;
    rf_skeleton *src = chain5(), *tgt = chain3();
    rf_animation *clip = fx_rest_clip(src, 2, 10);
    rf_animation_set_rotation(clip, 1, 2, fx_rot(Z, 40));  /* the unmapped u1 bends */
    rf_animation_set_rotation(clip, 1, 4, fx_rot(X, -25)); /* and u2 */
    rf_mapping *m = fx_mapping(4, 1);
    fx_map(m, 0, 0, 0, 1, 0, 0), fx_map(m, 1, 0, 1, 1, 0, 0);
    fx_map(m, 2, 0, 3, 1, 0, 0), fx_map(m, 3, 0, 5, 1, 0, 0);
    rf_retarget_options o = opts();
    run r = do_run(src, clip, tgt, m, &o);
    rf_xform ws[6], wt[4];
    fx_world(src, clip, 1, ws);
    fx_world(tgt, r.out, 1, wt);
    assert_true(fx_angle(rf_v3_sub(wt[2].t, wt[1].t), rf_v3_sub(ws[3].t, ws[1].t)) < 1e-4);
    assert_true(fx_angle(rf_v3_sub(wt[3].t, wt[2].t), rf_v3_sub(ws[5].t, ws[3].t)) < 1e-4);
    run_free(&r);
    rf_mapping_free(m), rf_animation_free(clip), rf_skeleton_free(src), rf_skeleton_free(tgt);
}

static void unmapped_leaf_keeps_rest(void **state)
{
    (void)state;
    rf_skeleton *src = arm_tpose(), *tgt = arm_apose();
    rf_animation *clip = arm_clip(src);
    rf_mapping *m = fx_mapping(8, 1);
    fx_map_same(m, 3); /* the hand is left unmapped */
    rf_retarget_options o = opts();
    run r = do_run(src, clip, tgt, m, &o);
    for (uint32_t f = 0; f < 3; f++)
        assert_true(rot_diff(local_rot(r.out, f, 3), tgt->joints[3].rest.r) < 1e-4);
    run_free(&r);
    rf_mapping_free(m), rf_animation_free(clip), rf_skeleton_free(src), rf_skeleton_free(tgt);
}

/* ---- mapping options ---- */

static rf_animation *swing_clip(const rf_skeleton *s, uint32_t frames)
{
    rf_animation *a = fx_rest_clip(s, frames, 10);
    for (uint32_t f = 0; f < frames; f++) {
        rf_animation_set_rotation(a, f, 1, fx_rot(Z, 5.0 * f));
        rf_animation_set_rotation(a, f, 2, fx_rot(Y, 3.0 * f));
    }
    return a;
}

static void delay_equals_shift(void **state)
{
    (void)state;
    rf_skeleton *src = arm_tpose(), *tgt = arm_apose();
    rf_animation *clip = swing_clip(src, 20);
    rf_mapping *plain = fx_mapping(8, 1), *late = fx_mapping(8, 1);
    fx_map_same(plain, 8);
    for (uint32_t j = 0; j < 8; j++)
        fx_map(late, j, 0, j, 1, 0.3f, 0); /* 3 frames at 10 fps */
    rf_retarget_options o = opts();
    run a = do_run(src, clip, tgt, plain, &o), b = do_run(src, clip, tgt, late, &o);
    for (uint32_t f = 0; f < 20; f++)
        for (uint32_t j = 0; j < 8; j++)
            assert_true(rot_diff(local_rot(b.out, f, j), local_rot(a.out, f < 3 ? 0 : f - 3, j)) <
                        1e-3);
    run_free(&a), run_free(&b);
    rf_mapping_free(plain), rf_mapping_free(late), rf_animation_free(clip);
    rf_skeleton_free(src), rf_skeleton_free(tgt);
}

static void reverse_inverts(void **state)
{
    (void)state;
    rf_skeleton *src = arm_tpose(), *tgt = arm_tpose();
    rf_animation *clip = fx_rest_clip(src, 2, 10);
    rf_animation_set_rotation(clip, 1, 1, fx_rot(Z, 30));
    rf_mapping *m = fx_mapping(8, 1);
    fx_map(m, 0, 0, 0, 1, 0, 0);
    fx_map(m, 1, 0, 1, 1, 0, RF_MAP_REVERSE);
    rf_retarget_options o = opts();
    run r = do_run(src, clip, tgt, m, &o);
    /* By hand: the upper arm turns -30 degrees about Z (the root does not move). */
    assert_true(rot_diff(local_rot(r.out, 1, 1), fx_rot(Z, -30)) < 1e-3);
    run_free(&r);
    rf_mapping_free(m), rf_animation_free(clip), rf_skeleton_free(src), rf_skeleton_free(tgt);
}

static void weights_blend_two_sources(void **state)
{
    (void)state;
    rf_skeleton *sa = arm_tpose(), *sb = arm_tpose(), *tgt = arm_tpose();
    rf_animation *ca = fx_rest_clip(sa, 2, 10), *cb = fx_rest_clip(sb, 2, 10);
    rf_quat qa = fx_rot(Z, 40), qb = fx_rot(X, -60);
    rf_animation_set_rotation(ca, 1, 1, qa);
    rf_animation_set_rotation(cb, 1, 1, qb);
    rf_mapping *m = fx_mapping(8, 2);
    fx_map(m, 0, 0, 0, 1, 0, 0);
    fx_map(m, 1, 0, 1, 0.5f, 0, 0);
    fx_map(m, 1, 1, 1, 0.5f, 0, 0);
    fx_map(m, 2, 0, 2, 1, 0, 0), fx_map(m, 3, 0, 3, 1, 0, 0);
    rf_rt_source s[2] = {{sa, ca}, {sb, cb}};
    char err[256];
    rf_retarget_options o = opts();
    rf_retarget *rt = rf_retarget_new(s, 2, tgt, m, &o, err, sizeof err);
    assert_non_null(rt);
    rf_animation *out = rf_retarget_clip(rt, NULL, NULL, err, sizeof err);
    assert_non_null(out);
    assert_true(rot_diff(local_rot(out, 1, 1), rf_quat_slerp(qa, qb, 0.5)) < 1e-3);
    rf_animation_free(out), rf_retarget_free(rt), rf_mapping_free(m);
    rf_animation_free(ca), rf_animation_free(cb);
    rf_skeleton_free(sa), rf_skeleton_free(sb), rf_skeleton_free(tgt);
}

/* ---- root motion ---- */

/* A biped: hips over two legs ending on the floor (y = 0), toes forward (+Z), a spine and head. */
static rf_skeleton *biped(double scale, double thigh, double shin)
{
    rf_skeleton *s = rf_skeleton_new(9);
    double k = scale;
    fx_joint(s, 0, "hips", -1, rf_v3(0, (thigh + shin + 0.05) * k, 0), rf_quat_identity());
    fx_joint(s, 1, "lthigh", 0, rf_v3(0.1 * k, 0, 0), rf_quat_identity());
    fx_joint(s, 2, "lknee", 1, rf_v3(0, -thigh * k, 0), rf_quat_identity());
    fx_joint(s, 3, "lankle", 2, rf_v3(0, -shin * k, 0), rf_quat_identity());
    fx_end_site(s, 3, rf_v3(0, -0.05 * k, 0.15 * k));
    fx_joint(s, 4, "rthigh", 0, rf_v3(-0.1 * k, 0, 0), rf_quat_identity());
    fx_joint(s, 5, "rknee", 4, rf_v3(0, -thigh * k, 0), rf_quat_identity());
    fx_joint(s, 6, "rankle", 5, rf_v3(0, -shin * k, 0), rf_quat_identity());
    fx_end_site(s, 6, rf_v3(0, -0.05 * k, 0.15 * k));
    fx_joint(s, 7, "spine", 0, rf_v3(0, 0.1 * k, 0), rf_quat_identity());
    fx_joint(s, 8, "head", 7, rf_v3(0, 0.5 * k, 0), rf_quat_identity());
    fx_end_site(s, 8, rf_v3(0, 0.2 * k, 0));
    return s;
}

static void root_scaled_by_hip_height(void **state)
{
    (void)state;
    rf_skeleton *src = biped(1, 0.5, 0.45), *tgt = biped(0.5, 0.5, 0.45);
    rf_animation *clip = fx_rest_clip(src, 2, 10);
    rf_animation_set_translation(clip, 1, 0, rf_v3(2, 1.1, 0));
    for (uint32_t j = 0; j < 9; j++)
        clip->channels[j] |= j == 0 ? RF_CHANNEL_TRANSLATION : 0;
    rf_mapping *m = fx_mapping(9, 1);
    fx_map_same(m, 9);
    rf_retarget_options o = opts();
    run r = do_run(src, clip, tgt, m, &o);
    rf_rt_info info;
    rf_retarget_info(r.rt, &info);
    assert_true(fabs(info.root_scale - 0.5) < 1e-6); /* hip heights 1 and 0.5 over the floor */
    /* By hand: 2 forward becomes 1; height 1.1 over the floor at 0 becomes 0.55. */
    rf_vec3 hip = rf_animation_translation(r.out, 1, 0);
    assert_true(rf_v3_dist(hip, rf_v3(1, 0.55, 0)) < 1e-6);
    run_free(&r);
    o.in_place = true;
    r = do_run(src, clip, tgt, m, &o);
    hip = rf_animation_translation(r.out, 1, 0);
    assert_true(rf_v3_dist(hip, rf_v3(0, 0.55, 0)) < 1e-6);
    run_free(&r);
    rf_mapping_free(m), rf_animation_free(clip), rf_skeleton_free(src), rf_skeleton_free(tgt);
}

/* `b` under a new root "base" at the origin (joint 0; b's joints follow, one index on). */
static rf_skeleton *on_base(const rf_skeleton *b)
{
    rf_skeleton *s = rf_skeleton_new(b->joint_count + 1);
    fx_joint(s, 0, "base", -1, rf_v3(0, 0, 0), rf_quat_identity());
    for (uint32_t j = 0; j < b->joint_count; j++) {
        const rf_joint *o = &b->joints[j];
        fx_joint(s, j + 1, o->name, o->parent + 1, o->rest.t, o->rest.r);
        s->joints[j + 1].flags = o->flags, s->joints[j + 1].end_site = o->end_site;
    }
    return s;
}

/* A source root its clip holds still while the hips' own translation walks (the Bandai files'
 * root on the floor), mapped onto the target's root as a matcher may: it drives nothing, and
 * the hips' walk is root motion, scaled by the legs and dropped by in_place. Driven by the still
 * root, the target's root stayed and its hips walked in their own translation, in place too. */
static void still_source_root_drives_nothing(void **state)
{
    (void)state;
    rf_skeleton *b1 = biped(1, 0.5, 0.45), *b2 = biped(0.5, 0.5, 0.45);
    rf_skeleton *src = on_base(b1), *tgt = on_base(b2);
    rf_animation *clip = fx_rest_clip(src, 2, 10);
    rf_animation_set_translation(clip, 1, 1, rf_v3(2, 1.1, 0));
    clip->channels[0] |= RF_CHANNEL_TRANSLATION, clip->channels[1] |= RF_CHANNEL_TRANSLATION;
    rf_mapping *m = fx_mapping(10, 1);
    fx_map_same(m, 10);
    rf_retarget_options o = opts();
    o.in_place = true;
    run r = do_run(src, clip, tgt, m, &o);
    rf_xform w0[10], w1[10];
    fx_world(tgt, r.out, 0, w0);
    fx_world(tgt, r.out, 1, w1);
    /* In place: the hips stay over where they stood, and every joint keeps to its rest's
     * distance from them (nothing left behind). */
    print_message("in place: hips moved (%.4f, %.4f, %.4f)\n", w1[1].t.x - w0[1].t.x,
                  w1[1].t.y - w0[1].t.y, w1[1].t.z - w0[1].t.z);
    assert_true(fabs(w1[1].t.x - w0[1].t.x) < 1e-6 && fabs(w1[1].t.z - w0[1].t.z) < 1e-6);
    run_free(&r);
    /* With root motion: 2 forward at the legs' ratio (hip heights 1 and 0.5) is 1. */
    o.in_place = false;
    r = do_run(src, clip, tgt, m, &o);
    fx_world(tgt, r.out, 0, w0);
    fx_world(tgt, r.out, 1, w1);
    assert_true(fabs(w1[1].t.x - w0[1].t.x - 1) < 1e-6 && fabs(w1[1].t.z - w0[1].t.z) < 1e-6);
    run_free(&r);
    rf_mapping_free(m), rf_animation_free(clip);
    rf_skeleton_free(src), rf_skeleton_free(tgt), rf_skeleton_free(b1), rf_skeleton_free(b2);
}

/* The biped with arms along x from its spine: shoulders, elbows and wrists (15 joints). */
static rf_skeleton *biped_arms(void)
{
    rf_skeleton *b = biped(1, 0.5, 0.45), *s = rf_skeleton_new(15);
    for (uint32_t j = 0; j < 9; j++) {
        const rf_joint *o = &b->joints[j];
        fx_joint(s, j, o->name, o->parent, o->rest.t, o->rest.r);
        s->joints[j].flags = o->flags, s->joints[j].end_site = o->end_site;
    }
    rf_skeleton_free(b);
    static const char *names[2][3] = {{"lshoulder", "lelbow", "lwrist"},
                                      {"rshoulder", "relbow", "rwrist"}};
    for (uint32_t k = 0; k < 2; k++) {
        double x = k ? -1 : 1;
        uint32_t j = 9 + 3 * k;
        fx_joint(s, j, names[k][0], 7, rf_v3(0.1 * x, 0.4, 0), rf_quat_identity());
        fx_joint(s, j + 1, names[k][1], (int32_t)j, rf_v3(0.25 * x, 0, 0), rf_quat_identity());
        fx_joint(s, j + 2, names[k][2], (int32_t)j + 1, rf_v3(0.25 * x, 0, 0), rf_quat_identity());
        fx_end_site(s, j + 2, rf_v3(0.1 * x, 0, 0));
    }
    return s;
}

/* A target whose rest lies on its back (the same body turned a quarter about x, hips a little
 * over the floor) keeps its arms driven: lying, the shoulders stand a body's thickness over
 * the lowest point, but the arms hang from them once the body stands as its source does. */
static void lying_rest_keeps_arms(void **state)
{
    (void)state;
    rf_skeleton *src = biped_arms(), *tgt = biped_arms();
    tgt->joints[0].rest.t = rf_v3(0, 0.2, 0);
    tgt->joints[0].rest.r = fx_rot(X, -90);
    tgt->up = Y;
    rf_animation *clip = fx_rest_clip(src, 2, 10);
    rf_mapping *m = fx_mapping(15, 1);
    fx_map_same(m, 15);
    rf_retarget_options o = opts();
    run r = do_run(src, clip, tgt, m, &o);
    for (uint32_t j = 9; j < 15; j++)
        print_message("%s: %s\n", tgt->joints[j].name,
                      r.rt->tj[j].kind == RF_RT_MAPPED ? "driven" : "held");
    for (uint32_t j = 9; j < 15; j++)
        assert_int_equal(r.rt->tj[j].kind, RF_RT_MAPPED);
    run_free(&r);
    rf_mapping_free(m), rf_animation_free(clip), rf_skeleton_free(src), rf_skeleton_free(tgt);
}

/* biped_arms with its arms' two bones `left` and `right` long each (its shoulders stand 1.5 over
 * its lowest point): wings, when long enough. */
static rf_skeleton *winged(double left, double right)
{
    rf_skeleton *s = biped_arms();
    for (uint32_t k = 0; k < 2; k++) {
        double x = k ? -1 : 1, len = k ? right : left;
        s->joints[10 + 3 * k].rest.t = rf_v3(len * x, 0, 0);
        s->joints[11 + 3 * k].rest.t = rf_v3(len * x, 0, 0);
        s->joints[11 + 3 * k].end_site = rf_v3(0.1 * x, 0, 0);
    }
    return s;
}

/* A limb clear of the floor that reaches more than 1.5 times its shoulder's height (a wing) is
 * held whole: its elbow and wrist keep their rest turns, and the source's arm swings it without
 * its twist, no farther than its reach allows. Wings of 1.45 + 1.45 + 0.1 reach 3.0 from
 * shoulders 1.5 over the floor, twice: their swing is eased into asin(1 / 2) = 30 degrees.
 * The source's left arm swings 80 degrees down and twists 90 degrees about itself; by hand the
 * left wing drops 30 tanh(80 / 30) = 29.71 degrees, and a vector across it along the facing (z)
 * stays where it was (the twist would have turned it onto the up). A pair is held both or
 * neither (greenman's lopsided arms: tests/rig/test_rig_bench_look.sh); a skeleton this small
 * built lopsided is read with no centerline at all. */
/* Wings of len + len + 0.1 from shoulders 1.5 over the floor, under a source whose left upper
 * arm turns by `arm`: the world transforms of frame 1 into w, and whether the left wing's elbow
 * and wrist kept their rest turns (the wing held whole). */
static bool wing_under_arm(double len, rf_quat arm, rf_xform w[15])
{
    rf_skeleton *src = biped_arms(), *tgt = winged(len, len);
    rf_animation *clip = fx_rest_clip(src, 2, 10);
    rf_animation_set_rotation(clip, 1, 9, arm);
    rf_mapping *m = fx_mapping(15, 1);
    fx_map_same(m, 15);
    rf_retarget_options o = opts();
    run r = do_run(src, clip, tgt, m, &o);
    fx_world(tgt, r.out, 1, w);
    bool whole = true;
    for (uint32_t j = 10; j < 12; j++)
        whole = whole && rot_diff(local_rot(r.out, 1, j), tgt->joints[j].rest.r) < 1e-6;
    run_free(&r);
    rf_mapping_free(m), rf_animation_free(clip), rf_skeleton_free(src), rf_skeleton_free(tgt);
    return whole;
}

static void wing_swings_whole(void **state)
{
    (void)state;
    rf_xform w[15];
    bool whole = wing_under_arm(1.45, rf_quat_mul(fx_rot(Z, -80), fx_rot(X, 90)), w);
    rf_vec3 wing = rf_v3_sub(w[11].t, w[9].t);
    double drop = fx_angle(wing, Y) - 90;
    double across = fx_angle(rf_quat_rotate(w[9].r, Z), Z);
    print_message("wing: dropped %.4f degrees, turned about itself %.4f\n", drop, across);
    assert_true(fabs(drop - 30 * tanh(80.0 / 30)) < 1e-3);
    assert_true(across < 1e-3);
    assert_true(whole);
}

/* A wing reaching 1.55 times its shoulder's height is held whole as well (random dragon seed
 * 16's auto-rigged wings reach 1.54 and 1.55): wings of 1.1125 + 1.1125 + 0.1 reach 2.325 from
 * shoulders 1.5 over the floor. By hand its swing under the 80-degree arm is eased into
 * asin(1 / 1.55) = 40.18 degrees: it drops 40.18 tanh(80 / 40.18) = 38.71 degrees, its elbow and
 * wrist at their rest turns. Under a bar of 1.6 it was driven as an arm and dropped the arm's
 * 80 degrees with the elbow turning. */
static void wing_held_from_one_and_a_half(void **state)
{
    (void)state;
    rf_xform w[15];
    bool whole = wing_under_arm(1.1125, fx_rot(Z, -80), w);
    double drop = fx_angle(rf_v3_sub(w[11].t, w[9].t), Y) - 90;
    double limit = asin(1 / 1.55) * 180 / RF_PI;
    print_message("a 1.55-times wing: dropped %.4f degrees (by hand %.4f)\n", drop,
                  limit * tanh(80 / limit));
    assert_true(fabs(drop - limit * tanh(80 / limit)) < 1e-3);
    assert_true(whole);
}

/* An upright body standing on its trunk (a bottom joint at its lowest point, a chest, a head:
 * greenman's build) takes a biped source's lean eased into 10 degrees: the biped balances its
 * leaning trunk over its legs, the trunk on the floor tips over. The biped's hips lean 50
 * degrees forward; the bottom tilts 10 tanh(50 / 10) = 9.9991 degrees (by hand), where it took
 * all 50. A source standing on its trunk too passes its lean as it is. */
static void trunk_standing_body_eases_lean(void **state)
{
    (void)state;
    rf_skeleton *src = biped(1, 0.5, 0.45), *tgt = rf_skeleton_new(3);
    fx_joint(tgt, 0, "bottom", -1, rf_v3(0, 0, 0), rf_quat_identity());
    fx_joint(tgt, 1, "chest", 0, rf_v3(0, 0.8, 0), rf_quat_identity());
    fx_joint(tgt, 2, "head", 1, rf_v3(0, 0.6, 0), rf_quat_identity());
    fx_end_site(tgt, 2, rf_v3(0, 0.3, 0));
    rf_animation *clip = fx_rest_clip(src, 2, 10);
    rf_animation_set_rotation(clip, 1, 0, fx_rot(X, 50));
    rf_mapping *m = fx_mapping(3, 1);
    fx_map(m, 0, 0, 0, 1, 0, 0), fx_map(m, 1, 0, 7, 1, 0, 0), fx_map(m, 2, 0, 8, 1, 0, 0);
    rf_retarget_options o = opts();
    run r = do_run(src, clip, tgt, m, &o);
    rf_xform w[3];
    fx_world(tgt, r.out, 1, w);
    double tilt = fx_angle(rf_v3_sub(w[1].t, w[0].t), Y);
    print_message("trunk on the floor under a 50-degree lean: %.4f degrees\n", tilt);
    assert_true(fabs(tilt - 10 * tanh(5)) < 1e-3);
    run_free(&r);
    /* The chain's own source (a bottom at its lowest point too) passes the lean whole. */
    rf_animation *own = fx_rest_clip(tgt, 2, 10);
    rf_animation_set_rotation(own, 1, 0, fx_rot(X, 50));
    rf_mapping *same = fx_mapping(3, 1);
    fx_map_same(same, 3);
    r = do_run(tgt, own, tgt, same, &o);
    fx_world(tgt, r.out, 1, w);
    assert_true(fabs(fx_angle(rf_v3_sub(w[1].t, w[0].t), Y) - 50) < 1e-3);
    run_free(&r);
    rf_mapping_free(m), rf_mapping_free(same), rf_animation_free(clip), rf_animation_free(own);
    rf_skeleton_free(src), rf_skeleton_free(tgt);
}

/* A target standing on a floor below the origin keeps its feet there. */
static void target_stays_on_its_floor(void **state)
{
    (void)state;
    rf_skeleton *src = biped(1, 0.5, 0.45), *tgt = biped(1, 0.5, 0.45);
    tgt->joints[0].rest.t.y -= 3; /* stands on y = -3 */
    rf_animation *clip = fx_rest_clip(src, 2, 10);
    rf_animation_set_translation(clip, 1, 0, rf_v3(0, 0.9, 0.5)); /* crouches 0.1 */
    rf_mapping *m = fx_mapping(9, 1);
    fx_map_same(m, 9);
    rf_retarget_options o = opts();
    run r = do_run(src, clip, tgt, m, &o);
    assert_true(rf_v3_dist(rf_animation_translation(r.out, 1, 0), rf_v3(0, -2.1, 0.5)) < 1e-6);
    run_free(&r);
    rf_mapping_free(m), rf_animation_free(clip), rf_skeleton_free(src), rf_skeleton_free(tgt);
}

/* The head turned 60 degrees where the target's own clip turns it 10 is held at 10 + the slack,
 * about the same axis; a turn within that range, and the spine (which the own clip never turns,
 * so it says nothing of it), are left as they were. */
static void centerline_turns_kept_in_own_range(void **state)
{
    (void)state;
    rf_skeleton *s = biped(1, 0.5, 0.45);
    rf_animation *clip = fx_rest_clip(s, 3, 10), *own = fx_rest_clip(s, 2, 10);
    rf_animation_set_rotation(clip, 1, 8, fx_rot(X, 60));
    rf_animation_set_rotation(clip, 1, 7, fx_rot(X, 40));
    rf_animation_set_rotation(clip, 2, 8, fx_rot(X, 3));
    rf_animation_set_rotation(own, 1, 8, fx_rot(Z, 10));
    rf_mapping *m = fx_mapping(9, 1);
    fx_map_same(m, 9);
    rf_retarget_options o = opts();
    run r = do_run(s, clip, s, m, &o);
    assert_int_equal(rf_retarget_limit_turns(r.rt, r.out, own), 1);
    assert_true(rot_diff(local_rot(r.out, 1, 8), fx_rot(X, 10 + RF_RT_TURN_SLACK)) < 1e-4);
    assert_true(rot_diff(local_rot(r.out, 2, 8), fx_rot(X, 3)) < 1e-4);
    assert_true(rot_diff(local_rot(r.out, 1, 7), fx_rot(X, 40)) < 1e-4);
    run_free(&r);
    rf_mapping_free(m), rf_animation_free(clip), rf_animation_free(own), rf_skeleton_free(s);
}

/* Turns past the limit in every direction, the long way round included (a quaternion with a
 * negative w: 200 degrees is 160 the other way), are cut back to the limit about their own axis:
 * the same rotations as raising the turn off rest to the power limit / turn (a slerp from
 * identity), checked here against that form. */
static void turns_cut_about_their_own_axis(void **state)
{
    (void)state;
    rf_skeleton *s = biped(1, 0.5, 0.45);
    rf_animation *clip = fx_rest_clip(s, 40, 10), *own = fx_rest_clip(s, 2, 10);
    rf_animation_set_rotation(own, 1, 8, fx_rot(Z, 10));
    rf_mapping *m = fx_mapping(9, 1);
    fx_map_same(m, 9);
    rf_retarget_options o = opts();
    run r = do_run(s, clip, s, m, &o);
    rf_quat rest = s->joints[8].rest.r, want[40];
    double limit = (10 + RF_RT_TURN_SLACK) * DEG;
    srand(3);
    for (uint32_t f = 0; f < 40; f++) {
        rf_vec3 axis = rf_v3(rand() % 201 - 100, rand() % 201 - 100, rand() % 201 - 100 + 0.5);
        rf_quat q = rf_quat_mul(rest, fx_rot(axis, 20 + 320.0 * f / 39)); /* 20 to 340 degrees */
        rf_animation_set_rotation(r.out, f, 8, q);
        q = rf_quat_normalize(rf_animation_rotation(r.out, f, 8)); /* as stored, in floats */
        rf_quat d = rf_quat_mul(rf_quat_conj(rest), q);
        double turn = 2 * acos(fmin(1, fabs(d.w)));
        want[f] = rf_quat_mul(rest, rf_rt_quat_pow(d, limit / turn));
    }
    assert_int_equal(rf_retarget_limit_turns(r.rt, r.out, own), 1);
    for (uint32_t f = 0; f < 40; f++) {
        assert_true(rot_diff(local_rot(r.out, f, 8), want[f]) < 1e-4);
        assert_true(fabs(rot_diff(local_rot(r.out, f, 8), rest) - 15) < 1e-4);
    }
    run_free(&r);
    rf_mapping_free(m), rf_animation_free(clip), rf_animation_free(own), rf_skeleton_free(s);
}

/* The source posed at two times at once (the contact tracks and the clearance) is the source
 * posed at each time alone, bit for bit: the same operations, interleaved. */
static void source_posed_two_at_once(void **state)
{
    (void)state;
    rf_skeleton *s = biped(1, 0.5, 0.45);
    s->joints[3].rest.s = rf_v3(1.5, 1.5, 1.5); /* a scaled joint: its children's products */
    rf_animation *clip = fx_rest_clip(s, 12, 10);
    srand(5);
    for (uint32_t f = 0; f < 12; f++)
        for (uint32_t j = 0; j < s->joint_count; j++) {
            rf_vec3 axis = rf_v3(rand() % 201 - 100, rand() % 201 - 100, rand() % 201 - 100 + 0.5);
            rf_animation_set_rotation(clip, f, j, fx_rot(axis, rand() % 360));
        }
    rf_mapping *m = fx_mapping(9, 1);
    fx_map_same(m, 9);
    rf_retarget_options o = opts();
    run r = do_run(s, clip, s, m, &o);
    size_t n = s->joint_count;
    rf_xform local[2][16], world[2][16], one_local[16], one_world[16];
    float rot[2][64], tr[2][48], one_rot[64], one_tr[48];
    assert_true(n <= 16);
    rf_rt_source_pose pose[2] = {{local[0], world[0], rot[0], tr[0]},
                                 {local[1], world[1], rot[1], tr[1]}};
    double t[2] = {0.25, 0.83}; /* between frames: sampled */
    uint8_t need[16] = {0};
    for (int some = 0; some < 2; some++) {
        for (size_t j = 0; j < n; j++)
            need[j] = !some || j < 5; /* all joints, then a chain from the root */
        rf_rt_source_world_two(r.rt, 0, t, pose, some ? need : NULL);
        for (int i = 0; i < 2; i++) {
            rf_rt_source_world_some(r.rt, 0, t[i], one_local, one_world, one_rot, one_tr,
                                    some ? need : NULL);
            for (size_t j = 0; j < n; j++)
                if (!some || need[j])
                    assert_memory_equal(&world[i][j], &one_world[j], sizeof one_world[j]);
        }
    }
    run_free(&r);
    rf_mapping_free(m), rf_animation_free(clip), rf_skeleton_free(s);
}

/* A target's own clip that turns the head 179 degrees sets no limit at all (no turn exceeds 180
 * plus the slack): a half turn in the clip stays as it is, not carried on past the half turn. */
static void half_turn_kept_under_own_range(void **state)
{
    (void)state;
    rf_skeleton *s = biped(1, 0.5, 0.45);
    rf_animation *clip = fx_rest_clip(s, 3, 10), *own = fx_rest_clip(s, 2, 10);
    rf_animation_set_rotation(own, 1, 8, fx_rot(Z, 179));
    rf_mapping *m = fx_mapping(9, 1);
    fx_map_same(m, 9);
    rf_retarget_options o = opts();
    run r = do_run(s, clip, s, m, &o);
    rf_quat half = rf_quat_make(1, 0, 0, 0); /* 180 degrees about X, exactly */
    rf_animation_set_rotation(r.out, 1, 8, half);
    assert_int_equal(rf_retarget_limit_turns(r.rt, r.out, own), 0);
    assert_true(rot_diff(local_rot(r.out, 1, 8), half) < 1e-4);
    run_free(&r);
    rf_mapping_free(m), rf_animation_free(clip), rf_animation_free(own), rf_skeleton_free(s);
}

/* ---- clip options ---- */

static void resampling_slerps(void **state)
{
    (void)state;
    rf_skeleton *src = arm_tpose(), *tgt = arm_apose();
    rf_animation *clip = swing_clip(src, 10);
    rf_mapping *m = fx_mapping(8, 1);
    fx_map_same(m, 8);
    rf_retarget_options o = opts();
    run base = do_run(src, clip, tgt, m, &o);
    o.fps = 20;
    run fine = do_run(src, clip, tgt, m, &o);
    assert_int_equal(fine.out->frame_count, 19);
    assert_true(fabs(fine.out->fps - 20) < 1e-12);
    for (uint32_t f = 0; f + 1 < 10; f++) {
        /* The upper arm hangs from a still root: its rotation is the source's times a constant,
         * so the new frames are the slerp of their neighbours. */
        rf_quat mid = rf_quat_slerp(local_rot(base.out, f, 1), local_rot(base.out, f + 1, 1), 0.5);
        assert_true(rot_diff(local_rot(fine.out, 2 * f, 1), local_rot(base.out, f, 1)) < 1e-3);
        assert_true(rot_diff(local_rot(fine.out, 2 * f + 1, 1), mid) < 1e-3);
    }
    run_free(&base), run_free(&fine);
    rf_mapping_free(m), rf_animation_free(clip), rf_skeleton_free(src), rf_skeleton_free(tgt);
}

static void frame_range(void **state)
{
    (void)state;
    rf_skeleton *src = arm_tpose(), *tgt = arm_apose();
    rf_animation *clip = swing_clip(src, 12);
    rf_mapping *m = fx_mapping(8, 1);
    fx_map_same(m, 8);
    rf_retarget_options o = opts();
    run all = do_run(src, clip, tgt, m, &o);
    o.first_frame = 5, o.last_frame = 9;
    run part = do_run(src, clip, tgt, m, &o);
    assert_int_equal(part.out->frame_count, 5);
    for (uint32_t f = 0; f < 5; f++)
        for (uint32_t j = 0; j < 8; j++)
            assert_true(rot_diff(local_rot(part.out, f, j), local_rot(all.out, f + 5, j)) < 1e-4);
    /* where the window starts in the source, for a measure to line the two up */
    assert_float_equal(all.out->source_start, 0, 1e-12);
    assert_float_equal(part.out->source_start, 5 / clip->fps, 1e-12);
    rf_animation *copy = rf_animation_copy(part.out);
    assert_non_null(copy);
    assert_float_equal(copy->source_start, part.out->source_start, 0);
    rf_animation_free(copy);
    run_free(&all), run_free(&part);
    o.first_frame = 20, o.last_frame = -1;
    char err[256];
    rf_rt_source s = {src, clip};
    rf_retarget *rt = rf_retarget_new(&s, 1, tgt, m, &o, err, sizeof err);
    assert_null(rf_retarget_clip(rt, NULL, NULL, err, sizeof err));
    /* the message says which end is wrong, and the frames there are */
    if (!strstr(err, "first_frame 20 is past the source clip's last frame (12 frames: 0..11)"))
        fail_msg("unexpected message: %s", err);
    rf_retarget_free(rt);
    rf_mapping_free(m), rf_animation_free(clip), rf_skeleton_free(src), rf_skeleton_free(tgt);
}

/* A seeded generator, so the motion is arbitrary but the same every run. */
static double lcg(uint32_t *seed)
{
    *seed = *seed * 1664525u + 1013904223u;
    return *seed / 4294967296.0;
}

static void identity_returns_the_clip(void **state)
{
    (void)state;
    rf_skeleton *s = biped(1, 0.5, 0.45);
    /* Rotated rests, so the identity is not a matter of identity rotations. */
    s->joints[1].rest.r = fx_rot(rf_v3(1, 2, 3), 20);
    s->joints[2].rest.r = fx_rot(rf_v3(-2, 1, 0), 35);
    s->joints[7].rest.r = fx_rot(Y, 90);
    rf_animation *clip = fx_rest_clip(s, 30, 30);
    uint32_t seed = 5;
    for (uint32_t f = 0; f < 30; f++) {
        for (uint32_t j = 0; j < 9; j++) {
            rf_vec3 axis = rf_v3(lcg(&seed) - 0.5, lcg(&seed) - 0.5, lcg(&seed) - 0.5);
            rf_quat q = rf_quat_mul(s->joints[j].rest.r, rf_quat_from_axis_angle(axis, 0.3));
            rf_animation_set_rotation(clip, f, j, q);
        }
        rf_animation_set_translation(clip, f, 0, rf_v3(0.05 * f, 1.0 + 0.02 * lcg(&seed), 0));
    }
    rf_mapping *m = fx_mapping(9, 1);
    fx_map_same(m, 9);
    rf_retarget_options o = opts();
    run r = do_run(s, clip, s, m, &o);
    for (uint32_t f = 0; f < 30; f++)
        for (uint32_t j = 0; j < 9; j++) {
            rf_quat a = local_rot(r.out, f, j), b = local_rot(clip, f, j);
            assert_true(1 - fabs(rf_quat_dot(a, b)) < 1e-10 || rot_diff(a, b) < 1e-3);
            assert_true(rf_v3_dist(rf_animation_translation(r.out, f, j),
                                   rf_animation_translation(clip, f, j)) < 1e-5);
            float *qa = r.out->rotations + ((size_t)f * 9 + j) * 4;
            float *qb = clip->rotations + ((size_t)f * 9 + j) * 4;
            double sign =
                qa[0] * qb[0] + qa[1] * qb[1] + qa[2] * qb[2] + qa[3] * qb[3] < 0 ? -1 : 1;
            for (int c = 0; c < 4; c++)
                assert_true(fabs(qa[c] * sign - qb[c]) < 1e-5);
        }
    run_free(&r);
    rf_mapping_free(m), rf_animation_free(clip), rf_skeleton_free(s);
}

/* ---- facing, mirror, degenerate rest ---- */

/* Plays a clip of a biped on another turned to face -Z, which keeps facing -Z: its bones point
 * where the source's point, turned half round about up with it (the hips turned round, the legs'
 * sides fixing the twist about the spine), so the clip plays where the target faces. With
 * `stated`, both files state +Z forward, the target's against its toes: the skeleton analysis
 * reads it facing -Z (its feet outvote the file), and so does the matcher, which pairs the sides
 * by that reading, so the retarget turns the body by it too. Turned by the file's +Z, each leg
 * was driven by the source leg on the other side of it. */
static void half_turned_target_plays(bool stated)
{
    rf_skeleton *src = biped(1, 0.5, 0.45), *tgt = biped(0.8, 0.55, 0.4);
    tgt->joints[0].rest.r = fx_rot(Y, 180);
    if (stated)
        src->forward = tgt->forward = rf_v3(0, 0, 1);
    rf_animation *clip = fx_rest_clip(src, 2, 10);
    rf_animation_set_rotation(clip, 1, 1, fx_rot(X, -40));
    rf_animation_set_rotation(clip, 1, 2, fx_rot(X, 60));
    rf_mapping *m = fx_mapping(9, 1);
    fx_map_same(m, 9);
    rf_retarget_options o = opts();
    run r = do_run(src, clip, tgt, m, &o);
    rf_xform ws[9], wt[9];
    rf_quat half = fx_rot(Y, 180);
    for (uint32_t f = 0; f < 2; f++) {
        fx_world(src, clip, f, ws);
        fx_world(tgt, r.out, f, wt);
        /* toes forward like the source's, the left thigh on the source's left, all turned */
        assert_true(fx_angle(bone_dir(tgt, wt, 3, 3),
                             rf_quat_rotate(half, bone_dir(src, ws, 3, 3))) < 1e-3);
        assert_true(fx_angle(rf_v3_sub(wt[2].t, wt[1].t),
                             rf_quat_rotate(half, rf_v3_sub(ws[2].t, ws[1].t))) < 1e-3);
        assert_true(fx_angle(rf_v3_sub(wt[1].t, wt[0].t),
                             rf_quat_rotate(half, rf_v3_sub(ws[1].t, ws[0].t))) < 1e-3);
    }
    run_free(&r);
    rf_mapping_free(m), rf_animation_free(clip), rf_skeleton_free(src), rf_skeleton_free(tgt);
}

static void opposite_facing_keeps_its_facing(void **state)
{
    (void)state;
    half_turned_target_plays(false);
}

static void stated_forward_against_the_body_gives_way(void **state)
{
    (void)state;
    half_turned_target_plays(true);
}

/* Four legs: hind legs under the hips, front legs under a chest ahead (+Z), feet forward. */
static rf_skeleton *quadruped(void)
{
    rf_skeleton *s = rf_skeleton_new(16);
    fx_joint(s, 0, "hips", -1, rf_v3(0, 1.0, -0.5), rf_quat_identity());
    const char *names[4][3] = {
        {"hl1", "hl2", "hl3"}, {"hr1", "hr2", "hr3"}, {"fl1", "fl2", "fl3"}, {"fr1", "fr2", "fr3"}};
    fx_joint(s, 7, "spine", 0, rf_v3(0, 0, 0.5), rf_quat_identity());
    fx_joint(s, 8, "chest", 7, rf_v3(0, 0, 0.5), rf_quat_identity());
    uint32_t first[4] = {1, 4, 9, 12};
    int32_t parent[4] = {0, 0, 8, 8};
    for (int leg = 0; leg < 4; leg++) {
        uint32_t j = first[leg];
        double side = leg % 2 ? -0.15 : 0.15;
        fx_joint(s, j, names[leg][0], parent[leg], rf_v3(side, 0, 0), rf_quat_identity());
        fx_joint(s, j + 1, names[leg][1], (int32_t)j, rf_v3(0, -0.5, 0), rf_quat_identity());
        fx_joint(s, j + 2, names[leg][2], (int32_t)j + 1, rf_v3(0, -0.45, 0), rf_quat_identity());
        fx_end_site(s, j + 2, rf_v3(0, -0.05, 0.1));
    }
    fx_joint(s, 15, "head", 8, rf_v3(0, 0.3, 0.3), rf_quat_identity());
    fx_end_site(s, 15, rf_v3(0, 0, 0.25));
    return s;
}

/* A quadruped built differently from its source (hind legs set back and lower, the spine rising
 * to a higher chest) stays as level as its source: at the source's rest, the target's hips keep
 * their rest rotation. A fit of the hips' directions (legs and spine) tilted them by the angle
 * between the two builds. */
static void top_joint_keeps_level(void **state)
{
    (void)state;
    rf_skeleton *src = quadruped(), *tgt = quadruped();
    tgt->joints[1].rest.t = rf_v3(0.15, -0.15, -0.25);
    tgt->joints[4].rest.t = rf_v3(-0.15, -0.15, -0.25);
    tgt->joints[7].rest.t = rf_v3(0, 0.25, 0.5);
    rf_animation *clip = fx_rest_clip(src, 2, 10);
    rf_mapping *m = fx_mapping(16, 1);
    fx_map_same(m, 16);
    rf_retarget_options o = opts();
    run r = do_run(src, clip, tgt, m, &o);
    rf_xform wt[16];
    for (uint32_t f = 0; f < 2; f++) {
        fx_world(tgt, r.out, f, wt);
        assert_true(rf_quat_angle(wt[0].r, tgt->joints[0].rest.r) < 1e-6);
    }
    run_free(&r);
    rf_mapping_free(m), rf_animation_free(clip), rf_skeleton_free(src), rf_skeleton_free(tgt);
}

/* Three seconds of stepping with a one-second cycle: the legs swing in opposite phase, and
 * swing out sideways by a constant 10 degrees each. */
static rf_animation *stepping(const rf_skeleton *s)
{
    rf_animation *a = fx_rest_clip(s, 90, 30);
    for (uint32_t f = 0; f < 90; f++) {
        double w = 30 * sin(2 * RF_PI * f / 30.0);
        rf_animation_set_rotation(a, f, 1, rf_quat_mul(fx_rot(X, w), fx_rot(Z, 10)));
        rf_animation_set_rotation(a, f, 4, rf_quat_mul(fx_rot(X, -w), fx_rot(Z, -10)));
        rf_animation_set_rotation(a, f, 2, fx_rot(X, 20 + w / 2));
        rf_animation_set_rotation(a, f, 5, fx_rot(X, 20 - w / 2));
    }
    return a;
}

static rf_vec3 seg(const rf_xform *w, uint32_t a, uint32_t b)
{
    return rf_v3_sub(w[b].t, w[a].t);
}

static void mirror_drives_second_pair(void **state)
{
    (void)state;
    rf_skeleton *src = biped(1, 0.5, 0.45), *tgt = quadruped();
    rf_animation *clip = stepping(src);
    rf_mapping *m = fx_mapping(16, 1);
    fx_map(m, 0, 0, 0, 1, 0, 0), fx_map(m, 7, 0, 7, 1, 0, 0), fx_map(m, 15, 0, 8, 1, 0, 0);
    for (uint32_t k = 0; k < 3; k++) {
        fx_map(m, 1 + k, 0, 1 + k, 1, 0, 0), fx_map(m, 4 + k, 0, 4 + k, 1, 0, 0);
        fx_map(m, 9 + k, 0, 1 + k, 1, 0, RF_MAP_MIRROR); /* front left from the left leg */
        fx_map(m, 12 + k, 0, 4 + k, 1, 0, RF_MAP_MIRROR);
    }
    rf_retarget_options o = opts();
    run r = do_run(src, clip, tgt, m, &o);
    rf_rt_info info;
    rf_retarget_info(r.rt, &info);
    assert_true(fabs(info.cycle - 1.0) < 1.5 / 30); /* within a frame or so of the true cycle */
    rf_xform a[16], b[16];
    for (uint32_t f = 0; f + 15 < 90; f++) {
        fx_world(tgt, r.out, f, a);
        fx_world(tgt, r.out, f + (uint32_t)lround(info.cycle * 15), b);
        /* The front left leg now does what the hind left leg does half a cycle on... */
        assert_true(fx_angle(seg(a, 9, 10), seg(b, 1, 2)) < 0.5);
        assert_true(fx_angle(seg(a, 10, 11), seg(b, 2, 3)) < 0.5);
    }
    run_free(&r);
    /* ... and taken from the other side, it is mirrored: the right leg half a cycle on, swung
     * out to the left, is the left leg now. */
    rf_mapping *x = fx_mapping(16, 1);
    fx_map(x, 0, 0, 0, 1, 0, 0), fx_map(x, 7, 0, 7, 1, 0, 0), fx_map(x, 15, 0, 8, 1, 0, 0);
    for (uint32_t k = 0; k < 3; k++) {
        fx_map(x, 1 + k, 0, 1 + k, 1, 0, 0), fx_map(x, 4 + k, 0, 4 + k, 1, 0, 0);
        fx_map(x, 9 + k, 0, 4 + k, 1, 0, RF_MAP_MIRROR);
        fx_map(x, 12 + k, 0, 1 + k, 1, 0, RF_MAP_MIRROR);
    }
    o.cycle = 1.0;
    r = do_run(src, clip, tgt, x, &o);
    for (uint32_t f = 0; f < 90; f++) {
        fx_world(tgt, r.out, f, a);
        assert_true(fx_angle(seg(a, 9, 10), seg(a, 1, 2)) < 1e-2);
        assert_true(fx_angle(seg(a, 12, 13), seg(a, 4, 5)) < 1e-2);
    }
    run_free(&r);
    rf_mapping_free(m), rf_mapping_free(x), rf_animation_free(clip);
    rf_skeleton_free(src), rf_skeleton_free(tgt);
}

/* Forelegs driven half a cycle later by the source's legs (the matcher's gait rule) are another
 * pair of legs: the legs in phase with the source say how long the target's legs are. Here the
 * forelegs are 0.2 longer than the hind legs. Aligned onto the source's straight legs, a hind
 * ankle stands at 1.0 - 0.5 - 0.45 = 0.05 under hips at 1.0 and its foot's tip (0.1118 long)
 * drops along the source foot's direction (0, -0.05, 0.15): by 0.1118 * 0.05 / 0.1581 = 0.0354,
 * so the leg is 1.0 - 0.0146 = 0.9854; a foreleg's ankle stands at 1.0 - 0.6 - 0.55 = -0.15, and
 * counted in (forelegs mapped in phase) the leg is 1.0 + 0.15 + 0.0354 = 1.1854. */
static void phase_legs_leave_leg_length(void **state)
{
    (void)state;
    rf_skeleton *src = biped(1, 0.5, 0.45), *tgt = quadruped();
    for (uint32_t j = 9; j <= 12; j += 3) {
        tgt->joints[j + 1].rest.t = rf_v3(0, -0.6, 0);
        tgt->joints[j + 2].rest.t = rf_v3(0, -0.55, 0);
    }
    rf_animation *clip = stepping(src);
    double drop = sqrt(0.05 * 0.05 + 0.1 * 0.1) * 0.05 / sqrt(0.05 * 0.05 + 0.15 * 0.15);
    for (int phase = 1; phase >= 0; phase--) {
        rf_mapping *m = fx_mapping(16, 1);
        fx_map(m, 0, 0, 0, 1, 0, 0), fx_map(m, 7, 0, 7, 1, 0, 0), fx_map(m, 15, 0, 8, 1, 0, 0);
        for (uint32_t k = 0; k < 3; k++) {
            fx_map(m, 1 + k, 0, 1 + k, 1, 0, 0), fx_map(m, 4 + k, 0, 4 + k, 1, 0, 0);
            fx_map(m, 9 + k, 0, 1 + k, 1, 0, phase ? RF_MAP_MIRROR : 0);
            fx_map(m, 12 + k, 0, 4 + k, 1, 0, phase ? RF_MAP_MIRROR : 0);
        }
        rf_retarget_options o = opts();
        run r = do_run(src, clip, tgt, m, &o);
        rf_rt_info info;
        rf_retarget_info(r.rt, &info);
        double want = phase ? 1.0 - (0.05 - drop) : 1.0 + 0.15 + drop;
        print_message("forelegs %s: leg %.4f (by hand %.4f)\n",
                      phase ? "half a cycle later" : "in phase", info.leg_target, want);
        assert_true(fabs(info.leg_target - want) < 1e-3);
        run_free(&r);
        rf_mapping_free(m);
    }
    rf_animation_free(clip), rf_skeleton_free(src), rf_skeleton_free(tgt);
}

/* A foot driven half a cycle later that steps is down where its own motion is (a quadruped's
 * forefoot under a biped's walk: its source's contacts are another body's). On 100 frames at 30
 * fps of made-up sole heights, 1 leg over the floor but frames 20-49 at 0.05 and frame 70 five
 * legs under it: by hand, its low (the 10th percentile) is 0.05 and its contacts are frames
 * 20-49, the one frame at 70 dropped as a run shorter than 0.05 s (two frames); the feet in phase
 * keep the contacts they had. */
static void phase_feet_down_by_own_motion(void **state)
{
    (void)state;
    rf_skeleton *src = biped(1, 0.5, 0.45), *tgt = quadruped();
    rf_animation *clip = stepping(src);
    rf_mapping *m = fx_mapping(16, 1);
    fx_map(m, 0, 0, 0, 1, 0, 0), fx_map(m, 7, 0, 7, 1, 0, 0), fx_map(m, 15, 0, 8, 1, 0, 0);
    for (uint32_t k = 0; k < 3; k++) {
        fx_map(m, 1 + k, 0, 1 + k, 1, 0, 0), fx_map(m, 4 + k, 0, 4 + k, 1, 0, 0);
        fx_map(m, 9 + k, 0, 1 + k, 1, 0, RF_MAP_MIRROR);
        fx_map(m, 12 + k, 0, 4 + k, 1, 0, RF_MAP_MIRROR);
    }
    rf_retarget_options o = opts();
    run r = do_run(src, clip, tgt, m, &o);
    enum { FRAMES = 100 };
    uint32_t feet = r.rt->effector_count, steps = 0;
    double *sole = malloc((size_t)feet * FRAMES * sizeof *sole);
    uint8_t *c = malloc((size_t)feet * FRAMES);
    assert_non_null(sole), assert_non_null(c);
    double floor = r.rt->floor_target, leg = r.rt->leg_target;
    for (uint32_t e = 0; e < feet; e++)
        for (uint32_t f = 0; f < FRAMES; f++) {
            double h = f >= 20 && f < 50 ? 0.05 : f == 70 ? -5 : 1;
            sole[(size_t)e * FRAMES + f] = floor + h * leg;
            c[(size_t)e * FRAMES + f] = f % 2; /* what the source's contacts said */
        }
    assert_true(rf_rt_phase_contacts(r.rt, FRAMES, 30, sole, c));
    for (uint32_t e = 0; e < feet; e++) {
        bool own = rf_rt_effector_steps(r.rt, e);
        steps += own;
        for (uint32_t f = 0; f < FRAMES; f++)
            assert_int_equal(c[(size_t)e * FRAMES + f], own ? f >= 20 && f < 50 : f % 2);
    }
    assert_int_equal(steps, 2); /* the two forefeet */
    free(sole), free(c);
    run_free(&r);
    rf_mapping_free(m), rf_animation_free(clip), rf_skeleton_free(src), rf_skeleton_free(tgt);
}

/* The biped's topology with every bone along local +X at zero rotation (as Maya joint orients
 * leave a BVH): its zero pose is no body; frame 0 of its clip stands it up. */
static rf_skeleton *flat_biped(void)
{
    rf_skeleton *s = rf_skeleton_new(9);
    fx_joint(s, 0, "hips", -1, rf_v3(0, 1.0, 0), rf_quat_identity());
    fx_joint(s, 1, "lthigh", 0, rf_v3(0.1, 0, 0), rf_quat_identity());
    fx_joint(s, 2, "lknee", 1, rf_v3(0.5, 0, 0), rf_quat_identity());
    fx_joint(s, 3, "lankle", 2, rf_v3(0.45, 0, 0), rf_quat_identity());
    fx_end_site(s, 3, rf_v3(0.15, 0, 0));
    fx_joint(s, 4, "rthigh", 0, rf_v3(0.1, 0, 0), rf_quat_identity());
    fx_joint(s, 5, "rknee", 4, rf_v3(0.5, 0, 0), rf_quat_identity());
    fx_joint(s, 6, "rankle", 5, rf_v3(0.45, 0, 0), rf_quat_identity());
    fx_end_site(s, 6, rf_v3(0.15, 0, 0));
    fx_joint(s, 7, "spine", 0, rf_v3(0.1, 0, 0), rf_quat_identity());
    fx_joint(s, 8, "head", 7, rf_v3(0.5, 0, 0), rf_quat_identity());
    fx_end_site(s, 8, rf_v3(0.2, 0, 0));
    return s;
}

static void degenerate_rest_uses_a_frame(void **state)
{
    (void)state;
    rf_skeleton *src = flat_biped(), *tgt = biped(0.9, 0.5, 0.45);
    rf_animation *clip = fx_rest_clip(src, 3, 10);
    for (uint32_t f = 0; f < 3; f++) {
        /* hips turned so the spine points up; legs turned down, the right one over to -X */
        rf_animation_set_rotation(clip, f, 0, fx_rot(Z, 90));
        rf_animation_set_rotation(clip, f, 1, fx_rot(Z, 180 - 10.0 * f));
        rf_animation_set_rotation(clip, f, 4, fx_rot(Y, 180));
        rf_animation_set_rotation(clip, f, 2, fx_rot(Z, 15.0 * f));
        rf_animation_set_rotation(clip, f, 3, fx_rot(Y, -90));
        rf_animation_set_rotation(clip, f, 6, fx_rot(Y, 90));
        rf_animation_set_rotation(clip, f, 7, fx_rot(Z, 5.0 * f));
    }
    rf_mapping *m = fx_mapping(9, 1);
    fx_map_same(m, 9);
    rf_retarget_options o = opts();
    run r = do_run(src, clip, tgt, m, &o);
    rf_rt_info info;
    rf_retarget_info(r.rt, &info);
    assert_int_equal(info.rest_frame, 0);
    rf_rt_report rep;
    char err[256];
    assert_true(
        rf_retarget_measure(r.rt, r.out, rf_retarget_start_time(r.rt), &rep, err, sizeof err));
    assert_true(rep.fidelity_bones >= 6);
    assert_true(rep.fidelity_max < 1e-2);
    run_free(&r);
    rf_mapping_free(m), rf_animation_free(clip), rf_skeleton_free(src), rf_skeleton_free(tgt);
}

/* ---- measures and the contact pass ---- */

static void measure_by_hand(void **state)
{
    (void)state;
    rf_skeleton *src = arm_tpose(), *tgt = arm_apose();
    rf_animation *clip = fx_rest_clip(src, 3, 10), *held = fx_rest_clip(tgt, 3, 10);
    rf_mapping *m = fx_mapping(8, 1);
    fx_map_same(m, 8);
    char err[256];
    rf_rt_source s = {src, clip};
    rf_retarget_options o = opts();
    rf_retarget *rt = rf_retarget_new(&s, 1, tgt, m, &o, err, sizeof err);
    rf_rt_report rep;
    assert_true(rf_retarget_measure(rt, held, 0, &rep, err, sizeof err));
    /* The target held in its A-pose against a T-pose. Measured bones: each arm's upper arm,
     * forearm and hand (45 degrees off each) and the head (0); the chest branches three ways,
     * so it is not one bone. Mean 6 x 45 / 7. */
    assert_int_equal(rep.fidelity_bones, 7);
    assert_true(fabs(rep.fidelity_mean - 270.0 / 7) < 1e-3);
    assert_true(fabs(rep.fidelity_max - 45) < 1e-3);
    assert_int_equal(rep.frames, 3);
    rf_retarget_free(rt);
    rf_mapping_free(m), rf_animation_free(clip), rf_animation_free(held);
    rf_skeleton_free(src), rf_skeleton_free(tgt);
}

static int cmp_weighted(const void *a, const void *b)
{
    double x = ((const rf_rt_weighted *)a)->value, y = ((const rf_rt_weighted *)b)->value;
    return (x > y) - (x < y);
}

/* The weighted quantile the part figures read: by hand on three values, then against sorting
 * and summing on 2000 values drawn with ties, at several q. */
static void weighted_quantile(void **state)
{
    (void)state;
    static const double q[] = {0, 0.25, 0.5, 0.75, 0.99, 1};
    static const double expect[] = {1, 1, 2, 2, 3, 3}; /* cumulated 1, 3, 4 of 4 */
    for (size_t i = 0; i < sizeof q / sizeof *q; i++) {
        rf_rt_weighted v[] = {{3, 1}, {1, 1}, {2, 2}};
        assert_true(rf_rt_weighted_quantile(v, 3, q[i]) == expect[i]);
    }
    assert_true(rf_rt_weighted_quantile(NULL, 0, 0.99) == 0);
    enum { N = 2000 };
    rf_rt_weighted *v = malloc(N * sizeof *v), *sorted = malloc(N * sizeof *v);
    uint32_t seed = 12345;
    for (size_t i = 0; i < N; i++) {
        seed = seed * 1664525u + 1013904223u;
        v[i].value = (double)(seed >> 24 & 63); /* 64 levels: many ties */
        seed = seed * 1664525u + 1013904223u;
        v[i].weight = 0.01 + (double)(seed >> 16 & 1023) / 64;
    }
    memcpy(sorted, v, N * sizeof *v);
    qsort(sorted, N, sizeof *sorted, cmp_weighted);
    double total = 0;
    for (size_t i = 0; i < N; i++)
        total += sorted[i].weight;
    for (size_t i = 0; i < sizeof q / sizeof *q; i++) {
        double sum = 0, want = sorted[N - 1].value;
        for (size_t k = 0; k < N; k++)
            if ((sum += sorted[k].weight) >= q[i] * total) {
                want = sorted[k].value;
                break;
            }
        rf_rt_weighted *copy = malloc(N * sizeof *copy);
        memcpy(copy, v, N * sizeof *v);
        assert_true(rf_rt_weighted_quantile(copy, N, q[i]) == want);
        free(copy);
    }
    free(v), free(sorted);
}

/* Adds box `b` of a boxes mesh: 1 x 2 x 1 at x = 3b, its top corners (y = 2) weighted wholly
 * to joint `top`, its bottom ones (y = 0) to `bottom`; 12 triangles. */
static void add_box_at(rf_mesh *m, uint32_t b, float x, float y, uint16_t top, uint16_t bottom)
{
    static const uint32_t tri[12][3] = {{0, 1, 2}, {0, 2, 3}, {4, 6, 5}, {4, 7, 6},
                                        {0, 4, 5}, {0, 5, 1}, {1, 5, 6}, {1, 6, 2},
                                        {2, 6, 7}, {2, 7, 3}, {3, 7, 4}, {3, 4, 0}};
    static const float corner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (uint32_t i = 0; i < 8; i++) {
        uint32_t v = b * 8 + i;
        m->positions[v * 3] = x + corner[i % 4][0];
        m->positions[v * 3 + 1] = y + (i < 4 ? 0.0f : 2.0f);
        m->positions[v * 3 + 2] = corner[i % 4][1];
        m->skin_joints[v * 4] = i < 4 ? bottom : top;
        m->skin_weights[v * 4] = 1;
    }
    for (uint32_t t = 0; t < 12; t++)
        for (uint32_t k = 0; k < 3; k++)
            m->triangles[(b * 12 + t) * 3 + k] = b * 8 + tri[t][k];
}

static void add_box(rf_mesh *m, uint32_t b, uint16_t top, uint16_t bottom)
{
    add_box_at(m, b, (float)(3 * b), 0, top, bottom);
}

/* A boxes mesh of `boxes` boxes (add_box fills them). */
static rf_mesh *boxes_mesh(uint32_t boxes)
{
    rf_mesh *m = rf_mesh_new();
    m->vertex_count = boxes * 8, m->triangle_count = boxes * 12;
    m->positions = calloc((size_t)m->vertex_count * 3, sizeof *m->positions);
    m->skin_joints = calloc((size_t)m->vertex_count * 4, sizeof *m->skin_joints);
    m->skin_weights = calloc((size_t)m->vertex_count * 4, sizeof *m->skin_weights);
    m->triangles = calloc((size_t)m->triangle_count * 3, sizeof *m->triangles);
    return m;
}

/* A body without legs is put on its mesh's floor frame by frame (rt_mesh_rest_each); a mesh
 * whose lowest point is no number (here every position NaN) gives no floor, and the clip is
 * left where it was, as the median frame's placement leaves it, not refused as "out of
 * memory". The target is the biped's hips, spine and head, driven by the source's. */
static void mesh_floor_without_number(void **state)
{
    (void)state;
    rf_skeleton *src = biped(1, 0.5, 0.45), *tgt = rf_skeleton_new(3);
    fx_joint(tgt, 0, "hips", -1, rf_v3(0, 1, 0), rf_quat_identity());
    fx_joint(tgt, 1, "spine", 0, rf_v3(0, 0.1, 0), rf_quat_identity());
    fx_joint(tgt, 2, "head", 1, rf_v3(0, 0.5, 0), rf_quat_identity());
    fx_end_site(tgt, 2, rf_v3(0, 0.2, 0));
    rf_animation *clip = fx_rest_clip(src, 20, 30);
    for (uint32_t f = 0; f < 20; f++)
        rf_animation_set_rotation(clip, f, 7, fx_rot(X, f));
    rf_mapping *m = fx_mapping(3, 1);
    fx_map(m, 0, 0, 0, 1, 0, 0), fx_map(m, 1, 0, 7, 1, 0, 0), fx_map(m, 2, 0, 8, 1, 0, 0);
    rf_retarget_options o = opts();
    run r = do_run(src, clip, tgt, m, &o);
    rf_mesh *mesh = boxes_mesh(1);
    add_box(mesh, 0, 2, 0);
    for (uint32_t i = 0; i < mesh->vertex_count * 3; i++)
        mesh->positions[i] = NAN;
    size_t size = (size_t)r.out->frame_count * r.out->joint_count * 3 * sizeof(float);
    float *before = malloc(size);
    memcpy(before, r.out->translations, size);
    char err[256] = "";
    bool ok = rf_retarget_mesh_floor(r.rt, r.out, mesh, NULL, err, sizeof err);
    if (!ok)
        print_message("refused: %s\n", err);
    assert_true(ok);
    assert_memory_equal(before, r.out->translations, size);
    free(before);
    rf_mesh_free(mesh);
    run_free(&r);
    rf_mapping_free(m), rf_animation_free(clip), rf_skeleton_free(src), rf_skeleton_free(tgt);
}

/* One box torn off and the rest still: 100 boxes held by joint 1, and a last one whose top
 * corners joint 1 holds and whose bottom ones joint 2 (1 under joint 1) holds, pulled 2 down in
 * every frame of the clip. The torn box's vertical edges grow from 2 to 4 (stretch 1.0 exactly)
 * and its side diagonals from sqrt(5) to sqrt(17); no other edge changes length. The whole mesh
 * counts 36 edges a box and at most 16 of the torn box's stretch, under 1% of 3636: its p99
 * is 0. The worst part is joint 2's: the torn box's bottom half, its largest value 1.0 (the
 * vertical edges, a third of its edges' length) is its p99. */
static void mesh_part_torn(void **state)
{
    (void)state;
    enum { BOXES = 101 };
    rf_skeleton *s = rf_skeleton_new(3);
    fx_joint(s, 0, "root", -1, rf_v3(0, 0, 0), rf_quat_identity());
    fx_joint(s, 1, "body", 0, rf_v3(0, 2, 0), rf_quat_identity());
    fx_joint(s, 2, "leg", 1, rf_v3(0, -1, 0), rf_quat_identity());
    rf_mesh *m = boxes_mesh(BOXES);
    for (uint32_t b = 0; b < BOXES; b++)
        add_box(m, b, 1, b == BOXES - 1 ? 2 : 1);
    rf_animation *clip = fx_rest_clip(s, 8, 30);
    for (uint32_t f = 0; f < 8; f++)
        rf_animation_set_translation(clip, f, 2, rf_v3(0, -3, 0));
    rf_rt_mesh_report rep;
    char err[256] = "";
    assert_true(rf_rt_mesh_measure(s, m, clip, Y, 0, &rep, err, sizeof err));
    print_message("one box torn of %u: stretch p99 %.4f, worst part %.4f (joint %u, %u edges, "
                  "of %u parts)\n",
                  BOXES, rep.stretch_p99, rep.part_stretch_p99, rep.part_joint, rep.part_edges,
                  rep.parts);
    assert_int_equal(rep.edges, BOXES * 36);
    assert_true(rep.stretch_p99 < 1e-6);
    assert_int_equal(rep.parts, 2);
    assert_int_equal(rep.part_joint, 2);
    assert_true(fabs(rep.part_stretch_p99 - 1.0) < 1e-5);
    /* Held at rest, nothing stretches anywhere. */
    rf_animation_free(clip);
    clip = fx_rest_clip(s, 8, 30);
    assert_true(rf_rt_mesh_measure(s, m, clip, Y, 0, &rep, err, sizeof err));
    assert_true(rep.stretch_p99 < 1e-6 && rep.part_stretch_p99 < 1e-6 && rep.parts == 2);
    rf_animation_free(clip);
    rf_mesh_free(m);
    rf_skeleton_free(s);
}

/* m with every triangle given three vertices of its own (positions and skin copied): a mesh
 * split at every edge, as one with flat normals or a texture seam everywhere is. */
static rf_mesh *unwelded(const rf_mesh *m)
{
    rf_mesh *u = boxes_mesh(0);
    u->vertex_count = m->triangle_count * 3, u->triangle_count = m->triangle_count;
    u->positions = realloc(u->positions, (size_t)u->vertex_count * 3 * sizeof *u->positions);
    u->skin_joints = realloc(u->skin_joints, (size_t)u->vertex_count * 4 * sizeof *u->skin_joints);
    u->skin_weights =
        realloc(u->skin_weights, (size_t)u->vertex_count * 4 * sizeof *u->skin_weights);
    u->triangles = realloc(u->triangles, (size_t)u->triangle_count * 3 * sizeof *u->triangles);
    for (uint32_t i = 0; i < u->vertex_count; i++) {
        uint32_t v = m->triangles[i];
        memcpy(u->positions + i * 3, m->positions + v * 3, 3 * sizeof *u->positions);
        memcpy(u->skin_joints + i * 4, m->skin_joints + v * 4, 4 * sizeof *u->skin_joints);
        memcpy(u->skin_weights + i * 4, m->skin_weights + v * 4, 4 * sizeof *u->skin_weights);
        u->triangles[i] = i;
    }
    return u;
}

/* The worst solid part's volume figure (and how many were measured) of mesh m under a clip
 * holding joint 2 at local translation `leg` in every frame. */
static double box_volume_off(const rf_skeleton *s, const rf_mesh *m, rf_vec3 leg, uint32_t *parts)
{
    rf_animation *clip = fx_rest_clip(s, 8, 30);
    for (uint32_t f = 0; f < 8; f++)
        rf_animation_set_translation(clip, f, 2, leg);
    rf_rt_mesh_report rep;
    char err[256] = "";
    assert_true(rf_rt_mesh_measure(s, m, clip, Y, 0, &rep, err, sizeof err));
    rf_animation_free(clip);
    *parts = rep.volume_parts;
    return rep.volume_p95;
}

/* The volume one 1 x 2 x 1 box keeps (rt-volume.c), worked by hand: its top corners on joint
 * 1, its bottom ones on joint 2 (1 under joint 1). Pulled 2 down in every frame it is 4 high,
 * twice its rest volume (off 1.0); pushed 1 up, 1 high (off 0.5); pushed 1 sideways, sheared,
 * its volume kept (off 0); held at rest, 0. Built of three vertices of its own per triangle it is
 * welded and read closed all the same; with a triangle left out it is open, not a solid, and
 * not measured. */
static void mesh_volume(void **state)
{
    (void)state;
    rf_skeleton *s = rf_skeleton_new(3);
    fx_joint(s, 0, "root", -1, rf_v3(0, 0, 0), rf_quat_identity());
    fx_joint(s, 1, "body", 0, rf_v3(0, 2, 0), rf_quat_identity());
    fx_joint(s, 2, "leg", 1, rf_v3(0, -1, 0), rf_quat_identity());
    rf_mesh *m = boxes_mesh(1);
    add_box(m, 0, 1, 2);
    rf_mesh *u = unwelded(m);
    const rf_mesh *both[2] = {m, u};
    uint32_t parts;
    for (int i = 0; i < 2; i++) {
        const rf_mesh *b = both[i];
        double down = box_volume_off(s, b, rf_v3(0, -3, 0), &parts);
        assert_int_equal(parts, 1);
        double up = box_volume_off(s, b, rf_v3(0, 0, 0), &parts);
        double side = box_volume_off(s, b, rf_v3(1, -1, 0), &parts);
        double rest = box_volume_off(s, b, rf_v3(0, -1, 0), &parts);
        print_message("box (%s): pulled down %.6f, pushed up %.6f, sheared %.6f, at rest %.6f\n",
                      i ? "unwelded" : "welded", down, up, side, rest);
        assert_true(fabs(down - 1.0) < 1e-5 && fabs(up - 0.5) < 1e-5);
        assert_true(side < 1e-5 && rest < 1e-5);
    }
    m->triangle_count--;
    box_volume_off(s, m, rf_v3(0, -3, 0), &parts);
    assert_int_equal(parts, 0);
    rf_mesh_free(u), rf_mesh_free(m);
    rf_skeleton_free(s);
}

/* Adds plate `p` of a plates mesh: a unit square at height y, from x to x + 1 (z 0 to 1), facing
 * up (or down), every corner on joint j; 2 triangles. */
static void add_plate(rf_mesh *m, uint32_t p, float x, float y, bool up, uint16_t j)
{
    static const float corner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (uint32_t i = 0; i < 4; i++) {
        uint32_t v = p * 4 + i;
        m->positions[v * 3] = x + corner[i][0], m->positions[v * 3 + 1] = y;
        m->positions[v * 3 + 2] = corner[i][1];
        m->skin_joints[v * 4] = j, m->skin_weights[v * 4] = 1;
    }
    uint32_t tri[2][3] = {{0, 2, 1}, {0, 3, 2}}; /* facing up: counter-clockwise seen from +y */
    for (uint32_t t = 0; t < 2; t++)
        for (uint32_t k = 0; k < 3; k++)
            m->triangles[(p * 2 + t) * 3 + k] = p * 4 + tri[t][up ? k : 2 - k];
}

/* Surfaces that touch at rest facing each other (a hand hanging against the thigh) are no seam:
 * pulled apart as the limbs move they tear nothing. Four plates, joints 1 (still) and 2 (moved
 * 1 along +z in every frame): a plate under another facing it, 0.005 apart, and two plates side
 * by side, facing the same way, whose touching edges are one cut surface (split vertices). Only
 * the two split pairs are seams, and they drift: torn p99 1 / 2, the mesh 2 high. BCN_Epileptic,
 * its hands against its thighs at rest, read torn limbs p99 17.9% of its height under the CMU
 * walk when facing pairs counted, nothing torn in its renders. */
static void touching_surfaces_are_no_seam(void **state)
{
    (void)state;
    rf_skeleton *s = rf_skeleton_new(3);
    fx_joint(s, 0, "root", -1, rf_v3(0, 0, 0), rf_quat_identity());
    fx_joint(s, 1, "body", 0, rf_v3(0, 1, 0), rf_quat_identity());
    fx_joint(s, 2, "hand", 0, rf_v3(0, 1, 0), rf_quat_identity());
    rf_mesh *m = rf_mesh_new();
    m->vertex_count = 16, m->triangle_count = 8;
    m->positions = calloc(16 * 3, sizeof *m->positions);
    m->skin_joints = calloc(16 * 4, sizeof *m->skin_joints);
    m->skin_weights = calloc(16 * 4, sizeof *m->skin_weights);
    m->triangles = calloc(8 * 3, sizeof *m->triangles);
    add_plate(m, 0, 0, 0, true, 1);       /* the thigh's side, facing up */
    add_plate(m, 1, 0, 0.005f, false, 2); /* the hand over it, facing down */
    add_plate(m, 2, 3, 2, true, 1);       /* a cut surface: this half on the body... */
    add_plate(m, 3, 4, 2, true, 2);       /* ...this half on the hand */
    rf_animation *clip = fx_rest_clip(s, 4, 30);
    for (uint32_t f = 0; f < 4; f++)
        rf_animation_set_translation(clip, f, 2, rf_v3(0, 1, 1));
    rf_rt_mesh_report rep;
    char err[256] = "";
    assert_true(rf_rt_mesh_measure(s, m, clip, Y, 0, &rep, err, sizeof err));
    print_message("touching plates: %u seams, torn p99 %.4f\n", rep.seams, rep.seam_p99);
    assert_int_equal(rep.seams, 2);
    assert_true(fabs(rep.seam_p99 - 0.5) < 1e-5);
    rf_animation_free(clip);
    rf_mesh_free(m);
    rf_skeleton_free(s);
}

/* One limb pulled off its neighbour among many that hold: 101 stacks of two boxes, the upper
 * box on joint 1, the lower one touching it (4 corners shared) on joint 3 (still, under joint 1)
 * in 100 stacks and on joint 2 (pulled 2 down in every frame) in the last. The mesh is 4 high,
 * so the last stack's 4 seams drift 2 / 4 = 0.5 and the other 400 do not move: the whole mesh's
 * torn-limb p99 is 0 (4 of 404 seams), the pair of joints 1 and 2 reads 0.5. */
/* retarget.measure's JSON report: a figure that is not finite (a mean over no bone, an overflow)
 * is null, so the report stays JSON (printf's "nan" and "inf" made jansson, and any reader,
 * refuse the whole file); finite figures and counts are kept, and a joint's name reaches the file
 * escaped for a terminal (ESC as the text \x1b), its quote and backslash escaped for JSON. */
static void measure_report_json(void **state)
{
    (void)state;
    rf_skeleton *s = rf_skeleton_new(3);
    fx_joint(s, 0, "hips", -1, rf_v3(0, 1, 0), rf_quat_identity());
    fx_joint(s, 1, "fo\"ot\x1b[31m", 0, rf_v3(0, -1, 0), rf_quat_identity());
    fx_joint(s, 2, "toe\\", 1, rf_v3(0, 0, 1), rf_quat_identity());
    rf_rt_report r = {.fidelity_mean = NAN,
                      .fidelity_max = INFINITY,
                      .fidelity_p95 = 12.5,
                      .fidelity_bones = 3,
                      .skate_target = -INFINITY,
                      .skate_source = 0.25,
                      .contact_frames = 4,
                      .ground_error = NAN,
                      .frames = 10,
                      .effectors = 1,
                      .foot_joint = {1},
                      .foot_skate = {NAN},
                      .foot_frames = {4},
                      .source_feet = 1};
    rf_rt_mesh_report m = {.frames = 10,
                           .height = 2,
                           .seams = 8,
                           .seam_p99 = NAN,
                           .stretch_p99 = 0.5,
                           .parts = 2,
                           .part_stretch_p99 = INFINITY,
                           .part_joint = 1,
                           .seam_parts = 1,
                           .seam_part_p99 = NAN,
                           .seam_joints = {1, 2},
                           .seam_part_seams = 8};
    FILE *f = tmpfile();
    assert_non_null(f);
    assert_true(rf_rt_report_write(f, &r, &m, NULL, s));
    rewind(f);
    json_error_t e;
    json_t *o = json_loadf(f, 0, &e);
    fclose(f);
    if (!o)
        fail_msg("the report is not JSON: line %d: %s", e.line, e.text);
    json_t *mesh = json_object_get(o, "mesh");
    json_t *foot = json_array_get(json_object_get(o, "feet"), 0);
    const char *nulls[] = {"fidelity_mean_deg", "fidelity_max_deg", "skate_target", "ground_error"};
    for (size_t i = 0; i < sizeof nulls / sizeof *nulls; i++)
        assert_true(json_is_null(json_object_get(o, nulls[i])));
    assert_true(json_is_null(json_object_get(mesh, "seam_p99")));
    assert_true(json_is_null(json_object_get(mesh, "part_stretch_p99")));
    assert_true(json_is_null(json_object_get(mesh, "seam_part_p99")));
    assert_true(json_is_null(json_object_get(foot, "skate")));
    assert_float_equal(json_number_value(json_object_get(o, "fidelity_p95_deg")), 12.5, 0);
    assert_float_equal(json_number_value(json_object_get(o, "skate_source")), 0.25, 0);
    assert_float_equal(json_number_value(json_object_get(mesh, "stretch_p99")), 0.5, 0);
    assert_int_equal(json_integer_value(json_object_get(o, "bones")), 3);
    assert_int_equal(json_integer_value(json_object_get(foot, "contact_frames")), 4);
    assert_int_equal(json_integer_value(json_object_get(o, "feet_count")), 1);
    assert_int_equal(json_integer_value(json_object_get(o, "source_feet")), 1);
    assert_string_equal(json_string_value(json_object_get(foot, "name")), "fo\"ot\\x1b[31m");
    assert_string_equal(json_string_value(json_object_get(mesh, "part_joint_name")),
                        "fo\"ot\\x1b[31m");
    assert_string_equal(
        json_string_value(json_array_get(json_object_get(mesh, "seam_joint_names"), 1)), "toe\\");
    assert_null(json_object_get(o, "mesh_reference"));
    json_decref(o);
    rf_skeleton_free(s);
}

static void mesh_seam_torn(void **state)
{
    (void)state;
    enum { STACKS = 101 };
    rf_skeleton *s = rf_skeleton_new(4);
    fx_joint(s, 0, "root", -1, rf_v3(0, 0, 0), rf_quat_identity());
    fx_joint(s, 1, "arm", 0, rf_v3(0, 4, 0), rf_quat_identity());
    fx_joint(s, 2, "hand", 1, rf_v3(0, -2, 0), rf_quat_identity());
    fx_joint(s, 3, "cuff", 1, rf_v3(0, -2, 0), rf_quat_identity());
    rf_mesh *m = boxes_mesh(STACKS * 2);
    for (uint32_t b = 0; b < STACKS; b++) {
        add_box_at(m, b * 2, (float)(3 * b), 2, 1, 1);
        add_box_at(m, b * 2 + 1, (float)(3 * b), 0, b == STACKS - 1 ? 2 : 3,
                   b == STACKS - 1 ? 2 : 3);
    }
    rf_animation *clip = fx_rest_clip(s, 8, 30);
    for (uint32_t f = 0; f < 8; f++)
        rf_animation_set_translation(clip, f, 2, rf_v3(0, -4, 0));
    rf_rt_mesh_report rep;
    char err[256] = "";
    assert_true(rf_rt_mesh_measure(s, m, clip, Y, 0, &rep, err, sizeof err));
    print_message("one stack pulled apart of %u: torn p99 %.4f, worst seam %.4f (joints %u and "
                  "%u, %u of %u seams, of %u pairs of joints)\n",
                  STACKS, rep.seam_p99, rep.seam_part_p99, rep.seam_joints[0], rep.seam_joints[1],
                  rep.seam_part_seams, rep.seams, rep.seam_parts);
    assert_int_equal(rep.seams, STACKS * 4);
    assert_true(rep.seam_p99 < 1e-6);
    assert_int_equal(rep.seam_parts, 2);
    assert_int_equal(rep.seam_joints[0], 1);
    assert_int_equal(rep.seam_joints[1], 2);
    assert_int_equal(rep.seam_part_seams, 4);
    assert_true(fabs(rep.seam_part_p99 - 0.5) < 1e-6);
    rf_animation_free(clip);
    rf_mesh_free(m);
    rf_skeleton_free(s);
}

/* A centerline bone of another body plan keeps its source's turn about up whole and its tilt eased
 * into 10 degrees (10 tanh(a / 10)): worked by hand for a pure turn, a pure 60 degree lean
 * (10 tanh 6 = 9.99988) and a 90 degree turn after a 40 degree lean (10 tanh 4 = 9.99329); with
 * no lean allowed, the turn alone. */
static void level_keeps_turn_limits_tilt(void **state)
{
    (void)state;
    const double deg = RF_PI / 180;
    rf_vec3 up = rf_v3(0, 1, 0), left = rf_v3(1, 0, 0);
    rf_quat turn = rf_quat_from_axis_angle(up, 90 * deg);
    const double tilt = 10 * deg;
    rf_quat q = rf_rt_level(turn, up, tilt);
    assert_true(rf_quat_angle(q, turn) < 1e-9);
    q = rf_rt_level(rf_quat_from_axis_angle(left, 60 * deg), up, tilt);
    assert_true(rf_quat_angle(q, rf_quat_from_axis_angle(left, 9.99988 * deg)) < 1e-6);
    rf_quat lean = rf_quat_from_axis_angle(left, 40 * deg);
    q = rf_rt_level(rf_quat_mul(lean, turn), up, tilt);
    rf_quat want = rf_quat_mul(rf_quat_from_axis_angle(left, 9.99329 * deg), turn);
    assert_true(rf_quat_angle(q, want) < 1e-6);
    /* No tilt at all: nothing to ease. */
    q = rf_rt_level(rf_quat_identity(), up, tilt);
    assert_true(rf_quat_angle(q, rf_quat_identity()) < 1e-12);
    /* A limit of 0 (a body on four legs under a biped): the lean goes, the turn stays. */
    q = rf_rt_level(rf_quat_mul(lean, turn), up, 0);
    assert_true(rf_quat_angle(q, turn) < 1e-9);
}
/* Turns a leg (thigh at j, knee j + 1) so the ankle of a thigh and shin of lengths a and b
 * reaches `ankle` from the hip joint `hip`, bending the knee forward (+Z), in the YZ plane. */
static void plant_leg(rf_animation *clip, uint32_t f, uint32_t j, rf_vec3 hip, rf_vec3 ankle,
                      double a, double b)
{
    rf_vec3 d = rf_v3_sub(ankle, hip);
    double len = rf_v3_len(d);
    double line = atan2(-d.z, -d.y); /* rotX angle taking straight down onto the line */
    double at_hip = acos((a * a + len * len - b * b) / (2 * a * len));
    double at_knee = acos((a * a + b * b - len * len) / (2 * a * b));
    rf_animation_set_rotation(clip, f, j, fx_rot(X, (line - at_hip) / DEG));
    rf_animation_set_rotation(clip, f, j + 1, fx_rot(X, (RF_PI - at_knee) / DEG));
}

static void contact_pass_pins_feet(void **state)
{
    (void)state;
    rf_skeleton *src = biped(1, 0.5, 0.45), *tgt = biped(1, 0.75, 0.2);
    rf_animation *clip = fx_rest_clip(src, 30, 30);
    for (uint32_t f = 0; f < 30; f++) {
        double z = -0.2 + 0.4 * f / 29.0;
        rf_animation_set_translation(clip, f, 0, rf_v3(0, 0.95, z));
        plant_leg(clip, f, 1, rf_v3(0.1, 0.95, z), rf_v3(0.1, 0.05, 0), 0.5, 0.45);
        plant_leg(clip, f, 4, rf_v3(-0.1, 0.95, z), rf_v3(-0.1, 0.05, 0), 0.5, 0.45);
    }
    clip->channels[0] |= RF_CHANNEL_TRANSLATION;
    rf_xform w[9];
    for (uint32_t f = 0; f < 30; f++) { /* the fixture: the source's feet do stay planted */
        fx_world(src, clip, f, w);
        assert_true(rf_v3_dist(w[3].t, rf_v3(0.1, 0.05, 0)) < 1e-5);
    }
    rf_mapping *m = fx_mapping(9, 1);
    fx_map_same(m, 9);
    rf_retarget_options o = opts();
    run r = do_run(src, clip, tgt, m, &o);
    rf_rt_info info;
    rf_retarget_info(r.rt, &info);
    assert_int_equal(info.effectors, 2); /* the ankles */
    char err[256];
    rf_rt_report before, after;
    double start = rf_retarget_start_time(r.rt);
    assert_true(rf_retarget_measure(r.rt, r.out, start, &before, err, sizeof err));
    assert_true(before.contact_frames > 50);
    assert_int_equal(before.effectors, 2);
    assert_int_equal(before.source_feet, 2); /* each ankle follows its own */
    assert_true(before.skate_source < 1e-4);
    assert_true(before.skate_target > 0.02); /* other bone proportions: the feet slide */
    const rf_ik_solver_api *api = &rf_ik_twobone_api;
    rf_ik_solver *solver = rf_ik_solver_new(api, api->create(NULL, err, sizeof err), "twobone");
    rf_rt_contact_stats st;
    assert_true(rf_retarget_contacts(r.rt, r.out, solver, &st, err, sizeof err));
    assert_int_equal(st.effectors, 2);
    assert_true(st.solves >= 29);
    assert_true(rf_retarget_measure(r.rt, r.out, start, &after, err, sizeof err));
    print_message("skate %.4f -> %.6f leg/s, fidelity %.2f -> %.2f deg, ground %.4f -> %.4f, "
                  "miss %.3g\n",
                  before.skate_target, after.skate_target, before.fidelity_mean,
                  after.fidelity_mean, before.ground_error, after.ground_error, st.max_error);
    assert_true(after.skate_target < 1e-3);
    assert_true(after.fidelity_mean < before.fidelity_mean + 20); /* the legs bend, no more */
    rf_ik_solver_free(solver);
    run_free(&r);
    rf_mapping_free(m), rf_animation_free(clip), rf_skeleton_free(src), rf_skeleton_free(tgt);
}

/* Legs of two bones whose foot is the shin's tip (a horse's): the source's ankle hangs below
 * the knee that drives the shin, so the shin's tip is pinned where the source's foot is, with
 * the thigh and the shin as the chain. */
static void contact_pass_pins_bone_tips(void **state)
{
    (void)state;
    rf_skeleton *src = biped(1, 0.5, 0.45), *tgt = rf_skeleton_new(7);
    fx_joint(tgt, 0, "hips", -1, rf_v3(0, 1.0, 0), rf_quat_identity());
    for (int side = 0; side < 2; side++) {
        uint32_t j = 1 + 2 * (uint32_t)side;
        fx_joint(tgt, j, side ? "rthigh" : "lthigh", 0, rf_v3(side ? -0.1 : 0.1, 0, 0),
                 rf_quat_identity());
        fx_joint(tgt, j + 1, side ? "rshin" : "lshin", (int32_t)j, rf_v3(0, -0.6, 0),
                 rf_quat_identity());
        fx_end_site(tgt, j + 1, rf_v3(0, -0.4, 0));
    }
    fx_joint(tgt, 5, "spine", 0, rf_v3(0, 0.1, 0), rf_quat_identity());
    fx_joint(tgt, 6, "head", 5, rf_v3(0, 0.5, 0), rf_quat_identity());
    fx_end_site(tgt, 6, rf_v3(0, 0.2, 0));
    rf_animation *clip = fx_rest_clip(src, 30, 30);
    for (uint32_t f = 0; f < 30; f++) {
        double z = -0.2 + 0.4 * f / 29.0;
        rf_animation_set_translation(clip, f, 0, rf_v3(0, 0.95, z));
        plant_leg(clip, f, 1, rf_v3(0.1, 0.95, z), rf_v3(0.1, 0.05, 0), 0.5, 0.45);
        plant_leg(clip, f, 4, rf_v3(-0.1, 0.95, z), rf_v3(-0.1, 0.05, 0), 0.5, 0.45);
    }
    clip->channels[0] |= RF_CHANNEL_TRANSLATION;
    rf_mapping *m = fx_mapping(7, 1);
    uint32_t from[7] = {0, 1, 2, 4, 5, 7, 8};
    for (uint32_t j = 0; j < 7; j++)
        fx_map(m, j, 0, from[j], 1, 0, 0);
    rf_retarget_options o = opts();
    run r = do_run(src, clip, tgt, m, &o);
    rf_rt_info info;
    rf_retarget_info(r.rt, &info);
    assert_int_equal(info.effectors, 2); /* the shins' tips */
    char err[256];
    const rf_ik_solver_api *api = &rf_ik_twobone_api;
    rf_ik_solver *solver = rf_ik_solver_new(api, api->create(NULL, err, sizeof err), "twobone");
    rf_rt_contact_stats st;
    assert_true(rf_retarget_contacts(r.rt, r.out, solver, &st, err, sizeof err));
    assert_true(st.solves >= 29);
    /* The left shin's tip stays where it was at the first frame (horizontally), and the
     * shin still hangs from the thigh (the chain was solved, not the tip moved alone). */
    rf_xform w0[7], w[7];
    fx_world(tgt, r.out, 0, w0);
    rf_vec3 tip0 = rf_xform_point(w0[2], rf_v3(0, -0.4, 0));
    for (uint32_t f = 1; f < 30; f++) {
        fx_world(tgt, r.out, f, w);
        rf_vec3 tip = rf_xform_point(w[2], rf_v3(0, -0.4, 0));
        assert_true(hypot(tip.x - tip0.x, tip.z - tip0.z) < 1e-3);
        assert_true(fabs(rf_v3_dist(w[1].t, w[2].t) - 0.6) < 1e-4);
    }
    rf_ik_solver_free(solver);
    run_free(&r);
    rf_mapping_free(m), rf_animation_free(clip), rf_skeleton_free(src), rf_skeleton_free(tgt);
}

/* A target of hips and two one-bone legs of length 1 (their tips), with a spine and a head when
 * n is 5. */
static rf_skeleton *one_bone_legs(uint32_t n)
{
    rf_skeleton *tgt = rf_skeleton_new(n);
    fx_joint(tgt, 0, "hips", -1, rf_v3(0, 1.0, 0), rf_quat_identity());
    fx_joint(tgt, 1, "lleg", 0, rf_v3(0.1, 0, 0), rf_quat_identity());
    fx_end_site(tgt, 1, rf_v3(0, -1.0, 0));
    fx_joint(tgt, 2, "rleg", 0, rf_v3(-0.1, 0, 0), rf_quat_identity());
    fx_end_site(tgt, 2, rf_v3(0, -1.0, 0));
    if (n < 5)
        return tgt;
    fx_joint(tgt, 3, "spine", 0, rf_v3(0, 0.1, 0), rf_quat_identity());
    fx_joint(tgt, 4, "head", 3, rf_v3(0, 0.5, 0), rf_quat_identity());
    fx_end_site(tgt, 4, rf_v3(0, 0.2, 0));
    return tgt;
}

/* 30 frames of src (biped(1, 0.5, 0.45)) moving its hips forward over both feet planted at z 0:
 * the knees bend and the thighs swing while the ankles stay. */
static rf_animation *planted_walk(const rf_skeleton *src)
{
    rf_animation *clip = fx_rest_clip(src, 30, 30);
    for (uint32_t f = 0; f < 30; f++) {
        double z = -0.2 + 0.4 * f / 29.0;
        rf_animation_set_translation(clip, f, 0, rf_v3(0, 0.95, z));
        plant_leg(clip, f, 1, rf_v3(0.1, 0.95, z), rf_v3(0.1, 0.05, 0), 0.5, 0.45);
        plant_leg(clip, f, 4, rf_v3(-0.1, 0.95, z), rf_v3(-0.1, 0.05, 0), 0.5, 0.45);
    }
    clip->channels[0] |= RF_CHANNEL_TRANSLATION;
    return clip;
}

/* One-bone legs hanging from the hips (the animalia wolf's and cat's): the contact pass may not
 * turn the hips, so each leg alone is turned to aim its tip at the pin: the feet slide far less
 * (the pin is out of reach when the hips move too far from it, so not to zero). */
static void contact_pass_aims_one_bone_legs(void **state)
{
    (void)state;
    rf_skeleton *src = biped(1, 0.5, 0.45), *tgt = one_bone_legs(5);
    rf_animation *clip = planted_walk(src);
    rf_mapping *m = fx_mapping(5, 1);
    uint32_t from[5] = {0, 2, 5, 7,
                        8}; /* the legs onto the shins: a whole leg would follow the reach */
    for (uint32_t j = 0; j < 5; j++)
        fx_map(m, j, 0, from[j], 1, 0, 0);
    rf_retarget_options o = opts();
    run r = do_run(src, clip, tgt, m, &o);
    rf_rt_info info;
    rf_retarget_info(r.rt, &info);
    assert_int_equal(info.effectors, 2); /* the legs' tips */
    char err[256];
    rf_rt_report before, after;
    double start = rf_retarget_start_time(r.rt);
    assert_true(rf_retarget_measure(r.rt, r.out, start, &before, err, sizeof err));
    const rf_ik_solver_api *api = &rf_ik_twobone_api;
    rf_ik_solver *solver = rf_ik_solver_new(api, api->create(NULL, err, sizeof err), "twobone");
    rf_rt_contact_stats st;
    rf_xform w0[5], w[5];
    fx_world(tgt, r.out, 0, w0);
    assert_true(rf_retarget_contacts(r.rt, r.out, solver, &st, err, sizeof err));
    assert_true(rf_retarget_measure(r.rt, r.out, start, &after, err, sizeof err));
    print_message("one-bone legs: skate %.4f -> %.4f leg/s\n", before.skate_target,
                  after.skate_target);
    assert_true(before.skate_target > 0.05);
    assert_true(after.skate_target < 0.5 * before.skate_target);
    for (uint32_t f = 0; f < 30; f++) { /* the hips never turn; the legs keep their length */
        fx_world(tgt, r.out, f, w);
        assert_true(rf_quat_angle(w[0].r, w0[0].r) < 1e-9);
        assert_true(fabs(rf_v3_dist(w[1].t, rf_xform_point(w[1], rf_v3(0, -1.0, 0))) - 1.0) < 1e-6);
    }
    rf_ik_solver_free(solver);
    run_free(&r);
    rf_mapping_free(m), rf_animation_free(clip), rf_skeleton_free(src), rf_skeleton_free(tgt);
}

/* A one-bone leg mapped to a source leg of three joints points where the whole source leg
 * reaches (hip to ankle), not along the thigh: with the knee bending under a walking body, the
 * thigh's own direction swings 20 to 40 degrees off the line to the planted ankle, and a rigid
 * leg copying it landed its foot where the source's foot never was (the animalia cat's feet
 * skated 0.15 leg/s under the CMU walk; 0.065 following the reach, the source's 0.068). */
static void one_bone_leg_follows_the_reach(void **state)
{
    (void)state;
    rf_skeleton *src = biped(1, 0.5, 0.45), *tgt = one_bone_legs(3);
    rf_animation *clip = planted_walk(src);
    rf_mapping *m = fx_mapping(3, 1);
    fx_map(m, 0, 0, 0, 1, 0, 0), fx_map(m, 1, 0, 1, 1, 0, 0), fx_map(m, 2, 0, 4, 1, 0, 0);
    rf_retarget_options o = opts();
    run r = do_run(src, clip, tgt, m, &o);
    double thigh_off = 0;
    for (uint32_t f = 0; f < 30; f++) {
        rf_xform ws[9], wt[3];
        fx_world(src, clip, f, ws);
        fx_world(tgt, r.out, f, wt);
        for (int side = 0; side < 2; side++) {
            uint32_t t = side ? 2 : 1, hip = side ? 4 : 1;
            rf_vec3 leg = rf_v3_sub(rf_xform_point(wt[t], rf_v3(0, -1.0, 0)), wt[t].t);
            rf_vec3 reach = rf_v3_sub(ws[hip + 2].t, ws[hip].t);
            assert_true(fx_angle(leg, reach) < 1e-3);
            thigh_off = fmax(thigh_off, fx_angle(leg, rf_v3_sub(ws[hip + 1].t, ws[hip].t)));
        }
    }
    assert_true(thigh_off > 10); /* the thigh alone would have pointed elsewhere */
    run_free(&r);
    rf_mapping_free(m), rf_animation_free(clip), rf_skeleton_free(src), rf_skeleton_free(tgt);
}

/* The lowest point over the clip's frames of a mesh whose every vertex one joint of s carries
 * wholly (a rigid part), posed by a. */
static double lowest_rigid(const rf_skeleton *s, const rf_animation *a, const rf_mesh *m)
{
    rf_xform rest[5], w[5];
    double low = INFINITY;
    for (uint32_t j = 0; j < s->joint_count; j++) {
        int32_t p = s->joints[j].parent;
        rest[j] = p < 0 ? s->joints[j].rest : rf_xform_mul(rest[p], s->joints[j].rest);
    }
    for (uint32_t f = 0; f < a->frame_count; f++) {
        fx_world(s, a, f, w);
        for (uint32_t v = 0; v < m->vertex_count; v++) {
            const float *p = m->positions + (size_t)v * 3;
            uint16_t j = m->skin_joints[(size_t)v * 4];
            rf_vec3 local = rf_xform_point(rf_xform_invert(rest[j]), rf_v3(p[0], p[1], p[2]));
            low = fmin(low, rf_xform_point(w[j], local).y);
        }
    }
    return low;
}

/* A body on one-bone legs (the animalia cat's) is raised where it would stand lower than its
 * source: the human crouches over its planted feet, its hips 0.15 lower at the end, and legs
 * that cannot bend followed the hips 0.16 into the floor, for no pass lifted them (the contact
 * pass only turns such a leg; the hold only lowered). The mesh: a box on each leg, its foot at
 * the rest floor y = 0, and one on the hips. */
static void rigid_legs_kept_out_of_the_floor(void **state)
{
    (void)state;
    rf_skeleton *src = biped(1, 0.5, 0.45), *tgt = one_bone_legs(5);
    rf_animation *clip = fx_rest_clip(src, 30, 30);
    for (uint32_t f = 0; f < 30; f++) {
        double y = 0.95 - 0.15 * f / 29.0;
        rf_animation_set_translation(clip, f, 0, rf_v3(0, y, 0));
        plant_leg(clip, f, 1, rf_v3(0.1, y, 0), rf_v3(0.1, 0.05, 0), 0.5, 0.45);
        plant_leg(clip, f, 4, rf_v3(-0.1, y, 0), rf_v3(-0.1, 0.05, 0), 0.5, 0.45);
    }
    clip->channels[0] |= RF_CHANNEL_TRANSLATION;
    rf_mapping *m = fx_mapping(5, 1);
    uint32_t from[5] = {0, 1, 4, 7, 8};
    for (uint32_t j = 0; j < 5; j++)
        fx_map(m, j, 0, from[j], 1, 0, 0);
    rf_retarget_options o = opts();
    run r = do_run(src, clip, tgt, m, &o);
    rf_mesh *mesh = boxes_mesh(3);
    add_box_at(mesh, 0, 0.05f, 0, 1, 1);  /* the left leg, x 0.05 .. 1.05 */
    add_box_at(mesh, 1, -1.05f, 0, 2, 2); /* the right leg */
    add_box_at(mesh, 2, -0.5f, 1, 0, 0);  /* the hips, over the legs */
    char err[256] = "";
    uint32_t lowered, raised;
    double deepest;
    assert_true(rf_retarget_mesh_floor(r.rt, r.out, mesh, NULL, err, sizeof err));
    double before = lowest_rigid(tgt, r.out, mesh);
    assert_true(
        rf_retarget_mesh_hold(r.rt, r.out, mesh, &lowered, &deepest, &raised, err, sizeof err));
    double after = lowest_rigid(tgt, r.out, mesh);
    print_message("rigid legs: lowest %.4f -> %.4f, raised in %u of 30 frames\n", before, after,
                  raised);
    assert_true(before < -0.05); /* sunk without the rise */
    assert_true(raised > 0);
    assert_true(after > -0.01);
    rf_mesh_free(mesh);
    run_free(&r);
    rf_mapping_free(m), rf_animation_free(clip), rf_skeleton_free(src), rf_skeleton_free(tgt);
}

static void bad_inputs_refused(void **state)
{
    (void)state;
    rf_skeleton *src = arm_tpose(), *tgt = arm_apose();
    rf_animation *clip = arm_clip(src);
    rf_mapping *empty = fx_mapping(8, 1), *wrong = fx_mapping(3, 1), *far = fx_mapping(8, 1);
    fx_map(far, 1, 0, 17, 1, 0, 0);
    rf_rt_source s = {src, clip};
    char err[256];
    assert_null(rf_retarget_new(&s, 1, tgt, empty, NULL, err, sizeof err));
    assert_non_null(strstr(err, "maps no target joint"));
    assert_null(rf_retarget_new(&s, 1, tgt, wrong, NULL, err, sizeof err));
    assert_non_null(strstr(err, "3 entries"));
    assert_null(rf_retarget_new(&s, 1, tgt, far, NULL, err, sizeof err));
    assert_non_null(strstr(err, "joint 17"));
    /* a parent after its child: both named, the name from the file escaped */
    free(tgt->joints[2].name), tgt->joints[2].name = strdup("l\x1b]0;x\x07");
    tgt->joints[2].parent = 3;
    assert_null(rf_retarget_new(&s, 1, tgt, far, NULL, err, sizeof err));
    assert_string_equal(err, "the target skeleton: joint 2 'l\\x1b]0;x\\x07' has parent 3 'h': "
                             "expected parents before children");
    tgt->joints[2].parent = 1;
    rf_mapping_free(empty), rf_mapping_free(wrong), rf_mapping_free(far);
    rf_animation_free(clip), rf_skeleton_free(src), rf_skeleton_free(tgt);
}

/* A clip too large for the memory left is refused before it is allocated, with the figures:
 * 200,000 joints x 2,752 frames x 7 floats x 2 = 30.8 GB (by hand). */
static void huge_clip_refused(void **state)
{
    (void)state;
    char err[512] = "";
    assert_true(rf_rt_output_fits(200000, 2752, false, 0, err, sizeof err));
    assert_true(rf_rt_output_fits(200000, 2752, true, 31000000000u, err, sizeof err));
    assert_false(rf_rt_output_fits(200000, 2752, true, 16000000000u, err, sizeof err));
    assert_non_null(strstr(err, "200000 joints x 2752 frames, about 30.8 GB"));
    assert_non_null(strstr(err, "16.0 GB of memory is left"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(tpose_drives_apose),
        cmocka_unit_test(chain3_drives_chain5),
        cmocka_unit_test(chain5_drives_chain3),
        cmocka_unit_test(unmapped_leaf_keeps_rest),
        cmocka_unit_test(delay_equals_shift),
        cmocka_unit_test(reverse_inverts),
        cmocka_unit_test(weights_blend_two_sources),
        cmocka_unit_test(root_scaled_by_hip_height),
        cmocka_unit_test(target_stays_on_its_floor),
        cmocka_unit_test(centerline_turns_kept_in_own_range),
        cmocka_unit_test(half_turn_kept_under_own_range),
        cmocka_unit_test(turns_cut_about_their_own_axis),
        cmocka_unit_test(source_posed_two_at_once),
        cmocka_unit_test(resampling_slerps),
        cmocka_unit_test(frame_range),
        cmocka_unit_test(identity_returns_the_clip),
        cmocka_unit_test(opposite_facing_keeps_its_facing),
        cmocka_unit_test(stated_forward_against_the_body_gives_way),
        cmocka_unit_test(mirror_drives_second_pair),
        cmocka_unit_test(phase_legs_leave_leg_length),
        cmocka_unit_test(phase_feet_down_by_own_motion),
        cmocka_unit_test(degenerate_rest_uses_a_frame),
        cmocka_unit_test(measure_by_hand),
        cmocka_unit_test(weighted_quantile),
        cmocka_unit_test(mesh_part_torn),
        cmocka_unit_test(mesh_volume),
        cmocka_unit_test(mesh_seam_torn),
        cmocka_unit_test(measure_report_json),
        cmocka_unit_test(contact_pass_pins_feet),
        cmocka_unit_test(contact_pass_pins_bone_tips),
        cmocka_unit_test(contact_pass_aims_one_bone_legs),
        cmocka_unit_test(one_bone_leg_follows_the_reach),
        cmocka_unit_test(touching_surfaces_are_no_seam),
        cmocka_unit_test(rigid_legs_kept_out_of_the_floor),
        cmocka_unit_test(top_joint_keeps_level),
        cmocka_unit_test(level_keeps_turn_limits_tilt),
        cmocka_unit_test(bad_inputs_refused),
        cmocka_unit_test(huge_clip_refused),
        cmocka_unit_test(still_source_root_drives_nothing),
        cmocka_unit_test(mesh_floor_without_number),
        cmocka_unit_test(lying_rest_keeps_arms),
        cmocka_unit_test(wing_swings_whole),
        cmocka_unit_test(wing_held_from_one_and_a_half),
        cmocka_unit_test(trunk_standing_body_eases_lean),
    };
    return cmocka_run_group_tests_name("retarget", tests, NULL, NULL);
}
