/* libFuzzer harness: every IK solver (plugins/ik-*) on arbitrary problems.
 *
 * The bytes describe a problem rather than being one, so that the fuzzer reaches what breaks
 * geometry code quickly: zero-length and coincident bones, huge and tiny offsets and scales,
 * non-unit, zero and NaN rotations, targets on a joint or out of range, limits with odd angles,
 * poles on the chain's line, bad parents, goals whose chain root is no ancestor.
 *
 *   byte 0     mode bits (RF_FZ_*)
 *   byte 1     joint count (2 to 17)
 *   byte 2     iteration cap (0 to 63)
 *   byte 3     tolerance (a table: ordinary, tiny, huge, zero, NaN)
 *   then       8 bytes per joint, then 12 per goal, reused cyclically when the input runs out
 *
 * Then it checks what ik.h promises, for each solver, with a state that has seen earlier inputs
 * and with a fresh one: a refusal says why and leaves the output untouched; a solve gives finite
 * unit rotations, the start pose's translations and scales, finite errors and a status per goal,
 * no more iterations than the cap, and the same answer from both states.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ccd.h"
#include "fuzz-values.h"
#include "fabrik.h"
#include "jacobian.h"
#include "twobone.h"

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

enum {
    RF_FZ_CHAIN = 1u << 0,     /* every joint hangs from the previous one */
    RF_FZ_LIMITS = 1u << 1,    /* joints get constraints */
    RF_FZ_TWO_GOALS = 1u << 2, /* a second goal */
    RF_FZ_ORIENT = 1u << 3,    /* orientation goals */
    RF_FZ_POLE = 1u << 4,      /* poles */
    RF_FZ_REFERENCE = 1u << 5, /* limits measured from a reference pose */
    RF_FZ_SLOW = 1u << 6,      /* the solvers' general forms only */
    RF_FZ_ROOTS = 1u << 7,     /* goals name a chain root */
};

#define RF_FZ_MAX_JOINTS 17u
#define RF_FZ_GOALS 2u

#define RF_FUZZ_CHECK(cond)                                                                        \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            fprintf(stderr, "fuzz_ik: broken promise: %s (%s:%d)\n", #cond, __FILE__, __LINE__);   \
            abort();                                                                               \
        }                                                                                          \
    } while (0)

static const rf_ik_solver_api *const rf_fz_solvers[] = {
    &rf_ik_ccd_api, &rf_ik_fabrik_api, &rf_ik_twobone_api,
    &rf_ik_dls_api, &rf_ik_pinv_api,   &rf_ik_jt_api,
};
#define RF_FZ_SOLVERS (sizeof rf_fz_solvers / sizeof rf_fz_solvers[0])

static void *rf_fz_states[RF_FZ_SOLVERS];

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    char err[160];
    for (size_t i = 0; i < RF_FZ_SOLVERS; i++) {
        rf_fz_states[i] = rf_fz_solvers[i]->create(NULL, err, sizeof err);
        RF_FUZZ_CHECK(rf_fz_states[i] != NULL);
    }
    return 0;
}

/* Numbers that break geometry: zero, tiny, huge, and ordinary ones; from the last 8 byte values
 * (rarer, or nearly every problem would be refused) non-finite ones and ones beyond range. */
static double rf_fz_value(uint8_t b)
{
    static const double table[16] = {0,   1,    -1, 0.5, 1e-9,   -1e-12, 10, -10,
                                     100, 0.25, 2,  0.1, 1e-300, 1e29,   3,  -0.5};
    static const double special[16] = {NAN,    INFINITY, -INFINITY, 1e300,  1e31, -1e31,
                                       1e-310, 1e15,     -1e15,     1e-30,  1e30, -1e29,
                                       1e20,   1e-200,   5e29,      -1e-300};
    if (b >= 248)
        return special[b & 15];
    double v = table[b & 15];
    return fabs(v) < 1e6 && v != 0 ? v * (1 + (b >> 4) * 0.125) : v;
}

