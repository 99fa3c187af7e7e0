/* Plugin loading: a good plugin loads; each broken rule is refused with its own message naming
 * the file. */
#include "testutil.h"

typedef struct fixture {
    rf_registry *reg;
    GPtrArray *diags;
} fixture;

static int setup(void **state)
{
    fixture *f = g_new0(fixture, 1);
    f->reg = rf_registry_new();
    f->diags = rf_diags_new();
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    rf_registry_free(f->reg);
    g_ptr_array_unref(f->diags);
    g_free(f);
    return 0;
}

static bool load(fixture *f, const char *name)
{
    g_autofree char *path = fixture_path(name);
    return rf_registry_load_file(f->reg, path, f->diags);
}

static void good_plugin_loads(void **state)
{
    fixture *f = *state;
    assert_true(load(f, "fx_good"));
    assert_int_equal(f->diags->len, 0);
    assert_int_equal(rf_registry_plugin_count(f->reg), 1);
    const rf_plugin *p = NULL;
    const rf_node_desc *d = rf_registry_find(f->reg, "test.source", &p);
    assert_non_null(d);
    assert_int_equal(d->kind, RF_KIND_IMPORTER);
    assert_non_null(strstr(rf_plugin_path(p), "fx_good.so"));
    assert_null(rf_registry_find(f->reg, "no.such", NULL));
}

static void other_major_refused(void **state)
{
    fixture *f = *state;
    assert_false(load(f, "fx_major"));
    g_autofree char *host =
        g_strdup_printf("host implements %d.%d.0", RF_ABI_VERSION_MAJOR, RF_ABI_VERSION_MINOR);
    assert_non_null(find_diag(f->diags, "fx_major.so", "incompatible plugin ABI",
                              "built for ABI 2.", host, NULL));
    assert_int_equal(rf_registry_plugin_count(f->reg), 0);
}

static void newer_minor_refused(void **state)
{
    fixture *f = *state;
    assert_false(load(f, "fx_minor"));
    g_autofree char *plugin =
        g_strdup_printf("built for ABI %d.%d.0", RF_ABI_VERSION_MAJOR, RF_ABI_VERSION_MINOR + 1);
    assert_non_null(find_diag(f->diags, "fx_minor.so", "incompatible plugin ABI", plugin,
                              "minor no greater", NULL));
}

static void older_minor_loads(void **state)
{
    fixture *f = *state;
    assert_true(RF_ABI_VERSION_MINOR > 0); /* the fixture below is built for minor 0 */
    assert_true(load(f, "fx_old"));
    assert_int_equal(f->diags->len, 0);
    const rf_plugin_entry *e = rf_plugin_entry_of(rf_registry_plugin(f->reg, 0));
    assert_int_equal(e->abi.minor, 0);
    assert_non_null(rf_registry_find(f->reg, "test.sink", NULL));
}

/* A skeleton made by a 1.0 plugin ends before the 1.1 fields: code built against 1.1 must not
 * touch them (here: the destructor must not free a bind pose the struct does not have). */
static void older_struct_read_safely(void **state)
{
    (void)state;
    rf_skeleton *s = rf_skeleton_new(2);
    assert_non_null(s);
    s->size = offsetof(rf_skeleton, bind);
    s->bind = (rf_xform *)(uintptr_t)1; /* what lies past a 1.0 struct: not ours to read */
    assert_false(RF_HAS_FIELD(s, rf_skeleton, bind));
    rf_skeleton_free(s); /* crashes if it frees the garbage pointer */
    rf_skeleton *n = rf_skeleton_new(1);
    assert_true(RF_HAS_FIELD(n, rf_skeleton, rest_source));
    rf_skeleton_free(n);
}

/* Loads `text` as a pipeline, validates and runs it against the fixture's registry. */
static rf_pipeline *run_text(fixture *f, const char *text)
{
    rf_pipeline *p = rf_pipeline_load_string(text, "abi.json", ".", f->diags);
    assert_non_null(p);
    assert_true(rf_pipeline_validate(p, f->reg, f->diags));
    assert_true(rf_pipeline_run(p, f->reg, NULL, f->diags));
    return p;
}

