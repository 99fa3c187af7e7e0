/* rf_rig_general: clean-up, skeleton, names from the skeleton analysis, bone heat, and the
 * skinned copy of the input mesh. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <rigflow/analysis.h>
#include <rigflow/model-copy.h>

#include "rig-internal.h"

/* The analysis's facing made level to the skeleton's up, or zero when it has none or when the
 * analysis read another up and its facing lies mostly along this one (it would say nothing of
 * which way the body faces). */
static rf_vec3 rf_rig_level_facing(rf_vec3 up, const rf_analysis *a)
{
    if (!(a->forward_confidence > 0) || !(rf_v3_len(up) > 0))
        return rf_v3(0, 0, 0);
    rf_vec3 u = rf_v3_normalize(up), f = a->forward;
    f = rf_v3_sub(f, rf_v3_scale(u, rf_v3_dot(f, u)));
    return rf_v3_len(f) > 0.7 ? rf_v3_normalize(f) : rf_v3(0, 0, 0);
}

/* Joint names say what the skeleton analysis found (section, side, rank, place in the chain),
 * e.g. leg_l0_1, so a person reading the rig sees its layout; the matcher never reads them. */
static bool rf_rig_name(rf_skeleton *s, rf_vec3 up, rf_vec3 forward)
{
    s->up = up, s->forward = forward; /* hints for the analysis, as a file's axes are */
    rf_analysis *a = rf_analyze(s, NULL);
    if (!a)
        return false;
    bool ok = true;
    for (uint32_t j = 0; ok && j < s->joint_count; j++) {
        char name[96];
        const rf_joint_info *ji = &a->joints[j];
        if (ji->section < 0) {
            snprintf(name, sizeof name, "joint%u", j);
        } else {
            const rf_section *sec = &a->sections[ji->section];
            const char side = sec->side == RF_SIDE_LEFT    ? 'l'
                              : sec->side == RF_SIDE_RIGHT ? 'r'
                                                           : 'c';
            snprintf(name, sizeof name, "%s_%c%u_%u", rf_section_type_name(sec->type), side,
                     sec->pair_rank, ji->index);
        }
        if (rf_skeleton_find(s, name) >= 0) {
            size_t l = strlen(name);
            snprintf(name + l, sizeof name - l, ".%u", j);
        }
        ok = (s->joints[j].name = rf_strdup(name)) != NULL;
    }
    /* What the file left unknown, the analysis's reading. A facing is kept however weak its
     * margin: the matcher reads the same rig the same way, and a format with fixed axes (glTF)
     * is written turned by it, so the exported rig reads back as the rig in memory is read. */
    if (rf_v3_len(up) == 0)
        s->up = a->up;
    if (rf_v3_len(forward) == 0)
        s->forward = rf_rig_level_facing(s->up, a);
    rf_analysis_free(a);
    return ok;
}

rf_skeleton *rf_rig_skeleton(const rf_rig_skel *k, const rf_rig_options *named)
{
    rf_skeleton *s = rf_skeleton_new(k->n);
    if (!s)
        return NULL;
    s->bind = malloc((size_t)k->n * sizeof *s->bind);
    s->rest_source = RF_REST_BIND;
    if (!s->bind || !(s->name = rf_strdup("rig.general"))) {
        rf_skeleton_free(s);
        return NULL;
    }
    for (uint32_t j = 0; j < k->n; j++) {
        const double *p = k->pos + (size_t)j * 3;
        int32_t par = k->parent[j];
        const double *q = par >= 0 ? k->pos + (size_t)par * 3 : NULL;
        s->joints[j].parent = par;
        s->joints[j].rest.t =
            q ? rf_v3(p[0] - q[0], p[1] - q[1], p[2] - q[2]) : rf_v3(p[0], p[1], p[2]);
        if (k->has_tip[j]) {
            const double *t = k->tip + (size_t)j * 3;
            s->joints[j].end_site = rf_v3(t[0] - p[0], t[1] - p[1], t[2] - p[2]);
            s->joints[j].flags |= RF_JOINT_HAS_END_SITE;
        }
        s->bind[j] = s->joints[j].rest;
    }
    if (named && !rf_rig_name(s, named->up, named->forward)) {
        rf_skeleton_free(s);
        return NULL;
    }
    return s;
}

/* ---- root ---- */

static double rf_rig_height(const rf_rig_skel *k, uint32_t j, rf_vec3 up)
{
    const double *p = k->has_tip[j] ? k->tip + (size_t)j * 3 : k->pos + (size_t)j * 3;
    return p[0] * up.x + p[1] * up.y + p[2] * up.z;
}

static uint32_t rf_rig_depth(const rf_rig_skel *k, uint32_t j)
{
    uint32_t d = 0;
    for (int32_t p = k->parent[j]; p >= 0; p = k->parent[p])
        d++;
    return d;
}

static uint32_t rf_rig_lca(const rf_rig_skel *k, uint32_t a, uint32_t b)
{
    uint32_t da = rf_rig_depth(k, a), db = rf_rig_depth(k, b);
    for (; da > db; da--)
        a = (uint32_t)k->parent[a];
    for (; db > da; db--)
        b = (uint32_t)k->parent[b];
    while (a != b)
        a = (uint32_t)k->parent[a], b = (uint32_t)k->parent[b];
    return a;
}

/* The girdles of a skeleton: where two leaves of the lowest fifth of the body (along the up they
 * are looked for by) meet above that fifth; feet that meet near the floor are a heel and its
 * toes, or legs merged into one column under a skirt. */
typedef struct rf_rig_girdle_set {
    uint8_t *on;    /* [n] 1 at a girdle */
    double *height; /* [n] a girdle's height along that up */
    int count;
} rf_rig_girdle_set;

static void rf_rig_girdle_set_free(rf_rig_girdle_set *g)
{
    free(g->on), free(g->height);
    memset(g, 0, sizeof *g);
}

/* The up girdles are looked for along: `declared` when it is not zero, else the one the skeleton
 * analysis reads. False when out of memory: +y in its place would look for feet on a body lying
 * on its side, and the second pass would grow from wherever they seemed to meet. */
static bool rf_rig_girdle_up(const rf_rig_skel *k, rf_vec3 declared, rf_vec3 *up)
{
    if (rf_v3_len(declared) > 0 || !k->n) {
        *up = k->n ? rf_v3_normalize(declared) : rf_v3(0, 1, 0);
        return true;
    }
    rf_skeleton *s = rf_rig_skeleton(k, NULL);
    rf_analysis *a = s ? rf_analyze(s, NULL) : NULL;
    if (a)
        *up = a->up;
    rf_analysis_free(a);
    rf_skeleton_free(s);
    return a != NULL;
}

/* k's girdles into g along `declared` (rf_rig_girdle_up). False when out of memory (g empty). */
static bool rf_rig_girdles(const rf_rig_skel *k, rf_vec3 declared, rf_rig_girdle_set *g)
{
    rf_vec3 up;
    memset(g, 0, sizeof *g);
    uint8_t *inner = calloc(k->n + 1, 1);
    g->on = calloc(k->n + 1, 1);
    g->height = calloc(k->n + 1, sizeof *g->height);
    bool ok = inner && g->on && g->height && rf_rig_girdle_up(k, declared, &up);
    double lo = INFINITY, hi = -INFINITY;
    for (uint32_t j = 0; ok && j < k->n; j++) {
        if (k->parent[j] >= 0)
            inner[k->parent[j]] = 1;
        lo = fmin(lo, rf_rig_height(k, j, up)), hi = fmax(hi, rf_rig_height(k, j, up));
    }
    double low = lo + 0.2 * (hi - lo);
    for (uint32_t i = 0; ok && i < k->n; i++)
        for (uint32_t j = i + 1; j < k->n; j++) {
            if (inner[i] || inner[j] || rf_rig_height(k, i, up) > low ||
                rf_rig_height(k, j, up) > low)
                continue;
            uint32_t m = rf_rig_lca(k, i, j);
            const double *p = k->pos + (size_t)m * 3;
            g->height[m] = p[0] * up.x + p[1] * up.y + p[2] * up.z;
            if (g->height[m] > low && !g->on[m])
                g->on[m] = 1, g->count++;
        }
    free(inner);
    if (!ok)
        rf_rig_girdle_set_free(g);
    return ok;
}

/* Where the feet meet: the highest girdle, the hips of a biped (not the ankle, where heel and
 * toe meet), a girdle or the spine of a quadruped, the body of a spider; the second pass grows
 * from there. NONE when there is no girdle. */
static uint32_t rf_rig_pick_root(const rf_rig_skel *k, const rf_rig_girdle_set *g)
{
    double best = -INFINITY;
    uint32_t root = RF_RIG_NONE;
    for (uint32_t m = 0; m < k->n; m++)
        if (g->on[m] && g->height[m] > best)
            best = g->height[m], root = m;
    return root;
}

