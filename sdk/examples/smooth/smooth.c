/* example.smooth: a filter plugin built out of tree against the installed SDK.
 * Smooths every joint's rotation over a centred window of frames: the window's quaternions are
 * sign-aligned to the centre frame (q and -q are the same rotation) and averaged, which for the
 * small angles between neighbouring frames is a close, cheap stand-in for the true mean. */
#include <rigflow/rigflow.h>

static rf_quat window_mean(const rf_animation *a, uint32_t f, uint32_t j, int64_t half)
{
    rf_quat centre = rf_animation_rotation(a, f, j), sum = {0, 0, 0, 0};
    for (int64_t k = -half; k <= half; k++) {
        int64_t g = (int64_t)f + k;
        if (g < 0 || g >= (int64_t)a->frame_count)
            continue;
        rf_quat q = rf_animation_rotation(a, (uint32_t)g, j);
        if (rf_quat_dot(q, centre) < 0)
            q = rf_quat_neg(q);
        sum.x += q.x, sum.y += q.y, sum.z += q.z, sum.w += q.w;
    }
    return rf_quat_normalize(sum);
}

static rf_animation *copy_shape(const rf_animation *in)
{
    rf_animation *out = rf_animation_new(in->joint_count, in->frame_count, in->fps);
    if (!out)
        return NULL;
    size_t n = (size_t)in->joint_count * in->frame_count;
    memcpy(out->translations, in->translations, n * 3 * sizeof(float));
    memcpy(out->channels, in->channels, in->joint_count);
    out->source_start = in->source_start; /* the same timeline */
    return out;
}

static bool smooth_process(void *self, const rf_host *host, rf_node *node)
{
    (void)self;
    const rf_animation *in = host->input(node, "animation", 0);
    int64_t half = host->param_int(node, "window") / 2;
    rf_animation *out = copy_shape(in);
    if (!out) {
        host->error(node, "out of memory for %u frames x %u joints", in->frame_count,
                    in->joint_count);
        return false;
    }
    for (uint32_t f = 0; f < in->frame_count; f++) {
        for (uint32_t j = 0; j < in->joint_count; j++)
            rf_animation_set_rotation(out, f, j, window_mean(in, f, j, half));
        host->progress(node, (f + 1.0) / in->frame_count);
    }
    return host->set_output(node, "animation", out, rf_animation_free);
}

static const rf_port_desc in_ports[] = {
    RF_PORT_DESC("animation", RF_TYPE_ANIMATION, 0, "clip to smooth")};
static const rf_port_desc out_ports[] = {
    RF_PORT_DESC("animation", RF_TYPE_ANIMATION, 0, "smoothed clip")};
static const rf_param_desc params[] = {RF_PARAM_DESC_INT(
    "window", 5, 1, 61, "frames averaged around each frame (odd; 1 leaves the clip as it is)")};

static const rf_node_desc smooth = {
    .size = sizeof(rf_node_desc),
    .type = "example.smooth",
    .kind = RF_KIND_FILTER,
    .doc = "Smooths joint rotations with a moving average over a window of frames.",
    RF_NODE_INPUTS(in_ports),
    RF_NODE_OUTPUTS(out_ports),
    RF_NODE_PARAMS(params),
    .process = smooth_process,
};

static const rf_node_desc *const nodes[] = {&smooth};

RF_PLUGIN_DEFINE("org.example.smooth", "Smoothing example", "1.0",
                 "An out-of-tree filter plugin: moving-average rotation smoothing", nodes);
