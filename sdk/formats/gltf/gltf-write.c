/* glTF 2.0 writer: JSON with jansson, one binary buffer of our own. See gltf-write.h and
 * doc/formats/gltf.md.
 *
 * Layout: nodes 0..n-1 are the joints in skeleton order (so skin.joints is the identity map and
 * node indices equal joint indices on re-import), then the mesh node, then a common root when the
 * skeleton has several roots (the validator wants one). Every accessor has its own buffer view,
 * 4-byte aligned. Accessor min/max are computed from the float32 values actually stored, which the
 * validator compares exactly; JSON numbers carry 9 significant digits, enough to round-trip a
 * float32.
 */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <jansson.h>

#include "rigflow/gltf-write.h"

enum {
    RF_GL_UNSIGNED_BYTE = 5121,
    RF_GL_UNSIGNED_SHORT = 5123,
    RF_GL_UNSIGNED_INT = 5125,
    RF_GL_FLOAT = 5126,
    RF_GL_ARRAY_BUFFER = 34962,
    RF_GL_ELEMENT_ARRAY_BUFFER = 34963,
};

typedef struct rf_gw {
    unsigned char *buf;
    size_t len, cap;
    json_t *views, *accessors;
    bool oom;
} rf_gw;

/* ---- buffer, views, accessors ---- */

static size_t rf_gw_append(rf_gw *g, const void *data, size_t bytes)
{
    size_t start = (g->len + 3) & ~(size_t)3;
    if (start + bytes > g->cap) {
        size_t cap = g->cap ? g->cap : 4096;
        while (cap < start + bytes)
            cap *= 2;
        unsigned char *b = realloc(g->buf, cap);
        if (!b) {
            g->oom = true;
            return 0;
        }
        g->buf = b, g->cap = cap;
    }
    memset(g->buf + g->len, 0, start - g->len);
    memcpy(g->buf + start, data, bytes);
    g->len = start + bytes;
    return start;
}

static int rf_gw_view(rf_gw *g, const void *data, size_t bytes, int target)
{
    size_t offset = rf_gw_append(g, data, bytes);
    json_t *v = json_pack("{s:i, s:I, s:I}", "buffer", 0, "byteOffset", (json_int_t)offset,
                          "byteLength", (json_int_t)bytes);
    if (v && target)
        json_object_set_new(v, "target", json_integer(target));
    if (!v || json_array_append_new(g->views, v))
        g->oom = true;
    return (int)json_array_size(g->views) - 1;
}

/* min and max (may be NULL) are stolen. */
static int rf_gw_accessor(rf_gw *g, int view, int ctype, size_t count, const char *type,
                          json_t *min, json_t *max)
{
    json_t *a = json_pack("{s:i, s:i, s:I, s:s}", "bufferView", view, "componentType", ctype,
                          "count", (json_int_t)count, "type", type);
    if (a && min)
        json_object_set_new(a, "min", min), json_object_set_new(a, "max", max);
    else
        json_decref(min), json_decref(max);
    if (!a || json_array_append_new(g->accessors, a))
        g->oom = true;
    return (int)json_array_size(g->accessors) - 1;
}

/* A float accessor of `count` elements of `comps` components, with min/max when asked. */
static int rf_gw_floats(rf_gw *g, const float *v, size_t count, int comps, const char *type,
                        bool bounds, int target)
{
    json_t *min = NULL, *max = NULL;
    if (bounds) {
        min = json_array(), max = json_array();
        for (int c = 0; c < comps; c++) {
            float lo = INFINITY, hi = -INFINITY;
            for (size_t i = 0; i < count; i++) {
                float x = v[i * (size_t)comps + (size_t)c];
                lo = x < lo ? x : lo, hi = x > hi ? x : hi;
            }
            json_array_append_new(min, json_real(count ? lo : 0));
            json_array_append_new(max, json_real(count ? hi : 0));
        }
    }
    int view = rf_gw_view(g, v, count * (size_t)comps * sizeof(float), target);
    return rf_gw_accessor(g, view, RF_GL_FLOAT, count, type, min, max);
}

/* ---- nodes and skin ---- */

static bool rf_gw_is_identity_q(rf_quat q)
{
    return fabs(q.x) < 1e-12 && fabs(q.y) < 1e-12 && fabs(q.z) < 1e-12;
}

