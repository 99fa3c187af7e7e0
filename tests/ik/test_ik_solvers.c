/* Every IK solver against geometry: reachable targets are reached, unreachable ones give the
 * straight chain pointing at the target, limits hold, trees with two effectors, agreement between
 * solvers, bad goals refused. Expected values come from lengths and the law of cosines, never
 * from a solver's own output. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "ik-fixtures.h"
#include "solvers.h"

#define DEG (RF_PI / 180.0)

static void *make_state(const rf_ik_solver_api *api)
{
    char err[160] = "";
    void *st = api->create(NULL, err, sizeof err);
    if (!st)
        fail_msg("%s: create failed: %s", api->name, err);
    return st;
}

static bool handles_links(const rf_ik_solver_api *api, uint32_t links)
{
    return !(api->capabilities & RF_IK_CAP_TWO_BONE) || links == 2;
}

static void solve_ok(const rf_ik_solver_api *api, void *st, fx_problem *f)
{
    if (!api->solve(st, &f->pb, &f->res))
        fail_msg("%s refused a good problem: %s", api->name, f->res.message);
}

/* Distances between consecutive chain joints stay the link lengths. */
static void assert_rigid(const fx_problem *f, const char *name)
{
    rf_vec3 p[FX_MAX_JOINTS];
    fx_world(f, p, NULL);
    for (uint32_t j = 1; j < f->n; j++) {
        double want = rf_v3_len(f->pose[j].t), got = rf_v3_dist(p[j], p[f->parents[j]]);
        if (fabs(got - want) > 1e-9)
            fail_msg("%s: joint %u moved off its bone: %g instead of %g", name, j, got, want);
    }
}

static void test_reaches_reachable_targets(void **unused)
{
    (void)unused;
    static const uint32_t links[] = {2, 5, 10};
    for (size_t s = 0; s < SOLVER_COUNT; s++) {
        const rf_ik_solver_api *api = SOLVERS[s];
        void *st = make_state(api);
        for (size_t l = 0; l < 3; l++) {
            if (!handles_links(api, links[l]))
                continue;
            fx_lcg g = {99};
            for (int k = 0; k < 40; k++) {
                fx_problem f;
                fx_chain(&f, links[l]);
                /* Any distance in [0, n] is reachable with n >= 2 unit links. */
                f.goals[0].target = fx_target(&g, links[l]);
                fx_wire(&f, 1, 1e-4, 2000);
                solve_ok(api, st, &f);
                if (!(f.status[0] & RF_IK_REACHED) || !(f.errors[0] <= 1e-4) || !f.res.reached)
                    fail_msg("%s: %u links, target %d: error %g after %u iterations", api->name,
                             links[l], k, f.errors[0], f.res.iterations);
                assert_rigid(&f, api->name);
            }
        }
        api->destroy(st);
    }
}

static void test_unreachable_gives_stretched_pose(void **unused)
{
    (void)unused;
    /* 3 unit links, target 5 away: the best pose is the straight chain towards it, 2 short. */
    rf_vec3 dir = rf_v3(2.0 / 7, 3.0 / 7, 6.0 / 7);
    for (size_t s = 0; s < SOLVER_COUNT; s++) {
        const rf_ik_solver_api *api = SOLVERS[s];
        uint32_t links = handles_links(api, 3) ? 3 : 2;
        void *st = make_state(api);
        fx_problem f;
        fx_chain(&f, links);
        f.goals[0].target = rf_v3_scale(dir, 5);
        fx_wire(&f, 1, 1e-3, 2000);
        solve_ok(api, st, &f);
        assert_true(f.status[0] & RF_IK_UNREACHABLE);
        assert_false(f.status[0] & RF_IK_REACHED);
        assert_false(f.res.reached);
        if (fabs(f.errors[0] - (5.0 - links)) > 1e-3)
            fail_msg("%s: error %g, the stretched chain is %g short", api->name, f.errors[0],
                     5.0 - links);
        /* A chain of length L whose joints stray h from the line is at least 2 h^2 / L
         * shorter end to end: the shortfall bounds how far off the line any joint can be. */
        double shortfall = fmax(0, f.errors[0] - (5.0 - links));
        double h = sqrt(shortfall * links / 2) + 1e-6;
        rf_vec3 p[FX_MAX_JOINTS];
        fx_world(&f, p, NULL);
        for (uint32_t j = 1; j <= links; j++)
            if (rf_v3_dist(p[j], rf_v3_scale(dir, j)) > h)
                fail_msg("%s: joint %u at (%g %g %g), not on the line to the target", api->name, j,
                         p[j].x, p[j].y, p[j].z);
        api->destroy(st);
    }
}

