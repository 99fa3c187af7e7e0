/* Ground-truth files and scoring (see truth.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rigflow/aimport.h"
#include "rigflow/analysis.h"
#include "rigflow/bvh.h"
#include "truth.h"

const char *const truth_type_names[16] = {
    "none", "root", "spine", "head", "tail", "arm", "hand", "leg", "foot", "appendage", "helper",
};

static int type_index(const char *name)
{
    for (int i = 0; i < 16 && truth_type_names[i]; i++)
        if (name && strcmp(name, truth_type_names[i]) == 0)
            return i;
    return 0;
}

static bool header_line(truth *t, const char *key, const char *value)
{
    if (strcmp(key, "source") == 0)
        snprintf(t->source, sizeof t->source, "%s", value);
    else if (strcmp(key, "target") == 0)
        snprintf(t->target, sizeof t->target, "%s", value);
    else if (strcmp(key, "kind") == 0)
        t->creature = strcmp(value, "creature") == 0;
    else
        return false;
    return true;
}

static bool joint_line(truth *t, char *line, int at)
{
    truth_joint *j = &t->joints[t->count];
    memset(j, 0, sizeof *j);
    char *tok = strtok(line, " \t\n");
    snprintf(j->name, sizeof j->name, "%s", tok);
    tok = strtok(NULL, " \t\n");
    if (!tok || strlen(tok) != 1 || !strchr("LRC", tok[0])) {
        fprintf(stderr, "%s:%d: expected JOINT L|R|C ACCEPTED...\n", t->file, at);
        return false;
    }
    j->side = tok[0];
    while ((tok = strtok(NULL, " \t\n")) && j->accept_count < TRUTH_MAX_ACCEPT)
        snprintf(j->accept[j->accept_count++], sizeof j->accept[0], "%s", tok);
    if (j->accept_count == 0) {
        fprintf(stderr, "%s:%d: %s accepts nothing (use - for unmapped)\n", t->file, at, j->name);
        return false;
    }
    t->count++;
    return true;
}

bool truth_read(const char *path, truth *t)
{
    memset(t, 0, sizeof *t);
    snprintf(t->file, sizeof t->file, "%s", path);
    FILE *f = fopen(path, "r");
    if (!f) {
        fprintf(stderr, "%s: cannot open\n", path);
        return false;
    }
    char line[1024];
    int at = 0, cap = 0;
    bool ok = true;
    while (ok && fgets(line, sizeof line, f)) {
        at++;
        char key[64], value[512];
        if (line[0] == '#' || line[strspn(line, " \t\n")] == '\0')
            continue;
        if (sscanf(line, "%63s %511s", key, value) == 2 && header_line(t, key, value))
            continue;
        if (t->count == cap) {
            cap = cap ? 2 * cap : 64;
            truth_joint *j = realloc(t->joints, (size_t)cap * sizeof *j);
            if (!j)
                break;
            t->joints = j;
        }
        ok = joint_line(t, line, at);
    }
    fclose(f);
    return ok && t->source[0] && t->target[0];
}

void truth_free(truth *t)
{
    free(t->joints);
    t->joints = NULL;
}

/* The matcher node's rule when a clip is connected: a rest pose that is no body is replaced
 * by the pose of the clip that shows the body best. */
static void use_clip_pose(rf_skeleton *s, const rf_animation *a)
{
    if (!rf_pose_degenerate(s))
        return;
    int32_t frame;
    rf_skeleton *v = rf_posed_best(s, a, &frame);
    for (uint32_t j = 0; v && j < s->joint_count; j++)
        s->joints[j].rest = v->joints[j].rest;
    rf_posed_free(v);
}

