/* Jacobian inverse kinematics after Buss ("Introduction to Inverse Kinematics with Jacobian
 * Transpose, Pseudoinverse and Damped Least Squares methods"): each step linearises the effector
 * positions e(theta) around the current pose, J = de/dtheta, and picks a joint step for the
 * error vector (targets minus effectors, each goal's part clamped to a largest step, as Buss
 * advises, so that the linear model is not trusted far away):
 *   - transpose:     dtheta = alpha J^T e, alpha = <e, J J^T e> / |J J^T e|^2;
 *   - pseudoinverse: dtheta = J^+ e through the SVD (one-sided Jacobi), singular values below
 *                    1e-2 x the largest taken as zero;
 *   - damped least squares: dtheta = J^T (J J^T + lambda^2 I)^-1 e, an m x m Cholesky solve
 *                    (m = 3 per goal), cheap however long the chain; lambda adapts as in
 *                    Levenberg-Marquardt (halved after a step that helps, down to 1e-3 x the
 *                    mean bone, quadrupled after one that does not), so that a stretched chain
 *                    still straightens fully.
 * All three share two safeguards: no joint turns more than 0.5 rad about an axis in one step,
 * and a step that makes the (weighted squared) error worse is halved, up to 6 times, before it
 * counts as a failure (a backtracking line search). Iterations count steps, not tries.
 * Degrees of freedom: three rotations about the world axes at each free joint, one about its
 * axis at a hinge. Every goal contributes three rows, scaled by the square root of its weight;
 * so several goals on a tree come naturally. Limits are kept by projecting each joint's new
 * rotation into them after the step (a clamping of the kind Buss discusses).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "jacobian.h"

typedef enum method { TRANSPOSE, PSEUDOINVERSE, DLS } method;

typedef struct jac_state {
    rf_ikc_work w; /* first: rf_ikc_state_free frees it */
    method how;
    double damping, max_step; /* 0: automatic, from the mean bone length */
    uint32_t cap_rows, cap_cols;
    double *J;      /* [rows][cols] row-major */
    double *e;      /* [rows] */
    double *y;      /* [rows] */
    double *S;      /* [rows][rows] */
    double *U;      /* [rows][rows] */
    double *sigma;  /* [rows] */
    double *B;      /* [rows][cols] */
    double *dtheta; /* [cols] */
    rf_vec3 *axis;  /* [cols] world axis of each degree of freedom */
    rf_quat *saved; /* [joints] local rotations before a step, to take it back */
    uint32_t cap_saved;
    uint32_t *col_joint; /* [cols] */
    /* per solve */
    uint32_t rows, cols;
    double lambda, step;
} jac_state;

#define GROW(ptr, count) ((ptr) = realloc((ptr), (size_t)(count) * sizeof *(ptr)))

static bool reserve(jac_state *st, uint32_t rows, uint32_t cols, uint32_t joints)
{
    if (joints > st->cap_saved) {
        if (!GROW(st->saved, joints))
            return false;
        st->cap_saved = joints;
    }
    if (rows > st->cap_rows) {
        if (!GROW(st->e, rows) || !GROW(st->y, rows) || !GROW(st->S, rows * rows) ||
            !GROW(st->U, rows * rows) || !GROW(st->sigma, rows))
            return false;
        st->cap_rows = rows;
        st->cap_cols = 0; /* J and B depend on both sizes */
    }
    if (cols > st->cap_cols) {
        size_t cells = (size_t)st->cap_rows * cols;
        if (!GROW(st->J, cells) || !GROW(st->B, cells) || !GROW(st->dtheta, cols) ||
            !GROW(st->axis, cols) || !GROW(st->col_joint, cols))
            return false;
        st->cap_cols = cols;
    }
    return true;
}

static void jac_free(void *state)
{
    jac_state *st = state;
    if (!st)
        return;
    free(st->J), free(st->e), free(st->y), free(st->S), free(st->U), free(st->sigma);
    free(st->B), free(st->dtheta), free(st->axis), free(st->col_joint), free(st->saved);
    rf_ikc_state_free(st);
}

static void *jac_create(const rf_ik_config *cfg, method how, char *err, size_t err_size)
{
    jac_state *st = rf_ikc_state_new(sizeof *st, cfg, err, err_size);
    if (!st)
        return NULL;
    st->how = how;
    if (cfg && RF_HAS_FIELD(cfg, rf_ik_config, max_step))
        st->damping = cfg->damping, st->max_step = cfg->max_step;
    uint32_t joints = rf_ikc_config_joints(cfg), goals = rf_ikc_config_goals(cfg);
    if (!reserve(st, 3 * goals, 3 * joints, joints)) {
        jac_free(st);
        snprintf(err, err_size, "out of memory");
        return NULL;
    }
    return st;
}

