/* Skeleton analysis, stage 5: sections.
 *
 * Limbs are the off-center subtrees; those long enough next to the others are body limbs (arm or
 * leg by the leg threshold), the rest are appendages (ears, eyes). Limb girdles on the centerline
 * give the spine: from the rear-most leg girdle to the front-most girdle. Beyond the front end
 * the centerline is the head, beyond the rear end the tail; a chain stops at a fan (three or more
 * children, or several on the centerline) or where the rig's bone axis shows the only child is
 * offset (a jaw under a skull): what hangs there are appendages. Limbs end at a fan whose
 * children are digits (hands, feet); following the thesis, a limb runs on through a junction
 * where exactly one child branches again, the others becoming digits along it (wings). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis-internal.h"

typedef struct rf_pending {
    uint32_t joint;
    int32_t parent_sec;
    rf_section_type type;
    uint32_t flags;
} rf_pending;

typedef struct rf_builder {
    rf_awork *w;
    rf_section *secs;
    uint32_t count, cap;
    rf_u32vec joints;
    int32_t *sec_of;
    double *down; /* longest center path below each center joint */
    double body_len;
    double *reach;         /* per limb root: farthest tip from its attachment */
    uint32_t *limb_joints; /* per limb root: joints in the limb */
    double *lowest;        /* per limb root: lowest height reached */
    uint8_t *branchy;      /* the subtree holds a junction */
    uint8_t *on_path;      /* on the spine path */
    rf_pending *queue;
    uint32_t q_head, q_tail;
    uint32_t *stack;
    int32_t rear, front; /* spine path ends (girdle joints), -1 without girdles */
    bool ok;
} rf_builder;

/* ---- building blocks ---- */

static int32_t new_section(rf_builder *b, rf_section_type type, uint32_t flags, int32_t parent,
                           int32_t attach)
{
    if (b->count == b->cap) {
        uint32_t cap = b->cap ? 2 * b->cap : 16;
        rf_section *s = realloc(b->secs, (size_t)cap * sizeof *s);
        if (!s) {
            b->ok = false;
            return RF_NONE;
        }
        b->secs = s, b->cap = cap;
    }
    rf_section *s = &b->secs[b->count];
    memset(s, 0, sizeof *s);
    s->type = type, s->flags = flags, s->parent = parent, s->attach_joint = attach;
    s->first = b->joints.n;
    s->mirror = RF_NONE;
    return (int32_t)b->count++;
}

static void add_joint(rf_builder *b, int32_t sec, uint32_t j)
{
    if (sec < 0 || !rf_u32vec_push(&b->joints, j)) {
        b->ok = false;
        return;
    }
    b->sec_of[j] = sec;
    b->secs[sec].bone_count++;
}

static void enqueue(rf_builder *b, uint32_t j, int32_t parent_sec, rf_section_type type,
                    uint32_t flags)
{
    if (b->sec_of[j] >= 0 || b->q_tail >= b->w->n)
        return;
    b->queue[b->q_tail++] = (rf_pending){j, parent_sec, type, flags};
}

static bool is_center(const rf_awork *w, uint32_t j)
{
    return w->center[j];
}

static double key(const rf_awork *w, rf_vec3 p)
{
    return rf_v3_dot(p, w->a->forward) + rf_v3_dot(p, w->a->up);
}

/* ---- measures used to decide ---- */

static void measure_center(rf_builder *b)
{
    rf_awork *w = b->w;
    b->body_len = 0;
    for (uint32_t i = w->order_count; i-- > 0;) {
        uint32_t j = w->order[i];
        if (!is_center(w, j))
            continue;
        double best = 0, second = 0;
        for (uint32_t k = w->child_off[j]; k < w->child_off[j + 1]; k++) {
            uint32_t c = w->child_idx[k];
            if (!is_center(w, c))
                continue;
            double d = b->down[c] + rf_v3_dist(rf_an_pos(w, c), rf_an_pos(w, j));
            if (d > best)
                second = best, best = d;
            else if (d > second)
                second = d;
        }
        if (best == 0)
            best = w->a->joints[j].length;
        b->down[j] = best;
        b->body_len = fmax(b->body_len, best + second);
    }
}

