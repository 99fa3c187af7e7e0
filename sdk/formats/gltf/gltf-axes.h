/* glTF's axes for the writer: content turned so the skeleton's declared up is +Y and its facing
 * +Z, as glTF 2.0 fixes them (private to librigflow-gltf). */
#ifndef RF_GLTF_AXES_H
#define RF_GLTF_AXES_H

#include <stdbool.h>

#include <rigflow/rigflow.h>

/* What the writer writes: the caller's data, or turned copies of it (owned here). */
typedef struct rf_gw_axes {
    const rf_skeleton *skeleton;
    const rf_animation **animations; /* [count] */
    const rf_mesh *mesh;
    rf_skeleton *own_skeleton;
    rf_animation **own_animations;
    rf_mesh *own_mesh;
} rf_gw_axes;

/* The turn taking `up` to +Y and `forward` (made level) to +Z; the identity when up is unknown
 * (zero), only up's turn when the facing is unknown or along up. */
rf_quat rf_gw_axes_turn(rf_vec3 up, rf_vec3 forward);

/* Fills `x` with the data to write: the inputs as they are when the skeleton already declares
 * glTF's axes (or none), else copies turned as a whole (root joints' rest and bind poses, their
 * keys, the mesh's vertices, normals, tangents, morph displacements and inverse binds), so
 * readers that take glTF's convention see the character upright and facing +Z. False when out of
 * memory. Free with rf_gw_axes_clear. */
bool rf_gw_axes_conform(rf_gw_axes *x, const rf_skeleton *s, const rf_animation *const *a,
                        uint32_t count, const rf_mesh *m);
void rf_gw_axes_clear(rf_gw_axes *x, uint32_t count);

#endif
