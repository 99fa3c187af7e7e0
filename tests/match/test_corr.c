/* Accuracy against joint name maps that others made (../shared/data/correspondences), so the
 * figures do not rest on this project's own truth files alone:
 *   - bvh/cmu_01_01.bvh is labelled by retarget-bvh's Motionbuilder map (its naming scheme),
 *   - bvh/boxing_toes.bvh by retarget-bvh's CMU map (LeftCollar, LeftHip...),
 *   - models/vrm_sample.glb by the file's own VRM humanoid map.
 * A joint is scored where both skeletons carry the same label among the ones every map agrees
 * on: hips and the limbs (shoulder, upper arm, forearm, hand, thigh, shin, foot, toe). Spine and
 * neck labels are left out: the maps cut those chains differently (Motionbuilder calls CMU's
 * Neck1 the head). Every ordered pair of the three skeletons is mapped by the matcher with its
 * defaults; the test fails below 95% or on a swapped side. It also checks the hand-written
 * tests/match/truth/boxing-cmu.truth against the maps. Skips (exit 77) without the data. */
#define _POSIX_C_SOURCE 200809L
#include <jansson.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "match-similarity/similarity.h"
#include "truth.h"

#define CORR_BAR 0.95

/* The labels scored, in retarget-bvh's canonical names, with the VRM humanoid names of the same
 * bones (a naming equivalence read from both specifications, not a mapping result). */
static const char *const labels[][2] = {
    {"hips", "hips"},
    {"shoulder.L", "leftShoulder"},
    {"upper_arm.L", "leftUpperArm"},
    {"forearm.L", "leftLowerArm"},
    {"hand.L", "leftHand"},
    {"thigh.L", "leftUpperLeg"},
    {"shin.L", "leftLowerLeg"},
    {"foot.L", "leftFoot"},
    {"toe.L", "leftToes"},
    {"shoulder.R", "rightShoulder"},
    {"upper_arm.R", "rightUpperArm"},
    {"forearm.R", "rightLowerArm"},
    {"hand.R", "rightHand"},
    {"thigh.R", "rightUpperLeg"},
    {"shin.R", "rightLowerLeg"},
    {"foot.R", "rightFoot"},
    {"toe.R", "rightToes"},
};
#define LABEL_COUNT ((int)(sizeof labels / sizeof labels[0]))

typedef struct labelled {
    const char *file; /* under RF_DATA_DIR */
    const char *map;  /* under RF_DATA_DIR/correspondences */
    bool vrm;         /* the map goes VRM name -> joint, else joint -> canonical */
    rf_skeleton *s;
    int32_t joint[LABEL_COUNT]; /* the joint carrying each label, or -1 */
} labelled;

static int label_index(const char *name, bool vrm)
{
    for (int i = 0; i < LABEL_COUNT; i++)
        if (strcmp(labels[i][vrm ? 1 : 0], name) == 0)
            return i;
    return -1;
}

/* Joint names in the maps do not always keep the file's case (Lowerback). */
static int32_t find_joint(const rf_skeleton *s, const char *name)
{
    for (uint32_t j = 0; j < s->joint_count; j++)
        if (s->joints[j].name && strcasecmp(s->joints[j].name, name) == 0)
            return (int32_t)j;
    return -1;
}

static bool read_labels(const char *data, labelled *l)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/correspondences/%s", data, l->map);
    json_error_t err;
    json_t *root = json_load_file(path, 0, &err);
    json_t *map = l->vrm ? root : json_object_get(root, "bones");
    if (!json_is_object(map)) {
        fprintf(stderr, "%s: %s\n", path, root ? "no bones object" : err.text);
        json_decref(root);
        return false;
    }
    for (int i = 0; i < LABEL_COUNT; i++)
        l->joint[i] = -1;
    const char *key;
    json_t *value;
    json_object_foreach(map, key, value)
    {
        const char *joint = l->vrm ? json_string_value(value) : key;
        const char *label = l->vrm ? key : json_string_value(value);
        int i = joint && label ? label_index(label, l->vrm) : -1;
        if (i >= 0)
            l->joint[i] = find_joint(l->s, joint);
    }
    json_decref(root);
    return true;
}

static int label_of(const labelled *l, int32_t joint)
{
    for (int i = 0; i < LABEL_COUNT; i++)
        if (joint >= 0 && l->joint[i] == joint)
            return i;
    return -1;
}

static bool left_label(int i)
{
    return strstr(labels[i][0], ".L") != NULL;
}

