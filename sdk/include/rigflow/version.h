/* rigflow SDK: the plugin ABI version.
 *
 * A plugin records the version it was built against in its entry (see plugin.h). The host accepts
 * a plugin whose major equals the host's major and whose minor is not greater than the host's
 * minor: minors only ever append fields and functions, so an older plugin sees a prefix of what
 * the host offers. The patch number never affects compatibility.
 */
#ifndef RIGFLOW_VERSION_H
#define RIGFLOW_VERSION_H

#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* History (minors only append):
 *   1.0  plugin entry, node descriptors, host table; skeleton, animation, mesh, mapping
 *   1.1  skeleton bind pose and rest source; mesh parts; clip lists; the self-test extension;
 *        mapping sections and sides
 *   1.2  the mesh's look (UV sets, colours, tangents, part materials, materials, images) and
 *        morph targets; every clip's motion on a clip list
 *   1.3  node types that may process beside other nodes (rf_node_desc.flags,
 *        RF_NODE_CONCURRENT) and the stream they print on (rf_host.out)
 *   1.4  where in its source's timeline a clip starts (rf_animation.source_start) */
#define RF_ABI_VERSION_MAJOR 1
#define RF_ABI_VERSION_MINOR 4
#define RF_ABI_VERSION_PATCH 0

typedef struct rf_version {
    uint32_t major;
    uint32_t minor;
    uint32_t patch;
} rf_version;

/* The version this header describes, for initialising an entry's `abi` field. */
#define RF_ABI_VERSION_INIT                                                                        \
    {                                                                                              \
        RF_ABI_VERSION_MAJOR, RF_ABI_VERSION_MINOR, RF_ABI_VERSION_PATCH                           \
    }

/* True when a plugin built against `plugin` may be loaded by a host built against `host`. */
static inline bool rf_version_compatible(rf_version host, rf_version plugin)
{
    return plugin.major == host.major && plugin.minor <= host.minor;
}

#ifdef __cplusplus
}
#endif

#endif
