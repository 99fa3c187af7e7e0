/* Skeleton analysis, stage 6: per-section and per-joint measures: sides, lengths, positions
 * along each section, bone directions, bends, where sections sit along the body, ranks among
 * limbs and digits, mirrored sections. */
#include <math.h>
#include <stdlib.h>

#include "analysis-internal.h"

static bool center_type(rf_section_type t)
{
    return t == RF_SECTION_ROOT || t == RF_SECTION_SPINE || t == RF_SECTION_HEAD ||
           t == RF_SECTION_TAIL;
}

static rf_side side_of_point(const rf_awork *w, rf_vec3 p, double margin)
{
    double d = rf_v3_dot(rf_v3_sub(p, w->plane_p), w->a->left);
    return d > margin ? RF_SIDE_LEFT : d < -margin ? RF_SIDE_RIGHT : RF_SIDE_CENTER;
}

static rf_side section_side(const rf_awork *w, const rf_section *s, uint32_t first)
{
    if (center_type(s->type))
        return RF_SIDE_CENTER;
    if (w->helper[first])
        return side_of_point(w, rf_an_pos(w, first), 0.5 * w->tol);
    int32_t r = w->limb_of[first];
    if (r < 0)
        return RF_SIDE_CENTER;
    rf_vec3 c = rf_v3_scale(w->sub_sum[r], 1.0 / w->sub_count[r]);
    return side_of_point(w, c, 0.1 * w->tol);
}

/* The length of the bone p ends, with the bone before it when the two lie in one straight line
 * (a forearm cut in two for its twist, as Rigify's deform bones are): the hand is compared with
 * the whole forearm, not its second half. */
static double forearm_length(const rf_analysis *a, int32_t p)
{
    const rf_joint_info *f = &a->joints[p];
    int32_t q = f->logical_parent;
    if (q < 0 || f->length <= 0 || a->joints[q].length <= 0)
        return f->length;
    const rf_joint_info *g = &a->joints[q];
    rf_vec3 d0 = rf_v3_normalize(rf_v3_sub(g->tip, g->pos));
    rf_vec3 d1 = rf_v3_normalize(rf_v3_sub(f->tip, f->pos));
    bool straight = rf_v3_dot(d0, d1) > 0.999 && rf_v3_dist(g->tip, f->pos) <= 1e-3 * g->length;
    return straight ? f->length + g->length : f->length;
}

/* A hand bone's length; when its tip is only a guess (no end site, no child along its axis: a
 * guess three quarters as long as the forearm), the farthest of its children's pivots, the
 * knuckles, says how long it is. */
static double hand_length(const rf_awork *w, uint32_t hand)
{
    const rf_joint_info *h = &w->a->joints[hand];
    if (!(h->flags & RF_JI_TIP_GUESSED) || rf_an_is_leaf(w, hand))
        return h->length;
    double len = 0;
    for (uint32_t k = w->child_off[hand]; k < w->child_off[hand + 1]; k++)
        len = fmax(len, rf_v3_dist(rf_an_pos(w, w->child_idx[k]), h->pos));
    return len;
}

/* Whether a fan's digits are measured from the wrist, the pivot of the bone they hang from: a
 * hand bone (no longer than three digits, and well short of the forearm before it), so
 * a palm bone starting at the wrist and a finger starting at the knuckle keep apart (the
 * knuckle lies half-way along the hand, not at its start). Digits on a forearm (a rig without
 * hand bones) start at its end, the wrist. */
static bool fan_from_wrist(const rf_awork *w, const rf_section *s)
{
    if (!(s->flags & RF_SECFL_FAN) || s->attach_joint < 0)
        return false;
    const rf_analysis *a = w->a;
    const uint32_t *js = a->section_joints + s->first;
    double reach = a->joints[js[s->bone_count - 1]].length;
    for (uint32_t k = 0; k + 1 < s->bone_count; k++)
        reach += rf_v3_dist(a->joints[js[k + 1]].pos, a->joints[js[k]].pos);
    const rf_joint_info *hand = &a->joints[s->attach_joint];
    int32_t p = hand->logical_parent;
    double len = hand_length(w, (uint32_t)s->attach_joint);
    return len <= 3 * reach && (p < 0 || len <= 0.6 * forearm_length(a, p));
}

/* Where a section's length is measured from: its own first pivot for the root chain and the
 * spine, else the point where it leaves its parent. */
