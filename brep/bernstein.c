/* Conversion between the Bernstein basis on [a, b] and the power basis in t.
 *
 * Method, and why. Both directions pass through the monomial basis in the local variable
 * s = (t - a) / (b - a):
 *   Bernstein <-> local monomial is a triangular map with integer entries (a forward
 *   difference table scaled by C(n, k), and its exact inverse);
 *   local monomial <-> power in t expands (t - a)^k / h^k, or (a + h s)^k, with explicit
 *   binomial coefficients, which are exact in double up to degree 50 or so.
 * No Vandermonde solve or interpolation through samples is involved, so the only error is
 * round-off in sums whose size is set by the problem itself: the power basis in t is badly
 * conditioned when the degree is high or [a, b] is short and far from 0, and no method can
 * avoid that once the caller asks for coefficients in t.
 * All steps run in place on a strided array, so out may alias in, nothing is allocated and
 * nothing can fail; the tensor versions apply the one-dimensional map to rows, then columns. */
#include "brep/nurbs.h"

#include <math.h>
#include <string.h>

/* c[k * st], k = 0 .. n: Bernstein on [a, b] -> power in t. */
static void bernstein_to_power_strided(double *c, long st, int n, double a, double b)
{
    /* c[i] becomes Delta^i c[0]. */
    for (int k = 1; k <= n; k++)
        for (int i = n; i >= k; i--)
            c[i * st] -= c[(i - 1) * st];
    double bin = 1.0, h = b - a, scale = 1.0;
    for (int k = 1; k <= n; k++) {
        bin = bin * (n - k + 1) / k;
        scale /= h;
        c[k * st] *= bin * scale;
    }
    /* Now f = sum c_k (t - a)^k, so p_j = sum_{k >= j} c_k C(k, j) (-a)^(k - j); p_j reads
     * only c_k with k >= j, so increasing j may overwrite c_j. */
    for (int j = 0; j <= n; j++) {
        double sum = c[j * st], cb = 1.0, pw = 1.0;
        for (int k = j + 1; k <= n; k++) {
            cb = cb * k / (k - j);
            pw *= -a;
            sum += c[k * st] * cb * pw;
        }
        c[j * st] = sum;
    }
}

/* c[k * st], k = 0 .. n: power in t -> Bernstein on [a, b]. */
static void power_to_bernstein_strided(double *c, long st, int n, double a, double b)
{
    /* t = a + h s: q_j = h^j sum_{k >= j} p_k C(k, j) a^(k - j), in place as above. */
    double h = b - a, hj = 1.0;
    for (int j = 0; j <= n; j++) {
        double sum = c[j * st], cb = 1.0, pw = 1.0;
        for (int k = j + 1; k <= n; k++) {
            cb = cb * k / (k - j);
            pw *= a;
            sum += c[k * st] * cb * pw;
        }
        c[j * st] = sum * hj;
        hj *= h;
    }
    double bin = 1.0;
    for (int k = 1; k <= n; k++) {
        bin = bin * (n - k + 1) / k;
        c[k * st] /= bin;
    }
    /* Undo the difference table, last pass first. */
    for (int k = n; k >= 1; k--)
        for (int i = k; i <= n; i++)
            c[i * st] += c[(i - 1) * st];
}

static void copy_coeffs(double *out, const double *in, long count)
{
    if (out != in)
        memmove(out, in, (size_t)count * sizeof *out);
}

void cb_bernstein_to_power(double *pow, const double *bern, int deg, double a, double b)
{
    copy_coeffs(pow, bern, deg + 1);
    bernstein_to_power_strided(pow, 1, deg, a, b);
}

void cb_power_to_bernstein(double *bern, const double *pow, int deg, double a, double b)
{
    copy_coeffs(bern, pow, deg + 1);
    power_to_bernstein_strided(bern, 1, deg, a, b);
}

void cb_bernstein_to_power_2d(double *pow, const double *bern, int m, int n, double u0,
                              double u1, double v0, double v1)
{
    copy_coeffs(pow, bern, (long)(m + 1) * (n + 1));
    for (int i = 0; i <= m; i++)
        bernstein_to_power_strided(pow + (long)i * (n + 1), 1, n, v0, v1);
    for (int j = 0; j <= n; j++)
        bernstein_to_power_strided(pow + j, n + 1, m, u0, u1);
}

void cb_power_to_bernstein_2d(double *bern, const double *pow, int m, int n, double u0,
                              double u1, double v0, double v1)
{
    copy_coeffs(bern, pow, (long)(m + 1) * (n + 1));
    for (int i = 0; i <= m; i++)
        power_to_bernstein_strided(bern + (long)i * (n + 1), 1, n, v0, v1);
    for (int j = 0; j <= n; j++)
        power_to_bernstein_strided(bern + j, n + 1, m, u0, u1);
}

/* C(n, k) in double: exact for the degrees used here (n <= 2 CB_MAX_DEGREE). */
static double binom(int n, int k)
{
    double c = 1.0;
    for (int i = 1; i <= k; i++)
        c = c * (n - k + i) / i;
    return c;
}

void cb_bernstein_mul_2d(double *out, double *bound, const double *a, const double *b, int m,
                         int n, int p, int q)
{
    int M = m + p, N = n + q;
    for (int k = 0; k < (M + 1) * (N + 1); k++) {
        out[k] = 0;
        if (bound)
            bound[k] = 0;
    }
    /* B_i^m B_k^p = C(m, i) C(p, k) / C(m + p, i + k) B_{i+k}^{m+p}, per direction. */
    for (int i = 0; i <= m; i++)
        for (int j = 0; j <= n; j++) {
            double aij = a[i * (n + 1) + j];
            if (aij == 0)
                continue;
            for (int k = 0; k <= p; k++)
                for (int l = 0; l <= q; l++) {
                    double c = binom(m, i) * binom(p, k) / binom(M, i + k) * binom(n, j) *
                               binom(q, l) / binom(N, j + l);
                    double t = c * aij * b[k * (q + 1) + l];
                    out[(i + k) * (N + 1) + j + l] += t;
                    if (bound)
                        bound[(i + k) * (N + 1) + j + l] += fabs(t);
                }
        }
    if (bound) {
        /* Each term went through at most 12 roundings (six binomial factors, their quotients
         * and products with a and b) and each sum through one per term: relative 2^-53 each,
         * so (12 + (m+1)(n+1)) 2^-53 (1 + small) bounds the error relative to the sum of the
         * terms' magnitudes; twice that, to cover the first-order approximation. */
        double gam = 2.0 * (12 + (m + 1) * (n + 1)) * ldexp(1.0, -53);
        for (int k = 0; k < (M + 1) * (N + 1); k++)
            bound[k] *= gam;
    }
}
