/* Retargeting on the shared data (../shared/data; skipped with a message without it): CMU onto
 * human skeletons with other rest poses and proportions, measured for direction fidelity; the
 * identity on a BVH and a glTF skeleton; a degenerate-rest source (Bandai); foot skate with and
 * without the contact pass; CMU onto the Fox through mirrored front legs; the Fox's Walk onto
 * Testwuson, its neck kept near its rest; CMU onto Testwuson, its shoulder blades kept near
 * theirs; the floor of a node tree with no skin (vrm_sample)
 * measured on its joints, bone tips and rigid meshes; greenman and the Fox turned about their up
 * with their axes, retargeted as the unturned ones turned.
 *
 * Mappings come from name correspondences in tests/retarget/maps/, written by reading each file's
 * skeleton (joint names and rest positions); the retargeter itself never sees a name. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include <cmocka.h>

#include "rigflow/aimport.h"
#include "rigflow/bvh.h"
#include "retarget.h"
#include "rigflow/model-copy.h"
#include "rt-fixtures.h"
#include "rt-maps.h"
#include "twobone.h"

/* ---- loading ---- */

typedef struct clip {
    rf_skeleton *skel;
    rf_animation *anim;
} clip;

static const char *data_dir(void)
{
    const char *d = getenv("RF_DATA_DIR");
    return d && *d ? d : NULL;
}

/* Loads data file `rel` (BVH natively, anything else through Assimp: its clip `clip_name`, NULL
 * for the first), or skips the test. */
static clip load_clip(const char *rel, const char *clip_name)
{
    clip c = {NULL, NULL};
    char path[4096], err[1024];
    const char *d = data_dir();
    snprintf(path, sizeof path, "%s/%s", d ? d : "", rel);
    if (!d || access(path, R_OK) != 0) {
        print_message("%s not found (RF_DATA_DIR, ../shared/data): skipped\n", rel);
        skip();
    }
    const char *ext = strrchr(rel, '.');
    if (ext && strcasecmp(ext, ".bvh") == 0) {
        bool ok = rf_bvh_read_file(path, NULL, &c.skel, &c.anim, err, sizeof err);
        if (!ok)
            print_error("%s\n", err);
        assert_true(ok);
        return c;
    }
    rf_ai_result r;
    rf_ai_options opts = {0};
    opts.clip = clip_name;
    bool ok = rf_ai_import(path, &opts, &r, NULL, NULL, err, sizeof err);
    if (!ok)
        print_error("%s\n", err);
    assert_true(ok);
    c.skel = r.skeleton, c.anim = r.animation;
    r.skeleton = NULL, r.animation = NULL;
    rf_ai_result_clear(&r);
    return c;
}

static clip load(const char *rel)
{
    return load_clip(rel, NULL);
}

static void clip_free(clip *c)
{
    rf_skeleton_free(c->skel);
    rf_animation_free(c->anim);
}

/* ---- mappings ---- */

/* The mapping of maps/NAME.txt (target joint, CMU joint). */
static rf_mapping *map_named(const char *name, const clip *tgt, const clip *src)
{
    char path[4096], err[512] = "";
    const char *dir = getenv("RF_SRCDIR");
    snprintf(path, sizeof path, "%s/tests/retarget/maps/%s.txt", dir ? dir : ".", name);
    rf_mapping *m = rt_map_read(path, tgt->skel, src->skel, err, sizeof err);
    if (!m)
        print_error("%s\n", err);
    assert_non_null(m);
    return m;
}

static void add_input(rf_mapping *m, int32_t t, uint32_t k, int32_t s, uint32_t flags)
{
    rf_map_entry *e = &m->entries[t];
    e->inputs = realloc(e->inputs, (e->input_count + 1) * sizeof *e->inputs);
    e->inputs[e->input_count++] = (rf_map_input){k, (uint32_t)s, 1, 0, flags};
}

/* ---- runs ---- */

typedef struct result {
    rf_retarget *rt;
    rf_animation *out;
    rf_rt_report rep;
} result;