static rf_vec3 start_point(const rf_awork *w, const rf_section *s, uint32_t first)
{
    bool own = s->type == RF_SECTION_ROOT ||
               (s->type == RF_SECTION_SPINE && !(s->flags & RF_SECFL_REVERSE)) ||
               w->parent[first] < 0;
    if (own)
        return rf_an_pos(w, first);
    if (fan_from_wrist(w, s))
        return w->a->joints[s->attach_joint].pos;
    /* digits start where the bone they fan out of ends (the wrist, not the elbow), and so does
     * the neck (at the top of the last spine bone, not at its pivot) */
    if (((s->flags & RF_SECFL_FAN) || s->type == RF_SECTION_HEAD) && s->attach_joint >= 0)
        return w->a->joints[s->attach_joint].tip;
    return w->attach_pt[first];
}

/* Positions along the section as fractions of its length; `extra` lengthens it beyond the last
 * tip (a limb ending in a fan counts its longest digit, so hands of one joint and of three
 * compare). */
static void measure_section(rf_awork *w, rf_section *s, double extra)
{
    rf_analysis *a = w->a;
    const uint32_t *js = a->section_joints + s->first;
    uint32_t m = s->bone_count;
    rf_vec3 p0 = start_point(w, s, js[0]);
    double d = rf_v3_dist(rf_an_pos(w, js[0]), p0);
    for (uint32_t k = 0; k < m; k++) {
        rf_joint_info *ji = &a->joints[js[k]];
        ji->u0 = d;
        d += k + 1 < m ? rf_v3_dist(a->joints[js[k + 1]].pos, ji->pos) : ji->length;
        ji->u1 = d;
    }
    d += extra;
    s->length = d;
    /* The spine is measured to its last pivot, the front girdle, where it meets the neck and the
     * arms: spines ending in a long bone and in a zero-length one then compare. */
    if (s->type == RF_SECTION_SPINE && !(s->flags & RF_SECFL_REVERSE) && m > 1) {
        double to_pivot = a->joints[js[m - 1]].u0;
        if (to_pivot > w->eps)
            d = to_pivot;
    }
    for (uint32_t k = 0; k < m; k++) {
        rf_joint_info *ji = &a->joints[js[k]];
        if (d > w->eps)
            ji->u0 /= d, ji->u1 /= d;
        else
            ji->u0 = (double)k / m, ji->u1 = (double)(k + 1) / m;
        rf_vec3 prev = k ? a->joints[js[k - 1]].pos : p0;
        rf_vec3 next = k + 1 < m ? a->joints[js[k + 1]].pos : ji->tip;
        rf_vec3 off = rf_v3_sub(ji->pos, rf_v3_scale(rf_v3_add(prev, next), 0.5));
        ji->bend = d > w->eps ? rf_v3_dot(off, a->forward) / d : 0;
    }
}

/* Bone directions; a zero-length bone takes the next real one along its chain, else the one
 * before. */
static void directions(rf_awork *w, const rf_section *s)
{
    rf_analysis *a = w->a;
    const uint32_t *js = a->section_joints + s->first;
    uint32_t m = s->bone_count;
    for (uint32_t k = 0; k < m; k++) {
        rf_joint_info *ji = &a->joints[js[k]];
        ji->dir = rf_v3_normalize(rf_v3_sub(ji->tip, ji->pos));
        if (ji->length <= w->eps)
            ji->flags |= RF_JI_ZERO_LENGTH, ji->dir = rf_v3(0, 0, 0);
    }
    rf_vec3 carry = rf_v3(0, 0, 0);
    for (uint32_t k = m; k-- > 0;) {
        rf_joint_info *ji = &a->joints[js[k]];
        if (rf_v3_len2(ji->dir) > 0)
            carry = ji->dir;
        else
            ji->dir = carry;
    }
    for (uint32_t k = 0; k < m; k++) {
        rf_joint_info *ji = &a->joints[js[k]];
        if (rf_v3_len2(ji->dir) > 0)
            carry = ji->dir;
        else
            ji->dir = carry;
    }
}

static double body_pos(const rf_awork *w, rf_vec3 p)
{
    const rf_analysis *a = w->a;
    if (w->rear < 0)
        return 0.5;
    rf_vec3 r = rf_an_pos(w, (uint32_t)w->rear), f = rf_an_pos(w, (uint32_t)w->front);
    rf_vec3 axis = rf_v3_sub(f, r);
    double l2 = rf_v3_len2(axis);
    if (l2 <= w->eps * w->eps)
        return 0.5 + rf_v3_dot(rf_v3_sub(p, r), a->forward) / a->size;
    return rf_v3_dot(rf_v3_sub(p, r), axis) / l2;
}

/* ---- ranks ---- */

typedef struct rf_rank_item {
    uint64_t group;
    double order;
    uint32_t sec;
} rf_rank_item;