/* A 5-link chain with every kind of limit. */
static void limited_chain(fx_problem *f)
{
    fx_chain(f, 5);
    rf_ik_constraint *c = f->limits;
    c[0].flags = RF_IK_LIMIT_CONE | RF_IK_LIMIT_TWIST;
    c[0].cone_angle = 100 * DEG, c[0].twist_min = -60 * DEG, c[0].twist_max = 60 * DEG;
    c[1].flags = RF_IK_LIMIT_HINGE, c[1].axis = rf_v3(1, 0, 0);
    c[1].min_angle = 0, c[1].max_angle = 120 * DEG;
    c[2].flags = RF_IK_LIMIT_CONE | RF_IK_LIMIT_TWIST;
    c[2].cone_angle = 45 * DEG, c[2].twist_min = -30 * DEG, c[2].twist_max = 30 * DEG;
    c[3].flags = RF_IK_LIMIT_HINGE, c[3].axis = rf_v3(0, 0, 1);
    c[3].min_angle = -90 * DEG, c[3].max_angle = 30 * DEG;
    c[4].flags = RF_IK_LIMIT_CONE, c[4].cone_angle = 60 * DEG;
}

static void assert_limits_hold(const fx_problem *f, const rf_ik_solver_api *api, uint32_t only)
{
    for (uint32_t j = 0; j < f->n; j++) {
        rf_ik_constraint c = f->limits[j];
        c.flags &= only;
        double v = fx_limit_violation(&c, rf_v3(0, 1, 0), f->pose[j].r, f->out[j].r);
        if (v > 1e-6)
            fail_msg("%s: joint %u is %g rad outside its limits", api->name, j, v);
    }
}

static void test_limits_hold_after_solves(void **unused)
{
    (void)unused;
    for (size_t s = 0; s < SOLVER_COUNT; s++) {
        const rf_ik_solver_api *api = SOLVERS[s];
        void *st = make_state(api);
        fx_lcg g = {7};
        for (int k = 0; k < 40; k++) {
            fx_problem f;
            if (handles_links(api, 5)) {
                limited_chain(&f);
                f.goals[0].target = fx_target(&g, 5);
            } else { /* two-bone: a hinged elbow */
                fx_chain(&f, 2);
                f.limits[1].flags = RF_IK_LIMIT_HINGE, f.limits[1].axis = rf_v3(1, 0, 0);
                f.limits[1].min_angle = 10 * DEG, f.limits[1].max_angle = 120 * DEG;
                f.goals[0].target = fx_target(&g, 2);
            }
            fx_wire(&f, 1, 1e-3, 200);
            solve_ok(api, st, &f);
            assert_limits_hold(&f, api, api->limits);
            assert_rigid(&f, api->name);
        }
        api->destroy(st);
    }
}

static void test_tree_with_two_effectors(void **unused)
{
    (void)unused;
    for (size_t s = 0; s < SOLVER_COUNT; s++) {
        const rf_ik_solver_api *api = SOLVERS[s];
        if (!(api->capabilities & RF_IK_CAP_MULTI_GOAL))
            continue;
        void *st = make_state(api);
        fx_lcg g = {99};
        int reached = 0;
        /* Slightly bent, as the DLS peer starts: a straight arm with its target right behind
         * it is a stationary point of the Jacobian methods' error (the transpose stalls there). */
        rf_quat bent = rf_quat_mul(rf_quat_from_axis_angle(rf_v3(0, 0, 1), 0.1),
                                   rf_quat_from_axis_angle(rf_v3(1, 0, 0), 0.15));
        for (int k = 0; k < 40; k++) {
            fx_problem f;
            fx_tree(&f);
            for (uint32_t j = 0; j < f.n; j++)
                if (j != 3)
                    f.pose[j].r = bent;
            /* within 0.9 x 3 of each arm's base: reachable by the arms alone */
            f.goals[0].target = rf_v3_add(rf_v3(1, 3, 0), fx_target(&g, 3));
            f.goals[1].target = rf_v3_add(rf_v3(-1, 3, 0), fx_target(&g, 3));
            fx_wire(&f, 2, 1e-3, 500);
            solve_ok(api, st, &f);
            reached += f.res.reached;
            assert_limits_hold(&f, api, RF_IK_LOCKED); /* the chest stays rigid */
            assert_rigid(&f, api->name);
            assert_true(f.res.max_error >= f.errors[0] && f.res.max_error >= f.errors[1]);
        }
        if (reached < 38)
            fail_msg("%s: both arms reached in only %d of 40 trees", api->name, reached);
        api->destroy(st);
    }
}

static void test_solvers_agree_on_reachable_targets(void **unused)
{
    (void)unused;
    fx_lcg g = {3};
    for (int k = 0; k < 20; k++) {
        rf_vec3 target = fx_target(&g, 2), first = {0, 0, 0};
        for (size_t s = 0; s < SOLVER_COUNT; s++) {
            void *st = make_state(SOLVERS[s]);
            fx_problem f;
            fx_chain(&f, 2);
            f.goals[0].target = target;
            fx_wire(&f, 1, 1e-5, 2000);
            solve_ok(SOLVERS[s], st, &f);
            rf_vec3 p[FX_MAX_JOINTS];
            fx_world(&f, p, NULL);
            if (s == 0)
                first = p[2];
            if (rf_v3_dist(p[2], first) > 2e-5 || rf_v3_dist(p[2], target) > 1e-5)
                fail_msg("%s disagrees on target %d", SOLVERS[s]->name, k);
            /* Two unit links: the elbow is 1 from the root and 1 from the target, so it sits
             * on the circle at half the distance (isosceles triangle). */
            double d = rf_v3_len(target);
            assert_float_equal(rf_v3_dot(p[1], rf_v3_scale(target, 1 / d)), d / 2, 1e-4);
            SOLVERS[s]->destroy(st);
        }
    }
}

