/* Measures of what a person sees: the character's mesh skinned by a clip (linear blend skinning,
 * on frames spread over the clip so the measure stays cheap) for torn limbs (vertices close at
 * rest that follow different joints drifting apart), the floor (the lowest vertex against the
 * rest floor; parts high at rest going under it) and stretch (edges against their rest length).
 * Any clip for the skeleton can be measured, so a character's own clips give the reference. */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "rt-internal.h"

#define RT_MESH_MAX_SEAMS 40000u
#define RT_MESH_MAX_EDGES 40000u
/* Vertices more than this fraction of the mesh's height over its lowest at rest are parts high
 * at rest (wings, tails, heads, a quadruped's chest): not what the character stands on. */
#define RT_MESH_HIGH 0.15
/* A part with fewer edges than this is not measured alone (rf_rt_mesh_report's parts). */
#define RT_PART_MIN_EDGES 12u
/* ... nor a pair of parts with fewer seams than this (rf_rt_mesh_report's seam_parts). */
#define RT_SEAM_MIN_PAIRS 4u

typedef struct rt_mesh_work {
    const rf_skeleton *s;
    const rf_mesh *m;
    uint32_t n, nv;
    rf_vec3 up;
    rf_mat4 *ibind;  /* [n] model space to joint space at bind time */
    rf_mat4 *skin;   /* [n] this pose's skinning matrices */
    rf_xform *local; /* [n] */
    rf_xform *world; /* [n] */
    rf_vec3 *rest;   /* [nv] the mesh skinned in the skeleton's rest pose */
    rf_vec3 *pos;    /* [nv] this frame's */
    uint32_t *seam;  /* [seams * 2] */
    uint32_t seams;
    uint32_t *edge; /* [edges * 2] */
    uint32_t edges;
    const double *expect; /* [sampled frame] how far over the floor the source is, scaled to the
                           * target (a jump), or NULL: the floor figures count from there */
    /* A node tree's rigid meshes (rt_mesh_check): the points also hold every joint that counts
     * (`counts`, NULL: all) and its bone's tip (`tip`, in its frame, zero: none) after the
     * mesh's vertices, and only the floor is measured. */
    bool rigid;
    const uint8_t *counts;
    const rf_vec3 *tip;
} rt_mesh_work;

static int rt_cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The k-th smallest of `count` values (reordered around it): Hoare's selection, linear on
 * average, where sorting a million drifts was most of the measure's time. */
double rf_rt_select(double *v, size_t count, size_t k)
{
    ptrdiff_t lo = 0, hi = (ptrdiff_t)count - 1, kk = (ptrdiff_t)k;
    while (lo < hi) {
        double pivot = v[lo + (hi - lo) / 2];
        ptrdiff_t i = lo, j = hi;
        while (i <= j) {
            while (v[i] < pivot)
                i++;
            while (v[j] > pivot)
                j--;
            if (i <= j) {
                double t = v[i];
                v[i++] = v[j], v[j--] = t;
            }
        }
        if (kk <= j)
            hi = j;
        else if (kk >= i)
            lo = i;
        else
            break; /* between the halves: equal to the pivot */
    }
    return v[kk];
}

/* The q-quantile of `count` values (reordered); 0 without values. */
static double rt_quantile(double *v, size_t count, double q)
{
    return count ? rf_rt_select(v, count, (size_t)(q * (double)(count - 1))) : 0;
}

/* The largest of `count` values, 0 without values. */
static double rt_max(const double *v, size_t count)
{
    double m = 0;
    for (size_t i = 0; i < count; i++)
        m = fmax(m, v[i]);
    return m;
}

static void rt_mw_free(rt_mesh_work *w)
{
    free(w->ibind), free(w->skin), free(w->local), free(w->world), free(w->rest), free(w->pos);
    free(w->seam), free(w->edge);
}

static void rt_mesh_fk(rt_mesh_work *w)
{
    for (uint32_t j = 0; j < w->n; j++) {
        int32_t p = w->s->joints[j].parent;
        w->world[j] = p < 0 ? w->local[j] : rf_xform_mul(w->world[p], w->local[j]);
    }
}

/* Skins the mesh in the pose held by w->world into `out`. */
static void rt_mesh_skin(rt_mesh_work *w, rf_vec3 *out)
{
    rf_skin_matrices(w->world, w->ibind, w->n, w->skin);
    for (uint32_t v = 0; v < w->m->vertex_count; v++)
        out[v] = rf_mesh_skin_vertex(w->m, w->skin, v);
    /* The joints and tips after the vertices (rigid: w->nv counts them); a joint that does not
     * count (a placement root) repeats the first vertex instead. */
    for (uint32_t j = 0, v = w->m->vertex_count; w->rigid && j < w->n; j++, v += 2) {
        bool counts = !w->counts || w->counts[j], tip = w->tip && rf_v3_len2(w->tip[j]) > 0;
        out[v] = counts ? w->world[j].t : out[0];
        out[v + 1] = counts && tip ? rf_xform_point(w->world[j], w->tip[j]) : out[v];
    }
}

int rf_rt_cmp_cell(const void *a, const void *b)
{
    uint64_t x = ((const rf_rt_cell *)a)->key, y = ((const rf_rt_cell *)b)->key;
    return (x > y) - (x < y);
}

static uint64_t rt_cell_key(int64_t x, int64_t y, int64_t z)
{
    return ((uint64_t)(x & 0x1fffff) << 42) | ((uint64_t)(y & 0x1fffff) << 21) |
           (uint64_t)(z & 0x1fffff);
}