/* The squared distance between points p and q. */
static double rf_rig_apart2(const double p[3], const double q[3])
{
    return (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
           (p[2] - q[2]) * (p[2] - q[2]);
}

/* The hips of a first-pass skeleton: of its girdles, the one farthest from mid, the middle of
 * the body's surface. A quadruped's chest, neck and head outweigh its hindquarters and tail, so
 * the middle lies towards the shoulders. The farthest girdle along the skeleton from the first
 * pass's root, the thickest point, was taken before; thickness is a whole number of thirds of a
 * voxel, the chest and the hips often tie, and the tie went to whichever the grid's scan met
 * first: a body without a declared forward turned 137 degrees is rigged in a frame turned half
 * round, its grid scanned from the other end, and the horse, cat, fox and wolf were rooted at the
 * shoulders. The middle turns with the body. NONE when there is no girdle. */
static uint32_t rf_rig_pick_hips(const rf_rig_skel *k, const rf_rig_girdle_set *g,
                                 const double mid[3])
{
    double best = -INFINITY;
    uint32_t hips = RF_RIG_NONE;
    for (uint32_t m = 0; m < k->n; m++) {
        double apart = rf_rig_apart2(k->pos + (size_t)m * 3, mid);
        if (g->on[m] && apart > best)
            best = apart, hips = m;
    }
    return hips;
}

/* The girdle of k nearest to point q, or NONE. */
static uint32_t rf_rig_girdle_near(const rf_rig_skel *k, const rf_rig_girdle_set *g,
                                   const double q[3])
{
    double best = INFINITY;
    uint32_t at = RF_RIG_NONE;
    for (uint32_t m = 0; m < k->n; m++) {
        double d = rf_rig_apart2(k->pos + (size_t)m * 3, q);
        if (g->on[m] && d < best)
            best = d, at = m;
    }
    return at;
}

/* Re-roots k at joint r: the links on the path from r to the old root turned round, the joints
 * renumbered breadth-first from r so parents still come first. The joints stay where they are;
 * only which one is the root changes. */
static bool rf_rig_reroot(rf_rig_skel *k, uint32_t r)
{
    uint32_t n = k->n;
    int32_t *par = malloc((n + 1) * sizeof *par);
    uint32_t *order = malloc((n + 1) * sizeof *order), *to = malloc((n + 1) * sizeof *to);
    rf_rig_skel o = {.n = n};
    o.pos = malloc((n + 1) * 3 * sizeof *o.pos), o.tip = malloc((n + 1) * 3 * sizeof *o.tip);
    o.parent = malloc((n + 1) * sizeof *o.parent), o.has_tip = malloc(n + 1);
    bool ok = par && order && to && o.pos && o.tip && o.parent && o.has_tip;
    if (ok) {
        memcpy(par, k->parent, n * sizeof *par);
        for (int32_t prev = -1, cur = (int32_t)r; cur >= 0;) {
            int32_t next = k->parent[cur];
            par[cur] = prev, prev = cur, cur = next;
        }
        uint32_t head = 0, tail = 0;
        order[tail++] = r;
        while (head < tail) /* breadth-first: each joint's children after it */
            for (uint32_t j = 0, at = order[head++]; j < n; j++)
                if (par[j] == (int32_t)at)
                    order[tail++] = j;
        ok = tail == n;
        for (uint32_t i = 0; ok && i < n; i++)
            to[order[i]] = i;
        for (uint32_t i = 0; ok && i < n; i++) {
            uint32_t j = order[i];
            memcpy(o.pos + (size_t)i * 3, k->pos + (size_t)j * 3, 3 * sizeof *o.pos);
            memcpy(o.tip + (size_t)i * 3, k->tip + (size_t)j * 3, 3 * sizeof *o.tip);
            o.has_tip[i] = k->has_tip[j];
            o.parent[i] = par[j] >= 0 ? (int32_t)to[par[j]] : -1;
        }
    }
    free(par), free(order), free(to);
    if (!ok) {
        rf_rig_skel_free(&o);
        return false;
    }
    rf_rig_skel_free(k);
    *k = o;
    return true;
}

/* A joint appended to k at p hanging from `parent`; false when out of memory (k unchanged). */
static bool rf_rig_append(rf_rig_skel *k, const double p[3], int32_t parent)
{
    size_t n = (size_t)k->n + 1;
    double *pos = realloc(k->pos, n * 3 * sizeof *pos);
    if (pos)
        k->pos = pos;
    double *tips = pos ? realloc(k->tip, n * 3 * sizeof *tips) : NULL;
    if (tips)
        k->tip = tips;
    int32_t *par = tips ? realloc(k->parent, n * sizeof *par) : NULL;
    if (par)
        k->parent = par;
    uint8_t *has = par ? realloc(k->has_tip, n) : NULL;
    if (!has)
        return false;
    k->has_tip = has;
    memcpy(k->pos + (n - 1) * 3, p, 3 * sizeof *p);
    memset(k->tip + (n - 1) * 3, 0, 3 * sizeof *k->tip);
    k->parent[n - 1] = parent, k->has_tip[n - 1] = 0;
    k->n = (uint32_t)n;
    return true;
}

/* A copy of the input's geometry (positions, normals, triangles, parts) without any skin. */
static rf_mesh *rf_rig_mesh_copy(const rf_mesh *in)
{
    rf_mesh bare = *in; /* borrowed arrays: the skin left out of the copy */
    bare.skin_joints = NULL, bare.skin_weights = NULL, bare.inverse_bind = NULL,
    bare.bind_count = 0;
    return rf_mesh_copy(&bare);
}

/* Up to four largest weights of a row, renormalised, into the mesh's skin arrays. */
static void rf_rig_top4(const double *row, uint32_t nj, uint16_t *js, float *ws)
{
    double w[4] = {0};
    uint32_t id[4] = {0};
    for (uint32_t j = 0; j < nj; j++) {
        int at = 4;
        while (at > 0 && row[j] > w[at - 1])
            at--;
        if (at == 4)
            continue;
        for (int k = 3; k > at; k--)
            w[k] = w[k - 1], id[k] = id[k - 1];
        w[at] = row[j], id[at] = j;
    }
    double sum = w[0] + w[1] + w[2] + w[3];
    for (int k = 0; k < 4; k++) {
        js[k] = (uint16_t)id[k];
        ws[k] = sum > 0 ? (float)(w[k] / sum) : (k == 0);
    }
}

/* The skin: each input vertex takes its proxy vertex's weights, or (specks, stray vertices) those
 * of the proxy vertex nearest it. */
static bool rf_rig_skin(const rf_mesh *in, const rf_rig_prep *p, const rf_rig_skel *k,
                        const double *w, rf_mesh *m, rf_rig_stats *st)
{
    uint32_t nj = k->n;
    rf_rig_bone *bones = NULL;
    uint32_t nb = rf_rig_bones(k, &bones);
    double *row = malloc((size_t)nj * sizeof *row);
    m->skin_joints = malloc((size_t)in->vertex_count * 4 * sizeof *m->skin_joints);
    m->skin_weights = malloc((size_t)in->vertex_count * 4 * sizeof *m->skin_weights);
    m->inverse_bind = malloc((size_t)nj * sizeof *m->inverse_bind);
    bool ok = nb && row && m->skin_joints && m->skin_weights && m->inverse_bind;
    rf_rig_near *grid = NULL;
    for (uint32_t v = 0; ok && v < in->vertex_count; v++) {
        const double *src = p->to_proxy[v] != RF_RIG_NONE ? w + (size_t)p->to_proxy[v] * nj : NULL;
        /* a speck (a button, a bolt, an eye) moves with the surface nearest it */
        if (!src && (grid || (grid = rf_rig_near_new(p)))) {
            double q[3] = {in->positions[v * 3], in->positions[v * 3 + 1],
                           in->positions[v * 3 + 2]};
            uint32_t at = rf_rig_near_vertex(grid, q);
            src = at != RF_RIG_NONE ? w + (size_t)at * nj : NULL;
            st->fallback_vertices += src != NULL;
        }
        if (!src) {
            double q[3] = {in->positions[v * 3], in->positions[v * 3 + 1],
                           in->positions[v * 3 + 2]};
            double c[3], best = INFINITY;
            memset(row, 0, nj * sizeof *row);
            uint32_t to = 0;
            for (uint32_t b = 0; b < nb; b++) {
                double d = rf_rig_seg_dist(q, &bones[b], c);
                if (d < best)
                    best = d, to = bones[b].joint;
            }
            row[to] = 1;
            st->fallback_vertices++;
            src = row;
        }
        rf_rig_top4(src, nj, m->skin_joints + (size_t)v * 4, m->skin_weights + (size_t)v * 4);
    }
    for (uint32_t j = 0; ok && j < nj; j++) {
        const double *q = k->pos + (size_t)j * 3;
        rf_xform inv = rf_xform_identity();
        inv.t = rf_v3(-q[0], -q[1], -q[2]); /* joints are unrotated: the inverse is a shift */
        m->inverse_bind[j] = rf_xform_to_mat4(inv);
    }
    m->bind_count = nj;
    rf_rig_near_free(grid);
    free(bones), free(row);
    return ok;
}

rf_rig_options rf_rig_defaults(const rf_rig_options *opts)
{
    rf_rig_options o = opts ? *opts : (rf_rig_options){0};
    o.resolution = o.resolution ? o.resolution : RF_RIG_RESOLUTION;
    o.proxy_triangles = o.proxy_triangles ? o.proxy_triangles : RF_RIG_PROXY_TRIANGLES;
    o.speck_size = o.speck_size > 0 ? o.speck_size : RF_RIG_SPECK_SIZE;
    o.segment = o.segment > 0 ? o.segment : RF_RIG_SEGMENT;
    return o;
}

/* Whether the root of k lies off the body's mirror plane (normal mirror[0..2], zero when the
 * body has none) by more than three voxels of size h; if so its image on the plane into at[].
 * The thickest point of a box body is anywhere along a flat ridge, often off to one side, and
 * bands grown from there reach one side's limbs before the other's: they come out unlike. */
static bool rf_rig_off_middle(const rf_rig_skel *k, const double mirror[4], double h, double at[3])
{
    if (!k->n || rf_v3_len((rf_vec3){mirror[0], mirror[1], mirror[2]}) == 0)
        return false;
    const double *p = k->pos; /* the root, joint 0 */
    double off = mirror[0] * p[0] + mirror[1] * p[1] + mirror[2] * p[2] - mirror[3];
    if (fabs(off) <= 3 * h)
        return false;
    for (int a = 0; a < 3; a++)
        at[a] = p[a] - off * mirror[a];
    return true;
}

/* Signed distance of point q from the plane mirror[0..2] . p = mirror[3]. */
static double rf_rig_plane_off(const double mirror[4], const double q[3])
{
    return mirror[0] * q[0] + mirror[1] * q[1] + mirror[2] * q[2] - mirror[3];
}

/* The end of joint j's bone when it is a leaf: its tip, else its pivot. */
static const double *rf_rig_end(const rf_rig_skel *k, uint32_t j)
{
    return k->has_tip[j] ? k->tip + (size_t)j * 3 : k->pos + (size_t)j * 3;
}

/* The first joint of leaf's chain: up from the leaf while the parent has one child and is no
 * root. */
static uint32_t rf_rig_chain_top(const rf_rig_skel *k, const uint32_t *kids, uint32_t leaf)
{
    uint32_t top = leaf;
    while (k->parent[top] >= 0 && kids[k->parent[top]] == 1 && k->parent[k->parent[top]] >= 0)
        top = (uint32_t)k->parent[top];
    return top;
}

/* Whether leaf a's chain has a mirror image among the chains leaving the same joint: one whose
 * end lies on the other side of the plane, between a third and three times as far from it (two
 * legs close together under a skirt both lie near the plane). */
static bool rf_rig_chain_paired(const rf_rig_skel *k, const uint32_t *kids, const double mirror[4],
                                uint32_t a)
{
    int32_t from = k->parent[rf_rig_chain_top(k, kids, a)];
    double oa = rf_rig_plane_off(mirror, rf_rig_end(k, a));
    for (uint32_t b = 0; b < k->n; b++) {
        if (b == a || kids[b] || k->parent[rf_rig_chain_top(k, kids, b)] != from)
            continue;
        double ob = rf_rig_plane_off(mirror, rf_rig_end(k, b));
        if (oa * ob < 0 && fabs(ob) >= fabs(oa) / 3 && fabs(ob) <= 3 * fabs(oa))
            return true;
    }
    return false;
}

#define RF_RIG_MIDDLE_OFF 4.0  /* voxels: how far off the mirror plane a middle chain may lie */
#define RF_RIG_MIDDLE_BOW 0.25 /* of its span: how far a chain between middles may stray */

/* Whether the chain ending at junction j (from the joint after the junction or root above it)
 * runs from the body's middle to its middle: both junctions within RF_RIG_MIDDLE_OFF voxels of
 * the mirror plane, and none of its joints further off than RF_RIG_MIDDLE_BOW of the span
 * between them. Such a chain is the spine or the neck, however its band pieces strayed: random
 * biped 8's waist, pulled five voxels towards one thigh, left the trunk from the hips sideways
 * and the skeleton analysis read it as an arm, its arms and head as fingers. Offsets all under
 * a voxel are the grid's own and stay. */
static bool rf_rig_between_middles(const rf_rig_skel *k, const uint32_t *kids,
                                   const double mirror[4], double h, uint32_t j)
{
    uint32_t top = rf_rig_chain_top(k, kids, j), from = (uint32_t)k->parent[top];
    const double *a = k->pos + (size_t)from * 3, *b = k->pos + (size_t)j * 3;
    if (fabs(rf_rig_plane_off(mirror, a)) > RF_RIG_MIDDLE_OFF * h ||
        fabs(rf_rig_plane_off(mirror, b)) > RF_RIG_MIDDLE_OFF * h)
        return false;
    double span = rf_v3_len(rf_v3_sub(rf_v3(b[0], b[1], b[2]), rf_v3(a[0], a[1], a[2])));
    double most = fabs(rf_rig_plane_off(mirror, b));
    for (uint32_t i = (uint32_t)k->parent[j]; i != from; i = (uint32_t)k->parent[i])
        most = fmax(most, fabs(rf_rig_plane_off(mirror, k->pos + (size_t)i * 3)));
    return most >= h && most <= RF_RIG_MIDDLE_BOW * span; /* under a voxel: the grid's own */
}

/* A chain of k (from the joint after a junction, or the root, down to a leaf) without a mirror
 * image, lying within four voxels of the body's mirror plane (h: a voxel's size) and a voxel or
 * more off it somewhere, is moved onto the plane: the spine, neck, head and tail of a symmetric
 * body lie on its middle, as artists put them. Left a few voxels to one side (the centroids of
 * band pieces a tilted or lopsided head or a hand near the neck pulls over), the skeleton
 * analysis read the neck and head of BCN_Epileptic as an unpaired right arm, and the matcher
 * gave the face's 20 joints to it. Offsets under a voxel are the grid's own and stay. */
static bool rf_rig_on_plane(rf_rig_skel *k, const double mirror[4], double h)
{
    if (rf_v3_len((rf_vec3){mirror[0], mirror[1], mirror[2]}) == 0)
        return true;
    uint32_t *kids = calloc(k->n + 1, sizeof *kids);
    uint8_t *move = calloc(k->n + 1, 1);
    if (!kids || !move) {
        free(kids), free(move);
        return false;
    }
    for (uint32_t j = 0; j < k->n; j++)
        if (k->parent[j] >= 0)
            kids[k->parent[j]]++;
    for (uint32_t leaf = 0; leaf < k->n; leaf++) {
        if (kids[leaf] || k->parent[leaf] < 0)
            continue;
        uint32_t top = rf_rig_chain_top(k, kids, leaf);
        double most = fabs(rf_rig_plane_off(mirror, rf_rig_end(k, leaf)));
        for (uint32_t j = leaf;; j = (uint32_t)k->parent[j]) {
            most = fmax(most, fabs(rf_rig_plane_off(mirror, k->pos + (size_t)j * 3)));
            if (j == top)
                break;
        }
        bool near = most <= RF_RIG_MIDDLE_OFF * h && most >= h;
        if (!near || rf_rig_chain_paired(k, kids, mirror, leaf))
            continue;
        for (uint32_t j = leaf;; j = (uint32_t)k->parent[j]) {
            move[j] = 1;
            if (j == top)
                break;
        }
    }
    for (uint32_t j = 0; j < k->n; j++) {
        if (kids[j] < 2 || k->parent[j] < 0 || !rf_rig_between_middles(k, kids, mirror, h, j))
            continue;
        uint32_t top = rf_rig_chain_top(k, kids, j);
        for (uint32_t i = j; i != (uint32_t)k->parent[top]; i = (uint32_t)k->parent[i])
            move[i] = 1;
    }
    for (uint32_t j = 0; j < k->n; j++) {
        if (!move[j])
            continue;
        double *p = k->pos + (size_t)j * 3, off = rf_rig_plane_off(mirror, p);
        for (int c = 0; c < 3; c++)
            p[c] -= off * mirror[c];
        if (k->has_tip[j]) {
            double *t = k->tip + (size_t)j * 3, to = rf_rig_plane_off(mirror, t);
            for (int c = 0; c < 3; c++)
                t[c] -= to * mirror[c];
        }
    }
    free(kids), free(move);
    return true;
}

/* Whether the skeleton analysis reads k's up within about 45 degrees (cosine 0.7) of the
 * declared up (true when none is declared), into *agree. The fire dragon turned 137 degrees kept
 * its legs in the first pass but was read lying on its side, its wings hanging: its girdles,
 * looked for along that up, put the second pass's seed on a wing. False when out of memory. */
static bool rf_rig_reads_up(const rf_rig_skel *k, rf_vec3 declared, bool *agree)
{
    rf_vec3 read;
    *agree = true;
    if (!(rf_v3_len(declared) > 0))
        return true;
    if (!rf_rig_girdle_up(k, rf_v3(0, 0, 0), &read))
        return false;
    *agree = rf_v3_dot(read, rf_v3_normalize(declared)) >= 0.7;
    return true;
}

/* The first pass on the body turned half round about y, the frame's up (x and z negated: the grid
 * met from its other end), turned back. */
static rf_rig_status rf_rig_extract_turned(const rf_rig_prep *p, const rf_rig_options *o,
                                           double *mirror, double *stand, rf_rig_skel *k, char *err,
                                           size_t err_size)
{
    rf_rig_prep q = *p;
    q.proxy.p = malloc(((size_t)p->proxy.nv + 1) * 3 * sizeof *q.proxy.p);
    if (!q.proxy.p)
        return rf_rig_oom(err, err_size, "out of memory turning the body");
    for (size_t v = 0; v < p->proxy.nv; v++) {
        q.proxy.p[v * 3] = -p->proxy.p[v * 3], q.proxy.p[v * 3 + 1] = p->proxy.p[v * 3 + 1];
        q.proxy.p[v * 3 + 2] = -p->proxy.p[v * 3 + 2];
    }
    for (int a = 0; a < 3; a += 2)
        q.lo[a] = -p->hi[a], q.hi[a] = -p->lo[a];
    rf_rig_status status = rf_rig_extract(&q, o, NULL, mirror, stand, k, err, err_size);
    free(q.proxy.p);
    if (status != RF_RIG_OK)
        return status;
    for (size_t j = 0; j < k->n; j++)
        for (int a = 0; a < 3; a += 2)
            k->pos[j * 3 + a] = -k->pos[j * 3 + a], k->tip[j * 3 + a] = -k->tip[j * 3 + a];
    mirror[0] = -mirror[0], mirror[2] = -mirror[2];
    stand[0] = -stand[0], stand[2] = -stand[2];
    return RF_RIG_OK;
}

/* How far k's root lies from point q. */
static double rf_rig_root_off(const rf_rig_skel *k, const double q[3])
{
    for (uint32_t j = 0; j < k->n; j++)
        if (k->parent[j] < 0)
            return sqrt((k->pos[j * 3] - q[0]) * (k->pos[j * 3] - q[0]) +
                        (k->pos[j * 3 + 1] - q[1]) * (k->pos[j * 3 + 1] - q[1]) +
                        (k->pos[j * 3 + 2] - q[2]) * (k->pos[j * 3 + 2] - q[2]));
    return INFINITY;
}

/* Of the first pass's roots, the two ends of its thickest voxels' ties, the turned pass's is
 * taken over the frame's own scan's only when it lies clearly nearer the middle of the body:
 * by this many voxels, and at most this fraction of the other's distance from it. */
#define RF_RIG_ROOT_APART 2.0
#define RF_RIG_ROOT_NEARER (2.0 / 3)

/* The first pass, grown from the thickest voxel. Thickness is a whole number of thirds of a
 * voxel and it often ties along a ridge; the grid's scan takes the tie it meets first, at one
 * end of the ridge. A body whose file declares no forward, turned half round, is rigged in a
 * frame turned half round with it ("Any facing, scale and position" in doc/autorig.md), its grid
 * scanned from the other end, and its first pass grew from the ridge's other end: the animalia
 * bird and bull frog were then read facing back. So the pass is grown from both ends (the grid
 * scanned as it lies and turned half round about up) and the one whose root lies nearer the
 * middle of the body's surface (mid), which turns with the body, is kept when it is clearly
 * the nearer (RF_RIG_ROOT_APART, RF_RIG_ROOT_NEARER); else the frame's own, as before. */
static rf_rig_status rf_rig_first_pass(const rf_rig_prep *p, const rf_rig_options *o,
                                       const double mid[3], double mirror[4], double stand[4],
                                       rf_rig_skel *k, char *err, size_t err_size)
{
    rf_rig_status status = rf_rig_extract(p, o, NULL, mirror, stand, k, err, err_size);
    if (status != RF_RIG_OK)
        return status;
    rf_rig_skel other;
    double other_mirror[4], other_stand[4] = {0};
    status = rf_rig_extract_turned(p, o, other_mirror, other_stand, &other, err, err_size);
    if (status == RF_RIG_REFUSED)
        return RF_RIG_OK; /* the frame's own pass stands */
    if (status == RF_RIG_NO_MEMORY) {
        /* a lack of memory says nothing of which pass to keep */
        rf_rig_skel_free(k);
        return status;
    }
    double apart = RF_RIG_ROOT_APART * p->longest / o->resolution;
    double own_off = rf_rig_root_off(k, mid), other_off = rf_rig_root_off(&other, mid);
    if (other_off < own_off - apart && other_off < RF_RIG_ROOT_NEARER * own_off) {
        rf_rig_skel_free(k);
        *k = other;
        memcpy(mirror, other_mirror, sizeof other_mirror);
        memcpy(stand, other_stand, sizeof other_stand);
    } else
        rf_rig_skel_free(&other);
    return RF_RIG_OK;
}

/* The girdles of analysis a: the joints its limbs hang from nearest to (*shallow) and farthest
 * from (*deep) the root. False when fewer than two lie at different depths. */
static bool rf_rig_girdle_ends(const rf_rig_skel *k, const rf_analysis *a, uint32_t *shallow,
                               uint32_t *deep)
{
    uint32_t dmax = 0, dmin = UINT32_MAX;
    *shallow = *deep = RF_RIG_NONE;
    for (uint32_t i = 0; i < a->section_count; i++) {
        const rf_section *sec = &a->sections[i];
        bool limb = sec->type == RF_SECTION_LEG || sec->type == RF_SECTION_ARM;
        if (!limb || sec->attach_joint < 0 || (uint32_t)sec->attach_joint >= k->n)
            continue;
        uint32_t d = rf_rig_depth(k, (uint32_t)sec->attach_joint);
        if (*deep == RF_RIG_NONE || d > dmax)
            dmax = d, *deep = (uint32_t)sec->attach_joint;
        if (*shallow == RF_RIG_NONE || d < dmin)
            dmin = d, *shallow = (uint32_t)sec->attach_joint;
    }
    return *deep != RF_RIG_NONE && dmax > dmin;
}

#define RF_RIG_BULK_STEPS 12
#define RF_RIG_BULK_RATIO 1.5 /* one end this much bulkier than the other is the head */

/* How bulky the outer half of centre section `sec` of a is: the most, over points along its
 * bones from where it hangs to its last tip, of the narrower of the body's two diameters there
 * (to the side, along up). A head ends in a skull; a tail tapers to its tip, and a fin or a
 * fan of feathers is thin one way. Sets *end to the section's far end; NAN when no ray there
 * meets the surface both ways. */
static double rf_rig_end_bulk(const rf_rig_surface *sf, const rf_analysis *a, const rf_section *sec,
                              rf_vec3 *end)
{
    rf_vec3 pts[65];
    uint32_t np = 0;
    if (sec->attach_joint >= 0)
        pts[np++] = a->joints[sec->attach_joint].pos;
    for (uint32_t i = 0; i < sec->bone_count && np < 63; i++)
        pts[np++] = a->joints[a->section_joints[sec->first + i]].pos;
    pts[np] = a->joints[a->section_joints[sec->first + sec->bone_count - 1]].tip;
    np += rf_v3_dist(pts[np], pts[np - 1]) > 0;
    double total = 0, best = NAN;
    for (uint32_t i = 1; i < np; i++)
        total += rf_v3_dist(pts[i - 1], pts[i]);
    *end = pts[np - 1];
    for (int step = 0; step < RF_RIG_BULK_STEPS && total > 0; step++) {
        double at = total * (0.5 + 0.45 * step / (RF_RIG_BULK_STEPS - 1)), q[3];
        uint32_t i = 1;
        for (; i + 1 < np && at > rf_v3_dist(pts[i - 1], pts[i]); i++)
            at -= rf_v3_dist(pts[i - 1], pts[i]);
        rf_vec3 x = rf_v3_lerp(pts[i - 1], pts[i], fmin(1, at / rf_v3_dist(pts[i - 1], pts[i])));
        q[0] = x.x, q[1] = x.y, q[2] = x.z;
        double w[2];
        for (int d = 0; d < 2; d++) {
            rf_vec3 v = d ? a->up : a->left;
            double dp[3] = {v.x, v.y, v.z}, dn[3] = {-v.x, -v.y, -v.z};
            w[d] = rf_rig_surface_hit(sf, q, dp) + rf_rig_surface_hit(sf, q, dn);
        }
        if (isfinite(w[0]) && isfinite(w[1]))
            best = isnan(best) ? fmin(w[0], w[1]) : fmax(best, fmin(w[0], w[1]));
    }
    return best;
}

/* Which end of a level body is its tail, by bulk (rf_rig_end_bulk) of the analysis's one head
 * and one tail section: the index of the thinner one, with *way from its far end to the
 * bulkier one's; -1 when the body has not one of each or neither is clearly the bulkier. */
static int32_t rf_rig_hind_end(const rf_rig_surface *sf, const rf_analysis *a, rf_vec3 *way)
{
    int32_t head = -1, tail = -1;
    for (uint32_t i = 0; i < a->section_count; i++) {
        rf_section_type t = a->sections[i].type;
        if (a->sections[i].side != RF_SIDE_CENTER || a->sections[i].bone_count == 0)
            continue;
        if (t == RF_SECTION_HEAD)
            head = head < 0 ? (int32_t)i : -2;
        else if (t == RF_SECTION_TAIL)
            tail = tail < 0 ? (int32_t)i : -2;
    }
    if (head < 0 || tail < 0)
        return -1;
    rf_vec3 he, te;
    double hb = rf_rig_end_bulk(sf, a, &a->sections[head], &he);
    double tb = rf_rig_end_bulk(sf, a, &a->sections[tail], &te);
    *way = hb > RF_RIG_BULK_RATIO * tb ? rf_v3_sub(he, te) : rf_v3_sub(te, he);
    return hb > RF_RIG_BULK_RATIO * tb ? tail : tb > RF_RIG_BULK_RATIO * hb ? head : -1;
}

/* The vote of the skeleton analysis's facing cue `name` (along its forward). */
static double rf_rig_cue(const rf_analysis *a, const char *name)
{
    for (int i = 0; i < RF_FORWARD_CUE_COUNT; i++)
        if (strcmp(rf_forward_cue_names[i], name) == 0)
            return a->forward_cues[i];
    return 0;
}

/* How the skeleton analysis reads k, up and facing as the rig is named; *s is the skeleton it
 * reads, to be freed after it. NULL when out of memory. */
static rf_analysis *rf_rig_read(const rf_rig_skel *k, const rf_rig_options *o, rf_skeleton **s)
{
    *s = rf_rig_skeleton(k, NULL);
    if (!*s)
        return NULL;
    (*s)->up = o->up, (*s)->forward = rf_v3_len(o->forward) > 0 ? o->forward : o->facing;
    rf_analysis *a = rf_analyze(*s, NULL);
    if (!a)
        rf_skeleton_free(*s), *s = NULL;
    return a;
}

/* A rig whose legs all hang from one joint says nothing of its facing by where it is rooted:
 * the skeleton analysis reads such a girdle as an insect's thorax, its bone running towards the
 * head and the chain hanging back from it starting at its pivot. A dragon whose wings span
 * three times its length is cut into bones so long that its hips and chest are one joint, its
 * neck and tail both a bone away from it, and the file's declared forward outvotes the
 * elevation of its ends however the body faces. So the chain of hind section `hind` of
 * analysis a (of k) is made to start at the pivot of the joint it hangs from: a joint there
 * begins it. Kept only when the analysis then reads the body facing the other way. False when
 * out of memory (k unchanged). */
static bool rf_rig_pivot_hind(rf_rig_skel *k, const rf_analysis *a, int32_t hind,
                              const rf_rig_options *o)
{
    uint32_t first = a->section_joints[a->sections[hind].first], root = 0;
    int32_t g = k->parent[first];
    if (g < 0 || rf_rig_apart2(k->pos + (size_t)first * 3, k->pos + (size_t)g * 3) == 0)
        return true;
    rf_rig_skel was;
    if (!rf_rig_skel_copy(k, &was))
        return false;
    double pivot[3];
    memcpy(pivot, k->pos + (size_t)g * 3, sizeof pivot);
    while (k->parent[root] >= 0)
        root = (uint32_t)k->parent[root];
    bool ok = rf_rig_append(k, pivot, g);
    if (ok)
        k->parent[first] = (int32_t)k->n - 1;
    ok = ok && rf_rig_reroot(k, root); /* parents before children again */
    rf_skeleton *s = NULL;
    rf_analysis *b = ok ? rf_rig_read(k, o, &s) : NULL;
    ok = b != NULL;
    bool turned = ok && rf_v3_dot(b->forward, a->forward) < 0;
    rf_analysis_free(b);
    rf_skeleton_free(s);
    if (turned) {
        rf_rig_skel_free(&was);
    } else {
        rf_rig_skel_free(k);
        *k = was;
    }
    return ok;
}

/* The skeleton analysis (so the matcher) reads a level body's facing partly from its hierarchy:
 * artists root it at its hind girdle and the spine runs forward from there to the shoulders.
 * Which girdle rf_rig_curve roots the rig at is a guess (the one farthest from the middle of
 * the surface, as a quadruped's chest, neck and head outweigh its rear), wrong on a body with a
 * long heavy tail. So when one end of a level body is clearly the head by its bulk
 * (rf_rig_hind_end), the hierarchy runs the other way (its deepest girdle behind its
 * shallowest) and the elevation of the ends votes against the hierarchy too, the rig is rooted
 * at that deepest girdle, its joints unmoved. Neither body cue alone overrules the rigger's
 * guess: the fire dragon's and the jungle wyvern's tails end bulkier than their heads, and the
 * bat holds its head lower than its rear. A rig whose hierarchy says nothing, its legs on one
 * girdle, is given a say the same way when both body cues vote against the facing read
 * (rf_rig_pivot_hind). Up and facing as the rig is named. False when out of memory. */
static bool rf_rig_root_hind(const rf_rig_prep *p, rf_rig_skel *k, const rf_rig_options *o)
{
    rf_skeleton *s;
    rf_analysis *a = rf_rig_read(k, o, &s);
    if (!a)
        return false;
    uint32_t shallow = RF_RIG_NONE, deep = RF_RIG_NONE;
    double elevation = rf_rig_cue(a, "elevation"), hierarchy = rf_rig_cue(a, "hierarchy");
    bool girdles = rf_rig_girdle_ends(k, a, &shallow, &deep);
    rf_vec3 g = girdles ? rf_v3_sub(a->joints[deep].pos, a->joints[shallow].pos) : rf_v3(0, 0, 0);
    /* the cheap tests first: the surface is built only for a level body whose elevation votes
     * against its hierarchy, or against its facing when the hierarchy is silent (the pooled
     * facing places the rig five times) */
    bool turn =
        girdles && fabs(rf_v3_dot(g, a->up)) < 0.5 * rf_v3_len(g) && elevation * hierarchy < 0;
    bool lone = hierarchy == 0 && elevation < 0;
    rf_rig_surface *sf = turn || lone ? rf_rig_surface_make(&p->proxy) : NULL;
    bool ok = sf || !(turn || lone);
    rf_vec3 way = rf_v3(0, 0, 0);
    int32_t hind = sf ? rf_rig_hind_end(sf, a, &way) : -1;
    rf_rig_surface_free(sf);
    turn = turn && hind >= 0 && rf_v3_dot(g, way) < 0;
    lone = lone && hind >= 0 && rf_v3_dot(a->forward, way) < 0;
    if (ok && turn && k->parent[deep] >= 0)
        ok = rf_rig_reroot(k, deep);
    else if (ok && lone)
        ok = rf_rig_pivot_hind(k, a, hind, o);
    rf_analysis_free(a);
    rf_skeleton_free(s);
    return ok;
}

rf_rig_status rf_rig_curve(const rf_rig_prep *p, const rf_rig_options *o, rf_rig_skel *k, char *err,
                           size_t err_size)
{
    double mirror[4], stand[4] = {0}, hips_at[3], seed[3];
    double mid[3] = {0, 0, 0}; /* the proxy's vertices' mean: where the hips are not */
    for (uint32_t v = 0; v < p->proxy.nv; v++)
        for (int a = 0; a < 3; a++)
            mid[a] += p->proxy.p[(size_t)v * 3 + a] / p->proxy.nv;
    rf_rig_status status = rf_rig_first_pass(p, o, mid, mirror, stand, k, err, err_size);
    if (status != RF_RIG_OK)
        return status; /* k holds nothing */
    /* Level sets grown from the hips cut the body square to its length (shoulders level, limbs
     * leaving symmetrically); from the thickest point they would ring the chest. So a second pass
     * starts where the first pass's two lowest leaves meet. Where the first pass kept legs the
     * bands had scored as bumps (rf_rig_stands_on), it starts where those legs leave the body,
     * found before junctions a short chain apart became one joint (the fire dragon's hips and
     * chest, a bone apart, were one), and the feet are the lowest along the declared up; so
     * they are where the analysis reads the first pass's up over 45 degrees off it. Girdles
     * not looked for are no answer: a lack of memory is said, not read as "no feet". */
    bool legs = stand[3] != 0, agree = true;
    rf_vec3 up = legs ? o->up : rf_v3(0, 0, 0); /* zero: the analysis's */
    rf_rig_girdle_set girdles = {0};
    const char *doing = "reading its up";
    if (!legs && !rf_rig_reads_up(k, o->up, &agree))
        goto no_memory;
    if (!agree)
        up = o->up;
    doing = "looking for the hips";
    if (!rf_rig_girdles(k, up, &girdles))
        goto no_memory;
    uint32_t r = rf_rig_pick_root(k, &girdles), hips = rf_rig_pick_hips(k, &girdles, mid);
    rf_rig_girdle_set_free(&girdles);
    if (hips != RF_RIG_NONE)
        memcpy(hips_at, k->pos + (size_t)hips * 3, sizeof hips_at);
    bool again = legs || (r != RF_RIG_NONE && k->parent[r] >= 0);
    if (legs)
        memcpy(seed, stand, sizeof seed);
    else if (again)
        memcpy(seed, k->pos + (size_t)r * 3, sizeof seed);
    else if (rf_rig_off_middle(k, mirror, p->longest / o->resolution, seed))
        again = true;
    if (again) {
        rf_rig_skel_free(k);
        status = rf_rig_extract(p, o, seed, NULL, NULL, k, err, err_size);
        if (status != RF_RIG_OK)
            return status;
    }
    doing = "centring the skeleton";
    if (!rf_rig_on_plane(k, mirror, p->longest / o->resolution))
        goto no_memory;
    /* The skeleton analysis (and so the matcher) reads which way a body faces partly from where
     * the root is: artists root a quadruped at its hips, and the spine runs from there to the
     * shoulders. The second pass's root, the highest girdle, is often the shoulders; the rig is
     * rooted again at the girdle nearest the hips, its joints unmoved. */
    if (hips == RF_RIG_NONE)
        return RF_RIG_OK;
    doing = "re-rooting the skeleton";
    if (!rf_rig_girdles(k, up, &girdles))
        goto no_memory;
    uint32_t g = rf_rig_girdle_near(k, &girdles, hips_at);
    rf_rig_girdle_set_free(&girdles);
    if (g == RF_RIG_NONE || k->parent[g] < 0 || rf_rig_reroot(k, g))
        return RF_RIG_OK;
no_memory:
    rf_rig_girdle_set_free(&girdles);
    rf_rig_skel_free(k);
    return rf_rig_oom(err, err_size, "out of memory %s", doing);
}

/* Marks in below[] the joints with a joint in used[] below them: a joint inside a chain whose
 * own bone moves no vertex still bends the chain. */
static void rf_rig_mark_below(const rf_rig_skel *k, const uint8_t *used, uint8_t *below)
{
    for (uint32_t j = k->n; j-- > 0;)
        if ((used[j] || below[j]) && k->parent[j] >= 0)
            below[k->parent[j]] = 1;
}

/* The skin from bone heat's rows w, written into a copy of the mesh, and s's joints that move no
 * vertex marked unweighted. */
static bool rf_rig_write_skin(const rf_mesh *mesh, const rf_rig_prep *p, const rf_rig_skel *k,
                              const double *w, rf_skeleton *s, rf_mesh **skinned, rf_rig_stats *st,
                              char *err, size_t err_size)
{
    bool ok = true;
    rf_mesh *m = rf_rig_mesh_copy(mesh);
    if (!m || !rf_rig_skin(mesh, p, k, w, m, st))
        ok = rf_rig_fail(err, err_size, "out of memory writing the rig");
    /* a joint whose bone won no vertex says so, as artists' helper joints do; out of memory is
     * said, never a rig without those marks (the matcher would drive the joints as body) */
    uint8_t *used = ok ? calloc(k->n + 1, 1) : NULL, *below = ok ? calloc(k->n + 1, 1) : NULL;
    if (ok && !(used && below))
        ok = rf_rig_fail(err, err_size, "out of memory writing the rig");
    if (ok) {
        for (size_t i = 0; i < (size_t)m->vertex_count * 4; i++)
            if (m->skin_weights[i] > 0)
                used[m->skin_joints[i]] = 1;
        rf_rig_mark_below(k, used, below);
        for (uint32_t j = 0; j < k->n; j++)
            if (!used[j] && !below[j])
                s->joints[j].flags |= RF_JOINT_UNWEIGHTED;
        st->joints = k->n;
        *skinned = m;
    } else {
        rf_mesh_free(m);
    }
    free(below), free(used);
    return ok;
}

bool rf_rig_weigh(const rf_mesh *mesh, const rf_rig_prep *p, const rf_rig_skel *k,
                  const rf_rig_options *o, rf_skeleton *s, rf_mesh **skinned, rf_rig_stats *st,
                  char *err, size_t err_size)
{
    double *w = NULL;
    *skinned = NULL;
    bool ok = rf_rig_heat(p, k, o, &w, NULL, st, err, err_size) &&
              rf_rig_write_skin(mesh, p, k, w, s, skinned, st, err, err_size);
    free(w);
    return ok;
}

/* A body carried level (a quadruped, a lizard, a bird in flight) has its spine along its back,
 * not through the middle where the curve skeleton runs: its spine joints (by the skeleton
 * analysis) move to RF_RIG_DORSAL of the body's depth from the belly along up. A trunk that
 * stands (a biped) is left. False when out of memory. */
#define RF_RIG_DORSAL 0.66
static bool rf_rig_dorsal(const rf_rig_prep *p, rf_rig_skel *k, const rf_rig_options *o)
{
    rf_skeleton *s = rf_rig_skeleton(k, NULL);
    if (!s)
        return false;
    s->up = o->up, s->forward = o->forward;
    rf_analysis *a = rf_analyze(s, NULL);
    uint8_t *spine = calloc(k->n + 1, 1);
    bool ok = a && spine;
    int32_t first = -1, last = -1;
    for (uint32_t j = 0; ok && j < k->n; j++) {
        int32_t sec = a->joints[j].section;
        if (sec < 0 || a->sections[sec].type != RF_SECTION_SPINE)
            continue;
        spine[j] = 1, last = (int32_t)j;
        first = first < 0 ? (int32_t)j : first;
    }
    if (first >= 0 && first != last) {
        rf_vec3 d = rf_v3_sub(a->joints[last].pos, a->joints[first].pos);
        if (fabs(rf_v3_dot(d, a->up)) < 0.5 * rf_v3_len(d))
            ok = rf_rig_skel_across(p, k, spine, a->up, RF_RIG_DORSAL);
    }
    free(spine);
    rf_analysis_free(a);
    rf_skeleton_free(s);
    return ok;
}

/* The narrower of the body's two diameters across `up` at q (along `fwd` and to the side),
 * by rays on the surface; INFINITY where a ray leaves the mesh. */
static double rf_rig_girth(const rf_rig_surface *sf, const double q[3], rf_vec3 up, rf_vec3 fwd)
{
    rf_vec3 side = rf_v3_normalize(rf_v3_cross(up, fwd));
    rf_vec3 f = rf_v3_normalize(rf_v3_cross(side, up));
    double best = INFINITY;
    for (int a = 0; a < 2; a++) {
        rf_vec3 d = a ? side : f;
        double dp[3] = {d.x, d.y, d.z}, dn[3] = {-d.x, -d.y, -d.z};
        best = fmin(best, rf_rig_surface_hit(sf, q, dp) + rf_rig_surface_hit(sf, q, dn));
    }
    return best;
}

#define RF_RIG_NECK_STEPS 24
#define RF_RIG_NECK_GIRTH 0.8 /* of the head's girth at its first joint: inside the head */

/* Head joint h of k moved down its bone to where the trunk enters the head's bulk: to the
 * lowest point from which the girth (rf_rig_girth, across up and fwd) stays at least
 * RF_RIG_NECK_GIRTH of the girth at the joint, when its bone from its parent rises within 45
 * degrees of up and that point lies between a fifth and nine tenths of the bone from its
 * parent (a neck narrower than the head below the joint: nothing moves). */
bool rf_rig_head_base(const rf_rig_prep *p, rf_rig_skel *k, uint32_t h, rf_vec3 up, rf_vec3 fwd)
{
    if (!(h < k->n && k->parent[h] >= 0 && rf_v3_len(rf_v3_cross(up, fwd)) > 0.5))
        return true;
    rf_rig_surface *sf = rf_rig_surface_make(&p->proxy);
    if (!sf)
        return false;
    double *q = k->pos + (size_t)h * 3, *b = k->pos + (size_t)k->parent[h] * 3;
    double d[3] = {q[0] - b[0], q[1] - b[1], q[2] - b[2]};
    double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double rise = d[0] * up.x + d[1] * up.y + d[2] * up.z;
    double head = rf_rig_girth(sf, q, up, fwd);
    int from = RF_RIG_NECK_STEPS;
    while (len > 0 && rise > 0.7 * len && isfinite(head) && from > 0) {
        double t = (double)(from - 1) / RF_RIG_NECK_STEPS, x[3];
        for (int c = 0; c < 3; c++)
            x[c] = b[c] + t * d[c];
        if (!(rf_rig_girth(sf, x, up, fwd) >= RF_RIG_NECK_GIRTH * head))
            break;
        from--;
    }
    double t = (double)from / RF_RIG_NECK_STEPS;
    if (from > 0 && t >= 0.2 && t <= 0.9)
        for (int c = 0; c < 3; c++)
            q[c] = b[c] + t * d[c];
    rf_rig_surface_free(sf);
    return true;
}

/* An upright body's head chain starts where the trunk enters the head's bulk: the curve
 * skeleton's first head joint may lie well inside a head wider than the trunk under it (a
 * robot's head box starts 0.4 below it), and the clip's neck then turned the head about a
 * pivot in its middle. The first joint of the analysis's head section moves down its bone
 * (rf_rig_head_base). */
static bool rf_rig_neck(const rf_rig_prep *p, rf_rig_skel *k, const rf_rig_options *o)
{
    rf_skeleton *s = rf_rig_skeleton(k, NULL);
    if (!s)
        return false;
    s->up = o->up, s->forward = o->forward;
    rf_analysis *a = rf_analyze(s, NULL);
    bool ok = a != NULL;
    int32_t h = -1;
    for (uint32_t j = 0; a && j < k->n && h < 0; j++) {
        int32_t sec = a->joints[j].section;
        if (sec >= 0 && a->sections[sec].type == RF_SECTION_HEAD && k->parent[j] >= 0)
            h = (int32_t)j;
    }
    if (ok && h >= 0)
        ok = rf_rig_head_base(p, k, (uint32_t)h, a->up, a->forward);
    rf_analysis_free(a);
    rf_skeleton_free(s);
    return ok;
}

/* ---- a head piece turns whole ---- */

/* How many triangles of loose part `part` of g the ray from q along d crosses (Moller and
 * Trumbore's test). */
static uint32_t rf_rig_crossings(const rf_rig_geo *g, const uint32_t *part_of, uint32_t part,
                                 const double q[3], const double d[3])
{
    uint32_t n = 0;
    for (uint32_t t = 0; t < g->nt; t++) {
        const uint32_t *tv = g->t + (size_t)t * 3;
        if (part_of[tv[0]] != part)
            continue;
        const double *a = g->p + (size_t)tv[0] * 3, *b = g->p + (size_t)tv[1] * 3,
                     *c = g->p + (size_t)tv[2] * 3;
        double e1[3], e2[3], s[3], h[3], qv[3];
        for (int i = 0; i < 3; i++)
            e1[i] = b[i] - a[i], e2[i] = c[i] - a[i], s[i] = q[i] - a[i];
        h[0] = d[1] * e2[2] - d[2] * e2[1], h[1] = d[2] * e2[0] - d[0] * e2[2];
        h[2] = d[0] * e2[1] - d[1] * e2[0];
        double det = e1[0] * h[0] + e1[1] * h[1] + e1[2] * h[2];
        if (fabs(det) < 1e-300)
            continue;
        double u = (s[0] * h[0] + s[1] * h[1] + s[2] * h[2]) / det;
        qv[0] = s[1] * e1[2] - s[2] * e1[1], qv[1] = s[2] * e1[0] - s[0] * e1[2];
        qv[2] = s[0] * e1[1] - s[1] * e1[0];
        double v = (d[0] * qv[0] + d[1] * qv[1] + d[2] * qv[2]) / det;
        double at = (e2[0] * qv[0] + e2[1] * qv[1] + e2[2] * qv[2]) / det;
        n += u >= 0 && v >= 0 && u + v <= 1 && at > 0;
    }
    return n;
}

/* Whether q lies in the bounding box of loose part `part` (a cheap test before the rays). */
static bool rf_rig_part_box_holds(const rf_rig_prep *p, uint32_t part, const double q[3])
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t v = 0; v < p->proxy.nv; v++) {
        if (p->proxy_part[v] != part)
            continue;
        for (int a = 0; a < 3; a++) {
            lo[a] = fmin(lo[a], p->proxy.p[(size_t)v * 3 + a]);
            hi[a] = fmax(hi[a], p->proxy.p[(size_t)v * 3 + a]);
        }
    }
    return q[0] >= lo[0] && q[0] <= hi[0] && q[1] >= lo[1] && q[1] <= hi[1] && q[2] >= lo[2] &&
           q[2] <= hi[2];
}

