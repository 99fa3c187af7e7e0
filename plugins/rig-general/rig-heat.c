/* Skin weights by bone heat (Baran and Popovic 2007): each joint's weight is the steady
 * temperature of the surface when the bones of that joint are held at 1 and the others at 0, heat
 * flowing into each vertex from the nearest bone it can see. The cotangent Laplacian plus the
 * heat terms make one sparse symmetric system, factored once with CHOLMOD and solved for all
 * joints at once; Embree answers "can this vertex see that bone". Loose parts that see no bone
 * at all (an eye inside a head) take heat from their nearest bone, so every part has a solution
 * and no vertex is left without weights. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <rigflow/memory.h>
#include <suitesparse/cholmod.h>

#include "rig-embree.h"

uint32_t rf_rig_bones(const rf_rig_skel *s, rf_rig_bone **out)
{
    rf_rig_bone *b = malloc((size_t)(2 * s->n + 1) * sizeof *b);
    uint8_t *has_child = calloc(s->n + 1, 1);
    uint32_t n = 0;
    if (!b || !has_child) {
        free(b), free(has_child);
        return 0;
    }
    for (uint32_t j = 0; j < s->n; j++) {
        int32_t p = s->parent[j];
        if (p < 0)
            continue;
        has_child[p] = 1;
        memcpy(b[n].a, s->pos + (size_t)p * 3, sizeof b[n].a);
        memcpy(b[n].b, s->pos + (size_t)j * 3, sizeof b[n].b);
        b[n++].joint = s->owns_in && s->owns_in[j] ? j : (uint32_t)p;
    }
    for (uint32_t j = 0; j < s->n; j++) {
        if (!s->has_tip[j] && has_child[j])
            continue;
        memcpy(b[n].a, s->pos + (size_t)j * 3, sizeof b[n].a);
        memcpy(b[n].b, s->has_tip[j] ? s->tip + (size_t)j * 3 : s->pos + (size_t)j * 3,
               sizeof b[n].b);
        b[n++].joint = j;
    }
    free(has_child);
    *out = b;
    return n;
}

double rf_rig_seg_dist(const double q[3], const rf_rig_bone *b, double c[3])
{
    double ab[3], aq[3], l2 = 0, dot = 0;
    for (int k = 0; k < 3; k++) {
        ab[k] = b->b[k] - b->a[k], aq[k] = q[k] - b->a[k];
        l2 += ab[k] * ab[k], dot += ab[k] * aq[k];
    }
    double u = l2 > 0 ? fmin(1, fmax(0, dot / l2)) : 0, d = 0;
    for (int k = 0; k < 3; k++) {
        c[k] = b->a[k] + ab[k] * u;
        d += (q[k] - c[k]) * (q[k] - c[k]);
    }
    return sqrt(d);
}

/* ---- visibility ---- */

typedef struct rf_rig_rays {
    RTCDevice dev;
    RTCScene scene;
    uint32_t *tri_part; /* [triangle] loose part */
} rf_rig_rays;

/* The context of one visibility query: Embree's, then the part the ray starts on. */
typedef struct rf_rig_ray_ctx {
    struct RTCIntersectContext rtc; /* first: Embree hands the filter a pointer to it */
    const uint32_t *tri_part;
    uint32_t part;
    uint32_t *crossings; /* when set: [part] surfaces of each part the ray crosses, every hit
                          * counted and passed through */
    uint32_t *crossed, *ncrossed; /* the parts crossed at all, in crossed[0..*ncrossed) */
} rf_rig_ray_ctx;

/* Only the ray's own loose part can hide a bone from it: separate parts that overlap (a box
 * model's upper and lower leg, a belt over a body) would otherwise hide each other's bones
 * from every vertex inside the overlap. */
static void rf_rig_own_part(const struct RTCFilterFunctionNArguments *args)
{
    const rf_rig_ray_ctx *c = (const rf_rig_ray_ctx *)args->context;
    /* RTCHitN is laid out by columns: Ng_x, Ng_y, Ng_z, u, v, primID, ... N entries each */
    const unsigned *prim = (const unsigned *)args->hit + 5 * (size_t)args->N;
    for (unsigned i = 0; i < args->N; i++) {
        if (args->valid[i] && c->crossings && c->crossings[c->tri_part[prim[i]]]++ == 0)
            c->crossed[(*c->ncrossed)++] = c->tri_part[prim[i]];
        if (args->valid[i] && (c->crossings || c->tri_part[prim[i]] != c->part))
            args->valid[i] = 0;
    }
}

static bool rf_rig_rays_make(rf_rig_rays *r, const rf_rig_geo *g, const uint32_t *vertex_part)
{
    memset(r, 0, sizeof *r);
    if (!(r->tri_part = malloc((size_t)(g->nt + 1) * sizeof *r->tri_part)))
        return false;
    for (uint32_t t = 0; t < g->nt; t++)
        r->tri_part[t] = vertex_part[g->t[t * 3]];
    if (!(r->dev = rtcNewDevice("threads=1,set_affinity=0")))
        return false;
    r->scene = rtcNewScene(r->dev);
    RTCGeometry geo = rf_rig_triangles(r->dev, g);
    if (!geo)
        return false;
    rtcSetGeometryOccludedFilterFunction(geo, rf_rig_own_part);
    rtcCommitGeometry(geo);
    rtcAttachGeometry(r->scene, geo);
    rtcReleaseGeometry(geo);
    rtcCommitScene(r->scene);
    return rtcGetDeviceError(r->dev) == RTC_ERROR_NONE;
}

static void rf_rig_rays_free(rf_rig_rays *r)
{
    if (r->scene)
        rtcReleaseScene(r->scene);
    if (r->dev)
        rtcReleaseDevice(r->dev);
    free(r->tri_part);
}

/* True when the segment from p (on loose part `part`) to q crosses no triangle of that part
 * (ends excluded by eps). */
static bool rf_rig_sees(const rf_rig_rays *r, uint32_t part, const double p[3], const double q[3],
                        double eps)
{
    double d[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
    double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (len <= 2 * eps)
        return true;
    struct RTCRay ray = {0};
    ray.org_x = (float)p[0], ray.org_y = (float)p[1], ray.org_z = (float)p[2];
    ray.dir_x = (float)(d[0] / len), ray.dir_y = (float)(d[1] / len),
    ray.dir_z = (float)(d[2] / len);
    ray.tnear = (float)eps, ray.tfar = (float)(len - eps);
    ray.mask = UINT32_MAX;
    rf_rig_ray_ctx ctx = {.tri_part = r->tri_part, .part = part};
    rtcInitIntersectContext(&ctx.rtc);
    rtcOccluded1(r->scene, &ctx.rtc, &ray);
    return ray.tfar >= 0;
}

static double rf_rig_dist3(const double *a, const double *b)
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2]));
}

/* With the bones' axes known: the bone from a joint to a child on the joint's axis continues
 * the joint's bone and is the joint's (a head over the hips' axis past helper joints: the torso
 * between is the hips'), whatever the leaf rule said. A leaf off its parent's axis owns the
 * offset from its parent only when the parent's bone goes on along its axis into a chain (a
 * torso running on to the neck: the legs hanging off it are single-joint limbs); a parent whose
 * chain ends there (BCN_Epileptic's neck, whose jaw, ponytail and face joints all sit off its
 * axis) keeps those offsets, as a head keeps its ears'. A joint with no child on its axis gets a
 * bone of its own along the axis, as long as the farthest of its parent and children is from
 * it. reach and on are scratch, [n] each. */
static void rf_rig_axis_bones(rf_rig_skel *k, const double *axis, double tiny, double *reach,
                              uint8_t *on)
{
    for (uint32_t j = 0; j < k->n; j++) {
        int32_t p = k->parent[j];
        reach[j] = p >= 0 ? rf_rig_dist3(k->pos + (size_t)j * 3, k->pos + (size_t)p * 3) : 0;
        on[j] = 0;
    }
    for (uint32_t j = 0; j < k->n; j++)
        if (k->parent[j] >= 0)
            on[k->parent[j]] |= 4; /* an inner joint */
    for (uint32_t c = 0; c < k->n; c++) {
        int32_t j = k->parent[c];
        if (j < 0)
            continue;
        const double *a = axis + (size_t)j * 3, *o = k->pos + (size_t)j * 3,
                     *q = k->pos + (size_t)c * 3;
        double len = rf_rig_dist3(o, q);
        double along = (q[0] - o[0]) * a[0] + (q[1] - o[1]) * a[1] + (q[2] - o[2]) * a[2];
        reach[j] = fmax(reach[j], len);
        if ((a[0] || a[1] || a[2]) && (len <= tiny || along >= 0.95 * len)) {
            /* within 18 degrees of the axis; 2: a chain goes on along it */
            on[j] |= 1 | (on[c] & 4 ? 2 : 0);
            if (k->owns_in)
                k->owns_in[c] = 0;
        }
    }
    for (uint32_t c = 0; k->owns_in && c < k->n; c++) {
        int32_t j = k->parent[c];
        const double *a = j >= 0 ? axis + (size_t)j * 3 : NULL;
        if (a && (a[0] || a[1] || a[2]) && !(on[j] & 2))
            k->owns_in[c] = 0;
    }
    for (uint32_t j = 0; j < k->n; j++) {
        const double *a = axis + (size_t)j * 3;
        if (!(a[0] || a[1] || a[2]) || (on[j] & 1) || k->has_tip[j] || !(reach[j] > tiny))
            continue;
        for (int c = 0; c < 3; c++)
            k->tip[(size_t)j * 3 + c] = k->pos[(size_t)j * 3 + c] + a[c] * reach[j];
        k->has_tip[j] = 1;
    }
}