static result retarget(const clip *src, const clip *tgt, const rf_mapping *m,
                       const rf_retarget_options *o)
{
    char err[512] = "";
    rf_rt_source s = {src->skel, src->anim};
    result r;
    memset(&r, 0, sizeof r);
    r.rt = rf_retarget_new(&s, 1, tgt->skel, m, o, err, sizeof err);
    if (!r.rt)
        print_error("%s\n", err);
    assert_non_null(r.rt);
    r.out = rf_retarget_clip(r.rt, NULL, NULL, err, sizeof err);
    assert_non_null(r.out);
    bool ok =
        rf_retarget_measure(r.rt, r.out, rf_retarget_start_time(r.rt), &r.rep, err, sizeof err);
    assert_true(ok);
    return r;
}

static void result_free(result *r)
{
    rf_animation_free(r->out);
    rf_retarget_free(r->rt);
}

static rf_retarget_options defaults(void)
{
    rf_retarget_options o;
    rf_retarget_options_default(&o);
    return o;
}

/* CMU 01_01 onto a human target; direction fidelity must stay under 5 degrees on average. */
static void cmu_onto(const char *rel, const char *map)
{
    clip src = load("bvh/cmu_01_01.bvh"), tgt = load(rel);
    rf_mapping *m = map_named(map, &tgt, &src);
    rf_retarget_options o = defaults();
    result r = retarget(&src, &tgt, m, &o);
    rf_rt_info info;
    rf_retarget_info(r.rt, &info);
    print_message("CMU onto %s: fidelity %.3f deg mean, p95 %.3f, max %.3f over %u bones x %u "
                  "frames; legs %.4g -> %.4g (root x%.4g); ground error %.3f leg\n",
                  rel, r.rep.fidelity_mean, r.rep.fidelity_p95, r.rep.fidelity_max,
                  r.rep.fidelity_bones, r.rep.frames, info.leg_source, info.leg_target,
                  info.root_scale, r.rep.ground_error);
    assert_true(r.rep.fidelity_bones >= 4);
    assert_true(r.rep.fidelity_mean < 5.0);
    assert_true(r.rep.ground_error < 0.05); /* feet on the floor as the source's are */
    result_free(&r);
    rf_mapping_free(m);
    clip_free(&src), clip_free(&tgt);
}

static void onto_boxing(void **state)
{
    (void)state;
    cmu_onto("bvh/boxing_toes.bvh", "boxing_toes");
}

static void onto_figure(void **state)
{
    (void)state;
    cmu_onto("models/RiggedFigure.glb", "RiggedFigure");
}

static void onto_greenman(void **state)
{
    (void)state;
    cmu_onto("models/greenman.glb", "greenman");
}

static void onto_bcn(void **state)
{
    (void)state;
    cmu_onto("models/BCN_Epileptic.X", "BCN_Epileptic");
}

static void onto_bandai(void **state)
{
    (void)state;
    cmu_onto("bvh/bandai_walk.bvh", "bandai");
}

/* ---- identity ---- */

static void identity_on(const char *rel)
{
    clip c = load(rel);
    uint32_t n = c.skel->joint_count;
    rf_mapping *m = rf_mapping_new(n, 1);
    for (uint32_t j = 0; j < n; j++)
        add_input(m, (int32_t)j, 0, (int32_t)j, 0);
    rf_retarget_options o = defaults();
    result r = retarget(&c, &c, m, &o);
    double worst_q = 0, worst_t = 0;
    assert_int_equal(r.out->frame_count, c.anim->frame_count);
    for (uint32_t f = 0; f < c.anim->frame_count; f++)
        for (uint32_t j = 0; j < n; j++) {
            const float *a = r.out->rotations + ((size_t)f * n + j) * 4;
            const float *b = c.anim->rotations + ((size_t)f * n + j) * 4;
            double dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
            for (int k = 0; k < 4; k++)
                worst_q = fmax(worst_q, fabs((dot < 0 ? -a[k] : a[k]) - b[k]));
            if (j == 0 || (c.anim->channels[j] & RF_CHANNEL_TRANSLATION))
                worst_t = fmax(worst_t, rf_v3_dist(rf_animation_translation(r.out, f, j),
                                                   rf_animation_translation(c.anim, f, j)));
        }
    print_message("%s onto itself: largest difference %.3g (quaternion components), %.3g (root "
                  "translation, %.3g of the leg)\n",
                  rel, worst_q, worst_t, worst_t / r.rep.frames);
    assert_true(worst_q < 1e-5);
    rf_rt_info info;
    rf_retarget_info(r.rt, &info);
    assert_true(worst_t < 1e-5 * info.leg_target);
    result_free(&r);
    rf_mapping_free(m);
    clip_free(&c);
}

