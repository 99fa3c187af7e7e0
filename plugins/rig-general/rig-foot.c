/* Feet read from the soles: a biped's toe bone laid along the foot it stands on.
 *
 * The layout lays a leg's toe joint along the curve skeleton, which thinning ends about a
 * radius short of the mesh and which runs into a foot only when the foot is long against its
 * thickness. A short foot (a random biped's, ankle to ball in a capsule as thick as the shin)
 * grows no branch of its own, so the toe bone pointed down the shin: the skeleton analysis then
 * read no foot, and a body whose only front-to-back cue is its feet was read facing whichever
 * way the file said. The sole is read from the mesh instead: the surface under the ankle that
 * belongs to this leg, and how far it reaches each way along the floor from where the leg
 * stands on it. A foot reaches well forward and little behind (the heel); a hoof, a robe's hem,
 * a leg's round end or a figurine's base reaches alike every way, or the pair's two "feet"
 * point apart, and is left as laid. doc/autorig.md, step 4 and "Feet from the soles". */
#include <math.h>
#include <stdint.h>

#include "rig-internal.h"

typedef struct rf_rig_sole {
    rf_vec3 u;         /* the way the foot points, along the floor */
    rf_vec3 column;    /* where the leg stands on the sole, along the floor (up's part 0) */
    rf_vec3 ball, tip; /* where the toe joint and the toe bone's tip go */
    double instep;     /* the foot's top over the ball: a low ankle no higher than this */
    double hock;       /* an ankle higher than this is a hock: its foot is left as laid */
} rf_rig_sole;

#define RF_RIG_SOLE_BAND 0.1   /* of the leg's height: the sole, over the lowest surface */
#define RF_RIG_SOLE_AROUND 0.6 /* of the leg's height: how far from the ankle a sole may reach */
#define RF_RIG_SOLE_REACH 0.08 /* of the leg's height: the least forward reach of a foot */
#define RF_RIG_SOLE_HEEL 1.6   /* forward reach over the reach behind: a foot, not a hoof */
#define RF_RIG_SOLE_BALL 0.6   /* the ball's share of the way from the ankle to the toes' tip */
#define RF_RIG_SOLE_HOCK 0.25  /* of the leg's height over the sole: an ankle higher is a hock */
#define RF_RIG_SOLE_FLAT 0.7   /* a toe bone this level (cosine) already lies along its foot */
#define RF_RIG_SOLE_PAIR 0.5   /* mirrored feet read pointing apart by more (cosine) are dropped */

/* q's offset from `from` across up (along the floor). */
static rf_vec3 rf_sole_flat(const double q[3], const double from[3], rf_vec3 up)
{
    rf_vec3 d = rf_v3(q[0] - from[0], q[1] - from[1], q[2] - from[2]);
    return rf_v3_sub(d, rf_v3_scale(up, rf_v3_dot(d, up)));
}

/* Whether vertex v lies at or under height `top` nearer leg i's ankle along the floor than any
 * other leg's, and within reach of it. */
static bool rf_sole_owns(const double v[3], rf_vec3 up, uint32_t i, const rf_rig_feet *f,
                         double top, double around)
{
    const double *ankle = f->pos[i][2];
    if (rf_rig_along(v, up) > top)
        return false;
    double mine = rf_v3_len(rf_sole_flat(v, ankle, up));
    if (mine > around)
        return false;
    for (uint32_t m = 0; m < f->n; m++)
        if (m != i && f->leg[m] && rf_v3_len(rf_sole_flat(v, f->pos[m][2], up)) < mine)
            return false;
    return true;
}

/* The height of the sole's top: the band over the lowest surface leg i owns under its ankle;
 * NAN when it owns none. */
