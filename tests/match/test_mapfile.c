/* Mapping files (doc/formats/mapping.md): written and read back unchanged, one entry per target
 * joint, overrides applied on a base mapping, and bad files refused with every problem named. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "mapping-file/mapfile.h"

static rf_skeleton *chain(const char *file, const char *const *names, uint32_t n)
{
    rf_skeleton *s = rf_skeleton_new(n);
    s->name = strdup(file);
    for (uint32_t i = 0; i < n; i++) {
        s->joints[i].name = strdup(names[i]);
        s->joints[i].parent = i ? 0 : -1;
    }
    return s;
}

static rf_skeleton *target_skel(void)
{
    static const char *const n[] = {"root", "spine", "l_arm", "r_arm"};
    return chain("target.glb", n, 4);
}

static rf_skeleton *source_skel(const char *file)
{
    static const char *const n[] = {"Hips", "Chest", "LeftArm", "RightArm"};
    return chain(file, n, 4);
}

static void set_input(rf_mapping *m, uint32_t j, rf_map_input in)
{
    rf_map_entry *e = &m->entries[j];
    e->inputs = realloc(e->inputs, (e->input_count + 1) * sizeof *e->inputs);
    e->inputs[e->input_count++] = in;
}

/* A mapping with labels and metrics, two sources, weights, a delay and flags. */
static rf_mapping *sample(void)
{
    rf_mapping *m = rf_mapping_new(4, 2);
    m->metric_count = 2;
    m->metric_names = calloc(2, sizeof(char *));
    m->metric_names[0] = strdup("same_side"), m->metric_names[1] = strdup("sequence");
    m->sections = calloc(4, sizeof(char *));
    m->sides = calloc(4, sizeof(char *));
    const char *sec[] = {"spine", "spine", "arm", "arm"},
               *side[] = {"center", "center", "left", "right"};
    for (uint32_t j = 0; j < 4; j++) {
        m->sections[j] = strdup(sec[j]), m->sides[j] = strdup(side[j]);
        m->entries[j].metrics = calloc(2, sizeof(double));
        m->entries[j].metrics[0] = 30, m->entries[j].metrics[1] = 0.5 * j;
        m->entries[j].score = 30 + 0.5 * j;
    }
    set_input(m, 0, (rf_map_input){0, 0, 1.0f, 0.0f, 0});
    set_input(m, 2, (rf_map_input){0, 2, 0.75f, 0.125f, RF_MAP_REVERSE});
    set_input(m, 2, (rf_map_input){1, 2, 0.25f, 0.0f, RF_MAP_MIRROR});
    set_input(m, 3, (rf_map_input){1, 3, 1.0f, 0.5f, 0});
    m->entries[1].score = 0; /* unmapped */
    return m;
}

static char *to_text(const rf_mapping *m, const rf_skeleton *t, const rf_skeleton *const *s,
                     uint32_t n, size_t *size)
{
    char *text = NULL, err[256];
    FILE *out = open_memstream(&text, size);
    assert_true(rf_mapfile_write(out, m, t, s, n, err, sizeof err));
    fclose(out);
    return text;
}

static void assert_same(const rf_mapping *a, const rf_mapping *b)
{
    assert_int_equal(a->target_joint_count, b->target_joint_count);
    assert_int_equal(a->metric_count, b->metric_count);
    for (uint32_t j = 0; j < a->target_joint_count; j++) {
        const rf_map_entry *x = &a->entries[j], *y = &b->entries[j];
        assert_int_equal(x->input_count, y->input_count);
        for (uint32_t k = 0; k < x->input_count; k++) {
            assert_int_equal(x->inputs[k].source, y->inputs[k].source);
            assert_int_equal(x->inputs[k].joint, y->inputs[k].joint);
            assert_true(x->inputs[k].weight == y->inputs[k].weight);
            assert_true(x->inputs[k].delay == y->inputs[k].delay);
            assert_int_equal(x->inputs[k].flags, y->inputs[k].flags);
        }
        assert_true(x->score == y->score);
        for (uint32_t q = 0; q < a->metric_count; q++)
            assert_true(x->metrics[q] == y->metrics[q]);
        assert_string_equal(a->sections[j], b->sections[j]);
        assert_string_equal(a->sides[j], b->sides[j]);
    }
}

