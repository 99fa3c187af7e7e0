/* The retarget plugin: node types "retarget" (source clips onto a target skeleton through a
 * mapping, with an optional contact pass through any IK solver) and "retarget.measure" (direction
 * fidelity and foot skate of any target clip). The work is in libretarget. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <rigflow/ik.h>
#include <rigflow/rigflow.h>
#include <rigflow/text.h>

#include "retarget.h"

#define ERR_SIZE 512

/* ---- shared inputs and parameters ---- */

#define RT_SOURCE_PORTS                                                                            \
    RF_PORT_DESC("sources", RF_TYPE_ANIMATION, RF_PORT_MULTIPLE,                                   \
                 "the source clips, one per source (several sources drive one target together)"),  \
        RF_PORT_DESC("source_skeletons", RF_TYPE_SKELETON, RF_PORT_MULTIPLE,                       \
                     "the skeleton of each source clip, in the same order (the mapping's source "  \
                     "indices)"),                                                                  \
        RF_PORT_DESC("target", RF_TYPE_SKELETON, 0, "the skeleton to animate"),                    \
        RF_PORT_DESC("mapping", RF_TYPE_MAPPING, 0,                                                \
                     "what drives each target joint (a matcher's output or a mapping file)")

#define RT_PLAN_PARAMS                                                                             \
    RF_PARAM_DESC_INT("rest_frame", -1, -1, 1e9,                                                   \
                      "source rest pose: -1 the skeleton's, or frame 0 when that pose is "         \
                      "degenerate (every bone on one line, e.g. Maya joint orients); N: frame N "  \
                      "of every source clip"),                                                     \
        RF_PARAM_DESC_ENUM("ground", "auto", "auto|rest|world",                                    \
                           "floors: auto (a rest hanging from the origin stands on the origin's "  \
                           "plane, any other on its lowest point), rest (lowest rest points; the " \
                           "source's from its clip), world (the origin's plane for both)")

/* Reads the inputs shared by both node types. False after host->error. */
static bool rt_gather(const rf_host *host, rf_node *node, rf_rt_source *src, uint32_t max,
                      uint32_t *count, const rf_skeleton **target, const rf_mapping **mapping)
{
    uint32_t na = host->input_count(node, "sources");
    uint32_t ns = host->input_count(node, "source_skeletons");
    if (na != ns) {
        host->error(node, "%u source clips but %u source skeletons: give one skeleton per clip", na,
                    ns);
        return false;
    }
    if (na > max) {
        host->error(node, "%u sources: at most %u are supported", na, max);
        return false;
    }
    for (uint32_t k = 0; k < na; k++) {
        src[k].animation = host->input(node, "sources", k);
        src[k].skeleton = host->input(node, "source_skeletons", k);
    }
    *count = na;
    *target = host->input(node, "target", 0);
    *mapping = host->input(node, "mapping", 0);
    if (*mapping && (*mapping)->source_count != na)
        host->log(node, RF_LOG_WARNING, "the mapping was made for %u source(s), %u are connected",
                  (*mapping)->source_count, na);
    return true;
}

static bool rt_ground_parse(const char *text, rf_rt_ground *g)
{
    *g = strcmp(text, "rest") == 0    ? RF_RT_GROUND_REST
         : strcmp(text, "world") == 0 ? RF_RT_GROUND_WORLD
                                      : RF_RT_GROUND_AUTO;
    return strcmp(text, "auto") == 0 || *g != RF_RT_GROUND_AUTO;
}

/* ---- retarget ---- */

static bool rt_create(const rf_host *host, rf_node *node, void **self)
{
    rf_retarget_options *o = calloc(1, sizeof *o);
    if (!o) {
        host->error(node, "out of memory");
        return false;
    }
    rf_retarget_options_default(o);
    o->rest_frame = (int32_t)host->param_int(node, "rest_frame");
    o->first_frame = (uint32_t)host->param_int(node, "first_frame");
    o->last_frame = (int32_t)host->param_int(node, "last_frame");
    o->fps = host->param_float(node, "fps");
    o->in_place = host->param_bool(node, "in_place");
    o->root_scale = host->param_float(node, "root_scale");
    o->cycle = host->param_float(node, "cycle");
    o->contact = host->param_bool(node, "contact");
    o->contact_height = host->param_float(node, "contact_height");
    o->contact_speed = host->param_float(node, "contact_speed");
    o->contact_blend = host->param_float(node, "contact_blend");
    o->hold_floor = host->param_bool(node, "hold_floor");
    if (!rt_ground_parse(host->param_string(node, "ground"), &o->ground)) {
        free(o);
        host->error(node, "ground: expected auto, rest or world");
        return false;
    }
    if (o->last_frame >= 0 && (uint32_t)o->last_frame < o->first_frame) {
        host->error(node, "last_frame %d comes before first_frame %u", o->last_frame,
                    o->first_frame);
        free(o);
        return false;
    }
    *self = o;
    return true;
}

