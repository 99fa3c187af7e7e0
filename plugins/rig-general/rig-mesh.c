/* Mesh clean-up for the rigger: check the input, weld duplicate vertices, find the loose parts,
 * set specks aside and, for big meshes, simplify a proxy with meshoptimizer. Every input vertex
 * keeps a way back to the proxy (or is marked to take the proxy vertex nearest it), so no vertex is
 * left without weights. */
#include <inttypes.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include <meshoptimizer.h>
#include <rigflow/memory.h>

#include "rig-internal.h"

/* Formats a failed step's message into err (when there is room); the three callers below differ
 * only in what they return. */
static void rf_rig_say(char *err, size_t n, const char *fmt, va_list ap) RF_RIG_PRINTF(3, 0);

static void rf_rig_say(char *err, size_t n, const char *fmt, va_list ap)
{
    if (err && n)
        vsnprintf(err, n, fmt, ap);
}

bool rf_rig_fail(char *err, size_t n, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    rf_rig_say(err, n, fmt, ap);
    va_end(ap);
    return false;
}

rf_rig_status rf_rig_refuse(char *err, size_t n, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    rf_rig_say(err, n, fmt, ap);
    va_end(ap);
    return RF_RIG_REFUSED;
}

rf_rig_status rf_rig_oom(char *err, size_t n, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    rf_rig_say(err, n, fmt, ap);
    va_end(ap);
    return RF_RIG_NO_MEMORY;
}

/* ---- heap ---- */

bool rf_rig_heap_push(rf_rig_heap *h, double key, uint32_t id)
{
    if (h->n == h->cap) {
        size_t cap = h->cap ? h->cap * 2 : 1024;
        double *k = realloc(h->key, cap * sizeof *k);
        if (k)
            h->key = k;
        uint32_t *d = realloc(h->id, cap * sizeof *d);
        if (d)
            h->id = d;
        if (!k || !d)
            return false;
        h->cap = cap;
    }
    size_t i = h->n++;
    while (i > 0) {
        size_t up = (i - 1) / 2;
        if (h->key[up] <= key)
            break;
        h->key[i] = h->key[up], h->id[i] = h->id[up];
        i = up;
    }
    h->key[i] = key, h->id[i] = id;
    return true;
}

bool rf_rig_heap_pop(rf_rig_heap *h, double *key, uint32_t *id)
{
    if (!h->n)
        return false;
    *key = h->key[0], *id = h->id[0];
    double k = h->key[--h->n];
    uint32_t d = h->id[h->n];
    size_t i = 0;
    for (;;) {
        size_t c = 2 * i + 1;
        if (c >= h->n)
            break;
        if (c + 1 < h->n && h->key[c + 1] < h->key[c])
            c++;
        if (h->key[c] >= k)
            break;
        h->key[i] = h->key[c], h->id[i] = h->id[c];
        i = c;
    }
    h->key[i] = k, h->id[i] = d;
    return true;
}

void rf_rig_heap_free(rf_rig_heap *h)
{
    free(h->key);
    free(h->id);
    memset(h, 0, sizeof *h);
}

/* ---- input checks ---- */

static bool rf_rig_check_input(const rf_mesh *m, char *err, size_t n)
{
    if (!m || !m->vertex_count || !m->positions)
        return rf_rig_fail(err, n, "the mesh is empty: nothing to rig");
    if (!m->triangle_count || !m->triangles)
        return rf_rig_fail(err, n,
                           "the mesh has %u vertices but no triangles (a point cloud?): a rig "
                           "needs a surface that encloses a volume",
                           m->vertex_count);
    for (size_t i = 0; i < (size_t)m->vertex_count * 3; i++)
        if (!isfinite(m->positions[i]) || fabsf(m->positions[i]) > 1e30f)
            return rf_rig_fail(err, n, "vertex %zu has a non-finite or huge coordinate", i / 3);
    for (size_t i = 0; i < (size_t)m->triangle_count * 3; i++)
        if (m->triangles[i] >= m->vertex_count)
            return rf_rig_fail(err, n, "triangle %zu names vertex %u of %u", i / 3, m->triangles[i],
                               m->vertex_count);
    return true;
}

/* What cleaning, weighting and the output take beyond the imported mesh: 94 bytes a vertex
 * at the peak on a 12-million-vertex scan (4 million triangles), rounded up, and the triangles'
 * share of it for meshes that index their vertices. */
