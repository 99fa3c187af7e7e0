/* Skeleton analysis, stage 3: up, forward and left.
 *
 * Up lies in the symmetry plane. Of the four in-plane directions, up is the one the limbs hang
 * away from: weighted by how much of each limb's reach points down and how steadily its chain
 * descends (a wing, a limb ending in a fan of long digits, at half weight; a limb short of the
 * ground by the share of its reach in that plane, hang_share), plus a bonus when a
 * mirrored pair of limbs touches the lowest level (feet on the ground), one for the ground the feet
 * span when the body stands over them, and one for the axis the file declares (RF_FILE_UP_VOTE,
 * deciding close calls). Forward is
 * then one of two directions; its sign is voted by the feet (toes point forward), by the knees of a
 * biped, the head marks, the ends' heights, the girdles, the hierarchy and by the file. Without
 * a declared forward nothing is read from the coordinate axes, so a body turned about its up
 * reads the same facing relative to itself (tests/match/test_facing). */
#include <math.h>
#include <stdlib.h>

#include "analysis-internal.h"

typedef struct rf_limb {
    uint32_t root;
    uint32_t end;     /* joint whose tip is farthest from the attachment */
    rf_vec3 attach;   /* where the limb leaves the body */
    rf_vec3 far;      /* that farthest tip */
    double lowest[4]; /* lowest height under each up candidate */
    double out[4];    /* how far from the attachment that lowest point is */
    double reach;     /* farthest tip, guessed ones included, from the attachment */
    uint32_t joints;
    double vote; /* its weight in the limbs cue: less for a wing (fan_vote) */
    int touch;   /* the last up candidate (1..4) under which it touched the ground */
    bool leg;
} rf_limb;

typedef struct rf_limbs {
    rf_limb *v;
    uint32_t n;
    int32_t *slot; /* limb index of each limb root */
} rf_limbs;

/* A limb's direction is measured from its own first pivot: the offset from its parent says
 * little (a clavicle, or a root node at the origin the limb hangs from). */
static rf_vec3 attach_point(const rf_awork *w, uint32_t root)
{
    return rf_an_pos(w, root);
}

static bool collect_limbs(const rf_awork *w, rf_limbs *ls)
{
    ls->v = calloc(w->n ? w->n : 1, sizeof *ls->v);
    ls->slot = malloc((size_t)(w->n ? w->n : 1) * sizeof *ls->slot);
    if (!ls->v || !ls->slot)
        return false;
    ls->n = 0;
    for (uint32_t i = 0; i < w->order_count; i++) {
        uint32_t j = w->order[i];
        int32_t r = w->limb_of[j];
        if (r < 0)
            continue;
        if ((uint32_t)r == j) {
            ls->slot[j] = (int32_t)ls->n;
            rf_limb *l = &ls->v[ls->n++];
            l->root = j, l->end = j;
            l->attach = attach_point(w, j);
            l->far = rf_an_pos(w, j);
        }
        /* only measured points: a guessed tip would decide by its guess */
        rf_limb *l = &ls->v[ls->slot[r]];
        const rf_joint_info *ji = &w->a->joints[j];
        rf_vec3 tip = (ji->flags & RF_JI_TIP_GUESSED) ? ji->pos : ji->tip;
        if (rf_v3_dist(tip, l->attach) > rf_v3_dist(l->far, l->attach))
            l->far = tip, l->end = j;
        l->reach = fmax(l->reach, rf_v3_dist(ji->tip, l->attach));
        l->joints++;
    }
    return true;
}

/* The deepest joint both a and b hang from; depth[] counts joints below the limb's first. */
static uint32_t limb_common(const rf_awork *w, const uint32_t *depth, uint32_t a, uint32_t b)
{
    while (depth[a] > depth[b])
        a = (uint32_t)w->parent[a];
    while (depth[b] > depth[a])
        b = (uint32_t)w->parent[b];
    while (a != b && depth[a] > 0)
        a = (uint32_t)w->parent[a], b = (uint32_t)w->parent[b];
    return a;
}

/* Per limb, the joint its far leaves (tips past 0.6 of its reach: digits, toes, a claw) fan
 * from, or UINT32_MAX when it has fewer than two. False when out of memory. */
static bool far_fans(const rf_awork *w, const rf_limbs *ls, uint32_t *depth, uint32_t *fan)
{
    uint32_t *count = calloc(ls->n ? ls->n : 1, sizeof *count);
    for (uint32_t i = 0; i < ls->n; i++)
        fan[i] = UINT32_MAX;
    if (!count)
        return false;
    for (uint32_t k = 0; k < w->order_count; k++) {
        uint32_t j = w->order[k];
        if (w->limb_of[j] < 0)
            continue;
        int32_t i = ls->slot[w->limb_of[j]];
        const rf_limb *l = &ls->v[i];
        depth[j] = j == l->root ? 0 : depth[w->parent[j]] + 1;
        if (!rf_an_is_leaf(w, j) || rf_v3_dist(w->a->joints[j].tip, l->attach) < 0.6 * l->reach)
            continue;
        fan[i] = count[i]++ ? limb_common(w, depth, fan[i], j) : j;
    }
    for (uint32_t i = 0; i < ls->n; i++)
        if (count[i] < 2)
            fan[i] = UINT32_MAX;
    free(count);
    return true;
}

/* A wing votes half for up: a limb whose far leaves (two or more) fan from a joint carrying three
 * or more leaves and reach over 0.35 of the limb's reach from it (membrane fingers; not toes,
 * claws or fingers, a tenth of a leg or arm long). Folded back, a wing three times a leg's reach
 * would otherwise outvote legs that do hang. Linear: one pass for the fans, one for the digits.
 * False when out of memory (every limb would vote whole). */
