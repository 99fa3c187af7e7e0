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
 * table functions are only ever appended, in a new minor version. A reader checks RF_HAS_FIELD
 * before using a field a peer may lack.
 *
 * Threading: in ABI 1.0 the host calls every plugin function from one thread at a time; a plugin
 * needs no locking for state reached only through its own functions.
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
    rf_param_type type;
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

    /* Log a message, prefixed with the node's id (node may be NULL). */
    void (*log)(rf_node *node, rf_log_level level, const char *fmt, ...) RF_PRINTF(3, 4);
    /* Record why the node failed; the host reports it with the node's id when process or create
     * returns false. The last call wins. */
    void (*error)(rf_node *node, const char *fmt, ...) RF_PRINTF(2, 3);
    /* Report progress of long work, fraction in [0, 1]; cheap to call per frame. */
    void (*progress)(rf_node *node, double fraction);
    /* True once the user asked to stop (SIGINT): return false from process soon after. */
    bool (*cancelled)(rf_node *node);
    /* The node's id in the pipeline. (static for the run) */
    const char *(*node_id)(rf_node *node);

    /* Parameter values, already validated against the declaration, defaults filled in. Asking
     * for a name the node type did not declare, or with the wrong type, is a programming error:
     * the host logs it and returns 0/false/"". Strings are (borrowed, valid for the run). */
    bool (*param_bool)(rf_node *node, const char *name);
    int64_t (*param_int)(rf_node *node, const char *name);
    double (*param_float)(rf_node *node, const char *name);
    /* STRING, ENUM and path params. INPUT_PATH is resolved against the pipeline's folder;
     * OUTPUT_PATH is the temporary file to write (see rf_param_type). "" when unset. */
    const char *(*param_string)(rf_node *node, const char *name);
    /* For an OUTPUT_PATH param: the final path the user asked for, to name in messages. */
    const char *(*param_output_target)(rf_node *node, const char *name);

    /* Number of connections on an input port (0 for an unconnected optional port). */
    uint32_t (*input_count)(rf_node *node, const char *port);
    /* The value on connection `index` of an input port, or NULL. (borrowed, read-only, valid
     * until process returns) */
    const void *(*input)(rf_node *node, const char *port, uint32_t index);
    /* Hand the value of an output port to the host, which frees it with `destroy` when the run
     * no longer needs it. Returns false (and frees it at once) for an undeclared port or a port
     * set twice. (transfer full) */
    bool (*set_output)(rf_node *node, const char *port, void *data, rf_destroy_fn destroy);
} rf_host;

/* One node type. Lifecycle for each node of a pipeline: create once with the parameters (per-clip
 * set-up), process once per run with the inputs, destroy. Work that later versions will do per
 * frame for live input belongs in process's inner loop, set-up in create. */
typedef struct rf_node_desc {
    uint32_t size;    /* sizeof(rf_node_desc) */
    const char *type; /* unique across all plugins, e.g. "bvh.import" */
    rf_node_kind kind;
    const char *doc;  /* one paragraph for `rigflow describe` */
    uint32_t input_count;
    const rf_port_desc *inputs;
    uint32_t output_count;
    const rf_port_desc *outputs;
    uint32_t param_count;
    const rf_param_desc *params;

    /* Optional. Make the node's state into *self from its parameters. Return false after
     * host->error on failure (nothing to destroy then). */
    bool (*create)(const rf_host *host, rf_node *node, void **self);
    /* Required. Read inputs, set every output, return true; or call host->error and return
     * false. `self` is what create made, or NULL without create. */
    bool (*process)(void *self, const rf_host *host, rf_node *node);
    /* Optional. Free what create made. */
    void (*destroy)(void *self);
    /* Optional. A capability table by reverse-DNS id (e.g. "rigflow.ik/1"), or NULL. (static) */
    const void *(*get_extension)(const char *id);
} rf_node_desc;

/* The one exported symbol: `RF_PLUGIN_EXPORT const rf_plugin_entry rigflow_plugin_entry`. */
typedef struct rf_plugin_entry {
    rf_version abi;          /* RF_ABI_VERSION_INIT: always the first field */
    uint32_t size;           /* sizeof(rf_plugin_entry) */
    const char *id;          /* reverse-DNS, unique, e.g. "org.rigflow.bvh" */
    const char *name;        /* human name */
    const char *version;     /* the plugin's own version */
    const char *description; /* one line */
    /* Optional. Called once after loading. Return false with a message in err (err_size bytes,
     * NUL-terminated) to refuse loading. */
    bool (*init)(const rf_host *host, char *err, size_t err_size);
    /* Optional. Called once before unloading, only if init succeeded or was absent. */
    void (*deinit)(void);
    uint32_t node_count;
    const rf_node_desc *const *nodes; /* (static) */
} rf_plugin_entry;

#ifdef __cplusplus
}
#endif

#endif
