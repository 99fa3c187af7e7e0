/* The same character re-rigged must move like the plain rig: CMU 01_01 onto RiggedFigure (skinned
 * mesh) and onto copies of it built here, every joint renamed to a meaningless name and
 * - as an IK rig: the feet moved under a new unweighted placement root at the origin, with an
 *   unweighted IK target on each foot and a pole before each knee (the Wizard's layout);
 * - as a forest: each thigh a root of its own;
 * - with an axis-and-unit conversion node inside the tree: a node turned 90 degrees and scaled
 *   100 times between the hips and the spine, the spine under it undoing both.
 * The plain rig's mapping is carried over joint for joint; the added placement root and axis
 * node are mapped too (onto the source's hips and spine, as a matcher might): the retargeter
 * must drop them. Each variant's mesh, skinned by its clip on sampled frames, must lie within 2%
 * of the figure's height of the plain rig's at every vertex. Skipped without $RF_DATA_DIR. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "rigflow/aimport.h"
#include "rigflow/bvh.h"
#include "retarget.h"
#include "rt-maps.h"
#include "twobone.h"

typedef struct rig {
    rf_skeleton *s;
    rf_mesh *m;
} rig;

/* One joint of a variant: its parent (an index in the same list), world rest, the plain rig's
 * joint it is (or -1 for an added one) and its flags. */
typedef struct jdesc {
    int32_t parent;
    rf_xform world;
    int32_t orig;
    uint32_t flags;
} jdesc;

static const char *data_dir(void)
{
    const char *d = getenv("RF_DATA_DIR");
    return d && *d ? d : NULL;
}

static char *data_path(const char *rel)
{
    static char path[4096];
    const char *d = data_dir();
    snprintf(path, sizeof path, "%s/%s", d ? d : "", rel);
    if (!d || access(path, R_OK) != 0) {
        print_message("%s not found (RF_DATA_DIR, ../shared/data): skipped\n", rel);
        skip();
    }
    return path;
}

/* The variant made of `d` (parents placed first, names meaningless), its mesh the plain one's
 * with the skin's joint indices and inverse binds carried over. */
static rig build(const rig *plain, const jdesc *d, uint32_t count)
{
    int32_t *at = malloc(count * sizeof *at); /* list index -> new index */
    uint32_t *order = malloc(count * sizeof *order), placed = 0;
    for (uint32_t i = 0; i < count; i++)
        at[i] = -1;
    while (placed < count)
        for (uint32_t i = 0; i < count; i++)
            if (at[i] < 0 && (d[i].parent < 0 || at[d[i].parent] >= 0))
                order[placed] = i, at[i] = (int32_t)placed++;
    rig r = {rf_skeleton_new(count), rf_mesh_new()};
    r.s->up = plain->s->up, r.s->forward = plain->s->forward;
    for (uint32_t k = 0; k < count; k++) {
        const jdesc *j = &d[order[k]];
        rf_joint *out = &r.s->joints[k];
        out->name = malloc(16);
        snprintf(out->name, 16, "n%u", (k * 7 + 3) % count);
        out->parent = j->parent < 0 ? -1 : at[j->parent];
        out->flags = j->flags;
        out->rest =
            j->parent < 0 ? j->world : rf_xform_mul(rf_xform_invert(d[j->parent].world), j->world);
        if (j->orig >= 0 && (plain->s->joints[j->orig].flags & RF_JOINT_HAS_END_SITE)) {
            out->flags |= RF_JOINT_HAS_END_SITE;
            out->end_site = plain->s->joints[j->orig].end_site;
        }
    }
    const rf_mesh *m = plain->m;
    int32_t *of = malloc(plain->s->joint_count * sizeof *of); /* plain joint -> new index */
    for (uint32_t i = 0; i < count; i++)
        if (d[i].orig >= 0)
            of[d[i].orig] = at[i];
    size_t nv = m->vertex_count, nt = m->triangle_count;
    r.m->vertex_count = m->vertex_count, r.m->triangle_count = m->triangle_count;
    r.m->positions = malloc(nv * 3 * sizeof(float));
    memcpy(r.m->positions, m->positions, nv * 3 * sizeof(float));
    r.m->triangles = malloc(nt * 3 * sizeof(uint32_t));
    memcpy(r.m->triangles, m->triangles, nt * 3 * sizeof(uint32_t));
    r.m->skin_weights = malloc(nv * 4 * sizeof(float));
    memcpy(r.m->skin_weights, m->skin_weights, nv * 4 * sizeof(float));
    r.m->skin_joints = malloc(nv * 4 * sizeof(uint16_t));
    for (size_t i = 0; i < nv * 4; i++)
        r.m->skin_joints[i] = (uint16_t)of[m->skin_joints[i]];
    r.m->bind_count = count;
    r.m->inverse_bind = malloc(count * sizeof(rf_mat4));
    for (uint32_t k = 0; k < count; k++) {
        const jdesc *j = &d[order[k]];
        if (j->orig >= 0)
            r.m->inverse_bind[k] = m->inverse_bind[j->orig];
        else
            assert_true(rf_mat4_invert(rf_xform_to_mat4(j->world), &r.m->inverse_bind[k]));
    }
    free(at), free(order), free(of);
    return r;
}

