/* The metrics of the skeletal-similarity matcher (thesis Table 1, plus body position and digit
 * order), the named weight sets, and the per-skeleton facts they read. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ms-internal.h"

const char *const rf_ms_metric_names[RF_MS_METRIC_COUNT] = {
    "same_side", "same_type",  "similar_type", "bone_count",    "orientation",
    "sequence",  "continuity", "preference",   "body_position", "digit_order",
};

/* Table 1 / Table 5 of the thesis, then the two metrics it lacked. */
static const rf_ms_weights default_weights = {{30, 50, 15, 10, 15, 16, 5, 0, 20, 20}};
static const rf_ms_weights thesis_weights = {{30, 50, 15, 10, 15, 16, 5, 0, 0, 0}};

bool rf_ms_weight_set(const char *name, rf_ms_weights *out, uint32_t *preferred)
{
    *preferred = 0;
    if (!name || !*name || strcmp(name, "default") == 0) {
        *out = default_weights;
        return true;
    }
    if (strcmp(name, "thesis") == 0) {
        *out = thesis_weights;
        return true;
    }
    const char *rest = NULL;
    if (strncmp(name, "prefer-", 7) == 0)
        *out = default_weights, rest = name + 7;
    else if (strncmp(name, "thesis-prefer-", 14) == 0)
        *out = thesis_weights, rest = name + 14;
    if (!rest || !*rest || strspn(rest, "0123456789") != strlen(rest) || strlen(rest) > 6)
        return false;
    *preferred = (uint32_t)strtoul(rest, NULL, 10);
    out->w[RF_MS_PREFERENCE] = 10;
    return true;
}

/* ---- kinds ---- */

static bool limb_type(rf_section_type t)
{
    return t == RF_SECTION_ARM || t == RF_SECTION_LEG;
}

/* Limbs spread along the body (two girdles or more) get their role from where they sit: front
 * half fore, rear half hind. Otherwise arms are fore and legs hind. */
static void limb_roles(rf_ms_skel *s, bool thesis)
{
    const rf_analysis *a = s->a;
    double lo = INFINITY, hi = -INFINITY;
    for (uint32_t k = 0; k < a->section_count; k++)
        if (limb_type(a->sections[k].type))
            lo = fmin(lo, a->sections[k].body_pos), hi = fmax(hi, a->sections[k].body_pos);
    bool spread = !thesis && hi - lo > 0.3;
    for (uint32_t k = 0; k < a->section_count; k++) {
        const rf_section *sec = &a->sections[k];
        if (!limb_type(sec->type))
            continue;
        bool fore = spread ? sec->body_pos >= 0.5 * (lo + hi) : sec->type == RF_SECTION_ARM;
        s->kind[k] = fore ? RF_MK_FORE : RF_MK_HIND;
        s->role_types[!fore] |= sec->type == RF_SECTION_ARM ? 1 : 2;
    }
}

static rf_ms_kind center_kind(const rf_section *sec)
{
    switch (sec->type) {
    case RF_SECTION_ROOT:
        return RF_MK_ROOT;
    case RF_SECTION_SPINE:
        return (sec->flags & RF_SECFL_REVERSE) ? RF_MK_SPINE_REVERSE : RF_MK_SPINE;
    case RF_SECTION_HEAD:
        return RF_MK_HEAD;
    case RF_SECTION_TAIL:
        return RF_MK_TAIL;
    case RF_SECTION_APPENDAGE:
        return RF_MK_APPENDAGE;
    case RF_SECTION_HELPER:
    case RF_SECTION_NONE:
    case RF_SECTION_TYPE_COUNT:
        return RF_MK_HELPER;
    default:
        return RF_MK_NONE;
    }
}

/* Digits take the role of the limb they hang from. */
static void digit_kinds(rf_ms_skel *s)
{
    const rf_analysis *a = s->a;
    for (uint32_t k = 0; k < a->section_count; k++) { /* parents come first */
        const rf_section *sec = &a->sections[k];
        if (sec->type != RF_SECTION_HAND && sec->type != RF_SECTION_FOOT)
            continue;
        uint8_t parent = sec->parent >= 0 ? s->kind[sec->parent] : RF_MK_NONE;
        bool fore =
            parent == RF_MK_FORE || parent == RF_MK_FORE_DIGIT ||
            (parent != RF_MK_HIND && parent != RF_MK_HIND_DIGIT && sec->type == RF_SECTION_HAND);
        s->kind[k] = fore ? RF_MK_FORE_DIGIT : RF_MK_HIND_DIGIT;
    }
}