static void measure_limbs(rf_builder *b)
{
    rf_awork *w = b->w;
    for (uint32_t i = 0; i < w->order_count; i++) {
        uint32_t j = w->order[i];
        int32_t r = w->limb_of[j];
        if (r < 0)
            continue;
        if ((uint32_t)r == j)
            b->reach[j] = 0, b->limb_joints[j] = 0, b->lowest[j] = INFINITY;
        const rf_joint_info *ji = &w->a->joints[j];
        b->reach[r] = fmax(b->reach[r], rf_v3_dist(ji->tip, w->attach_pt[r]));
        b->limb_joints[r]++;
        b->lowest[r] = fmin(b->lowest[r], fmin(rf_an_height(w, ji->pos), rf_an_height(w, ji->tip)));
    }
    for (uint32_t i = w->order_count; i-- > 0;) {
        uint32_t j = w->order[i];
        bool br = rf_an_child_count(w, j) >= 2;
        for (uint32_t k = w->child_off[j]; k < w->child_off[j + 1] && !br; k++)
            br = b->branchy[w->child_idx[k]];
        b->branchy[j] = br;
    }
}

static double max_reach(const rf_builder *b)
{
    double m = 0;
    for (uint32_t i = 0; i < b->w->order_count; i++) {
        uint32_t j = b->w->order[i];
        if (b->w->limb_of[j] == (int32_t)j)
            m = fmax(m, b->reach[j]);
    }
    return m;
}

static bool is_leg(const rf_builder *b, uint32_t r)
{
    const rf_analysis *a = b->w->a;
    double t = b->w->opt.leg_threshold > 0 ? b->w->opt.leg_threshold : 0.25;
    return (b->lowest[r] - a->ground) <= t * a->height;
}

/* A body limb, not an ear or an eye: a single bone reaching 0.6 of the longest limb (a curve
 * skeleton's ears, one bone each, reach 0.55 of a fox's legs: taken for arms they made a girdle
 * of the head and ran the spine into it), a chain a fifth of it, or standing on the ground from
 * well above it (a bird's one-bone leg beside its long wings). */
static bool substantial(const rf_builder *b, uint32_t r, double longest)
{
    const rf_awork *w = b->w;
    double drop = rf_an_height(w, rf_an_pos(w, r)) - b->lowest[r];
    return b->reach[r] >= 0.6 * longest ||
           (b->limb_joints[r] >= 2 && b->reach[r] >= 0.2 * longest) ||
           (is_leg(b, r) && drop >= 0.1 * w->a->height);
}

/* ---- the spine path ---- */

static void girdle_ends(rf_builder *b)
{
    rf_awork *w = b->w;
    double longest = max_reach(b);
    int32_t rear_leg = RF_NONE, rear_any = RF_NONE, front = RF_NONE;
    for (uint32_t i = 0; i < w->order_count; i++) {
        uint32_t r = w->order[i];
        int32_t g = w->parent[r];
        /* A root-chain joint lies above the body and already has its section: a limb hanging
         * from it does not make it a girdle (found by fuzz_analysis: the spine listed it again). */
        if (w->limb_of[r] != (int32_t)r || g < 0 || !is_center(w, (uint32_t)g) ||
            w->root_chain[g] || !substantial(b, r, longest))
            continue;
        w->a->joints[g].flags |= RF_JI_GIRDLE;
        double kg = key(w, rf_an_pos(w, (uint32_t)g));
        if (is_leg(b, r) && (rear_leg < 0 || kg < key(w, rf_an_pos(w, (uint32_t)rear_leg))))
            rear_leg = g;
        if (rear_any < 0 || kg < key(w, rf_an_pos(w, (uint32_t)rear_any)))
            rear_any = g;
        if (front < 0 || kg > key(w, rf_an_pos(w, (uint32_t)front)))
            front = g;
    }
    b->rear = rear_leg >= 0 ? rear_leg : rear_any;
    b->front = front;
}