static void expect_refusal(const rf_ik_solver_api *api, void *st, fx_problem *f, const char *what)
{
    memset(f->out, 0x5a, sizeof f->out);
    unsigned char before[sizeof f->out];
    memcpy(before, f->out, sizeof before);
    if (api->solve(st, &f->pb, &f->res))
        fail_msg("%s accepted %s", api->name, what);
    if (!strstr(f->res.message, what))
        fail_msg("%s: message '%s' does not say '%s'", api->name, f->res.message, what);
    assert_memory_equal(before, f->out, sizeof before);
}

static void test_bad_goals_are_refused(void **unused)
{
    (void)unused;
    for (size_t s = 0; s < SOLVER_COUNT; s++) {
        const rf_ik_solver_api *api = SOLVERS[s];
        void *st = make_state(api);
        fx_problem f;
        fx_chain(&f, 2);
        f.goals[0].target = rf_v3(NAN, 0, 0);
        fx_wire(&f, 1, 1e-3, 10);
        expect_refusal(api, st, &f, "not finite");
        fx_chain(&f, 2);
        f.goals[0].effector = 99;
        fx_wire(&f, 1, 1e-3, 10);
        expect_refusal(api, st, &f, "does not exist");
        fx_chain(&f, 2);
        f.goals[0].weight = 0;
        fx_wire(&f, 1, 1e-3, 10);
        expect_refusal(api, st, &f, "weight");
        fx_chain(&f, 2);
        f.goals[0].target = rf_v3(0.5, 0.5, 0);
        fx_wire(&f, 1, NAN, 10);
        expect_refusal(api, st, &f, "tolerance");
        /* finite but beyond what squared distances hold (1e31 squared twice overflows) */
        fx_chain(&f, 2);
        f.goals[0].target = rf_v3(0, 1e31, 0);
        fx_wire(&f, 1, 1e-3, 10);
        expect_refusal(api, st, &f, "out of range");
        fx_chain(&f, 2);
        f.goals[0].flags = RF_IK_GOAL_POLE, f.goals[0].pole = rf_v3(-1e300, 0, 0);
        fx_wire(&f, 1, 1e-3, 10);
        expect_refusal(api, st, &f, "out of range");
        fx_chain(&f, 2);
        f.pose[2].t = rf_v3(0, 2e30, 0);
        fx_wire(&f, 1, 1e-3, 10);
        expect_refusal(api, st, &f, "joint 2: the start pose puts it up to");
        fx_chain(&f, 2); /* each scale in range, their product not */
        f.pose[0].s = f.pose[1].s = rf_v3(1e20, 1e20, 1e20);
        fx_wire(&f, 1, 1e-3, 10);
        expect_refusal(api, st, &f, "joint 1: the start pose puts it up to");
        api->destroy(st);
    }
}

static void test_orientation_goal_turns_the_effector(void **unused)
{
    (void)unused;
    rf_quat want = rf_quat_from_axis_angle(rf_v3(1, 1, 0), 0.7);
    for (size_t s = 0; s < SOLVER_COUNT; s++) {
        const rf_ik_solver_api *api = SOLVERS[s];
        if (!(api->capabilities & RF_IK_CAP_ORIENTATION))
            continue;
        void *st = make_state(api);
        fx_problem f;
        fx_chain(&f, 2);
        f.goals[0].target = rf_v3(0.8, 1.1, 0.3);
        f.goals[0].flags = RF_IK_GOAL_ORIENTATION;
        f.goals[0].orientation = want;
        fx_wire(&f, 1, 1e-4, 500);
        solve_ok(api, st, &f);
        rf_quat r[FX_MAX_JOINTS];
        fx_world(&f, NULL, r);
        rf_quat diff = rf_quat_mul(rf_quat_conj(r[2]), want); /* its vector part: sin(angle/2) */
        assert_true(rf_v3_len(rf_v3(diff.x, diff.y, diff.z)) < 1e-9);
        assert_true(f.angle_errors[0] < 1e-9);
        assert_true(f.status[0] & RF_IK_REACHED);
        api->destroy(st);
    }
}

static void test_solves_in_place(void **unused)
{
    (void)unused;
    for (size_t s = 0; s < SOLVER_COUNT; s++) {
        const rf_ik_solver_api *api = SOLVERS[s];
        void *st = make_state(api);
        fx_problem f;
        fx_chain(&f, 2);
        f.goals[0].target = rf_v3(1.2, 0.4, -0.3);
        fx_wire(&f, 1, 1e-4, 500);
        f.res.pose = f.pose; /* the start pose array is also the output */
        solve_ok(api, st, &f);
        memcpy(f.out, f.pose, sizeof f.out);
        rf_vec3 p[FX_MAX_JOINTS];
        fx_world(&f, p, NULL);
        assert_true(rf_v3_dist(p[2], f.goals[0].target) <= 1e-4);
        api->destroy(st);
    }
}

