/* rf_rig_template: a humanoid or quadruped template embedded into the general rigger's curve
 * skeleton (after Baran and Popovic 2007, who embed a template into a discretised medial
 * skeleton). The skeleton analysis reads the curve skeleton (legs, arms, sides, front and rear
 * girdles, head); each template chain is laid along the curve it matches, its joints at the
 * template's relative places along that curve (an elbow or a knee at the curve's sharpest bend
 * near its place), and named as animation tools expect (Hips, Spine, LeftUpLeg...). A body the
 * template does not fit is refused with the reason. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <rigflow/analysis.h>
#include <rigflow/model-copy.h>

#include "rig-internal.h"

/* A curve through the body: points and the arc length at each. */
#define RF_TPL_MAXPTS 512
typedef struct rf_tpl_curve {
    uint32_t n;
    double p[RF_TPL_MAXPTS][3];
    double s[RF_TPL_MAXPTS]; /* arc length from the first point */
} rf_tpl_curve;

static void rf_tpl_add(rf_tpl_curve *c, const double q[3])
{
    if (c->n == RF_TPL_MAXPTS)
        return;
    double d = 0;
    if (c->n) {
        const double *l = c->p[c->n - 1];
        d = sqrt((q[0] - l[0]) * (q[0] - l[0]) + (q[1] - l[1]) * (q[1] - l[1]) +
                 (q[2] - l[2]) * (q[2] - l[2]));
        if (d < 1e-12)
            return; /* coincident points would give no direction */
    }
    memcpy(c->p[c->n], q, 3 * sizeof(double));
    c->s[c->n] = c->n ? c->s[c->n - 1] + d : 0;
    c->n++;
}

static double rf_tpl_len(const rf_tpl_curve *c)
{
    return c->n ? c->s[c->n - 1] : 0;
}

/* The point at fraction f of the curve's length. */
static void rf_tpl_at(const rf_tpl_curve *c, double f, double out[3])
{
    double s = fmin(fmax(f, 0), 1) * rf_tpl_len(c);
    uint32_t i = 1;
    while (i + 1 < c->n && c->s[i] < s)
        i++;
    if (c->n < 2) {
        memcpy(out, c->p[0], 3 * sizeof(double));
        return;
    }
    double span = c->s[i] - c->s[i - 1], t = span > 0 ? (s - c->s[i - 1]) / span : 0;
    for (int a = 0; a < 3; a++)
        out[a] = c->p[i - 1][a] + t * (c->p[i][a] - c->p[i - 1][a]);
}

/* The part of curve c between fractions f0 and f1, into out. */
static void rf_tpl_sub(const rf_tpl_curve *c, double f0, double f1, rf_tpl_curve *out)
{
    double p[3], len = rf_tpl_len(c);
    out->n = 0;
    rf_tpl_at(c, f0, p);
    rf_tpl_add(out, p);
    for (uint32_t i = 0; i < c->n; i++)
        if (c->s[i] > f0 * len && c->s[i] < f1 * len)
            rf_tpl_add(out, c->p[i]);
    rf_tpl_at(c, f1, p);
    rf_tpl_add(out, p);
}

/* The cosine of the angle curve c turns by at its interior point i. */
static double rf_tpl_turn_cos(const rf_tpl_curve *c, uint32_t i)
{
    double u[3], v[3], nu = 0, nv = 0, dot = 0;
    for (int a = 0; a < 3; a++) {
        u[a] = c->p[i][a] - c->p[i - 1][a], v[a] = c->p[i + 1][a] - c->p[i][a];
        nu += u[a] * u[a], nv += v[a] * v[a], dot += u[a] * v[a];
    }
    return dot / sqrt(nu * nv);
}

/* Where the curve bends most (turning angle over 15 degrees) between fractions lo and hi; `dflt`
 * when it runs straight there (a limb held straight has its elbow or knee at the template's
 * place). The index of the point bending there into *at_point when given, 0 for none. */
static double rf_tpl_bend_at(const rf_tpl_curve *c, double lo, double hi, double dflt,
                             uint32_t *at_point)
{
    double len = rf_tpl_len(c), best = cos(15 * M_PI / 180), at = dflt;
    if (at_point)
        *at_point = 0;
    for (uint32_t i = 1; len > 0 && i + 1 < c->n; i++) {
        double f = c->s[i] / len, cosang = f < lo || f > hi ? 1 : rf_tpl_turn_cos(c, i);
        if (cosang < best) {
            best = cosang, at = f;
            if (at_point)
                *at_point = i;
        }
    }
    return at;
}

static double rf_tpl_bend(const rf_tpl_curve *c, double lo, double hi, double dflt)
{
    return rf_tpl_bend_at(c, lo, hi, dflt, NULL);
}

/* The common ancestor of joints a and b, -1 when they have none. Parents come before their
 * children (model.h), so of two different joints the later is no ancestor of the other and
 * climbs: the walk needs no memory, which marking a's ancestors did (and an allocation failing
 * there read as no path at all). */
static int32_t rf_tpl_common(const rf_rig_skel *k, uint32_t a, uint32_t b)
{
    int32_t i = (int32_t)a, j = (int32_t)b;
    while (i >= 0 && j >= 0 && i != j) {
        if (i > j)
            i = k->parent[i];
        else
            j = k->parent[j];
    }
    return i >= 0 && j >= 0 ? i : -1;
}

/* The tree path from joint a to joint b (up from a to their common ancestor, down to b). */
static void rf_tpl_path(const rf_rig_skel *k, uint32_t a, uint32_t b, rf_tpl_curve *c)
{
    uint32_t down[RF_TPL_MAXPTS], nd = 0;
    int32_t meet = rf_tpl_common(k, a, b);
    for (int32_t j = (int32_t)b; j >= 0 && j != meet && nd < RF_TPL_MAXPTS; j = k->parent[j])
        down[nd++] = (uint32_t)j;
    for (int32_t j = (int32_t)a; j >= 0 && j != meet; j = k->parent[j])
        rf_tpl_add(c, k->pos + (size_t)j * 3);
    if (meet >= 0)
        rf_tpl_add(c, k->pos + (size_t)meet * 3);
    for (uint32_t i = nd; i-- > 0;)
        rf_tpl_add(c, k->pos + (size_t)down[i] * 3);
}

/* The end of a joint's bone: its end site, or its pivot. */
static const double *rf_tpl_end(const rf_rig_skel *k, uint32_t j)
{
    return k->has_tip[j] ? k->tip + (size_t)j * 3 : k->pos + (size_t)j * 3;
}

/* The leaf below joint j (j's subtree, not entering joints flagged in `skip`) farthest along
 * the tree from j, counting its end site, into *leaf; its distance into *reach. j itself when it
 * is a leaf. False when out of memory. */
static bool rf_tpl_far_leaf(const rf_rig_skel *k, uint32_t j, const uint8_t *skip, uint32_t *leaf,
                            double *reach)
{
    double *d = malloc((k->n + 1) * sizeof *d);
    uint8_t *in = calloc(k->n + 1, 1);
    uint32_t best = j;
    *reach = 0, *leaf = j;
    if (!d || !in) {
        free(d), free(in);
        return false;
    }
    in[j] = 1, d[j] = 0;
    for (uint32_t i = j + 1; i < k->n; i++) { /* parents come first */
        int32_t p = k->parent[i];
        if (p < 0 || !in[p] || (skip && skip[i]))
            continue;
        in[i] = 1;
        const double *a = k->pos + (size_t)i * 3, *b = k->pos + (size_t)p * 3;
        d[i] = d[p] + sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                           (a[2] - b[2]) * (a[2] - b[2]));
    }
    for (uint32_t i = j; i < k->n; i++) {
        if (!in[i])
            continue;
        const double *a = k->pos + (size_t)i * 3, *t = rf_tpl_end(k, i);
        double r = d[i] + sqrt((a[0] - t[0]) * (a[0] - t[0]) + (a[1] - t[1]) * (a[1] - t[1]) +
                               (a[2] - t[2]) * (a[2] - t[2]));
        if (r > *reach)
            *reach = r, best = i;
    }
    free(d), free(in);
    *leaf = best;
    return true;
}

static double rf_tpl_dist(const double *a, const double *b)
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2]));
}

static bool rf_tpl_is_leaf(const rf_rig_skel *k, uint32_t j)
{
    for (uint32_t i = j + 1; i < k->n; i++) /* parents come first */
        if (k->parent[i] == (int32_t)j)
            return false;
    return true;
}

