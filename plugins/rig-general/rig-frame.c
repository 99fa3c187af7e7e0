/* The frame a mesh is rigged in. The voxel grid, the bounding box every length is measured
 * against and the flatness check all lie along the rigger's axes; rigged along the file's, a
 * body turned 30 degrees about its up was voxelised diagonally, its box grew, and its rig came
 * out unlike the unturned one's (CD-J2J over the 23 shared models 0.068 -> 0.075, a sheet
 * refused unturned was rigged turned). So the mesh is turned into a frame of its own before it
 * is rigged, and the rig turned back: y the declared up (+y when the file declares none), z the
 * declared forward made level; when the file declares no forward, the body's own axis across
 * up (a side of its footprint's smallest box, or its vertices' principal axis), of its four
 * directions the one nearest the file's forward (+z, turned with a declared up other than +y),
 * and that forward itself within 15 degrees. A body whose file declares a forward then meets
 * the grid as it did unturned at any turn about up, or tipped over with its declared up; one
 * declaring none at turns of 15 to 45 degrees, and otherwise on that grid turned by quarter
 * turns. A file declaring +y up and +z forward, or one modelled along its axes, is rigged in
 * its own axes as before. doc/autorig.md, "Any facing, scale and
 * position". */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <rigflow/memory.h>

#include "rig-internal.h"

#define RF_RIG_DEG (3.14159265358979323846 / 180) /* radians per degree */

static rf_vec3 rf_rig_level(rf_vec3 v, rf_vec3 u)
{
    return rf_v3_sub(v, rf_v3_scale(u, rf_v3_dot(v, u)));
}

typedef struct rf_rig_pt {
    double x, y;
} rf_rig_pt;

static int rf_rig_pt_cmp(const void *pa, const void *pb)
{
    const rf_rig_pt *a = pa, *b = pb;
    return a->x < b->x ? -1 : a->x > b->x ? 1 : a->y < b->y ? -1 : a->y > b->y;
}