static void identity_cmu(void **state)
{
    (void)state;
    identity_on("bvh/cmu_01_01.bvh");
}

static void identity_fox(void **state)
{
    (void)state;
    identity_on("models/Fox.glb");
}

/* ---- a degenerate rest as the source ---- */

static void bandai_onto_cmu(void **state)
{
    (void)state;
    clip src = load("bvh/bandai_walk.bvh"), tgt = load("bvh/cmu_01_01.bvh");
    /* The Bandai map read the other way round: CMU joints from Bandai joints. */
    rf_mapping *fwd = map_named("bandai", &src, &tgt);
    rf_mapping *m = rf_mapping_new(tgt.skel->joint_count, 1);
    for (uint32_t j = 0; j < src.skel->joint_count; j++)
        if (fwd->entries[j].input_count)
            add_input(m, (int32_t)fwd->entries[j].inputs[0].joint, 0, (int32_t)j, 0);
    rf_mapping_free(fwd);
    rf_retarget_options o = defaults();
    result r = retarget(&src, &tgt, m, &o);
    rf_rt_info info;
    rf_retarget_info(r.rt, &info);
    print_message("Bandai walk onto CMU: source rest from frame %d; fidelity %.3f deg mean, p95 "
                  "%.3f over %u bones\n",
                  info.rest_frame, r.rep.fidelity_mean, r.rep.fidelity_p95, r.rep.fidelity_bones);
    assert_int_equal(info.rest_frame, 0); /* its zero pose is no body */
    assert_true(r.rep.fidelity_mean < 5.0);
    result_free(&r);
    rf_mapping_free(m);
    clip_free(&src), clip_free(&tgt);
}

/* ---- foot skate and the contact pass ---- */

static void contact_pass_on_cmu(void **state)
{
    (void)state;
    clip src = load("bvh/cmu_01_01.bvh"), tgt = load("models/RiggedFigure.glb");
    rf_mapping *m = map_named("RiggedFigure", &tgt, &src);
    rf_retarget_options o = defaults();
    result r = retarget(&src, &tgt, m, &o);
    char err[512];
    const rf_ik_solver_api *api = &rf_ik_twobone_api;
    rf_ik_solver *solver = rf_ik_solver_new(api, api->create(NULL, err, sizeof err), "twobone");
    rf_rt_contact_stats st;
    assert_true(rf_retarget_contacts(r.rt, r.out, solver, &st, err, sizeof err));
    rf_rt_report after;
    assert_true(
        rf_retarget_measure(r.rt, r.out, rf_retarget_start_time(r.rt), &after, err, sizeof err));
    print_message("CMU onto RiggedFigure: foot skate %.4f leg/s without the contact pass, %.4f "
                  "with it (source %.4f) over %u contact frames; %u feet, largest miss %.3g; "
                  "fidelity %.2f -> %.2f deg\n",
                  r.rep.skate_target, after.skate_target, r.rep.skate_source, r.rep.contact_frames,
                  st.effectors, st.max_error, r.rep.fidelity_mean, after.fidelity_mean);
    assert_int_equal(st.effectors, 2);
    assert_true(r.rep.contact_frames > 100);
    assert_true(after.skate_target < 0.5 * r.rep.skate_target);
    assert_true(after.skate_target <= r.rep.skate_source + 0.01);
    rf_ik_solver_free(solver);
    result_free(&r);
    rf_mapping_free(m);
    clip_free(&src), clip_free(&tgt);
}