/* The rest mesh's vertex normals (area-weighted, unit; zero on a vertex of no area) into n. */
static void rt_mesh_normals(const rt_mesh_work *w, rf_vec3 *n)
{
    for (uint32_t v = 0; v < w->nv; v++)
        n[v] = rf_v3(0, 0, 0);
    for (size_t t = 0; t < w->m->triangle_count; t++) {
        const uint32_t *i = w->m->triangles + t * 3;
        if (i[0] >= w->nv || i[1] >= w->nv || i[2] >= w->nv)
            continue;
        rf_vec3 f = rf_v3_cross(rf_v3_sub(w->rest[i[1]], w->rest[i[0]]),
                                rf_v3_sub(w->rest[i[2]], w->rest[i[0]]));
        for (int k = 0; k < 3; k++)
            n[i[k]] = rf_v3_add(n[i[k]], f);
    }
    for (uint32_t v = 0; v < w->nv; v++)
        n[v] = rf_v3_len(n[v]) > 0 ? rf_v3_normalize(n[v]) : n[v];
}

/* Below this cosine between their normals, two vertices close at rest face each other: two
 * surfaces touching (a hand hanging against the thigh, knees together), not one surface cut
 * into parts (a seam's split vertices, a sleeve over an arm face the same way). They part as
 * the limbs move, and counted as seams BCN_Epileptic, its hands against its thighs at rest, read
 * torn limbs p99 17.9% of its height under the CMU walk, nothing torn in its renders. */
#define RT_SEAM_FACING -0.5

/* Seams: pairs of vertices within 1% of the height at rest whose dominant joints differ and that
 * do not face each other (RT_SEAM_FACING), found through a grid of that cell size (the 27 cells
 * around each vertex). */
static bool rt_mesh_seams(rt_mesh_work *w, double height)
{
    double eps = 0.01 * height;
    rf_rt_cell *cells = malloc((w->nv ? w->nv : 1) * sizeof *cells);
    rf_vec3 *normal = malloc((w->nv ? w->nv : 1) * sizeof *normal);
    w->seam = malloc(RT_MESH_MAX_SEAMS * 2 * sizeof *w->seam);
    if (!cells || !normal || !w->seam) {
        free(cells), free(normal);
        return false;
    }
    rt_mesh_normals(w, normal);
    for (uint32_t v = 0; v < w->nv; v++) {
        rf_vec3 p = w->rest[v];
        cells[v].key = rt_cell_key((int64_t)floor(p.x / eps), (int64_t)floor(p.y / eps),
                                   (int64_t)floor(p.z / eps));
        cells[v].v = v;
    }
    qsort(cells, w->nv, sizeof *cells, rf_rt_cmp_cell);
    for (uint32_t i = 0; i < w->nv && w->seams < RT_MESH_MAX_SEAMS; i++) {
        uint32_t a = cells[i].v, ja = rf_mesh_heaviest_joint(w->m, a);
        rf_vec3 p = w->rest[a];
        int64_t cx = (int64_t)floor(p.x / eps), cy = (int64_t)floor(p.y / eps),
                cz = (int64_t)floor(p.z / eps);
        for (int d = 0; d < 27 && w->seams < RT_MESH_MAX_SEAMS; d++) {
            rf_rt_cell probe = {rt_cell_key(cx + d % 3 - 1, cy + d / 3 % 3 - 1, cz + d / 9 - 1), 0};
            rf_rt_cell *hit = bsearch(&probe, cells, w->nv, sizeof *cells, rf_rt_cmp_cell);
            while (hit && hit > cells && hit[-1].key == probe.key)
                hit--;
            for (; hit && hit < cells + w->nv && hit->key == probe.key; hit++) {
                uint32_t b = hit->v;
                if (b <= a || rf_mesh_heaviest_joint(w->m, b) == ja ||
                    rf_v3_dist(p, w->rest[b]) > eps ||
                    rf_v3_dot(normal[a], normal[b]) < RT_SEAM_FACING)
                    continue;
                w->seam[w->seams * 2] = a, w->seam[w->seams * 2 + 1] = b;
                if (++w->seams == RT_MESH_MAX_SEAMS)
                    break;
            }
        }
    }
    free(cells), free(normal);
    return true;
}

/* Edges of the triangles, one in `stride` when there are many. */
static bool rt_mesh_edges(rt_mesh_work *w, double height)
{
    const rf_mesh *m = w->m;
    size_t total = (size_t)m->triangle_count * 3;
    size_t stride =
        total > RT_MESH_MAX_EDGES ? (total + RT_MESH_MAX_EDGES - 1) / RT_MESH_MAX_EDGES : 1;
    w->edge = malloc((RT_MESH_MAX_EDGES + 1) * 2 * sizeof *w->edge);
    if (!w->edge)
        return false;
    for (size_t e = 0; e < total && w->edges < RT_MESH_MAX_EDGES; e += stride) {
        const uint32_t *t = m->triangles + e / 3 * 3;
        uint32_t a = t[e % 3], b = t[(e + 1) % 3];
        if (a >= w->nv || b >= w->nv || rf_v3_dist(w->rest[a], w->rest[b]) <= 1e-6 * height)
            continue;
        w->edge[w->edges * 2] = a, w->edge[w->edges * 2 + 1] = b;
        w->edges++;
    }
    return true;
}

/* Whether the mesh can be measured with the clip: 1 when it can, 0 when it cannot (err says why),
 * -1 out of memory. A mesh hung on too few joints to stand for the body is refused, or, when
 * `rigid` is given, taken as a node tree's rigid parts (*rigid). */