bool rf_rig_leaf_tips(const rf_rig_prep *p, rf_rig_skel *k, const double *axis)
{
    double tiny = 1e-9 * p->longest, *reach = malloc(((size_t)k->n + 1) * sizeof *reach);
    uint8_t *inner = calloc(k->n + 1, 1);
    if (!reach || !inner) {
        free(reach), free(inner);
        return false;
    }
    if (axis)
        rf_rig_axis_bones(k, axis, tiny, reach, inner);
    memset(inner, 0, k->n);
    for (uint32_t i = 0; i < k->n; i++)
        if (k->parent[i] >= 0)
            inner[k->parent[i]] = 1;
    for (uint32_t i = 0; i < k->n; i++) {
        if (inner[i] || k->has_tip[i] || k->parent[i] < 0)
            continue;
        const double *a = k->pos + (size_t)k->parent[i] * 3, *b = k->pos + (size_t)i * 3;
        const double *ax = axis ? axis + (size_t)i * 3 : NULL;
        bool along = ax && (ax[0] || ax[1] || ax[2]);
        double len = rf_rig_dist3(a, b);
        if (!(len > tiny))
            continue;
        for (int c = 0; c < 3; c++)
            k->tip[(size_t)i * 3 + c] = b[c] + (along ? ax[c] * len : b[c] - a[c]);
        k->has_tip[i] = 1;
    }
    free(reach), free(inner);
    return true;
}

/* ---- the proxy vertex nearest a point ---- */

struct rf_rig_near {
    double lo[3], h; /* the proxy's box corner and the cell size */
    uint32_t n[3];   /* cells along each axis */
    uint32_t *start; /* [cells + 1] where each cell's vertices begin in `id` */
    uint32_t *id;    /* proxy vertices by cell */
    const rf_rig_geo *g;
};

static uint32_t rf_rig_near_axis(const rf_rig_near *gr, int a, double x)
{
    double c = floor((x - gr->lo[a]) / gr->h);
    return c < 0 ? 0 : c >= gr->n[a] ? gr->n[a] - 1 : (uint32_t)c;
}

static size_t rf_rig_near_cell(const rf_rig_near *gr, const uint32_t c[3])
{
    return ((size_t)c[2] * gr->n[1] + c[1]) * gr->n[0] + c[0];
}

rf_rig_near *rf_rig_near_new(const rf_rig_prep *p)
{
    rf_rig_near *gr = calloc(1, sizeof *gr);
    if (!gr)
        return NULL;
    gr->g = &p->proxy;
    gr->h = p->longest / 32;
    size_t cells = 1;
    for (int a = 0; a < 3; a++) {
        gr->lo[a] = p->lo[a];
        gr->n[a] = (uint32_t)fmin(64, floor((p->hi[a] - p->lo[a]) / gr->h) + 1);
        cells *= gr->n[a];
    }
    gr->start = calloc(cells + 2, sizeof *gr->start);
    gr->id = malloc(((size_t)p->proxy.nv + 1) * sizeof *gr->id);
    if (!gr->start || !gr->id) {
        rf_rig_near_free(gr);
        return NULL;
    }
    for (uint32_t i = 0; i < p->proxy.nv; i++) { /* counting sort by cell */
        uint32_t c[3];
        for (int a = 0; a < 3; a++)
            c[a] = rf_rig_near_axis(gr, a, p->proxy.p[(size_t)i * 3 + a]);
        gr->start[rf_rig_near_cell(gr, c) + 2]++;
    }
    for (size_t k = 2; k < cells + 2; k++)
        gr->start[k] += gr->start[k - 1];
    for (uint32_t i = 0; i < p->proxy.nv; i++) {
        uint32_t c[3];
        for (int a = 0; a < 3; a++)
            c[a] = rf_rig_near_axis(gr, a, p->proxy.p[(size_t)i * 3 + a]);
        gr->id[gr->start[rf_rig_near_cell(gr, c) + 1]++] = i;
    }
    return gr;
}

void rf_rig_near_free(rf_rig_near *gr)
{
    if (gr)
        free(gr->start), free(gr->id), free(gr);
}

/* The vertices of the cells at Chebyshev distance r from cell c, the nearest to q kept. */
static void rf_rig_near_ring(const rf_rig_near *gr, const uint32_t c[3], int r, const double q[3],
                             double *best, uint32_t *at)
{
    for (int dz = -r; dz <= r; dz++)
        for (int dy = -r; dy <= r; dy++)
            for (int dx = -r; dx <= r; dx++) {
                if (abs(dx) != r && abs(dy) != r && abs(dz) != r)
                    continue; /* inside the ring: visited before */
                long x = (long)c[0] + dx, y = (long)c[1] + dy, z = (long)c[2] + dz;
                if (x < 0 || y < 0 || z < 0 || x >= gr->n[0] || y >= gr->n[1] || z >= gr->n[2])
                    continue;
                uint32_t cc[3] = {(uint32_t)x, (uint32_t)y, (uint32_t)z};
                size_t k = rf_rig_near_cell(gr, cc);
                for (uint32_t e = gr->start[k]; e < gr->start[k + 1]; e++) {
                    const double *v = gr->g->p + (size_t)gr->id[e] * 3;
                    double d = (q[0] - v[0]) * (q[0] - v[0]) + (q[1] - v[1]) * (q[1] - v[1]) +
                               (q[2] - v[2]) * (q[2] - v[2]);
                    if (d < *best)
                        *best = d, *at = gr->id[e];
                }
            }
}

uint32_t rf_rig_near_vertex(const rf_rig_near *gr, const double q[3])
{
    uint32_t c[3], at = RF_RIG_NONE;
    double best = INFINITY, out = 0; /* out: how far q lies outside the grid */
    for (int a = 0; a < 3; a++) {
        c[a] = rf_rig_near_axis(gr, a, q[a]);
        double lo = gr->lo[a], hi = gr->lo[a] + gr->n[a] * gr->h;
        out = fmax(out, fmax(lo - q[a], q[a] - hi));
    }
    int rings = (int)fmax(gr->n[0], fmax(gr->n[1], gr->n[2]));
    for (int r = 0; r <= rings; r++) {
        rf_rig_near_ring(gr, c, r, q, &best, &at);
        /* every vertex of a farther ring is more than r cells (plus q's distance outside the
         * grid) away */
        double bound = fmax(0, out) + r * gr->h;
        if (at != RF_RIG_NONE && best <= bound * bound)
            break;
    }
    return at;
}

/* For each proxy vertex of a part marked in from[], the nearest vertex within r of another part
 * but `skip` into touch[i] (RF_RIG_NONE when none is that near, and for the vertices of other
 * parts): where loose parts touch. r is at most the grid's cell (longest / 32), so the 27 cells
 * around a vertex's hold every vertex that near. */
static void rf_rig_near_touch(const rf_rig_near *gr, const uint32_t *part, const uint8_t *from,
                              uint32_t skip, double r, uint32_t *touch)
{
    const rf_rig_geo *g = gr->g;
    for (uint32_t i = 0; i < g->nv; i++) {
        const double *q = g->p + (size_t)i * 3;
        double best = r * r;
        uint32_t c[3];
        touch[i] = RF_RIG_NONE;
        if (!from[part[i]])
            continue;
        for (int a = 0; a < 3; a++)
            c[a] = rf_rig_near_axis(gr, a, q[a]);
        for (int dz = -1; dz <= 1; dz++)
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    long x = (long)c[0] + dx, y = (long)c[1] + dy, z = (long)c[2] + dz;
                    if (x < 0 || y < 0 || z < 0 || x >= gr->n[0] || y >= gr->n[1] || z >= gr->n[2])
                        continue;
                    uint32_t cc[3] = {(uint32_t)x, (uint32_t)y, (uint32_t)z};
                    size_t k = rf_rig_near_cell(gr, cc);
                    for (uint32_t e = gr->start[k]; e < gr->start[k + 1]; e++) {
                        uint32_t o = gr->id[e];
                        const double *v = g->p + (size_t)o * 3;
                        double d = (q[0] - v[0]) * (q[0] - v[0]) + (q[1] - v[1]) * (q[1] - v[1]) +
                                   (q[2] - v[2]) * (q[2] - v[2]);
                        if (part[o] != part[i] && part[o] != skip && d <= best)
                            best = d, touch[i] = o;
                    }
                }
    }
}

/* ---- heat sources ---- */

/* The heat c in H = c / d^2. Larger c keeps each vertex closer to its nearest bone (sharper
 * weights), smaller c blends more widely. Artists' weights on the shared models are mostly
 * sharper than bone heat's at c = 1 (a mean of 1.0 to 1.8 joints per vertex above the
 * benchmark's pruning on 21 of 23 models, against 1.3 to 3.2); c = 2 matched them better on the
 * artists' own skeletons (precision 64% -> 67%, recall 84% -> 83%, L1 0.71 -> 0.67;
 * doc/autorig.md). */
#define RF_RIG_HEAT 2.0

typedef struct rf_rig_src {
    double h;        /* heat coefficient c/d^2 (before the vertex area) */
    uint32_t joint;  /* the joint whose bone heats the vertex */
    uint32_t joint2; /* another joint whose bone is as near and seen (the heat shared), or NONE */
} rf_rig_src;

typedef struct rf_rig_bd {
    double d;
    uint32_t b;
} rf_rig_bd;

static int rf_rig_bd_cmp(const void *pa, const void *pb)
{
    const rf_rig_bd *a = pa, *b = pb;
    return a->d < b->d ? -1 : a->d > b->d;
}

/* Whether bone b's nearest point to q is its end (b->b), the bone having a length. Read from
 * where q projects, not by comparing the nearest point with the end: that point is computed
 * from the start (a + (b - a)), which differs from b in the last digit whenever the two are
 * not of one magnitude, as joints placed by inverse binds or by the curve skeleton are. */
