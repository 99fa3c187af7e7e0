/* report.html: one self-contained HTML page of a mapping and a retarget (doc/report.md).
 *
 * The page carries everything it needs: three.js and its orbit controls and glTF loader read from
 * where Debian's libjs-three installs them (configure --with-three) and inlined, our viewer script
 * and style compiled into the plugin, the data as one <script type="application/json"> block
 * (html-out.h escapes it), and the target's skinned mesh as a GLB written with our glTF writer
 * and embedded as base64. So it opens offline, from a mail attachment or a CI artefact.
 *
 * Long clips are sampled (at most `fps` frames per second and `max_frames` frames), and the page
 * says so; the measures keep every frame, their plots draw each pixel's largest value. */
#include "config.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <rigflow/plugin.h>

#include <rigflow/analysis.h>
#include <rigflow/gltf-write.h>

#include "html-out.h"
/* generated in the build tree from viewer.js, viewer.css and viewer.html (embed.sh) */
#include <report-assets.h>

#define RF_REPORT_MAX_SOURCES 16

/* One skeleton on the page and the clip it plays, sampled on the page's timeline. */
typedef struct rf_rep_char {
    const char *role; /* "source" or "target" */
    const rf_skeleton *s;
    const rf_animation *a; /* may be NULL: the rest pose stands still */
    rf_analysis *an;
    bool posed;         /* the rest pose is no body: analysed in a pose of the clip instead */
    int32_t pose_frame; /* that pose's frame, or -1 for the clip's mean pose */
} rf_rep_char;

/* The page's timeline: `total` frames at `fps`, every `step`th shown. */
typedef struct rf_rep_timeline {
    uint32_t total, step, shown;
    double fps;
} rf_rep_timeline;

typedef struct rf_rep {
    const rf_host *host;
    rf_node *node;
    rf_rep_char chars[RF_REPORT_MAX_SOURCES + 1];
    uint32_t source_count;
    const rf_mapping *mapping;
    const rf_mesh *mesh;
    const rf_measures **measures; /* [measure_count], every one connected */
    uint32_t measure_count;
    rf_rep_timeline tl;
} rf_rep;

static rf_rep_char *rf_rep_target(rf_rep *r)
{
    return &r->chars[r->source_count];
}

/* ---- checking the inputs ---- */

/* The mapping (optional) must fit the skeletons on the page: its joints index them. */
static bool rf_rep_check_mapping(rf_rep *r)
{
    const rf_host *h = r->host;
    rf_node *n = r->node;
    const rf_mapping *m = r->mapping;
    if (!m)
        return true;
    if (m->target_joint_count != rf_rep_target(r)->s->joint_count) {
        h->error(n, "the mapping is for %u target joints but the target has %u",
                 m->target_joint_count, rf_rep_target(r)->s->joint_count);
        return false;
    }
    for (uint32_t j = 0; j < m->target_joint_count; j++)
        for (uint32_t i = 0; i < m->entries[j].input_count; i++) {
            const rf_map_input *in = &m->entries[j].inputs[i];
            if (in->source >= r->source_count || in->joint >= r->chars[in->source].s->joint_count) {
                h->error(n,
                         "the mapping drives target joint %u from source %u joint %u, which "
                         "the report's source skeletons do not have",
                         j, in->source, in->joint);
                return false;
            }
        }
    return true;
}

