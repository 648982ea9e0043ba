/* roots.h — exact isolation of the real roots of an integer polynomial in an interval.
 *
 * Debian's FLINT 2.9 has resultants and squarefree factorisation but no real-root isolation;
 * this is the Descartes / Vincent-Collins-Akritas method with exact Taylor shifts
 * (ssi-primer section 5; Collins and Akritas 1976). Roots are found exactly: every root of the
 * polynomial in [a, b] gets an isolating interval with rational (dyadic in the unit interval)
 * end points that holds it and no other root, and a root that lands on an end point or a
 * subdivision point is reported as an exact rational. Multiple roots are reported once (the
 * work is done on the squarefree part). */
#ifndef CB_SSI_ROOTS_H
#define CB_SSI_ROOTS_H

#include <flint/fmpq.h>
#include <flint/fmpz_poly.h>

#include "brep/status.h"

/* lo == hi: the root is exactly lo. lo < hi: exactly one root lies in the open (lo, hi), and
 * neither end point is a root. */
typedef struct {
    fmpq_t lo, hi;
} cb_root_interval_struct;

typedef struct {
    fmpz_poly_t sqfree;            /* primitive squarefree part of the polynomial */
    slong n;                       /* number of roots */
    slong alloc;
    cb_root_interval_struct *root; /* sorted increasingly, pairwise disjoint */
} cb_roots_struct;
typedef cb_roots_struct cb_roots_t[1];

void cb_roots_init(cb_roots_t r);
void cb_roots_clear(cb_roots_t r);

/* Isolates the distinct real roots of p in the closed interval [a, b] (a < b). The zero
 * polynomial (every point a root) is rejected with CB_ERR_INVALID, as is a > b or a == b. */
cb_status cb_roots_isolate(cb_roots_t r, const fmpz_poly_t p, const fmpq_t a, const fmpq_t b,
                           cb_error *err);

/* Shrinks the isolating interval of root k by bisection until hi - lo <= width (width > 0), or
 * until the root is hit exactly. The intervals are those of plain bisection; the steps are
 * integer sign tests, and from 8 steps on a Newton guess of the last cell, confirmed by the
 * exact signs at its ends, replaces them. */
void cb_roots_refine(cb_roots_t r, slong k, const fmpq_t width);

/* Whether root k is rational, and if so its interval made that point: the simplest rational in
 * the interval, checked exactly. A root p / d (lowest terms) is found once the interval is
 * narrower than 1 / (2 d^2): no other rational of denominator at most d fits in it. */
int cb_roots_try_rational(cb_roots_t r, slong k);

/* Midpoint of root k's interval, rounded to a double. */
double cb_roots_mid_d(const cb_roots_t r, slong k);

#endif