#define RF_RIG_BYTES_PER_VERTEX 100
#define RF_RIG_BYTES_PER_TRIANGLE 40

bool rf_rig_memory_fits(uint64_t vertices, uint64_t triangles, bool known, uint64_t available,
                        char *err, size_t n)
{
    uint64_t need = vertices * RF_RIG_BYTES_PER_VERTEX + triangles * RF_RIG_BYTES_PER_TRIANGLE;
    if (!known || need <= available)
        return true;
    return rf_rig_fail(err, n,
                       "the mesh is too large for the memory left: %" PRIu64
                       " vertices and %" PRIu64
                       " triangles need about %.1f GB to rig and %.1f GB is available; simplify "
                       "it first (a few hundred thousand triangles rig as well)",
                       vertices, triangles, need / 1e9, available / 1e9);
}

/* Bone heat's weights, CHOLMOD's right-hand sides and its solution: a double per proxy vertex
 * and joint each. A given skeleton's joint count is the file's (up to 65535), so this, not the
 * mesh, can be what does not fit. */
#define RF_RIG_BYTES_PER_WEIGHT 24

bool rf_rig_heat_fits(uint64_t vertices, uint64_t joints, bool known, uint64_t available, char *err,
                      size_t n)
{
    uint64_t need = vertices * joints * RF_RIG_BYTES_PER_WEIGHT;
    if (!known || need <= available)
        return true;
    return rf_rig_fail(err, n,
                       "bone heat over %" PRIu64 " vertices for %" PRIu64
                       " joints needs about %.1f GB and %.1f GB is available; mark the joints "
                       "that carry no skin unweighted or simplify the mesh first",
                       vertices, joints, need / 1e9, available / 1e9);
}

/* ---- welding ---- */

typedef struct rf_rig_key {
    int64_t k[3];
    uint32_t v;
} rf_rig_key;

static int rf_rig_key_cmp(const void *pa, const void *pb)
{
    const rf_rig_key *a = pa, *b = pb;
    for (int i = 0; i < 3; i++)
        if (a->k[i] != b->k[i])
            return a->k[i] < b->k[i] ? -1 : 1;
    return a->v < b->v ? -1 : a->v > b->v;
}

static void rf_rig_bbox_f(const rf_mesh *m, double lo[3], double hi[3])
{
    for (int a = 0; a < 3; a++)
        lo[a] = INFINITY, hi[a] = -INFINITY;
    for (uint32_t v = 0; v < m->vertex_count; v++)
        for (int a = 0; a < 3; a++) {
            double x = m->positions[(size_t)v * 3 + a];
            lo[a] = fmin(lo[a], x), hi[a] = fmax(hi[a], x);
        }
}

/* Vertices closer than a millionth of the mesh's size become one. weld[v] gets the new index. */
static bool rf_rig_weld(const rf_mesh *m, uint32_t *weld, uint32_t *count)
{
    double lo[3], hi[3];
    rf_rig_bbox_f(m, lo, hi);
    double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                       (hi[2] - lo[2]) * (hi[2] - lo[2]));
    double cell = diag > 0 ? diag * 1e-6 : 1.0;
    rf_rig_key *keys = malloc((size_t)m->vertex_count * sizeof *keys);
    if (!keys)
        return false;
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        for (int a = 0; a < 3; a++)
            keys[v].k[a] = (int64_t)floor((m->positions[(size_t)v * 3 + a] - lo[a]) / cell + 0.5);
        keys[v].v = v;
    }
    qsort(keys, m->vertex_count, sizeof *keys, rf_rig_key_cmp);
    uint32_t c = 0;
    for (uint32_t i = 0; i < m->vertex_count; i++) {
        if (i && memcmp(keys[i].k, keys[i - 1].k, sizeof keys[i].k) != 0)
            c++;
        weld[keys[i].v] = c;
    }
    *count = m->vertex_count ? c + 1 : 0;
    free(keys);
    return true;
}

/* ---- loose parts ---- */

static uint32_t rf_rig_find(uint32_t *up, uint32_t x)
{
    while (up[x] != x)
        x = up[x] = up[up[x]];
    return x;
}

static void rf_rig_union(uint32_t *up, uint32_t a, uint32_t b)
{
    a = rf_rig_find(up, a), b = rf_rig_find(up, b);
    if (a != b)
        up[a > b ? a : b] = a < b ? a : b;
}

