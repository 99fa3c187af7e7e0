/* The skeletal-similarity matcher: scoring, the best candidates, the one-input-section rule,
 * duplicate-bone removal, the threshold, reversed knees, mirroring, blending several sources. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <rigflow/model-copy.h>

#include "ms-internal.h"

#define RF_MS_DEFAULT_THRESHOLD 80.0

static const rf_ms_candidate no_candidate = {RF_MS_NO_SOURCE, 0, 0, {0}};

static double total_of(const double *m)
{
    double t = 0;
    for (int i = 0; i < RF_MS_METRIC_COUNT; i++)
        t += m[i];
    return t;
}

/* ---- set-up ---- */

/* Every second pair of legs, counted from the front: its sides swap (the thesis's mirror
 * setting) or it is flagged to play half a cycle away. */
static void mirror_setup(rf_ms_ctx *c)
{
    const rf_analysis *a = c->tgt.a;
    for (uint32_t s = 0; s < a->section_count; s++) {
        const rf_section *sec = &a->sections[s];
        int32_t limb = (int32_t)s; /* a foot takes its leg's rank */
        while (limb >= 0 && a->sections[limb].type != RF_SECTION_LEG)
            limb = a->sections[limb].type == RF_SECTION_FOOT ? a->sections[limb].parent : -1;
        bool second = limb >= 0 && a->sections[limb].pair_rank % 2 == 1;
        c->flip[s] = second && c->o->mirror == RF_MS_MIRROR_SWAP;
        c->phase[s] = (second && c->o->mirror == RF_MS_MIRROR_PHASE) || c->gait[s];
        (void)sec;
    }
}

static bool ctx_init(rf_ms_ctx *c, const rf_skeleton *target, const rf_skeleton *const *sources,
                     uint32_t n, const rf_ms_options *o, char *err, size_t err_size)
{
    memset(c, 0, sizeof *c);
    c->o = o;
    uint32_t unused;
    if (o->weights)
        c->wt = *o->weights;
    else
        rf_ms_weight_set(o->thesis ? "thesis" : "default", &c->wt, &unused);
    c->threshold = o->threshold_given ? o->threshold : RF_MS_DEFAULT_THRESHOLD;
    c->angle = o->orientation_angle > 0 ? o->orientation_angle
               : o->thesis              ? fmax(1e-6, c->wt.w[RF_MS_ORIENTATION])
                                        : 45.0;
    c->cos_angle = c->angle < 180 ? cos(c->angle * RF_PI / 180.0) : -2;
    c->nsrc = n;
    c->src = calloc(n ? n : 1, sizeof *c->src);
    if (!c->src || !rf_ms_skel_init(&c->tgt, target, &o->target_analysis, o->thesis)) {
        snprintf(err, err_size, "out of memory analysing the target skeleton");
        return false;
    }
    for (uint32_t k = 0; k < n; k++)
        if (!rf_ms_skel_init(&c->src[k], sources[k], &o->source_analysis, o->thesis)) {
            snprintf(err, err_size, "out of memory analysing source %u", k);
            return false;
        }
    size_t ns = c->tgt.a->section_count ? c->tgt.a->section_count : 1;
    c->flip = calloc(ns, 1);
    c->phase = calloc(ns, 1);
    c->gait = calloc(ns, 1);
    if (!c->flip || !c->phase || !c->gait) {
        snprintf(err, err_size, "out of memory");
        return false;
    }
    c->gait_legs = rf_ms_gait_setup(c);
    mirror_setup(c);
    return true;
}

static void ctx_clear(rf_ms_ctx *c)
{
    rf_ms_skel_clear(&c->tgt);
    for (uint32_t k = 0; c->src && k < c->nsrc; k++)
        rf_ms_skel_clear(&c->src[k]);
    free(c->src);
    free(c->flip);
    free(c->phase);
    free(c->gait);
}

static bool source_on(const rf_ms_ctx *c, uint32_t k, int32_t only)
{
    return (only < 0 || (uint32_t)only == k) && !(c->o->disabled && c->o->disabled[k]);
}

/* ---- the best candidates ---- */

/* A source section as a candidate section for the current target section: its row in `sec`,
 * the sum of its section metrics, and which source and section it is. */
typedef struct rf_ms_row {
    double base;
    uint32_t row, k, ss;
} rf_ms_row;

typedef struct rf_ms_pass {
    rf_ms_candidate *best;  /* [target joint] */
    rf_ms_candidate *final; /* [target joint] */
    uint8_t *settled;       /* [target joint] assigned with its limb (a lent digit; 2: a toe;
                             * 3: a girdle joint taking a neck, neck_at_girdle; 4: a headless
                             * trunk's girdle joint taking the head, head_at_girdle; 5: a
                             * rear trunk joint taking a reverse spine, trunk_from_rear; 6: a
                             * trunk rooted at the front taking places, trunk_from_front; 7: a
                             * joint given the joint holding its unweighted match's skin,
                             * skin_holders) */
    rf_ms_candidate *top;   /* [target joint * 3] or NULL */
    uint8_t *top_count;
    double *sec;       /* section metrics of the current target section against every
                        * source section: [sum of source sections][metric] */
    uint32_t *sec_off; /* [source] first row of source k in sec */
    rf_ms_row *rows;   /* the source sections worth scoring, best section metrics first */
    uint32_t row_count;
} rf_ms_pass;

/* The best three candidates of one target joint. Equal totals keep the order the sources,
 * sections and joints come in (rank), whatever order they are scored in. */
typedef struct rf_ms_top {
    rf_ms_candidate *c;
    uint64_t rank[3];
    uint8_t *count;
} rf_ms_top;

static void keep_top(rf_ms_top *top, const rf_ms_candidate *cand, uint64_t rank)
{
    int n = *top->count, at = n;
    while (at > 0 && (cand->total > top->c[at - 1].total ||
                      (cand->total == top->c[at - 1].total && rank < top->rank[at - 1])))
        at--;
    if (at >= 3)
        return;
    for (int i = (n < 3 ? n : 2); i > at; i--)
        top->c[i] = top->c[i - 1], top->rank[i] = top->rank[i - 1];
    top->c[at] = *cand, top->rank[at] = rank;
    if (n < 3)
        (*top->count)++;
}

static double top_floor(const rf_ms_top *top)
{
    return *top->count == 3 ? top->c[2].total : -INFINITY;
}

static bool kinds_meet(uint8_t kt, uint8_t ks)
{
    if (kt == RF_MK_HELPER || ks == RF_MK_HELPER)
        return false;
    return (kt == RF_MK_ROOT) == (ks == RF_MK_ROOT); /* ground roots only with ground roots */
}

static int cmp_row(const void *a, const void *b)
{
    const rf_ms_row *x = a, *y = b;
    if (x->base != y->base)
        return x->base > y->base ? -1 : 1;
    return (x->row > y->row) - (x->row < y->row);
}

/* Scores target section ts against every source section, and sorts those its joints may match
 * best first: a joint's search then stops at the first section that cannot reach its top three. */
static void section_rows(const rf_ms_ctx *c, rf_ms_pass *p, uint32_t ts, int32_t only)
{
    p->row_count = 0;
    for (uint32_t k = 0; k < c->nsrc; k++) {
        if (!source_on(c, k, only))
            continue;
        for (uint32_t ss = 0; ss < c->src[k].a->section_count; ss++) {
            if (!kinds_meet(c->tgt.kind[ts], c->src[k].kind[ss]))
                continue;
            uint32_t row = p->sec_off[k] + ss;
            double *sm = &p->sec[(size_t)row * RF_MS_METRIC_COUNT];
            rf_ms_section_metrics(c, ts, k, ss, sm);
            p->rows[p->row_count++] = (rf_ms_row){total_of(sm), row, k, ss};
        }
    }
    qsort(p->rows, p->row_count, sizeof *p->rows, cmp_row);
}

/* The most a metric can add: its weight, or nothing when a user made the weight negative. */
static double most(double w)
{
    return w > 0 ? w : 0;
}

/* One source joint as a candidate for target joint t: skipped (false) when even full
 * orientation points could not lift it past `floor`, the third best so far, so the angle is
 * only computed for candidates that may enter the top three. */
static bool score_candidate(const rf_ms_ctx *c, const double *sm, double base, uint32_t t,
                            uint32_t k, uint32_t j, const rf_ms_candidate *parent, double floor,
                            rf_ms_candidate *cand)
{
    double seq = rf_ms_sequence(c, t, k, j), cont = rf_ms_continuity(c, parent, k, j);
    if (base + seq + cont + most(c->wt.w[RF_MS_ORIENTATION]) < floor - 1e-9)
        return false; /* the margin: the bound adds in another order than total_of */
    *cand = (rf_ms_candidate){k, j, 0, {0}};
    memcpy(cand->metrics, sm, sizeof cand->metrics);
    cand->metrics[RF_MS_SEQUENCE] = seq;
    cand->metrics[RF_MS_CONTINUITY] = cont;
    cand->metrics[RF_MS_ORIENTATION] = rf_ms_orientation(c, t, k, j);
    cand->total = total_of(cand->metrics);
    return true;
}

/* Scores target joint t against the joints of the source sections that can still enter its top
 * three (a section's metrics plus the most its joints can add bound what it can reach). */
static void score_joint(const rf_ms_ctx *c, rf_ms_pass *p, uint32_t t)
{
    const double *w = c->wt.w;
    double joint_max =
        most(w[RF_MS_ORIENTATION]) + most(w[RF_MS_SEQUENCE]) + most(w[RF_MS_CONTINUITY]);
    int32_t pa = c->tgt.anc[t];
    const rf_ms_candidate *parent = pa >= 0 ? &p->best[pa] : NULL;
    rf_ms_candidate local[3];
    uint8_t nlocal = 0;
    rf_ms_top top = {
        p->top ? &p->top[(size_t)t * 3] : local, {0}, p->top ? &p->top_count[t] : &nlocal};
    for (uint32_t r = 0; r < p->row_count; r++) {
        const rf_ms_row *row = &p->rows[r];
        if (row->base + joint_max < top_floor(&top) - 1e-9)
            break; /* sorted: no later section can do better */
        const rf_ms_skel *s = &c->src[row->k];
        const double *sm = &p->sec[(size_t)row->row * RF_MS_METRIC_COUNT];
        const uint32_t *js = rf_section_joints(s->a, row->ss);
        for (uint32_t i = 0; i < s->a->sections[row->ss].bone_count; i++) {
            rf_ms_candidate cand;
            if (s->matchable[js[i]] &&
                score_candidate(c, sm, row->base, t, row->k, js[i], parent, top_floor(&top), &cand))
                keep_top(&top, &cand, (uint64_t)row->row << 32 | i);
        }
    }
    p->best[t] = *top.count ? top.c[0] : no_candidate;
}

