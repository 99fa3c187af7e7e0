/* rig-bench --look: the animated result judged as a person sees it, a mesh moving on a floor.
 * For each model and rigger a second graph is run through the engine, the graph of
 * pipelines/scan-to-animation.json with the bench's rigger and without the export, so the
 * figures are the ones a user gets from that pipeline; retarget.measure writes them as JSON into
 * a folder of the bench's own, and its line goes to a stream that is not the CSV. The rigger
 * runs again (it is deterministic, and fast beside the retarget): the bench's own graph fails as
 * a whole when any node does, and a look that fails must not take the rig's row with it. */
#include <errno.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <rigflow/text.h>

#include "commands.h"
#include "rig-bench-look.h"

bool rf_rig_look_begin(rf_rig_look_setup *s, const char *motion, int frames)
{
    memset(s, 0, sizeof *s);
    if (!motion)
        return true;
    if (frames < 2) {
        fprintf(stderr, "rigflow rig-bench: --look-frames: expected 2 frames or more\n");
        return false;
    }
    if (!g_file_test(motion, G_FILE_TEST_IS_REGULAR)) {
        g_autofree char *shown = rf_printable(motion);
        fprintf(stderr, "rigflow rig-bench: --look: %s: no such file\n", shown);
        return false;
    }
    if (!rf_check_utf8_name("rig-bench", motion))
        return false;
    g_autoptr(GError) err = NULL;
    s->dir = g_dir_make_tmp("rigflow-look-XXXXXX", &err);
    s->lines = fopen("/dev/null", "w");
    if (!s->dir || !s->lines) {
        fprintf(stderr, "rigflow rig-bench: --look: cannot make a temporary folder: %s\n",
                err ? err->message : g_strerror(errno));
        rf_rig_look_end(s);
        return false;
    }
    s->motion = g_strdup(motion);
    s->frames = frames;
    return true;
}

void rf_rig_look_end(rf_rig_look_setup *s)
{
    if (s->dir) {
        g_autofree char *json = g_build_filename(s->dir, "measure.json", NULL);
        (void)remove(json);
        (void)remove(s->dir);
    }
    if (s->lines)
        fclose(s->lines);
    g_free(s->dir), g_free(s->motion);
    memset(s, 0, sizeof *s);
}

void rf_rig_look_none(rf_rig_look *l, const char *status)
{
    l->stretch_p99 = l->part_p99 = l->seam_p99 = l->floor_median = l->floor_p95 = NAN;
    l->joint[0] = '\0';
    g_strlcpy(l->status, status, sizeof l->status);
}

static bool look_has_input(const rf_node_desc *d, const char *name)
{
    for (uint32_t i = 0; i < d->input_count; i++)
        if (!strcmp(d->inputs[i].name, name))
            return true;
    return false;
}

static json_t *look_node(json_t *nodes, const char *id, const char *type)
{
    json_t *n = json_pack("{s:s, s:s, s:{}, s:{}}", "id", id, "type", type, "inputs", "params");
    /* json_array_append_new releases n when it fails (out of memory): NULL then, and the graph
     * misses the node, which the pipeline's validation names */
    return n && json_array_append_new(nodes, n) == 0 ? n : NULL;
}

static void look_in(json_t *node, const char *port, const char *from, bool list)
{
    json_object_set_new(json_object_get(node, "inputs"), port,
                        list ? json_pack("[s]", from) : json_string(from));
}

static void look_param(json_t *node, const char *name, json_t *value)
{
    json_object_set_new(json_object_get(node, "params"), name, value);
}

/* The retarget's and the measure's shared inputs: the motion, the new rig and the mapping. */
static void look_sources(json_t *node)
{
    look_in(node, "sources", "motion.animation", true);
    look_in(node, "source_skeletons", "motion.skeleton", true);
    look_in(node, "target", "rig.skeleton", false);
    look_in(node, "mapping", "map.mapping", false);
    look_in(node, "mesh", "rig.mesh", false);
}

/* pipelines/scan-to-animation.json's graph (its nodes and links, the retarget cut at the last
 * frame asked for) with `rigger`; NULL with why. */
