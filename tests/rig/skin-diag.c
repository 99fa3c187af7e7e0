/* skin-diag [--joints] FILE...: bone heat (rf_rig_bind) on each rigged FILE's own skeleton,
 * against the artist's weights, as rig-bench's "artist's skeleton" columns judge it (weights
 * under 0.15 of a vertex's largest pruned), and what lies behind those numbers: the mean count
 * of joints per vertex left after pruning (artist's and ours), how often the heaviest joint is
 * the same, and with --joints the precision and recall per artist joint and the twelve most
 * frequent (artist's heaviest -> ours) confusions. A development aid (doc/autorig.md,
 * "Skinning on the artists' skeletons"); the tests check the same through rig-bench. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <rigflow/aimport.h>
#include <rigflow/text.h>

#include "rig.h"

/* `text` with every byte that is not printable UTF-8 escaped (file and joint names are data),
 * malloc'd; NULL when out of memory. */
static char *sd_shown(const char *text)
{
    size_t n = rf_text_escape(text, NULL, 0, 0);
    char *out = malloc(n + 1);
    if (out)
        rf_text_escape(text, out, n + 1, 0);
    return out;
}

typedef struct sd_sums {
    double precision, recall, l1, art_joints, our_joints, same_heaviest, vertices;
} sd_sums;

/* Per vertex weights summed per joint, under 0.15 of the largest dropped, renormalised. */
static void sd_row(const rf_mesh *m, uint32_t v, uint32_t nj, double *w)
{
    double mx = 0, sum = 0;
    memset(w, 0, nj * sizeof *w);
    for (int k = 0; k < 4; k++)
        if (m->skin_joints[v * 4 + k] < nj)
            w[m->skin_joints[v * 4 + k]] += m->skin_weights[v * 4 + k];
    for (uint32_t j = 0; j < nj; j++)
        mx = fmax(mx, w[j]);
    for (uint32_t j = 0; j < nj; j++)
        sum += w[j] = w[j] < 0.15 * mx ? 0 : w[j];
    for (uint32_t j = 0; sum > 0 && j < nj; j++)
        w[j] /= sum;
}

static uint32_t sd_heaviest(const double *w, uint32_t nj)
{
    uint32_t best = 0;
    for (uint32_t j = 1; j < nj; j++)
        best = w[j] > w[best] ? j : best;
    return best;
}

/* Adds vertex v to the sums; per artist joint (its heaviest) into jp/jr/jn, the confusion into
 * conf[artist * nj + ours]. */
static void sd_vertex(const double *wa, const double *wo, uint32_t nj, sd_sums *s, double *jp,
                      double *jr, double *jn, unsigned *conf)
{
    uint32_t na = 0, no = 0, both = 0;
    double l1 = 0;
    for (uint32_t j = 0; j < nj; j++) {
        na += wa[j] > 0, no += wo[j] > 0, both += wa[j] > 0 && wo[j] > 0;
        l1 += fabs(wa[j] - wo[j]);
    }
    if (!na)
        return; /* the artist left it unweighted */
    uint32_t ha = sd_heaviest(wa, nj), ho = sd_heaviest(wo, nj);
    double p = no ? (double)both / no : 0, r = (double)both / na;
    s->precision += p, s->recall += r, s->l1 += l1, s->vertices++;
    s->art_joints += na, s->our_joints += no, s->same_heaviest += ha == ho;
    jp[ha] += p, jr[ha] += r, jn[ha]++;
    conf[(size_t)ha * nj + ho]++;
}

/* Whether joint a lies above joint d in s (an ancestor). */
static bool sd_above(const rf_skeleton *s, uint32_t a, uint32_t d)
{
    for (int32_t p = s->joints[d].parent; p >= 0; p = s->joints[p].parent)
        if ((uint32_t)p == a)
            return true;
    return false;
}

