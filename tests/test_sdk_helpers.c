/* The SDK's header-only helpers: text escaping (rigflow/text.h), deep copies of the data
 * model (rigflow/model-copy.h), prefaulting (rigflow/prefault.h) and the memory left
 * (rigflow/memory.h). Expected strings and figures are written out by hand from the rules. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <rigflow/memory.h>
#include <rigflow/model-copy.h>
#include <rigflow/prefault.h>
#include <rigflow/text.h>

/* rf_text_utf8_len on each case: the length and code point worked out by hand from RFC 3629. */
static void utf8_decoding(void **state)
{
    (void)state;
    uint32_t cp = 0;
    assert_int_equal(rf_text_utf8_len((const unsigned char *)"A", &cp), 1);
    assert_int_equal(cp, 0x41);
    assert_int_equal(rf_text_utf8_len((const unsigned char *)"\x07", &cp),
                     1); /* controls are UTF-8 */
    assert_int_equal(rf_text_utf8_len((const unsigned char *)"\xc3\xa9", &cp), 2);
    assert_int_equal(cp, 0xe9);
    assert_int_equal(rf_text_utf8_len((const unsigned char *)"\xe2\x80\xa8", &cp), 3);
    assert_int_equal(cp, 0x2028);
    assert_int_equal(rf_text_utf8_len((const unsigned char *)"\xf0\x9f\x90\x8d", &cp), 4);
    assert_int_equal(cp, 0x1f40d);
    assert_int_equal(rf_text_utf8_len((const unsigned char *)"", NULL), 0);
    assert_int_equal(rf_text_utf8_len((const unsigned char *)"\xe9t\xe9", NULL), 0); /* Latin-1 */
    assert_int_equal(rf_text_utf8_len((const unsigned char *)"\xc0\xaf", NULL), 0);  /* overlong */
    assert_int_equal(rf_text_utf8_len((const unsigned char *)"\xe0\x80\xaf", NULL), 0);
    assert_int_equal(rf_text_utf8_len((const unsigned char *)"\xed\xa0\x80", NULL), 0); /* D800 */
    assert_int_equal(rf_text_utf8_len((const unsigned char *)"\xf4\x90\x80\x80", NULL), 0);
    assert_int_equal(rf_text_utf8_len((const unsigned char *)"\xe2\x80", NULL), 0); /* cut short */
    assert_int_equal(rf_text_utf8_len((const unsigned char *)"\x80", NULL), 0);
}

static void escaped_is(const char *in, const char *want, uint32_t flags)
{
    char out[128];
    size_t n = rf_text_escape(in, out, sizeof out, flags);
    assert_string_equal(out, want);
    assert_int_equal(n, strlen(want));
}

static void controls_are_escaped(void **state)
{
    (void)state;
    escaped_is("Hips", "Hips", 0);
    escaped_is("\x1b]0;owned\x07", "\\x1b]0;owned\\x07", 0); /* OSC: set the title */
    escaped_is("a\x1b[31mred", "a\\x1b[31mred", 0);          /* CSI: colours */
    escaped_is("x\x7fy", "x\\x7fy", 0);                      /* DEL */
    escaped_is("line\nnext\tcol", "line\\x0anext\\x09col", 0);
    escaped_is("line\nnext\tcol", "line\nnext\tcol", RF_TEXT_KEEP_LINES);
    escaped_is("\r", "\\x0d", RF_TEXT_KEEP_LINES);
    escaped_is(NULL, "", 0);
}

static void c1_and_invalid_utf8_are_escaped(void **state)
{
    (void)state;
    escaped_is("\xc2\x9b"
               "31m",
               "\\xc2\\x9b31m", 0); /* U+009B, the 8-bit CSI, in UTF-8 */
    escaped_is("\x9b"
               "31m",
               "\\x9b31m", 0);                                 /* a raw 8-bit CSI byte */
    escaped_is("\xc0\xaf", "\\xc0\\xaf", 0);                   /* overlong '/' */
    escaped_is("\xed\xa0\x80", "\\xed\\xa0\\x80", 0);          /* a surrogate */
    escaped_is("\xf4\x90\x80\x80", "\\xf4\\x90\\x80\\x80", 0); /* beyond U+10FFFF */
    escaped_is("\xe9\xaa", "\\xe9\\xaa", 0);                   /* cut short */
}

