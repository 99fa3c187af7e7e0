/* rerig: a rigged model's skeleton laid out again in other conventions, its mesh and skin kept, for
 * testing the matcher and the retarget on layouts the artist did not choose.
 *
 *   rerig [--seed N] [--no-helpers] [--no-split] [--no-frames] IN OUT.glb
 *
 * The layout of tests/match/gen.c's conventions, on a real character:
 *   - a ground root at the model's origin above the old roots, and an IK target at each of the
 *     two lowest leaves (the feet) with a pole in front of it, hung from the ground root and
 *     weighted nowhere (helper bones);
 *   - every long bone (a joint with one child, longer than 12% of the longest edge of the
 *     joints' box) split in two by a joint at its middle, which takes the bone's weights
 *     smoothly from none on its near third to all on its far third (an extra spine joint);
 *   - every joint's frame turned so its local +Y runs along its bone, twisted about it at random
 *     (Blender's convention), the inverse binds following: the mesh at rest is unchanged.
 * --no-helpers, --no-split and --no-frames leave out one change each, to tell which one a
 * difference comes from. A line says what changed. Exit status 0, 1 when IN cannot be read or OUT
 * written, 2 on a usage error. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <rigflow/aimport.h>
#include <rigflow/gltf-write.h>
#include <rigflow/model-copy.h>

#define RR_SPLIT 0.12 /* of the skeleton's size: a bone longer than this is split */

typedef struct rr_joint {
    int32_t parent;
    rf_vec3 pos;
    rf_quat rot;
    char *name;
    int32_t from; /* the old joint it is, or -1 for a new one */
} rr_joint;

typedef struct rr_build {
    rr_joint *j;
    uint32_t n;
    int32_t *to_new; /* [old] new index */
    int32_t *mid;    /* [old] the joint splitting its bone, or -1 */
    uint64_t rng;
    bool helpers, split, frames;
} rr_build;

static double rr_rnd(rr_build *b)
{
    b->rng ^= b->rng >> 12, b->rng ^= b->rng << 25, b->rng ^= b->rng >> 27;
    return (double)((b->rng * 2685821657736338717ULL) >> 11) / 9007199254740992.0;
}

static uint32_t rr_add(rr_build *b, int32_t parent, rf_vec3 pos, const char *name, int32_t from)
{
    rr_joint *j = &b->j[b->n];
    j->parent = parent, j->pos = pos, j->rot = rf_quat_identity(), j->from = from;
    j->name = rf_strdup(name);
    return b->n++;
}

/* The one child of old joint i, or -1 when it has none or several. */
static int32_t rr_only_child(const rf_skeleton *s, uint32_t i)
{
    int32_t only = -1;
    for (uint32_t k = i + 1; k < s->joint_count; k++)
        if (s->joints[k].parent == (int32_t)i) {
            if (only >= 0)
                return -1;
            only = (int32_t)k;
        }
    return only;
}

/* Whether old joint i has no child. */
static bool rr_leaf(const rf_skeleton *s, uint32_t i)
{
    for (uint32_t k = i + 1; k < s->joint_count; k++)
        if (s->joints[k].parent == (int32_t)i)
            return false;
    return true;
}

/* The ground root, the old joints (each long bone split), then the helpers at the two lowest
 * leaves; returns how many bones were split. */
static uint32_t rr_layout(rr_build *b, const rf_skeleton *s, const rf_vec3 *p, rf_vec3 up)
{
    double lo = INFINITY, hi = -INFINITY, size = 0;
    rf_vec3 bmin = p[0], bmax = p[0];
    for (uint32_t i = 0; i < s->joint_count; i++) {
        lo = fmin(lo, rf_v3_dot(p[i], up)), hi = fmax(hi, rf_v3_dot(p[i], up));
        bmin = rf_v3(fmin(bmin.x, p[i].x), fmin(bmin.y, p[i].y), fmin(bmin.z, p[i].z));
        bmax = rf_v3(fmax(bmax.x, p[i].x), fmax(bmax.y, p[i].y), fmax(bmax.z, p[i].z));
    }
    size = fmax(bmax.x - bmin.x, fmax(bmax.y - bmin.y, bmax.z - bmin.z));
    int32_t ground = b->helpers ? (int32_t)rr_add(b, -1, rf_v3(0, 0, 0), "rerig_ground", -1) : -1;
    uint32_t split = 0;
    char name[64];
    for (uint32_t i = 0; i < s->joint_count; i++) {
        int32_t op = s->joints[i].parent;
        int32_t parent = op < 0 ? ground : b->mid[op] >= 0 ? b->mid[op] : b->to_new[op];
        b->to_new[i] = (int32_t)rr_add(b, parent, p[i], s->joints[i].name, (int32_t)i);
        int32_t c = rr_only_child(s, i);
        b->mid[i] = -1;
        if (b->split && c >= 0 && rf_v3_dist(p[i], p[c]) > RR_SPLIT * size) {
            snprintf(name, sizeof name, "rerig_mid_%u", i);
            b->mid[i] = (int32_t)rr_add(b, b->to_new[i], rf_v3_lerp(p[i], p[c], 0.5), name, -1);
            split++;
        }
    }
    int32_t feet[2] = {-1, -1};
    for (uint32_t i = 0; i < s->joint_count; i++) {
        if (!rr_leaf(s, i))
            continue;
        if (feet[0] < 0 || rf_v3_dot(p[i], up) < rf_v3_dot(p[feet[0]], up))
            feet[1] = feet[0], feet[0] = (int32_t)i;
        else if (feet[1] < 0 || rf_v3_dot(p[i], up) < rf_v3_dot(p[feet[1]], up))
            feet[1] = (int32_t)i;
    }
    for (int f = 0; f < 2 && feet[f] >= 0 && b->helpers; f++) {
        snprintf(name, sizeof name, "rerig_ik_%d", f);
        rr_add(b, ground, p[feet[f]], name, -1);
        snprintf(name, sizeof name, "rerig_pole_%d", f);
        rr_add(b, ground, rf_v3_add(p[feet[f]], rf_v3_scale(up, 0.3 * (hi - lo))), name, -1);
    }
    return split;
}