/* Upper arm 3, forearm 2, target 4 from the shoulder along +y, pole towards +z. */
static void test_twobone_follows_the_law_of_cosines(void **unused)
{
    (void)unused;
    const double a = 3, b = 2, d = 4, lengths[2] = {3, 2};
    void *st = make_state(&rf_ik_twobone_api);
    fx_problem f;
    fx_chain_lengths(&f, lengths, 2);
    f.goals[0].target = rf_v3(0, d, 0);
    f.goals[0].flags = RF_IK_GOAL_POLE;
    f.goals[0].pole = rf_v3(0, 0, 5);
    fx_wire(&f, 1, 1e-9, 1);
    solve_ok(&rf_ik_twobone_api, st, &f);
    rf_vec3 p[FX_MAX_JOINTS];
    fx_world(&f, p, NULL);
    /* The elbow is a from the shoulder and b from the target: along the target line at
     * x = (a^2 - b^2 + d^2) / 2d, off it by sqrt(a^2 - x^2), on the pole's side. */
    double x = (a * a - b * b + d * d) / (2 * d), h = sqrt(a * a - x * x);
    assert_float_equal(p[1].x, 0, 1e-9);
    assert_float_equal(p[1].y, x, 1e-9);
    assert_float_equal(p[1].z, h, 1e-9);
    assert_true(rf_v3_dist(p[2], f.goals[0].target) < 1e-9);
    /* the elbow's inner angle, by the law of cosines */
    double inner = rf_v3_angle(rf_v3_sub(p[0], p[1]), rf_v3_sub(p[2], p[1]));
    assert_float_equal(inner, acos((a * a + b * b - d * d) / (2 * a * b)), 1e-9);
    assert_int_equal(f.res.iterations, 1);
    /* Pole on the other side: the mirror image. */
    f.goals[0].pole = rf_v3(0, 1, -5);
    fx_wire(&f, 1, 1e-9, 1);
    solve_ok(&rf_ik_twobone_api, st, &f);
    fx_world(&f, p, NULL);
    assert_float_equal(p[1].z, -h, 1e-9);
    /* Too short a chain for the target: straight towards it, flagged. */
    f.goals[0].target = rf_v3(0, 7, 0);
    fx_wire(&f, 1, 1e-9, 1);
    solve_ok(&rf_ik_twobone_api, st, &f);
    fx_world(&f, p, NULL);
    assert_true(rf_v3_dist(p[2], rf_v3(0, 5, 0)) < 1e-9);
    assert_true(f.status[0] & RF_IK_UNREACHABLE);
    rf_ik_twobone_api.destroy(st);
}

/* The angle, about the line from joint h to the effector e, between the chain's bend (its inner
 * joints' offsets from that line, summed) and the pole: worked out here from positions alone. */
static double pole_miss(const fx_problem *f, uint32_t h, uint32_t e, rf_vec3 pole)
{
    rf_vec3 p[FX_MAX_JOINTS];
    fx_world(f, p, NULL);
    rf_vec3 a = rf_v3_normalize(rf_v3_sub(p[e], p[h])), bend = {0, 0, 0};
    for (int32_t j = f->parents[e]; j != (int32_t)h; j = f->parents[j])
        bend = rf_v3_add(bend, rf_v3_sub(p[j], p[h]));
    rf_vec3 to_pole = rf_v3_sub(pole, p[h]);
    bend = rf_v3_sub(bend, rf_v3_scale(a, rf_v3_dot(bend, a)));
    to_pole = rf_v3_sub(to_pole, rf_v3_scale(a, rf_v3_dot(to_pole, a)));
    return rf_v3_angle(bend, to_pole);
}

/* With a pole, every solver bends the chain towards it (a two-bone limb, a 4-link chain, one arm
 * of the tree), still reaching the target; the other arm is left where it was. */