static rf_vec3 rf_fz_vec(uint8_t a, uint8_t b, uint8_t c)
{
    return rf_v3(rf_fz_value(a), rf_fz_value(b), rf_fz_value(c));
}

static rf_quat rf_fz_quat(uint8_t b)
{
    return rf_fz_quat_of(b, (b >> 3) == 31);
}

static double rf_fz_angle(uint8_t b)
{
    static const double table[8] = {0, 0.5, 1.5, 3.14159, -0.7, 3.5, 1e-9, -3.2};
    return b == 255 ? NAN : table[b & 7] + (b >> 3) * 0.05;
}

typedef struct rf_fz_reader {
    const uint8_t *data;
    size_t size, at;
} rf_fz_reader;

static uint8_t rf_fz_byte(rf_fz_reader *r)
{
    if (r->size == 0)
        return 0;
    uint8_t b = r->data[r->at % r->size];
    r->at++;
    return b;
}

/* One problem with its arrays, and the result arrays a solve writes. */
typedef struct rf_fz_problem {
    int32_t parents[RF_FZ_MAX_JOINTS];
    rf_xform pose[RF_FZ_MAX_JOINTS], reference[RF_FZ_MAX_JOINTS];
    rf_ik_constraint limits[RF_FZ_MAX_JOINTS];
    rf_ik_goal goals[RF_FZ_GOALS];
    rf_ik_problem pb;
} rf_fz_problem;

static void rf_fz_joint(rf_fz_problem *p, uint32_t j, rf_fz_reader *r, unsigned mode)
{
    uint8_t b = rf_fz_byte(r);
    if (j == 0)
        p->parents[j] = b == 255 ? 0 : -1; /* 0: not an earlier joint */
    else if (mode & RF_FZ_CHAIN)
        p->parents[j] = (int32_t)j - 1;
    else
        p->parents[j] = b == 255 ? (int32_t)j + 1 : (int32_t)(b % (j + 1)) - 1;
    p->pose[j].t = rf_fz_vec(rf_fz_byte(r), rf_fz_byte(r), rf_fz_byte(r));
    p->pose[j].r = rf_fz_quat(rf_fz_byte(r));
    uint8_t s = rf_fz_byte(r);
    double k = s == 255 ? -1 : s == 254 ? 0 : fabs(rf_fz_value(s)); /* rarely refused */
    p->pose[j].s = s < 200 ? rf_v3(1, 1, 1) : rf_v3(k, 1, k);
    p->reference[j] = p->pose[j];
    p->reference[j].r = rf_fz_quat(s >> 3);
    rf_ik_constraint *c = &p->limits[j];
    memset(c, 0, sizeof *c);
    c->size = sizeof *c;
    uint8_t f = rf_fz_byte(r), a = rf_fz_byte(r);
    if (mode & RF_FZ_LIMITS) {
        /* mostly combinations ik.h allows, with ranges the right way round; now and then not */
        static const uint32_t kinds[8] = {0,
                                          RF_IK_LIMIT_HINGE,
                                          RF_IK_LIMIT_CONE,
                                          RF_IK_LIMIT_TWIST,
                                          RF_IK_LIMIT_CONE | RF_IK_LIMIT_TWIST,
                                          RF_IK_LOCKED,
                                          RF_IK_LIMIT_CONE | RF_IK_LIMIT_TWIST,
                                          RF_IK_LIMIT_HINGE | RF_IK_LIMIT_CONE};
        bool odd = (f & 0x78) == 0x78;
        c->flags = kinds[odd ? f & 7 : f % 7];
        c->axis = rf_fz_vec(a, a >> 2, a >> 4);
        c->min_angle = rf_fz_angle(a);
        c->max_angle = odd ? rf_fz_angle(f >> 3) : c->min_angle + fabs(rf_fz_angle(f >> 3));
        c->cone_angle = odd ? rf_fz_angle(a >> 3) : fmod(fabs(rf_fz_angle(a >> 3)), RF_PI);
        c->twist_min = -fabs(rf_fz_angle(a >> 1));
        c->twist_max = odd ? rf_fz_angle(f >> 1) : fabs(rf_fz_angle(f >> 1));
        c->bone_axis = (f & 0x80) ? rf_fz_vec(f, a, f >> 4) : rf_v3(0, 0, 0);
    }
}

