/* rig-fit MODEL...: fits the template rigger's layouts (where each joint sits along the curve it
 * follows, rf_rig_tpl_layout) to the artist rigs of rigged models, and says how well a fit
 * generalises: for each model, the layout fitted on the other models of its template
 * (leave-one-out) is scored on it, so no model is scored by a layout trained on it. Prints per
 * model CD-J2J (as rig-bench computes it, joints only) with the built-in layout, the
 * leave-one-out fit and the fit on every model, then the layouts fitted on every model.
 * A development aid behind doc/autorig.md's layout table; slow (a minute or two). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <rigflow/aimport.h>

#include "rig-internal.h"

#define FIT_MAX 64

/* Rigs with fewer skinned joints than this are scored but not trained on (--min-joints). */
static uint32_t fit_min_joints;
/* Only these parameters are fitted (--params a,b,...; NULL: all). */
static const char *fit_only;

static bool fit_wanted(const char *name)
{
    if (!fit_only)
        return true;
    size_t n = strlen(name);
    for (const char *p = fit_only; (p = strstr(p, name)); p += n)
        if ((p == fit_only || p[-1] == ',') && (p[n] == ',' || p[n] == 0))
            return true;
    return false;
}

typedef struct fit_model {
    const char *name;
    rf_rig_prep prep;
    rf_rig_skel curve;
    rf_rig_options opts;
    rf_vec3
        facing; /* the body's, read once as the template rigger reads it (rf_rig_pooled_facing) */
    rf_vec3 *artist; /* skinned artist joints, bind pose */
    uint32_t nart;
    double longest;
    int kind; /* 0 humanoid, 1 quadruped, -1 refused */
} fit_model;

/* The parameters fitted: offsets into the layout; a bend window moves with its fraction. */
typedef struct fit_param {
    const char *name;
    size_t at, lo, hi; /* offsetof the fraction, its window's ends (0: none) */
} fit_param;

#define P(f)                                                                                       \
    {                                                                                              \
#f, offsetof(rf_rig_tpl_layout, f), 0, 0                                                   \
    }