static bool rf_rig_nearest_is_end(const double q[3], const rf_rig_bone *b)
{
    double l2 = 0, dot = 0;
    for (int k = 0; k < 3; k++) {
        double ab = b->b[k] - b->a[k];
        l2 += ab * ab, dot += ab * (q[k] - b->a[k]);
    }
    return l2 > 0 && dot >= l2;
}

/* Three bones or more meeting at one point (a wrist with fingers fanning from one pivot, a
 * pelvis with the legs and the spine) are equally near every vertex whose nearest point on each
 * is that point. The one bone ending there (the limb leading into the junction) heats such a
 * vertex, not whichever two branches the sort put first: the fire dragon's wing membranes, whose
 * corners at the wrist its artist gave to the forearm, 68% -> 69% (doc/autorig.md). Returns
 * that bone's joint, or RF_RIG_NONE for two bones (a bend: both heat it) or no single ending
 * one. bd is sorted, bd[k] the bone chosen, tie the tolerance of equal distances. */
static uint32_t rf_rig_junction(const double q[3], const rf_rig_bone *bones, uint32_t nb,
                                const rf_rig_bd *bd, uint32_t k, double tie)
{
    uint32_t meeting = 0, ending = RF_RIG_NONE, ends = 0;
    for (uint32_t t = k; t < nb && t < 8 && bd[t].d - bd[k].d <= tie; t++) {
        const rf_rig_bone *b = &bones[bd[t].b];
        meeting++;
        if (rf_rig_nearest_is_end(q, b))
            ending = b->joint, ends++;
    }
    return meeting >= 3 && ends == 1 ? ending : RF_RIG_NONE;
}

static bool rf_rig_open_parts(const rf_rig_prep *p, uint8_t *open, double *vol);

/* Each proxy vertex's outward normal, area-weighted and not normalised, into nrm[nv * 3]: the
 * triangles' winding turned by the sign of the volume its part holds, zero on a part holding
 * none (a sheet: no side is out). False when out of memory. */
static bool rf_rig_normals(const rf_rig_prep *p, double *nrm)
{
    const rf_rig_geo *g = &p->proxy;
    uint8_t *open = calloc(p->proxy_parts + 1, 1);
    double *vol = calloc(p->proxy_parts + 1, sizeof *vol);
    bool ok = open && vol && rf_rig_open_parts(p, open, vol);
    memset(nrm, 0, (size_t)g->nv * 3 * sizeof *nrm);
    for (uint32_t t = 0; ok && t < g->nt; t++) {
        const uint32_t *v = g->t + (size_t)t * 3;
        const double *a = g->p + (size_t)v[0] * 3, *b = g->p + (size_t)v[1] * 3,
                     *c = g->p + (size_t)v[2] * 3;
        double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double out = vol[p->proxy_part[v[0]]], f = out > 0 ? 1 : out < 0 ? -1 : 0;
        double cr[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                        e1[0] * e2[1] - e1[1] * e2[0]};
        for (int k = 0; k < 3; k++)
            for (int d = 0; d < 3; d++)
                nrm[(size_t)v[k] * 3 + d] += f * cr[d];
    }
    free(open), free(vol);
    return ok;
}

/* A bone of the rigger's own skeleton lies inside the volume it was grown from, so a vertex
 * sees it from inside its surface. One lying in front of the surface, or behind its tangent
 * plane by less than 17 degrees (the cosine of its direction with the outward normal above
 * -0.3), lies across a gap: where a hand rests on a hip and the skins touch, the hip's vertices
 * see the hand's bone through the contact, with no surface between to hide it, and the hand
 * carried the hip's skin away in sheets under the CMU walk (BCN_Epileptic's worst part's
 * stretch 511.9 -> 132.2). A given skeleton's bones may lie outside the skin (leaf ends,
 * helpers), and it keeps the test off. -0.3 to -0.5 read alike on BCN_Epileptic (132 to 138)
 * and after the matcher (doc/autorig-log.md, "Skinning, round five"). */
#define RF_RIG_FRONT (-0.3)

/* Whether point c lies in front of the surface at q (normal n, not normalised): its direction
 * from q more than RF_RIG_FRONT towards n. False where n is unknown (zero). */
static bool rf_rig_in_front(const double n[3], const double q[3], const double c[3])
{
    double d[3] = {c[0] - q[0], c[1] - q[1], c[2] - q[2]};
    double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    double dd = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    return nn > 0 && dd > 0 && n[0] * d[0] + n[1] * d[1] + n[2] * d[2] > RF_RIG_FRONT * nn * dd;
}

/* The nearest bone each vertex sees (trying the 8 nearest); src[i].h = 0 when it sees none. A
 * loose part where no vertex sees a bone takes its nearest bones unseen. */
static void rf_rig_sources(const rf_rig_prep *p, const rf_rig_bone *bones, uint32_t nb,
                           const rf_rig_rays *rays, bool leaf_points_own, const double *nrm,
                           rf_rig_src *src, rf_rig_bd *bd, uint8_t *lit, rf_rig_stats *st)
{
    double eps = 1e-5 * p->longest, floor_d = 1e-3 * p->longest;
    st->unseen_vertices = 0;
    /* bones ending at a leaf joint that has no end site (its bone is a point there) */
    uint8_t *tipless = leaf_points_own ? calloc(nb + 1, 1) : NULL;
    for (uint32_t b = 0; tipless && b < nb; b++)
        for (uint32_t k = 0; k < nb && !tipless[b]; k++)
            tipless[b] = k != b && !memcmp(bones[k].a, bones[k].b, sizeof bones[k].a) &&
                         !memcmp(bones[k].a, bones[b].b, sizeof bones[k].a);
    for (uint32_t i = 0; i < p->proxy.nv; i++) {
        const double *q = p->proxy.p + (size_t)i * 3;
        double c[3];
        for (uint32_t b = 0; b < nb; b++) {
            bd[b].d = rf_rig_seg_dist(q, &bones[b], c), bd[b].b = b;
            /* a vertex whose nearest point on a bone is the end of a leaf joint without an end
             * site lies beyond that joint: the leaf's point wins the tie, as a leaf joint of an
             * artist's skeleton owns the limb past it */
            if (tipless && tipless[b] && rf_rig_nearest_is_end(q, &bones[b]))
                bd[b].d += 1e-9 * (bd[b].d + p->longest);
        }
        qsort(bd, nb, sizeof *bd, rf_rig_bd_cmp);
        double d0 = fmax(bd[0].d, floor_d);
        src[i].h = 0, src[i].joint = bones[bd[0].b].joint, src[i].joint2 = RF_RIG_NONE;
        uint32_t k = 0;
        /* the bones in front of the surface are passed over first (nrm given); when the vertex
         * sees no other, seen ones in front are taken as before */
        for (int front = nrm ? 0 : 1; front < 2 && src[i].h == 0; front++)
            for (k = 0; k < nb && k < 8; k++) {
                rf_rig_seg_dist(q, &bones[bd[k].b], c);
                if (!front && rf_rig_in_front(nrm + (size_t)i * 3, q, c))
                    continue;
                if (!rays || rf_rig_sees(rays, p->proxy_part[i], q, c, eps)) {
                    double d = fmax(bd[k].d, floor_d);
                    src[i].h = RF_RIG_HEAT / (d * d), src[i].joint = bones[bd[k].b].joint;
                    lit[p->proxy_part[i]] = 1;
                    break;
                }
            }
        /* two bones meeting at a joint are equally near every vertex whose nearest point on
         * both is that joint (the outside of a bend): both heat it, as in Pinocchio, instead
         * of whichever the sort put first */
        double tie = 1e-10 * (bd[0].d + p->longest);
        for (uint32_t t = k + 1; src[i].h > 0 && t < nb && t < 8 && bd[t].d - bd[k].d <= tie; t++) {
            rf_rig_seg_dist(q, &bones[bd[t].b], c);
            if (bones[bd[t].b].joint != src[i].joint &&
                (!rays || rf_rig_sees(rays, p->proxy_part[i], q, c, eps))) {
                src[i].joint2 = bones[bd[t].b].joint;
                break;
            }
        }
        uint32_t into =
            src[i].joint2 != RF_RIG_NONE ? rf_rig_junction(q, bones, nb, bd, k, tie) : RF_RIG_NONE;
        if (into != RF_RIG_NONE)
            src[i].joint = into, src[i].joint2 = RF_RIG_NONE;
        if (src[i].h == 0) {
            st->unseen_vertices++;
            src[i].h = -1.0 / (d0 * d0); /* kept for the part fallback below */
        }
    }
    for (uint32_t i = 0; i < p->proxy.nv; i++)
        src[i].h = src[i].h < 0 ? (lit[p->proxy_part[i]] ? 0 : -src[i].h) : src[i].h;
    free(tipless);
}

/* ---- the system ---- */

/* Area of triangle t and the cotangents of its three corners into cot[]. */
static double rf_rig_tri(const rf_rig_geo *g, uint32_t t, double cot[3])
{
    const double *v[3];
    for (int k = 0; k < 3; k++)
        v[k] = g->p + (size_t)g->t[t * 3 + k] * 3;
    double area = 0;
    for (int k = 0; k < 3; k++) {
        const double *o = v[k], *a = v[(k + 1) % 3], *b = v[(k + 2) % 3];
        double e1[3] = {a[0] - o[0], a[1] - o[1], a[2] - o[2]};
        double e2[3] = {b[0] - o[0], b[1] - o[1], b[2] - o[2]};
        double dot = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
        double cr[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                        e1[0] * e2[1] - e1[1] * e2[0]};
        double s = sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
        area = s / 2;
        /* obtuse corners and slivers would break the maximum principle (weights outside 0..1)
         * and the factorisation: keep each cotangent in [0, 1000] */
        cot[k] = s > 0 ? fmin(1000, fmax(0, dot / s)) : 0;
    }
    return area;
}

