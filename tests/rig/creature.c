/* creature: a random creature mesh skinned to a generated skeleton (tests/match/gen.c), for
 * testing the riggers and scan-to-animation on bodies nobody tuned them to.
 *
 *   creature [--plan biped|quadruped|dragon] [--seed N] [--legs PAIRS] [--obj BARE.obj] OUT.glb
 *
 * Each bone gets a closed capsule around it (its thickness from what the bone is: a trunk, a
 * limb segment, a digit, a tail tapering to its tip), weighted wholly to its joint: loose parts
 * overlapping at the joints, as many real models are built (RobotExpressive has 19). Most
 * dragons' wings (7 in 10) get a membrane, one open sheet between the fingers and back to the
 * flank, each vertex weighted to the wing bone nearest it. --legs adds PAIRS (1 to 4) more pairs
 * of legs along the trunk of a quadruped or a dragon, copies of its hind legs. Helpers and
 * ground roots get no surface and no weight. The GLB holds the skeleton and the skinned mesh, the
 * answer rig-bench measures a rigger against; glTF fixes +Y up, so it is written with the body's
 * up turned onto +Y (by the glTF writer, from the skeleton's declared up) and its facing left as
 * generated, any way about up, as a scan exported to GLB faces. --obj also writes the bare mesh
 * exactly as generated (any up, any facing, scale 0.01 to 100, moved off the origin), as a scan
 * comes. A line on stdout says what was made. Exit status 0, 1 when a file cannot be written,
 * 2 on a usage error. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <rigflow/gltf-write.h>
#include <rigflow/model-copy.h>

#include "gen.h"

#define CR_AROUND 12 /* vertices around a capsule */
#define CR_CAP 4     /* rings in each end cap, the pole excluded */

typedef struct cr_mesh {
    float *pos, *nrm;
    uint32_t *tri;
    uint16_t *joint;
    uint32_t nv, nt, cap_v, cap_t;
} cr_mesh;

static uint64_t cr_rng;

/* A draw of the mesh's own, so the generator's skeleton is the one test_generated checks. */
static double cr_rnd(double lo, double hi)
{
    cr_rng ^= cr_rng >> 12, cr_rng ^= cr_rng << 25, cr_rng ^= cr_rng >> 27;
    double u = (double)((cr_rng * 2685821657736338717ULL) >> 11) / 9007199254740992.0;
    return lo + (hi - lo) * u;
}

static bool cr_grow(cr_mesh *m, uint32_t nv, uint32_t nt)
{
    if (m->nv + nv > m->cap_v) {
        m->cap_v = 2 * (m->nv + nv);
        float *p = realloc(m->pos, (size_t)m->cap_v * 3 * sizeof *p);
        float *n = p ? realloc(m->nrm, (size_t)m->cap_v * 3 * sizeof *n) : NULL;
        uint16_t *j = n ? realloc(m->joint, (size_t)m->cap_v * sizeof *j) : NULL;
        if (p)
            m->pos = p;
        if (n)
            m->nrm = n;
        if (j)
            m->joint = j;
        if (!j)
            return false;
    }
    if (m->nt + nt > m->cap_t) {
        m->cap_t = 2 * (m->nt + nt);
        uint32_t *t = realloc(m->tri, (size_t)m->cap_t * 3 * sizeof *t);
        if (!t)
            return false;
        m->tri = t;
    }
    return true;
}

static void cr_vertex(cr_mesh *m, rf_vec3 p, rf_vec3 n, uint16_t joint)
{
    float *d = m->pos + (size_t)m->nv * 3, *e = m->nrm + (size_t)m->nv * 3;
    d[0] = (float)p.x, d[1] = (float)p.y, d[2] = (float)p.z;
    e[0] = (float)n.x, e[1] = (float)n.y, e[2] = (float)n.z;
    m->joint[m->nv++] = joint;
}

static void cr_tri(cr_mesh *m, uint32_t a, uint32_t b, uint32_t c)
{
    uint32_t *t = m->tri + (size_t)m->nt++ * 3;
    t[0] = a, t[1] = b, t[2] = c;
}

/* A closed capsule of radius r around the segment a-b (a sphere when they meet), its triangles
 * wound outwards: rings from the pole beyond a to the pole beyond b, CR_AROUND vertices each. */