/* The working state of rf_rig_prepare. */
typedef struct rf_rig_clean {
    const rf_mesh *m;
    uint32_t *weld; /* [input vertex] welded index */
    uint32_t nw;    /* welded vertices */
    double *wp;     /* [nw][3] welded positions */
    uint32_t *tris; /* welded, non-degenerate triangles */
    uint32_t nt;
    uint32_t *part; /* [nw] loose part (root of the union), NONE for stray vertices */
    uint8_t *speck; /* [nw] 1 where the vertex belongs to a speck */
} rf_rig_clean;

static bool rf_rig_welded_triangles(rf_rig_clean *c)
{
    const rf_mesh *m = c->m;
    c->wp = calloc((size_t)c->nw * 3, sizeof *c->wp);
    c->tris = malloc((size_t)m->triangle_count * 3 * sizeof *c->tris);
    if (!c->wp || !c->tris)
        return false;
    for (uint32_t v = 0; v < m->vertex_count; v++)
        for (int a = 0; a < 3; a++)
            c->wp[(size_t)c->weld[v] * 3 + a] = m->positions[(size_t)v * 3 + a];
    c->nt = 0;
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        uint32_t a = c->weld[m->triangles[t * 3]], b = c->weld[m->triangles[t * 3 + 1]],
                 d = c->weld[m->triangles[t * 3 + 2]];
        if (a == b || b == d || a == d)
            continue;
        c->tris[c->nt * 3] = a, c->tris[c->nt * 3 + 1] = b, c->tris[c->nt * 3 + 2] = d;
        c->nt++;
    }
    return true;
}

/* Parts by union-find over the triangles; a part whose box spans less than speck_size of the
 * whole box's diagonal is a speck. Returns the part count through *parts, specks in *specks. */
static bool rf_rig_parts(rf_rig_clean *c, double speck_size, uint32_t *parts, uint32_t *specks)
{
    uint32_t *up = malloc((size_t)c->nw * sizeof *up);
    c->part = malloc((size_t)c->nw * sizeof *c->part);
    c->speck = calloc(c->nw ? c->nw : 1, 1);
    double *box = malloc((size_t)c->nw * 6 * sizeof *box);
    uint8_t *used = calloc(c->nw ? c->nw : 1, 1);
    bool ok = up && c->part && c->speck && box && used;
    if (ok) {
        for (uint32_t v = 0; v < c->nw; v++)
            up[v] = v;
        for (uint32_t t = 0; t < c->nt; t++) {
            const uint32_t *x = c->tris + t * 3;
            rf_rig_union(up, x[0], x[1]), rf_rig_union(up, x[1], x[2]);
            used[x[0]] = used[x[1]] = used[x[2]] = 1;
        }
        double all_lo[3] = {INFINITY, INFINITY, INFINITY},
               all_hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (uint32_t v = 0; v < c->nw; v++)
            for (int a = 0; a < 3; a++)
                box[v * 6 + a] = INFINITY, box[v * 6 + 3 + a] = -INFINITY;
        *parts = 0;
        for (uint32_t v = 0; v < c->nw; v++) {
            c->part[v] = used[v] ? rf_rig_find(up, v) : RF_RIG_NONE;
            if (!used[v])
                continue;
            *parts += c->part[v] == v;
            double *b = box + (size_t)c->part[v] * 6;
            for (int a = 0; a < 3; a++) {
                double x = c->wp[(size_t)v * 3 + a];
                b[a] = fmin(b[a], x), b[3 + a] = fmax(b[3 + a], x);
                all_lo[a] = fmin(all_lo[a], x), all_hi[a] = fmax(all_hi[a], x);
            }
        }
        double all = 0;
        for (int a = 0; a < 3; a++)
            all += (all_hi[a] - all_lo[a]) * (all_hi[a] - all_lo[a]);
        *specks = 0;
        for (uint32_t v = 0; v < c->nw; v++) {
            if (c->part[v] == RF_RIG_NONE)
                continue;
            const double *b = box + (size_t)c->part[v] * 6;
            double d = 0;
            for (int a = 0; a < 3; a++)
                d += (b[3 + a] - b[a]) * (b[3 + a] - b[a]);
            c->speck[v] = d < speck_size * speck_size * all;
            *specks += c->speck[v] && c->part[v] == v;
        }
    }
    free(up);
    free(box);
    free(used);
    return ok;
}

/* ---- proxy ---- */