static int cmp_rank(const void *x, const void *y)
{
    const rf_rank_item *a = x, *b = y;
    if (a->group != b->group)
        return a->group < b->group ? -1 : 1;
    if (a->order != b->order)
        return a->order > b->order ? -1 : 1;
    return a->sec < b->sec ? -1 : a->sec > b->sec;
}

/* Where a fan's digits start: the end of the bone they fan out of (the wrist). */
static rf_vec3 fan_origin(const rf_awork *w, const rf_section *sec)
{
    if (sec->attach_joint < 0)
        return rf_an_pos(w, w->a->section_joints[sec->first]);
    /* a hand bone's guessed tip (no end site, several children) may lie past its fingers'
     * ends: the wrist then */
    const rf_joint_info *hand = &w->a->joints[sec->attach_joint];
    return (hand->flags & RF_JI_TIP_GUESSED) ? hand->pos : hand->tip;
}

/* Where a digit ends: its last tip, or its last pivot when that tip is only a guess. */
static rf_vec3 digit_end(const rf_awork *w, uint32_t last)
{
    const rf_joint_info *ji = &w->a->joints[last];
    bool guessed = (ji->flags & RF_JI_TIP_GUESSED) && rf_v3_dist(ji->pos, ji->tip) > 0;
    return guessed && ji->index > 0 ? ji->pos : ji->tip;
}

/* Limbs rank front to back among their type and side; digits rank forward-most first within
 * their fan (fan_ranks then puts a thumb first). */
static bool ranks(rf_awork *w)
{
    rf_analysis *a = w->a;
    rf_rank_item *it = malloc((size_t)(a->section_count ? a->section_count : 1) * sizeof *it);
    if (!it)
        return false;
    uint32_t n = 0;
    for (uint32_t s = 0; s < a->section_count; s++) {
        rf_section *sec = &a->sections[s];
        if (center_type(sec->type) || sec->type == RF_SECTION_HELPER)
            continue;
        rf_rank_item *r = &it[n++];
        r->sec = s;
        if (sec->flags & RF_SECFL_FAN) {
            uint32_t last = a->section_joints[sec->first + sec->bone_count - 1];
            rf_vec3 v = rf_v3_normalize(rf_v3_sub(digit_end(w, last), fan_origin(w, sec)));
            r->group = (1ull << 40) | (uint32_t)(sec->attach_joint + 1);
            r->order = rf_v3_dot(v, a->forward) + 0.5 * rf_v3_dot(v, a->up);
        } else {
            r->group = ((uint64_t)sec->type << 8) | sec->side;
            r->order = sec->body_pos;
        }
    }
    qsort(it, n, sizeof *it, cmp_rank);
    for (uint32_t i = 0; i < n;) {
        uint32_t e = i;
        while (e < n && it[e].group == it[i].group)
            e++;
        for (uint32_t k = i; k < e; k++) {
            a->sections[it[k].sec].pair_rank = k - i;
            a->sections[it[k].sec].pair_count = e - i;
        }
        i = e;
    }
    free(it);
    return true;
}

static void mirror_sections(rf_awork *w)
{
    rf_analysis *a = w->a;
    for (uint32_t s = 0; s < a->section_count; s++) {
        rf_section *sec = &a->sections[s];
        if (sec->side == RF_SIDE_CENTER)
            continue;
        for (uint32_t k = 0; k < sec->bone_count; k++) {
            int32_t m = a->joints[a->section_joints[sec->first + k]].mirror;
            if (m < 0 || a->joints[m].section < 0)
                continue;
            rf_section *o = &a->sections[a->joints[m].section];
            if (o->type == sec->type && o->side != sec->side && o->side != RF_SIDE_CENTER)
                sec->mirror = a->joints[m].section;
            break;
        }
    }
}

/* The thumb stands apart: of a fan's digits, the one turned furthest from the line of the limb,
 * by 20 degrees more than any other. It takes rank 0, the others keep their order after it. */
