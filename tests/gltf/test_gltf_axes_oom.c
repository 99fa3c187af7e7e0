/* glTF's axes when memory runs out: rf_gw_axes_conform is run with its k-th allocation failing,
 * for every k until it needs no more, on a turned character (two clips and a gap, a mesh with
 * normals, tangents, a morph target and inverse binds). Each failure returns false and the
 * clear frees what was made (leaks show under the sanitizer and valgrind runs); the writer
 * calls it before opening the file, so nothing is half written. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <rigflow/model-copy.h>

#include "../../sdk/formats/gltf/gltf-axes.h"

#include "../alloc-fail.h" /* this program's own allocations fail on demand */

static void every_allocation_fails_once(void **state)
{
    (void)state;
    rf_skeleton *s = rf_skeleton_new(3);
    s->joints[1].parent = 0;
    s->joints[0].name = rf_strdup("hips");
    s->name = rf_strdup("walker");
    s->bind = calloc(3, sizeof *s->bind);
    s->up = rf_v3(0, 0, 1), s->forward = rf_v3(1, 0, 0);
    rf_animation *a = rf_animation_new(3, 4, 30), *b = rf_animation_new(3, 2, 30);
    a->name = rf_strdup("walk");
    rf_mesh *m = rf_mesh_new();
    m->name = rf_strdup("body");
    m->vertex_count = 3, m->triangle_count = 1;
    m->positions = calloc(9, sizeof(float)), m->normals = calloc(9, sizeof(float));
    m->tangents = calloc(12, sizeof(float)), m->triangles = calloc(3, sizeof(uint32_t));
    m->bind_count = 3, m->inverse_bind = calloc(3, sizeof *m->inverse_bind);
    m->morph_target_count = 1, m->morph_targets = calloc(1, sizeof *m->morph_targets);
    m->morph_targets[0] = rf_morph_target_new("smile", 3);
    const rf_animation *clips[3] = {a, NULL, b};
    long failed = 0, k;
    for (k = 0;; k++) {
        calls = 0, fail_at = k;
        rf_gw_axes x;
        bool ok = rf_gw_axes_conform(&x, s, clips, 3, m);
        fail_at = -1;
        if (ok) {
            assert_ptr_not_equal(x.skeleton, s); /* turned: copies were made */
            assert_true(calls <= k);             /* no allocation left to fail */
        }
        failed += !ok;
        rf_gw_axes_clear(&x, 3);
        if (ok)
            break;
    }
    print_message("# %ld allocations, each failing once: refused %ld times\n", k, failed);
    assert_true(k > 10);
    assert_int_equal(failed, k);
    rf_skeleton_free(s), rf_animation_free(a), rf_animation_free(b), rf_mesh_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(every_allocation_fails_once)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
