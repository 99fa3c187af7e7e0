/* A mesh drawing a skeleton: one thin double pyramid per bone, skinned to the bone's joint. */
#ifndef RF_CV_BONE_MESH_H
#define RF_CV_BONE_MESH_H

#include <rigflow/rigflow.h>

/* A mesh of one double pyramid per bone (parent to child at rest, a tenth as wide as long),
 * each vertex weighted wholly to the parent, so a glTF viewer that draws only meshes (Blender's
 * renders, three.js's editor) shows a mesh-less skeleton's motion. A bone whose child moves
 * against its parent in any of the nclips clips (its local translation straying by over 5% of
 * its length: a root carrying the hips) is not drawn, as no rigid bone can follow it; clips of
 * another joint count are not looked at. NULL when the skeleton has no bone of any length to
 * draw, a parent after its child, a rest position that is not finite or more than 65536
 * joints, or out of memory (err says which). (transfer full: rf_mesh_free) */
rf_mesh *rf_cv_bone_mesh(const rf_skeleton *s, const rf_animation *const *clips, uint32_t nclips,
                         char *err, size_t err_size);

#endif
