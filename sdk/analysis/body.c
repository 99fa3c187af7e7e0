/* Skeleton analysis, stage 4: the body tree.
 *
 * Ground roots and armature nodes above the body form the root chain. Parts hanging from other
 * roots or from the root chain (a forest: legs under a separate root, feet parented to the
 * ground root for IK) are attached to the nearest bone of the body: to a leaf's end they
 * continue its chain, elsewhere they hang from that bone's joint. */
#include <math.h>
#include <stdlib.h>

#include "analysis-internal.h"

static int32_t main_root(const rf_awork *w)
{
    int32_t best = RF_NONE;
    for (uint32_t i = 0; i < w->order_count; i++) {
        uint32_t j = w->order[i];
        if (w->parent[j] < 0 && (best < 0 || w->sub_count[j] > w->sub_count[best]))
            best = (int32_t)j;
    }
    return best;
}

static int32_t largest_child(const rf_awork *w, uint32_t j)
{
    int32_t best = RF_NONE;
    for (uint32_t k = w->child_off[j]; k < w->child_off[j + 1]; k++) {
        uint32_t c = w->child_idx[k];
        if (best < 0 || w->sub_count[c] > w->sub_count[best])
            best = (int32_t)c;
    }
    return best;
}

/* The lowest height of the pivots and tips of j's descendants into *lo. False when out of
 * memory. */
static bool descendants_low(const rf_awork *w, uint32_t j, double *lo)
{
    uint32_t *stack = malloc((size_t)(w->n ? w->n : 1) * sizeof *stack), top = 0;
    *lo = INFINITY;
    if (!stack)
        return false;
    for (uint32_t c = w->child_off[j]; c < w->child_off[j + 1]; c++)
        stack[top++] = w->child_idx[c];
    while (top > 0) {
        uint32_t k = stack[--top];
        const rf_joint_info *ji = &w->a->joints[k];
        *lo = fmin(*lo, fmin(rf_an_height(w, ji->pos), rf_an_height(w, ji->tip)));
        for (uint32_t c = w->child_off[k]; c < w->child_off[k + 1]; c++)
            stack[top++] = w->child_idx[c];
    }
    free(stack);
    return true;
}

/* A root-chain joint sits low (at the ground) or far from the body, with its body in one child
 * and at most small parts (IK feet) beside it. The chain only counts if it leads to a branching
 * body. False when out of memory. */
static bool root_chain(rf_awork *w, uint32_t root)
{
    rf_analysis *a = w->a;
    uint32_t r = root, steps = 0;
    bool ground = false; /* the chain has passed an unweighted joint */
    for (;;) {
        int32_t b = largest_child(w, r);
        if (b < 0)
            break;
        bool small = true;
        for (uint32_t k = w->child_off[r]; k < w->child_off[r + 1] && small; k++) {
            uint32_t c = w->child_idx[k];
            small = (int32_t)c == b || w->sub_count[c] <= fmax(2, 0.1 * w->sub_count[b]);
        }
        bool low = rf_an_height(w, rf_an_pos(w, r)) <= a->ground + 0.15 * a->height;
        /* or a placement far from its body, whatever the axes say: a clip's first frame may
         * leave the body metres from the origin's root */
        bool far = rf_an_child_count(w, r) == 1 &&
                   rf_v3_dist(rf_an_pos(w, r), rf_an_pos(w, (uint32_t)b)) > 0.5 * w->sub_len[b];
        /* a ground root stands among the feet: a root far below all the body under it is
         * that body's bottom (a curve skeleton rooted in greenman's belly, no legs; huesitos'
         * stem). Not once the chain has passed a joint the skin says is no body: an artist's
         * unweighted ground roots, whose chain reads as it did (facing included) */
        ground |= w->weights_known && !w->weighted[r];
        double under = -INFINITY;
        if (low && !ground && !descendants_low(w, r, &under))
            return false;
        low = low && under <= a->ground + 0.15 * a->height;
        if (!small || !(low || far))
            break;
        r = (uint32_t)b, steps++;
    }
    uint32_t below = r; /* the chain must lead to a branching body, not to a bare chain */
    for (uint32_t i = 0; i < w->n && rf_an_child_count(w, below) == 1; i++)
        below = w->child_idx[w->child_off[below]];
    if (steps == 0 || rf_an_child_count(w, below) < 2) {
        w->top = (int32_t)root;
        return true;
    }
    w->top = (int32_t)r;
    for (uint32_t j = root; j != r; j = (uint32_t)largest_child(w, j))
        w->root_chain[j] = 1;
    return true;
}

#define RF_MAX_DETACHED 256

/* The part hangs from the body joint nearest to it: from a leaf's end it continues that chain
 * (a foot under its shin), elsewhere it hangs from that pivot (legs under a torso). Pivots, not
 * bones: a leg where the torso meets the neck belongs to the torso's end, not to the neck. */
