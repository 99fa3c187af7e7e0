/* Skeletons built the way production rigs are (see rigs.h). Bodies are laid out in a canonical
 * frame (+Y up, +Z forward, +X left, the left side written once and mirrored), then turned to
 * one of four facings, perhaps laid Z up, scaled, moved and written in one of two conventions. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rigs.h"

#define RIGS_MAX 400

const char *const rigs_plan_names[RIGS_PLAN_COUNT] = {"humanoid", "quadruped", "hexapod", "dragon",
                                                      "bird"};
const char *const rigs_part_names[RIGS_PART_COUNT] = {
    "helper", "root", "pelvis", "spine", "chest", "neck", "head", "jaw", "tail", "limb", "digit"};

typedef struct rj {
    int parent;
    int main;         /* the child continuing this bone, or -1 (the bone ends at tip) */
    rf_vec3 pos, tip; /* canonical frame */
    rigs_label label;
    unsigned flags;
    bool axis; /* an axis-conversion node: written with a quarter turn */
} rj;

typedef struct rb {
    rj j[RIGS_MAX];
    int n;
    uint64_t rng;
} rb;

static double rnd(rb *b)
{
    b->rng ^= b->rng >> 12, b->rng ^= b->rng << 25, b->rng ^= b->rng >> 27;
    return (double)((b->rng * 2685821657736338717ULL) >> 11) / 9007199254740992.0;
}
static double r(rb *b, double lo, double hi)
{
    return lo + (hi - lo) * rnd(b);
}
static int ir(rb *b, int lo, int hi)
{
    return lo + (int)(rnd(b) * (hi - lo + 1));
}
static rf_vec3 v(double x, double y, double z)
{
    return rf_v3(x, y, z);
}
static rf_vec3 mir(rf_vec3 p, int side)
{
    return side == 2 ? v(-p.x, p.y, p.z) : p;
}

static rigs_label lab(rigs_part part, int side, rigs_role role, int seg)
{
    rigs_label l = {0};
    l.part = (uint8_t)part, l.side = (uint8_t)side, l.role = (uint8_t)role, l.seg = (uint8_t)seg;
    return l;
}

/* Adds a joint; `continues`: its parent's bone ends here (a chain), else it branches off. */
static int add(rb *b, int parent, rf_vec3 pos, rigs_label label, bool continues)
{
    if (b->n == RIGS_MAX)
        return parent;
    rj *j = &b->j[b->n];
    memset(j, 0, sizeof *j);
    j->parent = parent, j->pos = pos, j->tip = pos, j->label = label, j->main = -1;
    if (continues && parent >= 0 && b->j[parent].main < 0)
        b->j[parent].main = b->n;
    return b->n++;
}

/* A chain of n joints from `from` towards `to` (the last tip at `to`), bowed by `bow`. */
static int chain(rb *b, int parent, rf_vec3 from, rf_vec3 to, int n, rigs_part part, rf_vec3 bow,
                 bool continues)
{
    int at = parent;
    for (int i = 0; i < n; i++) {
        double t = (double)i / n;
        rf_vec3 p = rf_v3_add(rf_v3_lerp(from, to, t), rf_v3_scale(bow, sin(RF_PI * t)));
        rigs_label l = lab(part, 0, RIGS_NO_ROLE, 0);
        l.index = (uint8_t)i, l.count = (uint8_t)n;
        at = add(b, at, p, l, i > 0 || continues);
    }
    b->j[at].tip = to;
    return at;
}

/* Pelvis to chest in n joints (1: one body joint, labelled pelvis with count 1). */
static int spine(rb *b, int parent, rf_vec3 pelvis, rf_vec3 chest, int n, int *first)
{
    int at = parent;
    for (int i = 0; i < n; i++) {
        double t = n > 1 ? (double)i / (n - 1) : 0;
        rf_vec3 p = rf_v3_lerp(pelvis, chest, t);
        if (i && i + 1 < n)
            p = rf_v3_add(p, v(0, r(b, -0.01, 0.01), r(b, -0.02, 0.02)));
        rigs_label l = lab(i == 0 ? RIGS_PELVIS : i + 1 == n ? RIGS_CHEST : RIGS_SPINE, 0, 0, 0);
        if (l.part == RIGS_SPINE)
            l.index = (uint8_t)(i - 1), l.count = (uint8_t)(n - 2);
        if (n == 1)
            l.count = 1; /* a one-joint body: pelvis and chest at once */
        at = add(b, at, p, l, true);
        if (i == 0)
            *first = at;
    }
    b->j[at].tip = n == 1 ? rf_v3_add(chest, rf_v3_sub(chest, pelvis)) : chest;
    if (n == 1)
        b->j[at].tip = rf_v3_add(pelvis, v(0, 0.02, 0.3));
    return at;
}

static void head(rb *b, int parent, rf_vec3 p, rf_vec3 toward, bool jaw)
{
    int h = add(b, parent, p, lab(RIGS_HEAD, 0, 0, 0), true);
    b->j[h].tip = rf_v3_add(p, toward);
    if (jaw) {
        double s = rf_v3_len(toward);
        int j = add(b, h, rf_v3_add(p, v(0, -0.25 * s, 0.15 * s)), lab(RIGS_JAW, 0, 0, 0), false);
        b->j[j].tip = rf_v3_add(b->j[j].pos, v(0, -0.15 * s, 0.6 * s));
    }
}