/* The node's inputs into r, each skeleton checked against its clip. */
static bool rf_rep_gather(rf_rep *r)
{
    const rf_host *h = r->host;
    rf_node *n = r->node;
    r->source_count = h->input_count(n, "sources");
    if (r->source_count > RF_REPORT_MAX_SOURCES) {
        h->error(n, "%u source skeletons: a report shows at most %d", r->source_count,
                 RF_REPORT_MAX_SOURCES);
        return false;
    }
    uint32_t clips = h->input_count(n, "source_animations");
    for (uint32_t k = 0; k < r->source_count; k++)
        r->chars[k] = (rf_rep_char){.role = "source",
                                    .s = h->input(n, "sources", k),
                                    .a = k < clips ? h->input(n, "source_animations", k) : NULL};
    *rf_rep_target(r) = (rf_rep_char){
        .role = "target", .s = h->input(n, "target", 0), .a = h->input(n, "animation", 0)};
    r->mapping = h->input(n, "mapping", 0);
    r->mesh = h->input(n, "mesh", 0);
    r->measure_count = h->input_count(n, "measures");
    r->measures = calloc(r->measure_count ? r->measure_count : 1, sizeof *r->measures);
    if (!r->measures) {
        h->error(n, "out of memory");
        return false;
    }
    for (uint32_t i = 0; i < r->measure_count; i++)
        r->measures[i] = h->input(n, "measures", i);
    for (uint32_t c = 0; c <= r->source_count; c++) {
        rf_rep_char *ch = &r->chars[c];
        if (ch->a && ch->a->frame_count == 0)
            ch->a = NULL; /* a clip without frames: the rest pose stands still */
        if (!ch->s) {
            h->error(n, "no %s skeleton reached the report", ch->role);
            return false;
        }
        if (ch->a && (ch->a->joint_count != ch->s->joint_count || !(ch->a->fps > 0))) {
            h->error(n, "the %s animation has %u joints at %g fps but its skeleton has %u joints",
                     ch->role, ch->a->joint_count, ch->a->fps, ch->s->joint_count);
            return false;
        }
    }
    return rf_rep_check_mapping(r);
}

/* The clip the timeline follows (the retargeted one, else the first source's), the frames shown:
 * at most `fps_cap` a second and `max_frames` in all. */
static void rf_rep_timeline_make(rf_rep *r, double fps_cap, uint32_t max_frames)
{
    const rf_animation *a = rf_rep_target(r)->a;
    for (uint32_t k = 0; !a && k < r->source_count; k++)
        a = r->chars[k].a;
    r->tl = (rf_rep_timeline){1, 1, 1, 30};
    if (!a || a->frame_count == 0)
        return;
    r->tl.total = a->frame_count;
    r->tl.fps = a->fps;
    /* in double, clamped to the clip: a file's fps may be 1e300 (Frame Time 1e-300) */
    double step = fps_cap > 0 && a->fps > fps_cap ? ceil(a->fps / fps_cap - 1e-9) : 1;
    if (max_frames > 0)
        step = fmax(step, ceil((double)a->frame_count / max_frames));
    r->tl.step = step < a->frame_count ? (uint32_t)step : a->frame_count;
    r->tl.shown = (a->frame_count - 1) / r->tl.step + 1;
}

/* The frame of clip `a` shown at timeline frame k, `start` seconds into that clip. */
static uint32_t rf_rep_frame_of(const rf_rep *r, const rf_animation *a, double start, uint32_t k)
{
    double t = start + (double)k * r->tl.step / r->tl.fps;
    double f = fmax(floor(t * a->fps + 0.5), 0);
    return f >= a->frame_count ? a->frame_count - 1 : (uint32_t)f;
}

/* Where character ch's clip starts on the page: a source plays from where the retargeted clip
 * was cut from it (its source_start), so both show the same moment of a window of the motion. */
static double rf_rep_start(rf_rep *r, const rf_rep_char *ch)
{
    const rf_animation *t = rf_rep_target(r)->a;
    return ch != rf_rep_target(r) && t && RF_HAS_FIELD(t, rf_animation, source_start)
               ? t->source_start
               : 0;
}

/* ---- characters ---- */

static uint32_t rf_rep_tip_count(const rf_skeleton *s)
{
    uint32_t n = 0;
    for (uint32_t j = 0; j < s->joint_count; j++)
        n += (s->joints[j].flags & RF_JOINT_HAS_END_SITE) != 0;
    return n;
}

