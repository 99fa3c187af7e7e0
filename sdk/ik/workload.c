/* The IK workloads, their measurement, and the CSV and SVG they are reported in. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "rigflow/ik-workload.h"

#define DEG (RF_PI / 180.0)

static const char *const workload_names[] = {
    "chain2-it10",       "chain2-it50",       "chain5-it10",
    "chain5-it50",       "chain10-it10",      "chain10-it50",
    "chain30-it10",      "chain30-it50",      "tree2-it10",
    "tree2-it50",        "arm-it10",          "arm-it50",
    "leg-it10",          "leg-it50",          "spinearm-it10",
    "spinearm-it50",     "chain2-it10-lim",   "chain2-it50-lim",
    "chain5-it10-lim",   "chain5-it50-lim",   "chain10-it10-lim",
    "chain10-it50-lim",  "chain30-it10-lim",  "chain30-it50-lim",
    "tree2-it10-lim",    "tree2-it50-lim",    "arm-it10-lim",
    "arm-it50-lim",      "leg-it10-lim",      "leg-it50-lim",
    "spinearm-it10-lim", "spinearm-it50-lim", NULL};

const char *const *rf_ikw_names(void)
{
    return workload_names;
}

bool rf_ikw_matches(const char *name, const char *workload)
{
    size_t n = strlen(name);
    if (n == 0 || strncmp(name, workload, n) != 0)
        return false;
    for (const char *const *w = workload_names; *w; w++)
        if (!strcmp(*w, name)) /* a full name selects that workload only */
            return workload[n] == '\0';
    char next = workload[n], last = name[n - 1];
    /* "chain" selects every chain, "chain1" none of chain10's */
    return next == '\0' || next == '-' ||
           (last >= 'a' && last <= 'z' && next >= '0' && next <= '9');
}

bool rf_ikw_needs_bvh(const char *name)
{
    return strncmp(name, "arm", 3) == 0 || strncmp(name, "leg", 3) == 0 ||
           strncmp(name, "spinearm", 8) == 0;
}

/* ---- construction ---- */

/* The peers' generator: an LCG and the target law (uniform direction by rejection in the unit
 * ball, radius uniform in 0.2..0.9 of the reach), in the peers' call order. */
typedef struct lcg {
    uint32_t seed;
} lcg;

static double rnd(lcg *g)
{
    g->seed = g->seed * 1664525u + 1013904223u;
    return g->seed / 4294967296.0;
}

static rf_vec3 target_in(lcg *g, double reach)
{
    double x, y, z;
    do {
        x = 2 * rnd(g) - 1, y = 2 * rnd(g) - 1, z = 2 * rnd(g) - 1;
    } while (x * x + y * y + z * z > 1);
    double l = sqrt(x * x + y * y + z * z), r = reach * (0.2 + 0.7 * rnd(g));
    if (l == 0)
        l = 1;
    return rf_v3(x / l * r, y / l * r, z / l * r);
}

static rf_ikw *alloc_workload(uint32_t joints, uint32_t goals, uint32_t samples)
{
    rf_ikw *w = calloc(1, sizeof *w);
    if (!w)
        return NULL;
    w->joint_count = joints, w->goal_count = goals, w->sample_count = samples;
    w->parents = calloc(joints, sizeof *w->parents);
    w->pose = calloc(joints, sizeof *w->pose);
    w->limits = calloc(joints, sizeof *w->limits);
    w->goals = calloc(goals, sizeof *w->goals);
    w->targets = calloc((size_t)samples * goals, sizeof *w->targets);
    if (!w->parents || !w->pose || !w->limits || !w->goals || !w->targets) {
        rf_ikw_free(w);
        return NULL;
    }
    for (uint32_t j = 0; j < joints; j++) {
        w->parents[j] = (int32_t)j - 1;
        w->pose[j] = rf_xform_identity();
        w->limits[j].size = sizeof w->limits[j];
    }
    w->tolerance = 1e-3;
    return w;
}

void rf_ikw_free(rf_ikw *w)
{
    if (!w)
        return;
    free(w->parents), free(w->pose), free(w->limits), free(w->goals), free(w->targets);
    free(w);
}

