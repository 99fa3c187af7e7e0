/* The bvh plugin: node types bvh.import and bvh.export over libbvh. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rigflow/plugin.h"
#include "rigflow/bvh.h"

#define ERR_SIZE 1024

/* Bridges libbvh's progress and warning callbacks to the host. */
typedef struct host_ctx {
    const rf_host *host;
    rf_node *node;
} host_ctx;

static bool on_progress(void *user, double fraction)
{
    host_ctx *c = user;
    c->host->progress(c->node, fraction);
    return !c->host->cancelled(c->node);
}

static void on_warning(void *user, const char *message)
{
    host_ctx *c = user;
    c->host->log(c->node, RF_LOG_WARNING, "%s", message);
}

/* ---- self-test (rigflow plugin-check) ---- */

/* A 3-joint chain whose middle joint has a rotated rest pose, moving over 2 frames. */
static bool make_sample(rf_skeleton **s, rf_animation **a)
{
    static const char *const names[3] = {"root", "mid", "tip"};
    *s = rf_skeleton_new(3);
    *a = rf_animation_new(3, 2, 30);
    for (uint32_t j = 0; *s && *a && j < 3; j++) {
        (*s)->joints[j].name = strdup(names[j]);
        (*s)->joints[j].parent = (int32_t)j - 1;
        (*s)->joints[j].rest.t = rf_v3(j ? 1 : 0, j, 0);
        (*a)->channels[j] = RF_CHANNEL_ROTATION;
        for (uint32_t f = 0; f < 2; f++) {
            rf_quat r = rf_quat_from_axis_angle(rf_v3(1, j, 2), 0.3 * (f + 1) + j);
            rf_animation_set_rotation(*a, f, j, r);
            rf_animation_set_translation(*a, f, j, (*s)->joints[j].rest.t);
        }
        if (!(*s)->joints[j].name)
            return false;
    }
    if (!*s || !*a)
        return false;
    (*s)->joints[1].rest.r = rf_quat_from_axis_angle(rf_v3(0, 0, 1), 1.0);
    return true;
}

/* World position of `joint` in `frame`. */
static rf_vec3 world_position(const rf_skeleton *s, const rf_animation *a, uint32_t frame,
                              uint32_t joint)
{
    rf_xform x = rf_xform_identity();
    for (int32_t j = (int32_t)joint; j >= 0; j = s->joints[j].parent) {
        rf_xform local = {rf_animation_translation(a, frame, (uint32_t)j),
                          rf_animation_rotation(a, frame, (uint32_t)j), rf_v3(1, 1, 1)};
        x = rf_xform_mul(local, x);
    }
    return x.t;
}

/* Writes the sample to a temporary file, reads it back and compares world positions. */
static bool selftest_run(const rf_host *host, char *err, size_t err_size)
{
    (void)host;
    rf_skeleton *s = NULL, *s2 = NULL;
    rf_animation *a = NULL, *a2 = NULL;
    FILE *f = tmpfile();
    char *text = NULL;
    bool ok = f && make_sample(&s, &a) &&
              rf_bvh_write_stream(f, "selftest.bvh", s, a, NULL, err, err_size);
    long size = ok && fflush(f) == 0 ? ftell(f) : -1;
    if (ok && size > 0 && (text = malloc((size_t)size)) != NULL) {
        rewind(f);
        ok = fread(text, 1, (size_t)size, f) == (size_t)size &&
             rf_bvh_read_memory(text, (size_t)size, "selftest.bvh", NULL, &s2, &a2, err, err_size);
    } else if (ok) {
        ok = false;
        snprintf(err, err_size, "cannot write or read a temporary file");
    }
    for (uint32_t f2 = 0; ok && f2 < 2; f2++)
        for (uint32_t j = 0; ok && j < 3; j++)
            if (rf_v3_dist(world_position(s, a, f2, j), world_position(s2, a2, f2, j)) > 1e-4) {
                ok = false;
                snprintf(err, err_size, "joint %u of frame %u moved in a write and read", j, f2);
            }
    if (f)
        fclose(f);
    free(text);
    rf_skeleton_free(s), rf_skeleton_free(s2);
    rf_animation_free(a), rf_animation_free(a2);
    return ok;
}

RF_SELFTEST_GET_EXTENSION(get_extension, selftest_run)

static const rf_importer_info importer = {sizeof(rf_importer_info), "bvh", "path"};

static const void *import_extension(const char *id)
{
    return strcmp(id, RF_IMPORTER_EXTENSION) == 0 ? &importer : get_extension(id);
}

/* ---- bvh.import ---- */

static bool import_process(void *self, const rf_host *host, rf_node *node)
{
    (void)self;
    host_ctx ctx = {host, node};
    rf_bvh_read_opts opts = {.progress = on_progress, .warning = on_warning, .user = &ctx};
    rf_skeleton *s;
    rf_animation *a;
    char err[ERR_SIZE];
    if (!rf_bvh_read_file(host->param_string(node, "path"), &opts, &s, &a, err, sizeof err)) {
        host->error(node, "%s", err);
        return false;
    }
    if (!host->set_output(node, "skeleton", s, rf_skeleton_free)) {
        rf_animation_free(a);
        host->error(node, "cannot set output 'skeleton'");
        return false;
    }
    if (!host->set_output(node, "animation", a, rf_animation_free)) {
        host->error(node, "cannot set output 'animation'");
        return false;
    }
    return true;
}