static void test_every_solver_honours_the_pole(void **unused)
{
    (void)unused;
    static const double lengths[2] = {3, 2};
    for (size_t s = 0; s < SOLVER_COUNT; s++) {
        const rf_ik_solver_api *api = SOLVERS[s];
        assert_true(api->capabilities & RF_IK_CAP_POLE);
        void *st = make_state(api);
        fx_lcg g = {5};
        for (int k = 0; k < 40; k++) {
            static fx_problem f;
            uint32_t links = k % 2 || !handles_links(api, 4) ? 2 : 4;
            double unit = k < 30 ? 1 : 1e-9; /* the last ones in nanometres: no absolute limits */
            double scaled[2] = {lengths[0] * unit, lengths[1] * unit};
            if (links == 2)
                fx_chain_lengths(&f, scaled, 2); /* reach: 1 to 5 units from the root */
            else
                fx_chain(&f, 4);
            for (uint32_t j = 1; j <= links; j++)
                f.pose[j].t = rf_v3_scale(f.pose[j].t, links == 4 ? unit : 1);
            for (uint32_t j = 1; j < links; j++) /* slightly bent, as in the tree test */
                f.pose[j].r = rf_quat_from_axis_angle(rf_v3(0.3, 0.5, 1), 0.2);
            f.goals[0].target = fx_target(&g, links == 2 ? 5 : 4);
            if (rf_v3_len(f.goals[0].target) < 1.2) /* the two-bone chain cannot fold closer */
                f.goals[0].target = rf_v3_scale(rf_v3_normalize(f.goals[0].target), 1.2);
            f.goals[0].target = rf_v3_scale(f.goals[0].target, unit);
            f.goals[0].flags = RF_IK_GOAL_POLE;
            f.goals[0].pole = rf_v3_scale(fx_target(&g, 1), 10 * unit);
            fx_wire(&f, 1, 1e-6 * unit, 500);
            solve_ok(api, st, &f);
            double miss = pole_miss(&f, 0, links, f.goals[0].pole);
            if (!(f.status[0] & RF_IK_REACHED) || miss > 1e-6)
                fail_msg("%s, %u links of %g, target %d: error %g, bend %g rad from the pole",
                         api->name, links, unit, k, f.errors[0], miss);
            if (unit == 1)
                assert_rigid(&f, api->name);
        }
        if (api->capabilities & RF_IK_CAP_MULTI_GOAL) {
            static fx_problem f, plain;
            fx_tree(&f);
            f.goals[0].target = rf_v3(2.5, 4, 1), f.goals[1].target = rf_v3(-2.5, 4, 1);
            plain = f;
            f.goals[0].flags = RF_IK_GOAL_POLE, f.goals[0].pole = rf_v3(2, 3, -5);
            fx_wire(&f, 2, 1e-6, 500);
            fx_wire(&plain, 2, 1e-6, 500);
            solve_ok(api, st, &f);
            solve_ok(api, st, &plain);
            rf_vec3 p[FX_MAX_JOINTS], q[FX_MAX_JOINTS];
            fx_world(&f, p, NULL);
            fx_world(&plain, q, NULL);
            double miss = pole_miss(&f, 4, 7, f.goals[0].pole); /* the left arm from its base */
            if (!f.res.reached || miss > 1e-6 || rf_v3_dist(p[11], q[11]) > 1e-9)
                fail_msg("%s, tree: error %g, bend %g rad from the pole, right arm moved %g",
                         api->name, f.res.max_error, miss, rf_v3_dist(p[11], q[11]));
        }
        api->destroy(st);
    }
}

/* A pole the swivel joint's limits do not allow is not met at the cost of the target: the hip
 * (a 10-degree cone) cannot swing the knee to the other side, so the leg stays as solved, its
 * foot on the target. */
static void test_a_pole_never_costs_reach(void **unused)
{
    (void)unused;
    static const double lengths[2] = {3, 2};
    for (size_t s = 0; s < SOLVER_COUNT; s++) {
        const rf_ik_solver_api *api = SOLVERS[s];
        void *st = make_state(api);
        static fx_problem f;
        fx_chain_lengths(&f, lengths, 2);
        /* bent at the start: the foot at (3 + 2 cos 0.6, 0, 2 sin 0.6), so the hip-foot line
         * rises towards +z and the knee, at (3, 0, 0), is on its -z side */
        f.pose[1].r = rf_quat_from_axis_angle(rf_v3(0, 1, 0), -0.6);
        f.limits[0].size = sizeof f.limits[0];
        f.limits[0].flags = RF_IK_LIMIT_CONE, f.limits[0].cone_angle = 10 * DEG;
        rf_vec3 foot = rf_v3(3 + 2 * cos(0.6), 0, 2 * sin(0.6));
        f.goals[0].target = rf_v3_scale(foot, 0.98); /* a little closer, along the same line */
        f.goals[0].flags = RF_IK_GOAL_POLE;
        f.goals[0].pole = rf_v3(0, 0, 10); /* the knee (now at -z) would swing half a turn */
        fx_wire(&f, 1, 1e-6, 500);
        solve_ok(api, st, &f);
        double v = fx_limit_violation(&f.limits[0], rf_v3(1, 0, 0), f.pose[0].r, f.out[0].r);
        if (!(f.status[0] & RF_IK_REACHED) || v > 1e-6)
            fail_msg("%s: error %g, hip %g rad outside its cone", api->name, f.errors[0], v);
        api->destroy(st);
    }
}

/* The same problem in another unit gives the same rotations: nothing in a solver may depend on
 * the size of the numbers (a threshold of 1e-12 on a length, say), only on their ratios. Free
 * and limited chains with a pole, in nanometres and in gigametres against metres. */