/* The body: triangles of non-speck parts, with their own compact vertex numbering. */
static bool rf_rig_body(const rf_rig_clean *c, rf_rig_geo *g, uint32_t *w2b)
{
    memset(g, 0, sizeof *g);
    for (uint32_t v = 0; v < c->nw; v++)
        w2b[v] = RF_RIG_NONE;
    g->t = malloc((size_t)(c->nt ? c->nt : 1) * 3 * sizeof *g->t);
    if (!g->t)
        return false;
    for (uint32_t t = 0; t < c->nt; t++) {
        const uint32_t *x = c->tris + t * 3;
        if (c->speck[x[0]])
            continue;
        for (int k = 0; k < 3; k++) {
            if (w2b[x[k]] == RF_RIG_NONE)
                w2b[x[k]] = g->nv++;
            g->t[g->nt * 3 + k] = w2b[x[k]];
        }
        g->nt++;
    }
    g->p = malloc((size_t)(g->nv ? g->nv : 1) * 3 * sizeof *g->p);
    if (!g->p)
        return false;
    for (uint32_t v = 0; v < c->nw; v++)
        if (w2b[v] != RF_RIG_NONE)
            memcpy(g->p + (size_t)w2b[v] * 3, c->wp + (size_t)v * 3, 3 * sizeof(double));
    return true;
}

/* Simplifies `body` to about `target` triangles into `proxy`; b2p[body vertex] gets the proxy
 * vertex, or NONE for vertices the simplifier dropped. */
static bool rf_rig_simplify(const rf_rig_geo *body, uint32_t target, rf_rig_geo *proxy,
                            uint32_t *b2p)
{
    memset(proxy, 0, sizeof *proxy);
    float *fp = malloc((size_t)body->nv * 3 * sizeof *fp);
    uint32_t *idx = malloc((size_t)body->nt * 3 * sizeof *idx);
    bool ok = fp && idx;
    size_t n = 0;
    if (ok) {
        for (size_t i = 0; i < (size_t)body->nv * 3; i++)
            fp[i] = (float)body->p[i];
        n = meshopt_simplify(idx, body->t, (size_t)body->nt * 3, fp, body->nv, 3 * sizeof(float),
                             (size_t)target * 3, 0.02f, 0, NULL);
        /* Borders and tight error bounds can stop the careful simplifier early; the sloppy one
         * always reaches the target (it may merge thin features, fine for a heat proxy). */
        if (n > (size_t)target * 3 * 3 / 2)
            n = meshopt_simplifySloppy(idx, body->t, (size_t)body->nt * 3, fp, body->nv,
                                       3 * sizeof(float), (size_t)target * 3, 0.05f, NULL);
    }
    for (uint32_t v = 0; ok && v < body->nv; v++)
        b2p[v] = RF_RIG_NONE;
    proxy->t = ok ? malloc((n ? n : 3) * sizeof *proxy->t) : NULL;
    proxy->p = ok ? malloc((size_t)(body->nv ? body->nv : 1) * 3 * sizeof *proxy->p) : NULL;
    ok = ok && proxy->t && proxy->p;
    for (size_t i = 0; ok && i < n; i++) {
        uint32_t v = idx[i];
        if (b2p[v] == RF_RIG_NONE) {
            b2p[v] = proxy->nv++;
            memcpy(proxy->p + (size_t)b2p[v] * 3, body->p + (size_t)v * 3, 3 * sizeof(double));
        }
        proxy->t[i] = b2p[v];
    }
    proxy->nt = (uint32_t)(n / 3);
    free(fp);
    free(idx);
    return ok;
}

/* Every body vertex the simplifier dropped takes the proxy vertex nearest along the body's
 * edges (so weights never jump across a gap between legs); vertices no proxy vertex reaches
 * stay NONE and take the proxy vertex nearest them in space. */