/* ---- one step ---- */

/* Columns: the degrees of freedom of every movable joint, with their world axes. */
static void build_columns(jac_state *st, rf_ikc_solve *s)
{
    uint32_t n = 0;
    for (uint32_t j = 0; j < s->n; j++) {
        if (!(s->w->flags[j] & RF_IKC_MOVABLE))
            continue;
        const rf_ik_constraint *c = rf_ikc_constraint(s->pb, j);
        if (c && (c->flags & RF_IK_LIMIT_HINGE)) {
            st->axis[n] = rf_ikc_hinge_axis_world(s, j), st->col_joint[n++] = j;
            continue;
        }
        for (int k = 0; k < 3; k++) {
            st->axis[n] = rf_v3(k == 0, k == 1, k == 2);
            st->col_joint[n++] = j;
        }
    }
    st->cols = n;
}

/* J (rotation about axis a at joint position p moves effector E by a x (E - p)) and e. */
static void build_system(jac_state *st, rf_ikc_solve *s)
{
    uint32_t m = st->rows, n = st->cols;
    for (uint32_t i = 0; i < s->goal_count; i++) {
        const rf_ik_goal *g = rf_ikc_goal(s->pb, i);
        double sw = sqrt(g->weight);
        rf_vec3 E = s->w->world[g->effector].t, d = rf_v3_sub(g->target, E);
        double len = rf_v3_len(d);
        if (len > st->step)
            d = rf_v3_scale(d, st->step / len);
        st->e[3 * i] = sw * d.x, st->e[3 * i + 1] = sw * d.y, st->e[3 * i + 2] = sw * d.z;
        for (uint32_t c = 0; c < n; c++) {
            uint32_t j = st->col_joint[c];
            rf_vec3 v = rf_v3(0, 0, 0);
            if ((s->w->goals[j] & (1ull << i)) && g->effector != j)
                v = rf_v3_scale(rf_v3_cross(st->axis[c], rf_v3_sub(E, s->w->world[j].t)), sw);
            st->J[(3 * i) * n + c] = v.x;
            st->J[(3 * i + 1) * n + c] = v.y;
            st->J[(3 * i + 2) * n + c] = v.z;
        }
    }
    (void)m;
}

/* out[rows] = J x[cols] */
static void mul_J(const jac_state *st, const double *x, double *out)
{
    for (uint32_t r = 0; r < st->rows; r++) {
        const double *row = st->J + (size_t)r * st->cols;
        double sum = 0;
        for (uint32_t c = 0; c < st->cols; c++)
            sum += row[c] * x[c];
        out[r] = sum;
    }
}

/* out[cols] = J^T y[rows] */
static void mul_Jt(const jac_state *st, const double *y, double *out)
{
    memset(out, 0, st->cols * sizeof *out);
    for (uint32_t r = 0; r < st->rows; r++) {
        const double *row = st->J + (size_t)r * st->cols;
        for (uint32_t c = 0; c < st->cols; c++)
            out[c] += row[c] * y[r];
    }
}

static void step_transpose(jac_state *st)
{
    mul_Jt(st, st->e, st->dtheta);
    mul_J(st, st->dtheta, st->y);
    double num = 0, den = 0;
    for (uint32_t r = 0; r < st->rows; r++)
        num += st->e[r] * st->y[r], den += st->y[r] * st->y[r];
    double alpha = den > 0 ? num / den : 0;
    for (uint32_t c = 0; c < st->cols; c++)
        st->dtheta[c] *= alpha;
}

static void step_dls(jac_state *st)
{
    uint32_t m = st->rows, n = st->cols;
    for (uint32_t a = 0; a < m; a++)
        for (uint32_t b = 0; b <= a; b++) {
            const double *ra = st->J + (size_t)a * n, *rb = st->J + (size_t)b * n;
            double s0 = 0, s1 = 0; /* two sums: half the dependency chain of one */
            uint32_t c = 0;
            for (; c + 1 < n; c += 2)
                s0 += ra[c] * rb[c], s1 += ra[c + 1] * rb[c + 1];
            if (c < n)
                s0 += ra[c] * rb[c];
            st->S[a * m + b] = st->S[b * m + a] = s0 + s1;
        }
    for (uint32_t a = 0; a < m; a++)
        st->S[a * m + a] += st->lambda * st->lambda, st->y[a] = st->e[a];
    if (!rf_ikc_cholesky_solve(st->S, st->y, (int)m))
        memset(st->y, 0, m * sizeof *st->y);
    mul_Jt(st, st->y, st->dtheta);
}