static bool fan_vote(const rf_awork *w, rf_limbs *ls)
{
    uint32_t *depth = calloc(w->n ? w->n : 1, sizeof *depth);
    uint32_t *fan = malloc((size_t)(ls->n ? ls->n : 1) * sizeof *fan);
    double *digit = calloc(ls->n ? ls->n : 1, sizeof *digit);
    uint32_t *leaves = calloc(ls->n ? ls->n : 1, sizeof *leaves);
    bool *under = calloc(w->n ? w->n : 1, sizeof *under);
    for (uint32_t i = 0; i < ls->n; i++)
        ls->v[i].vote = 1;
    bool ok = depth && fan && digit && leaves && under && far_fans(w, ls, depth, fan);
    if (ok) {
        for (uint32_t k = 0; k < w->order_count; k++) {
            uint32_t j = w->order[k];
            if (w->limb_of[j] < 0)
                continue;
            int32_t i = ls->slot[w->limb_of[j]];
            under[j] = j == fan[i] || (j != ls->v[i].root && under[w->parent[j]]);
            if (!under[j])
                continue;
            digit[i] = fmax(digit[i], rf_v3_dist(w->a->joints[j].tip, rf_an_pos(w, fan[i])));
            leaves[i] += rf_an_is_leaf(w, j);
        }
        for (uint32_t i = 0; i < ls->n; i++)
            if (leaves[i] >= 3 && digit[i] > 0.35 * ls->v[i].reach)
                ls->v[i].vote = 0.5;
    }
    free(depth), free(fan), free(digit), free(leaves), free(under);
    return ok;
}

/* Share of the limb's height change along its path (root to far end) that goes down along u. */
static double descent(const rf_awork *w, const rf_limb *l, rf_vec3 u)
{
    double down = 0, total = 0;
    rf_vec3 below = l->far;
    uint32_t j = l->end;
    for (uint32_t step = 0; step < w->n; step++) {
        rf_vec3 above = rf_an_pos(w, j);
        double dh = rf_v3_dot(rf_v3_sub(below, above), u);
        down += fmax(0, -dh), total += fabs(dh);
        below = above;
        if (j == l->root)
            break;
        j = (uint32_t)w->parent[j];
    }
    return total > 0 ? down / total : 0;
}

/* Marks the limbs that touch the ground under candidate `cand`: their lowest point lies within
 * `tol` (or 12% of their reach) of the lowest limb point `lo`, far out along the limb (a foot,
 * not a sprawled leg's knee when the body is turned over; a one-joint limb is a foot of its own).
 * Returns their count and adds their reach to *reach. */
static uint32_t touch_ground(rf_limbs *ls, int cand, double lo, double tol, double *reach)
{
    uint32_t touching = 0;
    for (uint32_t i = 0; i < ls->n; i++) {
        rf_limb *l = &ls->v[i];
        bool far = l->out[cand] >= 0.6 * l->reach || l->joints == 1;
        if (far && l->lowest[cand] <= lo + fmax(tol, 0.12 * l->reach))
            l->touch = cand + 1, touching++, *reach += l->reach;
    }
    return touching;
}

/* Whether a centerline joint lies under the ground level: no body stands on its head. */
static bool body_below(const rf_awork *w, rf_vec3 u, double ground)
{
    for (uint32_t i = 0; i < w->order_count; i++) {
        uint32_t j = w->order[i];
        if (w->center[j] && !w->root_chain[j] && rf_v3_dot(rf_an_pos(w, j), u) < ground)
            return true;
    }
    return false;
}

/* The ground the body stands on, 0..1. Under the right up, the lowest points of two or more
 * limbs span an area, across the body and along it (feet with toes, a quadruped's four feet,
 * an insect's six), and the body stands over them: its mean pivot lies within their span along
 * the body, give or take a limb's reach. Under a wrong up the lowest points are the ends of one
 * mirrored pair (wing tips, a foreleg pair's toes: a segment across the body) or the body
 * itself lies lower (a head under raised hands). Measured against the touching limbs' mean
 * reach: any scale, any bone count. */
static double ground_support(const rf_awork *w, rf_limbs *ls, rf_vec3 u, int cand, double lo,
                             double hi)
{
    rf_vec3 c = rf_v3_normalize(rf_v3_cross(w->plane_n, u));
    double tol = 0.05 * (hi - lo), reach = 0;
    uint32_t touching = touch_ground(ls, cand, lo, tol, &reach);
    if (touching < 2 || reach <= 0 || body_below(w, u, lo - tol))
        return 0;
    double xlo = INFINITY, xhi = -INFINITY, ylo = INFINITY, yhi = -INFINITY;
    rf_vec3 sum = rf_v3(0, 0, 0);
    for (uint32_t i = 0; i < w->order_count; i++) {
        uint32_t j = w->order[i];
        sum = rf_v3_add(sum, rf_an_pos(w, j));
        const rf_limb *l = w->limb_of[j] >= 0 ? &ls->v[ls->slot[w->limb_of[j]]] : NULL;
        if (!l || l->touch != cand + 1)
            continue;
        const rf_joint_info *ji = &w->a->joints[j];
        /* a guessed tip points the right way in a rig with a bone axis (a toe's end) */
        bool guessed = (ji->flags & RF_JI_TIP_GUESSED) && w->conv_axis < 0;
        for (int e = 0; e < 2 - guessed; e++) {
            rf_vec3 p = e ? ji->tip : ji->pos;
            if (rf_v3_dot(p, u) > lo + fmax(tol, 0.12 * l->reach))
                continue;
            double x = rf_v3_dot(p, w->plane_n), y = rf_v3_dot(p, c);
            xlo = fmin(xlo, x), xhi = fmax(xhi, x), ylo = fmin(ylo, y), yhi = fmax(yhi, y);
        }
    }
    double unit = reach / touching, mid = rf_v3_dot(sum, c) / w->order_count;
    double stand = fmax(0, 1 - fmax(0, fmax(ylo - mid, mid - yhi)) / unit);
    return stand * fmin(1, fmin(xhi - xlo, yhi - ylo) / (0.15 * unit));
}

/* How much of a limb's in-plane drop counts as hanging: all of it for a limb reaching the ground
 * level `floor` (a leg stands on its foot, however far it splays: an insect's), else the share of
 * its reach that lies in the mirror plane. A level wing swept a little back reaches mostly
 * sideways: counted whole, its small backward part read the animalia bat lying on its belly as
 * standing on its tail. */
static double hang_share(const rf_limb *l, rf_vec3 full, rf_vec3 in_plane, int cand, double floor)
{
    double len = rf_v3_len(full);
    if (l->lowest[cand] <= floor || len <= 0)
        return 1;
    return rf_v3_len(in_plane) / len;
}

/* How well u explains the limbs as hanging down (0..1), plus 0.15 per limb (up to four) when two
 * or more reach the lowest level (feet on the ground: four legs say more than two wing tips) and
 * up to 0.45 more as their end bones lie flat (feet, not tips pointing down: a bird's flat toes
 * outvote its longer folded wings), plus up to 0.8 for the ground the feet span
 * (ground_support). The lowest level is the lowest limb's: a mesh node or ground root at the
 * origin says nothing. */