void rf_ikw_truncate(rf_ikw *w, uint32_t count)
{
    if (count < w->sample_count)
        w->sample_count = count;
}

static void set_cone(rf_ik_constraint *c, double cone_deg, double twist_deg)
{
    c->flags = RF_IK_LIMIT_CONE | (twist_deg > 0 ? RF_IK_LIMIT_TWIST : 0);
    c->cone_angle = cone_deg * DEG;
    c->twist_min = -twist_deg * DEG, c->twist_max = twist_deg * DEG;
}

static void set_hinge(rf_ik_constraint *c, rf_vec3 axis, double min_deg, double max_deg)
{
    c->flags = RF_IK_LIMIT_HINGE;
    c->axis = axis;
    c->min_angle = min_deg * DEG, c->max_angle = max_deg * DEG;
}

/* Links along +y. Limits: a wide ball at the root, then alternately a knee-like hinge (0..150
 * degrees about x) and a 60 degree cone with 45 degrees of twist. */
static rf_ikw *make_chain(uint32_t links, bool limited)
{
    uint32_t samples = 200000 / (links * 10); /* the three.js peer's count for 10 iterations */
    if (samples < 2000)
        samples = 2000;
    rf_ikw *w = alloc_workload(links + 1, 1, samples);
    if (!w)
        return NULL;
    for (uint32_t j = 1; j <= links; j++)
        w->pose[j].t = rf_v3(0, 1, 0);
    w->goals[0] = rf_ik_goal_make(links, rf_v3(0, 0, 0));
    for (uint32_t j = 0; limited && j < links; j++) {
        if (j == 0)
            set_cone(&w->limits[j], 120, 90);
        else if (j % 2)
            set_hinge(&w->limits[j], rf_v3(1, 0, 0), 0, 150);
        else
            set_cone(&w->limits[j], 60, 45);
    }
    lcg g = {99};
    for (uint32_t k = 0; k < samples; k++)
        w->targets[k] = target_in(&g, links);
    return w;
}

/* The DLS peer's tree: spine joints 0-2, chest 3 (rigid: the arms hang off it), left arm 4-7
 * from (1, 3, 0), right arm 8-11 from (-1, 3, 0); goals on the arm tips, targets around each
 * arm's base within its reach of 3. */
static rf_ikw *make_tree(bool limited)
{
    rf_ikw *w = alloc_workload(12, 2, 400);
    if (!w)
        return NULL;
    for (uint32_t j = 1; j < 12; j++)
        w->pose[j].t = rf_v3(0, 1, 0);
    w->parents[4] = 3, w->pose[4].t = rf_v3(1, 0, 0);
    w->parents[8] = 3, w->pose[8].t = rf_v3(-1, 0, 0);
    w->limits[3].flags = RF_IK_LOCKED;
    for (uint32_t j = 0; limited && j < 12; j++) {
        if (j < 3)
            set_cone(&w->limits[j], 30, 30);
        else if (j == 4 || j == 8)
            set_cone(&w->limits[j], 100, 90);
        else if (j == 5 || j == 9)
            set_hinge(&w->limits[j], rf_v3(1, 0, 0), 0, 150);
        else if (j == 6 || j == 10)
            set_cone(&w->limits[j], 60, 45);
    }
    w->goals[0] = rf_ik_goal_make(7, rf_v3(0, 0, 0));
    w->goals[1] = rf_ik_goal_make(11, rf_v3(0, 0, 0));
    lcg g = {99};
    for (uint32_t k = 0; k < w->sample_count; k++) {
        w->targets[2 * k] = rf_v3_add(rf_v3(1, 3, 0), target_in(&g, 3));
        w->targets[2 * k + 1] = rf_v3_add(rf_v3(-1, 3, 0), target_in(&g, 3));
    }
    return w;
}

/* ---- a skeleton from a BVH hierarchy: names, parents and offsets only ---- */

#define BVH_MAX 256

typedef struct bvh_skel {
    uint32_t count;
    char name[BVH_MAX][32];
    int32_t parent[BVH_MAX];
    rf_vec3 offset[BVH_MAX];
} bvh_skel;

