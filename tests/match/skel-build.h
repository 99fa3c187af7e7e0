/* Hand-built skeletons for the matching tests: joints given by name, parent name and world
 * position, turned and scaled as a whole so one body can face any way. A joint whose name starts
 * with '.' is not a joint: it becomes its parent's end site (the tip of a leaf bone). */
#ifndef RF_TEST_SKEL_BUILD_H
#define RF_TEST_SKEL_BUILD_H

#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include <rigflow/model.h>

typedef struct sb_joint {
    const char *name;
    const char *parent; /* NULL for a root */
    double x, y, z;
    unsigned flags; /* rf_joint_flags, e.g. RF_JOINT_UNWEIGHTED */
} sb_joint;

static inline char *sb_strdup(const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = malloc(n);
    memcpy(d, s, n);
    return d;
}

/* Builds the skeleton with every world position p mapped to rot * (scale * p) + offset. Rest
 * rotations stay identity (as in BVH), so local translations are world offsets. */
static inline rf_skeleton *sb_build_xf(const sb_joint *js, size_t n, rf_quat rot, double scale,
                                       rf_vec3 offset)
{
    size_t count = 0;
    for (size_t i = 0; i < n; i++)
        count += js[i].name[0] != '.';
    rf_skeleton *s = rf_skeleton_new((uint32_t)count);
    int32_t *index = malloc(n * sizeof *index);
    rf_vec3 *world = malloc(n * sizeof *world);
    for (size_t i = 0, k = 0; i < n; i++) {
        world[i] = rf_v3_add(
            rf_quat_rotate(rot, rf_v3_scale(rf_v3(js[i].x, js[i].y, js[i].z), scale)), offset);
        int32_t p = -1;
        for (size_t q = 0; js[i].parent && q < i; q++)
            if (js[q].name[0] != '.' && strcmp(js[q].name, js[i].parent) == 0)
                p = (int32_t)q;
        if (js[i].name[0] == '.') {
            rf_joint *pj = &s->joints[index[p]];
            pj->flags |= RF_JOINT_HAS_END_SITE;
            pj->end_site = rf_v3_sub(world[i], world[p]);
            index[i] = -1;
            continue;
        }
        rf_joint *j = &s->joints[k];
        j->name = sb_strdup(js[i].name);
        j->parent = p >= 0 ? index[p] : -1;
        j->flags = js[i].flags;
        j->rest.t = p >= 0 ? rf_v3_sub(world[i], world[p]) : world[i];
        index[i] = (int32_t)k++;
    }
    free(index);
    free(world);
    return s;
}

static inline rf_skeleton *sb_build(const sb_joint *js, size_t n)
{
    return sb_build_xf(js, n, rf_quat_identity(), 1.0, rf_v3(0, 0, 0));
}

/* Index of the joint named `name` (the test fails on -1 through the caller's assert). */
static inline int32_t sb_find(const rf_skeleton *s, const char *name)
{
    return rf_skeleton_find(s, name);
}

/* A biped facing +Z with +Y up (left is +X): hips, spine, chest, neck, head, clavicles, arms
 * with a hand and two fingers, legs with a foot and toes. */
static const sb_joint sb_biped[] = {
    {"hips", NULL, 0, 1.00, 0, 0},
    {"spine", "hips", 0, 1.15, -0.01, 0},
    {"chest", "spine", 0, 1.35, -0.01, 0},
    {"neck", "chest", 0, 1.55, 0, 0},
    {"head", "neck", 0, 1.65, 0.02, 0},
    {".", "head", 0, 1.85, 0.03, 0},
    {"l_clavicle", "chest", 0.03, 1.50, 0, 0},
    {"l_arm", "l_clavicle", 0.18, 1.50, -0.02, 0},
    {"l_forearm", "l_arm", 0.46, 1.50, -0.04, 0},
    {"l_hand", "l_forearm", 0.72, 1.50, -0.02, 0},
    {"l_finger", "l_hand", 0.80, 1.50, -0.02, 0},
    {".", "l_finger", 0.88, 1.50, -0.02, 0},
    {"l_thumb", "l_hand", 0.76, 1.49, 0.03, 0},
    {".", "l_thumb", 0.80, 1.48, 0.07, 0},
    {"r_clavicle", "chest", -0.03, 1.50, 0, 0},
    {"r_arm", "r_clavicle", -0.18, 1.50, -0.02, 0},
    {"r_forearm", "r_arm", -0.46, 1.50, -0.04, 0},
    {"r_hand", "r_forearm", -0.72, 1.50, -0.02, 0},
    {"r_finger", "r_hand", -0.80, 1.50, -0.02, 0},
    {".", "r_finger", -0.88, 1.50, -0.02, 0},
    {"r_thumb", "r_hand", -0.76, 1.49, 0.03, 0},
    {".", "r_thumb", -0.80, 1.48, 0.07, 0},
    {"l_thigh", "hips", 0.10, 0.95, 0, 0},
    {"l_shin", "l_thigh", 0.10, 0.52, 0.03, 0},
    {"l_foot", "l_shin", 0.10, 0.08, 0, 0},
    {"l_toe", "l_foot", 0.10, 0.01, 0.13, 0},
    {".", "l_toe", 0.10, 0.0, 0.20, 0},
    {"r_thigh", "hips", -0.10, 0.95, 0, 0},
    {"r_shin", "r_thigh", -0.10, 0.52, 0.03, 0},
    {"r_foot", "r_shin", -0.10, 0.08, 0, 0},
    {"r_toe", "r_foot", -0.10, 0.01, 0.13, 0},
    {".", "r_toe", -0.10, 0.0, 0.20, 0},
};