static void up_score(const rf_awork *w, rf_limbs *ls, rf_vec3 u, int cand, double *cue)
{
    double hang = 0, reach = 0, lo = INFINITY, hi = -INFINITY;
    for (uint32_t i = 0; i < ls->n; i++)
        lo = fmin(lo, ls->v[i].lowest[cand]);
    for (uint32_t i = 0; i < w->order_count; i++) {
        const rf_joint_info *ji = &w->a->joints[w->order[i]];
        hi = fmax(hi, fmax(rf_v3_dot(ji->pos, u), rf_v3_dot(ji->tip, u)));
    }
    for (uint32_t i = 0; i < ls->n; i++) {
        rf_vec3 full = rf_v3_sub(ls->v[i].far, ls->v[i].attach);
        rf_vec3 v = rf_v3_sub(full, rf_v3_scale(w->plane_n, rf_v3_dot(full, w->plane_n)));
        reach += ls->v[i].vote * rf_v3_len(v);
        hang += ls->v[i].vote * hang_share(&ls->v[i], full, v, cand, lo + 0.05 * (hi - lo)) *
                descent(w, &ls->v[i], u) * fmax(0, -rf_v3_dot(v, u));
    }
    uint32_t grounded = 0;
    double flat = 0;
    for (uint32_t i = 0; i < ls->n; i++) {
        const rf_limb *l = &ls->v[i];
        double drop = rf_v3_dot(l->attach, u) - l->lowest[cand]; /* a leg reaches down to it */
        if (l->lowest[cand] > lo + 0.05 * (hi - lo) || l->out[cand] < 0.6 * l->reach ||
            drop < 0.5 * l->reach)
            continue;
        const rf_joint_info *end = &w->a->joints[ls->v[i].end];
        rf_vec3 d = rf_v3_normalize(rf_v3_sub(end->tip, end->pos));
        grounded++;
        flat += fabs(rf_v3_dot(d, u)) < 0.8;
    }
    double bonus = grounded >= 2 ? 0.15 * fmin(grounded, 4) + 0.45 * flat / grounded : 0;
    cue[0] = (reach > 0 ? hang / reach : 0) + bonus;
    cue[1] = 0.8 * ground_support(w, ls, u, cand, lo, hi);
}

/* Each limb's lowest measured point (pivots, known tips) under each candidate, and how far out
 * along the limb it is: a leg stands on its foot, while seen along the body its hip may be its
 * lowest point. */
static void limb_lowest(const rf_awork *w, rf_limbs *ls, const rf_vec3 *cands)
{
    for (uint32_t i = 0; i < ls->n; i++)
        for (int c = 0; c < 4; c++)
            ls->v[i].lowest[c] = INFINITY, ls->v[i].out[c] = 0;
    for (uint32_t i = 0; i < w->order_count; i++) {
        uint32_t j = w->order[i];
        if (w->limb_of[j] < 0)
            continue;
        rf_limb *l = &ls->v[ls->slot[w->limb_of[j]]];
        const rf_joint_info *ji = &w->a->joints[j];
        bool guessed = (ji->flags & RF_JI_TIP_GUESSED) != 0;
        for (int c = 0; c < 4; c++)
            for (int e = 0; e < 2 - guessed; e++) {
                rf_vec3 p = e ? ji->tip : ji->pos;
                double h = rf_v3_dot(p, cands[c]);
                if (h < l->lowest[c])
                    l->lowest[c] = h, l->out[c] = rf_v3_dist(p, l->attach);
            }
    }
}

static rf_vec3 perpendicular_to(rf_vec3 n, rf_vec3 hint)
{
    rf_vec3 a = rf_v3_sub(hint, rf_v3_scale(n, rf_v3_dot(hint, n)));
    if (rf_v3_len(a) < 1e-6)
        a = rf_v3_sub(rf_v3(1, 0, 0), rf_v3_scale(n, n.x));
    if (rf_v3_len(a) < 1e-6)
        a = rf_v3_sub(rf_v3(0, 0, 1), rf_v3_scale(n, n.z));
    return rf_v3_normalize(a);
}

/* The axes an in-plane up candidate snaps to: the body's reference axes, or with a declared up
 * but no forward, that up and the plane's normal laid level (the coordinate axes would tilt the
 * up of a body turned about it, whose plane then is no longer near one of them). */
static void snap_axes(const rf_awork *w, rf_vec3 n, rf_vec3 axes[3])
{
    rf_an_frame(w, axes);
    rf_vec3 u = w->skel->up, f = w->skel->forward;
    bool up_only = !w->opt.ignore_file_axes && rf_v3_isfinite(u) && rf_v3_len2(u) > 1e-24 &&
                   !(rf_v3_isfinite(f) && rf_v3_len2(f) > 1e-24) && rf_v3_len2(w->opt.up) == 0 &&
                   rf_v3_len2(w->opt.forward) == 0;
    if (!up_only)
        return;
    u = rf_v3_normalize(u);
    rf_vec3 l = rf_v3_sub(n, rf_v3_scale(u, rf_v3_dot(n, u)));
    if (rf_v3_len(l) < 0.5) /* the plane lies level: keep the coordinate axes */
        return;
    axes[0] = rf_v3_normalize(l), axes[1] = u, axes[2] = rf_v3_normalize(rf_v3_cross(axes[0], u));
}

/* The four in-plane candidates: the body's reference axes (rf_an_frame) when the plane is
 * aligned with one of them. Snapping to the coordinate axes instead read a rig turned 30 degrees
 * with its declared axes another way than the same rig unturned: the unturned plane, 4 degrees
 * off x, snapped up to +y, the turned one kept its tilt and the spine read as an arm. */