static void rig_free(rig *r)
{
    rf_skeleton_free(r->s);
    rf_mesh_free(r->m);
}

/* The plain rig's joints as a list to edit (world rests), with room for `extra` more. */
static jdesc *plain_list(const rig *plain, uint32_t extra)
{
    uint32_t n = plain->s->joint_count;
    rf_xform *world = malloc(n * sizeof *world);
    rf_skeleton_world_rest(plain->s, world);
    jdesc *d = calloc(n + extra, sizeof *d);
    for (uint32_t j = 0; j < n; j++)
        d[j] = (jdesc){plain->s->joints[j].parent, world[j], (int32_t)j, 0};
    free(world);
    return d;
}

/* RiggedFigure's joints the variants are built around (read off its rest positions). */
enum {
    HIPS = 0,
    SPINE = 1,
    THIGH_L = 11,
    KNEE_L = 12,
    FOOT_L = 13,
    THIGH_R = 15,
    KNEE_R = 16,
    FOOT_R = 17
};

static rig ik_rig(const rig *plain)
{
    uint32_t n = plain->s->joint_count;
    jdesc *d = plain_list(plain, 5);
    uint32_t root = n;
    d[root] = (jdesc){-1, rf_xform_identity(), -1, RF_JOINT_UNWEIGHTED};
    d[FOOT_L].parent = d[FOOT_R].parent = (int32_t)root;
    const int feet[2] = {FOOT_L, FOOT_R}, knees[2] = {KNEE_L, KNEE_R};
    for (int i = 0; i < 2; i++) {
        d[n + 1 + i] = (jdesc){(int32_t)root, d[feet[i]].world, -1, RF_JOINT_UNWEIGHTED};
        rf_xform pole = rf_xform_identity();
        pole.t = rf_v3_add(d[knees[i]].world.t, rf_v3(0, 0, 0.4)); /* it faces +Z */
        d[n + 3 + i] = (jdesc){(int32_t)root, pole, -1, RF_JOINT_UNWEIGHTED};
    }
    rig r = build(plain, d, n + 5);
    free(d);
    return r;
}

static rig forest(const rig *plain)
{
    jdesc *d = plain_list(plain, 0);
    d[THIGH_L].parent = d[THIGH_R].parent = -1;
    rig r = build(plain, d, plain->s->joint_count);
    free(d);
    return r;
}

static rig axis_node(const rig *plain)
{
    uint32_t n = plain->s->joint_count;
    jdesc *d = plain_list(plain, 1);
    rf_xform x = {d[SPINE].world.t, rf_quat_from_axis_angle(rf_v3(1, 0, 0), RF_PI / 2),
                  rf_v3(100, 100, 100)};
    d[n] = (jdesc){HIPS, x, -1, RF_JOINT_UNWEIGHTED};
    d[SPINE].parent = (int32_t)n;
    rig r = build(plain, d, n + 1);
    free(d);
    return r;
}

/* The plain mapping carried over to a variant (joint for joint by the plain rig's index, found
 * through the inverse binds, which `build` carried over), and the added joints that carry body
 * (a placement root, an axis node) mapped as a matcher might: onto the input of their first
 * child that is mapped. */
