/* rigflow: the command. Loads plugins from the search path, then runs one subcommand. */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "batch.h"
#include "commands.h"
#include "config.h"
#include "ik-bench.h"
#include "rig-bench.h"
#include "inspect.h"
#include "map-cmd.h"
#include "report-cmd.h"

static volatile sig_atomic_t interrupted; /* C11 7.14.1.1: what a handler may write */

static void on_sigint(int sig)
{
    (void)sig;
    interrupted = 1;
    signal(SIGINT, SIG_DFL); /* a second Ctrl-C stops at once */
}

void rf_print_diags(const GPtrArray *diags, const char *severity)
{
    for (guint i = 0; i < diags->len; i++) {
        g_autofree char *line = rf_diag_format(g_ptr_array_index((GPtrArray *)diags, i));
        fprintf(stderr, "rigflow: %s: %s\n", severity, line);
    }
}

bool rf_parse_options(const char *name, const char *args, const char *summary,
                      const GOptionEntry *entries, int *argc, char ***argv)
{
    /* the usage line reads "rigflow NAME [OPTION…] ARGS" */
    g_autofree char *prgname = g_strdup_printf("rigflow %s", name);
    g_set_prgname(prgname);
    g_autoptr(GOptionContext) ctx = g_option_context_new(args);
    g_option_context_set_summary(ctx, summary);
    if (entries)
        g_option_context_add_main_entries(ctx, entries, NULL);
    g_autoptr(GError) error = NULL;
    if (!g_option_context_parse(ctx, argc, argv, &error)) {
        fprintf(stderr, "rigflow %s: %s (see rigflow %s --help)\n", name, error->message, name);
        return false;
    }
    return true;
}

bool rf_check_utf8_name(const char *name, const char *file)
{
    if (g_utf8_validate(file, -1, NULL))
        return true;
    g_autofree char *shown = rf_printable(file);
    fprintf(stderr,
            "rigflow %s: %s: expected a file name in UTF-8 text (pipelines are JSON, which holds "
            "only UTF-8); rename the file, e.g. with convmv\n",
            name, shown);
    return false;
}

/* Nodes processed at once by the runs of this process: `run --jobs`, else one per processor. */
static gint run_jobs;

static int run_with(rf_pipeline *p, const rf_registry *reg, bool profile, bool quiet, FILE *out,
                    GPtrArray *diags)
{
    rf_run_options opts;
    rf_run_options_init(&opts);
    opts.profile = profile, opts.quiet = quiet, opts.progress = isatty(2) != 0;
    opts.cancel_flag = &interrupted;
    opts.jobs = run_jobs > 0 ? (unsigned)run_jobs : g_get_num_processors();
    opts.out = out;
    interrupted = 0;
    signal(SIGINT, on_sigint);
    bool ok = rf_pipeline_run(p, reg, &opts, diags);
    signal(SIGINT, SIG_DFL);
    return ok ? RF_EXIT_OK : interrupted ? RF_EXIT_CANCELLED : RF_EXIT_RUN;
}

int rf_run_interruptible_diags(rf_pipeline *p, const rf_registry *reg, bool profile, bool quiet,
                               GPtrArray *diags)
{
    return run_with(p, reg, profile, quiet, NULL, diags);
}

int rf_run_interruptible_out(rf_pipeline *p, const rf_registry *reg, FILE *out, GPtrArray *diags)
{
    return run_with(p, reg, false, true, out, diags);
}

int rf_run_interruptible(rf_pipeline *p, const rf_registry *reg, bool profile, bool quiet)
{
    g_autoptr(GPtrArray) diags = rf_diags_new();
    int code = rf_run_interruptible_diags(p, reg, profile, quiet, diags);
    rf_print_diags(diags, "error");
    return code;
}

/* Each NODE.PARAM once: a second -p of one parameter is a slip (for another parameter), and the
 * run would silently keep the last value. */