static void test_solvers_work_in_any_unit(void **unused)
{
    (void)unused;
    static const double units[2] = {1e-9, 1e9};
    for (size_t s = 0; s < SOLVER_COUNT; s++) {
        const rf_ik_solver_api *api = SOLVERS[s];
        void *st = make_state(api);
        fx_lcg g = {23};
        for (int k = 0; k < 24; k++) {
            static fx_problem base, f;
            uint32_t links = handles_links(api, 5) ? (k % 2 ? 5 : 3) : 2;
            if (links == 5 && k % 4 == 1)
                limited_chain(&base);
            else
                fx_chain(&base, links);
            for (uint32_t j = 1; j < links; j++)
                base.pose[j].r = rf_quat_from_axis_angle(rf_v3(0.3, 0.5, 1), 0.2);
            base.goals[0].target = fx_target(&g, links);
            base.goals[0].flags = k % 3 ? RF_IK_GOAL_POLE : 0;
            base.goals[0].pole = rf_v3_scale(fx_target(&g, 1), 10);
            fx_wire(&base, 1, 1e-6, 100);
            solve_ok(api, st, &base);
            for (int u = 0; u < 2; u++) {
                f = base;
                for (uint32_t j = 0; j < f.n; j++)
                    f.pose[j].t = rf_v3_scale(f.pose[j].t, units[u]);
                f.goals[0].target = rf_v3_scale(f.goals[0].target, units[u]);
                f.goals[0].pole = rf_v3_scale(f.goals[0].pole, units[u]);
                fx_wire(&f, 1, 1e-6 * units[u], 100);
                solve_ok(api, st, &f);
                double worst = 0;
                for (uint32_t j = 0; j < f.n; j++)
                    worst = fmax(worst, rf_quat_angle(f.out[j].r, base.out[j].r));
                /* Short of a limit-bound target, the steps of a Jacobian method may part at a
                 * pinning decision that rounding tips either way: the same error, other poses. */
                bool reached = base.status[0] & RF_IK_REACHED;
                if ((reached && worst > 1e-5) || f.status[0] != base.status[0] ||
                    fabs(f.errors[0] / units[u] - base.errors[0]) > 1e-4 * (1 + base.errors[0]))
                    fail_msg("%s, %u links, problem %d, unit %g: rotations %g rad apart, status "
                             "%u against %u, error %g against %g",
                             api->name, links, k, units[u], worst, f.status[0], base.status[0],
                             f.errors[0] / units[u], base.errors[0]);
            }
        }
        api->destroy(st);
    }
}

static void test_twobone_refuses_other_chains(void **unused)
{
    (void)unused;
    void *st = make_state(&rf_ik_twobone_api);
    fx_problem f;
    fx_chain(&f, 3);
    f.goals[0].target = rf_v3(1, 1, 0);
    fx_wire(&f, 1, 1e-3, 1);
    expect_refusal(&rf_ik_twobone_api, st, &f, "chain of 2 bones");
    f.goals[0].chain_root = 1; /* the last two bones of the three */
    fx_wire(&f, 1, 1e-3, 1);
    solve_ok(&rf_ik_twobone_api, st, &f);
    rf_ik_twobone_api.destroy(st);
}

/* A state made for 2 joints and 1 goal grows for bigger problems instead of failing them. */
static void test_states_grow_past_their_config(void **unused)
{
    (void)unused;
    rf_ik_config cfg = {sizeof cfg, 2, 1, 0, 0};
    for (size_t s = 0; s < SOLVER_COUNT; s++) {
        const rf_ik_solver_api *api = SOLVERS[s];
        char err[160];
        void *st = api->create(&cfg, err, sizeof err);
        assert_non_null(st);
        fx_problem f;
        uint32_t links = handles_links(api, 10) ? 10 : 2;
        fx_chain(&f, links);
        f.goals[0].target = rf_v3(0.5, 0.3 * links, 0.2);
        fx_wire(&f, 1, 1e-4, 2000);
        solve_ok(api, st, &f);
        assert_true(f.res.reached);
        if (api->capabilities & RF_IK_CAP_MULTI_GOAL) {
            fx_tree(&f);
            f.goals[0].target = rf_v3(1.5, 4.5, 0.5);
            f.goals[1].target = rf_v3(-1.5, 4.5, 0.5);
            fx_wire(&f, 2, 1e-4, 2000);
            solve_ok(api, st, &f);
            assert_int_equal(f.res.size, sizeof f.res);
        }
        api->destroy(st);
    }
}

/* ---- fast paths against general forms ---- */

/* The start poses the fast-path tests try: the straight chain; each joint turned a little
 * (random axes, up to 0.6 rad) and scaled 0.8 to 1.2; and a zig-zag folded back on itself,
 * whose first turns are nearly half turns. */
enum start_kind { STRAIGHT, BENT, FOLDED };

static void shaped_chain(fx_problem *f, uint32_t links, enum start_kind kind, fx_lcg *g)
{
    fx_chain(f, links);
    for (uint32_t j = 0; kind == BENT && j <= links; j++) {
        rf_vec3 axis = rf_v3(fx_rnd(g) - 0.5, fx_rnd(g) - 0.5, fx_rnd(g) - 0.5);
        f->pose[j].r = rf_quat_from_axis_angle(axis, 0.6 * fx_rnd(g));
        double k = 0.8 + 0.4 * fx_rnd(g);
        f->pose[j].s = rf_v3(k, k, k);
    }
    for (uint32_t j = 1; kind == FOLDED && j < links; j++) /* each link back along the last */
        f->pose[j].r = rf_quat_from_axis_angle(rf_v3(0.01 * j, 0, 1), RF_PI * (1 - 1e-7 * j));
}

/* Solves f with the fast paths on or off; its outputs stay in f. */
static void solve_with(const rf_ik_solver_api *api, void *st, fx_problem *f, bool fast)
{
    rf_ikc_fast_paths = fast;
    solve_ok(api, st, f);
    rf_ikc_fast_paths = true;
}

/* Largest distance between the joints of two solved poses of the same problem, and the largest
 * angle between their world rotations. */
