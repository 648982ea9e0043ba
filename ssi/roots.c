/* Real-root isolation by Descartes' rule of signs with exact Taylor shifts (VCA). */
#include "ssi/roots.h"

#include <stdlib.h>

#include <arb_poly.h>
#include <flint/fmpq_poly.h>
#include <flint/fmpz_vec.h>
#include <flint/nmod_poly.h>

void cb_roots_init(cb_roots_t r)
{
    fmpz_poly_init(r->sqfree);
    r->n = r->alloc = 0;
    r->root = NULL;
}

static void roots_reset(cb_roots_t r)
{
    for (slong k = 0; k < r->n; k++) {
        fmpq_clear(r->root[k].lo);
        fmpq_clear(r->root[k].hi);
    }
    r->n = 0;
}

void cb_roots_clear(cb_roots_t r)
{
    roots_reset(r);
    flint_free(r->root);
    fmpz_poly_clear(r->sqfree);
}

/* Appends the interval [lo, hi], taking over the values of lo and hi (left zero). */
static void roots_push(cb_roots_t r, fmpq_t lo, fmpq_t hi)
{
    if (r->n == r->alloc) {
        r->alloc = r->alloc ? 2 * r->alloc : 8;
        r->root = flint_realloc(r->root, (size_t)r->alloc * sizeof *r->root);
    }
    cb_root_interval_struct *iv = r->root + r->n++;
    *iv->lo = *lo;
    *iv->hi = *hi;
    fmpq_init(lo);
    fmpq_init(hi);
}

/* out = a + (b - a) c / 2^k: the image of a dyadic point of the unit interval. */
static void unit_to_interval(fmpq_t out, const fmpz_t c, ulong k, const fmpq_t a,
                             const fmpq_t len)
{
    fmpz_t den;
    fmpz_init(den);
    fmpz_one_2exp(den, k);
    fmpq_set_fmpz_frac(out, c, den);
    fmpq_mul(out, out, len);
    fmpq_add(out, out, a);
    fmpz_clear(den);
}

static slong sign_variations(const fmpz_poly_t p)
{
    slong v = 0;
    int last = 0;
    for (slong i = 0; i < fmpz_poly_length(p); i++) {
        int s = fmpz_sgn(p->coeffs + i);
        if (s) {
            if (last && s != last)
                v++;
            last = s;
        }
    }
    return v;
}

/* Descartes' bound on the roots of p in (0, 1): the sign variations of (x + 1)^n p(1/(x + 1)),
 * exact when it is 0 or 1. */
static slong descartes_unit(const fmpz_poly_t p, fmpz_poly_t tmp, const fmpz_t one)
{
    fmpz_poly_reverse(tmp, p, fmpz_poly_length(p));
    fmpz_poly_taylor_shift(tmp, tmp, one);
    return sign_variations(tmp);
}

/* A piece of the unit interval still to examine: (c / 2^k, (c + 1) / 2^k), with p the
 * polynomial mapped onto it so that the piece is (0, 1) for p. An end point that is a root
 * (already reported exactly and divided out of p) is flagged: an isolating interval must not
 * end on a root, so a flagged piece with one root is halved until the root is off the flag. */
typedef struct {
    fmpz_poly_t p;
    fmpz_t c;
    ulong k;
    int root_lo, root_hi;
} piece;

typedef struct {
    piece *item;
    slong n, alloc;
} piece_stack;

static piece *stack_push(piece_stack *s)
{
    if (s->n == s->alloc) {
        s->alloc = s->alloc ? 2 * s->alloc : 16;
        s->item = flint_realloc(s->item, s->alloc * sizeof *s->item);
    }
    piece *it = &s->item[s->n++];
    fmpz_poly_init(it->p);
    fmpz_init(it->c);
    return it;
}

static void record_open(cb_roots_t r, const piece *it, const fmpq_t a, const fmpq_t len)
{
    fmpq_t lo, hi;
    fmpz_t c1;
    fmpq_init(lo);
    fmpq_init(hi);
    fmpz_init(c1);
    fmpz_add_ui(c1, it->c, 1);
    unit_to_interval(lo, it->c, it->k, a, len);
    unit_to_interval(hi, c1, it->k, a, len);
    roots_push(r, lo, hi);
    fmpz_clear(c1);
}

static void record_exact(cb_roots_t r, const fmpq_t x)
{
    fmpq_t lo, hi;
    fmpq_init(lo);
    fmpq_init(hi);
    fmpq_set(lo, x);
    fmpq_set(hi, x);
    roots_push(r, lo, hi);
}