/* The leaf of the tree farthest from joint `from` along the tree, in any direction (up through
 * parents too: a box model's head may hang anywhere), never entering a joint flagged in `block`;
 * its distance, end site included, into *reach. With `up` given, of the leaves reaching at least
 * `least` the one whose end lies highest instead (a biped's head stands above its chest, where a
 * tail reaching farther would win by length). The leaf into *leaf, `from` when nothing is
 * reachable. False when out of memory. */
static bool rf_tpl_far_any(const rf_rig_skel *k, uint32_t from, const uint8_t *block,
                           const rf_vec3 *up, double least, uint32_t *leaf, double *reach)
{
    double *d = malloc((k->n + 1) * sizeof *d);
    uint32_t *queue = malloc((k->n + 1) * sizeof *queue), best = from, high = from, head = 0,
             tail = 0;
    uint8_t *seen = calloc(k->n + 1, 1);
    double top = -INFINITY, high_reach = 0;
    *reach = 0, *leaf = from;
    if (!d || !queue || !seen) {
        free(d), free(queue), free(seen);
        return false;
    }
    d[from] = 0, seen[from] = 1, queue[tail++] = from;
    while (head < tail) {
        uint32_t j = queue[head++];
        const double *e = rf_tpl_end(k, j);
        double r = d[j] + rf_tpl_dist(k->pos + (size_t)j * 3, e);
        if (r > *reach && rf_tpl_is_leaf(k, j))
            *reach = r, best = j;
        if (up && r >= least && rf_tpl_is_leaf(k, j) &&
            e[0] * up->x + e[1] * up->y + e[2] * up->z > top)
            top = e[0] * up->x + e[1] * up->y + e[2] * up->z, high = j, high_reach = r;
        for (uint32_t i = 0; i < k->n; i++) { /* neighbours: the parent and the children */
            bool next = (k->parent[j] == (int32_t)i) || (k->parent[i] == (int32_t)j);
            if (!next || seen[i] || block[i])
                continue;
            seen[i] = 1, queue[tail++] = i;
            d[i] = d[j] + rf_tpl_dist(k->pos + (size_t)i * 3, k->pos + (size_t)j * 3);
        }
    }
    free(d), free(queue), free(seen);
    if (high != from)
        best = high, *reach = high_reach;
    *leaf = best;
    return true;
}

static double rf_tpl_height(const rf_rig_skel *k, uint32_t j, rf_vec3 up)
{
    const double *p = k->pos + (size_t)j * 3;
    return p[0] * up.x + p[1] * up.y + p[2] * up.z;
}

/* Flags into `above` the joints below `first` (not first itself) that rise above joint
 * `girdle`: a leg hangs down, so a branch of its curve skeleton climbing above the leg's girdle
 * is something else merged into it (a head leaving the body by a foreleg). False when out of
 * memory. */
static bool rf_tpl_rising(const rf_rig_skel *k, rf_vec3 up, uint32_t girdle, uint32_t first,
                          uint8_t *above)
{
    uint8_t *in = calloc(k->n + 1, 1);
    if (!in)
        return false;
    in[first] = 1;
    double top = rf_tpl_height(k, girdle, up);
    for (uint32_t j = first + 1; j < k->n; j++) /* parents come first */
        if (k->parent[j] >= 0 && in[k->parent[j]]) {
            in[j] = 1;
            if (rf_tpl_height(k, j, up) > top)
                above[j] = 1;
        }
    for (uint32_t j = first + 1; j < k->n; j++) /* and all below them */
        if (k->parent[j] >= 0 && above[k->parent[j]])
            above[j] = 1;
    free(in);
    return true;
}

/* The curve of a limb: from joint `from` (its girdle) down to the farthest end below the limb's
 * first joint, its end site included. False when out of memory. */
static bool rf_tpl_limb(const rf_rig_skel *k, uint32_t from, uint32_t first, const uint8_t *skip,
                        rf_tpl_curve *c)
{
    double reach;
    uint32_t leaf;
    c->n = 0;
    if (!rf_tpl_far_leaf(k, first, skip, &leaf, &reach))
        return false;
    rf_tpl_path(k, from, leaf, c);
    rf_tpl_add(c, rf_tpl_end(k, leaf));
    return true;
}

/* ---- the template being laid out ---- */

#define RF_TPL_MAXJ 40
typedef struct rf_tpl {
    uint32_t n;
    char name[RF_TPL_MAXJ][24];
    int32_t parent[RF_TPL_MAXJ];
    double pos[RF_TPL_MAXJ][3], tip[RF_TPL_MAXJ][3];
    uint8_t has_tip[RF_TPL_MAXJ];
    uint32_t trunk, trunk_count; /* Hips, the spine and the neck: joints [trunk, +count) */
    int32_t head;                /* the Head joint, -1 before the trunk is laid */
} rf_tpl;

static int32_t rf_tpl_joint(rf_tpl *t, const char *name, int32_t parent, const double p[3])
{
    if (t->n == RF_TPL_MAXJ)
        return -1;
    uint32_t j = t->n++;
    snprintf(t->name[j], sizeof t->name[j], "%s", name);
    t->parent[j] = parent, t->has_tip[j] = 0;
    memcpy(t->pos[j], p, sizeof t->pos[j]);
    return (int32_t)j;
}

static void rf_tpl_tip(rf_tpl *t, int32_t j, const double p[3])
{
    if (j < 0)
        return;
    memcpy(t->tip[j], p, sizeof t->tip[j]);
    t->has_tip[j] = 1;
}

/* Joints named names[0..count) along curve c at fractions f[], each the child of the one before
 * (the first of `parent`), the last with the curve's end as its end site. Returns the first. */
static int32_t rf_tpl_chain(rf_tpl *t, const rf_tpl_curve *c, int32_t parent,
                            const char *const *names, const double *f, uint32_t count)
{
    int32_t first = -1, j = parent;
    for (uint32_t i = 0; i < count; i++) {
        double p[3];
        rf_tpl_at(c, f[i], p);
        j = rf_tpl_joint(t, names[i], j, p);
        if (i == 0)
            first = j;
    }
    double end[3];
    rf_tpl_at(c, 1, end);
    rf_tpl_tip(t, j, end);
    return first;
}

/* ---- what the analysis found ---- */

typedef struct rf_tpl_body {
    /* mirrored pairs of limb sections [pair][left, right], the longest first; legs front first */
    int32_t leg[2][2], arm[2][2];
    uint32_t leg_pairs, arm_pairs;
    uint32_t legs[3], arms[3]; /* sections per side: left, right, centre */
    uint32_t wing_pairs;       /* kept arm pairs that are wings (rf_rig_is_wing) */
} rf_tpl_body;

/* Keeps a mirrored pair in slots (at most two, ordered by `key`, largest first). */
static void rf_tpl_keep(int32_t pairs[2][2], double keys[2], uint32_t *n, int32_t l, int32_t r,
                        double key)
{
    uint32_t at = *n < 2 ? (*n)++ : 2;
    while (at > 0 && keys[at - 1] < key) {
        if (at < 2)
            pairs[at][0] = pairs[at - 1][0], pairs[at][1] = pairs[at - 1][1],
            keys[at] = keys[at - 1];
        at--;
    }
    if (at < 2)
        pairs[at][0] = l, pairs[at][1] = r, keys[at] = key;
}

/* The body's mirrored pairs of legs and arms. Arms are ranked by length (a head the analysis
 * took for an arm has no mirror, and a short pair of wings or spikes yields to the arms), legs
 * front first. False when out of memory (no pair read, which would refuse the body as fitting
 * no template). */
