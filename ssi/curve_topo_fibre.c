/* Certified analysis of one critical line s = alpha of the curve h = 0 (ssi/curve_topo.h). */
#include "ssi/curve_topo.h"

#include <string.h>

#include <arb_fmpz_poly.h>
#include <arb_poly.h>
#include <flint/fmpz_poly_factor.h>

void cb_ctopo_fibre_init(cb_ctopo_fibre_t F)
{
    F->n_box = F->alloc_box = 0;
    F->box = NULL;
    cb_roots_init(F->left_roots);
    cb_roots_init(F->right_roots);
}

static void fibre_reset(cb_ctopo_fibre_t F)
{
    for (slong i = 0; i < F->n_box; i++) {
        cb_ctopo_fibre_box_struct *b = F->box + i;
        fmpq_clear(b->c);
        fmpq_clear(b->d);
        fmpq_clear(b->t_lo);
        fmpq_clear(b->t_hi);
    }
    F->n_box = 0;
}

void cb_ctopo_fibre_clear(cb_ctopo_fibre_t F)
{
    fibre_reset(F);
    flint_free(F->box);
    cb_roots_clear(F->left_roots);
    cb_roots_clear(F->right_roots);
}

/* Appends a box [c, d] holding no root yet; returns its index. */
static slong box_push(cb_ctopo_fibre_t F, const fmpq_t c, const fmpq_t d)
{
    if (F->n_box == F->alloc_box) {
        F->alloc_box = F->alloc_box ? 2 * F->alloc_box : 8;
        F->box = flint_realloc(F->box, (size_t)F->alloc_box * sizeof *F->box);
    }
    slong i = F->n_box++;
    cb_ctopo_fibre_box_struct *b = F->box + i;
    fmpq_init(b->c);
    fmpq_init(b->d);
    fmpq_init(b->t_lo);
    fmpq_init(b->t_hi);
    fmpq_set(b->c, c);
    fmpq_set(b->d, d);
    fmpq_set(b->t_lo, c);
    fmpq_set(b->t_hi, d);
    b->mult = 1;
    b->has_root = 0;
    b->sides = 0;
    b->singular = b->tangential = 0;
    b->n_left = b->n_right = 0;
    b->first_left = b->first_right = -1;
    return i;
}

static void arb_set_fmpq_interval(arb_t x, const fmpq_t lo, const fmpq_t hi, slong prec)
{
    arb_t b;
    arb_init(b);
    arb_set_fmpq(x, lo, prec);
    arb_set_fmpq(b, hi, prec);
    arb_union(x, x, b, prec);
    arb_clear(b);
}

/* A multiple fibre root, boxed with its t-derivative of order mult non-zero. */
typedef struct {
    fmpq_t lo, hi; /* enclosure of the root */
    slong mult;
    unsigned sides;
    int singular, tangential;
    int live;       /* inside [t0, t1] */
    slong fac, idx; /* rational alpha: root idx of the factor fac of the fibre */
} pin_struct;

/* Everything known about the line while its boxes are being certified. */
typedef struct {
    const cb_ctopo_curve_struct *C;
    cb_ctopo_line_struct *L;
    cb_roots_struct *cv;
    slong k;
    int rational;
    fmpq_t eps;               /* rational alpha: half width of the helping interval */
    slong n_fac;
    cb_roots_struct *fac;     /* rational alpha: roots of the multiple factors of the fibre */
    slong n_pin;
    pin_struct pin[64];
    int root_at[2];           /* t0 / t1 is a fibre root */
    int rep_at[2];            /* ... lying on a repeated factor */
    slong gcd_deg;
    cb_bipoly_t hf;           /* irrational alpha: h without the t-coefficients vanishing at
                                 alpha, so that its leading one does not (subresultants) */
    cb_bipoly_t *deriv;       /* deriv[m] = d^m h / dt^m */
    slong n_deriv;
    arb_poly_struct *fib;     /* fib[m](t) encloses deriv[m](s, t) for every s in the current
                                 s-range: coefficients in s enclosed once per range */
    slong n_fib, alloc_fib;
    slong fib_prec;
    fmpq_t sl, sr;            /* the s-range of the boxes */
    fmpq_t w;                 /* half-width of the pinned boxes */
    fmpq_t t0, t1;            /* copies of the curve's: GCC 12 misjudges the members' sizes */
    slong prec;               /* working precision of the first attempt (C->prec) */
    int have_beta;            /* irrational alpha: beta_num, beta_den computed */
    fmpz_poly_t beta_num, beta_den; /* the multiple root is beta_num(alpha) / beta_den(alpha):
                                       -sres_{k,k-1} and k psc_k, exact, made only when ball
                                       determinants at alpha do not decide */
} line_state;

static cb_status state_pin_push(line_state *st, cb_error *err)
{
    if (st->n_pin == 64)
        return cb_error_set(err, CB_ERR_UNSUPPORTED,
                            "curve topology: more than 64 multiple roots on one critical line");
    pin_struct *p = st->pin + st->n_pin++;
    fmpq_init(p->lo);
    fmpq_init(p->hi);
    p->mult = 2;
    p->sides = 0;
    p->singular = p->tangential = 0;
    p->fac = p->idx = -1;
    return CB_OK;
}

/* Bits to which an irrational-looking critical value is refined before its analysis, to
 * recognise a rational one (see cb_ctopo_fibre_analyse). */
#define RATIONAL_PROBE_BITS 160

static void range_update(line_state *st)
{
    cb_ctopo_line_struct *L = st->L;
    if (st->rational) {
        /* Through locals: GCC 12 misreads the sizes of the struct members here. */
        fmpq_t a, x;
        fmpq_init(a);
        fmpq_init(x);
        fmpq_set(a, L->lo);
        fmpq_sub(x, a, st->eps);
        if (L->has_left)
            fmpq_swap(L->left, x);
        fmpq_add(x, a, st->eps);
        if (L->has_right)
            fmpq_swap(L->right, x);
        fmpq_clear(x);
        fmpq_clear(a);
    } else if (!fmpq_equal(st->cv->root[st->k].lo, st->cv->root[st->k].hi)) {
        fmpq_set(L->lo, st->cv->root[st->k].lo);
        fmpq_set(L->hi, st->cv->root[st->k].hi);
        fmpq_set(L->left, L->lo);
        fmpq_set(L->right, L->hi);
    }
    /* (A refinement that hit a rational alpha exactly keeps the helping lines it had: they
     * must not collapse onto alpha. cb_ctopo_fibre_analyse turns such lines rational first.) */
    fmpq_set(st->sl, L->has_left ? L->left : L->lo);
    fmpq_set(st->sr, L->has_right ? L->right : L->hi);
    st->n_fib = 0;
}

