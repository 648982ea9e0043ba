/* inversion.h — parameters of a point on a patch from its Dixon matrix (Yang, Jia, Yan, ACM TOG
 * 2023, Theorem 4.1 and Remarks 2-3): X is on P(u, v) iff D(X) U(u, v) = 0, and the real
 * solutions (u, v) of that system, kept when P(u, v) is within a distance threshold of X, are
 * the parameters of X; X lies on the trimmed patch iff one of them is inside the box. */
#ifndef CB_SSI_INVERSION_H
#define CB_SSI_INVERSION_H

#include "ssi/dixon.h"

typedef struct {
    double dist_tol;  /* keep (u, v) when |P(u, v) - X| <= dist_tol (Euclidean, model units);
                         default 1e-6, the kernel tolerance of the paper's experiments */
    double param_tol; /* slack, relative to the box size, for "inside the box" and for merging
                         two solutions that are the same preimage; default 1e-9 */
} cb_inversion_params;

/* Fills the documented defaults. */
void cb_inversion_params_default(cb_inversion_params *par);

typedef struct {
    double u, v;  /* parameters in the caller's domain (cb_dixon_patch_t::domain) */
    double dist;  /* |P(u, v) - X| */
    int inside;   /* (u, v) in the box, up to param_tol */
} cb_inversion_point;

typedef struct {
    slong n, alloc;
    cb_inversion_point *pt; /* every accepted real solution, sorted by u then v */
    int inside;             /* some solution is inside: X lies on the trimmed patch */
} cb_inversion_struct;
typedef cb_inversion_struct cb_inversion_t[1];

void cb_inversion_init(cb_inversion_t res);
void cb_inversion_clear(cb_inversion_t res);

/* Solves D(X) U(u, v) = 0 for the Euclidean point X (w = 1), D = the pencil of P.
 * Method (Remark 3): X is taken exactly (doubles are dyadic), D(X) is an integer matrix, two
 * random integer combinations of its rows give two polynomials p1, p2 of bidegree
 * (2m - 1, n - 1) in (u, v); the real roots u of Res_v(p1, p2) (of p1 itself when n = 1, where
 * U holds no v) are isolated exactly (cb_roots_isolate) and refined to double precision; for
 * each, the real roots v of a random combination of the moving planes f, g, h at (u, X) are
 * isolated the same way. Every candidate (u, v) is polished by Gauss-Newton on |P(u, v) - X|
 * (at most 12 steps, each kept only if the distance drops), then kept if within dist_tol;
 * duplicates (within param_tol) are merged. Redundant roots of the two-row system (Remark 3) are rejected
 * by the distance test. Fails on non-finite X or parameters, and with CB_ERR_NUMERIC if four
 * random row pairs all give a zero resultant (D(X) of rank <= 1). */
cb_status cb_inversion_solve(cb_inversion_t res, const cb_dixon_pencil_t D,
                             const cb_dixon_patch_t P, const double X[3],
                             const cb_inversion_params *par, cb_error *err);

#endif