static rf_mapping *carry_mapping(const rf_mapping *pm, const rig *plain, const rig *v)
{
    uint32_t n = v->s->joint_count;
    rf_mapping *m = rf_mapping_new(n, 1);
    for (uint32_t k = 0; k < n; k++) {
        int32_t o = -1;
        for (uint32_t j = 0; j < plain->s->joint_count && o < 0; j++)
            if (!memcmp(&plain->m->inverse_bind[j], &v->m->inverse_bind[k], sizeof(rf_mat4)))
                o = (int32_t)j;
        if (o < 0)
            continue;
        const rf_map_entry *e = &pm->entries[o];
        m->entries[k].input_count = e->input_count;
        m->entries[k].inputs = malloc((e->input_count + 1) * sizeof *e->inputs);
        memcpy(m->entries[k].inputs, e->inputs, e->input_count * sizeof *e->inputs);
    }
    /* Added joints carrying body take their first mapped child's input. */
    for (uint32_t k = n; k-- > 0;) {
        if (m->entries[k].input_count || !(v->s->joints[k].flags & RF_JOINT_UNWEIGHTED))
            continue;
        for (uint32_t c = k + 1; c < n; c++)
            if (v->s->joints[c].parent == (int32_t)k && m->entries[c].input_count &&
                !(v->s->joints[c].flags & RF_JOINT_UNWEIGHTED)) {
                m->entries[k].input_count = 1;
                m->entries[k].inputs = malloc(sizeof *m->entries[k].inputs);
                m->entries[k].inputs[0] = m->entries[c].inputs[0];
                break;
            }
    }
    return m;
}

/* Retargets the clip onto a rig as the pipeline does: the clip, the mesh's floor, the contact
 * pass with the two-bone solver, the parts pass and the whole mesh's floor after it. */
static rf_animation *run(const rf_skeleton *src, const rf_animation *clip, const rig *r,
                         const rf_mapping *m)
{
    char err[512] = "";
    rf_rt_source s = {src, clip};
    rf_retarget *rt = rf_retarget_new(&s, 1, r->s, m, NULL, err, sizeof err);
    if (!rt)
        print_error("%s\n", err);
    assert_non_null(rt);
    rf_animation *out = rf_retarget_clip(rt, NULL, NULL, err, sizeof err);
    assert_non_null(out);
    assert_true(rf_retarget_mesh_floor(rt, out, r->m, NULL, err, sizeof err));
    const rf_ik_solver_api *api = &rf_ik_twobone_api;
    rf_ik_solver *solver = rf_ik_solver_new(api, api->create(NULL, err, sizeof err), "twobone");
    rf_rt_contact_stats st;
    assert_true(rf_retarget_contacts(rt, out, solver, &st, err, sizeof err));
    rf_rt_parts_stats ps;
    assert_true(rf_retarget_parts_above(rt, out, &ps));
    assert_true(rf_retarget_mesh_clear(rt, out, r->m, NULL, err, sizeof err));
    rf_ik_solver_free(solver);
    rf_retarget_free(rt);
    return out;
}

/* The mesh skinned by frame f of a rig's clip, into pos. */
static void skin(const rig *r, const rf_animation *a, uint32_t f, rf_vec3 *pos)
{
    uint32_t n = r->s->joint_count;
    rf_xform *local = malloc(n * sizeof *local), *world = malloc(n * sizeof *world);
    rf_animation_local_pose(a, r->s, f, local);
    for (uint32_t j = 0; j < n; j++) {
        int32_t p = r->s->joints[j].parent;
        local[j].r = rf_quat_normalize(local[j].r);
        world[j] = p < 0 ? local[j] : rf_xform_mul(world[p], local[j]);
    }
    rf_mat4 *skin = malloc(n * sizeof *skin);
    rf_skin_matrices(world, r->m->inverse_bind, n, skin);
    for (uint32_t v = 0; v < r->m->vertex_count; v++)
        pos[v] = rf_mesh_skin_vertex(r->m, skin, v);
    free(local), free(world), free(skin);
}

