/* Curve skeleton from the volume. The proxy is voxelised and closed (holes narrower than two
 * voxels sealed, and axis votes where wider ones let the flood in), a chamfer distance field
 * gives the thickness, geodesic distance from a root (the thickest point, or a seed) is cut into
 * bands, and every connected piece of a band becomes a node at its centroid, linked to the piece
 * of the band below it touches most. Pieces split where limbs leave the body, so junctions appear
 * by themselves; short side branches (bumps) are pruned against the body's thickness; chains are
 * cut into joints at even lengths, mirrored limbs alike. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rig-internal.h"

typedef struct rf_rig_grid {
    int nx, ny, nz;
    size_t n;
    double org[3], h;
    uint8_t *solid;
    int32_t *df;     /* chamfer 3-4-5 distance to the outside, in thirds of a voxel */
    uint32_t *comp;  /* solid component, NONE outside */
    double *geo;     /* geodesic distance from the component's root, in voxels */
    uint32_t *node;  /* band piece */
    uint32_t main;   /* the main solid component: the seed's, else the largest */
    double sym_n[3]; /* the body's mirror plane: points p with sym_n . p = sym_d ... */
    double sym_d;
    bool sym; /* ... when the body has one */
} rf_rig_grid;

typedef struct rf_rig_node {
    double sum[3];
    double sq[3][3]; /* sums of the voxels' coordinate products: the piece's spread */
    uint32_t count;
    uint32_t band, comp;
    int32_t maxdf;
    int32_t parent;
    uint32_t children; /* live children, while pruning */
    uint8_t dead;
    uint8_t end; /* left a leaf by pruning a mirrored pair of twigs: an end of the body */
    uint8_t leg; /* the end of a leg kept from pruning by rf_rig_stands_on */
} rf_rig_node;

typedef struct rf_rig_nodes {
    rf_rig_node *v;
    uint32_t n, cap;
} rf_rig_nodes;

static size_t rf_rig_at(const rf_rig_grid *g, int x, int y, int z)
{
    return ((size_t)z * g->ny + y) * g->nx + x;
}

static void rf_rig_xyz(const rf_rig_grid *g, size_t i, int *x, int *y, int *z)
{
    *x = (int)(i % g->nx), *y = (int)((i / g->nx) % g->ny), *z = (int)(i / ((size_t)g->nx * g->ny));
}

/* ---- voxelisation ---- */

static void rf_rig_mark(rf_rig_grid *g, uint8_t *surf, const double p[3])
{
    int c[3];
    for (int a = 0; a < 3; a++)
        c[a] = (int)floor((p[a] - g->org[a]) / g->h);
    if (c[0] >= 0 && c[1] >= 0 && c[2] >= 0 && c[0] < g->nx && c[1] < g->ny && c[2] < g->nz)
        surf[rf_rig_at(g, c[0], c[1], c[2])] = 1;
}

/* Every voxel a triangle passes through, sampled at a third of a voxel: the triangles whose
 * which[] flag equals want (all when which is NULL). */
static void rf_rig_raster(rf_rig_grid *g, const rf_rig_geo *m, const uint8_t *which, int want,
                          uint8_t *surf)
{
    for (uint32_t t = 0; t < m->nt; t++) {
        if (which && which[t] != want)
            continue;
        const double *a = m->p + (size_t)m->t[t * 3] * 3, *b = m->p + (size_t)m->t[t * 3 + 1] * 3,
                     *c = m->p + (size_t)m->t[t * 3 + 2] * 3;
        double e = 0;
        for (int k = 0; k < 3; k++)
            e = fmax(e, fmax(fabs(b[k] - a[k]), fmax(fabs(c[k] - a[k]), fabs(c[k] - b[k]))));
        int s = (int)ceil(e / (g->h / 3)) + 1;
        for (int i = 0; i <= s; i++)
            for (int j = 0; i + j <= s; j++) {
                double u = (double)i / s, v = (double)j / s, q[3];
                for (int k = 0; k < 3; k++)
                    q[k] = a[k] + (b[k] - a[k]) * u + (c[k] - a[k]) * v;
                rf_rig_mark(g, surf, q);
            }
    }
}

