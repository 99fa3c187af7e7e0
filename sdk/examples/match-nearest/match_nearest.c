/* example.match-nearest: a matcher plugin built out of tree against the installed SDK and its
 * skeleton analysis library (pkg-config rigflow-plugin rigflow-analysis).
 * A geometric baseline: each skeleton's rest pose is seen in its body's own frame (the analysis
 * finds up, forward and the sides), scaled by its height, and every target joint is mapped to the
 * nearest source joint on its side. It knows nothing of limbs or chains, which is what makes it a
 * useful yardstick for real matchers. */
#include <stdio.h>

#include <rigflow/analysis.h>
#include <rigflow/rigflow.h>

/* A joint seen in its body's own frame: left, up and forward from the skeleton analysis (the
 * installed rigflow-analysis library), in heights above the ground, so facing, scale and the
 * file's axes do not matter; and its side, so a left hand never maps to a right one. */
typedef struct body_point {
    rf_vec3 at;
    rf_side side;
} body_point;

static body_point *body_points(const rf_skeleton *s)
{
    rf_analysis *a = rf_analyze(s, NULL);
    body_point *p = calloc(s->joint_count ? s->joint_count : 1, sizeof *p);
    if (!a || !p) {
        rf_analysis_free(a), free(p);
        return NULL;
    }
    for (uint32_t i = 0; i < s->joint_count; i++) {
        rf_vec3 d = rf_v3_scale(a->joints[i].pos, 1.0 / a->height);
        p[i].at = rf_v3(rf_v3_dot(d, a->left), rf_v3_dot(d, a->up) - a->ground / a->height,
                        rf_v3_dot(d, a->forward));
        p[i].side = a->joints[i].side;
    }
    rf_analysis_free(a);
    return p;
}

/* The nearest source joint on the same side, or on any side when that side has none. */
static bool map_joint(rf_map_entry *e, body_point at, body_point *const *src,
                      const uint32_t *counts, uint32_t nsrc)
{
    double best = INFINITY;
    rf_map_input in = {0, 0, 1.0f, 0.0f, 0};
    for (int any_side = 0; any_side < 2 && !isfinite(best); any_side++)
        for (uint32_t s = 0; s < nsrc; s++)
            for (uint32_t j = 0; j < counts[s]; j++) {
                double d = rf_v3_dist(at.at, src[s][j].at);
                if ((any_side || src[s][j].side == at.side) && d < best)
                    best = d, in.source = s, in.joint = j;
            }
    if (!isfinite(best))
        return true; /* no source joints: leave unmapped */
    e->inputs = malloc(sizeof *e->inputs);
    e->metrics = malloc(sizeof *e->metrics);
    if (!e->inputs || !e->metrics)
        return false;
    e->input_count = 1;
    e->inputs[0] = in;
    e->metrics[0] = best;
    e->score = 1.0 / (1.0 + best);
    return true;
}

static bool nearest_process(void *self, const rf_host *host, rf_node *node)
{
    (void)self;
    const rf_skeleton *target = host->input(node, "target", 0);
    uint32_t nsrc = host->input_count(node, "sources");
    body_point *src[64] = {0};
    uint32_t counts[64] = {0};
    if (nsrc > 64) {
        host->error(node, "%u sources given; this example handles up to 64", nsrc);
        return false;
    }
    rf_mapping *m = rf_mapping_new(target->joint_count, nsrc);
    body_point *tp = body_points(target);
    bool ok = m && tp;
    for (uint32_t s = 0; ok && s < nsrc; s++) {
        const rf_skeleton *sk = host->input(node, "sources", s);
        counts[s] = sk->joint_count;
        ok = (src[s] = body_points(sk)) != NULL;
    }
    if (ok && (m->metric_names = calloc(1, sizeof(char *))) &&
        (m->metric_names[0] = malloc(sizeof "distance")))
        memcpy(m->metric_names[0], "distance", sizeof "distance"), m->metric_count = 1;
    for (uint32_t j = 0; ok && j < target->joint_count; j++)
        ok = map_joint(&m->entries[j], tp[j], src, counts, nsrc);
    for (uint32_t s = 0; s < nsrc; s++)
        free(src[s]);
    free(tp);
    if (!ok) {
        rf_mapping_free(m);
        host->error(node, "out of memory");
        return false;
    }
    return host->set_output(node, "mapping", m, rf_mapping_free);
}

static const rf_port_desc in_ports[] = {
    RF_PORT_DESC("target", RF_TYPE_SKELETON, 0, "skeleton to map onto"),
    RF_PORT_DESC("sources", RF_TYPE_SKELETON, RF_PORT_MULTIPLE, "skeletons to map from")};
static const rf_port_desc out_ports[] = {
    RF_PORT_DESC("mapping", RF_TYPE_MAPPING, 0, "nearest source joint per target joint")};

static const rf_node_desc nearest = {
    .size = sizeof(rf_node_desc),
    .type = "example.match-nearest",
    .kind = RF_KIND_MATCHER,
    .doc = "Maps each target joint to the nearest source joint on its side, rest poses seen in the "
           "body's own frame.",
    RF_NODE_INPUTS(in_ports),
    RF_NODE_OUTPUTS(out_ports),
    .process = nearest_process,
};

static const rf_node_desc *const nodes[] = {&nearest};

RF_PLUGIN_DEFINE(
    "org.example.match-nearest", "Nearest-joint matcher example", "1.0",
    "An out-of-tree matcher plugin: nearest joint on the same side, in the body's frame", nodes);