/* ---- limbs ---- */

/* A limb on the left side, mirrored for the right: points p[0..n-1] with their segments, the
 * last bone ending at tip. twist: 0 none, 1 a roll leaf in the upper and lower segments
 * (Unreal's mannequin), 2 those segments split in two (Rigify's deform bones). */
typedef struct limb_spec {
    int n;
    rf_vec3 p[6];
    uint8_t seg[6];
    rf_vec3 tip;
    int twist;
    double twist_at; /* where a roll leaf sits along its segment */
} limb_spec;

static int limb(rb *b, int parent, const limb_spec *L, int side, rigs_role role)
{
    int at = parent;
    for (int i = 0; i < L->n; i++) {
        rf_vec3 p = mir(L->p[i], side), next = mir(i + 1 < L->n ? L->p[i + 1] : L->tip, side);
        at = add(b, at, p, lab(RIGS_LIMB, side, role, L->seg[i]), true);
        if (!L->twist || (L->seg[i] != 1 && L->seg[i] != 2))
            continue;
        rigs_label tl = lab(RIGS_LIMB, side, role, L->seg[i]);
        tl.twist = true;
        if (L->twist == 2) {
            at = add(b, at, rf_v3_lerp(p, next, 0.5), tl, true);
        } else {
            int t = add(b, at, rf_v3_lerp(p, next, L->twist_at), tl, false);
            b->j[t].tip = rf_v3_lerp(p, next, L->twist_at + 0.15);
        }
    }
    b->j[at].tip = mir(L->tip, side);
    return at;
}

typedef struct hand_spec {
    int count;   /* digits, thumb included */
    bool thumb;  /* the first is a thumb */
    bool palm;   /* non-thumb digits start with a palm bone at the wrist (Rigify) */
    int segs[5]; /* phalanges per digit */
    double len;  /* wrist to knuckles */
    double flen; /* finger length */
    bool foot;   /* toes */
} hand_spec;

/* Digits fanning from the wrist along dir (left side), spread across `across`. */
static void digits(rb *b, int hand, rf_vec3 wrist, rf_vec3 dir, rf_vec3 across, int side,
                   rigs_role role, const hand_spec *h)
{
    int fingers = h->count - h->thumb;
    for (int d = 0; d < h->count; d++) {
        bool thumb = h->thumb && d == 0;
        int rank = d - h->thumb;
        double spread = fingers > 1 ? 0.5 - (double)rank / (fingers - 1) : 0;
        rf_vec3 knuckle, fdir;
        if (thumb) {
            knuckle = rf_v3_add(wrist, rf_v3_add(rf_v3_scale(dir, 0.2 * h->len),
                                                 rf_v3_scale(across, 0.35 * h->len)));
            fdir = rf_v3_normalize(rf_v3_add(dir, rf_v3_scale(across, h->foot ? -3 : 0.9)));
        } else {
            knuckle = rf_v3_add(wrist, rf_v3_add(rf_v3_scale(dir, h->len),
                                                 rf_v3_scale(across, spread * 0.6 * h->len)));
            fdir = rf_v3_normalize(rf_v3_add(dir, rf_v3_scale(across, spread * 0.3)));
        }
        rigs_label l = lab(RIGS_DIGIT, side, role, 0);
        l.count = (uint8_t)fingers, l.digit = (uint8_t)(thumb ? 0 : rank), l.thumb = thumb,
        l.foot = h->foot;
        int at = hand;
        if (h->palm && !thumb) { /* a palm bone from the wrist to the knuckle */
            at =
                add(b, at, mir(rf_v3_add(wrist, rf_v3_scale(across, spread * 0.15 * h->len)), side),
                    l, false);
        }
        rf_vec3 p = knuckle;
        for (int s = 0; s < h->segs[d]; s++) {
            /* a wing's membrane fingers start at its wrist: their first bone is a palm bone */
            l.seg = (uint8_t)(role == RIGS_WINGS ? s : s + 1);
            at = add(b, at, mir(p, side), l, s > 0 || (h->palm && !thumb));
            p = rf_v3_add(p, rf_v3_scale(fdir, h->flen / h->segs[d] * (thumb ? 0.8 : 1)));
        }
        b->j[at].tip = mir(p, side);
    }
}

static void hand_draw(rb *b, hand_spec *h, int min, int max, double scale)
{
    h->count = ir(b, min, max);
    h->thumb = h->count >= 2 && rnd(b) < 0.9;
    h->palm = rnd(b) < 0.35;
    int segs = ir(b, 1, 3);
    for (int d = 0; d < 5; d++)
        h->segs[d] = rnd(b) < 0.8 ? segs : ir(b, 1, 3);
    h->len = r(b, 0.07, 0.1) * scale, h->flen = r(b, 0.06, 0.1) * scale;
    h->foot = false;
}

