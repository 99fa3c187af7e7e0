/* libFuzzer harness: the BVH reader (rf_bvh_read_memory) on arbitrary bytes.
 *
 * Beyond "no crash, no leak, no undefined behaviour" (the sanitizers' part), every accepted file
 * must give a skeleton and animation that keep the data model's promises, because every later node
 * indexes arrays with them unchecked: parents before children, one animation column per joint,
 * finite sampling rate, unique joint names. An accepted file is also written back and must read
 * again with the same shape: the writer may not produce a file its own reader refuses.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rigflow/bvh.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Stops the run with a message libFuzzer records as a crash: the input broke a promise. */
#define RF_FUZZ_CHECK(cond)                                                                        \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            fprintf(stderr, "fuzz_bvh: broken promise: %s (%s:%d)\n", #cond, __FILE__, __LINE__);  \
            abort();                                                                               \
        }                                                                                          \
    } while (0)

static void rf_fuzz_check_skeleton(const rf_skeleton *s)
{
    RF_FUZZ_CHECK(s->size >= sizeof(rf_skeleton) && s->joints);
    for (uint32_t i = 0; i < s->joint_count; i++) {
        const rf_joint *j = &s->joints[i];
        RF_FUZZ_CHECK(j->parent >= -1 && j->parent < (int32_t)i);
        RF_FUZZ_CHECK(j->name != NULL);
        for (uint32_t k = 0; k < i && s->joint_count <= 64; k++) /* small files: O(n^2) is fine */
            RF_FUZZ_CHECK(strcmp(s->joints[k].name, j->name) != 0);
    }
}

static void rf_fuzz_check_animation(const rf_skeleton *s, const rf_animation *a)
{
    RF_FUZZ_CHECK(a->joint_count == s->joint_count);
    RF_FUZZ_CHECK(a->fps > 0 && isfinite(a->fps));
    RF_FUZZ_CHECK(a->rotations && a->translations && a->channels);
    /* Touch the last value so ASan sees an array shorter than frames x joints. */
    size_t n = (size_t)a->frame_count * a->joint_count;
    if (n) {
        volatile float last = a->rotations[n * 4 - 1] + a->translations[n * 3 - 1];
        (void)last;
    }
}

/* Writes the file back to memory and reads it again: same joints, same frames. */
static void rf_fuzz_round_trip(const rf_skeleton *s, const rf_animation *a)
{
    char *text = NULL, err[512];
    size_t len = 0;
    FILE *out = open_memstream(&text, &len);
    RF_FUZZ_CHECK(out != NULL);
    bool wrote = rf_bvh_write_stream(out, "fuzz-out.bvh", s, a, NULL, err, sizeof err);
    RF_FUZZ_CHECK(fclose(out) == 0);
    if (!wrote) { /* refusing to write (e.g. NaN values) is allowed, with a reason */
        RF_FUZZ_CHECK(err[0] != '\0');
        free(text);
        return;
    }
    rf_skeleton *s2 = NULL;
    rf_animation *a2 = NULL;
    bool ok = rf_bvh_read_memory(text, len, "fuzz-out.bvh", NULL, &s2, &a2, err, sizeof err);
    if (!ok)
        fprintf(stderr, "fuzz_bvh: the written file does not read back: %s\n", err);
    RF_FUZZ_CHECK(ok);
    RF_FUZZ_CHECK(s2->joint_count == s->joint_count);
    RF_FUZZ_CHECK(a2->frame_count == a->frame_count);
    rf_skeleton_free(s2);
    rf_animation_free(a2);
    free(text);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    rf_skeleton *s = NULL;
    rf_animation *a = NULL;
    char err[512] = "";
    if (!rf_bvh_read_memory((const char *)data, size, "fuzz.bvh", NULL, &s, &a, err, sizeof err)) {
        /* A refusal names the source: "fuzz.bvh:LINE: ..." or "fuzz.bvh: ...". */
        RF_FUZZ_CHECK(strncmp(err, "fuzz.bvh", 8) == 0);
        RF_FUZZ_CHECK(s == NULL && a == NULL);
        return 0;
    }
    rf_fuzz_check_skeleton(s);
    rf_fuzz_check_animation(s, a);
    rf_fuzz_round_trip(s, a);
    rf_skeleton_free(s);
    rf_animation_free(a);
    return 0;
}
