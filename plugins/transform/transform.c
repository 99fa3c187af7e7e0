/* The `transform` node: a skeleton and the mesh skinned to it scaled, turned and moved together,
 * as one rigid motion with a uniform scale, x' = R (s x) + offset. A rigger is meant to rig a
 * mesh of any facing, scale and position alike; `rigflow rig-bench --turn/--scale/--offset`
 * puts this node after both imports (the artist's rig and the bare mesh), so the rig it measures
 * against moves with the mesh. The skeleton's declared up and forward turn with it, as they would
 * in a file saved turned (or, with turn_axes false, stay as declared: a format whose axes are
 * fixed). doc/autorig.md, "rig-bench".
 *
 * Joints keep their rotations relative to their parents: a root's rest (and bind) takes the turn
 * and the offset, every joint's local translation and end site the scale, so no scale enters a
 * joint's frame. A mesh's inverse binds follow: IB' = S IB T^-1 (T the motion, S the scale in
 * the joint's frame), so each vertex keeps its place in its joints' frames up to the scale. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <rigflow/model-copy.h>
#include <rigflow/rigflow.h>

typedef struct rf_tf {
    double s;   /* uniform scale, > 0 */
    rf_quat r;  /* the turn */
    rf_vec3 t;  /* the offset, added last */
    rf_mat4 m;  /* the whole motion */
    rf_mat4 mi; /* its inverse */
} rf_tf;

/* "x,y,z" of three finite numbers into v; false otherwise. */
static bool rf_tf_vec(const char *text, rf_vec3 *v)
{
    double c[3];
    char *end = NULL;
    const char *s = text;
    for (int a = 0; a < 3; a++) {
        c[a] = strtod(s, &end);
        if (end == s || !isfinite(c[a]))
            return false;
        s = end;
        if (a < 2 && *s++ != ',')
            return false;
    }
    if (*s)
        return false;
    *v = rf_v3(c[0], c[1], c[2]);
    return true;
}

/* The axis to turn about: the skeleton's declared up ("up"; +y when it declares none) or x,y,z;
 * false with why for anything else or a zero axis. */
static bool rf_tf_axis(const char *text, const rf_skeleton *s, rf_vec3 *axis, char *why, size_t n)
{
    if (!strcmp(text, "up")) {
        *axis = s && rf_v3_len(s->up) > 0 ? rf_v3_normalize(s->up) : rf_v3(0, 1, 0);
        return true;
    }
    if (!rf_tf_vec(text, axis) || !(rf_v3_len(*axis) > 0)) {
        snprintf(why, n, "axis: expected up or three numbers x,y,z not all zero");
        return false;
    }
    *axis = rf_v3_normalize(*axis);
    return true;
}

static void rf_tf_make(rf_tf *f, double scale, double degrees, rf_vec3 axis, rf_vec3 offset)
{
    f->s = scale;
    f->r = rf_quat_from_axis_angle(axis, degrees * 3.14159265358979323846 / 180.0);
    f->t = offset;
    rf_xform x = {offset, f->r, rf_v3(scale, scale, scale)};
    f->m = rf_xform_to_mat4(x);
    f->mi = rf_xform_to_mat4(rf_xform_invert(x));
}

static void rf_tf_skeleton(const rf_tf *f, rf_skeleton *s, bool turn_axes)
{
    bool has_bind = RF_HAS_FIELD(s, rf_skeleton, bind) && s->bind;
    for (uint32_t j = 0; j < s->joint_count; j++) {
        rf_joint *jt = &s->joints[j];
        jt->end_site = rf_v3_scale(jt->end_site, f->s);
        rf_xform *x[2] = {&jt->rest, has_bind ? &s->bind[j] : NULL};
        for (int k = 0; k < 2; k++) {
            if (!x[k])
                continue;
            x[k]->t = rf_v3_scale(x[k]->t, f->s);
            if (jt->parent < 0) {
                x[k]->t = rf_v3_add(rf_quat_rotate(f->r, x[k]->t), f->t);
                x[k]->r = rf_quat_normalize(rf_quat_mul(f->r, x[k]->r));
            }
        }
    }
    if (turn_axes && rf_v3_len(s->up) > 0)
        s->up = rf_quat_rotate(f->r, s->up);
    if (turn_axes && rf_v3_len(s->forward) > 0)
        s->forward = rf_quat_rotate(f->r, s->forward);
}

static void rf_tf_points(float *p, uint32_t n, uint32_t stride, rf_mat4 m, bool points)
{
    for (uint32_t v = 0; p && v < n; v++) {
        float *q = p + (size_t)v * stride;
        rf_vec3 a = rf_v3(q[0], q[1], q[2]);
        a = points ? rf_mat4_point(m, a) : rf_mat4_dir(m, a);
        q[0] = (float)a.x, q[1] = (float)a.y, q[2] = (float)a.z;
    }
}

static void rf_tf_mesh(const rf_tf *f, rf_mesh *m)
{
    rf_xform turn = {rf_v3(0, 0, 0), f->r, rf_v3(1, 1, 1)};
    rf_mat4 r = rf_xform_to_mat4(turn),
            sr = rf_xform_to_mat4((rf_xform){rf_v3(0, 0, 0), f->r, rf_v3(f->s, f->s, f->s)});
    rf_tf_points(m->positions, m->vertex_count, 3, f->m, true);
    rf_tf_points(m->normals, m->vertex_count, 3, r, false);
    if (RF_HAS_FIELD(m, rf_mesh, tangents))
        rf_tf_points(m->tangents, m->vertex_count, 4, r, false);
    if (RF_HAS_FIELD(m, rf_mesh, morph_targets))
        for (uint32_t i = 0; i < m->morph_target_count; i++) {
            rf_tf_points(m->morph_targets[i]->positions, m->vertex_count, 3, sr, false);
            rf_tf_points(m->morph_targets[i]->normals, m->vertex_count, 3, r, false);
        }
    rf_mat4 scale = rf_mat4_identity();
    scale.m[0] = scale.m[5] = scale.m[10] = f->s;
    for (uint32_t j = 0; m->inverse_bind && j < m->bind_count; j++)
        m->inverse_bind[j] = rf_mat4_mul(scale, rf_mat4_mul(m->inverse_bind[j], f->mi));
}

