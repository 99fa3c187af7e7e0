/* `rigflow ik-bench`: the IK comparison harness. It finds every node type of kind ik that offers
 * the "rigflow.ik/1" extension, makes each solver's state itself, and runs it on the workloads
 * of plugins/ik-common/workload.h, timing the plugin's own code as loaded. */
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "ik-bench.h"
#include "rigflow/ik-workload.h"

typedef struct bench_solver {
    const char *type; /* node type, e.g. "ik.fabrik" */
    const rf_ik_solver_api *api;
    void *state;
} bench_solver;

/* A solver is asked for by its short name ("fabrik") or its node type ("ik.fabrik"). */
static bool wanted(char **names, const char *type, const char *name)
{
    if (!names || !*names)
        return true;
    for (char **n = names; *n; n++)
        if (!strcmp(*n, type) || !strcmp(*n, name))
            return true;
    return false;
}

static GArray *find_solvers(rf_registry *reg, char **names)
{
    GArray *out = g_array_new(FALSE, TRUE, sizeof(bench_solver));
    for (guint i = 0; i < rf_registry_plugin_count(reg); i++) {
        const rf_plugin_entry *e = rf_plugin_entry_of(rf_registry_plugin(reg, i));
        for (uint32_t k = 0; k < e->node_count; k++) {
            const rf_node_desc *d = e->nodes[k];
            const rf_ik_solver_api *api = d->kind == RF_KIND_IK && d->get_extension
                                              ? d->get_extension(RF_IK_EXTENSION)
                                              : NULL;
            /* a type shadowed by an earlier folder on the path is not the one in use */
            if (!rf_ik_api_usable(api) || rf_registry_find(reg, d->type, NULL) != d ||
                !wanted(names, d->type, api->name))
                continue;
            bench_solver s = {d->type, api, NULL};
            g_array_append_val(out, s);
        }
    }
    return out;
}

/* The limb workloads' skeleton: --bvh, else the shared data beside the checkout. */
static char *default_bvh(void)
{
    const char *data = g_getenv("RF_DATA_DIR");
    char *path = g_build_filename(data ? data : "../shared/data", "bvh", "cmu_01_01.bvh", NULL);
    if (g_file_test(path, G_FILE_TEST_EXISTS))
        return path;
    g_free(path);
    return NULL;
}

static void bench_one(bench_solver *s, const rf_ikw *w, double min_time, int reps)
{
    char msg[200] = "";
    rf_ikw_stats st;
    int rc = rf_ikw_run(s->api, s->state, w, min_time, reps, &st, msg, sizeof msg);
    if (rc == 1)
        rf_ikw_csv_row(stdout, s->api->name, w->name, &st);
    else
        fprintf(stderr, "rigflow ik-bench: %s on %s: %s: %s\n", s->api->name, w->name,
                rc == 0 ? "skipped" : "failed", msg);
    fflush(stdout);
}

static bool selected(char **names, const char *workload)
{
    if (!names || !*names)
        return true;
    for (char **n = names; *n; n++)
        if (rf_ikw_matches(*n, workload))
            return true;
    return false;
}

static int run_benchmarks(GArray *solvers, char **workloads, const char *bvh, double min_time,
                          int reps)
{
    int found = 0;
    for (const char *const *name = rf_ikw_names(); *name; name++)
        found += selected(workloads, *name);
    if (!found) {
        fprintf(stderr, "rigflow ik-bench: no workload matches (see --list)\n");
        return RF_EXIT_USAGE;
    }
    rf_ikw_csv_header(stdout);
    for (const char *const *name = rf_ikw_names(); *name; name++) {
        if (!selected(workloads, *name))
            continue;
        if (rf_ikw_needs_bvh(*name) && !bvh) {
            fprintf(stderr,
                    "rigflow ik-bench: %s skipped: no BVH skeleton (--bvh or RF_DATA_DIR)\n",
                    *name);
            continue;
        }
        char err[200];
        rf_ikw *w = rf_ikw_make(*name, bvh, err, sizeof err);
        if (!w) {
            fprintf(stderr, "rigflow ik-bench: %s: %s\n", *name, err);
            return RF_EXIT_RUN;
        }
        for (guint i = 0; i < solvers->len; i++)
            bench_one(&g_array_index(solvers, bench_solver, i), w, min_time, reps);
        rf_ikw_free(w);
    }
    return RF_EXIT_OK;
}

