/* `rigflow rig-bench`: the riggers against artists' rigs. For each model and each rigger plugin
 * offering "rigflow.rigger/1" a pipeline is built in memory and run by the engine: the model
 * imported as it is (the artist's rig and skin: the answer) and with its rig ignored (the bare
 * mesh), the rigger on the bare mesh, and the skeletal-similarity matcher mapping the rigger's
 * joints onto the artist's. Joint distances follow RigNet's and UniRig's evaluation (chamfer
 * distances normalised by the mesh's longest bounding-box edge); skinning is compared through
 * the matcher's mapping. The rigger is timed on its own through its extension. doc/autorig.md. */
#include <errno.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <rigflow/analysis.h>
#include <rigflow/rigger.h>
#include <rigflow/text.h>

#include "commands.h"
#include "rig-bench-look.h"
#include "rig-bench.h"

typedef struct rb_rigger {
    const rf_node_desc *desc;
    const rf_rigger_api *api;
} rb_rigger;

/* How each model is moved before it is rigged: the artist's rig and the bare mesh alike, so
 * CD-J2J and the skinning compare like with like. */
static rf_rig_move rb_moved = {.scale = 1, .axis = "up", .offset = "0,0,0"};

/* --no-axes: the riggers are given no up or forward, as from a format that declares none (OBJ,
 * STL, PLY), so they find the body's up themselves; the artist's rig keeps its axes. */
static bool rb_no_axes;

/* Joints as points and bones as segments, in model space. */
typedef struct rb_rig {
    uint32_t n;
    rf_vec3 *pos;
    int32_t *parent; /* within this set, -1 for roots */
    uint32_t *joint; /* [n] index in the skeleton */
} rb_rig;

static bool rb_wanted(char **names, const rf_node_desc *d, const rf_rigger_api *api)
{
    if (!names || !*names)
        return true;
    for (char **n = names; *n; n++)
        if (!strcmp(*n, d->type) || !strcmp(*n, api->name))
            return true;
    return false;
}

static GArray *rb_find_riggers(rf_registry *reg, char **names)
{
    GArray *out = g_array_new(FALSE, TRUE, sizeof(rb_rigger));
    for (guint i = 0; i < rf_registry_plugin_count(reg); i++) {
        const rf_plugin_entry *e = rf_plugin_entry_of(rf_registry_plugin(reg, i));
        for (uint32_t k = 0; k < e->node_count; k++) {
            const rf_node_desc *d = e->nodes[k];
            const rf_rigger_api *api = d->kind == RF_KIND_RIGGER && d->get_extension
                                           ? d->get_extension(RF_RIGGER_EXTENSION)
                                           : NULL;
            if (!api || rf_registry_find(reg, d->type, NULL) != d || !rb_wanted(names, d, api))
                continue;
            rb_rigger r = {d, api};
            g_array_append_val(out, r);
        }
    }
    return out;
}

/* ---- rigs as points and segments ---- */

static void rb_rig_free(rb_rig *r)
{
    g_free(r->pos), g_free(r->parent), g_free(r->joint);
    memset(r, 0, sizeof *r);
}

/* World joint positions of a skinned model: from the mesh's inverse binds (the pose the skin was
 * made in) where it has them, else the rest pose. */
static void rb_world(const rf_skeleton *s, const rf_mesh *m, rf_vec3 *out)
{
    rf_xform *w = g_new(rf_xform, s->joint_count + 1);
    rf_skeleton_world_rest(s, w);
    for (uint32_t j = 0; j < s->joint_count; j++) {
        rf_mat4 b;
        out[j] = w[j].t;
        if (m && m->inverse_bind && m->bind_count == s->joint_count &&
            rf_mat4_invert(m->inverse_bind[j], &b))
            out[j] = rf_v3(b.m[12], b.m[13], b.m[14]);
    }
    g_free(w);
}

/* The joints that carry skin (helpers, IK targets and poles left out), linked to their nearest
 * kept ancestor. */
static void rb_rig_make(const rf_skeleton *s, const rf_mesh *m, bool skinned_only, rb_rig *r)
{
    rf_vec3 *world = g_new(rf_vec3, s->joint_count + 1);
    int32_t *kept = g_new(int32_t, s->joint_count + 1);
    rb_world(s, m, world);
    r->pos = g_new(rf_vec3, s->joint_count + 1);
    r->parent = g_new(int32_t, s->joint_count + 1);
    r->joint = g_new(uint32_t, s->joint_count + 1);
    r->n = 0;
    for (uint32_t j = 0; j < s->joint_count; j++) {
        kept[j] = -1;
        if (skinned_only && (s->joints[j].flags & RF_JOINT_UNWEIGHTED))
            continue;
        int32_t p = s->joints[j].parent;
        while (p >= 0 && kept[p] < 0)
            p = s->joints[p].parent;
        kept[j] = (int32_t)r->n;
        r->pos[r->n] = world[j];
        r->parent[r->n] = p >= 0 ? kept[p] : -1;
        r->joint[r->n++] = j;
    }
    g_free(world), g_free(kept);
}

static double rb_seg_dist(rf_vec3 q, rf_vec3 a, rf_vec3 b)
{
    rf_vec3 ab = rf_v3_sub(b, a);
    double l2 = rf_v3_dot(ab, ab);
    double u = l2 > 0 ? fmin(1, fmax(0, rf_v3_dot(rf_v3_sub(q, a), ab) / l2)) : 0;
    return rf_v3_len(rf_v3_sub(q, rf_v3_add(a, rf_v3_scale(ab, u))));
}

/* Distance from q to the nearest joint (bones false) or bone (bones true) of r; a rig with no
 * bone falls back to its joints. */
static double rb_nearest(rf_vec3 q, const rb_rig *r, bool bones)
{
    double best = INFINITY;
    bool any = false;
    for (uint32_t j = 0; bones && j < r->n; j++)
        if (r->parent[j] >= 0) {
            best = fmin(best, rb_seg_dist(q, r->pos[r->parent[j]], r->pos[j]));
            any = true;
        }
    for (uint32_t j = 0; !any && j < r->n; j++)
        best = fmin(best, rf_v3_len(rf_v3_sub(q, r->pos[j])));
    return best;
}