static void test_round_trip(void **state)
{
    (void)state;
    rf_skeleton *t = target_skel(), *s0 = source_skel("walk.bvh"), *s1 = source_skel("run.bvh");
    const rf_skeleton *src[2] = {s0, s1};
    rf_mapping *m = sample();
    size_t size;
    char *text = to_text(m, t, src, 2, &size), err[1024];
    assert_non_null(strstr(text, "\"format\": \"rigflow.mapping\""));
    assert_non_null(strstr(text, "\"target\": \"target.glb\""));
    assert_non_null(strstr(text, "\"run.bvh\""));
    assert_non_null(strstr(text, "\"target\": \"spine\",\n      \"inputs\": []"));
    rf_mapfile *f = rf_mapfile_parse(text, size, "t.json", err, sizeof err);
    assert_non_null(f);
    assert_int_equal(f->joint_count, 4); /* every target joint, mapped or not */
    assert_string_equal(f->target, "target.glb");
    rf_mapping *back = rf_mapfile_resolve(f, t, src, 2, err, sizeof err);
    assert_non_null(back);
    assert_same(m, back);
    rf_mapping *copy = rf_mapping_copy(back);
    assert_same(back, copy);
    rf_mapping_free(copy);
    rf_mapping_free(back);
    rf_mapfile_free(f);
    free(text);
    rf_mapping_free(m);
    rf_skeleton_free(t), rf_skeleton_free(s0), rf_skeleton_free(s1);
}

/* A partial file replaces only the joints it lists. */
static void test_overrides(void **state)
{
    (void)state;
    rf_skeleton *t = target_skel(), *s0 = source_skel("walk.bvh"), *s1 = source_skel("run.bvh");
    const rf_skeleton *src[2] = {s0, s1};
    rf_mapping *base = sample();
    const char *text = "{\"format\": \"rigflow.mapping\", \"version\": 1, \"joints\": ["
                       "{\"target\": \"spine\", \"inputs\": [{\"source\": 1, \"joint\": \"Chest\","
                       " \"delay\": 0.2}]},"
                       "{\"target\": \"r_arm\", \"inputs\": []}]}";
    char err[1024];
    rf_mapfile *f = rf_mapfile_parse(text, strlen(text), "o.json", err, sizeof err);
    assert_non_null(f);
    rf_mapping *m = rf_mapfile_apply(f, base, t, src, 2, err, sizeof err);
    assert_non_null(m);
    assert_int_equal(m->entries[1].input_count, 1);
    assert_int_equal(m->entries[1].inputs[0].source, 1);
    assert_int_equal(m->entries[1].inputs[0].joint, 1);
    assert_true(m->entries[1].inputs[0].weight == 1.0f);
    assert_true(m->entries[1].inputs[0].delay == 0.2f);
    assert_int_equal(m->entries[3].input_count, 0); /* unmapped by the override */
    assert_int_equal(m->entries[2].input_count, 2); /* untouched */
    assert_int_equal(m->entries[0].inputs[0].joint, 0);
    rf_mapping_free(m);
    /* the same file as a whole mapping: the joints it does not list are unmapped */
    m = rf_mapfile_resolve(f, t, src, 2, err, sizeof err);
    assert_int_equal(m->entries[0].input_count, 0);
    assert_int_equal(m->entries[1].input_count, 1);
    rf_mapping_free(m);
    rf_mapfile_free(f);
    rf_mapping_free(base);
    rf_skeleton_free(t), rf_skeleton_free(s0), rf_skeleton_free(s1);
}

/* Each bad file, and words its message must contain. */
static void expect_refused(const char *text, const char *const *needles)
{
    char err[2048];
    rf_skeleton *t = target_skel(), *s0 = source_skel("walk.bvh");
    const rf_skeleton *src[1] = {s0};
    rf_mapfile *f = rf_mapfile_parse(text, strlen(text), "bad.json", err, sizeof err);
    rf_mapping *m = f ? rf_mapfile_resolve(f, t, src, 1, err, sizeof err) : NULL;
    if (m)
        fail_msg("accepted: %s", text);
    for (; *needles; needles++)
        if (!strstr(err, *needles))
            fail_msg("message \"%s\" lacks \"%s\"", err, *needles);
    rf_mapfile_free(f);
    rf_skeleton_free(t), rf_skeleton_free(s0);
}

#define HEAD "{\"format\": \"rigflow.mapping\", \"version\": 1, "

