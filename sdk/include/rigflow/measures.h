/* rigflow SDK: measures over time, the port type "rigflow.measures".
 *
 * A measuring node (retarget.measure, or any third party's) hands its per-frame figures to the
 * nodes after it as named series on the clip's frames, plus one-line warnings. A consumer (the
 * HTML report) shows every series it finds without knowing them in advance, so a new measure
 * appears in the report as soon as a node outputs it.
 *
 * Header-only, calloc/free based like model.h, so any plugin can make and free these values.
 */
#ifndef RIGFLOW_MEASURES_H
#define RIGFLOW_MEASURES_H

#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <rigflow/model-copy.h>

#ifdef __cplusplus
extern "C" {
#endif

#define RF_TYPE_MEASURES "rigflow.measures"

enum rf_series_flags {
    RF_SERIES_CONTACT = 1u << 0,      /* 0/1 per frame: `joint` touches the ground */
    RF_SERIES_HIGHER_WORSE = 1u << 1, /* the frames worth a look are the highest ones */
};

/* One figure per frame of the measured clip. */
typedef struct rf_series {
    char *name;     /* e.g. "direction error, mean over bones"; owned */
    char *unit;     /* e.g. "deg", "leg/s", or ""; owned */
    int32_t joint;  /* target joint the series is about, or -1 for the whole character */
    uint32_t flags; /* rf_series_flags */
    float *values;  /* [frame_count]; NAN where the frame was not measured; owned */
} rf_series;

typedef struct rf_measures {
    uint32_t size;
    uint32_t frame_count; /* frames of the measured clip */
    double fps;           /* its rate */
    uint32_t series_count;
    rf_series *series; /* [series_count], owned */
    uint32_t warning_count;
    char **warnings; /* [warning_count] one line each, plain text; owned */
} rf_measures;

/* Empty measures for a clip of `frame_count` frames at `fps`, or NULL when out of memory.
 * (transfer full: free with rf_measures_free) */
static inline rf_measures *rf_measures_new(uint32_t frame_count, double fps)
{
    rf_measures *m = (rf_measures *)calloc(1, sizeof *m);
    if (!m)
        return NULL;
    m->size = sizeof *m;
    m->frame_count = frame_count;
    m->fps = fps;
    return m;
}

/* Frees measures, their series and warnings. NULL is allowed. Usable as a set_output destroy. */
static inline void rf_measures_free(void *measures)
{
    rf_measures *m = (rf_measures *)measures;
    if (!m)
        return;
    for (uint32_t i = 0; i < m->series_count; i++) {
        free(m->series[i].name);
        free(m->series[i].unit);
        free(m->series[i].values);
    }
    for (uint32_t i = 0; i < m->warning_count; i++)
        free(m->warnings[i]);
    free(m->series);
    free(m->warnings);
    free(m);
}

/* Appends a series with every value NAN and returns its values to fill in, or NULL when out of
 * memory (the measures are unchanged then). */
static inline float *rf_measures_add(rf_measures *m, const char *name, const char *unit,
                                     int32_t joint, uint32_t flags)
{
    rf_series *grown = (rf_series *)realloc(m->series, (m->series_count + 1) * sizeof *grown);
    if (!grown)
        return NULL;
    m->series = grown;
    rf_series s = {rf_strdup(name ? name : ""), rf_strdup(unit ? unit : ""), joint, flags,
                   (float *)malloc((m->frame_count ? m->frame_count : 1) * sizeof(float))};
    if (!s.name || !s.unit || !s.values) {
        free(s.name), free(s.unit), free(s.values);
        return NULL;
    }
    for (uint32_t f = 0; f < m->frame_count; f++)
        s.values[f] = NAN;
    m->series[m->series_count++] = s;
    return s.values;
}

/* Appends a one-line warning (printf format). Returns false when out of memory. */
static inline bool rf_measures_warn(rf_measures *m, const char *fmt, ...)
#if defined(__GNUC__) || defined(__clang__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
static inline bool rf_measures_warn(rf_measures *m, const char *fmt, ...)
{
    char line[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    char **grown = (char **)realloc(m->warnings, (m->warning_count + 1) * sizeof *grown);
    if (!grown)
        return false;
    m->warnings = grown;
    if (!(grown[m->warning_count] = rf_strdup(line)))
        return false;
    m->warning_count++;
    return true;
}

#ifdef __cplusplus
}
#endif

#endif
