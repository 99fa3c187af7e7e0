/* Node glue shared by assimp.import and the generic import node: parameters in, outputs out.
 * (Part of librfassimp so both plugins declare the same parameters and behave alike.) Nothing
 * here calls Assimp: the import itself is aimport-node-import.c. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rigflow/aimport-node.h"

const rf_param_desc rf_ai_node_params[RF_AI_NODE_PARAM_COUNT] = {
    RF_PARAM_DESC_INPUT_PATH(
        "path", RF_PARAM_REQUIRED,
        "the model file (anything Assimp reads: glTF/GLB, FBX, .x, Collada, B3D, Ogre, MD5...)"),
    RF_PARAM_DESC_STRING(
        "clip", "",
        "the clip to import, by name or index; empty for the first (the clips output lists them); "
        "* imports every clip onto the clips output (the first is also the animation)"),
    RF_PARAM_DESC_ENUM(
        "rest_pose", "bind", "bind|node",
        "rest pose: bind (default: the pose the mesh was skinned in, so the skeleton fits the "
        "mesh) or node (the scene nodes' transforms); both are kept in the skeleton's bind field"),
    RF_PARAM_DESC_FLOAT("fps", 0, 0, 1000,
                        "resampling rate; 0 (default) keeps the clip's own key rate when its keys "
                        "are regular, else 30"),
    RF_PARAM_DESC_BOOL(
        "require_skeleton", 1,
        "refuse a file without a skeleton (default); false imports meshes of unrigged files"),
    RF_PARAM_DESC_BOOL(
        "ignore_rig", 0,
        "import the bare mesh (bind pose, no skin, no joints, no clips) for a rigger"),
};

const rf_port_desc rf_ai_node_outputs[RF_AI_NODE_OUTPUT_COUNT] = {
    RF_PORT_DESC("skeleton", RF_TYPE_SKELETON, 0,
                 "joints with unique names; rest pose as chosen, bind pose in the bind field; up "
                 "and forward"),
    RF_PORT_DESC(
        "animation", RF_TYPE_ANIMATION, 0,
        "the chosen clip resampled to a fixed rate (one rest frame when the file has no clip)"),
    RF_PORT_DESC(
        "mesh", RF_TYPE_MESH, 0,
        "every mesh merged, skinned to the skeleton (top 4 weights), inverse binds, with its "
        "materials, images, UV sets, colours, tangents and morph targets; may be empty"),
    RF_PORT_DESC("clips", RF_TYPE_CLIPS, 0,
                 "every clip in the file and which was used; with clip *, each one's motion too"),
};

static rf_clip_list *rf_ai_node_clips(rf_ai_result *r)
{
    rf_clip_list *l = rf_clip_list_new(r->clip_count);
    if (!l)
        return NULL;
    l->selected = r->selected_clip;
    l->animations = r->clip_animations; /* moved too (NULL unless every clip was imported) */
    r->clip_animations = NULL;
    for (uint32_t i = 0; i < r->clip_count; i++) {
        l->clips[i].name = r->clips[i].name; /* moved: the result forgets them below */
        r->clips[i].name = NULL;
        l->clips[i].duration = r->clips[i].duration;
        l->clips[i].fps = r->clips[i].fps;
        l->clips[i].frames = r->clips[i].frames;
    }
    return l;
}

bool rf_ai_node_outputs_set(const rf_host *host, rf_node *node, rf_ai_result *r)
{
    rf_clip_list *clips = rf_ai_node_clips(r);
    rf_mesh *mesh = r->mesh ? r->mesh : rf_mesh_new();
    if (!clips || !mesh) {
        rf_clip_list_free(clips);
        if (mesh != r->mesh)
            rf_mesh_free(mesh);
        host->error(node, "out of memory");
        return false;
    }
    bool ok = host->set_output(node, "skeleton", r->skeleton, rf_skeleton_free);
    ok = host->set_output(node, "animation", r->animation, rf_animation_free) && ok;
    ok = host->set_output(node, "mesh", mesh, rf_mesh_free) && ok;
    ok = host->set_output(node, "clips", clips, rf_clip_list_free) && ok;
    r->skeleton = NULL, r->animation = NULL, r->mesh = NULL; /* the host owns them now */
    rf_ai_result_clear(r);
    if (!ok)
        host->error(node, "the host refused an output");
    return ok;
}

/* Here rather than in aimport.c: a plugin that only hands results on (the converter, which
 * loads the Assimp import on first use, aimport-node.h) links no Assimp code through it. */
void rf_ai_result_clear(rf_ai_result *r)
{
    rf_skeleton_free(r->skeleton);
    rf_animation_free(r->animation);
    rf_mesh_free(r->mesh);
    for (unsigned i = 0; i < r->clip_count; i++) {
        free(r->clips[i].name);
        if (r->clip_animations)
            rf_animation_free(r->clip_animations[i]);
    }
    free(r->clips);
    free(r->clip_animations);
    memset(r, 0, sizeof *r);
    r->selected_clip = -1;
}
