/* Volume kept: how far each closed loose part of a skinned mesh strays from its rest volume as a
 * clip poses it. A part a person sees as a solid (a low-poly box, a boot, a head) keeps its
 * volume when it moves whole, bends a little at a joint or shears; blended between joints that
 * turn apart it is crushed or blown up, and flattened it loses most of it. Edge stretch reads such
 * a box like any bent knee (the bull frog's body box dragged flat by its legs' roots: stretch
 * p99 55.6% of the height, within the walks of sound rigs) and torn limbs not at all (no seam
 * crosses a loose part), so this is the figure that sees it. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rt-internal.h"

/* A closed part is measured when its rest volume is at least this share of its box's (a solid,
 * not a sheet folded shut) and its box's diagonal this share of the mesh's height (no specks). */
#define RT_VOLUME_SOLID 0.05
#define RT_VOLUME_SIZE 0.02

typedef struct rt_spot {
    float p[3];
    uint32_t v;
} rt_spot;

static int rt_cmp_spot(const void *a, const void *b)
{
    const float *p = ((const rt_spot *)a)->p, *q = ((const rt_spot *)b)->p;
    for (int c = 0; c < 3; c++)
        if (p[c] != q[c])
            return (p[c] > q[c]) - (p[c] < q[c]);
    return 0;
}

/* Each vertex's welded id into id[] (vertices at the same position, as a mesh split at its
 * texture or normal seams has them, share one); false when out of memory. The positions are
 * sorted with their vertex beside them: no sort context outside the call, so measures may run
 * on several threads. */
static bool rt_weld(const rf_mesh *m, uint32_t *id)
{
    rt_spot *s = malloc(((size_t)m->vertex_count + 1) * sizeof *s);
    if (!s)
        return false;
    for (uint32_t v = 0; v < m->vertex_count; v++)
        memcpy(s[v].p, m->positions + (size_t)v * 3, sizeof s[v].p), s[v].v = v;
    qsort(s, m->vertex_count, sizeof *s, rt_cmp_spot);
    for (uint32_t i = 0; i < m->vertex_count; i++)
        id[s[i].v] = i && !rt_cmp_spot(&s[i - 1], &s[i]) ? id[s[i - 1].v] : s[i].v;
    free(s);
    return true;
}

static uint32_t rt_find(uint32_t *up, uint32_t a)
{
    while (up[a] != a)
        a = up[a] = up[up[a]];
    return a;
}

static bool rt_tri_ok(const rf_mesh *m, uint32_t t)
{
    const uint32_t *v = m->triangles + (size_t)t * 3;
    return v[0] < m->vertex_count && v[1] < m->vertex_count && v[2] < m->vertex_count;
}

/* Loose parts by welded vertex into up[] (union-find roots), and open[root] set where an edge of
 * the part is not shared by exactly two triangles. False when out of memory. */
static bool rt_parts_closed(const rf_mesh *m, const uint32_t *id, uint32_t *up, uint8_t *open)
{
    rf_rt_cell *e = malloc(((size_t)m->triangle_count * 3 + 1) * sizeof *e);
    if (!e)
        return false;
    for (uint32_t v = 0; v < m->vertex_count; v++)
        up[v] = v;
    size_t n = 0;
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        if (!rt_tri_ok(m, t))
            continue;
        const uint32_t *v = m->triangles + (size_t)t * 3;
        for (int k = 0; k < 3; k++) {
            uint32_t a = id[v[k]], b = id[v[(k + 1) % 3]];
            up[rt_find(up, a)] = rt_find(up, b);
            e[n].key = a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a, e[n++].v = t;
        }
    }
    qsort(e, n, sizeof *e, rf_rt_cmp_cell);
    for (size_t i = 0, end; i < n; i = end) {
        for (end = i; end < n && e[end].key == e[i].key; end++)
            ;
        if (end - i != 2)
            open[rt_find(up, (uint32_t)(e[i].key >> 32))] = 1;
    }
    free(e);
    return true;
}

/* The signed volume of part p's triangles at positions pos, about its reference vertex. */
static double rt_part_volume(const rf_rt_volumes *v, const rf_mesh *m, const rf_vec3 *pos,
                             uint32_t p)
{
    rf_vec3 o = pos[v->origin[p]];
    double sum = 0;
    for (uint32_t i = v->first[p]; i < v->first[p + 1]; i++) {
        const uint32_t *t = m->triangles + (size_t)v->tris[i] * 3;
        rf_vec3 a = rf_v3_sub(pos[t[0]], o), b = rf_v3_sub(pos[t[1]], o),
                c = rf_v3_sub(pos[t[2]], o);
        sum += rf_v3_dot(a, rf_v3_cross(b, c));
    }
    return sum / 6;
}

/* Part p of root r kept when it is a solid of some size: its triangles listed, its rest volume
 * and the joint carrying most of its vertices recorded. */