static bool cr_capsule(cr_mesh *m, rf_vec3 a, rf_vec3 b, double r, uint16_t joint)
{
    double len = rf_v3_dist(a, b);
    rf_vec3 d = len > 1e-12 ? rf_v3_scale(rf_v3_sub(b, a), 1 / len) : rf_v3(0, 1, 0);
    rf_vec3 side = fabs(d.x) < 0.9 ? rf_v3(1, 0, 0) : rf_v3(0, 1, 0);
    rf_vec3 u = rf_v3_normalize(rf_v3_cross(side, d)), v = rf_v3_cross(d, u); /* u x v = d */
    int mid = (int)fmin(8, floor(len / (2 * r))); /* rings along the body between the caps */
    int rings = 2 * CR_CAP + 2 + mid;
    if (!cr_grow(m, (uint32_t)(rings * CR_AROUND + 2), (uint32_t)(2 * rings * CR_AROUND)))
        return false;
    uint32_t first = m->nv;
    cr_vertex(m, rf_v3_sub(a, rf_v3_scale(d, r)), rf_v3_scale(d, -1), joint);
    for (int k = 0; k < rings; k++) {
        rf_vec3 c;
        double along, out; /* the ring's normal: along d and out from the axis */
        if (k <= CR_CAP) { /* the cap beyond a, then a's own ring */
            double phi = RF_PI / 2 * (k + 1) / (CR_CAP + 1);
            c = a, along = -cos(phi), out = sin(phi);
        } else if (k <= CR_CAP + mid) { /* along the body */
            c = rf_v3_lerp(a, b, (double)(k - CR_CAP) / (mid + 1)), along = 0, out = 1;
        } else { /* b's own ring, then the cap beyond it */
            double phi = RF_PI / 2 * (rings - k) / (CR_CAP + 1);
            c = b, along = cos(phi), out = sin(phi);
        }
        for (int s = 0; s < CR_AROUND; s++) {
            double t = 2 * RF_PI * s / CR_AROUND;
            rf_vec3 radial = rf_v3_add(rf_v3_scale(u, cos(t)), rf_v3_scale(v, sin(t)));
            rf_vec3 n = rf_v3_add(rf_v3_scale(d, along), rf_v3_scale(radial, out));
            cr_vertex(m, rf_v3_add(c, rf_v3_scale(n, r)), n, joint);
        }
    }
    uint32_t last = m->nv;
    cr_vertex(m, rf_v3_add(b, rf_v3_scale(d, r)), d, joint);
    for (int s = 0; s < CR_AROUND; s++) {
        uint32_t s1 = (uint32_t)(s + 1) % CR_AROUND;
        cr_tri(m, first, first + 1 + s1, first + 1 + (uint32_t)s);
        for (int k = 0; k + 1 < rings; k++) {
            uint32_t r0 = first + 1 + (uint32_t)(k * CR_AROUND), r1 = r0 + CR_AROUND;
            cr_tri(m, r0 + (uint32_t)s, r0 + s1, r1 + (uint32_t)s);
            cr_tri(m, r0 + s1, r1 + s1, r1 + (uint32_t)s);
        }
        uint32_t rl = first + 1 + (uint32_t)((rings - 1) * CR_AROUND);
        cr_tri(m, rl + (uint32_t)s, rl + s1, last);
    }
    return true;
}

/* How thick a bone is, in the generator's canonical units (a biped about 1.7 tall): trunk,
 * limbs and tail by what they are, scaled by the creature's build (trunk) and its limbs' build;
 * 0 for a bone with no surface of its own. */
static double cr_radius(const gen_skel *g, uint32_t i, double trunk, double limbs)
{
    const gen_label *l = &g->label[i];
    bool bip = g->plan == GEN_BIPED;
    double len = rf_v3_dist(g->bone_from[i], g->bone_to[i]) / g->scale;
    static const double fore[] = {0.05, 0.055, 0.045, 0.035, 0.025};
    static const double hind[] = {0.07, 0.075, 0.055, 0.04, 0.03};
    switch (l->part) {
    case GEN_PELVIS:
    case GEN_SPINE:
    case GEN_CHEST:
        return (bip ? 0.13 : 0.17) * trunk;
    case GEN_NECK:
        return (bip ? 0.06 : 0.08) * trunk;
    case GEN_HEAD:
        return 0.45 * len;
    case GEN_JAW:
        return 0.3 * len;
    case GEN_EYE:
        return 0.03;
    case GEN_TAIL:
        return 0.07 * trunk * (1 - 0.75 * l->place);
    case GEN_FORE:
        return fore[l->seg < 5 ? l->seg : 4] * limbs;
    case GEN_HIND:
        return hind[l->seg < 5 ? l->seg : 4] * limbs;
    case GEN_WING:
        return (l->seg == 1 ? 0.035 : 0.028) * limbs;
    case GEN_DIGIT:
        return (l->wing ? 0.015 : 0.012) * limbs;
    default:
        return 0; /* helpers and ground roots */
    }
}