/* Divides p by x (p(0) = 0) or by x - 1 (p(1) = 0); both divisions are exact. */
static void divide_by_x(fmpz_poly_t p) { fmpz_poly_shift_right(p, p, 1); }

static void divide_by_x_minus_1(fmpz_poly_t p)
{
    fmpz_poly_t d;
    fmpz_poly_init(d);
    fmpz_poly_set_coeff_si(d, 0, -1);
    fmpz_poly_set_coeff_si(d, 1, 1);
    fmpz_poly_div(p, p, d);
    fmpz_poly_clear(d);
}

/* Isolates the roots of u in the open unit interval; u squarefree, u(0), u(1) != 0; root_lo
 * and root_hi say whether 0 and 1 are roots of the polynomial u was divided from. */
static void isolate_unit(cb_roots_t r, const fmpz_poly_t u, int root_lo, int root_hi,
                         const fmpq_t a, const fmpq_t len)
{
    piece_stack st = {NULL, 0, 0};
    fmpz_poly_t tmp;
    fmpz_t one;
    fmpq_t x;
    fmpz_poly_init(tmp);
    fmpz_init_set_ui(one, 1);
    fmpq_init(x);
    piece *first = stack_push(&st);
    fmpz_poly_set(first->p, u);
    first->k = 0;
    first->root_lo = root_lo;
    first->root_hi = root_hi;
    while (st.n > 0) {
        piece it = st.item[--st.n];
        slong v = descartes_unit(it.p, tmp, one);
        if (v == 1 && !it.root_lo && !it.root_hi) {
            record_open(r, &it, a, len);
        } else if (v >= 1) {
            /* Halve: left(x) = 2^n p(x / 2) on (0, 1/2), right(x) = left(x + 1) on (1/2, 1). */
            slong n = fmpz_poly_degree(it.p);
            stack_push(&st);
            stack_push(&st); /* both pushed before taking pointers: a push may move the stack */
            piece *right = &st.item[st.n - 2], *left = &st.item[st.n - 1];
            fmpz_poly_set(left->p, it.p);
            for (slong i = 0; i <= n; i++)
                fmpz_mul_2exp(left->p->coeffs + i, left->p->coeffs + i, (ulong)(n - i));
            fmpz_poly_taylor_shift(right->p, left->p, one);
            left->k = right->k = it.k + 1;
            fmpz_mul_2exp(left->c, it.c, 1);
            fmpz_add_ui(right->c, left->c, 1);
            left->root_lo = it.root_lo;
            right->root_hi = it.root_hi;
            left->root_hi = right->root_lo = fmpz_is_zero(right->p->coeffs);
            if (left->root_hi) {
                /* The midpoint is a root: report it exactly and keep it off both halves. */
                unit_to_interval(x, right->c, right->k, a, len);
                record_exact(r, x);
                divide_by_x(right->p);
                divide_by_x_minus_1(left->p);
            }
        }
        fmpz_poly_clear(it.p);
        fmpz_clear(it.c);
    }
    flint_free(st.item);
    fmpq_clear(x);
    fmpz_clear(one);
    fmpz_poly_clear(tmp);
}

static int cmp_interval(const void *pa, const void *pb)
{
    const cb_root_interval_struct *a = pa, *b = pb;
    return fmpq_cmp(a->lo, b->lo);
}

/* 1 when p (degree >= 1) is proved squarefree: modulo a prime q not dividing its leading
 * coefficient, gcd(p, p') = 1 (a square factor f^2 of p keeps its degree modulo q and divides
 * both). Then p / gcd(p, p') is p itself, and the integer gcd, nearly half of an isolation of the
 * small polynomials of a Dixon inversion, is not needed. 0: not proved (the gcd decides). */
static int squarefree_mod_prime(const fmpz_poly_t p)
{
    const ulong q = UWORD(0xffffffffffffffc5); /* 2^64 - 59, the largest 64-bit prime */
    nmod_poly_t a, da;
    nmod_poly_init(a, q);
    nmod_poly_init(da, q);
    fmpz_poly_get_nmod_poly(a, p);
    int ok = nmod_poly_degree(a) == fmpz_poly_degree(p);
    if (ok) {
        nmod_poly_derivative(da, a);
        nmod_poly_gcd(da, a, da);
        ok = nmod_poly_degree(da) == 0;
    }
    nmod_poly_clear(a);
    nmod_poly_clear(da);
    return ok;
}

