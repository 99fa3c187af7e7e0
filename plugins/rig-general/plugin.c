/* The rig.general plugin: node type rig.general (kind rigger), mesh in, skeleton and skinned mesh
 * out. The work is in librigauto (rig.h); doc/autorig.md explains the method. */
#include <stdio.h>
#include <string.h>

#include <rigflow/rigflow.h>
#include <rigflow/rigger.h>

#include "rig-node.h"

static const rf_port_desc rf_rig_inputs[] = {RF_RIG_NODE_INPUTS};

static const rf_port_desc rf_rig_outputs[] = {
    RF_PORT_DESC("skeleton", RF_TYPE_SKELETON, 0,
                 "the curve skeleton cut into joints; rest = bind pose, joints unrotated, names "
                 "from the skeleton analysis (e.g. leg_l0_1)"),
    RF_PORT_DESC("mesh", RF_TYPE_MESH, 0,
                 "the input mesh skinned to it by bone heat (every vertex weighted, at most 4 "
                 "joints)"),
    RF_PORT_DESC("animation", RF_TYPE_ANIMATION, 0, "one frame of the rest pose"),
};

static const rf_param_desc rf_rig_params[] = {RF_RIG_NODE_PARAMS};

static bool rf_rig_process(void *self, const rf_host *host, rf_node *node)
{
    (void)self;
    const rf_mesh *in = host->input(node, "mesh", 0);
    rf_rig_options o = rf_rig_node_options(host, node);
    rf_skeleton *s = NULL;
    rf_mesh *m = NULL;
    rf_rig_stats st;
    char err[512];
    rf_rig_node_ctx ctx = {host, node};
    if (!in) {
        host->error(node, "no mesh on input 'mesh'");
        return false;
    }
    if (!rf_rig_general(in, &o, &s, &m, &st, rf_rig_node_progress, &ctx, err, sizeof err)) {
        host->error(node, "cannot rig the mesh%s%s: %s", in->name ? " " : "",
                    in->name ? "(named in the file)" : "", err);
        return false;
    }
    if (st.joints < 3)
        host->log(node, RF_LOG_WARNING,
                  "only %u joints: the mesh has no limbs the voxel skeleton can separate (a blob?)",
                  st.joints);
    return rf_rig_node_output(host, node, s, m, &st);
}

static bool rf_rig_api_rig(const rf_mesh *mesh, rf_skeleton **skeleton, rf_mesh **skinned,
                           char *err, size_t err_size)
{
    return rf_rig_general(mesh, NULL, skeleton, skinned, NULL, NULL, NULL, err, err_size);
}

static bool rf_rig_api_rig_axes(const rf_mesh *mesh, const rf_skeleton *axes,
                                rf_skeleton **skeleton, rf_mesh **skinned, char *err,
                                size_t err_size)
{
    rf_rig_options o = rf_rig_axes_options(axes);
    return rf_rig_general(mesh, &o, skeleton, skinned, NULL, NULL, NULL, err, err_size);
}

static const rf_rigger_api rf_rig_api = {
    .size = sizeof(rf_rigger_api),
    .name = "general",
    .doc = "voxel curve skeleton from geodesic level sets, bone-heat weights",
    .rig = rf_rig_api_rig,
    .skin = rf_rig_node_skin,
    .rig_axes = rf_rig_api_rig_axes,
};

static const void *rf_rig_extension(const char *id)
{
    return strcmp(id, RF_RIGGER_EXTENSION) == 0 ? &rf_rig_api : NULL;
}

static const rf_node_desc rf_rig_general_node = {
    .size = sizeof(rf_node_desc),
    .type = "rig.general",
    .kind = RF_KIND_RIGGER,
    .doc = "Rigs any body from its mesh: a curve skeleton from the voxelised volume (geodesic "
           "level sets grown from where the feet meet), pruned and cut into joints at junctions "
           "and even lengths, named by the skeleton analysis; skin weights by bone heat "
           "(visibility by Embree, solved with CHOLMOD). Welds, sets specks aside, simplifies "
           "big scans into a proxy. See doc/autorig.md.",
    RF_NODE_INPUTS(rf_rig_inputs),
    RF_NODE_OUTPUTS(rf_rig_outputs),
    RF_NODE_PARAMS(rf_rig_params),
    .process = rf_rig_process,
    .get_extension = rf_rig_extension,
};

static const rf_node_desc *const rf_rig_nodes[] = {&rf_rig_general_node};

RF_PLUGIN_DEFINE("org.rigflow.rig-general", "General auto-rigger", "0.1.0",
                 "skeleton and skin weights for an unrigged mesh of any body", rf_rig_nodes);