static json_t *rf_gw_vec(const double *v, int n)
{
    json_t *a = json_array();
    for (int i = 0; i < n; i++)
        json_array_append_new(a, json_real(v[i]));
    return a;
}

static json_t *rf_gw_joint_node(const rf_skeleton *s, uint32_t j)
{
    const rf_joint *jt = &s->joints[j];
    json_t *n = json_pack("{s:s}", "name", jt->name ? jt->name : "");
    rf_xform x = jt->rest;
    rf_quat q = rf_quat_normalize(x.r);
    double t[3] = {x.t.x, x.t.y, x.t.z}, r[4] = {q.x, q.y, q.z, q.w}, sc[3] = {x.s.x, x.s.y, x.s.z};
    if (t[0] != 0 || t[1] != 0 || t[2] != 0)
        json_object_set_new(n, "translation", rf_gw_vec(t, 3));
    if (!rf_gw_is_identity_q(q))
        json_object_set_new(n, "rotation", rf_gw_vec(r, 4));
    if (sc[0] != 1 || sc[1] != 1 || sc[2] != 1)
        json_object_set_new(n, "scale", rf_gw_vec(sc, 3));
    return n;
}

/* Gives every joint node its "children", in one pass over the parents: a scan of the later
 * joints per joint would be quadratic in the joint count. */
static void rf_gw_link_children(const rf_skeleton *s, json_t *nodes)
{
    for (uint32_t k = 0; k < s->joint_count; k++) {
        int32_t p = s->joints[k].parent;
        if (p < 0 || (uint32_t)p >= k)
            continue;
        json_t *parent = json_array_get(nodes, (size_t)p);
        json_t *children = json_object_get(parent, "children");
        if (!children) {
            children = json_array();
            json_object_set_new(parent, "children", children);
        }
        json_array_append_new(children, json_integer(k));
    }
}

static uint32_t rf_gw_root_count(const rf_skeleton *s)
{
    uint32_t n = 0;
    for (uint32_t j = 0; j < s->joint_count; j++)
        n += s->joints[j].parent < 0;
    return n;
}

/* Inverse bind matrices: the mesh's when it has one per joint, else the inverse of the
 * skeleton's world rest pose. The last row is written exactly (0 0 0 1), as the spec requires. */
static int rf_gw_ibms(rf_gw *g, const rf_skeleton *s, const rf_mesh *m)
{
    uint32_t n = s->joint_count;
    float *f = calloc((size_t)n * 16, sizeof *f);
    rf_xform *world = calloc(n, sizeof *world);
    if (!f || !world) {
        free(f), free(world);
        g->oom = true;
        return -1;
    }
    rf_skeleton_world_rest(s, world);
    for (uint32_t j = 0; j < n; j++) {
        rf_mat4 ib;
        if (m->inverse_bind && m->bind_count == n)
            ib = m->inverse_bind[j];
        else if (!rf_mat4_invert(rf_xform_to_mat4(world[j]), &ib))
            ib = rf_mat4_identity();
        for (int k = 0; k < 16; k++)
            f[j * 16 + (uint32_t)k] = (float)ib.m[k];
        f[j * 16 + 3] = f[j * 16 + 7] = f[j * 16 + 11] = 0.0f, f[j * 16 + 15] = 1.0f;
    }
    int acc = rf_gw_floats(g, f, n, 16, "MAT4", false, 0);
    free(f), free(world);
    return acc;
}

/* ---- mesh ---- */

static int rf_gw_indices(rf_gw *g, const rf_mesh *m)
{
    size_t n = (size_t)m->triangle_count * 3;
    if (m->vertex_count <= 65535) {
        uint16_t *idx = malloc(n * sizeof *idx);
        if (!idx) {
            g->oom = true;
            return -1;
        }
        for (size_t i = 0; i < n; i++)
            idx[i] = (uint16_t)m->triangles[i];
        int view = rf_gw_view(g, idx, n * sizeof *idx, RF_GL_ELEMENT_ARRAY_BUFFER);
        free(idx);
        return rf_gw_accessor(g, view, RF_GL_UNSIGNED_SHORT, n, "SCALAR", NULL, NULL);
    }
    int view = rf_gw_view(g, m->triangles, n * sizeof(uint32_t), RF_GL_ELEMENT_ARRAY_BUFFER);
    return rf_gw_accessor(g, view, RF_GL_UNSIGNED_INT, n, "SCALAR", NULL, NULL);
}

