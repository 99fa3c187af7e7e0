/* Joint roles (see analysis.h): which joints of a rigged character are body, which only place or
 * convert it, and which are IK targets, poles or other helpers, from skin weights, motion and
 * geometry. A name never counts: the same rig renamed gets the same roles. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rigflow/analysis.h"

const char *rf_joint_role_name(rf_joint_role role)
{
    static const char *const names[RF_ROLE_COUNT] = {"body",      "placement", "axis",
                                                     "ik-target", "ik-pole",   "helper"};
    return (unsigned)role < RF_ROLE_COUNT ? names[role] : "?";
}

void rf_joint_roles_free(rf_joint_roles *r)
{
    if (!r)
        return;
    free(r->role), free(r->body_joint), free(r->weighted), free(r->turned);
    free(r);
}

/* What the roles are found from, per joint. */
typedef struct roles_work {
    const rf_skeleton *s;
    uint32_t n;
    int32_t *parent;      /* sanitised: -1 or a smaller index */
    rf_vec3 *pos;         /* world rest pivots */
    const rf_analysis *a; /* bone tips */
    uint8_t *carries;     /* weighted, or a descendant is */
    uint8_t *w_above;     /* a proper ancestor is weighted */
    uint8_t *has_body;    /* a child carries body (the joint is inside a limb, not its end) */
    uint32_t *wcount;     /* weighted joints in the subtree */
    uint32_t wtotal;
    rf_vec3 up;
    double height, low; /* extent of the weighted pivots along up, their lowest height */
    bool have_clips;
} roles_work;

static void roles_weights(roles_work *w, const rf_mesh *mesh, uint8_t *weighted)
{
    const rf_skeleton *s = w->s;
    if (mesh && mesh->skin_joints && mesh->skin_weights) {
        uint32_t skinned = 0;
        memset(weighted, 0, w->n);
        for (size_t i = 0; i < (size_t)mesh->vertex_count * RF_MESH_MAX_INFLUENCES; i++)
            if (mesh->skin_weights[i] > 0 && mesh->skin_joints[i] < w->n &&
                !weighted[mesh->skin_joints[i]])
                weighted[mesh->skin_joints[i]] = 1, skinned++;
        if (skinned * 4 >= w->n)
            return;
    }
    /* A skin on fewer than a quarter of the joints (a mesh hung rigidly on a node or two, a
     * node tree with no skin) says nothing about which joints are body. */
    uint32_t skinned = 0;
    for (uint32_t j = 0; j < w->n; j++)
        skinned += !(s->joints[j].flags & RF_JOINT_UNWEIGHTED);
    for (uint32_t j = 0; j < w->n; j++)
        weighted[j] = skinned * 4 < w->n || !(s->joints[j].flags & RF_JOINT_UNWEIGHTED);
}

/* A joint is turned when some frame's rotation differs from the clip's first by more than a
 * quarter degree (files that key every joint repeat the rest in most of them). */
static void roles_motion(roles_work *w, const rf_animation *const *clips, uint32_t count,
                         uint8_t *turned)
{
    const double cos_half = cos(0.25 * RF_PI / 180.0 / 2.0);
    for (uint32_t c = 0; clips && c < count; c++) {
        const rf_animation *a = clips[c];
        if (!a || a->joint_count != w->n || !a->frame_count)
            continue;
        w->have_clips = true;
        for (uint32_t j = 0; j < w->n; j++) {
            rf_quat q0 = rf_quat_normalize(rf_animation_rotation(a, 0, j));
            for (uint32_t f = 1; !turned[j] && f < a->frame_count; f++) {
                double d = fabs(rf_quat_dot(q0, rf_quat_normalize(rf_animation_rotation(a, f, j))));
                turned[j] = isfinite(d) && d < cos_half;
            }
        }
    }
}