/* Marks in `out` every voxel reachable from the corner through 6-neighbours not in `wall`. */
static bool rf_rig_flood(const rf_rig_grid *g, const uint8_t *wall, uint8_t *out)
{
    size_t *queue = malloc(g->n * sizeof *queue);
    if (!queue)
        return false;
    size_t head = 0, tail = 0;
    memset(out, 0, g->n);
    out[0] = 1, queue[tail++] = 0;
    static const int d6[6][3] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                 {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
    while (head < tail) {
        int x, y, z;
        rf_rig_xyz(g, queue[head++], &x, &y, &z);
        for (int k = 0; k < 6; k++) {
            int a = x + d6[k][0], b = y + d6[k][1], c = z + d6[k][2];
            if (a < 0 || b < 0 || c < 0 || a >= g->nx || b >= g->ny || c >= g->nz)
                continue;
            size_t j = rf_rig_at(g, a, b, c);
            if (!out[j] && !wall[j])
                out[j] = 1, queue[tail++] = j;
        }
    }
    free(queue);
    return true;
}

/* Counts, per voxel, the axis directions (of six) in which a surface voxel lies between it and
 * the grid's edge, into votes. */
static void rf_rig_votes(const rf_rig_grid *g, const uint8_t *surf, uint8_t *votes)
{
    int dims[3] = {g->nx, g->ny, g->nz};
    size_t stride[3] = {1, (size_t)g->nx, (size_t)g->nx * g->ny};
    memset(votes, 0, g->n);
    for (int ax = 0; ax < 3; ax++) {
        int a1 = (ax + 1) % 3, a2 = (ax + 2) % 3;
        for (int u = 0; u < dims[a1]; u++)
            for (int w = 0; w < dims[a2]; w++) {
                size_t base = (size_t)u * stride[a1] + (size_t)w * stride[a2];
                int first = -1, last = -1;
                for (int i = 0; i < dims[ax]; i++)
                    if (surf[base + (size_t)i * stride[ax]]) {
                        last = i;
                        if (first < 0)
                            first = i;
                    }
                for (int i = 0; first >= 0 && i < dims[ax]; i++)
                    votes[base + (size_t)i * stride[ax]] += (i > first) + (i < last);
            }
    }
}

static int rf_rig_u64_cmp(const void *pa, const void *pb);

/* Per triangle, whether its loose part is open: some edge of the part not shared by exactly two
 * triangles. NULL when out of memory. */
static uint8_t *rf_rig_open_triangles(const rf_rig_geo *m, const uint32_t *part, uint32_t parts)
{
    size_t n = (size_t)m->nt * 3;
    uint64_t *e = malloc(n * sizeof *e + 1);
    uint8_t *open_part = calloc(parts + 1, 1), *open_tri = calloc(m->nt + 1, 1);
    if (!e || !open_part || !open_tri) {
        free(e), free(open_part), free(open_tri);
        return NULL;
    }
    for (uint32_t t = 0; t < m->nt; t++)
        for (int k = 0; k < 3; k++) {
            uint64_t a = m->t[t * 3 + k], b = m->t[t * 3 + (k + 1) % 3];
            e[t * 3 + k] = a < b ? a << 32 | b : b << 32 | a;
        }
    qsort(e, n, sizeof *e, rf_rig_u64_cmp);
    for (size_t i = 0, j; i < n; i = j) {
        for (j = i; j < n && e[j] == e[i];)
            j++;
        if (j - i != 2)
            open_part[part[(uint32_t)(e[i] >> 32)]] = 1;
    }
    for (uint32_t t = 0; t < m->nt; t++)
        open_tri[t] = open_part[part[m->t[t * 3]]];
    free(e), free(open_part);
    return open_tri;
}

/* The generalized winding number of the mesh at q (Jacobson et al. 2013): the triangles' signed
 * solid angles over 4 pi; about 1 inside a surface with holes, 0 outside, whichever way round. */
static double rf_rig_winding(const rf_rig_geo *m, const double q[3])
{
    double sum = 0;
    for (uint32_t t = 0; t < m->nt; t++) {
        double v[3][3], l[3];
        for (int k = 0; k < 3; k++) {
            const double *p = m->p + (size_t)m->t[t * 3 + k] * 3;
            v[k][0] = p[0] - q[0], v[k][1] = p[1] - q[1], v[k][2] = p[2] - q[2];
            l[k] = sqrt(v[k][0] * v[k][0] + v[k][1] * v[k][1] + v[k][2] * v[k][2]);
        }
        double det = v[0][0] * (v[1][1] * v[2][2] - v[1][2] * v[2][1]) -
                     v[0][1] * (v[1][0] * v[2][2] - v[1][2] * v[2][0]) +
                     v[0][2] * (v[1][0] * v[2][1] - v[1][1] * v[2][0]);
        double d01 = v[0][0] * v[1][0] + v[0][1] * v[1][1] + v[0][2] * v[1][2];
        double d02 = v[0][0] * v[2][0] + v[0][1] * v[2][1] + v[0][2] * v[2][2];
        double d12 = v[1][0] * v[2][0] + v[1][1] * v[2][1] + v[1][2] * v[2][2];
        sum += 2 * atan2(det, l[0] * l[1] * l[2] + d01 * l[2] + d02 * l[1] + d12 * l[0]);
    }
    return fabs(sum / (4 * M_PI));
}

/* Hole sealing (the thickening, the axis votes) also fills narrow gaps between parts: two legs a
 * few voxels apart, an arm along the body. Each voxel that only the sealing made solid (the
 * surface alone lets the flood reach it: plain_out) is kept only when the winding number puts it
 * inside. Skipped on big meshes, where it would cost more than the rest of the rig. */
static void rf_rig_winding_check(rf_rig_grid *g, const rf_rig_geo *m, const uint8_t *surf,
                                 const uint8_t *plain_out)
{
    size_t count = 0;
    for (size_t i = 0; i < g->n; i++)
        count += g->solid[i] && !surf[i] && plain_out[i];
    if ((double)count * m->nt > 3e7)
        return;
    for (size_t i = 0; i < g->n; i++) {
        if (!g->solid[i] || surf[i] || !plain_out[i])
            continue;
        int x, y, z;
        rf_rig_xyz(g, i, &x, &y, &z);
        double q[3] = {g->org[0] + (x + 0.5) * g->h, g->org[1] + (y + 0.5) * g->h,
                       g->org[2] + (z + 0.5) * g->h};
        g->solid[i] = rf_rig_winding(m, q) >= 0.5;
    }
}

/* Solid = the closed inside. The surfaces of open parts (holes, missing faces) are thickened by
 * one voxel to stop the flood from the corner (sealing small holes), and the thickening is taken
 * back where the flood touches it; closed parts have no holes to seal, so their surface alone
 * stops the flood and limbs a few voxels apart (legs side by side, an arm along the body) stay
 * apart. */
static bool rf_rig_voxelise(rf_rig_grid *g, const rf_rig_geo *m, const uint32_t *part,
                            uint32_t parts)
{
    uint8_t *surf = calloc(g->n, 1), *open = calloc(g->n, 1), *thick = calloc(g->n, 1),
            *out = malloc(g->n), *open_tri = rf_rig_open_triangles(m, part, parts);
    g->solid = calloc(g->n, 1);
    bool ok = surf && open && thick && out && g->solid && open_tri, any_open = false;
    if (ok) {
        rf_rig_raster(g, m, open_tri, 1, open);
        rf_rig_raster(g, m, open_tri, 0, surf);
        for (size_t i = 0; i < g->n; i++)
            surf[i] |= open[i], thick[i] = surf[i], any_open |= open[i];
        for (int z = 1; z < g->nz - 1; z++)
            for (int y = 1; y < g->ny - 1; y++)
                for (int x = 1; x < g->nx - 1; x++) {
                    if (!open[rf_rig_at(g, x, y, z)])
                        continue;
                    for (int dz = -1; dz <= 1; dz++)
                        for (int dy = -1; dy <= 1; dy++)
                            for (int dx = -1; dx <= 1; dx++)
                                thick[rf_rig_at(g, x + dx, y + dy, z + dz)] = 1;
                }
        ok = rf_rig_flood(g, thick, out);
    }
    for (int z = 1; ok && z < g->nz - 1; z++)
        for (int y = 1; y < g->ny - 1; y++)
            for (int x = 1; x < g->nx - 1; x++) {
                size_t i = rf_rig_at(g, x, y, z);
                if (out[i])
                    continue;
                bool touches = false;
                for (int dz = -1; dz <= 1 && !touches && thick[i] && !surf[i]; dz++)
                    for (int dy = -1; dy <= 1 && !touches; dy++)
                        for (int dx = -1; dx <= 1 && !touches; dx++)
                            touches = out[rf_rig_at(g, x + dx, y + dy, z + dz)];
                g->solid[i] = !touches;
            }
    /* Open parts with holes wider than the thickening let the flood in. Where their surface lies
     * between a voxel and the grid's edge in five of the six axis directions, the voxel is inside
     * all the same (a hole blocks one direction at most; the space between two legs is open in
     * three). */
    uint8_t *votes = ok && any_open ? out : NULL; /* the flood's array is no longer needed */
    if (votes) {
        rf_rig_votes(g, open, votes);
        for (size_t i = 0; i < g->n; i++)
            g->solid[i] |= votes[i] >= 5;
        ok = rf_rig_flood(g, surf, out) && (rf_rig_winding_check(g, m, surf, out), true);
    }
    free(surf), free(open), free(thick), free(out), free(open_tri);
    return ok;
}

/* ---- distance field ---- */

static void rf_rig_chamfer_pass(rf_rig_grid *g, int dir)
{
    int z0 = dir > 0 ? 0 : g->nz - 1, y0 = dir > 0 ? 0 : g->ny - 1, x0 = dir > 0 ? 0 : g->nx - 1;
    for (int z = z0; z >= 0 && z < g->nz; z += dir)
        for (int y = y0; y >= 0 && y < g->ny; y += dir)
            for (int x = x0; x >= 0 && x < g->nx; x += dir) {
                size_t i = rf_rig_at(g, x, y, z);
                if (!g->df[i])
                    continue;
                int32_t best = g->df[i];
                for (int dz = -1; dz <= 0; dz++)
                    for (int dy = -1; dy <= 1; dy++)
                        for (int dx = -1; dx <= 1; dx++) {
                            if (dz == 0 && (dy > 0 || (dy == 0 && dx >= 0)))
                                continue; /* only neighbours already visited in this pass */
                            int a = x + dx * dir, b = y + dy * dir, c = z + dz * dir;
                            if (a < 0 || b < 0 || c < 0 || a >= g->nx || b >= g->ny || c >= g->nz)
                                continue;
                            int k = abs(dx) + abs(dy) + abs(dz);
                            int32_t w = k == 1 ? 3 : k == 2 ? 4 : 5;
                            int32_t v = g->df[rf_rig_at(g, a, b, c)] + w;
                            best = v < best ? v : best;
                        }
                g->df[i] = best;
            }
}

static bool rf_rig_distance(rf_rig_grid *g)
{
    if (!(g->df = malloc(g->n * sizeof *g->df)))
        return false;
    for (size_t i = 0; i < g->n; i++)
        g->df[i] = g->solid[i] ? INT32_MAX / 2 : 0;
    rf_rig_chamfer_pass(g, 1);
    rf_rig_chamfer_pass(g, -1);
    return true;
}

/* ---- geodesic bands ---- */

/* The 26 neighbour offsets and their lengths. */
static int rf_rig_d26[26][3];
static double rf_rig_l26[26];
static void rf_rig_init26(void)
{
    int k = 0;
    for (int dz = -1; dz <= 1; dz++)
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++) {
                if (!dx && !dy && !dz)
                    continue;
                rf_rig_d26[k][0] = dx, rf_rig_d26[k][1] = dy, rf_rig_d26[k][2] = dz;
                rf_rig_l26[k++] = sqrt((double)(dx * dx + dy * dy + dz * dz));
            }
}

static bool rf_rig_neighbour(const rf_rig_grid *g, size_t i, int k, size_t *j)
{
    int x, y, z;
    rf_rig_xyz(g, i, &x, &y, &z);
    x += rf_rig_d26[k][0], y += rf_rig_d26[k][1], z += rf_rig_d26[k][2];
    if (x < 0 || y < 0 || z < 0 || x >= g->nx || y >= g->ny || z >= g->nz)
        return false;
    *j = rf_rig_at(g, x, y, z);
    return true;
}

/* ---- the mirror plane ---- */

/* Eigenvectors of the symmetric 3x3 matrix a (destroyed) into the columns of v, by Jacobi
 * rotations. */
static void rf_rig_eigen3(double a[3][3], double v[3][3])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            v[i][j] = i == j;
    for (int sweep = 0; sweep < 32; sweep++) {
        double off = fabs(a[0][1]) + fabs(a[0][2]) + fabs(a[1][2]);
        if (off < 1e-15 * (fabs(a[0][0]) + fabs(a[1][1]) + fabs(a[2][2]) + 1e-300))
            break;
        for (int p = 0; p < 2; p++)
            for (int q = p + 1; q < 3; q++) {
                if (a[p][q] == 0)
                    continue;
                double th = (a[q][q] - a[p][p]) / (2 * a[p][q]);
                double tn = (th >= 0 ? 1 : -1) / (fabs(th) + sqrt(th * th + 1));
                double c = 1 / sqrt(tn * tn + 1), sn = tn * c;
                for (int k = 0; k < 3; k++) { /* a = J^T a J */
                    double x = a[k][p], y = a[k][q];
                    a[k][p] = c * x - sn * y, a[k][q] = sn * x + c * y;
                }
                for (int k = 0; k < 3; k++) {
                    double x = a[p][k], y = a[q][k];
                    a[p][k] = c * x - sn * y, a[q][k] = sn * x + c * y;
                }
                for (int k = 0; k < 3; k++) {
                    double x = v[k][p], y = v[k][q];
                    v[k][p] = c * x - sn * y, v[k][q] = sn * x + c * y;
                }
            }
    }
}

