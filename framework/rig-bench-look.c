/* rig-bench --look: the animated result judged as a person sees it, a mesh moving on a floor.
 * For each model and rigger the pipeline file pipelines/scan-to-animation.json itself (the
 * installed one, or the source tree's from a build tree, as `rigflow report` reads its own) is
 * run through the engine with its rigger node's type set to the bench's rigger and without its
 * export, so the figures are the ones a user gets from that pipeline; retarget.measure writes
 * them as JSON into a folder of the bench's own, and the nodes' lines go to a stream that is not
 * the CSV. The rigger runs again (it is deterministic, and fast beside the retarget): the
 * bench's own graph fails as a whole when any node does, and a look that fails must not take
 * the rig's row with it. */
#include <errno.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <rigflow/text.h>

#include "commands.h"
#include "rig-bench-look.h"

bool rf_rig_look_begin(rf_rig_look_setup *s, const char *motion, int frames,
                       const rf_rig_move *move)
{
    memset(s, 0, sizeof *s);
    s->move = move;
    if (!motion)
        return true;
    if (frames < 2 && frames != 0) {
        fprintf(stderr, "rigflow rig-bench: --look-frames: expected 2 frames or more, or 0 for "
                        "the whole motion\n");
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
    s->pipeline = rf_pipeline_file("scan-to-animation.json");
    json_error_t e;
    s->graph = json_load_file(s->pipeline, 0, &e);
    if (!json_is_array(json_object_get(s->graph, "nodes"))) {
        /* jansson's message quotes the bytes near the error as they are (an ESC) */
        g_autofree char *shown = rf_printable(s->pipeline);
        g_autofree char *why = rf_printable(s->graph ? "it has no nodes" : e.text);
        fprintf(stderr, "rigflow rig-bench: --look: cannot read the pipeline %s: %s\n", shown, why);
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
    json_decref(s->graph);
    g_free(s->dir), g_free(s->motion), g_free(s->pipeline);
    memset(s, 0, sizeof *s);
}

void rf_rig_look_none(rf_rig_look *l, const char *status)
{
    l->stretch_p99 = l->part_p99 = l->seam_p99 = l->floor_median = l->floor_p95 = NAN;
    l->parts_below = l->fidelity_mean = l->fidelity_p95 = l->feet = l->source_feet = NAN;
    l->volume_off = NAN;
    l->joint[0] = '\0';
    g_strlcpy(l->status, status, sizeof l->status);
}

/* The node `id` of the graph's nodes, and its index into *at (may be NULL); NULL when none. */
static json_t *look_node(json_t *nodes, const char *id, size_t *at)
{
    size_t i;
    json_t *node;
    json_array_foreach(nodes, i, node)
    {
        const char *nid = json_string_value(json_object_get(node, "id"));
        if (nid && !strcmp(nid, id)) {
            if (at)
                *at = i;
            return node;
        }
    }
    return NULL;
}

/* The pipeline file's graph for `rigger`, as text: its export left out (the bench writes no
 * character), its rigger node of type `rigger`, fed the mesh's axes only when that rigger reads
 * them, and without the parameters the file gives another rigger type (they need not exist in
 * this one), the mesh moved as the bench moves it. NULL with why. (free()) */
static char *look_graph(const rf_rig_look_setup *s, const rf_node_desc *rigger, char *why, size_t n)
{
    json_t *graph = json_deep_copy(s->graph), *nodes = json_object_get(graph, "nodes");
    json_t *rig = look_node(nodes, "rig", NULL);
    size_t at;
    char *text = NULL;
    if (!rig || !look_node(nodes, "mesh", NULL) || !look_node(nodes, "measure", NULL)) {
        snprintf(why, n, "failed: the pipeline has no node 'mesh', 'rig' or 'measure'");
    } else {
        if (look_node(nodes, "export", &at))
            json_array_remove(nodes, at);
        const char *type = json_string_value(json_object_get(rig, "type"));
        if (!type || strcmp(type, rigger->type))
            json_object_del(rig, "params");
        json_object_set_new(rig, "type", json_string(rigger->type));
        if (!rf_rig_has_input(rigger, "axes") || s->no_axes)
            json_object_del(json_object_get(rig, "inputs"), "axes");
        /* the motion plays on the mesh that was rigged: moved, when the bench moves it */
        if (s->move && s->move->on)
            rf_rig_move_insert(graph, s->move, "mesh", "mesh_moved");
        text = json_dumps(graph, JSON_COMPACT);
        if (!text)
            snprintf(why, n, "failed: out of memory building the look's pipeline");
    }
    json_decref(graph);
    return text;
}

/* A number of the measure's "mesh" object in %, NaN when absent. */
static double look_pct(json_t *mesh, const char *key)
{
    json_t *v = json_object_get(mesh, key);
    return json_is_number(v) ? 100 * json_number_value(v) : NAN;
}

/* A number of the report, NaN when absent or null. */
static double look_num(json_t *report, const char *key)
{
    json_t *v = json_object_get(report, key);
    return json_is_number(v) ? json_number_value(v) : NAN;
}

/* The measure's figures of the skeleton into out: read whatever the mesh's status, as a rigid
 * mesh's skeleton still moves. */
static void look_read_skeleton(json_t *report, rf_rig_look *out)
{
    out->fidelity_mean = look_num(report, "fidelity_mean_deg");
    out->fidelity_p95 = look_num(report, "fidelity_p95_deg");
    out->feet = look_num(report, "feet_count");
    out->source_feet = look_num(report, "source_feet");
}

/* The measure's JSON report into out. */
static void look_read(const char *json, rf_rig_look *out)
{
    json_error_t err;
    json_t *report = json_load_file(json, 0, &err);
    json_t *mesh = json_object_get(report, "mesh"), *bones = json_object_get(report, "bones");
    if (report && !(json_is_integer(bones) && json_integer_value(bones) <= 0))
        look_read_skeleton(report, out);
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
        out->parts_below = look_pct(mesh, "parts_below");
        out->volume_off = look_pct(mesh, "volume_p95"); /* NaN: no solid part measured */
        const char *joint = json_string_value(json_object_get(mesh, "part_joint_name"));
        g_strlcpy(out->joint, joint ? joint : "", sizeof out->joint);
        g_strlcpy(out->status, "ok", sizeof out->status);
    }
    json_decref(report);
}

/* The file's parameters the bench sets, as `rigflow run -p` sets them: the model, the motion
 * (paths from the current folder), the retarget cut at the last frame asked for (the whole
 * motion: -1), the measure's samples and its report written. */
static bool look_params(rf_pipeline *p, const rf_rig_look_setup *s, const char *model,
                        const char *json, GPtrArray *diags)
{
    g_autofree char *mesh = g_strdup_printf("mesh.path=%s", model);
    g_autofree char *motion = g_strdup_printf("motion.path=%s", s->motion);
    g_autofree char *last = g_strdup_printf("retarget.last_frame=%d", s->frames - 1);
    g_autofree char *samples = g_strdup_printf("measure.mesh_frames=%d", RF_RIG_LOOK_SAMPLES);
    g_autofree char *report = g_strdup_printf("measure.path=%s", json);
    return rf_pipeline_override(p, mesh, diags) && rf_pipeline_override(p, motion, diags) &&
           rf_pipeline_override(p, last, diags) && rf_pipeline_override(p, samples, diags) &&
           rf_pipeline_override(p, report, diags);
}

/* Runs the graph; false with a status in out (RF_EXIT_CANCELLED in *code on Ctrl-C). */
static bool look_execute(const rf_registry *reg, const rf_rig_look_setup *s, const char *text,
                         const char *model, const char *json, rf_rig_look *out, int *code)
{
    g_autofree char *dir = g_path_get_dirname(s->pipeline);
    g_autoptr(GPtrArray) diags = rf_diags_new();
    rf_pipeline *p = rf_pipeline_load_string(text, s->pipeline, dir, diags);
    *code = RF_EXIT_RUN;
    if (p && look_params(p, s, model, json, diags) && rf_pipeline_validate(p, reg, diags) &&
        !diags->len)
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
    char *text = look_graph(s, rigger, out->status, sizeof out->status);
    int code = RF_EXIT_OK;
    if (text && look_execute(reg, s, text, model, json, out, &code))
        look_read(json, out);
    free(text);
    return code == RF_EXIT_CANCELLED ? code : RF_EXIT_OK;
}
