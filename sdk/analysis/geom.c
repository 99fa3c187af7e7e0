/* Skeleton analysis, stage 1: sanitised world pivots, the rig's bone-axis convention, bone tips
 * and helper joints, and the tree every later stage walks. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis-internal.h"

bool rf_u32vec_push(rf_u32vec *a, uint32_t x)
{
    if (a->n == a->cap) {
        uint32_t cap = a->cap ? a->cap * 2 : 16;
        uint32_t *v = realloc(a->v, (size_t)cap * sizeof *v);
        if (!v)
            return false;
        a->v = v;
        a->cap = cap;
    }
    a->v[a->n++] = x;
    return true;
}

static rf_vec3 finite_or(rf_vec3 v, rf_vec3 fallback)
{
    return rf_v3_isfinite(v) ? v : fallback;
}

/* A transform with every non-finite part replaced, so one bad number spoils one joint only. */
static rf_xform sane_xform(rf_xform x)
{
    x.t = finite_or(x.t, rf_v3(0, 0, 0));
    x.r = rf_quat_normalize(x.r);
    if (!rf_v3_isfinite(x.s))
        x.s = rf_v3(1, 1, 1);
    return x;
}

/* The box's diagonal sets every tolerance of the analysis; measured along the coordinate axes
 * it grew as a body turned (a biped turned 30 degrees about up: 3.5% larger), which moved the
 * symmetry plane's on-plane test and read a turned rig differently from the same rig unturned.
 * Along rf_an_frame it is the same for any turn of a body with its declared axes. */
void rf_an_frame(const rf_awork *w, rf_vec3 ax[3])
{
    ax[0] = rf_v3(1, 0, 0), ax[1] = rf_v3(0, 1, 0), ax[2] = rf_v3(0, 0, 1);
    rf_vec3 u = w->opt.up, f = w->opt.forward;
    bool forced =
        rf_v3_isfinite(u) && rf_v3_isfinite(f) && rf_v3_len2(u) > 1e-24 && rf_v3_len2(f) > 1e-24;
    if (!forced) {
        if (w->opt.ignore_file_axes)
            return;
        u = w->skel->up, f = w->skel->forward;
        if (!(rf_v3_isfinite(u) && rf_v3_isfinite(f)))
            return;
    }
    u = rf_v3_normalize(u), f = rf_v3_normalize(f);
    f = rf_v3_sub(f, rf_v3_scale(u, rf_v3_dot(f, u)));
    if (rf_v3_len2(u) == 0 || rf_v3_len2(f) < 1e-6) /* no axes, or forward along up */
        return;
    f = rf_v3_normalize(f);
    ax[0] = rf_v3_cross(u, f), ax[1] = u, ax[2] = f;
}

/* rf_an_frame, or with a declared up and no forward, that up and the pivots' horizontal
 * principal axes, which turn with the body about its up. */
static void box_frame(const rf_awork *w, rf_vec3 ax[3])
{
    rf_an_frame(w, ax);
    rf_vec3 u = w->skel->up, f = w->skel->forward;
    if (w->opt.ignore_file_axes || rf_v3_len2(w->opt.up) > 0 || !rf_v3_isfinite(u) ||
        rf_v3_len2(u) < 1e-24 || (rf_v3_isfinite(f) && rf_v3_len2(f) > 1e-24))
        return;
    u = rf_v3_normalize(u);
    rf_vec3 e0 = rf_v3_normalize(rf_v3_cross(u, fabs(u.x) < 0.9 ? rf_v3(1, 0, 0) : rf_v3(0, 0, 1)));
    rf_vec3 e1 = rf_v3_cross(u, e0), mean = rf_v3(0, 0, 0);
    for (uint32_t i = 0; i < w->n; i++)
        mean = rf_v3_add(mean, w->a->joints[i].pos);
    mean = rf_v3_scale(mean, 1.0 / (w->n ? w->n : 1));
    double sxx = 0, syy = 0, sxy = 0;
    for (uint32_t i = 0; i < w->n; i++) {
        rf_vec3 d = rf_v3_sub(w->a->joints[i].pos, mean);
        double x = rf_v3_dot(d, e0), y = rf_v3_dot(d, e1);
        sxx += x * x, syy += y * y, sxy += x * y;
    }
    double t = 0.5 * atan2(2 * sxy, sxx - syy); /* the major axis's angle from e0 */
    rf_vec3 h = rf_v3_add(rf_v3_scale(e0, cos(t)), rf_v3_scale(e1, sin(t)));
    ax[0] = h, ax[1] = u, ax[2] = rf_v3_cross(h, u);
}

