/* Jacobian inverse kinematics after Buss ("Introduction to Inverse Kinematics with Jacobian
 * Transpose, Pseudoinverse and Damped Least Squares methods"): each step linearises the effector
 * positions e(theta) around the current pose, J = de/dtheta, and picks a joint step for the
 * error vector (targets minus effectors, each goal's part clamped to a largest step, as Buss
 * advises, so that the linear model is not trusted far away):
 *   - transpose:     dtheta = alpha J^T e, alpha = <e, J J^T e> / |J J^T e|^2;
 *   - pseudoinverse: dtheta = J^+ e through the SVD (one-sided Jacobi), singular values below
 *                    1e-2 x the largest taken as zero;
 *   - damped least squares: dtheta = J^T (J J^T + lambda^2 I)^-1 e, an m x m Cholesky solve
 *                    (m = 3 per goal; for one goal the 3 x 3 adjugate), cheap however long the
 *                    chain, with J J^T and J^T y summed joint by joint rather than through J;
 *                    lambda adapts as in Levenberg-Marquardt (halved after a step that helps,
 *                    down to 1e-3 x the mean bone, quadrupled after one that does not), so that
 *                    a stretched chain still straightens fully.
 * All three share two safeguards: no joint turns more than 0.5 rad about an axis in one step,
 * and a step that makes the (weighted squared) error worse is halved, up to 6 times, before it
 * counts as a failure (a backtracking line search). Iterations count steps, not tries.
 * Degrees of freedom: three rotations about the world axes at each free joint, one about its
 * axis at a hinge. Every goal contributes three rows, scaled by the square root of its weight;
 * so several goals on a tree come naturally. Limits are kept by projecting each joint's new
 * rotation into them after the step; a joint the step would push against its limits (losing most
 * of its turn to the projection) is pinned and the step worked out again without it.
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
    uint32_t *hinge_col; /* [cols] the columns of hinges, whose axes turn with their parents */
    uint32_t hinges;
    uint32_t *group; /* [cols + 1] each movable joint's first column, then cols: a joint
                      * with one column is a hinge, with three a free joint */
    uint32_t groups;
    bool *pinned; /* [joints] pressed against its limits by this step's turn: left out of it */
    /* per solve */
    uint32_t rows, cols;
    double lambda, step;
} jac_state;

#define GROW(ptr, count) ((ptr) = realloc((ptr), (size_t)(count) * sizeof *(ptr)))

static bool reserve(jac_state *st, uint32_t rows, uint32_t cols, uint32_t joints)
{
    if (joints > st->cap_saved) {
        if (!GROW(st->saved, joints) || !GROW(st->pinned, joints))
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
            !GROW(st->axis, cols) || !GROW(st->col_joint, cols) || !GROW(st->hinge_col, cols) ||
            !GROW(st->group, cols + 1))
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
    free(st->B), free(st->dtheta), free(st->axis), free(st->col_joint), free(st->hinge_col);
    free(st->group), free(st->saved), free(st->pinned);
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
    st->hinges = st->groups = 0;
    for (uint32_t j = 0; j < s->n; j++) {
        if (!(s->w->flags[j] & RF_IKC_MOVABLE))
            continue;
        st->group[st->groups++] = n;
        const rf_ik_constraint *c = rf_ikc_constraint(s->pb, j);
        if (c && (c->flags & RF_IK_LIMIT_HINGE)) {
            st->hinge_col[st->hinges++] = n;
            st->axis[n] = rf_ikc_hinge_axis_world(s, j), st->col_joint[n++] = j;
            continue;
        }
        for (int k = 0; k < 3; k++) {
            st->axis[n] = rf_v3(k == 0, k == 1, k == 2);
            st->col_joint[n++] = j;
        }
    }
    st->cols = st->group[st->groups] = n;
}

/* The hinges' world axes, which turn with their parents (the other columns' world axes are
 * fixed). */
static void refresh_hinge_axes(jac_state *st, rf_ikc_solve *s)
{
    for (uint32_t h = 0; h < st->hinges; h++) {
        uint32_t c = st->hinge_col[h];
        st->axis[c] = rf_ikc_hinge_axis_world(s, st->col_joint[c]);
    }
}