static void rf_fz_goal(rf_fz_problem *p, uint32_t i, uint32_t n, rf_fz_reader *r, unsigned mode)
{
    uint8_t e = rf_fz_byte(r), root = rf_fz_byte(r);
    rf_ik_goal *g = &p->goals[i];
    *g = rf_ik_goal_make(e >= 240 ? n + e : (i == 0 ? n - 1 : e % n),
                         rf_fz_vec(rf_fz_byte(r), rf_fz_byte(r), rf_fz_byte(r)));
    if (mode & RF_FZ_ROOTS)
        g->chain_root = root >= 250 ? (int32_t)root : (int32_t)(root % n) - 1;
    g->weight = (root & 1) ? 1 : rf_fz_value(root >> 1);
    rf_vec3 pole = rf_fz_vec(rf_fz_byte(r), rf_fz_byte(r), rf_fz_byte(r));
    uint8_t o = rf_fz_byte(r);
    if (mode & RF_FZ_POLE)
        g->flags |= RF_IK_GOAL_POLE, g->pole = pole;
    if (mode & RF_FZ_ORIENT)
        g->flags |= RF_IK_GOAL_ORIENTATION, g->orientation = rf_fz_quat(o);
    (void)rf_fz_byte(r), (void)rf_fz_byte(r); /* room for later fields: keeps inputs stable */
}

static void rf_fz_build(rf_fz_problem *p, const uint8_t *data, size_t size, unsigned *mode)
{
    static const double tolerances[16] = {1e-3, 1e-6, 1e-12, 1e-4, 1e-300, 1,    1e-3, 1e-3,
                                          1e-2, 1e-5, 1e-9,  0.1,  1e-3,   1e-3, 0,    NAN};
    memset(p, 0, sizeof *p);
    *mode = size > 0 ? data[0] : 0;
    uint32_t n = 2 + (size > 1 ? data[1] % (RF_FZ_MAX_JOINTS - 1) : 0);
    rf_fz_reader r = {size > 4 ? data + 4 : data, size > 4 ? size - 4 : size, 0};
    for (uint32_t j = 0; j < n; j++)
        rf_fz_joint(p, j, &r, *mode);
    uint32_t goals = (*mode & RF_FZ_TWO_GOALS) ? 2 : 1;
    for (uint32_t i = 0; i < goals; i++)
        rf_fz_goal(p, i, n, &r, *mode);
    p->pb = (rf_ik_problem){sizeof p->pb,
                            n,
                            p->parents,
                            p->pose,
                            (*mode & RF_FZ_REFERENCE) ? p->reference : NULL,
                            (*mode & RF_FZ_LIMITS) ? p->limits : NULL,
                            goals,
                            p->goals,
                            tolerances[size > 3 ? data[3] & 15 : 0],
                            size > 2 ? data[2] % 64u : 10u};
}

typedef struct rf_fz_result {
    rf_xform pose[RF_FZ_MAX_JOINTS];
    double errors[RF_FZ_GOALS], angle_errors[RF_FZ_GOALS];
    uint32_t status[RF_FZ_GOALS];
    rf_ik_result res;
    bool ok;
} rf_fz_result;

/* A sentinel pose the solver must leave alone when it refuses. */
static const rf_xform rf_fz_untouched = {{-7, -7, -7}, {0.5, 0.5, 0.5, 0.5}, {3, 3, 3}};

