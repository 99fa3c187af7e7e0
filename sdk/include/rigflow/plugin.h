/* rigflow SDK: the plugin ABI.
 *
 * A plugin is a shared object that exports exactly one symbol, `rigflow_plugin_entry`, a const
 * rf_plugin_entry. The entry names the node types the plugin provides; each node type declares
 * its kind, typed input and output ports, and parameters. The host validates pipelines against
 * these declarations before it runs anything, then drives each node through create, process and
 * destroy. Everything a plugin needs from the host (parameters, inputs, outputs, logging,
 * progress, errors) comes through the rf_host table passed in, so a plugin links nothing from the
 * host and needs only these headers.
 *
 * Growth rules: every struct that crosses the boundary starts with a size field (sizeof at the
 * producer's build, except rf_plugin_entry, whose first field is the ABI version); fields and
 * table functions are only ever appended, in a new minor version. Each struct's 1.0 layout is its
 * minimum (the RF_*_SIZE_1_0 constants below): the host refuses anything smaller, copies what a
 * plugin gives it (min(size, sizeof)) into a zeroed struct of its own build, so a field appended
 * after the plugin was built reads as zero, and walks a plugin's descriptor arrays by their
 * elements' own size, never by its own sizeof. Kinds and types are fixed-width integers, never
 * enums, whose size is the compiler's choice. A reader checks RF_HAS_FIELD before using a field a
 * peer may lack.
 *
 * Threading, marked on every function below:
 *   [main-thread]  called by the host from the thread that loaded the plugin (init, deinit,
 *                  get_extension), never concurrently with another call into the same plugin;
 *   [node-thread]  called for one node at a time: create, process and destroy of one node never
 *                  overlap, but a host running several pipelines at once (a batch of runs in
 *                  threads, a live loop beside an offline run) may call them for different nodes
 *                  from different threads at once, so state shared between nodes must be
 *                  read-only or locked;
 *   [thread-safe]  host services a plugin may call from any thread during the call it was
 *                  handed the host in.
 * Separate processes (batch workers) share nothing and need no care.
 *
 * Annotations: (borrowed) the caller keeps ownership and the pointer is valid only for the call
 * unless said otherwise; (transfer full) the receiver owns it; (static) valid while the plugin is
 * loaded.
 */
#ifndef RIGFLOW_PLUGIN_H
#define RIGFLOW_PLUGIN_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "model.h"
#include "version.h"