/* The fraction of the sampled solid voxels whose mirror image across n . p = d is solid too. */
static double rf_rig_mirror_score(const rf_rig_grid *g, const size_t *pick, size_t np,
                                  const double n[3], double d)
{
    size_t hit = 0;
    for (size_t s = 0; s < np; s++) {
        int x, y, z;
        rf_rig_xyz(g, pick[s], &x, &y, &z);
        double p[3] = {g->org[0] + (x + 0.5) * g->h, g->org[1] + (y + 0.5) * g->h,
                       g->org[2] + (z + 0.5) * g->h};
        double off = n[0] * p[0] + n[1] * p[1] + n[2] * p[2] - d;
        int c[3];
        for (int a = 0; a < 3; a++)
            c[a] = (int)floor((p[a] - 2 * off * n[a] - g->org[a]) / g->h);
        if (c[0] >= 0 && c[1] >= 0 && c[2] >= 0 && c[0] < g->nx && c[1] < g->ny && c[2] < g->nz &&
            g->solid[rf_rig_at(g, c[0], c[1], c[2])])
            hit++;
    }
    return np ? (double)hit / np : 0;
}

#define RF_RIG_MIRROR_SAMPLES 5000
#define RF_RIG_MIRROR_MIN 0.8 /* mirrored solid over solid for a body to count as symmetric */

/* The body's mirror plane: of the planes square to its principal axes and to the grid's axes,
 * through its centroid or up to two voxels either side, the one that maps most of its solid
 * voxels onto solid ones (a sample of them). A body counts as symmetric when four in five map;
 * a posed or asymmetric body (a staff held out, a curled tail) then simply has no plane. */
static bool rf_rig_symmetry(rf_rig_grid *g)
{
    size_t count = 0;
    for (size_t i = 0; i < g->n; i++)
        count += g->solid[i] != 0;
    size_t stride = count / RF_RIG_MIRROR_SAMPLES + 1, np = 0;
    size_t *pick = malloc((count / stride + 1) * sizeof *pick);
    if (!pick)
        return false;
    double c[3] = {0}, m[3][3] = {{0}};
    for (size_t i = 0, seen = 0; i < g->n; i++)
        if (g->solid[i] && seen++ % stride == 0)
            pick[np++] = i;
    for (size_t s = 0; s < np; s++) {
        int x, y, z;
        rf_rig_xyz(g, pick[s], &x, &y, &z);
        double p[3] = {(x + 0.5) * g->h, (y + 0.5) * g->h, (z + 0.5) * g->h};
        for (int a = 0; a < 3; a++) {
            c[a] += p[a] / (double)np;
            for (int b = 0; b < 3; b++)
                m[a][b] += p[a] * p[b] / (double)np;
        }
    }
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
            m[a][b] -= c[a] * c[b];
    double v[3][3], best = 0;
    rf_rig_eigen3(m, v);
    for (int k = 0; np && k < 6; k++) {
        double n[3] = {k < 3 ? v[0][k] : k == 3, k < 3 ? v[1][k] : k == 4,
                       k < 3 ? v[2][k] : k == 5};
        double at = 0;
        for (int a = 0; a < 3; a++)
            at += n[a] * (c[a] + g->org[a]);
        for (int o = -4; o <= 4; o++) {
            double score = rf_rig_mirror_score(g, pick, np, n, at + o * g->h / 2);
            if (score > best) {
                best = score, g->sym_d = at + o * g->h / 2;
                memcpy(g->sym_n, n, sizeof n);
            }
        }
    }
    g->sym = best >= RF_RIG_MIRROR_MIN;
    free(pick);
    return true;
}

/* Labels solid components and grows geodesic distance in each from its thickest voxel. */
/* The solid voxel nearest the seed, preferring thick ones: a junction's centroid can lie between
 * the legs, outside, and its nearest voxel in one thigh. */
static size_t rf_rig_seed_voxel(const rf_rig_grid *g, const double *seed)
{
    size_t at = SIZE_MAX;
    double best = INFINITY;
    for (size_t i = 0; seed && i < g->n; i++) {
        if (!g->solid[i])
            continue;
        int x, y, z;
        rf_rig_xyz(g, i, &x, &y, &z);
        double d[3] = {g->org[0] + (x + 0.5) * g->h - seed[0],
                       g->org[1] + (y + 0.5) * g->h - seed[1],
                       g->org[2] + (z + 0.5) * g->h - seed[2]};
        double score = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) - g->df[i] / 3.0 * g->h;
        if (score < best)
            best = score, at = i;
    }
    return at;
}

/* Labels the solid's components (26-connected) into g->comp; their count into *ncomp, the
 * largest into g->main, each one's thickest voxel into thick[] (g->n entries, caller's). */
static bool rf_rig_components(rf_rig_grid *g, size_t *queue, size_t *thick, uint32_t *ncomp)
{
    size_t best = 0;
    *ncomp = 0;
    for (size_t i = 0; i < g->n; i++)
        g->comp[i] = RF_RIG_NONE, g->geo[i] = INFINITY;
    for (size_t s = 0; s < g->n; s++) {
        if (!g->solid[s] || g->comp[s] != RF_RIG_NONE)
            continue;
        size_t head = 0, tail = 0, root = s;
        g->comp[s] = *ncomp, queue[tail++] = s;
        while (head < tail) {
            size_t i = queue[head++], j;
            if (g->df[i] > g->df[root])
                root = i;
            for (int k = 0; k < 26; k++)
                if (rf_rig_neighbour(g, i, k, &j) && g->solid[j] && g->comp[j] == RF_RIG_NONE)
                    g->comp[j] = *ncomp, queue[tail++] = j;
        }
        thick[*ncomp] = root;
        if (tail > best)
            best = tail, g->main = *ncomp;
        (*ncomp)++;
    }
    return true;
}

/* Each other component grows from its voxel nearest the main component (breadth-first through
 * the whole grid), where it meets the body: a separate leg of a robot from its hip, not from its
 * thickest point. Overwrites thick[] for those components. */
static bool rf_rig_near_main(rf_rig_grid *g, size_t *queue, size_t *thick, uint32_t ncomp)
{
    uint32_t *dist = malloc(g->n * sizeof *dist);
    uint32_t *best = malloc((size_t)(ncomp ? ncomp : 1) * sizeof *best);
    if (!dist || !best) {
        free(dist), free(best);
        return false;
    }
    size_t head = 0, tail = 0;
    for (size_t i = 0; i < g->n; i++) {
        dist[i] = g->comp[i] == g->main ? 0 : UINT32_MAX;
        if (!dist[i])
            queue[tail++] = i;
    }
    while (head < tail) {
        size_t i = queue[head++], j;
        for (int k = 0; k < 26; k++)
            if (rf_rig_neighbour(g, i, k, &j) && dist[j] == UINT32_MAX)
                dist[j] = dist[i] + 1, queue[tail++] = j;
    }
    for (uint32_t c = 0; c < ncomp; c++)
        best[c] = UINT32_MAX;
    for (size_t i = 0; i < g->n; i++) {
        uint32_t c = g->comp[i];
        if (c != RF_RIG_NONE && c != g->main && dist[i] < best[c])
            best[c] = dist[i], thick[c] = i;
    }
    free(dist), free(best);
    return true;
}

/* Geodesic distance inside each component from its root: the seed's voxel (or the thickest)
 * for the main one, the voxel nearest the main one for the others. */
static bool rf_rig_geodesic(rf_rig_grid *g, const double *seed, uint32_t *ncomp)
{
    g->comp = malloc(g->n * sizeof *g->comp);
    g->geo = malloc(g->n * sizeof *g->geo);
    size_t *queue = malloc(g->n * sizeof *queue), *root = malloc(g->n * sizeof *root);
    rf_rig_heap h = {0};
    bool ok = g->comp && g->geo && queue && root && rf_rig_components(g, queue, root, ncomp) &&
              rf_rig_near_main(g, queue, root, *ncomp);
    size_t seed_at = ok ? rf_rig_seed_voxel(g, seed) : SIZE_MAX;
    if (seed_at != SIZE_MAX) {
        g->main = g->comp[seed_at];
        root[g->main] = seed_at;
    }
    for (uint32_t c = 0; ok && c < *ncomp; c++) {
        g->geo[root[c]] = 0;
        ok = rf_rig_heap_push(&h, 0, (uint32_t)root[c]);
    }
    double d;
    uint32_t i;
    while (ok && rf_rig_heap_pop(&h, &d, &i)) {
        if (d > g->geo[i])
            continue;
        size_t j;
        for (int k = 0; k < 26 && ok; k++)
            if (rf_rig_neighbour(g, i, k, &j) && g->solid[j] && d + rf_rig_l26[k] < g->geo[j]) {
                g->geo[j] = d + rf_rig_l26[k];
                ok = rf_rig_heap_push(&h, g->geo[j], (uint32_t)j);
            }
    }
    free(queue), free(root);
    rf_rig_heap_free(&h);
    return ok;
}

#define RF_RIG_BAND 2.0 /* voxels of geodesic distance per band */

static uint32_t rf_rig_band(const rf_rig_grid *g, size_t i)
{
    return (uint32_t)(g->geo[i] / RF_RIG_BAND);
}

static bool rf_rig_node_add(rf_rig_nodes *ns, uint32_t band, uint32_t comp)
{
    if (ns->n == ns->cap) {
        uint32_t cap = ns->cap ? ns->cap * 2 : 256;
        rf_rig_node *v = realloc(ns->v, cap * sizeof *v);
        if (!v)
            return false;
        ns->v = v, ns->cap = cap;
    }
    rf_rig_node *nd = &ns->v[ns->n++];
    memset(nd, 0, sizeof *nd);
    nd->band = band, nd->comp = comp, nd->parent = -1;
    return true;
}