static double rf_rig_turn(rf_rig_pt o, rf_rig_pt a, rf_rig_pt b)
{
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

/* The convex hull of p[0..n) (sorted in place) into h, counter-clockwise; its size. */
static size_t rf_rig_hull(rf_rig_pt *p, size_t n, rf_rig_pt *h)
{
    qsort(p, n, sizeof *p, rf_rig_pt_cmp);
    size_t k = 0;
    for (size_t i = 0; i < n; h[k++] = p[i++])
        while (k >= 2 && rf_rig_turn(h[k - 2], h[k - 1], p[i]) <= 0)
            k--;
    for (size_t i = n - 1, lo = k + 1; i-- > 0; h[k++] = p[i])
        while (k >= lo && rf_rig_turn(h[k - 2], h[k - 1], p[i]) <= 0)
            k--;
    return k > 1 ? k - 1 : k;
}

/* The direction, across up u, of a side of the smallest rectangle around m's footprint (its
 * vertices seen from above; the smallest lies along a side of their convex hull): a body
 * modelled along the file's axes has its footprint's box along them, where the vertices'
 * principal axes lean with any lopsided pose (the ninja's by 4 degrees, the fish's by 13), and
 * a body turned turns its box with it. Zero when the vertices do not spread across u; NULL-free
 * but may fail for lack of memory (zero too). */
static rf_vec3 rf_rig_footprint(const rf_mesh *m, rf_vec3 u)
{
    rf_vec3 helper = fabs(u.x) < 0.9 ? rf_v3(1, 0, 0) : rf_v3(0, 0, 1);
    rf_vec3 a = rf_v3_normalize(rf_v3_cross(u, helper)), b = rf_v3_cross(u, a);
    size_t n = m->vertex_count;
    rf_rig_pt *p = malloc((n + 1) * sizeof *p), *h = malloc((2 * n + 2) * sizeof *h);
    rf_vec3 best = rf_v3(0, 0, 0);
    if (!p || !h || n < 3) {
        free(p), free(h);
        return best;
    }
    for (size_t v = 0; v < n; v++) {
        rf_vec3 q = rf_v3(m->positions[v * 3], m->positions[v * 3 + 1], m->positions[v * 3 + 2]);
        p[v] = (rf_rig_pt){rf_v3_dot(q, a), rf_v3_dot(q, b)};
    }
    size_t k = rf_rig_hull(p, n, h);
    double least = INFINITY;
    for (size_t i = 0; i < k; i++) {
        rf_rig_pt e = {h[(i + 1) % k].x - h[i].x, h[(i + 1) % k].y - h[i].y};
        double len = hypot(e.x, e.y);
        if (!(len > 0))
            continue;
        e.x /= len, e.y /= len;
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        for (size_t j = 0; j < k; j++) {
            double s = h[j].x * e.x + h[j].y * e.y, t = -h[j].x * e.y + h[j].y * e.x;
            lo[0] = fmin(lo[0], s), hi[0] = fmax(hi[0], s);
            lo[1] = fmin(lo[1], t), hi[1] = fmax(hi[1], t);
        }
        double area = (hi[0] - lo[0]) * (hi[1] - lo[1]);
        if (area < least * (1 - 1e-9))
            least = area, best = rf_v3_add(rf_v3_scale(a, e.x), rf_v3_scale(b, e.y));
    }
    free(p), free(h);
    return best;
}

/* The longest principal axis of m's vertices across up u (either sign); zero when they do not
 * spread across u. */
static rf_vec3 rf_rig_principal(const rf_mesh *m, rf_vec3 u)
{
    rf_vec3 helper = fabs(u.x) < 0.9 ? rf_v3(1, 0, 0) : rf_v3(0, 0, 1);
    rf_vec3 a = rf_v3_normalize(rf_v3_cross(u, helper)), b = rf_v3_cross(u, a), c = {0, 0, 0};
    size_t n = m->vertex_count;
    for (size_t v = 0; v < n; v++)
        c = rf_v3_add(c,
                      rf_v3(m->positions[v * 3], m->positions[v * 3 + 1], m->positions[v * 3 + 2]));
    c = rf_v3_scale(c, n ? 1.0 / n : 0);
    double caa = 0, cab = 0, cbb = 0;
    for (size_t v = 0; v < n; v++) {
        rf_vec3 d = rf_v3_sub(
            rf_v3(m->positions[v * 3], m->positions[v * 3 + 1], m->positions[v * 3 + 2]), c);
        double x = rf_v3_dot(d, a), y = rf_v3_dot(d, b);
        caa += x * x, cab += x * y, cbb += y * y;
    }
    if (!(caa + cbb > 0))
        return rf_v3(0, 0, 0);
    double th = 0.5 * atan2(2 * cab, caa - cbb);
    return rf_v3_add(rf_v3_scale(a, cos(th)), rf_v3_scale(b, sin(th)));
}

/* The body's axis across up u: a side of its footprint's smallest box when one lies within
 * 5 degrees of the vertices' principal axis, else that axis. A body modelled along the file's
 * axes has its footprint's box exactly along them, where the principal axis leans with a
 * lopsided pose (half a degree on the animalia box models, enough to move a voxel boundary);
 * but the smallest box of a body with spread wings or fins lies anywhere (the wyvern's at 45
 * degrees), and there the principal axis is the steadier. Both turn with the body. */
static rf_vec3 rf_rig_body_axis(const rf_mesh *m, rf_vec3 u)
{
    rf_vec3 e = rf_rig_principal(m, u), f = rf_rig_footprint(m, u);
    if (!(rf_v3_len(f) > 0))
        return e;
    for (int k = 0; k < 4; k++, f = rf_v3_cross(u, f))
        if (rf_v3_dot(f, e) >= cos(5 * RF_RIG_DEG))
            return f;
    return e;
}

/* Of the four directions across up u square to or along axis e, the one nearest the file's own
 * forward: files that declare no facing still mostly face +z with +y up, and the skeleton
 * analysis that names the rig leans on that (rigged along the footprint's longest side
 * whichever way it pointed, four of the 23 shared rigs were read facing back). A file whose up
 * is not +y is taken as turned from there by the shortest turn, its +z with it (+z up: -y),
 * so a model tipped over with its declared up is rigged as it was standing. */
static rf_vec3 rf_rig_nearest_file_axis(rf_vec3 e, rf_vec3 u)
{
    rf_vec3 ref = rf_rig_level(
        rf_quat_rotate(rf_quat_from_two_vectors(rf_v3(0, 1, 0), u), rf_v3(0, 0, 1)), u);
    rf_vec3 best = e, cand = e;
    for (int k = 0; k < 4; k++, cand = rf_v3_cross(u, cand))
        if (rf_v3_dot(cand, ref) > rf_v3_dot(best, ref))
            best = cand;
    /* within 15 degrees the file's own axes are kept: a body modelled along them can lean
     * that far from its estimated axis (the bent ogre fish by 13 degrees, the ninja by 3), and
     * a grid turned by a few degrees moves voxel boundaries as much as any turn does */
    if (rf_v3_len(ref) > 0 && rf_v3_len(best) > 0 &&
        rf_v3_dot(rf_v3_normalize(best), rf_v3_normalize(ref)) >= cos(15 * RF_RIG_DEG))
        return ref;
    return best;
}

/* The turn from the file's axes into the rigging frame, into f->q; false when it is none. */
static bool rf_rig_frame_find(const rf_mesh *m, const rf_rig_options *o, rf_rig_frame *f)
{
    rf_vec3 u = rf_v3_len(o->up) > 0 ? rf_v3_normalize(o->up) : rf_v3(0, 1, 0);
    rf_vec3 z =
        rf_v3_len(o->forward) > 0 ? rf_rig_level(rf_v3_normalize(o->forward), u) : rf_v3(0, 0, 0);
    if (!(rf_v3_len(z) > 0.5)) /* none declared, or one along up: the body's own axis */
        z = rf_rig_nearest_file_axis(rf_rig_body_axis(m, u), u);
    if (!(rf_v3_len(z) > 0))
        return false;
    z = rf_v3_normalize(z);
    rf_vec3 x = rf_v3_cross(u, z);
    /* rows x, u, z turn the file's axes into the frame's: column-major, so m[c * 4 + r] */
    rf_mat4 t = rf_mat4_identity();
    const rf_vec3 rows[3] = {x, u, z};
    for (int r = 0; r < 3; r++)
        t.m[0 * 4 + r] = rows[r].x, t.m[1 * 4 + r] = rows[r].y, t.m[2 * 4 + r] = rows[r].z;
    rf_xform xf;
    if (!rf_mat4_to_xform(t, &xf))
        return false;
    f->q = rf_quat_normalize(xf.r);
    f->turned = fabs(f->q.w) < 1 - 1e-12;
    return f->turned;
}

bool rf_rig_frame_enter(const rf_mesh *mesh, const rf_rig_options *opts, rf_rig_frame *f,
                        rf_mesh *in, rf_rig_options *o)
{
    memset(f, 0, sizeof *f);
    *o = opts ? *opts : (rf_rig_options){0};
    if (!mesh) {
        memset(in, 0, sizeof *in);
        return true;
    }
    *in = *mesh; /* borrowed arrays: only the positions are the frame's own */
    /* a mesh the rigger's checks refuse (no positions, non-finite ones, too large for the
     * memory left) is left as it is, for them to name what is wrong: turned, its copy and its
     * footprint's hull would take memory before rf_rig_prepare could refuse it */
    uint64_t available = 0;
    bool known = rf_memory_available(&available);
    char why[8];
    bool usable =
        mesh->positions != NULL && rf_rig_memory_fits(mesh->vertex_count, mesh->triangle_count,
                                                      known, available, why, sizeof why);
    for (size_t i = 0; usable && i < (size_t)mesh->vertex_count * 3; i++)
        usable = isfinite(mesh->positions[i]);
    if (!usable || !mesh->vertex_count || !rf_rig_frame_find(mesh, o, f))
        return true;
    f->positions = malloc((size_t)mesh->vertex_count * 3 * sizeof *f->positions);
    if (!f->positions)
        return false;
    for (size_t i = 0; i < (size_t)mesh->vertex_count * 3; i += 3) {
        rf_vec3 p = rf_quat_rotate(
            f->q, rf_v3(mesh->positions[i], mesh->positions[i + 1], mesh->positions[i + 2]));
        f->positions[i] = (float)p.x, f->positions[i + 1] = (float)p.y;
        f->positions[i + 2] = (float)p.z;
    }
    in->positions = f->positions;
    o->up = rf_quat_rotate(f->q, o->up), o->forward = rf_quat_rotate(f->q, o->forward);
    return true;
}

/* Every joint's frame turned back (conjugated, so unrotated joints stay unrotated). */
static void rf_rig_frame_joint(rf_quat back, rf_quat fwd, rf_xform *x)
{
    x->t = rf_quat_rotate(back, x->t);
    x->r = rf_quat_normalize(rf_quat_mul(rf_quat_mul(back, x->r), fwd));
}

void rf_rig_frame_leave(rf_rig_frame *f, const rf_mesh *mesh, rf_skeleton *s, rf_mesh *skinned)
{
    if (f->turned && s) {
        rf_quat back = rf_quat_conj(f->q);
        bool has_bind = RF_HAS_FIELD(s, rf_skeleton, bind) && s->bind;
        for (uint32_t j = 0; j < s->joint_count; j++) {
            rf_rig_frame_joint(back, f->q, &s->joints[j].rest);
            if (has_bind)
                rf_rig_frame_joint(back, f->q, &s->bind[j]);
            s->joints[j].end_site = rf_quat_rotate(back, s->joints[j].end_site);
        }
        s->up = rf_quat_rotate(back, s->up), s->forward = rf_quat_rotate(back, s->forward);
    }
    if (f->turned && skinned && skinned->positions && skinned->vertex_count == mesh->vertex_count) {
        memcpy(skinned->positions, mesh->positions,
               (size_t)mesh->vertex_count * 3 * sizeof *mesh->positions);
        rf_mat4 to = rf_xform_to_mat4((rf_xform){{0, 0, 0}, f->q, {1, 1, 1}});
        rf_mat4 from = rf_xform_to_mat4((rf_xform){{0, 0, 0}, rf_quat_conj(f->q), {1, 1, 1}});
        for (uint32_t j = 0; skinned->inverse_bind && j < skinned->bind_count; j++)
            skinned->inverse_bind[j] = rf_mat4_mul(from, rf_mat4_mul(skinned->inverse_bind[j], to));
    }
    free(f->positions);
    memset(f, 0, sizeof *f);
}