/* World pivots of every joint, then the tips of the joints with an end site, into out (floats,
 * 3 per point). */
static void rf_rep_points(const rf_skeleton *s, const rf_xform *world, float *out)
{
    size_t p = 0;
    for (uint32_t j = 0; j < s->joint_count; j++, p += 3)
        out[p] = (float)world[j].t.x, out[p + 1] = (float)world[j].t.y,
        out[p + 2] = (float)world[j].t.z;
    for (uint32_t j = 0; j < s->joint_count; j++) {
        if (!(s->joints[j].flags & RF_JOINT_HAS_END_SITE))
            continue;
        rf_vec3 t = rf_xform_point(world[j], s->joints[j].end_site);
        out[p] = (float)t.x, out[p + 1] = (float)t.y, out[p + 2] = (float)t.z;
        p += 3;
    }
}

static void rf_rep_pose_world(const rf_skeleton *s, const rf_animation *a, uint32_t f,
                              rf_xform *world)
{
    rf_animation_local_pose(a, s, f, world);
    for (uint32_t j = 0; j < s->joint_count; j++) {
        int32_t p = s->joints[j].parent;
        if (p >= 0)
            world[j] = rf_xform_mul(world[p], world[j]);
    }
}

static const char *rf_rep_section(const rf_rep *r, const rf_rep_char *ch, uint32_t j, bool side)
{
    const rf_mapping *m = r->mapping;
    bool target = ch == &r->chars[r->source_count];
    if (target && m && RF_HAS_FIELD(m, rf_mapping, sides)) {
        char **names = side ? m->sides : m->sections;
        if (names && names[j])
            return names[j]; /* where the matcher placed it: the view the mapping was made in */
    }
    const rf_joint_info *ji = &ch->an->joints[j];
    if (side)
        return rf_side_name(ji->side);
    return ji->section >= 0 ? rf_section_type_name(ch->an->sections[ji->section].type) : NULL;
}

static void rf_rep_vec(FILE *f, rf_vec3 v)
{
    fputc('[', f);
    rf_html_json_number(f, v.x), fputc(',', f);
    rf_html_json_number(f, v.y), fputc(',', f);
    rf_html_json_number(f, v.z);
    fputc(']', f);
}

static bool rf_rep_write_char(rf_rep *r, FILE *f, rf_rep_char *ch)
{
    const rf_skeleton *s = ch->s;
    uint32_t np = s->joint_count + rf_rep_tip_count(s);
    rf_xform *world = malloc((s->joint_count ? s->joint_count : 1) * sizeof *world);
    size_t frames = ch->a ? r->tl.shown : 1;
    float *pts = malloc(((size_t)np * 3 * frames + 1) * sizeof *pts);
    if (!world || !pts) {
        free(world), free(pts);
        return false;
    }
    fputs("{\"role\":", f);
    rf_html_json_string(f, ch->role);
    fputs(",\"name\":", f);
    rf_html_json_string(f, s->name);
    fputs(",\"joints\":[", f);
    for (uint32_t j = 0; j < s->joint_count; j++) {
        fprintf(f, "%s{\"name\":", j ? "," : "");
        rf_html_json_string(f, s->joints[j].name);
        fprintf(f, ",\"parent\":%d,\"section\":", s->joints[j].parent);
        rf_html_json_string(f, rf_rep_section(r, ch, j, false));
        fputs(",\"side\":", f);
        rf_html_json_string(f, rf_rep_section(r, ch, j, true));
        fputc('}', f);
    }
    fputs("],\"tips\":[", f);
    for (uint32_t j = 0, n = 0; j < s->joint_count; j++)
        if (s->joints[j].flags & RF_JOINT_HAS_END_SITE)
            fprintf(f, "%s%u", n++ ? "," : "", j);
    fputs("],\"up\":", f);
    rf_rep_vec(f, ch->an->up);
    fputs(",\"forward\":", f);
    rf_rep_vec(f, ch->an->forward);
    fputs(",\"height\":", f);
    rf_html_json_number(f, ch->an->height);
    fputs(",\"ground\":", f);
    rf_html_json_number(f, ch->an->ground);
    rf_skeleton_world_rest(s, world);
    rf_rep_points(s, world, pts);
    fputs(",\"rest\":", f);
    rf_html_json_floats(f, pts, (size_t)np * 3);
    fputs(",\"frames\":", f);
    if (ch->a) {
        double start = rf_rep_start(r, ch);
        for (uint32_t k = 0; k < r->tl.shown; k++) {
            rf_rep_pose_world(s, ch->a, rf_rep_frame_of(r, ch->a, start, k), world);
            rf_rep_points(s, world, pts + (size_t)k * np * 3);
        }
        rf_html_json_floats(f, pts, (size_t)np * 3 * r->tl.shown);
    } else {
        fputs("null", f);
    }
    fputc('}', f);
    free(world), free(pts);
    return true;
}

