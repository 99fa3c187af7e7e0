/* The skeleton analysis's facing when the file declares no forward (.b3d, .X, Ogre .mesh): it
 * must come from the body, so a body turned about its up reads the same facing relative to the
 * body and puts every joint on the same side and in the same kind of section, whichever way
 * it was turned. Checked on every rigged model of the shared data (its declared forward, if any,
 * cleared; skipped without $RF_DATA_DIR) and on a made-up quadruped with one-bone legs and no
 * head marks, whose only cues are where its parts lie. The creatures' facing is also checked
 * against where their artists put the head (truths, below). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "rigflow/analysis.h"
#include "truth.h"

static const double turns[] = {90, 137, 180, 30, -61};
#define TURN_COUNT (sizeof turns / sizeof turns[0])

/* Turns a skeleton by q about the origin: its roots' rest and bind transforms, its declared up
 * (the forward stays undeclared). */
static void turn_skeleton(rf_skeleton *s, rf_quat q)
{
    bool bind = RF_HAS_FIELD(s, rf_skeleton, bind) && s->bind;
    for (uint32_t j = 0; j < s->joint_count; j++) {
        if (s->joints[j].parent >= 0)
            continue;
        rf_xform *x[2] = {&s->joints[j].rest, bind ? &s->bind[j] : NULL};
        for (int k = 0; k < 2; k++)
            if (x[k])
                x[k]->t = rf_quat_rotate(q, x[k]->t),
                x[k]->r = rf_quat_normalize(rf_quat_mul(q, x[k]->r));
    }
    s->up = rf_quat_rotate(q, s->up);
}

static rf_section_type type_of(const rf_analysis *a, uint32_t j)
{
    int32_t sec = a->joints[j].section;
    return sec >= 0 ? a->sections[sec].type : RF_SECTION_NONE;
}

/* Analyses s unturned and turned by every angle of `turns` about `up`; counts the turns that
 * read another facing or put a joint elsewhere (printed), into *bad. */
static void check_turns(const char *label, rf_skeleton *s, rf_vec3 up, int *bad)
{
    rf_analysis_options o = {.use_bind_pose = true};
    rf_analysis *a0 = rf_analyze(s, &o);
    if (!a0) {
        printf("%s: out of memory\n", label);
        (*bad)++;
        return;
    }
    printf("%s: forward (%.3f %.3f %.3f) from %s, confidence %.2f\n", label, a0->forward.x,
           a0->forward.y, a0->forward.z, a0->forward_source, a0->forward_confidence);
    double done = 0;
    for (size_t i = 0; i < TURN_COUNT; i++) {
        rf_quat q = rf_quat_from_axis_angle(up, (turns[i] - done) * RF_PI / 180);
        turn_skeleton(s, q);
        done = turns[i];
        rf_quat all = rf_quat_from_axis_angle(up, turns[i] * RF_PI / 180);
        rf_analysis *a = rf_analyze(s, &o);
        if (!a)
            continue;
        double f = rf_v3_dot(a->forward, rf_quat_rotate(all, a0->forward));
        uint32_t moved = 0, first = UINT32_MAX;
        for (uint32_t j = 0; j < s->joint_count; j++)
            if (type_of(a, j) != type_of(a0, j) || a->joints[j].side != a0->joints[j].side) {
                moved++;
                first = first == UINT32_MAX ? j : first;
            }
        if (f < 0.99 || moved) {
            (*bad)++;
            printf("%s turned %.0f: forward %.3f of the unturned (%s, %s unturned), %u joints "
                   "elsewhere",
                   label, turns[i], f, a->forward_source, a0->forward_source, moved);
            if (first != UINT32_MAX)
                printf(" (%s: %s %s, unturned %s %s)",
                       s->joints[first].name ? s->joints[first].name : "?",
                       rf_side_name(a->joints[first].side), rf_section_type_name(type_of(a, first)),
                       rf_side_name(a0->joints[first].side),
                       rf_section_type_name(type_of(a0, first)));
            printf("\n");
        }
        rf_analysis_free(a);
    }
    rf_analysis_free(a0);
}

/* A quadruped facing -x with +y up: a level spine from its middle joint to the hips and the
 * chest, a neck rising to the head at the front and a jaw hanging from it lower than the tail's
 * root, which is carried high at the back; four straight one-bone legs. No feet, knees, head
 * marks or hierarchy say which end is the front (the root is the middle of the spine); the
 * neck and head held high over the front legs do, though the body's front end (the jaw) is
 * lower than its rear end (the tail's root): read from those two joints, it faced back. */
