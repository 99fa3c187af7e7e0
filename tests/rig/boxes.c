/* Box meshes for the rigger's tests (boxes.h). */
#include "boxes.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

void add_box_faces(rf_mesh *m, double x0, double y0, double z0, double x1, double y1, double z1,
                   bool top)
{
    static const int corner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                     {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    static const uint32_t face[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7},
                                         {0, 1, 5}, {0, 5, 4}, {3, 6, 2}, {3, 7, 6},
                                         {0, 4, 7}, {0, 7, 3}, {1, 2, 6}, {1, 6, 5}};
    uint32_t base = m->vertex_count;
    for (int c = 0; c < 8; c++) {
        float *p = m->positions + (size_t)(base + c) * 3;
        p[0] = (float)(corner[c][0] ? x1 : x0), p[1] = (float)(corner[c][1] ? y1 : y0);
        p[2] = (float)(corner[c][2] ? z1 : z0);
    }
    uint32_t n = 0;
    for (int t = 0; t < 12; t++) {
        if (!top && (t == 6 || t == 7)) /* the y = y1 side */
            continue;
        for (int k = 0; k < 3; k++)
            m->triangles[(size_t)(m->triangle_count + n) * 3 + k] = base + face[t][k];
        n++;
    }
    m->vertex_count += 8, m->triangle_count += n;
}

void add_box(rf_mesh *m, double x0, double y0, double z0, double x1, double y1, double z1)
{
    add_box_faces(m, x0, y0, z0, x1, y1, z1, true);
}

void add_table_boxes(rf_mesh *m)
{
    add_box(m, -1, 1, -0.4, 1, 1.4, 0.4);         /* body, 2 long, on legs 1 high */
    add_box(m, 0.95, 1.2, -0.25, 1.5, 1.7, 0.25); /* a head, so the body has a front */
    add_box(m, -1, 0, -0.4, -0.8, 1.05, -0.2);
    add_box(m, 0.8, 0, -0.4, 1, 1.05, -0.2);
    add_box(m, -1, 0, 0.2, -0.8, 1.05, 0.4);
    add_box(m, 0.8, 0, 0.2, 1, 1.05, 0.4);
}

void scale_turn(rf_mesh *m, double scale, double turn)
{
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        float *p = m->positions + (size_t)v * 3;
        double x = p[0], z = p[2];
        p[0] = (float)(scale * (x * cos(turn) + z * sin(turn)));
        p[1] = (float)(scale * p[1]);
        p[2] = (float)(scale * (-x * sin(turn) + z * cos(turn)));
    }
}

void lay_z_up(rf_mesh *m)
{
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        float *p = m->positions + (size_t)v * 3, y = p[1];
        p[1] = -p[2], p[2] = y;
    }
}

rf_mesh *box_mesh(uint32_t boxes)
{
    rf_mesh *m = rf_mesh_new();
    if (!m)
        return NULL;
    m->positions = calloc((size_t)boxes * 8 * 3, sizeof(float));
    m->triangles = calloc((size_t)boxes * 12 * 3, sizeof(uint32_t));
    if (!m->positions || !m->triangles) {
        rf_mesh_free(m);
        return NULL;
    }
    return m;
}

rf_mesh *table_creature(double scale, double turn)
{
    rf_mesh *m = box_mesh(6);
    if (!m)
        return NULL;
    add_table_boxes(m);
    scale_turn(m, scale, turn);
    return m;
}
