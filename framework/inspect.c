/* `rigflow inspect FILE`. Runs a one-node pipeline with the importer the plugins say reads the
 * file (rf_registry_importer_for; with require_skeleton off where the importer has it, so
 * unrigged files still show their meshes) and prints its outputs. Going through the pipeline engine
 * rather than linking the importers keeps the command free of Assimp and shows exactly what a
 * pipeline gets.
 */
#include <stdio.h>
#include <string.h>

#include <jansson.h>

#include "commands.h"
#include "inspect.h"

typedef struct rf_inspect_opts {
    char *clip;
    char *rest;
} rf_inspect_opts;

static bool rf_inspect_declares(const rf_node_desc *d, const char *param)
{
    for (uint32_t i = 0; i < d->param_count; i++)
        if (strcmp(d->params[i].name, param) == 0)
            return true;
    return false;
}

/* The one-node pipeline; the options are set only where the importer declares them. */
static char *rf_inspect_pipeline_json(const rf_node_desc *d, const char *path_param,
                                      const char *path, const rf_inspect_opts *o)
{
    json_t *params = json_pack("{s:s}", path_param, path);
    if (rf_inspect_declares(d, "require_skeleton"))
        json_object_set_new(params, "require_skeleton", json_false());
    if (o->clip && rf_inspect_declares(d, "clip"))
        json_object_set_new(params, "clip", json_string(o->clip));
    if (o->rest && rf_inspect_declares(d, "rest_pose"))
        json_object_set_new(params, "rest_pose", json_string(o->rest));
    json_t *doc =
        json_pack("{s:s, s:i, s:[{s:s, s:s, s:o}]}", "format", "rigflow.pipeline", "version", 1,
                  "nodes", "id", "source", "type", d->type, "params", params);
    char *text = json_dumps(doc, JSON_COMPACT);
    json_decref(doc);
    return text;
}

/* ---- printing ---- */

static const char *rf_inspect_rest_name(const rf_skeleton *s)
{
    if (!RF_HAS_FIELD(s, rf_skeleton, rest_source))
        return "as in the file";
    switch (s->rest_source) {
    case RF_REST_NODE:
        return "node transforms";
    case RF_REST_BIND:
        return "bind pose (the mesh's)";
    default:
        return "as in the file";
    }
}

static void rf_inspect_axis(const char *label, rf_vec3 v)
{
    if (rf_v3_len2(v) == 0)
        printf("  %s: unknown\n", label);
    else
        printf("  %s: (%g %g %g)\n", label, v.x, v.y, v.z);
}

static void rf_inspect_skeleton(const rf_skeleton *s)
{
    printf("skeleton: %u joints, rest pose: %s\n", s->joint_count, rf_inspect_rest_name(s));
    rf_inspect_axis("up", s->up);
    rf_inspect_axis("forward", s->forward);
    if (!s->joint_count)
        return;
    g_autofree rf_xform *world = g_new(rf_xform, s->joint_count);
    g_autofree int *depth = g_new0(int, s->joint_count);
    rf_skeleton_world_rest(s, world);
    printf("  %-4s %-32s %-24s %-30s %s\n", "#", "joint (tree)", "parent", "rest (local)",
           "rest (world)");
    for (uint32_t j = 0; j < s->joint_count; j++) {
        const rf_joint *jt = &s->joints[j];
        depth[j] = jt->parent >= 0 ? depth[jt->parent] + 1 : 0;
        g_autofree char *name = rf_printable(jt->name);
        g_autofree char *parent = rf_printable(jt->parent >= 0 ? s->joints[jt->parent].name : "-");
        g_autofree char *tree = g_strdup_printf("%*s%s", depth[j] * 2, "", name);
        g_autofree char *local =
            g_strdup_printf("(%.4f %.4f %.4f)", jt->rest.t.x, jt->rest.t.y, jt->rest.t.z);
        printf("  %-4u %-32s %-24s %-30s (%.4f %.4f %.4f)%s\n", j, tree, parent, local,
               world[j].t.x, world[j].t.y, world[j].t.z,
               jt->flags & RF_JOINT_UNWEIGHTED ? " unweighted" : "");
    }
}

static void rf_inspect_clips(const rf_clip_list *clips, const rf_animation *a)
{
    if (!clips) { /* importers without a clip list (BVH) have one clip: the animation */
        g_autofree char *name = rf_printable(a && a->name ? a->name : "motion");
        if (a)
            printf("clips: 1\n  0 %-24s %u frames at %g fps (%.3f s)\n", name, a->frame_count,
                   a->fps, a->frame_count > 1 ? (a->frame_count - 1) / a->fps : 0.0);
        return;
    }
    printf("clips: %u%s\n", clips->count, clips->count ? "" : " (none: the rest pose only)");
    for (uint32_t i = 0; i < clips->count; i++) {
        g_autofree char *name = rf_printable(clips->clips[i].name);
        printf("  %-2u %-24s %u frames at %g fps (%.3f s)%s\n", i, name, clips->clips[i].frames,
               clips->clips[i].fps, clips->clips[i].duration,
               (int32_t)i == clips->selected ? "  [imported]" : "");
    }
}

