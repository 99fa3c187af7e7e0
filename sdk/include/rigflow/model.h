/* rigflow SDK: the data model that flows between nodes: skeleton, animation, mesh, mapping.
 *
 * Port type ids (checked when a pipeline is validated, never by C type identity):
 *   "rigflow.skeleton"  rf_skeleton      "rigflow.animation" rf_animation
 *   "rigflow.mesh"      rf_mesh          "rigflow.mapping"   rf_mapping
 *   "rigflow.clips"     rf_clip_list
 *
 * Every struct starts with its size (sizeof at the producer's build) so that fields can be appended
 * in later minor versions: a consumer reads a field only when `size` covers it (RF_HAS_FIELD).
 *
 * Memory: the constructors and destructors here are header-only and use the C library's
 * calloc/free, so any plugin can create or free any value without linking the host. A value handed
 * to the host through set_output belongs to the host from then on; values read through input() are
 * borrowed and read-only.
 */
#ifndef RIGFLOW_MODEL_H
#define RIGFLOW_MODEL_H

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "rfmath.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RF_TYPE_SKELETON "rigflow.skeleton"
#define RF_TYPE_ANIMATION "rigflow.animation"
#define RF_TYPE_MESH "rigflow.mesh"
#define RF_TYPE_MAPPING "rigflow.mapping"

/* The size of `type` up to and including `field`: a struct of an older layout ends there. */
#define RF_SIZE_THROUGH(type, field) (offsetof(type, field) + sizeof(((type *)0)->field))

/* True when a struct whose leading size field says `s->size` contains `field`. */
#define RF_HAS_FIELD(s, type, field) ((s)->size >= RF_SIZE_THROUGH(type, field))

/* ---- skeleton ---- */

enum rf_joint_flags {
    RF_JOINT_HAS_END_SITE = 1u << 0, /* end_site holds the tip of a leaf bone */
    RF_JOINT_UNWEIGHTED = 1u << 1,   /* a helper (IK target, pole, control): no skin weights */
};

typedef struct rf_joint {
    char *name;       /* unique within the skeleton; owned by the skeleton */
    int32_t parent;   /* index of the parent, always less than this joint's index; -1 for a root */
    uint32_t flags;   /* rf_joint_flags */
    rf_xform rest;    /* rest pose, local to the parent */
    rf_vec3 end_site; /* tip of a leaf bone in this joint's local space (RF_JOINT_HAS_END_SITE) */
} rf_joint;

typedef struct rf_skeleton {
    uint32_t size;
    uint32_t joint_count;
    rf_joint *joints; /* joint_count entries, parents before children */
    char *name;       /* where the skeleton came from (file name), may be NULL; owned */
    rf_vec3 up;       /* up axis as found in the source, or zero when unknown */
    rf_vec3 forward;  /* facing as found in the source, or zero when unknown */
    /* Appended in 1.1 (check with RF_HAS_FIELD before reading): */
    rf_xform *bind;       /* [joint_count] local bind pose, the pose the mesh was skinned in (world
                           * bind = inverse of the mesh's inverse_bind), or NULL when the source has
                           * none; owned */
    uint32_t rest_source; /* rf_rest_source: what `rest` holds */
} rf_skeleton;

/* Where a skeleton's rest pose came from. Files with a skin carry two candidate poses: the pose
 * the mesh was bound in (bind) and the nodes' own transforms (node), which differ in many files. */
typedef enum rf_rest_source {
    RF_REST_AS_FILE = 0, /* the only pose the format has (e.g. BVH offsets, zero rotations) */
    RF_REST_NODE,        /* the scene nodes' transforms */
    RF_REST_BIND,        /* the bind pose of the skin (equal to `bind`) */
} rf_rest_source;

/* A skeleton of `joint_count` joints, all roots with identity rest and no names, or NULL when out
 * of memory. (transfer full: free with rf_skeleton_free) */
static inline rf_skeleton *rf_skeleton_new(uint32_t joint_count)
{
    rf_skeleton *s = (rf_skeleton *)calloc(1, sizeof *s);
    if (!s)
        return NULL;
    s->size = sizeof *s;
    s->joint_count = joint_count;
    s->joints = (rf_joint *)calloc(joint_count ? joint_count : 1, sizeof *s->joints);
    if (!s->joints) {
        free(s);
        return NULL;
    }
    for (uint32_t i = 0; i < joint_count; i++) {
        s->joints[i].parent = -1;
        s->joints[i].rest = rf_xform_identity();
    }
    return s;
}

