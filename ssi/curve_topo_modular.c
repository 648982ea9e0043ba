/* Modular resultants and determinants of polynomials in Z[s] for the curve topology
 * (ssi/curve_topo.h): evaluation at s = 0, 1, 2, ... modulo word-size primes, interpolation,
 * Chinese remaindering. The number of primes is fixed in advance by a proved bound on the
 * coefficients of the result (bound_bits), never by the residues settling, so the results
 * are exact. */
#include "ssi/curve_topo.h"
#include "ssi/implicit_internal.h"

#include <flint/fmpz_vec.h>
#include <flint/nmod_mat.h>
#include <flint/nmod_poly.h>
#include <flint/ulong_extras.h>

/* Primes just above 2^59: word-size for nmod arithmetic, far above any evaluation point or
 * degree met here (points never collide modulo p), and small enough that nmod_mat's dot
 * products of up to about 1000 terms accumulate in two limbs (at 2^62 it takes three and
 * slower determinants). */
#define CB_MODULAR_PRIME_START (UWORD(1) << 59)

static _cb_prime_seq modular_primes = {CB_MODULAR_PRIME_START, {0}};

static void norm1(fmpz_t n, const fmpz_poly_t p)
{
    fmpz_zero(n);
    for (slong i = 0; i < p->length; i++)
        if (fmpz_sgn(p->coeffs + i) >= 0)
            fmpz_add(n, n, p->coeffs + i);
        else
            fmpz_sub(n, n, p->coeffs + i);
}

static void add_norm1_sqr(fmpz_t acc, const fmpz_poly_t p)
{
    fmpz_t n;
    fmpz_init(n);
    norm1(n, p);
    fmpz_addmul(acc, n, n);
    fmpz_clear(n);
}

/* Bound on det(M), M a square matrix over Z[s] whose row i has sq[i] = sum_j ||M_ij||_1^2
 * (Goldstein and Graham 1974): for |z| = 1, |M_ij(z)| <= ||M_ij||_1, so Hadamard's inequality
 * gives |det M(z)| <= prod_i sqrt(sq[i]); a coefficient of det M is the mean of
 * det M(z) z^-k over the unit circle, hence bounded by the same product. With
 * sq[i] < 2^bits(sq[i]) the return value b satisfies 2^b > every |coefficient|. Rows repeat
 * (Sylvester matrices), hence the multiplicities mult[i]. */
static flint_bitcnt_t bound_bits(const fmpz *sq, const slong *mult, slong rows)
{
    flint_bitcnt_t b = 0;
    for (slong i = 0; i < rows; i++)
        b += (flint_bitcnt_t)mult[i] * fmpz_bits(sq + i);
    return (b + 1) / 2;
}

/* Adds the residues rp modulo a new prime to r modulo M (symmetric representatives). */
static void crt_step(fmpz_poly_t r, fmpz_t M, const nmod_poly_t rp)
{
    if (fmpz_is_one(M))
        fmpz_poly_set_nmod_poly(r, rp);
    else
        fmpz_poly_CRT_ui(r, r, M, rp, 1);
    fmpz_mul_ui(M, M, rp->mod.n);
}

/* Primes are taken until their product M >= 2^(b + 1) > 2 max |coefficient|: the symmetric
 * residues modulo the odd M are then the coefficients themselves. */
static int crt_done(const fmpz_t M, flint_bitcnt_t b)
{
    return fmpz_bits(M) >= b + 2;
}

static cb_status check_normalised(const cb_bipoly_struct *f, const char *name, cb_error *err)
{
    if (f->len > 0 && fmpz_poly_is_zero(f->c + f->len - 1))
        return cb_error_set(err, CB_ERR_INVALID,
                            "resultant: %s has a zero leading coefficient in t (length %ld)",
                            name, (long)f->len);
    return CB_OK;
}

