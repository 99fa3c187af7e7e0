/* librigflow: the host side. Plugin loading and the registry of node types, pipeline loading,
 * validation and execution. Used by the rigflow command, the tests and the benchmarks; not part
 * of the plugin SDK (plugins see only sdk/include/rigflow).
 *
 * No global state: every function works on the objects passed in, so batch runs and several
 * pipelines in one process need no rewrite. libltdl itself is process-global; the loader guards
 * it with a lock.
 */
#ifndef RIGFLOW_HOST_H
#define RIGFLOW_HOST_H

#include <glib.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <rigflow/rigflow.h>

/* librigflow is built with hidden visibility; this marks its public functions. */
#define RF_HOST_API __attribute__((visibility("default")))

/* Exit codes of the rigflow command (doc/cli.md). */
enum rf_exit {
    RF_EXIT_OK = 0,
    RF_EXIT_RUN = 1,        /* a node failed while running, or a file could not be written */
    RF_EXIT_USAGE = 2,      /* bad command line */
    RF_EXIT_VALIDATION = 3, /* the pipeline is invalid (syntax, types, params, graph) */
    RF_EXIT_PLUGIN = 4,     /* a requested plugin could not be loaded */
    RF_EXIT_LOCKED = 5,     /* rigflow batch: another batch holds the output folder */
    RF_EXIT_QUEUED = 6,     /* rigflow batch --status: jobs still pending or running */
    RF_EXIT_CANCELLED = 130 /* interrupted by SIGINT */
};

/* ---- diagnostics ---- */

/* One problem found while loading plugins or validating a pipeline. */
typedef struct rf_diag {
    char *file;    /* the file concerned, or NULL */
    int line;      /* 1-based, or 0 */
    int column;    /* 1-based, or 0 */
    char *node;    /* node id, or NULL */
    char *pointer; /* JSON pointer into the pipeline, or NULL */
    char *message; /* what is wrong and what was expected */
} rf_diag;

/* A list of rf_diag; free with g_ptr_array_unref. */
RF_HOST_API GPtrArray *rf_diags_new(void);
RF_HOST_API void rf_diags_add(GPtrArray *diags, const char *file, int line, int column,
                              const char *node, const char *pointer, const char *fmt, ...)
    G_GNUC_PRINTF(7, 8);
/* "file:line:col: node 'id' at /pointer: message" with the parts that are present. */
RF_HOST_API char *rf_diag_format(const rf_diag *d);

/* `text` (NULL reads as "") with every byte that is not printable UTF-8 (controls other than
 * newline and tab, C1 controls, invalid sequences) written as \xNN, as rigflow/text.h escapes:
 * messages and listings quote names from files, and a hostile file must not drive the terminal.
 * (transfer full) */
RF_HOST_API char *rf_printable(const char *text);

/* ---- plugins and the registry ---- */

typedef struct rf_plugin rf_plugin; /* one loaded shared object */
typedef struct rf_registry rf_registry;

RF_HOST_API rf_registry *rf_registry_new(void);
/* Unloads every plugin (calling deinit) and frees the registry. NULL allowed. */
RF_HOST_API void rf_registry_free(rf_registry *reg);

/* Loads one plugin file (.so, or a libtool .la). On refusal returns false and adds a diag naming
 * the file: not a plugin, incompatible ABI, failed init, or duplicate node type. */
RF_HOST_API bool rf_registry_load_file(rf_registry *reg, const char *path, GPtrArray *diags);
/* Loads every plugin in a folder (a .la wins over the .so it describes). Returns the number
 * loaded; refusals go to diags. */
RF_HOST_API int rf_registry_load_dir(rf_registry *reg, const char *dir, GPtrArray *diags);
/* Loads from the search path, in order: `extra` folders (--plugin-path, may be NULL), then the
 * colon-separated RIGFLOW_PLUGIN_PATH, then the installed pluginsdir. A node type found in an
 * earlier folder shadows the same type later on the path. */
RF_HOST_API void rf_registry_load_search_path(rf_registry *reg, const char *const *extra,
                                              GPtrArray *diags);

/* Lazy loading, for commands that need only the node types they name (`rigflow run`): set
 * before rf_registry_load_search_path, it leaves the plugin files the plugin index knows
 * (framework/plugin-index.c) unopened until one of their node types is looked up, and opens all
 * of them when the plugins are listed (rf_registry_plugin_count, rf_registry_plugin,
 * rf_registry_importer_for). Files the index does not know are opened at once and entered. */
RF_HOST_API void rf_registry_set_lazy(rf_registry *reg, bool lazy);
/* Moves into diags the refusals met while opening plugins on demand (lazy loading). */
RF_HOST_API void rf_registry_take_diags(rf_registry *reg, GPtrArray *diags);

RF_HOST_API guint rf_registry_plugin_count(const rf_registry *reg);
RF_HOST_API const rf_plugin *rf_registry_plugin(const rf_registry *reg, guint index);
RF_HOST_API const rf_plugin_entry *rf_plugin_entry_of(const rf_plugin *p);
RF_HOST_API const char *rf_plugin_path(const rf_plugin *p);

/* The node type registered under `type`, or NULL; *plugin (may be NULL) gets its plugin. */
RF_HOST_API const rf_node_desc *rf_registry_find(const rf_registry *reg, const char *type,
                                                 const rf_plugin **plugin);

/* "importer", "exporter", ... or "unknown". */
/* The importer for the file `path`: the node type of kind importer whose rigflow.importer/1
 * extension lists the file's suffix, else the first that reads anything ("*"); NULL when none
 * does. *path_param receives the parameter that takes the file's path. (borrowed) */
RF_HOST_API const rf_node_desc *rf_registry_importer_for(const rf_registry *reg, const char *path,
                                                         const char **path_param);