typedef struct rt_progress_ctx {
    const rf_host *host;
    rf_node *node;
} rt_progress_ctx;

static bool rt_on_progress(void *user, double fraction)
{
    rt_progress_ctx *c = user;
    c->host->progress(c->node, fraction);
    return !c->host->cancelled(c->node);
}

/* The contact pass, when asked for and a solver is connected. False after host->error. */
static bool rt_contact_pass(rf_retarget *rt, rf_animation *out, const rf_retarget_options *o,
                            const rf_host *host, rf_node *node)
{
    const rf_ik_solver *solver = host->input_count(node, "ik") ? host->input(node, "ik", 0) : NULL;
    if (!o->contact)
        return true;
    if (!solver) {
        host->log(node, RF_LOG_INFO, "no IK solver on input 'ik': contact pass skipped");
        return true;
    }
    if (!rf_ik_solver_usable(solver)) {
        host->error(node, "the IK solver on input 'ik' is incomplete (its size or functions)");
        return false;
    }
    rf_rt_contact_stats st;
    char err[ERR_SIZE];
    if (!rf_retarget_contacts(rt, out, solver, &st, err, sizeof err)) {
        host->error(node, "contact pass (%s): %s", solver->api->name, err);
        return false;
    }
    if (!st.effectors)
        host->log(node, RF_LOG_INFO,
                  "contact pass: no foot to pin (no mapped chain ends near the source's floor "
                  "with two bones above it): feet follow the clip unpinned");
    else
        host->log(node, RF_LOG_INFO,
                  "contact pass (%s): %u feet, %u foot-frames pinned, %u solves, largest miss %.3g",
                  solver->api->name, st.effectors, st.contact_frames, st.solves, st.max_error);
    if (st.steps)
        host->log(node, RF_LOG_INFO,
                  "feet driven half a cycle later took %u steps where the body moved on from them",
                  st.steps);
    return true;
}

/* With the target's own clip on 'reference', centerline joints keep within its range. */
static bool rt_limit_turns(rf_retarget *rt, rf_animation *out, const rf_skeleton *target,
                           const rf_host *host, rf_node *node)
{
    const rf_animation *ref =
        host->input_count(node, "reference") ? host->input(node, "reference", 0) : NULL;
    if (!ref)
        return true;
    if (ref->joint_count != target->joint_count) {
        host->log(node, RF_LOG_INFO,
                  "the reference clip has %u joints, the target %u: turns not limited",
                  ref->joint_count, target->joint_count);
        return true;
    }
    int n = rf_retarget_limit_turns(rt, out, ref);
    if (n < 0) {
        host->error(node, "out of memory");
        return false;
    }
    if (n > 0)
        host->log(node, RF_LOG_INFO,
                  "%d spine, neck or tail joints held within the turns of the target's own clip "
                  "(plus %.0f degrees)",
                  n, RF_RT_TURN_SLACK);
    return true;
}

/* The target's skinned mesh when one is connected and can stand for the body (*mesh, else NULL:
 * a mesh that cannot is said in one line, and the clip keeps the skeleton's floor). False only
 * when memory ran out. */
static bool rt_usable_mesh(const rf_retarget *rt, const rf_animation *out, const rf_host *host,
                           rf_node *node, const rf_mesh **mesh)
{
    char err[ERR_SIZE];
    *mesh = host->input_count(node, "mesh") ? host->input(node, "mesh", 0) : NULL;
    if (!*mesh)
        return true;
    int usable = rf_retarget_mesh_usable(rt, *mesh, out, NULL, err, sizeof err);
    if (usable < 0) {
        host->error(node, "%s", err);
        return false;
    }
    if (!usable) {
        host->log(node, RF_LOG_INFO, "floor from the skeleton only: %s", err);
        *mesh = NULL;
    }
    return true;
}

/* With the target's usable mesh, the clip stands on the mesh's floor. The mesh passes fail only
 * for memory once the mesh was found usable, and then fail the node: a clip left half-placed on
 * its floor is no result. */
static bool rt_mesh_floor(rf_retarget *rt, rf_animation *out, const rf_mesh *mesh,
                          const rf_host *host, rf_node *node)
{
    char err[ERR_SIZE];
    double shift;
    if (!mesh)
        return true;
    if (!rf_retarget_mesh_floor(rt, out, mesh, &shift, err, sizeof err)) {
        host->error(node, "on the mesh's floor: %s", err);
        return false;
    }
    host->log(node, RF_LOG_INFO, "on the mesh's floor: root moved %.4g along up", shift);
    return true;
}