static int rt_mesh_check(const rf_skeleton *s, const rf_mesh *m, const rf_animation *a, bool *rigid,
                         char *err, size_t err_size)
{
    if (rigid)
        *rigid = false;
    if (!m || !m->vertex_count || !m->positions || !m->skin_joints || !m->skin_weights) {
        rf_rt_fail(err, err_size, "the mesh is not skinned");
        return 0;
    }
    if (!a || a->joint_count != s->joint_count || !a->frame_count) {
        rf_rt_fail(err, err_size, "the clip measured on the mesh does not fit its skeleton");
        return 0;
    }
    if (m->inverse_bind && m->bind_count != s->joint_count) {
        rf_rt_fail(err, err_size, "the mesh is bound to %u joints, the skeleton has %u",
                   m->bind_count, s->joint_count);
        return 0;
    }
    uint8_t *used = calloc(s->joint_count ? s->joint_count : 1, 1);
    if (!used) {
        rf_rt_fail(err, err_size, "out of memory");
        return -1;
    }
    uint32_t skinned = 0;
    for (size_t i = 0; i < (size_t)m->vertex_count * RF_MESH_MAX_INFLUENCES; i++) {
        if (!(m->skin_weights[i] > 0))
            continue;
        if (m->skin_joints[i] >= s->joint_count) {
            rf_rt_fail(err, err_size, "vertex %zu is weighted to joint %u of %u", i / 4,
                       m->skin_joints[i], s->joint_count);
            free(used);
            return 0;
        }
        skinned += !used[m->skin_joints[i]], used[m->skin_joints[i]] = 1;
    }
    free(used);
    /* A mesh hung on a node or two (a node tree's rigid parts) does not stand for the body. */
    if (skinned < 2 || skinned * 4 < s->joint_count) {
        if (rigid)
            return *rigid = true, 1;
        rf_rt_fail(err, err_size,
                   "the mesh is skinned to %u of the %u joints, too few to stand for "
                   "the body",
                   skinned, s->joint_count);
        return 0;
    }
    return 1;
}

static bool rt_mesh_prepare(rt_mesh_work *w)
{
    size_t n = w->n ? w->n : 1, nv = w->nv;
    w->ibind = malloc(n * sizeof *w->ibind), w->skin = malloc(n * sizeof *w->skin);
    w->local = malloc(n * sizeof *w->local), w->world = malloc(n * sizeof *w->world);
    w->rest = malloc(nv * sizeof *w->rest), w->pos = malloc(nv * sizeof *w->pos);
    if (!w->ibind || !w->skin || !w->local || !w->world || !w->rest || !w->pos)
        return false;
    for (uint32_t j = 0; j < w->n; j++)
        w->local[j] = w->s->joints[j].rest;
    rt_mesh_fk(w);
    for (uint32_t j = 0; j < w->n; j++)
        if (!w->m->inverse_bind && !rf_mat4_invert(rf_xform_to_mat4(w->world[j]), &w->ibind[j]))
            w->ibind[j] = rf_mat4_identity();
    if (w->m->inverse_bind)
        memcpy(w->ibind, w->m->inverse_bind, w->n * sizeof *w->ibind);
    rt_mesh_skin(w, w->rest);
    return true;
}

/* Per frame figures: the lowest vertex, the lowest vertex of the parts high at rest, and the
 * drift of every seam and stretch of every edge into the caller's arrays. */
static void rt_mesh_frame(rt_mesh_work *w, double height, double floor_h, const uint8_t *high,
                          double *low, double *part_low, double *drift, double *stretch)
{
    *low = INFINITY, *part_low = INFINITY;
    for (uint32_t v = 0; v < w->nv; v++) {
        double h = rf_v3_dot(w->pos[v], w->up);
        *low = fmin(*low, h);
        if (high[v])
            *part_low = fmin(*part_low, h);
    }
    *low = (*low - floor_h) / height;
    *part_low = isfinite(*part_low) ? (*part_low - floor_h) / height : 0;
    for (uint32_t i = 0; i < w->seams; i++) {
        uint32_t a = w->seam[i * 2], b = w->seam[i * 2 + 1];
        double d0 = rf_v3_dist(w->rest[a], w->rest[b]), d = rf_v3_dist(w->pos[a], w->pos[b]);
        drift[i] = fabs(d - d0) / height;
    }
    for (uint32_t i = 0; i < w->edges; i++) {
        uint32_t a = w->edge[i * 2], b = w->edge[i * 2 + 1];
        stretch[i] =
            fabs(rf_v3_dist(w->pos[a], w->pos[b]) / rf_v3_dist(w->rest[a], w->rest[b]) - 1);
    }
}

/* The part vertex v belongs to: the joint carrying it most, or w->n for a vertex without weights
 * (not measured). */
static uint32_t rt_part_of(const rt_mesh_work *w, uint32_t v)
{
    uint32_t j = rf_mesh_heaviest_joint(w->m, v);
    return j < w->n ? j : w->n;
}

static void rt_swap_weighted(rf_rt_weighted *a, rf_rt_weighted *b)
{
    rf_rt_weighted t = *a;
    *a = *b, *b = t;
}

/* By selection, as rf_rt_select (sorting every part's edges over every frame would cost what
 * the whole measure costs): the range left holds the answer, `below` weighs what lies before it,
 * and each pass splits the range three ways about a pivot. */
double rf_rt_weighted_quantile(rf_rt_weighted *v, size_t count, double q)
{
    double total = 0, below = 0;
    for (size_t i = 0; i < count; i++)
        total += v[i].weight;
    double target = q * total;
    size_t lo = 0, hi = count;
    while (lo < hi) {
        double pivot = v[lo + (hi - lo) / 2].value, less = 0, same = 0;
        size_t lt = lo, i = lo, gt = hi;
        while (i < gt) {
            if (v[i].value < pivot)
                less += v[i].weight, rt_swap_weighted(&v[lt++], &v[i++]);
            else if (v[i].value > pivot)
                rt_swap_weighted(&v[i], &v[--gt]);
            else
                same += v[i++].weight;
        }
        if (lt > lo && below + less >= target)
            hi = lt;
        else if (below + less + same >= target || gt == hi)
            return pivot; /* or rounding left the whole short of the target: the largest */
        else
            below += less + same, lo = gt;
    }
    return 0; /* no values */
}

/* The edges of each part: list[start[j] .. start[j + 1]) are part j's (an edge in the part of
 * each of its ends), part w->n holding those of vertices without weights. *most gets the edges
 * of the largest part. Arrays the caller frees, or false when memory runs out. */
