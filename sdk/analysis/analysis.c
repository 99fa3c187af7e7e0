/* Skeleton analysis: runs the stages in order (see analysis-internal.h) and reports. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <rigflow/text.h>

#include "analysis-internal.h"

static void empty_axes(rf_analysis *a)
{
    a->up = rf_v3(0, 1, 0), a->forward = rf_v3(0, 0, 1), a->left = rf_v3(1, 0, 0);
    a->plane_normal = a->left;
    a->up_source = a->forward_source = "default";
    a->size = a->height = 1;
    a->root = RF_NONE;
}

static void work_free(rf_awork *w)
{
    rf_an_grid_reset(w);
    free((void *)w->local);
    free(w->world);
    free(w->file_parent);
    free(w->parent);
    free(w->child_off);
    free(w->child_idx);
    free(w->order);
    free(w->helper);
    free(w->weighted);
    free(w->own_sign);
    free(w->tip_set);
    free(w->center);
    free(w->limb_of);
    free(w->sub_sum);
    free(w->sub_count);
    free(w->sub_len);
    free(w->hash);
    free(w->root_chain);
    free(w->detached);
    free(w->attach_pt);
}

static bool work_alloc(rf_awork *w)
{
    size_t n = w->n;
    w->world = malloc(n * sizeof *w->world);
    w->file_parent = malloc(n * sizeof *w->file_parent);
    w->parent = malloc(n * sizeof *w->parent);
    w->child_off = calloc(n + 1, sizeof *w->child_off);
    w->child_idx = malloc(n * sizeof *w->child_idx);
    w->order = malloc(n * sizeof *w->order);
    w->helper = calloc(n, 1);
    w->weighted = calloc(n, 1);
    w->own_sign = calloc(n, 1);
    w->tip_set = calloc(n, 1);
    w->center = calloc(n, 1);
    w->limb_of = malloc(n * sizeof *w->limb_of);
    w->sub_sum = calloc(n, sizeof *w->sub_sum);
    w->sub_count = calloc(n, sizeof *w->sub_count);
    w->sub_len = calloc(n, sizeof *w->sub_len);
    w->hash = calloc(n, sizeof *w->hash);
    w->root_chain = calloc(n, 1);
    w->detached = calloc(n, 1);
    w->attach_pt = calloc(n, sizeof *w->attach_pt);
    return w->world && w->file_parent && w->parent && w->child_off && w->child_idx && w->order &&
           w->helper && w->weighted && w->own_sign && w->tip_set && w->center && w->limb_of &&
           w->sub_sum && w->sub_count && w->sub_len && w->hash && w->root_chain && w->detached &&
           w->attach_pt;
}

static bool run_stages(rf_awork *w)
{
    if (!rf_an_prepare(w) || !rf_an_subtree_stats(w) || !rf_an_symmetry(w) || !rf_an_classify(w) ||
        !rf_an_axes(w))
        return false;
    for (uint32_t j = 0; j < w->n; j++)
        w->attach_pt[j] =
            w->parent[j] >= 0 ? rf_an_pos(w, (uint32_t)w->parent[j]) : rf_an_pos(w, j);
    if (!rf_an_body(w))
        return false;
    rf_an_grid_reset(w); /* the body has its own order */
    /* Again on the body tree: parts attached by proximity (feet under the ground root, legs of
     * another root) now count with their limbs. */
    if (!rf_an_axes(w) || !rf_an_recentre(w) || !rf_an_classify(w) || !rf_an_mirrors(w))
        return false;
    for (uint32_t j = 0; j < w->n; j++)
        w->a->joints[j].logical_parent = w->helper[j] ? w->file_parent[j] : w->parent[j];
    return rf_an_sections(w);
}

/* A forced axis is a direction only: scaled so that its largest component is 1, since a length
 * such as 1e300 overflows to infinity when squared and normalises to zero; dropped (so detected)
 * when it is not finite or next to nothing. */
static rf_vec3 forced_axis(rf_vec3 v)
{
    double m = fmax(fabs(v.x), fmax(fabs(v.y), fabs(v.z)));
    if (!isfinite(v.x + v.y + v.z) || !(m > 1e-12))
        return rf_v3(0, 0, 0);
    return rf_v3_scale(v, 1.0 / m);
}

rf_analysis *rf_analyze(const rf_skeleton *skeleton, const rf_analysis_options *opts)
{
    rf_analysis *a = calloc(1, sizeof *a);
    if (!a)
        return NULL;
    empty_axes(a);
    uint32_t n = skeleton && skeleton->joints ? skeleton->joint_count : 0;
    if (n == 0)
        return a;
    a->joint_count = n;
    a->joints = calloc(n, sizeof *a->joints);
    rf_awork w = {0};
    w.skel = skeleton, w.a = a, w.n = n, w.top = RF_NONE, w.rear = w.front = RF_NONE;
    if (opts)
        w.opt = *opts;
    w.opt.up = forced_axis(w.opt.up), w.opt.forward = forced_axis(w.opt.forward);
    for (uint32_t j = 0; a->joints && j < n; j++)
        a->joints[j].section = a->joints[j].mirror = a->joints[j].logical_parent = RF_NONE;
    bool ok = a->joints && work_alloc(&w) && run_stages(&w);
    work_free(&w);
    if (!ok) {
        rf_analysis_free(a);
        return NULL;
    }
    return a;
}

