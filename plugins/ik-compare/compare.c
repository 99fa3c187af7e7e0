/* ik.compare: a report node that runs every solver connected to it on the standard IK workloads
 * and writes the comparison as CSV (the columns of `rigflow ik-bench`) and an SVG chart of mean
 * error against the iteration cap, one line per solver. The solvers arrive configured on
 * rigflow.ik-solver ports, exactly as a retargeter's contact pass would receive them. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <rigflow/ik.h>
#include <rigflow/plugin.h>

#include "rigflow/ik-workload.h"

#define DEFAULT_WORKLOADS                                                                          \
    "chain2-it10,chain5-it10,chain5-it50,chain10-it10,chain10-it50,chain30-it50,tree2-it50,"       \
    "chain10-it50-lim,tree2-it50-lim,arm-it50,leg-it50,arm-it50-lim"

static const rf_port_desc inputs[] = {
    RF_PORT_DESC("solvers", RF_TYPE_IK_SOLVER, RF_PORT_MULTIPLE,
                 "the solvers to compare, each a node of kind ik"),
};

static const rf_param_desc params[] = {
    RF_PARAM_DESC_OUTPUT_PATH(
        "csv", RF_PARAM_REQUIRED,
        "the table: solver,workload,us_per_solve,converged,mean_error,mean_iterations"),
    RF_PARAM_DESC_OUTPUT_PATH("svg", RF_PARAM_REQUIRED,
                              "the chart: mean error against the iteration cap, per solver"),
    RF_PARAM_DESC_STRING(
        "workloads", DEFAULT_WORKLOADS,
        "comma-separated workload names or families (see rigflow ik-bench --list)"),
    RF_PARAM_DESC_INPUT_PATH(
        "bvh", 0,
        "skeleton for the limb workloads (arm, leg, spinearm); they are skipped without it"),
    RF_PARAM_DESC_STRING(
        "chart", "chain10",
        "the workload family the chart runs at each iteration cap (chainN, tree2, arm, leg, ...)"),
    RF_PARAM_DESC_FLOAT("chart-tolerance", 1e-6, 1e-12, 1,
                        "tolerance for the chart's solves (small, so the caps show convergence)"),
    RF_PARAM_DESC_INT("chart-samples", 200, 1, 100000, "targets per point of the chart"),
    RF_PARAM_DESC_FLOAT("min-time", 0.02, 0, 60,
                        "seconds each timing repetition lasts at least (0: no timing)"),
};

static const char *solver_label(const rf_ik_solver *s)
{
    return s->label && *s->label ? s->label : s->api->name;
}

/* Every solver on one workload: CSV rows; skips (a shape a solver refuses) become log lines. */
static bool table_workload(const rf_host *host, rf_node *node, FILE *csv, const char *name,
                           const char *bvh)
{
    char err[200];
    if (rf_ikw_needs_bvh(name) && !*bvh) {
        host->log(node, RF_LOG_INFO, "%s skipped: no bvh parameter", name);
        return true;
    }
    rf_ikw *w = rf_ikw_make(name, bvh, err, sizeof err);
    if (!w) {
        host->error(node, "workload %s: %s", name, err);
        return false;
    }
    double min_time = host->param_float(node, "min-time");
    for (uint32_t i = 0; i < host->input_count(node, "solvers"); i++) {
        const rf_ik_solver *s = host->input(node, "solvers", i);
        rf_ikw_stats st;
        int rc = rf_ikw_run(s->api, s->state, w, min_time, 3, &st, err, sizeof err);
        if (rc == 1)
            rf_ikw_csv_row(csv, solver_label(s), name, &st);
        else
            host->log(node, RF_LOG_INFO, "%s on %s %s: %s", solver_label(s), name,
                      rc ? "failed" : "skipped", err);
    }
    rf_ikw_free(w);
    return true;
}

/* Workload names from the comma list in its order: a full name is that workload, anything else
 * a family or prefix (see rf_ikw_matches). */
static bool write_table(const rf_host *host, rf_node *node, FILE *csv, const char *bvh)
{
    char *list = strdup(host->param_string(node, "workloads")), *save = NULL;
    if (!list)
        return host->error(node, "out of memory"), false;
    rf_ikw_csv_header(csv);
    bool ok = true;
    for (char *tok = strtok_r(list, ", ", &save); ok && tok; tok = strtok_r(NULL, ", ", &save)) {
        bool any = false;
        for (const char *const *n = rf_ikw_names(); ok && *n; n++)
            if (rf_ikw_matches(tok, *n)) {
                any = true;
                ok = table_workload(host, node, csv, *n, bvh) && !host->cancelled(node);
            }
        if (!any) {
            host->error(node, "workloads: no workload is called '%s'", tok);
            ok = false;
        }
    }
    free(list);
    return ok;
}

