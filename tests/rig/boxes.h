/* Box meshes for the rigger's tests (test_rig, test_rig_up_oom): closed boxes appended to a mesh
 * whose arrays have room for them (8 vertices and 12 triangles a box), and the table creature,
 * a box body on four box legs with a box head, the body every rigger test starts from. */
#ifndef RIGFLOW_TESTS_RIG_BOXES_H
#define RIGFLOW_TESTS_RIG_BOXES_H

#include <stdbool.h>
#include <stdint.h>

#include <rigflow/model.h>

/* The box x0..x1, y0..y1, z0..z1 appended to m, its faces wound outwards; without `top`, its
 * y = y1 side left open (10 triangles). */
void add_box_faces(rf_mesh *m, double x0, double y0, double z0, double x1, double y1, double z1,
                   bool top);
/* A closed box appended to m. */
void add_box(rf_mesh *m, double x0, double y0, double z0, double x1, double y1, double z1);

/* A new mesh (rf_mesh_free) with room for `boxes` boxes, none in it yet. */
rf_mesh *box_mesh(uint32_t boxes);

/* The table creature's six boxes appended to m: a body 2 long (x -1 to 1) on four legs 1 high,
 * symmetric about z = 0, and a head at +x, so the body has a front. */
void add_table_boxes(rf_mesh *m);
/* m's vertices scaled by `scale` about the origin and turned by `turn` radians about +y. */
void scale_turn(rf_mesh *m, double scale, double turn);
/* m's vertices laid down as a Z-up file saves a body standing on +y: (x, y, z) -> (x, -z, y). */
void lay_z_up(rf_mesh *m);

/* A new mesh (rf_mesh_free) of the table creature scaled and turned (scale_turn). */
rf_mesh *table_creature(double scale, double turn);

#endif
