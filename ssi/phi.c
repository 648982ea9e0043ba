/* phi(s, t) = F(Q(s, t)): exact by modular interpolation and CRT, Bernstein form over Q's box,
 * floating evaluation. */
#include <math.h>

#include <flint/fmpz_poly.h>
#include <flint/fmpz_vec.h>

#include "ssi/dixon_internal.h"
#include "ssi/implicit.h"
#include "ssi/implicit_internal.h"

void cb_phi_init(cb_phi_t phi)
{
    phi->ds = phi->dt = -1;
    phi->c = NULL;
    phi->cd = phi->bern = NULL;
    phi->exp = 0;
    for (int i = 0; i < 4; i++)
        phi->box[i] = 0.0;
}

void cb_phi_clear(cb_phi_t phi)
{
    if (phi->c)
        _fmpz_vec_clear(phi->c, (phi->ds + 1) * (phi->dt + 1));
    flint_free(phi->cd);
    flint_free(phi->bern);
    cb_phi_init(phi);
}

/* In place on the M + 1 power coefficients c[0], c[stride], ... of q(x), x = (A + H sigma) 2^-E:
 * the integers beta_i = sum_{k<=i} C(M-k, i-k) p_k of p(sigma) = 2^(E M) q(x(sigma)), so that
 * the Bernstein coefficients of q on the box are beta_i / (C(M, i) 2^(E M)). bin: Pascal's
 * triangle, C(a, b) at a (a + 1) / 2 + b, for a <= M. */
static void line_to_bernstein(fmpz *c, slong stride, slong M, const fmpz_t A, const fmpz_t H,
                              ulong E, const fmpz *bin)
{
    fmpz_poly_t acc, lin;
    fmpz_poly_init(acc);
    fmpz_poly_init(lin);
    fmpz_poly_set_coeff_fmpz(lin, 0, A);
    fmpz_poly_set_coeff_fmpz(lin, 1, H);
    fmpz_t t, p;
    fmpz_init(t);
    fmpz_init(p);
    /* Horner in (A + H sigma) with coefficients c_k 2^(E (M - k)). */
    for (slong k = M; k >= 0; k--) {
        fmpz_poly_mul(acc, acc, lin);
        fmpz_mul_2exp(t, c + k * stride, E * (ulong)(M - k));
        fmpz_poly_get_coeff_fmpz(p, acc, 0);
        fmpz_add(t, t, p);
        fmpz_poly_set_coeff_fmpz(acc, 0, t);
    }
    for (slong i = 0; i <= M; i++) {
        fmpz_zero(t);
        for (slong k = 0; k <= i; k++) {
            fmpz_poly_get_coeff_fmpz(p, acc, k);
            fmpz_addmul(t, bin + (M - k) * (M - k + 1) / 2 + (i - k), p);
        }
        fmpz_set(c + i * stride, t);
    }
    fmpz_clear(p);
    fmpz_clear(t);
    fmpz_poly_clear(acc);
    fmpz_poly_clear(lin);
}

/* The end points lo, hi of a box side as (A, H) with lo = A 2^-E, hi - lo = H 2^-E exactly. */
static ulong side_dyadic(fmpz_t A, fmpz_t H, double lo, double hi)
{
    fmpz v[2];
    fmpz_init(v);
    fmpz_init(v + 1);
    double x[2] = {lo, hi};
    slong e = _cb_dyadic_to_fmpz(v, x, 2);
    ulong E = 0;
    if (e >= 0) {
        fmpz_mul_2exp(v, v, (ulong)e);
        fmpz_mul_2exp(v + 1, v + 1, (ulong)e);
    } else {
        E = (ulong)(-e);
    }
    fmpz_set(A, v);
    fmpz_sub(H, v + 1, v);
    fmpz_clear(v);
    fmpz_clear(v + 1);
    return E;
}