/* The diagonal of the box around the pivots of the joints with flag `want` (unweighted or
 * not), or of all joints when `all`, along rf_an_frame; 0 when there are none. */
static double extent(const rf_awork *w, bool all, bool want)
{
    rf_vec3 lo = rf_v3(INFINITY, INFINITY, INFINITY), hi = rf_v3(-INFINITY, -INFINITY, -INFINITY);
    rf_vec3 ax[3];
    box_frame(w, ax);
    uint32_t count = 0;
    for (uint32_t i = 0; i < w->n; i++) {
        bool unweighted = (w->skel->joints[i].flags & RF_JOINT_UNWEIGHTED) != 0;
        if ((!all && unweighted != want) || (w->a->joints[i].flags & RF_JI_PLACEMENT))
            continue;
        rf_vec3 q = w->a->joints[i].pos;
        rf_vec3 p = rf_v3(rf_v3_dot(q, ax[0]), rf_v3_dot(q, ax[1]), rf_v3_dot(q, ax[2]));
        lo = rf_v3(fmin(lo.x, p.x), fmin(lo.y, p.y), fmin(lo.z, p.z));
        hi = rf_v3(fmax(hi.x, p.x), fmax(hi.y, p.y), fmax(hi.z, p.z));
        count++;
    }
    return count ? rf_v3_dist(lo, hi) : 0.0;
}

static void bounding_size(rf_awork *w)
{
    double size = extent(w, true, false);
    w->a->size = isfinite(size) && size > 1e-12 ? size : 1.0;
    w->eps = 1e-4 * w->a->size;
    w->tol = 0.04 * w->a->size;
}

/* The pose to analyse, parents and world pivots, with bad numbers and bad parents neutralised. */
bool rf_an_geometry(rf_awork *w)
{
    const rf_skeleton *s = w->skel;
    bool bind = w->opt.use_bind_pose && RF_HAS_FIELD(s, rf_skeleton, bind) && s->bind;
    rf_xform *local = malloc((size_t)(w->n ? w->n : 1) * sizeof *local);
    if (!local)
        return false;
    uint32_t unweighted = 0;
    for (uint32_t i = 0; i < w->n; i++) {
        local[i] = sane_xform(bind ? s->bind[i] : s->joints[i].rest);
        int32_t p = s->joints[i].parent;
        w->file_parent[i] = (p >= 0 && (uint32_t)p < i) ? p : RF_NONE;
        w->parent[i] = w->file_parent[i];
        unweighted += (s->joints[i].flags & RF_JOINT_UNWEIGHTED) != 0;
    }
    w->local = local;
    for (uint32_t i = 0; i < w->n; i++) {
        int32_t p = w->file_parent[i];
        w->world[i] = p < 0 ? local[i] : rf_xform_mul(w->world[p], local[i]);
        rf_vec3 fallback = p < 0 ? rf_v3(0, 0, 0) : w->world[p].t;
        w->world[i].t = finite_or(w->world[i].t, fallback);
        w->a->joints[i].pos = w->world[i].t;
    }
    bounding_size(w);
    /* Weights tell helpers apart only when some joints have them and some do not, and when
     * the weighted joints span most of the skeleton: a mesh skinned to the head alone (a VRM
     * sample's UI quads) says nothing about the limbs. */
    w->weights_known = unweighted > 0 && unweighted < w->n &&
                       extent(w, false, false) >= 0.5 * extent(w, true, false);
    for (uint32_t i = 0; i < w->n; i++) {
        w->weighted[i] = !w->weights_known || !(s->joints[i].flags & RF_JOINT_UNWEIGHTED);
        if (!w->weighted[i])
            w->a->joints[i].flags |= RF_JI_UNWEIGHTED;
    }
    return true;
}

