/* The pipeline engine's internal data: shared by pipeline.c (loading), validate.c (checks),
 * run.c (execution) and host.c (the services plugins call while a node runs). */
#ifndef RIGFLOW_PIPELINE_INTERNAL_H
#define RIGFLOW_PIPELINE_INTERNAL_H

#include <jansson.h>

#include "rigflow-host.h"

/* The format this host reads: "format": RF_PIPELINE_FORMAT, "version": RF_PIPELINE_VERSION. */
#define RF_PIPELINE_FORMAT "rigflow.pipeline"
#define RF_PIPELINE_VERSION 1

/* One edge into an input port: "node.port". */
typedef struct rf_conn {
    char *node;          /* upstream node id */
    char *port;          /* upstream output port */
    struct rf_node *src; /* resolved at validation */
    uint32_t src_port;   /* index into src's outputs */
    char *pointer;       /* JSON pointer of the edge, for messages */
} rf_conn;

/* A parameter's value after validation, defaults filled in. */
typedef struct rf_pvalue {
    uint32_t type; /* rf_param_type of the declaration: the getters read their own type only */
    bool b;
    int64_t i;
    double f;
    char *s;      /* strings, enums, resolved paths (for outputs: the temporary file) */
    char *target; /* OUTPUT_PATH: the final path */
} rf_pvalue;

typedef struct rf_output {
    void *data;            /* what consumers read: `owned`, or its copy in this build's layout */
    rf_destroy_fn destroy; /* the producer's, for `owned` */
    bool set;
    void *owned; /* what the producer handed over */
} rf_output;

struct rf_node {
    guint index; /* position in pipeline->nodes */
    char *id;
    char *type;
    char *pointer;  /* "/nodes/N" */
    json_t *json;   /* the node's object (borrowed from the pipeline's root) */
    bool malformed; /* failed the structural checks at load */
    bool bad;       /* failed a stage: later stages do not pile errors onto it */
    const rf_node_desc *desc;
    const rf_plugin *plugin;
    GPtrArray **inputs; /* [desc->input_count] arrays of rf_conn* */
    rf_pvalue *params;  /* [desc->param_count] */
    rf_output *outputs; /* [desc->output_count] */
    void *self;         /* what desc->create made */
    bool created;
    char *error; /* set through host->error */
    struct rf_pipeline *pipeline;
    gint64 last_progress; /* monotonic µs of the last progress line drawn */
    /* a run's account of the node's process (run.c, run-group.c) */
    struct rf_held *held; /* what it prints while it processes beside others; NULL alone */
    bool ran, ok;         /* process was called / returned true */
    gint64 took;          /* µs process took */
};
typedef struct rf_node rf_node;

struct rf_pipeline {
    char *name; /* file name used in messages */
    char *dir;  /* folder relative paths resolve against */
    json_t *root;
    GPtrArray *nodes;      /* rf_node*, in file order */
    GHashTable *by_id;     /* id -> rf_node* */
    GHashTable *overrides; /* "node.param" -> folder its relative path resolves against */
    GPtrArray *load_diags; /* structural problems found at load, reported by validate */
    GArray *order;         /* node indices in dependency order, after validation */
    bool valid;
    const rf_run_options *opts; /* &run_opts during a run */
    rf_run_options run_opts;    /* the caller's options, whatever its struct's size (run.c) */
    GPtrArray *temp_files;      /* outputs written during a run, removed unless it succeeds */
    GPtrArray *syncs;           /* rf_file_sync of the outputs whose node has finished (run.c) */
};

/* Index of a declared param / input / output port by name, or -1. */
int rf_desc_param_index(const rf_node_desc *d, const char *name);
int rf_desc_input_index(const rf_node_desc *d, const char *name);
int rf_desc_output_index(const rf_node_desc *d, const char *name);

/* Frees what validation bound to a node (edges and parameter values). */
void rf_node_clear_bindings(rf_node *n);

/* Releases everything a run produced (outputs, node state, parameter values). */
void rf_pipeline_reset_run(rf_pipeline *p);
/* What a node prints while it processes beside others (run-group.c): its stdout in a buffer and
 * its log lines with where they fell in it, copied out in the run's order. */
typedef struct rf_held rf_held;
/* The stream host->out hands the node. */
FILE *rf_held_out(rf_held *h);
/* Keeps one whole line the node logged (for stderr). */
void rf_held_log(rf_held *h, const char *line);

/* The node at position i of the run's order. */
rf_node *rf_run_node_at(rf_pipeline *p, guint i);
/* Calls the node's process once, timing it (any thread); records ran, ok and took. */
void rf_node_process(rf_node *n);
/* What the run does after a node's process, on the run's thread and in the run's order: its
 * profile line, its error or a missing output into diags (false), the fsync of its files. */
bool rf_node_report(rf_node *n, GPtrArray *diags);
/* Processes the nodes from order position `first` on that may process at once (at most `jobs`
 * at a time) and reports them in order, as rf_node_report; returns the position after them in
 * *next. False when one failed (the nodes after it in the order are then not reported). */
bool rf_run_group(rf_pipeline *p, guint first, guint jobs, guint *next, GPtrArray *diags);

/* Frees an output value (and its copy in this build's layout, if one was made) and clears it. */
void rf_output_clear(rf_output *o);

#endif
