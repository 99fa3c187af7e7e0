/* libFuzzer harness: pipeline loading, command-line overrides and validation.
 *
 * The input is the pipeline text, optionally followed by a line "--" and one override
 * ("node.param=value") per line, as `rigflow run -p` would apply them. The registry holds the
 * fixture plugin and the bundled plugins of the build tree (RF_FUZZ_PLUGINS: colon-separated
 * folders or .so files), so validation sees every parameter and port type the project declares.
 * Validation must touch no file and load no code; a refusal must say why.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rigflow-host.h"

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static rf_registry *rf_fuzz_reg;

#define RF_FUZZ_CHECK(cond)                                                                        \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            fprintf(stderr, "fuzz_pipeline: broken promise: %s (%s:%d)\n", #cond, __FILE__,        \
                    __LINE__);                                                                     \
            abort();                                                                               \
        }                                                                                          \
    } while (0)

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    rf_fuzz_reg = rf_registry_new();
    g_autoptr(GPtrArray) diags = rf_diags_new();
    const char *env = g_getenv("RF_FUZZ_PLUGINS");
    g_auto(GStrv) items = g_strsplit(env ? env : "", ":", -1);
    for (char **it = items; *it; it++) {
        if (g_str_has_suffix(*it, ".so"))
            rf_registry_load_file(rf_fuzz_reg, *it, diags);
        else if (**it)
            rf_registry_load_dir(rf_fuzz_reg, *it, diags);
    }
    /* Fuzzing against an empty registry would only ever see "plugin not installed". */
    if (rf_registry_plugin_count(rf_fuzz_reg) == 0) {
        fprintf(stderr, "fuzz_pipeline: no plugin loaded from RF_FUZZ_PLUGINS='%s'\n",
                env ? env : "");
        exit(2);
    }
    return 0;
}

/* Every diag has a message, and formats. */
static void rf_fuzz_check_diags(GPtrArray *diags)
{
    for (guint i = 0; i < diags->len; i++) {
        const rf_diag *d = g_ptr_array_index(diags, i);
        RF_FUZZ_CHECK(d->message && *d->message);
        g_free(rf_diag_format(d));
    }
}

static void rf_fuzz_overrides(rf_pipeline *p, const char *lines, GPtrArray *diags)
{
    g_auto(GStrv) list = g_strsplit(lines, "\n", 64);
    for (char **o = list; *o; o++) {
        guint before = diags->len;
        if (!rf_pipeline_override(p, *o, diags))
            RF_FUZZ_CHECK(diags->len > before || strchr(*o, '=')); /* see override's comment */
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    g_autofree char *text =
        g_strndup((const char *)data, size); /* stops at a NUL, as a file read */
    char *overrides = strstr(text, "\n--\n");
    if (overrides) {
        *overrides = '\0';
        overrides += 4;
    }
    g_autoptr(GPtrArray) diags = rf_diags_new();
    rf_pipeline *p = rf_pipeline_load_string(text, "fuzz.json", "/nonexistent/fuzz", diags);
    if (!p) {
        RF_FUZZ_CHECK(diags->len > 0);
        rf_fuzz_check_diags(diags);
        return 0;
    }
    if (overrides)
        rf_fuzz_overrides(p, overrides, diags);
    guint before = diags->len;
    bool valid = rf_pipeline_validate(p, rf_fuzz_reg, diags);
    RF_FUZZ_CHECK(valid == (diags->len == before)); /* invalid exactly when something is said */
    if (valid) /* validating again gives the same answer: no state left from the first pass */
        RF_FUZZ_CHECK(rf_pipeline_validate(p, rf_fuzz_reg, diags));
    rf_fuzz_check_diags(diags);
    rf_pipeline_free(p);
    return 0;
}
