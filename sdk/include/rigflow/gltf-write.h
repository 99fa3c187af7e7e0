/* glTF 2.0 writer (.gltf with the buffer embedded, or .glb): convenience library librfgltf.
 *
 * Writes a skeleton as a node tree with a skin (inverse bind matrices; without a mesh too, so
 * readers build an armature), a skinned mesh with its materials and embedded images when a mesh
 * is given, and animations whose samplers share one time accessor each (one sampling rate),
 * keeping only the channels that differ from the rest pose. doc/formats/gltf.md says why
 * this is our own writer rather than Assimp's exporter.
 */
#ifndef RF_GLTF_WRITE_H
#define RF_GLTF_WRITE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

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

/* As rf_gltf_write_file with several clips, written as one named glTF animation each (NULL
 * entries are skipped). The mesh's materials, textures (images embedded), texture coordinates,
 * vertex colours and tangents are written too. */
bool rf_gltf_write_clips(const char *path, const char *name, const rf_skeleton *skeleton,
                         const rf_animation *const *animations, uint32_t animation_count,
                         const rf_mesh *mesh, const rf_gltf_write_opts *opts, char *err,
                         size_t err_size);

/* Whether a GLB of a `json_bytes` JSON text and `bin_bytes` of binary data fits in the format's
 * uint32 length fields (headers and padding counted): GLB holds at most 4 GiB - 1 bytes. On
 * false the message in err names `name`, the size the file would have and the limit. The
 * writers check it before opening the file. */
bool rf_gltf_glb_fits(const char *name, uint64_t json_bytes, uint64_t bin_bytes, char *err,
                      size_t err_size);

#endif