/* Every connected piece of a band is a node. */
static bool rf_rig_pieces(rf_rig_grid *g, rf_rig_nodes *ns)
{
    g->node = malloc(g->n * sizeof *g->node);
    size_t *queue = malloc(g->n * sizeof *queue);
    bool ok = g->node && queue;
    for (size_t i = 0; ok && i < g->n; i++)
        g->node[i] = RF_RIG_NONE;
    for (size_t s = 0; ok && s < g->n; s++) {
        if (!g->solid[s] || g->node[s] != RF_RIG_NONE || !isfinite(g->geo[s]))
            continue;
        uint32_t band = rf_rig_band(g, s), id = ns->n;
        if (!(ok = rf_rig_node_add(ns, band, g->comp[s])))
            break;
        size_t head = 0, tail = 0;
        g->node[s] = id, queue[tail++] = s;
        while (head < tail) {
            size_t i = queue[head++], j;
            rf_rig_node *nd = &ns->v[id];
            int x, y, z;
            rf_rig_xyz(g, i, &x, &y, &z);
            nd->sum[0] += x, nd->sum[1] += y, nd->sum[2] += z;
            int c[3] = {x, y, z};
            for (int a = 0; a < 3; a++)
                for (int b = 0; b < 3; b++)
                    nd->sq[a][b] += (double)c[a] * c[b];
            nd->count++;
            nd->maxdf = g->df[i] > nd->maxdf ? g->df[i] : nd->maxdf;
            for (int k = 0; k < 26; k++)
                if (rf_rig_neighbour(g, i, k, &j) && g->solid[j] && g->node[j] == RF_RIG_NONE &&
                    isfinite(g->geo[j]) && rf_rig_band(g, j) == band)
                    g->node[j] = id, queue[tail++] = j;
        }
    }
    free(queue);
    return ok;
}

static int rf_rig_u64_cmp(const void *pa, const void *pb)
{
    uint64_t a = *(const uint64_t *)pa, b = *(const uint64_t *)pb;
    return a < b ? -1 : a > b;
}

/* Each node's parent: the piece of the band below that its voxels touch most. */
static bool rf_rig_link(const rf_rig_grid *g, rf_rig_nodes *ns)
{
    uint64_t *pairs = malloc(g->n * sizeof *pairs);
    if (!pairs)
        return false;
    size_t np = 0;
    for (size_t i = 0; i < g->n; i++) {
        if (g->node[i] == RF_RIG_NONE)
            continue;
        uint32_t me = g->node[i], band = ns->v[me].band;
        size_t j;
        for (int k = 0; k < 26 && band > 0; k++)
            if (rf_rig_neighbour(g, i, k, &j) && g->node[j] != RF_RIG_NONE &&
                ns->v[g->node[j]].band == band - 1) {
                pairs[np++] = (uint64_t)me << 32 | g->node[j];
                break;
            }
    }
    qsort(pairs, np, sizeof *pairs, rf_rig_u64_cmp);
    uint32_t best_count = 0;
    for (size_t i = 0; i < np;) {
        size_t e = i;
        while (e < np && pairs[e] == pairs[i])
            e++;
        uint32_t child = (uint32_t)(pairs[i] >> 32);
        if (i == 0 || (uint32_t)(pairs[i - 1] >> 32) != child)
            best_count = 0;
        if (e - i > best_count) {
            best_count = (uint32_t)(e - i);
            ns->v[child].parent = (int32_t)(uint32_t)pairs[i];
        }
        i = e;
    }
    free(pairs);
    return true;
}

/* ---- the node tree ---- */

typedef struct rf_rig_tree {
    const rf_rig_grid *g;
    rf_rig_nodes *ns;
    double (*pos)[3];   /* world centroid per node */
    double *radius;     /* world thickness per node */
    uint32_t main_comp; /* the largest solid component */
    double seg;         /* bone length, world units */
    double *len;        /* per leaf while pruning: how far its side branch reaches */
    double *score;      /* that over the length a limb needs (under 1: a bump) */
    uint32_t *start;    /* the side branch's first node, below its junction */
    uint32_t *far;      /* per node: the farthest band a pruned branch below it reached ... */
    double *far_r;      /* ... and that branch's thickness at its end */
    double floor, top;  /* the body's lowest and highest points along up (the frame's y) */
    double stand[4];    /* where legs scored as bumps leave the body, stand[3] 1 if any */
} rf_rig_tree;

static double rf_rig_dist3(const double *a, const double *b)
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2]));
}

static void rf_rig_count_children(rf_rig_tree *t)
{
    for (uint32_t i = 0; i < t->ns->n; i++)
        t->ns->v[i].children = 0;
    for (uint32_t i = 0; i < t->ns->n; i++)
        if (!t->ns->v[i].dead && t->ns->v[i].parent >= 0)
            t->ns->v[t->ns->v[i].parent].children++;
}

/* Prunes the shortest side branch shorter than the body is thick where it leaves; false when
 * none is left to prune. */
/* The farthest band each live node's subtree reaches, into reach[], and its leaf count (capped
 * at 2: a chain or not) into leaves[]. */
static void rf_rig_reach(const rf_rig_tree *t, uint32_t *reach, uint8_t *leaves)
{
    const rf_rig_node *v = t->ns->v;
    for (uint32_t i = 0; i < t->ns->n; i++)
        reach[i] = v[i].band, leaves[i] = 0;
    for (uint32_t i = 0; i < t->ns->n; i++) {
        if (v[i].dead || v[i].children)
            continue;
        for (int32_t k = (int32_t)i; k >= 0; k = v[k].parent) {
            reach[k] = reach[k] > v[i].band ? reach[k] : v[i].band;
            leaves[k] = leaves[k] < 2 ? leaves[k] + 1 : 2;
        }
    }
}

/* True when j sits at an extremity (all its branches end without branching again) and the
 * branch through its child c is shorter than half a bone and reaches less than 40% as far as
 * another: a heel beside the toes, an ear beside the top of the head. */
static bool rf_rig_twig(const rf_rig_tree *t, const uint32_t *reach, const uint8_t *leaves,
                        uint32_t j, uint32_t c)
{
    const rf_rig_node *v = t->ns->v;
    uint32_t mine = reach[c] - v[j].band, most = 0;
    for (uint32_t k = 0; k < t->ns->n; k++) {
        if (v[k].dead || v[k].parent != (int32_t)j)
            continue;
        if (leaves[k] > 1)
            return false;
        if (k != c && (v[k].comp != v[j].comp || reach[k] < v[j].band))
            continue; /* a part hanging from another: its bands do not compare */
        if (k != c && reach[k] - v[j].band > most)
            most = reach[k] - v[j].band;
    }
    return mine * 10 < most * 4 && mine * RF_RIG_BAND * t->g->h < 0.5 * t->seg;
}

/* Whether node k continues the chain above it: its parent has no other child and is no root. */
static bool rf_rig_chain_up(const rf_rig_node *v, uint32_t k)
{
    return v[k].parent >= 0 && v[v[k].parent].children == 1 && v[v[k].parent].parent >= 0;
}

/* A branch's own thickness: the mean thickness of the outer half of its chain from `leaf`, the
 * leaf itself left out. The inner half lies in the body it leaves (as thick as the body there),
 * and the leaf is where the distance field falls to nothing: with the whole chain's mean, the
 * bull frog's short box hind leg measured 3.3 times its thickness and was pruned as a bump. */
static double rf_rig_branch_thickness(const rf_rig_tree *t, uint32_t leaf)
{
    const rf_rig_node *v = t->ns->v;
    uint32_t count = 1;
    for (uint32_t k = leaf; rf_rig_chain_up(v, k); k = (uint32_t)v[k].parent)
        count++;
    if (count == 1)
        return t->radius[leaf];
    uint32_t outer = count / 2, n = 0; /* the nodes 1 .. outer up from the leaf */
    double sum = 0;
    for (uint32_t k = (uint32_t)v[leaf].parent; n < outer; k = (uint32_t)v[k].parent)
        sum += t->radius[k], n++;
    return sum / n;
}

/* The spread of node i's voxels (in voxels): along the unit normal n into *across, and the
 * largest spread of any direction square to n into *along. */
static void rf_rig_spread(const rf_rig_tree *t, uint32_t i, const double n[3], double *across,
                          double *along)
{
    const rf_rig_node *v = &t->ns->v[i];
    double m[3], c[3][3], e[3][3];
    for (int a = 0; a < 3; a++)
        m[a] = v->sum[a] / v->count;
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
            c[a][b] = v->sq[a][b] / v->count - m[a] * m[b];
    double cn[3] = {0}, nn = 0;
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
            cn[a] += c[a][b] * n[b];
    for (int a = 0; a < 3; a++)
        nn += n[a] * cn[a];
    /* c with its part along n taken out: (I - nn^T) c (I - nn^T) */
    double pc[3][3];
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
            pc[a][b] = c[a][b] - n[a] * cn[b] - cn[a] * n[b] + n[a] * n[b] * nn;
    rf_rig_eigen3(pc, e);
    double big = fmax(pc[0][0], fmax(pc[1][1], pc[2][2]));
    *across = sqrt(fmax(nn, 0)), *along = sqrt(fmax(big, 0));
}