/* ---- a quadruped ---- */

static void cmu_onto_fox(void **state)
{
    (void)state;
    clip src = load("bvh/cmu_01_01.bvh"), tgt = load("models/Fox.glb");
    rf_mapping *m = map_named("Fox", &tgt, &src);
    rf_retarget_options o = defaults();
    o.first_frame = 200, o.last_frame = 1200; /* the walk, not the standing start */
    result r = retarget(&src, &tgt, m, &o);
    rf_rt_info info;
    rf_retarget_info(r.rt, &info);
    print_message("CMU onto the Fox: cycle %.3f s, legs %.4g -> %.4g, %u feet, fidelity %.2f deg "
                  "over %u bones (its level spine and neck differ from the upright source's by "
                  "design), skate %.4f leg/s (source %.4f) over %u contact frames\n",
                  info.cycle, info.leg_source, info.leg_target, info.effectors, r.rep.fidelity_mean,
                  r.rep.fidelity_bones, r.rep.skate_target, r.rep.skate_source,
                  r.rep.contact_frames);
    assert_int_equal(info.effectors, 4);
    assert_int_equal(r.rep.effectors, 4);
    assert_int_equal(r.rep.source_feet, 2);            /* four feet follow the human's two */
    assert_true(info.cycle > 0.5 && info.cycle < 2.0); /* a walking stride */
    /* The spine stays level: a body-plan difference is kept, not aligned away. */
    rf_xform *w = malloc(tgt.skel->joint_count * sizeof *w);
    int32_t hip = rf_skeleton_find(tgt.skel, "b_Hip_01");
    int32_t neck = rf_skeleton_find(tgt.skel, "b_Neck_04");
    for (uint32_t f = 0; f < r.out->frame_count; f += 50) {
        for (uint32_t j = 0; j < tgt.skel->joint_count; j++) {
            rf_xform x = {rf_animation_translation(r.out, f, j),
                          rf_quat_normalize(rf_animation_rotation(r.out, f, j)),
                          tgt.skel->joints[j].rest.s};
            int32_t p = tgt.skel->joints[j].parent;
            w[j] = p < 0 ? x : rf_xform_mul(w[p], x);
        }
        rf_vec3 spine = rf_v3_normalize(rf_v3_sub(w[neck].t, w[hip].t));
        assert_true(fabs(spine.y) < 0.7); /* within about 45 degrees of level */
    }
    free(w);
    result_free(&r);
    rf_mapping_free(m);
    clip_free(&src), clip_free(&tgt);
}

/* The largest turn of target joint `name` off its rest, over the clip, in degrees. */
static double turn_off_rest(const rf_animation *a, const rf_skeleton *s, const char *name)
{
    int32_t j = rf_skeleton_find(s, name);
    assert_true(j >= 0);
    rf_quat rest_inv = rf_quat_conj(s->joints[j].rest.r);
    double worst = 0;
    for (uint32_t f = 0; f < a->frame_count; f++) {
        rf_quat d = rf_quat_mul(rest_inv, rf_quat_normalize(rf_animation_rotation(a, f, j)));
        worst = fmax(worst, 2 * acos(fmin(1, fabs(d.w))) * 180 / RF_PI);
    }
    return worst;
}

/* The Fox's Walk onto Testwuson: a neck built differently (the Fox's rises, Testwuson's runs
 * forward) takes the Fox's neck turns, not its shape. Aligning the neck joints onto the Fox's rest
 * directions held the last front-spine joint and the neck 59-69 degrees off their rest in every
 * frame, bent opposite ways (a crease behind the head, read back in Blender); its own clip turns
 * them 0-7 degrees, the Fox's Walk its own 0-17. */