/* Both sides of a limb pair with the same spec (a symmetric body), a hand on each if asked. */
static void pair(rb *b, int parent, const limb_spec *L, rigs_role role, const hand_spec *h,
                 rf_vec3 across)
{
    for (int side = 1; side <= 2; side++) {
        int end = limb(b, parent, L, side, role);
        if (!h || !h->count)
            continue;
        rf_vec3 wrist = L->p[L->n - 1], dir = rf_v3_normalize(rf_v3_sub(L->tip, wrist));
        b->j[end].tip = mir(rf_v3_add(wrist, rf_v3_scale(dir, h->len)), side);
        digits(b, end, wrist, dir, across, side, role, h);
    }
}

/* ---- body plans ---- */

static int twist_style(rb *b)
{
    double x = rnd(b);
    return x < 0.45 ? 0 : x < 0.75 ? 1 : 2;
}

/* An arm from `base` (the left shoulder's inner end): clavicle or not, T, A or down pose. */
static limb_spec arm_spec(rb *b, rf_vec3 base, double scale, double down, int twist)
{
    limb_spec L = {0};
    rf_vec3 dir = rf_v3_normalize(v(cos(down), -sin(down), r(b, -0.08, 0.08)));
    rf_vec3 shoulder = rf_v3_add(base, v(0.14 * scale, r(b, -0.02, 0.02), -0.01));
    if (rnd(b) < 0.7)
        L.p[L.n] = rf_v3_add(base, v(0.02 * scale, 0, 0.01)), L.seg[L.n++] = 0;
    rf_vec3 elbow = rf_v3_add(shoulder, rf_v3_scale(dir, r(b, 0.26, 0.33) * scale));
    /* IK-ready rigs bend the elbow a little; motion capture and many game rigs keep it straight */
    double bend = rnd(b) < 0.3 ? 0 : r(b, 0.03, 0.2);
    rf_vec3 fore = rf_v3_normalize(rf_v3_add(dir, v(0, 0, sin(bend))));
    rf_vec3 wrist = rf_v3_add(elbow, rf_v3_scale(fore, r(b, 0.23, 0.28) * scale));
    L.p[L.n] = shoulder, L.seg[L.n++] = 1;
    L.p[L.n] = elbow, L.seg[L.n++] = 2;
    L.p[L.n] = wrist, L.seg[L.n++] = 3;
    L.tip = rf_v3_add(wrist, rf_v3_scale(fore, 0.08 * scale));
    L.twist = twist, L.twist_at = r(b, 0.2, 0.8);
    return L;
}

static limb_spec human_leg(rb *b, double H, double width, int twist)
{
    limb_spec L = {0};
    if (rnd(b) < 0.25)
        L.p[L.n] = v(0.02, H, 0), L.seg[L.n++] = 0;
    double kh = r(b, 0.48, 0.55) * H;
    L.p[L.n] = v(width, H - 0.05 * H, 0), L.seg[L.n++] = 1;
    L.p[L.n] = v(width, kh, 0.02 * H), L.seg[L.n++] = 2;
    L.p[L.n] = v(width, 0.08 * H, -0.01 * H), L.seg[L.n++] = 3;
    rf_vec3 ball = v(width, 0.015 * H, 0.13 * H);
    if (rnd(b) < 0.85)
        L.p[L.n] = ball, L.seg[L.n++] = 4, L.tip = v(width, 0.01 * H, 0.2 * H);
    else
        L.tip = ball;
    L.twist = twist, L.twist_at = r(b, 0.2, 0.8);
    return L;
}

static void humanoid(rb *b, int root)
{
    double H = r(b, 0.75, 1.05), T = r(b, 0.4, 0.6), s = r(b, 0.85, 1.2);
    rf_vec3 hips = v(0, H, 0), chest_p = v(0, H + 0.7 * T, r(b, -0.02, 0.02));
    int pelvis, chest = spine(b, root, hips, chest_p, ir(b, 1, 5), &pelvis);
    rf_vec3 nb = v(0, H + T, 0.01), nt = rf_v3_add(nb, v(0, r(b, 0.08, 0.14), r(b, 0, 0.03)));
    int neck = chain(b, chest, nb, nt, ir(b, 1, 3), RIGS_NECK, v(0, 0, 0.005), true);
    head(b, neck, nt, v(0, r(b, 0.18, 0.25), 0.02), rnd(b) < 0.3);
    int twist = twist_style(b);
    double pose = rnd(b), down = pose < 0.4   ? r(b, 0, 0.1)
                                 : pose < 0.8 ? r(b, 0.6, 0.8)
                                              : r(b, 1.3, 1.45);
    hand_spec h;
    hand_draw(b, &h, 0, 5, s);
    limb_spec arm = arm_spec(b, v(0.01, H + 0.93 * T, 0), s, down, twist);
    pair(b, chest, &arm, RIGS_FORE, &h, v(0, 0, 1));
    double extra = rnd(b);
    if (extra < 0.15) { /* a second pair of arms below the first */
        limb_spec lower = arm_spec(b, v(0.01, H + 0.72 * T, 0), s * 0.9, r(b, 0.3, 1.2), twist);
        pair(b, chest, &lower, RIGS_MID, &h, v(0, 0, 1));
    } else if (extra < 0.3) { /* wings from the upper back */
        limb_spec w = {0};
        rf_vec3 sh = v(0.08, H + 0.9 * T, -0.08), dir = rf_v3_normalize(v(1, r(b, 0.3, 1), -0.4));
        w.p[0] = sh, w.seg[0] = 1;
        w.p[1] = rf_v3_add(sh, rf_v3_scale(dir, 0.35 * s)), w.seg[1] = 2;
        w.p[2] = rf_v3_add(w.p[1], rf_v3_scale(dir, 0.4 * s)), w.seg[2] = 3, w.n = 3;
        w.tip = rf_v3_add(w.p[2], rf_v3_scale(dir, 0.1 * s));
        hand_spec wh = {ir(b, 3, 4), false, false, {1, 1, 1, 1, 1}, 0.05 * s, 0.6 * s, false};
        for (int d = 0; d < 5; d++)
            wh.segs[d] = ir(b, 1, 2);
        pair(b, chest, &w, RIGS_WINGS, &wh, rf_v3_normalize(v(0, -0.3, -1)));
    }
    limb_spec leg = human_leg(b, H, r(b, 0.08, 0.12), twist);
    pair(b, pelvis, &leg, RIGS_HIND, NULL, v(0, 0, 1));
}