#define RF_RIG_FIN_ACROSS 0.5 /* voxels: the spread of a sheet one voxel thick is 0 */
#define RF_RIG_FIN_ALONG 3.0  /* voxels: the spread within the plane a fin needs */
#define RF_RIG_FIN_OFF 2.5    /* voxels from the mirror plane, which may tilt a little */

/* Whether the side branch from `leaf` up to `start` is a fin: a sheet with no thickness of its
 * own (each band piece at most a voxel thick, wide within the plate), lying in the body's mirror
 * plane: a fish's dorsal or anal fin, a crest. Artists do not rig such a plate; the curve
 * skeleton runs a chain into each of its corners, and the skeleton analysis reads those as legs
 * and feet. A leg is round, not a sheet; a wing is a plate too but leaves the body sideways, in
 * pairs, never along its mirror plane. Voxels counted by weight, so the few voxels of a piece
 * at a corner do not decide. */
static bool rf_rig_fin(const rf_rig_tree *t, uint32_t leaf, uint32_t start)
{
    if (!t->g->sym)
        return false;
    const rf_rig_node *v = t->ns->v;
    const double *n = t->g->sym_n;
    for (uint32_t k = leaf;; k = (uint32_t)v[k].parent) { /* on the plane first: cheap */
        double o = n[0] * t->pos[k][0] + n[1] * t->pos[k][1] + n[2] * t->pos[k][2] - t->g->sym_d;
        if (fabs(o) > RF_RIG_FIN_OFF * t->g->h)
            return false;
        if (k == start)
            break;
    }
    double across = 0, along = 0, w = 0;
    for (uint32_t k = leaf;; k = (uint32_t)v[k].parent) {
        double a, l;
        rf_rig_spread(t, k, n, &a, &l);
        across += a * v[k].count, along += l * v[k].count, w += v[k].count;
        if (k == start)
            break;
    }
    return across <= RF_RIG_FIN_ACROSS * w && along >= RF_RIG_FIN_ALONG * w;
}

/* Whether node k is a piece of a sheet in the mirror plane: at most a voxel thick across it
 * and lying on it. */
static bool rf_rig_sheet_node(const rf_rig_tree *t, uint32_t k)
{
    const double *n = t->g->sym_n;
    double o = n[0] * t->pos[k][0] + n[1] * t->pos[k][1] + n[2] * t->pos[k][2] - t->g->sym_d, a, l;
    if (fabs(o) > RF_RIG_FIN_OFF * t->g->h)
        return false;
    rf_rig_spread(t, k, n, &a, &l);
    return a <= RF_RIG_FIN_ACROSS;
}

/* Chains that end in a fin end where the fin starts: a fish's tail runs on into its tail fin,
 * a sheet the curve skeleton crosses to one of its corners. From each leaf, the nodes that are
 * sheet pieces in the mirror plane (rf_rig_sheet_node) go when together they make a fin
 * (rf_rig_fin) and something thicker is left above them; bone heat gives the fin to the bone
 * that ends where it starts. */
static void rf_rig_trim_fins(rf_rig_tree *t)
{
    rf_rig_node *v = t->ns->v;
    if (!t->g->sym)
        return;
    for (uint32_t i = 0; i < t->ns->n; i++) {
        if (v[i].dead || v[i].children || v[i].parent < 0 || !rf_rig_sheet_node(t, i))
            continue;
        uint32_t top = i;
        while (v[top].parent >= 0 && v[v[top].parent].children == 1 &&
               v[v[top].parent].parent >= 0 && rf_rig_sheet_node(t, (uint32_t)v[top].parent))
            top = (uint32_t)v[top].parent;
        uint32_t above = (uint32_t)v[top].parent;
        if (rf_rig_sheet_node(t, above) || !rf_rig_fin(t, i, top))
            continue;
        for (uint32_t k = i;; k = (uint32_t)v[k].parent) {
            v[k].dead = 1;
            if (k == top)
                break;
        }
        v[above].children--;
    }
}

/* Each live leaf's side branch measured into t->len, t->score and t->start (score INFINITY:
 * not a side branch, so never pruned): how far it reaches beyond its junction, and that over
 * what a limb needs, the body's thickness where it leaves and 3.5 times its own thickness (a
 * limb is long and thin; a belly, a cheek or the corner of a box head is short and wide); 0 for
 * a twig at an extremity (rf_rig_twig). */
static void rf_rig_measure(rf_rig_tree *t, const uint32_t *reach, const uint8_t *leaves)
{
    rf_rig_node *v = t->ns->v;
    for (uint32_t i = 0; i < t->ns->n; i++) {
        t->score[i] = INFINITY;
        if (v[i].dead || v[i].children || v[i].parent < 0)
            continue;
        uint32_t k = i, far = i;
        for (; rf_rig_chain_up(v, k); k = (uint32_t)v[k].parent)
            far = t->far[k] > t->far[far] ? k : far;
        far = t->far[k] > t->far[far] ? k : far;
        if (v[k].parent < 0)
            continue;
        double thick = rf_rig_branch_thickness(t, i);
        uint32_t junction = (uint32_t)v[k].parent;
        /* how far the branch reaches beyond its junction along the body: its bands (centroid
         * distances mislead where a thin piece of a band lies far from the band's middle), or
         * the bumps pruned from it (a head's two ears: the head still reaches as far) */
        double len =
            (double)(t->far[far] - v[junction].band) * RF_RIG_BAND * t->g->h + t->far_r[far];
        bool apart = v[i].comp != v[junction].comp || v[i].band <= v[junction].band;
        if (apart) { /* a solid part hanging from another: its bands count from its own root */
            len = t->radius[i];
            for (uint32_t q = i; q != junction; q = (uint32_t)v[q].parent)
                len += rf_rig_dist3(t->pos[q], t->pos[v[q].parent]);
        }
        if (v[junction].children < 2 || v[i].end)
            continue;
        bool twig = !apart && (rf_rig_twig(t, reach, leaves, junction, k) || rf_rig_fin(t, i, k));
        t->len[i] = len, t->start[i] = k;
        t->score[i] = twig ? 0 : len / fmax(t->radius[junction], 3.5 * thick);
    }
}

/* The side branch leaf whose end lies nearest leaf i's mirror image across the body's plane,
 * within half of i's reach (at least two voxels), reaching between half and twice as far as
 * i's branch; NONE when the body has no plane, i ends on the plane (a tail, a snout: its own
 * image) or nothing mirrors it. */
static uint32_t rf_rig_mirror_leaf(const rf_rig_tree *t, uint32_t i)
{
    if (!t->g->sym)
        return RF_RIG_NONE;
    const double *p = t->pos[i], *n = t->g->sym_n;
    double off = n[0] * p[0] + n[1] * p[1] + n[2] * p[2] - t->g->sym_d;
    double tol = fmax(0.5 * t->len[i], 2 * t->g->h);
    if (fabs(off) < tol / 2)
        return RF_RIG_NONE;
    double q[3] = {p[0] - 2 * off * n[0], p[1] - 2 * off * n[1], p[2] - 2 * off * n[2]};
    uint32_t best = RF_RIG_NONE;
    double near = tol;
    for (uint32_t j = 0; j < t->ns->n; j++) {
        if (j == i || !isfinite(t->score[j]) || t->len[j] > 2 * t->len[i] ||
            2 * t->len[j] < t->len[i])
            continue;
        double d = rf_rig_dist3(q, t->pos[j]);
        if (d < near)
            near = d, best = j;
    }
    return best;
}

/* Kills the side branch of leaf i, from the leaf up to its junction, which keeps how far the
 * branch reached (within the same solid part). */
static void rf_rig_kill(rf_rig_tree *t, uint32_t i)
{
    rf_rig_node *v = t->ns->v;
    uint32_t junction = (uint32_t)v[t->start[i]].parent;
    for (uint32_t k = i;; k = (uint32_t)v[k].parent) {
        if (v[k].comp == v[junction].comp && t->far[k] > t->far[junction])
            t->far[junction] = t->far[k], t->far_r[junction] = t->far_r[k];
        if (k == t->start[i])
            break;
    }
    for (uint32_t k = i; k != t->start[i]; k = (uint32_t)v[k].parent)
        v[k].dead = 1;
    v[t->start[i]].dead = 1;
}

#define RF_RIG_STAND_LOW 0.2  /* of the body's height: where feet end */
#define RF_RIG_STAND_DROP 0.4 /* of the body's height: how far legs reach below their girdle */

/* Whether leaf i and its mirror image m are legs the body stands on: both leave one junction,
 * end in the lowest fifth of the body along up (the rigger's frame has the declared up as y)
 * and reach down from the junction at least 0.4 of the body's height. Such a pair is never a
 * bump. Measured by bands, a leg leaving the body across them (bands grown from the chest ring
 * the trunk and the leg's top together) reaches only as far as it hangs below the last band it
 * shares with the body: the fire dragon's box legs, under a thick body and a wingspan that sets
 * the bone length, scored as a heel beside its tail and went, the second pass found no feet to
 * grow from, and the skeleton analysis read the wings as the legs the body hangs from. An ear,
 * an eye, a jaw's corners, a bat's head lying low do not reach that far below where they leave
 * the body. */
