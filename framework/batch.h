/* rigflow batch: one pipeline run over the cross product of input globs, in a pool of worker
 * processes, with a resumable manifest and a Slurm job-array backend (doc/batch.md).
 *
 *   batch.c           the command: options, the plan (jobs, their names and outputs), the run
 *   batch-pool.c      worker processes forked once, jobs sent to them, crashes survived
 *   batch-manifest.c  the lock, the manifest (JSON lines) and what a rerun may skip
 *   batch-slurm.c     job-array script, submission, --status and --resubmit
 */
#ifndef RIGFLOW_BATCH_H
#define RIGFLOW_BATCH_H

#include <jansson.h>

#include <rigflow/text.h>

#include "commands.h"

/* The folder inside --out DIR that holds the batch's own files (manifests, lock, logs). */
#define RF_BATCH_STATE "rigflow-batch"

/* One --over node.param=GLOB: the files it matched and the name part each contributes. */
typedef struct rf_batch_over {
    char *param;      /* "node.param" */
    char *pattern;    /* as given */
    GPtrArray *paths; /* absolute paths of the matches, sorted */
    GPtrArray *names; /* escaped name part of each match (see batch.c: job names) */
} rf_batch_over;

/* One output-path parameter of the pipeline: every job writes it as DIR/NAME + suffix. */
typedef struct rf_batch_output {
    char *param;  /* "node.param" */
    char *suffix; /* ".glb", or ".node-param.glb" when outputs share an extension */
} rf_batch_output;

/* One run of the pipeline. */
typedef struct rf_batch_job {
    guint index;        /* position in the full cross product (shards take index % N) */
    char *name;         /* collision-free, derived from the inputs */
    GPtrArray *assign;  /* "node.param=value" overrides handed to the engine, in order */
    GPtrArray *outputs; /* final output paths, one per rf_batch_output */
    GPtrArray *inputs;  /* files the job reads whose size and mtime are recorded */
    json_t *params;     /* {"node.param": "value"} of every override, for the manifest */
} rf_batch_job;

typedef struct rf_batch {
    char *pipeline;      /* absolute path */
    char *pipeline_text; /* read once; every job parses it afresh */
    char *out;           /* absolute --out DIR */
    char *state;         /* DIR/rigflow-batch */
    char **params;       /* -p overrides as given */
    GPtrArray *overs;    /* rf_batch_over* */
    GPtrArray *outputs;  /* rf_batch_output* */
    GPtrArray *jobs;     /* rf_batch_job*, the full cross product */
    int shard, shards;   /* this process's shard of `shards` (shards 0: all jobs) */
    int workers;         /* -j */
    double job_timeout;  /* --job-timeout: seconds a job may run before it is stopped; 0: none */
    bool quiet;
} rf_batch;

void rf_batch_free(rf_batch *b);

/* ---- manifest and lock (batch-manifest.c) ---- */

/* Takes the lock of this batch (or shard) in b->state. Returns the lock's descriptor, or -1
 * after printing which process holds it. The lock goes with the process (kill -9 included). */
int rf_batch_lock(const rf_batch *b);
/* True when another process holds the lock file `name` of the state folder; `holder` (n bytes)
 * then says who ("pid 123 on node7"). */
bool rf_batch_lock_holder(const char *state, const char *name, char *holder, size_t n);
/* True, after printing who, when a batch or an array task holds DIR now (a submission checks
 * it: its tasks would find DIR locked). */
bool rf_batch_busy(const rf_batch *b);
/* The manifest this process appends to, opened for appending (O_APPEND), or -1 with a message. */
int rf_batch_manifest_open(const rf_batch *b);
/* Appends one record as one line with one write, then fsyncs: a crash keeps whole lines. */
bool rf_batch_manifest_append(int fd, json_t *record);
/* The newest record of every job from every manifest in the state folder: name -> json_t*. */
GHashTable *rf_batch_manifest_load(const char *state);
/* True when `rec` says the job finished and nothing it depends on changed since. */
bool rf_batch_record_current(const rf_batch_job *job, json_t *rec);
/* {"path", "size", "mtime_ns"} of each of the job's inputs as they are now. */
json_t *rf_batch_inputs_json(const rf_batch_job *job);
/* The manifest record of a job (outputs may be NULL). (transfer full) */
json_t *rf_batch_record(const rf_batch_job *job, const char *status, const char *error,
                        json_t *outputs, double seconds);
/* Removes temporary files a killed worker left in DIR (the engine's ".NAME.rf-XXXXXX.EXT"):
 * those of `job`, or every one when job is NULL. */
void rf_batch_clean_temps(const rf_batch *b, const rf_batch_job *job);

/* ---- the worker pool (batch-pool.c) ---- */

typedef struct rf_batch_stats {
    guint done, failed, crashed, skipped, interrupted, total;
    guint unrecorded;    /* finished jobs whose record the manifest could not take */
    GPtrArray *failures; /* "failed NAME: error" lines for the closing summary */
    bool no_worker;      /* a worker process could not be started: the batch stopped */
} rf_batch_stats;

/* Runs `todo` (rf_batch_job*) on b->workers processes forked from this one, appending each
 * finished job's record to the manifest `mfd`. Prints progress and failures. Returns false when
 * interrupted (SIGINT or SIGTERM to the batch, or to a worker during its job). */
bool rf_batch_pool_run(rf_batch *b, const rf_registry *reg, GPtrArray *todo, int mfd,
                       rf_batch_stats *stats);

/* ---- Slurm (batch-slurm.c) ---- */

typedef struct rf_slurm_options {
    char *partition, *time, *mem;
    int array_size;
} rf_slurm_options;

/* Writes the job-array script into the state folder and submits it with sbatch. `argv` is the
 * batch's command line with the Slurm options removed. */
int rf_batch_slurm_submit(rf_batch *b, const rf_registry *reg, const rf_slurm_options *o,
                          char **argv);
/* rigflow batch --status DIR: the manifests merged with what Slurm says of the array. */
int rf_batch_status(const char *dir);
/* rigflow batch --resubmit DIR: submits again the array tasks of the failed and missing jobs. */
int rf_batch_resubmit(const char *dir);

/* Writes DIR/rigflow-batch/plan.json: every job's name, for --status and --resubmit. */
void rf_batch_write_plan(const rf_batch *b);

int rf_cmd_batch(rf_registry *reg, int argc, char **argv);

#endif
