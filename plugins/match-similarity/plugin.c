/* The skeletal-similarity matcher node (see similarity.h and doc/matching.md). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <rigflow/rigflow.h>

#include "rigflow/match-names.h"
#include "similarity.h"

#define MAX_SOURCES 64

/* "+y", "-z", "x" or "x,y,z"; "" leaves the axis to detection. */
static bool parse_axis(const char *text, rf_vec3 *out)
{
    *out = rf_v3(0, 0, 0);
    if (!text || !*text)
        return true;
    double sign = 1;
    const char *p = text;
    if (*p == '+' || *p == '-')
        sign = *p++ == '-' ? -1 : 1;
    if (p[0] && !p[1] && strchr("xyzXYZ", p[0])) {
        char c = (char)(p[0] | 0x20);
        *out = rf_v3(sign * (c == 'x'), sign * (c == 'y'), sign * (c == 'z'));
        return true;
    }
    double x, y, z;
    char end;
    if (sscanf(text, "%lf,%lf,%lf%c", &x, &y, &z, &end) != 3 || !isfinite(x + y + z) ||
        x * x + y * y + z * z == 0)
        return false;
    *out = rf_v3(x, y, z);
    return true;
}

/* "same_side=20,body_position=0": changes to the weight set. */
static bool parse_weights(const char *text, rf_ms_weights *w, char *err, size_t err_size)
{
    const char *p = text;
    while (p && *p) {
        size_t len = strcspn(p, ",");
        char item[64];
        snprintf(item, sizeof item, "%.*s", (int)(len < 63 ? len : 63), p);
        char *eq = strchr(item, '=');
        int m = -1;
        if (eq) {
            *eq = '\0';
            for (int i = 0; i < RF_MS_METRIC_COUNT; i++)
                if (strcmp(item, rf_ms_metric_names[i]) == 0)
                    m = i;
        }
        char *end = NULL;
        double v = eq ? strtod(eq + 1, &end) : 0;
        if (m < 0 || !end || *end || !isfinite(v)) {
            snprintf(err, err_size,
                     "weights: '%.*s' is not METRIC=NUMBER with a metric of: "
                     "same_side, same_type, similar_type, bone_count, orientation, sequence, "
                     "continuity, preference, body_position, digit_order",
                     (int)len, p);
            return false;
        }
        w->w[m] = v;
        p += len + (p[len] == ',');
    }
    return true;
}

/* "1,3": sources to leave out. */
static bool parse_disabled(const char *text, uint8_t *disabled, uint32_t n)
{
    for (const char *p = text; p && *p;) {
        char *end;
        long k = strtol(p, &end, 10);
        if (end == p || k < 0 || (uint32_t)k >= n || (*end && *end != ','))
            return false;
        disabled[k] = 1;
        p = *end ? end + 1 : end;
    }
    return true;
}

typedef struct ms_params {
    rf_ms_options o;
    rf_ms_weights w;
    uint8_t disabled[MAX_SOURCES];
    const char *strategy;
    bool explain;
    int64_t repeat;
    int64_t pose_frame;
} ms_params;

static bool read_axes(const rf_host *h, rf_node *node, rf_analysis_options *a, const char *up,
                      const char *fwd)
{
    if (!parse_axis(h->param_string(node, up), &a->up) ||
        !parse_axis(h->param_string(node, fwd), &a->forward)) {
        h->error(node, "%s/%s: expected an axis such as +y, -z or 0,1,0", up, fwd);
        return false;
    }
    return true;
}

