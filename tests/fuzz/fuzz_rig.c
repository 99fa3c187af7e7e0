/* libFuzzer harness: the general auto-rigger (plugins/rig-general, librigauto) on arbitrary
 * meshes.
 *
 * The bytes describe a mesh rather than being one, so that the fuzzer reaches the shapes that
 * break geometry code quickly: coincident and duplicate vertices, slivers and degenerate
 * triangles, flat and thin meshes, loose parts and specks, indices out of range, NaN and huge
 * coordinates, any scale.
 *
 *   byte 0      mode bits (RF_FZ_*)
 *   byte 1      vertex count / 2 (so up to 510)
 *   byte 2      triangle count / 2 (so up to 510)
 *   then        3 bytes per vertex (a point on a 256^3 grid), then 3 bytes per triangle (indices
 *               modulo the vertex count, or raw with RF_FZ_RAW_INDEX), reused cyclically
 *
 * With RF_FZ_BIND the mesh is weighted to a given skeleton instead (rf_rig_bind), made of the
 * same bytes read from the end backwards: 1 to 8 joints, each a parent byte taken as signed (so
 * roots, parents after their child, past the end, the joint itself) and a translation.
 *
 * Then it checks what rig.h promises: either false with a message and nothing allocated, or a
 * skeleton whose parents come first and a copy of the mesh with every vertex weighted by at most
 * four existing joints, weights summing to 1.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rig.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

enum {
    RF_FZ_NAN = 1u << 0,         /* one coordinate is NaN */
    RF_FZ_HUGE = 1u << 1,        /* coordinates scaled by 1e20 */
    RF_FZ_TINY = 1u << 2,        /* coordinates scaled by 1e-6 */
    RF_FZ_RAW_INDEX = 1u << 3,   /* triangle indices not reduced modulo the vertex count */
    RF_FZ_FLAT = 1u << 4,        /* every z is 0 */
    RF_FZ_NO_VIS = 1u << 5,      /* no visibility rays */
    RF_FZ_SMALL_PROXY = 1u << 6, /* simplify above 1000 triangles... and the speck size at 0.3 */
    RF_FZ_BIND = 1u << 7,        /* weight to a skeleton the bytes give (rf_rig_bind) */
};

static void rf_fz_broken(const char *what)
{
    fprintf(stderr, "broken promise: %s\n", what);
    abort();
}

static rf_mesh *rf_fz_mesh(const uint8_t *data, size_t size, uint8_t mode)
{
    rf_mesh *m = rf_mesh_new();
    uint32_t nv = 2u * data[1], nt = 2u * data[2];
    const uint8_t *body = data + 3;
    size_t left = size - 3;
    m->vertex_count = nv, m->triangle_count = nt;
    m->positions = calloc((size_t)nv * 3 + 1, sizeof(float));
    m->triangles = calloc((size_t)nt * 3 + 1, sizeof(uint32_t));
    double scale = mode & RF_FZ_HUGE ? 1e20 : mode & RF_FZ_TINY ? 1e-6 : 0.01;
    size_t k = 0;
    for (uint32_t i = 0; i < nv * 3; i++, k++) {
        uint8_t b = left ? body[k % left] : (uint8_t)i;
        m->positions[i] = (float)(b * scale);
        if ((mode & RF_FZ_FLAT) && i % 3 == 2)
            m->positions[i] = 0;
    }
    if ((mode & RF_FZ_NAN) && nv)
        m->positions[(data[1] * 7u) % (nv * 3)] = NAN;
    for (uint32_t i = 0; i < nt * 3; i++, k++) {
        uint8_t b = left ? body[k % left] : (uint8_t)i;
        m->triangles[i] = mode & RF_FZ_RAW_INDEX ? b : (nv ? b % nv : 0);
    }
    return m;
}

static void rf_fz_check(const rf_mesh *in, const rf_skeleton *s, const rf_mesh *m)
{
    if (!s || !m || !s->joint_count)
        rf_fz_broken("success without a skeleton or mesh");
    for (uint32_t j = 0; j < s->joint_count; j++)
        if (s->joints[j].parent >= (int32_t)j || !s->joints[j].name)
            rf_fz_broken("a parent after its child, or a joint without a name");
    if (m->vertex_count != in->vertex_count || m->bind_count != s->joint_count)
        rf_fz_broken("the skinned mesh does not match");
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        double sum = 0;
        for (int k = 0; k < 4; k++) {
            if (m->skin_joints[v * 4 + k] >= s->joint_count)
                rf_fz_broken("a weight names a joint that does not exist");
            if (!(m->skin_weights[v * 4 + k] >= 0))
                rf_fz_broken("a negative or NaN weight");
            sum += m->skin_weights[v * 4 + k];
        }
        if (!(fabs(sum - 1) < 1e-3))
            rf_fz_broken("a vertex whose weights do not sum to 1");
    }
}