static bool rt_parts_list(const rt_mesh_work *w, uint32_t **start_out, uint32_t **list_out,
                          uint32_t *most)
{
    uint32_t *start = calloc((size_t)w->n + 2, sizeof *start);
    uint32_t *fill = malloc(((size_t)w->n + 1) * sizeof *fill);
    uint32_t *list = malloc(((size_t)w->edges * 2 + 1) * sizeof *list);
    bool ok = start && fill && list;
    for (uint32_t i = 0; ok && i < w->edges; i++) {
        uint32_t ja = rt_part_of(w, w->edge[i * 2]), jb = rt_part_of(w, w->edge[i * 2 + 1]);
        start[ja + 1]++;
        start[jb + 1] += jb != ja;
    }
    *most = 0;
    for (uint32_t j = 0; ok && j < w->n; j++)
        *most = start[j + 1] > *most ? start[j + 1] : *most;
    for (uint32_t j = 0; ok && j <= w->n; j++)
        start[j + 1] += start[j], fill[j] = start[j];
    for (uint32_t i = 0; ok && i < w->edges; i++) {
        uint32_t ja = rt_part_of(w, w->edge[i * 2]), jb = rt_part_of(w, w->edge[i * 2 + 1]);
        list[fill[ja]++] = i;
        if (jb != ja)
            list[fill[jb]++] = i;
    }
    free(fill);
    if (!ok)
        free(start), free(list), start = list = NULL;
    *start_out = start, *list_out = list;
    return ok;
}

/* The worst part's stretch (rf_rt_mesh_report's parts): each part's p99 over its edges and all
 * frames (`stretch`, [frame][edge]), each edge counting by its rest length: how much of the
 * part's outline stretches, as the eye sees it. Unweighted, the short edges of the ring where two
 * bones' weights blend (a thin leg's knee: 1.8 units of an 80-unit spider.obj stretched to 6.3)
 * made a limb that looks whole the worst. */
static bool rt_mesh_parts(const rt_mesh_work *w, const double *stretch, uint32_t frames,
                          rf_rt_mesh_report *r)
{
    uint32_t *start, *list, most;
    if (!rt_parts_list(w, &start, &list, &most))
        return false;
    rf_rt_weighted *vals = malloc(((size_t)most * frames + 1) * sizeof *vals);
    for (uint32_t j = 0; vals && j < w->n; j++) {
        uint32_t count = start[j + 1] - start[j];
        if (count < RT_PART_MIN_EDGES)
            continue;
        size_t k = 0;
        for (uint32_t e = start[j]; e < start[j + 1]; e++) {
            uint32_t a = w->edge[list[e] * 2], b = w->edge[list[e] * 2 + 1];
            double len = rf_v3_dist(w->rest[a], w->rest[b]);
            for (uint32_t f = 0; f < frames; f++, k++)
                vals[k].value = stretch[(size_t)f * w->edges + list[e]], vals[k].weight = len;
        }
        double p = rf_rt_weighted_quantile(vals, k, 0.99);
        if (!r->parts || p > r->part_stretch_p99)
            r->part_stretch_p99 = p, r->part_joint = j, r->part_edges = count;
        r->parts++;
    }
    bool ok = vals != NULL;
    free(start), free(list), free(vals);
    return ok;
}

/* The worst pair of parts' torn-limb figure (rf_rt_mesh_report's seam_parts): the seams
 * sorted by the two joints carrying their ends most, then each group's p99 over its seams and
 * all frames (`drift`, [frame][seam]). */
static bool rt_mesh_seam_parts(const rt_mesh_work *w, const double *drift, uint32_t frames,
                               rf_rt_mesh_report *r)
{
    rf_rt_cell *by = malloc(((size_t)w->seams + 1) * sizeof *by);
    double *vals = malloc(((size_t)w->seams * frames + 1) * sizeof *vals);
    bool ok = by && vals;
    for (uint32_t i = 0; ok && i < w->seams; i++) {
        uint64_t a = rt_part_of(w, w->seam[i * 2]), b = rt_part_of(w, w->seam[i * 2 + 1]);
        by[i].key = a < b ? a << 32 | b : b << 32 | a;
        by[i].v = i;
    }
    if (ok)
        qsort(by, w->seams, sizeof *by, rf_rt_cmp_cell);
    for (uint32_t i = 0, end = 0; ok && i < w->seams; i = end) {
        for (end = i; end < w->seams && by[end].key == by[i].key; end++)
            ;
        uint32_t a = (uint32_t)(by[i].key >> 32), b = (uint32_t)by[i].key;
        if (end - i < RT_SEAM_MIN_PAIRS || a >= w->n || b >= w->n)
            continue;
        size_t k = 0;
        for (uint32_t f = 0; f < frames; f++)
            for (uint32_t s = i; s < end; s++)
                vals[k++] = drift[(size_t)f * w->seams + by[s].v];
        double p = rt_quantile(vals, k, 0.99);
        if (!r->seam_parts || p > r->seam_part_p99) {
            r->seam_part_p99 = p, r->seam_part_seams = end - i;
            r->seam_joints[0] = a, r->seam_joints[1] = b;
        }
        r->seam_parts++;
    }
    free(by), free(vals);
    return ok;
}

/* The floor figures from the per-frame lowest points. */
static void rt_mesh_floor(rf_rt_mesh_report *r, double *low, const double *part_low,
                          uint32_t frames)
{
    uint32_t below = 0;
    double depth = 0;
    for (uint32_t i = 0; i < frames; i++) {
        r->floating += low[i] > 0.03;
        r->sinking += low[i] < -0.03;
        below += part_low[i] < -0.01;
        depth = fmax(depth, -part_low[i]);
    }
    r->floating /= frames, r->sinking /= frames;
    r->parts_below = (double)below / frames;
    r->parts_depth = depth;
    r->floor_median = rt_quantile(low, frames, 0.5);
    for (uint32_t i = 0; i < frames; i++)
        low[i] = fabs(low[i]);
    r->floor_p95 = rt_quantile(low, frames, 0.95);
}

