/* What each joint is for, on both sides (rigflow/analysis.h roles): placement roots and axis
 * conversion nodes neither drive nor receive body motion, so their mapping inputs are dropped;
 * joints their hierarchy parent does not carry (a foot under a placement root, a limb that is a
 * root of its own, IK targets and poles) are anchored to the body joint they belong to and
 * placed from it every frame, rigidly as at rest. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rigflow/analysis.h"
#include "rt-internal.h"

bool rf_rt_carries(const rf_skeleton *s, int32_t a, uint32_t j)
{
    for (int32_t p = (int32_t)j; p >= 0; p = s->joints[p].parent)
        if (p == a)
            return true;
    return false;
}

static bool rt_is_helper(uint8_t role)
{
    return role == RF_ROLE_IK_TARGET || role == RF_ROLE_IK_POLE || role == RF_ROLE_HELPER;
}

/* Body joints below each joint in the hierarchy, and the top of the body: the body joint hanging
 * from no body joint that carries the most of them (the others hanging so are parts placed
 * elsewhere: feet under a placement root, legs that are roots of their own). */
static int32_t rt_body_top(const rf_retarget *rt, const rf_joint_roles *r)
{
    uint32_t *count = calloc(rt->n, sizeof *count), best_count = 0;
    int32_t best = RF_RT_NONE;
    if (!count)
        return RF_RT_NONE;
    for (uint32_t j = rt->n; j-- > 0;) {
        count[j] += r->role[j] == RF_ROLE_BODY;
        int32_t p = rt->target->joints[j].parent;
        if (p >= 0)
            count[p] += count[j];
    }
    for (uint32_t j = 0; j < rt->n; j++) {
        int32_t p = rt->target->joints[j].parent;
        bool root = r->role[j] == RF_ROLE_BODY && (p < 0 || r->role[p] != RF_ROLE_BODY);
        if (root && count[j] > best_count)
            best_count = count[j], best = (int32_t)j;
    }
    free(count);
    return best;
}

/* Whether source joint j is a root its clip holds still (every frame's local transform the
 * first's, within a millionth of the skeleton's size or rotation) while a child's translation
 * moves: a placement root the body travels from, as the Bandai files' root on the floor under
 * their hips. Without skin weights the roles cannot tell it from a body root; driving the
 * target's root from it left the travel to the target's hips' own translation, outside root
 * motion (huesitos under the Bandai walk: its stem stretched 22 times, in place too). */
static bool rt_still_root(const rf_rt_src *src, uint32_t j)
{
    const rf_skeleton *s = src->skel;
    const rf_animation *a = src->anim;
    if (s->joints[j].parent >= 0 || !a || a->joint_count != s->joint_count || a->frame_count < 2)
        return false;
    double eps = 1e-6 * (src->size > 0 ? src->size : 1);
    rf_vec3 t0 = rf_animation_translation(a, 0, j);
    rf_quat r0 = rf_quat_normalize(rf_animation_rotation(a, 0, j));
    for (uint32_t f = 1; f < a->frame_count; f++)
        if (rf_v3_dist(rf_animation_translation(a, f, j), t0) > eps ||
            fabs(rf_quat_dot(rf_quat_normalize(rf_animation_rotation(a, f, j)), r0)) < 1 - 1e-9)
            return false;
    for (uint32_t c = 0; c < s->joint_count; c++) {
        if (s->joints[c].parent != (int32_t)j || !(a->channels[c] & RF_CHANNEL_TRANSLATION))
            continue;
        rf_vec3 c0 = rf_animation_translation(a, 0, c);
        for (uint32_t f = 1; f < a->frame_count; f++)
            if (rf_v3_dist(rf_animation_translation(a, f, c), c0) > eps)
                return true;
    }
    return false;
}

/* The placement or axis joint above the body top nearest it whose mapping has inputs, when the
 * top itself has none: its inputs are the body's (a root the matcher gave the source's hips,
 * which only places the body). Moved to the top, the hips drive and carry the root motion of the
 * whole body; dropped, the body's first driven joints below the top each carried root motion of
 * their own and the unmapped joints between stayed behind (a quadruped whose hind legs hang from
 * an unmapped pelvis was pulled into a bar along its spine). -1 when there is none. */
static int32_t rt_top_input(const rf_retarget *rt, int32_t top)
{
    const rf_mapping *m = rt->mapping;
    if (top < 0 || m->entries[top].input_count)
        return RF_RT_NONE;
    for (int32_t p = rt->target->joints[top].parent; p >= 0; p = rt->target->joints[p].parent)
        if (rf_joint_role_is_frame((rf_joint_role)rt->t_role[p]) && m->entries[p].input_count)
            return p;
    return RF_RT_NONE;
}