/* A plugin built against the frozen 1.0 headers (tests/abi-1.0) loads, reads as declared and
 * runs in this host; its 1.0-sized skeleton reaches consumers in this build's layout, the
 * fields appended since 1.0 zero. */
static void frozen_abi10_plugin_loads_and_runs(void **state)
{
    fixture *f = *state;
    assert_true(load(f, "fx_abi10"));
    assert_int_equal(f->diags->len, 0);
    const rf_node_desc *d = rf_registry_find(f->reg, "abi10.chain", NULL);
    assert_non_null(d);
    assert_int_equal(d->kind, RF_KIND_IMPORTER);
    assert_int_equal(d->param_count, 3);
    assert_string_equal(d->params[2].name, "prefix");
    assert_string_equal(d->params[2].default_string, "bone");
    assert_true(d->params[1].max == 10);
    assert_string_equal(d->outputs[0].type, RF_TYPE_SKELETON);
    rf_pipeline *p =
        run_text(f, "{\"format\": \"rigflow.pipeline\", \"version\": 1, \"nodes\": ["
                    "{\"id\": \"make\", \"type\": \"abi10.chain\", \"params\": {\"joints\": 4}},"
                    "{\"id\": \"count\", \"type\": \"abi10.count\", \"params\": {\"expect\": 4},"
                    " \"inputs\": {\"skeleton\": \"make.skeleton\"}}]}");
    const rf_skeleton *s = rf_pipeline_result(p, "make", "skeleton");
    assert_non_null(s);
    assert_int_equal(s->size, sizeof(rf_skeleton));
    assert_true(RF_HAS_FIELD(s, rf_skeleton, rest_source));
    assert_null(s->bind);
    assert_int_equal(s->rest_source, 0);
    assert_string_equal(s->joints[3].name, "bone3");
    rf_pipeline_free(p);
}

/* Descriptors with a field appended after this host's layout (a wider element in every array)
 * are walked by their own size: every parameter reads as declared, and the node runs. */
static void wider_descriptors_walked_by_their_size(void **state)
{
    fixture *f = *state;
    assert_true(load(f, "fx_wide"));
    assert_int_equal(f->diags->len, 0);
    const rf_node_desc *d = rf_registry_find(f->reg, "wide.sum", NULL);
    assert_non_null(d);
    assert_int_equal(d->size, sizeof(rf_node_desc));
    assert_int_equal(d->param_count, 3);
    assert_string_equal(d->params[1].name, "b");
    assert_true(d->params[1].max == 50);
    assert_string_equal(d->params[2].name, "c");
    assert_int_equal(d->params[2].size, sizeof(rf_param_desc));
    assert_string_equal(d->outputs[0].name, "value");
    rf_pipeline *p =
        run_text(f, "{\"format\": \"rigflow.pipeline\", \"version\": 1, \"nodes\": ["
                    "{\"id\": \"sum\", \"type\": \"wide.sum\", \"params\": {\"b\": 7}}]}");
    const double *v = rf_pipeline_result(p, "sum", "value");
    assert_non_null(v);
    assert_true(*v == 1.5 + 7 + 100);
    rf_pipeline_free(p);
}

static void missing_entry_refused(void **state)
{
    fixture *f = *state;
    assert_false(load(f, "fx_noentry"));
    assert_non_null(
        find_diag(f->diags, "fx_noentry.so", "not a rigflow plugin", "rigflow_plugin_entry", NULL));
}

static void failed_init_refused(void **state)
{
    fixture *f = *state;
    assert_false(load(f, "fx_initfail"));
    assert_non_null(find_diag(f->diags, "fx_initfail.so", "failed to initialise",
                              "licence file is missing", NULL));
    assert_null(rf_registry_find(f->reg, "test.source", NULL));
}

static void duplicate_type_refused(void **state)
{
    fixture *f = *state;
    assert_true(load(f, "fx_good"));
    assert_false(load(f, "fx_dup"));
    assert_non_null(
        find_diag(f->diags, "fx_dup.so", "duplicate node type 'test.source'", "fx_good.so", NULL));
    assert_int_equal(rf_registry_plugin_count(f->reg), 1);
}

/* A plugin listing one node type twice: the registry would find the first descriptor only, and
 * the second would never run without a word. */
