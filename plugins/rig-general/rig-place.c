/* Joint placement by the mesh itself: the curve skeleton gives each joint's place along a limb
 * or the body; the surface, found by casting rays (Embree), gives its place across: a level
 * trunk's spine at a given depth between belly and back (rf_rig_skel_across, used by both
 * riggers), a wing's joints towards its leading edge (rf_rig_skel_chord, which also measures a
 * wing modelled as a sheet of no thickness), or the centre of the cross-section square to the
 * bone (rf_rig_skel_centre, a layout option of the template rigger, off: doc/autorig-log.md says
 * why). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rig-embree.h"

/* Rays cast from a joint in the plane of its cross-section: twice this many, evenly spread. */
#define RF_PLACE_PAIRS 8

struct rf_rig_surface {
    RTCDevice dev;
    RTCScene scene;
};

RTCGeometry rf_rig_triangles(RTCDevice dev, const rf_rig_geo *g)
{
    RTCGeometry geo = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *vb = rtcSetNewGeometryBuffer(geo, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                        3 * sizeof(float), g->nv);
    unsigned *ib = rtcSetNewGeometryBuffer(geo, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                           3 * sizeof(unsigned), g->nt);
    if (!vb || !ib) {
        rtcReleaseGeometry(geo);
        return NULL;
    }
    for (size_t i = 0; i < (size_t)g->nv * 3; i++)
        vb[i] = (float)g->p[i];
    memcpy(ib, g->t, (size_t)g->nt * 3 * sizeof *ib);
    return geo;
}

rf_rig_surface *rf_rig_surface_make(const rf_rig_geo *g)
{
    rf_rig_surface *s = calloc(1, sizeof *s);
    if (!s || !(s->dev = rtcNewDevice("threads=1,set_affinity=0"))) {
        free(s);
        return NULL;
    }
    s->scene = rtcNewScene(s->dev);
    RTCGeometry geo = rf_rig_triangles(s->dev, g);
    if (geo) {
        rtcCommitGeometry(geo);
        rtcAttachGeometry(s->scene, geo);
        rtcReleaseGeometry(geo);
    }
    rtcCommitScene(s->scene);
    if (!geo || rtcGetDeviceError(s->dev) != RTC_ERROR_NONE) {
        rf_rig_surface_free(s);
        return NULL;
    }
    return s;
}

void rf_rig_surface_free(rf_rig_surface *s)
{
    if (!s)
        return;
    if (s->scene)
        rtcReleaseScene(s->scene);
    if (s->dev)
        rtcReleaseDevice(s->dev);
    free(s);
}

double rf_rig_surface_hit(const rf_rig_surface *s, const double p[3], const double dir[3])
{
    struct RTCRayHit rh = {0};
    rh.ray.org_x = (float)p[0], rh.ray.org_y = (float)p[1], rh.ray.org_z = (float)p[2];
    rh.ray.dir_x = (float)dir[0], rh.ray.dir_y = (float)dir[1], rh.ray.dir_z = (float)dir[2];
    rh.ray.tnear = 0, rh.ray.tfar = INFINITY;
    rh.ray.mask = UINT32_MAX;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    rtcIntersect1(s->scene, &ctx, &rh);
    return rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? INFINITY : rh.ray.tfar;
}

/* Two unit vectors square to d and to each other. */
static void rf_place_frame(const double d[3], double u[3], double v[3])
{
    double a[3] = {1, 0, 0};
    if (fabs(d[0]) > 0.6)
        a[0] = 0, a[1] = 1;
    u[0] = a[1] * d[2] - a[2] * d[1], u[1] = a[2] * d[0] - a[0] * d[2],
    u[2] = a[0] * d[1] - a[1] * d[0];
    double n = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (int i = 0; i < 3; i++)
        u[i] /= n;
    v[0] = d[1] * u[2] - d[2] * u[1], v[1] = d[2] * u[0] - d[0] * u[2],
    v[2] = d[0] * u[1] - d[1] * u[0];
}

/* One step towards the centre of the section through p square to the unit direction d: rays
 * in that plane meet the surface at a fan of points around p, and the fan's area centroid is
 * the section's centre as far as the rays see it (a rectangle's in one step, where the mean of
 * chord midpoints creeps towards it). The shift into *shift; false when a ray leaves the mesh
 * or meets it beyond `reach` (p is not inside a section the rays can close). */
