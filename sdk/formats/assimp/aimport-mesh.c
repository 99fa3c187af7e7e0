/* Assimp import: every mesh instance merged into one rf_mesh skinned to the one skeleton.
 *
 * Positions are in model space, the space in which joint world transforms live (the scene root's
 * space with every static ancestor applied). Skinned meshes keep their vertices as given, with
 * the bones' offset matrices as inverse binds (the convention of Assimp and glTF: world =
 * joint global * offset * vertex), mapped into model space as aimport.c's rf_ai_mesh_spaces
 * explains, so meshes bound in different spaces come together. Rigid meshes
 * hung below a joint become skinned to that joint with weight 1, placed at its bind pose. Skin
 * weights keep the four largest per vertex, normalised to sum to 1.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aimport-internal.h"

typedef struct rf_ai_mesh_build {
    rf_ai_ctx *c;
    rf_mesh *m;
    bool skinned;
    uint32_t v, t, p;    /* vertices, triangles and parts written so far */
    uint32_t unweighted; /* skinned vertices that had no weight at all */
    bool any_normals;
} rf_ai_mesh_build;

static bool rf_ai_has_triangles(const struct aiMesh *mesh)
{
    return (mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) && mesh->mNumVertices > 0;
}

static uint32_t rf_ai_triangle_count(const struct aiMesh *mesh)
{
    uint32_t n = 0;
    for (unsigned f = 0; f < mesh->mNumFaces; f++)
        n += mesh->mFaces[f].mNumIndices == 3;
    return n;
}

static bool rf_ai_mesh_alloc(rf_ai_mesh_build *b, size_t verts, size_t tris, unsigned parts)
{
    rf_ai_ctx *c = b->c;
    if (verts > UINT32_MAX / 4 || tris > UINT32_MAX / 3)
        return rf_ai_fail(c, "too many vertices (%zu) or triangles (%zu)", verts, tris);
    if (c->joint_count > UINT16_MAX)
        return rf_ai_fail(c, "%u joints: a skin indexes at most 65535", c->joint_count);
    rf_mesh *m = b->m = rf_mesh_new();
    if (!m)
        return rf_ai_fail(c, "out of memory");
    m->vertex_count = (uint32_t)verts, m->triangle_count = (uint32_t)tris;
    m->positions = calloc(verts * 3, sizeof(float));
    m->normals = calloc(verts * 3, sizeof(float));
    m->triangles = calloc(tris ? tris * 3 : 1, sizeof(uint32_t));
    m->parts = calloc(parts, sizeof *m->parts);
    bool ok = m->positions && m->normals && m->triangles && m->parts;
    if (b->skinned) {
        m->skin_joints = calloc(verts * 4, sizeof(uint16_t));
        m->skin_weights = calloc(verts * 4, sizeof(float));
        m->inverse_bind = calloc(c->joint_count, sizeof(rf_mat4));
        m->bind_count = c->joint_count;
        ok = ok && m->skin_joints && m->skin_weights && m->inverse_bind;
    }
    return ok ? true : rf_ai_fail(c, "out of memory for %zu vertices", verts);
}

/* Keeps the four largest weights of a vertex: a new weight replaces the smallest kept one. */
static void rf_ai_add_weight(rf_mesh *m, uint32_t v, uint16_t joint, float w)
{
    uint16_t *js = m->skin_joints + (size_t)v * 4;
    float *ws = m->skin_weights + (size_t)v * 4;
    for (int i = 0; i < 4; i++)
        if (ws[i] > 0 && js[i] == joint) { /* a bone listed twice for one vertex */
            ws[i] += w;
            return;
        }
    int min = 0;
    for (int i = 1; i < 4; i++)
        if (ws[i] < ws[min])
            min = i;
    if (w > ws[min])
        js[min] = joint, ws[min] = w;
}

/* The transform taking this mesh's vertices into model space (see the file comment). */
static rf_mat4 rf_ai_mesh_to_model(rf_ai_ctx *c, int node, unsigned mesh_index)
{
    const struct aiMesh *mesh = c->scene->mMeshes[mesh_index];
    if (mesh->mNumBones == 0) {
        int j = rf_ai_joint_above(c, node);
        if (j < 0)
            return c->node_global[node];
        rf_mat4 jinv;
        if (!rf_mat4_invert(c->node_global[c->joint_node[j]], &jinv))
            return c->node_global[node];
        return rf_mat4_mul(c->bind_global[j], rf_mat4_mul(jinv, c->node_global[node]));
    }
    return c->mesh_space[mesh_index];
}

static void rf_ai_copy_vertices(rf_ai_mesh_build *b, const struct aiMesh *mesh, rf_mat4 to_model)
{
    rf_mesh *m = b->m;
    for (unsigned i = 0; i < mesh->mNumVertices; i++) {
        const struct aiVector3D *p = &mesh->mVertices[i];
        rf_vec3 q = rf_mat4_point(to_model, rf_v3(p->x, p->y, p->z));
        float *dst = m->positions + (size_t)(b->v + i) * 3;
        dst[0] = (float)q.x, dst[1] = (float)q.y, dst[2] = (float)q.z;
        if (!mesh->mNormals)
            continue;
        const struct aiVector3D *nv = &mesh->mNormals[i];
        rf_vec3 n = rf_v3_normalize(rf_mat4_dir(to_model, rf_v3(nv->x, nv->y, nv->z)));
        float *nd = m->normals + (size_t)(b->v + i) * 3;
        nd[0] = (float)n.x, nd[1] = (float)n.y, nd[2] = (float)n.z;
    }
}