static double rf_sole_top(const rf_rig_geo *g, rf_vec3 up, uint32_t i, const rf_rig_feet *f,
                          double height)
{
    double ankle = rf_rig_along(f->pos[i][2], up), low = INFINITY;
    for (uint32_t v = 0; v < g->nv; v++) {
        const double *q = g->p + (size_t)v * 3;
        if (rf_rig_along(q, up) < low &&
            rf_sole_owns(q, up, i, f, ankle, RF_RIG_SOLE_AROUND * height))
            low = rf_rig_along(q, up);
    }
    return isfinite(low) ? low + RF_RIG_SOLE_BAND * height : NAN;
}

/* Where the leg stands on its sole: the middle of the surface leg i owns in the band just over
 * the sole (its shin's cross-section over the foot) into col, or its ankle joint when there is
 * none there. The ankle joint as laid may lie anywhere over the foot (a curve skeleton that ran
 * on into the toes laid it there), and from the toes the heel is the far end. */
static void rf_sole_column(const rf_rig_geo *g, rf_vec3 up, uint32_t i, const rf_rig_feet *f,
                           double top, double band, double around, double col[3])
{
    double sum[3] = {0, 0, 0};
    uint32_t n = 0;
    for (uint32_t v = 0; v < g->nv; v++) {
        const double *q = g->p + (size_t)v * 3;
        if (rf_rig_along(q, up) > top && rf_sole_owns(q, up, i, f, top + band, around))
            sum[0] += q[0], sum[1] += q[1], sum[2] += q[2], n++;
    }
    for (int c = 0; c < 3; c++)
        col[c] = n ? sum[c] / n : f->pos[i][2][c];
}

/* The sole of leg i read from g into s; false when it reads no foot (too short, reaching behind
 * where the leg stands on it as far as before it, or no surface there). */
static bool rf_sole_read(const rf_rig_geo *g, rf_vec3 up, uint32_t i, const rf_rig_feet *f,
                         rf_rig_sole *s)
{
    double height = rf_rig_along(f->pos[i][0], up) - rf_rig_along(f->tip[i], up);
    if (!(height > 0))
        return false;
    double top = rf_sole_top(g, up, i, f, height), around = RF_RIG_SOLE_AROUND * height, col[3];
    if (!isfinite(top))
        return false;
    rf_sole_column(g, up, i, f, top, RF_RIG_SOLE_BAND * height, around, col);
    rf_vec3 far = rf_v3(0, 0, 0);
    for (uint32_t v = 0; v < g->nv; v++) {
        const double *q = g->p + (size_t)v * 3;
        rf_vec3 d = rf_sole_flat(q, col, up);
        if (rf_v3_len(d) > rf_v3_len(far) && rf_sole_owns(q, up, i, f, top, around))
            far = d;
    }
    double reach = rf_v3_len(far), back = 0, tip_h = 0, lo = INFINITY, hi = -INFINITY;
    if (!(reach >= RF_RIG_SOLE_REACH * height))
        return false;
    rf_vec3 u = rf_v3_scale(far, 1 / reach);
    uint32_t at_tip = 0;
    for (uint32_t v = 0; v < g->nv; v++) {
        const double *q = g->p + (size_t)v * 3;
        if (!rf_sole_owns(q, up, i, f, top, around))
            continue;
        double t = rf_v3_dot(rf_sole_flat(q, col, up), u), h = rf_rig_along(q, up);
        back = fmax(back, -t);
        if (t >= 0.8 * reach)
            tip_h += h, at_tip++;
        if (fabs(t - RF_RIG_SOLE_BALL * reach) <= 0.1 * reach)
            lo = fmin(lo, h), hi = fmax(hi, h);
    }
    if (reach < RF_RIG_SOLE_HEEL * back || !at_tip || !(lo <= hi))
        return false;
    rf_vec3 base = rf_v3_sub(rf_v3(col[0], col[1], col[2]), rf_v3_scale(up, rf_rig_along(col, up)));
    s->u = u, s->column = base;
    s->ball = rf_v3_add(rf_v3_add(base, rf_v3_scale(u, RF_RIG_SOLE_BALL * reach)),
                        rf_v3_scale(up, 0.5 * (lo + hi)));
    s->tip = rf_v3_add(rf_v3_add(base, rf_v3_scale(u, reach)), rf_v3_scale(up, tip_h / at_tip));
    s->instep = hi;
    s->hock = top - RF_RIG_SOLE_BAND * height + RF_RIG_SOLE_HOCK * height;
    return true;
}

