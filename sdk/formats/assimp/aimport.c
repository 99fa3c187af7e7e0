/* Assimp import: scene loading, joint selection, skeleton, rest poses and axes.
 *
 * Joint selection (doc/formats.md): the skin bones, their ancestors up to the lowest common
 * ancestor of all bones (the skeleton root R), R's ancestors as long as they are animated (their
 * motion would be lost otherwise), and the animated helper nodes below R (IK targets, poles,
 * controls: kept, flagged unweighted). Everything above R is static and is baked into the root
 * joint's rest transform, so world positions are those of the scene. Files without skin fall back
 * to the animated nodes, then to the tree of transform-only nodes (a node tree with meshes hung on
 * it, as in a VRM humanoid).
 */
#include <ctype.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <assimp/cfileio.h>
#include <assimp/cimport.h>
#include <assimp/config.h>
#include <assimp/metadata.h>
#include <assimp/postprocess.h>

#include "rigflow/memory.h"
#include "rigflow/model-copy.h"
#include "aimport-internal.h"
#include "aimport-io.h"

bool rf_ai_fail(rf_ai_ctx *c, const char *fmt, ...)
{
    if (!c->err || !c->err_size)
        return false;
    int n = snprintf(c->err, c->err_size, "%s: ", c->path);
    if (n < 0 || (size_t)n >= c->err_size)
        return false;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(c->err + n, c->err_size - (size_t)n, fmt, ap);
    va_end(ap);
    return false;
}

/* Assimp reports running out of memory as its C++ exception's text; a second try would only run
 * out again. Says so with the file's size and the memory there was, and returns true. */
static bool rf_ai_out_of_memory(rf_ai_ctx *c, const char *why)
{
    if (!strstr(why, "bad_alloc"))
        return false;
    struct stat st;
    uint64_t left = 0;
    double mb = stat(c->path, &st) == 0 ? (double)st.st_size / 1e6 : 0;
    if (rf_memory_available(&left))
        return !rf_ai_fail(c,
                           "out of memory reading it (%.0f MB, with %.1f GB of memory left to "
                           "the process): a smaller or simplified file is needed",
                           mb, (double)left / 1e9);
    return !rf_ai_fail(
        c, "out of memory reading it (%.0f MB): a smaller or simplified file is needed", mb);
}