/* Frees a skeleton, its joints and their names. NULL is allowed. Usable as a set_output destroy. */
static inline void rf_skeleton_free(void *skeleton)
{
    rf_skeleton *s = (rf_skeleton *)skeleton;
    if (!s)
        return;
    for (uint32_t i = 0; i < s->joint_count; i++)
        free(s->joints[i].name);
    free(s->joints);
    free(s->name);
    if (RF_HAS_FIELD(s, rf_skeleton, bind))
        free(s->bind);
    free(s);
}

/* Index of the joint named `name`, or -1. Linear: look names up once, then work with indices. */
static inline int32_t rf_skeleton_find(const rf_skeleton *s, const char *name)
{
    for (uint32_t i = 0; i < s->joint_count; i++)
        if (s->joints[i].name && strcmp(s->joints[i].name, name) == 0)
            return (int32_t)i;
    return -1;
}

/* The first joint whose parent does not come before it (itself, a later joint or past the end),
 * or -1 when the skeleton keeps the promise above. Writers check it before they place joints:
 * the host does not check a plugin's skeleton. */
static inline int64_t rf_skeleton_misordered(const rf_skeleton *s)
{
    for (uint32_t i = 0; i < s->joint_count; i++)
        if (s->joints[i].parent >= (int32_t)i)
            return i;
    return -1;
}

/* World (model-space) rest transform of every joint into `world` (joint_count entries, caller's).
 */
static inline void rf_skeleton_world_rest(const rf_skeleton *s, rf_xform *world)
{
    for (uint32_t i = 0; i < s->joint_count; i++) {
        int32_t p = s->joints[i].parent;
        world[i] = p < 0 ? s->joints[i].rest : rf_xform_mul(world[p], s->joints[i].rest);
    }
}

/* ---- animation ---- */

enum rf_channel_flags {
    RF_CHANNEL_ROTATION = 1u << 0,    /* the joint's rotation is keyed by the source */
    RF_CHANNEL_TRANSLATION = 1u << 1, /* the joint's translation is keyed by the source */
};

/* Sampled local motion, frames x joints, in two flat arrays (never one allocation per key). */
typedef struct rf_animation {
    uint32_t size;
    uint32_t joint_count; /* matches the skeleton the animation was made for */
    uint32_t frame_count;
    double fps;          /* frames per second, > 0 */
    char *name;          /* clip name, may be NULL; owned */
    float *rotations;    /* [frame][joint][4]: local rotation quaternion x, y, z, w */
    float *translations; /* [frame][joint][3]: local translation (the rest one where not keyed) */
    uint8_t *channels;   /* [joint]: rf_channel_flags, what the source keyed */
    /* 1.4: the time (seconds) in the clip this one was made from that its frame 0 plays, so a
     * node comparing it with that clip (retarget.measure against the retarget's sources) lines
     * the two up: a retarget from its first_frame sets it; 0 for a clip that starts where its
     * source does or has none. A node deriving a clip on the same timeline keeps it. */
    double source_start;
} rf_animation;

/* An animation with all rotations identity and translations zero, or NULL when out of memory or
 * when frames x joints overflows. (transfer full: free with rf_animation_free) */
static inline rf_animation *rf_animation_new(uint32_t joint_count, uint32_t frame_count, double fps)
{
    size_t n = (size_t)joint_count * (size_t)frame_count;
    if (joint_count && n / joint_count != frame_count)
        return NULL;
    if (n > SIZE_MAX / (4 * sizeof(float)))
        return NULL;
    rf_animation *a = (rf_animation *)calloc(1, sizeof *a);
    if (!a)
        return NULL;
    a->size = sizeof *a;
    a->joint_count = joint_count;
    a->frame_count = frame_count;
    a->fps = fps;
    a->rotations = (float *)malloc((n ? n : 1) * 4 * sizeof(float));
    a->translations = (float *)calloc(n ? n : 1, 3 * sizeof(float));
    a->channels = (uint8_t *)calloc(joint_count ? joint_count : 1, 1);
    if (!a->rotations || !a->translations || !a->channels) {
        free(a->rotations);
        free(a->translations);
        free(a->channels);
        free(a);
        return NULL;
    }
    for (size_t i = 0; i < n; i++) {
        float *q = a->rotations + i * 4;
        q[0] = q[1] = q[2] = 0.0f;
        q[3] = 1.0f;
    }
    return a;
}

