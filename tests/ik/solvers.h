/* The solvers under test, linked directly from their convenience libraries. */
#ifndef RIGFLOW_TESTS_IK_SOLVERS_H
#define RIGFLOW_TESTS_IK_SOLVERS_H

#include "ccd.h"
#include "fabrik.h"
#include "jacobian.h"
#include "twobone.h"

static const rf_ik_solver_api *const SOLVERS[] = {
    &rf_ik_fabrik_api, &rf_ik_ccd_api,  &rf_ik_twobone_api,
    &rf_ik_dls_api,    &rf_ik_pinv_api, &rf_ik_jt_api,
};
#define SOLVER_COUNT (sizeof SOLVERS / sizeof SOLVERS[0])

#endif