static const rf_port_desc import_outputs[] = {
    RF_PORT_DESC("skeleton", RF_TYPE_SKELETON, 0,
                 "The joints in file order: names, parents, OFFSETs as rest translations with "
                 "identity rest rotations, End Sites as end_site."),
    RF_PORT_DESC(
        "animation", RF_TYPE_ANIMATION, 0,
        "Every frame's local rotations (Euler channels in degrees, composed in their listed order) "
        "and translations (the position channels, else the OFFSET); fps is 1 / Frame Time."),
};

static const rf_param_desc import_params[] = {
    RF_PARAM_DESC_INPUT_PATH(
        "path", RF_PARAM_REQUIRED,
        "The BVH file to read (any channel order, 3 or 6 channels per joint, LF or CRLF)."),
};

static const rf_node_desc import_node = {
    .size = sizeof(rf_node_desc),
    .type = "bvh.import",
    .kind = RF_KIND_IMPORTER,
    .doc = "Reads a Biovision Hierarchy (.bvh) motion capture file into a skeleton and its "
           "animation. The rest pose is the zero-rotation pose with the OFFSETs; malformed "
           "files are refused with the line and what was expected.",
    RF_NODE_OUTPUTS(import_outputs),
    RF_NODE_PARAMS(import_params),
    .process = import_process,
    .get_extension = import_extension,
    .flags = RF_NODE_CONCURRENT,
};

/* ---- bvh.export ---- */

static bool export_process(void *self, const rf_host *host, rf_node *node)
{
    (void)self;
    host_ctx ctx = {host, node};
    const rf_skeleton *s = host->input(node, "skeleton", 0);
    const rf_animation *a =
        host->input_count(node, "animation") ? host->input(node, "animation", 0) : NULL;
    const char *target = host->param_output_target(node, "path");
    rf_bvh_write_opts opts = {0};
    opts.precision = (int)host->param_int(node, "precision");
    opts.all_positions = host->param_bool(node, "all_positions");
    opts.progress = on_progress, opts.user = &ctx;
    if (!rf_bvh_order_parse(host->param_string(node, "rotation_order"), &opts.order)) {
        host->error(node, "rotation_order: expected ZYX, ZXY, YXZ, YZX, XYZ or XZY");
        return false;
    }
    char err[ERR_SIZE];
    if (!s) {
        host->error(node, "no skeleton on input 'skeleton'");
        return false;
    }
    if (!rf_bvh_write_file(host->param_string(node, "path"), target && *target ? target : NULL, s,
                           a, &opts, err, sizeof err)) {
        host->error(node, "%s", err);
        return false;
    }
    return true;
}

static const rf_port_desc export_inputs[] = {
    RF_PORT_DESC("skeleton", RF_TYPE_SKELETON, 0,
                 "The skeleton to write; rest rotations are folded into the motion so the "
                 "zero-rotation pose is the rest pose."),
    RF_PORT_DESC("animation", RF_TYPE_ANIMATION, RF_PORT_OPTIONAL,
                 "The motion for that skeleton; without it one frame of the rest pose is written."),
};

static const rf_param_desc export_params[] = {
    RF_PARAM_DESC_OUTPUT_PATH("path", RF_PARAM_REQUIRED, "The BVH file to write."),
    RF_PARAM_DESC_INT("precision", 9, 3, 17,
                      "Significant digits of every number; 9 keeps float data exact on re-import."),
    RF_PARAM_DESC_ENUM("rotation_order", "ZYX", "ZYX|ZXY|YXZ|YZX|XYZ|XZY",
                       "Rotation channel order, composed left to right (ZYX: Rz Ry Rx)."),
    RF_PARAM_DESC_BOOL("all_positions", 0,
                       "Give every joint position channels (6 channels), not only roots and joints "
                       "whose translation is animated."),
};

static const rf_node_desc export_node = {
    .size = sizeof(rf_node_desc),
    .type = "bvh.export",
    .kind = RF_KIND_EXPORTER,
    .doc = "Writes a skeleton and its animation as a BVH file that re-imports to the same "
           "skeleton and motion. Skeletons with rotated rest joints (glTF, FBX rigs) are written "
           "with world-aligned OFFSETs, keeping every frame's world pose.",
    RF_NODE_INPUTS(export_inputs),
    RF_NODE_PARAMS(export_params),
    .process = export_process,
    .get_extension = get_extension,
    .flags = RF_NODE_CONCURRENT,
};

static const rf_node_desc *const nodes[] = {&import_node, &export_node};

RF_PLUGIN_DEFINE("org.rigflow.bvh", "BVH", "0.1.0",
                 "Biovision Hierarchy (.bvh) motion capture import and export", nodes);