/* About -log2(w) (within 1), at least 0, for w > 0. */
static slong neg_log2(const fmpq_t w)
{
    slong b = (slong)fmpz_bits(fmpq_denref(w)) - (slong)fmpz_bits(fmpq_numref(w)) - 1;
    return FLINT_MAX(b, 0);
}

/* How many bits the interval lo < hi knows. */
static slong interval_bits(const fmpq_t lo, const fmpq_t hi)
{
    fmpq_t w;
    fmpq_init(w);
    fmpq_sub(w, hi, lo);
    slong b = neg_log2(w);
    fmpq_clear(w);
    return b;
}

/* Irrational alpha: refines its interval to width <= 2^-bits (exactly, by bisection on the sign
 * of the squarefree critical polynomial) and updates the s-range. */
static void alpha_refine(line_state *st, slong bits)
{
    fmpq_t w;
    fmpq_init(w);
    fmpz_one(fmpq_numref(w));
    fmpz_one_2exp(fmpq_denref(w), (ulong)bits);
    cb_roots_refine(st->cv, st->k, w);
    fmpq_clear(w);
    range_update(st);
}

/* Shrinks the s-range: alpha's interval to 1/16 of its width, or eps to eps / 16. */
static void range_shrink(line_state *st)
{
    if (st->rational) {
        fmpq_div_2exp(st->eps, st->eps, 4);
    } else {
        fmpq_t w;
        fmpq_init(w);
        fmpq_sub(w, st->cv->root[st->k].hi, st->cv->root[st->k].lo);
        fmpq_div_2exp(w, w, 4);
        cb_roots_refine(st->cv, st->k, w);
        fmpq_clear(w);
    }
    range_update(st);
}

/* Encloses p(S) by the mean value form p(m) + p'(S) (S - m), intersected with Horner's: on
 * the narrow interval of an algebraic number Horner alone loses to cancellation. */
static void poly_eval_mv(arb_t y, const fmpz_poly_t p, const arb_t S, slong prec)
{
    fmpz_poly_t dp;
    arb_t m, g;
    fmpz_poly_init(dp);
    arb_init(m);
    arb_init(g);
    fmpz_poly_derivative(dp, p);
    arb_get_mid_arb(m, S);
    arb_fmpz_poly_evaluate_arb(g, dp, S, prec);
    arb_sub(y, S, m, prec);
    arb_mul(g, g, y, prec);
    arb_fmpz_poly_evaluate_arb(y, p, m, prec);
    arb_add(y, y, g, prec);
    arb_fmpz_poly_evaluate_arb(g, p, S, prec);
    arb_intersection(y, y, g, prec);
    arb_clear(g);
    arb_clear(m);
    fmpz_poly_clear(dp);
}

/* Makes deriv[0 .. m] available. */
static void deriv_fit(line_state *st, slong m)
{
    while (st->n_deriv <= m) {
        slong n = st->n_deriv;
        st->deriv = flint_realloc(st->deriv, (size_t)(n + 1) * sizeof *st->deriv);
        cb_bipoly_init(st->deriv[n]);
        if (n == 0)
            cb_bipoly_set(st->deriv[0], st->C->h);
        else
            cb_bipoly_derivative_t(st->deriv[n], st->deriv[n - 1]);
        st->n_deriv++;
    }
}

/* The ball polynomial in t enclosing d^m h / dt^m over the current s-range, made at precision
 * prec (kept until the range or the precision changes). */
static const arb_poly_struct *fib_poly(line_state *st, slong m, slong prec)
{
    if (prec != st->fib_prec) {
        st->n_fib = 0;
        st->fib_prec = prec;
    }
    if (m >= st->alloc_fib) {
        st->fib = flint_realloc(st->fib, (size_t)(m + 1) * sizeof *st->fib);
        for (slong i = st->alloc_fib; i <= m; i++)
            arb_poly_init(st->fib + i);
        st->alloc_fib = m + 1;
    }
    if (m < st->n_fib)
        return st->fib + m;
    arb_t S, c;
    arb_init(S);
    arb_init(c);
    arb_set_fmpq_interval(S, st->sl, st->sr, prec);
    deriv_fit(st, m);
    for (slong i = st->n_fib; i <= m; i++) {
        const cb_bipoly_struct *q = st->deriv[i];
        arb_poly_zero(st->fib + i);
        for (slong j = 0; j < q->len; j++) {
            poly_eval_mv(c, q->c + j, S, prec);
            arb_poly_set_coeff_arb(st->fib + i, j, c);
        }
    }
    st->n_fib = m + 1;
    arb_clear(c);
    arb_clear(S);
    return st->fib + m;
}

/* Is d^m h / dt^m free of zeros on [sl, sr] x [c, d]? The t-polynomial is Taylor-shifted to
 * the centre of [c, d] and evaluated on the centred interval: the shifted coefficients have
 * the size of the function there, where Horner on [c, d] (or a mean value form with a Horner
 * derivative) pays for the cancellation among large power-basis coefficients — at bidegree 12
 * that forced boxes of width 1e-4 and tens of thousands of them per line. */
static int nonzero_on(line_state *st, slong m, const fmpq_t c, const fmpq_t d, slong prec)
{
    const arb_poly_struct *H = fib_poly(st, m, prec);
    arb_poly_t G;
    arb_t T, tm, y;
    arb_poly_init(G);
    arb_init(T);
    arb_init(tm);
    arb_init(y);
    arb_set_fmpq_interval(T, c, d, prec);
    arb_get_mid_arb(tm, T);
    arb_sub(T, T, tm, prec);
    arb_poly_taylor_shift(G, H, tm, prec);
    arb_poly_evaluate(y, G, T, prec);
    int ok = !arb_contains_zero(y);
    arb_clear(y);
    arb_clear(tm);
    arb_clear(T);
    arb_poly_clear(G);
    return ok;
}