/* Reads the HIERARCHY section: enough for rest offsets (the motion is not needed). */
static bool read_bvh(const char *path, bvh_skel *s, char *err, size_t n)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return snprintf(err, n, "cannot open %s", path), false;
    char tok[64];
    int32_t stack[BVH_MAX], depth = 0, current = -1;
    bool end_site = false;
    s->count = 0;
    while (fscanf(f, "%63s", tok) == 1 && strcmp(tok, "MOTION") != 0) {
        if (!strcmp(tok, "ROOT") || !strcmp(tok, "JOINT")) {
            if (s->count == BVH_MAX || fscanf(f, "%31s", s->name[s->count]) != 1)
                break;
            s->parent[s->count] = depth > 0 ? stack[depth - 1] : -1;
            current = (int32_t)s->count++;
        } else if (!strcmp(tok, "End")) {
            end_site = true;
        } else if (!strcmp(tok, "{")) {
            if (depth == BVH_MAX)
                break;
            stack[depth++] = end_site ? -2 : current;
        } else if (!strcmp(tok, "}")) {
            depth = depth > 0 ? depth - 1 : 0;
            end_site = false;
        } else if (!strcmp(tok, "OFFSET")) {
            rf_vec3 o;
            if (fscanf(f, "%lf %lf %lf", &o.x, &o.y, &o.z) != 3)
                break;
            if (!end_site && current >= 0)
                s->offset[current] = o;
        }
    }
    fclose(f);
    if (s->count == 0)
        return snprintf(err, n, "%s: no joints in its HIERARCHY", path), false;
    return true;
}

static int32_t bvh_find(const bvh_skel *s, const char *name)
{
    for (uint32_t j = 0; j < s->count; j++)
        if (!strcmp(s->name[j], name))
            return (int32_t)j;
    return -1;
}

/* The path from joint `top` down to joint `tip` as a chain problem: the top joint gets its world
 * rest transform (the problem's space is the skeleton's). */
static rf_ikw *make_limb(const bvh_skel *s, const char *top, const char *tip, uint32_t samples,
                         char *err, size_t n)
{
    int32_t a = bvh_find(s, top), b = bvh_find(s, tip), path[BVH_MAX];
    uint32_t len = 0;
    for (int32_t j = b; j >= 0 && len < BVH_MAX; j = s->parent[j]) {
        path[len++] = j;
        if (j == a)
            break;
    }
    if (a < 0 || b < 0 || path[len - 1] != a)
        return snprintf(err, n, "the BVH has no chain %s..%s", top, tip), NULL;
    rf_ikw *w = alloc_workload(len, 1, samples);
    if (!w)
        return snprintf(err, n, "out of memory"), NULL;
    rf_vec3 origin = rf_v3(0, 0, 0);
    for (int32_t j = a; j >= 0; j = s->parent[j])
        origin = rf_v3_add(origin, s->offset[j]); /* the rest pose has no rotations */
    double reach = 0;
    for (uint32_t k = 0; k < len; k++) {
        int32_t j = path[len - 1 - k];
        w->pose[k].t = k == 0 ? origin : s->offset[j];
        reach += k == 0 ? 0 : rf_v3_len(s->offset[j]);
    }
    w->goals[0] = rf_ik_goal_make(len - 1, rf_v3(0, 0, 0));
    lcg g = {99};
    for (uint32_t k = 0; k < samples; k++)
        w->targets[k] = rf_v3_add(origin, target_in(&g, reach));
    return w;
}

/* Anatomical-ish limits for the limbs: ball shoulders and hips, hinge elbows and knees. */
static void limit_limb(rf_ikw *w, const char *kind)
{
    uint32_t n = w->joint_count;
    if (!strcmp(kind, "leg")) {
        set_cone(&w->limits[0], 100, 45);
        set_hinge(&w->limits[1], rf_v3(1, 0, 0), 0, 150);
        return;
    }
    /* arm and spinearm end shoulder, elbow, wrist; spinearm's spine bends little */
    for (uint32_t j = 0; j + 3 < n; j++)
        set_cone(&w->limits[j], 30, 30);
    set_cone(&w->limits[n - 3], 110, 90);
    set_hinge(&w->limits[n - 2], rf_v3(0, 1, 0), -150, 0);
}

