/* Set-up facts about each skeleton: which pose is its rest, world rests, bone tips, up and the
 * symmetry plane (from the skeleton analysis), leg lengths, floors and root scales. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rigflow/analysis.h"
#include "rt-internal.h"

/* The dominant direction of the bones of a pose, and the fraction of their summed length lying
 * along it (1: every bone on one line): the scatter matrix of the bone directions weighted by
 * length, by power iteration. Offsets from a root joint are placement, not bones. */
static double rt_collinearity(const rf_skeleton *s, const rf_xform *world, rf_vec3 *axis)
{
    double m[3][3] = {{0}}, trace = 0;
    for (uint32_t j = 0; j < s->joint_count; j++) {
        int32_t p = s->joints[j].parent;
        if (p < 0 || s->joints[p].parent < 0)
            continue;
        rf_vec3 d = rf_v3_sub(world[j].t, world[p].t);
        double len = rf_v3_len(d);
        if (!(len > 0) || !isfinite(len))
            continue;
        double v[3] = {d.x / len, d.y / len, d.z / len};
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++)
                m[r][c] += len * v[r] * v[c];
        trace += len;
    }
    if (!(trace > 0))
        return 0;
    double x[3] = {1, 0.7, 0.3}, lambda = 0;
    for (int it = 0; it < 64; it++) {
        double y[3] = {0};
        for (int r = 0; r < 3; r++)
            y[r] = m[r][0] * x[0] + m[r][1] * x[1] + m[r][2] * x[2];
        lambda = sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
        if (!(lambda > 0))
            return 0;
        for (int r = 0; r < 3; r++)
            x[r] = y[r] / lambda;
    }
    *axis = rf_v3(x[0], x[1], x[2]);
    return lambda / trace;
}

static uint32_t rt_leaf_count(const rf_skeleton *s)
{
    uint32_t leaves = 0;
    for (uint32_t j = 0; j < s->joint_count; j++) {
        bool has_child = false;
        for (uint32_t c = j + 1; c < s->joint_count && !has_child; c++)
            has_child = s->joints[c].parent == (int32_t)j;
        leaves += !has_child;
    }
    return leaves;
}

static void rt_world(const rf_skeleton *s, const rf_xform *local, rf_xform *world)
{
    for (uint32_t j = 0; j < s->joint_count; j++) {
        int32_t p = s->joints[j].parent;
        world[j] = p < 0 ? local[j] : rf_xform_mul(world[p], local[j]);
    }
}

/* A source's world pose from its local one, read in the target's frame (src->turn). */
static void rt_source_world(const rf_rt_src *src, const rf_xform *local, rf_xform *world)
{
    for (uint32_t j = 0; j < src->n; j++) {
        int32_t p = src->skel->joints[j].parent;
        world[j] = p < 0 ? rf_rt_source_root(src, local[j]) : rf_xform_mul(world[p], local[j]);
    }
}

/* A branched pose whose bones nearly all lie on one line across the up axis is no body (Maya
 * joint orients leave every bone along its local X at zero rotation). A straight chain (a fish,
 * a strip) may be straight, and a body with its limbs hanging along up (arms down) is a body. */
static bool rt_degenerate(const rf_skeleton *s, const rf_xform *world)
{
    rf_vec3 axis = rf_v3(0, 1, 0);
    rf_vec3 up = rf_v3_len2(s->up) > 0.5 ? rf_v3_normalize(s->up) : rf_v3(0, 1, 0);
    return rt_leaf_count(s) >= 3 && rt_collinearity(s, world, &axis) > 0.9 &&
           fabs(rf_v3_dot(axis, up)) < 0.7;
}

/* Tips (in each joint's local rest frame), up and the symmetry plane, from the analysis of the
 * skeleton posed in `local`. */
typedef struct rt_axes {
    rf_vec3 up, forward, left, center;
    double size;
    rf_vec3 own_up;      /* the analysis's up (from the limbs), whatever the file states */
    uint8_t *centerline; /* [n] or NULL: joints the analysis puts on the centerline */
    int32_t *logical;    /* [n] or NULL: parents in the analysed tree (a part hanging from a
                          * placement root or a root of its own, attached where it sits) */
    int32_t *mirror;     /* [n] or NULL: the joint mirrored across the symmetry plane, or -1 */
} rt_axes;

static bool rt_analyse(const rf_skeleton *s, const rf_xform *local, const rf_xform *world,
                       rf_vec3 *tip, rt_axes *axes)
{
    rf_skeleton copy = *s;
    rf_joint *joints = malloc((s->joint_count ? s->joint_count : 1) * sizeof *joints);
    if (!joints)
        return false;
    memcpy(joints, s->joints, s->joint_count * sizeof *joints);
    for (uint32_t j = 0; j < s->joint_count; j++)
        joints[j].rest = local[j];
    copy.joints = joints;
    if (RF_HAS_FIELD(s, rf_skeleton, bind))
        copy.bind = NULL; /* analyse this pose, not the bind pose */
    rf_analysis *a = rf_analyze(&copy, NULL);
    free(joints);
    if (!a)
        return false;
    for (uint32_t j = 0; j < s->joint_count; j++) {
        rf_vec3 d = rf_v3_sub(a->joints[j].tip, world[j].t);
        bool has = rf_v3_len(d) > 1e-9 * a->size && rf_v3_isfinite(d);
        rf_xform inv = rf_xform_invert(world[j]);
        tip[j] = has ? rf_v3_mul(inv.s, rf_quat_rotate(inv.r, d)) : rf_v3(0, 0, 0);
    }
    /* The file's axes when it states them; the analysis's otherwise. Left is rebuilt from the
     * chosen up and forward so the two always agree. A stated forward the analysis reads the
     * body facing against (its feet or its hierarchy outvote the file's one vote) gives way:
     * the matcher pairs sides as the analysis reads them, and a body turned by the file's
     * forward had each limb driven by the source's limb of the other side (a random dragon
     * saved facing -z in a glTF file, which states +z: its wings 140 and 164 degrees off the
     * walk's arms, turned over). */
    bool file_up = rf_v3_len2(s->up) > 0.5, file_fwd = rf_v3_len2(s->forward) > 0.5;
    axes->up = file_up ? rf_v3_normalize(s->up) : a->up;
    rf_vec3 fwd = file_fwd && rf_v3_dot(s->forward, a->forward) >= 0 ? s->forward : a->forward;
    fwd = rf_v3_normalize(rf_v3_sub(fwd, rf_v3_scale(axes->up, rf_v3_dot(fwd, axes->up))));
    if (rf_v3_len2(fwd) == 0)
        fwd = rf_v3_normalize(rf_v3_cross(rf_v3(1, 0, 0), axes->up));
    axes->forward = fwd;
    axes->left = rf_v3_normalize(rf_v3_cross(axes->up, fwd));
    axes->center = a->plane_point;
    axes->size = a->size > 0 ? a->size : 1;
    axes->own_up = a->up;
    for (uint32_t j = 0; axes->centerline && j < s->joint_count; j++)
        axes->centerline[j] = a->joints[j].side == RF_SIDE_CENTER;
    for (uint32_t j = 0; axes->logical && j < s->joint_count; j++)
        axes->logical[j] = a->joints[j].logical_parent;
    for (uint32_t j = 0; axes->mirror && j < s->joint_count; j++)
        axes->mirror[j] = a->joints[j].mirror;
    rf_analysis_free(a);
    return true;
}

