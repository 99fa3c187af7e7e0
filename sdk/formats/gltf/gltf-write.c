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
#include <inttypes.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <jansson.h>

#include "gltf-axes.h"
#include "rigflow/gltf-write.h"
#include "rigflow/prefault.h"
#include "rigflow/text.h"

enum {
    RF_GL_UNSIGNED_BYTE = 5121,
    RF_GL_UNSIGNED_SHORT = 5123,
    RF_GL_UNSIGNED_INT = 5125,
    RF_GL_FLOAT = 5126,
    RF_GL_ARRAY_BUFFER = 34962,
    RF_GL_ELEMENT_ARRAY_BUFFER = 34963,
};

/* A part of the binary chunk made only as the GLB is written: an animation channel's outputs,
 * streamed to the file from the clip (rf_gw_write_part) instead of built in the buffer first:
 * 3 MB of the benchmark's 3.2 MB chunk, whose pages the buffer took 1.2 ms to map. */
typedef struct rf_gw_part {
    size_t at;    /* bytes of the buffer before it in the chunk */
    size_t bytes; /* its length */
    const rf_animation *anim;
    uint32_t joint;
    bool rotation; /* the rotations, else the translations */
} rf_gw_part;

typedef struct rf_gw {
    unsigned char *buf;
    size_t len, cap; /* len: the chunk's length, the parts included; buf holds len - held */
    bool stream;     /* a GLB: animation outputs become parts */
    size_t held;     /* bytes of the parts */
    rf_gw_part *parts;
    size_t part_count;
    json_t *views, *accessors;
    json_t *images, *samplers, *textures; /* filled by the materials (rf_gw_materials) */
    json_t *texture_of;                   /* "image:sampler" -> texture index (a hash table) */
    int *image_index;                     /* [mesh image] glTF image index, or -1 when left out */
    uint32_t uv_sets;                     /* TEXCOORD_n written */
    uint32_t morphs;                      /* morph targets written */
    const rf_morph_target **morph;        /* [morphs] the mesh's targets written */
    int *morph_view;                      /* [morphs * 2] POSITION and NORMAL views (or -1) */
    bool oom;
} rf_gw;

/* ---- buffer, views, accessors ---- */

/* Room for `bytes` more at the buffer's end, 4-aligned with the padding zeroed: its offset, and
 * in *at where to write them (NULL when out of memory, then g->oom is set). */
static size_t rf_gw_reserve(rf_gw *g, size_t bytes, unsigned char **at)
{
    size_t start = (g->len + 3) & ~(size_t)3, end = start - g->held + bytes; /* in buf */
    *at = NULL;
    if (end > g->cap || !g->buf) { /* a buffer even for no bytes: a part may come first */
        size_t cap = g->cap ? g->cap : 4096;
        while (cap < end)
            cap *= 2;
        unsigned char *b = realloc(g->buf, cap);
        if (!b) {
            g->oom = true;
            return 0;
        }
        rf_prefault(b + g->cap, cap - g->cap); /* the new part: written from here on */
        g->buf = b, g->cap = cap;
    }
    memset(g->buf + g->len - g->held, 0, start - g->len);
    g->len = start + bytes;
    *at = g->buf + start - g->held;
    return start;
}

/* Room for a part of `bytes` (4-aligned, the padding before it in the buffer): its offset in the
 * chunk, or -1 (and g->oom) when out of memory. */
static ptrdiff_t rf_gw_part_add(rf_gw *g, size_t bytes, const rf_animation *a, uint32_t j,
                                bool rotation)
{
    unsigned char *at;
    size_t start = rf_gw_reserve(g, 0, &at);
    rf_gw_part *p = at ? realloc(g->parts, (g->part_count + 1) * sizeof *p) : NULL;
    if (!p) {
        g->oom = true;
        return -1;
    }
    g->parts = p;
    g->parts[g->part_count++] = (rf_gw_part){start - g->held, bytes, a, j, rotation};
    g->len += bytes, g->held += bytes;
    return (ptrdiff_t)start;
}

static size_t rf_gw_append(rf_gw *g, const void *data, size_t bytes)
{
    unsigned char *at;
    size_t offset = rf_gw_reserve(g, bytes, &at);
    if (at)
        memcpy(at, data, bytes);
    return offset;
}

/* A view of the `bytes` at `offset` in the buffer. */
static int rf_gw_view_at(rf_gw *g, size_t offset, size_t bytes, int target)
{
    json_t *v = json_pack("{s:i, s:I, s:I}", "buffer", 0, "byteOffset", (json_int_t)offset,
                          "byteLength", (json_int_t)bytes);
    if (v && target)
        json_object_set_new(v, "target", json_integer(target));
    if (!v || json_array_append_new(g->views, v))
        g->oom = true;
    return (int)json_array_size(g->views) - 1;
}