/* Where the mesh stands higher over its floor than the source over its own (its jumps above
 * all), the clip is lowered, and on rigid legs raised where it stands lower
 * (rf_retarget_mesh_hold), each said in one line. */
static bool rt_mesh_hold(rf_retarget *rt, rf_animation *out, const rf_mesh *mesh,
                         const rf_retarget_options *o, const rf_host *host, rf_node *node)
{
    char err[ERR_SIZE];
    uint32_t lowered, raised;
    double deepest;
    if (!mesh || !o->hold_floor)
        return true;
    if (!rf_retarget_mesh_hold(rt, out, mesh, &lowered, &deepest, &raised, err, sizeof err)) {
        host->error(node, "holding the floor: %s", err);
        return false;
    }
    if (lowered)
        host->log(node, RF_LOG_INFO,
                  "standing higher than the source: the clip lowered in %u of %u frames (at "
                  "most %.4g)",
                  lowered, out->frame_count, deepest);
    if (raised)
        host->log(node, RF_LOG_INFO,
                  "standing lower than the source on legs of one bone each, which the contact "
                  "pass cannot bend: the clip raised in %u of %u frames",
                  raised, out->frame_count);
    return true;
}

/* Parts that are not feet kept above the floor, and how often that was needed. */
static bool rt_parts_pass(rf_retarget *rt, rf_animation *out, const rf_host *host, rf_node *node)
{
    rf_rt_parts_stats st;
    if (!rf_retarget_parts_above(rt, out, &st)) {
        host->error(node, "out of memory");
        return false;
    }
    if (st.frames)
        host->log(node, RF_LOG_INFO,
                  "parts that are not feet lifted over the floor in %u of %u frames (%u turns)",
                  st.frames, out->frame_count, st.turns);
    return true;
}

/* What the parts pass could not lift out of the floor in the median frame raises the whole clip,
 * said in one line. */
static bool rt_mesh_clear(rf_retarget *rt, rf_animation *out, const rf_mesh *mesh,
                          const rf_host *host, rf_node *node)
{
    char err[ERR_SIZE];
    double shift = 0;
    if (!mesh)
        return true;
    if (!rf_retarget_mesh_clear(rt, out, mesh, &shift, err, sizeof err)) {
        host->error(node, "clearing the floor: %s", err);
        return false;
    }
    if (shift > 0)
        host->log(node, RF_LOG_INFO,
                  "parts still under the floor in the median frame: the clip raised %.4g along up",
                  shift);
    return true;
}

/* Whether any of the n floats at v is infinite or NaN: its exponent bits all set, which adding
 * one to the exponent carries into the sign bit. Eight at a time with no branch, which the
 * compiler turns into vector operations. */
static bool rt_any_nonfinite(const float *v, size_t n)
{
    uint32_t bad = 0;
    size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        uint32_t bits[8];
        memcpy(bits, v + i, sizeof bits);
        for (int k = 0; k < 8; k++)
            bad |= (bits[k] & 0x7F800000u) + 0x00800000u;
    }
    for (; i < n; i++) {
        uint32_t bits;
        memcpy(&bits, v + i, sizeof bits);
        bad |= (bits & 0x7F800000u) + 0x00800000u;
    }
    return (bad & 0x80000000u) != 0;
}

/* A clip with a non-finite value is refused, naming where (the frame, the joint by index and
 * escaped name), rather than written. */
static bool rt_finite(const rf_animation *a, const rf_skeleton *s, const rf_host *host,
                      rf_node *node)
{
    size_t n = (size_t)a->frame_count * a->joint_count;
    /* A clip is finite but for a bug: looked over in bulk first (7 checks a joint-frame one
     * by one were 6.3 M instructions of the benchmark's run), then searched for the message. */
    if (!rt_any_nonfinite(a->rotations, n * 4) && !rt_any_nonfinite(a->translations, n * 3))
        return true;
    for (size_t i = 0; i < n; i++) {
        const float *q = a->rotations + i * 4, *t = a->translations + i * 3;
        bool ok = isfinite(q[0]) && isfinite(q[1]) && isfinite(q[2]) && isfinite(q[3]) &&
                  isfinite(t[0]) && isfinite(t[1]) && isfinite(t[2]);
        if (ok)
            continue;
        char label[160];
        uint32_t j = (uint32_t)(i % a->joint_count);
        host->error(node,
                    "the retargeted clip has a non-finite value at frame %zu, joint %u '%s': "
                    "not written",
                    i / a->joint_count, j, rf_joint_label(s, j, label, sizeof label));
        return false;
    }
    return true;
}