cb_status cb_roots_isolate(cb_roots_t r, const fmpz_poly_t p, const fmpq_t a, const fmpq_t b,
                           cb_error *err)
{
    if (fmpz_poly_is_zero(p))
        return cb_error_set(err, CB_ERR_INVALID,
                            "root isolation: the zero polynomial vanishes everywhere");
    if (fmpq_cmp(a, b) >= 0)
        return cb_error_set(err, CB_ERR_INVALID, "root isolation: empty interval [a, b], a >= b");
    roots_reset(r);
    if (fmpz_poly_degree(p) < 1) {
        fmpz_poly_set_ui(r->sqfree, 1);
        return CB_OK;
    }

    fmpz_poly_t g, u;
    fmpq_poly_t q, lin;
    fmpq_t len;
    fmpz_poly_init(g);
    fmpz_poly_init(u);
    fmpq_poly_init(q);
    fmpq_poly_init(lin);
    fmpq_init(len);

    if (squarefree_mod_prime(p)) {
        fmpz_poly_primitive_part(r->sqfree, p);
    } else {
        fmpz_poly_derivative(g, p);
        fmpz_poly_gcd(g, p, g);
        fmpz_poly_div(r->sqfree, p, g);
        fmpz_poly_primitive_part(r->sqfree, r->sqfree);
    }

    /* u(x) = sqfree(a + (b - a) x) with its denominators cleared: [a, b] becomes [0, 1]. */
    fmpq_sub(len, b, a);
    fmpq_poly_set_coeff_fmpq(lin, 0, a);
    fmpq_poly_set_coeff_fmpq(lin, 1, len);
    fmpq_poly_set_fmpz_poly(q, r->sqfree);
    fmpq_poly_compose(q, q, lin);
    fmpq_poly_get_numerator(u, q);
    fmpz_poly_primitive_part(u, u);

    int root_at_a = fmpz_is_zero(u->coeffs);
    if (root_at_a) {
        record_exact(r, a);
        divide_by_x(u);
    }
    fmpz_t sum;
    fmpz_init(sum);
    for (slong i = 0; i < fmpz_poly_length(u); i++)
        fmpz_add(sum, sum, u->coeffs + i);
    int root_at_b = fmpz_is_zero(sum);
    fmpz_clear(sum);
    if (root_at_b)
        divide_by_x_minus_1(u);
    if (fmpz_poly_degree(u) >= 1)
        isolate_unit(r, u, root_at_a, root_at_b, a, len);
    if (root_at_b)
        record_exact(r, b);
    if (r->n > 1)
        qsort(r->root, (size_t)r->n, sizeof *r->root, cmp_interval);

    fmpq_clear(len);
    fmpq_poly_clear(lin);
    fmpq_poly_clear(q);
    fmpz_poly_clear(u);
    fmpz_poly_clear(g);
    return CB_OK;
}

/* Sign of p at x_k = (A 2^k + L N) / (D 2^k), D > 0, given c_i = p_i D^(d - i): the sign of
 * sum_i c_i X^i 2^(k (d - i)) with X = A 2^k + L N, that is of p(x_k) (D 2^k)^d. Integer Horner
 * without the gcds of a rational evaluation, which made the bisection below the larger part
 * of a Dixon inversion. */
static int sign_at_step(const fmpz *c, slong d, const fmpz_t A, const fmpz_t L, const fmpz_t N,
                        ulong k, fmpz_t X, fmpz_t acc, fmpz_t t)
{
    fmpz_mul_2exp(X, A, k);
    fmpz_addmul(X, L, N);
    fmpz_set(acc, c + d);
    for (slong i = d - 1; i >= 0; i--) {
        fmpz_mul(acc, acc, X);
        fmpz_mul_2exp(t, c + i, k * (ulong)(d - i));
        fmpz_add(acc, acc, t);
    }
    return fmpz_sgn(acc);
}

/* out = (A 2^k + L N) / (D 2^k) in lowest terms. */
static void step_point(fmpq_t out, const fmpz_t A, const fmpz_t L, const fmpz_t D, const fmpz_t N,
                       ulong k)
{
    fmpz_t num, den;
    fmpz_init(num);
    fmpz_init(den);
    fmpz_mul_2exp(num, A, k);
    fmpz_addmul(num, L, N);
    fmpz_mul_2exp(den, D, k);
    fmpq_set_fmpz_frac(out, num, den);
    fmpz_clear(num);
    fmpz_clear(den);
}

/* A guess for the cell c of the last bisection step (lo + (hi - lo) [c, c + 1] / 2^K, lo =
 * A / D, hi - lo = L / D) holding the root: Newton's method on the midpoints of balls at K + 64
 * bits from the interval's midpoint. 0 when it leaves the interval or does not settle within
 * 2 log2(K) + 16 steps. Only a guess: the caller checks the cell's ends exactly. */