/* Builds L + A H (upper triangle) and solves it for every joint's right-hand side A H p_j. */
static bool rf_rig_solve(const rf_rig_geo *g, const rf_rig_src *src, uint32_t nj, double *w,
                         char *err, size_t n)
{
    cholmod_common cc;
    cholmod_start(&cc);
    cc.print = 0;
    size_t nnz = (size_t)g->nv + (size_t)g->nt * 6;
    cholmod_triplet *T = cholmod_allocate_triplet(g->nv, g->nv, nnz, 1, CHOLMOD_REAL, &cc);
    double *area = calloc(g->nv, sizeof *area);
    bool ok = T && area;
    size_t k = 0;
    int *ti = ok ? T->i : NULL, *tj = ok ? T->j : NULL;
    double *tx = ok ? T->x : NULL;
    double *diag = ok ? calloc(g->nv, sizeof *diag) : NULL;
    ok = ok && diag;
    for (uint32_t t = 0; ok && t < g->nt; t++) {
        double cot[3], a = rf_rig_tri(g, t, cot);
        for (int c = 0; c < 3; c++) {
            uint32_t u = g->t[t * 3 + (c + 1) % 3], v = g->t[t * 3 + (c + 2) % 3];
            /* the edge opposite corner c; a small uniform term keeps every edge connected */
            double e = cot[c] / 2 + 1e-3;
            ti[k] = (int)(u < v ? u : v), tj[k] = (int)(u < v ? v : u), tx[k++] = -e;
            diag[u] += e, diag[v] += e;
            area[g->t[t * 3 + c]] += a / 3;
        }
    }
    double mean = 0;
    for (uint32_t i = 0; ok && i < g->nv; i++)
        mean += diag[i] / g->nv;
    for (uint32_t i = 0; ok && i < g->nv; i++) {
        ti[k] = tj[k] = (int)i;
        tx[k++] = diag[i] + area[i] * src[i].h + 1e-9 * mean;
    }
    if (T)
        T->nnz = k;
    cholmod_sparse *A = ok ? cholmod_triplet_to_sparse(T, k, &cc) : NULL;
    cholmod_factor *L = A ? cholmod_analyze(A, &cc) : NULL;
    ok = L && cholmod_factorize(A, L, &cc) && cc.status == CHOLMOD_OK;
    cholmod_dense *B = ok ? cholmod_zeros(g->nv, nj, CHOLMOD_REAL, &cc) : NULL, *X = NULL;
    if (B) {
        double *bx = B->x;
        for (uint32_t i = 0; i < g->nv; i++) {
            double heat = area[i] * src[i].h;
            if (src[i].joint2 != RF_RIG_NONE)
                bx[(size_t)src[i].joint2 * g->nv + i] = heat / 2, heat /= 2;
            bx[(size_t)src[i].joint * g->nv + i] = heat;
        }
        X = cholmod_solve(CHOLMOD_A, L, B, &cc);
    }
    if (X) {
        const double *xx = X->x;
        for (uint32_t i = 0; i < g->nv; i++)
            for (uint32_t j = 0; j < nj; j++)
                w[(size_t)i * nj + j] = xx[(size_t)j * g->nv + i];
    } else if (!area || !diag || cc.status == CHOLMOD_OUT_OF_MEMORY) {
        ok = rf_rig_fail(err, n, "out of memory solving bone heat over %u vertices", g->nv);
    } else {
        ok = false;
        rf_rig_fail(err, n,
                    "the bone-heat system of %u vertices could not be solved (CHOLMOD "
                    "status %d)",
                    g->nv, cc.status);
    }
    cholmod_free_dense(&X, &cc), cholmod_free_dense(&B, &cc);
    cholmod_free_factor(&L, &cc), cholmod_free_sparse(&A, &cc), cholmod_free_triplet(&T, &cc);
    cholmod_finish(&cc);
    free(area), free(diag);
    return ok;
}

/* How much of each vertex's largest weight is taken off every weight of the vertex before the
 * row is normalised again: artists' weights are sharper than bone heat's (1.0 to 1.8 joints per
 * vertex above 0.15 of the largest on 21 of the 23 shared models, bone heat 1.1 to 2.3 at c = 2
 * with the artists' skeletons), and a raised heat c makes them sharper only by moving every
 * boundary. Taking a share off narrows each blend where it is (a vertex weighted 0.6 / 0.4
 * becomes 0.63 / 0.37, one at 0.83 / 0.17 or beyond moves with one joint) and is continuous
 * in the weights, so no seam appears where a weight is dropped. On the artists' own
 * skeletons, 0.2: precision 75.4% -> 80.6%, recall 86.7% -> 81.6%, L1 0.506 -> 0.476
 * (doc/autorig.md); bone heat then gives 1.0 to 1.6 joints per vertex. */
#define RF_RIG_SHARPEN 0.2

/* Rows made non-negative, sharpened and summing to 1; a row with no heat at all takes its
 * nearest bone. plain[] gets each row summing to 1 before it is sharpened (the part rules
 * below use it where sharpening would tear a part). */
static void rf_rig_normalise(const rf_rig_prep *p, const rf_rig_bone *bones, uint32_t nb,
                             uint32_t nj, double *w, double *plain, rf_rig_stats *st)
{
    for (uint32_t i = 0; i < p->proxy.nv; i++) {
        double *row = w + (size_t)i * nj, *raw = plain + (size_t)i * nj, sum = 0, most = 0;
        double total = 0;
        for (uint32_t j = 0; j < nj; j++) {
            most = fmax(most, row[j] = isfinite(row[j]) && row[j] > 1e-6 ? row[j] : 0);
            total += row[j];
        }
        for (uint32_t j = 0; j < nj; j++) {
            raw[j] = isfinite(total) && total > 1e-9 ? row[j] / total : 0;
            sum += row[j] = fmax(0, row[j] - RF_RIG_SHARPEN * most);
        }
        if (sum > 1e-9 && isfinite(sum)) {
            for (uint32_t j = 0; j < nj; j++)
                row[j] /= sum;
            st->heat_vertices++;
            continue;
        }
        double c[3], best = INFINITY;
        uint32_t to = 0;
        for (uint32_t b = 0; b < nb; b++) {
            double d = rf_rig_seg_dist(p->proxy.p + (size_t)i * 3, &bones[b], c);
            if (d < best)
                best = d, to = bones[b].joint;
        }
        memset(row, 0, nj * sizeof *row);
        row[to] = 1;
        memcpy(raw, row, nj * sizeof *row);
        st->fallback_vertices++;
    }
}

/* ---- loose parts enclosing bones ---- */

#define RF_RIG_SAMPLES 8 /* points per bone for the enclosure test */

/* The surfaces of each part a ray from q along d crosses, counted into crossings[part] (zeroed
 * by the caller); each part crossed is appended to crossed[*ncrossed] when its count leaves 0. */
static void rf_rig_cross(const rf_rig_rays *r, const double q[3], const float d[3], double far,
                         uint32_t *crossings, uint32_t *crossed, uint32_t *ncrossed)
{
    struct RTCRay ray = {0};
    ray.org_x = (float)q[0], ray.org_y = (float)q[1], ray.org_z = (float)q[2];
    ray.dir_x = d[0], ray.dir_y = d[1], ray.dir_z = d[2];
    ray.tnear = 0, ray.tfar = (float)far, ray.mask = UINT32_MAX;
    rf_rig_ray_ctx ctx = {.tri_part = r->tri_part,
                          .part = RF_RIG_NONE,
                          .crossings = crossings,
                          .crossed = crossed,
                          .ncrossed = ncrossed};
    rtcInitIntersectContext(&ctx.rtc);
    rtcOccluded1(r->scene, &ctx.rtc, &ray);
}

/* Which loose parts enclose point q: rays from q both ways along one oblique line (not along the
 * faces of an axis-aligned box) each cross an enclosing closed part's surface an odd number of
 * times; an open sheet (a cape) passes one way only. The counts into ahead[] and behind[], the
 * parts crossed into crossed[0..return value), perhaps twice. */
static uint32_t rf_rig_enclosing(const rf_rig_rays *r, const double q[3], double far,
                                 uint32_t *ahead, uint32_t *behind, uint32_t *crossed)
{
    static const float d[2][3] = {{0.5773f, 0.6172f, 0.5345f}, {-0.5773f, -0.6172f, -0.5345f}};
    uint32_t ncrossed = 0;
    rf_rig_cross(r, q, d[0], far, ahead, crossed, &ncrossed);
    rf_rig_cross(r, q, d[1], far, behind, crossed, &ncrossed);
    return ncrossed;
}

/* A row of weights kept to the joints whose bones the vertex's part encloses (held[j] > 0),
 * renormalised; a row with none of them left takes the joint holding the most. */
static void rf_rig_keep_enclosed(const double *held, uint32_t nj, double *row)
{
    double total = 0;
    uint32_t best = 0;
    for (uint32_t j = 0; j < nj; j++) {
        best = held[j] > held[best] ? j : best;
        total += row[j] = held[j] > 0 ? row[j] : 0;
    }
    for (uint32_t j = 0; j < nj; j++)
        row[j] = total > 0 ? row[j] / total : j == best;
}

/* The bone length each loose part encloses per joint, into held[part * nj + joint] and its sum
 * into sum[part]: points along each bone, each tested for the parts enclosing it. A bone whose
 * only point inside a part is its last (a torso's bone ending at a hip at the top of a leg box, a
 * neck's ending at the back of a head box) only reaches into that part and holds none of it.
 * inside[part] and touched[] are scratch. */