/* A quadruped's leg (left side) under a girdle at `top`, of height h. */
static limb_spec quad_leg(rb *b, rf_vec3 top, double h, double width, bool fore, bool digitigrade)
{
    limb_spec L = {0};
    double z = top.z;
    if (rnd(b) < (fore ? 0.5 : 0.3)) /* a scapula or a hip offset */
        L.p[L.n] = v(0.03, top.y + (fore ? 0.05 * h : 0), z + (fore ? 0.05 * h : 0)),
        L.seg[L.n++] = 0;
    L.p[L.n] = v(width, top.y - 0.12 * h, z), L.seg[L.n++] = 1;
    double bend = fore ? -0.08 : 0.1; /* elbows point back, knees forward */
    L.p[L.n] = v(width, r(b, 0.5, 0.62) * h, z + bend * h), L.seg[L.n++] = 2;
    double ankle = digitigrade ? r(b, 0.22, 0.38) * h : r(b, 0.08, 0.14) * h;
    double back = digitigrade && !fore ? -0.12 : -0.02;
    L.p[L.n] = v(width, ankle, z + back * h), L.seg[L.n++] = 3;
    rf_vec3 ball = v(width, 0.03 * h, z + (digitigrade ? 0.0 : 0.05) * h);
    if (rnd(b) < 0.6)
        L.p[L.n] = ball, L.seg[L.n++] = 4, L.tip = v(width, 0, ball.z + 0.07 * h);
    else
        L.tip = ball;
    L.twist = rnd(b) < 0.2 ? ir(b, 1, 2) : 0;
    L.twist_at = r(b, 0.3, 0.7);
    return L;
}

static void wings(rb *b, int parent, rf_vec3 base, double span, bool folded, int hand_bone)
{
    limb_spec w = {0};
    rf_vec3 dir =
        folded ? rf_v3_normalize(v(0.3, 0.1, -1)) : rf_v3_normalize(v(1, r(b, 0, 0.4), -0.2));
    w.p[w.n] = v(0.06, base.y + 0.05, base.z - 0.05), w.seg[w.n++] = 1;
    w.p[w.n] = rf_v3_add(w.p[0], rf_v3_scale(dir, 0.3 * span)), w.seg[w.n++] = 2;
    rf_vec3 wrist = rf_v3_add(w.p[1], rf_v3_scale(dir, 0.35 * span));
    if (hand_bone)
        w.p[w.n] = wrist, w.seg[w.n++] = 3;
    w.tip = hand_bone ? rf_v3_add(wrist, rf_v3_scale(dir, 0.1 * span)) : wrist;
    hand_spec wh = {ir(b, 1, 5), false, false, {1, 1, 1, 1, 1}, 0.05 * span, 0.5 * span, false};
    if (wh.count > 2)
        wh.flen = span;
    for (int d = 0; d < 5; d++)
        wh.segs[d] = ir(b, 1, 3);
    pair(b, parent, &w, RIGS_WINGS, &wh, v(0, 0, -1));
}

static void quadruped(rb *b, int root, bool dragon)
{
    double h = r(b, 0.45, 1.0), len = r(b, 0.6, 1.4);
    rf_vec3 pp = v(0, h, -len / 2), cp = v(0, h + r(b, -0.05, 0.1), len / 2);
    int pelvis, chest = spine(b, root, pp, cp, ir(b, 1, 5), &pelvis);
    rf_vec3 nt = rf_v3_add(cp, v(0, r(b, 0.2, 0.5), r(b, 0.15, 0.4)));
    int nn = ir(b, 3, 7);
    int neck = chain(b, chest, rf_v3_add(cp, v(0, 0.05, 0.05)), nt, nn, RIGS_NECK,
                     v(0, 0.03, -0.03), true);
    head(b, neck, nt, rf_v3_scale(rf_v3_normalize(v(0, -0.3, 1)), r(b, 0.15, 0.3)), rnd(b) < 0.4);
    int tails = dragon ? ir(b, 4, 12) : ir(b, 0, 10);
    if (tails)
        chain(b, pelvis, rf_v3_add(pp, v(0, 0.02, -0.06)),
              rf_v3_add(pp, v(0, r(b, -0.4, 0.2), -r(b, 0.3, 1.2))), tails, RIGS_TAIL,
              v(0, r(b, -0.05, 0.05), 0), false);
    double width = r(b, 0.08, 0.18);
    bool digi = rnd(b) < 0.5;
    limb_spec fore = quad_leg(b, cp, h, width, true, digi);
    limb_spec hind = quad_leg(b, pp, h, width, false, digi || rnd(b) < 0.6);
    pair(b, chest, &fore, RIGS_FORE, NULL, v(0, 0, 1));
    pair(b, pelvis, &hind, RIGS_HIND, NULL, v(0, 0, 1));
    if (dragon)
        wings(b, chest, cp, r(b, 0.8, 1.6), rnd(b) < 0.3, rnd(b) < 0.6);
}

