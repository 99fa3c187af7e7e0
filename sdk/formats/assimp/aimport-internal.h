/* Shared state of one import, split across aimport.c (scene, joints, skeleton, axes),
 * aimport-mesh.c (merged skinned mesh) and aimport-anim.c (clips and resampling). */
#ifndef RF_AIMPORT_INTERNAL_H
#define RF_AIMPORT_INTERNAL_H

#include <stdint.h>

#include <assimp/cfileio.h>
#include <assimp/scene.h>

#include "aimport-io.h"
#include "rigflow/aimport.h"
#include <rigflow/model-copy.h>

typedef struct rf_ai_ctx {
    const char *path;
    const struct aiScene *scene;
    rf_ai_log_fn log;
    void *user;
    char *err;
    size_t err_size;
    rf_ai_confine confine; /* what Assimp, and the texture reader, may open */
    struct aiFileIO io;

    /* Every node of the scene in depth-first pre-order (parents before children). */
    unsigned node_count;
    const struct aiNode **nodes;
    int *node_parent;              /* [node] index of the parent node, -1 for the scene root */
    rf_mat4 *node_global;          /* [node] scene-root space transform */
    const struct aiBone **bone_of; /* [node] the first bone naming the node, or NULL */
    rf_mat4 *bone_offset;          /* [node] that bone's inverse bind in model space */
    rf_mat4 *mesh_space;           /* [aiMesh] mesh space to model space (see mesh_spaces) */
    double *weight_sum;            /* [node] sum of skin weights over every mesh */
    uint8_t *animated;             /* [node] keyed by some clip */
    int *joint_of;                 /* [node] joint index, or -1 */

    struct rf_ai_name_ref *by_name; /* every node, sorted by name (rf_ai_find_node) */

    unsigned joint_count;
    int *joint_node;      /* [joint] node index */
    rf_mat4 *bind_global; /* [joint] world bind transform */
} rf_ai_ctx;

/* Printf-style error into ctx->err naming ctx->path first; returns false for tail calls. */
bool rf_ai_fail(rf_ai_ctx *c, const char *fmt, ...) RF_PRINTF(2, 3);
void rf_ai_logf(rf_ai_ctx *c, int level, const char *fmt, ...) RF_PRINTF(3, 4);

rf_mat4 rf_ai_mat4(const struct aiMatrix4x4 *m);
/* Index of the node named `name`, or -1 (linear: call once per bone or channel). */
int rf_ai_find_node(const rf_ai_ctx *c, const char *name);
/* Nearest joint at or above node n, or -1. */
int rf_ai_joint_above(const rf_ai_ctx *c, int n);
/* Local node transform of joint j as the animation sees it: for a root joint, the product of
 * every ancestor's transform (static ancestors are baked into the root). */
rf_mat4 rf_ai_joint_node_local(const rf_ai_ctx *c, unsigned j);

/* aimport-mesh.c: merges every mesh instance into one mesh; NULL result with true when the scene
 * has no triangles. */
bool rf_ai_build_mesh(rf_ai_ctx *c, rf_mesh **out);
void rf_ai_skin_end_sites(rf_skeleton *s, const rf_mesh *m);

/* aimport-look.c: the materials of the parts (part_mesh: [part] aiMesh index) and their images
 * into m; textures that cannot be had are left out with a warning. False when out of memory. */
bool rf_ai_build_materials(rf_ai_ctx *c, rf_mesh *m, const unsigned *part_mesh);

/* aimport-anim.c */
bool rf_ai_list_clips(rf_ai_ctx *c, const rf_ai_options *o, rf_ai_result *r);
bool rf_ai_select_clip(rf_ai_ctx *c, const char *spec, int *index);
bool rf_ai_build_animation(rf_ai_ctx *c, const rf_skeleton *s, int clip, const rf_ai_clip *info,
                           rf_animation **out);

#endif