static uint32_t depth_of(const rf_awork *w, uint32_t j)
{
    uint32_t d = 0;
    while (w->parent[j] >= 0 && d < w->n)
        j = (uint32_t)w->parent[j], d++;
    return d;
}

/* The lowest common ancestor of x and y, or RF_NONE when they lie in different trees. */
static int32_t lca(const rf_awork *w, uint32_t x, uint32_t y)
{
    uint32_t dx = depth_of(w, x), dy = depth_of(w, y);
    while (dx > dy)
        x = (uint32_t)w->parent[x], dx--;
    while (dy > dx)
        y = (uint32_t)w->parent[y], dy--;
    while (x != y && w->parent[x] >= 0 && w->parent[y] >= 0)
        x = (uint32_t)w->parent[x], y = (uint32_t)w->parent[y];
    return x == y ? (int32_t)x : RF_NONE;
}

/* Appends the joints from `from` (exclusive) down to `to` (inclusive) in hierarchical order. */
static void add_down(rf_builder *b, int32_t sec, uint32_t from, uint32_t to)
{
    rf_awork *w = b->w;
    uint32_t count = 0;
    for (uint32_t j = to; j != from && count < w->n; j = (uint32_t)w->parent[j]) {
        b->stack[count++] = j;
        if (w->parent[j] < 0)
            break;
    }
    while (count > 0) {
        uint32_t j = b->stack[--count];
        add_joint(b, sec, j);
        b->on_path[j] = 1;
    }
}

/* ---- chains ---- */

/* Degrees between the bone into j and the step from j to its child c; 0 when either is too
 * short to say (coincident joints continue a chain). */
static double turn(const rf_awork *w, uint32_t j, uint32_t c)
{
    int32_t p = w->parent[j];
    rf_vec3 in = p >= 0 ? rf_v3_sub(rf_an_pos(w, j), rf_an_pos(w, (uint32_t)p)) : rf_v3(0, 0, 0);
    rf_vec3 out = rf_v3_sub(rf_an_pos(w, c), rf_an_pos(w, j));
    if (rf_v3_len(in) <= w->eps || rf_v3_len(out) <= w->eps)
        return 0;
    return rf_v3_angle(in, out) * 180.0 / RF_PI;
}

/* The child continuing a center chain at j, or -1 at a fan or an offset-only child. */
static int32_t center_next(const rf_builder *b, uint32_t j)
{
    const rf_awork *w = b->w;
    uint32_t centers = 0, all = rf_an_child_count(w, j);
    int32_t only = RF_NONE, connected = RF_NONE;
    for (uint32_t k = w->child_off[j]; k < w->child_off[j + 1]; k++) {
        uint32_t c = w->child_idx[k];
        if (!is_center(w, c) || b->sec_of[c] >= 0)
            continue;
        centers++, only = (int32_t)c;
        if (rf_v3_dist(rf_an_pos(w, c), w->a->joints[j].tip) <= w->eps)
            connected = (int32_t)c;
    }
    /* With a bone axis: the connected child, unless it folds back down the chain (a bone
     * under the skull pointing into the body). Only within the chain: a tail's first bone may
     * rise from the pelvis and the tail hang from it. */
    int32_t p = w->parent[j];
    bool inside = p >= 0 && b->sec_of[p] >= 0 && b->sec_of[p] == b->sec_of[j];
    if (w->conv_axis >= 0)
        return connected >= 0 && inside && turn(w, j, (uint32_t)connected) > 120.0 ? RF_NONE
                                                                                   : connected;
    if (centers != 1 || all >= 3)
        return RF_NONE;
    /* Without a bone axis, a lone child continues the chain only if it goes on roughly the same
     * way: a jaw hanging forward and down from the skull does not. Only within the chain, as
     * above: the bone into the chain's first joint is another section's. */
    if (!inside)
        return only;
    return turn(w, j, (uint32_t)only) > 75.0 ? RF_NONE : only;
}

