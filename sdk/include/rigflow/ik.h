/* rigflow SDK: the inverse kinematics interface.
 *
 * One interface for every IK solver, so that a pipeline (or a retargeter's contact pass) can use
 * whichever solver it is connected to. A solver is a function table (rf_ik_solver_api) plus state
 * made from a configuration. It reaches other nodes in two ways:
 *   - as a value on a port of type RF_TYPE_IK_SOLVER ("rigflow.ik-solver"): an rf_ik_solver made
 *     by the process function of a node of kind RF_KIND_IK. A consumer declares an input of that
 *     type and calls value->api->solve(value->state, &problem, &result);
 *   - through the node type's get_extension(RF_IK_EXTENSION) ("rigflow.ik/1"), which returns the
 *     same const rf_ik_solver_api, for harnesses that make their own state.
 *
 * The problem: a pose of a skeleton or a sub-tree of one (parents and local transforms), goals
 * (an end-effector joint, a target position, optionally an orientation, a weight), per-joint
 * constraints (shared data: hinge, ball-and-socket cone, twist limits), a tolerance and an
 * iteration cap. Targets and the transforms of root joints (parent -1) are in one space, the
 * "problem space"; to solve a sub-tree of a bigger skeleton, give its top joint its world
 * transform. Scale must be uniform per joint.
 *
 * Constraints are measured from a reference rotation per joint (the problem's `reference` pose,
 * or the start pose when NULL): a joint's relative rotation is q = reference.r^-1 * local.r.
 *   - hinge: q is a rotation about `axis` (in the joint's reference frame) by an angle in
 *     [min_angle, max_angle];
 *   - cone: the bone axis turned by q stays within `cone_angle` of the bone axis at reference;
 *   - twist: the twist of q about the bone axis (swing-twist split, q = swing * twist) lies in
 *     [twist_min, twist_max].
 * The bone axis is `bone_axis` in the reference frame, or when zero the offset of the joint's
 * first child (lowest index) in the problem. Angles are radians.
 *
 * Memory: solve never allocates for a problem within the joint and goal counts the state was
 * created for (rf_ik_config); a bigger problem makes the state grow its scratch once. Every
 * pointer in a problem is (borrowed) for the call; result arrays are the caller's.
 *
 * Threading: one state serves one thread at a time; make one state per thread.
 *
 * Growth: every struct starts with a size field (sizeof at the producer's build); fields are only
 * appended. Readers check RF_HAS_FIELD (model.h) before using a later field. Arrays of such
 * structs (goals, constraints) are read with the stride of their first element's size, so a
 * caller built against an older header still works.
 */
#ifndef RIGFLOW_IK_H
#define RIGFLOW_IK_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "rfmath.h"
#include "model.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Port type of an rf_ik_solver value. */
#define RF_TYPE_IK_SOLVER "rigflow.ik-solver"
/* get_extension id returning a const rf_ik_solver_api. */
#define RF_IK_EXTENSION "rigflow.ik/1"

/* ---- constraints ---- */

enum rf_ik_limit_flags {
    RF_IK_LIMIT_HINGE = 1u << 0, /* one axis, angle range: axis, min_angle, max_angle */
    RF_IK_LIMIT_CONE = 1u << 1,  /* ball and socket: cone_angle around the bone axis */
    RF_IK_LIMIT_TWIST = 1u << 2, /* twist about the bone axis: twist_min, twist_max */
    RF_IK_LOCKED = 1u << 3,      /* the joint keeps its start rotation */
};

/* Limits of one joint. A zeroed struct (with size set) is a free ball joint. HINGE excludes CONE
 * and TWIST (a hinge has one degree of freedom). */
typedef struct rf_ik_constraint {
    uint32_t size;    /* sizeof(rf_ik_constraint) */
    uint32_t flags;   /* rf_ik_limit_flags */
    rf_vec3 axis;     /* HINGE: axis in the joint's reference frame (need not be unit) */
    double min_angle; /* HINGE: radians, min_angle <= max_angle, within [-pi, pi] */
    double max_angle;
    rf_vec3 bone_axis; /* CONE, TWIST: bone axis in the reference frame; zero: first child */
    double cone_angle; /* CONE: largest swing of the bone axis, radians in [0, pi] */
    double twist_min;  /* TWIST: radians, twist_min <= twist_max, within [-pi, pi] */
    double twist_max;
} rf_ik_constraint;

/* ---- goals ---- */

