/* The Jacobian solver tables (transpose, SVD pseudoinverse, damped least squares), for the plugin
 * and for tests that link the solvers directly. */
#ifndef RIGFLOW_IK_JACOBIAN_H
#define RIGFLOW_IK_JACOBIAN_H

#include "rigflow/ik-common.h"

extern const rf_ik_solver_api rf_ik_jt_api;
extern const rf_ik_solver_api rf_ik_pinv_api;
extern const rf_ik_solver_api rf_ik_dls_api;

#endif
