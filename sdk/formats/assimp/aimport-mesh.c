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
#include <stdio.h>
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
    unsigned *part_mesh; /* [part] the aiMesh each part came from */
    uint32_t uv_sets;    /* texture coordinate sets kept (the most any part has, at most 2) */
    bool colors;         /* some part has vertex colours */
    bool tangents;       /* every part has tangents and normals */
    bool morphs_capped;  /* morph targets past the memory bound were left out */
} rf_ai_mesh_build;

static uint32_t rf_ai_uv_sets(const struct aiMesh *mesh)
{
    uint32_t n = 0;
    while (n < RF_MESH_MAX_UV_SETS && mesh->mTextureCoords[n])
        n++;
    return n;
}

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
    for (uint32_t k = 0; k < b->uv_sets; k++)
        m->uvs[k] = calloc(verts ? verts * 2 : 2, sizeof(float));
    m->uv_set_count = b->uv_sets;
    if (b->colors)
        m->colors = calloc(verts ? verts * 4 : 4, sizeof(float));
    if (b->tangents)
        m->tangents = calloc(verts ? verts * 4 : 4, sizeof(float));
    b->part_mesh = calloc(parts, sizeof *b->part_mesh);
    bool ok = m->positions && m->normals && m->triangles && m->parts && b->part_mesh &&
              (!b->uv_sets || m->uvs[0]) && (b->uv_sets < 2 || m->uvs[1]) &&
              (!b->colors || m->colors) && (!b->tangents || m->tangents);
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

/* Texture coordinates (glTF's origin: Assimp's v runs upwards, glTF's downwards), vertex
 * colours (white where a part has none) and tangents with their handedness. */
static void rf_ai_copy_look(rf_ai_mesh_build *b, const struct aiMesh *mesh, rf_mat4 to_model)
{
    rf_mesh *m = b->m;
    for (unsigned i = 0; i < mesh->mNumVertices; i++) {
        size_t v = b->v + i;
        for (uint32_t k = 0; k < b->uv_sets; k++) {
            const struct aiVector3D *uv =
                mesh->mTextureCoords[k] ? &mesh->mTextureCoords[k][i] : NULL;
            m->uvs[k][v * 2] = uv ? uv->x : 0.0f;
            m->uvs[k][v * 2 + 1] = uv ? 1.0f - uv->y : 0.0f;
        }
        if (b->colors) {
            const struct aiColor4D *col = mesh->mColors[0] ? &mesh->mColors[0][i] : NULL;
            float *d = m->colors + v * 4;
            d[0] = col ? col->r : 1.0f, d[1] = col ? col->g : 1.0f;
            d[2] = col ? col->b : 1.0f, d[3] = col ? col->a : 1.0f;
        }
        if (b->tangents) {
            const struct aiVector3D *t = &mesh->mTangents[i], *n = &mesh->mNormals[i];
            rf_vec3 tv = rf_v3_normalize(rf_mat4_dir(to_model, rf_v3(t->x, t->y, t->z)));
            rf_vec3 nv = rf_mat4_dir(to_model, rf_v3(n->x, n->y, n->z));
            double w = 1.0;
            if (mesh->mBitangents) {
                const struct aiVector3D *bt = &mesh->mBitangents[i];
                rf_vec3 bv = rf_mat4_dir(to_model, rf_v3(bt->x, bt->y, bt->z));
                w = rf_v3_dot(rf_v3_cross(nv, tv), bv) < 0 ? -1.0 : 1.0;
            }
            float *d = m->tangents + v * 4;
            d[0] = (float)tv.x, d[1] = (float)tv.y, d[2] = (float)tv.z, d[3] = (float)w;
        }
    }
}

#define RF_AI_MORPH_BYTES_MAX ((size_t)1 << 30) /* all targets' displacements together */

/* The merged mesh's target named `name`, made (zero everywhere) when new; NULL when out of memory
 * or past the memory bound (warned once). */