/* Mean over a's joints (or points sampled along a's bones) of the distance to b's joints/bones. */
static double rb_mean(const rb_rig *a, const rb_rig *b, bool from_bones, bool to_bones)
{
    double sum = 0;
    uint32_t count = 0;
    for (uint32_t j = 0; j < a->n; j++) {
        if (!from_bones || a->parent[j] < 0) {
            if (!from_bones)
                sum += rb_nearest(a->pos[j], b, to_bones), count++;
            continue;
        }
        for (int k = 0; k <= 10; k++) {
            rf_vec3 q = rf_v3_lerp(a->pos[a->parent[j]], a->pos[j], k / 10.0);
            sum += rb_nearest(q, b, to_bones), count++;
        }
    }
    if (from_bones && !count)
        return rb_mean(a, b, false, to_bones);
    return count ? sum / count : NAN;
}

static double rb_chamfer(const rb_rig *p, const rb_rig *g, bool from_bones, bool to_bones)
{
    return 0.5 * (rb_mean(p, g, from_bones, to_bones) + rb_mean(g, p, from_bones, to_bones));
}

/* ---- skinning ---- */

/* Which artist joint each predicted joint stands for: the matcher's answer (m, may be NULL);
 * unmapped joints take their nearest mapped ancestor's, else the nearest artist joint. With
 * `nearest`, every joint takes the nearest artist joint (the skin compared without the
 * matcher's judgement). */
typedef enum rb_map_how { RB_MAP_MATCHER, RB_MAP_NEAREST, RB_MAP_SKIN } rb_map_how;

static void rb_map_joints(const rf_skeleton *pred, const rb_rig *p, const rf_mapping *m,
                          const rf_skeleton *art, const rb_rig *g, bool nearest, uint32_t *to)
{
    if (nearest || (m && m->target_joint_count != pred->joint_count))
        m = NULL;
    for (uint32_t j = 0; j < pred->joint_count; j++) {
        /* a match to an artist joint that carries no weights (a helper, the armature's root)
         * says nothing about skin: it counts as unmapped */
        int32_t k = (int32_t)j;
        while (k >= 0 &&
               !(m && m->entries[k].input_count &&
                 m->entries[k].inputs[0].joint < art->joint_count &&
                 !(art->joints[m->entries[k].inputs[0].joint].flags & RF_JOINT_UNWEIGHTED)))
            k = pred->joints[k].parent;
        if (k >= 0) {
            to[j] = m->entries[k].inputs[0].joint;
            continue;
        }
        double best = INFINITY;
        to[j] = g->n ? g->joint[0] : 0;
        for (uint32_t i = 0; i < g->n; i++) {
            double d = rf_v3_len(rf_v3_sub(p->pos[j], g->pos[i]));
            if (d < best)
                best = d, to[j] = g->joint[i];
        }
    }
}

/* `--joint-map skin`: each predicted joint stands for the artist joint whose weights overlap
 * its own most over the shared vertices (the sum over vertices of the two weights' products),
 * the answer's own skin read back: what a mapping joint for joint could reach at best on this
 * rig, so a row's loss can be told the mapping's or the rig's. Joints without weights keep the
 * nearest artist joint `to` holds (they change no figure). Not a strict bound: summing several
 * predicted joints into one artist joint can do better per vertex than each one's best. */
static void rb_map_skin(const rf_mesh *am, const rf_mesh *pm, uint32_t np, uint32_t na,
                        uint32_t *to)
{
    double *ov = g_new0(double, (size_t)np *na + 1);
    for (uint32_t v = 0; v < am->vertex_count && v < pm->vertex_count; v++)
        for (int k = 0; k < 4; k++) {
            uint32_t a = pm->skin_joints[v * 4 + k];
            for (int l = 0; a < np && l < 4; l++) {
                uint32_t b = am->skin_joints[v * 4 + l];
                if (b < na)
                    ov[(size_t)a * na + b] +=
                        (double)pm->skin_weights[v * 4 + k] * am->skin_weights[v * 4 + l];
            }
        }
    for (uint32_t j = 0; j < np; j++) {
        const double *row = ov + (size_t)j * na;
        double best = 0;
        for (uint32_t b = 0; b < na; b++)
            if (row[b] > best)
                best = row[b], to[j] = b;
    }
    g_free(ov);
}

typedef struct rb_skin {
    double precision, recall, l1;
    uint32_t unweighted;
} rb_skin;

/* Weights under 0.15 of the vertex's largest dropped, the rest renormalised. */
static void rb_prune(double *w, uint32_t n)
{
    double mx = 0, sum = 0;
    for (uint32_t j = 0; j < n; j++)
        mx = fmax(mx, w[j]);
    for (uint32_t j = 0; j < n; j++)
        sum += w[j] = w[j] < 0.15 * mx ? 0 : w[j];
    for (uint32_t j = 0; sum > 0 && j < n; j++)
        w[j] /= sum;
}

static void rb_skin_compare(const rf_mesh *art, const rf_mesh *pred, const uint32_t *to,
                            uint32_t nj, rb_skin *out)
{
    double *wg = g_new0(double, nj + 1), *wp = g_new0(double, nj + 1);
    double sp = 0, sr = 0, sl = 0;
    uint32_t counted = 0;
    memset(out, 0, sizeof *out);
    for (uint32_t v = 0; v < art->vertex_count && v < pred->vertex_count; v++) {
        memset(wg, 0, nj * sizeof *wg), memset(wp, 0, nj * sizeof *wp);
        double tp = 0;
        for (int k = 0; k < 4; k++) {
            uint16_t a = art->skin_joints[v * 4 + k], b = pred->skin_joints[v * 4 + k];
            if (a < nj)
                wg[a] += art->skin_weights[v * 4 + k];
            tp += pred->skin_weights[v * 4 + k];
            if (to[b] < nj)
                wp[to[b]] += pred->skin_weights[v * 4 + k];
        }
        if (!(tp > 0)) {
            out->unweighted++;
            continue;
        }
        rb_prune(wg, nj), rb_prune(wp, nj);
        uint32_t np = 0, ng = 0, both = 0;
        double l1 = 0;
        for (uint32_t j = 0; j < nj; j++) {
            np += wp[j] > 0, ng += wg[j] > 0, both += wp[j] > 0 && wg[j] > 0;
            l1 += fabs(wp[j] - wg[j]);
        }
        if (!ng)
            continue; /* the artist left it unweighted: nothing to compare */
        sp += np ? (double)both / np : 0, sr += (double)both / ng, sl += l1, counted++;
    }
    out->precision = counted ? sp / counted : NAN;
    out->recall = counted ? sr / counted : NAN;
    out->l1 = counted ? sl / counted : NAN;
    g_free(wg), g_free(wp);
}