static bool rf_tpl_limbs(const rf_analysis *a, rf_tpl_body *b)
{
    memset(b, 0, sizeof *b);
    memset(b->leg, -1, sizeof b->leg), memset(b->arm, -1, sizeof b->arm);
    double leg_key[2] = {0}, arm_key[2] = {0};
    uint8_t *used = calloc(a->section_count + 1, 1);
    if (!used)
        return false;
    for (uint32_t s = 0; s < a->section_count; s++) {
        const rf_section *sec = &a->sections[s];
        bool leg = sec->type == RF_SECTION_LEG;
        if (!leg && sec->type != RF_SECTION_ARM)
            continue;
        int side = sec->side == RF_SIDE_LEFT ? 0 : sec->side == RF_SIDE_RIGHT ? 1 : 2;
        leg ? b->legs[side]++ : b->arms[side]++;
    }
    /* mirror images first; then (the analysis pairs limbs by shape, and four like legs may
     * leave a pair unmatched) a left limb left over takes the right one of the same type and
     * rank, when their lengths are alike */
    for (int pass = 0; pass < 2; pass++)
        for (uint32_t s = 0; s < a->section_count; s++) {
            const rf_section *sec = &a->sections[s];
            bool leg = sec->type == RF_SECTION_LEG;
            if ((!leg && sec->type != RF_SECTION_ARM) || sec->side != RF_SIDE_LEFT || used[s])
                continue;
            int32_t m = -1;
            if (pass == 0 && sec->mirror >= 0 && a->sections[sec->mirror].type == sec->type &&
                !used[sec->mirror])
                m = sec->mirror;
            for (uint32_t r = 0; pass == 1 && r < a->section_count && m < 0; r++) {
                const rf_section *o = &a->sections[r];
                if (o->type == sec->type && o->side == RF_SIDE_RIGHT && !used[r] &&
                    o->pair_rank == sec->pair_rank &&
                    fmin(o->length, sec->length) > 0.6 * fmax(o->length, sec->length))
                    m = (int32_t)r;
            }
            if (m < 0)
                continue;
            used[m] = used[s] = 1;
            if (leg)
                rf_tpl_keep(b->leg, leg_key, &b->leg_pairs, (int32_t)s, m,
                            sec->body_pos + a->sections[m].body_pos);
            else
                rf_tpl_keep(b->arm, arm_key, &b->arm_pairs, (int32_t)s, m,
                            sec->length + a->sections[m].length);
        }
    free(used);
    double leg = 0;
    for (uint32_t s = 0; s < a->section_count; s++)
        leg = a->sections[s].type == RF_SECTION_LEG ? fmax(leg, a->sections[s].length) : leg;
    for (uint32_t i = 0; i < b->arm_pairs; i++)
        b->wing_pairs += rf_rig_is_wing(RF_RIG_LIMB_ARM, a->sections[b->arm[i][0]].length, leg) &&
                         rf_rig_is_wing(RF_RIG_LIMB_ARM, a->sections[b->arm[i][1]].length, leg);
    return true;
}

/* The joint a limb section hangs from on the body, and its first joint. */
static void rf_tpl_ends(const rf_analysis *a, int32_t sec, uint32_t *girdle, uint32_t *first)
{
    const rf_section *s = &a->sections[sec];
    *first = rf_section_joints(a, (uint32_t)sec)[0];
    *girdle = s->attach_joint >= 0 ? (uint32_t)s->attach_joint : *first;
}

/* The common ancestor of two joints (a when they have none). */
static uint32_t rf_tpl_meet(const rf_rig_skel *k, uint32_t a, uint32_t b)
{
    int32_t m = rf_tpl_common(k, a, b);
    return m >= 0 ? (uint32_t)m : a;
}

/* ---- the templates ---- */

typedef struct rf_tpl_ctx {
    const rf_rig_skel *k;
    const rf_analysis *a;
    const rf_tpl_body *b;
    rf_tpl *t;
    uint8_t *limb;   /* [joint] in a limb section or below one: not the head or the tail */
    int swap;        /* the ends swapped against the analysis's forward: sides swapped too */
    int facing;      /* -1: no facing read (or a biped's declared); 1: the analysis's forward
                      * faces back against the facing read (rf_tpl_facing), its sides
                      * swapped; 0: not */
    rf_vec3 forward; /* hips to chest (quadruped), zero when the analysis's forward stands */
    const rf_rig_tpl_layout *lay; /* where the joints go along each curve */
    bool human;                   /* the humanoid template: its head is the highest leaf */
    rf_vec3 up;                   /* the body's up (declared, else the analysis's) */
    const rf_rig_prep *p;         /* the cleaned mesh (NULL: no shoulder rule) */
    rf_rig_surface *sf;           /* its surface for rays, made for a humanoid's arms */
    double legs;                  /* the longest leg's reach, against which an arm is a wing */
    bool oom; /* an allocation failed laying the template: the template laid is no answer (a limb
               * with no curve, a head or a tail not looked for), the run fails out of memory */
} rf_tpl_ctx;

/* The built-in layouts (doc/autorig.md, "The template rigger", says how they were chosen). */
const rf_rig_tpl_layout rf_rig_tpl_humanoid = {
    .spine = {0.25, 0.5, 0.75},
    .neck_at = 0.29,
    .head = 0.35,
    .shoulder = 0.14,
    .arm = 0.16,
    .hand = 0.8,
    .elbow = 0.40,
    .elbow_lo = 0.28,
    .elbow_hi = 0.53,
    .upleg = 0.22,
    .knee = 0.47,
    .knee_lo = 0.35,
    .knee_hi = 0.6,
    .ankle_rise = 0.28,
    .toe = 0.32,
    .centre = false,
};
const rf_rig_tpl_layout rf_rig_tpl_quadruped = {
    .spine = {0.13, 0.5, 0.75},
    .neck_at = 0.5,
    .head = 0.38,
    .shoulder = 0.34,
    .arm = 0.39,
    .hand = 0.82,
    .elbow = 0.5,
    .elbow_lo = 0.4,
    .elbow_hi = 0.65,
    .upleg = 0.24,
    .knee = 0.38,
    .knee_lo = 0.25,
    .knee_hi = 0.5,
    .hock = 0.68,
    .hock_lo = 0.55,
    .hock_hi = 0.8,
    .toe = 0.44,
    .tail = {0.1, 0.32, 0.54, 0.76},
    .centre = false,
    .dorsal = 0.68,
};

static const char *const rf_tpl_side[2] = {"Left", "Right"};

/* A side's joint name ("LeftUpLeg") into buf. */
static const char *rf_tpl_sided(char buf[24], int side, const char *part)
{
    snprintf(buf, 24, "%s%s", rf_tpl_side[side], part);
    return buf;
}

#define RF_TPL_ANKLE 0.82 /* a biped's ankle along its leg's curve when no height places it */

/* Where a limb's four joints go along its curve c (girdle to tip), as fractions into f[]: a
 * leg's hip, knee at the curve's bend near the middle, ankle where the curve comes down to the
 * foot's height (or at its bend, for a hock) and toe; an arm's (a foreleg's) clavicle, upper
 * arm, elbow at the bend near the middle, and hand. The index of the curve's point whose bend
 * gave the knee into *knee_at (0: none did, the layout's place). */
static void rf_tpl_fractions(const rf_tpl_curve *c, rf_vec3 up, rf_rig_limb_kind kind,
                             const rf_rig_tpl_layout *l, double f[4], uint32_t *knee_at)
{
    *knee_at = 0;
    if (kind == RF_RIG_LIMB_ARM || kind == RF_RIG_LIMB_FORELEG) {
        f[0] = l->shoulder, f[1] = l->arm, f[3] = l->hand;
        f[2] = rf_tpl_bend(c, l->elbow_lo, l->elbow_hi, l->elbow);
        return;
    }
    bool hind = kind == RF_RIG_LIMB_HIND_LEG;
    double knee = rf_tpl_bend_at(c, l->knee_lo, l->knee_hi, l->knee, knee_at);
    double ankle = hind ? rf_tpl_bend(c, l->hock_lo, l->hock_hi, l->hock) : RF_TPL_ANKLE;
    if (!hind) { /* the ankle: first point within ankle_rise of the leg's height of its lowest */
        double lo = INFINITY, top = 0;
        for (uint32_t i = 0; i < c->n; i++) {
            double h = c->p[i][0] * up.x + c->p[i][1] * up.y + c->p[i][2] * up.z;
            lo = fmin(lo, h), top = i ? top : h;
        }
        for (uint32_t i = 1; i < c->n; i++) {
            double h = c->p[i][0] * up.x + c->p[i][1] * up.y + c->p[i][2] * up.z;
            if (h <= lo + l->ankle_rise * (top - lo)) {
                ankle = fmin(fmax(c->s[i] / rf_tpl_len(c), 0.7), 0.9);
                break;
            }
        }
    }
    f[0] = l->upleg, f[1] = knee, f[2] = ankle, f[3] = ankle + l->toe * (1 - ankle);
}

/* The curve of the limb whose first joint is `first`, from its girdle, and where its joints go
 * along it. A leg hangs down, so what climbs above its girdle is left out (a head merged into a
 * foreleg); an arm may rise. False when out of memory. */