/* The rotation whose columns are x, y, z (an orthonormal right-handed basis). */
static rf_quat rt_frame_rot(rf_vec3 x, rf_vec3 y, rf_vec3 z)
{
    rf_mat4 m = rf_mat4_identity();
    m.m[0] = x.x, m.m[1] = x.y, m.m[2] = x.z;
    m.m[4] = y.x, m.m[5] = y.y, m.m[6] = y.z;
    m.m[8] = z.x, m.m[9] = z.y, m.m[10] = z.z;
    rf_xform out;
    return rf_mat4_to_xform(m, &out) ? out.r : rf_quat_identity();
}

static bool rt_source_rest(rf_retarget *rt, rf_rt_src *src, char *err, size_t err_size)
{
    const rf_skeleton *s = src->skel;
    for (uint32_t j = 0; j < src->n; j++)
        src->rest_local[j] = s->joints[j].rest;
    rt_source_world(src, src->rest_local, src->rest_world);
    for (uint32_t j = 0; j < src->n; j++)
        src->skel_pos[j] = src->rest_world[j].t;
    int32_t frame = rt->opt.rest_frame;
    if (frame < 0 && rt_degenerate(s, src->rest_world) && src->anim->frame_count > 0)
        frame = 0;
    if (frame >= 0) {
        if ((uint32_t)frame >= src->anim->frame_count) {
            rf_rt_fail(err, err_size, "rest_frame %d is past the clip's %u frames", frame,
                       src->anim->frame_count);
            return false;
        }
        rf_animation_local_pose(src->anim, s, (uint32_t)frame, src->rest_local);
        for (uint32_t j = 0; j < src->n; j++)
            src->rest_local[j].r = rf_quat_normalize(src->rest_local[j].r);
        rt_source_world(src, src->rest_local, src->rest_world);
    }
    src->rest_frame = frame;
    return true;
}

bool rf_rt_sources_prepare(rf_retarget *rt, char *err, size_t err_size)
{
    for (uint32_t k = 0; k < rt->source_count; k++) {
        rf_rt_src *src = &rt->src[k];
        size_t n = src->n ? src->n : 1;
        src->turn = rf_quat_identity(); /* read in its own frame until the target's is known */
        src->rest_local = malloc(n * sizeof *src->rest_local);
        src->rest_world = malloc(n * sizeof *src->rest_world);
        src->skel_pos = malloc(n * sizeof *src->skel_pos);
        src->tip = calloc(n, sizeof *src->tip);
        src->need_pos = calloc(n, 1);
        src->parent = malloc(n * sizeof *src->parent);
        if (!src->rest_local || !src->rest_world || !src->skel_pos || !src->tip || !src->need_pos ||
            !src->parent) {
            rf_rt_fail(err, err_size, "out of memory");
            return false;
        }
        for (uint32_t j = 0; j < src->n; j++)
            src->parent[j] = src->skel->joints[j].parent;
        if (!rt_source_rest(rt, src, err, err_size))
            return false;
        rt_axes axes = {.centerline = NULL, .logical = NULL};
        if (!rt_analyse(src->skel, src->rest_local, src->rest_world, src->tip, &axes)) {
            rf_rt_fail(err, err_size, "out of memory");
            return false;
        }
        src->up = axes.up, src->forward = axes.forward, src->left = axes.left;
        src->center = axes.center, src->size = axes.size;
    }
    return true;
}

/* A skeleton of the target's body joints only: from[k] is the target joint of joint k, parent[k]
 * its parent (an index in the same list, always smaller), each at the same world rest. */
typedef struct rt_body_view {
    rf_skeleton skel;
    rf_joint *joints;
    rf_xform *local, *world;
    uint32_t *from;
} rt_body_view;

static void rt_body_view_free(rt_body_view *v)
{
    free(v->joints), free(v->local), free(v->world), free(v->from);
}

/* The body joints `from` (count of them, in an order where each parent in `bparent`, a target
 * joint or -1, comes first) as a skeleton. */
static bool rt_body_view_make(const rf_retarget *rt, const uint32_t *order, const int32_t *bparent,
                              uint32_t count, rt_body_view *v)
{
    const rf_skeleton *t = rt->target;
    int32_t *at = malloc(rt->n * sizeof *at);
    v->joints = malloc(count * sizeof *v->joints);
    v->local = malloc(count * sizeof *v->local), v->world = malloc(count * sizeof *v->world);
    v->from = malloc(count * sizeof *v->from);
    if (!at || !v->joints || !v->local || !v->world || !v->from) {
        free(at);
        return false;
    }
    for (uint32_t k = 0; k < count; k++)
        at[order[k]] = (int32_t)k;
    for (uint32_t k = 0; k < count; k++) {
        uint32_t j = order[k];
        int32_t p = bparent[j];
        v->from[k] = j;
        v->joints[k] = t->joints[j];
        v->joints[k].parent = p >= 0 ? at[p] : RF_RT_NONE;
        v->world[k] = rt->t_rest_world[j];
        v->local[k] = v->joints[k].rest =
            p >= 0 ? rf_xform_mul(rf_xform_invert(rt->t_rest_world[p]), v->world[k]) : v->world[k];
    }
    free(at);
    v->skel = *t;
    v->skel.joint_count = count, v->skel.joints = v->joints;
    if (RF_HAS_FIELD(t, rf_skeleton, bind))
        v->skel.bind = NULL;
    return true;
}

/* Orders the body joints so each comes after its parent in `bparent` (a parent that would come
 * after is dropped). */
static uint32_t rt_body_order(const rf_retarget *rt, int32_t *bparent, uint32_t *order)
{
    const uint8_t *role = rt->t_roles->role;
    uint8_t *placed = calloc(rt->n, 1);
    uint32_t count = 0, want = 0;
    if (!placed)
        return 0;
    for (uint32_t j = 0; j < rt->n; j++)
        want += role[j] == RF_ROLE_BODY;
    for (uint32_t pass = 0; count < want; pass++) {
        uint32_t before = count;
        for (uint32_t j = 0; j < rt->n; j++)
            if (role[j] == RF_ROLE_BODY && !placed[j] && (bparent[j] < 0 || placed[bparent[j]]))
                order[count++] = j, placed[j] = 1;
        if (count == before) /* a cycle: the rest hang from nothing */
            for (uint32_t j = 0; j < rt->n; j++)
                if (role[j] == RF_ROLE_BODY && !placed[j])
                    bparent[j] = RF_RT_NONE;
    }
    free(placed);
    return count;
}