static bool rf_place_step(const rf_rig_surface *s, const double p[3], const double d[3],
                          double reach, double shift[3])
{
    double u[3], v[3], x[2 * RF_PLACE_PAIRS], y[2 * RF_PLACE_PAIRS];
    rf_place_frame(d, u, v);
    for (int i = 0; i < 2 * RF_PLACE_PAIRS; i++) {
        double ang = M_PI * i / RF_PLACE_PAIRS, c = cos(ang), sn = sin(ang), w[3];
        for (int a = 0; a < 3; a++)
            w[a] = c * u[a] + sn * v[a];
        double h = rf_rig_surface_hit(s, p, w);
        if (!(h <= reach))
            return false;
        x[i] = h * c, y[i] = h * sn;
    }
    double area = 0, cx = 0, cy = 0;
    for (int i = 0; i < 2 * RF_PLACE_PAIRS; i++) {
        int k = (i + 1) % (2 * RF_PLACE_PAIRS);
        double a = 0.5 * (x[i] * y[k] - x[k] * y[i]); /* triangle p, hit i, hit k */
        area += a, cx += a * (x[i] + x[k]) / 3, cy += a * (y[i] + y[k]) / 3;
    }
    if (!(area > 0))
        return false;
    cx /= area, cy /= area;
    for (int a = 0; a < 3; a++)
        shift[a] = cx * u[a] + cy * v[a];
    return true;
}

bool rf_rig_centre(const rf_rig_surface *s, double p[3], const double dir[3], double reach,
                   double limit)
{
    double n = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    if (!(n > 0))
        return false;
    double d[3] = {dir[0] / n, dir[1] / n, dir[2] / n}, q[3] = {p[0], p[1], p[2]}, shift[3];
    bool moved = false;
    for (int it = 0; it < 3 && rf_place_step(s, q, d, reach, shift); it++) {
        for (int a = 0; a < 3; a++)
            q[a] += shift[a];
        moved = true;
    }
    double m = sqrt((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) +
                    (q[2] - p[2]) * (q[2] - p[2]));
    if (!moved || m > limit)
        return false; /* no closed section, or one that would carry the joint elsewhere */
    memcpy(p, q, sizeof q);
    return true;
}

/* The direction of the bone through joint j: from its parent to its first child (or its end
 * site), the two halves given equal say so a bend (a knee) takes the plane that halves it. */
static bool rf_place_bone_dir(const rf_rig_skel *k, uint32_t j, double d[3])
{
    const double *at = k->pos + (size_t)j * 3, *out = NULL;
    const double *in = k->parent[j] >= 0 ? k->pos + (size_t)k->parent[j] * 3 : NULL;
    for (uint32_t i = j + 1; i < k->n && !out; i++) /* parents come first */
        if (k->parent[i] == (int32_t)j)
            out = k->pos + (size_t)i * 3;
    if (!out && k->has_tip[j])
        out = k->tip + (size_t)j * 3;
    const double *ends[2][2] = {{in, at}, {at, out}};
    memset(d, 0, 3 * sizeof(double));
    for (int h = 0; h < 2; h++) {
        if (!ends[h][0] || !ends[h][1])
            continue;
        const double *a = ends[h][0], *b = ends[h][1];
        double len = sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) +
                          (b[2] - a[2]) * (b[2] - a[2]));
        for (int c = 0; len > 0 && c < 3; c++)
            d[c] += (b[c] - a[c]) / len;
    }
    return d[0] != 0 || d[1] != 0 || d[2] != 0;
}

bool rf_rig_skel_centre(const rf_rig_prep *p, rf_rig_skel *k)
{
    rf_rig_surface *s = rf_rig_surface_make(&p->proxy);
    double *moved = s ? malloc(((size_t)k->n + 1) * 3 * sizeof *moved) : NULL;
    bool ok = moved != NULL;
    for (uint32_t j = 0; moved && j < k->n; j++) {
        double d[3];
        memcpy(moved + (size_t)j * 3, k->pos + (size_t)j * 3, 3 * sizeof(double));
        if (rf_place_bone_dir(k, j, d))
            rf_rig_centre(s, moved + (size_t)j * 3, d, 0.25 * p->longest, 0.04 * p->longest);
    }
    if (moved)
        memcpy(k->pos, moved, (size_t)k->n * 3 * sizeof *moved);
    free(moved);
    rf_rig_surface_free(s);
    return ok;
}

/* Joint q moved along unit fw to fraction `at` of the way through the mesh from its surface
 * behind to its surface ahead (rf_rig_skel_across, one joint). */
static void rf_place_across(const rf_rig_surface *s, double longest, double q[3],
                            const double fw[3], double at)
{
    double bw[3] = {-fw[0], -fw[1], -fw[2]};
    double ahead = rf_rig_surface_hit(s, q, fw), behind = rf_rig_surface_hit(s, q, bw);
    if (!isfinite(behind) && ahead <= 0.25 * longest) {
        /* outside, under the body (a root where two legs meet below the belly): the depth
         * is the body's above it, from the belly up */
        double in[3], step = ahead + 1e-6 * longest;
        for (int a = 0; a < 3; a++)
            in[a] = q[a] + step * fw[a];
        double depth = rf_rig_surface_hit(s, in, fw);
        if (depth <= 0.5 * longest)
            for (int a = 0; a < 3; a++)
                q[a] = in[a] + at * depth * fw[a];
        return;
    }
    if (ahead > 0.25 * longest || behind > 0.25 * longest)
        return;
    double shift = at * (ahead + behind) - behind;
    for (int a = 0; a < 3; a++)
        q[a] += shift * fw[a];
}