static void up_candidates(const rf_awork *w, rf_vec3 *c)
{
    rf_vec3 axes[3], n = w->plane_n;
    snap_axes(w, n, axes);
    rf_vec3 hint = axes[1];
    double nx = fabs(rf_v3_dot(n, axes[0])), ny = fabs(rf_v3_dot(n, axes[1])),
           nz = fabs(rf_v3_dot(n, axes[2]));
    int k = nx >= ny && nx >= nz ? 0 : ny >= nz ? 1 : 2;
    bool aligned = fabs(rf_v3_dot(n, axes[k])) >= cos(10.0 * RF_PI / 180.0);
    if (aligned)
        hint = axes[k == 1 ? 2 : 1];
    if (rf_v3_len2(w->skel->up) > 0 && !w->opt.ignore_file_axes && rf_v3_isfinite(w->skel->up))
        hint = w->skel->up;
    rf_vec3 a = perpendicular_to(n, hint);
    if (aligned) { /* snap a to the nearest axis other than the plane's */
        int m = (k + 1) % 3;
        int o = (k + 2) % 3;
        m = fabs(rf_v3_dot(a, axes[m])) >= fabs(rf_v3_dot(a, axes[o])) ? m : o;
        a = rf_v3_scale(axes[m], rf_v3_dot(a, axes[m]) >= 0 ? 1 : -1);
    }
    rf_vec3 b = rf_v3_normalize(rf_v3_cross(n, a));
    c[0] = a, c[1] = rf_v3_scale(a, -1), c[2] = b, c[3] = rf_v3_scale(b, -1);
}

static bool file_up(const rf_awork *w, rf_vec3 *up)
{
    rf_vec3 u = w->skel->up;
    if (w->opt.ignore_file_axes || !rf_v3_isfinite(u) || rf_v3_len2(u) == 0)
        return false;
    *up = rf_v3_normalize(u);
    return true;
}

const char *const rf_up_cue_names[RF_UP_CUE_COUNT] = {"limbs", "ground", "file"};

/* Each cue's score for the up chosen against its best score for another candidate. */
static void up_cues(rf_analysis *a, double cue[4][RF_UP_CUE_COUNT], int best)
{
    for (int i = 0; i < RF_UP_CUE_COUNT; i++) {
        double other = 0;
        for (int c = 0; c < 4; c++)
            if (c != best)
                other = fmax(other, cue[c][i]);
        a->up_cues[i] = cue[best][i] - other;
    }
}

int rf_up_dissent(const rf_analysis *a)
{
    /* a close call (the runner-up within a quarter of the winner) names any cue that preferred
     * another axis; a clear one only a cue that preferred it by half a full vote */
    double bar = a->up_confidence < 0.25 ? 0 : -0.5;
    int worst = -1;
    for (int i = 0; i < RF_UP_CUE_COUNT; i++)
        if (a->up_cues[i] < bar && (worst < 0 || a->up_cues[i] < a->up_cues[worst]))
            worst = i;
    return worst;
}

/* The declared up's vote: it decides close calls between the limbs' readings. A body lying
 * level with its limbs flat (a bat on its belly, wings spread; a wyvern's curve skeleton with
 * wings laid out) has its limbs hang nearly as well under the axis it lies along as under its
 * real up, and 0.3 let the animalia bat's and the general rigger's jungle wyvern stand on their
 * tails; 0.45 reads both right. It stays well under what the limbs and ground of a plain body
 * give (0.8 also stood the artist's bat right, but cost the retarget sweep two passing runs). */
#define RF_FILE_UP_VOTE 0.45

static void detect_up(rf_awork *w, rf_limbs *ls)
{
    rf_analysis *a = w->a;
    rf_vec3 cands[4], fu;
    up_candidates(w, cands);
    limb_lowest(w, ls, cands);
    bool have_file = file_up(w, &fu);
    /* Limbs measured over little of the body (single leaf bones) are weak evidence: the axis
     * the file declares then weighs more. So are limbs reaching mostly sideways, out of the
     * mirror plane the candidates lie in (wings spread level, arms in a T): their weight is the
     * share of their reach that lies in the plane. */
    double extent = 0, span = 0;
    for (uint32_t i = 0; i < ls->n; i++) {
        rf_vec3 v = rf_v3_sub(ls->v[i].far, ls->v[i].attach);
        extent += rf_v3_len(rf_v3_sub(v, rf_v3_scale(w->plane_n, rf_v3_dot(v, w->plane_n))));
        span += rf_v3_len(v);
    }
    double strength = fmin(1, extent / (0.3 * a->size)) * (span > 0 ? extent / span : 1);
    double score[4], cue[4][RF_UP_CUE_COUNT] = {{0}};
    int best = 0;
    for (int c = 0; c < 4; c++) {
        if (ls->n)
            up_score(w, ls, cands[c], c, cue[c]);
        cue[c][0] *= strength, cue[c][1] *= strength;
        cue[c][2] = have_file && rf_v3_dot(cands[c], fu) > 0.9 ? RF_FILE_UP_VOTE : 0;
        score[c] = cue[c][0] + cue[c][1] + cue[c][2];
        if (score[c] > score[best])
            best = c;
    }
    up_cues(a, cue, best);
    double second = 0;
    for (int c = 0; c < 4; c++)
        if (c != best)
            second = fmax(second, score[c]);
    a->up = cands[best];
    if (ls->n == 0) {
        for (int i = 0; i < RF_UP_CUE_COUNT; i++)
            a->up_cues[i] = 0;
        a->up = have_file ? perpendicular_to(w->plane_n, fu) : cands[0];
        a->up_source = have_file ? "file" : "default";
        a->up_confidence = 0;
        return;
    }
    a->up_source = "limbs";
    a->up_confidence = score[best] > 0 ? fmin(1, fmax(0, (score[best] - second) / score[best])) : 0;
}

/* ---- forward ---- */

typedef struct rf_votes {
    double feet, knees;
} rf_votes;

/* The points of a limb's path, root first, into pts; returns their count (pivots and far tip). */
static uint32_t limb_path(const rf_awork *w, const rf_limb *l, rf_vec3 *pts, uint32_t max)
{
    uint32_t count = 0, j = l->end;
    pts[count++] = l->far;
    for (uint32_t step = 0; step < w->n && count < max; step++) {
        pts[count++] = rf_an_pos(w, j);
        if (j == l->root || w->parent[j] < 0)
            break;
        j = (uint32_t)w->parent[j];
    }
    for (uint32_t i = 0; i < count / 2; i++) { /* reverse: root first */
        rf_vec3 t = pts[i];
        pts[i] = pts[count - 1 - i];
        pts[count - 1 - i] = t;
    }
    return count;
}

/* The centerline stands taller than it is long (a biped, not a dragon on two legs). */
static bool upright(const rf_awork *w)
{
    double lo = INFINITY, hi = -INFINITY, back = INFINITY, front = -INFINITY;
    rf_vec3 c = rf_v3_normalize(rf_v3_cross(w->plane_n, w->a->up));
    for (uint32_t i = 0; i < w->order_count; i++) {
        uint32_t j = w->order[i];
        if (!w->center[j] || w->root_chain[j])
            continue;
        double h = rf_an_height(w, rf_an_pos(w, j)), x = rf_v3_dot(rf_an_pos(w, j), c);
        lo = fmin(lo, h), hi = fmax(hi, h), back = fmin(back, x), front = fmax(front, x);
    }
    return hi - lo > front - back;
}