static bool rt_process(void *self, const rf_host *host, rf_node *node)
{
    const rf_retarget_options *o = self;
    rf_rt_source src[64];
    uint32_t count;
    const rf_skeleton *target;
    const rf_mapping *mapping;
    if (!rt_gather(host, node, src, 64, &count, &target, &mapping))
        return false;
    char err[ERR_SIZE];
    rf_retarget *rt = rf_retarget_new(src, count, target, mapping, o, err, sizeof err);
    if (!rt) {
        host->error(node, "%s", err);
        return false;
    }
    rt_progress_ctx ctx = {host, node};
    rf_animation *out = rf_retarget_clip(rt, rt_on_progress, &ctx, err, sizeof err);
    if (!out) {
        rf_retarget_free(rt);
        host->error(node, "%s", err);
        return false;
    }
    rf_rt_info info;
    rf_retarget_info(rt, &info);
    char rest[48] = "its skeleton's";
    if (info.rest_frame >= 0)
        snprintf(rest, sizeof rest, "frame %d of its clip", info.rest_frame);
    host->log(node, RF_LOG_INFO,
              "%u of %u target joints mapped, %u sharing a chain's rotation; legs %.4g -> %.4g "
              "(root motion x%.4g); source rest: %s",
              info.mapped, target->joint_count, info.shared, info.leg_source, info.leg_target,
              info.root_scale, rest);
    if (info.dropped || info.anchored)
        host->log(node, RF_LOG_INFO,
                  "%u mapping inputs on or from placement, axis-conversion or helper joints "
                  "dropped; %u joints placed from the body joint they belong to",
                  info.dropped, info.anchored);
    if (info.whole && info.whole_first >= 0) {
        char a[128], sa[256];
        rf_text_escape(rf_joint_label(target, (uint32_t)info.whole_first, a, sizeof a), sa,
                       sizeof sa, 0);
        char more[48] = "";
        if (info.whole > 1)
            snprintf(more, sizeof more, " and %u more", info.whole - 1);
        host->log(node, RF_LOG_INFO,
                  "%u limb%s held whole from the root ('%s'%s): reaching further than it "
                  "could hang (a wing), each keeps its joints past the root at their rest turns "
                  "and swings no further than its reach allows",
                  info.whole, info.whole > 1 ? "s" : "", sa, more);
    }
    if (info.top_from >= 0 && info.top_to >= 0) {
        char a[128], b[128], sa[256], sb[256];
        rf_text_escape(rf_joint_label(target, (uint32_t)info.top_from, a, sizeof a), sa, sizeof sa,
                       0);
        rf_text_escape(rf_joint_label(target, (uint32_t)info.top_to, b, sizeof b), sb, sizeof sb,
                       0);
        host->log(node, RF_LOG_INFO,
                  "the inputs of '%s', which only places the body, drive its top joint '%s' "
                  "(mapped to nothing): the whole body moves with them",
                  sa, sb);
    }
    if (!rt_limit_turns(rt, out, target, host, node)) {
        rf_retarget_free(rt), rf_animation_free(out);
        return false;
    }
    const rf_mesh *mesh;
    bool ok =
        rt_usable_mesh(rt, out, host, node, &mesh) && rt_mesh_floor(rt, out, mesh, host, node);
    ok = ok && rt_contact_pass(rt, out, o, host, node);
    ok = ok && rt_mesh_hold(rt, out, mesh, o, host, node);
    ok = ok && rt_parts_pass(rt, out, host, node);
    ok = ok && rt_mesh_clear(rt, out, mesh, host, node);
    ok = ok && rt_finite(out, target, host, node);
    rf_retarget_free(rt);
    if (!ok) {
        rf_animation_free(out);
        return false;
    }
    return host->set_output(node, "animation", out, rf_animation_free);
}

static const rf_port_desc rt_inputs[] = {
    RT_SOURCE_PORTS,
    RF_PORT_DESC(
        "ik", RF_TYPE_IK_SOLVER, RF_PORT_OPTIONAL,
        "an IK solver (any node of kind ik) for the contact pass; without it feet are not pinned"),
    RF_PORT_DESC("mesh", RF_TYPE_MESH, RF_PORT_OPTIONAL,
                 "the target's skinned mesh: the clip is put on its floor (its lowest vertex in "
                 "the median frame on the lowest at rest), not only on the skeleton's"),
    RF_PORT_DESC("reference", RF_TYPE_ANIMATION, RF_PORT_OPTIONAL,
                 "the target's own clip: its spine, neck and tail turn no further off their rest "
                 "than it turns them (plus 5 degrees)"),
};

static const rf_port_desc rt_outputs[] = {
    RF_PORT_DESC("animation", RF_TYPE_ANIMATION, 0,
                 "the target's clip: local rotations of every joint, the root's translation"),
};