/* ---- mapping, measures ---- */

static void rf_rep_write_mapping(const rf_rep *r, FILE *f)
{
    const rf_mapping *m = r->mapping;
    if (!m) {
        fputs("null", f);
        return;
    }
    fputs("{\"metrics\":[", f);
    for (uint32_t i = 0; i < m->metric_count; i++) {
        fputs(i ? "," : "", f);
        rf_html_json_string(f, m->metric_names[i]);
    }
    fputs("],\"rows\":[", f);
    for (uint32_t j = 0; j < m->target_joint_count; j++) {
        const rf_map_entry *e = &m->entries[j];
        fputs(j ? ",{\"inputs\":[" : "{\"inputs\":[", f);
        for (uint32_t i = 0; i < e->input_count; i++) {
            const rf_map_input *in = &e->inputs[i];
            fprintf(f, "%s{\"source\":%u,\"joint\":%u,\"flags\":%u,\"weight\":", i ? "," : "",
                    in->source, in->joint, in->flags);
            rf_html_json_number(f, in->weight);
            fputs(",\"delay\":", f);
            rf_html_json_number(f, in->delay);
            fputc('}', f);
        }
        fputs("],\"score\":", f);
        rf_html_json_number(f, e->score);
        fputs(",\"metrics\":", f);
        if (e->metrics) {
            fputc('[', f);
            for (uint32_t i = 0; i < m->metric_count; i++) {
                fputs(i ? "," : "", f);
                rf_html_json_number(f, e->metrics[i]);
            }
            fputc(']', f);
        } else {
            fputs("null", f);
        }
        fputc('}', f);
    }
    fputs("]}", f);
}

static void rf_rep_write_measures(rf_rep *r, FILE *f)
{
    uint32_t joints = rf_rep_target(r)->s->joint_count;
    fputc('[', f);
    bool first = true;
    for (uint32_t i = 0; i < r->measure_count; i++) {
        const rf_measures *ms = r->measures[i];
        for (uint32_t k = 0; ms && k < ms->series_count; k++) {
            const rf_series *s = &ms->series[k];
            fputs(first ? "{\"name\":" : ",{\"name\":", f);
            first = false;
            rf_html_json_string(f, s->name);
            fputs(",\"unit\":", f);
            rf_html_json_string(f, s->unit);
            /* a joint the target lacks (another plugin's mistake) reads as the whole character */
            int32_t joint = s->joint >= 0 && (uint32_t)s->joint < joints ? s->joint : -1;
            fprintf(f, ",\"joint\":%d,\"contact\":%s,\"higher_worse\":%s,\"fps\":", joint,
                    s->flags & RF_SERIES_CONTACT ? "true" : "false",
                    s->flags & RF_SERIES_HIGHER_WORSE ? "true" : "false");
            rf_html_json_number(f, ms->fps);
            fputs(",\"values\":", f);
            rf_html_json_floats(f, s->values, ms->frame_count);
            fputc('}', f);
        }
    }
    fputc(']', f);
}

