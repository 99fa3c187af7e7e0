/* Joint mapping speed: the time of one rf_ms_match call, files imported once before,
 * for CMU onto the Fox, onto the fire dragon, the dragon onto the wyvern, CMU onto a synthetic
 * 200-joint creature, a 187-joint creature onto a 200-joint one (the thesis's largest case) and
 * larger creatures to show how the time grows. Both strategies: the default (similarity) and the
 * thesis as written. The thesis measured 0.47 s for 27 bones and 3.1 s for 187 (its Table 7).
 *
 * usage: bench_match DATA_DIR [--quick] [CASE]   (CASE: run only the case of that name)
 * Prints one CSV line per case: case,target_joints,source_joints,strategy,analysis_us,map_us
 * where map_us is the median of 7 batches, each repeating the call for at least 200 ms (30 ms
 * with --quick), and analysis_us the part of it spent analysing both skeletons. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "match-similarity/similarity.h"
#include "truth.h"

static double now_us(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e6 + (double)ts.tv_nsec / 1e3;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* ---- a synthetic winged quadruped of any size ----
 * Facing +Z, up +Y, BVH-like (identity rests, end sites on leaves): ground root, spine, neck,
 * skull with jaw and eyes, a tail, four legs with a fan of toes, two wings with a fan of fingers.
 * The tail takes whatever joints are left to reach the asked count. */

typedef struct creature {
    rf_skeleton *s;
    rf_vec3 *world;
    uint32_t n;
} creature;

static int32_t cr_add(creature *c, int32_t parent, rf_vec3 p)
{
    uint32_t i = c->n++;
    rf_joint *j = &c->s->joints[i];
    char name[32];
    snprintf(name, sizeof name, "j%u", i); /* meaningless names: geometry only */
    j->name = strdup(name);
    j->parent = parent;
    c->world[i] = p;
    j->rest.t = parent >= 0 ? rf_v3_sub(p, c->world[parent]) : p;
    return (int32_t)i;
}

static void cr_tip(creature *c, int32_t j, rf_vec3 tip)
{
    c->s->joints[j].flags |= RF_JOINT_HAS_END_SITE;
    c->s->joints[j].end_site = rf_v3_sub(tip, c->world[j]);
}

/* n joints from `from` towards `to` (the last bone ends at `to`); returns the last. */
static int32_t cr_chain(creature *c, int32_t parent, rf_vec3 from, rf_vec3 to, int n)
{
    int32_t j = parent;
    for (int k = 0; k < n; k++)
        j = cr_add(c, j, rf_v3_lerp(from, to, (double)k / n));
    if (n > 0)
        cr_tip(c, j, to);
    return j;
}

static void cr_fan(creature *c, int32_t hand, rf_vec3 base, rf_vec3 dir, rf_vec3 spread, int digits,
                   int segs)
{
    for (int d = 0; d < digits; d++) {
        double t = digits > 1 ? (double)d / (digits - 1) - 0.5 : 0;
        rf_vec3 to = rf_v3_add(rf_v3_add(base, dir), rf_v3_scale(spread, t));
        cr_chain(c, hand, base, to, segs);
    }
}

static void cr_leg(creature *c, int32_t girdle, double side, double z, int digits, int segs)
{
    rf_vec3 hip = rf_v3(0.3 * side, 1.0, z), knee = rf_v3(0.35 * side, 0.55, z + 0.1);
    rf_vec3 ankle = rf_v3(0.35 * side, 0.2, z - 0.1), foot = rf_v3(0.35 * side, 0.05, z);
    int32_t j = cr_add(c, girdle, hip);
    j = cr_add(c, j, knee);
    j = cr_add(c, j, ankle);
    j = cr_add(c, j, foot);
    cr_fan(c, j, foot, rf_v3(0, -0.03, 0.25), rf_v3(0.2 * side, 0, 0), digits, segs);
}

static void cr_wing(creature *c, int32_t chest, double side, int digits, int segs)
{
    int32_t j = cr_add(c, chest, rf_v3(0.2 * side, 1.35, 0.5));
    j = cr_add(c, j, rf_v3(0.9 * side, 1.6, 0.4));
    j = cr_add(c, j, rf_v3(1.7 * side, 1.5, 0.3));
    rf_vec3 hand = rf_v3(2.3 * side, 1.45, 0.2);
    j = cr_add(c, j, hand);
    cr_fan(c, j, hand, rf_v3(0.9 * side, -0.3, -0.8), rf_v3(0.4 * side, 0, 0.8), digits, segs);
}

/* digits (toes per foot and fingers per wing) and their segments grow with the size so the
 * creature is not all tail. */