static void check_repeats(const char *path, char **params, GPtrArray *diags)
{
    for (char **a = params; a && *a; a++) {
        size_t n = strcspn(*a, "=");
        for (char **b = params; b != a; b++)
            if (strcspn(*b, "=") == n && !strncmp(*a, *b, n)) {
                rf_diags_add(diags, path, 0, 0, NULL, NULL,
                             "-p %.*s given twice ('%s' and '%s'): expected each parameter once",
                             (int)n, *a, *b, *a);
                break;
            }
    }
}

/* Loads, overrides and validates a pipeline; prints what is wrong. Returns NULL with *code set. */
static rf_pipeline *prepare(rf_registry *reg, const char *path, char **params, int *code)
{
    g_autoptr(GPtrArray) diags = rf_diags_new();
    rf_pipeline *p = rf_pipeline_load(path, diags);
    check_repeats(path, params, diags);
    for (char **kv = params; p && kv && *kv; kv++)
        rf_pipeline_override(p, *kv, diags);
    if (p) /* validated even after a bad override, so every problem is listed at once */
        rf_pipeline_validate(p, reg, diags);
    rf_registry_take_diags(reg, diags); /* a plugin opened for the pipeline and refused */
    if (p && diags->len == 0)
        return p;
    rf_print_diags(diags, "error");
    fprintf(stderr, "rigflow: %s: %u problem%s found\n", path, diags->len,
            diags->len == 1 ? "" : "s");
    rf_pipeline_free(p);
    *code = RF_EXIT_VALIDATION;
    return NULL;
}

static int cmd_validate(rf_registry *reg, int argc, char **argv)
{
    g_auto(GStrv) params = NULL;
    const GOptionEntry entries[] = {{"param", 'p', 0, G_OPTION_ARG_FILENAME_ARRAY, &params,
                                     "Override a parameter", "NODE.PARAM=VALUE"},
                                    {NULL, 0, 0, 0, NULL, NULL, NULL}};
    if (!rf_parse_options("validate", "PIPELINE", "Check a pipeline without running it.", entries,
                          &argc, &argv) ||
        argc != 2) {
        if (argc != 2)
            fprintf(stderr, "rigflow validate: expected one PIPELINE file\n");
        return RF_EXIT_USAGE;
    }
    int code = RF_EXIT_OK;
    rf_pipeline *p = prepare(reg, argv[1], params, &code);
    if (p)
        printf("%s: valid\n", argv[1]);
    rf_pipeline_free(p);
    return code;
}

static int cmd_run(rf_registry *reg, int argc, char **argv)
{
    g_auto(GStrv) params = NULL;
    gboolean profile = FALSE, quiet = FALSE;
    const GOptionEntry entries[] = {
        {"param", 'p', 0, G_OPTION_ARG_FILENAME_ARRAY, &params,
         "Override a parameter (repeatable; relative paths are relative to the current folder)",
         "NODE.PARAM=VALUE"},
        {"profile", 0, 0, G_OPTION_ARG_NONE, &profile, "Print each node's run time", NULL},
        {"quiet", 'q', 0, G_OPTION_ARG_NONE, &quiet, "Print errors only", NULL},
        {"jobs", 'j', 0, G_OPTION_ARG_INT, &run_jobs,
         "Process up to N independent nodes at once (default: one per processor; 1: one after "
         "another). The output is the same either way",
         "N"},
        {NULL, 0, 0, 0, NULL, NULL, NULL}};
    run_jobs = -1; /* not given */
    if (!rf_parse_options("run", "PIPELINE", "Validate and run a pipeline.", entries, &argc, &argv))
        return RF_EXIT_USAGE;
    if (run_jobs == -1)
        run_jobs = 0;
    else if (run_jobs < 1) {
        fprintf(stderr, "rigflow run: --jobs %d: expected a count of 1 or more\n", run_jobs);
        return RF_EXIT_USAGE;
    }
    if (argc != 2) {
        fprintf(stderr, "rigflow run: expected one PIPELINE file (see rigflow run --help)\n");
        return RF_EXIT_USAGE;
    }
    int code = RF_EXIT_OK;
    gint64 t0 = g_get_monotonic_time();
    rf_pipeline *p = prepare(reg, argv[1], params, &code);
    if (!p)
        return code;
    if (profile) /* validation opens the plugins of the pipeline's node types (lazy loading) */
        fprintf(stderr, "profile: validation, plugins opened: %.3f ms\n",
                (double)(g_get_monotonic_time() - t0) / 1000.0);
    code = rf_run_interruptible(p, reg, profile, quiet || g_getenv("RIGFLOW_QUIET") != NULL);
    /* The process ends here, and its exit returns the run's memory at once: freeing the retarget
     * pipeline's 30 MB of clips and meshes block by block (rf_pipeline_free, as an embedding host
     * does), then closing the plugins, took about 1 ms more. exit, not return: main would close
     * the plugins; stdio is flushed and leak checkers still see the pipeline from this frame. */
    fflush(NULL);
    exit(code);
}