cb_status cb_bipoly_resultant(fmpz_poly_t r, const cb_bipoly_struct *f, const cb_bipoly_struct *g,
                              cb_error *err)
{
    cb_status st = check_normalised(f, "f", err);
    if (st == CB_OK)
        st = check_normalised(g, "g", err);
    if (st != CB_OK)
        return st;
    if (f->len == 0 || g->len == 0) {
        fmpz_poly_zero(r);
        return CB_OK;
    }
    slong m = f->len - 1, n = g->len - 1;
    /* A constant in t gives a diagonal Sylvester matrix. */
    if (m == 0 || n == 0) {
        fmpz_poly_pow(r, m == 0 ? f->c : g->c, (ulong)(m == 0 ? n : m));
        return CB_OK;
    }

    /* Sylvester matrix: n rows of f's coefficients, m rows of g's; degree in s at most
     * n deg_s f + m deg_s g. */
    fmpz sq[2];
    slong mult[2] = {n, m};
    fmpz_init(sq + 0);
    fmpz_init(sq + 1);
    for (slong j = 0; j <= m; j++)
        add_norm1_sqr(sq + 0, f->c + j);
    for (slong j = 0; j <= n; j++)
        add_norm1_sqr(sq + 1, g->c + j);
    flint_bitcnt_t bits = bound_bits(sq, mult, 2);
    fmpz_clear(sq + 0);
    fmpz_clear(sq + 1);
    slong npts = n * cb_bipoly_deg_s(f) + m * cb_bipoly_deg_s(g) + 1;
    /* A point is bad when a leading coefficient in t vanishes there modulo p (the degrees in t
     * drop and the fibre resultant is not the resultant's value); unless a leading coefficient
     * vanishes identically modulo p, at most their degrees' sum of points are bad. */
    slong max_x = npts + fmpz_poly_degree(f->c + m) + fmpz_poly_degree(g->c + n);

    nmod_poly_struct *fp = flint_malloc((size_t)(m + n + 2) * sizeof *fp), *gp = fp + m + 1;
    mp_ptr xs = _nmod_vec_init(npts), ys = _nmod_vec_init(npts);
    nmod_poly_t a, b, rp;
    fmpz_t M;
    fmpz_init(M);
    fmpz_one(M);
    fmpz_poly_zero(r);
    ulong p = CB_MODULAR_PRIME_START;
    while (!crt_done(M, bits)) {
        p = _cb_prime_seq_next(&modular_primes, p);
        nmod_poly_init(a, p);
        nmod_poly_init(b, p);
        nmod_poly_init(rp, p);
        for (slong j = 0; j <= m + n + 1; j++) {
            nmod_poly_init(fp + j, p);
            fmpz_poly_get_nmod_poly(fp + j, j <= m ? f->c + j : g->c + j - m - 1);
        }
        nmod_poly_fit_length(a, m + 1);
        nmod_poly_fit_length(b, n + 1);
        slong k = 0;
        for (slong x = 0; x < max_x && k < npts; x++) {
            for (slong j = 0; j <= m; j++)
                a->coeffs[j] = nmod_poly_evaluate_nmod(fp + j, (mp_limb_t)x);
            for (slong j = 0; j <= n; j++)
                b->coeffs[j] = nmod_poly_evaluate_nmod(gp + j, (mp_limb_t)x);
            if (a->coeffs[m] == 0 || b->coeffs[n] == 0)
                continue;
            a->length = m + 1;
            b->length = n + 1;
            xs[k] = (mp_limb_t)x;
            ys[k++] = nmod_poly_resultant(a, b);
        }
        /* Too few good points: a leading coefficient vanishes modulo p; the prime is skipped. */
        if (k == npts) {
            nmod_poly_interpolate_nmod_vec_fast(rp, xs, ys, npts);
            crt_step(r, M, rp);
        }
        for (slong j = 0; j <= m + n + 1; j++)
            nmod_poly_clear(fp + j);
        nmod_poly_clear(rp);
        nmod_poly_clear(b);
        nmod_poly_clear(a);
    }
    fmpz_clear(M);
    _nmod_vec_clear(ys);
    _nmod_vec_clear(xs);
    flint_free(fp);
    return CB_OK;
}

void cb_bipoly_resultant_dt(fmpz_poly_t r, const cb_bipoly_struct *p)
{
    cb_bipoly_t pt;
    cb_bipoly_init(pt);
    cb_bipoly_derivative_t(pt, p);
    (void)cb_bipoly_resultant(r, p, pt, NULL);
    cb_bipoly_clear(pt);
}