#define PW(f)                                                                                      \
    {                                                                                              \
#f, offsetof(rf_rig_tpl_layout, f), offsetof(rf_rig_tpl_layout, f##_lo),                   \
            offsetof(rf_rig_tpl_layout, f##_hi)                                                    \
    }
static const fit_param fit_params[2][20] = {
    {P(spine[0]),
     P(spine[1]),
     P(spine[2]),
     P(neck_at),
     P(head),
     P(shoulder),
     P(arm),
     P(hand),
     PW(elbow),
     P(upleg),
     PW(knee),
     P(ankle_rise),
     P(toe),
     {NULL, 0, 0, 0}},
    {P(spine[0]),
     P(spine[1]),
     P(spine[2]),
     P(neck_at),
     P(head),
     P(shoulder),
     P(arm),
     P(hand),
     PW(elbow),
     P(upleg),
     PW(knee),
     PW(hock),
     P(toe),
     P(tail[0]),
     P(tail[1]),
     P(tail[2]),
     P(tail[3]),
     P(dorsal),
     {NULL, 0, 0, 0}},
};

static double *fit_at(rf_rig_tpl_layout *l, size_t off)
{
    return (double *)((char *)l + off);
}

static double fit_dist(const double *a, rf_vec3 b)
{
    return sqrt((a[0] - b.x) * (a[0] - b.x) + (a[1] - b.y) * (a[1] - b.y) +
                (a[2] - b.z) * (a[2] - b.z));
}

/* CD-J2J of joints t against model m's artist joints, as rig-bench computes it. */
static double fit_cd(const fit_model *m, const rf_rig_skel *t)
{
    double to = 0, from = 0;
    for (uint32_t j = 0; j < t->n; j++) {
        double best = INFINITY;
        for (uint32_t a = 0; a < m->nart; a++)
            best = fmin(best, fit_dist(t->pos + (size_t)j * 3, m->artist[a]));
        to += best;
    }
    for (uint32_t a = 0; a < m->nart; a++) {
        double best = INFINITY;
        for (uint32_t j = 0; j < t->n; j++)
            best = fmin(best, fit_dist(t->pos + (size_t)j * 3, m->artist[a]));
        from += best;
    }
    return 0.5 * (to / t->n + from / m->nart) / m->longest;
}

/* CD-J2J of the template laid out by `lay` on model m; NAN when it does not fit. */
static double fit_score(fit_model *m, const rf_rig_tpl_layout *lay)
{
    rf_rig_skel t = {0};
    char names[40][24], err[512];
    rf_rig_template_kind got;
    rf_vec3 up, fw;
    if (!rf_rig_template_place(&m->prep, &m->curve, &m->opts, m->facing, RF_RIG_TEMPLATE_AUTO, lay,
                               lay, &t, names, &got, &up, &fw, err, sizeof err))
        return NAN;
    double cd = fit_cd(m, &t);
    rf_rig_skel_free(&t);
    return cd;
}

/* CD-J2J of the general rigger's joints on model m with the layouts given (its limbs cut by
 * them); NAN when out of memory. */
static double fit_general(fit_model *m, const rf_rig_tpl_layout *humanoid,
                          const rf_rig_tpl_layout *quadruped)
{
    const rf_rig_skel *c = &m->curve;
    rf_rig_skel k = {.n = c->n};
    k.pos = malloc((c->n + 1) * 3 * sizeof *k.pos), k.tip = malloc((c->n + 1) * 3 * sizeof *k.tip);
    k.parent = malloc((c->n + 1) * sizeof *k.parent), k.has_tip = malloc(c->n + 1);
    double cd = NAN;
    if (k.pos && k.tip && k.parent && k.has_tip) {
        memcpy(k.pos, c->pos, c->n * 3 * sizeof *k.pos);
        memcpy(k.tip, c->tip, c->n * 3 * sizeof *k.tip);
        memcpy(k.parent, c->parent, c->n * sizeof *k.parent);
        memcpy(k.has_tip, c->has_tip, c->n);
        if (rf_rig_general_place(&m->prep, &k, &m->opts, humanoid, quadruped))
            cd = fit_cd(m, &k);
    }
    rf_rig_skel_free(&k);
    return cd;
}

/* Mean score over the models of template `kind`, model `leave` left out (-1: none). */
static double fit_mean(fit_model *ms, int n, int kind, int leave, const rf_rig_tpl_layout *lay)
{
    double sum = 0;
    int count = 0;
    for (int i = 0; i < n; i++)
        if (ms[i].kind == kind && i != leave && ms[i].nart >= fit_min_joints) {
            double s = fit_score(&ms[i], lay);
            sum += isnan(s) ? 0.5 : s, count++; /* a layout that loses the fit is bad */
        }
    return count ? sum / count : NAN;
}

/* Joints must stay in order along their curve. */
static bool fit_sane(const rf_rig_tpl_layout *l, int kind)
{
    bool ok = l->spine[0] > 0.02 && l->spine[0] < l->spine[1] && l->spine[1] < l->spine[2] &&
              l->spine[2] < 0.98 && l->shoulder >= 0 && l->shoulder < l->arm &&
              l->arm < l->elbow_lo && l->elbow_hi < l->hand && l->hand < 0.98 && l->upleg >= 0 &&
              l->upleg < l->knee_lo && l->neck_at > 0.2 && l->neck_at < 0.9 && l->head > 0 &&
              l->head < 0.9 && l->toe > 0 && l->toe < 1 && l->ankle_rise >= 0 &&
              l->ankle_rise < 0.5 && l->dorsal >= 0 && l->dorsal < 1;
    if (kind == 1)
        ok = ok && l->knee_hi < l->hock_lo && l->hock_hi < 0.98 && l->tail[0] > 0 &&
             l->tail[0] < l->tail[1] && l->tail[1] < l->tail[2] && l->tail[2] < l->tail[3] &&
             l->tail[3] < 1;
    else
        ok = ok && l->knee_hi < 0.7;
    return ok;
}

/* Coordinate descent from `start` on the models of `kind` but `leave`. */
static rf_rig_tpl_layout fit(fit_model *ms, int n, int kind, int leave,
                             const rf_rig_tpl_layout *start)
{
    rf_rig_tpl_layout best = *start;
    best.centre = false; /* across the limb, not along it: fitted without */
    double score = fit_mean(ms, n, kind, leave, &best);
    const double steps[] = {0.08, 0.04, 0.02};
    for (int s = 0; s < 3; s++)
        for (int sweep = 0; sweep < 2; sweep++)
            for (const fit_param *p = fit_params[kind]; p->name; p++)
                for (int sign = -1; sign <= 1; sign += 2) {
                    if (!fit_wanted(p->name))
                        continue;
                    rf_rig_tpl_layout l = best;
                    double d = sign * steps[s];
                    *fit_at(&l, p->at) += d;
                    if (p->lo)
                        *fit_at(&l, p->lo) += d, *fit_at(&l, p->hi) += d;
                    if (!fit_sane(&l, kind))
                        continue;
                    double sc = fit_mean(ms, n, kind, leave, &l);
                    if (sc < score - 1e-6)
                        score = sc, best = l;
                }
    best.centre = start->centre;
    return best;
}

static bool fit_load(const char *path, fit_model *m)
{
    char err[1024];
    rf_ai_result art, bare;
    rf_ai_options with = {0}, without = {.ignore_rig = true};
    memset(m, 0, sizeof *m);
    m->name = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
    m->kind = -1;
    if (!rf_ai_import(path, &with, &art, NULL, NULL, err, sizeof err)) {
        fprintf(stderr, "rig-fit: %s\n", err);
        return false;
    }
    bool ok = art.skeleton && art.skeleton->joint_count && art.mesh && art.mesh->skin_weights &&
              rf_ai_import(path, &without, &bare, NULL, NULL, err, sizeof err);
    if (!ok) {
        rf_ai_result_clear(&art);
        return false;
    }
    const rf_skeleton *s = art.skeleton;
    const rf_mesh *am = art.mesh;
    rf_xform *w = calloc(s->joint_count + 1, sizeof *w);
    m->artist = calloc(s->joint_count + 1, sizeof *m->artist);
    rf_skeleton_world_rest(s, w);
    for (uint32_t j = 0; j < s->joint_count; j++) {
        if (s->joints[j].flags & RF_JOINT_UNWEIGHTED)
            continue;
        rf_mat4 b;
        m->artist[m->nart] = w[j].t;
        if (am->inverse_bind && am->bind_count == s->joint_count &&
            rf_mat4_invert(am->inverse_bind[j], &b))
            m->artist[m->nart] = rf_v3(b.m[12], b.m[13], b.m[14]);
        m->nart++;
    }
    free(w);
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t v = 0; v < am->vertex_count; v++)
        for (int a = 0; a < 3; a++)
            lo[a] = fmin(lo[a], am->positions[v * 3 + a]),
            hi[a] = fmax(hi[a], am->positions[v * 3 + a]);
    for (int a = 0; a < 3; a++)
        m->longest = fmax(m->longest, hi[a] - lo[a]);
    rf_rig_options o = {0};
    if (bare.skeleton)
        o.up = bare.skeleton->up, o.forward = bare.skeleton->forward;
    m->opts = rf_rig_defaults(&o);
    rf_rig_stats st;
    ok = rf_rig_prepare(bare.mesh, &m->opts, &m->prep, &st, err, sizeof err) == RF_RIG_OK &&
         rf_rig_curve(&m->prep, &m->opts, &m->curve, err, sizeof err) == RF_RIG_OK;
    m->facing = rf_v3(0, 0, 0);
    if (ok && !(rf_v3_len(m->opts.forward) > 0))
        ok = rf_rig_pooled_facing(&m->prep, NULL, &m->opts, &m->facing);
    if (ok) {
        rf_rig_skel t = {0};
        char names[40][24];
        rf_rig_template_kind got;
        rf_vec3 up, fw;
        if (rf_rig_template_place(&m->prep, &m->curve, &m->opts, m->facing, RF_RIG_TEMPLATE_AUTO,
                                  NULL, NULL, &t, names, &got, &up, &fw, err, sizeof err))
            m->kind = got == RF_RIG_TEMPLATE_HUMANOID ? 0 : 1;
        rf_rig_skel_free(&t);
    }
    rf_ai_result_clear(&art), rf_ai_result_clear(&bare);
    return ok;
}