static void rt_part_keep(rf_rt_volumes *v, const rf_mesh *m, const rf_vec3 *rest, double height,
                         uint32_t p, uint32_t *votes, uint32_t joints)
{
    rf_vec3 lo = rest[v->origin[p]], hi = lo;
    memset(votes, 0, ((size_t)joints + 1) * sizeof *votes);
    for (uint32_t i = v->first[p]; i < v->first[p + 1]; i++)
        for (int k = 0; k < 3; k++) {
            uint32_t x = m->triangles[(size_t)v->tris[i] * 3 + k];
            rf_vec3 q = rest[x];
            lo = rf_v3(fmin(lo.x, q.x), fmin(lo.y, q.y), fmin(lo.z, q.z));
            hi = rf_v3(fmax(hi.x, q.x), fmax(hi.y, q.y), fmax(hi.z, q.z));
            uint32_t j = rf_mesh_heaviest_joint(m, x);
            votes[j < joints ? j : joints]++;
        }
    rf_vec3 d = rf_v3_sub(hi, lo);
    v->rest[p] = rt_part_volume(v, m, rest, p);
    v->keep[p] = fabs(v->rest[p]) >= RT_VOLUME_SOLID * d.x * d.y * d.z && d.x * d.y * d.z > 0 &&
                 rf_v3_len(d) >= RT_VOLUME_SIZE * height;
    v->joint[p] = 0;
    for (uint32_t j = 1; j < joints; j++)
        v->joint[p] = votes[j] > votes[v->joint[p]] ? j : v->joint[p];
}

/* The closed parts' triangles grouped by part (first[], tris[]), from the union-find roots. */
static bool rt_group(rf_rt_volumes *v, const rf_mesh *m, const uint32_t *id, uint32_t *up,
                     const uint8_t *open, uint32_t *slot)
{
    uint32_t parts = 0;
    for (uint32_t x = 0; x < m->vertex_count; x++)
        slot[x] = UINT32_MAX;
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        uint32_t r = rt_tri_ok(m, t) ? rt_find(up, id[m->triangles[(size_t)t * 3]]) : UINT32_MAX;
        if (r != UINT32_MAX && !open[r] && slot[r] == UINT32_MAX)
            slot[r] = parts++;
    }
    v->parts = parts;
    v->first = calloc((size_t)parts + 2, sizeof *v->first);
    v->tris = malloc(((size_t)m->triangle_count + 1) * sizeof *v->tris);
    v->origin = malloc(((size_t)parts + 1) * sizeof *v->origin);
    if (!v->first || !v->tris || !v->origin)
        return false;
    for (uint32_t t = 0; t < m->triangle_count; t++)
        if (rt_tri_ok(m, t)) {
            uint32_t r = rt_find(up, id[m->triangles[(size_t)t * 3]]);
            if (slot[r] != UINT32_MAX)
                v->first[slot[r] + 2]++, v->origin[slot[r]] = m->triangles[(size_t)t * 3];
        }
    for (uint32_t p = 0; p < parts; p++)
        v->first[p + 2] += v->first[p + 1];
    for (uint32_t t = 0; t < m->triangle_count; t++)
        if (rt_tri_ok(m, t)) {
            uint32_t r = rt_find(up, id[m->triangles[(size_t)t * 3]]);
            if (slot[r] != UINT32_MAX)
                v->tris[v->first[slot[r] + 1]++] = t;
        }
    return true;
}

bool rf_rt_volumes_find(const rf_mesh *m, const rf_vec3 *rest, uint32_t joints, double height,
                        rf_rt_volumes *v)
{
    memset(v, 0, sizeof *v);
    size_t nv = (size_t)m->vertex_count + 1;
    uint32_t *id = malloc(nv * sizeof *id), *up = malloc(nv * sizeof *up);
    uint32_t *slot = malloc(nv * sizeof *slot),
             *votes = malloc(((size_t)joints + 1) * sizeof *votes);
    uint8_t *open = calloc(nv, 1);
    bool ok = id && up && slot && votes && open && m->triangles && rt_weld(m, id) &&
              rt_parts_closed(m, id, up, open) && rt_group(v, m, id, up, open, slot);
    v->rest = ok ? malloc(((size_t)v->parts + 1) * sizeof *v->rest) : NULL;
    v->joint = ok ? malloc(((size_t)v->parts + 1) * sizeof *v->joint) : NULL;
    v->keep = ok ? malloc((size_t)v->parts + 1) : NULL;
    ok = ok && v->rest && v->joint && v->keep;
    for (uint32_t p = 0; ok && p < v->parts; p++)
        rt_part_keep(v, m, rest, height, p, votes, joints);
    free(id), free(up), free(slot), free(votes), free(open);
    if (!ok && m->triangles)
        rf_rt_volumes_free(v);
    return ok || !m->triangles;
}

void rf_rt_volumes_at(const rf_rt_volumes *v, const rf_mesh *m, const rf_vec3 *pos, double *off)
{
    for (uint32_t p = 0; p < v->parts; p++)
        off[p] = v->keep[p] ? fabs(rt_part_volume(v, m, pos, p) / v->rest[p] - 1) : 0;
}

void rf_rt_volumes_free(rf_rt_volumes *v)
{
    free(v->first), free(v->tris), free(v->origin), free(v->rest), free(v->joint), free(v->keep);
    memset(v, 0, sizeof *v);
}
