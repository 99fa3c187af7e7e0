/* The rig.general plugin: node type rig.general (kind rigger), mesh in, skeleton and skinned mesh
 * out. The work is in librigauto (rig.h); doc/autorig.md explains the method. */
#include <stdio.h>
#include <string.h>

#include <rigflow/rigflow.h>
#include <rigflow/rigger.h>

#include "rig.h"

static const rf_port_desc rf_rig_inputs[] = {
    RF_PORT_DESC("mesh", RF_TYPE_MESH, 0,
                 "the mesh to rig (any skin it has is ignored): one body, loose parts allowed"),
    RF_PORT_DESC("axes", RF_TYPE_SKELETON, RF_PORT_OPTIONAL,
                 "the importer's skeleton (even an empty one): its up and forward, as the file "
                 "declares them, are kept; without it they come from the skeleton analysis"),
};

static const rf_port_desc rf_rig_outputs[] = {
    RF_PORT_DESC("skeleton", RF_TYPE_SKELETON, 0,
                 "the curve skeleton cut into joints; rest = bind pose, joints unrotated, names "
                 "from the skeleton analysis (e.g. leg_l0_1)"),
    RF_PORT_DESC("mesh", RF_TYPE_MESH, 0,
                 "the input mesh skinned to it by bone heat (every vertex weighted, at most 4 "
                 "joints)"),
    RF_PORT_DESC("animation", RF_TYPE_ANIMATION, 0, "one frame of the rest pose"),
};

static const rf_param_desc rf_rig_params[] = {
    RF_PARAM_DESC_INT("resolution", 96, 16, 256,
                      "voxels along the longest bounding-box edge for the skeleton (default 96)"),
    RF_PARAM_DESC_INT("proxy_triangles", 20000, 1000, 1000000,
                      "meshes above this are simplified into a proxy for the weights"),
    RF_PARAM_DESC_FLOAT("speck_size", 0.02, 0.001, 0.5,
                        "loose parts smaller than this fraction of the mesh's diagonal are specks"),
    RF_PARAM_DESC_FLOAT("segment", 0.12, 0.02, 1,
                        "bone length, as a fraction of the longest bounding-box edge"),
    RF_PARAM_DESC_BOOL("visibility", 1,
                       "heat a vertex only from bones it can see (ray casting); false: from the "
                       "nearest bone"),
};

typedef struct rf_rig_node_ctx {
    const rf_host *host;
    rf_node *node;
} rf_rig_node_ctx;

static void rf_rig_node_progress(void *user, double f)
{
    rf_rig_node_ctx *c = user;
    c->host->progress(c->node, f);
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

static bool rf_rig_process(void *self, const rf_host *host, rf_node *node)
{
    (void)self;
    const rf_mesh *in = host->input(node, "mesh", 0);
    rf_rig_options o = {
        .resolution = (uint32_t)host->param_int(node, "resolution"),
        .proxy_triangles = (uint32_t)host->param_int(node, "proxy_triangles"),
        .speck_size = host->param_float(node, "speck_size"),
        .segment = host->param_float(node, "segment"),
        .no_visibility = !host->param_bool(node, "visibility"),
    };
    const rf_skeleton *axes = host->input_count(node, "axes") ? host->input(node, "axes", 0) : NULL;
    if (axes)
        o.up = axes->up, o.forward = axes->forward;
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
    host->log(node, RF_LOG_INFO,
              "%u joints; %u vertices (%u welded), %u loose parts of which %u specks, heat on %u "
              "triangles: %u vertices by heat, %u by nearest bone, %u saw no bone",
              st.joints, st.vertices, st.welded, st.parts, st.specks, st.proxy_triangles,
              st.heat_vertices, st.fallback_vertices, st.unseen_vertices);
    if (st.joints < 3)
        host->log(node, RF_LOG_WARNING,
                  "only %u joints: the mesh has no limbs the voxel skeleton can separate (a blob?)",
                  st.joints);
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

static bool rf_rig_api_rig(const rf_mesh *mesh, rf_skeleton **skeleton, rf_mesh **skinned,
                           char *err, size_t err_size)
{
    return rf_rig_general(mesh, NULL, skeleton, skinned, NULL, NULL, NULL, err, err_size);
}

static bool rf_rig_api_skin(const rf_mesh *mesh, const rf_skeleton *skeleton,
                            const rf_mat4 *inverse_bind, rf_mesh **skinned, char *err,
                            size_t err_size)
{
    return rf_rig_bind(mesh, skeleton, inverse_bind, NULL, skinned, NULL, err, err_size);
}

static const rf_rigger_api rf_rig_api = {
    .size = sizeof(rf_rigger_api),
    .name = "general",
    .doc = "voxel curve skeleton from geodesic level sets, bone-heat weights",
    .rig = rf_rig_api_rig,
    .skin = rf_rig_api_skin,
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