/* Whether loose part `part` encloses q: the ray both ways along one oblique line (not along a
 * box's faces) crosses it an odd number of times; an open part (a sheet, a cape) is crossed
 * one way only, or evenly, and encloses nothing. */
static bool rf_rig_part_encloses(const rf_rig_prep *p, uint32_t part, const double q[3])
{
    static const double d[3] = {0.5377, 0.7071, 0.4592}, e[3] = {-0.5377, -0.7071, -0.4592};
    return rf_rig_crossings(&p->proxy, p->proxy_part, part, q, d) % 2 == 1 &&
           rf_rig_crossings(&p->proxy, p->proxy_part, part, q, e) % 2 == 1;
}

/* k without the joints flagged in drop[] (whole subtrees: a dropped joint's children are
 * dropped too); parents still come first. */
static void rf_rig_drop(rf_rig_skel *k, const uint8_t *drop, int32_t *to)
{
    uint32_t n = 0;
    for (uint32_t j = 0; j < k->n; j++) {
        to[j] = -1;
        if (drop[j])
            continue;
        to[j] = (int32_t)n;
        memmove(k->pos + (size_t)n * 3, k->pos + (size_t)j * 3, 3 * sizeof *k->pos);
        memmove(k->tip + (size_t)n * 3, k->tip + (size_t)j * 3, 3 * sizeof *k->tip);
        k->has_tip[n] = k->has_tip[j];
        k->parent[n] = k->parent[j] >= 0 ? to[k->parent[j]] : -1;
        if (k->owns_in)
            k->owns_in[n] = k->owns_in[j];
        n++;
    }
    k->n = n;
}

