/* Random skeletons with ground truth by construction (see gen.h). Bodies are laid out in a
 * canonical frame (+Y up, +Z forward, +X left), then turned, scaled, moved and written in one of
 * two rig conventions. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gen.h"

#define GEN_MAX 256

typedef struct gen_joint {
    int parent;
    int main;         /* the child continuing this bone, or -1 (its bone ends at tip) */
    rf_vec3 pos, tip; /* canonical frame; tip: where a leaf's bone ends */
    gen_label label;
    unsigned flags;
} gen_joint;

typedef struct gen_build {
    gen_joint j[GEN_MAX];
    int n;
    uint64_t rng;
    bool weights; /* helpers are flagged unweighted */
} gen_build;

static double rnd(gen_build *b)
{
    b->rng ^= b->rng >> 12, b->rng ^= b->rng << 25, b->rng ^= b->rng >> 27;
    return (double)((b->rng * 2685821657736338717ULL) >> 11) / 9007199254740992.0;
}

static double range(gen_build *b, double lo, double hi)
{
    return lo + (hi - lo) * rnd(b);
}
static int irange(gen_build *b, int lo, int hi)
{
    return lo + (int)(rnd(b) * (hi - lo + 1));
}

static int add(gen_build *b, int parent, rf_vec3 pos, gen_label label)
{
    if (b->n == GEN_MAX)
        return parent;
    gen_joint *j = &b->j[b->n];
    memset(j, 0, sizeof *j);
    j->parent = parent, j->pos = pos, j->label = label;
    j->tip = pos;
    j->main = -1;
    /* chains continue their parent's bone; jaws, eyes and the digits of a fan hang off it */
    bool side_branch = label.part == GEN_JAW || label.part == GEN_EYE ||
                       (label.part == GEN_DIGIT && label.seg == 1);
    if (parent >= 0 && b->j[parent].main < 0 && !side_branch)
        b->j[parent].main = b->n;
    return b->n++;
}

static gen_label lab(gen_part part, int side, int seg)
{
    gen_label l = {part, side, seg, 0, 0, false, 0};
    return l;
}

static rf_vec3 mirror_x(rf_vec3 v, int side)
{
    return side == 2 ? rf_v3(-v.x, v.y, v.z) : v;
}

/* A chain of n joints from a to b (pivots at a, ..., the last one before b), its last tip at b. */
static int chain(gen_build *b, int parent, rf_vec3 from, rf_vec3 to, int n, gen_part part,
                 double jitter)
{
    int last = parent;
    for (int i = 0; i < n; i++) {
        rf_vec3 p = rf_v3_lerp(from, to, (double)i / n);
        if (i)
            p = rf_v3_add(p, rf_v3(0, range(b, -jitter, jitter), range(b, -jitter, jitter)));
        gen_label l = lab(part, 0, i);
        l.place = (i + 0.5) / n;
        last = add(b, last, p, l);
    }
    b->j[last].tip = to;
    return last;
}

/* Fingers fanning from the wrist along `dir` (the hand's direction), thumb first. */
static void fingers(gen_build *b, int hand, rf_vec3 wrist, rf_vec3 dir, int side, int count,
                    bool wing, double len)
{
    rf_vec3 fwd = rf_v3(0, 0, 1);
    for (int d = 0; d < count; d++) {
        double spread = count > 1 ? (double)d / (count - 1) : 0.5;
        rf_vec3 v;
        if (wing) /* wing fingers spread in the horizontal plane, forward to back */
            v = rf_v3_normalize(rf_v3_add(rf_v3_scale(dir, 1 - 0.6 * spread),
                                          rf_v3_scale(fwd, 0.8 - 1.9 * spread)));
        else if (d == 0 && count > 1) /* the thumb: forward and out of the hand's line */
            v = rf_v3_normalize(rf_v3_add(dir, rf_v3(0, -0.2, 1.1)));
        else
            v = rf_v3_normalize(rf_v3_add(dir, rf_v3(0, 0, 0.25 - 0.5 * spread)));
        int segs = wing ? irange(b, 1, 2) : irange(b, 1, 3), at = hand;
        rf_vec3 p = rf_v3_add(wrist, rf_v3_scale(v, wing ? 0.01 : 0.02));
        for (int s = 0; s < segs; s++) {
            gen_label l = {GEN_DIGIT, side, s + 1, d, count, wing, spread};
            at = add(b, at, p, l);
            p = rf_v3_add(p, rf_v3_scale(v, len / segs));
        }
        b->j[at].tip = p;
    }
}