static void attach(rf_awork *w, uint32_t d, const uint8_t *body)
{
    int32_t best = RF_NONE;
    double best_d = INFINITY;
    rf_vec3 p = rf_an_pos(w, d);
    for (uint32_t i = 0; i < w->order_count; i++) {
        uint32_t j = w->order[i];
        if (!body[j])
            continue;
        double dist = rf_v3_dist(p, rf_an_pos(w, j));
        if (rf_an_is_leaf(w, j))
            dist = fmin(dist, rf_v3_dist(p, w->a->joints[j].tip));
        if (dist < best_d - w->eps) /* ties: the first, shallowest joint on that pivot */
            best_d = dist, best = (int32_t)j;
    }
    if (best < 0)
        return;
    w->parent[d] = best;
    w->attach_pt[d] = rf_an_pos(w, (uint32_t)best);
    w->detached[d] = 1;
}

/* A single leaf hanging from the root chain on a body joint's pivot (an IK target on the ankle)
 * or far from every one (a pole before the knee) is a helper, weights or not: a foot parented
 * to the ground root continues its shin from the shin's end, where no pivot is. */
static bool ik_leaf(rf_awork *w, uint32_t d, const uint8_t *body)
{
    int32_t p = w->parent[d];
    if (p < 0 || !w->root_chain[p] || !rf_an_is_leaf(w, d))
        return false;
    double nearest = INFINITY;
    rf_vec3 at = rf_an_pos(w, d);
    for (uint32_t i = 0; i < w->order_count; i++)
        if (body[w->order[i]])
            nearest = fmin(nearest, rf_v3_dist(at, rf_an_pos(w, w->order[i])));
    if (!(nearest <= 1e-3 * w->a->size || (isfinite(nearest) && nearest > 0.2 * w->a->size)))
        return false;
    w->helper[d] = 1;
    return true;
}

/* Roots other than the main one, and small parts hanging from the root chain, attach to the
 * nearest body bone. False when out of memory. */
static bool attach_detached(rf_awork *w, uint32_t root)
{
    uint8_t *body = calloc(w->n ? w->n : 1, 1);
    uint32_t *parts = malloc((size_t)(w->n ? w->n : 1) * sizeof *parts);
    bool ok = body && parts;
    if (!ok)
        goto out;
    uint32_t count = 0;
    for (uint32_t i = 0; i < w->order_count; i++) {
        uint32_t j = w->order[i];
        int32_t p = w->parent[j];
        bool part = (p < 0 && j != root) ||
                    (p >= 0 && w->root_chain[p] && !w->root_chain[j] && (int32_t)j != w->top);
        if (part)
            parts[count++] = j;
        body[j] = !part && !w->root_chain[j] && (p < 0 ? j == root : body[p] || w->root_chain[p]);
    }
    for (uint32_t i = 0; i < count && i < RF_MAX_DETACHED; i++)
        if (!ik_leaf(w, parts[i], body))
            attach(w, parts[i], body);
out:
    free(body);
    free(parts);
    return ok;
}

/* Props: off-center leaves without a mirror image of their own whose parent's mirror has fewer
 * children (a weapon socket in one fist of a symmetric body). Made helpers so the hand keeps its
 * shape. Returns whether there were any. Only on clearly symmetric bodies. */
static bool unpaired_leaves(rf_awork *w)
{
    bool any = false;
    if (!w->have_plane || w->a->symmetry < 0.75)
        return false;
    for (uint32_t i = 0; i < w->order_count; i++) {
        uint32_t j = w->order[i];
        int32_t p = w->parent[j];
        int32_t twin = w->a->joints[j].mirror; /* a twin is mutual; a socket's is a knuckle */
        if (w->center[j] || !rf_an_is_leaf(w, j) || p < 0 ||
            (twin >= 0 && w->a->joints[twin].mirror == (int32_t)j))
            continue;
        int32_t m = w->a->joints[p].mirror;
        if (m >= 0 && rf_an_child_count(w, (uint32_t)m) < rf_an_child_count(w, (uint32_t)p)) {
            w->helper[j] = 1, any = true;
            w->a->joints[j].flags |= RF_JI_UNPAIRED;
        }
    }
    return any;
}

static bool settle_tree(rf_awork *w)
{
    if (!rf_an_build_tree(w))
        return false;
    rf_an_grid_reset(w); /* a new order */
    rf_an_tips(w);
    return rf_an_subtree_stats(w) && rf_an_classify(w) && rf_an_mirrors(w);
}

bool rf_an_body(rf_awork *w)
{
    int32_t root = main_root(w);
    w->a->root = root;
    if (root < 0)
        return true;
    for (uint32_t j = 0; j < w->n; j++)
        w->attach_pt[j] =
            w->parent[j] >= 0 ? rf_an_pos(w, (uint32_t)w->parent[j]) : rf_an_pos(w, j);
    if (!root_chain(w, (uint32_t)root) || !attach_detached(w, (uint32_t)root) || !settle_tree(w) ||
        (unpaired_leaves(w) && !settle_tree(w)))
        return false;
    w->a->root = w->top;
    if (w->top >= 0)
        w->a->joints[w->top].flags |= RF_JI_ROOT;
    return true;
}
