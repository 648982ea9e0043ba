/* implicit_internal.h — modular kernels shared by implicit.c and phi.c: evaluation of F mod p,
 * univariate Newton interpolation on the nodes 0, 1, 2, ..., the coefficient bound and CRT
 * bookkeeping. Not part of the public API. */
#ifndef CB_SSI_IMPLICIT_INTERNAL_H
#define CB_SSI_IMPLICIT_INTERNAL_H

#include <stdatomic.h>

#include <flint/nmod_vec.h>

#include "ssi/implicit.h"

/* F(X) mod p for homogeneous X (4 residues) from the reduced coefficients Fp (layout of F);
 * work holds _cb_implicit_eval_nmod_work(N) limbs. */
ulong _cb_implicit_eval_nmod(const ulong *Fp, slong N, const ulong X[4], nmod_t mod,
                             ulong *work);
slong _cb_implicit_eval_nmod_work(slong N);

/* In place on the L + 1 values c[0], c[stride], ... at the nodes 0..L: the Newton divided
 * differences [0..i] f. Each c[i] depends on the values 0..i only. */
void _cb_nmod_divdiff(ulong *c, slong stride, slong L, nmod_t mod);

/* In place: Newton coefficients on the nodes 0..L to monomial coefficients. tmp holds L + 1. */
void _cb_nmod_newton_to_mono(ulong *c, slong stride, slong L, nmod_t mod, ulong *tmp);

/* Number of bits b with sum |v_i| < 2^b. */
slong _cb_fmpz_vec_l1_bits(const fmpz *v, slong n);

/* The primes after start in increasing order, the first CB_PRIME_SEQ_LEN of them kept once
 * found: every patch pair asks for the same few, and n_nextprime's primality tests were 4% of
 * a small intersection. An entry depends on its index alone, so threads that fill it at once
 * store the same value (atomically). Define one as {start} with static storage. */
#define CB_PRIME_SEQ_LEN 64
typedef struct {
    ulong start;
    _Atomic ulong p[CB_PRIME_SEQ_LEN];
} _cb_prime_seq;

/* The least prime of the sequence above prev (the first one when prev < start); beyond the
 * kept ones, n_nextprime. */
ulong _cb_prime_seq_next(_cb_prime_seq *seq, ulong prev);

/* The prime after prev for CRT: the primes above 2^62 in increasing order, starting with the
 * first one when prev = 0 (deterministic; each is > 2^62). */
ulong _cb_crt_prime(ulong prev);

#endif