/* Children lists of `parent`, skipping joints for which skip[] is set (skip may be NULL). */
static bool build_children(rf_awork *w, const int32_t *parent, const uint8_t *skip)
{
    memset(w->child_off, 0, (size_t)(w->n + 1) * sizeof *w->child_off);
    for (uint32_t i = 0; i < w->n; i++)
        if (parent[i] >= 0 && !(skip && skip[i]))
            w->child_off[parent[i] + 1]++;
    for (uint32_t i = 0; i < w->n; i++)
        w->child_off[i + 1] += w->child_off[i];
    uint32_t *fill = malloc((size_t)(w->n ? w->n : 1) * sizeof *fill);
    if (!fill)
        return false;
    memcpy(fill, w->child_off, (size_t)w->n * sizeof *fill);
    for (uint32_t i = 0; i < w->n; i++)
        if (parent[i] >= 0 && !(skip && skip[i]))
            w->child_idx[fill[parent[i]]++] = i;
    free(fill);
    return true;
}

/* Unit local direction of the child offset c within joint j's frame. */
static rf_vec3 local_offset(const rf_awork *w, uint32_t j, uint32_t c)
{
    rf_vec3 d = rf_v3_sub(w->a->joints[c].pos, w->a->joints[j].pos);
    return rf_quat_rotate(rf_quat_conj(w->world[j].r), d);
}

/* Axis (0..2) a unit vector lies along, within about 18 degrees, or -1. */
static int along_axis(rf_vec3 d, double *component)
{
    double c[3] = {d.x, d.y, d.z};
    int k = 0;
    for (int i = 1; i < 3; i++)
        if (fabs(c[i]) > fabs(c[k]))
            k = i;
    *component = c[k];
    return fabs(c[k]) >= 0.95 ? k : -1;
}

/* Many rigs (Blender's +Y, Maya's +-X) point every bone along one local axis. Knowing it gives
 * leaf bones a direction and tells connected children from offset ones (a jaw below a skull). */
static void convention(rf_awork *w)
{
    uint32_t votes[3][2] = {{0}}, candidates = 0;
    for (uint32_t j = 0; j < w->n; j++) {
        int best = -1, sign = 0;
        double best_c = 0;
        for (uint32_t k = w->child_off[j]; k < w->child_off[j + 1]; k++) {
            uint32_t c = w->child_idx[k];
            if (rf_v3_dist(w->a->joints[c].pos, w->a->joints[j].pos) <= w->eps)
                continue;
            double comp;
            int axis = along_axis(rf_v3_normalize(local_offset(w, j, c)), &comp);
            if (best < 0 || fabs(comp) > fabs(best_c))
                best = axis, best_c = comp, sign = comp > 0 ? 1 : -1;
        }
        if (best_c == 0)
            continue;
        candidates++;
        if (best >= 0) {
            votes[best][sign > 0]++;
            w->own_sign[j] = (int8_t)sign;
        }
    }
    int axis = 0;
    for (int k = 1; k < 3; k++)
        if (votes[k][0] + votes[k][1] > votes[axis][0] + votes[axis][1])
            axis = k;
    uint32_t total = votes[axis][0] + votes[axis][1];
    w->conv_axis = (total >= 3 && total >= 0.7 * candidates) ? axis : -1;
    w->conv_sign = votes[axis][1] >= votes[axis][0] ? 1 : -1;
    for (uint32_t j = 0; j < w->n; j++) /* signs voted along another axis mean nothing */
        if (w->own_sign[j] && w->conv_axis >= 0) {
            double comp;
            int best = -1;
            for (uint32_t k = w->child_off[j]; k < w->child_off[j + 1] && best != w->conv_axis; k++)
                best = along_axis(rf_v3_normalize(local_offset(w, j, w->child_idx[k])), &comp);
            if (best != w->conv_axis)
                w->own_sign[j] = 0;
        }
}

/* World direction of joint j's local convention axis with the given sign. */
rf_vec3 rf_an_axis_dir(const rf_awork *w, uint32_t j, int sign)
{
    rf_vec3 e = rf_v3(w->conv_axis == 0, w->conv_axis == 1, w->conv_axis == 2);
    return rf_v3_normalize(rf_quat_rotate(w->world[j].r, rf_v3_scale(e, sign)));
}