/* A chain of center joints from `start`; other center children become pending appendages. */
static int32_t center_chain(rf_builder *b, uint32_t start, rf_section_type type, uint32_t flags,
                            int32_t parent_sec, int32_t attach)
{
    rf_awork *w = b->w;
    int32_t sec = new_section(b, type, flags, parent_sec, attach);
    int32_t j = (int32_t)start;
    while (j >= 0 && b->ok) {
        add_joint(b, sec, (uint32_t)j);
        int32_t next = center_next(b, (uint32_t)j);
        for (uint32_t k = w->child_off[j]; k < w->child_off[j + 1]; k++) {
            uint32_t c = w->child_idx[k];
            if ((int32_t)c != next && is_center(w, c))
                enqueue(b, c, sec, RF_SECTION_APPENDAGE, 0);
        }
        j = next;
    }
    return sec;
}

/* The main chain among candidate children (longest), the others pending appendages. */
static void beyond(rf_builder *b, uint32_t end, rf_section_type type, int32_t parent_sec,
                   int side_sign)
{
    rf_awork *w = b->w;
    int32_t main = RF_NONE;
    double k_end = key(w, rf_an_pos(w, end)), main_ahead = 0;
    for (uint32_t k = w->child_off[end]; k < w->child_off[end + 1]; k++) {
        uint32_t c = w->child_idx[k];
        if (!is_center(w, c) || b->sec_of[c] >= 0 || b->on_path[c])
            continue;
        rf_vec3 mid = rf_v3_scale(w->sub_sum[c], 1.0 / w->sub_count[c]);
        double kc = key(w, mid) - k_end;
        /* a tail lies behind the girdle, however high it is carried (a raised tail is higher
         * than the one body joint it hangs from, like a neck) */
        double ahead = rf_v3_dot(rf_v3_sub(mid, rf_an_pos(w, end)), w->a->forward);
        if (side_sign < 0)
            kc = ahead;
        if (side_sign && kc * side_sign < 0)
            continue;
        /* of two chains rising from one girdle, a tail held high may be the longer: the head
         * is the one in front, the other behind */
        bool longer = main < 0 || b->down[c] > b->down[main];
        if (side_sign > 0 && main >= 0 && ahead * main_ahead < 0)
            longer = ahead > main_ahead;
        if (longer)
            main = (int32_t)c, main_ahead = ahead;
    }
    if (main >= 0)
        center_chain(b, (uint32_t)main, type, 0, parent_sec, (int32_t)end);
}

/* A tail that leaves the spine just in front of the rear girdle: a curve skeleton's root sits
 * low between the hind legs and its tail rises from the spine joint above it, an artist's tail
 * from the pelvis itself. When the rear girdle carries no tail, the longest center branch off
 * the spine path in the rear half of the body whose joints lie behind the girdle is the tail. */
static void tail_off_spine(rf_builder *b, uint32_t rear, uint32_t front, int32_t rear_sec)
{
    rf_awork *w = b->w;
    for (uint32_t s = 0; s < b->count; s++)
        if (b->secs[s].type == RF_SECTION_TAIL)
            return;
    rf_vec3 f = w->a->forward, at = rf_an_pos(w, rear);
    double span = rf_v3_dot(rf_v3_sub(rf_an_pos(w, front), at), f);
    int32_t main = RF_NONE, from = RF_NONE;
    for (uint32_t i = 0; span > 0 && i < w->order_count; i++) {
        uint32_t j = w->order[i];
        if (!b->on_path[j] || rf_v3_dot(rf_v3_sub(rf_an_pos(w, j), at), f) > 0.5 * span)
            continue;
        for (uint32_t k = w->child_off[j]; k < w->child_off[j + 1]; k++) {
            uint32_t c = w->child_idx[k];
            if (!is_center(w, c) || b->on_path[c] || b->sec_of[c] >= 0)
                continue;
            rf_vec3 mid = rf_v3_scale(w->sub_sum[c], 1.0 / w->sub_count[c]);
            if (rf_v3_dot(rf_v3_sub(mid, at), f) >= -0.05 * w->a->size)
                continue;
            if (main < 0 || b->down[c] > b->down[main])
                main = (int32_t)c, from = (int32_t)j;
        }
    }
    if (main >= 0)
        center_chain(b, (uint32_t)main, RF_SECTION_TAIL, 0,
                     from == (int32_t)rear ? rear_sec : b->sec_of[from], from);
}