/* Whether leg i's toe bone (toe joint to tip) already lies along the floor the way u points. */
static bool rf_sole_laid(const rf_rig_feet *f, uint32_t i, rf_vec3 up, rf_vec3 u)
{
    rf_vec3 b = rf_v3(f->tip[i][0] - f->pos[i][3][0], f->tip[i][1] - f->pos[i][3][1],
                      f->tip[i][2] - f->pos[i][3][2]);
    double len = rf_v3_len(b);
    rf_vec3 flat = rf_v3_sub(b, rf_v3_scale(up, rf_v3_dot(b, up)));
    return len > 0 && rf_v3_len(flat) >= RF_RIG_SOLE_FLAT * len && rf_v3_dot(flat, u) > 0;
}

uint32_t rf_rig_feet_soles(const rf_rig_geo *g, rf_vec3 up, rf_rig_feet *f)
{
    rf_rig_sole sole[RF_RIG_MAX_LIMBS];
    bool found[RF_RIG_MAX_LIMBS] = {0};
    up = rf_v3_normalize(up);
    for (uint32_t i = 0; i < f->n && i < RF_RIG_MAX_LIMBS; i++)
        found[i] = f->leg[i] && rf_sole_read(g, up, i, f, &sole[i]);
    /* a pair of feet reads one way: pointing apart, one of them read a tail or a hem */
    bool keep[RF_RIG_MAX_LIMBS] = {0};
    for (uint32_t i = 0; i < f->n && i < RF_RIG_MAX_LIMBS; i++) {
        int32_t m = f->mirror[i];
        keep[i] =
            found[i] && (m < 0 || !found[m] || rf_v3_dot(sole[i].u, sole[m].u) >= RF_RIG_SOLE_PAIR);
    }
    /* a hock (a bird's ankle, high over toes spread on the floor) keeps its foot as laid: toes
     * laid flat under it dipped under the floor when the walk's ankles bent (the animalia bird
     * sank in 8% of the frames) */
    for (uint32_t i = 0; i < f->n && i < RF_RIG_MAX_LIMBS; i++)
        keep[i] = keep[i] && rf_rig_along(f->pos[i][2], up) < sole[i].hock;
    /* a pair is laid alike or not at all: one foot on its curve, its twin on its sole, read as
     * no pair (the laid toe came out a helper joint) */
    bool lay[RF_RIG_MAX_LIMBS] = {0};
    for (uint32_t i = 0; i < f->n && i < RF_RIG_MAX_LIMBS; i++) {
        int32_t m = f->mirror[i];
        bool twin = m >= 0 && f->leg[m];
        lay[i] = keep[i] && (!twin || keep[m]) &&
                 (!rf_sole_laid(f, i, up, sole[i].u) ||
                  (twin && !rf_sole_laid(f, (uint32_t)m, up, sole[m].u)));
    }
    uint32_t laid = 0;
    for (uint32_t i = 0; i < f->n && i < RF_RIG_MAX_LIMBS; i++) {
        if (!lay[i])
            continue;
        double *ankle = f->pos[i][2]; /* over the column, no higher than the foot */
        rf_vec3 at = rf_v3_add(sole[i].column,
                               rf_v3_scale(up, fmin(rf_rig_along(ankle, up), sole[i].instep)));
        ankle[0] = at.x, ankle[1] = at.y, ankle[2] = at.z;
        f->pos[i][3][0] = sole[i].ball.x, f->pos[i][3][1] = sole[i].ball.y;
        f->pos[i][3][2] = sole[i].ball.z;
        f->tip[i][0] = sole[i].tip.x, f->tip[i][1] = sole[i].tip.y, f->tip[i][2] = sole[i].tip.z;
        laid++;
    }
    return laid;
}