/* Of each fan, the digit a limb goes on into when compared with a limb without one: the
 * middle finger (of the non-thumbs, the middle rank; the longest on a tie). */
static void main_digits(rf_ms_skel *s)
{
    const rf_analysis *a = s->a;
    for (uint32_t j = 0; j < a->joint_count; j++)
        s->main_digit[j] = -1;
    for (uint32_t k = 0; k < a->section_count; k++) {
        const rf_section *sec = &a->sections[k];
        if (!(sec->flags & RF_SECFL_FAN) || (sec->flags & RF_SECFL_THUMB) || sec->attach_joint < 0)
            continue;
        int32_t *m = &s->main_digit[sec->attach_joint];
        double mid = 0.5 * sec->pair_count; /* ranks run 0..count-1, a thumb at 0 */
        if (*m < 0) {
            *m = (int32_t)k;
            continue;
        }
        const rf_section *o = &a->sections[*m];
        double d = fabs(sec->pair_rank - mid), od = fabs(o->pair_rank - mid);
        if (d < od || (d == od && sec->bone_count > o->bone_count))
            *m = (int32_t)k;
    }
}

/* How far along the hand's longest digit, from the wrist, the main digit's first joint sits:
 * the longest digit of the fan, since a leaf digit's length may only be guessed (a one-bone
 * finger of a rig without end sites). A wing's membrane fingers start a short way past its
 * wrist, against fingers many times longer: palm bones, not knuckles. */
static double knuckle_share(const rf_analysis *a, int32_t hand, const rf_joint_info *first)
{
    double longest = 0;
    for (uint32_t k = 0; k < a->section_count; k++) {
        const rf_section *d = &a->sections[k];
        if (d->attach_joint == hand && (d->flags & RF_SECFL_FAN) && !(d->flags & RF_SECFL_THUMB))
            longest = fmax(longest, d->length);
    }
    double at = rf_v3_dist(first->pos, a->joints[hand].pos);
    return at + longest > 0 ? at / (at + longest) : 0;
}

/* Joints counted along a section from its first real bone: a limb's thigh is 0, shin 1, foot 2
 * whether or not a hip offset comes first (-1), and an unweighted link in the middle of a leg
 * (a rig's mechanism) shares the place of the bone after it. A digit counts from the wrist: a
 * palm bone starting there is 0, a finger's first joint at the knuckle 1, with a palm bone
 * before it or not (digits are measured from the wrist, so the knuckle lies well along; the
 * hand's middle finger tells whether its fingers start at the knuckles or at the wrist). A
 * thumb counts from its first joint wherever that sits: rigs start it at the wrist or beside the
 * knuckles for the same bone. */
static void steps(rf_ms_skel *s, uint32_t k)
{
    const rf_analysis *a = s->a;
    const uint32_t *js = rf_section_joints(a, k);
    int32_t count = 0;
    const rf_section *sec = &a->sections[k];
    if ((sec->flags & RF_SECFL_FAN) && !(sec->flags & RF_SECFL_THUMB) && sec->attach_joint >= 0) {
        /* at the knuckle: well along the digit's reach from the wrist, and at the far end of
         * the hand bone (a palm bone starts beside the wrist, however short the hand) */
        int32_t md = s->main_digit[sec->attach_joint];
        const rf_joint_info *hand = &a->joints[sec->attach_joint];
        const rf_joint_info *first =
            md >= 0 ? &a->joints[rf_section_joints(a, (uint32_t)md)[0]] : NULL;
        if (first && knuckle_share(a, sec->attach_joint, first) >= 0.25 &&
            rf_v3_dist(first->pos, hand->pos) >= 0.6 * hand->length)
            count = 1;
    }
    for (uint32_t i = 0; i < a->sections[k].bone_count; i++) {
        const rf_joint_info *ji = &a->joints[js[i]];
        if (ji->flags & RF_JI_OFFSET) {
            s->step[js[i]] = -1;
            continue;
        }
        s->step[js[i]] = count;
        bool link = (ji->flags & RF_JI_UNWEIGHTED) && i + 1 < a->sections[k].bone_count;
        count += s->matchable[js[i]] && !link;
    }
}

