/* The Assimp importer plugin: node type assimp.import. The work is in librfassimp (aimport.c). */
#include <rigflow/rigflow.h>

#include "rigflow/aimport-node.h"

static bool rf_assimp_process(void *self, const rf_host *host, rf_node *node)
{
    (void)self;
    return rf_ai_node_import(host, node);
}

/* Whatever Assimp reads: the host then prefers an importer that names a file's suffix. */
static const rf_importer_info rf_assimp_importer = {sizeof(rf_importer_info), "*", "path"};

static const void *rf_assimp_extension(const char *id)
{
    return strcmp(id, RF_IMPORTER_EXTENSION) == 0 ? &rf_assimp_importer : NULL;
}

static const rf_node_desc rf_assimp_import = {
    .size = sizeof(rf_node_desc),
    .type = "assimp.import",
    .kind = RF_KIND_IMPORTER,
    .doc = "Imports a rigged model through Assimp: skeleton (skin bones, their ancestors and "
           "animated helpers, flagged unweighted), one clip (or, with clip *, every clip) "
           "resampled to a fixed rate, every mesh merged and skinned to that skeleton with its "
           "materials, textures, UV sets, colours and morph targets, and the list of clips. See "
           "doc/formats.md.",
    .output_count = RF_AI_NODE_OUTPUT_COUNT,
    .outputs = rf_ai_node_outputs,
    .param_count = RF_AI_NODE_PARAM_COUNT,
    .params = rf_ai_node_params,
    .process = rf_assimp_process,
    .get_extension = rf_assimp_extension,
    .flags = RF_NODE_CONCURRENT,
};

static const rf_node_desc *const rf_assimp_nodes[] = {&rf_assimp_import};

RF_PLUGIN_EXPORT const rf_plugin_entry rigflow_plugin_entry = {
    .abi = RF_ABI_VERSION_INIT,
    .size = sizeof(rf_plugin_entry),
    .id = "org.rigflow.assimp",
    .name = "Assimp importer",
    .version = "0.1.0",
    .description = "glTF/GLB, FBX, DirectX .x, Collada, B3D, Ogre, MD5 and more through Assimp",
    .node_count = 1,
    .nodes = rf_assimp_nodes,
};
