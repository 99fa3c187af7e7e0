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
 * position". A file that declares no up (OBJ, STL, PLY: the importer leaves it zero) gets the
 * body's own, found from its curve skeleton and how it stands (rf_rig_body_up), or +y with a
 * warning when none is found ("An up the file does not declare"). A body declaring no forward
 * is named facing the way its skeletons on the grid turned every quarter way read, pooled
 * (rf_rig_pooled_facing): one grid's skeleton changes with where the voxel boundaries fall. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <rigflow/analysis.h>
#include <rigflow/memory.h>

#include "rig-internal.h"

#define RF_RIG_DEG (3.14159265358979323846 / 180) /* radians per degree */

static rf_vec3 rf_rig_level(rf_vec3 v, rf_vec3 u)
{
    return rf_v3_sub(v, rf_v3_scale(u, rf_v3_dot(v, u)));
}

typedef struct rf_rig_pt {
    double x, y; /* in the plane across up */
    double h;    /* the height along up (carried through the hull's sort, not compared) */
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

/* m's vertices seen along up u, projected once for every measure across u: in the plane axes
 * a, b (u, a and b right-handed; the same for the footprint's box and the standing margin), each
 * with its height along u, with room for a subset of them and for a convex hull. */
typedef struct rf_rig_view {
    rf_vec3 a, b;
    size_t n;
    rf_rig_pt *p;   /* [n] every vertex (sorted by the hull of all of them) */
    rf_rig_pt *sub; /* [n + 1] room for a subset */
    rf_rig_pt *h;   /* [2n + 2] room for a hull */
    double lo, hi;  /* the lowest and highest height */
} rf_rig_view;

static void rf_rig_view_free(rf_rig_view *v)
{
    free(v->p), free(v->sub), free(v->h);
    memset(v, 0, sizeof *v);
}

/* False when out of memory (v left empty). */
static bool rf_rig_view_make(const rf_mesh *m, rf_vec3 u, rf_rig_view *v)
{
    memset(v, 0, sizeof *v);
    rf_vec3 helper = fabs(u.x) < 0.9 ? rf_v3(1, 0, 0) : rf_v3(0, 0, 1);
    v->a = rf_v3_normalize(rf_v3_cross(u, helper)), v->b = rf_v3_cross(u, v->a);
    v->n = m->vertex_count, v->lo = INFINITY, v->hi = -INFINITY;
    v->p = malloc((v->n + 1) * sizeof *v->p), v->sub = malloc((v->n + 1) * sizeof *v->sub);
    v->h = malloc((2 * v->n + 2) * sizeof *v->h);
    if (!v->p || !v->sub || !v->h) {
        rf_rig_view_free(v);
        return false;
    }
    for (size_t i = 0; i < v->n; i++) {
        rf_vec3 q = rf_v3(m->positions[i * 3], m->positions[i * 3 + 1], m->positions[i * 3 + 2]);
        v->p[i] = (rf_rig_pt){rf_v3_dot(q, v->a), rf_v3_dot(q, v->b), rf_v3_dot(q, u)};
        v->lo = fmin(v->lo, v->p[i].h), v->hi = fmax(v->hi, v->p[i].h);
    }
    return true;
}

/* The direction, across up u, of a side of the smallest rectangle around m's footprint (its
 * vertices seen from above; the smallest lies along a side of their convex hull): a body
 * modelled along the file's axes has its footprint's box along them, where the vertices'
 * principal axes lean with any lopsided pose (the ninja's by 4 degrees, the fish's by 13), and
 * a body turned turns its box with it. Zero into *out when the vertices do not spread across u;
 * false when out of memory. */
static bool rf_rig_footprint(const rf_mesh *m, rf_vec3 u, rf_vec3 *out)
{
    *out = rf_v3(0, 0, 0);
    if (m->vertex_count < 3)
        return true;
    rf_rig_view v;
    if (!rf_rig_view_make(m, u, &v))
        return false;
    size_t k = rf_rig_hull(v.p, v.n, v.h);
    const rf_rig_pt *h = v.h;
    double least = INFINITY;
    for (size_t i = 0; i < k; i++) {
        rf_rig_pt e = {h[(i + 1) % k].x - h[i].x, h[(i + 1) % k].y - h[i].y, 0};
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
            least = area, *out = rf_v3_add(rf_v3_scale(v.a, e.x), rf_v3_scale(v.b, e.y));
    }
    rf_rig_view_free(&v);
    return true;
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
 * degrees), and there the principal axis is the steadier. Both turn with the body. False when
 * out of memory. */
static bool rf_rig_body_axis(const rf_mesh *m, rf_vec3 u, rf_vec3 *out)
{
    rf_vec3 e = rf_rig_principal(m, u), f;
    if (!rf_rig_footprint(m, u, &f))
        return false;
    *out = e;
    for (int k = 0; rf_v3_len(f) > 0 && k < 4; k++, f = rf_v3_cross(u, f))
        if (rf_v3_dot(f, e) >= cos(5 * RF_RIG_DEG)) {
            *out = f;
            break;
        }
    return true;
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

/* ---- an up the file does not declare ---- */

/* Twice the signed area of the polygon h[0..n). */
static double rf_rig_area2(const rf_rig_pt *h, size_t n)
{
    double a = 0;
    for (size_t i = 0; i < n; i++)
        a += h[i].x * h[(i + 1) % n].y - h[(i + 1) % n].x * h[i].y;
    return a;
}

/* The distance from c to the nearest edge of the convex polygon h[0..n) (counter-clockwise),
 * positive inside. */
static double rf_rig_inside(const rf_rig_pt *h, size_t n, rf_rig_pt c)
{
    double margin = INFINITY;
    for (size_t i = 0; i < n; i++) {
        rf_rig_pt e = {h[(i + 1) % n].x - h[i].x, h[(i + 1) % n].y - h[i].y, 0};
        double len = hypot(e.x, e.y);
        if (len > 0)
            margin = fmin(margin, (e.x * (c.y - h[i].y) - e.y * (c.x - h[i].x)) / len);
    }
    return margin;
}

/* The centre of m's surface (each triangle weighted by its area: a scan's surface need not be
 * closed, so no volume is assumed) seen along u, in the plane axes a, b. False for no area. */
static bool rf_rig_surface_centre(const rf_mesh *m, rf_vec3 a, rf_vec3 b, rf_rig_pt *c)
{
    double cx = 0, cy = 0, area = 0;
    for (size_t t = 0; t < m->triangle_count; t++) {
        rf_vec3 q[3];
        for (int i = 0; i < 3; i++) {
            const float *v = m->positions + (size_t)m->triangles[t * 3 + i] * 3;
            q[i] = rf_v3(v[0], v[1], v[2]);
        }
        double w = rf_v3_len(rf_v3_cross(rf_v3_sub(q[1], q[0]), rf_v3_sub(q[2], q[0])));
        rf_vec3 mid = rf_v3_scale(rf_v3_add(rf_v3_add(q[0], q[1]), q[2]), 1.0 / 3);
        cx += w * rf_v3_dot(mid, a), cy += w * rf_v3_dot(mid, b), area += w;
    }
    *c = (rf_rig_pt){area > 0 ? cx / area : 0, area > 0 ? cy / area : 0, 0};
    return area > 0 && isfinite(cx) && isfinite(cy);
}

/* How squarely m stands on its lowest points under up u: seen from above, the distance from
 * the centre of its surface to the nearest edge of the convex hull of its vertices within 5%
 * of its height of the lowest (positive inside), as a fraction of the square root of its whole
 * footprint's area (the hull of all its vertices). A body stands over its feet; seen along a
 * wrong up it rests on a snout, a tail or a wing tip with its centre beside them (the
 * measures are in doc/autorig.md, "An up the file does not declare"). NAN into *margin when
 * the lowest vertices or the whole footprint make no area (a point, a line) or the surface
 * has none; false when out of memory. */
bool rf_rig_support(const rf_mesh *m, rf_vec3 u, double *margin)
{
    *margin = NAN;
    rf_rig_view v;
    rf_rig_pt c;
    if (!rf_rig_view_make(m, u, &v))
        return false;
    size_t k = 0;
    for (size_t i = 0; i < v.n; i++)
        if (v.p[i].h <= v.lo + 0.05 * (v.hi - v.lo))
            v.sub[k++] = v.p[i];
    size_t nh = k >= 3 ? rf_rig_hull(v.sub, k, v.h) : 0;
    if (nh >= 3 && rf_rig_area2(v.h, nh) > 0 && rf_rig_surface_centre(m, v.a, v.b, &c)) {
        double inside = rf_rig_inside(v.h, nh, c);
        size_t na = rf_rig_hull(v.p, v.n, v.h);
        double all = 0.5 * rf_rig_area2(v.h, na);
        if (all > 0)
            *margin = inside / sqrt(all);
    }
    rf_rig_view_free(&v);
    return true;
}

/* The file's axis direction nearest v, or zero when v lies more than 25 degrees from every
 * one: a scan is saved along its file's axes, Y-up or Z-up, and a reading between them is no
 * reading. */
static rf_vec3 rf_rig_snap_axis(rf_vec3 v)
{
    const double c[3] = {v.x, v.y, v.z};
    int k = fabs(c[0]) >= fabs(c[1]) && fabs(c[0]) >= fabs(c[2]) ? 0
            : fabs(c[1]) >= fabs(c[2])                           ? 1
                                                                 : 2;
    if (!(fabs(c[k]) >= cos(25 * RF_RIG_DEG) * rf_v3_len(v)))
        return rf_v3(0, 0, 0);
    double s = c[k] > 0 ? 1 : -1;
    return rf_v3(k == 0 ? s : 0, k == 1 ? s : 0, k == 2 ? s : 0);
}

/* The analysis's reading of the curve skeleton is taken when it is sure enough and the body
 * stands over its lowest points along it. Measured on the shared models turned every quarter
 * way (doc/autorig.md): right readings came with a confidence of 0.37 and up, standing margins
 * of 0.09 and up; the wrong ones that would have turned a body standing right were the winged
 * and finned bodies (the fire dragon read along its length at 0.99, margin 0.04; the wyvern
 * 0.37, 0.05; the bat 0.58 and the angelfish 0.69, neither standing on the axis read). */
#define RF_RIG_UP_CONFIDENCE 0.35
#define RF_RIG_UP_SUPPORT 0.07

/* The file's six axis directions, in the order rf_rig_axis_index numbers them. */
static const rf_vec3 rf_rig_axes[6] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                       {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};

/* The index in rf_rig_axes of the axis direction v (snapped: one component +-1). */
static int rf_rig_axis_index(rf_vec3 v)
{
    int k = fabs(v.x) >= fabs(v.y) && fabs(v.x) >= fabs(v.z) ? 0 : fabs(v.y) >= fabs(v.z) ? 1 : 2;
    double c = k == 0 ? v.x : k == 1 ? v.y : v.z;
    return k * 2 + (c < 0);
}

static const char *rf_rig_axis_name(rf_vec3 v)
{
    static const char *const names[6] = {"+x", "-x", "+y", "-y", "+z", "-z"};
    return names[rf_rig_axis_index(v)];
}

/* The prepared body p turned by q into t: its proxy's vertices and box, t's other arrays
 * borrowed from p (free t->proxy.p alone). False when out of memory. */
static bool rf_rig_prep_turned(const rf_rig_prep *p, rf_quat q, rf_rig_prep *t)
{
    *t = *p;
    size_t n = (size_t)p->proxy.nv * 3;
    if (!(t->proxy.p = malloc((n ? n : 1) * sizeof *t->proxy.p)))
        return false;
    for (int a = 0; a < 3; a++)
        t->lo[a] = INFINITY, t->hi[a] = -INFINITY;
    for (size_t i = 0; i < n; i += 3) {
        rf_vec3 v = rf_quat_rotate(q, rf_v3(p->proxy.p[i], p->proxy.p[i + 1], p->proxy.p[i + 2]));
        t->proxy.p[i] = v.x, t->proxy.p[i + 1] = v.y, t->proxy.p[i + 2] = v.z;
        for (int a = 0; a < 3; a++)
            t->lo[a] = fmin(t->lo[a], t->proxy.p[i + a]),
            t->hi[a] = fmax(t->hi[a], t->proxy.p[i + a]);
    }
    return true;
}

/* The curve skeleton of the prepared body p turned by q (its proxy's vertices, box and all),
 * read by the skeleton analysis with no axes: its up turned back to the file's axes and
 * snapped into out, with m's standing margin along it from support[] (rf_rig_axes' order). p
 * is left as it was. False when out of memory. */
static bool rf_rig_read_up(rf_rig_prep *p, rf_quat q, const rf_rig_options *o,
                           const double support[6], rf_rig_up *out)
{
    memset(out, 0, sizeof *out);
    out->source = "no curve skeleton";
    out->support = NAN;
    rf_rig_prep t;
    if (!rf_rig_prep_turned(p, q, &t))
        return false;
    rf_rig_skel k = {0};
    char err[256];
    rf_skeleton *s = NULL;
    bool ok = true;
    err[0] = '\0';
    rf_rig_status status = rf_rig_curve(&t, o, &k, err, sizeof err);
    if (status != RF_RIG_OK) {
        ok = status != RF_RIG_NO_MEMORY;
        snprintf(out->why, sizeof out->why, "%.199s", err);
    } else if (!(s = rf_rig_skeleton(&k, NULL)))
        ok = false;
    else {
        rf_analysis_options ao = {.ignore_file_axes = true};
        rf_analysis *a = rf_analyze(s, &ao);
        if (a) {
            out->read = rf_quat_rotate(rf_quat_conj(q), a->up);
            out->confidence = a->up_confidence, out->source = a->up_source;
            out->axis = rf_rig_snap_axis(out->read);
        } else
            ok = false; /* the analysis fails only when out of memory: no reading of the body */
        rf_analysis_free(a);
    }
    rf_skeleton_free(s);
    rf_rig_skel_free(&k);
    free(t.proxy.p);
    if (rf_v3_len(out->axis) > 0)
        out->support = support[rf_rig_axis_index(out->axis)];
    out->found = rf_v3_len(out->axis) > 0 && strcmp(out->source, "limbs") == 0 &&
                 out->confidence >= RF_RIG_UP_CONFIDENCE && out->support >= RF_RIG_UP_SUPPORT;
    return ok;
}

/* A standing margin for ordering: none (NAN) below any. */
static double rf_rig_margin_rank(double margin)
{
    return isnan(margin) ? -INFINITY : margin;
}

/* The five axis directions other than +y (the file's own, read first) into stand, as indices
 * of rf_rig_axes, the one the body stands on best first: a body mostly stands on its feet by
 * more than on its side or back (the bull frog upside down, stood on its feet first, not last:
 * 2.0 -> 0.8 s of processor time). */
static void rf_rig_stand_order(const double support[6], int stand[5])
{
    const int axes[5] = {4, 5, 0, 1, 3}; /* +z, -z, +x, -x, -y: the order among equals */
    for (int i = 0; i < 5; i++) {
        int j = i;
        for (; j > 0 &&
               rf_rig_margin_rank(support[axes[i]]) > rf_rig_margin_rank(support[stand[j - 1]]);
             j--)
            stand[j] = stand[j - 1];
        stand[j] = axes[i];
    }
}

/* The turn that stands the body on axis direction i of rf_rig_axes (brings it onto +y). */
static rf_quat rf_rig_stand_turn(int i)
{
    return i == 3 ? rf_quat_from_axis_angle(rf_v3(1, 0, 0), 3.14159265358979323846)
                  : rf_quat_from_two_vectors(rf_rig_axes[i], rf_v3(0, 1, 0));
}

/* Readings each under the confidence bar that name the same axis, one the body stands on, add up
 * (rf_rig_tally): RobotExpressive laid on its side reads its true up at 0.28 as the file has it
 * and at 0.28 and 0.23 stood on either side, and no reading names another axis. A reading under
 * RF_RIG_UP_WEAK is no vote. */
#define RF_RIG_UP_WEAK 0.15

typedef struct rf_rig_votes {
    rf_rig_up best; /* the surest reading counted */
    double sum;     /* their confidences */
    bool split;     /* two counted readings name different axes */
} rf_rig_votes;

/* Counts reading u into v when it names an axis the body stands on, from its limbs, at
 * RF_RIG_UP_WEAK or more. */
static void rf_rig_tally(rf_rig_votes *v, const rf_rig_up *u)
{
    if (!(rf_v3_len(u->axis) > 0) || strcmp(u->source, "limbs") != 0 ||
        !(u->confidence >= RF_RIG_UP_WEAK) || !(u->support >= RF_RIG_UP_SUPPORT))
        return;
    v->split = v->split || (v->sum > 0 && rf_v3_dot(u->axis, v->best.axis) < 0.99);
    if (!(v->sum > 0) || u->confidence > v->best.confidence)
        v->best = *u;
    v->sum += u->confidence;
}

/* A standing margin under the bar, from RF_RIG_UP_NARROW, is taken along an axis the body's limbs
 * read as its up with a confidence that rises, as the margin falls, from the bar's
 * (RF_RIG_UP_CONFIDENCE at a margin of RF_RIG_UP_SUPPORT) to RF_RIG_UP_SURE (at a margin of 0):
 * a biped standing with its feet together stands on a narrow footprint (random biped 5: margin
 * 0.057, its limbs read at 0.81; biped 46: 0.0699, read at 0.42), which the bar alone leaves out
 * for the sake of bodies that would topple onto a wrong axis by as little (the fire dragon reads
 * its length at 0.51 by 0.044; the angelfish at 0.71 by next to none). */
#define RF_RIG_UP_SURE 0.8
#define RF_RIG_UP_NARROW 0.03 /* the least margin taken so: a fish lying flat balances at 0 */

/* Whether reading u names an axis the body stands on by under the bar, from its limbs, as
 * surely as that margin asks (above). */
static bool rf_rig_sure_narrow(const rf_rig_up *u)
{
    if (!(rf_v3_len(u->axis) > 0) || !(u->support >= RF_RIG_UP_NARROW) ||
        !(u->support < RF_RIG_UP_SUPPORT) || strcmp(u->source, "limbs") != 0)
        return false;
    double short_of = 1 - u->support / RF_RIG_UP_SUPPORT; /* 0 at the bar, 1 at no margin */
    return u->confidence >=
           RF_RIG_UP_CONFIDENCE + short_of * (RF_RIG_UP_SURE - RF_RIG_UP_CONFIDENCE);
}

/* The reading as the file has it (out) taken, when as_is, if it is sure of a narrow stand
 * (rf_rig_sure_narrow); else the body stood on each axis direction other than +y it stands on by
 * under the bar, in stand[]'s order, and read: the first read standing on that axis, surely,
 * goes into out. False when out of memory. */
static bool rf_rig_read_narrow(rf_rig_prep *p, const rf_rig_options *o, const double support[6],
                               const int stand[5], bool as_is, rf_rig_up *out)
{
    if (as_is && rf_rig_sure_narrow(out)) {
        out->found = out->narrow = true;
        return true;
    }
    for (int i = 0; i < 5; i++) {
        double margin = support[stand[i]];
        if (!(margin >= RF_RIG_UP_NARROW) || margin >= RF_RIG_UP_SUPPORT)
            continue;
        rf_rig_up u;
        if (!rf_rig_read_up(p, rf_rig_stand_turn(stand[i]), o, support, &u))
            return false;
        if (rf_v3_dot(u.axis, rf_rig_axes[stand[i]]) > 0.99 && rf_rig_sure_narrow(&u)) {
            *out = u;
            out->found = out->narrow = true;
            return true;
        }
    }
    return true;
}

/* A body that stands over its lowest points by under the bar along several axis directions and
 * by the bar along none (a dragon saved Z up whose wings and tail spread its footprint): stood on
 * each of them and read, an up taken only where the body stood on it reads a narrow stance on it
 * surely (rf_rig_read_narrow); the reading as the file has it is not enough here (the fire
 * dragon's, along its length, comes within 0.01 of the bar). False when out of memory. */
static bool rf_rig_read_unstood(rf_rig_prep *p, const rf_rig_options *o, const double support[6],
                                rf_rig_up *out)
{
    int stand[5];
    rf_rig_stand_order(support, stand);
    return rf_rig_read_up(p, rf_quat_identity(), o, support, out) &&
           rf_rig_read_narrow(p, o, support, stand, false, out);
}

/* The body p stood on each axis direction other than +y it stands on (support[], in
 * rf_rig_axes' order) and read, into out when an up is found (see rf_rig_body_up), or when
 * none is, the axis its weaker readings agree on (rf_rig_tally, out's own reading as the file
 * has it counted first); false when out of memory. */
static bool rf_rig_read_stands(rf_rig_prep *p, const rf_rig_options *o, const double support[6],
                               rf_rig_up *out)
{
    rf_rig_up other = {.found = false};
    rf_rig_votes votes = {.sum = 0};
    bool agree = true;
    int stand[5];
    rf_rig_tally(&votes, out); /* the reading as the file has it */
    rf_rig_stand_order(support, stand);
    for (int i = 0; i < 5; i++) {
        rf_vec3 d = rf_rig_axes[stand[i]];
        if (!(support[stand[i]] >= RF_RIG_UP_SUPPORT))
            continue;
        rf_rig_up u;
        if (!rf_rig_read_up(p, rf_rig_stand_turn(stand[i]), o, support, &u))
            return false;
        if (u.found && rf_v3_dot(u.axis, d) > 0.99) { /* stood on it, read standing on it */
            *out = u;
            return true;
        }
        if (u.found) {
            agree = agree && (!other.found || rf_v3_dot(u.axis, other.axis) > 0.99);
            if (!other.found || u.confidence > other.confidence)
                other = u;
        }
        rf_rig_tally(&votes, &u);
    }
    if (other.found && agree)
        *out = other;
    else if (!other.found && !votes.split && votes.sum >= RF_RIG_UP_CONFIDENCE) {
        *out = votes.best;
        out->found = true, out->confidence = votes.sum;
    } else if (!other.found && !votes.split) /* the readings that stand do not disagree */
        return rf_rig_read_narrow(p, o, support, stand, true, out);
    return true;
}

/* A body that stands over its lowest points along one axis direction alone (`only`), by less
 * than the bar: a dragon's wings spread its footprint, which the margin is a fraction of, and
 * its true up reads 0.047 to 0.070 (random dragons of bench/creatures.sh), every other axis
 * under 0 or the one opposite. Stood on that axis, its curve skeleton read standing on it from
 * its limbs and sure enough (RF_RIG_UP_CONFIDENCE), it is found. False when out of memory. */
static bool rf_rig_read_only_stand(rf_rig_prep *p, const rf_rig_options *o, const double support[6],
                                   int only, rf_rig_up *out)
{
    rf_rig_up u;
    if (!rf_rig_read_up(p, rf_rig_stand_turn(only), o, support, &u))
        return false;
    *out = u; /* found or not, what was read goes into the node's log */
    out->found = rf_v3_dot(u.axis, rf_rig_axes[only]) > 0.99 && strcmp(u.source, "limbs") == 0 &&
                 u.confidence >= RF_RIG_UP_CONFIDENCE;
    return true;
}

/* The body read as the file has it first; when that finds no up, the body stood on each other
 * axis direction in turn (the curve skeleton is grown from where the feet meet, its highest
 * girdle, so a body lying down can grow one the analysis reads nothing from). An axis is taken
 * at once when the body stood on it is read standing on it; else an up read with the body stood
 * on another axis is taken when every reading sure enough and standing names it (stood on its
 * back or its head RobotExpressive's curve skeleton reads its true up at 0.68, stood on its
 * feet at 0.28 only; no reading that passes both bars named a wrong axis on the shared models
 * turned every quarter way, doc/autorig.md). A reading is only taken along an axis the body
 * stands on (rf_rig_support), so the standing margin along each of the six is measured first,
 * and no curve skeleton is grown for the body stood on one it does not stand on, nor at all
 * when it stands on none; but a body that stands by under the bar on one axis alone is stood
 * and read on that one (rf_rig_read_only_stand), and on several, on each (rf_rig_read_unstood);
 * when nothing else finds an up, a narrow stance read surely is taken (rf_rig_read_narrow). */
bool rf_rig_body_up(const rf_mesh *m, const rf_rig_options *opts, rf_rig_up *out)
{
    memset(out, 0, sizeof *out);
    out->source = "no curve skeleton";
    out->support = NAN;
    double support[6];
    bool stands = false;
    int only = -1, over = 0; /* the axis with a margin over 0, when one alone has */
    for (int i = 0; i < 6; i++) {
        if (!rf_rig_support(m, rf_rig_axes[i], &support[i]))
            return false;
        stands |= support[i] >= RF_RIG_UP_SUPPORT;
        if (support[i] > 0)
            only = i, over++;
    }
    if (!stands && !over) {
        out->source = "no axis to stand on";
        snprintf(out->why, sizeof out->why,
                 "it stands over its lowest points along none of the file's axes");
        return true;
    }
    rf_rig_options o = rf_rig_defaults(opts);
    o.up = o.forward = rf_v3(0, 0, 0);
    rf_rig_stats st;
    rf_rig_prep p;
    char err[256];
    rf_rig_status status = rf_rig_prepare(m, &o, &p, &st, err, sizeof err);
    if (status != RF_RIG_OK) {
        snprintf(out->why, sizeof out->why, "%.199s", err);
        return status != RF_RIG_NO_MEMORY;
    }
    bool ok = stands ? rf_rig_read_up(&p, rf_quat_identity(), &o, support, out) &&
                           (out->found || rf_rig_read_stands(&p, &o, support, out))
              : over == 1 ? rf_rig_read_only_stand(&p, &o, support, only, out)
                          : rf_rig_read_unstood(&p, &o, support, out);
    rf_rig_prep_free(&p);
    return ok;
}

/* The up of a body whose file declares none into o->up (the found one, else +y), and what was
 * decided into f's note for the node's log. False when out of memory. */
static bool rf_rig_frame_up(const rf_mesh *m, rf_rig_options *o, rf_rig_frame *f)
{
    rf_rig_up u;
    if (!rf_rig_body_up(m, o, &u))
        return false;
    o->up = u.found ? u.axis : rf_v3(0, 1, 0);
    f->up_assumed = !u.found;
    if (u.found) /* a margin under the bar: the one axis it stands on at all, or read surely */
        snprintf(f->up_note, sizeof f->up_note,
                 "up %s, not declared by the file: found from the body (its limbs read by the "
                 "skeleton analysis, confidence %.2f, and it stands over its lowest points, "
                 "margin %.3f%s)",
                 rf_rig_axis_name(u.axis), u.confidence, u.support,
                 !(u.support < RF_RIG_UP_SUPPORT) ? ""
                 : u.narrow ? ", under the bar but read surely enough: a narrow stance"
                            : ", under the bar but along no other axis");
    else if (rf_v3_len(u.axis) > 0) {
        char margin[32] = "none (no footprint)";
        if (!isnan(u.support))
            snprintf(margin, sizeof margin, "%.2f", u.support);
        snprintf(f->up_note, sizeof f->up_note,
                 "up not declared by the file and not found from the body (the skeleton analysis "
                 "read %s from %s, confidence %.2f; standing margin %s): +y assumed; a body "
                 "saved lying is rigged lying (stand it up with a transform node)",
                 rf_rig_axis_name(u.axis), u.source, u.confidence, margin);
    } else
        snprintf(
            f->up_note, sizeof f->up_note,
            "up not declared by the file and not found from the body (%s%s%.100s): +y assumed; "
            "a body saved lying is rigged lying (stand it up with a transform node)",
            u.source, u.why[0] ? ": " : "", u.why);
    return true;
}

/* ---- a facing the grid does not decide ---- */

/* The facing the skeleton analysis reads on skeleton k (up u declared, no forward), made level
 * to u and weighted by the sum of the cues that voted for it, turned by q and added to *sum;
 * nothing when no cue spoke or the facing lies mostly along u (an up read otherwise, as the
 * angelfish's: it says nothing of which way the body faces, as for the rig's own, rf_rig_name).
 * False when out of memory. */
static bool rf_rig_facing_read(const rf_rig_skel *k, rf_vec3 u, rf_quat q, rf_vec3 *sum)
{
    rf_skeleton *s = rf_rig_skeleton(k, NULL);
    if (!s)
        return false;
    s->up = u; /* as the rig is named (rf_rig_skeleton) */
    rf_analysis *a = rf_analyze(s, NULL);
    rf_vec3 f = a ? rf_rig_level(a->forward, rf_v3_normalize(u)) : rf_v3(0, 0, 0);
    if (rf_v3_len(f) > 0.7) {
        double w = 0;
        for (int i = 0; i < RF_FORWARD_CUE_COUNT; i++)
            w += a->forward_cues[i]; /* signed along a->forward: their sum is its margin */
        *sum = rf_v3_add(*sum, rf_v3_scale(rf_quat_rotate(q, rf_v3_normalize(f)), w));
    }
    rf_analysis_free(a);
    rf_skeleton_free(s);
    return a != NULL;
}

/* The general rigger's skeleton of p turned by q (curve skeleton, limbs laid) read for facing
 * into *sum, turned back (rf_rig_facing_read). False when out of memory. */
static bool rf_rig_facing_turned(const rf_rig_prep *p, const rf_rig_options *o, rf_quat q,
                                 rf_vec3 *sum)
{
    rf_rig_prep t;
    if (!rf_rig_prep_turned(p, q, &t))
        return false;
    rf_rig_options ot = *o;
    ot.up = rf_quat_rotate(q, o->up);
    rf_rig_skel k = {0};
    char err[256];
    err[0] = '\0';
    bool ok = true;
    rf_rig_status status = rf_rig_curve(&t, &ot, &k, err, sizeof err);
    if (status != RF_RIG_OK)
        ok = status != RF_RIG_NO_MEMORY; /* refused this way: no vote */
    else
        ok = rf_rig_general_place(&t, &k, &ot, NULL, NULL) &&
             rf_rig_facing_read(&k, ot.up, rf_quat_conj(q), sum);
    rf_rig_skel_free(&k);
    free(t.proxy.p);
    return ok;
}

bool rf_rig_placed_facing(const rf_rig_prep *p, const rf_rig_skel *k, const rf_rig_options *o,
                          rf_vec3 *out)
{
    *out = rf_v3(0, 0, 0);
    rf_rig_skel c;
    if (!rf_rig_skel_copy(k, &c))
        return false;
    rf_skeleton *s = rf_rig_general_place(p, &c, o, NULL, NULL) ? rf_rig_skeleton(&c, NULL) : NULL;
    rf_rig_skel_free(&c);
    if (!s)
        return false;
    s->up = o->up, s->forward = o->forward; /* as the general rigger's rig is named */
    rf_analysis *a = rf_analyze(s, NULL);
    rf_vec3 u = rf_v3_len(o->up) > 0 ? rf_v3_normalize(o->up) : a ? a->up : rf_v3(0, 1, 0);
    rf_vec3 f = a ? rf_rig_level(a->forward, u) : rf_v3(0, 0, 0);
    if (rf_v3_len(f) > 0.7)
        *out = rf_v3_normalize(f);
    rf_analysis_free(a);
    rf_skeleton_free(s);
    return a != NULL;
}

bool rf_rig_pooled_facing(const rf_rig_prep *p, const rf_rig_skel *k, const rf_rig_options *o,
                          rf_vec3 *out)
{
    *out = rf_v3(0, 0, 0);
    rf_vec3 u = rf_v3_len(o->up) > 0 ? rf_v3_normalize(o->up) : rf_v3(0, 1, 0), sum = {0, 0, 0};
    if (k) {
        rf_rig_skel c;
        if (!rf_rig_skel_copy(k, &c))
            return false;
        bool ok = rf_rig_general_place(p, &c, o, NULL, NULL) &&
                  rf_rig_facing_read(&c, o->up, rf_quat_identity(), &sum);
        rf_rig_skel_free(&c);
        if (!ok)
            return false;
    }
    for (int t = k ? 1 : 0; t < 4; t++)
        if (!rf_rig_facing_turned(p, o, rf_quat_from_axis_angle(u, t * 90 * RF_RIG_DEG), &sum))
            return false;
    sum = rf_rig_level(sum, u);
    if (rf_v3_len(sum) > 1e-6)
        *out = rf_v3_normalize(sum);
    return true;
}

void rf_rig_frame_stats(const rf_rig_frame *f, rf_rig_stats *st)
{
    if (!st)
        return;
    memcpy(st->up_note, f->up_note, sizeof st->up_note);
    st->up_assumed = f->up_assumed;
}

/* The turn from the file's axes into the rigging frame, into f->q, f->turned false when it is
 * none; false when out of memory. */
static bool rf_rig_frame_find(const rf_mesh *m, const rf_rig_options *o, rf_rig_frame *f)
{
    rf_vec3 u = rf_v3_len(o->up) > 0 ? rf_v3_normalize(o->up) : rf_v3(0, 1, 0);
    rf_vec3 z =
        rf_v3_len(o->forward) > 0 ? rf_rig_level(rf_v3_normalize(o->forward), u) : rf_v3(0, 0, 0);
    if (!(rf_v3_len(z) > 0.5)) { /* none declared, or one along up: the body's own axis */
        if (!rf_rig_body_axis(m, u, &z))
            return false;
        z = rf_rig_nearest_file_axis(z, u);
    }
    f->turned = false;
    if (!(rf_v3_len(z) > 0))
        return true;
    z = rf_v3_normalize(z);
    rf_vec3 x = rf_v3_cross(u, z);
    /* rows x, u, z turn the file's axes into the frame's: column-major, so m[c * 4 + r] */
    rf_mat4 t = rf_mat4_identity();
    const rf_vec3 rows[3] = {x, u, z};
    for (int r = 0; r < 3; r++)
        t.m[0 * 4 + r] = rows[r].x, t.m[1 * 4 + r] = rows[r].y, t.m[2 * 4 + r] = rows[r].z;
    rf_xform xf;
    if (!rf_mat4_to_xform(t, &xf))
        return true;
    f->q = rf_quat_normalize(xf.r);
    f->turned = fabs(f->q.w) < 1 - 1e-12;
    return true;
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
    /* a mesh the rigger's checks refuse (no positions, non-finite ones, a triangle naming a
     * vertex it does not have, too large for the memory left) is left as it is, for them to
     * name what is wrong: turned, its copy and its footprint's hull would take memory before
     * rf_rig_prepare could refuse it, and the up's search reads its triangles */
    uint64_t available = 0;
    bool known = rf_memory_available(&available);
    char why[8];
    bool usable =
        mesh->positions != NULL && rf_rig_memory_fits(mesh->vertex_count, mesh->triangle_count,
                                                      known, available, why, sizeof why);
    for (size_t i = 0; usable && i < (size_t)mesh->vertex_count * 3; i++)
        usable = isfinite(mesh->positions[i]);
    usable = usable && (mesh->triangles || !mesh->triangle_count);
    for (size_t i = 0; usable && i < (size_t)mesh->triangle_count * 3; i++)
        usable = mesh->triangles[i] < mesh->vertex_count;
    if (!usable || !mesh->vertex_count)
        return true;
    if (!(rf_v3_len(o->up) > 0) && rf_v3_isfinite(o->up) && !rf_rig_frame_up(mesh, o, f))
        return false;
    if (!rf_rig_frame_find(mesh, o, f))
        return false;
    if (!f->turned)
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
