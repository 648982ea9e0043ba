/* Exact zero tests at real algebraic numbers and principal subresultant coefficients. */
#include "ssi/curve_topo.h"

#include <arb_fmpz_poly.h>
#include <arb_mat.h>

static int sign_at(const fmpz_poly_t p, const fmpq_t x)
{
    fmpq_t v;
    fmpq_init(v);
    fmpz_poly_evaluate_fmpq(v, p, x);
    int s = fmpq_sgn(v);
    fmpq_clear(v);
    return s;
}

int cb_ctopo_alg_vanishes(const fmpz_poly_t p, const fmpz_poly_t r, const fmpq_t lo,
                         const fmpq_t hi)
{
    if (fmpz_poly_is_zero(p))
        return 1;
    if (fmpq_equal(lo, hi))
        return sign_at(p, lo) == 0;
    fmpz_poly_t g;
    fmpz_poly_init(g);
    fmpz_poly_gcd(g, p, r);
    /* g divides the squarefree r, so it has at most one root in (lo, hi), simple, and none at
     * the ends (r does not vanish there). */
    int v = fmpz_poly_degree(g) >= 1 && sign_at(g, lo) * sign_at(g, hi) < 0;
    fmpz_poly_clear(g);
    return v;
}

/* Entry (row, col) of the j-th subresultant matrix of h and h_t as the coefficient index of t
 * it reads, or -1 for a structural zero. Rows 0 .. n-2-j hold t^(n-2-j-row) h, the rest
 * t^(n-1-j-(row-(n-1-j))) h_t; column c < size-1 is the power t^(2n-2-j-c), the last column
 * the power t^col. */
static slong sres_index(slong n, slong j, slong row, slong c, slong col, int *is_deriv)
{
    slong size = 2 * n - 1 - 2 * j;
    slong power = c < size - 1 ? 2 * n - 2 - j - c : col;
    slong shift;
    if (row < n - 1 - j) {
        *is_deriv = 0;
        shift = n - 2 - j - row;
    } else {
        *is_deriv = 1;
        shift = n - 1 - j - (row - (n - 1 - j));
    }
    slong idx = power - shift;
    slong top = *is_deriv ? n - 1 : n;
    return (idx < 0 || idx > top) ? -1 : idx;
}

void cb_ctopo_sres_coeff(fmpz_poly_t out, const cb_bipoly_struct *h, slong j, slong col)
{
    slong n = h->len - 1;
    slong size = 2 * n - 1 - 2 * j;
    if (col < 0 || col > j)
        col = j;
    /* The distinct entries: c_0 .. c_n of h, then c_1 .. n c_n of h_t. */
    fmpz_poly_struct *poly = flint_malloc((size_t)(2 * n + 1) * sizeof *poly);
    slong *idx = flint_malloc((size_t)(size * size) * sizeof *idx);
    for (slong i = 0; i <= n; i++)
        poly[i] = h->c[i]; /* shallow, read only */
    for (slong i = 0; i < n; i++) {
        fmpz_poly_init(poly + n + 1 + i);
        fmpz_poly_scalar_mul_si(poly + n + 1 + i, h->c + i + 1, i + 1);
    }
    for (slong row = 0; row < size; row++)
        for (slong c = 0; c < size; c++) {
            int d;
            slong k = sres_index(n, j, row, c, col, &d);
            idx[row * size + c] = k < 0 ? -1 : d ? n + 1 + k : k;
        }
    _cb_fmpz_poly_mat_det_indexed(out, poly, 2 * n + 1, idx, size);
    for (slong i = n + 1; i < 2 * n + 1; i++)
        fmpz_poly_clear(poly + i);
    flint_free(idx);
    flint_free(poly);
}

void cb_ctopo_sres_coeff_arb(arb_t out, const cb_bipoly_struct *h, slong j, slong col, const arb_t s,
                            slong prec)
{
    slong n = h->len - 1;
    slong size = 2 * n - 1 - 2 * j;
    if (col < 0 || col > j)
        col = j;
    arb_ptr hv = _arb_vec_init(n + 1);
    for (slong i = 0; i <= n; i++)
        arb_fmpz_poly_evaluate_arb(hv + i, h->c + i, s, prec);
    arb_mat_t M;
    arb_mat_init(M, size, size);
    for (slong row = 0; row < size; row++)
        for (slong c = 0; c < size; c++) {
            int d;
            slong idx = sres_index(n, j, row, c, col, &d);
            if (idx < 0)
                continue;
            if (d)
                arb_mul_si(arb_mat_entry(M, row, c), hv + idx + 1, idx + 1, prec);
            else
                arb_set(arb_mat_entry(M, row, c), hv + idx);
        }
    arb_mat_det(out, M, prec);
    arb_mat_clear(M);
    _arb_vec_clear(hv, n + 1);
}