/* The joint at a limb's far point: its end, or a leaf whose tip is only guessed sitting where the
 * end's bone ends (the far point counts a guessed leaf by its pivot, which its parent's tip
 * reached first: a foot bone without an end site under a shin). */
static uint32_t far_leaf(const rf_awork *w, const rf_limb *l)
{
    for (uint32_t k = w->child_off[l->end]; k < w->child_off[l->end + 1]; k++) {
        uint32_t c = w->child_idx[k];
        if (rf_an_child_count(w, c) == 0 && (w->a->joints[c].flags & RF_JI_TIP_GUESSED) &&
            rf_v3_dist(rf_an_pos(w, c), l->far) <= w->eps)
            return c;
    }
    return l->end;
}

/* Appends to pts the tips of the chain that goes on past a limb's far point, one child after
 * another, and returns the new count; *last is the chain's last joint. The far point is the tip
 * farthest from where the limb leaves the body, and a folded leg's foot turns back towards the
 * body from there (a sitting frog's shin runs back and down, its foot forward): the foot is
 * the chain's last bone, not the bone reaching farthest. A guessed leaf is left to far_leaf. */
static uint32_t chain_past_far(const rf_awork *w, const rf_limb *l, rf_vec3 *pts, uint32_t np,
                               uint32_t max, uint32_t *last)
{
    uint32_t j = l->end;
    while (np < max && rf_an_child_count(w, j) == 1) {
        uint32_t ch = w->child_idx[w->child_off[j]];
        if (w->limb_of[ch] != (int32_t)l->root || (w->a->joints[ch].flags & RF_JI_TIP_GUESSED))
            break;
        pts[np++] = w->a->joints[ch].tip;
        j = ch;
    }
    *last = j;
    return np;
}

/* The last bone of a leg's path pts[np] is the leg itself, not a foot: it starts in the leg's
 * upper third (low and top its lowest and highest) and is most of the path's length. A bone from
 * about the hip to the floor, set splayed or swung (a frog's or a lizard's one-bone legs, a box
 * moved by one joint), says how the leg stands, not where the toes point. */
static bool leg_itself(const rf_awork *w, const rf_vec3 *pts, uint32_t np, double low, double top)
{
    double above = 0, last = rf_v3_dist(pts[np - 2], pts[np - 1]);
    for (uint32_t k = 0; k + 2 < np; k++)
        above += rf_v3_dist(pts[k], pts[k + 1]);
    return rf_an_height(w, pts[np - 2]) > low + (2.0 / 3.0) * (top - low) && last > above;
}

/* Feet: the part of a grounded limb near the ground points forward. Knees of a biped bend
 * forward. Both measured along c (forward up to sign). */
static void vote_limbs(rf_awork *w, rf_limbs *ls, rf_vec3 c, rf_votes *v, uint32_t *legs)
{
    rf_analysis *a = w->a;
    rf_vec3 pts[64];
    *legs = 0;
    for (uint32_t i = 0; i < ls->n; i++) {
        rf_limb *l = &ls->v[i];
        double top = rf_an_height(w, l->attach), low = INFINITY;
        uint32_t np = limb_path(w, l, pts, 63);
        for (uint32_t k = 0; k < np; k++)
            low = fmin(low, rf_an_height(w, pts[k]));
        l->leg = low <= a->ground + 0.25 * a->height && top - low > 0.2 * a->height;
        if (!l->leg)
            continue;
        (*legs)++;
        uint32_t last;
        np = chain_past_far(w, l, pts, np, 62, &last);
        for (uint32_t k = 0; k < np; k++)
            low = fmin(low, rf_an_height(w, pts[k]));
        /* A leaf's guessed tip points the right way in a rig with a bone axis: the foot may be
         * that leaf, measured along its own bone (a guessed length would weigh the bones above
         * it: a digitigrade shin running back to the hock is no foot). */
        const rf_joint_info *end = &w->a->joints[last == l->end ? far_leaf(w, l) : last];
        bool guessed_leaf = false;
        if (w->conv_axis >= 0 && (end->flags & RF_JI_TIP_GUESSED) &&
            rf_v3_dist(end->tip, pts[np - 1]) > w->eps)
            pts[np++] = end->tip, guessed_leaf = true;
        double foot_top = low + 0.2 * (top - low);
        uint32_t f = np - 1;
        while (f > 0 && rf_an_height(w, pts[f - 1]) <= foot_top)
            f--;
        bool foot_bone = true;
        if (f == np - 1 && f > 0) /* only the end is low: use the last bone */
            f--, foot_bone = !leg_itself(w, pts, np, low, top);
        if (guessed_leaf)
            f = np - 2, foot_bone = true;
        /* a foot lies along the ground: count it by how flat it is */
        rf_vec3 foot = rf_v3_sub(pts[np - 1], pts[f]);
        double reach = rf_v3_dist(l->far, l->attach), flen = rf_v3_len(foot);
        double flat = flen > 0 ? sqrt(fmax(0, 1 - pow(rf_an_height(w, foot) / flen, 2))) : 0;
        if (foot_bone && reach > 0 && flen > 0.02 * reach && flat >= 0.7) /* 0.3 per flat foot */
            v->feet += 0.3 * flat * rf_v3_dot(foot, c) / flen;
    }
    if (*legs != 2 || !upright(w))
        return;
    for (uint32_t i = 0; i < ls->n; i++) {
        rf_limb *l = &ls->v[i];
        uint32_t np = l->leg ? limb_path(w, l, pts, 64) : 0;
        double best = 0, reach = rf_v3_dist(l->far, l->attach);
        for (uint32_t k = 1; k + 1 < np; k++) {
            /* a knee joins two real leg bones (not a pelvis offset, not the foot) */
            if (rf_v3_dist(pts[k - 1], pts[k]) < 0.15 * reach ||
                rf_v3_dist(pts[k + 1], pts[k]) < 0.15 * reach ||
                rf_an_height(w, pts[k]) <= rf_an_height(w, pts[np - 1]) + 0.15 * reach)
                continue;
            rf_vec3 mid = rf_v3_scale(rf_v3_add(pts[k - 1], pts[k + 1]), 0.5);
            double b = rf_v3_dot(rf_v3_sub(pts[k], mid), c);
            if (fabs(b) > fabs(best))
                best = b;
        }
        if (reach > 0 && fabs(best) > 0.02 * reach)
            v->knees += (best > 0 ? 0.15 : -0.15); /* weaker: birds bend theirs back */
    }
}

