/* glTF's axes for the writer (gltf-axes.h). A format that declares its axes (FBX's GlobalSettings,
 * a rigger's reading of the body) may hand over a character lying along +Z or facing -X; glTF
 * has no field for it and every reader assumes +Y up and the front at +Z, so the content is
 * turned instead. Only roots carry the turn: every other joint is local to its parent. */
#include <math.h>
#include <stdlib.h>

#include "gltf-axes.h"
#include "rigflow/model-copy.h"

rf_quat rf_gw_axes_turn(rf_vec3 up, rf_vec3 forward)
{
    if (!(rf_v3_len(up) > 0) || !rf_v3_isfinite(up))
        return rf_quat_identity();
    if (!rf_v3_isfinite(forward)) /* no facing, as a zero one: the content is still stood up */
        forward = rf_v3(0, 0, 0);
    rf_vec3 u = rf_v3_normalize(up);
    rf_quat q = rf_quat_from_two_vectors(u, rf_v3(0, 1, 0));
    rf_vec3 f = rf_v3_sub(forward, rf_v3_scale(u, rf_v3_dot(forward, u)));
    if (!(rf_v3_len(f) > 1e-6 * rf_v3_len(forward)))
        return q; /* facing unknown or along up: upright only */
    f = rf_quat_rotate(q, f);
    /* about +Y, the level facing (x, z) onto +Z */
    rf_quat yaw = rf_quat_from_axis_angle(rf_v3(0, 1, 0), -atan2(f.x, f.z));
    return rf_quat_normalize(rf_quat_mul(yaw, q));
}

static void rf_gw_turn_floats(float *v, size_t count, size_t stride, rf_quat q)
{
    for (size_t i = 0; v && i < count; i++) {
        float *p = v + i * stride;
        rf_vec3 r = rf_quat_rotate(q, rf_v3(p[0], p[1], p[2]));
        p[0] = (float)r.x, p[1] = (float)r.y, p[2] = (float)r.z;
    }
}

static void rf_gw_turn_root(rf_xform *x, rf_quat q)
{
    x->t = rf_quat_rotate(q, x->t);
    x->r = rf_quat_normalize(rf_quat_mul(q, x->r));
}

static void rf_gw_turn_skeleton(rf_skeleton *s, rf_quat q)
{
    for (uint32_t j = 0; j < s->joint_count; j++)
        if (s->joints[j].parent < 0) {
            rf_gw_turn_root(&s->joints[j].rest, q);
            if (RF_HAS_FIELD(s, rf_skeleton, bind) && s->bind)
                rf_gw_turn_root(&s->bind[j], q);
        }
    s->up = rf_v3(0, 1, 0), s->forward = rf_v3_len(s->forward) > 0 ? rf_v3(0, 0, 1) : s->forward;
}

static void rf_gw_turn_clip(rf_animation *a, const rf_skeleton *s, rf_quat q)
{
    for (uint32_t j = 0; j < a->joint_count; j++) {
        if (s->joints[j].parent >= 0)
            continue;
        for (uint32_t f = 0; f < a->frame_count; f++) {
            rf_xform x = {rf_animation_translation(a, f, j), rf_animation_rotation(a, f, j),
                          rf_v3(1, 1, 1)};
            rf_gw_turn_root(&x, q);
            rf_animation_set_translation(a, f, j, x.t);
            rf_animation_set_rotation(a, f, j, x.r);
        }
    }
}

static void rf_gw_turn_mesh(rf_mesh *m, rf_quat q)
{
    size_t n = m->vertex_count;
    rf_gw_turn_floats(m->positions, n, 3, q);
    rf_gw_turn_floats(m->normals, n, 3, q);
    rf_gw_turn_floats(m->tangents, n, 4, q);
    for (uint32_t t = 0; t < m->morph_target_count; t++) {
        rf_gw_turn_floats(m->morph_targets[t]->positions, n, 3, q);
        rf_gw_turn_floats(m->morph_targets[t]->normals, n, 3, q);
    }
    /* model space is turned: a point's old coordinates are the turned ones turned back */
    rf_xform back = {rf_v3(0, 0, 0), rf_quat_conj(q), rf_v3(1, 1, 1)};
    rf_mat4 undo = rf_xform_to_mat4(back);
    for (uint32_t j = 0; m->inverse_bind && j < m->bind_count; j++)
        m->inverse_bind[j] = rf_mat4_mul(m->inverse_bind[j], undo);
}

bool rf_gw_axes_conform(rf_gw_axes *x, const rf_skeleton *s, const rf_animation *const *a,
                        uint32_t count, const rf_mesh *m)
{
    *x = (rf_gw_axes){.skeleton = s, .mesh = m};
    x->animations = calloc(count ? count : 1, sizeof *x->animations);
    if (!x->animations)
        return false;
    for (uint32_t i = 0; i < count; i++)
        x->animations[i] = a[i];
    rf_quat q = rf_gw_axes_turn(s->up, s->forward);
    if (rf_quat_angle(q, rf_quat_identity()) < 1e-9)
        return true;
    x->own_animations = calloc(count ? count : 1, sizeof *x->own_animations);
    bool ok = x->own_animations && (x->own_skeleton = rf_skeleton_copy(s)) &&
              (!m || (x->own_mesh = rf_mesh_copy(m)));
    for (uint32_t i = 0; ok && i < count; i++)
        ok = !a[i] || (x->own_animations[i] = rf_animation_copy(a[i]));
    if (!ok)
        return false;
    for (uint32_t i = 0; i < count; i++)
        if (x->own_animations[i]) {
            rf_gw_turn_clip(x->own_animations[i], s, q);
            x->animations[i] = x->own_animations[i];
        }
    rf_gw_turn_skeleton(x->own_skeleton, q);
    x->skeleton = x->own_skeleton;
    if (x->own_mesh)
        rf_gw_turn_mesh(x->own_mesh, q), x->mesh = x->own_mesh;
    return true;
}

void rf_gw_axes_clear(rf_gw_axes *x, uint32_t count)
{
    for (uint32_t i = 0; x->own_animations && i < count; i++)
        rf_animation_free(x->own_animations[i]);
    free(x->own_animations), free(x->animations);
    rf_skeleton_free(x->own_skeleton), rf_mesh_free(x->own_mesh);
    *x = (rf_gw_axes){0};
}