/* The worst solid part's volume figure (rf_rt_mesh_report's volume_*): each part's p95 over
 * the frames of `off` ([frame][part], rf_rt_volumes_at). */
static bool rt_mesh_volumes(const rf_rt_volumes *v, double *off, uint32_t frames,
                            rf_rt_mesh_report *r)
{
    double *vals = malloc(((size_t)frames + 1) * sizeof *vals);
    for (uint32_t p = 0; vals && p < v->parts; p++) {
        if (!v->keep[p])
            continue;
        for (uint32_t f = 0; f < frames; f++)
            vals[f] = off[(size_t)f * v->parts + p];
        double q = rt_quantile(vals, frames, 0.95);
        if (!r->volume_parts || q > r->volume_p95)
            r->volume_p95 = q, r->volume_joint = v->joint[p];
        r->volume_parts++;
    }
    free(vals);
    return vals != NULL;
}

static bool rt_mesh_run(rt_mesh_work *w, const rf_animation *anim, uint32_t frames,
                        rf_rt_mesh_report *r)
{
    double lo = INFINITY, hi = -INFINITY;
    for (uint32_t v = 0; v < w->nv; v++) {
        double h = rf_v3_dot(w->rest[v], w->up);
        lo = fmin(lo, h), hi = fmax(hi, h);
    }
    double height = hi > lo ? hi - lo : 1;
    r->height = height;
    uint8_t *high = malloc(w->nv);
    double *low = malloc(frames * sizeof *low), *part_low = malloc(frames * sizeof *part_low);
    bool ok = high && low && part_low &&
              (w->rigid || (rt_mesh_seams(w, height) && rt_mesh_edges(w, height)));
    double *drift = ok ? malloc(((size_t)w->seams * frames + 1) * sizeof *drift) : NULL;
    double *stretch = ok ? malloc(((size_t)w->edges * frames + 1) * sizeof *stretch) : NULL;
    rf_rt_volumes vol = {0};
    ok = ok && drift && stretch &&
         (w->rigid || rf_rt_volumes_find(w->m, w->rest, w->n, height, &vol));
    double *off = ok ? malloc(((size_t)vol.parts * frames + 1) * sizeof *off) : NULL;
    ok = ok && off;
    for (uint32_t v = 0; ok && v < w->nv; v++)
        high[v] = rf_v3_dot(w->rest[v], w->up) > lo + RT_MESH_HIGH * height;
    for (uint32_t i = 0; ok && i < frames; i++) {
        uint32_t f =
            frames > 1 ? (uint32_t)((uint64_t)i * (anim->frame_count - 1) / (frames - 1)) : 0;
        rf_animation_local_pose(anim, w->s, f, w->local);
        for (uint32_t j = 0; j < w->n; j++)
            w->local[j].r = rf_quat_normalize(w->local[j].r);
        rt_mesh_fk(w);
        rt_mesh_skin(w, w->pos);
        rt_mesh_frame(w, height, lo, high, &low[i], &part_low[i], drift + (size_t)i * w->seams,
                      stretch + (size_t)i * w->edges);
        rf_rt_volumes_at(&vol, w->m, w->pos, off + (size_t)i * vol.parts);
        if (w->expect)
            low[i] -= w->expect[i] / height;
    }
    if (ok) {
        r->frames = frames, r->seams = w->seams, r->edges = w->edges, r->rigid = w->rigid;
        rt_mesh_floor(r, low, part_low, frames);
        size_t ns = (size_t)w->seams * frames;
        r->seam_max = rt_max(drift, ns);
        ok = w->rigid || rt_mesh_seam_parts(w, drift, frames, r);
        r->seam_p99 = rt_quantile(drift, ns, 0.99);
        ok = ok && (w->rigid || rt_mesh_parts(w, stretch, frames, r));
        r->stretch_p99 = rt_quantile(stretch, (size_t)w->edges * frames, 0.99);
        ok = ok && rt_mesh_volumes(&vol, off, frames, r);
    }
    free(high), free(low), free(part_low), free(drift), free(stretch), free(off);
    rf_rt_volumes_free(&vol);
    return ok;
}

bool rf_rt_mesh_measure(const rf_skeleton *skeleton, const rf_mesh *mesh, const rf_animation *anim,
                        rf_vec3 up, uint32_t max_frames, rf_rt_mesh_report *report, char *err,
                        size_t err_size)
{
    memset(report, 0, sizeof *report);
    if (rt_mesh_check(skeleton, mesh, anim, NULL, err, err_size) <= 0)
        return false;
    rt_mesh_work w = {.s = skeleton, .m = mesh, .n = skeleton->joint_count};
    w.nv = mesh->vertex_count;
    w.up = rf_v3_len2(up) > 0               ? rf_v3_normalize(up)
           : rf_v3_len2(skeleton->up) > 0.5 ? rf_v3_normalize(skeleton->up)
                                            : rf_v3(0, 1, 0);
    uint32_t frames = max_frames ? max_frames : 24;
    frames = frames < anim->frame_count ? frames : anim->frame_count;
    bool ok = rt_mesh_prepare(&w) && rt_mesh_run(&w, anim, frames, report);
    rt_mw_free(&w);
    if (!ok)
        rf_rt_fail(err, err_size, "out of memory");
    return ok;
}

/* The frame the i-th of `count` samples spread over a clip of `frames` frames reads. */
static uint32_t rt_sample_frame(uint32_t i, uint32_t count, uint32_t frames)
{
    return count > 1 ? (uint32_t)((uint64_t)i * (frames - 1) / (count - 1)) : 0;
}