/* Whether a rigger's skinned mesh can be compared with the artist's: the model's vertices (the
 * rigger's contract is a skinned copy of the mesh) and weights only on joints its skeleton has
 * (`joints`). A plugin's bug is reported, not read past the tables. False with why. */
static bool rb_skin_usable(const rf_mesh *art, const rf_mesh *pred, uint32_t joints, char *why,
                           size_t n)
{
    if (pred->vertex_count != art->vertex_count || !pred->skin_joints) {
        snprintf(why, n, "the rigger's mesh has %u vertices%s, the model %u", pred->vertex_count,
                 pred->skin_joints ? "" : " without joint indices", art->vertex_count);
        return false;
    }
    for (size_t i = 0; i < (size_t)pred->vertex_count * 4; i++)
        if (pred->skin_joints[i] >= joints) {
            snprintf(why, n, "the rigger's skin names joint %u at vertex %zu, of %u joints",
                     pred->skin_joints[i], i / 4, joints);
            return false;
        }
    return true;
}

/* ---- one model ---- */

/* "humanoid" when the artist's rig has two arms and two legs, else "other". */
static const char *rb_body(const rf_skeleton *s)
{
    rf_analysis_options o = {.use_bind_pose = true};
    rf_analysis *a = rf_analyze(s, &o);
    uint32_t arms = 0, legs = 0;
    for (uint32_t i = 0; a && i < a->section_count; i++)
        arms += a->sections[i].type == RF_SECTION_ARM,
            legs += a->sections[i].type == RF_SECTION_LEG;
    rf_analysis_free(a);
    return arms == 2 && legs == 2 ? "humanoid" : "other";
}

/* How far the skeleton analysis (what the matcher reads) agrees about the two rigs' up and
 * forward axes: cosines into out[0] and out[1]. The rigs share the mesh, so 1 is right; -1 up or
 * forward means the matcher reads the rig upside down or facing back (its sides swapped). */
static void rb_axes_agree(const rf_skeleton *art, const rf_skeleton *pred, double out[2])
{
    rf_analysis_options o = {.use_bind_pose = true};
    rf_analysis *a = rf_analyze(art, &o), *b = rf_analyze(pred, &o);
    out[0] = a && b ? rf_v3_dot(a->up, b->up) : NAN;
    out[1] = a && b ? rf_v3_dot(a->forward, b->forward) : NAN;
    rf_analysis_free(a), rf_analysis_free(b);
}

static double rb_longest(const rf_mesh *m)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, l = 0;
    for (uint32_t v = 0; v < m->vertex_count; v++)
        for (int a = 0; a < 3; a++)
            lo[a] = fmin(lo[a], m->positions[v * 3 + a]),
            hi[a] = fmax(hi[a], m->positions[v * 3 + a]);
    for (int a = 0; a < 3; a++)
        l = fmax(l, hi[a] - lo[a]);
    return l;
}

static void rb_csv_text_to(FILE *out, const char *s)
{
    /* file names and messages are data: quote them, double any quote, and escape as
     * rigflow/text.h does every byte that is not printable UTF-8 (controls, line breaks, C1
     * controls such as a 0xc2 0x9b CSI, invalid bytes): one row per line, nothing raw on a
     * terminal */
    size_t n = rf_text_escape(s, NULL, 0, 0);
    char *text = g_malloc(n + 1);
    rf_text_escape(s, text, n + 1, 0);
    fputc('"', out);
    for (const char *c = text; *c; c++)
        if (*c == '"')
            fputs("\"\"", out);
        else
            fputc(*c, out);
    fputc('"', out);
    g_free(text);
}

static void rb_csv_text(const char *s)
{
    rb_csv_text_to(stdout, s);
}

/* --look: the motion and the look of the model being measured (NULL while none is: its cells
 * read nan and its status says why). */
static rf_rig_look_setup rb_look_setup;
static const rf_rig_look *rb_look_now;

/* The look's cells at the end of a row: the figures in % of the mesh's height. */
static void rb_look_cells(void)
{
    rf_rig_look none;
    const rf_rig_look *l = rb_look_now;
    if (!l) {
        rf_rig_look_none(&none, rb_look_setup.motion ? "not run: no rig" : "off");
        l = &none;
    }
    printf(",%.2f,%.2f,", l->stretch_p99, l->part_p99);
    rb_csv_text(l->joint);
    printf(",%.2f,%.2f,%.2f,%.2f,%.2f,%.2f,%.0f,%.0f,%.2f,", l->seam_p99,
           rf_text_shown_zero(l->floor_median, 2), l->floor_p95, l->parts_below, l->fidelity_mean,
           l->fidelity_p95, l->feet, l->source_feet, l->volume_off);
    rb_csv_text(l->status);
}

static void rb_row(const rb_rigger *r, const char *model, const char *body, uint32_t nart,
                   uint32_t npred, const double *cd, const rb_skin *sk, const rb_skin *given,
                   double secs, const char *status)
{
    printf("%s,", r->api->name);
    rb_csv_text(model);
    printf(",%s,%u,%u,%.4f,%.4f,%.4f,%.3f,%.3f,%.3f,%u,%.3f,%.3f,%.3f,%.4f,%.4f,%.2f,%.2f,%.3f,",
           body, nart, npred, cd[0], cd[1], cd[2], sk->precision, sk->recall, sk->l1,
           sk->unweighted, given->precision, given->recall, given->l1, cd[3], cd[4], cd[5], cd[6],
           secs);
    rb_csv_text(status);
    rb_look_cells();
    putchar('\n');
    fflush(stdout);
}