/* The caller's mapping without inputs on target placement, axis and helper joints (helpers are
 * placed from their body joint) or from source placement and axis joints; the inputs of the
 * frame joint rt_top_input finds go to the body's top instead. */
static bool rt_filter_mapping(rf_retarget *rt, rf_joint_roles *const *sroles, int32_t top)
{
    const rf_mapping *m = rt->mapping;
    rf_mapping *own = rf_mapping_new(m->target_joint_count, m->source_count);
    if (!own)
        return false;
    rt->own_map = own;
    int32_t moved = rt_top_input(rt, top);
    rt->top_from = moved, rt->top_to = moved >= 0 ? top : RF_RT_NONE;
    for (uint32_t j = 0; j < m->target_joint_count; j++) {
        uint32_t from = (int32_t)j == top && moved >= 0 ? (uint32_t)moved : j;
        const rf_map_entry *e = &m->entries[from];
        rf_map_entry *out = &own->entries[j];
        uint8_t role = rt->t_role[j];
        if (!e->input_count || (int32_t)j == moved)
            continue;
        if (rf_joint_role_is_frame((rf_joint_role)role) || rt_is_helper(role)) {
            rt->dropped += e->input_count;
            continue;
        }
        out->inputs = malloc(e->input_count * sizeof *out->inputs);
        if (!out->inputs)
            return false;
        out->score = e->score;
        for (uint32_t i = 0; i < e->input_count; i++) {
            const rf_map_input *in = &e->inputs[i];
            const rf_joint_roles *sr = sroles[in->source];
            if ((sr && rf_joint_role_is_frame((rf_joint_role)sr->role[in->joint])) ||
                rt_still_root(&rt->src[in->source], in->joint))
                rt->dropped++;
            else
                out->inputs[out->input_count++] = *in;
        }
    }
    rt->mapping = own;
    return true;
}

/* Distance from p to the segment a-b. */
static double rt_seg_dist(rf_vec3 p, rf_vec3 a, rf_vec3 b)
{
    rf_vec3 ab = rf_v3_sub(b, a);
    double l2 = rf_v3_len2(ab), t = l2 > 0 ? rf_v3_dot(rf_v3_sub(p, a), ab) / l2 : 0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    return rf_v3_dist(p, rf_v3_add(a, rf_v3_scale(ab, t)));
}

/* The joint of the main body (the top's subtree) whose bones (pivot to each child's pivot, or the
 * pivot alone) pass nearest j's pivot: where a part hanging from a placement root sits on the
 * body. Guessed tips do not count (the analysis guesses a knee's toward whatever it attached
 * there by proximity). -1 when there is none. */
static int32_t rt_nearest_body(const rf_retarget *rt, const rf_joint_roles *r, uint32_t j,
                               int32_t top)
{
    rf_vec3 p = rt->t_rest_world[j].t;
    int32_t best = RF_RT_NONE;
    double best_d = INFINITY;
    for (uint32_t b = 0; b < rt->n; b++) {
        if (r->role[b] != RF_ROLE_BODY || !rf_rt_carries(rt->target, top, b))
            continue;
        double d = rf_v3_dist(p, rt->t_rest_world[b].t);
        int32_t up = rt->target->joints[b].parent; /* the bone from b's parent to b */
        if (up >= 0 && r->role[up] == RF_ROLE_BODY)
            d = fmin(d, rt_seg_dist(p, rt->t_rest_world[up].t, rt->t_rest_world[b].t));
        if (d < best_d)
            best_d = d, best = d < rf_v3_dist(p, rt->t_rest_world[b].t) ? up : (int32_t)b;
    }
    return best;
}

/* The body joint j hangs from: for a body joint its parent in the analysed tree, carried on past
 * axis nodes (which move with their own parents); past a placement root or helper, the body
 * joint it sits next to (-1 at the top of the body). For a helper the body joint it sits on or
 * next to; -1 for placement and axis joints. */
static int32_t rt_body_parent(const rf_retarget *rt, const rf_joint_roles *r, uint32_t j,
                              int32_t top)
{
    uint8_t role = r->role[j];
    if (rt_is_helper(role))
        return r->body_joint[j];
    if (role != RF_ROLE_BODY)
        return RF_RT_NONE;
    int32_t p = rt->t_logical[j];
    for (uint32_t guard = 0; p >= 0 && r->role[p] == RF_ROLE_AXIS && guard < rt->n; guard++)
        p = rt->target->joints[p].parent;
    if (p < 0 || r->role[p] == RF_ROLE_BODY)
        return p;
    return (int32_t)j == top || top < 0 ? RF_RT_NONE : rt_nearest_body(rt, r, j, top);
}