/* What stands on the floor at rest, as a mask over the vertices into *base, and the rest mesh's
 * lowest along up into *floor_h: the whole mesh (`all`) or its vertices low at rest (parts high
 * at rest left out: a dragon's wings hanging through the floor must not lift its feet off it;
 * the parts pass lifts them), less the limbs `aside` carries. */
static bool rt_mesh_base(const rt_mesh_work *w, bool all, const uint8_t *aside, uint8_t **base,
                         double *floor_h)
{
    double lo = INFINITY, top = -INFINITY;
    for (uint32_t v = 0; v < w->nv; v++) {
        double h = rf_v3_dot(w->rest[v], w->up);
        lo = fmin(lo, h), top = fmax(top, h);
    }
    *floor_h = lo;
    if (!(*base = malloc(w->nv ? w->nv : 1)))
        return false;
    for (uint32_t v = 0; v < w->nv; v++)
        (*base)[v] = all || (rf_v3_dot(w->rest[v], w->up) <= lo + RT_MESH_HIGH * (top - lo) &&
                             !(aside && aside[rf_mesh_heaviest_joint(w->m, v)]));
    return true;
}

/* The lowest vertex of `base` with the clip posed at frame f, along up; that of `also` too in
 * *also_low when `also` is not NULL. */
static double rt_mesh_low_at(rt_mesh_work *w, const rf_animation *anim, uint32_t f,
                             const uint8_t *base, const uint8_t *also, double *also_low)
{
    rf_animation_local_pose(anim, w->s, f, w->local);
    for (uint32_t j = 0; j < w->n; j++)
        w->local[j].r = rf_quat_normalize(w->local[j].r);
    rt_mesh_fk(w);
    rt_mesh_skin(w, w->pos);
    double low = INFINITY, other = INFINITY;
    for (uint32_t v = 0; v < w->nv; v++) {
        double h = rf_v3_dot(w->pos[v], w->up);
        low = base[v] ? fmin(low, h) : low;
        other = also && also[v] ? fmin(other, h) : other;
    }
    if (also)
        *also_low = other;
    return low;
}

/* The lowest vertex in each of `count` frames spread over the clip, over the rest mesh's lowest
 * raised by clear[i] (how far the source stands over its floor then), into low (sorted), of
 * what stands on the floor (rt_mesh_base). */
static bool rt_mesh_lows(rt_mesh_work *w, const rf_animation *anim, uint32_t count, bool all,
                         const uint8_t *aside, const double *clear, double *low)
{
    uint8_t *base;
    double floor_h;
    if (!rt_mesh_base(w, all, aside, &base, &floor_h))
        return false;
    for (uint32_t i = 0; i < count; i++)
        low[i] = rt_mesh_low_at(w, anim, rt_sample_frame(i, count, anim->frame_count), base, NULL,
                                NULL) -
                 (floor_h + clear[i]);
    free(base);
    qsort(low, count, sizeof *low, rt_cmp_double);
    return true;
}

/* For each joint, the vertices it carries most that reach farthest along the 6 axes and the 8
 * diagonals of its rest frame: where its part of the mesh reaches, whatever way it turns (the
 * parts pass keeps them over the floor, not only the joint's pivot). */
static bool rt_mesh_hulls(rf_retarget *rt, const rt_mesh_work *w)
{
    static const signed char dir[RF_RT_HULL][3] = {
        {1, 0, 0},  {-1, 0, 0}, {0, 1, 0},   {0, -1, 0}, {0, 0, 1},   {0, 0, -1},  {1, 1, 1},
        {1, 1, -1}, {1, -1, 1}, {1, -1, -1}, {-1, 1, 1}, {-1, 1, -1}, {-1, -1, 1}, {-1, -1, -1}};
    size_t n = rt->n ? rt->n : 1;
    free(rt->t_hull);
    rt->t_hull = calloc(n * RF_RT_HULL, sizeof *rt->t_hull);
    double *best = malloc(n * RF_RT_HULL * sizeof *best);
    if (!rt->t_hull || !best) {
        free(best);
        return false;
    }
    for (size_t i = 0; i < n * RF_RT_HULL; i++)
        best[i] = 0; /* the pivot (0, 0, 0) reaches 0 along every direction */
    for (uint32_t v = 0; v < w->nv; v++) {
        uint32_t j = rf_mesh_heaviest_joint(w->m, v);
        if (j >= rt->n)
            continue;
        rf_vec3 p = rf_xform_point(rf_xform_invert(w->world[j]), w->rest[v]);
        for (uint32_t d = 0; d < RF_RT_HULL; d++) {
            double reach = dir[d][0] * p.x + dir[d][1] * p.y + dir[d][2] * p.z;
            if (reach > best[j * RF_RT_HULL + d])
                best[j * RF_RT_HULL + d] = reach, rt->t_hull[j * RF_RT_HULL + d] = p;
        }
    }
    free(best);
    return true;
}

/* The joints of limbs driven by source limbs of another kind (RF_RT_IN_KIND: a quadruped's
 * forelegs hanging from shoulder blades that take a human's clavicle turns) or by the source's
 * legs half a cycle later (RF_RT_IN_PHASE: a quadruped's forelegs under a biped's legs, longer
 * or shorter than its hind legs): their reach says nothing of where the body stands, so the
 * first placement leaves them to the contact and parts passes. NULL when there are none (or out
 * of memory: then they count). */
static uint8_t *rt_limbs_aside(const rf_retarget *rt)
{
    uint8_t *aside = NULL;
    for (uint32_t j = 0; j < rt->n; j++) {
        const rf_rt_tjoint *tj = &rt->tj[j];
        bool kind = false;
        for (uint32_t i = 0; tj->kind == RF_RT_MAPPED && i < tj->input_count; i++)
            kind = kind || (rt->in[tj->first_input + i].flags & (RF_RT_IN_KIND | RF_RT_IN_PHASE));
        if (kind && !aside && !(aside = calloc(rt->n, 1)))
            return NULL;
        for (uint32_t c = j; kind && c < rt->n; c++)
            aside[c] = aside[c] || rf_rt_carries(rt->target, (int32_t)j, c);
    }
    return aside;
}

