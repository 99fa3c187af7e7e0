/* Accuracy on random skeletons with ground truth known by construction (gen.h): bipeds,
 * quadrupeds and winged creatures with random bone counts, proportions, poses, scale, facing, up
 * axis, rig conventions, names and helpers, mapped onto each other. Prints the accuracy per kind
 * of pair and fails below the bars, or on any side swap. RF_GEN_PAIRS sets the pairs per kind
 * (default 60); RF_GEN_VERBOSE=1 prints every wrong joint. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gen.h"
#include "match-similarity/similarity.h"

typedef struct kind {
    const char *name;
    gen_plan source, target;
    double bar;
} kind;

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
static void one_pair(const kind *k, uint64_t seed, int *joints, int *right, int *swaps, int *cj,
                     int *cr, bool verbose)
{
    gen_skel s = gen_make(k->source, seed * 2 + 1), t = gen_make(k->target, seed * 2 + 2);
    char err[256];
    const rf_skeleton *src[1] = {s.s};
    rf_mapping *m = rf_ms_match(t.s, src, 1, NULL, NULL, err, sizeof err);
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
    gen_free(&s);
    gen_free(&t);
}

int main(void)
{
    const kind kinds[] = {
        {"biped onto biped", GEN_BIPED, GEN_BIPED, 0.90},
        {"quadruped onto quadruped", GEN_QUADRUPED, GEN_QUADRUPED, 0.85},
        {"dragon onto dragon", GEN_DRAGON, GEN_DRAGON, 0.85},
        {"biped onto quadruped", GEN_BIPED, GEN_QUADRUPED, 0.80},
        {"quadruped onto biped", GEN_QUADRUPED, GEN_BIPED, 0.80},
    };
    const char *env = getenv("RF_GEN_PAIRS");
    int pairs = env ? atoi(env) : 60;
    bool verbose = getenv("RF_GEN_VERBOSE") && strcmp(getenv("RF_GEN_VERBOSE"), "0") != 0;
    bool ok = true;
    int all_swaps = 0;
    for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; k++) {
        int joints = 0, right = 0, swaps = 0, cj[CLS_COUNT] = {0}, cr[CLS_COUNT] = {0};
        for (int p = 0; p < pairs; p++) {
            if (verbose)
                printf("  %s, seed %d\n", kinds[k].name, p);
            one_pair(&kinds[k], (uint64_t)(1000 * k + p), &joints, &right, &swaps, cj, cr, verbose);
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
        all_swaps += swaps;
    }
    return ok && all_swaps == 0 ? 0 : 1;
}