/* e: per goal, the way to its target, clamped to the largest step, times sqrt(weight). */
static void build_error(jac_state *st, rf_ikc_solve *s)
{
    for (uint32_t i = 0; i < s->goal_count; i++) {
        const rf_ik_goal *g = rf_ikc_goal(s->pb, i);
        double sw = sqrt(g->weight);
        rf_vec3 d = rf_v3_sub(g->target, s->w->world[g->effector].t);
        double len2 = rf_v3_len2(d); /* the square root only for a step to clamp */
        if (len2 > st->step * st->step)
            d = rf_v3_scale(d, st->step / sqrt(len2));
        st->e[3 * i] = sw * d.x, st->e[3 * i + 1] = sw * d.y, st->e[3 * i + 2] = sw * d.z;
    }
}

/* J (rotation about axis a at joint position p moves effector E by a x (E - p)). */
static void build_system(jac_state *st, rf_ikc_solve *s)
{
    uint32_t n = st->cols;
    for (uint32_t i = 0; i < s->goal_count; i++) {
        const rf_ik_goal *g = rf_ikc_goal(s->pb, i);
        double sw = sqrt(g->weight);
        rf_vec3 E = s->w->world[g->effector].t;
        for (uint32_t c = 0; c < n; c++) {
            uint32_t j = st->col_joint[c];
            rf_vec3 v = rf_v3(0, 0, 0);
            if ((s->w->goals[j] & (1ull << i)) && g->effector != j && !st->pinned[j])
                v = rf_v3_scale(rf_v3_cross(st->axis[c], rf_v3_sub(E, s->w->world[j].t)), sw);
            st->J[(3 * i) * n + c] = v.x;
            st->J[(3 * i + 1) * n + c] = v.y;
            st->J[(3 * i + 2) * n + c] = v.z;
        }
    }
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

/* ---- damped least squares without the Jacobian ----
 * J is never needed by itself: S = J J^T and J^T y can be summed joint by joint from the lever
 * arms r = E - p (effector less joint position). A free joint's three columns for goal i are
 * sqrt(w_i) (e_k x r), so its part of S's block (i, i') is sqrt(w_i w_i') ((r.r') I - r' r^T),
 * and its part of J^T y is sum_i sqrt(w_i) r x y_i; a hinge's column is sqrt(w_i) (a x r). That
 * is 9 products per joint and goal pair instead of 18 per joint and row pair, no J to write
 * and read back, and a 3 x 3 system solved in closed form for the usual single goal. */

/* The lever arms, times sqrt(weight), of each movable joint g for each goal i, at
 * lev[g * goals + i]; zero where the goal does not move the joint, which then adds nothing to
 * S or J^T y. They go where J would be (J is not needed). */
static rf_vec3 *levers(jac_state *st, rf_ikc_solve *s)
{
    uint32_t goals = s->goal_count;
    rf_vec3 *lev = (rf_vec3 *)st->J;
    for (uint32_t i = 0; i < goals; i++) {
        const rf_ik_goal *g = rf_ikc_goal(s->pb, i);
        rf_vec3 E = s->w->world[g->effector].t;
        double sw = sqrt(g->weight);
        for (uint32_t k = 0; k < st->groups; k++) {
            uint32_t j = st->col_joint[st->group[k]];
            bool moves = (s->w->goals[j] & (1ull << i)) && g->effector != j && !st->pinned[j];
            lev[k * goals + i] =
                moves ? rf_v3_scale(rf_v3_sub(E, s->w->world[j].t), sw) : rf_v3(0, 0, 0);
        }
    }
    return lev;
}

/* Adds joint g's part of S's block (a, b), a >= b, from its lever arms for goals a and b. */
static void add_block(jac_state *st, uint32_t g, uint32_t a, uint32_t b, rf_vec3 ra, rf_vec3 rb)
{
    uint32_t m = st->rows, c = st->group[g];
    double *S = st->S + (size_t)3 * a * m + 3 * b;
    rf_vec3 u, v; /* the block is d I + u v^T */
    double d = 0;
    if (st->group[g + 1] - c == 1) /* a hinge: (axis x ra)(axis x rb)^T */
        u = rf_v3_cross(st->axis[c], ra), v = rf_v3_cross(st->axis[c], rb);
    else /* free: (ra.rb) I - rb ra^T */
        d = rf_v3_dot(ra, rb), u = rf_v3_scale(rb, -1), v = ra;
    const double *x = &u.x, *y = &v.x;
    for (int p = 0; p < 3; p++)
        for (int q = 0; q < 3; q++)
            S[p * m + q] += x[p] * y[q];
    for (int p = 0; p < 3; p++)
        S[p * m + p] += d;
}

/* S = J J^T for a single goal: a symmetric 3 x 3, summed in registers. */
static void sum_normal_matrix_1(jac_state *st, const rf_vec3 *lev)
{
    double s00 = 0, s10 = 0, s11 = 0, s20 = 0, s21 = 0, s22 = 0;
    for (uint32_t g = 0; g < st->groups; g++) {
        uint32_t c = st->group[g];
        rf_vec3 r = lev[g];
        if (st->group[g + 1] - c == 1) { /* a hinge: (axis x r)(axis x r)^T */
            rf_vec3 u = rf_v3_cross(st->axis[c], r);
            s00 += u.x * u.x, s10 += u.y * u.x, s11 += u.y * u.y;
            s20 += u.z * u.x, s21 += u.z * u.y, s22 += u.z * u.z;
            continue;
        }
        double xx = r.x * r.x, yy = r.y * r.y, zz = r.z * r.z; /* |r|^2 I - r r^T */
        s00 += yy + zz, s11 += xx + zz, s22 += xx + yy;
        s10 -= r.y * r.x, s20 -= r.z * r.x, s21 -= r.z * r.y;
    }
    st->S[0] = s00, st->S[3] = s10, st->S[4] = s11, st->S[6] = s20, st->S[7] = s21;
    st->S[8] = s22;
}

/* S = J J^T, its lower triangle (what the Cholesky solve reads). */
static void sum_normal_matrix(jac_state *st, const rf_vec3 *lev, uint32_t goals)
{
    if (goals == 1) {
        sum_normal_matrix_1(st, lev);
        return;
    }
    uint32_t m = st->rows;
    memset(st->S, 0, (size_t)m * m * sizeof *st->S);
    for (uint32_t g = 0; g < st->groups; g++)
        for (uint32_t a = 0; a < goals; a++)
            for (uint32_t b = 0; b <= a; b++)
                add_block(st, g, a, b, lev[g * goals + a], lev[g * goals + b]);
}

/* dtheta = J^T y: per free joint sum_i r_i x y_i, per hinge sum_i (axis x r_i) . y_i. */
static void transpose_times(jac_state *st, const rf_vec3 *lev, uint32_t goals)
{
    for (uint32_t g = 0; g < st->groups; g++) {
        uint32_t c = st->group[g];
        rf_vec3 sum = rf_v3(0, 0, 0);
        for (uint32_t i = 0; i < goals; i++) {
            rf_vec3 y = rf_v3(st->y[3 * i], st->y[3 * i + 1], st->y[3 * i + 2]);
            sum = rf_v3_add(sum, rf_v3_cross(lev[g * goals + i], y));
        }
        if (st->group[g + 1] - c == 1) /* (axis x r) . y = axis . (r x y) */
            st->dtheta[c] = rf_v3_dot(st->axis[c], sum);
        else
            st->dtheta[c] = sum.x, st->dtheta[c + 1] = sum.y, st->dtheta[c + 2] = sum.z;
    }
}

/* Solves (S + lambda^2 I) y = e for a 3 x 3 S (one goal) by its adjugate: nine products in
 * parallel and one division, where a Cholesky factorisation chains three square roots and six
 * divisions. The matrix is symmetric positive definite (damped), and its conditioning is what
 * the damping keeps in check; the solve's error is of the order of the Cholesky one's. */
static bool solve3(const double *S, double lambda2, const double *e, double *y)
{
    double a = S[0] + lambda2, b = S[3], c = S[6], d = S[4] + lambda2, f = S[7];
    double g = S[8] + lambda2;
    double c00 = d * g - f * f, c01 = c * f - b * g, c02 = b * f - c * d;
    double c11 = a * g - c * c, c12 = b * c - a * f, c22 = a * d - b * b;
    double det = a * c00 + b * c01 + c * c02;
    if (!(det > 0) || !isfinite(det))
        return false;
    double k = 1.0 / det;
    y[0] = (c00 * e[0] + c01 * e[1] + c02 * e[2]) * k;
    y[1] = (c01 * e[0] + c11 * e[1] + c12 * e[2]) * k;
    y[2] = (c02 * e[0] + c12 * e[1] + c22 * e[2]) * k;
    return true;
}

static void step_dls_direct(jac_state *st, rf_ikc_solve *s)
{
    uint32_t m = st->rows;
    const rf_vec3 *lev = levers(st, s);
    sum_normal_matrix(st, lev, s->goal_count);
    bool ok;
    if (m == 3) {
        ok = solve3(st->S, st->lambda * st->lambda, st->e, st->y);
    } else {
        for (uint32_t a = 0; a < m; a++)
            st->S[a * m + a] += st->lambda * st->lambda, st->y[a] = st->e[a];
        ok = rf_ikc_cholesky_solve(st->S, st->y, (int)m);
    }
    if (!ok)
        memset(st->y, 0, m * sizeof *st->y);
    transpose_times(st, lev, s->goal_count);
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

/* sin(x) / x and cos(x) from x^2 (both are even), for x^2 <= 0.25 by their Taylor series to
 * x^14 and x^16 (the next terms are below 1e-19); libm's sin and cos beyond. A step turns each
 * joint by at most 0.5 rad about each axis, so by at most 0.87 rad, and the turn quaternion
 * needs half of that: the series serve every step, with no square root for the angle and no
 * library call (which was a tenth of a solve). */
static void half_turn(double x2, double *sinc, double *cosine)
{
    if (!(x2 <= 0.25)) {
        double x = sqrt(x2);
        *sinc = sin(x) / x, *cosine = cos(x);
        return;
    }
    double sn = -1.0 / 1307674368000, cn = 1.0 / 20922789888000; /* x^14 / 15!, x^16 / 16! */
    sn = sn * x2 + 1.0 / 6227020800, cn = cn * x2 - 1.0 / 87178291200;
    sn = sn * x2 - 1.0 / 39916800, cn = cn * x2 + 1.0 / 479001600;
    sn = sn * x2 + 1.0 / 362880, cn = cn * x2 - 1.0 / 3628800;
    sn = sn * x2 - 1.0 / 5040, cn = cn * x2 + 1.0 / 40320;
    sn = sn * x2 + 1.0 / 120, cn = cn * x2 - 1.0 / 720;
    sn = sn * x2 - 1.0 / 6, cn = cn * x2 + 1.0 / 24;
    *sinc = sn * x2 + 1, *cosine = (cn * x2 - 0.5) * x2 + 1;
}

/* Joint j's new local rotation when group g turns by its part of dtheta times scale (world
 * axes, measured at the current pose), before its limits. */
static rf_quat turned_local(const jac_state *st, rf_ikc_solve *s, uint32_t g, double scale)
{
    uint32_t c = st->group[g], j = st->col_joint[c];
    rf_vec3 omega =
        st->group[g + 1] - c == 1 /* a hinge, or a free joint's world axes */
            ? rf_v3_scale(st->axis[c], scale * st->dtheta[c])
            : rf_v3_scale(rf_v3(st->dtheta[c], st->dtheta[c + 1], st->dtheta[c + 2]), scale);
    double angle2 = rf_v3_len2(omega), k, cosine;
    if (angle2 == 0)
        return s->local[j].r;
    /* A world-axis turn of joint j is, in its parent's frame, a turn about the axis seen from the
     * parent: local' = (parent^-1 omega) local. */
    rf_vec3 in_parent = rf_quat_rotate(rf_quat_conj(rf_ikc_parent_rot(s, j)), omega);
    half_turn(0.25 * angle2, &k, &cosine);
    k *= 0.5; /* sin(angle / 2) / angle: the axis is omega / angle, no normalising */
    rf_quat turn = rf_quat_make(in_parent.x * k, in_parent.y * k, in_parent.z * k, cosine);
    return rf_quat_mul(turn, s->local[j].r);
}

/* Turns every joint by its part of dtheta (world axes, all measured at the same pose), projects
 * into the limits, then recomputes world transforms. */
static void apply_step(jac_state *st, rf_ikc_solve *s, double scale)
{
    for (uint32_t g = 0; g < st->groups; g++) {
        uint32_t j = st->col_joint[st->group[g]];
        rf_quat local = turned_local(st, s, g, scale);
        s->local[j].r = s->constrained ? rf_ikc_constrain_local(s, j, local) : local;
    }
    rf_ikc_fk(s);
}

/* A joint whose limits would take back more than this fraction of its turn is pinned. Measured
 * on the it50-lim workloads (0.2, 0.5 and 0.8 tried): 0.5 converged on the most targets. */
#define PIN_FRACTION 0.5

/* Pins the joints this step would push out of their limits (their projection taking back most
 * of their turn): they stay put, and the step is worked out again without them, so the free
 * joints take up what the pinned ones cannot (the clamping of joint limits Buss describes: a
 * joint at its limit is taken out of the Jacobian). Without it a joint pressed against its limit
 * kept absorbing its share of every step, which the projection then threw away. True when any
 * joint was pinned; pinned[] is all false before. */
static bool pin_limited(jac_state *st, rf_ikc_solve *s)
{
    bool any = false;
    for (uint32_t g = 0; g < st->groups; g++) {
        uint32_t j = st->col_joint[st->group[g]];
        if (!rf_ikc_constraint(s->pb, j))
            continue;
        rf_quat now = s->local[j].r, want = turned_local(st, s, g, 1);
        rf_quat kept = rf_ikc_constrain_local(s, j, want);
        double turn = rf_quat_angle(now, want), allowed = rf_quat_angle(now, kept);
        if (turn > 1e-12 && allowed < PIN_FRACTION * turn)
            st->pinned[j] = any = true;
    }
    return any;
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

static void compute_raw_step(jac_state *st, rf_ikc_solve *s)
{
    if (st->how == DLS && rf_ikc_fast_paths) {
        step_dls_direct(st, s);
    } else {
        build_system(st, s);
        if (st->how == TRANSPOSE)
            step_transpose(st);
        else if (st->how == PSEUDOINVERSE)
            step_pinv(st);
        else
            step_dls(st);
    }
    clamp_step(st);
}

static void compute_step(jac_state *st, rf_ikc_solve *s)
{
    refresh_hinge_axes(st, s);
    build_error(st, s);
    if (s->constrained)
        memset(st->pinned, 0, s->n * sizeof *st->pinned);
    compute_raw_step(st, s);
    if (s->constrained && pin_limited(st, s))
        compute_raw_step(st, s);
}

/* Takes the step, halving it while it makes things worse (a backtracking line search: the
 * linear model can overshoot, most of all near singular poses). Returns false when even the
 * smallest try does not help: the pose is then unchanged. Either way w->err is current after,
 * and *err its largest. */
static bool take_step(jac_state *st, rf_ikc_solve *s, double *obj, double *err)
{
    for (uint32_t j = 0; j < s->n; j++)
        st->saved[j] = s->local[j].r;
    double scale = 1;
    for (int tries = 0; tries < 6; tries++, scale *= 0.5) {
        apply_step(st, s, scale);
        double largest = rf_ikc_errors(s), now = objective(s);
        if (now < *obj) {
            *obj = now, *err = largest;
            return true;
        }
        for (uint32_t j = 0; j < s->n; j++)
            s->local[j].r = st->saved[j];
        rf_ikc_fk(s); /* the next try measures its turns from the pose it started at */
    }
    *err = rf_ikc_errors(s);
    return false;
}

static uint32_t jac_iterate(jac_state *st, rf_ikc_solve *s, double lambda_min)
{
    double tol = s->pb->tolerance, err = rf_ikc_errors(s), obj = objective(s), best = err;
    uint32_t it = 0, stalled = 0;
    while (err > tol && it < s->pb->max_iterations) {
        compute_step(st, s);
        it++;
        bool better = take_step(st, s, &obj, &err);
        /* Damping adapts as in Levenberg-Marquardt: less after a good step (faster, and a
         * stretched chain can straighten fully), more after a failed one. */
        st->lambda = better ? fmax(lambda_min, 0.5 * st->lambda) : 4 * st->lambda;
        stalled = err < best * (1 - 1e-12) ? 0 : stalled + 1; /* relative: any unit */
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
    memset(st->pinned, 0, s.n * sizeof *st->pinned); /* none: a free problem never pins */
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
    rf_ikc_finish_current(&s, it);
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
#define JAC_CAPS (RF_IK_CAP_MULTI_GOAL | RF_IK_CAP_ORIENTATION | RF_IK_CAP_POLE)

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