static int list_all(GArray *solvers)
{
    printf("solvers:\n");
    for (guint i = 0; i < solvers->len; i++) {
        bench_solver *s = &g_array_index(solvers, bench_solver, i);
        printf("  %-20s %-24s %s\n", s->api->name, s->type, s->api->doc ? s->api->doc : "");
    }
    printf("workloads:\n");
    for (const char *const *name = rf_ikw_names(); *name; name++)
        printf("  %s\n", *name);
    return RF_EXIT_OK;
}

static bool make_states(GArray *solvers)
{
    for (guint i = 0; i < solvers->len; i++) {
        bench_solver *s = &g_array_index(solvers, bench_solver, i);
        char err[160] = "";
        if (!(s->state = s->api->create(NULL, err, sizeof err))) {
            fprintf(stderr, "rigflow ik-bench: %s: %s\n", s->type, err);
            return false;
        }
    }
    return true;
}

static void free_states(GArray *solvers)
{
    for (guint i = 0; i < solvers->len; i++) {
        bench_solver *s = &g_array_index(solvers, bench_solver, i);
        if (s->state)
            s->api->destroy(s->state);
    }
}

int rf_cmd_ik_bench(rf_registry *reg, int argc, char **argv)
{
    g_auto(GStrv) solver_names = NULL;
    g_auto(GStrv) workloads = NULL;
    g_autofree char *bvh = NULL;
    double min_time = 0.05;
    int reps = 3;
    gboolean list = FALSE;
    const GOptionEntry entries[] = {
        {"solver", 's', 0, G_OPTION_ARG_STRING_ARRAY, &solver_names,
         "A solver by name or node type (repeatable; default: every ik solver found)", "NAME"},
        {"workload", 'w', 0, G_OPTION_ARG_STRING_ARRAY, &workloads,
         "A workload, or a prefix such as chain10 (repeatable; default: all)", "NAME"},
        {"bvh", 0, 0, G_OPTION_ARG_FILENAME, &bvh,
         "Skeleton for the limb workloads (default: $RF_DATA_DIR/bvh/cmu_01_01.bvh)", "FILE"},
        {"min-time", 0, 0, G_OPTION_ARG_DOUBLE, &min_time,
         "Seconds each timing repetition lasts at least (default 0.05)", "S"},
        {"reps", 0, 0, G_OPTION_ARG_INT, &reps, "Timing repetitions, median taken (default 3)",
         "N"},
        {"list", 0, 0, G_OPTION_ARG_NONE, &list, "List the solvers and workloads", NULL},
        {NULL, 0, 0, 0, NULL, NULL, NULL}};
    if (!rf_parse_options("ik-bench", "",
                          "Compare the IK solvers: CSV of "
                          "solver,workload,us_per_solve,converged,mean_error,mean_iterations.",
                          entries, &argc, &argv))
        return RF_EXIT_USAGE;
    if (argc > 1 || reps < 1 || !(min_time >= 0)) {
        fprintf(stderr, "rigflow ik-bench: unexpected arguments (see rigflow ik-bench --help)\n");
        return RF_EXIT_USAGE;
    }
    GArray *solvers = find_solvers(reg, solver_names);
    int code = RF_EXIT_OK;
    if (list)
        code = list_all(solvers);
    else if (solvers->len == 0) {
        fprintf(stderr, "rigflow ik-bench: no IK solver plugin found%s\n",
                solver_names ? " under those names" : " (set RIGFLOW_PLUGIN_PATH)");
        code = RF_EXIT_USAGE;
    } else if (!make_states(solvers))
        code = RF_EXIT_RUN;
    else {
        if (!bvh)
            bvh = default_bvh();
        code = run_benchmarks(solvers, workloads, bvh, min_time, reps);
    }
    free_states(solvers);
    g_array_free(solvers, TRUE);
    return code;
}