static void select_best(const rf_ms_ctx *c, rf_ms_pass *p, int32_t only)
{
    const rf_analysis *a = c->tgt.a;
    for (uint32_t ts = 0; ts < a->section_count; ts++) {
        section_rows(c, p, ts, only);
        const uint32_t *js = rf_section_joints(a, ts);
        for (uint32_t i = 0; i < a->sections[ts].bone_count; i++) {
            uint32_t t = js[i];
            p->best[t] = no_candidate;
            if (c->tgt.matchable[t] && c->tgt.kind[ts] != RF_MK_HELPER)
                score_joint(c, p, t);
        }
    }
}

/* ---- one input section per target section, duplicate removal ---- */

/* A section's joints as the assignment sees them: the joint, its place counted in bones, its
 * pivot and tip along the section. A limb may go on into its main digit. */
/* A mapped entry of a line by the source section its best candidate lies in (input_section). */
typedef struct rf_ms_vote {
    uint64_t key; /* source << 32 | section */
    uint32_t i;   /* the entry */
} rf_ms_vote;

typedef struct rf_ms_line {
    uint32_t *joint;
    int32_t *step;
    double *u0, *u1;
    rf_ms_vote *vote; /* scratch for input_section */
    uint32_t n;
    double unit;   /* what places along the line were divided by */
    int32_t last;  /* the largest step (line_summary) */
    bool cut;      /* a bone cut in two (has_cut), kept so each pair's cost stays O(1) */
    int32_t first; /* the first real bone's entry, -1 when none (line_summary, turned) */
    bool cut_end;  /* its last entry ends the section though it is not the section's last
                    * (spine_before_girdle) */
    int32_t skull; /* in a head, the entry standing for the skull when not its last (skull_at),
                    * else -1 */
} rf_ms_line;

static bool line_alloc(rf_ms_line *l, uint32_t cap)
{
    cap = cap ? cap : 1;
    l->joint = malloc(cap * sizeof *l->joint);
    l->step = malloc(cap * sizeof *l->step);
    l->u0 = malloc(cap * sizeof *l->u0);
    l->u1 = malloc(cap * sizeof *l->u1);
    l->vote = malloc(cap * sizeof *l->vote);
    l->n = 0;
    return l->joint && l->step && l->u0 && l->u1 && l->vote;
}

static void line_free(rf_ms_line *l)
{
    free(l->joint);
    free(l->step);
    free(l->u0);
    free(l->u1);
    free(l->vote);
}

static bool is_limb(const rf_analysis *a, uint32_t s)
{
    rf_section_type t = a->sections[s].type;
    return (t == RF_SECTION_ARM || t == RF_SECTION_LEG) && !(a->sections[s].flags & RF_SECFL_FAN);
}

static void line_section(const rf_ms_skel *s, uint32_t sec, rf_ms_line *l)
{
    const uint32_t *js = rf_section_joints(s->a, sec);
    l->n = 0;
    for (uint32_t i = 0; i < s->a->sections[sec].bone_count; i++) {
        uint32_t j = js[i];
        if (!s->matchable[j])
            continue;
        l->joint[l->n] = j, l->step[l->n] = s->step[j];
        l->u0[l->n] = s->a->joints[j].u0, l->u1[l->n] = s->a->joints[j].u1;
        l->n++;
    }
    /* a limb's length reaches the end of its longest digit: where its own bones end */
    l->unit = 1;
    if (l->n && is_limb(s->a, sec) && l->u1[l->n - 1] > 0.2 && l->u1[l->n - 1] < 1)
        l->unit = l->u1[l->n - 1];
}

/* Two limbs that both end in digits, one with far longer digits than the other, are placed
 * along their own bones: a wing's long membrane fingers would crowd its arm into the first half
 * of its length, against an arm whose fingers are short. */
static void own_places(rf_ms_line *tl, rf_ms_line *sl)
{
    if (tl->unit >= 1 || sl->unit >= 1 || fmin(tl->unit, sl->unit) > 0.7 * fmax(tl->unit, sl->unit))
        return;
    for (uint32_t i = 0; i < tl->n; i++)
        tl->u0[i] /= tl->unit, tl->u1[i] /= tl->unit;
    for (uint32_t i = 0; i < sl->n; i++)
        sl->u0[i] /= sl->unit, sl->u1[i] /= sl->unit;
}

/* The joints of a limb's main digit after the limb's own, placed along the limb (whose length
 * reaches the end of its longest digit). Returns the digit section, or -1 when there is none. */
static int32_t line_digit(const rf_ms_skel *s, uint32_t sec, rf_ms_line *l)
{
    const rf_analysis *a = s->a;
    const rf_section *limb = &a->sections[sec];
    uint32_t last = rf_section_joints(a, sec)[limb->bone_count - 1];
    int32_t d = s->main_digit[last];
    if (d < 0 || l->n == 0)
        return -1;
    double base = a->joints[last].u1,
           scale = limb->length > 0 ? a->sections[d].length / limb->length : 0;
    int32_t step = l->step[l->n - 1] + 1;
    const uint32_t *js = rf_section_joints(a, (uint32_t)d);
    for (uint32_t i = 0; i < a->sections[d].bone_count; i++) {
        uint32_t j = js[i];
        if (!s->matchable[j])
            continue;
        l->joint[l->n] = j, l->step[l->n] = step + s->step[j];
        l->u0[l->n] = base + a->joints[j].u0 * scale, l->u1[l->n] = base + a->joints[j].u1 * scale;
        l->n++;
    }
    return d;
}

/* What a bone of difference in the count from the limb's start costs: digits and chains of one
 * bone anchor on it (0.6); limbs line up by it (0.3), unless the one with more real bones has a
 * bone cut in two (two in a straight line, as rigs cut a thigh or forearm for twist): past the
 * cut the count is off and places decide (0.1). */
static int32_t last_step(const rf_ms_line *l)
{
    int32_t most = 0;
    for (uint32_t i = 0; i < l->n; i++)
        most = l->step[i] > most ? l->step[i] : most;
    return most;
}

/* Whether a line has two real bones in a straight line, one continuing the other (under half a
 * degree), while it bends elsewhere (two degrees or more): a bone cut in two. */
/* The cosine of the angle between real bones i - 1 and i of a line (a bone continuing another
 * may give a hair over 1), or 2 when either is no real bone (an offset, zero length) or the
 * second is a leaf whose direction is only guessed (often its parent's: no straight cut). */
static double turn_cos(const rf_analysis *a, const rf_ms_line *l, uint32_t i)
{
    const rf_joint_info *p = &a->joints[l->joint[i - 1]], *j = &a->joints[l->joint[i]];
    if (l->step[i - 1] < 0 || p->length <= 0 || j->length <= 0 ||
        ((p->flags | j->flags) & RF_JI_ZERO_LENGTH) || (j->flags & RF_JI_TIP_GUESSED))
        return 2;
    return rf_v3_dot(p->dir, j->dir);
}

static bool has_cut(const rf_analysis *a, const rf_ms_line *l)
{
    bool straight = false, bent = false;
    double longest = 0;
    uint32_t own = 0; /* the limb's own bones: a digit lent to the line turns across the hand */
    while (own < l->n && a->joints[l->joint[own]].section == a->joints[l->joint[0]].section)
        longest = fmax(longest, a->joints[l->joint[own++]].length);
    uint32_t long_straight = 0;
    for (uint32_t i = 1; i < own; i++) {
        double d = turn_cos(a, l, i);
        /* an elbow or a knee joins two long bones; a hand or a foot is short */
        bool elbow =
            fmin(a->joints[l->joint[i - 1]].length, a->joints[l->joint[i]].length) >= 0.5 * longest;
        bool line = d < 1.5 && d > cos(0.5 * RF_PI / 180.0); /* a dot may round past 1 */
        straight |= line;
        long_straight += line && elbow;
        bent |= d < cos(2.0 * RF_PI / 180.0) && elbow;
    }
    /* a straight elbow explains one straight joint between long bones, not two */
    bent |= long_straight >= 2;
    /* an arm held straight throughout (motion capture's T-pose) has no cut */
    return straight && bent;
}

/* What the cost of every pair of entries reads of a whole line, once the line is final: the DP
 * compares every entry of one line with every entry of the other, and walking the lines again for
 * each pair made long chains (thousands of joints in one line) take minutes. */
static void line_summary(const rf_analysis *a, rf_ms_line *l)
{
    l->skull = -1;
    l->cut_end = false;
    l->last = last_step(l);
    l->cut = has_cut(a, l);
    l->first = -1;
    for (uint32_t f = 0; f < l->n && l->first < 0; f++) {
        const rf_joint_info *r = &a->joints[l->joint[f]];
        if (l->step[f] >= 0 && r->length > 0 && !(r->flags & RF_JI_ZERO_LENGTH))
            l->first = (int32_t)f;
    }
}

/* What leaving each bone of a limb out costs: the second half of a bone cut in two is often on
 * one side only, so leaving it out is cheap. */
static void skip_prices(const rf_analysis *a, const rf_ms_line *l, double *out)
{
    const rf_section *sec = l->n ? &a->sections[a->joints[l->joint[0]].section] : NULL;
    bool limb = sec && (sec->type == RF_SECTION_ARM || sec->type == RF_SECTION_LEG) &&
                !(sec->flags & RF_SECFL_FAN);
    bool cut = limb && l->cut;
    for (uint32_t i = 0; i < l->n; i++) {
        out[i] = RF_MS_SKIP_COST;
        if (cut && i > 0 && turn_cos(a, l, i) < 1.5 && turn_cos(a, l, i) > cos(0.5 * RF_PI / 180.0))
            out[i] = 0.1;
    }
}

static double step_weight(bool digit, const rf_ms_line *tl, const rf_ms_line *sl)
{
    if (digit || tl->n == 1 || sl->n == 1)
        return 0.6;
    if (tl->last == sl->last)
        return 0.3;
    bool cut = tl->last > sl->last ? tl->cut : sl->cut;
    return cut ? 0.1 : 0.3;
}

/* The angle of entry i's bone from the line's first real bone (0 when either has none): how far
 * the limb has turned by then, whatever pose the limb is held in. */
static double turned(const rf_analysis *a, const rf_ms_line *l, uint32_t i)
{
    const rf_joint_info *j = &a->joints[l->joint[i]];
    if (l->first < 0 || j->length <= 0)
        return 0;
    return rf_v3_angle(a->joints[l->joint[l->first]].dir, j->dir);
}

/* Where a cut limb's bone counts say little, which way a bone points still tells a shin from a
 * foot: 0 (alike) to 1 (45 degrees apart or more), in the bodies' frames; between limbs of two
 * kinds (an arm held out against a foreleg standing under the body, pointing elsewhere
 * throughout yet turning alike along its length) the less of that and of how far each has
 * turned from its limb's first bone. */
