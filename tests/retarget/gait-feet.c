/* gait-feet: how each leg's foot stands on the floor through a clip, as a person sees it.
 *
 *   gait-feet FILE [NEAR]
 *
 * FILE is an animated character (GLB, BVH, anything Assimp reads). Its legs are the skeleton
 * analysis's leg sections (limbs reaching the floor at rest), fore or hind by where they hang
 * along the body when they hang far apart (else "leg"), as the analysis reads the file's facing
 * (it reads some exported quadrupeds back to front: the first joint named beside says which). A leg
 * is what it carries: with a skinned mesh (what render-frames draws) the vertices whose largest
 * weight lies on its joints (its feet and toes included), its height the lowest of them over the
 * mesh's lowest vertex at rest; for a skeleton alone (a BVH, whose rest hangs from the origin) its
 * joints, over the 5th percentile through the clip of the body's lowest joint. Heights are in
 * percent of the rest height. Its foot is its point lowest at rest (the sole), followed through the
 * clip. Prints per leg: its role, side and first joint, the least and the median height, the share
 * of frames within NEAR percent (default 3) of the floor, and the leg's tilt: the angle between
 * straight down and the line from its first joint to its foot, the median and the 90th percentile
 * over frames, in degrees. A leg folded flat forward or held level tilts 60-90 degrees; one that
 * walks swings some 30 either way of down and has its foot on the floor part of the cycle. Last,
 * how fast the sole slides along the floor between frames when the leg is down (within NEAR), in
 * percent of the height per second. Exit 0, or 1 with a message on bad input. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "rigflow/aimport.h"
#include "rigflow/analysis.h"
#include "rigflow/bvh.h"
#include "rigflow/text.h"

#define GF_MAX_LEGS 64

typedef struct gf_char {
    rf_skeleton *skel;
    rf_animation *anim;
    rf_mesh *mesh; /* skinned to skel, or NULL */
} gf_char;

/* The first influence of a weight over 0 naming a joint past the mesh's bind matrices, or
 * SIZE_MAX (also without a mesh). */
static size_t gf_stray_joint(const rf_mesh *m)
{
    for (size_t k = 0; m && k < (size_t)m->vertex_count * RF_MESH_MAX_INFLUENCES; k++)
        if (m->skin_weights[k] > 0 && m->skin_joints[k] >= m->bind_count)
            return k;
    return SIZE_MAX;
}

static bool gf_load(const char *path, gf_char *c, char *err, size_t n)
{
    memset(c, 0, sizeof *c);
    const char *ext = strrchr(path, '.');
    if (ext && strcasecmp(ext, ".bvh") == 0)
        return rf_bvh_read_file(path, NULL, &c->skel, &c->anim, err, n);
    rf_ai_result r;
    if (!rf_ai_import(path, NULL, &r, NULL, NULL, err, n))
        return false;
    c->skel = r.skeleton, c->anim = r.animation;
    if (r.mesh && r.mesh->skin_weights && r.mesh->inverse_bind &&
        r.mesh->bind_count == r.skeleton->joint_count)
        c->mesh = r.mesh, r.mesh = NULL;
    r.skeleton = NULL, r.animation = NULL;
    rf_ai_result_clear(&r);
    /* rf_mesh_skin_vertex reads a skinning matrix for every joint a vertex names */
    size_t bad = gf_stray_joint(c->mesh);
    if (bad != SIZE_MAX)
        snprintf(err, n, "%s: vertex %zu is skinned to joint %u of a skeleton of %u", path,
                 bad / RF_MESH_MAX_INFLUENCES, (unsigned)c->mesh->skin_joints[bad],
                 c->mesh->bind_count);
    return bad == SIZE_MAX;
}

/* [joint] the leg (index into legs, leg sections) whose section or hanging sections hold it,
 * or -1. */
static int32_t *gf_leg_of(const rf_analysis *a, const uint32_t *legs, uint32_t nlegs)
{
    int32_t *of = malloc((a->joint_count ? a->joint_count : 1) * sizeof *of);
    for (uint32_t j = 0; of && j < a->joint_count; j++) {
        of[j] = -1;
        for (int32_t s = a->joints[j].section; s >= 0 && of[j] < 0; s = a->sections[s].parent)
            for (uint32_t l = 0; l < nlegs; l++)
                if (legs[l] == (uint32_t)s)
                    of[j] = (int32_t)l;
    }
    return of;
}