bool rf_rig_has_input(const rf_node_desc *d, const char *name)
{
    for (uint32_t i = 0; i < d->input_count; i++)
        if (!strcmp(d->inputs[i].name, name))
            return true;
    return false;
}

static bool rb_has_param(const rf_node_desc *d, const char *name)
{
    for (uint32_t i = 0; i < d->param_count; i++)
        if (!strcmp(d->params[i].name, name))
            return true;
    return false;
}

/* The node ids whose outputs are the artist's rig and the bare mesh: the imports', or the
 * transform nodes' after them when the model is moved. */
static const char *rb_artist_id(void)
{
    return rb_moved.on ? "artist_moved" : "artist";
}

static const char *rb_mesh_id(void)
{
    return rb_moved.on ? "mesh_moved" : "mesh";
}

/* An input's source "node.port" read from `from`'s skeleton or mesh, rewritten to `to`'s. */
static void rb_rewire_one(json_t *src, const char *from, const char *to)
{
    const char *text = json_string_value(src);
    size_t n = strlen(from);
    if (!text || strncmp(text, from, n) || text[n] != '.' ||
        (strcmp(text + n + 1, "skeleton") && strcmp(text + n + 1, "mesh")))
        return;
    g_autofree char *moved = g_strdup_printf("%s.%s", to, text + n + 1);
    json_string_set(src, moved);
}

bool rf_rig_move_insert(json_t *graph, const rf_rig_move *m, const char *from, const char *to)
{
    json_t *nodes = json_object_get(graph, "nodes"), *node;
    size_t i, k;
    json_array_foreach(nodes, i, node)
    {
        const char *port;
        json_t *src, *item;
        json_object_foreach(json_object_get(node, "inputs"), port, src)
        {
            rb_rewire_one(src, from, to);
            json_array_foreach(src, k, item) rb_rewire_one(item, from, to);
        }
    }
    g_autofree char *sk = g_strdup_printf("%s.skeleton", from);
    g_autofree char *me = g_strdup_printf("%s.mesh", from);
    json_t *t = json_pack("{s:s, s:s, s:{s:s, s:s}, s:{s:f, s:s, s:f, s:s, s:b}}", "id", to, "type",
                          "transform", "inputs", "skeleton", sk, "mesh", me, "params", "turn",
                          m->turn, "axis", m->axis, "scale", m->scale, "offset", m->offset,
                          "turn_axes", !m->fixed_axes);
    return t && json_array_append_new(nodes, t) == 0;
}

/* The graph for one model and one rigger (see the file comment), validated; NULL with a reason
 * in why. */
static rf_pipeline *rb_pipeline(const rf_registry *reg, const rb_rigger *r, const char *path,
                                char *why, size_t n)
{
    const char *param = NULL;
    const rf_node_desc *imp = rf_registry_importer_for(reg, path, &param);
    if (!imp || !rb_has_param(imp, "ignore_rig")) {
        snprintf(why, n, "%s", imp ? "its importer cannot ignore a rig" : "no importer reads it");
        return NULL;
    }
    json_t *rig_in = json_pack("{s:s}", "mesh", "mesh.mesh");
    if (rf_rig_has_input(r->desc, "axes") && !rb_no_axes)
        json_object_set_new(rig_in, "axes", json_string("mesh.skeleton"));
    /* the matcher pairs joints by correspondence: forelegs with arms, not its gait rule; a
     * girdle joint whose bone is the neck's with the neck, not the chest */
    json_t *graph = json_pack(
        "{s:s, s:i, s:[{s:s, s:s, s:{s:s}}, {s:s, s:s, s:{s:s, s:b, s:b}}, {s:s, s:s, s:o}, "
        "{s:s, s:s, s:{s:s, s:[s]}, s:{s:s, s:s}}]}",
        "format", "rigflow.pipeline", "version", 1, "nodes", "id", "artist", "type", imp->type,
        "params", param, path, "id", "mesh", "type", imp->type, "params", param, path, "ignore_rig",
        1, "require_skeleton", 0, "id", "rig", "type", r->desc->type, "inputs", rig_in, "id", "map",
        "type", "skeletal-similarity", "inputs", "target", "rig.skeleton", "sources",
        "artist.skeleton", "params", "forelegs", "arms", "girdle", "neck");
    if (graph && rb_moved.on) {
        rf_rig_move_insert(graph, &rb_moved, "artist", "artist_moved");
        rf_rig_move_insert(graph, &rb_moved, "mesh", "mesh_moved");
    }
    char *text = graph ? json_dumps(graph, JSON_COMPACT) : NULL;
    json_decref(graph);
    g_autofree char *cwd = g_get_current_dir();
    g_autoptr(GPtrArray) diags = rf_diags_new();
    rf_pipeline *p = text ? rf_pipeline_load_string(text, "rig-bench", cwd, diags) : NULL;
    free(text);
    if (!p || !rf_pipeline_validate(p, reg, diags) || diags->len) {
        g_autofree char *msg = diags->len ? rf_diag_format(g_ptr_array_index(diags, 0)) : NULL;
        snprintf(why, n, "%s", msg ? msg : "the graph could not be built");
        rf_pipeline_free(p);
        return NULL;
    }
    return p;
}

/* The rigger's skinning alone on the artist's skeleton, in the pose the artist bound it in,
 * against the artist's weights joint for joint (no mapping): how skinning methods are compared
 * given one skeleton. NaN when the rigger cannot skin a given skeleton. */