static void root_section(rf_builder *b)
{
    rf_awork *w = b->w;
    int32_t sec = RF_NONE;
    for (uint32_t i = 0; i < w->order_count; i++) {
        uint32_t j = w->order[i];
        if (!w->root_chain[j])
            continue;
        if (sec < 0)
            sec = new_section(b, RF_SECTION_ROOT, 0, RF_NONE, RF_NONE);
        add_joint(b, sec, j);
    }
}

/* Spine from the rear girdle to the front one (the part below their common ancestor runs
 * backwards and is flagged), head and tail beyond. Without girdles: the longest center chain. */
static void center_sections(rf_builder *b)
{
    rf_awork *w = b->w;
    int32_t top = w->top;
    if (top < 0)
        return;
    int32_t root_sec = b->count ? 0 : RF_NONE;
    int32_t top_attach = w->parent[top];
    /* Girdles in different trees (a forest) have no spine between them, and girdles whose
     * common ancestor already lies in the root section none of their own: either way the spine
     * path would list joints another section holds (found by fuzz_analysis). */
    int32_t common = b->rear >= 0 ? lca(w, (uint32_t)b->rear, (uint32_t)b->front) : RF_NONE;
    if (b->rear >= 0 && (common < 0 || b->sec_of[common] >= 0))
        b->rear = b->front = RF_NONE;
    if (b->rear < 0) {
        int32_t sec = new_section(b, RF_SECTION_SPINE, 0, root_sec, top_attach);
        for (int32_t j = top; j >= 0 && b->ok;) {
            add_joint(b, sec, (uint32_t)j);
            int32_t next = RF_NONE;
            for (uint32_t k = w->child_off[j]; k < w->child_off[j + 1]; k++) {
                uint32_t c = w->child_idx[k];
                if (!is_center(w, c))
                    continue;
                if (next < 0 || b->down[c] > b->down[next])
                    next = (int32_t)c;
            }
            for (uint32_t k = w->child_off[j]; k < w->child_off[j + 1]; k++) {
                uint32_t c = w->child_idx[k];
                if ((int32_t)c != next && is_center(w, c))
                    enqueue(b, c, sec, RF_SECTION_APPENDAGE, 0);
            }
            j = next;
        }
        return;
    }
    uint32_t rear = (uint32_t)b->rear, front = (uint32_t)b->front;
    uint32_t l = (uint32_t)lca(w, rear, front);
    int32_t spine = new_section(b, RF_SECTION_SPINE, 0, root_sec, top_attach);
    if (is_center(w, (uint32_t)top) && lca(w, (uint32_t)top, l) == top) {
        add_joint(b, spine, (uint32_t)top);
        b->on_path[top] = 1;
        add_down(b, spine, (uint32_t)top, l);
    } else {
        add_joint(b, spine, l);
        b->on_path[l] = 1;
    }
    add_down(b, spine, l, front);
    if (rear != l) {
        int32_t rev = new_section(b, RF_SECTION_SPINE, RF_SECFL_REVERSE, spine, (int32_t)l);
        add_down(b, rev, l, rear);
    }
    int32_t rear_sec = b->sec_of[rear];
    if (front == rear) { /* one girdle: split what lies beyond by direction */
        beyond(b, front, RF_SECTION_HEAD, spine, 1); /* the head first: it takes the neck */
        beyond(b, rear, RF_SECTION_TAIL, spine, -1);
    } else {
        beyond(b, front, RF_SECTION_HEAD, spine, 0);
        beyond(b, rear, RF_SECTION_TAIL, rear_sec, 0);
        tail_off_spine(b, rear, front, rear_sec);
    }
    /* center branches off the spine path */
    for (uint32_t i = 0; i < w->order_count; i++) {
        uint32_t j = w->order[i];
        if (!b->on_path[j])
            continue;
        for (uint32_t k = w->child_off[j]; k < w->child_off[j + 1]; k++) {
            uint32_t c = w->child_idx[k];
            if (is_center(w, c) && !b->on_path[c])
                enqueue(b, c, b->sec_of[j], RF_SECTION_APPENDAGE, 0);
        }
    }
}