static double turn_apart(const rf_ms_ctx *c, const rf_ms_line *tl, uint32_t i, uint32_t k,
                         const rf_ms_line *sl, uint32_t q)
{
    uint32_t t = tl->joint[i], j = sl->joint[q];
    rf_vec3 a, b;
    if (!rf_ms_body_dirs(c, t, k, j, &a, &b))
        return 0;
    double d = rf_v3_angle(a, b);
    if (c->tgt.a->sections[c->tgt.a->joints[t].section].type !=
        c->src[k].a->sections[c->src[k].a->joints[j].section].type)
        d = fmin(d, fabs(turned(c->tgt.a, tl, i) - turned(c->src[k].a, sl, q)));
    return fmin(1, d / (0.25 * RF_PI));
}

/* Where the target's head chain has its skull when its last bone is not it: a curve skeleton's
 * head chain runs on past the skull to the snout's or the hat's tip, where an artist's skull bone
 * spans the whole head from where the neck enters it. Where the source's skull (its last bone) is
 * longer than the rest of its head chain (a skull, not a neck's last link) and more than one and
 * a half times the target's last bone (as shares of the bodies' heights), the target entry whose
 * pivot lies that share back from the chain's tip, nearer the source skull's place along its
 * chain than the target's last pivot, stands for the skull; the bones beyond it (a snout) follow
 * it unmapped. A target's last bone whose tip is guessed (a leaf without an end site) has no
 * length to tell a snout from a short head, so it keeps its place. Only the target's: a source
 * skull left unmapped would leave the target's head without its motion. */
static void skull_at(const rf_ms_ctx *c, rf_ms_line *tl, uint32_t k, const rf_ms_line *sl)
{
    const rf_analysis *at = c->tgt.a, *as = c->src[k].a;
    if (tl->n < 3 || sl->n < 2 || at->height <= 0 || as->height <= 0 ||
        at->sections[at->joints[tl->joint[0]].section].type != RF_SECTION_HEAD)
        return;
    double skull = as->joints[sl->joint[sl->n - 1]].length / as->height, neck = 0;
    for (uint32_t q = 0; q + 1 < sl->n; q++)
        neck += as->joints[sl->joint[q]].length / as->height;
    double from_tip = at->joints[tl->joint[tl->n - 1]].length / at->height;
    if (!(skull > 1.5 * from_tip) || !(skull > neck) ||
        (at->joints[tl->joint[tl->n - 1]].flags & RF_JI_TIP_GUESSED))
        return;
    uint32_t near = tl->n - 1;
    double best = fabs(from_tip - skull);
    for (uint32_t i = tl->n - 1; i-- > 1;) {
        from_tip += at->joints[tl->joint[i]].length / at->height;
        if (fabs(from_tip - skull) < best)
            best = fabs(from_tip - skull), near = i;
    }
    /* and by places along the chains: the source's skull starts nearer that pivot than the
     * target's last */
    double start = sl->u0[sl->n - 1];
    if (near + 1 < tl->n && fabs(tl->u0[near] - start) < fabs(tl->u0[tl->n - 1] - start))
        tl->skull = (int32_t)near;
}

/* The end marks of entry i (see rf_ms_skel.ends), with the skull where skull_at put it: the
 * skull's entry is the head's end (1) and the one before it the neck's (4); entries past it
 * carry no end mark. */
static uint8_t end_marks(const rf_ms_skel *s, const rf_ms_line *l, uint32_t i)
{
    uint8_t e = s->ends[l->joint[i]];
    if (l->cut_end && i + 1 == l->n)
        e |= 1;
    if (l->skull < 0)
        return e;
    e &= 2;
    if ((int32_t)i == l->skull)
        e |= 1;
    else if ((int32_t)i + 1 == l->skull)
        e |= 4;
    return e;
}

/* Whether a target limb of several joints meets a source limb of one: a one-bone leg (a low-poly
 * rig's one joint at the hip) is the whole leg, so it drives the first joint of the target's
 * longer chain, a short offset bone at the hip or shoulder included, and the joints after it
 * follow as its children. Its entries are then counted from the chain's first joint, not from its
 * first real bone, and an offset meets the one bone unmarked: by steps and marks the one bone
 * drove the first real bone, leaving the offset's skin to the body. Only this way round: a
 * target limb of one joint takes the source's first real bone, the one that swings the leg (an
 * offset barely moves). */
static bool one_bone_limb(const rf_analysis *at, const rf_ms_line *tl, const rf_ms_line *sl)
{
    return sl->n == 1 && tl->n > 1 && is_limb(at, at->joints[tl->joint[0]].section);
}

/* Whether a target limb starts with a real bone where its mirror limb does too: no offset bone
 * at either socket (a curve skeleton's branch that met the trunk wherever its thinning joined
 * it, not at a socket the rigger cut). Mirror limbs are read alike. */
static bool starts_unsocketed(const rf_analysis *a, const rf_ms_line *l)
{
    if (l->first != 0)
        return false;
    int32_t m = a->joints[l->joint[0]].mirror;
    if (m < 0 || a->joints[m].section < 0)
        return false;
    const uint32_t *mj = rf_section_joints(a, (uint32_t)a->joints[m].section);
    return mj[0] == (uint32_t)m && !(a->joints[m].flags & RF_JI_OFFSET) && a->joints[m].length > 0;
}

/* The source limb entry whose pivot lies nearest target joint t's in the bodies' frames (the
 * limb's own bones, past any offset), and how far off it and the entry of step `want` lie
 * (infinite when there is none). */
static int32_t nearest_pivot(const rf_ms_ctx *c, uint32_t t, uint32_t k, const rf_ms_line *sl,
                             int32_t want, double *best, double *wanted)
{
    const rf_analysis *at = c->tgt.a, *as = c->src[k].a;
    rf_vec3 p = c->tgt.bplace[t];
    rf_side st = at->joints[t].side;
    int32_t near = -1;
    *best = *wanted = INFINITY;
    for (uint32_t q = (uint32_t)sl->first; q < sl->n; q++) {
        uint32_t j = sl->joint[q];
        if (as->sections[as->joints[j].section].flags & RF_SECFL_FAN)
            break; /* a lent digit: the limb's own bones only */
        rf_vec3 b = c->src[k].bplace[j];
        rf_side ss = as->joints[j].side;
        if (st != RF_SIDE_CENTER && ss != RF_SIDE_CENTER && st != ss)
            b.x = -b.x;
        double d = rf_v3_len(rf_v3_sub(p, b));
        if (sl->step[q] == want && d < *wanted)
            *wanted = d;
        if (d < *best)
            *best = d, near = (int32_t)q;
    }
    return near;
}

/* Where two rigs of one body are paired joint for joint (girdle=neck, the skin's
 * correspondence), a target limb that lacks the source limb's first bones counts its bones from
 * the source bone its pivots say, and is placed from that bone's place on; by steps from their
 * first real bones every bone follows one or two off. Two readings, in the bodies' frames:
 * - a limb that starts without an offset, it and its mirror (a curve skeleton's branch that met
 *   the trunk wherever its thinning joined it), whose first pivot lies under half as far from a
 *   later source pivot as from the source's first real one: the ninja's and BCN_Epileptic's legs,
 *   from the knee, their thighs' skin left to the trunk's root;
 * - a limb whose last own pivot lies under half as far from a later source pivot than from the
 *   one its count gives, its first real pivot nearer the source pivot it then counts from too:
 *   the ninja's arms, lying against the body, from an offset at its side by the elbow.
 * Not a limb that starts with an offset at its socket and lines up at its end (the Fox's
 * forelegs, RobotExpressive's legs, from the elbow and the knee too by their pivots): the skin
 * of their first real bone covers the source's first bone as well, and counting from the first
 * real bones pairs the skin better (Fox 68% -> 63%, RobotExpressive 63% -> 52% counted from
 * their pivots). */
static void steps_from_body(const rf_ms_ctx *c, rf_ms_line *tl, uint32_t k, const rf_ms_line *sl)
{
    const rf_analysis *at = c->tgt.a, *as = c->src[k].a;
    if (!c->o->girdle_neck || c->o->thesis || sl->first < 0 || tl->first < 0 ||
        !is_limb(at, at->joints[tl->joint[0]].section) ||
        !is_limb(as, as->joints[sl->joint[0]].section))
        return;
    int32_t s0 = sl->step[sl->first], shift = 0;
    double best, wanted;
    if (starts_unsocketed(at, tl)) {
        int32_t q = nearest_pivot(c, tl->joint[0], k, sl, s0, &best, &wanted);
        if (q >= 0 && best < 0.5 * wanted)
            shift = sl->step[q] - s0 - tl->step[0];
    }
    /* the limb's end: its last own bone against the source's */
    uint32_t e = (uint32_t)tl->first;
    while (e + 1 < tl->n &&
           at->joints[tl->joint[e + 1]].section == at->joints[tl->joint[0]].section)
        e++;
    if (shift <= 0) {
        int32_t q = nearest_pivot(c, tl->joint[e], k, sl, s0 + tl->step[e], &best, &wanted);
        if (q >= 0 && best < 0.5 * wanted)
            shift = sl->step[q] - s0 - tl->step[e];
        /* and its first real bone's pivot lies nearer the source pivot it then counts from */
        double moved, stays;
        uint32_t f = tl->joint[tl->first];
        nearest_pivot(c, f, k, sl, s0 + tl->step[tl->first] + shift, &best, &moved);
        nearest_pivot(c, f, k, sl, s0 + tl->step[tl->first], &best, &stays);
        if (shift > 0 && !(moved < stays))
            shift = 0;
    }
    if (shift <= 0)
        return;
    /* its places run from the place of the source pivot its first real bone now counts from to
     * the limb's end, as the source's do */
    double at_u = NAN;
    for (uint32_t q = (uint32_t)sl->first; q < sl->n && isnan(at_u); q++)
        if (sl->step[q] == s0 + shift)
            at_u = sl->u0[q];
    double base = tl->u0[tl->first], span = 1 - base > 1e-9 ? 1 - base : 1;
    for (uint32_t i = 0; i < tl->n; i++) {
        if (tl->step[i] >= 0)
            tl->step[i] += shift;
        if (isnan(at_u))
            continue;
        tl->u0[i] = at_u + (1 - at_u) * (tl->u0[i] - base) / span;
        tl->u1[i] = at_u + (1 - at_u) * (tl->u1[i] - base) / span;
    }
    tl->last = last_step(tl);
}

/* The DP's cost of entry i of the target line against entry q of the source line: the thesis
 * compares bone length ratios; here pivot and tip places along the sections, bone counts along
 * limbs and digits, and landmarks, which only fit landmarks. */