/* No curve point crosses the horizontal edge t = c over the s-range (t0, t1 need no proof:
 * their crossings are critical values, and alpha is the only one in the range). */
static int edge_clear(line_state *st, const fmpq_t c, slong prec)
{
    if (fmpq_equal(c, st->t0) || fmpq_equal(c, st->t1))
        return 1;
    return nonzero_on(st, 0, c, c, prec);
}

/* ---------------------------------------------------------------- exact fibre facts ------- */

/* Rational alpha: factor h(alpha, t); multiple roots in [t0, t1] become pins. */
static cb_status rational_facts(line_state *st, cb_error *err)
{
    const cb_ctopo_curve_struct *C = st->C;
    const fmpq *alpha = st->L->lo;
    fmpz_poly_t f, hs, g;
    fmpz_poly_factor_t fac;
    cb_bipoly_t d;
    cb_status stt = CB_OK;
    fmpz_poly_init(f);
    fmpz_poly_init(hs);
    fmpz_poly_init(g);
    fmpz_poly_factor_init(fac);
    cb_bipoly_init(d);

    cb_bipoly_eval_s_fmpq(f, C->h, alpha);
    cb_bipoly_derivative_s(d, C->h);
    cb_bipoly_eval_s_fmpq(hs, d, alpha);
    if (C->rep->len > 0)
        cb_bipoly_eval_s_fmpq(g, C->rep, alpha);
    for (int i = 0; i < 2; i++) {
        fmpq_t v;
        fmpq_init(v);
        fmpz_poly_evaluate_fmpq(v, f, i ? st->t1 : st->t0);
        st->root_at[i] = fmpq_is_zero(v);
        if (C->rep->len > 0) {
            fmpz_poly_evaluate_fmpq(v, g, i ? st->t1 : st->t0);
            st->rep_at[i] = fmpq_is_zero(v);
        }
        fmpq_clear(v);
    }
    fmpz_poly_factor_squarefree(fac, f);
    st->fac = flint_malloc((size_t)FLINT_MAX(fac->num, 1) * sizeof *st->fac);
    for (slong i = 0; i < fac->num && stt == CB_OK; i++) {
        if (fac->exp[i] < 2 || fmpz_poly_degree(fac->p + i) < 1)
            continue;
        slong fi = st->n_fac++;
        cb_roots_init(st->fac + fi);
        stt = cb_roots_isolate(st->fac + fi, fac->p + i, st->t0, st->t1, err);
        for (slong r = 0; r < st->fac[fi].n && stt == CB_OK; r++) {
            stt = state_pin_push(st, err);
            if (stt != CB_OK)
                break;
            pin_struct *p = st->pin + st->n_pin - 1;
            const cb_root_interval_struct *iv = st->fac[fi].root + r;
            p->mult = fac->exp[i];
            p->fac = fi;
            p->idx = r;
            p->singular = cb_ctopo_alg_vanishes(hs, st->fac[fi].sqfree, iv->lo, iv->hi);
            p->tangential = C->rep->len > 0 &&
                            cb_ctopo_alg_vanishes(g, st->fac[fi].sqfree, iv->lo, iv->hi);
            if (fmpq_equal(iv->lo, iv->hi))
                p->sides = fmpq_equal(iv->lo, st->t0)   ? CB_CTOPO_SIDE_T0
                           : fmpq_equal(iv->lo, st->t1) ? CB_CTOPO_SIDE_T1
                                                       : 0;
        }
    }
    fmpz_poly_derivative(hs, f);
    fmpz_poly_gcd(hs, f, hs);
    st->gcd_deg = fmpz_poly_degree(hs);
    cb_bipoly_clear(d);
    fmpz_poly_factor_clear(fac);
    fmpz_poly_clear(g);
    fmpz_poly_clear(hs);
    fmpz_poly_clear(f);
    return stt;
}

/* Makes the exact beta_num = -sres_{k,k-1}, beta_den = k psc_k (k = gcd_deg >= 1); beta_den
 * may already be there (non-zero: psc_k does not vanish at alpha) from the gcd degree. */
static void beta_exact(line_state *st)
{
    if (st->have_beta)
        return;
    slong k = st->gcd_deg;
    if (fmpz_poly_is_zero(st->beta_den)) {
        cb_ctopo_sres_coeff(st->beta_den, st->hf, k, k);
        fmpz_poly_scalar_mul_si(st->beta_den, st->beta_den, k);
    }
    cb_ctopo_sres_coeff(st->beta_num, st->hf, k, k - 1);
    fmpz_poly_neg(st->beta_num, st->beta_num);
    st->have_beta = 1;
}

/* beta = -sres_{k,k-1}(alpha) / (k psc_k(alpha)) as a ball: from the exact polynomials when
 * they exist, else from the subresultant determinants evaluated at the alpha ball (cheap, but
 * the Sylvester matrix is nearly singular at a critical value, so this can stay undecided). */
static void beta_ball(arb_t beta, line_state *st, slong prec)
{
    arb_t S, den;
    arb_init(S);
    arb_init(den);
    arb_set_fmpq_interval(S, st->L->lo, st->L->hi, prec);
    if (st->have_beta) {
        poly_eval_mv(den, st->beta_den, S, prec);
        poly_eval_mv(beta, st->beta_num, S, prec);
    } else {
        cb_ctopo_sres_coeff_arb(den, st->hf, st->gcd_deg, st->gcd_deg, S, prec);
        arb_mul_si(den, den, st->gcd_deg, prec);
        cb_ctopo_sres_coeff_arb(beta, st->hf, st->gcd_deg, st->gcd_deg - 1, S, prec);
        arb_neg(beta, beta);
    }
    arb_div(beta, beta, den, prec);
    arb_clear(den);
    arb_clear(S);
}

/* Encloses beta in a ball of width <= 2^-goal. beta = N(alpha) / D(alpha) where N and D can
 * both be tiny at alpha (a root of D within 2^-300 of alpha was met at bidegree 12), so the
 * bits of alpha double per round with the precision following; after four rounds the exact
 * N, D replace the determinants. 0 if still undecided after eight rounds. */