/* Moves the clip along up so the median sampled frame's lowest vertex (of the whole mesh, or of
 * what stands on the floor at rest) sits on the rest mesh's lowest; only up when `raise_only`. */
static bool rt_mesh_place(rf_retarget *rt, rf_animation *anim, const rf_mesh *mesh, bool all,
                          bool raise_only, double *shift, char *err, size_t err_size)
{
    if (shift)
        *shift = 0;
    if (rt_mesh_check(rt->target, mesh, anim, NULL, err, err_size) <= 0)
        return false;
    rf_rt_floors_measured(rt);
    rt_mesh_work w = {.s = rt->target, .m = mesh, .n = rt->n, .nv = mesh->vertex_count};
    w.up = rt->up;
    uint32_t count = anim->frame_count < 32 ? anim->frame_count : 32, at[32];
    double low[32], clear[32];
    for (uint32_t i = 0; i < count; i++)
        at[i] = rt_sample_frame(i, count, anim->frame_count);
    /* What stands on the floor is put on it as it stands (the contact pass then lifts the feet
     * as far as the source's); the last raise counts the floor from where the source is, as the
     * measure does (in a jump, in the air). */
    memset(clear, 0, sizeof clear);
    uint8_t *aside = rt_limbs_aside(rt);
    bool ok =
        (!all || rf_rt_clearance(rt, rf_retarget_start_time(rt), anim->fps, count, at, clear)) &&
        rt_mesh_prepare(&w) && (all || rt_mesh_hulls(rt, &w)) &&
        rt_mesh_lows(&w, anim, count, all, aside, clear, low);
    free(aside);
    if (ok && !all) {
        rt->mesh_floor = INFINITY;
        for (uint32_t v = 0; v < w.nv; v++)
            rt->mesh_floor = fmin(rt->mesh_floor, rf_v3_dot(w.rest[v], w.up));
    }
    rt_mw_free(&w);
    if (!ok) {
        rf_rt_fail(err, err_size, "out of memory");
        return false;
    }
    double lift = -(count % 2 ? low[count / 2] : 0.5 * (low[count / 2 - 1] + low[count / 2]));
    if (!isfinite(lift) || (raise_only && !(lift > 0)))
        return true;
    if (shift)
        *shift = lift;
    /* The contact and parts passes read soles from joints and bone tips too: their floor is
     * where the skeleton stands when its skin stands on the mesh's floor, the skeleton's lowest
     * point at rest (the skin's lowest lies that far under it), not the skeleton's floor moved
     * with the body. The lift also holds how far the pose's skin reaches under its joints
     * further than at rest: counted as a floor, it pinned spider.obj's feet 10.5 units (of 80)
     * over its skin's floor under the CMU walk. */
    if (!all)
        rt->floor_target = rt->t_rest_low;
    if (!rf_rt_lift(rt, anim, lift)) {
        rf_rt_fail(err, err_size, "out of memory");
        return false;
    }
    return true;
}

/* A body with no foot to pin (a fish lying on its fins, a blob standing on its bottom) stands on
 * nothing but its skin, so its lowest vertex of what stands on the floor at rest is put on the
 * floor in every frame, raised by how far the source stands over its own (in a jump, in the
 * air), not only in the median frame: a level body taking a human's lean (eased, "Body plans")
 * pitches its nose or its belly through the floor in the frames the source leans furthest. Read
 * every tenth of a second (rt_rest_step) and interpolated between. */
static uint32_t rt_rest_step(const rf_animation *anim)
{
    double per = floor(anim->fps / 10); /* clamped before the conversion: any rate may come */
    return per >= 1 ? (uint32_t)fmin(per, anim->frame_count) : 1;
}

/* Whether some target joint is driven by a source joint low in its source's rest (under half
 * its legs' height: a knee, a foot): the target has legs in this mapping, even where no foot of
 * theirs could be pinned (the fire dragon under the Fox's Walk), and stands on them. */
static bool rt_legs_driven(const rf_retarget *rt)
{
    for (uint32_t j = 0; j < rt->n; j++) {
        const rf_rt_tjoint *tj = &rt->tj[j];
        for (uint32_t i = 0; tj->kind == RF_RT_MAPPED && i < tj->input_count; i++) {
            const rf_rt_input *in = &rt->in[tj->first_input + i];
            const rf_rt_src *src = &rt->src[in->source];
            double h = rf_rt_height(src->up, src->rest_world[in->joint].t);
            if (h < src->lowest + 0.5 * src->leg)
                return true;
        }
    }
    return false;
}

/* Each frame's lowest vertex of what stands put where the source's lowest point stands over its
 * floor (rf_rt_clearance), through the root-motion joints; with `lower_only` only the frames
 * that stand higher move, and no further than the lowest vertex of the limbs left out of what
 * stands (rt_limbs_aside) goes: lowered onto its hind legs, a horse under a human's walk put its
 * forelegs through the floor (floor p95 2.97 -> 4.73% of its height over the whole walk); with
 * `rise` too the frames that stand lower are raised by the whole difference. *lowered counts the
 * frames lowered, *deepest the largest lowering, *raised the frames raised. */
