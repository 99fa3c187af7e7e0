/* Mapping files: names resolved against skeletons, whole or as overrides (see mapfile.h). */
#include <stdlib.h>
#include <string.h>

#include "mapfile-internal.h"

static uint32_t hash_name(const char *s)
{
    uint32_t h = 2166136261u;
    for (; *s; s++)
        h = (h ^ (unsigned char)*s) * 16777619u;
    return h;
}

bool rf_name_index_init(rf_name_index *ix, const rf_skeleton *s)
{
    uint32_t size = 16;
    while (size < 2 * s->joint_count && size < (1u << 30))
        size *= 2;
    ix->s = s, ix->mask = size - 1;
    ix->slot = calloc(size, sizeof *ix->slot);
    if (!ix->slot)
        return false;
    for (uint32_t j = 0; j < s->joint_count; j++) {
        const char *n = s->joints[j].name;
        if (!n || rf_name_index_find(ix, n) >= 0) /* the first of duplicate names wins */
            continue;
        uint32_t h = hash_name(n) & ix->mask;
        while (ix->slot[h])
            h = (h + 1) & ix->mask;
        ix->slot[h] = j + 1;
    }
    return true;
}

int32_t rf_name_index_find(const rf_name_index *ix, const char *name)
{
    for (uint32_t h = hash_name(name) & ix->mask; ix->slot[h]; h = (h + 1) & ix->mask) {
        const char *n = ix->s->joints[ix->slot[h] - 1].name;
        if (n && strcmp(n, name) == 0)
            return (int32_t)ix->slot[h] - 1;
    }
    return -1;
}

void rf_name_index_clear(rf_name_index *ix)
{
    free(ix->slot);
    ix->slot = NULL;
}

/* ---- resolving ---- */

typedef struct rf_resolver {
    const rf_mapfile *f;
    const rf_skeleton *target;
    const rf_skeleton *const *sources;
    uint32_t source_count;
    rf_name_index tix;
    rf_name_index *six;
    int32_t *target_of;    /* [file joint] target joint, or -1 */
    int32_t *source_joint; /* [file input, flattened] source joint, or -1 */
    rf_errs e;
} rf_resolver;

static const char *skel_name(const rf_skeleton *s, const char *fallback)
{
    return s && s->name ? s->name : fallback;
}

/* Lists every unknown target name in one message. */
static void check_targets(rf_resolver *r)
{
    char list[400] = "";
    uint32_t unknown = 0;
    for (uint32_t i = 0; i < r->f->joint_count; i++) {
        const char *n = r->f->joints[i].target;
        r->target_of[i] = n ? rf_name_index_find(&r->tix, n) : -1;
        if (!n || r->target_of[i] >= 0)
            continue;
        size_t used = strlen(list);
        if (unknown++ < 12)
            snprintf(list + used, sizeof list - used, "%s'%s'", unknown > 1 ? ", " : "", n);
    }
    if (unknown)
        rf_errs_add(&r->e, "%u target joint%s not in the target skeleton %s: %s%s", unknown,
                    unknown == 1 ? " is" : "s are", skel_name(r->target, "(unnamed)"), list,
                    unknown > 12 ? ", ..." : "");
}

static void check_inputs(rf_resolver *r)
{
    uint32_t at = 0;
    for (uint32_t i = 0; i < r->f->joint_count; i++)
        for (uint32_t k = 0; k < r->f->joints[i].input_count; k++, at++) {
            const rf_mapfile_input *in = &r->f->joints[i].inputs[k];
            r->source_joint[at] = -1;
            if (in->source >= r->source_count) {
                rf_errs_add(&r->e, "at /joints/%u/inputs/%u: source %u, but %u source%s connected",
                            i, k, in->source, r->source_count,
                            r->source_count == 1 ? " is" : "s are");
                continue;
            }
            r->source_joint[at] =
                in->joint ? rf_name_index_find(&r->six[in->source], in->joint) : -1;
            if (r->source_joint[at] < 0)
                rf_errs_add(&r->e, "at /joints/%u/inputs/%u: source %u (%s) has no joint '%s'", i,
                            k, in->source, skel_name(r->sources[in->source], "unnamed"),
                            in->joint ? in->joint : "");
        }
}

static uint32_t total_inputs(const rf_mapfile *f)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < f->joint_count; i++)
        n += f->joints[i].input_count;
    return n;
}

static bool resolver_init(rf_resolver *r, const rf_mapfile *f, const rf_skeleton *target,
                          const rf_skeleton *const *sources, uint32_t n, char *err, size_t err_size)
{
    memset(r, 0, sizeof *r);
    r->f = f, r->target = target, r->sources = sources, r->source_count = n;
    r->e = (rf_errs){err, err_size, 0, 0, f->name ? f->name : "mapping"};
    if (err && err_size)
        err[0] = '\0';
    r->six = calloc(n ? n : 1, sizeof *r->six);
    r->target_of = malloc((f->joint_count ? f->joint_count : 1) * sizeof *r->target_of);
    uint32_t ni = total_inputs(f);
    r->source_joint = malloc((ni ? ni : 1) * sizeof *r->source_joint);
    bool ok = r->six && r->target_of && r->source_joint && rf_name_index_init(&r->tix, target);
    for (uint32_t k = 0; ok && k < n; k++)
        ok = sources[k] && rf_name_index_init(&r->six[k], sources[k]);
    if (!ok) {
        rf_errs_add(&r->e, "out of memory (or a missing source skeleton)");
        return false;
    }
    check_targets(r);
    check_inputs(r);
    rf_errs_finish(&r->e);
    return r->e.count == 0;
}