static void type_listed_twice_refused(void **state)
{
    fixture *f = *state;
    assert_false(load(f, "fx_twice"));
    assert_non_null(find_diag(f->diags, "fx_twice.so", "malformed rigflow plugin",
                              "node type 'test.pair' twice", NULL));
    assert_int_equal(rf_registry_plugin_count(f->reg), 0);
    assert_null(rf_registry_find(f->reg, "test.pair", NULL));
}

static void unresolved_symbol_refused_at_load(void **state)
{
    fixture *f = *state;
    assert_false(load(f, "fx_unresolved"));
    assert_non_null(find_diag(f->diags, "fx_unresolved.so", "cannot load plugin",
                              "rf_fixture_symbol_nobody_defines", NULL));
}

static void not_a_shared_object_refused(void **state)
{
    fixture *f = *state;
    g_autofree char *dir = g_dir_make_tmp("rf-test-XXXXXX", NULL);
    g_autofree char *path = g_build_filename(dir, "junk.so", NULL);
    assert_true(g_file_set_contents(path, "not an ELF file", -1, NULL));
    assert_false(rf_registry_load_file(f->reg, path, f->diags));
    assert_non_null(find_diag(f->diags, "junk.so", "cannot load plugin", NULL));
    g_unlink(path);
    g_rmdir(dir);
}

static void same_plugin_twice_is_shadowed(void **state)
{
    fixture *f = *state;
    assert_true(load(f, "fx_good"));
    assert_true(load(f, "fx_good"));
    assert_int_equal(f->diags->len, 0);
    assert_int_equal(rf_registry_plugin_count(f->reg), 1);
}

static void world_writable_folder_refused(void **state)
{
    fixture *f = *state;
    g_autofree char *dir = g_dir_make_tmp("rf-test-XXXXXX", NULL);
    assert_int_equal(chmod(dir, 0777), 0);
    assert_int_equal(rf_registry_load_dir(f->reg, dir, f->diags), 0);
    assert_non_null(find_diag(f->diags, dir, "writable by other users", NULL));
    g_rmdir(dir);
}

static void search_path_finds_build_tree(void **state)
{
    fixture *f = *state;
    g_autofree char *path = fixture_path("fx_good");
    g_autofree char *dir = g_path_get_dirname(path);
    const char *extra[] = {dir, NULL};
    rf_registry_load_search_path(f->reg, extra, f->diags);
    assert_non_null(rf_registry_find(f->reg, "test.sink", NULL));
    /* the broken fixtures in the same folder are refused, each with its reason */
    assert_non_null(find_diag(f->diags, "fx_major.so", "incompatible", NULL));
    assert_non_null(find_diag(f->diags, "fx_dup.so", "duplicate node type", NULL));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(good_plugin_loads, setup, teardown),
        cmocka_unit_test_setup_teardown(other_major_refused, setup, teardown),
        cmocka_unit_test_setup_teardown(newer_minor_refused, setup, teardown),
        cmocka_unit_test_setup_teardown(older_minor_loads, setup, teardown),
        cmocka_unit_test_setup_teardown(older_struct_read_safely, setup, teardown),
        cmocka_unit_test_setup_teardown(frozen_abi10_plugin_loads_and_runs, setup, teardown),
        cmocka_unit_test_setup_teardown(wider_descriptors_walked_by_their_size, setup, teardown),
        cmocka_unit_test_setup_teardown(missing_entry_refused, setup, teardown),
        cmocka_unit_test_setup_teardown(failed_init_refused, setup, teardown),
        cmocka_unit_test_setup_teardown(duplicate_type_refused, setup, teardown),
        cmocka_unit_test_setup_teardown(type_listed_twice_refused, setup, teardown),
        cmocka_unit_test_setup_teardown(unresolved_symbol_refused_at_load, setup, teardown),
        cmocka_unit_test_setup_teardown(not_a_shared_object_refused, setup, teardown),
        cmocka_unit_test_setup_teardown(same_plugin_twice_is_shadowed, setup, teardown),
        cmocka_unit_test_setup_teardown(world_writable_folder_refused, setup, teardown),
        cmocka_unit_test_setup_teardown(search_path_finds_build_tree, setup, teardown),
    };
    return cmocka_run_group_tests_name("plugins", tests, NULL, NULL);
}