/* The largest distance between the two rigs' skinned vertices over sampled frames, over the
 * figure's height. */
static double worst(const rig *a, const rf_animation *ca, const rig *b, const rf_animation *cb)
{
    uint32_t nv = a->m->vertex_count;
    rf_vec3 *pa = malloc(nv * sizeof *pa), *pb = malloc(nv * sizeof *pb);
    double lo = INFINITY, hi = -INFINITY, far = 0;
    skin(a, ca, 0, pa);
    for (uint32_t v = 0; v < nv; v++)
        lo = fmin(lo, pa[v].y), hi = fmax(hi, pa[v].y);
    for (uint32_t f = 0; f < ca->frame_count; f += 97) {
        skin(a, ca, f, pa);
        skin(b, cb, f, pb);
        for (uint32_t v = 0; v < nv; v++)
            far = fmax(far, rf_v3_dist(pa[v], pb[v]));
    }
    free(pa), free(pb);
    return far / (hi - lo);
}

static void test_rerig(void **state)
{
    (void)state;
    char err[1024];
    rf_skeleton *src = NULL;
    rf_animation *clip = NULL;
    assert_true(
        rf_bvh_read_file(data_path("bvh/cmu_01_01.bvh"), NULL, &src, &clip, err, sizeof err));
    rf_ai_result res;
    assert_true(rf_ai_import(data_path("models/RiggedFigure.glb"), NULL, &res, NULL, NULL, err,
                             sizeof err));
    rig plain = {res.skeleton, res.mesh};
    res.skeleton = NULL, res.mesh = NULL;
    rf_ai_result_clear(&res);
    char path[4096];
    const char *dir = getenv("RF_SRCDIR");
    snprintf(path, sizeof path, "%s/tests/retarget/maps/RiggedFigure.txt", dir ? dir : ".");
    rf_mapping *pm = rt_map_read(path, plain.s, src, err, sizeof err);
    assert_non_null(pm);
    rf_animation *base = run(src, clip, &plain, pm);
    static const char *const names[] = {"IK rig", "forest", "axis-and-unit node"};
    rig (*const make[])(const rig *) = {ik_rig, forest, axis_node};
    for (int i = 0; i < 3; i++) {
        rig v = make[i](&plain);
        rf_mapping *m = carry_mapping(pm, &plain, &v);
        rf_animation *out = run(src, clip, &v, m);
        double far = worst(&plain, base, &v, out);
        print_message("%s: the farthest vertex %.4f%% of the height from the plain rig's\n",
                      names[i], 100 * far);
        assert_true(far <= 0.02);
        rf_animation_free(out), rf_mapping_free(m), rig_free(&v);
    }
    /* The IK rig's feet flagged reversed, as a matcher reading the file's tree (feet under the
     * placement root) may flag them: the feet are placed from the shins, so the flag does not
     * hold and the rig still moves like the plain one (unheeded, the feet pitch the other way). */
    rig v = ik_rig(&plain);
    rf_mapping *m = carry_mapping(pm, &plain, &v);
    const int feet[2] = {FOOT_L, FOOT_R};
    uint32_t flagged = 0;
    for (int i = 0; i < 2; i++) /* the variant's joints are reordered: found by their binds */
        for (uint32_t k = 0; k < v.s->joint_count; k++)
            if (!memcmp(&plain.m->inverse_bind[feet[i]], &v.m->inverse_bind[k], sizeof(rf_mat4)))
                for (uint32_t q = 0; q < m->entries[k].input_count; q++)
                    m->entries[k].inputs[q].flags |= RF_MAP_REVERSE, flagged++;
    assert_int_equal(flagged, 2);
    rf_animation *out = run(src, clip, &v, m);
    double far = worst(&plain, base, &v, out);
    print_message("IK rig, feet flagged reversed: the farthest vertex %.4f%% of the height\n",
                  100 * far);
    assert_true(far <= 0.02);
    rf_animation_free(out), rf_mapping_free(m), rig_free(&v);
    rf_animation_free(base), rf_mapping_free(pm), rig_free(&plain);
    rf_skeleton_free(src), rf_animation_free(clip);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_rerig)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