static bool roles_prepare(roles_work *w, const uint8_t *weighted)
{
    uint32_t n = w->n;
    size_t m = n ? n : 1;
    w->parent = malloc(m * sizeof *w->parent);
    w->pos = malloc(m * sizeof *w->pos);
    w->carries = calloc(m, 1), w->w_above = calloc(m, 1), w->has_body = calloc(m, 1);
    w->wcount = calloc(m, sizeof *w->wcount);
    rf_xform *world = malloc(m * sizeof *world);
    if (!w->parent || !w->pos || !w->carries || !w->w_above || !w->has_body || !w->wcount ||
        !world) {
        free(world);
        return false;
    }
    for (uint32_t j = 0; j < n; j++) {
        int32_t p = w->s->joints[j].parent;
        w->parent[j] = p >= 0 && (uint32_t)p < j ? p : -1;
        p = w->parent[j];
        world[j] = p < 0 ? w->s->joints[j].rest : rf_xform_mul(world[p], w->s->joints[j].rest);
        w->pos[j] = rf_v3_isfinite(world[j].t) ? world[j].t : rf_v3(0, 0, 0);
    }
    free(world);
    for (uint32_t j = n; j-- > 0;) {
        w->wcount[j] += weighted[j];
        w->wtotal += weighted[j];
        if (w->parent[j] >= 0)
            w->wcount[w->parent[j]] += w->wcount[j];
        w->carries[j] = w->carries[j] || weighted[j];
        if (w->parent[j] >= 0 && w->carries[j])
            w->carries[w->parent[j]] = 1, w->has_body[w->parent[j]] = 1;
    }
    for (uint32_t j = 0; j < n; j++) {
        int32_t p = w->parent[j];
        w->w_above[j] = p >= 0 && (w->w_above[p] || weighted[p]);
    }
    double hi = -INFINITY;
    w->low = INFINITY;
    for (uint32_t j = 0; j < n; j++) {
        if (!weighted[j])
            continue;
        double h = rf_v3_dot(w->pos[j], w->up);
        w->low = fmin(w->low, h), hi = fmax(hi, h);
    }
    w->height = hi > w->low ? hi - w->low : 1;
    if (!isfinite(w->low))
        w->low = 0;
    return true;
}

/* Whether the rest of joint j does more than move: a turn beyond a degree or a scale. */
static bool roles_converts(const rf_joint *jt)
{
    rf_quat r = rf_quat_normalize(jt->rest.r);
    rf_vec3 s = jt->rest.s;
    bool turns = fabs(r.w) < cos(0.5 * RF_PI / 180.0);
    bool scales = fabs(s.x - 1) > 1e-3 || fabs(s.y - 1) > 1e-3 || fabs(s.z - 1) > 1e-3;
    return turns || scales;
}

/* Whether the rest only swaps axes: a turn by quarter turns (every entry of its matrix 0 or +-1)
 * or a scale. An unweighted bone inside a limb at any other angle is a bone, not a conversion. */
static bool roles_swaps_axes(const rf_joint *jt)
{
    rf_vec3 s = jt->rest.s;
    if (fabs(s.x - 1) > 1e-3 || fabs(s.y - 1) > 1e-3 || fabs(s.z - 1) > 1e-3)
        return true;
    rf_mat4 m =
        rf_xform_to_mat4((rf_xform){rf_v3(0, 0, 0), rf_quat_normalize(jt->rest.r), rf_v3(1, 1, 1)});
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
            double v = fabs(m.m[c * 4 + r]);
            if (fmin(v, fabs(v - 1)) > 0.02)
                return false;
        }
    return true;
}

/* Whether j's pivot sits on its parent's or on every child's (a node inserted into a bone). */
static bool roles_coincident(const roles_work *w, uint32_t j)
{
    double eps = 1e-3 * w->height;
    int32_t p = w->parent[j];
    if (p >= 0 && rf_v3_dist(w->pos[j], w->pos[p]) <= eps)
        return true;
    bool any = false;
    for (uint32_t c = j + 1; c < w->n; c++) {
        if (w->parent[c] != (int32_t)j)
            continue;
        if (rf_v3_dist(w->pos[j], w->pos[c]) > eps)
            return false;
        any = true;
    }
    return any;
}

/* The role of an unweighted joint that carries body. */
static rf_joint_role roles_frame(const roles_work *w, uint32_t j, const uint8_t *turned)
{
    if (w->have_clips && turned[j])
        return RF_ROLE_BODY; /* it moves the body */
    bool above = !w->w_above[j];
    /* Above the body, a conversion carries all of it (a hip joint beside the torso carries one
     * leg); inside, it sits in a bone and only swaps axes or scales. */
    const rf_joint *jt = &w->s->joints[j];
    bool all = w->wcount[j] == w->wtotal;
    if (roles_converts(jt) && ((above && all) || (roles_coincident(w, j) && roles_swaps_axes(jt))))
        return RF_ROLE_AXIS;
    if (!above || (!all && w->parent[j] >= 0))
        return RF_ROLE_BODY; /* an unweighted joint of the body's own chain, or a limb's root
                              * beside the rest of the body */
    /* Without clips, only a root standing on the floor under the body is surely placement: an
     * unweighted pelvis at hip height moves the body in any clip. */
    bool on_floor = rf_v3_dot(w->pos[j], w->up) - w->low <= 0.1 * w->height;
    return w->have_clips || on_floor ? RF_ROLE_PLACEMENT : RF_ROLE_BODY;
}