static bool per_section(rf_ms_skel *s, bool thesis)
{
    const rf_analysis *a = s->a;
    uint8_t *thumbs = calloc(a->joint_count ? a->joint_count : 1, 1); /* fans with a thumb */
    if (!thumbs)
        return false;
    for (uint32_t k = 0; k < a->section_count; k++)
        if ((a->sections[k].flags & RF_SECFL_THUMB) && a->sections[k].attach_joint >= 0)
            thumbs[a->sections[k].attach_joint] = 1;
    for (uint32_t k = 0; k < a->section_count; k++) {
        const rf_section *sec = &a->sections[k];
        uint32_t found = 0; /* the last matchable joint, and in a head the neck's end before it */
        for (uint32_t i = sec->bone_count; i-- > 0 && found < 2;)
            if (s->matchable[rf_section_joints(a, k)[i]]) {
                s->ends[rf_section_joints(a, k)[i]] |= found ? 4 : 1;
                found += found || sec->type == RF_SECTION_HEAD ? 1 : 2;
            }
        for (uint32_t i = 0; i < sec->bone_count; i++)
            if (s->matchable[rf_section_joints(a, k)[i]]) {
                s->ends[rf_section_joints(a, k)[i]] |= 2;
                break;
            }
        steps(s, k);
        s->kind[k] = center_kind(sec);
        /* place among the fingers other than the thumb, 0..1 from the thumb's side */
        bool thumbed =
            (sec->flags & RF_SECFL_FAN) && sec->attach_joint >= 0 && thumbs[sec->attach_joint];
        uint32_t fingers = sec->pair_count - thumbed, rank = sec->pair_rank - thumbed;
        s->digit_frac[k] =
            (sec->flags & RF_SECFL_THUMB) || fingers < 2 ? 0.5 : (double)rank / (fingers - 1);
        s->count[k] = 0;
        for (uint32_t i = 0; i < sec->bone_count; i++)
            s->count[k] += thesis || s->matchable[rf_section_joints(a, k)[i]];
    }
    free(thumbs);
    limb_roles(s, thesis);
    digit_kinds(s);
    return true;
}

/* Placement roots, axis-conversion nodes, IK targets, poles and other unweighted helpers
 * (rf_joint_roles_find) neither drive nor take body motion. Only a rig that marks unweighted
 * joints can have them: without marks the roles are all body and are not looked for. False
 * when out of memory (the roles not found would leave an IK target or a placement matchable). */
static bool leave_out_non_body(rf_ms_skel *s)
{
    bool marked = false;
    for (uint32_t j = 0; j < s->skel->joint_count && !marked; j++)
        marked = (s->skel->joints[j].flags & RF_JOINT_UNWEIGHTED) != 0;
    if (!marked)
        return true;
    rf_joint_roles *r = rf_joint_roles_find(s->skel, NULL, NULL, 0);
    if (!r)
        return false;
    const rf_analysis *a = s->a;
    uint32_t n = r->joint_count < a->joint_count ? r->joint_count : a->joint_count;
    double lo = INFINITY, hi = -INFINITY;
    for (uint32_t j = 0; j < n; j++)
        if (r->role[j] == RF_ROLE_BODY) {
            double h = rf_v3_dot(a->joints[j].pos, a->up);
            lo = fmin(lo, h), hi = fmax(hi, h);
        }
    for (uint32_t j = 0; j < n; j++) {
        if (r->role[j] == RF_ROLE_BODY)
            continue;
        /* A placement or axis node is left out where it lies off the body (on the floor, above
         * it): an unweighted root inside it is the body's own first joint (a pelvis bone that
         * happens to carry no skin, its rest turned by the rig's bone axis). */
        double h = rf_v3_dot(a->joints[j].pos, a->up), tol = 0.1 * (hi - lo);
        bool off = !(h > lo + tol && h < hi + 0.1 * tol);
        if (!rf_joint_role_is_frame((rf_joint_role)r->role[j]) || off)
            s->matchable[j] = 0;
    }
    rf_joint_roles_free(r);
    return true;
}

