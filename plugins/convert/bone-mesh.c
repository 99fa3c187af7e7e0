/* The exporter's stand-in mesh for a skeleton without one (bone-mesh.h). */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "bone-mesh.h"

#include <rigflow/text.h>

enum { RF_BM_VERTS = 6, RF_BM_TRIS = 8 };

/* Two unit vectors perpendicular to the unit `d` and to each other, v = d x u. */
static void rf_bm_basis(rf_vec3 d, rf_vec3 *u, rf_vec3 *v)
{
    rf_vec3 a = fabs(d.x) < 0.9 ? rf_v3(1, 0, 0) : rf_v3(0, 1, 0);
    *u = rf_v3_normalize(rf_v3_cross(a, d));
    *v = rf_v3_cross(d, *u);
}

/* Bone b from p to c, all of it owned by `joint`: the base at p, a ring of four a sixth of the
 * way along, the tip at c. Faces wound outwards (counter-clockwise seen from outside). */
static void rf_bm_bone(rf_mesh *m, uint32_t b, rf_vec3 p, rf_vec3 c, uint16_t joint)
{
    rf_vec3 d = rf_v3_sub(c, p), u, v;
    double len = rf_v3_len(d);
    rf_bm_basis(rf_v3_scale(d, 1 / len), &u, &v);
    rf_vec3 mid = rf_v3_add(p, rf_v3_scale(d, 1.0 / 6)), pts[RF_BM_VERTS] = {p, c};
    rf_vec3 ring[4] = {u, v, rf_v3_scale(u, -1), rf_v3_scale(v, -1)};
    for (int i = 0; i < 4; i++)
        pts[2 + i] = rf_v3_add(mid, rf_v3_scale(ring[i], 0.1 * len));
    uint32_t v0 = b * RF_BM_VERTS;
    for (uint32_t i = 0; i < RF_BM_VERTS; i++) {
        float *pos = m->positions + (size_t)(v0 + i) * 3;
        pos[0] = (float)pts[i].x, pos[1] = (float)pts[i].y, pos[2] = (float)pts[i].z;
        m->skin_joints[(size_t)(v0 + i) * 4] = joint;
        m->skin_weights[(size_t)(v0 + i) * 4] = 1.0f;
    }
    uint32_t *t = m->triangles + (size_t)b * RF_BM_TRIS * 3;
    for (uint32_t i = 0; i < 4; i++) {
        uint32_t r0 = v0 + 2 + i, r1 = v0 + 2 + (i + 1) % 4;
        uint32_t tri[6] = {v0, r1, r0, v0 + 1, r0, r1}; /* base cone, tip cone */
        for (int k = 0; k < 6; k++)
            t[i * 6 + (uint32_t)k] = tri[k];
    }
}

/* How far a joint may move against its parent in a clip, of its rest distance from it, and
 * still be drawn as a rigid bone on the parent: mocap that keys every joint's position holds it
 * still within its noise, a root that carries the hips walks them away. */
#define RF_BM_SLIDE 0.05

/* Whether joint j keeps its place against its parent through every frame of the clips: its
 * local translation strays from the first frame's by at most RF_BM_SLIDE of its rest length. */
static bool rf_bm_held(const rf_skeleton *s, uint32_t j, const rf_animation *const *clips,
                       uint32_t nclips)
{
    double most = RF_BM_SLIDE * rf_v3_len(s->joints[j].rest.t);
    for (uint32_t c = 0; c < nclips; c++) {
        const rf_animation *a = clips[c];
        if (!a || a->joint_count != s->joint_count || !a->frame_count)
            continue;
        rf_vec3 first = rf_animation_translation(a, 0, j);
        for (uint32_t f = 1; f < a->frame_count; f++)
            if (!(rf_v3_dist(rf_animation_translation(a, f, j), first) <= most))
                return false;
    }
    return true;
}

/* Whether joint j ends a bone worth drawing: it has a parent, is apart from it by more than a
 * millionth of the skeleton's span (coincident helper joints draw nothing), and keeps its place
 * against it in the clips (a bone from a BVH's root at the origin to the hips it walks away
 * would stand there as a spike). */
