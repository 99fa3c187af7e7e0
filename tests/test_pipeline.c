/* Pipeline validation (every error class names the node and JSON pointer and says what was
 * expected) and runs (dependency order, overrides, nothing half-written on failure). */
#include <unistd.h>

#include "testutil.h"

typedef struct fixture {
    rf_registry *reg;
    GPtrArray *diags;
    char *dir; /* scratch folder for outputs */
} fixture;

static int setup(void **state)
{
    fixture *f = g_new0(fixture, 1);
    f->reg = rf_registry_new();
    f->diags = rf_diags_new();
    g_autofree char *good = fixture_path("fx_good");
    assert_true(rf_registry_load_file(f->reg, good, f->diags));
    f->dir = g_dir_make_tmp("rf-pipeline-XXXXXX", NULL);
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    rf_registry_free(f->reg);
    g_ptr_array_unref(f->diags);
    g_autoptr(GDir) d = g_dir_open(f->dir, 0, NULL);
    for (const char *name; d && (name = g_dir_read_name(d));) {
        g_autofree char *p = g_build_filename(f->dir, name, NULL);
        g_unlink(p);
    }
    g_rmdir(f->dir);
    g_free(f->dir);
    g_free(f);
    return 0;
}

#define HEAD "{\"format\": \"rigflow.pipeline\", \"version\": 1, \"nodes\": ["

/* Loads and validates `nodes` (the inside of the nodes list). */
static rf_pipeline *check(fixture *f, const char *nodes, bool expect_valid)
{
    g_autofree char *text = g_strdup_printf(HEAD "%s]}", nodes);
    rf_pipeline *p = rf_pipeline_load_string(text, "test.json", f->dir, f->diags);
    assert_non_null(p);
    bool valid = rf_pipeline_validate(p, f->reg, f->diags);
    if (valid != expect_valid)
        find_diag(f->diags, "\x01", NULL); /* prints every diag */
    assert_int_equal(valid, expect_valid);
    return p;
}

static void syntax_error_has_line_and_column(void **state)
{
    fixture *f = *state;
    const char *text = "{\"format\": \"rigflow.pipeline\",\n  \"version\": 1,\n  \"nodes\": [}\n";
    assert_null(rf_pipeline_load_string(text, "bad.json", ".", f->diags));
    const rf_diag *d = find_diag(f->diags, "bad.json:3:", "JSON syntax error", NULL);
    assert_non_null(d);
    assert_int_equal(d->line, 3);
    assert_true(d->column > 0);
}

static void header_and_structure_checked(void **state)
{
    fixture *f = *state;
    const char *text = "{\"format\": \"other\", \"version\": 7, \"extra\": 1, \"nodes\": "
                       "[{\"type\": \"test.source\"}, {\"id\": \"a.b\", \"type\": 3}]}";
    rf_pipeline *p = rf_pipeline_load_string(text, "s.json", ".", f->diags);
    assert_false(rf_pipeline_validate(p, f->reg, f->diags));
    assert_non_null(find_diag(f->diags, "/format", "rigflow.pipeline", NULL));
    assert_non_null(find_diag(f->diags, "/version", "version 7 is not supported", NULL));
    assert_non_null(find_diag(f->diags, "/extra", "unknown key", NULL));
    assert_non_null(find_diag(f->diags, "/nodes/0", "needs an \"id\"", NULL));
    assert_non_null(find_diag(f->diags, "/nodes/1", "needs an \"id\"", NULL));
    rf_pipeline_free(p);
}

static void duplicate_ids_refused(void **state)
{
    fixture *f = *state;
    rf_pipeline *p = check(f,
                           "{\"id\": \"a\", \"type\": \"test.source\"},"
                           "{\"id\": \"a\", \"type\": \"test.source\"}",
                           false);
    assert_non_null(
        find_diag(f->diags, "node 'a'", "/nodes/1", "duplicate node id", "/nodes/0", NULL));
    rf_pipeline_free(p);
}