static bool read_params(const rf_host *h, rf_node *node, uint32_t n, ms_params *p)
{
    memset(p, 0, sizeof *p);
    char err[512];
    const char *set = h->param_string(node, "weights");
    if (!rf_ms_weight_set(set, &p->w, &p->o.preferred_source)) {
        h->error(node, "weights: unknown set '%s' (default, thesis, prefer-N, thesis-prefer-N)",
                 set);
        return false;
    }
    if (!parse_weights(h->param_string(node, "set_weights"), &p->w, err, sizeof err)) {
        h->error(node, "%s", err);
        return false;
    }
    const char *mirror = h->param_string(node, "mirror");
    p->strategy = h->param_string(node, "strategy");
    p->o.weights = &p->w;
    p->o.thesis = strcmp(p->strategy, "thesis") == 0;
    p->o.threshold_given = true;
    p->o.threshold = h->param_float(node, "threshold");
    p->o.keep_duplicates = !h->param_bool(node, "remove_duplicates");
    p->o.mirror = strcmp(mirror, "swap") == 0    ? RF_MS_MIRROR_SWAP
                  : strcmp(mirror, "phase") == 0 ? RF_MS_MIRROR_PHASE
                                                 : RF_MS_MIRROR_NONE;
    p->o.no_reverse = !h->param_bool(node, "reverse");
    p->o.forelegs_arms = strcmp(h->param_string(node, "forelegs"), "arms") == 0;
    p->o.girdle_neck = strcmp(h->param_string(node, "girdle"), "neck") == 0;
    p->o.blend = h->param_bool(node, "blend");
    p->o.orientation_angle = h->param_float(node, "orientation_angle");
    p->o.target_analysis.leg_threshold = p->o.source_analysis.leg_threshold =
        h->param_float(node, "leg_threshold");
    p->explain = h->param_bool(node, "explain");
    p->repeat = h->param_int(node, "repeat");
    p->pose_frame = h->param_int(node, "pose_frame");
    if (!parse_disabled(h->param_string(node, "disable"), p->disabled, n)) {
        h->error(node, "disable: expected source indices below %u separated by commas", n);
        return false;
    }
    p->o.disabled = p->disabled;
    return read_axes(h, node, &p->o.target_analysis, "target_up", "target_forward") &&
           read_axes(h, node, &p->o.source_analysis, "source_up", "source_forward");
}