/* Every joint's pivot in the body's frame (rf_ms_body_place), and that frame. */
static void body_places(rf_ms_skel *s)
{
    const rf_analysis *a = s->a;
    rf_vec3 lo = rf_v3(INFINITY, INFINITY, INFINITY), hi = rf_v3(-INFINITY, -INFINITY, -INFINITY);
    double fwd = 0;
    uint32_t n = 0;
    for (uint32_t j = 0; j < a->joint_count; j++) {
        if (!s->matchable[j])
            continue;
        fwd += rf_v3_dot(a->joints[j].pos, a->forward), n++;
        for (int e = 0; e < 2; e++) {
            rf_vec3 p = e ? a->joints[j].tip : a->joints[j].pos;
            rf_vec3 b = rf_v3(rf_v3_dot(p, a->left), rf_v3_dot(p, a->up), rf_v3_dot(p, a->forward));
            lo = rf_v3(fmin(lo.x, b.x), fmin(lo.y, b.y), fmin(lo.z, b.z));
            hi = rf_v3(fmax(hi.x, b.x), fmax(hi.y, b.y), fmax(hi.z, b.z));
        }
    }
    s->bfwd = n ? fwd / n : 0;
    double h = n ? fmax(hi.x - lo.x, fmax(hi.y - lo.y, hi.z - lo.z)) : 0;
    s->bscale = h > 0 && isfinite(h) ? h : 1;
    for (uint32_t j = 0; j < a->joint_count; j++)
        s->bplace[j] = rf_ms_body_place(s, a->joints[j].pos);
}

/* Joints a mapping can drive: not helpers, not control joints sitting on their child. False
 * when out of memory. */
static bool per_joint(rf_ms_skel *s)
{
    const rf_analysis *a = s->a;
    for (uint32_t j = 0; j < a->joint_count; j++) {
        const rf_joint_info *ji = &a->joints[j];
        bool helper = ji->section < 0 || a->sections[ji->section].type == RF_SECTION_HELPER;
        s->matchable[j] = !helper && !(ji->flags & (RF_JI_CONTROL | RF_JI_END_MARKER));
        s->bdir[j] = rf_v3(rf_v3_dot(ji->dir, a->left), rf_v3_dot(ji->dir, a->up),
                           rf_v3_dot(ji->dir, a->forward));
    }
    if (!leave_out_non_body(s))
        return false;
    body_places(s);
    for (uint32_t j = 0; j < a->joint_count; j++) {
        int32_t p = a->joints[j].logical_parent;
        for (uint32_t step = 0; p >= 0 && !s->matchable[p] && step < a->joint_count; step++)
            p = a->joints[p].logical_parent;
        s->anc[j] = p >= 0 && s->matchable[p] ? p : -1;
    }
    return true;
}

/* A section whose first joints are left out (a control root above a one-bone torso) is
 * measured from its first matchable joint: places along it are the body's, so the torso's pivot
 * at the hips lines up with a pelvis. Places run to 1 at the section's end. */
static void measure_from_body(rf_ms_skel *s)
{
    rf_analysis *a = s->a;
    for (uint32_t k = 0; k < a->section_count; k++) {
        const rf_section *sec = &a->sections[k];
        const uint32_t *js = rf_section_joints(a, k);
        uint32_t f = 0, m = sec->bone_count;
        while (f < m && !s->matchable[js[f]])
            f++;
        uint32_t g = f;
        if (g == m || f == 0 || a->joints[js[g]].u0 == 0)
            continue;
        double shift = a->joints[js[g]].u0, end = 1;
        for (uint32_t i = g; i < m; i++)
            end = fmax(end, a->joints[js[i]].u1);
        if (end - shift <= 1e-9)
            continue;
        for (uint32_t i = f; i < m; i++) {
            rf_joint_info *ji = &a->joints[js[i]];
            ji->u0 = (ji->u0 - shift) / (end - shift), ji->u1 = (ji->u1 - shift) / (end - shift);
        }
    }
}

