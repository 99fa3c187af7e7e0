/* The FABRIK solver table, for the plugin and for tests that link the solver directly. */
#ifndef RIGFLOW_IK_FABRIK_H
#define RIGFLOW_IK_FABRIK_H

#include "rigflow/ik-common.h"

extern const rf_ik_solver_api rf_ik_fabrik_api;

#endif