static void printable_utf8_is_kept(void **state)
{
    (void)state;
    escaped_is("Oberschenkel_\xc3\xa4", "Oberschenkel_\xc3\xa4", 0); /* a-umlaut */
    escaped_is("\xe9\xaa\xa8", "\xe9\xaa\xa8", 0);                   /* a CJK character */
    escaped_is("\xc2\xa0nbsp", "\xc2\xa0nbsp", 0);                   /* U+00A0, just past C1 */
    escaped_is("\xf0\x9f\xa6\xb4", "\xf0\x9f\xa6\xb4", 0);           /* U+1F9B4 */
}

static void escape_truncates_between_characters(void **state)
{
    (void)state;
    char out[6];
    assert_int_equal(rf_text_escape("ab\x1b"
                                    "cd",
                                    out, sizeof out, 0),
                     8);
    assert_string_equal(out, "ab"); /* "\x1b" does not fit whole: nothing of it is written */
    assert_int_equal(rf_text_escape("abc", out, 0, 0), 3);
    char label[16];
    rf_skeleton *s = rf_skeleton_new(2);
    s->joints[0].name = rf_strdup("\x1b[2J");
    assert_string_equal(rf_joint_label(s, 0, label, sizeof label), "\\x1b[2J");
    assert_string_equal(rf_joint_label(s, 1, label, sizeof label), "#1");
    assert_string_equal(rf_joint_label(NULL, 7, label, sizeof label), "#7");
    rf_skeleton_free(s);
}

static rf_skeleton *two_joints(void)
{
    rf_skeleton *s = rf_skeleton_new(2);
    s->joints[0].name = rf_strdup("root");
    s->joints[1].name = rf_strdup("tip");
    s->joints[1].parent = 0;
    s->joints[1].rest.t = rf_v3(0, 2, 0);
    s->name = rf_strdup("two.bvh");
    s->bind = calloc(2, sizeof *s->bind);
    s->bind[1] = s->joints[1].rest;
    s->rest_source = RF_REST_BIND;
    return s;
}

static void shown_is(double v, int decimals, const char *fmt, const char *want)
{
    char out[64];
    snprintf(out, sizeof out, fmt, rf_text_shown_zero(v, decimals));
    assert_string_equal(out, want);
}

/* rf_text_shown_zero: what shows as zero prints unsigned, any other value as printf has it. */
static void shown_zero_has_no_sign(void **state)
{
    (void)state;
    shown_is(-0.0, 2, "%.2f", "0.00");
    shown_is(-2.3e-9, 2, "%.2f", "0.00");
    shown_is(-0.0049, 2, "%.2f", "0.00");
    shown_is(-0.006, 2, "%.2f", "-0.01");
    shown_is(-0.04, 1, "%+.1f", "+0.0");
    shown_is(-0.06, 1, "%+.1f", "-0.1");
    shown_is(0.0, 2, "%.2f", "0.00");
    shown_is(1.7, 1, "%+.1f", "+1.7");
    shown_is(-1e300, 2, "%.0e", "-1e+300"); /* 300 digits before the point: kept */
}

static void skeleton_copy_is_deep(void **state)
{
    (void)state;
    rf_skeleton *s = two_joints();
    rf_skeleton *c = rf_skeleton_copy(s);
    assert_non_null(c);
    assert_int_equal(c->joint_count, 2);
    assert_string_equal(c->joints[1].name, "tip");
    assert_ptr_not_equal(c->joints[1].name, s->joints[1].name);
    assert_int_equal(c->joints[1].parent, 0);
    assert_true(c->joints[1].rest.t.y == 2);
    assert_string_equal(c->name, "two.bvh");
    assert_non_null(c->bind);
    assert_ptr_not_equal(c->bind, s->bind);
    assert_true(c->bind[1].t.y == 2);
    assert_int_equal(c->rest_source, RF_REST_BIND);
    /* A 1.0 skeleton (no bind fields): the copy is of this build, its bind absent. */
    s->size = RF_SKELETON_SIZE_1_0;
    rf_skeleton *old = rf_skeleton_copy(s);
    assert_int_equal(old->size, sizeof(rf_skeleton));
    assert_null(old->bind);
    assert_int_equal(old->rest_source, 0);
    s->size = sizeof *s;
    rf_skeleton_free(old), rf_skeleton_free(c), rf_skeleton_free(s);
    assert_null(rf_skeleton_copy(NULL));
}