static void test_bad_files(void **state)
{
    (void)state;
    expect_refused("{\"format\": \"rigflow.mapping\",",
                   (const char *const[]){"bad.json:1:", "JSON", NULL});
    expect_refused("[1, 2]", (const char *const[]){"JSON object", NULL});
    expect_refused("{\"format\": \"rigflow.pipeline\", \"version\": 1, \"joints\": []}",
                   (const char *const[]){"not a mapping file", NULL});
    expect_refused("{\"format\": \"rigflow.mapping\", \"version\": 2, \"joints\": []}",
                   (const char *const[]){"version 2 is not supported", "reads version 1", NULL});
    expect_refused(HEAD "\"joints\": [], \"colour\": 1}",
                   (const char *const[]){"unknown key 'colour'", NULL});
    expect_refused(HEAD "\"joint\": []}", (const char *const[]){"/joints", NULL});
    expect_refused(HEAD "\"joints\": [{\"target\": \"root\"}]}",
                   (const char *const[]){"/joints/0/inputs", NULL});
    expect_refused(HEAD "\"joints\": [{\"target\": \"root\", \"inputs\": [{\"source\": 0, "
                        "\"joint\": \"Hips\", \"weight\": 0}]}]}",
                   (const char *const[]){"/joints/0/inputs/0/weight", "from 1e-06", NULL});
    /* finite as a double but not as the mapping's float: refused, not turned into inf or 0 */
    expect_refused(HEAD "\"joints\": [{\"target\": \"root\", \"inputs\": [{\"source\": 0, "
                        "\"joint\": \"Hips\", \"weight\": 1e103}]}]}",
                   (const char *const[]){"/joints/0/inputs/0/weight", "to 1e+06", NULL});
    expect_refused(HEAD "\"joints\": [{\"target\": \"root\", \"inputs\": [{\"source\": 0, "
                        "\"joint\": \"Hips\", \"delay\": 1e300}]}]}",
                   (const char *const[]){"/joints/0/inputs/0/delay", "from 0 to 1e+06", NULL});
    expect_refused(HEAD "\"joints\": [{\"target\": \"root\", \"inputs\": [{\"source\": 0, "
                        "\"joint\": \"Hips\", \"delay\": -1}]}]}",
                   (const char *const[]){"delay", NULL});
    expect_refused(HEAD "\"joints\": [{\"target\": \"root\", \"inputs\": [{\"source\": \"a\", "
                        "\"joint\": \"Hips\"}]}]}",
                   (const char *const[]){"/source", "integer", NULL});
    expect_refused(HEAD "\"joints\": [{\"target\": \"root\", \"inputs\": []}, {\"target\": "
                        "\"root\", \"inputs\": []}]}",
                   (const char *const[]){"'root' is listed again", NULL});
    /* names the skeletons lack: all of them, in one message */
    expect_refused(HEAD
                   "\"joints\": [{\"target\": \"tail\", \"inputs\": []}, {\"target\": \"wing\","
                   " \"inputs\": []}]}",
                   (const char *const[]){"2 target joints are not in the target skeleton", "'tail'",
                                         "'wing'", NULL});
    expect_refused(HEAD "\"joints\": [{\"target\": \"root\", \"inputs\": [{\"source\": 0, "
                        "\"joint\": \"Pelvis\"}]}]}",
                   (const char *const[]){"bad.json: at /joints/0/inputs/0: source 0 (walk.bvh) "
                                         "has no joint 'Pelvis'",
                                         NULL});
    expect_refused(HEAD "\"joints\": [{\"target\": \"root\", \"inputs\": [{\"source\": 3, "
                        "\"joint\": \"Hips\"}]}]}",
                   (const char *const[]){"source 3, but 1 source is connected", NULL});
    expect_refused(HEAD "\"metrics\": [\"a\"], \"joints\": [{\"target\": \"root\", \"inputs\": [],"
                        " \"metrics\": {\"b\": 1}}]}",
                   (const char *const[]){"metric 'b' is not in /metrics", NULL});
    char err[64];
    assert_null(rf_mapfile_read("/nonexistent/m.json", err, sizeof err));
    assert_non_null(strstr(err, "cannot open"));
}

/* Metrics without a list, labels missing, inputs with defaults. */
static void test_lenient_parts(void **state)
{
    (void)state;
    const char *text = HEAD "\"joints\": [{\"target\": \"l_arm\", \"inputs\": [{\"source\": 0, "
                            "\"joint\": \"LeftArm\", \"reverse\": true}], \"score\": 81, "
                            "\"metrics\": {\"same_type\": 50, \"same_side\": 30}}]}";
    char err[512];
    rf_skeleton *t = target_skel(), *s0 = source_skel("walk.bvh");
    const rf_skeleton *src[1] = {s0};
    rf_mapfile *f = rf_mapfile_parse(text, strlen(text), "ok.json", err, sizeof err);
    assert_non_null(f);
    assert_int_equal(f->metric_count, 2);
    rf_mapping *m = rf_mapfile_resolve(f, t, src, 1, err, sizeof err);
    assert_non_null(m);
    assert_int_equal(m->entries[2].inputs[0].flags, RF_MAP_REVERSE);
    assert_true(m->entries[2].inputs[0].weight == 1.0f);
    assert_true(m->entries[2].score == 81);
    assert_string_equal(m->metric_names[1], "same_side");
    assert_true(m->entries[2].metrics[1] == 30);
    rf_mapping_free(m);
    rf_mapfile_free(f);
    /* the writer refuses what it cannot name */
    rf_mapping *wrong = rf_mapping_new(2, 1);
    char *text2 = NULL;
    size_t size;
    FILE *out = open_memstream(&text2, &size);
    assert_false(rf_mapfile_write(out, wrong, t, src, 1, err, sizeof err));
    fclose(out);
    free(text2);
    rf_mapping_free(wrong);
    rf_skeleton_free(t), rf_skeleton_free(s0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_round_trip),
        cmocka_unit_test(test_overrides),
        cmocka_unit_test(test_bad_files),
        cmocka_unit_test(test_lenient_parts),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