/* Frees an animation. NULL is allowed. Usable as a set_output destroy. */
static inline void rf_animation_free(void *animation)
{
    rf_animation *a = (rf_animation *)animation;
    if (!a)
        return;
    free(a->rotations);
    free(a->translations);
    free(a->channels);
    free(a->name);
    free(a);
}

static inline rf_quat rf_animation_rotation(const rf_animation *a, uint32_t frame, uint32_t joint)
{
    const float *q = a->rotations + ((size_t)frame * a->joint_count + joint) * 4;
    return rf_quat_make(q[0], q[1], q[2], q[3]);
}
static inline void rf_animation_set_rotation(rf_animation *a, uint32_t frame, uint32_t joint,
                                             rf_quat r)
{
    float *q = a->rotations + ((size_t)frame * a->joint_count + joint) * 4;
    q[0] = (float)r.x, q[1] = (float)r.y, q[2] = (float)r.z, q[3] = (float)r.w;
}
static inline rf_vec3 rf_animation_translation(const rf_animation *a, uint32_t frame,
                                               uint32_t joint)
{
    const float *t = a->translations + ((size_t)frame * a->joint_count + joint) * 3;
    return rf_v3(t[0], t[1], t[2]);
}
static inline void rf_animation_set_translation(rf_animation *a, uint32_t frame, uint32_t joint,
                                                rf_vec3 v)
{
    float *t = a->translations + ((size_t)frame * a->joint_count + joint) * 3;
    t[0] = (float)v.x, t[1] = (float)v.y, t[2] = (float)v.z;
}

/* Local pose of one frame as transforms (scale taken from the skeleton's rest), into `local`
 * (joint_count entries, caller's). */
static inline void rf_animation_local_pose(const rf_animation *a, const rf_skeleton *s,
                                           uint32_t frame, rf_xform *local)
{
    for (uint32_t j = 0; j < a->joint_count && j < s->joint_count; j++) {
        local[j].t = rf_animation_translation(a, frame, j);
        local[j].r = rf_animation_rotation(a, frame, j);
        local[j].s = s->joints[j].rest.s;
    }
}

/* ---- mesh ---- */

#define RF_MESH_MAX_INFLUENCES 4
#define RF_MESH_MAX_UV_SETS 2

typedef struct rf_mesh {
    uint32_t size;
    char *name; /* may be NULL; owned */
    uint32_t vertex_count;
    uint32_t triangle_count;
    float *positions;      /* [vertex][3] */
    float *normals;        /* [vertex][3], or NULL */
    uint32_t *triangles;   /* [triangle][3] vertex indices */
    uint16_t *skin_joints; /* [vertex][4] joint indices, or NULL when the mesh is not skinned */
    float *skin_weights;   /* [vertex][4] weights summing to 1, or NULL */
    uint32_t bind_count;   /* entries in inverse_bind (the skeleton's joint count), or 0 */
    rf_mat4 *inverse_bind; /* [joint] model space to joint space at bind time, or NULL */
    /* Appended in 1.1 (check with RF_HAS_FIELD before reading): */
    uint32_t part_count;        /* source meshes merged into this one, or 0 */
    struct rf_mesh_part *parts; /* [part_count], or NULL; owned */
    /* Appended in 1.2, the look (check with RF_HAS_FIELD before reading): */
    uint32_t uv_set_count;           /* texture coordinate sets in uvs, 0 to RF_MESH_MAX_UV_SETS */
    float *uvs[RF_MESH_MAX_UV_SETS]; /* [set][vertex][2] in glTF's convention: (0, 0) is the image's
                                      * top-left corner, v grows downwards; or NULL */
    float *colors;                   /* [vertex][4] linear RGBA vertex colours, or NULL */
    float *tangents;        /* [vertex][4] unit tangent xyz and the bitangent's sign w (+-1), as
                             * glTF's TANGENT; NULL when the source has none (or no normals) */
    int32_t *part_material; /* [part_count] index into materials of each part, -1 for none; or
                             * NULL (no part has a material) */
    uint32_t material_count;
    struct rf_material **materials; /* [material_count] owned */
    uint32_t image_count;
    struct rf_image **images; /* [image_count] owned; textures name them by index */
    uint32_t morph_target_count;
    struct rf_morph_target **morph_targets; /* [morph_target_count] owned (blend shapes) */
} rf_mesh;