/* An arm from the chest: optional clavicle, upper arm, forearm, hand, fingers. */
static void arm(gen_build *b, int chest, rf_vec3 c, int side, double scale)
{
    double down = range(b, 0, 0.9); /* T-pose to A-pose */
    rf_vec3 dir =
        mirror_x(rf_v3_normalize(rf_v3(cos(down), -sin(down), range(b, -0.1, 0.1))), side);
    rf_vec3 shoulder = rf_v3_add(c, mirror_x(rf_v3(0.17 * scale, -0.04, 0), side));
    int at = chest;
    if (rnd(b) < 0.6)
        at = add(b, at, rf_v3_add(c, mirror_x(rf_v3(range(b, 0, 0.04), 0, 0), side)),
                 lab(GEN_FORE, side, 0));
    double up = range(b, 0.26, 0.34) * scale, lo = range(b, 0.24, 0.3) * scale;
    at = add(b, at, shoulder, lab(GEN_FORE, side, 1));
    rf_vec3 elbow = rf_v3_add(shoulder, rf_v3_scale(dir, up));
    at = add(b, at, elbow, lab(GEN_FORE, side, 2));
    rf_vec3 wrist = rf_v3_add(elbow, rf_v3_scale(dir, lo));
    at = add(b, at, wrist, lab(GEN_FORE, side, 3));
    int count = irange(b, 0, 5);
    b->j[at].tip = rf_v3_add(wrist, rf_v3_scale(dir, 0.08 * scale));
    if (count)
        fingers(b, at, wrist, dir, side, count, false, 0.09 * scale);
}

/* A leg from the pelvis: optional hip offset, thigh, shin, foot, optional toe. `digitigrade`
 * puts the ankle high with a long metatarsus (quadrupeds' hind legs); `front` makes a foreleg. */
static void leg(gen_build *b, int pelvis, rf_vec3 hip, double height, int side, bool digitigrade,
                gen_part part, double width)
{
    rf_vec3 socket = rf_v3_add(hip, mirror_x(rf_v3(width, -0.05 * height, 0), side));
    int at = pelvis;
    if (part == GEN_HIND && rnd(b) < 0.4)
        at = add(b, at, hip, lab(part, side, 0));
    double knee = range(b, 0.45, 0.55), ankle = digitigrade ? range(b, 0.25, 0.35) : 0.06;
    double bend = part == GEN_FORE ? -0.02 : 0.04;
    at = add(b, at, socket, lab(part, side, 1));
    rf_vec3 k = rf_v3(socket.x, height * knee, socket.z + bend * height);
    at = add(b, at, k, lab(part, side, 2));
    double hock = digitigrade && part == GEN_HIND ? -0.06 : 0.0;
    rf_vec3 a = rf_v3(socket.x, height * ankle, socket.z + hock * height);
    at = add(b, at, a, lab(part, side, 3));
    rf_vec3 ball = rf_v3(socket.x, 0.01 * height, a.z + (digitigrade ? 0.03 : 0.12) * height);
    if (rnd(b) < 0.7) {
        at = add(b, at, ball, lab(part, side, 4));
        b->j[at].tip = rf_v3(socket.x, 0, ball.z + 0.06 * height);
    } else {
        b->j[at].tip = ball;
    }
}