bool rf_ms_skel_init(rf_ms_skel *s, const rf_skeleton *skel, const rf_analysis_options *ao,
                     bool thesis)
{
    memset(s, 0, sizeof *s);
    s->skel = skel;
    s->a = rf_analyze(skel, ao);
    if (!s->a)
        return false;
    size_t n = s->a->joint_count ? s->a->joint_count : 1;
    size_t ns = s->a->section_count ? s->a->section_count : 1;
    s->kind = calloc(ns, 1);
    s->count = calloc(ns, sizeof *s->count);
    s->digit_frac = calloc(ns, sizeof *s->digit_frac);
    s->matchable = calloc(n, 1);
    s->anc = calloc(n, sizeof *s->anc);
    s->bdir = calloc(n, sizeof *s->bdir);
    s->bplace = calloc(n, sizeof *s->bplace);
    s->ends = calloc(n, 1);
    s->step = calloc(n, sizeof *s->step);
    s->main_digit = malloc(n * sizeof *s->main_digit);
    if (!s->kind || !s->count || !s->digit_frac || !s->matchable || !s->anc || !s->bdir ||
        !s->bplace || !s->ends || !s->step || !s->main_digit)
        return false;
    if (!per_joint(s))
        return false;
    if (!thesis)
        measure_from_body(s);
    main_digits(s);
    return per_section(s, thesis);
}

void rf_ms_skel_clear(rf_ms_skel *s)
{
    rf_analysis_free(s->a);
    free(s->kind);
    free(s->count);
    free(s->digit_frac);
    free(s->matchable);
    free(s->anc);
    free(s->bdir);
    free(s->bplace);
    free(s->ends);
    free(s->step);
    free(s->main_digit);
    memset(s, 0, sizeof *s);
}

/* ---- metrics ---- */

/* Whether the fan the digit section `k` belongs to has a thumb. */
static bool fan_has_thumb(const rf_analysis *a, uint32_t k)
{
    for (uint32_t d = 0; d < a->section_count; d++)
        if (a->sections[d].attach_joint == a->sections[k].attach_joint &&
            (a->sections[d].flags & RF_SECFL_FAN) && (a->sections[d].flags & RF_SECFL_THUMB))
            return true;
    return false;
}

/* The length of the main digit of the fan digit section `k` belongs to, against the limb it
 * hangs from; 0 when unknown. */
static double digit_reach(const rf_ms_skel *s, uint32_t k)
{
    const rf_section *sec = &s->a->sections[k];
    if (sec->attach_joint < 0 || sec->parent < 0)
        return 0;
    int32_t d = s->main_digit[sec->attach_joint];
    double limb = s->a->sections[sec->parent].length;
    return d >= 0 && limb > 0 ? s->a->sections[d].length / limb : 0;
}

/* A thumb is its own kind of digit: it turns across the palm, not along the fingers' curl. A
 * finger of a hand that has its own thumb is not driven by a source hand's thumb while that
 * hand has other digits (it takes them, whatever its bone count); a wing's membrane fingers (digits
 * far longer for their limb than the source hand's, in a fan without a thumb) are not driven by a
 * source hand's thumb while that hand has other digits: they take its fingers. */
static bool thumb_misfit(const rf_ms_skel *t, uint32_t ts, const rf_ms_skel *s, uint32_t ss)
{
    const rf_section *st = &t->a->sections[ts], *sc = &s->a->sections[ss];
    if (!(st->flags & RF_SECFL_FAN) || !(sc->flags & RF_SECFL_THUMB) || sc->pair_count < 2)
        return false;
    if (!(st->flags & RF_SECFL_THUMB) && fan_has_thumb(t->a, ts))
        return true; /* a finger beside its own hand's thumb */
    double rt = digit_reach(t, ts), rs = digit_reach(s, ss);
    return rs > 0 && rt > 3 * rs && !fan_has_thumb(t->a, ts);
}