typedef struct command {
    const char *name;
    rf_command_fn fn;
    const char *summary;
} command;

static const command commands[] = {
    {"run", cmd_run, "validate and run a pipeline"},
    {"validate", cmd_validate, "check a pipeline without running it"},
    {"plugins", rf_cmd_plugins, "list the plugins found and their node types"},
    {"describe", rf_cmd_describe, "show a node type's ports and parameters"},
    {"inspect", rf_cmd_inspect, "show what a model or motion file imports as"},
    {"plugin-check", rf_cmd_plugin_check, "check plugin files, each check in its own process"},
    {"ik-bench", rf_cmd_ik_bench, "compare the IK solver plugins on standard workloads (CSV)"},
    {"rig-bench", rf_cmd_rig_bench, "compare the rigger plugins with artists' rigs (CSV)"},
    {"map", rf_cmd_map, "map a target skeleton's joints onto source skeletons"},
    {"report", rf_cmd_report, "retarget a clip and write an HTML page to look at the result"},
    {"batch", rf_cmd_batch, "run a pipeline over many inputs (worker pool or Slurm array)"},
};

static void print_help(void)
{
    printf("Usage: rigflow [--plugin-path DIR]... [--quiet] COMMAND [ARGS]...\n\n"
           "Run character animation pipelines built from plugins.\n\nCommands:\n");
    for (size_t i = 0; i < G_N_ELEMENTS(commands); i++)
        printf("  %-10s %s\n", commands[i].name, commands[i].summary);
    printf("\nOptions:\n"
           "  --plugin-path DIR  look for plugins in DIR first (repeatable); then\n"
           "                     $RIGFLOW_PLUGIN_PATH (colon-separated), then %s\n"
           "  -q, --quiet        print errors only\n"
           "  -h, --help         show this help (COMMAND --help for a command's)\n"
           "  --version          show the version\n\n"
           "Exit status: 0 ok, 1 run failed, 2 usage error, 3 invalid pipeline,\n"
           "4 plugin could not be loaded, 5 batch folder locked, 6 batch still queued,\n"
           "130 interrupted.\n",
           RF_PLUGINSDIR);
}

static const command *find_command(const char *name)
{
    for (size_t i = 0; i < G_N_ELEMENTS(commands); i++)
        if (strcmp(commands[i].name, name) == 0)
            return &commands[i];
    return NULL;
}

/* Global options come before the command; returns the index of the command, or -1 to exit with
 * *code. */
