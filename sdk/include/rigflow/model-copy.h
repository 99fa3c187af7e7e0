/* rigflow SDK: deep copies of the data model's values (model.h).
 *
 * A copy is a struct of this build: it has every field this header knows, those the original
 * lacks (an older producer's struct, see RF_HAS_FIELD) zero. Each returns NULL when out of memory
 * (nothing is leaked) and is (transfer full): free it with the type's rf_*_free.
 */
#ifndef RIGFLOW_MODEL_COPY_H
#define RIGFLOW_MODEL_COPY_H

#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <rigflow/model.h>

#ifdef __cplusplus
extern "C" {
#endif

/* A copy of `s`, or NULL when `s` is NULL or out of memory. */
static inline char *rf_strdup(const char *s)
{
    if (!s)
        return NULL;
    size_t n = strlen(s) + 1;
    char *d = (char *)malloc(n);
    if (d)
        memcpy(d, s, n);
    return d;
}

/* A copy of `count` elements of `size` bytes at `p`; NULL for a NULL `p` (then *ok is kept) or
 * when out of memory (then *ok becomes false). */
static inline void *rf_memdup(const void *p, size_t count, size_t size, bool *ok)
{
    if (!p)
        return NULL;
    if (size && count > SIZE_MAX / size) {
        *ok = false;
        return NULL;
    }
    size_t bytes = count * size;
    void *d = malloc(bytes ? bytes : 1);
    if (d)
        memcpy(d, p, bytes);
    else
        *ok = false;
    return d;
}

/* A copy of `count` strings (NULL entries stay NULL); NULL for a NULL `v`. */
static inline char **rf_strv_dup(char *const *v, uint32_t count, bool *ok)
{
    if (!v)
        return NULL;
    char **d = (char **)calloc(count ? count : 1, sizeof *d);
    if (!d) {
        *ok = false;
        return NULL;
    }
    for (uint32_t i = 0; i < count; i++)
        if (v[i] && !(d[i] = rf_strdup(v[i])))
            *ok = false;
    return d;
}

static inline rf_skeleton *rf_skeleton_copy(const rf_skeleton *s)
{
    rf_skeleton *c = s ? rf_skeleton_new(s->joint_count) : NULL;
    if (!c)
        return NULL;
    bool ok = true;
    for (uint32_t j = 0; j < s->joint_count; j++) {
        c->joints[j] = s->joints[j];
        c->joints[j].name = NULL;
        if (s->joints[j].name && !(c->joints[j].name = rf_strdup(s->joints[j].name)))
            ok = false;
    }
    c->name = rf_strdup(s->name);
    ok = ok && (!s->name || c->name);
    c->up = s->up;
    c->forward = s->forward;
    if (RF_HAS_FIELD(s, rf_skeleton, rest_source)) {
        c->bind = (rf_xform *)rf_memdup(s->bind, s->joint_count, sizeof *s->bind, &ok);
        c->rest_source = s->rest_source;
    }
    if (!ok) {
        rf_skeleton_free(c);
        return NULL;
    }
    return c;
}

static inline rf_animation *rf_animation_copy(const rf_animation *a)
{
    rf_animation *c = a ? rf_animation_new(a->joint_count, a->frame_count, a->fps) : NULL;
    if (!c)
        return NULL;
    size_t n = (size_t)a->joint_count * a->frame_count;
    memcpy(c->rotations, a->rotations, n * 4 * sizeof *a->rotations);
    memcpy(c->translations, a->translations, n * 3 * sizeof *a->translations);
    memcpy(c->channels, a->channels, a->joint_count);
    c->source_start = RF_HAS_FIELD(a, rf_animation, source_start) ? a->source_start : 0;
    c->name = rf_strdup(a->name);
    if (a->name && !c->name) {
        rf_animation_free(c);
        return NULL;
    }
    return c;
}

static inline rf_material *rf_material_copy(const rf_material *m)
{
    rf_material *c = m ? rf_material_new() : NULL;
    if (!c)
        return NULL;
    size_t n = m->size < sizeof *c ? m->size : sizeof *c; /* an older producer's: zero tail */
    memcpy(c, m, n);
    c->size = sizeof *c;
    c->name = rf_strdup(m->name);
    if (m->name && !c->name) {
        rf_material_free(c);
        return NULL;
    }
    return c;
}

static inline rf_image *rf_image_copy(const rf_image *im)
{
    return im ? rf_image_new(im->name, im->mime_type ? im->mime_type : "", im->bytes,
                             im->byte_count)
              : NULL;
}

static inline rf_morph_target *rf_morph_target_copy(const rf_morph_target *t, uint32_t vertices)
{
    rf_morph_target *c = t ? rf_morph_target_new(t->name ? t->name : "", vertices) : NULL;
    bool ok = c != NULL;
    if (c) {
        c->weight = t->weight;
        if (t->positions)
            memcpy(c->positions, t->positions, (size_t)vertices * 3 * sizeof(float));
        c->normals = (float *)rf_memdup(t->normals, (size_t)vertices * 3, sizeof(float), &ok);
    }
    if (!ok) {
        rf_morph_target_free(c);
        return NULL;
    }
    return c;
}

/* The look and the morph targets of `m` (1.2) into `c`; false when out of memory. */
static inline bool rf_mesh_copy_look(rf_mesh *c, const rf_mesh *m)
{
    bool ok = true;
    size_t nv = m->vertex_count;
    if (!RF_HAS_FIELD(m, rf_mesh, morph_targets))
        return true;
    c->uv_set_count = m->uv_set_count;
    for (uint32_t k = 0; k < RF_MESH_MAX_UV_SETS; k++)
        c->uvs[k] = (float *)rf_memdup(m->uvs[k], nv * 2, sizeof(float), &ok);
    c->colors = (float *)rf_memdup(m->colors, nv * 4, sizeof(float), &ok);
    c->tangents = (float *)rf_memdup(m->tangents, nv * 4, sizeof(float), &ok);
    c->part_material = (int32_t *)rf_memdup(m->part_material, m->part_count, sizeof(int32_t), &ok);
    if (m->materials && m->material_count) {
        c->materials = (rf_material **)calloc(m->material_count, sizeof *c->materials);
        c->material_count = c->materials ? m->material_count : 0;
        for (uint32_t i = 0; i < c->material_count; i++)
            if (m->materials[i] && !(c->materials[i] = rf_material_copy(m->materials[i])))
                ok = false;
        ok = ok && c->materials;
    }
    if (m->images && m->image_count) {
        c->images = (rf_image **)calloc(m->image_count, sizeof *c->images);
        c->image_count = c->images ? m->image_count : 0;
        for (uint32_t i = 0; i < c->image_count; i++)
            if (m->images[i] && !(c->images[i] = rf_image_copy(m->images[i])))
                ok = false;
        ok = ok && c->images;
    }
    if (m->morph_targets && m->morph_target_count) {
        c->morph_targets =
            (rf_morph_target **)calloc(m->morph_target_count, sizeof *c->morph_targets);
        c->morph_target_count = c->morph_targets ? m->morph_target_count : 0;
        for (uint32_t i = 0; i < c->morph_target_count; i++)
            if (m->morph_targets[i] &&
                !(c->morph_targets[i] = rf_morph_target_copy(m->morph_targets[i], m->vertex_count)))
                ok = false;
        ok = ok && c->morph_targets;
    }
    return ok;
}

static inline rf_mesh *rf_mesh_copy(const rf_mesh *m)
{
    rf_mesh *c = m ? rf_mesh_new() : NULL;
    if (!c)
        return NULL;
    bool ok = true;
    size_t nv = m->vertex_count, infl = RF_MESH_MAX_INFLUENCES;
    c->name = rf_strdup(m->name);
    ok = !m->name || c->name;
    c->vertex_count = m->vertex_count;
    c->triangle_count = m->triangle_count;
    c->positions = (float *)rf_memdup(m->positions, nv * 3, sizeof(float), &ok);
    c->normals = (float *)rf_memdup(m->normals, nv * 3, sizeof(float), &ok);
    c->triangles =
        (uint32_t *)rf_memdup(m->triangles, (size_t)m->triangle_count * 3, sizeof(uint32_t), &ok);
    c->skin_joints = (uint16_t *)rf_memdup(m->skin_joints, nv * infl, sizeof(uint16_t), &ok);
    c->skin_weights = (float *)rf_memdup(m->skin_weights, nv * infl, sizeof(float), &ok);
    c->bind_count = m->bind_count;
    c->inverse_bind = (rf_mat4 *)rf_memdup(m->inverse_bind, m->bind_count, sizeof(rf_mat4), &ok);
    if (RF_HAS_FIELD(m, rf_mesh, parts) && m->parts) {
        c->parts = (rf_mesh_part *)rf_memdup(m->parts, m->part_count, sizeof *m->parts, &ok);
        c->part_count = c->parts ? m->part_count : 0;
        for (uint32_t i = 0; c->parts && i < c->part_count; i++)
            if (m->parts[i].name && !(c->parts[i].name = rf_strdup(m->parts[i].name)))
                ok = false;
    }
    if (!rf_mesh_copy_look(c, m))
        ok = false;
    if (!ok) {
        rf_mesh_free(c);
        return NULL;
    }
    return c;
}

/* One mapping entry's inputs and metrics (`metric_count` of them) into a zeroed `d`. */
static inline bool rf_map_entry_copy(rf_map_entry *d, const rf_map_entry *s, uint32_t metric_count)
{
    bool ok = true;
    *d = *s;
    d->inputs = (rf_map_input *)rf_memdup(s->inputs, s->input_count, sizeof *s->inputs, &ok);
    d->metrics = (double *)rf_memdup(s->metrics, metric_count, sizeof *s->metrics, &ok);
    if (!d->inputs)
        d->input_count = 0;
    return ok;
}

static inline rf_mapping *rf_mapping_copy(const rf_mapping *m)
{
    rf_mapping *c = m ? rf_mapping_new(m->target_joint_count, m->source_count) : NULL;
    if (!c)
        return NULL;
    bool ok = true;
    c->metric_names = rf_strv_dup(m->metric_names, m->metric_count, &ok);
    c->metric_count = c->metric_names ? m->metric_count : 0;
    if (RF_HAS_FIELD(m, rf_mapping, sides)) {
        c->sections = rf_strv_dup(m->sections, m->target_joint_count, &ok);
        c->sides = rf_strv_dup(m->sides, m->target_joint_count, &ok);
    }
    for (uint32_t j = 0; ok && j < m->target_joint_count; j++)
        ok = rf_map_entry_copy(&c->entries[j], &m->entries[j], c->metric_count);
    if (!ok) {
        rf_mapping_free(c);
        return NULL;
    }
    return c;
}

#ifdef __cplusplus
}
#endif

#endif