/* Refuses a malformed axis or offset when the pipeline is set up, before any import runs. */
static bool rf_tf_create(const rf_host *host, rf_node *node, void **self)
{
    rf_vec3 v;
    char why[128];
    *self = NULL;
    if (!rf_tf_axis(host->param_string(node, "axis"), NULL, &v, why, sizeof why)) {
        host->error(node, "%s", why);
        return false;
    }
    if (!rf_tf_vec(host->param_string(node, "offset"), &v)) {
        host->error(node, "offset: expected three numbers x,y,z");
        return false;
    }
    return true;
}

static bool rf_tf_process(void *self, const rf_host *host, rf_node *node)
{
    (void)self;
    const rf_skeleton *s =
        host->input_count(node, "skeleton") ? host->input(node, "skeleton", 0) : NULL;
    const rf_mesh *m = host->input_count(node, "mesh") ? host->input(node, "mesh", 0) : NULL;
    rf_vec3 axis, offset;
    char why[128];
    if (!rf_tf_axis(host->param_string(node, "axis"), s, &axis, why, sizeof why) ||
        !rf_tf_vec(host->param_string(node, "offset"), &offset)) {
        if (rf_tf_axis(host->param_string(node, "axis"), s, &axis, why, sizeof why))
            snprintf(why, sizeof why, "offset: expected three numbers x,y,z");
        host->error(node, "%s", why);
        return false;
    }
    rf_tf f;
    rf_tf_make(&f, host->param_float(node, "scale"), host->param_float(node, "turn"), axis, offset);
    rf_skeleton *so = s ? rf_skeleton_copy(s) : NULL;
    rf_mesh *mo = m ? rf_mesh_copy(m) : NULL;
    if ((s && !so) || (m && !mo)) {
        rf_skeleton_free(so), rf_mesh_free(mo);
        host->error(node, "out of memory");
        return false;
    }
    bool ok = true;
    if (so) {
        rf_tf_skeleton(&f, so, host->param_bool(node, "turn_axes"));
        ok = host->set_output(node, "skeleton", so, rf_skeleton_free);
    }
    if (mo) {
        rf_tf_mesh(&f, mo);
        ok = host->set_output(node, "mesh", mo, rf_mesh_free) && ok;
    }
    if (!ok)
        host->error(node, "the host refused an output");
    return ok;
}

static const rf_port_desc rf_tf_inputs[] = {
    RF_PORT_DESC("skeleton", RF_TYPE_SKELETON, RF_PORT_OPTIONAL,
                 "a skeleton (its declared up names the axis `up`; the up and forward it "
                 "declares turn with it)"),
    RF_PORT_DESC("mesh", RF_TYPE_MESH, RF_PORT_OPTIONAL,
                 "a mesh, skinned to the skeleton or not (its inverse binds follow)"),
};

static const rf_port_desc rf_tf_outputs[] = {
    RF_PORT_DESC("skeleton", RF_TYPE_SKELETON, 0, "the skeleton moved (when one was given)"),
    RF_PORT_DESC("mesh", RF_TYPE_MESH, 0, "the mesh moved (when one was given)"),
};

static const rf_param_desc rf_tf_params[] = {
    RF_PARAM_DESC_FLOAT("turn", 0, -36000, 36000, "degrees to turn about `axis` (right-handed)"),
    RF_PARAM_DESC_STRING("axis", "up",
                         "up (the skeleton's declared up axis, +y when it declares none) or a "
                         "direction x,y,z"),
    RF_PARAM_DESC_FLOAT("scale", 1, 1e-9, 1e9,
                        "uniform scale, applied first (about the model's origin)"),
    RF_PARAM_DESC_STRING("offset", "0,0,0", "x,y,z added last, in the model's units after scaling"),
    RF_PARAM_DESC_BOOL("turn_axes", true,
                       "turn the skeleton's declared up and forward with it; false keeps them as "
                       "declared (a file saved turned whose format always declares the same "
                       "axes: a model lying on its side in a glTF, read as +y up)"),
};

static const rf_node_desc rf_tf_desc = {
    .size = sizeof(rf_node_desc),
    .type = "transform",
    .kind = RF_KIND_FILTER,
    .doc = "Scales, turns and moves a skeleton and its mesh together, their skin kept: x' = "
           "turn(scale x) + offset. For measuring how a rigger or a matcher copes with any "
           "facing, scale and position (rigflow rig-bench --turn, --scale, --offset).",
    RF_NODE_INPUTS(rf_tf_inputs),
    RF_NODE_OUTPUTS(rf_tf_outputs),
    RF_NODE_PARAMS(rf_tf_params),
    .create = rf_tf_create,
    .process = rf_tf_process,
};

static const rf_node_desc *const rf_tf_nodes[] = {&rf_tf_desc};

RF_PLUGIN_DEFINE("org.rigflow.transform", "transform", "1.0",
                 "A rigid motion with a uniform scale for a skeleton and its mesh", rf_tf_nodes);