static void rf_rig_held(const rf_rig_rays *rays, const rf_rig_bone *bones, uint32_t nb, uint32_t nj,
                        double far, double *held, double *sum, uint32_t *ahead, uint32_t *behind,
                        uint32_t *crossed, uint32_t *inside, uint32_t *touched)
{
    for (uint32_t b = 0; b < nb; b++) {
        double len = 0;
        uint32_t ntouched = 0;
        for (int c = 0; c < 3; c++)
            len += (bones[b].b[c] - bones[b].a[c]) * (bones[b].b[c] - bones[b].a[c]);
        len = sqrt(len) / RF_RIG_SAMPLES;
        for (int k = 0; len > 0 && k < RF_RIG_SAMPLES; k++) {
            double t = (k + 0.5) / RF_RIG_SAMPLES, q[3];
            for (int c = 0; c < 3; c++)
                q[c] = bones[b].a[c] + t * (bones[b].b[c] - bones[b].a[c]);
            uint32_t n = rf_rig_enclosing(rays, q, far, ahead, behind, crossed);
            for (uint32_t x = 0; x < n; x++) {
                uint32_t part = crossed[x];
                if ((ahead[part] & 1) && (behind[part] & 1)) {
                    if (!inside[part])
                        touched[ntouched++] = part;
                    /* the count of points inside, and 1 << 16 when the last is */
                    inside[part] += 1 + (k == RF_RIG_SAMPLES - 1 ? 1u << 16 : 0);
                }
                ahead[part] = behind[part] = 0;
            }
        }
        for (uint32_t x = 0; x < ntouched; x++) {
            uint32_t part = touched[x], n = inside[part] & 0xffff;
            if (!(n == 1 && inside[part] >> 16))
                held[(size_t)part * nj + bones[b].joint] += n * len, sum[part] += n * len;
            inside[part] = 0;
        }
    }
}

/* The bone length each loose part encloses per joint (rf_rig_held): held[part * nj + joint] and
 * its sum over joints, sum[part]. Measured once per rig, for the front rule's parts
 * (rf_rig_front_parts) and the ownership rules (rf_rig_part_joints): the rays cost more than the
 * np * nj doubles kept between them. */
typedef struct rf_rig_enclosed {
    double *held, *sum;
} rf_rig_enclosed;

/* False when out of memory. */
static bool rf_rig_enclosed_make(const rf_rig_prep *p, const rf_rig_rays *rays,
                                 const rf_rig_bone *bones, uint32_t nb, uint32_t nj,
                                 rf_rig_enclosed *e)
{
    uint32_t np = p->proxy_parts;
    e->held = calloc((size_t)np * nj + 1, sizeof *e->held);
    e->sum = calloc(np + 1, sizeof *e->sum);
    uint32_t *ahead = calloc(np + 1, sizeof *ahead), *behind = calloc(np + 1, sizeof *behind);
    uint32_t *crossed = malloc((2 * (size_t)np + 1) * sizeof *crossed);
    uint32_t *inside = calloc(np + 1, sizeof *inside),
             *touched = malloc((np + 1) * sizeof *touched);
    bool ok = e->held && e->sum && ahead && behind && crossed && inside && touched;
    if (ok)
        rf_rig_held(rays, bones, nb, nj, 4 * p->longest, e->held, e->sum, ahead, behind, crossed,
                    inside, touched);
    free(ahead), free(behind), free(crossed), free(inside), free(touched);
    return ok;
}

static void rf_rig_enclosed_free(rf_rig_enclosed *e)
{
    free(e->held), free(e->sum);
    e->held = e->sum = NULL;
}

/* Clears the outward normals of the vertices of loose parts that enclose no bone (`e`), so the
 * test of bones in front of the surface (rf_rig_in_front) is off there: its premise, a bone seen
 * from inside the surface around it, holds only for a part around a bone. Every bone lies
 * outside a strand of hair or a tuft, so half its vertices passed the nearest bone over and took
 * one beyond it: Testwuson's tail tuft flew off its tip under the CMU walk (worst part 75.7 ->
 * 867.4). */
static void rf_rig_front_parts(const rf_rig_prep *p, const rf_rig_enclosed *e, double *nrm)
{
    for (uint32_t i = 0; p->proxy_parts > 1 && i < p->proxy.nv; i++)
        if (!(e->sum[p->proxy_part[i]] > 0))
            memset(nrm + (size_t)i * 3, 0, 3 * sizeof *nrm);
}

static int rf_rig_edge_cmp(const void *pa, const void *pb)
{
    const uint64_t *a = pa, *b = pb;
    return *a < *b ? -1 : *a > *b;
}

/* Marks open[part] for each loose part with an edge on one triangle only (a sheet, a cape, a
 * skirt open at its hem, a wing's membrane) or no volume inside it (a sheet made double-sided,
 * every edge on two triangles back to back). vol[part] (zeroed by the caller) gets the signed
 * volume the part's triangles hold, positive when they face out, 0 for a part holding none (a
 * part with a few holes still holds about its volume). False when out of memory. */
static bool rf_rig_open_parts(const rf_rig_prep *p, uint8_t *open, double *vol)
{
    size_t ne = (size_t)p->proxy.nt * 3;
    uint64_t *e = malloc((ne + 1) * sizeof *e);
    double *area = calloc(p->proxy_parts + 1, sizeof *area);
    if (!e || !area) {
        free(e), free(area);
        return false;
    }
    for (size_t t = 0; t < p->proxy.nt; t++) {
        double q[3][3], cot[3]; /* the corners from the proxy's box corner, for precision */
        for (int k = 0; k < 3; k++)
            for (int c = 0; c < 3; c++)
                q[k][c] = p->proxy.p[(size_t)p->proxy.t[t * 3 + k] * 3 + c] - p->lo[c];
        uint32_t part = p->proxy_part[p->proxy.t[t * 3]];
        /* the signed volume of the tetrahedron from the box corner, summed over a closed
         * surface, is the volume it holds */
        vol[part] += (q[0][0] * (q[1][1] * q[2][2] - q[1][2] * q[2][1]) -
                      q[0][1] * (q[1][0] * q[2][2] - q[1][2] * q[2][0]) +
                      q[0][2] * (q[1][0] * q[2][1] - q[1][1] * q[2][0])) /
                     6;
        area[part] += rf_rig_tri(&p->proxy, (uint32_t)t, cot);
        for (int k = 0; k < 3; k++) {
            uint64_t u = p->proxy.t[t * 3 + k], v = p->proxy.t[t * 3 + (k + 1) % 3];
            e[t * 3 + k] = u < v ? u << 32 | v : v << 32 | u;
        }
    }
    qsort(e, ne, sizeof *e, rf_rig_edge_cmp);
    for (size_t i = 0; i < ne;) {
        size_t k = i;
        while (k < ne && e[k] == e[i])
            k++;
        if (k - i == 1)
            open[p->proxy_part[e[i] >> 32]] = 1;
        i = k;
    }
    /* a sphere holds 0.094 A^1.5, a box a hundred times thinner than it is wide 0.003 */
    for (uint32_t q = 0; q < p->proxy_parts; q++)
        if (!(fabs(vol[q]) > 1e-5 * pow(area[q], 1.5)))
            open[q] = 1, vol[q] = 0;
    free(e), free(area);
    return true;
}

/* Which loose parts lie around a bone: a line through some point of it (its ends included) meets
 * the part on both sides, along one of three oblique directions. A skirt or a cuff around a leg
 * is, though it encloses nothing (it is open); a horn, an ear or a membrane beside the bones is
 * not. Marks around[part]; ahead, behind and crossed as for rf_rig_enclosing. */
static void rf_rig_around(const rf_rig_rays *rays, const rf_rig_bone *bones, uint32_t nb,
                          double far, uint32_t *ahead, uint32_t *behind, uint32_t *crossed,
                          uint8_t *around)
{
    static const float d[3][3] = {
        {0.5773f, 0.6172f, 0.5345f}, {-0.6172f, 0.5345f, 0.5773f}, {0.5345f, -0.5773f, 0.6172f}};
    for (uint32_t b = 0; b < nb; b++)
        for (int k = 0; k <= RF_RIG_SAMPLES; k++) {
            double t = (double)k / RF_RIG_SAMPLES, q[3];
            for (int c = 0; c < 3; c++)
                q[c] = bones[b].a[c] + t * (bones[b].b[c] - bones[b].a[c]);
            for (int l = 0; l < 3; l++) {
                float back[3] = {-d[l][0], -d[l][1], -d[l][2]};
                uint32_t n = 0;
                rf_rig_cross(rays, q, d[l], far, ahead, crossed, &n);
                rf_rig_cross(rays, q, back, far, behind, crossed, &n);
                for (uint32_t x = 0; x < n; x++) {
                    uint32_t part = crossed[x];
                    around[part] |= ahead[part] && behind[part];
                    ahead[part] = behind[part] = 0;
                }
            }
        }
}

/* A closed loose part that encloses no bone (an ear, a horn, a box on a box model's head) is
 * moved rigidly by the joint bone heat gives more than half of its surface to (area-weighted),
 * as artists bind such pieces: blended between the bones near it, it shears as they turn. A
 * part split evenly keeps its blend, as no joint has the better claim, and so do the parts
 * marked in bends[]: those lying around a bone (a cuff) and open ones (a cape, a skirt, a wing's
 * membrane), which bend with the joints under them. sum[part] is the bone length the part
 * encloses; owner[] is set for the parts taken. False when out of memory. */