enum rf_ik_goal_flags {
    RF_IK_GOAL_ORIENTATION = 1u << 0, /* also match `orientation` (the effector's rotation) */
    RF_IK_GOAL_POLE = 1u << 1,        /* `pole` is a point the chain should bend towards */
};

typedef struct rf_ik_goal {
    uint32_t size;       /* sizeof(rf_ik_goal) */
    uint32_t flags;      /* rf_ik_goal_flags */
    uint32_t effector;   /* joint index whose origin should reach `target` */
    int32_t chain_root;  /* the highest joint this goal may rotate (an ancestor of the effector),
                          * or -1 for the effector's root in the problem */
    rf_vec3 target;      /* problem space */
    rf_quat orientation; /* with RF_IK_GOAL_ORIENTATION: the effector's rotation, problem space */
    rf_vec3 pole;        /* with RF_IK_GOAL_POLE: problem space */
    double weight;       /* > 0: relative pull where goals compete (FABRIK centroids, Jacobian rows,
                          * CCD averaging) */
} rf_ik_goal;

/* ---- problem and result ---- */

typedef struct rf_ik_problem {
    uint32_t size; /* sizeof(rf_ik_problem) */
    uint32_t joint_count;
    const int32_t *parents;    /* [joint_count], parents[i] < i, or -1 for a root */
    const rf_xform *pose;      /* [joint_count] start pose, local to the parent */
    const rf_xform *reference; /* [joint_count] rotations constraints are measured from, or NULL
                                * for the start pose; only .r is read */
    const rf_ik_constraint *constraints; /* [joint_count], or NULL for all free */
    uint32_t goal_count;
    const rf_ik_goal *goals; /* [goal_count] */
    double tolerance;        /* > 0: a goal is reached when its position error is at most this */
    uint32_t max_iterations; /* cap; 0 makes iterative solvers only evaluate the start pose */
} rf_ik_problem;

enum rf_ik_goal_status {
    RF_IK_REACHED = 1u << 0,     /* position error <= tolerance */
    RF_IK_UNREACHABLE = 1u << 1, /* the target is farther from the goal's pivot (the chain root's
                                  * origin) than the chain's total length: no pose reaches it, the
                                  * result is the best stretched pose */
};

typedef struct rf_ik_result {
    uint32_t size;        /* sizeof(rf_ik_result) */
    rf_xform *pose;       /* [joint_count] the caller's: the solved local pose; may be the same
                           * array as problem->pose to solve in place */
    double *errors;       /* [goal_count] the caller's, or NULL: position error per goal */
    double *angle_errors; /* [goal_count] the caller's, or NULL: radians, 0 without an
                           * orientation goal */
    uint32_t *status;     /* [goal_count] the caller's, or NULL: rf_ik_goal_status */
    uint32_t iterations;  /* out: iterations used (solver-defined: one sweep or one step) */
    double max_error;     /* out: largest position error */
    bool reached;         /* out: every goal reached */
    char message[160];    /* out: why solve refused the problem */
} rf_ik_result;

/* ---- solvers ---- */

enum rf_ik_capabilities {
    RF_IK_CAP_MULTI_GOAL = 1u << 0,  /* several goals at once, on a tree */
    RF_IK_CAP_ORIENTATION = 1u << 1, /* honours RF_IK_GOAL_ORIENTATION */
    RF_IK_CAP_POLE = 1u << 2,        /* honours RF_IK_GOAL_POLE */
    RF_IK_CAP_TWO_BONE = 1u << 3,    /* only chains of exactly two bones per goal */
};

/* Options for a solver state. Zero fields mean the defaults. */
typedef struct rf_ik_config {
    uint32_t size;       /* sizeof(rf_ik_config) */
    uint32_t max_joints; /* scratch sized for this many joints (default 256) */
    uint32_t max_goals;  /* and this many goals (default 8) */
    double damping;      /* damped least squares lambda, in length units (default 0.1 x the mean
                          * bone length) */
    double max_step;     /* Jacobian methods: largest target displacement per step, length units
                          * (default: the mean bone length of the problem) */
} rf_ik_config;

