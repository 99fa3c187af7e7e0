/* Shared code of the IK solver plugins: problem checking, the per-solve work area (forward
 * kinematics, the joints each goal moves, reach), constraint projection, small dense linear
 * algebra, result filling and the node type boilerplate. Linked statically into each solver
 * module (libikcommon.la), so it is not part of any ABI: names use the rf_ikc_ prefix.
 */
#ifndef RIGFLOW_IKCOMMON_H
#define RIGFLOW_IKCOMMON_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <rigflow/ik.h>
#include <rigflow/plugin.h>

/* Goals per problem: each joint carries a bit mask of the goals whose chain holds it. */
#define RF_IKC_MAX_GOALS 64

enum rf_ikc_joint_flags {
    RF_IKC_ON_PATH = 1u << 0,  /* between some goal's pivot and its effector (both included) */
    RF_IKC_MOVABLE = 1u << 1,  /* on a path, above an effector, not locked: a solver rotates it */
    RF_IKC_PIVOT = 1u << 2,    /* top of a path: its origin does not move */
    RF_IKC_EFFECTOR = 1u << 3, /* some goal's effector */
};

/* Scratch that grows to the largest problem seen; solve itself then allocates nothing. */
typedef struct rf_ikc_work {
    uint32_t cap_joints, cap_goals;
    rf_xform *world;    /* [J] world (problem space) transforms of the current pose */
    rf_vec3 *pos;       /* [J] positions a solver proposes (FABRIK's forward pass) */
    rf_quat *ref;       /* [J] reference rotations (copied: the pose may be solved in place) */
    rf_vec3 *bone_axis; /* [J] unit bone axis in the reference frame, for cone and twist */
    double *bone_len;   /* [J] distance from the parent's origin (rigid) */
    double *weight;     /* [J] sum of goal weights at and below the joint, on paths */
    int32_t *driver;    /* [J] nearest movable proper ancestor on a path, or -1 */
    rf_xform *rel;      /* [J] transform relative to the driver (constant: locked between) */
    int32_t *first;     /* [J] first path joint this joint drives, or -1 (list by `next`) */
    int32_t *next;      /* [J] next path joint with the same driver, or -1 */
    rf_vec3 *acc;       /* [J] a solver's accumulators */
    rf_quat *turn;      /* [J] a solver's per-joint rotations */
    double *acc_w;      /* [J] */
    uint64_t *goals;    /* [J] mask of goals whose path holds the joint */
    uint8_t *flags;     /* [J] rf_ikc_joint_flags */
    uint32_t *pivot;    /* [G] the goal's pivot joint */
    double *reach;      /* [G] total bone length from pivot to effector */
    double *err;        /* [G] current position errors */
    rf_vec3 *eff;       /* [G] a solver's running effector positions */
    /* A chain solver's arrays, indexed by position along the chain (pivot 0), not by joint. */
    rf_vec3 *cpos;  /* [J] world positions */
    rf_vec3 *coff;  /* [J] a bone vector to the next chain joint (world) */
    rf_quat *crot;  /* [J] world rotations */
    rf_quat *cpend; /* [J] turns not yet applied to crot */
    double *clen;   /* [J] length of the bone from this chain joint to the next */
    /* The plan: the structure of the last problem (parents, constraint flags, goals' effectors
     * and chain roots) and what follows from it alone (flags, goals, driver, first, next and
     * pivot above; the path of a single free chain). A problem with the same structure, the usual
     * case of one solver state fed frame after frame, reuses it instead of walking its paths again.
     */
    uint32_t plan_joints, plan_goals; /* plan_joints 0: no plan */
    int32_t *plan_parents;            /* [J] */
    uint32_t *plan_limits;            /* [J] constraint flags */
    uint32_t *plan_goal;              /* [2G] effector, chain_root */
    bool plan_constrained, plan_branched;
    bool plan_limited;   /* some joint has limit flags */
    uint32_t *path;      /* [J] a single free chain: the pivot's ancestors (root first), then the
                          * chain, pivot first, effector last */
    uint32_t path_above; /* ancestors in path */
    uint32_t path_bones; /* bones of the chain; 0: not a single free chain */
} rf_ikc_work;

bool rf_ikc_work_reserve(rf_ikc_work *w, uint32_t joints, uint32_t goals);
void rf_ikc_work_free(rf_ikc_work *w);