static void resolver_clear(rf_resolver *r)
{
    rf_name_index_clear(&r->tix);
    for (uint32_t k = 0; r->six && k < r->source_count; k++)
        rf_name_index_clear(&r->six[k]);
    free(r->six);
    free(r->target_of);
    free(r->source_joint);
}

/* Entry j from file joint i (inputs starting at `at` in source_joint), metrics by name. */
static bool fill(const rf_resolver *r, rf_mapping *m, uint32_t i, uint32_t at)
{
    const rf_mapfile_joint *fj = &r->f->joints[i];
    rf_map_entry *e = &m->entries[r->target_of[i]];
    free(e->inputs);
    e->inputs = calloc(fj->input_count ? fj->input_count : 1, sizeof *e->inputs);
    e->input_count = 0;
    if (!e->inputs)
        return false;
    for (uint32_t k = 0; k < fj->input_count; k++) {
        const rf_mapfile_input *in = &fj->inputs[k];
        uint32_t flags = (in->reverse ? RF_MAP_REVERSE : 0) | (in->mirror ? RF_MAP_MIRROR : 0);
        e->inputs[e->input_count++] = (rf_map_input){in->source, (uint32_t)r->source_joint[at + k],
                                                     (float)in->weight, (float)in->delay, flags};
    }
    e->score = fj->input_count ? fj->score : 0;
    for (uint32_t q = 0; e->metrics && q < m->metric_count; q++) {
        e->metrics[q] = 0;
        for (uint32_t p = 0; p < r->f->metric_count; p++)
            if (m->metric_names[q] && r->f->metric_names[p] &&
                strcmp(m->metric_names[q], r->f->metric_names[p]) == 0)
                e->metrics[q] = fj->metrics ? fj->metrics[p] : 0;
    }
    return true;
}

static bool label(char **slot, const char *value)
{
    if (!value)
        return true;
    free(*slot);
    return (*slot = rf_strdup(value)) != NULL;
}

static bool fill_all(const rf_resolver *r, rf_mapping *m)
{
    uint32_t at = 0;
    for (uint32_t i = 0; i < r->f->joint_count; i++) {
        const rf_mapfile_joint *fj = &r->f->joints[i];
        uint32_t t = (uint32_t)r->target_of[i];
        if (!fill(r, m, i, at) || (m->sections && !label(&m->sections[t], fj->section)) ||
            (m->sides && !label(&m->sides[t], fj->side)))
            return false;
        at += fj->input_count;
    }
    return true;
}

/* A fresh mapping with the file's metric names and empty labels. */
static rf_mapping *empty_mapping(const rf_mapfile *f, uint32_t joints, uint32_t sources)
{
    rf_mapping *m = rf_mapping_new(joints, sources);
    bool ok = m != NULL;
    if (ok) {
        m->metric_count = f->metric_count;
        m->metric_names = rf_strv_dup(f->metric_names, f->metric_count, &ok);
        m->sections = calloc(joints ? joints : 1, sizeof(char *));
        m->sides = calloc(joints ? joints : 1, sizeof(char *));
        ok = ok && m->sections && m->sides;
    }
    for (uint32_t j = 0; ok && j < joints; j++)
        ok = !f->metric_count ||
             (m->entries[j].metrics = calloc(f->metric_count, sizeof(double))) != NULL;
    if (!ok) {
        rf_mapping_free(m);
        return NULL;
    }
    return m;
}

rf_mapping *rf_mapfile_resolve(const rf_mapfile *f, const rf_skeleton *target,
                               const rf_skeleton *const *sources, uint32_t source_count, char *err,
                               size_t err_size)
{
    rf_resolver r;
    rf_mapping *m = NULL;
    if (resolver_init(&r, f, target, sources, source_count, err, err_size)) {
        m = empty_mapping(f, target->joint_count, source_count);
        if (m && !fill_all(&r, m)) {
            rf_mapping_free(m);
            m = NULL;
        }
        if (!m)
            snprintf(err, err_size, "mapping: out of memory");
    }
    resolver_clear(&r);
    return m;
}

rf_mapping *rf_mapfile_apply(const rf_mapfile *f, const rf_mapping *base, const rf_skeleton *target,
                             const rf_skeleton *const *sources, uint32_t source_count, char *err,
                             size_t err_size)
{
    if (!base || base->target_joint_count != target->joint_count) {
        snprintf(err, err_size,
                 "mapping: the mapping to override has %u entries but the target "
                 "has %u joints",
                 base ? base->target_joint_count : 0, target->joint_count);
        return NULL;
    }
    rf_resolver r;
    rf_mapping *m = NULL;
    if (resolver_init(&r, f, target, sources, source_count, err, err_size)) {
        m = rf_mapping_copy(base);
        if (m)
            m->source_count = source_count > m->source_count ? source_count : m->source_count;
        if (m && !fill_all(&r, m)) {
            rf_mapping_free(m);
            m = NULL;
        }
        if (!m)
            snprintf(err, err_size, "mapping: out of memory");
    }
    resolver_clear(&r);
    return m;
}