/* Normals only when every one is a usable direction: the validator rejects non-unit normals and
 * a reader computes its own without them. */
static int rf_gw_normals(rf_gw *g, const rf_mesh *m)
{
    if (!m->normals)
        return -1;
    float *nv = malloc((size_t)m->vertex_count * 3 * sizeof *nv);
    if (!nv) {
        g->oom = true;
        return -1;
    }
    for (uint32_t i = 0; i < m->vertex_count; i++) {
        const float *s = m->normals + (size_t)i * 3;
        rf_vec3 n = rf_v3_normalize(rf_v3(s[0], s[1], s[2]));
        if (rf_v3_len2(n) == 0 || !rf_v3_isfinite(n)) {
            free(nv);
            return -1;
        }
        nv[i * 3] = (float)n.x, nv[i * 3 + 1] = (float)n.y, nv[i * 3 + 2] = (float)n.z;
    }
    int acc = rf_gw_floats(g, nv, m->vertex_count, 3, "VEC3", false, RF_GL_ARRAY_BUFFER);
    free(nv);
    return acc;
}

/* JOINTS_0 and WEIGHTS_0: weights renormalised in float32, an unused slot points at joint 0. */
static bool rf_gw_skin_attributes(rf_gw *g, const rf_mesh *m, uint32_t joints, json_t *attrs)
{
    size_t n = (size_t)m->vertex_count * 4;
    uint16_t *js = malloc(n * sizeof *js);
    float *ws = malloc(n * sizeof *ws);
    if (!js || !ws) {
        free(js), free(ws);
        g->oom = true;
        return false;
    }
    for (size_t v = 0; v < m->vertex_count; v++) {
        double sum = 0;
        for (int k = 0; k < 4; k++)
            sum += m->skin_weights[v * 4 + k] > 0 ? m->skin_weights[v * 4 + k] : 0;
        for (int k = 0; k < 4; k++) {
            float w = m->skin_weights[v * 4 + k];
            bool used = w > 0 && sum > 0 && m->skin_joints[v * 4 + k] < joints;
            ws[v * 4 + k] = used ? (float)(w / sum) : 0.0f;
            js[v * 4 + k] = used ? m->skin_joints[v * 4 + k] : 0;
        }
        if (!(sum > 0))
            ws[v * 4] = 1.0f; /* a vertex nothing moves follows the first joint */
    }
    int jview = rf_gw_view(g, js, n * sizeof *js, RF_GL_ARRAY_BUFFER);
    int jacc = rf_gw_accessor(g, jview, RF_GL_UNSIGNED_SHORT, m->vertex_count, "VEC4", NULL, NULL);
    int wacc = rf_gw_floats(g, ws, m->vertex_count, 4, "VEC4", false, RF_GL_ARRAY_BUFFER);
    free(js), free(ws);
    json_object_set_new(attrs, "JOINTS_0", json_integer(jacc));
    json_object_set_new(attrs, "WEIGHTS_0", json_integer(wacc));
    return true;
}

static json_t *rf_gw_mesh(rf_gw *g, const rf_mesh *m, uint32_t joints, bool skinned)
{
    json_t *attrs = json_object();
    int pos = rf_gw_floats(g, m->positions, m->vertex_count, 3, "VEC3", true, RF_GL_ARRAY_BUFFER);
    json_object_set_new(attrs, "POSITION", json_integer(pos));
    int nrm = rf_gw_normals(g, m);
    if (nrm >= 0)
        json_object_set_new(attrs, "NORMAL", json_integer(nrm));
    if (skinned)
        rf_gw_skin_attributes(g, m, joints, attrs);
    json_t *prim = json_pack("{s:o, s:i}", "attributes", attrs, "indices", rf_gw_indices(g, m));
    return json_pack("{s:s, s:[o]}", "name", m->name ? m->name : "mesh", "primitives", prim);
}

/* ---- animation ---- */

static bool rf_gw_rotation_moves(const rf_animation *a, const rf_skeleton *s, uint32_t j,
                                 double eps)
{
    rf_quat rest = rf_quat_normalize(s->joints[j].rest.r);
    for (uint32_t f = 0; f < a->frame_count; f++)
        if (rf_quat_angle(rest, rf_quat_normalize(rf_animation_rotation(a, f, j))) > eps)
            return true;
    return false;
}