static rf_ikw *make_bvh_workload(const char *kind, bool limited, const char *bvh, char *err,
                                 size_t n)
{
    if (!bvh || !*bvh)
        return snprintf(err, n, "needs a BVH skeleton (none given)"), NULL;
    bvh_skel *s = malloc(sizeof *s);
    if (!s)
        return snprintf(err, n, "out of memory"), NULL;
    rf_ikw *w = NULL;
    if (read_bvh(bvh, s, err, n)) {
        if (!strcmp(kind, "arm"))
            w = make_limb(s, "LeftArm", "LeftHand", 2000, err, n);
        else if (!strcmp(kind, "leg"))
            w = make_limb(s, "LeftUpLeg", "LeftFoot", 2000, err, n);
        else
            w = make_limb(s, "LowerBack", "LeftHand", 2000, err, n);
    }
    free(s);
    if (w && limited)
        limit_limb(w, kind);
    return w;
}

static rf_ikw *finish(rf_ikw *w, const char *name, unsigned cap)
{
    if (w) {
        snprintf(w->name, sizeof w->name, "%s", name);
        w->max_iterations = cap;
    }
    return w;
}

rf_ikw *rf_ikw_make(const char *name, const char *bvh_path, char *err, size_t err_size)
{
    unsigned links = 0, cap = 0;
    char kind[16] = "";
    bool limited = strstr(name, "-lim") != NULL;
    rf_ikw *w = NULL;
    if (sscanf(name, "chain%u-it%u", &links, &cap) == 2 && links >= 1 && links <= 1000)
        w = make_chain(links, limited);
    else if (sscanf(name, "tree2-it%u", &cap) == 1)
        w = make_tree(limited);
    else if (sscanf(name, "%15[a-z]-it%u", kind, &cap) == 2 && rf_ikw_needs_bvh(kind))
        return finish(make_bvh_workload(kind, limited, bvh_path, err, err_size), name, cap);
    else
        return snprintf(err, err_size, "unknown workload '%s'", name), NULL;
    if (!w)
        snprintf(err, err_size, "out of memory");
    return finish(w, name, cap);
}

/* ---- measurement ---- */

static double now_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

typedef struct run_ctx {
    const rf_ik_solver_api *api;
    void *state;
    const rf_ikw *w;
    rf_ik_goal *goals;
    rf_ik_problem pb;
    rf_ik_result res;
} run_ctx;

/* One solve of sample k, from the workload's start pose (the output is a separate array, so
 * every solve starts from the same pose). */
static bool solve_sample(run_ctx *c, uint32_t k)
{
    for (uint32_t g = 0; g < c->w->goal_count; g++) {
        c->goals[g] = c->w->goals[g];
        c->goals[g].target = c->w->targets[(size_t)k * c->w->goal_count + g];
    }
    return c->api->solve(c->state, &c->pb, &c->res);
}

static int accuracy_pass(run_ctx *c, rf_ikw_stats *st, char *msg, size_t n)
{
    double conv = 0, err = 0, its = 0;
    for (uint32_t k = 0; k < c->w->sample_count; k++) {
        if (!solve_sample(c, k)) {
            snprintf(msg, n, "%s", c->res.message);
            return k == 0 ? 0 : -1;
        }
        conv += c->res.reached;
        for (uint32_t g = 0; g < c->w->goal_count; g++)
            err += c->res.errors[g];
        its += c->res.iterations;
    }
    double samples = c->w->sample_count ? c->w->sample_count : 1;
    st->converged = conv / samples;
    st->mean_error = err / (samples * (c->w->goal_count ? c->w->goal_count : 1));
    st->mean_iterations = its / samples;
    return 1;
}

/* Median over reps of the time per solve, each rep repeating whole passes for min_seconds. */
static double time_passes(run_ctx *c, double min_seconds, int reps)
{
    double per[16];
    if (reps < 1)
        reps = 1;
    if (reps > 16)
        reps = 16;
    for (int r = 0; r < reps; r++) {
        double t0 = now_seconds(), t;
        uint64_t solves = 0;
        do {
            for (uint32_t k = 0; k < c->w->sample_count; k++)
                solve_sample(c, k);
            solves += c->w->sample_count;
            t = now_seconds() - t0;
        } while (t < min_seconds);
        per[r] = 1e6 * t / (double)(solves ? solves : 1);
    }
    qsort(per, (size_t)reps, sizeof per[0], cmp_double);
    return reps % 2 ? per[reps / 2] : 0.5 * (per[reps / 2 - 1] + per[reps / 2]);
}