/* How alike two different kinds are, 0..1: the similar-type metric. Limbs of the two roles and
 * a limb with its digits are alike; so are the centerline sections; appendages are closest to
 * digits (thesis, chapter 6). */
static double kind_similarity(rf_ms_kind a, rf_ms_kind b)
{
    static const struct {
        rf_ms_kind a, b;
        double s;
    } pairs[] = {
        {RF_MK_FORE, RF_MK_HIND, 1},
        {RF_MK_FORE_DIGIT, RF_MK_HIND_DIGIT, 1},
        {RF_MK_FORE, RF_MK_FORE_DIGIT, 1},
        {RF_MK_HIND, RF_MK_HIND_DIGIT, 1},
        {RF_MK_FORE, RF_MK_HIND_DIGIT, 0.5},
        {RF_MK_HIND, RF_MK_FORE_DIGIT, 0.5},
        {RF_MK_SPINE, RF_MK_TAIL, 1},
        {RF_MK_SPINE, RF_MK_HEAD, 1},
        {RF_MK_HEAD, RF_MK_TAIL, 0.5},
        {RF_MK_SPINE, RF_MK_SPINE_REVERSE, 0.5},
        {RF_MK_SPINE_REVERSE, RF_MK_TAIL, 1},
        {RF_MK_ROOT, RF_MK_SPINE, 0.5},
        {RF_MK_APPENDAGE, RF_MK_FORE_DIGIT, 0.6},
        {RF_MK_APPENDAGE, RF_MK_HIND_DIGIT, 0.6},
        {RF_MK_APPENDAGE, RF_MK_FORE, 0.3},
        {RF_MK_APPENDAGE, RF_MK_HIND, 0.3},
    };
    for (size_t i = 0; i < sizeof pairs / sizeof pairs[0]; i++)
        if ((pairs[i].a == a && pairs[i].b == b) || (pairs[i].a == b && pairs[i].b == a))
            return pairs[i].s;
    return 0;
}

static rf_side flipped(rf_side s)
{
    return s == RF_SIDE_LEFT ? RF_SIDE_RIGHT : s == RF_SIDE_RIGHT ? RF_SIDE_LEFT : s;
}

static bool limb_kind(uint8_t k)
{
    return k == RF_MK_FORE || k == RF_MK_HIND;
}

void rf_ms_section_metrics(const rf_ms_ctx *c, uint32_t ts, uint32_t k, uint32_t ss, double *m)
{
    const rf_ms_skel *t = &c->tgt, *s = &c->src[k];
    const rf_section *st = &t->a->sections[ts], *sc = &s->a->sections[ss];
    const double *w = c->wt.w;
    rf_side side = c->flip[ts] ? flipped(st->side) : st->side;
    uint8_t kt = t->kind[ts], ks = s->kind[ss];
    memset(m, 0, RF_MS_METRIC_COUNT * sizeof *m);
    m[RF_MS_SAME_SIDE] = side == sc->side ? w[RF_MS_SAME_SIDE] : 0;
    m[RF_MS_SAME_TYPE] =
        kt == ks && !(!c->o->thesis && thumb_misfit(t, ts, s, ss)) ? w[RF_MS_SAME_TYPE] : 0;
    double similar = kind_similarity(kt, ks);
    /* toes and fingers are alike only in the thesis: a bird's toes are not a dragon's wing
     * fingers, which hang from another limb */
    bool digits = (kt == RF_MK_FORE_DIGIT && ks == RF_MK_HIND_DIGIT) ||
                  (kt == RF_MK_HIND_DIGIT && ks == RF_MK_FORE_DIGIT);
    if (digits && !c->o->thesis)
        similar = 0.3;
    m[RF_MS_SIMILAR_TYPE] = kt != ks ? w[RF_MS_SIMILAR_TYPE] * similar : 0;
    m[RF_MS_BONE_COUNT] = t->count[ts] == s->count[ss] ? w[RF_MS_BONE_COUNT] : 0;
    m[RF_MS_PREFERENCE] = k == c->o->preferred_source ? w[RF_MS_PREFERENCE] : 0;
    if ((limb_kind(kt) || kt == RF_MK_APPENDAGE) && (limb_kind(ks) || ks == RF_MK_APPENDAGE)) {
        double bt = fmax(-1, fmin(2, st->body_pos)), bs = fmax(-1, fmin(2, sc->body_pos));
        double near = fmax(0, 1 - fabs(bt - bs));
        /* where the source has limbs of one role both held up (arms, wings) and on the ground,
         * a target limb takes the one of its own type: a dragon's wings drive a bird's wings,
         * its forelegs stay off them (a lone pair of arms still drives forelegs) */
        uint8_t own = st->type == RF_SECTION_ARM ? 1 : 2;
        if (kt == ks && st->type != sc->type && (s->role_types[ks == RF_MK_HIND] & own) &&
            !c->o->thesis)
            near *= 0.2;
        m[RF_MS_BODY_POSITION] = w[RF_MS_BODY_POSITION] * near;
    }
    /* digits: a thumb for a thumb, then the fingers in their order across the hand */
    if ((st->flags & RF_SECFL_FAN) && (sc->flags & RF_SECFL_FAN) &&
        !((st->flags ^ sc->flags) & RF_SECFL_THUMB))
        m[RF_MS_DIGIT_ORDER] =
            w[RF_MS_DIGIT_ORDER] * (0.6 + 0.4 * (1 - fabs(t->digit_frac[ts] - s->digit_frac[ss])));
}