/* Analyses one body view, results mapped back to the target's joints. */
static bool rt_body_analyse(rf_retarget *rt, rt_body_view *v, uint32_t count, rt_axes *axes)
{
    int32_t *logical = malloc(count * sizeof *logical), *mirror = malloc(count * sizeof *mirror);
    rf_vec3 *tip = calloc(count, sizeof *tip);
    uint8_t *center = calloc(count, 1);
    rt_axes ba = {.centerline = center, .logical = logical, .mirror = mirror};
    bool ok =
        logical && mirror && tip && center && rt_analyse(&v->skel, v->local, v->world, tip, &ba);
    for (uint32_t j = 0; ok && j < rt->n; j++) {
        rt->t_tip[j] = rf_v3(0, 0, 0), rt->t_centerline[j] = 0;
        rt->t_logical[j] = rt->target->joints[j].parent, rt->t_mirror[j] = RF_RT_NONE;
    }
    for (uint32_t k = 0; ok && k < count; k++) {
        uint32_t j = v->from[k];
        rt->t_tip[j] = tip[k], rt->t_centerline[j] = center[k];
        rt->t_logical[j] = logical[k] >= 0 ? (int32_t)v->from[logical[k]] : RF_RT_NONE;
        rt->t_mirror[j] = mirror[k] >= 0 ? (int32_t)v->from[mirror[k]] : RF_RT_NONE;
    }
    if (ok)
        *axes = (rt_axes){ba.up,     ba.forward,       ba.left,       ba.center,   ba.size,
                          ba.own_up, axes->centerline, axes->logical, axes->mirror};
    free(logical), free(mirror), free(tip), free(center);
    return ok;
}

/* The target analysed on its body alone: placement roots, axis nodes and helpers left out, each
 * body joint hung from its nearest body ancestor, then (a second time) a part hanging from no
 * body joint (a foot under a placement root, a leg that is a root of its own) hung from where
 * the first analysis attached it, always at the same world rest. The tips, axes and tree the
 * analysis finds are then the plain rig's however the body is rigged around: an IK rig's
 * placement root at the feet would otherwise hang from a knee by proximity and turn its tip,
 * and feet as roots change the rig's bone-axis vote. */
static bool rt_target_analyse(rf_retarget *rt, const rf_xform *local, rt_axes *axes)
{
    const rf_skeleton *t = rt->target;
    const uint8_t *role = rt->t_roles->role;
    uint32_t n = rt->n, nb = 0, roots = 0;
    for (uint32_t j = 0; j < n; j++)
        nb += role[j] == RF_ROLE_BODY;
    if (!nb || nb == n)
        return rt_analyse(t, local, rt->t_rest_world, rt->t_tip, axes);
    int32_t *bparent = malloc(n * sizeof *bparent);
    uint32_t *order = malloc(n * sizeof *order);
    bool ok = bparent && order;
    for (uint32_t j = 0; ok && j < n; j++) {
        int32_t p = t->joints[j].parent;
        while (p >= 0 && role[p] != RF_ROLE_BODY)
            p = t->joints[p].parent;
        bparent[j] = p;
        roots += role[j] == RF_ROLE_BODY && p < 0;
    }
    for (int pass = 0; ok && pass < (roots > 1 ? 2 : 1); pass++) {
        rt_body_view v = {0};
        uint32_t count = rt_body_order(rt, bparent, order);
        ok = count && rt_body_view_make(rt, order, bparent, count, &v) &&
             rt_body_analyse(rt, &v, count, axes);
        rt_body_view_free(&v);
        for (uint32_t j = 0; ok && pass == 0 && j < n; j++) /* roots hung where attached */
            if (role[j] == RF_ROLE_BODY && bparent[j] < 0 && rt->t_logical[j] >= 0 &&
                !rf_rt_carries(t, (int32_t)j, (uint32_t)rt->t_logical[j]))
                bparent[j] = rt->t_logical[j];
    }
    free(bparent), free(order);
    return ok;
}

/* Reads source `src` in the target's frame from now on: its rest, axes and every pose turned
 * (about the origin) by the inverse of the turn of the target's body frame (up, forward) onto
 * the source's. The clip then plays where the target faces, with the target's up: a target
 * turned by any angle with its axes gets the same motion turned, and the joints above its mapped
 * body (an unmapped root carrying skin) stay in line with the body they carry, where turning the
 * target onto the source's facing turned the mapped body alone (the general rigger's greenman
 * turned 30 degrees: stretch p99 18.1 -> 41.2% of the height, torn between its unmapped root
 * and its spine). Heights along up, lengths and angles are unchanged by the turn. */
static void rt_source_turn(const rf_retarget *rt, rf_rt_src *src)
{
    rf_quat ft = rt_frame_rot(rt->left, rt->up, rt->forward);
    rf_quat fs = rt_frame_rot(src->left, src->up, src->forward);
    rf_quat body = rt->t_degenerate ? rf_quat_identity() : rf_quat_mul(fs, rf_quat_conj(ft));
    src->turn = rf_quat_normalize(rf_quat_conj(body));
    for (uint32_t j = 0; j < src->n; j++) {
        src->rest_world[j] = rf_rt_source_root(src, src->rest_world[j]);
        src->skel_pos[j] = rf_quat_rotate(src->turn, src->skel_pos[j]);
    }
    src->up = rf_quat_rotate(src->turn, src->up);
    src->forward = rf_quat_rotate(src->turn, src->forward);
    src->left = rf_quat_rotate(src->turn, src->left);
    src->center = rf_quat_rotate(src->turn, src->center);
}

bool rf_rt_target_prepare(rf_retarget *rt, char *err, size_t err_size)
{
    const rf_skeleton *t = rt->target;
    size_t n = rt->n ? rt->n : 1;
    rf_xform *local = malloc(n * sizeof *local);
    rt->t_rest_world = malloc(n * sizeof *rt->t_rest_world);
    rt->t_tip = calloc(n, sizeof *rt->t_tip);
    rt->t_centerline = calloc(n, 1);
    rt->t_logical = malloc(n * sizeof *rt->t_logical);
    rt->t_mirror = malloc(n * sizeof *rt->t_mirror);
    if (!local || !rt->t_rest_world || !rt->t_tip || !rt->t_centerline || !rt->t_logical ||
        !rt->t_mirror) {
        free(local);
        rf_rt_fail(err, err_size, "out of memory");
        return false;
    }
    for (uint32_t j = 0; j < rt->n; j++)
        local[j] = t->joints[j].rest;
    rt_world(t, local, rt->t_rest_world);
    for (uint32_t j = 0; j < rt->n; j++)
        rt->t_mirror[j] = RF_RT_NONE;
    rt_axes axes = {
        .centerline = rt->t_centerline, .logical = rt->t_logical, .mirror = rt->t_mirror};
    rt->t_roles = rf_joint_roles_find(t, NULL, NULL, 0);
    bool ok = rt->t_roles && rt_target_analyse(rt, local, &axes);
    free(local);
    if (!ok) {
        rf_rt_fail(err, err_size, "out of memory");
        return false;
    }
    rt->up = axes.up, rt->forward = axes.forward, rt->left = axes.left;
    rt->center = axes.center, rt->size = axes.size, rt->t_own_up = axes.own_up;
    rt->t_degenerate = rt_degenerate(t, rt->t_rest_world);
    if (rt->t_degenerate && rf_v3_len2(t->up) < 0.5) {
        /* An analysis of a pose that is no body finds no up: the target will stand as the source
         * does, so it has the source's. */
        rt->up = rt->src[0].up, rt->forward = rt->src[0].forward, rt->left = rt->src[0].left;
    }
    for (uint32_t k = 0; k < rt->source_count; k++)
        rt_source_turn(rt, &rt->src[k]);
    return true;
}