static bool rf_tpl_limb_laid(const rf_rig_skel *k, rf_vec3 up, uint32_t girdle, uint32_t first,
                             rf_rig_limb_kind kind, const rf_rig_tpl_layout *l, rf_tpl_curve *c,
                             double f[4], uint32_t *knee_at)
{
    uint8_t *skip = calloc(k->n + 1, 1);
    c->n = 0;
    bool ok = skip && (kind == RF_RIG_LIMB_ARM || rf_tpl_rising(k, up, girdle, first, skip)) &&
              rf_tpl_limb(k, girdle, first, skip, c);
    free(skip);
    if (ok)
        rf_tpl_fractions(c, up, kind, l, f, knee_at);
    return ok;
}

#define RF_TPL_KNEE_TURN 20 /* degrees: a bend kept as the knee when the raised curve has none */

/* The knee of a leg laid again from a raised start (f: hip, knee, ankle, toe as fractions of the
 * longer curve) whose bends gave none: at `kept`, where the curve as found bent by kept_cos (its
 * cosine; NAN: it bent nowhere in the knee's range), when that bend turns by RF_TPL_KNEE_TURN
 * degrees or more, else at the layout's share of the way from the hip to the ankle. The raised
 * start meets the curve at a bend of its own, no knee; and a bend of a few degrees past the 15
 * that rf_tpl_bend asks may be a hem's (BCN_Epileptic's, where its shorts end, 17 degrees, 0.72
 * of the way to the ankle): its artist's knees lie at 0.47, within 0.02 of that share. */
static double rf_tpl_knee_kept(const rf_rig_tpl_layout *l, const double *f, double kept,
                               double kept_cos)
{
    if (kept_cos <= cos(RF_TPL_KNEE_TURN * M_PI / 180))
        return fmin(fmax(kept, f[0]), f[2]);
    return f[0] + (l->knee - l->upleg) / (RF_TPL_ANKLE - l->upleg) * (f[2] - f[0]);
}

/* c with its first point (the girdle's pivot) moved to `start`, arc lengths measured again.
 * False when out of memory. */
static bool rf_tpl_restart(rf_tpl_curve *c, const double start[3])
{
    if (!c->n)
        return true;
    rf_tpl_curve *old = malloc(sizeof *old);
    if (!old)
        return false;
    *old = *c;
    c->n = 0;
    rf_tpl_add(c, start);
    for (uint32_t i = 1; i < old->n; i++)
        rf_tpl_add(c, old->p[i]);
    free(old);
    return true;
}

/* The curve a limb's joints are laid along into c (from `start` when given) and where its
 * joints go into f[]; cut at arc length `reach` when that is shorter (0: whole). False when
 * out of memory. */
static bool rf_tpl_limb_curve(const rf_rig_skel *k, rf_vec3 up, uint32_t girdle, uint32_t first,
                              rf_rig_limb_kind kind, const rf_rig_tpl_layout *l,
                              const double *start, double reach, rf_tpl_curve *c, double f[4])
{
    uint32_t was_at, now_at;
    if (!rf_tpl_limb_laid(k, up, girdle, first, kind, l, c, f, &was_at))
        return false;
    if (start) {
        /* the ankle stays where the foot's height put it on the curve as found, measured from
         * the foot: a start raised above the girdle (rf_rig_legs_raise) is no taller foot; and
         * so does a knee found at a bend there when the longer curve has no bend in the knee's
         * range (the Wizard's right knee, its bend near the top of the range, went a sixth of
         * the leg up to the template's place) or bends only where the raised start meets the
         * curve (point 1: BCN_Epileptic's knees went there, a fifth of the way down the leg) */
        double knee = f[1], ankle = f[2], was = rf_tpl_len(c);
        double kept_cos = was_at ? rf_tpl_turn_cos(c, was_at) : NAN;
        if (!rf_tpl_restart(c, start))
            return false;
        rf_tpl_fractions(c, up, kind, l, f, &now_at);
        double now = rf_tpl_len(c);
        if (kind == RF_RIG_LIMB_LEG && now > 0) {
            f[2] = fmin(fmax(1 - (1 - ankle) * was / now, f[0]), 1);
            if (now_at <= 1)
                f[1] = rf_tpl_knee_kept(l, f, 1 - (1 - knee) * was / now, kept_cos);
            f[3] = f[2] + l->toe * (1 - f[2]);
        }
    }
    double len = rf_tpl_len(c);
    if (reach > 0 && reach < len) {
        rf_tpl_curve *cut = malloc(sizeof *cut);
        if (!cut)
            return false;
        rf_tpl_sub(c, 0, reach / len, cut);
        memcpy(c, cut, sizeof *c);
        free(cut);
        rf_tpl_fractions(c, up, kind, l, f, &now_at);
    }
    return true;
}

bool rf_rig_limb_reach(const rf_rig_skel *k, rf_vec3 up, uint32_t girdle, uint32_t first,
                       rf_rig_limb_kind kind, const double *start, double *reach)
{
    rf_tpl_curve *c = malloc(sizeof *c);
    double f[4];
    bool ok =
        c && rf_tpl_limb_curve(k, up, girdle, first, kind, &rf_rig_tpl_humanoid, start, 0, c, f);
    *reach = ok ? rf_tpl_len(c) : 0;
    free(c);
    return ok;
}

/* A laid limb whose curve reaches more than this many times as far as its mirror image's
 * carries a prop past its hand (the Wizard's staff, the ninja's sword: 1.75 and 1.93 times;
 * every other pair of the shared models, at any turn, within 1.19): it is laid along its curve
 * only as far as its mirror image reaches, so its elbow and hand lie where its twin's do, and
 * the prop goes with its last joint, as artists bind a weapon to the hand. Laid along the whole
 * curve, the hand went into the prop and the elbow to the wrist. */
#define RF_RIG_PROP_REACH 1.4

double rf_rig_limb_prop_cut(double reach, double twin)
{
    return twin > 0 && reach > RF_RIG_PROP_REACH * twin ? twin : 0;
}

bool rf_rig_limb_place_within(const rf_rig_skel *k, rf_vec3 up, uint32_t girdle, uint32_t first,
                              rf_rig_limb_kind kind, const rf_rig_tpl_layout *l,
                              const double *start, double reach, double pos[4][3], double tip[3])
{
    rf_tpl_curve *c = malloc(sizeof *c);
    double f[4];
    if (!c || !rf_tpl_limb_curve(k, up, girdle, first, kind, l, start, reach, c, f)) {
        /* no curve to lay joints along: all at the first joint, as a point (defined, not used) */
        for (int i = 0; i < 4; i++)
            memcpy(pos[i], k->pos + (size_t)first * 3, 3 * sizeof(double));
        memcpy(tip, pos[3], 3 * sizeof(double));
        free(c);
        return false;
    }
    for (int i = 0; i < 4; i++)
        rf_tpl_at(c, f[i], pos[i]);
    rf_tpl_at(c, 1, tip);
    free(c);
    return true;
}

bool rf_rig_limb_place(const rf_rig_skel *k, rf_vec3 up, uint32_t girdle, uint32_t first,
                       rf_rig_limb_kind kind, const rf_rig_tpl_layout *l, const double *start,
                       double pos[4][3], double tip[3])
{
    return rf_rig_limb_place_within(k, up, girdle, first, kind, l, start, 0, pos, tip);
}

static double rf_tpl_up(const double p[3], rf_vec3 up)
{
    return p[0] * up.x + p[1] * up.y + p[2] * up.z;
}

#define RF_TPL_CHEST_RISE 0.25 /* of the laid trunk's rise: arms leaving that far below */

/* Where an arm leaving the curve skeleton well below its first joint starts instead: on the
 * laid trunk (Hips up to the Neck) at the height of the arm's first joint, as the general
 * rigger's chest joint (rf_rig_chest in rig.c) hangs its arms. The curve skeleton's bands may
 * meet a robot's arms only where a coarse trunk bone starts, a third of its height below its
 * shoulders, and laid from there the elbow took the turn at the shoulder. True with the point
 * in at[] when the girdle lies more than RF_TPL_CHEST_RISE of the trunk's rise below the arm's
 * first joint and that height is on the trunk. */