int rf_ikw_run(const rf_ik_solver_api *api, void *state, const rf_ikw *w, double min_seconds,
               int reps, rf_ikw_stats *stats, char *msg, size_t msg_size)
{
    run_ctx c = {api, state, w, NULL, {0}, {0}};
    rf_xform *out = calloc(w->joint_count, sizeof *out);
    double *errors = calloc(w->goal_count + 1, sizeof *errors);
    uint32_t *status = calloc(w->goal_count + 1, sizeof *status);
    c.goals = calloc(w->goal_count + 1, sizeof *c.goals);
    int rc = -1;
    memset(stats, 0, sizeof *stats);
    if (!out || !errors || !status || !c.goals) {
        snprintf(msg, msg_size, "out of memory");
        goto done;
    }
    c.pb =
        (rf_ik_problem){sizeof c.pb, w->joint_count, w->parents, w->pose,      NULL,
                        w->limits,   w->goal_count,  c.goals,    w->tolerance, w->max_iterations};
    c.res.size = sizeof c.res;
    c.res.pose = out, c.res.errors = errors, c.res.status = status;
    rc = accuracy_pass(&c, stats, msg, msg_size);
    if (rc == 1 && min_seconds > 0)
        stats->us_per_solve = time_passes(&c, min_seconds, reps);
done:
    free(out), free(errors), free(status), free(c.goals);
    return rc;
}

/* ---- reports ---- */

void rf_ikw_csv_header(FILE *out)
{
    fputs("solver,workload,us_per_solve,converged,mean_error,mean_iterations\n", out);
}

void rf_ikw_csv_row(FILE *out, const char *solver, const char *workload, const rf_ikw_stats *s)
{
    fprintf(out, "%s,%s,%.3f,%.4f,%.3e,%.2f\n", solver, workload, s->us_per_solve, s->converged,
            s->mean_error, s->mean_iterations);
}

const double rf_ikw_chart_caps[RF_IKW_CHART_CAPS] = {1, 2, 3, 4, 5, 7, 10, 15, 20, 30, 50, 100};

/* Chart geometry: the plot area, with room for axis labels and a legend on the right. */
enum { SVG_W = 820, SVG_H = 500, PLOT_L = 90, PLOT_R = 600, PLOT_T = 60, PLOT_B = 430 };

static const char *const palette[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e",
                                      "#9467bd", "#8c564b", "#e377c2", "#17becf"};

static void svg_text(FILE *out, double x, double y, const char *anchor, int size, const char *s)
{
    fprintf(out, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"%s\" font-size=\"%d\">", x, y, anchor,
            size);
    for (; *s; s++) { /* names come from users: escape what XML needs */
        if (*s == '<')
            fputs("&lt;", out);
        else if (*s == '>')
            fputs("&gt;", out);
        else if (*s == '&')
            fputs("&amp;", out);
        else
            fputc(*s, out);
    }
    fputs("</text>\n", out);
}

/* The decades the finite positive values span (at least one). */
static void error_range(uint32_t count, const double *ys, int *lo, int *hi)
{
    double mn = INFINITY, mx = -INFINITY;
    for (uint32_t i = 0; i < count; i++)
        if (isfinite(ys[i]) && ys[i] > 0)
            mn = fmin(mn, ys[i]), mx = fmax(mx, ys[i]);
    if (!isfinite(mn))
        mn = 1e-3, mx = 1;
    *lo = (int)floor(log10(fmax(mn, 1e-16)));
    *hi = (int)ceil(log10(mx));
    if (*hi <= *lo)
        *hi = *lo + 1;
}