static void fox_walk_onto_testwuson(void **state)
{
    (void)state;
    clip src = load_clip("models/Fox.glb", "Walk"), tgt = load("models/Testwuson.X");
    rf_mapping *m = map_named("Testwuson-Fox", &tgt, &src);
    rf_retarget_options o = defaults();
    result r = retarget(&src, &tgt, m, &o);
    double spine = turn_off_rest(r.out, tgt.skel, "Spine_Front04");
    double neck = turn_off_rest(r.out, tgt.skel, "Neck");
    print_message("the Fox's Walk onto Testwuson: the neck's joints at most %.1f and %.1f degrees "
                  "off their rest\n",
                  spine, neck);
    assert_true(spine < 30 && neck < 30);
    result_free(&r);
    rf_mapping_free(m);
    clip_free(&src), clip_free(&tgt);
}

/* CMU 01_01 onto Testwuson: its shoulder blades (rest pointing down) are mapped from CMU's
 * clavicles (rest and clip pointing sideways). Aligned onto the clavicles' direction they stood
 * 110-116 degrees off their rest in every frame (read back in Blender), crushing the skin over
 * them; its own clips turn them 0-29. They now take the clavicles' turns off their rest. */
static void cmu_onto_testwuson_blades(void **state)
{
    (void)state;
    clip src = load("bvh/cmu_01_01.bvh"), tgt = load("models/Testwuson.X");
    rf_mapping *m = map_named("Testwuson-CMU", &tgt, &src);
    rf_retarget_options o = defaults();
    result r = retarget(&src, &tgt, m, &o);
    double left = turn_off_rest(r.out, tgt.skel, "ForeLeg_L_01");
    double right = turn_off_rest(r.out, tgt.skel, "ForeLeg_R_01");
    print_message("CMU onto Testwuson: the shoulder blades at most %.1f and %.1f degrees off "
                  "their rest\n",
                  left, right);
    assert_true(left < 45 && right < 45);
    result_free(&r);
    rf_mapping_free(m);
    clip_free(&src), clip_free(&tgt);
}

/* vrm_sample is a node tree: no skin, its only meshes (a few quads) hung on 2 of its 23 nodes.
 * The mesh measure takes its joints and bone tips with those quads, for the floor only: standing
 * at rest and moved up by 0.1 in every frame, it stands 0.1 over its floor, in fractions of a
 * height that spans at least its joints (the quads alone span less than half of it). */
static void node_tree_floor(void **state)
{
    (void)state;
    char path[4096], err[1024] = "";
    const char *d = data_dir();
    snprintf(path, sizeof path, "%s/models/vrm_sample.glb", d ? d : "");
    if (!d || access(path, R_OK) != 0) {
        print_message("models/vrm_sample.glb not found (RF_DATA_DIR, ../shared/data): skipped\n");
        skip();
    }
    rf_ai_result ai;
    rf_ai_options opts = {0};
    assert_true(rf_ai_import(path, &opts, &ai, NULL, NULL, err, sizeof err));
    assert_non_null(ai.mesh);
    rf_skeleton *s = ai.skeleton;
    uint32_t n = s->joint_count;
    clip c = {s, fx_rest_clip(s, 4, 30)};
    rf_mapping *m = rf_mapping_new(n, 1);
    for (uint32_t j = 0; j < n; j++)
        add_input(m, (int32_t)j, 0, (int32_t)j, 0);
    rf_rt_source src = {c.skel, c.anim};
    rf_retarget_options o = defaults();
    rf_retarget *rt = rf_retarget_new(&src, 1, s, m, &o, err, sizeof err);
    assert_non_null(rt);
    rf_animation *up = rf_animation_copy(c.anim);
    rf_vec3 lift = rf_v3_scale(rf_v3_normalize(s->up), 0.1);
    double lo = INFINITY, hi = -INFINITY;
    rf_xform *w = malloc(n * sizeof *w);
    fx_world(s, c.anim, 0, w);
    for (uint32_t j = 0; j < n; j++) {
        double h = rf_v3_dot(rf_v3_normalize(s->up), w[j].t);
        lo = fmin(lo, h), hi = fmax(hi, h);
        if (s->joints[j].parent < 0)
            for (uint32_t f = 0; f < up->frame_count; f++)
                rf_animation_set_translation(up, f, j,
                                             rf_v3_add(rf_animation_translation(up, f, j), lift));
    }
    rf_rt_mesh_report rep;
    assert_true(rf_retarget_mesh_measure(rt, ai.mesh, up, 0, 0, &rep, err, sizeof err));
    print_message("vrm_sample moved up 0.1: floor median %.4f of its height %.4f (joints span "
                  "%.4f), seams %u, edges %u\n",
                  rep.floor_median, rep.height, hi - lo, rep.seams, rep.edges);
    assert_true(rep.rigid && rep.seams == 0 && rep.edges == 0);
    assert_true(rep.height >= hi - lo - 1e-9);
    assert_true(fabs(rep.floor_median * rep.height - 0.1) < 1e-5);
    assert_true(fabs(rep.floor_p95 * rep.height - 0.1) < 1e-5);
    free(w);
    rf_animation_free(up);
    rf_retarget_free(rt);
    rf_mapping_free(m);
    ai.skeleton = NULL;
    rf_ai_result_clear(&ai);
    clip_free(&c);
}