/* ---- leg lengths and floors ---- */

/* A body standing on its trunk: hips no higher than this fraction of the rest's height over its
 * lowest point (a body without legs, or on stubs beside its bottom); a body on legs stands
 * with its hips higher. */
#define RT_TRUNK_HIPS 0.25

bool rf_rt_weights_known(const rf_skeleton *s)
{
    uint32_t weighted = 0;
    for (uint32_t j = 0; j < s->joint_count; j++)
        weighted += !(s->joints[j].flags & RF_JOINT_UNWEIGHTED);
    return weighted * 4 >= s->joint_count;
}

/* Whether a skin says which of s's joints carry it: s was bound to a mesh (it has a bind pose)
 * and its joints are marked as rf_rt_weights_known reads them. A BVH skeleton marks none
 * unweighted and was bound to nothing: its joints say nothing of a skin. */
static bool rt_skin_says(const rf_skeleton *s)
{
    return RF_HAS_FIELD(s, rf_skeleton, bind) && s->bind && rf_rt_weights_known(s);
}

bool rf_rt_span(const rf_skeleton *s, const rf_xform *world, const rf_vec3 *tip, rf_vec3 up,
                const uint8_t *skip, bool weighted, double *low, double *high)
{
    *low = INFINITY, *high = -INFINITY;
    bool known = weighted && rf_rt_weights_known(s);
    for (uint32_t j = 0; j < s->joint_count; j++) {
        if ((known && (s->joints[j].flags & RF_JOINT_UNWEIGHTED)) || (skip && skip[j]))
            continue;
        double h = rf_rt_height(up, world[j].t);
        *low = fmin(*low, h), *high = fmax(*high, h);
        if (rf_v3_len2(tip[j]) > 0) {
            h = rf_rt_height(up, rf_xform_point(world[j], tip[j]));
            *low = fmin(*low, h), *high = fmax(*high, h);
        }
    }
    return isfinite(*low) && isfinite(*high);
}

/* Lowest height along up of the joints of `s` posed in `world` and of their tips; unweighted
 * helpers (IK targets, sockets) and the joints in `above` (placement roots above the hips, may
 * be NULL) do not count (0 when none does). */
static double rt_lowest(const rf_skeleton *s, const rf_xform *world, const rf_vec3 *tip, rf_vec3 up,
                        const uint8_t *above)
{
    double low, high;
    return rf_rt_span(s, world, tip, up, above, true, &low, &high) ? low : 0;
}

/* The height of a rest from its lowest point to its highest (joints and bone tips). */
static double rt_extent(const rf_skeleton *s, const rf_xform *world, const rf_vec3 *tip, rf_vec3 up,
                        const uint8_t *above)
{
    double low, high;
    return rf_rt_span(s, world, tip, up, above, true, &low, &high) ? high - low : 0;
}

/* Whether joint j has children (parents given per joint). */
static bool rt_has_children(const rf_skeleton *s, const int32_t *parent, uint32_t j)
{
    for (uint32_t c = 0; c < s->joint_count; c++)
        if (parent[c] == (int32_t)j)
            return true;
    return false;
}

/* The joint whose height is the hip height: from j down while it has exactly one child besides
 * unweighted leaves (placement roots, armature nodes and ground roots sit above the hips; IK
 * targets and sockets hang from them). `parent` is the tree to walk: the file's, or the body
 * parents that carry a leg hanging elsewhere (a forest's, a placement root's) back to its hips.
 * Where the skin says which joints carry it, a joint that does is body, not placement, and the
 * walk stops there: a body with no legs (greenman's auto-rig: its bottom joint, then its chest
 * with the two arms) was read with its hips at the chest, its bottom above them, its "legs" from
 * the chest down to the hands' tips (0.018 units for 16.3 of CMU's), and the floor for parts that
 * are not feet at the hands' height: the parts pass held the hanging arms up there, and the arm
 * whose shoulder lies high in the body swung through the top of it. */
static uint32_t rt_hip_below(const rf_skeleton *s, const int32_t *parent, uint32_t j)
{
    bool known = rt_skin_says(s);
    for (int guard = 0; guard < 64 && !(known && !(s->joints[j].flags & RF_JOINT_UNWEIGHTED));
         guard++) {
        uint32_t only = 0, count = 0;
        for (uint32_t c = 0; c < s->joint_count; c++)
            if (parent[c] == (int32_t)j &&
                (!(s->joints[c].flags & RF_JOINT_UNWEIGHTED) || rt_has_children(s, parent, c)))
                only = c, count++;
        if (count != 1)
            break;
        j = only;
    }
    return j;
}

/* Marks the proper ancestors of `hip` in `above` ([joint_count], the caller's): placement, not
 * body. Where the skin says which joints carry it, an ancestor that does is body and stays
 * unmarked (huesitos' auto-rig stands on a stem hanging above its hips in the tree: its legs are
 * the hips' height over the stem's foot). */
static void rt_mark_above(const rf_skeleton *s, uint32_t hip, uint8_t *above)
{
    bool known = rt_skin_says(s);
    memset(above, 0, s->joint_count);
    for (int32_t p = s->joints[hip].parent; p >= 0; p = s->joints[p].parent)
        above[p] = !(known && !(s->joints[p].flags & RF_JOINT_UNWEIGHTED));
}

/* The source joint whose motion moves the root of the target (the first root-motion input from
 * source k), or -1. */
static int32_t rt_hip_of(const rf_retarget *rt, uint32_t k)
{
    for (uint32_t j = 0; j < rt->n; j++) {
        const rf_rt_tjoint *tj = &rt->tj[j];
        if (!tj->root_motion)
            continue;
        for (uint32_t i = 0; i < tj->input_count; i++)
            if (rt->in[tj->first_input + i].source == k)
                return (int32_t)rt->in[tj->first_input + i].joint;
    }
    return RF_RT_NONE;
}

static int32_t rt_target_hip(const rf_retarget *rt)
{
    for (uint32_t j = 0; j < rt->n; j++)
        if (rt->tj[j].root_motion)
            return (int32_t)j;
    return RF_RT_NONE;
}

/* Floor of a skeleton from its rest: a rest whose root sits at the origin carries no placement
 * (BVH files hang the body from the origin), so its floor is the origin's plane; any other rest
 * stands on its lowest point. */