/* Each joint's frame along its bone (local +Y to its first child), twisted at random; a leaf
 * keeps its parent's frame, the ground root and the helpers none. */
static void rr_frames(rr_build *b, const rf_xform *w)
{
    for (uint32_t i = 0; i < b->n; i++) {
        if (!b->frames) { /* the old joints' own frames; a splitting joint takes its parent's */
            b->j[i].rot = b->j[i].from >= 0     ? w[b->j[i].from].r
                          : b->j[i].parent >= 0 ? b->j[b->j[i].parent].rot
                                                : rf_quat_identity();
            continue;
        }
        int32_t child = -1;
        for (uint32_t k = i + 1; k < b->n && child < 0; k++)
            if (b->j[k].parent == (int32_t)i)
                child = (int32_t)k;
        if (b->j[i].from < 0 && strncmp(b->j[i].name, "rerig_mid", 9))
            continue; /* ground root, helpers */
        rf_vec3 d = child >= 0 ? rf_v3_sub(b->j[child].pos, b->j[i].pos) : rf_v3(0, 0, 0);
        if (rf_v3_len(d) > 1e-9)
            b->j[i].rot = rf_quat_mul(rf_quat_from_two_vectors(rf_v3(0, 1, 0), rf_v3_normalize(d)),
                                      rf_quat_from_axis_angle(rf_v3(0, 1, 0), 6 * rr_rnd(b) - 3));
        else if (b->j[i].parent >= 0)
            b->j[i].rot = b->j[b->j[i].parent].rot;
    }
}

static rf_skeleton *rr_skeleton(const rr_build *b, const rf_skeleton *old)
{
    rf_skeleton *s = rf_skeleton_new(b->n);
    if (!s)
        return NULL;
    s->up = old->up, s->forward = old->forward;
    s->bind = calloc(b->n, sizeof *s->bind);
    s->rest_source = RF_REST_BIND;
    for (uint32_t i = 0; i < b->n; i++) {
        const rr_joint *j = &b->j[i];
        rf_joint *o = &s->joints[i];
        rf_xform w = {j->pos, j->rot, rf_v3(1, 1, 1)};
        rf_xform pw = rf_xform_identity();
        if (j->parent >= 0)
            pw = (rf_xform){b->j[j->parent].pos, b->j[j->parent].rot, rf_v3(1, 1, 1)};
        o->parent = j->parent;
        o->name = rf_strdup(j->name);
        o->rest = rf_xform_mul(rf_xform_invert(pw), w);
        if (j->from >= 0)
            o->flags = old->joints[j->from].flags & RF_JOINT_UNWEIGHTED;
        else if (strncmp(j->name, "rerig_mid", 9))
            o->flags = RF_JOINT_UNWEIGHTED;
        if (s->bind)
            s->bind[i] = o->rest;
    }
    return s;
}

/* How much of old joint i's weight at x its splitting joint takes: none on the bone's near
 * third, all on its far third, smoothly between (as an artist blends an extra spine joint). */
static double rr_far_share(const rr_build *b, const rf_skeleton *old, const rf_vec3 *p, uint32_t i,
                           rf_vec3 x)
{
    int32_t c = rr_only_child(old, i);
    if (b->mid[i] < 0 || c < 0)
        return 0;
    rf_vec3 d = rf_v3_sub(p[c], p[i]);
    double t = rf_v3_dot(rf_v3_sub(x, p[i]), d) / rf_v3_dot(d, d);
    t = fmin(1, fmax(0, (t - 1.0 / 3) * 3));
    return t * t * (3 - 2 * t);
}

/* The skin on the new joints: old joint i's weights to its new index, shared with the joint
 * splitting its bone along it (the four heaviest kept, renormalised); inverse binds of the new
 * frames. */