static void fit_free(fit_model *m)
{
    rf_rig_prep_free(&m->prep);
    rf_rig_skel_free(&m->curve);
    free(m->artist);
    memset(m, 0, sizeof *m);
}

static void fit_print(const char *title, const rf_rig_tpl_layout *l, int kind)
{
    printf("%s:", title);
    for (const fit_param *p = fit_params[kind]; p->name; p++)
        printf(" %s=%.2f", p->name, *fit_at((rf_rig_tpl_layout *)l, p->at));
    printf("\n");
}

/* The layouts as they were before they were fitted to the shared artist rigs (doc/autorig.md,
 * "Where the joints go"): a leave-one-out fit starts from these (--prefit), as the shipped
 * layouts' own fit did, so no model's score starts from a layout that saw it. */
static const rf_rig_tpl_layout fit_prefit[2] = {
    {.spine = {0.25, 0.5, 0.75},
     .neck_at = 0.55,
     .head = 0.35,
     .shoulder = 0.06,
     .arm = 0.2,
     .hand = 0.8,
     .elbow = 0.52,
     .elbow_lo = 0.4,
     .elbow_hi = 0.65,
     .upleg = 0.1,
     .knee = 0.47,
     .knee_lo = 0.35,
     .knee_hi = 0.6,
     .ankle_rise = 0.12,
     .toe = 0.6},
    {.spine = {0.25, 0.5, 0.75},
     .neck_at = 0.5,
     .head = 0.5,
     .shoulder = 0.06,
     .arm = 0.25,
     .hand = 0.82,
     .elbow = 0.5,
     .elbow_lo = 0.4,
     .elbow_hi = 0.65,
     .upleg = 0.1,
     .knee = 0.38,
     .knee_lo = 0.25,
     .knee_hi = 0.5,
     .hock = 0.68,
     .hock_lo = 0.55,
     .hock_hi = 0.8,
     .toe = 0.6,
     .tail = {0.1, 0.32, 0.54, 0.76},
     .dorsal = 0.5},
};

