/* A BVH clip out as GLB (libbvh reads it, librfgltf writes it), checked by the Khronos
 * glTF-Validator and read back through Assimp (librfassimp). cmu_01_01.bvh per the data README:
 * 31 joints, 2752 frames at 120 fps. Skips with a message without $RF_DATA_DIR. */
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
#include "rigflow/bvh.h"
#include "rigflow/gltf-write.h"

/* Angle between two rotations, accurate near zero (2 acos of a dot product near 1 is not). */
static double rf_rot_diff(rf_quat a, rf_quat b)
{
    rf_quat d = rf_quat_mul(rf_quat_conj(rf_quat_normalize(a)), rf_quat_normalize(b));
    return 2.0 * atan2(sqrt(d.x * d.x + d.y * d.y + d.z * d.z), fabs(d.w));
}

static void test_bvh_to_glb(void **state)
{
    (void)state;
    const char *data = getenv("RF_DATA_DIR");
    char in[4096], out[] = "/tmp/rf-test-XXXXXX.glb", err[1024];
    snprintf(in, sizeof in, "%s/bvh/cmu_01_01.bvh", data ? data : "");
    if (!data || access(in, R_OK) != 0) {
        print_message("RF_DATA_DIR/bvh/cmu_01_01.bvh not found (../shared/data): skipped\n");
        skip();
    }
    rf_skeleton *s = NULL;
    rf_animation *a = NULL;
    assert_true(rf_bvh_read_file(in, NULL, &s, &a, err, sizeof err));
    assert_int_equal(s->joint_count, 31);
    assert_int_equal(a->frame_count, 2752);
    int fd = mkstemps(out, 4);
    assert_true(fd >= 0);
    close(fd);
    bool ok = rf_gltf_write_file(out, NULL, s, a, NULL, NULL, err, sizeof err);
    if (!ok)
        print_error("%s\n", err);
    assert_true(ok);
    rf_gltf_check_valid(out);

    rf_ai_result r;
    ok = rf_ai_import(out, NULL, &r, NULL, NULL, err, sizeof err);
    if (!ok)
        print_error("%s\n", err);
    assert_true(ok);
    assert_int_equal(r.skeleton->joint_count, s->joint_count);
    assert_int_equal(r.animation->frame_count, a->frame_count);
    assert_true(fabs(r.animation->fps - a->fps) < 1e-5 * a->fps); /* times went through float32 */
    rf_xform *wa = calloc(s->joint_count, sizeof *wa), *wb = calloc(s->joint_count, sizeof *wb);
    rf_skeleton_world_rest(s, wa);
    rf_skeleton_world_rest(r.skeleton, wb);
    double worst_pos = 0, worst_rot = 0, worst_root = 0;
    for (uint32_t j = 0; j < s->joint_count; j++) {
        int32_t k = rf_skeleton_find(r.skeleton, s->joints[j].name);
        assert_int_equal(k, (int32_t)j);
        assert_int_equal(r.skeleton->joints[j].parent, s->joints[j].parent);
        worst_pos = fmax(worst_pos, rf_v3_dist(wa[j].t, wb[j].t));
        for (uint32_t f = 0; f < a->frame_count; f++)
            worst_rot = fmax(worst_rot, rf_rot_diff(rf_animation_rotation(a, f, j),
                                                    rf_animation_rotation(r.animation, f, j)));
    }
    for (uint32_t f = 0; f < a->frame_count; f++)
        worst_root = fmax(worst_root, rf_v3_dist(rf_animation_translation(a, f, 0),
                                                 rf_animation_translation(r.animation, f, 0)));
    print_message("worst: rest position %g, rotation %g rad, root translation %g\n", worst_pos,
                  worst_rot, worst_root);
    assert_true(worst_pos < 1e-4);
    assert_true(worst_rot < 1e-4);
    assert_true(worst_root < 1e-3); /* float32 of values up to tens of units */
    free(wa), free(wb);
    rf_ai_result_clear(&r);
    rf_skeleton_free(s);
    rf_animation_free(a);
    unlink(out);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_bvh_to_glb)};
    return rf_gltf_exit_status(cmocka_run_group_tests_name("bvh-gltf", tests, NULL, NULL));
}