/* Moves end along the line from o through it until it lies as far along that line as q does,
 * when q lies farther. */
static void rf_rig_reach_along(const double *o, double *end, const double *q)
{
    double dir[3], len = sqrt(rf_rig_apart2(end, o)), along = 0;
    for (int c = 0; c < 3; c++)
        dir[c] = (end[c] - o[c]) / len, along += (q[c] - o[c]) * dir[c];
    if (along > len)
        for (int c = 0; c < 3; c++)
            end[c] = o[c] + along * dir[c];
}

/* The point among joint j's pivot (e 0) and tip (e 1, when it has one) of k, or NULL. */
static const double *rf_rig_point(const rf_rig_skel *k, uint32_t j, int e)
{
    return e ? (k->has_tip[j] ? k->tip + (size_t)j * 3 : NULL) : k->pos + (size_t)j * 3;
}

/* For each joint j of k, in anc[], j itself when drop[j] is clear, else its nearest ancestor
 * not dropped; in tip[] ([n][3], set[] flagging which), for a joint a left a leaf by the drop,
 * the end of its new bone: along the line to the dropped pivot farthest from a's, as far as any
 * dropped pivot or tip reaches along it. The farthest point itself may be a leaf's tip aimed
 * aside (to the gap between two legs), the line of pivots is the leg's. */
static void rf_rig_drop_ends(const rf_rig_skel *k, const uint8_t *drop, int32_t *anc, double *tip,
                             uint8_t *set, uint8_t *inner)
{
    for (uint32_t j = 0; j < k->n; j++) {
        int32_t p = k->parent[j];
        anc[j] = !drop[j] || p < 0 ? (int32_t)j : anc[p];
        if (!drop[j] && p >= 0)
            inner[p] = 1;
    }
    for (int pass = 0; pass < 2; pass++)
        for (uint32_t j = 0; j < k->n; j++) {
            uint32_t a = (uint32_t)anc[j];
            if (!drop[j] || inner[a])
                continue;
            const double *o = k->pos + (size_t)a * 3;
            double *end = tip + (size_t)a * 3;
            for (int e = 0; e < 1 + pass; e++) {
                const double *q = rf_rig_point(k, j, e);
                double d = q ? rf_rig_apart2(q, o) : 0;
                if (!pass && d > 0 && (!set[a] || d > rf_rig_apart2(end, o)))
                    memcpy(end, q, 3 * sizeof *q), set[a] = 1;
                else if (pass && d > 0 && set[a])
                    rf_rig_reach_along(o, end, q);
            }
        }
}

/* The least share of a vertex's weight by which a joint visibly moves it: the share the
 * skinning's evaluation prunes below (doc/autorig.md, rig-bench). */
#define RF_RIG_MOVES 0.15

/* Flags in moves[] the joints of the n whose rows w ([nv][n]) give some vertex at least
 * RF_RIG_MOVES of its weight: a joint below that everywhere moves nothing anyone sees. */
static void rf_rig_moving(const double *w, uint32_t nv, uint32_t n, uint8_t *moves)
{
    for (uint32_t v = 0; v < nv; v++) {
        const double *row = w + (size_t)v * n;
        double sum = 0;
        for (uint32_t j = 0; j < n; j++)
            sum += row[j];
        for (uint32_t j = 0; sum > 0 && j < n; j++)
            if (row[j] >= RF_RIG_MOVES * sum)
                moves[j] = 1;
    }
}

/* Drops the joints a low-poly box holds below the joint it moves with alone (boxed[], from
 * rf_rig_heat), and the joints that move no vertex visibly (rf_rig_moving: the twigs past the
 * angelfish's fins, the cat's back where bone heat gives its box to the body), where every joint
 * below them is dropped too (a joint inside a chain still bends it), folding their columns of w
 * ([proxy vertex][k->n]) into their nearest kept ancestor's (the body's vertices about the box's
 * top may weight them a little). They bend nothing of the box; kept, they had no skin, read as
 * helpers to the matcher, and the leg ended at the box's joint with its bone short of the floor:
 * the retarget found no foot there (the animalia cat's forelegs took the human's arms). Dropped,
 * the joint left at the chain's end takes their reach as its tip (rf_rig_drop_ends), and its
 * bone reaches the floor as an artist's one-bone leg's does. False when out of memory. */
static bool rf_rig_prune(const rf_rig_prep *p, rf_rig_skel *k, const uint8_t *boxed, double **w)
{
    uint32_t n = k->n, nv = p->proxy.nv, dropped = 0;
    uint8_t *held = calloc(n + 1, 1), *drop = calloc(n + 1, 1), *set = calloc(n + 1, 1),
            *inner = calloc(n + 1, 1);
    int32_t *anc = malloc((n + 1) * sizeof *anc), *to = malloc((n + 1) * sizeof *to);
    double *tip = malloc((n + 1) * 3 * sizeof *tip);
    bool ok = held && drop && set && inner && anc && to && tip;
    if (ok)
        rf_rig_moving(*w, nv, n, held);
    for (uint32_t j = 0; ok && j < n; j++)
        held[j] = held[j] && !boxed[j];
    if (ok)
        rf_rig_mark_below(k, held, drop); /* drop[] first holds "something kept below" */
    for (uint32_t j = 0; ok && j < n; j++)
        drop[j] = k->parent[j] >= 0 && !held[j] && !drop[j], dropped += drop[j];
    double *kept = ok && dropped ? calloc((size_t)nv * (n - dropped) + 1, sizeof *kept) : NULL;
    ok = ok && (!dropped || kept);
    if (ok && dropped) {
        rf_rig_drop_ends(k, drop, anc, tip, set, inner);
        for (uint32_t j = 0; j < n; j++)
            if (set[j])
                memcpy(k->tip + (size_t)j * 3, tip + (size_t)j * 3, 3 * sizeof *tip),
                    k->has_tip[j] = 1;
        rf_rig_drop(k, drop, to);
        for (uint32_t v = 0; v < nv; v++)
            for (uint32_t j = 0; j < n; j++)
                kept[(size_t)v * k->n + (uint32_t)to[anc[j]]] += (*w)[(size_t)v * n + j];
        free(*w);
        *w = kept;
    }
    free(held), free(drop), free(set), free(inner), free(anc), free(to), free(tip);
    return ok;
}

/* The joint where the head's bulk starts: of the joints from the head's first joint h down
 * (flagged in sub[]), the first whose girth (rf_rig_girth) is at least RF_RIG_NECK_GIRTH of the
 * largest among them; a neck narrower than the head keeps its joint. NONE when no girth is
 * measured. False when out of memory (no girth measured is not a neck that keeps its joint). */
static bool rf_rig_bulk(const rf_rig_prep *p, const rf_rig_skel *k, const uint8_t *sub, rf_vec3 up,
                        rf_vec3 fwd, uint32_t *bulk)
{
    *bulk = RF_RIG_NONE;
    if (!(rf_v3_len(rf_v3_cross(up, fwd)) > 0.5))
        return true;
    rf_rig_surface *sf = rf_rig_surface_make(&p->proxy);
    double *g = sf ? malloc((k->n + 1) * sizeof *g) : NULL, most = 0;
    uint32_t b = RF_RIG_NONE;
    for (uint32_t j = 0; g && j < k->n; j++) {
        g[j] = sub[j] ? rf_rig_girth(sf, k->pos + (size_t)j * 3, up, fwd) : NAN;
        most = isfinite(g[j]) ? fmax(most, g[j]) : most;
    }
    for (uint32_t j = 0; g && j < k->n && b == RF_RIG_NONE; j++) /* parents come first */
        if (isfinite(g[j]) && most > 0 && g[j] >= RF_RIG_NECK_GIRTH * most)
            b = j;
    bool ok = g != NULL;
    free(g);
    rf_rig_surface_free(sf);
    *bulk = b;
    return ok;
}

/* The ends of the bones of the joints flagged in drop[] (pivots and leaf ends), the farthest
 * from q into end[]. */
static void rf_rig_farthest(const rf_rig_skel *k, const uint8_t *drop, const double q[3],
                            double end[3])
{
    double far = -1;
    for (uint32_t j = 0; j < k->n; j++)
        for (int e = 0; drop[j] && e < 1 + k->has_tip[j]; e++) {
            const double *x = (e ? k->tip : k->pos) + (size_t)j * 3;
            double d = (x[0] - q[0]) * (x[0] - q[0]) + (x[1] - q[1]) * (x[1] - q[1]) +
                       (x[2] - q[2]) * (x[2] - q[2]);
            if (d > far)
                far = d, memcpy(end, x, 3 * sizeof *end);
        }
}

/* A head modelled as a piece of its own (a robot's head box, a head with its neck) turns whole
 * on one joint, as an artist binds it: the curve skeleton runs its head chain on through the
 * piece, two or three joints inside one closed part, and the clip's neck and head joints bent
 * the box between them (the CMU walk tipped a robot's head forward and drew its rim into a V,
 * its lower ring bound to the chest). From the joint where the head's bulk starts
 * (rf_rig_bulk: the analysis's first head joint, or one past a neck), when it and the middle
 * of every bone below it lie inside one closed loose part that does not enclose the trunk
 * joint the head hangs from (a twig's pivot at a box's corner may lie just outside), the
 * joints below it go and its bone reaches to the farthest of their ends; bone
 * heat then gives the piece's bulk to that joint alone. A head of the body's own surface (one
 * mesh, which encloses the trunk too) is left: its chain bends with the neck it models. False
 * when out of memory. */
static bool rf_rig_head_whole(const rf_rig_prep *p, rf_rig_skel *k, const rf_rig_options *o)
{
    rf_skeleton *s = rf_rig_skeleton(k, NULL);
    if (!s)
        return false;
    s->up = o->up, s->forward = o->forward;
    rf_analysis *a = rf_analyze(s, NULL);
    rf_skeleton_free(s);
    if (!a)
        return false;
    int32_t h = -1;
    for (uint32_t j = 0; j < k->n && h < 0; j++) {
        int32_t sec = a->joints[j].section;
        if (sec >= 0 && a->sections[sec].type == RF_SECTION_HEAD && k->parent[j] >= 0)
            h = (int32_t)j;
    }
    rf_vec3 up = a->up, fwd = a->forward;
    rf_analysis_free(a);
    if (h < 0)
        return true;
    uint8_t *sub = calloc(k->n + 1, 1), *drop = calloc(k->n + 1, 1);
    int32_t *to = malloc((k->n + 1) * sizeof *to);
    bool ok = sub && drop && to;
    for (uint32_t j = (uint32_t)h; ok && j < k->n; j++) /* parents come first */
        sub[j] = j == (uint32_t)h || (k->parent[j] >= 0 && sub[k->parent[j]]);
    uint32_t b = RF_RIG_NONE, below = 0;
    ok = ok && rf_rig_bulk(p, k, sub, up, fwd, &b);
    for (uint32_t j = b + 1; b != RF_RIG_NONE && j < k->n; j++)
        if (k->parent[j] >= 0 && ((uint32_t)k->parent[j] == b || drop[k->parent[j]]))
            drop[j] = 1, below++;
    const double *trunk = k->pos + (size_t)k->parent[h] * 3;
    for (uint32_t part = 0; below && part < p->proxy_parts; part++) {
        bool whole = rf_rig_part_box_holds(p, part, k->pos + (size_t)b * 3) &&
                     rf_rig_part_encloses(p, part, k->pos + (size_t)b * 3) &&
                     !rf_rig_part_encloses(p, part, trunk);
        for (uint32_t j = b + 1; whole && j < k->n; j++) { /* the middle of each bone dropped */
            const double *x = k->pos + (size_t)j * 3, *y = k->pos + (size_t)k->parent[j] * 3;
            double mid[3] = {(x[0] + y[0]) / 2, (x[1] + y[1]) / 2, (x[2] + y[2]) / 2};
            whole = !drop[j] || rf_rig_part_encloses(p, part, mid);
        }
        if (!whole)
            continue;
        rf_rig_farthest(k, drop, k->pos + (size_t)b * 3, k->tip + (size_t)b * 3);
        k->has_tip[b] = 1;
        rf_rig_drop(k, drop, to);
        break;
    }
    free(sub), free(drop), free(to);
    return ok;
}

#define RF_RIG_BOTTOM_GAP 0.25 /* of the body's height between its bottom and the skeleton's */

/* A body whose skeleton stops well above its bottom (a blob body on stubs too short to keep:
 * its trunk's two ends are cones shorter than the body is thick, pruned as bumps) gets a joint
 * below its root, three quarters of the way down to the surface under it, and is rooted there:
 * artists put one at the body's bottom, and without it the lower body hangs from a root in its
 * middle. Up is the declared one, else the analysis's. False when out of memory. */