static void unknown_type_says_plugin_not_installed(void **state)
{
    fixture *f = *state;
    rf_pipeline *p = check(f,
                           "{\"id\": \"m\", \"type\": \"match.magic\"},"
                           "{\"id\": \"out\", \"type\": \"test.sink\", \"params\": {\"path\": "
                           "\"x.txt\"}, \"inputs\": {\"in\": \"m.mapping\"}}",
                           false);
    assert_non_null(find_diag(f->diags, "node 'm'", "/nodes/0/type",
                              "plugin not installed: match.magic", NULL));
    /* the downstream node is not blamed for its upstream's missing plugin */
    assert_int_equal(f->diags->len, 1);
    rf_pipeline_free(p);
}

static void param_errors(void **state)
{
    fixture *f = *state;
    rf_pipeline *p = check(f,
                           "{\"id\": \"s\", \"type\": \"test.source\", \"params\": {"
                           "\"value\": 250, \"fail\": \"yes\", \"mode\": \"turbo\","
                           "\"count\": 2.5, \"colour\": 1}}",
                           false);
    assert_non_null(
        find_diag(f->diags, "node 's'", "/nodes/0/params/value", "out of range", "[0, 100]", NULL));
    assert_non_null(find_diag(f->diags, "/nodes/0/params/fail", "expects a bool", NULL));
    assert_non_null(
        find_diag(f->diags, "/nodes/0/params/mode", "expected one of fast, slow", NULL));
    assert_non_null(find_diag(f->diags, "/nodes/0/params/count", "expects an int", NULL));
    assert_non_null(find_diag(f->diags, "/nodes/0/params/colour", "unknown parameter 'colour'",
                              "value, fail, mode, count", NULL));
    assert_int_equal(f->diags->len, 5);
    rf_pipeline_free(p);
}

static void missing_required_param(void **state)
{
    fixture *f = *state;
    rf_pipeline *p = check(f,
                           "{\"id\": \"s\", \"type\": \"test.source\"},"
                           "{\"id\": \"w\", \"type\": \"test.sink\", \"inputs\": {\"in\": "
                           "\"s.value\"}}",
                           false);
    assert_non_null(find_diag(f->diags, "node 'w'", "missing required parameter 'path'", NULL));
    rf_pipeline_free(p);
}

static void port_errors(void **state)
{
    fixture *f = *state;
    rf_pipeline *p = check(f,
                           "{\"id\": \"s\", \"type\": \"test.source\"},"
                           "{\"id\": \"w\", \"type\": \"test.sink\", \"params\": {\"path\": "
                           "\"o.txt\"}, \"inputs\": {\"input\": \"s.value\"}},"
                           "{\"id\": \"x\", \"type\": \"test.pair\", \"inputs\": {\"a\": "
                           "[\"s.valeur\", \"ghost.value\"], \"b\": [\"s.value\", \"s.value\"]}}",
                           false);
    assert_non_null(find_diag(f->diags, "node 'w'", "/nodes/1/inputs/input",
                              "unknown input port 'input'", "in (test.number)", NULL));
    assert_non_null(find_diag(f->diags, "node 'w'", "missing required input 'in'", NULL));
    assert_non_null(find_diag(f->diags, "node 'x'", "/nodes/2/inputs/a/0", "has no output 'valeur'",
                              "value (test.number)", NULL));
    assert_non_null(find_diag(f->diags, "/nodes/2/inputs/a/1", "node 'ghost'", NULL));
    assert_non_null(find_diag(f->diags, "/nodes/2/inputs/b", "takes one connection", NULL));
    rf_pipeline_free(p);
}

static void cycle_names_nodes(void **state)
{
    fixture *f = *state;
    rf_pipeline *p = check(f,
                           "{\"id\": \"s\", \"type\": \"test.source\"},"
                           "{\"id\": \"p1\", \"type\": \"test.pair\", \"inputs\": {\"a\": "
                           "\"p2.sum\", \"b\": \"s.value\"}},"
                           "{\"id\": \"p2\", \"type\": \"test.pair\", \"inputs\": {\"a\": "
                           "\"p1.sum\"}},"
                           "{\"id\": \"after\", \"type\": \"test.pair\", \"inputs\": {\"a\": "
                           "\"p2.sum\"}}",
                           false);
    const rf_diag *d = find_diag(f->diags, "cycle:", "p1", "p2", NULL);
    assert_non_null(d);
    assert_null(strstr(d->message, "after")); /* downstream of the cycle, not on it */
    assert_int_equal(f->diags->len, 1);
    rf_pipeline_free(p);
}

