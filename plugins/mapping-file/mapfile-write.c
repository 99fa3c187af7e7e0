/* Mapping files: writing (see mapfile.h and doc/formats/mapping.md). */
#include <jansson.h>
#include <math.h>
#include <string.h>

#include "mapfile-internal.h"

static json_t *name_or_index(const rf_skeleton *s, uint32_t j)
{
    if (s && j < s->joint_count && s->joints[j].name)
        return json_string(s->joints[j].name);
    char buf[24];
    snprintf(buf, sizeof buf, "#%u", j);
    return json_string(buf);
}

/* JSON has no NaN or infinity: a bad number is written as 0. */
static json_t *number(double v)
{
    return json_real(isfinite(v) ? v : 0.0);
}

static json_t *input_json(const rf_map_input *in, const rf_skeleton *const *sources,
                          uint32_t source_count)
{
    json_t *o = json_object();
    json_object_set_new(o, "source", json_integer(in->source));
    json_object_set_new(
        o, "joint",
        name_or_index(in->source < source_count ? sources[in->source] : NULL, in->joint));
    json_object_set_new(o, "weight", number(in->weight));
    json_object_set_new(o, "delay", number(in->delay));
    json_object_set_new(o, "reverse", json_boolean(in->flags & RF_MAP_REVERSE));
    if (in->flags & RF_MAP_MIRROR)
        json_object_set_new(o, "mirror", json_true());
    return o;
}

static json_t *joint_json(const rf_mapping *m, uint32_t j, const rf_skeleton *target,
                          const rf_skeleton *const *sources, uint32_t source_count)
{
    const rf_map_entry *e = &m->entries[j];
    json_t *o = json_object(), *ins = json_array(), *metrics = json_object();
    json_object_set_new(o, "target", name_or_index(target, j));
    for (uint32_t k = 0; k < e->input_count; k++)
        json_array_append_new(ins, input_json(&e->inputs[k], sources, source_count));
    json_object_set_new(o, "inputs", ins);
    json_object_set_new(o, "score", number(e->score));
    for (uint32_t q = 0; e->metrics && q < m->metric_count; q++)
        if (m->metric_names && m->metric_names[q])
            json_object_set_new(metrics, m->metric_names[q], number(e->metrics[q]));
    json_object_set_new(o, "metrics", metrics);
    bool labels = RF_HAS_FIELD(m, rf_mapping, sides);
    if (labels && m->sections && m->sections[j])
        json_object_set_new(o, "section", json_string(m->sections[j]));
    if (labels && m->sides && m->sides[j])
        json_object_set_new(o, "side", json_string(m->sides[j]));
    return o;
}

static json_t *document(const rf_mapping *m, const rf_skeleton *target,
                        const rf_skeleton *const *sources, uint32_t source_count)
{
    json_t *root = json_object(), *srcs = json_array(), *metrics = json_array();
    json_t *joints = json_array();
    json_object_set_new(root, "format", json_string(RF_MAPFILE_FORMAT));
    json_object_set_new(root, "version", json_integer(RF_MAPFILE_VERSION));
    json_object_set_new(root, "target", target->name ? json_string(target->name) : json_null());
    for (uint32_t k = 0; k < source_count; k++)
        json_array_append_new(srcs,
                              json_string(sources[k] && sources[k]->name ? sources[k]->name : ""));
    json_object_set_new(root, "sources", srcs);
    for (uint32_t q = 0; m->metric_names && q < m->metric_count; q++)
        json_array_append_new(metrics, json_string(m->metric_names[q] ? m->metric_names[q] : ""));
    json_object_set_new(root, "metrics", metrics);
    for (uint32_t j = 0; j < m->target_joint_count; j++)
        json_array_append_new(joints, joint_json(m, j, target, sources, source_count));
    json_object_set_new(root, "joints", joints);
    return root;
}

bool rf_mapfile_write(FILE *out, const rf_mapping *m, const rf_skeleton *target,
                      const rf_skeleton *const *sources, uint32_t source_count, char *err,
                      size_t err_size)
{
    if (!m || !target || m->target_joint_count != target->joint_count) {
        snprintf(err, err_size, "the mapping has %u entries but the target has %u joints",
                 m ? m->target_joint_count : 0, target ? target->joint_count : 0);
        return false;
    }
    for (uint32_t j = 0; j < m->target_joint_count; j++)
        for (uint32_t k = 0; k < m->entries[j].input_count; k++)
            if (m->entries[j].inputs[k].source >= source_count) {
                snprintf(err, err_size,
                         "target joint %u is driven by source %u, but %u source%s "
                         "given",
                         j, m->entries[j].inputs[k].source, source_count,
                         source_count == 1 ? " is" : "s are");
                return false;
            }
    json_t *root = document(m, target, sources, source_count);
    if (!root) {
        snprintf(err, err_size, "out of memory");
        return false;
    }
    int rc = json_dumpf(root, out, JSON_INDENT(2) | JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(10));
    json_decref(root);
    if (rc != 0 || fputc('\n', out) == EOF || fflush(out) != 0 || ferror(out)) {
        snprintf(err, err_size, "cannot write: %s", strerror(errno));
        return false;
    }
    return true;
}

bool rf_mapfile_write_path(const char *path, const rf_mapping *m, const rf_skeleton *target,
                           const rf_skeleton *const *sources, uint32_t source_count, char *err,
                           size_t err_size)
{
    FILE *out = fopen(path, "wb");
    if (!out) {
        snprintf(err, err_size, "%s: cannot create: %s", path, strerror(errno));
        return false;
    }
    char inner[512];
    bool ok = rf_mapfile_write(out, m, target, sources, source_count, inner, sizeof inner);
    if (fclose(out) != 0 && ok) {
        snprintf(inner, sizeof inner, "cannot write: %s", strerror(errno));
        ok = false;
    }
    if (!ok)
        snprintf(err, err_size, "%s: %s", path, inner);
    return ok;
}
