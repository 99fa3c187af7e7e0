/* The rig.template plugin: node type rig.template (kind rigger), mesh in, skeleton and skinned
 * mesh out. A humanoid or quadruped template with standard joint names laid into the general
 * rigger's curve skeleton (rig-template.c); doc/autorig.md explains the method. */
#include <stdio.h>
#include <string.h>

#include <rigflow/rigflow.h>
#include <rigflow/rigger.h>

#include "rig-node.h"

static const rf_port_desc rf_tpl_inputs[] = {RF_RIG_NODE_INPUTS};

static const rf_port_desc rf_tpl_outputs[] = {
    RF_PORT_DESC("skeleton", RF_TYPE_SKELETON, 0,
                 "the template's joints (Hips, Spine, Spine1, Spine2, Neck, Head, LeftShoulder, "
                 "LeftArm, LeftForeArm, LeftHand, LeftUpLeg, LeftLeg, LeftFoot, LeftToeBase, the "
                 "Right ones, Tail..Tail3 for a quadruped with a tail); rest = bind pose, joints "
                 "unrotated"),
    RF_PORT_DESC("mesh", RF_TYPE_MESH, 0,
                 "the input mesh skinned to it by bone heat (every vertex weighted, at most 4 "
                 "joints)"),
    RF_PORT_DESC("animation", RF_TYPE_ANIMATION, 0, "one frame of the rest pose"),
};

static const rf_param_desc rf_tpl_params[] = {
    RF_PARAM_DESC_ENUM("template", "auto", "auto|humanoid|quadruped",
                       "auto: the humanoid for a body with a pair of legs and a pair of arms, the "
                       "quadruped for two pairs of legs; a body that fits none is refused"),
    RF_RIG_NODE_PARAMS,
};

static rf_rig_template_kind rf_tpl_kind(const char *s)
{
    return s && strcmp(s, "humanoid") == 0    ? RF_RIG_TEMPLATE_HUMANOID
           : s && strcmp(s, "quadruped") == 0 ? RF_RIG_TEMPLATE_QUADRUPED
                                              : RF_RIG_TEMPLATE_AUTO;
}

static bool rf_tpl_process(void *self, const rf_host *host, rf_node *node)
{
    (void)self;
    const rf_mesh *in = host->input(node, "mesh", 0);
    rf_rig_options o = rf_rig_node_options(host, node);
    rf_rig_template_kind kind = rf_tpl_kind(host->param_string(node, "template"));
    rf_skeleton *s = NULL;
    rf_mesh *m = NULL;
    rf_rig_stats st;
    char err[512];
    rf_rig_node_ctx ctx = {host, node};
    if (!in) {
        host->error(node, "no mesh on input 'mesh'");
        return false;
    }
    if (!rf_rig_template(in, &o, kind, &s, &m, &st, rf_rig_node_progress, &ctx, err, sizeof err)) {
        host->error(node, "cannot rig the mesh with a template: %s", err);
        return false;
    }
    return rf_rig_node_output(host, node, s, m, &st);
}

static bool rf_tpl_api_rig(const rf_mesh *mesh, rf_skeleton **skeleton, rf_mesh **skinned,
                           char *err, size_t err_size)
{
    return rf_rig_template(mesh, NULL, RF_RIG_TEMPLATE_AUTO, skeleton, skinned, NULL, NULL, NULL,
                           err, err_size);
}

static bool rf_tpl_api_rig_axes(const rf_mesh *mesh, const rf_skeleton *axes,
                                rf_skeleton **skeleton, rf_mesh **skinned, char *err,
                                size_t err_size)
{
    rf_rig_options o = rf_rig_axes_options(axes);
    return rf_rig_template(mesh, &o, RF_RIG_TEMPLATE_AUTO, skeleton, skinned, NULL, NULL, NULL, err,
                           err_size);
}

static const rf_rigger_api rf_tpl_api = {
    .size = sizeof(rf_rigger_api),
    .name = "template",
    .doc = "humanoid or quadruped template laid into the curve skeleton, bone-heat weights",
    .rig = rf_tpl_api_rig,
    .skin = rf_rig_node_skin,
    .rig_axes = rf_tpl_api_rig_axes,
};

static const void *rf_tpl_extension(const char *id)
{
    return strcmp(id, RF_RIGGER_EXTENSION) == 0 ? &rf_tpl_api : NULL;
}

static const rf_node_desc rf_rig_template_node = {
    .size = sizeof(rf_node_desc),
    .type = "rig.template",
    .kind = RF_KIND_RIGGER,
    .doc = "Rigs a humanoid or a quadruped from its mesh with a template of standard joint names "
           "(Hips, Spine, LeftUpLeg, ...): the general rigger's curve skeleton, read by the "
           "skeleton analysis (legs, arms, sides, girdles, head, tail), carries the template's "
           "joints at their relative places along each chain, elbows and knees at the chain's "
           "bend; skin weights by bone heat. A body that fits no template is refused with the "
           "reason, so a pipeline can fall back to rig.general. See doc/autorig.md.",
    RF_NODE_INPUTS(rf_tpl_inputs),
    RF_NODE_OUTPUTS(rf_tpl_outputs),
    RF_NODE_PARAMS(rf_tpl_params),
    .process = rf_tpl_process,
    .get_extension = rf_tpl_extension,
};

static const rf_node_desc *const rf_tpl_nodes[] = {&rf_rig_template_node};

RF_PLUGIN_DEFINE("org.rigflow.rig-template", "Template auto-rigger", "0.1.0",
                 "a humanoid or quadruped template skeleton with standard names for an unrigged "
                 "mesh",
                 rf_tpl_nodes);
