/* Skeleton analysis, stage 2: the plane of symmetry, the centerline and the limbs.
 *
 * Sibling subtrees with the same shape (same topology, similar length) propose mirror planes; the
 * plane that reflects the most joints onto other joints wins. Checking every joint against the
 * plane is what makes this hold where the thesis's angle comparison at one junction is
 * ambiguous (four identical legs of a wolf, fingers, coincident hip joints). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis-internal.h"

/* ---- subtree statistics ---- */

static uint64_t mix64(uint64_t h)
{
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdULL;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ULL;
    return h ^ (h >> 33);
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

/* Count, pivot sum, length and topology hash of every subtree, children before parents. False
 * when out of memory: a hash without the children's would pair subtrees of other shapes. */
bool rf_an_subtree_stats(rf_awork *w)
{
    uint64_t *buf = malloc((size_t)(w->n ? w->n : 1) * sizeof *buf);
    if (!buf)
        return false;
    for (uint32_t i = w->order_count; i-- > 0;) {
        uint32_t j = w->order[i];
        const rf_joint_info *ji = &w->a->joints[j];
        w->sub_count[j] = 1;
        w->sub_sum[j] = ji->pos;
        w->sub_len[j] = rf_an_is_leaf(w, j) ? rf_v3_dist(ji->tip, ji->pos) : 0.0;
        uint32_t k0 = w->child_off[j], k1 = w->child_off[j + 1];
        for (uint32_t k = k0; k < k1; k++) {
            uint32_t c = w->child_idx[k];
            w->sub_count[j] += w->sub_count[c];
            w->sub_sum[j] = rf_v3_add(w->sub_sum[j], w->sub_sum[c]);
            w->sub_len[j] += w->sub_len[c] + rf_v3_dist(w->a->joints[c].pos, ji->pos);
            buf[k - k0] = w->hash[c];
        }
        uint64_t h = mix64(0x9e3779b97f4a7c15ULL + (k1 - k0));
        qsort(buf, k1 - k0, sizeof *buf, cmp_u64);
        for (uint32_t k = 0; k < k1 - k0; k++)
            h = mix64(h ^ (buf[k] + 0x632be59bd9b4e019ULL));
        w->hash[j] = h;
    }
    free(buf);
    return true;
}

/* ---- a spatial hash of pivots for "is there a joint near this point" ---- */

typedef struct rf_grid {
    double cell;
    uint32_t mask;
    uint32_t *off; /* [mask + 2] */
    uint32_t *idx;
} rf_grid;

static int64_t cell_of(double x, double cell)
{
    double c = floor(x / cell);
    /* plain comparisons: fmin/fmax are library calls here; NaN lands in cell 0 */
    return c > 1e17 ? (int64_t)1e17 : c < -1e17 ? (int64_t)-1e17 : c == c ? (int64_t)c : 0;
}

static uint32_t cell_hash(int64_t x, int64_t y, int64_t z, uint32_t mask)
{
    uint64_t h = mix64((uint64_t)x * 0x9e3779b97f4a7c15ULL ^ (uint64_t)y * 0xc2b2ae3d27d4eb4fULL ^
                       (uint64_t)z * 0x165667b19e3779f9ULL);
    return (uint32_t)(h & mask);
}

static uint32_t point_hash(rf_vec3 p, double cell, uint32_t mask)
{
    return cell_hash(cell_of(p.x, cell), cell_of(p.y, cell), cell_of(p.z, cell), mask);
}

static bool grid_build(rf_grid *g, const rf_awork *w, double cell)
{
    uint32_t buckets = 16;
    while (buckets < 2 * w->order_count && buckets < (1u << 30))
        buckets *= 2;
    g->cell = cell;
    g->mask = buckets - 1;
    g->off = calloc((size_t)buckets + 1, sizeof *g->off);
    g->idx = malloc((size_t)(w->order_count ? w->order_count : 1) * sizeof *g->idx);
    if (!g->off || !g->idx)
        return false;
    for (uint32_t i = 0; i < w->order_count; i++)
        g->off[point_hash(rf_an_pos(w, w->order[i]), cell, g->mask) + 1]++;
    for (uint32_t b = 0; b < buckets; b++)
        g->off[b + 1] += g->off[b];
    uint32_t *fill = malloc((size_t)buckets * sizeof *fill);
    if (!fill)
        return false;
    memcpy(fill, g->off, (size_t)buckets * sizeof *fill);
    for (uint32_t i = 0; i < w->order_count; i++) {
        uint32_t j = w->order[i];
        g->idx[fill[point_hash(rf_an_pos(w, j), cell, g->mask)]++] = j;
    }
    free(fill);
    return true;
}

static void grid_free(rf_grid *g)
{
    free(g->off);
    free(g->idx);
}

void rf_an_grid_reset(rf_awork *w)
{
    if (w->grid)
        grid_free(w->grid);
    free(w->grid);
    w->grid = NULL;
}

/* The grid of the pivots in `order` with cells of the symmetry tolerance, kept in the work
 * (several stages ask for it); NULL when out of memory. */
static const rf_grid *work_grid(rf_awork *w)
{
    if (w->grid)
        return w->grid;
    w->grid = calloc(1, sizeof *w->grid);
    if (w->grid && !grid_build(w->grid, w, w->tol))
        rf_an_grid_reset(w);
    return w->grid;
}

/* Squared distances from a coordinate x to the cells before, at and after its own along one
 * axis. */
static void cell_gaps(double x, double cell, double gap[3])
{
    double f = x / cell - floor(x / cell);
    gap[0] = f * f * cell * cell;
    gap[1] = 0;
    gap[2] = (1 - f) * (1 - f) * cell * cell;
}

/* Looks through one cell's joints for one nearer to p than *best_d2 on the wanted side. */
static void cell_scan(const rf_grid *g, const rf_awork *w, uint32_t b, rf_vec3 p, uint32_t self,
                      int side, double *best_d2, int32_t *best, uint32_t *examined)
{
    for (uint32_t k = g->off[b]; k < g->off[b + 1] && *examined < 48; k++) {
        uint32_t j = g->idx[k];
        (*examined)++;
        double d2 = rf_v3_len2(rf_v3_sub(rf_an_pos(w, j), p));
        if (j == self || d2 > *best_d2)
            continue;
        double s = rf_an_plane_dist(w, rf_an_pos(w, j));
        if (side && s * side <= 0)
            continue;
        *best_d2 = d2, *best = (int32_t)j;
    }
}

/* The joint nearest to p within the grid's cell size whose signed plane distance has the sign
 * `side` (or any when side is 0), other than `self`; -1 when none. Looks at no more than 48
 * joints, so clusters of coincident joints cannot make the analysis quadratic. The 27 cells
 * around p are visited own cell first on each axis, and a row, column or cell further away than
 * the best match so far is skipped whole. Two neighbour cells sharing a bucket are rare and only
 * look at the same joints twice, so they are not weeded out. */
static int32_t grid_nearest(const rf_grid *g, const rf_awork *w, rf_vec3 p, uint32_t self, int side)
{
    static const int step[3] = {0, -1, 1};
    int64_t cx = cell_of(p.x, g->cell), cy = cell_of(p.y, g->cell), cz = cell_of(p.z, g->cell);
    double gx[3], gy[3], gz[3];
    cell_gaps(p.x, g->cell, gx), cell_gaps(p.y, g->cell, gy), cell_gaps(p.z, g->cell, gz);
    int32_t best = RF_NONE;
    double best_d2 = g->cell * g->cell;
    uint32_t examined = 0;
    for (int a = 0; a < 3; a++) {
        int dx = step[a];
        for (int b = 0; b < 3 && gx[dx + 1] <= best_d2; b++) {
            int dy = step[b];
            for (int c = 0; c < 3 && gx[dx + 1] + gy[dy + 1] <= best_d2; c++) {
                int dz = step[c];
                if (gx[dx + 1] + gy[dy + 1] + gz[dz + 1] <= best_d2)
                    cell_scan(g, w, cell_hash(cx + dx, cy + dy, cz + dz, g->mask), p, self, side,
                              &best_d2, &best, &examined);
            }
        }
    }
    return best;
}

/* ---- candidate planes ---- */

double rf_an_plane_dist(const rf_awork *w, rf_vec3 p)
{
    return rf_v3_dot(rf_v3_sub(p, w->plane_p), w->plane_n);
}

typedef struct rf_plane_cluster {
    rf_vec3 n_sum, p_sum;
    double weight;
} rf_plane_cluster;

#define RF_MAX_CLUSTERS 32

typedef struct rf_candidates {
    rf_plane_cluster c[RF_MAX_CLUSTERS];
    int count;
    uint32_t proposals;
} rf_candidates;

static void propose(rf_candidates *cs, rf_vec3 n, rf_vec3 p, double weight)
{
    n = rf_v3_normalize(n);
    if (rf_v3_len2(n) == 0 || !rf_v3_isfinite(p))
        return;
    cs->proposals++;
    for (int i = 0; i < cs->count; i++) {
        rf_vec3 m = rf_v3_normalize(cs->c[i].n_sum);
        double d = rf_v3_dot(m, n);
        if (fabs(d) >= cos(10.0 * RF_PI / 180.0)) {
            if (d < 0)
                n = rf_v3_scale(n, -1);
            cs->c[i].n_sum = rf_v3_add(cs->c[i].n_sum, rf_v3_scale(n, weight));
            cs->c[i].p_sum = rf_v3_add(cs->c[i].p_sum, rf_v3_scale(p, weight));
            cs->c[i].weight += weight;
            return;
        }
    }
    if (cs->count == RF_MAX_CLUSTERS)
        return;
    rf_plane_cluster *c = &cs->c[cs->count++];
    c->n_sum = rf_v3_scale(n, weight);
    c->p_sum = rf_v3_scale(p, weight);
    c->weight = weight;
}

typedef struct rf_hashed {
    uint64_t hash;
    uint32_t joint;
} rf_hashed;

static int cmp_hashed(const void *a, const void *b)
{
    const rf_hashed *x = a, *y = b;
    if (x->hash != y->hash)
        return x->hash < y->hash ? -1 : 1;
    return x->joint < y->joint ? -1 : x->joint > y->joint;
}

static rf_vec3 centroid(const rf_awork *w, uint32_t j)
{
    return rf_v3_scale(w->sub_sum[j], 1.0 / w->sub_count[j]);
}

/* The last joint of the chain starting at j, or -1 when the subtree branches. */
static int32_t chain_end(const rf_awork *w, uint32_t j)
{
    for (uint32_t steps = w->sub_count[j]; steps-- > 0;) {
        uint32_t k0 = w->child_off[j], k1 = w->child_off[j + 1];
        if (k1 == k0)
            return (int32_t)j;
        if (k1 - k0 > 1)
            return RF_NONE;
        j = w->child_idx[k0];
    }
    return RF_NONE;
}

/* Two sibling chains whose lengths differ, but whose ends lie as far from the joint they leave
 * (within a tenth): a curve skeleton's arms, one reaching the shoulder straight from the chest,
 * the other by a detour up the body (greenman's). Their centroids say little of a plane; their
 * ends, the hands, do. */
static void propose_ends(rf_awork *w, rf_candidates *cs, uint32_t ja, uint32_t jb)
{
    int32_t ea = chain_end(w, ja), eb = chain_end(w, jb), p = w->parent[ja];
    if (ea < 0 || eb < 0 || p < 0 || w->parent[jb] != p)
        return;
    rf_vec3 a = rf_an_pos(w, (uint32_t)ea), b = rf_an_pos(w, (uint32_t)eb),
            o = rf_an_pos(w, (uint32_t)p);
    double da = rf_v3_dist(a, o), db = rf_v3_dist(b, o);
    if (fabs(da - db) > 0.1 * fmax(da, db) || rf_v3_dist(a, b) <= w->tol)
        return;
    propose(cs, rf_v3_sub(a, b), rf_v3_scale(rf_v3_add(a, b), 0.5),
            w->sub_count[ja] + w->sub_count[jb]);
}

/* Pairs of siblings with equal topology and similar length propose the plane between them. */
static void propose_siblings(rf_awork *w, rf_candidates *cs, rf_hashed *kids, uint32_t k)
{
    qsort(kids, k, sizeof *kids, cmp_hashed);
    for (uint32_t a = 0; a < k; a++) {
        /* Only the first few of a run of identical siblings: enough to find the plane. */
        for (uint32_t b = a + 1; b < k && b < a + 8 && kids[b].hash == kids[a].hash; b++) {
            uint32_t ja = kids[a].joint, jb = kids[b].joint;
            double la = w->sub_len[ja], lb = w->sub_len[jb];
            if (fabs(la - lb) > 0.25 * fmax(la, lb) + w->eps) {
                propose_ends(w, cs, ja, jb);
                continue;
            }
            rf_vec3 ca = centroid(w, ja), cb = centroid(w, jb);
            if (rf_v3_dist(ca, cb) <= 0.25 * w->tol)
                continue;
            propose(cs, rf_v3_sub(ca, cb), rf_v3_scale(rf_v3_add(ca, cb), 0.5),
                    w->sub_count[ja] + w->sub_count[jb]);
            if (cs->proposals > 4096)
                return;
        }
    }
}

static void gather_candidates(rf_awork *w, rf_candidates *cs, rf_hashed *kids)
{
    uint32_t k = 0; /* the roots are siblings under a virtual root */
    for (uint32_t i = 0; i < w->order_count; i++) {
        uint32_t j = w->order[i];
        if (w->parent[j] < 0)
            kids[k++] = (rf_hashed){w->hash[j], j};
    }
    propose_siblings(w, cs, kids, k);
    for (uint32_t i = 0; i < w->order_count && cs->proposals <= 4096; i++) {
        uint32_t j = w->order[i];
        k = 0;
        for (uint32_t c = w->child_off[j]; c < w->child_off[j + 1]; c++)
            kids[k++] = (rf_hashed){w->hash[w->child_idx[c]], w->child_idx[c]};
        if (k >= 2)
            propose_siblings(w, cs, kids, k);
    }
}

/* Mirror matches of the plane (n, p): off-plane joints whose reflection lands on a joint on
 * the other side, plus a quarter point per joint on the plane, less a quarter point per
 * off-plane joint without a twin. A body's own plane leaves few of those; a plane across it
 * (front to back) pairs forelegs with hind legs and leaves the rest single, and without the
 * cost one chance pair more (a neck's extra joint landing on the tail's mirror image) outvoted
 * the body's plane. Gives up, returning -1, as soon as the score cannot exceed `need` even if
 * every joint left matched. */
static double plane_score(rf_awork *w, const rf_grid *g, rf_vec3 n, rf_vec3 p, double need,
                          uint32_t *off, uint32_t *matched)
{
    w->plane_n = n, w->plane_p = p;
    uint32_t on = 0;
    *off = *matched = 0;
    for (uint32_t i = 0; i < w->order_count; i++) {
        if (*matched + 0.25 * on - 0.25 * (*off - *matched) + (w->order_count - i) <= need)
            return -1;
        uint32_t j = w->order[i];
        rf_vec3 q = rf_an_pos(w, j);
        double d = rf_an_plane_dist(w, q);
        if (fabs(d) <= 0.5 * w->tol) {
            on++;
            continue;
        }
        (*off)++;
        rf_vec3 r = rf_v3_sub(q, rf_v3_scale(n, 2 * d));
        if (grid_nearest(g, w, r, j, d > 0 ? -1 : 1) >= 0)
            (*matched)++;
    }
    return fmax(0.0, *matched + 0.25 * on - 0.25 * (*off - *matched)); /* -1 is "gave up" */
}

static rf_vec3 all_centroid(const rf_awork *w)
{
    rf_vec3 s = rf_v3(0, 0, 0);
    for (uint32_t i = 0; i < w->order_count; i++)
        s = rf_v3_add(s, rf_an_pos(w, w->order[i]));
    return w->order_count ? rf_v3_scale(s, 1.0 / w->order_count) : s;
}

/* Moves the plane to the mean of its matched pairs' midpoints, and turns it to their mean
 * direction. */
static void refine_plane(rf_awork *w, const rf_grid *g)
{
    rf_vec3 nsum = rf_v3(0, 0, 0), psum = rf_v3(0, 0, 0);
    uint32_t count = 0;
    for (uint32_t i = 0; i < w->order_count; i++) {
        uint32_t j = w->order[i];
        rf_vec3 q = rf_an_pos(w, j);
        double d = rf_an_plane_dist(w, q);
        if (d <= 0.5 * w->tol)
            continue; /* one side only: each pair once */
        int32_t m = grid_nearest(g, w, rf_v3_sub(q, rf_v3_scale(w->plane_n, 2 * d)), j, -1);
        if (m < 0)
            continue;
        nsum = rf_v3_add(nsum, rf_v3_normalize(rf_v3_sub(q, rf_an_pos(w, (uint32_t)m))));
        psum = rf_v3_add(psum, rf_v3_scale(rf_v3_add(q, rf_an_pos(w, (uint32_t)m)), 0.5));
        count++;
    }
    if (count == 0)
        return;
    rf_vec3 n = rf_v3_normalize(nsum);
    if (rf_v3_len2(n) > 0 && rf_v3_dot(n, w->plane_n) > 0.9)
        w->plane_n = n;
    w->plane_p = rf_v3_scale(psum, 1.0 / count);
}

/* The up axis forced or declared by the file (zero when neither): the symmetry plane holds it. */
static rf_vec3 known_up(const rf_awork *w)
{
    rf_vec3 u = w->opt.up;
    if (!(rf_v3_isfinite(u) && rf_v3_len2(u) > 1e-24) && !w->opt.ignore_file_axes)
        u = w->skel->up;
    return rf_v3_isfinite(u) && rf_v3_len2(u) > 1e-24 ? rf_v3_normalize(u) : rf_v3(0, 0, 0);
}

/* The pivots' horizontal principal axis across up `u` (the way a fish or a snake lies), snapped
 * to a reference axis within 10 degrees (a body modelled along its file's axes keeps them);
 * zero when the pivots stand in one vertical line. */
static rf_vec3 level_body_axis(const rf_awork *w, rf_vec3 u)
{
    rf_vec3 ax[3];
    rf_an_frame(w, ax);
    rf_vec3 e0 = rf_v3_sub(ax[0], rf_v3_scale(u, rf_v3_dot(ax[0], u)));
    if (rf_v3_len(e0) < 0.5)
        e0 = rf_v3_sub(ax[2], rf_v3_scale(u, rf_v3_dot(ax[2], u)));
    e0 = rf_v3_normalize(e0);
    rf_vec3 e1 = rf_v3_cross(u, e0), mean = all_centroid(w);
    double sxx = 0, syy = 0, sxy = 0;
    for (uint32_t i = 0; i < w->order_count; i++) {
        rf_vec3 d = rf_v3_sub(rf_an_pos(w, w->order[i]), mean);
        double x = rf_v3_dot(d, e0), y = rf_v3_dot(d, e1);
        sxx += x * x, syy += y * y, sxy += x * y;
    }
    if (!(sxx + syy > 1e-12 * w->a->size * w->a->size * (w->order_count + 1)))
        return rf_v3(0, 0, 0);
    double t = 0.5 * atan2(2 * sxy, sxx - syy);
    rf_vec3 h = rf_v3_add(rf_v3_scale(e0, cos(t)), rf_v3_scale(e1, sin(t)));
    for (int k = 0; k < 3; k += 2) {
        rf_vec3 a = rf_v3_sub(ax[k], rf_v3_scale(u, rf_v3_dot(ax[k], u)));
        if (rf_v3_len(a) > 0.99 && fabs(rf_v3_dot(rf_v3_normalize(a), h)) >= cos(RF_PI / 18))
            return rf_v3_normalize(a);
    }
    return h;
}

/* The normal kept when no plane wins (every joint then lies on the centerline): the file's
 * left when it declares both axes; with an up alone, the level axis across the pivots' level
 * principal axis, so the plane holds the body's length and turns with it (a coordinate axis
 * read a fish turned 137 degrees about up across its length, facing sideways); else a
 * coordinate axis across the known up, so that the up and forward candidates drawn from it are
 * directions. */
static rf_vec3 no_plane_normal(const rf_awork *w, rf_vec3 up)
{
    const rf_skeleton *s = w->skel;
    if (!w->opt.ignore_file_axes && rf_v3_len2(s->up) > 0 && rf_v3_len2(s->forward) > 0) {
        rf_vec3 l = rf_v3_normalize(rf_v3_cross(s->up, s->forward));
        if (rf_v3_len2(l) > 0 && fabs(rf_v3_dot(l, up)) < 0.5)
            return l;
    }
    if (rf_v3_len2(up) > 0) {
        rf_vec3 e = level_body_axis(w, up);
        if (rf_v3_len2(e) > 0)
            return rf_v3_normalize(rf_v3_cross(up, e));
    }
    return fabs(up.x) < 0.7 ? rf_v3(1, 0, 0) : rf_v3(0, 0, 1);
}

/* The planes scored: the most heavily proposed. */
#define RF_SCORED_CLUSTERS 12

static int cmp_cluster(const void *a, const void *b)
{
    double x = ((const rf_plane_cluster *)a)->weight, y = ((const rf_plane_cluster *)b)->weight;
    return x > y ? -1 : x < y;
}

/* Chooses the symmetry plane: forced axes define it; otherwise the best scoring candidate.
 * False when out of memory (no plane looked for is no plane found). */
bool rf_an_symmetry(rf_awork *w)
{
    rf_vec3 center = all_centroid(w);
    rf_candidates *cs = calloc(1, sizeof *cs);
    rf_hashed *kids = malloc((size_t)(w->n ? w->n : 1) * sizeof *kids);
    const rf_grid *g = work_grid(w);
    bool ok = cs && kids && g;
    w->plane_n = rf_v3(1, 0, 0), w->plane_p = center;
    if (!ok)
        goto out;
    rf_vec3 fu = w->opt.up, ff = w->opt.forward, up = known_up(w);
    /* No plane at all scores as every joint on it, a quarter point each: a proposed plane has
     * to mirror more than a quarter of the joints off it to beat that (a fish's one chain, a
     * rig whose siblings differ). Axes forced by the caller define the plane whatever it
     * scores. Axis planes through a chosen offset were measured as candidates too (doc/
     * matching.md, "Symmetry plane") and lost more rigs than they found. */
    double best = 0.25 * w->order_count;
    if (rf_v3_len2(fu) > 0 && rf_v3_len2(ff) > 0 && rf_v3_len2(rf_v3_cross(fu, ff)) > 0) {
        propose(cs, rf_v3_cross(fu, ff), center, 1); /* forced: only the offset is searched */
        best = -1;
    } else {
        gather_candidates(w, cs, kids);
    }
    qsort(cs->c, (size_t)cs->count, sizeof cs->c[0], cmp_cluster);
    uint32_t best_off = 0, best_matched = 0;
    rf_vec3 bn = no_plane_normal(w, up), bp = center;
    for (int i = 0; i < cs->count && i < RF_SCORED_CLUSTERS; i++) {
        rf_vec3 n = rf_v3_normalize(cs->c[i].n_sum);
        rf_vec3 p = rf_v3_scale(cs->c[i].p_sum, 1.0 / cs->c[i].weight);
        uint32_t off, matched;
        /* A plane beats "no plane" on a tie: it comes from the skeleton. */
        double bonus = 1e-3;
        double score = plane_score(w, g, n, p, best - bonus, &off, &matched);
        rf_vec3 nu = rf_v3_sub(n, rf_v3_scale(up, rf_v3_dot(n, up)));
        if (rf_v3_len(nu) > 0.5 && fabs(rf_v3_dot(n, up)) > 0.02) {
            /* the same plane stood upright: mirrored limbs of a rig cut from a scan rarely
             * match to the degree, and a tilt of a few degrees misses the far joints */
            nu = rf_v3_normalize(nu);
            uint32_t off_u, matched_u;
            double score_u =
                plane_score(w, g, nu, p, fmax(score, best - bonus), &off_u, &matched_u);
            if (score_u > score)
                n = nu, score = score_u, off = off_u, matched = matched_u;
        }
        /* on a tie the plane whose off-plane joints more often find a twin: a body seen
         * front to back can match as many joints as seen left to right, never all of them */
        bool tie = score >= 0 && fabs(score + bonus - best) < 1e-6 && off > 0 && best_off > 0 &&
                   (double)matched / off > (double)best_matched / best_off;
        if (score >= 0 && (score + bonus > best + 1e-6 || tie))
            best = score + bonus, bn = n, bp = p, best_off = off, best_matched = matched;
    }
    w->plane_n = bn, w->plane_p = bp;
    /* "no plane" leaves every joint on the centerline (off 0: symmetric); a forced plane that
     * mirrors none of its off-plane joints keeps them counted (symmetry 0) */
    uint32_t off = best_off, matched = best_matched;
    if (best_matched > 0) { /* a plane won: move it onto its pairs */
        refine_plane(w, g);
        plane_score(w, g, w->plane_n, w->plane_p, -1, &off, &matched);
        if (matched < best_matched) { /* the refinement made it worse: keep the original */
            w->plane_n = bn, w->plane_p = bp;
            off = best_off, matched = best_matched;
        }
    }
    w->a->symmetry = off ? (double)matched / off : 1.0;
    w->have_plane = matched > 0;
out:
    free(kids);
    free(cs);
    return ok;
}

/* Moves the plane along its normal to the mean midpoint of its twin pairs. Called once up is
 * known and the normal stood upright: the offset found with a tilted normal (a curve skeleton's
 * legs a tenth of the body apart in height) is off by the tilt times the body's height at the
 * chest, enough to put the spine off the centerline. Pairs are looked for from both sides: the
 * nearest image of a left joint need not have that joint as its own nearest (an arm longer than
 * the other, a staff), and looked for from one side only the offset depended on which way the
 * normal pointed, that is on which way the body was read to face (the general rigger's Wizard
 * rig read facing -z put its spine off the centerline, an arm). False when out of memory. */
bool rf_an_recentre(rf_awork *w)
{
    const rf_grid *g = w->have_plane ? work_grid(w) : NULL;
    if (w->have_plane && !g)
        return false;
    double sum = 0;
    uint32_t count = 0;
    for (uint32_t i = 0; g && i < w->order_count; i++) {
        uint32_t j = w->order[i];
        rf_vec3 q = rf_an_pos(w, j);
        double d = rf_an_plane_dist(w, q);
        if (fabs(d) <= 0.5 * w->tol)
            continue;
        int32_t m =
            grid_nearest(g, w, rf_v3_sub(q, rf_v3_scale(w->plane_n, 2 * d)), j, d > 0 ? -1 : 1);
        if (m >= 0)
            sum += 0.5 * (d + rf_an_plane_dist(w, rf_an_pos(w, (uint32_t)m))), count++;
    }
    if (count)
        w->plane_p = rf_v3_add(w->plane_p, rf_v3_scale(w->plane_n, sum / count));
    w->a->plane_point = w->plane_p;
    return true;
}

/* ---- centerline and limbs ---- */

/* Center: near the plane, with a subtree centred on it, under a center parent, and without a
 * twin across the plane (eyes close to the plane are a pair, not the centerline). */
/* Per joint off the plane by more than `tiny`: whether a joint lies near its reflection on the
 * other side (its twin). One query per joint, shared by the tests below. */
static int32_t twin_of(const rf_awork *w, const rf_grid *g, uint32_t j, double tiny)
{
    rf_vec3 q = rf_an_pos(w, j);
    double d = rf_an_plane_dist(w, q);
    if (fabs(d) <= tiny)
        return RF_NONE;
    return grid_nearest(g, w, rf_v3_sub(q, rf_v3_scale(w->plane_n, 2 * d)), j, d > 0 ? -1 : 1);
}

/* Twins are mutual: each the nearest to the other's reflection. Where one side's chain has a
 * joint more than the other's (a curve skeleton's arms of 4 and 5 joints, a hair apart), the
 * joint left over finds a twin that has one already, and would weigh its side in the centring
 * (balanced_offset) alone. NULL when out of memory. */
static uint8_t *twins(const rf_awork *w, const rf_grid *g, double tiny)
{
    uint8_t *twin = calloc(w->n ? w->n : 1, 1);
    int32_t *near = malloc((size_t)(w->n ? w->n : 1) * sizeof *near);
    if (!twin || !near) {
        free(near);
        free(twin);
        return NULL;
    }
    for (uint32_t j = 0; j < w->n; j++)
        near[j] = RF_NONE;
    for (uint32_t i = 0; i < w->order_count; i++)
        near[w->order[i]] = twin_of(w, g, w->order[i], tiny);
    for (uint32_t i = 0; i < w->order_count; i++) {
        uint32_t j = w->order[i];
        twin[j] = near[j] >= 0 && near[near[j]] == (int32_t)j;
    }
    free(near);
    return twin;
}

/* Per joint: whether all its descendants lie off the plane on one side (a hip offset bone on
 * the pelvis pivot carrying a leg), however narrow the hips are next to the wingspan that sets
 * the tolerances, and one of them has a twin across the plane (the other leg): a head whose
 * chain leans a little to one side has none and stays on the centerline. */
static uint8_t *one_sided(const rf_awork *w, const uint8_t *twin, double tiny, uint8_t *trunk)
{
    uint8_t *side = calloc(w->n ? w->n : 1, 1); /* bits: 1 left, 2 right, 4 on, 8 twinned */
    uint8_t *out = calloc(w->n ? w->n : 1, 1);
    if (!side || !out) {
        free(side);
        free(out);
        return NULL;
    }
    for (uint32_t i = w->order_count; i-- > 0;) {
        uint32_t j = w->order[i];
        uint8_t below = 0;
        for (uint32_t k = w->child_off[j]; k < w->child_off[j + 1]; k++) {
            uint32_t c = w->child_idx[k];
            double d = rf_an_plane_dist(w, rf_an_pos(w, c));
            below |= side[c] | (d > tiny ? 1 : d < -tiny ? 2 : 4) | (twin[c] ? 8 : 0);
        }
        side[j] = below;
        out[j] = (below & 7) == 1 || (below & 7) == 2 ? (below & 8) != 0 : 0;
        trunk[j] = (below & 3) == 3 && (below & 8);
    }
    free(side);
    return out;
}

/* Per joint, the mean distance from the plane of the joints of its subtree that are on the plane
 * (within tol_c) or have a twin across it (NAN when none are): how far off centre the body
 * hanging from it sits. A prop held in one hand (a staff, a sword) has no twin and does not pull
 * the spine carrying it off the centerline. */
static double *balanced_offset(const rf_awork *w, const uint8_t *twin, double tol_c)
{
    double *sum = calloc(w->n ? w->n : 1, sizeof *sum);
    uint32_t *count = calloc(w->n ? w->n : 1, sizeof *count);
    if (!sum || !count) {
        free(count);
        free(sum);
        return NULL;
    }
    for (uint32_t i = w->order_count; i-- > 0;) {
        uint32_t j = w->order[i];
        double d = rf_an_plane_dist(w, rf_an_pos(w, j));
        if (fabs(d) <= tol_c || twin[j])
            sum[j] += d, count[j]++;
        if (w->parent[j] >= 0)
            sum[w->parent[j]] += sum[j], count[w->parent[j]] += count[j];
    }
    for (uint32_t j = 0; j < w->n; j++)
        sum[j] = count[j] ? sum[j] / count[j] : NAN;
    free(count);
    return sum;
}

/* The centerline and the limbs. False when out of memory: a joint measured without its twins
 * (or without the grid that finds them) may be read on the centerline or off it wrongly. */
bool rf_an_classify(rf_awork *w)
{
    /* without a plane every joint is on the centerline (below): nothing to measure */
    const rf_grid *grid = w->have_plane ? work_grid(w) : NULL;
    double tol_c = 0.5 * w->tol, tiny = 0.05 * w->tol;
    uint8_t *twinned = grid ? twins(w, grid, 0.25 * w->tol) : NULL;
    uint8_t *trunk = twinned ? calloc(w->n ? w->n : 1, 1) : NULL;
    uint8_t *lateral = trunk ? one_sided(w, twinned, 0.25 * w->tol, trunk) : NULL;
    double *offset = twinned ? balanced_offset(w, twinned, tol_c) : NULL;
    bool ok = !w->have_plane || (lateral && offset);
    for (uint32_t i = 0; i < w->order_count; i++) {
        uint32_t j = w->order[i];
        int32_t p = w->parent[j];
        rf_vec3 q = rf_an_pos(w, j);
        double d = rf_an_plane_dist(w, q);
        double sub = offset && !isnan(offset[j]) ? offset[j] : rf_an_plane_dist(w, centroid(w, j));
        /* A joint carrying twins on both sides (the arms hang from it) is the trunk: it may
         * wobble off the plane by the whole tolerance (a curve skeleton's spine). At half of it
         * the general rigger's Wizard rig had its spine 0.0774 off with the limit at 0.0777,
         * and read facing -z (the plane's offset 0.002 elsewhere) its spine was an arm. */
        double lim = lateral && trunk[j] ? w->tol : tol_c;
        bool center = (p < 0 || w->center[p]) && fabs(d) <= lim && fabs(sub) <= tol_c &&
                      !(lateral && lateral[j]);
        /* No symmetry: no sides. The root chain and the body's top are the centerline, and
         * before they are known the root carrying most of the skeleton (a placement node at the
         * origin, the body standing away from it, is no limb). */
        bool forced = !w->have_plane || w->root_chain[j] || (int32_t)j == w->top ||
                      (p < 0 && w->top < 0 && 2 * w->sub_count[j] > w->order_count);
        if (center && fabs(d) > tiny && grid) {
            rf_vec3 r = rf_v3_sub(q, rf_v3_scale(w->plane_n, 2 * d));
            int32_t twin = grid_nearest(grid, w, r, j, d > 0 ? -1 : 1);
            center = twin < 0 || rf_v3_dist(rf_an_pos(w, (uint32_t)twin), r) > 0.5 * fabs(d);
        }
        w->center[j] = center || forced;
        center = w->center[j];
        if (center)
            w->limb_of[j] = RF_NONE;
        else
            w->limb_of[j] = (p < 0 || w->center[p]) ? (int32_t)j : w->limb_of[p];
    }
    free(offset);
    free(lateral);
    free(trunk);
    free(twinned);
    return ok;
}

/* Each off-center joint's mirror image: the nearest joint to its reflection, other side. False
 * when out of memory. */
bool rf_an_mirrors(rf_awork *w)
{
    for (uint32_t j = 0; j < w->n; j++)
        w->a->joints[j].mirror = RF_NONE;
    const rf_grid *g = w->have_plane ? work_grid(w) : NULL;
    if (!g)
        return !w->have_plane;
    for (uint32_t i = 0; i < w->order_count; i++) {
        uint32_t j = w->order[i];
        if (w->center[j])
            continue;
        rf_vec3 q = rf_an_pos(w, j);
        double d = rf_an_plane_dist(w, q);
        int32_t m =
            grid_nearest(g, w, rf_v3_sub(q, rf_v3_scale(w->plane_n, 2 * d)), j, d > 0 ? -1 : 1);
        if (m >= 0 && !w->center[m])
            w->a->joints[j].mirror = m;
    }
    return true;
}