/* Sign of the convention axis for joint j: its own when a child showed it, else the sign of the
 * joint's offset from its parent along the parent's axis (a leaf continues its parent), else the
 * rig's usual sign. */
static int axis_sign(const rf_awork *w, uint32_t j)
{
    if (w->own_sign[j])
        return w->own_sign[j];
    int32_t p = w->file_parent[j];
    if (p >= 0 && w->own_sign[p])
        return w->own_sign[p];
    return w->conv_sign;
}

/* Length of the nearest non-zero bone above j (how long a guessed leaf should be). */
static double ancestor_length(const rf_awork *w, uint32_t j)
{
    uint32_t at = j;
    for (int step = 0; step < 64 && w->parent[at] >= 0; step++) {
        uint32_t p = (uint32_t)w->parent[at];
        double d = rf_v3_dist(w->a->joints[at].pos, w->a->joints[p].pos);
        if (d > w->eps)
            return d;
        at = p;
    }
    return 0.05 * w->a->size;
}

/* A guessed tip for a bone with nothing beyond it: along the rig's bone axis when it has one,
 * else straight on from the parent bone, three quarters as long as the bone above. */
static void guess_tip(rf_awork *w, uint32_t j)
{
    rf_joint_info *ji = &w->a->joints[j];
    rf_vec3 dir = rf_v3(0, 0, 0);
    if (w->conv_axis >= 0)
        dir = rf_an_axis_dir(w, j, axis_sign(w, j));
    else if (w->parent[j] >= 0)
        dir = rf_v3_normalize(rf_v3_sub(ji->pos, w->a->joints[w->parent[j]].pos));
    if (rf_v3_len2(dir) == 0) {
        ji->tip = ji->pos;
        return;
    }
    ji->tip = rf_v3_add(ji->pos, rf_v3_scale(dir, 0.75 * ancestor_length(w, j)));
    ji->flags |= RF_JI_TIP_GUESSED;
}

/* The child continuing j's bone along the rig's axis, or -1. */
static int32_t connected_child(const rf_awork *w, uint32_t j)
{
    rf_vec3 e = rf_an_axis_dir(w, j, axis_sign(w, j));
    int32_t best = RF_NONE;
    double best_c = 0.9;
    for (uint32_t k = w->child_off[j]; k < w->child_off[j + 1]; k++) {
        uint32_t c = w->child_idx[k];
        rf_vec3 d = rf_v3_sub(w->a->joints[c].pos, w->a->joints[j].pos);
        double len = rf_v3_len(d);
        if (len <= w->eps)
            continue;
        double comp = rf_v3_dot(d, e) / len;
        if (comp >= best_c)
            best_c = comp, best = (int32_t)c;
    }
    return best;
}

/* Whether j's only child c is a leaf folding back more than 120 degrees against the bone j hangs
 * from (a prop or a display card hung under a head): it ends nothing, so the bone goes on. */
static bool folds_back(const rf_awork *w, uint32_t j, uint32_t c)
{
    int32_t p = w->parent[j];
    if (p < 0 || rf_an_child_count(w, c))
        return false;
    rf_vec3 in = rf_v3_sub(w->a->joints[j].pos, w->a->joints[p].pos);
    rf_vec3 out = rf_v3_sub(w->a->joints[c].pos, w->a->joints[j].pos);
    double li = rf_v3_len(in), lo = rf_v3_len(out);
    return li > w->eps && lo > w->eps && rf_v3_dot(in, out) < -0.5 * li * lo;
}