/* ---- a turned target ---- */

/* Turns skeleton s by `degrees` about its declared up (+y when it declares none) through the
 * origin, its declared up and forward with it, as the transform node turns a model: its roots'
 * rests turned, every other joint's rest kept relative to its parent. */
static void turn_skeleton(rf_skeleton *s, double degrees)
{
    rf_vec3 axis = rf_v3_len(s->up) > 0 ? rf_v3_normalize(s->up) : rf_v3(0, 1, 0);
    rf_quat q = rf_quat_from_axis_angle(axis, degrees * RF_PI / 180.0);
    for (uint32_t j = 0; j < s->joint_count; j++)
        if (s->joints[j].parent < 0) {
            s->joints[j].rest.r = rf_quat_normalize(rf_quat_mul(q, s->joints[j].rest.r));
            s->joints[j].rest.t = rf_quat_rotate(q, s->joints[j].rest.t);
        }
    s->up = rf_quat_rotate(q, s->up);
    s->forward = rf_quat_rotate(q, s->forward);
}

/* The largest distance, in leg lengths, between the world joint positions of clip b on skeleton
 * sb and those of clip a on sa turned by `degrees` about axis, over every joint of every frame. */
static double turned_apart(const rf_skeleton *sa, const rf_animation *a, const rf_skeleton *sb,
                           const rf_animation *b, rf_vec3 axis, double degrees, double leg)
{
    uint32_t n = sa->joint_count;
    rf_quat q = rf_quat_from_axis_angle(axis, degrees * RF_PI / 180.0);
    rf_xform *wa = malloc(n * sizeof *wa), *wb = malloc(n * sizeof *wb);
    assert_true(wa && wb && a->frame_count == b->frame_count);
    double worst = 0;
    for (uint32_t f = 0; f < a->frame_count; f++) {
        fx_world(sa, a, f, wa);
        fx_world(sb, b, f, wb);
        for (uint32_t j = 0; j < n; j++)
            worst = fmax(worst, rf_v3_dist(rf_quat_rotate(q, wa[j].t), wb[j].t) / leg);
    }
    free(wa), free(wb);
    return worst;
}

/* CMU 01_01 onto `rel` (mapping maps/MAP.txt, frames first..last), the target as read and turned
 * by 30 and 137 degrees about its up with its axes (as the transform node turns it), feet
 * pinned by the two-bone solver: the turned runs are the unturned run turned, every joint
 * within 1e-4 leg lengths over every frame (float rounding of positions a few hundred legs from
 * the origin), and the measures the same. Turned onto the source's facing, as the retargeter did
 * before it read the source in the target's frame, a target turned 30 degrees played unturned
 * while an unmapped root above its body (the Fox's axis node) kept its turned rest: its joints
 * stood up to 3.21 (greenman) and 2.45 (the Fox) legs from the unturned run turned. */