/* ---- warnings and the lines at the top ---- */

static void rf_rep_warn_axes(FILE *f, const rf_rep_char *ch, bool *first)
{
    const rf_analysis *an = ch->an;
    char line[256];
    if (ch->posed) {
        if (ch->pose_frame >= 0)
            snprintf(line, sizeof line,
                     "%s: its rest pose is no body (all pivots on one line); sections and axes "
                     "from frame %d of its clip",
                     ch->role, ch->pose_frame);
        else
            snprintf(line, sizeof line,
                     "%s: its rest pose is no body (all pivots on one line); sections and axes "
                     "from its clip's mean pose",
                     ch->role);
        fputs(*first ? "" : ",", f), rf_html_json_string(f, line), *first = false;
    }
    if (an->up_confidence < 0.5) {
        snprintf(line, sizeof line, "%s: the up axis is a guess (from %s, confidence %.2f)",
                 ch->role, an->up_source, an->up_confidence);
        fputs(*first ? "" : ",", f), rf_html_json_string(f, line), *first = false;
    }
    if (an->forward_confidence < 0.5) {
        snprintf(line, sizeof line, "%s: the forward axis is a guess (from %s, confidence %.2f)",
                 ch->role, an->forward_source, an->forward_confidence);
        fputs(*first ? "" : ",", f), rf_html_json_string(f, line), *first = false;
    }
}

static void rf_rep_write_warnings(rf_rep *r, FILE *f)
{
    bool first = true;
    fputc('[', f);
    for (uint32_t i = 0; i < r->measure_count; i++)
        for (uint32_t k = 0; r->measures[i] && k < r->measures[i]->warning_count; k++) {
            fputs(first ? "" : ",", f);
            rf_html_json_string(f, r->measures[i]->warnings[k]);
            first = false;
        }
    for (uint32_t c = 0; c <= r->source_count; c++)
        rf_rep_warn_axes(f, &r->chars[c], &first);
    const rf_mapping *m = r->mapping;
    uint32_t unmapped = 0;
    for (uint32_t j = 0; m && j < m->target_joint_count; j++)
        unmapped += m->entries[j].input_count == 0;
    if (unmapped) {
        char line[128];
        snprintf(line, sizeof line, "%u of %u target joints are unmapped (marked in the table)",
                 unmapped, m->target_joint_count);
        fputs(first ? "" : ",", f), rf_html_json_string(f, line);
    }
    fputc(']', f);
}

static void rf_rep_write_texts(rf_rep *r, FILE *f)
{
    const rf_rep_char *t = rf_rep_target(r);
    char line[512];
    const char *title = r->host->param_string(r->node, "title");
    if (!*title)
        title = t->s->name ? t->s->name : "";
    fputs("\"title\":", f);
    rf_html_json_string(f, title);
    size_t n = snprintf(line, sizeof line, "target: %u joints", t->s->joint_count);
    for (uint32_t k = 0; k < r->source_count && n < sizeof line; k++)
        n += snprintf(line + n, sizeof line - n, "; source %u: %u joints", k + 1,
                      r->chars[k].s->joint_count);
    if (r->tl.total > 1 && n < sizeof line)
        snprintf(line + n, sizeof line - n, "; %u frames at %g fps (%.2f s)", r->tl.total,
                 r->tl.fps, r->tl.total / r->tl.fps);
    fputs(",\"summary\":", f);
    rf_html_json_string(f, line);
    line[0] = 0;
    if (r->tl.step > 1)
        snprintf(line, sizeof line,
                 "Frames are sampled to keep the page fast: %u of %u shown (one in %u)%s.",
                 r->tl.shown, r->tl.total, r->tl.step,
                 r->measure_count ? "; the measure plots keep every frame" : "");
    if (!r->mesh || !r->mesh->vertex_count)
        strncat(line,
                line[0] ? " The target has no mesh: its skeleton is shown alone."
                        : "The target has no mesh: its skeleton is shown alone.",
                sizeof line - strlen(line) - 1);
    fputs(",\"notice\":", f);
    rf_html_json_string(f, line);
    fprintf(f, ",\"timeline\":{\"total\":%u,\"step\":%u,\"shown\":%u,\"fps\":", r->tl.total,
            r->tl.step, r->tl.shown);
    rf_html_json_number(f, r->tl.fps);
    fputc('}', f);
}