static bool rf_rig_stands_on(const rf_rig_tree *t, uint32_t i, uint32_t m)
{
    if (m == RF_RIG_NONE)
        return false;
    const rf_rig_node *v = t->ns->v;
    int32_t junction = v[t->start[i]].parent;
    double h = t->top - t->floor, low = t->floor + RF_RIG_STAND_LOW * h;
    return junction >= 0 && junction == v[t->start[m]].parent && t->pos[i][1] < low &&
           t->pos[m][1] < low &&
           t->pos[junction][1] - fmax(t->pos[i][1], t->pos[m][1]) >= RF_RIG_STAND_DROP * h;
}

/* Prunes the shortest bump (a side branch scoring under 1) with its mirror image, if it has
 * one: a twig and its image are kept or dropped as one, by their mean score, so the rig of a
 * symmetric body comes out symmetric. Pruned one at a time, the second of two twigs alike (the
 * two eyes at the front of a head) no longer leaves a junction once the first is gone, and
 * stays as the chain's end. False when no bump is left. */
static bool rf_rig_prune_one(rf_rig_tree *t, uint32_t *reach, uint8_t *leaves)
{
    rf_rig_node *v = t->ns->v;
    rf_rig_reach(t, reach, leaves);
    rf_rig_measure(t, reach, leaves);
    double best = INFINITY;
    uint32_t best_leaf = RF_RIG_NONE, best_pair = RF_RIG_NONE;
    for (uint32_t i = 0; i < t->ns->n; i++) {
        if (!isfinite(t->score[i]) || t->len[i] >= best)
            continue;
        uint32_t m = rf_rig_mirror_leaf(t, i);
        double score = m == RF_RIG_NONE ? t->score[i] : (t->score[i] + t->score[m]) / 2;
        if (score < 1 && rf_rig_stands_on(t, i, m)) {
            const double *at = t->pos[v[t->start[i]].parent];
            if (!t->stand[3] || at[1] > t->stand[1])
                t->stand[0] = at[0], t->stand[1] = at[1], t->stand[2] = at[2], t->stand[3] = 1;
            v[i].leg = v[m].leg = 1;
            continue;
        }
        if (score < 1)
            best = t->len[i], best_leaf = i, best_pair = m;
    }
    if (best_leaf == RF_RIG_NONE)
        return false;
    rf_rig_kill(t, best_leaf);
    if (best_pair != RF_RIG_NONE)
        rf_rig_kill(t, best_pair);
    rf_rig_count_children(t);
    /* a junction the pair leaves a leaf is an end of the body (a head whose two ears, eyes or
     * box corners went): kept, as it was when one twig of the two went and the other carried
     * the chain on, and when both left it, it ends halfway between their ends: the body
     * reaches that far, on its middle */
    for (int e = 0; e < 2 && best_pair != RF_RIG_NONE; e++) {
        int32_t junction = v[t->start[e ? best_pair : best_leaf]].parent;
        if (v[junction].children)
            continue;
        v[junction].end = 1;
        if (junction == v[t->start[best_pair]].parent && !e)
            for (int a = 0; a < 3; a++)
                t->pos[junction][a] = 0.5 * (t->pos[best_leaf][a] + t->pos[best_pair][a]);
    }
    return true;
}

/* Pieces of other solid components hang, nearest first, from the nearest node of the tree grown
 * so far (Prim's order): a robot's separate legs from its torso, its torso from its head, rather
 * than everything from the largest part. */
static bool rf_rig_attach(rf_rig_tree *t)
{
    rf_rig_node *v = t->ns->v;
    uint32_t n = t->ns->n, nc = 0;
    for (uint32_t i = 0; i < n; i++)
        nc = v[i].comp + 1 > nc ? v[i].comp + 1 : nc;
    uint8_t *in = calloc(nc + 1, 1);
    if (!in)
        return false;
    in[t->main_comp] = 1;
    for (;;) {
        double best = INFINITY;
        uint32_t child = RF_RIG_NONE, to = 0;
        for (uint32_t i = 0; i < n; i++) {
            if (v[i].parent >= 0 || v[i].dead || in[v[i].comp])
                continue;
            for (uint32_t k = 0; k < n; k++)
                if (!v[k].dead && in[v[k].comp] && rf_rig_dist3(t->pos[i], t->pos[k]) < best)
                    best = rf_rig_dist3(t->pos[i], t->pos[k]), child = i, to = k;
        }
        if (child == RF_RIG_NONE)
            break;
        v[child].parent = (int32_t)to;
        in[v[child].comp] = 1;
    }
    free(in);
    return true;
}

/* ---- joints ---- */

typedef struct rf_rig_build {
    rf_rig_tree *t;
    rf_rig_skel *s;
    double seg;     /* bone length, world units */
    uint32_t *path; /* scratch */
    uint32_t cap;   /* joints s's arrays hold */
    bool full;      /* out of memory growing them: joints were left out */
} rf_rig_build;

/* Room in b->s for one joint more. A chain gives at most a joint per band piece, but a leg cut
 * along its polyline (rf_rig_chain) may take more joints than it has pieces, so the arrays,
 * sized by the pieces, grow when full. */
static bool rf_rig_joint_room(rf_rig_build *b)
{
    rf_rig_skel *s = b->s;
    if (s->n < b->cap)
        return true;
    uint32_t cap = b->cap > UINT32_MAX / 2 ? UINT32_MAX : 2 * b->cap + 8;
    double *pos = realloc(s->pos, (size_t)cap * 3 * sizeof *pos);
    s->pos = pos ? pos : s->pos;
    double *tip = pos ? realloc(s->tip, (size_t)cap * 3 * sizeof *tip) : NULL;
    s->tip = tip ? tip : s->tip;
    int32_t *parent = tip ? realloc(s->parent, (size_t)cap * sizeof *parent) : NULL;
    s->parent = parent ? parent : s->parent;
    uint8_t *has_tip = parent ? realloc(s->has_tip, cap) : NULL;
    s->has_tip = has_tip ? has_tip : s->has_tip;
    if (!has_tip || cap <= s->n)
        return false;
    memset(s->tip + (size_t)b->cap * 3, 0, (size_t)(cap - b->cap) * 3 * sizeof *s->tip);
    b->cap = cap;
    return true;
}

/* Adds a joint at p under `parent`; out of room (b->full), the parent stands for it. */
static uint32_t rf_rig_joint_add(rf_rig_build *b, const double p[3], int32_t parent)
{
    if (!rf_rig_joint_room(b)) {
        b->full = true;
        return parent >= 0 ? (uint32_t)parent : 0;
    }
    rf_rig_skel *s = b->s;
    uint32_t j = s->n++;
    memcpy(s->pos + (size_t)j * 3, p, 3 * sizeof(double));
    s->parent[j] = parent;
    s->has_tip[j] = 0;
    return j;
}

/* The path of a chain, from the key node above down to key node `to`, into b->path; returns its
 * point count and its length along the centroids into *arc_len. */
static uint32_t rf_rig_chain_path(rf_rig_build *b, uint32_t to, double *arc_len)
{
    rf_rig_node *v = b->t->ns->v;
    uint32_t len = 0;
    for (uint32_t k = to;; k = (uint32_t)v[k].parent) {
        b->path[len++] = k;
        if (v[k].parent < 0 || (len > 1 && v[k].children != 1))
            break;
    }
    for (uint32_t i = 0; i < len / 2; i++) {
        uint32_t x = b->path[i];
        b->path[i] = b->path[len - 1 - i], b->path[len - 1 - i] = x;
    }
    *arc_len = 0;
    for (uint32_t i = 1; i < len; i++)
        *arc_len += rf_rig_dist3(b->t->pos[b->path[i]], b->t->pos[b->path[i - 1]]);
    return len;
}

/* One chain cut into `pieces` bones of even length, hanging from joint from_joint. Returns the
 * joint at `to`, or for a leaf the last joint, which carries the leaf as its tip. */
static uint32_t rf_rig_chain(rf_rig_build *b, uint32_t to, uint32_t from_joint, bool leaf,
                             uint32_t pieces)
{
    double total;
    uint32_t len = rf_rig_chain_path(b, to, &total), joint = from_joint;
    double arc = 0;
    uint32_t next = 1; /* the next cut wanted, in pieces */
    if (b->t->ns->v[to].leg && len >= 2 && len < pieces + 1) {
        /* a leg with fewer band pieces than the cuts it needs: cut along the polyline */
        for (uint32_t i = 1; i < len && next < pieces; i++) {
            const double *p = b->t->pos[b->path[i - 1]], *q = b->t->pos[b->path[i]];
            double step = rf_rig_dist3(p, q);
            for (; next < pieces && step > 0 && arc + step >= total * next / pieces; next++) {
                double f = (total * next / pieces - arc) / step, at[3];
                for (int c = 0; c < 3; c++)
                    at[c] = p[c] + f * (q[c] - p[c]);
                joint = rf_rig_joint_add(b, at, (int32_t)joint);
            }
            arc += step;
        }
    }
    for (uint32_t i = 1; i + 1 < len && next < pieces; i++) {
        arc += rf_rig_dist3(b->t->pos[b->path[i]], b->t->pos[b->path[i - 1]]);
        double step = rf_rig_dist3(b->t->pos[b->path[i + 1]], b->t->pos[b->path[i]]);
        double want = total * next / pieces;
        /* cut at the path point nearest the wanted length */
        if (arc >= want || arc + step / 2 >= want) {
            joint = rf_rig_joint_add(b, b->t->pos[b->path[i]], (int32_t)joint);
            next++;
        }
    }
    const double *end = b->t->pos[b->path[len - 1]];
    if (leaf && joint != from_joint) {
        memcpy(b->s->tip + (size_t)joint * 3, end, 3 * sizeof(double));
        b->s->has_tip[joint] = 1;
    } else {
        joint = rf_rig_joint_add(b, end, (int32_t)joint);
    }
    return joint;
}

