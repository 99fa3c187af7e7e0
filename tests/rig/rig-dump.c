/* rig-dump [--template] FILE: rigs the mesh of FILE (its rig ignored) with librigauto (the
 * general rigger, or the template rigger) with the axes the file declares and prints the joints
 * ("J index parent x y z") and every vertex with its heaviest joint ("V x y z joint"), for
 * tests/rig/rig-view.py to draw, and on stderr how the skeleton analysis reads the rig. A
 * development aid; the tests check the same data. */
#include <stdio.h>
#include <string.h>

#include <rigflow/aimport.h>
#include <rigflow/analysis.h>

#include "rig.h"

/* How the skeleton analysis (what the matcher reads) reads the rig, on stderr: its up and
 * facing with where each came from, and its sections with their joints. */
static void rf_rig_dump_analysis(const rf_skeleton *s)
{
    rf_analysis_options ao = {.use_bind_pose = true};
    rf_analysis *a = rf_analyze(s, &ao);
    if (!a)
        return;
    fprintf(stderr, "analysis: up %.2f %.2f %.2f (%s, %.2f), forward %.2f %.2f %.2f (%s, %.2f)\n",
            a->up.x, a->up.y, a->up.z, a->up_source, a->up_confidence, a->forward.x, a->forward.y,
            a->forward.z, a->forward_source, a->forward_confidence);
    fprintf(stderr, "analysis: forward cues");
    for (int i = 0; i < RF_FORWARD_CUE_COUNT; i++)
        fprintf(stderr, " %s %.2f", rf_forward_cue_names[i], a->forward_cues[i]);
    fprintf(stderr, "\n");
    for (uint32_t i = 0; i < a->section_count; i++) {
        const rf_section *sec = &a->sections[i];
        fprintf(stderr, "analysis: [%u] %s side %d on [%d], length %.3f:", i,
                rf_section_type_name(sec->type), (int)sec->side, sec->parent, sec->length);
        for (uint32_t k = 0; k < sec->bone_count; k++)
            fprintf(stderr, " %s", s->joints[a->section_joints[sec->first + k]].name);
        fprintf(stderr, "\n");
    }
    rf_analysis_free(a);
}

int main(int argc, char **argv)
{
    bool template = argc == 3 && strcmp(argv[1], "--template") == 0;
    if (argc != 2 && !template) {
        fprintf(stderr, "usage: rig-dump [--template] FILE\n");
        return 2;
    }
    argv += template;
    rf_ai_options o = {.ignore_rig = true};
    rf_ai_result r;
    char err[1024];
    if (!rf_ai_import(argv[1], &o, &r, NULL, NULL, err, sizeof err)) {
        fprintf(stderr, "rig-dump: %s\n", err);
        return 1;
    }
    rf_skeleton *s;
    rf_mesh *m;
    rf_rig_stats st;
    /* The axes the file declares, as the pipelines' rigger node and rig-bench pass them: without
     * them the analysis may read the body another way and the rig differs from theirs. */
    rf_rig_options ro = {0};
    if (r.skeleton)
        ro.up = r.skeleton->up, ro.forward = r.skeleton->forward;
    bool ok = template ? rf_rig_template(r.mesh, &ro, RF_RIG_TEMPLATE_AUTO, &s, &m, &st, NULL, NULL,
                                         err, sizeof err)
                       : rf_rig_general(r.mesh, &ro, &s, &m, &st, NULL, NULL, err, sizeof err);
    if (!ok) {
        fprintf(stderr, "rig-dump: %s: %s\n", argv[1], err);
        rf_ai_result_clear(&r);
        return 1;
    }
    rf_xform *w = calloc(s->joint_count + 1, sizeof *w);
    rf_skeleton_world_rest(s, w);
    for (uint32_t j = 0; j < s->joint_count; j++)
        printf("J %u %d %g %g %g %s\n", j, s->joints[j].parent, w[j].t.x, w[j].t.y, w[j].t.z,
               s->joints[j].name);
    for (uint32_t v = 0; v < m->vertex_count; v++)
        printf("V %g %g %g %u\n", m->positions[v * 3], m->positions[v * 3 + 1],
               m->positions[v * 3 + 2], m->skin_joints[v * 4]);
    fprintf(stderr,
            "%u joints, %u vertices, %u welded, %u proxy triangles, %u parts (%u specks), %u heat, "
            "%u fallback, %u unseen\n",
            st.joints, st.vertices, st.welded, st.proxy_triangles, st.parts, st.specks,
            st.heat_vertices, st.fallback_vertices, st.unseen_vertices);
    free(w);
    rf_rig_dump_analysis(s);
    rf_skeleton_free(s);
    rf_mesh_free(m);
    rf_ai_result_clear(&r);
    return 0;
}