void rf_analysis_free(rf_analysis *a)
{
    if (!a)
        return;
    free(a->joints);
    free(a->sections);
    free(a->section_joints);
    free(a);
}

static const char *const type_names[RF_SECTION_TYPE_COUNT] = {
    "none", "root", "spine", "head", "tail", "arm", "hand", "leg", "foot", "appendage", "helper",
};

const char *rf_section_type_name(rf_section_type type)
{
    return (unsigned)type < RF_SECTION_TYPE_COUNT ? type_names[type] : "none";
}

bool rf_section_type_parse(const char *name, rf_section_type *type)
{
    for (int t = 0; name && t < RF_SECTION_TYPE_COUNT; t++)
        if (strcmp(name, type_names[t]) == 0) {
            *type = (rf_section_type)t;
            return true;
        }
    return false;
}

const char *rf_side_name(rf_side side)
{
    return side == RF_SIDE_LEFT ? "left" : side == RF_SIDE_RIGHT ? "right" : "center";
}

static void print_section(const rf_analysis *a, const rf_skeleton *skel, uint32_t s, FILE *out)
{
    const rf_section *sec = &a->sections[s];
    char buf[32];
    fprintf(out, "  [%u] %s %s%s%s%s: %u bone%s, length %.4g, at body %.2f", s,
            rf_side_name(sec->side), rf_section_type_name(sec->type),
            sec->flags & RF_SECFL_WING ? " (wing)" : "",
            sec->flags & RF_SECFL_FAN ? " (digit)" : "",
            sec->flags & RF_SECFL_REVERSE ? " (reverse)" : "", sec->bone_count,
            sec->bone_count == 1 ? "" : "s", sec->length, sec->body_pos);
    if (sec->pair_count > 1)
        fprintf(out, ", rank %u of %u", sec->pair_rank + 1, sec->pair_count);
    if (sec->mirror >= 0)
        fprintf(out, ", mirrors [%d]", sec->mirror);
    if (sec->parent >= 0)
        fprintf(out, ", on [%d]", sec->parent);
    fputs(":", out);
    for (uint32_t k = 0; k < sec->bone_count; k++) {
        uint32_t j = a->section_joints[sec->first + k];
        const rf_joint_info *ji = &a->joints[j];
        fprintf(out, " %s", rf_joint_label(skel, j, buf, sizeof buf));
        if (ji->flags & (RF_JI_CONTROL | RF_JI_END_MARKER))
            fputs(ji->flags & RF_JI_CONTROL ? "(ctrl)" : "(end)", out);
    }
    fputc('\n', out);
}

void rf_analysis_print(const rf_analysis *a, const rf_skeleton *skeleton, FILE *out)
{
    fprintf(out, "up      (%.3f %.3f %.3f) from %s, confidence %.2f\n", a->up.x, a->up.y, a->up.z,
            a->up_source, a->up_confidence);
    fputs("        cues:", out);
    for (int i = 0; i < RF_UP_CUE_COUNT; i++)
        if (a->up_cues[i] != 0)
            fprintf(out, " %s %+.2f", rf_up_cue_names[i], a->up_cues[i]);
    fputc('\n', out);
    int up_dissent = rf_up_dissent(a);
    if (up_dissent >= 0)
        fprintf(out, "warning: up cues disagree (%s prefers another axis): check up, or force it\n",
                rf_up_cue_names[up_dissent]);
    fprintf(out, "forward (%.3f %.3f %.3f) from %s, confidence %.2f\n", a->forward.x, a->forward.y,
            a->forward.z, a->forward_source, a->forward_confidence);
    fputs("        cues:", out);
    for (int i = 0; i < RF_FORWARD_CUE_COUNT; i++)
        if (a->forward_cues[i] != 0)
            fprintf(out, " %s %+.2f", rf_forward_cue_names[i], a->forward_cues[i]);
    fputc('\n', out);
    int dissent = rf_forward_dissent(a);
    if (dissent >= 0)
        fprintf(out,
                "warning: facing cues disagree (%s votes the other way): check forward, or "
                "force it\n",
                rf_forward_cue_names[dissent]);
    fprintf(out, "left    (%.3f %.3f %.3f); symmetry %.2f; size %.4g, height %.4g\n", a->left.x,
            a->left.y, a->left.z, a->symmetry, a->size, a->height);
    fprintf(out, "%u sections:\n", a->section_count);
    for (uint32_t s = 0; s < a->section_count; s++)
        print_section(a, skeleton, s, out);
}