/* Bones per chain: its length over the bone length, rounded, at least 2 for a leaf (one joint
 * of its own to carry the tip). Sibling leaf chains of lengths within a quarter of each other
 * get the same count, so mirrored limbs come out with the same joints, which is what the
 * skeleton analysis pairs them by. */
static void rf_rig_pieces_of(rf_rig_build *b, const uint32_t *ends, uint32_t n, uint32_t *pieces)
{
    rf_rig_node *v = b->t->ns->v;
    double len[64];
    for (uint32_t i = 0; i < n && i < 64; i++) {
        rf_rig_chain_path(b, ends[i], &len[i]);
        pieces[i] = (uint32_t)fmax(1, floor(len[i] / b->seg + 0.5));
        if (!v[ends[i]].children && pieces[i] < 2)
            pieces[i] = 2;
        if (v[ends[i]].leg && pieces[i] < 3) /* a thigh, a shin and a foot */
            pieces[i] = 3;
    }
    for (uint32_t i = 0; i < n && i < 64; i++)
        for (uint32_t j = 0; j < n && j < 64; j++)
            if (!v[ends[i]].children && !v[ends[j]].children &&
                fabs(len[i] - len[j]) < 0.25 * fmax(len[i], len[j]) && pieces[j] > pieces[i])
                pieces[i] = pieces[j];
}

/* Walks the live tree from `root` depth-first without recursion, emitting joints chain by chain;
 * parents always precede children. */
static bool rf_rig_emit(rf_rig_build *b, uint32_t root)
{
    rf_rig_nodes *ns = b->t->ns;
    rf_rig_node *v = ns->v;
    uint32_t *stack = malloc((size_t)ns->n * 2 * sizeof *stack);
    uint32_t *first = calloc((size_t)ns->n + 1, sizeof *first),
             *kids = malloc(ns->n * sizeof *kids);
    uint32_t *fill = malloc(ns->n * sizeof *fill);
    if (!stack || !first || !kids || !fill) {
        free(stack), free(first), free(kids), free(fill);
        return false;
    }
    for (uint32_t i = 0; i < ns->n; i++)
        if (!v[i].dead && v[i].parent >= 0)
            first[v[i].parent + 1]++;
    for (uint32_t i = 0; i < ns->n; i++)
        first[i + 1] += first[i];
    memcpy(fill, first, ns->n * sizeof *fill);
    for (uint32_t i = 0; i < ns->n; i++)
        if (!v[i].dead && v[i].parent >= 0)
            kids[fill[v[i].parent]++] = i;
    size_t sp = 0;
    stack[sp++] = root, stack[sp++] = rf_rig_joint_add(b, b->t->pos[root], -1);
    while (sp) {
        uint32_t joint = stack[--sp], key = stack[--sp];
        uint32_t ends[64], pieces[64], n = 0;
        /* the key nodes below: a junction a short chain away is merged into this one (limbs
         * leave a body one band apart, the left a little before the right) */
        uint32_t todo[64], nt = 0;
        todo[nt++] = key;
        while (nt && n < 64) {
            uint32_t from = todo[--nt];
            for (uint32_t e = first[from]; e < first[from + 1] && n < 64; e++) {
                uint32_t k = kids[e];
                while (v[k].children == 1)
                    k = kids[first[k]];
                double len;
                rf_rig_chain_path(b, k, &len);
                double r = fmin(b->t->radius[key], b->t->radius[k]);
                if (v[k].children && len < fmax(1.5 * r, 0.75 * b->seg) && nt < 64)
                    todo[nt++] = k;
                else
                    ends[n++] = k;
            }
        }
        rf_rig_pieces_of(b, ends, n, pieces);
        for (uint32_t i = 0; i < n; i++) {
            uint32_t j = rf_rig_chain(b, ends[i], joint, v[ends[i]].children == 0, pieces[i]);
            if (v[ends[i]].children)
                stack[sp++] = ends[i], stack[sp++] = j;
        }
    }
    free(stack), free(first), free(kids), free(fill);
    return !b->full;
}

/* ---- entry ---- */

static void rf_rig_grid_free(rf_rig_grid *g)
{
    free(g->solid), free(g->df), free(g->comp), free(g->geo), free(g->node);
    memset(g, 0, sizeof *g);
}

static bool rf_rig_grid_make(rf_rig_grid *g, const rf_rig_prep *p, uint32_t res)
{
    memset(g, 0, sizeof *g);
    g->h = p->longest / res;
    int d[3];
    for (int a = 0; a < 3; a++) {
        d[a] = (int)ceil((p->hi[a] - p->lo[a]) / g->h) + 5;
        g->org[a] = p->lo[a] - 2.5 * g->h;
    }
    g->nx = d[0], g->ny = d[1], g->nz = d[2];
    g->n = (size_t)d[0] * d[1] * d[2];
    return true;
}

static bool rf_rig_tree_make(rf_rig_tree *t, const rf_rig_grid *g, rf_rig_nodes *ns)
{
    t->g = g, t->ns = ns;
    t->pos = malloc((size_t)(ns->n ? ns->n : 1) * sizeof *t->pos);
    t->radius = malloc((size_t)(ns->n ? ns->n : 1) * sizeof *t->radius);
    if (!t->pos || !t->radius)
        return false;
    uint32_t *size = calloc(ns->n + 1, sizeof *size);
    if (!size)
        return false;
    for (uint32_t i = 0; i < ns->n; i++) {
        for (int a = 0; a < 3; a++)
            t->pos[i][a] = g->org[a] + (ns->v[i].sum[a] / ns->v[i].count + 0.5) * g->h;
        t->radius[i] = ns->v[i].maxdf / 3.0 * g->h;
        if (ns->v[i].comp < ns->n)
            size[ns->v[i].comp] += ns->v[i].count;
    }
    t->main_comp = g->main;
    /* components too small to carry a bone of their own: heat reaches them from nearby bones */
    for (uint32_t i = 0; i < ns->n; i++)
        if (ns->v[i].comp != t->main_comp && size[ns->v[i].comp] < 64)
            ns->v[i].dead = 1;
    free(size);
    return true;
}

/* ---- contacts ---- */

/* Geodesic distance over the proxy's surface (its edges) from vertex src into d[] (INFINITY where
 * unreachable). */
static bool rf_rig_surface_geodesic(const rf_rig_geo *m, uint32_t src, double *d)
{
    uint32_t *start = calloc((size_t)m->nv + 1, sizeof *start);
    uint32_t *adj = malloc((size_t)m->nt * 6 * sizeof *adj + 1);
    rf_rig_heap h = {0};
    bool ok = start && adj;
    for (uint32_t t = 0; ok && t < m->nt; t++)
        for (int e = 0; e < 3; e++)
            start[m->t[t * 3 + e] + 1] += 2;
    for (uint32_t v = 0; ok && v < m->nv; v++)
        start[v + 1] += start[v];
    uint32_t *fill = ok ? calloc((size_t)m->nv + 1, sizeof *fill) : NULL;
    ok = ok && fill;
    for (uint32_t t = 0; ok && t < m->nt; t++)
        for (int e = 0; e < 3; e++) {
            uint32_t a = m->t[t * 3 + e], b = m->t[t * 3 + (e + 1) % 3];
            adj[start[a] + fill[a]++] = b;
            adj[start[b] + fill[b]++] = a;
        }
    for (uint32_t v = 0; v < m->nv; v++)
        d[v] = INFINITY;
    if (ok) {
        d[src] = 0;
        ok = rf_rig_heap_push(&h, 0, src);
    }
    double dv;
    uint32_t v;
    while (ok && rf_rig_heap_pop(&h, &dv, &v)) {
        if (dv > d[v])
            continue;
        for (uint32_t k = start[v]; k < start[v + 1]; k++) {
            uint32_t u = adj[k];
            double nd = dv + rf_rig_dist3(m->p + (size_t)v * 3, m->p + (size_t)u * 3);
            if (nd < d[u]) {
                d[u] = nd;
                ok = rf_rig_heap_push(&h, nd, u);
            }
        }
    }
    rf_rig_heap_free(&h);
    free(start), free(adj), free(fill);
    return ok;
}

/* A jump in distance along the surface between neighbouring voxels that makes a contact, as a
 * fraction of the longest edge: a hand on a hip is as far from it along the surface as the arm
 * and the flank are long together; the two sides of a crease or a thin plate are not. */
#define RF_RIG_CONTACT 0.3

