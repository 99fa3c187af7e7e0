/* The IK plugins as the host loads them: every ik node type offers the solver table through
 * get_extension and a rigflow.ik-solver output; a pipeline hands a configured solver to whoever
 * is connected (here the test, and ik.compare, which writes its CSV and SVG). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>
#include <glib.h>
#include <glib/gstdio.h>

#include <rigflow/ik.h>

#include "rigflow-host.h"

static rf_registry *load_plugins(void)
{
    rf_registry *reg = rf_registry_new();
    g_autoptr(GPtrArray) diags = rf_diags_new();
    rf_registry_load_search_path(reg, NULL, diags);
    return reg;
}

static void test_every_ik_node_offers_the_solver_table(void **unused)
{
    (void)unused;
    rf_registry *reg = load_plugins();
    static const char *const types[] = {"ik.fabrik", "ik.ccd",           "ik.twobone",
                                        "ik.dls",    "ik.jacobian-pinv", "ik.jacobian-transpose"};
    for (size_t i = 0; i < G_N_ELEMENTS(types); i++) {
        const rf_node_desc *d = rf_registry_find(reg, types[i], NULL);
        if (!d)
            fail_msg("%s not found on RIGFLOW_PLUGIN_PATH", types[i]);
        assert_int_equal(d->kind, RF_KIND_IK);
        assert_int_equal(d->output_count, 1);
        assert_string_equal(d->outputs[0].type, RF_TYPE_IK_SOLVER);
        const rf_ik_solver_api *api = d->get_extension(RF_IK_EXTENSION);
        assert_non_null(api);
        assert_true(api->size >= sizeof *api);
        assert_null(d->get_extension("rigflow.ik/999"));
    }
    rf_registry_free(reg);
}

static rf_pipeline *run_text(rf_registry *reg, const char *text)
{
    g_autoptr(GPtrArray) diags = rf_diags_new();
    rf_pipeline *p = rf_pipeline_load_string(text, "ik-test.json", g_get_tmp_dir(), diags);
    rf_run_options opts;
    rf_run_options_init(&opts);
    opts.quiet = true;
    if (!p || !rf_pipeline_validate(p, reg, diags) || !rf_pipeline_run(p, reg, &opts, diags)) {
        for (guint i = 0; i < diags->len; i++)
            print_message("%s\n", rf_diag_format(g_ptr_array_index(diags, i)));
        fail_msg("the pipeline did not run");
    }
    return p;
}

static void test_a_pipeline_hands_out_a_working_solver(void **unused)
{
    (void)unused;
    rf_registry *reg = load_plugins();
    rf_pipeline *p = run_text(
        reg, "{\"format\": \"rigflow.pipeline\", \"version\": 1, \"nodes\": ["
             "{\"id\": \"solver\", \"type\": \"ik.dls\", \"params\": {\"max-joints\": 4}}]}");
    const rf_ik_solver *s = rf_pipeline_result(p, "solver", "solver");
    assert_non_null(s);
    assert_string_equal(s->label, "solver");
    /* Two unit links from the origin; a target 1.5 away is reachable: the effector gets there. */
    int32_t parents[3] = {-1, 0, 1};
    rf_xform pose[3] = {rf_xform_identity(), rf_xform_identity(), rf_xform_identity()}, out[3];
    pose[1].t = pose[2].t = rf_v3(0, 1, 0);
    rf_ik_goal goal = rf_ik_goal_make(2, rf_v3(0.9, 1.2, 0));
    rf_ik_problem pb = {sizeof pb, 3, parents, pose, NULL, NULL, 1, &goal, 1e-6, 100};
    double err;
    rf_ik_result res = {sizeof res, out, &err, NULL, NULL, 0, 0, false, ""};
    assert_true(s->api->solve(s->state, &pb, &res));
    assert_true(res.reached);
    assert_true(err <= 1e-6);
    rf_pipeline_free(p);
    rf_registry_free(reg);
}

static char *read_all(const char *path)
{
    char *text = NULL;
    if (!g_file_get_contents(path, &text, NULL, NULL))
        fail_msg("%s was not written", path);
    return text;
}

static void test_compare_writes_csv_and_chart(void **unused)
{
    (void)unused;
    rf_registry *reg = load_plugins();
    g_autofree char *dir = g_dir_make_tmp("rf-ik-XXXXXX", NULL);
    g_autofree char *csv = g_build_filename(dir, "ik.csv", NULL);
    g_autofree char *svg = g_build_filename(dir, "ik.svg", NULL);
    g_autofree char *text = g_strdup_printf(
        "{\"format\": \"rigflow.pipeline\", \"version\": 1, \"nodes\": ["
        "{\"id\": \"fabrik\", \"type\": \"ik.fabrik\"}, {\"id\": \"ccd\", \"type\": \"ik.ccd\"},"
        "{\"id\": \"compare\", \"type\": \"ik.compare\", \"params\": {\"csv\": \"%s\", \"svg\": "
        "\"%s\", \"workloads\": \"chain5-it10,tree2-it10\", \"min-time\": 0, \"chart\": "
        "\"chain5\", "
        "\"chart-samples\": 20}, \"inputs\": {\"solvers\": [\"fabrik.solver\", \"ccd.solver\"]}}]}",
        csv, svg);
    rf_pipeline_free(run_text(reg, text));
    g_autofree char *table = read_all(csv);
    assert_non_null(
        strstr(table, "solver,workload,us_per_solve,converged,mean_error,mean_iterations\n"));
    assert_non_null(strstr(table, "\nfabrik,chain5-it10,"));
    assert_non_null(strstr(table, "\nccd,tree2-it10,"));
    assert_null(strstr(table, "-lim")); /* full names select only themselves */
    g_autofree char *chart = read_all(svg);
    assert_non_null(strstr(chart, "<svg"));
    assert_non_null(strstr(chart, "mean position error (log scale)"));
    assert_non_null(strstr(chart, "iteration cap (log scale)"));
    assert_non_null(strstr(chart, ">fabrik</text>")); /* the legend */
    assert_non_null(strstr(chart, ">ccd</text>"));
    g_unlink(csv), g_unlink(svg), g_rmdir(dir);
    rf_registry_free(reg);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_ik_node_offers_the_solver_table),
        cmocka_unit_test(test_a_pipeline_hands_out_a_working_solver),
        cmocka_unit_test(test_compare_writes_csv_and_chart),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