static void head(gen_build *b, int neck_end, rf_vec3 p, rf_vec3 toward, double size)
{
    int h = add(b, neck_end, p, lab(GEN_HEAD, 0, 0));
    b->j[h].tip = rf_v3_add(p, rf_v3_scale(toward, size));
    if (rnd(b) < 0.3) { /* a jaw under the skull */
        int jaw = add(b, h, rf_v3_add(p, rf_v3(0, -0.3 * size, 0.2 * size)), lab(GEN_JAW, 0, 0));
        b->j[jaw].tip = rf_v3_add(b->j[jaw].pos, rf_v3(0, -0.2 * size, 0.5 * size));
    }
    if (rnd(b) < 0.3) /* eyes */
        for (int side = 1; side <= 2; side++) {
            int e =
                add(b, h, rf_v3_add(p, mirror_x(rf_v3(0.3 * size, 0.3 * size, 0.5 * size), side)),
                    lab(GEN_EYE, side, 0));
            b->j[e].tip = rf_v3_add(b->j[e].pos, rf_v3(0, 0, 0.1 * size));
        }
}

/* Spine from the pelvis to the chest: n joints, the first the pelvis, the last the chest. */
static int spine(gen_build *b, int parent, rf_vec3 pelvis, rf_vec3 chest, int n, int *first)
{
    int at = parent;
    for (int i = 0; i < n; i++) {
        rf_vec3 p = rf_v3_lerp(pelvis, chest, (double)i / (n - 1));
        if (i && i + 1 < n)
            p = rf_v3_add(p, rf_v3(0, range(b, -0.01, 0.01), range(b, -0.02, 0.02)));
        gen_label l = lab(i == 0 ? GEN_PELVIS : i + 1 == n ? GEN_CHEST : GEN_SPINE, 0, i);
        l.place = (double)i / (n - 1);
        at = add(b, at, p, l);
        if (i == 0)
            *first = at;
    }
    return at;
}

static void biped(gen_build *b, int root)
{
    double leg_h = range(b, 0.8, 1.0), torso = range(b, 0.45, 0.6), s = range(b, 0.8, 1.2);
    rf_vec3 hips = rf_v3(0, leg_h, 0), top = rf_v3(0, leg_h + torso, range(b, -0.03, 0.03));
    int pelvis, chest = spine(b, root, hips, top, irange(b, 2, 5), &pelvis);
    rf_vec3 neck_top = rf_v3_add(top, rf_v3(0, range(b, 0.08, 0.15), range(b, 0, 0.03)));
    int neck = chain(b, chest, top, neck_top, irange(b, 1, 3), GEN_NECK, 0.005);
    head(b, neck, neck_top, rf_v3(0, 1, 0), range(b, 0.15, 0.25));
    uint64_t state = b->rng; /* the same draws for both sides: a symmetric body */
    for (int side = 1; side <= 2; side++)
        b->rng = state, arm(b, chest, rf_v3_add(top, rf_v3(0, -0.03, 0)), side, s);
    state = b->rng;
    for (int side = 1; side <= 2; side++)
        b->rng = state, leg(b, pelvis, hips, leg_h, side, false, GEN_HIND, 0.1);
}

static void quadruped(gen_build *b, int root, bool wings)
{
    double h = range(b, 0.6, 1.0), len = range(b, 0.6, 1.2);
    rf_vec3 pelvis_p = rf_v3(0, h, -len / 2), chest_p = rf_v3(0, h + range(b, -0.05, 0.1), len / 2);
    int pelvis, chest = spine(b, root, pelvis_p, chest_p, irange(b, 3, 6), &pelvis);
    rf_vec3 nt = rf_v3_add(chest_p, rf_v3(0, range(b, 0.15, 0.4), range(b, 0.2, 0.4)));
    int neck = chain(b, chest, chest_p, nt, irange(b, 1, 4), GEN_NECK, 0.01);
    head(b, neck, nt, rf_v3_normalize(rf_v3(0, -0.3, 1)), range(b, 0.15, 0.3));
    int tails = irange(b, 0, 8);
    if (tails)
        chain(b, pelvis, rf_v3_add(pelvis_p, rf_v3(0, 0.03, -0.08)),
              rf_v3_add(pelvis_p, rf_v3(0, range(b, -0.3, 0.2), -range(b, 0.4, 1.0))), tails,
              GEN_TAIL, 0.02);
    double width = range(b, 0.1, 0.2);
    uint64_t state = b->rng; /* the same draws for both sides: a symmetric body */
    for (int side = 1; side <= 2; side++) {
        b->rng = state;
        leg(b, chest, chest_p, h, side, rnd(b) < 0.5, GEN_FORE, width);
        leg(b, pelvis, pelvis_p, h, side, true, GEN_HIND, width);
    }
    state = b->rng;
    for (int side = 1; wings && side <= 2; side++) {
        b->rng = state;
        rf_vec3 dir =
            mirror_x(rf_v3_normalize(rf_v3(1, range(b, -0.1, 0.3), range(b, -0.3, 0.1))), side);
        rf_vec3 sh = rf_v3_add(chest_p, mirror_x(rf_v3(0.15, 0.1, 0), side));
        int at = add(b, chest, sh, lab(GEN_WING, side, 1));
        rf_vec3 el = rf_v3_add(sh, rf_v3_scale(dir, range(b, 0.5, 0.8)));
        at = add(b, at, el, lab(GEN_WING, side, 2));
        rf_vec3 wr = rf_v3_add(el, rf_v3_scale(dir, range(b, 0.5, 0.9)));
        fingers(b, at, wr, dir, side, irange(b, 3, 5), true, range(b, 0.8, 1.5));
        b->j[at].tip = wr;
    }
}