void rf_ai_logf(rf_ai_ctx *c, int level, const char *fmt, ...)
{
    if (!c->log)
        return;
    char buf[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    c->log(c->user, level, buf);
}

rf_mat4 rf_ai_mat4(const struct aiMatrix4x4 *m)
{
    /* Assimp stores rows (a1..a4 is the first row, translation in a4, b4, c4); ours is
     * column-major. */
    rf_mat4 r = {{m->a1, m->b1, m->c1, m->d1, m->a2, m->b2, m->c2, m->d2, m->a3, m->b3, m->c3,
                  m->d3, m->a4, m->b4, m->c4, m->d4}};
    return r;
}

/* One node in the name index: sorted by name, then meshless first, then file order, so the first
 * entry of a name is the node rf_ai_find_node wants. */
typedef struct rf_ai_name_ref {
    const char *name;
    int meshy;
    int node;
} rf_ai_name_ref;

static int rf_ai_name_ref_cmp(const void *pa, const void *pb)
{
    const rf_ai_name_ref *a = pa, *b = pb;
    int d = strcmp(a->name, b->name);
    if (d)
        return d;
    if (a->meshy != b->meshy)
        return a->meshy - b->meshy;
    return (a->node > b->node) - (a->node < b->node);
}

/* Sorts the nodes by name once: a linear search per bone or channel would be quadratic. */
static bool rf_ai_index_names(rf_ai_ctx *c)
{
    c->by_name = calloc(c->node_count ? c->node_count : 1, sizeof *c->by_name);
    if (!c->by_name)
        return false;
    for (unsigned i = 0; i < c->node_count; i++)
        c->by_name[i] =
            (rf_ai_name_ref){c->nodes[i]->mName.data, c->nodes[i]->mNumMeshes != 0, (int)i};
    qsort(c->by_name, c->node_count, sizeof *c->by_name, rf_ai_name_ref_cmp);
    return true;
}

int rf_ai_find_node(const rf_ai_ctx *c, const char *name)
{
    /* Bones and channels name their node; names need not be unique (glTF mesh nodes often share
     * a joint's name), and a bone is a transform, so a node without meshes wins. */
    size_t lo = 0, hi = c->node_count;
    while (lo < hi) { /* the first entry not below name */
        size_t mid = lo + (hi - lo) / 2;
        if (strcmp(c->by_name[mid].name, name) < 0)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < c->node_count && strcmp(c->by_name[lo].name, name) == 0 ? c->by_name[lo].node : -1;
}

int rf_ai_joint_above(const rf_ai_ctx *c, int n)
{
    for (; n >= 0; n = c->node_parent[n])
        if (c->joint_of[n] >= 0)
            return c->joint_of[n];
    return -1;
}

rf_mat4 rf_ai_joint_node_local(const rf_ai_ctx *c, unsigned j)
{
    int n = c->joint_node[j];
    int p = c->node_parent[n];
    if (p >= 0 && c->joint_of[p] >= 0)
        return rf_ai_mat4(&c->nodes[n]->mTransformation);
    return c->node_global[n];
}

/* ---- loading ---- */

/* A GLB states its own length in its header; one that disagrees with the file (a truncated or
 * corrupt download) is refused with both lengths, as the glTF validator does, before Assimp
 * reads whatever part of it is there. True for every file that is not a GLB. */
static bool rf_ai_glb_length_ok(rf_ai_ctx *c)
{
    int fd = open(c->path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0)
        return true; /* the import says why it cannot read it */
    unsigned char h[12];
    struct stat st;
    bool glb = fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && read(fd, h, sizeof h) == 12 &&
               memcmp(h, "glTF", 4) == 0;
    close(fd);
    if (!glb)
        return true;
    uint32_t declared =
        (uint32_t)h[8] | (uint32_t)h[9] << 8 | (uint32_t)h[10] << 16 | (uint32_t)h[11] << 24;
    if ((long long)declared == (long long)st.st_size)
        return true;
    return rf_ai_fail(c,
                      "the GLB header declares a length of %u bytes but the file has %lld: "
                      "truncated or corrupt",
                      declared, (long long)st.st_size);
}

/* Assimp keeps the last import's error in one global string: imports on threads of their own
 * (nodes processing at once) take turns, so the message read is the failed import's own. */
static pthread_mutex_t rf_ai_import_lock = PTHREAD_MUTEX_INITIALIZER;

static const struct aiScene *rf_ai_import_locked(rf_ai_ctx *c, unsigned flags, struct aiFileIO *io,
                                                 const struct aiPropertyStore *props, char *error,
                                                 size_t error_size)
{
    pthread_mutex_lock(&rf_ai_import_lock);
    const struct aiScene *s = aiImportFileExWithProperties(c->path, flags, io, props);
    if (!s)
        snprintf(error, error_size, "%s", aiGetErrorString());
    pthread_mutex_unlock(&rf_ai_import_lock);
    return s;
}

static const struct aiScene *rf_ai_load(rf_ai_ctx *c)
{
    if (!rf_ai_glb_length_ok(c))
        return NULL;
    /* Assimp reads only the model and files in its folder (aimport-io.c). */
    rf_ai_confine *cf = &c->confine;
    struct aiFileIO *io = &c->io;
    if (!rf_ai_confine_init(cf, c->path, io)) {
        rf_ai_fail(c, "cannot resolve the model's folder: %s", strerror(errno));
        return NULL;
    }
    struct aiPropertyStore *props = aiCreatePropertyStore();
    /* FBX pivots would otherwise appear as extra "$AssimpFbx$" nodes between real joints. */
    aiSetImportPropertyInteger(props, AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS, 0);
    unsigned flags = aiProcess_Triangulate | aiProcess_SortByPType;
    char first[512], second[8];
    const struct aiScene *s = rf_ai_import_locked(c, flags | aiProcess_ValidateDataStructure, io,
                                                  props, first, sizeof first);
    if (!s) {
        /* Some files (every B3D creature here) fail validation only for keys past the clip's end;
         * import without the step and clamp the keys while resampling. */
        bool oom = rf_ai_out_of_memory(c, first);
        if (!oom)
            s = rf_ai_import_locked(c, flags, io, props, second, sizeof second);
        if (s)
            rf_ai_logf(c, 1,
                       "%s: Assimp's validation failed (%s); imported without it, keys outside a "
                       "clip are clamped",
                       c->path, first);
        else if (!oom)
            rf_ai_fail(c, "Assimp cannot read it: %s%s%s", first, cf->refused[0] ? "; " : "",
                       cf->refused);
    }
    if (s && cf->refused[0])
        rf_ai_logf(c, 1, "%s: %s (%u reads refused)", c->path, cf->refused, cf->refused_count);
    aiReleasePropertyStore(props);
    /* the confinement stays for the textures (aimport-look.c); rf_ai_ctx_free clears it */
    cf->refused[0] = '\0', cf->refused_count = 0;
    return s;
}

/* ---- the node table ---- */

static void rf_ai_count_nodes(const struct aiNode *n, unsigned *count)
{
    (*count)++;
    for (unsigned i = 0; i < n->mNumChildren; i++)
        rf_ai_count_nodes(n->mChildren[i], count);
}

static void rf_ai_flatten(rf_ai_ctx *c, const struct aiNode *n, int parent)
{
    int self = (int)c->node_count++;
    c->nodes[self] = n;
    c->node_parent[self] = parent;
    rf_mat4 local = rf_ai_mat4(&n->mTransformation);
    c->node_global[self] = parent < 0 ? local : rf_mat4_mul(c->node_global[parent], local);
    for (unsigned i = 0; i < n->mNumChildren; i++)
        rf_ai_flatten(c, n->mChildren[i], self);
}

static double rf_ai_mat_diff(rf_mat4 a, rf_mat4 b)
{
    double d = 0, scale = 1;
    for (int i = 0; i < 16; i++) {
        d = fmax(d, fabs(a.m[i] - b.m[i]));
        scale = fmax(scale, fabs(a.m[i]));
    }
    return d / scale;
}

static rf_mat4 rf_ai_mesh_node_global(const rf_ai_ctx *c, unsigned mesh)
{
    for (unsigned i = 0; i < c->node_count; i++)
        for (unsigned k = 0; k < c->nodes[i]->mNumMeshes; k++)
            if (c->nodes[i]->mMeshes[k] == mesh)
                return c->node_global[i];
    return rf_mat4_identity();
}

/* How many of the mesh's bones put their bind pose at their node pose through `space`. */
static unsigned rf_ai_space_votes(const rf_mat4 *cand, unsigned n, rf_mat4 space)
{
    unsigned votes = 0;
    for (unsigned i = 0; i < n; i++)
        votes += rf_ai_mat_diff(cand[i], space) < 1e-3;
    return votes;
}

#define RF_AI_VOTE_ALL_MAX 4096u

/* The candidate agreeing with more than half of the others, if any is. */
static unsigned rf_ai_space_majority(const rf_mat4 *cand, unsigned n)
{
    unsigned m = 0, count = 0;
    for (unsigned i = 0; i < n; i++) {
        if (count == 0)
            m = i, count = 1;
        else if (rf_ai_mat_diff(cand[i], cand[m]) < 1e-3)
            count++;
        else
            count--;
    }
    return m;
}

/* Model space. Assimp skins as world = joint global * offset * vertex, and where the offsets
 * lead depends on the format: glTF's inverse binds and .x offsets are relative to the model,
 * FBX folds the mesh node's transform in, some glTF files bind relative to the mesh node. A bone
 * whose node rest equals its bind pose tells the mesh space G exactly: G = node global * offset.
 * The identity or the mesh node's global transform, whichever more bones agree with (the
 * identity on a tie), unless a majority of the bones agree on another space. Files whose node
 * rest differs from the bind pose for most bones (girl) thus keep the identity rather than a
 * space a few bones agree on by chance. Vertices become G * v and inverse binds offset * G^-1:
 * that skins identically, puts the bind pose in the scene's space beside the animation, and
 * brings meshes bound in different spaces (BCN_Epileptic's three) together. */
static rf_mat4 rf_ai_mesh_space(rf_ai_ctx *c, unsigned m)
{
    const struct aiMesh *mesh = c->scene->mMeshes[m];
    rf_mat4 *cand = calloc(mesh->mNumBones + 2, sizeof *cand), best = rf_mat4_identity();
    if (!cand)
        return best;
    unsigned n = 0;
    for (unsigned b = 0; b < mesh->mNumBones; b++) {
        int node = rf_ai_find_node(c, mesh->mBones[b]->mName.data);
        if (node >= 0)
            cand[n++] =
                rf_mat4_mul(c->node_global[node], rf_ai_mat4(&mesh->mBones[b]->mOffsetMatrix));
    }
    unsigned best_votes = rf_ai_space_votes(cand, n, best);
    rf_mat4 mg = rf_ai_mesh_node_global(c, m), inv;
    unsigned v = rf_ai_space_votes(cand, n, mg);
    if (v > best_votes)
        best = mg, best_votes = v;
    /* Every bone's candidate against every other is quadratic: beyond a real rig's bone count,
     * only the majority element (Boyer-Moore vote) can be the one wanted. */
    unsigned lo = 0, hi = n;
    if (n > RF_AI_VOTE_ALL_MAX)
        lo = rf_ai_space_majority(cand, n), hi = lo + 1;
    for (unsigned i = lo; i < hi && i < n; i++)
        if ((v = rf_ai_space_votes(cand, n, cand[i])) > best_votes && v * 2 > n &&
            rf_mat4_invert(cand[i], &inv))
            best = cand[i], best_votes = v;
    free(cand);
    return best;
}

static void rf_ai_mesh_spaces(rf_ai_ctx *c)
{
    for (unsigned m = 0; m < c->scene->mNumMeshes; m++)
        c->mesh_space[m] =
            c->scene->mMeshes[m]->mNumBones ? rf_ai_mesh_space(c, m) : rf_mat4_identity();
}

static void rf_ai_mark_bones(rf_ai_ctx *c)
{
    const struct aiScene *s = c->scene;
    rf_ai_mesh_spaces(c);
    for (unsigned m = 0; m < s->mNumMeshes; m++) {
        const struct aiMesh *mesh = s->mMeshes[m];
        rf_mat4 space_inv = rf_mat4_identity();
        rf_mat4_invert(c->mesh_space[m], &space_inv);
        for (unsigned b = 0; b < mesh->mNumBones; b++) {
            const struct aiBone *bone = mesh->mBones[b];
            int n = rf_ai_find_node(c, bone->mName.data);
            if (n < 0) {
                rf_ai_logf(c, 1, "%s: bone '%s' of mesh '%s' names no node; ignored", c->path,
                           bone->mName.data, mesh->mName.data);
                continue;
            }
            if (!c->bone_of[n]) {
                c->bone_of[n] = bone;
                c->bone_offset[n] = rf_mat4_mul(rf_ai_mat4(&bone->mOffsetMatrix), space_inv);
            }
            for (unsigned w = 0; w < bone->mNumWeights; w++)
                if (isfinite(bone->mWeights[w].mWeight) && bone->mWeights[w].mWeight > 0)
                    c->weight_sum[n] += bone->mWeights[w].mWeight;
        }
    }
    for (unsigned a = 0; a < s->mNumAnimations; a++) {
        const struct aiAnimation *anim = s->mAnimations[a];
        for (unsigned ch = 0; ch < anim->mNumChannels; ch++) {
            int n = rf_ai_find_node(c, anim->mChannels[ch]->mNodeName.data);
            if (n >= 0)
                c->animated[n] = 1;
        }
    }
}

static bool rf_ai_build_table(rf_ai_ctx *c)
{
    unsigned count = 0;
    rf_ai_count_nodes(c->scene->mRootNode, &count);
    c->nodes = calloc(count, sizeof *c->nodes);
    c->node_parent = calloc(count, sizeof *c->node_parent);
    c->node_global = calloc(count, sizeof *c->node_global);
    c->bone_of = calloc(count, sizeof *c->bone_of);
    c->bone_offset = calloc(count, sizeof *c->bone_offset);
    c->weight_sum = calloc(count, sizeof *c->weight_sum);
    c->animated = calloc(count, sizeof *c->animated);
    c->joint_of = calloc(count, sizeof *c->joint_of);
    c->joint_node = calloc(count, sizeof *c->joint_node);
    c->bind_global = calloc(count, sizeof *c->bind_global);
    c->mesh_space = calloc(c->scene->mNumMeshes + 1, sizeof *c->mesh_space);
    if (!c->mesh_space || !c->nodes || !c->node_parent || !c->node_global || !c->bone_of ||
        !c->bone_offset || !c->weight_sum || !c->animated || !c->joint_of || !c->joint_node ||
        !c->bind_global)
        return rf_ai_fail(c, "out of memory for %u nodes", count);
    rf_ai_flatten(c, c->scene->mRootNode, -1);
    for (unsigned i = 0; i < count; i++)
        c->joint_of[i] = -1;
    if (!rf_ai_index_names(c))
        return rf_ai_fail(c, "out of memory for %u nodes", count);
    rf_ai_mark_bones(c);
    return true;
}

static void rf_ai_ctx_free(rf_ai_ctx *c)
{
    free(c->nodes);
    free(c->node_parent);
    free(c->node_global);
    free(c->bone_of);
    free(c->bone_offset);
    free(c->weight_sum);
    free(c->animated);
    free(c->joint_of);
    free(c->joint_node);
    free(c->bind_global);
    free(c->mesh_space);
    free(c->by_name);
    rf_ai_confine_clear(&c->confine);
    if (c->scene)
        aiReleaseImport(c->scene);
}

/* ---- joint selection ---- */

static bool rf_ai_is_camera_or_light(const rf_ai_ctx *c, const struct aiNode *n)
{
    const struct aiScene *s = c->scene;
    for (unsigned i = 0; i < s->mNumCameras; i++)
        if (strcmp(s->mCameras[i]->mName.data, n->mName.data) == 0)
            return true;
    for (unsigned i = 0; i < s->mNumLights; i++)
        if (strcmp(s->mLights[i]->mName.data, n->mName.data) == 0)
            return true;
    return false;
}

/* The lowest common ancestor of the seeds: the last node in pre-order whose subtree holds every
 * seed (one pass; an LCA walk per seed would be quadratic on a deep chain). */
static int rf_ai_seeds_root(const rf_ai_ctx *c, const uint8_t *seed)
{
    unsigned *below = calloc(c->node_count ? c->node_count : 1, sizeof *below), total = 0;
    if (!below)
        return 0;
    for (unsigned i = c->node_count; i-- > 0;) {
        below[i] += seed[i];
        total += seed[i];
        if (c->node_parent[i] >= 0)
            below[c->node_parent[i]] += below[i];
    }
    int root = 0;
    for (unsigned i = 0; i < c->node_count; i++)
        if (below[i] == total)
            root = (int)i;
    free(below);
    return root;
}

static bool rf_ai_any_bone(const rf_ai_ctx *c)
{
    for (unsigned i = 0; i < c->node_count; i++)
        if (c->bone_of[i])
            return true;
    return false;
}

/* Seeds are the nodes that must be joints; which kind depends on what the file has. */
static int rf_ai_pick_seeds(const rf_ai_ctx *c, uint8_t *seed, const char **why)
{
    int count = 0;
    /* Bones, and animated transform nodes: helpers such as IK targets often sit beside the
     * armature rather than below it, and their motion belongs to the rig. */
    for (unsigned i = 0; i < c->node_count; i++)
        if (c->bone_of[i] || (c->animated[i] && c->nodes[i]->mNumMeshes == 0))
            seed[i] = 1, count++;
    *why = "skin bones and animated nodes";
    if (rf_ai_any_bone(c))
        return count;
    /* No skin: the tree of transform-only nodes is the skeleton (a node-animated rig, a glTF
     * written from a BVH, a VRM node tree). Only a real hierarchy counts, so a scene of rigid
     * parts under a bare root (no skeleton) yields nothing. */
    *why = count ? "animated and transform-only nodes (no skin)"
                 : "transform-only nodes (no skin, no animation)";
    for (unsigned i = 1; i < c->node_count; i++) {
        const struct aiNode *n = c->nodes[i];
        int p = c->node_parent[(int)i];
        bool parent_empty = c->nodes[p]->mNumMeshes == 0;
        if (n->mNumMeshes == 0 && parent_empty && !rf_ai_is_camera_or_light(c, n) && !seed[i])
            seed[i] = 1, count++;
    }
    if (count && c->nodes[0]->mNumMeshes == 0)
        seed[0] = 1, count++;
    return count >= 2 ? count : 0;
}

static void rf_ai_mark_up_to(const rf_ai_ctx *c, uint8_t *sel, int n, int root)
{
    /* A node already marked has its path to the root marked: stop there (linear overall). */
    for (; n >= 0 && !sel[n]; n = c->node_parent[n]) {
        sel[n] = 1;
        if (n == root)
            break;
    }
}

/* Fills c->joint_of / joint_node / joint_count. */
static void rf_ai_select_joints(rf_ai_ctx *c)
{
    uint8_t *seed = calloc(c->node_count, 1), *sel = calloc(c->node_count, 1);
    const char *why = "";
    if (!seed || !sel || !rf_ai_pick_seeds(c, seed, &why)) {
        free(seed), free(sel);
        return;
    }
    int root = rf_ai_seeds_root(c, seed);
    while (c->node_parent[root] >= 0 && c->animated[c->node_parent[root]])
        root = c->node_parent[root];
    for (unsigned i = 0; i < c->node_count; i++)
        if (seed[i])
            rf_ai_mark_up_to(c, sel, (int)i, root);
    for (unsigned i = 0; i < c->node_count; i++)
        if (sel[i]) { /* pre-order keeps parents before children */
            c->joint_of[i] = (int)c->joint_count;
            c->joint_node[c->joint_count++] = (int)i;
        }
    rf_ai_logf(c, 2, "%s: %u joints from %s, skeleton root '%s'", c->path, c->joint_count, why,
               c->nodes[root]->mName.data);
    free(seed), free(sel);
}

/* ---- skeleton ---- */

/* The joint names given so far, with the next suffix to try for each: open addressing over a
 * power-of-two table at most half full, so that uniqueness costs constant time per joint (a
 * search of the skeleton per joint, and per suffix, would be quadratic). */
typedef struct rf_ai_name_slot {
    const char *name; /* borrowed from the skeleton */
    unsigned next;    /* the suffix to try next when this name comes again */
} rf_ai_name_slot;

static rf_ai_name_slot *rf_ai_name_slot_of(rf_ai_name_slot *t, size_t mask, const char *name)
{
    uint64_t h = 1469598103934665603u; /* FNV-1a */
    for (const unsigned char *p = (const unsigned char *)name; *p; p++)
        h = (h ^ *p) * 1099511628211u;
    size_t i = (size_t)h & mask;
    while (t[i].name && strcmp(t[i].name, name) != 0)
        i = (i + 1) & mask;
    return &t[i];
}

/* Joint names must be unique: empty names become "joint<i>", a repeated name gets ".1", ".2"...
 * in joint order (the first keeps its name), with a warning naming each change. */
static bool rf_ai_name_joints(rf_ai_ctx *c, rf_skeleton *s)
{
    size_t cap = 16;
    while (cap < (size_t)s->joint_count * 2)
        cap *= 2;
    rf_ai_name_slot *table = calloc(cap, sizeof *table);
    if (!table)
        return rf_ai_fail(c, "out of memory");
    for (unsigned j = 0; j < s->joint_count; j++) {
        const char *src = c->nodes[c->joint_node[j]]->mName.data;
        char buf[1100];
        if (!src[0])
            snprintf(buf, sizeof buf, "joint%u", j);
        else
            snprintf(buf, sizeof buf, "%s", src);
        size_t base = strlen(buf);
        rf_ai_name_slot *first = rf_ai_name_slot_of(table, cap - 1, buf), *slot = first;
        for (unsigned k = first->name ? first->next : 0; slot->name; k++) {
            snprintf(buf + base, sizeof buf - base, ".%u", k + 1);
            first->next = k + 1;
            slot = rf_ai_name_slot_of(table, cap - 1, buf);
        }
        if (strcmp(buf, src) != 0 && src[0])
            rf_ai_logf(c, 1, "%s: duplicate joint name '%s' renamed '%s'", c->path, src, buf);
        s->joints[j].name = rf_strdup(buf);
        if (!s->joints[j].name) {
            free(table);
            return rf_ai_fail(c, "out of memory");
        }
        slot->name = s->joints[j].name;
    }
    free(table);
    return true;
}

static rf_xform rf_ai_to_xform(rf_ai_ctx *c, rf_mat4 m, unsigned j, const char *what)
{
    rf_xform x;
    if (rf_mat4_to_xform(m, &x))
        return x;
    rf_ai_logf(c, 1, "%s: joint %u: singular %s transform replaced by the identity", c->path, j,
               what);
    return rf_xform_identity();
}

/* World bind pose: the inverse of the bone's offset where the joint is a bone, else the parent's
 * bind times the node's transform (helpers and containers move rigidly with their parent). */
static void rf_ai_bind_pose(rf_ai_ctx *c, rf_skeleton *s, bool *has_bind)
{
    *has_bind = false;
    for (unsigned j = 0; j < c->joint_count; j++) {
        int n = c->joint_node[j];
        rf_mat4 inv;
        if (c->bone_of[n] && rf_mat4_invert(c->bone_offset[n], &inv)) {
            c->bind_global[j] = inv;
            *has_bind = true;
        } else {
            int p = s->joints[j].parent;
            rf_mat4 local = rf_ai_joint_node_local(c, j);
            c->bind_global[j] = p < 0 ? local : rf_mat4_mul(c->bind_global[p], local);
        }
    }
}

static bool rf_ai_fill_poses(rf_ai_ctx *c, rf_skeleton *s, rf_ai_rest rest)
{
    bool has_bind;
    rf_ai_bind_pose(c, s, &has_bind);
    if (has_bind) {
        s->bind = calloc(s->joint_count ? s->joint_count : 1, sizeof *s->bind);
        if (!s->bind)
            return rf_ai_fail(c, "out of memory");
    }
    for (unsigned j = 0; j < s->joint_count; j++) {
        int p = s->joints[j].parent;
        rf_xform node = rf_ai_to_xform(c, rf_ai_joint_node_local(c, j), j, "node");
        rf_mat4 local = c->bind_global[j], pinv;
        if (p >= 0 && rf_mat4_invert(c->bind_global[p], &pinv))
            local = rf_mat4_mul(pinv, c->bind_global[j]);
        if (s->bind)
            s->bind[j] = rf_ai_to_xform(c, local, j, "bind");
        s->joints[j].rest = (rest == RF_AI_REST_BIND && s->bind) ? s->bind[j] : node;
    }
    s->rest_source = (rest == RF_AI_REST_BIND && s->bind) ? RF_REST_BIND : RF_REST_NODE;
    if (rest == RF_AI_REST_BIND && !s->bind && s->joint_count)
        rf_ai_logf(c, 2, "%s: no skin, so no bind pose: the rest pose is the nodes' own", c->path);
    return true;
}

static bool rf_ai_build_skeleton(rf_ai_ctx *c, const rf_ai_options *o, rf_skeleton **out)
{
    rf_skeleton *s = rf_skeleton_new(c->joint_count);
    if (!s)
        return rf_ai_fail(c, "out of memory");
    for (unsigned j = 0; j < c->joint_count; j++) {
        int p = c->node_parent[c->joint_node[j]];
        s->joints[j].parent = p >= 0 ? c->joint_of[p] : -1;
    }
    const char *slash = strrchr(c->path, '/');
    s->name = rf_strdup(slash ? slash + 1 : c->path);
    if (!s->name) {
        rf_skeleton_free(s);
        return rf_ai_fail(c, "out of memory");
    }
    if (!rf_ai_name_joints(c, s) || !rf_ai_fill_poses(c, s, o->rest)) {
        rf_skeleton_free(s);
        return false;
    }
    *out = s;
    return true;
}

/* ---- axes ---- */

static bool rf_ai_meta_int(const struct aiMetadata *md, const char *key, int *v)
{
    if (!md)
        return false;
    for (unsigned i = 0; i < md->mNumProperties; i++) {
        if (strcmp(md->mKeys[i].data, key) != 0)
            continue;
        if (md->mValues[i].mType == AI_INT32) {
            *v = *(const int32_t *)md->mValues[i].mData;
            return true;
        }
        if (md->mValues[i].mType == AI_UINT64) {
            *v = (int)*(const uint64_t *)md->mValues[i].mData;
            return true;
        }
    }
    return false;
}

static rf_vec3 rf_ai_axis(int axis, int sign)
{
    rf_vec3 v = rf_v3(0, 0, 0);
    double k = sign < 0 ? -1.0 : 1.0;
    if (axis == 0)
        v.x = k;
    else if (axis == 1)
        v.y = k;
    else if (axis == 2)
        v.z = k;
    return v;
}

static bool rf_ai_has_ext(const char *path, const char *ext)
{
    size_t n = strlen(path), e = strlen(ext);
    if (n < e)
        return false;
    for (size_t i = 0; i < e; i++)
        if (tolower((unsigned char)path[n - e + i]) != ext[i])
            return false;
    return true;
}

/* Formats that declare no axes and have no convention for them. */
static bool rf_ai_no_axes(const char *path)
{
    static const char *const exts[] = {".obj", ".stl", ".ply", ".off"};
    for (size_t i = 0; i < sizeof exts / sizeof *exts; i++)
        if (rf_ai_has_ext(path, exts[i]))
            return true;
    return false;
}

static void rf_ai_axes(rf_ai_ctx *c, rf_skeleton *s)
{
    const struct aiMetadata *md = c->scene->mMetaData;
    int up = 1, up_sign = 1, front = 2, front_sign = 1;
    if (rf_ai_has_ext(c->path, ".gltf") || rf_ai_has_ext(c->path, ".glb")) {
        /* glTF 2.0 fixes the convention: +Y up, the front of an asset faces +Z. */
        s->up = rf_v3(0, 1, 0), s->forward = rf_v3(0, 0, 1);
        return;
    }
    if (rf_ai_meta_int(md, "UpAxis", &up) && rf_ai_meta_int(md, "FrontAxis", &front)) {
        /* FBX declares its axes in GlobalSettings; Assimp leaves the data in them. */
        rf_ai_meta_int(md, "UpAxisSign", &up_sign);
        rf_ai_meta_int(md, "FrontAxisSign", &front_sign);
        s->up = rf_ai_axis(up, up_sign), s->forward = rf_ai_axis(front, front_sign);
        return;
    }
    if (rf_ai_no_axes(c->path)) {
        /* OBJ, STL, PLY and OFF have no axes at all: a scan or a CAD part is as often saved
         * Z-up as Y-up. Up is left unknown (zero, as rf_skeleton says) rather than read as
         * Assimp's +Y: a rigger then finds it from the body, and every other user takes +Y
         * as before (doc/formats.md, "Axes"). */
        s->up = rf_v3(0, 0, 0), s->forward = rf_v3(0, 0, 0);
        rf_ai_logf(c, 2, "%s: up and facing not declared by the format (+Y assumed unless found)",
                   c->path);
        return;
    }
    /* Every other Assimp importer hands over Y-up, right-handed data (.x and B3D are converted
     * from left-handed by Assimp itself). Their formats declare no facing: report it unknown
     * rather than guess (doc/formats.md). */
    s->up = rf_v3(0, 1, 0);
    s->forward = rf_v3(0, 0, 0);
    rf_ai_logf(c, 2, "%s: up +Y (Assimp's convention), facing not declared by the format", c->path);
}

/* ---- flags and the entry point ---- */

static void rf_ai_flag_unweighted(rf_skeleton *s, const rf_mesh *m)
{
    if (!m || !m->skin_weights)
        return;
    uint8_t *used = calloc(s->joint_count ? s->joint_count : 1, 1);
    if (!used)
        return;
    for (size_t i = 0; i < (size_t)m->vertex_count * 4; i++)
        if (m->skin_weights[i] > 0 && m->skin_joints[i] < s->joint_count)
            used[m->skin_joints[i]] = 1;
    for (unsigned j = 0; j < s->joint_count; j++)
        if (!used[j])
            s->joints[j].flags |= RF_JOINT_UNWEIGHTED;
    free(used);
}

bool rf_ai_rest_parse(const char *text, rf_ai_rest *rest)
{
    if (!text || !*text || strcmp(text, "bind") == 0)
        *rest = RF_AI_REST_BIND;
    else if (strcmp(text, "node") == 0)
        *rest = RF_AI_REST_NODE;
    else
        return false;
    return true;
}

/* The mesh alone: placed as the rig bound it (so a rigged file's artist rig fits it), with its
 * skin dropped, an empty skeleton and one empty rest frame. */
static bool rf_ai_run_bare(rf_ai_ctx *c, const rf_ai_options *o, rf_ai_result *r)
{
    /* the skeleton is built and dropped: building it works out the bind pose the mesh uses */
    rf_skeleton *rig = NULL;
    bool ok = rf_ai_build_skeleton(c, o, &rig) && rf_ai_build_mesh(c, &r->mesh);
    rf_skeleton_free(rig);
    if (!ok)
        return false;
    if (r->mesh) {
        free(r->mesh->skin_joints), r->mesh->skin_joints = NULL;
        free(r->mesh->skin_weights), r->mesh->skin_weights = NULL;
        free(r->mesh->inverse_bind), r->mesh->inverse_bind = NULL;
        r->mesh->bind_count = 0;
    }
    if (!(r->skeleton = rf_skeleton_new(0)))
        return rf_ai_fail(c, "out of memory");
    rf_ai_axes(c, r->skeleton);
    return rf_ai_build_animation(c, r->skeleton, -1, NULL, &r->animation);
}

static bool rf_ai_run(rf_ai_ctx *c, const rf_ai_options *o, rf_ai_result *r)
{
    if (!(c->scene = rf_ai_load(c)) || !rf_ai_build_table(c))
        return false;
    rf_ai_select_joints(c);
    if (o->ignore_rig)
        return rf_ai_run_bare(c, o, r);
    if (!c->joint_count && o->require_skeleton)
        return rf_ai_fail(c,
                          "no skeleton: no skinned bones, animated nodes or node hierarchy "
                          "(%u meshes, %u animations)%s%s; a skeleton is required here",
                          c->scene->mNumMeshes, c->scene->mNumAnimations,
                          c->confine.missing[0] ? "; files it asked for that are not beside it: "
                                                : "",
                          c->confine.missing);
    if (!rf_ai_build_skeleton(c, o, &r->skeleton) || !rf_ai_build_mesh(c, &r->mesh))
        return false;
    rf_ai_flag_unweighted(r->skeleton, r->mesh);
    rf_ai_skin_end_sites(r->skeleton, r->mesh);
    rf_ai_axes(c, r->skeleton);
    if (!rf_ai_list_clips(c, o, r) || !rf_ai_select_clip(c, o->clip, &r->selected_clip))
        return false;
    if (!rf_ai_build_animation(c, r->skeleton, r->selected_clip,
                               r->selected_clip >= 0 ? &r->clips[r->selected_clip] : NULL,
                               &r->animation))
        return false;
    if (!o->clip || strcmp(o->clip, RF_AI_ALL_CLIPS) != 0 || !r->clip_count)
        return true;
    r->clip_animations = calloc(r->clip_count, sizeof *r->clip_animations);
    if (!r->clip_animations)
        return rf_ai_fail(c, "out of memory for %u clips", r->clip_count);
    for (unsigned i = 0; i < r->clip_count; i++) {
        /* the selected clip is resampled already: a copy costs less and logs nothing twice */
        if ((int)i == r->selected_clip) {
            if (!(r->clip_animations[i] = rf_animation_copy(r->animation)))
                return rf_ai_fail(c, "out of memory for clip '%s'", r->clips[i].name);
        } else if (!rf_ai_build_animation(c, r->skeleton, (int)i, &r->clips[i],
                                          &r->clip_animations[i]))
            return false;
    }
    return true;
}

typedef struct rf_ai_job {
    rf_ai_ctx *c;
    const rf_ai_options *o;
    rf_ai_result *r;
    bool ok;
} rf_ai_job;

static void rf_ai_job_run(void *p)
{
    rf_ai_job *j = p;
    j->ok = rf_ai_run(j->c, j->o, j->r);
    rf_ai_ctx_free(j->c); /* releasing the scene recurses too */
}

bool rf_ai_import(const char *path, const rf_ai_options *opts, rf_ai_result *out, rf_ai_log_fn log,
                  void *user, char *err, size_t err_size)
{
    static const rf_ai_options defaults = {0};
    rf_ai_ctx c = {.path = path, .log = log, .user = user, .err = err, .err_size = err_size};
    memset(out, 0, sizeof *out);
    out->selected_clip = -1;
    /* Assimp recurses once per level of node nesting: run it on a stack sized for the file
     * (aimport-io.c), so a deeply nested hostile file cannot overflow it. */
    rf_ai_job job = {&c, opts ? opts : &defaults, out, false};
    rf_ai_call_with_stack_for(path, rf_ai_job_run, &job);
    if (!job.ok)
        rf_ai_result_clear(out);
    return job.ok;
}