static void port_type_mismatch_names_both_ends(void **state)
{
    fixture *f = *state;
    rf_pipeline *p = check(f,
                           "{\"id\": \"t\", \"type\": \"test.text\"},"
                           "{\"id\": \"w\", \"type\": \"test.sink\", \"params\": {\"path\": "
                           "\"o.txt\"}, \"inputs\": {\"in\": \"t.text\"}}",
                           false);
    assert_non_null(find_diag(f->diags, "node 'w'", "/nodes/1/inputs/in",
                              "input in of node w expects test.number",
                              "node t's output text is test.text", NULL));
    rf_pipeline_free(p);
}

static void every_error_reported_at_once(void **state)
{
    fixture *f = *state;
    rf_pipeline *p = check(f,
                           "{\"id\": \"a\", \"type\": \"nope.a\"},"
                           "{\"id\": \"s\", \"type\": \"test.source\", \"params\": {\"value\": "
                           "-1}},"
                           "{\"id\": \"t\", \"type\": \"test.text\"},"
                           "{\"id\": \"w\", \"type\": \"test.sink\", \"params\": {\"path\": "
                           "\"o.txt\"}, \"inputs\": {\"in\": \"t.text\"}}",
                           false);
    assert_non_null(find_diag(f->diags, "plugin not installed: nope.a", NULL));
    assert_non_null(find_diag(f->diags, "out of range", NULL));
    assert_non_null(find_diag(f->diags, "expects test.number", NULL));
    assert_int_equal(f->diags->len, 3);
    rf_pipeline_free(p);
}

static bool file_exists(const char *dir, const char *name)
{
    g_autofree char *p = g_build_filename(dir, name, NULL);
    return g_file_test(p, G_FILE_TEST_EXISTS);
}

static int count_files(const char *dir)
{
    int n = 0;
    g_autoptr(GDir) d = g_dir_open(dir, 0, NULL);
    while (d && g_dir_read_name(d))
        n++;
    return n;
}

static void run_in_dependency_order(void **state)
{
    fixture *f = *state;
    rf_pipeline *p = check(f,
                           "{\"id\": \"s1\", \"type\": \"test.source\", \"params\": {\"value\": "
                           "2}},"
                           "{\"id\": \"w\", \"type\": \"test.sink\", \"params\": {\"path\": "
                           "\"out.txt\"}, \"inputs\": {\"in\": \"add.sum\"}},"
                           "{\"id\": \"add\", \"type\": \"test.pair\", \"inputs\": {\"a\": "
                           "[\"s1.value\", \"s2.value\"], \"b\": \"s1.value\"}},"
                           "{\"id\": \"s2\", \"type\": \"test.source\", \"params\": {\"value\": "
                           "5}}",
                           true);
    assert_true(rf_pipeline_run(p, f->reg, NULL, f->diags));
    const double *sum = rf_pipeline_result(p, "add", "sum");
    assert_non_null(sum);
    assert_true(*sum == 9.0); /* 2 + 5 from a, 2 from b */
    g_autofree char *out = g_build_filename(f->dir, "out.txt", NULL);
    g_autofree char *text = NULL;
    assert_true(g_file_get_contents(out, &text, NULL, NULL));
    assert_string_equal(text, "9\n");
    assert_int_equal(count_files(f->dir), 1); /* no temporary file left */
    rf_pipeline_free(p);
}

static void failing_node_leaves_no_output(void **state)
{
    fixture *f = *state;
    rf_pipeline *p = check(f,
                           "{\"id\": \"s\", \"type\": \"test.source\"},"
                           "{\"id\": \"w\", \"type\": \"test.sink\", \"params\": {\"path\": "
                           "\"out.txt\", \"fail\": true}, \"inputs\": {\"in\": \"s.value\"}}",
                           true);
    assert_false(rf_pipeline_run(p, f->reg, NULL, f->diags));
    assert_non_null(find_diag(f->diags, "node 'w'", "test.sink failed",
                              "failed after writing part of", "out.txt", NULL));
    assert_false(file_exists(f->dir, "out.txt"));
    assert_int_equal(count_files(f->dir), 0);
    rf_pipeline_free(p);
}