/* Orientation: the angle between the bones in their bodies' frames (a bone on the other side is
 * mirrored first); full points at zero, falling quadratically to none at the maximum angle. */
double rf_ms_orientation(const rf_ms_ctx *c, uint32_t t, uint32_t k, uint32_t j)
{
    rf_vec3 a, b;
    if (!rf_ms_body_dirs(c, t, k, j, &a, &b))
        return 0;
    /* most pairs point too far apart to score: a dot product settles them */
    if (rf_v3_dot(a, b) <= c->cos_angle * sqrt(rf_v3_len2(a) * rf_v3_len2(b)))
        return 0;
    double deg = rf_v3_angle(a, b) * 180.0 / RF_PI, x = deg / c->angle;
    return x < 1 ? c->wt.w[RF_MS_ORIENTATION] * (1 - x * x) : 0;
}

/* Sequence: the thesis gives the points for the same index in the section; here for the same
 * place, pivot and tip measured as fractions of the section's length, so a zero-length joint or
 * a missing clavicle does not shift the rest. */
double rf_ms_sequence(const rf_ms_ctx *c, uint32_t t, uint32_t k, uint32_t j)
{
    const rf_joint_info *a = &c->tgt.a->joints[t], *b = &c->src[k].a->joints[j];
    if (c->o->thesis)
        return a->index == b->index ? c->wt.w[RF_MS_SEQUENCE] : 0;
    /* comparisons, not fmin/fmax: this runs for every pair of joints and those are calls */
    double ua = a->u1 < 1.5 ? a->u1 : 1.5, ub = b->u1 < 1.5 ? b->u1 : 1.5;
    double x = 1 - (fabs(a->u0 - b->u0) + fabs(ua - ub)) / 0.5;
    return x > 0 ? c->wt.w[RF_MS_SEQUENCE] * x : 0;
}

void rf_ms_joint_metrics(const rf_ms_ctx *c, uint32_t t, uint32_t k, uint32_t j, double *m)
{
    m[RF_MS_ORIENTATION] = rf_ms_orientation(c, t, k, j);
    m[RF_MS_SEQUENCE] = rf_ms_sequence(c, t, k, j);
}

/* Continuity: half for staying with the source the parent's match came from, half for a
 * candidate whose parent is that match (the chain goes on in order). */
double rf_ms_continuity(const rf_ms_ctx *c, const rf_ms_candidate *parent, uint32_t k, uint32_t j)
{
    if (!parent || parent->source == RF_MS_NO_SOURCE)
        return 0;
    double w = c->wt.w[RF_MS_CONTINUITY], points = 0;
    if (parent->source == k) {
        points += 0.5 * w;
        if (c->src[k].anc[j] == (int32_t)parent->joint)
            points += 0.5 * w;
    }
    return points;
}