static bool rf_rig_bottom(const rf_rig_prep *p, rf_rig_skel *k, rf_vec3 up)
{
    double u[3] = {up.x, up.y, up.z}, lo = INFINITY, hi = -INFINITY, low = INFINITY;
    for (uint32_t v = 0; v < p->proxy.nv; v++) {
        const double *q = p->proxy.p + (size_t)v * 3;
        double h = q[0] * u[0] + q[1] * u[1] + q[2] * u[2];
        lo = fmin(lo, h), hi = fmax(hi, h);
    }
    for (uint32_t j = 0; j < k->n; j++) /* joints and the ends of leaf bones */
        for (int e = 0; e < 1 + k->has_tip[j]; e++) {
            const double *q = (e ? k->tip : k->pos) + (size_t)j * 3;
            low = fmin(low, q[0] * u[0] + q[1] * u[1] + q[2] * u[2]);
        }
    if (!k->n || rf_v3_len(up) == 0 || low - lo <= RF_RIG_BOTTOM_GAP * (hi - lo))
        return true;
    rf_rig_surface *surf = rf_rig_surface_make(&p->proxy);
    if (!surf)
        return false;
    double down[3] = {-u[0], -u[1], -u[2]};
    double d = rf_rig_surface_hit(surf, k->pos, down); /* from the root, joint 0 */
    rf_rig_surface_free(surf);
    if (!isfinite(d))
        return true;
    double at[3];
    for (int a = 0; a < 3; a++)
        at[a] = k->pos[a] + 0.75 * d * down[a];
    /* the rig's root, as artists root such a body at its bottom: hung from the old root, the
     * joint took the clip's hips in the matcher and turned the body over (greenman under the
     * CMU walk: stretch p99 84, parts under the floor in a quarter of the frames; rooted, 20) */
    return rf_rig_append(k, at, 0) && rf_rig_reroot(k, k->n - 1);
}

#define RF_RIG_LOW_END 0.2 /* of the body's height: the bottom where a free end stands */
#define RF_RIG_STEM 0.25   /* of the body's height: how far a stem rises to its junction */

/* The low point of joint j along u: its pivot, or its leaf bone's end when lower. */
static double rf_rig_low_of(const rf_rig_skel *k, uint32_t j, const double u[3])
{
    const double *q = k->pos + (size_t)j * 3, *t = k->tip + (size_t)j * 3;
    double h = q[0] * u[0] + q[1] * u[1] + q[2] * u[2];
    return k->has_tip[j] ? fmin(h, t[0] * u[0] + t[1] * u[1] + t[2] * u[2]) : h;
}

/* The one leaf of k that reaches the bottom fifth of the body (heights lo..hi along u), when
 * the chain above it rises unbranched by a quarter of the height or more to a junction that is
 * the root, or that the root stands a quarter of the height above: the root stands in the
 * trunk and the trunk's lower stretch hangs from it (huesitos read with no axes, whose frame
 * then follows its own axis, is rooted at the top of its stem, above its fork). NONE when no
 * leaf, or more than one (feet, a quadruped's legs, a tail beside them), stands there, or when
 * the chain leaves the body elsewhere (a fish's tail fin, whose root is at its head, as high).
 * Into *end; false when out of memory. */
static bool rf_rig_free_end(const rf_rig_skel *k, const double u[3], double lo, double hi,
                            uint32_t *found)
{
    uint32_t *kids = calloc(k->n + 1, sizeof *kids), end = RF_RIG_NONE;
    *found = RF_RIG_NONE;
    if (!kids)
        return false;
    for (uint32_t j = 0; j < k->n; j++)
        if (k->parent[j] >= 0)
            kids[k->parent[j]]++;
    double low = lo + RF_RIG_LOW_END * (hi - lo);
    uint32_t count = 0;
    for (uint32_t j = 0; j < k->n; j++)
        if (!kids[j] && rf_rig_low_of(k, j, u) <= low)
            count++, end = j;
    if (count != 1 || k->parent[end] < 0) {
        free(kids);
        return true;
    }
    int32_t up = k->parent[end]; /* up the chain to its junction */
    while (k->parent[up] >= 0 && kids[up] == 1)
        up = k->parent[up];
    const double *q = k->pos + (size_t)up * 3, *r = k->pos;
    double at = q[0] * u[0] + q[1] * u[1] + q[2] * u[2];
    bool rises = at - rf_rig_low_of(k, end, u) >= RF_RIG_STEM * (hi - lo);
    bool above = r[0] * u[0] + r[1] * u[1] + r[2] * u[2] - at >= RF_RIG_STEM * (hi - lo);
    free(kids);
    *found = rises && (k->parent[up] < 0 || above) ? end : RF_RIG_NONE;
    return true;
}

/* A body whose trunk ends low in one free end (a stem, a pole, a tail it stands on: no pair of
 * feet meets in a girdle to root it at) and is rooted where that end's chain leaves the rest is
 * rooted at the end instead, as artists root it, low in the body: rooted at its junction, the
 * stem hung down from the root as an appendage and the matcher gave it an upper branch's joints
 * (huesitos, its artist's lowest bone unmatched). The joints stay where they are. Up is the
 * declared one, else the analysis's. False when out of memory. */
static bool rf_rig_root_low(const rf_rig_prep *p, rf_rig_skel *k, rf_vec3 up)
{
    double u[3] = {up.x, up.y, up.z}, lo = INFINITY, hi = -INFINITY;
    if (!k->n || rf_v3_len(up) == 0)
        return true;
    for (uint32_t v = 0; v < p->proxy.nv; v++) {
        const double *q = p->proxy.p + (size_t)v * 3;
        double h = q[0] * u[0] + q[1] * u[1] + q[2] * u[2];
        lo = fmin(lo, h), hi = fmax(hi, h);
    }
    uint32_t end;
    if (!rf_rig_free_end(k, u, lo, hi, &end))
        return false;
    if (end == RF_RIG_NONE)
        return true;
    k->has_tip[end] = 0; /* a root's bones are those to its children */
    return rf_rig_reroot(k, end);
}

/* ---- limbs cut as artists cut them ---- */

/* An arm whose curve reaches more than this many times as far as the longest laid leg's is a
 * wing (the bat's, bird's, owl's and the dragons' 2.3 to 5.6 times; a human's arm, the Wizard's
 * and RobotExpressive's, 1.36 and 1.47). A wing's bones run along its leading edge, the
 * membrane or feathers trailing behind them, where the curve skeleton of the flat wing runs
 * through the middle of its chord: its joints past the clavicle go this far from the back edge
 * to the front (rf_rig_skel_chord along the body's level facing; a wing of no thickness, the
 * bat's sheet, walked in its plane). The clavicle stays with the body: moved too, the matcher
 * read the bird's and the bat's shoulders otherwise and their bodies stretched under a walk. */
#define RF_RIG_WING_REACH 2.0
#define RF_RIG_WING_EDGE 0.85
/* A wing's elbow and wrist along its curve from the girdle: the hand and its fingers make up
 * the outer half of a wing (a bat's, a bird's, a pterosaur's), so its wrist lies near the middle
 * of the span, not where an arm's hand does (0.8). The winged artist rigs of the shared data put
 * their last wing joint 0.36 (the owl) to 0.49 (the jungle wyvern) of the way out, and the
 * dragons their elbow at 0.21 and 0.24; laid at an arm's fractions, the rigger's hand stood 0.17
 * to 0.27 of the longest edge from any artist joint, in the outer wing where none has one. */
#define RF_RIG_WING_ELBOW 0.22
#define RF_RIG_WING_WRIST 0.43

bool rf_rig_is_wing(rf_rig_limb_kind kind, double reach, double legs)
{
    return kind == RF_RIG_LIMB_ARM && legs > 0 && reach > RF_RIG_WING_REACH * legs;
}

void rf_rig_wing_layout(const rf_rig_tpl_layout *l, bool wing, rf_rig_tpl_layout *out)
{
    *out = *l;
    if (wing)
        out->elbow = out->elbow_lo = out->elbow_hi = RF_RIG_WING_ELBOW,
        out->hand = RF_RIG_WING_WRIST;
}

/* A limb to lay out again: where it leaves the body, its first joint, its kind and layout. */
typedef struct rf_rig_limb {
    uint32_t girdle, first;
    uint32_t sec, mirror; /* its analysis section, and its mirror image's */
    rf_rig_limb_kind kind;
    const rf_rig_tpl_layout *lay;
} rf_rig_limb;

/* Whether joint j is joint `top` or below it. */
static bool rf_rig_below(const rf_rig_skel *k, uint32_t j, uint32_t top)
{
    for (int32_t i = (int32_t)j; i >= 0; i = k->parent[i])
        if ((uint32_t)i == top)
            return true;
    return false;
}

/* Length of the tree path from the root to joint j. */
static double rf_rig_from_root(const rf_rig_skel *k, uint32_t j)
{
    double d = 0;
    for (int32_t i = (int32_t)j; k->parent[i] >= 0; i = k->parent[i]) {
        const double *a = k->pos + (size_t)i * 3, *b = k->pos + (size_t)k->parent[i] * 3;
        d += sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                  (a[2] - b[2]) * (a[2] - b[2]));
    }
    return d;
}

/* Whether a joint below `first` stands higher (along up) than joint `girdle`. */
static bool rf_rig_rises(const rf_rig_skel *k, rf_vec3 up, uint32_t girdle, uint32_t first)
{
    const double *g = k->pos + (size_t)girdle * 3;
    double top = g[0] * up.x + g[1] * up.y + g[2] * up.z;
    for (uint32_t j = first + 1; j < k->n; j++) { /* parents come first */
        const double *p = k->pos + (size_t)j * 3;
        if (rf_rig_below(k, j, first) && p[0] * up.x + p[1] * up.y + p[2] * up.z > top)
            return true;
    }
    return false;
}

/* Where limb section `sec` leaves the body: where it meets its mirror image (the hips of two
 * legs leaving the body a band apart), or the joint it hangs from. */
static uint32_t rf_rig_girdle_of(const rf_rig_skel *k, const rf_analysis *a, uint32_t sec)
{
    const rf_section *s = &a->sections[sec];
    uint32_t first = rf_section_joints(a, sec)[0];
    uint32_t g = s->attach_joint >= 0 ? (uint32_t)s->attach_joint : first;
    if (s->mirror >= 0 && a->sections[s->mirror].attach_joint >= 0)
        g = rf_rig_lca(k, g, (uint32_t)a->sections[s->mirror].attach_joint);
    return g;
}

/* How far girdle g lies along `facing`, or with none its distance from the root (which
 * rf_rig_curve puts at the hips): of four legs' girdles the smaller is the hind one. */
static double rf_rig_girdle_ahead(const rf_rig_skel *k, uint32_t g, rf_vec3 facing)
{
    return rf_v3_len(facing) > 0 ? rf_rig_along(k->pos + (size_t)g * 3, facing)
                                 : rf_rig_from_root(k, g);
}

/* The limbs of k the layouts know (rf_rig_tpl_humanoid, rf_rig_tpl_quadruped: fitted to artist
 * rigs), mirrored pairs only (an arm without a mirror image is often the torso and head of a
 * body whose arms merged with it): a biped's longest pair of arms (or wings; a quadruped's
 * "arms" are ears or horns, which keep their own cut), and the legs of a body with two of them
 * or four (a quadruped's forelegs and hind legs; the hind pair's girdle is the one behind along
 * `facing`, the forward the file declares or the one the rigger read, else the one nearer the
 * root, as rf_rig_curve roots the skeleton at the hips).
 * Legs of a body with six or more are left as the curve cut them: no layout was fitted to
 * them. Returns the count. */
static uint32_t rf_rig_limbs_found(const rf_rig_skel *k, const rf_analysis *a, rf_vec3 facing,
                                   const rf_rig_tpl_layout *const lay[2], rf_rig_limb *out)
{
    uint32_t n = 0, legs = 0;
    double arm_len = 0; /* the longest pair of arms: the arms (or wings), not ears or spikes */
    for (uint32_t s = 0; s < a->section_count; s++) {
        const rf_section *sec = &a->sections[s];
        legs += sec->type == RF_SECTION_LEG && sec->side != RF_SIDE_CENTER;
        if (sec->type == RF_SECTION_ARM && sec->mirror >= 0)
            arm_len = fmax(arm_len, sec->length + a->sections[sec->mirror].length);
    }
    /* the hind girdle of four legs: the one behind along the facing (the root may be at
     * either girdle, and the analysis's places along the body count from it: the bull frog's
     * front pair read as hind), else the one nearer the root */
    double hind_at = INFINITY;
    for (uint32_t s = 0; legs == 4 && s < a->section_count; s++)
        if (a->sections[s].type == RF_SECTION_LEG && a->sections[s].side != RF_SIDE_CENTER)
            hind_at = fmin(hind_at, rf_rig_girdle_ahead(k, rf_rig_girdle_of(k, a, s), facing));
    for (uint32_t s = 0; s < a->section_count && n < RF_RIG_MAX_LIMBS; s++) {
        const rf_section *sec = &a->sections[s];
        bool leg = sec->type == RF_SECTION_LEG;
        if ((!leg && sec->type != RF_SECTION_ARM) || sec->mirror < 0 || !sec->bone_count)
            continue;
        if (leg ? legs != 2 && legs != 4
                : legs != 2 || sec->length + a->sections[sec->mirror].length < arm_len)
            continue;
        rf_rig_limb *l = &out[n];
        l->sec = s, l->mirror = (uint32_t)sec->mirror;
        l->first = rf_section_joints(a, s)[0];
        l->girdle = rf_rig_girdle_of(k, a, s);
        if (l->girdle == l->first || !rf_rig_below(k, l->first, l->girdle) ||
            (leg && rf_rig_rises(k, a->up, l->girdle, l->first)))
            continue; /* a limb not hanging below its girdle (the root itself): nothing to lay
                       * it from; a leg carrying what rises above its girdle (a head merged into
                       * a foreleg): kept whole */
        if (!leg) {
            l->kind = RF_RIG_LIMB_ARM, l->lay = lay[0];
        } else if (legs == 2) {
            l->kind = RF_RIG_LIMB_LEG, l->lay = lay[0];
        } else {
            bool hind = rf_rig_girdle_ahead(k, l->girdle, facing) <= hind_at + 1e-9;
            l->kind = hind ? RF_RIG_LIMB_HIND_LEG : RF_RIG_LIMB_FORELEG;
            l->lay = lay[1];
        }
        n++;
    }
    return n;
}

/* Where a pair of laid arms leaving trunk joint g well below their shoulders hangs: the curve
 * skeleton's bands may meet the arms only where a coarse trunk bone starts (a robot's arms hung
 * from its hips' joint, a sixth of its height below where they leave the torso), and laid along
 * the curve from there the elbow took the turn at the shoulder and the whole arm swung from the
 * hips. With y the mean height of the arms' first joints and t its share of the rise of the
 * bone from g to its highest child that is no limb: under a quarter g serves; up to 0.85 a
 * chest joint goes on that bone at y (the bone's child in *split, the point in at[]); beyond,
 * the child serves (in *split). */
typedef enum rf_rig_hang { RF_RIG_HANG_GIRDLE, RF_RIG_HANG_CHEST, RF_RIG_HANG_TOP } rf_rig_hang;

static rf_rig_hang rf_rig_chest(const rf_rig_skel *k, rf_vec3 up, double y, const uint8_t *drop,
                                uint32_t g, uint32_t *split, double at[3])
{
    double rise = y - rf_rig_height(k, g, up), best = 0;
    uint32_t top = g;
    for (uint32_t j = g + 1; j < k->n; j++) /* parents come first */
        if (k->parent[j] == (int32_t)g && !drop[j] &&
            rf_rig_height(k, j, up) - rf_rig_height(k, g, up) > best)
            best = rf_rig_height(k, j, up) - rf_rig_height(k, g, up), top = j;
    double t = best > 0 ? rise / best : 0;
    if (!(t >= 0.25))
        return RF_RIG_HANG_GIRDLE;
    *split = top;
    if (t > 0.85)
        return RF_RIG_HANG_TOP;
    const double *a = k->pos + (size_t)g * 3, *b = k->pos + (size_t)top * 3;
    for (int c = 0; c < 3; c++)
        at[c] = a[c] + t * (b[c] - a[c]);
    return RF_RIG_HANG_CHEST;
}

/* The mean height of the laid arms hung from girdle g: of their first joints on the curve
 * skeleton (lp NULL), or of their clavicles as laid (lp); NAN for fewer than two arms. */
static double rf_rig_arms_height(const rf_rig_skel *k, rf_vec3 up, const rf_rig_limb *limbs,
                                 uint32_t nl, const uint8_t *laid, const double (*lp)[4][3],
                                 uint32_t g)
{
    double y = 0;
    uint32_t arms = 0;
    for (uint32_t i = 0; i < nl; i++)
        if (laid[i] && limbs[i].kind == RF_RIG_LIMB_ARM && limbs[i].girdle == g)
            y += lp ? rf_rig_along(lp[i][0], up) : rf_rig_height(k, limbs[i].first, up), arms++;
    return arms < 2 ? NAN : y / arms;
}

#define RF_RIG_SHOULDER_STEP 0.01 /* of the longest edge, up the trunk */
#define RF_RIG_SHOULDER_REACH 0.4 /* of the longest edge: how far up to look */
#define RF_RIG_SHOULDER_ARMS 0.9  /* of the widest: where the arms have joined the chest */
#define RF_RIG_SHOULDER_NECK 0.5  /* of the widest: the neck above the shoulders */
#define RF_RIG_SHOULDER_JOIN 1.2  /* the widest at least this of the width at the arm's start */
#define RF_RIG_SHOULDER_OUT 0.8   /* of the way out to the shoulder's surface */
#define RF_RIG_SHOULDER_RISE 0.03 /* of the longest edge above the upper arm joint: a move */
#define RF_RIG_SHOULDER_MAX 64    /* steps */
#define RF_RIG_SHOULDER_HANG 0.6  /* drop over reach: an arm lower than 31 degrees under level */