static rf_skeleton *made_quadruped(void)
{
    static const struct {
        const char *name;
        int parent;
        double x, y, z;
        double tx, ty, tz; /* end site, world, for leaves */
    } js[] = {
        {"mid", -1, 0, 1, 0, 0, 0, 0},
        {"hips", 0, 0.5, 1, 0, 0, 0, 0},
        {"chest", 0, -0.5, 1, 0, 0, 0, 0},
        {"neck", 2, -0.8, 1.2, 0, 0, 0, 0},
        {"head", 3, -1.0, 1.6, 0, 0, 0, 0},
        {"jaw", 4, -1.2, 0.9, 0, -1.4, 0.85, 0},
        {"tail", 1, 0.8, 1.2, 0, 1.4, 0.9, 0},
        {"fl", 2, -0.5, 0.9, 0.2, -0.5, 0, 0.2},
        {"fr", 2, -0.5, 0.9, -0.2, -0.5, 0, -0.2},
        {"hl", 1, 0.5, 0.9, 0.2, 0.5, 0, 0.2},
        {"hr", 1, 0.5, 0.9, -0.2, 0.5, 0, -0.2},
    };
    uint32_t n = sizeof js / sizeof js[0];
    rf_skeleton *s = rf_skeleton_new(n);
    if (!s)
        return NULL;
    for (uint32_t i = 0; i < n; i++) {
        rf_joint *j = &s->joints[i];
        int p = js[i].parent;
        j->name = malloc(strlen(js[i].name) + 1);
        if (j->name)
            strcpy(j->name, js[i].name);
        j->parent = p;
        j->rest.t = p >= 0 ? rf_v3(js[i].x - js[p].x, js[i].y - js[p].y, js[i].z - js[p].z)
                           : rf_v3(js[i].x, js[i].y, js[i].z);
        if (js[i].tx != 0 || js[i].ty != 0 || js[i].tz != 0) {
            j->flags |= RF_JOINT_HAS_END_SITE;
            j->end_site = rf_v3(js[i].tx - js[i].x, js[i].ty - js[i].y, js[i].tz - js[i].z);
        }
    }
    s->up = rf_v3(0, 1, 0);
    return s;
}

static const char *const models[] = {"models/BCN_Epileptic.X",
                                     "models/Fox.glb",
                                     "models/RiggedFigure.glb",
                                     "models/RobotExpressive.glb",
                                     "models/Testwuson.X",
                                     "models/Wizard.glb",
                                     "models/animation_with_skeleton.fbx",
                                     "models/creatures/animala_horse.b3d",
                                     "models/creatures/animalia_angelfish.b3d",
                                     "models/creatures/animalia_bat.b3d",
                                     "models/creatures/animalia_bird.b3d",
                                     "models/creatures/animalia_bull_frog.b3d",
                                     "models/creatures/animalia_cat.b3d",
                                     "models/creatures/animalia_fox.b3d",
                                     "models/creatures/animalia_owl.b3d",
                                     "models/creatures/animalia_wolf.b3d",
                                     "models/creatures/draconis_fire_dragon.b3d",
                                     "models/creatures/draconis_jungle_wyvern.b3d",
                                     "models/girl.glb",
                                     "models/greenman.glb",
                                     "models/huesitos.fbx",
                                     "models/ogre/fish.mesh",
                                     "models/ogre/ninja.mesh"};

/* Which way the shared creatures face, by hand from the files (rigflow inspect: the joints the
 * artist named head or neck lie on one side of those named torso or tail, arms before legs):
 * every one faces -z, and stands up the +y its file declares (the animalia bat lies on its belly,
 * wings spread level: its joints all lie within 0.13 of one height, while it is 0.44 long from
 * head to feet and 1.5 across the wing tips, each wing reaching 0.35 back for 0.62 sideways). The
 * analysis's forward must point from the second joint to the first and its up along the file's.
 * None may be read wrong: the bat was read standing on its tail (up -z) while its wings, swept back
 * from level, counted as limbs hanging, and the angelfish, two joints from body to tail, was read
 * facing its tail by the lean cue before a level limbless chain was read from its root. */