static json_t *look_graph(const rf_registry *reg, const rf_rig_look_setup *s,
                          const rf_node_desc *rigger, const char *model, const char *json,
                          char *why, size_t n)
{
    const char *mesh_param = NULL, *motion_param = NULL;
    const rf_node_desc *mesh_imp = rf_registry_importer_for(reg, model, &mesh_param);
    const rf_node_desc *motion_imp = rf_registry_importer_for(reg, s->motion, &motion_param);
    if (!mesh_imp || !motion_imp) {
        snprintf(why, n, "no importer reads the %s", mesh_imp ? "motion" : "model");
        return NULL;
    }
    json_t *graph =
        json_pack("{s:s, s:i, s:[]}", "format", "rigflow.pipeline", "version", 1, "nodes");
    json_t *nodes = json_object_get(graph, "nodes");
    if (!nodes) {
        json_decref(graph);
        snprintf(why, n, "out of memory building the look's pipeline");
        return NULL;
    }
    json_t *mesh = look_node(nodes, "mesh", mesh_imp->type);
    look_param(mesh, mesh_param, json_string(model));
    look_param(mesh, "require_skeleton", json_false());
    look_param(mesh, "ignore_rig", json_true());
    json_t *rig = look_node(nodes, "rig", rigger->type);
    look_in(rig, "mesh", "mesh.mesh", false);
    if (look_has_input(rigger, "axes") && !s->no_axes)
        look_in(rig, "axes", "mesh.skeleton", false);
    look_param(look_node(nodes, "motion", motion_imp->type), motion_param, json_string(s->motion));
    json_t *map = look_node(nodes, "map", "skeletal-similarity");
    look_in(map, "target", "rig.skeleton", false);
    look_in(map, "sources", "motion.skeleton", true);
    look_in(map, "source_animations", "motion.animation", true);
    look_node(nodes, "ik", "ik.twobone");
    json_t *rt = look_node(nodes, "retarget", "retarget");
    look_sources(rt);
    look_in(rt, "ik", "ik.solver", false);
    look_param(rt, "last_frame", json_integer(s->frames - 1));
    json_t *measure = look_node(nodes, "measure", "retarget.measure");
    look_sources(measure);
    look_in(measure, "animation", "retarget.animation", false);
    look_param(measure, "path", json_string(json));
    return graph;
}

/* A number of the measure's "mesh" object in %, NaN when absent. */
static double look_pct(json_t *mesh, const char *key)
{
    json_t *v = json_object_get(mesh, key);
    return json_is_number(v) ? 100 * json_number_value(v) : NAN;
}

/* The measure's JSON report into out. */
static void look_read(const char *json, rf_rig_look *out)
{
    json_error_t err;
    json_t *report = json_load_file(json, 0, &err);
    json_t *mesh = json_object_get(report, "mesh"), *bones = json_object_get(report, "bones");
    if (!report)
        snprintf(out->status, sizeof out->status, "error: the measure's report: %s", err.text);
    else if (!json_is_object(mesh))
        snprintf(out->status, sizeof out->status, "no mesh measures (a mesh without skin?)");
    else if (json_is_true(json_object_get(mesh, "rigid")))
        snprintf(out->status, sizeof out->status, "no skin: the mesh moved rigidly");
    else if (json_is_integer(bones) && json_integer_value(bones) <= 0)
        /* the matcher mapped too little for any bone to follow the motion (a collapsed source):
         * the mesh barely moves and its figures would read as the best look of all */
        snprintf(out->status, sizeof out->status,
                 "not measured: the motion moves no bone of the rig (too little mapped)");
    else {
        out->stretch_p99 = look_pct(mesh, "stretch_p99");
        out->part_p99 = look_pct(mesh, "part_stretch_p99");
        out->seam_p99 = look_pct(mesh, "seam_p99");
        out->floor_median = look_pct(mesh, "floor_median");
        out->floor_p95 = look_pct(mesh, "floor_p95");
        const char *joint = json_string_value(json_object_get(mesh, "part_joint_name"));
        g_strlcpy(out->joint, joint ? joint : "", sizeof out->joint);
        g_strlcpy(out->status, "ok", sizeof out->status);
    }
    json_decref(report);
}

/* Runs the graph; false with a status in out (RF_EXIT_CANCELLED in *code on Ctrl-C). */
static bool look_execute(const rf_registry *reg, const rf_rig_look_setup *s, json_t *graph,
                         rf_rig_look *out, int *code)
{
    char *text = json_dumps(graph, JSON_COMPACT);
    g_autofree char *cwd = g_get_current_dir();
    g_autoptr(GPtrArray) diags = rf_diags_new();
    rf_pipeline *p = text ? rf_pipeline_load_string(text, "rig-bench look", cwd, diags) : NULL;
    free(text);
    *code = RF_EXIT_RUN;
    if (p && rf_pipeline_validate(p, reg, diags) && !diags->len)
        *code = rf_run_interruptible_out(p, reg, s->lines, diags);
    rf_pipeline_free(p);
    if (*code == RF_EXIT_OK)
        return true;
    g_autofree char *msg = diags->len ? rf_diag_format(g_ptr_array_index(diags, 0)) : NULL;
    snprintf(out->status, sizeof out->status, "%s: %s",
             *code == RF_EXIT_CANCELLED ? "interrupted" : "failed",
             msg ? msg : "the graph could not be built");
    return false;
}

int rf_rig_look_run(const rf_registry *reg, const rf_rig_look_setup *s, const rf_node_desc *rigger,
                    const char *model, rf_rig_look *out)
{
    rf_rig_look_none(out, "not measured");
    if (!s->motion)
        return RF_EXIT_OK;
    g_autofree char *json = g_build_filename(s->dir, "measure.json", NULL);
    (void)remove(json); /* a report from the model before must not be read as this one's */
    json_t *graph = look_graph(reg, s, rigger, model, json, out->status, sizeof out->status);
    int code = RF_EXIT_OK;
    if (graph && look_execute(reg, s, graph, out, &code))
        look_read(json, out);
    json_decref(graph);
    return code == RF_EXIT_CANCELLED ? code : RF_EXIT_OK;
}