static bool rf_tpl_chest_at(const rf_tpl_ctx *x, uint32_t girdle, uint32_t first, double at[3])
{
    const rf_tpl *t = x->t;
    rf_vec3 up = x->a->up;
    uint32_t a = t->trunk, e = t->trunk + t->trunk_count - 1;
    if (!x->human || t->trunk_count < 2 || e >= t->n)
        return false;
    double h = rf_tpl_height(x->k, first, up), lo = rf_tpl_up(t->pos[a], up),
           hi = rf_tpl_up(t->pos[e], up);
    if (hi - lo <= 0 || h - rf_tpl_height(x->k, girdle, up) < RF_TPL_CHEST_RISE * (hi - lo))
        return false;
    for (uint32_t j = a; j < e; j++) { /* the trunk is a chain, parents first */
        double y0 = rf_tpl_up(t->pos[j], up), y1 = rf_tpl_up(t->pos[j + 1], up);
        if (y1 <= y0 || h < y0 || h > y1)
            continue;
        double f = (h - y0) / (y1 - y0);
        for (int c = 0; c < 3; c++)
            at[c] = t->pos[j][c] + f * (t->pos[j + 1][c] - t->pos[j][c]);
        return true;
    }
    return false;
}

/* Where the curve of a limb from `girdle` through its first joint `first` starts: on the laid
 * trunk for a humanoid's arm leaving the curve skeleton well below its first joint
 * (rf_tpl_chest_at, into at[]), else at the girdle (NULL). */
static const double *rf_tpl_limb_start(const rf_tpl_ctx *x, uint32_t girdle, uint32_t first,
                                       rf_rig_limb_kind kind, double at[3])
{
    return kind == RF_RIG_LIMB_ARM && rf_tpl_chest_at(x, girdle, first, at) ? at : NULL;
}

/* A mirrored pair of limbs of `kind` (sections sec[0], sec[1]) laid along their curves from
 * `girdle` and named, from the girdle down: a leg's thigh, shin, foot and toe, or an arm's (a
 * foreleg's) clavicle, upper arm, forearm and hand; sec[s] takes side s ^ swap's names. The
 * general rigger's limb rules: a limb reaching far past its twin is laid only as far as the twin
 * reaches (rf_rig_limb_prop_cut), an arm hanging beside the trunk gets its shoulder where the
 * trunk's width says (rf_rig_shoulder). A foreleg's curve, as a leg's, leaves out what rises
 * above its girdle. Out of memory sets x->oom. */
static void rf_tpl_lay_pair(rf_tpl_ctx *x, const int32_t sec[2], int swap, uint32_t girdle,
                            int32_t parent, rf_rig_limb_kind kind)
{
    static const char *const leg[4] = {"UpLeg", "Leg", "Foot", "ToeBase"};
    static const char *const arm[4] = {"Shoulder", "Arm", "ForeArm", "Hand"};
    bool is_leg = kind == RF_RIG_LIMB_LEG || kind == RF_RIG_LIMB_HIND_LEG;
    double at[2][3], reach[2];
    const double *start[2];
    uint32_t first[2];
    for (int s = 0; s < 2; s++) {
        uint32_t g;
        rf_tpl_ends(x->a, sec[s], &g, &first[s]);
        start[s] = rf_tpl_limb_start(x, girdle, first[s], kind, at[s]);
        if (!rf_rig_limb_reach(x->k, x->a->up, girdle, first[s], kind, start[s], &reach[s])) {
            x->oom = true;
            return;
        }
    }
    for (int s = 0; s < 2; s++) {
        double pos[4][3], tip[3], cut = rf_rig_limb_prop_cut(reach[s], reach[1 - s]);
        rf_rig_tpl_layout lay; /* a wing: elbow and wrist where wings have them */
        rf_rig_wing_layout(x->lay, rf_rig_is_wing(kind, cut > 0 ? cut : reach[s], x->legs), &lay);
        if (!rf_rig_limb_place_within(x->k, x->a->up, girdle, first[s], kind, &lay, start[s], cut,
                                      pos, tip)) {
            x->oom = true;
            return;
        }
        if (kind == RF_RIG_LIMB_ARM && x->sf)
            rf_rig_shoulder(x->sf, x->p->longest, rf_v3_normalize(x->a->up),
                            start[s] ? start[s] : x->k->pos + (size_t)girdle * 3, &lay, pos);
        char nb[24];
        int32_t j = parent;
        for (int i = 0; i < 4; i++)
            j = rf_tpl_joint(x->t, rf_tpl_sided(nb, s ^ swap, is_leg ? leg[i] : arm[i]), j, pos[i]);
        rf_tpl_tip(x->t, j, tip);
    }
}

/* Flags the joints of the limbs the template uses, and everything below them. False when out of
 * memory (a leg's rising branch left marked would hide the way to a head merged into it). */
static bool rf_tpl_mark_limbs(const rf_rig_skel *k, const rf_analysis *a, const rf_tpl_body *b,
                              rf_rig_template_kind kind, uint8_t *limb)
{
    int32_t secs[4];
    uint32_t n = 0;
    bool quadruped = kind == RF_RIG_TEMPLATE_QUADRUPED;
    for (int side = 0; side < 2; side++)
        secs[n++] = b->leg[0][side], secs[n++] = quadruped ? b->leg[1][side] : b->arm[0][side];
    for (uint32_t i = 0; i < n; i++) {
        if (secs[i] < 0)
            continue;
        const uint32_t *js = rf_section_joints(a, (uint32_t)secs[i]);
        for (uint32_t m = 0; m < a->sections[secs[i]].bone_count; m++)
            limb[js[m]] = 1;
    }
    for (uint32_t j = 0; j < k->n; j++)
        if (k->parent[j] >= 0 && limb[k->parent[j]])
            limb[j] = 1;
    uint8_t *above = calloc(k->n + 1, 1);
    bool ok = above != NULL;
    for (uint32_t p = 0; ok && p < 2; p++) /* legs: what rises above the girdle is no leg */
        for (int side = 0; ok && side < 2; side++) {
            int32_t sec = b->leg[p][side];
            if (sec < 0)
                continue;
            uint32_t first = rf_section_joints(a, (uint32_t)sec)[0];
            int32_t g = a->sections[sec].attach_joint;
            ok = rf_tpl_rising(k, a->up, g >= 0 ? (uint32_t)g : first, first, above);
        }
    for (uint32_t j = 0; ok && j < k->n; j++)
        limb[j] = limb[j] && !above[j];
    /* and the stem the leg shares with it, so the way to the head is open */
    for (uint32_t j = 0; ok && j < k->n; j++)
        if (above[j])
            for (int32_t p = k->parent[j]; p >= 0 && limb[p]; p = k->parent[p])
                limb[p] = 0;
    free(above);
    return ok;
}

/* Flags the joints on the tree path from a to b, b included and a not. */
static void rf_tpl_block_path(const rf_rig_skel *k, uint32_t a, uint32_t b, uint8_t *block)
{
    uint32_t m = rf_tpl_meet(k, a, b);
    for (int32_t j = (int32_t)b; j >= 0 && (uint32_t)j != m; j = k->parent[j])
        block[j] = 1;
    for (int32_t j = (int32_t)a; j >= 0 && (uint32_t)j != m; j = k->parent[j])
        block[j] = 1;
    if (m != a)
        block[m] = 1;
    block[a] = 0;
}

/* Whether joint j lies on the tree path from a to b. */
static bool rf_tpl_on_path(const rf_rig_skel *k, uint32_t a, uint32_t b, uint32_t j)
{
    uint32_t m = rf_tpl_meet(k, a, b);
    for (int32_t i = (int32_t)a; i >= 0; i = k->parent[i]) {
        if ((uint32_t)i == j)
            return true;
        if ((uint32_t)i == m)
            break;
    }
    for (int32_t i = (int32_t)b; i >= 0 && (uint32_t)i != m; i = k->parent[i])
        if ((uint32_t)i == j)
            return true;
    return false;
}

/* The body's centre line. The head is the leaf farthest from the chest (where the arms or
 * forelegs leave) that is no limb, not reached through the hips; the spine runs from the hips to
 * where the way to the head leaves the way to the chest (the chest itself, unless the forelegs
 * hang off the neck, as on some box models), then neck and head to that leaf. Returns Spine2,
 * or -1 when there is no head or memory ran out (x->oom set); the neck's base into *neck. */