/* Singular values below this fraction of the largest count as zero. Tiny ones would make the
 * step all but one huge turn along a near-singular direction (a nearly straight chain), and the
 * turn clamp would then shrink the useful part of the step to nothing. */
#define PINV_CUTOFF 1e-2

static void step_pinv(jac_state *st)
{
    uint32_t m = st->rows, n = st->cols;
    rf_ikc_svd(st->J, (int)m, (int)n, st->B, st->U, st->sigma);
    double top = 0;
    for (uint32_t k = 0; k < m; k++)
        top = fmax(top, st->sigma[k]);
    memset(st->dtheta, 0, n * sizeof *st->dtheta);
    for (uint32_t k = 0; k < m; k++) {
        double sk = st->sigma[k];
        if (!(sk > PINV_CUTOFF * top))
            continue;
        double coef = 0; /* (u_k . e) / sigma_k^2: B's column k is sigma_k v_k */
        for (uint32_t r = 0; r < m; r++)
            coef += st->U[k * m + r] * st->e[r];
        coef /= sk * sk;
        for (uint32_t c = 0; c < n; c++)
            st->dtheta[c] += coef * st->B[(size_t)k * n + c];
    }
}

/* Scales the step down so no joint turns more than MAX_TURN about any axis: the linear model
 * holds only for small turns, and near a singularity (a stretched chain) all three methods can
 * ask for huge ones. */
#define MAX_TURN 0.5
static void clamp_step(jac_state *st)
{
    double largest = 0;
    for (uint32_t c = 0; c < st->cols; c++)
        largest = fabs(st->dtheta[c]) > largest ? fabs(st->dtheta[c]) : largest; /* no libm call */
    if (largest > MAX_TURN)
        for (uint32_t c = 0; c < st->cols; c++)
            st->dtheta[c] *= MAX_TURN / largest;
}

/* Turns every joint by its part of dtheta (world axes, all measured at the same pose), projects
 * into the limits, then recomputes world transforms. */
static void apply_step(jac_state *st, rf_ikc_solve *s, double scale)
{
    for (uint32_t c = 0; c < st->cols;) {
        uint32_t j = st->col_joint[c];
        rf_vec3 omega = rf_v3(0, 0, 0);
        for (; c < st->cols && st->col_joint[c] == j; c++)
            omega = rf_v3_add(omega, rf_v3_scale(st->axis[c], scale * st->dtheta[c]));
        double angle = rf_v3_len(omega);
        if (angle == 0)
            continue;
        /* A world-axis turn of joint j is, in its parent's frame, a turn about the axis seen
         * from the parent: local' = (parent^-1 omega) local. */
        rf_vec3 in_parent = rf_quat_rotate(rf_quat_conj(rf_ikc_parent_rot(s, j)), omega);
        double k = sin(0.5 * angle) / angle; /* the axis is omega / angle: no normalising */
        rf_quat turn =
            rf_quat_make(in_parent.x * k, in_parent.y * k, in_parent.z * k, cos(0.5 * angle));
        s->local[j].r = rf_ikc_constrain_local(s, j, rf_quat_mul(turn, s->local[j].r));
    }
    rf_ikc_fk(s);
}

/* The mean length of the bones on the goals' paths: the scale for damping and step clamps. */
static double mean_bone(const rf_ikc_solve *s)
{
    double sum = 0;
    uint32_t count = 0;
    for (uint32_t j = 0; j < s->n; j++)
        if ((s->w->flags[j] & RF_IKC_ON_PATH) && !(s->w->flags[j] & RF_IKC_PIVOT))
            sum += s->w->bone_len[j], count++;
    return count && sum > 0 ? sum / count : 1.0;
}

/* What the steps minimise: the weighted sum of squared position errors (w->err current). */
static double objective(const rf_ikc_solve *s)
{
    double sum = 0;
    for (uint32_t i = 0; i < s->goal_count; i++)
        sum += rf_ikc_goal(s->pb, i)->weight * s->w->err[i] * s->w->err[i];
    return sum;
}

static void compute_step(jac_state *st, rf_ikc_solve *s)
{
    build_columns(st, s);
    build_system(st, s);
    if (st->how == TRANSPOSE)
        step_transpose(st);
    else if (st->how == PSEUDOINVERSE)
        step_pinv(st);
    else
        step_dls(st);
    clamp_step(st);
}

/* Takes the step, halving it while it makes things worse (a backtracking line search: the
 * linear model can overshoot, most of all near singular poses). Returns false when even the
 * smallest try does not help: the pose is then unchanged. */
