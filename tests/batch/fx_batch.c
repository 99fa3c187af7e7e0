/* Test fixture for rigflow batch: a node that copies a small text file, and does what the file
 * asks first, so one folder of inputs makes jobs that succeed, fail, crash or run long:
 *   "fail ..."    the node fails with a message naming the file
 *   "crash ..."   the process aborts, as a plugin with a fatal bug would
 *   "kill ..."    the process gets SIGKILL, as from the OOM killer
 *   "sleep S ..." the node takes S seconds (watching for an interrupt), then copies
 *   "gate PATH"   the node waits (watching for an interrupt) until PATH exists, then copies:
 *                 a job that is surely still running when a test kills its batch
 * Anything else is copied as is, after the line "copied by test.copy". */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <rigflow/plugin.h>

static char *read_small(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    char *buf = calloc(1, 4097);
    size_t n = fread(buf, 1, 4096, f);
    buf[n] = '\0';
    fclose(f);
    return buf;
}

static bool wait_seconds(const rf_host *host, rf_node *node, double s)
{
    for (double t = 0; t < s; t += 0.01) {
        if (host->cancelled(node))
            return false;
        usleep(10000);
    }
    return true;
}

static bool wait_for_file(const rf_host *host, rf_node *node, const char *line)
{
    char path[4097];
    snprintf(path, sizeof path, "%.*s", (int)strcspn(line, "\n"), line);
    while (access(path, F_OK) != 0) {
        if (host->cancelled(node))
            return false;
        usleep(10000);
    }
    return true;
}

static bool copy_process(void *self, const rf_host *host, rf_node *node)
{
    (void)self;
    const char *in = host->param_string(node, "input");
    char *text = read_small(in);
    if (!text) {
        host->error(node, "cannot read %s", in);
        return false;
    }
    bool ok = true;
    if (strncmp(text, "fail", 4) == 0) {
        host->error(node, "%s asks to fail", in);
        ok = false;
    } else if (strncmp(text, "crash", 5) == 0) {
        fprintf(stderr, "test.copy: crashing as %s asks\n", in);
        abort();
    } else if (strncmp(text, "kill", 4) == 0) {
        fprintf(stderr, "test.copy: crashing as %s asks\n", in);
        fflush(stderr);
        raise(SIGKILL);
    } else if (strncmp(text, "sleep ", 6) == 0 && !wait_seconds(host, node, atof(text + 6))) {
        host->error(node, "interrupted");
        ok = false;
    } else if (strncmp(text, "gate ", 5) == 0) {
        ok = wait_for_file(host, node, text + 5);
        if (!ok)
            host->error(node, "interrupted");
    }
    FILE *f = ok ? fopen(host->param_string(node, "output"), "wb") : NULL;
    if (ok && (!f || fprintf(f, "copied by test.copy\n%s", text) < 0 || fclose(f) != 0)) {
        host->error(node, "cannot write %s", host->param_output_target(node, "output"));
        ok = false;
    }
    free(text);
    return ok;
}

static const rf_param_desc copy_params[] = {
    RF_PARAM_DESC_INPUT_PATH("input", RF_PARAM_REQUIRED, "the text file to copy"),
    RF_PARAM_DESC_OUTPUT_PATH("output", RF_PARAM_REQUIRED, "the copy"),
    RF_PARAM_DESC_STRING("tag", "", "any text (batch tests change it to see jobs redone)")};

static const rf_node_desc copy = {
    .size = sizeof(rf_node_desc),
    .type = "test.copy",
    .kind = RF_KIND_EXPORTER,
    .doc = "copies a small text file, failing, crashing or sleeping when the file says so",
    RF_NODE_PARAMS(copy_params),
    .process = copy_process,
};
static const rf_node_desc *const nodes[] = {&copy};

RF_PLUGIN_EXPORT const rf_plugin_entry rigflow_plugin_entry = {
    .abi = RF_ABI_VERSION_INIT,
    .size = sizeof(rf_plugin_entry),
    .id = "org.rigflow.test.batch",
    .name = "batch test fixture",
    .version = "1.0",
    .description = "a node whose input decides whether it succeeds, fails or crashes",
    .node_count = 1,
    .nodes = nodes,
};