static int32_t rf_tpl_trunk(rf_tpl_ctx *x, uint32_t hips, uint32_t chest, int32_t *hips_j,
                            uint32_t *neck)
{
    double neck_at = x->lay->neck_at, neck_f = x->lay->head;
    const rf_rig_skel *k = x->k;
    rf_tpl_curve sp = {0}, hd = {0};
    uint8_t *skip = malloc(k->n + 1);
    if (!skip) {
        x->oom = true;
        return -1;
    }
    /* beyond the chest, away from the whole way back to the hips, first (a tail leaving the
     * spine near the hips may reach farther than the head); through that way only when nothing
     * of a head's size lies beyond */
    memcpy(skip, x->limb, k->n);
    rf_tpl_block_path(k, chest, hips, skip);
    skip[hips] = 1;
    rf_tpl_path(k, hips, chest, &sp);
    double reach, least = 0.15 * rf_tpl_len(&sp);
    const rf_vec3 *up = x->human ? &x->up : NULL;
    uint32_t leaf;
    bool ok = rf_tpl_far_any(k, chest, skip, up, least, &leaf, &reach);
    if (ok && (leaf == chest || reach < least)) {
        memcpy(skip, x->limb, k->n);
        skip[hips] = 1;
        ok = rf_tpl_far_any(k, chest, skip, up, least, &leaf, &reach);
    }
    sp.n = 0;
    free(skip);
    x->oom = x->oom || !ok;
    if (!ok || (leaf == chest && !k->has_tip[chest]))
        return -1;
    *neck = chest;
    for (int32_t j = (int32_t)chest; j >= 0; j = k->parent[j]) /* chest up to the meeting */
        if (rf_tpl_on_path(k, hips, leaf, (uint32_t)j)) {
            *neck = (uint32_t)j;
            break;
        }
    if (!rf_tpl_on_path(k, hips, leaf, *neck)) /* the way to the head goes down from the chest */
        *neck = chest;
    rf_tpl_path(k, hips, *neck, &sp);
    rf_tpl_path(k, *neck, leaf, &hd);
    rf_tpl_add(&hd, rf_tpl_end(k, leaf));
    if (rf_tpl_len(&sp) < 0.25 * rf_tpl_len(&hd)) {
        /* the arms leave where the legs do (a short torso, a box body): the spine takes the
         * first part of the centre line, hips to head, as far as the template's neck */
        rf_tpl_curve all = {0};
        rf_tpl_path(k, hips, leaf, &all);
        rf_tpl_add(&all, rf_tpl_end(k, leaf));
        rf_tpl_sub(&all, 0, neck_at, &sp);
        rf_tpl_sub(&all, neck_at, 1, &hd);
    }
    if (rf_tpl_len(&hd) < 0.25 * rf_tpl_len(&sp) || hd.n < 2 || sp.n < 2)
        return -1;
    double p[3];
    rf_tpl_at(&sp, 0, p);
    int32_t h = rf_tpl_joint(x->t, "Hips", -1, p);
    const char *const sn[3] = {"Spine", "Spine1", "Spine2"};
    const double *sf = x->lay->spine;
    int32_t j = h;
    for (int i = 0; i < 3; i++) {
        rf_tpl_at(&sp, sf[i], p);
        j = rf_tpl_joint(x->t, sn[i], j, p);
    }
    int32_t spine2 = j;
    const char *const hn[2] = {"Neck", "Head"};
    const double hf[2] = {0, neck_f};
    x->t->head = rf_tpl_chain(x->t, &hd, spine2, hn, hf, 2) + 1; /* Neck, then Head */
    x->t->trunk = (uint32_t)h, x->t->trunk_count = (uint32_t)(spine2 - h) + 2;
    *hips_j = h;
    return spine2;
}

/* A tail: the farthest leaf from the hips that is no limb, leaving the hips or the spine's
 * first third (a box cat's tail leaves above its hips) and not the way on to the neck, when it
 * reaches at least a quarter of the spine's length beyond where it leaves. Out of memory sets
 * x->oom (no tail looked for is no answer). */
static void rf_tpl_tail(rf_tpl_ctx *x, uint32_t hips, uint32_t neck, int32_t hips_j)
{
    const rf_rig_skel *k = x->k;
    uint8_t *skip = malloc(k->n + 1), *spine = calloc(k->n + 1, 1);
    rf_tpl_curve sp = {0}, c = {0};
    rf_tpl_path(k, hips, neck, &sp);
    double len = rf_tpl_len(&sp);
    if (!skip || !spine) {
        free(skip), free(spine);
        x->oom = true;
        return;
    }
    memcpy(skip, x->limb, k->n);
    rf_tpl_block_path(k, hips, neck, spine);
    for (uint32_t j = 0; j < k->n; j++) { /* the spine beyond its first third is blocked */
        if (!spine[j])
            continue;
        rf_tpl_curve to = {0};
        rf_tpl_path(k, hips, j, &to);
        skip[j] = skip[j] || rf_tpl_len(&to) > len / 3;
    }
    double reach;
    uint32_t leaf;
    if (!rf_tpl_far_any(k, hips, skip, NULL, 0, &leaf, &reach)) {
        free(skip), free(spine);
        x->oom = true;
        return;
    }
    uint32_t from = leaf;
    while (from != hips && !spine[from] && k->parent[from] >= 0) /* where it leaves the spine */
        from = (uint32_t)k->parent[from];
    if (!spine[from] && from != hips)
        from = hips;
    free(skip), free(spine);
    if (leaf == hips)
        return;
    rf_tpl_path(k, from, leaf, &c);
    rf_tpl_add(&c, rf_tpl_end(k, leaf));
    if (rf_tpl_len(&c) < 0.25 * len)
        return;
    const char *const tn[4] = {"Tail", "Tail1", "Tail2", "Tail3"};
    const double *tf = x->lay->tail;
    rf_tpl_chain(x->t, &c, hips_j, tn, tf, 4);
}

static bool rf_tpl_humanoid(rf_tpl_ctx *x, char *err, size_t n)
{
    const rf_tpl_body *b = x->b;
    uint32_t gl[2], ga[2], first;
    for (int s = 0; s < 2; s++) {
        rf_tpl_ends(x->a, b->leg[0][s], &gl[s], &first);
        rf_tpl_ends(x->a, b->arm[0][s], &ga[s], &first);
    }
    uint32_t hips = rf_tpl_meet(x->k, gl[0], gl[1]), chest = rf_tpl_meet(x->k, ga[0], ga[1]);
    uint32_t neck;
    int32_t hips_j = -1, spine2 = rf_tpl_trunk(x, hips, chest, &hips_j, &neck);
    if (spine2 < 0 && !x->oom)
        return rf_rig_fail(err, n,
                           "the humanoid template found no neck and head above the "
                           "shoulders");
    int swap = x->facing == 1;
    for (int s = 0; s < 2 && !x->oom; s++) { /* the legs' reach, which tells a wing */
        uint32_t g, leg;
        double r = 0;
        rf_tpl_ends(x->a, b->leg[0][s], &g, &leg);
        x->oom = !rf_rig_limb_reach(x->k, x->a->up, hips, leg, RF_RIG_LIMB_LEG, NULL, &r);
        x->legs = fmax(x->legs, r);
    }
    if (!x->oom)
        rf_tpl_lay_pair(x, b->arm[0], swap, chest, spine2, RF_RIG_LIMB_ARM);
    if (!x->oom)
        rf_tpl_lay_pair(x, b->leg[0], swap, hips, hips_j, RF_RIG_LIMB_LEG);
    return !x->oom || rf_rig_fail(err, n, "out of memory laying the humanoid template");
}

/* Length of the tree path from the root (joint 0: parents come first) to joint j. */
static double rf_tpl_from_root(const rf_rig_skel *k, uint32_t j)
{
    rf_tpl_curve c = {0};
    rf_tpl_path(k, 0, j, &c);
    return rf_tpl_len(&c);
}

