/* The convert plugin's Assimp import, a module of its own (convert-assimp.mod beside convert.so)
 * that the plugin loads the first time it imports something other than BVH (convert.c): opening
 * libassimp and what it needs (libstdc++, draco) costs about 2.5 ms of relocations, which a run
 * that reads only BVH never needs. One exported symbol, RF_CV_ASSIMP_SYMBOL. */
#include <rigflow/rigflow.h>

#include "rigflow/aimport-node.h"

#include "convert-assimp.h"

RF_PLUGIN_EXPORT bool rf_cv_assimp_import(const rf_host *host, rf_node *node)
{
    return rf_ai_node_import(host, node);
}