static const rf_param_desc rt_params[] = {
    RT_PLAN_PARAMS,
    RF_PARAM_DESC_INT("first_frame", 0, 0, 1e9,
                      "first source frame to retarget (of the first source's clip)"),
    RF_PARAM_DESC_INT("last_frame", -1, -1, 1e9,
                      "last source frame, inclusive; -1 for the clip's last"),
    RF_PARAM_DESC_FLOAT("fps", 0, 0, 1000,
                        "output frame rate (resampled with slerp); 0 keeps the first source's"),
    RF_PARAM_DESC_BOOL(
        "in_place", 0,
        "no horizontal root motion: the target stays where it stands (its height still moves)"),
    RF_PARAM_DESC_FLOAT("root_scale", 0, 0, 1e6,
                        "scale of the root motion; 0 uses the ratio of the legs (hip heights)"),
    RF_PARAM_DESC_FLOAT(
        "cycle", 0, 0, 1e6,
        "seconds of one motion cycle, for mirrored inputs (half a cycle apart); 0 detects it"),
    RF_PARAM_DESC_BOOL(
        "contact", 1,
        "pin the target's feet while the source's touch the ground (needs the ik input)"),
    RF_PARAM_DESC_FLOAT(
        "contact_height", 0.12, 0, 10,
        "a source foot is in contact when this low over its lowest, in leg lengths"),
    RF_PARAM_DESC_FLOAT("contact_speed", 0.6, 0, 100,
                        "... and this slow horizontally, in leg lengths per second"),
    RF_PARAM_DESC_FLOAT("contact_blend", 0.15, 0, 10,
                        "seconds over which a released foot eases back to the retargeted motion"),
    RF_PARAM_DESC_BOOL("hold_floor", 1,
                       "with the mesh input: the target stands no higher over its floor than the "
                       "source over its own, scaled by the legs (its jumps above all)"),
};

/* A T-pose arm driving an A-pose arm must point the same way. */
static bool rt_selftest(const rf_host *host, char *err, size_t err_size);

static const rf_selftest rt_selftest_ext = {sizeof(rf_selftest), rt_selftest};

static const void *rt_extension(const char *id)
{
    return strcmp(id, RF_SELFTEST_EXTENSION) == 0 ? &rt_selftest_ext : NULL;
}

static const rf_node_desc rt_node = {
    .size = sizeof(rf_node_desc),
    .type = "retarget",
    .kind = RF_KIND_RETARGETER,
    .doc = "Moves the source clips onto the target skeleton through the mapping: world-space "
           "rotations relative to each rest pose, with the rests aligned so the target points "
           "its bones where the source points its (T-pose onto A-pose, degenerate rests), "
           "unmapped joints between mapped ones sharing the rotation, root motion scaled by the "
           "legs and kept on the ground, the mapping's weights, delays, reverse and mirror; "
           "with an IK solver on 'ik', feet are pinned while the source's touch the ground. See "
           "doc/retargeting.md.",
    RF_NODE_INPUTS(rt_inputs),
    RF_NODE_OUTPUTS(rt_outputs),
    RF_NODE_PARAMS(rt_params),
    .create = rt_create,
    .process = rt_process,
    .destroy = free,
    .get_extension = rt_extension,
};

/* ---- retarget.measure ---- */

/* What the mesh measures found, for this clip and the character's own clip (the reference). */
typedef struct rt_mesh_figures {
    bool have, have_ref;
    rf_rt_mesh_report clip, ref;
} rt_mesh_figures;

static bool rt_write_report(const rf_host *host, rf_node *node, const rf_rt_report *r,
                            const rt_mesh_figures *m, const rf_skeleton *s)
{
    const char *path = host->param_string(node, "path");
    if (!*path)
        return true;
    FILE *f = fopen(path, "w");
    if (!f) {
        host->error(node, "cannot write %s", host->param_output_target(node, "path"));
        return false;
    }
    bool written =
        rf_rt_report_write(f, r, m->have ? &m->clip : NULL, m->have_ref ? &m->ref : NULL, s);
    if (fclose(f) != 0 || !written) {
        host->error(node, "cannot write %s", host->param_output_target(node, "path"));
        return false;
    }
    return true;
}