/* The width of the mesh through q along d both ways (first surface each way), and the way
 * along d into *ahead; INFINITY when a ray leaves without meeting it. */
static double rf_rig_width(const rf_rig_surface *sf, const double q[3], rf_vec3 d, double *ahead)
{
    double dp[3] = {d.x, d.y, d.z}, dn[3] = {-d.x, -d.y, -d.z};
    *ahead = rf_rig_surface_hit(sf, q, dp);
    return *ahead + rf_rig_surface_hit(sf, q, dn);
}

/* An arm laid from girdle point g (pos: clavicle, upper arm, elbow, hand) that hangs beside the
 * trunk (its hand lower under its upper arm joint than RF_RIG_SHOULDER_HANG of how far it lies
 * out from it: the girl's arms, 37 degrees under level, left the trunk 0.1 of her height under
 * her artist's shoulders, and the elbow laid half way down that short arm) leaves the trunk
 * below the armpit, where the curve skeleton's bands first part arm from chest, and the layout
 * put clavicle and upper arm there, a tenth of the height or more under the shoulder (the
 * ninja, BCN_Epileptic). The trunk's width across the body (from the line up through g towards
 * the arm, by rays) says where the shoulder is: above the armpit the rays run on into the arms
 * and the width jumps (to RF_RIG_SHOULDER_ARMS of its largest), above the shoulders it falls to
 * the neck's (under RF_RIG_SHOULDER_NECK of it); the shoulder joint lies halfway between, where
 * both artists put it (within 0.01 of the longest edge). The upper arm joint moves there,
 * RF_RIG_SHOULDER_OUT of the way out to the surface, the clavicle on the way out to it where
 * the layout has it against the upper arm (l->shoulder over l->arm), the elbow halfway on to
 * the hand. No jump (the arm held out, its rays running into it from its start) or no neck
 * within reach: nothing moves. */
void rf_rig_shoulder(const rf_rig_surface *sf, double longest, rf_vec3 up, const double g[3],
                     const rf_rig_tpl_layout *l, double pos[4][3])
{
    rf_vec3 out = rf_v3(pos[3][0] - g[0], pos[3][1] - g[1], pos[3][2] - g[2]);
    out = rf_v3_sub(out, rf_v3_scale(up, rf_v3_dot(out, up)));
    rf_vec3 span = rf_v3(pos[3][0] - pos[1][0], pos[3][1] - pos[1][1], pos[3][2] - pos[1][2]);
    double drop = -rf_v3_dot(span, up);
    if (!sf || rf_v3_len(out) < 1e-9 * longest ||
        !(drop >
          RF_RIG_SHOULDER_HANG * rf_v3_len(rf_v3_sub(span, rf_v3_scale(up, rf_v3_dot(span, up))))))
        return; /* no surface, or an arm held out, not hanging */
    rf_vec3 side = rf_v3_normalize(out);
    double hg = rf_rig_along(g, up), from = fmax(hg, rf_rig_along(pos[1], up));
    double w[RF_RIG_SHOULDER_MAX], ahead[RF_RIG_SHOULDER_MAX], widest = 0;
    int n = 0, top = -1;
    for (; n < RF_RIG_SHOULDER_MAX && n * RF_RIG_SHOULDER_STEP <= RF_RIG_SHOULDER_REACH; n++) {
        double q[3], y = from + n * RF_RIG_SHOULDER_STEP * longest;
        for (int c = 0; c < 3; c++)
            q[c] = g[c] + (y - hg) * (c == 0 ? up.x : c == 1 ? up.y : up.z);
        w[n] = rf_rig_width(sf, q, side, &ahead[n]);
        if (!isfinite(w[n]))
            break;
        if (w[n] > widest)
            widest = w[n], top = n;
    }
    int arms = -1, neck = -1;
    for (int i = 0; i <= top && arms < 0; i++)
        arms = w[i] >= RF_RIG_SHOULDER_ARMS * widest ? i : -1;
    for (int i = top + 1; top >= 0 && i < n && neck < 0; i++)
        neck = w[i] < RF_RIG_SHOULDER_NECK * widest ? i : -1;
    if (arms < 0 || neck < 0 || !(widest >= RF_RIG_SHOULDER_JOIN * w[0]))
        return;
    int at = (arms + neck) / 2;
    double y = from + 0.5 * (arms + neck) * RF_RIG_SHOULDER_STEP * longest;
    if (y - rf_rig_along(pos[1], up) < RF_RIG_SHOULDER_RISE * longest)
        return;
    double reach = RF_RIG_SHOULDER_OUT * ahead[at];
    double clavicle = l->arm > 0 ? fmin(l->shoulder / l->arm, 1) : 1; /* as the layout has it */
    for (int c = 0; c < 3; c++) {
        double on = g[c] + (y - hg) * (c == 0 ? up.x : c == 1 ? up.y : up.z);
        double s = c == 0 ? side.x : c == 1 ? side.y : side.z;
        pos[0][c] = on + clavicle * reach * s;
        pos[1][c] = on + reach * s;
        pos[2][c] = 0.5 * (pos[1][c] + pos[3][c]);
    }
}

#define RF_RIG_CROTCH_GAP 0.5 /* the width between the legs against the trunk's above them */
#define RF_RIG_CROTCH_STEPS 40

/* The height where a biped's trunk closes over its legs (the crotch, or the pelvis inside a
 * skirt or robe), walked up from where its legs branch (mid-way between their first joints
 * f0, f1) to its arms' height ya along the line through that mid-point: below it, the rays
 * across the body (between the legs, towards them) meet the legs' inner sides close by; above
 * it they run through the trunk, more than 1 / RF_RIG_CROTCH_GAP times as wide. The curve
 * skeleton parts the legs lower, where the cloth or the thighs part from each other: at the
 * hem of a skirt or robe (the girl, the Wizard, BCN_Epileptic), and a little under the crotch
 * of a slim figure. NAN when the trunk is met at the branch already, or a ray leaves the mesh
 * (a bird's legs under its body). */
static double rf_rig_crotch(const rf_rig_surface *sf, rf_vec3 up, const double f0[3],
                            const double f1[3], double ya)
{
    rf_vec3 side = rf_v3(f1[0] - f0[0], f1[1] - f0[1], f1[2] - f0[2]);
    side = rf_v3_sub(side, rf_v3_scale(up, rf_v3_dot(side, up)));
    double yb = 0.5 * (rf_rig_along(f0, up) + rf_rig_along(f1, up)), ahead, low = INFINITY;
    if (rf_v3_len(side) <= 0 || !(ya > yb))
        return NAN;
    side = rf_v3_normalize(side);
    for (int i = 0; i <= RF_RIG_CROTCH_STEPS; i++) {
        double y = yb + (ya - yb) * i / RF_RIG_CROTCH_STEPS, q[3];
        for (int c = 0; c < 3; c++)
            q[c] = 0.5 * (f0[c] + f1[c]) + (y - yb) * (c == 0 ? up.x : c == 1 ? up.y : up.z);
        double w = rf_rig_width(sf, q, side, &ahead);
        if (!isfinite(w))
            return NAN;
        if (w * RF_RIG_CROTCH_GAP > low)
            return i > 0 ? y : NAN;
        low = fmin(low, w);
    }
    return NAN;
}

#define RF_RIG_HIPS_SHARE 0.58 /* of the shoulders' height over the feet: the lowest hips */

/* The height a biped's hips go no lower than, or NAN: only for two laid legs and arms, on a
 * body without wings (a bird's or a bat's legs hang under a body that closes at once, and its
 * wings are no arms to measure up to). The higher of where its trunk closes over its legs
 * (rf_rig_crotch) and RF_RIG_HIPS_SHARE of the way from its feet to its shoulders, as laid
 * (lp: each limb's joints after rf_rig_shoulder; the arm's second joint, the upper arm's): a
 * trunk that closes low (the ninja's hakama joins between its knees and its hips) still puts
 * the hips where the body's proportions do. The artists' hips of the shared data's wingless
 * bipeds lie at 0.56 to 0.68 of their arms' girdle height, cartoon robot and human alike
 * (doc/autorig-log.md). The legs' indices into leg[]. */
static double rf_rig_hips_at(const rf_rig_surface *sf, rf_vec3 up, const rf_rig_skel *k,
                             const rf_rig_limb *limbs, uint32_t nl, const uint8_t *laid,
                             const double (*lp)[4][3], const double (*tips)[3], uint32_t leg[2])
{
    uint32_t nlegs = 0, narms = 0;
    double ya = 0, ys = 0;
    for (uint32_t i = 0; i < nl; i++) {
        if (!laid[i])
            continue;
        if (limbs[i].kind == RF_RIG_LIMB_ARM) {
            ya += rf_rig_along(k->pos + (size_t)limbs[i].first * 3, up), narms++;
            ys += rf_rig_along(lp[i][1], up);
        } else if (nlegs++ < 2)
            leg[nlegs - 1] = i;
    }
    if (!sf || nlegs != 2 || !narms)
        return NAN;
    double yc = rf_rig_crotch(sf, up, k->pos + (size_t)limbs[leg[0]].first * 3,
                              k->pos + (size_t)limbs[leg[1]].first * 3, ya / narms);
    double feet = 0.5 * (rf_rig_along(tips[leg[0]], up) + rf_rig_along(tips[leg[1]], up));
    double share = feet + RF_RIG_HIPS_SHARE * (ys / narms - feet);
    return isfinite(yc) ? fmax(yc, share) : share;
}

/* A biped's legs laid again when their hips (pos[0]) lie under the height yc where its trunk
 * closes over them: the layout lays the hip a fraction (upleg) down a curve that runs from the
 * legs' girdle straight down inside a skirt to the hem, 0.10 to 0.22 of the longest edge under
 * the artist's hips. The curve is started instead above the girdle, as high as puts the hip at
 * yc on a leg hanging straight to its tip, so hip, knee and ankle spread over the whole leg.
 * That start into start[]; false when the leg is not raised. */
static bool rf_rig_legs_start(const rf_rig_skel *k, rf_vec3 up, const rf_rig_limb *lm, double yc,
                              const double pos[4][3], const double tip[3], double start[3])
{
    double hip = rf_rig_along(pos[0], up), foot = rf_rig_along(tip, up);
    double f = lm->lay->upleg, top = (yc - f * foot) / (1 - f);
    const double *g = k->pos + (size_t)lm->girdle * 3;
    if (!(hip < yc) || !(top > rf_rig_along(g, up)))
        return false;
    for (int c = 0; c < 3; c++)
        start[c] = g[c] + (top - rf_rig_along(g, up)) * (c == 0 ? up.x : c == 1 ? up.y : up.z);
    return true;
}

/* The pair of legs leg[] laid again from their raised starts (rf_rig_legs_start). Each is cut
 * where it reaches past its twin (rf_rig_limb_prop_cut) by their reaches from those starts,
 * not from their girdles: legs pressed together part low in the curve skeleton (random biped
 * 19's at its knees, where one hung from the spine's first joint above the other's), and by
 * their curves up to the fork one reached 1.4 times the other, so raised it was cut off at its
 * knee. False when out of memory. */
static bool rf_rig_legs_raise(const rf_rig_skel *k, rf_vec3 up, const rf_rig_limb *limbs,
                              const uint32_t leg[2], double yc, const double *cuts,
                              double (*lp)[4][3], double (*tips)[3])
{
    double start[2][3], reach[2];
    bool raised[2];
    for (int s = 0; s < 2; s++) {
        const rf_rig_limb *lm = &limbs[leg[s]];
        raised[s] = rf_rig_legs_start(k, up, lm, yc, lp[leg[s]], tips[leg[s]], start[s]);
    }
    if (!raised[0] && !raised[1])
        return true; /* nothing laid again: no reach to measure */
    for (int s = 0; s < 2; s++) {
        const rf_rig_limb *lm = &limbs[leg[s]];
        if (!rf_rig_limb_reach(k, up, lm->girdle, lm->first, lm->kind, raised[s] ? start[s] : NULL,
                               &reach[s]))
            return false;
    }
    for (int s = 0; s < 2; s++) {
        const rf_rig_limb *lm = &limbs[leg[s]];
        double cut = cuts[leg[s]] > 0 ? rf_rig_limb_prop_cut(reach[s], reach[1 - s]) : 0;
        if (raised[s] && !rf_rig_limb_place_within(k, up, lm->girdle, lm->first, lm->kind, lm->lay,
                                                   start[s], cut, lp[leg[s]], tips[leg[s]]))
            return false;
    }
    return true;
}

/* The joint two raised legs hang from (g in o) moved up to their hips' height h0, h1 when it
 * lies below it: the hips laid higher than where the curve skeleton's legs branch (inside a
 * skirt or hakama) would otherwise hang from a pelvis under them, and the bone up from it
 * would carry the thighs' tops. No more than half way up to any child g has already (the
 * legs are hung from it after): the spine stays above it. */
static void rf_rig_pelvis_raise(rf_rig_skel *o, rf_vec3 up, int32_t g, const double h0[3],
                                const double h1[3])
{
    if (g < 0)
        return;
    double *q = o->pos + (size_t)g * 3;
    double rise = 0.5 * (rf_rig_along(h0, up) + rf_rig_along(h1, up)) - rf_rig_along(q, up);
    for (uint32_t j = (uint32_t)g + 1; j < o->n && rise > 0; j++)
        if (o->parent[j] == g)
            rise =
                fmin(rise, 0.5 * (rf_rig_along(o->pos + (size_t)j * 3, up) - rf_rig_along(q, up)));
    if (!(rise > 0))
        return;
    q[0] += rise * up.x, q[1] += rise * up.y, q[2] += rise * up.z;
}

/* Where the arms hang from: the trunk joint chest_g (UINT32_MAX: each its girdle), through a
 * chest joint at `at` on the bone to `split` (chest true) or from `split` itself. */
typedef struct rf_rig_arms_hang {
    uint32_t girdle, split;
    bool chest;
    double at[3];
} rf_rig_arms_hang;

/* The arms' hang read from where their first joints leave the curve skeleton (lp NULL) or, when
 * that put them on their girdle, from their clavicles as laid: an arm hanging beside the trunk
 * leaves it below the armpit, and its shoulder, moved up where it is (rf_rig_shoulder), may lie
 * a good way up the trunk bone above (BCN_Epileptic) or past its top (the ninja). */
static void rf_rig_arms_hang_find(const rf_rig_skel *k, rf_vec3 up, const rf_rig_limb *limbs,
                                  uint32_t nl, const uint8_t *laid, const uint8_t *drop,
                                  const double (*lp)[4][3], rf_rig_arms_hang *h)
{
    if (lp && h->girdle != UINT32_MAX)
        return;
    for (uint32_t i = 0; i < nl; i++) {
        if (!laid[i] || limbs[i].kind != RF_RIG_LIMB_ARM)
            continue;
        uint32_t g = limbs[i].girdle;
        double y = rf_rig_arms_height(k, up, limbs, nl, laid, lp, g);
        rf_rig_hang how =
            isfinite(y) ? rf_rig_chest(k, up, y, drop, g, &h->split, h->at) : RF_RIG_HANG_GIRDLE;
        if (how == RF_RIG_HANG_CHEST || (lp && how == RF_RIG_HANG_TOP)) {
            h->girdle = g, h->chest = how == RF_RIG_HANG_CHEST;
            return;
        }
    }
}

/* o: k's joints not dropped, in k's order, with the chest of h (if any) put before `split`;
 * to[] maps k's joints to o's, *chest is the chest's index or -1. */
static void rf_rig_trunk_copy(const rf_rig_skel *k, const uint8_t *drop, const rf_rig_arms_hang *h,
                              rf_rig_skel *o, int32_t *to, int32_t *chest)
{
    *chest = -1;
    for (uint32_t j = 0; j < k->n; j++) {
        to[j] = -1;
        if (drop[j])
            continue;
        if (h->chest && j == h->split) { /* the chest, on the trunk bone to j */
            *chest = (int32_t)o->n++;
            memcpy(o->pos + (size_t)*chest * 3, h->at, sizeof h->at);
            o->has_tip[*chest] = 0, o->parent[*chest] = to[h->girdle];
        }
        uint32_t i = o->n++;
        to[j] = (int32_t)i;
        memcpy(o->pos + (size_t)i * 3, k->pos + (size_t)j * 3, 3 * sizeof *o->pos);
        memcpy(o->tip + (size_t)i * 3, k->tip + (size_t)j * 3, 3 * sizeof *o->tip);
        o->has_tip[i] = k->has_tip[j];
        o->parent[i] = h->chest && j == h->split ? *chest
                       : k->parent[j] >= 0       ? to[k->parent[j]]
                                                 : -1;
    }
}

/* Which limbs of k get laid: not one inside another limb, nor one whose girdle another limb
 * replaces; drop[] marks every joint the laid limbs replace. */
static void rf_rig_laid_find(const rf_rig_skel *k, const rf_rig_limb *limbs, uint32_t nl,
                             uint8_t *laid, uint8_t *drop)
{
    for (uint32_t i = 0; i < nl; i++) {
        laid[i] = 1;
        for (uint32_t m = 0; m < nl; m++)
            if (limbs[m].first != limbs[i].first &&
                (rf_rig_below(k, limbs[i].girdle, limbs[m].first) ||
                 rf_rig_below(k, limbs[i].first, limbs[m].first)))
                laid[i] = 0;
        if (!laid[i])
            continue;
        drop[limbs[i].first] = 1;
        for (uint32_t j = limbs[i].first + 1; j < k->n; j++) /* parents come first */
            if (k->parent[j] >= 0 && drop[k->parent[j]])
                drop[j] = 1;
    }
}