static void compare_poses(const fx_problem *a, const fx_problem *b, double *dist, double *angle)
{
    static rf_vec3 pa[FX_MAX_JOINTS], pb[FX_MAX_JOINTS];
    static rf_quat ra[FX_MAX_JOINTS], rb[FX_MAX_JOINTS];
    fx_world(a, pa, ra);
    fx_world(b, pb, rb);
    *dist = *angle = 0;
    for (uint32_t j = 0; j < a->n; j++) {
        *dist = fmax(*dist, rf_v3_dist(pa[j], pb[j]));
        *angle = fmax(*angle, rf_quat_angle(ra[j], rb[j]));
    }
}

/* One problem solved by the fast path and by the general form. CCD's two forms make the same
 * turns, so they agree on iterations, positions and rotations; FABRIK's general form works on
 * rotations where the fast path works on positions, so they agree on positions (not on the roll
 * of each bone) and iterations where the target is reachable. Where it is not, the fast path puts
 * the chain straight at once, the general form iterates until it stops gaining or reaches the
 * cap, a little short of straight: the fast path's error is never the larger. */
static void check_agreement(const rf_ik_solver_api *api, void *st, const fx_problem *f,
                            const char *what, bool scaled)
{
    static fx_problem fast, slow;
    fast = *f, slow = *f;
    fx_wire(&fast, 1, f->pb.tolerance, f->pb.max_iterations);
    fx_wire(&slow, 1, f->pb.tolerance, f->pb.max_iterations);
    solve_with(api, st, &fast, true);
    solve_with(api, st, &slow, false);
    bool ccd = !strcmp(api->name, "ccd");
    bool reachable = !(slow.status[0] & RF_IK_UNREACHABLE);
    double dist, angle, scale = f->n;
    compare_poses(&fast, &slow, &dist, &angle);
    if ((ccd || reachable) && fast.res.iterations != slow.res.iterations)
        fail_msg("%s, %s: %u iterations on the fast path, %u on the general one", api->name, what,
                 fast.res.iterations, slow.res.iterations);
    double tol_dist = 1e-9 * scale;
    bool worse = ccd || reachable ? fabs(fast.errors[0] - slow.errors[0]) > tol_dist
                                  : fast.errors[0] > slow.errors[0] + tol_dist;
    if (fast.status[0] != slow.status[0] || worse)
        fail_msg("%s, %s: status %u, error %g on the fast path; %u, %g on the general one",
                 api->name, what, fast.status[0], fast.errors[0], slow.status[0], slow.errors[0]);
    if (((ccd || reachable) && dist > tol_dist) || (ccd && angle > 1e-9 * scale))
        fail_msg("%s, %s: the poses differ by %g (positions), %g rad (rotations)", api->name, what,
                 dist, angle);
    if (!scaled) /* assert_rigid takes bones to be as long as their offsets */
        assert_rigid(&fast, api->name);
}

static void test_fast_paths_agree_with_general_forms(void **unused)
{
    (void)unused;
    static const uint32_t links[] = {2, 3, 5, 10, 30};
    static const char *const kinds[] = {"straight", "bent", "folded"};
    const rf_ik_solver_api *apis[] = {&rf_ik_ccd_api, &rf_ik_fabrik_api};
    for (size_t s = 0; s < 2; s++) {
        void *st = make_state(apis[s]);
        fx_lcg g = {11};
        static fx_problem f;
        for (size_t l = 0; l < 5; l++)
            for (int kind = STRAIGHT; kind <= FOLDED; kind++)
                for (int k = 0; k < 12; k++) {
                    char what[80];
                    shaped_chain(&f, links[l], (enum start_kind)kind, &g);
                    /* the last targets out of reach; some goals turn only the lower links */
                    double reach = k < 10 ? links[l] : 1.5 * links[l];
                    f.goals[0].target = rf_v3_scale(fx_target(&g, 1), reach);
                    if (k % 3 == 2)
                        f.goals[0].chain_root = 1;
                    fx_wire(&f, 1, 1e-4, k % 2 ? 10 : 200);
                    snprintf(what, sizeof what, "%u links, %s, target %d", links[l], kinds[kind],
                             k);
                    check_agreement(apis[s], st, &f, what, kind == BENT);
                }
        apis[s]->destroy(st);
    }
}

/* Damped least squares sums J J^T and J^T y joint by joint instead of building J: the same
 * steps, so the same iterations and poses, on chains and on the tree, with free joints and
 * hinges (one on the spine, which both arms' goals move, so the hinge adds to S's off-diagonal
 * blocks). */