static double rt_rest_floor(const rf_skeleton *s, const rf_xform *world, double lowest, double leg)
{
    if (s->joint_count && rf_v3_len(world[0].t) <= 1e-6 * fmax(leg, 1e-12))
        return 0;
    return lowest;
}

static int rt_cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The lowest height the clip's body reaches in most frames: the 5th percentile of per-frame
 * lowest points (over one frame in 16, at least 16 and at most 128, spread across the clip), so
 * that a stray frame does not lower the floor. */
static double rt_clip_floor(const rf_retarget *rt, uint32_t k, const uint8_t *above)
{
    const rf_rt_src *src = &rt->src[k];
    uint32_t frames = src->anim->frame_count, samples = frames / 16;
    samples = samples < 16 ? (frames < 16 ? frames : 16) : samples > 128 ? 128 : samples;
    double *low = malloc((samples ? samples : 1) * sizeof *low);
    rf_xform *local = malloc(src->n * sizeof *local), *world = malloc(src->n * sizeof *world);
    double result = 0;
    if (low && local && world && samples) {
        for (uint32_t i = 0; i < samples; i++) {
            uint32_t f = samples > 1 ? (uint32_t)((uint64_t)i * (frames - 1) / (samples - 1)) : 0;
            rf_animation_local_pose(src->anim, src->skel, f, local);
            rt_source_world(src, local, world);
            low[i] = rt_lowest(src->skel, world, src->tip, src->up, above);
        }
        qsort(low, samples, sizeof *low, rt_cmp_double);
        result = low[(uint32_t)(0.05 * (samples - 1))];
    }
    free(low), free(local), free(world);
    return result;
}

/* The source's leg when the joint that drives the target's root is not the source's hips: the
 * walk down from it ended on a limb's last joint (a target whose root maps to a source thigh
 * reads the toe's height above the other foot) or no higher than the lowest point. The height
 * then comes from the source's own hips, found from its root as for any skeleton, else half its
 * height. Read from the toe, or as one unit, it scaled the root motion by the file's units:
 * Bandai's walk, kick and run onto Testwuson moved ten to eighty times too far (floor p95 11,
 * 101 and 563% of the height). */
static double rt_own_leg(const rf_rt_src *src, uint32_t h, double lowest)
{
    double leg = rf_rt_height(src->up, src->rest_world[h].t) - lowest;
    if (leg > 0 && rt_has_children(src->skel, src->parent, h))
        return leg;
    uint32_t root = 0;
    while (root + 1 < src->n && src->parent[root] >= 0)
        root++;
    uint32_t own = rt_hip_below(src->skel, src->parent, root);
    double own_leg = rf_rt_height(src->up, src->rest_world[own].t) - lowest;
    if (own_leg > 0 && rt_has_children(src->skel, src->parent, own))
        return own_leg;
    if (leg > 0)
        return leg;
    leg = 0.5 * rt_extent(src->skel, src->rest_world, src->tip, src->up, NULL);
    return leg > 0 ? leg : 1;
}

static bool rt_source_ground(rf_retarget *rt, uint32_t k)
{
    rf_rt_src *src = &rt->src[k];
    src->above = malloc(src->n ? src->n : 1);
    if (!src->above)
        return false;
    int32_t hip = rt_hip_of(rt, k);
    uint32_t h = rt_hip_below(src->skel, src->parent, hip >= 0 ? (uint32_t)hip : 0);
    rt_mark_above(src->skel, h, src->above);
    double lowest = rt_lowest(src->skel, src->rest_world, src->tip, src->up, src->above);
    src->leg = rt_own_leg(src, h, lowest);
    src->lowest = lowest;
    src->on_legs =
        rf_rt_height(src->up, src->rest_world[h].t) - lowest >=
        RT_TRUNK_HIPS * rt_extent(src->skel, src->rest_world, src->tip, src->up, src->above);
    double clip = rt->opt.ground == RF_RT_GROUND_WORLD ? 0 : rt_clip_floor(rt, k, src->above);
    src->floor = src->stand = clip;
    if (rt->opt.ground != RF_RT_GROUND_AUTO)
        return true;
    /* The skeleton's own rest (not a frame used as rest) says where it stands. */
    rf_xform *world = malloc(src->n * sizeof *world);
    if (!world)
        return false;
    for (uint32_t j = 0; j < src->n; j++)
        world[j] = src->skel->joints[j].rest;
    rt_source_world(src, world, world);
    double rest = src->rest_frame < 0 ? lowest : clip;
    double floor = rt_rest_floor(src->skel, world, rest, src->leg);
    /* A clip whose feet stay away from the rest's floor has a floor of its own. */
    src->floor = fabs(clip - floor) <= 0.2 * src->leg ? floor : clip;
    /* Only the origin's plane is a convention; a rest standing on its lowest point measures it. */
    if (src->floor != floor || rf_v3_len(world[0].t) > 1e-6 * src->leg)
        src->stand = src->floor;
    free(world);
    return true;
}

void rf_rt_floors_measured(rf_retarget *rt)
{
    for (uint32_t k = 0; k < rt->source_count; k++)
        rt->src[k].floor = rt->src[k].stand;
}

double rf_rt_over_floor(const rf_retarget *rt, uint32_t k, const rf_xform *world, int32_t j)
{
    const rf_rt_src *src = &rt->src[k];
    double low = j >= 0 ? rf_rt_sole(src->skel, world, src->tip, src->up, (uint32_t)j)
                        : rt_lowest(src->skel, world, src->tip, src->up, src->above);
    return (low - src->floor) / src->leg;
}

/* The clearance of source 0 posed in `world` (rf_rt_clearance). */
static double rt_clear_of(const rf_retarget *rt, const rf_xform *world)
{
    double over = rf_rt_over_floor(rt, 0, world, -1);
    return isfinite(over) && over > 0 ? over * rt->leg_target : 0;
}

bool rf_rt_clearance(const rf_retarget *rt, double start, double fps, uint32_t count,
                     const uint32_t *frame, double *out)
{
    size_t m = rt->max_src_n ? rt->max_src_n : 1;
    rf_rt_source_pose pose[2];
    bool ok = true;
    for (int k = 0; k < 2; k++) {
        pose[k].local = malloc(m * sizeof *pose[k].local);
        pose[k].world = malloc(m * sizeof *pose[k].world);
        pose[k].rot = malloc(m * 4 * sizeof *pose[k].rot);
        pose[k].tr = malloc(m * 3 * sizeof *pose[k].tr);
        ok = ok && pose[k].local && pose[k].world && pose[k].rot && pose[k].tr;
    }
    uint32_t i = 0;
    for (; ok && i + 1 < count; i += 2) { /* two poses at once: rf_rt_source_world_two */
        double t[2] = {start + (frame ? frame[i] : i) / fps,
                       start + (frame ? frame[i + 1] : i + 1) / fps};
        rf_rt_source_world_two(rt, 0, t, pose, NULL);
        out[i] = rt_clear_of(rt, pose[0].world), out[i + 1] = rt_clear_of(rt, pose[1].world);
    }
    if (ok && i < count) {
        rf_rt_source_world(rt, 0, start + (frame ? frame[i] : i) / fps, pose[0].local,
                           pose[0].world, pose[0].rot, pose[0].tr);
        out[i] = rt_clear_of(rt, pose[0].world);
    }
    for (int k = 0; k < 2; k++)
        free(pose[k].local), free(pose[k].world), free(pose[k].rot), free(pose[k].tr);
    return ok;
}

