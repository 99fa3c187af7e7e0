/* The retarget's mesh passes when memory runs out: the floor (rf_retarget_mesh_floor), the hold
 * in the source's jumps (rf_retarget_mesh_hold) and the last clearing (rf_retarget_mesh_clear),
 * run in the node's order on a fresh plan and clip with their k-th allocation failing, for every
 * k until they need no more. Each run either stops at a pass saying "out of memory" or gives the
 * clip the run with memory to spare gives, to the bit: a failed allocation is never taken for a
 * mesh that cannot be used, nor for "no limb set aside" or "nothing to lower", which would leave
 * the character floating or sunk without a word. The retarget node fails on such a pass
 * (plugins/retarget/plugin.c); before, it logged the message as an info line and wrote the clip.
 * Two targets: a biped whose legs are driven (the floor from the median frame, then the hold) and
 * a body without legs (hips, spine, head), stood on its mesh frame by frame. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "retarget.h"
#include "rt-fixtures.h"

/* allocations of this program and of the retarget code linked into it fail on demand */
#include "../alloc-fail.h"

#define X rf_v3(1, 0, 0)

/* A biped of 9 joints (hips, left and right thigh, knee, ankle with a toe tip, spine, head),
 * hips 1 over the floor; `legs` false keeps hips, spine and head only (3 joints). */
static rf_skeleton *body(bool legs)
{
    rf_skeleton *s = rf_skeleton_new(legs ? 9 : 3);
    fx_joint(s, 0, "hips", -1, rf_v3(0, 1, 0), rf_quat_identity());
    fx_joint(s, 1, "spine", 0, rf_v3(0, 0.1, 0), rf_quat_identity());
    fx_joint(s, 2, "head", 1, rf_v3(0, 0.5, 0), rf_quat_identity());
    fx_end_site(s, 2, rf_v3(0, 0.2, 0));
    for (uint32_t k = 0; legs && k < 2; k++) {
        uint32_t j = 3 + 3 * k;
        double x = k ? -0.1 : 0.1;
        fx_joint(s, j, k ? "rthigh" : "lthigh", 0, rf_v3(x, 0, 0), rf_quat_identity());
        fx_joint(s, j + 1, k ? "rknee" : "lknee", (int32_t)j, rf_v3(0, -0.5, 0),
                 rf_quat_identity());
        fx_joint(s, j + 2, k ? "rankle" : "lankle", (int32_t)j + 1, rf_v3(0, -0.45, 0),
                 rf_quat_identity());
        fx_end_site(s, j + 2, rf_v3(0, -0.05, 0.15));
    }
    return s;
}

/* Adds an axis-aligned box from lo to hi, every corner carried by joint j. */
static void add_box(rf_mesh *m, uint16_t j, rf_vec3 lo, rf_vec3 hi)
{
    static const uint32_t tri[12][3] = {{0, 1, 2}, {0, 2, 3}, {4, 6, 5}, {4, 7, 6},
                                        {0, 4, 5}, {0, 5, 1}, {1, 5, 6}, {1, 6, 2},
                                        {2, 6, 7}, {2, 7, 3}, {3, 7, 4}, {3, 4, 0}};
    static const int corner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    uint32_t base = m->vertex_count;
    for (uint32_t i = 0; i < 8; i++) {
        float *p = m->positions + (size_t)(base + i) * 3;
        p[0] = (float)(corner[i % 4][0] ? hi.x : lo.x);
        p[1] = (float)(i < 4 ? lo.y : hi.y);
        p[2] = (float)(corner[i % 4][1] ? hi.z : lo.z);
        m->skin_joints[(base + i) * 4] = j;
        m->skin_weights[(base + i) * 4] = 1;
    }
    for (uint32_t t = 0; t < 12; t++)
        for (uint32_t k = 0; k < 3; k++)
            m->triangles[(m->triangle_count + t) * 3 + k] = base + tri[t][k];
    m->vertex_count += 8, m->triangle_count += 12;
}

/* A box around each bone of body(legs), standing on y = 0; a biped's soles reach 0.08 under
 * its skeleton's, so its floor pass has a clip to move. */
static rf_mesh *body_mesh(bool legs)
{
    rf_mesh *m = calloc(1, sizeof *m);
    m->positions = calloc(9 * 8 * 3, sizeof *m->positions);
    m->skin_joints = calloc(9 * 8 * 4, sizeof *m->skin_joints);
    m->skin_weights = calloc(9 * 8 * 4, sizeof *m->skin_weights);
    m->triangles = calloc(9 * 12 * 3, sizeof *m->triangles);
    add_box(m, 0, rf_v3(-0.15, legs ? 0.95 : 0, -0.1), rf_v3(0.15, 1.1, 0.1));
    add_box(m, 1, rf_v3(-0.15, 1.1, -0.1), rf_v3(0.15, 1.6, 0.1));
    add_box(m, 2, rf_v3(-0.1, 1.6, -0.1), rf_v3(0.1, 1.8, 0.1));
    for (uint32_t k = 0; legs && k < 2; k++) {
        double x = k ? -0.1 : 0.1;
        uint16_t j = (uint16_t)(3 + 3 * k);
        add_box(m, j, rf_v3(x - 0.05, 0.5, -0.05), rf_v3(x + 0.05, 0.95, 0.05));
        add_box(m, j + 1, rf_v3(x - 0.05, 0.05, -0.05), rf_v3(x + 0.05, 0.5, 0.05));
        add_box(m, j + 2, rf_v3(x - 0.05, -0.08, -0.05), rf_v3(x + 0.05, 0.05, 0.15));
    }
    return m;
}