/* IK targets at the feet and poles in front of the knees, parented to the root. */
static void helpers(gen_build *b, int root)
{
    int n = b->n;
    for (int i = 0; i < n; i++) {
        const gen_label *l = &b->j[i].label;
        if (l->part != GEN_HIND || l->seg != 3)
            continue;
        int t = add(b, root, b->j[i].pos, lab(GEN_HELPER, l->side, 0));
        b->j[t].flags = RF_JOINT_UNWEIGHTED;
        b->j[t].tip = rf_v3_add(b->j[t].pos, rf_v3(0, 0, 0.05));
        int p =
            add(b, root, rf_v3_add(b->j[i].pos, rf_v3(0, 0.4, 0.5)), lab(GEN_HELPER, l->side, 0));
        b->j[p].flags = RF_JOINT_UNWEIGHTED;
        b->j[p].tip = rf_v3_add(b->j[p].pos, rf_v3(0, 0, 0.05));
    }
}

/* ---- writing the skeleton ---- */

static rf_vec3 bone_end(const gen_build *b, int i)
{
    return b->j[i].main >= 0 ? b->j[b->j[i].main].pos : b->j[i].tip;
}

static char *name_of(gen_build *b, int i, bool meaningful)
{
    static const char *const parts[] = {"helper", "pelvis", "spine", "chest", "neck",
                                        "head",   "tail",   "fore",  "hind",  "digit",
                                        "wing",   "ground", "jaw",   "eye"};
    static const char *const sides[] = {"", "_L", "_R"};
    char buf[64];
    if (meaningful)
        snprintf(buf, sizeof buf, "%s%d%s_%d", parts[b->j[i].label.part], b->j[i].label.seg,
                 sides[b->j[i].label.side], i);
    else
        snprintf(buf, sizeof buf, "j%03x%c", (unsigned)(rnd(b) * 4000) * 1000 + (unsigned)i,
                 'a' + (int)(rnd(b) * 26));
    char *s = malloc(strlen(buf) + 1);
    strcpy(s, buf);
    return s;
}

typedef struct gen_frame {
    rf_quat rot;
    double scale;
    rf_vec3 offset;
    bool blender; /* bones along local +Y, leaves without end sites */
} gen_frame;

static rf_quat bone_rotation(gen_build *b, rf_vec3 dir)
{
    rf_quat q = rf_quat_from_two_vectors(rf_v3(0, 1, 0), dir);
    return rf_quat_mul(q, rf_quat_from_axis_angle(rf_v3(0, 1, 0), range(b, -3, 3)));
}