/* A zeroed solver state of `size` bytes whose first member is an rf_ikc_work, reserved for the
 * config's joint and goal counts (defaults 256 and 8); NULL with a message when out of memory. */
void *rf_ikc_state_new(size_t size, const rf_ik_config *cfg, char *err, size_t err_size);
/* Frees such a state (its work area too). NULL allowed. */
void rf_ikc_state_free(void *state);
/* The config's counts with defaults applied. */
uint32_t rf_ikc_config_joints(const rf_ik_config *cfg);
uint32_t rf_ikc_config_goals(const rf_ik_config *cfg);

/* One solve in progress. */
typedef struct rf_ikc_solve {
    const rf_ik_problem *pb;
    rf_ik_result *res;
    rf_xform *local; /* = res->pose */
    rf_ikc_work *w;
    uint32_t n; /* joint count */
    uint32_t goal_count;
    bool constrained;      /* some movable joint has limits */
    bool branched;         /* some path joint drives two or more path joints */
    const uint32_t *chain; /* a single free chain's joints, pivot first (rf_ikc_chain_begin) */
} rf_ikc_solve;

/* Tests turn this off to compare the solvers' fast paths with their general forms on the same
 * problems. */
extern bool rf_ikc_fast_paths;

/* Sized-array access: arrays of size-prefixed structs are read with the stride of the first
 * element's size, so a caller built against an older header still works. */
static inline const rf_ik_goal *rf_ikc_goal(const rf_ik_problem *pb, uint32_t i)
{
    size_t stride = pb->goals[0].size;
    return (const rf_ik_goal *)((const char *)pb->goals + stride * i);
}
/* NULL for a free joint (no constraints, or no limit flags). */
static inline const rf_ik_constraint *rf_ikc_constraint(const rf_ik_problem *pb, uint32_t j)
{
    if (!pb->constraints)
        return NULL;
    size_t stride = pb->constraints[0].size;
    const rf_ik_constraint *c =
        (const rf_ik_constraint *)((const char *)pb->constraints + stride * j);
    return c->flags ? c : NULL;
}

/* Checks a problem without touching res->pose; false with res->message on refusal. */
bool rf_ikc_check(const rf_ik_problem *pb, rf_ik_result *res);
/* Checks the problem (message in res->message on refusal), grows the work area, copies the start
 * pose into res->pose (rotations unit) and sets up the problem's structure (paths, pivots,
 * drivers: the plan, reused while the structure stays the same). */
bool rf_ikc_start(rf_ikc_solve *s, const rf_ik_problem *pb, rf_ik_result *res, rf_ikc_work *w);
/* What depends on the pose: reference rotations, bone axes, world transforms, bone lengths,
 * transforms relative to drivers, weights and reach. */
void rf_ikc_prepare(rf_ikc_solve *s);
/* rf_ikc_start, then rf_ikc_prepare. */
bool rf_ikc_begin(rf_ikc_solve *s, const rf_ik_problem *pb, rf_ik_result *res, rf_ikc_work *w);
/* Applies orientation goals, recomputes world transforms and fills errors, status, max_error,
 * reached. */
void rf_ikc_finish(rf_ikc_solve *s, uint32_t iterations);
/* rf_ikc_finish for a solver that leaves every world transform current (the general forms of
 * CCD, FABRIK and the Jacobian methods do): no forward kinematics again. */
void rf_ikc_finish_current(rf_ikc_solve *s, uint32_t iterations);

/* ---- a single free chain ----
 * One goal on a chain with no limits and no locked joint: the shape where a solver can work on
 * the chain's positions alone, with no per-joint lookups. After rf_ikc_start (no rf_ikc_prepare
 * needed): */

/* True when the problem is a single free chain (and fast paths are on). */
bool rf_ikc_is_free_chain(const rf_ikc_solve *s);
/* World transforms of the chain and the pivot's ancestors (only those), s->chain, the chain's
 * positions into w->cpos, bone lengths into w->clen, reach into w->reach[0]. Returns the bone
 * count m (s->chain[m] is the effector). */
uint32_t rf_ikc_chain_begin(rf_ikc_solve *s);
/* The result, as rf_ikc_finish gives it for any problem, with the effector where w->cpos[m]
 * says (the solver leaves it there: where its solved local rotations put it, to rounding); with
 * an orientation goal, forward kinematics of the chain and the effector's turn first. */