/* The laid legs' feet read from their soles (rf_rig_feet_soles): the laid legs of a biped's
 * layout (a quadruped's third leg joint is an elbow or a hock), each paired with its mirror
 * image. */
static void rf_rig_feet_laid(const rf_rig_prep *p, rf_vec3 up, const rf_rig_limb *limbs,
                             uint32_t nl, const uint8_t *laid, const uint8_t *is_wing,
                             double (*lp)[4][3], double (*tips)[3])
{
    uint8_t leg[RF_RIG_MAX_LIMBS] = {0};
    int32_t mirror[RF_RIG_MAX_LIMBS];
    for (uint32_t i = 0; i < nl; i++) {
        leg[i] = laid[i] && limbs[i].kind == RF_RIG_LIMB_LEG && !is_wing[i];
        mirror[i] = -1;
        for (uint32_t m = 0; m < nl; m++)
            if (m != i && laid[m] && limbs[m].sec == limbs[i].mirror)
                mirror[i] = (int32_t)m;
    }
    rf_rig_feet f = {.n = nl, .pos = lp, .tip = tips, .leg = leg, .mirror = mirror};
    rf_rig_feet_soles(&p->proxy, up, &f);
}

/* k with each limb's joints (its first joint and all below it) replaced by the four its layout
 * places along the limb's curve, hanging from its girdle (or from a chest joint put on the
 * trunk where a pair of arms leaves it, rf_rig_arms_hang_find). Limbs inside another limb, or
 * whose girdle another limb replaces, stay. */
static bool rf_rig_relay(const rf_rig_prep *p, rf_rig_skel *k, const rf_analysis *a,
                         const rf_rig_limb *limbs, uint32_t nl)
{
    uint32_t n = k->n;
    uint8_t *drop = calloc(n + 1, 1);
    int32_t *to = malloc((n + 1) * sizeof *to);
    rf_rig_skel o = {0};
    size_t cap = (size_t)n + 4 * nl + 2; /* a chest too */
    o.pos = malloc(cap * 3 * sizeof *o.pos), o.tip = calloc(cap * 3, sizeof *o.tip);
    o.parent = malloc(cap * sizeof *o.parent), o.has_tip = calloc(cap, 1);
    bool ok = drop && to && o.pos && o.tip && o.parent && o.has_tip;
    uint8_t laid[RF_RIG_MAX_LIMBS] = {0};
    bool arms = false;
    for (uint32_t i = 0; i < nl; i++)
        arms = arms || limbs[i].kind == RF_RIG_LIMB_ARM;
    rf_rig_surface *sf = p && arms ? rf_rig_surface_make(&p->proxy) : NULL;
    ok = ok && (sf || !(p && arms)); /* without it the shoulders would stay where they are */
    if (ok)
        rf_rig_laid_find(k, limbs, nl, laid, drop);
    rf_rig_arms_hang hang = {.girdle = UINT32_MAX, .split = UINT32_MAX};
    if (ok)
        rf_rig_arms_hang_find(k, a->up, limbs, nl, laid, drop, NULL, &hang);
    const double *chest_at = hang.girdle != UINT32_MAX ? hang.at : NULL;
    double reach[RF_RIG_MAX_LIMBS] = {0};
    for (uint32_t i = 0; ok && i < nl; i++) {
        bool chested =
            chest_at && limbs[i].kind == RF_RIG_LIMB_ARM && limbs[i].girdle == hang.girdle;
        if (laid[i])
            ok = rf_rig_limb_reach(k, a->up, limbs[i].girdle, limbs[i].first, limbs[i].kind,
                                   chested ? chest_at : NULL, &reach[i]);
    }
    double legs = 0; /* the longest laid leg's reach, against which an arm is a wing */
    for (uint32_t i = 0; ok && i < nl; i++)
        if (limbs[i].kind != RF_RIG_LIMB_ARM)
            legs = fmax(legs, reach[i]);
    uint8_t *wing = ok ? calloc(cap, 1) : NULL;
    bool wings = false;
    ok = ok && wing;
    double(*lp)[4][3] = ok ? malloc(nl * sizeof *lp) : NULL; /* each limb's joints, as laid */
    double(*tips)[3] = ok ? malloc(nl * sizeof *tips) : NULL;
    uint8_t is_wing[RF_RIG_MAX_LIMBS] = {0};
    double cuts[RF_RIG_MAX_LIMBS] = {0};
    ok = ok && lp && tips;
    for (uint32_t i = 0; ok && i < nl; i++) {
        if (!laid[i])
            continue;
        double(*pos)[3] = lp[i], cut = 0;
        bool chested =
            chest_at && limbs[i].kind == RF_RIG_LIMB_ARM && limbs[i].girdle == hang.girdle;
        for (uint32_t m = 0; m < nl; m++) /* a limb reaching far past its mirror image's reach */
            if (laid[m] && limbs[m].sec == limbs[i].mirror)
                cut = rf_rig_limb_prop_cut(reach[i], reach[m]);
        double laid_reach = cut > 0 ? fmin(cut, reach[i]) : reach[i];
        cuts[i] = cut;
        is_wing[i] = rf_rig_is_wing(limbs[i].kind, laid_reach, legs);
        wings = wings || is_wing[i];
        rf_rig_tpl_layout wl;
        rf_rig_wing_layout(limbs[i].lay, is_wing[i], &wl);
        if (!rf_rig_limb_place_within(k, a->up, limbs[i].girdle, limbs[i].first, limbs[i].kind, &wl,
                                      chested ? chest_at : NULL, cut, pos, tips[i])) {
            ok = false;
            break;
        }
        if (limbs[i].kind == RF_RIG_LIMB_ARM && sf) /* sf: p given and its surface made */
            rf_rig_shoulder(sf, p->longest, rf_v3_normalize(a->up),
                            chested ? chest_at : k->pos + (size_t)limbs[i].girdle * 3, &wl, pos);
    }
    uint32_t leg[2];
    double yc = ok && !wings
                    ? rf_rig_hips_at(sf, rf_v3_normalize(a->up), k, limbs, nl, laid,
                                     (const double(*)[4][3])lp, (const double(*)[3])tips, leg)
                    : NAN;
    if (isfinite(yc) && ok)
        ok = rf_rig_legs_raise(k, rf_v3_normalize(a->up), limbs, leg, yc, cuts, lp, tips);
    if (ok && p)
        rf_rig_feet_laid(p, a->up, limbs, nl, laid, is_wing, lp, tips);
    if (ok)
        rf_rig_arms_hang_find(k, a->up, limbs, nl, laid, drop, (const double(*)[4][3])lp, &hang);
    int32_t chest = -1;
    if (ok)
        rf_rig_trunk_copy(k, drop, &hang, &o, to, &chest);
    if (ok && isfinite(yc) && limbs[leg[0]].girdle == limbs[leg[1]].girdle)
        rf_rig_pelvis_raise(&o, rf_v3_normalize(a->up), to[limbs[leg[0]].girdle], lp[leg[0]][0],
                            lp[leg[1]][0]);
    for (uint32_t i = 0; ok && i < nl; i++) {
        if (!laid[i])
            continue;
        bool hung = limbs[i].kind == RF_RIG_LIMB_ARM && limbs[i].girdle == hang.girdle;
        int32_t parent = !hung ? to[limbs[i].girdle] : hang.chest ? chest : to[hang.split];
        for (int m = 0; m < 4; m++) {
            uint32_t j = o.n++;
            wing[j] = is_wing[i] && m > 0; /* the clavicle stays with the body */
            memcpy(o.pos + (size_t)j * 3, lp[i][m], sizeof lp[i][m]);
            o.parent[j] = parent, o.has_tip[j] = 0, parent = (int32_t)j;
        }
        memcpy(o.tip + (size_t)parent * 3, tips[i], sizeof tips[i]);
        o.has_tip[parent] = 1;
    }
    free(lp), free(tips);
    rf_vec3 facing = ok && wings ? rf_rig_level_facing(a->up, a) : rf_v3(0, 0, 0);
    if (ok && p && rf_v3_len(facing) > 0)
        ok = rf_rig_skel_chord(p, &o, wing, facing, RF_RIG_WING_EDGE);
    free(drop), free(to), free(wing);
    rf_rig_surface_free(sf);
    if (!ok) {
        rf_rig_skel_free(&o);
        return false;
    }
    rf_rig_skel_free(k);
    *k = o;
    return true;
}

/* Whether joint g is a stalk the curve skeleton ran down inside a thick trunk to where the pair
 * of legs first, twin parts: the two legs its only children, g lower than its parent. Laid from
 * the stalk's foot, the layout's hip went that much down the leg (a box horse's forelegs hung
 * from the bottom of its chest, their hips a quarter of the leg under it, and the stalk's bone
 * carried both thighs' tops). */
static bool rf_rig_is_stalk(const rf_rig_skel *k, rf_vec3 up, uint32_t g, uint32_t first,
                            uint32_t twin)
{
    int32_t p = k->parent[g];
    if (p < 0 || g == first || g == twin ||
        !(rf_rig_height(k, g, up) < rf_rig_height(k, (uint32_t)p, up)))
        return false;
    for (uint32_t j = g + 1; j < k->n; j++) /* parents come first */
        if (k->parent[j] == (int32_t)g && j != first && j != twin)
            return false;
    return true;
}

/* k with every stalk of a mirrored pair of legs (rf_rig_is_stalk) taken out, the legs hung
 * from the joint above it as the curve skeleton hangs them from a slimmer trunk. *cut counts
 * them. False when out of memory. */
static bool rf_rig_stalks_cut(rf_rig_skel *k, const rf_analysis *a, uint32_t *cut)
{
    uint8_t *drop = calloc(k->n + 1, 1);
    int32_t *to = malloc((k->n + 1) * sizeof *to);
    bool ok = drop && to;
    *cut = 0;
    for (uint32_t s = 0; ok && s < a->section_count; s++) {
        const rf_section *sec = &a->sections[s];
        if (sec->type != RF_SECTION_LEG || sec->mirror < 0 || !sec->bone_count ||
            !a->sections[sec->mirror].bone_count)
            continue;
        uint32_t first = rf_section_joints(a, s)[0];
        uint32_t twin = rf_section_joints(a, (uint32_t)sec->mirror)[0];
        uint32_t g = rf_rig_girdle_of(k, a, s);
        if (drop[g] || !rf_rig_is_stalk(k, a->up, g, first, twin))
            continue;
        k->parent[first] = k->parent[twin] = k->parent[g];
        drop[g] = 1, (*cut)++;
    }
    if (ok && *cut)
        rf_rig_drop(k, drop, to);
    free(drop), free(to);
    return ok;
}

/* k as the skeleton analysis reads it for laying limbs, its skeleton into *s (the caller frees
 * both; NULL when out of memory). The file's axes go as hints, and the declared up as fact, not
 * as a hint: the mesh stands on it (the rig's frame has it as y). As a hint it is one vote among
 * the limbs' own, and a pair of wings spread level, sweeping forward a little, outvoted the fire
 * dragon's short legs: the wings were laid as legs and the legs as nothing. Without a declared
 * up the analysis reads it from the limbs. */
static rf_analysis *rf_rig_read_laid(const rf_rig_skel *k, const rf_rig_options *o, rf_skeleton **s)
{
    *s = rf_rig_skeleton(k, NULL);
    if (!*s)
        return NULL;
    (*s)->up = o->up, (*s)->forward = o->forward;
    rf_analysis_options ao = {.up = o->up};
    return rf_analyze(*s, &ao);
}

/* The way the body faces: the file's declared forward, else the one the rigger read. */
static rf_vec3 rf_rig_facing_of(const rf_rig_options *o)
{
    return rf_v3_len(o->forward) > 0 ? o->forward : o->facing;
}

/* The general rigger's limbs cut where artists put the joints of a limb of that kind (the
 * template's fitted layouts), not into even bones: a knee at the leg's bend, the hip joint a
 * little into the leg, one bone for the hand and its fingers. The rest of the curve skeleton
 * (spine, neck, tail, fins, a spider's legs) keeps its even bones. False when out of memory. */
static bool rf_rig_limbs(const rf_rig_prep *p, rf_rig_skel *k, const rf_rig_options *o,
                         const rf_rig_tpl_layout *const lay[2])
{
    rf_skeleton *s;
    rf_analysis *a = rf_rig_read_laid(k, o, &s);
    uint32_t cut = 0;
    bool ok = a && rf_rig_stalks_cut(k, a, &cut);
    if (ok && cut) { /* read again without them */
        rf_analysis_free(a), rf_skeleton_free(s);
        a = rf_rig_read_laid(k, o, &s);
        ok = a != NULL;
    }
    rf_rig_limb limbs[RF_RIG_MAX_LIMBS];
    uint32_t nl = ok ? rf_rig_limbs_found(k, a, rf_rig_facing_of(o), lay, limbs) : 0;
    if (ok && nl)
        ok = rf_rig_relay(p, k, a, limbs, nl);
    rf_analysis_free(a);
    rf_skeleton_free(s);
    return ok;
}

/* The girdle of a body's front legs: of its pairs of legs' girdles, the one furthest along
 * `facing` and the one nearest the head's first joint, when both cues name the same one (a
 * glTF declares +Z forward whichever way the body faces; the analysis may read a tail as the
 * head); for a body with no head (random dragon 12's curve skeleton ends at its chest), the
 * facing's alone when it was read from the body (`read`: no forward declared). -1 when they
 * differ, or for no facing or under four legs. The longest leg's length into *leg_len. */
static int32_t rf_rig_front_girdle(const rf_rig_skel *k, const rf_analysis *a, rf_vec3 facing,
                                   bool read, double *leg_len)
{
    uint32_t legs = 0;
    int32_t ahead = -1, near = -1, head = -1;
    double best = INFINITY;
    *leg_len = 0;
    for (uint32_t s = 0; s < a->section_count && head < 0; s++)
        if (a->sections[s].type == RF_SECTION_HEAD && a->sections[s].bone_count)
            head = (int32_t)rf_section_joints(a, s)[0];
    for (uint32_t s = 0; s < a->section_count; s++) {
        const rf_section *sec = &a->sections[s];
        if (sec->type != RF_SECTION_LEG || sec->side == RF_SIDE_CENTER)
            continue;
        legs++, *leg_len = fmax(*leg_len, sec->length);
        uint32_t g = rf_rig_girdle_of(k, a, s);
        const double *q = k->pos + (size_t)g * 3;
        if (sec->mirror < 0)
            continue;
        if (ahead < 0 || rf_rig_along(q, facing) > rf_rig_along(k->pos + (size_t)ahead * 3, facing))
            ahead = (int32_t)g;
        if (head < 0)
            continue;
        const double *h = k->pos + (size_t)head * 3;
        double d = rf_v3_dist(rf_v3(q[0], q[1], q[2]), rf_v3(h[0], h[1], h[2]));
        if (d < best)
            best = d, near = (int32_t)g;
    }
    if (legs < 4 || !(rf_v3_len(facing) > 0))
        return -1;
    return head >= 0 ? (ahead == near ? ahead : -1) : read ? ahead : -1;
}

/* A pair of wings (arms) on a body of four or more legs, which the limb layouts leave as the
 * curve skeleton has them, hangs from the girdle of the front legs, the shoulders, as wings do
 * (rf_rig_front_girdle): the curve skeleton's bands meet a wing where its membrane reaches the
 * body, which may be the hips' joint (random dragon seed 16's wings hung from its hips), and
 * the skeleton analysis then read them as limbs of the hind girdle and the matcher drove them
 * by the walk's legs, their membranes swinging down through the walk. False when out of
 * memory. */
static bool rf_rig_wings_hang(rf_rig_skel *k, const rf_analysis *a, rf_vec3 facing, bool read)
{
    double leg_len;
    int32_t front = rf_rig_front_girdle(k, a, facing, read, &leg_len);
    if (front < 0)
        return true;
    for (uint32_t s = 0; s < a->section_count; s++) {
        const rf_section *sec = &a->sections[s];
        if (sec->type != RF_SECTION_ARM || sec->mirror <= (int32_t)s || !sec->bone_count ||
            (sec->flags & RF_SECFL_FAN) || !a->sections[sec->mirror].bone_count ||
            !rf_rig_is_wing(RF_RIG_LIMB_ARM, sec->length, leg_len))
            continue; /* ears, horns, spikes: wings reach far past the legs */
        uint32_t f[2] = {rf_section_joints(a, s)[0],
                         rf_section_joints(a, (uint32_t)sec->mirror)[0]};
        int32_t g = k->parent[f[0]];
        /* already on the front girdle, or holding it (no loop is made) */
        if (g < 0 || k->parent[f[1]] != g || g == front || rf_rig_below(k, (uint32_t)front, f[0]) ||
            rf_rig_below(k, (uint32_t)front, f[1]))
            continue;
        k->parent[f[0]] = k->parent[f[1]] = front;
        return rf_rig_reroot(k, 0); /* parents first again (the root is joint 0); one pair */
    }
    return true;
}

/* rf_rig_wings_hang on k as the skeleton analysis reads it, the declared up as fact (as the
 * limbs are read to be laid). False when out of memory. */
static bool rf_rig_wings_placed(rf_rig_skel *k, const rf_rig_options *o)
{
    rf_skeleton *s;
    rf_analysis *a = rf_rig_read_laid(k, o, &s);
    bool ok = a && rf_rig_wings_hang(k, a, rf_rig_facing_of(o), !(rf_v3_len(o->forward) > 0));
    rf_analysis_free(a);
    rf_skeleton_free(s);
    return ok;
}