/* ---- the mesh as GLB ---- */

/* The target's clip at the shown frames (at the shown rate), for the GLB. */
static rf_animation *rf_rep_sampled(const rf_rep *r, const rf_animation *a)
{
    rf_animation *out = rf_animation_new(a->joint_count, r->tl.shown, r->tl.fps / r->tl.step);
    for (uint32_t k = 0; out && k < r->tl.shown; k++) {
        uint32_t f = rf_rep_frame_of(r, a, 0, k);
        size_t n = a->joint_count;
        memcpy(out->rotations + k * n * 4, a->rotations + f * n * 4, n * 4 * sizeof(float));
        memcpy(out->translations + k * n * 3, a->translations + f * n * 3, n * 3 * sizeof(float));
    }
    if (out)
        memcpy(out->channels, a->channels, a->joint_count);
    return out;
}

static int rf_rep_base64_file(FILE *f, const char *path)
{
    FILE *in = fopen(path, "rb");
    if (!in)
        return -1;
    unsigned char buf[3 * 16384];
    size_t n;
    fputc('"', f);
    while ((n = fread(buf, 1, sizeof buf, in)) > 0)
        rf_html_base64(f, buf, n);
    fputc('"', f);
    int bad = ferror(in);
    fclose(in);
    return bad ? -1 : 0;
}

static bool rf_rep_write_glb(rf_rep *r, FILE *f, const char *out_path)
{
    const rf_rep_char *t = rf_rep_target(r);
    fputs(",\"glb\":", f);
    if (!r->mesh || !r->mesh->vertex_count) {
        fputs("null", f);
        return true;
    }
    size_t len = strlen(out_path) + 16;
    char *tmp = malloc(len);
    rf_animation *clip = t->a ? rf_rep_sampled(r, t->a) : NULL;
    char err[256] = "out of memory";
    rf_gltf_write_opts o = {.binary = true, .generator = "rigflow report"};
    bool ok = tmp && (!t->a || clip);
    if (ok) {
        snprintf(tmp, len, "%s.mesh.glb", out_path);
        ok = rf_gltf_write_file(tmp, "the report's mesh", t->s, clip, r->mesh, &o, err, sizeof err);
        ok = ok && rf_rep_base64_file(f, tmp) == 0;
        unlink(tmp);
    }
    if (!ok)
        r->host->error(r->node, "cannot embed the target's mesh: %s", err);
    free(tmp);
    rf_animation_free(clip);
    return ok;
}

/* ---- the page ---- */

static const char *const rf_rep_three_files[] = {"build/three.min.js",
                                                 "examples/js/controls/OrbitControls.js",
                                                 "examples/js/loaders/GLTFLoader.js"};
#define RF_REP_THREE_FILES (sizeof rf_rep_three_files / sizeof rf_rep_three_files[0])

/* Path of three.js file i (malloc'd), from the node's `three` or configure's folder. */
static char *rf_rep_three_path(const rf_host *host, rf_node *node, size_t i)
{
    const char *dir = host->param_string(node, "three");
    if (!*dir)
        dir = RF_THREE_DIR;
    size_t len = strlen(dir) + strlen(rf_rep_three_files[i]) + 2;
    char *path = malloc(len);
    if (path)
        snprintf(path, len, "%s/%s", dir, rf_rep_three_files[i]);
    return path;
}