static void sd_print_joints(const rf_skeleton *s, const double *jp, const double *jr,
                            const double *jn, unsigned *conf)
{
    uint32_t nj = s->joint_count;
    /* where the heaviest joints differ, on which side of the artist's joint ours lies: a joint
     * below it (a boundary of ours nearer the root than the artist's), above it, or elsewhere */
    unsigned below = 0, above = 0, apart = 0;
    for (size_t i = 0; i < (size_t)nj * nj; i++)
        if (i / nj != i % nj && conf[i]) {
            uint32_t a = (uint32_t)(i / nj), o = (uint32_t)(i % nj);
            *(sd_above(s, a, o) ? &below : sd_above(s, o, a) ? &above : &apart) += conf[i];
        }
    printf("  heaviest differs: ours below the artist's %u, above %u, elsewhere %u vertices\n",
           below, above, apart);
    for (uint32_t j = 0; j < nj; j++)
        if (jn[j]) {
            char *name = sd_shown(s->joints[j].name);
            printf("  %-28s %6.0f vertices  P %.2f  R %.2f\n", name ? name : "?", jn[j],
                   jp[j] / jn[j], jr[j] / jn[j]);
            free(name);
        }
    for (int t = 0; t < 12; t++) {
        size_t best = 0;
        unsigned most = 0;
        for (size_t i = 0; i < (size_t)nj * nj; i++)
            if (i / nj != i % nj && conf[i] > most)
                most = conf[i], best = i;
        if (!most)
            break;
        char *a = sd_shown(s->joints[best / nj].name), *o = sd_shown(s->joints[best % nj].name);
        printf("  artist %s -> ours %s: %u vertices\n", a ? a : "?", o ? o : "?", most);
        free(a), free(o);
        conf[best] = 0;
    }
}

/* Bone heat on the skeleton of one rigged file against its artist's weights, printed. */
static int sd_compare(const char *shown, const rf_skeleton *s, const rf_mesh *am, bool joints)
{
    uint32_t nj = s->joint_count;
    rf_mesh bare = *am; /* borrowed arrays, the artist's skin hidden */
    bare.skin_joints = NULL, bare.skin_weights = NULL, bare.inverse_bind = NULL;
    bare.bind_count = 0;
    const rf_mat4 *inv = am->bind_count == nj ? am->inverse_bind : NULL;
    rf_mesh *m = NULL;
    char err[1024];
    if (!rf_rig_bind(&bare, s, inv, NULL, &m, NULL, err, sizeof err)) {
        char *why = sd_shown(err);
        fprintf(stderr, "skin-diag: %s: %s\n", shown, why ? why : "bone heat failed");
        free(why);
        return 1;
    }
    double *wa = calloc(nj, sizeof *wa), *wo = calloc(nj, sizeof *wo);
    double *jp = calloc(nj, sizeof *jp), *jr = calloc(nj, sizeof *jr), *jn = calloc(nj, sizeof *jn);
    unsigned *conf = calloc((size_t)nj * nj, sizeof *conf);
    bool ok = wa && wo && jp && jr && jn && conf;
    sd_sums t = {0};
    for (uint32_t v = 0; ok && v < am->vertex_count; v++) {
        sd_row(am, v, nj, wa), sd_row(m, v, nj, wo);
        sd_vertex(wa, wo, nj, &t, jp, jr, jn, conf);
    }
    double n = t.vertices > 0 ? t.vertices : NAN;
    if (ok)
        printf("%s: %.0f vertices  P %.3f  R %.3f  L1 %.3f  joints per vertex: artist %.2f, "
               "ours %.2f  heaviest the same: %.3f\n",
               shown, t.vertices, t.precision / n, t.recall / n, t.l1 / n, t.art_joints / n,
               t.our_joints / n, t.same_heaviest / n);
    else
        fprintf(stderr, "skin-diag: %s: out of memory\n", shown);
    if (ok && joints)
        sd_print_joints(s, jp, jr, jn, conf);
    free(wa), free(wo), free(jp), free(jr), free(jn), free(conf);
    rf_mesh_free(m);
    return ok ? 0 : 1;
}

static int sd_file(const char *path, bool joints)
{
    rf_ai_options o = {0};
    rf_ai_result r;
    char err[1024];
    char *shown = sd_shown(path);
    int code = 1;
    if (!rf_ai_import(path, &o, &r, NULL, NULL, err, sizeof err)) {
        char *why = sd_shown(err);
        fprintf(stderr, "skin-diag: %s\n", why ? why : "import failed");
        free(why), free(shown);
        return 1;
    }
    if (!r.mesh || !r.mesh->skin_weights || !r.mesh->skin_joints || !r.skeleton ||
        !r.skeleton->joint_count)
        fprintf(stderr, "skin-diag: %s: no skinned mesh to compare with\n", shown ? shown : "?");
    else
        code = sd_compare(shown ? shown : "?", r.skeleton, r.mesh, joints);
    rf_ai_result_clear(&r);
    free(shown);
    return code;
}

int main(int argc, char **argv)
{
    bool joints = argc > 1 && !strcmp(argv[1], "--joints");
    if (argc < 2 + joints) {
        fprintf(stderr, "usage: skin-diag [--joints] FILE...\n");
        return 2;
    }
    int bad = 0;
    for (int i = 1 + joints; i < argc; i++)
        bad |= sd_file(argv[i], joints);
    return bad;
}
