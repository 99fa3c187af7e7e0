/* The module holding the convert plugin's Assimp import (convert-assimp.c). */
#ifndef RF_CONVERT_ASSIMP_H
#define RF_CONVERT_ASSIMP_H

#include <rigflow/plugin.h>

/* Its file, in the convert plugin's own folder: not .so, since the host opens every .so of a
 * plugin folder as a plugin. */
#define RF_CV_ASSIMP_MODULE "convert-assimp.mod"
#define RF_CV_ASSIMP_SYMBOL "rf_cv_assimp_import"

/* rf_ai_node_import (rigflow/aimport-node.h). */
typedef bool (*rf_cv_assimp_import_fn)(const rf_host *host, rf_node *node);
bool rf_cv_assimp_import(const rf_host *host, rf_node *node);

#endif