static int beta_narrow(arb_t beta, line_state *st, slong goal)
{
    slong prec = st->prec;
    for (slong round = 0; round < 8; round++) {
        if (round > 0) {
            slong bits = 2 * interval_bits(st->L->lo, st->L->hi) + 64;
            alpha_refine(st, bits);
            prec = FLINT_MAX(prec, bits + st->prec);
        }
        if (round == 4)
            beta_exact(st);
        beta_ball(beta, st, prec);
        if (arb_is_finite(beta) && mag_cmp_2exp_si(arb_radref(beta), -goal) <= 0)
            return 1;
    }
    return 0;
}

/* p(s) = sum_j q_j(s) N(s)^j D(s)^(n-j): q(s, N/D) with denominators cleared. */
static void compose_rational(fmpz_poly_t out, const cb_bipoly_t q, const fmpz_poly_t N,
                             const fmpz_poly_t D)
{
    fmpz_poly_t acc, term;
    fmpz_poly_init(acc);
    fmpz_poly_init(term);
    /* Horner: acc = acc N + q_j D^(n-j), done as acc = acc N + q_j D^... by scaling acc. */
    for (slong j = q->len - 1; j >= 0; j--) {
        fmpz_poly_mul(acc, acc, N);
        fmpz_poly_pow(term, D, (ulong)(q->len - 1 - j));
        fmpz_poly_mul(term, term, q->c + j);
        fmpz_poly_add(acc, acc, term);
    }
    fmpz_poly_swap(out, acc);
    fmpz_poly_clear(term);
    fmpz_poly_clear(acc);
}

/* Is the ball polynomial G zero-free on [c, d]? Mean value form G(m) + G'([c, d]) ([c, d] - m)
 * with bisection, at most *budget evaluations of the form (a "no" is then no proof of a zero,
 * only of none found in time). Why the budget: near a zero of G at or just beyond an end of
 * [c, d] the leaves this form proves shrink geometrically, and in the monomial basis, whose
 * coefficients cancel there, faster still: a gcd c (1 - t)^9 on [0, 1] (linkrods' sweep
 * against a plane) ran past 300 s without one. */
static int arb_poly_zero_free(const arb_poly_t G, const arb_poly_t dG, const fmpq_t c,
                              const fmpq_t d, slong depth, slong *budget, slong prec)
{
    if (*budget <= 0)
        return 0;
    (*budget)--;
    arb_t T, m, y, g;
    fmpq_t mid;
    arb_init(T);
    arb_init(m);
    arb_init(y);
    arb_init(g);
    fmpq_init(mid);
    arb_set_fmpq_interval(T, c, d, prec);
    arb_get_mid_arb(m, T);
    arb_poly_evaluate(y, G, m, prec);
    arb_poly_evaluate(g, dG, T, prec);
    arb_sub(m, T, m, prec);
    arb_addmul(y, g, m, prec);
    int ok = !arb_contains_zero(y);
    if (!ok && depth > 0) {
        fmpq_add(mid, c, d);
        fmpq_div_2exp(mid, mid, 1);
        ok = arb_poly_zero_free(G, dG, c, mid, depth - 1, budget, prec) &&
             arb_poly_zero_free(G, dG, mid, d, depth - 1, budget, prec);
    }
    fmpq_clear(mid);
    arb_clear(g);
    arb_clear(y);
    arb_clear(m);
    arb_clear(T);
    return ok;
}

/* Does G's enclosure at the point x contain zero (then no bisection can prove [.., x] or
 * [x, ..] zero-free)? */
static int arb_poly_maybe_zero_at(const arb_poly_t G, const fmpq_t x, slong prec)
{
    arb_t X, y;
    arb_init(X);
    arb_init(y);
    arb_set_fmpq(X, x, prec);
    arb_poly_evaluate(y, G, X, prec);
    int z = arb_contains_zero(y);
    arb_clear(y);
    arb_clear(X);
    return z;
}

/* Is the gcd sum_i sres_{k,i}(alpha) t^i of h(alpha, t) and h_t(alpha, t) proved free of
 * zeros on [t0, t1] (ball arithmetic, alpha refined as the precision grows)? */
static int gcd_real_free(line_state *st, slong k)
{
    int ok = 0;
    arb_poly_t G, dG;
    arb_t S, c;
    fmpq_t w;
    arb_poly_init(G);
    arb_poly_init(dG);
    arb_init(S);
    arb_init(c);
    fmpq_init(w);
    for (slong round = 0; round < 4 && !ok; round++) {
        slong prec = st->prec << round;
        fmpz_one(fmpq_numref(w));
        fmpz_one_2exp(fmpq_denref(w), (ulong)(prec / 2));
        cb_roots_refine(st->cv, st->k, w);
        arb_set_fmpq_interval(S, st->cv->root[st->k].lo, st->cv->root[st->k].hi, prec);
        for (slong i = 0; i <= k; i++) {
            cb_ctopo_sres_coeff_arb(c, st->hf, k, i, S, prec);
            arb_poly_set_coeff_arb(G, i, c);
        }
        arb_poly_derivative(dG, G, prec);
        /* 2^12 evaluations: in the SSI, topology and Boolean tests a proof took 3, a failure
         * 93 to 127 */
        slong budget = 1 << 12;
        ok = !arb_poly_maybe_zero_at(G, st->t0, prec) &&
             !arb_poly_maybe_zero_at(G, st->t1, prec) &&
             arb_poly_zero_free(G, dG, st->t0, st->t1, st->C->opts->max_depth, &budget, prec);
    }
    range_update(st);
    fmpq_clear(w);
    arb_clear(c);
    arb_clear(S);
    arb_poly_clear(dG);
    arb_poly_clear(G);
    return ok;
}

/* Is psc_j(alpha) proved non-zero by the ball determinant? alpha is refined to 64, 128, 256
 * bits (the determinant's enclosure widens with the ill-conditioning of the Sylvester matrix
 * near a critical value). A "no" is not a proof of zero: the caller decides exactly. */