static void rf_fz_solve(const rf_ik_solver_api *api, void *state, const rf_fz_problem *p,
                        rf_fz_result *out)
{
    memset(out, 0, sizeof *out);
    for (uint32_t j = 0; j < RF_FZ_MAX_JOINTS; j++)
        out->pose[j] = rf_fz_untouched;
    out->res.size = sizeof out->res;
    out->res.pose = out->pose, out->res.errors = out->errors;
    out->res.angle_errors = out->angle_errors, out->res.status = out->status;
    out->ok = api->solve(state, &p->pb, &out->res);
}

static bool rf_fz_same_xform(rf_xform a, rf_xform b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

static void rf_fz_check(const rf_fz_problem *p, const rf_fz_result *out)
{
    const rf_ik_problem *pb = &p->pb;
    const rf_ik_result *res = &out->res;
    if (!out->ok) {
        RF_FUZZ_CHECK(res->message[0] != '\0');
        for (uint32_t j = 0; j < pb->joint_count; j++)
            RF_FUZZ_CHECK(rf_fz_same_xform(out->pose[j], rf_fz_untouched));
        return;
    }
    for (uint32_t j = 0; j < pb->joint_count; j++) {
        rf_xform x = out->pose[j];
        RF_FUZZ_CHECK(isfinite(x.r.x + x.r.y + x.r.z + x.r.w));
        RF_FUZZ_CHECK(fabs(rf_quat_dot(x.r, x.r) - 1) < 1e-9);
        RF_FUZZ_CHECK(memcmp(&x.t, &pb->pose[j].t, sizeof x.t) == 0);
        RF_FUZZ_CHECK(memcmp(&x.s, &pb->pose[j].s, sizeof x.s) == 0);
    }
    double worst = 0;
    bool all = true;
    for (uint32_t i = 0; i < pb->goal_count; i++) {
        RF_FUZZ_CHECK(isfinite(out->errors[i]) && out->errors[i] >= 0);
        RF_FUZZ_CHECK(isfinite(out->angle_errors[i]) && out->angle_errors[i] >= 0);
        RF_FUZZ_CHECK((out->status[i] & ~(uint32_t)(RF_IK_REACHED | RF_IK_UNREACHABLE)) == 0);
        RF_FUZZ_CHECK((out->status[i] & RF_IK_REACHED) == (out->errors[i] <= pb->tolerance));
        worst = fmax(worst, out->errors[i]);
        all = all && (out->status[i] & RF_IK_REACHED);
    }
    RF_FUZZ_CHECK(res->max_error == worst);
    RF_FUZZ_CHECK(res->reached == all);
    RF_FUZZ_CHECK(res->iterations <= (pb->max_iterations > 1 ? pb->max_iterations : 1));
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static rf_fz_problem p;
    static rf_fz_result used, fresh;
    unsigned mode;
    rf_fz_build(&p, data, size, &mode);
    rf_ikc_fast_paths = !(mode & RF_FZ_SLOW);
    char err[160];
    for (size_t i = 0; i < RF_FZ_SOLVERS; i++) {
        const rf_ik_solver_api *api = rf_fz_solvers[i];
        rf_fz_solve(api, rf_fz_states[i], &p, &used);
        rf_fz_check(&p, &used);
        void *state = api->create(NULL, err, sizeof err);
        RF_FUZZ_CHECK(state != NULL);
        rf_fz_solve(api, state, &p, &fresh);
        api->destroy(state);
        /* a state that has seen other problems answers as a fresh one does */
        RF_FUZZ_CHECK(used.ok == fresh.ok);
        RF_FUZZ_CHECK(strcmp(used.res.message, fresh.res.message) == 0);
        for (uint32_t j = 0; used.ok && j < p.pb.joint_count; j++)
            RF_FUZZ_CHECK(rf_fz_same_xform(used.pose[j], fresh.pose[j]));
        RF_FUZZ_CHECK(used.res.iterations == fresh.res.iterations);
    }
    rf_ikc_fast_paths = true;
    return 0;
}