/* A limb or digit chain from `start`: through single children, and through a junction where
 * exactly one child branches again (its siblings become digits along the way). */
static void limb_chain(rf_builder *b, uint32_t start, rf_section_type type, uint32_t flags,
                       int32_t parent_sec, rf_section_type digit_type)
{
    rf_awork *w = b->w;
    int32_t sec = new_section(b, type, flags, parent_sec, w->parent[start]);
    int32_t j = (int32_t)start;
    bool digit = (flags & RF_SECFL_FAN) != 0;
    while (j >= 0 && b->ok) {
        add_joint(b, sec, (uint32_t)j);
        uint32_t count = rf_an_child_count(w, (uint32_t)j), branching = 0;
        int32_t next = RF_NONE;
        for (uint32_t k = w->child_off[j]; k < w->child_off[j + 1]; k++)
            if (b->branchy[w->child_idx[k]])
                branching++, next = (int32_t)w->child_idx[k];
        /* Through a junction only into a part as long as the limb so far (a wing beyond its
         * mid-wing digits), not into a fist that happens to hold a weapon bone. */
        double so_far = rf_v3_dist(rf_an_pos(w, (uint32_t)j), w->attach_pt[start]);
        if (count == 1)
            next = (int32_t)w->child_idx[w->child_off[j]];
        else if (branching != 1 || digit || w->sub_len[next] < 0.5 * so_far)
            next = RF_NONE;
        for (uint32_t k = w->child_off[j]; k < w->child_off[j + 1]; k++) {
            uint32_t c = w->child_idx[k];
            if ((int32_t)c == next)
                continue;
            enqueue(b, c, sec, digit_type, RF_SECFL_FAN);
            if (next >= 0 && type == RF_SECTION_ARM)
                b->secs[sec].flags |= RF_SECFL_WING; /* digits before the last bone */
        }
        j = next;
    }
}

static void drain(rf_builder *b)
{
    while (b->q_head < b->q_tail && b->ok) {
        rf_pending p = b->queue[b->q_head++];
        if (b->sec_of[p.joint] >= 0)
            continue;
        if (is_center(b->w, p.joint))
            center_chain(b, p.joint, p.type, p.flags, p.parent_sec, b->w->parent[p.joint]);
        else
            limb_chain(b, p.joint, p.type, p.flags, p.parent_sec, p.type);
    }
}

static void limb_sections(rf_builder *b)
{
    rf_awork *w = b->w;
    double longest = max_reach(b);
    for (uint32_t i = 0; i < w->order_count && b->ok; i++) {
        uint32_t r = w->order[i];
        if (w->limb_of[r] != (int32_t)r || b->sec_of[r] >= 0)
            continue;
        int32_t parent_sec = w->parent[r] >= 0 ? b->sec_of[w->parent[r]] : RF_NONE;
        uint32_t flags = w->detached[r] ? RF_SECFL_DETACHED : 0;
        if (!substantial(b, r, longest)) {
            limb_chain(b, r, RF_SECTION_APPENDAGE, flags, parent_sec, RF_SECTION_APPENDAGE);
        } else if (is_leg(b, r)) {
            limb_chain(b, r, RF_SECTION_LEG, flags, parent_sec, RF_SECTION_FOOT);
        } else {
            limb_chain(b, r, RF_SECTION_ARM, flags, parent_sec, RF_SECTION_HAND);
        }
        drain(b);
    }
}

