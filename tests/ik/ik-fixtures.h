/* Problems for the IK tests: chains of unit links and a two-armed tree, the peers' LCG for
 * targets, and independent checks of joint limits (written here from the definitions in ik.h,
 * not shared with the solvers). */
#ifndef RIGFLOW_TESTS_IK_FIXTURES_H
#define RIGFLOW_TESTS_IK_FIXTURES_H

#include <stdint.h>

#include <rigflow/ik.h>

#define FX_MAX_JOINTS 256

typedef struct fx_problem {
    uint32_t n;
    int32_t parents[FX_MAX_JOINTS];
    rf_xform pose[FX_MAX_JOINTS];
    rf_xform out[FX_MAX_JOINTS];
    rf_ik_constraint limits[FX_MAX_JOINTS];
    rf_ik_goal goals[4];
    double errors[4], angle_errors[4];
    uint32_t status[4];
    rf_ik_problem pb;
    rf_ik_result res;
} fx_problem;

/* A straight chain along +y: joint 0 at the origin, `links` unit links, the effector last. */
void fx_chain(fx_problem *f, uint32_t links);
/* A chain along +x with the given link lengths (two-bone tests). */
void fx_chain_lengths(fx_problem *f, const double *lengths, uint32_t links);
/* The tree of the peers' DLS benchmark: a 3-link spine (joints 0-2, chest 3 locked), two 3-link
 * arms starting 1 to either side of the chest (4-7 left, tip 7; 8-11 right, tip 11). */
void fx_tree(fx_problem *f);
/* Links the problem and result to the arrays, with `goals` goals, tolerance and cap. */
void fx_wire(fx_problem *f, uint32_t goals, double tol, uint32_t max_iterations);

/* World positions of the solved pose. */
void fx_world(const fx_problem *f, rf_vec3 *pos, rf_quat *rot);

/* The peers' LCG (seed 99) and target law: uniform direction, radius (0.2..0.9) x reach. */
typedef struct fx_lcg {
    uint32_t seed;
} fx_lcg;
double fx_rnd(fx_lcg *g);
rf_vec3 fx_target(fx_lcg *g, double reach);

/* Largest amount by which joint j's relative rotation breaks its limits (radians, 0 inside). */
double fx_limit_violation(const rf_ik_constraint *c, rf_vec3 bone_axis, rf_quat ref, rf_quat local);

#endif
