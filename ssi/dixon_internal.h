/* dixon_internal.h — helpers shared by dixon.c, implicit*.c, phi.c and inversion.c: exact
 * dyadic scaling, modular reduction of patches and pencils, pivoted elimination modulo p. Not
 * part of the public API. */
#ifndef CB_SSI_DIXON_INTERNAL_H
#define CB_SSI_DIXON_INTERNAL_H

#include <flint/flint.h>
#include <flint/nmod_mat.h>
#include <flint/nmod_vec.h>

#include "ssi/dixon.h"

/* Fixed seed for every pseudo-random choice in the module, so results reproduce. */
#define CB_DIXON_SEED 0x5eed1234u

/* Writes n finite doubles x as integers out with x[i] = out[i] 2^e (exact: a double is a
 * dyadic rational); e is the smallest exponent that makes them all integers. Returns e. */
slong _cb_dyadic_to_fmpz(fmpz *out, const double *x, slong n);

/* out[i] = v[i] 2^-e with e = max bits of v, so |out[i]| <= 1 (each rounded once). Returns e. */
slong _cb_fmpz_vec_get_d_scaled(double *out, const fmpz *v, slong n);

/* Number of coefficients (m+1)(n+1) of one component. */
static inline slong _cb_dixon_patch_len(const cb_dixon_patch_t P)
{
    return (P->m + 1) * (P->n + 1);
}

/* The four components reduced mod p: cp[q len + i (n+1) + j]. */
void _cb_dixon_patch_reduce(ulong *cp, const cb_dixon_patch_t P, nmod_t mod);

/* Values of the four components at (u, v) mod p from the reduced coefficients cp. */
void _cb_dixon_patch_eval_nmod(ulong out[4], const ulong *cp, slong m, slong n, ulong u,
                               ulong v, nmod_t mod);

/* Values of the four components at every integer point (i, j), i <= du, j <= dv, mod p:
 * out[q (du + 1)(dv + 1) + i (dv + 1) + j]. The sums over v are made once per column j, so a
 * point costs m + 1 products instead of (m + 1)(n + 1). */
void _cb_dixon_patch_eval_grid_nmod(ulong *out, const ulong *cp, slong m, slong n, slong du,
                                    slong dv, nmod_t mod);

/* Homogeneous value and first partials at real (u, v), scaled as P->cd: h[0] = (a,b,c,d),
 * h[1] = d/du, h[2] = d/dv. */
void _cb_dixon_patch_eval_h(double h[3][4], const cb_dixon_patch_t P, double u, double v);

/* The four matrices reduced mod p: Dp[q size^2 + i size + j]. */
void _cb_dixon_pencil_reduce(ulong *Dp, const cb_dixon_pencil_t D, nmod_t mod);

/* M = sum_q X[q] Dp[q] mod p (X reduced). */
void _cb_dixon_pencil_eval_nmod(nmod_mat_t M, const ulong *Dp, slong size, const ulong X[4],
                                nmod_t mod);

/* Gaussian elimination of A (destroyed) with pivot search over the whole remaining block.
 * Returns the rank r and the original row and column indices of the r pivots: the r x r
 * submatrix of the original A on those rows and columns is non-singular. */
slong _cb_nmod_mat_pivots(slong *rows, slong *cols, nmod_mat_t A);

#endif
