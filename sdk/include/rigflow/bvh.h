/* BVH (Biovision Hierarchy) reading and writing, shared by the bvh plugin and any other plugin
 * that links the libbvh convenience library. Internal to the project: not part of the SDK.
 *
 * Conventions (see doc/formats/bvh.md):
 * - Rest pose: zero rotations plus OFFSETs. A joint's rest translation is its OFFSET.
 * - Rotation channels are degrees, composed in the order they are listed: for
 *   "Zrotation Xrotation Yrotation" the local rotation is Rz * Rx * Ry.
 * - Position channels give the local translation directly (they replace the OFFSET, as three.js's
 *   BVHLoader does); a joint without position channels keeps its OFFSET in every frame.
 * - An End Site becomes the parent's end_site with RF_JOINT_HAS_END_SITE.
 *
 * Errors are written to a caller's buffer as "FILE:LINE: what was found and what was expected".
 */
#ifndef RIGFLOW_PLUGINS_BVH_H
#define RIGFLOW_PLUGINS_BVH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include <rigflow/plugin.h> /* the data model, and RF_PRINTF */

/* Called now and then during long reads and writes with the fraction done, in [0, 1]. Returning
 * false cancels the operation, which then fails with the message "cancelled". */
typedef bool (*rf_bvh_progress_fn)(void *user, double fraction);
/* Receives a warning about something tolerated (e.g. motion lines beyond the declared Frames). */
typedef void (*rf_bvh_warning_fn)(void *user, const char *message);

typedef struct rf_bvh_read_opts {
    rf_bvh_progress_fn progress; /* may be NULL */
    rf_bvh_warning_fn warning;   /* may be NULL */
    void *user;                  /* passed to both */
    int threads;                 /* 0: a second thread for large files when there is a second
                                  * processor; 1: the caller's thread only. Callbacks always run
                                  * on the caller's thread. */
} rf_bvh_read_opts;

/* Rotation orders for writing; the letters give the channel order, composed left to right. */
typedef enum rf_bvh_order {
    RF_BVH_ORDER_ZYX = 0,
    RF_BVH_ORDER_ZXY,
    RF_BVH_ORDER_YXZ,
    RF_BVH_ORDER_YZX,
    RF_BVH_ORDER_XYZ,
    RF_BVH_ORDER_XZY,
} rf_bvh_order;

typedef struct rf_bvh_write_opts {
    int precision;               /* significant digits of every number, 3..17; 0 means 9 */
    rf_bvh_order order;          /* rotation channel order */
    bool all_positions;          /* give every joint position channels (6 channels) */
    rf_bvh_progress_fn progress; /* may be NULL */
    void *user;
} rf_bvh_write_opts;

/* Reads the BVH file at `path`. On success stores a new skeleton and animation (transfer full:
 * free with rf_skeleton_free / rf_animation_free) and returns true; otherwise writes a message
 * naming the file and line into err (err_size bytes) and returns false. opts may be NULL. */
bool rf_bvh_read_file(const char *path, const rf_bvh_read_opts *opts, rf_skeleton **skeleton,
                      rf_animation **animation, char *err, size_t err_size);

/* The same from memory: `data` holds `size` bytes (no terminator needed); `name` names the
 * source in messages and becomes the skeleton's and clip's name. (data borrowed) */
bool rf_bvh_read_memory(const char *data, size_t size, const char *name,
                        const rf_bvh_read_opts *opts, rf_skeleton **skeleton,
                        rf_animation **animation, char *err, size_t err_size);

/* Writes `skeleton` and `animation` (may be NULL: one frame of the rest pose at 30 fps) as BVH
 * to `path`. Rest rotations are folded into the motion: OFFSETs are written in the world-aligned
 * rest frame and rotations converted so the zero-rotation pose is the rest pose and every frame's
 * world pose is kept. `name` names the output in messages (NULL: path). opts may be NULL. */
bool rf_bvh_write_file(const char *path, const char *name, const rf_skeleton *skeleton,
                       const rf_animation *animation, const rf_bvh_write_opts *opts, char *err,
                       size_t err_size);

/* The same to an open stream; the caller closes it and checks its errors. */
bool rf_bvh_write_stream(FILE *out, const char *name, const rf_skeleton *skeleton,
                         const rf_animation *animation, const rf_bvh_write_opts *opts, char *err,
                         size_t err_size);

/* Parses one decimal number at s ([+-]digits[.digits][(e|E)[+-]digits], or a leading '.'),
 * exactly as strtod in the C locale would, whatever the current locale. Returns the end of the
 * number, or NULL when s does not start with one. s must be terminated by any non-number
 * character (e.g. NUL or a space). */
const char *rf_bvh_parse_double(const char *s, double *out);

/* Writes v as printf's "%.*g" with `precision` significant digits would, except that -0 is
 * written 0, into buf (size bytes, at least 32 for the fast path); returns the length. Several
 * times faster than snprintf for the usual BVH values, which is what the writer spends its time
 * on; falls back to snprintf whenever the result could differ. */
int rf_bvh_format_number(char *buf, size_t size, int precision, double v);

/* Local rotation of Euler channels in degrees composed in the listed order; axes[i] is 0, 1, 2
 * for X, Y, Z. */
rf_quat rf_bvh_euler_to_quat(const int *axes, const double *degrees, int count);

/* Euler angles in degrees for `order` (angles[i] for the i-th listed axis) whose composition in
 * that order is q; exact at gimbal lock (the last angle is then 0). */
void rf_bvh_quat_to_euler(rf_quat q, rf_bvh_order order, double angles[3]);

/* The axes (0 = X, 1 = Y, 2 = Z) of an order, in channel order. */
void rf_bvh_order_axes(rf_bvh_order order, int axes[3]);

/* Parses "ZYX", "zxy", ...; returns false for anything else. */
bool rf_bvh_order_parse(const char *text, rf_bvh_order *order);

#endif