#define CR_SHEET 6 /* each membrane triangle cut into CR_SHEET^2 */

/* Distance from x to the bone of joint i. */
static double cr_bone_dist(const gen_skel *g, uint32_t i, rf_vec3 x)
{
    rf_vec3 a = g->bone_from[i], d = rf_v3_sub(g->bone_to[i], a);
    double dd = rf_v3_dot(d, d);
    double t = dd > 0 ? fmin(1, fmax(0, rf_v3_dot(rf_v3_sub(x, a), d) / dd)) : 0;
    return rf_v3_dist(x, rf_v3_add(a, rf_v3_scale(d, t)));
}

/* The wing bone of `side` (its upper and lower wing, its fingers) nearest x. */
static uint16_t cr_wing_bone(const gen_skel *g, int side, rf_vec3 x)
{
    uint16_t best = 0;
    double near = INFINITY;
    for (uint32_t i = 0; i < g->s->joint_count; i++) {
        const gen_label *l = &g->label[i];
        if (l->side != side || !(l->part == GEN_WING || (l->part == GEN_DIGIT && l->wing)))
            continue;
        double d = cr_bone_dist(g, i, x);
        if (d < near)
            near = d, best = (uint16_t)i;
    }
    return best;
}

/* One membrane triangle, cut into a grid of small ones (one sheet, both sides showing, as
 * modellers build wings), each vertex weighted to the wing bone nearest it. */
static bool cr_sheet_tri(const gen_skel *g, cr_mesh *m, int side, rf_vec3 a, rf_vec3 b, rf_vec3 c)
{
    rf_vec3 n = rf_v3_cross(rf_v3_sub(b, a), rf_v3_sub(c, a));
    if (rf_v3_len(n) <= 0)
        return true;
    n = rf_v3_normalize(n);
    if (!cr_grow(m, (CR_SHEET + 1) * (CR_SHEET + 2) / 2, CR_SHEET * CR_SHEET))
        return false;
    uint32_t first = m->nv, row[CR_SHEET + 2];
    for (int i = 0, at = 0; i <= CR_SHEET; i++) { /* rows from a towards b, c */
        row[i] = (uint32_t)at;
        for (int j = 0; j <= CR_SHEET - i; j++, at++) {
            rf_vec3 x = rf_v3_add(a, rf_v3_add(rf_v3_scale(rf_v3_sub(b, a), (double)j / CR_SHEET),
                                               rf_v3_scale(rf_v3_sub(c, a), (double)i / CR_SHEET)));
            cr_vertex(m, x, n, cr_wing_bone(g, side, x));
        }
    }
    for (int i = 0; i < CR_SHEET; i++)
        for (int j = 0; j < CR_SHEET - i; j++) {
            uint32_t p = first + row[i] + (uint32_t)j, q = first + row[i + 1] + (uint32_t)j;
            cr_tri(m, p, p + 1, q);
            if (j + 1 < CR_SHEET - i)
                cr_tri(m, p + 1, q + 1, q);
        }
    return true;
}

/* A wing's membrane: from the wrist between each two fingers' tips, and from the wrist, the
 * elbow and the shoulder back to the flank (the hind leg's socket on that side). */