static void animation_mesh_mapping_copies(void **state)
{
    (void)state;
    rf_animation *a = rf_animation_new(2, 3, 30);
    rf_animation_set_rotation(a, 2, 1, rf_quat_make(0, 0, 1, 0));
    a->name = rf_strdup("walk");
    a->channels[1] = RF_CHANNEL_ROTATION;
    rf_animation *ac = rf_animation_copy(a);
    assert_int_equal(ac->frame_count, 3);
    assert_true(ac->fps == 30);
    assert_true(rf_animation_rotation(ac, 2, 1).z == 1);
    assert_string_equal(ac->name, "walk");
    assert_int_equal(ac->channels[1], RF_CHANNEL_ROTATION);
    rf_animation_free(ac), rf_animation_free(a);

    rf_mesh *m = rf_mesh_new();
    m->vertex_count = 3, m->triangle_count = 1;
    m->positions = calloc(9, sizeof(float));
    m->positions[4] = 5;
    m->triangles = calloc(3, sizeof(uint32_t));
    m->triangles[2] = 2;
    m->part_count = 1;
    m->parts = calloc(1, sizeof *m->parts);
    m->parts[0].name = rf_strdup("body");
    m->parts[0].vertex_count = 3;
    m->uv_set_count = 1;
    m->uvs[0] = calloc(6, sizeof(float));
    m->uvs[0][5] = 0.5f;
    m->part_material = calloc(1, sizeof(int32_t));
    m->material_count = 1;
    m->materials = calloc(1, sizeof *m->materials);
    m->materials[0] = rf_material_new();
    m->materials[0]->name = rf_strdup("skin");
    m->materials[0]->roughness = 0.25f;
    m->materials[0]->base_color_texture.image = 0;
    m->image_count = 1;
    m->images = calloc(1, sizeof *m->images);
    m->images[0] = rf_image_new("skin.png", "image/png", "\x89PNG", 4);
    m->morph_target_count = 1;
    m->morph_targets = calloc(1, sizeof *m->morph_targets);
    m->morph_targets[0] = rf_morph_target_new("smile", 3);
    m->morph_targets[0]->positions[8] = 2;
    rf_mesh *mc = rf_mesh_copy(m);
    assert_true(mc->uvs[0][5] == 0.5f);
    assert_ptr_not_equal(mc->uvs[0], m->uvs[0]);
    assert_null(mc->uvs[1]);
    assert_int_equal(mc->part_material[0], 0);
    assert_string_equal(mc->materials[0]->name, "skin");
    assert_ptr_not_equal(mc->materials[0]->name, m->materials[0]->name);
    assert_true(mc->materials[0]->roughness == 0.25f);
    assert_int_equal(mc->materials[0]->base_color_texture.image, 0);
    assert_int_equal(mc->images[0]->byte_count, 4);
    assert_memory_equal(mc->images[0]->bytes, "\x89PNG", 4);
    assert_string_equal(mc->images[0]->mime_type, "image/png");
    assert_string_equal(mc->morph_targets[0]->name, "smile");
    assert_true(mc->morph_targets[0]->positions[8] == 2);
    assert_true(mc->positions[4] == 5);
    assert_int_equal(mc->triangles[2], 2);
    assert_null(mc->normals);
    assert_null(mc->skin_joints);
    assert_string_equal(mc->parts[0].name, "body");
    assert_ptr_not_equal(mc->parts[0].name, m->parts[0].name);
    rf_mesh_free(mc), rf_mesh_free(m);

    rf_mapping *p = rf_mapping_new(2, 1);
    p->metric_count = 1;
    p->metric_names = calloc(1, sizeof(char *));
    p->metric_names[0] = rf_strdup("distance");
    p->entries[1].input_count = 1;
    p->entries[1].inputs = calloc(1, sizeof(rf_map_input));
    p->entries[1].inputs[0] = (rf_map_input){0, 1, 1.0f, 0.0f, RF_MAP_REVERSE};
    p->entries[1].metrics = calloc(1, sizeof(double));
    p->entries[1].metrics[0] = 0.25;
    p->entries[1].score = 9;
    p->sides = calloc(2, sizeof(char *));
    p->sides[1] = rf_strdup("left");
    rf_mapping *pc = rf_mapping_copy(p);
    assert_int_equal(pc->entries[1].inputs[0].joint, 1);
    assert_int_equal(pc->entries[1].inputs[0].flags, RF_MAP_REVERSE);
    assert_true(pc->entries[1].metrics[0] == 0.25);
    assert_true(pc->entries[1].score == 9);
    assert_int_equal(pc->entries[0].input_count, 0);
    assert_string_equal(pc->metric_names[0], "distance");
    assert_null(pc->sections);
    assert_null(pc->sides[0]);
    assert_string_equal(pc->sides[1], "left");
    rf_mapping_free(pc), rf_mapping_free(p);
}