/* A skeleton of 1 to 8 joints from the bytes read backwards: a parent byte as signed, then a
 * translation on the mesh's grid. Nothing is made consistent: that is rf_rig_bind's job. */
static rf_skeleton *rf_fz_skeleton(const uint8_t *data, size_t size, double scale)
{
    size_t k = size - 1;
    uint32_t n = data[k] % 8 + 1;
    rf_skeleton *s = rf_skeleton_new(n);
    for (uint32_t j = 0; s && j < n; j++) {
        uint8_t b[4];
        for (int i = 0; i < 4; i++)
            b[i] = data[k], k = k ? k - 1 : size - 1;
        s->joints[j].parent = (int8_t)b[0] < 0 ? -1 : (int32_t)j - 1 - (int8_t)b[0] % 3;
        if (b[0] == 0x7f)
            s->joints[j].parent = (int32_t)j + 1; /* after its child, or past the end */
        if (b[0] == 0x7e)
            s->joints[j].parent = (int32_t)j; /* its own parent */
        s->joints[j].rest = rf_xform_identity();
        s->joints[j].rest.t = rf_v3(b[1] * scale, b[2] * scale, b[3] * scale);
    }
    return s;
}

/* rf_rig_bind's promise: false with a message and nothing allocated, or a copy of the mesh whose
 * every vertex is weighted by at most four of the skeleton's joints, weights summing to 1. */
static void rf_fz_bind(const rf_mesh *in, const rf_rig_options *o, const uint8_t *data, size_t size,
                       double scale)
{
    rf_skeleton *s = rf_fz_skeleton(data, size, scale);
    rf_mesh *m = (rf_mesh *)1;
    char err[512] = "";
    if (rf_rig_bind(in, s, NULL, o, &m, NULL, err, sizeof err)) {
        if (!m || m->vertex_count != in->vertex_count || m->bind_count != s->joint_count)
            rf_fz_broken("the weighted mesh does not match");
        for (uint32_t v = 0; v < m->vertex_count; v++) {
            double sum = 0;
            for (int k = 0; k < 4; k++) {
                if (m->skin_joints[v * 4 + k] >= s->joint_count)
                    rf_fz_broken("a weight names a joint that does not exist");
                if (!(m->skin_weights[v * 4 + k] >= 0))
                    rf_fz_broken("a negative or NaN weight");
                sum += m->skin_weights[v * 4 + k];
            }
            if (!(fabs(sum - 1) < 1e-3))
                rf_fz_broken("a vertex whose weights do not sum to 1");
        }
        rf_mesh_free(m);
    } else if (m || !err[0]) {
        rf_fz_broken("a refusal without a message, or with something allocated");
    }
    rf_skeleton_free(s);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 3)
        return 0;
    uint8_t mode = data[0];
    rf_mesh *in = rf_fz_mesh(data, size, mode);
    rf_rig_options o = {.resolution = 24, .no_visibility = (mode & RF_FZ_NO_VIS) != 0};
    if (mode & RF_FZ_SMALL_PROXY)
        o.proxy_triangles = 100, o.speck_size = 0.3;
    if (mode & RF_FZ_BIND) {
        rf_fz_bind(in, &o, data, size, mode & RF_FZ_HUGE ? 1e20 : mode & RF_FZ_TINY ? 1e-6 : 0.01);
        rf_mesh_free(in);
        return 0;
    }
    rf_skeleton *s = (rf_skeleton *)1;
    rf_mesh *m = (rf_mesh *)1;
    char err[512] = "";
    if (rf_rig_general(in, &o, &s, &m, NULL, NULL, NULL, err, sizeof err)) {
        rf_fz_check(in, s, m);
        rf_skeleton_free(s);
        rf_mesh_free(m);
    } else if (s || m || !err[0]) {
        rf_fz_broken("a refusal without a message, or with something allocated");
    }
    rf_mesh_free(in);
    return 0;
}