static void svg_axes(FILE *out, const char *title, uint32_t xs_count, const double *xs, int lo,
                     int hi)
{
    char label[32];
    double lx0 = log10(xs[0]), lx1 = log10(xs[xs_count - 1]);
    svg_text(out, (PLOT_L + PLOT_R) / 2.0, 30, "middle", 16, title);
    for (int d = lo; d <= hi; d++) { /* a grid line and a label per decade of error */
        double y = PLOT_B - (PLOT_B - PLOT_T) * (double)(d - lo) / (hi - lo);
        fprintf(out, "<line x1=\"%d\" y1=\"%.1f\" x2=\"%d\" y2=\"%.1f\" stroke=\"#ddd\"/>\n",
                PLOT_L, y, PLOT_R, y);
        snprintf(label, sizeof label, "1e%d", d);
        svg_text(out, PLOT_L - 8, y + 4, "end", 12, label);
    }
    for (uint32_t i = 0; i < xs_count; i++) {
        double x = PLOT_L + (PLOT_R - PLOT_L) * (log10(xs[i]) - lx0) / (lx1 - lx0);
        fprintf(out, "<line x1=\"%.1f\" y1=\"%d\" x2=\"%.1f\" y2=\"%d\" stroke=\"#eee\"/>\n", x,
                PLOT_T, x, PLOT_B);
        snprintf(label, sizeof label, "%g", xs[i]);
        svg_text(out, x, PLOT_B + 18, "middle", 12, label);
    }
    fprintf(out,
            "<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\" fill=\"none\" stroke=\"#333\"/>\n",
            PLOT_L, PLOT_T, PLOT_R - PLOT_L, PLOT_B - PLOT_T);
    svg_text(out, (PLOT_L + PLOT_R) / 2.0, PLOT_B + 45, "middle", 14, "iteration cap (log scale)");
    fprintf(out,
            "<text x=\"22\" y=\"%.1f\" text-anchor=\"middle\" font-size=\"14\" "
            "transform=\"rotate(-90 22 %.1f)\">mean position error (log scale)</text>\n",
            (PLOT_T + PLOT_B) / 2.0, (PLOT_T + PLOT_B) / 2.0);
}

static void svg_series(FILE *out, uint32_t s, const char *name, uint32_t xs_count, const double *xs,
                       const double *ys, int lo, int hi)
{
    const char *color = palette[s % (sizeof palette / sizeof palette[0])];
    double lx0 = log10(xs[0]), lx1 = log10(xs[xs_count - 1]);
    fprintf(out, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"2\" points=\"", color);
    for (uint32_t i = 0; i < xs_count; i++) {
        if (!isfinite(ys[i]) || ys[i] <= 0)
            continue;
        double x = PLOT_L + (PLOT_R - PLOT_L) * (log10(xs[i]) - lx0) / (lx1 - lx0);
        double ly = fmin(fmax(log10(ys[i]), lo), hi);
        fprintf(out, "%.1f,%.1f ", x, PLOT_B - (PLOT_B - PLOT_T) * (ly - lo) / (hi - lo));
    }
    fputs("\"/>\n", out);
    double ly = PLOT_T + 10 + 22.0 * s; /* legend entry */
    fprintf(out,
            "<line x1=\"%d\" y1=\"%.1f\" x2=\"%d\" y2=\"%.1f\" stroke=\"%s\" "
            "stroke-width=\"3\"/>\n",
            PLOT_R + 20, ly, PLOT_R + 50, ly, color);
    svg_text(out, PLOT_R + 58, ly + 4, "start", 13, name);
}

bool rf_ikw_write_svg(FILE *out, const char *title, uint32_t series, const char *const *names,
                      uint32_t xs_count, const double *xs, const double *ys)
{
    int lo, hi;
    error_range(series * xs_count, ys, &lo, &hi);
    fprintf(out,
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" "
            "viewBox=\"0 0 %d %d\" font-family=\"sans-serif\">\n"
            "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n",
            SVG_W, SVG_H, SVG_W, SVG_H);
    svg_axes(out, title, xs_count, xs, lo, hi);
    for (uint32_t s = 0; s < series; s++)
        svg_series(out, s, names[s], xs_count, xs, ys + (size_t)s * xs_count, lo, hi);
    fputs("</svg>\n", out);
    return !ferror(out);
}