static bool cr_membrane(const gen_skel *g, cr_mesh *m, int side)
{
    rf_vec3 tip[8], shoulder = {0}, elbow = {0}, flank = {0};
    int tips = 0;
    bool have_flank = false;
    for (uint32_t i = 0; i < g->s->joint_count; i++) {
        const gen_label *l = &g->label[i];
        if (l->side != side)
            continue;
        if (l->part == GEN_WING && l->seg == 1)
            shoulder = g->bone_from[i];
        else if (l->part == GEN_WING && l->seg == 2)
            elbow = g->bone_from[i];
        else if (l->part == GEN_HIND && l->seg == 1)
            flank = g->bone_from[i], have_flank = true;
        else if (l->part == GEN_DIGIT && l->wing && l->digit < 8) {
            tip[l->digit] = g->bone_to[i]; /* the finger's last segment comes last */
            tips = l->digit + 1 > tips ? l->digit + 1 : tips;
        }
    }
    if (tips < 2 || !have_flank)
        return true;
    rf_vec3 wrist = elbow;
    for (uint32_t i = 0; i < g->s->joint_count; i++)
        if (g->label[i].side == side && g->label[i].part == GEN_WING && g->label[i].seg == 2)
            wrist = g->bone_to[i];
    bool ok = true;
    for (int d = 0; ok && d + 1 < tips; d++)
        ok = cr_sheet_tri(g, m, side, wrist, tip[d], tip[d + 1]);
    return ok && cr_sheet_tri(g, m, side, wrist, tip[tips - 1], flank) &&
           cr_sheet_tri(g, m, side, wrist, flank, elbow) &&
           cr_sheet_tri(g, m, side, elbow, flank, shoulder);
}

/* The capsules (their triangles first, *closed of them), then the membranes. */
static bool cr_build(const gen_skel *g, cr_mesh *m, uint32_t *closed)
{
    double trunk = cr_rnd(0.7, 1.4), limbs = cr_rnd(0.7, 1.2);
    bool membranes = cr_rnd(0, 1) < 0.7;
    for (uint32_t i = 0; i < g->s->joint_count; i++) {
        double r = cr_radius(g, i, trunk, limbs) * g->scale;
        if (r > 0 && !cr_capsule(m, g->bone_from[i], g->bone_to[i], r, (uint16_t)i))
            return false;
    }
    *closed = m->nt;
    for (int side = 1; membranes && side <= 2; side++)
        if (!cr_membrane(g, m, side))
            return false;
    return m->nv > 0;
}

/* Extra pairs of legs along the trunk (an insect's, a centipede's middle legs): each a copy of
 * the hind legs (thigh to toe, frames and end sites alike) moved k/(pairs + 1) of the way from
 * the pelvis to the chest, level, so its feet stand on the floor (spaced evenly along the trunk,
 * each hung from the spine joint nearest its place). Appended to the skeleton, labels and bones.
 * False when out of memory. */
static bool cr_add_legs(gen_skel *g, int pairs)
{
    uint32_t n = g->s->joint_count, spine[64], ns = 0, legs[32], nl = 0;
    for (uint32_t i = 0; i < n; i++) {
        const gen_label *l = &g->label[i];
        if ((l->part == GEN_PELVIS || l->part == GEN_SPINE || l->part == GEN_CHEST) && ns < 64)
            spine[ns++] = i;
        if (l->part == GEN_HIND && l->seg >= 1 && nl < 32)
            legs[nl++] = i;
    }
    if (ns < 3 || !nl || pairs <= 0)
        return true;
    uint32_t add = (uint32_t)pairs * nl, total = n + add;
    rf_skeleton *s = rf_skeleton_new(total);
    gen_label *label = realloc(g->label, total * sizeof *label);
    rf_vec3 *from = realloc(g->bone_from, total * sizeof *from);
    rf_vec3 *to = realloc(g->bone_to, total * sizeof *to);
    rf_xform *w = calloc(total, sizeof *w);
    int32_t *copy = malloc(n * sizeof *copy);
    if (label)
        g->label = label;
    if (from)
        g->bone_from = from;
    if (to)
        g->bone_to = to;
    if (!s || !label || !from || !to || !w || !copy) {
        rf_skeleton_free(s), free(w), free(copy);
        return false;
    }
    s->up = g->s->up, s->forward = g->s->forward;
    for (uint32_t i = 0; i < n; i++) { /* the old joints as they were */
        s->joints[i] = g->s->joints[i];
        s->joints[i].name = rf_strdup(g->s->joints[i].name);
    }
    rf_skeleton_world_rest(g->s, w);
    uint32_t at = n;
    char name[64];
    for (int k = 1; k <= pairs; k++) {
        rf_vec3 at_k = rf_v3_lerp(w[spine[0]].t, w[spine[ns - 1]].t, (double)k / (pairs + 1));
        uint32_t host = spine[0];
        for (uint32_t i = 1; i < ns; i++) /* the spine joint nearest that place */
            if (rf_v3_dist(w[spine[i]].t, at_k) < rf_v3_dist(w[host].t, at_k))
                host = spine[i];
        rf_vec3 d = rf_v3_sub(at_k, w[spine[0]].t);
        d = rf_v3_sub(d, rf_v3_scale(g->up, rf_v3_dot(d, g->up))); /* level: feet on the floor */
        for (uint32_t i = 0; i < n; i++)
            copy[i] = -1;
        for (uint32_t e = 0; e < nl; e++, at++) {
            uint32_t h = legs[e];
            int32_t hp = g->s->joints[h].parent;
            int32_t parent = copy[hp] >= 0 ? copy[hp] : (int32_t)host;
            copy[h] = (int32_t)at;
            w[at] = w[h], w[at].t = rf_v3_add(w[h].t, d);
            rf_joint *j = &s->joints[at];
            *j = g->s->joints[h];
            j->parent = parent;
            j->rest = rf_xform_mul(rf_xform_invert(w[parent]), w[at]);
            snprintf(name, sizeof name, "%s_pair%d", g->s->joints[h].name, k);
            j->name = rf_strdup(name);
            g->label[at] = g->label[h];
            g->bone_from[at] = rf_v3_add(g->bone_from[h], d);
            g->bone_to[at] = rf_v3_add(g->bone_to[h], d);
        }
    }
    rf_skeleton_free(g->s);
    g->s = s;
    free(w), free(copy);
    return true;
}

