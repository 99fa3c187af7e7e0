/* libFuzzer harness: the skeleton analysis (framework/analysis) on arbitrary trees.
 *
 * The bytes describe a skeleton rather than being one, so that the fuzzer reaches the shapes that
 * break geometry code quickly: deep chains, wide fans, zero-length bones, coincident joints,
 * NaN and infinite positions, non-unit rotations, bad parent indices, a bind pose that differs
 * from the rest pose, forced axes that are zero, parallel or NaN.
 *
 *   byte 0      mode bits (RF_FZ_*)
 *   bytes 1, 2  joint count (little-endian, capped at 4 per record and 512); RF_FZ_MANY
 *               multiplies it by 16, up to 8192
 *   then        8 bytes per joint, reused cyclically when the input runs out
 *
 * Then it checks what analysis.h promises: every index it returns is in range, sections list
 * each joint once, parents come before children, and the axes are finite unit vectors.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rigflow/analysis.h"
#include "fuzz-values.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

enum {
    RF_FZ_CHAIN = 1u << 0,      /* every joint hangs from the previous one */
    RF_FZ_UP = 1u << 1,         /* force an up axis */
    RF_FZ_FORWARD = 1u << 2,    /* force a forward axis */
    RF_FZ_BIND = 1u << 3,       /* give the skeleton a bind pose and analyse it */
    RF_FZ_NO_FILE = 1u << 4,    /* ignore the file's axes */
    RF_FZ_MANY = 1u << 5,       /* scale the joint count up to 100 000 */
    RF_FZ_BAD_PARENT = 1u << 6, /* allow parent indices that break the model's rule */
    RF_FZ_FILE_AXES = 1u << 7,  /* the skeleton states up and forward */
};

#define RF_FZ_MAX_JOINTS 512u
#define RF_FZ_MAX_MANY 8192u

#define RF_FUZZ_CHECK(cond)                                                                        \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            fprintf(stderr, "fuzz_analysis: broken promise: %s (%s:%d)\n", #cond, __FILE__,        \
                    __LINE__);                                                                     \
            abort();                                                                               \
        }                                                                                          \
    } while (0)

/* Numbers that break geometry: zero, tiny, huge, non-finite, and ordinary ones. */
static double rf_fz_value(uint8_t b)
{
    static const double table[16] = {0,   1,   -1,  0.5,      1e-9,      -1e-12, 10, -10,
                                     100, 1e6, NAN, INFINITY, -INFINITY, 1e300,  2,  0.1};
    double v = table[b & 15];
    return isfinite(v) ? v + (b >> 4) * 0.125 : v;
}

static rf_vec3 rf_fz_vec(uint8_t a, uint8_t b, uint8_t c)
{
    return rf_v3(rf_fz_value(a), rf_fz_value(b), rf_fz_value(c));
}

static rf_quat rf_fz_quat(uint8_t b)
{
    return rf_fz_quat_of(b, true);
}

typedef struct rf_fz_input {
    const uint8_t *rec; /* the joint records */
    size_t rec_size;
} rf_fz_input;

static const uint8_t *rf_fz_record(const rf_fz_input *in, uint32_t i)
{
    static const uint8_t zeros[8];
    if (in->rec_size < 8)
        return zeros;
    return in->rec + ((size_t)i % (in->rec_size / 8)) * 8;
}

static int32_t rf_fz_parent(uint32_t i, uint8_t b, unsigned mode)
{
    if (i == 0)
        return (mode & RF_FZ_BAD_PARENT) && b >= 250 ? (int32_t)b : -1;
    if (mode & RF_FZ_CHAIN)
        return (int32_t)i - 1;
    if ((mode & RF_FZ_BAD_PARENT) && b >= 250)
        return b & 1 ? (int32_t)(i + b) : -(int32_t)b; /* forward or below -1 */
    if (b == 249)
        return -1; /* a forest */
    uint32_t back = (uint32_t)b % (i < 64 ? i : 64);
    return (int32_t)(i - 1 - back);
}

static void rf_fz_joint(rf_joint *j, const uint8_t *r, uint32_t i, unsigned mode)
{
    static const char *const names[] = {"Hips", "Spine", "LeftArm", "RightArm", "Head", "", "j"};
    j->parent = rf_fz_parent(i, r[0], mode);
    j->rest.t = rf_fz_vec(r[1], r[2], r[3]);
    j->rest.r = rf_fz_quat(r[5]);
    if ((r[5] >> 3) == 31)
        j->rest.s = rf_v3(0, 0, 0); /* a collapsed joint */
    j->flags = r[4] & (RF_JOINT_HAS_END_SITE | RF_JOINT_UNWEIGHTED);
    j->end_site = rf_fz_vec(r[4] >> 2, r[6], r[7] >> 1);
    if (r[6] % 3 == 0) /* names do not matter to the analysis but must print */
        j->name = strdup(names[r[7] % (sizeof names / sizeof *names)]);
}