typedef struct rf_ik_solver_api {
    uint32_t size;         /* sizeof(rf_ik_solver_api) */
    const char *name;      /* short name, e.g. "fabrik" */
    const char *doc;       /* one line */
    uint32_t limits;       /* rf_ik_limit_flags the solver honours: joints it moves stay in them */
    uint32_t capabilities; /* rf_ik_capabilities */
    /* A state for `config` (NULL: defaults), or NULL with a message in err. (transfer full) */
    void *(*create)(const rf_ik_config *config, char *err, size_t err_size);
    /* Solves `problem` from its start pose into result. Returns false, with result->message, when
     * the problem is refused (bad index, non-finite value, coordinates or scales beyond 1e30,
     * unsupported shape): result->pose is then untouched. A goal not reached is not a refusal:
     * see result->status. */
    bool (*solve)(void *state, const rf_ik_problem *problem, rf_ik_result *result);
    void (*destroy)(void *state);
} rf_ik_solver_api;

/* The value on a RF_TYPE_IK_SOLVER port: a configured solver. */
typedef struct rf_ik_solver {
    uint32_t size;               /* sizeof(rf_ik_solver) */
    const rf_ik_solver_api *api; /* (static while the plugin is loaded) */
    void *state;                 /* owned: api->destroy frees it */
    char *label;                 /* owned, may be NULL: the id of the node that made it */
} rf_ik_solver;

/* A solver value owning `state`, or NULL when out of memory (state is then destroyed).
 * (transfer full: free with rf_ik_solver_free) */
static inline rf_ik_solver *rf_ik_solver_new(const rf_ik_solver_api *api, void *state,
                                             const char *label)
{
    rf_ik_solver *s = (rf_ik_solver *)calloc(1, sizeof *s);
    char *copy = NULL;
    if (s && label) {
        size_t n = strlen(label) + 1;
        copy = (char *)malloc(n);
        if (copy)
            memcpy(copy, label, n);
    }
    if (!s || (label && !copy)) {
        free(s);
        api->destroy(state);
        return NULL;
    }
    s->size = sizeof *s;
    s->api = api;
    s->state = state;
    s->label = copy;
    return s;
}

/* Frees a solver value and its state. NULL allowed. Usable as a set_output destroy. */
static inline void rf_ik_solver_free(void *solver)
{
    rf_ik_solver *s = (rf_ik_solver *)solver;
    if (!s)
        return;
    if (s->api && s->state)
        s->api->destroy(s->state);
    free(s->label);
    free(s);
}

/* A free goal for `effector` reaching `target`, weight 1. */
static inline rf_ik_goal rf_ik_goal_make(uint32_t effector, rf_vec3 target)
{
    rf_ik_goal g;
    memset(&g, 0, sizeof g);
    g.size = sizeof g;
    g.effector = effector;
    g.chain_root = -1;
    g.target = target;
    g.orientation = rf_quat_identity();
    g.weight = 1.0;
    return g;
}

/* The 1.0 layout of each struct, the smallest a solver or caller accepts: fields appended later
 * are read only when the struct's size covers them (RF_HAS_FIELD), and goal and constraint arrays
 * are walked by their elements' own size. */
#define RF_IK_CONSTRAINT_SIZE_1_0 RF_SIZE_THROUGH(rf_ik_constraint, twist_max)
#define RF_IK_GOAL_SIZE_1_0 RF_SIZE_THROUGH(rf_ik_goal, weight)
#define RF_IK_PROBLEM_SIZE_1_0 RF_SIZE_THROUGH(rf_ik_problem, max_iterations)
#define RF_IK_RESULT_SIZE_1_0 RF_SIZE_THROUGH(rf_ik_result, message)
#define RF_IK_CONFIG_SIZE_1_0 RF_SIZE_THROUGH(rf_ik_config, max_step)
#define RF_IK_SOLVER_API_SIZE_1_0 RF_SIZE_THROUGH(rf_ik_solver_api, destroy)
#define RF_IK_SOLVER_SIZE_1_0 RF_SIZE_THROUGH(rf_ik_solver, label)

/* True when `api` (a get_extension(RF_IK_EXTENSION) answer) is complete enough to drive. */
static inline bool rf_ik_api_usable(const rf_ik_solver_api *api)
{
    return api && api->size >= RF_IK_SOLVER_API_SIZE_1_0 && api->create && api->solve &&
           api->destroy;
}

/* True when `s` (a value on an RF_TYPE_IK_SOLVER port) is complete enough to drive. */
static inline bool rf_ik_solver_usable(const rf_ik_solver *s)
{
    return s && s->size >= RF_IK_SOLVER_SIZE_1_0 && rf_ik_api_usable(s->api);
}

#ifdef __cplusplus
}
#endif

#endif