static bool rf_rig_boneless_owners(const rf_rig_prep *p, const uint8_t *bends, const double *sum,
                                   uint32_t largest, uint32_t nj, const double *w, uint32_t *owner)
{
    uint32_t np = p->proxy_parts, nfree = 0;
    uint32_t *slot = malloc(((size_t)np + 1) * sizeof *slot);
    if (!slot)
        return false;
    for (uint32_t q = 0; q < np; q++)
        slot[q] = q != largest && !(sum[q] > 0) && !bends[q] ? nfree++ : RF_RIG_NONE;
    /* [slot][joint] the part's surface area times each joint's weight, the total in [slot][nj] */
    double *tot = calloc((size_t)nfree * (nj + 1) + 1, sizeof *tot);
    if (!tot) {
        free(slot);
        return false;
    }
    for (uint32_t t = 0; t < p->proxy.nt; t++) {
        const uint32_t *v = p->proxy.t + (size_t)t * 3;
        uint32_t at = slot[p->proxy_part[v[0]]];
        double cot[3], a = at == RF_RIG_NONE ? 0 : rf_rig_tri(&p->proxy, t, cot) / 3;
        for (int c = 0; a > 0 && c < 3; c++) {
            double *row = tot + (size_t)at * (nj + 1);
            for (uint32_t j = 0; j < nj; j++)
                row[j] += a * w[(size_t)v[c] * nj + j];
            row[nj] += a;
        }
    }
    for (uint32_t q = 0; q < np; q++) {
        if (slot[q] == RF_RIG_NONE)
            continue;
        const double *row = tot + (size_t)slot[q] * (nj + 1);
        uint32_t best = 0;
        for (uint32_t j = 1; j < nj; j++)
            best = row[j] > row[best] ? j : best;
        if (row[nj] > 0 && row[best] > 0.5 * row[nj] * (1 + 1e-9))
            owner[q] = best;
    }
    free(tot), free(slot);
    return true;
}

static uint32_t rf_rig_root(uint32_t *uf, uint32_t q)
{
    while (uf[q] != q)
        q = uf[q] = uf[uf[q]];
    return q;
}

/* The loose parts of each prop (rf_rig_props) into uf[] (union-find roots), its members' count
 * into members[root] and whether they already move with one joint (owner[], the same for all)
 * into agree[root]; the surface of the members that bend (bends[]: open, or lying around a bone)
 * into bent[root], of the others into whole[root]. */
static void rf_rig_prop_parts(const rf_rig_prep *p, const uint32_t *touch, const uint8_t *boneless,
                              const uint8_t *bends, const double *area, const uint32_t *owner,
                              uint32_t *uf, uint32_t *members, uint8_t *agree, double *whole,
                              double *bent)
{
    uint32_t np = p->proxy_parts;
    for (uint32_t q = 0; q < np; q++)
        uf[q] = q, members[q] = 0, agree[q] = 1;
    for (uint32_t i = 0; i < p->proxy.nv; i++) {
        uint32_t a = p->proxy_part[i];
        if (boneless[a] && touch[i] != RF_RIG_NONE && boneless[p->proxy_part[touch[i]]])
            uf[rf_rig_root(uf, a)] = rf_rig_root(uf, p->proxy_part[touch[i]]);
    }
    for (uint32_t q = 0; q < np; q++) {
        if (!boneless[q])
            continue;
        uint32_t g = rf_rig_root(uf, q);
        (bends[q] ? bent : whole)[g] += area[q];
        members[g]++;
    }
    /* every member's owner against the root's */
    for (uint32_t q = 0; q < np; q++)
        if (boneless[q])
            agree[rf_rig_root(uf, q)] &=
                owner[q] != RF_RIG_NONE && owner[q] == owner[rf_rig_root(uf, q)];
}

/* Loose parts enclosing no bone that touch one another (a vertex within a hundredth of the
 * longest edge of another's) make one prop: a staff's shaft, the wrap at its grip and the
 * pieces of its head. A prop of two pieces or more that do not already move with one joint,
 * touching a part that encloses bones (not the body: the staff the rigger ran a bone along, the
 * hand holding it), moves with one joint, the one weighted most on that part's vertices where
 * the prop touches it most, so it stays whole: each piece taken alone went with the joint bone
 * heat gave it most or kept its blend, and the auto-rigged Wizard's staff came apart, its head
 * with the forearm and its shaft with the hand (worst seam 37.0 -> 13.1 under the CMU walk). A
 * prop made mostly of open parts (a cape with a brooch) keeps its weights and bends. Only the
 * rigger's own rigs: on the artists' skeletons the pieces' own joints were measured better
 * (doc/autorig-log.md, "Skinning, round five"). sum[] and area[] per part, bends[] the open
 * parts and those lying around a bone, owner[] the joint moving each part alone. False when out
 * of memory. */
static bool rf_rig_props(const rf_rig_prep *p, uint32_t largest, const double *sum,
                         const uint8_t *bends, const double *area, const uint32_t *owner,
                         uint32_t nj, double *w)
{
    uint32_t np = p->proxy_parts, nv = p->proxy.nv, npairs = 0, nslots = 0, best = 0;
    rf_rig_near *gr = rf_rig_near_new(p);
    uint32_t *touch = malloc(((size_t)nv + 1) * sizeof *touch);
    uint32_t *uf = malloc(((size_t)np + 1) * sizeof *uf), *host = malloc((np + 1) * sizeof *host);
    uint32_t *members = malloc(((size_t)np + 1) * sizeof *members);
    uint32_t *slot = malloc(((size_t)np + 1) * sizeof *slot);
    uint64_t *pairs = malloc(((size_t)nv + 1) * sizeof *pairs);
    double *bent = calloc(np + 1, sizeof *bent), *whole = calloc(np + 1, sizeof *whole);
    uint8_t *boneless = calloc(np + 1, 1), *agree = malloc(np + 1);
    bool ok =
        gr && touch && uf && host && members && slot && pairs && bent && whole && boneless && agree;
    for (uint32_t q = 0; ok && q < np; q++)
        boneless[q] = q != largest && !(sum[q] > 0), host[q] = RF_RIG_NONE;
    if (ok) {
        rf_rig_near_touch(gr, p->proxy_part, boneless, largest, 0.01 * p->longest, touch);
        rf_rig_prop_parts(p, touch, boneless, bends, area, owner, uf, members, agree, whole, bent);
    }
    /* the part holding bones each prop touches with the most vertices */
    for (uint32_t i = 0; ok && i < nv; i++) {
        uint32_t a = p->proxy_part[i], b = touch[i] != RF_RIG_NONE ? p->proxy_part[touch[i]] : a;
        if (boneless[a] && sum[b] > 0)
            pairs[npairs++] = (uint64_t)rf_rig_root(uf, a) << 32 | b;
    }
    if (ok)
        qsort(pairs, npairs, sizeof *pairs, rf_rig_edge_cmp);
    for (uint32_t k = 0; ok && k < npairs;) {
        uint32_t e = k, g = (uint32_t)(pairs[k] >> 32);
        while (e < npairs && pairs[e] == pairs[k])
            e++;
        best = k == 0 || (uint32_t)(pairs[k - 1] >> 32) != g ? 0 : best;
        if (e - k > best && members[g] >= 2 && !agree[g] && whole[g] > bent[g])
            best = e - k, host[g] = (uint32_t)pairs[k];
        k = e;
    }
    for (uint32_t q = 0; ok && q < np; q++)
        slot[q] = host[q] != RF_RIG_NONE ? nslots++ : RF_RIG_NONE;
    double *row = ok ? calloc((size_t)nslots * nj + 1, sizeof *row) : NULL;
    ok = ok && row;
    for (uint32_t i = 0; ok && i < nv; i++) { /* the holder's weights where the prop touches it */
        uint32_t a = p->proxy_part[i], g = boneless[a] ? rf_rig_root(uf, a) : RF_RIG_NONE;
        if (g != RF_RIG_NONE && slot[g] != RF_RIG_NONE && touch[i] != RF_RIG_NONE &&
            p->proxy_part[touch[i]] == host[g])
            for (uint32_t j = 0; j < nj; j++)
                row[(size_t)slot[g] * nj + j] += w[(size_t)touch[i] * nj + j];
    }
    for (uint32_t i = 0; ok && i < nv; i++) {
        uint32_t a = p->proxy_part[i], g = boneless[a] ? rf_rig_root(uf, a) : RF_RIG_NONE, j = 0;
        if (g == RF_RIG_NONE || slot[g] == RF_RIG_NONE)
            continue;
        const double *r = row + (size_t)slot[g] * nj;
        for (uint32_t c = 1; c < nj; c++)
            j = r[c] > r[j] ? c : j;
        memset(w + (size_t)i * nj, 0, nj * sizeof *w);
        w[(size_t)i * nj + j] = 1;
    }
    rf_rig_near_free(gr);
    free(touch), free(uf), free(host), free(members), free(slot), free(pairs), free(bent);
    free(whole), free(boneless), free(agree), free(row);
    return ok;
}

/* Whether bone heat gives joint j more than half of loose part q (the mean of its vertices'
 * weights). */
static bool rf_rig_heat_agrees(const rf_rig_prep *p, uint32_t q, uint32_t nj, const double *w,
                               uint32_t j)
{
    double share = 0, n = 0;
    for (uint32_t i = 0; i < p->proxy.nv; i++)
        if (p->proxy_part[i] == q)
            share += w[(size_t)i * nj + j], n++;
    return share > 0.5 * n;
}

/* Whether loose part q holds bones (sum [part]) with fewer than four vertices (verts [part]) for
 * each joint whose bones it holds (held [part][nj]). */
static bool rf_rig_low_poly(const double *held, const double *sum, const uint32_t *verts,
                            uint32_t nj, uint32_t q)
{
    uint32_t joints = 0;
    for (uint32_t j = 0; j < nj; j++)
        joints += held[(size_t)q * nj + j] > 0;
    return sum[q] > 0 && verts[q] < 4 * joints;
}