static bool rf_tpl_quadruped(rf_tpl_ctx *x, bool declared, char *err, size_t n)
{
    const rf_tpl_body *b = x->b;
    uint32_t g[2][2], first;
    for (int p = 0; p < 2; p++)
        for (int s = 0; s < 2; s++)
            rf_tpl_ends(x->a, b->leg[p][s], &g[p][s], &first);
    uint32_t chest = rf_tpl_meet(x->k, g[0][0], g[0][1]),
             hips = rf_tpl_meet(x->k, g[1][0], g[1][1]);
    /* Without a forward the file declares, which end is the front is the analysis's weakest
     * guess, so the body's facing read on the grid's quarter turns decides (rf_tpl_facing);
     * without that either, the curve skeleton is rooted at the hips (the girdle farther from the
     * body's middle, rf_rig_curve), so the girdle nearer the root is the hips (the Fox without
     * its axes, rooted at its chest, was read facing back so). Swapping the ends swaps the sides
     * too. */
    int front = x->facing == 1 || (!declared && x->facing < 0 &&
                                   rf_tpl_from_root(x->k, chest) < rf_tpl_from_root(x->k, hips));
    if (front) {
        uint32_t t = chest;
        chest = hips, hips = t;
    }
    x->swap = front;
    if (hips == chest)
        return rf_rig_fail(err, n,
                           "the quadruped template found the fore and hind legs "
                           "leaving the body at one place (no spine between them)");
    uint32_t neck;
    int32_t hips_j = -1, spine2 = rf_tpl_trunk(x, hips, chest, &hips_j, &neck);
    if (spine2 < 0 && !x->oom)
        return rf_rig_fail(err, n,
                           "the quadruped template found no neck and head beyond the "
                           "forelegs");
    if (!x->oom)
        rf_tpl_tail(x, hips, neck, hips_j);
    if (!x->oom)
        rf_tpl_lay_pair(x, b->leg[front], front, chest, spine2, RF_RIG_LIMB_FORELEG);
    if (!x->oom)
        rf_tpl_lay_pair(x, b->leg[1 - front], front, hips, hips_j, RF_RIG_LIMB_HIND_LEG);
    if (x->oom)
        return rf_rig_fail(err, n, "out of memory laying the quadruped template");
    const double *hp = x->k->pos + (size_t)hips * 3, *cp = x->k->pos + (size_t)chest * 3;
    x->forward = rf_v3(cp[0] - hp[0], cp[1] - hp[1], cp[2] - hp[2]);
    return true;
}

/* Which template the body fits, or false with why not. */
static bool rf_tpl_pick(const rf_tpl_body *b, rf_rig_template_kind want, rf_rig_template_kind *got,
                        char *err, size_t n)
{
    bool two_legs = b->leg_pairs == 1 && b->legs[0] + b->legs[1] == 2;
    bool four_legs = b->leg_pairs == 2 && b->legs[0] + b->legs[1] == 4;
    bool two_arms = b->arm_pairs >= 1;
    char found[200];
    snprintf(found, sizeof found,
             "the skeleton analysis of its curve skeleton found %u left, %u right and %u "
             "unpaired legs (%u mirrored pairs), %u left, %u right and %u unpaired arms (%u "
             "pairs)",
             b->legs[0], b->legs[1], b->legs[2], b->leg_pairs, b->arms[0], b->arms[1], b->arms[2],
             b->arm_pairs);
    if ((want == RF_RIG_TEMPLATE_AUTO || want == RF_RIG_TEMPLATE_HUMANOID) && two_legs &&
        two_arms) {
        *got = RF_RIG_TEMPLATE_HUMANOID;
        return true;
    }
    /* A pair of wings besides four legs (a dragon's) is no part of the quadruped template: laid
     * without them, its tail went along a wing and the wings hung from the spine and the tail,
     * torn apart under a walk (random dragons: torn p99 median 73% of the height). */
    if ((want == RF_RIG_TEMPLATE_AUTO || want == RF_RIG_TEMPLATE_QUADRUPED) && four_legs &&
        b->wing_pairs)
        return rf_rig_fail(err, n,
                           "the body fits no template: %s; a pair of its arms are wings (over "
                           "twice as long as its legs), which the quadruped template has not",
                           found);
    if ((want == RF_RIG_TEMPLATE_AUTO || want == RF_RIG_TEMPLATE_QUADRUPED) && four_legs) {
        *got = RF_RIG_TEMPLATE_QUADRUPED;
        return true;
    }
    const char *need = want == RF_RIG_TEMPLATE_HUMANOID ? "a humanoid needs a pair of legs and a "
                                                          "pair of arms"
                       : want == RF_RIG_TEMPLATE_QUADRUPED
                           ? "a quadruped needs two pairs of legs"
                           : "a humanoid needs a pair of legs and a pair of arms, a quadruped "
                             "two pairs of legs";
    return rf_rig_fail(err, n, "the body fits no template: %s; %s", found, need);
}

/* The template as a working skeleton. */
static bool rf_tpl_to_skel(const rf_tpl *t, rf_rig_skel *k)
{
    memset(k, 0, sizeof *k);
    k->n = t->n;
    k->pos = malloc((t->n + 1) * 3 * sizeof *k->pos);
    k->tip = calloc((t->n + 1) * 3, sizeof *k->tip);
    k->parent = malloc((t->n + 1) * sizeof *k->parent);
    k->has_tip = calloc(t->n + 1, 1);
    if (!k->pos || !k->tip || !k->parent || !k->has_tip) {
        rf_rig_skel_free(k);
        return false;
    }
    for (uint32_t j = 0; j < t->n; j++) {
        memcpy(k->pos + (size_t)j * 3, t->pos[j], 3 * sizeof(double));
        memcpy(k->tip + (size_t)j * 3, t->tip[j], 3 * sizeof(double));
        k->has_tip[j] = t->has_tip[j];
        k->parent[j] = t->parent[j];
    }
    return true;
}

/* Whether the analysis a faces back against `facing`, the body's facing read on its skeletons
 * on the grid turned every quarter way, pooled (rf_rig_pooled_facing), as the general rigger
 * names its rig: 1 when it does (the template's sides and ends are then swapped), 0 when not, -1
 * when no facing was read. This one grid's curve skeleton alone reads a facing that flips with
 * where the voxel boundaries fall (BCN_Epileptic and the animalia bird turned a quarter way, the
 * Fox without its axes: read facing back), and the sides with it. The analysis keeps its own
 * mirror plane and limbs: read again with its forward forced either way, it paired no limbs of
 * the bat or the ninja. A biped's facing declared by its file stands (rf_tpl_embed): the
 * general rigger's reading of a declared one (rf_rig_placed_facing) only swaps a quadruped's
 * ends. */
static int rf_tpl_facing(const rf_analysis *a, rf_vec3 facing)
{
    return !(rf_v3_len(facing) > 0) ? -1 : rf_v3_dot(a->forward, facing) < 0;
}

/* The template laid into the curve skeleton k, into t. */
static bool rf_tpl_embed(const rf_rig_prep *p, const rf_rig_skel *k, const rf_rig_options *o,
                         rf_vec3 facing, rf_rig_template_kind want, const rf_rig_tpl_layout *lay[2],
                         rf_tpl *t, rf_rig_template_kind *kind, rf_vec3 *up, rf_vec3 *forward,
                         char *err, size_t n)
{
    rf_skeleton *s = rf_rig_skeleton(k, NULL);
    if (!s)
        return rf_rig_fail(err, n, "out of memory");
    s->up = o->up, s->forward = o->forward; /* hints, as a file's axes are */
    bool declared = rf_v3_len(o->forward) > 0;
    rf_analysis *a = rf_analyze(s, NULL);
    uint8_t *limb = calloc(k->n + 1, 1);
    bool ok = a && limb;
    if (!ok)
        rf_rig_fail(err, n, "out of memory");
    rf_tpl_body b;
    rf_rig_template_kind got = RF_RIG_TEMPLATE_AUTO;
    if (ok && !rf_tpl_limbs(a, &b))
        ok = rf_rig_fail(err, n, "out of memory pairing the limbs");
    ok = ok && rf_tpl_pick(&b, want, &got, err, n);
    if (ok && !rf_tpl_mark_limbs(k, a, &b, got, limb))
        ok = rf_rig_fail(err, n, "out of memory marking the limbs");
    if (ok) {
        bool human = got == RF_RIG_TEMPLATE_HUMANOID;
        rf_tpl_ctx x = {.k = k,
                        .a = a,
                        .b = &b,
                        .t = t,
                        .limb = limb,
                        .lay = lay[!human],
                        .human = human,
                        .up = rf_v3_len(o->up) > 0 ? o->up : a->up,
                        .p = p,
                        .facing = declared && human ? -1 : rf_tpl_facing(a, facing),
                        .sf = p && human ? rf_rig_surface_make(&p->proxy) : NULL};
        *kind = got;
        memset(t, 0, sizeof *t);
        if (p && human && !x.sf) /* the shoulders would stay where the curve has them */
            ok = rf_rig_fail(err, n, "out of memory");
        else
            ok = got == RF_RIG_TEMPLATE_HUMANOID ? rf_tpl_humanoid(&x, err, n)
                                                 : rf_tpl_quadruped(&x, declared, err, n);
        rf_rig_surface_free(x.sf);
        *up = rf_v3_len(o->up) > 0 ? o->up : a->up;
        /* the quadruped's forward, hips to chest, made level */
        rf_vec3 f = x.forward;
        double along = f.x * up->x + f.y * up->y + f.z * up->z;
        f = rf_v3(f.x - along * up->x, f.y - along * up->y, f.z - along * up->z);
        *forward = declared                       ? o->forward
                   : x.facing >= 0                ? rf_v3_scale(a->forward, x.facing ? -1 : 1)
                   : rf_v3_len(f) > 0             ? rf_v3_scale(f, 1 / rf_v3_len(f))
                   : a->forward_confidence >= 0.3 ? a->forward
                                                  : rf_v3(0, 0, 0);
    }
    free(limb);
    rf_analysis_free(a);
    rf_skeleton_free(s);
    return ok;
}