void _cb_fmpz_poly_mat_det_indexed(fmpz_poly_t d, const fmpz_poly_struct *poly, slong npoly,
                                   const slong *idx, slong size)
{
    fmpz *norm = _fmpz_vec_init(npoly), *sq = _fmpz_vec_init(size);
    slong *mult = flint_malloc((size_t)size * sizeof *mult);
    for (slong k = 0; k < npoly; k++)
        norm1(norm + k, poly + k);
    /* Degree: each term of the expansion takes one entry per row. */
    slong npts = 1;
    int zero_row = 0;
    for (slong i = 0; i < size; i++) {
        slong deg = -1;
        for (slong j = 0; j < size; j++) {
            slong k = idx[i * size + j];
            if (k < 0)
                continue;
            fmpz_addmul(sq + i, norm + k, norm + k);
            deg = FLINT_MAX(deg, fmpz_poly_degree(poly + k));
        }
        mult[i] = 1;
        zero_row |= deg < 0;
        npts += FLINT_MAX(deg, 0);
    }
    flint_bitcnt_t bits = bound_bits(sq, mult, size);
    flint_free(mult);
    _fmpz_vec_clear(sq, size);
    _fmpz_vec_clear(norm, npoly);
    if (zero_row) {
        fmpz_poly_zero(d);
        return;
    }

    nmod_poly_struct *pp = flint_malloc((size_t)npoly * sizeof *pp);
    mp_ptr xs = _nmod_vec_init(npts), ys = _nmod_vec_init(npts), ev = _nmod_vec_init(npoly);
    nmod_mat_t E;
    nmod_poly_t rp;
    fmpz_t M;
    fmpz_init(M);
    fmpz_one(M);
    fmpz_poly_zero(d);
    for (slong k = 0; k < npts; k++)
        xs[k] = (mp_limb_t)k;
    ulong p = CB_MODULAR_PRIME_START;
    while (!crt_done(M, bits)) {
        p = _cb_prime_seq_next(&modular_primes, p);
        nmod_mat_init(E, size, size, p);
        nmod_poly_init(rp, p);
        for (slong k = 0; k < npoly; k++) {
            nmod_poly_init(pp + k, p);
            fmpz_poly_get_nmod_poly(pp + k, poly + k);
        }
        for (slong x = 0; x < npts; x++) {
            /* Each distinct polynomial once: a Sylvester matrix repeats its entries. */
            for (slong k = 0; k < npoly; k++)
                ev[k] = nmod_poly_evaluate_nmod(pp + k, xs[x]);
            for (slong i = 0; i < size * size; i++)
                nmod_mat_entry(E, i / size, i % size) = idx[i] < 0 ? 0 : ev[idx[i]];
            ys[x] = _nmod_mat_det(E); /* destroys E; refilled at the next point */
        }
        nmod_poly_interpolate_nmod_vec_fast(rp, xs, ys, npts);
        crt_step(d, M, rp);
        for (slong k = 0; k < npoly; k++)
            nmod_poly_clear(pp + k);
        nmod_poly_clear(rp);
        nmod_mat_clear(E);
    }
    fmpz_clear(M);
    _nmod_vec_clear(ev);
    _nmod_vec_clear(ys);
    _nmod_vec_clear(xs);
    flint_free(pp);
}

cb_status cb_fmpz_poly_mat_det(fmpz_poly_t d, const fmpz_poly_mat_t A, cb_error *err)
{
    slong size = fmpz_poly_mat_nrows(A);
    if (fmpz_poly_mat_ncols(A) != size)
        return cb_error_set(err, CB_ERR_INVALID, "determinant: %ld x %ld matrix is not square",
                            (long)size, (long)fmpz_poly_mat_ncols(A));
    if (size == 0) {
        fmpz_poly_one(d);
        return CB_OK;
    }
    fmpz_poly_struct *entry = flint_malloc((size_t)(size * size) * sizeof *entry);
    slong *idx = flint_malloc((size_t)(size * size) * sizeof *idx);
    for (slong i = 0; i < size * size; i++) {
        entry[i] = *fmpz_poly_mat_entry(A, i / size, i % size); /* shallow, read only */
        idx[i] = fmpz_poly_is_zero(entry + i) ? -1 : i;
    }
    _cb_fmpz_poly_mat_det_indexed(d, entry, size * size, idx, size);
    flint_free(idx);
    flint_free(entry);
    return CB_OK;
}
