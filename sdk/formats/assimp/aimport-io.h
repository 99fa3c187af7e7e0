/* What Assimp may read, and the stack it runs on: see aimport-io.c. */
#ifndef RF_AIMPORT_IO_H
#define RF_AIMPORT_IO_H

#include <stdbool.h>

struct aiFileIO;

typedef struct rf_ai_confine {
    const char *model;      /* the model's path as given (borrowed) */
    char *root;             /* the model's folder, symbolic links resolved */
    unsigned refused_count; /* reads refused */
    char refused[640];      /* what the first refusal was, or "" */
    char missing[512];      /* files asked for that are not there, comma-separated, or "" */
} rf_ai_confine;

/* Fills *io so that Assimp reads only the model at `model_path` and regular files inside its
 * folder; refusals are recorded in *cf. False when the folder cannot be resolved. Clear with
 * rf_ai_confine_clear once the import is done. */
bool rf_ai_confine_init(rf_ai_confine *cf, const char *model_path, struct aiFileIO *io);
void rf_ai_confine_clear(rf_ai_confine *cf);

/* Calls fn(arg) on a thread whose stack is sized for importing the file at `path` (on the
 * caller's own stack when no thread can be made), and returns when it is done. */
void rf_ai_call_with_stack_for(const char *path, void (*fn)(void *), void *arg);

#endif