int main(int argc, char **argv)
{
    bool prefit = false, general = false;
    for (;;) {
        if (argc > 2 && (!strcmp(argv[1], "--min-joints") || !strcmp(argv[1], "--params"))) {
            if (!strcmp(argv[1], "--params"))
                fit_only = argv[2];
            else
                fit_min_joints = (uint32_t)strtoul(argv[2], NULL, 10);
            argc -= 2, argv += 2;
        } else if (argc > 1 && !strcmp(argv[1], "--prefit")) {
            prefit = true, argc--, argv++;
        } else if (argc > 1 && !strcmp(argv[1], "--general")) {
            general = true, argc--, argv++;
        } else {
            break;
        }
    }
    if (argc < 2 || argc > FIT_MAX) {
        fprintf(stderr,
                "usage: rig-fit [--min-joints N] [--params NAME,...] [--prefit] [--general] "
                "MODEL... (rigged models, at most %d; rigs with fewer than N skinned joints are "
                "scored, not trained on; only the parameters named are fitted; --prefit: fits "
                "start from the layouts before their fit to the shared rigs, not the built-in "
                "ones; --general: also the general rigger's CD-J2J with the built-in layouts and "
                "with the leave-one-out one for the model's template)\n",
                FIT_MAX - 1);
        return 2;
    }
    static fit_model ms[FIT_MAX];
    int n = 0;
    for (int i = 1; i < argc; i++)
        if (fit_load(argv[i], &ms[n]) && ms[n].kind >= 0)
            n++;
        else
            fit_free(&ms[n]);
    const rf_rig_tpl_layout *builtin[2] = {&rf_rig_tpl_humanoid, &rf_rig_tpl_quadruped};
    const rf_rig_tpl_layout *dflt[2] = {prefit ? &fit_prefit[0] : builtin[0],
                                        prefit ? &fit_prefit[1] : builtin[1]};
    printf("model,template,artist_joints,builtin,leave_one_out,all%s\n",
           general ? ",general_builtin,general_leave_one_out" : "");
    double sum[2][5] = {{0}}, count[2] = {0};
    rf_rig_tpl_layout all[2];
    for (int k = 0; k < 2; k++)
        all[k] = fit(ms, n, k, -1, dflt[k]);
    for (int i = 0; i < n; i++) {
        int k = ms[i].kind;
        rf_rig_tpl_layout loo = fit(ms, n, k, i, dflt[k]);
        double s[5] = {fit_score(&ms[i], dflt[k]), fit_score(&ms[i], &loo),
                       fit_score(&ms[i], &all[k])};
        printf("%s,%s,%u,%.4f,%.4f,%.4f", ms[i].name, k ? "quadruped" : "humanoid", ms[i].nart,
               s[0], s[1], s[2]);
        if (general) { /* the other template's layout saw no model of this one: built in */
            s[3] = fit_general(&ms[i], builtin[0], builtin[1]);
            s[4] = fit_general(&ms[i], k ? builtin[0] : &loo, k ? &loo : builtin[1]);
            printf(",%.4f,%.4f", s[3], s[4]);
        }
        printf("\n");
        fflush(stdout);
        for (int c = 0; c < 5; c++)
            sum[k][c] += s[c];
        count[k]++;
    }
    for (int k = 0; k < 2; k++) {
        if (!count[k])
            continue;
        printf("mean %s (%g models),%.4f,%.4f,%.4f", k ? "quadruped" : "humanoid", count[k],
               sum[k][0] / count[k], sum[k][1] / count[k], sum[k][2] / count[k]);
        if (general)
            printf(",%.4f,%.4f", sum[k][3] / count[k], sum[k][4] / count[k]);
        printf("\n");
    }
    fit_print("humanoid fitted on all", &all[0], 0);
    fit_print("quadruped fitted on all", &all[1], 1);
    for (int i = 0; i < n; i++)
        fit_free(&ms[i]);
    return 0;
}