/* The generated skeleton and the capsules as a skinned rf_mesh (the arrays handed over). */
static rf_mesh *cr_skinned(const gen_skel *g, cr_mesh *c)
{
    rf_mesh *m = rf_mesh_new();
    uint32_t nj = g->s->joint_count;
    if (!m)
        return NULL;
    m->vertex_count = c->nv, m->triangle_count = c->nt;
    m->positions = c->pos, m->normals = c->nrm, m->triangles = c->tri;
    c->pos = c->nrm = NULL, c->tri = NULL;
    m->skin_joints = calloc((size_t)c->nv * 4, sizeof *m->skin_joints);
    m->skin_weights = calloc((size_t)c->nv * 4, sizeof *m->skin_weights);
    m->inverse_bind = calloc(nj, sizeof *m->inverse_bind);
    rf_xform *w = calloc(nj, sizeof *w);
    if (!m->skin_joints || !m->skin_weights || !m->inverse_bind || !w) {
        free(w);
        rf_mesh_free(m);
        return NULL;
    }
    for (uint32_t v = 0; v < c->nv; v++)
        m->skin_joints[v * 4] = c->joint[v], m->skin_weights[v * 4] = 1;
    rf_skeleton_world_rest(g->s, w);
    m->bind_count = nj;
    for (uint32_t j = 0; j < nj; j++)
        m->inverse_bind[j] = rf_xform_to_mat4(rf_xform_invert(w[j]));
    free(w);
    return m;
}

/* The bare mesh as an OBJ, written beside and renamed into place (no half-written file). */
static bool cr_write_obj(const char *path, const rf_mesh *m)
{
    size_t n = strlen(path) + 8;
    char *tmp = malloc(n);
    snprintf(tmp, n, "%s.tmp", path);
    FILE *f = fopen(tmp, "w");
    bool ok = f != NULL;
    for (uint32_t v = 0; ok && v < m->vertex_count; v++) {
        const float *p = m->positions + (size_t)v * 3;
        ok = fprintf(f, "v %.9g %.9g %.9g\n", p[0], p[1], p[2]) > 0;
    }
    for (uint32_t t = 0; ok && t < m->triangle_count; t++) {
        const uint32_t *i = m->triangles + (size_t)t * 3;
        ok = fprintf(f, "f %u %u %u\n", i[0] + 1, i[1] + 1, i[2] + 1) > 0;
    }
    if (f)
        ok = fclose(f) == 0 && ok;
    ok = ok && rename(tmp, path) == 0;
    if (!ok) {
        fprintf(stderr, "creature: %s: %s\n", path, strerror(errno));
        remove(tmp);
    }
    free(tmp);
    return ok;
}

/* The mesh's extent along up (the body's height as generated, whatever its frame). */
static double cr_height(const rf_mesh *m, rf_vec3 up)
{
    double lo = INFINITY, hi = -INFINITY;
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        const float *q = m->positions + (size_t)v * 3;
        double h = rf_v3_dot(rf_v3(q[0], q[1], q[2]), up);
        lo = fmin(lo, h), hi = fmax(hi, h);
    }
    return hi - lo;
}

