/* The solvers under test, linked directly from their convenience libraries. */
#ifndef RIGFLOW_TESTS_IK_SOLVERS_H
#define RIGFLOW_TESTS_IK_SOLVERS_H

#include "fabrik.h"

static const rf_ik_solver_api *const SOLVERS[] = {
    &rf_ik_fabrik_api,
};
#define SOLVER_COUNT (sizeof SOLVERS / sizeof SOLVERS[0])

#endif
