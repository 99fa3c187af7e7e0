/* Assimp scene to rigflow skeleton, animation and mesh (convenience library librfassimp).
 *
 * Used by the assimp.import node, by the generic import node, by `rigflow inspect` and by the
 * tests, which link it directly. The options struct follows the ufbx shape: zero-initialise it
 * and every zero is a sensible default. doc/formats.md describes what each format gives and how
 * the traps (joint selection, bind versus node rest pose, B3D validation, millisecond ticks,
 * axes, meshes sharing a skeleton) are handled.
 */
#ifndef RF_AIMPORT_H
#define RF_AIMPORT_H

#include <stdbool.h>
#include <stddef.h>

#include <rigflow/rigflow.h>

typedef enum rf_ai_rest {
    RF_AI_REST_BIND = 0, /* the skin's bind pose where there is one (default: matches the mesh) */
    RF_AI_REST_NODE,     /* the scene nodes' own transforms */
} rf_ai_rest;

/* The clip option asking for every clip (rf_ai_result.clip_animations). */
#define RF_AI_ALL_CLIPS "*"

typedef struct rf_ai_options {
    const char *clip;      /* clip name, or its decimal index; NULL or "" for the first; "*" for
                            * every clip (the first is also the animation) */
    rf_ai_rest rest;       /* which pose becomes rf_joint.rest */
    double fps;            /* resampling rate; 0 picks the clip's own key rate (see aimport.c) */
    bool require_skeleton; /* refuse a file in which no skeleton is found */
    bool ignore_rig;       /* give the bare mesh (in its bind pose, unskinned), no joints, no clips:
                            * what a rigger starts from; a rigged file's rig is then the answer */
} rf_ai_options;

/* One animation clip of the file, as listed (whether or not it was selected). */
typedef struct rf_ai_clip {
    char *name;      /* never NULL: unnamed clips are called "clip<index>" */
    double duration; /* seconds */
    double fps;      /* the rate the clip is (or would be) resampled at */
    unsigned frames; /* frames at that rate, both ends included */
} rf_ai_clip;

typedef struct rf_ai_result {
    rf_skeleton *skeleton;   /* zero joints when the file has none and none was required */
    rf_animation *animation; /* the selected clip, or one frame of the rest pose without clips */
    rf_mesh *mesh;           /* all meshes merged, or NULL when the file has no triangles */
    unsigned clip_count;
    rf_ai_clip *clips;              /* [clip_count] */
    int selected_clip;              /* index into clips, or -1 when the file has none */
    rf_animation **clip_animations; /* [clip_count] every clip when asked for "*", else NULL */
} rf_ai_result;

/* Receives warnings (level 1) and information (level 2) while importing. */
typedef void (*rf_ai_log_fn)(void *user, int level, const char *message);

/* Imports `path`. On success fills *out (free with rf_ai_result_clear) and returns true; on
 * failure returns false with a message naming the file in err (err_size bytes) and leaves *out
 * empty. `opts` and `log` may be NULL. */
bool rf_ai_import(const char *path, const rf_ai_options *opts, rf_ai_result *out, rf_ai_log_fn log,
                  void *user, char *err, size_t err_size);

/* Frees what rf_ai_import put into *r (the pointers still set) and zeroes it. */
void rf_ai_result_clear(rf_ai_result *r);

/* Parses "bind" or "node" into *rest; false for anything else. */
bool rf_ai_rest_parse(const char *text, rf_ai_rest *rest);

#endif