static void find_thumb(rf_awork *w, uint32_t *fan, uint32_t n)
{
    rf_analysis *a = w->a;
    const rf_section *first = &a->sections[fan[0]];
    if (n < 2 || first->parent < 0 || (a->sections[first->parent].flags & RF_SECFL_FAN))
        return; /* thumbs are on hands and feet, not on fans within a digit */
    rf_vec3 o = fan_origin(w, first);
    rf_vec3 axis = rf_v3_normalize(
        rf_v3_sub(o, rf_an_pos(w, a->section_joints[a->sections[first->parent].first])));
    if (rf_v3_len2(axis) == 0)
        return;
    double best = -1, second = -1;
    uint32_t thumb = 0;
    for (uint32_t i = 0; i < n; i++) {
        const rf_section *sec = &a->sections[fan[i]];
        uint32_t last = a->section_joints[sec->first + sec->bone_count - 1];
        double dev = rf_v3_angle(rf_v3_sub(digit_end(w, last), o), axis);
        if (dev > best)
            second = best, best = dev, thumb = i;
        else if (dev > second)
            second = dev;
    }
    if (best - second < 20.0 * RF_PI / 180.0)
        return;
    rf_section *t = &a->sections[fan[thumb]];
    for (uint32_t i = 0; i < n; i++)
        if (a->sections[fan[i]].pair_rank < t->pair_rank)
            a->sections[fan[i]].pair_rank++;
    t->pair_rank = 0;
    t->flags |= RF_SECFL_THUMB;
}

static int cmp_pair(const void *x, const void *y)
{
    const uint64_t a = *(const uint64_t *)x, b = *(const uint64_t *)y;
    return a < b ? -1 : a > b;
}

/* Digits grouped by the joint their fan hangs from (attach joint in the high bits, section in
 * the low ones, sorted). */
static bool fan_ranks(rf_awork *w)
{
    rf_analysis *a = w->a;
    uint64_t *key = malloc((size_t)(a->section_count ? a->section_count : 1) * sizeof *key);
    uint32_t *fan = malloc((size_t)(a->section_count ? a->section_count : 1) * sizeof *fan);
    if (!key || !fan) {
        free(key);
        free(fan);
        return false;
    }
    uint32_t n = 0;
    for (uint32_t s = 0; s < a->section_count; s++)
        if (a->sections[s].flags & RF_SECFL_FAN)
            key[n++] = ((uint64_t)(uint32_t)(a->sections[s].attach_joint + 1) << 32) | s;
    qsort(key, n, sizeof *key, cmp_pair);
    for (uint32_t i = 0; i < n;) {
        uint32_t e = i;
        while (e < n && key[e] >> 32 == key[i] >> 32)
            fan[e] = (uint32_t)key[e], e++;
        find_thumb(w, fan + i, e - i);
        i = e;
    }
    free(key);
    free(fan);
    return true;
}

static bool limb_type(rf_section_type t)
{
    return t == RF_SECTION_ARM || t == RF_SECTION_LEG;
}

/* Limbs ending in a fan are measured again to the end of their longest digit. */
static bool extend_by_digits(rf_awork *w)
{
    rf_analysis *a = w->a;
    double *longest = calloc(w->n ? w->n : 1, sizeof *longest);
    if (!longest)
        return false;
    for (uint32_t s = 0; s < a->section_count; s++) {
        const rf_section *sec = &a->sections[s];
        if ((sec->flags & RF_SECFL_FAN) && sec->attach_joint >= 0) {
            /* beyond the hand bone (its tip, or its knuckles when that tip is a guess) */
            double from_tip = sec->length;
            if (fan_from_wrist(w, sec))
                from_tip = fmax(0, from_tip - hand_length(w, (uint32_t)sec->attach_joint));
            longest[sec->attach_joint] = fmax(longest[sec->attach_joint], from_tip);
        }
    }
    for (uint32_t s = 0; s < a->section_count; s++) {
        rf_section *sec = &a->sections[s];
        uint32_t last = a->section_joints[sec->first + sec->bone_count - 1];
        if (limb_type(sec->type) && !(sec->flags & RF_SECFL_FAN) && longest[last] > 0)
            measure_section(w, sec, longest[last]);
    }
    free(longest);
    return true;
}

/* A limb's first bone, short, shorter than the next, starting near where the limb leaves the
 * body and running sideways (or very short), is an offset: a clavicle, or a hip bone from the
 * pelvis centre to the socket. Many rigs have none, so the matcher keeps offsets for offsets. */
static void mark_offsets(rf_awork *w)
{
    rf_analysis *a = w->a;
    for (uint32_t s = 0; s < a->section_count; s++) {
        const rf_section *sec = &a->sections[s];
        if (!limb_type(sec->type) || (sec->flags & RF_SECFL_FAN) || sec->bone_count < 2)
            continue;
        uint32_t j = a->section_joints[sec->first];
        rf_joint_info *ji = &a->joints[j];
        const rf_joint_info *next = &a->joints[a->section_joints[sec->first + 1]];
        double len = (ji->u1 - ji->u0) * sec->length, limb = sec->length;
        double after = (next->u1 - next->u0) * sec->length;
        bool tiny = len < 0.1 * limb;
        bool near = rf_v3_dist(ji->pos, w->attach_pt[j]) <= 0.3 * limb;
        bool sideways = fabs(rf_v3_dot(ji->dir, a->left)) >= 0.5;
        /* shorter than the bone after it: an upper arm is not, a clavicle is */
        if (len < 0.35 * limb && (tiny || (near && sideways && len < 0.8 * after)))
            ji->flags |= RF_JI_OFFSET;
    }
}