static double pair_cost(const rf_ms_ctx *c, const rf_ms_line *tl, uint32_t i, uint32_t k,
                        const rf_ms_line *sl, uint32_t q)
{
    const rf_analysis *at = c->tgt.a, *as = c->src[k].a;
    uint32_t t = tl->joint[i], j = sl->joint[q];
    const rf_joint_info *a = &at->joints[t], *b = &as->joints[j];
    if (c->o->thesis) {
        double lt = at->sections[a->section].length, ls = as->sections[b->section].length;
        return fabs((lt > 0 ? a->length / lt : 0) - (ls > 0 ? b->length / ls : 0));
    }
    /* in a digit the tip of the shorter line's last bone ends the whole finger, as the longer
     * line's last does: against a bone in the middle of the longer line it tells the count as
     * much as a place, and the steps below price the count (a one-bone finger against a finger
     * of two past the palm, whose last bone's length the skin tells, not a guess): half */
    bool chain_end = (at->sections[a->section].flags & RF_SECFL_FAN) &&
                     ((q + 1 == sl->n && sl->n < tl->n) || (i + 1 == tl->n && tl->n < sl->n));
    double cost = fabs(tl->u0[i] - sl->u0[q]) +
                  (chain_end ? 0.25 : 0.5) * fabs(fmin(tl->u1[i], 1.5) - fmin(sl->u1[q], 1.5));
    /* a tail of one bone has no place along a tail to compare: its root anchors it (below);
     * nor has a head of one joint (an artist's skull joint at the base of the skull, a curve
     * skeleton's near its top or after a long neck from the body's middle: the one skull) */
    rf_section_type st = at->sections[a->section].type;
    if ((st == RF_SECTION_TAIL || st == RF_SECTION_HEAD) && (tl->n == 1 || sl->n == 1))
        cost *= 0.25;
    /* nor has a digit of one bone (whose length a leaf without an end site only guesses) */
    if ((at->sections[a->section].flags & RF_SECFL_FAN) && tl->n == 1)
        cost *= 0.25;
    /* the spine's ends (pelvis, chest), a limb's offset bone (clavicle, hip offset), the skull at
     * the end of the neck */
    bool whole = one_bone_limb(at, tl, sl);
    uint32_t marks = whole ? 0 : (a->flags ^ b->flags) & RF_JI_OFFSET;
    rf_section_type type = at->sections[a->section].type;
    /* a chain of one joint is anchored at its start: a one-bone tail is the tail's root */
    uint8_t et = tl->n == 1 ? 2 : end_marks(&c->tgt, tl, i),
            es = sl->n == 1 ? 2 : end_marks(&c->src[k], sl, q);
    uint8_t ends = et ^ es;
    if (type == RF_SECTION_SPINE && !(at->sections[a->section].flags & RF_SECFL_REVERSE))
        marks |= (uint32_t)ends << 8;
    if (type == RF_SECTION_HEAD) /* the skull, and the neck's ends on either side */
        marks |= (uint32_t)(ends & 7) << 8;
    if (type == RF_SECTION_TAIL) /* tails of any length: root to root, tip to tip */
        marks |= (uint32_t)ends << 8;
    for (; marks; marks &= marks - 1) /* twice for a chain of one joint: only its anchor */
        cost += tl->n == 1 || sl->n == 1 ? 0.5 : 0.25;
    /* a neck's last joint before the skull is held harder: necks differ most in how their
     * length splits (a human's two neck joints against a horse's seven), so its place says less
     * than in a spine, and the end joint carries the head's turn; a neck of one joint is both
     * ends and follows its place */
    if (type == RF_SECTION_HEAD && (ends & 4) && (et & 6) != 6 && (es & 6) != 6)
        cost += 0.5;
    /* limbs and digits: bones counted from the first real one (thigh, shin, foot whatever their
     * proportions, plantigrade or not); digits, whose segments vary most in length, and limbs of
     * one bone count twice: their first joints (at the knuckle or the wrist alike; a one-bone
     * leg and a thigh) anchor them. Steps beyond the first cost a quarter: a segment cut in two
     * for twist (a thigh and its second half) shifts the count of every bone after it, not
     * their places. */
    bool digit = (at->sections[a->section].flags & RF_SECFL_FAN) != 0;
    if (type != RF_SECTION_SPINE && type != RF_SECTION_HEAD && type != RF_SECTION_TAIL &&
        type != RF_SECTION_ROOT) {
        int32_t ts = whole ? (int32_t)i + sl->step[q] : tl->step[i];
        cost += step_weight(digit, tl, sl) *
                (ts == sl->step[q] ? 0 : 1 + 0.25 * (abs(ts - sl->step[q]) - 1));
    }
    return cost;
}

static int vote_order(const void *x, const void *y)
{
    const rf_ms_vote *a = x, *b = y;
    if (a->key != b->key)
        return a->key < b->key ? -1 : 1;
    return a->i < b->i ? -1 : a->i > b->i;
}

/* Thesis 4.2.2: the input section of the first mapped bone is used for the whole target section
 * when more than half of its mapped bones come from it. Beyond the thesis, the section most of
 * them chose is used (ties: the first bone's), so a two-bone thumb split one and one still
 * follows its first bone. Votes are counted by sorting, not bone against bone: a hostile chain
 * of many thousand joints must not take minutes. Returns false when none qualifies. */
static bool input_section(const rf_ms_ctx *c, const rf_ms_pass *p, const rf_ms_line *tl,
                          uint32_t *k, uint32_t *ss)
{
    uint32_t mapped = 0;
    for (uint32_t i = 0; i < tl->n; i++) {
        const rf_ms_candidate *b = &p->best[tl->joint[i]];
        if (b->source == RF_MS_NO_SOURCE)
            continue;
        uint32_t sec = (uint32_t)c->src[b->source].a->joints[b->joint].section;
        tl->vote[mapped++] = (rf_ms_vote){(uint64_t)b->source << 32 | sec, i};
    }
    if (mapped == 0)
        return false;
    uint32_t first = tl->vote[0].i, most = 0, pick = first;
    qsort(tl->vote, mapped, sizeof *tl->vote, vote_order);
    for (uint32_t g = 0, e; g < mapped; g = e) {
        for (e = g + 1; e < mapped && tl->vote[e].key == tl->vote[g].key;)
            e++;
        uint32_t votes = e - g, at = tl->vote[g].i; /* the group's first entry */
        bool counts = !c->o->thesis || at == first;
        if (counts && (votes > most || (votes == most && at < pick)))
            most = votes, pick = at;
    }
    if (c->o->thesis && 2 * most <= mapped)
        return false;
    const rf_ms_candidate *f = &p->best[tl->joint[pick]];
    *k = f->source;
    *ss = (uint32_t)c->src[f->source].a->joints[f->joint].section;
    return true;
}

/* Each target joint's best joint within the chosen source section (duplicates kept). */
static void best_within(const rf_ms_ctx *c, rf_ms_pass *p, const rf_ms_line *tl, uint32_t k,
                        const rf_ms_line *sl)
{
    for (uint32_t i = 0; i < tl->n; i++) {
        double best = -INFINITY;
        p->final[tl->joint[i]] = no_candidate;
        for (uint32_t q = 0; q < sl->n; q++) {
            double jm[RF_MS_METRIC_COUNT] = {0};
            rf_ms_joint_metrics(c, tl->joint[i], k, sl->joint[q], jm);
            double score = jm[RF_MS_ORIENTATION] + jm[RF_MS_SEQUENCE];
            if (score > best)
                best = score, p->final[tl->joint[i]] = (rf_ms_candidate){k, sl->joint[q], 0, {0}};
        }
    }
}

/* Where two limbs' bone counts say little (one has a bone cut in two), a target bone pays for
 * pointing elsewhere than the source bone, beyond what it pays against the source bone it points
 * most alike (a rig whose bones all point elsewhere, or a limb held in another pose, pays
 * nothing): up to 0.3. */
static void add_turns(const rf_ms_ctx *c, const rf_ms_line *tl, uint32_t k, const rf_ms_line *sl,
                      double *cost)
{
    if (c->o->thesis || tl->n == 0 || !is_limb(c->tgt.a, c->tgt.a->joints[tl->joint[0]].section) ||
        step_weight(false, tl, sl) >= 0.3)
        return;
    for (uint32_t i = 0; i < tl->n; i++) {
        double least = 1;
        for (uint32_t q = 0; q < sl->n; q++)
            least = fmin(least, turn_apart(c, tl, i, k, sl, q));
        for (uint32_t q = 0; q < sl->n; q++)
            cost[(size_t)i * sl->n + q] += 0.3 * (turn_apart(c, tl, i, k, sl, q) - least);
    }
}

/* Assigns along the two lines. The thesis matches every bone of the shorter section; here
 * either side may also leave a bone out at a price, so a hip offset on one side and a toe on the
 * other do not shift the whole leg. */
static bool remove_duplicates(const rf_ms_ctx *c, rf_ms_pass *p, const rf_ms_line *tl, uint32_t k,
                              const rf_ms_line *sl)
{
    uint32_t n = tl->n, m = sl->n;
    double *cost = malloc((size_t)(n ? n : 1) * (m ? m : 1) * sizeof *cost);
    double *skip = malloc((size_t)(n + m ? n + m : 1) * sizeof *skip);
    int32_t *match = malloc((size_t)(n ? n : 1) * sizeof *match);
    bool ok = cost && match && skip;
    if (ok) {
        for (uint32_t i = 0; i < n; i++)
            for (uint32_t q = 0; q < m; q++)
                cost[(size_t)i * m + q] =
                    pair_cost(c, tl, i, k, sl, q) + 1e-6 * fabs((double)i / n - (double)q / m);
        add_turns(c, tl, k, sl, cost);
        skip_prices(c->tgt.a, tl, skip);
        skip_prices(c->src[k].a, sl, skip + n);
        ok = (c->o->thesis
                  ? rf_ms_assign(cost, n, m, match)
                  : rf_ms_align_priced(cost, n, m, RF_MS_SKIP_COST, skip, skip + n, match)) >= 0;
    }
    free(skip);
    for (uint32_t i = 0; ok && i < n; i++)
        p->final[tl->joint[i]] =
            match[i] >= 0 ? (rf_ms_candidate){k, sl->joint[match[i]], 0, {0}} : no_candidate;
    free(cost);
    free(match);
    return ok;
}

/* Whether the limb ends in toes: a fan whose main digit starts at the ground and lies along it
 * (fingers of a hand hanging low are no toes). */
static bool toes(const rf_ms_skel *s, uint32_t limb)
{
    const rf_analysis *a = s->a;
    int32_t md = s->main_digit[rf_section_joints(a, limb)[a->sections[limb].bone_count - 1]];
    if (md < 0)
        return false;
    const rf_joint_info *toe = &a->joints[rf_section_joints(a, (uint32_t)md)[0]];
    return rf_v3_dot(toe->pos, a->up) - a->ground <= 0.1 * a->height &&
           fabs(rf_v3_dot(toe->dir, a->up)) <= 0.5;
}

/* A limb ending in a fan of digits against one ending in a single chain: the hand of one is
 * bones of the other's arm. The fan side lends its main digit to the assignment, and a target
 * digit settled that way is not settled again with its own section. */