static void rb_skin_given(const rb_rigger *r, const rf_skeleton *as, const rf_mesh *am,
                          rb_skin *out)
{
    *out = (rb_skin){NAN, NAN, NAN, 0};
    if (!RF_HAS_FIELD(r->api, rf_rigger_api, skin) || !r->api->skin)
        return;
    rf_mesh bare = *am; /* borrowed arrays, the artist's skin hidden from the rigger */
    bare.skin_joints = NULL, bare.skin_weights = NULL, bare.inverse_bind = NULL,
    bare.bind_count = 0;
    const rf_mat4 *inv = am->bind_count == as->joint_count ? am->inverse_bind : NULL;
    rf_mesh *m = NULL;
    char err[256] = "no mesh returned";
    if (r->api->skin(&bare, as, inv, &m, err, sizeof err) &&
        !rb_skin_usable(am, m, as->joint_count, err, sizeof err)) {
        rf_mesh_free(m);
        m = NULL;
    }
    if (!m) {
        g_autofree char *shown = rf_printable(err); /* may quote the model's joint names */
        fprintf(stderr, "rigflow rig-bench: %s on the artist's skeleton: %s\n", r->api->name,
                shown);
        return;
    }
    uint32_t *same = g_new(uint32_t, as->joint_count + 1);
    for (uint32_t j = 0; j < as->joint_count; j++)
        same[j] = j;
    rb_skin_compare(am, m, same, as->joint_count, out);
    g_free(same);
    rf_mesh_free(m);
}

/* Seconds the rigger's core takes on the bare mesh, called directly as ik-bench calls solvers,
 * with the axes the pipeline's rigger node was given (NAN when it fails). */
static double rb_time(const rb_rigger *r, const rf_mesh *mesh, const rf_skeleton *axes)
{
    rf_mesh bare = *mesh; /* borrowed arrays, the skin hidden from the rigger */
    bare.skin_joints = NULL, bare.skin_weights = NULL, bare.inverse_bind = NULL,
    bare.bind_count = 0;
    rf_skeleton *s = NULL;
    rf_mesh *m = NULL;
    char err[256];
    gint64 t0 = g_get_monotonic_time();
    bool ok = RF_HAS_FIELD(r->api, rf_rigger_api, rig_axes) && r->api->rig_axes
                  ? r->api->rig_axes(&bare, axes, &s, &m, err, sizeof err)
                  : r->api->rig(&bare, &s, &m, err, sizeof err);
    double secs = (g_get_monotonic_time() - t0) / 1e6;
    rf_skeleton_free(s), rf_mesh_free(m);
    return ok ? secs : NAN;
}

/* --joints FILE: one row per joint of either rig (positions and distances as fractions of the
 * longest edge) naming the nearest joint of the other rig, so a placement error can be traced
 * to the joints that make it. NULL when not asked for. */
static FILE *rb_joints_out;

/* What --joints adds to a rigger joint's row: the artist joint the skinning columns count it
 * as (`to`, by --joint-map), the one whose skin its own overlaps most (`skin_to`) and its skin's
 * weight summed over the vertices (`weight`), so a row's loss can be traced to the joints that
 * make it; NULL for the artist's rows and where the skins cannot be compared. */
typedef struct rb_joint_maps {
    const uint32_t *to, *skin_to;
    const double *weight;
} rb_joint_maps;

static void rb_joint_rows(const char *rigger, const char *model, const char *which,
                          const rf_skeleton *as, const rb_rig *a, const rf_skeleton *bs,
                          const rb_rig *b, double L, const rb_joint_maps *maps)
{
    for (uint32_t j = 0; j < a->n; j++) {
        uint32_t near = 0, i = a->joint[j];
        double best = INFINITY;
        for (uint32_t k = 0; k < b->n; k++) {
            double d = rf_v3_len(rf_v3_sub(a->pos[j], b->pos[k]));
            if (d < best)
                best = d, near = k;
        }
        fprintf(rb_joints_out, "%s,", rigger);
        rb_csv_text_to(rb_joints_out, model);
        fprintf(rb_joints_out, ",%s,", which);
        rb_csv_text_to(rb_joints_out, as->joints[i].name);
        fprintf(rb_joints_out, ",%.5f,%.5f,%.5f,", a->pos[j].x / L, a->pos[j].y / L,
                a->pos[j].z / L);
        rb_csv_text_to(rb_joints_out, b->n ? bs->joints[b->joint[near]].name : "");
        fprintf(rb_joints_out, ",%.5f,", b->n ? best / L : NAN);
        rb_csv_text_to(rb_joints_out, maps && maps->to ? bs->joints[maps->to[i]].name : "");
        fputc(',', rb_joints_out);
        rb_csv_text_to(rb_joints_out,
                       maps && maps->skin_to ? bs->joints[maps->skin_to[i]].name : "");
        fprintf(rb_joints_out, ",%.1f\n", maps && maps->weight ? maps->weight[i] : NAN);
    }
}

/* Each predicted joint's skin weight summed over the vertices (joints without weights 0). */
static double *rb_joint_weights(const rf_mesh *pm, uint32_t np)
{
    double *w = g_new0(double, (size_t)np + 1);
    for (size_t v = 0; v < (size_t)pm->vertex_count * 4; v++)
        if (pm->skin_joints[v] < np)
            w[pm->skin_joints[v]] += pm->skin_weights[v];
    return w;
}