/* Bernstein coefficients over the box, scaled by 2^-exp, from the exact power coefficients. */
static void phi_bernstein(cb_phi_t phi)
{
    slong ds = phi->ds, dt = phi->dt, w = dt + 1, len = (ds + 1) * w;
    fmpz *beta = _fmpz_vec_init(len);
    _fmpz_vec_set(beta, phi->c, len);
    fmpz_t A, H;
    fmpz_init(A);
    fmpz_init(H);
    /* The binomials, once for all lines (they were a quarter of phi's time). */
    slong M = FLINT_MAX(ds, dt), nbin = (M + 1) * (M + 2) / 2;
    fmpz *bin = _fmpz_vec_init(nbin);
    for (slong a = 0; a <= M; a++) {
        fmpz_one(bin + a * (a + 1) / 2);
        fmpz_one(bin + a * (a + 1) / 2 + a);
        for (slong b = 1; b < a; b++)
            fmpz_add(bin + a * (a + 1) / 2 + b, bin + (a - 1) * a / 2 + b - 1,
                     bin + (a - 1) * a / 2 + b);
    }
    ulong Es = side_dyadic(A, H, phi->box[0], phi->box[1]);
    for (slong j = 0; j <= dt; j++)
        line_to_bernstein(beta + j, w, ds, A, H, Es, bin);
    ulong Et = side_dyadic(A, H, phi->box[2], phi->box[3]);
    for (slong i = 0; i <= ds; i++)
        line_to_bernstein(beta + i * w, 1, dt, A, H, Et, bin);
    slong shift = (slong)(Es * (ulong)ds + Et * (ulong)dt) + phi->exp;
    for (slong i = 0; i <= ds; i++)
        for (slong j = 0; j <= dt; j++) {
            const fmpz *b = beta + i * w + j;
            if (fmpz_is_zero(b)) {
                phi->bern[i * w + j] = 0.0;
                continue;
            }
            slong xb, xc1, xc2;
            double mb = fmpz_get_d_2exp(&xb, b);
            double mc1 = fmpz_get_d_2exp(&xc1, bin + ds * (ds + 1) / 2 + i);
            double mc2 = fmpz_get_d_2exp(&xc2, bin + dt * (dt + 1) / 2 + j);
            phi->bern[i * w + j] = ldexp(mb / (mc1 * mc2), (int)(xb - xc1 - xc2 - shift));
        }
    fmpz_clear(A);
    fmpz_clear(H);
    _fmpz_vec_clear(bin, nbin);
    _fmpz_vec_clear(beta, len);
}