/* An insect: thorax joints carry three pairs of legs, upright or sprawled; abdomen behind. */
static void hexapod(rb *b, int root)
{
    double h = r(b, 0.15, 0.4), len = r(b, 0.3, 0.6);
    bool sprawl = rnd(b) < 0.5;
    rf_vec3 pp = v(0, h, -len / 2), cp = v(0, h + r(b, -0.02, 0.04), len / 2);
    int n = ir(b, 1, 3), pelvis, chest = spine(b, root, pp, cp, n, &pelvis);
    int mid = n == 3 ? b->j[chest].parent : chest;
    int tails = ir(b, 1, 4);
    chain(b, pelvis, rf_v3_add(pp, v(0, 0, -0.03)),
          rf_v3_add(pp, v(0, r(b, -0.1, 0.1), -r(b, 0.4, 0.9))), tails, RIGS_TAIL, v(0, 0.03, 0),
          false);
    int neck = chest;
    if (rnd(b) < 0.5)
        neck = chain(b, chest, rf_v3_add(cp, v(0, 0, 0.04)), rf_v3_add(cp, v(0, 0.02, 0.1)), 1,
                     RIGS_NECK, v(0, 0, 0), true);
    head(b, neck, rf_v3_add(cp, v(0, 0.02, 0.1)), v(0, 0, r(b, 0.1, 0.2)), rnd(b) < 0.3);
    int parents[3] = {chest, mid, pelvis};
    rigs_role roles[3] = {RIGS_FORE, RIGS_MID, RIGS_HIND};
    double sweep[3] = {0.6, 0, -0.6};
    bool coxa = rnd(b) < 0.7, tarsus_toe = rnd(b) < 0.4;
    for (int p = 0; p < 3; p++) {
        rf_vec3 at = b->j[parents[p]].pos;
        rf_vec3 out = rf_v3_normalize(v(1, 0, sweep[p] + r(b, -0.1, 0.1)));
        limb_spec L = {0};
        if (coxa)
            L.p[L.n] = v(0.03, at.y - 0.02, at.z), L.seg[L.n++] = 0;
        rf_vec3 hip = v(0.06, at.y - 0.03, at.z);
        L.p[L.n] = hip, L.seg[L.n++] = 1;
        rf_vec3 knee =
            sprawl ? rf_v3_add(hip, rf_v3_add(rf_v3_scale(out, 0.3), v(0, 0.2 * h + 0.1, 0)))
                   : rf_v3_add(hip, rf_v3_add(rf_v3_scale(out, 0.2), v(0, -0.2 * h, 0)));
        L.p[L.n] = knee, L.seg[L.n++] = 2;
        rf_vec3 ankle =
            rf_v3_add(v(knee.x, 0.05 * h, knee.z), rf_v3_scale(out, sprawl ? 0.35 : 0.08));
        L.p[L.n] = ankle, L.seg[L.n++] = 3;
        rf_vec3 end = rf_v3_add(v(ankle.x, 0, ankle.z), rf_v3_scale(out, 0.12));
        if (tarsus_toe)
            L.p[L.n] = rf_v3_lerp(ankle, end, 0.5), L.seg[L.n++] = 4;
        L.tip = end;
        pair(b, parents[p], &L, roles[p], NULL, v(0, 0, 1));
    }
}