static bool rf_gw_translation_moves(const rf_animation *a, const rf_skeleton *s, uint32_t j,
                                    double eps)
{
    for (uint32_t f = 0; f < a->frame_count; f++)
        if (rf_v3_dist(rf_animation_translation(a, f, j), s->joints[j].rest.t) > eps)
            return true;
    return false;
}

static int rf_gw_rotation_output(rf_gw *g, const rf_animation *a, uint32_t j)
{
    float *v = malloc((size_t)a->frame_count * 4 * sizeof *v);
    if (!v) {
        g->oom = true;
        return -1;
    }
    rf_quat prev = rf_quat_identity();
    for (uint32_t f = 0; f < a->frame_count; f++) {
        rf_quat q = rf_quat_normalize(rf_animation_rotation(a, f, j));
        if (f > 0 && rf_quat_dot(q, prev) < 0) /* the short way between frames */
            q = rf_quat_neg(q);
        prev = q;
        v[f * 4] = (float)q.x, v[f * 4 + 1] = (float)q.y, v[f * 4 + 2] = (float)q.z;
        v[f * 4 + 3] = (float)q.w;
    }
    int acc = rf_gw_floats(g, v, a->frame_count, 4, "VEC4", false, 0);
    free(v);
    return acc;
}

static int rf_gw_translation_output(rf_gw *g, const rf_animation *a, uint32_t j)
{
    float *v = malloc((size_t)a->frame_count * 3 * sizeof *v);
    if (!v) {
        g->oom = true;
        return -1;
    }
    for (uint32_t f = 0; f < a->frame_count; f++) {
        rf_vec3 t = rf_animation_translation(a, f, j);
        v[f * 3] = (float)t.x, v[f * 3 + 1] = (float)t.y, v[f * 3 + 2] = (float)t.z;
    }
    int acc = rf_gw_floats(g, v, a->frame_count, 3, "VEC3", false, 0);
    free(v);
    return acc;
}

static void rf_gw_channel(json_t *samplers, json_t *channels, int input, int output, uint32_t node,
                          const char *path)
{
    json_array_append_new(samplers, json_pack("{s:i, s:i, s:s}", "input", input, "output", output,
                                              "interpolation", "LINEAR"));
    json_array_append_new(channels, json_pack("{s:I, s:{s:I, s:s}}", "sampler",
                                              (json_int_t)json_array_size(samplers) - 1, "target",
                                              "node", (json_int_t)node, "path", path));
}

/* The animation, or NULL when no channel moves (glTF forbids an animation without channels). */
static json_t *rf_gw_animation(rf_gw *g, const rf_animation *a, const rf_skeleton *s, double eps)
{
    json_t *samplers = json_array(), *channels = json_array();
    int input = -1;
    for (uint32_t j = 0; j < s->joint_count; j++) {
        bool rot = rf_gw_rotation_moves(a, s, j, eps), tr = rf_gw_translation_moves(a, s, j, eps);
        if ((rot || tr) && input < 0) {
            /* One time accessor for every sampler: the clip has one sampling rate. */
            float *t = malloc((size_t)a->frame_count * sizeof *t);
            if (!t) {
                g->oom = true;
                break;
            }
            for (uint32_t f = 0; f < a->frame_count; f++)
                t[f] = (float)(f / a->fps);
            input = rf_gw_floats(g, t, a->frame_count, 1, "SCALAR", true, 0);
            free(t);
        }
        if (rot)
            rf_gw_channel(samplers, channels, input, rf_gw_rotation_output(g, a, j), j, "rotation");
        if (tr)
            rf_gw_channel(samplers, channels, input, rf_gw_translation_output(g, a, j), j,
                          "translation");
    }
    if (!json_array_size(channels)) {
        json_decref(samplers), json_decref(channels);
        return NULL;
    }
    return json_pack("{s:s, s:o, s:o}", "name", a->name ? a->name : "clip", "samplers", samplers,
                     "channels", channels);
}

/* ---- document ---- */