/* Whether loose part q is a low-poly box holding the bones of more joints than it can bend at:
 * not the body, not moved by one joint already, and with fewer than four vertices for each joint
 * whose bones it holds (a piece modelled to bend has four or more, RF_RIG_PIECE_JOINTS). A box of
 * four-sided rings bends only at a ring, and fewer rings than joints cannot follow them: an
 * eight-corner leg box holding a cat's hips' bone and four leg bones, a horse's lower leg of
 * three rings holding five. Eight corners around the bones of two joints stay blended: the
 * artists of the animalia bird and owl blend such a box. */
static bool rf_rig_is_box(const double *held, const double *sum, const uint32_t *owner,
                          const uint32_t *verts, uint32_t largest, uint32_t nj, uint32_t q)
{
    return q != largest && owner[q] == RF_RIG_NONE && rf_rig_low_poly(held, sum, verts, nj, q);
}

/* A low-poly body box moves with the joints holding most of the bone length inside it, not
 * with the limbs whose first bones reach into it from parts of their own: blended among all of
 * them, the bull frog's body box (8 corners, 12 joints) was dragged flat by its legs' roots
 * under a walk. Its rows (w [nv][nj]) drop the joints holding under RF_RIG_BODY_HOLDS of the
 * most any one holds there that another part holds bones of and moves with (held [part][nj],
 * owner [part]); a limb modelled with the body (the animalia fox's legs) keeps its weights, as
 * does one whose part moves with another joint (the animalia bat's), having no other skin. */
#define RF_RIG_BODY_HOLDS 0.25

static bool rf_rig_body_box_keep(const rf_rig_prep *p, const double *held, const uint32_t *owner,
                                 uint32_t nj, uint32_t part, double *w)
{
    const double *h = held + (size_t)part * nj;
    double *keep = malloc((nj + 1) * sizeof *keep), most = 0;
    if (!keep)
        return false;
    for (uint32_t j = 0; j < nj; j++)
        most = fmax(most, h[j]);
    for (uint32_t j = 0; j < nj; j++) {
        bool elsewhere = false;
        for (uint32_t q = 0; q < p->proxy_parts && !elsewhere; q++)
            elsewhere = q != part && held[(size_t)q * nj + j] > 0 &&
                        (owner[q] == RF_RIG_NONE || owner[q] == j);
        /* kept joints count as holding; the one holding most takes a row left empty */
        keep[j] = h[j] >= RF_RIG_BODY_HOLDS * most || !elsewhere ? 1 + h[j] : 0;
    }
    for (uint32_t i = 0; i < p->proxy.nv; i++)
        if (p->proxy_part[i] == part)
            rf_rig_keep_enclosed(keep, nj, w + (size_t)i * nj);
    free(keep);
    return true;
}

/* Whether a box standing on the floor lies splayed: the bones it holds (held, [nj]; to a child
 * and to a leaf's tip) reach within a twentieth of the body's height of its lowest point, and
 * their rise along up, summed, is under seven tenths of their length. A leg box moved by one
 * joint swings as a column under its pivot, as the animalia cat's, horse's, wolf's and fox's
 * do (rise nine tenths of their length and more); a box lying splayed (the bull frog's, about
 * half) carries its leg's folds and foot sideways along the floor, and moved by one joint the
 * rig loses the foot the retarget pins and the skeleton analysis reads the facing from (after
 * the matcher .676 / .759 -> .654 / .692): it keeps its blend. Boxes off the floor (a head's,
 * a tail's) are not asked. */
static bool rf_rig_splayed(const rf_rig_prep *p, const rf_rig_skel *s, const double *held,
                           rf_vec3 up)
{
    double lo = INFINITY, hi = -INFINITY, len = 0, rise = 0, low = INFINITY;
    for (uint32_t i = 0; i < p->proxy.nv; i++) {
        double h = rf_rig_along(p->proxy.p + (size_t)i * 3, up);
        lo = fmin(lo, h), hi = fmax(hi, h);
    }
    for (uint32_t c = 0; c < 2 * s->n; c++) { /* bones to a child, then to a leaf's tip */
        int32_t j = c < s->n ? s->parent[c] : (int32_t)(c - s->n);
        if (j < 0 || !(held[j] > 0) || (c >= s->n && !s->has_tip[j]))
            continue;
        const double *a = s->pos + (size_t)j * 3;
        const double *b = c < s->n ? s->pos + (size_t)c * 3 : s->tip + (size_t)j * 3;
        double d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        len += sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        rise += fabs(rf_rig_along(d, up));
        low = fmin(low, fmin(rf_rig_along(a, up), rf_rig_along(b, up)));
    }
    return len > 0 && low - lo <= 0.05 * (hi - lo) && rise < 0.7 * len;
}

/* Whether joint p of s has exactly one child. */
static bool rf_rig_only_child(const rf_rig_skel *s, int32_t p)
{
    uint32_t kids = 0;
    for (uint32_t c = 0; c < s->n && kids < 2; c++)
        kids += s->parent[c] == p;
    return kids == 1;
}

/* The joint a low-poly box moves with alone: the deepest joint whose bones below it, its own
 * included, hold more than half the bone length inside the box (h, [nj], total its sum), where
 * the bones inside it are split in half along the chain; the joint holding the most may be the
 * hips, whose bone runs into the top of a cat's leg box ahead of the leg's four short bones. That
 * joint must pivot inside the box, its parent's bone held there too: a bone entering a box from
 * a pivot outside it (the hips' into the animalia fox's tail box) is the body's, and the box
 * keeps its blend (RF_RIG_NONE; after the matcher .72 / .73 on the fox, .85 / .86 kept). sub is
 * scratch, [nj]. */
static uint32_t rf_rig_box_owner(const rf_rig_skel *s, const double *h, double total, double *sub)
{
    uint32_t nj = s->n, owner = RF_RIG_NONE;
    memcpy(sub, h, nj * sizeof *sub);
    for (uint32_t c = nj; c-- > 0;)
        if (s->parent[c] >= 0)
            sub[s->parent[c]] += sub[c];
    for (uint32_t j = 0; j < nj; j++)
        if (h[j] > 0 && sub[j] > 0.5 * total && (owner == RF_RIG_NONE || sub[j] < sub[owner]))
            owner = j;
    if (owner == RF_RIG_NONE || !(s->parent[owner] >= 0 && h[s->parent[owner]] > 0))
        return RF_RIG_NONE;
    /* up through short links wholly inside the box, each under a fifth of the bone length the
     * box holds below the joint: the curve skeleton leaves such links where a limb leaves the
     * body (the cat's foreleg, 0.02 and 0.04 over a leg of 0.25); below the box's joint they
     * would bend nothing, and a file read back flags them as joints without skin, which the
     * matcher leaves out of the leg */
    for (int32_t p = s->parent[owner]; p >= 0 && rf_rig_only_child(s, p); p = s->parent[owner]) {
        double link = rf_rig_dist3(s->pos + (size_t)p * 3, s->pos + (size_t)owner * 3);
        if (!(h[p] >= 0.999 * link && link < 0.2 * sub[owner]))
            break;
        owner = (uint32_t)p;
    }
    return owner;
}

/* Flags in boxed[] the joints below `owner` whose bones the box it moves (h, [nj]) holds: they
 * bend nothing of it. */
static void rf_rig_mark_boxed(const rf_rig_skel *s, const double *h, uint32_t owner, uint8_t *boxed)
{
    for (uint32_t j = owner + 1; j < s->n; j++) {
        int32_t a = s->parent[j];
        while (a > (int32_t)owner) /* parents come first: an ancestor's index is smaller */
            a = s->parent[a];
        if (a == (int32_t)owner && h[j] > 0)
            boxed[j] = 1;
    }
}

/* A part enclosing the bones of this many joints or more, with at least four vertices for each,
 * is a piece modelled to deform (a head carrying a jaw, lips, eyes and a ponytail; an arm with
 * its hand), not a box: the boxes of the artists' box models hold the bones of one to four
 * joints, and a box of eight corners holding many of the rigger's own short bones cannot bend
 * between them; BCN_Epileptic's head holds eleven joints' bones in 874 vertices. */
#define RF_RIG_PIECE_JOINTS 5

/* Whether the joints whose bones a part holds (held[j] > 0) branch in it: some joint has two
 * children or more among them (a neck carrying a jaw, lips, eyes and a ponytail; a hand its
 * fingers), not one chain (a spider's loose leg). seen is scratch, [n]. */
static bool rf_rig_branches(const rf_rig_skel *s, const double *held, uint8_t *seen)
{
    bool branch = false;
    memset(seen, 0, s->n);
    for (uint32_t c = 0; c < s->n && !branch; c++) {
        int32_t j = s->parent[c];
        if (j < 0 || !(held[c] > 0))
            continue;
        branch = seen[j];
        seen[j] = 1;
    }
    return branch;
}