static bool lend_digits(const rf_ms_ctx *c, rf_ms_pass *p, uint32_t ts, rf_ms_line *tl, uint32_t k,
                        uint32_t ss, rf_ms_line *sl)
{
    if (c->o->thesis || !is_limb(c->tgt.a, ts) || !is_limb(c->src[k].a, ss))
        return false;
    const rf_analysis *at = c->tgt.a, *as = c->src[k].a;
    uint32_t tl_last = rf_section_joints(at, ts)[at->sections[ts].bone_count - 1];
    uint32_t sl_last = rf_section_joints(as, ss)[as->sections[ss].bone_count - 1];
    bool tfan = c->tgt.main_digit[tl_last] >= 0, sfan = c->src[k].main_digit[sl_last] >= 0;
    if (tfan && !sfan) {
        /* a foot's toes against a single toe bone count as that bone's kind (2) */
        bool foot = toes(&c->tgt, ts);
        uint32_t before = tl->n;
        line_digit(&c->tgt, ts, tl);
        for (uint32_t i = before; i < tl->n; i++)
            p->settled[tl->joint[i]] = foot ? 2 : 1;
        return foot;
    } else if (sfan && !tfan) {
        line_digit(&c->src[k], ss, sl);
    }
    return false;
}

/* The other digits of a fan whose main digit its limb settled (a bird's toes against a human's
 * single toe bone): parallel digits take what the main digit took, joint by joint, as the thesis
 * suggests for digits a source lacks (its 5.3.1); a thumb, or a toe turned 45 degrees or more
 * away from the main one (a hallux), is no parallel digit and stays unmapped. */
static void share_lent(const rf_ms_ctx *c, rf_ms_pass *p, uint32_t ts)
{
    const rf_analysis *a = c->tgt.a;
    uint32_t last = rf_section_joints(a, ts)[a->sections[ts].bone_count - 1];
    int32_t md = c->tgt.main_digit[last];
    if (md < 0)
        return;
    const uint32_t *mj = rf_section_joints(a, (uint32_t)md);
    uint32_t mn = a->sections[md].bone_count;
    for (uint32_t d = 0; d < a->section_count; d++) {
        const rf_section *sec = &a->sections[d];
        if (d == (uint32_t)md || sec->attach_joint != (int32_t)last ||
            !(sec->flags & RF_SECFL_FAN) || (sec->flags & RF_SECFL_THUMB))
            continue;
        const uint32_t *js = rf_section_joints(a, d);
        /* only parallel digits: a toe turned away (a hallux pointing back) is no copy */
        bool parallel = rf_v3_dot(a->joints[js[0]].dir, a->joints[mj[0]].dir) >= 0.7;
        for (uint32_t i = 0; i < sec->bone_count; i++) {
            p->final[js[i]] = i < mn && parallel ? p->final[mj[i]] : no_candidate;
            p->settled[js[i]] = 2;
        }
    }
}

static bool settle_sections(const rf_ms_ctx *c, rf_ms_pass *p, rf_ms_line *tl, rf_ms_line *sl)
{
    const rf_analysis *a = c->tgt.a;
    for (uint32_t ts = 0; ts < a->section_count; ts++) {
        uint32_t k, ss;
        line_section(&c->tgt, ts, tl);
        if (tl->n && p->settled[tl->joint[0]])
            continue; /* a digit its limb has settled */
        for (uint32_t i = 0; i < tl->n; i++)
            p->final[tl->joint[i]] = p->best[tl->joint[i]];
        if (tl->n == 0 || !input_section(c, p, tl, &k, &ss))
            continue;
        line_section(&c->src[k], ss, sl);
        if (!c->o->thesis)
            own_places(tl, sl);
        bool lent = lend_digits(c, p, ts, tl, k, ss, sl);
        line_summary(a, tl), line_summary(c->src[k].a, sl);
        if (!c->o->thesis)
            skull_at(c, tl, k, sl);
        steps_from_body(c, tl, k, sl);
        if (c->o->keep_duplicates)
            best_within(c, p, tl, k, sl);
        else if (!remove_duplicates(c, p, tl, k, sl))
            return false;
        if (lent)
            share_lent(c, p, ts);
    }
    return true;
}

/* The trunk from girdle joint g toward h, the head chain's first joint: where it starts (g's
 * pivot; where g is a control joint sitting on h, the first ancestor's off it), its direction and
 * length, and how far along it g's limbs leave (their first real bone's pivot, past an offset;
 * the farthest of g's limbs: the front pair where one joint carries all four). Not g's own bone:
 * a rig's bone axis may point it at an arm. */
typedef struct rf_ms_trunk {
    rf_vec3 from, dir;
    double len, limbs;
} rf_ms_trunk;

static bool trunk_at(const rf_analysis *a, uint32_t g, uint32_t h, rf_ms_trunk *t)
{
    int32_t f = (int32_t)g;
    while (f >= 0 && rf_v3_dist(a->joints[f].pos, a->joints[h].pos) <= 1e-6 * a->height)
        f = a->joints[f].logical_parent;
    if (f < 0 || !(a->height > 0))
        return false;
    t->from = a->joints[f].pos;
    t->len = rf_v3_dist(a->joints[h].pos, t->from);
    t->dir = rf_v3_scale(rf_v3_sub(a->joints[h].pos, t->from), 1 / t->len);
    t->limbs = NAN;
    for (uint32_t s = 0; s < a->section_count; s++) {
        if (a->sections[s].attach_joint != (int32_t)g || !is_limb(a, s))
            continue;
        const uint32_t *js = rf_section_joints(a, s);
        uint32_t i = 0;
        while (i + 1 < a->sections[s].bone_count && (a->joints[js[i]].flags & RF_JI_OFFSET))
            i++;
        double at = rf_v3_dot(rf_v3_sub(a->joints[js[i]].pos, t->from), t->dir);
        if (!(at <= t->limbs))
            t->limbs = at;
    }
    return isfinite(t->limbs);
}

/* Where point p lies along the trunk, in body heights from where the limbs leave. */
static double trunk_place(const rf_analysis *a, const rf_ms_trunk *t, rf_vec3 p)
{
    return (rf_v3_dot(rf_v3_sub(p, t->from), t->dir) - t->limbs) / a->height;
}

/* Drops a line's first entry, the rest placed along what is left of the line. */
static void line_drop_first(rf_ms_line *l)
{
    double base = l->u0[1], span = 1 - base > 1e-9 ? 1 - base : 1;
    for (uint32_t i = 0; i + 1 < l->n; i++) {
        l->joint[i] = l->joint[i + 1], l->step[i] = l->step[i + 1];
        l->u0[i] = (l->u0[i + 1] - base) / span, l->u1[i] = (l->u1[i + 1] - base) / span;
    }
    l->n--;
}

/* Places a spine line so that 1 is where the limbs leave, `limbs` past the pivot of its last
 * entry (the girdle joint) along the trunk: a line's places run to its girdle joint's pivot,
 * and an artist's chest joint pivots well below the shoulders (the Wizard's Torso, at the base
 * of the ribs), a curve skeleton's girdle joint where the arms leave. */
static void line_to_limbs(const rf_analysis *a, rf_ms_line *l, double limbs)
{
    const rf_joint_info *g = &a->joints[l->joint[l->n - 1]];
    double per = g->length > 0 ? (l->u1[l->n - 1] - l->u0[l->n - 1]) / g->length : 0;
    double end = l->u0[l->n - 1] + fmax(0, limbs) * per;
    for (uint32_t i = 0; end > 1e-9 && i < l->n; i++)
        l->u0[i] /= end, l->u1[i] /= end;
}

/* After the girdle rule gave the target's girdle joint the source's neck, the rest of the
 * target's spine is aligned again with the whole of the source's, both placed from where their
 * limbs leave: the joint before the girdle now ends the target's trunk, and takes the source's
 * chest where the girdle joint had held it (the Wizard's curve skeleton: its spine's middle
 * joints took the artist's Hips and Abdomen, lying below them, and the chest, Torso, drove no
 * joint). */
static bool spine_before_girdle(const rf_ms_ctx *c, rf_ms_pass *p, uint32_t g, uint32_t k,
                                uint32_t gk, const rf_ms_trunk *tt, const rf_ms_trunk *ts,
                                rf_ms_line *tl, rf_ms_line *sl)
{
    const rf_analysis *at = c->tgt.a, *as = c->src[k].a;
    line_section(&c->tgt, (uint32_t)at->joints[g].section, tl);
    line_section(&c->src[k], (uint32_t)as->joints[gk].section, sl);
    if (tl->n < 2 || tl->joint[tl->n - 1] != g || sl->n < 1 || sl->joint[sl->n - 1] != gk)
        return true;
    line_to_limbs(at, tl, tt->limbs), line_to_limbs(as, sl, ts->limbs);
    tl->n--;
    line_summary(at, tl), line_summary(as, sl);
    tl->cut_end = true;
    return remove_duplicates(c, p, tl, k, sl);
}

/* After the head chain's alignment under girdle=neck: its bones whose middle lies past the
 * source's skull pivot (measured as for the girdle joint) are the skull's, the first of them
 * taking it (unless an earlier joint has it) and the rest following. The alignment goes by places
 * along each head chain, and an artist's skull joint may sit far back at the head's base
 * (Testwuson's, after two neck joints), where the curve skeleton's head chain starts further on. */
static void skull_past(const rf_ms_ctx *c, rf_ms_pass *p, const rf_ms_line *tl, uint32_t k,
                       const rf_ms_line *sl, const rf_ms_trunk *tt, const rf_ms_trunk *ts)
{
    const rf_analysis *at = c->tgt.a, *as = c->src[k].a;
    uint32_t skull = sl->joint[sl->n - 1];
    double sp = trunk_place(as, ts, as->joints[skull].pos);
    bool taken = false;
    for (uint32_t i = 0; i < tl->n; i++) {
        const rf_joint_info *ji = &at->joints[tl->joint[i]];
        rf_vec3 end = i + 1 < tl->n ? at->joints[tl->joint[i + 1]].pos : ji->tip;
        double m = 0.5 * (trunk_place(at, tt, ji->pos) + trunk_place(at, tt, end));
        rf_ms_candidate *f = &p->final[tl->joint[i]];
        if (m > sp)
            *f = taken ? no_candidate : (rf_ms_candidate){k, skull, 0, {0}};
        taken = taken || (f->source == k && f->joint == skull);
    }
}

/* After the girdle joint took the source's neck (girdle=neck): where the middle of its bone lies
 * past the source's skull pivot, both placed in the bodies' frames from the target's girdle
 * pivot along its bone, it takes the skull. The Wizard's curve skeleton carries its arms near
 * its chin, so its girdle joint sits at the artist's skull pivot and its bone runs into the big
 * head (918 of its 5413 vertices); measured from where each rig's limbs leave (the rule
 * above), the rig's arms leaving higher than the artist's, that bone lies in the artist's neck. */