/* The joints above the hips (rt->t_above) and those of limbs driven by the source's legs half a
 * cycle later (RF_RT_IN_PHASE): the legs in phase with the source say how long the target's legs
 * are. A Fox's foreleg laid along a human's straight leg reaches 4 units (of 31) lower than its
 * hind leg, and counted in it raised the Fox's root motion and its whole walk by as much. NULL
 * when there are none. */
static uint8_t *rt_phase_aside(const rf_retarget *rt)
{
    uint8_t *aside = NULL;
    for (uint32_t j = 0; j < rt->n; j++) {
        const rf_rt_tjoint *tj = &rt->tj[j];
        bool phase = false;
        for (uint32_t i = 0; tj->kind == RF_RT_MAPPED && i < tj->input_count; i++)
            phase = phase || (rt->in[tj->first_input + i].flags & RF_RT_IN_PHASE);
        if (phase && !aside && (aside = malloc(rt->n)))
            memcpy(aside, rt->t_above, rt->n);
        for (uint32_t c = j; phase && aside && c < rt->n; c++)
            aside[c] = aside[c] || rf_rt_carries(rt->target, (int32_t)j, c);
    }
    return aside;
}

/* The target posed in its aligned rest (each source at its rest): leg length and lowest point. */
static bool rt_target_leg(rf_retarget *rt, double *leg)
{
    uint32_t n = rt->n, slots = rt->slot_count;
    float *rot = malloc((size_t)(n ? n : 1) * 7 * sizeof *rot);
    float *srot = malloc((size_t)slots * (rt->max_src_n ? rt->max_src_n : 1) * 7 * sizeof *srot);
    rf_rt_pose *poses = malloc((slots ? slots : 1) * sizeof *poses);
    rf_xform *world = malloc((n ? n : 1) * sizeof *world);
    if (!rot || !srot || !poses || !world) {
        free(rot), free(srot), free(poses), free(world);
        return false;
    }
    for (uint32_t s = 0; s < slots; s++) {
        const rf_rt_src *src = &rt->src[rt->slots[s].source];
        float *r = srot + (size_t)s * rt->max_src_n * 7, *t = r + (size_t)rt->max_src_n * 4;
        for (uint32_t j = 0; j < src->n; j++) {
            rf_xform x = src->rest_local[j];
            r[j * 4] = (float)x.r.x, r[j * 4 + 1] = (float)x.r.y;
            r[j * 4 + 2] = (float)x.r.z, r[j * 4 + 3] = (float)x.r.w;
            t[j * 3] = (float)x.t.x, t[j * 3 + 1] = (float)x.t.y, t[j * 3 + 2] = (float)x.t.z;
        }
        poses[s].rotations = r, poses[s].translations = t;
    }
    rt->root_motion_on = false;
    rf_retarget_frame(rt, poses, rot, rot + (size_t)n * 4);
    rt->root_motion_on = true;
    rt->w0 = malloc((n ? n : 1) * sizeof *rt->w0); /* the aligned rest's world rotations */
    if (rt->w0)
        memcpy(rt->w0, rt->work.q, n * sizeof *rt->w0);
    for (uint32_t j = 0; j < n; j++) {
        const float *q = rot + j * 4, *t = rot + (size_t)n * 4 + j * 3;
        rf_xform x = {rf_v3(t[0], t[1], t[2]), rf_quat_make(q[0], q[1], q[2], q[3]),
                      rt->target->joints[j].rest.s};
        int32_t p = rt->target->joints[j].parent;
        world[j] = p < 0 ? x : rf_xform_mul(world[p], x);
    }
    int32_t hip = rt_target_hip(rt);
    uint32_t h = rt_hip_below(rt->target, rt->lparent, hip >= 0 ? (uint32_t)hip : 0);
    rt->t_hip = h;
    rt_mark_above(rt->target, h, rt->t_above);
    uint8_t *skip = rt_phase_aside(rt);
    double lowest = rt_lowest(rt->target, world, rt->t_tip, rt->up, skip ? skip : rt->t_above);
    free(skip);
    *leg = rf_rt_height(rt->up, world[h].t) - lowest;
    rt->aligned_low = lowest;
    rt->t_aligned = malloc((n ? n : 1) * sizeof *rt->t_aligned);
    for (uint32_t j = 0; rt->t_aligned && j < n; j++)
        rt->t_aligned[j] = world[j].t;
    free(rot), free(srot), free(poses), free(world);
    return rt->t_aligned && rt->w0;
}

/* An upright body standing on its trunk (greenman, legless or on stubs at its sides: hips under
 * a quarter of its height over its lowest point at rest) takes a source's lean eased as a body
 * of another plan does ("Body plans"), when the source stands on legs: a human leans its trunk
 * 30-60 degrees in a crouch and balances it over legs bent back; laid on a trunk standing on the
 * floor, the lean tipped the whole body forward, 54 degrees at most under CMU 01_01's jumps. The
 * top mapped centerline joints (the trunk, carrying the body) are eased; the centerline above
 * keeps its source's turns (eased too, greenman's auto-rig's worst part read 87.8% of its
 * height for 86.5). Their inputs are flagged RF_RT_IN_LEVEL after the plan (the aligned rest is
 * the same either way: at the source's rest there is no lean), and the frame's fast paths are
 * chosen again. */
static bool rt_trunk_lean(rf_retarget *rt, double lowest)
{
    if (rt->plan_differs || rt->t_degenerate || rt->t_hip >= rt->n || !rt->src[0].on_legs)
        return true; /* a source on its trunk too leans as such a body does */
    double height = rt_extent(rt->target, rt->t_rest_world, rt->t_tip, rt->up, rt->t_above);
    double hips = rf_rt_height(rt->up, rt->t_rest_world[rt->t_hip].t) - lowest;
    if (!(height > 0) || !(hips < RT_TRUNK_HIPS * height))
        return true;
    bool any = false;
    for (uint32_t j = 0; j < rt->n; j++) {
        const rf_rt_tjoint *tj = &rt->tj[j];
        for (uint32_t i = 0; rt->t_centerline[j] && tj->root_motion && i < tj->input_count; i++)
            rt->in[tj->first_input + i].flags |= RF_RT_IN_LEVEL, any = true;
    }
    return !any || rf_rt_hot_init(rt);
}