static void test_direct_dls_agrees_with_the_jacobian(void **unused)
{
    (void)unused;
    void *st = make_state(&rf_ik_dls_api);
    static fx_problem f, fast, slow;
    fx_lcg g = {17};
    for (int k = 0; k < 60; k++) {
        uint32_t goals = 1;
        if (k < 40) {
            static const uint32_t links[] = {2, 3, 5, 10};
            shaped_chain(&f, links[k % 4], (enum start_kind)(k % 3), &g);
            f.goals[0].target = fx_target(&g, links[k % 4]);
        } else {
            fx_tree(&f);
            f.limits[1].flags = RF_IK_LIMIT_HINGE, f.limits[1].axis = rf_v3(1, 0.3, 0);
            f.limits[1].min_angle = -3, f.limits[1].max_angle = 3;
            f.limits[5] = f.limits[1], f.limits[9] = f.limits[1];
            f.goals[0].target = rf_v3_add(rf_v3(1, 3, 0), fx_target(&g, 3));
            f.goals[1].target = rf_v3_add(rf_v3(-1, 3, 0), fx_target(&g, 3));
            f.goals[1].weight = 0.5;
            goals = 2;
        }
        fast = f, slow = f;
        fx_wire(&fast, goals, 1e-5, 100);
        fx_wire(&slow, goals, 1e-5, 100);
        solve_with(&rf_ik_dls_api, st, &fast, true);
        solve_with(&rf_ik_dls_api, st, &slow, false);
        double dist, angle;
        compare_poses(&fast, &slow, &dist, &angle);
        if (fast.res.iterations != slow.res.iterations || dist > 1e-9 * f.n || angle > 1e-9 * f.n)
            fail_msg("dls, problem %d: %u and %u iterations, poses %g apart (%g rad)", k,
                     fast.res.iterations, slow.res.iterations, dist, angle);
    }
    rf_ik_dls_api.destroy(st);
}

/* 200 links reaching 150 away: turns whose quaternions, unnormalised, multiply past the range
 * of a double along the chain. */
static void test_long_chains_stay_finite(void **unused)
{
    (void)unused;
    const rf_ik_solver_api *apis[] = {&rf_ik_ccd_api, &rf_ik_fabrik_api};
    static fx_problem f;
    for (size_t s = 0; s < 2; s++) {
        void *st = make_state(apis[s]);
        fx_lcg g = {5};
        for (int k = 0; k < 3; k++) {
            shaped_chain(&f, 200, k == 2 ? FOLDED : BENT, &g);
            f.goals[0].target = rf_v3_scale(fx_target(&g, 1), 150);
            fx_wire(&f, 1, 1e-3, 30);
            check_agreement(apis[s], st, &f, "200 links", k < 2);
            assert_true(isfinite(f.out[0].r.w));
        }
        apis[s]->destroy(st);
    }
}

/* One state fed problems of different shapes in turn gives each the result a fresh state
 * gives it: what it remembers of the last problem's structure never leaks into the next. */
static void test_states_follow_changing_problems(void **unused)
{
    (void)unused;
    for (size_t s = 0; s < SOLVER_COUNT; s++) {
        const rf_ik_solver_api *api = SOLVERS[s];
        void *st = make_state(api);
        uint32_t links = handles_links(api, 5) ? 5 : 2;
        for (int round = 0; round < 8; round++) {
            static fx_problem f, fresh;
            fx_chain(&f, links);
            f.goals[0].target = rf_v3(0.6, 0.5 * links, 0.4);
            uint32_t goals = 1;
            if (round % 4 == 1 && links > 2) /* the lower links only */
                f.goals[0].chain_root = 2;
            if (round % 4 == 2) /* a hinge */
                f.limits[1].flags = RF_IK_LIMIT_HINGE, f.limits[1].axis = rf_v3(1, 0, 0),
                f.limits[1].min_angle = -1, f.limits[1].max_angle = 1;
            if (round % 4 == 3 && (api->capabilities & RF_IK_CAP_MULTI_GOAL)) {
                fx_tree(&f);
                goals = 2;
            }
            fx_wire(&f, goals, 1e-4, 100);
            fresh = f;
            fx_wire(&fresh, goals, 1e-4, 100);
            solve_ok(api, st, &f);
            void *other = make_state(api);
            solve_ok(api, other, &fresh);
            api->destroy(other);
            assert_memory_equal(f.out, fresh.out, f.n * sizeof f.out[0]);
            assert_int_equal(f.res.iterations, fresh.res.iterations);
            /* a bad problem of the same shape is refused although its structure is known */
            f.pose[1].t.x = NAN;
            fx_wire(&f, goals, 1e-4, 100);
            expect_refusal(api, st, &f, "not finite");
            f.pose[1].t.x = 0;
            f.parents[1] = 1;
            fx_wire(&f, goals, 1e-4, 100);
            expect_refusal(api, st, &f, "not an earlier joint");
        }
        api->destroy(st);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_reaches_reachable_targets),
        cmocka_unit_test(test_unreachable_gives_stretched_pose),
        cmocka_unit_test(test_limits_hold_after_solves),
        cmocka_unit_test(test_tree_with_two_effectors),
        cmocka_unit_test(test_solvers_agree_on_reachable_targets),
        cmocka_unit_test(test_bad_goals_are_refused),
        cmocka_unit_test(test_orientation_goal_turns_the_effector),
        cmocka_unit_test(test_solves_in_place),
        cmocka_unit_test(test_twobone_follows_the_law_of_cosines),
        cmocka_unit_test(test_twobone_refuses_other_chains),
        cmocka_unit_test(test_every_solver_honours_the_pole),
        cmocka_unit_test(test_a_pole_never_costs_reach),
        cmocka_unit_test(test_solvers_work_in_any_unit),
        cmocka_unit_test(test_states_grow_past_their_config),
        cmocka_unit_test(test_fast_paths_agree_with_general_forms),
        cmocka_unit_test(test_direct_dls_agrees_with_the_jacobian),
        cmocka_unit_test(test_long_chains_stay_finite),
        cmocka_unit_test(test_states_follow_changing_problems),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