void rf_ikc_chain_finish(rf_ikc_solve *s, uint32_t m, uint32_t iterations);

/* World transforms of every joint from res->pose. */
void rf_ikc_fk(rf_ikc_solve *s);
/* World transform of joint j from its parent's (already current) world transform. */
/* The world transform of a joint with local transform b under a parent whose world transform
 * is a: rf_xform_mul without its renormalisation (local rotations are unit: begin and every
 * update normalise them, and a product of a few hundred unit quaternions stays unit to
 * rounding). FK runs once per joint per iteration, so the saved sqrt counts. */
static inline rf_xform rf_ikc_fk_step(const rf_xform *a, const rf_xform *b)
{
    rf_xform out;
    out.t = rf_v3_add(a->t, rf_quat_rotate(a->r, rf_v3_mul(a->s, b->t)));
    out.r = rf_quat_mul(a->r, b->r);
    out.s = rf_v3_mul(a->s, b->s);
    return out;
}
static inline void rf_ikc_fk_joint(rf_ikc_solve *s, uint32_t j)
{
    int32_t p = s->pb->parents[j];
    s->w->world[j] = p < 0 ? s->local[j] : rf_ikc_fk_step(&s->w->world[p], &s->local[j]);
}
/* After joint j's local rotation changed: its world rotation (its origin does not move). */
static inline void rf_ikc_fk_rot(rf_ikc_solve *s, uint32_t j)
{
    int32_t p = s->pb->parents[j];
    s->w->world[j].r = p < 0 ? s->local[j].r : rf_quat_mul(s->w->world[p].r, s->local[j].r);
}
/* The shortest rotation taking direction u onto v (neither need be unit), with two square roots
 * instead of rf_quat_from_two_vectors' three: the solvers' inner loops call it per joint. */
static inline rf_quat rf_ikc_turn(rf_vec3 u, rf_vec3 v)
{
    double uv = sqrt(rf_v3_len2(u) * rf_v3_len2(v));
    double d = rf_v3_dot(u, v);
    if (!(uv > 1e-300) || d < -uv * (1 - 1e-12))
        return rf_quat_from_two_vectors(u, v); /* zero or opposite: its special cases */
    rf_vec3 c = rf_v3_cross(u, v);
    rf_quat q = rf_quat_make(c.x, c.y, c.z, uv + d);
    double k = 1.0 / sqrt(rf_quat_dot(q, q));
    return rf_quat_make(q.x * k, q.y * k, q.z * k, q.w * k);
}
/* q scaled to unit length, skipping the square root and division when it is unit to 1e-15
 * already, as a product of unit quaternions is to rounding. */
static inline rf_quat rf_ikc_unit(rf_quat q)
{
    double n = rf_quat_dot(q, q);
    return fabs(n - 1) < 1e-15 ? q : rf_quat_normalize(q);
}
/* Position errors of every goal from the current world transforms into w->err; returns the
 * largest. */
double rf_ikc_errors(rf_ikc_solve *s);

/* World rotation of j's parent (identity for a root). */
static inline rf_quat rf_ikc_parent_rot(const rf_ikc_solve *s, uint32_t j)
{
    int32_t p = s->pb->parents[j];
    return p < 0 ? rf_quat_identity() : s->w->world[p].r;
}
/* `local` projected into joint j's limits (unchanged for a free joint). */
rf_quat rf_ikc_constrain_local(const rf_ikc_solve *s, uint32_t j, rf_quat local);
/* Sets joint j's world rotation to `world_rot` (its parent's world transform current), projects
 * it into j's limits and updates world[j]. Returns the world rotation actually applied. */
rf_quat rf_ikc_set_world_rot(rf_ikc_solve *s, uint32_t j, rf_quat world_rot);

/* ---- constraints ---- */

/* Projects a relative rotation (reference^-1 * local) into the limits of `c` (NULL: free).
 * `bone_axis` is the unit bone axis in the reference frame. */
rf_quat rf_ikc_project(const rf_ik_constraint *c, rf_vec3 bone_axis, rf_quat q);
/* Signed angle of the twist of q about unit axis a, in (-pi, pi]. */
double rf_ikc_twist_angle(rf_quat q, rf_vec3 a);
/* Signed angle about unit axis a that turns u towards v, both projected on the plane normal to a
 * (0 when either projection vanishes). */