static int parse_globals(int argc, char **argv, GPtrArray *plugin_path, bool *quiet, int *code)
{
    int i = 1;
    for (; i < argc && argv[i][0] == '-'; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            print_help();
            return *code = RF_EXIT_OK, -1;
        } else if (!strcmp(a, "--version")) {
            printf("rigflow %s (plugin ABI %d.%d.%d)\n", PACKAGE_VERSION, RF_ABI_VERSION_MAJOR,
                   RF_ABI_VERSION_MINOR, RF_ABI_VERSION_PATCH);
            return *code = RF_EXIT_OK, -1;
        } else if (!strcmp(a, "--quiet") || !strcmp(a, "-q")) {
            *quiet = true;
        } else if (!strcmp(a, "--plugin-path") && i + 1 < argc) {
            g_ptr_array_add(plugin_path, argv[++i]);
        } else if (g_str_has_prefix(a, "--plugin-path=")) {
            g_ptr_array_add(plugin_path, (char *)a + strlen("--plugin-path="));
        } else {
            fprintf(stderr, "rigflow: unknown option %s (see rigflow --help)\n", a);
            return *code = RF_EXIT_USAGE, -1;
        }
    }
    if (i >= argc) {
        fprintf(stderr, "rigflow: no command given (see rigflow --help)\n");
        return *code = RF_EXIT_USAGE, -1;
    }
    return i;
}

/* When the command runs from a libtool build tree (unpacked, not installed), the plugins built
 * beside it: `_build/rigflow` then works without RIGFLOW_PLUGIN_PATH. NULL elsewhere. */
char *rf_build_tree_dir(void)
{
    g_autofree char *exe = g_file_read_link("/proc/self/exe", NULL);
    if (!exe)
        return NULL;
    char *dir = g_path_get_dirname(exe);
    g_autofree char *base = g_path_get_basename(dir);
    if (strcmp(base, ".libs") == 0) { /* libtool's wrapper runs .libs/lt-rigflow */
        char *up = g_path_get_dirname(dir);
        g_free(dir);
        dir = up;
    }
    g_autofree char *status = g_build_filename(dir, "config.status", NULL);
    if (g_file_test(status, G_FILE_TEST_EXISTS))
        return dir;
    g_free(dir);
    return NULL;
}

char *rf_pipeline_file(const char *name)
{
    g_autofree char *build = rf_build_tree_dir();
    return g_build_filename(build ? RF_SRC_PIPELINESDIR : RF_PIPELINESDIR, name, NULL);
}

static char *build_tree_plugins(void)
{
    g_autofree char *dir = rf_build_tree_dir();
    char *plugins = dir ? g_build_filename(dir, "plugins", NULL) : NULL;
    if (plugins && g_file_test(plugins, G_FILE_TEST_IS_DIR))
        return plugins;
    g_free(plugins);
    return NULL;
}

int main(int argc, char **argv)
{
    g_autoptr(GPtrArray) plugin_path = g_ptr_array_new();
    bool quiet = false;
    int code = RF_EXIT_OK;
    int first = parse_globals(argc, argv, plugin_path, &quiet, &code);
    if (first < 0)
        return code;
    const command *cmd = find_command(argv[first]);
    if (!cmd) {
        fprintf(stderr, "rigflow: unknown command '%s' (see rigflow --help)\n", argv[first]);
        return RF_EXIT_USAGE;
    }
    g_autofree char *built = build_tree_plugins();
    if (built && !g_getenv("RIGFLOW_PLUGIN_PATH"))
        g_ptr_array_add(plugin_path, built);
    g_ptr_array_add(plugin_path, NULL);
    rf_registry *reg = rf_registry_new();
    g_autoptr(GPtrArray) diags = rf_diags_new();
    /* Commands that look up only the node types of their pipeline open only those plugins. */
    rf_registry_set_lazy(reg, strcmp(cmd->name, "run") == 0 || strcmp(cmd->name, "validate") == 0 ||
                                  strcmp(cmd->name, "report") == 0);
    rf_registry_load_search_path(reg, (const char *const *)plugin_path->pdata, diags);
    if (quiet) /* --quiet also applies to the command's own logging */
        g_setenv("RIGFLOW_QUIET", "1", TRUE);
    bool listing = strcmp(cmd->name, "plugins") == 0;
    if (!quiet && !listing)
        rf_print_diags(diags, "warning");
    code = cmd->fn(reg, argc - first, argv + first);
    if (listing && diags->len) { /* refusals are part of what `plugins` reports */
        rf_print_diags(diags, "refused");
        code = code == RF_EXIT_OK ? RF_EXIT_PLUGIN : code;
    }
    rf_registry_free(reg);
    return code;
}