static bool rf_rig_carry(const rf_rig_geo *body, uint32_t *b2p)
{
    uint32_t nv = body->nv;
    uint32_t *deg = calloc((size_t)nv + 1, sizeof *deg);
    uint32_t *adj = malloc((size_t)body->nt * 6 * sizeof *adj);
    double *dist = malloc((size_t)(nv ? nv : 1) * sizeof *dist);
    rf_rig_heap h = {0};
    bool ok = deg && adj && dist;
    for (uint32_t t = 0; ok && t < body->nt; t++)
        for (int k = 0; k < 3; k++)
            deg[body->t[t * 3 + k] + 1] += 2;
    for (uint32_t v = 0; ok && v < nv; v++)
        deg[v + 1] += deg[v];
    uint32_t *fill = ok ? malloc((size_t)(nv ? nv : 1) * sizeof *fill) : NULL;
    ok = ok && fill;
    if (ok) {
        memcpy(fill, deg, (size_t)nv * sizeof *fill);
        for (uint32_t t = 0; t < body->nt; t++)
            for (int k = 0; k < 3; k++) {
                uint32_t a = body->t[t * 3 + k];
                adj[fill[a]++] = body->t[t * 3 + (k + 1) % 3];
                adj[fill[a]++] = body->t[t * 3 + (k + 2) % 3];
            }
        for (uint32_t v = 0; v < nv; v++) {
            dist[v] = b2p[v] != RF_RIG_NONE ? 0 : INFINITY;
            if (b2p[v] != RF_RIG_NONE)
                ok = ok && rf_rig_heap_push(&h, 0, v);
        }
    }
    double d;
    uint32_t v;
    while (ok && rf_rig_heap_pop(&h, &d, &v)) {
        if (d > dist[v])
            continue;
        for (uint32_t e = deg[v]; e < deg[v + 1]; e++) {
            uint32_t u = adj[e];
            const double *a = body->p + (size_t)v * 3, *b = body->p + (size_t)u * 3;
            double nd = d + sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                                 (a[2] - b[2]) * (a[2] - b[2]));
            if (nd < dist[u]) {
                dist[u] = nd, b2p[u] = b2p[v];
                ok = rf_rig_heap_push(&h, nd, u);
            }
        }
    }
    rf_rig_heap_free(&h);
    free(deg);
    free(adj);
    free(dist);
    free(fill);
    return ok;
}

static void rf_rig_geo_free(rf_rig_geo *g)
{
    free(g->p);
    free(g->t);
    memset(g, 0, sizeof *g);
}

/* Parts of the proxy (for the heat solve, which needs heat in every part). */
static bool rf_rig_proxy_parts(rf_rig_prep *p)
{
    uint32_t nv = p->proxy.nv;
    uint32_t *up = malloc((size_t)(nv ? nv : 1) * sizeof *up);
    p->proxy_part = malloc((size_t)(nv ? nv : 1) * sizeof *p->proxy_part);
    if (!up || !p->proxy_part) {
        free(up);
        return false;
    }
    for (uint32_t v = 0; v < nv; v++)
        up[v] = v;
    for (uint32_t t = 0; t < p->proxy.nt; t++) {
        rf_rig_union(up, p->proxy.t[t * 3], p->proxy.t[t * 3 + 1]);
        rf_rig_union(up, p->proxy.t[t * 3 + 1], p->proxy.t[t * 3 + 2]);
    }
    p->proxy_parts = 0;
    for (uint32_t v = 0; v < nv; v++) {
        uint32_t r = rf_rig_find(up, v);
        p->proxy_part[v] = r == v ? p->proxy_parts++ : p->proxy_part[r];
    }
    free(up);
    return true;
}

/* A mesh far from its origin for its size (a scan kept in survey coordinates) reaches us in
 * single precision, whose steps grow with the distance: a body of 1 at 1e7 has lost everything
 * finer than 1, and would read as flat or as a staircase. Refused with where it lies when the
 * steps pass a sixty-fourth of the body (a voxel of the coarsest grid), not rigged wrongly. */
static bool rf_rig_precise(const rf_rig_prep *p, char *err, size_t n)
{
    double far = 0;
    for (int a = 0; a < 3; a++)
        far = fmax(far, fmax(fabs(p->lo[a]), fabs(p->hi[a])));
    double step = far * FLT_EPSILON;
    if (step <= p->longest / 64)
        return true;
    return rf_rig_fail(err, n,
                       "the mesh lies %.3g from its origin, %.3g times its size: its "
                       "single-precision coordinates there keep steps of %.3g, %.0f%% of its "
                       "size, too coarse to rig (move it near the origin)",
                       far, far / p->longest, step, 100 * step / p->longest);
}