double rf_ikc_angle_about(rf_vec3 a, rf_vec3 u, rf_vec3 v);
/* Hinge axis of joint j in problem space (unit), with its parent's world transform current. */
rf_vec3 rf_ikc_hinge_axis_world(const rf_ikc_solve *s, uint32_t j);

/* ---- small dense linear algebra (row-major) ---- */

/* Singular values of the m x n matrix A (m <= n) by one-sided Jacobi
 * rotations on the columns of A^T. On return B (n x m, column k = sigma_k v_k, column-major: B[k *
 * n + i]) and U (m x m, column k = u_k: U[k * m + i]) with A = sum_k u_k sigma_k v_k^T, and
 * sigma[k]. Returns the sweeps used. */
int rf_ikc_svd(const double *A, int m, int n, double *B, double *U, double *sigma);
/* Solves S x = b in place for a symmetric positive definite m x m S (overwritten by its Cholesky
 * factor). Returns false when S is not positive definite. */
bool rf_ikc_cholesky_solve(double *S, double *b, int m);

/* ---- plugin boilerplate ---- */

/* The output port and parameters every solver node type shares: "solver" of RF_TYPE_IK_SOLVER;
 * max-joints, max-goals. */
extern const rf_port_desc rf_ikc_solver_output;
/* clang-format off */
#define RF_IKC_COMMON_PARAMS                                                                       \
    {.size = sizeof(rf_param_desc), .name = "max-joints", .type = RF_PARAM_INT,                    \
     .flags = RF_PARAM_HAS_RANGE, .default_number = 256, .min = 1, .max = 65536,                   \
     .doc = "joints the solver preallocates for (larger problems grow it once)"},                  \
    {.size = sizeof(rf_param_desc), .name = "max-goals", .type = RF_PARAM_INT,                     \
     .flags = RF_PARAM_HAS_RANGE, .default_number = 8, .min = 1, .max = RF_IKC_MAX_GOALS,          \
     .doc = "goals the solver preallocates for"}
/* clang-format on */

/* create/process/destroy for a solver node whose configuration is only the shared params plus,
 * optionally, "damping" and "max-step" floats. process makes an rf_ik_solver for `api` on the
 * "solver" port. */
bool rf_ikc_node_create(const rf_host *host, rf_node *node, void **self);
bool rf_ikc_node_process(const rf_ik_solver_api *api, void *self, const rf_host *host,
                         rf_node *node);
void rf_ikc_node_destroy(void *self);

/* Defines `static const rf_node_desc ident##_node`: a node type of kind ik named `type`, whose
 * run hands a solver made by `api` (an rf_ik_solver_api *) to its "solver" port and whose
 * get_extension offers `api` as RF_IK_EXTENSION (how `rigflow ik-bench` finds solvers), and
 * which may process beside other nodes (it only makes the solver). `params`
 * is a static array of rf_param_desc starting with RF_IKC_COMMON_PARAMS; `create` makes the
 * node's rf_ik_config (rf_ikc_node_create, or one that reads more parameters after it). Needs
 * <string.h>. Every solver plugin is these descriptors and its entry table. */
#define RF_IKC_NODE_TYPE(ident, api, type, doc, params, create)                                    \
    static bool ident##_process(void *self, const rf_host *host, rf_node *node)                    \
    {                                                                                              \
        return rf_ikc_node_process((api), self, host, node);                                       \
    }                                                                                              \
    static const void *ident##_extension(const char *id)                                           \
    {                                                                                              \
        return strcmp(id, RF_IK_EXTENSION) == 0 ? (const void *)(api) : NULL;                      \
    }                                                                                              \
    static const rf_node_desc ident##_node = {sizeof(rf_node_desc),                                \
                                              (type),                                              \
                                              RF_KIND_IK,                                          \
                                              (doc),                                               \
                                              0,                                                   \
                                              NULL,                                                \
                                              1,                                                   \
                                              &rf_ikc_solver_output,                               \
                                              sizeof(params) / sizeof((params)[0]),                \
                                              (params),                                            \
                                              (create),                                            \
                                              ident##_process,                                     \
                                              rf_ikc_node_destroy,                                 \
                                              ident##_extension,                                   \
                                              RF_NODE_CONCURRENT}

#endif