static void write_joint(gen_build *b, const gen_frame *f, rf_skeleton *s, rf_quat *world, int i)
{
    rf_joint *j = &s->joints[i];
    int p = b->j[i].parent;
    rf_vec3 pos = rf_v3_add(rf_quat_rotate(f->rot, rf_v3_scale(b->j[i].pos, f->scale)), f->offset);
    rf_vec3 end =
        rf_v3_add(rf_quat_rotate(f->rot, rf_v3_scale(bone_end(b, i), f->scale)), f->offset);
    rf_vec3 ppos =
        p >= 0 ? rf_v3_add(rf_quat_rotate(f->rot, rf_v3_scale(b->j[p].pos, f->scale)), f->offset)
               : rf_v3(0, 0, 0);
    j->parent = p;
    j->flags = b->weights ? b->j[i].flags : 0;
    world[i] = rf_quat_identity();
    if (f->blender && rf_v3_dist(end, pos) > 1e-9)
        world[i] = bone_rotation(b, rf_v3_sub(end, pos));
    rf_quat pr = p >= 0 ? world[p] : rf_quat_identity();
    j->rest.t = rf_quat_rotate(rf_quat_conj(pr), rf_v3_sub(pos, ppos));
    j->rest.r = rf_quat_normalize(rf_quat_mul(rf_quat_conj(pr), world[i]));
    bool leaf = true;
    for (int k = i + 1; k < b->n && leaf; k++)
        leaf = b->j[k].parent != i;
    if (leaf && !f->blender && rf_v3_dist(end, pos) > 1e-9 && rnd(b) < 0.8) {
        j->flags |= RF_JOINT_HAS_END_SITE;
        j->end_site = rf_v3_sub(end, pos);
    }
}

static rf_skeleton *emit(gen_build *b, const gen_frame *f, bool meaningful)
{
    rf_skeleton *s = rf_skeleton_new((uint32_t)b->n);
    rf_quat world[GEN_MAX];
    for (int i = 0; i < b->n; i++) {
        write_joint(b, f, s, world, i);
        s->joints[i].name = name_of(b, i, meaningful);
    }
    return s;
}

static rf_vec3 to_frame(const gen_frame *f, rf_vec3 p)
{
    return rf_v3_add(rf_quat_rotate(f->rot, rf_v3_scale(p, f->scale)), f->offset);
}

/* The bones and axes as built, for gen_skel's body fields; draws nothing from the generator. */
static void body_frame(const gen_build *b, const gen_frame *f, gen_skel *g)
{
    g->bone_from = malloc((size_t)b->n * sizeof *g->bone_from);
    g->bone_to = malloc((size_t)b->n * sizeof *g->bone_to);
    for (int i = 0; i < b->n; i++) {
        g->bone_from[i] = to_frame(f, b->j[i].pos);
        g->bone_to[i] = to_frame(f, bone_end(b, i));
    }
    g->up = rf_quat_rotate(f->rot, rf_v3(0, 1, 0));
    g->forward = rf_quat_rotate(f->rot, rf_v3(0, 0, 1));
    g->scale = f->scale;
}

gen_skel gen_make(gen_plan plan, uint64_t seed)
{
    gen_build *b = calloc(1, sizeof *b);
    gen_skel g = {0};
    b->rng = seed * 0x9E3779B97F4A7C15ULL + 1;
    b->weights = rnd(b) < 0.5;
    int root = -1;
    if (rnd(b) < 0.5) { /* a ground root above the body */
        root = add(b, -1, rf_v3(0, 0, 0), lab(GEN_GROUND, 0, 0));
        b->j[root].flags = RF_JOINT_UNWEIGHTED;
    }
    if (plan == GEN_BIPED)
        biped(b, root);
    else
        quadruped(b, root, plan == GEN_DRAGON);
    if (root >= 0 && b->weights && rnd(b) < 0.7)
        helpers(b, root);
    gen_frame f = {rf_quat_from_axis_angle(rf_v3(0, 1, 0), range(b, -RF_PI, RF_PI)),
                   exp(range(b, log(0.01), log(100))), rf_v3(range(b, -5, 5), 0, range(b, -5, 5)),
                   rnd(b) < 0.5};
    if (rnd(b) < 0.25) /* Z up */
        f.rot = rf_quat_mul(rf_quat_from_axis_angle(rf_v3(1, 0, 0), RF_PI / 2), f.rot);
    g.s = emit(b, &f, rnd(b) < 0.5);
    g.plan = plan;
    body_frame(b, &f, &g);
    g.label = malloc((size_t)b->n * sizeof *g.label);
    for (int i = 0; i < b->n; i++)
        g.label[i] = b->j[i].label;
    free(b);
    return g;
}