cb_status cb_phi_compute(cb_phi_t phi, const cb_implicit_t F, const cb_dixon_patch_t Q,
                         cb_error *err)
{
    slong N = F->deg, m = Q->m, n = Q->n, qlen = _cb_dixon_patch_len(Q);
    if (N < 1 || N * m > 4096 || N * n > 4096)
        return cb_error_set(err, CB_ERR_UNSUPPORTED, "phi of bidegree (%ld, %ld) (implicit "
                            "degree %ld, patch bidegree (%ld, %ld)) is out of range",
                            (long)(N * m), (long)(N * n), (long)N, (long)m, (long)n);
    slong ds = N * m, dt = N * n, w = dt + 1, len = (ds + 1) * w;
    slong flen = cb_poly3_len((int)N);
    slong qbits = 0;
    for (int q = 0; q < 4; q++)
        qbits = FLINT_MAX(qbits, _cb_fmpz_vec_l1_bits(Q->coef + q * qlen, qlen));
    slong need = _cb_fmpz_vec_l1_bits(F->c, flen) + N * qbits + 1;

    fmpz *c = _fmpz_vec_init(len);
    fmpz_t M, Mold;
    fmpz_init_set_ui(M, 1);
    fmpz_init(Mold);
    ulong *Fp = flint_malloc((size_t)flen * sizeof(ulong));
    ulong *cp = flint_malloc((size_t)(4 * qlen) * sizeof(ulong));
    ulong *pw = flint_malloc((size_t)_cb_implicit_eval_nmod_work(N) * sizeof(ulong));
    ulong *val = flint_malloc((size_t)len * sizeof(ulong));
    ulong *grid = flint_malloc((size_t)(4 * len) * sizeof(ulong));
    ulong *tmp = flint_malloc((size_t)(FLINT_MAX(ds, dt) + 1) * sizeof(ulong));
    ulong p = 0;
    while ((slong)fmpz_bits(M) - 1 <= need) {
        p = _cb_crt_prime(p);
        nmod_t mod;
        nmod_init(&mod, p);
        _fmpz_vec_get_nmod_vec(Fp, F->c, flen, mod);
        _cb_dixon_patch_reduce(cp, Q, mod);
        _cb_dixon_patch_eval_grid_nmod(grid, cp, m, n, ds, dt, mod);
        for (slong k = 0; k < len; k++) {
            ulong X[4] = {grid[k], grid[len + k], grid[2 * len + k], grid[3 * len + k]};
            val[k] = _cb_implicit_eval_nmod(Fp, N, X, mod, pw);
        }
        /* A full tensor grid: interpolate along t on every row, then along s. */
        for (slong i = 0; i <= ds; i++) {
            _cb_nmod_divdiff(val + i * w, 1, dt, mod);
            _cb_nmod_newton_to_mono(val + i * w, 1, dt, mod, tmp);
        }
        for (slong j = 0; j <= dt; j++) {
            _cb_nmod_divdiff(val + j, w, ds, mod);
            _cb_nmod_newton_to_mono(val + j, w, ds, mod, tmp);
        }
        fmpz_set(Mold, M);
        for (slong i = 0; i < len; i++)
            fmpz_CRT_ui(c + i, c + i, Mold, val[i], p, 1);
        fmpz_mul_ui(M, M, p);
    }
    fmpz_clear(M);
    fmpz_clear(Mold);
    flint_free(Fp);
    flint_free(cp);
    flint_free(pw);
    flint_free(val);
    flint_free(grid);
    flint_free(tmp);

    cb_phi_clear(phi);
    phi->ds = ds;
    phi->dt = dt;
    phi->c = c;
    for (int i = 0; i < 4; i++)
        phi->box[i] = Q->box[i];
    phi->cd = flint_malloc((size_t)len * sizeof(double));
    phi->bern = flint_malloc((size_t)len * sizeof(double));
    phi->exp = _cb_fmpz_vec_get_d_scaled(phi->cd, c, len);
    phi_bernstein(phi);
    return CB_OK;
}

double cb_phi_eval_d(const cb_phi_t phi, double s, double t)
{
    slong w = phi->dt + 1;
    double acc = 0.0;
    for (slong i = phi->ds; i >= 0; i--) {
        double r = 0.0;
        for (slong j = phi->dt; j >= 0; j--)
            r = r * t + phi->cd[i * w + j];
        acc = acc * s + r;
    }
    return acc;
}

double cb_phi_eval_direct_d(const cb_implicit_t F, const cb_dixon_patch_t Q, double s,
                            double t)
{
    double h[3][4];
    _cb_dixon_patch_eval_h(h, Q, s, t);
    slong N = F->deg;
    double pw[4][CB_POLY3_MAX_DEGREE + 1];
    for (int q = 0; q < 4; q++) {
        pw[q][0] = 1.0;
        for (slong e = 1; e <= N; e++)
            pw[q][e] = pw[q][e - 1] * h[0][q];
    }
    double acc = 0.0;
    slong idx = 0;
    for (slong tt = 0; tt <= N; tt++)
        for (slong mm = 0; mm <= tt; mm++)
            for (slong k = 0; k <= mm; k++, idx++)
                acc += F->cd[idx] * pw[0][tt - mm] * pw[1][mm - k] * pw[2][k] * pw[3][N - tt];
    return acc;
}