/* The source: the legged body jumping (hips up to 0.3 over their rest, legs tucked) and leaning
 * forward in 30 frames, so every pass has something to move. */
static rf_animation *jump_clip(const rf_skeleton *s)
{
    rf_animation *a = fx_rest_clip(s, 30, 30);
    for (uint32_t f = 0; f < 30; f++) {
        double up = f >= 10 && f < 20 ? 0.3 * sin(RF_PI * (f - 10) / 10.0) : 0;
        rf_animation_set_translation(a, f, 0, rf_v3(0, 1 + up, 0.02 * f));
        rf_animation_set_rotation(a, f, 1, fx_rot(X, f));
        for (uint32_t j = 3; j < 9; j += 3) {
            rf_animation_set_rotation(a, f, j, fx_rot(X, -120 * up));
            rf_animation_set_rotation(a, f, j + 1, fx_rot(X, 200 * up));
        }
    }
    a->channels[0] |= RF_CHANNEL_TRANSLATION;
    return a;
}

/* The three passes in the node's order; false at the first that fails, its message in err. */
static bool mesh_passes(rf_retarget *rt, rf_animation *out, const rf_mesh *mesh, char *err,
                        size_t size)
{
    uint32_t lowered, raised;
    double deepest;
    return rf_retarget_mesh_floor(rt, out, mesh, NULL, err, size) &&
           rf_retarget_mesh_hold(rt, out, mesh, &lowered, &deepest, &raised, err, size) &&
           rf_retarget_mesh_clear(rt, out, mesh, NULL, err, size);
}

/* Runs the plan and the passes with allocation number `fail` failing (-1: none) in the passes
 * (-2: the passes not run). Returns the clip, or NULL when a pass failed (its message checked to
 * say so). */
static rf_animation *passes_failing(const rf_skeleton *src, const rf_animation *clip,
                                    const rf_skeleton *tgt, const rf_mapping *m,
                                    const rf_mesh *mesh, long fail)
{
    char err[256] = "";
    rf_retarget_options o;
    rf_retarget_options_default(&o);
    rf_rt_source s = {src, clip};
    calls = 0, fail_at = -1;
    rf_retarget *rt = rf_retarget_new(&s, 1, tgt, m, &o, err, sizeof err);
    assert_non_null(rt);
    rf_animation *out = rf_retarget_clip(rt, NULL, NULL, err, sizeof err);
    assert_non_null(out);
    calls = 0, fail_at = fail;
    bool ok = fail == -2 || mesh_passes(rt, out, mesh, err, sizeof err);
    fail_at = -1;
    rf_retarget_free(rt);
    if (!ok) {
        if (!strstr(err, "out of memory"))
            fail_msg("allocation %ld failing: \"%s\", not out of memory", fail, err);
        rf_animation_free(out);
        return NULL;
    }
    return out;
}

static void sweep(bool legs)
{
    rf_skeleton *src = body(true), *tgt = body(legs);
    rf_animation *clip = jump_clip(src);
    rf_mapping *m = fx_mapping(tgt->joint_count, 1);
    fx_map_same(m, tgt->joint_count);
    rf_mesh *mesh = body_mesh(legs);
    rf_animation *want = passes_failing(src, clip, tgt, m, mesh, -1);
    assert_non_null(want);
    long needed = calls, failed = 0;
    print_message("# %s: the passes make %ld allocations\n", legs ? "biped" : "legless", needed);
    assert_true(needed > 0);
    size_t n = (size_t)want->frame_count * want->joint_count;
    rf_animation *plain = passes_failing(src, clip, tgt, m, mesh, -2);
    /* the passes have something to do: a sweep over passes that change nothing proves nothing */
    assert_true(memcmp(plain->translations, want->translations, n * 3 * sizeof(float)));
    rf_animation_free(plain);
    for (long k = 0; k < needed; k++) {
        rf_animation *got = passes_failing(src, clip, tgt, m, mesh, k);
        if (!got) {
            failed++;
            continue;
        }
        if (memcmp(got->translations, want->translations, n * 3 * sizeof(float)) ||
            memcmp(got->rotations, want->rotations, n * 4 * sizeof(float)))
            fail_msg("allocation %ld failing: the passes said nothing and gave another clip", k);
        rf_animation_free(got);
    }
    print_message("# %ld of them failing stopped the passes with \"out of memory\"\n", failed);
    assert_true(failed > 0);
    rf_animation_free(want);
    rf_mesh_free(mesh);
    rf_mapping_free(m), rf_animation_free(clip), rf_skeleton_free(src), rf_skeleton_free(tgt);
}

static void biped_passes_fail_or_match(void **state)
{
    (void)state;
    sweep(true);
}

static void legless_passes_fail_or_match(void **state)
{
    (void)state;
    sweep(false);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(biped_passes_fail_or_match),
        cmocka_unit_test(legless_passes_fail_or_match),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