/* The sink's output is complete (its fsync already begun on a thread) when a later node fails:
 * the run still removes it and leaves no temporary file. */
static void later_failure_removes_finished_output(void **state)
{
    fixture *f = *state;
    rf_pipeline *p = check(f,
                           "{\"id\": \"s\", \"type\": \"test.source\"},"
                           "{\"id\": \"w\", \"type\": \"test.sink\", \"params\": {\"path\": "
                           "\"out.txt\"}, \"inputs\": {\"in\": \"s.value\"}},"
                           "{\"id\": \"a\", \"type\": \"test.pair\", \"inputs\": {\"a\": "
                           "\"s.value\"}},"
                           "{\"id\": \"z\", \"type\": \"test.sink\", \"params\": {\"path\": "
                           "\"late.txt\", \"fail\": true}, \"inputs\": {\"in\": \"a.sum\"}}",
                           true);
    assert_false(rf_pipeline_run(p, f->reg, NULL, f->diags)); /* order: s, w, a, z */
    assert_non_null(find_diag(f->diags, "node 'z'", "failed after writing part of", NULL));
    assert_int_equal(count_files(f->dir), 0);
    rf_pipeline_free(p);
}

/* A committed output has the mode a new file would have had (mkstemp made it 0600). */
static void output_gets_new_file_mode(void **state)
{
    fixture *f = *state;
    rf_pipeline *p = check(f,
                           "{\"id\": \"s\", \"type\": \"test.source\"},"
                           "{\"id\": \"w\", \"type\": \"test.sink\", \"params\": {\"path\": "
                           "\"out.txt\"}, \"inputs\": {\"in\": \"s.value\"}}",
                           true);
    mode_t mask = umask(022);
    bool ok = rf_pipeline_run(p, f->reg, NULL, f->diags);
    umask(mask);
    assert_true(ok);
    g_autofree char *out = g_build_filename(f->dir, "out.txt", NULL);
    GStatBuf st;
    assert_int_equal(g_stat(out, &st), 0);
    assert_int_equal(st.st_mode & 0777, 0644);
    assert_int_equal(count_files(f->dir), 1);
    rf_pipeline_free(p);
}

static void upstream_failure_leaves_no_output(void **state)
{
    fixture *f = *state;
    rf_pipeline *p = check(f,
                           "{\"id\": \"w\", \"type\": \"test.sink\", \"params\": {\"path\": "
                           "\"out.txt\"}, \"inputs\": {\"in\": \"s.value\"}},"
                           "{\"id\": \"s\", \"type\": \"test.source\", \"params\": {\"fail\": "
                           "true}}",
                           true);
    assert_false(rf_pipeline_run(p, f->reg, NULL, f->diags));
    assert_non_null(find_diag(f->diags, "node 's'", "asked to fail", NULL));
    assert_int_equal(count_files(f->dir), 0);
    rf_pipeline_free(p);
}

/* An output whose name is long but legal (251 bytes; a file name holds 255): its temporary file
 * beside it, 11 bytes longer, was refused ("File name too long") and the output could not be
 * written at all. */
static void long_output_name_written(void **state)
{
    fixture *f = *state;
    char name[252];
    memset(name, 'a', 247);
    memcpy(name + 247, ".txt", 5);
    g_autofree char *nodes =
        g_strdup_printf("{\"id\": \"s\", \"type\": \"test.source\"},"
                        "{\"id\": \"w\", \"type\": \"test.sink\", \"params\": {\"path\": \"%s\"}, "
                        "\"inputs\": {\"in\": \"s.value\"}}",
                        name);
    rf_pipeline *p = check(f, nodes, true);
    bool ok = rf_pipeline_run(p, f->reg, NULL, f->diags);
    if (!ok)
        find_diag(f->diags, "\x01", NULL); /* prints every diag */
    assert_true(ok);
    assert_true(file_exists(f->dir, name));
    assert_int_equal(count_files(f->dir), 1); /* no temporary file left */
    rf_pipeline_free(p);
}