bool rf_rt_ground_prepare(rf_retarget *rt, char *err, size_t err_size)
{
    bool ok = true;
    for (uint32_t k = 0; k < rt->source_count; k++)
        ok = ok && rt_source_ground(rt, k);
    rt->t_above = malloc(rt->n ? rt->n : 1);
    if (!ok || !rt->t_above || !rt_target_leg(rt, &rt->leg_target)) {
        rf_rt_fail(err, err_size, "out of memory");
        return false;
    }
    if (!(rt->leg_target > 0)) {
        /* No legs (the hips are the body's lowest point: a blob, a fish): the source's legs
         * scaled by the two bodies' heights, so root motion and the clearances keep the
         * target's proportions (the source's legs in its own units moved greenman's auto-rig,
         * 2 units tall, by CMU's 16-unit strides). */
        const rf_rt_src *s0 = &rt->src[0];
        double ht = rt_extent(rt->target, rt->t_rest_world, rt->t_tip, rt->up, rt->t_above);
        double hs = rt_extent(s0->skel, s0->rest_world, s0->tip, s0->up, s0->above);
        rt->leg_target = ht > 0 && hs > 0 ? s0->leg * ht / hs : s0->leg;
    }
    double lowest = rt_lowest(rt->target, rt->t_rest_world, rt->t_tip, rt->up, rt->t_above);
    rt->t_rest_low = lowest;
    if (!rt_trunk_lean(rt, lowest)) {
        rf_rt_fail(err, err_size, "out of memory");
        return false;
    }
    if (rt->opt.ground == RF_RT_GROUND_WORLD)
        rt->floor_target = 0;
    else if (rt->opt.ground == RF_RT_GROUND_REST)
        rt->floor_target = lowest;
    else
        rt->floor_target = rt_rest_floor(rt->target, rt->t_rest_world, lowest, rt->leg_target);
    for (uint32_t k = 0; k < rt->source_count; k++)
        rt->src[k].scale =
            rt->opt.root_scale > 0 ? rt->opt.root_scale : rt->leg_target / rt->src[k].leg;
    return true;
}

/* ---- keeping the target on its floor ---- */

/* Height of the lowest point of joint j and everything below it (joints and bone tips): the
 * sole of a foot, toes included. */
/* The lower of `low` and the heights of joint c and its bone tip. */
static inline double rt_point_low(double low, const rf_xform *world, const rf_vec3 *tip, rf_vec3 up,
                                  uint32_t c)
{
    low = fmin(low, rf_rt_height(up, world[c].t));
    if (rf_v3_len2(tip[c]) > 0)
        low = fmin(low, rf_rt_height(up, rf_xform_point(world[c], tip[c])));
    return low;
}

double rf_rt_sole(const rf_skeleton *s, const rf_xform *world, const rf_vec3 *tip, rf_vec3 up,
                  uint32_t j)
{
    /* Runs for every foot at every frame of the contact pass: since parents come before their
     * children, "c is j or below it" is one look at c's parent's flag, not a walk up the tree. */
    enum { RT_SOLE_FLAGS = 1024 };
    uint8_t flag[RT_SOLE_FLAGS];
    double low = INFINITY;
    for (uint32_t c = j; c < s->joint_count; c++) {
        int32_t p = s->joints[c].parent;
        bool below = c == j;
        if (c - j < RT_SOLE_FLAGS) {
            below = below || (p >= (int32_t)j && flag[p - (int32_t)j]);
            flag[c - j] = below;
        } else {
            for (; !below && p >= (int32_t)j; p = s->joints[p].parent)
                below = p == (int32_t)j;
        }
        if (below)
            low = rt_point_low(low, world, tip, up, c);
    }
    return low;
}

uint32_t rf_rt_below(const rf_skeleton *s, uint32_t j, uint32_t *below)
{
    uint32_t count = 0;
    for (uint32_t c = j; c < s->joint_count; c++)
        if (rf_rt_carries(s, (int32_t)j, c))
            below[count++] = c;
    return count;
}

double rf_rt_over_floor_below(const rf_retarget *rt, uint32_t k, const rf_xform *world,
                              const uint32_t *below, uint32_t count)
{
    const rf_rt_src *src = &rt->src[k];
    double low = INFINITY;
    for (uint32_t i = 0; i < count; i++)
        low = rt_point_low(low, world, src->tip, src->up, below[i]);
    return (low - src->floor) / src->leg;
}

/* The 5th percentile of per-frame lowest points of the target clip `out` (sampled over one
 * frame in 16, at least 16 and at most 128 frames) and of the source frames at the same times, each
 * over its own floor in its own leg lengths. */
static bool rt_clip_lows(rf_retarget *rt, const rf_animation *out, double *low_t, double *low_s)
{
    uint32_t frames = out->frame_count, samples = frames / 16;
    samples = samples < 16 ? (frames < 16 ? frames : 16) : samples > 128 ? 128 : samples;
    size_t m = rt->max_src_n > rt->n ? rt->max_src_n : rt->n;
    double *lt = malloc((samples + 1) * sizeof *lt), *ls = malloc((samples + 1) * sizeof *ls);
    rf_xform *local = malloc(m * sizeof *local), *world = malloc(m * sizeof *world);
    float *rot = malloc(m * 4 * sizeof *rot), *tr = malloc(m * 3 * sizeof *tr);
    bool ok = lt && ls && local && world && rot && tr && samples;
    if (ok) {
        double start = rf_retarget_start_time(rt);
        for (uint32_t i = 0; i < samples; i++) {
            uint32_t f = samples > 1 ? (uint32_t)((uint64_t)i * (frames - 1) / (samples - 1)) : 0;
            rf_rt_target_fk(rt, out, f, world);
            lt[i] =
                (rt_lowest(rt->target, world, rt->t_tip, rt->up, rt->t_above) - rt->floor_target) /
                rt->leg_target;
            rf_rt_source_world(rt, 0, start + f / out->fps, local, world, rot, tr);
            ls[i] = rf_rt_over_floor(rt, 0, world, -1);
        }
        qsort(lt, samples, sizeof *lt, rt_cmp_double);
        qsort(ls, samples, sizeof *ls, rt_cmp_double);
        *low_t = lt[(uint32_t)(0.05 * (samples - 1))];
        *low_s = ls[(uint32_t)(0.05 * (samples - 1))];
    }
    free(lt), free(ls), free(local), free(world), free(rot), free(tr);
    return ok;
}

/* Median of `count` values (reordered). */
static double rt_median(double *v, uint32_t count)
{
    qsort(v, count, sizeof *v, rt_cmp_double);
    return count % 2 ? v[count / 2] : 0.5 * (v[count / 2 - 1] + v[count / 2]);
}

/* How far the target's feet in contact sit from where the source's say they should (their soles
 * over the target floor as the source's over theirs, in leg lengths): the median over one frame
 * in 16 (at least 16, at most 128) spread over the clip, contacts read on that coarser timeline.
 * False (and no figure) without a contact in those frames or when out of memory. */
