/* Duplicate-bone removal (thesis 4.2.2, Tables 3 and 4): of all order-preserving ways to match
 * the bones of a target section with those of a source section, the one with the smallest summed
 * cost. The thesis enumerates the sets; dynamic programming finds the same minimum in O(n m):
 * f[i][k] is the best cost for the first i target and first k source bones, and each step either
 * matches bone i with bone k or skips a bone of the longer side. */
#include <math.h>
#include <stdlib.h>

#include "similarity.h"

enum { STEP_MATCH = 1, STEP_SKIP_TARGET = 2, STEP_SKIP_SOURCE = 3 };

/* Walks the steps back from (n, m) to (0, 0), setting match[i] for every matched target bone.
 * The first row and column hold skips, so the walk never leaves the table. */
static void trace_back(const unsigned char *step, size_t w, uint32_t n, uint32_t m, int32_t *match)
{
    for (uint32_t i = n, k = m; i > 0 || k > 0;) {
        unsigned char how = step[i * w + k];
        if (how == STEP_MATCH)
            match[i - 1] = (int32_t)(k - 1), i--, k--;
        else if (how == STEP_SKIP_TARGET)
            i--;
        else
            k--;
    }
}

double rf_ms_assign(const double *cost, uint32_t n, uint32_t m, int32_t *match)
{
    for (uint32_t i = 0; i < n; i++)
        match[i] = -1;
    if (n == 0 || m == 0)
        return 0;
    bool skip_target = n > m; /* the longer side may skip; every bone of the shorter is matched */
    size_t w = (size_t)m + 1;
    double *f = malloc((size_t)(n + 1) * w * sizeof *f);
    unsigned char *step = malloc((size_t)(n + 1) * w);
    if (!f || !step) {
        free(f);
        free(step);
        return -1;
    }
    for (uint32_t i = 0; i <= n; i++)
        for (uint32_t k = 0; k <= m; k++) {
            double *c = &f[i * w + k];
            if (i == 0 || k == 0) {
                /* nothing matched yet: free only if the shorter side has none left over */
                bool ok = skip_target ? k == 0 : i == 0;
                *c = ok ? 0 : INFINITY;
                step[i * w + k] = i ? STEP_SKIP_TARGET : STEP_SKIP_SOURCE;
                continue;
            }
            double best = f[(i - 1) * w + (k - 1)] + cost[(size_t)(i - 1) * m + (k - 1)];
            unsigned char how = STEP_MATCH;
            double skip = skip_target ? f[(i - 1) * w + k] : f[i * w + (k - 1)];
            if (skip < best)
                best = skip, how = skip_target ? STEP_SKIP_TARGET : STEP_SKIP_SOURCE;
            *c = best, step[i * w + k] = how;
        }
    double total = f[n * w + m];
    trace_back(step, w, n, m, match);
    free(f);
    free(step);
    return total;
}

/* The same with a price for leaving a bone out on either side: an alignment, as between two
 * strings, where matching costs cost[i * m + k] and leaving target bone i out costs skip_t[i],
 * source bone k skip_s[k] (NULL: `skip` for every bone). */
double rf_ms_align_priced(const double *cost, uint32_t n, uint32_t m, double skip,
                          const double *skip_t, const double *skip_s, int32_t *match)
{
    for (uint32_t i = 0; i < n; i++)
        match[i] = -1;
    /* A finite price keeps every cell of the first row and column reachable by skips, which the
     * walk back relies on: an infinite or NaN one left cells with no step, and the walk ran off
     * the table. */
    if (!(skip >= 0 && isfinite(skip)))
        return -1;
    for (uint32_t i = 0; skip_t && i < n; i++)
        if (!(skip_t[i] >= 0 && isfinite(skip_t[i])))
            return -1;
    for (uint32_t k = 0; skip_s && k < m; k++)
        if (!(skip_s[k] >= 0 && isfinite(skip_s[k])))
            return -1;
    size_t w = (size_t)m + 1;
    double *f = malloc((size_t)(n + 1) * w * sizeof *f);
    unsigned char *step = malloc((size_t)(n + 1) * w);
    if (!f || !step) {
        free(f);
        free(step);
        return -1;
    }
    for (uint32_t i = 0; i <= n; i++)
        for (uint32_t k = 0; k <= m; k++) {
            double best = i == 0 && k == 0 ? 0 : INFINITY;
            unsigned char how = 0;
            double st = i ? (skip_t ? skip_t[i - 1] : skip) : 0;
            double ss = k ? (skip_s ? skip_s[k - 1] : skip) : 0;
            if (i && k && f[(i - 1) * w + k - 1] + cost[(size_t)(i - 1) * m + k - 1] < best)
                best = f[(i - 1) * w + k - 1] + cost[(size_t)(i - 1) * m + k - 1], how = STEP_MATCH;
            if (i && f[(i - 1) * w + k] + st < best)
                best = f[(i - 1) * w + k] + st, how = STEP_SKIP_TARGET;
            if (k && f[i * w + k - 1] + ss < best)
                best = f[i * w + k - 1] + ss, how = STEP_SKIP_SOURCE;
            f[i * w + k] = best, step[i * w + k] = how;
        }
    double total = f[n * w + m];
    trace_back(step, w, n, m, match);
    free(f);
    free(step);
    return total;
}

double rf_ms_align(const double *cost, uint32_t n, uint32_t m, double skip, int32_t *match)
{
    return rf_ms_align_priced(cost, n, m, skip, NULL, NULL, match);
}