static void girdle_past_skull(const rf_ms_ctx *c, rf_ms_pass *p, uint32_t g, const rf_ms_line *tl,
                              uint32_t k, const rf_ms_line *sl)
{
    const rf_analysis *at = c->tgt.a, *as = c->src[k].a;
    if (tl->n < 1 || sl->n < 1 || p->final[g].source != k)
        return;
    uint32_t skull = sl->joint[sl->n - 1];
    rf_vec3 g0 = rf_ms_body_place(&c->tgt, at->joints[g].pos),
            h0 = rf_ms_body_place(&c->tgt, at->joints[tl->joint[0]].pos);
    rf_vec3 dir = rf_v3_sub(h0, g0);
    double len = rf_v3_len(dir);
    if (!(len > 0))
        return;
    dir = rf_v3_scale(dir, 1 / len);
    double sp = rf_v3_dot(rf_v3_sub(rf_ms_body_place(&c->src[k], as->joints[skull].pos), g0), dir);
    if (0.5 * len > sp)
        p->final[g] = (rf_ms_candidate){k, skull, 0, {0}};
}

/* The neck at the girdle (girdle=neck). Artists hang the forelimbs from a chest joint whose bone
 * ends where they leave (the animalia cat's Torso, a human's upper chest) and start the neck
 * there; a curve skeleton's girdle joint sits where the limbs leave and its bone runs on out of
 * the trunk into the neck: the section cut puts the neck's first bone at the end of the spine.
 * Where the target's spine ends at such a joint (its limbs leave in the first half of the
 * stretch to its head chain, and it is not the spine's first: a root's skin reaches behind it)
 * and the source's at a chest (its limbs in the second half), and the target's girdle bone lies
 * mostly past the source's neck pivot (both measured from where the limbs leave, in body
 * heights), the target's girdle joint takes the source's first neck joint and its head chain is
 * aligned with the rest of the source's head; a source head of one joint (pivoting where the
 * neck starts) is taken by both. Before, the cat's head joint took the artist's Neck and its
 * girdle joint the Torso: the neck's skin followed the chest and the head's the neck. Only on
 * the target's side. Not by default: the truths of tests/match drive the joint carrying the
 * limbs by the source's chest, as motion wants; rig-bench asks for it (the skin's
 * correspondence). */
static bool neck_at_girdle(const rf_ms_ctx *c, rf_ms_pass *p, rf_ms_line *tl, rf_ms_line *sl)
{
    const rf_analysis *at = c->tgt.a;
    for (uint32_t th = 0;
         th < at->section_count && c->o->girdle_neck && !c->o->thesis && !c->o->keep_duplicates;
         th++) {
        int32_t g = at->sections[th].attach_joint;
        if (at->sections[th].type != RF_SECTION_HEAD || g < 0 || !c->tgt.matchable[g])
            continue;
        const rf_section *gs = &at->sections[at->joints[g].section];
        if (gs->type != RF_SECTION_SPINE || (gs->flags & RF_SECFL_REVERSE) ||
            (c->tgt.ends[g] & 3) != 1)
            continue;
        line_section(&c->tgt, th, tl);
        const rf_ms_candidate *fh = tl->n ? &p->final[tl->joint[0]] : NULL;
        if (!fh || fh->source == RF_MS_NO_SOURCE)
            continue;
        uint32_t k = fh->source;
        const rf_analysis *as = c->src[k].a;
        int32_t hs = as->joints[fh->joint].section, gk = as->sections[hs].attach_joint;
        if (as->sections[hs].type != RF_SECTION_HEAD || gk < 0)
            continue;
        /* the girdle joint follows the source's spine (mapped to it, or left to its ancestors) */
        const rf_ms_candidate *fg = &p->final[g];
        if (fg->source != RF_MS_NO_SOURCE &&
            (fg->source != k || as->joints[fg->joint].section != as->joints[gk].section))
            continue;
        line_section(&c->src[k], (uint32_t)hs, sl);
        rf_ms_trunk tt, ts;
        if (sl->n < 1 || !trunk_at(at, (uint32_t)g, tl->joint[0], &tt) ||
            !trunk_at(as, (uint32_t)gk, sl->joint[0], &ts))
            continue;
        /* the target's limbs leave in the first half of the stretch to the head, the source's in
         * the second, and the target's girdle bone lies mostly past the source's neck pivot
         * (both from where the limbs leave, in body heights) */
        double mid = 0.5 * (trunk_place(at, &tt, at->joints[g].pos) +
                            trunk_place(at, &tt, at->joints[tl->joint[0]].pos));
        if (!(tt.limbs < 0.5 * tt.len) || !(ts.limbs >= 0.5 * ts.len) ||
            !(mid > trunk_place(as, &ts, as->joints[sl->joint[0]].pos)))
            continue;
        p->final[g] = (rf_ms_candidate){k, sl->joint[0], 0, {0}};
        p->settled[g] = 3;
        uint32_t h0 = sl->joint[0], n0 = sl->n;
        if (!spine_before_girdle(c, p, (uint32_t)g, k, (uint32_t)gk, &tt, &ts, tl, sl))
            return false;
        line_section(&c->tgt, th, tl);
        line_section(&c->src[k], (uint32_t)hs, sl);
        if (sl->n != n0 || sl->joint[0] != h0 || n0 < 2)
            continue;
        line_drop_first(sl);
        line_summary(at, tl), line_summary(as, sl);
        skull_at(c, tl, k, sl);
        if (!remove_duplicates(c, p, tl, k, sl))
            return false;
        skull_past(c, p, tl, k, sl, &tt, &ts);
        girdle_past_skull(c, p, (uint32_t)g, tl, k, sl);
    }
    return true;
}

/* The source head section hanging from the last joint of source section ss, or -1. */
static int32_t head_on(const rf_analysis *as, uint32_t ss)
{
    const uint32_t *js = rf_section_joints(as, ss);
    int32_t last = as->sections[ss].bone_count ? (int32_t)js[as->sections[ss].bone_count - 1] : -1;
    for (uint32_t h = 0; last >= 0 && h < as->section_count; h++)
        if (as->sections[h].type == RF_SECTION_HEAD && as->sections[h].attach_joint == last)
            return (int32_t)h;
    return -1;
}

/* A target without a head (girdle=neck): a curve skeleton of a body whose head is no protrusion
 * of its own (greenman's blob) ends its spine at the girdle joint, whose bone carries all the
 * skin above where the limbs leave. Where the source's head chain hangs from its spine's end and
 * its limbs leave in the second half of the stretch to it (its neck starts at the girdle, as the
 * rule above reads it), that skin is the source head's first joint's: the target's girdle joint
 * takes it. The target's girdle is its spine's last joint, not its first (a root's skin reaches
 * behind it), and its limbs leave at it: in the second half of the last bone's stretch, or past
 * it, not halfway up the trunk. */
static void head_at_girdle(const rf_ms_ctx *c, rf_ms_pass *p)
{
    const rf_analysis *at = c->tgt.a;
    if (!c->o->girdle_neck || c->o->thesis || c->o->keep_duplicates)
        return;
    for (uint32_t s = 0; s < at->section_count; s++)
        if (at->sections[s].type == RF_SECTION_HEAD)
            return;
    for (uint32_t ts = 0; ts < at->section_count; ts++) {
        const rf_section *sec = &at->sections[ts];
        if (sec->type != RF_SECTION_SPINE || (sec->flags & RF_SECFL_REVERSE) || sec->bone_count < 2)
            continue;
        const uint32_t *js = rf_section_joints(at, ts);
        uint32_t g = js[sec->bone_count - 1];
        int32_t before = at->joints[g].logical_parent;
        const rf_ms_candidate *fs = &p->final[js[0]];
        if (!c->tgt.matchable[g] || before < 0 || fs->source == RF_MS_NO_SOURCE)
            continue;
        uint32_t k = fs->source;
        const rf_analysis *as = c->src[k].a;
        int32_t ss = as->joints[fs->joint].section;
        int32_t hs =
            ss >= 0 && as->sections[ss].type == RF_SECTION_SPINE ? head_on(as, (uint32_t)ss) : -1;
        if (hs < 0)
            continue;
        uint32_t gk = (uint32_t)as->sections[hs].attach_joint,
                 h0 = rf_section_joints(as, (uint32_t)hs)[0];
        rf_ms_trunk tt, tsrc;
        if (!trunk_at(as, gk, h0, &tsrc))
            continue;
        /* the target's last spine bone, and where g's limbs leave along it */
        tt.from = at->joints[before].pos;
        tt.len = rf_v3_dist(at->joints[g].pos, tt.from);
        if (!(tt.len > 0))
            continue;
        tt.dir = rf_v3_scale(rf_v3_sub(at->joints[g].pos, tt.from), 1 / tt.len);
        tt.limbs = NAN;
        for (uint32_t l = 0; l < at->section_count; l++) {
            if (at->sections[l].attach_joint != (int32_t)g || !is_limb(at, l))
                continue;
            double place =
                rf_v3_dot(rf_v3_sub(at->joints[rf_section_joints(at, l)[0]].pos, tt.from), tt.dir);
            tt.limbs = isnan(tt.limbs) ? place : fmax(tt.limbs, place);
        }
        if (!(tt.limbs >= 0.5 * tt.len) || !(tsrc.limbs >= 0.5 * tsrc.len))
            continue;
        p->final[g] = (rf_ms_candidate){k, h0, 0, {0}};
        p->settled[g] = 4;
    }
}

/* Where target point p lies along a source section's axis (from its first pivot `from`, unit
 * `d`), both in their bodies' frames: two rigs of one body compare there as they lie. */
static double axis_place(const rf_ms_ctx *c, rf_vec3 p, rf_vec3 from, rf_vec3 d)
{
    return rf_v3_dot(rf_v3_sub(rf_ms_body_place(&c->tgt, p), from), d);
}

/* Source k's section s as an axis in its body's frame: from its first pivot toward its last
 * bone's tip (not from the joint it leaves: Testwuson's root lies in the belly, below the back). */
static bool section_axis(const rf_ms_ctx *c, uint32_t k, uint32_t s, rf_vec3 *from, rf_vec3 *d)
{
    const rf_analysis *as = c->src[k].a;
    const uint32_t *js = rf_section_joints(as, s);
    uint32_t n = as->sections[s].bone_count;
    if (!n)
        return false;
    *from = rf_ms_body_place(&c->src[k], as->joints[js[0]].pos);
    rf_vec3 end = rf_ms_body_place(&c->src[k], as->joints[js[n - 1]].tip);
    double len = rf_v3_len(rf_v3_sub(end, *from));
    if (!(len > 0))
        return false;
    *d = rf_v3_scale(rf_v3_sub(end, *from), 1 / len);
    return true;
}

/* The matchable joint of source k's section s whose bone holds place m along its axis (the
 * first where m lies before it), or RF_MS_NO_SOURCE. */