static int gf_cmp(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

/* The heights in pose `world`: per leg its lowest point into low[leg] and where its foot is
 * (foot[leg]: the vertex or joint of the leg lowest at rest, see gf_feet) into lowp[leg]; the
 * body's lowest into *body and highest into *top (mesh vertices, else joints). */
static void gf_pose(const gf_char *c, const rf_analysis *a, const int32_t *leg_of,
                    const rf_xform *world, rf_mat4 *skin, uint32_t nlegs, int32_t *foot,
                    double *low, rf_vec3 *lowp, double *body, double *top)
{
    const rf_skeleton *s = c->skel;
    for (uint32_t l = 0; l < nlegs; l++)
        low[l] = INFINITY, lowp[l] = rf_v3(0, 0, 0);
    *body = INFINITY, *top = -INFINITY;
    if (c->mesh)
        rf_skin_matrices(world, c->mesh->inverse_bind, s->joint_count, skin);
    uint32_t count = c->mesh ? c->mesh->vertex_count : s->joint_count;
    for (uint32_t i = 0; i < count; i++) {
        rf_vec3 p = c->mesh ? rf_mesh_skin_vertex(c->mesh, skin, i) : world[i].t;
        uint32_t j = c->mesh ? rf_mesh_heaviest_joint(c->mesh, i) : i;
        double h = rf_v3_dot(p, a->up);
        *body = fmin(*body, h), *top = fmax(*top, h);
        int32_t l = j < s->joint_count ? leg_of[j] : -1;
        if (l >= 0 && h < low[l])
            low[l] = h;
        if (l >= 0 && foot[l] == (int32_t)i)
            lowp[l] = p;
    }
}

/* Each leg's foot: the index (vertex, or joint without a mesh) of its lowest point at rest, whose
 * height is low[leg] (gf_pose in the rest pose). */
static void gf_feet(const gf_char *c, const rf_analysis *a, const int32_t *leg_of,
                    const rf_xform *world, uint32_t nlegs, const double *low, int32_t *foot)
{
    uint32_t count = c->mesh ? c->mesh->vertex_count : c->skel->joint_count;
    rf_mat4 *skin = malloc(c->skel->joint_count * sizeof *skin);
    if (skin && c->mesh)
        rf_skin_matrices(world, c->mesh->inverse_bind, c->skel->joint_count, skin);
    for (uint32_t i = 0; skin && i < count; i++) {
        uint32_t j = c->mesh ? rf_mesh_heaviest_joint(c->mesh, i) : i;
        int32_t l = j < c->skel->joint_count ? leg_of[j] : -1;
        rf_vec3 p = c->mesh ? rf_mesh_skin_vertex(c->mesh, skin, i) : world[i].t;
        if (l >= 0 && l < (int32_t)nlegs && foot[l] < 0 && rf_v3_dot(p, a->up) <= low[l])
            foot[l] = (int32_t)i;
    }
    free(skin);
}

static void gf_world(const gf_char *c, uint32_t frame, rf_xform *local, rf_xform *world)
{
    rf_animation_local_pose(c->anim, c->skel, frame, local);
    for (uint32_t j = 0; j < c->skel->joint_count; j++) {
        int32_t p = c->skel->joints[j].parent;
        world[j] = p < 0 ? local[j] : rf_xform_mul(world[p], local[j]);
    }
}

/* Degrees between straight down and the line from leg section s's first joint to `foot`. */
static double gf_tilt(const rf_analysis *a, uint32_t s, const rf_xform *world, rf_vec3 foot)
{
    rf_vec3 d = rf_v3_sub(foot, world[rf_section_joints(a, s)[0]].t);
    return rf_v3_len2(d) > 0 ? rf_v3_angle(d, rf_v3_scale(a->up, -1)) * 180 / RF_PI : 0;
}

/* The mean horizontal speed of the sole (sole[frames]) between frames when the leg is down
 * (heights `col` within `near`), in percent of the height per second. */
static double gf_skate(const gf_char *c, const rf_analysis *a, const rf_vec3 *sole,
                       const double *col, uint32_t frames, double near, double height)
{
    double sum = 0;
    uint32_t count = 0;
    for (uint32_t f = 1; f < frames; f++) {
        if (col[f] > near || col[f - 1] > near)
            continue;
        rf_vec3 d = rf_v3_sub(sole[f], sole[f - 1]);
        d = rf_v3_sub(d, rf_v3_scale(a->up, rf_v3_dot(d, a->up)));
        sum += rf_v3_len(d) * c->anim->fps, count++;
    }
    return count ? 100.0 * sum / count / height : 0;
}

static void gf_print(const gf_char *c, const rf_analysis *a, const uint32_t *legs, uint32_t nlegs,
                     uint32_t l, double *col, uint32_t frames, double near, double *tilt,
                     double skate)
{
    double blo = INFINITY, bhi = -INFINITY;
    for (uint32_t i = 0; i < nlegs; i++)
        blo = fmin(blo, a->sections[legs[i]].body_pos),
        bhi = fmax(bhi, a->sections[legs[i]].body_pos);
    const rf_section *sec = &a->sections[legs[l]];
    uint32_t down = 0;
    for (uint32_t f = 0; f < frames; f++)
        down += col[f] <= near;
    qsort(col, frames, sizeof *col, gf_cmp);
    qsort(tilt, frames, sizeof *tilt, gf_cmp);
    const char *role = bhi - blo <= 0.3                     ? "leg"
                       : sec->body_pos >= 0.5 * (blo + bhi) ? "fore"
                                                            : "hind";
    char name[256];
    rf_joint_label(c->skel, rf_section_joints(a, legs[l])[0], name, sizeof name);
    printf("%s %s (%s): foot least %.1f%%, median %.1f%%, within %.1f%% of the floor in %.0f%% of "
           "frames; tilt %.0f deg (p90 %.0f); sliding while down %.1f%%/s\n",
           role, rf_side_name(sec->side), name, col[0], col[frames / 2], near,
           100.0 * down / frames, tilt[frames / 2], tilt[frames - 1 - frames / 10], skate);
}

static bool gf_report(const gf_char *c, const rf_analysis *a, const uint32_t *legs, uint32_t nlegs,
                      double near)
{
    uint32_t n = c->skel->joint_count, frames = c->anim->frame_count, w = nlegs + 1;
    int32_t *leg_of = gf_leg_of(a, legs, nlegs);
    rf_xform *local = malloc(n * sizeof *local), *world = malloc(n * sizeof *world);
    rf_mat4 *skin = malloc(n * sizeof *skin);
    double *low = malloc((size_t)frames * w * sizeof *low), *col = malloc(frames * sizeof *col);
    double *tilt = malloc((size_t)frames * nlegs * sizeof *tilt);
    rf_vec3 *sole = malloc((size_t)frames * nlegs * sizeof *sole);
    rf_vec3 lowp[GF_MAX_LEGS];
    int32_t foot[GF_MAX_LEGS];
    bool ok = leg_of && local && world && skin && low && col && tilt && sole;
    double body, top, floor = 0;
    if (ok) {
        rf_skeleton_world_rest(c->skel, world);
        for (uint32_t l = 0; l < nlegs; l++)
            foot[l] = -1;
        gf_pose(c, a, leg_of, world, skin, nlegs, foot, low, lowp, &floor, &top);
        gf_feet(c, a, leg_of, world, nlegs, low, foot);
        double height = c->mesh ? top - floor : a->height;
        for (uint32_t f = 0; f < frames; f++) {
            gf_world(c, f, local, world);
            gf_pose(c, a, leg_of, world, skin, nlegs, foot, &low[(size_t)f * w + 1], lowp, &body,
                    &top);
            low[(size_t)f * w] = body;
            for (uint32_t l = 0; l < nlegs; l++) {
                tilt[(size_t)l * frames + f] = gf_tilt(a, legs[l], world, lowp[l]);
                sole[(size_t)l * frames + f] = lowp[l];
            }
        }
        if (!c->mesh) { /* the floor a skeleton alone stands on through its clip */
            for (uint32_t f = 0; f < frames; f++)
                col[f] = low[(size_t)f * w];
            qsort(col, frames, sizeof *col, gf_cmp);
            floor = col[(size_t)(0.05 * (frames - 1))];
        }
        for (uint32_t l = 0; l < nlegs; l++) {
            for (uint32_t f = 0; f < frames; f++)
                col[f] = 100.0 * (low[(size_t)f * w + 1 + l] - floor) / height;
            double skate = gf_skate(c, a, &sole[(size_t)l * frames], col, frames, near, height);
            gf_print(c, a, legs, nlegs, l, col, frames, near, &tilt[(size_t)l * frames], skate);
        }
    }
    free(sole), free(tilt), free(col), free(low), free(skin), free(world), free(local),
        free(leg_of);
    return ok;
}

int main(int argc, char **argv)
{
    if (argc < 2 || argc > 3 || strcmp(argv[1], "--help") == 0) {
        fprintf(stderr, "usage: gait-feet FILE [NEAR]\n");
        return argc == 2 ? 0 : 1;
    }
    double near = argc == 3 ? atof(argv[2]) : 3.0;
    char err[1024];
    gf_char c;
    if (!gf_load(argv[1], &c, err, sizeof err)) {
        fprintf(stderr, "gait-feet: %s\n", err);
        return 1;
    }
    rf_analysis *a = rf_analyze(c.skel, NULL);
    uint32_t legs[GF_MAX_LEGS], nlegs = 0;
    for (uint32_t s = 0; a && s < a->section_count && nlegs < GF_MAX_LEGS; s++)
        if (a->sections[s].type == RF_SECTION_LEG)
            legs[nlegs++] = s;
    int rc = 0;
    if (!a || nlegs == 0 || !c.anim || c.anim->frame_count == 0) {
        fprintf(stderr, "gait-feet: %s: no legs or no clip\n", argv[1]);
        rc = 1;
    } else {
        printf("%u legs, %u frames (%s)\n", nlegs, c.anim->frame_count,
               c.mesh ? "skinned mesh" : "skeleton");
        if (!gf_report(&c, a, legs, nlegs, near)) {
            fprintf(stderr, "gait-feet: out of memory\n");
            rc = 1;
        }
    }
    rf_analysis_free(a);
    rf_mesh_free(c.mesh), rf_animation_free(c.anim), rf_skeleton_free(c.skel);
    return rc;
}