bool rf_rig_general_place(const rf_rig_prep *p, rf_rig_skel *k, const rf_rig_options *o,
                          const rf_rig_tpl_layout *humanoid, const rf_rig_tpl_layout *quadruped)
{
    const rf_rig_tpl_layout *const lay[2] = {humanoid ? humanoid : &rf_rig_tpl_humanoid,
                                             quadruped ? quadruped : &rf_rig_tpl_quadruped};
    if (!rf_rig_limbs(p, k, o, lay) || !rf_rig_wings_placed(k, o))
        return false;
    if (!rf_rig_dorsal(p, k, o) || !rf_rig_neck(p, k, o) || !rf_rig_head_whole(p, k, o))
        return false;
    rf_skeleton *s = rf_rig_skeleton(k, NULL);
    if (!s)
        return false;
    s->up = o->up, s->forward = o->forward;
    rf_analysis *a = rf_analyze(s, NULL);
    rf_vec3 up = a && rf_v3_len(o->up) > 0 ? rf_v3_normalize(o->up) : a ? a->up : rf_v3(0, 0, 0);
    bool ok = a && rf_rig_bottom(p, k, up) && rf_rig_root_low(p, k, up);
    rf_analysis_free(a);
    rf_skeleton_free(s);
    return ok && rf_rig_root_hind(p, k, o);
}

static bool rf_rig_general_framed(const rf_mesh *mesh, const rf_rig_options *opts,
                                  rf_skeleton **skeleton, rf_mesh **skinned, rf_rig_stats *stats,
                                  rf_rig_progress_fn progress, void *user, char *err,
                                  size_t err_size)
{
    rf_rig_options o = rf_rig_defaults(opts);
    rf_rig_stats st_local, *st = stats ? stats : &st_local;
    memset(st, 0, sizeof *st);
    *skeleton = NULL, *skinned = NULL;
    rf_rig_prep p;
    rf_rig_skel k = {0};
    if (rf_rig_prepare(mesh, &o, &p, st, err, err_size) != RF_RIG_OK)
        return false;
    if (progress)
        progress(user, 0.1);
    bool ok = rf_rig_curve(&p, &o, &k, err, err_size) == RF_RIG_OK;
    /* a body whose file declares no forward faces the way its skeletons on the grid turned
     * every quarter way read, pooled (rf_rig_pooled_facing), not the way one grid's reads: its
     * limbs are laid (which pair of four legs is hind) and the rig named by it */
    if (ok && !(rf_v3_len(o.forward) > 0) && !rf_rig_pooled_facing(&p, &k, &o, &o.facing))
        ok = rf_rig_fail(err, err_size, "out of memory reading the body's facing");
    if (ok && !rf_rig_general_place(&p, &k, &o, NULL, NULL))
        ok = rf_rig_fail(err, err_size, "out of memory laying out the limbs");
    if (ok && progress)
        progress(user, 0.4);
    rf_rig_options named = o;
    if (!(rf_v3_len(o.forward) > 0))
        named.forward = o.facing;
    double *w = NULL;
    uint8_t *boxed = ok ? calloc(k.n + 1, 1) : NULL;
    if (ok && !boxed)
        ok = rf_rig_fail(err, err_size, "out of memory weighting the rig");
    ok = ok && rf_rig_heat(&p, &k, &o, &w, boxed, st, err, err_size);
    if (ok && !rf_rig_prune(&p, &k, boxed, &w))
        ok = rf_rig_fail(err, err_size, "out of memory dropping joints that move no vertex");
    free(boxed);
    rf_skeleton *s = ok ? rf_rig_skeleton(&k, &named) : NULL;
    if (ok && !s)
        ok = rf_rig_fail(err, err_size, "out of memory writing the rig");
    ok = ok && rf_rig_write_skin(mesh, &p, &k, w, s, skinned, st, err, err_size);
    free(w);
    if (ok && progress)
        progress(user, 0.9);
    if (ok)
        *skeleton = s;
    else
        rf_skeleton_free(s);
    rf_rig_skel_free(&k);
    rf_rig_prep_free(&p);
    return ok;
}

bool rf_rig_general(const rf_mesh *mesh, const rf_rig_options *opts, rf_skeleton **skeleton,
                    rf_mesh **skinned, rf_rig_stats *stats, rf_rig_progress_fn progress, void *user,
                    char *err, size_t err_size)
{
    rf_rig_frame f;
    rf_mesh in;
    rf_rig_options o;
    *skeleton = NULL, *skinned = NULL;
    if (!rf_rig_frame_enter(mesh, opts, &f, &in, &o))
        return rf_rig_fail(err, err_size, "out of memory turning a mesh of %u vertices",
                           mesh ? mesh->vertex_count : 0);
    bool ok = rf_rig_general_framed(mesh ? &in : NULL, &o, skeleton, skinned, stats, progress, user,
                                    err, err_size);
    rf_rig_frame_stats(&f, stats);
    rf_rig_frame_leave(&f, mesh, ok ? *skeleton : NULL, ok ? *skinned : NULL);
    return ok;
}

/* ---- a given skeleton ---- */

/* The weighted joints of `s` as a working skeleton in model space (each linked to its nearest
 * weighted ancestor, a leaf's end site as its tip), into k; their skeleton indices into ids. */
static bool rf_rig_from_skeleton(const rf_skeleton *s, const rf_mat4 *world, rf_rig_skel *k,
                                 uint32_t *ids)
{
    uint32_t n = s->joint_count;
    int32_t *at = malloc((size_t)(n + 1) * sizeof *at);
    k->pos = malloc((size_t)(n + 1) * 3 * sizeof *k->pos);
    k->tip = calloc((size_t)(n + 1) * 3, sizeof *k->tip);
    k->parent = malloc((size_t)(n + 1) * sizeof *k->parent);
    k->has_tip = calloc(n + 1, 1);
    k->n = 0;
    if (!at || !k->pos || !k->tip || !k->parent || !k->has_tip) {
        free(at);
        return false;
    }
    for (uint32_t j = 0; j < n; j++) {
        at[j] = -1;
        if (s->joints[j].flags & RF_JOINT_UNWEIGHTED)
            continue;
        int32_t p = s->joints[j].parent;
        while (p >= 0 && at[p] < 0)
            p = s->joints[p].parent; /* parents precede children */
        uint32_t i = k->n++;
        at[j] = (int32_t)i, ids[i] = j;
        k->parent[i] = p >= 0 ? at[p] : -1;
        rf_vec3 o = rf_mat4_point(world[j], rf_v3(0, 0, 0));
        k->pos[i * 3] = o.x, k->pos[i * 3 + 1] = o.y, k->pos[i * 3 + 2] = o.z;
        if (s->joints[j].flags & RF_JOINT_HAS_END_SITE) {
            rf_vec3 t = rf_mat4_point(world[j], s->joints[j].end_site);
            k->tip[i * 3] = t.x, k->tip[i * 3 + 1] = t.y, k->tip[i * 3 + 2] = t.z;
            k->has_tip[i] = 1;
        }
    }
    /* A leaf hanging from a joint whose chain goes on through another child (a leg as one
     * joint on an artist's torso, which also carries the neck) owns the bone from its parent,
     * with or without an end site of its own: an end says how far the leg reaches, not where
     * the torso's region stops (the animalia wolf's legs 84% -> 91% with ends from the skin).
     * A joint whose children are all leaves (a head with ears, a hand with one-joint digits) is
     * the end of its chain and keeps those bones. */
    uint32_t *kids = calloc(k->n + 1, sizeof *kids);
    uint8_t *inner = calloc(k->n + 1, 1), *goes_on = calloc(k->n + 1, 1);
    k->owns_in = calloc(k->n + 1, 1);
    bool ok = kids && inner && goes_on && k->owns_in;
    for (uint32_t i = 0; ok && i < k->n; i++)
        if (k->parent[i] >= 0)
            kids[k->parent[i]]++, inner[k->parent[i]] = 1;
    for (uint32_t i = 0; ok && i < k->n; i++)
        if (k->parent[i] >= 0 && inner[i])
            goes_on[k->parent[i]] = 1;
    for (uint32_t i = 0; ok && i < k->n; i++)
        k->owns_in[i] = k->parent[i] >= 0 && !inner[i] && goes_on[k->parent[i]];
    free(goes_on), free(kids), free(inner), free(at);
    return ok;
}

/* The local axis a skeleton's bones run along, when it keeps to one: DCC tools aim each
 * joint's frame down its bone (Blender +y, 3ds Max +x), so a joint has a child on that axis of
 * its frame, the same axis throughout the file; children off it are branches (legs and a tail
 * off a torso) or an armature's root's offsets. Returns 0..5 (+x, -x, +y, -y, +z, -z) when at
 * least two joints and three in five of those with children have a child on one axis, else -1:
 * frames that say nothing of the bones (identity frames, as BVH leaves them, put legs on -y,
 * the spine on +y and arms on x). A child at its parent's pivot (a helper) says nothing. */
static int rf_rig_bone_axis(const rf_skeleton *s, const rf_mat4 *world)
{
    uint32_t n = s->joint_count, with[6] = {0}, total = 0;
    uint8_t *on = calloc((size_t)n * 6 + 1, 1), *any = calloc(n + 1, 1);
    rf_vec3 lo = rf_v3(INFINITY, INFINITY, INFINITY), hi = rf_v3(-INFINITY, -INFINITY, -INFINITY);
    for (uint32_t j = 0; j < n; j++) {
        rf_vec3 at = rf_mat4_point(world[j], rf_v3(0, 0, 0));
        lo = rf_v3(fmin(lo.x, at.x), fmin(lo.y, at.y), fmin(lo.z, at.z));
        hi = rf_v3(fmax(hi.x, at.x), fmax(hi.y, at.y), fmax(hi.z, at.z));
    }
    double extent = n ? rf_v3_dist(lo, hi) : 0; /* the skeleton's size, wherever it stands */
    for (uint32_t j = 0; on && any && j < n; j++) {
        int32_t p = s->joints[j].parent;
        rf_mat4 inv;
        if (p < 0 || !rf_mat4_invert(world[p], &inv))
            continue;
        rf_vec3 at = rf_mat4_point(world[j], rf_v3(0, 0, 0));
        if (!(rf_v3_dist(at, rf_mat4_point(world[p], rf_v3(0, 0, 0))) > 1e-4 * extent))
            continue;
        rf_vec3 o = rf_mat4_point(inv, at); /* the child in its parent's frame */
        double len = rf_v3_len(o), c[3] = {o.x, o.y, o.z};
        any[p] = 1;
        for (int a = 0; a < 3; a++)
            if (fabs(c[a]) >= 0.999 * len)
                on[(size_t)p * 6 + 2 * a + (c[a] < 0)] = 1;
    }
    for (uint32_t j = 0; on && any && j < n; j++) {
        total += any[j];
        for (int a = 0; a < 6; a++)
            with[a] += on[(size_t)j * 6 + a];
    }
    int best = 0;
    for (int a = 1; a < 6; a++)
        best = with[a] > with[best] ? a : best;
    free(on), free(any);
    return with[best] >= 2 && with[best] >= 0.6 * total ? best : -1;
}

/* Each working joint's bone direction by the skeleton's axis convention (unit, world) into
 * axis[i * 3], zero where the skeleton keeps none. */
static void rf_rig_axes(const rf_skeleton *s, const rf_mat4 *world, const rf_rig_skel *k,
                        const uint32_t *ids, double *axis)
{
    int a = rf_rig_bone_axis(s, world);
    memset(axis, 0, ((size_t)k->n + 1) * 3 * sizeof *axis);
    for (uint32_t i = 0; a >= 0 && i < k->n; i++) {
        double l[3] = {0, 0, 0};
        l[a / 2] = a % 2 ? -1 : 1;
        rf_vec3 d = rf_mat4_dir(world[ids[i]], rf_v3(l[0], l[1], l[2]));
        double len = rf_v3_len(d);
        if (len > 0)
            axis[i * 3] = d.x / len, axis[i * 3 + 1] = d.y / len, axis[i * 3 + 2] = d.z / len;
    }
}

/* Whether skeleton s keeps the model's promise that a parent comes before its child: every
 * walk up the given skeleton (to a weighted ancestor, the world rest pose) relies on it, and a
 * joint its own parent or a parent past the end would loop or read out of bounds. */
static bool rf_rig_check_parents(const rf_skeleton *s, char *err, size_t n)
{
    for (uint32_t j = 0; j < s->joint_count; j++) {
        int32_t p = s->joints[j].parent;
        if (p < -1 || p >= (int32_t)j)
            return rf_rig_fail(err, n,
                               "joint %u has parent %d: expected a parent before its child (or -1 "
                               "for a root)",
                               j, (int)p);
    }
    return true;
}

/* World matrices of the joints: inverses of the given inverse binds, or the rest pose. */
static bool rf_rig_world_of(const rf_skeleton *s, const rf_mat4 *inverse_bind, rf_mat4 *world,
                            char *err, size_t n)
{
    rf_xform *rest = inverse_bind ? NULL : malloc((size_t)(s->joint_count + 1) * sizeof *rest);
    if (!inverse_bind && !rest)
        return rf_rig_fail(err, n, "out of memory");
    if (rest)
        rf_skeleton_world_rest(s, rest);
    for (uint32_t j = 0; j < s->joint_count; j++) {
        if (rest) {
            world[j] = rf_xform_to_mat4(rest[j]);
        } else if (!rf_mat4_invert(inverse_bind[j], &world[j])) {
            free(rest);
            return rf_rig_fail(err, n, "joint %u's inverse bind matrix is singular", j);
        }
        /* a joint at NaN or infinity has no place to heat from (and a NaN ray aborts Embree) */
        rf_vec3 at = rf_mat4_point(world[j], rf_v3(0, 0, 0));
        if (!(rf_v3_isfinite(at) && fabs(at.x) + fabs(at.y) + fabs(at.z) < 1e30)) {
            free(rest);
            return rf_rig_fail(err, n, "joint %u stands at a non-finite or huge position", j);
        }
    }
    free(rest);
    return true;
}

bool rf_rig_bind(const rf_mesh *mesh, const rf_skeleton *skeleton, const rf_mat4 *inverse_bind,
                 const rf_rig_options *opts, rf_mesh **skinned, rf_rig_stats *stats, char *err,
                 size_t err_size)
{
    rf_rig_options o = rf_rig_defaults(opts);
    o.leaf_points_own = true;
    o.given_bones = true;
    rf_rig_stats st_local, *st = stats ? stats : &st_local;
    memset(st, 0, sizeof *st);
    *skinned = NULL;
    uint32_t nj = skeleton->joint_count;
    rf_mat4 *world = malloc((size_t)(nj + 1) * sizeof *world);
    uint32_t *ids = malloc((size_t)(nj + 1) * sizeof *ids);
    rf_rig_skel k = {0};
    rf_rig_prep p;
    double *w = NULL;
    rf_mesh *m = NULL;
    bool prepared = false, ok = world && ids;
    if (!ok)
        rf_rig_fail(err, err_size, "out of memory");
    if (ok && nj > UINT16_MAX) /* skin joint indices are 16-bit */
        ok = rf_rig_fail(err, err_size, "the skeleton has %u joints; at most %u can carry weights",
                         nj, (unsigned)UINT16_MAX);
    ok = ok && rf_rig_check_parents(skeleton, err, err_size) &&
         rf_rig_world_of(skeleton, inverse_bind, world, err, err_size);
    if (ok && !rf_rig_from_skeleton(skeleton, world, &k, ids))
        ok = rf_rig_fail(err, err_size, "out of memory");
    if (ok && !k.n)
        ok = rf_rig_fail(err, err_size, "the skeleton has no joint that may carry weights");
    ok = ok && (prepared = rf_rig_prepare(mesh, &o, &p, st, err, err_size) == RF_RIG_OK);
    /* Artists' leaf joints (a head, a hand, a tail's last joint) move the part of the mesh
     * beyond them, along a bone whose end most formats do not store; heated as points they lost
     * that part to their parent's bone. Given an end along their bone's axis, they keep it. */
    double *axis = ok ? malloc(((size_t)k.n + 1) * 3 * sizeof *axis) : NULL;
    if (ok && !axis)
        ok = rf_rig_fail(err, err_size, "out of memory");
    if (ok)
        rf_rig_axes(skeleton, world, &k, ids, axis);
    if (ok && !rf_rig_leaf_tips(&p, &k, axis))
        ok = rf_rig_fail(err, err_size, "out of memory");
    free(axis);
    ok = ok && rf_rig_heat(&p, &k, &o, &w, NULL, st, err, err_size);
    m = ok ? rf_rig_mesh_copy(mesh) : NULL;
    if (ok && (!m || !rf_rig_skin(mesh, &p, &k, w, m, st)))
        ok = rf_rig_fail(err, err_size, "out of memory writing the skin");
    if (ok) {
        /* back to the skeleton's joint indices and the pose it was given in */
        for (size_t i = 0; i < (size_t)m->vertex_count * 4; i++)
            m->skin_joints[i] = (uint16_t)ids[m->skin_joints[i]];
        rf_mat4 *inv = realloc(m->inverse_bind, (size_t)(nj + 1) * sizeof *inv);
        if (inv) {
            m->inverse_bind = inv;
            for (uint32_t j = 0; j < nj; j++)
                if (inverse_bind)
                    inv[j] = inverse_bind[j];
                else if (!rf_mat4_invert(world[j], &inv[j])) /* a rest pose is rigid */
                    inv[j] = rf_xform_to_mat4(rf_xform_identity());
            m->bind_count = nj;
        }
        ok = inv != NULL;
        if (!ok)
            rf_rig_fail(err, err_size, "out of memory writing the skin");
    }
    st->joints = k.n;
    if (ok)
        *skinned = m;
    else
        rf_mesh_free(m);
    free(w), free(world), free(ids);
    rf_rig_skel_free(&k);
    if (prepared)
        rf_rig_prep_free(&p);
    return ok;
}