static void rf_rep_three_missing(const rf_host *host, rf_node *node, const char *path)
{
    host->error(node,
                "cannot read three.js file %s (install Debian's libjs-three, or point "
                "report.three or configure --with-three at a folder holding build/, examples/js/)",
                path);
}

static bool rf_rep_three(rf_rep *r, FILE *f)
{
    for (size_t i = 0; i < RF_REP_THREE_FILES; i++) {
        char *path = rf_rep_three_path(r->host, r->node, i);
        if (!path)
            return false;
        fputs("<script>\n", f);
        int bad = rf_html_copy_file(f, path);
        fputs("\n</script>\n", f);
        if (bad)
            rf_rep_three_missing(r->host, r->node, path);
        free(path);
        if (bad)
            return false;
    }
    return true;
}

/* three.js is checked before any node runs, so a missing file fails in milliseconds. */
static bool html_create(const rf_host *host, rf_node *node, void **self)
{
    *self = NULL;
    if (!*host->param_string(node, "path"))
        return true;
    for (size_t i = 0; i < RF_REP_THREE_FILES; i++) {
        char *path = rf_rep_three_path(host, node, i);
        bool readable = path && access(path, R_OK) == 0;
        if (!readable)
            rf_rep_three_missing(host, node, path ? path : "(out of memory)");
        free(path);
        if (!readable)
            return false;
    }
    return true;
}

static bool rf_rep_write(rf_rep *r, FILE *f, const char *path)
{
    fprintf(f,
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            "<title>rigflow report</title>\n<style>\n%s</style>\n</head>\n<body>\n%s",
            rf_report_viewer_css, rf_report_viewer_html);
    fputs("<script type=\"application/json\" id=\"rf-data\">{", f);
    rf_rep_write_texts(r, f);
    fputs(",\"characters\":[", f);
    for (uint32_t c = 0; c <= r->source_count; c++) {
        fputs(c ? "," : "", f);
        if (!rf_rep_write_char(r, f, &r->chars[c])) {
            r->host->error(r->node, "out of memory");
            return false;
        }
    }
    fputs("],\"mapping\":", f);
    rf_rep_write_mapping(r, f);
    fputs(",\"measures\":", f);
    rf_rep_write_measures(r, f);
    fputs(",\"warnings\":", f);
    rf_rep_write_warnings(r, f);
    if (!rf_rep_write_glb(r, f, path))
        return false;
    fputs("}</script>\n", f);
    if (!rf_rep_three(r, f))
        return false;
    fprintf(f, "<script>\n%s</script>\n</body>\n</html>\n", rf_report_viewer_js);
    return true;
}

/* Sections and axes as the matcher finds them: from the rest pose, or, where the rest pose is no
 * body (every pivot on one line), from the pose of the clip that shows the body best. */
static bool rf_rep_analyze(rf_rep *r)
{
    for (uint32_t c = 0; c <= r->source_count; c++) {
        rf_rep_char *ch = &r->chars[c];
        rf_skeleton *view = NULL;
        bool degenerate = false, clip = ch->a && ch->a->frame_count;
        /* out of memory is said, never read as a rest pose that is a body (nor as a clip that
         * does not fit) */
        bool ok = !clip || rf_pose_degenerate_check(ch->s, &degenerate);
        if (ok && degenerate) {
            view = rf_posed_best(ch->s, ch->a, &ch->pose_frame);
            ok = view || ch->a->joint_count != ch->s->joint_count;
        }
        ch->posed = view != NULL;
        ch->an = ok ? rf_analyze(view ? view : ch->s, NULL) : NULL;
        rf_posed_free(view);
        if (!ch->an) {
            r->host->error(r->node, "out of memory");
            return false;
        }
    }
    return true;
}