#ifdef __cplusplus
extern "C" {
#endif

#if defined(__GNUC__) || defined(__clang__)
#define RF_PLUGIN_EXPORT __attribute__((visibility("default")))
#define RF_PRINTF(fmt, args) __attribute__((format(printf, fmt, args)))
#else
#define RF_PLUGIN_EXPORT
#define RF_PRINTF(fmt, args)
#endif

/* The name of the one symbol a plugin exports. */
#define RF_PLUGIN_ENTRY_SYMBOL "rigflow_plugin_entry"

/* Values of rf_node_desc.kind (a uint32_t in the struct: an enum's size is the compiler's). */
typedef enum rf_node_kind {
    RF_KIND_IMPORTER = 1, /* reads files into data */
    RF_KIND_EXPORTER,     /* writes data to files */
    RF_KIND_MATCHER,      /* maps joints between skeletons */
    RF_KIND_RETARGETER,   /* moves motion from source skeletons to a target */
    RF_KIND_IK,           /* inverse kinematics solvers */
    RF_KIND_RIGGER,       /* builds skeletons and skins for meshes */
    RF_KIND_FILTER,       /* transforms data of one type into the same type */
    RF_KIND_REPORT,       /* measures and summarises */
} rf_node_kind;

/* Values of rf_param_desc.type (a uint32_t in the struct). */
typedef enum rf_param_type {
    RF_PARAM_BOOL = 1,    /* JSON true/false */
    RF_PARAM_INT,         /* JSON integer; range in min/max when RF_PARAM_HAS_RANGE */
    RF_PARAM_FLOAT,       /* JSON number; range in min/max when RF_PARAM_HAS_RANGE */
    RF_PARAM_STRING,      /* JSON string */
    RF_PARAM_ENUM,        /* JSON string, one of `choices` */
    RF_PARAM_INPUT_PATH,  /* a file read by the node; relative paths resolve against the pipeline */
    RF_PARAM_OUTPUT_PATH, /* a file written by the node: the node is handed a temporary path in
                           * the same folder, with the same extension, and the host renames it
                           * into place only when the whole run succeeds */
} rf_param_type;

enum rf_param_flags {
    RF_PARAM_REQUIRED = 1u << 0,  /* no default: a pipeline must set it */
    RF_PARAM_HAS_RANGE = 1u << 1, /* min and max bound an INT or FLOAT (inclusive) */
};

typedef struct rf_param_desc {
    uint32_t size;              /* sizeof(rf_param_desc) */
    const char *name;           /* [a-z0-9_-]+, unique within the node type */
    uint32_t type;              /* rf_param_type */
    uint32_t flags;             /* rf_param_flags */
    double default_number;      /* BOOL (0/1), INT, FLOAT default */
    const char *default_string; /* STRING, ENUM or path default; NULL means "" */
    double min, max;            /* with RF_PARAM_HAS_RANGE */
    const char *choices;        /* ENUM: the allowed values separated by '|' */
    const char *doc;            /* one line for `rigflow describe` */
} rf_param_desc;

enum rf_port_flags {
    RF_PORT_OPTIONAL = 1u << 0, /* an input that may stay unconnected */
    RF_PORT_MULTIPLE = 1u << 1, /* an input that takes one or more connections, in order */
};

typedef struct rf_port_desc {
    uint32_t size;    /* sizeof(rf_port_desc) */
    const char *name; /* unique among the node type's inputs (or outputs) */
    const char *type; /* type id, e.g. RF_TYPE_SKELETON; third parties use reverse-DNS ids */
    uint32_t flags;   /* rf_port_flags (inputs only) */
    const char *doc;
} rf_port_desc;

/* The host's handle on one node of a running pipeline. Opaque to plugins. */
typedef struct rf_node rf_node;

typedef enum rf_log_level {
    RF_LOG_ERROR = 0,
    RF_LOG_WARNING,
    RF_LOG_INFO,
    RF_LOG_DEBUG,
} rf_log_level;

typedef void (*rf_destroy_fn)(void *data);

/* Services the host offers. Passed to init, create and process; valid while the plugin is loaded.
 * Functions taking an rf_node accept only the node being created or processed at the time. */
typedef struct rf_host {
    uint32_t size;  /* sizeof(rf_host) at the host's build */
    rf_version abi; /* the host's ABI version */

    /* [thread-safe] Log a message, prefixed with the node's id (node may be NULL). */
    void (*log)(rf_node *node, rf_log_level level, const char *fmt, ...) RF_PRINTF(3, 4);
    /* [thread-safe] Record why the node failed; the host reports it with the node's id when process
     * or create returns false. The last call wins. */
    void (*error)(rf_node *node, const char *fmt, ...) RF_PRINTF(2, 3);
    /* [thread-safe] Report progress of long work, fraction in [0, 1]; cheap to call per frame. */
    void (*progress)(rf_node *node, double fraction);
    /* [thread-safe] True once the user asked to stop (SIGINT): return false from process soon
     * after. */
    bool (*cancelled)(rf_node *node);
    /* [thread-safe] The node's id in the pipeline. (static for the run) */
    const char *(*node_id)(rf_node *node);

    /* [thread-safe] Parameter values, already validated against the declaration, defaults filled
     * in. Each getter reads its own type only (param_float also reads an INT parameter): asking
     * for a name the node type did not declare, or with another type, is a programming error:
     * the host logs it and returns 0/false/"". Strings are (borrowed, valid for the run). */
    bool (*param_bool)(rf_node *node, const char *name);
    int64_t (*param_int)(rf_node *node, const char *name);
    double (*param_float)(rf_node *node, const char *name);
    /* STRING, ENUM and path params. INPUT_PATH is resolved against the pipeline's folder;
     * OUTPUT_PATH is the temporary file to write (see rf_param_type). "" when unset. */
    const char *(*param_string)(rf_node *node, const char *name);
    /* For an OUTPUT_PATH param: the final path the user asked for, to name in messages. */
    const char *(*param_output_target)(rf_node *node, const char *name);

    /* [thread-safe] Number of connections on an input port (0 for an unconnected optional port). */
    uint32_t (*input_count)(rf_node *node, const char *port);
    /* [thread-safe] The value on connection `index` of an input port, or NULL. (borrowed,
     * read-only, valid until process returns) */
    const void *(*input)(rf_node *node, const char *port, uint32_t index);
    /* [thread-safe] Hand the value of an output port to the host, which frees it with `destroy`
     * when the run no longer needs it. Returns false (and frees it at once) for an undeclared port
     * or a port set twice. (transfer full) */
    bool (*set_output)(rf_node *node, const char *port, void *data, rf_destroy_fn destroy);

    /* Appended in 1.3 (check with RF_HAS_FIELD, or call rf_node_out below): */
    /* [thread-safe] The stream a node prints its results on (what `rigflow run` shows on stdout):
     * stdout while the node runs alone; a buffer of the host's while it runs beside other nodes
     * (RF_NODE_CONCURRENT), which the host copies to stdout, with the node's log lines to stderr,
     * once every node before it in the run's order has printed, so the output reads byte for byte
     * as a run of one node at a time. (borrowed, valid during process) */
    FILE *(*out)(rf_node *node);
} rf_host;

/* One node type. Lifecycle for each node of a pipeline: create once with the parameters (per-clip
 * set-up), process once per run with the inputs, destroy. Work that later versions will do per
 * frame for live input belongs in process's inner loop, set-up in create. */
typedef struct rf_node_desc {
    uint32_t size;    /* sizeof(rf_node_desc) */
    const char *type; /* unique across all plugins, e.g. "bvh.import" */
    uint32_t kind;    /* rf_node_kind */
    const char *doc;  /* one paragraph for `rigflow describe` */
    uint32_t input_count;
    const rf_port_desc *inputs;
    uint32_t output_count;
    const rf_port_desc *outputs;
    uint32_t param_count;
    const rf_param_desc *params;

    /* [node-thread] Optional. Make the node's state into *self from its parameters. Return false
     * after host->error on failure (nothing to destroy then). */
    bool (*create)(const rf_host *host, rf_node *node, void **self);
    /* [node-thread] Required. Read inputs, set every output, return true; or call host->error and
     * return false. `self` is what create made, or NULL without create. */
    bool (*process)(void *self, const rf_host *host, rf_node *node);
    /* [node-thread] Optional. Free what create made. */
    void (*destroy)(void *self);
    /* [main-thread] Optional. A capability table by reverse-DNS id (e.g. "rigflow.ik/1"), or NULL.
     * (static) */
    const void *(*get_extension)(const char *id);

    /* Appended in 1.3 (zero in a descriptor built before it): */
    uint32_t flags; /* rf_node_flags */
} rf_node_desc;

/* Bits of rf_node_desc.flags. */
enum rf_node_flags {
    /* process may run on a thread of the host's while nodes of the same run that do not read its
     * outputs (nor it theirs) process on others. The node type promises that process prints only
     * through host->out and host->log, writes no file but its OUTPUT_PATH parameters' temporary
     * files, and changes no process-wide state (current folder, locale, signal handlers, the
     * standard streams, global variables of a library it shares with other node types). Without
     * the flag a node processes alone, as every node did before 1.3. */
    RF_NODE_CONCURRENT = 1u << 0,
};

/* A self-test a node type may offer through get_extension(RF_SELFTEST_EXTENSION). `rigflow
 * plugin-check` runs it in a separate process: it should exercise the node's core on data it
 * makes itself and return false with a message in err (err_size bytes) when something is wrong. */
#define RF_SELFTEST_EXTENSION "rigflow.selftest/1"
typedef struct rf_selftest {
    uint32_t size;                                                /* sizeof(rf_selftest) */
    bool (*run)(const rf_host *host, char *err, size_t err_size); /* [main-thread] */
} rf_selftest;

/* What an importer reads, offered by a node type of kind RF_KIND_IMPORTER through
 * get_extension(RF_IMPORTER_EXTENSION), so that a host can pick the importer for a file from its
 * name (`rigflow inspect`, `rigflow map`) without knowing any plugin: a node type that lists the
 * file's suffix is preferred to one that reads anything ("*"), and among equals the first loaded.
 */
#define RF_IMPORTER_EXTENSION "rigflow.importer/1"
typedef struct rf_importer_info {
    uint32_t size;          /* sizeof(rf_importer_info) */
    const char *suffixes;   /* file name endings read, '|'-separated, without the dot, matched
                             * without regard to case ("bvh", "glb|gltf"), or "*" for whatever
                             * the node's library reads */
    const char *path_param; /* the node's INPUT_PATH parameter that names the file */
} rf_importer_info;

/* The one exported symbol: `RF_PLUGIN_EXPORT const rf_plugin_entry rigflow_plugin_entry`. */
typedef struct rf_plugin_entry {
    rf_version abi;          /* RF_ABI_VERSION_INIT: always the first field */
    uint32_t size;           /* sizeof(rf_plugin_entry) */
    const char *id;          /* reverse-DNS, unique, e.g. "org.rigflow.bvh" */
    const char *name;        /* human name */
    const char *version;     /* the plugin's own version */
    const char *description; /* one line */
    /* [main-thread] Optional. Called once after loading. Return false with a message in err
     * (err_size bytes, NUL-terminated) to refuse loading. */
    bool (*init)(const rf_host *host, char *err, size_t err_size);
    /* [main-thread] Optional. Called once before unloading, only if init succeeded or was absent.
     */
    void (*deinit)(void);
    uint32_t node_count;
    const rf_node_desc *const *nodes; /* (static) */
} rf_plugin_entry;

/* ---- descriptor builders ----
 * Designated initialisers that set the size and leave every field not named zero (no default,
 * no range, no flags), so a descriptor reads as what it declares and survives appended fields:
 *
 *   static const rf_param_desc params[] = {
 *       RF_PARAM_DESC_INT("window", 5, 1, 99, "frames averaged around each frame"),
 *       RF_PARAM_DESC_ENUM("mode", "fast", "fast|exact", "how the average is taken"),
 *       RF_PARAM_DESC(.name = "path", .type = RF_PARAM_INPUT_PATH, .flags = RF_PARAM_REQUIRED,
 *                     .doc = "the file to read"),
 *   };
 *   static const rf_port_desc inputs[] = {RF_PORT_DESC("animation", RF_TYPE_ANIMATION, 0, "...")};
 *   static const rf_node_desc smooth = {
 *       .size = sizeof(rf_node_desc), .type = "example.smooth", .kind = RF_KIND_FILTER,
 *       RF_NODE_INPUTS(inputs), RF_NODE_OUTPUTS(outputs), RF_NODE_PARAMS(params),
 *       .process = smooth_process,
 *   };
 */
#define RF_COUNT_OF(array) ((uint32_t)(sizeof(array) / sizeof((array)[0])))

#define RF_PARAM_DESC(...)                                                                         \
    {                                                                                              \
        .size = sizeof(rf_param_desc), __VA_ARGS__                                                 \
    }
#define RF_PARAM_DESC_BOOL(name_, default_, doc_)                                                  \
    RF_PARAM_DESC(.name = (name_), .type = RF_PARAM_BOOL, .default_number = (default_),            \
                  .doc = (doc_))
#define RF_PARAM_DESC_INT(name_, default_, min_, max_, doc_)                                       \
    RF_PARAM_DESC(.name = (name_), .type = RF_PARAM_INT, .flags = RF_PARAM_HAS_RANGE,              \
                  .default_number = (default_), .min = (min_), .max = (max_), .doc = (doc_))
#define RF_PARAM_DESC_FLOAT(name_, default_, min_, max_, doc_)                                     \
    RF_PARAM_DESC(.name = (name_), .type = RF_PARAM_FLOAT, .flags = RF_PARAM_HAS_RANGE,            \
                  .default_number = (default_), .min = (min_), .max = (max_), .doc = (doc_))
#define RF_PARAM_DESC_STRING(name_, default_, doc_)                                                \
    RF_PARAM_DESC(.name = (name_), .type = RF_PARAM_STRING, .default_string = (default_),          \
                  .doc = (doc_))
#define RF_PARAM_DESC_ENUM(name_, default_, choices_, doc_)                                        \
    RF_PARAM_DESC(.name = (name_), .type = RF_PARAM_ENUM, .default_string = (default_),            \
                  .choices = (choices_), .doc = (doc_))
/* A file the node reads or writes; `flags` RF_PARAM_REQUIRED or 0 (optional: "" when unset). */
#define RF_PARAM_DESC_INPUT_PATH(name_, flags_, doc_)                                              \
    RF_PARAM_DESC(.name = (name_), .type = RF_PARAM_INPUT_PATH, .flags = (flags_), .doc = (doc_))
#define RF_PARAM_DESC_OUTPUT_PATH(name_, flags_, doc_)                                             \
    RF_PARAM_DESC(.name = (name_), .type = RF_PARAM_OUTPUT_PATH, .flags = (flags_), .doc = (doc_))

#define RF_PORT_DESC(name_, type_, flags_, doc_)                                                   \
    {                                                                                              \
        .size = sizeof(rf_port_desc), .name = (name_), .type = (type_), .flags = (flags_),         \
        .doc = (doc_)                                                                              \
    }

/* A node descriptor's counted arrays, counted by the compiler. */
#define RF_NODE_INPUTS(array) .input_count = RF_COUNT_OF(array), .inputs = (array)
#define RF_NODE_OUTPUTS(array) .output_count = RF_COUNT_OF(array), .outputs = (array)
#define RF_NODE_PARAMS(array) .param_count = RF_COUNT_OF(array), .params = (array)

/* A get_extension function named `fn` that offers the self-test `run` (and nothing else):
 *   static bool my_selftest(const rf_host *host, char *err, size_t err_size) { ... }
 *   RF_SELFTEST_GET_EXTENSION(my_get_extension, my_selftest)
 *   ... .get_extension = my_get_extension, ... */
#define RF_SELFTEST_GET_EXTENSION(fn, run)                                                         \
    static const rf_selftest fn##_selftest = {sizeof(rf_selftest), (run)};                         \
    static const void *fn(const char *id)                                                          \
    {                                                                                              \
        return strcmp(id, RF_SELFTEST_EXTENSION) == 0 ? &fn##_selftest : NULL;                     \
    }

/* The plugin's one exported symbol, its node types counted from the array `nodes_`
 * (`static const rf_node_desc *const nodes_[] = {&a, &b};`). */
#define RF_PLUGIN_DEFINE(id_, name_, version_, description_, nodes_)                               \
    RF_PLUGIN_EXPORT const rf_plugin_entry rigflow_plugin_entry = {                                \
        .abi = RF_ABI_VERSION_INIT,                                                                \
        .size = sizeof(rf_plugin_entry),                                                           \
        .id = (id_),                                                                               \
        .name = (name_),                                                                           \
        .version = (version_),                                                                     \
        .description = (description_),                                                             \
        .node_count = RF_COUNT_OF(nodes_),                                                         \
        .nodes = (nodes_),                                                                         \
    }

/* Where node's results are printed: host->out(node) from a host that offers it (1.3), else
 * stdout (a 1.3 plugin is only loaded by a 1.3 host, but an embedding host may hand an older
 * table). (borrowed, valid during process) */
static inline FILE *rf_node_out(const rf_host *host, rf_node *node)
{
    return RF_HAS_FIELD(host, rf_host, out) && host->out ? host->out(node) : stdout;
}

/* The 1.0 layout of each struct, the smallest a host accepts (see the growth rules above). */
#define RF_PLUGIN_ENTRY_SIZE_1_0 RF_SIZE_THROUGH(rf_plugin_entry, nodes)
#define RF_NODE_DESC_SIZE_1_0 RF_SIZE_THROUGH(rf_node_desc, get_extension)
#define RF_PORT_DESC_SIZE_1_0 RF_SIZE_THROUGH(rf_port_desc, doc)
#define RF_PARAM_DESC_SIZE_1_0 RF_SIZE_THROUGH(rf_param_desc, doc)
#define RF_HOST_SIZE_1_0 RF_SIZE_THROUGH(rf_host, set_output)
#define RF_SELFTEST_SIZE_1_0 RF_SIZE_THROUGH(rf_selftest, run)
#define RF_IMPORTER_INFO_SIZE_1_0 RF_SIZE_THROUGH(rf_importer_info, path_param)

#ifdef __cplusplus
}
#endif

#endif