/* Head marks: a fan of three or more children, short side branches (ears, eyes), or an offset
 * child under a bone of its own (a jaw under the skull). Each votes for its end of the body. */
static double vote_head(const rf_awork *w, const rf_limbs *ls, rf_vec3 c)
{
    double longest = 0, vote = 0;
    for (uint32_t i = 0; i < ls->n; i++)
        longest = fmax(longest, ls->v[i].reach);
    rf_vec3 sum = rf_v3(0, 0, 0);
    uint32_t count = 0;
    for (uint32_t i = 0; i < w->order_count; i++)
        if (w->center[w->order[i]] && !w->root_chain[w->order[i]])
            sum = rf_v3_add(sum, rf_an_pos(w, w->order[i])), count++;
    if (count == 0)
        return 0;
    rf_vec3 mid = rf_v3_scale(sum, 1.0 / count);
    for (uint32_t i = 0; i < w->order_count; i++) {
        uint32_t j = w->order[i];
        if (!w->center[j] || w->root_chain[j])
            continue;
        bool connected = false, offset = false, girdle = false, mark;
        uint32_t shorts = 0;
        for (uint32_t k = w->child_off[j]; k < w->child_off[j + 1]; k++) {
            uint32_t ch = w->child_idx[k];
            if (!w->center[ch] && w->limb_of[ch] == (int32_t)ch) {
                const rf_limb *l = &ls->v[ls->slot[ch]];
                shorts += l->reach < 0.3 * longest;
                girdle |= l->reach >= 0.3 * longest || l->joints >= 2;
            } else if (w->center[ch] && w->sub_len[ch] < 0.3 * longest) {
                shorts++;
            }
            if (w->center[ch] && w->conv_axis >= 0) {
                bool on = rf_v3_dist(rf_an_pos(w, ch), w->a->joints[j].tip) <= w->eps;
                connected |= on, offset |= !on;
            }
        }
        /* a skull hangs from a neck: a root's children are offset from its tip as a rule (a
         * control root's torso), so a root's offset child marks no head */
        mark = !girdle && (shorts >= 2 || (offset && !connected && w->parent[j] >= 0));
        double along = rf_v3_dot(rf_v3_sub(rf_an_pos(w, j), mid), c);
        if (mark && fabs(along) > 0.05 * w->a->size)
            vote += along > 0 ? 0.3 : -0.3;
    }
    return fmax(-0.6, fmin(0.6, vote));
}

/* A horizontal body holds its head higher than its tail: the mean height of the centerline's
 * pivots in the front and in the rear fifth of its length. Its two end joints alone read a
 * curve skeleton's ears or snout, drooping past the head's end, as the lower end. */
static double vote_elevation(const rf_awork *w, rf_vec3 c)
{
    double xlo = INFINITY, xhi = -INFINITY, hmin = INFINITY, hmax = -INFINITY;
    for (uint32_t i = 0; i < w->order_count; i++) {
        uint32_t j = w->order[i];
        if (!w->center[j] || w->root_chain[j])
            continue;
        double h = rf_an_height(w, rf_an_pos(w, j)), x = rf_v3_dot(rf_an_pos(w, j), c);
        hmin = fmin(hmin, h), hmax = fmax(hmax, h), xlo = fmin(xlo, x), xhi = fmax(xhi, x);
    }
    if (!(xhi - xlo > hmax - hmin))
        return 0;
    double sum[2] = {0, 0}, cut = 0.2 * (xhi - xlo);
    uint32_t count[2] = {0, 0};
    for (uint32_t i = 0; i < w->order_count; i++) {
        uint32_t j = w->order[i];
        if (!w->center[j] || w->root_chain[j])
            continue;
        double h = rf_an_height(w, rf_an_pos(w, j)), x = rf_v3_dot(rf_an_pos(w, j), c);
        int e = x >= xhi - cut ? 1 : x <= xlo + cut ? 0 : -1;
        if (e >= 0)
            sum[e] += h, count[e]++;
    }
    if (!count[0] || !count[1])
        return 0;
    double dh = sum[1] / count[1] - sum[0] / count[0];
    if (fabs(dh) < 0.05 * w->a->height)
        return 0;
    return dh > 0 ? 0.2 : -0.2;
}

/* The last resort, for bodies that give no other cue (an owl: one torso bone, a head, wings):
 * the highest point of the centerline leans forward of the centerline's middle. */
static double vote_lean(const rf_awork *w, rf_vec3 c)
{
    rf_vec3 sum = rf_v3(0, 0, 0), top = rf_v3(0, 0, 0);
    double best = -INFINITY;
    uint32_t count = 0;
    for (uint32_t i = 0; i < w->order_count; i++) {
        uint32_t j = w->order[i];
        if (!w->center[j] || w->root_chain[j])
            continue;
        rf_vec3 p = rf_an_pos(w, j), t = w->a->joints[j].tip;
        sum = rf_v3_add(sum, p), count++;
        if (rf_an_height(w, t) > best)
            best = rf_an_height(w, t), top = t;
    }
    if (count < 2)
        return 0;
    double along = rf_v3_dot(rf_v3_sub(top, rf_v3_scale(sum, 1.0 / count)), c);
    return fabs(along) > 0.05 * w->a->size ? (along > 0 ? 0.1 : -0.1) : 0;
}

/* Girdles carry what the body needs at each end: limbs that do not reach the ground (arms,
 * wings) hang at the front of a horizontal body, the legs it stands on behind or under them (a
 * bird, a dragon, a centaur); measured from where each kind of limb leaves the body. */