/* The look: counts, then one line per material (its name escaped: bytes from the file). */
static void rf_inspect_look(const rf_mesh *m)
{
    static const char *const modes[] = {"opaque", "mask", "blend"};
    if (!RF_HAS_FIELD(m, rf_mesh, images))
        return;
    printf("look: %u materials, %u images, %u UV sets, %s, %s, %u morph targets\n",
           m->material_count, m->image_count, m->uv_set_count,
           m->colors ? "vertex colours" : "no vertex colours",
           m->tangents ? "tangents" : "no tangents",
           RF_HAS_FIELD(m, rf_mesh, morph_targets) ? m->morph_target_count : 0);
    for (uint32_t i = 0; i < m->material_count && m->materials; i++) {
        const rf_material *t = m->materials[i];
        if (!t)
            continue;
        g_autofree char *name = rf_printable(t->name ? t->name : "");
        printf("  %-2u %-24s base colour %.3g %.3g %.3g %.3g", i, name, t->base_color[0],
               t->base_color[1], t->base_color[2], t->base_color[3]);
        if (t->base_color_texture.image >= 0 &&
            (uint32_t)t->base_color_texture.image < m->image_count)
            printf(" x image %d (%s, %zu bytes)", t->base_color_texture.image,
                   m->images[t->base_color_texture.image]->mime_type,
                   m->images[t->base_color_texture.image]->byte_count);
        printf(", metallic %.3g, roughness %.3g%s%s%s, %s%s\n", t->metallic, t->roughness,
               t->normal_texture.image >= 0 ? ", normal map" : "",
               t->occlusion_texture.image >= 0 ? ", occlusion map" : "",
               t->emissive_texture.image >= 0 ? ", emissive map" : "",
               modes[t->alpha_mode <= 2 ? t->alpha_mode : 0],
               t->double_sided ? ", double-sided" : "");
    }
}

static void rf_inspect_mesh(const rf_mesh *m)
{
    if (!m || !m->vertex_count) {
        printf("meshes: none\n");
        return;
    }
    uint32_t parts = RF_HAS_FIELD(m, rf_mesh, parts) ? m->part_count : 0;
    printf("meshes: %u merged, %u vertices, %u triangles, %s\n", parts ? parts : 1, m->vertex_count,
           m->triangle_count, m->skin_joints ? "skinned (4 weights per vertex)" : "not skinned");
    for (uint32_t i = 0; i < parts; i++) {
        g_autofree char *name = rf_printable(m->parts[i].name);
        printf("  %-2u %-32s %u vertices, %u triangles\n", i, name, m->parts[i].vertex_count,
               m->parts[i].triangle_count);
    }
    rf_inspect_look(m);
}

/* ---- the command ---- */

static int rf_inspect_run(rf_registry *reg, const char *file, const rf_inspect_opts *o)
{
    if (!rf_check_utf8_name("inspect", file))
        return RF_EXIT_RUN;
    const char *path_param = NULL;
    const rf_node_desc *d = rf_registry_importer_for(reg, file, &path_param);
    g_autofree char *shown = rf_printable(file);
    if (!d) {
        fprintf(stderr,
                "rigflow inspect: %s: no installed importer reads this file (see rigflow "
                "plugins)\n",
                shown);
        return RF_EXIT_RUN;
    }
    const char *type = d->type;
    g_autofree char *cwd = g_get_current_dir();
    char *text = rf_inspect_pipeline_json(d, path_param, file, o);
    g_autoptr(GPtrArray) diags = rf_diags_new();
    rf_pipeline *p = text ? rf_pipeline_load_string(text, "inspect", cwd, diags) : NULL;
    free(text);
    int code = p && rf_pipeline_validate(p, reg, diags)
                   ? rf_run_interruptible_diags(p, reg, false, true, diags) /* Ctrl-C: 130 */
                   : RF_EXIT_RUN;
    if (code != RF_EXIT_OK) {
        rf_print_diags(diags, "error");
        rf_pipeline_free(p);
        return code;
    }
    printf("%s (read by %s)\n", shown, type);
    const rf_skeleton *s = rf_pipeline_result(p, "source", "skeleton");
    if (s)
        rf_inspect_skeleton(s);
    rf_inspect_clips(rf_pipeline_result(p, "source", "clips"),
                     rf_pipeline_result(p, "source", "animation"));
    rf_inspect_mesh(rf_pipeline_result(p, "source", "mesh"));
    rf_pipeline_free(p);
    return RF_EXIT_OK;
}

int rf_cmd_inspect(rf_registry *reg, int argc, char **argv)
{
    rf_inspect_opts o = {0};
    const GOptionEntry entries[] = {
        {"clip", 'c', 0, G_OPTION_ARG_STRING, &o.clip, "Clip to import (name or index)", "CLIP"},
        {"rest", 'r', 0, G_OPTION_ARG_STRING, &o.rest, "Rest pose: bind (default) or node", "POSE"},
        {NULL, 0, 0, 0, NULL, NULL, NULL}};
    int code = RF_EXIT_USAGE;
    if (!rf_parse_options("inspect", "FILE",
                          "Show what rigflow imports from a file: the skeleton tree (names, "
                          "parents, rest positions), the clips and the meshes.",
                          entries, &argc, &argv))
        goto out;
    if (argc != 2) {
        fprintf(stderr, "rigflow inspect: expected one FILE (see rigflow inspect --help)\n");
        goto out;
    }
    code = rf_inspect_run(reg, argv[1], &o);
out:
    g_free(o.clip);
    g_free(o.rest);
    return code;
}