static bool take_step(jac_state *st, rf_ikc_solve *s, double *obj)
{
    for (uint32_t j = 0; j < s->n; j++)
        st->saved[j] = s->local[j].r;
    double scale = 1;
    for (int tries = 0; tries < 6; tries++, scale *= 0.5) {
        apply_step(st, s, scale);
        rf_ikc_errors(s);
        double now = objective(s);
        if (now < *obj) {
            *obj = now;
            return true;
        }
        for (uint32_t j = 0; j < s->n; j++)
            s->local[j].r = st->saved[j];
        rf_ikc_fk(s); /* the next try measures its turns from the pose it started at */
    }
    rf_ikc_errors(s);
    return false;
}

static uint32_t jac_iterate(jac_state *st, rf_ikc_solve *s, double lambda_min)
{
    double tol = s->pb->tolerance, err = rf_ikc_errors(s), obj = objective(s), best = err;
    uint32_t it = 0, stalled = 0;
    while (err > tol && it < s->pb->max_iterations) {
        compute_step(st, s);
        it++;
        bool better = take_step(st, s, &obj);
        /* Damping adapts as in Levenberg-Marquardt: less after a good step (faster, and a
         * stretched chain can straighten fully), more after a failed one. */
        st->lambda = better ? fmax(lambda_min, 0.5 * st->lambda) : 4 * st->lambda;
        err = rf_ikc_errors(s);
        stalled = err < best - 1e-12 * (1 + best) ? 0 : stalled + 1;
        best = fmin(best, err);
        if (stalled >= 10) /* unreachable or limit-bound: nothing left to gain */
            break;
    }
    return it;
}

static bool jac_solve(void *state, const rf_ik_problem *pb, rf_ik_result *res)
{
    jac_state *st = state;
    rf_ikc_solve s;
    if (!rf_ikc_begin(&s, pb, res, &st->w))
        return false;
    uint32_t cols = 0;
    for (uint32_t j = 0; j < s.n; j++)
        cols += (s.w->flags[j] & RF_IKC_MOVABLE) ? 3 : 0;
    st->rows = 3 * s.goal_count;
    if (!reserve(st, st->rows, cols, s.n)) {
        snprintf(res->message, sizeof res->message, "out of memory for %u joints", s.n);
        return false;
    }
    double bone = mean_bone(&s);
    st->step = st->max_step > 0 ? st->max_step : bone;
    st->lambda = st->damping > 0 ? st->damping : 0.1 * bone;
    double lambda_min = fmin(st->lambda, 1e-3 * bone);
    uint32_t it = 0;
    if (s.goal_count > 0 && cols > 0) {
        build_columns(st, &s);
        if (st->how == PSEUDOINVERSE && st->rows > st->cols) {
            /* The one-sided SVD works on the short side; so many goals on so few joints are
             * over-determined, which damped least squares handles. */
            st->how = DLS;
            it = jac_iterate(st, &s, lambda_min);
            st->how = PSEUDOINVERSE;
        } else {
            it = jac_iterate(st, &s, lambda_min);
        }
    }
    rf_ikc_finish(&s, it);
    return true;
}

static void *jt_create(const rf_ik_config *cfg, char *err, size_t n)
{
    return jac_create(cfg, TRANSPOSE, err, n);
}
static void *pinv_create(const rf_ik_config *cfg, char *err, size_t n)
{
    return jac_create(cfg, PSEUDOINVERSE, err, n);
}
static void *dls_create(const rf_ik_config *cfg, char *err, size_t n)
{
    return jac_create(cfg, DLS, err, n);
}

#define JAC_LIMITS (RF_IK_LIMIT_HINGE | RF_IK_LIMIT_CONE | RF_IK_LIMIT_TWIST | RF_IK_LOCKED)
#define JAC_CAPS (RF_IK_CAP_MULTI_GOAL | RF_IK_CAP_ORIENTATION)

const rf_ik_solver_api rf_ik_jt_api = {sizeof(rf_ik_solver_api),
                                       "jacobian-transpose",
                                       "Jacobian transpose (Buss)",
                                       JAC_LIMITS,
                                       JAC_CAPS,
                                       jt_create,
                                       jac_solve,
                                       jac_free};
const rf_ik_solver_api rf_ik_pinv_api = {sizeof(rf_ik_solver_api),
                                         "jacobian-pinv",
                                         "Jacobian pseudoinverse through the SVD (Buss)",
                                         JAC_LIMITS,
                                         JAC_CAPS,
                                         pinv_create,
                                         jac_solve,
                                         jac_free};
const rf_ik_solver_api rf_ik_dls_api = {sizeof(rf_ik_solver_api),
                                        "dls",
                                        "Jacobian damped least squares (Buss)",
                                        JAC_LIMITS,
                                        JAC_CAPS,
                                        dls_create,
                                        jac_solve,
                                        jac_free};