/* glTF sampler values (OpenGL enums): 0 leaves the reader's default (repeat, its own filters). */
enum rf_texture_sampler {
    RF_TEX_NEAREST = 9728,
    RF_TEX_LINEAR = 9729,
    RF_TEX_LINEAR_MIPMAP_LINEAR = 9987,
    RF_TEX_REPEAT = 10497,
    RF_TEX_CLAMP_TO_EDGE = 33071,
    RF_TEX_MIRRORED_REPEAT = 33648,
};

/* A texture a material uses: an image, the coordinate set that maps it, and how it is sampled. */
typedef struct rf_texture_ref {
    int32_t image;           /* index into rf_mesh.images, or -1 for no texture */
    uint32_t uv_set;         /* index of the texture coordinate set, < rf_mesh.uv_set_count */
    float scale;             /* normal map: the normal scale; occlusion: the strength; others: 1 */
    uint16_t wrap_s, wrap_t; /* rf_texture_sampler wrap mode, or 0 */
    uint16_t mag_filter, min_filter; /* rf_texture_sampler filter, or 0 */
} rf_texture_ref;

typedef enum rf_alpha_mode {
    RF_ALPHA_OPAQUE = 0,
    RF_ALPHA_MASK,  /* transparent below alpha_cutoff, opaque above */
    RF_ALPHA_BLEND, /* blended by alpha */
} rf_alpha_mode;

/* A surface in glTF's metallic-roughness terms. Formats with other shading models map onto it
 * on import (diffuse colour and texture become the base colour; doc/formats.md). */
typedef struct rf_material {
    uint32_t size;
    char *name;          /* may be NULL; owned */
    float base_color[4]; /* linear RGBA factor, multiplied with the texture */
    rf_texture_ref base_color_texture;
    float metallic, roughness;                 /* factors in [0, 1] */
    rf_texture_ref metallic_roughness_texture; /* roughness in G, metalness in B */
    rf_texture_ref normal_texture;
    rf_texture_ref occlusion_texture; /* occlusion in R */
    rf_texture_ref emissive_texture;
    float emissive[3];     /* linear RGB factor */
    uint32_t alpha_mode;   /* rf_alpha_mode */
    float alpha_cutoff;    /* RF_ALPHA_MASK only */
    uint32_t double_sided; /* non-zero: both faces are drawn */
} rf_material;

/* An image file's bytes as found in the source (never decoded). */
typedef struct rf_image {
    uint32_t size;
    char *name;      /* where it came from (file name or embedded name), may be NULL; owned */
    char *mime_type; /* "image/png" or "image/jpeg"; owned */
    size_t byte_count;
    unsigned char *bytes; /* [byte_count] owned */
} rf_image;

/* A morph target (blend shape): per-vertex displacements over the whole mesh, zero where a part
 * does not have it, added to the base mesh times the target's weight. */
typedef struct rf_morph_target {
    uint32_t size;
    char *name;       /* unique within the mesh; owned */
    float weight;     /* the weight at rest, usually 0 */
    float *positions; /* [vertex][3] displacement of the position, in the mesh's space */
    float *normals;   /* [vertex][3] displacement of the normal, or NULL */
} rf_morph_target;

/* A target of `vertex_count` zero displacements (no normals), or NULL when out of memory.
 * (transfer full: free with rf_morph_target_free) */
static inline rf_morph_target *rf_morph_target_new(const char *name, uint32_t vertex_count)
{
    rf_morph_target *t = (rf_morph_target *)calloc(1, sizeof *t);
    if (!t)
        return NULL;
    t->size = sizeof *t;
    t->positions = (float *)calloc(vertex_count ? (size_t)vertex_count * 3 : 3, sizeof(float));
    t->name = (char *)malloc(strlen(name) + 1);
    if (!t->positions || !t->name) {
        free(t->positions), free(t->name), free(t);
        return NULL;
    }
    strcpy(t->name, name);
    return t;
}

static inline void rf_morph_target_free(void *target)
{
    rf_morph_target *t = (rf_morph_target *)target;
    if (t) {
        free(t->name);
        free(t->positions);
        free(t->normals);
    }
    free(t);
}

static inline rf_texture_ref rf_texture_ref_none(void)
{
    rf_texture_ref t = {-1, 0, 1.0f, 0, 0, 0, 0};
    return t;
}

/* A material with glTF's defaults (white, metallic 1, roughness 1, opaque, cutoff 0.5, no
 * textures), or NULL when out of memory. (transfer full: free with rf_material_free) */