static bool rt_mesh_rest_each(rf_retarget *rt, rf_animation *anim, const rf_mesh *mesh,
                              bool lower_only, bool rise, uint32_t *lowered, double *deepest,
                              uint32_t *raised)
{
    uint32_t frames = anim->frame_count, step = rt_rest_step(anim);
    uint32_t count = (frames - 1) / step + 2;
    rt_mesh_work w = {.s = rt->target, .m = mesh, .n = rt->n, .nv = mesh->vertex_count};
    w.up = rt->up;
    uint32_t *at = malloc(count * sizeof *at);
    double *clear = calloc(count, sizeof *clear), *lift = malloc(frames * sizeof *lift);
    uint8_t *aside = rt_limbs_aside(rt), *base = NULL, *reach = NULL;
    double floor_h = 0, reach_low = INFINITY;
    for (uint32_t i = 0; at && i < count; i++)
        at[i] = (uint64_t)i * step < frames ? i * step : frames - 1;
    bool ok = at && clear && lift &&
              rf_rt_clearance(rt, rf_retarget_start_time(rt), anim->fps, count, at, clear) &&
              rt_mesh_prepare(&w) && rt_mesh_base(&w, false, aside, &base, &floor_h) &&
              (!lower_only || !aside || rt_mesh_base(&w, false, NULL, &reach, &floor_h));
    /* A frame whose lowest point is no number (no vertex stands, or none is one) gives no lift:
     * the clip stays where rt_mesh_place put it, as that does with such a median frame. */
    bool finite = true;
    for (uint32_t i = 0; ok && finite && i < count; i++) {
        double need = floor_h + clear[i];
        clear[i] = need - rt_mesh_low_at(&w, anim, at[i], base, reach, &reach_low);
        finite = isfinite(clear[i]);
        if (lower_only && !(rise && clear[i] > 0))
            clear[i] = fmin(0, fmax(clear[i], fmin(0, need - reach_low)));
    }
    for (uint32_t f = 0; ok && finite && f < frames; f++) {
        uint32_t i = f / step;
        double span = at[i + 1] > at[i] ? at[i + 1] - at[i] : 1, t = (f - at[i]) / span;
        lift[f] = clear[i] + t * (clear[i + 1] - clear[i]);
        *lowered += lift[f] < 0;
        *raised += lift[f] > 0;
        *deepest = fmax(*deepest, -lift[f]);
    }
    ok = ok && (!finite || rf_rt_lift_each(rt, anim, lift));
    rt_mw_free(&w);
    free(at), free(clear), free(lift), free(aside), free(base), free(reach);
    return ok;
}

bool rf_retarget_mesh_floor(rf_retarget *rt, rf_animation *anim, const rf_mesh *mesh, double *shift,
                            char *err, size_t err_size)
{
    if (!rt_mesh_place(rt, anim, mesh, false, false, shift, err, err_size))
        return false;
    if (rt->effector_count || !anim->frame_count || rt->opt.root_scale > 0 || rt_legs_driven(rt))
        return true;
    uint32_t lowered = 0, raised = 0;
    double deepest = 0;
    if (!rt_mesh_rest_each(rt, anim, mesh, false, false, &lowered, &deepest, &raised)) {
        rf_rt_fail(err, err_size, "out of memory");
        return false;
    }
    return true;
}

bool rf_retarget_mesh_hold(rf_retarget *rt, rf_animation *anim, const rf_mesh *mesh,
                           uint32_t *lowered, double *deepest, uint32_t *raised, char *err,
                           size_t err_size)
{
    *lowered = 0, *deepest = 0, *raised = 0;
    if (rt_mesh_check(rt->target, mesh, anim, NULL, err, err_size) <= 0)
        return false;
    if (anim->frame_count &&
        !rt_mesh_rest_each(rt, anim, mesh, true, rf_rt_feet_rigid(rt), lowered, deepest, raised)) {
        rf_rt_fail(err, err_size, "out of memory");
        return false;
    }
    return true;
}

bool rf_retarget_mesh_clear(rf_retarget *rt, rf_animation *anim, const rf_mesh *mesh, double *shift,
                            char *err, size_t err_size)
{
    return rt_mesh_place(rt, anim, mesh, true, true, shift, err, err_size);
}

int rf_retarget_mesh_usable(const rf_retarget *rt, const rf_mesh *mesh, const rf_animation *anim,
                            bool *rigid, char *err, size_t err_size)
{
    return rt_mesh_check(rt->target, mesh, anim, rigid, err, err_size);
}

bool rf_retarget_mesh_measure(rf_retarget *rt, const rf_mesh *mesh, const rf_animation *anim,
                              double start, uint32_t max_frames, rf_rt_mesh_report *report,
                              char *err, size_t err_size)
{
    memset(report, 0, sizeof *report);
    rt_mesh_work w = {.s = rt->target, .m = mesh, .n = rt->n};
    if (rt_mesh_check(rt->target, mesh, anim, &w.rigid, err, err_size) <= 0)
        return false;
    uint8_t *counts = malloc(rt->n ? rt->n : 1);
    bool known = rf_rt_weights_known(rt->target);
    for (uint32_t j = 0; counts && j < rt->n; j++)
        counts[j] =
            !rt->t_above[j] && !(known && (rt->target->joints[j].flags & RF_JOINT_UNWEIGHTED));
    /* The retarget put a node tree on its skeleton's floor, not on a mesh's: the sources keep
     * theirs as it did. */
    if (!w.rigid)
        rf_rt_floors_measured(rt);
    w.nv = mesh->vertex_count + (w.rigid ? 2 * rt->n : 0);
    w.counts = counts, w.tip = rt->t_tip, w.up = rt->up;
    uint32_t frames = max_frames ? max_frames : 24;
    frames = frames < anim->frame_count ? frames : anim->frame_count;
    double *expect = malloc((frames ? frames : 1) * sizeof *expect);
    uint32_t *at = malloc((frames ? frames : 1) * sizeof *at);
    for (uint32_t i = 0; at && i < frames; i++)
        at[i] = rt_sample_frame(i, frames, anim->frame_count);
    bool ok = counts && expect && at && rf_rt_clearance(rt, start, anim->fps, frames, at, expect);
    free(at);
    w.expect = expect;
    ok = ok && rt_mesh_prepare(&w) && rt_mesh_run(&w, anim, frames, report);
    rt_mw_free(&w);
    free(expect), free(counts);
    if (!ok)
        rf_rt_fail(err, err_size, "out of memory");
    return ok;
}