/* A bird: long S-shaped neck, wings folded or spread, digitigrade legs with toes. */
static void bird(rb *b, int root)
{
    double h = r(b, 0.3, 0.8), len = r(b, 0.25, 0.5);
    rf_vec3 pp = v(0, h, -len / 3), cp = v(0, h + 0.1 * len, 2 * len / 3);
    int pelvis, chest = spine(b, root, pp, cp, ir(b, 1, 3), &pelvis);
    rf_vec3 nt = rf_v3_add(cp, v(0, r(b, 0.3, 0.7) * h, r(b, 0.05, 0.2)));
    int neck = chain(b, chest, rf_v3_add(cp, v(0, 0.03, 0.03)), nt, ir(b, 4, 7), RIGS_NECK,
                     v(0, 0, 0.06), true);
    head(b, neck, nt, v(0, 0, r(b, 0.08, 0.15)), rnd(b) < 0.3);
    int tails = ir(b, 0, 2);
    if (tails)
        chain(b, pelvis, rf_v3_add(pp, v(0, 0, -0.05)), rf_v3_add(pp, v(0, 0.05, -0.3 * len)),
              tails, RIGS_TAIL, v(0, 0, 0), false);
    wings(b, chest, cp, r(b, 0.4, 1.0), rnd(b) < 0.5, 1);
    limb_spec L = {0};
    double w = r(b, 0.04, 0.08);
    L.p[L.n] = v(w, h - 0.03, pp.z), L.seg[L.n++] = 1;
    L.p[L.n] = v(w, 0.6 * h, pp.z + 0.12 * h), L.seg[L.n++] = 2;
    L.p[L.n] = v(w, 0.3 * h, pp.z - 0.05 * h), L.seg[L.n++] = 3;
    rf_vec3 ball = v(w, 0.02 * h, pp.z);
    L.tip = ball;
    L.twist = 0;
    bool toes = rnd(b) < 0.7;
    hand_spec t = {toes ? ir(b, 3, 4) : 0, false, false, {2, 3, 3, 2, 2}, 0.0, 0.1 * h, true};
    t.thumb = t.count == 4; /* the hallux points back */
    if (!toes) {
        L.p[L.n] = ball, L.seg[L.n++] = 4, L.tip = v(w, 0, pp.z + 0.1 * h);
        pair(b, pelvis, &L, RIGS_HIND, NULL, v(1, 0, 0));
        return;
    }
    L.tip = rf_v3_add(ball, v(0, 0, 0.001));
    t.len = 0.001;
    for (int side = 1; side <= 2; side++) {
        int end = limb(b, pelvis, &L, side, RIGS_HIND);
        b->j[end].tip = mir(ball, side);
        digits(b, end, ball, v(0, 0, 1), v(1, 0, 0), side, RIGS_HIND, &t);
    }
}

/* Ground root at the origin, perhaps an axis-conversion node under it; returns the body's
 * parent. */
static int roots(rb *b, bool helpers)
{
    int root = -1;
    if (helpers || rnd(b) < 0.15) {
        root = add(b, -1, v(0, 0, 0), lab(RIGS_ROOT, 0, 0, 0), false);
        b->j[root].flags = RF_JOINT_UNWEIGHTED;
    }
    if (helpers && rnd(b) < 0.5) {
        root = add(b, root, v(0, 0, 0), lab(RIGS_ROOT, 0, 0, 0), false);
        b->j[root].axis = true;
        b->j[root].flags = RF_JOINT_UNWEIGHTED;
    }
    return root;
}

/* IK targets at the ankles and wrists, poles before the knees and behind the elbows, all under
 * the top root (Blender IK rigs, Unreal's ik_foot_root). */
static void ik_helpers(rb *b, double reach)
{
    int n = b->n, top = 0;
    bool hands = rnd(b) < 0.5;
    for (int i = 0; i < n; i++) {
        const rigs_label *l = &b->j[i].label;
        if (l->part != RIGS_LIMB || l->twist || l->seg != 3 ||
            (l->role != RIGS_HIND && !(hands && l->role == RIGS_FORE)))
            continue;
        int t = add(b, top, b->j[i].pos, lab(RIGS_HELPER, l->side, 0, 0), false);
        b->j[t].tip = rf_v3_add(b->j[t].pos, v(0, 0, 0.1 * reach));
        rf_vec3 knee = b->j[b->j[i].parent].pos;
        double dz = l->role == RIGS_HIND ? 0.5 * reach : -0.5 * reach;
        int p = add(b, top, rf_v3_add(knee, v(0, 0, dz)), lab(RIGS_HELPER, l->side, 0, 0), false);
        b->j[p].tip = rf_v3_add(b->j[p].pos, v(0, 0.05 * reach, 0));
        b->j[t].flags = b->j[p].flags = RF_JOINT_UNWEIGHTED;
    }
}

/* ---- writing ---- */

typedef struct frame {
    rf_quat rot;
    double scale;
    rf_vec3 offset;
    bool blender; /* bones along local +Y with a random roll, leaves without end sites */
    bool skinned; /* helpers flagged unweighted */
} frame;

static rf_vec3 world_pos(const frame *f, rf_vec3 p)
{
    return rf_v3_add(rf_quat_rotate(f->rot, rf_v3_scale(p, f->scale)), f->offset);
}

static char *name_of(rb *b, int i)
{
    char buf[64];
    double x = rnd(b);
    if (x < 0.4)
        snprintf(buf, sizeof buf, "Bone.%03d", i);
    else if (x < 0.8)
        snprintf(buf, sizeof buf, "n%04x%c", (unsigned)(rnd(b) * 60000), 'a' + (int)(rnd(b) * 26));
    else
        snprintf(buf, sizeof buf, "%s%u_%d", rigs_part_names[b->j[i].label.part], b->j[i].label.seg,
                 i);
    char *s = malloc(strlen(buf) + 1);
    strcpy(s, buf);
    return s;
}

