/* Test plugin with deliberate memory and undefined-behaviour bugs, loaded with dlopen like any
 * plugin: test_sanitizers.sh checks that a --enable-sanitizers build reports them from inside a
 * plugin (instrumented plugin, sanitizer runtime in the host). Never installed. */
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include <rigflow/plugin.h>

/* Reads one byte past a heap block (AddressSanitizer), or overflows a signed int (UBSan). */
static bool overflow_process(void *self, const rf_host *host, rf_node *node)
{
    (void)self;
    const char *what = host->param_string(node, "bug");
    if (strcmp(what, "signed") == 0) {
        volatile int big = INT_MAX;
        volatile int sum = big + (int)host->param_int(node, "by");
        return sum != 0;
    }
    /* Through a volatile pointer, so that UBSan cannot size the block and AddressSanitizer is
     * the one to catch the read. */
    char *volatile block = malloc(8);
    memset(block, 0, 8);
    volatile char past = block[8 + host->param_int(node, "by") - 1];
    free(block);
    return past == 0;
}

static const rf_param_desc overflow_params[] = {
    RF_PARAM_DESC_ENUM("bug", "heap", "heap|signed", "which bug to commit"),
    RF_PARAM_DESC(.name = "by", .type = RF_PARAM_INT, .default_number = 1, .doc = "how far past")};

static const rf_node_desc overflow_node = {
    .size = sizeof(rf_node_desc),
    .type = "test.overflow",
    .kind = RF_KIND_FILTER,
    .doc = "commits a memory bug",
    RF_NODE_PARAMS(overflow_params),
    .process = overflow_process,
};

static const rf_node_desc *const nodes[] = {&overflow_node};

RF_PLUGIN_EXPORT const rf_plugin_entry rigflow_plugin_entry = {
    .abi = RF_ABI_VERSION_INIT,
    .size = sizeof(rf_plugin_entry),
    .id = "org.rigflow.test.overflow",
    .name = "overflow fixture",
    .version = "0.1.0",
    .description = "deliberate bugs for the sanitizer test",
    .node_count = 1,
    .nodes = nodes,
};