static int sres_ball_nonzero(line_state *st, slong j)
{
    arb_t S, v;
    arb_init(S);
    arb_init(v);
    int ok = 0;
    for (slong bits = 64; bits <= 256 && !ok; bits *= 2) {
        alpha_refine(st, bits);
        slong prec = st->prec + 2 * bits;
        arb_set_fmpq_interval(S, st->L->lo, st->L->hi, prec);
        cb_ctopo_sres_coeff_arb(v, st->hf, j, j, S, prec);
        ok = !arb_contains_zero(v);
    }
    arb_clear(v);
    arb_clear(S);
    return ok;
}

/* Is the single multiple root (alpha, beta), of multiplicity k + 1 in its fibre, a singular
 * point? Where lc_t h(alpha) != 0 every point of the fibre is finite, and Teissier's lemma
 * (f, f_t)_p = mu_p + (f, s - alpha)_p - 1 summed over the fibre gives
 * ord_alpha Res_t(h, h_t) = mu + k, every other root being simple: the point is singular
 * (mu >= 1) iff the k-th derivative of res vanishes at alpha too. Otherwise h_s(alpha, beta)
 * is tried in ball arithmetic, then decided exactly as h_s(s, N/D) with denominators cleared. */
static int beta_singular(line_state *st, const fmpz_poly_t res, slong k)
{
    const cb_ctopo_curve_struct *C = st->C;
    const fmpz_poly_struct *r = st->cv->sqfree;
    fmpz_poly_t q;
    fmpz_poly_init(q);
    int sing;
    if (st->hf->len == C->h->len) {
        fmpz_poly_set(q, res);
        for (slong i = 0; i < k; i++)
            fmpz_poly_derivative(q, q);
        sing = cb_ctopo_alg_vanishes(q, r, st->L->lo, st->L->hi);
    } else {
        cb_bipoly_t d;
        arb_t beta, S, y;
        cb_bipoly_init(d);
        arb_init(beta);
        arb_init(S);
        arb_init(y);
        cb_bipoly_derivative_s(d, C->h);
        sing = -1;
        if (beta_narrow(beta, st, 64)) {
            slong prec = FLINT_MAX(st->prec, 2 * interval_bits(st->L->lo, st->L->hi));
            arb_set_fmpq_interval(S, st->L->lo, st->L->hi, prec);
            cb_bipoly_eval_arb(y, d, S, beta, prec);
            if (!arb_contains_zero(y))
                sing = 0;
        }
        if (sing < 0) {
            beta_exact(st);
            compose_rational(q, d, st->beta_num, st->beta_den);
            sing = cb_ctopo_alg_vanishes(q, r, st->L->lo, st->L->hi);
        }
        arb_clear(y);
        arb_clear(S);
        arb_clear(beta);
        cb_bipoly_clear(d);
    }
    fmpz_poly_clear(q);
    return sing;
}

/* Irrational alpha: gcd degree, single multiple root (or CB_ERR_UNSUPPORTED), its exact
 * properties. */
