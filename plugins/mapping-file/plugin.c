/* mapping.read and mapping.write: mapping files in pipelines (see mapfile.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <rigflow/rigflow.h>

#include "mapfile.h"

#define MAX_SOURCES 64
#define ERR_SIZE 4096

static bool skeletons(const rf_host *h, rf_node *node, const rf_skeleton **t, const rf_skeleton **s,
                      uint32_t *n)
{
    *t = h->input(node, "target", 0);
    *n = h->input_count(node, "sources");
    if (!*t || *n > MAX_SOURCES) {
        h->error(node, "needs the target skeleton and at most %d source skeletons", MAX_SOURCES);
        return false;
    }
    for (uint32_t k = 0; k < *n; k++)
        if (!(s[k] = h->input(node, "sources", k))) {
            h->error(node, "source %u has no skeleton", k);
            return false;
        }
    return true;
}

static bool write_process(void *self, const rf_host *h, rf_node *node)
{
    (void)self;
    const rf_skeleton *t, *s[MAX_SOURCES];
    uint32_t n;
    const rf_mapping *m = h->input(node, "mapping", 0);
    if (!skeletons(h, node, &t, s, &n))
        return false;
    if (!m) {
        h->error(node, "no mapping on input 'mapping'");
        return false;
    }
    char err[ERR_SIZE];
    if (!rf_mapfile_write_path(h->param_string(node, "path"), m, t, s, n, err, sizeof err)) {
        h->error(node, "%s", err);
        return false;
    }
    return true;
}

static bool read_process(void *self, const rf_host *h, rf_node *node)
{
    (void)self;
    const rf_skeleton *t, *s[MAX_SOURCES];
    uint32_t n;
    if (!skeletons(h, node, &t, s, &n))
        return false;
    const rf_mapping *base = h->input_count(node, "base") ? h->input(node, "base", 0) : NULL;
    char *err = malloc(ERR_SIZE);
    if (!err) {
        h->error(node, "out of memory");
        return false;
    }
    rf_mapfile *f = rf_mapfile_read(h->param_string(node, "path"), err, ERR_SIZE);
    rf_mapping *m = NULL;
    if (f)
        m = base ? rf_mapfile_apply(f, base, t, s, n, err, ERR_SIZE)
                 : rf_mapfile_resolve(f, t, s, n, err, ERR_SIZE);
    if (!m)
        h->error(node, "%s", err);
    free(err);
    rf_mapfile_free(f);
    return m && h->set_output(node, "mapping", m, rf_mapping_free);
}

/* Self-test: a mapping written and read back is the same mapping. */
static bool selftest_run(const rf_host *host, char *err, size_t err_size)
{
    (void)host;
    rf_skeleton *a = rf_skeleton_new(2), *b = rf_skeleton_new(2);
    rf_mapping *m = rf_mapping_new(2, 1);
    if (!a || !b || !m)
        return false;
    const char *names[] = {"root", "tip"};
    for (int i = 0; i < 2; i++) {
        a->joints[i].name = malloc(8), b->joints[i].name = malloc(8);
        snprintf(a->joints[i].name, 8, "%s", names[i]);
        snprintf(b->joints[i].name, 8, "%s", names[1 - i]);
    }
    a->joints[1].parent = b->joints[1].parent = 0;
    m->entries[0].inputs = calloc(1, sizeof(rf_map_input));
    m->entries[0].input_count = 1;
    m->entries[0].inputs[0] = (rf_map_input){0, 1, 0.5f, 0.25f, RF_MAP_REVERSE};
    char *text = NULL;
    size_t size = 0;
    FILE *mem = open_memstream(&text, &size);
    const rf_skeleton *src = b;
    bool ok = mem && rf_mapfile_write(mem, m, a, &src, 1, err, err_size);
    if (mem)
        fclose(mem);
    rf_mapfile *f = ok ? rf_mapfile_parse(text, size, "selftest", err, err_size) : NULL;
    rf_mapping *back = f ? rf_mapfile_resolve(f, a, &src, 1, err, err_size) : NULL;
    ok = back && back->entries[0].input_count == 1 && back->entries[0].inputs[0].joint == 1 &&
         back->entries[0].inputs[0].weight == 0.5f &&
         back->entries[0].inputs[0].flags == RF_MAP_REVERSE && back->entries[1].input_count == 0;
    if (!ok && err_size && !err[0])
        snprintf(err, err_size, "a mapping written and read back changed");
    free(text);
    rf_mapfile_free(f);
    rf_mapping_free(back);
    rf_mapping_free(m);
    rf_skeleton_free(a);
    rf_skeleton_free(b);
    return ok;
}

RF_SELFTEST_GET_EXTENSION(get_extension, selftest_run)

#define SKELETON_INPUTS                                                                            \
    RF_PORT_DESC("target", RF_TYPE_SKELETON, 0, "The target skeleton (joint names and order)."),   \
        RF_PORT_DESC("sources", RF_TYPE_SKELETON, RF_PORT_MULTIPLE | RF_PORT_OPTIONAL,             \
                     "The source skeletons, in the mapping's source order.")

static const rf_port_desc write_inputs[] = {
    RF_PORT_DESC("mapping", RF_TYPE_MAPPING, 0, "The mapping to save."),
    SKELETON_INPUTS,
};

static const rf_param_desc write_params[] = {
    RF_PARAM_DESC_OUTPUT_PATH("path", RF_PARAM_REQUIRED,
                              "The mapping file to write (JSON, doc/formats/mapping.md)."),
};

static const rf_node_desc write_node = {
    .size = sizeof(rf_node_desc),
    .type = "mapping.write",
    .kind = RF_KIND_EXPORTER,
    .doc = "Saves a mapping as a rigflow.mapping JSON file: one entry for every target joint, with "
           "its inputs by name, weight, delay, reverse and mirror, score, per-metric breakdown, "
           "section and side, for people to read and edit.",
    RF_NODE_INPUTS(write_inputs),
    RF_NODE_PARAMS(write_params),
    .process = write_process,
    .get_extension = get_extension,
};

static const rf_port_desc read_inputs[] = {
    SKELETON_INPUTS,
    RF_PORT_DESC(
        "base", RF_TYPE_MAPPING, RF_PORT_OPTIONAL,
        "When connected, the file holds overrides: the joints it lists replace base's entries."),
};

static const rf_port_desc read_outputs[] = {
    RF_PORT_DESC(
        "mapping", RF_TYPE_MAPPING, 0,
        "The mapping: the file alone (unlisted joints unmapped), or base with the overrides."),
};

static const rf_param_desc read_params[] = {
    RF_PARAM_DESC_INPUT_PATH("path", RF_PARAM_REQUIRED, "The mapping file to read."),
};

static const rf_node_desc read_node = {
    .size = sizeof(rf_node_desc),
    .type = "mapping.read",
    .kind = RF_KIND_MATCHER,
    .doc = "Loads a mapping file instead of computing one, or applies a partial file of manual "
           "overrides on top of a computed mapping (connect 'base'). Unknown joint names, bad "
           "values and other versions are refused, every problem listed.",
    RF_NODE_INPUTS(read_inputs),
    RF_NODE_OUTPUTS(read_outputs),
    RF_NODE_PARAMS(read_params),
    .process = read_process,
    .get_extension = get_extension,
};

static const rf_node_desc *const nodes[] = {&read_node, &write_node};

RF_PLUGIN_DEFINE("org.rigflow.mapping-file", "mapping files", "0.1.0",
                 "Read and write joint mappings as editable JSON files", nodes);