void gen_free(gen_skel *g)
{
    rf_skeleton_free(g->s);
    free(g->label);
    free(g->bone_from);
    free(g->bone_to);
    memset(g, 0, sizeof *g);
}

/* ---- ground truth ---- */

static int chain_count(const gen_skel *g, gen_part part)
{
    int n = 0;
    for (uint32_t i = 0; i < g->s->joint_count; i++)
        n += g->label[i].part == part;
    return n;
}

static int finger_count(const gen_skel *g, int side, bool wing)
{
    int most = 0;
    for (uint32_t i = 0; i < g->s->joint_count; i++)
        if (g->label[i].part == GEN_DIGIT && g->label[i].side == side && g->label[i].wing == wing)
            most = g->label[i].fingers > most ? g->label[i].fingers : most;
    return most;
}

/* Where along its chain a joint sits, and how close two places must be. */
static bool near_place(const gen_skel *a, const gen_label *x, const gen_skel *b, const gen_label *y)
{
    int na = chain_count(a, x->part), nb = chain_count(b, y->part);
    if (x->part == GEN_SPINE)
        na += 2, nb += 2; /* pelvis and chest are the chain's ends */
    double step = fmax(1.0 / (na > 1 ? na - (x->part == GEN_SPINE) : 1),
                       1.0 / (nb > 1 ? nb - (x->part == GEN_SPINE) : 1));
    return fabs(x->place - y->place) <= 0.5 * step + 1e-9;
}

static bool thumb(const gen_label *l)
{
    return l->digit == 0 && l->fingers > 1 && !l->wing;
}

static bool label_match(const gen_skel *t, const gen_label *x, const gen_skel *s,
                        const gen_label *y)
{
    if (x->part == GEN_HELPER || y->part == GEN_HELPER || x->side != y->side)
        return false;
    if (x->part != y->part)
        return false;
    switch (x->part) {
    case GEN_SPINE:
    case GEN_NECK:
    case GEN_TAIL:
        return near_place(t, x, s, y);
    case GEN_FORE:
    case GEN_HIND:
    case GEN_WING:
        return x->seg == y->seg;
    case GEN_DIGIT:
        if (x->wing != y->wing || x->seg != y->seg)
            return false;
        return x->wing ? fabs(x->place - y->place) <= 0.35 : thumb(x) == thumb(y);
    default:
        return true;
    }
}

/* Unmapped is right when the source has no counterpart, or fewer joints in that chain. */
static bool may_be_unmapped(const gen_skel *t, const gen_label *x, const gen_skel *s)
{
    if (x->part == GEN_HELPER || x->part == GEN_GROUND || x->part == GEN_JAW || x->part == GEN_EYE)
        return true;
    for (uint32_t j = 0; j < s->s->joint_count; j++)
        if (label_match(t, x, s, &s->label[j]))
            goto found;
    return true;
found:
    if (x->part == GEN_SPINE || x->part == GEN_NECK || x->part == GEN_TAIL)
        return chain_count(t, x->part) > chain_count(s, x->part);
    if (x->part == GEN_DIGIT)
        return !thumb(x) && finger_count(t, x->side, x->wing) > finger_count(s, x->side, x->wing);
    return false;
}

bool gen_accepts(const gen_skel *target, uint32_t t, const gen_skel *source, int32_t j)
{
    const gen_label *x = &target->label[t];
    if (j < 0)
        return may_be_unmapped(target, x, source);
    return label_match(target, x, source, &source->label[j]);
}

bool gen_swapped(const gen_skel *target, uint32_t t, const gen_skel *source, int32_t j)
{
    return j >= 0 && target->label[t].side && source->label[j].side &&
           target->label[t].side != source->label[j].side;
}
