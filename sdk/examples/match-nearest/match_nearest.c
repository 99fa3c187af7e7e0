/* example.match-nearest: a matcher plugin built out of tree against the installed SDK.
 * A geometric baseline: each skeleton's rest pose is scaled into a unit box (keeping its aspect),
 * and every target joint is mapped to the nearest source joint in that box. It knows nothing of
 * limbs or sides, which is what makes it a useful yardstick for real matchers. */
#include <stdio.h>

#include <rigflow/rigflow.h>

/* World rest positions scaled so the skeleton's largest extent is 1, from its box's minimum. */
static rf_vec3 *unit_positions(const rf_skeleton *s)
{
    rf_xform *w = calloc(s->joint_count ? s->joint_count : 1, sizeof *w);
    rf_vec3 *p = calloc(s->joint_count ? s->joint_count : 1, sizeof *p);
    if (!w || !p) {
        free(w), free(p);
        return NULL;
    }
    rf_skeleton_world_rest(s, w);
    rf_vec3 lo = w[0].t, hi = w[0].t;
    for (uint32_t i = 0; i < s->joint_count; i++) {
        lo = rf_v3(fmin(lo.x, w[i].t.x), fmin(lo.y, w[i].t.y), fmin(lo.z, w[i].t.z));
        hi = rf_v3(fmax(hi.x, w[i].t.x), fmax(hi.y, w[i].t.y), fmax(hi.z, w[i].t.z));
    }
    rf_vec3 ext = rf_v3_sub(hi, lo);
    double size = fmax(ext.x, fmax(ext.y, ext.z));
    for (uint32_t i = 0; i < s->joint_count; i++)
        p[i] = rf_v3_scale(rf_v3_sub(w[i].t, lo), size > 0 ? 1.0 / size : 0.0);
    free(w);
    return p;
}

static bool map_joint(rf_map_entry *e, rf_vec3 at, rf_vec3 *const *src, const uint32_t *counts,
                      uint32_t nsrc)
{
    double best = INFINITY;
    rf_map_input in = {0, 0, 1.0f, 0.0f, 0};
    for (uint32_t s = 0; s < nsrc; s++)
        for (uint32_t j = 0; j < counts[s]; j++) {
            double d = rf_v3_dist(at, src[s][j]);
            if (d < best)
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
    rf_vec3 *src[64] = {0};
    uint32_t counts[64] = {0};
    if (nsrc > 64) {
        host->error(node, "%u sources given; this example handles up to 64", nsrc);
        return false;
    }
    rf_mapping *m = rf_mapping_new(target->joint_count, nsrc);
    rf_vec3 *tp = unit_positions(target);
    bool ok = m && tp;
    for (uint32_t s = 0; ok && s < nsrc; s++) {
        const rf_skeleton *sk = host->input(node, "sources", s);
        counts[s] = sk->joint_count;
        ok = (src[s] = unit_positions(sk)) != NULL;
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
    {sizeof(rf_port_desc), "target", RF_TYPE_SKELETON, 0, "skeleton to map onto"},
    {sizeof(rf_port_desc), "sources", RF_TYPE_SKELETON, RF_PORT_MULTIPLE, "skeletons to map from"}};
static const rf_port_desc out_ports[] = {
    {sizeof(rf_port_desc), "mapping", RF_TYPE_MAPPING, 0, "nearest source joint per target joint"}};

static const rf_node_desc nearest = {
    .size = sizeof(rf_node_desc),
    .type = "example.match-nearest",
    .kind = RF_KIND_MATCHER,
    .doc = "Maps each target joint to the nearest source joint, rest poses scaled to a unit box.",
    .input_count = 2,
    .inputs = in_ports,
    .output_count = 1,
    .outputs = out_ports,
    .process = nearest_process,
};

static const rf_node_desc *const nodes[] = {&nearest};

RF_PLUGIN_EXPORT const rf_plugin_entry rigflow_plugin_entry = {
    .abi = RF_ABI_VERSION_INIT,
    .size = sizeof(rf_plugin_entry),
    .id = "org.example.match-nearest",
    .name = "Nearest-joint matcher example",
    .version = "1.0",
    .description = "An out-of-tree matcher plugin: nearest joint in a unit box",
    .node_count = 1,
    .nodes = nodes,
};