static creature cr_make(uint32_t count)
{
    int digits = count >= 600 ? 6 : 5, segs = count >= 600 ? 6 : 3;
    int spine = 12, neck = 10;
    int fixed = 1 + spine + neck + 4 + 4 * (4 + digits * segs) + 2 * (4 + (digits - 1) * 5);
    int tail = (int)count - fixed;
    creature c = {rf_skeleton_new(count), calloc(count, sizeof(rf_vec3)), 0};
    if (tail < 1) {
        fprintf(stderr, "bench_match: a creature needs at least %d joints\n", fixed + 1);
        exit(2);
    }
    int32_t root = cr_add(&c, -1, rf_v3(0, 0, 0));
    int32_t pelvis = cr_add(&c, root, rf_v3(0, 1.0, -0.6));
    int32_t chest = cr_chain(&c, pelvis, rf_v3(0, 1.02, -0.45), rf_v3(0, 1.1, 0.6), spine - 1);
    int32_t neck_end = cr_chain(&c, chest, rf_v3(0, 1.1, 0.6), rf_v3(0, 1.8, 1.2), neck);
    int32_t skull = cr_add(&c, neck_end, rf_v3(0, 1.8, 1.2));
    cr_tip(&c, skull, rf_v3(0, 1.9, 1.7));
    cr_tip(&c, cr_add(&c, skull, rf_v3(0, 1.75, 1.3)), rf_v3(0, 1.7, 1.65));
    for (int side = -1; side <= 1; side += 2)
        cr_tip(&c, cr_add(&c, skull, rf_v3(0.08 * side, 1.92, 1.45)),
               rf_v3(0.09 * side, 1.92, 1.5));
    cr_chain(&c, pelvis, rf_v3(0, 0.98, -0.8), rf_v3(0, 0.6, -3.5), tail);
    for (int side = -1; side <= 1; side += 2) {
        cr_leg(&c, pelvis, side, -0.6, digits, segs);
        cr_leg(&c, chest, side, 0.6, digits, segs);
        cr_wing(&c, chest, side, digits - 1, 5);
    }
    free(c.world);
    return c;
}

/* ---- timing ---- */

typedef struct bench_case {
    const char *name;
    const rf_skeleton *target, *source;
} bench_case;

static double time_batch(const bench_case *bc, const rf_ms_options *o, double min_us, int analyse)
{
    char err[256];
    int reps = 0;
    double start = now_us(), end;
    do {
        if (analyse) {
            rf_analysis_free(rf_analyze(bc->target, NULL));
            rf_analysis_free(rf_analyze(bc->source, NULL));
        } else {
            rf_mapping_free(rf_ms_match(bc->target, &bc->source, 1, o, NULL, err, sizeof err));
        }
        reps++;
        end = now_us();
    } while (end - start < min_us);
    return (end - start) / reps;
}

static double median_time(const bench_case *bc, const rf_ms_options *o, double min_us, int analyse)
{
    double t[7];
    for (int b = 0; b < 7; b++)
        t[b] = time_batch(bc, o, min_us, analyse);
    qsort(t, 7, sizeof t[0], cmp_double);
    return t[3];
}

static void run_case(const bench_case *bc, double min_us)
{
    if (!bc->target || !bc->source) {
        printf("%s,,,skipped (file missing),,\n", bc->name);
        return;
    }
    double analysis = median_time(bc, NULL, min_us, 1);
    for (int thesis = 0; thesis <= 1; thesis++) {
        rf_ms_weights w;
        uint32_t pref;
        rf_ms_weight_set(thesis ? "thesis" : "default", &w, &pref);
        rf_ms_options o = {.weights = &w, .thesis = thesis != 0};
        double us = median_time(bc, &o, min_us, 0);
        printf("%s,%u,%u,%s,%.1f,%.1f\n", bc->name, bc->target->joint_count,
               bc->source->joint_count, thesis ? "thesis" : "similarity", analysis, us);
        fflush(stdout);
    }
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: bench_match DATA_DIR [--quick] [CASE]\n");
        return 2;
    }
    bool quick = argc > 2 && strcmp(argv[2], "--quick") == 0;
    const char *only = argc > 2 + quick ? argv[2 + quick] : NULL;
    double min_us = quick ? 30e3 : 200e3;
    rf_skeleton *cmu = truth_load(argv[1], "bvh/cmu_01_01.bvh");
    rf_skeleton *fox = truth_load(argv[1], "models/Fox.glb");
    rf_skeleton *dragon = truth_load(argv[1], "models/creatures/draconis_fire_dragon.b3d");
    rf_skeleton *wyvern = truth_load(argv[1], "models/creatures/draconis_jungle_wyvern.b3d");
    creature c187 = cr_make(187), c200 = cr_make(200), c1000 = cr_make(1000), c2000 = cr_make(2000);
    const bench_case cases[] = {
        {"cmu-fox", fox, cmu},
        {"cmu-dragon", dragon, cmu},
        {"dragon-wyvern", wyvern, dragon},
        {"cmu-synth200", c200.s, cmu},
        {"synth187-synth200", c200.s, c187.s},
        {"synth1000-synth1000", c1000.s, c1000.s},
        {"synth2000-synth2000", c2000.s, c2000.s},
    };
    printf("case,target_joints,source_joints,strategy,analysis_us,map_us\n");
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
        if (!only || strcmp(only, cases[i].name) == 0)
            run_case(&cases[i], min_us);
    rf_skeleton *all[] = {cmu, fox, dragon, wyvern, c187.s, c200.s, c1000.s, c2000.s};
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
        rf_skeleton_free(all[i]);
    return 0;
}