/* Joints no rule reached (parts of other trees that were not attached): appendages. */
static void leftovers(rf_builder *b)
{
    rf_awork *w = b->w;
    for (uint32_t i = 0; i < w->order_count && b->ok; i++) {
        uint32_t j = w->order[i];
        if (b->sec_of[j] >= 0)
            continue;
        int32_t p = w->parent[j];
        enqueue(b, j, p >= 0 ? b->sec_of[p] : RF_NONE, RF_SECTION_APPENDAGE, 0);
        drain(b);
    }
}

static void helper_sections(rf_builder *b)
{
    rf_awork *w = b->w;
    for (uint32_t j = 0; j < w->n && b->ok; j++) { /* file order: parents first */
        if (!w->helper[j])
            continue;
        int32_t p = w->file_parent[j];
        int32_t sec = (p >= 0 && w->helper[p]) ? b->sec_of[p] : RF_NONE;
        if (sec < 0 || sec != (int32_t)b->count - 1) {
            int32_t parent_sec = p >= 0 ? b->sec_of[p] : RF_NONE;
            sec = new_section(b, RF_SECTION_HELPER, 0, parent_sec, p);
        }
        add_joint(b, sec, j);
    }
}

static bool builder_init(rf_builder *b, rf_awork *w)
{
    size_t n = w->n ? w->n : 1;
    memset(b, 0, sizeof *b);
    b->w = w, b->ok = true, b->rear = b->front = RF_NONE;
    b->sec_of = malloc(n * sizeof *b->sec_of);
    b->down = calloc(n, sizeof *b->down);
    b->reach = calloc(n, sizeof *b->reach);
    b->limb_joints = calloc(n, sizeof *b->limb_joints);
    b->lowest = calloc(n, sizeof *b->lowest);
    b->branchy = calloc(n, 1);
    b->on_path = calloc(n, 1);
    b->queue = calloc(n, sizeof *b->queue);
    b->stack = malloc(n * sizeof *b->stack);
    if (!b->sec_of || !b->down || !b->reach || !b->limb_joints || !b->lowest || !b->branchy ||
        !b->on_path || !b->queue || !b->stack)
        return false;
    for (uint32_t j = 0; j < w->n; j++)
        b->sec_of[j] = RF_NONE;
    return true;
}

static void builder_free(rf_builder *b)
{
    free(b->sec_of);
    free(b->down);
    free(b->reach);
    free(b->limb_joints);
    free(b->lowest);
    free(b->branchy);
    free(b->on_path);
    free(b->queue);
    free(b->stack);
    free(b->secs);
    free(b->joints.v);
}

bool rf_an_sections(rf_awork *w)
{
    rf_builder b;
    bool ok = builder_init(&b, w);
    if (ok) {
        for (uint32_t j = 0; j < w->n; j++) {
            rf_joint_info *ji = &w->a->joints[j];
            ji->length = rf_v3_dist(ji->pos, ji->tip);
        }
        measure_center(&b);
        measure_limbs(&b);
        girdle_ends(&b);
        root_section(&b);
        center_sections(&b);
        drain(&b);
        for (uint32_t i = 0; i < w->order_count; i++) { /* center joints of other trees */
            uint32_t j = w->order[i];
            if (is_center(w, j) && b.sec_of[j] < 0) {
                enqueue(&b, j, RF_NONE, RF_SECTION_APPENDAGE, 0);
                drain(&b);
            }
        }
        limb_sections(&b);
        leftovers(&b);
        helper_sections(&b);
        ok = b.ok;
        w->rear = b.rear, w->front = b.front;
    }
    if (ok) {
        rf_analysis *a = w->a;
        a->sections = b.secs, a->section_count = b.count;
        a->section_joints = b.joints.v;
        b.secs = NULL, b.joints.v = NULL;
        for (uint32_t j = 0; j < w->n; j++)
            a->joints[j].section = b.sec_of[j];
    }
    builder_free(&b);
    return ok && rf_an_measure(w);
}