static int rf_gw_view(rf_gw *g, const void *data, size_t bytes, int target)
{
    return rf_gw_view_at(g, rf_gw_append(g, data, bytes), bytes, target);
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

/* A name from a file as a JSON string, which must be UTF-8: bytes that are not become U+FFFD
 * (a Latin-1 name would otherwise make the string, and the node or clip holding it, vanish). */
static json_t *rf_gw_name(const char *name)
{
    json_t *j = json_string(name ? name : "");
    if (j)
        return j;
    size_t len = strlen(name);
    char *fixed = malloc(len * 3 + 1), *o = fixed;
    if (!fixed)
        return NULL;
    for (const unsigned char *c = (const unsigned char *)name; *c;) {
        size_t n = rf_text_utf8_len(c, NULL);
        memcpy(o, n ? (const char *)c : "\xef\xbf\xbd", n ? n : 3);
        o += n ? n : 3, c += n ? n : 1;
    }
    *o = '\0';
    j = json_string(fixed);
    free(fixed);
    return j;
}

static json_t *rf_gw_joint_node(const rf_skeleton *s, uint32_t j)
{
    const rf_joint *jt = &s->joints[j];
    json_t *n = json_pack("{s:o}", "name", rf_gw_name(jt->name));
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

/* A vertex attribute written once as a buffer view; each primitive reads its part of it through
 * an accessor of its own (byteOffset), so parts share no vertices and readers that copy a
 * primitive's whole accessors (Assimp) do not multiply them. */
typedef struct rf_gw_attr {
    const char *name; /* "POSITION", "NORMAL", ... */
    int view;
    int ctype;        /* componentType */
    size_t bytes;     /* per vertex */
    const char *type; /* "VEC3", ... */
} rf_gw_attr;

#define RF_GW_MAX_ATTRS 8

typedef struct rf_gw_attrs {
    rf_gw_attr a[RF_GW_MAX_ATTRS];
    int n;
} rf_gw_attrs;

static void rf_gw_attr_add(rf_gw *g, rf_gw_attrs *as, const char *name, const void *data,
                           size_t count, int ctype, size_t bytes, const char *type)
{
    if (as->n == RF_GW_MAX_ATTRS)
        return;
    int view = rf_gw_view(g, data, count * bytes, RF_GL_ARRAY_BUFFER);
    json_t *v = json_array_get(g->views, (size_t)view); /* parts' accessors share it */
    if (v)
        json_object_set_new(v, "byteStride", json_integer((json_int_t)bytes));
    as->a[as->n++] = (rf_gw_attr){name, view, ctype, bytes, type};
}

/* The indices of `count` triangles from `first`, relative to vertex `base`. */
static int rf_gw_indices(rf_gw *g, const rf_mesh *m, uint32_t first, uint32_t count, uint32_t base,
                         uint32_t vertices)
{
    size_t n = (size_t)count * 3;
    const uint32_t *tri = m->triangles + (size_t)first * 3;
    bool shorts = vertices <= 65535;
    void *idx = malloc(n * (shorts ? sizeof(uint16_t) : sizeof(uint32_t)));
    if (!idx) {
        g->oom = true;
        return -1;
    }
    for (size_t i = 0; i < n; i++)
        if (shorts)
            ((uint16_t *)idx)[i] = (uint16_t)(tri[i] - base);
        else
            ((uint32_t *)idx)[i] = tri[i] - base;
    int view = rf_gw_view(g, idx, n * (shorts ? 2 : 4), RF_GL_ELEMENT_ARRAY_BUFFER);
    free(idx);
    return rf_gw_accessor(g, view, shorts ? RF_GL_UNSIGNED_SHORT : RF_GL_UNSIGNED_INT, n, "SCALAR",
                          NULL, NULL);
}

/* Normals only when every one is a usable direction: the validator rejects non-unit normals and
 * a reader computes its own without them. */
static void rf_gw_normals(rf_gw *g, const rf_mesh *m, rf_gw_attrs *as)
{
    if (!m->normals)
        return;
    float *nv = malloc((size_t)m->vertex_count * 3 * sizeof *nv);
    if (!nv) {
        g->oom = true;
        return;
    }
    for (uint32_t i = 0; i < m->vertex_count; i++) {
        const float *s = m->normals + (size_t)i * 3;
        rf_vec3 n = rf_v3_normalize(rf_v3(s[0], s[1], s[2]));
        if (rf_v3_len2(n) == 0 || !rf_v3_isfinite(n)) {
            free(nv);
            return;
        }
        nv[i * 3] = (float)n.x, nv[i * 3 + 1] = (float)n.y, nv[i * 3 + 2] = (float)n.z;
    }
    rf_gw_attr_add(g, as, "NORMAL", nv, m->vertex_count, RF_GL_FLOAT, 12, "VEC3");
    free(nv);
}

/* JOINTS_0 and WEIGHTS_0: weights renormalised in float32, an unused slot points at joint 0. */
static void rf_gw_skin_attributes(rf_gw *g, const rf_mesh *m, uint32_t joints, rf_gw_attrs *as)
{
    size_t n = (size_t)m->vertex_count * 4;
    uint16_t *js = malloc(n * sizeof *js);
    float *ws = malloc(n * sizeof *ws);
    if (!js || !ws) {
        free(js), free(ws);
        g->oom = true;
        return;
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
    rf_gw_attr_add(g, as, "JOINTS_0", js, m->vertex_count, RF_GL_UNSIGNED_SHORT, 8, "VEC4");
    rf_gw_attr_add(g, as, "WEIGHTS_0", ws, m->vertex_count, RF_GL_FLOAT, 16, "VEC4");
    free(js), free(ws);
}

/* Tangents only beside written normals, and only when every one is a unit direction with a
 * handedness of +-1 (what the validator demands). */
static void rf_gw_tangents(rf_gw *g, const rf_mesh *m, rf_gw_attrs *as)
{
    float *tv = malloc((size_t)m->vertex_count * 4 * sizeof *tv);
    if (!tv) {
        g->oom = true;
        return;
    }
    for (uint32_t i = 0; i < m->vertex_count; i++) {
        const float *s = m->tangents + (size_t)i * 4;
        rf_vec3 t = rf_v3_normalize(rf_v3(s[0], s[1], s[2]));
        if (rf_v3_len2(t) == 0 || !rf_v3_isfinite(t) || !isfinite(s[3])) {
            free(tv);
            return;
        }
        tv[i * 4] = (float)t.x, tv[i * 4 + 1] = (float)t.y, tv[i * 4 + 2] = (float)t.z;
        tv[i * 4 + 3] = s[3] < 0 ? -1.0f : 1.0f;
    }
    rf_gw_attr_add(g, as, "TANGENT", tv, m->vertex_count, RF_GL_FLOAT, 16, "VEC4");
    free(tv);
}

/* Texture coordinates and vertex colours (clamped to [0, 1], as COLOR_0 requires), finite only. */
static void rf_gw_look_attributes(rf_gw *g, const rf_mesh *m, bool normals, rf_gw_attrs *as)
{
    static const char *const uv_names[RF_MESH_MAX_UV_SETS] = {"TEXCOORD_0", "TEXCOORD_1"};
    if (!RF_HAS_FIELD(m, rf_mesh, images))
        return;
    size_t n = m->vertex_count;
    for (uint32_t k = 0; k < m->uv_set_count && k < RF_MESH_MAX_UV_SETS && m->uvs[k]; k++) {
        bool finite = true;
        for (size_t i = 0; i < n * 2 && finite; i++)
            finite = isfinite(m->uvs[k][i]);
        if (!finite)
            break;
        rf_gw_attr_add(g, as, uv_names[k], m->uvs[k], n, RF_GL_FLOAT, 8, "VEC2");
        g->uv_sets = k + 1;
    }
    if (m->colors) {
        float *c = malloc(n * 4 * sizeof *c);
        if (!c) {
            g->oom = true;
            return;
        }
        for (size_t i = 0; i < n * 4; i++)
            c[i] = m->colors[i] > 0 ? (m->colors[i] < 1 ? m->colors[i] : 1.0f) : 0.0f;
        rf_gw_attr_add(g, as, "COLOR_0", c, n, RF_GL_FLOAT, 16, "VEC4");
        free(c);
    }
    if (normals && m->tangents)
        rf_gw_tangents(g, m, as);
}

/* The accessors of vertices [first, first + count) of every attribute (POSITION with bounds). */
static json_t *rf_gw_part_attributes(rf_gw *g, const rf_mesh *m, const rf_gw_attrs *as,
                                     uint32_t first, uint32_t count)
{
    json_t *attrs = json_object();
    for (int i = 0; i < as->n; i++) {
        const rf_gw_attr *a = &as->a[i];
        json_t *min = NULL, *max = NULL;
        if (strcmp(a->name, "POSITION") == 0) {
            min = json_array(), max = json_array();
            for (int c = 0; c < 3; c++) {
                float lo = INFINITY, hi = -INFINITY;
                for (size_t v = first; v < (size_t)first + count; v++) {
                    float x = m->positions[v * 3 + (size_t)c];
                    lo = x < lo ? x : lo, hi = x > hi ? x : hi;
                }
                json_array_append_new(min, json_real(count ? lo : 0));
                json_array_append_new(max, json_real(count ? hi : 0));
            }
        }
        int acc = rf_gw_accessor(g, a->view, a->ctype, count, a->type, min, max);
        json_t *aj = json_array_get(g->accessors, (size_t)acc);
        if (first && aj)
            json_object_set_new(aj, "byteOffset", json_integer((json_int_t)(first * a->bytes)));
        json_object_set_new(attrs, a->name, json_integer(acc));
    }
    return attrs;
}

static int32_t rf_gw_part_material(const rf_mesh *m, uint32_t p)
{
    if (!RF_HAS_FIELD(m, rf_mesh, images) || !m->part_material)
        return -1;
    int32_t k = m->part_material[p];
    return k >= 0 && (uint32_t)k < m->material_count && m->materials && m->materials[k] ? k : -1;
}

/* Parts usable as primitives: each a vertex range its triangles stay inside. */
static bool rf_gw_parts_usable(const rf_mesh *m)
{
    if (!RF_HAS_FIELD(m, rf_mesh, parts) || !m->parts || !m->part_count)
        return false;
    for (uint32_t p = 0; p < m->part_count; p++) {
        const rf_mesh_part *pt = &m->parts[p];
        if (pt->first_vertex > m->vertex_count ||
            pt->vertex_count > m->vertex_count - pt->first_vertex ||
            pt->first_triangle > m->triangle_count ||
            pt->triangle_count > m->triangle_count - pt->first_triangle)
            return false;
        for (size_t i = (size_t)pt->first_triangle * 3;
             i < ((size_t)pt->first_triangle + pt->triangle_count) * 3; i++)
            if (m->triangles[i] < pt->first_vertex ||
                m->triangles[i] - pt->first_vertex >= pt->vertex_count)
                return false;
    }
    return true;
}

static bool rf_gw_all_finite(const float *v, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite(v[i]))
            return false;
    return true;
}

/* The mesh's morph targets as buffer views (NORMAL displacements only beside written normals);
 * targets holding a non-finite value are left out. */
static void rf_gw_morph_views(rf_gw *g, const rf_mesh *m, bool normals)
{
    if (!RF_HAS_FIELD(m, rf_mesh, morph_targets) || !m->morph_targets || !m->morph_target_count)
        return;
    g->morph = calloc(m->morph_target_count, sizeof *g->morph);
    g->morph_view = calloc((size_t)m->morph_target_count * 2, sizeof *g->morph_view);
    if (!g->morph || !g->morph_view) {
        g->oom = true;
        return;
    }
    size_t n = (size_t)m->vertex_count * 3;
    for (uint32_t i = 0; i < m->morph_target_count; i++) {
        const rf_morph_target *t = m->morph_targets[i];
        if (!t || !t->positions || !rf_gw_all_finite(t->positions, n) ||
            (t->normals && !rf_gw_all_finite(t->normals, n)))
            continue;
        int *views = g->morph_view + (size_t)g->morphs * 2;
        g->morph[g->morphs++] = t;
        views[0] = rf_gw_view(g, t->positions, n * sizeof(float), RF_GL_ARRAY_BUFFER);
        views[1] = normals && t->normals
                       ? rf_gw_view(g, t->normals, n * sizeof(float), RF_GL_ARRAY_BUFFER)
                       : -1;
        for (int k = 0; k < 2; k++) {
            json_t *v = views[k] >= 0 ? json_array_get(g->views, (size_t)views[k]) : NULL;
            if (v)
                json_object_set_new(v, "byteStride", json_integer(12));
        }
    }
}

/* A VEC3 float accessor over vertices [first, first + count) of a morph view, with the bounds
 * POSITION targets need; one without a buffer view (all zeros, as glTF defines it) where the part
 * does not move. */
static int rf_gw_morph_accessor(rf_gw *g, int view, const float *v, uint32_t first, uint32_t count)
{
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    bool moves = false;
    for (size_t i = first; i < (size_t)first + count; i++)
        for (int c = 0; c < 3; c++) {
            float x = v[i * 3 + (size_t)c];
            moves |= x != 0;
            lo[c] = x < lo[c] ? x : lo[c], hi[c] = x > hi[c] ? x : hi[c];
        }
    json_t *a = json_pack("{s:i, s:I, s:s, s:o, s:o}", "componentType", RF_GL_FLOAT, "count",
                          (json_int_t)count, "type", "VEC3", "min", rf_gw_vec(lo, 3), "max",
                          rf_gw_vec(hi, 3));
    if (a && moves) {
        json_object_set_new(a, "bufferView", json_integer(view));
        if (first)
            json_object_set_new(a, "byteOffset", json_integer((json_int_t)first * 12));
    }
    if (!a || json_array_append_new(g->accessors, a))
        g->oom = true;
    return (int)json_array_size(g->accessors) - 1;
}

static json_t *rf_gw_part_targets(rf_gw *g, uint32_t first, uint32_t count)
{
    json_t *targets = json_array();
    for (uint32_t i = 0; i < g->morphs; i++) {
        const int *views = g->morph_view + (size_t)i * 2;
        json_t *t =
            json_pack("{s:i}", "POSITION",
                      rf_gw_morph_accessor(g, views[0], g->morph[i]->positions, first, count));
        if (views[1] >= 0)
            json_object_set_new(t, "NORMAL",
                                json_integer(rf_gw_morph_accessor(g, views[1], g->morph[i]->normals,
                                                                  first, count)));
        json_array_append_new(targets, t);
    }
    return targets;
}

/* One primitive per part, each with its material; the whole mesh as one primitive when the
 * parts cannot be (none, or triangles crossing between them). */
static json_t *rf_gw_primitives(rf_gw *g, const rf_mesh *m, const rf_gw_attrs *as)
{
    json_t *prims = json_array();
    bool parts = rf_gw_parts_usable(m);
    for (uint32_t p = 0; p < (parts ? m->part_count : 1); p++) {
        const rf_mesh_part whole = {NULL, 0, m->vertex_count, 0, m->triangle_count};
        const rf_mesh_part *pt = parts ? &m->parts[p] : &whole;
        if (!pt->triangle_count)
            continue;
        json_t *attrs = rf_gw_part_attributes(g, m, as, pt->first_vertex, pt->vertex_count);
        int idx = rf_gw_indices(g, m, pt->first_triangle, pt->triangle_count, pt->first_vertex,
                                pt->vertex_count);
        json_t *prim = json_pack("{s:o, s:i}", "attributes", attrs, "indices", idx);
        int32_t mat = parts ? rf_gw_part_material(m, p) : -1;
        if (mat >= 0)
            json_object_set_new(prim, "material", json_integer(mat));
        if (g->morphs) /* every primitive has every target (glTF requires the same list) */
            json_object_set_new(prim, "targets",
                                rf_gw_part_targets(g, pt->first_vertex, pt->vertex_count));
        json_array_append_new(prims, prim);
    }
    return prims;
}

static json_t *rf_gw_mesh(rf_gw *g, const rf_mesh *m, uint32_t joints, bool skinned)
{
    rf_gw_attrs as = {.n = 0};
    rf_gw_attr_add(g, &as, "POSITION", m->positions, m->vertex_count, RF_GL_FLOAT, 12, "VEC3");
    rf_gw_normals(g, m, &as);
    rf_gw_look_attributes(g, m, as.n == 2, &as);
    if (skinned)
        rf_gw_skin_attributes(g, m, joints, &as);
    rf_gw_morph_views(g, m, as.n >= 2 && strcmp(as.a[1].name, "NORMAL") == 0);
    json_t *mesh = json_pack("{s:o, s:o}", "name", rf_gw_name(m->name ? m->name : "mesh"),
                             "primitives", rf_gw_primitives(g, m, &as));
    if (g->morphs) { /* weights at rest, and the names readers (Blender, three.js) show */
        json_t *weights = json_array(), *names = json_array();
        for (uint32_t i = 0; i < g->morphs; i++) {
            json_array_append_new(
                weights, json_real(isfinite(g->morph[i]->weight) ? g->morph[i]->weight : 0));
            json_array_append_new(names, rf_gw_name(g->morph[i]->name));
        }
        json_object_set_new(mesh, "weights", weights);
        json_object_set_new(mesh, "extras", json_pack("{s:o}", "targetNames", names));
    }
    return mesh;
}

/* ---- materials, textures, images ---- */

/* Every image glTF can carry (PNG, JPEG) as a buffer view; g->image_index maps ours to theirs. */
static void rf_gw_images(rf_gw *g, const rf_mesh *m)
{
    g->image_index = calloc(m->image_count ? m->image_count : 1, sizeof *g->image_index);
    if (!g->image_index) {
        g->oom = true;
        return;
    }
    for (uint32_t i = 0; i < m->image_count; i++) {
        const rf_image *im = m->images ? m->images[i] : NULL;
        g->image_index[i] = -1;
        if (!im || !im->bytes || !im->byte_count || !im->mime_type ||
            (strcmp(im->mime_type, "image/png") != 0 && strcmp(im->mime_type, "image/jpeg") != 0))
            continue;
        int view = rf_gw_view(g, im->bytes, im->byte_count, 0);
        json_t *j = json_pack("{s:i, s:s}", "bufferView", view, "mimeType", im->mime_type);
        if (im->name && *im->name)
            json_object_set_new(j, "name", rf_gw_name(im->name));
        if (!j || json_array_append_new(g->images, j))
            g->oom = true;
        g->image_index[i] = (int)json_array_size(g->images) - 1;
    }
}

static uint16_t rf_gw_wrap(uint16_t w)
{
    return w == RF_TEX_REPEAT || w == RF_TEX_CLAMP_TO_EDGE || w == RF_TEX_MIRRORED_REPEAT ? w : 0;
}

/* The index of a sampler with these settings, added when new; -1 for all defaults. */
static int rf_gw_sampler(rf_gw *g, const rf_texture_ref *t)
{
    /* Only the values glTF allows (anything else is the reader's default): they are few, so
     * the samplers stay few and the linear search below stays short. */
    uint16_t mag = t->mag_filter == 9728 || t->mag_filter == 9729 ? t->mag_filter : 0;
    uint16_t min = t->min_filter >= 9728 && t->min_filter <= 9729   ? t->min_filter
                   : t->min_filter >= 9984 && t->min_filter <= 9987 ? t->min_filter
                                                                    : 0;
    uint16_t ws = rf_gw_wrap(t->wrap_s), wt = rf_gw_wrap(t->wrap_t);
    if (!ws && !wt && !mag && !min)
        return -1;
    json_t *want = json_object();
    if (mag)
        json_object_set_new(want, "magFilter", json_integer(mag));
    if (min)
        json_object_set_new(want, "minFilter", json_integer(min));
    if (ws)
        json_object_set_new(want, "wrapS", json_integer(ws));
    if (wt)
        json_object_set_new(want, "wrapT", json_integer(wt));
    for (size_t i = 0; i < json_array_size(g->samplers); i++)
        if (json_equal(json_array_get(g->samplers, i), want)) {
            json_decref(want);
            return (int)i;
        }
    json_array_append_new(g->samplers, want);
    return (int)json_array_size(g->samplers) - 1;
}

/* {"index", "texCoord"} for a texture reference, or NULL when it names nothing writable. */
static json_t *rf_gw_texture_info(rf_gw *g, const rf_mesh *m, const rf_texture_ref *t)
{
    if (t->image < 0 || (uint32_t)t->image >= m->image_count || g->image_index[t->image] < 0 ||
        t->uv_set >= g->uv_sets)
        return NULL;
    int sampler = rf_gw_sampler(g, t);
    char key[32];
    snprintf(key, sizeof key, "%d:%d", g->image_index[t->image], sampler);
    json_t *known = json_object_get(g->texture_of, key);
    json_int_t index = known ? json_integer_value(known) : (json_int_t)json_array_size(g->textures);
    if (!known) {
        json_t *tex = json_pack("{s:i}", "source", g->image_index[t->image]);
        if (tex && sampler >= 0)
            json_object_set_new(tex, "sampler", json_integer(sampler));
        if (!tex || json_array_append_new(g->textures, tex) ||
            json_object_set_new(g->texture_of, key, json_integer(index)))
            g->oom = true;
    }
    return json_pack("{s:I, s:I}", "index", index, "texCoord", (json_int_t)t->uv_set);
}

static json_t *rf_gw_floats_json(const float *v, int n)
{
    json_t *a = json_array();
    for (int i = 0; i < n; i++)
        json_array_append_new(a, json_real(isfinite(v[i]) ? v[i] : 0.0));
    return a;
}

static double rf_gw_unit(float v)
{
    return v > 0 ? (v < 1 ? v : 1) : 0;
}

static json_t *rf_gw_material(rf_gw *g, const rf_mesh *m, const rf_material *mat)
{
    json_t *j = json_object();
    if (!mat)
        return j; /* glTF's default material keeps the indices of the others */
    if (mat->name && *mat->name)
        json_object_set_new(j, "name", rf_gw_name(mat->name));
    float base[4];
    for (int i = 0; i < 4; i++)
        base[i] = (float)rf_gw_unit(mat->base_color[i]);
    json_t *pbr = json_pack("{s:o, s:f, s:f}", "baseColorFactor", rf_gw_floats_json(base, 4),
                            "metallicFactor", rf_gw_unit(mat->metallic), "roughnessFactor",
                            rf_gw_unit(mat->roughness));
    json_t *t = rf_gw_texture_info(g, m, &mat->base_color_texture);
    if (t)
        json_object_set_new(pbr, "baseColorTexture", t);
    if ((t = rf_gw_texture_info(g, m, &mat->metallic_roughness_texture)))
        json_object_set_new(pbr, "metallicRoughnessTexture", t);
    json_object_set_new(j, "pbrMetallicRoughness", pbr);
    if ((t = rf_gw_texture_info(g, m, &mat->normal_texture))) {
        json_object_set_new(t, "scale", json_real(mat->normal_texture.scale));
        json_object_set_new(j, "normalTexture", t);
    }
    if ((t = rf_gw_texture_info(g, m, &mat->occlusion_texture))) {
        json_object_set_new(t, "strength", json_real(rf_gw_unit(mat->occlusion_texture.scale)));
        json_object_set_new(j, "occlusionTexture", t);
    }
    if ((t = rf_gw_texture_info(g, m, &mat->emissive_texture)))
        json_object_set_new(j, "emissiveTexture", t);
    float em[3];
    for (int i = 0; i < 3; i++)
        em[i] = (float)rf_gw_unit(mat->emissive[i]);
    json_object_set_new(j, "emissiveFactor", rf_gw_floats_json(em, 3));
    static const char *const modes[] = {"OPAQUE", "MASK", "BLEND"};
    json_object_set_new(j, "alphaMode",
                        json_string(modes[mat->alpha_mode <= 2 ? mat->alpha_mode : 0]));
    if (mat->alpha_mode == RF_ALPHA_MASK)
        json_object_set_new(j, "alphaCutoff",
                            json_real(mat->alpha_cutoff >= 0 ? mat->alpha_cutoff : 0.5));
    json_object_set_new(j, "doubleSided", json_boolean(mat->double_sided != 0));
    return j;
}

/* materials, textures, samplers and images of the document (after the mesh: texture
 * coordinates must be known to be written). */
static void rf_gw_materials(rf_gw *g, const rf_mesh *m, json_t *doc)
{
    if (!RF_HAS_FIELD(m, rf_mesh, images) || !m->material_count || !m->materials)
        return;
    rf_gw_images(g, m);
    if (g->oom)
        return;
    json_t *mats = json_array();
    for (uint32_t i = 0; i < m->material_count; i++)
        json_array_append_new(mats, rf_gw_material(g, m, m->materials[i]));
    json_object_set_new(doc, "materials", mats);
    if (json_array_size(g->textures))
        json_object_set_new(doc, "textures", json_incref(g->textures));
    if (json_array_size(g->samplers))
        json_object_set_new(doc, "samplers", json_incref(g->samplers));
    if (json_array_size(g->images))
        json_object_set_new(doc, "images", json_incref(g->images));
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

/* The channel outputs are written straight into the buffer: a copy made first and appended
 * cost a second pass over 160 KB a joint. */
/* Joint j's rotations at frames [first, end) into v, each the short way from the one before
 * (*prev: the frame before first's, carried from one call to the next). */
static void rf_gw_rotations(const rf_animation *a, uint32_t j, uint32_t first, uint32_t end,
                            rf_quat *prev, float *v)
{
    for (uint32_t f = first; f < end; f++, v += 4) {
        rf_quat q = rf_quat_normalize(rf_animation_rotation(a, f, j));
        if (f > 0 && rf_quat_dot(q, *prev) < 0) /* the short way between frames */
            q = rf_quat_neg(q);
        *prev = q;
        v[0] = (float)q.x, v[1] = (float)q.y, v[2] = (float)q.z, v[3] = (float)q.w;
    }
}

static void rf_gw_translations(const rf_animation *a, uint32_t j, uint32_t first, uint32_t end,
                               float *v)
{
    for (uint32_t f = first; f < end; f++, v += 3) {
        rf_vec3 t = rf_animation_translation(a, f, j);
        v[0] = (float)t.x, v[1] = (float)t.y, v[2] = (float)t.z;
    }
}

/* A channel's outputs: a part of a GLB, or written into the buffer (a .gltf's base64). */
static int rf_gw_channel_output(rf_gw *g, const rf_animation *a, uint32_t j, bool rotation)
{
    size_t width = rotation ? 4 : 3, bytes = (size_t)a->frame_count * width * sizeof(float);
    ptrdiff_t offset;
    if (g->stream)
        offset = rf_gw_part_add(g, bytes, a, j, rotation);
    else {
        unsigned char *at;
        offset = (ptrdiff_t)rf_gw_reserve(g, bytes, &at);
        float *v = (float *)(void *)at; /* 4-aligned in a malloc'd buffer */
        rf_quat prev = rf_quat_identity();
        if (at && rotation)
            rf_gw_rotations(a, j, 0, a->frame_count, &prev, v);
        else if (at)
            rf_gw_translations(a, j, 0, a->frame_count, v);
        offset = at ? offset : -1;
    }
    if (offset < 0)
        return -1;
    int view = rf_gw_view_at(g, (size_t)offset, bytes, 0);
    return rf_gw_accessor(g, view, RF_GL_FLOAT, a->frame_count, rotation ? "VEC4" : "VEC3", NULL,
                          NULL);
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

/* The animation, or NULL without joints. A clip in which nothing moves (a one-frame rest pose, a
 * held pose) still gets the first joint's rotation, so the clip, its name and its length
 * survive: glTF forbids an animation without channels. */
static json_t *rf_gw_animation(rf_gw *g, const rf_animation *a, const rf_skeleton *s, double eps)
{
    json_t *samplers = json_array(), *channels = json_array();
    int input = -1;
    /* One pass past the last joint gives a motionless clip its one channel (on joint 0). */
    for (uint32_t k = 0; k <= s->joint_count && !g->oom; k++) {
        bool past = k == s->joint_count;
        uint32_t j = past ? 0 : k;
        bool rot = past ? input < 0 : rf_gw_rotation_moves(a, s, j, eps);
        bool tr = !past && rf_gw_translation_moves(a, s, j, eps);
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
            rf_gw_channel(samplers, channels, input, rf_gw_channel_output(g, a, j, true), j,
                          "rotation");
        if (tr)
            rf_gw_channel(samplers, channels, input, rf_gw_channel_output(g, a, j, false), j,
                          "translation");
    }
    if (!json_array_size(channels) || g->oom) {
        json_decref(samplers), json_decref(channels);
        return NULL;
    }
    return json_pack("{s:o, s:o, s:o}", "name", rf_gw_name(a->name ? a->name : "clip"), "samplers",
                     samplers, "channels", channels);
}

/* ---- document ---- */

/* A skin of every joint: the mesh's, or one of its own without a mesh, so that readers build an
 * armature rather than a tree of empties. */
static json_t *rf_gw_skin(rf_gw *g, const rf_skeleton *s, const rf_mesh *m)
{
    json_t *joints = json_array();
    for (uint32_t j = 0; j < s->joint_count; j++)
        json_array_append_new(joints, json_integer(j));
    static const rf_mesh none = {.size = sizeof none};
    json_t *skin = json_pack("{s:o, s:i}", "joints", joints, "inverseBindMatrices",
                             rf_gw_ibms(g, s, m ? m : &none));
    if (rf_gw_root_count(s) == 1)
        json_object_set_new(skin, "skeleton", json_integer(0));
    return skin;
}

static json_t *rf_gw_document(rf_gw *g, const rf_skeleton *s, const rf_animation *const *clips,
                              uint32_t count, const rf_mesh *m, const rf_gltf_write_opts *o)
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
        json_t *mesh_node =
            json_pack("{s:o, s:i}", "name", rf_gw_name(m->name ? m->name : "mesh"), "mesh", 0);
        json_object_set_new(doc, "meshes",
                            json_pack("[o]", rf_gw_mesh(g, m, s->joint_count, skinned)));
        if (skinned) {
            json_object_set_new(doc, "skins", json_pack("[o]", rf_gw_skin(g, s, m)));
            json_object_set_new(mesh_node, "skin", json_integer(0));
        }
        json_array_append_new(nodes, mesh_node);
        json_array_append_new(scene_nodes, json_integer((json_int_t)json_array_size(nodes) - 1));
    } else if (s->joint_count) {
        json_object_set_new(doc, "skins", json_pack("[o]", rf_gw_skin(g, s, NULL)));
    }
    if (m)
        rf_gw_materials(g, m, doc);
    json_t *anims = json_array();
    for (uint32_t i = 0; i < count; i++) {
        json_t *anim = clips[i] && clips[i]->frame_count && s->joint_count
                           ? rf_gw_animation(g, clips[i], s, o->epsilon)
                           : NULL;
        if (anim)
            json_array_append_new(anims, anim);
    }
    if (json_array_size(anims))
        json_object_set_new(doc, "animations", anims);
    else
        json_decref(anims);
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

/* GLB's file and chunk lengths are uint32 (glTF 2.0, "Binary glTF Layout"): the file is the
 * 12-byte header, the JSON chunk's 8-byte header and text padded to 4, and the binary chunk's
 * header and data padded to 4 when there is data. Done in uint64_t so a count from a 32-bit
 * size_t cannot wrap first. */
bool rf_gltf_glb_fits(const char *name, uint64_t json_bytes, uint64_t bin_bytes, char *err,
                      size_t err_size)
{
    uint64_t total = UINT64_MAX; /* counts past a quarter of uint64 only say "too big" */
    if (json_bytes <= UINT64_MAX / 4 && bin_bytes <= UINT64_MAX / 4)
        total = 12 + 8 + (json_bytes + 3) / 4 * 4 + (bin_bytes ? 8 + (bin_bytes + 3) / 4 * 4 : 0);
    if (total <= UINT32_MAX)
        return true;
    if (err && err_size)
        snprintf(err, err_size,
                 "%s: the GLB would be %" PRIu64 " bytes, over the format's limit of %" PRIu32
                 " bytes (its length fields are uint32); write .gltf instead or fewer frames",
                 name ? name : "glb", total, UINT32_MAX);
    return false;
}

/* Frames made and written at a time by rf_gw_write_part. */
#define RF_GW_PART_FRAMES 8192u

/* A part's floats, made frame by frame as rf_gw_channel_output would have made them. */
static bool rf_gw_write_part(FILE *f, const rf_gw_part *p, float *v)
{
    rf_quat prev = rf_quat_identity();
    for (uint32_t first = 0; first < p->anim->frame_count; first += RF_GW_PART_FRAMES) {
        uint32_t end = first + RF_GW_PART_FRAMES < p->anim->frame_count ? first + RF_GW_PART_FRAMES
                                                                        : p->anim->frame_count;
        size_t n = (size_t)(end - first) * (p->rotation ? 4 : 3);
        if (p->rotation)
            rf_gw_rotations(p->anim, p->joint, first, end, &prev, v);
        else
            rf_gw_translations(p->anim, p->joint, first, end, v);
        if (fwrite(v, sizeof *v, n, f) != n)
            return false;
    }
    return true;
}

/* The binary chunk's bytes: the buffer with the parts written in their places. */
static bool rf_gw_write_chunk(FILE *f, const rf_gw *g)
{
    float *v = g->part_count ? malloc(RF_GW_PART_FRAMES * 4 * sizeof *v) : NULL;
    bool ok = !g->part_count || v;
    size_t done = 0; /* bytes of the buffer written */
    for (size_t i = 0; ok && i < g->part_count; i++) {
        const rf_gw_part *p = &g->parts[i];
        ok = fwrite(g->buf + done, 1, p->at - done, f) == p->at - done && rf_gw_write_part(f, p, v);
        done = p->at;
    }
    size_t rest = g->len - g->held - done;
    ok = ok && fwrite(g->buf + done, 1, rest, f) == rest;
    free(v);
    return ok;
}

static bool rf_gw_write_glb(FILE *f, const char *json, const rf_gw *g)
{
    size_t jlen = strlen(json), jpad = (4 - jlen % 4) % 4, blen = (g->len + 3) & ~(size_t)3;
    size_t total = 12 + 8 + jlen + jpad + (g->len ? 8 + blen : 0);
    unsigned char h[20];
    rf_gw_u32(h, 0x46546C67u), rf_gw_u32(h + 4, 2), rf_gw_u32(h + 8, (uint32_t)total);
    rf_gw_u32(h + 12, (uint32_t)(jlen + jpad)), rf_gw_u32(h + 16, 0x4E4F534Au);
    static const char spaces[4] = "   ", zeros[4] = {0};
    bool ok = fwrite(h, 1, 20, f) == 20 && fwrite(json, 1, jlen, f) == jlen &&
              fwrite(spaces, 1, jpad, f) == jpad;
    if (ok && g->len) {
        unsigned char b[8];
        rf_gw_u32(b, (uint32_t)blen), rf_gw_u32(b + 4, 0x004E4942u);
        ok = fwrite(b, 1, 8, f) == 8 && rf_gw_write_chunk(f, g) &&
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

/* Joints glTF can hold: parents before children (rigflow/model.h; the host does not check a
 * plugin's skeleton, and the nodes, the world rest and the scene's root rely on it) and a rest
 * pose of numbers (JSON has none for NaN: the number would drop out of the node's array). */
/* Names come from files: a refusal names joint `j` by its index and its name escaped
 * (rf_joint_label: "#j" when it has none), so the index finds it in the file and no control
 * byte of a hostile name reaches the terminal. */
#define RF_GW_LABEL 160

static bool rf_gw_check_joints(const rf_skeleton *s, const char *name, char *err, size_t err_size)
{
    char label[RF_GW_LABEL], why[2 * RF_GW_LABEL + 96];
    int64_t bad = rf_skeleton_misordered(s);
    if (bad >= 0) {
        snprintf(err, err_size, "%s: %s", name,
                 rf_skeleton_order_error(s, (uint32_t)bad, why, sizeof why));
        return false;
    }
    for (uint32_t j = 0; j < s->joint_count; j++) {
        const rf_xform *x = &s->joints[j].rest;
        if (!rf_v3_isfinite(x->t) || !rf_v3_isfinite(x->s) ||
            !isfinite(x->r.x + x->r.y + x->r.z + x->r.w)) {
            snprintf(err, err_size, "%s: joint %u '%s': its rest pose is not finite", name, j,
                     rf_joint_label(s, j, label, sizeof label));
            return false;
        }
    }
    return true;
}

static bool rf_gw_check(const rf_skeleton *s, const rf_animation *const *clips, uint32_t count,
                        const rf_mesh *m, const char *name, char *err, size_t err_size)
{
    if (!rf_gw_check_joints(s, name, err, err_size))
        return false;
    char clip[RF_GW_LABEL]; /* a clip's name, from a file too, escaped */
    for (uint32_t i = 0; i < count; i++) {
        const rf_animation *a = clips[i];
        rf_text_escape(a ? a->name : NULL, clip, sizeof clip, 0);
        if (a && a->joint_count != s->joint_count) {
            snprintf(err, err_size, "%s: animation %u '%s' has %u joints, the skeleton %u", name, i,
                     clip, a->joint_count, s->joint_count);
            return false;
        }
        if (a && a->frame_count && !(a->fps > 0)) {
            snprintf(err, err_size, "%s: animation %u '%s': fps must be > 0 (got %g)", name, i,
                     clip, a->fps);
            return false;
        }
        /* glTF keeps times as float32 seconds and wants them strictly increasing: a file's rate
         * may be 1e300 fps (its times all 0) or its clip long enough to run out of digits */
        for (uint32_t f = 1; a && f < a->frame_count; f++)
            if (!((float)(f / a->fps) > (float)((f - 1) / a->fps))) {
                snprintf(err, err_size,
                         "%s: animation %u '%s': frames %u and %u fall on one time in glTF's "
                         "float32 seconds (%g fps)",
                         name, i, clip, f - 1, f, a->fps);
                return false;
            }
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
    /* refused before the file is opened: opening would already truncate one of that name */
    if (text && binary && !rf_gltf_glb_fits(name, strlen(text), g->len, err, err_size)) {
        free(text);
        return false;
    }
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
    return rf_gltf_write_clips(path, name, skeleton, &animation, animation ? 1 : 0, mesh, opts, err,
                               err_size);
}

bool rf_gltf_write_clips(const char *path, const char *name, const rf_skeleton *skeleton,
                         const rf_animation *const *animations, uint32_t animation_count,
                         const rf_mesh *mesh, const rf_gltf_write_opts *opts, char *err,
                         size_t err_size)
{
    rf_gltf_write_opts o = {.binary = rf_gw_has_ext(path, ".glb")};
    if (opts)
        o = *opts;
    if (!(o.epsilon > 0))
        o.epsilon = 1e-6;
    name = name ? name : path;
    if (mesh && (!mesh->vertex_count || !mesh->triangle_count))
        mesh = NULL;
    if (!rf_gw_check(skeleton, animations, animation_count, mesh, name, err, err_size))
        return false;
    rf_gw_axes axes;
    if (!rf_gw_axes_conform(&axes, skeleton, animations, animation_count, mesh)) {
        rf_gw_axes_clear(&axes, animation_count);
        snprintf(err, err_size, "%s: out of memory turning the character to glTF's axes", name);
        return false;
    }
    skeleton = axes.skeleton, animations = axes.animations, mesh = axes.mesh;
    rf_gw g = {.stream = o.binary,
               .views = json_array(),
               .accessors = json_array(),
               .images = json_array(),
               .samplers = json_array(),
               .textures = json_array(),
               .texture_of = json_object()};
    json_t *doc = rf_gw_document(&g, skeleton, animations, animation_count, mesh, &o);
    bool ok = doc && !g.oom && rf_gw_emit(path, name, doc, &g, o.binary, err, err_size);
    if (!ok && (!doc || g.oom))
        snprintf(err, err_size, "%s: out of memory while building the glTF document", name);
    json_decref(doc), json_decref(g.views), json_decref(g.accessors);
    json_decref(g.images), json_decref(g.samplers), json_decref(g.textures);
    json_decref(g.texture_of);
    free(g.image_index);
    free(g.morph), free(g.morph_view);
    free(g.buf), free(g.parts);
    rf_gw_axes_clear(&axes, animation_count);
    return ok;
}