/* One line of mesh figures: this clip's, and beside each the reference clip's. */
static void rt_mesh_line(FILE *out, const char *label, const rt_mesh_figures *m,
                         const rf_skeleton *s)
{
    const rf_rt_mesh_report *c = &m->clip, *r = m->have_ref ? &m->ref : NULL;
    if (c->rigid) {
        fprintf(out,
                "%s: skeleton and node meshes (%u frames, %% of height; no skin: joints, bone tips "
                "and the meshes hung rigidly on nodes): floor median %+.1f p95 %.1f (floating "
                "%.0f%%, sinking %.0f%% of frames); parts under the floor %.0f%% of frames, %.1f "
                "deep; torn limbs and stretch do not apply (a rigid part neither tears nor "
                "stretches)\n",
                label, c->frames, rf_text_shown_zero(100 * c->floor_median, 1), 100 * c->floor_p95,
                100 * c->floating, 100 * c->sinking, 100 * c->parts_below, 100 * c->parts_depth);
        return;
    }
    fprintf(out, "%s: mesh (%u frames, %% of height%s): torn p99 %.2f%s", label, c->frames,
            r ? ", own clip in brackets" : "", 100 * c->seam_p99, r ? "" : "");
    if (r)
        fprintf(out, " [%.2f]", 100 * r->seam_p99);
    fprintf(out, "; floor median %+.1f p95 %.1f", rf_text_shown_zero(100 * c->floor_median, 1),
            100 * c->floor_p95);
    if (r)
        fprintf(out, " [%+.1f, %.1f]", rf_text_shown_zero(100 * r->floor_median, 1),
                100 * r->floor_p95);
    fprintf(out,
            " (floating %.0f%%, sinking %.0f%% of frames); parts under the floor %.0f%% of "
            "frames, %.1f deep",
            100 * c->floating, 100 * c->sinking, 100 * c->parts_below, 100 * c->parts_depth);
    if (r)
        fprintf(out, " [%.0f%%]", 100 * r->parts_below);
    fprintf(out, "; stretch p99 %.1f", 100 * c->stretch_p99);
    if (r)
        fprintf(out, " [%.1f]", 100 * r->stretch_p99);
    if (c->parts) {
        char name[128];
        fprintf(out, "; worst part %.1f", 100 * c->part_stretch_p99);
        if (r && r->parts)
            fprintf(out, " [%.1f]", 100 * r->part_stretch_p99);
        fprintf(out, " (joint '%s', %u edges, of %u parts)",
                rf_joint_label(s, c->part_joint, name, sizeof name), c->part_edges, c->parts);
    }
    if (c->seam_parts) {
        char a[128], b[128];
        fprintf(out, "; worst seam %.2f", 100 * c->seam_part_p99);
        if (r && r->seam_parts)
            fprintf(out, " [%.2f]", 100 * r->seam_part_p99);
        fprintf(out, " (joints '%s' and '%s', %u of the %u seams)",
                rf_joint_label(s, c->seam_joints[0], a, sizeof a),
                rf_joint_label(s, c->seam_joints[1], b, sizeof b), c->seam_part_seams, c->seams);
    }
    if (c->volume_parts) {
        char name[128];
        fprintf(out, "; worst solid's volume off %.1f%%", 100 * c->volume_p95);
        if (r && r->volume_parts)
            fprintf(out, " [%.1f%%]", 100 * r->volume_p95);
        fprintf(out, " (joint '%s', of %u solid parts)",
                rf_joint_label(s, c->volume_joint, name, sizeof name), c->volume_parts);
    }
    fprintf(out, "\n");
}

/* The mesh measures, when a skinned mesh is connected: a mesh that cannot be measured is said
 * in one line and does not fail the node; memory running out does (a report without the mesh's
 * figures would read as a mesh that could not be measured). */
static bool rt_measure_mesh(const rf_host *host, rf_node *node, rf_retarget *rt, double start,
                            const rf_skeleton *target, rt_mesh_figures *m)
{
    const rf_mesh *mesh = host->input_count(node, "mesh") ? host->input(node, "mesh", 0) : NULL;
    const rf_animation *anim = host->input(node, "animation", 0);
    if (!mesh)
        return true;
    const rf_animation *ref =
        host->input_count(node, "reference") ? host->input(node, "reference", 0) : NULL;
    uint32_t frames = (uint32_t)host->param_int(node, "mesh_frames");
    char err[ERR_SIZE];
    const char *label = host->param_string(node, "label");
    label = *label ? label : host->node_id(node);
    bool rigid;
    int usable = rf_retarget_mesh_usable(rt, mesh, anim, &rigid, err, sizeof err);
    if (usable <= 0) {
        if (usable < 0)
            host->error(node, "%s", err);
        else
            host->log(node, RF_LOG_INFO, "no mesh measures: %s", err);
        return usable == 0;
    }
    m->have = rf_retarget_mesh_measure(rt, mesh, anim, start, frames, &m->clip, err, sizeof err);
    if (!m->have) {
        host->error(node, "measuring the mesh: %s", err);
        return false;
    }
    m->have_ref =
        ref && ref->frame_count > 1 && !m->clip.rigid &&
        rf_rt_mesh_measure(target, mesh, ref, rf_v3(0, 0, 0), frames, &m->ref, err, sizeof err);
    rt_mesh_line(rf_node_out(host, node), label, m, target);
    return true;
}

