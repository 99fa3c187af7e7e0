/* The mesh as Embree sees it, for the parts of librigauto that cast rays (bone heat's visibility,
 * joint placement across the body). */
#ifndef RF_RIG_EMBREE_H
#define RF_RIG_EMBREE_H

#include <embree3/rtcore.h>

#include "rig-internal.h"

/* A triangle geometry of g's vertices (as floats) and triangles on dev, not yet committed (a
 * caller may add a filter first); NULL when Embree could not allocate its buffers. */
RTCGeometry rf_rig_triangles(RTCDevice dev, const rf_rig_geo *g);

#endif