static inline rf_material *rf_material_new(void)
{
    rf_material *m = (rf_material *)calloc(1, sizeof *m);
    if (!m)
        return NULL;
    m->size = sizeof *m;
    for (int i = 0; i < 4; i++)
        m->base_color[i] = 1.0f;
    m->metallic = m->roughness = 1.0f;
    m->alpha_cutoff = 0.5f;
    m->base_color_texture = m->metallic_roughness_texture = rf_texture_ref_none();
    m->normal_texture = m->occlusion_texture = m->emissive_texture = rf_texture_ref_none();
    return m;
}

static inline void rf_material_free(void *material)
{
    rf_material *m = (rf_material *)material;
    if (m)
        free(m->name);
    free(m);
}

/* An image holding a copy of `bytes`, or NULL when out of memory. name may be NULL.
 * (transfer full: free with rf_image_free) */
static inline rf_image *rf_image_new(const char *name, const char *mime_type, const void *bytes,
                                     size_t byte_count)
{
    rf_image *im = (rf_image *)calloc(1, sizeof *im);
    if (!im)
        return NULL;
    im->size = sizeof *im;
    im->byte_count = byte_count;
    im->bytes = (unsigned char *)malloc(byte_count ? byte_count : 1);
    im->mime_type = (char *)malloc(strlen(mime_type) + 1);
    im->name = name ? (char *)malloc(strlen(name) + 1) : NULL;
    if (!im->bytes || !im->mime_type || (name && !im->name)) {
        free(im->bytes), free(im->mime_type), free(im->name), free(im);
        return NULL;
    }
    if (byte_count)
        memcpy(im->bytes, bytes, byte_count);
    strcpy(im->mime_type, mime_type);
    if (name)
        strcpy(im->name, name);
    return im;
}

static inline void rf_image_free(void *image)
{
    rf_image *im = (rf_image *)image;
    if (im) {
        free(im->name);
        free(im->mime_type);
        free(im->bytes);
    }
    free(im);
}

/* One source mesh inside a merged rf_mesh: a contiguous run of vertices and triangles. */
typedef struct rf_mesh_part {
    char *name; /* may be NULL; owned by the mesh */
    uint32_t first_vertex, vertex_count;
    uint32_t first_triangle, triangle_count;
} rf_mesh_part;

/* An empty mesh (no vertices, no arrays) with its size set, or NULL when out of memory.
 * (transfer full: free with rf_mesh_free) */
static inline rf_mesh *rf_mesh_new(void)
{
    rf_mesh *m = (rf_mesh *)calloc(1, sizeof *m);
    if (m)
        m->size = sizeof *m;
    return m;
}

/* The joint carrying the largest weight of skinned vertex v (the first of equals). */
static inline uint32_t rf_mesh_heaviest_joint(const rf_mesh *m, uint32_t v)
{
    const float *w = m->skin_weights + (size_t)v * RF_MESH_MAX_INFLUENCES;
    uint32_t best = 0;
    for (uint32_t i = 1; i < RF_MESH_MAX_INFLUENCES; i++)
        if (w[i] > w[best])
            best = i;
    return m->skin_joints[(size_t)v * RF_MESH_MAX_INFLUENCES + best];
}

/* The skinning matrices of a pose: for each of `n` joints its world transform times its inverse
 * bind (model space to the joint's space at bind time), into skin[n]. */
static inline void rf_skin_matrices(const rf_xform *world, const rf_mat4 *inverse_bind, uint32_t n,
                                    rf_mat4 *skin)
{
    for (uint32_t j = 0; j < n; j++)
        skin[j] = rf_mat4_mul(rf_xform_to_mat4(world[j]), inverse_bind[j]);
}

/* Vertex v of skinned mesh m posed by linear blend skinning: its bind position carried by the
 * skinning matrix (rf_skin_matrices) of each joint weighing on it, averaged by the weights over
 * their sum; its bind position when no weight is over 0. Every joint a vertex names must have a
 * matrix in `skin`: callers check skin_joints against the skeleton once, not here per vertex
 * (the mesh measures skin a mesh dozens of times a clip). */
