/* Builders for the retargeting tests: small skeletons, clips and mappings written out by hand. */
#ifndef RF_RT_FIXTURES_H
#define RF_RT_FIXTURES_H

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <rigflow/rigflow.h>

#define DEG (RF_PI / 180.0)

/* Sets joint j: name, parent, offset (rest translation), rest rotation. */
static inline void fx_joint(rf_skeleton *s, uint32_t j, const char *name, int32_t parent,
                            rf_vec3 offset, rf_quat rest)
{
    s->joints[j].name = malloc(strlen(name) + 1);
    strcpy(s->joints[j].name, name);
    s->joints[j].parent = parent;
    s->joints[j].rest.t = offset;
    s->joints[j].rest.r = rest;
}

static inline void fx_end_site(rf_skeleton *s, uint32_t j, rf_vec3 tip)
{
    s->joints[j].flags |= RF_JOINT_HAS_END_SITE;
    s->joints[j].end_site = tip;
}

static inline rf_quat fx_rot(rf_vec3 axis, double degrees)
{
    return rf_quat_from_axis_angle(axis, degrees * DEG);
}

/* A clip of `frames` frames holding the skeleton's rest pose. */
static inline rf_animation *fx_rest_clip(const rf_skeleton *s, uint32_t frames, double fps)
{
    rf_animation *a = rf_animation_new(s->joint_count, frames, fps);
    for (uint32_t f = 0; f < frames; f++)
        for (uint32_t j = 0; j < s->joint_count; j++) {
            rf_animation_set_rotation(a, f, j, s->joints[j].rest.r);
            rf_animation_set_translation(a, f, j, s->joints[j].rest.t);
        }
    for (uint32_t j = 0; j < s->joint_count; j++)
        a->channels[j] = RF_CHANNEL_ROTATION;
    return a;
}

/* World transforms of frame f of a clip. */
static inline void fx_world(const rf_skeleton *s, const rf_animation *a, uint32_t f,
                            rf_xform *world)
{
    for (uint32_t j = 0; j < s->joint_count; j++) {
        rf_xform x = {rf_animation_translation(a, f, j),
                      rf_quat_normalize(rf_animation_rotation(a, f, j)), s->joints[j].rest.s};
        int32_t p = s->joints[j].parent;
        world[j] = p < 0 ? x : rf_xform_mul(world[p], x);
    }
}

/* A mapping onto `target_n` joints with no inputs. */
static inline rf_mapping *fx_mapping(uint32_t target_n, uint32_t sources)
{
    return rf_mapping_new(target_n, sources);
}

/* Adds an input to target joint t. */
static inline void fx_map(rf_mapping *m, uint32_t t, uint32_t source, uint32_t joint, float weight,
                          float delay, uint32_t flags)
{
    rf_map_entry *e = &m->entries[t];
    e->inputs = realloc(e->inputs, (e->input_count + 1) * sizeof *e->inputs);
    e->inputs[e->input_count++] = (rf_map_input){source, joint, weight, delay, flags};
}

/* Maps target joint i from source joint i for every i < n (identical layouts). */
static inline void fx_map_same(rf_mapping *m, uint32_t n)
{
    for (uint32_t j = 0; j < n; j++)
        fx_map(m, j, 0, j, 1, 0, 0);
}

/* Angle in degrees between two vectors. */
static inline double fx_angle(rf_vec3 a, rf_vec3 b)
{
    return rf_v3_angle(a, b) / DEG;
}

#endif