static int newton_cell(fmpz_t c, const fmpz_poly_t p, const fmpq_t lo, const fmpq_t hi,
                       const fmpz_t A, const fmpz_t L, const fmpz_t D, ulong K)
{
    slong prec = (slong)K + 64;
    arb_poly_t ap;
    arb_t x, v, dv, a, b;
    arf_t step, tiny;
    fmpq_t q;
    arb_poly_init(ap);
    arb_init(x);
    arb_init(v);
    arb_init(dv);
    arb_init(a);
    arb_init(b);
    arf_init(step);
    arf_init(tiny);
    fmpq_init(q);
    arb_poly_set_fmpz_poly(ap, p, prec);
    arb_set_fmpq(a, lo, prec);
    arb_set_fmpq(b, hi, prec);
    arb_add(x, a, b, prec);
    arb_mul_2exp_si(x, x, -1);
    /* Settled: a step below 2^-(K + 4) of the interval's width. */
    arb_sub(v, b, a, prec);
    arf_mul_2exp_si(tiny, arb_midref(v), -(slong)K - 4);
    int ok = 0;
    slong iters = 2 * (slong)FLINT_BIT_COUNT(K) + 16;
    for (slong it = 0; it < iters; it++) {
        arb_get_mid_arb(x, x);
        arb_poly_evaluate2(v, dv, ap, x, prec);
        if (arf_is_zero(arb_midref(dv)))
            break;
        arf_div(step, arb_midref(v), arb_midref(dv), prec, ARF_RND_NEAR);
        arf_sub(arb_midref(x), arb_midref(x), step, prec, ARF_RND_NEAR);
        if (arf_cmp(arb_midref(x), arb_midref(a)) <= 0 ||
            arf_cmp(arb_midref(x), arb_midref(b)) >= 0)
            break;
        if (arf_cmpabs(step, tiny) <= 0) {
            ok = 1;
            break;
        }
    }
    if (ok) {
        /* c = floor((x D - A) 2^K / L) */
        arf_get_fmpq(q, arb_midref(x));
        fmpz_mul(fmpq_numref(q), fmpq_numref(q), D);
        fmpz_submul(fmpq_numref(q), fmpq_denref(q), A);
        fmpz_mul_2exp(fmpq_numref(q), fmpq_numref(q), K);
        fmpz_mul(fmpq_denref(q), fmpq_denref(q), L);
        fmpz_fdiv_q(c, fmpq_numref(q), fmpq_denref(q));
    }
    fmpq_clear(q);
    arf_clear(step);
    arf_clear(tiny);
    arb_clear(x);
    arb_clear(v);
    arb_clear(dv);
    arb_clear(a);
    arb_clear(b);
    arb_poly_clear(ap);
    return ok;
}

