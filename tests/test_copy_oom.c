/* rigflow/model-copy.h when memory runs out: every allocation of a copy is made to fail in turn
 * (the k-th, for every k until the copy succeeds), and each time the copy must return NULL having
 * freed exactly what it allocated: nothing of the original freed, nothing leaked. The header's
 * functions are inline, so the allocator they call is replaced here by one that counts, fails on
 * demand and knows every block it handed out. */
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#define RF_T_MAX_BLOCKS 4096

static void *rf_t_live[RF_T_MAX_BLOCKS]; /* blocks handed out and not freed */
static size_t rf_t_nlive;
static long rf_t_calls, rf_t_fail_at = -1; /* fail the allocation with this index (-1: none) */
static unsigned rf_t_bad_frees;            /* frees of a block not handed out, or freed twice */

static void *rf_t_track(void *p)
{
    if (p && rf_t_nlive < RF_T_MAX_BLOCKS)
        rf_t_live[rf_t_nlive++] = p;
    return p;
}

static bool rf_t_fail(void)
{
    return rf_t_fail_at >= 0 && rf_t_calls++ == rf_t_fail_at;
}

static void *rf_t_malloc(size_t n)
{
    return rf_t_fail() ? NULL : rf_t_track(malloc(n));
}

static void *rf_t_calloc(size_t n, size_t size)
{
    return rf_t_fail() ? NULL : rf_t_track(calloc(n, size));
}

static void rf_t_free(void *p)
{
    if (!p)
        return;
    for (size_t i = 0; i < rf_t_nlive; i++)
        if (rf_t_live[i] == p) {
            rf_t_live[i] = rf_t_live[--rf_t_nlive];
            free(p);
            return;
        }
    rf_t_bad_frees++; /* not ours to free: leaving it alone keeps the test running */
}

#define malloc rf_t_malloc
#define calloc rf_t_calloc
#define free rf_t_free
#include <rigflow/model-copy.h>
#undef malloc
#undef calloc
#undef free

/* A mesh with a part of every kind a copy duplicates: named parts, UVs, a material, an image and
 * a morph target. */
static rf_mesh *make_mesh(void)
{
    rf_mesh *m = rf_mesh_new();
    m->name = rf_strdup("body");
    m->vertex_count = 3;
    m->triangle_count = 1;
    m->positions = rf_t_calloc(9, sizeof(float));
    m->triangles = rf_t_calloc(3, sizeof(uint32_t));
    m->part_count = 3;
    m->parts = rf_t_calloc(3, sizeof *m->parts);
    m->parts[0].name = rf_strdup("head");
    m->parts[1].name = rf_strdup("torso");
    m->parts[2].name = rf_strdup("tail");
    m->uv_set_count = 1;
    m->uvs[0] = rf_t_calloc(6, sizeof(float));
    m->part_material = rf_t_calloc(3, sizeof(int32_t));
    m->material_count = 1;
    m->materials = rf_t_calloc(1, sizeof *m->materials);
    m->materials[0] = rf_material_new();
    m->materials[0]->name = rf_strdup("skin");
    m->image_count = 1;
    m->images = rf_t_calloc(1, sizeof *m->images);
    m->images[0] = rf_image_new("skin.png", "image/png", "\x89PNG", 4);
    m->morph_target_count = 1;
    m->morph_targets = rf_t_calloc(1, sizeof *m->morph_targets);
    m->morph_targets[0] = rf_morph_target_new("smile", 3);
    return m;
}

static rf_skeleton *make_skeleton(void)
{
    rf_skeleton *s = rf_skeleton_new(3);
    s->name = rf_strdup("fox");
    for (uint32_t j = 0; j < 3; j++) {
        s->joints[j].name = rf_strdup(j == 0 ? "hips" : j == 1 ? "spine" : "head");
        s->joints[j].parent = (int32_t)j - 1;
    }
    s->bind = rf_t_calloc(3, sizeof *s->bind);
    return s;
}

static rf_mapping *make_mapping(void)
{
    rf_mapping *p = rf_mapping_new(2, 1);
    p->metric_count = 1;
    p->metric_names = rf_t_calloc(1, sizeof(char *));
    p->metric_names[0] = rf_strdup("distance");
    for (uint32_t j = 0; j < 2; j++) {
        p->entries[j].input_count = 1;
        p->entries[j].inputs = rf_t_calloc(1, sizeof(rf_map_input));
        p->entries[j].metrics = rf_t_calloc(1, sizeof(double));
    }
    p->sections = rf_t_calloc(2, sizeof(char *));
    p->sections[0] = rf_strdup("spine");
    p->sides = rf_t_calloc(2, sizeof(char *));
    p->sides[1] = rf_strdup("left");
    return p;
}

/* Fails allocation 0, 1, 2... of copy(original) until it succeeds; every failure must leave the
 * original's blocks alone and free all of the copy's. Returns the copy. */
static void *copy_under_oom(void *(*copy)(const void *), const void *original)
{
    size_t before = rf_t_nlive;
    void *c = NULL;
    long k = 0;
    for (; !c && k < 1000; k++) {
        rf_t_calls = 0, rf_t_fail_at = k;
        c = copy(original);
        rf_t_fail_at = -1;
        if (!c) {
            assert_int_equal(rf_t_bad_frees, 0);  /* the original's blocks stay its own */
            assert_int_equal(rf_t_nlive, before); /* and the copy's are all freed */
        }
    }
    assert_non_null(c); /* some k is past the copy's last allocation */
    assert_true(k > 3);
    return c;
}

static void *mesh_copy(const void *m)
{
    return rf_mesh_copy(m);
}
static void *skeleton_copy(const void *s)
{
    return rf_skeleton_copy(s);
}
static void *mapping_copy(const void *p)
{
    return rf_mapping_copy(p);
}

static void copies_fail_cleanly(void **state)
{
    (void)state;
    rf_mesh *m = make_mesh();
    rf_mesh *mc = copy_under_oom(mesh_copy, m);
    assert_string_equal(mc->parts[2].name, "tail");
    rf_mesh_free(mc), rf_mesh_free(m);
    rf_skeleton *s = make_skeleton();
    rf_skeleton *sc = copy_under_oom(skeleton_copy, s);
    assert_string_equal(sc->joints[2].name, "head");
    rf_skeleton_free(sc), rf_skeleton_free(s);
    rf_mapping *p = make_mapping();
    rf_mapping *pc = copy_under_oom(mapping_copy, p);
    assert_string_equal(pc->sides[1], "left");
    rf_mapping_free(pc), rf_mapping_free(p);
    assert_int_equal(rf_t_bad_frees, 0);
    assert_int_equal(rf_t_nlive, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(copies_fail_cleanly),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