/* rf_prefault maps every whole page of a fresh large array (mincore reports them resident, as
 * no write has touched them) and changes no byte already written; an array below
 * RF_PREFAULT_MIN is left alone. Without MADV_POPULATE_WRITE it does nothing: skipped. */
static void prefault_maps_whole_pages(void **state)
{
    (void)state;
#if defined(MADV_POPULATE_WRITE)
    const size_t size = (size_t)4 << 20, page = (size_t)sysconf(_SC_PAGESIZE);
    unsigned char *a = malloc(size); /* glibc maps an array this large afresh */
    assert_non_null(a);
    memcpy(a, "rigflow", 8);
    uintptr_t b = ((uintptr_t)a + page - 1) & ~(uintptr_t)(page - 1);
    uintptr_t e = ((uintptr_t)a + size) & ~(uintptr_t)(page - 1);
    size_t pages = (e - b) / page;
    unsigned char *in = malloc(pages);
    assert_non_null(in);
    assert_int_equal(mincore((void *)b, e - b, in), 0);
    size_t before = 0, after = 0;
    for (size_t i = 0; i < pages; i++)
        before += in[i] & 1;
    rf_prefault(a, size);
    assert_int_equal(mincore((void *)b, e - b, in), 0);
    for (size_t i = 0; i < pages; i++)
        after += in[i] & 1;
    if (before == pages) { /* already mapped (a reused heap): nothing to tell */
        free(in), free(a);
        skip();
    }
    assert_int_equal(after, pages);
    assert_memory_equal(a, "rigflow", 8);
    rf_prefault(NULL, size); /* no array: nothing */
    free(in), free(a);
#else
    skip();
#endif
}