static rf_skeleton *emit(rb *b, const frame *f)
{
    rf_skeleton *s = rf_skeleton_new((uint32_t)b->n);
    rf_quat world[RIGS_MAX];
    for (int i = 0; i < b->n; i++) {
        rf_joint *j = &s->joints[i];
        int p = b->j[i].parent;
        rf_vec3 pos = world_pos(f, b->j[i].pos);
        rf_vec3 end = world_pos(f, b->j[i].main >= 0 ? b->j[b->j[i].main].pos : b->j[i].tip);
        rf_vec3 ppos = p >= 0 ? world_pos(f, b->j[p].pos) : v(0, 0, 0);
        world[i] = rf_quat_identity();
        if (b->j[i].axis)
            world[i] = rf_quat_mul(f->rot, rf_quat_from_axis_angle(v(1, 0, 0), -RF_PI / 2));
        else if (f->blender && rf_v3_dist(end, pos) > 1e-9 * f->scale)
            world[i] = rf_quat_mul(rf_quat_from_two_vectors(v(0, 1, 0), rf_v3_sub(end, pos)),
                                   rf_quat_from_axis_angle(v(0, 1, 0), r(b, -3, 3)));
        rf_quat pr = p >= 0 ? world[p] : rf_quat_identity();
        j->parent = p;
        j->flags = f->skinned ? b->j[i].flags : 0;
        j->rest.t = rf_quat_rotate(rf_quat_conj(pr), rf_v3_sub(pos, ppos));
        j->rest.r = rf_quat_normalize(rf_quat_mul(rf_quat_conj(pr), world[i]));
        j->name = name_of(b, i);
        bool leaf = true;
        for (int k = i + 1; k < b->n && leaf; k++)
            leaf = b->j[k].parent != i;
        if (leaf && !f->blender && rf_v3_dist(end, pos) > 1e-9 * f->scale) {
            j->flags |= RF_JOINT_HAS_END_SITE;
            j->end_site = rf_quat_rotate(rf_quat_conj(world[i]), rf_v3_sub(end, pos));
        }
    }
    return s;
}

rigs_skel rigs_make(rigs_plan plan, uint64_t seed)
{
    rb *b = calloc(1, sizeof *b);
    rigs_skel g = {0};
    b->rng = seed * 0xD1B54A32D192ED03ULL + 7;
    for (int i = 0; i < 4; i++)
        rnd(b);
    g.helpers = rnd(b) < 1.0 / 3;
    int root = roots(b, g.helpers);
    if (plan == RIGS_HUMANOID)
        humanoid(b, root);
    else if (plan == RIGS_QUADRUPED || plan == RIGS_DRAGON)
        quadruped(b, root, plan == RIGS_DRAGON);
    else if (plan == RIGS_HEXAPOD)
        hexapod(b, root);
    else
        bird(b, root);
    if (g.helpers && root >= 0)
        ik_helpers(b, plan == RIGS_HEXAPOD ? 0.3 : 1.0);
    g.facing = ir(b, 0, 3);
    frame f = {rf_quat_from_axis_angle(v(0, 1, 0), g.facing * RF_PI / 2),
               exp(r(b, log(0.01), log(100))), v(r(b, -3, 3), 0, r(b, -3, 3)), rnd(b) < 0.5,
               rnd(b) < 0.6};
    if (rnd(b) < 0.3) /* Z up */
        f.rot = rf_quat_mul(rf_quat_from_axis_angle(v(1, 0, 0), RF_PI / 2), f.rot);
    f.offset = rf_v3_scale(f.offset, f.scale);
    g.up = rf_quat_rotate(f.rot, v(0, 1, 0)), g.forward = rf_quat_rotate(f.rot, v(0, 0, 1));
    g.s = emit(b, &f);
    g.plan = plan;
    g.label = malloc((size_t)b->n * sizeof *g.label);
    for (int i = 0; i < b->n; i++)
        g.label[i] = b->j[i].label;
    free(b);
    return g;
}

void rigs_free(rigs_skel *g)
{
    rf_skeleton_free(g->s);
    free(g->label);
    memset(g, 0, sizeof *g);
}

/* ---- ground truth ---- */

static bool has_role(const rigs_skel *g, int role)
{
    for (uint32_t i = 0; i < g->s->joint_count; i++)
        if (g->label[i].part == RIGS_LIMB && g->label[i].role == role)
            return true;
    return false;
}

/* Which source limb roles may drive a target limb of role `tr`. */
static bool roles_fit(const rigs_skel *t, int tr, const rigs_skel *s, int sr)
{
    if (tr == sr)
        return true;
    if (tr == RIGS_MID) /* a middle pair: either neighbour's source */
        return sr == RIGS_FORE || sr == RIGS_HIND;
    if (tr == RIGS_WINGS) /* wings: the source's wings, else its forelimbs */
        return sr == RIGS_FORE && !has_role(s, RIGS_WINGS);
    if (tr == RIGS_FORE && sr == RIGS_WINGS) /* forelimbs from wings where the source has none */
        return !has_role(s, RIGS_FORE) && !has_role(t, RIGS_WINGS);
    return false;
}