/* Distance from p to the segment a-b. */
static double roles_seg_dist(rf_vec3 p, rf_vec3 a, rf_vec3 b)
{
    rf_vec3 ab = rf_v3_sub(b, a);
    double l2 = rf_v3_len2(ab), t = l2 > 0 ? rf_v3_dot(rf_v3_sub(p, a), ab) / l2 : 0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    return rf_v3_dist(p, rf_v3_add(a, rf_v3_scale(ab, t)));
}

/* The role of an unweighted joint carrying no body, and the body joint it belongs to. */
static rf_joint_role roles_helper(const roles_work *w, uint32_t j, const uint8_t *role,
                                  int32_t *body)
{
    int32_t near_piv = -1, near_seg = -1;
    double d_piv = INFINITY, d_seg = INFINITY;
    for (uint32_t b = 0; b < w->n; b++) {
        if (role[b] != RF_ROLE_BODY || !w->carries[b])
            continue;
        double d = rf_v3_dist(w->pos[j], w->pos[b]);
        if (d < d_piv)
            d_piv = d, near_piv = (int32_t)b;
        if (w->a && w->a->joint_count == w->n && rf_v3_isfinite(w->a->joints[b].tip)) {
            double ds = roles_seg_dist(w->pos[j], w->pos[b], w->a->joints[b].tip);
            if (ds < d_seg)
                d_seg = ds, near_seg = (int32_t)b;
        }
        if (d < d_seg)
            d_seg = d, near_seg = (int32_t)b;
    }
    *body = near_seg >= 0 ? near_seg : near_piv;
    if (near_piv < 0)
        return RF_ROLE_HELPER;
    bool own_parent = w->parent[j] == near_piv;
    /* Controls live outside the body's hierarchy; a joint hanging from a body joint (a socket in
     * a fist, a hat's anchor) is carried by it and is no pole. */
    int32_t jp = w->parent[j];
    bool outside = jp < 0 || role[jp] != RF_ROLE_BODY || !w->carries[jp];
    if (d_piv <= 0.03 * w->height && !own_parent) {
        *body = near_piv;
        return RF_ROLE_IK_TARGET;
    }
    int32_t np = w->parent[near_piv];
    bool middle = np >= 0 && role[np] == RF_ROLE_BODY && w->carries[np]; /* not a limb's root */
    if (d_seg > 0.05 * w->height && middle && outside) {
        *body = near_piv;
        return RF_ROLE_IK_POLE;
    }
    return RF_ROLE_HELPER;
}

static rf_joint_roles *roles_alloc(uint32_t n)
{
    rf_joint_roles *r = calloc(1, sizeof *r);
    size_t m = n ? n : 1;
    if (!r)
        return NULL;
    r->joint_count = n;
    r->role = calloc(m, 1), r->body_joint = malloc(m * sizeof *r->body_joint);
    r->weighted = calloc(m, 1), r->turned = calloc(m, 1);
    if (!r->role || !r->body_joint || !r->weighted || !r->turned) {
        rf_joint_roles_free(r);
        return NULL;
    }
    for (uint32_t j = 0; j < n; j++)
        r->body_joint[j] = -1;
    return r;
}

rf_joint_roles *rf_joint_roles_find(const rf_skeleton *s, const rf_mesh *mesh,
                                    const rf_animation *const *clips, uint32_t clip_count)
{
    uint32_t n = s ? s->joint_count : 0;
    rf_joint_roles *r = roles_alloc(n);
    if (!r || !n)
        return r;
    roles_work w = {.s = s, .n = n};
    rf_analysis *a = rf_analyze(s, NULL);
    if (!a) { /* out of memory: +y in place of the body's up would read other roles */
        rf_joint_roles_free(r);
        return NULL;
    }
    w.up = a->up;
    w.a = a;
    roles_weights(&w, mesh, r->weighted);
    roles_motion(&w, clips, clip_count, r->turned);
    bool ok = roles_prepare(&w, r->weighted);
    for (uint32_t j = 0; ok && j < n; j++)
        if (!r->weighted[j] && w.carries[j])
            r->role[j] = (uint8_t)roles_frame(&w, j, r->turned);
    for (uint32_t j = 0; ok && j < n; j++)
        if (!r->weighted[j] && !w.carries[j])
            r->role[j] = (uint8_t)roles_helper(&w, j, r->role, &r->body_joint[j]);
    free(w.parent), free(w.pos), free(w.carries), free(w.w_above), free(w.has_body);
    free(w.wcount);
    rf_analysis_free(a);
    if (!ok) {
        rf_joint_roles_free(r);
        return NULL;
    }
    return r;
}
