/* The analytic two-bone solver table, for the plugin and for tests that link it directly. */
#ifndef RIGFLOW_IK_TWOBONE_H
#define RIGFLOW_IK_TWOBONE_H

#include "rigflow/ik-common.h"

extern const rf_ik_solver_api rf_ik_twobone_api;

#endif