static void turned_alike(const char *rel, const char *map, int32_t first, int32_t last)
{
    clip src = load("bvh/cmu_01_01.bvh"), tgt = load(rel);
    rf_mapping *m = map_named(map, &tgt, &src);
    rf_retarget_options o = defaults();
    o.first_frame = (uint32_t)first, o.last_frame = last;
    char err[512];
    const rf_ik_solver_api *api = &rf_ik_twobone_api;
    rf_ik_solver *solver = rf_ik_solver_new(api, api->create(NULL, err, sizeof err), "twobone");
    result base = retarget(&src, &tgt, m, &o);
    rf_rt_contact_stats st;
    assert_true(rf_retarget_contacts(base.rt, base.out, solver, &st, err, sizeof err));
    assert_true(rf_retarget_measure(base.rt, base.out, rf_retarget_start_time(base.rt), &base.rep,
                                    err, sizeof err));
    rf_rt_info info;
    rf_retarget_info(base.rt, &info);
    rf_vec3 axis = rf_v3_len(tgt.skel->up) > 0 ? rf_v3_normalize(tgt.skel->up) : rf_v3(0, 1, 0);
    const double turns[] = {30, 137};
    for (size_t i = 0; i < sizeof turns / sizeof *turns; i++) {
        clip turned = {rf_skeleton_copy(tgt.skel), NULL};
        assert_non_null(turned.skel);
        turn_skeleton(turned.skel, turns[i]);
        result r = retarget(&src, &turned, m, &o);
        assert_true(rf_retarget_contacts(r.rt, r.out, solver, &st, err, sizeof err));
        assert_true(rf_retarget_measure(r.rt, r.out, rf_retarget_start_time(r.rt), &r.rep, err,
                                        sizeof err));
        double apart =
            turned_apart(tgt.skel, base.out, turned.skel, r.out, axis, turns[i], info.leg_target);
        print_message("CMU onto %s turned %g degrees: joints %.3g leg from the unturned run "
                      "turned; fidelity %.4f (%.4f), skate %.4f (%.4f) leg/s, ground %.4f (%.4f) "
                      "leg\n",
                      rel, turns[i], apart, r.rep.fidelity_mean, base.rep.fidelity_mean,
                      r.rep.skate_target, base.rep.skate_target, r.rep.ground_error,
                      base.rep.ground_error);
        assert_true(apart < 1e-4);
        assert_true(fabs(r.rep.fidelity_mean - base.rep.fidelity_mean) < 1e-3);
        assert_true(fabs(r.rep.skate_target - base.rep.skate_target) < 1e-4);
        assert_true(fabs(r.rep.ground_error - base.rep.ground_error) < 1e-4);
        result_free(&r);
        clip_free(&turned);
    }
    rf_ik_solver_free(solver);
    result_free(&base);
    rf_mapping_free(m);
    clip_free(&src), clip_free(&tgt);
}

static void turned_greenman(void **state)
{
    (void)state;
    turned_alike("models/greenman.glb", "greenman", 0, -1);
}

static void turned_fox(void **state)
{
    (void)state;
    turned_alike("models/Fox.glb", "Fox", 200, 1200);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(onto_boxing),
        cmocka_unit_test(onto_figure),
        cmocka_unit_test(onto_greenman),
        cmocka_unit_test(onto_bcn),
        cmocka_unit_test(onto_bandai),
        cmocka_unit_test(identity_cmu),
        cmocka_unit_test(identity_fox),
        cmocka_unit_test(bandai_onto_cmu),
        cmocka_unit_test(contact_pass_on_cmu),
        cmocka_unit_test(cmu_onto_fox),
        cmocka_unit_test(fox_walk_onto_testwuson),
        cmocka_unit_test(cmu_onto_testwuson_blades),
        cmocka_unit_test(node_tree_floor),
        cmocka_unit_test(turned_greenman),
        cmocka_unit_test(turned_fox),
    };
    return cmocka_run_group_tests_name("retarget on shared data", tests, NULL, NULL);
}