static inline rf_vec3 rf_mesh_skin_vertex(const rf_mesh *m, const rf_mat4 *skin, uint32_t v)
{
    const float *p = m->positions + (size_t)v * 3;
    rf_vec3 bind = rf_v3(p[0], p[1], p[2]), sum = rf_v3(0, 0, 0);
    double wsum = 0;
    for (uint32_t i = 0; i < RF_MESH_MAX_INFLUENCES; i++) {
        size_t k = (size_t)v * RF_MESH_MAX_INFLUENCES + i;
        double w = m->skin_weights[k];
        if (!(w > 0))
            continue;
        sum = rf_v3_add(sum, rf_v3_scale(rf_mat4_point(skin[m->skin_joints[k]], bind), w));
        wsum += w;
    }
    return wsum > 0 ? rf_v3_scale(sum, 1.0 / wsum) : bind;
}

/* Frees a mesh and every array it holds. NULL is allowed. Usable as a set_output destroy. */
static inline void rf_mesh_free(void *mesh)
{
    rf_mesh *m = (rf_mesh *)mesh;
    if (!m)
        return;
    free(m->name);
    free(m->positions);
    free(m->normals);
    free(m->triangles);
    free(m->skin_joints);
    free(m->skin_weights);
    free(m->inverse_bind);
    if (RF_HAS_FIELD(m, rf_mesh, parts)) {
        for (uint32_t i = 0; i < m->part_count; i++)
            free(m->parts[i].name);
        free(m->parts);
    }
    if (RF_HAS_FIELD(m, rf_mesh, images)) {
        for (uint32_t i = 0; i < RF_MESH_MAX_UV_SETS; i++)
            free(m->uvs[i]);
        free(m->colors);
        free(m->tangents);
        free(m->part_material);
        for (uint32_t i = 0; m->materials && i < m->material_count; i++)
            rf_material_free(m->materials[i]);
        free(m->materials);
        for (uint32_t i = 0; m->images && i < m->image_count; i++)
            rf_image_free(m->images[i]);
        free(m->images);
    }
    if (RF_HAS_FIELD(m, rf_mesh, morph_targets)) {
        for (uint32_t i = 0; m->morph_targets && i < m->morph_target_count; i++)
            rf_morph_target_free(m->morph_targets[i]);
        free(m->morph_targets);
    }
    free(m);
}

/* ---- clip list ---- */

#define RF_TYPE_CLIPS "rigflow.clips"

/* One animation clip a file holds, whether or not it was the one imported. */
typedef struct rf_clip_info {
    char *name;      /* never NULL; owned by the list */
    double duration; /* seconds */
    double fps;      /* the rate the importer resamples the clip at */
    uint32_t frames; /* frames at that rate, both ends included */
} rf_clip_info;

/* The clips of a multi-clip file (glTF, FBX, .x, Ogre), so a user can pick one by name or index. */
typedef struct rf_clip_list {
    uint32_t size;
    uint32_t count;
    rf_clip_info *clips; /* [count], owned */
    int32_t selected;    /* index of the clip the importer output, or -1 */
    /* Appended in 1.2 (check with RF_HAS_FIELD before reading): */
    rf_animation **animations; /* [count] each clip's motion where it was imported (every clip
                                * when asked for all, clip "*"), NULL entries for the others; or
                                * NULL; owned */
} rf_clip_list;

/* A list of `count` clips with NULL names (the producer fills them in), or NULL when out of memory.
 * (transfer full: free with rf_clip_list_free) */
static inline rf_clip_list *rf_clip_list_new(uint32_t count)
{
    rf_clip_list *l = (rf_clip_list *)calloc(1, sizeof *l);
    if (!l)
        return NULL;
    l->size = sizeof *l;
    l->count = count;
    l->selected = -1;
    l->clips = (rf_clip_info *)calloc(count ? count : 1, sizeof *l->clips);
    if (!l->clips) {
        free(l);
        return NULL;
    }
    return l;
}

/* Frees a clip list and its names. NULL is allowed. Usable as a set_output destroy. */
static inline void rf_clip_list_free(void *list)
{
    rf_clip_list *l = (rf_clip_list *)list;
    if (!l)
        return;
    for (uint32_t i = 0; i < l->count; i++)
        free(l->clips[i].name);
    free(l->clips);
    if (RF_HAS_FIELD(l, rf_clip_list, animations) && l->animations) {
        for (uint32_t i = 0; i < l->count; i++)
            rf_animation_free(l->animations[i]);
        free(l->animations);
    }
    free(l);
}

/* ---- mapping ---- */