static double vote_girdles(const rf_awork *w, const rf_limbs *ls, rf_vec3 c)
{
    double free_sum = 0, leg_sum = 0, longest = 0;
    uint32_t frees = 0, legs = 0;
    for (uint32_t i = 0; i < ls->n; i++)
        longest = fmax(longest, ls->v[i].reach);
    for (uint32_t i = 0; i < ls->n; i++) {
        const rf_limb *l = &ls->v[i];
        if (l->reach < 0.4 * longest || l->joints < 2)
            continue; /* ears, eyes, a control: too small to be a limb pair */
        double x = rf_v3_dot(l->attach, c), low = INFINITY;
        rf_vec3 pts[64];
        uint32_t np = limb_path(w, l, pts, 64);
        for (uint32_t k = 0; k < np; k++)
            low = fmin(low, rf_an_height(w, pts[k]));
        if (l->leg)
            leg_sum += x, legs++;
        else if (low > w->a->ground + 0.5 * w->a->height) /* held up, not a short leg */
            free_sum += x, frees++;
    }
    if (frees < 2 || legs < 2 || upright(w))
        return 0;
    double d = free_sum / frees - leg_sum / legs;
    return fabs(d) > 0.05 * w->a->size ? (d > 0 ? 0.3 : -0.3) : 0;
}

/* One girdle joint carrying every limb (an insect's one-joint thorax): the rig still grows
 * from it towards the head, so its bone runs forward and the chain beyond it (neck, head) starts
 * at its far end, while a chain hanging back from it (abdomen, tail) starts at its pivot. Votes
 * for the side of the centre child set off from the pivot when the other one sits on it. */
static double vote_one_girdle(const rf_awork *w, uint32_t j, rf_vec3 c)
{
    rf_vec3 at = rf_an_pos(w, j);
    double near = INFINITY, far = 0, near_x = 0, far_x = 0;
    uint32_t count = 0;
    for (uint32_t k = w->child_off[j]; k < w->child_off[j + 1]; k++) {
        uint32_t ch = w->child_idx[k];
        if (!w->center[ch] || w->sub_count[ch] == 0)
            continue;
        double d = rf_v3_dist(rf_an_pos(w, ch), at);
        rf_vec3 mid = rf_v3_scale(w->sub_sum[ch], 1.0 / w->sub_count[ch]);
        double x = rf_v3_dot(rf_v3_sub(rf_v3_lerp(mid, w->a->joints[ch].tip, 0.5), at), c);
        if (d < near)
            near = d, near_x = x;
        if (d >= far)
            far = d, far_x = x;
        count++;
    }
    /* two chains, one on the pivot and one a real bone away, running opposite ways */
    if (count != 2 || far < 0.05 * w->a->size || near > 0.25 * far || near_x * far_x >= 0)
        return 0;
    return far_x > 0 ? 0.25 : -0.25;
}

/* A body without limbs lying level (a fish, a snake) is rigged from its head or trunk towards
 * the tail, the end that moves most: the chain's root lies at the front end, the rest of it
 * behind (the Ogre fish and the animalia angelfish both; the angelfish's two joints said
 * nothing else, and the lean cue read it facing its tail). */
static double vote_chain_root(const rf_awork *w, rf_vec3 c)
{
    int32_t r = w->top;
    if (r < 0 || upright(w))
        return 0;
    rf_vec3 sum = rf_v3(0, 0, 0);
    uint32_t count = 0;
    for (uint32_t i = 0; i < w->order_count; i++) {
        uint32_t j = w->order[i];
        if (w->limb_of[j] >= 0)
            return 0;
        if (!w->root_chain[j])
            sum = rf_v3_add(sum, rf_v3_add(rf_an_pos(w, j), w->a->joints[j].tip)), count += 2;
    }
    if (count < 4)
        return 0;
    double along =
        rf_v3_dot(rf_v3_sub(rf_v3_scale(sum, 1.0 / count), rf_an_pos(w, (uint32_t)r)), c);
    return fabs(along) > 0.05 * w->a->size ? (along > 0 ? -0.25 : 0.25) : 0;
}

/* Rigs are built from the hips outwards: the body's root is the rear girdle (or near it) and
 * the hierarchy runs forward through the spine to the front girdle. The girdle deepest in the
 * hierarchy is the front one. It outweighs the elevation of the ends (0.25 against 0.2: an
 * insect carries its abdomen higher or lower than its head) but not the feet or the head marks,
 * as a rig rooted at the chest reads backwards. NAN when out of memory. */
static double vote_hierarchy(const rf_awork *w, rf_vec3 c)
{
    uint32_t *depth = calloc(w->n ? w->n : 1, sizeof *depth);
    if (!depth)
        return NAN;
    int32_t shallow = RF_NONE, deep = RF_NONE;
    for (uint32_t i = 0; i < w->order_count; i++) {
        uint32_t j = w->order[i];
        depth[j] = w->parent[j] >= 0 ? depth[w->parent[j]] + 1 : 0;
        bool girdle = false;
        for (uint32_t k = w->child_off[j]; k < w->child_off[j + 1]; k++)
            girdle |= !w->center[w->child_idx[k]] && w->limb_of[w->child_idx[k]] >= 0;
        if (!w->center[j] || w->root_chain[j] || !girdle)
            continue;
        if (shallow < 0 || depth[j] < depth[shallow])
            shallow = (int32_t)j;
        if (deep < 0 || depth[j] > depth[deep])
            deep = (int32_t)j;
    }
    double vote = shallow < 0 ? vote_chain_root(w, c) : 0;
    if (shallow >= 0 && deep == shallow && !upright(w))
        vote = vote_one_girdle(w, (uint32_t)shallow, c);
    if (shallow >= 0 && deep != shallow && !upright(w)) {
        double d =
            rf_v3_dot(rf_v3_sub(rf_an_pos(w, (uint32_t)deep), rf_an_pos(w, (uint32_t)shallow)), c);
        vote = fabs(d) > 0.05 * w->a->size ? (d > 0 ? 0.25 : -0.25) : 0;
    }
    free(depth);
    return vote;
}

const char *const rf_forward_cue_names[RF_FORWARD_CUE_COUNT] = {
    "feet", "knees", "head", "elevation", "file", "lean", "girdles", "hierarchy"};

int rf_forward_dissent(const rf_analysis *a)
{
    int worst = -1;
    for (int i = 0; i < RF_FORWARD_CUE_COUNT; i++)
        if (a->forward_cues[i] < 0 && (worst < 0 || a->forward_cues[i] < a->forward_cues[worst]))
            worst = i;
    return worst;
}

static double vote_file(const rf_awork *w, rf_vec3 c)
{
    rf_vec3 ff = w->skel->forward;
    if (w->opt.ignore_file_axes || !rf_v3_isfinite(ff) || rf_v3_len2(ff) == 0)
        return 0;
    double d = rf_v3_dot(rf_v3_normalize(ff), c);
    return d > 0.5 ? 0.3 : d < -0.5 ? -0.3 : 0;
}