/* Real bones of a leg down to its ground contact: offsets and a last bone lying flat on the
 * ground (a toe) left out. */
static uint32_t leg_bones(const rf_awork *w, const rf_section *sec)
{
    const rf_analysis *a = w->a;
    uint32_t n = 0;
    for (uint32_t k = 0; k < sec->bone_count; k++) {
        const rf_joint_info *ji = &a->joints[a->section_joints[sec->first + k]];
        bool toe = k + 1 == sec->bone_count && fabs(rf_v3_dot(ji->dir, a->up)) < 0.5;
        n += !(ji->flags & RF_JI_OFFSET) && !toe && ji->length > w->eps;
    }
    return n;
}

/* A quadruped's foreleg with one real bone more than the hind leg on its side, beginning at the
 * top of the body and running forward and down to a bone running back: that first bone is the
 * scapula, a girdle bone like a clavicle (forelegs hang from a shoulder blade; hind legs join
 * the pelvis directly). */
static void mark_scapulae(rf_awork *w)
{
    rf_analysis *a = w->a;
    for (uint32_t s = 0; s < a->section_count; s++) {
        const rf_section *fore = &a->sections[s];
        if (fore->type != RF_SECTION_LEG || (fore->flags & RF_SECFL_FAN) || fore->bone_count < 3)
            continue;
        for (uint32_t h = 0; h < a->section_count; h++) {
            const rf_section *hind = &a->sections[h];
            if (h == s || hind->type != RF_SECTION_LEG || (hind->flags & RF_SECFL_FAN) ||
                hind->side != fore->side || hind->body_pos > fore->body_pos - 0.5)
                continue;
            rf_joint_info *first = &a->joints[a->section_joints[fore->first]];
            const rf_joint_info *second = &a->joints[a->section_joints[fore->first + 1]];
            bool down = rf_v3_dot(first->dir, a->up) < -0.5;
            bool top = rf_an_height(w, first->pos) >= a->ground + 0.75 * a->height;
            /* the shoulder blade slopes forward and down to the shoulder joint, the upper arm
             * back and down to the elbow */
            bool vee =
                rf_v3_dot(first->dir, a->forward) > 0.1 && rf_v3_dot(second->dir, a->forward) < 0;
            /* or it starts on the back, no lower than the joint it hangs from and nearer the
             * centerline than the shoulder joint below it (a blade laid on the ribs) */
            uint32_t fj = a->section_joints[fore->first];
            double in = fabs(rf_v3_dot(rf_v3_sub(first->pos, w->plane_p), a->left));
            double out = fabs(rf_v3_dot(rf_v3_sub(second->pos, w->plane_p), a->left));
            bool blade =
                rf_an_height(w, first->pos) >= rf_an_height(w, w->attach_pt[fj]) && in < 0.5 * out;
            if (!(first->flags & RF_JI_OFFSET) && down && ((top && vee) || blade) &&
                leg_bones(w, fore) == leg_bones(w, hind) + 1)
                first->flags |= RF_JI_OFFSET;
        }
    }
}

bool rf_an_measure(rf_awork *w)
{
    rf_analysis *a = w->a;
    for (uint32_t s = 0; s < a->section_count; s++) {
        rf_section *sec = &a->sections[s];
        uint32_t first = a->section_joints[sec->first];
        sec->side = section_side(w, sec, first);
        measure_section(w, sec, 0);
        directions(w, sec);
        /* A limb sits where it leaves the body: its girdle when the body has two, else where
         * its first joint is (four legs on one torso joint). */
        bool own = !center_type(sec->type) && w->rear == w->front;
        sec->body_pos = body_pos(w, own ? rf_an_pos(w, first) : start_point(w, sec, first));
        for (uint32_t k = 0; k < sec->bone_count; k++) {
            rf_joint_info *ji = &a->joints[a->section_joints[sec->first + k]];
            ji->index = k;
            ji->side = sec->side;
        }
    }
    if (!extend_by_digits(w))
        return false;
    mark_offsets(w);
    mark_scapulae(w);
    mirror_sections(w);
    return ranks(w) && fan_ranks(w);
}