static uint32_t joint_along(const rf_ms_ctx *c, uint32_t k, uint32_t s, rf_vec3 from, rf_vec3 d,
                            double m)
{
    const rf_analysis *as = c->src[k].a;
    const uint32_t *js = rf_section_joints(as, s);
    uint32_t got = RF_MS_NO_SOURCE;
    for (uint32_t i = 0; i < as->sections[s].bone_count; i++) {
        if (!c->src[k].matchable[js[i]])
            continue;
        rf_vec3 q = rf_ms_body_place(&c->src[k], as->joints[js[i]].pos);
        if (got != RF_MS_NO_SOURCE && rf_v3_dot(rf_v3_sub(q, from), d) > m)
            break;
        got = js[i];
    }
    return got;
}

/* The first spine section of a that runs from the root toward the rear girdle, or -1. */
static int32_t reverse_spine(const rf_analysis *a)
{
    for (uint32_t s = 0; s < a->section_count; s++)
        if (a->sections[s].type == RF_SECTION_SPINE && (a->sections[s].flags & RF_SECFL_REVERSE) &&
            a->sections[s].bone_count)
            return (int32_t)s;
    return -1;
}

/* Target joint t takes source k's joint j, set apart from the alignment as `how` says. */
static void take_along(rf_ms_pass *p, uint32_t t, uint32_t k, uint32_t j, uint8_t how)
{
    if (j == RF_MS_NO_SOURCE)
        return;
    p->final[t] = (rf_ms_candidate){k, j, 0, {0}};
    p->settled[t] = how;
}

/* A trunk rooted at the rear (girdle=neck). The general rigger roots its spine at the hips and
 * runs it forward; an artist may root the back in its middle and run a reverse spine from there
 * to the pelvis, which the section alignment cannot reach from the target's one forward spine:
 * the target's rear joints took the forward spine's first joints (Testwuson's hips, 842 of its
 * 11196 vertices, the artist's tail; BCN_Epileptic's pelvis, 1122 of 15378, the unweighted
 * root's nearest). Each leading target spine joint lying behind the reverse spine's first pivot,
 * placed along it in the bodies' frames, takes the reverse joint whose bone holds that place:
 * the spine's first joint by its pivot (at the trunk's rear end, its skin lies about it: the
 * hips), the others by their bone's middle; the joints after them, to the girdle joint, take
 * the forward spine's joint whose bone holds their bone's middle. */
static void trunk_from_rear(const rf_ms_ctx *c, rf_ms_pass *p)
{
    const rf_analysis *at = c->tgt.a;
    if (reverse_spine(at) >= 0)
        return; /* the target has a rear spine of its own: the alignment paired them */
    for (uint32_t ts = 0; ts < at->section_count; ts++) {
        const rf_section *sec = &at->sections[ts];
        if (sec->type != RF_SECTION_SPINE || sec->bone_count < 2)
            continue;
        const uint32_t *js = rf_section_joints(at, ts);
        const rf_ms_candidate *f0 = &p->final[js[0]];
        if (f0->source == RF_MS_NO_SOURCE)
            continue;
        uint32_t k = f0->source;
        const rf_analysis *as = c->src[k].a;
        int32_t s0 = as->joints[f0->joint].section, sr = reverse_spine(as);
        rf_vec3 from, d;
        if (sr < 0 || s0 < 0 || (as->sections[s0].flags & RF_SECFL_REVERSE) ||
            !section_axis(c, k, (uint32_t)sr, &from, &d))
            continue;
        uint32_t i = 0;
        for (; i + 1 < sec->bone_count; i++) {
            double m = axis_place(c, at->joints[js[i]].pos, from, d);
            if (i > 0)
                m = 0.5 * (m + axis_place(c, at->joints[js[i + 1]].pos, from, d));
            if (!(m > 0))
                break;
            if (c->tgt.matchable[js[i]])
                take_along(p, js[i], k, joint_along(c, k, (uint32_t)sr, from, d, m), 5);
        }
        /* the rest, but for the girdle joint (its own rules'), was aligned from the wrong
         * start: placed along the forward spine the same way (BCN_Epileptic's took the artist
         * joint above the one whose skin they hold) */
        if (i > 0 && section_axis(c, k, (uint32_t)s0, &from, &d))
            for (; i + 1 < sec->bone_count; i++) {
                double m = 0.5 * (axis_place(c, at->joints[js[i]].pos, from, d) +
                                  axis_place(c, at->joints[js[i + 1]].pos, from, d));
                if (c->tgt.matchable[js[i]])
                    take_along(p, js[i], k, joint_along(c, k, (uint32_t)s0, from, d, m), 5);
            }
    }
}

/* A trunk rooted at the front (girdle=neck): the general rigger may root a quadruped's trunk at
 * its shoulders (the Fox: a one-bone spine on to the neck, a reverse spine back to the hips
 * carrying the tail and hind legs) where the artist roots it at the hips and runs one spine
 * forward. The alignment paired the target's one-bone forward spine with the source spine's
 * first joint (the root at the shoulders took the artist's b_Hip_01) and its reverse spine with
 * nothing (its skin followed the root's). Each joint of both, placed by its bone's middle along
 * the source's spine in the bodies' frames, takes the source joint whose bone holds that place
 * (its first or last where the place lies beyond its ends). */
static void trunk_from_front(const rf_ms_ctx *c, rf_ms_pass *p)
{
    const rf_analysis *at = c->tgt.a;
    int32_t tr = reverse_spine(at), a = tr >= 0 ? at->sections[tr].attach_joint : -1;
    if (a < 0 || at->joints[a].section < 0)
        return;
    uint32_t tf = (uint32_t)at->joints[a].section;
    if (at->sections[tf].type != RF_SECTION_SPINE || (at->sections[tf].flags & RF_SECFL_REVERSE) ||
        rf_section_joints(at, tf)[0] != (uint32_t)a || p->final[a].source == RF_MS_NO_SOURCE)
        return;
    uint32_t k = p->final[a].source;
    const rf_analysis *as = c->src[k].a;
    int32_t s0 = as->joints[p->final[a].joint].section;
    rf_vec3 from, d;
    if (s0 < 0 || reverse_spine(as) >= 0 || as->sections[s0].type != RF_SECTION_SPINE ||
        !section_axis(c, k, (uint32_t)s0, &from, &d))
        return; /* a source with a reverse spine of its own: the alignment paired them */
    const uint32_t secs[2] = {tf, (uint32_t)tr};
    for (int q = 0; q < 2; q++) {
        const uint32_t *js = rf_section_joints(at, secs[q]);
        for (uint32_t i = 0; i < at->sections[secs[q]].bone_count; i++) {
            const rf_joint_info *ji = &at->joints[js[i]];
            double m = 0.5 * (axis_place(c, ji->pos, from, d) + axis_place(c, ji->tip, from, d));
            if (c->tgt.matchable[js[i]])
                take_along(p, js[i], k, joint_along(c, k, (uint32_t)s0, from, d, m), 6);
        }
    }
}

/* The trunk rooted at its other end than the source's (girdle=neck only: the skin's
 * correspondence; for motion the alignment's answer drives the trunk from the source's root). */
static void trunk_ends(const rf_ms_ctx *c, rf_ms_pass *p)
{
    if (!c->o->girdle_neck || c->o->thesis || c->o->keep_duplicates)
        return;
    trunk_from_rear(c, p);
    trunk_from_front(c, p);
}

/* Whether source joint j of source k carries no skin in a rig that says which joints do. */
static bool skinless(const rf_ms_ctx *c, uint32_t k, uint32_t j)
{
    return (c->src[k].a->joints[j].flags & RF_JI_UNWEIGHTED) != 0;
}

/* How far source joint j of source k lies from target joint t in the bodies' frames, the
 * source's side mirrored onto the target's. */
static double body_apart(const rf_ms_ctx *c, uint32_t t, uint32_t k, uint32_t j)
{
    rf_vec3 b = c->src[k].bplace[j];
    rf_side st = c->tgt.a->joints[t].side, ss = c->src[k].a->joints[j].side;
    if (st != RF_SIDE_CENTER && ss != RF_SIDE_CENTER && st != ss)
        b.x = -b.x;
    return rf_v3_len(rf_v3_sub(c->tgt.bplace[t], b));
}

/* The source joint that holds the skin about unweighted source joint j, for target joint t: its
 * nearest weighted ancestor (whose skin runs on over the links after it) or the next weighted
 * joint of its section (the bone after a link, as the steps count one), whichever pivot lies
 * nearer t's; -1 when there is neither. */
static int32_t skin_holder(const rf_ms_ctx *c, uint32_t t, uint32_t k, uint32_t j)
{
    const rf_ms_skel *s = &c->src[k];
    int32_t up = s->anc[j], down = -1;
    for (uint32_t guard = 0; up >= 0 && skinless(c, k, (uint32_t)up) && guard < s->a->joint_count;
         guard++)
        up = s->anc[up];
    const rf_joint_info *ji = &s->a->joints[j];
    if (ji->section >= 0) {
        const uint32_t *js = rf_section_joints(s->a, (uint32_t)ji->section);
        for (uint32_t i = ji->index + 1; i < s->a->sections[ji->section].bone_count && down < 0;
             i++)
            if (s->matchable[js[i]] && !skinless(c, k, js[i]))
                down = (int32_t)js[i];
    }
    if (up < 0 ||
        (down >= 0 && body_apart(c, t, k, (uint32_t)down) < body_apart(c, t, k, (uint32_t)up)))
        return down;
    return up;
}

/* Under girdle=neck (the skin's correspondence), a target joint given a source joint that carries
 * no skin, in a source rig that marks which joints do (an armature's pivot in the trunk, a
 * mechanism link in a neck or a leg), takes the source joint that holds the skin about it
 * (skin_holder). Such a match says nothing of the skin: RobotExpressive's trunk took its
 * unweighted Body and Torso, and its chest's skin was counted as its Head's. Not for motion: an
 * unweighted pivot may carry the motion its weighted children follow. */
static void skin_holders(const rf_ms_ctx *c, rf_ms_pass *p)
{
    if (!c->o->girdle_neck || c->o->thesis)
        return;
    for (uint32_t t = 0; t < c->tgt.a->joint_count; t++) {
        const rf_ms_candidate *f = &p->final[t];
        if (f->source == RF_MS_NO_SOURCE || !skinless(c, f->source, f->joint))
            continue;
        int32_t h = skin_holder(c, t, f->source, f->joint);
        if (h >= 0)
            take_along(p, t, f->source, (uint32_t)h, 7);
    }
}

/* Under girdle=neck (the skin's correspondence), a target limb without digits whose last joints
 * the alignment gave the source's lent main digit (a mitten hand against a fist: the general
 * rigger's Wizard) keeps it: the skin around it is the source hand's. Not for motion: a human's
 * finger would curl a quadruped's paw. */
static bool lent_hand(const rf_ms_ctx *c, uint32_t ts, uint32_t k, uint32_t ss)
{
    const rf_analysis *as = c->src[k].a;
    int32_t limb =
        as->sections[ss].attach_joint >= 0 ? as->joints[as->sections[ss].attach_joint].section : -1;
    return c->o->girdle_neck && !c->o->thesis && is_limb(c->tgt.a, ts) &&
           (as->sections[ss].flags & RF_SECFL_FAN) && limb >= 0 && is_limb(as, (uint32_t)limb);
}

