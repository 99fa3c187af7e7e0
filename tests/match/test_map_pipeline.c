/* Mapping through the host: pipelines/map.json on every skeleton of $RF_DATA_DIR (spider.fbx,
 * which has none, refused), the names strategy, a mapping loaded from a file, overrides applied
 * on a computed mapping, and a bad mapping file refused with its problems named. Needs the
 * bundled plugins ($RIGFLOW_PLUGIN_PATH); skips without $RF_DATA_DIR. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>
#include <glib.h>
#include <glib/gstdio.h>

#include "mapping-file/mapfile.h"
#include "rigflow-host.h"

typedef struct fixture {
    rf_registry *reg;
    char *data, *tmp, *pipeline;
} fixture;

static int setup(void **state)
{
    fixture *f = g_new0(fixture, 1);
    g_autoptr(GPtrArray) diags = rf_diags_new();
    f->reg = rf_registry_new();
    rf_registry_load_search_path(f->reg, NULL, diags);
    f->data = g_strdup(g_getenv("RF_DATA_DIR"));
    f->tmp = g_dir_make_tmp("rf-map-XXXXXX", NULL);
    f->pipeline = g_build_filename(g_getenv("RF_SRCDIR") ? g_getenv("RF_SRCDIR") : ".", "pipelines",
                                   "map.json", NULL);
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    rf_registry_free(f->reg);
    g_autoptr(GDir) d = g_dir_open(f->tmp, 0, NULL);
    for (const char *n; d && (n = g_dir_read_name(d));) {
        g_autofree char *p = g_build_filename(f->tmp, n, NULL);
        g_remove(p);
    }
    g_rmdir(f->tmp);
    g_free(f->data), g_free(f->tmp), g_free(f->pipeline);
    g_free(f);
    return 0;
}

static bool have_data(const fixture *f)
{
    if (f->data && g_file_test(f->data, G_FILE_TEST_IS_DIR))
        return true;
    print_message("skipped: RF_DATA_DIR is not there\n");
    return false;
}

/* Runs a pipeline file with overrides; returns the diagnostics text ("" on success). */
static char *run(const fixture *f, const char *file, const char *const *overrides)
{
    g_autoptr(GPtrArray) diags = rf_diags_new();
    rf_pipeline *p = rf_pipeline_load(file, diags);
    for (; p && *overrides; overrides++)
        rf_pipeline_override(p, *overrides, diags);
    rf_run_options opts;
    rf_run_options_init(&opts);
    opts.quiet = true;
    bool ok = p && diags->len == 0 && rf_pipeline_validate(p, f->reg, diags) &&
              rf_pipeline_run(p, f->reg, &opts, diags);
    GString *text = g_string_new("");
    for (guint i = 0; i < diags->len; i++) {
        g_autofree char *d = rf_diag_format(g_ptr_array_index(diags, i));
        g_string_append_printf(text, "%s\n", d);
    }
    if (!ok && text->len == 0)
        g_string_append(text, "failed");
    rf_pipeline_free(p);
    return g_string_free(text, FALSE);
}

static char *map_file(const fixture *f, const char *source, const char *target, const char *out,
                      const char *extra)
{
    g_autofree char *s = g_strdup_printf("source.path=%s/%s", f->data, source);
    g_autofree char *t = g_strdup_printf("target.path=%s/%s", f->data, target);
    g_autofree char *o = g_strdup_printf("save.path=%s", out);
    const char *ov[] = {s, t, o, extra, NULL};
    return run(f, f->pipeline, ov);
}

/* Every skeleton of the data set as the target, CMU as the source. */
/* One run of test_every_file: spider.fbx refused without output, anything else mapped. */
static void check_every(const char *rel, bool spider, const char *err, const char *out)
{
    if (spider) {
        assert_true(err[0] != '\0');
        assert_false(g_file_test(out, G_FILE_TEST_EXISTS));
        print_message("spider.fbx refused: %s\n", err);
    } else if (err[0]) {
        fail_msg("%s: %s", rel, err);
    } else {
        char e[512];
        rf_mapfile *mf = rf_mapfile_read(out, e, sizeof e);
        if (!mf)
            fail_msg("%s: %s", rel, e);
        assert_true(mf->joint_count > 0);
        rf_mapfile_free(mf);
    }
}

static void test_every_file(void **state)
{
    fixture *f = *state;
    if (!have_data(f))
        return;
    const char *const dirs[] = {"bvh", "models", "models/creatures", "models/ogre"};
    int files = 0;
    for (size_t d = 0; d < G_N_ELEMENTS(dirs); d++) {
        g_autofree char *dir = g_build_filename(f->data, dirs[d], NULL);
        g_autoptr(GDir) gd = g_dir_open(dir, 0, NULL);
        for (const char *n; gd && (n = g_dir_read_name(gd));) {
            if (!g_str_has_suffix(n, ".bvh") && !g_str_has_suffix(n, ".glb") &&
                !g_str_has_suffix(n, ".gltf") && !g_str_has_suffix(n, ".X") &&
                !g_str_has_suffix(n, ".fbx") && !g_str_has_suffix(n, ".b3d") &&
                !g_str_has_suffix(n, ".mesh"))
                continue;
            g_autofree char *rel = g_build_filename(dirs[d], n, NULL);
            g_autofree char *out = g_build_filename(f->tmp, "every.json", NULL);
            g_remove(out);
            for (int as_source = 0; as_source <= 1; as_source++) {
                g_remove(out);
                g_autofree char *err = as_source ? map_file(f, rel, "bvh/cmu_01_01.bvh", out, NULL)
                                                 : map_file(f, "bvh/cmu_01_01.bvh", rel, out, NULL);
                check_every(rel, strcmp(n, "spider.fbx") == 0, err, out);
            }
            files++;
        }
    }
    print_message("mapped onto and from %d files\n", files);
    assert_true(files >= 25);
}