bool rf_rig_skel_across(const rf_rig_prep *p, rf_rig_skel *k, const uint8_t *which, rf_vec3 axis,
                        double at)
{
    double n = rf_v3_len(axis);
    if (!(n > 0))
        return true;
    rf_rig_surface *s = rf_rig_surface_make(&p->proxy);
    double fw[3] = {axis.x / n, axis.y / n, axis.z / n};
    for (uint32_t j = 0; s && j < k->n; j++)
        if (which[j])
            rf_place_across(s, p->longest, k->pos + (size_t)j * 3, fw, at);
    rf_rig_surface_free(s);
    return s != NULL;
}

#define RF_PLACE_SHEET_STEP 0.004 /* of the longest edge: how finely a sheet's reach is walked */
#define RF_PLACE_SHEET_OFF 0.002  /* of the longest edge: how far off the sheet the rays start */

/* Whether the sheet through q (a surface of no thickness lying in the plane of unit vectors d
 * and fw, unit normal n) covers the point q + t fw: a ray from just off the plane at q to that
 * point crosses the plane there alone, so it meets the surface at that distance, or the sheet
 * has an edge or a hole there. A part in the way is met sooner and ends the sheet too: the
 * body where a wing leaves it, so the joints at a wing's root stay (moved forward like the
 * clavicle, they cost the bat's look under a walk, stretch p99 53.5 -> 66.1). */
static bool rf_place_covers(const rf_rig_surface *s, const double q[3], const double n[3],
                            const double fw[3], double t, double off)
{
    double o[3], dir[3], len = 0;
    for (int a = 0; a < 3; a++)
        o[a] = q[a] - off * n[a], dir[a] = q[a] + t * fw[a] - o[a], len += dir[a] * dir[a];
    len = sqrt(len);
    for (int a = 0; a < 3; a++)
        dir[a] /= len;
    return fabs(rf_rig_surface_hit(s, o, dir) - len) <= 0.5 * off;
}

/* How far the sheet through q reaches along fw (0 when it does not cover q's own neighbourhood),
 * walked in steps up to `reach`; INFINITY when it reaches that far. */
static double rf_place_sheet_reach(const rf_rig_surface *s, const double q[3], const double n[3],
                                   const double fw[3], double longest, double reach)
{
    double step = RF_PLACE_SHEET_STEP * longest, off = RF_PLACE_SHEET_OFF * longest, t = step;
    for (; t <= reach; t += step)
        if (!rf_place_covers(s, q, n, fw, t, off))
            return t - step;
    return INFINITY;
}

/* The chord through joint j of k along unit fw, for a joint lying in a sheet: the ways the sheet
 * reaches ahead and behind into *ahead and *behind; false when j is not on a sheet across fw
 * (no bone direction, a bone along fw, or no sheet under it). */
static bool rf_place_sheet_chord(const rf_rig_surface *s, const rf_rig_skel *k, uint32_t j,
                                 const double fw[3], double longest, double *ahead, double *behind)
{
    double d[3], n[3];
    if (!rf_place_bone_dir(k, j, d))
        return false;
    n[0] = d[1] * fw[2] - d[2] * fw[1], n[1] = d[2] * fw[0] - d[0] * fw[2],
    n[2] = d[0] * fw[1] - d[1] * fw[0];
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(len > 0.5 * sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])))
        return false; /* the bone runs too near fw for a plane of the two */
    for (int a = 0; a < 3; a++)
        n[a] /= len;
    const double *q = k->pos + (size_t)j * 3, bw[3] = {-fw[0], -fw[1], -fw[2]};
    *ahead = rf_place_sheet_reach(s, q, n, fw, longest, 0.25 * longest);
    *behind = rf_place_sheet_reach(s, q, n, bw, longest, 0.25 * longest);
    return isfinite(*ahead) && isfinite(*behind) && *ahead + *behind > 0;
}

bool rf_rig_skel_chord(const rf_rig_prep *p, rf_rig_skel *k, const uint8_t *which, rf_vec3 axis,
                       double at)
{
    double n = rf_v3_len(axis);
    if (!(n > 0))
        return true;
    rf_rig_surface *s = rf_rig_surface_make(&p->proxy);
    double fw[3] = {axis.x / n, axis.y / n, axis.z / n}, bw[3] = {-fw[0], -fw[1], -fw[2]};
    for (uint32_t j = 0; s && j < k->n; j++) {
        if (!which[j])
            continue;
        double *q = k->pos + (size_t)j * 3, ahead, behind;
        if (isfinite(rf_rig_surface_hit(s, q, fw)) || isfinite(rf_rig_surface_hit(s, q, bw))) {
            rf_place_across(s, p->longest, q, fw, at); /* inside a volume, or beside one */
            continue;
        }
        if (!rf_place_sheet_chord(s, k, j, fw, p->longest, &ahead, &behind))
            continue;
        double shift = at * (ahead + behind) - behind;
        for (int a = 0; a < 3; a++)
            q[a] += shift * fw[a];
    }
    rf_rig_surface_free(s);
    return s != NULL;
}