static bool rf_bm_is_bone(const rf_skeleton *s, const rf_xform *w, uint32_t j, double span,
                          const rf_animation *const *clips, uint32_t nclips)
{
    int32_t p = s->joints[j].parent;
    return p >= 0 && rf_v3_dist(w[p].t, w[j].t) > 1e-6 * span && rf_bm_held(s, j, clips, nclips);
}

static double rf_bm_span(const rf_xform *w, uint32_t n)
{
    rf_vec3 lo = w[0].t, hi = w[0].t;
    for (uint32_t j = 1; j < n; j++) {
        lo = rf_v3(fmin(lo.x, w[j].t.x), fmin(lo.y, w[j].t.y), fmin(lo.z, w[j].t.z));
        hi = rf_v3(fmax(hi.x, w[j].t.x), fmax(hi.y, w[j].t.y), fmax(hi.z, w[j].t.z));
    }
    return rf_v3_dist(lo, hi);
}

static bool rf_bm_alloc(rf_mesh *m, uint32_t bones)
{
    m->vertex_count = bones * RF_BM_VERTS, m->triangle_count = bones * RF_BM_TRIS;
    m->positions = calloc((size_t)m->vertex_count * 3, sizeof *m->positions);
    m->triangles = calloc((size_t)m->triangle_count * 3, sizeof *m->triangles);
    m->skin_joints = calloc((size_t)m->vertex_count * 4, sizeof *m->skin_joints);
    m->skin_weights = calloc((size_t)m->vertex_count * 4, sizeof *m->skin_weights);
    return m->positions && m->triangles && m->skin_joints && m->skin_weights;
}

/* Parents before children, as rigflow/model.h promises but the host does not check of a
 * plugin's skeleton: a parent past its child would be read before it is placed, or past the end. */
static bool rf_bm_ordered(const rf_skeleton *s, char *err, size_t err_size)
{
    int64_t bad = rf_skeleton_misordered(s);
    if (bad >= 0)
        rf_skeleton_order_error(s, (uint32_t)bad, err, err_size);
    return bad < 0;
}

/* Rest positions that are numbers: a bone not drawn for a NaN would be a silent guess. */
static bool rf_bm_finite(const rf_skeleton *s, const rf_xform *w, char *err, size_t err_size)
{
    char label[160]; /* the joint's name from the file, escaped */
    for (uint32_t j = 0; j < s->joint_count; j++)
        if (!rf_v3_isfinite(w[j].t)) {
            snprintf(err, err_size, "joint %u '%s': its rest position is not finite", j,
                     rf_joint_label(s, j, label, sizeof label));
            return false;
        }
    return true;
}

rf_mesh *rf_cv_bone_mesh(const rf_skeleton *s, const rf_animation *const *clips, uint32_t nclips,
                         char *err, size_t err_size)
{
    uint32_t n = s->joint_count, bones = 0;
    if (!rf_bm_ordered(s, err, err_size))
        return NULL;
    rf_xform *w = calloc(n ? n : 1, sizeof *w);
    rf_mesh *m = w && n <= UINT16_MAX + 1u ? rf_mesh_new() : NULL;
    if (!m) {
        snprintf(err, err_size,
                 n > UINT16_MAX + 1u ? "%u joints: a mesh's joint index holds 65536"
                                     : "out of memory drawing %u bones",
                 n);
        free(w);
        return NULL;
    }
    rf_skeleton_world_rest(s, w);
    if (!rf_bm_finite(s, w, err, err_size)) {
        free(w), rf_mesh_free(m);
        return NULL;
    }
    double span = n ? rf_bm_span(w, n) : 0;
    for (uint32_t j = 0; j < n; j++)
        bones += rf_bm_is_bone(s, w, j, span, clips, nclips);
    if (!bones || !rf_bm_alloc(m, bones)) {
        snprintf(err, err_size,
                 bones ? "out of memory drawing %u bones"
                       : "the skeleton has no bone of any length that keeps its length in the "
                         "clips to draw (%u joints)",
                 bones ? bones : n);
        free(w), rf_mesh_free(m);
        return NULL;
    }
    for (uint32_t j = 0, b = 0; j < n; j++)
        if (rf_bm_is_bone(s, w, j, span, clips, nclips)) {
            uint32_t p = (uint32_t)s->joints[j].parent;
            rf_bm_bone(m, b++, w[p].t, w[j].t, (uint16_t)p);
        }
    free(w);
    return m;
}