/* Scores of the final choices (continuity with the final parents), then the threshold. */
static void finalize(const rf_ms_ctx *c, rf_ms_pass *p)
{
    const rf_analysis *a = c->tgt.a;
    for (uint32_t ts = 0; ts < a->section_count; ts++) {
        const uint32_t *js = rf_section_joints(a, ts);
        for (uint32_t i = 0; i < a->sections[ts].bone_count; i++) {
            rf_ms_candidate *f = &p->final[js[i]];
            if (f->source == RF_MS_NO_SOURCE)
                continue;
            uint32_t k = f->source, ss = (uint32_t)c->src[k].a->joints[f->joint].section;
            rf_ms_section_metrics(c, ts, k, ss, f->metrics);
            /* toes lent to a foot; a girdle joint's neck bone taking the source's neck */
            if ((p->settled[js[i]] == 2 && is_limb(c->src[k].a, ss)) || p->settled[js[i]] >= 3 ||
                lent_hand(c, ts, k, ss)) {
                f->metrics[RF_MS_SAME_TYPE] = c->wt.w[RF_MS_SAME_TYPE];
                f->metrics[RF_MS_SIMILAR_TYPE] = 0;
            }
            rf_ms_joint_metrics(c, js[i], k, f->joint, f->metrics);
            int32_t pa = c->tgt.anc[js[i]];
            f->metrics[RF_MS_CONTINUITY] =
                rf_ms_continuity(c, pa >= 0 ? &p->final[pa] : NULL, k, f->joint);
            f->total = total_of(f->metrics);
            if (f->total < c->threshold)
                *f = no_candidate;
        }
    }
}

static bool run_pass(const rf_ms_ctx *c, rf_ms_pass *p, int32_t only)
{
    uint32_t most = 1;
    for (uint32_t k = 0; k < c->nsrc; k++)
        most = c->src[k].a->joint_count > most ? c->src[k].a->joint_count : most;
    rf_ms_line tl = {0}, sl = {0};
    bool ok = line_alloc(&tl, c->tgt.a->joint_count) && line_alloc(&sl, most);
    if (ok) {
        select_best(c, p, only);
        ok = settle_sections(c, p, &tl, &sl) && neck_at_girdle(c, p, &tl, &sl);
        if (ok)
            head_at_girdle(c, p), trunk_ends(c, p);
        if (ok)
            skin_holders(c, p);
        finalize(c, p);
    }
    line_free(&tl);
    line_free(&sl);
    return ok;
}

static bool pass_alloc(const rf_ms_ctx *c, rf_ms_pass *p, bool explain)
{
    size_t n = c->tgt.a->joint_count ? c->tgt.a->joint_count : 1;
    memset(p, 0, sizeof *p);
    p->best = calloc(n, sizeof *p->best);
    p->final = calloc(n, sizeof *p->final);
    p->settled = calloc(n, 1);
    p->sec_off = calloc(c->nsrc ? c->nsrc : 1, sizeof *p->sec_off);
    uint32_t rows = 0;
    for (uint32_t k = 0; p->sec_off && k < c->nsrc; k++)
        p->sec_off[k] = rows, rows += c->src[k].a->section_count;
    p->sec = calloc((size_t)(rows ? rows : 1) * RF_MS_METRIC_COUNT, sizeof *p->sec);
    p->rows = malloc((size_t)(rows ? rows : 1) * sizeof *p->rows);
    if (explain) {
        p->top = calloc(n * 3, sizeof *p->top);
        p->top_count = calloc(n, 1);
    }
    if (!p->best || !p->final || !p->settled || !p->sec_off || !p->sec || !p->rows ||
        (explain && (!p->top || !p->top_count)))
        return false;
    for (size_t j = 0; j < n; j++)
        p->best[j] = p->final[j] = no_candidate;
    return true;
}

static void pass_free(rf_ms_pass *p)
{
    free(p->best);
    free(p->final);
    free(p->settled);
    free(p->sec);
    free(p->sec_off);
    free(p->rows);
    free(p->top);
    free(p->top_count);
}

/* ---- the mapping ---- */

static bool bends_apart(double a, double b)
{
    return fabs(a) > 0.03 && fabs(b) > 0.03 && (a > 0) != (b > 0);
}

static uint32_t input_flags(const rf_ms_ctx *c, uint32_t t, const rf_ms_candidate *f)
{
    const rf_joint_info *a = &c->tgt.a->joints[t], *b = &c->src[f->source].a->joints[f->joint];
    uint32_t flags = c->phase[a->section] ? RF_MAP_MIRROR : 0;
    uint8_t ka = c->tgt.kind[a->section], kb = c->src[f->source].kind[b->section];
    bool limbs = (ka == RF_MK_FORE || ka == RF_MK_HIND) && (kb == RF_MK_FORE || kb == RF_MK_HIND);
    if (!c->o->no_reverse && limbs && bends_apart(a->bend, b->bend))
        flags |= RF_MAP_REVERSE; /* a knee bending the other way (thesis, chapter 6) */
    return flags;
}

static bool mapping_labels(rf_mapping *m, const rf_analysis *a)
{
    m->metric_count = RF_MS_METRIC_COUNT;
    m->metric_names = calloc(RF_MS_METRIC_COUNT, sizeof *m->metric_names);
    m->sections = calloc(m->target_joint_count ? m->target_joint_count : 1, sizeof(char *));
    m->sides = calloc(m->target_joint_count ? m->target_joint_count : 1, sizeof(char *));
    if (!m->metric_names || !m->sections || !m->sides)
        return false;
    for (int i = 0; i < RF_MS_METRIC_COUNT; i++)
        if (!(m->metric_names[i] = rf_strdup(rf_ms_metric_names[i])))
            return false;
    for (uint32_t j = 0; j < m->target_joint_count; j++) {
        const rf_joint_info *ji = &a->joints[j];
        rf_section_type t = ji->section >= 0 ? a->sections[ji->section].type : RF_SECTION_NONE;
        m->sections[j] = rf_strdup(rf_section_type_name(t));
        m->sides[j] = rf_strdup(rf_side_name(ji->side));
        if (!m->sections[j] || !m->sides[j])
            return false;
    }
    return true;
}

/* Fills entry j from the final choice of each pass (one pass, or one per source when
 * blending): one input per pass that mapped it, equal weights. */
static bool fill_entry(const rf_ms_ctx *c, rf_map_entry *e, uint32_t j, rf_ms_pass *passes,
                       uint32_t npass)
{
    uint32_t count = 0;
    const rf_ms_candidate *best = NULL;
    for (uint32_t q = 0; q < npass; q++)
        if (passes[q].final[j].source != RF_MS_NO_SOURCE) {
            count++;
            if (!best || passes[q].final[j].total > best->total)
                best = &passes[q].final[j];
        }
    e->metrics = calloc(RF_MS_METRIC_COUNT, sizeof *e->metrics);
    if (!e->metrics)
        return false;
    if (!count)
        return true;
    e->inputs = calloc(count, sizeof *e->inputs);
    if (!e->inputs)
        return false;
    for (uint32_t q = 0; q < npass; q++) {
        const rf_ms_candidate *f = &passes[q].final[j];
        if (f->source == RF_MS_NO_SOURCE)
            continue;
        e->inputs[e->input_count++] =
            (rf_map_input){f->source, f->joint, 1.0f / (float)count, 0.0f, input_flags(c, j, f)};
    }
    e->score = best->total;
    memcpy(e->metrics, best->metrics, sizeof best->metrics);
    return true;
}

static rf_mapping *build_mapping(const rf_ms_ctx *c, rf_ms_pass *passes, uint32_t npass)
{
    uint32_t n = c->tgt.a->joint_count;
    rf_mapping *m = rf_mapping_new(n, c->nsrc);
    bool ok = m && mapping_labels(m, c->tgt.a);
    for (uint32_t j = 0; ok && j < n; j++)
        ok = fill_entry(c, &m->entries[j], j, passes, npass);
    if (!ok) {
        rf_mapping_free(m);
        return NULL;
    }
    return m;
}

/* ---- entry point ---- */

static void keep_explanation(rf_ms_ctx *c, rf_ms_pass *p, rf_ms_explain *e)
{
    e->target = c->tgt.a, c->tgt.a = NULL;
    e->source_count = c->nsrc;
    e->sources = calloc(c->nsrc ? c->nsrc : 1, sizeof *e->sources);
    for (uint32_t k = 0; e->sources && k < c->nsrc; k++)
        e->sources[k] = c->src[k].a, c->src[k].a = NULL;
    e->joint_count = e->target->joint_count;
    e->top = p->top, p->top = NULL;
    e->top_count = p->top_count, p->top_count = NULL;
    e->settled = p->settled, p->settled = NULL;
    e->threshold = c->threshold;
    e->gait_legs = c->gait_legs;
}

static rf_mapping *match_all(rf_ms_ctx *c, rf_ms_explain *explain, char *err, size_t err_size)
{
    uint32_t npass = c->o->blend ? c->nsrc : 1;
    rf_ms_pass *passes = calloc(npass, sizeof *passes);
    bool ok = passes != NULL;
    for (uint32_t q = 0; ok && q < npass; q++) {
        int32_t only = c->o->blend ? (int32_t)q : -1;
        ok = pass_alloc(c, &passes[q], explain && q == 0) &&
             ((only >= 0 && !source_on(c, q, only)) || run_pass(c, &passes[q], only));
    }
    rf_mapping *m = ok ? build_mapping(c, passes, npass) : NULL;
    if (!m)
        snprintf(err, err_size, "out of memory while matching");
    if (m && explain && !c->o->blend)
        keep_explanation(c, &passes[0], explain);
    for (uint32_t q = 0; passes && q < npass; q++)
        pass_free(&passes[q]);
    free(passes);
    return m;
}

rf_mapping *rf_ms_match(const rf_skeleton *target, const rf_skeleton *const *sources,
                        uint32_t source_count, const rf_ms_options *opts, rf_ms_explain *explain,
                        char *err, size_t err_size)
{
    rf_ms_options defaults = {0};
    const rf_ms_options *o = opts ? opts : &defaults;
    uint32_t enabled = 0;
    for (uint32_t k = 0; k < source_count; k++)
        enabled += !(o->disabled && o->disabled[k]) && sources[k];
    if (!target || enabled == 0) {
        snprintf(err, err_size, "%s", target ? "no source skeleton to map from" : "no target");
        return NULL;
    }
    for (uint32_t k = 0; k < source_count; k++)
        if (!sources[k]) {
            snprintf(err, err_size, "source %u is missing", k);
            return NULL;
        }
    rf_ms_ctx c;
    rf_mapping *m = NULL;
    if (ctx_init(&c, target, sources, source_count, o, err, err_size))
        m = match_all(&c, explain, err, err_size);
    ctx_clear(&c);
    return m;
}
