/* glTF 2.0 writer (.gltf with the buffer embedded, or .glb): convenience library librfgltf.
 *
 * Writes a skeleton as a node tree, a skinned mesh with its skin (inverse bind matrices) when a
 * mesh is given, and one animation whose samplers share a single time accessor (one sampling
 * rate), keeping only the channels that differ from the rest pose. doc/formats/gltf.md says why
 * this is our own writer rather than Assimp's exporter.
 */
#ifndef RF_GLTF_WRITE_H
#define RF_GLTF_WRITE_H

#include <stdbool.h>
#include <stddef.h>

#include <rigflow/rigflow.h>

typedef struct rf_gltf_write_opts {
    bool binary;           /* GLB; otherwise JSON with the buffer as a base64 data URI */
    double epsilon;        /* a channel whose every frame is within this of the rest value is left
                            * out (radians for rotations, scene units for translations); 0: 1e-6 */
    const char *generator; /* asset.generator; NULL: "rigflow" */
} rf_gltf_write_opts;

/* Writes `path`. `animation` and `mesh` may be NULL (a mesh with no vertices counts as none); a
 * given animation must match the skeleton's joint count, and a skinned mesh's joint indices must
 * be within it. `name` names the output in messages (NULL: path). On failure returns false with
 * a message in err and leaves no file behind. opts may be NULL (JSON by the path's extension:
 * ".glb" means binary). */
bool rf_gltf_write_file(const char *path, const char *name, const rf_skeleton *skeleton,
                        const rf_animation *animation, const rf_mesh *mesh,
                        const rf_gltf_write_opts *opts, char *err, size_t err_size);

#endif