static bool rf_rig_bbox(rf_rig_prep *p, char *err, size_t n)
{
    for (int a = 0; a < 3; a++)
        p->lo[a] = INFINITY, p->hi[a] = -INFINITY;
    for (uint32_t v = 0; v < p->proxy.nv; v++)
        for (int a = 0; a < 3; a++) {
            p->lo[a] = fmin(p->lo[a], p->proxy.p[(size_t)v * 3 + a]);
            p->hi[a] = fmax(p->hi[a], p->proxy.p[(size_t)v * 3 + a]);
        }
    double e[3], shortest = INFINITY;
    p->longest = 0;
    for (int a = 0; a < 3; a++) {
        e[a] = p->hi[a] - p->lo[a];
        p->longest = fmax(p->longest, e[a]), shortest = fmin(shortest, e[a]);
    }
    if (!(p->longest > 0))
        return rf_rig_fail(err, n, "the mesh has no extent: all its vertices coincide");
    if (!rf_rig_precise(p, err, n))
        return false;
    if (shortest < 1e-3 * p->longest)
        return rf_rig_fail(err, n,
                           "the mesh is flat (%.3g by %.3g by %.3g): a rig needs a volume, not a "
                           "sheet",
                           e[0], e[1], e[2]);
    return true;
}

rf_rig_status rf_rig_prepare(const rf_mesh *m, const rf_rig_options *o, rf_rig_prep *out,
                             rf_rig_stats *st, char *err, size_t n)
{
    memset(out, 0, sizeof *out);
    uint64_t available = 0;
    bool known = rf_memory_available(&available);
    if (!rf_rig_check_input(m, err, n) ||
        !rf_rig_memory_fits(m->vertex_count, m->triangle_count, known, available, err, n))
        return RF_RIG_REFUSED;
    rf_rig_clean c = {.m = m};
    rf_rig_geo body = {0};
    uint32_t *w2b = NULL, *b2p = NULL;
    rf_rig_status status = RF_RIG_OK;
    bool ok = (c.weld = malloc((size_t)m->vertex_count * sizeof *c.weld)) &&
              rf_rig_weld(m, c.weld, &c.nw) && rf_rig_welded_triangles(&c) &&
              rf_rig_parts(&c, o->speck_size, &st->parts, &st->specks) &&
              (w2b = malloc((size_t)c.nw * sizeof *w2b)) && rf_rig_body(&c, &body, w2b);
    if (!ok) {
        status =
            rf_rig_oom(err, n, "out of memory cleaning a mesh of %u vertices", m->vertex_count);
        goto done;
    }
    st->vertices = m->vertex_count, st->welded = c.nw;
    if (!body.nt) {
        if (c.nt)
            status = rf_rig_refuse(err, n,
                                   "the mesh is nothing but specks: %u loose parts, none "
                                   "spanning %.0f%% of the whole",
                                   st->parts, o->speck_size * 100);
        else
            status = rf_rig_refuse(err, n, "the mesh has only degenerate triangles (%u of them)",
                                   m->triangle_count);
        goto done;
    }
    ok = (b2p = malloc((size_t)body.nv * sizeof *b2p)) != NULL;
    if (ok && body.nt > o->proxy_triangles) {
        ok = rf_rig_simplify(&body, o->proxy_triangles, &out->proxy, b2p) &&
             rf_rig_carry(&body, b2p);
    } else if (ok) {
        for (uint32_t v = 0; v < body.nv; v++)
            b2p[v] = v;
        out->proxy = body;
        memset(&body, 0, sizeof body);
    }
    ok = ok && (out->to_proxy = malloc((size_t)m->vertex_count * sizeof *out->to_proxy));
    for (uint32_t v = 0; ok && v < m->vertex_count; v++) {
        uint32_t b = w2b[c.weld[v]];
        out->to_proxy[v] = b == RF_RIG_NONE ? RF_RIG_NONE : b2p[b];
    }
    ok = ok && rf_rig_proxy_parts(out);
    if (!ok)
        status = rf_rig_oom(err, n, "out of memory simplifying a mesh of %u triangles", body.nt);
    else if (!rf_rig_bbox(out, err, n))
        status = RF_RIG_REFUSED;
    st->proxy_triangles = out->proxy.nt;
done:
    free(c.weld), free(c.wp), free(c.tris), free(c.part), free(c.speck);
    free(w2b), free(b2p);
    rf_rig_geo_free(&body);
    if (status != RF_RIG_OK)
        rf_rig_prep_free(out);
    return status;
}

void rf_rig_prep_free(rf_rig_prep *p)
{
    rf_rig_geo_free(&p->proxy);
    free(p->to_proxy);
    free(p->proxy_part);
    memset(p, 0, sizeof *p);
}