static cb_status irrational_facts(line_state *st, cb_error *err)
{
    const cb_ctopo_curve_struct *C = st->C;
    const fmpz_poly_struct *r = st->cv->sqfree;
    const fmpq *lo = st->L->lo, *hi = st->L->hi;
    /* Where lc_t(h) vanishes the fibre h(alpha, t) has a lower degree (branches escape to
     * infinity, outside the box); its gcd structure is that of the truncation hf. */
    slong top = C->h->len - 1;
    while (top > 0 && cb_ctopo_alg_vanishes(C->h->c + top, r, lo, hi))
        top--;
    cb_bipoly_set(st->hf, C->h);
    st->hf->len = top + 1;
    for (int i = 0; i < 2; i++) {
        st->root_at[i] = C->side_t[i] || cb_ctopo_alg_vanishes(C->bnd[i], r, lo, hi);
        if (st->root_at[i] && C->rep->len > 0) {
            fmpz_poly_t g;
            fmpz_poly_init(g);
            cb_bipoly_eval_t_fmpq(g, C->rep, i ? st->t1 : st->t0);
            st->rep_at[i] = cb_ctopo_alg_vanishes(g, r, lo, hi);
            fmpz_poly_clear(g);
        }
    }

    slong n = st->hf->len - 1;
    st->gcd_deg = 0;
    fmpz_poly_t res;
    fmpz_poly_init(res);
    /* A fibre of degree < 2 in t (lc_t h vanishing with all but the lowest one or two
     * coefficients) has no multiple root; its subresultants would be empty determinants. */
    if (n >= 2 && top < C->h->len - 1)
        cb_bipoly_resultant_dt(res, st->hf); /* psc_0 of hf */
    else if (n >= 2)
        fmpz_poly_set(res, C->res);
    int multiple = n >= 2 && cb_ctopo_alg_vanishes(res, r, lo, hi);
    if (multiple) {
        fmpz_poly_t p;
        fmpz_poly_init(p);
        for (slong j = 1; j < n; j++) {
            if (sres_ball_nonzero(st, j)) {
                st->gcd_deg = j;
                break;
            }
            cb_ctopo_sres_coeff(p, st->hf, j, j);
            if (!cb_ctopo_alg_vanishes(p, r, lo, hi)) {
                st->gcd_deg = j;
                fmpz_poly_scalar_mul_si(st->beta_den, p, j);
                break;
            }
        }
        fmpz_poly_clear(p);
    }
    slong k = st->gcd_deg;
    if (k == 0) {
        fmpz_poly_clear(res);
        return CB_OK;
    }

    /* gcd = psc_k (t - beta)^k  <=>  sres_{k,i} k^(k-i) psc_k^(k-i-1) = C(k,i) sres_{k,k-1}^(k-i)
     * for i < k - 1: a single multiple root, of multiplicity k + 1. A fold (k = 1) needs no
     * proof and no exact subresultant. */
    fmpz_poly_t pk, pk1, a, b, e;
    fmpz_t bin;
    fmpz_poly_init(pk);
    fmpz_poly_init(pk1);
    fmpz_poly_init(a);
    fmpz_poly_init(b);
    fmpz_poly_init(e);
    fmpz_init(bin);
    int generic = 1;
    cb_status stt = CB_OK;
    /* Several multiple roots, or one of order > 2: if the gcd is proved free of real roots
     * in [t0, t1] (cheap, ball arithmetic; such as two complex conjugate crossings of two
     * circles), every real fibre root in the box is simple, nothing needs pinning and the exact subresultants
     * of the identity below (determinants of order 2n - 1 - 2k, tens of seconds at t-degree
     * 24) are skipped. */
    if (k >= 2 && gcd_real_free(st, k))
        goto done;
    if (k >= 2) {
        beta_exact(st);
        fmpz_poly_scalar_divexact_si(pk, st->beta_den, k);
        fmpz_poly_neg(pk1, st->beta_num);
    }
    for (slong i = 0; i + 1 < k && generic; i++) {
        cb_ctopo_sres_coeff(a, st->hf, k, i);
        fmpz_poly_pow(e, pk, (ulong)(k - i - 1));
        fmpz_poly_mul(a, a, e);
        fmpz_ui_pow_ui(bin, (ulong)k, (ulong)(k - i));
        fmpz_poly_scalar_mul_fmpz(a, a, bin);
        fmpz_poly_pow(b, pk1, (ulong)(k - i));
        fmpz_bin_uiui(bin, (ulong)k, (ulong)i);
        fmpz_poly_scalar_mul_fmpz(b, b, bin);
        fmpz_poly_sub(a, a, b);
        generic = cb_ctopo_alg_vanishes(a, r, lo, hi);
    }
    if (!generic) {
        stt = cb_error_set(err, CB_ERR_UNSUPPORTED,
                           "curve topology: critical fibre not in generic position (more than "
                           "one multiple root over the irrational critical value s ~ %.17g)",
                           st->L->s);
        goto done;
    }
    stt = state_pin_push(st, err);
    if (stt != CB_OK)
        goto done;
    pin_struct *p = st->pin;
    p->mult = k + 1;
    for (int i = 0; i < 2 && !p->sides; i++) {
        if (!st->root_at[i])
            continue;
        /* beta = t_i iff N - t_i D vanishes at alpha (beta = N / D). */
        const fmpq *ti = i ? st->t1 : st->t0;
        beta_exact(st);
        fmpz_poly_scalar_mul_fmpz(a, st->beta_num, fmpq_denref(ti));
        fmpz_poly_scalar_mul_fmpz(b, st->beta_den, fmpq_numref(ti));
        fmpz_poly_sub(a, a, b);
        if (cb_ctopo_alg_vanishes(a, r, lo, hi)) {
            p->sides = i ? CB_CTOPO_SIDE_T1 : CB_CTOPO_SIDE_T0;
            fmpq_set(p->lo, ti);
            fmpq_set(p->hi, ti);
        }
    }
    p->singular = beta_singular(st, res, k);
    /* On a repeated factor g (g | h): g(alpha, .) then has beta as a multiple root, the only
     * multiple root h(alpha, .) has; so it is Res_t(g, g_t)(alpha) = 0. */
    p->tangential = C->rep->len > 1 && cb_ctopo_alg_vanishes(C->rep_res, r, lo, hi);
done:
    fmpz_clear(bin);
    fmpz_poly_clear(e);
    fmpz_poly_clear(b);
    fmpz_poly_clear(a);
    fmpz_poly_clear(pk1);
    fmpz_poly_clear(pk);
    fmpz_poly_clear(res);
    return stt;
}

/* ------------------------------------------------------------------ certification -------- */

static void fmpq_set_arf(fmpq_t q, const arf_t x) { arf_get_fmpq(q, x); }

/* Enclosure of pin i of width <= w (exact rational roots), or of the ball beta; 0 if the
 * enclosure is not yet decided against [t0, t1] (caller shrinks and retries), -1 if the root
 * lies outside [t0, t1]. */
static int pin_enclose(line_state *st, pin_struct *p, const fmpq_t w, slong prec)
{
    if (st->rational) {
        cb_roots_struct *R = st->fac + p->fac;
        cb_roots_refine(R, p->idx, w);
        fmpq_set(p->lo, R->root[p->idx].lo);
        fmpq_set(p->hi, R->root[p->idx].hi);
        return 1;
    }
    if (p->sides)
        return 1;
    /* beta is not t0 or t1 here (proved exactly), so narrowing decides which side it is on. */
    arb_t beta;
    arf_t x;
    arb_init(beta);
    arf_init(x);
    int ok = 0;
    slong goal = neg_log2(w) + 3;
    for (slong extra = 0; extra < 4 && ok == 0; extra++) {
        if (!beta_narrow(beta, st, goal + 32 * extra))
            break;
        arb_get_lbound_arf(x, beta, prec);
        fmpq_set_arf(p->lo, x);
        arb_get_ubound_arf(x, beta, prec);
        fmpq_set_arf(p->hi, x);
        if (fmpq_cmp(p->hi, st->t0) < 0 || fmpq_cmp(p->lo, st->t1) > 0)
            ok = -1;
        else if (fmpq_cmp(p->lo, st->t0) >= 0 && fmpq_cmp(p->hi, st->t1) <= 0)
            ok = 1;
    }
    arf_clear(x);
    arb_clear(beta);
    return ok;
}

/* Bisects [c, d] into boxes where h != 0 (dropped) or h_t != 0 with clear edges (kept). */
static int partition(cb_ctopo_fibre_t F, line_state *st, const fmpq_t c, const fmpq_t d,
                     slong depth, slong prec)
{
    if (fmpq_cmp(c, d) >= 0)
        return 1;
    if (nonzero_on(st, 0, c, d, prec))
        return 1;
    if (nonzero_on(st, 1, c, d, prec) && edge_clear(st, c, prec) && edge_clear(st, d, prec)) {
        box_push(F, c, d);
        return 1;
    }
    if (depth >= st->C->opts->max_depth)
        return 0;
    /* Cut at a dyadic point near the middle (small denominators keep the exact arithmetic
     * cheap at any depth); the middle itself can be a root of a designed curve, where no edge
     * test ever passes, so the first of 1/2, 3/8, 5/8, 7/16, 9/16 with a clear edge is taken. */
    static const slong cut[5][2] = {{1, 1}, {3, 3}, {5, 3}, {7, 4}, {9, 4}};
    fmpq_t m, len;
    fmpq_init(m);
    fmpq_init(len);
    fmpq_sub(len, d, c);
    for (int i = 0; i < 5; i++) {
        fmpq_mul_si(m, len, cut[i][0]);
        fmpq_div_2exp(m, m, (ulong)cut[i][1]);
        fmpq_add(m, m, c);
        if (edge_clear(st, m, prec))
            break;
        if (i == 4) {
            fmpq_add(m, c, d);
            fmpq_div_2exp(m, m, 1);
        }
    }
    fmpq_clear(len);
    int ok = partition(F, st, c, m, depth + 1, prec) && partition(F, st, m, d, depth + 1, prec);
    fmpq_clear(m);
    return ok;
}