static json_t *rf_gw_document(rf_gw *g, const rf_skeleton *s, const rf_animation *a,
                              const rf_mesh *m, const rf_gltf_write_opts *o)
{
    json_t *nodes = json_array(), *scene_nodes = json_array();
    json_t *doc = json_pack("{s:{s:s, s:s}, s:i}", "asset", "version", "2.0", "generator",
                            o->generator ? o->generator : "rigflow", "scene", 0);
    for (uint32_t j = 0; j < s->joint_count; j++)
        json_array_append_new(nodes, rf_gw_joint_node(s, j));
    rf_gw_link_children(s, nodes);
    if (rf_gw_root_count(s) > 1) {
        json_t *children = json_array();
        for (uint32_t j = 0; j < s->joint_count; j++)
            if (s->joints[j].parent < 0)
                json_array_append_new(children, json_integer(j));
        json_array_append_new(nodes, json_pack("{s:s, s:o}", "name", "root", "children", children));
        json_array_append_new(scene_nodes, json_integer((json_int_t)json_array_size(nodes) - 1));
    } else if (s->joint_count) {
        json_array_append_new(scene_nodes, json_integer(0));
    }
    if (m) {
        bool skinned = m->skin_joints && m->skin_weights && s->joint_count;
        json_t *mesh_node = json_pack("{s:s, s:i}", "name", m->name ? m->name : "mesh", "mesh", 0);
        json_object_set_new(doc, "meshes",
                            json_pack("[o]", rf_gw_mesh(g, m, s->joint_count, skinned)));
        if (skinned) {
            json_t *joints = json_array();
            for (uint32_t j = 0; j < s->joint_count; j++)
                json_array_append_new(joints, json_integer(j));
            json_t *skin = json_pack("{s:o, s:i}", "joints", joints, "inverseBindMatrices",
                                     rf_gw_ibms(g, s, m));
            if (rf_gw_root_count(s) == 1)
                json_object_set_new(skin, "skeleton", json_integer(0));
            json_object_set_new(doc, "skins", json_pack("[o]", skin));
            json_object_set_new(mesh_node, "skin", json_integer(0));
        }
        json_array_append_new(nodes, mesh_node);
        json_array_append_new(scene_nodes, json_integer((json_int_t)json_array_size(nodes) - 1));
    }
    json_t *anim = a && a->frame_count ? rf_gw_animation(g, a, s, o->epsilon) : NULL;
    if (anim)
        json_object_set_new(doc, "animations", json_pack("[o]", anim));
    json_object_set_new(doc, "nodes", nodes);
    json_object_set_new(doc, "scenes", json_pack("[{s:o}]", "nodes", scene_nodes));
    return doc;
}

static char *rf_gw_base64(const unsigned char *d, size_t n)
{
    static const char tbl[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    char *out = malloc((n + 2) / 3 * 4 + 1), *p = out;
    if (!out)
        return NULL;
    for (size_t i = 0; i < n; i += 3) {
        uint32_t v = (uint32_t)d[i] << 16 | (i + 1 < n ? (uint32_t)d[i + 1] << 8 : 0) |
                     (i + 2 < n ? d[i + 2] : 0);
        *p++ = tbl[v >> 18 & 63], *p++ = tbl[v >> 12 & 63];
        *p++ = i + 1 < n ? tbl[v >> 6 & 63] : '=';
        *p++ = i + 2 < n ? tbl[v & 63] : '=';
    }
    *p = '\0';
    return out;
}

static void rf_gw_u32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)v, p[1] = (unsigned char)(v >> 8), p[2] = (unsigned char)(v >> 16);
    p[3] = (unsigned char)(v >> 24);
}

static bool rf_gw_write_glb(FILE *f, const char *json, const rf_gw *g)
{
    size_t jlen = strlen(json), jpad = (4 - jlen % 4) % 4, blen = (g->len + 3) & ~(size_t)3;
    size_t total = 12 + 8 + jlen + jpad + (g->len ? 8 + blen : 0);
    if (total > UINT32_MAX)
        return false;
    unsigned char h[20];
    rf_gw_u32(h, 0x46546C67u), rf_gw_u32(h + 4, 2), rf_gw_u32(h + 8, (uint32_t)total);
    rf_gw_u32(h + 12, (uint32_t)(jlen + jpad)), rf_gw_u32(h + 16, 0x4E4F534Au);
    static const char spaces[4] = "   ", zeros[4] = {0};
    bool ok = fwrite(h, 1, 20, f) == 20 && fwrite(json, 1, jlen, f) == jlen &&
              fwrite(spaces, 1, jpad, f) == jpad;
    if (ok && g->len) {
        unsigned char b[8];
        rf_gw_u32(b, (uint32_t)blen), rf_gw_u32(b + 4, 0x004E4942u);
        ok = fwrite(b, 1, 8, f) == 8 && fwrite(g->buf, 1, g->len, f) == g->len &&
             fwrite(zeros, 1, blen - g->len, f) == blen - g->len;
    }
    return ok;
}

