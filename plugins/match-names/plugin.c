/* The "names" matcher node: joint mapping by normalised names (see names.h). */
#include <stdio.h>
#include <string.h>

#include <rigflow/rigflow.h>

#include "rigflow/match-names.h"

#define MAX_SOURCES 64

static bool process(void *self, const rf_host *h, rf_node *node)
{
    (void)self;
    const rf_skeleton *t = h->input(node, "target", 0), *s[MAX_SOURCES];
    uint32_t n = h->input_count(node, "sources");
    if (!t || n == 0 || n > MAX_SOURCES) {
        h->error(node, "needs a target skeleton and 1 to %d source skeletons", MAX_SOURCES);
        return false;
    }
    for (uint32_t k = 0; k < n; k++)
        if (!(s[k] = h->input(node, "sources", k))) {
            h->error(node, "source %u has no skeleton", k);
            return false;
        }
    char err[256];
    rf_mapping *m =
        rf_names_match(t, s, n, h->param_float(node, "min_similarity"), err, sizeof err);
    if (!m) {
        h->error(node, "%s", err);
        return false;
    }
    return h->set_output(node, "mapping", m, rf_mapping_free);
}

/* Self-test: rig naming schemes that mean the same joints. */
static bool selftest_run(const rf_host *host, char *err, size_t err_size)
{
    (void)host;
    static const char *const same[][2] = {
        {"mixamorig:LeftUpLeg", "thigh.L"},
        {"LeftForeArm", "lowerarm_l"},
        {"Hips", "pelvis"},
        {"RightHand", "hand.R"},
        {"Bip01 L Clavicle", "LeftCollar"},
        {"Spine1", "spine_01"},
    };
    for (size_t i = 0; i < sizeof same / sizeof same[0]; i++) {
        rf_name_key a, b;
        rf_name_normalize(same[i][0], false, &a);
        rf_name_normalize(same[i][1], false, &b);
        if (rf_name_similarity(&a, &b) < 0.99) {
            snprintf(err, err_size, "%s and %s should name the same joint", same[i][0], same[i][1]);
            return false;
        }
    }
    return true;
}

RF_SELFTEST_GET_EXTENSION(get_extension, selftest_run)

static const rf_port_desc inputs[] = {
    RF_PORT_DESC("target", RF_TYPE_SKELETON, 0, "The skeleton to drive."),
    RF_PORT_DESC("sources", RF_TYPE_SKELETON, RF_PORT_MULTIPLE,
                 "The skeletons whose motion will drive it, in order."),
};

static const rf_port_desc outputs[] = {
    RF_PORT_DESC(
        "mapping", RF_TYPE_MAPPING, 0,
        "One entry per target joint; its one metric, 'name', is the name similarity in percent."),
};

static const rf_param_desc params[] = {
    RF_PARAM_DESC_FLOAT("min_similarity", 0.5, 0, 1,
                        "Names less alike than this (0..1) leave the joint unmapped."),
};

static const rf_node_desc node_desc = {
    .size = sizeof(rf_node_desc),
    .type = "names",
    .kind = RF_KIND_MATCHER,
    .doc = "Maps joints by their names: namespaces and rig prefixes dropped (mixamorig:, Bip01), "
           "names split at separators, case changes and digits, sides read from L/R/Left/.L/_l, "
           "synonyms folded (pelvis/hips, upperarm/arm, collar/clavicle). Useless on meaningless "
           "names (Joint1...): compare with skeletal-similarity. doc/matching.md.",
    RF_NODE_INPUTS(inputs),
    RF_NODE_OUTPUTS(outputs),
    RF_NODE_PARAMS(params),
    .process = process,
    .get_extension = get_extension,
};

static const rf_node_desc *const nodes[] = {&node_desc};

RF_PLUGIN_DEFINE("org.rigflow.match-names", "names", "0.1.0",
                 "Joint mapping by normalised joint names", nodes);