/* An order in which every joint comes after its hierarchy parent and its anchor: levels relaxed
 * pass by pass (index order settles the hierarchy; each pass settles one more anchor hop).
 * False when the anchors make a cycle. */
static bool rt_order(rf_retarget *rt)
{
    uint32_t n = rt->n, *level = calloc(n, sizeof *level), *count = NULL;
    if (!level)
        return false;
    bool changed = true, ok = true;
    for (uint32_t pass = 0; changed && ok; pass++) {
        changed = false;
        for (uint32_t j = 0; j < n; j++) {
            int32_t p = rt->target->joints[j].parent, a = rt->anchor[j];
            uint32_t l = p >= 0 ? level[p] + 1 : 0;
            if (a >= 0 && level[a] + 1 > l)
                l = level[a] + 1;
            if (l != level[j])
                level[j] = l, changed = true;
        }
        ok = pass <= rt->anchored + 1;
    }
    uint32_t max = 0;
    for (uint32_t j = 0; j < n; j++)
        max = level[j] > max ? level[j] : max;
    count = ok ? calloc(max + 2, sizeof *count) : NULL;
    if (count) {
        for (uint32_t j = 0; j < n; j++)
            count[level[j] + 1]++;
        for (uint32_t l = 1; l <= max + 1; l++)
            count[l] += count[l - 1];
        for (uint32_t j = 0; j < n; j++)
            rt->lorder[count[level[j]]++] = j;
    }
    free(level), free(count);
    return ok;
}

/* Anchors: a joint whose body parent its hierarchy does not carry through is placed from it. */
static void rt_anchors(rf_retarget *rt, const rf_joint_roles *r)
{
    int32_t top = rt_body_top(rt, r);
    rt->anchored = 0;
    for (uint32_t j = 0; j < rt->n; j++) {
        int32_t p = rt->target->joints[j].parent, b = rt_body_parent(rt, r, j, top);
        rt->anchor[j] = RF_RT_NONE;
        rt->lparent[j] = p;
        /* Carried already, or hanging from j itself (it cannot place its own ancestor). */
        if (b < 0 || rf_rt_carries(rt->target, b, j) ||
            rf_rt_carries(rt->target, (int32_t)j, (uint32_t)b))
            continue;
        rt->anchor[j] = b, rt->lparent[j] = b, rt->anchored++;
        rt->anchor_off[j] = rf_xform_mul(rf_xform_invert(rt->t_rest_world[b]), rt->t_rest_world[j]);
    }
}

/* The joints whose world transform placing the anchored joints reads: the anchors, the
 * anchored joints' hierarchy parents, and their ancestors. */
static void rt_needs(rf_retarget *rt)
{
    for (uint32_t j = 0; j < rt->n; j++) {
        if (rt->anchor[j] < 0)
            continue;
        int32_t from[2] = {rt->anchor[j], rt->target->joints[j].parent};
        for (int i = 0; i < 2; i++)
            for (int32_t a = from[i]; a >= 0 && !rt->t_need[a]; a = rt->target->joints[a].parent)
                rt->t_need[a] = 1;
    }
}

/* A body joint whose bone ends where a part placed from it begins (a knee whose foot hangs from
 * a placement root) has its tip there: the analysis guessed it from the tree it built, where the
 * placement root itself may hang from the knee by proximity. */
static void rt_tips(rf_retarget *rt)
{
    for (uint32_t c = 0; c < rt->n; c++) {
        int32_t b = rt->anchor[c];
        if (b < 0 || rt->t_role[c] != RF_ROLE_BODY || rt->t_role[b] != RF_ROLE_BODY)
            continue;
        bool has_child = false;
        for (uint32_t k = 0; k < rt->n && !has_child; k++)
            has_child = rt->target->joints[k].parent == b && rt->t_role[k] == RF_ROLE_BODY;
        if (has_child)
            continue;
        rf_xform inv = rf_xform_invert(rt->t_rest_world[b]);
        rf_vec3 tip = rf_xform_point(inv, rt->t_rest_world[c].t);
        rf_vec3 old = rt->t_tip[b];
        /* The nearest such part when there are several. */
        if (rf_v3_len2(old) == 0 || rt->t_tip_set[b] == 0 || rf_v3_len2(tip) < rf_v3_len2(old))
            rt->t_tip[b] = tip, rt->t_tip_set[b] = 1;
    }
}

