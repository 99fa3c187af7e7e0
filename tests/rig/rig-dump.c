/* rig-dump [--template] FILE: rigs the mesh of FILE (its rig ignored) with librigauto (the
 * general rigger, or the template rigger) with the axes the file declares and prints the joints
 * ("J index parent x y z") and every vertex with its heaviest joint ("V x y z joint"), for
 * tests/rig/rig-view.py to draw. A development aid; the tests check the same data. */
#include <stdio.h>
#include <string.h>

#include <rigflow/aimport.h>

#include "rig.h"

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
    bool ok = template ? rf_rig_template(r.mesh, &ro, RF_RIG_TEMPLATE_AUTO, &s, &m, &st, NULL,
                                         NULL, err, sizeof err)
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
    rf_skeleton_free(s);
    rf_mesh_free(m);
    rf_ai_result_clear(&r);
    return 0;
}