/* A loose part that encloses bones is moved by the joints whose bones it encloses, and only by
 * them: a sleeve over an elbow by the upper arm and the forearm, not by the chest beside it.
 * When one joint holds seven tenths of the bone length inside it or more, by that joint alone,
 * as the boxes of a low-poly model are bound: bone heat blends such a box between the bones it
 * touches and shears it. Blended between its own joints, such a part keeps bone heat's plain
 * rows (plain[], not sharpened): sharpening sends each corner of a box to the joint nearest
 * it, a thigh box's top corners to the hips and its bottom ones to the knee, and tears the box
 * into a wedge as they turn. A part enclosing the bones of RF_RIG_PIECE_JOINTS joints or more
 * is blended among its own joints and never moved by one alone: a head holding the neck's bone
 * and the short bones of its face and jaw would go stiff with the neck. Where its joints branch
 * (a face fanning from the neck, fingers from a hand) it keeps the sharpened rows, as the body
 * does: each face joint then owns its region as the artists give it (BCN_Epileptic 72% -> 74%
 * precision on its artist's skeleton). Where they run as one chain it takes the plain rows:
 * sharpened, a loose spider leg of five joints' bones was drawn into a spike under the CMU walk.
 * A low-poly box holding more joints' bones than it has rings to bend at moves with the joint
 * pivoting inside it where its bones split in half (rf_rig_is_box, rf_rig_box_owner): blended, an
 * animalia cat's leg boxes and a horse's lower legs sheared into wedges under the CMU walk. Not
 * in a layout whose joints must all keep skin (o->keep_joints, the template's): the joints below
 * that one would move nothing, and the general rigger drops them (rf_rig_prune in rig.c).
 * The part with the largest surface (the body) moves with one joint only when bone heat
 * agrees, giving that joint more than half of it: a box model's body box holding the torso's
 * bone (the animalia bird's, the owl's), a robot's head piece holding the head's; a bat's body
 * box, which holds the torso's bone but carries the roots of the head and the wings, keeps its
 * weights; a low-poly body box not moved by one joint sheds the limbs reaching into it from
 * parts of their own (rf_rig_body_box_keep). A closed part enclosing no bone moves with the joint
 * bone heat gives most of it (rf_rig_boneless_owners); an open one keeps its weights. */
static bool rf_rig_part_joints(const rf_rig_prep *p, const rf_rig_rays *rays, const rf_rig_skel *s,
                               const rf_rig_bone *bones, uint32_t nb, const rf_rig_enclosed *e,
                               double *w, const double *plain, const rf_rig_options *o,
                               uint8_t *boxed)
{
    uint32_t nj = s->n;
    uint32_t np = p->proxy_parts;
    const double *held = e->held, *sum = e->sum;
    uint32_t *ahead = calloc(np + 1, sizeof *ahead), *behind = calloc(np + 1, sizeof *behind);
    uint32_t *crossed = malloc((2 * (size_t)np + 1) * sizeof *crossed);
    double *area = calloc(np + 1, sizeof *area);
    uint32_t *owner = malloc((np + 1) * sizeof *owner);
    uint8_t *bends =
        calloc(np + 1, 1); /* parts that keep bone heat's blend (rf_rig_boneless_owners) */
    /* parts holding RF_RIG_PIECE_JOINTS joints' bones; 2 set where those joints branch */
    uint8_t *piece = calloc(np + 1, 1), *seen = malloc(nj + 1);
    bool ok = ahead && behind && crossed && area && owner && bends && piece && seen;
    if (ok)
        rf_rig_around(rays, bones, nb, 4 * p->longest, ahead, behind, crossed, bends);
    double *vol = ok ? calloc(np + 1, sizeof *vol) : NULL;
    ok = ok && vol && rf_rig_open_parts(p, bends, vol);
    free(vol);
    uint32_t largest = 0, *verts = ok ? calloc(np + 1, sizeof *verts) : NULL;
    ok = ok && verts;
    for (uint32_t i = 0; ok && i < p->proxy.nv; i++)
        verts[p->proxy_part[i]]++;
    for (uint32_t t = 0; ok && t < p->proxy.nt; t++) {
        double cot[3];
        area[p->proxy_part[p->proxy.t[t * 3]]] += rf_rig_tri(&p->proxy, t, cot);
    }
    for (uint32_t part = 0; ok && part < np; part++) {
        largest = area[part] > area[largest] ? part : largest;
        owner[part] = RF_RIG_NONE;
        const double *h = held + (size_t)part * nj;
        uint32_t best = 0, joints = h[0] > 0;
        for (uint32_t j = 1; j < nj; j++)
            best = h[j] > h[best] ? j : best, joints += h[j] > 0;
        piece[part] = joints >= RF_RIG_PIECE_JOINTS && verts[part] >= 4 * joints;
        piece[part] |= piece[part] && rf_rig_branches(s, h, seen) ? 2 : 0;
        if (sum[part] > 0 && h[best] >= 0.7 * sum[part] && !piece[part])
            owner[part] = best;
    }
    if (ok && owner[largest] != RF_RIG_NONE &&
        !rf_rig_heat_agrees(p, largest, nj, w, owner[largest]))
        owner[largest] = RF_RIG_NONE;
    double *sub = ok ? malloc((nj + 1) * sizeof *sub) : NULL;
    ok = ok && sub;
    for (uint32_t q = 0; ok && q < np; q++)
        if (!o->keep_joints && rf_rig_is_box(held, sum, owner, verts, largest, nj, q) &&
            !rf_rig_splayed(p, s, held + (size_t)q * nj, rf_v3_normalize(o->up))) {
            owner[q] = rf_rig_box_owner(s, held + (size_t)q * nj, sum[q], sub);
            if (boxed && owner[q] != RF_RIG_NONE)
                rf_rig_mark_boxed(s, held + (size_t)q * nj, owner[q], boxed);
        }
    free(sub);
    ok = ok && rf_rig_boneless_owners(p, bends, sum, largest, nj, w, owner);
    for (uint32_t i = 0; ok && i < p->proxy.nv; i++)
        if (p->proxy_part[i] != largest && sum[p->proxy_part[i]] > 0 &&
            owner[p->proxy_part[i]] == RF_RIG_NONE) {
            if (!(piece[p->proxy_part[i]] & 2))
                memcpy(w + (size_t)i * nj, plain + (size_t)i * nj, nj * sizeof *w);
            rf_rig_keep_enclosed(held + (size_t)p->proxy_part[i] * nj, nj, w + (size_t)i * nj);
        }
    if (ok && owner[largest] == RF_RIG_NONE && rf_rig_low_poly(held, sum, verts, nj, largest))
        ok = rf_rig_body_box_keep(p, held, owner, nj, largest, w);
    for (uint32_t i = 0; ok && i < p->proxy.nv; i++) {
        uint32_t j = owner[p->proxy_part[i]];
        if (j == RF_RIG_NONE)
            continue;
        memset(w + (size_t)i * nj, 0, nj * sizeof *w);
        w[(size_t)i * nj + j] = 1;
    }
    ok = ok && (o->given_bones || rf_rig_props(p, largest, sum, bends, area, owner, nj, w));
    free(ahead), free(behind), free(crossed), free(area), free(owner);
    free(bends), free(piece), free(verts), free(seen);
    return ok;
}

bool rf_rig_heat(const rf_rig_prep *p, const rf_rig_skel *s, const rf_rig_options *o, double **w,
                 uint8_t *boxed, rf_rig_stats *st, char *err, size_t n)
{
    uint64_t available = 0;
    bool known = rf_memory_available(&available);
    *w = NULL;
    if (!rf_rig_heat_fits(p->proxy.nv, s->n, known, available, err, n))
        return false;
    rf_rig_bone *bones = NULL;
    uint32_t nb = rf_rig_bones(s, &bones), nj = s->n;
    rf_rig_src *src = malloc((size_t)p->proxy.nv * sizeof *src);
    rf_rig_bd *bd = malloc((size_t)(nb ? nb : 1) * sizeof *bd);
    uint8_t *lit = calloc(p->proxy_parts + 1, 1);
    *w = calloc((size_t)p->proxy.nv * nj, sizeof **w);
    double *plain = NULL; /* taken once the solver's arrays are freed: the peak stays theirs */
    double *nrm = NULL;   /* outward normals for rf_rig_in_front (the rigger's own bones) */
    rf_rig_rays rays = {0};
    rf_rig_enclosed enc = {0}; /* which loose parts enclose which bones: two rules read it */
    bool ok = nb && src && bd && lit && *w;
    if (!ok)
        rf_rig_fail(err, n, "out of memory weighting %u vertices", p->proxy.nv);
    if (ok && !rf_rig_rays_make(&rays, &p->proxy, p->proxy_part))
        ok = rf_rig_fail(err, n, "out of memory building the ray-casting scene (Embree)");
    if (ok && p->proxy_parts > 1 && !rf_rig_enclosed_make(p, &rays, bones, nb, nj, &enc))
        ok = rf_rig_fail(err, n, "out of memory weighting %u vertices", p->proxy.nv);
    if (ok && !o->given_bones &&
        !((nrm = malloc(((size_t)p->proxy.nv + 1) * 3 * sizeof *nrm)) && rf_rig_normals(p, nrm)))
        ok = rf_rig_fail(err, n, "out of memory weighting %u vertices", p->proxy.nv);
    if (ok && !o->given_bones)
        rf_rig_front_parts(p, &enc, nrm);
    if (ok) {
        rf_rig_sources(p, bones, nb, o->no_visibility ? NULL : &rays, o->leaf_points_own, nrm, src,
                       bd, lit, st);
        free(nrm), nrm = NULL;
        ok = rf_rig_solve(&p->proxy, src, nj, *w, err, n);
    }
    if (ok && !(plain = malloc(((size_t)p->proxy.nv * nj + 1) * sizeof *plain)))
        ok = rf_rig_fail(err, n, "out of memory weighting %u vertices", p->proxy.nv);
    if (ok)
        rf_rig_normalise(p, bones, nb, nj, *w, plain, st);
    if (ok && p->proxy_parts > 1 &&
        !rf_rig_part_joints(p, &rays, s, bones, nb, &enc, *w, plain, o, boxed))
        ok = rf_rig_fail(err, n, "out of memory weighting %u vertices", p->proxy.nv);
    rf_rig_rays_free(&rays);
    rf_rig_enclosed_free(&enc);
    free(bones), free(src), free(bd), free(lit), free(plain), free(nrm);
    if (!ok)
        free(*w), *w = NULL;
    return ok;
}
