/* Small dense linear algebra for the Jacobian solvers: an SVD and a Cholesky solve. Sizes are a
 * few rows (3 per goal) by up to a few hundred columns (3 per joint), so simple O(m^2 n) methods
 * with no allocation are the right tool. */
#include <math.h>
#include <string.h>

#include "rigflow/ik-common.h"

/* Rotates columns p and q of an (rows)-long column-major matrix by (c, s). */
static void rotate_cols(double *M, int rows, int p, int q, double c, double s)
{
    double *x = M + (size_t)p * rows, *y = M + (size_t)q * rows;
    for (int i = 0; i < rows; i++) {
        double a = x[i], b = y[i];
        x[i] = c * a - s * b;
        y[i] = s * a + c * b;
    }
}

static double dot(const double *x, const double *y, int n)
{
    double s = 0;
    for (int i = 0; i < n; i++)
        s += x[i] * y[i];
    return s;
}

/* One-sided Jacobi (Hestenes): rotate pairs of columns of B = A^T until they are orthogonal.
 * It works on the short dimension only (m columns) and is accurate for small singular values,
 * which the pseudoinverse divides by. */
int rf_ikc_svd(const double *A, int m, int n, double *B, double *U, double *sigma)
{
    memcpy(B, A, (size_t)m * n * sizeof *B); /* row k of A is column k of A^T */
    for (int k = 0; k < m * m; k++)
        U[k] = (k % (m + 1)) == 0 ? 1.0 : 0.0;
    int sweep = 0;
    for (; sweep < 30; sweep++) {
        bool rotated = false;
        for (int p = 0; p < m - 1; p++)
            for (int q = p + 1; q < m; q++) {
                double *bp = B + (size_t)p * n, *bq = B + (size_t)q * n;
                double alpha = dot(bp, bp, n), beta = dot(bq, bq, n), gamma = dot(bp, bq, n);
                if (fabs(gamma) <= 1e-15 * sqrt(alpha * beta) || gamma == 0)
                    continue;
                rotated = true;
                double zeta = (beta - alpha) / (2 * gamma);
                double t = (zeta >= 0 ? 1.0 : -1.0) / (fabs(zeta) + sqrt(1 + zeta * zeta));
                double c = 1 / sqrt(1 + t * t), s = c * t;
                rotate_cols(B, n, p, q, c, s);
                rotate_cols(U, m, p, q, c, s);
            }
        if (!rotated)
            break;
    }
    for (int k = 0; k < m; k++)
        sigma[k] = sqrt(dot(B + (size_t)k * n, B + (size_t)k * n, n));
    return sweep + 1;
}

bool rf_ikc_cholesky_solve(double *S, double *b, int m)
{
    for (int j = 0; j < m; j++) {
        double d = S[j * m + j];
        for (int k = 0; k < j; k++)
            d -= S[j * m + k] * S[j * m + k];
        if (!(d > 0))
            return false;
        d = sqrt(d);
        S[j * m + j] = d;
        for (int i = j + 1; i < m; i++) {
            double v = S[i * m + j];
            for (int k = 0; k < j; k++)
                v -= S[i * m + k] * S[j * m + k];
            S[i * m + j] = v / d;
        }
    }
    for (int i = 0; i < m; i++) { /* L y = b */
        double v = b[i];
        for (int k = 0; k < i; k++)
            v -= S[i * m + k] * b[k];
        b[i] = v / S[i * m + i];
    }
    for (int i = m - 1; i >= 0; i--) { /* L^T x = y */
        double v = b[i];
        for (int k = i + 1; k < m; k++)
            v -= S[k * m + i] * b[k];
        b[i] = v / S[i * m + i];
    }
    return true;
}