static rf_morph_target *rf_ai_morph_target(rf_ai_mesh_build *b, const char *name, bool normals)
{
    rf_mesh *m = b->m;
    for (uint32_t i = 0; i < m->morph_target_count; i++)
        if (strcmp(m->morph_targets[i]->name, name) == 0)
            return m->morph_targets[i];
    size_t bytes = (size_t)m->vertex_count * 24;
    if ((size_t)(m->morph_target_count + 1) * bytes > RF_AI_MORPH_BYTES_MAX) {
        if (!b->morphs_capped)
            rf_ai_logf(b->c, 1,
                       "%s: morph target '%s' and later ones left out: more than 1 GiB of "
                       "displacements",
                       b->c->path, name);
        b->morphs_capped = true;
        return NULL;
    }
    rf_morph_target **grown =
        realloc(m->morph_targets, (m->morph_target_count + 1) * sizeof *grown);
    if (!grown)
        return NULL;
    m->morph_targets = grown;
    rf_morph_target *t = rf_morph_target_new(name, m->vertex_count);
    if (t && normals && !(t->normals = calloc((size_t)m->vertex_count * 3 + 3, sizeof(float)))) {
        rf_morph_target_free(t);
        t = NULL;
    }
    if (t)
        m->morph_targets[m->morph_target_count++] = t;
    return t;
}

/* Morph targets: Assimp gives each as a whole replacement mesh (aiAnimMesh); rigflow keeps the
 * displacement from the base, in model space, merged by name across parts. */