static rf_skeleton *rf_fz_skeleton(const uint8_t *data, size_t size, unsigned *mode)
{
    *mode = size ? data[0] : 0;
    uint32_t n = size >= 3 ? (uint32_t)data[1] | (uint32_t)data[2] << 8 : 0;
    /* A few joints per record: short inputs stay small and fast, so the fuzzer explores shapes
     * rather than spending its time on one big repetitive tree (RF_FZ_MANY asks for that). */
    uint32_t most = size > 3 ? 2 + (uint32_t)((size - 3) / 8) * 4 : 2;
    n = n < most ? n : most;
    n = n < RF_FZ_MAX_JOINTS ? n : RF_FZ_MAX_JOINTS;
    if (*mode & RF_FZ_MANY)
        n = n * 16 < RF_FZ_MAX_MANY ? n * 16 : RF_FZ_MAX_MANY;
    rf_fz_input in = {size > 3 ? data + 3 : NULL, size > 3 ? size - 3 : 0};
    rf_skeleton *s = rf_skeleton_new(n);
    RF_FUZZ_CHECK(s != NULL);
    for (uint32_t i = 0; i < n; i++)
        rf_fz_joint(&s->joints[i], rf_fz_record(&in, i), i, *mode);
    if (*mode & RF_FZ_BIND) {
        s->bind = calloc(n ? n : 1, sizeof *s->bind);
        for (uint32_t i = 0; i < n; i++) {
            const uint8_t *r = rf_fz_record(&in, i);
            s->bind[i].t = rf_fz_vec(r[3], r[1], r[2]); /* a different pose */
            s->bind[i].r = rf_fz_quat(r[7]);
            s->bind[i].s = rf_v3(1, 1, 1);
        }
    }
    if (*mode & RF_FZ_FILE_AXES) {
        const uint8_t *r = rf_fz_record(&in, 0);
        s->up = rf_fz_vec(r[1], r[2], r[3]);
        s->forward = rf_fz_vec(r[5], r[6], r[7]);
    }
    return s;
}

static bool rf_fz_unit(rf_vec3 v)
{
    double l = rf_v3_len(v);
    return isfinite(l) && fabs(l - 1) < 1e-6;
}

static void rf_fz_check_sections(const rf_analysis *a)
{
    uint32_t listed = 0;
    for (uint32_t s = 0; s < a->section_count; s++) {
        const rf_section *sec = &a->sections[s];
        RF_FUZZ_CHECK(sec->type > RF_SECTION_NONE && sec->type < RF_SECTION_TYPE_COUNT);
        RF_FUZZ_CHECK(sec->first == listed); /* sections list their joints in order */
        listed += sec->bone_count;
        RF_FUZZ_CHECK(listed <= a->joint_count);
        RF_FUZZ_CHECK(sec->parent >= -1 && sec->parent < (int32_t)s);
        RF_FUZZ_CHECK(sec->mirror >= -1 && sec->mirror < (int32_t)a->section_count);
        RF_FUZZ_CHECK(sec->attach_joint >= -1 && sec->attach_joint < (int32_t)a->joint_count);
        for (uint32_t k = 0; k < sec->bone_count; k++) {
            uint32_t j = rf_section_joints(a, s)[k];
            RF_FUZZ_CHECK(j < a->joint_count);
            RF_FUZZ_CHECK(a->joints[j].section == (int32_t)s && a->joints[j].index == k);
        }
    }
    RF_FUZZ_CHECK(listed == a->joint_count); /* every joint in exactly one section */
}

static void rf_fz_check(const rf_analysis *a, uint32_t n)
{
    RF_FUZZ_CHECK(a->joint_count == n);
    RF_FUZZ_CHECK(n == 0 ? a->root == -1 : a->root >= 0 && a->root < (int32_t)n);
    RF_FUZZ_CHECK(rf_fz_unit(a->up) && rf_fz_unit(a->forward) && rf_fz_unit(a->left));
    RF_FUZZ_CHECK(fabs(rf_v3_dot(a->up, a->forward)) < 1e-6);
    RF_FUZZ_CHECK(a->size > 0 && a->height > 0);
    RF_FUZZ_CHECK(a->symmetry >= 0 && a->symmetry <= 1);
    for (uint32_t i = 0; i < n; i++) {
        const rf_joint_info *j = &a->joints[i];
        RF_FUZZ_CHECK(j->section >= 0 && j->section < (int32_t)a->section_count);
        RF_FUZZ_CHECK(j->mirror >= -1 && j->mirror < (int32_t)n);
        RF_FUZZ_CHECK(j->logical_parent >= -1 && j->logical_parent < (int32_t)n);
    }
    rf_fz_check_sections(a);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static FILE *sink;
    if (!sink)
        sink = fopen("/dev/null", "w");
    unsigned mode;
    rf_skeleton *s = rf_fz_skeleton(data, size, &mode);
    rf_analysis_options o = {0};
    const uint8_t *r = size >= 11 ? data + size - 8 : (const uint8_t[8]){0};
    if (mode & RF_FZ_UP)
        o.up = rf_fz_vec(r[0], r[1], r[2]);
    if (mode & RF_FZ_FORWARD)
        o.forward = rf_fz_vec(r[3], r[4], r[5]);
    o.leg_threshold = (r[6] & 3) == 3 ? rf_fz_value(r[7]) : 0;
    o.use_bind_pose = (mode & RF_FZ_BIND) != 0;
    o.ignore_file_axes = (mode & RF_FZ_NO_FILE) != 0;
    rf_analysis *a = rf_analyze(s, &o);
    RF_FUZZ_CHECK(a != NULL);
    rf_fz_check(a, s->joint_count);
    if (sink && s->joint_count <= RF_FZ_MAX_JOINTS)
        rf_analysis_print(a, s, sink);
    rf_analysis_free(a);
    rf_skeleton_free(s);
    return 0;
}