static const rf_mapfile_joint *entry(const rf_mapfile *mf, const char *target)
{
    for (uint32_t i = 0; i < mf->joint_count; i++)
        if (strcmp(mf->joints[i].target, target) == 0)
            return &mf->joints[i];
    return NULL;
}

static void test_strategies(void **state)
{
    fixture *f = *state;
    if (!have_data(f))
        return;
    g_autofree char *out = g_build_filename(f->tmp, "names.json", NULL);
    g_autofree char *err =
        map_file(f, "bvh/cmu_01_01.bvh", "bvh/dme_rest_cmu.bvh", out, "map.strategy=names");
    assert_string_equal(err, "");
    char e[512];
    rf_mapfile *mf = rf_mapfile_read(out, e, sizeof e);
    assert_non_null(mf);
    assert_int_equal(mf->metric_count, 1);
    assert_string_equal(entry(mf, "LeftForeArm")->inputs[0].joint, "LeftForeArm");
    rf_mapfile_free(mf);
    g_autofree char *err2 =
        map_file(f, "bvh/cmu_01_01.bvh", "models/Fox.glb", out, "map.strategy=thesis");
    assert_string_equal(err2, "");
}

/* A pipeline that computes a mapping, applies a file of overrides and saves the result. */
static void test_overrides_and_loading(void **state)
{
    fixture *f = *state;
    if (!have_data(f))
        return;
    g_autofree char *over = g_build_filename(f->tmp, "over.json", NULL);
    g_file_set_contents(over,
                        "{\"format\": \"rigflow.mapping\", \"version\": 1, \"joints\": ["
                        "{\"target\": \"b_Tail01_012\", \"inputs\": [{\"source\": 0, \"joint\": "
                        "\"LowerBack\", \"delay\": 0.1, \"reverse\": true}]},"
                        "{\"target\": \"b_Head_05\", \"inputs\": []}]}",
                        -1, NULL);
    g_autofree char *pipe = g_build_filename(f->tmp, "over-pipeline.json", NULL);
    g_autofree char *text = g_strdup_printf(
        "{\"format\": \"rigflow.pipeline\", \"version\": 1, \"nodes\": ["
        "{\"id\": \"source\", \"type\": \"import\", \"params\": {\"path\": "
        "\"%s/bvh/cmu_01_01.bvh\"}},"
        "{\"id\": \"target\", \"type\": \"import\", \"params\": {\"path\": \"%s/models/Fox.glb\"}},"
        "{\"id\": \"map\", \"type\": \"skeletal-similarity\", \"inputs\": {\"target\": "
        "\"target.skeleton\", \"sources\": [\"source.skeleton\"]}},"
        "{\"id\": \"edit\", \"type\": \"mapping.read\", \"params\": {\"path\": \"over.json\"},"
        " \"inputs\": {\"base\": \"map.mapping\", \"target\": \"target.skeleton\", \"sources\": "
        "[\"source.skeleton\"]}},"
        "{\"id\": \"save\", \"type\": \"mapping.write\", \"params\": {\"path\": \"out.json\"},"
        " \"inputs\": {\"mapping\": \"edit.mapping\", \"target\": \"target.skeleton\", "
        "\"sources\": [\"source.skeleton\"]}}]}",
        f->data, f->data);
    g_file_set_contents(pipe, text, -1, NULL);
    const char *none[] = {NULL};
    g_autofree char *err = run(f, pipe, none);
    assert_string_equal(err, "");
    g_autofree char *out = g_build_filename(f->tmp, "out.json", NULL);
    char e[512];
    rf_mapfile *mf = rf_mapfile_read(out, e, sizeof e);
    assert_non_null(mf);
    const rf_mapfile_joint *tail = entry(mf, "b_Tail01_012");
    assert_int_equal(tail->input_count, 1);
    assert_string_equal(tail->inputs[0].joint, "LowerBack");
    assert_true(tail->inputs[0].reverse);
    assert_true(tail->inputs[0].delay > 0.09);
    assert_int_equal(entry(mf, "b_Head_05")->input_count, 0);
    assert_string_equal(entry(mf, "b_Neck_04")->inputs[0].joint, "Neck"); /* computed, kept */
    rf_mapfile_free(mf);

    /* a bad override file: the run fails, naming what is wrong, and writes nothing */
    g_file_set_contents(over,
                        "{\"format\": \"rigflow.mapping\", \"version\": 1, \"joints\": ["
                        "{\"target\": \"b_Wing\", \"inputs\": []}]}",
                        -1, NULL);
    g_remove(out);
    g_autofree char *err2 = run(f, pipe, none);
    assert_non_null(strstr(err2, "'b_Wing'"));
    assert_false(g_file_test(out, G_FILE_TEST_EXISTS));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_every_file, setup, teardown),
        cmocka_unit_test_setup_teardown(test_strategies, setup, teardown),
        cmocka_unit_test_setup_teardown(test_overrides_and_loading, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