/* Maps target t onto source s and scores the labelled joints. */
static void score_pair(const labelled *s, const labelled *t, int *joints, int *right, int *swaps)
{
    char err[256];
    const rf_skeleton *src = s->s;
    rf_ms_options homology = {0}; /* the labels pair forelegs with arms, not the gait rule's */
    homology.forelegs_arms = true;
    rf_mapping *m = rf_ms_match(t->s, &src, 1, &homology, NULL, err, sizeof err);
    int n = 0, ok = 0, sw = 0;
    for (int i = 0; m && i < LABEL_COUNT; i++) {
        if (t->joint[i] < 0 || s->joint[i] < 0)
            continue;
        const rf_map_entry *e = &m->entries[t->joint[i]];
        int32_t got = e->input_count ? (int32_t)e->inputs[0].joint : -1;
        int other = label_of(s, got);
        n++;
        ok += got == s->joint[i];
        bool swapped = other >= 0 && i > 0 && other > 0 && left_label(i) != left_label(other);
        sw += swapped;
        if (got != s->joint[i])
            printf("    wrong: %-16s <- %-16s expected %s%s\n", t->s->joints[t->joint[i]].name,
                   got >= 0 ? src->joints[got].name : "(unmapped)", src->joints[s->joint[i]].name,
                   swapped ? "  SIDE SWAPPED" : "");
    }
    if (!m)
        printf("    matcher failed: %s\n", err);
    rf_mapping_free(m);
    printf("  %-22s onto %-22s %2d of %2d right\n", s->file, t->file, ok, n);
    *joints += n, *right += ok, *swaps += sw;
}

/* Where the maps label a joint of both skeletons of a hand-written truth file, the file must
 * accept that correspondence. Returns the number of disagreements. */
static int check_truth(const char *srcdir, const labelled *s, const labelled *t, const char *name)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/tests/match/truth/%s", srcdir, name);
    truth tr = {0};
    if (!truth_read(path, &tr))
        return 1;
    int bad = 0;
    for (int i = 0; i < LABEL_COUNT; i++) {
        if (t->joint[i] < 0 || s->joint[i] < 0)
            continue;
        const char *tn = t->s->joints[t->joint[i]].name, *sn = s->s->joints[s->joint[i]].name;
        bool accepted = false;
        for (int k = 0; k < tr.count; k++)
            for (int a = 0; strcmp(tr.joints[k].name, tn) == 0 && a < tr.joints[k].accept_count;
                 a++)
                accepted = accepted || strcmp(tr.joints[k].accept[a], sn) == 0;
        if (!accepted) {
            printf("  %s: %s does not accept %s, which the maps say\n", name, tn, sn);
            bad++;
        }
    }
    truth_free(&tr);
    return bad;
}

int main(void)
{
    const char *data = getenv("RF_DATA_DIR"), *srcdir = getenv("RF_SRCDIR");
    labelled sk[] = {
        {"bvh/cmu_01_01.bvh", "retarget_bvh_known_rigs/known_rigs/mb.json", false, NULL, {0}},
        {"bvh/boxing_toes.bvh", "retarget_bvh_known_rigs/known_rigs/cmu.json", false, NULL, {0}},
        {"models/vrm_sample.glb", "vrm_sample_humanBones.json", true, NULL, {0}},
    };
    int n = (int)(sizeof sk / sizeof sk[0]);
    char probe[1024];
    snprintf(probe, sizeof probe, "%s/correspondences/vrm_sample_humanBones.json",
             data ? data : "");
    FILE *f = data ? fopen(probe, "r") : NULL;
    if (!f) {
        printf("SKIP: RF_DATA_DIR unset or without correspondences/\n");
        return 77;
    }
    fclose(f);
    for (int i = 0; i < n; i++)
        if (!(sk[i].s = truth_load(data, sk[i].file)) || !read_labels(data, &sk[i]))
            return 1;
    int joints = 0, right = 0, swaps = 0;
    for (int a = 0; a < n; a++)
        for (int b = 0; b < n; b++)
            if (a != b)
                score_pair(&sk[a], &sk[b], &joints, &right, &swaps);
    int disagree = srcdir ? check_truth(srcdir, &sk[1], &sk[0], "boxing-cmu.truth") : 0;
    double acc = joints ? (double)right / joints : 1;
    printf("labelled joints right: %.1f%% of %d (bar %.0f%%), sides swapped: %d, truth files "
           "disagreeing with the maps: %d\n",
           100 * acc, joints, 100 * CORR_BAR, swaps, disagree);
    for (int i = 0; i < n; i++)
        rf_skeleton_free(sk[i].s);
    return acc >= CORR_BAR && swaps == 0 && disagree == 0 && joints > 0 ? 0 : 1;
}