static void tip_from_children(rf_awork *w, uint32_t j)
{
    rf_joint_info *ji = &w->a->joints[j];
    uint32_t count = rf_an_child_count(w, j);
    if (count == 1 && folds_back(w, j, w->child_idx[w->child_off[j]])) {
        /* Straight on from the bone above, whatever the rig's axis says: the child may have
         * set this joint's own axis sign. */
        int32_t p = w->parent[j];
        rf_vec3 dir = rf_v3_normalize(rf_v3_sub(ji->pos, w->a->joints[p].pos));
        ji->tip = rf_v3_add(ji->pos, rf_v3_scale(dir, 0.75 * ancestor_length(w, j)));
        ji->flags |= RF_JI_TIP_GUESSED;
        return;
    }
    if (w->conv_axis >= 0) {
        int32_t c = connected_child(w, j);
        if (c >= 0) {
            ji->tip = w->a->joints[c].pos;
            return;
        }
        uint32_t only = count == 1 ? w->child_idx[w->child_off[j]] : 0;
        if (count == 1 && rf_v3_dist(w->a->joints[only].pos, ji->pos) <= w->eps) {
            ji->tip = ji->pos; /* a control joint sitting on its child */
            return;
        }
        guess_tip(w, j); /* only offset children (a head over its jaw): the bone is its own */
        return;
    }
    if (count == 1) {
        ji->tip = w->a->joints[w->child_idx[w->child_off[j]]].pos;
        return;
    }
    rf_vec3 sum = rf_v3(0, 0, 0);
    uint32_t used = 0;
    for (uint32_t k = w->child_off[j]; k < w->child_off[j + 1]; k++) {
        rf_vec3 p = w->a->joints[w->child_idx[k]].pos;
        if (rf_v3_dist(p, ji->pos) > w->eps)
            sum = rf_v3_add(sum, p), used++;
    }
    ji->tip = used ? rf_v3_scale(sum, 1.0 / used) : ji->pos;
}

/* Tips of every bone from the current tree: end sites and end markers first, then children,
 * then a guess. */
void rf_an_tips(rf_awork *w)
{
    for (uint32_t j = 0; j < w->n; j++) {
        rf_joint_info *ji = &w->a->joints[j];
        if (w->tip_set[j])
            continue;
        ji->flags &= ~(uint32_t)RF_JI_TIP_GUESSED;
        if (rf_an_is_leaf(w, j))
            guess_tip(w, j);
        else
            tip_from_children(w, j);
    }
}

static void end_sites(rf_awork *w)
{
    for (uint32_t j = 0; j < w->n; j++) {
        const rf_joint *sj = &w->skel->joints[j];
        if (!(sj->flags & RF_JOINT_HAS_END_SITE) || !rf_v3_isfinite(sj->end_site))
            continue;
        rf_vec3 tip = rf_xform_point(w->world[j], sj->end_site);
        if (rf_v3_isfinite(tip)) {
            w->a->joints[j].tip = tip;
            w->tip_set[j] = 1;
        }
    }
}

/* An unweighted leaf that is its weighted parent's only child and lies on along the parent's
 * bone (an exporter's "_end" joint) marks the parent's tip. */
static bool end_marker(rf_awork *w, uint32_t j)
{
    int32_t p = w->file_parent[j];
    if (p < 0 || !w->weighted[p] || rf_an_child_count(w, (uint32_t)p) != 1 || w->tip_set[p])
        return false;
    rf_vec3 off = rf_v3_sub(w->a->joints[j].pos, w->a->joints[p].pos);
    if (rf_v3_len(off) <= w->eps)
        return false;
    int32_t pp = w->file_parent[p];
    rf_vec3 in = pp >= 0 ? rf_v3_sub(w->a->joints[p].pos, w->a->joints[pp].pos) : rf_v3(0, 0, 0);
    if (rf_v3_len(in) > w->eps) {
        if (rf_v3_angle(off, in) > 50.0 * RF_PI / 180.0 || rf_v3_len(off) > 3.0 * rf_v3_len(in))
            return false;
    }
    w->a->joints[p].tip = w->a->joints[j].pos;
    w->tip_set[p] = 1;
    return true;
}

/* A twist or roll leaf: a leaf lying inside its parent's bone, on the line from the parent to
 * the child the bone continues into, and pointing along it (Unreal's upperarm_twist_01 beside
 * lowerarm). It only spreads its segment's twist over the skin: it is part of that segment, not
 * a digit or a limb of its own, and stays still with it when unmapped. */
#define RF_AN_ROLL_SIBLINGS 64