/* The time in the sources that the measured clip's frame 0 plays: first_frame when given, else
 * where the clip says it starts. A clip the retarget cut from frame 150 measured against the
 * sources' start read the dragon's jump over the source standing still as floating (29% of
 * frames, p95 11.2% of its height; against its own window 4%, 1.6%). */
static double rt_measure_start(const rf_host *host, rf_node *node, const rf_rt_source *src,
                               const rf_animation *anim)
{
    int64_t first = host->param_int(node, "first_frame");
    if (first >= 0)
        return src[0].animation && src[0].animation->fps > 0 ? first / src[0].animation->fps : 0;
    return anim && RF_HAS_FIELD(anim, rf_animation, source_start) ? anim->source_start : 0;
}

static bool rt_measure_process(void *self, const rf_host *host, rf_node *node)
{
    (void)self;
    rf_rt_source src[64];
    uint32_t count;
    const rf_skeleton *target;
    const rf_mapping *mapping;
    if (!rt_gather(host, node, src, 64, &count, &target, &mapping))
        return false;
    rf_retarget_options o;
    rf_retarget_options_default(&o);
    o.rest_frame = (int32_t)host->param_int(node, "rest_frame");
    rt_ground_parse(host->param_string(node, "ground"), &o.ground);
    char err[ERR_SIZE];
    rf_retarget *rt = rf_retarget_new(src, count, target, mapping, &o, err, sizeof err);
    rf_rt_report r;
    const rf_animation *anim = host->input(node, "animation", 0);
    rf_measures *series = anim ? rf_measures_new(anim->frame_count, anim->fps) : NULL;
    double start = rt_measure_start(host, node, src, anim);
    bool ok =
        rt && series && rf_retarget_measure_series(rt, anim, start, &r, series, err, sizeof err);
    if (!ok) {
        if (rt && !series)
            snprintf(err, sizeof err, "out of memory");
        rf_retarget_free(rt);
        host->error(node, "%s", err);
        rf_measures_free(series);
        return false;
    }
    if (!host->set_output(node, "measures", series, rf_measures_free)) {
        rf_retarget_free(rt);
        return false;
    }
    const char *label = host->param_string(node, "label");
    FILE *out = rf_node_out(host, node);
    fprintf(out,
            "%s: direction fidelity %.2f deg mean (p95 %.2f, max %.2f) over %u bones x %u frames; "
            "foot skate %.4f leg/s (source %.4f) over %u contact frames; ground error %.3f leg\n",
            *label ? label : host->node_id(node), r.fidelity_mean, r.fidelity_p95, r.fidelity_max,
            r.fidelity_bones, r.frames, r.skate_target, r.skate_source, r.contact_frames,
            r.ground_error);
    rt_mesh_figures mf = {0};
    bool measured = rt_measure_mesh(host, node, rt, start, target, &mf);
    rf_retarget_free(rt);
    fflush(out);
    return measured && rt_write_report(host, node, &r, &mf, target);
}

static const rf_port_desc rt_measure_inputs[] = {
    RT_SOURCE_PORTS,
    RF_PORT_DESC("animation", RF_TYPE_ANIMATION, 0,
                 "the target clip to measure (from retarget, or any other tool)"),
    RF_PORT_DESC(
        "mesh", RF_TYPE_MESH, RF_PORT_OPTIONAL,
        "the target's skinned mesh: adds the measures on the mesh (torn limbs, floor, stretch "
        "over the whole mesh and in its worst part: the vertices one joint carries most; the "
        "volume its closed solid parts keep)"),
    RF_PORT_DESC("reference", RF_TYPE_ANIMATION, RF_PORT_OPTIONAL,
                 "a clip of the target's own, measured on the mesh the same way as the reference"),
};

static const rf_port_desc rt_measure_outputs[] = {
    RF_PORT_DESC("measures", RF_TYPE_MEASURES, 0,
                 "the figures per frame (direction error, contacts, foot skate) for a report"),
};

static const rf_param_desc rt_measure_params[] = {
    RT_PLAN_PARAMS,
    RF_PARAM_DESC_INT("first_frame", -1, -1, 1e9,
                      "the source frame the measured clip starts at (default -1: where the clip "
                      "says it starts, the retarget's first_frame for a clip it made)"),
    RF_PARAM_DESC_INT(
        "mesh_frames", 24, 1, 1e6,
        "frames spread over the clip that the mesh measures skin (they cost a skinning each)"),
    RF_PARAM_DESC_STRING("label", "", "text before the figures (default: the node id)"),
    RF_PARAM_DESC(.name = "path", .type = RF_PARAM_OUTPUT_PATH, .default_string = "",
                  .doc = "also write the figures as JSON to this file (optional; a figure that is "
                         "not finite is null)"),
};