/* Where the surface touches another stretch of the same part that lies far from it along the
 * surface (a hand on a hip), the volume joins what the mesh keeps apart, and the bands would
 * reach the arm through the hand. Each solid voxel takes a nearest proxy vertex (a breadth-first
 * flood from the vertices' voxels); the surface distance from the vertex nearest the seed,
 * compared across neighbouring voxels, bounds from below how far apart their vertices lie along
 * the surface. Where it jumps by more than RF_RIG_CONTACT, the far side's voxels (the hand's)
 * leave the solid, so the arm is reached through the shoulder. */

static bool rf_rig_cut_contacts(rf_rig_grid *g, const rf_rig_prep *p, const double *seed)
{
    const rf_rig_geo *m = &p->proxy;
    uint32_t *label = malloc(g->n * sizeof *label);
    size_t *queue = malloc(g->n * sizeof *queue);
    double *d = malloc((size_t)(m->nv ? m->nv : 1) * sizeof *d);
    uint8_t *cut = calloc(g->n, 1);
    bool ok = label && queue && d && cut && m->nv;
    uint32_t src = 0;
    double best = INFINITY;
    for (uint32_t v = 0; ok && v < m->nv; v++)
        if (rf_rig_dist3(m->p + (size_t)v * 3, seed) < best)
            best = rf_rig_dist3(m->p + (size_t)v * 3, seed), src = v;
    ok = ok && rf_rig_surface_geodesic(m, src, d);
    size_t head = 0, tail = 0;
    for (size_t i = 0; ok && i < g->n; i++)
        label[i] = RF_RIG_NONE;
    for (uint32_t v = 0; ok && v < m->nv; v++) {
        int c[3];
        for (int a = 0; a < 3; a++)
            c[a] = (int)((m->p[(size_t)v * 3 + a] - g->org[a]) / g->h);
        if (c[0] < 0 || c[1] < 0 || c[2] < 0 || c[0] >= g->nx || c[1] >= g->ny || c[2] >= g->nz)
            continue;
        size_t i = rf_rig_at(g, c[0], c[1], c[2]);
        if (g->solid[i] && label[i] == RF_RIG_NONE)
            label[i] = v, queue[tail++] = i;
    }
    while (ok && head < tail) {
        size_t i = queue[head++], j;
        for (int k = 0; k < 26; k++)
            if (rf_rig_neighbour(g, i, k, &j) && g->solid[j] && label[j] == RF_RIG_NONE)
                label[j] = label[i], queue[tail++] = j;
    }
    double jump = RF_RIG_CONTACT * p->longest;
    for (size_t i = 0; ok && i < g->n; i++) {
        size_t j;
        if (label[i] == RF_RIG_NONE || !isfinite(d[label[i]]))
            continue;
        for (int k = 0; k < 26; k++)
            if (rf_rig_neighbour(g, i, k, &j) && label[j] != RF_RIG_NONE && isfinite(d[label[j]]) &&
                p->proxy_part[label[j]] == p->proxy_part[label[i]] &&
                d[label[i]] - d[label[j]] > jump) {
                cut[i] = 1;
                break;
            }
    }
    for (size_t i = 0; ok && i < g->n; i++)
        if (cut[i])
            g->solid[i] = 0;
    free(label), free(queue), free(d), free(cut);
    return ok || !m->nv;
}

rf_rig_status rf_rig_extract(const rf_rig_prep *p, const rf_rig_options *o, const double *seed,
                             double *mirror, double *stand, rf_rig_skel *out, char *err, size_t n)
{
    rf_rig_status status = RF_RIG_OK;
    memset(out, 0, sizeof *out);
    rf_rig_init26();
    rf_rig_grid g;
    rf_rig_nodes ns = {0};
    rf_rig_tree t = {0};
    uint32_t ncomp = 0;
    rf_rig_grid_make(&g, p, o->resolution);
    bool ok = rf_rig_voxelise(&g, &p->proxy, p->proxy_part, p->proxy_parts) &&
              rf_rig_distance(&g) && rf_rig_symmetry(&g);
    if (ok && mirror) {
        for (int a = 0; a < 3; a++)
            mirror[a] = g.sym ? g.sym_n[a] : 0;
        mirror[3] = g.sym ? g.sym_d : 0;
    }
    ok = ok && (!seed || rf_rig_cut_contacts(&g, p, seed)) && rf_rig_geodesic(&g, seed, &ncomp) &&
         rf_rig_pieces(&g, &ns) && rf_rig_link(&g, &ns) && rf_rig_tree_make(&t, &g, &ns);
    if (!ok) {
        status = rf_rig_oom(err, n, "out of memory on a %dx%dx%d voxel grid", g.nx, g.ny, g.nz);
        goto done;
    }
    if (!ns.n) {
        status =
            rf_rig_refuse(err, n, "the mesh encloses no volume at %u voxels across", o->resolution);
        goto done;
    }
    t.seg = o->segment * p->longest;
    t.floor = p->lo[1], t.top = p->hi[1];
    if (!rf_rig_attach(&t)) {
        status = rf_rig_oom(err, n, "out of memory linking the mesh's parts");
        goto done;
    }
    rf_rig_count_children(&t);
    uint32_t *reach = malloc((size_t)ns.n * sizeof *reach);
    uint8_t *leaves = malloc(ns.n);
    t.len = malloc((size_t)ns.n * sizeof *t.len);
    t.score = malloc((size_t)ns.n * sizeof *t.score);
    t.start = malloc((size_t)ns.n * sizeof *t.start);
    t.far = malloc((size_t)ns.n * sizeof *t.far);
    t.far_r = malloc((size_t)ns.n * sizeof *t.far_r);
    bool pruning = reach && leaves && t.len && t.score && t.start && t.far && t.far_r;
    for (uint32_t i = 0; pruning && i < ns.n; i++)
        t.far[i] = ns.v[i].band, t.far_r[i] = t.radius[i];
    while (pruning && rf_rig_prune_one(&t, reach, leaves))
        ;
    rf_rig_trim_fins(&t);
    rf_rig_count_children(&t);
    if (stand)
        memcpy(stand, t.stand, sizeof t.stand);
    free(reach), free(leaves), free(t.len), free(t.score), free(t.start), free(t.far),
        free(t.far_r);
    t.len = NULL, t.score = NULL, t.start = NULL, t.far = NULL, t.far_r = NULL;
    if (!pruning) {
        status = rf_rig_oom(err, n, "out of memory pruning the skeleton");
        goto done;
    }
    uint32_t root = RF_RIG_NONE;
    for (uint32_t i = 0; i < ns.n; i++)
        if (ns.v[i].parent < 0 && !ns.v[i].dead && ns.v[i].comp == t.main_comp)
            root = i;
    /* the seed's component is the main one when there is a seed; a body whose main part kept
     * no piece is refused for what it is, not read as a lack of memory */
    if (root == RF_RIG_NONE) {
        status = rf_rig_refuse(err, n,
                               "the curve skeleton has no root joint: no piece of the body's "
                               "main part is left at %u voxels across",
                               o->resolution);
        goto done;
    }
    out->pos = malloc((size_t)ns.n * 3 * sizeof *out->pos);
    out->tip = calloc((size_t)ns.n * 3, sizeof *out->tip);
    out->parent = malloc((size_t)ns.n * sizeof *out->parent);
    out->has_tip = calloc(ns.n, 1);
    rf_rig_build b = {.t = &t, .s = out, .seg = o->segment * p->longest, .cap = ns.n};
    b.path = malloc((size_t)ns.n * sizeof *b.path);
    ok = out->pos && out->tip && out->parent && out->has_tip && b.path && rf_rig_emit(&b, root);
    free(b.path);
    if (!ok)
        status = rf_rig_oom(err, n, "out of memory building the skeleton");
done:
    free(t.pos), free(t.radius), free(ns.v);
    rf_rig_grid_free(&g);
    if (status != RF_RIG_OK)
        rf_rig_skel_free(out);
    return status;
}

bool rf_rig_skel_copy(const rf_rig_skel *k, rf_rig_skel *out)
{
    size_t n = (size_t)k->n + 1;
    memset(out, 0, sizeof *out);
    out->pos = malloc(n * 3 * sizeof *out->pos), out->tip = malloc(n * 3 * sizeof *out->tip);
    out->parent = malloc(n * sizeof *out->parent), out->has_tip = malloc(n);
    out->owns_in = k->owns_in ? malloc(n) : NULL;
    if (!out->pos || !out->tip || !out->parent || !out->has_tip || (k->owns_in && !out->owns_in)) {
        rf_rig_skel_free(out);
        return false;
    }
    out->n = k->n;
    memcpy(out->pos, k->pos, (size_t)k->n * 3 * sizeof *out->pos);
    memcpy(out->tip, k->tip, (size_t)k->n * 3 * sizeof *out->tip);
    memcpy(out->parent, k->parent, (size_t)k->n * sizeof *out->parent);
    memcpy(out->has_tip, k->has_tip, k->n);
    if (k->owns_in)
        memcpy(out->owns_in, k->owns_in, k->n);
    return true;
}

void rf_rig_skel_free(rf_rig_skel *s)
{
    free(s->pos), free(s->parent), free(s->tip), free(s->has_tip), free(s->owns_in);
    memset(s, 0, sizeof *s);
}