enum rf_map_flags {
    RF_MAP_REVERSE = 1u << 0, /* play the source joint's rotation reversed (inverse) */
    RF_MAP_MIRROR = 1u << 1,  /* opposite phase: sample the source half a cycle away, mirrored */
};

/* One source joint driving a target joint. */
typedef struct rf_map_input {
    uint32_t source; /* index of the source skeleton (order of the matcher's inputs) */
    uint32_t joint;  /* joint index in that source skeleton */
    float weight;    /* blend weight among a target joint's inputs, > 0 */
    float delay;     /* seconds: the source is sampled this much earlier */
    uint32_t flags;  /* rf_map_flags */
} rf_map_input;

/* What drives one target joint: zero inputs leaves it to the retargeter (unmapped). */
typedef struct rf_map_entry {
    uint32_t input_count;
    rf_map_input *inputs; /* owned by the mapping */
    double score;         /* the matcher's total score for the best input; 0 when unmapped */
    double *metrics;      /* [mapping->metric_count] per-metric breakdown, or NULL */
} rf_map_entry;

typedef struct rf_mapping {
    uint32_t size;
    uint32_t source_count;
    uint32_t target_joint_count;
    rf_map_entry *entries; /* one per target joint, in the target skeleton's order */
    uint32_t metric_count;
    char **metric_names; /* [metric_count], owned */
    /* Appended in 1.1 (check with RF_HAS_FIELD before reading): */
    char **sections; /* [target_joint_count] where the matcher placed each target joint: a section
                      * type ("spine", "head", "tail", "arm", "hand", "leg", "foot", "appendage",
                      * "root", "helper"; doc/matching.md), NULL entries allowed; or NULL; owned */
    char **sides;    /* [target_joint_count] "left", "right" or "center", same rules; owned */
} rf_mapping;

/* A mapping with every target joint unmapped, or NULL when out of memory.
 * (transfer full: free with rf_mapping_free) */
static inline rf_mapping *rf_mapping_new(uint32_t target_joint_count, uint32_t source_count)
{
    rf_mapping *m = (rf_mapping *)calloc(1, sizeof *m);
    if (!m)
        return NULL;
    m->size = sizeof *m;
    m->source_count = source_count;
    m->target_joint_count = target_joint_count;
    m->entries =
        (rf_map_entry *)calloc(target_joint_count ? target_joint_count : 1, sizeof *m->entries);
    if (!m->entries) {
        free(m);
        return NULL;
    }
    return m;
}

/* Frees a mapping, its entries, inputs, metrics and names. NULL is allowed. */
static inline void rf_mapping_free(void *mapping)
{
    rf_mapping *m = (rf_mapping *)mapping;
    if (!m)
        return;
    for (uint32_t i = 0; i < m->target_joint_count; i++) {
        free(m->entries[i].inputs);
        free(m->entries[i].metrics);
    }
    for (uint32_t i = 0; i < m->metric_count; i++)
        free(m->metric_names[i]);
    free(m->metric_names);
    if (RF_HAS_FIELD(m, rf_mapping, sides)) {
        for (uint32_t i = 0; m->sections && i < m->target_joint_count; i++)
            free(m->sections[i]);
        for (uint32_t i = 0; m->sides && i < m->target_joint_count; i++)
            free(m->sides[i]);
        free(m->sections);
        free(m->sides);
    }
    free(m->entries);
    free(m);
}

/* ---- growth ---- */

/* The 1.0 layout of each struct (1.1 for the clip list, which 1.1 added), the smallest a consumer
 * may be handed. The host gives a consumer nothing smaller than its own build's structs: a value
 * an older plugin produced reaches it as a copy whose appended fields are zero. Array elements
 * without a size (rf_joint, rf_map_input, rf_map_entry, rf_clip_info, rf_mesh_part) never grow:
 * what they would gain goes into a new array appended to the struct that holds them. */
#define RF_SKELETON_SIZE_1_0 RF_SIZE_THROUGH(rf_skeleton, forward)
#define RF_ANIMATION_SIZE_1_0 RF_SIZE_THROUGH(rf_animation, channels)
#define RF_MESH_SIZE_1_0 RF_SIZE_THROUGH(rf_mesh, inverse_bind)
#define RF_MAPPING_SIZE_1_0 RF_SIZE_THROUGH(rf_mapping, metric_names)
#define RF_CLIP_LIST_SIZE_1_1 RF_SIZE_THROUGH(rf_clip_list, selected)

#ifdef __cplusplus
}
#endif

#endif