/* Chains (spine interior, neck, tail): ends to ends, interior by overlapping place. */
static bool chain_fit(const rigs_label *x, const rigs_label *y)
{
    int n = x->count, m = y->count, i = x->index, k = y->index;
    if (x->part == RIGS_SPINE) { /* interior: pelvis and chest are the anchored ends */
        double lo = fmax((double)i / n, (double)k / m), hi = fmin((i + 1.0) / n, (k + 1.0) / m);
        return hi - lo >= 0.5 * fmin(1.0 / n, 1.0 / m) - 1e-9;
    }
    if (n == 1 || m == 1)
        return true;
    bool tf = i == 0, tl = i == n - 1, sf = k == 0, sl = k == m - 1;
    if (tf || tl || sf || sl)
        return (tf && sf) || (tl && sl);
    double lo = fmax((double)i / n, (double)k / m), hi = fmin((i + 1.0) / n, (k + 1.0) / m);
    return hi - lo >= 0.5 * fmin(1.0 / n, 1.0 / m) - 1e-9;
}

static int fingers_of(const rigs_label *l)
{
    return l->count;
}

static bool digit_fit(const rigs_skel *t, const rigs_label *x, const rigs_skel *s,
                      const rigs_label *y)
{
    if (!roles_fit(t, x->role, s, y->role) || x->thumb != y->thumb || x->foot != y->foot)
        return false;
    if (x->role == RIGS_WINGS) /* membrane fingers: any of the same side and segment */
        return x->seg == y->seg;
    if (x->seg != y->seg || x->thumb)
        return x->seg == y->seg;
    int n = fingers_of(x), m = fingers_of(y), i = x->digit, k = y->digit;
    if (n == 1 || m == 1)
        return true;
    double a = (double)i / (n - 1), c = (double)k / (m - 1);
    return fabs(a - c) <= 0.5 * fmax(1.0 / (n - 1), 1.0 / (m - 1)) + 1e-9;
}

static bool label_fit(const rigs_skel *t, const rigs_label *x, const rigs_skel *s,
                      const rigs_label *y)
{
    if (x->side != y->side || x->part == RIGS_HELPER || y->part == RIGS_HELPER)
        return false;
    /* a one-joint body is pelvis and chest at once */
    bool xbody = x->part == RIGS_PELVIS || x->part == RIGS_CHEST;
    bool ybody = y->part == RIGS_PELVIS || y->part == RIGS_CHEST;
    if (xbody && ybody &&
        (x->part == y->part || (x->part == RIGS_PELVIS && x->count == 1) ||
         (y->part == RIGS_PELVIS && y->count == 1)))
        return true;
    /* a toe digit of a foot and a foot's single toe bone */
    if (x->part == RIGS_DIGIT && x->foot && !x->thumb && x->seg == 1 && y->part == RIGS_LIMB)
        return y->seg == 4 && roles_fit(t, x->role, s, y->role);
    if (y->part == RIGS_DIGIT && y->foot && !y->thumb && y->seg == 1 && x->part == RIGS_LIMB)
        return x->seg == 4 && roles_fit(t, x->role, s, y->role);
    if (x->part != y->part)
        return false;
    switch (x->part) {
    case RIGS_SPINE:
    case RIGS_NECK:
    case RIGS_TAIL:
        return chain_fit(x, y);
    case RIGS_LIMB: /* a twist joint is its segment; a segment's own joint is not a twist */
        return x->seg == y->seg && roles_fit(t, x->role, s, y->role) && (x->twist || !y->twist);
    case RIGS_DIGIT:
        return digit_fit(t, x, s, y);
    default:
        return true;
    }
}

/* Unmapped is right where the source has no counterpart; where the target's chain has more
 * joints than the source's (its interior; both ends of a chain the source gives one joint);
 * for twist joints (the retargeter keeps them still with their segment), middle limb pairs,
 * wing fingers, and wings beside forelimbs when the source has no wings. */
static bool may_be_unmapped(const rigs_skel *t, const rigs_label *x, const rigs_skel *s)
{
    if (x->part == RIGS_HELPER || x->part == RIGS_ROOT || x->part == RIGS_JAW || x->twist ||
        x->role == RIGS_MID)
        return true;
    if (x->role == RIGS_WINGS && has_role(t, RIGS_FORE) && !has_role(s, RIGS_WINGS))
        return true;
    int fits = 0, m = 0;
    for (uint32_t j = 0; j < s->s->joint_count; j++)
        if (label_fit(t, x, s, &s->label[j]))
            fits++, m = s->label[j].count;
    if (!fits)
        return true;
    switch (x->part) {
    case RIGS_SPINE:
        return x->count > m;
    case RIGS_NECK:
    case RIGS_TAIL:
        if (m == 1)
            return x->count > 1;
        return x->index > 0 && x->index + 1 < x->count && x->count > m;
    case RIGS_DIGIT:
        return x->role == RIGS_WINGS;
    default:
        return false;
    }
}

bool rigs_accepts(const rigs_skel *target, uint32_t t, const rigs_skel *source, int32_t j)
{
    const rigs_label *x = &target->label[t];
    if (j < 0)
        return may_be_unmapped(target, x, source);
    if (x->part == RIGS_ROOT)
        return source->label[j].part == RIGS_ROOT;
    return label_fit(target, x, source, &source->label[j]);
}

bool rigs_swapped(const rigs_skel *target, uint32_t t, const rigs_skel *source, int32_t j)
{
    return j >= 0 && target->label[t].side && source->label[j].side &&
           target->label[t].side != source->label[j].side;
}