/* Whether the caller or the file gives a forward (rf_an_frame's z is then a facing). */
static bool declared_forward(const rf_awork *w)
{
    rf_vec3 f = w->opt.forward;
    if (!(rf_v3_isfinite(f) && rf_v3_len2(f) > 1e-24) && !w->opt.ignore_file_axes)
        f = w->skel->forward;
    return rf_v3_isfinite(f) && rf_v3_len2(f) > 1e-24;
}

/* The very last resort when no forward is declared and no cue speaks (a fish's one chain, a
 * standing body without feet or knees to read): rigs grow from the hips, behind the body's
 * middle (as vote_hierarchy has it), so the body's joints lie mostly on the front side of its
 * top joint: a quadruped's chest and head, a biped's toes, hands and face. Weaker than any
 * cue, and read at a finer margin than they are (a hundredth of the body, the lean's fifth),
 * since only a body the same front and back has nothing to go by. The coordinate +z it
 * replaces read a body turned about up facing another way relative to the body at most
 * turns. */
static double vote_from_root(const rf_awork *w, rf_vec3 c)
{
    int32_t r = w->top >= 0 ? w->top : w->a->root;
    if (r < 0)
        return 0;
    rf_vec3 sum = rf_v3(0, 0, 0);
    uint32_t count = 0;
    for (uint32_t i = 0; i < w->order_count; i++) {
        uint32_t j = w->order[i];
        if (!w->root_chain[j])
            sum = rf_v3_add(sum, rf_v3_add(rf_an_pos(w, j), w->a->joints[j].tip)), count += 2;
    }
    if (count < 2)
        return 0;
    rf_vec3 mid = rf_v3_scale(sum, 1.0 / count);
    double along = rf_v3_dot(rf_v3_sub(mid, rf_an_pos(w, (uint32_t)r)), c);
    return fabs(along) > 0.01 * w->a->size ? (along > 0 ? 0.05 : -0.05) : 0;
}

/* False when out of memory (a cue not counted would decide the facing without it). */
static bool detect_forward(rf_awork *w, rf_limbs *ls)
{
    rf_analysis *a = w->a;
    rf_vec3 c = rf_v3_normalize(rf_v3_cross(w->plane_n, a->up));
    rf_votes v = {0};
    uint32_t legs;
    vote_limbs(w, ls, c, &v, &legs);
    double cue[RF_FORWARD_CUE_COUNT] = {
        fmax(-1, fmin(1, v.feet)), v.knees, vote_head(w, ls, c),    vote_elevation(w, c),
        vote_file(w, c),           0,       vote_girdles(w, ls, c), vote_hierarchy(w, c)};
    if (isnan(cue[7]))
        return false;
    bool silent = true;
    for (int i = 0; i < RF_FORWARD_CUE_COUNT; i++)
        silent = silent && cue[i] == 0;
    if (silent)
        cue[5] = vote_lean(w, c); /* only when nothing else says anything */
    if (silent && cue[5] == 0 && !declared_forward(w))
        cue[7] = vote_from_root(w, c);
    double sum = 0, weight = 0;
    int strongest = -1;
    for (int i = 0; i < RF_FORWARD_CUE_COUNT; i++)
        sum += cue[i], weight += fabs(cue[i]);
    for (int i = 0; i < RF_FORWARD_CUE_COUNT; i++) /* the source: the strongest that agrees */
        if (cue[i] * sum > 0 && (strongest < 0 || fabs(cue[i]) > fabs(cue[strongest])))
            strongest = i;
    a->forward = rf_v3_scale(c, sum < 0 ? -1 : 1);
    a->forward_confidence = weight > 0 ? fabs(sum) / (weight + 0.25) : 0;
    a->forward_source = strongest >= 0 ? rf_forward_cue_names[strongest] : "default";
    for (int i = 0; i < RF_FORWARD_CUE_COUNT; i++)
        a->forward_cues[i] = sum < 0 ? -cue[i] : cue[i];
    rf_vec3 ax[3];
    rf_an_frame(w, ax);
    if (strongest < 0 || sum == 0) /* nothing to go by: the frame's forward, +Z (glTF) */
        a->forward = rf_v3_scale(c, rf_v3_dot(c, ax[2]) < 0 ? -1 : 1);
    return true;
}

static void measure_heights(rf_awork *w)
{
    double lo = INFINITY, hi = -INFINITY;
    for (uint32_t i = 0; i < w->order_count; i++) {
        const rf_joint_info *ji = &w->a->joints[w->order[i]];
        double h0 = rf_an_height(w, ji->pos), h1 = rf_an_height(w, ji->tip);
        lo = fmin(lo, fmin(h0, h1)), hi = fmax(hi, fmax(h0, h1));
    }
    w->a->ground = isfinite(lo) ? lo : 0;
    w->a->height = isfinite(hi - lo) && hi - lo > 1e-12 ? hi - lo : w->a->size;
}

static bool usable(rf_vec3 v)
{
    return rf_v3_isfinite(v) && rf_v3_len2(v) > 1e-24;
}

/* Up, forward and left. False when out of memory: the limbs not collected, or a cue not
 * counted, would read the axes another way than the skeleton gives them. */
bool rf_an_axes(rf_awork *w)
{
    rf_analysis *a = w->a;
    rf_limbs ls = {0};
    bool ok = collect_limbs(w, &ls) && fan_vote(w, &ls);
    if (!ok)
        goto out;
    if (usable(w->opt.up)) {
        a->up = rf_v3_normalize(w->opt.up);
        a->up_source = "forced", a->up_confidence = 1;
    } else {
        detect_up(w, &ls);
    }
    w->plane_n = perpendicular_to(a->up, w->plane_n);
    measure_heights(w);
    rf_vec3 ff = w->opt.forward;
    if (usable(ff) && rf_v3_len(rf_v3_cross(a->up, rf_v3_normalize(ff))) > 1e-6) {
        a->forward = perpendicular_to(a->up, ff);
        a->forward_source = "forced", a->forward_confidence = 1;
    } else if (!detect_forward(w, &ls)) {
        ok = false;
        goto out;
    }
    a->left = rf_v3_normalize(rf_v3_cross(a->up, a->forward));
    w->plane_n = a->left;
    a->plane_normal = a->left, a->plane_point = w->plane_p;
out:
    free(ls.v);
    free(ls.slot);
    return ok;
}
