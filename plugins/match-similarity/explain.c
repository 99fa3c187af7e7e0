/* `--explain`: what the skeletal-similarity matcher saw and why it chose what it chose. */
#include <stdlib.h>
#include <string.h>

#include <rigflow/text.h>

#include "similarity.h"

static void print_candidate(const rf_ms_candidate *c, const rf_skeleton *const *sources, FILE *out)
{
    char buf[256];
    fprintf(out, "      %u:%-22s %7.2f  ", c->source,
            rf_joint_label(sources ? sources[c->source] : NULL, c->joint, buf, sizeof buf), c->total);
    for (int i = 0; i < RF_MS_METRIC_COUNT; i++)
        if (c->metrics[i] != 0)
            fprintf(out, " %s=%.4g", rf_ms_metric_names[i], c->metrics[i]);
    fputc('\n', out);
}

static void print_joint(const rf_ms_explain *e, const rf_mapping *m, const rf_skeleton *target,
                        const rf_skeleton *const *sources, uint32_t j, FILE *out)
{
    char buf[256];
    const rf_joint_info *ji = &e->target->joints[j];
    const char *type =
        ji->section >= 0 ? rf_section_type_name(e->target->sections[ji->section].type) : "none";
    fprintf(out, "%s (%s %s)", rf_joint_label(target, j, buf, sizeof buf), rf_side_name(ji->side), type);
    const rf_map_entry *en = m && j < m->target_joint_count ? &m->entries[j] : NULL;
    if (en && en->input_count) {
        const rf_map_input *in = &en->inputs[0];
        fprintf(out, " <- %u:%s, score %.2f%s%s\n", in->source,
                rf_joint_label(sources ? sources[in->source] : NULL, in->joint, buf, sizeof buf),
                en->score, in->flags & RF_MAP_REVERSE ? ", reversed" : "",
                in->flags & RF_MAP_MIRROR ? ", mirrored" : "");
    } else {
        fputs(" unmapped\n", out);
    }
    for (uint32_t k = 0; e->top_count && k < e->top_count[j]; k++)
        print_candidate(&e->top[(size_t)j * 3 + k], sources, out);
}

void rf_ms_explain_print(const rf_ms_explain *e, const rf_mapping *m, const rf_skeleton *target,
                         const rf_skeleton *const *sources, FILE *out)
{
    if (!e->target)
        return;
    fprintf(out, "Target joints, each with its three best candidates (source:joint total "
                 "metrics):\n");
    for (uint32_t j = 0; j < e->joint_count; j++)
        print_joint(e, m, target, sources, j, out);
    fputs("\nTarget ", out);
    rf_text_fputs(target && target->name ? target->name : "skeleton", out, 0);
    fputs(":\n", out);
    rf_analysis_print(e->target, target, out);
    for (uint32_t k = 0; k < e->source_count; k++) {
        fprintf(out, "\nSource %u ", k);
        rf_text_fputs(sources && sources[k]->name ? sources[k]->name : "skeleton", out, 0);
        fputs(":\n", out);
        rf_analysis_print(e->sources[k], sources ? sources[k] : NULL, out);
    }
}

void rf_ms_explain_clear(rf_ms_explain *e)
{
    rf_analysis_free(e->target);
    for (uint32_t k = 0; e->sources && k < e->source_count; k++)
        rf_analysis_free(e->sources[k]);
    free(e->sources);
    free(e->top);
    free(e->top_count);
    memset(e, 0, sizeof *e);
}
