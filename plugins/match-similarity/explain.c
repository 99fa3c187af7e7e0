/* `--explain`: what the skeletal-similarity matcher saw and why it chose what it chose. */
#include <stdlib.h>
#include <string.h>

#include <rigflow/text.h>

#include "similarity.h"

static void print_candidate(const rf_ms_candidate *c, const rf_skeleton *const *sources, FILE *out)
{
    char buf[256];
    fprintf(out, "      %u:%-22s %7.2f  ", c->source,
            rf_joint_label(sources ? sources[c->source] : NULL, c->joint, buf, sizeof buf),
            c->total);
    for (int i = 0; i < RF_MS_METRIC_COUNT; i++)
        if (c->metrics[i] != 0)
            fprintf(out, " %s=%.4g", rf_ms_metric_names[i], c->metrics[i]);
    fputc('\n', out);
}

/* The metric that put a ahead of b most, and by how much. */
static int deciding_metric(const rf_ms_candidate *a, const rf_ms_candidate *b, double *by)
{
    int best = -1;
    for (int i = 0; i < RF_MS_METRIC_COUNT; i++) {
        double d = a->metrics[i] - b->metrics[i];
        if (d > 0 && (best < 0 || d > *by))
            best = i, *by = d;
    }
    return best;
}

/* Why the joint got what it got: the winner against the runner-up, the section alignment
 * overruling the best candidate, or nothing good enough. */
static void print_why(const rf_ms_explain *e, const rf_map_entry *en,
                      const rf_skeleton *const *sources, uint32_t j, FILE *out)
{
    char buf[256];
    uint8_t n = e->top_count ? e->top_count[j] : 0;
    const rf_ms_candidate *top = e->top ? &e->top[(size_t)j * 3] : NULL;
    const rf_map_input *in = en && en->input_count ? &en->inputs[0] : NULL;
    fputs("    why: ", out);
    /* The girdle=neck rules that settle a joint outright, by their settled code (3 on). */
    static const char *const settled_why[] = {
        "a girdle joint whose bone runs past the source's neck pivot takes the source's neck",
        "the girdle joint ending a trunk without a head takes the source's head",
        "a trunk joint lying behind where the source's reverse spine starts takes the reverse "
        "spine's joint there",
        "a trunk rooted at the front, against a source's rooted at the rear, takes the source "
        "spine's joint where it lies",
        "its match carries no skin: it takes the source joint that holds the skin there",
    };
    unsigned code = in && e->settled ? e->settled[j] : 0;
    if (code >= 3 && code - 3 < sizeof settled_why / sizeof *settled_why) {
        fprintf(out, "%s (girdle=neck)\n", settled_why[code - 3]);
        return;
    }
    if (n == 0) {
        fputs(in ? "placed by the section alignment\n" : "no candidate of a kind that may match\n",
              out);
        return;
    }
    const char *best =
        rf_joint_label(sources ? sources[top[0].source] : NULL, top[0].joint, buf, sizeof buf);
    if (!in) {
        if (top[0].total < e->threshold)
            fprintf(out, "its best candidate, %u:%s, scores %.2f, under the threshold %.0f\n",
                    top[0].source, best, top[0].total, e->threshold);
        else
            fprintf(out,
                    "left out by the section alignment (%u:%s scored %.2f alone, but its "
                    "section's joints went to joints at their places)\n",
                    top[0].source, best, top[0].total);
        return;
    }
    if (in->source != top[0].source || in->joint != top[0].joint) {
        fprintf(out,
                "placed by the section alignment, over %u:%s that scored best alone "
                "(%.2f): the joints of a section are assigned in order\n",
                top[0].source, best, top[0].total);
        return;
    }
    if (n == 1) {
        fputs("the only candidate\n", out);
        return;
    }
    double by = 0;
    int m = deciding_metric(&top[0], &top[1], &by);
    fprintf(out, "beat %u:%s by %.2f", top[1].source,
            rf_joint_label(sources ? sources[top[1].source] : NULL, top[1].joint, buf, sizeof buf),
            top[0].total - top[1].total);
    if (m >= 0)
        fprintf(out, ", decided by %s (+%.2f)", rf_ms_metric_names[m], by);
    fputc('\n', out);
}

static void print_joint(const rf_ms_explain *e, const rf_mapping *m, const rf_skeleton *target,
                        const rf_skeleton *const *sources, uint32_t j, FILE *out)
{
    char buf[256];
    const rf_joint_info *ji = &e->target->joints[j];
    const char *type =
        ji->section >= 0 ? rf_section_type_name(e->target->sections[ji->section].type) : "none";
    fprintf(out, "%s (%s %s)", rf_joint_label(target, j, buf, sizeof buf), rf_side_name(ji->side),
            type);
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
    print_why(e, en, sources, j, out);
    for (uint32_t k = 0; e->top_count && k < e->top_count[j]; k++)
        print_candidate(&e->top[(size_t)j * 3 + k], sources, out);
}

/* Facing read from cues that disagree: every joint of one side may be on the other. */
static void facing_warning(const rf_analysis *a, const char *what, FILE *out)
{
    bool target = strcmp(what, "the target") == 0;
    int u = rf_up_dissent(a);
    if (u >= 0)
        fprintf(out,
                "warning: %s's up axis is uncertain (up from %s, confidence %.2f, but %s prefers "
                "another axis): if its sides or limbs come out wrong, force the axis (-p "
                "map.%s_up=...)\n",
                what, a->up_source, a->up_confidence, rf_up_cue_names[u],
                target ? "target" : "source");
    int d = rf_forward_dissent(a);
    if (d < 0)
        return;
    fprintf(out,
            "warning: %s's facing is uncertain (forward from %s, confidence %.2f, but %s votes "
            "the other way): if its sides come out swapped, force the axis (-p "
            "map.%s_forward=...)\n",
            what, a->forward_source, a->forward_confidence, rf_forward_cue_names[d],
            target ? "target" : "source");
}

void rf_ms_explain_print(const rf_ms_explain *e, const rf_mapping *m, const rf_skeleton *target,
                         const rf_skeleton *const *sources, FILE *out)
{
    if (!e->target)
        return;
    facing_warning(e->target, "the target", out);
    for (uint32_t k = 0; k < e->source_count; k++) {
        char what[32];
        snprintf(what, sizeof what, "source %u", k);
        facing_warning(e->sources[k], what, out);
    }
    if (e->gait_legs)
        fprintf(out,
                "gait: %u forelegs stand on the floor and every source walks on two legs: each "
                "foreleg takes the source's leg of its side half a cycle later (mirrored), a trot "
                "(-p map.forelegs=arms keeps the arms)\n",
                e->gait_legs);
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
    free(e->settled);
    memset(e, 0, sizeof *e);
}