static void rf_ai_copy_morphs(rf_ai_mesh_build *b, const struct aiMesh *mesh, rf_mat4 to_model)
{
    for (unsigned k = 0; k < mesh->mNumAnimMeshes; k++) {
        const struct aiAnimMesh *am = mesh->mAnimMeshes[k];
        if (!am || !am->mVertices || am->mNumVertices != mesh->mNumVertices)
            continue;
        char name[64];
        snprintf(name, sizeof name, "morph%u", k);
        bool normals = am->mNormals && mesh->mNormals;
        rf_morph_target *t =
            rf_ai_morph_target(b, am->mName.data[0] ? am->mName.data : name, normals);
        if (!t)
            return;
        t->weight = isfinite(am->mWeight) ? am->mWeight : 0.0f;
        for (unsigned i = 0; i < mesh->mNumVertices; i++) {
            const struct aiVector3D *p = &am->mVertices[i], *q = &mesh->mVertices[i];
            rf_vec3 d = rf_mat4_dir(to_model, rf_v3(p->x - q->x, p->y - q->y, p->z - q->z));
            float *dst = t->positions + (size_t)(b->v + i) * 3;
            dst[0] = (float)d.x, dst[1] = (float)d.y, dst[2] = (float)d.z;
            if (!normals || !t->normals)
                continue;
            const struct aiVector3D *n = &am->mNormals[i], *n0 = &mesh->mNormals[i];
            rf_vec3 dn = rf_mat4_dir(to_model, rf_v3(n->x - n0->x, n->y - n0->y, n->z - n0->z));
            float *nd = t->normals + (size_t)(b->v + i) * 3;
            nd[0] = (float)dn.x, nd[1] = (float)dn.y, nd[2] = (float)dn.z;
        }
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
    b->part_mesh[b->p] = mesh_index;
    rf_mesh_part *part = &b->m->parts[b->p++];
    const char *name = mesh->mName.data[0] ? mesh->mName.data : b->c->nodes[node]->mName.data;
    part->name = rf_strdup(name);
    b->any_normals |= mesh->mNormals != NULL;
    part->first_vertex = b->v, part->vertex_count = mesh->mNumVertices;
    part->first_triangle = b->t;
    rf_mat4 to_model = rf_ai_mesh_to_model(b->c, node, mesh_index);
    rf_ai_copy_vertices(b, mesh, to_model);
    rf_ai_copy_look(b, mesh, to_model);
    rf_ai_copy_morphs(b, mesh, to_model);
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
    rf_ai_mesh_build b = {.c = c, .skinned = c->joint_count > 0, .tangents = true};
    *out = NULL;
    for (unsigned i = 0; i < c->node_count; i++)
        for (unsigned k = 0; k < c->nodes[i]->mNumMeshes; k++) {
            unsigned mi = c->nodes[i]->mMeshes[k];
            if (mi >= s->mNumMeshes)
                return rf_ai_fail(c, "node '%s' names mesh %u of %u", c->nodes[i]->mName.data, mi,
                                  s->mNumMeshes);
            if (!rf_ai_has_triangles(s->mMeshes[mi]))
                continue;
            const struct aiMesh *mesh = s->mMeshes[mi];
            b.uv_sets = rf_ai_uv_sets(mesh) > b.uv_sets ? rf_ai_uv_sets(mesh) : b.uv_sets;
            b.colors |= mesh->mColors[0] != NULL;
            b.tangents &= mesh->mTangents && mesh->mNormals;
            verts += s->mMeshes[mi]->mNumVertices;
            tris += rf_ai_triangle_count(s->mMeshes[mi]);
            parts++;
        }
    if (!parts)
        return true;
    bool ok = rf_ai_mesh_alloc(&b, verts, tris, parts);
    for (unsigned i = 0; ok && i < c->node_count; i++)
        for (unsigned k = 0; ok && k < c->nodes[i]->mNumMeshes; k++) {
            unsigned mi = c->nodes[i]->mMeshes[k];
            if (rf_ai_has_triangles(s->mMeshes[mi]))
                ok = rf_ai_add_instance(&b, (int)i, mi);
        }
    if (ok) {
        b.m->part_count = b.p;
        ok = rf_ai_build_materials(c, b.m, b.part_mesh);
    }
    free(b.part_mesh);
    if (!ok) {
        rf_mesh_free(b.m);
        return false;
    }
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

/* ---- leaf bones' ends from the skin ---- */

/* The leaf joint (flagged in `leaf`) vertex v is weighted most to, with v in its bind space into
 * *l; -1 when another joint weights v most. */
static int32_t rf_ai_vertex_leaf(const rf_mesh *m, const uint8_t *leaf, uint32_t v, rf_vec3 *l)
{
    const uint16_t *js = m->skin_joints + (size_t)v * 4;
    const float *ws = m->skin_weights + (size_t)v * 4;
    int best = 0;
    for (int k = 1; k < 4; k++)
        best = ws[k] > ws[best] ? k : best;
    uint32_t j = js[best];
    if (!(ws[best] > 0) || j >= m->bind_count || !leaf[j])
        return -1;
    const float *p = m->positions + (size_t)v * 3;
    *l = rf_mat4_point(m->inverse_bind[j], rf_v3(p[0], p[1], p[2]));
    return (int32_t)j;
}

/* A leaf joint without an end site (Assimp's formats have none) ends where the skin it carries
 * ends: of the vertices it weights most, taken into its bind space, the mean gives the bone's
 * direction and the farthest along it its length. Without this a reader can only guess a leaf's
 * length from its parent's distance, which says nothing of it (a box model's leg hung from a
 * pivot beside its parent's: a leg guessed at a third of its length). A leaf whose vertices lie
 * around its pivot (the mean under a quarter of the farthest vertex's distance: a pivot in the
 * middle of its part) gets none: the skin tells no direction. */
void rf_ai_skin_end_sites(rf_skeleton *s, const rf_mesh *m)
{
    uint32_t n = s->joint_count;
    if (!m || !m->skin_joints || !m->skin_weights || !m->inverse_bind || m->bind_count != n || !n)
        return;
    rf_vec3 *mean = calloc(n, sizeof *mean);
    double *count = calloc(n, sizeof *count), *reach = calloc(n, sizeof *reach),
           *radius = calloc(n, sizeof *radius);
    uint8_t *leaf = malloc(n);
    if (!mean || !count || !reach || !radius || !leaf)
        goto done;
    memset(leaf, 1, n);
    for (uint32_t j = 0; j < n; j++) {
        if (s->joints[j].parent >= 0)
            leaf[s->joints[j].parent] = 0;
        if (s->joints[j].flags & RF_JOINT_HAS_END_SITE)
            leaf[j] = 0;
    }
    rf_vec3 l;
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        int32_t j = rf_ai_vertex_leaf(m, leaf, v, &l);
        if (j >= 0)
            mean[j] = rf_v3_add(mean[j], l), count[j]++, radius[j] = fmax(radius[j], rf_v3_len(l));
    }
    for (uint32_t j = 0; j < n; j++)
        if (leaf[j] && count[j] > 0) {
            mean[j] = rf_v3_scale(mean[j], 1 / count[j]);
            leaf[j] = rf_v3_len(mean[j]) >= 0.25 * radius[j] && radius[j] > 0;
            if (leaf[j])
                mean[j] = rf_v3_scale(mean[j], 1 / rf_v3_len(mean[j]));
        } else {
            leaf[j] = 0;
        }
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        int32_t j = rf_ai_vertex_leaf(m, leaf, v, &l);
        if (j >= 0)
            reach[j] = fmax(reach[j], rf_v3_dot(l, mean[j]));
    }
    for (uint32_t j = 0; j < n; j++)
        if (leaf[j] && reach[j] > 0) {
            s->joints[j].end_site = rf_v3_scale(mean[j], reach[j]);
            s->joints[j].flags |= RF_JOINT_HAS_END_SITE;
        }
done:
    free(mean), free(count), free(reach), free(radius), free(leaf);
}