static bool roll_leaf(const rf_awork *w, uint32_t j)
{
    int32_t p = w->file_parent[j];
    /* a segment carries its next segment and a few roll leaves; a joint with hundreds of
     * children is a fan of parts (or a hostile file), and testing every leaf against every
     * sibling would be quadratic in them */
    if (p < 0 || !rf_an_is_leaf(w, j) || rf_an_child_count(w, (uint32_t)p) < 2 ||
        rf_an_child_count(w, (uint32_t)p) > RF_AN_ROLL_SIBLINGS)
        return false;
    rf_vec3 pj = w->a->joints[j].pos, pp = w->a->joints[p].pos;
    for (uint32_t k = w->child_off[p]; k < w->child_off[p + 1]; k++) {
        uint32_t c = w->child_idx[k];
        if (c == j)
            continue;
        rf_vec3 bone = rf_v3_sub(w->a->joints[c].pos, pp);
        double len = rf_v3_len(bone);
        if (len <= w->eps)
            continue;
        rf_vec3 d = rf_v3_scale(bone, 1.0 / len), rel = rf_v3_sub(pj, pp);
        double t = rf_v3_dot(rel, d) / len;
        double off = rf_v3_len(rf_v3_sub(rel, rf_v3_scale(d, t * len)));
        if (t < 0.05 || t > 0.95 || off > 0.03 * len)
            continue;
        /* its own bone: the end site, or the rig's bone axis (tips come later) */
        rf_vec3 own = w->tip_set[j]       ? rf_v3_sub(w->a->joints[j].tip, pj)
                      : w->conv_axis >= 0 ? rf_an_axis_dir(w, j, axis_sign(w, j))
                                          : rf_v3(0, 0, 0);
        if (rf_v3_len(own) > w->eps && rf_v3_dot(own, d) < 0.94 * rf_v3_len(own))
            continue; /* a side branch (a thumb, a weapon) leaves the line */
        return true;
    }
    return false;
}

/* Helpers from skin weights (only when the skeleton says which joints have them): end markers,
 * unweighted leaves (IK targets, poles, sockets) and wholly unweighted subtrees (control rigs).
 * Unweighted joints sitting on their only child are control joints: kept, never driven. Roll
 * leaves are helpers with or without weights. False when out of memory (a control rig would be
 * read as body). */
bool rf_an_helpers(rf_awork *w)
{
    for (uint32_t j = 0; j < w->n; j++)
        if (roll_leaf(w, j))
            w->helper[j] = 1;
    if (!w->weights_known)
        return true;
    uint8_t *all_unweighted = calloc(w->n ? w->n : 1, 1);
    if (!all_unweighted)
        return false;
    for (uint32_t i = w->n; i-- > 0;) {
        bool all = !w->weighted[i];
        for (uint32_t k = w->child_off[i]; k < w->child_off[i + 1] && all; k++)
            all = all_unweighted[w->child_idx[k]];
        all_unweighted[i] = all;
    }
    for (uint32_t j = 0; j < w->n; j++) {
        rf_joint_info *ji = &w->a->joints[j];
        if (w->weighted[j])
            continue;
        if (rf_an_is_leaf(w, j)) {
            if (end_marker(w, j))
                ji->flags |= RF_JI_END_MARKER;
            w->helper[j] = 1;
        } else if (all_unweighted[j]) {
            w->helper[j] = 1;
        }
    }
    free(all_unweighted);
    /* Control joints, once helpers are known: an armature node with IK targets beside the body
     * still sits on its one real child. */
    for (uint32_t j = 0; j < w->n; j++) {
        uint32_t real = 0, only = 0;
        for (uint32_t k = w->child_off[j]; k < w->child_off[j + 1]; k++)
            if (!w->helper[w->child_idx[k]])
                real++, only = w->child_idx[k];
        if (!w->weighted[j] && !w->helper[j] && real == 1 &&
            rf_v3_dist(w->a->joints[only].pos, w->a->joints[j].pos) <= w->eps)
            w->a->joints[j].flags |= RF_JI_CONTROL;
    }
    return true;
}

/* Parents first, helpers left out of `order` (they stay in `hlp_order`). */
bool rf_an_build_tree(rf_awork *w)
{
    if (!build_children(w, w->parent, w->helper))
        return false;
    uint32_t n = 0;
    for (uint32_t i = 0; i < w->n; i++)
        if (!w->helper[i] && (w->parent[i] < 0 || w->helper[w->parent[i]]))
            w->order[n++] = i;
    for (uint32_t head = 0; head < n; head++) {
        uint32_t j = w->order[head];
        for (uint32_t k = w->child_off[j]; k < w->child_off[j + 1]; k++)
            w->order[n++] = w->child_idx[k];
    }
    w->order_count = n;
    return true;
}