static double now_us(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec * 1e6 + t.tv_nsec / 1e3;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static rf_mapping *match_once(const ms_params *p, const rf_skeleton *t, const rf_skeleton **s,
                              uint32_t n, rf_ms_explain *ex, char *err, size_t err_size)
{
    if (strcmp(p->strategy, "names") == 0)
        return rf_names_match(t, s, n, 0, err, err_size);
    return rf_ms_match(t, s, n, &p->o, ex, err, err_size);
}

/* `repeat` > 1: map that many times and print the median time in microseconds on stderr (the
 * inputs are imported once, before). */
static bool time_repeats(const rf_host *h, rf_node *node, const ms_params *p, const rf_skeleton *t,
                         const rf_skeleton **s, uint32_t n)
{
    double *us = malloc((size_t)p->repeat * sizeof *us);
    char err[512];
    if (!us) {
        h->error(node, "out of memory");
        return false;
    }
    for (int64_t i = 0; i < p->repeat; i++) {
        double t0 = now_us();
        rf_mapping *m = match_once(p, t, s, n, NULL, err, sizeof err);
        us[i] = now_us() - t0;
        rf_mapping_free(m);
    }
    qsort(us, (size_t)p->repeat, sizeof *us, cmp_double);
    fprintf(stderr, "map_us_median=%.1f\n", us[p->repeat / 2]);
    free(us);
    return true;
}

static bool gather(const rf_host *h, rf_node *node, const rf_skeleton **t, const rf_skeleton **s,
                   uint32_t *n)
{
    *t = h->input(node, "target", 0);
    *n = h->input_count(node, "sources");
    if (*n > MAX_SOURCES) {
        h->error(node, "%u sources connected; at most %d are supported", *n, MAX_SOURCES);
        return false;
    }
    for (uint32_t k = 0; k < *n; k++)
        if (!(s[k] = h->input(node, "sources", k))) {
            h->error(node, "source %u has no skeleton", k);
            return false;
        }
    if (!*t || *n == 0) {
        h->error(node, "needs a target skeleton and at least one source skeleton");
        return false;
    }
    if ((*t)->joint_count == 0) {
        h->error(node, "the target has no joints: nothing to map (a file without a skeleton?)");
        return false;
    }
    return true;
}

static bool match_and_output(const rf_host *h, rf_node *node, const ms_params *p,
                             const rf_skeleton *t, const rf_skeleton **s, uint32_t n)
{
    if (p->repeat > 1 && !time_repeats(h, node, p, t, s, n))
        return false;
    rf_ms_explain ex = {0};
    char err[512];
    rf_mapping *m = match_once(p, t, s, n, p->explain ? &ex : NULL, err, sizeof err);
    if (!m) {
        h->error(node, "%s", err);
        return false;
    }
    if (p->explain && ex.target) {
        rf_ms_explain_print(&ex, m, t, s, stdout);
        fflush(stdout);
    }
    rf_ms_explain_clear(&ex);
    uint32_t mapped = 0, phased = 0;
    for (uint32_t j = 0; j < m->target_joint_count; j++) {
        mapped += m->entries[j].input_count > 0;
        phased += m->entries[j].input_count > 0 && (m->entries[j].inputs[0].flags & RF_MAP_MIRROR);
    }
    h->log(node, RF_LOG_INFO, "%u of %u target joints mapped", mapped, m->target_joint_count);
    if (phased && p->o.mirror == RF_MS_MIRROR_NONE) /* only the gait rule flags them then */
        h->log(node, RF_LOG_INFO,
               "%u joints of forelegs on the floor driven by the source's legs of their side half "
               "a cycle later, a trot (the source's fore limbs are arms; forelegs=arms keeps them)",
               phased);
    return h->set_output(node, "mapping", m, rf_mapping_free);
}

/* The skeleton to analyse into *out: `skel` itself, or a view of it in a pose of its connected
 * clip (frame pose_frame, or the pose showing the body best when the rest pose is degenerate).
 * False (the node failed) when out of memory: the rest pose in place of the pose asked for would
 * be another mapping. */
static bool posed(const rf_host *h, rf_node *node, const ms_params *p, const rf_skeleton *skel,
                  const rf_animation *anim, const char *what, rf_skeleton **view,
                  const rf_skeleton **out)
{
    bool degenerate = false;
    *view = NULL, *out = skel;
    if (anim && p->pose_frame < 0 && !rf_pose_degenerate_check(skel, &degenerate)) {
        h->error(node, "out of memory");
        return false;
    }
    if (!anim || (p->pose_frame < 0 && !degenerate))
        return true;
    bool fits = anim->joint_count == skel->joint_count && anim->frame_count > 0;
    int32_t frame = (int32_t)p->pose_frame;
    *view =
        frame >= 0 ? rf_posed_view(skel, anim, (uint32_t)frame) : rf_posed_best(skel, anim, &frame);
    if (!*view && fits) {
        h->error(node, "out of memory");
        return false;
    }
    if (!*view) {
        h->log(node, RF_LOG_WARNING, "%s: its clip does not fit the skeleton; rest pose used",
               what);
        return true;
    }
    char pose[64];
    if (frame >= 0)
        snprintf(pose, sizeof pose, "frame %u",
                 frame < (int32_t)anim->frame_count ? (uint32_t)frame : anim->frame_count - 1);
    else
        snprintf(pose, sizeof pose, "the mean pose");
    h->log(node, RF_LOG_INFO, "%s: analysed in %s of its clip%s", what, pose,
           p->pose_frame < 0 ? " (the rest pose is no body: every bone on one line)" : "");
    *out = *view;
    return true;
}

/* False when out of memory (said). */
static bool pose_all(const rf_host *h, rf_node *node, const ms_params *p, const rf_skeleton **t,
                     const rf_skeleton **s, uint32_t n, rf_skeleton **views)
{
    if (!posed(h, node, p, *t, h->input(node, "target_animation", 0), "target", &views[n], t))
        return false;
    uint32_t na = h->input_count(node, "source_animations");
    for (uint32_t k = 0; k < n; k++) {
        char what[32];
        snprintf(what, sizeof what, "source %u", k);
        const rf_animation *a = k < na ? h->input(node, "source_animations", k) : NULL;
        if (!posed(h, node, p, s[k], a, what, &views[k], &s[k]))
            return false;
    }
    return true;
}

static bool process(void *self, const rf_host *h, rf_node *node)
{
    (void)self;
    const rf_skeleton *t, *s[MAX_SOURCES];
    rf_skeleton *views[MAX_SOURCES + 1] = {0};
    uint32_t n;
    ms_params p;
    if (!gather(h, node, &t, s, &n) || !read_params(h, node, n, &p))
        return false;
    bool ok = pose_all(h, node, &p, &t, s, n, views) && match_and_output(h, node, &p, t, s, n);
    for (uint32_t k = 0; k <= n; k++)
        rf_posed_free(views[k]);
    return ok;
}

/* Self-test: a biped mapped onto itself turned to face the other way maps every joint to
 * itself. */
static bool selftest_run(const rf_host *host, char *err, size_t err_size)
{
    (void)host;
    static const struct {
        const char *name;
        int parent;
        double x, y, z;
    } j[] = {
        {"hips", -1, 0, 1, 0},         {"spine", 0, 0, 1.3, 0},    {"head", 1, 0, 1.6, 0},
        {"l_arm", 1, 0.2, 1.5, 0},     {"l_fore", 3, 0.5, 1.5, 0}, {"r_arm", 1, -0.2, 1.5, 0},
        {"r_fore", 5, -0.5, 1.5, 0},   {"l_leg", 0, 0.1, 0.9, 0},  {"l_shin", 7, 0.1, 0.5, 0.05},
        {"l_foot", 8, 0.1, 0.05, 0},   {"r_leg", 0, -0.1, 0.9, 0}, {"r_shin", 10, -0.1, 0.5, 0.05},
        {"r_foot", 11, -0.1, 0.05, 0},
    };
    uint32_t n = sizeof j / sizeof j[0];
    rf_skeleton *a = rf_skeleton_new(n), *b = rf_skeleton_new(n);
    bool ok = a && b;
    for (uint32_t i = 0; ok && i < n; i++) {
        rf_vec3 w = rf_v3(j[i].x, j[i].y, j[i].z), pw = rf_v3(0, 0, 0);
        if (j[i].parent >= 0)
            pw = rf_v3(j[j[i].parent].x, j[j[i].parent].y, j[j[i].parent].z);
        a->joints[i].parent = b->joints[i].parent = j[i].parent;
        a->joints[i].rest.t = rf_v3_sub(w, pw);
        rf_vec3 off = a->joints[i].rest.t; /* b faces -Z: turned half around +Y */
        b->joints[i].rest.t = rf_v3(-off.x, off.y, -off.z);
    }
    char msg[256];
    rf_mapping *m =
        ok ? rf_ms_match(b, (const rf_skeleton *const *)&a, 1, NULL, NULL, msg, sizeof msg) : NULL;
    for (uint32_t i = 0; m && i < n && ok; i++)
        if (m->entries[i].input_count != 1 || m->entries[i].inputs[0].joint != i) {
            snprintf(err, err_size, "joint %s did not map to itself", j[i].name);
            ok = false;
        }
    if (!m && ok)
        snprintf(err, err_size, "matching failed"), ok = false;
    rf_mapping_free(m);
    rf_skeleton_free(a);
    rf_skeleton_free(b);
    return ok;
}

static const rf_selftest selftest = {sizeof(rf_selftest), selftest_run};

static const void *get_extension(const char *id)
{
    return strcmp(id, RF_SELFTEST_EXTENSION) == 0 ? &selftest : NULL;
}

static const rf_port_desc inputs[] = {
    RF_PORT_DESC("target", RF_TYPE_SKELETON, 0, "The skeleton to drive."),
    RF_PORT_DESC(
        "sources", RF_TYPE_SKELETON, RF_PORT_MULTIPLE,
        "The skeletons whose motion will drive it, in order (the mapping's source indices)."),
    RF_PORT_DESC("target_animation", RF_TYPE_ANIMATION, RF_PORT_OPTIONAL,
                 "The target's clip: its frame gives the pose to analyse when the rest pose is no "
                 "body (see pose_frame)."),
    RF_PORT_DESC("source_animations", RF_TYPE_ANIMATION, RF_PORT_OPTIONAL | RF_PORT_MULTIPLE,
                 "The sources' clips, in the sources' order, for the same purpose."),
};

static const rf_port_desc outputs[] = {
    RF_PORT_DESC("mapping", RF_TYPE_MAPPING, 0,
                 "One entry per target joint: its input (or none), score, per-metric breakdown, "
                 "section and side."),
};

/* The matcher's many parameters, one line each: name, type, flags, default number and string,
 * range, choices, doc; a designated initialiser underneath. */
#define P(name_, type_, flags_, num, str, lo, hi, choices_, doc_)                                  \
    RF_PARAM_DESC(.name = (name_), .type = (type_), .flags = (flags_), .default_number = (num),    \
                  .default_string = (str), .min = (lo), .max = (hi), .choices = (choices_),        \
                  .doc = (doc_))

static const rf_param_desc params[] = {
    P("strategy", RF_PARAM_ENUM, 0, 0, "similarity", 0, 0, "similarity|thesis|names",
      "similarity: the thesis's method with what it lacked; thesis: the thesis as written; "
      "names: normalised name matching."),
    P("weights", RF_PARAM_STRING, 0, 0, "default", 0, 0, NULL,
      "Weight set: default, thesis, prefer-N (10 points for source N), thesis-prefer-N."),
    P("set_weights", RF_PARAM_STRING, 0, 0, "", 0, 0, NULL,
      "Changes to the weight set, e.g. 'same_side=40,body_position=0'."),
    P("threshold", RF_PARAM_FLOAT, RF_PARAM_HAS_RANGE, 80, NULL, -1e6, 1e6, NULL,
      "Minimum total score of a match; 80 maps every section with a same-type, same-side "
      "counterpart and no more."),
    P("remove_duplicates", RF_PARAM_BOOL, 0, 1, NULL, 0, 0, NULL,
      "Assign bones along each pair of sections in order by bone length (thesis 4.2.2)."),
    P("mirror", RF_PARAM_ENUM, 0, 0, "none", 0, 0, "none|swap|phase",
      "Every second pair of legs: swap takes the other side's source (the thesis's mirror "
      "setting), phase flags it to play half a cycle away."),
    P("forelegs", RF_PARAM_ENUM, 0, 0, "gait", 0, 0, "gait|arms",
      "Forelegs standing on the floor when every source walks on two legs (arms off the "
      "floor): gait drives each from the source's leg of its side half a cycle later (a trot); "
      "arms keeps the arms on them (homology)."),
    P("girdle", RF_PARAM_ENUM, 0, 0, "chest", 0, 0, "chest|neck",
      "A girdle joint whose limbs leave at its pivot and whose bone runs on past the source's "
      "neck pivot (a curve skeleton's): chest drives it by the source's chest, the joint carrying "
      "the limbs (for motion); neck by the source's first neck joint, where its bone and skin lie "
      "(correspondence: rig-bench's skinning), with the rest of the spine aligned again below "
      "it, a trunk without a head giving its girdle joint the source's head, a limb without "
      "digits keeping the source's fist, limbs that lack the source's first bones counted from "
      "where their pivots lie in the bodies' frames, a girdle bone lying past the source's "
      "skull pivot given the skull, and a match to a source joint that carries no skin moved "
      "to the source joint holding the skin there."),
    P("reverse", RF_PARAM_BOOL, 0, 1, NULL, 0, 0, NULL,
      "Flag joints whose chain bends the other way than their source's (knees) as reversed."),
    P("blend", RF_PARAM_BOOL, 0, 0, NULL, 0, 0, NULL,
      "With several sources: drive each joint from every source that maps it, weights equal."),
    P("disable", RF_PARAM_STRING, 0, 0, "", 0, 0, NULL,
      "Sources to leave out, as indices separated by commas, e.g. '1'."),
    P("orientation_angle", RF_PARAM_FLOAT, RF_PARAM_HAS_RANGE, 0, NULL, 0, 180, NULL,
      "Angle in degrees where orientation points reach zero; 0: 45 (thesis strategy: the "
      "orientation weight, 15)."),
    P("leg_threshold", RF_PARAM_FLOAT, RF_PARAM_HAS_RANGE, 0.25, NULL, 0, 1, NULL,
      "A limb ending below this fraction of the body's height is a leg."),
    P("target_up", RF_PARAM_STRING, 0, 0, "", 0, 0, NULL,
      "Force the target's up axis (+y, -z, or x,y,z); empty: detect."),
    P("target_forward", RF_PARAM_STRING, 0, 0, "", 0, 0, NULL,
      "Force the target's facing; empty: detect."),
    P("source_up", RF_PARAM_STRING, 0, 0, "", 0, 0, NULL, "Force the sources' up axis."),
    P("source_forward", RF_PARAM_STRING, 0, 0, "", 0, 0, NULL, "Force the sources' facing."),
    P("explain", RF_PARAM_BOOL, 0, 0, NULL, 0, 0, NULL,
      "Print, per target joint, the three best candidates with every metric, then the sections "
      "and sides found, on standard output."),
    P("repeat", RF_PARAM_INT, RF_PARAM_HAS_RANGE, 1, NULL, 1, 1000000, NULL,
      "Map this many times and print map_us_median=<microseconds> on standard error."),
    P("pose_frame", RF_PARAM_INT, RF_PARAM_HAS_RANGE, -1, NULL, -1, 1e9, NULL,
      "The pose to analyse for skeletons whose clip is connected: -1 the rest pose, or when "
      "that is no body (every bone on one line, as Maya joint orients leave it) the clip's mean "
      "pose or most symmetric frame; N: frame N."),
};

static const rf_node_desc node_desc = {
    .size = sizeof(rf_node_desc),
    .type = "skeletal-similarity",
    .kind = RF_KIND_MATCHER,
    .doc = "Maps the joints of a target skeleton onto one or more source skeletons from geometry "
           "and hierarchy alone: sections (spine, head, tail, arms, hands, legs, feet) and sides "
           "are detected, every pair of joints is scored by weighted metrics (Weijden 2014, "
           "Table 1, plus body position and digit order), duplicate bones are removed along each "
           "section, and matches under the threshold stay unmapped. doc/matching.md.",
    RF_NODE_INPUTS(inputs),
    RF_NODE_OUTPUTS(outputs),
    RF_NODE_PARAMS(params),
    .process = process,
    .get_extension = get_extension,
};

static const rf_node_desc *const nodes[] = {&node_desc};

RF_PLUGIN_EXPORT const rf_plugin_entry rigflow_plugin_entry = {
    .abi = RF_ABI_VERSION_INIT,
    .size = sizeof(rf_plugin_entry),
    .id = "org.rigflow.match-similarity",
    .name = "skeletal-similarity",
    .version = "0.1.0",
    .description = "Automatic joint mapping between different skeletons from geometry and "
                   "hierarchy",
    .node_count = 1,
    .nodes = nodes,
};