static int cmp_pin(const void *x, const void *y)
{
    const pin_struct *a = x, *b = y;
    return fmpq_cmp(a->lo, b->lo);
}

static int cmp_box(const void *x, const void *y)
{
    const cb_ctopo_fibre_box_struct *a = x, *b = y;
    return fmpq_cmp(a->c, b->c);
}

/* Puts every helping root of R into its box; 0 if one is in no box. */
static int assign_roots(cb_ctopo_fibre_t F, cb_roots_t R, int right)
{
    slong b = 0;
    for (slong i = 0; i < R->n; i++) {
        cb_root_interval_struct *iv = R->root + i;
        int placed = 0;
        for (int tries = 0; tries < 200 && !placed; tries++) {
            for (b = 0; b < F->n_box; b++)
                if (fmpq_cmp(F->box[b].c, iv->lo) <= 0 && fmpq_cmp(iv->hi, F->box[b].d) <= 0)
                    break;
            if (b < F->n_box) {
                placed = 1;
            } else {
                if (fmpq_equal(iv->lo, iv->hi))
                    return 0;
                fmpq_t w;
                fmpq_init(w);
                fmpq_sub(w, iv->hi, iv->lo);
                fmpq_div_2exp(w, w, 1);
                cb_roots_refine(R, i, w);
                fmpq_clear(w);
            }
        }
        if (!placed)
            return 0;
        cb_ctopo_fibre_box_struct *B = F->box + b;
        slong *n = right ? &B->n_right : &B->n_left;
        slong *first = right ? &B->first_right : &B->first_left;
        if (*n == 0)
            *first = i;
        (*n)++;
    }
    return 1;
}

/* What an attempt asks of the next one: narrower pinned boxes, a narrower s-range. */
#define FAIL_W 1
#define FAIL_S 2

/* One attempt at certifying the boxes with the current s-range and pin half-width st->w;
 * 0 on success, else FAIL_* bits. The pinned boxes' edge values shrink like w^mult while
 * the ball overestimation shrinks with the s-range, so only a failing derivative test (the
 * box is too tall) shrinks w. */
static int attempt(cb_ctopo_fibre_t F, line_state *st, slong att, cb_error *err,
                   cb_status *stt)
{
    const cb_ctopo_curve_struct *C = st->C;
    cb_ctopo_line_struct *L = st->L;
    slong prec = st->prec + 32 * att;
    int fail = 0;
    fmpq_t c, d, tw;
    fmpq_init(c);
    fmpq_init(d);
    fmpq_init(tw);
    fibre_reset(F);

    /* Pinned boxes: half-width w, enclosures of width <= w / 4. */
    fmpq_div_2exp(tw, st->w, 2);
    for (slong i = 0; i < st->n_pin; i++) {
        int e = pin_enclose(st, st->pin + i, tw, prec);
        if (e == 0)
            fail |= FAIL_S;
        st->pin[i].live = e > 0;
    }
    if (!fail && st->n_pin > 1)
        qsort(st->pin, (size_t)st->n_pin, sizeof *st->pin, cmp_pin);
    fmpq_set(c, st->t0);
    for (slong i = 0; i < st->n_pin && !fail; i++) {
        pin_struct *p = st->pin + i;
        if (!p->live)
            continue;
        fmpq_sub(d, p->lo, st->w);
        if (fmpq_cmp(d, st->t0) < 0)
            fmpq_set(d, st->t0);
        /* Below the box: the gap from the previous box, which must not overlap it. */
        if (fmpq_cmp(c, d) > 0)
            fail |= FAIL_W;
        else if (!partition(F, st, c, d, 0, prec))
            fail |= FAIL_S;
        fmpq_add(c, p->hi, st->w);
        if (fmpq_cmp(c, st->t1) > 0)
            fmpq_set(c, st->t1);
        if (!fail && !nonzero_on(st, p->mult, d, c, prec))
            fail |= FAIL_W | FAIL_S;
        if (!fail && !(edge_clear(st, d, prec) && edge_clear(st, c, prec)))
            fail |= FAIL_S;
        if (!fail) {
            slong b = box_push(F, d, c);
            cb_ctopo_fibre_box_struct *B = F->box + b;
            B->mult = p->mult;
            B->has_root = 1;
            B->sides = p->sides;
            B->singular = p->singular;
            B->tangential = p->tangential;
            fmpq_set(B->t_lo, p->lo);
            fmpq_set(B->t_hi, p->hi);
        }
    }
    if (!fail && !partition(F, st, c, st->t1, 0, prec))
        fail |= FAIL_S;
    int ok = !fail;
    if (ok && F->n_box > 1)
        qsort(F->box, (size_t)F->n_box, sizeof *F->box, cmp_box);

    /* Helping roots, each inside one box. */
    if (ok && L->has_left) {
        fmpz_poly_t f;
        fmpz_poly_init(f);
        cb_bipoly_eval_s_fmpq(f, C->h, L->left);
        *stt = cb_roots_isolate(F->left_roots, f, st->t0, st->t1, err);
        ok = *stt == CB_OK && assign_roots(F, F->left_roots, 0);
        fmpz_poly_clear(f);
    }
    if (ok && L->has_right) {
        fmpz_poly_t f;
        fmpz_poly_init(f);
        cb_bipoly_eval_s_fmpq(f, C->h, L->right);
        *stt = cb_roots_isolate(F->right_roots, f, st->t0, st->t1, err);
        ok = *stt == CB_OK && assign_roots(F, F->right_roots, 1);
        fmpz_poly_clear(f);
    }

    /* Unpinned boxes: a root iff a branch enters, or a side root known exactly. */
    for (slong b = 0; ok && b < F->n_box; b++) {
        cb_ctopo_fibre_box_struct *B = F->box + b;
        if (B->mult > 1)
            continue;
        for (int i = 0; i < 2; i++) {
            const fmpq *ti = i ? st->t1 : st->t0;
            if (st->root_at[i] && fmpq_cmp(B->c, ti) <= 0 && fmpq_cmp(ti, B->d) <= 0) {
                B->sides = i ? CB_CTOPO_SIDE_T1 : CB_CTOPO_SIDE_T0;
                B->tangential = st->rep_at[i];
                fmpq_set(B->t_lo, ti);
                fmpq_set(B->t_hi, ti);
            }
        }
        B->has_root = B->sides || B->n_left + B->n_right > 0;
    }
    fmpq_clear(tw);
    fmpq_clear(d);
    fmpq_clear(c);
    if (!ok && !fail)
        fail = FAIL_S;
    return fail;
}