bool rf_rt_roles_prepare(rf_retarget *rt, char *err, size_t err_size)
{
    uint32_t n = rt->n;
    rf_joint_roles *tr = rt->t_roles; /* found with the target's analysis */
    rt->t_roles = NULL;
    rf_joint_roles **sr = calloc(rt->source_count, sizeof *sr);
    rt->t_role = malloc(n);
    rt->lparent = malloc(n * sizeof *rt->lparent);
    rt->anchor = malloc(n * sizeof *rt->anchor);
    rt->anchor_off = malloc(n * sizeof *rt->anchor_off);
    rt->lorder = malloc(n * sizeof *rt->lorder);
    rt->t_need = calloc(n, 1);
    rt->t_tip_set = calloc(n, 1);
    bool ok = tr && sr && rt->t_role && rt->lparent && rt->anchor && rt->anchor_off && rt->lorder &&
              rt->t_need && rt->t_tip_set;
    for (uint32_t k = 0; ok && k < rt->source_count; k++) {
        const rf_animation *clip = rt->src[k].anim;
        ok = (sr[k] = rf_joint_roles_find(rt->src[k].skel, NULL, &clip, 1)) != NULL;
    }
    if (ok) {
        memcpy(rt->t_role, tr->role, n);
        ok = rt_filter_mapping(rt, sr, rt_body_top(rt, tr));
    }
    if (ok) {
        rt_anchors(rt, tr);
        if (!rt_order(rt)) { /* anchors in a cycle: every joint follows its hierarchy */
            for (uint32_t j = 0; j < n; j++)
                rt->anchor[j] = RF_RT_NONE, rt->lparent[j] = rt->target->joints[j].parent;
            rt->anchored = 0;
            rt_order(rt);
        }
        rt_needs(rt);
        rt_tips(rt);
    }
    for (uint32_t k = 0; sr && k < rt->source_count; k++)
        rf_joint_roles_free(sr[k]);
    free(sr);
    rf_joint_roles_free(tr);
    if (!ok)
        rf_rt_fail(err, err_size, "out of memory");
    return ok;
}

void rf_rt_place_anchored(const rf_retarget *rt, float *rotations, float *translations,
                          const rf_quat *q, rf_xform *tw)
{
    for (uint32_t i = 0; i < rt->n; i++) {
        uint32_t j = rt->lorder[i];
        int32_t p = rt->target->joints[j].parent, a = rt->anchor[j];
        float *r = rotations + (size_t)j * 4, *t = translations + (size_t)j * 3;
        rf_xform local = {rf_v3(t[0], t[1], t[2]), rf_quat_make(r[0], r[1], r[2], r[3]),
                          rt->target->joints[j].rest.s};
        rf_xform pw = p >= 0 ? tw[p] : rf_xform_identity();
        if (a < 0) {
            /* A driven joint under an anchored undriven one (whose rotation the placement just
             * changed) was turned against the parent's old rotation: its own world rotation
             * (from its inputs: such a joint is never in the local-only fast form), against the
             * placed parent. */
            if (q && p >= 0 && rt->anchor[p] >= 0 && rt->tj[p].kind != RF_RT_MAPPED &&
                rt->tj[j].kind != RF_RT_REST) {
                local.r = rf_quat_normalize(rf_quat_mul(rf_quat_conj(pw.r), q[j]));
                r[0] = (float)local.r.x, r[1] = (float)local.r.y, r[2] = (float)local.r.z;
                r[3] = (float)local.r.w;
            }
            if (rt->t_need[j])
                tw[j] = p >= 0 ? rf_xform_mul(pw, local) : local;
            continue;
        }
        rf_xform want = rf_xform_mul(tw[a], rt->anchor_off[j]);
        if (rt->tj[j].kind == RF_RT_MAPPED) /* its own rotation: from its inputs, or as it was */
            want.r = q ? q[j] : rf_xform_mul(pw, local).r;
        rf_xform inv = rf_xform_invert(pw);
        local.t = rf_xform_point(inv, want.t);
        local.r = rf_quat_normalize(rf_quat_mul(inv.r, want.r));
        tw[j] = p >= 0 ? rf_xform_mul(pw, local) : local;
        r[0] = (float)local.r.x, r[1] = (float)local.r.y, r[2] = (float)local.r.z;
        r[3] = (float)local.r.w;
        t[0] = (float)local.t.x, t[1] = (float)local.t.y, t[2] = (float)local.t.z;
    }
}
