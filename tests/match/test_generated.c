/* Accuracy on random skeletons with ground truth known by construction (gen.h): bipeds,
 * quadrupeds and winged creatures with random bone counts, proportions, poses, scale, facing, up
 * axis, rig conventions, names and helpers, mapped onto each other. Prints the accuracy per kind
 * of pair and fails below the bars, or on any side swap; with $RF_DATA_DIR also CMU's skeleton
 * (labelled by hand below) onto generated bipeds, quadrupeds and dragons. RF_GEN_PAIRS sets the
 * pairs per kind (default 60); RF_GEN_VERBOSE=1 prints every wrong joint. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "gen.h"
#include "match-similarity/similarity.h"
#include "truth.h"

typedef struct kind {
    const char *name;
    int source; /* a gen_plan, or -1: CMU */
    gen_plan target;
    double bar;
    int swaps; /* side swaps as measured (0 but for CMU onto dragons: see doc/matching.md) */
} kind;

/* CMU's joints in this generator's labels, from their positions: the spine between Hips and
 * Spine1 in thirds, the neck in quarters, digits from the wrist (LeftFingerBase the finger's
 * first bone, LThumb the thumb). */
typedef struct cmu_label {
    const char *name;
    gen_label l;
} cmu_label;

#define GL(part, side, seg, digit, fingers, place)                                                 \
    {                                                                                              \
        part, side, seg, digit, fingers, false, place                                              \
    }
#define CMU_SIDE(L, S, side)                                                                       \
    {L "HipJoint", GL(GEN_HIND, side, 0, 0, 0, 0)}, {S "UpLeg", GL(GEN_HIND, side, 1, 0, 0, 0)},   \
        {S "Leg", GL(GEN_HIND, side, 2, 0, 0, 0)}, {S "Foot", GL(GEN_HIND, side, 3, 0, 0, 0)},     \
        {S "ToeBase", GL(GEN_HIND, side, 4, 0, 0, 0)},                                             \
        {S "Shoulder", GL(GEN_FORE, side, 0, 0, 0, 0)}, {S "Arm", GL(GEN_FORE, side, 1, 0, 0, 0)}, \
        {S "ForeArm", GL(GEN_FORE, side, 2, 0, 0, 0)}, {S "Hand", GL(GEN_FORE, side, 3, 0, 0, 0)}, \
        {S "FingerBase", GL(GEN_DIGIT, side, 1, 1, 2, 1)},                                         \
        {L "Fingers", GL(GEN_DIGIT, side, 2, 1, 2, 1)},                                            \
    {                                                                                              \
        L "Thumb", GL(GEN_DIGIT, side, 1, 0, 2, 0)                                                 \
    }

static const cmu_label cmu_labels[] = {
    {"Hips", GL(GEN_PELVIS, 0, 0, 0, 0, 0)},
    {"LowerBack", GL(GEN_SPINE, 0, 1, 0, 0, 1.0 / 3)},
    {"Spine", GL(GEN_SPINE, 0, 2, 0, 0, 2.0 / 3)},
    {"Spine1", GL(GEN_CHEST, 0, 3, 0, 0, 1)},
    {"Neck", GL(GEN_NECK, 0, 0, 0, 0, 0.25)},
    {"Neck1", GL(GEN_NECK, 0, 1, 0, 0, 0.75)},
    {"Head", GL(GEN_HEAD, 0, 0, 0, 0, 0)},
    CMU_SIDE("L", "Left", 1),
    CMU_SIDE("R", "Right", 2),
};

static bool cmu_gen(const char *data, gen_skel *g)
{
    struct stat st;
    memset(g, 0, sizeof *g);
    if (!data || stat(data, &st) != 0 || !(g->s = truth_load(data, "bvh/cmu_01_01.bvh")))
        return false;
    g->label = calloc(g->s->joint_count, sizeof *g->label);
    for (uint32_t j = 0; j < g->s->joint_count; j++) {
        size_t k = 0, n = sizeof cmu_labels / sizeof cmu_labels[0];
        while (k < n && strcmp(cmu_labels[k].name, g->s->joints[j].name))
            k++;
        if (k == n) {
            printf("CMU joint %s has no label\n", g->s->joints[j].name);
            gen_free(g);
            return false;
        }
        g->label[j] = cmu_labels[k].l;
    }
    g->plan = GEN_BIPED;
    return true;
}

static const char *const part_names[] = {"helper", "pelvis", "spine", "chest", "neck",
                                         "head",   "tail",   "fore",  "hind",  "digit",
                                         "wing",   "ground", "jaw",   "eye"};

static void explain_wrong(const gen_skel *t, const gen_skel *s, uint32_t j, int32_t got)
{
    const gen_label *l = &t->label[j];
    printf("    wrong: %s %s side %d seg %d digit %d place %.2f <- ", t->s->joints[j].name,
           part_names[l->part], l->side, l->seg, l->digit, l->place);
    if (got < 0)
        printf("(unmapped)\n");
    else
        printf("%s %s side %d seg %d digit %d place %.2f\n", s->s->joints[got].name,
               part_names[s->label[got].part], s->label[got].side, s->label[got].seg,
               s->label[got].digit, s->label[got].place);
}