static void missing_output_folder_reported(void **state)
{
    fixture *f = *state;
    rf_pipeline *p = check(f,
                           "{\"id\": \"s\", \"type\": \"test.source\"},"
                           "{\"id\": \"w\", \"type\": \"test.sink\", \"params\": {\"path\": "
                           "\"no/such/folder/out.txt\"}, \"inputs\": {\"in\": \"s.value\"}}",
                           true);
    assert_false(rf_pipeline_run(p, f->reg, NULL, f->diags));
    assert_non_null(
        find_diag(f->diags, "node 'w'", "no/such/folder/out.txt", "cannot write", NULL));
    rf_pipeline_free(p);
}

/* An output naming a folder is refused before any node runs, and so before any other output is
 * moved into place: found at commit, a.txt (committed first) was left by a failed run. */
static void output_naming_a_folder_is_refused_first(void **state)
{
    fixture *f = *state;
    g_autofree char *sub = g_build_filename(f->dir, "sub", NULL);
    assert_int_equal(g_mkdir(sub, 0700), 0);
    rf_pipeline *p = check(f,
                           "{\"id\": \"s\", \"type\": \"test.source\"},"
                           "{\"id\": \"w1\", \"type\": \"test.sink\", \"params\": {\"path\": "
                           "\"a.txt\"}, \"inputs\": {\"in\": \"s.value\"}},"
                           "{\"id\": \"w2\", \"type\": \"test.sink\", \"params\": {\"path\": "
                           "\"sub\"}, \"inputs\": {\"in\": \"s.value\"}}",
                           true);
    assert_false(rf_pipeline_run(p, f->reg, NULL, f->diags));
    assert_false(file_exists(f->dir, "a.txt"));
    assert_non_null(find_diag(f->diags, "node 'w2'", "cannot write", "sub", "is a folder", NULL));
    assert_int_equal(count_files(f->dir), 1); /* the folder alone: no temporary file either */
    rf_pipeline_free(p);
    g_rmdir(sub);
}

/* Two outputs naming one file (here through a/../): the second would replace the first's
 * output without a word; validation refuses it, naming both. */
static void two_outputs_naming_one_file_refused(void **state)
{
    fixture *f = *state;
    rf_pipeline *p = check(f,
                           "{\"id\": \"s\", \"type\": \"test.source\"},"
                           "{\"id\": \"w1\", \"type\": \"test.sink\", \"params\": {\"path\": "
                           "\"a.txt\"}, \"inputs\": {\"in\": \"s.value\"}},"
                           "{\"id\": \"w2\", \"type\": \"test.sink\", \"params\": {\"path\": "
                           "\"x/../a.txt\"}, \"inputs\": {\"in\": \"s.value\"}}",
                           false);
    assert_non_null(find_diag(f->diags, "node 'w2'", "parameter 'path' writes", "a.txt",
                              "node 'w1' parameter 'path'", "replace", NULL));
    rf_pipeline_free(p);
}

static void cancelled_run_leaves_no_output(void **state)
{
    fixture *f = *state;
    rf_pipeline *p = check(f,
                           "{\"id\": \"s\", \"type\": \"test.source\"},"
                           "{\"id\": \"w\", \"type\": \"test.sink\", \"params\": {\"path\": "
                           "\"out.txt\"}, \"inputs\": {\"in\": \"s.value\"}}",
                           true);
    volatile sig_atomic_t flag = 1;
    rf_run_options opts;
    rf_run_options_init(&opts);
    opts.cancel_flag = &flag;
    assert_false(rf_pipeline_run(p, f->reg, &opts, f->diags));
    assert_non_null(find_diag(f->diags, "interrupted", NULL));
    assert_int_equal(count_files(f->dir), 0);
    rf_pipeline_free(p);
}