/* Mean error of every solver at every cap of the chart (NAN where a solver refuses). */
static bool chart_points(const rf_host *host, rf_node *node, rf_ikw *w, uint32_t count, double *ys)
{
    char err[200];
    for (uint32_t i = 0; i < count; i++) {
        const rf_ik_solver *s = host->input(node, "solvers", i);
        for (uint32_t c = 0; c < RF_IKW_CHART_CAPS; c++) {
            rf_ikw_stats st;
            w->max_iterations = (uint32_t)rf_ikw_chart_caps[c];
            int rc = rf_ikw_run(s->api, s->state, w, 0, 1, &st, err, sizeof err);
            ys[i * RF_IKW_CHART_CAPS + c] = rc == 1 ? st.mean_error : NAN;
            if (rc < 0)
                return host->error(node, "%s: %s", solver_label(s), err), false;
        }
        host->progress(node, 0.5 + 0.5 * (i + 1) / count);
    }
    return true;
}

/* The legend entry: the solver's label, marked when it refused the chart's workload. */
static const char *label_for(const rf_ik_solver *s, const double *ys, char *buf, size_t size)
{
    bool any = false;
    for (uint32_t c = 0; c < RF_IKW_CHART_CAPS; c++)
        any = any || !isnan(ys[c]);
    snprintf(buf, size, "%s%s", solver_label(s), any ? "" : " (n/a)");
    return buf;
}

static bool write_chart(const rf_host *host, rf_node *node, FILE *svg, const char *bvh)
{
    char name[64], err[200], title[160];
    const char *family = host->param_string(node, "chart");
    snprintf(name, sizeof name, "%s-it1", family);
    rf_ikw *w = rf_ikw_make(name, bvh, err, sizeof err);
    if (!w)
        return host->error(node, "chart workload %s: %s", family, err), false;
    rf_ikw_truncate(w, (uint32_t)host->param_int(node, "chart-samples"));
    w->tolerance = host->param_float(node, "chart-tolerance");
    uint32_t count = host->input_count(node, "solvers");
    double *ys = calloc((size_t)count * RF_IKW_CHART_CAPS + 1, sizeof *ys);
    const char **labels = calloc(count + 1, sizeof *labels);
    char(*names)[64] = calloc(count + 1, sizeof *names);
    bool ok = ys && labels && names && chart_points(host, node, w, count, ys);
    if (ok) {
        for (uint32_t i = 0; i < count; i++)
            labels[i] = label_for(host->input(node, "solvers", i), ys + i * RF_IKW_CHART_CAPS,
                                  names[i], sizeof names[i]);
        snprintf(title, sizeof title, "IK solvers on %s: %u targets, tolerance %g", family,
                 w->sample_count, w->tolerance);
        ok = rf_ikw_write_svg(svg, title, count, labels, RF_IKW_CHART_CAPS, rf_ikw_chart_caps, ys);
        if (!ok)
            host->error(node, "cannot write %s", host->param_output_target(node, "svg"));
    } else if (!ys || !labels || !names) {
        host->error(node, "out of memory");
    }
    free(ys), free(labels), free(names);
    rf_ikw_free(w);
    return ok;
}

static FILE *open_output(const rf_host *host, rf_node *node, const char *param)
{
    FILE *f = fopen(host->param_string(node, param), "w");
    if (!f)
        host->error(node, "cannot write %s", host->param_output_target(node, param));
    return f;
}

static bool process(void *self, const rf_host *host, rf_node *node)
{
    (void)self;
    for (uint32_t i = 0; i < host->input_count(node, "solvers"); i++)
        if (!rf_ik_solver_usable(host->input(node, "solvers", i))) {
            host->error(node, "solver %u on input 'solvers' is incomplete (its size or functions)",
                        i);
            return false;
        }
    const char *bvh = host->param_string(node, "bvh");
    FILE *csv = open_output(host, node, "csv");
    if (!csv)
        return false;
    bool ok = write_table(host, node, csv, bvh);
    if (fclose(csv) != 0 && ok) {
        host->error(node, "cannot write %s", host->param_output_target(node, "csv"));
        ok = false;
    }
    host->progress(node, 0.5);
    FILE *svg = ok ? open_output(host, node, "svg") : NULL;
    if (!svg)
        return false;
    ok = write_chart(host, node, svg, bvh);
    if (fclose(svg) != 0 && ok) {
        host->error(node, "cannot write %s", host->param_output_target(node, "svg"));
        ok = false;
    }
    return ok;
}

static const rf_node_desc compare_node = {
    sizeof(rf_node_desc),
    "ik.compare",
    RF_KIND_REPORT,
    "Runs every connected IK solver on the standard workloads (chains of unit links, the "
    "two-effector tree, BVH limbs; with and without joint limits) and writes a CSV table (time "
    "per solve, convergence, mean error, iterations) and an SVG chart of mean error against the "
    "iteration cap.",
    sizeof inputs / sizeof inputs[0],
    inputs,
    0,
    NULL,
    sizeof params / sizeof params[0],
    params,
    NULL,
    process,
    NULL,
    NULL,
    0, /* flags: it times solvers, so it processes alone */
};

static const rf_node_desc *const nodes[] = {&compare_node};

RF_PLUGIN_DEFINE("org.rigflow.ik-compare", "IK comparison report", "0.1.0",
                 "Compares IK solvers on standard workloads: CSV table and SVG chart", nodes);
