/* The general auto-rigger (librigauto): an unrigged mesh in, a skeleton and the mesh skinned to it
 * out, for any body (doc/autorig.md). Linked by the rig.general plugin, `rigflow rig-bench` and
 * the tests.
 *
 * Steps: clean the mesh (weld, split into loose parts, set specks aside, simplify a proxy when it
 * is big), voxelise the closed volume, grow geodesic level sets (from the thickest point, then
 * again from where the feet meet), link their pieces into a curve skeleton, prune it and cut it
 * into joints at junctions and even lengths; then weight the mesh by bone heat. Everything is
 * measured relative to the mesh's bounding box, so any unit and any facing behave alike.
 */
#ifndef RF_RIG_H
#define RF_RIG_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <rigflow/model.h>

/* The defaults, one home for the library (rf_rig_defaults) and the node's parameters. */
#define RF_RIG_RESOLUTION 96
#define RF_RIG_PROXY_TRIANGLES 20000
#define RF_RIG_SPECK_SIZE 0.02
#define RF_RIG_SEGMENT 0.12

/* Zero-initialised is the default everywhere (the RF_RIG_ values above). */
typedef struct rf_rig_options {
    uint32_t resolution;      /* voxels along the longest bounding-box edge; 0: default */
    uint32_t proxy_triangles; /* simplify a proxy above this many triangles; 0: default */
    double speck_size;        /* a loose part spanning less than this fraction of the whole
                               * mesh's bounding-box diagonal is a speck; 0: default */
    double segment;           /* the longest bone as a fraction of the longest edge; 0: default */
    bool no_visibility;       /* heat every vertex from its nearest bone, seen or not */
    rf_vec3 up, forward;      /* the axes the file declares (zero: unknown); the skeleton keeps
                               * them and the analysis naming its joints starts from them */
    bool leaf_points_own;     /* a leaf joint without an end site owns the vertices past it (an
                               * artist's convention; set when binding a given skeleton) */
    bool given_bones;         /* the skeleton was not grown inside this mesh: its bones may lie
                               * outside the skin, so a bone in front of a vertex's surface is
                               * not passed over (set when binding a given skeleton) */
    bool keep_joints;         /* every joint keeps skin to move (a template's named layout): a
                               * low-poly box is never moved by one joint alone where that would
                               * leave the joints inside it moving nothing (set by the template
                               * rigger; the general rigger drops such joints instead) */
    rf_vec3 facing;           /* the way the body faces as the general rigger read it from its
                               * own skeletons, for a file that declares no forward (zero: none
                               * read); set by the rigger itself */
} rf_rig_options;

#define RF_RIG_UP_NOTE 320 /* bytes of rf_rig_stats.up_note */

/* What happened, for logs and the benchmark. */
typedef struct rf_rig_stats {
    uint32_t vertices, welded; /* input vertices, after welding */
    uint32_t parts, specks;    /* loose parts, of which specks */
    uint32_t proxy_triangles;  /* triangles the heat was solved on */
    uint32_t joints;
    uint32_t heat_vertices;       /* proxy vertices weighted by heat */
    uint32_t fallback_vertices;   /* vertices not heated: specks and strays, weighted like the
                                   * surface nearest them (or the nearest bone) */
    uint32_t unseen_vertices;     /* proxy vertices that saw no bone (heated by their neighbours) */
    bool up_assumed;              /* the file declared no up and the body showed none: +y taken */
    char up_note[RF_RIG_UP_NOTE]; /* how the up of a file that declares none was decided, or "" */
} rf_rig_stats;

/* Called with the fraction done; may be NULL. */
typedef void (*rf_rig_progress_fn)(void *user, double fraction);

/* Rigs `mesh`. On success returns true with a new skeleton (rest pose = bind pose, identity
 * rotations) and a copy of the mesh skinned to it (every vertex weighted, inverse binds set).
 * On failure returns false with a reason in err and nothing allocated. `opts`, `stats` and
 * `progress` may be NULL. */
bool rf_rig_general(const rf_mesh *mesh, const rf_rig_options *opts, rf_skeleton **skeleton,
                    rf_mesh **skinned, rf_rig_stats *stats, rf_rig_progress_fn progress, void *user,
                    char *err, size_t err_size);

/* Which template rf_rig_template lays into the body. */
typedef enum rf_rig_template_kind {
    RF_RIG_TEMPLATE_AUTO =
        0, /* the humanoid for two legs and two arms, the quadruped for four legs */
    RF_RIG_TEMPLATE_HUMANOID,  /* Hips, Spine..Spine2, Neck, Head; Shoulder, Arm, ForeArm, Hand;
                                * UpLeg, Leg, Foot, ToeBase per side */
    RF_RIG_TEMPLATE_QUADRUPED, /* the same names, the forelegs as arms from the chest, and
                                * Tail..Tail3 when the body has a tail */
} rf_rig_template_kind;

/* Rigs `mesh` with a template (doc/autorig.md): the general rigger's curve skeleton, read by the
 * skeleton analysis, carries the template's joints at their relative places along each chain,
 * with standard names; bone heat as rf_rig_general. A body that fits no template (or not the one
 * asked for) is refused with the reason in err. Same terms as rf_rig_general. */
bool rf_rig_template(const rf_mesh *mesh, const rf_rig_options *opts, rf_rig_template_kind kind,
                     rf_skeleton **skeleton, rf_mesh **skinned, rf_rig_stats *stats,
                     rf_rig_progress_fn progress, void *user, char *err, size_t err_size);

/* Weights `mesh` to a given skeleton by bone heat (the rigger's skinning alone). inverse_bind
 * ([joint_count], may be NULL: the rest pose) places the joints; joints flagged
 * RF_JOINT_UNWEIGHTED get no weights. Returns a skinned copy carrying those inverse binds, or
 * false with a reason. `opts` and `stats` may be NULL. */
bool rf_rig_bind(const rf_mesh *mesh, const rf_skeleton *skeleton, const rf_mat4 *inverse_bind,
                 const rf_rig_options *opts, rf_mesh **skinned, rf_rig_stats *stats, char *err,
                 size_t err_size);

#endif