/* The run's options by their size (rigflow-host.h): a run with `opts`, true when it succeeded. */
static bool run_sized(fixture *f, const rf_run_options *opts)
{
    rf_pipeline *p = check(f,
                           "{\"id\": \"s\", \"type\": \"test.source\"},"
                           "{\"id\": \"w\", \"type\": \"test.sink\", \"params\": {\"path\": "
                           "\"out.txt\"}, \"inputs\": {\"in\": \"s.value\"}}",
                           true);
    bool ok = rf_pipeline_run(p, f->reg, opts, f->diags);
    rf_pipeline_free(p);
    return ok;
}

/* rf_run_options grows by appending: librigflow reads the fields a caller's `size` covers. A
 * struct zero-initialised without rf_run_options_init (size 0) is read through `out` (its
 * cancel flag stops the run); an older caller's, whose size ends before cancel_flag, has
 * whatever lies beyond left unread (the run goes on, as that caller could not ask otherwise); a
 * newer caller's longer struct runs when the fields this librigflow does not know are zero, and
 * is refused, naming why, when one is set. */
static void run_options_by_size(void **state)
{
    fixture *f = *state;
    volatile sig_atomic_t flag = 1;
    rf_run_options zeroed = {.cancel_flag = &flag};
    assert_false(run_sized(f, &zeroed));
    assert_non_null(find_diag(f->diags, "interrupted", NULL));
    assert_int_equal(count_files(f->dir), 0);
    g_ptr_array_set_size(f->diags, 0);
    rf_run_options older = {.size = RF_SIZE_THROUGH(rf_run_options, progress),
                            .cancel_flag = &flag};
    assert_true(run_sized(f, &older));
    assert_int_equal(count_files(f->dir), 1);
    struct {
        rf_run_options o;
        uint64_t unknown;
    } newer = {.unknown = 0};
    rf_run_options_init(&newer.o);
    newer.o.size = sizeof newer;
    assert_true(run_sized(f, &newer.o));
    newer.unknown = 7;
    assert_false(run_sized(f, &newer.o));
    assert_non_null(find_diag(f->diags, "does not know", "newer", NULL));
}

static void overrides_are_typed_and_relative_to_cwd(void **state)
{
    fixture *f = *state;
    g_autofree char *text = g_strdup_printf(
        HEAD "{\"id\": \"s\", \"type\": \"test.source\"},"
             "{\"id\": \"w\", \"type\": \"test.sink\", \"params\": {\"path\": \"a.txt\"}, "
             "\"inputs\": {\"in\": \"s.value\"}}]}");
    rf_pipeline *p = rf_pipeline_load_string(text, "o.json", "/nonexistent", f->diags);
    g_autofree char *cwd = g_get_current_dir();
    assert_int_equal(chdir(f->dir), 0); /* the user's folder when typing the override */
    assert_true(rf_pipeline_override(p, "s.value=42.5", f->diags));
    assert_true(rf_pipeline_override(p, "w.path=b.txt", f->diags));
    assert_false(rf_pipeline_override(p, "nobody.value=1", f->diags));
    assert_false(rf_pipeline_override(p, "novalue", f->diags));
    assert_non_null(find_diag(f->diags, "no node 'nobody'", NULL));
    assert_non_null(find_diag(f->diags, "expected node.param=value", NULL));
    g_ptr_array_set_size(f->diags, 0);
    assert_int_equal(chdir(cwd), 0);
    assert_true(rf_pipeline_validate(p, f->reg, f->diags));
    assert_true(rf_pipeline_run(p, f->reg, NULL, f->diags));
    assert_true(file_exists(f->dir, "b.txt"));
    assert_true(*(const double *)rf_pipeline_result(p, "s", "value") == 42.5);
    rf_pipeline_free(p);

    p = rf_pipeline_load_string(text, "o.json", f->dir, f->diags);
    assert_true(rf_pipeline_override(p, "s.value=lots", f->diags));
    assert_false(rf_pipeline_validate(p, f->reg, f->diags));
    assert_non_null(
        find_diag(f->diags, "/nodes/0/params/value", "\"lots\"", "expected float", NULL));
    rf_pipeline_free(p);
}