/* Everything geometry needs before symmetry: pivots, the axis convention, tips, helpers. */
/* Whether p lies clearly outside the box lo..hi: further from it than a tenth of its diagonal
 * (a ground root between the feet is inside). */
static bool outside(rf_vec3 p, rf_vec3 lo, rf_vec3 hi)
{
    rf_vec3 q = rf_v3(fmin(fmax(p.x, lo.x), hi.x), fmin(fmax(p.y, lo.y), hi.y),
                      fmin(fmax(p.z, lo.z), hi.z));
    return rf_v3_dist(p, q) > 0.1 * rf_v3_dist(lo, hi);
}

/* Whether p lies under the box lo..hi along the up the file declares (or the caller forced),
 * within its extent across that up: the bottom of a body without legs (a curve skeleton rooted
 * in greenman's belly, its first bone rising to the arms), or a ground root (the root chain's,
 * body.c), not a placement beside the body. */
static bool under(const rf_awork *w, rf_vec3 p, rf_vec3 lo, rf_vec3 hi)
{
    rf_vec3 up = w->opt.up;
    if (!(rf_v3_isfinite(up) && rf_v3_len2(up) > 1e-24) && !w->opt.ignore_file_axes)
        up = w->skel->up;
    if (!(rf_v3_isfinite(up) && rf_v3_len2(up) > 1e-24))
        return false;
    up = rf_v3_normalize(up);
    rf_vec3 mid = rf_v3_scale(rf_v3_add(lo, hi), 0.5);
    double rise = rf_v3_dot(rf_v3_sub(mid, p), up);
    /* raised to the box's middle, it falls inside the box */
    return rise > 0 && !outside(rf_v3_add(p, rf_v3_scale(up, rise)), lo, hi);
}

/* Roots placed away from their body: a root with one branching child, outside the box of the
 * child's subtree (a clip's frame may put the body metres from the origin). Helpers; the size
 * and tolerances are measured without them. False when out of memory. */
static bool placements(rf_awork *w)
{
    rf_vec3 *lo = malloc((size_t)(w->n ? w->n : 1) * sizeof *lo);
    rf_vec3 *hi = malloc((size_t)(w->n ? w->n : 1) * sizeof *hi);
    bool any = false;
    if (!lo || !hi) {
        free(lo), free(hi);
        return false;
    }
    for (uint32_t i = 0; i < w->n; i++)
        lo[i] = hi[i] = w->a->joints[i].pos;
    for (uint32_t i = w->n; i-- > 0;) { /* children after parents */
        int32_t p = w->file_parent[i];
        if (p >= 0) {
            lo[p] = rf_v3(fmin(lo[p].x, lo[i].x), fmin(lo[p].y, lo[i].y), fmin(lo[p].z, lo[i].z));
            hi[p] = rf_v3(fmax(hi[p].x, hi[i].x), fmax(hi[p].y, hi[i].y), fmax(hi[p].z, hi[i].z));
        }
    }
    for (uint32_t r = 0; r < w->n; r++) {
        if (w->file_parent[r] >= 0 || rf_an_child_count(w, r) != 1 || w->helper[r])
            continue;
        uint32_t c = w->child_idx[w->child_off[r]];
        if (rf_an_child_count(w, c) >= 2 && outside(rf_an_pos(w, r), lo[c], hi[c]) &&
            !under(w, rf_an_pos(w, r), lo[c], hi[c])) {
            w->helper[r] = 1, any = true;
            w->a->joints[r].flags |= RF_JI_PLACEMENT;
            w->parent[c] = RF_NONE; /* the body's root, measured from its own pivot */
        }
    }
    free(lo);
    free(hi);
    if (any)
        bounding_size(w);
    return true;
}

bool rf_an_prepare(rf_awork *w)
{
    if (!rf_an_geometry(w) || !build_children(w, w->file_parent, NULL))
        return false;
    convention(w);
    end_sites(w);
    if (!rf_an_helpers(w) || !placements(w) || !rf_an_build_tree(w))
        return false;
    rf_an_tips(w);
    return true;
}