static void rb_measure(const rb_rigger *r, const char *base, const rf_pipeline *pl, rb_map_how how)
{
    const rf_skeleton *as = rf_pipeline_result(pl, rb_artist_id(), "skeleton");
    const rf_mesh *am = rf_pipeline_result(pl, rb_artist_id(), "mesh");
    const rf_skeleton *ps = rf_pipeline_result(pl, "rig", "skeleton");
    const rf_mesh *pm = rf_pipeline_result(pl, "rig", "mesh");
    const rf_mapping *map = rf_pipeline_result(pl, "map", "mapping");
    double cd[7] = {NAN, NAN, NAN, NAN, NAN, NAN, NAN};
    rb_skin sk = {NAN, NAN, NAN, 0};
    if (!as || !am || !am->skin_weights || !ps || !pm || !pm->skin_weights) {
        rb_row(r, base, "-", 0, 0, cd, &sk, &sk, NAN, "skipped: no skinned mesh to compare with");
        return;
    }
    /* the unmoved mesh's edge, scaled: a turn changes a box's edges, not the body's size, and
     * the columns of a moved model must be comparable with the unmoved run's */
    const rf_mesh *as_read = rf_pipeline_result(pl, "artist", "mesh");
    double L = rb_longest(as_read ? as_read : am) * (rb_moved.on ? rb_moved.scale : 1);
    if (!(L > 0) || !isfinite(L)) {
        /* Every column is a fraction of this length: none can be given without it. */
        rb_row(r, base, "-", 0, 0, cd, &sk, &sk, NAN, "skipped: the artist's mesh has no extent");
        return;
    }
    rb_rig g = {0}, p = {0};
    rb_rig_make(as, am, true, &g);
    rb_rig_make(ps, pm, false, &p);
    cd[0] = rb_chamfer(&p, &g, false, false) / L;
    cd[1] = 0.5 * (rb_mean(&p, &g, false, true) + rb_mean(&g, &p, false, true)) / L;
    cd[2] = rb_chamfer(&p, &g, true, true) / L;
    /* CD-J2J's two halves: the rigger's joints far from any artist joint (extra or misplaced
     * joints), the artist's joints far from any of the rigger's (missing ones) */
    cd[3] = rb_mean(&p, &g, false, false) / L, cd[4] = rb_mean(&g, &p, false, false) / L;
    rb_axes_agree(as, ps, cd + 5);
    char why[300] = "ok";
    uint32_t *to = g_new(uint32_t, ps->joint_count + 1);
    rb_map_joints(ps, &p, map, as, &g, how != RB_MAP_MATCHER, to);
    bool usable = rb_skin_usable(am, pm, ps->joint_count, why, sizeof why);
    if (usable) {
        if (how == RB_MAP_SKIN)
            rb_map_skin(am, pm, ps->joint_count, as->joint_count, to);
        rb_skin_compare(am, pm, to, as->joint_count, &sk);
    }
    if (rb_joints_out) {
        rb_joint_maps maps = {to, NULL, NULL};
        uint32_t *skin_to = NULL;
        double *weight = NULL;
        if (usable) {
            skin_to = g_memdup2(to, sizeof *to * (ps->joint_count + 1));
            rb_map_skin(am, pm, ps->joint_count, as->joint_count, skin_to);
            weight = rb_joint_weights(pm, ps->joint_count);
            maps.skin_to = skin_to, maps.weight = weight;
        }
        rb_joint_rows(r->api->name, base, "rigger", ps, &p, as, &g, L, &maps);
        rb_joint_rows(r->api->name, base, "artist", as, &g, ps, &p, L, NULL);
        g_free(skin_to), g_free(weight);
    }
    rb_skin given;
    rb_skin_given(r, as, am, &given);
    rb_row(r, base, rb_body(as), g.n, ps->joint_count, cd, &sk, &given,
           rb_time(r, am, rb_no_axes ? NULL : rf_pipeline_result(pl, rb_mesh_id(), "skeleton")),
           why);
    g_free(to);
    rb_rig_free(&g), rb_rig_free(&p);
}

/* One model through one rigger: a row, whatever happens. RF_EXIT_RUN when the model could not
 * be read at all, RF_EXIT_CANCELLED on Ctrl-C (no row: the bench stops). */
static int rb_one(const rf_registry *reg, const rb_rigger *r, const char *path, rb_map_how how)
{
    const char *base = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
    double cd[7] = {NAN, NAN, NAN, NAN, NAN, NAN, NAN};
    rb_skin sk = {NAN, NAN, NAN, 0};
    char why[600];
    if (!g_file_test(path, G_FILE_TEST_IS_REGULAR)) {
        /* Not a refusal by the rigger: a bench over a missing file must not read as done. */
        g_autofree char *shown = rf_printable(path);
        fprintf(stderr, "rigflow rig-bench: %s: no such file\n", shown);
        rb_row(r, base, "-", 0, 0, cd, &sk, &sk, NAN, "error: no such file");
        return RF_EXIT_RUN;
    }
    if (!rf_check_utf8_name("rig-bench", path)) {
        rb_row(r, base, "-", 0, 0, cd, &sk, &sk, NAN, "error: the file name is not UTF-8");
        return RF_EXIT_RUN;
    }
    rf_pipeline *p = rb_pipeline(reg, r, path, why, sizeof why);
    if (!p) {
        g_autofree char *shown = rf_printable(path);
        fprintf(stderr, "rigflow rig-bench: %s: %s\n", shown, why);
        return RF_EXIT_RUN;
    }
    g_autoptr(GPtrArray) diags = rf_diags_new();
    bool unreadable = false;
    int code = rf_run_interruptible_diags(p, reg, false, true, diags);
    rf_rig_look look;
    if (code == RF_EXIT_OK && rb_look_setup.motion &&
        rf_rig_look_run(reg, &rb_look_setup, r->desc, path, &look) == RF_EXIT_CANCELLED) {
        code = RF_EXIT_CANCELLED;
    }
    if (code == RF_EXIT_OK) {
        rb_look_now = rb_look_setup.motion ? &look : NULL;
        rb_measure(r, base, p, how);
        rb_look_now = NULL;
    } else if (code == RF_EXIT_CANCELLED) {
        g_autofree char *shown = rf_printable(path);
        fprintf(stderr, "rigflow rig-bench: interrupted during %s\n", shown);
    } else {
        const rf_diag *d = diags->len ? g_ptr_array_index(diags, 0) : NULL;
        g_autofree char *msg = d ? rf_diag_format(d) : NULL;
        /* the import nodes failing is the model unreadable (an error of the bench's input, like
         * a missing file); any later node failing is the rigger refusing a model it was given */
        unreadable = d && d->node && (!strcmp(d->node, "artist") || !strcmp(d->node, "mesh"));
        snprintf(why, sizeof why, "%s: %s", unreadable ? "error: cannot read the model" : "refused",
                 msg ? msg : "the run failed");
        if (unreadable) {
            g_autofree char *shown = rf_printable(path);
            fprintf(stderr, "rigflow rig-bench: %s: cannot read the model: %s\n", shown,
                    msg ? msg : "the import failed");
        }
        rb_row(r, base, "-", 0, 0, cd, &sk, &sk, NAN, why);
    }
    rf_pipeline_free(p);
    return code == RF_EXIT_CANCELLED ? code : unreadable ? RF_EXIT_RUN : RF_EXIT_OK;
}