/* A quadruped facing -Z with +Y up (left is -X): pelvis root, spine to the chest, neck and
 * head in front, a tail behind, four 4-bone legs (hind legs with a backward hock). */
static const sb_joint sb_quadruped[] = {
    {"pelvis", NULL, 0, 1.00, 0.50, 0},      {"spine1", "pelvis", 0, 1.05, 0.20, 0},
    {"spine2", "spine1", 0, 1.05, -0.10, 0}, {"chest", "spine2", 0, 1.00, -0.40, 0},
    {"neck", "chest", 0, 1.20, -0.60, 0},    {"head", "neck", 0, 1.35, -0.75, 0},
    {".", "head", 0, 1.30, -0.95, 0},        {"tail1", "pelvis", 0, 1.05, 0.60, 0},
    {"tail2", "tail1", 0, 1.00, 0.80, 0},    {"tail3", "tail2", 0, 0.90, 1.00, 0},
    {".", "tail3", 0, 0.80, 1.20, 0},        {"fl1", "chest", -0.15, 0.90, -0.40, 0},
    {"fl2", "fl1", -0.15, 0.50, -0.36, 0},   {"fl3", "fl2", -0.15, 0.10, -0.42, 0},
    {"fl4", "fl3", -0.15, 0.02, -0.50, 0},   {".", "fl4", -0.15, 0.0, -0.56, 0},
    {"fr1", "chest", 0.15, 0.90, -0.40, 0},  {"fr2", "fr1", 0.15, 0.50, -0.36, 0},
    {"fr3", "fr2", 0.15, 0.10, -0.42, 0},    {"fr4", "fr3", 0.15, 0.02, -0.50, 0},
    {".", "fr4", 0.15, 0.0, -0.56, 0},       {"hl1", "pelvis", -0.15, 0.90, 0.50, 0},
    {"hl2", "hl1", -0.15, 0.55, 0.40, 0},    {"hl3", "hl2", -0.15, 0.30, 0.55, 0},
    {"hl4", "hl3", -0.15, 0.03, 0.50, 0},    {".", "hl4", -0.15, 0.0, 0.44, 0},
    {"hr1", "pelvis", 0.15, 0.90, 0.50, 0},  {"hr2", "hr1", 0.15, 0.55, 0.40, 0},
    {"hr3", "hr2", 0.15, 0.30, 0.55, 0},     {"hr4", "hr3", 0.15, 0.03, 0.50, 0},
    {".", "hr4", 0.15, 0.0, 0.44, 0},
};

/* The general rigger's curve skeleton of greenman (a blob body with two stubby arms and no legs
 * or head of its own; positions as the rigger placed them, +Y up, facing +Z, left +X): the root
 * at the bottom of the belly, the chest above it, the right arm straight out from the chest, the
 * left one by a detour up the body first, so the arms' chains are the same length in joints but
 * not in bones, and their hands a hair apart in height. */
static const sb_joint sb_blob_rig[] = {
    {"root", NULL, -0.0567, 0.2977, 0.0141, 0},  {"chest", "root", -0.0567, 0.8367, 0.0141, 0},
    {"l0", "chest", 0.3351, 1.0910, -0.0031, 0}, {"l1", "l0", 0.3190, 1.1220, -0.0017, 0},
    {"l2", "l1", 0.9649, 0.8326, 0.0134, 0},     {"l3", "l2", 1.0224, 0.8132, 0.0124, 0},
    {"r0", "chest", -0.9649, 0.7804, 0.0134, 0}, {"r1", "r0", -1.0224, 0.7621, 0.0124, 0},
    {"r2", "r1", -1.0794, 0.7471, 0.0117, 0},    {"r3", "r2", -1.1340, 0.7294, 0.0102, 0},
};

#define SB_COUNT(a) (sizeof(a) / sizeof((a)[0]))

#endif