static bool rr_skin(const rr_build *b, const rf_skeleton *old, const rf_vec3 *p, rf_mesh *m)
{
    enum { K = RF_MESH_MAX_INFLUENCES };
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        const float *q = m->positions + (size_t)v * 3;
        rf_vec3 x = rf_v3(q[0], q[1], q[2]);
        uint16_t *jj = m->skin_joints + (size_t)v * K;
        float *ww = m->skin_weights + (size_t)v * K;
        uint16_t nj[2 * K] = {0};
        float nw[2 * K] = {0};
        int n = 0;
        for (int k = 0; k < K; k++) {
            if (jj[k] >= old->joint_count || !(ww[k] > 0))
                continue;
            double far = rr_far_share(b, old, p, jj[k], x);
            nj[n] = (uint16_t)b->to_new[jj[k]], nw[n++] = (float)(ww[k] * (1 - far));
            if (far > 0)
                nj[n] = (uint16_t)b->mid[jj[k]], nw[n++] = (float)(ww[k] * far);
        }
        for (int a = 1; a < n; a++) /* heaviest first */
            for (int c = a; c > 0 && nw[c - 1] < nw[c]; c--) {
                float tw = nw[c];
                uint16_t tj = nj[c];
                nw[c] = nw[c - 1], nj[c] = nj[c - 1], nw[c - 1] = tw, nj[c - 1] = tj;
            }
        float sum = 0;
        for (int k = 0; k < K && k < n; k++)
            sum += nw[k];
        for (int k = 0; k < K; k++) {
            jj[k] = k < n ? nj[k] : 0;
            ww[k] = k < n && sum > 0 ? nw[k] / sum : 0;
        }
    }
    free(m->inverse_bind);
    m->inverse_bind = calloc(b->n, sizeof *m->inverse_bind);
    if (!m->inverse_bind)
        return false;
    m->bind_count = b->n;
    for (uint32_t i = 0; i < b->n; i++) {
        rf_xform w = {b->j[i].pos, b->j[i].rot, rf_v3(1, 1, 1)};
        m->inverse_bind[i] = rf_xform_to_mat4(rf_xform_invert(w));
    }
    return true;
}

int main(int argc, char **argv)
{
    unsigned long long seed = 1;
    bool helpers = true, split = true, frames = true;
    int a = 1;
    for (; a < argc && argv[a][0] == '-'; a++) {
        char *end = NULL;
        if (strcmp(argv[a], "--seed") == 0 && a + 1 < argc)
            seed = strtoull(argv[++a], &end, 10);
        if (end && (*end || !*argv[a]))
            break;
        if (!end && !(strcmp(argv[a], "--no-helpers") == 0 && !(helpers = false)) &&
            !(strcmp(argv[a], "--no-split") == 0 && !(split = false)) &&
            !(strcmp(argv[a], "--no-frames") == 0 && !(frames = false)))
            break;
    }
    if (argc - a != 2) {
        fprintf(stderr,
                "usage: rerig [--seed N] [--no-helpers] [--no-split] [--no-frames] IN OUT.glb\n");
        return 2;
    }
    rf_ai_options o = {.rest = RF_AI_REST_BIND, .require_skeleton = true};
    rf_ai_result r;
    char err[1024] = "";
    if (!rf_ai_import(argv[a], &o, &r, NULL, NULL, err, sizeof err)) {
        fprintf(stderr, "rerig: %s\n", err);
        return 1;
    }
    rf_skeleton *old = r.skeleton;
    if (!r.mesh || !r.mesh->skin_joints || !old->joint_count) {
        fprintf(stderr, "rerig: %s: no skinned mesh\n", argv[a]);
        rf_ai_result_clear(&r);
        return 1;
    }
    uint32_t n = old->joint_count;
    rf_xform *w = calloc(n, sizeof *w);
    rf_vec3 *p = calloc(n, sizeof *p);
    rr_build b = {calloc(3 * n + 5, sizeof *b.j),
                  0,
                  calloc(n, sizeof *b.to_new),
                  calloc(n, sizeof *b.mid),
                  seed * 0x9E3779B97F4A7C15ULL + 3,
                  helpers,
                  split,
                  frames};
    rf_skeleton_world_rest(old, w);
    for (uint32_t i = 0; i < n; i++)
        p[i] = w[i].t;
    rf_vec3 up = rf_v3_len(old->up) > 0 ? old->up : rf_v3(0, 1, 0);
    uint32_t nsplit = rr_layout(&b, old, p, up);
    rr_frames(&b, w);
    rf_skeleton *s = rr_skeleton(&b, old);
    bool ok = s && rr_skin(&b, old, p, r.mesh) &&
              rf_gltf_write_file(argv[a + 1], NULL, s, NULL, r.mesh, NULL, err, sizeof err);
    if (ok)
        printf("%s: %u joints -> %u (%u bones split, %u new roots and helpers, frames %s)\n",
               argv[a], n, b.n, nsplit, b.n - n - nsplit, frames ? "along the bones" : "kept");
    else
        fprintf(stderr, "rerig: %s\n", err[0] ? err : "out of memory");
    for (uint32_t i = 0; i < b.n; i++)
        free(b.j[i].name);
    free(b.j), free(b.to_new), free(b.mid), free(w), free(p);
    rf_skeleton_free(s);
    rf_ai_result_clear(&r);
    return ok ? 0 : 1;
}