static int rb_run(const rf_registry *reg, GArray *riggers, int nfiles, char **files, rb_map_how how)
{
    printf(
        "rigger,model,body,artist_joints,joints,cd_j2j,cd_j2b,cd_b2b,precision,recall,l1,"
        "unweighted,given_precision,given_recall,given_l1,j2j_to_artist,j2j_from_artist,up_agree,"
        "forward_agree,seconds,status,look_stretch_p99,look_worst_part,look_worst_joint,"
        "look_torn_p99,look_floor_median,look_floor_p95,look_parts_below,look_fidelity_mean,"
        "look_fidelity_p95,look_feet,look_source_feet,look_volume_off,look_status\n");
    int bad = 0;
    for (int i = 0; i < nfiles; i++)
        for (guint k = 0; k < riggers->len; k++) {
            int code = rb_one(reg, &g_array_index(riggers, rb_rigger, k), files[i], how);
            if (code == RF_EXIT_CANCELLED)
                return code;
            bad += code != RF_EXIT_OK;
        }
    return bad ? RF_EXIT_RUN : RF_EXIT_OK;
}

/* "x,y,z": three finite numbers. */
static bool rb_vec_ok(const char *text, double v[3])
{
    const char *s = text;
    char *end = NULL;
    for (int a = 0; a < 3; a++) {
        v[a] = g_ascii_strtod(s, &end);
        if (end == s || !isfinite(v[a]) || (a < 2 && *end != ','))
            return false;
        s = end + (a < 2);
    }
    return !*end;
}

/* One number, finite, from min to max. */
static bool rb_number_ok(const char *text, double min, double max, double *v)
{
    char *end = NULL;
    *v = g_ascii_strtod(text, &end);
    return end != text && !*end && isfinite(*v) && *v >= min && *v <= max;
}

/* --turn, --axis, --scale and --offset checked into rb_moved; false after saying what is wrong. */
static bool rb_motion_parse(const char *turn, const char *axis, const char *scale,
                            const char *offset, bool fixed_axes)
{
    double v[3];
    const char *bad = NULL;
    rb_moved = (rf_rig_move){.scale = 1, .axis = "up", .offset = "0,0,0"};
    if (turn && !rb_number_ok(turn, -36000, 36000, &rb_moved.turn))
        bad = "--turn: expected degrees, a number from -36000 to 36000";
    else if (scale && !rb_number_ok(scale, 1e-9, 1e9, &rb_moved.scale))
        bad = "--scale: expected a factor from 1e-9 to 1e9 (1 keeps the size)";
    else if (axis && strcmp(axis, "up") &&
             (!rb_vec_ok(axis, v) || (v[0] == 0 && v[1] == 0 && v[2] == 0)))
        bad = "--axis: expected up or a direction x,y,z (three numbers, not all zero)";
    else if (offset && !rb_vec_ok(offset, v))
        bad = "--offset: expected x,y,z (three numbers, in the model's units)";
    if (bad) {
        fprintf(stderr, "rigflow rig-bench: %s\n", bad);
        return false;
    }
    if (axis && strlen(axis) >= sizeof rb_moved.axis) {
        fprintf(stderr, "rigflow rig-bench: --axis: too long\n");
        return false;
    }
    if (offset && strlen(offset) >= sizeof rb_moved.offset) {
        fprintf(stderr, "rigflow rig-bench: --offset: too long\n");
        return false;
    }
    g_strlcpy(rb_moved.axis, axis ? axis : "up", sizeof rb_moved.axis);
    g_strlcpy(rb_moved.offset, offset ? offset : "0,0,0", sizeof rb_moved.offset);
    rb_moved.fixed_axes = fixed_axes;
    rb_moved.on = turn || axis || scale || offset || fixed_axes;
    return true;
}