static const rf_node_desc rt_measure_node = {
    .size = sizeof(rf_node_desc),
    .type = "retarget.measure",
    .kind = RF_KIND_REPORT,
    .doc = "Measures a target clip against its sources and prints one line: direction fidelity "
           "(angle between each mapped target bone's world direction and its source bone's, per "
           "frame) and foot skate (horizontal speed of target feet while the source's are in "
           "contact, in leg lengths per second). Same definitions as the tests and benchmarks.",
    RF_NODE_INPUTS(rt_measure_inputs),
    RF_NODE_OUTPUTS(rt_measure_outputs),
    RF_NODE_PARAMS(rt_measure_params),
    .process = rt_measure_process,
    .flags = RF_NODE_CONCURRENT,
};

/* ---- self-test ---- */

/* A chest with two arms drooping by `droop` degrees (bones along local +-X) and a head. */
static rf_skeleton *rt_torso(double droop, double scale)
{
    rf_skeleton *s = rf_skeleton_new(6);
    if (!s)
        return NULL;
    int32_t parent[6] = {-1, 0, 1, 0, 3, 0};
    double x[6] = {0, 1, 1, -1, -1, 0};
    for (uint32_t j = 0; j < 6; j++) {
        s->joints[j].parent = parent[j];
        s->joints[j].rest.t = rf_v3(x[j] * scale, j == 5 ? scale : 0, 0);
    }
    double a = droop * RF_PI / 180;
    s->joints[1].rest.r = rf_quat_from_axis_angle(rf_v3(0, 0, 1), -a);
    s->joints[3].rest.r = rf_quat_from_axis_angle(rf_v3(0, 0, 1), a);
    uint32_t leaf[3] = {2, 4, 5};
    for (int i = 0; i < 3; i++) {
        s->joints[leaf[i]].flags |= RF_JOINT_HAS_END_SITE;
        s->joints[leaf[i]].end_site = leaf[i] == 5 ? rf_v3(0, scale, 0) : s->joints[leaf[i]].rest.t;
    }
    return s;
}

/* The identity mapping of n joints, or NULL. */
static rf_mapping *rt_same_mapping(uint32_t n)
{
    rf_mapping *m = rf_mapping_new(n, 1);
    for (uint32_t j = 0; m && j < n; j++) {
        m->entries[j].inputs = calloc(1, sizeof *m->entries[j].inputs);
        if (!m->entries[j].inputs) {
            rf_mapping_free(m);
            return NULL;
        }
        m->entries[j].input_count = 1;
        m->entries[j].inputs[0] = (rf_map_input){0, j, 1, 0, 0};
    }
    return m;
}

static bool rt_selftest(const rf_host *host, char *err, size_t err_size)
{
    (void)host;
    rf_skeleton *src = rt_torso(0, 1), *tgt = rt_torso(45, 0.8);
    rf_animation *clip = src ? rf_animation_new(6, 2, 10) : NULL;
    rf_mapping *m = rt_same_mapping(6);
    bool ok = src && tgt && clip && m;
    for (uint32_t j = 0; ok && j < 6; j++)
        for (uint32_t f = 0; f < 2; f++)
            rf_animation_set_translation(clip, f, j, src->joints[j].rest.t);
    if (ok)
        rf_animation_set_rotation(clip, 1, 1, rf_quat_from_axis_angle(rf_v3(0, 0, 1), 0.5));
    rf_rt_source s = {src, clip};
    rf_retarget *rt = ok ? rf_retarget_new(&s, 1, tgt, m, NULL, err, err_size) : NULL;
    rf_rt_report r = {0};
    rf_animation *out = rt ? rf_retarget_clip(rt, NULL, NULL, err, err_size) : NULL;
    ok = out && rf_retarget_measure(rt, out, 0, &r, err, err_size);
    if (ok && !(r.fidelity_bones >= 4 && r.fidelity_max < 1e-3)) {
        snprintf(err, err_size, "A-pose arms off by %g degrees over %u bones", r.fidelity_max,
                 r.fidelity_bones);
        ok = false;
    }
    rf_animation_free(out), rf_retarget_free(rt), rf_mapping_free(m), rf_animation_free(clip);
    rf_skeleton_free(src), rf_skeleton_free(tgt);
    return ok;
}

static const rf_node_desc *const rt_nodes[] = {&rt_node, &rt_measure_node};

RF_PLUGIN_EXPORT const rf_plugin_entry rigflow_plugin_entry = {
    .abi = RF_ABI_VERSION_INIT,
    .size = sizeof(rf_plugin_entry),
    .id = "org.rigflow.retarget",
    .name = "Retargeting",
    .version = "0.1.0",
    .description = "Motion retargeting between different skeletons, and its measures",
    .node_count = 2,
    .nodes = rt_nodes,
};