/* The signed volume of the mesh's first `closed` triangles, the closed capsules (positive when
 * they wind outwards). */
static double cr_volume(const rf_mesh *m, uint32_t closed)
{
    double vol = 0;
    for (uint32_t t = 0; t < closed; t++) {
        rf_vec3 p[3];
        for (int k = 0; k < 3; k++) {
            const float *q = m->positions + (size_t)m->triangles[t * 3 + k] * 3;
            p[k] = rf_v3(q[0], q[1], q[2]);
        }
        vol += rf_v3_dot(p[0], rf_v3_cross(p[1], p[2])) / 6;
    }
    return vol;
}

static int cr_usage(void)
{
    fprintf(stderr,
            "usage: creature [--plan biped|quadruped|dragon] [--seed N] [--legs PAIRS] [--obj "
            "BARE.obj] OUT.glb\n");
    return 2;
}

int main(int argc, char **argv)
{
    static const char *const plans[] = {"biped", "quadruped", "dragon"};
    int plan = GEN_BIPED;
    unsigned long long seed = 1;
    const char *obj = NULL, *out = NULL;
    long legs = 0;
    for (int a = 1; a < argc; a++) {
        if (strcmp(argv[a], "--plan") == 0 && a + 1 < argc) {
            for (plan = 0; plan < GEN_PLAN_COUNT && strcmp(plans[plan], argv[a + 1]); plan++)
                ;
            if (plan == GEN_PLAN_COUNT)
                return cr_usage();
            a++;
        } else if (strcmp(argv[a], "--seed") == 0 && a + 1 < argc) {
            char *end;
            seed = strtoull(argv[++a], &end, 10);
            if (*end || !*argv[a])
                return cr_usage();
        } else if (strcmp(argv[a], "--legs") == 0 && a + 1 < argc) {
            char *end;
            legs = strtol(argv[++a], &end, 10);
            if (*end || !*argv[a] || legs < 0 || legs > 4)
                return cr_usage();
        } else if (strcmp(argv[a], "--obj") == 0 && a + 1 < argc) {
            obj = argv[++a];
        } else if (argv[a][0] != '-' && !out) {
            out = argv[a];
        } else {
            return cr_usage();
        }
    }
    if (!out)
        return cr_usage();
    gen_skel g = gen_make((gen_plan)plan, seed);
    if ((legs && plan == GEN_BIPED) || !cr_add_legs(&g, (int)legs)) {
        fprintf(stderr, legs && plan == GEN_BIPED
                            ? "creature: --legs needs a quadruped or a dragon\n"
                            : "creature: out of memory\n");
        gen_free(&g);
        return legs && plan == GEN_BIPED ? 2 : 1;
    }
    cr_rng = seed * 0xD1B54A32D192ED03ULL + 7;
    cr_mesh c = {0};
    uint32_t closed = 0;
    rf_mesh *m = cr_build(&g, &c, &closed) ? cr_skinned(&g, &c) : NULL;
    free(c.pos), free(c.nrm), free(c.tri), free(c.joint);
    if (!m) {
        fprintf(stderr, "creature: out of memory\n");
        gen_free(&g);
        return 1;
    }
    /* glTF's +Y up: the writer turns the body's up onto it; the facing stays as generated */
    g.s->up = g.up;
    char err[1024] = "";
    bool ok = (!obj || cr_write_obj(obj, m)) &&
              rf_gltf_write_file(out, NULL, g.s, NULL, m, NULL, err, sizeof err);
    if (!ok && err[0])
        fprintf(stderr, "creature: %s\n", err);
    if (ok)
        printf(
            "%s seed %llu: %u joints, %u vertices, %u triangles, volume %.4g, up %.2f,%.2f,%.2f, "
            "facing %.2f,%.2f,%.2f, scale %.4g, height %.6g\n",
            plans[plan], seed, g.s->joint_count, m->vertex_count, m->triangle_count,
            cr_volume(m, closed), g.up.x, g.up.y, g.up.z, g.forward.x, g.forward.y, g.forward.z,
            g.scale, cr_height(m, g.up));
    rf_mesh_free(m);
    gen_free(&g);
    return ok ? 0 : 1;
}