static const struct {
    const char *model, *front, *back;
} truths[] = {
    {"models/creatures/animalia_wolf.b3d", "Head", "Tail"},
    {"models/creatures/animalia_cat.b3d", "Head", "Tail"},
    {"models/creatures/animalia_fox.b3d", "Head", "Torso"},
    {"models/creatures/animala_horse.b3d", "Head", "Tail.1"},
    {"models/creatures/animalia_bird.b3d", "Head", "Torso"},
    {"models/creatures/animalia_owl.b3d", "Head", "Torso"},
    {"models/creatures/animalia_bull_frog.b3d", "Arm.L", "Leg.L"},
    {"models/creatures/draconis_fire_dragon.b3d", "Neck.1", "Torso.1"},
    {"models/creatures/draconis_jungle_wyvern.b3d", "Neck.1", "Torso.1"},
    {"models/creatures/animalia_angelfish.b3d", "Body", "Tail"},
    {"models/creatures/animalia_bat.b3d", "Head", "Torso"},
};
#define KNOWN_WRONG 0

/* Counts the creatures of `truths` read facing another way than they do. */
static int check_truths(const char *data)
{
    int wrong = 0;
    for (size_t i = 0; i < sizeof truths / sizeof truths[0]; i++) {
        rf_skeleton *s = truth_load(data, truths[i].model);
        rf_analysis_options o = {.use_bind_pose = true};
        rf_analysis *a = s ? rf_analyze(s, &o) : NULL;
        int32_t f = s ? rf_skeleton_find(s, truths[i].front) : -1;
        int32_t b = s ? rf_skeleton_find(s, truths[i].back) : -1;
        if (!a || f < 0 || b < 0) {
            printf("%s: cannot be read, or lacks %s or %s\n", truths[i].model, truths[i].front,
                   truths[i].back);
            wrong++;
        } else {
            rf_vec3 d = rf_v3_sub(a->joints[f].pos, a->joints[b].pos);
            rf_vec3 up = rf_v3_len(s->up) > 0 ? rf_v3_normalize(s->up) : rf_v3(0, 1, 0);
            if (rf_v3_dot(a->up, up) < 0.9) {
                printf("%s: read up (%.2f %.2f %.2f) from %s, the file's is (%.2f %.2f %.2f)\n",
                       truths[i].model, a->up.x, a->up.y, a->up.z, a->up_source, up.x, up.y, up.z);
                wrong++;
            } else if (rf_v3_dot(d, a->forward) <= 0) {
                printf("%s: read facing away from %s (forward from %s)\n", truths[i].model,
                       truths[i].front, a->forward_source);
                wrong++;
            }
        }
        rf_analysis_free(a);
        rf_skeleton_free(s);
    }
    printf("%d of %zu creatures read facing or standing another way (at most %d)\n", wrong,
           sizeof truths / sizeof truths[0], KNOWN_WRONG);
    return wrong > KNOWN_WRONG;
}

int main(void)
{
    int bad = 0;
    rf_skeleton *q = made_quadruped();
    if (!q)
        return 1;
    rf_analysis *a = rf_analyze(q, NULL);
    if (!a || rf_v3_dot(a->forward, rf_v3(-1, 0, 0)) < 0.99) {
        printf("made-up quadruped: forward (%.3f %.3f %.3f) from %s, expected -x\n",
               a ? a->forward.x : NAN, a ? a->forward.y : NAN, a ? a->forward.z : NAN,
               a ? a->forward_source : "-");
        bad++;
    }
    rf_analysis_free(a);
    check_turns("made-up quadruped", q, rf_v3(0, 1, 0), &bad);
    rf_skeleton_free(q);

    const char *data = getenv("RF_DATA_DIR");
    struct stat st;
    if (!data || stat(data, &st) != 0) {
        printf("SKIP: RF_DATA_DIR (%s) is not there: the shared rigs are not checked\n",
               data ? data : "unset");
        return bad ? 1 : 77;
    }
    for (size_t m = 0; m < sizeof models / sizeof models[0]; m++) {
        rf_skeleton *s = truth_load(data, models[m]);
        if (!s) {
            printf("%s: cannot be read\n", models[m]);
            bad++;
            continue;
        }
        s->forward = rf_v3(0, 0, 0); /* a file that declares none */
        rf_vec3 up = rf_v3_len(s->up) > 0 ? rf_v3_normalize(s->up) : rf_v3(0, 1, 0);
        check_turns(models[m], s, up, &bad);
        rf_skeleton_free(s);
    }
    bad += check_truths(data);
    printf("%d checks failed (a wrong facing, or a turn read otherwise)\n", bad);
    return bad ? 1 : 0;
}