/* Classes of joints, as the second generator's test reports them (test_rigs.c). */
enum { CLS_FINGERS, CLS_CHAINS, CLS_LIMBS, CLS_HELPERS, CLS_BODY, CLS_COUNT };
static const char *const class_names[CLS_COUNT] = {"fingers", "chains", "limbs", "helpers", "body"};

static int class_of(const gen_label *l)
{
    switch (l->part) {
    case GEN_HELPER:
    case GEN_GROUND:
        return CLS_HELPERS;
    case GEN_SPINE:
    case GEN_NECK:
    case GEN_TAIL:
        return CLS_CHAINS;
    case GEN_FORE:
    case GEN_HIND:
    case GEN_WING:
        return CLS_LIMBS;
    case GEN_DIGIT:
        return l->wing ? CLS_LIMBS : CLS_FINGERS;
    default:
        return CLS_BODY;
    }
}

/* Maps one random pair; adds its joints, right ones and swaps, per class too. */
static void one_pair(const kind *k, const gen_skel *cmu, uint64_t seed, int *joints, int *right,
                     int *swaps, int *cj, int *cr, bool verbose)
{
    gen_skel s = k->source >= 0 ? gen_make((gen_plan)k->source, seed * 2 + 1) : *cmu;
    gen_skel t = gen_make(k->target, seed * 2 + 2);
    char err[256];
    const rf_skeleton *src[1] = {s.s};
    rf_ms_options homology = {0}; /* the labels pair forelegs with arms, not the gait rule's */
    homology.forelegs_arms = true;
    rf_mapping *m = rf_ms_match(t.s, src, 1, &homology, NULL, err, sizeof err);
    for (uint32_t j = 0; m && j < t.s->joint_count; j++) {
        int32_t got = m->entries[j].input_count ? (int32_t)m->entries[j].inputs[0].joint : -1;
        bool ok = gen_accepts(&t, j, &s, got);
        *joints += 1, *right += ok;
        cj[class_of(&t.label[j])]++, cr[class_of(&t.label[j])] += ok;
        *swaps += gen_swapped(&t, j, &s, got);
        if (!ok && verbose)
            explain_wrong(&t, &s, j, got);
    }
    if (!m)
        printf("  seed %llu: %s\n", (unsigned long long)seed, err);
    rf_mapping_free(m);
    if (k->source >= 0)
        gen_free(&s);
    gen_free(&t);
}

int main(void)
{
    const kind kinds[] = {
        {"biped onto biped", GEN_BIPED, GEN_BIPED, 0.90, 0},
        {"quadruped onto quadruped", GEN_QUADRUPED, GEN_QUADRUPED, 0.85, 0},
        {"dragon onto dragon", GEN_DRAGON, GEN_DRAGON, 0.85, 0},
        {"biped onto quadruped", GEN_BIPED, GEN_QUADRUPED, 0.80, 0},
        {"quadruped onto biped", GEN_QUADRUPED, GEN_BIPED, 0.80, 0},
        {"CMU onto bipeds", -1, GEN_BIPED, 0.96, 0},
        {"CMU onto quadrupeds", -1, GEN_QUADRUPED, 0.97, 0},
        {"CMU onto dragons", -1, GEN_DRAGON, 0.63, 38},
    };
    gen_skel cmu;
    bool have_cmu = cmu_gen(getenv("RF_DATA_DIR"), &cmu);
    if (!have_cmu)
        printf("SKIP the CMU pairs: RF_DATA_DIR has no bvh/cmu_01_01.bvh\n");
    const char *env = getenv("RF_GEN_PAIRS");
    int pairs = env ? atoi(env) : 60;
    bool verbose = getenv("RF_GEN_VERBOSE") && strcmp(getenv("RF_GEN_VERBOSE"), "0") != 0;
    bool ok = true;
    int all_swaps = 0;
    for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; k++) {
        if (kinds[k].source < 0 && !have_cmu)
            continue;
        int joints = 0, right = 0, swaps = 0, cj[CLS_COUNT] = {0}, cr[CLS_COUNT] = {0};
        for (int p = 0; p < pairs; p++) {
            if (verbose)
                printf("  %s, seed %d\n", kinds[k].name, p);
            one_pair(&kinds[k], &cmu, (uint64_t)(1000 * k + p), &joints, &right, &swaps, cj, cr,
                     verbose);
        }
        double acc = joints ? (double)right / joints : 1;
        printf("%-26s %3d pairs %6d joints: %5.1f%% right (bar %.0f%%), %d sides swapped\n",
               kinds[k].name, pairs, joints, 100 * acc, 100 * kinds[k].bar, swaps);
        printf("   ");
        for (int c = 0; c < CLS_COUNT; c++)
            if (cj[c])
                printf(" %s %.1f%% (%d)", class_names[c], 100.0 * cr[c] / cj[c], cj[c]);
        printf("\n");
        ok = ok && acc >= kinds[k].bar;
        all_swaps += swaps > kinds[k].swaps;
    }
    if (have_cmu)
        gen_free(&cmu);
    return ok && all_swaps == 0 ? 0 : 1;
}
