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