static bool rf_tpl_name(rf_skeleton *s, char (*names)[24], uint32_t n, rf_vec3 up, rf_vec3 forward)
{
    free(s->name);
    if (!(s->name = rf_strdup("rig.template")))
        return false;
    for (uint32_t j = 0; j < n; j++)
        if (!(s->joints[j].name = rf_strdup(names[j])))
            return false;
    s->up = up, s->forward = forward;
    return true;
}

/* The general rigger's head rule on the laid template. Its Head lies along the way from the
 * neck's base to the head's top, inside a head wider than the neck (a robot's head box): bone
 * heat split the box between Neck and Head, and the CMU walk's neck drew its lower rim down to
 * the chest. The Head moves down to where the head's bulk starts (rf_rig_head_base, as the
 * general rigger's first head joint does). False when out of memory. */
static bool rf_tpl_head(const rf_rig_prep *p, rf_rig_skel *k, const rf_tpl *t, rf_vec3 up,
                        rf_vec3 fwd)
{
    return !(t->head > 0 && (uint32_t)t->head < k->n) ||
           rf_rig_head_base(p, k, (uint32_t)t->head, up, fwd);
}

bool rf_rig_template_place(const rf_rig_prep *p, const rf_rig_skel *k, const rf_rig_options *o,
                           rf_vec3 facing, rf_rig_template_kind want,
                           const rf_rig_tpl_layout *humanoid, const rf_rig_tpl_layout *quadruped,
                           rf_rig_skel *out, char (*names)[24], rf_rig_template_kind *got,
                           rf_vec3 *up, rf_vec3 *forward, char *err, size_t n)
{
    const rf_rig_tpl_layout *lay[2] = {humanoid ? humanoid : &rf_rig_tpl_humanoid,
                                       quadruped ? quadruped : &rf_rig_tpl_quadruped};
    rf_tpl *t = calloc(1, sizeof *t);
    if (!t)
        return rf_rig_fail(err, n, "out of memory");
    bool ok = rf_tpl_embed(p, k, o, facing, want, lay, t, got, up, forward, err, n);
    if (ok && !rf_tpl_to_skel(t, out))
        ok = rf_rig_fail(err, n, "out of memory");
    if (ok) {
        bool human = *got == RF_RIG_TEMPLATE_HUMANOID;
        const rf_rig_tpl_layout *l = lay[!human];
        if (l->centre && !rf_rig_skel_centre(p, out))
            ok = rf_rig_fail(err, n, "out of memory");
        /* the spine lies towards the back: a quadruped's up, a biped's back (when known) */
        rf_vec3 back = human ? rf_v3_scale(*forward, -1) : *up;
        uint8_t trunk[RF_TPL_MAXJ] = {0};
        for (uint32_t j = t->trunk; j < t->trunk + t->trunk_count && j < t->n; j++)
            trunk[j] = 1;
        if (ok && l->dorsal > 0 && rf_v3_len(back) > 0 &&
            !rf_rig_skel_across(p, out, trunk, back, l->dorsal))
            ok = rf_rig_fail(err, n, "out of memory");
        /* the head left inside its bulk would be a rig unlike the one with memory to spare */
        if (ok && !rf_tpl_head(p, out, t, *up, *forward))
            ok = rf_rig_fail(err, n, "out of memory placing the head");
        for (uint32_t j = 0; ok && j < t->n; j++)
            memcpy(names[j], t->name[j], 24);
        if (!ok)
            rf_rig_skel_free(out);
    }
    free(t);
    return ok;
}

static bool rf_rig_template_framed(const rf_mesh *mesh, const rf_rig_options *opts,
                                   rf_rig_template_kind kind, rf_skeleton **skeleton,
                                   rf_mesh **skinned, rf_rig_stats *stats,
                                   rf_rig_progress_fn progress, void *user, char *err,
                                   size_t err_size)
{
    rf_rig_options o = rf_rig_defaults(opts);
    o.keep_joints = true; /* the template's named joints all stay, each with skin */
    rf_rig_stats st_local, *st = stats ? stats : &st_local;
    memset(st, 0, sizeof *st);
    *skeleton = NULL, *skinned = NULL;
    rf_rig_prep p;
    rf_rig_skel k = {0}, tk = {0};
    char names[RF_TPL_MAXJ][24];
    rf_rig_template_kind got = RF_RIG_TEMPLATE_AUTO;
    rf_vec3 up = rf_v3(0, 0, 0), forward = rf_v3(0, 0, 0);
    if (rf_rig_prepare(mesh, &o, &p, st, err, err_size) != RF_RIG_OK)
        return false;
    if (progress)
        progress(user, 0.1);
    bool ok = rf_rig_curve(&p, &o, &k, err, err_size) == RF_RIG_OK;
    /* a body faces the way the general rigger reads it: with no forward declared, its
     * skeletons on the grid turned every quarter way pooled (rf_rig_pooled_facing); with one,
     * its rig read with that forward as a hint (rf_rig_placed_facing), which a quadruped's
     * ends are laid by: the curve skeleton's hierarchy, not yet rooted behind the bulkier end
     * (rf_rig_root_hind), outvoted the elevation of its ends on 8 of 20 random quadrupeds */
    rf_vec3 facing = rf_v3(0, 0, 0);
    if (ok && !(rf_v3_len(o.forward) > 0) && !rf_rig_pooled_facing(&p, NULL, &o, &facing))
        ok = rf_rig_fail(err, err_size, "out of memory reading the body's facing");
    else if (ok && rf_v3_len(o.forward) > 0 && !rf_rig_placed_facing(&p, &k, &o, &facing))
        ok = rf_rig_fail(err, err_size, "out of memory reading the body's facing");
    ok = ok && rf_rig_template_place(&p, &k, &o, facing, kind, NULL, NULL, &tk, names, &got, &up,
                                     &forward, err, err_size);
    if (ok && progress)
        progress(user, 0.4);
    rf_skeleton *s = ok ? rf_rig_skeleton(&tk, NULL) : NULL;
    if (ok && (!s || !rf_tpl_name(s, names, tk.n, up, forward)))
        ok = rf_rig_fail(err, err_size, "out of memory writing the rig");
    ok = ok && rf_rig_weigh(mesh, &p, &tk, &o, s, skinned, st, err, err_size);
    if (ok)
        *skeleton = s;
    else
        rf_skeleton_free(s);
    rf_rig_skel_free(&k), rf_rig_skel_free(&tk);
    rf_rig_prep_free(&p);
    return ok;
}

/* Rigged in its own frame (rig-frame.c) and turned back, as rf_rig_general. */
bool rf_rig_template(const rf_mesh *mesh, const rf_rig_options *opts, rf_rig_template_kind kind,
                     rf_skeleton **skeleton, rf_mesh **skinned, rf_rig_stats *stats,
                     rf_rig_progress_fn progress, void *user, char *err, size_t err_size)
{
    rf_rig_frame f;
    rf_mesh in;
    rf_rig_options o;
    *skeleton = NULL, *skinned = NULL;
    if (!rf_rig_frame_enter(mesh, opts, &f, &in, &o))
        return rf_rig_fail(err, err_size, "out of memory turning a mesh of %u vertices",
                           mesh ? mesh->vertex_count : 0);
    bool ok = rf_rig_template_framed(mesh ? &in : NULL, &o, kind, skeleton, skinned, stats,
                                     progress, user, err, err_size);
    rf_rig_frame_stats(&f, stats);
    rf_rig_frame_leave(&f, mesh, ok ? *skeleton : NULL, ok ? *skinned : NULL);
    return ok;
}