int rf_cmd_rig_bench(rf_registry *reg, int argc, char **argv)
{
    g_auto(GStrv) names = NULL;
    gboolean list = FALSE, fixed_axes = FALSE, no_axes = FALSE;
    g_autofree char *joint_map = NULL, *joints = NULL, *look = NULL, *turn = NULL, *axis = NULL,
                    *scale = NULL, *offset = NULL;
    gint look_frames = -1; /* not given: the whole motion */
    const GOptionEntry entries[] = {
        {"joint-map", 0, 0, G_OPTION_ARG_STRING, &joint_map,
         "How predicted joints are matched to the artist's for the skinning columns: matcher "
         "(default: the skeletal-similarity matcher; a joint it leaves unmapped, or maps to an "
         "artist joint without weights, takes its nearest mapped ancestor's), nearest (the "
         "nearest artist joint) or skin (the artist joint whose weights overlap its own most: "
         "what a mapping could reach on the rig)",
         "HOW"},
        {"rigger", 'r', 0, G_OPTION_ARG_STRING_ARRAY, &names,
         "A rigger by name or node type (repeatable; default: every rigger found)", "NAME"},
        {"list", 0, 0, G_OPTION_ARG_NONE, &list, "List the riggers", NULL},
        {"joints", 0, 0, G_OPTION_ARG_FILENAME, &joints,
         "Also write every joint of both rigs to FILE as CSV (rigger,model,rig,joint,x,y,z,"
         "nearest,distance: positions and the distance to the other rig's nearest joint, "
         "named, as fractions of the longest bounding-box edge; mapped,skin_mapped,weight on "
         "the rigger's rows: the artist joint the skinning columns count the joint as, the "
         "one its skin overlaps most, and its skin's weight summed over the vertices)",
         "FILE"},
        {"look", 0, 0, G_OPTION_ARG_FILENAME, &look,
         "Also play the motion in FILE (a BVH, glTF...) on each auto-rig through the pipeline "
         "file scan-to-animation.json, its rigger node the bench's (the matcher, the retarget "
         "with feet pinned, on the skin's floor), and add retarget.measure's figures on the mesh "
         "as the look_ columns (default: not run, the columns nan)",
         "FILE"},
        {"look-frames", 0, 0, G_OPTION_ARG_INT, &look_frames,
         "With --look, play the motion's first N frames (default 0: all of it; the look is "
         "measured on 120 frames spread over them)",
         "N"},
        {"turn", 0, 0, G_OPTION_ARG_STRING, &turn,
         "Turn each model (the artist's rig and the bare mesh alike) by DEG degrees about --axis "
         "before rigging, its declared up and forward with it",
         "DEG"},
        {"axis", 0, 0, G_OPTION_ARG_STRING, &axis,
         "The axis --turn turns about: up (default: the up the file declares, +y when it "
         "declares none) or a direction x,y,z",
         "AXIS"},
        {"scale", 0, 0, G_OPTION_ARG_STRING, &scale,
         "Scale each model by F (about its origin, before the turn)", "F"},
        {"offset", 0, 0, G_OPTION_ARG_STRING, &offset,
         "Move each model by x,y,z in its own units (after the scale and the turn)", "X,Y,Z"},
        {"fixed-axes", 0, 0, G_OPTION_ARG_NONE, &fixed_axes,
         "With --turn, leave the up and forward the file declares as they were (a model saved "
         "turned in a format whose axes are fixed: a model lying on its side in a glTF)",
         NULL},
        {"no-axes", 0, 0, G_OPTION_ARG_NONE, &no_axes,
         "Give the riggers no declared up or forward, as from an OBJ, STL or PLY file: they find "
         "the body's up themselves (with --turn 90 --axis 1,0,0, a Z-up scan)",
         NULL},
        {NULL, 0, 0, 0, NULL, NULL, NULL}};
    if (!rf_parse_options(
            "rig-bench", "MODEL...",
            "Rig each rigged MODEL with its rig ignored and compare with the "
            "artist's: CSV of rigger,model,body,artist_joints,joints,cd_j2j,cd_j2b,"
            "cd_b2b (fractions of the longest bounding-box edge),precision,recall,l1 "
            "(skinning, weights under 0.15 of a vertex's largest pruned),unweighted "
            "(vertices without weights),given_precision,given_recall,given_l1 (the "
            "rigger's skinning alone, on the artist's skeleton),j2j_to_artist,j2j_from_artist "
            "(CD-J2J's two halves),up_agree,forward_agree (cosines between the skeleton "
            "analysis's axes for the two rigs: -1 is upside down or facing back),"
            "seconds,status, then with --look the motion on the auto-rig as retarget.measure "
            "judges it on the mesh, in % of its height: look_stretch_p99 (edge stretch, whole "
            "mesh),look_worst_part,look_worst_joint (the same in the part one joint carries "
            "most),look_torn_p99 (seams between parts of different joints pulled apart),"
            "look_floor_median,look_floor_p95 (the lowest vertex over the floor),"
            "look_parts_below (% of the frames whose parts high at rest, wings, tails, props, go "
            "under the floor),look_fidelity_mean,look_fidelity_p95 (degrees between each mapped "
            "bone and its source bone: the motion's directions on the rig),look_feet,"
            "look_source_feet (the feet the retarget found and pins, and the motion's feet they "
            "follow: a leg without a foot swings as an arm),look_volume_off (% its volume the "
            "worst closed solid part strays from its rest volume, p95 over the frames: a box "
            "crushed or flattened between joints; nan with none),look_status. "
            "Exit status: 0 when every model was measured (a rigger's refusal or a failed look is "
            "a row), 1 when a model could not be read, 2 on a usage error, 130 on Ctrl-C. With "
            "--turn, --axis, --scale or --offset every model is moved so (the artist's rig with "
            "the mesh) before it is rigged, and --look plays on it moved; the columns stay "
            "fractions of the unmoved mesh's "
            "longest bounding-box edge, scaled.",
            entries, &argc, &argv))
        return RF_EXIT_USAGE;
    if (!rb_motion_parse(turn, axis, scale, offset, fixed_axes))
        return RF_EXIT_USAGE;
    rb_no_axes = no_axes;
    rb_map_how how = RB_MAP_MATCHER;
    if (joint_map && !strcmp(joint_map, "nearest"))
        how = RB_MAP_NEAREST;
    else if (joint_map && !strcmp(joint_map, "skin"))
        how = RB_MAP_SKIN;
    else if (joint_map && strcmp(joint_map, "matcher")) {
        fprintf(stderr, "rigflow rig-bench: --joint-map: expected matcher, nearest or skin\n");
        return RF_EXIT_USAGE;
    }
    if (look_frames != -1 && !look) {
        fprintf(stderr, "rigflow rig-bench: --look-frames: only with --look MOTION\n");
        return RF_EXIT_USAGE;
    }
    if (!rf_rig_look_begin(&rb_look_setup, look, look_frames == -1 ? 0 : look_frames, &rb_moved))
        return RF_EXIT_USAGE;
    rb_look_setup.no_axes = rb_no_axes;
    GArray *riggers = rb_find_riggers(reg, names);
    int code = RF_EXIT_OK;
    if (list) {
        for (guint i = 0; i < riggers->len; i++) {
            rb_rigger *r = &g_array_index(riggers, rb_rigger, i);
            printf("%-12s %-16s %s\n", r->api->name, r->desc->type, r->api->doc ? r->api->doc : "");
        }
    } else if (riggers->len == 0) {
        fprintf(stderr, "rigflow rig-bench: no rigger plugin found%s\n",
                names ? " under those names" : " (set RIGFLOW_PLUGIN_PATH)");
        code = RF_EXIT_USAGE;
    } else if (argc < 2) {
        fprintf(stderr, "rigflow rig-bench: name the rigged models to measure (see --help)\n");
        code = RF_EXIT_USAGE;
    } else if (joints && !(rb_joints_out = fopen(joints, "w"))) {
        g_autofree char *shown = rf_printable(joints);
        fprintf(stderr, "rigflow rig-bench: --joints: cannot write %s: %s\n", shown,
                g_strerror(errno));
        code = RF_EXIT_USAGE;
    } else {
        if (rb_joints_out)
            fputs("rigger,model,rig,joint,x,y,z,nearest,distance,mapped,skin_mapped,weight\n",
                  rb_joints_out);
        code = rb_run(reg, riggers, argc - 1, argv + 1, how);
        if (rb_joints_out && fclose(rb_joints_out) != 0) {
            fprintf(stderr, "rigflow rig-bench: --joints: write failed\n");
            code = RF_EXIT_RUN;
        }
        rb_joints_out = NULL;
    }
    g_array_free(riggers, TRUE);
    rf_rig_look_end(&rb_look_setup);
    return code;
}