static bool rf_gw_has_ext(const char *path, const char *ext)
{
    size_t n = strlen(path), e = strlen(ext);
    if (n < e)
        return false;
    for (size_t i = 0; i < e; i++)
        if ((path[n - e + i] | 0x20) != ext[i])
            return false;
    return true;
}

static bool rf_gw_check(const rf_skeleton *s, const rf_animation *a, const rf_mesh *m,
                        const char *name, char *err, size_t err_size)
{
    if (a && a->joint_count != s->joint_count) {
        snprintf(err, err_size, "%s: the animation has %u joints, the skeleton %u", name,
                 a->joint_count, s->joint_count);
        return false;
    }
    if (a && a->frame_count && !(a->fps > 0)) {
        snprintf(err, err_size, "%s: the animation's fps must be > 0 (got %g)", name, a->fps);
        return false;
    }
    for (size_t i = 0; m && i < (size_t)m->triangle_count * 3; i++)
        if (m->triangles[i] >= m->vertex_count) {
            snprintf(err, err_size, "%s: triangle %zu uses vertex %u of %u", name, i / 3,
                     m->triangles[i], m->vertex_count);
            return false;
        }
    return true;
}

static bool rf_gw_emit(const char *path, const char *name, json_t *doc, rf_gw *g, bool binary,
                       char *err, size_t err_size)
{
    json_t *buffer = json_pack("{s:I}", "byteLength", (json_int_t)g->len);
    if (!binary && g->len) {
        char *b64 = rf_gw_base64(g->buf, g->len);
        size_t n = b64 ? strlen(b64) + 64 : 0;
        char *uri = b64 ? malloc(n) : NULL;
        if (uri)
            snprintf(uri, n, "data:application/octet-stream;base64,%s", b64);
        json_object_set_new(buffer, "uri", uri ? json_string(uri) : json_null());
        free(b64), free(uri);
    }
    if (g->len)
        json_object_set_new(doc, "buffers", json_pack("[o]", buffer));
    else
        json_decref(buffer);
    json_object_set_new(doc, "bufferViews", json_incref(g->views));
    json_object_set_new(doc, "accessors", json_incref(g->accessors));
    char *text = json_dumps(doc, JSON_COMPACT | JSON_REAL_PRECISION(9));
    FILE *f = text ? fopen(path, "wb") : NULL;
    bool ok = f && (binary ? rf_gw_write_glb(f, text, g) : fputs(text, f) >= 0);
    int e = ok ? 0 : errno; /* why, before free() can change errno (e.g. ENOSPC, EFBIG) */
    if (f && fclose(f) != 0 && ok)
        ok = false, e = errno;
    if (!ok) {
        snprintf(err, err_size, "%s: cannot write the glTF file: %s", name,
                 !text ? "out of memory"
                 : e   ? strerror(e)
                       : "write error");
        if (f)
            remove(path);
    }
    free(text);
    return ok;
}

bool rf_gltf_write_file(const char *path, const char *name, const rf_skeleton *skeleton,
                        const rf_animation *animation, const rf_mesh *mesh,
                        const rf_gltf_write_opts *opts, char *err, size_t err_size)
{
    rf_gltf_write_opts o = {.binary = rf_gw_has_ext(path, ".glb")};
    if (opts)
        o = *opts;
    if (!(o.epsilon > 0))
        o.epsilon = 1e-6;
    name = name ? name : path;
    if (mesh && (!mesh->vertex_count || !mesh->triangle_count))
        mesh = NULL;
    if (!rf_gw_check(skeleton, animation, mesh, name, err, err_size))
        return false;
    rf_gw g = {.views = json_array(), .accessors = json_array()};
    json_t *doc = rf_gw_document(&g, skeleton, animation, mesh, &o);
    bool ok = doc && !g.oom && rf_gw_emit(path, name, doc, &g, o.binary, err, err_size);
    if (!ok && (!doc || g.oom))
        snprintf(err, err_size, "%s: out of memory while building the glTF document", name);
    json_decref(doc), json_decref(g.views), json_decref(g.accessors);
    free(g.buf);
    return ok;
}