/* A file of made-up /proc or /sys contents under dir. */
static void put(const char *dir, const char *name, const char *text)
{
    char path[2048];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

/* rf_memory_available_at on a made-up Slurm task: MemAvailable 8 000 000 kB (8.192 GB), the job's
 * cgroup limited to 2 GB with 0.5 GB used, its step and task cgroups unlimited ("max"). What is
 * left is the job's 1.5 GB, worked out by hand; reading the task's own cgroup alone said 8.192 GB.
 * The same with the task's cgroup path longer than the line the header reads: the job's limit is
 * still found. */
static void memory_limit_above_own_cgroup(void **state)
{
    (void)state;
    char root[] = "/tmp/rf-memory-XXXXXX", dir[2048], long_name[701];
    assert_non_null(mkdtemp(root));
    const char *dirs[] = {"proc",     "proc/self",       "cg",
                          "cg/job_7", "cg/job_7/step_0", "cg/job_7/step_0/task_0"};
    for (size_t i = 0; i < sizeof dirs / sizeof *dirs; i++) {
        snprintf(dir, sizeof dir, "%s/%s", root, dirs[i]);
        assert_int_equal(mkdir(dir, 0700), 0);
    }
    snprintf(dir, sizeof dir, "%s/proc", root);
    put(dir, "meminfo", "MemTotal:       16000000 kB\nMemAvailable:    8000000 kB\n");
    snprintf(dir, sizeof dir, "%s/cg/job_7", root);
    put(dir, "memory.max", "2000000000\n");
    put(dir, "memory.current", "500000000\n");
    put(dir, "step_0/memory.max", "max\n");
    put(dir, "step_0/memory.current", "400000000\n");
    put(dir, "step_0/task_0/memory.max", "max\n");
    put(dir, "step_0/task_0/memory.current", "300000000\n");
    snprintf(dir, sizeof dir, "%s/proc/self", root);
    put(dir, "cgroup", "4:memory:/elsewhere\n0::/job_7/step_0/task_0\n");
    char proc[2048], cg[2048];
    snprintf(proc, sizeof proc, "%s/proc", root);
    snprintf(cg, sizeof cg, "%s/cg", root);
    uint64_t left = 0;
    assert_true(rf_memory_available_at(proc, cg, &left));
    assert_int_equal(left, 1500000000u);
    memset(long_name, 'a', sizeof long_name - 1);
    long_name[sizeof long_name - 1] = '\0';
    char line[1024];
    snprintf(line, sizeof line, "0::/job_7/%s\n", long_name);
    put(dir, "cgroup", line);
    left = 0;
    assert_true(rf_memory_available_at(proc, cg, &left));
    assert_int_equal(left, 1500000000u);
    /* cgroup v1 (this memory controller's own hierarchy, cg/memory): the job's limit of 3 GB
     * with 1 GB used, the step below it unlimited (v1 says so with a number near 2^63): 2 GB */
    const char *v1[] = {"cg/memory", "cg/memory/job_9", "cg/memory/job_9/step_0"};
    for (size_t i = 0; i < sizeof v1 / sizeof *v1; i++) {
        snprintf(dir, sizeof dir, "%s/%s", root, v1[i]);
        assert_int_equal(mkdir(dir, 0700), 0);
    }
    snprintf(dir, sizeof dir, "%s/cg/memory/job_9", root);
    put(dir, "memory.limit_in_bytes", "3000000000\n");
    put(dir, "memory.usage_in_bytes", "1000000000\n");
    put(dir, "step_0/memory.limit_in_bytes", "9223372036854771712\n");
    put(dir, "step_0/memory.usage_in_bytes", "900000000\n");
    snprintf(dir, sizeof dir, "%s/proc/self", root);
    put(dir, "cgroup", "5:cpu,cpuacct:/job_9\n4:memory:/job_9/step_0\n0::/\n");
    left = 0;
    assert_true(rf_memory_available_at(proc, cg, &left));
    assert_int_equal(left, 2000000000u);
    /* nothing there at all: nothing known, not a limit of 0 */
    assert_false(rf_memory_available_at("/nonexistent/proc", "/nonexistent/cg", &left));
    char cmd[2100];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", root);
    assert_int_equal(system(cmd), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(utf8_decoding),
        cmocka_unit_test(prefault_maps_whole_pages),
        cmocka_unit_test(controls_are_escaped),
        cmocka_unit_test(c1_and_invalid_utf8_are_escaped),
        cmocka_unit_test(printable_utf8_is_kept),
        cmocka_unit_test(escape_truncates_between_characters),
        cmocka_unit_test(shown_zero_has_no_sign),
        cmocka_unit_test(skeleton_copy_is_deep),
        cmocka_unit_test(animation_mesh_mapping_copies),
        cmocka_unit_test(memory_limit_above_own_cgroup),
    };
    return cmocka_run_group_tests_name("sdk helpers", tests, NULL, NULL);
}