static void relative_pipeline_folder_made_absolute(void **state)
{
    fixture *f = *state;
    g_autofree char *cwd = g_get_current_dir();
    assert_int_equal(chdir(f->dir), 0);
    assert_int_equal(g_mkdir("sub", 0755), 0);
    g_autofree char *text = g_strdup_printf(
        HEAD "{\"id\": \"s\", \"type\": \"test.source\"},"
             "{\"id\": \"w\", \"type\": \"test.sink\", \"params\": {\"path\": \"r.txt\"}, "
             "\"inputs\": {\"in\": \"s.value\"}}]}");
    rf_pipeline *p = rf_pipeline_load_string(text, "sub/p.json", "sub", f->diags);
    assert_true(rf_pipeline_validate(p, f->reg, f->diags));
    assert_int_equal(chdir(cwd), 0); /* the folder given was relative to where we were */
    assert_true(rf_pipeline_run(p, f->reg, NULL, f->diags));
    g_autofree char *out = g_build_filename(f->dir, "sub", "r.txt", NULL);
    assert_true(g_file_test(out, G_FILE_TEST_EXISTS));
    g_unlink(out);
    g_autofree char *sub = g_build_filename(f->dir, "sub", NULL);
    g_rmdir(sub);
    rf_pipeline_free(p);
}

static void relative_paths_resolve_against_pipeline_folder(void **state)
{
    fixture *f = *state;
    rf_pipeline *p = check(f,
                           "{\"id\": \"s\", \"type\": \"test.source\"},"
                           "{\"id\": \"w\", \"type\": \"test.sink\", \"params\": {\"path\": "
                           "\"rel.txt\"}, \"inputs\": {\"in\": \"s.value\"}}",
                           true);
    assert_true(rf_pipeline_run(p, f->reg, NULL, f->diags));
    assert_true(file_exists(f->dir, "rel.txt"));
    rf_pipeline_free(p);
}

/* A parameter read with a getter of another type reads 0, never a stale default or another
 * field of the value (a FLOAT of 7.9 read with param_int used to give the default, 1). */
static void getters_read_their_own_type_only(void **state)
{
    fixture *f = *state;
    rf_pipeline *p = check(f,
                           "{\"id\": \"g\", \"type\": \"test.getters\", \"params\": "
                           "{\"f\": 7.9, \"i\": 5, \"b\": true}}",
                           true);
    assert_true(rf_pipeline_run(p, f->reg, NULL, f->diags));
    const double *v = rf_pipeline_result(p, "g", "values");
    assert_non_null(v);
    assert_true(v[0] == 0); /* FLOAT 7.9 read with param_int */
    assert_true(v[1] == 0); /* INT 5 read with param_bool */
    assert_true(v[2] == 0); /* BOOL true read with param_float */
    assert_true(v[3] == 5); /* INT read with param_float: its value */
    rf_pipeline_free(p);
}

int main(void)
{
#define T(fn) cmocka_unit_test_setup_teardown(fn, setup, teardown)
    const struct CMUnitTest tests[] = {
        T(syntax_error_has_line_and_column),
        T(header_and_structure_checked),
        T(duplicate_ids_refused),
        T(unknown_type_says_plugin_not_installed),
        T(param_errors),
        T(missing_required_param),
        T(port_errors),
        T(cycle_names_nodes),
        T(port_type_mismatch_names_both_ends),
        T(every_error_reported_at_once),
        T(run_in_dependency_order),
        T(failing_node_leaves_no_output),
        T(upstream_failure_leaves_no_output),
        T(later_failure_removes_finished_output),
        T(output_gets_new_file_mode),
        T(missing_output_folder_reported),
        T(long_output_name_written),
        T(output_naming_a_folder_is_refused_first),
        T(two_outputs_naming_one_file_refused),
        T(cancelled_run_leaves_no_output),
        T(run_options_by_size),
        T(overrides_are_typed_and_relative_to_cwd),
        T(relative_paths_resolve_against_pipeline_folder),
        T(getters_read_their_own_type_only),
        T(relative_pipeline_folder_made_absolute),
    };
    return cmocka_run_group_tests_name("pipeline", tests, NULL, NULL);
}