rf_skeleton *truth_load(const char *data_dir, const char *rel)
{
    char path[1024], err[1024];
    snprintf(path, sizeof path, "%s/%s", data_dir, rel);
    size_t len = strlen(path);
    if (len > 4 && strcmp(path + len - 4, ".bvh") == 0) {
        rf_skeleton *s = NULL;
        rf_animation *a = NULL;
        if (!rf_bvh_read_file(path, NULL, &s, &a, err, sizeof err)) {
            fprintf(stderr, "%s\n", err);
            return NULL;
        }
        use_clip_pose(s, a);
        rf_animation_free(a);
        return s;
    }
    rf_ai_result r = {0};
    if (!rf_ai_import(path, NULL, &r, NULL, NULL, err, sizeof err)) {
        fprintf(stderr, "%s\n", err);
        return NULL;
    }
    rf_skeleton *s = r.skeleton;
    r.skeleton = NULL;
    rf_ai_result_clear(&r);
    return s;
}

static const truth_joint *find(const truth *t, const char *name)
{
    for (int i = 0; name && i < t->count; i++)
        if (strcmp(t->joints[i].name, name) == 0)
            return &t->joints[i];
    return NULL;
}

static bool accepts(const truth_joint *j, const char *source_name)
{
    for (int i = 0; i < j->accept_count; i++)
        if (strcmp(j->accept[i], source_name ? source_name : "-") == 0)
            return true;
    return false;
}

/* Mapped onto a source joint the truth gives to a joint of the other side. */
static bool swapped(const truth *t, const truth_joint *j, const char *source_name)
{
    if (j->side == 'C' || !source_name)
        return false;
    for (int i = 0; i < t->count; i++)
        if (t->joints[i].side != 'C' && t->joints[i].side != j->side &&
            accepts(&t->joints[i], source_name))
            return true;
    return false;
}

/* Every target joint is listed and every accepted name exists: typos must not pass silently. */
static void check_names(const truth *t, const rf_skeleton *target, const rf_skeleton *source,
                        truth_score *s, FILE *verbose)
{
    for (uint32_t j = 0; j < target->joint_count; j++)
        if (!find(t, target->joints[j].name)) {
            s->missing++;
            if (verbose)
                fprintf(verbose, "  %s: target joint %s is not in the truth file\n", t->file,
                        target->joints[j].name);
        }
    for (int i = 0; i < t->count; i++) {
        bool known = rf_skeleton_find(target, t->joints[i].name) >= 0;
        for (int k = 0; k < t->joints[i].accept_count; k++)
            known = known && (strcmp(t->joints[i].accept[k], "-") == 0 ||
                              rf_skeleton_find(source, t->joints[i].accept[k]) >= 0);
        if (!known) {
            s->missing++;
            if (verbose)
                fprintf(verbose, "  %s: line for %s names a joint the skeletons lack\n", t->file,
                        t->joints[i].name);
        }
    }
}

void truth_score_mapping(const truth *t, const rf_mapping *m, const rf_skeleton *target,
                         const rf_skeleton *source, truth_score *s, FILE *verbose)
{
    memset(s, 0, sizeof *s);
    check_names(t, target, source, s, verbose);
    for (uint32_t j = 0; j < target->joint_count && j < m->target_joint_count; j++) {
        const truth_joint *tj = find(t, target->joints[j].name);
        if (!tj)
            continue;
        const rf_map_entry *e = &m->entries[j];
        const char *got = e->input_count ? source->joints[e->inputs[0].joint].name : NULL;
        bool ok = accepts(tj, got);
        int type =
            RF_HAS_FIELD(m, rf_mapping, sections) && m->sections ? type_index(m->sections[j]) : 0;
        s->joints++, s->correct += ok;
        s->by_type_joints[type]++, s->by_type_correct[type] += ok;
        if (swapped(t, tj, got))
            s->swapped++;
        if (!ok && verbose)
            fprintf(verbose, "    wrong: %-20s (%s) <- %-18s accepted:", tj->name,
                    truth_type_names[type], got ? got : "(unmapped)");
        for (int k = 0; !ok && verbose && k < tj->accept_count; k++)
            fprintf(verbose, " %s", tj->accept[k]);
        if (!ok && verbose)
            fputc('\n', verbose);
    }
}