void cb_roots_refine(cb_roots_t r, slong k, const fmpq_t width)
{
    cb_root_interval_struct *iv = &r->root[k];
    fmpq_t w;
    fmpq_init(w);
    fmpq_sub(w, iv->hi, iv->lo);
    if (fmpq_cmp(w, width) <= 0) {
        fmpq_clear(w);
        return;
    }
    /* Bisection: after j steps the interval is lo + (hi - lo) [c, c + 1] / 2^j. The number of
     * steps K is the least with (hi - lo) / 2^K <= width. */
    fmpq_div(w, w, width);
    ulong K = (ulong)FLINT_MAX(0, fmpz_bits(fmpq_numref(w)) - fmpz_bits(fmpq_denref(w)));
    fmpz_t A, L, D, N, c, X, acc, t;
    fmpz_init(A);
    fmpz_init(L);
    fmpz_init(D);
    fmpz_init(N);
    fmpz_init(c);
    fmpz_init(X);
    fmpz_init(acc);
    fmpz_init(t);
    for (;;) {
        fmpz_mul_2exp(t, fmpq_denref(w), K);
        if (fmpz_cmp(t, fmpq_numref(w)) >= 0)
            break;
        K++;
    }
    /* lo = A / D, hi - lo = L / D. */
    fmpz_mul(D, fmpq_denref(iv->lo), fmpq_denref(iv->hi));
    fmpz_mul(A, fmpq_numref(iv->lo), fmpq_denref(iv->hi));
    fmpz_mul(L, fmpq_numref(iv->hi), fmpq_denref(iv->lo));
    fmpz_sub(L, L, A);
    slong d = fmpz_poly_degree(r->sqfree);
    fmpz *cf = _fmpz_vec_init(d + 1);
    fmpz_one(t);
    for (slong i = d; i >= 0; i--) {
        fmpz_mul(cf + i, r->sqfree->coeffs + i, t);
        fmpz_mul(t, t, D);
    }
    int sign_lo = sign_at_step(cf, d, A, L, c, 0, X, acc, t), exact = 0;
    /* The bisection ends in the cell of 2^K holding the root, or at a cell end that is the root
     * (every cell end is a midpoint of the bisection, which would hit it): where Newton's
     * guess is confirmed by the signs at a cell's ends, that is the answer without the K
     * steps (the 160-bit probe of a critical value, the 2^-56 of a Dixon inversion). */
    ulong j0 = 1;
    if (K >= 8 && newton_cell(N, r->sqfree, iv->lo, iv->hi, A, L, D, K)) {
        fmpz_t last;
        fmpz_init(last);
        fmpz_one_2exp(last, K);
        fmpz_sub_ui(last, last, 1);
        for (int tries = 0; tries < 4 && j0 == 1; tries++) {
            if (fmpz_sgn(N) < 0)
                fmpz_zero(N);
            if (fmpz_cmp(N, last) > 0)
                fmpz_set(N, last);
            int s0 = fmpz_is_zero(N) ? sign_lo : sign_at_step(cf, d, A, L, N, K, X, acc, t);
            fmpz_add_ui(c, N, 1);
            int s1 = fmpz_cmp(N, last) == 0 ? -sign_lo
                                             : sign_at_step(cf, d, A, L, c, K, X, acc, t);
            if (s0 == 0 || s1 == 0) {
                step_point(iv->lo, A, L, D, s0 == 0 ? N : c, K);
                fmpq_set(iv->hi, iv->lo);
                exact = 1;
                j0 = K + 1;
            } else if (s0 == sign_lo && s1 != sign_lo) {
                fmpz_set(c, N);
                j0 = K + 1;
            } else if (s0 != sign_lo) {
                fmpz_sub_ui(N, N, 1);
            } else {
                fmpz_add_ui(N, N, 1);
            }
        }
        fmpz_clear(last);
        if (j0 == 1)
            fmpz_zero(c);
    }
    for (ulong j = j0; j <= K; j++) {
        fmpz_mul_2exp(N, c, 1);
        fmpz_add_ui(N, N, 1);
        int s = sign_at_step(cf, d, A, L, N, j, X, acc, t);
        if (s == 0) {
            step_point(iv->lo, A, L, D, N, j);
            fmpq_set(iv->hi, iv->lo);
            exact = 1;
            break;
        }
        if (s == sign_lo)
            fmpz_swap(c, N);
        else
            fmpz_mul_2exp(c, c, 1);
    }
    if (!exact) {
        step_point(iv->lo, A, L, D, c, K);
        fmpz_add_ui(c, c, 1);
        step_point(iv->hi, A, L, D, c, K);
    }
    _fmpz_vec_clear(cf, d + 1);
    fmpz_clear(A);
    fmpz_clear(L);
    fmpz_clear(D);
    fmpz_clear(N);
    fmpz_clear(c);
    fmpz_clear(X);
    fmpz_clear(acc);
    fmpz_clear(t);
    fmpq_clear(w);
}

double cb_roots_mid_d(const cb_roots_t r, slong k)
{
    fmpq_t mid;
    fmpq_init(mid);
    fmpq_add(mid, r->root[k].lo, r->root[k].hi);
    fmpq_div_2exp(mid, mid, 1);
    double d = fmpq_get_d(mid);
    fmpq_clear(mid);
    return d;
}

int cb_roots_try_rational(cb_roots_t r, slong k)
{
    cb_root_interval_struct *iv = &r->root[k];
    if (fmpq_equal(iv->lo, iv->hi))
        return 1;
    fmpq_t q, val;
    fmpq_init(q);
    fmpq_init(val);
    fmpq_simplest_between(q, iv->lo, iv->hi);
    /* A rational root p / d of an integer polynomial has d dividing the leading coefficient:
     * most candidates fail that before the exact evaluation. */
    int rational = 0;
    if (fmpz_divisible(fmpz_poly_lead(r->sqfree), fmpq_denref(q))) {
        fmpz_poly_evaluate_fmpq(val, r->sqfree, q);
        rational = fmpq_is_zero(val);
    }
    if (rational) {
        fmpq_set(iv->lo, q);
        fmpq_set(iv->hi, q);
    }
    fmpq_clear(val);
    fmpq_clear(q);
    return rational;
}