cb_status cb_ctopo_fibre_analyse(cb_ctopo_fibre_t F, const cb_ctopo_curve_struct *C,
                                cb_roots_t cv, slong k, cb_ctopo_line_struct *L, cb_error *err)
{
    line_state st;
    memset(&st, 0, sizeof st);
    st.C = C;
    st.L = L;
    st.cv = cv;
    st.k = k;
    st.rational = fmpq_equal(L->lo, L->hi);
    fmpq_init(st.eps);
    fmpq_init(st.sl);
    fmpq_init(st.sr);
    cb_bipoly_init(st.hf);
    fmpq_init(st.w);
    fmpq_init(st.t0);
    fmpq_init(st.t1);
    fmpq_set(st.t0, C->t0);
    fmpq_set(st.t1, C->t1);
    st.prec = C->prec;
    fmpz_poly_init(st.beta_num);
    fmpz_poly_init(st.beta_den);
    fmpq_sub(st.w, st.t1, st.t0);
    fmpq_div_2exp(st.w, st.w, 3);
    if (!st.rational) {
        /* An interval that is not a point may still hold a rational alpha (a dyadic one is hit
         * exactly by bisection, possibly late, when the helping lines would collapse onto it;
         * others, such as 7/19 where a Bezier patch of a B-spline with a knot at 13/16 meets
         * a designed feature at a dyadic point, never are). Refined to
         * 2^-RATIONAL_PROBE_BITS, the interval shows every dyadic alpha of fewer bits, and
         * its simplest rational every alpha of denominator below 2^(RATIONAL_PROBE_BITS / 2)
         * (checked exactly); such a line becomes rational, with helping lines alpha -+ eps
         * inside its isolating interval (which holds no other critical value), eps a power of
         * two at most a quarter of the room on either side. Two multiple roots over a
         * rational alpha are handled exactly, over an irrational one not yet. */
        fmpq_t w;
        fmpq_init(w);
        fmpz_one(fmpq_numref(w));
        fmpz_one_2exp(fmpq_denref(w), RATIONAL_PROBE_BITS);
        cb_roots_refine(cv, k, w);
        const cb_root_interval_struct *iv = cv->root + k;
        if (cb_roots_try_rational(cv, k)) {
            fmpq_t room;
            fmpq_init(room);
            fmpq_sub(room, iv->lo, L->lo);
            fmpq_sub(w, L->hi, iv->lo);
            if (fmpq_cmp(w, room) < 0)
                fmpq_set(room, w);
            fmpq_div_2exp(room, room, 2);
            fmpq_one(w);
            while (fmpq_cmp(w, room) > 0)
                fmpq_div_2exp(w, w, 1);
            fmpq_set(L->lo, iv->lo);
            fmpq_set(L->hi, iv->lo);
            fmpq_sub(L->left, L->lo, w);
            fmpq_add(L->right, L->lo, w);
            L->s = fmpq_get_d(L->lo);
            st.rational = 1;
            fmpq_clear(room);
        }
        fmpq_clear(w);
    }
    if (st.rational)
        fmpq_sub(st.eps, L->has_right ? L->right : L->lo, L->has_right ? L->lo : L->left);
    range_update(&st);

    cb_status stt = st.rational ? rational_facts(&st, err) : irrational_facts(&st, err);
    L->gcd_deg = st.gcd_deg;
    int done = 0;
    for (slong att = 0; stt == CB_OK && att < C->opts->max_attempts; att++) {
        int fail = attempt(F, &st, att, err, &stt);
        if (!fail) {
            done = 1;
            break;
        }
        if (fail & FAIL_W)
            fmpq_div_2exp(st.w, st.w, 1);
        if (fail & FAIL_S)
            range_shrink(&st);
    }
    if (stt == CB_OK && !done)
        stt = cb_error_set(err, CB_ERR_NUMERIC,
                           "curve topology: the critical line s ~ %.17g could not be certified "
                           "in %ld attempts",
                           L->s, (long)C->opts->max_attempts);
    if (stt != CB_OK)
        fibre_reset(F);

    for (slong i = 0; i < st.n_pin; i++) {
        fmpq_clear(st.pin[i].lo);
        fmpq_clear(st.pin[i].hi);
    }
    for (slong i = 0; i < st.n_fac; i++)
        cb_roots_clear(st.fac + i);
    flint_free(st.fac);
    for (slong i = 0; i < st.n_deriv; i++)
        cb_bipoly_clear(st.deriv[i]);
    flint_free(st.deriv);
    for (slong i = 0; i < st.alloc_fib; i++)
        arb_poly_clear(st.fib + i);
    flint_free(st.fib);
    cb_bipoly_clear(st.hf);
    fmpz_poly_clear(st.beta_num);
    fmpz_poly_clear(st.beta_den);
    fmpq_clear(st.w);
    fmpq_clear(st.t0);
    fmpq_clear(st.t1);
    fmpq_clear(st.sr);
    fmpq_clear(st.sl);
    fmpq_clear(st.eps);
    return stt;
}