static bool html_process(void *self, const rf_host *host, rf_node *node)
{
    (void)self;
    const char *path = host->param_string(node, "path");
    if (!*path)
        return true; /* no path, no report: pipelines carry the node for whoever asks */
    rf_rep r = {.host = host, .node = node};
    bool ok = rf_rep_gather(&r) && rf_rep_analyze(&r);
    if (ok) {
        rf_rep_timeline_make(&r, host->param_float(node, "fps"),
                             (uint32_t)host->param_int(node, "max_frames"));
        FILE *f = fopen(path, "w");
        if (!f) {
            host->error(node, "cannot write %s", host->param_output_target(node, "path"));
            ok = false;
        } else {
            ok = rf_rep_write(&r, f, path);
            bool bad = ferror(f) != 0;
            if ((fclose(f) != 0 || bad) && ok) {
                host->error(node, "cannot write %s", host->param_output_target(node, "path"));
                ok = false;
            }
        }
    }
    for (uint32_t c = 0; c <= r.source_count && c <= RF_REPORT_MAX_SOURCES; c++)
        rf_analysis_free(r.chars[c].an);
    free(r.measures);
    if (ok)
        host->log(node, RF_LOG_INFO, "report: %s", host->param_output_target(node, "path"));
    return ok;
}

static const rf_port_desc html_inputs[] = {
    RF_PORT_DESC("target", RF_TYPE_SKELETON, 0, "the skeleton driven"),
    RF_PORT_DESC("sources", RF_TYPE_SKELETON, RF_PORT_OPTIONAL | RF_PORT_MULTIPLE,
                 "the source skeletons, in the mapping's order"),
    RF_PORT_DESC("source_animations", RF_TYPE_ANIMATION, RF_PORT_OPTIONAL | RF_PORT_MULTIPLE,
                 "their clips, played beside the target's"),
    RF_PORT_DESC("animation", RF_TYPE_ANIMATION, RF_PORT_OPTIONAL,
                 "the target's (retargeted) clip"),
    RF_PORT_DESC("mesh", RF_TYPE_MESH, RF_PORT_OPTIONAL,
                 "the target's skinned mesh, embedded as GLB"),
    RF_PORT_DESC("mapping", RF_TYPE_MAPPING, RF_PORT_OPTIONAL, "the mapping: lines, table, scores"),
    RF_PORT_DESC(
        "measures", RF_TYPE_MEASURES, RF_PORT_OPTIONAL | RF_PORT_MULTIPLE,
        "measures over time (retarget.measure, ...): every series is plotted, warnings shown"),
};

static const rf_param_desc html_params[] = {
    RF_PARAM_DESC(.name = "path", .type = RF_PARAM_OUTPUT_PATH, .default_string = "",
                  .doc = "the HTML file to write; empty: the node does nothing"),
    RF_PARAM_DESC_STRING("title", "", "the page's title (default: the target's file name)"),
    RF_PARAM_DESC_FLOAT("fps", 30, 0, 1000,
                        "show at most this many frames per second of the clip (0: all)"),
    RF_PARAM_DESC_INT("max_frames", 1500, 0, 1e7,
                      "show at most this many frames, sampled evenly (0: no limit)"),
    RF_PARAM_DESC_STRING("three", "",
                         "folder of three.js r111 (build/three.min.js, examples/js/); default: "
                         "configure's --with-three"),
};

const rf_node_desc rf_report_html_node = {
    .size = sizeof(rf_node_desc),
    .type = "report.html",
    .kind = RF_KIND_REPORT,
    .doc = "Writes one self-contained HTML page (no network needed): source and target "
           "skeletons side by side in 3D with their sections and axes, the target's skinned "
           "mesh, mapping lines and a table of every target joint with its scores, the motions "
           "playing in sync, the measures over time and the run's warnings. doc/report.md.",
    RF_NODE_INPUTS(html_inputs),
    RF_NODE_PARAMS(html_params),
    .create = html_create,
    .process = html_process,
};