static bool rf_ai_copy_triangles(rf_ai_mesh_build *b, const struct aiMesh *mesh)
{
    for (unsigned f = 0; f < mesh->mNumFaces; f++) {
        const struct aiFace *face = &mesh->mFaces[f];
        if (face->mNumIndices != 3)
            continue; /* points and lines have no place in a skinned surface */
        for (int k = 0; k < 3; k++) {
            if (face->mIndices[k] >= mesh->mNumVertices)
                return rf_ai_fail(b->c, "mesh '%s': face %u uses vertex %u of %u", mesh->mName.data,
                                  f, face->mIndices[k], mesh->mNumVertices);
            b->m->triangles[(size_t)b->t * 3 + k] = b->v + face->mIndices[k];
        }
        b->t++;
    }
    return true;
}

static void rf_ai_copy_skin(rf_ai_mesh_build *b, int node, const struct aiMesh *mesh)
{
    rf_ai_ctx *c = b->c;
    for (unsigned i = 0; i < mesh->mNumBones; i++) {
        const struct aiBone *bone = mesh->mBones[i];
        int n = rf_ai_find_node(c, bone->mName.data);
        if (n < 0 || c->joint_of[n] < 0)
            continue;
        for (unsigned w = 0; w < bone->mNumWeights; w++) {
            const struct aiVertexWeight *vw = &bone->mWeights[w];
            if (vw->mVertexId < mesh->mNumVertices && isfinite(vw->mWeight) && vw->mWeight > 0)
                rf_ai_add_weight(b->m, b->v + vw->mVertexId, (uint16_t)c->joint_of[n], vw->mWeight);
        }
    }
    /* Rigid parts and vertices no bone reaches follow the nearest joint above the mesh node. */
    int fallback = rf_ai_joint_above(c, node);
    for (unsigned i = 0; i < mesh->mNumVertices; i++) {
        float *ws = b->m->skin_weights + (size_t)(b->v + i) * 4;
        uint16_t *js = b->m->skin_joints + (size_t)(b->v + i) * 4;
        double sum = (double)ws[0] + ws[1] + ws[2] + ws[3];
        if (sum > 0) {
            for (int k = 0; k < 4; k++)
                ws[k] = (float)(ws[k] / sum);
            continue;
        }
        if (mesh->mNumBones)
            b->unweighted++;
        js[0] = (uint16_t)(fallback >= 0 ? fallback : 0), ws[0] = 1.0f;
    }
}

static bool rf_ai_add_instance(rf_ai_mesh_build *b, int node, unsigned mesh_index)
{
    const struct aiMesh *mesh = b->c->scene->mMeshes[mesh_index];
    rf_mesh_part *part = &b->m->parts[b->p++];
    const char *name = mesh->mName.data[0] ? mesh->mName.data : b->c->nodes[node]->mName.data;
    part->name = rf_ai_strdup(name);
    b->any_normals |= mesh->mNormals != NULL;
    part->first_vertex = b->v, part->vertex_count = mesh->mNumVertices;
    part->first_triangle = b->t;
    rf_ai_copy_vertices(b, mesh, rf_ai_mesh_to_model(b->c, node, mesh_index));
    if (!rf_ai_copy_triangles(b, mesh))
        return false;
    part->triangle_count = b->t - part->first_triangle;
    if (b->skinned)
        rf_ai_copy_skin(b, node, mesh);
    b->v += mesh->mNumVertices;
    return true;
}

static void rf_ai_fill_inverse_binds(rf_ai_ctx *c, rf_mesh *m)
{
    for (unsigned j = 0; j < c->joint_count; j++) {
        int n = c->joint_node[j];
        if (c->bone_of[n])
            m->inverse_bind[j] = c->bone_offset[n];
        else if (!rf_mat4_invert(c->bind_global[j], &m->inverse_bind[j]))
            m->inverse_bind[j] = rf_mat4_identity();
    }
}

bool rf_ai_build_mesh(rf_ai_ctx *c, rf_mesh **out)
{
    const struct aiScene *s = c->scene;
    size_t verts = 0, tris = 0;
    unsigned parts = 0;
    *out = NULL;
    for (unsigned i = 0; i < c->node_count; i++)
        for (unsigned k = 0; k < c->nodes[i]->mNumMeshes; k++) {
            unsigned mi = c->nodes[i]->mMeshes[k];
            if (mi >= s->mNumMeshes)
                return rf_ai_fail(c, "node '%s' names mesh %u of %u", c->nodes[i]->mName.data, mi,
                                  s->mNumMeshes);
            if (!rf_ai_has_triangles(s->mMeshes[mi]))
                continue;
            verts += s->mMeshes[mi]->mNumVertices;
            tris += rf_ai_triangle_count(s->mMeshes[mi]);
            parts++;
        }
    if (!parts)
        return true;
    rf_ai_mesh_build b = {.c = c, .skinned = c->joint_count > 0};
    bool ok = rf_ai_mesh_alloc(&b, verts, tris, parts);
    for (unsigned i = 0; ok && i < c->node_count; i++)
        for (unsigned k = 0; ok && k < c->nodes[i]->mNumMeshes; k++) {
            unsigned mi = c->nodes[i]->mMeshes[k];
            if (rf_ai_has_triangles(s->mMeshes[mi]))
                ok = rf_ai_add_instance(&b, (int)i, mi);
        }
    if (!ok) {
        rf_mesh_free(b.m);
        return false;
    }
    b.m->part_count = b.p;
    if (!b.any_normals) {
        free(b.m->normals);
        b.m->normals = NULL;
    }
    b.m->triangle_count = b.t;
    if (b.skinned)
        rf_ai_fill_inverse_binds(c, b.m);
    if (b.unweighted)
        rf_ai_logf(c, 1, "%s: %u skinned vertices had no weight; bound to the mesh's joint",
                   c->path, b.unweighted);
    *out = b.m;
    return true;
}
