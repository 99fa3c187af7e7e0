/* Rigger node plumbing shared by rig.general and rig.template (rig-node.h). */
#include "rig-node.h"

void rf_rig_node_progress(void *user, double f)
{
    rf_rig_node_ctx *c = user;
    c->host->progress(c->node, f);
}

rf_rig_options rf_rig_node_options(const rf_host *host, rf_node *node)
{
    const rf_skeleton *axes = host->input_count(node, "axes") ? host->input(node, "axes", 0) : NULL;
    rf_rig_options o = rf_rig_axes_options(axes);
    o.resolution = (uint32_t)host->param_int(node, "resolution");
    o.proxy_triangles = (uint32_t)host->param_int(node, "proxy_triangles");
    o.speck_size = host->param_float(node, "speck_size");
    o.segment = host->param_float(node, "segment");
    o.no_visibility = !host->param_bool(node, "visibility");
    return o;
}

rf_rig_options rf_rig_axes_options(const rf_skeleton *axes)
{
    rf_rig_options o = {0};
    if (axes)
        o.up = axes->up, o.forward = axes->forward;
    return o; /* zeros elsewhere: the riggers take their defaults */
}

/* One frame holding the rest pose, so exporters and retargeters have an animation to start from. */
static rf_animation *rf_rig_rest_clip(const rf_skeleton *s)
{
    rf_animation *a = rf_animation_new(s->joint_count, 1, 30);
    for (uint32_t j = 0; a && j < s->joint_count; j++) {
        rf_animation_set_translation(a, 0, j, s->joints[j].rest.t);
        rf_animation_set_rotation(a, 0, j, s->joints[j].rest.r);
    }
    return a;
}

bool rf_rig_node_output(const rf_host *host, rf_node *node, rf_skeleton *s, rf_mesh *m,
                        const rf_rig_stats *st)
{
    host->log(
        node, RF_LOG_INFO,
        "%u joints; %u vertices (%u welded), %u loose parts of which %u specks, heat on %u "
        "triangles: %u vertices by heat, %u (specks) by the surface nearest them, %u saw no bone",
        st->joints, st->vertices, st->welded, st->parts, st->specks, st->proxy_triangles,
        st->heat_vertices, st->fallback_vertices, st->unseen_vertices);
    if (st->up_note[0]) /* a file that declares no up: how the rig's up was decided */
        host->log(node, st->up_assumed ? RF_LOG_WARNING : RF_LOG_INFO, "%s", st->up_note);
    rf_animation *a = rf_rig_rest_clip(s);
    if (!a) {
        rf_skeleton_free(s), rf_mesh_free(m);
        host->error(node, "out of memory");
        return false;
    }
    bool ok = host->set_output(node, "skeleton", s, rf_skeleton_free);
    ok = host->set_output(node, "mesh", m, rf_mesh_free) && ok;
    ok = host->set_output(node, "animation", a, rf_animation_free) && ok;
    if (!ok)
        host->error(node, "the host refused an output");
    return ok;
}

bool rf_rig_node_skin(const rf_mesh *mesh, const rf_skeleton *skeleton, const rf_mat4 *inverse_bind,
                      rf_mesh **skinned, char *err, size_t err_size)
{
    return rf_rig_bind(mesh, skeleton, inverse_bind, NULL, skinned, NULL, err, err_size);
}
