/* Dense bivariate integer polynomials sum_j c_j(s) t^j for the curve topology (ssi/curve_topo.h). */
#include "ssi/curve_topo.h"

#include <arb_fmpz_poly.h>
#include <flint/fmpq_poly.h>

void cb_bipoly_init(cb_bipoly_struct *p)
{
    p->len = p->alloc = 0;
    p->c = NULL;
}

void cb_bipoly_clear(cb_bipoly_struct *p)
{
    for (slong j = 0; j < p->alloc; j++)
        fmpz_poly_clear(p->c + j);
    flint_free(p->c);
}

static void bipoly_fit(cb_bipoly_struct *p, slong len)
{
    if (len <= p->alloc)
        return;
    p->c = flint_realloc(p->c, (size_t)len * sizeof *p->c);
    for (slong j = p->alloc; j < len; j++)
        fmpz_poly_init(p->c + j);
    p->alloc = len;
}

static void bipoly_normalise(cb_bipoly_struct *p)
{
    while (p->len > 0 && fmpz_poly_is_zero(p->c + p->len - 1))
        p->len--;
}

void cb_bipoly_set(cb_bipoly_struct *p, const cb_bipoly_struct *q)
{
    if (p == q)
        return;
    bipoly_fit(p, q->len);
    for (slong j = 0; j < q->len; j++)
        fmpz_poly_set(p->c + j, q->c + j);
    p->len = q->len;
}

void cb_bipoly_swap(cb_bipoly_struct *p, cb_bipoly_struct *q)
{
    cb_bipoly_struct t = *p;
    *p = *q;
    *q = t;
}

slong cb_bipoly_deg_s(const cb_bipoly_struct *p)
{
    slong d = -1;
    for (slong j = 0; j < p->len; j++)
        d = FLINT_MAX(d, fmpz_poly_degree(p->c + j));
    return d;
}

void cb_bipoly_set_fmpz_mpoly(cb_bipoly_struct *p, const fmpz_mpoly_t f, const fmpz_mpoly_ctx_t ctx)
{
    slong degs[2];
    ulong exp[2];
    fmpz_t c;
    fmpz_init(c);
    fmpz_mpoly_degrees_si(degs, f, ctx);
    slong len = fmpz_mpoly_is_zero(f, ctx) ? 0 : degs[1] + 1;
    bipoly_fit(p, len);
    for (slong j = 0; j < len; j++)
        fmpz_poly_zero(p->c + j);
    for (slong i = 0; i < fmpz_mpoly_length(f, ctx); i++) {
        fmpz_mpoly_get_term_exp_ui(exp, f, i, ctx);
        fmpz_mpoly_get_term_coeff_fmpz(c, f, i, ctx);
        fmpz_poly_set_coeff_fmpz(p->c + exp[1], (slong)exp[0], c);
    }
    p->len = len;
    fmpz_clear(c);
}

void cb_bipoly_get_fmpz_mpoly(fmpz_mpoly_t f, const cb_bipoly_struct *p, const fmpz_mpoly_ctx_t ctx)
{
    ulong exp[2];
    fmpz_mpoly_zero(f, ctx);
    for (slong j = 0; j < p->len; j++)
        for (slong i = 0; i < fmpz_poly_length(p->c + j); i++) {
            if (fmpz_is_zero(p->c[j].coeffs + i))
                continue;
            exp[0] = (ulong)i;
            exp[1] = (ulong)j;
            fmpz_mpoly_set_coeff_fmpz_ui(f, p->c[j].coeffs + i, exp, ctx);
        }
}

void cb_bipoly_derivative_t(cb_bipoly_struct *d, const cb_bipoly_struct *p)
{
    if (p->len <= 1) {
        d->len = 0;
        return;
    }
    bipoly_fit(d, p->len - 1);
    for (slong j = 1; j < p->len; j++)
        fmpz_poly_scalar_mul_si(d->c + j - 1, p->c + j, j);
    d->len = p->len - 1;
    bipoly_normalise(d);
}

void cb_bipoly_derivative_s(cb_bipoly_struct *d, const cb_bipoly_struct *p)
{
    bipoly_fit(d, p->len);
    for (slong j = 0; j < p->len; j++)
        fmpz_poly_derivative(d->c + j, p->c + j);
    d->len = p->len;
    bipoly_normalise(d);
}

void cb_bipoly_eval_s_fmpq(fmpz_poly_t out, const cb_bipoly_struct *p, const fmpq_t s)
{
    fmpq_poly_t q;
    fmpq_t v;
    fmpq_poly_init(q);
    fmpq_init(v);
    for (slong j = 0; j < p->len; j++) {
        fmpz_poly_evaluate_fmpq(v, p->c + j, s);
        fmpq_poly_set_coeff_fmpq(q, j, v);
    }
    fmpq_poly_get_numerator(out, q); /* the canonical denominator of q is positive */
    fmpq_clear(v);
    fmpq_poly_clear(q);
}

void cb_bipoly_eval_t_fmpq(fmpz_poly_t out, const cb_bipoly_struct *p, const fmpq_t t)
{
    /* Horner in t over Q[s]: acc = acc t + c_j. */
    fmpq_poly_t acc, cj;
    fmpq_poly_init(acc);
    fmpq_poly_init(cj);
    for (slong j = p->len - 1; j >= 0; j--) {
        fmpq_poly_scalar_mul_fmpq(acc, acc, t);
        fmpq_poly_set_fmpz_poly(cj, p->c + j);
        fmpq_poly_add(acc, acc, cj);
    }
    fmpq_poly_get_numerator(out, acc);
    fmpq_poly_clear(cj);
    fmpq_poly_clear(acc);
}

void cb_bipoly_eval_arb(arb_t y, const cb_bipoly_struct *p, const arb_t s, const arb_t t, slong prec)
{
    arb_t c;
    arb_init(c);
    arb_zero(y);
    for (slong j = p->len - 1; j >= 0; j--) {
        arb_mul(y, y, t, prec);
        arb_fmpz_poly_evaluate_arb(c, p->c + j, s, prec);
        arb_add(y, y, c, prec);
    }
    arb_clear(c);
}