RF_HOST_API const char *rf_kind_name(rf_node_kind kind);
RF_HOST_API const char *rf_param_type_name(rf_param_type type);

/* ---- pipelines ---- */

typedef struct rf_pipeline rf_pipeline;

/* Options for a run. The struct grows by appending fields, as the plugin ABI's structs do, and
 * starts with its size so librigflow reads only the fields the caller was built with (older or
 * newer): begin with rf_run_options_init(&o), then set what you need. Every zero is a sensible
 * default. A struct zero-initialised without it (size 0, `rf_run_options o = {.quiet = true}`)
 * still works: it is read as the fields through `out`, and fields appended later take their
 * defaults there. A caller built against a newer librigflow whose struct is longer than this
 * one's may leave the fields this librigflow does not know at zero (their defaults); any of them
 * set fails the run with a diag rather than be ignored. doc/architecture.md, "The host API". */
typedef struct rf_run_options {
    /* sizeof(rf_run_options) as the caller was built (rf_run_options_init sets it); 0: every
     * field through `out` */
    size_t size;
    bool profile;  /* print per-node wall time to stderr */
    bool quiet;    /* no progress, no info logs */
    bool progress; /* draw progress on stderr (the command sets it for a terminal) */
    /* set non-zero (from a signal handler) to stop the run: sig_atomic_t, the one type C11
     * (7.14.1.1) lets a handler write; librigflow is not the plugin ABI (sdk/include/rigflow),
     * and sig_atomic_t is int on the platforms it builds for, so hosts built against
     * `volatile int *` still link and run */
    volatile sig_atomic_t *cancel_flag;
    /* the most nodes processed at once: 0 or 1, one after another; N, nodes of types marked
     * RF_NODE_CONCURRENT that do not read each other's outputs process up to N at a time, their
     * output printed in the order a run of one at a time prints it */
    unsigned jobs;
    /* where nodes print their results (rf_host.out): NULL for stdout; a command whose own
     * stdout is a table (rig-bench's CSV) sends a node's lines elsewhere */
    FILE *out;
    /* new fields go here, at the end, read only when `size` covers them (RF_HAS_FIELD) */
} rf_run_options;

/* The fields a struct with size 0 holds: the layout when `size` was introduced. */
#define RF_RUN_OPTIONS_SIZE_1 RF_SIZE_THROUGH(rf_run_options, out)

/* Every option at its default and `size` set to this header's struct: inline, so the size is
 * the caller's, whatever librigflow it runs against. Every byte is cleared, padding too: a longer
 * struct's bytes past the fields librigflow knows must read zero. */
static inline void rf_run_options_init(rf_run_options *o)
{
    memset(o, 0, sizeof *o);
    o->size = sizeof *o;
}

/* Parses a pipeline file. Returns NULL with diags on a syntax or structure error. */
RF_HOST_API rf_pipeline *rf_pipeline_load(const char *path, GPtrArray *diags);
/* Parses pipeline JSON text; `dir` is the folder relative paths resolve against, `name` the
 * file name used in messages. */
RF_HOST_API rf_pipeline *rf_pipeline_load_string(const char *text, const char *name,
                                                 const char *dir, GPtrArray *diags);
RF_HOST_API void rf_pipeline_free(rf_pipeline *p);
/* Applies "node.param=value". The value is kept as text and typed at validation by the
 * parameter's declaration (bool: true, false, 1 or 0; int and float: a whole decimal number;
 * strings, enums and paths: the text as it is, a relative path resolved against the current
 * folder, not the pipeline's), so "-p x.name=123" stays the string "123" for a string
 * parameter. A value that does not read as the declared type fails validation, naming it.
 * Returns false with a diag for a malformed override or an unknown node. */
RF_HOST_API bool rf_pipeline_override(rf_pipeline *p, const char *assignment, GPtrArray *diags);
/* Staged validation against the registry. Adds every problem found to diags; true when none. */
RF_HOST_API bool rf_pipeline_validate(rf_pipeline *p, const rf_registry *reg, GPtrArray *diags);
/* Runs a validated pipeline with `opts` (NULL: every default; see rf_run_options). On failure
 * returns false with a diag naming the failing node; no output file is left behind. */
RF_HOST_API bool rf_pipeline_run(rf_pipeline *p, const rf_registry *reg, const rf_run_options *opts,
                                 GPtrArray *diags);
/* The output value of `node.port` after a successful run (borrowed, valid until the pipeline is
 * freed), or NULL. For tests and embedding. */
RF_HOST_API const void *rf_pipeline_result(const rf_pipeline *p, const char *node,
                                           const char *port);

/* The start of the name of the temporary file a run writes `target` to, in the target's folder,
 * until the run succeeds: ".STEM.rf-" (the stem cut at 200 bytes), then 6 random characters and
 * the target's extension. For tools that clean up after a run killed before it could (rigflow
 * batch). (transfer full) */
RF_HOST_API char *rf_output_temp_prefix(const char *target);

/* Calls fn for every output-path parameter of a validated pipeline, in file order: the node id,
 * the parameter's name and the final path asked for ("" when unset). For batch runs, which name
 * each job's outputs. */
typedef void (*rf_output_param_fn)(const char *node, const char *param, const char *path,
                                   void *data);
RF_HOST_API void rf_pipeline_foreach_output(const rf_pipeline *p, rf_output_param_fn fn,
                                            void *data);

/* Creates and destroys one node of `type` with default parameters (a plugin's self-check).
 * Returns false with a diag when create fails. */
RF_HOST_API bool rf_node_type_try_create(const rf_registry *reg, const char *type,
                                         GPtrArray *diags);

/* The rf_host table the engine hands to plugins. */
RF_HOST_API const rf_host *rf_host_table(void);

#endif
