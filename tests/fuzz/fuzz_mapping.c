/* libFuzzer harness: the mapping-file reader (plugins/mapping-file, doc/formats/mapping.md).
 *
 * Parses the bytes, then resolves them against two small fixed skeletons, as a whole mapping and
 * as overrides on a base mapping, the way mapping.read does. Every mapping that resolves must keep
 * the data model's promises (one entry per target joint, source and joint indices in range,
 * positive finite weights), and written back it must read and resolve again to the same shape.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mapfile.h"

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define RF_FUZZ_CHECK(cond)                                                                        \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            fprintf(stderr, "fuzz_mapping: broken promise: %s (%s:%d)\n", #cond, __FILE__,         \
                    __LINE__);                                                                     \
            abort();                                                                               \
        }                                                                                          \
    } while (0)

static rf_skeleton *rf_fz_target, *rf_fz_sources[2];

/* A skeleton whose joints are `names` in a chain from the first. */
static rf_skeleton *rf_fz_chain(const char *name, const char *const *names, uint32_t count)
{
    rf_skeleton *s = rf_skeleton_new(count);
    RF_FUZZ_CHECK(s != NULL);
    s->name = strdup(name);
    for (uint32_t i = 0; i < count; i++) {
        s->joints[i].name = strdup(names[i]);
        s->joints[i].parent = (int32_t)i - 1;
        s->joints[i].rest.t = rf_v3(0, 1, 0);
    }
    return s;
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    static const char *const target[] = {"Hips", "Spine", "Neck", "Head", "LeftArm", "RightArm"};
    static const char *const a[] = {"hips", "spine", "neck", "head"};
    static const char *const b[] = {"Root", "Chest", "Skull", "", "Ünïcode"};
    rf_fz_target = rf_fz_chain("target.bvh", target, 6);
    rf_fz_sources[0] = rf_fz_chain("a.bvh", a, 4);
    rf_fz_sources[1] = rf_fz_chain("b.glb", b, 5);
    return 0;
}

static void rf_fz_check_mapping(const rf_mapping *m)
{
    RF_FUZZ_CHECK(m->target_joint_count == rf_fz_target->joint_count);
    RF_FUZZ_CHECK(m->source_count == 2);
    for (uint32_t t = 0; t < m->target_joint_count; t++) {
        const rf_map_entry *e = &m->entries[t];
        RF_FUZZ_CHECK(e->input_count == 0 || e->inputs);
        for (uint32_t i = 0; i < e->input_count; i++) {
            const rf_map_input *in = &e->inputs[i];
            RF_FUZZ_CHECK(in->source < m->source_count);
            RF_FUZZ_CHECK(in->joint < rf_fz_sources[in->source]->joint_count);
            RF_FUZZ_CHECK(in->weight > 0 && isfinite(in->weight) && isfinite(in->delay));
        }
        RF_FUZZ_CHECK(m->metric_count == 0 || e->metrics || e->input_count == 0);
    }
}

/* Written back, the mapping reads and resolves again with the same inputs per target joint. */
static void rf_fz_round_trip(const rf_mapping *m)
{
    char *text = NULL, err[2048] = "";
    size_t len = 0;
    FILE *out = open_memstream(&text, &len);
    RF_FUZZ_CHECK(out != NULL);
    const rf_skeleton *const *src = (const rf_skeleton *const *)rf_fz_sources;
    bool wrote = rf_mapfile_write(out, m, rf_fz_target, src, 2, err, sizeof err);
    RF_FUZZ_CHECK(fclose(out) == 0);
    if (!wrote) {
        RF_FUZZ_CHECK(err[0] != '\0');
        free(text);
        return;
    }
    rf_mapfile *f = rf_mapfile_parse(text, len, "written.json", err, sizeof err);
    if (!f)
        fprintf(stderr, "fuzz_mapping: the written file does not read back:\n%s\n%s\n", err, text);
    RF_FUZZ_CHECK(f != NULL);
    rf_mapping *again = rf_mapfile_resolve(f, rf_fz_target, src, 2, err, sizeof err);
    if (!again)
        fprintf(stderr, "fuzz_mapping: the written file does not resolve:\n%s\n%s\n", err, text);
    RF_FUZZ_CHECK(again != NULL);
    for (uint32_t t = 0; t < m->target_joint_count; t++)
        RF_FUZZ_CHECK(again->entries[t].input_count == m->entries[t].input_count);
    rf_mapping_free(again);
    rf_mapfile_free(f);
    free(text);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char err[4096] = "";
    rf_mapfile *f = rf_mapfile_parse((const char *)data, size, "fuzz.json", err, sizeof err);
    if (!f) {
        RF_FUZZ_CHECK(strncmp(err, "fuzz.json", 9) == 0); /* a refusal names the file */
        return 0;
    }
    const rf_skeleton *const *src = (const rf_skeleton *const *)rf_fz_sources;
    rf_mapping *m = rf_mapfile_resolve(f, rf_fz_target, src, 2, err, sizeof err);
    if (m) {
        rf_fz_check_mapping(m);
        rf_fz_round_trip(m);
        rf_mapping *base = rf_mapping_copy(m);
        RF_FUZZ_CHECK(base != NULL);
        rf_mapping *over = rf_mapfile_apply(f, base, rf_fz_target, src, 2, err, sizeof err);
        RF_FUZZ_CHECK(over != NULL); /* what resolves applies */
        rf_fz_check_mapping(over);
        rf_mapping_free(over);
        rf_mapping_free(base);
        rf_mapping_free(m);
    } else {
        RF_FUZZ_CHECK(err[0] != '\0');
    }
    rf_mapfile_free(f);
    return 0;
}