static bool rt_contact_shift(rf_retarget *rt, const rf_animation *out, double *shift)
{
    uint32_t frames = out->frame_count, aim = frames / 16;
    aim = aim < 16 ? 16 : aim > 128 ? 128 : aim;
    uint32_t step = frames > aim ? (frames + aim - 1) / aim : 1;
    uint32_t samples = (frames + step - 1) / step, e_count = rt->effector_count;
    double *sole = malloc(((size_t)e_count * samples + 1) * sizeof *sole);
    double *diff = malloc(((size_t)e_count * samples + 1) * sizeof *diff);
    rf_xform *world = malloc((rt->n ? rt->n : 1) * sizeof *world);
    uint8_t *c = sole && diff && world
                     ? rf_rt_detect_contacts(rt, samples, out->fps / step,
                                             rf_retarget_start_time(rt), NULL, sole)
                     : NULL;
    uint32_t count = 0;
    for (uint32_t i = 0; c && i < samples; i++) {
        bool any = false;
        for (uint32_t e = 0; e < e_count; e++)
            any = any || c[(size_t)e * samples + i];
        if (!any)
            continue;
        rf_rt_target_fk(rt, out, i * step, world);
        for (uint32_t e = 0; e < e_count; e++) {
            if (!c[(size_t)e * samples + i])
                continue;
            double want = rt->floor_target + sole[(size_t)e * samples + i] * rt->leg_target;
            diff[count++] =
                want - rf_rt_sole(rt->target, world, rt->t_tip, rt->up, rt->effectors[e]);
        }
    }
    if (count)
        *shift = rt_median(diff, count);
    free(sole), free(diff), free(world), free(c);
    return count > 0;
}

/* The topmost of the joints above root-motion joint j that carry skin and that nothing drives
 * (kept at their rest, not placed from another joint), all of them up to j's parent; -1 when
 * j's parent is no such joint or the skin does not say which joints carry it. */
static int32_t rt_body_above(const rf_retarget *rt, uint32_t j)
{
    const rf_skeleton *s = rt->target;
    int32_t top = -1;
    if (!rt_skin_says(s))
        return -1;
    for (int32_t p = s->joints[j].parent; p >= 0; p = s->joints[p].parent) {
        if (rt->tj[p].kind != RF_RT_REST || rt->anchor[p] >= 0 ||
            (s->joints[p].flags & RF_JOINT_UNWEIGHTED))
            break;
        top = p;
    }
    return top;
}

/* Root motion moves the whole body: where a root-motion joint hangs from joints that carry skin
 * and that nothing drives (the general rigger's root under huesitos' spine: the stem it stands
 * on), its horizontal displacement is handed up to the topmost of them, which keep their rest
 * rotations, so the body walks with what it stands on instead of sliding off it (CMU 01_01's
 * first 120 frames tore huesitos' stem from its spine, stretch p99 52% of its height with its
 * legs measured to the stem's foot, 12% in place). Height stays with the joint: a crouch
 * bends over what it stands on. */
bool rf_rt_carry_root(rf_retarget *rt, rf_animation *out)
{
    for (uint32_t j = 0; j < rt->n; j++) {
        int32_t a = rt->tj[j].root_motion ? rt_body_above(rt, j) : -1;
        if (a < 0)
            continue;
        int32_t p = rt->target->joints[j].parent, pa = rt->target->joints[a].parent;
        rf_xform pw = rt->t_rest_world[p],
                 aw_inv = pa >= 0 ? rf_xform_invert(rt->t_rest_world[pa]) : rf_xform_identity();
        rf_vec3 rest = rt->target->joints[j].rest.t;
        for (uint32_t f = 0; f < out->frame_count; f++) {
            rf_vec3 t = rf_animation_translation(out, f, j);
            rf_vec3 d = rf_quat_rotate(pw.r, rf_v3_mul(pw.s, rf_v3_sub(t, rest)));
            rf_vec3 h = rf_rt_horizontal(rt->up, d);
            rf_vec3 hj = rf_v3_mul(rt->tj[j].parent_world_inv.s,
                                   rf_quat_rotate(rt->tj[j].parent_world_inv.r, h));
            rf_vec3 ha = rf_v3_mul(aw_inv.s, rf_quat_rotate(aw_inv.r, h));
            rf_animation_set_translation(out, f, j, rf_v3_sub(t, hj));
            rf_animation_set_translation(
                out, f, (uint32_t)a, rf_v3_add(rf_animation_translation(out, f, (uint32_t)a), ha));
        }
        out->channels[a] |= RF_CHANNEL_TRANSLATION;
    }
    return true;
}

/* The leg ratio places the hips; the feet then sit over the floor as the source's do only if
 * the legs are built alike. Measure where the clip's feet in contact (or, without feet, its
 * lowest points) fall, relative to each floor and leg, and move the root-motion joints up or down
 * by the difference. */
bool rf_rt_ground_fix(rf_retarget *rt, rf_animation *out)
{
    double low_t, low_s, shift;
    if (rt->opt.root_scale > 0 || !out->frame_count)
        return true; /* an explicit scale is the user's placement */
    if (!rt->effector_count || !rt_contact_shift(rt, out, &shift)) {
        if (!rt_clip_lows(rt, out, &low_t, &low_s))
            return false;
        shift = (low_s - low_t) * rt->leg_target;
    }
    rt->ground_shift = shift;
    return rf_rt_lift(rt, out, shift);
}

/* Moves the root-motion joints along up by shift, or by each[f] in frame f when each is given. */
static bool rt_lift_by(rf_retarget *rt, rf_animation *out, double shift, const double *each)
{
    bool moved = false;
    for (uint32_t j = 0; j < rt->n; j++) {
        if (!rt->tj[j].root_motion)
            continue;
        moved = true;
        for (uint32_t f = 0; f < out->frame_count; f++) {
            rf_vec3 lift = rf_v3_scale(rt->up, each ? each[f] : shift);
            rf_vec3 d = rf_quat_rotate(rt->tj[j].parent_world_inv.r, lift);
            d = rf_v3_mul(rt->tj[j].parent_world_inv.s, d);
            rf_animation_set_translation(out, f, j,
                                         rf_v3_add(rf_animation_translation(out, f, j), d));
        }
    }
    if (!moved || !rt->anchored)
        return true;
    /* Anchored joints hang from placement joints that did not move: place them again. */
    rf_xform *tw = malloc(rt->n * sizeof *tw);
    if (!tw)
        return false;
    for (uint32_t f = 0; f < out->frame_count; f++)
        rf_rt_place_anchored(rt, out->rotations + (size_t)f * rt->n * 4,
                             out->translations + (size_t)f * rt->n * 3, NULL, tw);
    free(tw);
    return true;
}

bool rf_rt_lift(rf_retarget *rt, rf_animation *out, double shift)
{
    return rt_lift_by(rt, out, shift, NULL);
}

bool rf_rt_lift_each(rf_retarget *rt, rf_animation *out, const double *shift)
{
    return rt_lift_by(rt, out, 0, shift);
}
